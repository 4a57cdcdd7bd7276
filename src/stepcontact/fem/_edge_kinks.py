"""Edge pressures with kinks inside element edges, integrated exactly (water loads, uplift).

Private: :func:`stepcontact.fem.assembly.load_vectors` calls :func:`water_forces` for the
loads of :mod:`stepcontact.model.water`.

A pressure function may say where it has kinks along a straight segment (a method
``breaks(a, b)``: fractions t ∈ (0, 1) for each segment a[i] → b[i]; e.g. the water level).
The consistent nodal forces f_i = ∫ p φ_i n ds of an edge with a kink are not integrated
exactly by the Gauss rule of the edge.  On such an edge p is replaced by its L² projection q on
the polynomials of the edge's degree k (1 for linear, 2 for quadratic elements): the moments
∫ p t^j dt, j ≤ k, are computed piece by piece between the kinks (Gauss–Legendre, exact for the
piecewise-linear p), and q has the same moments, so ∫ q φ_i ds = ∫ p φ_i ds for every shape
function φ_i of the edge.  The nodal forces are then those of the ordinary edge integration
(:func:`stepcontact.fem.continuum.edge_load`) with q: exact for straight edges.
"""

from __future__ import annotations

import numpy as np

from stepcontact.contact.boundary import continuum_edges, edge_facets
from stepcontact.errors import ModelError
from stepcontact.fem import continuum as _fem
from stepcontact.model import Body, EdgeLoad, Model

_GL_X, _GL_W = np.polynomial.legendre.leggauss(4)  # exact to degree 7 on each piece
_GL_X, _GL_W = 0.5 * (_GL_X + 1.0), 0.5 * _GL_W  # on [0, 1]


def _projected(p, a: np.ndarray, b: np.ndarray, breaks: list[np.ndarray], k: int):
    """q(x, y): on segment i the polynomial of degree k in t (x = a_i + t (b_i − a_i)) with the
    moments ∫₀¹ p t^j dt, j = 0…k, of p."""
    H = 1.0 / (np.arange(k + 1)[:, None] + np.arange(k + 1)[None, :] + 1.0)  # ∫ t^(i+j) dt
    coef = np.zeros((len(a), k + 1))
    for i, br in enumerate(breaks):
        knots = np.r_[0.0, np.asarray(br, float), 1.0]
        lo, hi = knots[:-1, None], knots[1:, None]
        t = (lo + (hi - lo) * _GL_X[None, :]).ravel()
        w = ((hi - lo) * _GL_W[None, :]).ravel()
        xy = a[i] + t[:, None] * (b[i] - a[i])
        pv = np.asarray(p(xy[:, 0], xy[:, 1]), dtype=float)
        moments = (w * pv) @ (t[:, None] ** np.arange(k + 1)[None, :])
        coef[i] = np.linalg.solve(H, moments)
    d = b - a
    L2 = np.einsum("ij,ij->i", d, d)

    def q(x, y):
        xy = np.stack([np.ravel(x), np.ravel(y)], axis=1)
        rel = xy[:, None, :] - a[None, :, :]  # (points, segments, 2)
        t = np.einsum("psj,sj->ps", rel, d) / L2[None, :]
        tc = np.clip(t, 0.0, 1.0)
        dist = np.linalg.norm(rel - tc[..., None] * d[None], axis=2)
        s = np.argmin(dist, axis=1)
        ts = t[np.arange(len(xy)), s]
        val = np.einsum("pj,pj->p", coef[s], ts[:, None] ** np.arange(k + 1)[None, :])
        return val.reshape(np.shape(x))

    return q


def edge_pressure_forces(model: Model, el: EdgeLoad, item: str) -> tuple[Body, np.ndarray]:
    """Consistent nodal forces (body-local vector DOFs, N) of the normal pressure of ``el``,
    exact on edges where the pressure has kinks it declares (``el.normal.breaks``)."""
    b, edges = continuum_edges(model, el.nodes, item, "water loads")
    facets = edge_facets(b, edges)
    p = el.normal
    a, c = b.points[edges[:, 0]], b.points[edges[:, 1]]
    brk = p.breaks(a, c) if hasattr(p, "breaks") else [np.zeros(0)] * len(edges)
    cut = np.array([len(t) > 0 for t in brk], dtype=bool)
    fb = np.zeros(2 * b.n_nodes)
    if np.any(~cut):
        fb += _fem.edge_load(b, facets[~cut], p, None, model.thickness)
    if np.any(cut):
        k = 2 if edges.shape[1] > 2 else 1
        q = _projected(p, a[cut], c[cut], [brk[i] for i in np.flatnonzero(cut)], k)
        fb += _fem.edge_load(b, facets[cut], q, None, model.thickness)
    if not np.all(np.isfinite(fb)):
        raise ModelError(item, "pressure function gives NaN or inf")
    return b, fb


def water_forces(model: Model, dofs, ld, item: str) -> np.ndarray:
    """Force vector (ndof,) of a :class:`~stepcontact.model.water.WaterLoad` or
    :class:`~stepcontact.model.water.Uplift` (per unit λ), N."""
    f = np.zeros(dofs.ndof)
    off = model.node_offsets
    for el in ld.edge_loads(model):
        b, fb = edge_pressure_forces(model, el, item)
        ids = off[b.name] + np.arange(b.n_nodes)
        np.add.at(f, dofs.of[ids][:, :2].ravel(), fb)
    return f
