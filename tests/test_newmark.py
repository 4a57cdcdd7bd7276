"""Newmark's (1965) rigid-block sliding (:func:`stepcontact.newmark_sliding`) and a dynamic
run's permanent slip beside it (:func:`stepcontact.joint_slip`,
:func:`stepcontact.sliding_comparison`), against closed forms and independent integrations.

* a rectangular pulse of amplitude A and duration t₀ on a block of yield acceleration N (all
  in m/s²): d = V²/(2N)(1 − N/A), V = A t₀ (derivation in the test) — the integrator to
  1e-12, the project's dynamic solver on a rigid discrete block and on a stiff elastic block
  on a rigid frictional base (tolerances derived from Δt in each test);
* a ramp record, the crossing of a_y inside a piece: closed form to 1e-12; a record refined by
  samples on its own lines: the same answer to round-off (the integration is exact per piece);
* one sine cycle of 0.5 g at 1 s for a_y = 0.1, 0.2, 0.3 g, one- and two-directional: the
  integrator against scipy's solve_ivp with event location on the exact sine, and the dynamic
  solver against the integrator;
* the comparison table and the rigid block's yield acceleration f g; errors name the argument.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import stepcontact as sc
from stepcontact.enums import Status
from stepcontact.errors import ModelError
from stepcontact.model.timefunction import Pulse

G = 9.81
MASS = 1000.0  # kg


def rectangular_pulse(A: float, N: float, t0: float) -> tuple[float, float]:
    """Newmark's rigid block under a rectangular pulse: (sliding distance, stop time).

    While the pulse lasts (0 ≤ t ≤ t₀) the ground accelerates at A > N and the block, held by
    friction at N, lags behind it at the relative acceleration A − N: at t₀ its relative
    velocity is v₁ = (A − N) t₀ and it has slid d₁ = (A − N) t₀²/2.  After the pulse the
    ground moves uniformly and friction decelerates the block at N: it stops after v₁/N,
    sliding d₂ = v₁²/(2N) more.  d = d₁ + d₂ = (A − N) t₀²/(2N) · (N + A − N)
    = A² t₀²/(2N) (1 − N/A) = V²/(2N)(1 − N/A), V = A t₀ — Newmark's V²/(2gN)(1 − N/A) with
    N and A in g."""
    V = A * t0
    return V**2 / (2 * N) * (1 - N / A), t0 + (A - N) * t0 / N


def discrete_block(f: float):
    """A rigid block of mass MASS (DOFs ux, uy, translations along x and y) on a rigid
    frictional base (friction f: yield acceleration f g), at rest under its weight."""
    dm = sc.DiscreteModel(K=[[0.0, 0.0], [0.0, 0.0]], normal_rows=[[0, 1]],
                          tangent_rows=[[1, 0]], loads={"weight": {"uy": -MASS * G}},
                          friction=f, dof_names=("ux", "uy"), dof_axes={"ux": "x", "uy": "y"},
                          program=[sc.Segment("weight", 1.0)])
    st = sc.solve_static(dm)
    assert st.status == Status.COMPLETED
    return dm, st


# ---- the integrator against closed forms ------------------------------------------------------
@pytest.mark.parametrize("A, N, t0", [(0.5 * G, 0.2 * G, 0.5), (3.0, 1.0, 0.1),
                                      (0.3 * G, 0.29 * G, 2.0)])
@pytest.mark.parametrize("two_way", [False, True])
def test_rectangular_pulse_slides_newmarks_closed_form(A, N, t0, two_way):
    """The record (0, A), (t₀, A), zero after it: the slide, its stop time and the peak
    relative velocity (A − N) t₀ against :func:`rectangular_pulse`, to 1e-12 relative
    (round-off: a handful of operations)."""
    d, t_stop = rectangular_pulse(A, N, t0)
    r = sc.newmark_sliding([0.0, t0], [A, A], N, two_way=two_way)
    # a positive ground acceleration slides the block towards −x relative to the ground
    assert r.permanent == pytest.approx(-d, rel=1e-12)
    assert r.magnitude == pytest.approx(d, rel=1e-12)
    assert len(r.slides) == 1
    start, stop, direction = r.slides[0]
    assert start == 0.0 and direction == -1
    assert stop == pytest.approx(t_stop, rel=1e-12)
    assert r.velocity.min() == pytest.approx(-(A - N) * t0, rel=1e-12)
    assert r.displacement[-1] == r.permanent and r.velocity[-1] == 0.0


def test_ramp_crossing_inside_a_piece_against_its_closed_form():
    """a(t) = c t on 0 ≤ t ≤ T (7 samples, a_y crossed inside the third piece), zero after:
    sliding from t_s = a_y/c with s(t) = c (t² − t_s²)/2 − a_y (t − t_s), so at T
    s₁ = s(T) and x₁ = c (T³ − t_s³)/6 − c t_s² (T − t_s)/2 − a_y (T − t_s)²/2; then it
    decelerates at a_y: x = x₁ + s₁²/(2 a_y), stop at T + s₁/a_y.  To 1e-12 relative."""
    c, T, ay = 4.0, 1.2, 1.0
    t = np.linspace(0.0, T, 7)
    r = sc.newmark_sliding(t, c * t, ay)
    ts = ay / c
    s1 = c * (T**2 - ts**2) / 2 - ay * (T - ts)
    x1 = c * (T**3 - ts**3) / 6 - c * ts**2 * (T - ts) / 2 - ay * (T - ts) ** 2 / 2
    assert r.permanent == pytest.approx(-(x1 + s1**2 / (2 * ay)), rel=1e-12)
    assert r.slides[0][0] == pytest.approx(ts, rel=1e-12)
    assert r.slides[0][1] == pytest.approx(T + s1 / ay, rel=1e-12)
    # the history holds the samples, the start of the slide and its stop after the record
    assert len(r.time) == len(t) + 2
    # a record starting at a_y exactly and rising slides from its first sample, listed once
    r0 = sc.newmark_sliding([0.0, 1.0, 2.0], [ay, 2 * ay, 0.0], ay)
    assert r0.slides[0][0] == 0.0 and np.all(np.diff(r0.time) > 0)
    k = np.searchsorted(r.time, 0.9)
    assert r.velocity[k] == pytest.approx(-(c * (r.time[k]**2 - ts**2) / 2
                                            - ay * (r.time[k] - ts)), rel=1e-12)


@pytest.mark.parametrize("two_way", [False, True])
def test_samples_on_the_records_own_lines_change_nothing(two_way):
    """A record refined by 9 samples on each of its straight pieces (the same piecewise-linear
    function) slides the same, to 1e-12 of the total sliding path: the integration is exact
    per piece, not a time-stepping whose answer depends on the sampling.  The record (800
    irregular samples, several slides both ways) runs past the 256-sample scanning window."""
    rng = np.random.default_rng(29)
    t = np.cumsum(rng.uniform(0.002, 0.02, 800))
    a = 3.0 * np.sin(7.0 * t) + 2.0 * np.sin(23.0 * t + 1.0) + rng.normal(0.0, 0.5, t.size)
    r = sc.newmark_sliding(t, a, 1.5, two_way=two_way)
    fine = np.linspace(0.0, 1.0, 11)[:-1]
    tf = np.append((t[:-1, None] + np.diff(t)[:, None] * fine).ravel(), t[-1])
    af = np.append((a[:-1, None] + np.diff(a)[:, None] * fine).ravel(), a[-1])
    rf = sc.newmark_sliding(tf, af, 1.5, two_way=two_way)
    path = np.abs(np.diff(r.displacement)).sum()
    assert np.all(np.diff(r.time) > 0) and np.all(np.diff(rf.time) > 0)  # each point once
    assert len(r.slides) >= 5 and len(rf.slides) == len(r.slides)
    assert abs(rf.permanent - r.permanent) <= 1e-12 * path
    assert np.allclose(np.array(rf.slides), np.array(r.slides), rtol=0, atol=1e-12 * t[-1])
    if two_way:
        assert {d for *_, d in r.slides} == {-1, 1}


# ---- one sine cycle: the integrator against solve_ivp ----------------------------------------
A_SINE = 0.5 * G


def sine(t):
    """One cycle of 0.5 g at 1 s, zero after it, m/s²."""
    return np.where(np.asarray(t) <= 1.0, A_SINE * np.sin(2 * np.pi * np.asarray(t)), 0.0)


def sine_reference(ay: float, two_way: bool) -> tuple[float, list]:
    """The rigid block under :func:`sine`, integrated by scipy's solve_ivp (DOP853, rtol
    1e-12) from each start to the zero of its sliding velocity (event location) — each start
    the root (brentq) of a(t) = ±a_y after the last stop, or the stop itself when a(t) is then
    beyond the other limit; a slide still going at t = 1 s decelerates at a_y.  (sliding
    displacement x along the driving direction, [(start, stop, d)])."""
    t0, x, slides = 0.0, 0.0, []
    grid = np.linspace(0.0, 1.0, 10001)
    while t0 < 1.0:
        a0 = float(sine(t0))
        beyond = (sine(grid) > ay) | ((sine(grid) < -ay) if two_way else False)
        later = np.flatnonzero((grid > t0) & beyond)
        if a0 > ay or (two_way and a0 < -ay):
            ts, d = t0, (1 if a0 > ay else -1)
        elif later.size == 0:
            break
        else:
            j = later[0]
            d = 1 if sine(grid[j]) > ay else -1
            ts = brentq(lambda t, d=d: float(sine(t)) - d * ay, max(grid[j - 1], t0), grid[j],
                        xtol=1e-15, rtol=1e-15)

        def stop(t, y):
            return y[0]

        stop.terminal, stop.direction = True, -d
        sol = solve_ivp(lambda t, y, d=d: [float(sine(t)) - d * ay, y[0]], (ts, 1.0),
                        [0.0, x], method="DOP853", rtol=1e-12, atol=1e-15, events=stop,
                        max_step=1e-3, first_step=1e-9)
        if sol.status == 1:
            te, x = float(sol.t_events[0][0]), float(sol.y_events[0][0][1])
        else:  # still sliding at the end of the cycle: a = 0, deceleration a_y
            s1, x1 = sol.y[:, -1]
            te, x = 1.0 + abs(s1) / ay, x1 + d * s1**2 / (2 * ay)
        slides.append((ts, te, d))
        t0 = te
    return x, slides


@pytest.mark.parametrize("ky", [0.1, 0.2, 0.3])
@pytest.mark.parametrize("two_way", [False, True])
def test_one_sine_cycle_against_an_independent_integration(ky, two_way):
    """The integrator on the sine tabulated at 20 001 samples (h = 5e-5 s) against
    :func:`sine_reference`.  The table differs from the sine by at most A ω² h²/8 = 6e-8
    m/s², which moves the displacement by at most about that times (1 s)² and the event
    times by that over the slope of a (|ȧ| ≥ 12 m/s³ at the crossings): tolerance 2e-7 m
    and 1e-7 s (measured: ≤ 6e-9 m, ≤ 4e-9 s)."""
    ay = ky * G
    x_ref, slides_ref = sine_reference(ay, two_way)
    t = np.linspace(0.0, 1.0, 20001)
    r = sc.newmark_sliding(t, sine(t), ay, two_way=two_way)
    assert abs(r.permanent - (-x_ref)) < 2e-7
    assert len(r.slides) == len(slides_ref) == (2 if two_way else 1)
    for (a0, a1, ad), (b0, b1, bd) in zip(r.slides, slides_ref, strict=True):
        assert ad == -bd  # the relative motion is opposite to the driving direction
        assert abs(a0 - b0) < 1e-7 and abs(a1 - b1) < 1e-7


# ---- the project's dynamic solver against Newmark ---------------------------------------------
def test_dynamic_solver_on_a_rigid_block_slides_newmarks_pulse_distance():
    """The discrete rigid block (f = 0.2: a_y = 0.2 g) under the ground acceleration
    Pulse(0.5 g, 0, 0.3 s, rectangular) along x: the slide of :func:`rectangular_pulse`.
    A rigid body under piecewise-constant accelerations is integrated exactly by Newmark's
    average acceleration (its displacement is quadratic in each step), the pulse's end is a
    break the steps land on and the stop is the zero of a linear velocity: exact to
    round-off, tolerance 1e-9 relative (measured 1.2e-12 at Δt = 10 ms).  The joint's slip
    (:func:`stepcontact.joint_slip`), the table (:func:`stepcontact.sliding_comparison`) and
    the yield acceleration f g (:func:`stepcontact.rigid_block_yield`) agree."""
    f, A, t0 = 0.2, 0.5 * G, 0.3
    d, t_stop = rectangular_pulse(A, f * G, t0)
    dm, st = discrete_block(f)
    res = sc.solve_dynamic(dm, dt=0.01, duration=1.0, mass=np.diag([MASS, MASS]), initial=st,
                           ground_acceleration=(Pulse(A, 0.0, t0, "rectangular"), (1, 0)))
    assert res.status == Status.COMPLETED
    assert res.u[-1][0] == pytest.approx(-d, rel=1e-9)
    assert res.events[-1].lam == pytest.approx(t_stop, rel=1e-9)
    js = sc.joint_slip(res, "contact")
    assert js.permanent_mean == pytest.approx(-d, rel=1e-9)
    assert js.permanent_max == js.permanent_mean and not js.sliding_at_end
    # a discrete model's contact row is u_x: its slip is the block's relative displacement
    assert np.allclose(js.mean, res.u[:, 0] - res.u[0, 0], rtol=0, atol=1e-12 * d)
    ay = sc.rigid_block_yield(st, "contact", MASS)  # the state before the record
    assert ay == pytest.approx(f * G, rel=1e-12)  # f W / m
    table = sc.sliding_comparison(res, ([0.0, t0], [A, A]), ay)
    # the run's own ground_acceleration (a rectangular pulse is linear by pieces: exact)
    again = sc.sliding_comparison(res, (Pulse(A, 0.0, t0, "rectangular"), (1, 0)), ay)
    assert again.rows[0]["newmark"] == table.rows[0]["newmark"]
    row = table.rows[0]
    assert row["interface"] == "contact" and row["ratio"] == pytest.approx(1.0, rel=1e-9)
    assert row["newmark"] == pytest.approx(-d, rel=1e-12)
    assert "contact" in str(table)


def test_dynamic_solver_on_a_stiff_elastic_block_slides_newmarks_pulse_distance():
    """A stiff elastic block (2 m × 1 m, E = 3e11 Pa, 4 × 2 elements, lumped mass) on a rigid
    base, f = 0.2, under the rectangular pulse 0.5 g for t₀ = 0.2 s: the mean slip of its
    base against :func:`rectangular_pulse`.  Its five CFEs start to slip one after another
    within the first step (five cut steps, each interpolated linearly, eq. (10)), and the
    slide lags the rigid block by a velocity deficit δv = (A − N) Δt/8 set in that first step
    and constant afterwards (measured at Δt = 4 and 1 ms, at t = 0.05, 0.1 and 0.2 s).
    Allowing twice that, δv ≤ (A − N) Δt/4, the distance, ∝ v₁² with v₁ = (A − N) t₀, is off
    by at most 2 δv / v₁ = Δt/(2 t₀).
    Tolerance Δt/(2 t₀): 5e-3 and 1.25e-3 at Δt = 2 and 0.5 ms (measured
    2.5e-3 and 6.1e-4: first order, halved at least when Δt is quartered)."""
    f, A, t0 = 0.2, 0.5 * G, 0.2
    d, _ = rectangular_pulse(A, f * G, t0)
    blk = sc.rectangle("block", (0, 0), (2.0, 1.0), 4, 2, sc.Material(3e11, 0.2, 2400.0))
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (3.0, 0.0)])
    m = sc.Model(name="block").add(blk)
    m = m.add(sc.Interface("base", m.select("block", y=0.0), ground, friction=f),
              sc.LoadPattern("weight", [sc.BodyForce()]), sc.Segment("weight", 1.0))
    st = sc.solve_static(m)
    errors = []
    for dt in (2e-3, 5e-4):
        res = sc.solve_dynamic(m, dt=dt, duration=0.6, initial=st, mass="lumped",
                               ground_acceleration=(Pulse(A, 0.0, t0, "rectangular"), (1, 0)))
        assert res.status == Status.COMPLETED and res.violation.max() < 1e-9
        js = sc.joint_slip(res, "base")
        assert not js.sliding_at_end
        errors.append(abs(js.permanent_mean / -d - 1))
        assert errors[-1] < dt / (2 * t0)
        # the base's tangent is +x: the slip is the block's displacement relative to the base
        xdofs = sc.assemble(m).dofs.of[:, 0]
        assert js.permanent_mean == pytest.approx(res.u[-1][xdofs].mean(), abs=1e-6 * d)
    assert errors[1] < errors[0] / 2


@pytest.mark.parametrize("ky", [0.1, 0.2, 0.3])
def test_dynamic_solver_on_a_rigid_block_slides_as_newmark_under_a_sine(ky):
    """The discrete rigid block (f = ky: a_y = ky g, sliding both ways: the two-directional
    block) under one sine cycle of 0.5 g at 1 s, tabulated at 1001 samples, zero after
    (Tabulated(hold=False)): its slide against the integrator on the same record.  The steps
    land on every sample; over a step where the ground acceleration is linear Newmark's
    average acceleration has the exact velocity (the trapezoidal rule) and a displacement
    increment Δt v + Δt²(ü₀ + ü₁)/4 where the exact one is Δt v + Δt²(2ü₀ + ü₁)/6: the
    difference Δt²(ü₀ − ü₁)/12 telescopes over a slide to at most Δt²/12 · 2(A + a_y) (the
    relative acceleration stays within ±(A + a_y)).  Tolerance: that bound times the number
    of slides, 2.0e-6 to 2.6e-6 m at Δt = 1 ms (measured 1.0e-7, 3.4e-8, 4.7e-7 m); the
    slides' starts and stops within 1e-2 Δt (measured ≤ 1.0e-3 Δt)."""
    dt = 1e-3
    t = np.linspace(0.0, 1.0, 1001)
    a = sine(t)
    a[-1] = 0.0
    r = sc.newmark_sliding(t, a, ky * G, two_way=True)
    dm, st = discrete_block(ky)
    res = sc.solve_dynamic(dm, dt=dt, duration=r.slides[-1][1] + 0.1,
                           mass=np.diag([MASS, MASS]), initial=st,
                           ground_acceleration=(sc.Tabulated(tuple(t), tuple(a), hold=False),
                                                (1, 0)))
    assert res.status == Status.COMPLETED
    tol = len(r.slides) * dt**2 / 12 * 2 * (A_SINE + ky * G)
    assert abs(res.u[-1][0] - r.permanent) < tol
    table = sc.sliding_comparison(res, (t, a), ky * G, two_way=True)
    assert abs(table.rows[0]["dynamic_mean"] - r.permanent) < tol
    # slip−, stuck, slip+, stuck: each slide's start and stop
    times = [e.lam for e in res.events]
    want = [x for s in r.slides for x in s[:2]]
    assert len(times) == len(want) == 4
    assert np.allclose(times, want, rtol=0, atol=1e-2 * dt)


