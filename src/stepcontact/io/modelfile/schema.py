"""The schema of a model file: one pydantic model per table (unknown keys, wrong types,
NaN/inf and out-of-range values are rejected).

The schema checks types and the shape of each table; the allowed kinds (elements, planes, CFE
kinds, mass matrices, pulse shapes, ...) and ranges (Poisson's ratio, Young's modulus, HHT-α,
restitution, friction angle) are the model's constants (:mod:`stepcontact.model.items`,
:mod:`~stepcontact.model.timefunction`, :mod:`~stepcontact.model.bond`), and a rule the
model's dataclasses own (the forms of a contact layer, of an uplift, ...) is asked of them,
so that each rule is written once.  :func:`schema` gives the JSON schema.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal, Union

from pydantic import (
    BaseModel,
    ConfigDict,
    Discriminator,
    Field,
    NonNegativeInt,
    PlainValidator,
    Tag,
    WithJsonSchema,
    field_validator,
    model_validator,
)

from stepcontact.enums import MAX_FACETS
from stepcontact.errors import ModelError
from stepcontact.io.modelfile.dam import DamSpec
from stepcontact.model.bodies import SolidKind
from stepcontact.model.bond import FRICTION_ANGLE_RANGE, Bond
from stepcontact.model.items import (
    NU_RANGE,
    CfeKind,
    ContactLayer,
    ElementKind,
    Interface,
    Material,
    PlaneKind,
    _parse_dofs,
    modulus_problem,
)
from stepcontact.model.mesh import (
    CYLINDER_MIN_AROUND,
    HALF_DISC_MIN_AROUND,
    SIZE_RATIO_MIN,
    cells_problem,
    corners_problem,
    grading_problem,
)
from stepcontact.model.obstacle import ObstacleSide
from stepcontact.model.records import RecordFormat, RecordUnits
from stepcontact.model.structure import CrackWaterChoice
from stepcontact.model.supports import _ALL_DOFS as ALL_DOFS
from stepcontact.model.timefunction import HHT_ALPHA_RANGE, RESTITUTION_RANGE, MassKind, PulseShape
from stepcontact.model.water import CrackWater, LinearProfile, Uplift

# tags of the discriminated unions; they appear in pydantic's error locations and are removed
# from the field paths shown to the user
_TAGS = {
    "kind=rectangle",
    "kind=mesh",
    "kind=quad",
    "kind=half_disc",
    "kind=polygon",
    "kind=box",
    "kind=extrude",
    "kind=cylinder",
    "kind=spherical_block",
    "kind=line",
    "kind=plane",
    "type=gravity",
    "type=nodal",
    "type=pressure",
    "type=edge_force",
    "type=water",
    "type=uplift",
    "type=crack_water",
    "type=displacement",
    "type=obstacle_motion",
    "type=seismic",
    "material=name",
    "material=table",
}


class _Spec(BaseModel):
    """Base of every table of the file: unknown keys and NaN/inf are errors."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, frozen=True)


Point = tuple[float, float]
#: a point or vector in space (3D bodies: x, y, z with z up)
Point3 = tuple[float, float, float]


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
        if (text := grading_problem(v)) is not None:
            raise ValueError(text)
        return v

    @model_validator(mode="after")
    def _non_empty(self) -> RectangleSpec:
        if (text := corners_problem(self.corner0, self.corner1)) is not None:
            raise ValueError(text)
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
    n_around: int = Field(ge=HALF_DISC_MIN_AROUND, description="cells along the arc (even)")
    element: ElementKind = Field(
        "quad4", description="element kind (linear or quadratic triangles and quads)")
    refine: bool = Field(True, description="cells shrinking towards the lowest point")
    ratio: float = Field(8.0, ge=SIZE_RATIO_MIN,
                         description="largest / smallest cell when refined")
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
        if (text := cells_problem(self.n, self.size)) is not None:
            raise ValueError(text)
        return self


