"""Lemke's method and its use for the rate problem of a new working scheme.

References: brute-force enumeration of the 2ⁿ complementary bases for small LCPs (a P-matrix
LCP has exactly one solution), and the least-index pivoting path of the same models.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import stepcontact as sc
import verification_models as vm
from stepcontact.solver.lcp import lemke


def enumerate_lcp(M: np.ndarray, q: np.ndarray) -> list[np.ndarray]:
    """All solutions z of the LCP (M, q) by enumeration of complementary bases (small n)."""
    n = len(q)
    out = []
    for basis in itertools.product([False, True], repeat=n):
        b = np.array(basis)  # True: z_i basic (w_i = 0)
        z = np.zeros(n)
        if b.any():
            try:
                z[b] = np.linalg.solve(M[np.ix_(b, b)], -q[b])
            except np.linalg.LinAlgError:
                continue
        w = M @ z + q
        scale = max(np.abs(q).max(), 1e-300)
        if np.all(z >= -1e-10 * max(np.abs(z).max(), 1e-300)) and np.all(w >= -1e-9 * scale):
            out.append(z)
    return out


@pytest.mark.parametrize("seed", range(40))
def test_lemke_matches_enumeration_on_p_matrices(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 7))
    A = rng.standard_normal((n, n))
    # a P-matrix, not symmetric: positive definite symmetric part plus a skew part
    M = A @ A.T + 0.2 * np.eye(n) + 0.5 * (lambda S: S - S.T)(rng.standard_normal((n, n)))
    q = rng.standard_normal(n) * 10.0 ** rng.integers(-3, 5)
    ref = enumerate_lcp(M, q)
    assert len(ref) == 1  # unique for a P-matrix
    sol = lemke(M, q)
    assert sol.solved
    tol = 1e-9 * max(np.abs(ref[0]).max(), 1e-300)
    assert np.allclose(sol.z, ref[0], atol=tol, rtol=1e-9)
    assert np.all(sol.w >= -1e-9 * np.abs(q).max())
    assert abs(sol.z @ sol.w) <= 1e-9 * np.abs(q).max() * max(np.abs(sol.z).max(), 1e-300)


def test_lemke_reports_an_infeasible_lcp():
    # w = −z − 1 ≥ 0 has no solution with z ≥ 0: ray termination, not a wrong answer
    sol = lemke(np.array([[-1.0]]), np.array([-1.0]))
    assert not sol.solved
    assert "ray" in sol.message


def test_lemke_trivial_and_degenerate():
    sol = lemke(np.eye(3), np.array([1.0, 0.0, 2.0]))
    assert sol.solved and np.all(sol.z == 0)
    # degenerate: two equal rows
    M = np.array([[2.0, 1.0], [2.0, 1.0]])
    sol = lemke(M, np.array([-2.0, -2.0]))
    assert sol.solved
    assert np.all(sol.w >= -1e-12) and abs(sol.z @ sol.w) < 1e-12


def _events(res):
    return [(e.cfe, e.transition.value, round(e.lam, 9)) for e in res.events]


MODELS = {
    "sliding block": lambda: vm.sliding_block(0.4, 10.0),
    "uplift slab": lambda: vm.uplift_slab("body_force", 5.0),
    "spring-held block": lambda: vm.spring_held_block(0.5),
    "stack": lambda: vm.random_frictional_model(
        "stack", (0.5, 0.8), [(0.6, -0.2), (-0.3, 0.4), (0.9, 0.1)],
        [(-0.8, 0.5), (0.2, -0.9), (0.7, 0.3)]),
    "beam": lambda: vm.random_frictional_model(
        "beam", (0.5, 0.5), [(0.4, -1.0), (-0.7, 0.8), (0.3, 0.2)],
        [(0.9, -0.4), (-0.2, 0.6), (0.5, -0.8)]),
}


@pytest.mark.parametrize("name", list(MODELS))
def test_lemke_rate_solver_gives_the_same_path(name):
    """Lemke's method on every rate problem (including the fully degenerate first state, where
    every touching CFE has N = Q = u_n = 0) gives the path of the least-index pivoting."""
    model = MODELS[name]()
    a = sc.solve_static(model)
    b = sc.solve_static(model, rate_solver="lemke")
    # every rate problem that needed a pivot was solved by Lemke's method instead (Lemke's mode
    # may also take a degenerate problem that the direct solve settled in round-off)
    assert b.counters["lemke"] > 0 or a.counters["pivots"] == 0
    assert b.counters["pivots"] == 0 or b.status == sc.Status.EQUILIBRIUM_LOST
    assert _events(a) == _events(b)
    assert a.status == b.status
    scale = max(np.abs(a.N).max(), 1e-300)
    assert np.allclose(a.N, b.N, atol=1e-9 * scale)
    assert np.allclose(a.Q, b.Q, atol=1e-9 * scale)
    assert b.residual.max() < 1e-9 and b.violation.max() < 1e-9


def test_lemke_takes_over_when_pivoting_cycles(monkeypatch):
    """If the least-index pivoting fails on a rate problem (it cycles when the problem is not a
    P-problem), the rate problem is solved by Lemke's method and the path is unchanged.  The
    failure is forced: the pivoting reports a cycle on every rate problem it is given."""
    from stepcontact.solver import rate
    from stepcontact.solver.lcp import LCPResult

    model = MODELS["beam"]()
    ref = sc.solve_static(model)
    forced = 0

    def cycling(M, q, start=None, max_pivots=None, tol=1e-12):
        nonlocal forced
        forced += 1
        return LCPResult(np.zeros(len(q)), np.array(q, dtype=float), False, 1,
                         "principal pivoting cycles")

    monkeypatch.setattr(rate, "principal_pivoting", cycling)
    res = sc.solve_static(model)
    # every rate problem the pivoting gave up on was solved by Lemke's method, including one
    # that the pivoting solves in the reference run
    assert forced > 0 and res.counters["lemke"] == forced > ref.counters["lemke"]
    assert res.status == ref.status
    assert _events(res) == _events(ref)
    scale = max(np.abs(ref.N).max(), 1e-300)
    assert np.allclose(res.N, ref.N, atol=1e-9 * scale)
    assert np.allclose(res.Q, ref.Q, atol=1e-9 * scale)
    assert res.violation.max() < 1e-9


def test_equilibrium_loss_reports_the_mechanism_scheme():
    """At loss of equilibrium the last state shows the scheme that is the mechanism (every CFE
    slipping for a sliding block), with the contact conditions still satisfied."""
    res = sc.solve_static(vm.sliding_block(0.4, 10.0))
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    last = res.state[-1]
    assert np.all((last == sc.ContactState.SLIP_POS) | (last == sc.ContactState.OPEN))
    assert res.violation[-1] < 1e-9
    assert res.events[-1].lam == pytest.approx(res.multipliers[-1].equilibrium_lost)


# ---- degenerate LCPs: the lexicographic minimum-ratio test -----------------------------------
# q with ties (equal entries, zeros): degenerate pivots.  M ≥ 0 with a positive diagonal is
# strictly copositive, so each LCP has a solution and Lemke's method must end in one.  Before
# the lexicographic rule (first row of z₀ by the smallest index, ties within 1e-12 only) these
# two cycled until the pivot budget (1 800 and 2 450 pivots) ran out.
CYCLED = [
    ([[1, 2, 0, 2, 1], [0, 2, 2, 1, 2], [0, 0, 2, 2, 2], [2, 1, 2, 2, 1], [2, 2, 1, 1, 2]],
     [-2.0, -2.0, 0.0, -2.0, 0.0]),
    ([[1, 1, 2, 2, 2, 2], [2, 1, 2, 0, 0, 1], [2, 0, 1, 0, 0, 2], [0, 0, 0, 2, 1, 0],
      [2, 2, 2, 2, 2, 0], [2, 2, 0, 1, 1, 1]],
     [-1.0, 0.0, 0.0, -1.0, 0.0, -1.0]),
]


def assert_complementary(M, q, z, tol: float = 1e-12) -> None:
    """z ≥ 0, w = M z + q ≥ 0, zᵀw = 0, each to ``tol`` relative to max(|q|, |M||z|)."""
    w = M @ z + q
    scale = max(np.abs(q).max(), np.abs(M).max() * np.abs(z).max())
    assert z.min() >= 0.0
    assert w.min() >= -tol * scale
    assert np.abs(z * w).max() <= tol * scale * max(np.abs(z).max(), 1e-300)


@pytest.mark.parametrize("case", range(len(CYCLED)))
def test_lexicographic_lemke_solves_lcps_that_cycled(case):
    """Reference: the enumeration of the complementary bases; Lemke's z is one of the LCP's
    solutions to 1e-12 (relative to max |z|) and satisfies the complementarity conditions to
    1e-12, in a handful of pivots (no cycling)."""
    M, q = (np.array(a, float) for a in CYCLED[case])
    sol = lemke(M, q)
    assert sol.solved, sol.message
    assert sol.pivots <= 2 * len(q)
    assert_complementary(M, q, sol.z)
    ref = enumerate_lcp(M, q)
    assert any(np.abs(sol.z - z).max() <= 1e-12 * np.abs(z).max() for z in ref)


@pytest.mark.parametrize("seed", range(40))
def test_lexicographic_lemke_on_degenerate_copositive_lcps(seed):
    """Random strictly copositive M (nonnegative integers, positive diagonal) and q of ties
    (entries in {0, −1} or {0, −2}): a solution exists; Lemke's method finds one that
    satisfies the complementarity conditions to 1e-12."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 12))
    M = rng.integers(0, 3, (n, n)).astype(float)
    np.fill_diagonal(M, rng.integers(1, 3, n))
    q = -(rng.random(n) < 0.4).astype(float) * rng.integers(1, 3)
    q[rng.integers(n)] = -1.0 * rng.integers(1, 3)  # at least one negative entry
    sol = lemke(M, q)
    assert sol.solved, sol.message
    assert_complementary(M, q, sol.z)


