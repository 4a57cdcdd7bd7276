"""The dam study on a user's model file (issue 29 §3): ``stepcontact study dam --model
FILE.toml``.

The file's bodies, meshes (Gmsh too), materials, supports and interfaces are used as they are;
its ``[dam]`` table (:class:`~stepcontact.io.modelfile.dam.DamSpec`) names the dam's bodies,
the base joint, the upstream and downstream faces, the heel and the toe, and gives the water,
drains, silt, the joint's strength for the checks, the guideline and k_h, k_v.  The file's own
``[patterns]``, ``[[program]]``, ``[[stages]]``, ``[dynamics]`` and ``[[added_masses]]`` are
not used (a :class:`DamFileWarning`): the study writes its own programs.

:func:`dam_file` reads the file into a :class:`DamFile`, which gives the study what the
parametric section (:class:`~stepcontact.study.dam.DamSection`) gives it: the
:class:`~stepcontact.model.combinations.DamSite` (:meth:`DamFile.site`), the combinations
(:meth:`DamFile.combinations`: usual, flood, extreme, post-earthquake, as
:func:`stepcontact.study.dam.combinations`), the pseudo-static earthquake, the joint's strength
and the level run's model (:meth:`DamFile.model`: self-weight, tailwater, then the reservoir
raised through the levels, its factor the level h in m) — so that
:func:`~stepcontact.study.dam_study.run_dam` runs it unchanged.

The uplift under the base (EM 1110-2-2100 (2005) ch. 3 [to be checked]): full reservoir head h
at the heel, the tailwater head t at the toe, at the drain line (distance X from the heel along
the base of length L) the head t + K (h − t), K = (1 − E)(L − X)/L for a drain efficiency E
(or K given), linear between (:class:`~stepcontact.model.combinations.BaseUplift`).

The rigid-base hand statics (:meth:`DamFile.hand_statics`, the figures of
:func:`stepcontact.study.dam.hand_statics`) are summed from the model's own geometry: the
weight of the dam's cells, the hydrostatic pressure integrated exactly on the faces' edges,
the uplift along the base — the sums of the forces and of their moments about the toe that a
reviewer checks.  The yield acceleration has no hand check here.

Example
-------
>>> from stepcontact.study.dam_file import dam_file                    # doctest: +SKIP
>>> from stepcontact.study.dam_study import run_dam                    # doctest: +SKIP
>>> study = run_dam(dam_file("examples/data/dam_study.toml"))          # doctest: +SKIP
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.io.modelfile.build import _Builder
from stepcontact.io.modelfile.dam import DamSpec, dam_geometry_problems
from stepcontact.io.modelfile.errors import _Problems, _validate
from stepcontact.io.modelfile.load import _read_toml
from stepcontact.model import Model, Segment
from stepcontact.model.combinations import (
    BaseUplift,
    Combination,
    DamSite,
    Earthquake,
    Reservoir,
    SelfWeight,
    Silt,
    Tailwater,
)
from stepcontact.model.supports import NodeSet
from stepcontact.model.water import UNIT_WEIGHT_WATER
from stepcontact.results.dam_checks import JointStrength
from stepcontact.study.dam import check_guideline

#: gravity, m/s² (as the parametric section's, :data:`stepcontact.study.dam.G`)
G = 9.81
#: the parts of a model file the study does not use
IGNORED = ("patterns", "program", "stages", "dynamics", "added_masses")


class DamFileWarning(UserWarning):
    """A part of a model file that the dam study does not use."""


@dataclass(frozen=True, eq=False)
class DamFile:
    """A user's model (``model``: bodies, supports and interfaces, no loads) and its ``[dam]``
    table ``spec``; ``upstream``/``downstream``: the faces' node sets; ``source``: the file.
    Built by :func:`dam_file`; the checks of the geometry name the field of ``[dam]``."""

    model: Model
    spec: DamSpec
    upstream: tuple[NodeSet, ...]
    downstream: tuple[NodeSet, ...]
    source: str = ""

    def __post_init__(self):
        d = self.spec
        check_guideline(d.guideline, d.guideline_variant)
        problems = dam_geometry_problems(d, self.model, {"upstream_face": self.upstream,
                                                         "downstream_face": self.downstream})
        if problems:
            raise ModelError(*problems[0])
        if not self.top_level > self.flood_level:
            raise ModelError("dam.max_level", f"must be above the flood level "
                             f"({self.flood_level:g} m), got {self.top_level:g}")
        if d.silt_level is not None and d.silt_level > self.height:
            raise ModelError("dam.silt_level", f"must be at most the dam's height "
                             f"({self.height:g} m), got {d.silt_level:g}")
        if self.interface.bond is not None and d.friction_angle is None:
            raise ModelError("dam.friction_angle", f"the joint '{d.joint}' has a bond: give "
                             "the peak friction angle φ of its checks (degrees)")

    # ---------------------------------------------------------------- geometry checks ---
    def _body(self, name: str):
        return next(b for b in self.model.bodies if b.name == name)

    # ----------------------------------------------------------------- what the study uses ---
    @property
    def interface(self):
        return next(i for i in self.model.interfaces if i.name == self.spec.joint)

    @property
    def joint(self) -> str:
        """The base joint's interface name."""
        return self.spec.joint

    @property
    def body(self) -> str:
        """The body of the crest point (the first dam body)."""
        return self.crest_body()[0]

    @property
    def heel(self) -> tuple[float, float]:
        return tuple(map(float, self.spec.heel))

    @property
    def toe(self) -> tuple[float, float]:
        return tuple(map(float, self.spec.toe))

    def crest_body(self) -> tuple[str, tuple[float, float]]:
        """(body, point) of the λ–u curve: ``[dam] crest`` on the dam body that has a node
        there, or the highest node of the upstream face."""
        if self.spec.crest is not None:
            c = np.asarray(self.spec.crest, float)
            for name in self.spec.bodies:
                pts = self._body(name).points
                if np.min(np.hypot(*(pts - c).T)) <= 1e-6 * max(self.height, 1.0):
                    return name, (float(c[0]), float(c[1]))
            raise ModelError("dam.crest", f"({c[0]:g}, {c[1]:g}) is not a node of the dam's "
                             "bodies")
        best = max(((ns.body, self._body(ns.body).points[i]) for ns in self.upstream
                    for i in ns.index), key=lambda t: t[1][1])
        return best[0], (float(best[1][0]), float(best[1][1]))

    @property
    def crest(self) -> tuple[float, float]:
        return self.crest_body()[1]

    @property
    def height(self) -> float:
        """The dam's height above the heel, m (its bodies' highest node)."""
        return float(max(self._body(b).points[:, 1].max() for b in self.spec.bodies))

    @property
    def base_length(self) -> float:
        """Heel to toe, m."""
        return float(math.dist(self.spec.heel, self.spec.toe))

    @property
    def normal_level(self) -> float:
        return float(self.spec.normal_level)

    @property
    def flood_level(self) -> float:
        return float(self.spec.normal_level if self.spec.flood_level is None
                     else self.spec.flood_level)

    @property
    def top_level(self) -> float:
        """The highest level of the run to failure, m (``max_level``, default 3 × height)."""
        return 3.0 * self.height if self.spec.max_level is None else float(self.spec.max_level)

    @property
    def levels(self) -> tuple[float, ...]:
        """The level run's segment ends, m: every ``level_step`` (default height / 20), the
        normal, flood and top levels (as :attr:`stepcontact.study.dam.DamSection.levels`)."""
        step = self.height / 20 if self.spec.level_step is None else float(self.spec.level_step)
        n = int(math.floor(self.top_level / step + 1e-9))
        stops = {round(k * step, 12) for k in range(1, n + 1)}
        stops |= {self.normal_level, self.flood_level, self.top_level}
        return tuple(sorted(v for v in stops if 0 < v <= self.top_level))

    @property
    def bonded(self) -> bool:
        return self.interface.bond is not None

    @property
    def friction_angle(self) -> float:
        """φ of the checks, degrees (``[dam] friction_angle``, default atan of the
        interface's friction)."""
        if self.spec.friction_angle is not None:
            return float(self.spec.friction_angle)
        return math.degrees(math.atan(float(self.interface.friction)))

    def __getattr__(self, key: str):
        # the [dam] table's plain values (k_h, k_v, max_kh, guideline, tailwater, ...)
        if key != "spec" and key in DamSpec.model_fields:
            return getattr(self.spec, key)
        raise AttributeError(key)

    @property
    def drain_ratio(self) -> float:
        """The drains' head ratio K (1 without drains): given, or (1 − E)(L − X)/L."""
        d = self.spec
        if d.drain is None:
            return 1.0
        if d.drain_ratio is not None:
            return float(d.drain_ratio)
        L = self.base_length
        X = float(math.dist(d.heel, d.drain))
        return (1.0 - float(d.drain_efficiency)) * (L - X) / L

    # -------------------------------------------------------------------- the builders ---
    def site(self) -> DamSite:
        """The model without loads as a :class:`~stepcontact.model.combinations.DamSite`."""
        d = self.spec
        return DamSite(self.model, base=d.joint, heel=self.heel, toe=self.toe,
                       upstream=self.upstream, dam=tuple(d.bodies),
                       downstream=self.downstream or None)

    def static_cases(self, level: float, *, silt: bool = True) -> tuple:
        """Self-weight, the reservoir at ``level`` (m), the tailwater, the uplift (drained or
        not) and (``silt``) the silt — as :func:`stepcontact.study.dam._static_cases`."""
        d = self.spec
        cases: list = [SelfWeight(g=G), Reservoir(float(level), crack_water=d.crack_water,
                                                  unit_weight=UNIT_WEIGHT_WATER)]
        if d.tailwater > 0:
            cases.append(Tailwater(float(d.tailwater), unit_weight=UNIT_WEIGHT_WATER))
        cases.append(self.uplift())
        if silt and d.silt_level is not None:
            cases.append(Silt(float(d.silt_level), float(d.silt_unit_weight), 1.0))
        return tuple(cases)

    def uplift(self) -> BaseUplift:
        """The uplift case: the drain line with its head ratio K, or none."""
        drain = None if self.spec.drain is None else tuple(map(float, self.spec.drain))
        return BaseUplift(drain=drain, ratio=self.drain_ratio if drain else 1.0 / 3.0,
                          unit_weight=UNIT_WEIGHT_WATER)

    def earthquake(self, k_h: float | None = None) -> Earthquake:
        """The pseudo-static earthquake at ``k_h`` (default the design k_h), k_v in the ratio
        k_v/k_h, with the reservoir's Westergaard pressure."""
        kh = float(self.spec.k_h if k_h is None else k_h)
        return Earthquake(kh, k_v=float(self.spec.k_v) * kh / float(self.spec.k_h), g=G)

    def combinations(self) -> list[Combination]:
        """usual, unusual (flood) (when the flood level is above the normal one), extreme
        (earthquake), post-earthquake (:func:`stepcontact.study.dam.combinations`)."""
        usual = self.static_cases(self.normal_level)
        out = [Combination("usual", "usual", usual)]
        if self.flood_level != self.normal_level:
            out.append(Combination("unusual (flood)", "flood",
                                   self.static_cases(self.flood_level)))
        quake = self.earthquake()
        return out + [Combination("extreme (earthquake)", "earthquake", usual + (quake,)),
                      Combination("post-earthquake", "post-earthquake", usual + (quake,))]

    def joint_strength(self) -> JointStrength:
        d = self.spec
        return JointStrength(cohesion=float(d.cohesion), friction_angle=self.friction_angle,
                             residual_cohesion=float(d.residual_cohesion),
                             residual_friction_angle=d.residual_friction_angle,
                             compressive_strength=d.compressive_strength)

    def level_model(self, levels: tuple[float, ...] | None = None) -> Model:
        """The level run: self-weight (pattern ``self-weight``), the tailwater, then the
        reservoir (its factor the level, m) through ``levels`` (default :attr:`levels`); no
        silt (as the parametric section's level run, :func:`stepcontact.study.dam.dam_model`)."""
        site = self.site()
        combo = Combination("level run", "usual", self.static_cases(self.top_level, silt=False))
        patterns = combo.patterns(site)
        program = [Segment("self-weight", 1.0)]
        if any(p.name == "tailwater" for p in patterns):
            program.append(Segment("tailwater", 1.0))
        program += [Segment("reservoir", float(h))
                    for h in (self.levels if levels is None else levels)]
        return site.model.add(*patterns, *program)

    def hand_statics(self, level: float) -> dict[str, float]:
        """Rigid-base limit-equilibrium statics at the reservoir ``level`` (m) from the
        model's own geometry — the keys of :func:`stepcontact.study.dam.hand_statics`, per the
        model's thickness (per metre of dam in plane strain): the weight ρ g A of the dam's
        cells (areas and centroids of their corner polygons), the hydrostatic pressure
        γ_w max(h − y, 0) on each edge of the upstream face (and of the downstream face at
        the tailwater level, the silt's K γ'_s on the upstream face), normal to the edge and
        integrated exactly (linear on the wet part of a straight edge: Simpson's rule), and
        the uplift γ_w × the head of :class:`~stepcontact.model.combinations.BaseUplift`
        along the base; uncracked base, no crack water.  Forces are resolved on the global
        axes (the base horizontal, as the section's); moments about the toe, positive when
        they resist; then ΣV, ΣH, ΣM, the resultant's position, e and the linear base
        pressures ΣV/L (1 ∓ 6e/L), and the factors tan φ ΣV/ΣH, (c L + tan φ ΣV)/ΣH and
        ΣM_r/ΣM_o.  Straight cell edges are assumed (the corner nodes)."""
        return _hand_statics(self, float(level))

    def hand_yield(self) -> None:
        """No rigid-base hand check of the yield acceleration for a model file's dam."""
        return None

    def hand_levels(self) -> dict[str, float | None]:
        """The rigid-base levels of sliding and of heel tension from :meth:`hand_statics`
        (:func:`stepcontact.study.dam_study.hand_levels`)."""
        from stepcontact.study.dam_study import hand_levels

        return hand_levels(self)

    def as_dict(self) -> dict:
        """The ``[dam]`` table and the file (``summary.json``)."""
        return {"model_file": self.source, **self.spec.model_dump(),
                "height": self.height, "base_length": self.base_length,
                "friction_angle_used": self.friction_angle, "drain_ratio_K": self.drain_ratio}


