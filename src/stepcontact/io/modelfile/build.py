"""Building the :class:`~stepcontact.model.Model` of a validated model file
(:class:`_Builder`): bodies, node sets, supports, springs, interfaces, loads, the program,
stages and dynamic intervals; an error a model item raises is reported at the field path of
the file.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.io.modelfile.checks import check_plausible
from stepcontact.io.modelfile.dam import dam_geometry_problems
from stepcontact.io.modelfile.errors import _known, _path, _Problems
from stepcontact.io.modelfile.references import _References
from stepcontact.io.modelfile.schema import (
    ALL_DOFS,
    BoxBodySpec,
    BoxSpec,
    CrackWaterSpec,
    CylinderSpec,
    EdgeForceLoad,
    ExtrudeSpec,
    GravityLoad,
    GroundMotionSpec,
    HalfDiscSpec,
    MaterialSpec,
    MeshBodySpec,
    NodalLoadSpec,
    NodeSetSpec,
    ObstacleMotionLoad,
    PlaneObstacleSpec,
    PolygonSpec,
    PressureLoad,
    QuadRegionSpec,
    RectangleSpec,
    SegmentSpec,
    SeismicLoadSpec,
    SphericalBlockSpec,
    UpliftLoadSpec,
    WaterLoadSpec,
    _body_name,
)
from stepcontact.model import plausible
from stepcontact.model.items import (
    Body,
    BodyForce,
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
    _parse_dofs,
    select_nodes,
)
from stepcontact.model.mesh import (
    box,
    cylinder,
    extrude,
    half_disc,
    polygon_region,
    quad_region,
    rectangle,
    spherical_block,
)
from stepcontact.model.obstacle import ObstacleMotion, RigidObstacle, RigidPlane
from stepcontact.model.program import cycles
from stepcontact.model.seismic import AddedMass, SeismicCoefficient
from stepcontact.model.size import check_size
from stepcontact.model.stages import Stage
from stepcontact.model.water import CrackWater, Uplift, WaterLoad


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


def _box(where: BoxSpec, atol: float) -> Callable[..., np.ndarray]:
    """Predicate of a box with inclusive bounds (tolerance ``atol``, m) on the coordinates
    (x, y[, z]) of a body's nodes."""
    lo = np.array([-np.inf if v is None else v for v in (where.xmin, where.ymin, where.zmin)])
    hi = np.array([np.inf if v is None else v for v in (where.xmax, where.ymax, where.zmax)])

    def inside(*xyz: np.ndarray) -> np.ndarray:
        out = np.ones(np.shape(xyz[0]), dtype=bool)
        for c, v in enumerate(xyz):
            out &= (v >= lo[c] - atol) & (v <= hi[c] + atol)
        return out

    return inside


def _section(b: RectangleSpec | QuadRegionSpec | PolygonSpec | HalfDiscSpec,
             mat: Material) -> Body:
    """The 2D body of the section of an extruded body (``kind = "extrude"``)."""
    if isinstance(b, RectangleSpec):
        return rectangle(b.name, b.corner0, b.corner1, b.nx, b.ny, mat, b.element,
                         grading=b.grading)
    if isinstance(b, QuadRegionSpec):
        return quad_region(b.name, b.corners, b.nx, b.ny, mat, b.element, grading=b.grading)
    if isinstance(b, PolygonSpec):
        return polygon_region(b.name, b.vertices, mat, b.element, n=b.n, size=b.size)
    return half_disc(b.name, b.center, b.radius, b.n_radial, b.n_around, mat, b.element,
                     refine_toward="bottom" if b.refine else None, ratio=b.ratio)


def _field_of(item: str, prefix: str) -> str | None:
    """``.field`` of a model item's error ``prefix.field`` (e.g. ``body 'b'.n[0]`` ->
    ``.n[0]``, ``frame 'f'.J`` -> ``.J``); None when the item names no field of it."""
    rest = item.removeprefix(prefix)
    if rest == item or not rest.startswith("."):
        return None
    return rest.split(" ")[0]


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
    if ns.where is not None and pts.shape[1] < 3:
        given = [k for k in ("zmin", "zmax") if getattr(ns.where, k) is not None]
        if given:
            raise ModelError(f"{path}.where.{given[0]}", f"body '{body.name}' is 2D: select "
                             "by x and y")
    atol = 1e-9 * max(1.0, float(np.ptp(pts, axis=0).max()) if len(pts) else 1.0)
    where = _box(ns.where, atol) if ns.where is not None else None
    try:
        return select_nodes(body, where, x=ns.x, y=ns.y, z=ns.z, boundary=ns.boundary,
                            name=name)
    except ModelError as e:
        raise ModelError(path, f"{e.problem} on body '{body.name}'") from None


