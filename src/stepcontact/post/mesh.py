"""The mesh of a result as the figures read it: its nodes, DOF map and bodies
(``res.geometry``), the displacements of a state (stored or recomputed), the outline of a
cell and of a body, and the node a curve follows (chosen by index, by coordinates, or the
one that moves most).  Used by the deformed shape, the contact-stress diagrams (the body
corners), the load–displacement curve and the time histories.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from stepcontact.post.common import _ranges

if TYPE_CHECKING:
    from stepcontact.results.result import StaticResult

#: outline node order of a cell in scikit-fem's local DOF order (corners, then the mid-side
#: nodes of the edges 01, 12, 23 (02 for triangles), 30)
_RING: dict[str, tuple[int, ...]] = {
    "tri3": (0, 1, 2),
    "tri6": (0, 3, 1, 4, 2, 5),
    "quad4": (0, 1, 2, 3),
    "quad8": (0, 4, 1, 5, 2, 6, 3, 7),
    "quad9": (0, 4, 1, 5, 2, 6, 3, 7),
}


def _geometry(res: StaticResult) -> tuple[np.ndarray, np.ndarray, list[dict]]:
    """(points (n, 2) m, dof_of (n, 3), bodies) of the result, or a ValueError."""
    geo = res.geometry or {}
    if not all(k in geo for k in ("points", "dof_of", "bodies")):
        raise ValueError(
            "this result has no mesh geometry (points, dof_of, bodies): it cannot be drawn"
        )
    return (np.asarray(geo["points"], dtype=float), np.asarray(geo["dof_of"]),
            list(geo["bodies"]))


def dof_names(points: np.ndarray, dof_of: np.ndarray) -> tuple[str, ...]:
    """The names of the columns of ``dof_of``: ux, uy, rz (2D); ux, uy, uz (3D continua) and
    rx, ry, rz (space frames)."""
    if points.shape[1] == 3:
        return ("ux", "uy", "uz", "rx", "ry", "rz")[: dof_of.shape[1]]
    return ("ux", "uy", "rz")


def _extent(points: np.ndarray) -> float:
    """Largest side of the bounding box of the nodes, m (1 when degenerate)."""
    size = float(np.max(np.ptp(points, axis=0))) if len(points) else 0.0
    return size if size > 0 and np.isfinite(size) else 1.0


def _missing_fields(res: StaticResult, i: int) -> ValueError:
    """The error for displacements a result neither stores nor can recompute."""
    stored = sorted(res.fields)
    have = (f"stored for states {_ranges(stored)}" if stored else "no field is stored")
    return ValueError(
        f"the displacements of state {i} are not in this result ({have}); give the result "
        "its model with res.recover_fields(model) (command line: --model MODEL.toml) to "
        "recompute any state exactly, or re-run with solve_static(model, "
        "store_fields='all') (an in-memory result recovers any state)"
    )


def _field(res: StaticResult, i: int) -> np.ndarray:
    """Displacement vector of state ``i``; a ValueError that says how to get it if missing."""
    try:
        return np.asarray(res.displacement(i), dtype=float)
    except KeyError:
        raise _missing_fields(res, i) from None


def _all_fields(res: StaticResult) -> np.ndarray:
    """Displacements (n_states, ndof) of every state: stored, the others recomputed in one
    solve; a ValueError that says how to get them if the result cannot."""
    try:
        return np.asarray(res.displacements(), dtype=float)
    except KeyError:
        missing = next(i for i in range(res.n_states) if i not in res.fields)
        raise _missing_fields(res, missing) from None


def _node_u(dof_of: np.ndarray, u: np.ndarray, comps: Sequence[int] = (0, 1)) -> np.ndarray:
    """Nodal values (n_nodes, len(comps)) of the DOF components ``comps`` (0 where none)."""
    d = dof_of[:, list(comps)]
    return np.where(d >= 0, u[np.maximum(d, 0)], 0.0)


def _ring(element: str, n_per_cell: int) -> tuple[np.ndarray, int]:
    """Outline node order of a cell and the number of nodes per edge (2, or 3 if quadratic)."""
    ring = _RING.get(element)
    if ring is None or max(ring) >= n_per_cell:
        ring = tuple(range(min(n_per_cell, 4)))  # unknown element: its corners
    return np.asarray(ring), 3 if len(ring) in (6, 8) else 2


def _cell_edges(cells: np.ndarray, element: str) -> np.ndarray:
    """(n_cells · n_edges, 2 or 3) node ids of every cell edge: end, [mid-side,] end."""
    ring, per = _ring(element, cells.shape[1])
    r = cells[:, ring]
    starts = np.arange(0, r.shape[1], per - 1)
    cols = (starts[:, None] + np.arange(per)[None, :]) % r.shape[1]
    return r[:, cols].reshape(-1, per)


def _boundary_edges(edges: np.ndarray) -> np.ndarray:
    """The edges that belong to one cell only (the outline of the body)."""
    if not len(edges):
        return edges
    key = np.sort(edges[:, [0, -1]], axis=1)
    _, inv, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    return edges[counts[inv.ravel()] == 1]


def _resolve_node(
    res: StaticResult,
    node: int | Sequence[float] | None,
    body: str | None,
    comp: int,
    u_last: np.ndarray,
) -> int:
    """Global node index from an index, coordinates (m) or None (the largest value of
    ``u_last`` — a displacement vector, or |u| of each DOF over the path — in ``comp``)."""
    points, dof_of, bodies = _geometry(res)
    names = [str(b["name"]) for b in bodies]
    owner = np.full(len(points), -1)
    for j, b in enumerate(bodies):
        owner[np.asarray(b["cells"], dtype=np.int64).ravel()] = j
    if body is not None and body not in names:
        raise ValueError(f"body '{body}' does not exist; bodies: {', '.join(names)}")
    cand = np.flatnonzero(owner == names.index(body)) if body is not None else np.arange(
        len(points))
    if isinstance(node, int | np.integer) and not isinstance(node, bool):
        if not 0 <= int(node) < len(points):
            raise ValueError(f"node {node} does not exist: nodes are 0..{len(points) - 1}")
        if dof_of[int(node), comp] < 0:
            raise ValueError(f"node {node} has no DOF {dof_names(points, dof_of)[comp]}")
        return int(node)
    cand = cand[dof_of[cand, comp] >= 0]
    if not cand.size:
        raise ValueError(f"no node{'' if body is None else f' of {body!r}'} has DOF "
                         f"{dof_names(points, dof_of)[comp]}")
    if node is None:
        return int(cand[np.argmax(np.abs(_node_u(dof_of, u_last, (comp,))[cand, 0]))])
    dim = points.shape[1]
    try:
        xy = np.asarray(node, dtype=float).reshape(dim)
    except (TypeError, ValueError):
        raise ValueError(
            f"node={node!r}: give a node index or its coordinates "
            f"{'(x, y, z)' if dim == 3 else '(x, y)'} in m") from None

    def at(v) -> str:
        return "(" + ", ".join(f"{c:g}" for c in v) + ")"

    d = np.linalg.norm(points[cand] - xy, axis=1)
    size = _extent(points)
    if d.min() > 0.05 * size:
        k = int(cand[np.argmin(d)])
        raise ValueError(f"no node near {at(xy)}: the nearest, node {k} at "
                         f"{at(points[k])}, is {d.min():.3g} m away")
    near = cand[d <= d.min() + 1e-9 * size]
    shared = sorted({names[owner[k]] for k in near})
    if len(shared) > 1:
        raise ValueError(f"the node at {at(xy)} is shared by bodies "
                         f"{', '.join(map(repr, shared))}: choose one (body=...; CLI: --body)")
    return int(near[0])


def _most_moving(res: StaticResult, node: int | Sequence[float] | None, body: str | None,
                 comp: int, peak: np.ndarray) -> tuple[int, int]:
    """(node, component) of the load–displacement curve: ``node`` (or the node with the
    largest ``peak`` — |u| of each DOF over the path — in ``comp``) and ``comp`` (or, when
    −1, the one of u_x, u_y (3D: u_x, u_y, u_z) in which it moves most)."""
    if comp >= 0:
        return _resolve_node(res, node, body, comp, peak), comp
    points, dof_of, _ = _geometry(res)
    best: tuple[float, int, int] | None = None
    for c in range(points.shape[1]):
        try:
            k = _resolve_node(res, node, body, c, peak)
        except ValueError:
            if c == 0:
                continue
            if best is None:
                raise
            break
        if best is None or peak[dof_of[k, c]] > best[0]:
            best = (float(peak[dof_of[k, c]]), k, c)
    assert best is not None
    return best[1], best[2]