def _cell_weight(model: Model, name: str, g: float) -> tuple[float, np.ndarray]:
    """(weight ρ g A, centroid) of body ``name`` from its cells' corner polygons (per unit
    thickness)."""
    b = next(x for x in model.bodies if x.name == name)
    nc = 4 if str(b.element).startswith("quad") else 3
    P = b.points[np.asarray(b.cells)[:, :nc]]  # (cells, corners, 2)
    Q = np.roll(P, -1, axis=1)
    cross = P[..., 0] * Q[..., 1] - Q[..., 0] * P[..., 1]
    A = 0.5 * cross.sum(axis=1)  # signed
    c = ((P + Q) * cross[..., None]).sum(axis=1) / (6.0 * A[:, None])
    area = np.abs(A)
    return float(b.material.density * g * area.sum()), (area @ c) / area.sum()


def _face_edges(model: Model, ns: NodeSet) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """(P0, P1, outward normal) of each boundary edge of ``ns``'s body with both ends in the
    set (the edges a WaterLoad loads)."""
    b = next(x for x in model.bodies if x.name == ns.body)
    edges = np.asarray(b.boundary)[:, :2]
    mine = edges[np.isin(edges, np.asarray(ns.index)).all(axis=1)]
    cells = np.asarray(b.cells)
    out = []
    for a, c in mine:  # the face's edges (not a hot path: tens of edges)
        owner = cells[np.flatnonzero((cells == a).any(axis=1) & (cells == c).any(axis=1))[0]]
        centre = b.points[owner].mean(axis=0)
        p0, p1 = b.points[a], b.points[c]
        t = (p1 - p0) / np.hypot(*(p1 - p0))
        n = np.array([t[1], -t[0]])
        if n @ (p0 - centre) < 0:
            n = -n
        out.append((p0, p1, n))
    return out


