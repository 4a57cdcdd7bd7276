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

Construction in stages (method.md §6): ``[[stages]]`` entries, in order, each with ``name``,
the names of the ``bodies``, ``interfaces`` (made at once), ``contacts``, ``supports`` and
``remove_supports`` of that stage, ``grout = {interface = bond table}`` and its own
``[[stages.program]]`` segments (the syntax of ``[[program]]``); a model with stages has no
top-level ``[[program]]`` (:class:`StageSpec`, :class:`stepcontact.Stage`).
:func:`schema` gives the complete JSON schema.
"""

from __future__ import annotations

import math
import os
import re
import tomllib
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, Literal, Union

import numpy as np
from pydantic import (
    BaseModel,
    ConfigDict,
    Discriminator,
    Field,
    NonNegativeInt,
    PlainValidator,
    Tag,
    ValidationError,
    WithJsonSchema,
    field_validator,
    model_validator,
)

from stepcontact.errors import ModelError, StepContactError
from stepcontact.io.meshfile import GROUP_KINDS, MeshFile, read_mesh
from stepcontact.model import meshcheck, plausible
from stepcontact.model.bond import FRICTION_ANGLE_RANGE, Bond
from stepcontact.model.items import (
    NU_RANGE,
    Body,
    BodyForce,
    CfeKind,
    ContactLayer,
    DofName,
    EdgeForce,
    EdgeLoad,
    ElementKind,
    Frame,
    Interface,
    LoadPattern,
    Material,
    Model,
    NodalLoad,
    NodeSet,
    PlaneKind,
    PrescribedDisplacement,
    Segment,
    Spring,
    Support,
    Tie,
    _parse_dofs,
    modulus_problem,
    select_nodes,
)
from stepcontact.model.mesh import half_disc, polygon_region, quad_region, rectangle
from stepcontact.model.obstacle import ObstacleMotion, ObstacleSide, RigidObstacle
from stepcontact.model.program import cycle_amplitudes, cycles
from stepcontact.model.size import check_size
from stepcontact.model.stages import Stage
from stepcontact.model.timefunction import (
    HHT_ALPHA_RANGE,
    RESTITUTION_RANGE,
    MassKind,
    PulseShape,
)
from stepcontact.model.water import CrackWater, LinearProfile, Uplift, WaterLoad

# tags of the discriminated unions; they appear in pydantic's error locations and are removed
# from the field paths shown to the user
_TAGS = {
    "kind=rectangle",
    "kind=mesh",
    "kind=quad",
    "kind=half_disc",
    "kind=polygon",
    "type=gravity",
    "type=nodal",
    "type=pressure",
    "type=edge_force",
    "type=water",
    "type=uplift",
    "type=crack_water",
    "type=displacement",
    "type=obstacle_motion",
    "material=name",
    "material=table",
}
_MAX_LISTED = 8


class _Spec(BaseModel):
    """Base of every table of the file: unknown keys and NaN/inf are errors."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, frozen=True)


Point = tuple[float, float]


# --------------------------------------------------------------------------------------------
# model, materials, bodies, frames
# --------------------------------------------------------------------------------------------
class ModelSection(_Spec):
    """``[model]``: name, plane ("strain" or "stress") and out-of-plane thickness (m)."""

    name: str | None = None
    plane: PlaneKind = "strain"
    thickness: float = Field(1.0, gt=0, description="out-of-plane thickness, m")


class MaterialSpec(_Spec):
    """``[materials.NAME]``: isotropic linear-elastic material."""

    E: float = Field(gt=0, description="Young's modulus, Pa")
    nu: float = Field(gt=NU_RANGE[0], lt=NU_RANGE[1], description="Poisson's ratio")
    density: float = Field(0.0, ge=0, description="mass density, kg/m³")

    @field_validator("E")
    @classmethod
    def _plausible_E(cls, v: float) -> float:
        if v > 0 and (text := modulus_problem(v)) is not None:
            raise ValueError(text)
        return v

    def build(self) -> Material:
        return Material(self.E, self.nu, self.density)


def _tagged_union(tagger, error_type: str, message: str, **variants: type) -> Any:
    """A pydantic union discriminated by ``tagger`` (value -> tag or None); ``variants`` maps
    each tag to its model.  An untaggable value fails with ``message`` (one line, no list of
    every variant's errors)."""
    members = tuple(Annotated[t, Tag(tag)] for tag, t in variants.items())
    return Annotated[Union[members],  # noqa: UP007 - a union built at run time
                     Discriminator(tagger, custom_error_type=error_type,
                                   custom_error_message=message)]


def _material_tag(v: Any) -> str | None:
    if isinstance(v, str):
        return "material=name"
    if isinstance(v, dict | MaterialSpec):
        return "material=table"
    return None


MaterialRef = _tagged_union(
    _material_tag, "material_ref", "must be a material name or an inline table {E, nu, density}",
    **{"material=name": str, "material=table": MaterialSpec},
)


class RectangleSpec(_Spec):
    """``[[bodies]]`` with ``kind = "rectangle"``: [x0, x1] × [y0, y1] meshed nx × ny."""

    name: str
    kind: Literal["rectangle"] = "rectangle"
    corner0: Point = Field(description="lower-left corner (x0, y0), m")
    corner1: Point = Field(description="upper-right corner (x1, y1), m")
    nx: int = Field(ge=1, description="cells along x")
    ny: int = Field(ge=1, description="cells along y")
    element: ElementKind = "quad4"
    grading: tuple[float, float] = Field(
        (1.0, 1.0), description="geometric growth of the cell sizes along x and y (> 0)"
    )
    material: MaterialRef

    @field_validator("grading")
    @classmethod
    def _positive_grading(cls, v: tuple[float, float]) -> tuple[float, float]:
        if min(v) <= 0:
            raise ValueError("grading factors must be > 0")
        return v

    @model_validator(mode="after")
    def _non_empty(self) -> RectangleSpec:
        if not (self.corner1[0] > self.corner0[0] and self.corner1[1] > self.corner0[1]):
            raise ValueError("corner1 must lie above and to the right of corner0")
        return self


class QuadRegionSpec(_Spec):
    """``[[bodies]]`` with ``kind = "quad"``: a convex four-sided region (corners
    counter-clockwise) meshed nx × ny by a bilinear map (:func:`stepcontact.quad_region`)."""

    name: str = Field(description="unique body name")
    kind: Literal["quad"]
    corners: tuple[Point, Point, Point, Point] = Field(
        description="the four corners, counter-clockwise, m; nx cells along corner 0→1")
    nx: int = Field(ge=1, description="cells along the edges 0→1 and 3→2")
    ny: int = Field(ge=1, description="cells along the edges 0→3 and 1→2")
    element: ElementKind = Field(
        "quad4", description="element kind (linear or quadratic triangles and quads)")
    grading: tuple[float, float] | dict[str, float] = Field(
        (1.0, 1.0), description="(gx, gy): last / first cell size along each direction; or "
        "{bottom|right|top|left = ratio}: cells shrinking towards those edges")
    material: MaterialRef = Field(description="a material name from `[materials.NAME]`, or "
                                  "an inline table `{E, nu, density}`")


class HalfDiscSpec(_Spec):
    """``[[bodies]]`` with ``kind = "half_disc"``: the lower half of a disc (flat face on top),
    refined towards its lowest point, for cylinder contact (:func:`stepcontact.half_disc`)."""

    name: str = Field(description="unique body name")
    kind: Literal["half_disc"]
    center: Point = Field(description="centre of the disc (the middle of the flat face), m")
    radius: float = Field(gt=0, description="radius, m")
    n_radial: int = Field(ge=1, description="rings of cells between the core and the arc")
    n_around: int = Field(ge=4, description="cells along the arc (even)")
    element: ElementKind = Field(
        "quad4", description="element kind (linear or quadratic triangles and quads)")
    refine: bool = Field(True, description="cells shrinking towards the lowest point")
    ratio: float = Field(8.0, ge=1, description="largest / smallest cell when refined")
    material: MaterialRef = Field(description="a material name from `[materials.NAME]`, or "
                                  "an inline table `{E, nu, density}`")


class PolygonSpec(_Spec):
    """``[[bodies]]`` with ``kind = "polygon"``: a simple polygon, every vertex a node
    (:func:`stepcontact.polygon_region`).  A triangle is meshed without gmsh: ``n`` cells
    along every edge (or ``size``), n² triangles similar to it, or three four-sided regions of
    quads; a polygon of more vertices is meshed by gmsh (the optional dependency)."""

    name: str = Field(description="unique body name")
    kind: Literal["polygon"]
    vertices: list[Point] = Field(
        min_length=3, description="the vertices in order (either way round), m; a triangular "
        "dam section: [[0, 0], [B, 0], [0, H]]")
    n: int | None = Field(None, ge=1, description="cells along every edge of a triangle "
                          "(polygons: the perimeter / (n × vertices) is the cell size)")
    size: float | None = Field(None, gt=0, description="cell size, m (instead of n)")
    element: ElementKind = Field(
        "tri3", description="element kind (linear or quadratic triangles and quads)")
    material: MaterialRef = Field(description="a material name from `[materials.NAME]`, or "
                                  "an inline table `{E, nu, density}`")

    @model_validator(mode="after")
    def _n_or_size(self) -> PolygonSpec:
        if (self.n is None) == (self.size is None):
            raise ValueError("give either n (cells along an edge) or size (m), not both")
        return self


class MeshBodySpec(_Spec):
    """``[[bodies]]`` with ``kind = "mesh"``: the cells of one physical surface of ``[mesh]``.

    ``group`` is the physical surface (default: ``name``); ``name`` defaults to ``group``.
    ``element`` defaults to the kind of the cells (tri3, tri6, quad4, quad8, quad9); a linear
    mesh may use the quadratic element of its shape.  ``material`` is required (a missing one
    is reported with the other problems of the file).
    """

    mesh: str | None = Field(None, description="not here: the mesh file goes in [mesh] file")
    kind: Literal["mesh"] = "mesh"
    name: str | None = None
    group: str | None = Field(None, description="physical surface (default: name)")
    element: ElementKind | None = None
    material: MaterialRef | None = None

    @field_validator("mesh")
    @classmethod
    def _mesh_in_section(cls, v: str | None) -> str | None:
        if v is not None:
            raise ValueError(
                f"give the mesh file once, in the [mesh] section (file = \"{v}\"), and the "
                "physical surface of this body here (kind = \"mesh\", group = \"...\")"
            )
        return v

    @model_validator(mode="after")
    def _named(self) -> MeshBodySpec:
        if self.name is None and self.group is None:
            raise ValueError("give the physical surface (group = ...) and/or the body name")
        return self

    @property
    def body_name(self) -> str:
        return self.name if self.name is not None else str(self.group)

    @property
    def surface(self) -> str:
        return self.group if self.group is not None else str(self.name)


def _body_tag(v: Any) -> str | None:
    if isinstance(v, dict):
        kind = v.get("kind")
        if kind is None or "mesh" in v:
            kind = "mesh" if ("group" in v or "mesh" in v) else "rectangle"
        return (f"kind={kind}" if kind in ("rectangle", "mesh", "quad", "half_disc", "polygon")
                else None)
    if isinstance(v, RectangleSpec | MeshBodySpec | QuadRegionSpec | HalfDiscSpec
                  | PolygonSpec):
        return f"kind={v.kind}"
    return None


BodySpec = _tagged_union(
    _body_tag, "body_kind",
    "kind must be 'rectangle', 'quad', 'half_disc', 'polygon' or 'mesh'",
    **{"kind=rectangle": RectangleSpec, "kind=quad": QuadRegionSpec,
       "kind=half_disc": HalfDiscSpec, "kind=polygon": PolygonSpec, "kind=mesh": MeshBodySpec},
)


def _body_name(b: RectangleSpec | MeshBodySpec | QuadRegionSpec | HalfDiscSpec
               | PolygonSpec) -> str:
    return b.body_name if isinstance(b, MeshBodySpec) else b.name


