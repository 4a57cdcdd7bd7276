"""scikit-fem glue: bases, element stiffness, edge and body loads, stresses of continuum bodies.

Private: users go through :mod:`stepcontact.model` and :mod:`stepcontact.fem.assembly`.
Everything is vectorised over the elements; nothing here loops over elements.  The stiffness
and mass of the linear elements on straight-sided meshes (tri3, quad4: :func:`linear_kernel`)
are NumPy element kernels, all elements at once, with scikit-fem's own quadrature rule; the
stiffness, self-weight and mean gradients (stress operator) of tet4 and hex8 bodies likewise
(:func:`solid_stiffness`: affine cells from reference integrals, the others at scikit-fem's
points, in blocks of elements); the other elements go through scikit-fem's generic form
assembly (:func:`_stiffness_generic`), which gives the same matrices to round-off but spends
most of its time evaluating the form per pair of basis functions (about 3.7 ms per hex8).
"""

from __future__ import annotations

import weakref

import numpy as np
from scipy import sparse
from skfem import (
    Basis,
    BilinearForm,
    ElementVector,
    FacetBasis,
    LinearForm,
    asm,
)
from skfem.helpers import ddot, dot, sym_grad, trace
from skfem.mesh.mesh_2d_2 import Mesh2D2
from skfem.quadrature import get_quadrature

from stepcontact.model.elements import scalar_element


def basis_of(body, vector: bool = True) -> Basis:
    """scikit-fem basis of a body (vector-valued by default: DOF d·i+c is node i, component c,
    d = 2 or 3 the body's dimension)."""
    e = scalar_element(body.element)
    return Basis(body.mesh, ElementVector(e) if vector else e)


def plane_lame(E: float, nu: float, plane: str) -> tuple[float, float]:
    """Lamé parameters (λ, μ) in Pa for plane strain (and 3D), or the plane-stress
    equivalents: λ = E ν / ((1 + ν)(1 − 2ν)), μ = E / (2 (1 + ν))."""
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    if plane == "stress":
        lam = 2 * lam * mu / (lam + 2 * mu)
    return lam, mu


def _plane_and_thickness(body, plane: str, thickness: float) -> tuple[str, float]:
    """The plane kind and thickness a body's forms use: as given in 2D; in 3D the full 3D
    Lamé parameters (those of plane strain) and no thickness (the volume is integrated)."""
    return (plane, thickness) if body.dim == 2 else ("strain", 1.0)


def stiffness(body, plane: str, thickness: float) -> sparse.csr_matrix:
    """Stiffness matrix (CSR, body-local vector DOFs) of a continuum body, N/m.

    K = ∫ (2μ ε(u):ε(v) + λ tr ε(u) tr ε(v)) t dA in 2D (thickness t) and ∫ … dV in 3D
    (isotropic Hooke's law, the form of ``skfem.models.elasticity.linear_elasticity``)."""
    r, c, v = stiffness_triplets(body, plane, thickness)
    n = body.dim * body.n_nodes
    return sparse.coo_matrix((v.ravel(), (r.ravel(), c.ravel())), shape=(n, n)).tocsr()


def stiffness_triplets(body, plane: str, thickness: float):
    """COO triplets (rows, cols, values; body-local vector DOFs d·i + c) of the stiffness of
    a continuum body, N/m, duplicates not yet summed: the element matrices of
    :func:`element_stiffness` for tri3 and quad4 on straight-sided meshes, of
    :func:`solid_stiffness` for tet4 and hex8 on linear geometries, else scikit-fem's
    generic assembly (:func:`_stiffness_generic`: quadratic elements, curved geometries)."""
    plane, thickness = _plane_and_thickness(body, plane, thickness)
    lam, mu = plane_lame(body.material.E, body.material.nu, plane)
    if solid_kernel(body):
        Ke = solid_stiffness(body, lam, mu)
        dofs = vector_dofs(body.cells, 3)
        nd = dofs.shape[1]
        return (np.broadcast_to(dofs[:, :, None], (len(dofs), nd, nd)),
                np.broadcast_to(dofs[:, None, :], (len(dofs), nd, nd)), Ke)
    data = linear_kernel(body)
    if data is None:
        K = _stiffness_generic(body, lam, mu, thickness).tocoo()
        return K.row, K.col, K.data
    grad, _, dx = data
    _cache_mean_gradients(body, grad, dx)
    Ke = element_stiffness(grad, dx, lam, mu, thickness)
    dofs = vector_dofs(body.cells)
    nd = dofs.shape[1]
    return (np.broadcast_to(dofs[:, :, None], (len(dofs), nd, nd)),
            np.broadcast_to(dofs[:, None, :], (len(dofs), nd, nd)), Ke)


