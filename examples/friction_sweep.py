"""A friction sweep on one factorisation, and a load segment that moves two patterns at once.

The block of ``block_on_base.py`` (2 m × 1 m of concrete on a concrete base): the structure is
condensed to its contact unknowns once (``sc.condense``); every friction coefficient then reuses
it.  Closed form: the block slides when the push reaches H = f·W.  Then, for f = 0.5, a second
program pushes and lifts the block together (``Segment(..., rates=...)``: push 20 kN and uplift
0.5 W per unit of the segment's parameter t), so that it slides at f (W − 0.5 W t) = 20 000 t.
Run:  python examples/friction_sweep.py
"""

import numpy as np

import stepcontact as sc

concrete = sc.Material(E=30e9, nu=0.2, density=2400)  # Pa, -, kg/m³
base = sc.rectangle("base", (0, 0), (4, 1), 16, 4, concrete)  # m
block = sc.rectangle("block", (1, 1), (3, 2), 10, 5, concrete)
m = sc.Model(bodies=[base, block], plane="strain", thickness=1.0, name="friction-sweep")
left = m.select("block", x=1)
m = m.add(
    sc.Support("bed", m.select("base", y=0), "xy"),
    sc.Interface("joint", plus=m.select("block", y=1), minus=m.select("base", y=1), friction=0.5),
    sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
    sc.LoadPattern("push", [sc.NodalLoad(left, fx=1.0 / len(left))]),  # 1 N per unit λ
    sc.LoadPattern("uplift", [sc.BodyForce(bodies=("block",), g=(0.0, 9.81))]),  # W per unit
    sc.Segment("weight", 1.0),
    sc.Segment("push", 1e6),
)
W = 2 * 1 * 2400 * 9.81  # N per metre run

c = sc.condense(m)  # one factorisation for the whole sweep
print("f      sliding load H, N     f·W, N          factorisations")
for f in np.linspace(0.2, 1.0, 5):
    res = sc.solve_static(m.with_friction(f), condensation=c, store_fields="ends")
    H = res.multipliers[-1].equilibrium_lost
    print(f"{f:.2f}   {H:14.6f}   {f * W:14.6f}   {res.counters['factorizations']}")
    assert abs(H / (f * W) - 1) < 1e-9
    assert res.counters["factorizations"] == 0

both = m.replace(program=(sc.Segment("weight", 1.0),
                          sc.Segment("push and uplift", 1.0,
                                     rates={"push": 2e4, "uplift": 0.5})))
res = sc.solve_static(both, condensation=c)
t = res.multipliers[-1].equilibrium_lost
t_exact = 0.5 * W / (2e4 + 0.25 * W)
print(f"push and uplift together: slides at t = {t:.10f} (closed form {t_exact:.10f})")
assert abs(t / t_exact - 1) < 1e-9
