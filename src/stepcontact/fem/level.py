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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from stepcontact.contact.boundary import continuum_edges, edge_shape, outward_normals
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

    def factors(self, h: float) -> np.ndarray:
        """g_p(h), Pa·m (exact): γ_w ∫ φ_i max(h − y, 0) ds over the wetted part of each edge."""
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
        levels = np.unique(self.y)
        lo, hi = min(h0, h1), max(h0, h1)
        tol = 1e-12 * max(1.0, abs(lo), abs(hi))
        inner = levels[(levels > lo + tol) & (levels < hi - tol)]
        return inner if h1 >= h0 else inner[::-1]

    def taylor(self, h0: float, h1: float) -> np.ndarray:
        """(DEGREE + 1, P) coefficients c_j with g_p(h0 + δ) = Σ_j c_j δ^j for h0 + δ between
        h0 and h1, a part of one piece (no node level strictly inside): exact, by sampling
        g at DEGREE + 1 points and solving the scaled Vandermonde system."""
        span = h1 - h0
        if span == 0:
            raise ValueError("empty level interval")
        z = np.linspace(0.0, 1.0, DEGREE + 1)
        V = z[:, None] ** np.arange(DEGREE + 1)[None, :]
        G = np.array([self.factors(h0 + zi * span) for zi in z])
        c = np.linalg.solve(V, G)
        return c / (span ** np.arange(DEGREE + 1))[:, None]


def level_basis(model: Model, dofs, pattern: LoadPattern) -> LevelBasis:
    """The virtual patterns of a level pattern (see the module docstring)."""
    item = f"load pattern '{pattern.name}'"
    off = model.node_offsets
    vecs, ys, lengths, gammas, edge_of, node_of, quads = [], [], [], [], [], [], []
    n_edges = 0
    for ld in pattern.loads:
        if not getattr(ld, "follows_level", False):
            continue  # proportional to the level: the pattern's own load vector
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
    return LevelBasis(pattern.name, names, np.array(vecs), np.concatenate(ys),
                      np.concatenate(lengths), np.concatenate(gammas),
                      np.array(edge_of, dtype=np.int64), np.array(node_of, dtype=np.int64),
                      np.concatenate(quads))


__all__ = ["LevelBasis", "is_level_pattern", "is_virtual", "level_basis", "virtual_name"]
