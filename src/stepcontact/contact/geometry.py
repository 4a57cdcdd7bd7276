"""Contact finite elements (CFEs) of frame type: generation along interfaces, geometry arrays.

A CFE k joins a point of S+ to the opposite point of S− (method.md §2).  Its kinematics are

    u_τk = t_k · (u⁺ − u⁻),        u_nk = −n_k · (u⁺ − u⁻) − g_k⁰

with n_k the unit normal pointing from S− to S+, t_k = (n_y, −n_x) (n turned clockwise:
+x for an interface whose normal is +y), g_k⁰ ≥ 0 the initial gap.
So u_n ≤ 0 means no interpenetration and u_n < 0 is an open gap (article sign convention).
Its end on S− may lie inside a boundary edge and is then interpolated from that edge's nodes
(node-to-segment); the meshes of the two sides need not match.

Forces: N_k (normal, ≤ 0 in compression) and Q_k (tangential) with |Q_k| ≤ −f_k N_k, eq. (1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model import Body, Frame, Interface, Model, NodeSet

MAX_END_NODES = 3


@dataclass(frozen=True, eq=False)
class ContactElements:
    """All CFEs of a model as arrays (m = number of CFEs).

    Attributes
    ----------
    names : tuple of str
        Interface names; ``interface[k]`` indexes into it.
    interface : (m,) int
    local : (m,) int
        Index of the CFE within its interface (ordered along S+).
    plus_nodes, minus_nodes : (m, 3) int
        Global node ids of each end's interpolation (−1 padding).
    plus_w, minus_w : (m, 3) float
        Interpolation weights of those nodes.
    normal, tangent : (m, 2) float
        Unit normal (S− → S+) and tangent t = (n_y, −n_x).
    x : (m, 2) float
        Coordinates of the S+ end, m.
    s : (m,) float
        Position along the interface (arc length along S+ from its first node), m.
    area : (m,) float
        Contact area A_k belonging to the CFE (tributary length × thickness), m².
    friction : (m,) float
        Friction coefficient f_k.
    gap : (m,) float
        Initial gap g_k⁰ ≥ 0, m.
    kn, kt : (m,) float
        Contact-layer stiffnesses C_nk, C_τk in N/m (eq. (11)); ``inf`` for rigid contact.
    """

    names: tuple[str, ...]
    interface: np.ndarray
    local: np.ndarray
    plus_nodes: np.ndarray
    plus_w: np.ndarray
    minus_nodes: np.ndarray
    minus_w: np.ndarray
    normal: np.ndarray
    tangent: np.ndarray
    x: np.ndarray
    s: np.ndarray
    area: np.ndarray
    friction: np.ndarray
    gap: np.ndarray
    kn: np.ndarray
    kt: np.ndarray

    @property
    def m(self) -> int:
        return len(self.interface)

    def __len__(self) -> int:
        return self.m

    def of(self, name: str) -> np.ndarray:
        """Indices of the CFEs of one interface, in order along it."""
        if name not in self.names:
            raise ModelError(f"interface '{name}'", f"no such interface (known: {self.names})")
        return np.flatnonzero(self.interface == self.names.index(name))

    @staticmethod
    def empty() -> ContactElements:
        z = np.zeros(0)
        zi = np.zeros(0, dtype=np.int64)
        return ContactElements(
            (), zi, zi, np.zeros((0, 3), np.int64), np.zeros((0, 3)), np.zeros((0, 3), np.int64),
            np.zeros((0, 3)), np.zeros((0, 2)), np.zeros((0, 2)), np.zeros((0, 2)),
            z, z, z, z, z, z,
        )


# --------------------------------------------------------------------------------------------
# curves on bodies
# --------------------------------------------------------------------------------------------
def curve_edges(body: Body | Frame, ns: NodeSet) -> np.ndarray:
    """Edges (local node ids; ends first, then mid-side) of a body whose nodes all lie in ``ns``.

    For a continuum these are boundary edges; for a frame, its bars.
    """
    edges = body.boundary if isinstance(body, Body) else body.cells
    inset = np.zeros(body.n_nodes, dtype=bool)
    inset[ns.index] = True
    return edges[np.all(inset[edges], axis=1)]


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


def _outward_normals(body: Body | Frame, edges: np.ndarray) -> np.ndarray | None:
    """Outward unit normals of continuum boundary edges (None for frames)."""
    pts = body.points
    d = pts[edges[:, 1]] - pts[edges[:, 0]]
    d /= np.linalg.norm(d, axis=1)[:, None]
    n = np.column_stack([d[:, 1], -d[:, 0]])
    if not isinstance(body, Body):
        return None
    # orient with the centroid of the element owning the edge
    mesh = body.mesh
    fac_of_edge = _edge_to_facet(body, edges)
    elem = mesh.f2t[0, fac_of_edge]
    centroid = mesh.p[:, mesh.t[:, elem]].mean(axis=1).T
    mid = 0.5 * (pts[edges[:, 0]] + pts[edges[:, 1]])
    flip = np.einsum("ij,ij->i", mid - centroid, n) < 0
    n[flip] *= -1
    return n


def _edge_to_facet(body: Body, edges: np.ndarray) -> np.ndarray:
    key_b = np.sort(body.boundary[:, :2], axis=1)
    key_e = np.sort(edges[:, :2], axis=1)
    nn = body.n_nodes
    kb = key_b[:, 0] * nn + key_b[:, 1]
    ke = key_e[:, 0] * nn + key_e[:, 1]
    order = np.argsort(kb)
    pos = order[np.searchsorted(kb[order], ke)]
    return body.boundary_facets[pos]


def _project(x: np.ndarray, a: np.ndarray, b: np.ndarray, chunk: int = 2048):
    """Closest point of each x on the segments [a_j, b_j]: (segment index, ξ in [0,1], dist)."""
    seg = np.empty(len(x), dtype=np.int64)
    xi = np.empty(len(x))
    dist = np.empty(len(x))
    ab = b - a
    L2 = np.einsum("ij,ij->i", ab, ab)
    for s in range(0, len(x), chunk):
        xs = x[s : s + chunk]
        t = np.einsum("pjk,jk->pj", xs[:, None, :] - a[None], ab) / L2[None]
        t = np.clip(t, 0.0, 1.0)
        c = a[None] + t[..., None] * ab[None]
        d = np.linalg.norm(xs[:, None, :] - c, axis=2)
        j = np.argmin(d, axis=1)
        seg[s : s + chunk] = j
        xi[s : s + chunk] = t[np.arange(len(xs)), j]
        dist[s : s + chunk] = d[np.arange(len(xs)), j]
    return seg, xi, dist


def _shape(xi: np.ndarray, quadratic: bool) -> np.ndarray:
    """Edge shape functions at ξ ∈ [0,1]: ends first, then mid-side."""
    if not quadratic:
        return np.column_stack([1 - xi, xi])
    return np.column_stack([(1 - xi) * (1 - 2 * xi), xi * (2 * xi - 1), 4 * xi * (1 - xi)])


def interface_elements(model: Model, itf: Interface) -> dict[str, np.ndarray]:
    """Arrays of the CFEs of one interface (see :class:`ContactElements`)."""
    item = f"interface '{itf.name}'"
    bp = model.body(itf.plus.body)
    bm = model.body(itf.minus.body)
    model.global_nodes(itf.plus)
    model.global_nodes(itf.minus)
    off = model.node_offsets
    scale = max(1.0, float(np.ptp(model.points, axis=0).max()))
    tol = 1e-9 * scale

    if itf.pairs:  # explicit node pairs, in the given order
        order = np.asarray(itf.plus.index, dtype=np.int64)
        s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(bp.points[order], axis=0), axis=1))]
    else:
        order, s = chain_order(bp, itf.plus)
    trib = tributary_lengths(bp, itf.plus)[order]
    if np.all(trib == 0):  # isolated nodes: use half distances to neighbours
        gaps = np.diff(s)
        trib = 0.5 * (np.r_[gaps, 0.0] + np.r_[0.0, gaps]) if len(s) > 1 else np.ones(1)
    xp = bp.points[order]
    m = len(order)
    if itf.pairs:
        return _pair_elements(model, itf, order, xp, s, trib, tol, scale)

    medges = curve_edges(bm, itf.minus)
    if len(medges) == 0:
        raise ModelError(f"{item}.minus", "the node set contains no edge of the body to project on")
    a = bm.points[medges[:, 0]]
    b = bm.points[medges[:, 1]]
    seg, xi, _ = _project(xp, a, b)
    # snap to nodes: node-to-node where the meshes match
    L = np.linalg.norm(b - a, axis=1)[seg]
    xi = np.where(xi * L <= tol, 0.0, np.where((1 - xi) * L <= tol, 1.0, xi))
    quad = medges.shape[1] == 3
    w_m = _shape(xi, quad)
    n_m = np.zeros((m, MAX_END_NODES), dtype=np.int64) - 1
    n_m[:, : medges.shape[1]] = medges[seg] + off[bm.name]
    wm = np.zeros((m, MAX_END_NODES))
    wm[:, : medges.shape[1]] = w_m
    xm = a[seg] + xi[:, None] * (b - a)[seg]

    if itf.normal is not None:
        nrm = np.tile(np.asarray(itf.normal, float) / np.linalg.norm(itf.normal), (m, 1))
    else:
        nout = _outward_normals(bm, medges)
        if nout is None:  # frame: orient towards the S+ point
            d = xp - xm
            dist = np.linalg.norm(d, axis=1)
            if np.any(dist <= tol):
                k = int(np.flatnonzero(dist <= tol)[0])
                raise ModelError(f"{item} CFE {k}", "its ends coincide and no normal is given")
            nrm = d / dist[:, None]
        else:
            nrm = nout[seg]
    return _finish(model, itf, order, xp, xm, nrm, s, trib, n_m, wm, tol, scale)


def _pair_elements(model: Model, itf: Interface, order, xp, s, trib, tol, scale):
    """CFEs of explicit node pairs plus[i] – minus[i] (``Interface.pairs``)."""
    item = f"interface '{itf.name}'"
    bm = model.body(itf.minus.body)
    m = len(order)
    mn = np.asarray(itf.minus.index, dtype=np.int64)
    xm = bm.points[mn]
    n_m = np.full((m, MAX_END_NODES), -1, dtype=np.int64)
    n_m[:, 0] = mn + model.node_offsets[bm.name]
    wm = np.zeros((m, MAX_END_NODES))
    wm[:, 0] = 1.0
    if itf.normal is not None:
        nrm = np.tile(np.asarray(itf.normal, float) / np.linalg.norm(itf.normal), (m, 1))
    else:
        d = xp - xm
        dist = np.linalg.norm(d, axis=1)
        if np.any(dist <= tol):
            k = int(np.flatnonzero(dist <= tol)[0])
            raise ModelError(
                f"{item} CFE {k} (nodes {order[k]} of '{itf.plus.body}' and {mn[k]} of "
                f"'{bm.name}')", "its ends coincide and no normal is given")
        nrm = d / dist[:, None]
    return _finish(model, itf, order, xp, xm, nrm, s, trib, n_m, wm, tol, scale)


def _finish(model: Model, itf: Interface, order, xp, xm, nrm, s, trib, n_m, wm, tol, scale):
    """Gaps, areas, layer stiffnesses and the S+ ends: the arrays of one interface."""
    item = f"interface '{itf.name}'"
    bp = model.body(itf.plus.body)
    off = model.node_offsets
    m = len(order)
    tan = np.column_stack([nrm[:, 1], -nrm[:, 0]])
    geo_gap = np.einsum("ij,ij->i", xp - xm, nrm)
    if itf.gap is None:
        gap = geo_gap
        bad = np.flatnonzero(gap < -1e-6 * scale)
        if bad.size:
            k = int(bad[0])
            raise ModelError(
                f"{item} CFE {k} at ({xp[k, 0]:.6g}, {xp[k, 1]:.6g})",
                f"S+ penetrates S- by {-gap[k]:.3g} m; give a gap or fix the geometry",
            )
        gap = np.maximum(gap, 0.0)
        gap[np.abs(gap) <= tol] = 0.0
    elif callable(itf.gap):
        gap = np.asarray(itf.gap(xp[:, 0], xp[:, 1]), float) * np.ones(m)
        if np.any(~np.isfinite(gap)) or np.any(gap < 0):
            k = int(np.flatnonzero(~(np.isfinite(gap) & (gap >= 0)))[0])
            raise ModelError(f"{item}.gap", f"gap function gives {gap[k]} at CFE {k}")
    else:
        gap = np.full(m, float(itf.gap))

    area = trib * model.thickness if itf.area is None else np.full(m, float(itf.area))
    if np.any(area <= 0):
        k = int(np.flatnonzero(area <= 0)[0])
        raise ModelError(f"{item} CFE {k}", "has zero contact area (isolated node?)")
    if itf.layer is not None:
        kn_a, kt_a = itf.layer.stiffness_per_area(f"{item}.layer")
        kn, kt = kn_a * area, kt_a * area
    else:
        kn = np.full(m, np.inf)
        kt = np.full(m, np.inf)

    n_p = np.full((m, MAX_END_NODES), -1, dtype=np.int64)
    n_p[:, 0] = order + off[bp.name]
    wp = np.zeros((m, MAX_END_NODES))
    wp[:, 0] = 1.0
    return dict(
        local=np.arange(m),
        plus_nodes=n_p,
        plus_w=wp,
        minus_nodes=n_m,
        minus_w=wm,
        normal=nrm,
        tangent=tan,
        x=xp,
        s=s,
        area=area,
        friction=np.full(m, float(itf.friction)),
        gap=gap,
        kn=kn,
        kt=kt,
    )




def build_contact(model: Model) -> ContactElements:
    """Generate the CFEs of every interface of ``model``."""
    if not model.interfaces:
        return ContactElements.empty()
    parts = [interface_elements(model, itf) for itf in model.interfaces]
    cat = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    iface = np.concatenate([np.full(len(p["local"]), i) for i, p in enumerate(parts)])
    return ContactElements(names=tuple(i.name for i in model.interfaces), interface=iface, **cat)