def _pressure_piece(p0, p1, q0: float, q1: float) -> tuple[float, np.ndarray]:
    """(∫ q ds, the point of action) of a pressure linear from q0 at p0 to q1 at p1."""
    L = float(np.hypot(*(p1 - p0)))
    F = 0.5 * (q0 + q1) * L
    if F == 0.0:
        return 0.0, p0
    s = L / 6.0 * (4 * 0.5 * (q0 + q1) * 0.5 * L + q1 * L) / F  # ∫ q s ds / ∫ q ds (Simpson)
    return F, p0 + (p1 - p0) * (s / L)


def _hydrostatic(model: Model, faces, level: float, gamma: float
                 ) -> list[tuple[np.ndarray, np.ndarray]]:
    """(force on the body, point of action) per wet edge of ``faces`` under γ max(h − y, 0)."""
    out = []
    for ns in faces:
        for p0, p1, n in _face_edges(model, ns):
            y0, y1 = float(p0[1]), float(p1[1])
            if min(y0, y1) >= level:
                continue
            if max(y0, y1) > level:  # the wet part of the edge
                w = (level - y0) / (y1 - y0)
                cut = p0 + (p1 - p0) * w
                p0, p1 = (p0, cut) if y0 < level else (cut, p1)
            F, at = _pressure_piece(p0, p1, gamma * (level - p0[1]), gamma * (level - p1[1]))
            out.append((-F * n, at))
    return out


