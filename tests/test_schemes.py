"""The working-scheme solver and the sparse backends against dense references.

* Woodbury-updated scheme solves equal dense solves of the full scheme matrix, over random
  sequences of schemes (with refactorisations forced in between by a small update rank), for
  relation right-hand sides and for load rates (the O(k n) path from the base's cached
  solution); factors stay valid while later schemes change the same rows;
* one factorisation per scheme: a scheme met again, regular or singular, is not factorised
  again, and the LU of a singular scheme serves the analysis of its mechanism; condition
  estimates from the LU (gecon) tell mechanisms as the SVD does;
* the whole static path with SuperLU equals the path with a dense LU of K₀ (a backend that
  runs everywhere, so the equivalence is checked in CI, not only where an extra is installed).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

import stepcontact as sc
import verification_models as vm
from stepcontact.contact.laws import OPEN, SLIP_NEG, SLIP_POS, STICK, CoulombLaw
from stepcontact.fem.assembly import assemble
from stepcontact.solver.condensation import Condensed
from stepcontact.solver.engine import EventEngine, norm2
from stepcontact.solver.schemes import (
    RCOND_MECHANISM,
    MechanismError,
    SchemeSolver,
    lu,
    rcond,
    scheme_rhs,
    scheme_rows,
)


def _engine(model, max_rank):
    system = assemble(model)
    cond = Condensed.from_system(system)
    cfe = system.cfe
    law = CoulombLaw(np.arange(cfe.m), cfe.friction, cfe.kn, cfe.kt)
    return EventEngine(SchemeSolver(cond.G, cond.d, max_rank=max_rank), [law], system.w0), cond


@pytest.mark.parametrize("max_rank", [4, 48])
@pytest.mark.parametrize("model", ["stack", "compliant"])
def test_woodbury_updates_equal_dense_solves(model, max_rank):
    """40 random schemes in a row (each CFE open, stuck or slipping either way): the rates
    from the base LU with Woodbury row updates (or a refactorisation, every few schemes with
    max_rank = 4: the stack has 6 CFEs, whose random schemes differ from the base by more than
    2 rows every time) equal a dense solve of the scheme's full matrix to 1e-9; singular schemes are
    reported as mechanisms by both."""
    mdl = (vm.random_frictional_model("stack", (0.4, 0.6), [(0, -1)] * 3, [(0, -1)] * 3)
           if model == "stack" else vm.spring_held_block(0.5))
    if model == "compliant":
        itf = mdl.interfaces[0]
        import dataclasses

        mdl = mdl.replace(interfaces=(dataclasses.replace(
            itf, layer=sc.ContactLayer(E=1e8, nu=0.3, thickness=0.01)),))
    eng, cond = _engine(mdl, max_rank)
    m = eng.m
    rng = np.random.default_rng(3)
    h, e = vm.first_forcing(cond)
    n_dense_singular = n_checked = 0
    for states, r in vm.random_scheme_cases(rng, m):
        rel = eng.relations(states, article=False)
        A, scale = scheme_rows(cond.G, cond.d, rel, np.arange(2 * m))
        b = scale * scheme_rhs(cond.d, rel, h, e, r)
        dense_singular = np.linalg.cond(A) > 1e12
        try:
            ds, dw = eng.rates(states, (h, e), r)
        except MechanismError:
            assert dense_singular
            n_dense_singular += 1
            continue
        assert not dense_singular
        t = sla.solve(A, b)
        w_hat = h - cond.G @ t
        s_ref, w_ref = t + cond.d * w_hat, w_hat + e
        assert np.allclose(ds, s_ref, rtol=1e-9, atol=1e-9 * np.abs(s_ref).max())
        assert np.allclose(dw, w_ref, rtol=1e-9, atol=1e-9 * np.abs(w_ref).max())
        # load rates alone (r = 0): the O(k n) update of the base's solution of the load
        ds, dw = eng.rates(states, (h, e))
        t = sla.solve(A, scale * scheme_rhs(cond.d, rel, h, e, np.zeros(2 * m)))
        w_hat = h - cond.G @ t
        s_ref, w_ref = t + cond.d * w_hat, w_hat + e
        assert np.allclose(ds, s_ref, rtol=1e-9, atol=1e-9 * np.abs(s_ref).max())
        assert np.allclose(dw, w_ref, rtol=1e-9, atol=1e-9 * np.abs(w_ref).max())
        n_checked += 1
    assert n_checked >= 10
    counters = eng.schemes.counters
    assert counters["scheme_updates"] > 0
    if max_rank == 4:
        assert counters["scheme_factorizations"] > 1


def _dense_rates(eng, cond, states, h, e, r):
    rel = eng.relations(states, article=False)
    A, scale = scheme_rows(cond.G, cond.d, rel, np.arange(2 * eng.m))
    t = sla.solve(A, scale * scheme_rhs(cond.d, rel, h, e, r))
    w_hat = h - cond.G @ t
    return t + cond.d * w_hat, w_hat + e


def test_factors_stay_valid_while_later_schemes_change_their_rows():
    """A factor kept in the cache (the rate problem's scheme, solved again for the correction)
    gives the same rates after later schemes have changed the same rows to other states (the
    base's cached rows and products are updated, the factor's own are not), and equals a dense
    solve; every scheme is factorised at most once."""
    eng, cond = _engine(vm.random_frictional_model("stack", (0.4, 0.6), [(0, -1)] * 3,
                                                   [(0, -1)] * 3), 48)
    m = eng.m
    name = next(iter(cond.hhat))
    h, e = cond.hhat[name], cond.e[name]
    r = np.random.default_rng(1).standard_normal(2 * m) * 1e-6
    base = np.full(m, STICK)
    first = base.copy()
    first[:2] = SLIP_POS
    kept = eng.factor(first)
    before = kept.load_rates(h, e), kept.solve(h, e, r)
    for st in (SLIP_NEG, OPEN, SLIP_POS, STICK):
        other = base.copy()
        other[:3] = st
        try:
            eng.rates(other, (h, e))
        except MechanismError:
            pass
    after = kept.load_rates(h, e), kept.solve(h, e, r)
    for (s0, w0), (s1, w1) in zip(before, after, strict=True):
        assert np.allclose(s1, s0, rtol=1e-12, atol=1e-12 * np.abs(s0).max())
        assert np.allclose(w1, w0, rtol=1e-12, atol=1e-12 * np.abs(w0).max())
    s_ref, w_ref = _dense_rates(eng, cond, first, h, e, 0 * r)
    assert np.allclose(before[0][0], s_ref, rtol=1e-9, atol=1e-9 * np.abs(s_ref).max())
    assert np.allclose(before[0][1], w_ref, rtol=1e-9, atol=1e-9 * np.abs(w_ref).max())
    n = eng.schemes.counters["scheme_factorizations"]
    eng.rates(first, (h, e))
    assert eng.schemes.counters["scheme_factorizations"] == n


def test_a_singular_scheme_is_factorised_once():
    """A mechanism (every CFE of the sliding block slipping the same way) is detected from the
    LU's condition estimate, and asking for it again — the rate problem's check, the
    Fredholm test of :meth:`EventEngine.drives`, the mechanism's analysis — factorises nothing
    more: the scheme matrix and its LU are the ones of the first attempt."""
    eng, cond = _engine(vm.sliding_block(0.4, 10.0), 48)
    m = eng.m
    name = next(iter(cond.hhat))
    forcing = (cond.hhat[name], cond.e[name])
    eng.rates(np.full(m, STICK), forcing)
    states = np.full(m, SLIP_POS)
    with pytest.raises(MechanismError) as info:
        eng.rates(states, forcing)
    A, f = info.value.A, info.value.lu
    assert rcond(f, A) <= RCOND_MECHANISM
    n = eng.schemes.counters["scheme_factorizations"]
    with pytest.raises(MechanismError):
        eng.rates(states, forcing)
    assert eng.drives(states, forcing)
    rel = eng.relations(states, article=False)
    assert eng.schemes.dense(rel)[0] is A and lu(A) is f
    assert eng.schemes.counters["scheme_factorizations"] == n
    # a copy of the matrix is factorised afresh (the LU is reused only for the same array)
    assert lu(A.copy()) is not f


@pytest.mark.parametrize("model", ["stack", "sliding"])
def test_condition_estimate_from_the_lu_tells_mechanisms_like_the_svd(model):
    """gecon's estimate from the LU and the SVD agree on which schemes are mechanisms (rcond
    below RCOND_MECHANISM) over random schemes, and the estimate is within a factor 10 of
    1/cond₁; the power-iteration ‖A‖₂ is within 5 % below the SVD's."""
    mdl = (vm.random_frictional_model("stack", (0.4, 0.6), [(0, -1)] * 3, [(0, -1)] * 3)
           if model == "stack" else vm.sliding_block(0.4, 10.0))
    eng, cond = _engine(mdl, 48)
    m = eng.m
    rng = np.random.default_rng(5)
    kinds = set()
    samples = [vm.random_states(rng, m)
               for _ in range(30)]
    for states in [*samples, np.full(m, OPEN), np.full(m, SLIP_POS), np.full(m, STICK)]:
        A, _ = scheme_rows(cond.G, cond.d, eng.relations(states, article=False),
                           np.arange(2 * m))
        est = rcond(lu(A), A)
        exact = 1.0 / np.linalg.cond(A, 1)
        singular = np.linalg.svd(A, compute_uv=False)
        svd_mech = singular[-1] <= 1e-12 * singular[0]
        assert (est <= RCOND_MECHANISM) == svd_mech
        kinds.add(bool(svd_mech))
        if not svd_mech:
            assert exact / 10 <= est <= exact * 10
        assert 0.95 <= norm2(A) / singular[0] <= 1 + 1e-12
    assert kinds == {True, False}


