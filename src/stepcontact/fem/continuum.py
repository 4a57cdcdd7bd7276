"""scikit-fem glue: bases, element stiffness, edge and body loads, stresses of continuum bodies.

Private: users go through :mod:`stepcontact.model` and :mod:`stepcontact.fem.assembly`.
Everything is vectorised over the elements by scikit-fem; nothing here loops over elements.
"""

from __future__ import annotations

import numpy as np
from skfem import (
    Basis,
    BilinearForm,
    ElementQuad1,
    ElementQuad2,
    ElementQuadS2,
    ElementTriP1,
    ElementTriP2,
    ElementVector,
    FacetBasis,
    LinearForm,
    asm,
)
from skfem.helpers import ddot, dot, sym_grad, trace
from skfem.mesh.mesh_2d_2 import Mesh2D2

from stepcontact.errors import ModelError

_ELEMENTS = {
    "tri3": (ElementTriP1, "MeshTri"),
    "tri6": (ElementTriP2, "MeshTri"),
    "quad4": (ElementQuad1, "MeshQuad"),
    "quad8": (ElementQuadS2, "MeshQuad"),
    "quad9": (ElementQuad2, "MeshQuad"),
}


def scalar_element(kind: str):
    return _ELEMENTS[kind][0]()


def basis_of(body, vector: bool = True) -> Basis:
    """scikit-fem basis of a body (vector-valued by default: DOF 2i+c is node i, component c)."""
    e = scalar_element(body.element)
    return Basis(body.mesh, ElementVector(e) if vector else e)


def body_arrays(name: str, mesh, kind: str):
    """Node coordinates, element connectivity and boundary edges of a body; checks geometry.

    Returns ``points (n,2)``, ``cells (nel, nper)``, ``boundary (nf, 2|3)``, ``facets (nf,)``.
    Raises :class:`ModelError` naming the body and element for inverted or degenerate elements
    and NaN/inf coordinates.
    """
    item = f"body '{name}'"
    cls_name = _ELEMENTS[kind][1]
    if not type(mesh).__name__.startswith(cls_name):
        raise ModelError(
            item, f"element '{kind}' needs a {cls_name} mesh, got {type(mesh).__name__}"
        )
    if not np.all(np.isfinite(mesh.p)):
        bad = int(np.flatnonzero(~np.all(np.isfinite(mesh.p), axis=0))[0])
        raise ModelError(f"{item} node {bad}", "coordinate is NaN or inf")
    # quadratic geometries (MeshTri2, MeshQuad2) list their mid-side nodes after the vertices
    n_vertices = int(mesh.t.max()) + 1 if isinstance(mesh, Mesh2D2) else mesh.p.shape[1]
    used = np.zeros(n_vertices, dtype=bool)
    used[mesh.t.ravel()] = True
    if not used.all():
        raise ModelError(f"{item} node {int(np.flatnonzero(~used)[0])}", "belongs to no element")
    _check_jacobians(item, mesh)
    b = Basis(mesh, scalar_element(kind))
    points = np.ascontiguousarray(b.doflocs.T)
    cells = np.ascontiguousarray(b.element_dofs.T)
    facets = mesh.boundary_facets()
    ends = mesh.facets[:, facets].T
    if b.facet_dofs.shape[0] > 0:
        boundary = np.column_stack([ends, b.facet_dofs[0, facets]])
    else:
        boundary = ends
    return points, cells, np.ascontiguousarray(boundary), facets


