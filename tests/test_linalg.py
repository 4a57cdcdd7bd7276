"""Sparse backends: every installed backend solves like SciPy's SuperLU and gives the same path."""

from __future__ import annotations

import gc

import numpy as np
import pytest
import scipy.sparse as sp

import stepcontact as sc
import verification_models as vm
from stepcontact.errors import SolverError
from stepcontact.solver.linalg import available_backends, factorize


def _spd(n: int = 200, seed: int = 0) -> sp.csc_matrix:
    rng = np.random.default_rng(seed)
    A = sp.random(n, n, density=0.02, random_state=seed, data_rvs=rng.standard_normal)
    return (A @ A.T + n * sp.eye(n)).tocsc()


@pytest.mark.parametrize("backend", [*available_backends(), "dense"])
def test_backend_solves_vectors_and_blocks(backend):
    K = _spd()
    F = factorize(K, backend)
    b = np.random.default_rng(1).standard_normal((K.shape[0], 3))
    x = F.solve(b)
    assert x.shape == b.shape
    assert np.abs(K @ x - b).max() <= 1e-10 * np.abs(b).max()
    x0 = F.solve(b[:, 0])
    assert x0.shape == (K.shape[0],)
    assert np.allclose(x0, x[:, 0], rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("backend", [b for b in available_backends() if b != "scipy"])
def test_backend_gives_the_scipy_path(backend):
    model = vm.sliding_block(0.4, 10.0)
    a = sc.solve_static(model, backend="scipy")
    b = sc.solve_static(model, backend=backend)
    assert [(e.cfe, e.transition) for e in a.events] == [(e.cfe, e.transition) for e in b.events]
    assert np.allclose(a.lam, b.lam, rtol=1e-9)
    assert np.allclose(a.N, b.N, rtol=1e-8, atol=1e-8 * np.abs(a.N).max())


def test_unknown_backend_and_singular_matrix_are_errors():
    with pytest.raises(SolverError, match="unknown linear-solver backend 'mumps'"):
        factorize(_spd(), "mumps")
    K = sp.csc_matrix(np.diag([1.0, 0.0, 2.0]))
    with pytest.raises(SolverError, match="singular"):
        factorize(K, "scipy")
    for K in (sp.csc_matrix(np.diag([1.0, 0.0, 2.0])), sp.csc_matrix(np.diag([1.0, -1.0]))):
        with pytest.raises(SolverError, match="singular"):
            factorize(K, "dense")


# ---- the condensed matrix from the factors (no solve per contact unknown) --------------------
def _block_model(r: int = 1) -> sc.Model:
    concrete = sc.Material(E=30e9, nu=0.2, density=2400)
    base = sc.rectangle("base", (0, 0), (4, 1), 8 * r, 2 * r, concrete)
    block = sc.rectangle("block", (1, 1), (3, 2), 6 * r, 3 * r, concrete)
    m = sc.Model(bodies=[base, block], plane="strain", thickness=1.0)
    return m.add(
        sc.Support("bed", m.select("base", y=0), "xy"),
        sc.Interface("joint", plus=m.select("block", y=1), minus=m.select("base", y=1),
                     friction=0.5),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
        sc.Segment("weight", 1.0),
    )


@pytest.mark.parametrize("backend", [b for b in available_backends() if b != "cholmod"])
def test_condensed_matrix_from_the_factors_equals_dense_inverse(backend):
    """G = B K⁻¹ Bᵀ read off the factors (Schur complement on the DOFs ordered last) equals
    the dense inverse to 1e-12 relative, with no solve per row of B."""
    from stepcontact.fem.assembly import assemble
    from stepcontact.solver.condensation import Condensation, contact_dofs, static_operator

    K0, Bf, *_ = static_operator(assemble(_block_model()))
    ref = Bf @ np.linalg.solve(K0.toarray(), Bf.T.toarray())
    c = Condensation.build(K0, Bf, backend)
    assert c.counters["condensed_columns"] == 0
    assert np.abs(c.G - ref).max() <= 1e-12 * np.abs(ref).max()
    # the same factor used by blocks of solves (a factor not ordered for B) agrees too
    plain = Condensation.build(K0, Bf, backend, factor=factorize(K0, backend))
    assert plain.counters["condensed_columns"] == Bf.shape[0]
    assert np.abs(plain.G - ref).max() <= 1e-12 * np.abs(ref).max()
    F = factorize(K0, backend, last=contact_dofs(Bf))
    assert F.can_condense(Bf)
    assert not F.can_condense(sp.csr_matrix(np.eye(1, K0.shape[0], 0)))  # an interior DOF


def test_fill_reducing_order_puts_the_given_dofs_last_and_groups_nodes():
    from stepcontact.fem.assembly import assemble
    from stepcontact.solver.condensation import contact_dofs, static_operator
    from stepcontact.solver.linalg import fill_reducing_order, node_groups

    system = assemble(_block_model(2))
    K0, Bf, d, free, *_ = static_operator(system)
    last = contact_dofs(Bf)
    order = fill_reducing_order(K0, last)
    assert np.array_equal(np.sort(order), np.arange(K0.shape[0]))
    assert set(order[-len(last):]) == set(last)
    node_of = system.dofs.node_of()[free]
    assert np.array_equal(np.sort(fill_reducing_order(K0, last, node_of)),
                          np.arange(K0.shape[0]))
    # without the node map, DOFs of equal two-step pattern are grouped: the two DOFs of a node
    # share a group in most places (a split or merged group costs ordering time only)
    groups = node_groups(K0)
    same = groups[::2] == groups[1::2] if np.array_equal(node_of[::2], node_of[1::2]) else None
    assert same is not None and same.mean() > 0.8  # 0.86 with mortar CFEs (wider B rows)
    order = fill_reducing_order(K0, last)
    assert set(order[-len(last):]) == set(last)


def test_too_many_contact_unknowns_for_dense_g_is_a_clear_error_before_any_work():
    """The size at which dense G stops being sensible is explicit: an estimate in the message,
    raised before the factorisation (no crash, no swapping)."""
    from stepcontact.fem.assembly import assemble
    from stepcontact.solver.condensation import (
        Condensation,
        check_dense_memory,
        dense_memory,
        schur_fits,
        static_operator,
    )

    K0, Bf, *_ = static_operator(assemble(_block_model()))
    need = sum(dense_memory(Bf.shape[0]).values())  # float64
    with pytest.raises(SolverError, match=rf"{Bf.shape[0] // 2} CFEs .*need about"):
        Condensation.build(K0, Bf, "scipy", memory_limit=0.4 * need)  # not even in float32
    with pytest.raises(SolverError, match=rf"{Bf.shape[0] // 2} CFEs .*in float64"):
        Condensation.build(K0, Bf, "scipy", memory_limit=0.9 * need, precision="float64")
    c = Condensation.build(K0, Bf, "scipy", memory_limit=0.9 * need)  # auto: float32 fits
    assert c.precision == "float32"
    check_dense_memory(Bf.shape[0], limit=2 * need)  # fits: no error
    with pytest.raises(SolverError, match=r"20000 CFEs \(2m = 40000 contact unknowns\) need "
                       r"about 19\.4 GB in float32"):
        check_dense_memory(40_000, limit=16 * 2**30)
    with pytest.raises(SolverError, match=r"need about 38\.7 GB in float64"):
        check_dense_memory(40_000, limit=16 * 2**30, precision="float64")
    assert schur_fits(1000, limit=1e9) and not schur_fits(20_000, limit=4e9)


# ---- small systems: a dense factorisation, never MKL -----------------------------------------
def _two_dof() -> sc.DiscreteModel:
    """tests/test_discrete.py's point on a rough floor (2 DOFs): pressed, then pushed until it
    slips at λ = f P and lifts off at λ = −P k₁₁/k₁₂ (closed forms there)."""
    return sc.DiscreteModel(
        K=[[2e3, -1e3], [-1e3, 2e3]], normal_rows=[[0.0, 1.0]], tangent_rows=[[1.0, 0.0]],
        loads={"press": {"uy": -1.0}, "push": {"ux": 1.0}}, friction=0.5,
        dof_names=("ux", "uy"), name="point",
        program=(sc.Segment("press", 100.0), sc.Segment("push", 300.0)))


def _same_path(a, b, rtol: float) -> None:
    assert a.status == b.status
    assert [(e.cfe, e.transition) for e in a.events] == [(e.cfe, e.transition) for e in b.events]
    assert np.allclose(a.lam, b.lam, rtol=rtol, atol=0.0)
    scale = max(np.abs(a.N).max(), np.abs(a.Q).max())
    assert np.abs(a.N - b.N).max() <= rtol * scale and np.abs(a.Q - b.Q).max() <= rtol * scale


@pytest.mark.parametrize("name", ["two-DOF", "block", "sliding block"])
def test_small_model_auto_backend_is_dense_and_gives_the_superlu_path(name):
    """Below DENSE_BELOW DOFs ``backend="auto"`` factorises densely (not PARDISO: a 2-DOF
    discrete model once crashed in its Schur phase).  Reference: the same run with SuperLU
    (``backend="scipy"``): the same events, λ and forces to 1e-12 relative (round-off of two
    factorisations of the same well-conditioned K₀); for the 2-DOF point also the closed forms
    λ_slip = f P = 50 and λ_lift = −P k₁₁/k₁₂ = 200 to 1e-12."""
    from stepcontact.solver.linalg import DENSE_BELOW

    model = {"two-DOF": _two_dof, "block": _block_model,
             "sliding block": lambda: vm.sliding_block(0.4, 10.0)}[name]()
    c = sc.condense(model)
    assert c.factor.name == "dense" and c.A.shape[0] < DENSE_BELOW
    auto = sc.solve_static(model)
    ref = sc.solve_static(model, backend="scipy")
    _same_path(auto, ref, 1e-12)
    assert auto.residual.max() < 1e-12 and auto.violation.max() < 1e-12
    if name == "two-DOF":
        lams = [e.lam for e in auto.events]
        assert lams == pytest.approx([50.0, 200.0], rel=1e-12)


def test_dense_condensed_matrix_equals_dense_inverse():
    """G = B K₀⁻¹ Bᵀ of the dense backend against numpy's solve, to 1e-12 relative."""
    from stepcontact.fem.assembly import assemble
    from stepcontact.solver.condensation import Condensation, static_operator

    K0, Bf, *_ = static_operator(assemble(_block_model()))
    ref = Bf @ np.linalg.solve(K0.toarray(), Bf.T.toarray())
    c = Condensation.build(K0, Bf, "dense")
    assert c.factor.name == "dense" and c.counters["condensed_columns"] == 0
    assert np.abs(c.G - ref).max() <= 1e-12 * np.abs(ref).max()


def test_large_model_keeps_the_sparse_backend():
    """At DENSE_BELOW DOFs or more ``auto`` keeps the first sparse backend (PARDISO when
    installed: the benchmarks rely on it)."""
    from stepcontact.solver.linalg import DENSE_BELOW, auto_backend

    c = sc.condense(_block_model(3))
    assert c.A.shape[0] >= DENSE_BELOW
    assert c.factor.name == factorize(sp.eye(1, format="csc"), available_backends()[0]).name
    assert auto_backend(DENSE_BELOW - 1) == "dense"
    assert auto_backend(DENSE_BELOW) == available_backends()[0]


# ---- PARDISO: one factorisation for the Schur complement and the solves ---------------------
def _pardiso_phases(monkeypatch) -> list[int]:
    """The PARDISO phases called from now on, in order (a spy on ``_Pardiso._call``)."""
    from stepcontact.solver import linalg

    phases: list[int] = []
    call = linalg._Pardiso._call

    def spy(self, pt, iparm, phase, *args):
        phases.append(int(phase))
        return call(self, pt, iparm, phase, *args)

    monkeypatch.setattr(linalg._Pardiso, "_call", spy)
    return phases


@pytest.mark.skipif("pypardiso" not in available_backends(),
                    reason="MKL PARDISO (pypardiso and mkl_rt) is not installed")
@pytest.mark.parametrize("spread", [False, True], ids=["contact DOFs", "scattered DOFs"])
def test_pardiso_schur_complement_and_solves_share_one_factorisation(monkeypatch, spread):
    """With DOFs ordered last, PARDISO factorises once (phase 12, partial, with the Schur
    complement: iparm[35] = 1) and then only substitutes (phases 331 and 333 around the dense
    Schur solve).  References: G = B K₀⁻¹ Bᵀ against numpy's dense solve to 1e-12 relative;
    the solves (a vector and a block of 4) against numpy's dense solve to 1e-12 relative (K₀ of
    the block model: condition number about 1e3; measured 6e-16 to 3e-15 for G, 8e-15 to
    2e-14 for the solves).  Also with a set of "last" DOFs scattered over the model (every 7th
    DOF), not a separator."""
    from stepcontact.fem.assembly import assemble
    from stepcontact.solver.condensation import contact_dofs, static_operator

    K0, Bf, *_ = static_operator(assemble(_block_model(2)))
    last = np.arange(0, K0.shape[0], 7) if spread else contact_dofs(Bf)
    B = sp.csr_matrix(np.eye(K0.shape[0])[last[::3]]) if spread else Bf
    Kd = K0.toarray()
    ref = B @ np.linalg.solve(Kd, B.T.toarray())
    phases = _pardiso_phases(monkeypatch)
    F = factorize(K0, "pypardiso", last=last)
    assert F.can_condense(B)
    G = F.condensed(B)
    assert np.abs(G - ref).max() <= 1e-12 * np.abs(ref).max()
    b = np.random.default_rng(2).standard_normal((K0.shape[0], 4))
    for rhs in (b[:, 0], b):
        x = F.solve(rhs)
        x_ref = np.linalg.solve(Kd, rhs)
        assert x.shape == rhs.shape
        assert np.abs(x - x_ref).max() <= 1e-12 * np.abs(x_ref).max()
    assert phases == [12, 331, 333, 331, 333]


@pytest.mark.skipif("pypardiso" not in available_backends(),
                    reason="MKL PARDISO (pypardiso and mkl_rt) is not installed")
def test_pardiso_solve_of_contact_forces_is_one_backward_substitution(monkeypatch):
    """A right-hand side on the contact DOFs only (B_fᵀ t: how a state's displacements and a
    mechanism's mode are recovered) is solved by the dense Schur solve and PARDISO's backward
    substitution alone (phase 333, no forward sweep).  Reference: numpy's dense solve of K₀
    of the block model, to 1e-12 relative (condition number about 1e3; a vector and a block
    of 3).  Then the displacements of the block model's run (which recovers its fields that
    way) satisfy K u + Bᵀ s = f to 1e-10 relative at every stored state (Condensed.check,
    an independent product with K; measured 7e-15)."""
    from stepcontact.fem.assembly import assemble
    from stepcontact.solver.condensation import contact_dofs, static_operator

    K0, Bf, *_ = static_operator(assemble(_block_model(2)))
    F = factorize(K0, "pypardiso", last=contact_dofs(Bf))
    t = np.random.default_rng(4).standard_normal((Bf.shape[0], 3))
    b = np.asarray(Bf.T @ t)
    Kd = K0.toarray()
    phases = _pardiso_phases(monkeypatch)
    for rhs in (b[:, 0], b):
        x = F.solve_last(rhs)
        x_ref = np.linalg.solve(Kd, rhs)
        assert x.shape == rhs.shape
        assert np.abs(x - x_ref).max() <= 1e-12 * np.abs(x_ref).max()
    assert phases == [333, 333]
    res = sc.solve_static(_block_model(2), backend="pypardiso", store_fields="all")
    assert res.status.value == "completed" and len(res.fields) == res.n_states
    assert np.nanmax(res.residual) <= 1e-10
    del res  # (its factorisation released here, not in the spy of another test)
    gc.collect()


@pytest.mark.skipif("pypardiso" not in available_backends(),
                    reason="MKL PARDISO (pypardiso and mkl_rt) is not installed")
def test_pardiso_for_many_solves_keeps_a_full_factorisation_for_the_solves(monkeypatch):
    """A driver that solves at every step (dynamics) asks for a second, full factorisation
    beside the partial one: then a solve is one phase 33 on it, not the block elimination.
    References: G from the partial factorisation and the solves (a vector and a block of 4)
    against numpy's dense solve, 1e-12 relative (K₀ of the block model, condition about 1e3);
    the phases called: 12 (partial, with Schur), 12 (full, once), then 33 per solve."""
    from stepcontact.fem.assembly import assemble
    from stepcontact.solver.condensation import contact_dofs, static_operator

    K0, Bf, *_ = static_operator(assemble(_block_model(2)))
    Kd = K0.toarray()
    phases = _pardiso_phases(monkeypatch)
    F = factorize(K0, "pypardiso", last=contact_dofs(Bf))
    F.for_many_solves()
    F.for_many_solves()  # (once is enough: a second call does nothing)
    ref = Bf @ np.linalg.solve(Kd, Bf.T.toarray())
    assert np.abs(F.condensed(Bf) - ref).max() <= 1e-12 * np.abs(ref).max()
    b = np.random.default_rng(3).standard_normal((K0.shape[0], 4))
    for rhs in (b[:, 0], b):
        x_ref = np.linalg.solve(Kd, rhs)
        assert np.abs(F.solve(rhs) - x_ref).max() <= 1e-12 * np.abs(x_ref).max()
    assert phases == [12, 12, 33, 33]


def test_small_models_never_look_for_mkl(monkeypatch):
    """The backend rule for small systems: below DENSE_BELOW DOFs ``auto`` chooses the dense
    factorisation without consulting the sparse backends, so MKL is never located or loaded
    (``_mkl_pardiso`` is made to fail the test if it is called): a static run of the 2-DOF
    point and of the block model (318 DOFs), and a dynamic run of a 2-DOF block on a floor
    pushed by P = 2fW for t_p = 0.2 s (200 steps).  Reference for the dynamic run: the rigid
    block's slip ½ a t_p², a = (P − fW)/m, at the end of the push, to 1e-3 relative (the
    time step's error, O(Δt/t_p) at most; measured 2.5e-5)."""
    from stepcontact.model.timefunction import Pulse
    from stepcontact.solver import linalg
    from stepcontact.solver.program import solve_dynamic

    def no_mkl():
        raise AssertionError("a small model looked for MKL PARDISO")

    monkeypatch.setattr(linalg, "_mkl_pardiso", no_mkl)
    for model in (_two_dof(), _block_model()):
        res = sc.solve_static(model)
        assert res.status.value == "completed"
        assert sc.condense(model).factor.name == "dense"
    m_, f, g, tp = 1000.0, 0.3, 9.81, 0.2
    dm = sc.DiscreteModel(K=[[0.0, 0.0], [0.0, 0.0]], normal_rows=[[0, 1]], tangent_rows=[[1, 0]],
                          loads={"weight": {"uy": -m_ * g}, "push": {"ux": 1.0}}, friction=f,
                          dof_names=("ux", "uy"), program=[sc.Segment("weight", 1.0)])
    P = 2 * f * m_ * g
    res = solve_dynamic(dm, dt=1e-3, duration=0.2, loads={"push": Pulse(P, 0.0, tp,
                                                                          "rectangular")},
                        mass=np.diag([m_, m_]), initial=sc.solve_static(dm))
    a1 = (P - f * m_ * g) / m_
    assert res.u[-1][0] == pytest.approx(0.5 * a1 * tp**2, rel=1e-3)


# ---- G from the dense Schur block: one triangular solve and a symmetric product (issue 28 §6)
def test_condensed_cholesky_equals_the_two_solve_route():
    """G = B_c S⁻¹ B_cᵀ as Wᵀ W (W = L⁻¹ B_cᵀ, S = L Lᵀ; ``linalg.condensed_cholesky``) against
    numpy's dense solve of S, to 1e-12 relative (S = A Aᵀ + c I, condition number below
    10; measured below 1e-15), exactly symmetric, with a row of B_c that touches no DOF (a
    zero row and column of G) and an empty B_c."""
    import scipy.linalg as sla

    from stepcontact.solver.linalg import condensed_cholesky, gram

    rng = np.random.default_rng(7)
    c, n2m = 300, 130
    A = rng.standard_normal((c, c))
    S = A @ A.T + c * np.eye(c)
    rows = np.repeat(np.arange(n2m), 4)
    cols = rng.integers(0, c, rows.size)
    Bc = sp.csr_matrix((rng.standard_normal(rows.size), (rows, cols)), shape=(n2m, c))
    Bc = sp.csr_matrix(Bc.multiply(np.arange(n2m)[:, None] != 17))  # row 17 empty
    Bc.eliminate_zeros()
    Bd = Bc.toarray()
    ref = Bd @ np.linalg.solve(S, Bd.T)
    L = sla.cho_factor(S.copy(), lower=True)[0]  # (its upper triangle holds garbage)
    G = condensed_cholesky(L, Bc)
    assert np.abs(G - ref).max() <= 1e-12 * np.abs(ref).max()
    assert np.array_equal(G, G.T) and not G[17].any()
    W = rng.standard_normal((50, 2100))  # more columns than one mirror block
    assert np.array_equal(gram(W), gram(W).T)
    assert np.abs(gram(W) - W.T @ W).max() <= 1e-12 * np.abs(W.T @ W).max()
    assert condensed_cholesky(L, sp.csr_matrix((0, c))).shape == (0, 0)


def _block3d() -> sc.Model:
    """A 1 × 1 × 0.5 m block (4 × 4 × 2 hex8) on a 2 × 2 × 0.5 m base (6 × 6 × 2 hex8, fixed at
    its bottom), non-matching meshes: 519 free DOFs, 75 contact unknowns on 150 contact DOFs."""
    concrete = sc.Material(30e9, 0.2, 2400)
    blk = sc.box("block", (0, 0, 0), (1, 1, 0.5), (4, 4, 2), concrete)
    base = sc.box("base", (-0.5, -0.5, -0.5), (1.5, 1.5, 0.0), (6, 6, 2), concrete)
    m = sc.Model(bodies=(blk, base))
    return m.add(
        sc.Support("bed", m.select("base", boundary="bottom"), "xyz"),
        sc.Interface("joint", m.select("block", boundary="bottom"),
                     m.select("base", boundary="top"), friction=0.5, facets=8),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
        sc.Segment("weight", 1.0))


@pytest.mark.parametrize("backend", [b for b in available_backends() if b != "cholmod"])
def test_3d_g_from_the_schur_block_equals_the_serial_blocked_solves(backend):
    """A 3D model's G read off the Schur block (PARDISO's Schur complement, or SuperLU's
    trailing block, then one triangular solve and a symmetric product) equals the serial
    blocked route's G (2m solves with a plain factorisation) to 1e-12 relative, and both equal
    numpy's dense solve of K₀ to 1e-12 relative (measured below 1e-14).  The route is the one
    asked for: no solve per contact unknown (``condensed_columns`` 0) and, with PARDISO, G
    formed once by ``condensed_cholesky`` (its counter) and exactly symmetric."""
    from stepcontact.fem.assembly import assemble
    from stepcontact.solver.condensation import Condensation, static_operator

    K0, Bf, *_ = static_operator(assemble(_block3d()))
    schur = Condensation.build(K0, Bf, backend)
    blocked = Condensation.build(K0, Bf, backend, factor=factorize(K0, backend), block=16)
    ref = Bf @ np.linalg.solve(K0.toarray(), Bf.T.toarray())
    assert schur.counters["condensed_columns"] == 0
    assert blocked.counters["condensed_columns"] == Bf.shape[0]
    scale = np.abs(ref).max()
    assert np.abs(schur.G - blocked.G).max() <= 1e-12 * scale
    assert np.abs(schur.G - ref).max() <= 1e-12 * scale
    assert np.abs(blocked.G - ref).max() <= 1e-12 * scale
    if backend == "pypardiso":
        assert schur.factor.stats == {"condensed_cholesky": 1}
        assert np.array_equal(schur.G, schur.G.T)


def test_superlu_blocks_of_g_solved_in_two_threads_give_the_serial_g(monkeypatch):
    """SciPy's SuperLU releases the GIL in its solves: G's column blocks are solved in
    ``SOLVE_THREADS`` threads (counter ``solve_threads``), each block with the arithmetic of
    the serial loop, so G is the serial G bit for bit (reference: the same build with one
    thread), and equals numpy's dense solve of K₀ to 1e-12 relative."""
    import os

    from stepcontact.fem.assembly import assemble
    from stepcontact.solver import condensation
    from stepcontact.solver.condensation import Condensation, static_operator

    K0, Bf, *_ = static_operator(assemble(_block3d()))
    factor = factorize(K0, "scipy")
    two = Condensation.build(K0, Bf, "scipy", factor=factor, block=16)
    assert two.counters.get("solve_threads", 1) == min(2, os.cpu_count() or 1)
    monkeypatch.setattr(condensation, "SOLVE_THREADS", 1)
    one = Condensation.build(K0, Bf, "scipy", factor=factor, block=16)
    assert "solve_threads" not in one.counters
    assert np.array_equal(two.G, one.G)
    ref = Bf @ np.linalg.solve(K0.toarray(), Bf.T.toarray())
    assert np.abs(two.G - ref).max() <= 1e-12 * np.abs(ref).max()