def _hand_statics(d: DamFile, h: float) -> dict[str, float]:
    """:meth:`DamFile.hand_statics`."""
    site, toe, sgn = d.site(), np.asarray(d.toe), (1.0 if d.toe[0] >= d.heel[0] else -1.0)
    t_mul = float(d.model.thickness)

    def moments(items) -> tuple[float, float, float, float]:
        """(horizontal force downstream, vertical force down, their moments about the toe,
        + resisting)."""
        H = V = MH = MV = 0.0
        for f, at in items:
            r = np.asarray(at) - toe
            H += sgn * f[0]
            V -= f[1]
            MH += sgn * (-r[1] * f[0])
            MV += sgn * (r[0] * f[1])
        return H * t_mul, V * t_mul, MH * t_mul, MV * t_mul

    W = MW = 0.0
    for name in d.spec.bodies:
        w, c = _cell_weight(d.model, name, G)
        W += w * t_mul
        MW += sgn * (toe[0] - c[0]) * w * t_mul
    Hu, Vu, MHu, MVu = moments(_hydrostatic(d.model, d.upstream, h, UNIT_WEIGHT_WATER))
    t = float(d.spec.tailwater)
    Hd, Vd, MHd, MVd = moments(_hydrostatic(d.model, d.downstream, t, UNIT_WEIGHT_WATER)) \
        if t > 0 else (0.0, 0.0, 0.0, 0.0)
    Hd = 0.0 - Hd  # the tailwater pushes upstream: its thrust as a positive number
    silt = d.spec.silt_level
    Hs, Vs, MHs, MVs = moments(_hydrostatic(d.model, d.upstream, float(silt),
                                            float(d.spec.silt_unit_weight))) \
        if silt is not None else (0.0, 0.0, 0.0, 0.0)
    uplift = d.uplift()
    pts = np.asarray(uplift.heads(site, h - d.heel[1], t - d.toe[1] if t > 0 else 0.0))
    m = np.array([-(toe - d.heel)[1], (toe - d.heel)[0]]) * sgn / d.base_length  # into the dam
    pieces = [_pressure_piece(pts[i, :2], pts[i + 1, :2], UNIT_WEIGHT_WATER * pts[i, 2],
                              UNIT_WEIGHT_WATER * pts[i + 1, 2]) for i in range(len(pts) - 1)]
    _, Uv, _, MU = moments([(F * m, at) for F, at in pieces])
    U = -Uv
    sum_V = W + Vu + Vd + Vs - U
    sum_H = Hu + Hs - Hd
    parts = [MW, MHu, MVu, MHd, MVd, MHs, MVs, MU]
    resisting = sum(v for v in parts if v > 0)
    overturning = -sum(v for v in parts if v < 0)
    sum_M = resisting - overturning
    L = d.base_length
    from_toe = sum_M / sum_V if sum_V else float("nan")
    e = L / 2 - from_toe
    tan, c = math.tan(math.radians(d.friction_angle)), float(d.spec.cohesion)

    def ratio(a: float, b: float) -> float:
        return a / b if b > 0 else float("inf")

    def lever(a: float, b: float) -> float:  # 0 without the force
        return a / b if b else 0.0

    return {"level": h, "W": W, "W_lever": lever(MW, W), "H_up": Hu,
            "H_up_arm": lever(-MHu, Hu), "V_up": Vu, "V_up_lever": lever(MVu, Vu),
            "H_down": Hd, "H_down_arm": lever(MHd, Hd), "V_down": Vd,
            "V_down_lever": lever(MVd, Vd), "H_silt": Hs, "H_silt_arm": lever(-MHs, Hs),
            "V_silt": Vs, "U": U, "U_lever": lever(-MU, U), "sum_V": sum_V,
            "sum_H": sum_H, "M_resisting": resisting, "M_overturning": overturning,
            "sum_M": sum_M, "resultant_from_toe": from_toe, "eccentricity": e,
            "sigma_heel": sum_V / L * (1 - 6 * e / L), "sigma_toe": sum_V / L * (1 + 6 * e / L),
            "sliding_factor": ratio(tan * sum_V, sum_H),
            "shear_friction_factor": ratio(c * L + tan * sum_V, sum_H),
            "overturning_factor": ratio(resisting, overturning)}