def test_the_slip_of_a_compliant_layer_leaves_out_its_elastic_part():
    """A rigid block on a compliant tangential layer (Jenkins, C_τ = 1e7 N/m, eq. (11)) under
    a rectangular ground pulse: after the last stop the block rings on the layer (u_τ varies
    by 0.6 mm) while its slip u_τ − Q/C_τ, the layer's plastic part, stays put — to 1e-12 of
    the slide (measured 2.5e-16 m)."""
    f, A, t0 = 0.3, 0.6 * G, 0.25
    d, _ = rectangular_pulse(A, f * G, t0)
    dm = sc.DiscreteModel(K=[[0.0, 0.0], [0.0, 0.0]], normal_rows=[[0, 1]],
                          tangent_rows=[[1, 0]], loads={"weight": {"uy": -MASS * G}},
                          friction=f, kt=1e7, dof_names=("ux", "uy"),
                          dof_axes={"ux": "x", "uy": "y"}, program=[sc.Segment("weight", 1.0)])
    st = sc.solve_static(dm)
    res = sc.solve_dynamic(dm, dt=1e-3, duration=1.0, mass=np.diag([MASS, MASS]), initial=st,
                           ground_acceleration=(Pulse(A, 0.0, t0, "rectangular"), (1, 0)))
    assert res.status == Status.COMPLETED
    js = sc.joint_slip(res, "contact")
    after = res.time > res.events[-1].lam
    assert after.sum() > 100 and not js.sliding_at_end
    assert np.ptp(res.ut[after, 0]) > 1e-3 * d  # the layer rings ...
    assert np.ptp(js.slip[after, 0]) < 1e-12 * d  # ... the slip does not
    assert js.permanent_mean == js.slip[-1, 0] and js.permanent_mean < -0.5 * d


