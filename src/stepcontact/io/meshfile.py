"""Gmsh meshes: physical surfaces become bodies, physical curves and points become node sets;
in a 3D mesh physical volumes become bodies and physical surfaces node sets (and named
boundaries of the bodies, :mod:`stepcontact.io.meshfile3d`).

A ``.msh`` file (any version meshio reads) is read with :func:`read_msh`.  Each *physical
surface* is one :class:`~stepcontact.model.Body` made of the cells of that group only, with its
own node numbering, so two surfaces that do not share nodes (a non-matching interface) are two
separate bodies.  Each *physical curve* or *physical point* is a
:class:`~stepcontact.model.NodeSet` of the body that contains its nodes; when a curve is shared
by two bodies (a conforming mesh), the body has to be named.

Gmsh element types map to the element kinds of :mod:`stepcontact.model`::

    triangle -> tri3     triangle6 -> tri6     quad -> quad4     quad8 -> quad8     quad9 -> quad9

A linear mesh may be used with the quadratic element of the same shape (``element="tri6"`` on
triangles, ``"quad8"``/``"quad9"`` on quads).  Clockwise cells are reordered counter-clockwise;
cells folded over a neighbour (both on the same side of their common edge), self-crossing or
non-convex quads and zero-area cells are errors naming the physical group and the element.
Coordinates are in metres; a 2D mesh must lie in the plane z = 0.  A mesh with volume cells
(or physical volumes) is 3D (:attr:`MeshFile.dim`): see :mod:`stepcontact.io.meshfile3d` for
its element types and checks.

:func:`mesh_geo` meshes a ``.geo`` file (or runs a gmsh Python script) when the ``gmsh``
package is installed (``pip install gmsh``).

Example
-------
>>> import stepcontact as sc
>>> from stepcontact.io.meshfile import read_msh
>>> mf = read_msh("examples/data/gmsh_block.msh")                # doctest: +SKIP
>>> concrete = sc.Material(30e9, 0.2, 2400)
>>> found, block = mf.body("foundation", concrete), mf.body("block", concrete)  # doctest: +SKIP
>>> m = sc.Model(bodies=[found, block]).add(                          # doctest: +SKIP
...     sc.Support("bed", mf.node_set("base"), "xy"),
...     sc.Interface("joint", plus=mf.node_set("block_bottom"),
...                  minus=mf.node_set("foundation_top"), friction=0.5))
"""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.io import meshfile3d as _3d
from stepcontact.model import Body, Material, NodeSet
from stepcontact.model.gmsh_api import gmsh_session
from stepcontact.model.mesh import REVERSED_NODE_ORDER

#: gmsh (meshio) cell type -> stepcontact element kind
CELL_KINDS: dict[str, str] = {
    "triangle": "tri3",
    "triangle6": "tri6",
    "quad": "quad4",
    "quad8": "quad8",
    "quad9": "quad9",
}
#: element kinds that can be used on the cells of each native kind
COMPATIBLE: dict[str, tuple[str, ...]] = {
    "tri3": ("tri3", "tri6"),
    "tri6": ("tri6",),
    "quad4": ("quad4", "quad8", "quad9"),
    "quad8": ("quad8",),
    "quad9": ("quad9",),
}
GROUP_KINDS = ("point", "curve", "surface", "volume")

_FLIP = REVERSED_NODE_ORDER  # gmsh node ordering
# nodes of a curve cell in their order along the curve
_ALONG = {"line": [0, 1], "line3": [0, 2, 1], "vertex": [0]}
_CORNERS = {"triangle": 3, "triangle6": 3, "quad": 4, "quad8": 4, "quad9": 4}


@dataclass(frozen=True)
class PhysicalGroup:
    """A gmsh physical group: ``dim`` 0 (point), 1 (curve), 2 (surface) or 3 (volume), and
    its tag."""

    name: str
    dim: int
    tag: int

    @property
    def kind(self) -> str:
        return GROUP_KINDS[self.dim]

    @property
    def label(self) -> str:
        """e.g. ``physical surface 'block'``."""
        return f"physical {self.kind} '{self.name}'"


@dataclass(frozen=True, eq=False)
class CellBlock:
    """Cells of one gmsh entity in one physical group (node indices into the file's points)."""

    type: str
    cells: np.ndarray
    entity: np.ndarray  # gmsh entity (geometrical) tag of each cell, -1 if unknown