def dam_file(path: str | Path) -> DamFile:
    """Read a model file with a ``[dam]`` table into a :class:`DamFile` (errors:
    :class:`~stepcontact.errors.ModelError` naming the field, e.g. ``dam.upstream_face``; a
    file without ``[dam]`` is an error naming the file).  The parts of the file the study does
    not use are a :class:`DamFileWarning`."""
    path = Path(str(path))
    spec = _validate(_read_toml(path))
    if spec.dam is None:
        raise ModelError(str(path), "has no [dam] table: the dam study needs one (the dam's "
                         "bodies, joint, faces, heel, toe and levels; docs/dam-study.md, "
                         "'From a model file')")
    problems = _Problems()
    builder = _Builder(spec, path.parent, problems)
    model = builder.model()
    problems.raise_if_any()
    assert model is not None
    for where, message in problems.warnings:
        warnings.warn(f"{where}: {message}", problems.category.get((where, message),
                                                                   FutureWarning), stacklevel=2)
    ignored = [k for k in IGNORED if getattr(spec, k)]
    if ignored:
        warnings.warn(DamFileWarning(
            f"{path.name}: {', '.join(ignored)} not used by the dam study (its loads and "
            "programs come from [dam])"), stacklevel=2)
    bare = model.replace(patterns=(), program=(), stages=(), dynamics=None, added_masses=())
    sets = builder.sets
    d = spec.dam
    out = DamFile(bare, d, tuple(sets[n] for n in d.faces("upstream_face")),
                  tuple(sets[n] for n in d.faces("downstream_face")), source=str(path))
    itf = out.interface
    if d.friction_angle is not None and itf.bond is None and not math.isclose(
            math.tan(math.radians(d.friction_angle)), float(itf.friction), rel_tol=1e-9):
        warnings.warn(DamFileWarning(
            f"dam.friction_angle: the checks use tan {d.friction_angle:g}° = "
            f"{math.tan(math.radians(d.friction_angle)):.6g} but the joint '{d.joint}' slides "
            f"in the runs with its friction {float(itf.friction):.6g}"), stacklevel=2)
    return out





