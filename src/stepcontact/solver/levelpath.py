"""A segment along which the load is a polynomial in its parameter: the water level.

For a pattern whose factor is a water level h (:mod:`stepcontact.fem.level`) the load is
f(h) = Σ_p g_p(h) v_p with g_p piecewise polynomials of degree ≤ 4 in h, whose pieces change at
the levels of the wetted nodes.  Within a piece, on a fixed working scheme, the contact
unknowns are linear in the load, so with μ = |h − h_now| the path is

    s(μ) = s + Σ_j μ^j ds_j,   w(μ) = w + Σ_j μ^j dw_j,   j = 1 … 4,

with (ds_j, dw_j) the scheme's rates under the j-th Taylor coefficient of the load at h_now
(:meth:`LevelPath.forcings`).  The event functions are then polynomials in μ, whose roots the
engine finds exactly (:meth:`~stepcontact.solver.engine.EventEngine.next_event_poly`).  At an
event point the scheme is decided with the first Taylor coefficient that does not vanish
(where the water just reaches a node the load starts like (h − y)², not linearly).
"""

from __future__ import annotations

import numpy as np

from stepcontact.fem.level import LevelBasis


class LevelPath:
    """The loads of one level segment, from level ``h0`` to ``h1`` (m)."""

    def __init__(self, basis: LevelBasis, cond, h0: float, h1: float):
        self.basis = basis
        self.h0, self.h1 = float(h0), float(h1)
        self.direction = 1.0 if h1 >= h0 else -1.0
        names = basis.names
        self.H = np.column_stack([cond.hhat[n] for n in names])
        self.E = np.column_stack([cond.e[n] for n in names])
        self.Y = np.column_stack([cond.y[n] for n in names])
        # the pattern's own loads, per metre of water (linear in the level)
        own = basis.pattern
        self.own = (cond.hhat[own], cond.e[own], cond.y[own], cond.system.loads[own].f)
        self.stops = np.r_[basis.breaks(h0, h1), self.h1]

    def add_stops(self, levels: np.ndarray) -> None:
        """More piece ends (m) inside the segment: levels where another load has a kink."""
        lo, hi = sorted((self.h0, self.h1))
        inner = np.asarray(levels, float)
        inner = inner[(inner > lo) & (inner < hi)]
        if inner.size:
            st = np.unique(np.r_[self.stops, inner])
            self.stops = st[np.argsort((st - self.h0) * self.direction, kind="stable")]

    def level(self, mu: float) -> float:
        return self.h0 + self.direction * mu

    def piece_end(self, mu: float) -> float:
        """μ of the end of the piece the path is in at μ (a node level or the segment end)."""
        h = self.level(mu)
        tol = 1e-12 * max(1.0, abs(h))
        ahead = self.stops[(self.stops - h) * self.direction > tol]
        end = ahead[0] if ahead.size else self.h1
        return abs(end - self.h0)

    def factors(self, mu: float) -> dict[str, float]:
        """Exact factors at μ: the level for the pattern, g_p(h) for its virtual patterns."""
        h = self.level(mu)
        g = self.basis.factors(h)
        out = dict(zip(self.basis.names, g.tolist(), strict=True))
        out[self.basis.pattern] = h
        return out

    def forcings(self, mu: float) -> tuple[list, np.ndarray]:
        """Forcings (ĥ_j, e_j) of the Taylor coefficients j = 1 … 4 of the load in μ at μ (on
        the current piece), and those coefficients (4, P) of the g_p.  On a segment of zero
        length (h1 = h0) they are all zero: the segment is a no-op, as a proportional
        segment of zero length is."""
        h = self.level(mu)
        end = self.level(self.piece_end(mu))
        h_own, e_own = self.own[0], self.own[1]
        if end == h:  # a segment of zero length (it ends at the current level): nothing moves
            c = np.zeros((self.basis.degree, len(self.basis.names)))
            h_own, e_own = np.zeros_like(h_own), np.zeros_like(e_own)
        else:
            c = self.basis.taylor(h, end)[1:]
            c = c * (self.direction ** np.arange(1, len(c) + 1))[:, None]
        out = [(self.H @ cj, self.E @ cj) for cj in c]
        out[0] = (out[0][0] + self.direction * h_own, out[0][1] + self.direction * e_own)
        self._own_active = bool(np.any(h_own) or np.any(e_own))
        return out, c

    def own_rate(self, j: int) -> float:
        """Rate of the pattern's own (proportional) load in the j-th coefficient."""
        return self.direction if j == 0 else 0.0

    def leading(self, forcings, coefs) -> int:
        """Index of the first Taylor coefficient whose load does not vanish (0-based)."""
        size = [np.abs(cj).max(initial=0.0) for cj in coefs]
        if getattr(self, "_own_active", False):
            return 0
        top = max(size, default=0.0)
        for j, s in enumerate(size):
            if s > 1e-12 * top:
                return j
        return 0

    def load(self, coef: np.ndarray, j: int = 0) -> np.ndarray:
        """Load vector of the j-th Taylor coefficient: Σ_p coef_p v_p (+ the pattern's own
        load for j = 0), N."""
        return self.basis.vectors.T @ coef + self.own_rate(j) * self.own[3]

    def scales(self, start: bool = False) -> tuple[float, float]:
        """(max |y|, max |f|) at the two ends of the segment and at its node levels (at its
        start h0 only if ``start``): the size of the response and of the load, for
        tolerances."""
        hs = np.r_[self.h0] if start else np.r_[self.h0, self.stops]
        g = np.array([self.basis.factors(h) for h in hs])
        y = np.abs(g @ self.Y.T + hs[:, None] * self.own[2][None, :]).max(initial=0.0)
        f = np.abs(g @ self.basis.vectors + hs[:, None] * self.own[3][None, :]).max(initial=0.0)
        return float(y), float(f)

    def reach(self, f_limit: float) -> float:
        """μ (m) of the first node level (or the segment's end) where the load's size
        max |f| exceeds ``f_limit`` (N); the segment's length if none does."""
        h = self.stops
        g = np.array([self.basis.factors(x) for x in h]).reshape(len(h), -1)
        f = np.abs(g @ self.basis.vectors + h[:, None] * self.own[3][None, :]).max(
            axis=1, initial=0.0)
        over = np.flatnonzero(f > f_limit)
        return abs((h[over[0]] if over.size else self.h1) - self.h0)

    def far_stops(self, growth: float) -> np.ndarray:
        """Levels (m) that split the segment beyond its last node level into pieces each
        ``growth`` times longer than the one before (from the last node level's distance to
        h0, at least 1 m): a level run far beyond the structure's size is expanded in Taylor
        terms over pieces of the path's own size, not over the whole run (whose powers
        μ^j of 1e10 m made the event roots round-off)."""
        span = abs(self.h1 - self.h0)
        inner = np.abs(self.stops[:-1] - self.h0)
        d = max(float(inner.max(initial=0.0)), 1.0)
        n = int(np.floor(np.log(span / d) / np.log(growth))) if span > d * growth else 0
        return self.h0 + self.direction * d * growth ** np.arange(1, n + 1, dtype=float)