@dataclass(frozen=True, eq=False)
class _Built:
    """A body made from a mesh file: file node -> local node (-1: not in the body), and the
    sorted side keys (a·n + b, a < b) with their mid-side nodes when the element adds them."""

    surface: str
    of_file: np.ndarray
    n_nodes: int
    edges: np.ndarray | None = None
    mid: np.ndarray | None = None
    #: 3D: physical surface -> (the body's nodes of its faces, first face not on the body's
    #: boundary or None)
    faces: dict = field(default_factory=dict)


@dataclass(eq=False)
class MeshFile:
    """A gmsh mesh with physical groups; make bodies and node sets from it.

    Attributes
    ----------
    path : Path
    points : ndarray (n, 2) or (n, 3)
        All nodes of the file (0-based, in file order), m.
    groups : dict of PhysicalGroup
        By name; unnamed groups are called ``volume_<tag>``, ``surface_<tag>``,
        ``curve_<tag>``, ``point_<tag>``.
    blocks : dict of tuple of CellBlock
        The cells of each group.
    dim : int
        2, or 3 for a mesh with volume cells or physical volumes (then the bodies are the
        physical volumes).
    cell_counts : dict
        The number of cells of each type in the file.
    """

    path: Path
    points: np.ndarray
    groups: dict[str, PhysicalGroup]
    blocks: dict[str, tuple[CellBlock, ...]]
    dim: int = 2
    cell_counts: dict = field(default_factory=dict)
    _built: dict[str, _Built] = field(default_factory=dict, repr=False)

    # ---- groups ---------------------------------------------------------------------------
    def names(self, dim: int | None = None) -> list[str]:
        """Names of the physical groups (of one dimension: 0 points, 1 curves, 2 surfaces)."""
        return [n for n, g in self.groups.items() if dim is None or g.dim == dim]

    @property
    def volumes(self) -> list[str]:
        return self.names(3)

    @property
    def body_groups(self) -> list[str]:
        """The groups that are bodies: physical surfaces (2D), physical volumes (3D)."""
        return self.names(self.dim)

    @property
    def surfaces(self) -> list[str]:
        return self.names(2)

    @property
    def curves(self) -> list[str]:
        return self.names(1)

    @property
    def point_groups(self) -> list[str]:
        return self.names(0)

    def group(self, name: str, dims: Sequence[int] | None = None) -> PhysicalGroup:
        """The physical group ``name``; errors list the groups the file has."""
        g = self.groups.get(name)
        if g is None:
            raise ModelError(
                f"mesh '{self.path.name}'",
                f"physical group '{name}' not found; groups are: {self.describe()}",
            )
        if dims is not None and g.dim not in dims:
            wanted = " or ".join(GROUP_KINDS[d] for d in dims)
            raise ModelError(
                g.label,
                f"is a physical {g.kind}, a {wanted} is needed here; "
                f"groups are: {self.describe()}",
            )
        return g

    def describe(self) -> str:
        """``surfaces 'a', 'b'; curves 'c'; points none`` (for messages)."""
        parts = []
        for dim in (3, 2, 1, 0) if self.dim == 3 else (2, 1, 0):
            names = self.names(dim)
            listed = ", ".join(repr(n) for n in names) if names else "none"
            parts.append(f"{GROUP_KINDS[dim]}s {listed}")
        return "; ".join(parts)

    def cells(self, surface: str) -> tuple[str, np.ndarray]:
        """Cell type and cells (file node indices, counter-clockwise) of a physical surface.

        Raises :class:`ModelError` naming the group and element for mixed or unsupported cell
        types and for inverted or degenerate cells.
        """
        g = self.group(surface, (2,))
        blocks = self.blocks[surface]
        types = sorted({b.type for b in blocks})
        if not blocks:
            raise ModelError(g.label, "has no cells")
        if len(types) > 1:
            raise ModelError(
                g.label, f"mixes cell types {', '.join(types)}; use one element type per surface"
            )
        if types[0] not in CELL_KINDS:
            raise ModelError(
                g.label,
                f"has '{types[0]}' cells; supported: {', '.join(CELL_KINDS)} (order 1 or 2)",
            )
        kind = types[0]
        cells = np.vstack([b.cells for b in blocks])
        cells, cw, degenerate = _orient(self.points, kind, cells)
        folded = _folds(self.points, cells, _CORNERS[kind], cw)
        bad = np.flatnonzero(degenerate)
        what = "degenerate (zero area, or three corners in a line)"
        if not bad.size:
            bad = np.unique(folded[:, 0])
            if bad.size and folded[0, 1] != folded[0, 0]:
                what = f"inverted (folded over element {int(folded[0, 1])})"
            else:
                what = "inverted (its sides cross or a corner is reflex)"
        if bad.size:
            first = int(bad[0])
            c = self.points[cells[first, : _CORNERS[kind]]].mean(axis=0)
            more = bad.size - 1
            also = f"; {more} more such element{'s' * (more > 1)}" if more else ""
            raise ModelError(
                f"{g.label} element {first}", f"is {what}, centroid ({c[0]:.6g}, {c[1]:.6g}){also}"
            )
        return kind, cells

    def element_kind(self, surface: str) -> str:
        """The native element kind of a physical surface (``tri3``, ``quad9``, ...)."""
        return CELL_KINDS[self.cells(surface)[0]]

    # ---- bodies -----------------------------------------------------------------------------
    def contents(self) -> str:
        """``element types found: tetra (5), triangle (2); physical volumes 'block'`` (for
        messages)."""
        what = []
        if self.cell_counts:
            what.append("element types found: " + ", ".join(
                f"{t} ({n})" for t, n in self.cell_counts.items()))
        if self.volumes:
            what.append("physical volumes " + ", ".join(f"'{v}'" for v in self.volumes))
        return "; ".join(what)

    def body(
        self,
        surface: str,
        material: Material,
        *,
        name: str | None = None,
        element: str | None = None,
    ) -> Body:
        """The body made of the cells of physical surface ``surface`` (named ``name``, default
        the group name), with the group's element kind or a compatible ``element``; in a 3D
        mesh, of physical volume ``surface`` (:meth:`solid`)."""
        if self.dim == 3:
            return self.solid(surface, material, name=name, element=element)
        name = surface if name is None else name
        kind, cells = self.cells(surface)
        native = CELL_KINDS[kind]
        element = native if element is None else element
        g = self.groups[surface]
        if element not in COMPATIBLE[native]:
            raise ModelError(
                g.label,
                f"has {native} cells: element '{element}' cannot be used, use one of "
                f"{', '.join(COMPATIBLE[native])}",
            )
        used, local = np.unique(cells, return_inverse=True)
        local = local.reshape(cells.shape)
        mesh = _skfem_mesh(kind, self.points[used], local)
        try:
            body = Body.from_mesh(name, mesh, element, material)
        except ModelError as e:
            raise ModelError(e.item.replace(f"body '{name}'", g.label), e.problem) from None
        # file node index -> local node index of the body (the local DOF order of scikit-fem's
        # elements is gmsh's for the corner and mid-side nodes)
        k = min(cells.shape[1], body.cells.shape[1])
        of_file = np.full(len(self.points), -1, dtype=np.int64)
        of_file[cells[:, :k]] = body.cells[:, :k]
        mapped = np.flatnonzero(of_file >= 0)
        err = np.abs(body.points[of_file[mapped]] - self.points[mapped]).max(initial=0.0)
        if err > 1e-9 * max(1.0, float(np.ptp(self.points, axis=0).max())):
            raise ModelError(g.label, f"node renumbering failed (mismatch {err:g} m)")
        edges = mid = None
        if element != native:  # mid-side nodes that the file does not have
            from stepcontact.fem.continuum import basis_of

            f = np.sort(body.mesh.facets, axis=0)
            edges = f[0].astype(np.int64) * body.n_nodes + f[1]
            mid = basis_of(body, vector=False).facet_dofs[0]
            order = np.argsort(edges)
            edges, mid = edges[order], mid[order]
        self._built[name] = _Built(surface, of_file, body.n_nodes, edges, mid)
        return body

    def solid(self, volume: str, material: Material, *, name: str | None = None,
              element: str | None = None) -> Body:
        """The 3D body made of the cells of physical volume ``volume`` (named ``name``, default
        the group name), with the group's element kind or a compatible ``element`` (tet10 on
        tetra, hex20 or hex27 on hexahedron).  Its named boundaries are the physical surfaces
        whose faces all lie on its boundary (``model.select(name, boundary="top")``)."""
        name = volume if name is None else name
        g = self.group(volume, (3,))
        kind, cells = _3d.volume_cells(g.label, self.blocks[volume])
        native = _3d.VOLUME_KINDS[kind]
        element = native if element is None else element
        if element not in _3d.VOLUME_COMPATIBLE[native]:
            raise ModelError(g.label, f"has {native} cells: element '{element}' cannot be used, "
                             f"use one of {', '.join(_3d.VOLUME_COMPATIBLE[native])}")
        mesh, _ = _3d.corner_mesh(kind, self.points, cells)
        try:
            body = Body.from_mesh(name, mesh, element, material)
        except ModelError as e:
            raise ModelError(e.item.replace(f"body '{name}'", g.label), e.problem) from None
        of_file = _3d.file_to_body(g.label, kind, self.points, cells, body)
        faces, named = {}, {}
        for s in self.surfaces:
            ids = [b.cells[:, : _3d.SURFACE_CORNERS[b.type]] for b in self.blocks[s]
                   if b.type in _3d.SURFACE_CORNERS]
            if not ids or len({a.shape[1] for a in ids}) > 1:
                continue
            local = of_file[np.vstack(ids)]
            if np.any(local < 0):
                continue  # not (all) on this body
            rows, bad = _3d.surface_rows(body, local)
            # the body's nodes of the faces (mid-edge and centre nodes of quadratic elements)
            faces[s] = (np.unique(body.boundary[rows].ravel()), bad)
            if bad is None:
                named[s] = body.boundary_facets[rows]
        if named:
            body = dataclasses.replace(body, mesh=body.mesh.with_boundaries(named))
        self._built[name] = _Built(volume, of_file, body.n_nodes, faces=faces)
        return body

    def bodies(
        self, materials: Material | Mapping[str, Material], element: str | None = None
    ) -> list[Body]:
        """One body per physical surface (named like the group), in the file's group order; in
        a 3D mesh one per physical volume.

        ``materials`` is one material for all, or a mapping from group name to material.
        """
        out = []
        for s in self.body_groups:
            mat = materials if isinstance(materials, Material) else materials.get(s)
            if mat is None:
                raise ModelError(self.groups[s].label, "has no material")
            out.append(self.body(s, mat, element=element))
        return out

    # ---- node sets --------------------------------------------------------------------------
    def node_ids(self, group: str) -> np.ndarray:
        """File node indices of a physical curve or point, in order along the curve."""
        self.group(group, (0, 1))
        blocks = self.blocks[group]
        if not blocks:
            return np.zeros(0, dtype=np.int64)
        seq = np.concatenate([b.cells[:, _ALONG[b.type]].ravel() for b in blocks])
        _, first = np.unique(seq, return_index=True)
        return seq[np.sort(first)]

    def owners(self, group: str) -> list[str]:
        """Physical surfaces (3D: volumes) whose cells contain every node of a curve or point
        group (3D: or surface)."""
        ids = self.node_ids(group) if self.groups[group].dim < 2 else np.unique(
            np.concatenate([b.cells.ravel() for b in self.blocks[group]] or [np.zeros(0, int)]))
        out = []
        for s in self.body_groups:
            nodes = np.concatenate([b.cells.ravel() for b in self.blocks[s]] or [np.zeros(0, int)])
            if ids.size and np.isin(ids, nodes).all():
                out.append(s)
        return out

    def node_set(self, group: str, body: str | Body | None = None, name: str = "") -> NodeSet:
        """Node set of a physical curve or point on a body made with :meth:`body`.

        ``body`` (a name or the Body) is needed only when the group's nodes belong to several
        bodies (a curve shared by two conforming surfaces).  ``name`` defaults to the group's.

        In a 3D mesh a physical surface is a node set too: the nodes of its faces on the body
        (with the mid-edge and centre nodes of quadratic elements); a surface that is not on
        the body's boundary (an inner face) is a ModelError.
        """
        if self.dim == 3:
            return self._solid_node_set(group, body, name)
        g = self.group(group, (0, 1))
        ids = self.node_ids(group)
        if ids.size == 0:
            raise ModelError(g.label, "has no nodes")
        name = name or group
        if isinstance(body, Body):
            body = body.name
        if body is not None:
            if body not in self._built:
                made = ", ".join(repr(b) for b in self._built) or "none yet"
                raise ModelError(
                    g.label,
                    f"body '{body}' was not made from this mesh (bodies made: {made})",
                )
            built = self._built[body]
            missing = built.of_file[ids] < 0
            if missing.any():
                x, y = self.points[ids[np.flatnonzero(missing)[0]]]
                raise ModelError(
                    g.label,
                    f"{int(missing.sum())} of its {ids.size} nodes are not nodes of body "
                    f"'{body}' (physical surface '{built.surface}'), e.g. at ({x:.6g}, {y:.6g})",
                )
            return NodeSet(body, self._local(g, built), name)
        hits = [b for b, built in self._built.items() if (built.of_file[ids] >= 0).all()]
        if len(hits) == 1:
            return NodeSet(hits[0], self._local(g, self._built[hits[0]]), name)
        if len(hits) > 1:
            raise ModelError(
                g.label,
                f"lies on bodies {', '.join(repr(h) for h in hits)} (a curve shared by "
                "conforming meshes): say which body the node set belongs to",
            )
        owners = self.owners(group)
        if owners:
            raise ModelError(
                g.label,
                f"lies on physical surface {', '.join(repr(o) for o in owners)}, which is not "
                "a body of the model",
            )
        raise ModelError(
            g.label, "is not on a single physical surface (split it into one group per body)"
        )

    def _local(self, g: PhysicalGroup, built: _Built) -> np.ndarray:
        """Local node indices of a group on a body, in order along the curve; with the
        mid-side nodes the body has and the file has not (quadratic elements on a linear
        mesh)."""
        if built.edges is None or g.dim == 0:
            return built.of_file[self.node_ids(g.name)]
        seq = []
        for b in self.blocks[g.name]:
            a, c = built.of_file[b.cells[:, 0]], built.of_file[b.cells[:, 1]]
            key = np.minimum(a, c) * built.n_nodes + np.maximum(a, c)
            pos = np.minimum(np.searchsorted(built.edges, key), len(built.edges) - 1)
            if np.any(built.edges[pos] != key):
                raise ModelError(g.label, "has a segment that is not an element side")
            seq.append(np.column_stack([a, built.mid[pos], c]).ravel())
        s = np.concatenate(seq)
        _, first = np.unique(s, return_index=True)
        return s[np.sort(first)]

    def _solid_node_set(self, group: str, body: str | Body | None, name: str) -> NodeSet:
        """:meth:`node_set` in a 3D mesh: points, curves (their file nodes) and surfaces (the
        nodes of their boundary faces on the body)."""
        g = self.group(group, (0, 1, 2))
        name = name or group
        if isinstance(body, Body):
            body = body.name
        if body is not None and body not in self._built:
            made = ", ".join(repr(b) for b in self._built) or "none yet"
            raise ModelError(g.label, f"body '{body}' was not made from this mesh (bodies "
                             f"made: {made})")
        cand = [body] if body is not None else list(self._built)
        ids = self.node_ids(group) if g.dim < 2 else np.unique(
            np.concatenate([b.cells.ravel() for b in self.blocks[group]] or [np.zeros(0, int)]))
        if ids.size == 0:
            raise ModelError(g.label, "has no nodes")
        hits = [b for b in cand if (self._built[b].of_file[ids] >= 0).all()]
        if not hits:
            where = f"body '{body}'" if body is not None else "any body made from this mesh"
            owners = [o for o in self.owners(group) if o not in {
                self._built[b].surface for b in self._built}]
            also = (f" (it lies on physical volume {', '.join(repr(o) for o in owners)}, "
                    "which is not a body of the model)") if owners else ""
            raise ModelError(g.label, f"is not on {where}{also}")
        if len(hits) > 1:
            raise ModelError(g.label, f"lies on bodies {', '.join(repr(h) for h in hits)} (a "
                             "surface shared by conforming meshes): say which body the node "
                             "set belongs to")
        built = self._built[hits[0]]
        if g.dim < 2:
            return NodeSet(hits[0], built.of_file[ids], name)
        nodes, bad = built.faces.get(group, (np.zeros(0, dtype=np.int64), 0))
        if bad is not None:
            cell = np.vstack([b.cells for b in self.blocks[group]])[bad]
            c = self.points[cell].mean(axis=0)
            raise ModelError(g.label, f"face {bad} (centroid ({c[0]:.6g}, {c[1]:.6g}, "
                             f"{c[2]:.6g})) is not a face on the boundary of body "
                             f"'{hits[0]}' (an inner face, or no face of its elements): node "
                             "sets and interfaces of a 3D body lie on its boundary")
        return NodeSet(hits[0], nodes, name)

    def orphan_nodes(self) -> np.ndarray:
        """File node indices used by no cell of any physical surface (3D: volume)."""
        used = np.zeros(len(self.points), dtype=bool)
        for s in self.body_groups:
            for b in self.blocks[s]:
                used[b.cells.ravel()] = True
        return np.flatnonzero(~used)