@pytest.mark.parametrize("seed", range(20))
def test_lexicographic_lemke_on_degenerate_convex_qp_lcps(seed):
    """Symmetric positive semidefinite, rank-deficient M (= A Aᵀ, A of entries in {−1, 0, 1})
    and q = w* − M z* from a complementary pair with indices where both vanish (degenerate):
    the LCP is the optimality condition of min ½zᵀMz + qᵀz over z ≥ 0.  Reference: OSQP on
    that QP; M z (the same for every minimiser of a convex QP) agrees to 1e-6 relative (OSQP's
    tolerance 1e-10, polished), and Lemke's z satisfies the complementarity conditions to
    1e-12."""
    osqp = pytest.importorskip("osqp")
    import scipy.sparse as sp

    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 9))
    A = rng.integers(-1, 2, (n, int(rng.integers(1, n)))).astype(float)
    M = A @ A.T
    kind = rng.integers(3, size=n)  # 0: z* > 0, 1: w* > 0, 2: both zero
    zs = np.where(kind == 0, rng.integers(1, 3, n), 0).astype(float)
    ws = np.where(kind == 1, rng.integers(1, 3, n), 0).astype(float)
    q = ws - M @ zs
    sol = lemke(M, q)
    assert sol.solved, sol.message
    assert_complementary(M, q, sol.z)
    prob = osqp.OSQP()
    prob.setup(sp.csc_matrix(M), q, sp.eye(n, format="csc"), np.zeros(n), np.full(n, np.inf),
               eps_abs=1e-10, eps_rel=1e-10, polishing=True, verbose=False, max_iter=200000)
    ref = prob.solve().x
    scale = max(np.abs(M @ ref).max(), np.abs(q).max())
    assert np.abs(M @ sol.z - M @ ref).max() <= 1e-6 * scale


