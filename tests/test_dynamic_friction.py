"""Friction in dynamics: a body brought to rest by friction, slip → stick of rigid and compliant
(Jenkins) friction located inside the step, and no chatter of a corner — against closed forms.

* a rigid block (mass m) on a rough rigid floor pushed by a pulse P(t): it starts to slide when
  P = f W, slides with m ẍ = P(t) − f W, and after the pulse decelerates at f g until it stops
  (closed form below); at rest with no load its friction force is zero;
* a Jenkins element (a tangential spring C_τ in series with the slider, eq. (11)) and rigid
  friction, each beside a spring k to the ground: from the friction limit the block slides
  under a constant push as a harmonic oscillator about its shifted equilibrium and stops after
  half a period π/ω, ω = √(k/m); the stop time converges at order 2 in Δt (eq. (10));
* a Jenkins element beside a spring k under a harmonic force: every stick → slip and slip →
  stick against an independent integration of the stick-slip oscillator (scipy's solve_ivp
  with event location);
* a stiff block on a rigid base under a half-sine ground acceleration: the rigid-block slide,
  with the number of events stable under refinement of Δt.
"""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.enums import Status, Transition
from stepcontact.model.timefunction import Constant, Harmonic, Pulse
from stepcontact.solver.program import solve_dynamic

G = 9.81


def floor_block(mass: float, f: float, k: float = 0.0, kt: float = np.inf, push: float = 0.0):
    """A block (DOFs ux, uy) on a rough floor, held by a spring k in x; the contact's layer
    C_τ = kt (inf: rigid); the static run puts on the weight (and a push along x)."""
    W = mass * G
    program = [sc.Segment("weight", 1.0)] + ([sc.Segment("push", push)] if push else [])
    dm = sc.DiscreteModel(K=[[k, 0.0], [0.0, 0.0]], normal_rows=[[0, 1]],
                          tangent_rows=[[1, 0]], loads={"weight": {"uy": -W}, "push": {"ux": 1.0}},
                          friction=f, kt=kt, dof_names=("ux", "uy"), program=program)
    st = sc.solve_static(dm)
    assert st.status == Status.COMPLETED
    return dm, st, np.diag([mass, mass])


def stops(res) -> list:
    return [e for e in res.events if e.transition == Transition.STUCK]


def zero_duration_pairs(res) -> int:
    """Events of one CFE that another of its events undoes at the same instant."""
    seen = Counter((e.cfe, e.lam) for e in res.events)
    return sum(c - 1 for c in seen.values() if c > 1)


def half_sine_closed_form(m_, f, P0, tp):
    """Rigid block pushed by P0 sin(π t/t_p) (P0 > f W), stopping after the pulse: start of the
    slide t_s = t_p/π asin(f W/P0); m v(t) = P0 t_p/π (cos(π t_s/t_p) − cos(π t/t_p))
    − f W (t − t_s); x(t) its integral; after t_p the deceleration f g: the stop at
    t_p + v(t_p)/(f g), the slide x(t_p) + v(t_p)²/(2 f g)."""
    W = m_ * G
    ts = tp / np.pi * np.arcsin(f * W / P0)
    c0 = np.cos(np.pi * ts / tp)
    v1 = (P0 * tp / np.pi * (c0 + 1.0) - f * W * (tp - ts)) / m_
    x1 = (P0 * tp / np.pi * (c0 * (tp - ts) + tp / np.pi * np.sin(np.pi * ts / tp))
          - 0.5 * f * W * (tp - ts) ** 2) / m_
    assert v1 > 0  # it still slides when the pulse ends
    return ts, tp + v1 / (f * G), x1 + v1**2 / (2 * f * G)


