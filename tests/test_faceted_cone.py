"""The faceted Coulomb cone through the solver (issue 26 §3): spring–mass models with two
tangential directions against the closed forms and the exact sweep of
tests/faceted_reference.py (an independent pure-NumPy reference).

Every reference and tolerance is stated in the test's docstring.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import faceted_reference as fr
import stepcontact as sc
from stepcontact.enums import FACET_SLIP, slipping

TOL = 1e-9


def pushed_point(k: int, theta: float, *, f: float = 0.5, N: float = 100.0,
                 angle: float = 0.0) -> sc.DiscreteModel:
    """A point (u_x, u_y, u_z; u_z > 0 lifts it) on a rough rigid plane, pressed with N, then
    pushed along θ up to 2 f N; springs of 1 kN/m to the ground hold it once it slips (they
    carry nothing while it sticks: rigid contact keeps u = 0)."""
    return sc.DiscreteModel(
        K=np.diag([1e3, 1e3, 1e3]), normal_rows=[[0, 0, 1]], tangent_rows=[[1, 0, 0]],
        tangent2_rows=[[0, 1, 0]], friction=f, facets=k, facet_angle=angle,
        loads={"press": {"uz": -1.0}, "push": {"ux": math.cos(theta), "uy": math.sin(theta)}},
        dof_names=("ux", "uy", "uz"),
        program=[sc.Segment("press", N), sc.Segment("push", 2 * f * N)])


def driven_point(steps: np.ndarray, k: int, *, angle: float = 0.0, ks: float = 100.0,
                 P: float = 10.0, f: float = 0.2) -> sc.DiscreteModel:
    """The reference's problem: a point pressed with P on a rough plane, held by an isotropic
    spring ks to a driver (d_x, d_y) that moves along the piecewise-linear path ``steps``
    (one prescribed pattern and one segment per leg)."""
    legs = np.diff(steps, axis=0)
    K = np.zeros((5, 5))
    for a, b in ((0, 3), (1, 4)):
        K[[a, b, a, b], [a, b, b, a]] += [ks, ks, -ks, -ks]
    K[2, 2] += 1e3
    prescribed = {f"leg{i}": {"dx": dx, "dy": dy} for i, (dx, dy) in enumerate(legs)}
    program = [sc.Segment("press", P)] + [sc.Segment(f"leg{i}", 1.0) for i in range(len(legs))]
    return sc.DiscreteModel(
        K=K, normal_rows=[[0, 0, 1, 0, 0]], tangent_rows=[[1, 0, 0, 0, 0]],
        tangent2_rows=[[0, 1, 0, 0, 0]], friction=f, loads={"press": {"uz": -1.0}},
        prescribed=prescribed, dof_names=("ux", "uy", "uz", "dx", "dy"), program=program,
        facets=k, facet_angle=angle)


def leg_ends(res, n_legs: int) -> np.ndarray:
    """The index of the state at the end of each leg (its factor 1, the next one's 0)."""
    factors, names = np.asarray(res.factors), list(res.pattern_names)
    out = []
    for leg in range(n_legs):
        done = np.isclose(factors[:, names.index(f"leg{leg}")], 1.0, rtol=0, atol=1e-12)
        if leg + 1 < n_legs:
            done &= factors[:, names.index(f"leg{leg + 1}")] == 0.0
        out.append(int(np.flatnonzero(done)[-1]))
    return np.array(out)


def dissipation(res) -> np.ndarray:
    """W = ∫ Q · du_τ along the recorded path (J), cumulative per state: between two states
    the scheme is fixed and Q, u_τ are linear in λ, so the trapezoid rule is exact."""
    Q, ut = np.asarray(res.Q_t)[:, 0], np.asarray(res.ut_t)[:, 0]
    inc = 0.5 * np.einsum("ij,ij->i", Q[1:] + Q[:-1], np.diff(ut, axis=0))
    return np.r_[0.0, np.cumsum(inc)]


def assert_admissible(res, tol: float = TOL) -> None:
    assert res.residual.max() < tol, res.residual.max()
    assert res.violation.max() < tol, res.violation.max()


@pytest.mark.parametrize("k", [4, 8, 16, 32])
def test_slip_limit_over_a_full_turn(k):
    """A point pressed with N = 100 N (f = 0.5), pushed along θ: it slips at
    |P| = f N cos(π/k) / cos(θ − θ_f) (θ_f the nearest facet normal; fr.slip_limit, checked
    there against the polygon's ray exit), to 1e-9 relative, for θ over a full turn and a
    turned polygon (vertex 0 at 0.3 rad)."""
    for theta in np.linspace(0.0, 2 * np.pi, 25)[:-1] + 0.05:
        res = sc.solve_static(pushed_point(k, theta, angle=0.3))
        assert res.status == sc.Status.COMPLETED, res.message
        ref = fr.slip_limit(50.0, k, theta, 0.3)
        assert res.multipliers[1].first_slip == pytest.approx(ref, rel=1e-9)
        assert_admissible(res)


@pytest.mark.parametrize("k", [4, 8, 16, 32])
def test_limit_and_direction_converge_with_the_facets(k):
    """As k grows the limit tends to f N: its error is at most 1 − cos(π/k) (exactly that in
    a facet's middle, 0 on a vertex); the slip direction (the final u_τ: the point slides
    from u = 0) is within π/k of the load's direction, and the true-cone ratio |Q| / (f|N|)
    of a slipping CFE lies in [cos(π/k), 1] (1e-12)."""
    err_max = 1 - math.cos(math.pi / k)
    for theta in np.linspace(0.0, 2 * np.pi / k, 7):  # one facet's sector, vertex to vertex
        res = sc.solve_static(pushed_point(k, theta))
        lim = res.multipliers[1].first_slip
        assert -1e-12 <= 1 - lim / 50.0 <= err_max + 1e-12
        u = np.asarray(res.ut_t)[-1, 0]
        dev = abs(math.remainder(math.atan2(u[1], u[0]) - theta, 2 * math.pi))
        assert dev <= math.pi / k + 1e-9
        sl = slipping(np.asarray(res.state)[:, 0])
        ratio = np.asarray(res.cone_ratio)[sl, 0]
        assert ratio.size and np.all(ratio >= math.cos(math.pi / k) - 1e-12)
        assert np.all(ratio <= 1 + 1e-12)
    # the two ends: a facet's middle (θ on its normal, π/k) and a vertex (θ = 0)
    mid = sc.solve_static(pushed_point(k, math.pi / k)).multipliers[1].first_slip
    assert 1 - mid / 50.0 == pytest.approx(err_max, rel=1e-9)
    assert sc.solve_static(pushed_point(k, 0.0)).multipliers[1].first_slip == pytest.approx(
        50.0, rel=1e-12)


@pytest.mark.parametrize("k, R", [(8, 3.0), (8, 2.0), (16, 2.0)])
def test_rotating_load_path_and_dissipation(k, R):
    """The spring's end driven around a circle of radius R·a (a = f N / k_s; 128 straight
    legs per turn, 3 turns): the point slips for ever.  Every event of the solver is an event
    of the exact sweep of the same polygonal path (fr.sweep), in order, with its state code,
    at the same load factor (1e-10), and the force at every leg's end is the sweep's (1e-10
    f N).  The dissipation of the last turn equals the sweep's (1e-9 relative) and the
    closed form of the circle's steady orbit (fr.circle_orbit, W_rev = 2k f N sin(π/k)
    (R − a sin(π/k)) resting at the vertices for R = 3a, k f N sin(2π/k) √(R² − a²) for
    R = 2a) to 2e-3 (the 128-gon driver against the circle: (2π/128)² ≈ 2.4e-3)."""
    ks, P, f = 100.0, 10.0, 0.2
    fN, a = f * P, f * P / ks
    beta = 2 * np.pi * np.arange(3 * 128 + 1) / 128
    steps = np.vstack([[0.0, 0.0], R * a * np.column_stack([np.cos(beta), np.sin(beta)])])
    res = sc.solve_static(driven_point(steps, k, ks=ks, P=P, f=f))
    assert res.status == sc.Status.COMPLETED, res.message
    assert_admissible(res)
    ref = fr.sweep(steps, ks, fN, k)
    codes = np.asarray(res.state)[:, 0]
    got = [(int(e.segment) - 1 + e.lam, int(codes[e.state])) for e in res.events]
    assert [c for _, c in got] == [new for _, _, new in ref.events]
    np.testing.assert_allclose([p for p, _ in got], [p for p, _, _ in ref.events], rtol=0,
                               atol=1e-10)
    ends = leg_ends(res, len(steps) - 1)
    np.testing.assert_allclose(np.asarray(res.Q_t)[ends, 0], ref.Q[1:], rtol=0, atol=1e-10 * fN)
    W = dissipation(res)[ends]
    last = W[-1] - W[-1 - 128]
    ref_last = ref.W[-1] - ref.W[-1 - 128]
    assert last == pytest.approx(ref_last, rel=1e-9)
    assert last == pytest.approx(fr.circle_orbit(fN, k, ks, R * a).dissipation_per_revolution,
                                 rel=2e-3)


@pytest.mark.parametrize("k, theta", [(8, 0.2), (8, 0.5), (5, 0.7), (16, 0.1)])
def test_stick_slip_hysteresis_oblique_to_the_facets(k, theta):
    """The spring's end moved back and forth along a line at θ (oblique to the facets),
    amplitude A = 5a, three cycles: the dissipation of the last cycle equals the closed form
    of the steady stick–slip loop (fr.hysteresis_dissipation: exact sums along the polygon)
    to 1e-9 relative, and the loop's turning forces sit at the polygon's vertices V± (the
    force at each turning point, 1e-10 f N)."""
    ks, P, f = 100.0, 10.0, 0.2
    fN, a = f * P, f * P / ks
    A = 5 * a
    steps = fr.line_driver(theta, A, 3, 1)
    res = sc.solve_static(driven_point(steps, k, ks=ks, P=P, f=f))
    assert res.status == sc.Status.COMPLETED, res.message
    assert_admissible(res)
    ends = leg_ends(res, len(steps) - 1)
    W = dissipation(res)[ends]
    W_ref, _ = fr.hysteresis_dissipation(fN, k, ks, theta, A)
    assert W[-1] - W[-5] == pytest.approx(W_ref, rel=1e-9)  # (a cycle: four legs of A)
    V = fr.vertices(fN, k)
    u = np.array([math.cos(theta), math.sin(theta)])
    Q_end = np.asarray(res.Q_t)[ends[-1], 0]  # after a forward travel: at V+
    np.testing.assert_allclose(Q_end, V[np.argmax(V @ u)], rtol=0, atol=1e-10 * fN)


def loaded_plate(k: int, theta: float, f: float, ratio: float, corners: int) -> sc.DiscreteModel:
    """A rigid plate (6 DOFs u_x, u_y, u_z, r_x, r_y, r_z; K = 0) on three or four corner
    contacts with zero gaps (every contact closed at N = Q = 0), loaded from zero by its
    weight (1 N per λ, down, through its centre) and a lateral force ``ratio`` per λ along θ
    in the contacts' plane: proportional loading from the fully degenerate start, every facet
    of every contact active at once."""
    xy = (np.array([[1, 1], [-1, 1], [-1, -1], [1, -1]], float) if corners == 4 else
          np.array([[1.0, 0.0], [-0.5, 0.8], [-0.5, -0.8]]))
    m = len(xy)
    a, t1, t2 = np.zeros((m, 6)), np.zeros((m, 6)), np.zeros((m, 6))
    for i, (x, y) in enumerate(xy):  # small rotations: u(p) = u + r × p, p = (x, y, 0)
        a[i, [2, 3, 4]] = [1.0, y, -x]
        t1[i, [0, 5]] = [1.0, -y]
        t2[i, [1, 5]] = [1.0, x]
    return sc.DiscreteModel(
        K=np.zeros((6, 6)), normal_rows=a, tangent_rows=t1, tangent2_rows=t2, friction=f,
        facets=k, loads={"load": {"uz": -1.0, "ux": ratio * math.cos(theta),
                                  "uy": ratio * math.sin(theta)}},
        dof_names=("ux", "uy", "uz", "rx", "ry", "rz"), program=[sc.Segment("load", 1e3)])


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(k=st.integers(3, 32), theta=st.floats(0.0, 2 * math.pi), f=st.floats(0.2, 1.5),
       q=st.one_of(st.floats(0.0, 0.97), st.floats(1.03, 2.0)), corners=st.sampled_from([3, 4]))
def test_degenerate_start_no_cycling_no_false_mechanism(k, theta, f, q, corners):
    """Loading from zero with every contact closed at N = Q = 0 (all k facets of every
    contact active at once, up to k = 32): the lateral force is q times the polygon's sliding
    limit of the whole plate in its direction, f W cos(π/k) / cos(θ − θ_f) (the plate
    translates; every contact's polygon is the same).  Below it (q ≤ 0.97) the program
    completes with every contact closed and the forces carry the loads (1e-9); above it
    (q ≥ 1.03) equilibrium is lost at λ = 0 — no cycling, no false mechanism, and every
    reported state admissible (residual and violation < 1e-9)."""
    lim = fr.slip_limit(f, k, theta)
    res = sc.solve_static(loaded_plate(k, theta, f, q * lim, corners))
    assert res.status != sc.Status.CYCLING
    assert_admissible(res)
    if q < 1:
        assert res.status == sc.Status.COMPLETED, res.message
        assert np.all(np.asarray(res.state)[-1] != 0)
        assert -res.N[-1].sum() == pytest.approx(1e3, rel=1e-9)
        Qsum = np.asarray(res.Q_t)[-1].sum(axis=0)
        np.testing.assert_allclose(Qsum, 1e3 * q * lim * np.array([math.cos(theta),
                                                                   math.sin(theta)]),
                                   rtol=0, atol=1e-9 * 1e3)
    else:
        assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
        assert res.multipliers[-1].equilibrium_lost == 0.0


def test_faceted_slip_states_are_named():
    """The result names a faceted slip by its facet (enums.state_label), its events are
    'slip' transitions, and its message states the polygon's limit error."""
    res = sc.solve_static(pushed_point(8, 0.3))
    codes = np.asarray(res.state)[:, 0]
    assert np.any(codes >= FACET_SLIP)
    assert any(e.transition == sc.Transition.SLIP for e in res.events)
    labels = res.state_labels(int(np.flatnonzero(codes >= FACET_SLIP)[0]))
    assert labels[0].startswith("slip (")
    # the polygon's limit error is stated: 1 − cos(π/8) = 7.61 %
    assert "8-gon" in res.message and f"{100 * (1 - math.cos(math.pi / 8)):.3g} %" in res.message


@pytest.mark.parametrize("theta", [0.3, 1.0, 2.5, 4.4])
def test_adaptive_orientation_slips_on_the_cone(theta):
    """``facet_adaptive``: at its first contact with the polygon the CFE's polygon turns so
    that a vertex lies on its force; it then slips at the cone's limit f N in any direction
    (1e-12) and slides exactly along the load (the vertex's normal cone holds the direction:
    1e-12 rad)."""
    res = sc.solve_static(pushed_point(8, theta).replace(facet_adaptive=True))
    assert res.status == sc.Status.COMPLETED, res.message
    assert res.multipliers[1].first_slip == pytest.approx(50.0, rel=1e-12)
    u = np.asarray(res.ut_t)[-1, 0]
    assert abs(math.remainder(math.atan2(u[1], u[0]) - theta, 2 * math.pi)) <= 1e-12
    assert_admissible(res)


def test_dynamics_in_3d_runs_on_the_faceted_cone():
    """A dynamic interval of a model with two tangential directions runs (issue 28 §3; no
    longer refused): the point pressed with N = 100 N and pushed along θ = 0.3 by 2 f N from
    t = 0 slips at once on facet 0 (θ lies in its normal's range) and slides, its springs
    holding it; the energy ledger balances to 1e-9 of the work (tests/test_dynamics3d.py
    checks the closed forms)."""
    dm = pushed_point(8, 0.3).replace(program=[sc.Segment("press", 100.0)])
    res = sc.solve_dynamic(dm, dt=1e-3, duration=5e-2, mass=np.eye(3),
                           initial=sc.solve_static(dm), loads={"push": lambda t: 100.0})
    assert res.status == sc.Status.COMPLETED, res.message
    assert res.events[0].transition == sc.Transition.SLIP and res.events[0].lam == 0.0
    assert int(res.state[1][0]) == FACET_SLIP + 0
    E = res.energy
    assert abs(E["error"][-1]) <= 1e-9 * E["external"][-1]


def test_3d_result_file_and_reused_condensation(tmp_path):
    """A 3D run saved and loaded (netCDF format 2): the tangential forces, displacements and
    faceted state codes come back exactly and so does the true-cone ratio; a condensation
    built once (sc.condense) serves runs with another friction and gives the same answer as
    a run without it (the slip limit, exactly)."""
    dm = pushed_point(8, 0.3)
    res = sc.solve_static(dm)
    path = tmp_path / "point3d.nc"
    res.save(path)
    back = sc.load_result(path)
    np.testing.assert_array_equal(np.asarray(back.Q_t), np.asarray(res.Q_t))
    np.testing.assert_array_equal(np.asarray(back.ut_t), np.asarray(res.ut_t))
    np.testing.assert_array_equal(np.asarray(back.state), np.asarray(res.state))
    np.testing.assert_array_equal(back.cone_ratio, res.cone_ratio)
    c = sc.condense(dm)
    for f in (0.5, 0.3):
        alone = sc.solve_static(dm.replace(friction=f))
        shared = sc.solve_static(dm.replace(friction=f), condensation=c)
        assert shared.multipliers[1].first_slip == alone.multipliers[1].first_slip
        assert alone.multipliers[1].first_slip == pytest.approx(
            fr.slip_limit(f * 100.0, 8, 0.3), rel=1e-9)


@settings(max_examples=40, deadline=None)
@given(sizes=st.lists(st.integers(1, 5), min_size=1, max_size=4), data=st.data())
def test_ordered_schemes_is_the_stable_sort_of_the_product(sizes, data):
    """The singular point's schemes (rate._ordered_schemes, keyed in vectorised blocks) come in
    exactly the order of a stable sort of itertools.product by (mixed redundant groups,
    distance from the guess) — the order the rate problem tried them in before, so its
    answers do not change (exact comparison of the two sequences)."""
    from stepcontact.solver.rate import _ordered_schemes

    options = [data.draw(st.lists(st.integers(0, 6), min_size=n, max_size=n, unique=True))
               for n in sizes]
    guess = np.array([data.draw(st.integers(0, 6)) for _ in sizes])
    pos = list(range(len(sizes)))
    groups = [np.array(g) for g in (pos[:2], pos[2:]) if len(g) > 1]

    def order(cb):
        cb = np.asarray(cb)
        return (sum(len(set(cb[g].tolist())) > 1 for g in groups), int(np.sum(cb != guess)))

    expected = sorted(itertools.product(*options), key=order)
    assert list(_ordered_schemes(options, groups, guess)) == [tuple(c) for c in expected]


def test_a_plate_on_four_corners_with_32_facets_under_a_normal_load():
    """Loading from zero with no lateral force, four corners of 32 facets each (the singular
    point's 34⁴ schemes: sorted in Python they cost 85 s of CPU, keyed in NumPy a fraction of
    a second): the run completes with every corner closed and the load carried (1e-9)."""
    res = sc.solve_static(loaded_plate(32, 0.0, 0.5, 0.0, 4))
    assert res.status == sc.Status.COMPLETED, res.message
    assert -res.N[-1].sum() == pytest.approx(1e3, rel=1e-9)
