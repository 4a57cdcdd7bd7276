"""Cracked-base analysis of a gravity dam: water enters the joint where it opens.

Plane strain, per metre of dam.  A 30 m concrete dam (base B = 18 m from heel (0, 0) to toe
(18, 0), crest 4 m, vertical upstream face) on rock, non-matching meshes (mortar CFEs), a rigid
joint with f = 1.0 and no cohesion.  Self-weight, then the reservoir rises from the base (the
water level h is the load parameter) with

* hydrostatic pressure γ_w (h − y) on the upstream face,
* uplift under the base, from the full head h at the heel to 0 at the toe (linear),
* **crack water** (`sc.CrackWater`, entering at the heel): where the joint has opened and is
  joined to the heel, the full reservoir pressure γ_w h acts on both faces instead of the
  uplift — the cracked-base assumption of dam design codes (e.g. USACE EM 1110-2-2200, FERC
  Engineering Guidelines ch. 3).

The water that enters a newly opened CFE loads its neighbour, which may open at the same level:
the crack runs along the base event by event, and the events at one level are listed in their
order.  The same dam without crack water is run beside it.

Check (hand statics of the last state): when the dam slides every CFE in contact slips, so
γ_w h²/2 = f (W − U(h) − ΣW_crack), with U the uplift over the whole base, γ_w h B/2, and
ΣW_crack the crack water's force beyond the uplift in the opened part (from the result).
Run:  python examples/cracked_base.py
"""

import numpy as np

import stepcontact as sc
from stepcontact.enums import Transition

GAMMA_W = 9810.0  # N/m³
f, B, HEIGHT, CREST = 1.0, 18.0, 30.0, 4.0  # -, m, m, m
concrete = sc.Material(E=25e9, nu=0.2, density=2400)
rock = sc.Material(E=15e9, nu=0.25, density=2650)


def dam_model(crack_water: bool, *, bond: sc.Bond | None = None,
              layer: sc.ContactLayer | None = None, levels=(40.0,),
              lifts=(), lift_bond: sc.Bond | None = None, staged: bool = True) -> sc.Model:
    """The dam on rock (f = 1.0, or a ``bond`` with its own friction, and an optional compliant
    ``layer`` in the joint), weight, then the reservoir raised through ``levels`` (m; the last
    one beyond failure).

    With ``lifts`` (the elevations of the lift joints, m, each a multiple of 1 m) the dam is
    one body per lift, ``lift 1`` from the base up, joined by the lift joints ``joint 1``, …
    (matching meshes, f = 1.0, bonded with ``lift_bond``), and — if ``staged`` — built in
    stages ``lift 1``, ``lift 2``, …: each lift placed on the deformed lifts below, its joint
    made at once (stress-free) and its weight ramping in; then the reservoir ("impounding")."""
    ys = [0.0, *map(float, lifts), HEIGHT]
    xs = [B - (B - CREST) * y / HEIGHT for y in ys]  # the downstream face at each y
    one = len(ys) == 2
    dams = [sc.quad_region("dam" if one else f"lift {k + 1}",
                           [(0, ys[k]), (xs[k], ys[k]), (xs[k + 1], ys[k + 1]), (0, ys[k + 1])],
                           18, round(ys[k + 1] - ys[k]), concrete) for k in range(len(ys) - 1)]
    names = tuple(d.name for d in dams)
    # 1.5 m cells (coarser than the dam's: the base's mortar CFEs sit on the rock's nodes),
    # with nodes at the heel (x = 0) and the toe (x = 18 m)
    rock_body = sc.rectangle("rock", (-21, -20), (39, 0), 40, 14, rock)
    m = sc.Model(bodies=[rock_body, *dams], name="cracked-base" if bond is None else
                 "bonded-dam")
    base = sc.Interface("base", plus=m.select(names[0], y=0), minus=m.select("rock", y=0),
                        friction=f, bond=bond, layer=layer)
    reservoir = [*(sc.WaterLoad(m.select(n, x=0.0), level=None) for n in names),  # factor: h
                 sc.Uplift(base, head=[(0.0, 0.0, 1.0), (B, 0.0, 0.0)])]  # h at the heel
    if crack_water:
        reservoir.append(sc.CrackWater(base, level=None, entry=(0.0, 0.0)))
    joints = [sc.Interface(f"joint {k}", plus=m.select(names[k], y=ys[k]),
                           minus=m.select(names[k - 1], y=ys[k]), friction=f, bond=lift_bond)
              for k in range(1, len(names))]
    m = m.add(
        sc.Support("deep rock", m.select("rock", y=-20), "xy"),
        base, *joints,
        sc.LoadPattern("weight", [sc.BodyForce(bodies=names)]),
        sc.LoadPattern("reservoir", reservoir),
    )
    weight = [sc.Segment("weight", 1.0)]
    filling = [sc.Segment("reservoir", h) for h in levels]  # from the base until the dam fails
    if one or not staged:
        return m.add(*weight, *filling)
    return m.add(sc.Stage(names[0], weight),
                 *(sc.Stage(names[k], bodies=(names[k],), interfaces=(f"joint {k}",))
                   for k in range(1, len(names))),
                 sc.Stage("impounding", filling))

