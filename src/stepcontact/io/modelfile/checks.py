"""Checks of a model file beyond its names: values outside what any real structure has
(warnings, :mod:`stepcontact.model.plausible`) and the geometry of the built model (element
quality, duplicate and orphan nodes, bodies that overlap without an interface).
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np

from stepcontact.io.meshfile import MeshFile
from stepcontact.io.modelfile.errors import _path, _Problems
from stepcontact.io.modelfile.schema import (
    BondSpec,
    CrackWaterSpec,
    GravityLoad,
    MaterialSpec,
    ModelFile,
    UpliftLoadSpec,
    WaterLoadSpec,
)
from stepcontact.model import meshcheck, plausible
from stepcontact.model.items import Body, Model, NodeSet
from stepcontact.model.water import LinearProfile


class _Built(Protocol):
    """What :func:`check_geometry` reads of the builder
    (:class:`~stepcontact.io.modelfile.build._Builder`): its problems, the field path and the
    physical surface of each body, the mesh."""

    p: _Problems
    paths: dict[str, str]
    surface_of: dict[str, str]
    mesh: MeshFile | None


def check_plausible(spec: ModelFile, p: _Problems) -> None:
    """Values outside what any real structure has (:mod:`stepcontact.model.plausible`):
    warnings with the field path (the Python objects built from the file warn with their
    own names; those warnings are silenced while the file is built)."""

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
            if isinstance(ld, GravityLoad) and ld.g is not None:
                p.implausible("gravity", math.hypot(*ld.g), f"{path}.g")
            if isinstance(ld, WaterLoadSpec | UpliftLoadSpec | CrackWaterSpec):
                p.implausible("unit_weight_water", ld.unit_weight, f"{path}.unit_weight")
            if isinstance(ld, UpliftLoadSpec) and ld.drained is not None:
                for key in ("head_up", "head_down"):
                    p.implausible("head", getattr(ld.drained, key), f"{path}.drained.{key}")
            elif isinstance(ld, UpliftLoadSpec):
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


def _where(b: _Built, name: str) -> str:
    """``body 'x'`` or ``physical surface 'x'`` for messages."""
    s = b.surface_of.get(name)
    kind = "volume" if b.mesh is not None and b.mesh.dim == 3 else "surface"
    return f"physical {kind} '{s}'" if s is not None else f"body '{name}'"

def check_geometry(builder: _Built, model: Model) -> None:
    """Element quality, nodes in no element, bodies overlapping without an interface (the
    element quality and the overlaps of plane bodies: a 3D body's inverted or degenerate
    elements are refused when it is made)."""
    p = builder.p
    continua = [b for b in model.bodies if isinstance(b, Body)]
    plane = [b for b in continua if b.dim == 2]
    for b in plane:
        pts, cells = meshcheck.corners(b)
        q = meshcheck.quality(pts, cells)
        path = builder.paths.get(b.name, f"body '{b.name}'")
        k = q.worst
        c = pts[cells[k]].mean(axis=0)
        at = f"centroid ({c[0]:.6g}, {c[1]:.6g})"
        if q.quality[k] <= 0:
            n = int(np.count_nonzero(q.quality <= 0))
            p.add(path, f"{_where(builder, b.name)} element {k} is inverted ({at}); "
                  f"{n} inverted element{'s' * (n > 1)}")
        elif q.quality[k] < meshcheck.QUALITY_WARN:
            n = int(np.count_nonzero(q.quality < meshcheck.QUALITY_WARN))
            p.warn(path, f"{_where(builder, b.name)} element {k} is nearly degenerate: quality "
                   f"{q.quality[k]:.3g} (1 is best), aspect ratio {q.aspect[k]:.3g}, {at}; "
                   f"{n} element{'s' * (n > 1)} below {meshcheck.QUALITY_WARN}")
        j = int(np.argmax(q.aspect))
        if q.aspect[j] > meshcheck.ASPECT_WARN:
            n = int(np.count_nonzero(q.aspect > meshcheck.ASPECT_WARN))
            c = pts[cells[j]].mean(axis=0)
            p.warn(path, f"{_where(builder, b.name)} element {j} is elongated: aspect ratio "
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
            at = ", ".join(f"{v:.6g}" for v in pts[k])
            p.warn(builder.paths.get(b.name, f"body '{b.name}'"),
                   f"{_where(builder, b.name)} has {n} duplicate node{'s' * (n > 1)} (e.g. nodes "
                   f"{', '.join(map(str, twins[:4]))} at ({at})): "
                   "elements that should share them are not connected")
    if builder.mesh is not None:
        orphans = builder.mesh.orphan_nodes()
        if orphans.size:
            at = ", ".join(f"{v:.6g}" for v in builder.mesh.points[orphans[0]])
            kind = "volume" if builder.mesh.dim == 3 else "surface"
            p.warn("mesh", f"{orphans.size} node{'s' * (orphans.size > 1)} of "
                   f"{builder.mesh.path.name} belong to no element of a physical {kind} and "
                   f"are ignored (e.g. node {int(orphans[0])} at ({at}))")
    joined = {frozenset((i.plus.body, i.minus.body)) for i in model.interfaces
              if isinstance(i.minus, NodeSet)}
    for ia, a in enumerate(plane):
        for b in plane[ia + 1:]:
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
                  f"{_where(builder, inner.name)} lies inside element {k} of "
                  f"{_where(builder, outer.name)}; join them with an [[interfaces]] entry or "
                  "fix the geometry")