def test_the_slip_of_a_3d_joint_has_two_components():
    """The 3D rigid point block (faceted cone, k = 8, a vertex along ±x; one CFE) under a
    rectangular ground pulse along x: it slides along −x by Newmark's distance (the vertex's
    resistance is f W, a_y = f g), to 1e-9 relative, with no slip along y; the table sets the
    slip's length beside Newmark."""
    f, A, t0 = 0.3, 0.6 * G, 0.25
    d, _ = rectangular_pulse(A, f * G, t0)
    names = ("ux", "uy", "uz")
    dm = sc.DiscreteModel(K=np.zeros((3, 3)), normal_rows=[[0, 0, 1]], tangent_rows=[[1, 0, 0]],
                          tangent2_rows=[[0, 1, 0]], friction=f, facets=8, dof_names=names,
                          loads={"weight": {"uz": -MASS * G}},
                          dof_axes={"ux": "x", "uy": "y", "uz": "z"},
                          program=[sc.Segment("weight", 1.0)])
    st = sc.solve_static(dm)
    res = sc.solve_dynamic(dm, dt=1e-2, duration=1.0, mass=MASS * np.eye(3), initial=st,
                           ground_acceleration=(Pulse(A, 0.0, t0, "rectangular"), (1, 0, 0)))
    assert res.status == Status.COMPLETED
    name = res.interface_names[0]
    js = sc.joint_slip(res, name)
    assert js.slip.shape == (res.n_states, 1, 2) and js.mean.shape == (res.n_states, 2)
    np.testing.assert_allclose(js.permanent_mean, [-d, 0.0], rtol=0, atol=1e-9 * d)
    assert js.permanent_max == pytest.approx(d, rel=1e-9)
    assert sc.rigid_block_yield(st, name, MASS) == pytest.approx(f * G, rel=1e-12)
    row = sc.sliding_comparison(res, ([0.0, t0], [A, A]), f * G).rows[0]
    assert row["dynamic_mean"] == pytest.approx(d, rel=1e-9)  # 3D: the slip's length
    assert row["ratio"] == pytest.approx(1.0, rel=1e-9)


