"""A gravity-dam monolith of finite width on a rock block in 3D: self-weight, then the reservoir
rising until the monolith slides.

The monolith (12 m high, base B = 8 m from the heel x = 0 to the toe x = 8, crest 2 m, vertical
upstream face, W_d = 4 m wide along y; hex8, 2 × 2 m cells at the base) stands on a rock block
(20 × 10 × 6 m, 2.5 m cells): the meshes of the joint do not match (mortar CFEs on the
monolith's base).  The joint is rigid with friction f = 0.7, the Coulomb cone an inscribed
8-gon turned so that a facet faces the slip direction x (``facet_angle`` = π/8): its limit
along x is f_k |N| with f_k = f cos(π/8) = 0.647, the polygon's conservative side (with a
vertex along x the limit would be f|N| itself, but the CFEs near the sides, whose slip leans
a little towards y, then turn between two facets within 1e-10 of the sliding level, in an
order that round-off decides).  z is up.

The second segment's parameter is the **water level** h (m): the hydrostatic pressure
γ_w (h − z) on the upstream face follows the level exactly (integrated on the wet part of each
face), and the uplift under the base (head h at the heel, 0 at the toe, linear; through the
CFEs, A_k p(x_k) across each) grows with it.  Events are located in h exactly.

Hand statics of the monolith (per the whole width W_d; H = γ_w W_d h²/2, U = γ_w W_d h B/2):
* sliding when H = f_k (W − U):  γ_w h²/2 + f_k γ_w B h/2 − f_k W/W_d = 0;
* at the design level h_d = 10 m: the friction-only factor f (W − U)/H (the true cone's, as
  ``interface_safety`` reports it), the overturning factor
  M_r/M_o about the toe = W x_W / (H h/3 + U 2B/3), and the normal resultant's distance from
  the toe (M_r − M_o)/(W − U) — against ``res.interface_safety("base")`` (3D: eccentricities in
  both directions, kern, sliding factor).  The uplift acts at the CFEs, so its moment is that
  of the CFE lumps (exact statics, checked to 1e-9) and differs from the continuous
  triangle's by the lumping (printed).
Run:  python examples/dam_monolith_3d.py
"""

import numpy as np
from skfem import MeshHex

import stepcontact as sc
from stepcontact.model.mesh import box

GAMMA_W, G = 9810.0, 9.81  # N/m³, m/s²
f, B, HEIGHT, CREST, WIDTH = 0.7, 8.0, 12.0, 2.0, 4.0  # -, m, m, m, m
H_D = 10.0  # design level, m
concrete = sc.Material(E=25e9, nu=0.2, density=2400)
rock = sc.Material(E=15e9, nu=0.25, density=2650)

# the monolith: a unit box mapped onto the trapezoid x ≤ B − (B − CREST) z / H (flat faces)
unit = box("dam", (0, 0, 0), (1.0, WIDTH, HEIGHT), (4, 2, 6), concrete)
p = unit.mesh.p.copy()
p[0] *= B - (B - CREST) * p[2] / HEIGHT
dam = sc.Body.from_mesh("dam", MeshHex(p, unit.mesh.t), "hex8", concrete)
foundation = box("rock", (-6.0, -3.0, -6.0), (14.0, 7.0, 0.0), (8, 4, 3), rock)
m = sc.Model(bodies=[foundation, dam], name="dam monolith 3D")
base = sc.Interface("base", plus=m.select("dam", lambda x, y, z: np.abs(z) < 1e-9),
                    minus=m.select("rock", boundary="top"), friction=f, facets=8,
                    facet_angle=np.pi / 8)
uplift_per_metre = sc.Uplift(base, head=lambda x, y: np.clip(1.0 - x / B, 0.0, 1.0),
                             through="cfes")
m = m.add(
    sc.Support("deep rock", m.select("rock", boundary="bottom"), "xyz"),
    base,
    sc.LoadPattern("weight", [sc.BodyForce(g=(0.0, 0.0, -G), bodies=("dam",))]),
    sc.LoadPattern("reservoir", [
        sc.WaterLoad(m.select("dam", lambda x, y, z: np.abs(x) < 1e-9), level=None),
        uplift_per_metre]),
    sc.Segment("weight", 1.0),
    sc.Segment("reservoir", H_D),    # the design level: a state is recorded there
    sc.Segment("reservoir", 20.0),   # and on until the monolith slides
)
res = sc.solve_static(m)
print(res.summary())

