"""Tests of the independent faceted-cone reference (tests/faceted_reference.py) itself.

References: the polygon's geometry from its vertices (segment projections and ray
intersections, computed here independently of the reference's sector formulas); the circle's
known results as k → ∞ (slip at f|N|, dissipation f|N| × slip length for a push, 2π f|N|
√(R² − a²) per revolution on a circular driver, 4 f|N| (A − a) per stick–slip cycle); the
reference's closed forms against its two integrators (the return mapping, and the exact
sweeping of a piecewise-linear driver); the energy balance driver work = dissipation + elastic
energy; step-size convergence.  Each test states its tolerance and the measured error.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import faceted_reference as fr

FN, KS = 2.0, 100.0  # f|N| in N, k_s in N/m
A_ = FN / KS  # a = f|N| / k_s, m


def _segment_projection(q: np.ndarray, fN: float, k: int, angle: float) -> np.ndarray:
    """The closest point of the polygon's boundary to q: brute force over its k edges."""
    V = fr.vertices(fN, k, angle)
    best, dist = None, np.inf
    for i in range(k):
        p0, p1 = V[i], V[(i + 1) % k]
        t = np.clip((q - p0) @ (p1 - p0) / ((p1 - p0) @ (p1 - p0)), 0.0, 1.0)
        c = p0 + t * (p1 - p0)
        if np.linalg.norm(q - c) < dist:
            best, dist = c, np.linalg.norm(q - c)
    return best


def test_state_codes_mirror_the_enums():
    from stepcontact.enums import FACET_SLIP, VERTEX_SLIP, ContactState

    assert (fr.STICK, fr.FACET_SLIP, fr.VERTEX_SLIP) == (ContactState.STICK, FACET_SLIP,
                                                        VERTEX_SLIP)


@pytest.mark.parametrize("k", [3, 4, 8, 32])
def test_projection_against_brute_force(k):
    """Outside points: the closest boundary point by brute force over the edges (1e-12 f|N|,
    measured ≤ 2e-15); inside points are returned unchanged with the stick code."""
    rng = np.random.default_rng(k)
    angle = rng.uniform(-np.pi, np.pi)
    for q in rng.normal(scale=1.5 * FN, size=(200, 2)):
        p, code = fr.project(q, FN, k, angle)
        th = fr.facet_normal_angles(k, angle)
        inside = np.all(np.cos(th) * q[0] + np.sin(th) * q[1] <= FN * math.cos(math.pi / k))
        if inside:
            assert code == fr.STICK and np.array_equal(p, q)
            continue
        np.testing.assert_allclose(p, _segment_projection(q, FN, k, angle), rtol=0,
                                   atol=1e-12 * FN)
        if code >= fr.VERTEX_SLIP:
            np.testing.assert_allclose(p, fr.vertices(FN, k, angle)[code - fr.VERTEX_SLIP],
                                       rtol=0, atol=1e-12 * FN)
        else:
            assert fr.FACET_SLIP <= code < fr.FACET_SLIP + k


@pytest.mark.parametrize("k", [4, 8, 16, 32])
def test_slip_limit_closed_form_against_the_ray_exit(k):
    """|P| = f|N| cos(π/k) / cos(θ − θ_f) (θ_f the nearest facet normal) equals the ray's exit
    from the vertices' polygon over a full turn (1e-12 relative; measured ≤ 7e-16); on a vertex
    |P| = f|N|, on a facet normal f|N| cos(π/k) (1e-14).  The form with the nearest vertex,
    cos(π/k) / cos(π/k − |θ − θ_v|), is the same; cos(θ − θ_v) in the denominator (the issue's
    wording) is not: it would put the vertex at f|N| cos(π/k)."""
    angle = 0.3
    theta = np.linspace(0.0, 2.0 * np.pi, 361)
    lim = fr.slip_limit(FN, k, theta, angle)
    ray = np.array([fr.ray_exit(FN, k, t, angle) for t in theta])
    np.testing.assert_allclose(lim, ray, rtol=1e-12)
    vert = angle + 2.0 * np.pi * np.arange(k) / k
    np.testing.assert_allclose(fr.slip_limit(FN, k, vert, angle), FN, rtol=1e-14)
    np.testing.assert_allclose(fr.slip_limit(FN, k, vert + np.pi / k, angle),
                               FN * math.cos(math.pi / k), rtol=1e-14)
    step = 2.0 * np.pi / k
    dv = np.abs(theta - (angle + step * np.round((theta - angle) / step)))  # |θ − θ_v|
    np.testing.assert_allclose(lim, FN * math.cos(math.pi / k) / np.cos(math.pi / k - dv),
                               rtol=1e-12)
    issue_form = FN * math.cos(math.pi / k) / math.cos(0.0)  # at θ = α, a vertex: θ_v = θ
    assert fr.ray_exit(FN, k, angle, angle) - issue_form == pytest.approx(
        FN * (1 - math.cos(math.pi / k)), rel=1e-12)


