"""Boundary topology of bodies: the curves a node set forms on a body (boundary edges of a
continuum, bars of a frame), their order and arc length, tributary lengths, the mesh facets of
edges, outward normals and the shape functions along an edge.

Public, for the contact elements (:mod:`stepcontact.contact.geometry`) and for the loads that
act on edges (:mod:`stepcontact.fem.assembly`, :mod:`stepcontact.fem.level`,
:mod:`stepcontact.fem._edge_kinks`).  Lengths in m.
"""

from __future__ import annotations

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model import Body, Frame, Model, NodeSet


def curve_edges(body: Body | Frame, ns: NodeSet) -> np.ndarray:
    """Edges (local node ids; ends first, then mid-side) of a body whose nodes all lie in ``ns``.

    For a continuum these are boundary edges; for a frame, its bars.
    """
    edges = body.boundary if isinstance(body, Body) else body.cells
    inset = np.zeros(body.n_nodes, dtype=bool)
    inset[ns.index] = True
    return edges[np.all(inset[edges], axis=1)]


def continuum_edges(model: Model, ns: NodeSet, item: str, what: str) -> tuple[Body, np.ndarray]:
    """The continuum body of node set ``ns`` and its boundary edges in the set (see
    :func:`curve_edges`), for loads that act on edges (``what``: "edge loads", "water
    loads", …); a frame or a set with no edge is a ModelError naming ``item``."""
    b = model.body(ns.body)
    if not isinstance(b, Body):
        raise ModelError(item, f"{what} need a continuum body, '{b.name}' is a frame")
    edges = curve_edges(b, ns)
    if len(edges) == 0:
        raise ModelError(f"{item} ({ns.label})", "contains no boundary edge")
    return b, edges


def chain_order(body: Body | Frame, ns: NodeSet) -> tuple[np.ndarray, np.ndarray]:
    """Nodes of ``ns`` ordered along the curve they form, and their arc length from the start.

    The curve starts at the end nearest to the set's first node.  Nodes of the set that lie on
    no edge of the set are appended in given order (arc length by straight distance).
    """
    edges = curve_edges(body, ns)
    pts = body.points
    if len(edges) == 0:
        idx = ns.index
        d = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(pts[idx], axis=0), axis=1))]
        return idx, d
    # walk the graph of edge ends (mid-side nodes are placed between their ends)
    ends = edges[:, :2]
    adj: dict[int, list[int]] = {}
    for e, (a, b) in enumerate(ends.tolist()):
        adj.setdefault(a, []).append(e)
        adj.setdefault(b, []).append(e)
    degree_one = [n for n, es in adj.items() if len(es) == 1]
    first = int(ns.index[0])
    if degree_one:
        start = min(degree_one, key=lambda n: np.linalg.norm(pts[n] - pts[first]))
    else:
        start = int(ends[0, 0])
    order = [start]
    used = np.zeros(len(edges), dtype=bool)
    cur = start
    while True:
        nxt = [e for e in adj[cur] if not used[e]]
        if not nxt:
            break
        e = nxt[0]
        used[e] = True
        a, b = ends[e]
        other = int(b if a == cur else a)
        if edges.shape[1] > 2:
            order.append(int(edges[e, 2]))
        order.append(other)
        cur = other
    order_arr = np.array(order, dtype=np.int64)
    if np.unique(order_arr).size < order_arr.size:  # closed loop: drop the repeated start
        order_arr = order_arr[:-1]
    rest = np.setdiff1d(ns.index, order_arr, assume_unique=False)
    order_arr = np.r_[order_arr, rest[np.argsort([np.flatnonzero(ns.index == r)[0] for r in rest])]]
    d = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(pts[order_arr], axis=0), axis=1))]
    return order_arr, d