class MeshSection(_Spec):
    """``[mesh]``: the gmsh mesh whose physical groups mesh bodies and node sets use.

    ``file`` is a ``.msh`` file, or a ``.geo`` file (or gmsh Python script) meshed with gmsh
    when it is installed, with ``order``, ``element`` and ``size``.  Relative to the model file.
    """

    file: str = Field(description=".msh file, or .geo / gmsh .py script; relative to this file")
    order: Literal[1, 2] | None = Field(None, description="element order (.geo only)")
    element: Literal["tri", "quad"] | None = Field(None, description="cells (.geo only)")
    size: float | None = Field(None, gt=0, description="largest element size, m (.geo only)")
    ignore: list[str] = Field([], description="physical surfaces that are not bodies")

    @model_validator(mode="after")
    def _geo_options(self) -> MeshSection:
        given = [k for k in ("order", "element", "size") if getattr(self, k) is not None]
        if given and not self.file.endswith((".geo", ".py")):
            raise ValueError(
                f"{', '.join(given)} only apply when meshing a .geo file or gmsh script"
            )
        return self


class FrameSpec(_Spec):
    """``[[frames]]``: a straight Euler–Bernoulli frame from ``start`` to ``end``."""

    name: str
    kind: Literal["line"] = "line"
    start: Point = Field(description="first node, m")
    end: Point = Field(description="last node, m")
    n: int = Field(ge=1, description="number of elements")
    E: float = Field(gt=0, description="Young's modulus, Pa")
    A: float = Field(gt=0, description="cross-section area, m²")
    I: float = Field(gt=0, description="second moment of area, m⁴")
    density: float = Field(0.0, ge=0, description="kg/m³")


# --------------------------------------------------------------------------------------------
# node sets, supports, ties, springs, interfaces
# --------------------------------------------------------------------------------------------
class BoxSpec(_Spec):
    """``where = {xmin, xmax, ymin, ymax}``: nodes inside the box (bounds inclusive, m)."""

    xmin: float | None = None
    xmax: float | None = None
    ymin: float | None = None
    ymax: float | None = None


class NodeSetSpec(_Spec):
    """``[node_sets.NAME]``: nodes of one body (or frame) by coordinate, box or index, or the
    nodes of a physical curve or point of ``[mesh]`` (``group``; ``body`` is then needed only
    for a curve shared by two conforming bodies)."""

    body: str | None = None
    group: str | None = Field(None, description="physical curve or point of [mesh]")
    x: float | None = Field(None, description="nodes with this x, m")
    y: float | None = Field(None, description="nodes with this y, m")
    where: BoxSpec | None = None
    index: list[NonNegativeInt] | None = Field(None, description="local node indices")
    boundary: bool = Field(True, description="only nodes on the body's boundary")

    @model_validator(mode="after")
    def _index_alone(self) -> NodeSetSpec:
        by_coord = self.x is not None or self.y is not None or self.where is not None
        if self.group is not None and (by_coord or self.index is not None):
            raise ValueError("give either group or x / y / where / index, not both")
        if self.group is None and self.body is None:
            raise ValueError("give body (with x / y / where / index) or group")
        if self.index is not None and (
            self.x is not None or self.y is not None or self.where is not None
        ):
            raise ValueError("give either index or x / y / where, not both")
        return self


def _check_dofs(v: str) -> str:
    try:
        _parse_dofs(v, "dofs")
    except ModelError as e:
        raise ValueError(e.problem) from None
    return v


class SupportSpec(_Spec):
    """``[[supports]]``: fixed degrees of freedom ("xy", "x", "y", "rz", "xyrz") of a node
    set."""

    name: str | None = None
    nodes: str
    dofs: str = "xy"

    @field_validator("dofs")
    @classmethod
    def _known_dofs(cls, v: str) -> str:
        return _check_dofs(v)


class TieSpec(_Spec):
    """``[[ties]]``: translations of node set ``a`` tied pairwise to those of ``b``."""

    name: str | None = None
    a: str
    b: str


class SpringSpec(_Spec):
    """``[[springs]]``: springs between node sets ``a`` and ``b`` (``b`` absent: ground), with
    stiffnesses ``kx``, ``ky`` along the axes and/or ``k`` along ``direction``."""

    name: str | None = None
    a: str
    b: str | None = None
    kx: float = Field(0.0, ge=0, description="stiffness along x, N/m")
    ky: float = Field(0.0, ge=0, description="stiffness along y, N/m")
    k: float = Field(0.0, ge=0, description="stiffness along `direction`, N/m")
    direction: Point | None = Field(
        None, description="axis (dx, dy) of `k` (any non-zero vector; normalised)"
    )
    damping: float = Field(
        0.0, ge=0,
        description="dashpot coefficient, N·s/m, in parallel with the spring (dynamics; "
                    "statics ignores it)",
    )


class LayerSpec(_Spec):
    """Compliant contact layer (eq. (11)): ``{kn, kt}`` in Pa/m or ``{thickness, E, nu}``;
    ``damping`` makes it a Kelvin–Voigt layer in dynamic runs."""

    kn: float | None = Field(None, gt=0, description="normal stiffness per area, Pa/m")
    kt: float | None = Field(None, gt=0, description="tangential stiffness per area, Pa/m")
    thickness: float | None = Field(None, gt=0, description="layer thickness ζ_n⁰, m")
    E: float | None = Field(None, gt=0, description="layer modulus E_c, Pa")
    nu: float | None = Field(None, gt=NU_RANGE[0], lt=NU_RANGE[1],
                             description="layer Poisson ratio μ_c")
    damping: float = Field(0.0, ge=0, description="normal damping per area, Pa·s/m "
                           "(dynamic runs: a Kelvin–Voigt layer)")

    @model_validator(mode="after")
    def _one_form(self) -> LayerSpec:
        text = ContactLayer.form_problem(self.kn, self.kt, self.thickness, self.E, self.nu)
        if text is not None:
            raise ValueError(text)
        return self

    def build(self) -> ContactLayer:
        if self.kn is not None:
            return ContactLayer(kn=self.kn, kt=self.kt, damping=self.damping)
        return ContactLayer(thickness=self.thickness, E=self.E, nu=self.nu or 0.0,
                            damping=self.damping)


class ObstacleSpec(_Spec):
    """``[[obstacles]]``: a rigid line or polyline (not meshed) that bodies may touch; an
    interface uses it with ``obstacle = "NAME"`` instead of ``minus``."""

    name: str
    points: list[Point] = Field(min_length=2, description="vertices [[x0, y0], [x1, y1], …], m")
    side: ObstacleSide = Field(
        "left", description="side the bodies lie on, walking from the first point to the last "
        "(left: a line drawn from left to right carries bodies above it)")


class InterfaceSpec(_Spec):
    """``[[interfaces]]``: CFEs from every node of ``plus`` (S+) to ``minus`` (S−), or to a
    rigid ``obstacle`` of ``[[obstacles]]``."""

    name: str
    plus: str
    minus: str | None = Field(None, description="node set of S- (or give obstacle)")
    obstacle: str | None = Field(None, description="a rigid obstacle of [[obstacles]] as S- "
                                 "(instead of minus)")
    friction: float = Field(0.0, ge=0, description="Coulomb friction coefficient")
    gap: float | None = Field(None, ge=0, description="initial gap, m (default: geometric)")
    normal: Point | None = Field(None, description="unit normal from S− to S+")
    layer: LayerSpec | None = None
    pairs: bool = Field(False, description="join plus[i] to minus[i] node to node, in the "
                        "node sets' order, instead of projecting S+ on S−")
    area: float | None = Field(None, gt=0, description="contact area of every CFE, m² "
                               "(default: tributary length × thickness)")
    cfe: CfeKind = Field(
        "auto", description="how CFEs join S+ to S−: node-to-node where the meshes match and "
        "mortar (segment-to-segment) otherwise (auto); node-to-segment is the article's CFE")
    bond: BondSpec | None = Field(None, description="initial strength of the joint (eq. (12)): "
                                  "its CFEs start bonded and break into frictional contact")

    @field_validator("normal")
    @classmethod
    def _nonzero(cls, v: Point | None) -> Point | None:
        if (text := Interface.normal_problem(v)) is not None:
            raise ValueError(f"normal {text}")
        return v

    @model_validator(mode="after")
    def _one_minus(self) -> InterfaceSpec:
        if (self.minus is None) == (self.obstacle is None):
            raise ValueError("give either minus (a node set) or obstacle (a rigid obstacle)")
        return self


# --------------------------------------------------------------------------------------------
# loads, patterns, program
# --------------------------------------------------------------------------------------------
def _profile(v: Any, what: str) -> LinearProfile:
    """{from = [x0, y0, v0], to = [x1, y1, v1]} or [[x, y, v], …] as a LinearProfile."""
    if isinstance(v, dict):
        if set(v) != {"from", "to"}:
            raise ValueError(f"a {what} by coordinates is a table {{from = [x0, y0, v0], "
                             "to = [x1, y1, v1]}")
        v = [v["from"], v["to"]]
    pts = []
    for q in v:
        if not isinstance(q, list | tuple) or len(q) != 3 or any(
                isinstance(c, bool) or not isinstance(c, int | float) or not math.isfinite(c)
                for c in q):
            raise ValueError(f"each point of a {what} by coordinates is [x, y, value] "
                             "(finite numbers)")
        pts.append(tuple(float(c) for c in q))
    try:
        return LinearProfile(tuple(pts))
    except ModelError as e:
        raise ValueError(e.problem) from None


def _pressure_value(v: Any) -> float | tuple[float, float] | LinearProfile:
    """A pressure (Pa): a finite number; {from = [x0, y0, p0], to = [x1, y1, p1]} (linear by
    coordinates); or a pair [start, end] of finite numbers (along the node set's order,
    deprecated)."""

    def num(x: Any) -> float:
        if isinstance(x, bool) or not isinstance(x, int | float):
            raise ValueError("must be a number (Pa) or a pair [start, end] of numbers (Pa), "
                             "or by coordinates {from = [x0, y0, p0], to = [x1, y1, p1]}")
        if not math.isfinite(x):
            raise ValueError("must be a finite number (NaN and inf are not allowed)")
        return float(x)

    if isinstance(v, dict):
        return _profile(v, "pressure")
    if isinstance(v, list | tuple):
        if len(v) != 2:
            raise ValueError("a varying pressure is a pair [start, end] (Pa)")
        return (num(v[0]), num(v[1]))
    return num(v)


_POINT_SCHEMA = {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3}
_FROM_TO_SCHEMA = {"type": "object", "properties": {"from": _POINT_SCHEMA, "to": _POINT_SCHEMA},
                   "required": ["from", "to"], "additionalProperties": False}