# ---- Lemke's method on the rate problem of a plate pressed and sheared from zero -------------
def sheared_plate(base: str, f: float = 1.0, ratio: float = 0.8) -> sc.Model:
    """A 2 m × 0.5 m plate (6 × 2 quad4) on a 3 m × 0.5 m base (mortar CFEs, zero gaps: every
    CFE starts closed at N = Q = 0); the base fixed at its bottom (``"elastic"``) or at every
    node (``"rigid"``).  Pressed by 1 Pa and sheared by ``ratio`` Pa along −x per unit λ on
    its top, proportionally from zero, to λ = 10⁶ (pattern 'press': below the friction limit
    on average, ratio < f, so the ends slip at λ = 0 and the plate holds); then a further
    shear of 1 Pa per unit λ (pattern 'shear') to 0.15·10⁶, short of sliding (at
    (f − ratio)·10⁶ = 0.2·10⁶)."""
    m = vm.block_on_base(friction=f, nx=6, ny=2, w=2.0, h=0.5)
    if base == "rigid":
        m = m.add(sc.Support("rigid_base", m.select("base", boundary=False)))
    top = m.select("block", y=0.5)
    return m.add(sc.LoadPattern("press", [sc.EdgeLoad(top, normal=1.0, tangential=-ratio)]),
                 sc.LoadPattern("shear", [sc.EdgeLoad(top, tangential=-1.0)]),
                 sc.Segment("press", 1e6), sc.Segment("shear", 0.15e6))


