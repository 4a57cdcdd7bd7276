"""The order of the dynamic solver's cut steps (eq. (10)): a stick → slip and a slip → stick
event located inside steps, the state cut there and Newmark restarted from it, converge at
second order in Δt where the steps resolve the motion.

The model: a rigid block m₁ on a rigid frictional base (f, normal force f (m₁ + m₂) g) carrying
a mass m₂ on a horizontal spring k (5 Hz), under a rectangular ground pulse A = 0.25 g for
0.3 s.  The block alone (m₁ A < f (m₁ + m₂) g) sticks at first; the spring's force, rising as
m₂ lags, makes it slip at t ≈ 0.03 s, inside a step; it stops after the pulse, inside a step.
The reference is an independent event-located integration in the test (scipy's solve_ivp,
DOP853, rtol 1e-12), stick and slip phases switched by Coulomb's law at the located times.

(Where a step does not resolve the motion — a stiff spring, ω Δt ≫ 1, or a stiff elastic block,
tests/test_newmark.py — the contact force of the stuck scheme at the step's end is the
trapezoidal rule's overshoot of the unresolved mode, the stick → slip time (10) falls at a fixed
fraction of Δt, and the slide lags by (A − N) times that time: first order, by design of (10).)
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

import stepcontact as sc
from stepcontact.enums import Status
from stepcontact.model.timefunction import Pulse

G = 9.81
M1, M2, F = 1000.0, 500.0, 0.2  # kg, kg, friction coefficient
OMEGA = 2 * np.pi * 5.0  # rad/s, the carried mass on its spring
K = M2 * OMEGA**2  # N/m
A, T0, T_END = 0.25 * G, 0.3, 0.45  # m/s², s, s
N_LIMIT = F * (M1 + M2) * G  # N, the friction limit


def reference() -> tuple[float, float, float]:
    """(slip start, stop time, slide) of the block by solve_ivp with event location: stick
    while |m₁ a_g − k (x₂ − x₁)| ≤ f N (the friction force that holds the block), slip
    m₁ ẍ₁ = k (x₂ − x₁) − m₁ a_g − s f N (s the sign of ẋ₁) until ẋ₁ = 0; m₂ ẍ₂ =
    −k (x₂ − x₁) − m₂ a_g throughout (relative coordinates, a_g = A for t < t₀, 0 after)."""
    opts = {"rtol": 1e-12, "atol": 1e-14, "method": "DOP853"}
    x2, v2 = 0.0, 0.0

    def stick_limit(t, y):  # the holding force reaches the limit (the block alone: A)
        return M1 * A - K * y[0] - N_LIMIT

    stick_limit.terminal, stick_limit.direction = True, 1
    stick = solve_ivp(lambda t, y: [y[1], -K * y[0] / M2 - A], (0.0, T0), [x2, v2],
                      events=stick_limit, **opts)
    assert stick.status == 1  # it slips during the pulse
    t_slip = stick.t[-1]
    s = np.sign(K * stick.y[0, -1] - M1 * A)  # the slip's direction (−1: against the ground)

    def slipping(ag):
        return lambda t, y: [y[1], (K * (y[2] - y[0]) - M1 * ag - s * N_LIMIT) / M1, y[3],
                             (-K * (y[2] - y[0]) - M2 * ag) / M2]

    def stops(t, y):
        return y[1]

    stops.terminal, stops.direction = True, -s
    y0 = [0.0, 0.0, stick.y[0, -1], stick.y[1, -1]]
    during = solve_ivp(slipping(A), (t_slip, T0), y0, events=stops, **opts)
    assert during.status == 0  # still slipping when the pulse ends
    after = solve_ivp(slipping(0.0), (T0, T_END), during.y[:, -1], events=stops, **opts)
    assert after.status == 1
    x1, _, x2, _ = after.y[:, -1]
    assert abs(K * (x2 - x1)) < N_LIMIT  # it stays stuck after the stop
    return t_slip, after.t[-1], x1


def test_cut_steps_converge_at_second_order_where_the_steps_resolve_the_motion():
    """The stop time (a slip → stick cut, after a stick → slip cut) against :func:`reference`
    at Δt = 8, 4, 2, 1 ms (ω Δt ≤ 0.25): order ≥ 1.8 by np.polyfit on log–log (measured 2.1;
    errors 4.2e-4, 1.2e-4, 1.8e-5, 5.4e-6 s).  Each error within Newmark's period error: the
    average acceleration rule lengthens the period by (ω Δt)²/12 relative, a time measured along
    the motion by at most that fraction of it — tolerance (ω Δt)²/12 · t_stop (measured 0.15–0.24
    of it), and (ω Δt)²/12 · t_slip for the slip's start (measured 0.09–0.21 of it); the slide
    within 1e-3 relative (measured 7.1e-4 at 8 ms, 7.3e-6 at 1 ms)."""
    t_slip, t_stop, slide = reference()
    dm = sc.DiscreteModel(K=[[K, 0, -K], [0, 0, 0], [-K, 0, K]], normal_rows=[[0, 1, 0]],
                          tangent_rows=[[1, 0, 0]],
                          loads={"weight": {"uy": -(M1 + M2) * G}}, friction=F,
                          dof_names=("ux", "uy", "u2"),
                          dof_axes={"ux": "x", "uy": "y", "u2": "x"},
                          program=[sc.Segment("weight", 1.0)])
    st = sc.solve_static(dm)
    assert st.status == Status.COMPLETED
    dts = np.array([8e-3, 4e-3, 2e-3, 1e-3])
    errors = []
    for dt in dts:
        res = sc.solve_dynamic(dm, dt=dt, duration=T_END, mass=np.diag([M1, M1 + M2, M2]),
                               initial=st,
                               ground_acceleration=(Pulse(A, 0.0, T0, "rectangular"), (1, 0)))
        assert res.status == Status.COMPLETED
        assert len(res.events) == 2  # slip, stuck
        period_error = (OMEGA * dt) ** 2 / 12
        assert abs(res.events[0].lam - t_slip) < period_error * t_slip
        errors.append(abs(res.events[1].lam - t_stop))
        assert errors[-1] < period_error * t_stop
        assert abs((res.u[-1][0] - res.u[0][0]) / slide - 1) < 1e-3
    order = np.polyfit(np.log(dts), np.log(errors), 1)[0]
    assert order >= 1.8, (order, errors)