Pressure = Annotated[
    float | tuple[float, float] | LinearProfile,
    PlainValidator(_pressure_value),
    WithJsonSchema(
        {
            "anyOf": [
                {"type": "number"},
                _FROM_TO_SCHEMA,
                {"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 2},
            ],
            "description": "Pa: a constant; {from = [x0, y0, p0], to = [x1, y1, p1]} linear in "
            "the coordinate along the line through the two points; or (deprecated) [start, end] "
            "along the node set's order",
        }
    ),
]


def _profile_value(v: Any) -> float | LinearProfile:
    """A head (m) or pressure (Pa) of an uplift: a number, {from, to} or [[x, y, v], …]."""
    if isinstance(v, dict):
        return _profile(v, "profile")
    if isinstance(v, list | tuple):
        if len(v) < 2:
            raise ValueError("give at least two points [x, y, value]")
        return _profile(v, "profile")
    if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
        raise ValueError("must be a finite number, {from = [x0, y0, v0], to = [x1, y1, v1]} or "
                         "points [[x, y, value], …]")
    return float(v)


Profile = Annotated[
    float | LinearProfile,
    PlainValidator(_profile_value),
    WithJsonSchema(
        {
            "anyOf": [
                {"type": "number"},
                _FROM_TO_SCHEMA,
                {"type": "array", "items": _POINT_SCHEMA, "minItems": 2},
            ],
            "description": "a constant; {from = [x0, y0, v0], to = [x1, y1, v1]}; or points "
            "[[x, y, v], …] (piecewise linear along the line from the first to the last point)",
        }
    ),
]


class BondSpec(_Spec):
    """Initial strength of a joint (eq. (12)), per unit area: the article's form
    ``{tensile, shear, alpha}`` (Pa, Pa, –; ``tension_alpha`` optional: the slope of the
    tension facets, default alpha) or Mohr–Coulomb ``{cohesion, tensile_strength,
    friction_angle}`` (Pa, Pa, degrees: a tension cut-off).  Strengths are a number or vary
    along the joint by coordinates.  ``friction``: f after the bond breaks (default: the
    interface's, or tan φ for Mohr–Coulomb); ``residual_cohesion``: C_r after the break, Pa
    (a number or varying like the strengths; default 0), lost where the joint opens."""

    tensile: Profile | None = Field(None, description="tensile strength σ_R, Pa")
    shear: Profile | None = Field(None, description="shear strength without normal force "
                                  "τ_R, Pa")
    alpha: float | None = Field(None, ge=0, description="α_R: growth of the shear strength "
                                "with compression (tan φ)")
    tension_alpha: float | None = Field(None, gt=0, description="α_t of the tension facets "
                                        "N + |Q|/α_t ≤ N_R (default α_R; inf: a cut-off)")
    cohesion: Profile | None = Field(None, description="Mohr–Coulomb cohesion c, Pa")
    tensile_strength: Profile | None = Field(None, description="Mohr–Coulomb tensile "
                                             "strength σ_t, Pa (a tension cut-off)")
    friction_angle: float | None = Field(None, ge=FRICTION_ANGLE_RANGE[0],
                                         lt=FRICTION_ANGLE_RANGE[1], description="Mohr–Coulomb "
                                         "friction angle φ, degrees")
    friction: float | None = Field(None, ge=0, description="friction coefficient after the "
                                   "bond breaks")
    residual_cohesion: Profile | None = Field(None, description="cohesion C_r after the bond "
                                              "breaks (until the joint opens), Pa")

    @field_validator("residual_cohesion")
    @classmethod
    def _not_negative(cls, v):
        if isinstance(v, float) and (text := Bond.residual_problem(v)) is not None:
            raise ValueError(text)
        return v

    @model_validator(mode="after")
    def _one_form(self) -> BondSpec:
        article = [self.tensile, self.shear, self.alpha]
        mc = [self.cohesion, self.tensile_strength, self.friction_angle]
        if any(v is not None for v in article) and any(v is not None for v in mc):
            raise ValueError("give either {tensile, shear, alpha} (eq. (12)) or {cohesion, "
                             "tensile_strength, friction_angle} (Mohr–Coulomb), not both")
        if not (all(v is not None for v in article) or all(v is not None for v in mc)):
            raise ValueError("give {tensile, shear, alpha} (eq. (12)) or {cohesion, "
                             "tensile_strength, friction_angle} (Mohr–Coulomb)")
        return self

    def build(self) -> Bond:
        residual = 0.0 if self.residual_cohesion is None else self.residual_cohesion
        if self.cohesion is not None:
            return Bond.mohr_coulomb(self.cohesion, self.tensile_strength, self.friction_angle,
                                     self.friction, residual)
        return Bond(self.tensile, self.shear, self.alpha, self.tension_alpha, self.friction,
                    residual)


class GravityLoad(_Spec):
    """Self-weight: density × ``g`` (m/s²) on ``bodies`` (all bodies when empty)."""

    type: Literal["gravity"] = "gravity"
    g: Point = (0.0, -9.81)
    bodies: list[str] = []


class NodalLoadSpec(_Spec):
    """The same force on every node of a node set: fx, fy in N, mz in N·m (n nodes: n times
    the force in all; for a total force along an edge use ``edge_force``)."""

    type: Literal["nodal"] = "nodal"
    nodes: str
    fx: float = 0.0
    fy: float = 0.0
    mz: float = 0.0


class PressureLoad(_Spec):
    """Tractions on the body edges in a node set, Pa: ``normal`` > 0 pushes into the body,
    ``tangential`` acts along t = (n_y, −n_x) (the outward normal turned clockwise: +x on a
    top face, as the CFE tangent), ``traction`` = [tx, ty] in global x, y."""

    type: Literal["pressure"] = "pressure"
    nodes: str
    normal: Pressure | None = None
    tangential: Pressure | None = Field(
        None, description="Pa along t = (n_y, -n_x), the outward normal n turned clockwise "
        "(+x on a top face, as the CFE tangent): a constant or {from = [x0, y0, p0], to = "
        "[x1, y1, p1]}")
    traction: tuple[Pressure, Pressure] | None = Field(
        None, description="[tx, ty]: traction in global x, y components, Pa (each a constant "
        "or {from = [x0, y0, p0], to = [x1, y1, p1]})")

    @model_validator(mode="after")
    def _something(self) -> PressureLoad:
        if self.normal is None and self.tangential is None and self.traction is None:
            raise ValueError("give normal, tangential and/or traction")
        return self


class EdgeForceLoad(_Spec):
    """A total force (fx, fy in N) spread as a uniform traction along the body edges in a node
    set (consistent nodal forces: they sum to exactly (fx, fy))."""

    type: Literal["edge_force"] = "edge_force"
    nodes: str
    fx: float = 0.0
    fy: float = 0.0


class WaterLoadSpec(_Spec):
    """Hydrostatic pressure p = unit_weight · max(level − y, 0) (Pa) on the body edges in a
    node set, pushing into the body; exact where the level cuts an edge."""

    type: Literal["water"] = "water"
    nodes: str
    level: float | None = Field(None, description="elevation of the free surface, m (y is "
                                "up); omitted: the pattern's factor is the level, m, and its "
                                "program segments raise or lower the water (exact events in "
                                "the level); such a pattern holds only water loads without "
                                "a level")
    unit_weight: float = Field(9810.0, gt=0, description="unit weight of water γ_w, N/m³")


class UpliftLoadSpec(_Spec):
    """Uplift in a joint: the pressure pushes the S+ and S− bodies of ``interface`` apart."""

    type: Literal["uplift"] = "uplift"
    interface: str
    head: Profile | None = Field(None, description="pressure head, m of water")
    pressure: Profile | None = Field(None, description="pressure, Pa")
    unit_weight: float = Field(9810.0, gt=0, description="unit weight of water γ_w, N/m³")

    @model_validator(mode="after")
    def _one(self) -> UpliftLoadSpec:
        if (text := Uplift.form_problem(self.head, self.pressure)) is not None:
            raise ValueError(text)
        return self


class CrackWaterSpec(_Spec):
    """Water in the opened parts of joint ``interface``: where a CFE is open, the pressure
    γ_w (level − y) acts on both faces (replacing the joint's uplift there)."""

    type: Literal["crack_water"] = "crack_water"
    interface: str
    level: float | None = Field(None, description="elevation of the water surface, m; "
                                "omitted: the pattern's factor is the level (a pattern with a "
                                "water load without a level)")
    unit_weight: float = Field(9810.0, gt=0, description="unit weight of water γ_w, N/m³")
    pressure: float | None = Field(None, description="pressure in the crack, Pa per unit "
                                   "factor, uniform (the pressure that reaches the gap through "
                                   "the joint), instead of a level")
    entry: Point | list[Point] | None = Field(
        None, description="where the water reaches the joint (the heel), m, or a list of such "
        "points: only open CFEs joined to one by open CFEs are wet; omitted: every open CFE")

    @model_validator(mode="after")
    def _level_or_pressure(self) -> CrackWaterSpec:
        if (text := CrackWater.form_problem(self.level, self.pressure)) is not None:
            raise ValueError(text)
        return self


class DisplacementLoad(_Spec):
    """Prescribed displacement ``value`` (m, or rad for rz) of ``dof`` of a node set."""

    type: Literal["displacement"] = "displacement"
    nodes: str
    dof: DofName
    value: float


class ObstacleMotionLoad(_Spec):
    """Rigid motion of an obstacle per unit λ: translation (dx, dy) in m and a small rotation
    (rad, counter-clockwise) about ``about`` (default: the obstacle's first point)."""

    type: Literal["obstacle_motion"] = "obstacle_motion"
    obstacle: str
    dx: float = 0.0
    dy: float = 0.0
    rotation: float = Field(0.0, description="small rotation, rad, counter-clockwise")
    about: Point | None = Field(None, description="centre of the rotation, m (default: the "
                                "obstacle's first point)")


def _load_tag(v: Any) -> str | None:
    t = v.get("type") if isinstance(v, dict) else getattr(v, "type", None)
    return (f"type={t}" if t in ("gravity", "nodal", "edge_force", "pressure", "displacement",
                                 "water", "uplift", "crack_water", "obstacle_motion")
            else None)


LoadSpec = _tagged_union(
    _load_tag, "load_type",
    "type must be 'gravity', 'nodal', 'edge_force', 'pressure', 'water', 'uplift', "
    "'crack_water', 'displacement' or 'obstacle_motion'",
    **{"type=gravity": GravityLoad, "type=nodal": NodalLoadSpec,
       "type=edge_force": EdgeForceLoad, "type=pressure": PressureLoad,
       "type=displacement": DisplacementLoad,
       "type=water": WaterLoadSpec, "type=uplift": UpliftLoadSpec,
       "type=crack_water": CrackWaterSpec, "type=obstacle_motion": ObstacleMotionLoad},
)


class PatternSpec(_Spec):
    """``[patterns.NAME]``: loads applied together with one load factor λ."""

    loads: list[LoadSpec] = []


def _amplitude_value(v: Any) -> float | list[float]:
    """The amplitude of a cyclic ``[[program]]`` entry: a finite number, or a non-empty list
    of them (one per cycle)."""

    def num(x: Any) -> float:
        if isinstance(x, bool) or not isinstance(x, int | float) or not math.isfinite(x):
            raise ValueError("must be a finite number, or a list of them (one per cycle)")
        return float(x)

    if isinstance(v, list | tuple):
        if not v:
            raise ValueError("is empty: give one amplitude, or one per cycle")
        return [num(x) for x in v]
    return num(v)


Amplitude = Annotated[
    float | list[float],
    PlainValidator(_amplitude_value),
    WithJsonSchema({"anyOf": [{"type": "number"},
                              {"type": "array", "items": {"type": "number"}, "minItems": 1}]}),
]


class SegmentSpec(_Spec):
    """``[[program]]`` (and ``[[stages.program]]``, the program of a construction stage): the
    factor of ``pattern`` goes from ``start`` to ``end``; with
    ``rates``, several patterns move at once (non-proportional loading) and ``pattern`` is the
    segment's own name.  With ``amplitude`` and ``cycles`` instead of ``end`` the entry is a
    cyclic program (:func:`stepcontact.cycles`): ``cycles`` times the factor goes to
    ``mean + amplitude``, then to ``mean − amplitude`` (two segments per cycle).  Required,
    unless the model is built in ``[[stages]]``: each stage then has its own
    ``[[stages.program]]`` and a top-level ``[[program]]`` is an error."""

    pattern: str = Field(description="load pattern; with rates: the segment's name (a label)")
    end: float | None = Field(None, description="load factor λ at the end of the segment "
                              "(required, unless the entry gives amplitude and cycles)")
    start: float | None = Field(None, description="default: where the pattern stands")
    rates: dict[str, float] | None = Field(
        None, description="{pattern = rate, …}: each pattern's factor changes by rate per unit "
        "of the segment's parameter (which goes from start to end)")
    amplitude: Amplitude | None = Field(
        None, description="cyclic entry (instead of end): the factor swings to mean ± "
        "amplitude, in the pattern's units per unit factor (N for 1 N per unit λ); a list: one "
        "amplitude per cycle; nonzero, of one sign (negative: the first half-cycle goes down)")
    cycles: int | None = Field(None, ge=1, description="cyclic entry: number of cycles, two "
                               "segments each (default with a list of amplitudes: its length)")
    mean: float = Field(0.0, description="cyclic entry: the factor the cycles swing about")

    @model_validator(mode="after")
    def _segment_or_cycles(self) -> SegmentSpec:
        cyclic = {"cycles", "mean"} & self.model_fields_set
        if self.amplitude is None:
            if cyclic:
                raise ValueError(f"{sorted(cyclic)[0]} belongs to a cyclic entry: give its "
                                 "amplitude too (and no end)")
            if self.end is None:
                raise ValueError("give end (one segment), or amplitude and cycles (a cyclic "
                                 "program)")
        elif self.end is not None:
            raise ValueError("give end (one segment) or amplitude and cycles (a cyclic "
                             "program), not both: the cycles end at mean − amplitude")
        return self


def _segments(s: SegmentSpec) -> tuple[Segment, ...]:
    """The segments of one ``[[program]]`` entry, a cyclic one expanded (none when its
    amplitudes are wrong: :meth:`_Builder.check_references` reports them)."""
    if s.amplitude is None:
        return (Segment(s.pattern, s.end, s.start, s.rates),)  # type: ignore[arg-type]
    try:
        return cycles(s.pattern, s.amplitude, s.cycles, mean=s.mean, start=s.start,
                      rates=s.rates)
    except ModelError:
        return ()


class StageSpec(_Spec):
    """``[[stages]]``: one construction stage (method.md §6; :class:`stepcontact.Stage`).  The
    stages run in the order of the file, in one static run that keeps the locked-in stresses
    and contact forces from stage to stage.  A stage lists what enters the structure when it
    begins, what leaves it and the joints grouted, then its own load segments
    (``[[stages.program]]``, the syntax of ``[[program]]``); the model's load program is the
    stages' programs in order, so a model with stages has no top-level ``[[program]]`` (move
    its segments into the first stage).  Bodies, interfaces and supports that no stage lists
    are in place from the start; each name is listed by one stage at most.  Automatic
    segments (events located) start a stage: the reactions of removed supports are released,
    and the loads of standing patterns ramp onto the bodies just built; so a later stage that
    removes supports or builds bodies may have no segment of its own."""

    name: str = Field(description="unique stage name (results show it)")
    bodies: list[str] = Field([], description="bodies built at this stage: inactive, unloaded "
                              "and stress-free before, then placed stress-free on the deformed "
                              "structure (their nodes start from zero displacement)")
    interfaces: list[str] = Field([], description="interfaces made at once at this stage: in "
                                  "contact and stress-free (the CFEs' current mutual "
                                  "displacements become their zero)")
    contacts: list[str] = Field([], description="interfaces that act from this stage with "
                                "their geometric gap in the current deformed configuration (a "
                                "CFE closes when its gap does)")
    supports: list[str] = Field([], description="supports (by name) placed at this stage: "
                                "they hold the DOFs where they are now")
    remove_supports: list[str] = Field([], description="supports removed at this stage: their "
                                       "reaction is released by an automatic segment at the "
                                       "start of the stage (events located)")
    grout: dict[str, BondSpec] = Field({}, description="{interface name = bond table}: the "
                                       "CFEs of an interface in place become bonded with that "
                                       "strength (eq. (12), the table of `[interfaces.bond]`), "
                                       "keeping their current forces; an open CFE is filled "
                                       "(its opening becomes its zero)")
    program: list[SegmentSpec] = Field([], description="`[[stages.program]]`: the stage's "
                                       "load segments, exactly as `[[program]]` (cyclic "
                                       "entries too); needed unless the stage removes supports "
                                       "or builds bodies (automatic segments) or has a "
                                       "dynamic interval")
    dynamics: DynamicsSpec | None = Field(None, description="`[stages.dynamics]`: a dynamic "
                                          "interval at the end of the stage, after its "
                                          "segments (the table of `[dynamics]`).  On a stage "
                                          "before the last, the static run goes on from where "
                                          "the motion leaves the structure: the force out of "
                                          "balance there (M a + C v) is released by an "
                                          "automatic segment; the patterns of its loads stand "
                                          "at g(T) after it.  On the last stage it is the "
                                          "model's `[dynamics]` (give it once)")


class TimeFunctionSpec(_Spec):
    """How a load pattern varies in time in the dynamic interval: ``type`` pulse (amplitude,
    start, duration, shape), harmonic (amplitude, frequency, phase, start), table (times,
    values, or csv = a two-column file) or constant (amplitude)."""

    pattern: str = Field(description="the load pattern it multiplies")
    type: Literal["pulse", "harmonic", "table", "constant"] = "pulse"
    amplitude: float = 1.0
    start: float = Field(0.0, description="s")
    duration: float | None = Field(None, gt=0, description="pulse duration, s")
    shape: PulseShape = "half_sine"
    frequency: float | None = Field(None, gt=0, description="harmonic frequency, Hz")
    phase: float = Field(0.0, description="harmonic phase, rad")
    times: list[float] | None = Field(None, description="table: times, s (increasing)")
    values: list[float] | None = Field(None, description="table: values at the times")
    csv: str | None = Field(None, description="table from a CSV file (time, value), relative "
                            "to the model file")

    @model_validator(mode="after")
    def _complete(self) -> TimeFunctionSpec:
        if self.type == "pulse" and self.duration is None:
            raise ValueError("a pulse needs its duration (s)")
        if self.type == "harmonic" and self.frequency is None:
            raise ValueError("a harmonic needs its frequency (Hz)")
        if self.type == "table" and (self.csv is None) == (self.times is None):
            raise ValueError("a table needs times and values, or csv")
        return self


class DampingSpec(_Spec):
    """Rayleigh damping: ``a0`` (1/s) and ``a1`` (s), or two damping ratios at two
    frequencies (Hz)."""

    a0: float = Field(0.0, ge=0)
    a1: float = Field(0.0, ge=0)
    ratios: tuple[float, float] | None = None
    frequencies: tuple[float, float] | None = None


class DynamicsSpec(_Spec):
    """``[dynamics]``: a dynamic interval after the load program (Newmark, events located in
    time), starting from the program's last state."""

    dt: float = Field(gt=0, description="time step, s")
    duration: float = Field(gt=0, description="length of the interval, s")
    mass: MassKind = "consistent"
    damping: DampingSpec = DampingSpec()
    restitution: float = Field(0.0, ge=RESTITUTION_RANGE[0], le=RESTITUTION_RANGE[1],
                               description="Newton's coefficient of impacts")
    alpha: float = Field(0.0, ge=HHT_ALPHA_RANGE[0], le=HHT_ALPHA_RANGE[1],
                         description="HHT-α numerical damping (0: Newmark's average "
                         "acceleration)")
    record_every: int = Field(1, ge=1)
    max_steps: int = Field(10_000_000, ge=1, description="limit of the number of time steps: "
                           "an interval with more (duration / dt) is refused before any work")
    loads: list[TimeFunctionSpec] = []


StageSpec.model_rebuild()


class ModelFile(_Spec):
    """The whole model file."""

    model: ModelSection = ModelSection()
    mesh: MeshSection | None = None
    materials: dict[str, MaterialSpec] = {}
    bodies: list[BodySpec] = []
    frames: list[FrameSpec] = []
    node_sets: dict[str, NodeSetSpec] = {}
    supports: list[SupportSpec] = []
    ties: list[TieSpec] = []
    springs: list[SpringSpec] = []
    obstacles: list[ObstacleSpec] = []
    interfaces: list[InterfaceSpec] = []
    patterns: dict[str, PatternSpec] = {}
    program: list[SegmentSpec] = Field([], description="the load program; required, "
                                       "unless the model has `[[stages]]` (then each stage "
                                       "has its own `[[stages.program]]` and this is an error)")
    stages: list[StageSpec] = Field([], description="construction stages, in order; their "
                                    "programs are the load program")
    dynamics: DynamicsSpec | None = None

    model_config = ConfigDict(json_schema_extra={"anyOf": [{"required": ["program"]},
                                                           {"required": ["stages"]}]})


# --------------------------------------------------------------------------------------------
# errors
# --------------------------------------------------------------------------------------------
_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _path(loc: tuple[str | int, ...] | list[str | int]) -> str:
    """pydantic location -> field path as written in the file, e.g. ``bodies[1].material.E``."""
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        elif part in _TAGS:
            continue
        else:
            key = part if _KEY.match(part) else f'"{part}"'
            out += f".{key}" if out else key
    return out or "model file"


def _message(err: dict[str, Any]) -> str:
    kind = err["type"]
    if kind == "missing":
        return "required field is missing"
    if kind == "extra_forbidden":
        return "unknown field (not part of the model file format)"
    if kind == "finite_number":
        msg = "must be a finite number (NaN and inf are not allowed)"
    elif kind in ("value_error", "assertion_error"):
        msg = str(err["msg"]).removeprefix("Value error, ").removeprefix("Assertion failed, ")
    else:
        msg = str(err["msg"])
        msg = msg[:1].lower() + msg[1:]
        msg = re.sub(r"^input should (be|have)", r"must \1", msg)
    value = err.get("input")
    if isinstance(value, str | int | float | bool) and repr(value) not in msg:
        msg += f" (got {value!r})"
    return msg


@dataclass(frozen=True)
class Problem:
    """One problem of a model file.

    ``item`` names the field (``bodies[1].material``), the physical group or the bodies
    concerned; ``severity`` is ``"error"`` (the model cannot be run) or ``"warning"``.
    """

    item: str
    message: str
    severity: Literal["error", "warning"] = "error"

    def __str__(self) -> str:
        return f"{self.item}: {self.message}"


class _Problems:
    """Collects (path, message) pairs and raises them as one :class:`ModelError`."""

    def __init__(self) -> None:
        self.items: list[tuple[str, str]] = []
        self.warnings: list[tuple[str, str]] = []
        #: the warning class of each warning (default: FutureWarning, a deprecation)
        self.category: dict[tuple[str, str], type[Warning]] = {}

    def add(self, path: str, problem: str) -> None:
        if (path, problem) not in self.items:
            self.items.append((path, problem))

    def warn(self, path: str, problem: str, category: type[Warning] = FutureWarning) -> None:
        self.warnings.append((path, problem))
        self.category[(path, problem)] = category

    def implausible(self, quantity: str, value: float, path: str) -> None:
        """A warning when ``value`` is outside the plausible range of ``quantity``
        (:data:`stepcontact.model.plausible.RANGES`)."""
        text = plausible.message(quantity, value, path)
        if text is not None:
            self.warn(path, text.removeprefix(f"{path} = ").strip(),
                      plausible.PlausibilityWarning)

    def raise_if_any(self) -> None:
        if self.items:
            raise _model_error(self.items)

    def problems(self) -> list[Problem]:
        return [Problem(p, m) for p, m in self.items] + [
            Problem(p, m, "warning") for p, m in self.warnings
        ]


def _model_error(items: list[tuple[str, str]]) -> ModelError:
    (path, problem), rest = items[0], items[1:]
    if rest:
        listed = "; ".join(f"{p}: {m}" for p, m in rest[:_MAX_LISTED])
        more = f"; and {len(rest) - _MAX_LISTED} more" if len(rest) > _MAX_LISTED else ""
        problem = f"{problem} (also {listed}{more})"
    err = ModelError(path, problem)
    err.errors = list(items)  # type: ignore[attr-defined]
    return err


def _validate(d: dict[str, Any]) -> ModelFile:
    try:
        spec = ModelFile.model_validate(d)
        items = []
    except ValidationError as e:
        items = [(_path(err["loc"]), _message(err)) for err in e.errors()]
    items += _program_problems(d)
    if items:
        raise _model_error(items) from None
    return spec


def _program_problems(d: Any) -> list[tuple[str, str]]:
    """A load program is given: top-level ``[[program]]`` segments, or ``[[stages]]`` each with
    its own (not both)."""
    if not isinstance(d, dict):
        return []
    program, stages = d.get("program"), d.get("stages")
    if stages:
        if program:
            return [("program", "is given together with [[stages]]: with stages the load "
                     "program is the stages' own; move these segments into the "
                     "[[stages.program]] of the first stage")]
        return []
    how = ("give the load program as [[program]] segments (or construction stages, "
           "[[stages]], each with its [[stages.program]])")
    if program is None:
        return [("program", f"required field is missing: {how}")]
    if isinstance(program, list) and not program:
        return [("program", f"is empty: {how}")]
    return []


# --------------------------------------------------------------------------------------------
# building the Model
# --------------------------------------------------------------------------------------------
def _deprecated_pairs(p: _Problems, path: str, ld: PressureLoad) -> None:
    """Warn about pressures given as [start, end]: they follow the node set's order."""
    given = {"normal": ld.normal, "tangential": ld.tangential}
    if ld.traction is not None:
        given |= {f"traction[{c}]": v for c, v in enumerate(ld.traction)}
    for key, v in given.items():
        if isinstance(v, tuple):
            p.warn(f"{path}.{key}", "a pair [start, end] varies along the node set's order, "
                   "which a reversed curve flips (deprecated): give the pressure by coordinates, "
                   "{from = [x0, y0, p0], to = [x1, y1, p1]}, or use type = \"water\"")


def _known(names) -> str:
    names = list(names)
    return ", ".join(repr(n) for n in names) if names else "none defined"


def _box(box: BoxSpec, atol: float) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    """Predicate of a box with inclusive bounds (tolerance ``atol``, m)."""
    lo = np.array([-np.inf if box.xmin is None else box.xmin,
                   -np.inf if box.ymin is None else box.ymin]) - atol
    hi = np.array([np.inf if box.xmax is None else box.xmax,
                   np.inf if box.ymax is None else box.ymax]) + atol

    def inside(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return (x >= lo[0]) & (x <= hi[0]) & (y >= lo[1]) & (y <= hi[1])

    return inside


def _build_node_set(name: str, ns: NodeSetSpec, body: Body | Frame) -> NodeSet:
    path = _path(["node_sets", name])
    if ns.index is not None:
        idx = np.asarray(ns.index, dtype=np.int64)
        if idx.size == 0:
            raise ModelError(f"{path}.index", "selects no node")
        if idx.max() >= body.n_nodes:
            raise ModelError(
                f"{path}.index",
                f"node {int(idx.max())} does not exist (body '{body.name}' has {body.n_nodes})",
            )
        return NodeSet(body.name, idx, name)
    pts = body.points
    atol = 1e-9 * max(1.0, float(np.ptp(pts, axis=0).max()) if len(pts) else 1.0)
    where = _box(ns.where, atol) if ns.where is not None else None
    try:
        return select_nodes(body, where, x=ns.x, y=ns.y, boundary=ns.boundary, name=name)
    except ModelError as e:
        raise ModelError(path, f"{e.problem} on body '{body.name}'") from None


class _Builder:
    """Builds the model of a validated file, collecting every problem on the way.

    Nothing stops at the first problem: an item that depends on a broken one (a node set of a
    body that could not be made, a support on that node set, ...) is skipped silently, since
    the broken item is reported already.
    """

    def __init__(self, spec: ModelFile, base: Path, problems: _Problems):
        self.spec = spec
        self.base = base
        self.p = problems
        self.mesh: MeshFile | None = None
        self.mesh_failed = False
        self.bodies: dict[str, Body | Frame] = {}
        self.paths: dict[str, str] = {}  # body name -> field path, e.g. "bodies[1]"
        self.surface_of: dict[str, str] = {}  # mesh body name -> physical surface
        self.failed: set[str] = set()  # bodies that could not be made
        self.sets: dict[str, NodeSet] = {}
        self.implicit: dict[str, str] = {}  # physical group used as a node set -> first path

    # ---- mesh and references -------------------------------------------------------------
    def read_mesh(self) -> None:
        ms = self.spec.mesh
        if ms is None:
            for i, b in enumerate(self.spec.bodies):
                if isinstance(b, MeshBodySpec):
                    self.p.add(f"bodies[{i}]", "a mesh body needs a mesh: add [mesh] with "
                               "file = \"NAME.msh\" (relative to the model file)")
            return
        path = Path(ms.file).expanduser()
        path = Path(os.path.normpath(path if path.is_absolute() else self.base / path))
        try:
            self.mesh = read_mesh(path, ms.order or 1, ms.element or "tri", ms.size)
        except ModelError as e:
            self.mesh_failed = True
            where = str(path)
            base = self.base.resolve()
            full = path.resolve()
            if not full.is_relative_to(base):  # say which file, wherever it is
                where = f"'{ms.file}' ({full}, outside the model file's folder {base})"
            self.p.add("mesh.file", f"{where}: {e.problem}")

    def _group_problem(self, name: str, dims: tuple[int, ...]) -> str | None:
        """Why ``name`` is not a usable physical group of these dimensions (None if it is)."""
        assert self.mesh is not None
        g = self.mesh.groups.get(name)
        wanted = " or ".join(GROUP_KINDS[d] for d in dims)
        if g is None:
            return (f"physical group '{name}' not found in {self.mesh.path.name}; groups are: "
                    f"{self.mesh.describe()}")
        if g.dim not in dims:
            return f"'{name}' is a physical {g.kind}, a physical {wanted} is needed here"
        return None

    def check_references(self) -> None:
        """Every name used (materials, bodies, node sets, physical groups, patterns) exists;
        names are unique."""
        spec, p, mesh = self.spec, self.p, self.mesh
        bodies = [_body_name(b) for b in spec.bodies] + [f.name for f in spec.frames]
        mesh_bodies = {b.body_name for b in spec.bodies if isinstance(b, MeshBodySpec)}
        surfaces: dict[str, str] = {}
        for i, b in enumerate(spec.bodies):
            if isinstance(b.material, str) and b.material not in spec.materials:
                p.add(
                    f"bodies[{i}].material",
                    f"unknown material '{b.material}' (known: {_known(spec.materials)})",
                )
            if not isinstance(b, MeshBodySpec):
                continue
            if b.material is None:
                p.add(f"bodies[{i}].material",
                      f"physical surface '{b.surface}' has no material: give material = "
                      "\"NAME\" or an inline table {E, nu, density}")
            if mesh is not None:
                field = f"bodies[{i}].{'group' if b.group is not None else 'name'}"
                why = self._group_problem(b.surface, (2,))
                if why is not None:
                    p.add(field, why)
                elif b.surface in surfaces:
                    p.add(field, f"physical surface '{b.surface}' is body '{surfaces[b.surface]}'"
                          " already")
                surfaces.setdefault(b.surface, b.body_name)
        if mesh is not None and self.spec.mesh is not None:
            ignore = self.spec.mesh.ignore
            for j, s in enumerate(ignore):
                why = self._group_problem(s, (2,))
                if why is not None:
                    p.add(f"mesh.ignore[{j}]", why)
            for s in mesh.surfaces:
                if s not in surfaces and s not in ignore:
                    p.add("mesh", f"physical surface '{s}' is not a body: add [[bodies]] with "
                          f"kind = \"mesh\", group = \"{s}\" and its material (or list it in "
                          "mesh.ignore)")
        seen: set[str] = set()
        for group in ("bodies", "frames"):
            for i, b in enumerate(getattr(spec, group)):
                name = _body_name(b) if group == "bodies" else b.name
                if name in seen:
                    p.add(f"{group}[{i}].name", f"duplicate body name '{name}'")
                seen.add(name)
        if not bodies:
            p.add("bodies", "the model has no body and no frame")
        for name, ns in spec.node_sets.items():
            path = _path(["node_sets", name])
            if ns.body is not None and ns.body not in bodies:
                p.add(f"{path}.body", f"unknown body '{ns.body}' (known: {_known(bodies)})")
            elif ns.group is not None and ns.body is not None and ns.body not in mesh_bodies:
                p.add(f"{path}.body", f"body '{ns.body}' is not a mesh body (kind = \"mesh\"); "
                      "a physical group's nodes belong to a mesh body")
            if ns.group is not None:
                if mesh is not None:
                    why = self._group_problem(ns.group, (0, 1))
                    if why is not None:
                        p.add(f"{path}.group", why)
                elif not self.mesh_failed:
                    p.add(f"{path}.group", "physical groups need the [mesh] section")

        def node_set(path: str, name: str | None) -> None:
            if name is None or name in spec.node_sets:
                return
            if mesh is not None and name in mesh.groups:
                why = self._group_problem(name, (0, 1))
                if why is None:
                    self.implicit.setdefault(name, path)
                else:
                    p.add(path, f"{why} (a node set or a physical curve or point)")
                return
            if self.mesh_failed:
                return  # may be a group of the mesh that could not be read
            groups = ""
            if mesh is not None:
                groups = f"; physical curves and points: {_known(mesh.names(1) + mesh.names(0))}"
            p.add(path, f"unknown node set '{name}' (known: {_known(spec.node_sets)}{groups})")

        for i, s in enumerate(spec.supports):
            node_set(f"supports[{i}].nodes", s.nodes)
        for i, t in enumerate(spec.ties):
            node_set(f"ties[{i}].a", t.a)
            node_set(f"ties[{i}].b", t.b)
        for i, s in enumerate(spec.springs):
            node_set(f"springs[{i}].a", s.a)
            node_set(f"springs[{i}].b", s.b)
        obstacles: set[str] = set()
        for i, ob in enumerate(spec.obstacles):
            if ob.name in obstacles:
                p.add(f"obstacles[{i}].name", f"duplicate obstacle name '{ob.name}'")
            obstacles.add(ob.name)
        used: set[str] = set()
        names: set[str] = set()
        for i, itf in enumerate(spec.interfaces):
            node_set(f"interfaces[{i}].plus", itf.plus)
            node_set(f"interfaces[{i}].minus", itf.minus)
            if itf.obstacle is not None:
                used.add(itf.obstacle)
                if itf.obstacle not in obstacles:
                    p.add(f"interfaces[{i}].obstacle", f"unknown obstacle '{itf.obstacle}' "
                          f"(known: {_known(obstacles)})")
            if itf.name in names:
                p.add(f"interfaces[{i}].name", f"duplicate interface name '{itf.name}'")
            names.add(itf.name)
        for pname, pat in spec.patterns.items():
            for j, ld in enumerate(pat.loads):
                path = f"{_path(['patterns', pname, 'loads', j])}"
                if isinstance(ld, GravityLoad):
                    for b in ld.bodies:
                        if b not in bodies:
                            p.add(f"{path}.bodies",
                                  f"unknown body '{b}' (known: {_known(bodies)})")
                elif isinstance(ld, UpliftLoadSpec | CrackWaterSpec):
                    if ld.interface not in names:
                        p.add(f"{path}.interface", f"unknown interface '{ld.interface}' "
                              f"(known: {_known(names)})")
                elif isinstance(ld, ObstacleMotionLoad):
                    if ld.obstacle not in obstacles:
                        p.add(f"{path}.obstacle", f"unknown obstacle '{ld.obstacle}' "
                              f"(known: {_known(obstacles)})")
                    elif ld.obstacle not in used:
                        p.add(f"{path}.obstacle", f"obstacle '{ld.obstacle}' is used by no "
                              "interface (an interface names it with obstacle = \"NAME\")")
                else:
                    node_set(f"{path}.nodes", ld.nodes)
                    if isinstance(ld, PressureLoad):
                        _deprecated_pairs(p, path, ld)
        current: dict[str, float] = {}
        for path, seg in self.program_entries():
            if seg.rates is not None:
                if not seg.rates:
                    p.add(f"{path}.rates", "is empty: give {pattern = rate, …}")
                for name in seg.rates:
                    if name not in spec.patterns:
                        p.add(f"{path}.rates.{name}",
                              f"unknown load pattern '{name}' (known: {_known(spec.patterns)})")
                if seg.pattern in spec.patterns:
                    p.add(f"{path}.pattern", f"'{seg.pattern}' is a load pattern: a "
                          "segment with rates is named by a label that is not a pattern")
            elif seg.pattern not in spec.patterns:
                p.add(f"{path}.pattern",
                      f"unknown load pattern '{seg.pattern}' (known: {_known(spec.patterns)})")
                continue
            now = current.get(seg.pattern, 0.0)
            if seg.start is not None and abs(seg.start - now) > 1e-12 * max(1.0, abs(now)):
                p.add(
                    f"{path}.start",
                    f"segments do not chain: pattern '{seg.pattern}' stands at λ = {now:g}, "
                    f"this segment starts at {seg.start:g}",
                )
            if seg.amplitude is None:
                current[seg.pattern] = seg.end  # type: ignore[assignment]
                continue
            try:  # a cyclic entry ends at mean − its last amplitude
                amps = cycle_amplitudes(seg.amplitude, seg.cycles, path, "cycles")
                current[seg.pattern] = seg.mean - amps[-1]
            except ModelError as e:
                p.add(e.item, e.problem)

        self.check_stages(bodies, names)

    def program_entries(self) -> Iterator[tuple[str, SegmentSpec]]:
        """Every ``[[program]]`` entry with its field path; with stages, the stages' entries
        in order (the model's load program)."""
        for i, seg in enumerate(self.spec.program):
            yield f"program[{i}]", seg
        for k, st in enumerate(self.spec.stages):
            for i, seg in enumerate(st.program):
                yield f"stages[{k}].program[{i}]", seg

    def check_stages(self, bodies: list[str], interfaces: set[str]) -> None:
        """The names a stage lists exist and are listed once (by one stage, in one of its
        lists); stage names are unique; a support is removed after it is placed; grout fills
        joints in place, after the first stage; a stage has a load segment (its own, or the
        automatic ones of removed supports and new bodies).  The checks of the solver's
        :class:`~stepcontact.solver.staging.StagePlan`, with the paths of the file."""
        spec, p = self.spec, self.p
        if not spec.stages:
            return
        supports: dict[str, list[int]] = {}
        for i, s in enumerate(spec.supports):
            supports.setdefault(s.name or s.nodes, []).append(i)
        known = {"body": bodies, "interface": sorted(interfaces), "support": list(supports)}
        lists = (("bodies", "body", "built"), ("interfaces", "interface", "made"),
                 ("contacts", "interface", "made"), ("supports", "support", "placed"),
                 ("remove_supports", "support", "removed"))
        first: dict[str, int] = {}
        claimed: dict[tuple[str, str], tuple[int, str]] = {}  # (what, name) -> (stage, list)
        for k, st in enumerate(spec.stages):
            item = f"stages[{k}]"
            if st.name in first:
                p.add(f"{item}.name", f"duplicate stage name '{st.name}' (also stages"
                      f"[{first[st.name]}])")
            first.setdefault(st.name, k)
            for key, kind, what in lists:
                for name in getattr(st, key):
                    if name not in known[kind]:
                        p.add(f"{item}.{key}", f"no such {kind} '{name}' (known: "
                              f"{_known(known[kind])})")
                        continue
                    if kind == "support" and len(supports[name]) > 1:
                        at = " and ".join(f"supports[{i}]" for i in supports[name])
                        p.add(f"{item}.{key}", f"support name '{name}' is ambiguous ({at} have "
                              "it): give those supports distinct names (name = \"...\")")
                    prev = claimed.get((what, name))
                    if prev is None:
                        claimed[(what, name)] = (k, key)
                    elif prev == (k, key):
                        p.add(f"{item}.{key}", f"lists {kind} '{name}' twice")
                    elif prev[0] == k:
                        p.add(f"{item}.{key}", f"{kind} '{name}' is listed in {prev[1]} too: "
                              "an interface is made at once (interfaces) or acts as a contact "
                              "with its gap (contacts)" if kind == "interface" else
                              f"{kind} '{name}' is listed in {prev[1]} too")
                    else:
                        p.add(f"{item}.{key}", f"{kind} '{name}' is already listed by "
                              f"stages[{prev[0]}] ('{spec.stages[prev[0]].name}')")
            for name in st.grout:
                if name not in interfaces:
                    p.add(f"{item}.grout", f"no such interface '{name}' (known: "
                          f"{_known(sorted(interfaces))})")
                elif k == 0:
                    p.add(f"{item}.grout", f"the first stage cannot grout interface '{name}' "
                          "(there is no earlier state to keep): give the interface its "
                          "strength from the start ([interfaces.bond]) or grout it at a later "
                          "stage")
            auto = bool(st.bodies or st.remove_supports or st.dynamics is not None)
            if k > 0 and not st.program and not auto:
                p.add(f"{item}.program", f"stage '{st.name}' has no load segment: give it a "
                      "[[stages.program]] entry (a stage begins with its first segment)")
        if len(spec.stages) == 1 and not spec.stages[0].program:
            p.add("stages[0].program", f"stage '{spec.stages[0].name}' has no load segment: "
                  "give it [[stages.program]] entries")
        for k, st in enumerate(spec.stages):
            for name in st.grout:
                j = claimed.get(("made", name), (0,))[0]
                if j > k:
                    p.add(f"stages[{k}].grout", f"interface '{name}' is made later, by "
                          f"stages[{j}] ('{spec.stages[j].name}'): grout joints in place")
        for (what, name), (k, key) in claimed.items():
            if what != "removed":
                continue
            j = claimed.get(("placed", name), (0, ""))[0]
            if k <= j:
                where = (f"placed by stages[{j}] ('{spec.stages[j].name}')" if
                         ("placed", name) in claimed else "in place from the start")
                p.add(f"stages[{k}].{key}", f"support '{name}' is removed before or when it is "
                      f"placed ({where}): remove it at a later stage")

    # ---- bodies and node sets -------------------------------------------------------------
    def _material(self, ref: str | MaterialSpec | None) -> Material | None:
        if isinstance(ref, str):
            spec = self.spec.materials.get(ref)
            return None if spec is None else spec.build()
        return None if ref is None else ref.build()

    def build_bodies(self) -> None:
        for i, b in enumerate(self.spec.bodies):
            name = _body_name(b)
            if name in self.paths:
                continue  # duplicate name, reported
            self.paths[name] = f"bodies[{i}]"
            mat = self._material(b.material)
            if isinstance(b, MeshBodySpec):
                self.surface_of[name] = b.surface
            if mat is None:
                self.failed.add(name)
                continue
            try:
                if isinstance(b, RectangleSpec):
                    self.bodies[name] = rectangle(
                        b.name, b.corner0, b.corner1, b.nx, b.ny, mat, b.element,
                        grading=b.grading,
                    )
                    continue
                if isinstance(b, QuadRegionSpec):
                    self.bodies[name] = quad_region(b.name, b.corners, b.nx, b.ny, mat,
                                                    b.element, grading=b.grading)
                    continue
                if isinstance(b, PolygonSpec):
                    try:
                        self.bodies[name] = polygon_region(b.name, b.vertices, mat, b.element,
                                                           n=b.n, size=b.size)
                    except ModelError as e:  # the field at fault: bodies[i].vertices, …
                        field = e.item.removeprefix(f"body '{b.name}'")
                        self.failed.add(name)
                        self.p.add(f"bodies[{i}]{field if field.startswith('.') else ''}",
                                   e.problem)
                    continue
                if isinstance(b, HalfDiscSpec):
                    self.bodies[name] = half_disc(
                        b.name, b.center, b.radius, b.n_radial, b.n_around, mat, b.element,
                        refine_toward="bottom" if b.refine else None, ratio=b.ratio)
                    continue
                if self.mesh is None or self._group_problem(b.surface, (2,)) is not None:
                    self.failed.add(name)
                    continue
                self.bodies[name] = self.mesh.body(b.surface, mat, name=name, element=b.element)
            except ModelError as e:
                self.failed.add(name)
                detail = e.problem if e.item.startswith("body ") else f"{e.item} {e.problem}"
                self.p.add(f"bodies[{i}]", detail)
        for i, f in enumerate(self.spec.frames):
            if f.name in self.paths:
                continue
            self.paths[f.name] = f"frames[{i}]"
            try:
                self.bodies[f.name] = Frame.line(
                    f.name, f.start, f.end, f.n, E=f.E, A=f.A, I=f.I, density=f.density
                )
            except ModelError as e:
                self.failed.add(f.name)
                self.p.add(f"frames[{i}]", e.problem)

    def check_size(self) -> None:
        """The whole model fits in this machine's memory (each rectangle was checked before
        it was meshed; mesh bodies and the sum of all are checked here, before assembly)."""
        if len(self.bodies) < 2 and self.mesh is None:
            return
        ndof = sum((3 if isinstance(b, Frame) else 2) * b.n_nodes for b in self.bodies.values())
        nodes = sum(b.n_nodes for b in self.bodies.values())
        try:
            check_size(ndof, "model", f"the model ({len(self.bodies)} bodies, {nodes} nodes)")
        except ModelError as e:
            self.p.add(e.item, e.problem)

    def _group_set(self, group: str, body: str | None, name: str, path: str, hint: str) -> None:
        """Node set ``name`` of a physical group; problems are reported at ``path``."""
        assert self.mesh is not None
        if self._group_problem(group, (0, 1)) is not None:
            return
        if body is not None and body not in self.bodies:
            return
        if body is None:
            broken = {s for b, s in self.surface_of.items() if b in self.failed}
            if broken & set(self.mesh.owners(group)):
                return  # on a body that could not be made
        try:
            self.sets[name] = self.mesh.node_set(group, body, name)
        except ModelError as e:
            extra = hint if "say which body" in e.problem else ""
            self.p.add(path, f"{e.item} {e.problem}{extra}")

    def build_node_sets(self) -> None:
        for name, ns in self.spec.node_sets.items():
            path = _path(["node_sets", name])
            if ns.group is not None:
                if self.mesh is not None:
                    hint = f": add body = \"...\" to [{path}]"
                    self._group_set(ns.group, ns.body, name, f"{path}.group", hint)
                continue
            body = self.bodies.get(str(ns.body))
            if body is None:
                continue
            try:
                self.sets[name] = _build_node_set(name, ns, body)
            except ModelError as e:
                self.p.add(e.item, e.problem)
        for group, path in self.implicit.items():
            hint = (f": define [node_sets.NAME] with group = \"{group}\" and body = \"...\" and "
                    "use NAME here")
            self._group_set(group, None, group, path, hint)

    # ---- plausible values -----------------------------------------------------------------
    def check_plausible(self) -> None:
        """Values outside what any real structure has (:mod:`stepcontact.model.plausible`):
        warnings with the field path (the Python objects built from the file warn with their
        own names; those warnings are silenced while the file is built)."""
        spec, p = self.spec, self.p

        def material(path: str, m: MaterialSpec) -> None:
            p.implausible("E", m.E, f"{path}.E")
            p.implausible("density", m.density, f"{path}.density")

        for name, m in spec.materials.items():
            material(_path(["materials", name]), m)
        for i, b in enumerate(spec.bodies):
            if isinstance(b.material, MaterialSpec):
                material(f"bodies[{i}].material", b.material)
        for i, f in enumerate(spec.frames):
            p.implausible("E", f.E, f"frames[{i}].E")
            p.implausible("density", f.density, f"frames[{i}].density")
        from stepcontact.model.bond import apex_problem

        def bond(path: str, b: BondSpec) -> None:
            if b.friction is not None:
                p.implausible("friction", b.friction, f"{path}.friction")
            if b.cohesion is not None:
                text = apex_problem(b.cohesion, b.tensile_strength, b.friction_angle)
                if text is not None:
                    p.warn(f"{path}.tensile_strength", text, plausible.PlausibilityWarning)

        for i, itf in enumerate(spec.interfaces):
            p.implausible("friction", itf.friction, f"interfaces[{i}].friction")
            if itf.bond is not None:
                bond(f"interfaces[{i}].bond", itf.bond)
        for k, st in enumerate(spec.stages):
            for name, b in st.grout.items():
                bond(_path(["stages", k, "grout", name]), b)
        for pname, pat in spec.patterns.items():
            for j, ld in enumerate(pat.loads):
                path = _path(["patterns", pname, "loads", j])
                if isinstance(ld, GravityLoad):
                    p.implausible("gravity", math.hypot(*ld.g), f"{path}.g")
                if isinstance(ld, WaterLoadSpec | UpliftLoadSpec | CrackWaterSpec):
                    p.implausible("unit_weight_water", ld.unit_weight, f"{path}.unit_weight")
                if isinstance(ld, UpliftLoadSpec):
                    key, value = (("head", ld.head) if ld.head is not None else
                                  ("pressure", ld.pressure))
                    values = ([pt[2] for pt in value.points]
                              if isinstance(value, LinearProfile) else [value])
                    for v in values:
                        p.implausible("head" if key == "head" else "water_pressure", v,
                                      f"{path}.{key}")
                if isinstance(ld, CrackWaterSpec) and ld.pressure is not None:
                    p.implausible("water_pressure", ld.pressure, f"{path}.pressure")
        dyns = [("dynamics", spec.dynamics)] + [(f"stages[{k}].dynamics", st.dynamics)
                                                for k, st in enumerate(spec.stages)]
        for where, dyn in dyns:
            if dyn is not None and dyn.damping.ratios is not None:
                for j, z in enumerate(dyn.damping.ratios):
                    p.implausible("damping_ratio", z, f"{where}.damping.ratios[{j}]")

    # ---- the model ------------------------------------------------------------------------
    def model(self) -> Model | None:
        """The model (None when it cannot be made); problems are in ``self.p``.  Warnings of
        implausible values are listed with their field paths (:meth:`check_plausible`)."""
        self.check_plausible()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", plausible.PlausibilityWarning)
            return self._model()

    def _model(self) -> Model | None:
        self.read_mesh()
        self.check_references()
        self.build_bodies()
        self.check_size()
        self.build_node_sets()
        spec, sets, p = self.spec, self.sets, self.p

        def have(*names: str | None) -> bool:
            return all(n is None or n in sets for n in names)

        supports = []
        for i, s in enumerate(spec.supports):
            if have(s.nodes):
                supports.append(Support(s.name or s.nodes, sets[s.nodes],
                                        _parse_dofs(s.dofs, f"supports[{i}].dofs")))
        ties = []
        for i, t in enumerate(spec.ties):
            if not have(t.a, t.b):
                continue
            if len(sets[t.a]) != len(sets[t.b]):
                p.add(
                    f"ties[{i}]",
                    f"node sets '{t.a}' ({len(sets[t.a])} nodes) and '{t.b}' ({len(sets[t.b])} "
                    "nodes) differ in size",
                )
                continue
            ties.append(Tie(t.name or f"{t.a}-{t.b}", sets[t.a], sets[t.b]))
        springs = []
        for i, s in enumerate(spec.springs):
            if not have(s.a, s.b):
                continue
            try:
                springs.append(Spring(
                    s.name or s.a, sets[s.a], None if s.b is None else sets[s.b], s.kx, s.ky,
                    k=s.k, direction=s.direction, damping=s.damping,
                ))
            except ModelError as e:  # e.g. a zero direction
                field = e.item.rpartition("'.")[2] if "'." in e.item else ""
                p.add(f"springs[{i}].{field}" if field else f"springs[{i}]", e.problem)
        obstacles: dict[str, RigidObstacle] = {}
        for i, ob in enumerate(spec.obstacles):
            try:
                obstacles[ob.name] = RigidObstacle(ob.name, ob.points, ob.side)
            except ModelError as e:
                field = e.item.rpartition("'.")[2] if "'." in e.item else ""
                p.add(f"obstacles[{i}].{field}" if field else f"obstacles[{i}]", e.problem)
        interfaces = []
        for i, itf in enumerate(spec.interfaces):
            if not have(itf.plus, itf.minus):
                continue
            if itf.obstacle is not None and itf.obstacle not in obstacles:
                continue
            try:
                interfaces.append(Interface(
                    itf.name,
                    sets[itf.plus],
                    sets[itf.minus] if itf.obstacle is None else obstacles[itf.obstacle],
                    friction=itf.friction,
                    gap=itf.gap,
                    normal=itf.normal,
                    layer=None if itf.layer is None else itf.layer.build(),
                    bond=None if itf.bond is None else itf.bond.build(),
                    pairs=itf.pairs,
                    area=itf.area,
                    cfe=itf.cfe,
                ))
            except ModelError as e:
                p.add(f"interfaces[{i}]", e.problem)
        patterns = []
        for pname, pat in spec.patterns.items():
            loads: list[object] = []
            for j, ld in enumerate(pat.loads):
                try:
                    self._load(ld, loads, interfaces, obstacles)
                except ModelError as e:  # e.g. a negative crack pressure
                    field = e.item.rpartition(".")[2] if "." in e.item else ""
                    path = _path(["patterns", pname, "loads", j])
                    p.add(f"{path}.{field}" if field else path, e.problem)
            patterns.append(LoadPattern(pname, tuple(loads)))
        program = [seg for s in spec.program for seg in _segments(s)]
        # stages whose names are wrong (reported) are left out: the model would repeat it
        pattern_names = {pt.name for pt in patterns}
        stages = (() if any(q.startswith("stages") for q, _ in p.items)
                  else self._stages(p, pattern_names))
        dynamics = self._dynamics(spec.dynamics, pattern_names, p)
        try:
            return Model(
                bodies=tuple(self.bodies.values()),
                plane=spec.model.plane,
                thickness=spec.model.thickness,
                supports=tuple(supports),
                ties=tuple(ties),
                springs=tuple(springs),
                interfaces=tuple(interfaces),
                patterns=tuple(patterns),
                program=tuple(program),
                name=spec.model.name or "model",
                dynamics=dynamics,
                stages=stages,
            )
        except ModelError as e:
            p.add(e.item, e.problem)
            return None

    def _load(self, ld: Any, loads: list, interfaces: list, obstacles: dict) -> None:
        """Append the load of the file's entry ``ld`` to ``loads`` (nothing where an item it
        needs is missing: that problem is reported already)."""
        if isinstance(ld, GravityLoad):
            loads.append(BodyForce(tuple(ld.g), tuple(ld.bodies)))
        elif isinstance(ld, UpliftLoadSpec):
            found = [i for i in interfaces if i.name == ld.interface]
            if found:
                loads.append(Uplift(found[0], ld.head, ld.pressure, ld.unit_weight))
        elif isinstance(ld, CrackWaterSpec):
            found = [i for i in interfaces if i.name == ld.interface]
            if found:
                loads.append(CrackWater(found[0], ld.level, ld.unit_weight,
                                        None if ld.entry is None else tuple(ld.entry),
                                        ld.pressure))
        elif isinstance(ld, ObstacleMotionLoad):
            if ld.obstacle in obstacles:
                loads.append(ObstacleMotion(obstacles[ld.obstacle], ld.dx, ld.dy,
                                            ld.rotation, ld.about))
        elif ld.nodes not in self.sets:
            return
        elif isinstance(ld, WaterLoadSpec):
            loads.append(WaterLoad(self.sets[ld.nodes], ld.level, ld.unit_weight))
        elif isinstance(ld, NodalLoadSpec):
            loads.append(NodalLoad(self.sets[ld.nodes], ld.fx, ld.fy, ld.mz))
        elif isinstance(ld, PressureLoad):
            loads.append(EdgeLoad(self.sets[ld.nodes], ld.normal, ld.tangential,
                                  None if ld.traction is None else tuple(ld.traction)))
        elif isinstance(ld, EdgeForceLoad):
            loads.append(EdgeForce(self.sets[ld.nodes], ld.fx, ld.fy))
        else:
            loads.append(PrescribedDisplacement(self.sets[ld.nodes], ld.dof, ld.value))

    def _stages(self, p: _Problems, pattern_names: set[str]) -> tuple[Stage, ...]:
        """The construction stages of the file (their names were checked by
        :meth:`check_stages`); a grout's bond that cannot be made is reported at its path."""
        stages = []
        for k, st in enumerate(self.spec.stages):
            grout = {}
            for name, bond in st.grout.items():
                path = _path(["stages", k, "grout", name])
                try:
                    grout[name] = built = bond.build()
                except ModelError as e:
                    p.add(path, e.problem)
                    continue
                for key in ("tensile", "shear"):  # constants; profiles: at validation
                    v = getattr(built, key)
                    if isinstance(v, int | float) and v < 0:
                        p.add(path, f"gives a {key} strength of {v:g} Pa: a strength must "
                              "be ≥ 0")
            try:
                stages.append(Stage(
                    st.name, tuple(seg for s in st.program for seg in _segments(s)),
                    tuple(st.bodies), tuple(st.interfaces), tuple(st.contacts),
                    tuple(st.supports), tuple(st.remove_supports), grout,
                    self._dynamics(st.dynamics, pattern_names, p, f"stages[{k}].dynamics")))
            except ModelError as e:  # reported by check_stages already, with its path
                p.add(f"stages[{k}]", e.problem)
        return tuple(stages)

    def _dynamics(self, spec, pattern_names: set[str], p, where: str = "dynamics"):
        """The dynamic interval of the file at ``where`` (``dynamics`` or
        ``stages[k].dynamics``; None without one)."""
        if spec is None:
            return None
        from stepcontact.fem.mass import rayleigh_coefficients
        from stepcontact.model import DynamicInterval
        from stepcontact.model.timefunction import Constant, Harmonic, Pulse, Tabulated

        loads = []
        for j, tf in enumerate(spec.loads):
            item = f"{where}.loads[{j}]"
            if tf.pattern not in pattern_names:
                p.add(f"{item}.pattern", f"unknown load pattern '{tf.pattern}' (known: "
                      f"{_known(pattern_names)})")
                continue
            try:
                if tf.type == "pulse":
                    g = Pulse(tf.amplitude, tf.start, tf.duration, tf.shape)
                elif tf.type == "harmonic":
                    g = Harmonic(tf.amplitude, tf.frequency, tf.phase, tf.start)
                elif tf.type == "constant":
                    g = Constant(tf.amplitude)
                elif tf.csv is not None:
                    path = Path(tf.csv)
                    if not path.is_absolute():
                        path = self.base / path
                    g = Tabulated.from_csv(path)
                else:
                    g = Tabulated(tuple(tf.times), tuple(tf.values or ()))
            except (ModelError, OSError) as e:
                p.add(item, getattr(e, "problem", str(e)))
                continue
            loads.append((tf.pattern, g))
        d = spec.damping
        try:
            damping = ((d.a0, d.a1) if d.ratios is None else rayleigh_coefficients(
                d.ratios[0], d.frequencies[0], d.ratios[1], d.frequencies[1])
                if d.frequencies is not None else None)
            if damping is None:
                p.add(f"{where}.damping", "ratios need their two frequencies (Hz)")
                return None
            return DynamicInterval(spec.dt, spec.duration, tuple(loads), spec.mass, damping,
                                   spec.restitution, spec.record_every, spec.alpha,
                                   spec.max_steps)
        except ModelError as e:
            item = e.item
            p.add(where + item[len("dynamics"):] if item.startswith("dynamics") else item,
                  e.problem)
            return None

    # ---- checks of ``validate`` -----------------------------------------------------------
    def _where(self, name: str) -> str:
        """``body 'x'`` or ``physical surface 'x'`` for messages."""
        s = self.surface_of.get(name)
        return f"physical surface '{s}'" if s is not None else f"body '{name}'"

    def check_geometry(self, model: Model) -> None:
        """Element quality, nodes in no element, bodies overlapping without an interface."""
        p = self.p
        continua = [b for b in model.bodies if isinstance(b, Body)]
        for b in continua:
            pts, cells = meshcheck.corners(b)
            q = meshcheck.quality(pts, cells)
            path = self.paths.get(b.name, f"body '{b.name}'")
            k = q.worst
            c = pts[cells[k]].mean(axis=0)
            at = f"centroid ({c[0]:.6g}, {c[1]:.6g})"
            if q.quality[k] <= 0:
                n = int(np.count_nonzero(q.quality <= 0))
                p.add(path, f"{self._where(b.name)} element {k} is inverted ({at}); "
                      f"{n} inverted element{'s' * (n > 1)}")
            elif q.quality[k] < meshcheck.QUALITY_WARN:
                n = int(np.count_nonzero(q.quality < meshcheck.QUALITY_WARN))
                p.warn(path, f"{self._where(b.name)} element {k} is nearly degenerate: quality "
                       f"{q.quality[k]:.3g} (1 is best), aspect ratio {q.aspect[k]:.3g}, {at}; "
                       f"{n} element{'s' * (n > 1)} below {meshcheck.QUALITY_WARN}")
            j = int(np.argmax(q.aspect))
            if q.aspect[j] > meshcheck.ASPECT_WARN:
                n = int(np.count_nonzero(q.aspect > meshcheck.ASPECT_WARN))
                c = pts[cells[j]].mean(axis=0)
                p.warn(path, f"{self._where(b.name)} element {j} is elongated: aspect ratio "
                       f"{q.aspect[j]:.3g}, quality {q.quality[j]:.3g}, centroid "
                       f"({c[0]:.6g}, {c[1]:.6g}); {n} element{'s' * (n > 1)} above "
                       f"{meshcheck.ASPECT_WARN:g}")
        cracked = {i.plus.body for i in model.interfaces
                   if i.plus.body == getattr(i.minus, "body", None)}
        for b in continua:
            if b.name in cracked:
                continue  # self-contact: coincident nodes are the two faces of a crack
            pts = np.asarray(b.points, dtype=float)
            tol = 1e-9 * max(float(np.ptp(pts, axis=0).max()), 1e-300)
            _, first, counts = np.unique(np.round(pts / tol), axis=0, return_index=True,
                                         return_counts=True)
            if np.any(counts > 1):
                k = int(first[np.argmax(counts > 1)])
                twins = np.flatnonzero(np.all(np.abs(pts - pts[k]) <= tol, axis=1))
                n = int(np.sum(counts[counts > 1] - 1))
                p.warn(self.paths.get(b.name, f"body '{b.name}'"),
                       f"{self._where(b.name)} has {n} duplicate node{'s' * (n > 1)} (e.g. nodes "
                       f"{', '.join(map(str, twins[:4]))} at ({pts[k, 0]:.6g}, {pts[k, 1]:.6g})): "
                       "elements that should share them are not connected")
        if self.mesh is not None:
            orphans = self.mesh.orphan_nodes()
            if orphans.size:
                x, y = self.mesh.points[orphans[0]]
                p.warn("mesh", f"{orphans.size} node{'s' * (orphans.size > 1)} of "
                       f"{self.mesh.path.name} belong to no element of a physical surface and "
                       f"are ignored (e.g. node {int(orphans[0])} at ({x:.6g}, {y:.6g}))")
        joined = {frozenset((i.plus.body, i.minus.body)) for i in model.interfaces
                  if isinstance(i.minus, NodeSet)}
        for ia, a in enumerate(continua):
            for b in continua[ia + 1:]:
                if frozenset((a.name, b.name)) in joined:
                    continue
                hit = meshcheck.overlap(a, b)
                inner, outer = (a, b) if hit is not None else (b, a)
                hit = hit if hit is not None else meshcheck.overlap(b, a)
                if hit is None:
                    continue
                (x, y), k = hit
                p.add(f"bodies '{a.name}' and '{b.name}'",
                      f"overlap without an interface: point ({x:.6g}, {y:.6g}) of "
                      f"{self._where(inner.name)} lies inside element {k} of "
                      f"{self._where(outer.name)}; join them with an [[interfaces]] entry or "
                      "fix the geometry")


def model_from_dict(d: dict[str, Any], base_dir: str | Path | None = None) -> Model:
    """Build a :class:`~stepcontact.model.Model` from the parsed contents of a model file.

    Parameters
    ----------
    d : dict
        The TOML document as a dict (what :func:`tomllib.load` returns).
    base_dir : path, optional
        Directory against which relative file names in the model (the mesh file) are
        resolved; default: the current directory.

    Raises
    ------
    ModelError
        Whose ``item`` is the field path of the first problem, e.g. ``bodies[1].material.E``;
        all problems are listed in the message and in its ``errors`` attribute.

    Example
    -------
    >>> import tomllib
    >>> from stepcontact.io.modelfile import model_from_dict
    >>> text = '''
    ... [materials.steel]
    ... E = 210e9
    ... nu = 0.3
    ... [[bodies]]
    ... name = "plate"
    ... corner0 = [0, 0]
    ... corner1 = [1, 1]
    ... nx = 2
    ... ny = 2
    ... material = "steel"
    ... [node_sets.bottom]
    ... body = "plate"
    ... y = 0
    ... [[supports]]
    ... nodes = "bottom"
    ... [patterns.push]
    ... loads = [{type = "nodal", nodes = "bottom", fx = 1e3}]
    ... [[program]]
    ... pattern = "push"
    ... end = 1
    ... '''
    >>> model_from_dict(tomllib.loads(text)).bodies[0].n_nodes
    9
    """
    spec = _validate(d)
    problems = _Problems()
    base = Path(base_dir) if base_dir is not None else Path.cwd()
    model = _Builder(spec, base, problems).model()
    problems.raise_if_any()
    assert model is not None
    for path, message in problems.warnings:  # deprecations, implausible values (validate
        # lists them too)
        category = problems.category.get((path, message), FutureWarning)
        warnings.warn(f"{path}: {message}", category, stacklevel=2)
    return model


def _read_toml(path: Path) -> dict[str, Any]:
    """The parsed TOML file; a missing file raises FileNotFoundError, anything else that is not
    a readable UTF-8 TOML file (a directory, a binary or UTF-16 file, bad syntax) a ModelError
    whose item is the file name."""
    if path.is_dir():
        raise ModelError(str(path), "is a directory, not a model file")
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise
    except OSError as e:
        raise ModelError(str(path), f"cannot be read: {e.strerror or e}") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        if data[:2] in (b"\xff\xfe", b"\xfe\xff"):
            raise ModelError(str(path), "is UTF-16 text: save it as UTF-8 (a model file is "
                             "TOML text in UTF-8)") from None
        raise ModelError(str(path), f"is not a UTF-8 text file (byte 0x{data[e.start]:02x} at "
                         f"offset {e.start}): a model file is TOML text in UTF-8") from None
    if "\x00" in text:
        raise ModelError(str(path), "not a text file (it contains NUL bytes): a model file is "
                         "TOML text in UTF-8")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ModelError(str(path), f"not a valid TOML file: {e}") from None


def load_model(path: str | Path) -> Model:
    """Read a TOML model file and build the :class:`~stepcontact.model.Model`.

    The model's name defaults to the file's stem when ``[model] name`` is not given; the mesh
    file of ``[mesh]`` is relative to the model file.

    Raises
    ------
    FileNotFoundError
        When the file does not exist.
    ModelError
        When the file is not valid TOML (``item`` is the file name) or the model is wrong
        (``item`` is the field path, e.g. ``interfaces[0].plus``).

    Example
    -------
    >>> from importlib.resources import files
    >>> from stepcontact.io.modelfile import load_model
    >>> model = load_model(files("stepcontact") / "data" / "demo.toml")
    >>> [itf.name for itf in model.interfaces]
    ['joint']
    """
    path = Path(str(path))
    d = _read_toml(path)
    model = model_from_dict(d, base_dir=path.parent)
    if not (d.get("model") or {}).get("name"):
        model = model.replace(name=path.stem)
    return model


# --------------------------------------------------------------------------------------------
# validation
# --------------------------------------------------------------------------------------------
@dataclass
class Validation:
    """What :func:`validation_report` found: every problem, and the model's size when it
    could be assembled."""

    path: Path
    problems: list[Problem] = field(default_factory=list)
    model: Model | None = None
    ndof: int | None = None
    n_cfes: int | None = None

    @property
    def errors(self) -> list[Problem]:
        return [p for p in self.problems if p.severity == "error"]

    @property
    def warnings(self) -> list[Problem]:
        return [p for p in self.problems if p.severity == "warning"]

    @property
    def ok(self) -> bool:
        return not self.errors

    def summary(self) -> dict[str, Any]:
        """Size of the model (what ``stepcontact validate --json`` prints)."""
        m = self.model
        if m is None:
            return {}
        return {
            "model": m.name,
            "bodies": len(m.bodies),
            "nodes": int(sum(b.n_nodes for b in m.bodies)),
            "elements": int(sum(len(b.cells) for b in m.bodies)),
            "dofs": self.ndof,
            "cfes": self.n_cfes,
            "interfaces": len(m.interfaces),
            "patterns": len(m.patterns),
            "segments": len(m.effective_program),
            "stages": len(m.stages),
        }


def validation_report(path: str | Path) -> Validation:
    """Check a model file and report *all* its problems (see :func:`validate_model_file`)."""
    path = Path(str(path))
    out = Validation(path)
    try:
        d = _read_toml(path)
    except FileNotFoundError:
        out.problems.append(Problem(str(path), "file not found"))
        return out
    except ModelError as e:
        out.problems.append(Problem(e.item, e.problem))
        return out
    try:
        spec = _validate(d)
    except ModelError as e:
        out.problems = [Problem(p, m) for p, m in getattr(e, "errors", [(e.item, e.problem)])]
        return out
    problems = _Problems()
    builder = _Builder(spec, path.parent, problems)
    model = builder.model()
    if model is not None:
        if not spec.model.name:
            model = model.replace(name=path.stem)
        builder.check_geometry(model)
        out.model = model
    if model is not None and not problems.items:
        from stepcontact.fem.assembly import assemble

        try:
            system = assemble(model)
            model.segments_resolved()
            from stepcontact.model.consistency import check_consistency, program_warnings

            check_consistency(model)  # what run refuses, seen in the model itself
            for item, text in program_warnings(model):
                problems.warn(item, text)
            out.ndof, out.n_cfes = int(system.dofs.ndof), int(system.cfe.m)
            from stepcontact.fem.loadcheck import zero_patterns

            for name, text in zero_patterns(model, system.loads):
                problems.warn(f"patterns.{name}", text)
            if model.stages:  # what a run checks of the stages before solving
                from stepcontact.solver.staging import StagePlan

                plan = StagePlan(system)
                for k in range(len(model.stages)):  # grout strengths at the joints' CFEs
                    plan.grout_stage(k)
            _check_mechanism(system)
            dyn_stages = [st.name for st in model.stages if st.dynamics is not None]
            if model.dynamics is not None or dyn_stages:  # mass for the dynamic interval
                from stepcontact.fem.mass import check_mass

                check_mass(system, "dynamics" if not dyn_stages else
                           f"stage '{dyn_stages[0]}'.dynamics")
        except StepContactError as e:
            problems.add(getattr(e, "item", "model"), getattr(e, "problem", str(e)))
    out.problems = problems.problems()
    return out


def _check_mechanism(system: Any) -> None:
    """What ``run`` checks first, without solving the contact problem: K₀ (the stiffness with
    the supports and every CFE stuck) is regular; else a ModelError naming the bodies that can
    move and how (:func:`stepcontact.solver.regularity.factorize_regular`)."""
    from stepcontact.solver.condensation import check_dense_memory, static_operator
    from stepcontact.solver.regularity import factorize_regular

    check_dense_memory(2 * system.m)  # the dense contact matrices fit (SolverError if not)
    K0, _, _, free, *_ = static_operator(system)
    factorize_regular(system, K0, free)


def validate_model_file(path: str | Path) -> list[Problem]:
    """Every problem of a model file at once, each naming its field or physical group.

    Checks the TOML syntax and the schema, unknown names (materials, bodies, node sets,
    physical groups, patterns), that every physical surface of the mesh is a body with a
    material, element quality (inverted elements are errors; nearly degenerate or elongated
    ones warnings, with the worst element's index, quality and aspect ratio), mesh nodes that
    belong to no element (warning), duplicate nodes of a body (warning), bodies that overlap
    without an interface between them, that the model assembles, that no load pattern is
    empty or zero (warning), and, without solving, what ``run`` checks first: that the dense
    contact matrices fit in memory and that the structure with every CFE stuck is not a
    mechanism (the error names the bodies that can move).  An empty list means the model is
    OK.

    Example
    -------
    >>> from importlib.resources import files
    >>> from stepcontact.io.modelfile import validate_model_file
    >>> validate_model_file(files("stepcontact") / "data" / "demo.toml")
    []
    """
    return validation_report(path).problems


def schema() -> dict[str, Any]:
    """The JSON schema of the model file format (a dict, ready for :func:`json.dumps`)."""
    return ModelFile.model_json_schema()


__all__ = [
    "ModelFile",
    "Problem",
    "Validation",
    "load_model",
    "model_from_dict",
    "schema",
    "validate_model_file",
    "validation_report",
]
