"""Geometric checks of continuum bodies: element quality and overlap of two bodies.

Used by :func:`stepcontact.io.modelfile.validate_model_file`; everything is vectorised over the
elements.  Only the corner nodes of the elements are used (curved sides are ignored).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from stepcontact.model.bodies import Body

#: elements with a quality below this are reported (1 is an equilateral triangle or a rectangle)
QUALITY_WARN = 0.1
#: elements whose longest side exceeds this many times their shortest side are reported
ASPECT_WARN = 50.0


@dataclass(frozen=True)
class Quality:
    """Element quality of a body.

    ``quality`` is 4√3·A / Σ l² for triangles (1 equilateral, 0 degenerate) and the smallest
    sine of the corner angles for quads (1 for a rectangle); it is negative for an inverted
    element (a quad whose corners turn different ways).  ``aspect`` is longest / shortest side.
    """

    quality: np.ndarray
    aspect: np.ndarray

    @property
    def worst(self) -> int:
        """Index of the element of lowest quality."""
        return int(np.argmin(self.quality))


def corners(body: Body) -> tuple[np.ndarray, np.ndarray]:
    """Vertex coordinates (n, 2), m, and corner indices of each element (nel, 3 | 4)."""
    mesh = body.mesh
    return np.asarray(mesh.p[:2].T), np.asarray(mesh.t.T)


def quality(points: np.ndarray, cells: np.ndarray) -> Quality:
    """Quality and aspect ratio of triangles (nel, 3) or quads (nel, 4), any orientation."""
    xy = points[cells]
    e_next = np.roll(xy, -1, axis=1) - xy
    e_prev = np.roll(xy, 1, axis=1) - xy
    length = np.linalg.norm(e_next, axis=2)
    cross = e_next[..., 0] * e_prev[..., 1] - e_next[..., 1] * e_prev[..., 0]
    aspect = length.max(axis=1) / np.maximum(length.min(axis=1), 1e-300)
    if cells.shape[1] == 3:
        area = 0.5 * np.abs(cross[:, 0])
        q = 4.0 * np.sqrt(3.0) * area / np.maximum((length**2).sum(axis=1), 1e-300)
        return Quality(q, aspect)
    sine = cross / np.maximum(length * np.roll(length, 1, axis=1), 1e-300)
    same = (np.sign(sine) == np.sign(sine[:, :1])).all(axis=1)
    q = np.abs(sine).min(axis=1)
    return Quality(np.where(same, q, -q), aspect)


def _triangles(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Triangles (ntri, 3, 2) covering the elements (quads split along a diagonal)."""
    if cells.shape[1] == 4:
        cells = np.vstack([cells[:, [0, 1, 2]], cells[:, [0, 2, 3]]])
    return points[cells]


def overlap(a: Body, b: Body, rtol: float = 1e-9) -> tuple[np.ndarray, int] | None:
    """A point of body ``a`` strictly inside an element of body ``b``, or None.

    The points tested are the corner nodes and element centroids of ``a``; points on an edge
    of ``b`` (bodies touching along a side) do not count.  Returns (point, element of ``b``).
    """
    pa, ca = corners(a)
    pb, cb = corners(b)
    lo = np.maximum(pa.min(axis=0), pb.min(axis=0))
    hi = np.minimum(pa.max(axis=0), pb.max(axis=0))
    size = max(float(np.ptp(np.vstack([pa, pb]), axis=0).max()), 1e-300)
    if np.any(hi - lo <= rtol * size):  # bounding boxes do not overlap with positive area
        return None
    test = np.vstack([pa, pa[ca].mean(axis=1)])
    tol = rtol * size
    test = test[np.all((test >= lo - tol) & (test <= hi + tol), axis=1)]
    if not len(test):
        return None
    tri = _triangles(pb, cb)
    n_cells = len(cb)
    centre = tri.mean(axis=1)
    radius = float(np.linalg.norm(tri - centre[:, None], axis=2).max())
    pairs = cKDTree(test).sparse_distance_matrix(
        cKDTree(centre), radius * (1 + 1e-9), output_type="ndarray"
    )
    if not len(pairs):
        return None
    i, j = pairs["i"], pairs["j"]
    x, t = test[i], tri[j]
    # barycentric coordinates of x in each candidate triangle
    d1, d2 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    det = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    r = x - t[:, 0]
    l1 = (r[:, 0] * d2[:, 1] - r[:, 1] * d2[:, 0]) / det
    l2 = (d1[:, 0] * r[:, 1] - d1[:, 1] * r[:, 0]) / det
    eps = 1e-7
    inside = (l1 > eps) & (l2 > eps) & (1 - l1 - l2 > eps)
    if cb.shape[1] == 4:  # a point on the diagonal of a quad is inside the quad too
        inside |= _on_diagonal(l1, l2, j >= n_cells, eps)
    if not inside.any():
        return None
    k = int(np.flatnonzero(inside)[0])
    return test[i[k]], int(j[k] % n_cells)


def _on_diagonal(l1: np.ndarray, l2: np.ndarray, second: np.ndarray, eps: float) -> np.ndarray:
    """Points strictly inside the diagonal 0-2 of a split quad: the side l1 = 0 of the first
    half (corners 0, 1, 2) or l2 = 0 of the second half (corners 0, 2, 3)."""
    along = np.where(second, l1, l2)
    across = np.where(second, l2, l1)
    return (np.abs(across) <= eps) & (along > eps) & (along < 1 - eps)


__all__ = ["ASPECT_WARN", "QUALITY_WARN", "Quality", "overlap", "quality"]
