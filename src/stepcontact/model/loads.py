"""Loads (nodal, edge pressures and forces, body forces, prescribed displacements) and the load
patterns that group them under one load factor λ (SI units: N, Pa, m)."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model import plausible
from stepcontact.model.obstacle import ObstacleMotion
from stepcontact.model.supports import NodeSet

# --------------------------------------------------------------------------------------------
# loads
# --------------------------------------------------------------------------------------------
#: standard gravity, m/s² (the default of :class:`BodyForce`)
G_STANDARD = 9.81


class _Downward(tuple):
    """The default ``g`` of :class:`BodyForce`: standard gravity downwards.  It is the 2D
    vector (0, −9.81); on a 3D body it acts along −z (:meth:`BodyForce.vector`)."""


#: the default gravity of :class:`BodyForce`: (0, −9.81) m/s², along −z on a 3D body
DOWNWARD = _Downward((0.0, -G_STANDARD))

PressureSpec = float | tuple[float, float] | Callable[[np.ndarray, np.ndarray], np.ndarray] | None


@dataclass(frozen=True, eq=False)
class NodalLoad:
    """The same force on **every** node of a node set: fx, fy (and fz on a 3D body) in N, mz
    in N·m (frames only; mx, my too on a space frame: moments about the global axes).

    A set of n nodes receives n × (fx, fy[, fz]) in total.  For a *total* force spread along
    the edges of a set (consistent nodal forces of a uniform traction) use :class:`EdgeForce`.
    """

    nodes: NodeSet
    fx: float = 0.0
    fy: float = 0.0
    mz: float = 0.0
    fz: float = 0.0
    mx: float = 0.0
    my: float = 0.0


@dataclass(frozen=True, eq=False)
class EdgeLoad:
    """Tractions on the boundary edges of a body whose nodes all lie in ``nodes``, Pa.

    The traction on an edge with outward unit normal n is

        q = −p_n n + p_t t + (q_x, q_y),        t = (n_y, −n_x),

    integrated over the thickness into consistent nodal forces.

    * ``normal`` p_n: pressure, positive pushing *into* the body (against n).
    * ``tangential`` p_t: shear along the edge tangent t = (n_y, −n_x), the outward normal
      turned **clockwise** — the same rule as the CFE tangent (n from S− to S+, see
      :mod:`stepcontact.contact.geometry`).  On a top face (n = +y) t = +x, on a bottom face
      (n = −y) t = −x, on a right face (n = +x) t = −y, on a left face (n = −x) t = +y.
      For a joint, the tangent of the top edge of S− is the CFE tangent.
    * ``traction`` (q_x, q_y): a traction given in global x, y components, whatever the edge's
      orientation.

    ``normal``, ``tangential`` and each component of ``traction`` can be a constant, a pair
    ``(p_start, p_end)`` varying linearly along the node set (from its first to its last node,
    by arc length), or a function ``p(x, y)`` of position (vectorised, arrays in m, returns
    Pa).

    On a 3D body the load acts on the boundary **faces** whose nodes all lie in ``nodes``
    (e.g. ``model.select(body, boundary="top")``): ``normal`` is a pressure on them (a
    constant or a function p(x, y, z)); ``tangential``, ``traction`` and (start, end) pairs
    are refused there (a total force on faces is an :class:`EdgeForce` with fz).

    Example
    -------
    >>> top = m.select("block", y=2.0)                         # doctest: +SKIP
    >>> EdgeLoad(top, tangential=1e3)          # 1 kPa along +x on a top face  # doctest: +SKIP
    >>> EdgeLoad(top, traction=(1e3, 0.0))     # the same load                 # doctest: +SKIP
    """

    nodes: NodeSet
    normal: PressureSpec = None
    tangential: PressureSpec = None
    traction: tuple[PressureSpec, PressureSpec] | None = None

    def __post_init__(self):
        if self.traction is not None:
            if not isinstance(self.traction, tuple | list | np.ndarray) or len(self.traction) != 2:
                raise ModelError("edge load.traction",
                                 "give the two components (tx, ty), Pa (numbers, [start, end] "
                                 "pairs or functions of (x, y))")
            object.__setattr__(self, "traction", tuple(self.traction))


@dataclass(frozen=True, eq=False)
class EdgeForce:
    """A **total** force (fx, fy) in N spread along the boundary edges of a body whose nodes
    all lie in ``nodes``: the uniform traction (fx, fy) / (L · thickness) over the edges'
    total length L, turned into consistent nodal forces.  The nodal forces sum exactly to
    (fx, fy) whatever the mesh; compare :class:`NodalLoad`, which puts its value on every node.
    On a 3D body: the total force (fx, fy, fz) over the boundary faces in ``nodes``, the
    uniform traction F / A over their area A.

    Example
    -------
    >>> EdgeForce(m.select("block", x=0.0), fx=1e4)   # 10 kN in all: left face  # doctest: +SKIP
    """

    nodes: NodeSet
    fx: float = 0.0
    fy: float = 0.0
    fz: float = 0.0


@dataclass(frozen=True, eq=False)
class BodyForce:
    """Self-weight: density × acceleration ``g`` (m/s²) on the named bodies (all when empty).

    ``g`` is (gx, gy) for 2D bodies and (gx, gy, gz) for 3D ones.  The default,
    :data:`DOWNWARD`, is standard gravity :data:`G_STANDARD` downwards: (0, −9.81) as a 2D
    vector, along −z on a 3D body (:meth:`vector`).
    """

    g: tuple[float, ...] = DOWNWARD
    bodies: tuple[str, ...] = ()

    def __post_init__(self):
        g = np.asarray(self.g, dtype=float)
        if g.shape not in ((2,), (3,)) or not np.all(np.isfinite(g)):
            raise ModelError("body force.g", f"must be a finite vector (gx, gy) or (gx, gy, gz), "
                             f"m/s², got {self.g!r}")
        plausible.warn("gravity", float(np.linalg.norm(g)), "body force |g|", stacklevel=4)

    def vector(self, dim: int = 2) -> tuple[float, ...]:
        """The acceleration (m/s²) on a body of dimension ``dim``: ``g`` as given, or
        :data:`G_STANDARD` along −y (2D) or −z (3D) by default; a ``g`` of the other
        dimension is a ModelError."""
        if isinstance(self.g, _Downward):
            return (0.0, -G_STANDARD) if dim == 2 else (0.0, 0.0, -G_STANDARD)
        if len(self.g) != dim:
            raise ModelError("body force.g", f"has {len(self.g)} components {tuple(self.g)!r}, "
                             f"but acts on a {dim}D body: give "
                             f"{'(gx, gy)' if dim == 2 else '(gx, gy, gz)'}, m/s²")
        return tuple(float(v) for v in self.g)


@dataclass(frozen=True, eq=False)
class PrescribedDisplacement:
    """Prescribed displacement ``value`` (m, or rad for rz) of ``dof`` of each node of a set.

    Scaled by the load factor λ_P of its pattern, like any load: the DOFs are at
    u = λ_P · ``value``.  They are fixed **from the start of the program**, not only from the
    first segment of their pattern: before it (λ_P = 0) they are held at zero and act as a
    support (their reaction is ``res.reaction(pattern, dof)``).  To leave a DOF free until
    later, give it no prescribed displacement and load it by forces instead.
    """

    nodes: NodeSet
    dof: str
    value: float


Load = NodalLoad | EdgeLoad | EdgeForce | BodyForce | PrescribedDisplacement | ObstacleMotion


@dataclass(frozen=True, eq=False)
class LoadPattern:
    """A named set of loads applied together with one load factor λ."""

    name: str
    loads: tuple = ()

    def __post_init__(self):
        object.__setattr__(self, "loads", tuple(self.loads))


def iter_loads(pattern: LoadPattern) -> Iterable:
    return iter(pattern.loads)
