"""A concrete block on a rigid 30° slope (a rigid obstacle, no foundation mesh): self-weight,
then a horizontal push until the block slides up the slope.

Closed form (statics of the block, α = 30°, f = 0.7 > tan α so the weight alone holds it):
sliding up the slope when P cos α − W sin α = f (W cos α + P sin α), i.e.

    P* = W (sin α + f cos α) / (cos α − f sin α),

with W = 2 m × 0.5 m × 2400 kg/m³ × 9.81 m/s² = 23 544 N per metre run.
Run:  python examples/block_on_rigid_slope.py
"""

import numpy as np

import stepcontact as sc

alpha, f = np.radians(30.0), 0.7
concrete = sc.Material(E=30e9, nu=0.2, density=2400)  # Pa, -, kg/m³
block = sc.rotate(sc.rectangle("block", (0, 0), (2, 0.5), 8, 2, concrete), alpha)  # m
m = sc.Model(bodies=[block], plane="strain", thickness=1.0, name="block-on-rigid-slope")
# the slope drawn upwards to the right: the block lies on its left (above it)
c, s = np.cos(alpha), np.sin(alpha)
slope = sc.RigidObstacle("slope", [(-5 * c, -5 * s), (5 * c, 5 * s)])
on_slope = m.select("block", lambda x, y: np.abs(-s * x + c * y) < 1e-9)
back_face = m.select("block", lambda x, y: np.abs(c * x + s * y) < 1e-9)
m = m.add(
    sc.Interface("base", plus=on_slope, minus=slope, friction=f),
    sc.LoadPattern("weight", [sc.BodyForce()]),
    sc.LoadPattern("push", [sc.EdgeForce(back_face, fx=1.0)]),  # 1 N along +x per unit λ
    sc.Segment("weight", 1.0),
    sc.Segment("push", 1e6),
)

res = sc.solve_static(m)
print(res.summary())
W = 2 * 0.5 * 2400 * 9.81
P = W * (s + f * c) / (c - f * s)
lost = res.multipliers[-1].equilibrium_lost
err = lost / P - 1
print(f"sliding up the slope at P = {lost:.6f} N, closed form {P:.6f} N, relative error {err:.1e}")
assert res.status == sc.Status.EQUILIBRIUM_LOST
assert abs(err) < 1e-9
assert max(res.residual) < 1e-9 and max(res.violation) < 1e-9