def test_a_block_stopped_by_friction_after_a_half_sine_pulse_keeps_no_friction_force():
    """Start of the slide, stop time and slide against the closed form (errors O(Δt²):
    measured 6.4e-7 s, 1.3e-5 s and 9e-5 relative at Δt = 1 ms; tolerances 0.01 Δt, 0.05 Δt
    and 2e-4); after the stop, with no load,
    |Q| ≤ 1e-9 f W (round-off; measured 2e-10) and no event fires."""
    m_, f, tp, dt = 1000.0, 0.3, 0.2, 1e-3
    W = m_ * G
    P0 = 3 * f * W
    dm, st, M = floor_block(m_, f)
    res = solve_dynamic(dm, dt=dt, duration=0.6, loads={"push": Pulse(P0, 0.0, tp, "half_sine")},
                        mass=M, initial=st)
    assert res.status == Status.COMPLETED
    assert res.violation.max() < 1e-9
    ts, t_stop, slide = half_sine_closed_form(m_, f, P0, tp)
    assert res.events[0].transition == Transition.SLIP_POS
    assert res.events[0].lam == pytest.approx(ts, abs=0.01 * dt)
    (stop,) = stops(res)
    assert abs(stop.lam - t_stop) < 0.05 * dt
    assert res.u[-1][0] == pytest.approx(slide, rel=2e-4)
    after = np.arange(res.n_states) >= stop.state
    assert np.abs(res.Q[after]).max() <= 1e-9 * f * W
    assert not [e for e in res.events if e.lam > stop.lam]


def test_a_stop_at_the_end_of_a_step_re_solves_the_friction_force():
    """A rectangular pulse 1.5 f W for t_p = 0.3 s: a₁ = (P − f W)/m = f g/2, the stop at
    t_p (1 + 1/2) = 0.45 s — the end of step 150 at Δt = 3 ms, where the slip velocity is zero
    at the step's end, so the stop is decided at the next step's start.  The friction force
    then is what equilibrium requires (0), not f W, with no events after (before: Q = ±f W
    alternating every step with the accelerations ±f g).  Closed forms: stop time and slide
    ½ a₁ t_p² + (a₁ t_p)²/(2 f g) to 1e-9 (Newmark is exact for piecewise constant forces);
    |Q| ≤ 1e-9 f W after the stop."""
    m_, f, tp, dt = 1000.0, 0.3, 0.3, 3e-3
    W = m_ * G
    P = 1.5 * f * W
    dm, st, M = floor_block(m_, f)
    res = solve_dynamic(dm, dt=dt, duration=0.9, loads={"push": Pulse(P, 0.0, tp, "rectangular")},
                        mass=M, initial=st)
    assert res.status == Status.COMPLETED
    a1 = (P - f * W) / m_
    (stop,) = stops(res)
    assert stop.lam == pytest.approx(1.5 * tp, rel=1e-9)
    assert res.u[-1][0] == pytest.approx(0.5 * a1 * tp**2 + (a1 * tp) ** 2 / (2 * f * G),
                                         rel=1e-9)
    after = np.arange(res.n_states) >= stop.state
    assert np.abs(res.Q[after]).max() <= 1e-9 * f * W
    assert np.abs(res.a[after][:, 0]).max() <= 1e-9 * f * G
    assert not [e for e in res.events if e.lam > stop.lam]


def test_a_stop_re_solves_the_friction_force_beside_compliant_contacts():
    """The same stop at the end of a step, in a model that also has a compliant contact (a
    wall with C_n = C_τ = 1e6 N/m, 1 m away, open): the rigid CFE's friction force is re-solved
    at its stop all the same (the compliant one's force, which follows its displacements, is
    held), |Q| ≤ 1e-9 f W after it (before: f W) and no events after.  (Here the pulse's jump at
    t = 0 is not followed in accelerations, the slip starts within the first step: the stop
    time within one step of the closed form 0.45 s.)"""
    m_, f, tp, dt = 1000.0, 0.3, 0.3, 3e-3
    W = m_ * G
    dm = sc.DiscreteModel(K=[[0.0, 0.0], [0.0, 0.0]], normal_rows=[[0, 1], [-1, 0]],
                          tangent_rows=[[1, 0], [0, 1]],
                          loads={"weight": {"uy": -W}, "push": {"ux": 1.0}}, friction=[f, 0.0],
                          kn=[np.inf, 1e6], kt=[np.inf, 1e6], gaps=[0.0, 1.0],
                          dof_names=("ux", "uy"), program=[sc.Segment("weight", 1.0)])
    st = sc.solve_static(dm)
    res = solve_dynamic(dm, dt=dt, duration=0.9, mass=np.diag([m_, m_]), initial=st,
                        loads={"push": Pulse(1.5 * f * W, 0.0, tp, "rectangular")})
    assert res.status == Status.COMPLETED
    (stop,) = stops(res)
    assert abs(stop.lam - 1.5 * tp) <= dt
    after = np.arange(res.n_states) >= stop.state
    assert np.abs(res.Q[after][:, 0]).max() <= 1e-9 * f * W
    assert not [e for e in res.events if e.lam > stop.lam]


