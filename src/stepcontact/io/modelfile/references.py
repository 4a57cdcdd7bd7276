"""The names of a model file: its mesh read, then every name it uses (materials, bodies,
node sets, physical groups, obstacles, interfaces, patterns, stages) checked to exist and to be
unique, each problem at its field path (:class:`_References`).
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

from stepcontact.errors import ModelError
from stepcontact.io.meshfile import GROUP_KINDS, MeshFile, read_mesh
from stepcontact.io.modelfile.dam import dam_problems
from stepcontact.io.modelfile.errors import _known, _path, _Problems
from stepcontact.io.modelfile.schema import (
    CrackWaterSpec,
    GravityLoad,
    MeshBodySpec,
    ModelFile,
    ObstacleMotionLoad,
    PressureLoad,
    SegmentSpec,
    SeismicLoadSpec,
    UpliftLoadSpec,
    _body_name,
)
from stepcontact.model.items import Body, Frame, NodeSet
from stepcontact.model.program import cycle_amplitudes
from stepcontact.model.stages import list_problems


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


class _References:
    """The names of a validated file: its mesh read, every name used checked (the first part
    of :class:`~stepcontact.io.modelfile.build._Builder`), collecting every problem on the way.

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

    @property
    def body_dims(self) -> tuple[int]:
        """The dimension of the mesh's body groups: (2,) physical surfaces, (3,) volumes."""
        return (3,) if self.mesh is not None and self.mesh.dim == 3 else (2,)

    @property
    def set_dims(self) -> tuple[int, ...]:
        """The dimensions of the groups that are node sets: curves and points; in a 3D mesh
        surfaces too."""
        return (0, 1, 2) if self.mesh is not None and self.mesh.dim == 3 else (0, 1)

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
        bodies = self._check_bodies()
        self._check_node_sets(bodies)
        names = self._check_users(bodies)
        self._check_program()
        self.check_stages(bodies, names)

    def _check_bodies(self) -> list[str]:
        """Materials, physical surfaces and body names; the names of bodies and frames."""
        spec, p, mesh = self.spec, self.p, self.mesh
        bodies = [_body_name(b) for b in spec.bodies] + [f.name for f in spec.frames]
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
                      f"physical {GROUP_KINDS[self.body_dims[0]]} '{b.surface}' has no "
                      "material: give material = "
                      "\"NAME\" or an inline table {E, nu, density}")
            if mesh is not None:
                field = f"bodies[{i}].{'group' if b.group is not None else 'name'}"
                why = self._group_problem(b.surface, self.body_dims)
                kind = GROUP_KINDS[self.body_dims[0]]
                if why is not None:
                    p.add(field, why)
                elif b.surface in surfaces:
                    p.add(field, f"physical {kind} '{b.surface}' is body "
                          f"'{surfaces[b.surface]}' already")
                surfaces.setdefault(b.surface, b.body_name)
        if mesh is not None and self.spec.mesh is not None:
            ignore = self.spec.mesh.ignore
            for j, s in enumerate(ignore):
                why = self._group_problem(s, self.body_dims)
                if why is not None:
                    p.add(f"mesh.ignore[{j}]", why)
            for s in mesh.body_groups:
                if s not in surfaces and s not in ignore:
                    p.add("mesh", f"physical {GROUP_KINDS[mesh.dim]} '{s}' is not a body: add "
                          f"[[bodies]] with kind = \"mesh\", group = \"{s}\" and its material "
                          "(or list it in mesh.ignore)")
        seen: set[str] = set()
        for group in ("bodies", "frames"):
            for i, b in enumerate(getattr(spec, group)):
                name = _body_name(b) if group == "bodies" else b.name
                if name in seen:
                    p.add(f"{group}[{i}].name", f"duplicate body name '{name}'")
                seen.add(name)
        if not bodies:
            p.add("bodies", "the model has no body and no frame")
        return bodies

    def _check_node_sets(self, bodies: list[str]) -> None:
        """The bodies and physical groups of ``[node_sets]``."""
        spec, p, mesh = self.spec, self.p, self.mesh
        mesh_bodies = {b.body_name for b in spec.bodies if isinstance(b, MeshBodySpec)}
        for name, ns in spec.node_sets.items():
            path = _path(["node_sets", name])
            if ns.body is not None and ns.body not in bodies:
                p.add(f"{path}.body", f"unknown body '{ns.body}' (known: {_known(bodies)})")
            elif ns.group is not None and ns.body is not None and ns.body not in mesh_bodies:
                p.add(f"{path}.body", f"body '{ns.body}' is not a mesh body (kind = \"mesh\"); "
                      "a physical group's nodes belong to a mesh body")
            if ns.group is not None:
                if mesh is not None:
                    why = self._group_problem(ns.group, self.set_dims)
                    if why is not None:
                        p.add(f"{path}.group", why)
                elif not self.mesh_failed:
                    p.add(f"{path}.group", "physical groups need the [mesh] section")

    def _node_set(self, path: str, name: str | None) -> None:
        """Node set ``name`` used at ``path`` exists (or is a physical curve or point)."""
        spec, p, mesh = self.spec, self.p, self.mesh
        if name is None or name in spec.node_sets:
            return
        if mesh is not None and name in mesh.groups:
            why = self._group_problem(name, self.set_dims)
            if why is None:
                self.implicit.setdefault(name, path)
            else:
                what = "surface, curve" if mesh.dim == 3 else "curve"
                p.add(path, f"{why} (a node set or a physical {what} or point)")
            return
        if self.mesh_failed:
            return  # may be a group of the mesh that could not be read
        groups = ""
        if mesh is not None:
            named = [n for d in reversed(self.set_dims) for n in mesh.names(d)]
            what = "surfaces, curves" if mesh.dim == 3 else "curves"
            groups = f"; physical {what} and points: {_known(named)}"
        p.add(path, f"unknown node set '{name}' (known: {_known(spec.node_sets)}{groups})")

    def _check_users(self, bodies: list[str]) -> set[str]:
        """The names supports, ties, springs, interfaces and loads use; the interfaces'
        names."""
        spec, p = self.spec, self.p
        for i, s in enumerate(spec.supports):
            self._node_set(f"supports[{i}].nodes", s.nodes)
        for i, t in enumerate(spec.ties):
            self._node_set(f"ties[{i}].a", t.a)
            self._node_set(f"ties[{i}].b", t.b)
        for i, s in enumerate(spec.springs):
            self._node_set(f"springs[{i}].a", s.a)
            self._node_set(f"springs[{i}].b", s.b)
        obstacles: set[str] = set()
        for i, ob in enumerate(spec.obstacles):
            if ob.name in obstacles:
                p.add(f"obstacles[{i}].name", f"duplicate obstacle name '{ob.name}'")
            obstacles.add(ob.name)
        used: set[str] = set()
        names: set[str] = set()
        for i, itf in enumerate(spec.interfaces):
            self._node_set(f"interfaces[{i}].plus", itf.plus)
            self._node_set(f"interfaces[{i}].minus", itf.minus)
            if itf.obstacle is not None:
                used.add(itf.obstacle)
                if itf.obstacle not in obstacles:
                    p.add(f"interfaces[{i}].obstacle", f"unknown obstacle '{itf.obstacle}' "
                          f"(known: {_known(obstacles)})")
            if itf.name in names:
                p.add(f"interfaces[{i}].name", f"duplicate interface name '{itf.name}'")
            names.add(itf.name)
        for i, am in enumerate(spec.added_masses):
            self._node_set(f"added_masses[{i}].nodes", am.nodes)
        if spec.dam is not None:  # the dam study's table (stepcontact.io.modelfile.dam)
            for which in ("upstream_face", "downstream_face"):
                for n in spec.dam.faces(which):
                    self._node_set(f"dam.{which}", n)
            for path, text in dam_problems(spec.dam, bodies, names):
                p.add(path, text)
        for pname, pat in spec.patterns.items():
            for j, ld in enumerate(pat.loads):
                path = f"{_path(['patterns', pname, 'loads', j])}"
                if isinstance(ld, SeismicLoadSpec):
                    for k, am in enumerate(ld.reservoir):
                        self._node_set(f"{path}.reservoir[{k}].nodes", am.nodes)
                if isinstance(ld, GravityLoad | SeismicLoadSpec):
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
                    self._node_set(f"{path}.nodes", ld.nodes)
                    if isinstance(ld, PressureLoad):
                        _deprecated_pairs(p, path, ld)
        return names

    def _check_program(self) -> None:
        """The patterns of the program's segments (and the stages'), the amplitudes of cyclic
        entries.  That segments chain is the model's rule, checked on the model built
        (:meth:`~stepcontact.io.modelfile.build._Builder.check_chain`)."""
        spec, p = self.spec, self.p
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
            if seg.amplitude is not None:
                try:
                    cycle_amplitudes(seg.amplitude, seg.cycles, path, "cycles")
                except ModelError as e:
                    p.add(e.item, e.problem)

    def program_entries(self) -> Iterator[tuple[str, SegmentSpec]]:
        """Every ``[[program]]`` entry with its field path; with stages, the stages' entries
        in order (the model's load program)."""
        for i, seg in enumerate(self.spec.program):
            yield f"program[{i}]", seg
        for k, st in enumerate(self.spec.stages):
            for i, seg in enumerate(st.program):
                yield f"stages[{k}].program[{i}]", seg

    def check_stages(self, bodies: list[str], interfaces: set[str]) -> None:
        """The names a stage lists exist and are listed once, a support is removed after it
        is placed, grout fills joints in place after the first stage: the rules of
        :func:`stepcontact.model.stages.list_problems` (those of the solver's
        :class:`~stepcontact.solver.staging.StagePlan`), with the paths of the file.  Here
        too: stage names are unique, a support a stage names is one, a stage has a load
        segment (its own, or the automatic ones of removed supports and new bodies)."""
        spec, p = self.spec, self.p
        if not spec.stages:
            return
        supports: dict[str, list[int]] = {}
        for i, s in enumerate(spec.supports):
            supports.setdefault(s.name or s.nodes, []).append(i)
        known = {"body": bodies, "interface": sorted(interfaces), "support": list(supports)}
        first: dict[str, int] = {}
        for k, st in enumerate(spec.stages):
            if st.name in first:
                p.add(f"stages[{k}].name", f"duplicate stage name '{st.name}' (also stages"
                      f"[{first[st.name]}])")
            first.setdefault(st.name, k)
            for key in ("supports", "remove_supports"):
                for name in getattr(st, key):
                    if len(supports.get(name, ())) > 1:
                        at = " and ".join(f"supports[{i}]" for i in supports[name])
                        p.add(f"stages[{k}].{key}", f"support name '{name}' is ambiguous ({at} "
                              "have it): give those supports distinct names (name = \"...\")")
        for k, key, text in list_problems(
                spec.stages, known, lambda j: f"stages[{j}] ('{spec.stages[j].name}')"):
            p.add(f"stages[{k}].{key}", text)
        for k, st in enumerate(spec.stages):
            auto = bool(st.bodies or st.remove_supports or st.dynamics is not None)
            if k > 0 and not st.program and not auto:
                p.add(f"stages[{k}].program", f"stage '{st.name}' has no load segment: give it "
                      "a [[stages.program]] entry (a stage begins with its first segment)")
        if len(spec.stages) == 1 and not spec.stages[0].program:
            p.add("stages[0].program", f"stage '{spec.stages[0].name}' has no load segment: "
                  "give it [[stages.program]] entries")
