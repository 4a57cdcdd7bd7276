"""A block on a rough floor hit by a pressure pulse: it lifts off, flies, lands and slides.

Dynamics with the contact followed exactly (`sc.solve_dynamic`): a rigid block of mass m
(a discrete model with the DOFs u_x, u_y of its centre and one contact with the floor,
f = 0.4) rests under its weight (a static run), then a half-sine pulse of duration
t_p = 0.1 s pushes it up and sideways with the peak force (1.5 W, 2 W).  Closed forms of a rigid
body:

* lift-off when 2 W sin(π t/t_p) = W: t₁ = t_p/π · asin(1/2) (sliding starts at t = 0, when
  the horizontal push exceeds f W);
* flight: y(t) from the pulse and gravity, landing where y = 0 again (found by root finding
  on the exact integral of the half-sine);
* landing is an impact (restitution 0): the vertical velocity vanishes, friction's impulse
  (at most f times the normal one) takes f |v_y| off the horizontal velocity, and the block
  slides to rest, decelerating at f g.

Printed last: the event times against the closed forms (relative differences) and the energy
ledger.  Figures: `block_pulse_dynamic.png` (displacements and velocities against time with the
events marked) and `block_pulse_energy.png` (the energy ledger).
Run:  python examples/block_pulse_dynamic.py   (figures in ./block_pulse_out/)
"""

from pathlib import Path

import numpy as np
from scipy.optimize import brentq

import stepcontact as sc
from stepcontact.enums import Transition

m, f, g, tp = 1000.0, 0.4, 9.81, 0.1  # kg, -, m/s², s
W = m * g
block = sc.DiscreteModel(
    K=[[0.0, 0.0], [0.0, 0.0]], normal_rows=[[0, 1]], tangent_rows=[[1, 0]],
    loads={"weight": {"uy": -W}, "pulse": {"ux": 1.5 * W, "uy": 2.0 * W}},
    friction=f, dof_names=("ux", "uy"), program=[sc.Segment("weight", 1.0)])
rest = sc.solve_static(block)
dt = 2e-4
res = sc.solve_dynamic(block, dt=dt, duration=0.6, mass=np.diag([m, m]), initial=rest,
                       loads={"pulse": sc.Pulse(1.0, 0.0, tp, "half_sine")})
print(res.summary())

# ---- closed forms ---------------------------------------------------------------------------
w = np.pi / tp


def y_of(t: float, t1: float) -> float:
    """Height of the block in flight (lift-off at t1 with zero vertical velocity), m:
    ÿ = 2 g sin(w t) − g while the pulse lasts, −g after."""
    s_p = min(t, tp)
    y = 2 * g * (np.cos(w * t1) * (s_p - t1) - (np.sin(w * s_p) - np.sin(w * t1)) / w) / w
    if t > tp:
        y += 2 * g * (np.cos(w * t1) - np.cos(w * tp)) / w * (t - tp)
    return y - 0.5 * g * (t - t1) ** 2


t_lift = tp / np.pi * np.arcsin(0.5)
t_land = brentq(lambda t: y_of(t, t_lift), t_lift + 1e-6, 2.0)
# horizontal: stuck until 1.5 W sin(w t) = f N with N = W − 2 W sin(w t), then sliding with
# ẍ = g (2.3 sin(w t) − 0.4) until lift-off, free (ẍ = 1.5 g sin(w t)) in the flight
t_slip = np.arcsin(f / (1.5 + 2 * f)) / w
vx_lift = g * ((1.5 + 2 * f) * (np.cos(w * t_slip) - np.cos(w * t_lift)) / w
               - f * (t_lift - t_slip))
vx_land = vx_lift + 1.5 * g * (np.cos(w * t_lift) - np.cos(w * min(t_land, tp))) / w
# the landing: the vertical impulse m |v_y| stops the fall (restitution 0) and friction's
# impulse, at most f m |v_y|, takes that much off the horizontal velocity
vy_land = 2 * g * (np.cos(w * t_lift) - np.cos(w * tp)) / w - g * (t_land - t_lift)
vx_after = vx_land - f * abs(vy_land)
t_stop = t_land + vx_after / (f * g)

ev = res.events
got = {
    "slip": next(e.lam for e in ev if e.transition == Transition.SLIP_POS),
    "lift-off": next(e.lam for e in ev if e.transition == Transition.OPENED),
    # the landing closes the contact straight into sliding (open → slip+)
    "landing": next(e.lam for e in ev if e.lam > t_lift and e.transition != Transition.OPENED),
    "at rest": next(e.lam for e in ev if e.transition == Transition.STUCK
                    and e.lam > t_land),
}
ref = {"slip": t_slip, "lift-off": t_lift, "landing": t_land, "at rest": t_stop}
print("\nevent       stepcontact (s)   closed form (s)   relative difference")
for key in got:
    print(f"{key:10s}  {got[key]:.9f}      {ref[key]:.9f}      {got[key] / ref[key] - 1:+.2e}")
e = res.energy
print(f"energy (J): work of the pulse {e['external'][-1]:.3f}, dissipated by friction "
      f"{e['friction'][-1]:.3f}, in the landing {e['impact'][-1]:.3f}, numerical "
      f"{e['numerical'][-1]:.3f}; balance error {e['error'][-1]:.1e}")

out = Path("block_pulse_out")  # beside where it runs
out.mkdir(exist_ok=True)
sc.plot_time_history(res, ["ux", "uy"], path=out / "block_pulse_dynamic.png")
sc.plot_energy(res, path=out / "block_pulse_energy.png")
print(f"figures: {out / 'block_pulse_dynamic.png'}, {out / 'block_pulse_energy.png'}")
for key in got:
    assert abs(got[key] / ref[key] - 1) < 1e-3, key
# (round-off: the step's right-hand side carries 4 M u/Δt², so each step loses ~1e-12 of it)
assert abs(e["error"][-1]) < 1e-6 * e["external"][-1]