@pytest.mark.parametrize("dt", [1e-3, 5e-4])
def test_jenkins_element_slips_and_stops_at_the_closed_form_times(dt):
    """A block on a compliant tangential layer C_τ (no spring to the ground) pushed by a
    rectangular pulse P = 3 f N for 0.05 s.  Stuck: x = P/C_τ (1 − cos ω t), ω = √(C_τ/m),
    slipping where C_τ x = f N: t₁ = acos(1 − f N/P)/ω; then m ẍ = P − f N until the pulse
    ends and −f N after, so the stop (ẋ = 0) is at t_p + v(t_p)/(f g).  Errors measured at
    Δt = 1 ms: 1.2e-6 s and 1.3e-5 s (before the fix the stop was found a step late: 4.8e-4 s);
    tolerance 0.05 Δt for both.  No zero-duration slip/stick pairs."""
    m_, f, kt, tp = 1.0, 0.3, 1e3, 0.05
    N = m_ * G
    P = 3 * f * N
    dm, st, M = floor_block(m_, f, kt=kt)
    w = np.sqrt(kt / m_)
    t1 = np.arccos(1 - f * N / P) / w
    v_tp = P / kt * w * np.sin(w * t1) + (P - f * N) / m_ * (tp - t1)
    t_stop = tp + v_tp / (f * G)
    res = solve_dynamic(dm, dt=dt, duration=0.3, loads={"push": Pulse(P, 0.0, tp, "rectangular")},
                        mass=M, initial=st)
    assert res.status == Status.COMPLETED
    slip = [e.lam for e in res.events if e.transition == Transition.SLIP_POS]
    assert abs(slip[0] - t1) < 0.05 * dt
    assert abs(stops(res)[0].lam - t_stop) < 0.05 * dt
    assert zero_duration_pairs(res) == 0


@pytest.mark.parametrize("kt", [np.inf, 1e4], ids=["rigid", "jenkins"])
def test_slip_to_stick_time_converges_at_second_order(kt):
    """A block (m = 1 kg, f = 0.3) held by a spring k = 1000 N/m, pushed statically to its
    friction limit (P_s = f N (1 + k/C_τ): the layer carries f N), then a further push
    ΔP = f N/2 at t = 0: it slides about its shifted equilibrium, x(t) = x_e + (x₀ − x_e)
    cos ω t, ω = √(k/m) (the layer's force stays f N), and stops at t = π/ω.  The error of
    the stop time over Δt = 4, 2, 1, 0.5 ms: the slope of log error against log Δt is
    2 ± 0.3 (measured 2.00 for both; before the fix, 0.79 for the Jenkins element)."""
    m_, f, k = 1.0, 0.3, 1e3
    N = m_ * G
    dm, st, M = floor_block(m_, f, k=k, kt=kt, push=f * N * (1 + k / kt))
    t_stop = np.pi / np.sqrt(k / m_)
    dts = np.array([4e-3, 2e-3, 1e-3, 5e-4])
    err = []
    for dt in dts:
        res = solve_dynamic(dm, dt=dt, duration=1.2 * t_stop, loads={"push": Constant(0.5 * f * N)},
                            mass=M, initial=st)
        assert res.status == Status.COMPLETED
        err.append(abs(stops(res)[0].lam - t_stop))
    order = np.polyfit(np.log(dts), np.log(err), 1)[0]
    assert abs(order - 2.0) <= 0.3


