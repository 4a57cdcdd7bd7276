"""Water loads whose level is the load parameter: the load as a piecewise polynomial in h.

A load pattern whose water loads have ``level=None`` (:class:`~stepcontact.model.WaterLoad`)
has the water level h (m) as its factor.  Its load is not proportional to h: on every straight
boundary edge e of the wetted faces the consistent nodal force of node i is

    f_ei(h) = g_ei(h) v_ei,   g_ei(h) = γ_w ∫_e φ_i(s) max(h − y(s), 0) ds,   v_ei = −n_e t,

with n_e the outward normal of the edge and t the thickness.  Between the levels of the edge's
end nodes g_ei is a polynomial in h of degree 3 (linear edges) or 4 (quadratic); below the
lower end it is 0, above the upper end linear in h.  So the pattern is assembled as one
*virtual pattern* per (edge, node) with the fixed vector v_ei and the factor g_ei(h):

    f(h) = Σ_p g_p(h) v_p.

Every piece of the solver that works with pattern factors (condensation, recovery of fields,
equilibrium checks, reactions, result files) then works unchanged; the solver moves along the
level with the Taylor coefficients of the g_p (exact within a piece, see
:meth:`LevelBasis.taylor`) and locates events as roots of polynomials.  The pattern's factor is
the level, so the result reports h as its factor; the pattern's other loads (not water loads
that follow the level) are its own load vector, multiplied by h: loads per metre of water,
e.g. an uplift whose head at the heel is the level (head 1 at the heel per unit factor).

**3D bodies** (:class:`FacetWetting`): the wetted faces are facets (triangles or
quadrilaterals, linear or quadratic), z is up and

    g_fi(h) = γ_w ∫_f φ_i max(h − z, 0) dA,   v_fi = −n_f (per node),

integrated exactly: the facet's reference domain is clipped by the level (the wet part of a
flat facet with straight sides — a triangle or a parallelogram — is a polygon in its local
coordinates, Sutherland–Hodgman with one half-plane), cut into triangles and integrated by a
Gauss rule of degree 6 (the integrand φ_i (h − z) dA has degree ≤ 5: biquadratic φ of a
``quad9``).  Between the levels of the corners g_fi is a polynomial in h of degree
deg φ + 3 (4 on ``tri3``, 5 on ``quad4`` and ``tri6``, 6 on ``quad8``, 7 on ``quad9``).  A
wetted facet that is not flat with straight sides (a warped or trapezoidal quadrilateral,
curved quadratic sides) has a wet part that is no polygon: it is refused by name.  The
facets' pieces that share a node and a normal (a flat face) make one virtual pattern, so a
planar face has one per wetted node.  The same integration gives the load of a 3D water load
at a fixed level (:func:`facet_water_forces`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from stepcontact.contact.boundary import continuum_edges, edge_facets, edge_shape, outward_normals
from stepcontact.contact.surface3d import (
    FACET_KINDS,
    Surface,
    _gauss_triangle,
    _reference_sides,
    shape,
    surface_of_mesh,
)
from stepcontact.errors import ModelError
from stepcontact.model import LoadPattern, Model

#: Gauss–Legendre points on the wetted part of an edge: the integrand φ_i (h − y) has degree
#: ≤ 3 along a straight edge, integrated exactly by 3 points (degree 5).
_GX, _GW = np.polynomial.legendre.leggauss(3)
_GX, _GW = 0.5 * (_GX + 1.0), 0.5 * _GW
#: degree of the g_p in h within a piece (4: quadratic edges)
DEGREE = 4
#: separator of a level pattern's name and the index of its virtual patterns
VIRTUAL = "@"


def is_level_pattern(pattern: LoadPattern) -> bool:
    """Does the pattern's factor stand for a water level (its water loads have level=None)?"""
    return any(getattr(ld, "follows_level", False) for ld in pattern.loads)


def virtual_name(pattern: str, k: int) -> str:
    """Name of the k-th virtual pattern of a level pattern."""
    return f"{pattern}{VIRTUAL}{k}"