# ---- hand statics -----------------------------------------------------------------------------
area = (B + CREST) / 2 * HEIGHT
W = concrete.density * G * area * WIDTH
x_w = (CREST * HEIGHT * (B - CREST / 2) + (B - CREST) * HEIGHT / 2 * (B - CREST) * 2 / 3) / area
f_k = f * np.cos(np.pi / 8)  # the 8-gon's limit along its facet normal x
a, b, c = GAMMA_W / 2, f_k * GAMMA_W * B / 2, -f_k * W / WIDTH
h_slide = (-b + np.sqrt(b * b - 4 * a * c)) / (2 * a)
sf = res.interface_safety("base")
print(f"\nW = {W:.1f} N, lever of W about the toe {x_w:.4f} m")
print(f"slides at level h = {sf.lam_sliding:.9f} m; hand statics {h_slide:.9f} m; "
      f"relative difference {sf.lam_sliding / h_slide - 1:.1e}")
assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
assert abs(sf.lam_sliding / h_slide - 1) < 1e-9

# the design state: the level h_d recorded at the end of the second segment
i = int(np.flatnonzero(np.asarray(res.segment) == 1)[-1])
h = res.factors[i, res.pattern_names.index("reservoir")]
assert abs(h - H_D) < 1e-12
Hh, U = GAMMA_W * WIDTH * h * h / 2, GAMMA_W * WIDTH * h * B / 2
M_r = W * x_w
M_o = Hh * h / 3 + U * 2 * B / 3  # the continuous uplift triangle: resultant B/3 from the heel
k = np.flatnonzero(np.asarray(res.cfe["interface"]) == 0)
xk, Ak = np.asarray(res.cfe["x"])[k], np.asarray(res.cfe["area"])[k]
U_k = GAMMA_W * h * Ak * np.clip(1.0 - xk[:, 0] / B, 0.0, 1.0)  # the uplift as the CFEs carry it
M_o_lumped = Hh * h / 3 + U_k @ (B - xk[:, 0])
d = sf.at(i)
from_toe = B - d["point"][0]
rows = [
    ("normal force ΣN, N", d["normal_force"], -(W - U)),
    ("shear |S|, N", d["shear_force"], Hh),
    ("friction-only factor f(W − U)/H", d["sliding_factor"], f * (W - U) / Hh),
    ("resultant from the toe, m (lumped uplift)", from_toe, (M_r - M_o_lumped) / (W - U)),
    ("overturning factor M_r/M_o (lumped uplift)", M_r / (M_r - (W - U) * from_toe),
     M_r / M_o_lumped),
]
print(f"\nat the design level h_d = {H_D:g} m         result          hand statics")
for name, got, want in rows:
    print(f"  {name:44s} {got:14.6f} {want:14.6f}")
    assert abs(got - want) <= 1e-9 * abs(want), name
print(f"  overturning factor with the continuous uplift triangle: {M_r / M_o:.6f} "
      f"(the CFE lumping moves it by {M_r / M_o_lumped / (M_r / M_o) - 1:+.2e})")
print(f"  eccentricities (e₁, e₂) = ({d['eccentricity'][0]:.4f}, {d['eccentricity'][1]:.2e}) m, "
      f"in the kern: {d['in_kern']}, compressed area {d['compressed_area']:.2f} m² "
      f"of {sf.area:.2f} m²")
assert abs(d["eccentricity"][1]) < 1e-9  # symmetric across the width
print(f"margin against sliding h_slide / h_d = {sf.lam_sliding / H_D:.4f}")

# the joint in its own plane at the design level and where the monolith slides
sc.plot_interface_map(res, "base", [i, len(res.lam) - 1], path="dam_monolith_3d_joint.png")
print("wrote dam_monolith_3d_joint.png")
