"""A triangular gravity dam on rock, step by step: weight, the reservoir rising, uplift with a
drainage line, water in the opened joint — against hand statics.

Plane strain, per metre of dam.  The section is a triangle (``sc.polygon_region``, no Gmsh):
heel (0, 0), toe (B, 0) = (21, 0), crest (0, H) = (0, 30) m, vertical upstream face; 21 cells
along every edge (1 m along the base), eight-node quads.  The rock below has 1 m cells at its
top, so the base's CFEs join node to node.  The joint is rigid, friction f = 1.0 (φ = 45°), no
cohesion.

Loads:
1. the dam's weight W (segment 1, λ from 0 to 1);
2. the reservoir, its **level h** the load factor (segments 2 and 3: to the design level
   h_d = 28 m, then on until the dam fails), with
   * the hydrostatic pressure γ_w (h − y) on the upstream face (above the crest, h > H, the
     face carries the trapezoid γ_w (h − y), 0 ≤ y ≤ H: the dam is overtopped);
   * uplift under the base with a **drainage line** at x_d = 2.1 m (0.1 B): head h at the
     heel, h/3 at the drains, 0 at the toe (no tailwater), linear between — the usual design
     assumption for working drains;
   * **crack water**: where the joint opens (joined to the heel), the full reservoir pressure
     γ_w (h − y) acts in the crack instead of the uplift (the drains do not relieve it).

Hand statics (per metre; levers from the heel):
* W = ρ g B H/2 at x = B/3; H_w = γ_w h²/2 at y = h/3 (h ≤ H);
  U = ∫ p_u dx over the piecewise linear profile, at x_U;
* with the joint closed, ΣN = W − U, ΣQ = H_w, and the normal resultant at
  x_R = (W B/3 + H_w h/3 − U x_U) / (W − U) — checked at h_d to 1e-9;
* the dam slides when ΣQ = f ΣN.  Without crack water the uplift is a given load, so this is
  the closed form H_w(h) = f (W − U(h)), whatever opens — checked to 1e-9 on the same dam run
  without crack water; with crack water at the failure state ΣN = W − U − ΣW_crack
  (ΣW_crack: the crack water's force beyond the uplift, from the result) and ΣQ = H_w
  (1e-9), and the pressure in the crack at the heel is γ_w h (1e-12).

The safety output of the interface (``res.interface_safety``) is printed in its own block at
the end.  Run:  python examples/triangular_dam.py
"""

import numpy as np

import stepcontact as sc
from stepcontact.enums import Transition

GAMMA_W = 9810.0  # N/m³
RHO_C, G = 2400.0, 9.81  # kg/m³, m/s²
B, HEIGHT, F = 21.0, 30.0, 1.0  # base, height (m), friction coefficient
X_DRAIN = 0.1 * B  # the drainage line, m from the heel
H_DESIGN = 28.0  # design level, m
N_EDGE = 21  # cells along every edge of the section
concrete = sc.Material(E=25e9, nu=0.2, density=RHO_C)
rock = sc.Material(E=15e9, nu=0.25, density=2650.0)
#: uplift head per metre of water (the pattern's factor is the level h): h at the heel,
#: h/3 at the drainage line, 0 at the toe
UPLIFT_HEAD = [(0.0, 0.0, 1.0), (X_DRAIN, 0.0, 1.0 / 3.0), (B, 0.0, 0.0)]


def dam_model(crack_water: bool = True) -> sc.Model:
    """The triangular dam on rock: weight, the reservoir to h_d, then on to 45 m."""
    dam = sc.polygon_region("dam", [(0.0, 0.0), (B, 0.0), (0.0, HEIGHT)], concrete, "quad8",
                            n=N_EDGE)
    foundation = sc.rectangle("rock", (-B, -B), (2 * B, 0.0), 63, 12, rock)  # 1 m × 1.75 m
    m = sc.Model(bodies=[foundation, dam], name="triangular dam")
    base = sc.Interface("base", plus=m.select("dam", y=0.0), minus=m.select("rock", y=0.0),
                        friction=F)
    reservoir = [sc.WaterLoad(m.select("dam", x=0.0), level=None),  # the factor is the level
                 sc.Uplift(base, head=UPLIFT_HEAD)]
    if crack_water:
        reservoir.append(sc.CrackWater(base, level=None, entry=(0.0, 0.0)))
    return m.add(
        sc.Support("deep rock", m.select("rock", y=-B)),
        base,
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("dam",))]),
        sc.LoadPattern("reservoir", reservoir),
        sc.Segment("weight", 1.0),
        sc.Segment("reservoir", H_DESIGN),  # a state is recorded at the design level
        sc.Segment("reservoir", 45.0),  # and on until the dam fails
    )


