"""Rigid obstacles: a fixed (or rigidly moving) line or polyline that bodies may touch.

An obstacle is not meshed.  It enters a model as the S− side of an
:class:`~stepcontact.model.Interface` (``minus=obstacle``): every S+ node gets one CFE whose S−
end is the node's closest point on the polyline, with the normal of that segment pointing
towards the bodies (:func:`stepcontact.contact.geometry.interface_elements`).

* A **fixed** obstacle has no nodes and no DOFs: the S− ends of its CFEs are the ground
  (``minus_nodes`` all −1), and the CFE kinematics are u_n = −n·u⁺ − g⁰, u_τ = t·u⁺.
* A **moving** obstacle (one that a load pattern moves by an :class:`ObstacleMotion`) gets one
  node at every vertex, numbered after the nodes of all bodies, whose x, y DOFs are prescribed:
  u = Σ_P λ_P (d_P + θ_P ẑ × (x − c_P)), the linearised rigid motion of each pattern.  The
  S− end of a CFE is interpolated from the two vertices of its segment (weights 1 − ξ, ξ), which
  is exact for a rigid (affine) motion.  The prescribed-displacement machinery then does the
  rest: the obstacle drives the contact through the condensation's ``e`` terms, and its
  reaction on the structure is ``res.reaction(obstacle_name, "x" | "y")``.

Which side the bodies lie on: walking along ``points`` from the first to the last, the bodies
are on the **left** (``side="left"``, default: the normal of a segment from a to b is
(−d_y, d_x) with d = (b − a)/|b − a|), or on the right (``side="right"``).  A ground line from
(−5, 0) to (5, 0) carries bodies above it.

Example
-------
>>> import stepcontact as sc
>>> ground = sc.RigidObstacle("ground", [(-5.0, 0.0), (5.0, 0.0)])   # bodies above y = 0
>>> ground.normals
array([[-0.,  1.]])
>>> lift = sc.ObstacleMotion(ground, dy=1e-3)   # 1 mm up per unit λ of its pattern
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal, get_args

import numpy as np

from stepcontact.errors import ModelError

ObstacleSide = Literal["left", "right"]
OBSTACLE_SIDES: tuple[str, ...] = get_args(ObstacleSide)


@dataclass(frozen=True, eq=False)
class RigidObstacle:
    """A rigid line or polyline the bodies may touch (not meshed, no stiffness).

    Parameters
    ----------
    name : str
        Unique name (also the name of its reaction for a moving obstacle).
    points : sequence of (x, y)
        Vertices of the polyline, m (at least two; no zero-length segment).
    side : "left" or "right"
        The side of the polyline the bodies lie on, walking from the first point to the last
        (default "left": a line drawn from left to right carries bodies above it).
    """

    name: str
    points: np.ndarray
    side: str = "left"

    def __post_init__(self):
        item = f"obstacle '{self.name}'"
        if not isinstance(self.name, str) or not self.name:
            raise ModelError("obstacle", f"needs a non-empty name, got {self.name!r}")
        try:
            pts = np.asarray(self.points, dtype=float)
        except (TypeError, ValueError):
            raise ModelError(f"{item}.points", "must be a list of (x, y) points, m") from None
        if pts.ndim != 2 or pts.shape[1] != 2:
            raise ModelError(f"{item}.points", f"must be a list of (x, y) points, m; got an "
                                               f"array of shape {pts.shape}")
        if len(pts) < 2:
            raise ModelError(f"{item}.points", "needs at least two points (a line)")
        if not np.all(np.isfinite(pts)):
            raise ModelError(f"{item}.points", "contains NaN or inf")
        L = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        scale = max(1.0, float(np.ptp(pts, axis=0).max()))
        short = np.flatnonzero(L <= 1e-12 * scale)
        if short.size:
            k = int(short[0])
            raise ModelError(f"{item}.points", f"segment {k} (points {k} and {k + 1}) has zero "
                                               "length")
        if self.side not in OBSTACLE_SIDES:
            raise ModelError(f"{item}.side", f"must be 'left' or 'right' (the side the bodies "
                                             f"lie on, walking along the points), got "
                                             f"{self.side!r}")
        pts = pts.copy()
        pts.setflags(write=False)
        object.__setattr__(self, "points", pts)

    @property
    def n_nodes(self) -> int:
        """Number of vertices (the nodes of a moving obstacle)."""
        return len(self.points)

    @property
    def normals(self) -> np.ndarray:
        """Unit normal of every segment (k − 1, 2), pointing towards the bodies."""
        d = np.diff(self.points, axis=0)
        d = d / np.linalg.norm(d, axis=1)[:, None]
        n = np.column_stack([-d[:, 1], d[:, 0]])
        return n if self.side == "left" else -n

    def same_as(self, other: RigidObstacle) -> bool:
        """The same geometry and side (two objects of one obstacle)."""
        return (self.side == other.side and self.points.shape == other.points.shape
                and bool(np.array_equal(self.points, other.points)))


@dataclass(frozen=True, eq=False)
class RigidPlane(RigidObstacle):
    """A fixed rigid plane that 3D bodies may touch (the 3D twin of a one-segment
    :class:`RigidObstacle`; not meshed, no nodes, no DOFs).

    It enters a 3D model as the S− side of an :class:`~stepcontact.model.Interface`: every S+
    node gets one CFE whose S− end is the ground, with the plane's normal n and the gap
    g⁰ = (x⁺ − x₀) · n (:mod:`stepcontact.contact.interface3d`).  A plane cannot be moved
    (an :class:`ObstacleMotion` of it is refused).

    Parameters
    ----------
    name : str
        Unique name.
    point : (x, y, z)
        A point x₀ of the plane, m.
    normal : (n_x, n_y, n_z)
        The plane's normal, pointing towards the bodies (need not be unit; default +z: bodies
        above the plane).

    Example
    -------
    >>> import stepcontact as sc
    >>> ground = sc.RigidPlane("ground", point=(0.0, 0.0, 0.0))    # bodies above z = 0
    >>> ground.normal
    array([0., 0., 1.])
    """

    points: np.ndarray | None = None
    point: tuple = (0.0, 0.0, 0.0)
    normal: tuple = (0.0, 0.0, 1.0)

    def __post_init__(self):
        item = f"obstacle '{self.name}'"
        if not isinstance(self.name, str) or not self.name:
            raise ModelError("obstacle", f"needs a non-empty name, got {self.name!r}")
        vals = {}
        for key in ("point", "normal"):
            try:
                v = np.asarray(getattr(self, key), dtype=float).ravel()
            except (TypeError, ValueError):
                v = np.zeros(0)
            if v.shape != (3,) or not np.all(np.isfinite(v)):
                raise ModelError(f"{item}.{key}", f"must be three finite numbers (x, y, z), got "
                                                  f"{getattr(self, key)!r}")
            vals[key] = v
        size = float(np.linalg.norm(vals["normal"]))
        if size == 0.0:
            raise ModelError(f"{item}.normal", "is the zero vector")
        n = vals["normal"] / size
        n.setflags(write=False)
        x0 = vals["point"].copy()
        x0.setflags(write=False)
        object.__setattr__(self, "normal", n)
        object.__setattr__(self, "point", x0)
        object.__setattr__(self, "points", x0[None, :])

    @property
    def normals(self) -> np.ndarray:
        """The plane's unit normal (1, 3), pointing towards the bodies."""
        return self.normal[None, :]

    def same_as(self, other: RigidObstacle) -> bool:
        """The same plane (point and normal)."""
        return (isinstance(other, RigidPlane) and bool(np.array_equal(self.point, other.point))
                and bool(np.array_equal(self.normal, other.normal)))


