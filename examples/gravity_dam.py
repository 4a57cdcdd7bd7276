"""A concrete gravity dam on rock: self-weight, then the reservoir rising until the dam slides.

Plane strain, per metre of dam.  The dam (12 m high, base B = 8 m from heel (0, 0) to toe
(8, 0), crest 2 m wide, vertical upstream face) is meshed with `quad_region`; the rock
(28 m × 8 m) with cells of another size, so the meshes of the joint do not match (mortar
CFEs).  The joint is rigid with friction f = 0.7 and no cohesion.

The load parameter of the second segment is the **water level** h (m): the hydrostatic
pressure γ_w (h − y) on the upstream face follows the level exactly, and the uplift under the
base (full head h at the heel, 0 at the toe, linear between: a load per metre of water) grows
with it.  Events are located in h exactly (the load is a polynomial in h between node levels).

Hand statics (W = γ_c A, H = γ_w h²/2, U = γ_w h B/2, levers about the toe):
* sliding when H = f (W − U):  γ_w h²/2 + f γ_w B h/2 − f W = 0;
* at the design level h_d = 10 m: the friction-only factor f (W − U)/H (the shear-friction
  factor without cohesion), the overturning factor M_resisting / M_overturning about the toe
  = W·x_W / (H·h/3 + U·2B/3) and the resultant's distance from the toe (M_r − M_o)/(W − U) —
  checked against the interface's safety output (``interface_safety(..., design=h_d)``) at
  the state recorded at h_d; the load margin against sliding h_slide / h_d.
Run:  python examples/gravity_dam.py
"""

import numpy as np

import stepcontact as sc

GAMMA_W = 9810.0  # N/m³
f, B, HEIGHT, CREST = 0.7, 8.0, 12.0, 2.0  # -, m, m, m
concrete = sc.Material(E=25e9, nu=0.2, density=2400)
rock = sc.Material(E=15e9, nu=0.25, density=2650)

dam = sc.quad_region("dam", [(0, 0), (B, 0), (CREST, HEIGHT), (0, HEIGHT)], 16, 24, concrete)
foundation = sc.rectangle("rock", (-10, -8), (18, 0), 35, 10, rock)  # 0.8 m cells
m = sc.Model(bodies=[foundation, dam], name="gravity-dam")
base = sc.Interface("base", plus=m.select("dam", y=0), minus=m.select("rock", y=0), friction=f)
uplift_per_metre = sc.Uplift(base, head=[(0.0, 0.0, 1.0), (B, 0.0, 0.0)])  # head h at the heel
m = m.add(
    sc.Support("deep rock", m.select("rock", y=-8), "xy"),
    base,
    sc.LoadPattern("weight", [sc.BodyForce(bodies=("dam",))]),
    sc.LoadPattern("reservoir", [sc.WaterLoad(m.select("dam", x=0.0), level=None),
                                 uplift_per_metre]),
    sc.Segment("weight", 1.0),
    sc.Segment("reservoir", 10.0),   # the design level: a state is recorded there
    sc.Segment("reservoir", 20.0),   # and on until the dam slides
)
res = sc.solve_static(m)
print(res.summary())

# ---- hand statics -----------------------------------------------------------------------------
area = (B + CREST) / 2 * HEIGHT
W = concrete.density * 9.81 * area
x_w = (CREST * HEIGHT * (B - CREST / 2) + (B - CREST) * HEIGHT / 2 * (B - CREST) * 2 / 3) / area
a, b, c = GAMMA_W / 2, f * GAMMA_W * B / 2, -f * W
h_slide = (-b + np.sqrt(b * b - 4 * a * c)) / (2 * a)
lam = res.multipliers[-1].equilibrium_lost
print(f"\nW = {W:.1f} N/m, lever of W about the toe {x_w:.4f} m")
print(f"sliding at level h = {lam:.9f} m; hand statics {h_slide:.9f} m; "
      f"relative difference {lam / h_slide - 1:.1e}")

h_d = 10.0
i = int(np.flatnonzero((res.segment == 1) & (res.kind == "segment_end"))[0])
H, U = GAMMA_W * h_d**2 / 2, GAMMA_W * h_d * B / 2
fs_slide = f * (W - U) / H
fs_over = W * x_w / (H * h_d / 3 + U * 2 * B / 3)
# the safety output at the design level (the state recorded at h_d): the engineers' factors
safety = res.interface_safety("base", design=h_d)
d = safety.design_values()
sN, sQ = abs(d["normal_force"]), abs(d["shear_force"])
M_r, M_o = W * x_w, H * h_d / 3 + U * 2 * B / 3
print(f"at h_d = {h_d} m (state {d['state']}, level {d['lam']:g}): ΣN = {sN:.1f} N (hand W − U "
      f"= {W - U:.1f}), ΣQ = {sQ:.1f} N (hand H = {H:.1f})")
print(f"friction-only factor N'·tanφ/H = {d['friction_only_factor']:.9f}; hand f(W − U)/H = "
      f"{fs_slide:.9f}")
print(f"shear-friction factor (c·A_c + N'·tanφ)/H = {d['shear_friction_factor']:.9f} ("
      f"cohesion: {d['cohesion_source']})")
print(f"overturning factor ΣM_r/ΣM_o about the toe = {d['overturning_factor']:.9f}; hand "
      f"W·x_W/(H·h/3 + U·2B/3) = {fs_over:.9f}")
print(f"resultant {d['resultant_from_toe']:.6f} m from the toe (hand (M_r − M_o)/(W − U) = "
      f"{(M_r - M_o) / (W - U):.6f}), e/B = {d['e_over_B']:.4f}, in the middle third: "
      f"{d['in_middle_third']}; compressed length {d['compressed_length']:g} m of {B:g}")
print(f"load margin against sliding: level at sliding / design level = "
      f"{safety.lam_sliding:.6g} m / {h_d:g} m = {safety.margin_sliding:.4f}")
assert d["state"] == i
assert abs(lam / h_slide - 1) < 1e-9
assert abs(d["friction_only_factor"] / fs_slide - 1) < 1e-9
assert abs(d["shear_friction_factor"] / fs_slide - 1) < 1e-9  # no cohesion
assert abs(d["overturning_factor"] / fs_over - 1) < 1e-9
assert abs(d["resultant_from_toe"] - (M_r - M_o) / (W - U)) < 1e-9 * B
assert abs(d["compressed_length"] - B) < 1e-9 * B and d["in_middle_third"]
assert abs(safety.margin_sliding - h_slide / h_d) < 1e-9
