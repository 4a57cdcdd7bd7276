"""Checks of the frictionless QP reference itself (tests/reference.py), independent of the
solver: hand-computable cases, KKT conditions recomputed from scratch, agreement of the three
active-set identification routes, and brute-force enumeration of the active sets."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from numpy.testing import assert_allclose

import verification_models as vm
from reference import (
    ReferenceFailure,
    final_factors,
    frictionless_reference,
    kkt_residuals,
    load_at,
)
from stepcontact import (
    ContactLayer,
    Frame,
    Interface,
    LoadPattern,
    Model,
    NodalLoad,
    PrescribedDisplacement,
    Segment,
    Support,
    rectangle,
)
from stepcontact.fem.assembly import assemble

E, A, I, L = 200e9, 1e-3, 1e-6, 2.0


def cantilever(P: float, gap: float, layer: ContactLayer | None = None) -> Model:
    """Cantilever frame (clamped at x = 0) whose tip rests on a rigid base through one CFE
    with initial gap ``gap``; tip load P downward (N)."""
    beam = Frame.line("beam", (0.0, 0.0), (L, 0.0), 4, E=E, A=A, I=I)
    base = rectangle("base", (L - 0.5, -0.5), (L + 0.5, 0.0), 2, 1, vm.CONCRETE)
    m = Model().add(beam, base)
    tip = m.select("beam", x=L)
    return m.add(
        Support("clamp", m.select("beam", x=0.0), "xyrz"),
        Support("rigid", m.select("base", boundary=False)),
        Interface("tip", tip, m.select("base", y=0.0), gap=gap, layer=layer),
        LoadPattern("P", [NodalLoad(tip, fy=-P)]),
        Segment("P", 1.0),
    )


@pytest.mark.parametrize("method", ["quadprog", "osqp", "active_set"])
@pytest.mark.parametrize("P", [1e3, 1e4])
def test_cantilever_on_unilateral_support(method, P):
    """Tip force R = P − 3 E I g / L³ when the gap closes, else 0 (free tip deflection
    P L³ / 3 E I).  Tolerance 1e-10 relative (Euler–Bernoulli frames are exact for this)."""
    g = 1e-3
    s = assemble(cantilever(P, g))
    r = frictionless_reference(s, method=method)
    free_tip = P * L**3 / (3 * E * I)
    tip_y = s.dofs.of[s.model.node_offsets["beam"] + 4, 1]
    if free_tip > g:
        assert_allclose(-r.N[0], P - 3 * E * I * g / L**3, rtol=1e-10)
        assert_allclose(r.u[tip_y], -g, rtol=1e-10)
        assert_allclose(r.un[0], 0.0, atol=1e-12 * g)
    else:
        assert_allclose(r.N[0], 0.0, atol=1e-10 * P)
        assert_allclose(r.u[tip_y], -free_tip, rtol=1e-10)
        assert_allclose(r.un[0], free_tip - g, rtol=1e-10)


@pytest.mark.parametrize("method", ["quadprog", "osqp", "active_set"])
def test_cantilever_with_compliant_layer(method):
    """Layer of stiffness C_n = kn · A_k (A_k = 1 m² for an isolated node, thickness 1 m):
    R = (P L³/3EI − g) / (L³/3EI + 1/C_n).  Tolerance 1e-10 relative."""
    P, g, kn = 1e4, 1e-3, 5e5
    s = assemble(cantilever(P, g, ContactLayer(kn=kn, kt=kn)))
    r = frictionless_reference(s, method=method)
    flex = L**3 / (3 * E * I)
    assert_allclose(-r.N[0], (P * flex - g) / (flex + 1.0 / kn), rtol=1e-10)
    assert_allclose(r.un[0] + r.N[0] / kn, 0.0, atol=1e-12 * g)


def test_prescribed_displacement_column():
    """A column pushed by a prescribed top displacement d onto a rigid base through a gap g:
    N = −EA/H (d − g).  Tolerance 1e-10 relative."""
    H, d, g = 3.0, 2e-3, 5e-4
    col = Frame.line("col", (0.0, 0.0), (0.0, H), 3, E=E, A=A, I=I)
    base = rectangle("base", (-0.5, -0.5), (0.5, 0.0), 2, 1, vm.CONCRETE)
    m = Model().add(col, base)
    top = m.select("col", y=H)
    m = m.add(
        Support("top", top, "xrz"),
        Support("rigid", m.select("base", boundary=False)),
        Interface("foot", m.select("col", y=0.0), m.select("base", y=0.0), gap=g),
        LoadPattern("press", [PrescribedDisplacement(top, "y", -d)]),
        Segment("press", 1.0),
    )
    s = assemble(m)
    r = frictionless_reference(s)
    assert_allclose(r.N[0], -E * A / H * (d - g), rtol=1e-10)
    f, ubar = load_at(s, final_factors(m))
    assert_allclose(r.u[s.fixed], ubar[s.fixed], atol=0.0)


MODELS = {
    "block0": lambda: vm.frictionless_block(0),
    "block1": lambda: vm.frictionless_block(1),
    "two_blocks": vm.frictionless_two_blocks,
    "frame": vm.frictionless_frame,
    "slab": lambda: vm.uplift_slab("body_force", 10.0),
}


@pytest.mark.parametrize("name", sorted(MODELS))
def test_kkt_and_methods_agree(name):
    """KKT residuals recomputed from the assembled system ≤ 1e-12 (equilibrium relative to
    ‖f‖, signs relative to max|N| and max|u|); quadprog, OSQP and the pure active-set start
    give the same solution to 1e-10 relative."""
    m = MODELS[name]()
    s = assemble(m)
    fac = final_factors(m)
    sols = {meth: frictionless_reference(s, fac, method=meth)
            for meth in ("quadprog", "osqp", "active_set")}
    for meth, r in sols.items():
        res = kkt_residuals(s, fac, r.u, r.N)
        for key, v in res.items():
            assert v <= 1e-12, f"{meth}: KKT residual {key} = {v:.2e}"
    ref = sols["quadprog"]
    if name != "slab":  # the other models are built so that part of the contact is open
        assert 0 < ref.active.sum() < s.m
    for meth in ("osqp", "active_set"):
        r = sols[meth]
        assert_allclose(r.u, ref.u, rtol=0, atol=1e-10 * np.abs(ref.u).max())
        assert_allclose(r.N, ref.N, rtol=0, atol=1e-10 * np.abs(ref.N).max())


@pytest.mark.parametrize("name", ["block0", "frame"])
def test_brute_force_active_set(name):
    """Among all 2^m active sets exactly one gives an admissible state (p ≥ 0 on it, u_n ≤ 0
    off it; tolerance 1e-10 relative) and it is the reference's: an enumeration that shares
    nothing with the reference but the assembled matrices."""
    m = MODELS[name]()
    s = assemble(m)
    fac = final_factors(m)
    f, ubar = load_at(s, fac)
    free = np.flatnonzero(~s.fixed)
    K = s.K.tocsr()
    ks = np.abs(K.diagonal()).max()  # scale forces to metres so the rank test is meaningful
    Kff = K[free][:, free].toarray() / ks
    rhs = (f[free] - K[free][:, s.fixed] @ ubar[s.fixed]) / ks
    Bn = s.B.tocsr()[s.m:]
    Bf = Bn[:, free].toarray()
    g = -s.w0[s.m:] - Bn[:, s.fixed] @ ubar[s.fixed]
    admissible = []
    for bits in itertools.product([False, True], repeat=s.m):
        act = np.array(bits)
        k = int(act.sum())
        M = np.block([[Kff, Bf[act].T], [Bf[act], np.zeros((k, k))]])
        if np.linalg.matrix_rank(M) < M.shape[0]:
            continue  # a mechanism for this active set
        sol = np.linalg.solve(M, np.r_[rhs, g[act]])
        x, p = sol[: len(free)], sol[len(free):]
        un = Bf @ x - g
        scale_p = max(np.abs(p).max(initial=0.0), 1.0)
        if np.all(p >= -1e-10 * scale_p) and np.all(un[~act] <= 1e-10 * np.abs(x).max()):
            admissible.append((act, x, p))
    ref = frictionless_reference(s, fac)
    # sets differing only by CFEs with p = 0 and u_n = 0 give the same state
    assert admissible
    for act, x, p in admissible:
        assert_allclose(x, ref.u[free], rtol=0, atol=1e-9 * np.abs(ref.u).max())
        N = np.zeros(s.m)
        N[act] = -p * ks
        assert_allclose(N, ref.N, rtol=0, atol=1e-9 * np.abs(ref.N).max())
    assert any(np.array_equal(act, ref.active) for act, _, _ in admissible)


def test_mechanism_is_reported():
    """A body held by nothing once every CFE is open is a mechanism: ReferenceFailure."""
    m = vm.uplift_slab("body_force", 20.0)  # uplift = 1.7 × weight at the end
    s = assemble(m)
    with pytest.raises(ReferenceFailure):
        frictionless_reference(s, method="active_set")
