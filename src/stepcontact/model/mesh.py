"""Mesh generators and rigid motions of bodies, built on scikit-fem meshes.

* :func:`rectangle` — a rectangle, uniform or graded;
* :func:`quad_region` — a mapped (bilinear) mesh of any convex four-sided region, graded
  towards an edge or a corner;
* :func:`half_disc` — a half disc (flat face on top) refined towards the lowest point of its
  arc, for Hertz-type contact;
* :func:`polygon_region` — a triangle (structured: a triangular dam section) or any simple
  polygon (meshed by gmsh);
* :func:`box` — a 3D box of tetrahedra or hexahedra with named faces (left, right, front,
  back, bottom, top);
* :func:`extrude` — a 2D body swept along z into a prismatic 3D body (quadrilaterals into
  hexahedra, triangles into tetrahedra);
* :func:`cylinder` — a circular cylinder along z (an O-grid section swept along z) with named
  bottom, top and side;
* :func:`rotate`, :func:`translate` — a body, a frame or a whole model moved rigidly.

Any other scikit-fem ``MeshTri``/``MeshQuad`` (or a meshio mesh converted with
``skfem.io.meshio.from_meshio``) becomes a body with :meth:`~stepcontact.model.Body.from_mesh`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree
from skfem import MeshHex, MeshQuad, MeshTet, MeshTri

from stepcontact.errors import ModelError
from stepcontact.model.bodies import ELEMENT_KINDS, SOLID_KINDS, Body, Frame, Material
from stepcontact.model.loads import BodyForce, PrescribedDisplacement
from stepcontact.model.obstacle import ObstacleMotion, RigidObstacle
from stepcontact.model.structure import Model
from stepcontact.model.supports import Spring

#: local node permutation reversing a cell's orientation (corners, then mid-edge nodes, then the
#: centre).  Gmsh, VTK and scikit-fem (P2 / serendipity / Q2) share this node order.
REVERSED_NODE_ORDER: dict[str, list[int]] = {
    "triangle": [0, 2, 1],
    "triangle6": [0, 2, 1, 5, 4, 3],
    "quad": [0, 3, 2, 1],
    "quad8": [0, 3, 2, 1, 7, 6, 5, 4],
    "quad9": [0, 3, 2, 1, 7, 6, 5, 4, 8],
}

# The rules of the mesh generators' arguments, in one place: the generators check them and the
# model file's schema asks them (:mod:`stepcontact.io.modelfile.schema`).
#: a size ratio (largest / smallest cell) is at least this
SIZE_RATIO_MIN = 1
#: cells along the arc of a half disc: at least this many (and even: a node at the contact point)
HALF_DISC_MIN_AROUND = 4


def corners_problem(corner0, corner1) -> str | None:
    """Why a rectangle's corners (x0, y0), (x1, y1) are refused: it is empty (None when not)."""
    (x0, y0), (x1, y1) = corner0, corner1
    if x1 > x0 and y1 > y0:
        return None
    return "corner1 must lie above and to the right of corner0"


def grading_problem(grading) -> str | None:
    """Why a grading (gx, gy) of a rectangle is refused: factors that are not finite and > 0."""
    try:
        g = np.asarray(grading, dtype=float) if not isinstance(grading, str) else np.zeros(0)
    except (TypeError, ValueError):
        g = np.zeros(0)
    if g.shape == (2,) and np.all(np.isfinite(g)) and np.all(g > 0):
        return None
    return "grading factors must be > 0"


def cells_problem(n, size) -> str | None:
    """Why the cells of a polygon are not given by one of ``n`` and ``size`` (None: they are)."""
    if (n is None) == (size is None):
        return ("give either n (cells along an edge) or size (m)"
                + (", not both" if n is not None else ""))
    return None


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
    if (text := corners_problem((x0, y0), (x1, y1))) is not None:
        raise ModelError(f"body '{name}'", text)
    if (text := grading_problem(grading)) is not None:
        raise ModelError(f"body '{name}'.grading", text)
    if nx < 1 or ny < 1:
        raise ModelError(f"body '{name}'", "nx and ny must be >= 1")
    from stepcontact.model.size import check_size, rectangle_size

    # refuse a mesh too large for this machine before making it
    cx = nx if xs is None else max(len(xs) - 1, 1)
    cy = ny if ys is None else max(len(ys) - 1, 1)
    nodes, cells = rectangle_size(cx, cy, element)
    check_size(2 * nodes, f"body '{name}'",
               f"the {cx} × {cy} {element} mesh of body '{name}' ({cells:.3g} cells)")
    xs = _axis(x0, x1, nx, grading[0]) if xs is None else _grid(name, "xs", xs, x0, x1)
    ys = _axis(y0, y1, ny, grading[1]) if ys is None else _grid(name, "ys", ys, y0, y1)
    if element.startswith("tri"):
        mesh = MeshTri.init_tensor(xs, ys)
    elif element.startswith("quad"):
        mesh = MeshQuad.init_tensor(xs, ys)
    else:
        raise ModelError(f"body '{name}'", f"unknown element '{element}'")
    return Body.from_mesh(name, mesh, element, material)


# --------------------------------------------------------------------------------------------
# 3D boxes
# --------------------------------------------------------------------------------------------
#: the named faces of a box: (axis, end) with end 0 at the lower coordinate, 1 at the upper;
#: left/right along x and bottom/top along z (up) as for a rectangle's sides, front/back along y
BOX_FACES: dict[str, tuple[int, int]] = {"left": (0, 0), "right": (0, 1), "front": (1, 0),
                                         "back": (1, 1), "bottom": (2, 0), "top": (2, 1)}


def box(
    name: str,
    corner0: tuple[float, float, float],
    corner1: tuple[float, float, float],
    n: tuple[int, int, int],
    material: Material,
    element: str = "hex8",
) -> Body:
    """A box [x0, x1] × [y0, y1] × [z0, z1] (m) meshed with ``n`` = (nx, ny, nz) cells.

    ``element`` is ``hex8``, ``hex20`` (serendipity), ``hex27`` (scikit-fem ``MeshHex`` with
    ``ElementHex1``, ``ElementHexS2``, ``ElementHex2``), ``tet4`` or ``tet10`` (``MeshTet``,
    each cell cut into tetrahedra by scikit-fem's ``init_tensor``, with ``ElementTetP1``,
    ``ElementTetP2``).  The faces are named boundaries of the mesh (:data:`BOX_FACES`):
    ``left``/``right`` at x0/x1, ``front``/``back`` at y0/y1, ``bottom``/``top`` at z0/z1 —
    select their nodes with ``model.select(name, boundary="top")``.  z is up: the default
    gravity of a 3D body acts along −z.

    Example
    -------
    >>> from stepcontact import Material
    >>> from stepcontact.model.mesh import box
    >>> b = box("block", (0, 0, 0), (2, 1, 1), (4, 2, 2), Material(30e9, 0.2, 2400))
    >>> b.n_nodes, b.dim, b.boundary_names
    (45, 3, ('left', 'right', 'front', 'back', 'bottom', 'top'))
    """
    item = f"body '{name}'"
    if element not in SOLID_KINDS:
        raise ModelError(f"{item}.element",
                         f"unknown element '{element}' for a box, use {', '.join(SOLID_KINDS)}")
    lo = _vector(f"{item}.corner0", corner0, "point", 3)
    hi = _vector(f"{item}.corner1", corner1, "point", 3)
    if np.any(hi <= lo):
        raise ModelError(item, "corner1 must lie beyond corner0 along x, y and z")
    try:
        counts = tuple(n)
    except TypeError:
        counts = ()
    if len(counts) != 3:
        raise ModelError(f"{item}.n", f"must be three cell counts (nx, ny, nz), got {n!r}")
    nx, ny, nz = (_check_count(name, f"n[{i}]", v) for i, v in enumerate(counts))
    from stepcontact.model.size import check_size

    per = 2 if element in ("tet10", "hex20", "hex27") else 1  # nodes per cell side, at most
    nodes = (per * nx + 1) * (per * ny + 1) * (per * nz + 1)
    check_size(3 * nodes, item, f"the {nx} × {ny} × {nz} {element} mesh of body '{name}'")
    axes = [np.linspace(lo[c], hi[c], k + 1) for c, k in enumerate((nx, ny, nz))]
    cls = MeshTet if element.startswith("tet") else MeshHex
    mesh = cls.init_tensor(*axes)
    tol = 1e-9 * float(np.max(hi - lo))

    def on(axis: int, value: float):
        return lambda x: np.abs(x[axis] - value) <= tol

    mesh = mesh.with_boundaries({face: on(axis, (lo, hi)[end][axis])
                                 for face, (axis, end) in BOX_FACES.items()})
    return Body.from_mesh(name, mesh, element, material)