# ---- hand statics ------------------------------------------------------------------------------
W = RHO_C * G * B * HEIGHT / 2  # N per metre, at x = B/3


def water_thrust(h: float) -> tuple[float, float]:
    """H_w (N) on the upstream face and its height above the base (m)."""
    d = min(h, HEIGHT)  # wetted height of the face
    Hw = GAMMA_W * d * (h - d / 2)  # ∫_0^d γ_w (h − y) dy
    y = GAMMA_W * d**2 * (h / 2 - d / 3) / Hw  # ∫ y p dy / H_w
    return Hw, y


def uplift(h: float) -> tuple[float, float]:
    """U (N) and its lever x_U from the heel (m) for the drained profile at level h."""
    U = Mx = 0.0
    for (a, _, pa), (b, _, pb) in zip(UPLIFT_HEAD[:-1], UPLIFT_HEAD[1:], strict=True):
        pa, pb = GAMMA_W * h * pa, GAMMA_W * h * pb
        U += (pa + pb) / 2 * (b - a)
        Mx += (b - a) / 6 * (pa * (2 * a + b) + pb * (a + 2 * b))
    return U, Mx / U


def closed_joint(h: float) -> tuple[float, float, float]:
    """ΣN, ΣQ (N) and the normal resultant's distance from the heel (m), joint closed."""
    Hw, yH = water_thrust(h)
    U, xU = uplift(h)
    N = W - U
    return N, Hw, (W * B / 3 + Hw * yH - U * xU) / N


def sliding_level() -> float:
    """The level at which H_w(h) = f (W − U(h)): U is linear in h; H_w quadratic up to the
    crest, linear above it (γ_w H (h − H/2))."""
    cu = uplift(1.0)[0]  # U per metre of level
    a, b, c = GAMMA_W / 2, F * cu, -F * W
    h = (-b + np.sqrt(b * b - 4 * a * c)) / (2 * a)
    if h > HEIGHT:  # overtopped: γ_w H h − γ_w H²/2 = f W − f cu h
        h = (F * W + GAMMA_W * HEIGHT**2 / 2) / (GAMMA_W * HEIGHT + F * cu)
    return h


