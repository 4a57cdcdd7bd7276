"""stepcontact: exact step-by-step analysis of structures with unilateral contact and friction."""

from .assembly import System, assemble
from .enums import ContactState, SlipTreatment, Status, Transition
from .errors import ModelError, SolverError, StepContactError
from .export import export_vtu, export_xdmf
from .mesh import rectangle
from .model import (
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
)
from .results import Event, Multipliers, StaticResult
from .static import StepInfo, solve_static

__version__ = "0.1.0"

__all__ = [
    "Body",
    "BodyForce",
    "ContactLayer",
    "ContactState",
    "EdgeLoad",
    "Frame",
    "Interface",
    "LoadPattern",
    "Material",
    "Model",
    "ModelError",
    "NodalLoad",
    "NodeSet",
    "PrescribedDisplacement",
    "Segment",
    "SlipTreatment",
    "SolverError",
    "Spring",
    "StepContactError",
    "Status",
    "Support",
    "Tie",
    "Transition",
    "rectangle",
    "assemble",
    "solve_static",
    "export_vtu",
    "export_xdmf",
    "Event",
    "Multipliers",
    "StaticResult",
    "StepInfo",
    "System",
]
