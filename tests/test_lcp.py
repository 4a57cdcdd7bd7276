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