def is_virtual(name: str) -> bool:
    """Is ``name`` a virtual pattern of a level pattern (not one the user named)?"""
    return VIRTUAL in name


@dataclass(frozen=True, eq=False)
class LevelBasis:
    """The load of one level pattern: f(h) = Σ_p g_p(h) v_p (module docstring).

    Attributes
    ----------
    pattern : str
    names : tuple of str
        The virtual patterns, one per (edge, node) of the wetted faces.
    vectors : (P, ndof) float
        v_p, N per unit g (Pa·m).
    y : (E, 2) float
        Elevations of the two ends of every edge, m.
    length : (E,) float
        Edge lengths, m.
    gamma : (E,) float
        Unit weight of water on each edge, N/m³.
    edge, node : (P,) int
        Edge of each virtual pattern and its local node (shape function) on that edge.
    quadratic : (E,) bool
    """

    pattern: str
    names: tuple[str, ...]
    vectors: np.ndarray
    y: np.ndarray
    length: np.ndarray
    gamma: np.ndarray
    edge: np.ndarray
    node: np.ndarray
    quadratic: np.ndarray
    facets: tuple[FacetWetting, ...] = ()

    @property
    def levels(self) -> np.ndarray:
        """Elevations (m) of the wetted edges' ends and facets' corners: the piece ends."""
        return np.concatenate([self.y.ravel()]
                              + [part.corner_levels.ravel() for part in self.facets])

    @property
    def degree(self) -> int:
        """Degree in h of the g_p within a piece."""
        return max([DEGREE if len(self.edge) else 0] + [p.degree for p in self.facets])

    def factors(self, h: float) -> np.ndarray:
        """g_p(h) (exact): γ_w ∫ φ_i max(h − y, 0) ds over the wetted part of each edge, Pa·m
        (2D), or the sum over a pattern's (facet, node) pairs of γ_w ∫ φ_i max(h − z, 0) dA,
        Pa·m² (3D, :class:`FacetWetting`)."""
        out = self._edge_factors(h) if len(self.edge) else np.zeros(len(self.names))
        for part in self.facets:
            out += part.factors(h)
        return out

    def _edge_factors(self, h: float) -> np.ndarray:
        ya, yb = self.y[:, 0], self.y[:, 1]
        dy = yb - ya
        with np.errstate(divide="ignore", invalid="ignore"):
            tc = np.where(dy != 0, (h - ya) / dy, np.where(h > ya, np.inf, -np.inf))
        # wetted part [t0, t1] of t ∈ [0, 1] where y(t) < h
        t0 = np.where(dy > 0, 0.0, np.clip(tc, 0.0, 1.0))
        t1 = np.where(dy > 0, np.clip(tc, 0.0, 1.0), 1.0)
        flat = dy == 0
        t0 = np.where(flat, 0.0, t0)
        t1 = np.where(flat, np.where(h > ya, 1.0, 0.0), t1)
        t1 = np.maximum(t1, t0)
        t = t0[:, None] + (t1 - t0)[:, None] * _GX[None, :]  # (E, 3)
        w = ((t1 - t0) * self.length * self.gamma)[:, None] * _GW[None, :]
        head = h - (ya[:, None] + t * dy[:, None])
        out = np.zeros(len(self.names))
        for quad in (False, True):
            sel = np.flatnonzero(self.quadratic[self.edge] == quad)
            if sel.size == 0:
                continue
            e = self.edge[sel]
            phi = edge_shape(t[e].ravel(), quad).reshape(len(sel), t.shape[1], -1)
            phi_i = phi[np.arange(len(sel)), :, self.node[sel]]
            out[sel] = np.einsum("pq,pq->p", w[e] * head[e], phi_i)
        return out

    def breaks(self, h0: float, h1: float) -> np.ndarray:
        """Levels strictly between h0 and h1 where some g_p changes polynomial (node levels),
        in the order the path meets them."""
        levels = np.unique(self.levels)
        lo, hi = min(h0, h1), max(h0, h1)
        tol = 1e-12 * max(1.0, abs(lo), abs(hi))
        inner = levels[(levels > lo + tol) & (levels < hi - tol)]
        return inner if h1 >= h0 else inner[::-1]

    def taylor(self, h0: float, h1: float) -> np.ndarray:
        """(d + 1, P) coefficients c_j with g_p(h0 + δ) = Σ_j c_j δ^j for h0 + δ between
        h0 and h1, a part of one piece (no node level strictly inside), d = :attr:`degree`:
        exact, by sampling g at d + 1 points and solving the scaled Vandermonde system."""
        span = h1 - h0
        if span == 0:
            raise ValueError("empty level interval")
        deg = self.degree
        z = np.linspace(0.0, 1.0, deg + 1)
        V = z[:, None] ** np.arange(deg + 1)[None, :]
        G = np.array([self.factors(h0 + zi * span) for zi in z])
        c = np.linalg.solve(V, G)
        return c / (span ** np.arange(deg + 1))[:, None]


