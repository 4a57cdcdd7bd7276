"""Element kernels of the linear elements (tri3, quad4): the NumPy stiffness and mass, all
elements at once, against scikit-fem's generic form assembly and a hand-computed triangle."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from skfem import MeshQuad, MeshTri, MeshTri2

import stepcontact as sc
from stepcontact.fem import continuum
from stepcontact.fem.mass import _mass_generic, continuum_mass
from stepcontact.model.bodies import Body, Material

#: the kernels and scikit-fem use the same quadrature points: only round-off separates them
#: (measured 2e-16 to 4e-16 relative in the max norm)
RTOL = 1e-12

MATERIALS = [Material(E=30e9, nu=0.2, density=2400.0), Material(E=210e9, nu=0.3, density=7850.0),
             Material(E=5e6, nu=0.45, density=1200.0)]


def _distorted(kind: str, material: Material, seed: int = 0) -> Body:
    """A 6 × 4 mesh of [0, 2] × [0, 1] with its inner nodes moved randomly by up to about a
    fifth of a cell: general quadrilaterals (not parallelograms), triangles of every shape."""
    mesh_cls = MeshTri if kind == "tri3" else MeshQuad
    m = mesh_cls.init_tensor(np.linspace(0.0, 2.0, 7), np.linspace(0.0, 1.0, 5))
    p = m.p.copy()
    inner = (p[0] > 0) & (p[0] < 2) & (p[1] > 0) & (p[1] < 1)
    p[:, inner] += 0.05 * np.random.default_rng(seed).standard_normal((2, int(inner.sum())))
    return Body.from_mesh("b", mesh_cls(p, m.t), kind, material)


def _rel(a: sp.spmatrix, b: sp.spmatrix) -> float:
    return float(abs(a - b).max() / abs(b).max())


@pytest.mark.parametrize("kind", ["tri3", "quad4"])
@pytest.mark.parametrize("plane", ["strain", "stress"])
@pytest.mark.parametrize("material", MATERIALS, ids=["concrete", "steel", "rubbery"])
def test_kernel_stiffness_equals_scikit_fem_assembly(kind, plane, material):
    """K of the element kernel equals scikit-fem's BilinearForm assembly of
    ∫ t (2μ ε:ε + λ tr ε tr ε) dA to 1e-12 relative (max norm) on a distorted mesh; the
    element means of the gradients it leaves for the stress operator equal the basis's."""
    body = _distorted(kind, material)
    assert continuum.linear_kernel(body) is not None
    K = continuum.stiffness(body, plane, 0.7)
    kernel_means = continuum._MEAN_GRADIENTS.pop(body)
    lam, mu = continuum.plane_lame(material.E, material.nu, plane)
    ref = continuum._stiffness_generic(body, lam, mu, 0.7)
    basis_means = continuum._MEAN_GRADIENTS[body]
    assert K.shape == ref.shape == (2 * body.n_nodes, 2 * body.n_nodes)
    assert _rel(K, ref) <= RTOL
    Gk, Gb = kernel_means[2], basis_means[2]
    assert np.abs(Gk - Gb).max() <= RTOL * np.abs(Gb).max()
    assert np.array_equal(kernel_means[3], basis_means[3]) and kernel_means[4] == basis_means[4]


@pytest.mark.parametrize("kind", ["tri3", "quad4"])
@pytest.mark.parametrize("lumped", [False, True], ids=["consistent", "HRZ"])
def test_kernel_mass_equals_scikit_fem_assembly(kind, lumped):
    """The consistent and the HRZ-lumped mass of the kernel equal scikit-fem's assembly to
    1e-12 relative; the total mass of each translation is ρ t × area (2 × 1 m²) to 1e-12."""
    material = MATERIALS[0]
    body = _distorted(kind, material, seed=1)
    M = continuum_mass(body, 0.7, lumped)
    assert _rel(M, _mass_generic(body, 0.7, lumped)) <= RTOL
    ux = np.zeros(2 * body.n_nodes)
    ux[0::2] = 1.0
    assert ux @ M @ ux == pytest.approx(material.density * 0.7 * 2.0, rel=1e-12)


