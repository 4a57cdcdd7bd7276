"""Contact finite elements (CFEs) of frame type: generation along interfaces, geometry arrays.

A CFE k joins a point of S+ to the opposite point of S− (method.md §2).  Its kinematics are

    u_τk = t_k · (u⁺ − u⁻),        u_nk = −n_k · (u⁺ − u⁻) − g_k⁰

with n_k the unit normal pointing from S− to S+, t_k = (n_y, −n_x) (n turned clockwise:
+x for an interface whose normal is +y), g_k⁰ ≥ 0 the initial gap.
So u_n ≤ 0 means no interpenetration and u_n < 0 is an open gap (article sign convention).
Its end on S− may lie inside a boundary edge and is then interpolated from that edge's nodes
(node-to-segment); the meshes of the two sides need not match.  Mortar CFEs sit on the nodes of
the coarser side, S+ or S−, their other end a weighted combination of the nodes opposite
(:func:`_mortar_elements`): the kinematics above do not depend on which side is called S+.

Forces: N_k (normal, ≤ 0 in compression) and Q_k (tangential) with |Q_k| ≤ −f_k N_k, eq. (1).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from stepcontact.contact.boundary import (
    chain_order,
    curve_edges,
    edge_shape,
    near_pairs,
    outward_normals,
    tributary_lengths,
)
from stepcontact.contact.interface3d import interface_parts
from stepcontact.contact.layout import ContactLayout
from stepcontact.errors import ModelError
from stepcontact.model import Body, Frame, Interface, Model, RigidObstacle

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
    cn : (m,) float
        Normal damping of the contact layer, N·s/m (0: none; dynamics only, a Kelvin–Voigt
        layer: :mod:`stepcontact.solver.dynamic`).
    bond : (m, 5) float
        Initial strength of bonded CFEs (eq. (12), :data:`~stepcontact.contact.laws.BOND_COLUMNS`:
        N_R, Q_R in N, α_R, 1/α_t, and the residual cohesion C_r A in N after the break); NaN
        rows for CFEs without a bond.
    n_t : int
        Tangential components per CFE: 1 (2D), 2 (3D: a discrete model with two tangential
        directions).  The geometry arrays above keep their 2D shapes; a set of CFEs without
        geometry (a discrete model) has them NaN, also with n_t = 2.
    facets : int
        Number k of facets of the faceted Coulomb cone (n_t = 2; 2 in 2D: slip+ and slip−).
    facet_angle : (m,) float
        Direction of vertex 0 of each CFE's polygon, rad, from t₁ towards t₂ (0 in 2D).
    facet_stagger : bool
        Every other CFE's polygon (odd k) turned by π/k more (the law applies it).
    facet_adaptive : bool
        Each CFE's polygon turned at its first slip so that a vertex lies on its force.
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
    cn: np.ndarray | None = None
    bond: np.ndarray | None = None
    n_t: int = 1
    facets: int = 2
    facet_angle: np.ndarray | None = None
    facet_stagger: bool = False
    facet_adaptive: bool = False

    def __post_init__(self):
        if self.cn is None:
            object.__setattr__(self, "cn", np.zeros(len(self.interface)))
        if self.bond is None:
            object.__setattr__(self, "bond", np.full((len(self.interface), 5), np.nan))
        if self.facet_angle is None:
            object.__setattr__(self, "facet_angle", np.zeros(len(self.interface)))

    @property
    def bonded(self) -> np.ndarray:
        """(m,) bool: CFEs with an initial strength (eq. (12))."""
        return ~np.isnan(self.bond[:, 0])

    @property
    def m(self) -> int:
        return len(self.interface)

    def __len__(self) -> int:
        return self.m

    @cached_property
    def layout(self) -> ContactLayout:
        """The layout of the contact unknowns of these CFEs (n_t tangential components)."""
        return ContactLayout(self.m, self.n_t)

    @property
    def basis(self) -> np.ndarray:
        """The local basis of every CFE, (m, 2, 2): rows t, n."""
        return self.layout.basis(self.tangent, self.normal)

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


def _to_segments(x: np.ndarray, a: np.ndarray, b: np.ndarray, j: np.ndarray):
    """Closest points of x[i] on the segments [a_j, b_j], j = j[i]: (ξ in [0, 1], distance)."""
    ab = b[j] - a[j]
    t = np.clip(np.einsum("ij,ij->i", x - a[j], ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    return t, np.linalg.norm(x - (a[j] + t[:, None] * ab), axis=1)


def _project(x: np.ndarray, a: np.ndarray, b: np.ndarray):
    """Closest point of each x on the segments [a_j, b_j]: (segment index, ξ in [0,1], dist).

    Exact and O(n log n): the segments' midpoints in a k-d tree give a first candidate at
    distance d; any closer segment has its midpoint within d + (longest segment)/2.  Ties go
    to the lowest segment index."""
    from scipy.spatial import cKDTree

    x = np.asarray(x, dtype=float).reshape(-1, 2)
    mid = 0.5 * (a + b)
    half = 0.5 * float(np.linalg.norm(b - a, axis=1).max(initial=0.0))
    tree = cKDTree(mid)
    k = min(4, len(a))
    _, cand = tree.query(x, k=k)
    cand = np.asarray(cand).reshape(len(x), -1)
    _, d = _to_segments(np.repeat(x, cand.shape[1], axis=0), a, b, cand.ravel())
    best = d.reshape(len(x), -1).min(axis=1)
    rows, cols = near_pairs(tree, x, best + half + 1e-12 * (best + half + 1.0))
    t, d = _to_segments(x[rows], a, b, cols)
    order = np.lexsort((cols, d, rows))  # by point, then distance, then segment index
    first = np.searchsorted(rows[order], np.arange(len(x)))
    pick = order[first]
    return cols[pick], t[pick], d[pick]


def interface_elements(model: Model, itf: Interface) -> dict[str, np.ndarray]:
    """Arrays of the CFEs of one interface (see :class:`ContactElements`); those of a 3D
    model from :func:`stepcontact.contact.interface3d.interface_parts`."""
    item = f"interface '{itf.name}'"
    bp = model.body(itf.plus.body)
    if model.dim == 3:
        scale = max(1.0, float(np.ptp(model.points, axis=0).max()))
        p = interface_parts(model, itf, 1e-9 * scale)
        return _finish(model, itf, p["order"], p["xp"], p["xm"], p["nrm"], p["s"], p["trib"],
                       p["n_m"], p["wm"], 1e-9 * scale, scale, plus=p.get("plus"),
                       geo_gap=p["geo_gap"], tan=p["tan"])
    obstacle = isinstance(itf.minus, RigidObstacle)
    bm = None if obstacle else model.body(itf.minus.body)
    model.global_nodes(itf.plus)
    if not obstacle:
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
    if obstacle:
        return _obstacle_elements(model, itf, order, xp, s, trib, tol, scale)

    medges = curve_edges(bm, itf.minus)
    if len(medges) == 0:
        raise ModelError(f"{item}.minus", "the node set contains no edge of the body to project on")
    kind = itf.cfe
    if kind in ("auto", "node-to-node"):
        match = _coincident(bp.points[order], bm.points, itf.minus.index, tol)
        if kind == "node-to-node" or (np.all(match >= 0) and _conforming(bp, bm, itf, tol)):
            return _node_to_node(model, itf, order, xp, s, trib, match, tol, scale)
    if kind in ("auto", "mortar") and len(curve_edges(bp, itf.plus)):
        out = _mortar_elements(model, itf, order, xp, s, tol, scale)
        if out is not None:
            return out
    if kind == "mortar":
        raise ModelError(f"{item}.plus", "mortar CFEs need edges on both sides, and S+ and S- "
                                         "must overlap: no edge of S+ faces an edge of S-")
    a = bm.points[medges[:, 0]]
    b = bm.points[medges[:, 1]]
    seg, xi, _ = _project(xp, a, b)
    # snap to nodes: node-to-node where the meshes match
    L = np.linalg.norm(b - a, axis=1)[seg]
    xi = np.where(xi * L <= tol, 0.0, np.where((1 - xi) * L <= tol, 1.0, xi))
    quad = medges.shape[1] == 3
    w_m = edge_shape(xi, quad)
    n_m = np.zeros((m, MAX_END_NODES), dtype=np.int64) - 1
    n_m[:, : medges.shape[1]] = medges[seg] + off[bm.name]
    wm = np.zeros((m, MAX_END_NODES))
    wm[:, : medges.shape[1]] = w_m
    xm = a[seg] + xi[:, None] * (b - a)[seg]

    if itf.normal is not None:
        nrm = np.tile(np.asarray(itf.normal, float) / np.linalg.norm(itf.normal), (m, 1))
    else:
        nout = outward_normals(bm, medges)
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


def _coincident(xp: np.ndarray, pts_m: np.ndarray, minus_index: np.ndarray,
                tol: float) -> np.ndarray:
    """For each S+ point, the S− node (local id, from ``minus_index``) at the same place, or −1."""
    from scipy.spatial import cKDTree

    idx = np.asarray(minus_index, dtype=np.int64)
    dist, j = cKDTree(pts_m[idx]).query(xp)
    return np.where(dist <= tol, idx[np.minimum(j, len(idx) - 1)], -1)


def _conforming(bp: Body | Frame, bm: Body | Frame, itf: Interface, tol: float) -> bool:
    """Do the meshes of S+ and S− match: every node of an S− edge has an S+ node at its place?"""
    mnodes = np.unique(curve_edges(bm, itf.minus))
    back = _coincident(bm.points[mnodes], bp.points, itf.plus.index, tol)
    return bool(np.all(back >= 0))


def _node_to_node(model: Model, itf: Interface, order, xp, s, trib, match, tol, scale):
    """CFEs joining each S+ node to the S− node at the same place (matching meshes)."""
    bad = np.flatnonzero(match < 0)
    if bad.size:
        k = int(bad[0])
        raise ModelError(
            f"interface '{itf.name}' CFE {k} at ({xp[k, 0]:.6g}, {xp[k, 1]:.6g})",
            "cfe = 'node-to-node' needs an S- node at every S+ node; none is there (use "
            "'mortar' for meshes that do not match)")
    bm = model.body(itf.minus.body)
    m = len(order)
    n_m = np.full((m, MAX_END_NODES), -1, dtype=np.int64)
    n_m[:, 0] = match + model.node_offsets[bm.name]
    wm = np.zeros((m, MAX_END_NODES))
    wm[:, 0] = 1.0
    xm = bm.points[match]
    if itf.normal is not None:
        nrm = np.tile(np.asarray(itf.normal, float) / np.linalg.norm(itf.normal), (m, 1))
    else:
        nrm = _nodal_normals_of_minus(model, itf, xp, tol)
    return _finish(model, itf, order, xp, xm, nrm, s, trib, n_m, wm, tol, scale)


def _nodal_normals_of_minus(model: Model, itf: Interface, xp: np.ndarray, tol: float):
    """Outward normal of S− at the edge nearest to each point (the node-to-segment choice)."""
    bm = model.body(itf.minus.body)
    medges = curve_edges(bm, itf.minus)
    seg, _, dist = _project(xp, bm.points[medges[:, 0]], bm.points[medges[:, 1]])
    nout = outward_normals(bm, medges)
    if nout is not None:
        return nout[seg]
    k = int(np.argmin(dist))
    raise ModelError(f"interface '{itf.name}' CFE {k}",
                     "its ends coincide on a frame and no normal is given")


def _gauss01(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre points and weights on [0, 1]."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


#: Gauss points on each S+/S− overlap: exact for polynomials up to degree 7, i.e. for the
#: products φ_i ψ_l of quadratic edges (degree 4) and their gap integrand (degree 3).
MORTAR_GAUSS = 4


def _edge_normals(mbody: Body | Frame, obody: Body | Frame, medges, oedges, pair_e, pair_f, h,
                  where: str):
    """Unit normals of the edges of the multiplier side M pointing from the other side O
    towards M: −(outward normal of M) for a continuum M; for a frame M the outward normal of
    the O edge it faces, or (two frames) the side M lies on.  ``where`` names M's edges in
    the error raised when the side cannot be told."""
    pts = mbody.points
    d = pts[medges[:, 1]] - pts[medges[:, 0]]
    d /= np.linalg.norm(d, axis=1)[:, None]
    n = np.column_stack([-d[:, 1], d[:, 0]])
    out_m = outward_normals(mbody, medges)
    if out_m is not None:
        return -out_m
    sign = np.zeros(len(medges))
    out_o = outward_normals(obody, oedges)
    if out_o is not None:
        np.add.at(sign, pair_e, np.einsum("ij,ij->i", n[pair_e], out_o[pair_f]))
    else:  # two frames: M lies on the side opposite to the gap
        np.add.at(sign, pair_e, -h)
    faced = np.unique(pair_e)
    if np.any(sign[faced] == 0):
        e = int(faced[np.flatnonzero(sign[faced] == 0)[0]])
        raise ModelError(f"{where}.normal", f"cannot tell which side of edge {e} faces the "
                         "other side of the interface: give the normal")
    return n * np.where(sign == 0, 1.0, np.sign(sign))[:, None]


def _mortar_pairs(pa, pb, ma, mb, tol):
    """Overlaps of S+ edges [pa, pb] with S− edges [ma, mb], projected along each S+ edge's
    normal: (e, f, ξ_lo, ξ_hi, ξ of S− ends, signed normal distance at mid-overlap).

    Where S− edges at different distances overlap one S+ edge (the far side of a curved
    body), only those within one edge length of the nearest are kept.  The candidates of an S+
    edge are the S− edges whose midpoints lie within d + 2.5 (L + L_max) of its midpoint (d its
    distance to S−, L its length, L_max the longest S− edge): a k-d tree, not all pairs.
    """
    from scipy.spatial import cKDTree

    L = np.linalg.norm(pb - pa, axis=1)
    e1 = (pb - pa) / L[:, None]
    nv = np.column_stack([-e1[:, 1], e1[:, 0]])
    Lm = np.linalg.norm(mb - ma, axis=1)
    cp = 0.5 * (pa + pb)
    _, _, d = _project(cp, ma, mb)
    e, f = near_pairs(cKDTree(0.5 * (ma + mb)), cp, d + 2.5 * (L + Lm.max(initial=0.0)) + tol)
    xa = np.einsum("ik,ik->i", ma[f] - pa[e], e1[e]) / L[e]
    xb = np.einsum("ik,ik->i", mb[f] - pa[e], e1[e]) / L[e]
    lo = np.clip(np.minimum(xa, xb), 0.0, 1.0)
    hi = np.clip(np.maximum(xa, xb), 0.0, 1.0)
    ok = (hi - lo) * L[e] > tol
    if not np.any(ok):
        return None
    e, f, xa, xb, lo, hi = e[ok], f[ok], xa[ok], xb[ok], lo[ok], hi[ok]
    mid = 0.5 * (lo + hi)
    eta = (mid - xa) / (xb - xa)
    xm = ma[f] + eta[:, None] * (mb[f] - ma[f])
    xpl = pa[e] + mid[:, None] * (pb[e] - pa[e])
    h = np.einsum("ij,ij->i", xm - xpl, nv[e])
    hmin = np.full(len(pa), np.inf)
    np.minimum.at(hmin, e, np.abs(h))
    keep = np.abs(h) <= hmin[e] + np.maximum(L[e], Lm[f]) + tol
    out = np.column_stack([e, f, lo, hi, xa, xb, h])[keep]
    return out[np.lexsort((out[:, 1], out[:, 0]))]  # by S+ edge, then S− edge


def _mean_edge_lengths(pa, pb, ma, mb, tol) -> tuple[float, float] | None:
    """Mean edge lengths (m) of S+ [pa, pb] and S− [ma, mb] where they face each other, each
    weighted by the length of the overlap pieces (the pieces of :func:`_mortar_pairs` seen
    from S+); None when no S+ edge faces S−."""
    pairs = _mortar_pairs(pa, pb, ma, mb, tol)
    if pairs is None:
        return None
    e, f = pairs[:, 0].astype(np.int64), pairs[:, 1].astype(np.int64)
    Lp = np.linalg.norm(pb - pa, axis=1)[e]
    Lm = np.linalg.norm(mb - ma, axis=1)[f]
    share = (pairs[:, 3] - pairs[:, 2]) * Lp
    return float(share @ Lp / share.sum()), float(share @ Lm / share.sum())


def multipliers_on_plus(model: Model, itf: Interface) -> bool:
    """Do the mortar CFEs of ``itf`` sit on S+ (True) or on S− (False)?

    On the coarser side of the two, whichever the user called S+: the overlap-weighted mean
    edge lengths (:func:`_mean_edge_lengths`) decide, S+ on a tie (equal within 1e-9).  See
    :func:`_mortar_elements` for why.
    """
    bp, bm = model.body(itf.plus.body), model.body(itf.minus.body)
    pe, me = curve_edges(bp, itf.plus), curve_edges(bm, itf.minus)
    if len(pe) == 0 or len(me) == 0:
        return True
    P, M = bp.points, bm.points
    scale = max(1.0, float(np.ptp(model.points, axis=0).max()))
    h = _mean_edge_lengths(P[pe[:, 0]], P[pe[:, 1]], M[me[:, 0]], M[me[:, 1]], 1e-9 * scale)
    return h is None or h[0] >= h[1] * (1.0 - 1e-9)


def _dual_mortar(model: Model, itf: Interface, on_plus: bool, tol: float) -> dict | None:
    """Dual mortar CFEs with the multiplier side M = S+ (``on_plus``) or S−, one per node k of
    M that faces the other side O (see :func:`_mortar_elements`).

    Returns None when no M edge faces O, else a dict of arrays over those nodes, in their
    order along M: ``node`` (local ids on M), ``D`` (∫φ_k ds over the faced part, m),
    ``cols``, ``w`` (global O nodes and their weights ∫ψ_k φ_l ds / D_k, padded with −1, 0),
    ``normal`` (unit, S− → S+), ``x`` (node k), ``x_other`` (its closest point on O), ``seg``,
    ``t`` (that point's O edge and position ξ on it) and ``gap`` (the signed distance
    (x⁺ − x⁻)·n between the two).
    """
    mset, oset = (itf.plus, itf.minus) if on_plus else (itf.minus, itf.plus)
    mbody, obody = model.body(mset.body), model.body(oset.body)
    medges, oedges = curve_edges(mbody, mset), curve_edges(obody, oset)
    X, Y = mbody.points, obody.points
    pairs = _mortar_pairs(X[medges[:, 0]], X[medges[:, 1]], Y[oedges[:, 0]], Y[oedges[:, 1]],
                          tol)
    if pairs is None:
        return None
    order, _ = chain_order(mbody, mset)
    trib = tributary_lengths(mbody, mset)[order]
    e, f = pairs[:, 0].astype(np.int64), pairs[:, 1].astype(np.int64)
    lo, hi, xa, xb, h = pairs[:, 2:].T
    m = len(order)
    pos = np.full(mbody.n_nodes, -1, dtype=np.int64)
    pos[order] = np.arange(m)

    # Gauss points of every overlap piece, on the M edge (ξ) and on the O edge (η)
    tg, wg = _gauss01(MORTAR_GAUSS)
    Lm = np.linalg.norm(X[medges[:, 1]] - X[medges[:, 0]], axis=1)[e]
    xi = lo[:, None] + (hi - lo)[:, None] * tg[None]
    w = ((hi - lo) * Lm)[:, None] * wg[None]
    eta = (xi - xa[:, None]) / (xb - xa)[:, None]
    phi = edge_shape(xi.ravel(), medges.shape[1] == 3).reshape(*xi.shape, -1)
    psi = edge_shape(eta.ravel(), oedges.shape[1] == 3).reshape(*eta.shape, -1)
    ne_, n_m = len(medges), medges.shape[1]
    phi, dropped = _lump_beyond_ends(medges, e, lo, hi, phi, tol / Lm)

    # dual (biorthogonal) weights on each M edge: ψ_i = Σ_j A_ij φ_j, A = D M⁻¹ with
    # M_ij = ∫ φ_i φ_j and D = diag(∫ φ_i) over the part of the edge that faces O, so that
    # ∫ ψ_i φ_j = δ_ij ∫ φ_i: the M end of CFE k is node k itself, as in the article's CFE
    Me = np.zeros((ne_, n_m, n_m))
    np.add.at(Me, e, np.einsum("pg,pgi,pgj->pij", w, phi, phi))
    Me += np.eye(n_m)[None] * dropped[:, :, None]  # lumped functions: decoupled, D = 0
    De = np.zeros((ne_, n_m))
    np.add.at(De, e, np.einsum("pg,pgi->pi", w, phi))
    faced = np.unique(e)
    A = np.zeros_like(Me)
    A[faced] = np.linalg.solve(Me[faced], np.eye(n_m)[None] * De[faced][:, :, None])
    A = np.swapaxes(A, 1, 2)  # solve gave M⁻¹ D (M symmetric); A = D M⁻¹ is its transpose
    dual = np.einsum("pij,pgj->pgi", A[e], phi)

    rows = pos[medges[e]]  # (pairs, n_m): the CFE of each M node of the pair's edge
    D = np.zeros(m)
    np.add.at(D, pos[medges[faced]], De[faced])
    W = np.einsum("pg,pgi,pgl->pil", w, dual, psi)
    n_o = oedges.shape[1]
    r_o = np.repeat(rows[:, :, None], n_o, 2)
    c_o = np.repeat(oedges[f][:, None, :], n_m, 1) + model.node_offsets[obody.name]

    mortar = D > 1e-9 * trib  # M nodes that face O
    if not np.any(mortar):
        return None
    # the M edge normals, oriented O → M, averaged at the nodes with the overlap weights, and
    # turned to point S− → S+
    side = "plus" if on_plus else "minus"
    ne = _edge_normals(mbody, obody, medges, oedges, e, f, h, f"interface '{itf.name}'.{side}")
    if not on_plus:
        ne = -ne
    if itf.normal is not None:
        nrm = np.tile(np.asarray(itf.normal, float) / np.linalg.norm(itf.normal), (m, 1))
    else:
        nrm = np.zeros((m, 2))
        np.add.at(nrm, pos[medges[faced]], De[faced][..., None] * ne[faced][:, None, :])
        nrm[mortar] /= np.linalg.norm(nrm[mortar], axis=1)[:, None]

    keep = mortar[r_o.ravel()]
    rr, cc = r_o.ravel()[keep], c_o.ravel()[keep]
    cols, wts = _pad_rows(_sparse((W.ravel()[keep] / D[rr], (rr, cc)), m, model.points.shape[0]))

    # M nodes whose edges face no part of O, or that lie beyond its ends (lumped), get no CFE:
    # there is no surface opposite them for a mutual displacement to be measured against
    k = np.flatnonzero(mortar)
    # the initial gap at the node (its distance to O along n_k), not its weighted mean: two
    # curved bodies touching at a node are then in contact from the start, where the weighted
    # mean would open every CFE by O(h²/R) and leave the bodies floating
    a, b = Y[oedges[:, 0]], Y[oedges[:, 1]]
    x = X[order[k]]
    seg, t, _ = _project(x, a, b)
    x_other = a[seg] + t[:, None] * (b - a)[seg]
    if itf.normal is None:
        nrm = _common_normals(mbody, obody, medges, oedges, ne, e, f, w.sum(axis=1),
                              order[k], nrm[k], seg, t)
    else:
        nrm = nrm[k]
    gap = np.einsum("ij,ij->i", x - x_other, nrm) * (1.0 if on_plus else -1.0)
    return dict(node=order[k], D=D[k], cols=cols[k], w=wts[k], normal=nrm, x=x,
                x_other=x_other, seg=seg, t=t, gap=gap)


def _nodal_normals(body: Body | Frame, edges: np.ndarray, edge_n: np.ndarray):
    """Unit normals and curvatures of a curve at its nodes, by body node id (0 elsewhere).

    The normal at an end node is the length-weighted mean of the normals ``edge_n`` of the
    edges meeting there (a mid-side node: its edge's).  The curvature is |κ| = ψ / ((L₁ + L₂)/2)
    (1/m) at a node between two edges turned by ψ, that of its neighbour at an end of the
    curve (0 for a lone edge), and the mean of its edge's ends at a mid-side node.
    """
    n_nodes = body.n_nodes
    ends = edges[:, :2]
    L = np.linalg.norm(body.points[ends[:, 1]] - body.points[ends[:, 0]], axis=1)
    nn = np.zeros((n_nodes, 2))
    turn = np.zeros((n_nodes, 2))
    length = np.zeros(n_nodes)
    for c in (0, 1):
        np.add.at(nn, ends[:, c], L[:, None] * edge_n)
        np.add.at(turn, ends[:, c], edge_n)
        np.add.at(length, ends[:, c], L)
    deg = np.bincount(ends.ravel(), minlength=n_nodes)
    kappa = np.zeros(n_nodes)
    two = deg == 2  # ψ = 2 arccos(|n₁ + n₂| / 2)
    psi = 2.0 * np.arccos(np.clip(np.linalg.norm(turn[two], axis=1) / 2.0, 0.0, 1.0))
    kappa[two] = psi / (length[two] / 2.0)
    lone = np.flatnonzero(deg == 1)
    if lone.size:  # the curve's ends: the neighbour's curvature
        which = np.isin(ends, lone)
        e_of, side = np.nonzero(which)
        kappa[ends[e_of, side]] = kappa[ends[e_of, 1 - side]]
    if edges.shape[1] == 3:
        nn[edges[:, 2]] = edge_n
        kappa[edges[:, 2]] = 0.5 * (kappa[ends[:, 0]] + kappa[ends[:, 1]])
    used = np.unique(edges)
    nn[used] /= np.linalg.norm(nn[used], axis=1)[:, None]
    return nn, kappa


def _common_normals(mbody, obody, medges, oedges, ne, pair_e, pair_f, share, nodes, n_m,
                    seg, t) -> np.ndarray:
    """Unit normals (S− → S+) of the CFEs at the M ``nodes``: the curvature-weighted mean

        n_k = (|κ_O| n_M + |κ_M| n_O) / (|κ_M| + |κ_O|)        (n_M + n_O where both are 0)

    of the M normal ``n_m`` at the node and the O normal n_O at the point opposite (O edge
    ``seg`` at ξ = ``t``), κ the curvatures of the two curves there (:func:`_nodal_normals`).
    It is the same whichever side carries the CFEs, and it is the normal of the plane that two
    bodies touch in: a curved body on a flat one gets the flat one's normal; two equal
    cylinders their common tangent's (x/R₁ − x/R₂ tilts cancel for any radii).  The normal of
    one side alone would tilt the friction cone by the angle between the two faces, x/R at a
    distance x from the first contact point: under the Hertz pressure a stuck joint would hold
    a shear p·x/R (a third of f p at the edge of the contact for f = 0.3, a/R = 0.1), and the
    stick zone of a cylinder sheared after pressing would come out shifted.
    """
    # the O edge normals, turned to agree with the M normals (S− → S+) of the edges they face
    d = obody.points[oedges[:, 1]] - obody.points[oedges[:, 0]]
    d /= np.linalg.norm(d, axis=1)[:, None]
    no = np.column_stack([-d[:, 1], d[:, 0]])
    agree = np.zeros(len(oedges))
    np.add.at(agree, pair_f, share * np.einsum("ij,ij->i", no[pair_f], ne[pair_e]))
    mean = (share[:, None] * ne[pair_e]).sum(axis=0)
    agree = np.where(agree == 0, no @ mean, agree)  # O edges facing no M edge
    no *= np.where(agree < 0, -1.0, 1.0)[:, None]
    _, k_m = _nodal_normals(mbody, medges, ne)
    nn_o, k_o = _nodal_normals(obody, oedges, no)
    a, b = oedges[seg, 0], oedges[seg, 1]
    n_o = (1 - t)[:, None] * nn_o[a] + t[:, None] * nn_o[b]
    n_o /= np.linalg.norm(n_o, axis=1)[:, None]
    km, ko = k_m[nodes], (1 - t) * k_o[a] + t * k_o[b]
    flat = km + ko == 0
    wm = np.where(flat, 0.5, ko / np.where(flat, 1.0, km + ko))
    n = wm[:, None] * n_m + (1 - wm)[:, None] * n_o
    return n / np.linalg.norm(n, axis=1)[:, None]


def _lump_beyond_ends(medges, pair_e, lo, hi, phi, tol_xi):
    """Shape functions φ̃ of the M edges (Gauss values ``phi``, (pairs, points, n)) with the
    functions of the nodes that lie beyond the ends of O lumped into the nearest node of the
    same edge that faces O, and which (edge, node) functions were lumped, (edges, n) bool.

    A node faces O when an overlap piece [ξ_lo, ξ_hi] of one of its edges covers its ξ (0, 1,
    ½ at a mid-side node).  An M edge that reaches beyond O (a foundation wider than the
    structure on it) keeps a partition of unity on the part that faces O, so the patch test
    holds there, and no CFE is made beyond O, where it would act at a point outside the
    contact (Wohlmuth's modification of the multiplier space at the end of the interface).
    An edge none of whose nodes faces O (O shorter than one M edge) is left as it is, and so
    is every edge when fewer than two nodes of M face O: the lumped functions would then be
    constants only, which carry no moment (a body standing on one node of a coarser face
    could turn).  Lumping also keeps the dual weights bounded: on a sliver of an edge the
    functions of its nodes are nearly dependent and their dual weights large (round-off of
    1e-8 relative in the contact conditions on quadratic edges facing O over a sixth).
    """
    n = medges.shape[1]
    xi_node = np.array([0.0, 1.0, 0.5])[:n]
    t = tol_xi[:, None]
    cover = (lo[:, None] <= xi_node + t) & (hi[:, None] >= xi_node - t)  # (pairs, n)
    faces = np.zeros(int(medges.max()) + 1, dtype=bool)
    faces[medges[pair_e][cover]] = True
    keep = faces[medges]  # (edges, n)
    if faces.sum() < 2:
        keep[:] = True
    keep[~keep.any(axis=1)] = True  # no node faces O: leave the edge alone
    gap = np.abs(xi_node[:, None] - xi_node[None])  # (i, j) distances in ξ
    dist = np.where(keep[:, None, :], gap[None], np.inf)
    target = np.where(keep, np.arange(n)[None], np.argmin(dist, axis=2))  # (edges, n)
    T = np.zeros((len(medges), n, n))
    np.put_along_axis(T, target[:, :, None], 1.0, axis=2)
    return np.einsum("pgi,pij->pgj", phi, T[pair_e]), ~keep


def _mortar_elements(model: Model, itf: Interface, order, xp, s, tol, scale):
    """Segment-to-segment (mortar) CFEs, one per node k of the multiplier side M.

    M is the **coarser** of S+ and S− (:func:`multipliers_on_plus`), whichever the user
    called S+; the other side is O.  The mutual displacement of CFE k is the M shape function
    φ_k-weighted mean over the overlap Γ_k of M and O (exact clipping of the segments,
    projected along the M edge normals, and Gauss integration on each overlap piece):

        u_k⁺ − u_k⁻ = (1/D_k) ∫_Γk φ_k (u⁺ − u⁻) ds,        D_k = ∫_Γk φ_k ds,

    so that u_τk and u_nk are the slip and the gap in the sense of a weighted average, and the
    forces N_k, Q_k act on both sides through the same weights (a uniform contact pressure p
    is N_k = p D_k × thickness on every CFE: the contact patch test, in either orientation).
    With the dual (biorthogonal) weights ψ_k the M end of CFE k is node k itself and its O end
    the combination (1/D_k) Σ_l (∫ψ_k φ_l ds) u_l of the O nodes.  The normal n_k is the
    curvature-weighted mean of the two faces' normals there, pointing from S− to S+
    (:func:`_common_normals`: the same whichever side is M), and the initial gap the node's
    distance to O along n_k.  M nodes whose edges face no O edge, or that lie beyond the ends
    of O, get no CFE (:func:`_lump_beyond_ends`).  Returns None when no edge of M faces O.

    Why the coarser side: the constraints u_nk ≥ 0 hold for the weighted means over the M
    nodes.  On the finer side there are more of them than the coarser side has nodes to
    follow: where the joint is closed, the finer side is forced onto the dual projection of
    the coarser side's piecewise-polynomial trace, which wiggles at the coarser side's nodes,
    and the pressures oscillate from CFE to CFE (±2–4 % of the peak in the Hertz test at a
    ratio 1.6), so that a joint near its opening limit opens early (8 % at 1.25) and a stick
    zone comes out too small.  On the coarser side the constraints are the coarser side's
    means of the finer side's trace, which the finer side meets without a wiggle.  Since
    u_τ = t·(u⁺ − u⁻) and u_n = −n·(u⁺ − u⁻) − g⁰ do not change when S+ and S− are swapped
    (n, t and u⁺ − u⁻ all change sign), both orientations give the same CFEs, the same
    operator B and the same N, Q, u_n, u_τ; only the CFE's reported point (``x``, ``s``) is
    on the side the user called S+: with M = S− it is the point Σ_l w_kl x_l of its S+ end
    (where its forces act on S+, so that moments of the CFE forces about any point are exact),
    ``s`` the arc length of its closest point on S+, and the CFEs are numbered along S+.

    The choice is exact (no threshold: the finer side never carries the CFEs, on a tie
    either may) and robust (each side is a plain dual mortar discretisation; the patch test
    holds in both orientations).  A segment-to-segment formulation on the common refinement,
    with one constraint per piece, would over-constrain a rigid joint (more constraints than
    the coarser side has nodes) and make the contact forces non-unique.
    """
    bp = model.body(itf.plus.body)
    on_plus = multipliers_on_plus(model, itf)
    r = _dual_mortar(model, itf, on_plus, tol)
    if r is None:
        return None
    own = np.full((len(r["node"]), 1), -1, dtype=np.int64)
    one = np.ones((len(r["node"]), 1))
    if on_plus:
        k = _positions(order, r["node"])
        own[:, 0] = r["node"] + model.node_offsets[bp.name]
        return _finish(model, itf, order[k], xp[k], r["x_other"], r["normal"], s[k], r["D"],
                       r["cols"], r["w"], tol, scale, plus=(own, one), geo_gap=r["gap"])
    # M = S−: each CFE's S+ end is the weighted combination Σ_l w_l x_l of S+ nodes, reported
    # at that point (the point its forces on S+ act at: their moment is exact) and at the arc
    # length along S+ of its closest point
    bm = model.body(itf.minus.body)
    own[:, 0] = r["node"] + model.node_offsets[bm.name]
    valid = r["cols"] >= 0
    pts = model.points[np.where(valid, r["cols"], 0)]
    x_plus = np.einsum("kl,klc->kc", np.where(valid, r["w"], 0.0), pts)
    pe = curve_edges(bp, itf.plus)
    seg, t, _ = _project(x_plus, bp.points[pe[:, 0]], bp.points[pe[:, 1]])
    t = np.where(t < 1e-12, 0.0, np.where(t > 1.0 - 1e-12, 1.0, t))  # at a node: its s
    s_node = np.zeros(bp.n_nodes)
    s_node[order] = s
    s_x = (1 - t) * s_node[pe[seg, 0]] + t * s_node[pe[seg, 1]]
    o = np.argsort(s_x, kind="stable")
    return _finish(model, itf, r["node"][o], x_plus[o], r["x"][o], r["normal"][o],
                   s_x[o], r["D"][o], own[o], one[o], tol, scale, plus=(r["cols"][o], r["w"][o]),
                   geo_gap=r["gap"][o])


def _positions(order: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """Index in ``order`` of each of ``nodes`` (all present)."""
    pos = np.full(int(max(order.max(), nodes.max())) + 1, -1, dtype=np.int64)
    pos[order] = np.arange(len(order))
    return pos[nodes]


def _sparse(data, m: int, n: int):
    import scipy.sparse as sp

    return sp.csr_matrix(data, shape=(m, n))


def _pad_rows(A) -> tuple[np.ndarray, np.ndarray]:
    """A CSR matrix's rows as (m, width) arrays of columns (−1 padding) and values."""
    A.sum_duplicates()
    A.eliminate_zeros()
    counts = np.diff(A.indptr)
    width = max(int(counts.max()) if counts.size else 1, 1)
    cols = np.full((A.shape[0], width), -1, dtype=np.int64)
    vals = np.zeros((A.shape[0], width))
    r = np.repeat(np.arange(A.shape[0]), counts)
    j = np.arange(A.nnz) - A.indptr[r]
    cols[r, j] = A.indices
    vals[r, j] = A.data
    return cols, vals


def _widen(a: np.ndarray, width: int, fill: float = -1) -> np.ndarray:
    """``a`` padded on the right to ``width`` columns with ``fill``."""
    if a.shape[1] >= width:
        return a
    pad = np.full((a.shape[0], width - a.shape[1]), fill, dtype=a.dtype)
    return np.concatenate([a, pad], axis=1)


def _obstacle_elements(model: Model, itf: Interface, order, xp, s, trib, tol, scale):
    """CFEs of S+ against a rigid obstacle (``itf.minus``), one per S+ node.

    The S− end of CFE k is the node's closest point x⁻ on the polyline and n_k the normal of
    its segment (towards the bodies), so that g_k⁰ = (x⁺ − x⁻)·n_k is the distance.  Where the
    closest point is a vertex between two segments, n_k is the direction from the vertex to the
    node (a node in front of a ridge), or, where they coincide or the node lies behind the
    vertex, the mean of the two segment normals.  S+ nodes whose projection falls beyond an end
    of the polyline get no CFE.  A fixed obstacle has no nodes (``minus_nodes`` −1); the end of
    a moving one is interpolated from its segment's vertex nodes (weights 1 − ξ, ξ).
    """
    obs = itf.minus
    item = f"interface '{itf.name}'"
    P = obs.points
    a, b = P[:-1], P[1:]
    nseg = obs.normals
    nv = len(P)
    seg, xi, dist = _project(xp, a, b)
    ab = (b - a)[seg]
    L = np.linalg.norm(ab, axis=1)
    t_raw = np.einsum("ij,ij->i", xp - a[seg], ab) / L**2
    beyond = ((seg == 0) & (t_raw * L < -tol)) | ((seg == nv - 2) & ((t_raw - 1) * L > tol))
    keep = np.flatnonzero(~beyond)
    if keep.size == 0:
        raise ModelError(item, f"no node of {itf.plus.label} lies opposite obstacle "
                         f"'{obs.name}' (every one projects beyond its ends): extend the "
                         "obstacle's points or check the node set")
    xp, order, s, trib = xp[keep], order[keep], s[keep], trib[keep]
    seg, xi, dist = seg[keep], xi[keep], dist[keep]
    m = len(order)
    xm = a[seg] + xi[:, None] * (b - a)[seg]
    if itf.normal is not None:
        nrm = np.tile(np.asarray(itf.normal, float) / np.linalg.norm(itf.normal), (m, 1))
    else:
        nrm = nseg[seg].copy()
        # closest point at a vertex between two segments
        Ls = np.linalg.norm(b - a, axis=1)[seg]
        vtx = np.where(xi * Ls <= tol, seg, np.where((1.0 - xi) * Ls <= tol, seg + 1, -1))
        inner = np.flatnonzero((vtx > 0) & (vtx < nv - 1))
        if inner.size:
            v = vtx[inner]
            mean = nseg[v - 1] + nseg[v]
            mean /= np.linalg.norm(mean, axis=1)[:, None]
            d = xp[inner] - P[v]
            front = (dist[inner] > tol) & (np.einsum("ij,ij->i", d, mean) > 0)
            nrm[inner] = np.where(front[:, None], d / np.maximum(dist[inner], tol)[:, None],
                                  mean)
    n_m = np.full((m, MAX_END_NODES), -1, dtype=np.int64)
    wm = np.zeros((m, MAX_END_NODES))
    off = model.obstacle_offsets.get(obs.name)
    if off is not None:  # a moving obstacle: its vertices are nodes
        n_m[:, 0], n_m[:, 1] = off + seg, off + seg + 1
        wm[:, 0], wm[:, 1] = 1.0 - xi, xi
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


def _finish(model: Model, itf: Interface, order, xp, xm, nrm, s, trib, n_m, wm, tol, scale,
            plus: tuple[np.ndarray, np.ndarray] | None = None,
            geo_gap: np.ndarray | None = None, tan: np.ndarray | None = None):
    """Gaps, areas, layer stiffnesses and the S+ ends: the arrays of one interface (2D or 3D).

    ``plus`` = (nodes, weights) of the S+ ends when they are not the S+ nodes themselves
    (mortar CFEs); ``geo_gap`` their geometric gap when it is not (x⁺ − x⁻)·n; ``tan`` the
    tangents (m, 2, 3) of 3D CFEs (2D: t = (n_y, −n_x)).
    """
    item = f"interface '{itf.name}'"
    bp = model.body(itf.plus.body)
    off = model.node_offsets
    m = len(order)
    if tan is None:
        tan = np.column_stack([nrm[:, 1], -nrm[:, 0]])
    if geo_gap is None:
        geo_gap = np.einsum("ij,ij->i", xp - xm, nrm)
    if itf.gap is None:
        gap = geo_gap
        bad = np.flatnonzero(gap < -1e-6 * scale)
        if bad.size:
            k = int(bad[0])
            raise ModelError(
                f"{item} CFE {k} at {_point(xp[k])}",
                f"S+ penetrates {minus_label(itf)} by {-gap[k]:.3g} m; give a gap or fix the "
                "geometry" + (" (or the obstacle's side: the bodies lie on its left, walking "
                              "along its points, unless side='right')"
                              if isinstance(itf.minus, RigidObstacle) else ""),
            )
        gap = np.maximum(gap, 0.0)
        gap[np.abs(gap) <= tol] = 0.0
    elif callable(itf.gap):
        gap = np.asarray(itf.gap(*xp.T), float) * np.ones(m)
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
        cn = itf.layer.damping * area
    else:
        kn = np.full(m, np.inf)
        kt = np.full(m, np.inf)
        cn = np.zeros(m)
    friction = np.full(m, float(itf.friction))
    bond = np.full((m, 5), np.nan)
    if itf.bond is not None:
        open_ = gap > 1e-9 * max(float(np.ptp(xp)) if m else 0.0, 1.0)
        if np.any(open_):
            k = int(np.flatnonzero(open_)[0])
            raise ModelError(f"{item}.bond", f"a bonded joint must be closed: CFE {k} at "
                             f"{_point(xp[k])} has a gap of {gap[k]:g} m")
        bond = itf.bond.arrays(xp, area, item)
        if itf.bond.friction is not None:
            friction[:] = float(itf.bond.friction)

    if plus is None:
        n_p = np.full((m, MAX_END_NODES), -1, dtype=np.int64)
        n_p[:, 0] = order + off[bp.name]
        wp = np.zeros((m, MAX_END_NODES))
        wp[:, 0] = 1.0
    else:
        n_p, wp = plus
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
        friction=friction,
        gap=gap,
        kn=kn,
        kt=kt,
        cn=cn,
        bond=bond,
    )




def _point(x: np.ndarray) -> str:
    """A point (x, y) or (x, y, z) for a message, m."""
    return "(" + ", ".join(f"{v:.6g}" for v in x) + ")"


def minus_label(itf: Interface) -> str:
    """``S-`` or ``obstacle 'NAME'`` (the S− side of an interface, for messages)."""
    return f"obstacle '{itf.minus.name}'" if isinstance(itf.minus, RigidObstacle) else "S-"


def build_contact(model: Model) -> ContactElements:
    """Generate the CFEs of every interface of ``model``."""
    if not model.interfaces:
        return ContactElements.empty()
    parts = [interface_elements(model, itf) for itf in model.interfaces]
    # one width for both ends of every CFE (the result file gives them one dimension)
    width = max(MAX_END_NODES, *(p[k].shape[1] for p in parts for k in ("plus_nodes",
                                                                          "minus_nodes")))
    for key, fill in (("plus_nodes", -1), ("plus_w", 0.0), ("minus_nodes", -1),
                      ("minus_w", 0.0)):
        for p in parts:
            p[key] = _widen(p[key], width, fill)
    cat = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    iface = np.concatenate([np.full(len(p["local"]), i) for i, p in enumerate(parts)])
    names = tuple(i.name for i in model.interfaces)
    if model.dim != 3:
        return ContactElements(names=names, interface=iface, **cat)
    # 3D: two tangential components on the faceted cone of the interfaces' k facets
    counts = {i.facet_count() for i in model.interfaces}
    if len(counts) > 1:
        raise ModelError(f"interface '{model.interfaces[-1].name}'.facets", "the interfaces of "
                         f"a model share one facet count k, got {sorted(counts)}")
    angle = np.concatenate([np.full(len(p["local"]), float(i.facet_angle))
                            for i, p in zip(model.interfaces, parts, strict=True)])
    return ContactElements(names=names, interface=iface, **cat, n_t=2, facets=counts.pop(),
                           facet_angle=angle)