# --------------------------------------------------------------------------------------------
# reading
# --------------------------------------------------------------------------------------------
def _dim(cell_type: str) -> int | None:
    """Dimension of a meshio cell type (None for a type that is no cell of a mesh)."""
    if cell_type == "vertex":
        return 0
    if cell_type.startswith("line"):
        return 1
    if cell_type.startswith(("triangle", "quad", "polygon")):
        return 2
    if cell_type.startswith(("tetra", "hexahedron", "wedge", "pyramid")):
        return 3
    return None


def _mesh_dim(item: str, m, pts: np.ndarray, named: dict[str, tuple[int, int]]
              ) -> tuple[int, dict[str, int]]:
    """The mesh's dimension — 3 with volume cells (tetrahedra, hexahedra, …) or physical
    volumes, else 2 — and its cell counts by type; a :class:`ModelError` on ``item`` (the mesh
    file) for a surface mesh whose points leave the plane z = const, naming the z range."""
    counts: dict[str, int] = {}
    for blk in m.cells:
        counts[blk.type] = counts.get(blk.type, 0) + len(blk.data)
    if any(_dim(t) == 3 for t in counts) or any(d == 3 for d, _ in named.values()):
        return 3, counts
    size = float(np.ptp(pts[:, :2], axis=0).max()) if len(pts) else 1.0
    zs = pts[:, 2] if pts.shape[1] > 2 and len(pts) else np.zeros(1)
    if np.ptp(zs) > 1e-9 * max(size, 1.0):
        found = ", ".join(f"{t} ({n})" for t, n in counts.items())
        raise ModelError(item, f"is not planar (element types found: {found}; points at z = "
                         f"{zs.min():.6g} … {zs.max():.6g} m): a surface mesh in space is "
                         "neither a 2D section (the plane z = 0) nor a 3D body (volume cells, "
                         "meshed in gmsh with Mesh 3)")
    return 2, counts