@pytest.mark.parametrize("k", [4, 8, 16, 32, 64, 128])
def test_limit_and_slip_direction_converge_to_the_circle(k):
    """As k grows: 0 ≤ 1 − |P|/(f|N|) ≤ 1 − cos(π/k) (attained on the facet normals, 1e-14)
    and the onset slip direction θ_f is within π/k of the load (1e-14)."""
    theta = np.linspace(0.0, 2.0 * np.pi, 1001)
    err = 1.0 - fr.slip_limit(FN, k, theta) / FN
    assert err.min() >= -1e-14
    assert err.max() <= 1.0 - math.cos(math.pi / k) + 1e-14
    assert np.abs(theta - fr.nearest_facet_normal(theta, k)).max() <= math.pi / k + 1e-14


PUSHES = [(8, 0.2, 0.0), (8, math.pi / 8 + 0.05, 0.0), (5, 1.0, 0.4), (8, 0.0, 0.0),
          (8, math.pi / 8, 0.0), (16, -2.0, 0.1)]


@pytest.mark.parametrize(("k", "theta", "angle"), PUSHES)
def test_straight_push_integrators_against_closed_form(k, theta, angle):
    """A push from rest along θ: slip path, force path and dissipation of the return mapping
    and of the sweep against :func:`straight_push` (1e-11 of the scale; measured ≤ 1e-14:
    both are exact on one facet and at one vertex).  The final state is the vertex nearest θ
    (or the facet when θ is a facet normal), and the dissipation per unit slip there is
    f|N| cos(θ − θ_v)."""
    s = np.linspace(0.0, 0.2, 801)
    d = s[:, None] * np.array([math.cos(theta), math.sin(theta)])
    cf = fr.straight_push(FN, k, KS, theta, s, angle)
    for path in (fr.return_mapping(d, KS, FN, k, angle), fr.sweep(d, KS, FN, k, angle)):
        np.testing.assert_allclose(path.x, cf.x, rtol=0, atol=1e-11 * 0.2)
        np.testing.assert_allclose(path.Q, cf.Q, rtol=0, atol=1e-11 * FN)
        np.testing.assert_allclose(path.W, cf.W, rtol=0, atol=1e-11 * FN * 0.2)
        stick = s < cf.s0 * (1 - 1e-9)
        assert np.all(path.code[stick] == fr.STICK)
        if math.isfinite(cf.s1) and cf.s1 < 0.2:
            step = 2.0 * np.pi / k
            v = int(round((theta - angle) / step)) % k
            assert path.code[-1] == fr.VERTEX_SLIP + v
            dv = theta - (angle + step * round((theta - angle) / step))
            assert cf.dissipation_per_slip == pytest.approx(FN * math.cos(dv), rel=1e-14)
            late = s > cf.s1 + 0.01
            dW = np.diff(path.W[late]) / np.diff(path.slip_length[late])
            np.testing.assert_allclose(dW, FN * math.cos(dv), rtol=1e-10)
        else:
            assert path.code[-1] >= fr.FACET_SLIP


def test_stick_limit_of_the_return_mapping():
    """The last stick state of a push lies within one step k_s Δs below the closed-form limit
    and the next state slips (k = 8, 12 directions)."""
    for theta in np.linspace(0.0, 2.0 * np.pi, 12, endpoint=False):
        s = np.linspace(0.0, 0.05, 5001)
        d = s[:, None] * np.array([math.cos(theta), math.sin(theta)])
        path = fr.return_mapping(d, KS, FN, 8)
        j = int(np.flatnonzero(path.code != fr.STICK)[0])
        lim = float(fr.slip_limit(FN, 8, theta))
        last = float(np.linalg.norm(path.Q[j - 1]))
        assert lim - KS * (s[1] - s[0]) <= last <= lim


