"""A slab on an elastic foundation hit from below by a pressure pulse: where and when it lifts.

The slab of `slab_uplift.py` (10 m × 1 m concrete on a 14 m × 6 m rock foundation, a
frictional joint, f = 0.7, non-matching meshes) rests under its weight (a static run); then an
uplift pulse, triangular along the joint (largest upstream) and half-sine in time, acts for
40 ms (`sc.solve_dynamic`: Newmark's average acceleration, lumped mass, Δt = 0.5 ms).  Its
peak is twice the uplift at which the static solver opens the joint; the upstream end lifts
off, flies and lands again.

Printed: the static opening pressure, the time of the first lift-off against the time at which
the pulse reaches the static opening pressure (inertia delays it), the largest uplift of the
upstream end, the landing, and the energy ledger.  The landing excites vibrations of the slab
far faster than Δt resolves (its 1 m thickness is crossed by a wave in 0.3 ms): the cuts at
the landing's events remove most of their energy, which the ledger books as `numerical` (see
the user guide, "The cuts' numerical dissipation"); the lift-off comes before it.
Figures (in ./slab_pulse_out/): the contact stresses at chosen instants
(`slab_pulse_stresses.png`), the upstream end's displacements and velocities with the events
(`slab_pulse_history.png`), every CFE's state against time (`slab_pulse_timeline.png`) and the
energy ledger (`slab_pulse_energy.png`).
Run:  python examples/slab_pulse_dynamic.py
"""

import runpy
from pathlib import Path

import numpy as np

import stepcontact as sc
from stepcontact.enums import Transition

# the model of slab_uplift.py (its function, without running that script)
slab_model = runpy.run_path(str(Path(__file__).with_name("slab_uplift.py")),
                            run_name="slab_uplift")["slab_model"]
m = slab_model()
static = sc.solve_static(m)
p_open = static.multipliers[-1].first_opening  # upstream uplift (Pa) that opens the joint
rest = sc.solve_static(m.replace(program=(sc.Segment("weight", 1.0),)))

start, length = 0.005, 0.040  # s
pulse = sc.Pulse(2.0 * p_open, start, length, "half_sine")
res = sc.solve_dynamic(m, dt=5e-4, duration=0.1, initial=rest, mass="lumped",
                       loads={"uplift": pulse})
print(res.summary())

# ---- what happened ------------------------------------------------------------------------
opened = [e for e in res.events if e.transition == Transition.OPENED]
t_lift = min(e.lam for e in opened)
# the pulse reaches the static opening pressure where 2 sin(π (t − start)/length) = 1
t_static = start + length / 6.0
upstream = int(np.argmin(np.where(res.cfe["interface"] == 0, res.cfe["x"][:, 0], np.inf)))
gap = -res.un[:, upstream]  # opening of the upstream CFE, m (un < 0 when open)
i_peak = int(np.argmax(gap))
closed = [e.lam for e in res.events if e.transition == Transition.CLOSED and e.lam > t_lift]
print(f"static: the joint opens at an upstream uplift of {p_open:,.0f} Pa; the pulse peaks at "
      f"{2 * p_open:,.0f} Pa, {1e3 * (start + length / 2):.1f} ms")
print(f"first lift-off {1e3 * t_lift:.3f} ms; the pulse passes the static opening pressure at "
      f"{1e3 * t_static:.3f} ms (inertia delays the lift-off by {1e3 * (t_lift - t_static):.3f}"
      f" ms)")
print(f"largest opening of the upstream end {1e3 * gap[i_peak]:.3f} mm at "
      f"{1e3 * res.time[i_peak]:.2f} ms; last landing {1e3 * max(closed):.2f} ms; "
      f"{sum(e.transition == Transition.OPENED for e in res.events)} openings, "
      f"{len(closed)} closings, {res.counters['impacts']} impacts")
e = res.energy
work = float(np.abs(e["external"]).max())
print("energy (J per m): " + ", ".join(f"{k} {v[-1]:.4g}" for k, v in e.items()))

out = Path("slab_pulse_out")
out.mkdir(exist_ok=True)
res.save(out / "slab_pulse.nc")
times = [start, t_lift, float(res.time[i_peak])]
sc.plot_interfaces(res, times, path=out / "slab_pulse_stresses.png")
# the slab's upstream bottom corner (2, 0): the nearest node of the slab (the foundation has
# one there too); its u_x, u_y and v_x, v_y, each curve named by its node and direction
sc.plot_time_history(res, point=(2.0, 0.0), body="slab", path=out / "slab_pulse_history.png")
sc.plot_event_timeline(res, path=out / "slab_pulse_timeline.png")
sc.plot_energy(res, path=out / "slab_pulse_energy.png")
print(f"result and figures written to {out}/")

# ---- checks ---------------------------------------------------------------------------------
assert res.status == sc.Status.COMPLETED
assert t_lift > t_static  # a body with mass lifts later than the load's static opening
assert gap[i_peak] > 0 and max(closed) > res.time[i_peak]  # it lifts and lands again
assert abs(e["error"]).max() < 1e-9 * work  # the ledger closes to round-off
assert res.residual.max() < 1e-9 and res.violation.max() < 1e-9
