"""K₀ singular or not: one diagnosis naming the free bodies, whichever way it is found.

K₀ = K_ff + B_fᵀ D B_f is built exactly as :meth:`Condensed.from_system` does.  A singular K₀
either stops the factorisation at an exact zero pivot (SuperLU on some machines) or is
factorised with round-off pivots; both must give the same ModelError.  A weak but real spring
is not a mechanism.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from skfem import MeshTri

import stepcontact as sc
from stepcontact.contact.geometry import build_contact
from stepcontact.fem import assembly as asm
from stepcontact.solver import linalg, regularity
from stepcontact.solver.condensation import stabilisation
from stepcontact.solver.regularity import RHO_SINGULAR, factorize_regular, relative_stiffness

MAT = sc.Material(1e9, 0.2, 1000.0)
CONCRETE = sc.Material(30e9, 0.2, 2400.0)
PREFIX = "the structure is a mechanism even with every CFE stuck: "


def _k0(system: asm.System):
    """K₀ and the free DOFs, as Condensed.from_system builds them."""
    free = np.flatnonzero(~system.fixed)
    K = system.K.tocsr()
    Kff = K[free][:, free].tocsr()
    Bf = system.B[:, free].tocsr()
    d = stabilisation(Kff, Bf)
    return (Kff + Bf.T @ sp.diags(d) @ Bf).tocsc(), free


def _unchecked(model: sc.Model) -> asm.System:
    """The assembled system without assemble()'s "is every body restrained" checks: the only
    way a body with no support at all reaches the factorisation."""
    dofs = asm.dof_map(model)
    fixed = np.zeros(dofs.ndof, dtype=bool)
    for s in model.supports:
        ids = model.global_nodes(s.nodes)
        for name in s.dofs:
            fixed[dofs.of[ids, asm._DOF_INDEX[name]]] = True
    cfe = build_contact(model)
    B, w0 = asm.contact_operator(cfe, dofs)
    return asm.System(model, dofs, asm.stiffness(model, dofs), fixed, {}, cfe, B, w0)


def _diagnosis(system: asm.System, **kw) -> str:
    K0, free = _k0(system)
    with pytest.raises(sc.ModelError) as info:
        factorize_regular(system, K0, free, **kw)
    assert info.value.item == "model"
    assert info.value.problem.startswith(PREFIX), info.value.problem
    assert info.value.problem.endswith("; add supports, springs or contact interfaces")
    return info.value.problem


def _block_held_by_one_cfe() -> sc.Model:
    """test_model_errors.py::test_mechanism_with_every_cfe_stuck_is_an_error: the block
    touches the base through one CFE at (0.5, 0) and can rotate about it."""
    base = sc.rectangle("base", (0, -1), (2, 0), 2, 1, MAT)
    blk = sc.rectangle("blk", (0, 0), (1, 1), 2, 2, MAT)
    m = sc.Model(bodies=[base, blk])
    one = sc.NodeSet("blk", [int(np.argmin(np.hypot(*(blk.points - [0.5, 0.0]).T)))])
    return m.add(
        sc.Support("s", m.select("base", y=-1)),
        sc.Interface("j", one, m.select("base", y=0), 0.5),
        sc.LoadPattern("w", [sc.BodyForce(), sc.NodalLoad(m.select("blk", y=1.0), fy=-1.0)]),
        sc.Segment("w", 1.0),
    )


class _FirstCall:
    """Stand-in for linalg.factorize whose first call (K₀ itself) is replaced by ``first``;
    later calls (the regularised matrix of the diagnosis) go to the real backend."""

    def __init__(self, first):
        self.first = first
        self.calls = 0

    def __call__(self, K, backend="auto", last=None, groups=None):
        self.calls += 1
        return (self.first(K, backend) if self.calls == 1 else
                linalg.factorize(K, backend, last=last, groups=groups))


def _zero_pivot(K, backend):
    raise sc.SolverError("stiffness matrix is singular (Factor is exactly singular)")


def _roundoff_pivots(K, backend):
    """A factor that 'succeeds': K₀ perturbed at round-off level (1e-15 of its diagonal)."""
    return linalg.factorize(K + sp.diags(1e-15 * K.diagonal()), backend)


# --------------------------------------------------------------------------------------------
def test_cfe_that_cannot_hold_the_block_same_diagnosis_both_ways(monkeypatch):
    system = asm.assemble(_block_held_by_one_cfe())
    expected = PREFIX + ("body 'blk' can move freely (rotation about (0.5, 0)); "
                         "add supports, springs or contact interfaces")
    natural = _diagnosis(system)  # whatever this machine's SuperLU does
    assert natural == expected

    pivot = _FirstCall(_zero_pivot)
    monkeypatch.setattr(regularity, "factorize", pivot)
    assert _diagnosis(system) == expected
    assert pivot.calls == 2  # K₀ failed, then the regularised matrix of the diagnosis

    roundoff = _FirstCall(_roundoff_pivots)
    monkeypatch.setattr(regularity, "factorize", roundoff)
    assert _diagnosis(system) == expected
    assert roundoff.calls == 2  # K₀ "factorised", found singular by ρ, then the diagnosis


def test_criterion_margin_of_the_mechanism():
    """ρ of a mechanism is round-off (measured ~1e-17), far below RHO_SINGULAR ≈ 2.2e-14,
    even from a factor that met no zero pivot."""
    K0, _ = _k0(asm.assemble(_block_held_by_one_cfe()))
    rho = relative_stiffness(K0, _roundoff_pivots(K0, "scipy"))
    assert 0.0 <= rho < 1e-2 * RHO_SINGULAR


@pytest.mark.parametrize(
    ("support", "modes"),
    [
        (None, "any rigid-body motion: translation along x and y, rotation"),
        ("roller", "translation along x"),
        ("one node y", "translation along x and rotation about (1, 2.5)"),
        ("pin", "rotation about (1, 2)"),
    ],
)
def test_floating_body_is_named_with_its_free_mode(support, modes):
    b = sc.rectangle("slab", (1, 2), (3, 3), 4, 2, MAT)
    m = sc.Model(bodies=[b])
    if support == "roller":
        m = m.add(sc.Support("s", m.select("slab", y=2), "y"))
    elif support == "one node y":
        m = m.add(sc.Support("s", m.select("slab", x=1, y=2), "y"))
    elif support == "pin":
        m = m.add(sc.Support("s", m.select("slab", x=1, y=2)))
    assert _diagnosis(_unchecked(m)) == (
        PREFIX + f"body 'slab' can move freely ({modes}); add supports, springs or contact "
        "interfaces")


def test_weak_but_real_spring_is_not_a_mechanism():
    """A 30 GPa block (K_ii ≈ 6e10 N/m) held in x only by a 5 N/m spring, y on rollers.

    The spring carries a unit force alone: u = F/k = 0.2 m at its node.  The match is checked
    to 1e-4: the *stored* stiffness annihilates the rigid translation only to round-off,
    ≈ eps·ΣK_ii ≈ 4e-5 N/m here, i.e. ~1e-5 of the spring, so 1e-6 is below what double
    precision can represent for this model whatever the solver."""
    b = sc.rectangle("b", (0, 0), (1, 1), 2, 2, CONCRETE)
    m = sc.Model(bodies=[b])
    node = m.select("b", x=0.0, y=0.5)
    m = m.add(sc.Support("rollers", m.select("b", y=0.0), "y"),
              sc.Spring("weak", node, None, kx=5.0))
    system = asm.assemble(m)
    K0, free = _k0(system)
    factor = factorize_regular(system, K0, free)
    rho = relative_stiffness(K0, factor)
    assert rho > 100 * RHO_SINGULAR  # measured 2e-11: the spring's share of the x mode
    f = np.zeros(system.ndof)
    j = system.dofs.of[m.global_nodes(node)[0], 0]
    f[j] = 1.0
    u = np.zeros(system.ndof)
    u[free] = factor.solve(f[free])
    assert np.all(np.isfinite(u))
    assert abs(u[j] / 0.2 - 1.0) < 1e-4
    ux = u[system.dofs.of[:, 0]]
    assert np.allclose(ux, 0.2, rtol=1e-4)  # a rigid translation: the body hardly deforms


def test_only_the_free_body_is_named():
    free_body = sc.rectangle("loose", (1, 2), (3, 3), 4, 2, MAT)
    held = sc.rectangle("held", (5, 0), (6, 1), 2, 2, MAT)
    m = sc.Model(bodies=[free_body, held])
    m = m.add(sc.Support("s", m.select("held", y=0)))
    text = _diagnosis(_unchecked(m))
    assert "body 'loose' can move freely (any rigid-body motion" in text
    assert "'held'" not in text


def test_every_moving_body_is_named_with_its_own_mode():
    """Three collinear hinges: each bar rotates about its support."""
    a = sc.Frame.line("a", (0, 0), (2, 0), 2, E=2e11, A=1e-2, I=1e-4)
    b = sc.Frame.line("b", (2, 0), (4, 0), 2, E=2e11, A=1e-2, I=1e-4)
    m = sc.Model(bodies=[a, b])
    m = m.add(sc.Support("p", m.select("a", x=0)), sc.Support("q", m.select("b", x=4)),
              sc.Tie("hinge", m.select("a", x=2), m.select("b", x=2)))
    assert _diagnosis(asm.assemble(m)) == PREFIX + (
        "body 'a' can move freely (rotation about (0, 0)), body 'b' can move freely (rotation "
        "about (4, 0)); add supports, springs or contact interfaces")


def test_internal_mechanism():
    """Two triangles sharing one vertex: one is fixed, the other turns about the vertex."""
    p = np.array([[0, 1, 0, 2, 2.0], [0, 0, 1, 0, 1.0]])
    t = np.array([[0, 1, 2], [1, 3, 4]]).T
    m = sc.Model(bodies=[sc.Body.from_mesh("bow", MeshTri(p, t), "tri3", MAT)])
    m = m.add(sc.Support("s", sc.NodeSet("bow", [0, 2])))
    assert "body 'bow' can move freely (internal mechanism)" in _diagnosis(asm.assemble(m))


def test_unknown_backend_is_not_a_mechanism():
    system = asm.assemble(_block_held_by_one_cfe())
    K0, free = _k0(system)
    with pytest.raises(sc.SolverError, match="unknown linear-solver backend"):
        factorize_regular(system, K0, free, backend="nope")


@pytest.mark.parametrize("backend", ["dense", "scipy"])
def test_check_and_load_solves_in_one_call(backend):
    """The regularity check solves the run's right-hand sides (loads, reaction resultants)
    in the call of its first inverse-iteration step (``factorize_regular_solving``): one
    factorisation, the same decision, and K₀⁻¹ rhs.  References: numpy's dense solve of K₀ to
    1e-12 relative (a block on a fixed bed, condition number 41; measured 3e-16 dense,
    5e-16 SuperLU); ρ equal to that of the separate check (relative_stiffness, the same start
    block) to 1e-6 relative (the same iteration up to the first solve's round-off; measured
    equal)."""
    b = sc.rectangle("b", (0, 0), (2, 1), 4, 2, CONCRETE)
    m = sc.Model(bodies=[b])
    m = m.add(sc.Support("bed", m.select("b", y=0.0), "xy"))
    system = asm.assemble(m)
    K0, free = _k0(system)
    rhs = np.random.default_rng(5).standard_normal((K0.shape[0], 3))
    factor, X = regularity.factorize_regular_solving(system, K0, free, rhs, backend)
    X_ref = np.linalg.solve(K0.toarray(), rhs)
    assert X.shape == rhs.shape
    assert np.abs(X - X_ref).max() <= 1e-12 * np.abs(X_ref).max()
    rho, _ = regularity.stiffness_and_solve(K0, factor, rhs, regular_above=regularity.RHO_REGULAR)
    rho_ref = relative_stiffness(K0, factor, regular_above=regularity.RHO_REGULAR)
    assert rho == pytest.approx(rho_ref, rel=1e-6) and rho > 100 * RHO_SINGULAR
