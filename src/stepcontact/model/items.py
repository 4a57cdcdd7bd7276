"""The model's items under one name: every dataclass, kind and range of the model, re-exported
from the modules that hold them (kept so that ``from stepcontact.model.items import …`` works).

* :mod:`stepcontact.model.bodies`: materials, bodies, frames; the plane, element and DOF kinds,
  the ranges of ν and E;
* :mod:`stepcontact.model.supports`: node sets, supports, ties, springs, :func:`select_nodes`;
* :mod:`stepcontact.model.loads`: loads and load patterns;
* :mod:`stepcontact.model.interfaces`: contact interfaces and contact layers (eq. (11));
* :mod:`stepcontact.model.structure`: the load program (segments, dynamic intervals) and
  :class:`Model`.

Everything is a plain, immutable dataclass.  Changing a model returns a new one
(:meth:`Model.add`, :func:`dataclasses.replace`).  Node sets are stored relative to a body
(body name + local node indices), so they stay valid when other bodies are added.

Units are SI throughout: metres, newtons, pascals, kilograms.  In 2D a force "per node" is a
force on the whole thickness of the model (N); pressures are in Pa and are multiplied by the
thickness when integrated.

Data flows one way: model -> :mod:`stepcontact.fem` -> :mod:`stepcontact.solver` ->
:mod:`stepcontact.results` -> post-processing.
"""

from stepcontact.model.bodies import (
    DOF_NAMES,
    E_RANGE,
    E_RATIO_MIN,
    ELEMENT_KINDS,
    NU_RANGE,
    PLANE_KINDS,
    Body,
    DofName,
    ElementKind,
    Frame,
    Material,
    PlaneKind,
    _either,
    modulus_problem,
)
from stepcontact.model.bond import Bond
from stepcontact.model.interfaces import CFE_KINDS, CfeKind, ContactLayer, Interface
from stepcontact.model.loads import (
    BodyForce,
    EdgeForce,
    EdgeLoad,
    Load,
    LoadPattern,
    NodalLoad,
    PrescribedDisplacement,
    PressureSpec,
    iter_loads,
)
from stepcontact.model.obstacle import ObstacleMotion, RigidObstacle, RigidPlane
from stepcontact.model.structure import DynamicInterval, Model, Segment, _check_stiffness_ratio
from stepcontact.model.supports import NodeSet, Spring, Support, Tie, _parse_dofs, select_nodes

__all__ = [
    "CFE_KINDS", "DOF_NAMES", "ELEMENT_KINDS", "E_RANGE", "E_RATIO_MIN", "NU_RANGE",
    "PLANE_KINDS", "Body", "BodyForce", "Bond", "CfeKind", "ContactLayer", "DofName",
    "DynamicInterval", "EdgeForce", "EdgeLoad", "ElementKind", "Frame", "Interface", "Load",
    "LoadPattern", "Material", "Model", "NodalLoad", "NodeSet", "ObstacleMotion", "PlaneKind",
    "PrescribedDisplacement", "PressureSpec", "RigidObstacle", "RigidPlane", "Segment",
    "Spring", "Support", "Tie", "_check_stiffness_ratio", "_either", "_parse_dofs", "iter_loads",
    "modulus_problem", "select_nodes",
]