# ---- errors name the argument -----------------------------------------------------------------
@pytest.mark.parametrize("args, item", [
    (([0.0, 1.0, 1.0], [1, 2, 3], 1.0), "t"),
    (([0.0, 2.0, 1.0], [1, 2, 3], 1.0), "t"),
    (([0.0, np.nan, 1.0], [1, 2, 3], 1.0), "t"),
    (([0.0], [1.0], 1.0), "t"),
    (([0.0, 1.0], [1.0, np.nan], 1.0), "a_ground"),
    (([0.0, 1.0], [1.0, 2.0, 3.0], 1.0), "a_ground"),
    (([0.0, 1.0], ["x", 2.0], 1.0), "a_ground"),
    ((["0", "y"], [1.0, 2.0], 1.0), "t"),
    (([0.0, 1.0], [1.0, 2.0], -0.5), "a_yield"),
    (([0.0, 1.0], [1.0, 2.0], 0.0), "a_yield"),
    (([0.0, 1.0], [1.0, 2.0], np.nan), "a_yield"),
    (([0.0, 1.0], [1.0, 2.0], "big"), "a_yield"),
])
def test_bad_input_names_the_argument(args, item):
    with pytest.raises(ModelError) as e:
        sc.newmark_sliding(*args)
    assert e.value.item == item
    assert str(e.value).startswith(f"{item}: ")


