"""Model files: a whole model (geometry, materials, contact, loads, program) in one TOML file.

The file is validated with pydantic (unknown keys, wrong types, NaN/inf and out-of-range
values are rejected) and then turned into an immutable :class:`~stepcontact.model.Model`.
Every problem is reported as one :class:`~stepcontact.errors.ModelError` whose ``item`` is the
path of the offending field in the file, e.g. ``bodies[1].material.E``,
``interfaces[0].plus`` or ``patterns.push.loads[0].normal``; when several fields are wrong,
all of them are listed in the message (and in the ``errors`` attribute of the exception).

Units are SI: m, N, Pa, kg/m³, m/s².  A short file::

    [model]
    name = "block on foundation"
    plane = "strain"            # or "stress"
    thickness = 1.0             # m

    [materials.concrete]
    E = 30e9                    # Pa
    nu = 0.2
    density = 2400              # kg/m³

    [[bodies]]
    name = "block"
    kind = "rectangle"
    corner0 = [0.0, 0.0]        # m
    corner1 = [2.0, 1.0]
    nx = 8
    ny = 4
    element = "quad4"           # tri3, tri6, quad4, quad8, quad9
    material = "concrete"       # or an inline table {E = ..., nu = ..., density = ...}

    [node_sets.block_bottom]
    body = "block"
    y = 0.0                     # nodes with y = 0 (also x = ..., where = {xmin, xmax, ymin, ymax})

    [[interfaces]]
    name = "joint"
    plus = "block_bottom"       # node-set names
    minus = "foundation_top"
    friction = 0.6

    [patterns.weight]
    loads = [{ type = "gravity", g = [0.0, -9.81], bodies = ["block"] }]

    [[program]]
    pattern = "weight"
    end = 1.0                   # λ goes from where the pattern stands (0) to 1

Bodies can also come from a gmsh mesh: ``[mesh] file = "dam.msh"`` (or a ``.geo`` file with
``order``, ``element``, ``size``), then ``[[bodies]] kind = "mesh"``, ``group = "<physical
surface>"``, ``material = ...``; physical curves and points are node sets, named directly
(``nodes = "base"``) or through ``[node_sets.NAME] group = "..."`` (see :mod:`.meshfile`).
:func:`validate_model_file` reports every problem of a file at once.

Load types: ``gravity`` (g, bodies), ``nodal`` (nodes, fx, fy in N, mz in N·m on every node
of the set), ``edge_force`` (nodes, fx, fy in N: a total force spread uniformly along the
set's edges), ``pressure`` (nodes, normal and/or tangential and/or traction = [tx, ty] in Pa,
each a pressure as below; tangential along t = (n_y, −n_x), the outward normal turned
clockwise, +x on a top face, like the CFE tangent), ``displacement``
(nodes, dof = "x" | "y" | "rz", value in m or rad).
Varying pressures are given by coordinates, ``{from = [x0, y0, p0], to = [x1, y1, p1]}``
(linear along the line through the two points); the older pair ``[start, end]`` follows the
node set's order (a reversed curve flips it) and is deprecated (a warning).  ``water``
(nodes, level in m, unit_weight in N/m³): hydrostatic pressure γ_w·max(level − y, 0);
``uplift`` (interface, head in m or pressure in Pa: a number, ``{from, to}`` or points
``[[x, y, v], …]``): the pressure pushes both sides of the joint apart; ``obstacle_motion``
(obstacle, dx, dy in m, rotation in rad, about = [x, y]): a rigid motion of an obstacle.

Rigid obstacles (not meshed): ``[[obstacles]] name = "ground"``, ``points = [[x0, y0], [x1,
y1], …]`` (m), ``side = "left"`` (the side the bodies lie on walking along the points; a line
drawn from left to right carries bodies above it) or ``"right"``; an interface against it gives
``obstacle = "ground"`` instead of ``minus``.

3D models (the dimension follows from the bodies, z up): ``box``, ``extrude``, ``cylinder`` and
``spherical_block`` bodies, or the physical volumes of a 3D gmsh mesh (its physical surfaces
are node sets); ``[[frames]]`` with 3D points are space frames (Iy, Iz, J, G or nu,
orientation; supports on rx, ry, rz, moments mx, my, mz); interfaces between faces take the
faceted cone's ``facets``, ``facet_angle`` and ``axis`` and a 3-vector ``normal``;
``[[obstacles]] kind = "plane"`` (point, normal) is rigid ground; an ``uplift`` acts through
the CFEs (``through``).  A field of the other dimension is an error at its path.

Construction in stages (method.md §6): ``[[stages]]`` entries, in order, each with ``name``,
the names of the ``bodies``, ``interfaces`` (made at once), ``contacts``, ``supports`` and
``remove_supports`` of that stage, ``grout = {interface = bond table}`` and its own
``[[stages.program]]`` segments (the syntax of ``[[program]]``); a model with stages has no
top-level ``[[program]]`` (:class:`StageSpec`, :class:`stepcontact.Stage`).
:func:`schema` gives the complete JSON schema.

The package is split along its seams, each importable on its own (they import one another, never the
package: no cycle): :mod:`.schema` (the pydantic models, :func:`schema`),
:mod:`.errors` (field paths, messages, :class:`Problem`), :mod:`.references` (the names a file
uses), :mod:`.build` (the :class:`~stepcontact.model.Model`), :mod:`.checks` (plausible values,
geometry) and :mod:`.load` (:func:`load_model`, :func:`model_from_dict`,
:func:`validate_model_file`, :func:`validation_report`).  Everything is importable from
``stepcontact.io.modelfile`` as before.
"""