#: the 3D element of an extruded 2D element
EXTRUDED_ELEMENT: dict[str, str] = {"tri3": "tet4", "tri6": "tet10", "quad4": "hex8",
                                    "quad8": "hex20", "quad9": "hex27"}


def extrude(body: Body, z: tuple[float, float], nz: int, *, name: str | None = None) -> Body:
    """A prismatic 3D body: the 2D ``body`` (its section in the x–y plane) swept along z from
    ``z[0]`` to ``z[1]`` (m) in ``nz`` layers, with its material.

    Quadrilaterals become hexahedra (``quad4``, ``quad8``, ``quad9`` → ``hex8``, ``hex20``,
    ``hex27``); each triangular prism is cut into three tetrahedra (``tri3``, ``tri6`` →
    ``tet4``, ``tet10``) by the rule of the vertices' numbers (on every side face the
    diagonal joins the higher-numbered bottom vertex to the lower-numbered top one), so that
    neighbouring prisms share their faces' diagonals and the mesh is conforming.  The end faces
    are the named boundaries ``start`` (z = z[0]) and ``end`` (z = z[1]).  The section's
    mesh must have straight edges (a linear scikit-fem geometry, as the generators of this
    module give).  The section keeps its axes: with a section whose y is up, give gravity
    explicitly, ``BodyForce(g=(0, -9.81, 0))``.

    Example
    -------
    >>> from stepcontact import Material, rectangle
    >>> from stepcontact.model.mesh import extrude
    >>> slab = extrude(rectangle("slab", (0, 0), (4, 1), 4, 1, Material(30e9, 0.2)), (0, 2), 2)
    >>> slab.element, slab.n_nodes, slab.boundary_names
    ('hex8', 30, ('start', 'end'))
    """
    item = f"body '{body.name}'"
    if not isinstance(body, Body) or body.dim != 2:
        raise ModelError("extrude", f"needs a 2D continuum body, got {type(body).__name__} "
                         f"'{getattr(body, 'name', '?')}'")
    if type(body.mesh).__name__.endswith("2"):
        raise ModelError(item, "has a curved (quadratic) geometry: extrude takes a mesh with "
                               "straight edges")
    zz = np.asarray(z, dtype=float) if np.ndim(z) == 1 else np.zeros(0)
    if zz.shape != (2,) or not np.all(np.isfinite(zz)) or zz[1] <= zz[0]:
        raise ModelError(f"{item} extrusion.z", f"must be (z0, z1) with z1 > z0, m; got {z!r}")
    nz = _check_count(body.name, "extrusion.nz", nz)
    from stepcontact.model.size import check_size

    per = 2 if body.element in ("tri6", "quad8", "quad9") else 1
    check_size(3 * body.n_nodes * (per * nz + 1), item,
               f"the extrusion of body '{body.name}' in {nz} layers")
    mesh = _extruded_mesh(body.mesh, zz, nz)
    points = mesh.p
    tol = 1e-9 * float(max(np.ptp(points, axis=1).max(), 1.0))
    mesh = mesh.with_boundaries({"start": lambda x: np.abs(x[2] - zz[0]) <= tol,
                                 "end": lambda x: np.abs(x[2] - zz[1]) <= tol})
    return Body.from_mesh(name or body.name, mesh, EXTRUDED_ELEMENT[body.element],
                          body.material)


def _extruded_mesh(section, zz: np.ndarray, nz: int):
    """The MeshHex (quadrilaterals) or MeshTet (triangles) of a linear 2D mesh swept along z
    from zz[0] to zz[1] in nz layers (see :func:`extrude`), without named boundaries."""
    section = _counter_clockwise(section)
    p2, t2 = section.p, section.t
    nv = p2.shape[1]
    zs = np.linspace(zz[0], zz[1], nz + 1)
    points = np.vstack([np.tile(p2, nz + 1), np.repeat(zs, nv)])
    layer = nv * np.arange(nz)  # the first vertex of each layer's bottom
    if t2.shape[0] == 4:
        # scikit-fem's local hex order from its unit cube: node l at offsets (dx, dy, dz);
        # (dx, dy) is the corner of the counter-clockwise quad at (s, t) = (dx, dy)
        unit = MeshHex.init_tensor(np.array([0.0, 1.0]), np.array([0.0, 1.0]),
                                   np.array([0.0, 1.0]))
        off = np.rint(unit.p[:, unit.t[:, 0]]).astype(np.int64)  # (3, 8)
        corner = np.array([[0, 3], [1, 2]])[off[0], off[1]]
        t = (t2[corner][:, :, None] + layer[None, None, :]
             + nv * off[2][:, None, None]).reshape(8, -1)
        mesh = MeshHex(points, t)
    else:
        v = np.sort(t2, axis=0)  # v0 < v1 < v2 of each triangle
        b = v[:, :, None] + layer[None, None, :]  # bottom, (3, nel, nz)
        u = b + nv  # top
        t = np.stack([np.stack([b[0], b[1], b[2], u[0]]), np.stack([b[1], b[2], u[0], u[1]]),
                      np.stack([b[2], u[0], u[1], u[2]])], axis=1).reshape(4, -1)
        mesh = MeshTet(points, t)
    return mesh


#: the section element of each 3D element kind (the inverse of :data:`EXTRUDED_ELEMENT`)
SECTION_ELEMENT: dict[str, str] = {v: k for k, v in EXTRUDED_ELEMENT.items()}
#: the cells around a cylinder: a multiple of 4, at least this many
CYLINDER_MIN_AROUND = 8


