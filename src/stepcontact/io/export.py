"""ParaView output: a result as a VTU time series (``.pvd``) or an XDMF time series.

One *frame* is written per selected reported state (the start, every event, every load-segment
start and end).  Each frame has two grids:

bodies (``NAME.pvd`` / ``FILE.xdmf``)
    The continuum cells of every body (VTK triangle, quadratic triangle, quad, quadratic quad,
    biquadratic quad for tri3, tri6, quad4, quad8, quad9), frame elements as line cells.
    Cells are oriented counter-clockwise (normals +z).  Point data ``displacement`` (3
    components, z = 0, m) and, when the model has frames, ``rotation`` (rad, NaN at nodes
    without a rotational DOF).  Cell data ``sigma_xx``, ``sigma_yy``, ``sigma_xy``,
    ``sigma_zz``, ``von_mises`` (Pa; NaN on frame cells, and at states whose stresses are
    neither stored nor recoverable — see below) and ``body`` (index into the model's bodies).
contact elements (``NAME_cfe.pvd`` / ``FILE_cfe.xdmf``)
    One line cell per CFE from its S+ point to its S− point (a degenerate line where they
    coincide).  Cell data ``N``, ``Q`` (N; N < 0 compression), ``sigma_n``, ``tau`` (Pa),
    ``un``, ``ut`` (m; u_n < 0 open gap), ``state`` (:class:`~stepcontact.enums.ContactState`
    codes: 0 open, 1 stick, 2 slip+, 3 slip−, 4 bonded, 5 closed), ``interface`` (index into the
    interface names), ``cfe`` (global index), ``local``, ``s`` (m), ``normal`` (S− → S+),
    ``area`` (m²), ``friction``, ``gap`` (m).  Point data ``displacement`` (m) only when the
    result knows the interpolation of the CFE ends (``cfe`` arrays ``plus_nodes``,
    ``plus_w``, ``minus_nodes``, ``minus_w``); without them, and for the CFEs on a fixed
    rigid obstacle (no S− nodes), the S− point is placed at x − g⁰ n.

3D results
----------
Bodies of tetrahedra and hexahedra (tet4, tet10, hex8, hex20, hex27) become VTK ``tetra``,
``tetra10``, ``hexahedron``, ``hexahedron20``, ``hexahedron27`` cells in VTK's node order (read
off a reference cell of scikit-fem, :func:`_vtk_node_order`), every cell of positive volume;
point data ``displacement`` (u_x, u_y, u_z, m), cell data ``sigma_xx``, ``sigma_yy``,
``sigma_zz``, ``sigma_xy``, ``sigma_yz``, ``sigma_xz``, their tensor ``stress`` (Pa, ParaView's
order XX, YY, ZZ, XY, YZ, XZ), ``von_mises`` and ``body``.  CFEs with two tangential
components (or of a 3D model) are points: one per CFE at its S+ point (a vertex cell), with
point data ``N``, ``Q1``, ``Q2``, ``Q_abs`` (N), ``Q_vector`` (Q1 t₁ + Q2 t₂, N, when the
result has 3D tangents), ``sigma_n``, ``tau_abs`` (Pa), ``un``, ``ut1``, ``ut2`` (m),
``state``, ``facet`` and ``vertex`` (where a faceted cone slips; −1 elsewhere), ``facets`` (the
cone's number of facets k), ``cone_ratio`` (|Q| / (f|N|)), ``normal``, ``interface``, ``cfe``,
``local``, ``area``, ``friction``, ``gap`` and the S+ point's ``displacement``.

Construction stages
-------------------
A staged result (``result.stage`` set) shows at each frame only what exists at its state.  A
VTU frame holds only the bodies built and the CFEs made by the state's stage (the other cells,
and the points only they use, are omitted: the mesh of a ``.pvd`` series may change between
frames; a frame before any CFE is made is an empty grid).  XDMF keeps one mesh for all frames:
there every cell is written and the cell array ``active`` (1 exists, 0 not yet built) selects
what to show (ParaView's Threshold filter).  Both formats add the cell arrays ``active`` and
``built_stage`` (the stage that built the body or made the CFE), the field data ``stage`` (in
XDMF also ``stage_name``) and list the stage names in the notes.  An unstaged result exports
exactly as without stages.

Time
----
ParaView needs increasing times.  The time of a frame is the load-path parameter
``t = Σ |Δλ|`` accumulated along the load program (:func:`load_path_parameter`): for a state
of segment k, t = Σ_{j<k} |λ_end,j − λ_start,j| + |λ − λ_start,k|, so t = λ for a single
segment starting at λ = 0 and t grows through unloading segments too.  Several states can share
one t (simultaneous events, a segment end and the next segment's start); the frame times are
then separated by ``TIME_SEPARATION`` × max(1, t_max) so that every frame keeps its own time
step.  Each VTU frame carries field data ``TimeValue`` (the frame time), ``load_path_t``
(exact t), ``lam`` (λ), ``segment``, ``state`` (reported-state index), ``state_kind`` (0 start,
1 segment start, 2 event, 3 segment end) and ``factors`` (load factors of all patterns).  XDMF
has no per-frame field data that meshio can read back: there the same values are
``<Information>`` elements of each time grid.

Fields
------
A run stores displacement fields and stresses only at the start, the segment starts and ends
and its last state (``store_fields="ends"``, the default).  The fields of the other states are
exact from their contact unknowns: a result in memory (or one given its model with
``res.recover_fields(model)``) recomputes every missing state of the export, in blocks of
states, each block with one multi-right-hand-side solve.  A result loaded from a file without
its model exports the states that have stored fields and logs which states it skipped and how
to get them (``stepcontact export --model MODEL.toml`` on the command line).

Writes are atomic: everything is written into a hidden temporary directory next to the target
and then renamed into place, so an interrupted export never leaves a half-written series.  A
full disk is a :class:`~stepcontact.io.atomic.WriteError` naming the export (the free space is
checked against the size of the first frame times the frames, and the HDF5 file of an XDMF
export is made in memory and written with plain file I/O), never a crash; the previous files
stay intact.

Example
-------
>>> import stepcontact as sc
>>> res = sc.solve_static(model)                                # doctest: +SKIP
>>> sc.export_vtu(res, "out/paraview")                          # doctest: +SKIP
PosixPath('out/paraview/result.pvd')
>>> sc.export_xdmf(res, "out/result.xdmf", states="ends")      # doctest: +SKIP
PosixPath('out/result.xdmf')
"""

from __future__ import annotations

import functools
import logging
import os
import re
import shutil
import tempfile
import uuid
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from xml.etree import ElementTree as ET
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np
from meshio.xdmf import TimeSeriesWriter
from meshio.xdmf.common import meshio_to_xdmf_type, meshio_type_to_xdmf_index, numpy_to_xdmf_dtype

from stepcontact.enums import FACET_SLIP, VERTEX_SLIP, ContactState
from stepcontact.io.atomic import check_free_space, write_bytes, write_error
from stepcontact.model.mesh import REVERSED_NODE_ORDER
from stepcontact.results.result import StaticResult

_log = logging.getLogger(__name__)

#: relative separation of frame times that would otherwise coincide (× max(1, t_max))
TIME_SEPARATION = 1e-9

#: memory of the displacements recomputed at once for an export (bytes): the states of a
#: block are recovered with one multi-right-hand-side solve
RECOVERY_BLOCK_BYTES = 256 * 2**20