def read_msh(path: str | os.PathLike) -> MeshFile:
    """Read a gmsh ``.msh`` file (format 2.2 or 4.1) with its physical groups.

    A mesh with volume cells or physical volumes is 3D (:attr:`MeshFile.dim`): its points
    keep their three coordinates and its physical volumes are the bodies.

    Raises
    ------
    ModelError
        When the file is missing or unreadable (``item`` is the file name), a surface mesh that
        is not planar, or has no physical group.
    """
    import meshio

    path = Path(path)
    item = f"mesh '{path}'"
    if path.is_dir():
        raise ModelError(item, "is a directory, not a mesh file")
    if not path.is_file():
        raise ModelError(item, "file not found")
    try:
        with open(path, "rb") as fh:
            fh.read(1)
    except OSError as e:
        raise ModelError(item, f"cannot be read: {e.strerror or e}") from None
    try:
        m = meshio.gmsh.read(str(path))
    except Exception as e:  # meshio raises many types for bad files
        raise ModelError(item, f"cannot read the mesh ({type(e).__name__}: {e})") from None
    pts = np.asarray(m.points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] < 2:
        raise ModelError(item, "has no 2D points")
    named = {str(k): (int(v[1]), int(v[0])) for k, v in (m.field_data or {}).items()}
    mesh_dim, counts = _mesh_dim(item, m, pts, named)
    pts = np.ascontiguousarray(pts[:, :mesh_dim])
    if pts.shape[1] < mesh_dim:
        raise ModelError(item, "has volume cells but 2D points")

    physical = m.cell_data.get("gmsh:physical")
    entity = m.cell_data.get("gmsh:geometrical")
    groups: dict[str, PhysicalGroup] = {}
    for n, (dim, tag) in named.items():
        groups[n] = PhysicalGroup(n, dim, tag)
    by_tag = {(g.dim, g.tag): g.name for g in groups.values()}
    if physical is not None:  # unnamed groups
        for blk, tags in zip(m.cells, physical, strict=True):
            dim = _dim(blk.type)
            for t in np.unique(np.asarray(tags)) if dim is not None else ():
                if t > 0 and (dim, int(t)) not in by_tag:
                    n = f"{GROUP_KINDS[dim]}_{int(t)}"
                    groups[n] = PhysicalGroup(n, dim, int(t))
                    by_tag[(dim, int(t))] = n
    if not groups:
        raise ModelError(
            item, "has no physical groups: define Physical Volume / Surface / Curve / Point "
            "in gmsh"
        )
    sets = {k: v for k, v in (m.cell_sets or {}).items() if not k.startswith("gmsh:")}
    blocks: dict[str, list[CellBlock]] = {n: [] for n in groups}
    for i, blk in enumerate(m.cells):
        dim = _dim(blk.type)
        if dim is None:
            continue
        data = np.asarray(blk.data, dtype=np.int64)
        ent = np.full(len(data), -1) if entity is None else np.asarray(entity[i]).ravel()
        for n, g in groups.items():
            if g.dim != dim:
                continue
            if n in sets:
                idx = np.asarray(sets[n][i] if sets[n][i] is not None else [], dtype=np.int64)
            elif physical is not None:
                idx = np.flatnonzero(np.asarray(physical[i]) == g.tag)
            else:
                continue
            if idx.size:
                blocks[n].append(CellBlock(blk.type, data[idx], ent[idx]))
    return MeshFile(path, pts, groups, {n: tuple(v) for n, v in blocks.items()}, mesh_dim,
                    counts)