def jenkins_reference(m_, k, kt, fN, force, T):
    """Event times of m ẍ + k x + Q = F(t), Q = C_τ (x − z), |Q| ≤ f N, the slider z moving
    only where |Q| = f N (in the direction of Q): stuck, ẍ from the spring forces and events
    where Q reaches ±f N; slipping, m ẍ = F − k x ∓ f N and the stop where ẋ = 0 (it sticks
    there, or slips on the same way if the stuck acceleration would push Q beyond the limit).
    Dormand–Prince 8 with rtol 1e-12 and located events (scipy's solve_ivp)."""
    from scipy.integrate import solve_ivp

    def stuck(t, y, z):
        return [y[1], (force(t) - k * y[0] - kt * (y[0] - z)) / m_]

    def up(t, y, z):
        return kt * (y[0] - z) - fN

    def down(t, y, z):
        return kt * (y[0] - z) + fN

    def sliding(t, y, sg):
        return [y[1], (force(t) - k * y[0] - sg * fN) / m_]

    def halt(t, y, sg):
        return y[1]

    up.terminal = down.terminal = halt.terminal = True
    up.direction, down.direction = 1, -1
    opts = {"rtol": 1e-12, "atol": 1e-14, "method": "DOP853"}
    t, y, z, sg, out = 0.0, np.zeros(2), 0.0, 0, []
    while True:
        if sg == 0:
            sol = solve_ivp(stuck, (t, T), y, events=[up, down], args=(z,), **opts)
        else:
            halt.direction = -sg
            sol = solve_ivp(sliding, (t, T), y, events=[halt], args=(sg,), **opts)
        t, y = sol.t[-1], sol.y[:, -1]
        if sol.status != 1:
            return out
        if sg == 0:
            sg = 1 if sol.t_events[0].size else -1
            out.append((t, Transition.SLIP_POS if sg > 0 else Transition.SLIP_NEG))
            continue
        y = np.array([y[0], 0.0])
        z = y[0] - sg * fN / kt
        if sg * (force(t) - k * y[0] - sg * fN) <= 0:  # (else it slips on the same way)
            sg = 0
            out.append((t, Transition.STUCK))


def test_forced_jenkins_element_against_an_independent_integration():
    """m = 1 kg, k = 400 N/m, C_τ = 2000 N/m, f N = 0.3 × 9.81 N, F = 6 sin(2π · 2 t) N for
    1.6 s: 12 stick → slip and slip → stick events in both directions.  Every transition as
    the reference's, at times within 0.05 Δt (measured max 4.3e-5 s at Δt = 2 ms, 1.1e-5 s at
    1 ms: second order; before the fix 4.8e-4 and 4.3e-4 s, a stop found a step late), the
    error falling at least 3 times when Δt halves."""
    m_, k, kt, f, F0, fr, T = 1.0, 400.0, 2e3, 0.3, 6.0, 2.0, 1.6
    N = m_ * G
    ref = jenkins_reference(m_, k, kt, f * N, lambda t: F0 * np.sin(2 * np.pi * fr * t), T)
    assert len(ref) >= 12
    dm = sc.DiscreteModel(K=[[k, 0.0], [0.0, 0.0]], normal_rows=[[0, 1]], tangent_rows=[[1, 0]],
                          loads={"weight": {"uy": -N}, "push": {"ux": 1.0}}, friction=f, kt=kt,
                          dof_names=("ux", "uy"), program=[sc.Segment("weight", 1.0)])
    st = sc.solve_static(dm)
    errors = []
    for dt in (2e-3, 1e-3):
        res = solve_dynamic(dm, dt=dt, duration=T, loads={"push": Harmonic(F0, fr)},
                            mass=np.diag([m_, m_]), initial=st)
        assert res.status == Status.COMPLETED
        got = [(e.lam, e.transition) for e in res.events]
        assert [tr for _, tr in got] == [tr for _, tr in ref]
        errors.append(max(abs(a - b) for (a, _), (b, _) in zip(got, ref, strict=True)))
        assert errors[-1] < 0.05 * dt
    assert errors[1] < errors[0] / 3


