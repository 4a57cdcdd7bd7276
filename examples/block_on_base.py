"""A concrete block on a concrete base: self-weight, then a horizontal push until it slides.

Closed form: the block slides as a whole when the push reaches H = f·W (f = 0.5,
W = 2 m × 1 m × 2400 kg/m³ × 9.81 m/s² = 47 088 N per metre run), i.e. at λ = 23 544 N.
Run:  python examples/block_on_base.py
"""

import stepcontact as sc


def block_model() -> sc.Model:
    """The block, its base, the joint (f = 0.5), self-weight and the push (N, m, Pa)."""
    concrete = sc.Material(E=30e9, nu=0.2, density=2400)  # Pa, -, kg/m³
    base = sc.rectangle("base", (0, 0), (4, 1), 16, 4, concrete)  # m
    block = sc.rectangle("block", (1, 1), (3, 2), 10, 5, concrete)
    m = sc.Model(bodies=[base, block], plane="strain", thickness=1.0, name="block-on-base")
    left = m.select("block", x=1)
    return m.add(
        sc.Support("bed", m.select("base", y=0), "xy"),
        sc.Interface("joint", plus=m.select("block", y=1), minus=m.select("base", y=1),
                     friction=0.5),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
        sc.LoadPattern("push", [sc.NodalLoad(left, fx=1.0 / len(left))]),  # 1 N per unit λ
        sc.Segment("weight", 1.0),
        sc.Segment("push", 1e6),
    )


if __name__ == "__main__":
    m = block_model()
    res = sc.solve_static(m)
    print(res.summary())
    print(res.events_table()[["step", "lam", "position", "transition", "N", "Q"]].to_string())
    W = 2 * 1 * 2400 * 9.81
    lost = res.multipliers[-1].equilibrium_lost
    err = lost / (0.5 * W) - 1
    print(f"sliding at H = {lost:.6f} N, f·W = {0.5 * W:.6f} N, relative error {err:.1e}")
    assert abs(lost / (0.5 * W) - 1) < 1e-9