from stepcontact.io.modelfile.errors import Problem
from stepcontact.io.modelfile.errors import _message as _message
from stepcontact.io.modelfile.errors import _path as _path
from stepcontact.io.modelfile.errors import _validate as _validate
from stepcontact.io.modelfile.load import (
    Validation,
    load_model,
    model_from_dict,
    validate_model_file,
    validation_report,
)
from stepcontact.io.modelfile.load import _read_toml as _read_toml
from stepcontact.io.modelfile.schema import (
    AddedMassSpec,
    Amplitude,
    BodySpec,
    BondSpec,
    BoxSpec,
    CrackWaterSpec,
    CylinderSpec,
    DampingSpec,
    DisplacementLoad,
    DynamicsSpec,
    EdgeForceLoad,
    FrameSpec,
    GravityLoad,
    HalfDiscSpec,
    InterfaceSpec,
    LayerSpec,
    LoadSpec,
    MaterialRef,
    MaterialSpec,
    MeshBodySpec,
    MeshSection,
    ModelFile,
    ModelSection,
    NodalLoadSpec,
    NodeSetSpec,
    ObstacleMotionLoad,
    ObstacleSpec,
    PatternSpec,
    PlaneObstacleSpec,
    Point,
    PolygonSpec,
    Pressure,
    PressureLoad,
    Profile,
    QuadRegionSpec,
    RectangleSpec,
    SegmentSpec,
    SeismicLoadSpec,
    SphericalBlockSpec,
    SpringSpec,
    StageSpec,
    SupportSpec,
    TieSpec,
    TimeFunctionSpec,
    UpliftLoadSpec,
    WaterLoadSpec,
    schema,
)

__all__ = [
    "ModelFile",
    "Problem",
    "Validation",
    "load_model",
    "model_from_dict",
    "schema",
    "validate_model_file",
    "validation_report",
    # the tables of the file (pydantic models), as before the split
    "AddedMassSpec",
    "Amplitude",
    "BodySpec",
    "BondSpec",
    "BoxSpec",
    "CrackWaterSpec",
    "CylinderSpec",
    "DampingSpec",
    "DisplacementLoad",
    "DynamicsSpec",
    "EdgeForceLoad",
    "FrameSpec",
    "GravityLoad",
    "HalfDiscSpec",
    "InterfaceSpec",
    "LayerSpec",
    "LoadSpec",
    "MaterialRef",
    "MaterialSpec",
    "MeshBodySpec",
    "MeshSection",
    "ModelSection",
    "NodalLoadSpec",
    "NodeSetSpec",
    "ObstacleMotionLoad",
    "ObstacleSpec",
    "PatternSpec",
    "PlaneObstacleSpec",
    "Point",
    "PolygonSpec",
    "Pressure",
    "PressureLoad",
    "Profile",
    "QuadRegionSpec",
    "RectangleSpec",
    "SegmentSpec",
    "SeismicLoadSpec",
    "SphericalBlockSpec",
    "SpringSpec",
    "StageSpec",
    "SupportSpec",
    "TieSpec",
    "TimeFunctionSpec",
    "UpliftLoadSpec",
    "WaterLoadSpec",
]