#: codes of the ``state_kind`` field data
STATE_KINDS = {"start": 0, "segment_start": 1, "event": 2, "segment_end": 3, "dynamics": 4}

StateSelection = str | int | Sequence[int] | np.ndarray | None

# element name of a body -> meshio cell type
_ELEMENT_TYPES = {
    "tri3": "triangle",
    "tri6": "triangle6",
    "quad4": "quad",
    "quad8": "quad8",
    "quad9": "quad9",
    "tet4": "tetra",
    "tet10": "tetra10",
    "hex8": "hexahedron",
    "hex20": "hexahedron20",
    "hex27": "hexahedron27",
    "frame2": "line",
}
# nodes per cell of a continuum body -> meshio cell type (bodies with other element names)
_NODES_TYPES = {3: "triangle", 6: "triangle6", 4: "quad", 8: "quad8", 9: "quad9"}
_NODES_TYPES_3D = {4: "tetra", 10: "tetra10", 8: "hexahedron", 20: "hexahedron20",
                   27: "hexahedron27"}
_NODES_PER_CELL = {"triangle": 3, "triangle6": 6, "quad": 4, "quad8": 8, "quad9": 9, "line": 2,
                   "tetra": 4, "tetra10": 10, "hexahedron": 8, "hexahedron20": 20,
                   "hexahedron27": 27}
#: VTK's parametric coordinates of the nodes of its 3D cells, in VTK's node order (corners,
#: mid-edge nodes, mid-face nodes, centre; vtkQuadraticTetra, vtkQuadraticHexahedron,
#: vtkTriQuadraticHexahedron): the cell's node order is read off a reference cell with them
_HEX_PCOORDS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1),
                (0, 1, 1),
                (.5, 0, 0), (1, .5, 0), (.5, 1, 0), (0, .5, 0), (.5, 0, 1), (1, .5, 1),
                (.5, 1, 1), (0, .5, 1), (0, 0, .5), (1, 0, .5), (1, 1, .5), (0, 1, .5),
                (0, .5, .5), (1, .5, .5), (.5, 0, .5), (.5, 1, .5), (.5, .5, 0), (.5, .5, 1),
                (.5, .5, .5)]
_VTK_PCOORDS = {
    "tetra10": [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (.5, 0, 0), (.5, .5, 0),
                (0, .5, 0), (0, 0, .5), (.5, 0, .5), (0, .5, .5)],
    "hexahedron": _HEX_PCOORDS[:8],
    "hexahedron20": _HEX_PCOORDS[:20],
    "hexahedron27": _HEX_PCOORDS,
}
_VTK_PCOORDS["tetra"] = _VTK_PCOORDS["tetra10"][:4]
# scikit-fem's P2 / serendipity / Q2 node order (corners, edges 01 12 20|23 30, centre) is
# VTK's order for quadratic triangles and (bi)quadratic quads
_REVERSE = REVERSED_NODE_ORDER
_STRESS_NAMES = ("sigma_xx", "sigma_yy", "sigma_xy", "sigma_zz")
#: a 3D body's stress components (:data:`stepcontact.fem.continuum.STRESS_COMPONENTS_3D`)
_STRESS_NAMES_3D = ("sigma_xx", "sigma_yy", "sigma_zz", "sigma_xy", "sigma_yz", "sigma_xz")
_CFE_END_KEYS = ("plus_nodes", "plus_w", "minus_nodes", "minus_w")


# --------------------------------------------------------------------------------------------
# frames: which states, at which times
# --------------------------------------------------------------------------------------------
def load_path_parameter(result: StaticResult) -> np.ndarray:
    """Load-path parameter t = Σ|Δλ| of every reported state (dimensionless, like λ).

    For a state of segment k: t = Σ_{j<k} |λ_end,j − λ_start,j| + |λ − λ_start,k|.  Within a
    segment λ moves monotonically from its start to its end, so this is the cumulative sum of
    |Δλ| along the states, continued across segment changes; t = λ for a single segment that
    starts at λ = 0.  Results without a usable load program fall back to Σ|Δλ| between
    consecutive states (t = 0 at state 0).

    Returns
    -------
    ndarray (n_states,)
    """
    lam = np.asarray(result.lam, dtype=float)
    seg = np.asarray(result.segment, dtype=np.int64)
    segs = list(result.segments)
    if lam.size == 0:
        return np.zeros(0)
    if segs and seg.min() >= 0 and seg.max() < len(segs):
        start = np.array([float(s[1]) for s in segs])
        end = np.array([float(s[2]) for s in segs])
        before = np.r_[0.0, np.cumsum(np.abs(end - start))]
        return before[seg] + np.abs(lam - start[seg])
    return np.r_[0.0, np.cumsum(np.abs(np.diff(lam)))]


def frame_times(t: np.ndarray) -> np.ndarray:
    """Strictly increasing frame times from non-decreasing values ``t``.

    A value that does not exceed its predecessor by ``TIME_SEPARATION`` × max(1, max|t|) is
    moved up to that separation; all other values are kept exactly.
    """
    t = np.asarray(t, dtype=float)
    out = t.copy()
    if out.size == 0:
        return out
    delta = TIME_SEPARATION * max(1.0, float(np.max(np.abs(t))))
    for k in range(1, len(out)):  # loop over frames
        out[k] = max(out[k], out[k - 1] + delta)
    return out


def _parse_selection(result: StaticResult, states: StateSelection) -> np.ndarray:
    """State indices named by ``states`` (sorted, unique; may lack displacement fields)."""
    n = result.n_states
    kind = np.asarray(result.kind).astype(str)
    if states is None:
        states = "all"
    if isinstance(states, str):
        key = states.strip().lower()
        if key == "stored":
            return np.array(sorted(k for k in result.fields if 0 <= k < n), dtype=np.int64)
        if key == "all":
            return np.arange(n, dtype=np.int64)
        if key == "events":
            return np.flatnonzero(kind == "event").astype(np.int64)
        if key == "ends":
            return np.flatnonzero(kind == "segment_end").astype(np.int64)
        try:
            states = [int(v) for v in key.split(",") if v.strip()]
        except ValueError:
            raise ValueError(
                f"states '{states}': use 'stored', 'all', 'events', 'ends' or state indices "
                "such as '0,3,-1'"
            ) from None
    idx = np.atleast_1d(np.asarray(states))
    if idx.size and idx.dtype.kind not in "iu":
        raise ValueError(f"states: expected integer state indices, got {idx.dtype}")
    idx = idx.astype(np.int64)
    bad = (idx < -n) | (idx >= n)
    if bad.any():
        raise ValueError(
            f"state {int(idx[bad][0])} does not exist (the result has {n} states, 0…{n - 1})"
        )
    return np.unique(np.where(idx < 0, idx + n, idx))


def select_states(
    result: StaticResult, states: StateSelection = None
) -> tuple[np.ndarray, np.ndarray]:
    """The states to export and the selected states skipped for lack of displacements.

    Parameters
    ----------
    result : StaticResult
    states : None, str, int or sequence of int
        ``None`` or ``"all"``: every reported state; ``"stored"``: every state with a stored
        displacement field (``result.fields``); ``"events"``: the event states; ``"ends"``:
        the load-segment ends; state indices (negative count from the end), also as a string
        ``"0,3,-1"``.  States are exported in increasing order.

    Returns
    -------
    (exported, skipped) : two int arrays
        ``skipped`` are selected states whose displacements were neither stored nor can be
        recomputed (a result loaded from a file has only its stored fields until
        ``result.recover_fields(model)``).
    """
    idx = _parse_selection(result, states)
    recover = getattr(result, "_recover", None) is not None
    have = np.array([recover or int(i) in result.fields for i in idx], dtype=bool)
    return idx[have], idx[~have]


