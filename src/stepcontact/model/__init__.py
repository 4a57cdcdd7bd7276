"""The model: plain immutable data (bodies, materials, node sets, supports, springs, interfaces,
load patterns, the load program) and mesh generators.  Nothing here knows about solving."""

from stepcontact.model.items import (
    Body,
    BodyForce,
    ContactLayer,
    EdgeLoad,
    Frame,
    Interface,
    LoadPattern,
    Material,
    Model,
    NodalLoad,
    NodeSet,
    PrescribedDisplacement,
    Segment,
    Spring,
    Support,
    Tie,
    iter_loads,
    select_nodes,
)
from stepcontact.model.mesh import rectangle

__all__ = [
    "Body", "BodyForce", "ContactLayer", "EdgeLoad", "Frame", "Interface", "LoadPattern",
    "Material", "Model", "NodalLoad", "NodeSet", "PrescribedDisplacement", "Segment", "Spring",
    "Support", "Tie", "iter_loads", "rectangle", "select_nodes",
]