@pytest.mark.parametrize("k", [64, 256, 1024])
def test_push_dissipation_tends_to_f_N_times_slip_length(k):
    """The circle's result for a push: W = f|N| × slip length; the polygon's is within the
    factor [cos(π/k), 1] of it (measured by the return mapping; the bound is exact)."""
    theta = 0.7
    s = np.linspace(0.0, 0.3, 1501)
    path = fr.return_mapping(s[:, None] * np.array([math.cos(theta), math.sin(theta)]),
                             KS, FN, k)
    L = path.slip_length[-1]
    assert L > 0.2
    assert FN * L * math.cos(math.pi / k) * (1 - 1e-12) <= path.W[-1] <= FN * L * (1 + 1e-12)


ORBITS = [(8, 1.5, 0.2, "pass"), (8, 2.0, 0.0, "pass"), (16, 2.0, 0.1, "pass"),
          (8, 3.0, 0.0, "dwell"), (5, 2.0, 0.0, "dwell"), (8, 6.0, 0.3, "dwell"),
          (4, 3.0, 0.0, "dwell")]


@pytest.mark.parametrize(("k", "Rf", "angle", "regime"), ORBITS)
def test_circle_orbit_against_the_sweep(k, Rf, angle, regime):
    """Driver on a circle of radius R: after two revolutions the sweep (exact for the chords
    of 4000 steps per revolution) follows the closed-form orbit: force and slip paths within
    Δβ² f|N| and Δβ² a (the chords' error; measured ≤ 0.22 Δβ²), the dissipation of the third
    revolution within 1e-5 relative (measured ≤ 4e-7)."""
    R = Rf * A_
    orb = fr.circle_orbit(FN, k, KS, R, angle)
    assert orb.regime == regime
    spr = 4000
    beta, d = fr.circle_driver(R, 3, spr)
    path = fr.sweep(d, KS, FN, k, angle)
    last = slice(2 * spr, 3 * spr + 1)
    db = 2.0 * np.pi / spr
    assert np.abs(path.Q[last] - orb.force(beta[last])).max() <= db ** 2 * FN
    assert np.abs(path.x[last] - orb.slip(beta[last])).max() <= db ** 2 * A_
    W = path.W[3 * spr] - path.W[2 * spr]
    assert W == pytest.approx(orb.dissipation_per_revolution, rel=1e-5)
    assert np.all(fr.STICK != path.code[last])  # slips for ever


def test_circle_orbit_return_mapping_converges():
    """The return mapping (closest-point projection per step) converges to the orbit: it errs
    by O(Δβ) in the steps that pass a vertex (regime "pass", k = 8, R = 2a): force error
    ≤ 0.5 Δβ f|N| at 1000, 4000 and 16000 steps per revolution (measured ≤ 0.17 Δβ f|N|)."""
    R = 2.0 * A_
    orb = fr.circle_orbit(FN, 8, KS, R)
    for spr in (1000, 4000, 16000):
        beta, d = fr.circle_driver(R, 3, spr)
        path = fr.return_mapping(d, KS, FN, 8)
        last = slice(2 * spr, 3 * spr + 1)
        err = np.abs(path.Q[last] - orb.force(beta[last])).max()
        assert err <= 0.5 * (2.0 * np.pi / spr) * FN


def test_sweep_converges_at_second_order_on_the_circle():
    """The sweep's only error on a circular driver is the chords': quartering Δβ (500 →
    2000 steps per revolution) cuts the force error by ≥ 8 (second order: 16; measured 15)."""
    R = 2.0 * A_
    orb = fr.circle_orbit(FN, 8, KS, R)
    errs = []
    for spr in (500, 2000):
        beta, d = fr.circle_driver(R, 3, spr)
        path = fr.sweep(d, KS, FN, 8)
        last = slice(2 * spr, 3 * spr + 1)
        errs.append(np.abs(path.Q[last] - orb.force(beta[last])).max())
    assert errs[1] <= errs[0] / 8


def test_energy_balance():
    """Driver work (trapezoidal) = dissipation + elastic energy |Q|²/(2 k_s) along a
    circular drive, to 1e-5 of one revolution's dissipation at 4000 steps per revolution
    (an O(Δβ²) quadrature error; measured ≤ 1.9e-6)."""
    R = 2.0 * A_
    beta, d = fr.circle_driver(R, 3, 4000)
    orb = fr.circle_orbit(FN, 8, KS, R)
    for path in (fr.sweep(d, KS, FN, 8), fr.return_mapping(d, KS, FN, 8)):
        bal = path.driver_work - path.W - (path.Q ** 2).sum(axis=1) / (2.0 * KS)
        assert np.abs(bal).max() <= 1e-5 * orb.dissipation_per_revolution