def cylinder(
    name: str,
    centre: tuple[float, float, float],
    radius: float,
    height: float,
    n: tuple[int, int, int],
    material: Material,
    element: str = "hex8",
) -> Body:
    """A circular cylinder with its axis along z: the base centred at ``centre`` (m), of
    ``radius`` and ``height`` (m), meshed with ``n`` = (n_around, n_radial, n_height) cells.

    The section is an O-grid: a central square of (n_around / 4)² quadrilaterals and
    ``n_radial`` rings of ``n_around`` quadrilaterals out to the circle, swept along z in
    ``n_height`` layers (:func:`extrude`: hexahedra, or each quadrilateral cut into two
    triangles and each prism into three tetrahedra).  The circle is the polygon of its
    ``n_around`` nodes (straight element edges, also for the quadratic elements): the volume is
    (N/2) r² sin(2π/N) H, N = n_around, which tends to π r² H.  ``n_around`` is a multiple of 4,
    at least :data:`CYLINDER_MIN_AROUND`.  Named boundaries: ``bottom`` (z = z₀), ``top``
    (z = z₀ + H) and ``side`` (the lateral faces, every node at the radius).

    Example
    -------
    >>> from stepcontact import Material
    >>> from stepcontact.model.mesh import cylinder
    >>> c = cylinder("pier", (0, 0, 0), 0.5, 2.0, (16, 2, 4), Material(30e9, 0.2))
    >>> c.element, c.boundary_names
    ('hex8', ('bottom', 'top', 'side'))
    """
    item = f"body '{name}'"
    if element not in SOLID_KINDS:
        raise ModelError(f"{item}.element", f"unknown element '{element}' for a cylinder, use "
                         f"{', '.join(SOLID_KINDS)}")
    c0 = _vector(f"{item}.centre", centre, "point", 3)
    for key, v in (("radius", radius), ("height", height)):
        if not isinstance(v, int | float | np.number) or not np.isfinite(v) or v <= 0:
            raise ModelError(f"{item}.{key}", f"must be a positive length, m; got {v!r}")
    try:
        counts = tuple(n)
    except TypeError:
        counts = ()
    if len(counts) != 3:
        raise ModelError(f"{item}.n", "must be three cell counts (n_around, n_radial, "
                         f"n_height), got {n!r}")
    around = _check_count(name, "n[0]", counts[0], CYLINDER_MIN_AROUND)
    if around % 4:
        raise ModelError(f"{item}.n[0]", f"the cells around must be a multiple of 4, got "
                         f"{around}")
    radial = _check_count(name, "n[1]", counts[1])
    layers = _check_count(name, "n[2]", counts[2])
    from stepcontact.model.size import check_size

    per = 2 if element in ("tet10", "hex20", "hex27") else 1
    section_nodes = (per * around // 4 + 1) ** 2 + per * around * per * radial
    check_size(3 * section_nodes * (per * layers + 1), item,
               f"the {around} × {radial} × {layers} {element} cylinder '{name}'")
    section = _disc(float(radius), around // 4, radial, quads=element.startswith("hex"))
    section = dataclasses.replace(section, doflocs=section.doflocs + c0[:2, None])
    zz = np.array([c0[2], c0[2] + float(height)])
    mesh = _extruded_mesh(section, zz, layers)
    tol = 1e-9 * float(max(radius, height))
    facets = mesh.boundary_facets()
    corners = mesh.p[:, mesh.facets[:, facets]]  # (3, corners, nf)
    r = np.hypot(corners[0] - c0[0], corners[1] - c0[1])
    faces = {"bottom": facets[np.all(np.abs(corners[2] - zz[0]) <= tol, axis=0)],
             "top": facets[np.all(np.abs(corners[2] - zz[1]) <= tol, axis=0)],
             "side": facets[np.all(np.abs(r - radius) <= tol, axis=0)]}
    return Body.from_mesh(name, mesh.with_boundaries(faces), element, material)


def _disc(r: float, k: int, rings: int, quads: bool):
    """The O-grid of a disc of radius r about the origin: a k × k square of quadrilaterals
    (half side 0.35 r) and ``rings`` rings of 4k quadrilaterals blended linearly from the
    square's boundary to the 4k points of the circle at the angles −π/4 + 2πi/(4k) (the
    square's corners at −π/4, π/4, …); triangles (each quadrilateral cut in two) when
    ``quads`` is False."""
    a = 0.35 * r
    s = np.linspace(-a, a, k + 1)
    gx, gy = np.meshgrid(s, s)  # grid node (ix, iy) is iy (k + 1) + ix
    grid = np.column_stack([gx.ravel(), gy.ravel()])
    g = np.arange((k + 1) ** 2).reshape(k + 1, k + 1)  # g[iy, ix]
    inner = np.column_stack([g[:-1, :-1].ravel(), g[:-1, 1:].ravel(), g[1:, 1:].ravel(),
                             g[1:, :-1].ravel()])
    # the square's boundary counter-clockwise from the corner (a, −a): right, top, left, bottom
    ring0 = np.r_[g[:k, k], g[k, k:0:-1], g[k:0:-1, 0], g[0, :k]]
    theta = -np.pi / 4 + 2 * np.pi * np.arange(4 * k) / (4 * k)
    circle = r * np.column_stack([np.cos(theta), np.sin(theta)])
    t = np.arange(1, rings + 1)[:, None, None] / rings
    layers = (1 - t) * grid[ring0][None] + t * circle[None]  # (rings, 4k, 2)
    ids = np.vstack([ring0, len(grid) + np.arange(rings * 4 * k).reshape(rings, 4 * k)])
    nxt = np.roll(ids, -1, axis=1)
    outer = np.column_stack([ids[:-1].ravel(), nxt[:-1].ravel(), nxt[1:].ravel(),
                             ids[1:].ravel()])
    points = np.vstack([grid, layers.reshape(-1, 2)]).T
    cells = np.vstack([inner, outer])
    if quads:
        return MeshQuad(points, cells.T.copy())
    tris = np.vstack([cells[:, [0, 1, 2]], cells[:, [0, 2, 3]]])
    return MeshTri(points, tris.T.copy(), sort_t=False)



# --------------------------------------------------------------------------------------------
# mapped quadrilateral regions
# --------------------------------------------------------------------------------------------
#: edges of a four-sided region by the corners they join (counter-clockwise from corner 0)
QUAD_EDGES: dict[str, tuple[int, int]] = {"bottom": (0, 1), "right": (1, 2), "top": (2, 3),
                                          "left": (3, 0)}


def _counter_clockwise(mesh):
    """The linear mesh with every cell numbered counter-clockwise (positive area).

    scikit-fem accepts either orientation (``init_tensor`` numbers its cells clockwise and
    ``MeshTri`` sorts the nodes of each cell); the generators of this module give positive
    areas, so the signed area is the cell's size.
    """
    x, y = mesh.p[:, mesh.t]
    area2 = np.sum(x * np.roll(y, -1, axis=0) - np.roll(x, -1, axis=0) * y, axis=0)
    kind = "triangle" if mesh.t.shape[0] == 3 else "quad"
    t = np.where(area2 < 0, mesh.t[REVERSED_NODE_ORDER[kind]], mesh.t)
    return MeshTri(mesh.p, t, sort_t=False) if kind == "triangle" else MeshQuad(mesh.p, t)


def _check_element(name: str, element: str) -> None:
    if element not in ELEMENT_KINDS:
        raise ModelError(f"body '{name}'.element",
                         f"unknown element '{element}', use {', '.join(ELEMENT_KINDS)}")


def _check_count(name: str, field: str, n, minimum: int = 1) -> int:
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < minimum:
        raise ModelError(f"body '{name}'.{field}", f"must be an integer >= {minimum}, got {n!r}")
    return int(n)


def _towards(n: int, start: float = 1.0, end: float = 1.0) -> np.ndarray:
    """n intervals of [0, 1] shrinking geometrically towards 0 (largest / smallest = ``start``)
    and/or towards 1 (``end``); with both, each half of the intervals grades towards its end."""
    if start == 1.0 and end == 1.0:
        return np.linspace(0.0, 1.0, n + 1)
    if end == 1.0:
        return _axis(0.0, 1.0, n, start)
    if start == 1.0:
        return 1.0 - _axis(0.0, 1.0, n, end)[::-1]
    n0 = n // 2
    if n0 == 0:
        return np.array([0.0, 1.0])
    mid = n0 / n
    first = mid * _axis(0.0, 1.0, n0, start)
    second = mid + (1.0 - mid) * (1.0 - _axis(0.0, 1.0, n - n0, end)[::-1])
    second[-1] = 1.0
    return np.r_[first, second[1:]]


def _parameters(name: str, grading, nx: int, ny: int) -> tuple[np.ndarray, np.ndarray]:
    """Grid lines s (corner 0 -> 1) and t (corner 0 -> 3) on [0, 1] of a ``grading`` spec."""
    item = f"body '{name}'.grading"
    if isinstance(grading, Mapping):
        bad = sorted(set(grading) - set(QUAD_EDGES))
        if bad:
            raise ModelError(item, f"unknown edge '{bad[0]}', use {', '.join(QUAD_EDGES)}")
        r = {}
        for edge in QUAD_EDGES:
            v = grading.get(edge, 1.0)
            if isinstance(v, bool) or not isinstance(v, int | float | np.floating | np.integer) \
                    or not np.isfinite(v) or v < SIZE_RATIO_MIN:
                raise ModelError(f"{item}['{edge}']", f"must be a size ratio >= {SIZE_RATIO_MIN} "
                                 f"(largest / smallest cell), got {v!r}")
            r[edge] = float(v)
        return (_towards(nx, r["left"], r["right"]), _towards(ny, r["bottom"], r["top"]))
    if grading_problem(grading) is not None:
        raise ModelError(item, "must be (gx, gy) with factors > 0, or {edge: ratio} with edges "
                               f"{', '.join(QUAD_EDGES)}; got {grading!r}")
    g = np.asarray(grading, dtype=float)
    return _axis(0.0, 1.0, nx, float(g[0])), _axis(0.0, 1.0, ny, float(g[1]))


def _corners(name: str, corners) -> np.ndarray:
    """Four finite corners of a strictly convex quadrilateral, counter-clockwise."""
    item = f"body '{name}'.corners"
    try:
        P = np.asarray(corners, dtype=float)
    except (TypeError, ValueError):
        raise ModelError(item, "must be four points (x, y), m") from None
    if P.shape != (4, 2) or not np.all(np.isfinite(P)):
        raise ModelError(item, f"must be four finite points (x, y), m; got shape {P.shape}")
    a = P - np.roll(P, 1, axis=0)  # edge into each corner
    b = np.roll(P, -1, axis=0) - P  # edge out of it
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    tol = 1e-12 * float(np.ptp(P, axis=0).max()) ** 2
    if np.all(cross < -tol):
        raise ModelError(item, "are clockwise: list them counter-clockwise")
    bad = np.flatnonzero(cross <= tol)
    if bad.size:
        raise ModelError(item, f"do not form a convex quadrilateral (the angle at corner "
                               f"{int(bad[0])} is not below 180°)")
    return P


def quad_region(
    name: str,
    corners,
    nx: int,
    ny: int,
    material: Material,
    element: str = "quad4",
    *,
    grading: tuple[float, float] | Mapping[str, float] = (1.0, 1.0),
) -> Body:
    r"""A body filling the convex quadrilateral ``corners`` (four points, counter-clockwise, m),
    meshed with ``nx`` cells along edge 0→1 (and 3→2) and ``ny`` along edge 0→3 (and 1→2).

    The mesh is the image of a structured grid (s, t) on the unit square under the bilinear
    (transfinite) map

    .. math::  \mathbf{x}(s, t) = (1-s)(1-t)\,\mathbf{P}_0 + s(1-t)\,\mathbf{P}_1
               + s t\,\mathbf{P}_2 + (1-s)t\,\mathbf{P}_3,

    so straight grid lines join points at equal fractions of opposite edges and the corners are
    nodes exactly.  ``element`` is ``tri3``, ``tri6``, ``quad4``, ``quad8`` or ``quad9`` (as for
    :func:`rectangle`: a scikit-fem ``MeshTri``/``MeshQuad`` made with ``init_tensor`` and
    mapped; quadratic elements add their nodes through :meth:`Body.from_mesh`).

    ``grading`` is either

    * ``(gx, gy)``: size of the last cell / size of the first, along s and along t (as for
      :func:`rectangle`); or
    * ``{edge: ratio}`` with edges ``"bottom"`` (corners 0→1), ``"right"`` (1→2), ``"top"``
      (2→3), ``"left"`` (3→0): the cells shrink geometrically towards that edge, ``ratio``
      (>= 1) being largest / smallest cell across it.  Two adjacent edges refine towards their
      common corner, e.g. ``{"bottom": 4, "left": 4}`` towards corner 0; two opposite edges
      refine towards both (each half of the cells grading towards its edge).

    Example
    -------
    >>> from stepcontact import Material
    >>> from stepcontact.model.mesh import quad_region
    >>> wedge = quad_region("wedge", [(0, 0), (4, 0), (4, 1), (0, 3)], 8, 4,
    ...                     Material(30e9, 0.2, 2400), grading={"bottom": 5.0})
    >>> wedge.n_nodes
    45
    """
    _check_element(name, element)
    nx = _check_count(name, "nx", nx)
    ny = _check_count(name, "ny", ny)
    P = _corners(name, corners)
    s, t = _parameters(name, grading, nx, ny)
    mesh = _mapped(P, s, t, MeshTri if element.startswith("tri") else MeshQuad)
    return Body.from_mesh(name, mesh, element, material)


def _mapped(P: np.ndarray, s: np.ndarray, t: np.ndarray, cls):
    """The tensor grid (s, t) on the unit square mapped bilinearly onto the quadrilateral P
    (the map of :func:`quad_region`), cells counter-clockwise."""
    unit = cls.init_tensor(s, t)
    S, T = unit.doflocs
    X = (np.outer(P[0], (1 - S) * (1 - T)) + np.outer(P[1], S * (1 - T))
         + np.outer(P[2], S * T) + np.outer(P[3], (1 - S) * T))
    return _counter_clockwise(dataclasses.replace(unit, doflocs=X))


# --------------------------------------------------------------------------------------------
# polygons: a structured triangle, or any simple polygon by gmsh
# --------------------------------------------------------------------------------------------
def _segments_cross(P: np.ndarray) -> tuple[int, int] | None:
    """The first pair of non-adjacent edges of the closed polygon P that touch or cross
    (edge i joins vertices i and i+1), or None."""
    k = len(P)
    A, B = P, np.roll(P, -1, axis=0)
    scale = float(np.ptp(P, axis=0).max())

    def orient(a, b, c):
        v = (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) \
            - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0])
        return np.where(np.abs(v) <= 1e-12 * scale**2, 0.0, np.sign(v))

    i, j = np.triu_indices(k, 2)
    keep = ~((i == 0) & (j == k - 1))  # the first and last edges are adjacent
    i, j = i[keep], j[keep]
    o1, o2 = orient(A[i], B[i], A[j]), orient(A[i], B[i], B[j])
    o3, o4 = orient(A[j], B[j], A[i]), orient(A[j], B[j], B[i])
    proper = (o1 * o2 < 0) & (o3 * o4 < 0)

    def on(a, b, c, o):  # c on the segment ab (collinear and inside its box)
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        return (o == 0) & np.all((c >= lo - 1e-12 * scale) & (c <= hi + 1e-12 * scale), axis=1)

    touch = (on(A[i], B[i], A[j], o1) | on(A[i], B[i], B[j], o2) | on(A[j], B[j], A[i], o3)
             | on(A[j], B[j], B[i], o4))
    bad = np.flatnonzero(proper | touch)
    return None if bad.size == 0 else (int(i[bad[0]]), int(j[bad[0]]))