# ------------------------------------------------------------------------- the report ---

def plot_model_section(study, path=None, *, dpi: float | None = None):
    """The model file's dam with its loads (m): the outline of every body's mesh (the dam's
    bodies dark), the upstream and downstream faces, heel, toe, crest point and drain line,
    the normal and flood levels and the tailwater; below, the uplift head along the base (m
    of water) at the normal and flood levels, uncracked."""
    from matplotlib.collections import LineCollection

    from stepcontact.post.common import DPI, figure_path, new_figure

    dpi = DPI if dpi is None else dpi
    p = figure_path(path, dpi)
    s: DamFile = study.section
    fig = new_figure(figsize=(9.0, 7.6))
    ax, axu = fig.subplots(2, 1, height_ratios=(3.0, 1.2))
    ax.set_aspect("equal", adjustable="datalim")
    for b in s.model.bodies:
        mine = b.name in s.spec.bodies
        edges = np.asarray(b.boundary)[:, :2]
        ax.add_collection(LineCollection(b.points[edges], colors="0.2" if mine else "#a08c64",
                                         linewidths=1.2 if mine else 0.8))
        ax.plot([], [], color="0.2" if mine else "#a08c64",
                label=f"{'dam' if mine else 'other'} body '{b.name}' (mesh outline)")
    for faces, color, label in ((s.upstream, "#1f77b4", "upstream face"),
                                (s.downstream, "#2ca02c", "downstream face")):
        for i, ns in enumerate(faces):
            pts = s._body(ns.body).points[np.asarray(ns.index)]
            ax.plot(pts[:, 0], pts[:, 1], ".", color=color, ms=5,
                    label=f"{label} '{ns.name}'" if i == 0 else None)
    H = s.height
    ups = np.concatenate([s._body(ns.body).points[np.asarray(ns.index)] for ns in s.upstream])
    x_up = float(ups[:, 0].min())
    sign = 1.0 if s.toe[0] >= s.heel[0] else -1.0
    reach = x_up - sign * 0.3 * H
    for lv, name, color in ((s.flood_level, "flood", "#ff7f0e"),
                            (s.normal_level, "normal", "#1f77b4")):
        y = min(lv, H)
        ax.plot([reach, x_up], [y, y], color=color, lw=1.4, ls="--",
                label=f"{name} level {lv:g} m")
    if s.spec.tailwater > 0:
        t = float(s.spec.tailwater)
        ax.plot([s.toe[0], s.toe[0] + sign * 0.3 * H], [t, t], color="#17becf", lw=1.4,
                ls="--", label=f"tailwater {t:g} m")
    ax.plot(*s.heel, "v", color="#d62728", ms=8, label=f"heel ({s.heel[0]:g}, {s.heel[1]:g})")
    ax.plot(*s.toe, "^", color="#9467bd", ms=8, label=f"toe ({s.toe[0]:g}, {s.toe[1]:g})")
    ax.plot(*s.crest, "o", mfc="none", color="k", ms=8,
            label=f"crest point ({s.crest[0]:g}, {s.crest[1]:g})")
    if s.spec.drain is not None:
        xd, yd = s.spec.drain
        ax.plot([xd, xd], [yd, yd - 0.2 * H], color="k", lw=1.5, ls=":",
                label=f"drains, K = {s.drain_ratio:.4g}")
    ax.autoscale_view()
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"Dam of {Path(s.source).name}: height {H:g} m, base {s.base_length:g} m "
                 f"(joint '{s.joint}')", fontsize="medium")
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="x-small", frameon=False)
    site = s.site()
    uplift = s.uplift()
    for lv, name, color in ((s.normal_level, "normal", "#1f77b4"),
                            (s.flood_level, "flood", "#ff7f0e")):
        pts = np.asarray(uplift.heads(site, lv - s.heel[1], float(s.spec.tailwater) - s.toe[1]))
        dist = np.hypot(pts[:, 0] - s.heel[0], pts[:, 1] - s.heel[1])
        axu.plot(dist, pts[:, 2], color=color, lw=1.5, marker=".",
                 label=f"{name} level {lv:g} m")
    return finish_uplift_panel(fig, axu, (0.0, s.base_length),
                               "distance from the heel along the base (m)", p, dpi)


