"""The model: plain immutable data (bodies, materials, node sets, supports, springs, interfaces,
load patterns, the load program) and mesh generators.  Nothing here knows about solving."""

from stepcontact.model.bodies import Body, Frame, Material
from stepcontact.model.interfaces import ContactLayer, Interface
from stepcontact.model.loads import (
    BodyForce,
    EdgeForce,
    EdgeLoad,
    LoadPattern,
    NodalLoad,
    PrescribedDisplacement,
    iter_loads,
)
from stepcontact.model.mesh import (
    box,
    cylinder,
    extrude,
    half_disc,
    polygon_region,
    quad_region,
    rectangle,
    rotate,
    translate,
)
from stepcontact.model.structure import DynamicInterval, Model, Segment
from stepcontact.model.supports import NodeSet, Spring, Support, Tie, select_nodes

__all__ = [
    "Body", "BodyForce", "box", "cylinder", "extrude", "ContactLayer", "DynamicInterval",
    "EdgeForce", "EdgeLoad", "Frame",
    "Interface", "LoadPattern", "Material", "Model", "NodalLoad", "NodeSet",
    "PrescribedDisplacement", "Segment", "Spring", "Support", "Tie", "half_disc", "iter_loads",
    "polygon_region",
    "quad_region", "rectangle", "rotate", "select_nodes", "translate",
]

# water loads (hydrostatic pressure, uplift) and pressures given by coordinates
from stepcontact.model.water import CrackWater, LinearProfile, Uplift, WaterLoad  # noqa: E402

__all__ += ["CrackWater", "LinearProfile", "Uplift", "WaterLoad"]
from stepcontact.model.water import Drains  # noqa: E402  (issue 29 §2)

__all__ += ["Drains"]

# joints with initial strength (eq. (12))
from stepcontact.model.bond import Bond  # noqa: E402

__all__ += ["Bond"]

# rigid obstacles (fixed or moving lines and polylines, not meshed)
from stepcontact.model.obstacle import ObstacleMotion, RigidObstacle, RigidPlane  # noqa: E402

__all__ += ["ObstacleMotion", "RigidObstacle", "RigidPlane"]

# a structure given by its matrices (stiffness, contact rows, loads)
from stepcontact.model.discrete import DiscreteModel  # noqa: E402

__all__ += ["DiscreteModel"]

# load programs built from a few numbers (cyclic loading)
from stepcontact.model.program import cycles  # noqa: E402

__all__ += ["cycles"]

# construction in stages (issue 12)
from stepcontact.model.stages import Stage  # noqa: E402

__all__ += ["Stage"]

# earthquakes on dams (issue 29 §1): the reservoir's added mass, pseudo-static coefficients
from stepcontact.model.seismic import AddedMass, SeismicCoefficient  # noqa: E402

__all__ += ["AddedMass", "SeismicCoefficient"]