def _orient(
    points: np.ndarray, kind: str, cells: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cells reordered counter-clockwise; which were clockwise; which are degenerate.

    A quad whose corners do not all turn the same way (self-crossing or with a reflex corner)
    is returned as it is and flagged by :func:`_folds` through a negative corner.
    """
    nc = _CORNERS[kind]
    xy = points[cells[:, :nc]]  # (n, nc, 2)
    e_next = np.roll(xy, -1, axis=1) - xy
    e_prev = np.roll(xy, 1, axis=1) - xy
    cross = e_next[..., 0] * e_prev[..., 1] - e_next[..., 1] * e_prev[..., 0]
    tol = 1e-12 * (e_next**2).sum(axis=2).max(axis=1)[:, None]
    degenerate = (np.abs(cross) <= tol).any(axis=1)
    cw = 0.5 * cross.sum(axis=1) < 0  # signed area (sum of corner cross products ∝ area)
    out = np.where(cw[:, None], cells[:, _FLIP[kind]], cells)
    return out, cw, degenerate


def _folds(points: np.ndarray, cells: np.ndarray, nc: int, cw: np.ndarray) -> np.ndarray:
    """Pairs (bad, other) of counter-clockwise cells that fold over each other.

    Two cells sharing an edge must lie on opposite sides of it; a quad must also turn the same
    way at all its corners (then it is paired with itself).  Of a folded pair, the cell that
    was clockwise in the file (else the later one) is reported first.
    """
    xy = points[cells[:, :nc]]
    e_next = np.roll(xy, -1, axis=1) - xy
    e_prev = np.roll(xy, 1, axis=1) - xy
    cross = e_next[..., 0] * e_prev[..., 1] - e_next[..., 1] * e_prev[..., 0]
    crossed = np.flatnonzero((cross < 0).any(axis=1))
    n = len(cells)
    a = cells[:, :nc].ravel()
    b = np.roll(cells[:, :nc], -1, axis=1).ravel()
    owner = np.repeat(np.arange(n), nc)
    key = np.minimum(a, b) * (int(cells.max()) + 1) + np.maximum(a, b)
    order = np.argsort(key, kind="stable")
    ks = key[order]
    twin = np.flatnonzero(ks[1:] == ks[:-1])  # shared edges: positions i, i+1 in sorted order
    e1, e2 = order[twin], order[twin + 1]
    p, d = points[a[e1]], points[b[e1]] - points[a[e1]]
    centre = xy.mean(axis=1)

    def side(c: np.ndarray) -> np.ndarray:
        r = c - p
        return np.sign(d[:, 0] * r[:, 1] - d[:, 1] * r[:, 0])

    fold = side(centre[owner[e1]]) == side(centre[owner[e2]])
    i, j = owner[e1][fold], owner[e2][fold]
    first_bad = np.where(cw[j] & ~cw[i], j, np.where(cw[i] & ~cw[j], i, np.maximum(i, j)))
    other = np.where(first_bad == i, j, i)
    pairs = np.vstack([np.column_stack([crossed, crossed]),
                       np.column_stack([first_bad, other])]).astype(np.int64)
    return pairs[np.argsort(pairs[:, 0], kind="stable")]


def _skfem_mesh(kind: str, pts: np.ndarray, cells: np.ndarray):
    """scikit-fem mesh of local points (n, 2) and cells (gmsh local node order)."""
    from skfem import MeshQuad1, MeshQuad2, MeshTri1, MeshTri2

    if kind == "triangle":
        return MeshTri1(pts.T.copy(), cells.T.copy(), sort_t=False)
    if kind == "triangle6":
        return MeshTri2(pts.T.copy(), cells.T.copy())
    if kind == "quad":
        return MeshQuad1(pts.T.copy(), cells.T.copy())
    if kind == "quad8":  # serendipity geometry = biquadratic with the centre it implies
        centre = -0.25 * pts[cells[:, :4]].sum(axis=1) + 0.5 * pts[cells[:, 4:8]].sum(axis=1)
        cells = np.column_stack([cells, len(pts) + np.arange(len(cells))])
        pts = np.vstack([pts, centre])
    return MeshQuad2(pts.T.copy(), cells.T.copy())


# --------------------------------------------------------------------------------------------
# meshing with gmsh
# --------------------------------------------------------------------------------------------
def mesh_geo(
    path: str | os.PathLike,
    order: int = 1,
    element: str = "tri",
    size: float | None = None,
    out: str | os.PathLike | None = None,
) -> Path:
    """Mesh a gmsh ``.geo`` file (or run a gmsh Python script) into a ``.msh`` file.

    Parameters
    ----------
    path : path
        A ``.geo`` file, meshed with the gmsh API (in 3D when it has volumes, else in 2D); or a
        ``.py`` script, run as
        ``python script.py OUT.msh`` in its own directory, which must write the mesh to the
        file named by its first argument.
    order : 1 or 2
        Element order (2: ``triangle6`` or ``quad9`` cells; ``tetra10`` or ``hexahedron27``).
    element : "tri" or "quad"
        ``"quad"`` recombines the triangles into quads (``.geo`` only).
    size : float, optional
        Largest element size, m (``Mesh.MeshSizeMax``; ``.geo`` only).
    out : path, optional
        The ``.msh`` file to write; default: ``path`` with the suffix ``.msh``.

    Returns
    -------
    Path of the ``.msh`` file (format 4.1).
    """
    path = Path(path)
    out = path.with_suffix(".msh") if out is None else Path(out)
    if not path.is_file():
        raise ModelError(f"mesh '{path}'", "file not found")
    if order not in (1, 2):
        raise ModelError(f"mesh '{path}'", f"order must be 1 or 2, got {order}")
    if element not in ("tri", "quad"):
        raise ModelError(f"mesh '{path}'", f"element must be 'tri' or 'quad', got '{element}'")
    if size is not None and not size > 0:
        raise ModelError(f"mesh '{path}'", f"size must be > 0, got {size}")
    if path.suffix == ".py":
        return _run_script(path, out)
    options = {"General.Terminal": 0.0, "Mesh.SecondOrderIncomplete": 0.0,
               "Mesh.MshFileVersion": 4.1, "Mesh.Binary": 0.0}
    if element == "quad":
        options["Mesh.RecombineAll"] = 1.0
    if size is not None:
        options["Mesh.MeshSizeMax"] = float(size)
    with gmsh_session(options, set_now=False) as gmsh:
        gmsh.option.setNumber("General.Terminal", 0)
        try:
            gmsh.open(str(path))  # a new model (a running session keeps its others)
        except Exception as e:
            raise ModelError(f"mesh '{path}'", f"gmsh cannot read it: {e}") from None
        for k, v in options.items():  # over the file's own
            gmsh.option.setNumber(k, v)
        # a geometry with volumes is meshed in 3D (tetrahedra; hexahedra where it is
        # transfinite and recombined, or extruded with Recombine)
        gmsh.model.mesh.generate(3 if gmsh.model.getEntities(3) else 2)
        if order == 2:
            gmsh.model.mesh.setOrder(2)
        out.parent.mkdir(parents=True, exist_ok=True)
        gmsh.write(str(out))
    return out


def _run_script(path: Path, out: Path) -> Path:
    out.parent.mkdir(parents=True, exist_ok=True)
    proc = subprocess.run(
        [sys.executable, path.name, str(out.resolve())],
        cwd=path.parent,
        capture_output=True,
        text=True,
        check=False,
    )
    if proc.returncode != 0:
        tail = " ".join((proc.stderr or proc.stdout).strip().splitlines()[-3:])
        raise ModelError(f"mesh script '{path}'", f"failed (exit {proc.returncode}): {tail}")
    if not out.is_file():
        raise ModelError(f"mesh script '{path}'", f"did not write the mesh to {out} (argv[1])")
    return out


def read_mesh(
    path: str | os.PathLike, order: int = 1, element: str = "tri", size: float | None = None
) -> MeshFile:
    """Read a ``.msh`` file, or mesh a ``.geo`` file / gmsh script first (in a temporary
    directory: nothing is written next to it) and read the result."""
    path = Path(path)
    if path.suffix not in (".geo", ".py"):
        return read_msh(path)
    with tempfile.TemporaryDirectory(prefix="stepcontact-gmsh-") as tmp:
        msh = mesh_geo(path, order, element, size, out=Path(tmp) / f"{path.stem}.msh")
        mf = read_msh(msh)
    mf.path = path
    return mf


__all__ = [
    "CELL_KINDS",
    "CellBlock",
    "MeshFile",
    "PhysicalGroup",
    "mesh_geo",
    "read_mesh",
    "read_msh",
]