def test_bad_comparison_input_names_the_item():
    dm, st = discrete_block(0.2)
    res = sc.solve_dynamic(dm, dt=0.01, duration=0.1, mass=np.diag([MASS, MASS]), initial=st,
                           ground_acceleration=(Pulse(G, 0.0, 0.05, "rectangular"), (1, 0)))
    with pytest.raises(ModelError, match="^interface: no interface 'base'"):
        sc.joint_slip(res, "base")
    with pytest.raises(ModelError, match="^mass: "):
        sc.rigid_block_yield(st, "contact", -1.0)
    with pytest.raises(ModelError, match="^record: "):
        sc.sliding_comparison(res, 3.0, 1.0)
    with pytest.raises(ModelError, match="^record: a half_sine pulse is not piecewise"):
        sc.sliding_comparison(res, Pulse(G, 0.0, 0.05), 1.0)
    with pytest.raises(ModelError, match="^record: "):
        sc.sliding_comparison(res, ([0.0, 1.0], ["x", 1.0]), 1.0)
    with pytest.raises(ModelError, match="^t: times must increase"):
        sc.sliding_comparison(res, ([0.0, 0.0], [1.0, 1.0]), 1.0)
    with pytest.raises(ModelError, match="^result: is not a dynamic result"):
        sc.joint_slip(st, "contact")
