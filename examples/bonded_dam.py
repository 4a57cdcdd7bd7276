"""A gravity dam built in two lifts, its base bonded to the rock: the reservoir rises and the
crack runs along the base, event by event, until the dam slides.

Plane strain, per metre of dam.  The dam of ``cracked_base.py`` (30 m high, base B = 18 m from
heel (0, 0) to toe (18, 0), crest 4 m, vertical upstream face) on rock, non-matching meshes
(mortar CFEs), **built in stages** (``sc.Stage``): the first lift (up to y = 15 m) is cast
and carries its own weight; the second lift is then placed on the deformed first lift, the
lift joint between them made at once (stress-free, bonded: c = 1 MPa, σ_t = 0.5 MPa,
φ = 45°), its weight ramping in; then the reservoir is filled ("impounding").

The concrete–rock joint has **initial strength** (article eq. (12), ``sc.Bond.mohr_coulomb``),
through a compliant layer (0.5 m, 2 GPa): cohesion c = 500 kPa, tensile strength σ_t = 50 kPa
and friction angle φ = 40°; where its bond breaks it becomes a frictional joint (f = tan 40° =
0.84, no cohesion left).  After construction the reservoir rises from the base (the water
level h is the load parameter) with

* hydrostatic pressure γ_w (h − y) on the upstream face,
* uplift under the base, from the full head h at the heel to 0 at the toe (linear), where
  the joint is closed (in a bonded joint: the pore pressure of the lift joint),
* crack water from the heel: where the bond has broken and the joint opened, joined to the
  heel, the full reservoir pressure γ_w h replaces the uplift.

The output gives the level at which the heel first cracks, the crack length against the level
(cascades at one level are listed in their order), the level at which the dam fails and how,
and at the design level h_d = 28 m the safety output (``interface_safety(..., design=h_d)``):
the shear-friction factor (the cohesion of the bonded, compressed part plus friction over the
thrust), the friction-only factor, the overturning factor about the toe (the crack water
counted), the resultant's position and the load margin, checked against the joint's forces.
The same dam built at once (both lifts cast together) is run beside it: building in stages locks
the first lift's weight in before the second lift stiffens it.  A figure shows the crack front
against the level (``bonded_dam_crack.png``).

Check (hand statics): at h_d the resultants of the joint's forces balance the loads (ΣN =
W − U − ΣW_crack, ΣQ = γ_w h²/2, to 1e-6 of W).
Run:  python examples/bonded_dam.py [--plot]
"""

import runpy
import sys
from pathlib import Path

import numpy as np

import stepcontact as sc
from stepcontact.enums import Transition

GAMMA_W = 9810.0  # N/m³
COHESION, TENSILE, PHI = 500e3, 50e3, 40.0  # Pa, Pa, degrees
H_DESIGN = 28.0  # m
LIFT = 15.0  # m, the height of the first lift
LIFT_BOND = sc.Bond.mohr_coulomb(1.0e6, 0.5e6, 45.0)  # the lift joint: c, σ_t (Pa), φ (°)
# the dam, the rock and the reservoir of cracked_base.py
base_script = runpy.run_path(str(Path(__file__).with_name("cracked_base.py")),
                             run_name="cracked_base")
B, HEIGHT, CREST, concrete = (base_script[k] for k in ("B", "HEIGHT", "CREST", "concrete"))


def dam_model(staged: bool = True) -> sc.Model:
    """The dam of cracked_base.py in two lifts, its base bonded (Mohr–Coulomb) through a
    compliant layer (0.5 m, 2 GPa: the compliance of the contact zone, eq. (11)); built in
    stages (or at once), then the level raised to the design level and on until the dam
    fails."""
    return base_script["dam_model"](
        crack_water=True, bond=sc.Bond.mohr_coulomb(COHESION, TENSILE, PHI),
        layer=sc.ContactLayer(thickness=0.5, E=2e9, nu=0.25), levels=(H_DESIGN, 60.0),
        lifts=(LIFT,), lift_bond=LIFT_BOND, staged=staged)


res = sc.solve_static(dam_model())
once = sc.solve_static(dam_model(staged=False))
print(res.summary())
print("\nThe stages and their segments (factor from → to):")
for k, (name, a, b) in enumerate(res.segments):
    stage = res.stage_names[int(res.stage[np.flatnonzero(res.segment == k)[0]])]
    print(f"  {stage:12s}  {name:26s} {a:6g} → {b:g}")

base = res.cfe["interface"] == res.interface_names.index("base")  # the base's CFEs
x_cfe, A = res.cfe["x"][base, 0], res.cfe["area"][base]


def crack(r: sc.StaticResult) -> list:
    """The break events of the base (the lift joint must stay bonded)."""
    breaks = [e for e in r.events if e.transition == Transition.BROKEN]
    assert all(base[e.cfe] for e in breaks)
    return breaks


breaks = crack(res)
print("\nThe crack along the base (level h in m; crack length from the heel: the broken CFEs'")
print("tributary lengths; ← same level as the line above):")
front, last, length = [], None, 0.0
for e in breaks:
    same = "  ←" if e.lam == last else ""
    on_tension = e.N >= (1 - 1e-9) * TENSILE * res.cfe["area"][e.cfe]
    mode = "tension facet" if on_tension else "shear facet"
    length += res.cfe["area"][e.cfe]
    print(f"  h = {e.lam:9.5f}  bond broken at x = {e.x:5.2f} m, crack length {length:5.2f} m "
          f"({mode}: N = {e.N / 1e3:8.1f} kN, Q = {e.Q / 1e3:7.1f} kN){same}")
    front.append((e.lam, e.x))
    last = e.lam
