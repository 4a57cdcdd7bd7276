"""A gravity dam whose base is bonded to the rock: the crack runs along the base as the
reservoir rises, event by event, until the dam slides.

Plane strain, per metre of dam.  The dam of ``cracked_base.py`` (30 m high, base B = 18 m from
heel (0, 0) to toe (18, 0), crest 4 m, vertical upstream face) on rock, non-matching meshes
(mortar CFEs).  The concrete–rock joint has **initial strength** (article eq. (12),
``sc.Bond.mohr_coulomb``): cohesion c = 250 kPa, tensile strength σ_t = 100 kPa and friction
angle φ = 40°; where its bond breaks it becomes a frictional joint (f = tan 40° = 0.84, no
cohesion left).  Self-weight, then the reservoir rises from the base (the water level h is the
load parameter) with

* hydrostatic pressure γ_w (h − y) on the upstream face,
* uplift under the base, from the full head h at the heel to 0 at the toe (linear), where
  the joint is closed (in a bonded joint: the pore pressure of the lift joint),
* crack water from the heel: where the bond has broken and the joint opened, joined to the
  heel, the full reservoir pressure γ_w h replaces the uplift.

The output gives the level at which the heel first cracks, the crack length against the level
(cascades at one level are listed in their order), the level at which the dam fails and how,
and at the design level h_d = 28 m the sliding factor (shear friction: the bonded part's
cohesion plus friction over the thrust) and the overturning factor, from the joint's forces.
A figure shows the crack front against the level (``bonded_dam_crack.png``).

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
# the dam, the rock and the reservoir of cracked_base.py
base_script = runpy.run_path(str(Path(__file__).with_name("cracked_base.py")),
                             run_name="cracked_base")
B, HEIGHT, CREST, concrete = (base_script[k] for k in ("B", "HEIGHT", "CREST", "concrete"))


def dam_model() -> sc.Model:
    """The dam of cracked_base.py with its base bonded (Mohr–Coulomb) through a compliant
    layer (0.5 m, 2 GPa: the compliance of the contact zone, eq. (11)); the level raised to
    the design level, then on until the dam fails."""
    return base_script["dam_model"](
        crack_water=True, bond=sc.Bond.mohr_coulomb(COHESION, TENSILE, PHI),
        layer=sc.ContactLayer(thickness=0.5, E=2e9, nu=0.25), levels=(H_DESIGN, 60.0))


res = sc.solve_static(dam_model())
print(res.summary())

x_cfe = res.cfe["x"][:, 0]
breaks = [e for e in res.events if e.transition == Transition.BROKEN]
print("\nThe crack along the base (level h in m; ← same level as the line above):")
front, last = [], None
for e in breaks:
    same = "  ←" if e.lam == last else ""
    on_tension = e.N >= (1 - 1e-9) * TENSILE * res.cfe["area"][e.cfe]
    mode = "tension facet" if on_tension else "shear facet"
    print(f"  h = {e.lam:9.5f}  bond broken at x = {e.x:5.2f} m ({mode}: N = {e.N / 1e3:8.1f} "
          f"kN, Q = {e.Q / 1e3:7.1f} kN){same}")
    front.append((e.lam, e.x))
    last = e.lam
h_crack = breaks[0].lam
h_fail = res.multipliers[-1].equilibrium_lost
print(f"\nthe heel first cracks at h = {h_crack:.4f} m; the dam fails at h = {h_fail:.4f} m "
      f"({res.message.split(': ')[-1]})")

# ---- the design level: shear friction and overturning factors from the joint's forces -------
i = int(np.flatnonzero((res.segment == 1) & (res.kind == "segment_end"))[0])
h = res.lam[i]
bonded = res.state[i] == int(sc.ContactState.BONDED)
A = res.cfe["area"]
N, Q = -res.N[i], res.Q[i]  # compression > 0
tan = np.tan(np.radians(PHI))
fs_slide = (COHESION * A[bonded].sum() + tan * N.sum()) / abs(Q.sum())
W = concrete.density * 9.81 * (B + CREST) / 2 * HEIGHT
x_w = (CREST * HEIGHT * CREST / 2 + (B - CREST) * HEIGHT / 2 * (CREST + (B - CREST) / 3)) / (
    (B + CREST) / 2 * HEIGHT)  # centroid from the heel
Hh, U = GAMMA_W * h * h / 2, GAMMA_W * h * B / 2
Wc = float(res.water[i].sum())  # the crack water beyond the uplift
# about the toe: resisting W (B − x_w); overturning the thrust, the uplift and the crack water
M_r = W * (B - x_w)
M_o = M_r - float((N * (B - x_cfe)).sum())  # what the base's forces do not resist
print(f"\nat the design level h = {h:g} m: bonds broken over {A[~bonded].sum():.2f} m, water "
      f"in the crack over {A[res.crack_pressure[i] > 0].sum():.2f} m, bonded "
      f"{A[bonded].sum():.2f} m of {A.sum():.2f} m")
print(f"  shear friction factor (c·A_bonded + tan φ ΣN)/ΣQ = {fs_slide:.3f}")
print(f"  overturning factor M_r/M_o about the toe = {M_r / M_o:.3f}")
# hand statics of the base's resultants
print(f"  ΣN = {N.sum() / 1e3:.1f} kN (W − U − ΣW_crack = {(W - U - Wc) / 1e3:.1f}), "
      f"ΣQ = {Q.sum() / 1e3:.1f} kN (γ_w h²/2 = {Hh / 1e3:.1f})")
assert abs(N.sum() - (W - U - Wc)) < 1e-6 * W
assert abs(abs(Q.sum()) - Hh) < 1e-6 * W
assert res.status == sc.Status.EQUILIBRIUM_LOST and h_crack < H_DESIGN < h_fail
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
    ax.set_title("bonded dam base: the crack against the level")
    ax.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig("bonded_dam_crack.png", dpi=120)
    print("wrote bonded_dam_crack.png")
