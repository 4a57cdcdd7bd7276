"""The ``[dam]`` table of a model file: what the dam study (``stepcontact study dam --model
FILE.toml``, :mod:`stepcontact.study.dam_file`) needs of a user's model (issue 29 §3).

The file's bodies, meshes (Gmsh too), materials, supports and interfaces are used as they
are; the table names the dam's bodies, the base joint (an interface), the upstream and
downstream faces (node sets), the heel and the toe, and gives the water, the drains, the
joint's strength for the checks, the guideline and the seismic coefficients.  SI units: m,
Pa, N/m³; angles in degrees; levels are elevations with the datum at the heel (y = 0).

The schema checks types and ranges (errors name the field, ``dam.upstream_face``);
:func:`dam_problems` checks the names against the file's bodies, interfaces and node sets;
:func:`dam_geometry_problems` the geometry on the built model (a face on the boundary of a dam
body, heel and toe nodes of the joint, the heel at y = 0, the drain on the base) — both when
the file is built or validated, and again when the study builds its site
(:func:`stepcontact.study.dam_file.dam_file`).
"""

from __future__ import annotations

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

Point = tuple[float, float]


class DamSpec(BaseModel):
    """``[dam]``: the dam study of this model (``stepcontact study dam --model FILE``); the
    file's own ``[patterns]``, ``[[program]]``, ``[[stages]]`` and ``[dynamics]`` are not used
    by the study (a warning), and ``[[program]]`` is not required with ``[dam]``."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, frozen=True)

    bodies: list[str] = Field(min_length=1, description="the dam's bodies (self-weight, "
                              "inertia)")
    joint: str = Field(description="the base joint: the name of an interface of the file")
    upstream_face: str | list[str] = Field(description="node set(s) of the upstream face "
                                           "(reservoir, silt, hydrodynamic pressure); a list "
                                           "for a face across several bodies")
    downstream_face: str | list[str] | None = Field(None, description="node set(s) of the "
                                                    "downstream face (tailwater); required "
                                                    "with a tailwater")
    heel: Point = Field(description="the heel (x, y), m: on the joint, at y = 0 (the datum "
                        "of the levels)")
    toe: Point = Field(description="the toe (x, y), m: on the joint; the moments are about it")
    crest: Point | None = Field(None, description="the point whose horizontal displacement "
                                "is the λ–u curve, m (default: the highest node of the "
                                "upstream face)")
    normal_level: float = Field(gt=0, description="normal reservoir level (usual "
                                "combination), m above the heel")
    flood_level: float | None = Field(None, gt=0, description="flood level (unusual "
                                      "combination), m (default: the normal level: no flood "
                                      "combination)")
    max_level: float | None = Field(None, gt=0, description="highest level of the run to "
                                    "failure, m (default 3 × the dam's height)")
    level_step: float | None = Field(None, gt=0, description="the level run's reported "
                                     "states every so many metres (default height / 20)")
    tailwater: float = Field(0.0, ge=0, description="tailwater level, m above the heel")
    crack_water: bool = Field(True, description="full reservoir pressure in the base where it "
                              "opens from the heel")
    drain: Point | None = Field(None, description="where the drain line meets the joint "
                                "(x, y), m (default: no drains)")
    drain_efficiency: float | None = Field(None, ge=0, le=1, description="drain efficiency "
                                           "E: the drain head ratio K = (1 − E)(L − X)/L")
    drain_ratio: float | None = Field(None, ge=0, le=1, description="the drain line's head "
                                      "ratio K itself (instead of drain_efficiency)")
    friction_angle: float | None = Field(None, gt=0, lt=90, description="peak friction angle "
                                         "φ of the joint for the checks, degrees (default: "
                                         "atan of the interface's friction, without a bond)")
    cohesion: float = Field(0.0, ge=0, description="peak cohesion c of the joint for the "
                            "checks, Pa")
    residual_friction_angle: float | None = Field(None, gt=0, lt=90, description="residual "
                                                  "friction angle for the checks, degrees")
    residual_cohesion: float = Field(0.0, ge=0, description="residual cohesion, Pa")
    compressive_strength: float | None = Field(None, gt=0, description="the joint's "
                                               "compressive strength, Pa (none: no stress "
                                               "check)")
    silt_level: float | None = Field(None, gt=0, description="silt against the upstream face "
                                     "up to this level, m")
    silt_unit_weight: float = Field(13.4e3, gt=0, description="the silt's equivalent fluid "
                                    "K γ'_s, N/m³")
    guideline: str = Field("usace", description="the guideline of the verdicts: usace, ferc "
                           "or cda")
    guideline_variant: str | None = Field(None, description="the guideline's variant (USACE: "
                                          "structure class, site information)")
    k_h: float = Field(0.1, gt=0, description="design horizontal seismic coefficient, g")
    k_v: float = Field(0.0, gt=-1, lt=1, description="design vertical seismic coefficient, "
                       "g, > 0 upwards")
    max_kh: float = Field(1.0, gt=0, description="the yield run's highest k_h, g")

    @model_validator(mode="after")
    def _consistent(self) -> DamSpec:
        if self.drain is None and (self.drain_efficiency is not None
                                   or self.drain_ratio is not None):
            raise ValueError("drain_efficiency / drain_ratio need the drain line's point: "
                             "give drain = [x, y]")
        if self.drain_efficiency is not None and self.drain_ratio is not None:
            raise ValueError("give drain_efficiency or drain_ratio, not both")
        if self.drain is not None and self.drain_efficiency is None and self.drain_ratio is None:
            raise ValueError("a drain line needs drain_efficiency (E) or drain_ratio (K)")
        if self.flood_level is not None and self.flood_level < self.normal_level:
            raise ValueError(f"flood_level ({self.flood_level:g} m) is below normal_level "
                             f"({self.normal_level:g} m)")
        if self.tailwater >= self.normal_level:
            raise ValueError(f"tailwater ({self.tailwater:g} m) must be below normal_level "
                             f"({self.normal_level:g} m)")
        if self.max_kh <= self.k_h:
            raise ValueError(f"max_kh ({self.max_kh:g}) must be above k_h ({self.k_h:g})")
        return self

    def faces(self, which: str) -> list[str]:
        """The node-set names of ``upstream_face`` or ``downstream_face`` (as a list)."""
        v = getattr(self, which)
        return [] if v is None else [v] if isinstance(v, str) else list(v)


def dam_problems(dam: DamSpec, bodies, interfaces) -> list[tuple[str, str]]:
    """(field, problem) of the ``[dam]`` table's bodies and joint that the file does not
    define (``bodies``, ``interfaces``: the file's names), and a tailwater without a
    downstream face.  The face node sets are checked as every node set the file uses."""
    out = []
    bodies, interfaces = set(bodies), set(interfaces)
    for i, b in enumerate(dam.bodies):
        if b not in bodies:
            out.append((f"dam.bodies[{i}]", f"no body '{b}' (bodies: "
                        f"{', '.join(map(repr, sorted(bodies))) or 'none'})"))
    if dam.joint not in interfaces:
        out.append(("dam.joint", f"no interface '{dam.joint}' (interfaces: "
                    f"{', '.join(map(repr, sorted(interfaces))) or 'none'})"))
    if not dam.faces("upstream_face"):
        out.append(("dam.upstream_face", "is empty: give the node set(s) of the upstream "
                    "face"))
    if dam.tailwater > 0 and not dam.faces("downstream_face"):
        out.append(("dam.downstream_face", f"is needed with a tailwater ({dam.tailwater:g} "
                    "m): the node set of the downstream face"))
    return out


def _face_problem(dam: DamSpec, bodies: dict, ns) -> str | None:
    """Why the node set ``ns`` is not a face of the dam: not on a dam body, a node inside
    its body, or no boundary edge with both ends in the set (None: a face)."""
    if ns.body not in dam.bodies:
        return (f"node set '{ns.name}' is on body '{ns.body}', not on the dam's bodies "
                f"({', '.join(dam.bodies)})")
    b = bodies[ns.body]
    edges = np.asarray(b.boundary)
    on = np.zeros(b.n_nodes, bool)
    on[edges.ravel()] = True
    idx = np.asarray(ns.index)
    inner = idx[~on[idx]]
    if inner.size:
        p = b.points[inner[0]]
        return (f"node set '{ns.name}' is not on a boundary of body '{ns.body}': "
                f"{inner.size} of its nodes are inside it (e.g. node {int(inner[0])} at "
                f"({p[0]:g}, {p[1]:g}))")
    if not np.isin(edges[:, :2], idx).all(axis=1).any():
        return (f"node set '{ns.name}' has no edge of the boundary of body '{ns.body}' (a "
                "face needs two adjacent boundary nodes at least)")
    return None


def _joint_problem(dam: DamSpec, bodies: dict, plus, point) -> str | None:
    """Why ``point`` is not a node of the joint's dam side ``plus`` (None: it is)."""
    pts = bodies[plus.body].points[np.asarray(plus.index)]
    dist = np.hypot(*(pts - np.asarray(point)).T)
    span = float(np.ptp(pts, axis=0).max()) if len(pts) > 1 else 1.0
    k = int(np.argmin(dist))
    if dist[k] <= 1e-6 * max(span, 1.0):
        return None
    return (f"({point[0]:g}, {point[1]:g}) is not on the joint '{dam.joint}': the nearest "
            f"node of its dam side is ({pts[k, 0]:g}, {pts[k, 1]:g}), {dist[k]:.3g} m away")


def dam_geometry_problems(dam: DamSpec, model, faces: dict) -> list[tuple[str, str]]:
    """(field, problem) of the ``[dam]`` table's geometry on the built ``model``: the heel at
    y = 0 (the levels' datum), each face node set (``faces``: {"upstream_face": [NodeSet],
    "downstream_face": [...]}) on the boundary of a dam body, heel and toe nodes of the
    joint's dam side (S+), the drain line on the base between them.  Names that do not
    exist are :func:`dam_problems`' (skipped here)."""
    out = []
    if dam.heel[1] != 0.0:
        out.append(("dam.heel", f"is at y = {dam.heel[1]:g} m: the levels are elevations "
                    "with the datum at the heel; put the heel at y = 0 (translate the model)"))
    bodies = {b.name: b for b in model.bodies}
    for which, sets in faces.items():
        for ns in sets:
            why = _face_problem(dam, bodies, ns) if ns.body in bodies else None
            if why:
                out.append((f"dam.{which}", why))
    itf = next((i for i in model.interfaces if i.name == dam.joint), None)
    plus = getattr(itf, "plus", None)
    if plus is not None and getattr(plus, "body", None) in bodies:
        for which in ("heel", "toe"):
            why = _joint_problem(dam, bodies, plus, getattr(dam, which))
            if why:
                out.append((f"dam.{which}", why))
    L = float(np.hypot(dam.toe[0] - dam.heel[0], dam.toe[1] - dam.heel[1]))
    if L == 0:
        out.append(("dam.toe", "coincides with the heel"))
    elif dam.drain is not None:
        u = (np.asarray(dam.toe) - np.asarray(dam.heel)) / L
        r = np.asarray(dam.drain) - np.asarray(dam.heel)
        if not (0.0 < float(r @ u) < L and abs(r[0] * u[1] - r[1] * u[0]) <= 1e-6 * L):
            out.append(("dam.drain", f"({dam.drain[0]:g}, {dam.drain[1]:g}) is not on the "
                        "base between the heel and the toe"))
    return out


__all__ = ["DamSpec", "dam_geometry_problems", "dam_problems"]