h_crack = breaks[0].lam
h_fail = res.multipliers[-1].equilibrium_lost
print(f"\nthe heel first cracks at h = {h_crack:.4f} m; the dam fails at h = {h_fail:.4f} m "
      f"({res.message.split(': ')[-1]})")
h_once = crack(once)[0].lam, once.multipliers[-1].equilibrium_lost
print(f"built at once: first cracking at h = {h_once[0]:.4f} m, failure at h = {h_once[1]:.4f} m"
      f" (building in stages: {h_crack - h_once[0]:+.4f} m and {h_fail - h_once[1]:+.4f} m)")

# ---- the design level: the safety output, against the joint's forces and the hand statics --
safety = res.interface_safety("base", design=H_DESIGN)
d = safety.design_values()
i = d["state"]  # the state recorded at the end of the segment to h_d
h = res.lam[i]
bonded = res.state[i][base] == int(sc.ContactState.BONDED)
N, Q = -res.N[i][base], res.Q[i][base]  # compression > 0
tan = np.tan(np.radians(PHI))
# by hand from the CFE forces: the cohesion c = τ_R on the bonded CFEs in compression (an intact
# bond in tension adds no cohesion), tan φ on the whole normal force
fs_slide = (COHESION * A[bonded & (N > 0)].sum() + tan * N.sum()) / abs(Q.sum())
W = concrete.density * 9.81 * (B + CREST) / 2 * HEIGHT
x_w = (CREST * HEIGHT * CREST / 2 + (B - CREST) * HEIGHT / 2 * (CREST + (B - CREST) / 3)) / (
    (B + CREST) / 2 * HEIGHT)  # centroid from the heel
Hh, U = GAMMA_W * h * h / 2, GAMMA_W * h * B / 2
Wc = float(res.water[i][base].sum())  # the crack water beyond the uplift
# about the toe: resisting W (B − x_w); overturning the thrust, the uplift and the crack water
M_r = W * (B - x_w)
M_o = M_r - float((N * (B - x_cfe)).sum())  # what the base's forces do not resist
print(f"\nat the design level h = {h:g} m: bonds broken over {A[~bonded].sum():.2f} m, water "
      f"in the crack over {A[res.crack_pressure[i][base] > 0].sum():.2f} m, bonded "
      f"{A[bonded].sum():.2f} m of {A.sum():.2f} m; compressed length "
      f"{d['compressed_length']:.2f} m")
print(f"  shear-friction factor (c·A_c + N'·tanφ)/H = {d['shear_friction_factor']:.4f} (by hand "
      f"from the CFE forces {fs_slide:.4f}; cohesion {d['cohesion'] / 1e3:.1f} kPa on average "
      f"over the compressed length: {d['cohesion_source']})")
print(f"  friction-only factor N'·tanφ/H = {d['friction_only_factor']:.4f}")
print(f"  overturning factor ΣM_r/ΣM_o about the toe = {d['overturning_factor']:.4f} (hand "
      f"W lever / the moment the base's forces do not resist: {M_r / M_o:.4f})")
print(f"  resultant {d['resultant_from_toe']:.3f} m from the toe, e/B = {d['e_over_B']:.3f}, "
      f"in the middle third: {d['in_middle_third']}")
print(f"  load margin: level at failure / design level = {safety.lam_sliding:.4f} m / "
      f"{H_DESIGN:g} m = {safety.margin_sliding:.4f}")
# hand statics of the base's resultants
print(f"  ΣN = {N.sum() / 1e3:.1f} kN (W − U − ΣW_crack = {(W - U - Wc) / 1e3:.1f}), "
      f"ΣQ = {Q.sum() / 1e3:.1f} kN (γ_w h²/2 = {Hh / 1e3:.1f})")
assert abs(N.sum() - (W - U - Wc)) < 1e-6 * W
assert abs(abs(Q.sum()) - Hh) < 1e-6 * W
assert abs(d["shear_friction_factor"] / fs_slide - 1) < 1e-9
assert abs(d["overturning_factor"] / (M_r / M_o) - 1) < 1e-6  # W's lever: to the hand's 1e-6
assert abs(d["resultant_from_toe"] - (M_r - M_o) / N.sum()) < 1e-6 * B
assert res.status == sc.Status.EQUILIBRIUM_LOST and h_crack < H_DESIGN < h_fail
assert res.stage_names == ("lift 1", "lift 2", "impounding")
assert abs(h_crack - h_once[0]) < 0.01 * h_crack  # the base's forces hardly depend on it
assert res.residual.max() < 1e-6 and res.violation.max() < 1e-9

if "--plot" in sys.argv:
    import matplotlib.pyplot as plt

    levels = np.array([lv for lv, _ in front])
    xs = np.maximum.accumulate(np.array([x for _, x in front]))
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.step(np.r_[levels, h_fail], np.r_[xs, xs[-1]], where="post", color="C3")
    ax.plot(levels, xs, "x", color="C3", label="bond broken (event)")
    ax.axvline(H_DESIGN, ls=":", color="0.5", label=f"design level {H_DESIGN:g} m")
    ax.set_xlabel("reservoir level h, m")
    ax.set_ylabel("crack front x from the heel, m")
    ax.set_title("bonded dam base (built in two lifts): the crack against the level")
    ax.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig("bonded_dam_crack.png", dpi=120)
    print("wrote bonded_dam_crack.png")