@dataclass(frozen=True, eq=False)
class ObstacleMotion:
    """A rigid motion of an obstacle, per unit λ of its load pattern (a load, like a
    prescribed displacement: its vertices are at u = λ_P · (this motion)).

    u(x) = (dx, dy) + θ ẑ × (x − c) = (dx − θ (y − c_y), dy + θ (x − c_x)),   small θ

    Parameters
    ----------
    obstacle : RigidObstacle or str
        The obstacle (or its name); it must be the ``minus`` side of an interface of the model.
    dx, dy : float
        Translation, m.
    rotation : float
        Small rotation θ, rad, counter-clockwise (linearised, like every displacement).
    about : (x, y) or None
        Centre c of the rotation, m; default the obstacle's first point.

    An obstacle moved by any pattern is fixed at its place until (and where) no pattern moves
    it; several motions (of one or several patterns) add up.

    Example
    -------
    >>> import stepcontact as sc
    >>> wall = sc.RigidObstacle("wall", [(2.0, 0.0), (2.0, 3.0)])   # bodies at x < 2
    >>> sc.LoadPattern("push", [sc.ObstacleMotion(wall, dx=-1e-3)])  # doctest: +ELLIPSIS
    LoadPattern(name='push', ...)
    """

    obstacle: RigidObstacle | str
    dx: float = 0.0
    dy: float = 0.0
    rotation: float = 0.0
    about: Sequence[float] | None = None

    def __post_init__(self):
        item = f"motion of obstacle '{self.name}'"
        if not isinstance(self.obstacle, RigidObstacle | str):
            raise ModelError("obstacle motion", f"obstacle must be a RigidObstacle or its name, "
                                                f"got {type(self.obstacle).__name__}")
        for key in ("dx", "dy", "rotation"):
            v = getattr(self, key)
            if not isinstance(v, int | float | np.floating | np.integer) or not np.isfinite(v):
                raise ModelError(f"{item}.{key}", f"must be a finite number, got {v!r}")
            object.__setattr__(self, key, float(v))
        if self.about is not None:
            c = np.asarray(self.about, dtype=float).ravel()
            if c.shape != (2,) or not np.all(np.isfinite(c)):
                raise ModelError(f"{item}.about", f"must be a finite point (x, y), m; got "
                                                  f"{self.about!r}")
            object.__setattr__(self, "about", (float(c[0]), float(c[1])))

    @property
    def name(self) -> str:
        """The name of the obstacle moved."""
        return self.obstacle if isinstance(self.obstacle, str) else self.obstacle.name

    def displacements(self, obstacle: RigidObstacle) -> np.ndarray:
        """Displacements (k, 2) of the obstacle's vertices per unit λ, m."""
        pts = obstacle.points
        c = pts[0] if self.about is None else np.asarray(self.about, dtype=float)
        r = pts - c
        return np.column_stack([self.dx - self.rotation * r[:, 1],
                                self.dy + self.rotation * r[:, 0]])


__all__ = ["OBSTACLE_SIDES", "ObstacleMotion", "RigidObstacle", "RigidPlane"]