def _check_jacobians(item: str, mesh) -> None:
    """Inverted (sign change) or degenerate (zero area) elements are errors naming the element."""
    mapping = mesh.mapping()
    if type(mesh).__name__.startswith("MeshTri"):
        X = np.array([[1 / 3], [1 / 3]])
    else:
        # corners and centre of scikit-fem's reference square [0, 1]²
        X = np.array([[0.0, 1.0, 1.0, 0.0, 0.5], [0.0, 0.0, 1.0, 1.0, 0.5]])
    det = mapping.detDF(X)  # (nel, nqp)
    size = np.ptp(mesh.p, axis=1).max() if mesh.p.size else 1.0
    tol = 1e-12 * size**2
    small = np.abs(det).min(axis=1) <= tol
    if small.any():
        raise ModelError(
            f"{item} element {int(np.flatnonzero(small)[0])}", "is degenerate (zero area)"
        )
    # an element whose Jacobian changes sign inside it is folded (inverted corner, bow-tie);
    # element orientation itself is free in scikit-fem, so only a sign change is an error
    sign = np.sign(det)
    bad = np.any(sign != sign[:, :1], axis=1)
    if bad.any():
        raise ModelError(
            f"{item} element {int(np.flatnonzero(bad)[0])}",
            "is inverted (its Jacobian changes sign)",
        )


def plane_lame(E: float, nu: float, plane: str) -> tuple[float, float]:
    """Lamé parameters (λ, μ) in Pa for plane strain, or the plane-stress equivalents."""
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    if plane == "stress":
        lam = 2 * lam * mu / (lam + 2 * mu)
    return lam, mu


def stiffness(body, plane: str, thickness: float):
    """Stiffness matrix (CSR, body-local vector DOFs) of a continuum body, N/m."""
    lam, mu = plane_lame(body.material.E, body.material.nu, plane)

    @BilinearForm
    def form(u, v, w):
        eu, ev = sym_grad(u), sym_grad(v)
        return thickness * (2 * mu * ddot(eu, ev) + lam * trace(eu) * trace(ev))

    return asm(form, basis_of(body)).tocsr()


def body_force(body, g, thickness: float) -> np.ndarray:
    """Consistent nodal forces of the self-weight ρ g (body-local vector DOFs), N."""
    rho = body.material.density
    gv = np.asarray(g, dtype=float)

    @LinearForm
    def form(v, w):
        return thickness * rho * (gv[0] * v[0] + gv[1] * v[1])

    return asm(form, basis_of(body))


def edge_load(body, facets: np.ndarray, pn, pt, thickness: float) -> np.ndarray:
    """Consistent nodal forces of edge pressures on the given boundary facets, N.

    ``pn(x, y)`` is the normal pressure (Pa, positive into the body), ``pt(x, y)`` the
    tangential traction (Pa) along t = (-n_y, n_x), n the outward normal.  Both are callables
    evaluated at the quadrature points, or None.
    """
    fb = FacetBasis(body.mesh, ElementVector(scalar_element(body.element)), facets=facets)

    @LinearForm
    def form(v, w):
        n = w.n
        t = np.array([-n[1], n[0]])
        x, y = w.x[0], w.x[1]
        trac = 0.0 * n
        if pn is not None:
            trac = trac - pn(x, y) * n
        if pt is not None:
            trac = trac + pt(x, y) * t
        return thickness * dot(trac, v)

    return asm(form, fb)


def stresses(body, u_body: np.ndarray, plane: str) -> np.ndarray:
    """Element-averaged stresses (nel, 4): σxx, σyy, σxy, σzz in Pa.

    σzz = λ(εxx+εyy) in plane strain and 0 in plane stress.
    """
    basis = basis_of(body)
    lam, mu = plane_lame(body.material.E, body.material.nu, plane)
    uh = basis.interpolate(u_body)
    eps = sym_grad(uh)  # (2, 2, nel, nqp)
    tr = eps[0, 0] + eps[1, 1]
    sxx = 2 * mu * eps[0, 0] + lam * tr
    syy = 2 * mu * eps[1, 1] + lam * tr
    sxy = 2 * mu * eps[0, 1]
    if plane == "strain":
        nu = body.material.nu
        szz = nu * (sxx + syy)
    else:
        szz = 0.0 * tr
    dx = basis.dx
    vol = dx.sum(axis=1)
    out = np.column_stack([(s * dx).sum(axis=1) / vol for s in (sxx, syy, sxy, szz)])
    return out
