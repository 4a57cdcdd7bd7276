"""Mesh generators for simple bodies (rectangles, graded blocks) built on scikit-fem meshes."""

from __future__ import annotations

import numpy as np
from skfem import MeshQuad, MeshTri

from stepcontact.errors import ModelError
from stepcontact.model.items import Body, Material

#: local node permutation reversing a cell's orientation (corners, then mid-edge nodes, then the
#: centre).  Gmsh, VTK and scikit-fem (P2 / serendipity / Q2) share this node order.
REVERSED_NODE_ORDER: dict[str, list[int]] = {
    "triangle": [0, 2, 1],
    "triangle6": [0, 2, 1, 5, 4, 3],
    "quad": [0, 3, 2, 1],
    "quad8": [0, 3, 2, 1, 7, 6, 5, 4],
    "quad9": [0, 3, 2, 1, 7, 6, 5, 4, 8],
}


def _axis(a: float, b: float, n: int, grading: float) -> np.ndarray:
    """n intervals from a to b; ``grading`` > 1 makes them grow geometrically from a to b."""
    if grading == 1.0:
        return np.linspace(a, b, n + 1)
    r = grading ** (1.0 / max(n - 1, 1))
    h = np.cumsum(np.r_[0.0, r ** np.arange(n)])
    return a + (b - a) * h / h[-1]


def _grid(name: str, field: str, v, a: float, b: float) -> np.ndarray:
    """Given grid lines: finite, strictly increasing, from a to b (the corners)."""
    v = np.asarray(v, float)
    item = f"body '{name}'.{field}"
    if v.ndim != 1 or len(v) < 2 or not np.all(np.isfinite(v)) or np.any(np.diff(v) <= 0):
        raise ModelError(item, "must be at least two finite, strictly increasing coordinates")
    tol = 1e-9 * max(abs(a), abs(b), b - a)
    if abs(v[0] - a) > tol or abs(v[-1] - b) > tol:
        raise ModelError(item, f"must run from {a:g} to {b:g} (the corners), got "
                               f"{v[0]:g} … {v[-1]:g}")
    return v


def rectangle(
    name: str,
    corner0: tuple[float, float],
    corner1: tuple[float, float],
    nx: int,
    ny: int,
    material: Material,
    element: str = "quad4",
    *,
    grading: tuple[float, float] = (1.0, 1.0),
    xs: np.ndarray | None = None,
    ys: np.ndarray | None = None,
) -> Body:
    """A rectangular body [x0, x1] × [y0, y1] (m) meshed with ``nx`` × ``ny`` cells.

    ``element`` is ``tri3``, ``tri6``, ``quad4``, ``quad8`` or ``quad9``.  ``grading`` gives
    geometric growth of the cell sizes along x and y; ``xs``/``ys`` give the grid lines directly.

    Example
    -------
    >>> from stepcontact import Material, rectangle
    >>> slab = rectangle("slab", (0, 0), (10, 1), 20, 4, Material(30e9, 0.2, 2400))
    >>> slab.n_nodes
    105
    """
    x0, y0 = map(float, corner0)
    x1, y1 = map(float, corner1)
    if not (x1 > x0 and y1 > y0):
        raise ModelError(f"body '{name}'", f"empty rectangle {corner0} - {corner1}")
    if nx < 1 or ny < 1:
        raise ModelError(f"body '{name}'", "nx and ny must be >= 1")
    xs = _axis(x0, x1, nx, grading[0]) if xs is None else _grid(name, "xs", xs, x0, x1)
    ys = _axis(y0, y1, ny, grading[1]) if ys is None else _grid(name, "ys", ys, y0, y1)
    if element.startswith("tri"):
        mesh = MeshTri.init_tensor(xs, ys)
    elif element.startswith("quad"):
        mesh = MeshQuad.init_tensor(xs, ys)
    else:
        raise ModelError(f"body '{name}'", f"unknown element '{element}'")
    return Body.from_mesh(name, mesh, element, material)


__all__ = ["rectangle"]