@pytest.mark.parametrize("base", ["elastic", "rigid"])
def test_lemke_on_a_plate_sheared_from_zero_completes_as_the_default(base):
    """At λ = 0 every CFE sits at every limit; the rate problem's M has the opposite columns of
    each CFE's slip rates a⁺, a⁻ (not copositive-plus) and Lemke's method ends on a secondary
    ray there (it ended the run in ``rate_problem`` before); the default solver then takes over
    (counted in ``lemke_fallbacks``).  Reference: the default solver's run — the same events
    (CFE, transition, segment) at the same λ to 1e-9 × 10⁶, the same forces to 1e-9 of the
    largest; and statics at the end: ΣN = −2 m × 10⁶ Pa, ΣQ = −2 m × 0.95·10⁶ Pa (the top
    loads' resultant), to 1e-9 relative."""
    model = sheared_plate(base)
    a = sc.solve_static(model)
    b = sc.solve_static(model, rate_solver="lemke")
    assert a.status == sc.Status.COMPLETED, a.message
    assert b.status == sc.Status.COMPLETED, b.message
    assert b.counters["lemke"] >= 1 and b.counters["lemke_fallbacks"] >= 1
    assert a.counters["lemke_fallbacks"] == 0
    assert [(e.cfe, e.transition, e.segment) for e in a.events] == \
        [(e.cfe, e.transition, e.segment) for e in b.events]
    assert {e.segment for e in a.events} == {0, 1}  # ends slip at λ = 0, one more CFE later
    lam_a = np.array([e.lam for e in a.events])
    lam_b = np.array([e.lam for e in b.events])
    assert np.abs(lam_a - lam_b).max() <= 1e-9 * 1e6
    scale = np.abs(a.N).max()
    assert np.allclose(a.N, b.N, atol=1e-9 * scale) and np.allclose(a.Q, b.Q, atol=1e-9 * scale)
    assert b.N[-1].sum() == pytest.approx(-2.0e6, rel=1e-9)
    assert b.Q[-1].sum() == pytest.approx(-0.95 * 2.0e6, rel=1e-9)
    assert b.residual.max() < 1e-9 and b.violation.max() < 1e-9
