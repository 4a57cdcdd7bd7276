"""A steel cylinder pressed on an aluminium block whose meshes do not match (Hertz contact).

Plane strain.  The lower half of a cylinder (R = 50 mm, E = 210 GPa, ν = 0.3) is pressed by a
uniform pressure on its flat face, P = 35 kN per mm of length in all (the NAFEMS load), onto
a block 200 mm × 100 mm (E = 70 GPa, ν = 0.3) fixed at its bottom.  The cylinder's mesh is
graded towards the contact point; the block's is uniform near the contact, 0.6 times the
cylinder's smallest step, so no node of one face meets a node of the other except at the
centre.  The contact is frictionless; the cylinder's nodes on its vertical axis are held in x
(a frictionless cylinder could otherwise turn about its centre: its arc's normals all pass
through it).

The interface uses mortar CFEs (the default where meshes do not match), with S+ on the
coarser face (the cylinder's arc).  Reference: Hertz line contact, half-width a = sqrt(4PR/(πE*)),
peak pressure p0 = 2P/(πa), profile p(x) = p0 sqrt(1 − x²/a²), 1/E* = Σ (1 − ν²)/E.
Run:  python examples/cylinder_on_block.py
"""

import numpy as np

import stepcontact as sc

R, P = 0.05, 35e6  # m, N per m of length
steel, alu = sc.Material(210e9, 0.3), sc.Material(70e9, 0.3)
e_star = 1 / ((1 - steel.nu**2) / steel.E + (1 - alu.nu**2) / alu.E)
a = np.sqrt(4 * P * R / (np.pi * e_star))
p0 = 2 * P / (np.pi * a)

cylinder = sc.half_disc("cylinder", (0.0, R), R, 14, 64, steel, ratio=10.0)
pts = cylinder.points
on_arc = np.abs(np.hypot(pts[:, 0], pts[:, 1] - R) - R) <= 1e-9 * R
h_arc = np.diff(np.sort(pts[on_arc, 0])).min()  # the smallest arc step, at the contact point
# the block: uniform cells of 0.6 × the cylinder's smallest arc step up to 2a from the contact
# point, then growing by 1.25 per cell, along x and in depth
near = np.arange(0.0, 2 * a, 0.6 * h_arc)
far = 2 * a * 1.25 ** np.arange(1, 40)
half = np.r_[near, far[far < 0.1], 0.1]
xs = np.r_[-half[::-1], half[1:]]
block = sc.rectangle("block", (-0.1, -0.1), (0.1, 0.0), 1, 1, alu, xs=xs, ys=-half[::-1])
m = sc.Model(bodies=[cylinder, block], name="cylinder-on-block")

top = m.select("cylinder", y=R)
arc = m.select("cylinder", where=lambda x, y: (np.hypot(x, y - R) > R * (1 - 1e-9))
               & (np.abs(x) <= 0.3 * R))
m = m.add(
    sc.Support("bottom", m.select("block", y=-0.1), "xy"),
    sc.Support("axis", m.select("cylinder", x=0.0, boundary=False), "x"),
    sc.Interface("hertz", plus=arc,
                 minus=m.select("block", y=0.0, where=lambda x, y: np.abs(x) <= 0.4 * R)),
    sc.LoadPattern("P", [sc.EdgeLoad(top, normal=P / (2 * R))]),  # Pa on the 2R-wide face
    sc.Segment("P", 1.0),
)

res = sc.solve_static(m)
print(res.summary())
x = res.cfe["x"][:, 0]
p = -res.N[-1] / res.cfe["area"]
closed = p > 1e-9 * p.max()
half_width = np.abs(x[closed]).max()
order = np.argsort(x)
inner = np.abs(x[order]) <= 0.9 * a
hertz = p0 * np.sqrt(np.clip(1 - (x[order] / a) ** 2, 0, None))
print(f"CFEs: {res.m} (mortar, S+ = the cylinder's arc);  Hertz a = {a * 1e3:.3f} mm, "
      f"p0 = {p0 / 1e6:.1f} MPa")
print("   x/a    p/p0   Hertz")
for xi, pi, hi in zip(x[order][inner], p[order][inner], hertz[inner], strict=True):
    print(f"{xi / a:+6.3f}  {pi / p0:6.4f}  {hi / p0:6.4f}")
err = np.abs(p[order][inner] - hertz[inner]).max() / p0
peak = p[np.argmin(np.abs(x))] / p0 - 1
force = abs((res.N[-1] * res.cfe["normal"][:, 1]).sum()) / P - 1
print(f"total contact force / P - 1 = {force:.1e}")
print(f"peak pressure error {peak:+.2%}, largest error for |x| <= 0.9a {err:.2%} of p0, "
      f"last closed CFE at |x| = {half_width / a:.3f} a")
assert abs(force) < 1e-9 and abs(peak) < 0.01 and err < 0.05