class BoxBodySpec(_Spec):
    """``[[bodies]]`` with ``kind = "box"``: a 3D box [x0, x1] × [y0, y1] × [z0, z1] (z up)
    meshed nx × ny × nz with tetrahedra or hexahedra (:func:`stepcontact.box`); its faces are
    the named boundaries ``left``/``right`` (x min/max), ``front``/``back`` (y min/max),
    ``bottom``/``top`` (z min/max) that node sets select with ``boundary = "top"``."""

    name: str = Field(description="unique body name")
    kind: Literal["box"]
    corner0: Point3 = Field(description="corner (x0, y0, z0) with the smallest coordinates, m")
    corner1: Point3 = Field(description="opposite corner (x1, y1, z1), m")
    nx: int = Field(ge=1, description="cells along x")
    ny: int = Field(ge=1, description="cells along y")
    nz: int = Field(ge=1, description="cells along z")
    element: SolidKind = Field("hex8", description="tet4, tet10, hex8, hex20 (serendipity) or "
                               "hex27")
    material: MaterialRef = Field(description="a material name from `[materials.NAME]`, or "
                                  "an inline table `{E, nu, density}`")

    @model_validator(mode="after")
    def _non_empty(self) -> BoxBodySpec:
        if not all(b > a for a, b in zip(self.corner0, self.corner1, strict=True)):
            raise ValueError("corner1 must exceed corner0 in x, y and z")
        return self


class CylinderSpec(_Spec):
    """``[[bodies]]`` with ``kind = "cylinder"``: a circular cylinder with its axis along z,
    the base centred at ``centre``, meshed with ``n = [n_around, n_radial, n_height]`` cells
    (:func:`stepcontact.cylinder`: an O-grid swept along z); its named boundaries are
    ``bottom``, ``top`` and ``side``."""

    name: str = Field(description="unique body name")
    kind: Literal["cylinder"]
    centre: Point3 = Field(description="centre of the base (x, y, z), m")
    radius: float = Field(gt=0, description="radius, m")
    height: float = Field(gt=0, description="height along z, m")
    n: tuple[int, int, int] = Field(description="cells [n_around (a multiple of 4, ≥ "
                                    f"{CYLINDER_MIN_AROUND}), n_radial, n_height]")
    element: SolidKind = Field("hex8", description="tet4, tet10, hex8, hex20 or hex27")
    material: MaterialRef = Field(description="a material name from `[materials.NAME]`, or "
                                  "an inline table `{E, nu, density}`")

    @field_validator("n")
    @classmethod
    def _counts(cls, v: tuple[int, int, int]) -> tuple[int, int, int]:
        if v[0] < CYLINDER_MIN_AROUND or v[0] % 4:
            raise ValueError(f"n_around = {v[0]}: the cells around must be a multiple of 4, "
                             f"at least {CYLINDER_MIN_AROUND}")
        if min(v[1:]) < 1:
            raise ValueError("n_radial and n_height must be at least 1")
        return v


class SphericalBlockSpec(_Spec):
    """``[[bodies]]`` with ``kind = "spherical_block"``: a block over [x0, x1] × [y0, y1]
    whose bottom is the sphere of ``radius`` resting on z = 0 at the origin and whose top is
    the plane z = ``top`` (:func:`stepcontact.model.mesh.spherical_block`, Hertz contact); its
    faces are named as a box's (``bottom`` the spherical face)."""

    name: str = Field(description="unique body name")
    kind: Literal["spherical_block"]
    radius: float = Field(gt=0, description="radius R of the sphere, m")
    xs: list[float] = Field(min_length=2, description="grid lines along x, m (increasing)")
    ys: list[float] = Field(min_length=2, description="grid lines along y, m (increasing)")
    top: float = Field(description="height of the flat top, m")
    layers: int | list[float] = Field(description="layers through the thickness: a number "
                                      "of uniform layers, or fractions from 0 (the sphere) "
                                      "to 1 (the top)")
    element: SolidKind = Field("hex8", description="tet4, tet10, hex8, hex20 or hex27")
    material: MaterialRef = Field(description="a material name from `[materials.NAME]`, or "
                                  "an inline table `{E, nu, density}`")


def _section_tag(v: Any) -> str | None:
    if isinstance(v, dict):
        kind = v.get("kind", "rectangle")
        return f"kind={kind}" if kind in ("rectangle", "quad", "half_disc", "polygon") else None
    if isinstance(v, RectangleSpec | QuadRegionSpec | HalfDiscSpec | PolygonSpec):
        return f"kind={v.kind}"
    return None