#: degree in h of the pieces of g_fi on a wetted facet: deg φ + 3 (module docstring)
FACET_DEGREE = {"tri3": 4, "tri6": 5, "quad4": 5, "quad8": 6, "quad9": 7}
#: Gauss rule on the triangles of a facet's wet part: exact to degree 6
_TX, _TW = _gauss_triangle(4)


@dataclass(frozen=True, eq=False)
class FacetWetting:
    """The wetted facets of one 3D water load: g_fi(h) = γ_w ∫_f φ_i max(h − z, 0) dA, exact
    (module docstring).

    Attributes
    ----------
    kind : str
        Facet kind (``tri3`` … ``quad9``, :data:`~stepcontact.contact.surface3d.FACET_KINDS`).
    z : (F, k) float
        Elevations of the facets' nodes (corners first), m.
    jac : (F,) float
        dA/dξ of each (flat, affine) facet, m² per unit reference area.
    gamma : float
        Unit weight of water, N/m³.
    group : (F, k) int
        Index of the virtual pattern each (facet, node) contributes to.
    n_groups : int
    """

    kind: str
    z: np.ndarray
    jac: np.ndarray
    gamma: float
    group: np.ndarray
    n_groups: int

    @property
    def corner_levels(self) -> np.ndarray:
        """(F, corners) elevations of the facets' corners, m: where the pieces change."""
        return self.z[:, : FACET_KINDS[self.kind][0]]

    @property
    def degree(self) -> int:
        return FACET_DEGREE[self.kind]

    def pair_factors(self, h: float) -> np.ndarray:
        """(F, k) g_fi(h), N/m·m (Pa·m²): γ_w ∫ φ_i (h − z) dA over each facet's wet part."""
        corners, _ = _reference_sides(self.kind)  # (nc, 2), counter-clockwise
        nc = len(corners)
        d = h - self.corner_levels  # (F, nc): > 0 wet
        d1 = np.roll(d, -1, axis=1)
        wet, wet1 = d > 0, d1 > 0
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(wet != wet1, d / (d - d1), 0.0)
        seg = np.roll(corners, -1, axis=0) - corners
        cross = corners[None] + t[..., None] * seg[None]  # (F, nc, 2)
        cand = np.stack([np.broadcast_to(corners, cross.shape), cross], axis=2).reshape(
            len(d), 2 * nc, 2)
        keep = np.stack([wet, wet != wet1], axis=2).reshape(len(d), 2 * nc)
        order = np.argsort(~keep, axis=1, kind="stable")
        poly = np.take_along_axis(cand, order[..., None], axis=1)  # kept vertices first
        count = keep.sum(axis=1)
        j = np.arange(1, 2 * nc - 1)
        A, B, C = poly[:, :1], poly[:, j], poly[:, j + 1]  # fan from the first vertex
        u, v = B - A, C - A
        det = np.abs(u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0])
        det = np.where(j[None] + 2 <= count[:, None], det, 0.0)  # (F, T)
        xi = A[:, :, None] + _TX[None, None, :, :1] * u[:, :, None] + \
            _TX[None, None, :, 1:] * v[:, :, None]  # (F, T, G, 2)
        N, _ = shape(self.kind, xi)  # (F, T, G, k)
        head = h - np.einsum("ftgk,fk->ftg", N, self.z)
        w = det[..., None] * _TW[None, None] * (self.jac * self.gamma)[:, None, None]
        return np.einsum("ftg,ftgk->fk", w * head, N)

    def factors(self, h: float) -> np.ndarray:
        """(n_groups,) the virtual patterns' factors g_p(h): the pairs' summed per group."""
        return np.bincount(self.group.ravel(), self.pair_factors(h).ravel(),
                           minlength=self.n_groups)