def _polygon(name: str, vertices) -> np.ndarray:
    """The vertices of a simple polygon with a positive area, counter-clockwise (a clockwise
    list is reversed, keeping its first vertex first)."""
    item = f"body '{name}'.vertices"
    try:
        P = np.asarray(vertices, dtype=float)
    except (TypeError, ValueError):
        raise ModelError(item, "must be a list of points (x, y), m") from None
    if P.ndim != 2 or P.shape[1:] != (2,) or len(P) < 3:
        raise ModelError(item, f"must be at least three points (x, y), m; got shape {P.shape}")
    if not np.all(np.isfinite(P)):
        raise ModelError(item, "must be finite")
    scale = float(np.ptp(P, axis=0).max())
    gap = np.hypot(*(np.roll(P, -1, axis=0) - P).T)
    if scale == 0 or np.any(gap <= 1e-12 * scale):
        k = int(np.argmin(gap))
        raise ModelError(item, f"vertices {k} and {(k + 1) % len(P)} coincide")
    area2 = float(np.sum(P[:, 0] * np.roll(P[:, 1], -1) - np.roll(P[:, 0], -1) * P[:, 1]))
    cross = _segments_cross(P)
    if cross is not None:
        i, j = cross
        raise ModelError(item, f"the polygon crosses itself: edge {i} (vertices {i}–"
                               f"{(i + 1) % len(P)}) meets edge {j} (vertices {j}–"
                               f"{(j + 1) % len(P)})")
    if abs(area2) <= 1e-12 * scale**2:
        raise ModelError(item, "the polygon has no area (its vertices are on one line)")
    return P if area2 > 0 else np.r_[P[:1], P[:0:-1]]