#: the section of an extruded body: a 2D body table of the generators
SectionSpec = _tagged_union(
    _section_tag, "section_kind", "kind must be 'rectangle', 'quad', 'half_disc' or 'polygon'",
    **{"kind=rectangle": RectangleSpec, "kind=quad": QuadRegionSpec,
       "kind=half_disc": HalfDiscSpec, "kind=polygon": PolygonSpec},
)
#: the material a section is validated with (the extruded body's own ``material`` is used)
_SECTION_MATERIAL = {"E": 1.0e9, "nu": 0.0}


class ExtrudeSpec(_Spec):
    """``[[bodies]]`` with ``kind = "extrude"``: a prismatic 3D body, a 2D section (the table of
    a ``rectangle``, ``quad``, ``polygon`` or ``half_disc`` body, without name and material)
    swept along z from ``z[0]`` to ``z[1]`` in ``nz`` layers (:func:`stepcontact.extrude`):
    quadrilaterals become hexahedra (quad4/8/9 → hex8/20/27), triangles tetrahedra (tri3/6 →
    tet4/10); its end faces are the named boundaries ``start`` and ``end``.  The section keeps
    its axes (with y up, give gravity as g = [0, -9.81, 0])."""

    name: str = Field(description="unique body name")
    kind: Literal["extrude"]
    section: SectionSpec = Field(description="the 2D section: {kind = \"rectangle\", corner0, "
                                 "corner1, nx, ny, element}, or a quad, polygon or half_disc")
    z: tuple[float, float] = Field(description="[z0, z1], m (z1 > z0)")
    nz: int = Field(ge=1, description="layers of cells along z")
    material: MaterialRef = Field(description="a material name from `[materials.NAME]`, or "
                                  "an inline table `{E, nu, density}`")

    @model_validator(mode="before")
    @classmethod
    def _section_of_the_body(cls, v: Any) -> Any:
        if isinstance(v, dict) and isinstance(v.get("section"), dict):
            sec = dict(v["section"])
            given = [k for k in ("name", "material") if k in sec]
            if given:
                raise ValueError(f"give {given[0]} on the extruded body, not in its section")
            v = {**v, "section": {**sec, "name": str(v.get("name", "section")),
                                  "material": _SECTION_MATERIAL}}
        return v

    @model_validator(mode="after")
    def _layers(self) -> ExtrudeSpec:
        if not self.z[1] > self.z[0]:
            raise ValueError("z = [z0, z1] needs z1 > z0")
        return self


class MeshBodySpec(_Spec):
    """``[[bodies]]`` with ``kind = "mesh"``: the cells of one physical surface of ``[mesh]``
    (of one physical volume in a 3D mesh).

    ``group`` is the physical surface or volume (default: ``name``); ``name`` defaults to
    ``group``.  ``element`` defaults to the kind of the cells (tri3, tri6, quad4, quad8, quad9;
    3D: tet4, tet10, hex8, hex20, hex27); a linear mesh may use the quadratic element of its
    shape.  ``material`` is required (a missing one
    is reported with the other problems of the file).
    """

    mesh: str | None = Field(None, description="not here: the mesh file goes in [mesh] file")
    kind: Literal["mesh"] = "mesh"
    name: str | None = None
    group: str | None = Field(None, description="physical surface, or physical volume of a "
                              "3D mesh (default: name)")
    element: ElementKind | SolidKind | None = None
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
        return (f"kind={kind}" if kind in ("rectangle", "mesh", "quad", "half_disc", "polygon",
                                           "box", "extrude", "cylinder", "spherical_block")
                else None)
    if isinstance(v, RectangleSpec | MeshBodySpec | QuadRegionSpec | HalfDiscSpec
                  | PolygonSpec | BoxBodySpec | ExtrudeSpec | CylinderSpec
                  | SphericalBlockSpec):
        return f"kind={v.kind}"
    return None