if __name__ == "__main__":
    res = sc.solve_static(dam_model(crack_water=True))
    print(res.summary())
    saf = res.interface_safety("base")

    # ---- 1. the weight alone -----------------------------------------------------------------
    i_w = int(np.flatnonzero((res.segment == 0) & (res.kind == "segment_end"))[0])
    print(f"\n1. weight: W = {W / 1e3:.1f} kN/m; ΣN = {-saf.normal_force[i_w] / 1e3:.1f} kN at "
          f"{saf.position[i_w]:.4f} m from the heel (hand: B/3 = {B / 3:.4f} m)")
    assert abs(-saf.normal_force[i_w] / W - 1) < 1e-9
    assert abs(saf.position[i_w] - B / 3) < 1e-9 * B

    # ---- 2. the design level: the joint closed -----------------------------------------------
    i_d = int(np.flatnonzero((res.segment == 1) & (res.kind == "segment_end"))[0])
    N_d, Q_d, x_d = closed_joint(H_DESIGN)
    U_d, xU_d = uplift(H_DESIGN)
    Hw_d, _ = water_thrust(H_DESIGN)
    print(f"\n2. design level h = {res.lam[i_d]:g} m: H_w = {Hw_d / 1e3:.1f} kN, U = "
          f"{U_d / 1e3:.1f} kN at {xU_d:.3f} m (drains at {X_DRAIN:.1f} m), "
          f"open length {saf.open_length[i_d]:.1f} m")
    print(f"   ΣN = {-saf.normal_force[i_d] / 1e3:.3f} kN (hand W − U = {N_d / 1e3:.3f}), "
          f"ΣQ = {saf.shear_force[i_d] / 1e3:.3f} kN (hand H_w = {Q_d / 1e3:.3f})")
    print(f"   resultant at {saf.position[i_d]:.4f} m from the heel (hand {x_d:.4f} m; middle "
          f"third up to {2 * B / 3:.1f} m)")
    assert saf.open_length[i_d] == 0.0
    assert abs(-saf.normal_force[i_d] / N_d - 1) < 1e-9
    assert abs(saf.shear_force[i_d] / Q_d - 1) < 1e-9
    assert abs(saf.position[i_d] - x_d) < 1e-9 * B

    # ---- 3. the level rises: the heel opens, water enters, the dam slides ----------------------
    opened = [e for e in res.events if e.transition == Transition.OPENED]
    lo, hi = H_DESIGN, HEIGHT  # rigid base, linear pressure: σ_heel = 0 where x_R = 2B/3
    for _ in range(60):
        lo, hi = ((lo + hi) / 2, hi) if closed_joint((lo + hi) / 2)[2] < 2 * B / 3 else \
            (lo, (lo + hi) / 2)
    print(f"\n3. the heel opens at h = {opened[0].lam:.4f} m (a rigid base with a linear "
          f"pressure, the middle-third rule, would put it at h = {lo:.4f} m); the crack, level "
          "by level:")
    for e in opened:
        print(f"   h = {e.lam:.5f} m: opened at x = {e.x:.1f} m")
    last = res.n_states - 1
    h_f = res.lam[last]
    Hw_f, _ = water_thrust(h_f)
    U_f, _ = uplift(h_f)
    crack = float(res.water[last].sum())  # the crack water's force beyond the uplift, N
    wet = res.crack_pressure[last] > 0
    print(f"   {res.message}")
    print(f"   at failure: ΣQ = {saf.shear_force[last] / 1e3:.3f} kN (H_w = {Hw_f / 1e3:.3f}), "
          f"ΣN = {-saf.normal_force[last] / 1e3:.3f} kN (W − U − ΣW_crack = "
          f"{(W - U_f - crack) / 1e3:.3f}), crack water over {saf.open_length[last]:.1f} m at "
          f"{res.crack_pressure[last][wet].max() / 1e3:.2f} kPa at the heel (γ_w h = "
          f"{GAMMA_W * h_f / 1e3:.2f})")
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    assert res.mechanism["bodies"][0]["mode"] == "sliding"
    assert abs(saf.shear_force[last] / Hw_f - 1) < 1e-9
    assert abs(-saf.normal_force[last] / (W - U_f - crack) - 1) < 1e-9
    assert abs(saf.shear_force[last] / (-F * saf.normal_force[last]) - 1) < 1e-9
    assert abs(res.crack_pressure[last][wet].max() / (GAMMA_W * h_f) - 1) < 1e-12

    # ---- 4. without crack water: the closed-form sliding level ---------------------------------
    dry = sc.solve_static(dam_model(crack_water=False))
    h_s = sliding_level()
    h_dry = dry.multipliers[-1].equilibrium_lost
    print(f"\n4. without crack water the dam slides at h = {h_dry:.6f} m; hand statics "
          f"H_w = f (W − U): h = {h_s:.6f} m; crack water lowers it by {h_dry - h_f:.2f} m")
    assert abs(h_dry / h_s - 1) < 1e-9

    # ---- safety output (res.interface_safety, as `stepcontact info --design 28` prints it) -----
    # the engineers' factors at the design level, with the joint as it is (no cohesion) and
    # with a design cohesion of 300 kPa on the compressed length; moments about the toe
    C_DESIGN = 300e3  # Pa
    safety = res.interface_safety("base", design=H_DESIGN, heel="auto")
    d = safety.design_values()
    dc = res.interface_safety("base", design=H_DESIGN, heel="auto",
                              cohesion=C_DESIGN).design_values()
    M_r = W * 2 * B / 3  # the weight's moment about the toe
    M_o = Hw_d * H_DESIGN / 3 + U_d * (B - xU_d)  # the water's thrust and the uplift
    print(f"\nsafety of 'base' at the design level h = {d['lam']:g} m (state {d['state']}):")
    print(f"   friction-only factor f·N'/H = {d['friction_only_factor']:.6f} (hand f (W − U)/H_w "
          f"= {F * N_d / Q_d:.6f})")
    print(f"   shear-friction factor (c·A_c + N'·tan φ)/H with c = {C_DESIGN / 1e3:g} kPa on "
          f"{dc['compressed_length']:.1f} m: {dc['shear_friction_factor']:.6f} (hand "
          f"(c B + f (W − U))/H_w = {(C_DESIGN * B + F * N_d) / Q_d:.6f})")
    print(f"   overturning factor ΣM_r/ΣM_o about the toe = {d['overturning_factor']:.6f} (hand "
          f"W·2B/3 / (H_w h/3 + U (B − x_U)) = {M_r / M_o:.6f})")
    print(f"   resultant {d['resultant_from_toe']:.4f} m from the toe, e/B = "
          f"{d['e_over_B']:+.4f}, in the middle third: {d['in_middle_third']}")
    print(f"   load margin: the dam slides at h = {safety.lam_sliding:.4f} m, level at sliding / "
          f"design level = {safety.margin_sliding:.4f}")
    assert abs(d["friction_only_factor"] / (F * N_d / Q_d) - 1) < 1e-9
    assert abs(dc["shear_friction_factor"] / ((C_DESIGN * B + F * N_d) / Q_d) - 1) < 1e-9
    assert abs(d["overturning_factor"] / (M_r / M_o) - 1) < 1e-9
    assert abs(d["resultant_from_toe"] - (B - x_d)) < 1e-9 * B