def test_block_solves_equal_vector_solves():
    """A block of relation right-hand sides (the rate problem's columns) equals the vector
    solves one by one."""
    eng, cond = _engine(vm.sliding_block(0.4, 10.0), 48)
    m = eng.m
    states = np.full(m, STICK)
    states[0] = SLIP_POS
    fact = eng.factor(states)
    R = np.random.default_rng(0).standard_normal((2 * m, 5))
    z = np.zeros((2 * m, 1))
    S, W = fact.solve(z, z, R)
    for j in range(5):
        s, w = fact.solve(np.zeros(2 * m), np.zeros(2 * m), R[:, j])
        assert np.allclose(S[:, j], s, rtol=1e-12, atol=1e-12 * np.abs(s).max())
        assert np.allclose(W[:, j], w, rtol=1e-12, atol=1e-12 * np.abs(w).max())


class _DenseLU:
    """A dense LU of K₀: an independent backend for the equivalence test."""

    name = "dense"

    def __init__(self, K):
        self.lu = sla.lu_factor(K.toarray())

    def solve(self, b):
        return sla.lu_solve(self.lu, np.asarray(b, dtype=float))


@pytest.mark.parametrize("name", ["sliding", "stack", "beam"])
def test_superlu_path_equals_dense_lu_path(name, monkeypatch):
    """The whole static path with SuperLU equals the path with a dense LU of K₀: same events
    (CFE, transition), λ to 1e-9, forces to 1e-8 of their scale."""
    from stepcontact.solver import regularity

    model = {
        "sliding": lambda: vm.sliding_block(0.4, 10.0),
        "stack": lambda: vm.random_frictional_model("stack", (0.3, 0.5), [(0.5, -1)] * 3,
                                                    [(-0.7, -0.5)] * 3),
        "beam": lambda: vm.random_frictional_model("beam", (0.4, 0.4), [(0.3, -1)] * 3,
                                                   [(0.2, 1.0)] * 3),
    }[name]()
    a = sc.solve_static(model, backend="scipy")
    monkeypatch.setattr(regularity, "factorize", lambda K, backend="auto", **kw: _DenseLU(K))
    b = sc.solve_static(model, backend="scipy")
    assert b.status == a.status
    assert b.message == a.message  # the same load factor and mechanism when equilibrium is lost

    def before_loss(r):
        """Events before the point where equilibrium is lost: at that point the rate problem
        has no unique solution, and which CFEs a factorisation's round-off records as stuck
        on the way to the mechanism is not part of the answer."""
        lost = r.multipliers[-1].equilibrium_lost if r.multipliers else None
        return [(e.cfe, e.transition) for e in r.events
                if lost is None or e.segment != r.multipliers[-1].segment
                or abs(e.lam - lost) > 1e-9 * abs(lost)]

    assert before_loss(a) == before_loss(b)
    n = min(len(a.lam), len(b.lam)) - (a.status == sc.Status.EQUILIBRIUM_LOST)
    assert np.allclose(a.lam[:n], b.lam[:n], rtol=1e-9, atol=1e-9 * np.abs(a.lam).max())
    assert np.allclose(a.N[:n], b.N[:n], rtol=1e-8, atol=1e-8 * np.abs(a.N).max())
    assert np.allclose(a.Q[:n], b.Q[:n], rtol=1e-8, atol=1e-8 * np.abs(a.N).max())


def test_condensation_takes_g_from_a_backend_that_forms_it():
    """The backend seam: a factor with ``condensed(B)`` (a Schur complement formed by the
    backend) gives G directly, and the run equals the one with G from block solves."""
    from stepcontact.solver.condensation import Condensation, static_operator

    model = vm.sliding_block(0.4, 10.0)
    system = assemble(model)
    K0, Bf, *_ = static_operator(system)

    class Schur(_DenseLU):
        calls = 0

        def condensed(self, B):
            Schur.calls += 1
            return (B @ self.solve(B.T.toarray()))

    ref = Condensation.build(K0, Bf)
    c = Condensation.build(K0, Bf, factor=Schur(K0))
    assert Schur.calls == 1
    assert np.allclose(c.G, ref.G, rtol=1e-9, atol=1e-9 * np.abs(ref.G).max())
    a = sc.solve_static(model, condensation=c)
    b = sc.solve_static(model)
    assert np.allclose(a.lam, b.lam, rtol=1e-9)