BodySpec = _tagged_union(
    _body_tag, "body_kind",
    "kind must be 'rectangle', 'quad', 'half_disc', 'polygon', 'box', 'extrude', 'cylinder', "
    "'spherical_block' or 'mesh'",
    **{"kind=rectangle": RectangleSpec, "kind=quad": QuadRegionSpec,
       "kind=half_disc": HalfDiscSpec, "kind=polygon": PolygonSpec, "kind=box": BoxBodySpec,
       "kind=extrude": ExtrudeSpec, "kind=cylinder": CylinderSpec,
       "kind=spherical_block": SphericalBlockSpec, "kind=mesh": MeshBodySpec},
)


def _body_name(b: RectangleSpec | MeshBodySpec | QuadRegionSpec | HalfDiscSpec
               | PolygonSpec | BoxBodySpec | ExtrudeSpec | CylinderSpec
               | SphericalBlockSpec) -> str:
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
    """``[[frames]]``: a straight Euler–Bernoulli frame from ``start`` to ``end``: a plane
    frame (2D points; E, A, I) or a space frame (3D points, 6 DOFs per node; E, A, Iy, Iz
    (default I), J, and G or nu; ``orientation`` a vector in the bars' local x'–y' plane,
    default the global z, or x for a bar along z) (:class:`stepcontact.Frame`)."""

    name: str
    kind: Literal["line"] = "line"
    start: Point | Point3 = Field(description="first node, m: (x, y), or (x, y, z) for a "
                                  "space frame")
    end: Point | Point3 = Field(description="last node, m")
    n: int = Field(ge=1, description="number of elements")
    E: float = Field(gt=0, description="Young's modulus, Pa")
    A: float = Field(gt=0, description="cross-section area, m²")
    I: float | None = Field(None, gt=0, description="second moment of area, m⁴ (a space "
                            "frame: the default of Iy and Iz)")
    density: float = Field(0.0, ge=0, description="kg/m³")
    Iy: float | None = Field(None, gt=0, description="space frames: second moment about the "
                             "local y' axis, m⁴")
    Iz: float | None = Field(None, gt=0, description="space frames: second moment about the "
                             "local z' axis, m⁴")
    J: float | None = Field(None, gt=0, description="space frames: torsion constant, m⁴")
    G: float | None = Field(None, gt=0, description="space frames: shear modulus, Pa (or nu)")
    nu: float | None = Field(None, gt=NU_RANGE[0], lt=NU_RANGE[1],
                             description="space frames: Poisson's ratio, G = E / (2 (1 + ν))")
    orientation: Point3 | None = Field(None, description="space frames: a vector in the bars' "
                                       "local x'–y' plane (not along the bar)")

    @model_validator(mode="after")
    def _one_dimension(self) -> FrameSpec:
        if len(self.start) != len(self.end):
            raise ValueError(f"start has {len(self.start)} coordinates and end "
                             f"{len(self.end)}: give both as (x, y) or both as (x, y, z)")
        return self

    @property
    def section(self) -> dict[str, Any]:
        """The space-frame options given (Iy, Iz, J, G, nu, orientation)."""
        return {k: getattr(self, k) for k in ("Iy", "Iz", "J", "G", "nu", "orientation")
                if getattr(self, k) is not None}


# --------------------------------------------------------------------------------------------
# node sets, supports, ties, springs, interfaces
# --------------------------------------------------------------------------------------------
class BoxSpec(_Spec):
    """``where = {xmin, xmax, ymin, ymax}`` (and ``zmin``, ``zmax`` on a 3D body): nodes
    inside the box (bounds inclusive, m)."""

    xmin: float | None = None
    xmax: float | None = None
    ymin: float | None = None
    ymax: float | None = None
    zmin: float | None = Field(None, description="3D bodies only, m")
    zmax: float | None = Field(None, description="3D bodies only, m")


