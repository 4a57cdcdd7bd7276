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
PressureSpec = float | tuple[float, float] | Callable[[np.ndarray, np.ndarray], np.ndarray] | None


@dataclass(frozen=True, eq=False)
class NodalLoad:
    """The same force on **every** node of a node set: fx, fy in N, mz in N·m (frames only).

    A set of n nodes receives n × (fx, fy) in total.  For a *total* force spread along the
    edges of a set (consistent nodal forces of a uniform traction) use :class:`EdgeForce`.
    """

    nodes: NodeSet
    fx: float = 0.0
    fy: float = 0.0
    mz: float = 0.0


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

    Example
    -------
    >>> EdgeForce(m.select("block", x=0.0), fx=1e4)   # 10 kN in all: left face  # doctest: +SKIP
    """

    nodes: NodeSet
    fx: float = 0.0
    fy: float = 0.0


@dataclass(frozen=True, eq=False)
class BodyForce:
    """Self-weight: density × acceleration ``g`` (m/s²) on the named bodies (all when empty)."""

    g: tuple[float, float] = (0.0, -9.81)
    bodies: tuple[str, ...] = ()

    def __post_init__(self):
        g = np.asarray(self.g, dtype=float)
        if g.shape != (2,) or not np.all(np.isfinite(g)):
            raise ModelError("body force.g", f"must be a finite vector (gx, gy), m/s², got "
                             f"{self.g!r}")
        plausible.warn("gravity", float(np.hypot(*g)), "body force |g|", stacklevel=4)


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