def test_circle_orbit_regimes_join_and_tend_to_the_circle():
    """At R = a / sin(π/k) both regimes give 2 k f|N| a cos²(π/k) (1e-12); as k → ∞,
    W_rev → 2π f|N| √(R² − a²) with 0 ≤ 1 − W_rev / W_circle ≤ (2π/k)² / 6 (pass regime,
    1 − k sin(2π/k)/(2π))."""
    for k in (5, 8, 16, 32):
        Rj = A_ / math.sin(math.pi / k)
        dwell = 2 * k * FN * math.sin(math.pi / k) * (Rj - A_ * math.sin(math.pi / k))
        pas = k * FN * math.sin(2 * math.pi / k) * math.sqrt(Rj ** 2 - A_ ** 2)
        assert dwell == pytest.approx(pas, rel=1e-12)
        assert fr.circle_orbit(FN, k, KS, Rj).dissipation_per_revolution == pytest.approx(
            2 * k * FN * A_ * math.cos(math.pi / k) ** 2, rel=1e-12)
    for k in (64, 256, 1024, 4096):
        for Rf in (1.5, 3.0):
            R = Rf * A_
            Wc = 2 * math.pi * FN * math.sqrt(R * R - A_ * A_)
            rel = 1 - fr.circle_orbit(FN, k, KS, R).dissipation_per_revolution / Wc
            assert 0 <= rel <= (2 * math.pi / k) ** 2 / 6


def test_circle_orbit_outside_its_range_is_refused():
    with pytest.raises(ValueError, match="does not slip for ever"):
        fr.circle_orbit(FN, 8, KS, 1.05 * A_)


HYSTERESIS = [(8, 0.2, 0.0), (8, -0.15, 0.1), (16, 0.05, 0.0), (5, 0.7, 0.0), (7, 2.0, 0.3),
              (4, 0.5, 0.0), (6, 0.1, 0.0)]


@pytest.mark.parametrize(("k", "theta", "angle"), HYSTERESIS)
def test_hysteresis_loop_against_the_integrators(k, theta, angle):
    """A driver back and forth along a line oblique to the facets (amplitude A = 8a): the
    dissipation of the 2nd and 3rd cycles of both integrators equals the closed form (1e-10
    relative; measured ≤ 3e-13: both integrators are exact on straight increments here), and
    the explicit even-k form equals the general one (1e-13)."""
    A = 8.0 * A_
    W, A_min = fr.hysteresis_dissipation(FN, k, KS, theta, A, angle)
    assert A_min < A
    if k % 2 == 0:
        assert fr.hysteresis_even(FN, k, KS, theta, A, angle) == pytest.approx(W, rel=1e-13)
    spq = 400
    d = fr.line_driver(theta, A, 3, spq)
    cyc = 4 * spq
    for path in (fr.return_mapping(d, KS, FN, k, angle), fr.sweep(d, KS, FN, k, angle)):
        for c in (1, 2):
            Wn = path.W[-1 - (c - 1) * cyc] - path.W[-1 - c * cyc]
            assert Wn == pytest.approx(W, rel=1e-10)
        vplus = int(np.argmax(fr.vertices(1.0, k, angle) @ [math.cos(theta), math.sin(theta)]))
        assert path.code[-1] == fr.VERTEX_SLIP + vplus  # resting at V+ at the turn


@pytest.mark.parametrize("k", [64, 256, 1024, 4096])
def test_hysteresis_tends_to_the_circle(k):
    """As k → ∞ the loop's dissipation → 4 f|N| (A − a) (the circle: stick over 2a, then
    slip at f|N|); for θ a quarter, half and three quarters of π/k from a vertex the
    relative difference is ≤ 1 − cos(π/k) (measured ≤ 0.65 (1 − cos(π/k)))."""
    A = 8.0 * A_
    circle = 4.0 * FN * (A - A_)
    for part in (0.25, 0.5, 0.75):
        theta = 3 * 2 * math.pi / k + part * math.pi / k
        W, _ = fr.hysteresis_dissipation(FN, k, KS, theta, A)
        assert abs(W / circle - 1) <= 1 - math.cos(math.pi / k)


def test_hysteresis_refusals():
    with pytest.raises(ValueError, match="facet normal"):
        fr.hysteresis_dissipation(FN, 8, KS, math.pi / 8, 8 * A_)
    with pytest.raises(ValueError, match="does not reach"):
        fr.hysteresis_dissipation(FN, 8, KS, 0.2, 0.5 * A_)