class NodeSetSpec(_Spec):
    """``[node_sets.NAME]``: nodes of one body (or frame) by coordinate, box or index, or the
    nodes of a physical curve or point of ``[mesh]`` (``group``; ``body`` is then needed only
    for a curve shared by two conforming bodies)."""

    body: str | None = None
    group: str | None = Field(None, description="physical curve or point of [mesh]")
    x: float | None = Field(None, description="nodes with this x, m")
    y: float | None = Field(None, description="nodes with this y, m")
    z: float | None = Field(None, description="nodes with this z, m (3D bodies)")
    where: BoxSpec | None = None
    index: list[NonNegativeInt] | None = Field(None, description="local node indices")
    boundary: bool | str = Field(True, description="only nodes on the body's boundary (true), "
                                 "every node (false), or the nodes of a named boundary of "
                                 "its mesh, e.g. \"top\" of a box")

    @model_validator(mode="after")
    def _index_alone(self) -> NodeSetSpec:
        by_coord = (self.x is not None or self.y is not None or self.z is not None
                    or self.where is not None)
        if self.group is not None and (by_coord or self.index is not None):
            raise ValueError("give either group or x / y / where / index, not both")
        if self.group is None and self.body is None:
            raise ValueError("give body (with x / y / where / index) or group")
        if self.index is not None and (by_coord or isinstance(self.boundary, str)):
            raise ValueError("give either index or x / y / z / where / boundary, not both")
        return self


def _check_dofs(v: str) -> str:
    try:
        _parse_dofs(v, "dofs", ALL_DOFS)
    except ModelError as e:
        raise ValueError(e.problem) from None
    return v


class SupportSpec(_Spec):
    """``[[supports]]``: fixed degrees of freedom ("xy", "x", "y", "rz", "xyrz"; on 3D bodies
    any of "x", "y", "z", e.g. "xyz") of a node set."""

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
    """``[[obstacles]]``: a rigid line or polyline (not meshed) that 2D bodies may touch; an
    interface uses it with ``obstacle = "NAME"`` instead of ``minus``."""

    name: str
    kind: Literal["line"] = "line"
    points: list[Point] = Field(min_length=2, description="vertices [[x0, y0], [x1, y1], …], m")
    side: ObstacleSide = Field(
        "left", description="side the bodies lie on, walking from the first point to the last "
        "(left: a line drawn from left to right carries bodies above it)")


class PlaneObstacleSpec(_Spec):
    """``[[obstacles]]`` with ``kind = "plane"``: a fixed rigid plane that 3D bodies may touch
    (:class:`stepcontact.RigidPlane`); an interface uses it with ``obstacle = "NAME"``."""

    name: str
    kind: Literal["plane"]
    point: Point3 = Field(description="a point of the plane (x, y, z), m")
    normal: Point3 = Field((0.0, 0.0, 1.0), description="normal pointing towards the bodies "
                           "(need not be unit; default +z: bodies above the plane)")

    @field_validator("normal")
    @classmethod
    def _nonzero(cls, v: Point3) -> Point3:
        if not any(v):
            raise ValueError("is the zero vector")
        return v


def _obstacle_tag(v: Any) -> str | None:
    kind = v.get("kind", "line") if isinstance(v, dict) else getattr(v, "kind", None)
    return f"kind={kind}" if kind in ("line", "plane") else None


AnyObstacleSpec = _tagged_union(
    _obstacle_tag, "obstacle_kind", "kind must be 'line' (2D, the default) or 'plane' (3D)",
    **{"kind=line": ObstacleSpec, "kind=plane": PlaneObstacleSpec},
)


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
    normal: Point | Point3 | None = Field(None, description="unit normal from S− to S+ "
                                         "((nx, ny), or (nx, ny, nz) in 3D)")
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
    facets: int | None = Field(None, ge=3, le=MAX_FACETS, description="3D: the number k of "
                               "facets of the faceted Coulomb cone, inscribed in the disc "
                               "|Q| ≤ f|N| (default 8; all interfaces of a model share one k)")
    facet_angle: float = Field(0.0, description="3D: direction of the polygon's vertex 0 "
                               "from t1 towards t2, rad (pi/k puts a facet's middle along t1)")
    axis: Point3 | None = Field(None, description="3D: direction of each CFE's first tangent "
                                "t1 (projected on the plane normal to n); default: the global "
                                "axis along which n has its smallest component (+x for a "
                                "horizontal joint)")

    @field_validator("axis")
    @classmethod
    def _axis_nonzero(cls, v: Point3 | None) -> Point3 | None:
        if v is not None and not any(v):
            raise ValueError("is the zero vector: give the direction of t1")
        return v

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
    g: list[float] | None = Field(
        None, min_length=2, max_length=3, description="acceleration (gx, gy) in 2D or (gx, gy, "
        "gz) in 3D, m/s²; default: 9.81 m/s² downwards, along −y in 2D, along −z on 3D bodies")
    bodies: list[str] = []