@dataclass(frozen=True)
class _Frames:
    states: np.ndarray  #: exported state indices
    t: np.ndarray  #: load-path parameter of those states
    time: np.ndarray  #: strictly increasing frame times
    skipped: np.ndarray  #: selected states without displacements


#: how to get the states a result loaded from a file does not store
HOW_TO_RECOVER = (
    "give the result its model with result.recover_fields(model) (command line: "
    "stepcontact export --model MODEL.toml) to recompute them exactly, or re-run with "
    "store_fields='all'"
)


def _frames(result: StaticResult, states: StateSelection) -> _Frames:
    kept, skipped = select_states(result, states)
    if skipped.size:
        _log.warning(
            "skipped %d selected state(s) without stored displacements (%s): the result "
            "stores fields only at states %s; %s", skipped.size, _short_list(skipped),
            _short_list(np.array(sorted(result.fields), dtype=np.int64)) or "none",
            HOW_TO_RECOVER,
        )
    if kept.size == 0:
        raise ValueError(
            "no selected state has stored displacements: nothing to export (select states "
            f"with fields, or {HOW_TO_RECOVER})"
        )
    t = load_path_parameter(result)[kept]
    return _Frames(kept, t, frame_times(t), skipped)


def _short_list(idx: np.ndarray, limit: int = 10) -> str:
    items = [str(int(i)) for i in idx[:limit]]
    return ", ".join(items) + (", …" if idx.size > limit else "")


def _field_data(result: StaticResult, i: int, t: float, time: float) -> dict[str, np.ndarray]:
    kind = str(np.asarray(result.kind).astype(str)[i])
    return {
        "TimeValue": np.array([time]),
        "load_path_t": np.array([t]),
        "lam": np.array([float(result.lam[i])]),
        "segment": np.array([int(result.segment[i])], dtype=np.int64),
        "state": np.array([i], dtype=np.int64),
        "state_kind": np.array([STATE_KINDS.get(kind, -1)], dtype=np.int64),
        "factors": np.asarray(result.factors[i], dtype=float).ravel(),
    } | ({} if getattr(result, "stage", None) is None
         else {"stage": np.array([int(result.stage[i])], dtype=np.int64)})


# --------------------------------------------------------------------------------------------
# grids
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _BodyGrid:
    points: np.ndarray  #: (n_nodes, 3), m
    blocks: list[tuple[str, np.ndarray]]  #: one (meshio type, connectivity) per body
    names: list[str]
    continuum: list[bool]
    dof_of: np.ndarray  #: (n_nodes, k) global dof of ux, uy, rz (3D: ux, uy, uz[, rx, ry, rz])
    dim: int = 2  #: 2: plane model (z = 0); 3: solids


@dataclass(frozen=True)
class _CfeGrid:
    points: np.ndarray  #: (2m, 3): S+ ends, then S− ends, m; (m, 3) S+ points (``vertex``)
    lines: np.ndarray  #: (m, 2) line cells; (m, 1) vertex cells
    nodes: np.ndarray | None  #: (2m, J) interpolation nodes of the ends (-1 padding; vertex: m)
    weights: np.ndarray | None  #: (2m, J)
    #: "line" (2D: S+ to S−, the data cell data) or "vertex" (3D: one point per CFE at its S+
    #: point, the data point data)
    kind: str = "line"


def _cell_type(body: dict, nodes_per_cell: int, dim: int = 2) -> str:
    element = str(body.get("element", ""))
    kind = str(body.get("kind", ""))
    by_nodes = _NODES_TYPES if dim == 2 else _NODES_TYPES_3D
    if kind == "frame":
        ctype = "line"
    elif element in _ELEMENT_TYPES:
        ctype = _ELEMENT_TYPES[element]
    elif nodes_per_cell in by_nodes and kind in ("continuum", ""):
        ctype = by_nodes[nodes_per_cell]
    else:
        raise ValueError(f"body '{body.get('name')}': cannot export element '{element}'")
    if _NODES_PER_CELL[ctype] != nodes_per_cell:
        raise ValueError(
            f"body '{body.get('name')}': element '{element}' with {nodes_per_cell} nodes per "
            "cell"
        )
    return ctype


def _counter_clockwise(ctype: str, cells: np.ndarray, xy: np.ndarray) -> np.ndarray:
    """``cells`` with every clockwise cell's node order reversed (positive signed area)."""
    if ctype not in _REVERSE or cells.size == 0:
        return cells
    n_corner = 3 if ctype.startswith("triangle") else 4
    c = xy[cells[:, :n_corner]]  # (n_el, n_corner, 2)
    nxt = np.roll(c, -1, axis=1)
    area2 = np.sum(c[..., 0] * nxt[..., 1] - nxt[..., 0] * c[..., 1], axis=1)
    return np.where((area2 < 0)[:, None], cells[:, _REVERSE[ctype]], cells)


#: the element whose scikit-fem node order a VTK 3D cell type is read off
_SKFEM_ELEMENT = {"tetra": "tet4", "tetra10": "tet10", "hexahedron": "hex8",
                  "hexahedron20": "hex20", "hexahedron27": "hex27"}


@functools.cache
def _vtk_node_order(ctype: str) -> tuple[np.ndarray, np.ndarray]:
    """The node order of a VTK 3D cell from scikit-fem's (the order of a body's ``cells``):
    ``cells[:, order]`` is VTK's, and ``vtk[:, mirror]`` the same cell mirrored (a cell of
    negative volume made positive).

    Read off one reference cell of scikit-fem (the unit cube, a tetrahedron of it): VTK's
    node v sits at the parametric point :data:`_VTK_PCOORDS` [v] of the cell's corners (for a
    hexahedron the cube's own coordinates; for a tetrahedron x0 + Σ ξ_j (x_j − x0)) and is
    the scikit-fem node there."""
    from skfem import Basis, MeshHex, MeshTet

    from stepcontact.model.elements import scalar_element

    tet = ctype.startswith("tetra")
    unit = np.array([0.0, 1.0])
    mesh = (MeshTet if tet else MeshHex).init_tensor(unit, unit, unit)
    basis = Basis(mesh, scalar_element(_SKFEM_ELEMENT[ctype]))
    X = basis.doflocs.T[basis.element_dofs[:, 0]]  # (n, 3) the reference cell's nodes
    pc = np.array(_VTK_PCOORDS[ctype], dtype=float)
    target = X[0] + pc @ (X[1:4] - X[0]) if tet else pc
    dist = np.linalg.norm(target[:, None, :] - X[None, :, :], axis=2)
    order = dist.argmin(axis=1)
    if dist.min(axis=1).max() > 1e-12 or sorted(order) != list(range(len(X))):
        raise RuntimeError(f"cannot match scikit-fem's {ctype} nodes to VTK's")  # pragma: no cover
    flipped = pc[:, [1, 0, 2]] if tet else pc * [1, 1, -1] + [0, 0, 1]
    mirror = np.array([int(np.flatnonzero(np.all(pc == q, axis=1))[0]) for q in flipped])
    return order, mirror