def test_a_corner_does_not_chatter_under_a_ground_acceleration_pulse():
    """A stiff block (2 m × 1 m, E = 3e11 Pa, 4 × 2 elements) on a rigid base, f = 0.5, under a
    half-sine ground acceleration g sin(π t/0.2 s): the rigid-block slide (relative to the
    ground) starts at t_s = t_p/π asin(f g/a) and decelerates at f g after the pulse; closed
    form −0.0542328 m (errors measured 1.8e-3 and 1.1e-4 relative at Δt = 4 and 1 ms;
    tolerances 3e-3 and 5e-4).  The trailing corner, its normal force near zero while the
    block slides, used to open and close again at the same instant every few steps (44 events
    at Δt = 1 ms against 10 at 4 ms); now, while the block slides, each CFE only starts to slip
    (5 events), none undone at its instant.  After the stop the undamped elastic block recoils
    on its base (stick/slip of single CFEs at distinct instants, from 10 events in all at 4 ms
    to 16 at 1 ms, and hundreds at 0.25 ms where its kHz modes are resolved: the discrete
    model's own vibration, not chatter).  With HHT-α = 0.1 damping those unresolved modes, the
    whole run's event count converges: within +20 % from Δt = 4 ms to 1 and 0.25 ms (measured
    12, 10, 10), the slide within the same tolerances."""
    f, tp, amp = 0.5, 0.2, G
    blk = sc.rectangle("block", (0, 0), (2.0, 1.0), 4, 2, sc.Material(3e11, 0.2, 2400.0))
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (3.0, 0.0)])
    m = sc.Model(name="block-on-rigid-base").add(blk)
    m = m.add(sc.Interface("base", m.select("block", y=0.0), ground, friction=f),
              sc.LoadPattern("weight", [sc.BodyForce()]), sc.Segment("weight", 1.0))
    st = sc.solve_static(m)
    xdofs = sc.assemble(m).dofs.of[:, 0]
    # closed form of the rigid block
    ts = tp / np.pi * np.arcsin(f * G / amp)
    c0 = np.cos(np.pi * ts / tp)
    v1 = -(amp * tp / np.pi * (c0 + 1.0) - f * G * (tp - ts))
    x1 = -(amp * tp / np.pi * (c0 * (tp - ts) + tp / np.pi * np.sin(np.pi * ts / tp))
           - 0.5 * f * G * (tp - ts) ** 2)
    slide = x1 - v1**2 / (2 * f * G)
    t_stop = tp - v1 / (f * G)
    counts = []
    for dt, tol in ((4e-3, 3e-3), (1e-3, 5e-4)):
        res = sc.solve_dynamic(m, dt=dt, duration=0.4, initial=st, mass="lumped",
                               ground_acceleration=(Pulse(amp, 0.0, tp, "half_sine"), (1, 0)))
        assert res.status == Status.COMPLETED
        assert res.violation.max() < 1e-9
        assert res.u[-1][xdofs].mean() == pytest.approx(slide, rel=tol)
        assert zero_duration_pairs(res) == 0
        # while it slides, each CFE starts to slip once and nothing else happens (no chatter)
        sliding = [e for e in res.events if e.lam < t_stop - 0.01]
        assert sorted(e.cfe for e in sliding) == list(range(5))
        assert all(e.transition == Transition.SLIP_NEG for e in sliding)
    for dt, tol in ((4e-3, 3e-3), (1e-3, 5e-4), (2.5e-4, 5e-4)):
        res = sc.solve_dynamic(m, dt=dt, duration=0.4, initial=st, mass="lumped", alpha=0.1,
                               ground_acceleration=(Pulse(amp, 0.0, tp, "half_sine"), (1, 0)))
        assert res.status == Status.COMPLETED
        assert res.u[-1][xdofs].mean() == pytest.approx(slide, rel=tol)
        assert zero_duration_pairs(res) == 0
        counts.append(len(res.events))
    assert max(counts[1:]) <= 1.2 * counts[0]