class NodalLoadSpec(_Spec):
    """The same force on every node of a node set: fx, fy (and fz on 3D bodies) in N, mz in
    N·m (n nodes: n times the force in all; for a total force along an edge or over faces use
    ``edge_force``)."""

    type: Literal["nodal"] = "nodal"
    nodes: str
    fx: float = 0.0
    fy: float = 0.0
    fz: float = Field(0.0, description="N, along z (3D bodies)")
    mz: float = Field(0.0, description="N·m, about z (frames)")
    mx: float = Field(0.0, description="N·m, about x (space frames)")
    my: float = Field(0.0, description="N·m, about y (space frames)")


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
    """A total force (fx, fy in N; and fz on 3D bodies) spread as a uniform traction along the
    body edges (3D: over the boundary faces) in a node set (consistent nodal forces: they sum
    to exactly (fx, fy[, fz]))."""

    type: Literal["edge_force"] = "edge_force"
    nodes: str
    fx: float = 0.0
    fy: float = 0.0
    fz: float = Field(0.0, description="N, along z (3D bodies)")


class WaterLoadSpec(_Spec):
    """Hydrostatic pressure p = unit_weight · max(level − y, 0) (Pa) on the body edges in a
    node set, pushing into the body; exact where the level cuts an edge.  On 3D bodies
    (z up) p = unit_weight · max(level − z, 0) on the faces, exact where the level cuts a
    face."""

    type: Literal["water"] = "water"
    nodes: str
    level: float | None = Field(None, description="elevation of the free surface, m (y is "
                                "up; z on 3D bodies); omitted: the pattern's factor is the "
                                "level, m, and its "
                                "program segments raise or lower the water (exact events in "
                                "the level); such a pattern holds only water loads without "
                                "a level")
    unit_weight: float = Field(9810.0, gt=0, description="unit weight of water γ_w, N/m³")


class DrainedSpec(_Spec):
    """The guidelines' bilinear uplift with a line of drains (:meth:`Uplift.drained`): the
    full head at the heel, h_down + (1 − E)(h_up − h_down)·r at the drains, the tailwater's
    head at the toe."""

    heel: Point = Field(description="the heel (x, y), m: the full head head_up")
    toe: Point = Field(description="the toe (x, y), m: the tailwater's head head_down")
    drain: Point = Field(description="where the drain line meets the joint (x, y), m")
    efficiency: float = Field(ge=0, le=1, description="drain efficiency E, 0 … 1")
    head_up: float = Field(1.0, description="pressure head at the heel, m of water (1: per "
                           "metre of level, when the pattern's factor is the level)")
    head_down: float = Field(0.0, description="pressure head at the toe (tailwater), m")
    reference: Literal["line", "tailwater"] = Field(
        "line", description="line: the drains reduce the heel–toe line's head at the drains, "
        "r = (L − X)/L; tailwater: the full head difference, r = 1 (USBR's h/3 is E = 2/3)")