if __name__ == "__main__":
    res = sc.solve_static(dam_model(crack_water=True))
    dry = sc.solve_static(dam_model(crack_water=False))
    print(res.summary())

    print("\nThe crack along the base (level h in m; x of the CFE in m; ← same level as above):")
    last = None
    for e in res.events:
        if e.segment == 1 and e.transition == Transition.OPENED:
            same = "  ←" if last is not None and e.lam == last else ""
            print(f"  h = {e.lam:9.5f}  opened at x = {e.x:5.2f}{same}")
            last = e.lam

    i = len(res.lam) - 1
    h = res.lam[i]
    wet = res.crack_pressure[i] > 0  # open and joined to the heel (the last one just opened)
    p_c = res.crack_pressure[i][wet] / 1e3
    print(f"\nat the last state (h = {h:.6f} m): water in the crack from the heel to x = "
          f"{res.cfe['x'][wet, 0].max(initial=0):.2f} m at {p_c.min():.2f} … {p_c.max():.2f} kPa"
          f" (γ_w h = {GAMMA_W * h / 1e3:.2f} kPa)")
    print(f"first opening: h = {res.multipliers[1].first_opening:.5f} m with crack water, "
          f"{dry.multipliers[1].first_opening:.5f} m without")
    print(f"dam fails at h = {res.multipliers[-1].equilibrium_lost:.5f} m with crack water, "
          f"{dry.multipliers[-1].equilibrium_lost:.5f} m without ({res.message.split(': ')[-1]})")

    # ---- hand statics of the sliding state ----------------------------------------------------
    W = concrete.density * 9.81 * (B + CREST) / 2 * HEIGHT
    U = GAMMA_W * h * B / 2
    Wc = float(res.water[i].sum())
    lhs, rhs = GAMMA_W * h * h / 2, f * (W - U - Wc)
    print(f"sliding: γ_w h²/2 = {lhs:.2f} N/m; f (W − U − ΣW_crack) = {rhs:.2f} N/m "
          f"(relative difference {lhs / rhs - 1:.1e})")
    assert res.status == sc.Status.EQUILIBRIUM_LOST and "sliding" in res.message
    assert abs(lhs / rhs - 1) < 1e-9
    # where the water had entered before the last opening: the full reservoir pressure (the dam
    # slid while water was entering the CFE that opened last: its pressure was still rising)
    x_last = [e.x for e in res.events if e.transition == Transition.OPENED][-1]
    done = (res.water[i] > 0) & (res.cfe["x"][:, 0] < x_last)
    np.testing.assert_allclose(res.crack_pressure[i][done], GAMMA_W * h, rtol=1e-9)
    assert res.multipliers[-1].equilibrium_lost < dry.multipliers[-1].equilibrium_lost