def _triangle_mesh(P: np.ndarray, n: int, quads: bool):
    """The triangle P (counter-clockwise) meshed with ``n`` cells along every edge.

    Triangles: the points A + (i/n)(B − A) + (j/n)(C − A), i + j ≤ n, joined into n² triangles
    all similar to ABC (the uniform refinement of ABC).  Quads (n even): the triangle cut at
    its centroid G and the mid-points of its edges into three convex quadrilaterals
    (vertex, mid-point, G, mid-point), each meshed n/2 × n/2 by :func:`_mapped`.
    """
    if quads:
        m = n // 2
        G = P.mean(axis=0)
        M = 0.5 * (P + np.roll(P, -1, axis=0))  # M[i]: the middle of edge i → i+1
        u = np.linspace(0.0, 1.0, m + 1)
        parts = [_mapped(np.array([P[i], M[i], G, M[i - 1]]), u, u, MeshQuad) for i in range(3)]
        points = np.hstack([q.p for q in parts])
        offsets = np.cumsum([0] + [q.nvertices for q in parts])
        cells = np.hstack([q.t + o for q, o in zip(parts, offsets[:-1], strict=True)])
        # merge the nodes the three parts share, keeping the coordinates of the first copy
        tol = 1e-9 * float(np.ptp(P, axis=0).max()) / n
        pairs = cKDTree(points.T).query_pairs(tol, output_type="ndarray")
        N = points.shape[1]
        graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(N, N))
        _, label = connected_components(graph, directed=False)
        first = np.full(label.max() + 1, N)
        np.minimum.at(first, label, np.arange(N))
        keep = np.sort(first)
        new = np.empty(label.max() + 1, dtype=np.int64)
        new[np.argsort(first)] = np.arange(len(keep))
        return MeshQuad(np.ascontiguousarray(points[:, keep]), new[label][cells])
    i, j = np.nonzero(np.add.outer(np.arange(n + 1), np.arange(n + 1)) <= n)
    index = np.full((n + 2, n + 2), -1)
    index[i, j] = np.arange(len(i))
    X = P[0][:, None] + np.outer(P[1] - P[0], i / n) + np.outer(P[2] - P[0], j / n)
    X[:, index[n, 0]], X[:, index[0, n]] = P[1], P[2]  # the vertices exactly
    a, b = np.nonzero(np.add.outer(np.arange(n), np.arange(n)) < n)
    up = np.stack([index[a, b], index[a + 1, b], index[a, b + 1]])
    a, b = np.nonzero(np.add.outer(np.arange(n), np.arange(n)) < n - 1)
    down = np.stack([index[a + 1, b], index[a + 1, b + 1], index[a, b + 1]])
    return MeshTri(X, np.hstack([up, down]), sort_t=False)


def _gmsh_polygon(name: str, P: np.ndarray, size: float, quads: bool):
    """A simple polygon meshed by gmsh (frontal Delaunay; quads recombined), cell size
    ``size``; its vertices are nodes."""
    from stepcontact.model.gmsh_api import gmsh_module, gmsh_session

    try:
        gmsh = gmsh_module()
    except ModelError as e:
        raise ModelError(f"body '{name}'.vertices",
                         f"a polygon of {len(P)} vertices is meshed by gmsh, which is not "
                         f"available ({e}); install it (pip install \"stepcontact[gmsh]\"), or "
                         "build the body from triangles and four-sided regions "
                         "(sc.polygon_region with three vertices, sc.quad_region)") from None
    # quads: recombined and then subdivided once (every cell a quad), from cells twice as large
    options = {"General.Terminal": 0.0, "Mesh.RecombineAll": 1.0 if quads else 0.0,
               "Mesh.SubdivisionAlgorithm": 1.0 if quads else 0.0, "Mesh.Algorithm": 6.0,
               "Mesh.MeshSizeMax": float(size) * (2.0 if quads else 1.0),
               "Mesh.MeshSizeMin": 0.0, "Mesh.MeshSizeFromPoints": 0.0,
               "Mesh.MeshSizeExtendFromBoundary": 1.0}
    with gmsh_session(options, gmsh):
        gmsh.model.add(f"stepcontact-polygon-{name}")
        tags = [gmsh.model.geo.addPoint(x, y, 0.0) for x, y in P]
        lines = [gmsh.model.geo.addLine(tags[i], tags[(i + 1) % len(P)]) for i in range(len(P))]
        loop = gmsh.model.geo.addCurveLoop(lines)
        gmsh.model.geo.addPlaneSurface([loop])
        gmsh.model.geo.synchronize()
        gmsh.model.mesh.generate(2)
        node_tags, xyz, _ = gmsh.model.mesh.getNodes()
        # gmsh element types: 2 triangle, 3 quadrangle
        _, cell_nodes = gmsh.model.mesh.getElementsByType(3 if quads else 2)
        others = len(gmsh.model.mesh.getElementsByType(2 if quads else 3)[0])
        gmsh.model.remove()
    if others:
        raise ModelError(f"body '{name}'.vertices", "gmsh left cells of another shape in the "
                         "mesh of the polygon; use triangles (element = 'tri3' or 'tri6')")
    order = np.argsort(node_tags)
    points = xyz.reshape(-1, 3)[order, :2].T  # by node tag
    used, cells = np.unique(np.searchsorted(node_tags[order], cell_nodes), return_inverse=True)
    points = points[:, used]  # only the nodes of the surface's cells
    # the vertices exactly (gmsh places its nodes on the geometry's points)
    points[:, np.argmin(np.hypot(*(points[:, :, None] - P.T[:, None, :])), axis=0)] = P.T
    points, cells = np.ascontiguousarray(points), cells.reshape(-1, 4 if quads else 3).T
    mesh = MeshQuad(points, cells) if quads else MeshTri(points, cells, sort_t=False)
    return _counter_clockwise(mesh)


#: nodes per cell of a large mesh (vertices and mid-side nodes shared by the neighbours)
_NODES_PER_CELL = {"tri3": 0.5, "tri6": 2.0, "quad4": 1.0, "quad8": 3.0, "quad9": 4.0}