class UpliftLoadSpec(_Spec):
    """Uplift in a joint: the pressure pushes the S+ and S− bodies of ``interface`` apart."""

    type: Literal["uplift"] = "uplift"
    interface: str
    head: Profile | None = Field(None, description="pressure head, m of water")
    pressure: Profile | None = Field(None, description="pressure, Pa")
    unit_weight: float = Field(9810.0, gt=0, description="unit weight of water γ_w, N/m³")
    through: Literal["faces", "cfes"] | None = Field(
        None, description="faces: integrated over each face's mesh; cfes: A_k p(x_k) across "
        "each CFE (exact effective stress on non-matching meshes); default faces in 2D, cfes "
        "in 3D (the only way in 3D, p at each CFE's plan position (x, y))")
    drained: DrainedSpec | None = Field(
        None, description="the bilinear uplift of a line of drains, instead of head or "
        "pressure (heel, toe, drain, efficiency, head_up, head_down, reference)")

    @model_validator(mode="after")
    def _one(self) -> UpliftLoadSpec:
        if self.drained is not None:
            if self.head is not None or self.pressure is not None:
                raise ValueError("give drained, or head or pressure, not both")
            return self
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
    entry: Point | list[Point] | Point3 | list[Point3] | list[list[Point3]] | None = Field(
        None, description="where the water reaches the joint (the heel), m, or a list of such "
        "points: only open CFEs joined to one by open CFEs are wet; omitted: every open CFE. "
        "A 3D joint takes (x, y, z) points: a point, a polyline along the upstream edge, or a "
        "list of polylines (the entry CFEs are the row along each)")
    bridge: float = Field(0.0, ge=0, description="m (2D, with an entry): closed CFEs within "
                          "this distance of the entry, not bonded, do not cut the crack from "
                          "the reservoir (the singular heel); 0: only open CFEs conduct water")
    rule: Literal["connected", "em1110"] = Field(
        "connected", description="the uplift beyond the crack's tip (2D, with an entry): "
        "connected: the given uplift; em1110: linear from the tip's pressure to the toe's, "
        "through the drained head while the crack has not reached the drains (USACE "
        "EM 1110-2-2100)")

    @model_validator(mode="after")
    def _level_or_pressure(self) -> CrackWaterSpec:
        if (text := CrackWater.form_problem(self.level, self.pressure)) is not None:
            raise ValueError(text)
        return self


class DisplacementLoad(_Spec):
    """Prescribed displacement ``value`` (m, or rad for rz) of ``dof`` of a node set."""

    type: Literal["displacement"] = "displacement"
    nodes: str
    dof: Literal[ALL_DOFS] = Field(  # type: ignore[valid-type]  # the model's DOF names
        description="x, y, rz (2D) or x, y, z (3D bodies)")
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


class AddedMassSpec(_Spec):
    """``[[added_masses]]`` (and a seismic load's ``reservoir``): Westergaard's added mass of
    a reservoir on the body edges in a node set, m_a = 7/8 · density · √(H (level − y))
    (kg/m², H = level − bottom) along the edges' normal (Kuo 1982), lumped on their nodes;
    in a dynamic interval it is part of the mass matrix (2D bodies)."""

    nodes: str = Field(description="the upstream face (a node set on a body's boundary)")
    level: float = Field(description="elevation of the free surface, m (y up)")
    bottom: float | None = Field(None, description="elevation of the reservoir bottom at the "
                                 "face, m (default: the face's lowest point)")
    density: float = Field(1000.0, gt=0, description="density of water ρ_w, kg/m³")


class SeismicLoadSpec(_Spec):
    """Pseudo-static seismic coefficients per unit factor: the body force ρ g (k_h ·
    direction, k_v) on ``bodies`` (all when empty; k_v > 0 upwards) and the added mass of each
    ``reservoir`` times the same acceleration (Westergaard's pressure 7/8 k_h γ_w √(H z) on a
    vertical face).  With k_h = 1 the pattern's factor is k_h: a segment of it locates the
    yield acceleration (``equilibrium_lost``)."""

    type: Literal["seismic"] = "seismic"
    k_h: float = Field(1.0, description="horizontal seismic coefficient per unit factor (g)")
    k_v: float = Field(0.0, description="vertical seismic coefficient per unit factor (g), "
                       "inertia upwards when positive")
    bodies: list[str] = Field([], description="the bodies the inertia acts on (all when "
                              "empty)")
    reservoir: list[AddedMassSpec] = Field([], description="reservoirs whose hydrodynamic "
                                           "force acts with the coefficients (the tables of "
                                           "`[[added_masses]]`)")
    direction: Literal[1, -1] = Field(1, description="+1: the horizontal inertia along +x "
                                      "(downstream with the reservoir on the left), −1: "
                                      "along −x")
    g: float = Field(9.81, gt=0, description="acceleration of gravity, m/s²")


def _load_tag(v: Any) -> str | None:
    t = v.get("type") if isinstance(v, dict) else getattr(v, "type", None)
    return (f"type={t}" if t in ("gravity", "nodal", "edge_force", "pressure", "displacement",
                                 "water", "uplift", "crack_water", "obstacle_motion",
                                 "seismic")
            else None)