def _stiffness_generic(body, lam: float, mu: float, thickness: float) -> sparse.csr_matrix:
    """scikit-fem's form assembly of ∫ t (2μ ε(u):ε(v) + λ tr ε(u) tr ε(v)) dA, N/m (any
    element; the reference of :func:`element_stiffness`)."""

    @BilinearForm
    def form(u, v, w):
        eu, ev = sym_grad(u), sym_grad(v)
        return thickness * (2 * mu * ddot(eu, ev) + lam * trace(eu) * trace(ev))

    basis = basis_of(body)
    _mean_gradients(body, basis)  # kept for the stress operator: no second basis later
    return asm(form, basis).tocsr()


def linear_kernel(body):
    """Basis-function data (:func:`isoparametric_data`) of a tri3 or quad4 body on a
    straight-sided mesh, for the element kernels; None for another element or a curved
    (quadratic) geometry."""
    if body.element not in ("tri3", "quad4") or isinstance(body.mesh, Mesh2D2):
        return None
    return isoparametric_data(body.points, body.cells, scalar_element(body.element))


def isoparametric_data(points: np.ndarray, cells: np.ndarray, elem):
    """Gradients, values and quadrature weights of the scalar basis functions of a mesh whose
    geometry is interpolated by the element itself (tri3, quad4; tet4, hex8 in 3D), all
    elements at once.

    With scikit-fem's quadrature (X_q, W_q) of order 2·maxdeg on the reference element (what
    its :class:`~skfem.Basis` uses: 3 points on a triangle, 3 × 3 on a quadrilateral) and the
    reference functions φ̂_i with gradients ∇̂φ̂_i, the map of element e gives

        J_eq = Σ_i x_ei ⊗ ∇̂φ̂_i(X_q),   ∇φ_i(x_eq) = J_eq⁻ᵀ ∇̂φ̂_i(X_q),   dx_eq = |det J_eq| W_q

    (simplices: J constant, the affine map).  ``points`` (n, d) in m, ``cells`` (nel, nb) the
    element's local node order, ``elem`` the scalar scikit-fem element.  Returns ``grad``
    (nel, nq, nb, d) in 1/m, ``phi`` (nq, nb) and ``dx`` (nel, nq) in m^d."""
    X, W = get_quadrature(elem.refdom, 2 * elem.maxdeg)
    cells = np.asarray(cells)
    nb = cells.shape[1]
    ref = [elem.lbasis(X, i) for i in range(nb)]
    phi = np.stack([np.broadcast_to(v, X.shape[1:]) for v, _ in ref], axis=1)  # (nq, nb)
    dref = np.stack([np.broadcast_to(g, X.shape) for _, g in ref], axis=0)  # (nb, d, nq)
    xe = np.asarray(points, dtype=float)[cells]  # (nel, nb, d)
    J = np.einsum("eia,ibq->eqab", xe, dref)  # ∂x_a/∂X_b
    if J.shape[-1] == 2:  # closed form: half the time of a batched inverse
        det = J[..., 0, 0] * J[..., 1, 1] - J[..., 0, 1] * J[..., 1, 0]
        inv_t = np.empty_like(J)  # J⁻ᵀ
        inv_t[..., 0, 0] = J[..., 1, 1] / det
        inv_t[..., 0, 1] = -J[..., 1, 0] / det
        inv_t[..., 1, 0] = -J[..., 0, 1] / det
        inv_t[..., 1, 1] = J[..., 0, 0] / det
    else:
        det = np.linalg.det(J)
        inv_t = np.linalg.inv(J).swapaxes(-1, -2)
    grad = np.einsum("eqab,ibq->eqia", inv_t, dref)
    return grad, phi, np.abs(det) * W


