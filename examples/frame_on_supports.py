"""A continuous beam (2D frame) on unilateral supports: it may lift off its middle supports.

A steel beam rests on five supports (rigid contact, frictionless) of a stiff base.  Its own
weight presses it down; an upward force then lifts its right end, and the supports next to it
open one after another.  A pin at the left end holds the beam horizontally.
Run:  python examples/frame_on_supports.py
"""

import numpy as np

import stepcontact as sc

steel = dict(E=210e9, A=0.01, I=2e-4, density=7850)
beam = sc.Frame.line("beam", (0, 0.5), (20, 0.5), 40, **steel)
base = sc.rectangle("base", (-1, 0), (21, 0.5), 44, 2, sc.Material(200e9, 0.2))
m = sc.Model(bodies=[base, beam], name="frame-on-supports")
xs = np.array([0.0, 5.0, 10.0, 15.0, 20.0])
on_support = m.select("beam", where=lambda x, y: np.isin(np.round(x, 9), xs))
m = m.add(
    sc.Support("ground", m.select("base", y=0), "xy"),
    sc.Support("pin", m.select("beam", x=0.0), "x"),  # frictionless supports: hold it in x
    sc.Interface("supports", plus=on_support, minus=m.select("base", y=0.5), friction=0.0),
    sc.LoadPattern("weight", [sc.BodyForce(bodies=("beam",))]),
    sc.LoadPattern("lift", [sc.NodalLoad(m.select("beam", x=20.0), fy=1.0)]),  # N per unit λ
    sc.Segment("weight", 1.0),
    sc.Segment("lift", 1e5),
)
res = sc.solve_static(m)
print(res.summary())
for e in res.events:
    print(f"λ = {e.lam:12.3f} N  support at x = {e.x:5.1f} m  {e.transition.value}")
# the last state is the mechanism itself: check the states of the equilibrium path
assert res.residual[:-1].max() < 1e-9 and res.violation[:-1].max() < 1e-9