LoadSpec = _tagged_union(
    _load_tag, "load_type",
    "type must be 'gravity', 'nodal', 'edge_force', 'pressure', 'water', 'uplift', "
    "'crack_water', 'displacement', 'obstacle_motion' or 'seismic'",
    **{"type=gravity": GravityLoad, "type=nodal": NodalLoadSpec,
       "type=edge_force": EdgeForceLoad, "type=pressure": PressureLoad,
       "type=displacement": DisplacementLoad,
       "type=water": WaterLoadSpec, "type=uplift": UpliftLoadSpec,
       "type=crack_water": CrackWaterSpec, "type=obstacle_motion": ObstacleMotionLoad,
       "type=seismic": SeismicLoadSpec},
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


class GroundMotionSpec(_Spec):
    """``[[dynamics.ground_motion]]``: an earthquake record applied as the ground acceleration
    (:class:`~stepcontact.model.records.AccelerationRecord`): a positive value accelerates the
    ground along +axis; the displacements reported are relative to the ground.  The records
    of one interval act together, one per axis (horizontal x with vertical y in 2D; x, y, z in
    3D)."""

    file: str = Field(description="the record file, relative to the model file")
    format: RecordFormat | None = Field(None, description="at2 (PEER NGA, in g; the default "
                                        "for a .AT2 file), two_column (time, value) or "
                                        "one_column (values, with dt)")
    units: RecordUnits | None = Field(None, description="units of a text file's values "
                                      "(required for two_column and one_column; an AT2 file "
                                      "is in g); g = 9.80665 m/s²")
    dt: float | None = Field(None, gt=0, description="time step of a one_column file, s")
    scale: float | None = Field(None, gt=0, description="factor on the record's values")
    target_pga: float | None = Field(None, gt=0, description="scale the record to this peak "
                                     "ground acceleration, m/s²")
    target_pga_g: float | None = Field(None, gt=0, description="scale the record to this peak "
                                       "ground acceleration, in g")
    polarity: Literal[1, -1] = Field(1, description="-1 flips the record's sign")
    axis: Literal["x", "y", "z"] = Field("x", description="the axis the ground accelerates "
                                         "along (y is vertical in 2D, z in 3D)")

    @model_validator(mode="after")
    def _one_scale(self) -> GroundMotionSpec:
        given = [k for k in ("scale", "target_pga", "target_pga_g")
                 if getattr(self, k) is not None]
        if len(given) > 1:
            raise ValueError(f"give one of scale, target_pga and target_pga_g, not "
                             f"{' and '.join(given)}")
        return self


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
    crack_water: CrackWaterChoice = Field(
        "full", description="water in the opened joints during the interval: full (enters "
        "every connected opening at its crack pressure), unchanged (the pre-earthquake wet set "
        "and pressures held) or none (held, and no pressure in the joints opened during it)")
    loads: list[TimeFunctionSpec] = []
    ground_motion: list[GroundMotionSpec] = Field([], description="earthquake records applied "
                                                  "together as the ground acceleration, one "
                                                  "per axis")


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
    obstacles: list[AnyObstacleSpec] = []
    interfaces: list[InterfaceSpec] = []
    patterns: dict[str, PatternSpec] = {}
    program: list[SegmentSpec] = Field([], description="the load program; required, "
                                       "unless the model has `[[stages]]` (then each stage "
                                       "has its own `[[stages.program]]` and this is an error)")
    stages: list[StageSpec] = Field([], description="construction stages, in order; their "
                                    "programs are the load program")
    dynamics: DynamicsSpec | None = None
    added_masses: list[AddedMassSpec] = Field([], description="reservoirs' added masses "
                                              "(Westergaard 1933), part of the mass matrix of "
                                              "the dynamic intervals")
    dam: DamSpec | None = Field(None, description="the dam study of this model (`stepcontact "
                                "study dam --model FILE`): its bodies, joint, faces, water, "
                                "strength and guideline; with it [[program]] is optional")

    model_config = ConfigDict(json_schema_extra={"anyOf": [{"required": ["program"]},
                                                           {"required": ["stages"]},
                                                           {"required": ["dam"]}]})


def schema() -> dict[str, Any]:
    """The JSON schema of the model file format (a dict, ready for :func:`json.dumps`)."""
    return ModelFile.model_json_schema()