class _Builder(_References):
    """Builds the model of a validated file, collecting every problem on the way (the names
    are checked first, :class:`~stepcontact.io.modelfile.references._References`).

    Nothing stops at the first problem: an item that depends on a broken one (a node set of a
    body that could not be made, a support on that node set, ...) is skipped silently, since
    the broken item is reported already.
    """

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
                if isinstance(b, ExtrudeSpec):
                    self.bodies[name] = extrude(_section(b.section, mat), b.z, b.nz,
                                                name=b.name)
                    continue
                if isinstance(b, BoxBodySpec):
                    self.bodies[name] = box(b.name, b.corner0, b.corner1, (b.nx, b.ny, b.nz),
                                            mat, b.element)
                    continue
                if isinstance(b, CylinderSpec):
                    self.bodies[name] = cylinder(b.name, b.centre, b.radius, b.height, b.n, mat,
                                                 b.element)
                    continue
                if isinstance(b, SphericalBlockSpec):
                    self.bodies[name] = spherical_block(b.name, b.radius, b.xs, b.ys, b.top,
                                                        b.layers, mat, b.element)
                    continue
                if isinstance(b, HalfDiscSpec):
                    self.bodies[name] = half_disc(
                        b.name, b.center, b.radius, b.n_radial, b.n_around, mat, b.element,
                        refine_toward="bottom" if b.refine else None, ratio=b.ratio)
                    continue
                if self.mesh is None or self._group_problem(
                        b.surface, (self.mesh.dim,)) is not None:
                    self.failed.add(name)
                    continue
                self.bodies[name] = self.mesh.body(b.surface, mat, name=name, element=b.element)
            except ModelError as e:
                self.failed.add(name)
                field = _field_of(e.item, f"body '{name}'")
                if field is not None:
                    self.p.add(f"bodies[{i}]{field}", e.problem)
                    continue
                detail = e.problem if e.item.startswith("body ") else f"{e.item} {e.problem}"
                self.p.add(f"bodies[{i}]", detail)
        for i, f in enumerate(self.spec.frames):
            if f.name in self.paths:
                continue
            self.paths[f.name] = f"frames[{i}]"
            try:
                self.bodies[f.name] = Frame.line(
                    f.name, f.start, f.end, f.n, E=f.E, A=f.A, I=f.I, density=f.density,
                    **f.section)
            except ModelError as e:
                self.failed.add(f.name)
                field = _field_of(e.item, f"frame '{f.name}'")
                self.p.add(f"frames[{i}]{field or ''}", e.problem)

    def check_size(self) -> None:
        """The whole model fits in this machine's memory (each rectangle was checked before
        it was meshed; mesh bodies and the sum of all are checked here, before assembly)."""
        if len(self.bodies) < 2 and self.mesh is None:
            return
        ndof = sum((len(b.dof_names) if isinstance(b, Frame) else b.dim) * b.n_nodes
                   for b in self.bodies.values())
        nodes = sum(b.n_nodes for b in self.bodies.values())
        try:
            check_size(ndof, "model", f"the model ({len(self.bodies)} bodies, {nodes} nodes)")
        except ModelError as e:
            self.p.add(e.item, e.problem)

    def _group_set(self, group: str, body: str | None, name: str, path: str, hint: str) -> None:
        """Node set ``name`` of a physical group; problems are reported at ``path``."""
        assert self.mesh is not None
        if self._group_problem(group, self.set_dims) is not None:
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

    # ---- the model ------------------------------------------------------------------------
    def model(self) -> Model | None:
        """The model (None when it cannot be made); problems are in ``self.p``.  Warnings of
        implausible values are listed with their field paths
        (:func:`~stepcontact.io.modelfile.checks.check_plausible`)."""
        check_plausible(self.spec, self.p)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", plausible.PlausibilityWarning)
            return self._model()

    def _model(self) -> Model | None:
        self.read_mesh()
        self.check_references()
        self.build_bodies()
        self.check_size()
        self.build_node_sets()
        self.check_dimension()
        spec, sets, p = self.spec, self.sets, self.p

        def have(*names: str | None) -> bool:
            return all(n is None or n in sets for n in names)

        supports = []
        for i, s in enumerate(spec.supports):
            if have(s.nodes):
                supports.append(Support(s.name or s.nodes, sets[s.nodes],
                                        _parse_dofs(s.dofs, f"supports[{i}].dofs",
                                                    ALL_DOFS)))
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
                obstacles[ob.name] = (RigidPlane(ob.name, point=ob.point, normal=ob.normal)
                                      if isinstance(ob, PlaneObstacleSpec)
                                      else RigidObstacle(ob.name, ob.points, ob.side))
            except ModelError as e:
                field = e.item.rpartition("'.")[2] if "'." in e.item else ""
                p.add(f"obstacles[{i}].{field}" if field else f"obstacles[{i}]", e.problem)
        interfaces = []
        for i, itf in enumerate(spec.interfaces):
            if not have(itf.plus, itf.minus) or f"interfaces[{i}]" in getattr(self, "skip", ()):
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
                    facets=itf.facets,
                    facet_angle=itf.facet_angle,
                    axis=itf.axis,
                ))
            except ModelError as e:
                field = _field_of(e.item, f"interface '{itf.name}'")
                p.add(f"interfaces[{i}]{field or ''}", e.problem)
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
            model = Model(
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
                added_masses=self._added_masses(p),
            )
        except ModelError as e:
            p.add(self.file_path(e.item), e.problem)
            return None
        self.check_chain(model)
        if spec.dam is not None:  # the dam study's table: its geometry on the model built
            faces = {w: [sets[n] for n in spec.dam.faces(w) if n in sets]
                     for w in ("upstream_face", "downstream_face")}
            for path, text in dam_geometry_problems(spec.dam, model, faces):
                p.add(path, text)
        return model

    #: the model's dimension (2 or 3), known after :meth:`check_dimension`
    dim: int = 2
    #: paths of interfaces not built: a field of the other dimension (reported)
    skip: set[str]

    def check_dimension(self) -> None:
        """The fields that belong to the other dimension, named by their path: the model is 3D
        when its bodies are (or, without continua, its frames), and then a rotation of a
        continuum's node, a moment on it, a 2-component gravity, a tangential or 2D traction,
        the plane options, a 2D obstacle line and an uplift on the faces are errors; in 2D
        anything along z, a rotation other than rz, the facet options of the faceted cone and
        a rigid plane.  Bodies and frames of both dimensions: an error at the first one of the
        other dimension."""
        spec, p = self.spec, self.p
        self.skip = set()
        continua = {n: b.dim for n, b in self.bodies.items() if isinstance(b, Body)}
        every = {n: b.dim for n, b in self.bodies.items()}
        first = next(iter(continua.values()), next(iter(every.values()), None))
        if first is None:
            return
        self.dim = dim = first
        for name, d in every.items():
            if d != dim:
                where = self.paths.get(name, f"body '{name}'")
                field = ".start" if where.startswith("frames") else ""
                p.add(where + field, f"is {d}D, but the model is {dim}D (its first "
                      f"{'body' if continua else 'frame'} is): all bodies and frames of a model "
                      "have one dimension")
        if dim == 3:
            for key in ("plane", "thickness"):
                if key in spec.model.model_fields_set:
                    p.add(f"model.{key}", "applies to 2D bodies only (plane strain or stress); "
                          "the bodies are 3D: leave it out")
        for i, s in enumerate(spec.supports):
            dofs = _parse_dofs(s.dofs, f"supports[{i}].dofs", ALL_DOFS)
            bad = [d for d in dofs if d not in self._dofs_of(s.nodes)]
            if bad:
                p.add(f"supports[{i}].dofs", f"'{bad[0]}' is not a degree of freedom of a "
                      f"{dim}D model's {self._owner(s.nodes)} (use "
                      f"{', '.join(self._dofs_of(s.nodes))})")
        self._check_interface_dimension(dim)
        for pname, pat in spec.patterns.items():
            for j, ld in enumerate(pat.loads):
                self._check_load_dimension(_path(["patterns", pname, "loads", j]), ld, dim)

    def _frame_set(self, name: str) -> bool:
        """Node set ``name`` lies on a frame."""
        ns = self.sets.get(name)
        return ns is not None and isinstance(self.bodies.get(ns.body), Frame)

    def _dofs_of(self, name: str) -> tuple[str, ...]:
        """The DOF names of the nodes of set ``name`` in a model of ``self.dim``."""
        ns = self.sets.get(name)
        body = None if ns is None else self.bodies.get(ns.body)
        if isinstance(body, Frame):
            return body.dof_names
        return ("x", "y", "z") if self.dim == 3 else ("x", "y", "rz")

    def _owner(self, name: str) -> str:
        """``body nodes (set 'base')`` for messages."""
        kind = ("space frame" if self.dim == 3 else "plane frame") \
            if self._frame_set(name) else "body"
        return f"{kind} nodes (set '{name}')"

    def _check_interface_dimension(self, dim: int) -> None:
        """The interfaces' and obstacles' fields of the other dimension."""
        spec, p = self.spec, self.p
        kinds = {ob.name: ob.kind for ob in spec.obstacles}
        for i, ob in enumerate(spec.obstacles):
            if (ob.kind == "plane") != (dim == 3):
                p.add(f"obstacles[{i}].kind", f"the model is {dim}D: " + (
                    "a 3D body meets a rigid plane (kind = \"plane\", point, normal)"
                    if dim == 3 else "a rigid plane is for 3D bodies; a 2D body meets a line "
                    "(points, side)"))
        for i, itf in enumerate(spec.interfaces):
            path = f"interfaces[{i}]"
            if dim == 2:
                for key, given in (("facets", itf.facets is not None),
                                   ("facet_angle", itf.facet_angle != 0.0),
                                   ("axis", itf.axis is not None)):
                    if given:
                        p.add(f"{path}.{key}", "applies to interfaces between 3D bodies only "
                              "(a 2D interface has the two facets slip+ and slip−)")
                        self.skip.add(path)
            if itf.normal is not None and len(itf.normal) != dim:
                p.add(f"{path}.normal", f"has {len(itf.normal)} components, the model is "
                      f"{dim}D: give {'[nx, ny, nz]' if dim == 3 else '[nx, ny]'}")
                self.skip.add(path)
            if itf.obstacle in kinds and (kinds[itf.obstacle] == "plane") != (dim == 3):
                self.skip.add(path)  # the obstacle's kind is reported

    def _check_load_dimension(self, path: str, ld: Any, dim: int) -> None:
        """One load's fields against the model's dimension (:meth:`check_dimension`)."""
        p = self.p
        other = f"the model is {dim}D"
        if isinstance(ld, GravityLoad) and ld.g is not None and len(ld.g) != dim:
            p.add(f"{path}.g", f"has {len(ld.g)} components, {other}: give "
                  f"{'[gx, gy, gz]' if dim == 3 else '[gx, gy]'} (m/s²) or leave it out "
                  "(9.81 m/s² downwards)")
        elif isinstance(ld, NodalLoadSpec | EdgeForceLoad):
            dofs = self._dofs_of(ld.nodes)
            for key in ("fz", "mx", "my", "mz"):
                if getattr(ld, key, 0.0) == 0.0:
                    continue
                turn = key.startswith("m")
                if (turn and "r" + key[1] not in dofs) or (not turn and "z" not in dofs):
                    why = (f"the {self._owner(ld.nodes)} have no rotation about {key[1]} (moments "
                           "act on frames: mz on plane frames, mx, my, mz on space frames)"
                           if turn else "no force along z")
                    p.add(f"{path}.{key}", f"{other}: {why}")
        elif isinstance(ld, PressureLoad) and dim == 3:
            for key in ("tangential", "traction"):
                if getattr(ld, key) is not None:
                    p.add(f"{path}.{key}", f"{other}: the faces of 3D bodies take a normal "
                          "pressure (or edge_force with fx, fy, fz)")
        elif isinstance(ld, UpliftLoadSpec) and dim == 3 and ld.through == "faces":
            p.add(f"{path}.through", f"{other}: an uplift in a 3D joint acts through its CFEs "
                  "(through = \"cfes\", the default in 3D: A_k p(x, y) across each CFE)")
        elif getattr(ld, "type", None) == "displacement":
            if ld.dof not in self._dofs_of(ld.nodes):
                p.add(f"{path}.dof", f"{other}: its {self._owner(ld.nodes)} move along "
                      f"{', '.join(self._dofs_of(ld.nodes))}")

    def file_path(self, item: str) -> str:
        """The field path of an item the model names in its own words (``load pattern 'w'
        load 0.through`` -> ``patterns.w.loads[0].through``, ``interface 'j'.normal`` ->
        ``interfaces[2].normal``, ``body 'b'`` / ``frame 'f'`` -> ``bodies[1]`` /
        ``frames[0]``); the item itself when it names nothing of the file."""
        if item.startswith("model.dynamics"):
            return item.removeprefix("model.")
        m = re.match(r"load pattern '(.+)' load (\d+)(.*)$", item)
        if m and m.group(1) in self.spec.patterns:
            return f"{_path(['patterns', m.group(1), 'loads', int(m.group(2))])}{m.group(3)}"
        m = re.match(r"(interface|body|frame) '(.+?)'(\..*)?$", item)
        if m is None:
            return item
        kind, name, rest = m.group(1), m.group(2), m.group(3) or ""
        if kind == "interface":
            found = [i for i, itf in enumerate(self.spec.interfaces) if itf.name == name]
            return f"interfaces[{found[0]}]{rest}" if found else item
        where = self.paths.get(name)
        return f"{where}{rest}" if where is not None else item

    def check_chain(self, model: Model) -> None:
        """Each segment starts where its pattern stands: the model's rule
        (:meth:`~stepcontact.model.Model.program_walk`: after segments with rates and the
        dynamic intervals of earlier stages too), reported at the path of its entry."""
        paths: list[str] = []
        for path, seg in self.program_entries():
            n = len(_segments(seg))
            if n == 0:
                return  # a cyclic entry whose amplitudes are wrong (reported)
            paths += [path] * n
        if len(paths) != len(model.effective_program):
            return  # a stage that could not be made (reported)
        try:
            for i, seg, now, start in model.program_walk():
                if abs(start - now) > 1e-12 * max(1.0, abs(now)):
                    self.p.add(f"{paths[i]}.start", f"segments do not chain: pattern "
                               f"'{seg.pattern}' stands at λ = {now:g}, this segment starts "
                               f"at {start:g}")
        except ModelError:
            return  # a name of the program, reported with its path already

    def _load(self, ld: Any, loads: list, interfaces: list, obstacles: dict) -> None:
        """Append the load of the file's entry ``ld`` to ``loads`` (nothing where an item it
        needs is missing: that problem is reported already)."""
        if isinstance(ld, GravityLoad):
            loads.append(BodyForce(bodies=tuple(ld.bodies)) if ld.g is None
                         else BodyForce(tuple(ld.g), tuple(ld.bodies)))
        elif isinstance(ld, UpliftLoadSpec):
            found = [i for i in interfaces if i.name == ld.interface]
            if found:
                through = ld.through or ("cfes" if self.dim == 3 else "faces")
                if ld.drained is not None:
                    d = ld.drained
                    loads.append(Uplift.drained(
                        found[0], heel=d.heel, toe=d.toe, drain=d.drain,
                        efficiency=d.efficiency, head_up=d.head_up, head_down=d.head_down,
                        reference=d.reference, unit_weight=ld.unit_weight, through=through))
                else:
                    loads.append(Uplift(found[0], ld.head, ld.pressure, ld.unit_weight,
                                        through))
        elif isinstance(ld, CrackWaterSpec):
            found = [i for i in interfaces if i.name == ld.interface]
            if found:
                loads.append(CrackWater(found[0], ld.level, ld.unit_weight,
                                        None if ld.entry is None else _entry_tuple(ld.entry),
                                        ld.pressure, ld.bridge, ld.rule))
        elif isinstance(ld, ObstacleMotionLoad):
            if ld.obstacle in obstacles:
                loads.append(ObstacleMotion(obstacles[ld.obstacle], ld.dx, ld.dy,
                                            ld.rotation, ld.about))
        elif isinstance(ld, SeismicLoadSpec):
            if all(am.nodes in self.sets for am in ld.reservoir):
                reservoir = []
                for k, am in enumerate(ld.reservoir):
                    try:
                        reservoir.append(self._added_mass(am))
                    except ModelError as e:
                        raise ModelError(e.item, f"reservoir[{k}]: {e.problem}") from None
                loads.append(SeismicCoefficient(ld.k_h, ld.k_v, tuple(ld.bodies),
                                                tuple(reservoir), float(ld.direction), ld.g))
        elif ld.nodes not in self.sets:
            return
        elif isinstance(ld, WaterLoadSpec):
            loads.append(WaterLoad(self.sets[ld.nodes], ld.level, ld.unit_weight))
        elif isinstance(ld, NodalLoadSpec):
            loads.append(NodalLoad(self.sets[ld.nodes], ld.fx, ld.fy, ld.mz, ld.fz, ld.mx,
                                   ld.my))
        elif isinstance(ld, PressureLoad):
            loads.append(EdgeLoad(self.sets[ld.nodes], ld.normal, ld.tangential,
                                  None if ld.traction is None else tuple(ld.traction)))
        elif isinstance(ld, EdgeForceLoad):
            loads.append(EdgeForce(self.sets[ld.nodes], ld.fx, ld.fy, ld.fz))
        else:
            loads.append(PrescribedDisplacement(self.sets[ld.nodes], ld.dof, ld.value))

    def _added_mass(self, am) -> AddedMass:
        """The :class:`~stepcontact.model.seismic.AddedMass` of a file's table (its node set
        exists)."""
        return AddedMass(self.sets[am.nodes], am.level, am.bottom, am.density)

    def _added_masses(self, p: _Problems) -> tuple[AddedMass, ...]:
        """The file's ``[[added_masses]]`` (a problem at its path where one cannot be made)."""
        out = []
        for i, am in enumerate(self.spec.added_masses):
            if am.nodes not in self.sets:
                continue  # reported
            try:
                out.append(self._added_mass(am))
            except ModelError as e:
                field = e.item.rpartition(".")[2] if "." in e.item else ""
                p.add(f"added_masses[{i}]" + (f".{field}" if field else ""), e.problem)
        return tuple(out)

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
        ground = self._ground_motion(spec.ground_motion, p, where)
        if ground is False:  # a record that could not be read: reported
            return None
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
                                   spec.max_steps, ground, crack_water=spec.crack_water)
        except ModelError as e:
            item = e.item
            p.add(where + item[len("dynamics"):] if item.startswith("dynamics") else item,
                  e.problem)
            return None


    def _ground_motion(self, specs, p, where: str):
        """The earthquake records of ``[[{where}.ground_motion]]`` as one
        :class:`~stepcontact.model.records.GroundMotion` (None without records; False when a
        record could not be read: the problem is reported, naming the field or the file and
        its line)."""
        if not specs:
            return None
        from stepcontact.model.records import AccelerationRecord, GroundMotion

        records, ok = [], True
        for j, gm in enumerate(specs):
            item = f"{where}.ground_motion[{j}]"
            if "xyz".index(gm.axis) >= self.dim:
                p.add(f"{item}.axis", f"'{gm.axis}' in a {self.dim}D model: give x or y (the "
                      "vertical is y)")
                ok = False
                continue
            path = Path(gm.file)
            if not path.is_absolute():
                path = self.base / path
            try:
                records.append(AccelerationRecord.read(
                    path, gm.format, units=gm.units, dt=gm.dt, scale=gm.scale,
                    target_pga=gm.target_pga, target_pga_g=gm.target_pga_g,
                    polarity=gm.polarity, axis=gm.axis, name=gm.file))
            except ModelError as e:  # a field of the table, or the file and its line
                field = e.item if e.item in GroundMotionSpec.model_fields else "file"
                text = e.problem if field != "file" or e.item == str(path) else str(e)
                p.add(f"{item}.{field}", f"{gm.file}: {text}" if field == "file" else text)
                ok = False
        if not ok:
            return False
        try:
            return GroundMotion(tuple(records))
        except ModelError as e:
            p.add(f"{where}.ground_motion", e.problem)
            return False


def _entry_tuple(entry) -> tuple:
    """A crack's entry from the file as nested tuples (a point, points or polylines)."""
    if isinstance(entry, list | tuple):
        return tuple(_entry_tuple(e) for e in entry)
    return entry