def element_stiffness(grad: np.ndarray, dx: np.ndarray, lam: float, mu: float,
                      thickness: float = 1.0) -> np.ndarray:
    """Element stiffness matrices (nel, d·nb, d·nb) of linear elasticity, all elements at
    once: with local DOF d·i + a (node i, component a),

        K_e[d·i+a, d·j+b] = t Σ_q dx_q (λ ∂_aφ_i ∂_bφ_j + μ ∂_bφ_i ∂_aφ_j + μ δ_ab ∇φ_i·∇φ_j)

    the matrix of ∫ t (2μ ε(u):ε(v) + λ tr ε(u) tr ε(v)) dA in the plane (λ, μ:
    :func:`plane_lame`, Pa; t the thickness, m: N/m), of ∫ (…) dV in 3D (t = 1: N/m);
    ``grad``, ``dx`` of :func:`isoparametric_data`."""
    nel, nq, nb, d = grad.shape
    Gf = grad.reshape(nel, nq, d * nb)  # column d·i + a: ∂_aφ_i
    T = np.matmul((Gf * dx[:, :, None]).transpose(0, 2, 1), Gf)  # Σ_q dx ∂_aφ_i ∂_bφ_j
    return thickness * _hooke(T.reshape(nel, nb, d, nb, d), lam, mu)