def tributary_lengths(body: Body | Frame, ns: NodeSet) -> np.ndarray:
    """∫ φ_i ds over the edges of the set for every body node (0 off the set), m.

    Straight edges: L/2 at each end of a linear edge; L/6, L/6, 2L/3 for a quadratic one.
    """
    edges = curve_edges(body, ns)
    out = np.zeros(body.n_nodes)
    if len(edges) == 0:
        return out
    pts = body.points
    L = np.linalg.norm(pts[edges[:, 1]] - pts[edges[:, 0]], axis=1)
    if edges.shape[1] == 2:
        np.add.at(out, edges[:, 0], L / 2)
        np.add.at(out, edges[:, 1], L / 2)
    else:
        np.add.at(out, edges[:, 0], L / 6)
        np.add.at(out, edges[:, 1], L / 6)
        np.add.at(out, edges[:, 2], 2 * L / 3)
    return out


def outward_normals(body: Body | Frame, edges: np.ndarray) -> np.ndarray | None:
    """Outward unit normals of continuum boundary edges (None for frames)."""
    pts = body.points
    d = pts[edges[:, 1]] - pts[edges[:, 0]]
    d /= np.linalg.norm(d, axis=1)[:, None]
    n = np.column_stack([d[:, 1], -d[:, 0]])
    if not isinstance(body, Body):
        return None
    # orient with the centroid of the element owning the edge
    mesh = body.mesh
    fac_of_edge = edge_facets(body, edges)
    elem = mesh.f2t[0, fac_of_edge]
    centroid = mesh.p[:, mesh.t[:, elem]].mean(axis=1).T
    mid = 0.5 * (pts[edges[:, 0]] + pts[edges[:, 1]])
    flip = np.einsum("ij,ij->i", mid - centroid, n) < 0
    n[flip] *= -1
    return n


def edge_facets(body: Body, edges: np.ndarray) -> np.ndarray:
    """The mesh facets (scikit-fem numbering) of boundary edges of a continuum body (of
    boundary faces, rows of ``body.boundary``, for a 3D body)."""
    if body.dim == 3:  # faces: matched by their sorted corners (3 or 4)
        nc = 3 if body.element.startswith("tet") else 4
        keys = np.sort(np.vstack([body.boundary[:, :nc], edges[:, :nc]]), axis=1)
        _, inv = np.unique(keys, axis=0, return_inverse=True)
        inv = inv.ravel()
        nb = len(body.boundary)
        pos = np.empty(int(inv.max()) + 1, dtype=np.int64)
        pos[inv[:nb]] = np.arange(nb)
        return body.boundary_facets[pos[inv[nb:]]]
    key_b = np.sort(body.boundary[:, :2], axis=1)
    key_e = np.sort(edges[:, :2], axis=1)
    nn = body.n_nodes
    kb = key_b[:, 0] * nn + key_b[:, 1]
    ke = key_e[:, 0] * nn + key_e[:, 1]
    order = np.argsort(kb)
    pos = order[np.searchsorted(kb[order], ke)]
    return body.boundary_facets[pos]


def edge_shape(xi: np.ndarray, quadratic: bool) -> np.ndarray:
    """Edge shape functions at ξ ∈ [0,1]: ends first, then mid-side."""
    if not quadratic:
        return np.column_stack([1 - xi, xi])
    return np.column_stack([(1 - xi) * (1 - 2 * xi), xi * (2 * xi - 1), 4 * xi * (1 - xi)])


def near_pairs(tree, x: np.ndarray, radius: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pairs (i, j) of a contact search: the points j of ``tree`` (a
    :class:`scipy.spatial.cKDTree`) within ``radius[i]`` (m) of x[i], grouped by i."""
    lists = tree.query_ball_point(x, radius)
    counts = np.fromiter((len(v) for v in lists), dtype=np.int64, count=len(lists))
    rows = np.repeat(np.arange(len(x)), counts)
    cols = np.fromiter((c for v in lists for c in v), dtype=np.int64, count=int(counts.sum()))
    return rows, cols


__all__ = ["chain_order", "continuum_edges", "curve_edges", "edge_facets", "edge_shape",
           "near_pairs", "outward_normals", "tributary_lengths"]
