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


def _solid(kind: str, shape: str, material: Material = MATERIALS[0]) -> Body:
    """A 4 × 3 × 2 tet4 or hex8 mesh of [0, 2] × [0, 1.5] × [−1, 0]: ``"box"`` as meshed
    (rectangular cells), ``"sheared"`` mapped by a general affine map (parallelepipeds, still
    affine), ``"distorted"`` with its inner nodes moved randomly by about a tenth of a cell
    (general trilinear hexahedra)."""
    from skfem import MeshHex, MeshTet

    mesh_cls = MeshTet if kind == "tet4" else MeshHex
    m = mesh_cls.init_tensor(np.linspace(0, 2, 5), np.linspace(0, 1.5, 4), np.linspace(-1, 0, 3))
    p = m.p.copy()
    if shape == "sheared":
        p = np.array([[1.0, 0.3, -0.2], [0.1, 0.9, 0.25], [0.05, -0.15, 1.1]]) @ p + 7.0
    elif shape == "distorted":
        inner = np.all((p > p.min(1, keepdims=True)) & (p < p.max(1, keepdims=True)), axis=0)
        p[:, inner] += 0.05 * np.random.default_rng(2).standard_normal((3, int(inner.sum())))
    return Body.from_mesh("s", mesh_cls(p, m.t), kind, material)


@pytest.mark.parametrize("kind", ["tet4", "hex8"])
@pytest.mark.parametrize("shape", ["box", "sheared", "distorted"])
@pytest.mark.parametrize("material", MATERIALS[:2], ids=["concrete", "steel"])
def test_solid_kernel_equals_scikit_fem_assembly(kind, shape, material):
    """The 3D kernel (affine cells by the reference integrals, the others at scikit-fem's 64
    points) gives K = ∫ (2μ ε:ε + λ tr ε tr ε) dV, the element means of the gradients (stress
    operator) and the self-weight ρ g ∫ φ_i dV of scikit-fem's generic assembly to 1e-12
    relative (max norm; measured below 1e-15); the affine cells are found: all tetrahedra,
    every box and sheared hexahedron, no hexahedron with a moved inner node."""
    body = _solid(kind, shape, material)
    affine, _ = continuum.affine_elements(body.points, body.cells,
                                          continuum.scalar_element(kind))
    if kind == "tet4" or shape != "distorted":
        assert affine.all()
    else:  # each of these hexahedra has a moved inner node
        assert not affine.any()
    assert continuum.solid_kernel(body)
    K = continuum.stiffness(body, "strain", 1.0)
    kernel_means = continuum._MEAN_GRADIENTS.pop(body)
    f = continuum.body_force(body, [0.3, -0.5, -9.81], 1.0)
    lam, mu = continuum.plane_lame(material.E, material.nu, "strain")
    ref = continuum._stiffness_generic(body, lam, mu, 1.0)
    basis_means = continuum._MEAN_GRADIENTS[body]
    assert K.shape == ref.shape == (3 * body.n_nodes, 3 * body.n_nodes)
    assert _rel(K, ref) <= RTOL
    Gk, Gb = kernel_means[2], basis_means[2]
    assert np.abs(Gk - Gb).max() <= RTOL * np.abs(Gb).max()
    assert np.array_equal(kernel_means[3], basis_means[3]) and kernel_means[4] == basis_means[4]
    from skfem import LinearForm, asm

    g = np.array([0.3, -0.5, -9.81])

    @LinearForm
    def weight(v, w):
        return material.density * (g[0] * v[0] + g[1] * v[1] + g[2] * v[2])

    f_ref = asm(weight, continuum.basis_of(body))
    assert np.abs(f - f_ref).max() <= RTOL * np.abs(f_ref).max()