def _affine_facets(surf: Surface, item: str) -> np.ndarray:
    """dA/dξ (F,) of flat facets with straight sides (triangles, parallelograms), whose wet
    part is a polygon in local coordinates; any other facet is a ModelError naming it."""
    X = surf.points[surf.facets]  # (F, k, 3)
    nc = FACET_KINDS[surf.kind][0]
    c = X[:, :nc]
    if nc == 3:  # X = X0 + r (X1 − X0) + s (X2 − X0)
        a, b, o = c[:, 1] - c[:, 0], c[:, 2] - c[:, 0], c[:, 0]
    else:  # X = c + r a + s b on [−1, 1]²
        o = c.mean(axis=1)
        a = 0.25 * (c[:, 1] - c[:, 0] + c[:, 2] - c[:, 3])
        b = 0.25 * (c[:, 3] - c[:, 0] + c[:, 2] - c[:, 1])
    xi = _TX if nc == 3 else 2 * _TX - 0.5  # sample points inside the reference domain
    N, _ = shape(surf.kind, xi)
    Xs = np.einsum("gk,fkd->fgd", N, X)
    Xa = o[:, None] + xi[None, :, :1] * a[:, None] + xi[None, :, 1:] * b[:, None]
    size = np.linalg.norm(np.ptp(X, axis=1), axis=1)
    off = np.flatnonzero(np.linalg.norm(Xs - Xa, axis=2).max(axis=1) > 1e-9 * size)
    if off.size:
        f = int(off[0])
        raise ModelError(f"{item} facet {f}", "is not a flat triangle or parallelogram with "
                         "straight sides (its corners "
                         f"{np.round(c[f], 6).tolist()}): the wetted part of such a face is not "
                         "integrated exactly; mesh the wetted faces with flat facets")
    return np.linalg.norm(np.cross(a, b), axis=1)


def wetted_facets(model: Model, ld, item: str):
    """The wetted facets of a water load on a 3D body: (body, surface of those facets, their
    affine dA/dξ)."""
    b, faces = continuum_edges(model, ld.nodes, item, "water loads")
    surf = surface_of_mesh(b.mesh, b.element, name=f"{item} ({ld.nodes.label})")
    if surf.points.shape != b.points.shape or np.abs(surf.points - b.points).max() > 0:
        raise AssertionError("surface nodes are not the body's nodes")  # pragma: no cover
    pos = np.full(int(surf.mesh_facets.max()) + 1, -1, dtype=np.int64)
    pos[surf.mesh_facets] = np.arange(len(surf))
    rows = pos[edge_facets(b, faces)]
    sel = Surface(surf.points, surf.facets[rows], surf.kind, surf.mesh_facets[rows], surf.name)
    return b, sel, _affine_facets(sel, item)


def facet_water_forces(model: Model, dofs, ld, item: str) -> np.ndarray:
    """Nodal forces (ndof,) of a water load at its fixed level on the faces of a 3D body, N:
    f_i = −Σ_f n_f g_fi(h_w) (exact, :class:`FacetWetting`)."""
    b, surf, jac = wetted_facets(model, ld, item)
    k = surf.facets.shape[1]
    wet = FacetWetting(surf.kind, surf.points[surf.facets, 2], jac, float(ld.unit_weight),
                       np.arange(surf.facets.size).reshape(-1, k), surf.facets.size)
    g = wet.pair_factors(float(ld.level))  # (F, k)
    force = -surf.normals[:, None, :] * g[..., None]  # (F, k, 3)
    f = np.zeros(dofs.ndof)
    ids = model.node_offsets[b.name] + surf.facets
    np.add.at(f, dofs.of[ids][..., :3].reshape(-1), force.reshape(-1))
    return f


