"""The scheme solver's explicit inverse and its low-rank updates against direct dense solves.

The reference of every test is the scheme matrix written here entry by entry from the
relation blocks (A_j = Σ_c S_jc e_c − Σ_c (S_jc d_c + W_jc) G_c, b_j = r_j − Σ_c (W_jc (ĥ_c +
e_c) + S_jc d_c ĥ_c); :mod:`stepcontact.solver.schemes`) and solved by LAPACK's LU with partial
pivoting (``scipy.linalg.solve``, rows scaled to a largest entry of 1), independent of the
solver's inverse, Woodbury updates and commits:

* a walk through 120 schemes of a block on a base (21 CFEs, n = 42), each differing from the
  one before in 1–4 CFEs (2–8 rows at once, as at a simultaneous event), with commits of the
  inverse forced every few schemes (max_rank 3 and 6; float64, and float32 refined against
  the exact operator): load rates, relation rates and a sparse block of unit rates equal the
  dense solve to 1e-12 relative (measured: 4e-14 at most), and after dozens of commits the
  base's inverse X satisfies ‖X A₀ − I‖∞ ≤ 1e-12;
* a scheme that is a mechanism (the block sliding as a rigid body) reached by an update — of
  rank within max_rank and beyond it (where the update would be committed) — is reported as a
  MechanismError by the full LU that arbitrates it, and the solver goes on with the base it
  had;
* an inverse corrupted by 1e-6 relative noise after a commit (what lost accuracy looks like)
  is detected by the backward-error check of its first solve and inverted afresh, and the
  rates still equal the dense solve to 1e-12;
* G y by symv (symmetric G) equals the full product to 1e-13 relative; a G that is not
  symmetric takes the full product;
* a *fresh* inverse that leaves a residual far above an LU solve's (its X perturbed by 1e-9
  relative noise, η about 1e-9 against 1e-16: what the inverse of an ill-conditioned scheme
  leaves on some loads, the fault of a staged bonded run) is refined on every solve — not
  only the first of its base — of the base and of its updates, without being inverted again,
  and the rates equal the dense solve to 1e-12 relative;
* the walk of the first test under the default, cost-based rank policy (updates, commits or
  inversions chosen by their weighted flops) equals the dense solves to 1e-12 relative.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

import verification_models as vm
from stepcontact.contact.laws import OPEN, SLIP_NEG, SLIP_POS, STICK, CoulombLaw
from stepcontact.fem.assembly import assemble
from stepcontact.solver.condensation import Condensed
from stepcontact.solver.engine import EventEngine
from stepcontact.solver.schemes import MechanismError, SchemeSolver

#: rates against the dense LU solve (relative to the largest rate): the walk's schemes have
#: cond(A) ≤ 65 (rows scaled), and the solver's rates after 70 commits are within 4e-14 of
#: the dense solve (float64 and refined float32 alike)
RTOL = 1e-12


@pytest.fixture(scope="module")
def block():
    """A 2 m block on a 4 m base (40 × 4 cells: 21 CFEs) condensed in float64 and float32."""
    system = assemble(vm.pushed_block(base_cells=(40, 4), block_cells=(20, 5)))
    c64 = Condensed.from_system(system, precision="float64")
    c32 = Condensed.from_system(system, precision="float32")
    return system, c64, c32


def _engine(system, cond, max_rank):
    cfe = system.cfe
    law = CoulombLaw(np.arange(cfe.m), cfe.friction, cfe.kn, cfe.kt)
    solver = SchemeSolver(cond.G, cond.d, max_rank=max_rank, product=cond.product)
    return EventEngine(solver, [law], system.w0)


def _dense(rel, G, d, h, e, r):
    """A and b of the scheme written entry by entry from its relation blocks."""
    m, nc = rel.layout.m, rel.layout.n_c
    n = m * nc
    A, b = np.zeros((n, n)), np.array(r, float)
    k = np.arange(m)
    for i in range(nc):
        rows = i * m + k
        for c in range(nc):
            cols = c * m + k
            S, W = rel.S[:, i, c], rel.W[:, i, c]
            A[rows, cols] += S
            A[rows] -= (S * d[cols] + W)[:, None] * G[cols]
            b[rows] -= W * (h[cols] + e[cols]) + S * d[cols] * h[cols]
    return A, b


def _cond(A):
    """cond₂ of A with its rows scaled to a largest entry of 1 (the rows' units apart)."""
    return np.linalg.cond(A / np.abs(A).max(axis=1, keepdims=True))


def _solve(A, b):
    """A⁻¹ b by LU on the rows scaled to a largest entry of 1 (rows in N and in m differ by
    the contact stiffness, 1e10: unscaled, partial pivoting loses those digits)."""
    s = np.abs(A).max(axis=1)
    return sla.solve(A / s[:, None], b / (s if b.ndim == 1 else s[:, None]))


def _rates(A, b, G, d, h, e):
    t = _solve(A, b)
    w_hat = h - G @ t
    return t + d * w_hat, w_hat + e


def _close(got, ref):
    for x, y in zip(got, ref, strict=True):
        assert np.abs(x - y).max() <= RTOL * max(np.abs(y).max(), 1e-300)


#: probabilities of stick, slip +, slip − and open in the walk
P_WALK = [0.3, 0.2, 0.2, 0.3]


def _walk(rng, m, steps):
    """Schemes each differing from the one before in 1–4 CFEs (stuck, slipping, open)."""
    states = np.full(m, STICK)
    for _ in range(steps):
        states = states.copy()
        k = rng.choice(m, size=rng.integers(1, 5), replace=False)
        states[k] = rng.choice([STICK, SLIP_POS, SLIP_NEG, OPEN], size=len(k),
                               p=P_WALK)
        yield states


def _checked_walk(eng, c64, rng):
    """The 120 schemes of :func:`_walk` through ``eng``: a regular one's rates (with and
    without a residual r) checked against the dense solve to RTOL, a singular one's
    (condition number > 1e12) MechanismError; yields (states, its dense matrix A, or None
    when singular)."""
    G, d = c64.G, c64.d
    n = 2 * eng.m
    h, e = vm.first_forcing(c64)
    for states in _walk(rng, eng.m, 120):
        rel = eng.relations(states, article=False)
        r = rng.standard_normal(n) * 1e-6
        A, b = _dense(rel, G, d, h, e, r)
        _, b0 = _dense(rel, G, d, h, e, np.zeros(n))
        if _cond(A) > 1e12:
            with pytest.raises(MechanismError):
                eng.rates(states, (h, e))
            yield states, None
            continue
        _close(eng.rates(states, (h, e)), _rates(A, b0, G, d, h, e))
        _close(eng.rates(states, (h, e), r), _rates(A, b, G, d, h, e))
        yield states, A


@pytest.mark.parametrize("precision", ["float64", "float32"])
@pytest.mark.parametrize("max_rank", [3, 6])
def test_walk_of_updates_and_commits_equals_dense_solves(block, max_rank, precision):
    """120 schemes, 2–8 rows changed at a time, commits every few schemes: every rate equals
    the dense solve to RTOL; mechanisms agree with the dense matrix's condition number."""
    system, c64, c32 = block
    cond = c64 if precision == "float64" else c32
    G, d = c64.G, c64.d
    eng = _engine(system, cond, max_rank)
    m, n = eng.m, 2 * eng.m
    h, e = vm.first_forcing(c64)
    rng = np.random.default_rng(4)
    checked = singular = 0
    for states, A in _checked_walk(eng, c64, rng):
        if A is None:
            singular += 1
            continue
        checked += 1
        if checked % 10 == 0:  # the rate problem's block: unit rates on 10 CFEs' rows
            cols = rng.choice(m, size=10, replace=False)
            R = np.zeros((n, 10))
            R[cols, np.arange(10)] = 1.0
            R[m + cols, np.arange(10)] = 0.5
            dS, dW = eng.factor(states).solve(np.zeros((n, 1)), np.zeros((n, 1)), R)
            t = _solve(A, R)  # (no load: b = R)
            w_hat = -G @ t
            _close((dS, dW), (t + d[:, None] * w_hat, w_hat))
    c = eng.schemes.counters
    assert checked >= 60 and c["scheme_commits"] >= 15, (checked, c)
    if precision == "float64":  # the base's inverse after the commits
        base = eng.schemes.base
        A0, _ = _dense(base.rel, G, d, h, e, np.zeros(n))
        XA = base.X @ (base.scale[:, None] * A0)
        assert base.commits >= 1
        assert np.abs(XA - np.eye(n)).max() <= RTOL


@pytest.mark.parametrize("max_rank", [48, 4])
def test_singular_update_is_a_mechanism(block, max_rank):
    """The block sliding as a rigid body (every CFE slipping the same way) from the stuck
    base: an update of rank m = 21 (Woodbury with max_rank 48, beyond max_rank 4) whose
    capacitance is singular; the full LU reports the mechanism, the base stays, and the next
    regular scheme equals the dense solve."""
    system, c64, _ = block
    G, d = c64.G, c64.d
    eng = _engine(system, c64, max_rank)
    m, n = eng.m, 2 * eng.m
    h, e = vm.first_forcing(c64)
    stuck = np.full(m, STICK)
    eng.rates(stuck, (h, e))
    base = eng.schemes.base
    sliding = np.full(m, SLIP_POS)
    A, _ = _dense(eng.relations(sliding, article=False), G, d, h, e, np.zeros(n))
    assert _cond(A) > 1e12  # the reference: singular
    before = dict(eng.schemes.counters)
    with pytest.raises(MechanismError) as info:
        eng.rates(sliding, (h, e))
    assert info.value.states is not None and np.array_equal(info.value.states, sliding)
    c = eng.schemes.counters
    assert c["scheme_updates"] == before["scheme_updates"] + 1
    assert c["scheme_inversions"] == before["scheme_inversions"] + 1  # the arbiter's LU
    assert c["scheme_commits"] == before["scheme_commits"]
    assert eng.schemes.base is base and base.alive
    other = stuck.copy()
    other[:3] = SLIP_NEG
    A, b = _dense(eng.relations(other, article=False), G, d, h, e, np.zeros(n))
    _close(eng.rates(other, (h, e)), _rates(A, b, G, d, h, e))


def test_lost_accuracy_is_inverted_afresh(block):
    """A commit, then its inverse corrupted by 1e-6 relative noise: the first solve's
    backward error (about 1e-6, against 1e-16 of a sound inverse) inverts the scheme afresh,
    and its rates equal the dense solve to RTOL."""
    system, c64, _ = block
    G, d = c64.G, c64.d
    eng = _engine(system, c64, 2)
    m, n = eng.m, 2 * eng.m
    h, e = vm.first_forcing(c64)
    stuck = np.full(m, STICK)
    eng.rates(stuck, (h, e))
    states = stuck.copy()
    states[:3] = SLIP_POS  # 3 rows > max_rank 2: committed
    rel = eng.relations(states, article=False)
    fac = eng.schemes.factor(rel)
    base = eng.schemes.base
    assert fac.V is None and base.commits == 1 and not base.checked
    noise = np.random.default_rng(0).standard_normal(base.X.shape)
    base.X += 1e-6 * np.abs(base.X).max() * noise
    A, b = _dense(rel, G, d, h, e, np.zeros(n))
    _close(eng.rates(states, (h, e)), _rates(A, b, G, d, h, e))
    c = eng.schemes.counters
    assert c["scheme_reinversions"] == 1 and c["scheme_inversions"] == 2
    assert eng.schemes.base is not base and eng.schemes.base.commits == 0


def test_symmetric_product(block):
    """G y by symv equals G @ y to 1e-13 relative for the (exactly symmetric) G; a G that is
    not symmetric is multiplied in full (equal to G @ y exactly)."""
    _, c64, _ = block
    G = np.ascontiguousarray(c64.G)
    G = 0.5 * (G + G.T)
    y = np.random.default_rng(1).standard_normal(G.shape[0])
    s = SchemeSolver(G, c64.d)
    ref = G @ y
    assert np.abs(s.g_product(y) - ref).max() <= 1e-13 * np.abs(ref).max()
    assert s._symv
    A = G.copy()
    A[0, 1] *= 1 + 1e-9
    s = SchemeSolver(A, c64.d)
    assert np.array_equal(s.g_product(y), A @ y) and s._symv is False


def test_a_fresh_inverse_is_checked_on_every_solve(block):
    """The base's inverse, fresh from an LU and checked on its first solve, then perturbed by
    1e-9 relative noise (a residual 1e7 times an LU solve's): every later solve — other loads
    on the base, relation rates, a Woodbury update of it — is refined to the dense solve's
    rates (RTOL), and the base is not inverted again (refinement is the remedy of a fresh
    inverse; a reinversion is for the drift of commits)."""
    system, c64, _ = block
    G, d = c64.G, c64.d
    eng = _engine(system, c64, None)
    m, n = eng.m, 2 * eng.m
    h, e = vm.first_forcing(c64)
    first = np.full(m, STICK)
    first[[0, 1]] = SLIP_POS  # (slipping CFEs: tangential rates w' that are not zero)
    first[m - 1] = OPEN
    eng.rates(first, (h, e))
    base = eng.schemes.base
    assert base.commits == 0 and base.checked
    noise = np.random.default_rng(2).standard_normal(base.X.shape)
    base.X += 1e-9 * np.abs(base.X).max() * noise
    base.loads.clear()  # (the solution of (h, e) cached before the noise)
    before = dict(eng.schemes.counters)
    update = first.copy()
    update[[5, 9]] = SLIP_NEG
    rng = np.random.default_rng(3)
    for states in (first, update):
        rel = eng.relations(states, article=False)
        for load in ((h, e), (2.0 * h - 0.5 * e, e)):
            A, b = _dense(rel, G, d, *load, np.zeros(n))
            _close(eng.rates(states, load), _rates(A, b, G, d, *load))
        r = rng.standard_normal(n) * 1e-6
        A, b = _dense(rel, G, d, h, e, r)
        _close(eng.rates(states, (h, e), r), _rates(A, b, G, d, h, e))
    c = eng.schemes.counters
    assert eng.schemes.base is base and base.alive
    assert c["refinements"] >= before["refinements"] + 6
    assert c["scheme_reinversions"] == before["scheme_reinversions"]
    assert c["scheme_inversions"] == before["scheme_inversions"]


def test_walk_under_the_cost_based_rank_policy(block):
    """The walk of :func:`test_walk_of_updates_and_commits_equals_dense_solves` (float64) with
    the default rank policy: every rate equals the dense solve to RTOL."""
    system, c64, _ = block
    eng = _engine(system, c64, None)
    walk = _checked_walk(eng, c64, np.random.default_rng(4))
    assert sum(A is not None for _, A in walk) >= 60


def test_solve_rows_equals_the_dense_solve(block):
    """:meth:`SchemeFactor.solve_rows` — (A⁻¹ b)[R] for right-hand sides b that vanish
    outside the rows R of a few CFEs, from the base's products V Z and columns Z (the rate
    problem's responses) — along the walk under the default rank policy (updates, commits,
    rows changed back): equal to the dense solve of the row-scaled
    scheme (independent LU) to RTOL of its largest entry."""
    system, c64, _ = block
    eng = _engine(system, c64, None)
    rng = np.random.default_rng(7)
    m, checked = eng.m, 0
    for states, A in _checked_walk(eng, c64, np.random.default_rng(5)):
        if A is None:
            continue
        fac = eng.factor(states, article=False)
        cf = np.sort(rng.choice(m, size=3, replace=False))
        R = np.concatenate([cf, cf + m])  # the CFEs' rows, component-major
        bs = np.zeros((len(R), 4))
        bs[rng.integers(0, len(R), 8), rng.integers(0, 4, 8)] = rng.standard_normal(8)
        full = np.zeros((2 * m, 4))
        full[R] = bs
        ref = _solve(A * fac.scale[:, None], full)[R]
        got = fac.solve_rows(R, bs)
        assert np.abs(got - ref).max() <= RTOL * max(np.abs(ref).max(), 1e-300)
        checked += 1
    assert checked >= 60


@pytest.mark.parametrize("dtype, tol", [(np.float64, 1e-12), (np.float32, 1e-4)])
@pytest.mark.parametrize("k, a", [(40, 1), (40, 3), (100, 50), (5, 5)])
def test_a_bordered_capacitance_lu_solves_as_the_dense_one(k, a, dtype, tol):
    """:func:`_border_lu` — the LU of C from that of its leading block, extended by a new
    rows and columns — in LAPACK's form: its solves equal the dense solve of C (numpy's, an
    independent LU) to ``tol`` of the solution, and its condition estimate is gecon's of the
    plain LU within a factor 10 (the same matrix)."""
    from stepcontact.solver.schemes import _border_lu, _lapack, lu_solve, rcond

    rng = np.random.default_rng(k + a)
    C = (np.eye(k + a) + 0.3 * rng.standard_normal((k + a, k + a))).astype(dtype)
    lead = np.array(C[:k, :k], order="F")
    f = _border_lu(_lapack("getrf", lead)(lead)[:2], C)
    b = rng.standard_normal((k + a, 2))
    ref = np.linalg.solve(C.astype(np.float64), b)
    assert np.abs(lu_solve(f, b) - ref).max() <= tol * np.abs(ref).max()
    anorm = float(np.abs(C).sum(axis=0).max())
    plain = np.array(C, order="F")
    r_plain = rcond(_lapack("getrf", plain)(plain)[:2], anorm=anorm)
    assert 0.1 < rcond(f, anorm=anorm) / r_plain < 10.0


def test_the_walk_with_bordered_capacitances_equals_dense_solves(block, monkeypatch):
    """The walk under the default rank policy with every capacitance of two or more rows
    extended from a recent one where it can (``BORDER_MIN`` = 2): every rate equals the
    dense solve to RTOL, and bordering happened."""
    import stepcontact.solver.schemes as schemes

    monkeypatch.setattr(schemes, "BORDER_MIN", 2)
    system, c64, _ = block
    eng = _engine(system, c64, None)
    walk = _checked_walk(eng, c64, np.random.default_rng(4))
    assert sum(A is not None for _, A in walk) >= 60
    assert eng.schemes.counters["scheme_bordered"] >= 5
