"""Values given by coordinates: a constant, a :class:`LinearProfile` between points, or a
function of (x, y) — the pressures and heads of water loads (:mod:`stepcontact.model.water`),
the strengths of bonded joints (:mod:`stepcontact.model.bond`) and edge pressures.

A pressure function takes arrays x, y (m) and gives values (Pa, or m of head before the unit
weight); it may tell its kinks inside straight segments (``breaks``) so that edge integration
splits there.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from stepcontact.errors import ModelError


def finite(v: float, item: str, *, positive: bool = False) -> float:
    """``v`` as a float; a ModelError naming ``item`` if it is NaN or inf (or, with
    ``positive``, not > 0)."""
    v = float(v)
    if not np.isfinite(v) or (positive and v <= 0):
        raise ModelError(item, f"must be {'positive and ' if positive else ''}finite, got {v}")
    return v


@dataclass(frozen=True, eq=False)
class LinearProfile:
    """A value (a pressure in Pa, or a head in m) linear between points given by coordinates.

    ``points`` are ``(x, y, value)`` triples, at least two.  A point (x, y) is placed by its
    coordinate ξ along the chord from the first point to the last (its projection on that
    line); the value is linear in ξ between consecutive points (piecewise linear through
    interior points, e.g. a drainage line) and continued linearly beyond the first and the last
    point.  The result is multiplied by ``scale`` (γ_w to turn a head into a pressure).

    The order of the nodes of a node set plays no part: reversing a curve changes nothing.

    Example
    -------
    >>> p = LinearProfile([(0.0, 10.0, 0.0), (0.0, 0.0, 98100.0)])  # hydrostatic, 10 m deep
    >>> p(np.array([0.0, 0.0]), np.array([0.0, 5.0])).tolist()
    [98100.0, 49050.0]
    """

    points: tuple[tuple[float, float, float], ...]
    scale: float = 1.0

    def __post_init__(self):
        pts = np.asarray(self.points, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 3 or len(pts) < 2:
            raise ModelError("linear profile", "give at least two points (x, y, value)")
        if not np.all(np.isfinite(pts)):
            raise ModelError("linear profile", "points contain NaN or inf")
        d = pts[-1, :2] - pts[0, :2]
        if np.hypot(*d) == 0:
            raise ModelError("linear profile", "the first and the last point coincide")
        xi = self._xi_of(pts[:, 0], pts[:, 1], pts)
        if np.any(np.diff(xi) <= 0):
            raise ModelError("linear profile", "the points must follow each other along the "
                             "line from the first to the last point")
        finite(self.scale, "linear profile.scale")
        object.__setattr__(self, "points", tuple(tuple(map(float, p)) for p in pts))

    @staticmethod
    def _xi_of(x, y, pts: np.ndarray) -> np.ndarray:
        a, d = pts[0, :2], pts[-1, :2] - pts[0, :2]
        return ((np.asarray(x, float) - a[0]) * d[0] + (np.asarray(y, float) - a[1]) * d[1]) / (
            d @ d)

    def __call__(self, x, y) -> np.ndarray:
        pts = np.asarray(self.points)
        xi = self._xi_of(x, y, pts)
        xs = self._xi_of(pts[:, 0], pts[:, 1], pts)
        j = np.clip(np.searchsorted(xs, xi, side="right") - 1, 0, len(xs) - 2)
        t = (xi - xs[j]) / (xs[j + 1] - xs[j])
        return self.scale * (pts[j, 2] + t * (pts[j + 1, 2] - pts[j, 2]))

    def breaks(self, a: np.ndarray, b: np.ndarray) -> list[np.ndarray]:
        """Kinks strictly inside each straight segment a[i] → b[i]: fractions t ∈ (0, 1)."""
        pts = np.asarray(self.points)
        xs = self._xi_of(pts[1:-1, 0], pts[1:-1, 1], pts)
        xa, xb = self._xi_of(a[:, 0], a[:, 1], pts), self._xi_of(b[:, 0], b[:, 1], pts)
        out = []
        for u, v in zip(xa, xb, strict=True):
            t = (xs - u) / (v - u) if v != u else np.zeros(0)
            out.append(np.sort(t[(t > 1e-12) & (t < 1 - 1e-12)]))
        return out


@dataclass(frozen=True, eq=False)
class _Scaled:
    """``factor`` × a pressure function (keeps its kinks)."""

    f: Callable
    factor: float

    def __call__(self, x, y) -> np.ndarray:
        return self.factor * np.asarray(self.f(x, y), dtype=float)

    def breaks(self, a, b):
        inner = getattr(self.f, "breaks", None)
        return inner(a, b) if inner is not None else [np.zeros(0)] * len(a)


def as_function(spec, item: str, scale: float) -> Callable:
    """A constant, a LinearProfile, a sequence of (x, y, value) points or a function of
    (x, y) as a pressure function (× ``scale``)."""
    if callable(spec):
        if isinstance(spec, LinearProfile):
            return LinearProfile(spec.points, spec.scale * scale)
        return _Scaled(spec, scale)
    if np.ndim(spec) == 0:
        v = finite(spec, item) * scale
        return lambda x, y: v + 0.0 * np.asarray(x, float)
    try:
        return LinearProfile(tuple(tuple(p) for p in spec), scale)
    except (TypeError, ValueError) as e:
        raise ModelError(item, f"give a number, points [(x, y, value), …] or a function of "
                         f"(x, y): {e}") from None
    except ModelError as e:
        raise ModelError(item, e.problem) from None


__all__ = ["LinearProfile", "as_function", "finite"]