def test_kernel_stiffness_of_one_triangle_by_hand():
    """The constant-strain triangle (0,0), (1,0), (0,1) in plane stress against the textbook
    K = t A Bᵀ D B (B from b_i = y_j − y_k, c_i = x_k − x_j over 2A; D of plane stress),
    to 1e-12 relative."""
    E, nu, t = 1e9, 0.25, 0.3
    xy = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    body = Body.from_mesh("t", MeshTri(xy.T, np.array([[0], [1], [2]])), "tri3",
                          Material(E=E, nu=nu, density=1000.0))
    xy = body.points[body.cells[0]]
    x, y = xy[:, 0], xy[:, 1]
    A2 = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0])
    b = np.array([y[1] - y[2], y[2] - y[0], y[0] - y[1]]) / A2
    c = np.array([x[2] - x[1], x[0] - x[2], x[1] - x[0]]) / A2
    B = np.zeros((3, 6))
    B[0, 0::2], B[1, 1::2], B[2, 0::2], B[2, 1::2] = b, c, c, b
    D = E / (1 - nu**2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
    ref = t * abs(A2) / 2 * B.T @ D @ B
    dofs = continuum.vector_dofs(body.cells)[0]
    K = continuum.stiffness(body, "stress", t).toarray()[np.ix_(dofs, dofs)]
    assert np.abs(K - ref).max() <= 1e-12 * np.abs(ref).max()


def test_quadratic_elements_and_curved_geometry_keep_the_generic_assembly():
    """tri6 and a tri3 body on a curved (quadratic) mesh have no kernel: scikit-fem assembles
    them (and its matrices are symmetric with the rigid motions in their null space: K u = 0
    for a translation to 1e-9 of ‖K‖ ‖u‖)."""
    tri6 = sc.rectangle("q", (0, 0), (1, 1), 2, 2, MATERIALS[0], element="tri6")
    curved = Body.from_mesh("c", MeshTri2.init_circle(1), "tri3", MATERIALS[0])
    for body in (tri6, curved):
        assert continuum.linear_kernel(body) is None
        K = continuum.stiffness(body, "strain", 1.0)
        u = np.tile([1.0, 0.0], body.n_nodes)
        assert np.abs(K @ u).max() <= 1e-9 * abs(K).max() * np.abs(u).max()


def test_model_stiffness_and_mass_equal_the_generic_assembly(monkeypatch):
    """The assembled K and M of a model with a tri3 and a quad4 body of different materials
    equal those of scikit-fem's assembly (kernels switched off) to 1e-12 relative."""
    from stepcontact.fem import assembly, mass

    base = sc.rectangle("base", (0, 0), (2, 1), 6, 3, MATERIALS[0], element="quad4")
    blk = sc.rectangle("blk", (0.5, 1), (1.5, 1.5), 4, 2, MATERIALS[1], element="tri3")
    m = sc.Model(bodies=[base, blk], plane="stress", thickness=0.4)
    m = m.add(sc.Support("bed", m.select("base", y=0), "xy"),
              sc.Interface("j", plus=m.select("blk", y=1), minus=m.select("base", y=1),
                           friction=0.5),
              sc.LoadPattern("w", [sc.BodyForce()]), sc.Segment("w", 1.0))
    system = assembly.assemble(m)
    M = mass.mass(m, system.dofs)
    monkeypatch.setattr(continuum, "linear_kernel", lambda body: None)
    monkeypatch.setattr(mass, "linear_kernel", lambda body: None)
    ref = assembly.assemble(m)
    assert _rel(system.K, ref.K) <= RTOL
    assert _rel(M, mass.mass(m, ref.dofs)) <= RTOL


@pytest.mark.parametrize("kind", ["tet4", "hex8"])
def test_kernels_are_ready_for_3d_solids(kind):
    """The same kernels on tetrahedra and hexahedra (for 3D continua) equal scikit-fem's
    assembly of ∫ (2μ ε:ε + λ tr ε tr ε) dV and of ∫ ρ φ_i φ_j dV to 1e-12 relative, on a
    2 × 2 × 2 box with its inner node moved off the centre (general hexahedra)."""
    from skfem import (
        Basis,
        BilinearForm,
        ElementHex1,
        ElementTetP1,
        ElementVector,
        MeshHex,
        MeshTet,
        asm,
    )
    from skfem.helpers import ddot, sym_grad, trace

    mesh_cls, elem = (MeshTet, ElementTetP1()) if kind == "tet4" else (MeshHex, ElementHex1())
    m = mesh_cls.init_tensor(*([np.linspace(0.0, 1.0, 3)] * 3))
    p = m.p.copy()
    p[:, np.argmin(np.linalg.norm(p - 0.5, axis=0))] += [0.07, -0.05, 0.04]
    m = mesh_cls(p, m.t)
    lam, mu, rho = 1.2e10, 0.8e10, 2400.0

    @BilinearForm
    def elastic(u, v, w):
        eu, ev = sym_grad(u), sym_grad(v)
        return 2 * mu * ddot(eu, ev) + lam * trace(eu) * trace(ev)

    @BilinearForm
    def mass(u, v, w):
        return rho * u * v

    ref_K = asm(elastic, Basis(m, ElementVector(elem, dim=3)))
    ref_M = asm(mass, Basis(m, elem))
    grad, phi, dx = continuum.isoparametric_data(m.p.T, m.t.T, elem)
    dofs = continuum.vector_dofs(m.t.T, 3)
    Ke = continuum.element_stiffness(grad, dx, lam, mu)
    n = 3 * m.p.shape[1]
    K = sp.coo_matrix((Ke.ravel(), (np.repeat(dofs, dofs.shape[1], axis=1).ravel(),
                                    np.tile(dofs, dofs.shape[1]).ravel())), shape=(n, n))
    Me = rho * np.einsum("eq,qi,qj->eij", dx, phi, phi)
    cells = m.t.T
    M = sp.coo_matrix((Me.ravel(), (np.repeat(cells, cells.shape[1], axis=1).ravel(),
                                    np.tile(cells, cells.shape[1]).ravel())),
                      shape=(m.p.shape[1],) * 2)
    assert _rel(K.tocsr(), ref_K) <= RTOL
    assert _rel(M.tocsr(), ref_M) <= RTOL
