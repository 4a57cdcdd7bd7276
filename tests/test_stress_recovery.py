"""Stress recovery operators (:class:`stepcontact.fem.continuum.StressRecovery`): the same
element-averaged stresses as the per-call evaluation through a scikit-fem basis, and the exact
Hooke stresses of a uniform strain field, for every element kind and both plane states."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose
from skfem import MeshQuad, MeshTri
from skfem.helpers import sym_grad

import stepcontact as sc
from stepcontact.fem.continuum import (
    StressRecovery,
    basis_of,
    plane_lame,
    stress_operator,
    stresses,
)

ELEMENTS = ("tri3", "tri6", "quad4", "quad8", "quad9")
PLANES = ("strain", "stress")
MAT = sc.Material(E=30e9, nu=0.2, density=2400)  # Pa, -, kg/m³


def per_call_stresses(body, u_body, plane):
    """The former implementation: a new basis, the strain at the quadrature points, the
    quadrature-weighted element mean of σxx, σyy, σxy, σzz (Pa)."""
    basis = basis_of(body)
    lam, mu = plane_lame(body.material.E, body.material.nu, plane)
    eps = sym_grad(basis.interpolate(u_body))  # (2, 2, nel, nqp)
    tr = eps[0, 0] + eps[1, 1]
    sxx = 2 * mu * eps[0, 0] + lam * tr
    syy = 2 * mu * eps[1, 1] + lam * tr
    sxy = 2 * mu * eps[0, 1]
    szz = body.material.nu * (sxx + syy) if plane == "strain" else 0.0 * tr
    dx = basis.dx
    vol = dx.sum(axis=1)
    return np.column_stack([(s * dx).sum(axis=1) / vol for s in (sxx, syy, sxy, szz)])


def distorted_body(element: str, seed: int = 0) -> sc.Body:
    """A 3 m × 1 m graded block whose interior nodes are moved at random (no element
    inverted), so that the strain varies inside each element."""
    rng = np.random.default_rng(seed)
    xs = np.r_[0.0, 0.4, 1.0, 1.8, 3.0]
    ys = np.r_[0.0, 0.3, 0.55, 1.0]
    mesh = (MeshTri if element.startswith("tri") else MeshQuad).init_tensor(xs, ys)
    p = mesh.p.copy()
    inner = (p[0] > 0) & (p[0] < 3) & (p[1] > 0) & (p[1] < 1)
    p[:, inner] += rng.uniform(-0.08, 0.08, (2, int(inner.sum())))
    return sc.Body.from_mesh(f"block-{element}", type(mesh)(p, mesh.t), element, MAT)


def hooke(eps: np.ndarray, plane: str) -> np.ndarray:
    """σxx, σyy, σxy, σzz (Pa) of a uniform strain (εxx, εyy, εxy) from the textbook formulas."""
    E, nu = MAT.E, MAT.nu
    exx, eyy, exy = eps
    if plane == "strain":
        c = E / ((1 + nu) * (1 - 2 * nu))
        sxx = c * ((1 - nu) * exx + nu * eyy)
        syy = c * (nu * exx + (1 - nu) * eyy)
        return np.array([sxx, syy, E / (1 + nu) * exy, nu * (sxx + syy)])
    c = E / (1 - nu**2)
    return np.array([c * (exx + nu * eyy), c * (nu * exx + eyy), E / (1 + nu) * exy, 0.0])


@pytest.mark.parametrize("plane", PLANES)
@pytest.mark.parametrize("element", ELEMENTS)
def test_operator_equals_per_call_evaluation(element, plane):
    body = distorted_body(element)
    rec = StressRecovery([body], plane)
    rng = np.random.default_rng(1)
    U = rng.standard_normal((2 * body.n_nodes, 3)) * 1e-3  # m
    for u in U.T:
        want = per_call_stresses(body, u, plane)
        assert want.shape == (len(body.cells), 4)
        got = rec(body.name, u)
        assert got.shape == want.shape
        assert_allclose(got, want, rtol=0, atol=1e-12 * np.abs(want).max())
        # the module function goes through the same (cached) operator
        assert_allclose(stresses(body, u, plane), got, rtol=0, atol=0)
    # a batch (n_dofs, k) gives (k, nel, 4)
    batch = rec(body.name, U)
    assert batch.shape == (3, len(body.cells), 4)
    for j in range(3):
        assert_allclose(batch[j], rec(body.name, U[:, j]), rtol=1e-14, atol=0)
    if plane == "stress":
        assert np.all(batch[..., 3] == 0.0)


@pytest.mark.parametrize("plane", PLANES)
@pytest.mark.parametrize("element", ELEMENTS)
def test_uniform_strain_gives_hooke_stresses(element, plane):
    """u = H·x with a constant H: every element carries the Hooke stresses of the symmetric
    part of H (the skew part, a rigid rotation, carries none); u is in every element space."""
    body = distorted_body(element, seed=3)
    H = np.array([[2.0e-4, -1.5e-4], [0.5e-4, -0.8e-4]])
    u = (body.points @ H.T).ravel()  # DOF 2i+c: node i, component c
    eps = np.array([H[0, 0], H[1, 1], 0.5 * (H[0, 1] + H[1, 0])])
    want = hooke(eps, plane)
    got = StressRecovery([body], plane)(body.name, u)
    assert_allclose(got, np.broadcast_to(want, got.shape), rtol=0,
                    atol=1e-9 * np.abs(want).max())
    # a pure rotation: no stress
    W = np.array([[0.0, -1e-3], [1e-3, 0.0]])
    rot = StressRecovery([body], plane)(body.name, (body.points @ W.T).ravel())
    assert np.abs(rot).max() <= 1e-9 * np.abs(want).max()


def test_model_bodies_frames_and_cache():
    base = sc.rectangle("base", (0, 0), (4, 1), 4, 2, MAT, element="quad8")
    block = sc.rectangle("block", (1, 1), (3, 2), 3, 2, MAT, element="tri3")
    beam = sc.Frame.line("beam", (0, 3), (4, 3), 4, E=200e9, A=0.01, I=1e-4)
    model = sc.Model(bodies=[base, beam, block], plane="stress")
    rec = StressRecovery(model)
    assert rec.plane == "stress"
    assert list(rec.operators) == ["base", "block"]  # the frame has no stresses
    assert "beam" not in rec and "base" in rec
    rng = np.random.default_rng(2)
    u = {b.name: rng.standard_normal(2 * b.n_nodes) * 1e-3 for b in (base, block)}
    out = rec.of(u)
    assert list(out) == ["base", "block"]
    for b in (base, block):
        assert out[b.name].shape == (len(b.cells), 4)
        want = per_call_stresses(b, u[b.name], "stress")
        assert_allclose(out[b.name], want, rtol=0, atol=1e-12 * np.abs(want).max())
    # built once per body and plane: later recoveries share the operators
    assert StressRecovery(model).operators["base"] is rec.operators["base"]
    assert stress_operator(base, "stress") is rec.operators["base"]
    assert stress_operator(base, "strain") is not rec.operators["base"]
    S = rec.operators["block"]
    assert S.format == "csr" and S.shape == (4 * len(block.cells), 2 * block.n_nodes)
    # explicit bodies + plane
    assert list(StressRecovery(model.bodies, "strain").operators) == ["base", "block"]


def test_errors():
    body = sc.rectangle("slab", (0, 0), (2, 1), 2, 1, MAT)
    rec = StressRecovery([body], "strain")
    with pytest.raises(ValueError, match=r"body 'slab': displacement of shape \(5,\)"):
        rec("slab", np.zeros(5))
    with pytest.raises(ValueError, match="expected"):
        rec("slab", np.zeros((2 * body.n_nodes, 2, 2)))
    with pytest.raises(KeyError, match="no continuum body 'beam'"):
        rec("beam", np.zeros(2))
    with pytest.raises(ValueError, match="plane='axisymmetric'"):
        StressRecovery([body], "axisymmetric")
    with pytest.raises(TypeError):
        StressRecovery([body])
