"""The finite elements of continuum bodies and the arrays of a body's mesh: node coordinates,
element connectivity, boundary edges and their facets, from a scikit-fem mesh (checked:
inverted or degenerate elements, NaN coordinates, nodes of no element).

Part of the model: a :class:`~stepcontact.model.Body` holds these arrays from its
construction (:meth:`Body.from_mesh`); the element matrices are :mod:`stepcontact.fem`'s.
"""

from __future__ import annotations

import numpy as np
from skfem import (
    Basis,
    ElementHex1,
    ElementHex2,
    ElementHexS2,
    ElementQuad1,
    ElementQuad2,
    ElementQuadS2,
    ElementTetP1,
    ElementTetP2,
    ElementTriP1,
    ElementTriP2,
)
from skfem.mesh.mesh_2d_2 import Mesh2D2

from stepcontact.errors import ModelError

_ELEMENTS = {
    "tri3": (ElementTriP1, "MeshTri"),
    "tri6": (ElementTriP2, "MeshTri"),
    "quad4": (ElementQuad1, "MeshQuad"),
    "quad8": (ElementQuadS2, "MeshQuad"),
    "quad9": (ElementQuad2, "MeshQuad"),
    "tet4": (ElementTetP1, "MeshTet"),
    "tet10": (ElementTetP2, "MeshTet"),
    "hex8": (ElementHex1, "MeshHex"),
    "hex20": (ElementHexS2, "MeshHex"),
    "hex27": (ElementHex2, "MeshHex"),
}


def scalar_element(kind: str):
    """The scalar scikit-fem element of an element kind ("tri3" … "quad9", "tet4" … "hex27")."""
    return _ELEMENTS[kind][0]()


def body_arrays(name: str, mesh, kind: str):
    """Node coordinates, element connectivity and boundary edges of a body; checks geometry.

    Returns ``points (n, dim)``, ``cells (nel, nper)``, ``boundary (nf, k)``, ``facets (nf,)``
    (see :class:`~stepcontact.model.Body`).  Raises :class:`ModelError` naming the body and
    element for inverted or degenerate elements and NaN/inf coordinates.
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
    quadratic_geometry = isinstance(mesh, Mesh2D2) or type(mesh).__name__.endswith("2")
    n_vertices = int(mesh.t.max()) + 1 if quadratic_geometry else mesh.p.shape[1]
    used = np.zeros(n_vertices, dtype=bool)
    used[mesh.t.ravel()] = True
    if not used.all():
        raise ModelError(f"{item} node {int(np.flatnonzero(~used)[0])}", "belongs to no element")
    _check_jacobians(item, mesh)
    elem = scalar_element(kind)
    # only the DOF numbers and locations are read: one quadrature point (the reference
    # centroid) instead of the element's full rule (64 points on a hex8, 343 on a hex27)
    b = Basis(mesh, elem, quadrature=(elem.doflocs.mean(axis=0)[:, None], np.ones(1)))
    points = np.ascontiguousarray(b.doflocs.T)
    cells = np.ascontiguousarray(b.element_dofs.T)
    facets = mesh.boundary_facets()
    ends = mesh.facets[:, facets].T
    if mesh.dim() == 3:  # the face's corners, its mid-edge nodes, its centre node
        parts = [ends]
        if b.edge_dofs.shape[0] > 0:
            parts.append(b.edge_dofs[0, mesh.f2e[:, facets]].T)
        if b.facet_dofs.shape[0] > 0:
            parts.append(b.facet_dofs[0, facets][:, None])
        boundary = np.column_stack(parts)
    elif b.facet_dofs.shape[0] > 0:
        boundary = np.column_stack([ends, b.facet_dofs[0, facets]])
    else:
        boundary = ends
    return points, cells, np.ascontiguousarray(boundary), facets


def _check_jacobians(item: str, mesh) -> None:
    """Inverted (sign change) or degenerate (zero area or volume) elements are errors naming the
    element."""
    mapping = mesh.mapping()
    kind = type(mesh).__name__
    if kind.startswith("MeshTri"):
        X = np.array([[1 / 3], [1 / 3]])
    elif kind.startswith("MeshTet"):
        X = np.full((3, 1), 0.25)
    elif kind.startswith("MeshHex"):
        # corners and centre of scikit-fem's reference cube [0, 1]³
        X = np.array([[0, 1, 0, 1, 0, 1, 0, 1, 0.5], [0, 0, 1, 1, 0, 0, 1, 1, 0.5],
                      [0, 0, 0, 0, 1, 1, 1, 1, 0.5]], dtype=float)
    else:
        # corners and centre of scikit-fem's reference square [0, 1]²
        X = np.array([[0.0, 1.0, 1.0, 0.0, 0.5], [0.0, 0.0, 1.0, 1.0, 0.5]])
    with np.errstate(divide="ignore", invalid="ignore"):  # a zero Jacobian: reported below
        det = mapping.detDF(X)  # (nel, nqp)
    size = np.ptp(mesh.p, axis=1).max() if mesh.p.size else 1.0
    dim = mesh.p.shape[0]
    tol = 1e-12 * size**dim
    small = np.abs(det).min(axis=1) <= tol
    if small.any():
        raise ModelError(
            f"{item} element {int(np.flatnonzero(small)[0])}",
            "is degenerate (zero area)" if dim == 2 else "is degenerate (zero volume)",
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


__all__ = ["body_arrays", "scalar_element"]