def _facet_patterns(model: Model, dofs, ld, item: str, first: int):
    """The virtual patterns of a level-following water load on a 3D body: one per (node,
    facet normal) — on a flat face one per wetted node — numbered from ``first``; returns
    (FacetWetting, vectors (P, ndof))."""
    b, surf, jac = wetted_facets(model, ld, item)
    k = surf.facets.shape[1]
    ids = model.node_offsets[b.name] + surf.facets  # (F, k) global nodes
    nrm = np.broadcast_to(surf.normals[:, None, :], (len(surf), k, 3)).reshape(-1, 3)
    key = np.column_stack([ids.reshape(-1), np.round(nrm * 1e9)])
    _, first_of, group = np.unique(key, axis=0, return_index=True, return_inverse=True)
    group = group.ravel()
    vecs = np.zeros((len(first_of), dofs.ndof))
    node = ids.reshape(-1)[first_of]
    vecs[np.arange(len(first_of))[:, None], dofs.of[node][:, :3]] = -nrm[first_of]
    wet = FacetWetting(surf.kind, surf.points[surf.facets, 2], jac, float(ld.unit_weight),
                       first + group.reshape(-1, k), 0)
    return wet, vecs


def level_basis(model: Model, dofs, pattern: LoadPattern) -> LevelBasis:
    """The virtual patterns of a level pattern (see the module docstring)."""
    item = f"load pattern '{pattern.name}'"
    off = model.node_offsets
    vecs, ys, lengths, gammas, edge_of, node_of, quads = [], [], [], [], [], [], []
    parts: list[FacetWetting] = []
    n_edges = 0
    for i, ld in enumerate(pattern.loads):
        if not getattr(ld, "follows_level", False):
            continue  # proportional to the level: the pattern's own load vector
        if model.body(ld.nodes.body).dim == 3:
            wet, v3 = _facet_patterns(model, dofs, ld, f"{item} load {i}", len(vecs))
            parts.append(wet)
            vecs.extend(v3)
            continue
        b, edges = continuum_edges(model, ld.nodes, item, "water loads")
        nout = outward_normals(b, edges)
        pts = b.points
        L = np.linalg.norm(pts[edges[:, 1]] - pts[edges[:, 0]], axis=1)
        k = edges.shape[1]
        for e in range(len(edges)):
            for i in range(k):
                v = np.zeros(dofs.ndof)
                d = dofs.of[off[b.name] + edges[e, i], :2]
                v[d] = -nout[e] * model.thickness
                vecs.append(v)
                edge_of.append(n_edges + e)
                node_of.append(i)
        ys.append(pts[edges[:, :2], 1])
        lengths.append(L)
        gammas.append(np.full(len(edges), float(ld.unit_weight)))
        quads.append(np.full(len(edges), k == 3))
        n_edges += len(edges)
    names = tuple(virtual_name(pattern.name, p) for p in range(len(vecs)))
    cat = (lambda xs, shape: np.concatenate(xs) if xs else np.zeros(shape))  # noqa: E731
    return LevelBasis(pattern.name, names, np.array(vecs), cat(ys, (0, 2)), cat(lengths, 0),
                      cat(gammas, 0), np.array(edge_of, dtype=np.int64),
                      np.array(node_of, dtype=np.int64), cat(quads, 0).astype(bool),
                      tuple(replace(p, n_groups=len(vecs)) for p in parts))


__all__ = ["FacetWetting", "LevelBasis", "facet_water_forces", "is_level_pattern", "is_virtual",
           "level_basis", "virtual_name", "wetted_facets"]