def _vtk_cells_3d(ctype: str, cells: np.ndarray, points: np.ndarray) -> np.ndarray:
    """A body's 3D cells (scikit-fem's node order) in VTK's node order, every cell of positive
    volume (a mirrored cell's nodes reordered)."""
    order, mirror = _vtk_node_order(ctype)
    vtk = cells[:, order]
    if vtk.size == 0:
        return vtk
    c = points[vtk[:, [0, 1, 3, 4] if ctype.startswith("hexa") else [0, 1, 2, 3]]]
    vol = np.einsum("ij,ij->i", np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]), c[:, 3] - c[:, 0])
    return np.where((vol < 0)[:, None], vtk[:, mirror], vtk)


def _body_grid(result: StaticResult) -> _BodyGrid:
    geo = result.geometry or {}
    if "points" not in geo or "dof_of" not in geo or not geo.get("bodies"):
        raise ValueError("the result has no geometry (points, dof_of, bodies): cannot export")
    pts = np.asarray(geo["points"], dtype=float)
    dim = 3 if pts.ndim == 2 and pts.shape[1] == 3 else 2
    xy = pts.reshape(-1, dim)
    points = xy if dim == 3 else np.column_stack([xy, np.zeros(len(xy))])
    dof_of = np.asarray(geo["dof_of"], dtype=np.int64)
    blocks, names, continuum = [], [], []
    for body in geo["bodies"]:
        cells = np.asarray(body["cells"], dtype=np.int64)
        cells = cells.reshape(len(cells), -1)
        ctype = _cell_type(body, cells.shape[1], dim)
        if ctype in _VTK_PCOORDS:
            cells = _vtk_cells_3d(ctype, cells, points)
        elif dim == 2:
            cells = _counter_clockwise(ctype, cells, xy)
        blocks.append((ctype, cells))
        names.append(str(body["name"]))
        continuum.append(ctype != "line")
    return _BodyGrid(points, blocks, names, continuum, dof_of, dim)


def _cfe_points(result: StaticResult) -> _CfeGrid:
    """3D CFEs: one point per CFE at its S+ point (``cfe["x"]``, 3 coordinates), a vertex
    cell each; the interpolation of the S+ end when the result knows it (its displacement)."""
    cfe, m = result.cfe, result.m
    x = np.asarray(cfe["x"], dtype=float).reshape(m, -1)
    points = x if x.shape[1] == 3 else np.column_stack([x[:, :2], np.zeros(m)])
    nodes = w = None
    if "plus_nodes" in cfe and "plus_w" in cfe:
        nodes = np.asarray(cfe["plus_nodes"]).astype(np.int64).reshape(m, -1)
        w = np.where(nodes >= 0, np.asarray(cfe["plus_w"], dtype=float).reshape(m, -1), 0.0)
    return _CfeGrid(points, np.arange(m, dtype=np.int64)[:, None], nodes, w, "vertex")


def _cfe_grid(result: StaticResult, body: _BodyGrid) -> _CfeGrid:
    if body.dim == 3 or result.n_t > 1:
        return _cfe_points(result)
    xy = body.points[:, :2]
    cfe = result.cfe
    m = result.m
    plus = np.asarray(cfe["x"], dtype=float).reshape(m, 2)
    if all(k in cfe for k in _CFE_END_KEYS):
        # the two ends may have different widths (a mortar CFE's S− end has more nodes)
        ends_n = [np.asarray(cfe[k]).astype(np.int64).reshape(m, -1)
                  for k in ("plus_nodes", "minus_nodes")]
        ends_w = [np.asarray(cfe[k]).astype(float).reshape(m, -1) for k in ("plus_w", "minus_w")]
        width = max(a.shape[1] for a in ends_n)
        nodes = np.concatenate([np.pad(a, ((0, 0), (0, width - a.shape[1])), constant_values=-1)
                                for a in ends_n])
        w = np.concatenate([np.pad(a, ((0, 0), (0, width - a.shape[1]))) for a in ends_w])
        w = np.where(nodes >= 0, w, 0.0)
        ends = np.einsum("pj,pjc->pc", w, xy[np.maximum(nodes, 0)])
        ends[:m] = plus
        ground = ~np.any(nodes[m:] >= 0, axis=1)  # S− end on a fixed rigid obstacle: no nodes
        if ground.any():
            gap = np.asarray(cfe.get("gap", np.zeros(m)), dtype=float).reshape(m)
            normal = np.asarray(cfe["normal"], dtype=float).reshape(m, 2)
            ends[m:][ground] = plus[ground] - gap[ground, None] * normal[ground]
    else:
        nodes = w = None
        gap = np.asarray(cfe.get("gap", np.zeros(m)), dtype=float).reshape(m)
        normal = np.asarray(cfe["normal"], dtype=float).reshape(m, 2)
        ends = np.concatenate([plus, plus - gap[:, None] * normal])
    points = np.column_stack([ends, np.zeros(2 * m)])
    lines = np.column_stack([np.arange(m), m + np.arange(m)]).astype(np.int64)
    return _CfeGrid(points, lines, nodes, w)