def test_return_mapping_converges_to_the_sweep_on_a_random_path():
    """A random piecewise-linear driver (30 legs, several turns of the force around the
    polygon, k = 8): the return mapping with n substeps per leg tends to the exact sweep;
    its force error at the legs' ends is ≤ 2 f|N| / n (O(1/n) from the vertex passages;
    measured ≤ 0.33 f|N| / n) for n = 50, 200, 800; the final dissipation within
    60 f|N| a / n (measured 2.5 f|N| a / n)."""
    rng = np.random.default_rng(3)
    legs = np.cumsum(rng.normal(scale=2.0 * A_, size=(31, 2)), axis=0)
    legs[0] = 0.0
    exact = fr.sweep(legs, KS, FN, 8, 0.1)
    assert len(set(exact.code.tolist())) > 4  # stick, facets and vertices visited
    for n in (50, 200, 800):
        t = np.linspace(0.0, 1.0, n + 1)[1:]
        d = np.vstack([legs[:1]] + [legs[i] + t[:, None] * (legs[i + 1] - legs[i])
                                    for i in range(30)])
        path = fr.return_mapping(d, KS, FN, 8, 0.1)
        err = np.abs(path.Q[::n] - exact.Q).max()
        assert err <= 2.0 * FN / n
        assert abs(path.W[-1] - exact.W[-1]) <= 2.0 * FN * A_ * 30 / n


def test_sweep_events_at_the_closed_form_points():
    """The sweep's events (driver legs of one step each: positions = load factors within
    the legs) fall where the closed forms put them (1e-12; measured ≤ 1e-15): a push slips
    at s0 and reaches the vertex at s1 (:func:`straight_push`); after a reversal at V+ the
    stick lasts t_H = 2a cos(π/k) / cos(π/k − |δ|) and V− is reached after the travel of
    :func:`_half_cycle`."""
    k, theta, L = 8, 0.2, 0.1
    u = np.array([math.cos(theta), math.sin(theta)])
    path = fr.sweep(np.array([[0.0, 0.0], L * u]), KS, FN, k)
    cf = fr.straight_push(FN, k, KS, theta, [L])
    assert [e[1:] for e in path.events] == [(fr.STICK, fr.FACET_SLIP + 0),
                                            (fr.FACET_SLIP + 0, fr.VERTEX_SLIP + 0)]
    np.testing.assert_allclose([e[0] for e in path.events], [cf.s0 / L, cf.s1 / L],
                               rtol=1e-12)
    A = 0.1
    path = fr.sweep(fr.line_driver(theta, A, 1, 1), KS, FN, k)  # 0 → A → 0 → −A → 0 → A
    after = [e for e in path.events if 1.0 < e[0] < 3.0]
    delta = theta  # from vertex 0
    tH = 2 * A_ * math.cos(math.pi / k) / math.cos(math.pi / k - delta)
    vminus, s_b, _ = fr._half_cycle(A_, k, 0.0, -u, 0)
    assert [e[1:] for e in after] == [(fr.STICK, fr.FACET_SLIP + 4),
                                      (fr.FACET_SLIP + 4, fr.VERTEX_SLIP + vminus)]
    np.testing.assert_allclose([e[0] for e in after], [1 + tH / A, 1 + s_b / A], rtol=1e-12)
    assert path.events[2] == (1.0, fr.VERTEX_SLIP + 0, fr.STICK)  # the reversal: stick


def test_sweep_reports_a_vertex_passed_without_rest_as_one_event():
    """Circular drive in the "pass" regime (k = 8, R = 2a, 64 straight legs per revolution):
    after the first revolution Q goes round the polygon facet after facet without resting,
    so every event is facet i → facet i + 1, one per 2π/k of driver angle (8 legs ± 1)."""
    k, R = 8, 2.0 * A_
    assert fr.circle_orbit(FN, k, KS, R).regime == "pass"
    beta = 2.0 * np.pi * np.arange(3 * 64 + 1) / 64
    path = fr.sweep(R * np.column_stack([np.cos(beta), np.sin(beta)]), KS, FN, k)
    late = [e for e in path.events if e[0] > 64]
    assert len(late) == 2 * k
    for _pos, old, new in late:
        assert fr.FACET_SLIP <= old < fr.VERTEX_SLIP and new == fr.FACET_SLIP + (
            old - fr.FACET_SLIP + 1) % k
    gaps = np.diff([e[0] for e in late])
    assert np.all(np.abs(gaps - 64 / k) <= 1.0)