def _hooke(T: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """Element matrices (nel, d·nb, d·nb) of isotropic elasticity from the integrals
    T[e, i, a, j, b] = ∫ ∂_aφ_i ∂_bφ_j (nel, nb, d, nb, d): λ T + μ Tᵀ⁽ᵃᵇ⁾ + μ δ_ab Σ_c T_cc
    (:func:`element_stiffness`)."""
    nel, nb, d = T.shape[:3]
    dot_ij = sum(T[:, :, a, :, a] for a in range(d))  # Σ_q dx ∇φ_i·∇φ_j
    K = lam * T + mu * T.transpose(0, 1, 4, 3, 2)
    for a in range(d):
        K[:, :, a, :, a] += mu * dot_ij
    return K.reshape(nel, d * nb, d * nb)


#: the 3D elements of the NumPy kernels (:func:`solid_stiffness`), on scikit-fem's linear
#: MeshTet and MeshHex (not on the quadratic geometries MeshTet2, MeshHex2)
SOLID_KERNELS = ("tet4", "hex8")
#: elements per block of the 3D kernels: bounds their work arrays (about 40 MB per block of
#: affine hexahedra, 230 MB of general ones with scikit-fem's 64 points)
_BLOCK = 4096


def solid_kernel(body) -> bool:
    """Whether the 3D kernels take the body: a tet4 or hex8 body on a linear geometry."""
    return body.element in SOLID_KERNELS and not type(body.mesh).__name__.endswith("2")


def _reference(elem):
    """scikit-fem's quadrature of ``elem`` (order 2·maxdeg, as its Basis) and the reference
    functions there: X (d, nq), W (nq,), φ̂ (nq, nb), ∇̂φ̂ (nb, d, nq)."""
    X, W = get_quadrature(elem.refdom, 2 * elem.maxdeg)
    ref = [elem.lbasis(X, i) for i in range(elem.doflocs.shape[0])]
    phi = np.stack([np.broadcast_to(v, X.shape[1:]) for v, _ in ref], axis=1)
    dref = np.stack([np.broadcast_to(g, X.shape) for _, g in ref], axis=0)
    return X, W, phi, dref


def affine_elements(points: np.ndarray, cells: np.ndarray, elem) -> tuple[np.ndarray,
                                                                          np.ndarray]:
    """Which elements map the reference element affinely, and their Jacobians there.

    The map x(X) = Σ_i x_i φ̂_i(X) of a tetrahedron is affine; that of a hexahedron
    (trilinear) is where its coefficients of XY, YZ, XZ and XYZ (from the nodes by the
    inverse Vandermonde matrix of the reference nodes) vanish to round-off of the coordinates
    (≤ 64 ε max |x_i| per element, m): parallelepipeds, every cell of box() and of an
    extruded quadrilateral mesh of parallelograms.  Returns ``affine`` (nel,) bool and
    J (nel, d, d) = ∂x_a/∂X_b at the reference centroid, the constant Jacobian of the affine
    elements.  ``points`` (n, d) m, ``cells`` (nel, nb) in the element's local node order."""
    xe = np.asarray(points, dtype=float)[np.asarray(cells)]  # (nel, nb, d)
    loc = np.asarray(elem.doflocs, dtype=float)  # (nb, d) reference nodes
    c = loc.mean(axis=0)[:, None]
    dref = np.stack([np.broadcast_to(elem.lbasis(c, i)[1], c.shape)[:, 0]
                     for i in range(len(loc))])  # (nb, d)
    J = np.einsum("eia,ib->eab", xe, dref)
    if len(loc) == loc.shape[1] + 1:  # a simplex: affine
        return np.ones(len(xe), dtype=bool), J
    X, Y, Z = loc.T
    V = np.column_stack([np.ones(len(loc)), X, Y, Z, X * Y, Y * Z, X * Z, X * Y * Z])
    coef = np.einsum("ki,eia->eka", np.linalg.inv(V)[4:], xe)  # the non-affine terms
    size = np.abs(xe).max(axis=(1, 2))
    return np.abs(coef).max(axis=(1, 2)) <= 64 * np.finfo(float).eps * size, J


def _blocks(idx: np.ndarray):
    """``idx`` in blocks of at most :data:`_BLOCK` elements."""
    for k in range(0, len(idx), _BLOCK):
        yield idx[k:k + _BLOCK]


def solid_stiffness(body, lam: float, mu: float) -> np.ndarray:
    """Element stiffness matrices (nel, 3·nb, 3·nb), N/m, of a tet4 or hex8 body
    (:func:`solid_kernel`), all elements in blocks of :data:`_BLOCK`; the matrix of
    ∫ (2μ ε(u):ε(v) + λ tr ε(u) tr ε(v)) dV of :func:`element_stiffness`, with local DOF
    3·i + a.  Also caches the element means of the gradients for the stress operator.

    Affine elements (:func:`affine_elements`: every tetrahedron, parallelepipeds) have a
    constant Jacobian J, so with A = J⁻ᵀ (∇φ_i = A ∇̂φ̂_i) and the reference integrals
    R[i, k, j, l] = Σ_q W_q ∂̂_kφ̂_i ∂̂_lφ̂_j (scikit-fem's rule: exact for these
    polynomials)

        ∫ ∂_aφ_i ∂_bφ_j dV = |det J| Σ_kl A_ak A_bl R[i, k, j, l],

    about 15 kflop per element instead of a sum over the 64 quadrature points of a hexahedron;
    the others are integrated at scikit-fem's points (:func:`isoparametric_data`).  Equal to
    scikit-fem's form assembly to round-off (tests/test_element_kernels.py, 1e-12)."""
    elem = scalar_element(body.element)
    _, W, _, dref = _reference(elem)
    cells = np.asarray(body.cells)
    points = np.asarray(body.points, dtype=float)
    nel, nb = cells.shape
    affine, J = affine_elements(points, cells, elem)
    Ke = np.empty((nel, 3 * nb, 3 * nb))
    Gs = np.empty((nb, 3, nel))  # element means of ∇φ_j, 1/m (see _mean_gradients)
    R = np.einsum("ikq,jlq,q->kijl", dref, dref, W).reshape(3, -1)
    gbar = dref @ W / W.sum()  # (nb, 3): reference means of ∇̂φ̂_j
    for blk in _blocks(np.flatnonzero(affine)):
        Jb = J[blk]
        A = np.linalg.inv(Jb).transpose(0, 2, 1)  # J⁻ᵀ
        Y = (A.reshape(-1, 3) @ R).reshape(len(blk), 3, nb * nb, 3)  # Σ_k A_ak R[i,k,j,l]
        T = np.einsum("eanl,ebl->enab", Y, A).reshape(len(blk), nb, nb, 3, 3)
        T *= np.abs(np.linalg.det(Jb))[:, None, None, None, None]
        Ke[blk] = _hooke(T.transpose(0, 1, 3, 2, 4), lam, mu)
        Gs[:, :, blk] = np.einsum("eak,jk->jae", A, gbar)
    for blk in _blocks(np.flatnonzero(~affine)):
        grad, _, dx = isoparametric_data(points, cells[blk], elem)
        Ke[blk] = element_stiffness(grad, dx, lam, mu)
        Gs[:, :, blk] = np.einsum("eqjd,eq->jde", grad, dx / dx.sum(axis=1, keepdims=True))
    out = (Gs, np.ascontiguousarray(vector_dofs(cells, 3).T), 3 * body.n_nodes)
    _MEAN_GRADIENTS[body] = (body.mesh, body.element, *out)
    return Ke


def solid_shape_integrals(body) -> np.ndarray:
    """∫ φ_i dV (nel, nb), m³, of every element of a tet4 or hex8 body (:func:`solid_kernel`):
    |det J| Σ_q W_q φ̂_i(X_q) on the affine elements, scikit-fem's points on the others."""
    elem = scalar_element(body.element)
    _, W, phi, _ = _reference(elem)
    cells = np.asarray(body.cells)
    affine, J = affine_elements(body.points, cells, elem)
    out = np.empty(cells.shape)
    out[affine] = np.abs(np.linalg.det(J[affine]))[:, None] * (W @ phi)[None, :]
    for blk in _blocks(np.flatnonzero(~affine)):
        _, _, dx = isoparametric_data(body.points, cells[blk], elem)
        out[blk] = dx @ phi
    return out


def vector_dofs(cells: np.ndarray, dim: int = 2) -> np.ndarray:
    """Local vector DOFs (nel, dim·nb) of the elements: dim·node + component."""
    cells = np.asarray(cells)
    return (dim * cells[:, :, None] + np.arange(dim)).reshape(len(cells), -1)


def _cache_mean_gradients(body, grad: np.ndarray, dx: np.ndarray) -> None:
    """Fill :func:`_mean_gradients`'s cache from the kernel's data (no basis for the stress
    operator): Ḡ_j = Σ_q ∇φ_j dx_q / Σ_q dx_q."""
    w = dx / dx.sum(axis=1, keepdims=True)
    Gs = np.einsum("eqjd,eq->jde", grad, w)
    out = (Gs, np.ascontiguousarray(vector_dofs(body.cells).T), 2 * body.n_nodes)
    _MEAN_GRADIENTS[body] = (body.mesh, body.element, *out)


def body_force(body, g, thickness: float) -> np.ndarray:
    """Consistent nodal forces of the self-weight ρ g (body-local vector DOFs), N:
    f_i = ∫ ρ g · φ_i t dA (2D) or ∫ ρ g · φ_i dV (3D); ``g`` has the body's dimension."""
    _, thickness = _plane_and_thickness(body, "strain", thickness)
    rho = body.material.density
    gv = np.asarray(g, dtype=float)
    if gv.shape != (body.dim,):
        raise ValueError(f"body '{body.name}': g {tuple(gv)} for a {body.dim}D body")

    if solid_kernel(body):  # ρ g_c ∫ φ_i dV on DOF 3i + c, all elements at once
        nodal = np.bincount(np.asarray(body.cells).ravel(), solid_shape_integrals(body).ravel(),
                            minlength=body.n_nodes)
        return (rho * nodal[:, None] * gv[None, :]).ravel()

    @LinearForm
    def form(v, w):
        return thickness * rho * sum(gv[c] * v[c] for c in range(len(gv)))

    return asm(form, basis_of(body))


def edge_load(body, facets: np.ndarray, pn, pt, thickness: float, traction=None) -> np.ndarray:
    """Consistent nodal forces of edge tractions on the given boundary facets, N (of surface
    tractions on boundary faces for a 3D body: q = −p_n n + (q_x, q_y, q_z), no p_t, the
    functions taking (x, y, z), integrated over the faces' area).

    The traction is q = −p_n n + p_t t + (q_x, q_y) with n the outward unit normal and
    t = (n_y, −n_x) the outward normal turned clockwise (the CFE tangent convention).
    ``pn(x, y)`` is the normal pressure (Pa, positive into the body), ``pt(x, y)`` the
    tangential traction along t (Pa), ``traction`` a pair (q_x(x, y), q_y(x, y)) of global
    components (Pa).  All are callables evaluated at the quadrature points, or None.
    """
    fb = FacetBasis(body.mesh, ElementVector(scalar_element(body.element)), facets=facets)
    _, thickness = _plane_and_thickness(body, "strain", thickness)
    if body.dim == 3 and pt is not None:
        raise ValueError("a tangential traction has no direction on a face: give traction")

    @LinearForm
    def form(v, w):
        n = w.n
        xs = tuple(w.x[c] for c in range(body.dim))  # (x, y) or (x, y, z)
        trac = 0.0 * n
        if pn is not None:
            trac = trac - pn(*xs) * n
        if pt is not None:
            t = np.array([n[1], -n[0]])
            trac = trac + pt(*xs) * t
        if traction is not None:
            for c, q in enumerate(traction):
                if q is not None:
                    trac[c] = trac[c] + q(*xs)
        return thickness * dot(trac, v)

    return asm(form, fb)


def edge_length(body, facets: np.ndarray) -> float:
    """Total length of the given boundary facets, m (exact for curved quadratic edges); their
    total area, m², for a 3D body."""
    fb = FacetBasis(body.mesh, scalar_element(body.element), facets=facets)
    return float(np.sum(fb.dx))


def stresses(body, u_body: np.ndarray, plane: str) -> np.ndarray:
    """Element-averaged stresses (nel, 4): σxx, σyy, σxy, σzz in Pa; for a 3D body (nel, 6):
    σxx, σyy, σzz, σxy, σyz, σxz (:data:`STRESS_COMPONENTS_3D`).

    σzz = λ(εxx+εyy) = ν(σxx+σyy) in plane strain and 0 in plane stress.  Each value is the
    quadrature-weighted mean over the element of the stress at its quadrature points.
    ``u_body`` is the body-local displacement vector (DOF 2i+c: node i, component c), or a
    batch (n_dofs, k) giving (k, nel, 4).

    Goes through the operator of :func:`stress_operator` (built once per body, plane and
    material, then cached): use :class:`StressRecovery` to hold the operators of a model.
    """
    return _apply(stress_operator(body, plane), u_body, body.name, body.dim)


#: stress operators of live bodies: body -> {(plane, E, nu): CSR matrix}
_OPERATORS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def stress_operator(body, plane: str) -> sparse.csr_matrix:
    """Sparse matrix S (4·nel, 2·n_nodes), Pa/m, with ``(S @ u_body).reshape(nel, 4)`` the
    element-averaged stresses σxx, σyy, σxy, σzz of :func:`stresses` (cached per body)."""
    key = (plane, float(body.material.E), float(body.material.nu))
    per_body = _OPERATORS.get(body)
    if per_body is None:
        per_body = _OPERATORS[body] = {}
    if key not in per_body:
        per_body[key] = _build_stress_operator(body, plane)
    return per_body[key]


#: element means of the basis-function gradients of live bodies: body -> (mesh, element, Ḡ,
#: vector element DOFs, number of DOFs), see :func:`_mean_gradients`
_MEAN_GRADIENTS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _mean_gradients(body, basis: Basis | None = None) -> tuple[np.ndarray, np.ndarray, int]:
    """Element means of the gradients of the body's scalar basis functions, once per body.

    Returns ``Gs`` (Nbfun_scalar, dim, nel), 1/m: Gs[j, d, e] = Σ_q ∂φ_j/∂x_d(x_q) dx_q /
    Σ_q dx_q over the quadrature points of element e; the element DOFs of the vector basis
    (dim·Nbfun_scalar, nel); and its number of DOFs.  Read from ``basis`` (the body's vector
    basis of :func:`basis_of`, as assembly builds it for the stiffness) or from a new one,
    then cached while the body lives: the stress operator needs no basis of its own.  Vector
    basis function i is scalar function i // dim in component i % dim (scikit-fem's
    ElementVector), so its component-(i % dim) gradient is the scalar one.
    """
    cached = _MEAN_GRADIENTS.get(body)
    if cached is not None and cached[0] is body.mesh and cached[1] == body.element:
        return cached[2:]
    if basis is None:
        basis = basis_of(body)
    dx = basis.dx  # (nel, nqp)
    w = dx / dx.sum(axis=1, keepdims=True)
    Gs = np.stack([np.einsum("deq,eq->de", phi[0].grad[0], w)
                   for phi in basis.basis[::body.dim]])
    out = (Gs, basis.element_dofs, int(basis.N))
    _MEAN_GRADIENTS[body] = (body.mesh, body.element, *out)
    return out


def _build_stress_operator(body, plane: str) -> sparse.csr_matrix:
    """Assemble the stress operator from the gradients of the basis functions (vectorised).

    The element average of a quantity linear in the strain is the same linear map of the
    element-averaged strain, so per local basis function j the averaged displacement gradient
    Ḡ_j = Σ_q ∇φ_j(x_q) dx_q / Σ_q dx_q (2, 2, nel) is taken through Hooke's law.  The means
    come from :func:`_mean_gradients` (read off the basis assembly built); the CSR arrays are
    written directly: row 4e + k (element e, stress k) holds the element's DOFs in ascending
    order, without the entries that vanish.
    """
    if plane not in ("strain", "stress"):
        raise ValueError(f"plane={plane!r}: use 'strain' or 'stress'")
    if body.dim == 3:
        return _build_stress_operator_3d(body)
    Gs, element_dofs, ndofs = _mean_gradients(body)
    lam, mu = plane_lame(body.material.E, body.material.nu, plane)
    nb, nel = element_dofs.shape
    # per element and vector basis function i: element mean of ∂(φ_i)_c/∂x_d (c, d, nel,
    # Nbfun), non-zero only for the component c = i % 2
    G = np.zeros((2, 2, nel, nb))
    Gt = Gs.transpose(1, 2, 0)  # (2, nel, Nbfun / 2)
    G[0, :, :, 0::2] = Gt
    G[1, :, :, 1::2] = Gt
    exx, eyy = G[0, 0], G[1, 1]
    exy = 0.5 * (G[0, 1] + G[1, 0])
    tr = exx + eyy
    data = np.empty((nel, 4, nb))
    data[:, 0] = 2 * mu * exx + lam * tr  # σxx
    data[:, 1] = 2 * mu * eyy + lam * tr  # σyy
    data[:, 2] = 2 * mu * exy  # σxy
    data[:, 3] = body.material.nu * (data[:, 0] + data[:, 1]) if plane == "strain" else 0.0
    # CSR arrays directly: row 4e + k (element e, stress k) holds data[e, k] in the columns of
    # the element's DOFs (distinct: no duplicates to sum)
    return _stress_csr(data, element_dofs, ndofs)


def _stress_csr(data: np.ndarray, element_dofs: np.ndarray, ndofs: int) -> sparse.csr_matrix:
    """The stress operator's CSR matrix from ``data`` (nel, k, nb): row k·e + j (element e,
    stress j) holds data[e, j] in the columns of the element's DOFs (distinct: no duplicates
    to sum)."""
    nel, k, nb = data.shape
    idx = np.int32 if max(ndofs, data.size) <= np.iinfo(np.int32).max else np.int64
    indices = np.broadcast_to(element_dofs.T[:, None, :], data.shape).astype(idx).ravel()
    indptr = np.arange(0, data.size + 1, nb, dtype=idx)
    S = sparse.csr_matrix((data.ravel(), indices, indptr), shape=(k * nel, ndofs))
    S.eliminate_zeros()
    S.sort_indices()
    return S


#: the stress components of a 3D body, in the order of :func:`stresses` (ParaView's order of
#: a symmetric tensor)
STRESS_COMPONENTS_3D = ("xx", "yy", "zz", "xy", "yz", "xz")


def _build_stress_operator_3d(body) -> sparse.csr_matrix:
    """The stress operator of a 3D body: rows 6e + j the element means of σ_j, j in
    :data:`STRESS_COMPONENTS_3D`, by Hooke's law σ = 2μ ε + λ tr(ε) I from the element-mean
    gradients of the basis functions (as in 2D, :func:`_build_stress_operator`)."""
    Gs, element_dofs, ndofs = _mean_gradients(body)
    lam, mu = plane_lame(body.material.E, body.material.nu, "strain")
    nb, nel = element_dofs.shape
    G = np.zeros((3, 3, nel, nb))  # element mean of ∂(φ_i)_c/∂x_d
    Gt = Gs.transpose(1, 2, 0)  # (3, nel, Nbfun / 3)
    for c in range(3):
        G[c, :, :, c::3] = Gt
    tr = G[0, 0] + G[1, 1] + G[2, 2]
    data = np.empty((nel, 6, nb))
    for j, (a, b) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))):
        eps = 0.5 * (G[a, b] + G[b, a])
        data[:, j] = 2 * mu * eps + (lam * tr if a == b else 0.0)
    return _stress_csr(data, element_dofs, ndofs)