def finish_uplift_panel(fig, axu, xlim: tuple[float, float], xlabel: str, path, dpi: float):
    """The uplift-head panel of a dam's section figure (this module's and the parametric
    study's, :mod:`stepcontact.study.dam_report`) dressed — limits, labels (head in m), grid,
    the legend beside it — and the figure saved to ``path`` (None: not saved)."""
    from stepcontact.post.common import save_figure

    axu.set_ylim(bottom=0.0)
    axu.set_xlim(*xlim)
    axu.set_xlabel(xlabel)
    axu.set_ylabel("uplift head (m)")
    axu.grid(True, alpha=0.3)
    axu.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="x-small",
               frameon=False, title="uncracked base", title_fontsize="x-small")
    save_figure(fig, path, dpi)
    return fig


def report_inputs(s: DamFile) -> list:
    """The report's "Model and inputs": the file, its bodies and the ``[dam]`` table."""
    from stepcontact.study.report import _Heading, _modulus, _Para, _Table

    bodies = [(b.name, "dam" if b.name in s.spec.bodies else "other",
               f"{b.n_nodes} nodes, {len(b.cells)} cells",
               f"E = {_modulus(b.material.E)}, ν = {b.material.nu:g}, ρ = "
               f"{b.material.density:g} kg/m³") for b in s.model.bodies]
    rows = [(k, "—" if v is None else f"{v:g}" if isinstance(v, float) else str(v),
             DamSpec.model_fields[k].description or "")
            for k, v in s.spec.model_dump().items()]
    itf = s.interface
    derived = [("height above the heel", f"{s.height:g}", "m"),
               ("base length heel → toe", f"{s.base_length:g}", "m"),
               ("φ of the checks", f"{s.friction_angle:g}", "°"),
               ("the interface's friction coefficient", f"{float(itf.friction):g}", "–"),
               ("the interface's bond", "yes" if itf.bond is not None else "none", ""),
               ("drain head ratio K", f"{s.drain_ratio:.6g}", "–"),
               ("levels of the level run", f"{len(s.levels)} up to {s.top_level:g}", "m")]
    return [_Heading(2, "Model and inputs"),
            _Para(f"The model file {s.source}: its bodies, supports and interfaces as given; "
                  "its [dam] table below (SI units; plane strain, per metre of dam; levels "
                  "are elevations above the heel). The file's own load patterns, program, "
                  "stages and dynamics are not used by the study."),
            _Table(("body", "role", "mesh", "material"), bodies),
            _Table(("[dam] field", "value", "meaning"), rows),
            _Table(("derived", "value", "unit"), derived)]