def test_solid_kernel_in_blocks_equals_one_block(monkeypatch):
    """Blocks of 7 elements (mixed affine and general hexahedra) give the stiffness of one
    block to 1e-15 relative: blocking only splits the same element computations."""
    body = _solid("hex8", "distorted")
    p = body.points.copy()
    p[:, 0] *= 1.3  # keeps the affine cells affine (a scaling), the others general
    body = Body.from_mesh("s", type(body.mesh)(p.T, body.mesh.t), "hex8", MATERIALS[0])
    whole = continuum.solid_stiffness(body, 1e9, 2e9)
    monkeypatch.setattr(continuum, "_BLOCK", 7)
    assert np.abs(continuum.solid_stiffness(body, 1e9, 2e9) - whole).max() <= (
        1e-15 * np.abs(whole).max())


def test_model_3d_stiffness_and_loads_equal_the_generic_assembly(monkeypatch):
    """A 3D model of two boxes (hex8 on tet4, different materials, node-to-node joint,
    self-weight) assembles K and the self-weight vector equal to those of scikit-fem's
    generic assembly (kernel switched off) to 1e-12 relative."""
    from stepcontact.fem import assembly

    base = sc.box("base", (0, 0, -1), (2, 2, 0), (4, 4, 2), MATERIALS[0], element="tet4")
    blk = sc.box("blk", (0.5, 0.5, 0), (1.5, 1.5, 0.5), (2, 2, 1), MATERIALS[1])
    m = sc.Model(bodies=[base, blk])
    m = m.add(sc.Support("bed", m.select("base", boundary="bottom"), "xyz"),
              sc.Interface("j", plus=m.select("blk", boundary="bottom"),
                           minus=m.select("base", lambda x, y, z: (np.abs(z) < 1e-9)
                                          & (x > 0.49) & (x < 1.51) & (y > 0.49) & (y < 1.51)),
                           friction=0.5),
              sc.LoadPattern("w", [sc.BodyForce()]), sc.Segment("w", 1.0))
    system = assembly.assemble(m)
    monkeypatch.setattr(continuum, "solid_kernel", lambda body: False)
    ref = assembly.assemble(m)
    assert _rel(system.K, ref.K) <= RTOL
    f, f_ref = system.loads["w"].f, ref.loads["w"].f
    assert np.abs(f - f_ref).max() <= RTOL * np.abs(f_ref).max()


@pytest.mark.parametrize("kind", ["tet10", "hex27"])
def test_quadratic_solids_keep_the_generic_assembly(kind):
    """tet10 and hex27 bodies have no 3D kernel: scikit-fem assembles them (symmetric, a rigid
    translation in the null space: K u = 0 to 1e-9 of ‖K‖ ‖u‖)."""
    body = sc.box("q", (0, 0, 0), (1, 1, 1), (1, 1, 1), MATERIALS[0], element=kind)
    assert not continuum.solid_kernel(body)
    K = continuum.stiffness(body, "strain", 1.0)
    assert abs(K - K.T).max() <= 1e-12 * abs(K).max()
    u = np.tile([0.0, 0.0, 1.0], body.n_nodes)
    assert np.abs(K @ u).max() <= 1e-9 * abs(K).max()


@pytest.mark.parametrize("kind", ["tri3", "tri6", "quad4", "quad9", "tet4", "tet10", "hex8",
                                  "hex20", "hex27"])
def test_body_arrays_equal_those_of_the_full_basis(kind):
    """A body's node coordinates and element connectivity (read from a basis with one
    quadrature point) equal, exactly, those of scikit-fem's basis with its full rule."""
    from skfem import Basis, MeshHex, MeshQuad, MeshTet, MeshTri

    from stepcontact.model.elements import body_arrays, scalar_element

    axes = [np.linspace(0.0, 1.0, 3), np.linspace(0.0, 2.0, 4)]
    mesh = {"tri": MeshTri, "qua": MeshQuad, "tet": MeshTet, "hex": MeshHex}[kind[:3]]
    mesh = mesh.init_tensor(*(axes + [np.linspace(-1.0, 0.0, 3)] if kind[:3] in ("tet", "hex")
                              else axes))
    points, cells, _, _ = body_arrays("b", mesh, kind)
    full = Basis(mesh, scalar_element(kind))
    assert np.array_equal(points, full.doflocs.T)
    assert np.array_equal(cells, full.element_dofs.T)
