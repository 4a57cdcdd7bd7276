"""Gmsh volumes as 3D bodies: the pieces :class:`~stepcontact.io.meshfile.MeshFile` uses for
a 3D mesh (physical volumes -> bodies, physical surfaces -> node sets and named boundaries).

Gmsh element types map to the element kinds of :mod:`stepcontact.model`::

    tetra -> tet4     tetra10 -> tet10     hexahedron -> hex8     hexahedron20 -> hex20
    hexahedron27 -> hex27

A body is built on the straight-edged (linear) geometry of its cells' corners, with the
element of the file's order (or a compatible quadratic one on a linear mesh); every node of
the file is then found at its place among the body's nodes (a KD-tree), so mid-edge, face
and centre nodes need no ordering table — and a second-order node off its straight edge (a
curved element) is a clear error, not a silently different geometry.  What meshio and
scikit-fem's reader do silently is refused here in one line naming the group: several volume
cell types in one body (scikit-fem keeps the first), wedges and pyramids, a named surface
that is not on the body's boundary (an inner face); the named boundaries of a second-order
mesh (which scikit-fem's reader drops) are built from the physical surfaces whatever their
order.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree
from skfem import MeshHex1, MeshTet1

from stepcontact.errors import ModelError
from stepcontact.model import Body

#: gmsh (meshio) volume cell type -> stepcontact element kind
VOLUME_KINDS: dict[str, str] = {
    "tetra": "tet4",
    "tetra10": "tet10",
    "hexahedron": "hex8",
    "hexahedron20": "hex20",
    "hexahedron27": "hex27",
}
#: element kinds that can be used on the cells of each native 3D kind
VOLUME_COMPATIBLE: dict[str, tuple[str, ...]] = {
    "tet4": ("tet4", "tet10"),
    "tet10": ("tet10",),
    "hex8": ("hex8", "hex20", "hex27"),
    "hex20": ("hex20",),
    "hex27": ("hex27",),
}
#: corner nodes of a volume cell (gmsh and VTK list them first)
_CORNERS = {"tetra": 4, "tetra10": 4, "hexahedron": 8, "hexahedron20": 8, "hexahedron27": 8}
#: corner nodes of a surface cell
SURFACE_CORNERS = {"triangle": 3, "triangle6": 3, "quad": 4, "quad8": 4, "quad9": 4}
#: gmsh's (VTK's) hexahedron corners in scikit-fem's order (skfem.io.meshio's mapping)
_HEX_CORNERS = [0, 4, 3, 1, 7, 5, 2, 6]


def volume_cells(label: str, blocks) -> tuple[str, np.ndarray]:
    """The cell type and the cells (file node indices) of a physical volume's blocks; one
    ModelError naming the group for none, several or an unsupported type."""
    if not blocks:
        raise ModelError(label, "has no cells")
    types = sorted({b.type for b in blocks})
    if len(types) > 1:
        raise ModelError(label, f"mixes cell types {', '.join(types)}: use one element type per "
                         "physical volume (meshio-based readers keep only the first type "
                         "silently); split it into one physical volume per type")
    if types[0] not in VOLUME_KINDS:
        raise ModelError(label, f"has '{types[0]}' cells; supported: "
                         f"{', '.join(VOLUME_KINDS)} (order 1 or 2)")
    return types[0], np.vstack([b.cells for b in blocks])


def corner_mesh(kind: str, points: np.ndarray, cells: np.ndarray):
    """The scikit-fem mesh (MeshTet1 or MeshHex1) of the cells' corners and the file nodes of
    its vertices (``used``: vertex i of the mesh is file node used[i])."""
    corners = cells[:, : _CORNERS[kind]]
    used, local = np.unique(corners, return_inverse=True)
    local = local.reshape(corners.shape)
    p = np.ascontiguousarray(points[used].T)
    if kind.startswith("hex"):
        return MeshHex1(p, np.ascontiguousarray(local[:, _HEX_CORNERS].T)), used
    return MeshTet1(p, np.ascontiguousarray(local.T)), used


def file_to_body(label: str, kind: str, points: np.ndarray, cells: np.ndarray,
                 body: Body) -> np.ndarray:
    """file node -> local node of ``body`` (−1: not in the body) for every node of the
    cells, found by place (1e-9 of the mesh's size); ModelError for a node that is not at a
    node of the body's straight-edged elements (a curved second-order element)."""
    nodes = np.unique(cells)
    size = max(1.0, float(np.ptp(points[nodes], axis=0).max()))
    dist, idx = cKDTree(body.points).query(points[nodes])
    off = dist > 1e-9 * size
    if off.any():
        k = int(np.flatnonzero(off)[0])
        x, y, z = points[nodes[k]]
        raise ModelError(label, f"node {int(nodes[k]) + 1} at ({x:.6g}, {y:.6g}, {z:.6g}) "
                         f"is {dist[k]:.3g} m off its {kind} element's straight edges: curved "
                         "second-order elements are not supported; mesh at order 1 and use "
                         "a quadratic element, or keep the edges straight")
    of_file = np.full(len(points), -1, dtype=np.int64)
    of_file[nodes] = idx
    return of_file


def _keys(rows: np.ndarray) -> np.ndarray:
    """One int64 key per row of sorted corner indices (a void view would do, but the keys
    also sort): the rank of each distinct row."""
    rows = np.sort(rows, axis=1)
    _, inv = np.unique(rows, axis=0, return_inverse=True)
    return inv.ravel()


def surface_rows(body: Body, faces: np.ndarray) -> tuple[np.ndarray, int | None]:
    """Rows of ``body.boundary`` of the faces given by their corners (body-local indices,
    (nf, 3 or 4)); and the first face that is not a boundary face of the body (None when all
    are).  A face of another shape (a triangle on hexahedra) is not on the boundary."""
    nvf = 3 if body.element.startswith("tet") else 4
    bnd = body.boundary[:, :nvf]
    if faces.shape[1] != nvf:
        return np.zeros(0, dtype=np.int64), 0
    keys = _keys(np.vstack([bnd, faces]))
    kb, kf = keys[: len(bnd)], keys[len(bnd):]
    order = np.argsort(kb)
    pos = np.minimum(np.searchsorted(kb[order], kf), len(kb) - 1)
    found = kb[order][pos] == kf
    if not found.all():
        return order[pos[found]], int(np.flatnonzero(~found)[0])
    return order[pos], None


__all__ = ["SURFACE_CORNERS", "VOLUME_COMPATIBLE", "VOLUME_KINDS", "corner_mesh",
           "file_to_body", "surface_rows", "volume_cells"]