def _apply(S: sparse.csr_matrix, u_body, name: str, dim: int = 2) -> np.ndarray:
    u = np.asarray(u_body, dtype=float)
    if u.ndim not in (1, 2) or u.shape[0] != S.shape[1]:
        raise ValueError(
            f"body '{name}': displacement of shape {u.shape}, expected ({S.shape[1]},) or "
            f"({S.shape[1]}, k) ({dim} DOFs per node)"
        )
    k = 4 if dim == 2 else 6
    nel = S.shape[0] // k
    out = S @ u
    if u.ndim == 1:
        return out.reshape(nel, k)
    return np.ascontiguousarray(out.reshape(nel, k, -1).transpose(2, 0, 1))


class StressRecovery:
    """Element-averaged stresses of the continuum bodies of a model, operators built once.

    ``StressRecovery(model)`` (or ``StressRecovery(bodies, plane)``) assembles per continuum
    body (frames are skipped) the sparse matrix of :func:`stress_operator`; recovering the
    stresses of a state is then one sparse product per body, with the results of
    :func:`stresses`: (nel, 4) σxx, σyy, σxy, σzz in Pa.

    Example
    -------
    >>> rec = StressRecovery(model)                       # doctest: +SKIP
    >>> rec.of({"slab": u_slab})["slab"].shape            # doctest: +SKIP
    (80, 4)
    >>> rec("slab", U_slab).shape   # a batch (n_dofs, k) -> (k, nel, 4)   # doctest: +SKIP
    """

    def __init__(self, bodies, plane: str | None = None):
        if plane is None:
            if not hasattr(bodies, "bodies"):
                raise TypeError("StressRecovery(model) or StressRecovery(bodies, plane)")
            bodies, plane = bodies.bodies, bodies.plane
        elif hasattr(bodies, "bodies"):
            bodies = bodies.bodies
        self.plane = str(plane)
        self.bodies = {b.name: b for b in bodies if getattr(b, "kind", None) == "continuum"}
        self.operators: dict[str, sparse.csr_matrix] = {
            name: stress_operator(b, self.plane) for name, b in self.bodies.items()
        }

    def __contains__(self, name: str) -> bool:
        return name in self.operators

    def __call__(self, name: str, u_body: np.ndarray) -> np.ndarray:
        """Stresses (nel, 4) of body ``name`` from its local displacements (n_dofs,), or
        (k, nel, 4) from a batch (n_dofs, k)."""
        S = self.operators.get(name)
        if S is None:
            raise KeyError(f"no continuum body '{name}'; bodies: {', '.join(self.operators)}")
        return _apply(S, u_body, name, self.bodies[name].dim)

    def of(self, u_per_body: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """Stresses of every body in ``u_per_body`` (body name -> local displacements)."""
        return {name: self(name, u) for name, u in u_per_body.items()}
