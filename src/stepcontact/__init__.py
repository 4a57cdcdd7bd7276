"""stepcontact: exact step-by-step analysis of structures with unilateral contact and friction."""

from .assembly import System, assemble
from .demo import demo_model
from .enums import ContactState, SlipTreatment, Status, Transition
from .errors import ModelError, SolverError, StepContactError
from .export import export_vtu, export_xdmf
from .io import load_result
from .mesh import rectangle
from .meshfile import MeshFile, read_msh
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
from .modelfile import load_model, model_from_dict, validate_model_file
from .results import Event, Multipliers, StaticResult
from .static import StepInfo, solve_static

_PLOTS = ("plot_interfaces", "plot_load_path", "plot_deformed", "plot_load_displacement",
          "plot_event_timeline")


def __getattr__(name: str):
    """Figures are imported on first use (matplotlib is slow to import)."""
    if name in _PLOTS:
        from . import plotting

        return getattr(plotting, name)
    raise AttributeError(f"module 'stepcontact' has no attribute '{name}'")


__version__ = "0.1.0"

__all__ = [
    "MeshFile",
    "demo_model",
    "load_model",
    "load_result",
    "model_from_dict",
    "read_msh",
    "validate_model_file",
    *_PLOTS,
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