# --------------------------------------------------------------------------------------------
# frame data
# --------------------------------------------------------------------------------------------
def _nodal_displacement(grid: _BodyGrid, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(n_nodes, 3) displacements (z = 0 in 2D), m, and the rotations, rad (NaN: no DOF):
    (n_nodes,) rz in 2D, (n_nodes, 3) rx, ry, rz in 3D (space frames; none: all NaN)."""
    dof = grid.dof_of
    disp = np.zeros((len(dof), 3))
    for c in range(grid.dim):
        disp[:, c] = np.where(dof[:, c] >= 0, u[np.maximum(dof[:, c], 0)], 0.0)
    if grid.dim == 3:
        r = dof[:, 3:6] if dof.shape[1] >= 6 else np.full((len(dof), 3), -1)
    else:
        r = dof[:, 2] if dof.shape[1] > 2 else np.full(len(dof), -1)
    rot = np.where(r >= 0, u[np.maximum(r, 0)], np.nan)
    return disp, rot


def von_mises(stress: np.ndarray) -> np.ndarray:
    """Von Mises stress (Pa) of (n, 4) stresses σxx, σyy, σxy, σzz (2D) or of (n, 6) stresses
    σxx, σyy, σzz, σxy, σyz, σxz (3D), Pa:
    √(½ ((σxx − σyy)² + (σyy − σzz)² + (σzz − σxx)²) + 3 (σxy² + σyz² + σxz²))."""
    if stress.shape[1] == 6:
        sxx, syy, szz, sxy, syz, sxz = (stress[:, j] for j in range(6))
    else:
        sxx, syy, sxy, szz = (stress[:, j] for j in range(4))
        syz = sxz = 0.0
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2)
                   + 3 * (sxy**2 + syz**2 + sxz**2))


def _body_data(
    grid: _BodyGrid, i: int, disp: np.ndarray, rot: np.ndarray,
    at_state: dict[str, np.ndarray],
) -> tuple[dict[str, np.ndarray], dict[str, list[np.ndarray]]]:
    point_data = {"displacement": disp}
    if np.any(grid.dof_of[:, (3 if grid.dim == 3 else 2):] >= 0):
        point_data["rotation"] = rot
    names = _STRESS_NAMES_3D if grid.dim == 3 else _STRESS_NAMES
    cell_data: dict[str, list[np.ndarray]] = {k: [] for k in (*names, "von_mises")}
    if grid.dim == 3:  # the symmetric tensor in ParaView's order XX, YY, ZZ, XY, YZ, XZ
        cell_data["stress"] = []
    cell_data["body"] = []
    for b, ((_, cells), name, cont) in enumerate(
        zip(grid.blocks, grid.names, grid.continuum, strict=True)
    ):
        s = np.full((len(cells), len(names)), np.nan)
        if cont and name in at_state:
            given = np.asarray(at_state[name], dtype=float)
            if given.shape != s.shape:
                raise ValueError(
                    f"stresses of body '{name}' at state {i}: shape {given.shape}, expected "
                    f"{s.shape}"
                )
            s = given
        for j, key in enumerate(names):
            cell_data[key].append(s[:, j].copy())
        cell_data["von_mises"].append(von_mises(s))
        if grid.dim == 3:
            cell_data["stress"].append(s.copy())
        cell_data["body"].append(np.full(len(cells), b, dtype=np.int32))
    return point_data, cell_data


def _cfe_static(result: StaticResult) -> dict[str, np.ndarray]:
    cfe, m = result.cfe, result.m

    def get(key: str, default: float) -> np.ndarray:
        return np.asarray(cfe.get(key, np.full(m, default)), dtype=float).reshape(m)

    normal = np.asarray(cfe["normal"], dtype=float).reshape(m, 2)
    return {
        "interface": np.asarray(cfe["interface"]).astype(np.int32).reshape(m),
        "cfe": np.arange(m, dtype=np.int32),
        "local": np.asarray(cfe.get("local", np.arange(m))).astype(np.int32).reshape(m),
        "s": get("s", np.nan),
        "normal": np.column_stack([normal, np.zeros(m)]),
        "area": get("area", np.nan),
        "friction": get("friction", np.nan),
        "gap": get("gap", np.nan),
    }


def _cfe_data(
    result: StaticResult, grid: _CfeGrid, static: dict[str, np.ndarray], i: int,
    disp: np.ndarray,
) -> tuple[dict[str, np.ndarray], dict[str, list[np.ndarray]]]:
    point_data = {}
    if grid.nodes is not None and grid.weights is not None:
        point_data["displacement"] = np.einsum(
            "pj,pjc->pc", grid.weights, disp[np.maximum(grid.nodes, 0)]
        )
    per_state = {
        "N": result.N[i], "Q": result.Q[i], "sigma_n": result.sigma_n[i], "tau": result.tau[i],
        "un": result.un[i], "ut": result.ut[i],
    }
    cell = {k: np.asarray(v, dtype=float).copy() for k, v in per_state.items()}
    cell["state"] = np.asarray(result.state[i]).astype(np.int32)
    cell |= static
    return point_data, {k: [v] for k, v in cell.items()}


def _cfe_static_3d(result: StaticResult) -> dict[str, np.ndarray]:
    """The per-CFE arrays of 3D CFEs that do not change along the path (point data)."""
    cfe, m = result.cfe, result.m

    def get(key: str, default: float) -> np.ndarray:
        return np.asarray(cfe.get(key, np.full(m, default)), dtype=float).reshape(m)

    normal = np.asarray(cfe.get("normal", np.full((m, 3), np.nan)), dtype=float).reshape(m, -1)
    out = {
        "interface": np.asarray(cfe["interface"]).astype(np.int32).reshape(m),
        "cfe": np.arange(m, dtype=np.int32),
        "local": np.asarray(cfe.get("local", np.arange(m))).astype(np.int32).reshape(m),
        "normal": normal if normal.shape[1] == 3 else np.column_stack([normal[:, :2],
                                                                       np.zeros(m)]),
        "area": get("area", np.nan),
        "friction": get("friction", np.nan),
        "gap": get("gap", np.nan),
    }
    if "facets" in cfe:  # a faceted Coulomb cone: its number of facets k
        out["facets"] = np.full(m, int(cfe["facets"]), dtype=np.int32)
    return out


def _tangents_3d(result: StaticResult) -> np.ndarray | None:
    """(m, n_t, 3) the CFEs' tangents t₁[, t₂] in global coordinates, or None when the result
    has no 3D tangent vectors (t₂ = n × t₁ when only t₁ is stored: the basis (t₁, t₂, n) is
    right-handed)."""
    cfe, m, n_t = result.cfe, result.m, result.n_t
    t1 = np.asarray(cfe.get("tangent", np.zeros((m, 0))), dtype=float).reshape(m, -1)
    n = np.asarray(cfe.get("normal", np.zeros((m, 0))), dtype=float).reshape(m, -1)
    if t1.shape[1] != 3 or not np.all(np.isfinite(t1)):
        return None
    if n_t == 1:
        return t1[:, None, :]
    t2 = np.asarray(cfe["tangent2"], dtype=float).reshape(m, 3) if "tangent2" in cfe else (
        np.cross(n, t1) if n.shape[1] == 3 else None)
    return None if t2 is None else np.stack([t1, t2], axis=1)


def _cfe_point_data(
    result: StaticResult, grid: _CfeGrid, static: dict[str, np.ndarray], i: int,
    disp: np.ndarray, tangents: np.ndarray | None,
) -> tuple[dict[str, np.ndarray], dict[str, list[np.ndarray]]]:
    """Point data of the 3D CFEs at state ``i``: forces N, Q1 … Q_(n_t), |Q| (N), the
    tangential force as a vector (N, with 3D tangents), σ_n, |τ| (Pa), u_n, u_t1 … (m), the
    state code with the facet or vertex a faceted cone slips on, the true-cone ratio
    |Q| / (f |N|) and the S+ point's displacement (m, when its interpolation is known)."""
    Qt = np.asarray(result.Q_t[i], dtype=float)  # (m, n_t)
    ut = np.asarray(result.ut_t[i], dtype=float)
    area = np.asarray(result.cfe["area"], dtype=float)
    q = np.linalg.norm(Qt, axis=1)
    st = np.asarray(result.state[i]).astype(np.int32)
    pd: dict[str, np.ndarray] = {"N": np.asarray(result.N[i], dtype=float).copy()}
    for j in range(Qt.shape[1]):
        pd[f"Q{j + 1}"] = Qt[:, j].copy()
    pd["Q_abs"] = q
    if tangents is not None:
        pd["Q_vector"] = np.einsum("kj,kjc->kc", Qt, tangents)
    pd["sigma_n"] = pd["N"] / area
    pd["tau_abs"] = q / area
    pd["un"] = np.asarray(result.un[i], dtype=float).copy()
    for j in range(ut.shape[1]):
        pd[f"ut{j + 1}"] = ut[:, j].copy()
    pd["state"] = st
    on_facet = (st >= FACET_SLIP) & (st < VERTEX_SLIP)
    pd["facet"] = np.where(on_facet, st - FACET_SLIP, -1).astype(np.int32)
    pd["vertex"] = np.where(st >= VERTEX_SLIP, st - VERTEX_SLIP, -1).astype(np.int32)
    pd["cone_ratio"] = np.asarray(result.cone_ratio[i], dtype=float)
    if grid.nodes is not None and grid.weights is not None:
        pd["displacement"] = np.einsum("pj,pjc->pc", grid.weights,
                                       disp[np.maximum(grid.nodes, 0)])
    return pd | static, {}


_Data = tuple[dict[str, np.ndarray], dict[str, list[np.ndarray]]]


def _state_fields(
    result: StaticResult, states: list[int], ndof: int
) -> Iterator[tuple[np.ndarray, dict[str, np.ndarray]]]:
    """(displacement vector, {body: stresses}) of every state of ``states``, in order: stored,
    or recomputed in blocks of states (one multi-right-hand-side solve per block).  Stresses
    that are neither stored nor recoverable are left out (NaN in the files)."""
    recover = getattr(result, "_recover", None)
    with_stresses = recover is not None and hasattr(recover, "stresses")
    block = max(1, RECOVERY_BLOCK_BYTES // (8 * max(ndof, 1)))
    for a in range(0, len(states), block):
        part = states[a : a + block]
        U = result.displacements(part)
        if with_stresses:
            stresses = result.stresses_at(part, displacements=U)
        else:
            stresses = {i: result.stresses.get(i, {}) for i in part}
        for i, u in zip(part, U, strict=True):
            yield np.asarray(u, dtype=float), stresses[i]


def _iter_frames(
    result: StaticResult, frames: _Frames, body: _BodyGrid, cfe: _CfeGrid | None
) -> Iterator[tuple[int, float, float, _Data, _Data | None]]:
    """Per frame: (state, t, time, body point/cell data, CFE point/cell data or None)."""
    vertex = cfe is not None and cfe.kind == "vertex"
    static = ({} if cfe is None else _cfe_static_3d(result) if vertex else _cfe_static(result))
    tangents = _tangents_3d(result) if vertex else None
    built = _built_stage(result, body.names) if _staged(result) else None
    states = frames.states.tolist()
    fields = _state_fields(result, states, int(body.dof_of.max(initial=-1)) + 1)
    for i, t, time, (u, at_state) in zip(states, frames.t, frames.time, fields, strict=True):
        disp, rot = _nodal_displacement(body, u)
        bpd, bcd = _body_data(body, i, disp, rot, at_state)
        cdata = (None if cfe is None
                 else _cfe_point_data(result, cfe, static, i, disp, tangents) if vertex
                 else _cfe_data(result, cfe, static, i, disp))
        if built is not None:
            _add_stage_data(result, i, body, built, bcd, cdata, vertex)
        yield i, float(t), float(time), (bpd, bcd), cdata


# --------------------------------------------------------------------------------------------
# construction stages: what exists at a state
# --------------------------------------------------------------------------------------------
def _staged(result: StaticResult) -> bool:
    return getattr(result, "stage", None) is not None


def _built_stage(result: StaticResult, names: list[str]) -> tuple[np.ndarray, np.ndarray]:
    """The stage at which every body (in the order of ``names``) and every CFE is built or
    made (index into ``result.stage_names``; -1: never in the run)."""
    built = np.array([next((k for k, b in enumerate(result.stage_bodies) if n in b), -1)
                      for n in names], dtype=np.int32)
    acts = np.asarray(result.stage_cfes, dtype=bool).reshape(-1, result.m)
    first = np.where(acts.any(axis=0), acts.argmax(axis=0), -1).astype(np.int32)
    return built, first


def _add_stage_data(
    result: StaticResult, i: int, body: _BodyGrid, built: tuple[np.ndarray, np.ndarray],
    bcd: dict[str, list[np.ndarray]], cdata: _Data | None, vertex: bool = False,
) -> None:
    """Cell data ``active`` (1 where the body / CFE exists at state ``i``) and
    ``built_stage`` of a staged result, added in place (3D CFEs: as point data)."""
    here = result.active_bodies(i)
    bcd["active"] = [np.full(len(c), int(n in here), dtype=np.int8)
                     for (_, c), n in zip(body.blocks, body.names, strict=True)]
    bcd["built_stage"] = [np.full(len(c), b, dtype=np.int32)
                          for (_, c), b in zip(body.blocks, built[0], strict=True)]
    if cdata is not None and vertex:
        cdata[0]["active"] = result.active_cfes(i).astype(np.int8)
        cdata[0]["built_stage"] = built[1]
    elif cdata is not None:
        cdata[1]["active"] = [result.active_cfes(i).astype(np.int8)]
        cdata[1]["built_stage"] = [built[1]]


def _keep_cells(
    points: np.ndarray, blocks: list[tuple[str, np.ndarray]], keep: list[bool], data: _Data
) -> tuple[np.ndarray, list[tuple[str, np.ndarray]], dict, dict]:
    """The grid without the blocks not in ``keep`` and without the points only they use
    (points of no cell stay); point and cell data cut to match."""
    point_data, cell_data = data
    used_off = np.zeros(len(points), bool)
    used_on = np.zeros(len(points), bool)
    for (_, cells), k in zip(blocks, keep, strict=True):
        (used_on if k else used_off)[cells.ravel()] = True
    stay = used_on | ~used_off
    new_id = np.cumsum(stay) - 1
    out_blocks = [(t, new_id[c]) for (t, c), k in zip(blocks, keep, strict=True) if k]
    pd = {key: np.asarray(v)[stay] for key, v in point_data.items()}
    cd = {key: [v for v, k in zip(vs, keep, strict=True) if k] for key, vs in cell_data.items()}
    return points[stay], out_blocks, pd, cd


def _keep_cfes(grid: _CfeGrid, keep: np.ndarray, data: _Data
               ) -> tuple[np.ndarray, list[tuple[str, np.ndarray]], dict, dict]:
    """The CFE grid of the CFEs in ``keep`` (their two end points each; 3D: their point)."""
    m = len(grid.lines)
    k = np.flatnonzero(keep)
    if grid.kind == "vertex":
        pd = {key: np.asarray(v)[k] for key, v in data[0].items()}
        return grid.points[k], [("vertex", np.arange(k.size, dtype=np.int64)[:, None])], pd, {}
    rows = np.r_[k, m + k]
    lines = np.column_stack([np.arange(k.size), k.size + np.arange(k.size)]).astype(np.int64)
    pd = {key: np.asarray(v)[rows] for key, v in data[0].items()}
    cd = {key: [np.asarray(v[0])[k]] for key, v in data[1].items()}
    return grid.points[rows], [("line", lines)], pd, cd


# --------------------------------------------------------------------------------------------
# VTU + PVD
# --------------------------------------------------------------------------------------------
def _field_data_xml(field_data: dict[str, np.ndarray]) -> str:
    """A VTK XML ``<FieldData>`` element with ASCII arrays (floats written exactly)."""
    parts = ["<FieldData>"]
    for name, value in field_data.items():
        v = np.atleast_1d(value)
        if v.dtype.kind == "f":
            typ, text = "Float64", " ".join(repr(float(x)) for x in v)
        else:
            typ, text = "Int64", " ".join(str(int(x)) for x in v)
        parts.append(
            f'<DataArray type="{typ}" Name={quoteattr(name)} NumberOfTuples="{v.size}" '
            f'format="ascii">{text}</DataArray>'
        )
    parts.append("</FieldData>")
    return "".join(parts)


def _write_vtu(
    path: Path,
    points: np.ndarray,
    blocks: list[tuple[str, np.ndarray]],
    point_data: dict[str, np.ndarray],
    cell_data: dict[str, list[np.ndarray]],
    field_data: dict[str, np.ndarray],
) -> None:
    mesh = meshio.Mesh(points, blocks, point_data=point_data, cell_data=cell_data)
    # an empty grid (no CFE made yet at a stage) uncompressed: a compressed array of no
    # blocks is an edge case of VTK's reader
    meshio.write(path, mesh, file_format="vtu",
                 **({} if len(points) else {"compression": None}))
    # meshio's VTU writer drops field data: insert it as the grid's first child
    text = path.read_text(encoding="utf-8")
    tag = "<UnstructuredGrid>"
    if tag not in text:
        raise RuntimeError(f"{path}: unexpected VTU layout written by meshio")
    text = text.replace(tag, tag + _field_data_xml(field_data), 1)
    path.write_text(text, encoding="utf-8")


def _comment(text: str) -> str:
    return " " + text.replace("--", "- -") + " "


def _write_pvd(path: Path, entries: list[tuple[float, str]], notes: list[str]) -> None:
    root = ET.Element("VTKFile", type="Collection", version="0.1", byte_order="LittleEndian")
    for note in notes:
        root.append(ET.Comment(_comment(note)))
    coll = ET.SubElement(root, "Collection")
    for time, file in entries:
        ET.SubElement(coll, "DataSet", timestep=repr(float(time)), group="", part="0", file=file)
    ET.indent(root)
    ET.ElementTree(root).write(path, encoding="utf-8", xml_declaration=True)


def _notes(result: StaticResult, body: _BodyGrid) -> list[str]:
    codes = ", ".join(f"{int(s)} {s.label}" for s in ContactState)
    if np.any(np.asarray(result.state) >= FACET_SLIP):  # a faceted cone's slip (3D)
        codes += (f", {FACET_SLIP} + i slip on facet i, {VERTEX_SLIP} + i slip at vertex i "
                  "of the faceted Coulomb cone")
    timing = ("time = the time of the dynamic analysis, s (lam holds it too)"
              if getattr(result, "path_axis", "lam") == "time"
              else "time = load-path parameter t = sum |dlambda|")
    return [
        f"stepcontact export; units SI: m, N, Pa; {timing}",
        "body ids: " + ", ".join(f"{k} {n}" for k, n in enumerate(body.names)),
        "interface ids: " + ", ".join(f"{k} {n}" for k, n in enumerate(result.interface_names)),
        f"CFE state codes: {codes}",
        *([f"faceted Coulomb cone of {int(result.cfe['facets'])} facets (point data facets; "
           "facet / vertex: where a CFE slips, -1 elsewhere)"] if "facets" in result.cfe
          else []),
        "field data of every frame: TimeValue, load_path_t, lam, segment, state, "
        "state_kind (0 start, 1 segment start, 2 event, 3 segment end), factors"
        + (", stage" if _staged(result) else ""),
    ] + ([
        "stage ids: " + ", ".join(f"{k} {n}" for k, n in enumerate(result.stage_names)),
        "construction stages: every frame holds the bodies and CFEs that exist at its state "
        "(cell data active = 1, built_stage = the stage that built them)",
    ] if _staged(result) else [])


_NAME_RE = re.compile(r"[^/\\\x00]+")


def _check_name(name: str) -> None:
    if not _NAME_RE.fullmatch(name) or name in (".", "..") or name.startswith("."):
        raise ValueError(f"name '{name}': use a plain file name (no path separators)")


def _is_series_dir(path: Path, name: str) -> bool:
    """True when ``path`` is a directory holding nothing but files of the series ``name``."""
    if not path.is_dir():
        return False
    pattern = re.compile(re.escape(name) + r"(_cfe)?_\d+\.vtu")
    return all(p.is_file() and pattern.fullmatch(p.name) for p in path.iterdir())


def export_vtu(
    result: StaticResult,
    directory: str | os.PathLike[str],
    *,
    states: StateSelection = None,
    name: str = "result",
) -> Path:
    """Write the result as VTU time series with ``.pvd`` collection files for ParaView.

    Files: ``DIR/NAME.pvd`` (bodies and frames), ``DIR/NAME_cfe.pvd`` (contact elements; not
    written for a model without CFEs), and the frames ``DIR/NAME/NAME_<state>.vtu`` and
    ``DIR/NAME/NAME_cfe_<state>.vtu``.  An existing series of the same name is replaced (the
    folder ``DIR/NAME`` must hold nothing else); other files in ``DIR`` are left alone.  The
    arrays, units and the time parameter are described in the module documentation
    (:mod:`stepcontact.io.export`) and in ``docs/paraview.md``.

    Parameters
    ----------
    result : StaticResult
        A result with geometry (from :func:`~stepcontact.solve_static` or a result file).
    directory : path
        Output folder (created).
    states : None, "all", "stored", "events", "ends", int or sequence of int
        States to write (see :func:`select_states`); default: every state.  States whose
        fields were not stored are recomputed exactly when the result can (in memory, or after
        ``result.recover_fields(model)``); otherwise they are skipped with a warning on the
        ``stepcontact.io.export`` logger that names them.
    name : str
        Base name of the files.

    Returns
    -------
    pathlib.Path
        The bodies' ``.pvd`` file (open it in ParaView; the CFEs' file is beside it).
    """
    _check_name(name)
    directory = Path(directory)
    frames = _frames(result, states)
    body = _body_grid(result)
    cfe = _cfe_grid(result, body) if result.m else None
    directory.mkdir(parents=True, exist_ok=True)
    data_dir = directory / name
    if data_dir.exists() and not _is_series_dir(data_dir, name):
        raise FileExistsError(
            f"'{data_dir}' exists and is not a VTU series '{name}' written by stepcontact: "
            "choose another name or directory"
        )
    width = max(4, len(str(result.n_states - 1)))
    notes = _notes(result, body)
    tmp = Path(tempfile.mkdtemp(prefix=f".{name}.", suffix=".tmp", dir=directory))
    try:
        _export_vtu_into(tmp, directory, name, result, frames, body, cfe, width, notes)
    except OSError as e:
        shutil.rmtree(tmp, ignore_errors=True)
        raise write_error(directory / f"{name}.pvd", e, "VTU export") from None
    return directory / f"{name}.pvd"


def _export_vtu_into(tmp: Path, directory: Path, name: str, result: StaticResult,
                     frames: _Frames, body: _BodyGrid, cfe: _CfeGrid | None, width: int,
                     notes: list[str]) -> None:
    """The body of :func:`export_vtu`: the series written into ``tmp``, then moved into
    ``directory``; the free space is checked after the first frame (its size × frames)."""
    data_dir = directory / name
    old: Path | None = None
    try:
        (tmp / name).mkdir()
        body_entries: list[tuple[float, str]] = []
        cfe_entries: list[tuple[float, str]] = []
        staged = _staged(result)
        for i, t, time, (bpd, bcd), cdata in _iter_frames(result, frames, body, cfe):
            fdata = _field_data(result, i, t, time)
            rel = f"{name}/{name}_{i:0{width}d}.vtu"
            if staged:  # only the bodies built at the state
                here = result.active_bodies(i)
                _write_vtu(tmp / rel, *_keep_cells(body.points, body.blocks,
                                                   [n in here for n in body.names],
                                                   (bpd, bcd)), fdata)
            else:
                _write_vtu(tmp / rel, body.points, body.blocks, bpd, bcd, fdata)
            body_entries.append((time, rel))
            if cfe is not None and cdata is not None:
                rel = f"{name}/{name}_cfe_{i:0{width}d}.vtu"
                if staged:  # only the CFEs made at the state
                    _write_vtu(tmp / rel, *_keep_cfes(cfe, result.active_cfes(i), cdata), fdata)
                else:
                    _write_vtu(tmp / rel, cfe.points, [(cfe.kind, cfe.lines)], *cdata, fdata)
                cfe_entries.append((time, rel))
            if len(body_entries) == 1 and len(frames.states) > 1:
                first = sum(f.stat().st_size for f in (tmp / name).iterdir())
                check_free_space(directory / f"{name}.pvd",
                                 first * (len(frames.states) - 1), "VTU export")
        pvd = tmp / f"{name}.pvd"
        cfe_pvd = tmp / f"{name}_cfe.pvd"
        _write_pvd(pvd, body_entries, notes)
        if cfe is not None:
            _write_pvd(cfe_pvd, cfe_entries, notes)
        # move into place: the frames folder first, then the collection files
        if data_dir.exists():
            old = directory / f".{name}.old-{uuid.uuid4().hex}"
            os.replace(data_dir, old)
        try:
            os.replace(tmp / name, data_dir)
        except BaseException:
            if old is not None:
                os.replace(old, data_dir)
                old = None
            raise
        if cfe is not None:
            os.replace(cfe_pvd, directory / cfe_pvd.name)
        else:
            (directory / cfe_pvd.name).unlink(missing_ok=True)
        os.replace(pvd, directory / pvd.name)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)


# --------------------------------------------------------------------------------------------
# XDMF
# --------------------------------------------------------------------------------------------
class _XdmfWriter(TimeSeriesWriter):
    """meshio's XDMF time-series writer with three fixes.

    The HDF5 file is written next to the ``.xdmf`` file (meshio opens it in the working
    directory), line cells get ``NodesPerElement="2"``, and mixed topologies with line cells are
    encoded correctly (type 2, node count 2, nodes).
    """

    def __enter__(self):
        import io

        import h5py

        self.h5_filename = str(self.filename.with_suffix(".h5"))
        self._h5_bytes = io.BytesIO()  # in memory: HDF5 never writes to the disk itself
        self.h5_file = h5py.File(self._h5_bytes, "w")
        return self

    def __exit__(self, *exc):
        self.h5_file.close()
        if exc[0] is None:
            write_bytes(self.h5_filename, self._h5_bytes.getvalue(), fsync=False,
                        what="XDMF data file")
            from meshio._common import write_xml

            write_xml(self.filename, self.xdmf_file)

    def cells(self, cells, grid: ET.Element) -> None:
        blocks = [(str(t), np.asarray(d)) for t, d in cells]
        if len({t for t, _ in blocks}) == 1:
            ctype = blocks[0][0]
            data = np.concatenate([d for _, d in blocks])
            attrs = {"TopologyType": meshio_to_xdmf_type[ctype][0],
                     "NumberOfElements": str(len(data))}
            if ctype in ("line", "vertex"):
                attrs["NodesPerElement"] = str(_NODES_PER_CELL.get(ctype, 1))
            dims = "{} {}".format(*data.shape)
        else:
            parts = []
            for ctype, d in blocks:
                cols = [np.full((len(d), 1), meshio_type_to_xdmf_index[ctype], dtype=d.dtype)]
                if ctype == "line":
                    cols.append(np.full((len(d), 1), 2, dtype=d.dtype))
                parts.append(np.hstack([*cols, d]).ravel())
            data = np.concatenate(parts)
            attrs = {"TopologyType": "Mixed",
                     "NumberOfElements": str(sum(len(d) for _, d in blocks))}
            dims = str(data.size)
        topo = ET.SubElement(grid, "Topology", **attrs)
        dt, prec = numpy_to_xdmf_dtype[data.dtype.name]
        item = ET.SubElement(topo, "DataItem", DataType=dt, Dimensions=dims,
                             Format=self.data_format, Precision=prec)
        item.text = self.numpy_to_xml_string(data)

    def information(self, values: dict[str, np.ndarray | str]) -> None:
        """Attach ``<Information>`` elements to the time grid written last."""
        grid = list(self.collection)[-1]
        for key, v in values.items():
            text = v if isinstance(v, str) else " ".join(
                repr(x) for x in np.atleast_1d(v).tolist())
            ET.SubElement(grid, "Information", Name=key, Value=text)


def export_xdmf(
    result: StaticResult,
    path: str | os.PathLike[str],
    *,
    states: StateSelection = None,
) -> Path:
    """Write the result as XDMF time series (``.xdmf`` + ``.h5``) for ParaView.

    Files: ``FILE.xdmf`` + ``FILE.h5`` (bodies and frames; one ``Mixed`` topology when the
    bodies have different cell types), ``FILE_cfe.xdmf`` + ``FILE_cfe.h5`` (contact elements;
    not written without CFEs).  Written with meshio's ``TimeSeriesWriter``; open them with
    ParaView's "Xdmf3 Reader T" (or "XDMF Reader").  Arrays, units and the time parameter as
    for :func:`export_vtu`; λ, segment and state index of each frame are ``<Information>``
    elements of its time grid.  Both pairs of files are written atomically.

    Parameters
    ----------
    result : StaticResult
    path : path
        The bodies' ``.xdmf`` file (parent folders are created).
    states : see :func:`select_states`

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    if path.suffix.lower() != ".xdmf":
        raise ValueError(f"'{path}': the XDMF file name must end in .xdmf")
    _check_name(path.name)
    frames = _frames(result, states)
    body = _body_grid(result)
    cfe = _cfe_grid(result, body) if result.m else None
    path.parent.mkdir(parents=True, exist_ok=True)
    cfe_path = path.with_name(f"{path.stem}_cfe.xdmf")
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.stem}.", suffix=".tmp", dir=path.parent))
    try:
        _export_xdmf_into(tmp, path, cfe_path, result, frames, body, cfe)
    except OSError as e:
        raise write_error(path, e, "XDMF export") from None
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return path


def _export_xdmf_into(tmp: Path, path: Path, cfe_path: Path, result: StaticResult,
                      frames: _Frames, body: _BodyGrid, cfe: _CfeGrid | None) -> None:
    """The body of :func:`export_xdmf`: both pairs of files written into ``tmp``, then moved
    into place."""
    with (
        _XdmfWriter(tmp / path.name) as wb,
        _XdmfWriter(tmp / cfe_path.name) as wc,
    ):
        wb.write_points_cells(body.points, body.blocks)
        if cfe is not None:
            wc.write_points_cells(cfe.points, [(cfe.kind, cfe.lines)])
        for i, t, time, (bpd, bcd), cdata in _iter_frames(result, frames, body, cfe):
            info = _field_data(result, i, t, time)
            if "stage" in info:
                info["stage_name"] = result.stage_names[int(result.stage[i])]
            wb.write_data(time, point_data=bpd, cell_data=bcd)
            wb.information(info)
            if cdata is not None:
                wc.write_data(time, point_data=cdata[0] or None, cell_data=cdata[1] or None)
                wc.information(info)
    outputs = [path] + ([cfe_path] if cfe is not None else [])
    for out in outputs:  # data first, then the XML that points to it
        os.replace(tmp / out.with_suffix(".h5").name, out.with_suffix(".h5"))
    for out in outputs:
        os.replace(tmp / out.name, out)
    if cfe is None:
        cfe_path.unlink(missing_ok=True)
        cfe_path.with_suffix(".h5").unlink(missing_ok=True)


__all__ = [
    "STATE_KINDS",
    "TIME_SEPARATION",
    "export_vtu",
    "export_xdmf",
    "frame_times",
    "load_path_parameter",
    "select_states",
    "von_mises",
]