def report_assumptions(s: DamFile) -> list:
    """The report's assumptions for a model file's dam."""
    from stepcontact.study.report import _Heading, _List

    d = s.spec
    uplift = ("Uplift under the base: full reservoir head h at the heel, the tailwater head "
              "t at the toe, linear between" if d.drain is None else
              f"Uplift under the base: full head h at the heel, t at the toe and t + K (h − t) "
              f"at the drain line ({d.drain[0]:g}, {d.drain[1]:g}), K = {s.drain_ratio:.4f}, "
              "linear between (EM 1110-2-2100 (2005) ch. 3 [to be checked])")
    return [_Heading(2, "Assumptions"), _List([
        "Plane strain (or as the file's [model] says), per metre of dam; the file's bodies "
        "linear elastic, its supports and interfaces as given; the only nonlinearity is the "
        "contact (unilateral, Coulomb friction, bonds), solved exactly event by event "
        "(Lukashevich & Rozin 2013).",
        "Loads (stepcontact.model.combinations on the file's DamSite): self-weight of the "
        f"dam's bodies ({', '.join(d.bodies)}, g = {G:g} m/s²); the reservoir's hydrostatic "
        "pressure (γ_w = 9810 N/m³) on the upstream face, its factor the level; the tailwater "
        "on the downstream face; the silt as an equivalent fluid. The weight of the other "
        "bodies is not applied.",
        uplift + "; it acts on both faces of the joint.",
        ("Crack water: where the joint has opened in a run connected to the heel, the full "
         "reservoir pressure replaces the uplift." if d.crack_water else "No crack water."),
        "The level run: self-weight, the tailwater, then the reservoir from the heel up "
        f"through the normal ({s.normal_level:g} m) and flood ({s.flood_level:g} m) levels to "
        f"{s.top_level:g} m or until the dam loses equilibrium (no silt in this run).",
        "Combinations: usual (normal level), unusual (flood level, when above the normal), "
        f"extreme (the usual loads and the pseudo-static earthquake k_h = {d.k_h:g}, k_v = "
        f"{d.k_v:g}, with Westergaard's pressure on the upstream face), post-earthquake; the "
        "yield acceleration: after the usual loads, k_h raised from 0 to "
        f"{d.max_kh:g} until equilibrium is lost (an exact event).",
        f"Checks of the joint '{d.joint}' with φ = {s.friction_angle:g}°, c = "
        f"{d.cohesion / 1e3:g} kPa against {d.guideline} "
        f"({d.guideline_variant or 'its default variant'}); required values marked [to be "
        "checked] were not confirmed against the document.",
        "Moments are about the toe; the resultant's position is measured from the toe along "
        "the base. Hand statics (rigid base, uncracked, no crack water): the weight of the "
        "dam's cells (corner polygons), the hydrostatic pressure integrated exactly on the "
        "faces' edges and the uplift along the base, resolved on the global axes (a "
        "horizontal base assumed for ΣV, ΣH and the linear base pressures); no hand check of "
        "the yield acceleration.",
        "One mesh (the file's): the levels of first opening and failure depend on it (the "
        "heel is a singular corner of the elastic solution).",
    ])]

__all__ = ["IGNORED", "DamFile", "DamFileWarning", "dam_file", "plot_model_section",
           "report_assumptions", "report_inputs"]
