"""stepcontact: exact step-by-step analysis of structures with unilateral contact and friction."""

from stepcontact.demo import demo_model
from stepcontact.enums import ContactState, SlipTreatment, Status, Transition
from stepcontact.errors import (
    ContactHeldWarning,
    ContactMeshWarning,
    ModelError,
    SolverError,
    StepContactError,
)
from stepcontact.fem.assembly import System, assemble
from stepcontact.fem.mass import rayleigh_coefficients
from stepcontact.io.export import export_vtu, export_xdmf
from stepcontact.io.meshfile import MeshFile, read_msh
from stepcontact.io.modelfile import load_model, model_from_dict, validate_model_file
from stepcontact.model import (
    Body,
    BodyForce,
    ContactLayer,
    DiscreteModel,
    DynamicInterval,
    EdgeForce,
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
from stepcontact.model.bond import Bond
from stepcontact.model.combinations import (  # issue 29 §2: load combinations
    BaseUplift,
    Combination,
    DamSite,
    Earthquake,
    Ice,
    PostTensioning,
    Reservoir,
    SelfWeight,
    Silt,
    Tailwater,
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
from stepcontact.model.obstacle import ObstacleMotion, RigidObstacle, RigidPlane
from stepcontact.model.program import cycles
from stepcontact.model.stages import Stage
from stepcontact.model.structure import CRACK_WATER_CHOICES  # issue 29 §1: crack water
from stepcontact.model.timefunction import Constant, Harmonic, Pulse, Tabulated
from stepcontact.model.water import (  # Drains, the *_RULES/REFERENCES: issue 29 §2 (damhand)
    CRACK_RULES,
    DRAIN_REFERENCES,
    CrackWater,
    Drains,
    LinearProfile,
    Uplift,
    WaterLoad,
)
from stepcontact.results.dam_checks import (  # issue 29 §2
    DamCheck,
    JointStrength,
    check_combination,
    guideline_table,
    load_guidelines,
)
from stepcontact.results.newmark import NewmarkSliding, newmark_sliding  # issue 29: Newmark
from stepcontact.results.result import Event, Multipliers, StaticResult, load_result
from stepcontact.results.sliding import (  # issue 29: a run's slip beside Newmark's block
    JointSlip,
    SlidingComparison,
    joint_slip,
    rigid_block_yield,
    sliding_comparison,
)
from stepcontact.solver.condensation import Condensation, condense
from stepcontact.solver.dynamic import DynamicResult
from stepcontact.solver.program import ProgramResult, run, solve_dynamic
from stepcontact.solver.static import StepInfo, solve_static

_PLOTS = ("plot_interfaces", "plot_interface_map", "plot_load_path", "plot_deformed",
          "plot_load_displacement",
          "plot_event_timeline", "plot_safety", "plot_time_history", "plot_energy")


#: the studies' public names (:mod:`stepcontact.study`), imported on first use
_STUDY = {"run_sweep": "sweep", "grid": "sweep", "cases_from_list": "sweep",
          "collect": "sweep", "to_grid": "sweep", "BasinStudy": "basin", "run_basin": "basin",
          "Slab": "slab", "Impulse": "slab", "limit_thickness": "slab",
          "hydraulic_jump": "hydraulics",
          # issue 29 §3: the dam study (a parametric gravity-dam section, its static runs)
          "DamSection": "dam", "dam_model": "dam", "run_dam": "dam_study",
          # issue 29 §2–§3 (damwire): the study's site, combinations and yield acceleration
          "dam_site": "dam", "run_yield": "dam_study",
          # issue 29 §1, §3 (damquake): the earthquake record in the dam study
          "QuakeRecord": "dam_quake", "run_quake": "dam_quake",
          # issue 29 §3 (damfile): the dam study on a user's model file with a [dam] table
          "dam_file": "dam_file", "DamFile": "dam_file"}


def __getattr__(name: str):
    """Figures (matplotlib is slow to import) and the studies are imported on first use."""
    if name in _PLOTS:
        from stepcontact.post import plotting

        return getattr(plotting, name)
    if name in _STUDY:
        import importlib

        return getattr(importlib.import_module(f"stepcontact.study.{_STUDY[name]}"), name)
    raise AttributeError(f"module 'stepcontact' has no attribute '{name}'")


__version__ = "0.1.0"

__all__ = [
    *_STUDY,
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
    "ContactHeldWarning",
    "ContactMeshWarning",
    "ContactState",
    "DiscreteModel",
    "EdgeForce",
    "EdgeLoad",
    "Frame",
    "Interface",
    "LoadPattern",
    "Material",
    "Model",
    "ModelError",
    "NodalLoad",
    "NodeSet",
    "ObstacleMotion",
    "PrescribedDisplacement",
    "RigidObstacle",
    "RigidPlane",
    "Segment",
    "cycles",
    "SlipTreatment",
    "SolverError",
    "Spring",
    "Stage",
    "StepContactError",
    "Status",
    "Support",
    "Tie",
    "Transition",
    "rectangle",
    "box",
    "cylinder",
    "extrude",
    "quad_region",
    "half_disc",
    "polygon_region",
    "rotate",
    "translate",
    "Bond",
    "CrackWater",
    "LinearProfile",
    "Uplift",
    "WaterLoad",
    "assemble",
    "solve_static",
    "solve_dynamic",
    "run",
    "ProgramResult",
    "DynamicInterval",
    "DynamicResult",
    "rayleigh_coefficients",
    "Constant",
    "Harmonic",
    "Pulse",
    "Tabulated",
    "condense",
    "Condensation",
    "export_vtu",
    "export_xdmf",
    "Event",
    "Multipliers",
    "StaticResult",
    "StepInfo",
    "System",
    # issue 29 §2: load combinations and the guidelines' checks
    "BaseUplift",
    "Combination",
    "DamCheck",
    "DamSite",
    "Earthquake",
    "Ice",
    "JointStrength",
    "PostTensioning",
    "Reservoir",
    "SelfWeight",
    "Silt",
    "Tailwater",
    "check_combination",
    "guideline_table",
    "load_guidelines",
    # issue 29, sliding displacement (Newmark)
    "JointSlip",
    "NewmarkSliding",
    "SlidingComparison",
    "joint_slip",
    "newmark_sliding",
    "rigid_block_yield",
    "sliding_comparison",
    # issue 29 §2 (damhand)
    "CRACK_RULES",
    "DRAIN_REFERENCES",
    "Drains",
    # issue 29 §1: crack water during an earthquake
    "CRACK_WATER_CHOICES",
]

# issue 29 §1 (helper "seismic"): the reservoir's added mass (Westergaard 1933, Kuo 1982) and
# pseudo-static seismic coefficients (the yield acceleration as an exact event)
from stepcontact.model.seismic import (  # noqa: E402
    AddedMass,
    SeismicCoefficient,
    westergaard_force,
    westergaard_mass,
)

__all__ += ["AddedMass", "SeismicCoefficient", "westergaard_force", "westergaard_mass"]
# issue 29 §1, ground motions from files: earthquake records (PEER .AT2, two-column,
# one-column with dt), their baseline figures, and the components that act together
from stepcontact.model.records import (  # noqa: E402
    AccelerationRecord,
    GroundMotion,
    RecordFigures,
    RecordGridWarning,
)

__all__ += ["AccelerationRecord", "GroundMotion", "RecordFigures", "RecordGridWarning"]