def polygon_region(
    name: str,
    vertices,
    material: Material,
    element: str = "tri3",
    *,
    n: int | None = None,
    size: float | None = None,
) -> Body:
    """A body filling the simple polygon ``vertices`` (m); every vertex is a node, so
    supports, loads and interfaces can select it.

    * **A triangle** (three vertices) is meshed without gmsh: ``n`` cells along every edge
      (or ``size``, m: n = ⌈longest edge / size⌉).  Triangles (``tri3``, ``tri6``): the uniform
      refinement of the triangle, n² cells all similar to it (its shape is their quality).
      Quads (``quad4``, ``quad8``, ``quad9``): the triangle cut at its centroid and the
      mid-points of its edges into three convex four-sided regions, each meshed n/2 × n/2
      (n rounded up to even).  A triangular dam section: ``polygon_region("dam", [(0, 0),
      (B, 0), (0, H)], concrete, n=12)``.
    * **Any other simple polygon** (no edge crosses another; convex or not) is meshed by gmsh
      (the optional dependency, ``pip install "stepcontact[gmsh]"``) with cells of about
      ``size`` (m; or the perimeter / (n × vertices)), quads recombined from triangles.

    The vertices may be listed either way round (clockwise lists are reversed); a polygon
    that crosses itself, repeats a vertex or has no area is a ``ModelError`` naming
    ``vertices``.  Quadratic elements put their mid-side nodes on the straight edges
    (:meth:`Body.from_mesh`), so the area and the centroid are the polygon's exactly.

    Example
    -------
    >>> from stepcontact import Material
    >>> from stepcontact.model.mesh import polygon_region
    >>> dam = polygon_region("dam", [(0, 0), (8, 0), (0, 10)], Material(30e9, 0.2, 2400), n=4)
    >>> dam.n_nodes, len(dam.cells)
    (15, 16)
    """
    item = f"body '{name}'"
    _check_element(name, element)
    P = _polygon(name, vertices)
    if (text := cells_problem(n, size)) is not None:
        raise ModelError(f"{item}.n", text)
    if n is not None:
        n = _check_count(name, "n", n)
    elif isinstance(size, bool) or not isinstance(size, int | float | np.floating | np.integer) \
            or not np.isfinite(size) or size <= 0:
        raise ModelError(f"{item}.size", f"must be a positive cell size in m, got {size!r}")
    quads = element.startswith("quad")
    edges = np.hypot(*(np.roll(P, -1, axis=0) - P).T)
    from stepcontact.model.size import check_size

    if len(P) == 3:
        if n is None:
            n = max(1, int(np.ceil(edges.max() / float(size) - 1e-9)))
        n = n + n % 2 if quads else n
        cells = 3 * (n // 2) ** 2 if quads else n * n
        nodes = int(cells * _NODES_PER_CELL[element]) + n + 1
        check_size(2 * nodes, item, f"the {element} mesh of body '{name}' ({cells:.3g} cells)")
        mesh = _triangle_mesh(P, n, quads)
    else:
        h = float(size) if size is not None else float(edges.sum()) / (n * len(P))
        area = 0.5 * float(np.sum(P[:, 0] * np.roll(P[:, 1], -1) - np.roll(P[:, 0], -1) * P[:, 1]))
        cells = area / (np.sqrt(3) / 4 * h * h)  # equilateral triangles of side h, about
        nodes = cells * _NODES_PER_CELL[element]
        check_size(int(2 * nodes), item, f"the {element} mesh of body '{name}' (about "
                   f"{cells:.3g} cells of size {h:.3g} m)")
        mesh = _gmsh_polygon(name, P, h, quads)
    return Body.from_mesh(name, mesh, element, material)


# --------------------------------------------------------------------------------------------
# half disc refined towards its contact point
# --------------------------------------------------------------------------------------------
def half_disc(
    name: str,
    center: tuple[float, float],
    radius: float,
    n_radial: int,
    n_around: int,
    material: Material,
    element: str = "quad4",
    *,
    refine_toward: str | None = "bottom",
    ratio: float = 8.0,
) -> Body:
    """The lower half of the disc of ``radius`` (m) about ``center``: flat face on top (y = y_c),
    arc below, its lowest point (x_c, y_c − R) a node, for Hertz-type contact on that point.

    The mesh (all cells convex and counter-clockwise) has two parts: a core, the square
    [x_c − R/2, x_c + R/2] × [y_c − R/2, y_c] under the flat face, meshed as a tensor grid; and
    a band of ``n_radial`` rings between the core and the arc, along ``n_around`` + 1 straight
    spokes that are rays from the centre (x_c, y_c) through the nodes of the arc.  ``n_around``
    (even, >= 4) counts the cells along the arc: uniform steps on the side quarters (|ψ| from 90°
    to 45°, ψ the angle from the downward vertical) and the rest on the bottom quarters.

    With ``refine_toward="bottom"`` the cells shrink geometrically towards the contact point:
    on the bottom quarters the largest / smallest angular step is ``ratio`` (smallest at the
    contact point, the core's grid lines following the spokes); along each spoke the innermost
    / outermost radial step is ratio^cos²ψ, i.e. ``ratio`` below the contact point, falling to
    uniform at the ends of the flat face.  ``refine_toward=None`` gives uniform steps.

    The arc is polygonal (straight element edges; quadratic elements put their mid-side nodes
    on the chords).  ``element``: ``tri3``, ``tri6``, ``quad4``, ``quad8`` or ``quad9``.

    Example
    -------
    >>> from stepcontact import Material
    >>> from stepcontact.model.mesh import half_disc
    >>> roller = half_disc("roller", (0.0, 0.5), 0.5, 8, 16, Material(210e9, 0.3, 7850))
    >>> bool((abs(roller.points - (0.0, 0.0)).sum(axis=1) == 0).any())  # the contact point
    True
    """
    item = f"body '{name}'"
    _check_element(name, element)
    M = _check_count(name, "n_radial", n_radial)
    N = _check_count(name, "n_around", n_around, HALF_DISC_MIN_AROUND)
    if N % 2:
        raise ModelError(f"{item}.n_around",
                         f"must be even (a node at the contact point), got {N}")
    c = _vector(f"{item}.center", center, "point")
    if not isinstance(radius, int | float | np.floating | np.integer) or not np.isfinite(radius) \
            or radius <= 0:
        raise ModelError(f"{item}.radius", f"must be positive and finite, got {radius!r}")
    if refine_toward not in ("bottom", None):
        raise ModelError(f"{item}.refine_toward",
                         f"must be 'bottom' (the contact point) or None, got {refine_toward!r}")
    if not isinstance(ratio, int | float | np.floating | np.integer) or not np.isfinite(ratio) \
            or ratio < SIZE_RATIO_MIN:
        raise ModelError(f"{item}.ratio", f"must be a size ratio >= {SIZE_RATIO_MIN}, got "
                         f"{ratio!r}")
    r = float(ratio) if refine_toward == "bottom" else 1.0
    R = float(radius)
    # spoke angles ψ from the downward vertical: n1 uniform steps on each side quarter
    # (|ψ| from 90° to 45°), n2 steps on the bottom quarters graded towards ψ = 0
    n1, n2 = _arc_split(N, r)
    g = _axis(0.0, 1.0, n2 // 2, r)  # from ψ = 0 to 45°, growing
    side = np.linspace(0.25, 0.5, n1 + 1)[1:]
    bottom = 0.25 * np.r_[-g[:0:-1], g]  # ψ / π on the bottom quarters, -1/4 … 1/4
    frac = np.r_[-side[::-1], bottom, side]  # ψ / π of spokes 0 … N
    psi = np.pi * frac
    arc = np.stack([R * np.sin(psi), -R * np.cos(psi)])
    arc[:, [0, N]] = [[-R, R], [0.0, 0.0]]  # the ends of the flat face, exactly
    # core: the square [-a, a] × [-a, 0] under the flat face, its grid lines where the spokes
    # (rays from the centre) cross its sides, so the band of rings around it is radial
    a = 0.5 * R
    xs = a * np.tan(np.pi * bottom)  # x of the bottom side's nodes
    xs[[0, -1]] = -a, a
    ys = -a / np.tan(np.pi * np.r_[0.25, side])  # y of the left side's nodes, -a … 0
    ys[[0, -1]] = -a, 0.0
    inner = np.hstack([
        np.stack([np.full(n1, -a), ys[::-1][:-1]]),  # left side, top to bottom (corner excl.)
        np.stack([xs, np.full(n2 + 1, -a)]),  # bottom side
        np.stack([np.full(n1, a), ys[1:]]),  # right side, bottom to top
    ])
    # ring j of spoke k at ρ_jk along it; steps shrink towards the arc by ratio^cos²ψ
    rho = np.stack([_axis(0.0, 1.0, M, 1.0 / rk) for rk in r ** np.cos(psi) ** 2], axis=1)
    band = inner[:, None, :] + rho[None] * (arc - inner)[:, None, :]  # (2, M+1, N+1)
    # topology by scikit-fem: the core's tensor grid and the band's (ring, spoke) grid, joined
    # where the band's first ring is the core's boundary
    core = MeshQuad.init_tensor(xs, ys)
    grid = MeshQuad.init_tensor(np.arange(M + 1.0), np.arange(N + 1.0))
    j, k = np.rint(grid.doflocs).astype(np.int64)
    points = np.hstack([core.doflocs, band[:, j, k]]) + c[:, None] + 0.0  # no -0.0
    cells = np.hstack([core.t, grid.t + core.nvertices])
    # merge the nodes the band and the core share (the same floats: one formula for both)
    unique, index = np.unique(points.T, axis=0, return_inverse=True)
    mesh = MeshQuad(np.ascontiguousarray(unique.T), index.ravel()[cells])
    if element.startswith("tri"):
        mesh = mesh.to_meshtri()
    return Body.from_mesh(name, _counter_clockwise(mesh), element, material)


def _arc_split(N: int, r: float) -> tuple[int, int]:
    """Cells (n1, n2) on each side quarter and on the two bottom quarters of the arc
    (N = 2 n1 + n2, n2 even): the side steps match the largest bottom step best."""
    best = None
    for n2 in range(2, N - 1, 2):
        n1 = (N - n2) // 2
        # largest bottom step / side step, both as fractions of 45°
        score = abs(np.log(np.diff(_axis(0.0, 1.0, n2 // 2, r))[-1] * n1))
        if best is None or score < best[0] - 1e-12:
            best = (score, n1, n2)
    return best[1], best[2]


# --------------------------------------------------------------------------------------------
# rigid motions
# --------------------------------------------------------------------------------------------
def _vector(item: str, v, what: str, dim: int = 2) -> np.ndarray:
    """``v`` as a finite point or vector of ``dim`` coordinates (m), else a ModelError naming
    ``item``."""
    try:
        a = np.asarray(v, dtype=float)
    except (TypeError, ValueError):
        a = np.zeros(0)
    if a.shape != (dim,) or not np.all(np.isfinite(a)):
        axes = "(x, y)" if dim == 2 else "(x, y, z)"
        raise ModelError(item, f"must be a finite {what} {axes}, m; got {v!r}")
    return a


def _moved(b, f):
    """A body or frame with its points mapped by ``f`` ((2, n) -> (2, n)); node numbering,
    node sets and element data are unchanged."""
    if isinstance(b, Body):
        mesh = dataclasses.replace(b.mesh, doflocs=f(b.mesh.doflocs))
        return dataclasses.replace(b, mesh=mesh, points=np.ascontiguousarray(f(b.points.T).T))
    if isinstance(b, Frame):
        return dataclasses.replace(b, points=f(b.points.T).T)
    raise ModelError("rotate/translate", f"expects a Body, Frame or Model, got {type(b).__name__}")


def _moved_obstacle(itf, f):
    """An interface whose rigid obstacle (``minus``) has its points mapped by ``f``."""
    if not isinstance(itf.minus, RigidObstacle):
        return itf
    obs = itf.minus
    return dataclasses.replace(itf, minus=dataclasses.replace(
        obs, points=np.ascontiguousarray(f(np.array(obs.points).T).T)))


def _rotated_spring(s: Spring, Q: np.ndarray) -> Spring:
    """A spring whose stiffness is Q k Qᵀ (its axes turned by the rotation Q)."""
    d = None if s.direction is None else tuple(float(v) for v in Q @ s.direction)
    if s.kx == s.ky:  # the axis part is isotropic
        return dataclasses.replace(s, direction=d)
    if s.direction is None and s.damping == 0:
        # kx ex⊗ex + ky ey⊗ey = min I + |kx - ky| e⊗e (e the stiffer axis), e turned by Q
        e = Q[:, 0] if s.kx > s.ky else Q[:, 1]
        kmin = min(s.kx, s.ky)
        return dataclasses.replace(s, kx=kmin, ky=kmin, k=abs(s.kx - s.ky),
                                   direction=(float(e[0]), float(e[1])))
    raise ModelError(f"spring '{s.name}'",
                     "has kx != ky and a direction or damping: it cannot be turned as one spring; "
                     "give its parts as separate springs along their directions (k, direction)")


def _rotated_component_pair(spec_x, spec_y, Q: np.ndarray, item: str):
    """Rotate a traction given by two component specs (numbers or [start, end] pairs)."""
    if callable(spec_x) or callable(spec_y):
        raise ModelError(item, "a traction given by functions of (x, y) cannot be rotated: "
                               "rotate the model with rotate_loads=False and give it rotated")
    a = np.broadcast_arrays(np.asarray(spec_x, float), np.asarray(spec_y, float))
    v = Q @ np.stack([a[0].ravel(), a[1].ravel()])
    if a[0].ndim == 0:
        return (float(v[0, 0]), float(v[1, 0]))
    return (tuple(float(t) for t in v[0]), tuple(float(t) for t in v[1]))


def _rotated_load(ld, Q: np.ndarray, item: str):
    """A load with its vectors turned by Q (global-axis components only)."""
    if isinstance(ld, BodyForce):
        return dataclasses.replace(ld, g=tuple(float(v) for v in Q @ np.asarray(ld.g, float)))
    if isinstance(ld, PrescribedDisplacement):
        if ld.dof in ("x", "y") and ld.value != 0:
            raise ModelError(item, f"a prescribed {ld.dof} displacement cannot be rotated (it "
                                   "acts along a global axis)")
        return ld
    if isinstance(ld, ObstacleMotion):
        if ld.dx != 0 or ld.dy != 0:
            raise ModelError(item, f"the motion of obstacle '{ld.name}' cannot be rotated (its "
                                   "translation acts along the global axes)")
        return ld
    changes = {}
    if hasattr(ld, "fx") and hasattr(ld, "fy"):  # nodal and total edge forces
        f = Q @ np.array([ld.fx, ld.fy], dtype=float)
        changes.update(fx=float(f[0]), fy=float(f[1]))
    if getattr(ld, "traction", None) is not None:  # edge tractions in global components
        changes["traction"] = _rotated_component_pair(*ld.traction, Q, f"{item}.traction")
    return dataclasses.replace(ld, **changes) if changes else ld


def rotate(item, angle: float, about: tuple[float, float] = (0.0, 0.0), *,
           rotate_loads: bool = False):
    """A copy of a body, a frame or a whole model turned by ``angle`` (radians,
    counter-clockwise) about the point ``about`` (m).

    What turns with a model: the nodes of every body and frame; the points of rigid obstacles;
    the given ``normal`` of each interface; the ``direction`` of each spring (and the axes of
    a spring with ``kx != ky``, which becomes ``min(kx, ky)`` on both axes plus ``|kx − ky|``
    along its turned stiffer axis).  Node sets are local node indices, so they, the supports,
    ties, interfaces and loads keep referring to the same nodes.  Edge pressures (``normal``,
    ``tangential``) follow the turned edges by construction.

    What does **not** turn (it lives in the global axes): gravity ``BodyForce.g``, nodal and
    edge forces given by (fx, fy), edge tractions given by global components, supports (a
    support of ``x`` alone still fixes the global x: use a spring along a direction for an
    inclined roller) and prescribed displacements.  With ``rotate_loads=True`` the force vectors
    (gravity, (fx, fy), global tractions) turn too, so the whole problem is turned rigidly and
    the results are the turned ones; a non-zero prescribed x or y displacement is then an
    error.  Functions of position (pressures p(x, y), gaps g(x, y)) are evaluated at the new
    coordinates, not mapped back.

    Example
    -------
    >>> import numpy as np
    >>> from stepcontact import Material, rectangle
    >>> from stepcontact.model.mesh import rotate
    >>> b = rotate(rectangle("b", (0, 0), (2, 1), 2, 1, Material(1e9, 0.3)), np.pi / 2)
    >>> b.points[-1].round(12) + 0.0   # the corner (2, 1) turned by 90°
    array([-1.,  2.])
    """
    a = float(angle)
    if not np.isfinite(a):
        raise ModelError("rotate.angle", f"must be finite (radians), got {angle!r}")
    c0 = _vector("rotate.about", about, "point")[:, None]
    cs, sn = np.cos(a), np.sin(a)
    Q = np.array([[cs, -sn], [sn, cs]])

    def f(p):
        return Q @ (p - c0) + c0

    if not isinstance(item, Model):
        return _moved(item, f)
    patterns = item.patterns
    if rotate_loads:
        patterns = tuple(
            dataclasses.replace(pat, loads=tuple(
                _rotated_load(ld, Q, f"load pattern '{pat.name}' load {i}")
                for i, ld in enumerate(pat.loads)))
            for pat in item.patterns)
    return item.replace(
        bodies=tuple(_moved(b, f) for b in item.bodies),
        interfaces=tuple(
            _moved_obstacle(i if i.normal is None else dataclasses.replace(
                i, normal=tuple(float(v) for v in Q @ np.asarray(i.normal, float))), f)
            for i in item.interfaces),
        springs=tuple(_rotated_spring(s, Q) for s in item.springs),
        patterns=patterns,
    )


def translate(item, offset: tuple[float, float]):
    """A copy of a body, a frame or a whole model moved by ``offset`` = (dx, dy), m.

    Only node coordinates (and the points of rigid obstacles) change (node sets are local
    indices and stay valid; directions, normals and loads are unchanged).  Functions of
    position (pressures p(x, y), gaps g(x, y)) are evaluated at the new coordinates.

    Example
    -------
    >>> from stepcontact import Material, rectangle
    >>> from stepcontact.model.mesh import translate
    >>> translate(rectangle("b", (0, 0), (2, 1), 2, 1, Material(1e9, 0.3)), (1, -1)).points[0]
    array([ 1., -1.])
    """
    d = _vector("translate.offset", offset, "vector")[:, None]

    def f(p):
        return p + d

    if not isinstance(item, Model):
        return _moved(item, f)
    return item.replace(bodies=tuple(_moved(b, f) for b in item.bodies),
                        interfaces=tuple(_moved_obstacle(i, f) for i in item.interfaces))


# --------------------------------------------------------------------------------------------
# a block with a spherical face (Hertz contact in 3D)
# --------------------------------------------------------------------------------------------
def spherical_block(
    name: str,
    radius: float,
    xs,
    ys,
    top: float,
    layers,
    material: Material,
    element: str = "hex8",
) -> Body:
    """A block over [x0, x1] × [y0, y1] whose bottom is the sphere of ``radius`` R (m) resting
    on the plane z = 0 at the origin, z_s(x, y) = R − √(R² − x² − y²), and whose top is the
    plane z = ``top`` (m): a spherical tip (a ball's cap) for Hertz-type point contact.

    ``xs``, ``ys`` are the grid lines (m, increasing; x² + y² < R² and z_s < top over the
    block), so the mesh can be refined towards the contact point; ``layers`` are the grid
    lines through the thickness as fractions ζ from 0 (the sphere) to 1 (the top), each
    column of nodes at z = z_s + ζ (top − z_s) (an integer n: n uniform layers).  The nodes of
    the bottom lie on the sphere (the faces are flat between them).  ``element`` as for
    :func:`box`; the faces are named boundaries as a box's (:data:`BOX_FACES`: ``bottom`` the
    spherical face, ``top``, ``left``/``right`` at x0/x1, ``front``/``back`` at y0/y1).

    Example
    -------
    >>> from stepcontact import Material
    >>> from stepcontact.model.mesh import spherical_block
    >>> tip = spherical_block("tip", 0.1, [0, 0.02, 0.05], [0, 0.02, 0.05], 0.05, 2,
    ...                       Material(210e9, 0.3))
    >>> bool(abs(tip.points.min(axis=0)).max() == 0.0), tip.n_nodes   # touches z = 0 at 0
    (True, 27)
    """
    item = f"body '{name}'"
    if element not in SOLID_KINDS:
        raise ModelError(f"{item}.element",
                         f"unknown element '{element}', use {', '.join(SOLID_KINDS)}")
    if not isinstance(radius, int | float | np.floating | np.integer) or not np.isfinite(radius) \
            or radius <= 0:
        raise ModelError(f"{item}.radius", f"must be positive and finite, got {radius!r}")
    R = float(radius)
    x, y = (_grid(name, field, v, *np.asarray(v, float)[[0, -1]])
            if np.ndim(v) == 1 and len(v) >= 2 else None for field, v in (("xs", xs), ("ys", ys)))
    if x is None or y is None:
        raise ModelError(item, "xs and ys must be lists of at least two grid lines (m)")
    if not isinstance(top, int | float | np.floating | np.integer) or not np.isfinite(top):
        raise ModelError(f"{item}.top", f"must be a finite height (m), got {top!r}")
    if np.ndim(layers) == 0:
        zeta = np.linspace(0.0, 1.0, _check_count(name, "layers", layers) + 1)
    else:
        zeta = _grid(name, "layers", layers, 0.0, 1.0)
    r2 = max(x[0] ** 2, x[-1] ** 2) + max(y[0] ** 2, y[-1] ** 2)
    if r2 >= R * R or R - np.sqrt(R * R - r2) >= top:
        raise ModelError(item, "the block's corners must lie inside the sphere's radius and "
                         "below the top (x² + y² < R², z_s < top)")
    from stepcontact.model.size import check_size

    per = 2 if element in ("tet10", "hex20", "hex27") else 1
    check_size(3 * (per * len(x) - per + 1) * (per * len(y) - per + 1)
               * (per * len(zeta) - per + 1), item, f"the mesh of body '{name}'")
    cls = MeshTet if element.startswith("tet") else MeshHex
    tol = 1e-9 * np.array([x[-1] - x[0], y[-1] - y[0], 1.0])  # per axis, m (ζ: 1)
    ends = {"left": (0, x[0]), "right": (0, x[-1]), "front": (1, y[0]), "back": (1, y[-1]),
            "bottom": (2, 0.0), "top": (2, 1.0)}

    def on(axis: int, value: float):
        return lambda q: np.abs(q[axis] - value) <= tol[axis]

    # the faces named on the parameter grid (x, y, ζ), then the nodes moved onto the sphere
    mesh = cls.init_tensor(x, y, zeta).with_boundaries({f: on(*e) for f, e in ends.items()})
    p = mesh.doflocs.copy()
    zs = R - np.sqrt(R * R - p[0] ** 2 - p[1] ** 2)
    p[2] = zs + p[2] * (top - zs)
    mesh = dataclasses.replace(mesh, doflocs=p)
    return Body.from_mesh(name, mesh, element, material)


__all__ = ["BOX_FACES", "EXTRUDED_ELEMENT", "QUAD_EDGES", "box", "cylinder", "extrude",
           "half_disc", "quad_region", "rectangle", "rotate", "spherical_block", "translate"]
