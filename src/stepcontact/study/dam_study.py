"""The dam study's static runs (issue 29 §3, first version): a gravity-dam section
(:class:`~stepcontact.study.dam.DamSection`) under self-weight, then the reservoir rising to
its normal level (the usual case), to its flood level (the unusual case) and on until the dam
slides or loses equilibrium (the incremental analysis to failure), in one run whose load
parameter is the reservoir level h (m).

:func:`run_dam` solves the section once (:func:`~stepcontact.solver.static.solve_static`) and
reads, with :func:`~stepcontact.results.safety.interface_safety`, the joint's figures at each
named level — ΣN, ΣQ, the friction-only and shear-friction factors, the overturning factor
about the toe, the resultant's position, the compressed and open lengths, σ_n at the heel and
the toe — and the **margins as factors on the level**: the level at the first opening of the
base, and the level at failure (sliding or overturning), each over the normal and the flood
level.  Beside them, the rigid-base hand statics of the same levels
(:func:`~stepcontact.study.dam.hand_statics`).  No guideline's criteria or verdicts here.

Example
-------
>>> from stepcontact.study.dam import DamSection
>>> st = run_dam(DamSection(cell=2.0))                       # doctest: +SKIP
>>> st.margins["failure / normal"]                           # doctest: +SKIP
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import brentq

from stepcontact.enums import ContactState, Status, Transition
from stepcontact.errors import SolverError
from stepcontact.model.combinations import Combination
from stepcontact.results.dam_checks import DamCheck, check_combination
from stepcontact.study.dam import (
    DAM,
    JOINT,
    DamSection,
    combinations,
    dam_model,
    dam_site,
    earthquake,
    hand_statics,
    hand_yield,
    joint_strength,
)
from stepcontact.study.dam_quake import QuakeRun, run_quake

#: the named levels of the study and what they stand for
CASES = {"self-weight": "self-weight (and tailwater), empty reservoir",
         "normal": "usual case: reservoir at the normal level",
         "flood": "unusual case: reservoir at the flood level"}


@dataclass
class NamedState:
    """The joint's figures at one state of the run (SI; forces per metre of dam, N; stresses
    Pa, σ_n ≤ 0 in compression; lengths m).  ``values``: the keys of
    :meth:`~stepcontact.results.safety.InterfaceSafety.at` plus ``sigma_heel``, ``sigma_toe``;
    ``hand``: :func:`~stepcontact.study.dam.hand_statics` at the level."""

    name: str
    description: str
    state: int
    level: float
    values: dict[str, Any]
    hand: dict[str, float]


@dataclass
class CombinationRun:
    """One load combination of the study: the ``combination``
    (:class:`~stepcontact.model.combinations.Combination`), its run ``result`` and its
    guideline ``checks`` (:class:`~stepcontact.results.dam_checks.DamCheck`)."""

    combination: Combination
    result: Any
    checks: DamCheck
    seconds: float = 0.0

    @property
    def verdict(self) -> str:
        """"pass", "FAIL" or "not evaluated" (no check with a required value)."""
        done = [r.passed for r in self.checks.rows if r.passed is not None]
        return "not evaluated" if not done else "pass" if all(done) else "FAIL"


@dataclass
class YieldAcceleration:
    """The incremental analysis to failure on the seismic coefficient: after the usual
    combination, k_h (with k_v in the section's ratio and the reservoir's hydrodynamic
    pressure) raised from 0 to ``section.max_kh`` on one segment whose λ is k_h.

    ``k_y``: the yield (critical) acceleration, g — the λ at which equilibrium is lost, an
    exact event (None: not lost up to ``top``; 0.0: lost before the earthquake); ``mode``
    (sliding, rotation…); ``design`` k_h and ``margin`` = k_y / k_h; ``first_slip`` and
    ``first_opening``: the k_h of the first CFE of the base to slip / to open on the segment;
    ``open_length`` (m) and ``crack_water`` (N per metre, the resultant of the crack water)
    at the last state; ``hand``: :func:`~stepcontact.study.dam.hand_yield` (rigid base, whole
    base compressed, no crack water); ``result`` the run."""

    k_y: float | None
    mode: str | None
    design: float
    top: float
    margin: float | None
    first_slip: float | None
    first_opening: float | None
    open_length: float
    crack_water: float
    hand: dict[str, float]
    result: Any
    message: str = ""
    seconds: float = 0.0


@dataclass
class DamStudy:
    """What :func:`run_dam` found.

    ``section``; ``result`` (the :class:`~stepcontact.results.result.StaticResult`);
    ``safety`` (its :class:`~stepcontact.results.safety.InterfaceSafety` for the joint, the
    normal level as the design value); ``named`` (the :class:`NamedState` of the self-weight,
    normal, flood, first-opening and last states); ``path``: arrays along the reservoir's
    states — ``level`` (m), ``crest_ux`` (m, the upstream crest corner's horizontal
    displacement), ``open_length`` (m), ``broken_length`` (m, a bonded joint's broken
    length); ``first_opening`` (level, x from the heel) or None (and ``first_break``, a
    bonded joint's first break); ``failure``: the level and
    mode of failure, or None when the dam holds up to ``section.top_level``; ``hand_levels``:
    the rigid-base levels of sliding and of heel tension; ``margins``: the factors on the
    level; ``seconds`` (CPU time of the run)."""

    section: DamSection
    result: Any
    safety: Any
    named: list[NamedState]
    path: dict[str, np.ndarray]
    first_opening: tuple[float, float] | None
    failure: tuple[float, str] | None
    hand_levels: dict[str, float | None]
    margins: dict[str, float | None]
    seconds: float = 0.0
    notes: list[str] = field(default_factory=list)
    first_break: tuple[float, float] | None = None
    combinations: list[CombinationRun] = field(default_factory=list)
    checks: DamCheck | None = None
    yield_acceleration: YieldAcceleration | None = None
    earthquake: QuakeRun | None = None

    def row(self, name: str) -> NamedState | None:
        return next((n for n in self.named if n.name == name), None)

    @property
    def verdicts(self) -> dict[str, str]:
        """{combination: "pass", "FAIL" or "not evaluated"} of the guideline checks."""
        return {c.combination.name: c.verdict for c in self.combinations}

    @property
    def verdict(self) -> str:
        """The overall verdict: "FAIL" if a combination fails, "pass" if every evaluated one
        passes, "not evaluated" without combinations or evaluated checks."""
        vs = [v for v in self.verdicts.values() if v != "not evaluated"]
        return "not evaluated" if not vs else "FAIL" if "FAIL" in vs else "pass"


class _Parametric:
    """The parametric section's builders (:mod:`stepcontact.study.dam`) under the names a
    model file's dam has them (:class:`stepcontact.study.dam_file.DamFile`): what the runs
    below take of a dam."""

    joint, body, heel = JOINT, DAM, (0.0, 0.0)

    def __init__(self, s: DamSection):
        self.s = s
        self.crest = s.corners[3]
        self.toe = (s.base_length, 0.0)

    def site(self):
        return dam_site(self.s)

    def combinations(self) -> list[Combination]:
        return combinations(self.s)

    def earthquake(self, k_h: float | None = None):
        return earthquake(self.s, k_h)

    def joint_strength(self):
        return joint_strength(self.s)

    def level_model(self, levels=None):
        return dam_model(self.s, levels)

    def hand_statics(self, level: float) -> dict[str, float]:
        return hand_statics(self.s, level)

    def hand_yield(self) -> dict[str, float]:
        return hand_yield(self.s)

    def hand_levels(self) -> dict[str, float | None]:
        return hand_levels(self.s)


def dam_of(s):
    """The builders of a dam: a :class:`~stepcontact.study.dam.DamSection`'s, or a model
    file's :class:`~stepcontact.study.dam_file.DamFile` itself (site, combinations,
    earthquake, joint strength, level model, hand figures; joint, body, heel, toe, crest)."""
    return _Parametric(s) if isinstance(s, DamSection) else s


def _joint(res, dam=None) -> np.ndarray:
    """The base's CFEs, heel to toe (by their distance along the base from the heel)."""
    name = JOINT if dam is None else dam.joint
    k = np.flatnonzero(np.asarray(res.cfe["interface"]) == list(res.interface_names).index(name))
    return k[np.argsort(_along(res, k, dam), kind="stable")]


def _along(res, k: np.ndarray, dam=None) -> np.ndarray:
    """Distance of the CFEs ``k`` from the heel along the base, m (x for the section)."""
    x = np.asarray(res.cfe["x"])[k, :2]
    if dam is None or isinstance(dam, _Parametric):
        return x[:, 0]
    heel, toe = np.asarray(dam.heel), np.asarray(dam.toe)
    return (x - heel) @ ((toe - heel) / np.hypot(*(toe - heel)))


def base_stresses(study: DamStudy, state: int) -> tuple[np.ndarray, np.ndarray]:
    """x from the heel (m; along the base for a model file's dam) and σ_n = N/A (Pa, ≤ 0 in
    compression) of the base's CFEs at ``state``."""
    res = study.result
    d = dam_of(study.section)
    k = _joint(res, d)
    return (_along(res, k, d),
            np.asarray(res.N)[state, k] / np.asarray(res.cfe["area"])[k])


def _segment_end(res, segment: int) -> int:
    idx = np.flatnonzero(np.asarray(res.segment) == segment)
    return int(idx[-1])


def _level_state(res, level: float) -> int | None:
    """The last state at the reservoir ``level`` (a segment of 'reservoir' ends there)."""
    lam, seg = np.asarray(res.lam, float), np.asarray(res.segment)
    reservoir = [g for g, (p, _, _) in enumerate(res.segments) if p == "reservoir"]
    hit = np.flatnonzero(np.isin(seg, reservoir) & (np.abs(lam - level) <= 1e-12 * level))
    return int(hit[-1]) if hit.size else None


def _hand_level(s, key: str, target: float) -> float | None:
    """The level h in (0, top_level] at which hand_statics' ``key`` falls to ``target`` (a
    root of the continuous statics; None if it does not within the range)."""
    d = dam_of(s)

    def g(h: float) -> float:
        return d.hand_statics(h)[key] - target

    lo, hi = 1e-9, s.top_level
    if g(lo) <= 0:
        return 0.0
    if g(hi) > 0:
        return None
    return float(brentq(g, lo, hi, xtol=1e-12, rtol=1e-13))


def hand_levels(s) -> dict[str, float | None]:
    """Rigid-base, uncracked limit-equilibrium levels (m): ``sliding`` (the shear-friction
    factor (c B + tan φ ΣV)/ΣH falls to 1) and ``heel_tension`` (the linear base pressure at
    the heel falls to 0: the resultant leaves the middle third)."""
    return {"sliding": _hand_level(s, "shear_friction_factor", 1.0),
            "heel_tension": _hand_level(s, "sigma_heel", 0.0)}


def _first_event(res, k: np.ndarray,
                 transition: Transition = Transition.OPENED) -> tuple[float, float] | None:
    """(level, x) of the first ``transition`` of a CFE of the base (opening, or a bond's
    break) while the reservoir rises."""
    reservoir = {g for g, (p, _, _) in enumerate(res.segments) if p == "reservoir"}
    on = set(k.tolist())
    for e in res.events:
        if e.segment in reservoir and e.cfe in on and e.transition == transition:
            return float(e.lam), float(e.x)
    return None


def _solve(model, what: str):
    from stepcontact.solver.static import solve_static

    res = solve_static(model)
    if res.status not in (Status.COMPLETED, Status.EQUILIBRIUM_LOST):
        raise SolverError(f"the dam's {what} run {res.message or res.status}: no answer to "
                          "report")
    return res


def run_combinations(s, say: Callable[[str], None] = lambda t: None
                     ) -> tuple[list[CombinationRun], DamCheck]:
    """Run each of the combinations of ``s`` (a :class:`~stepcontact.study.dam.DamSection`,
    :func:`~stepcontact.study.dam.combinations`, or a model file's
    :class:`~stepcontact.study.dam_file.DamFile`) and check its last state against the
    guideline (:func:`~stepcontact.results.dam_checks.check_combination`, the base joint)."""
    d = dam_of(s)
    site = d.site()
    runs, total = [], None
    for combo in d.combinations():
        say(f"combination '{combo.name}' ({combo.condition})")
        t0 = time.process_time()
        res = _solve(combo.model(site), f"'{combo.name}' combination")
        chk = check_combination(res, combo, site, guideline=s.guideline,
                                variant=s.guideline_variant, joints=[d.joint],
                                strength=d.joint_strength())
        runs.append(CombinationRun(combo, res, chk, time.process_time() - t0))
        total = chk if total is None else total + chk
    return runs, total


def run_yield(s, say: Callable[[str], None] = lambda t: None) -> YieldAcceleration:
    """The incremental analysis to failure on k_h (:class:`YieldAcceleration`): the usual
    combination, then one segment of the earthquake pattern from k_h = 0 to
    ``s.max_kh``; the yield acceleration is the λ at which equilibrium is lost (exact).
    ``s``: a :class:`~stepcontact.study.dam.DamSection` or a model file's
    :class:`~stepcontact.study.dam_file.DamFile`."""
    d = dam_of(s)
    site = d.site()
    usual = d.combinations()[0]
    combo = Combination("yield acceleration", "earthquake",
                        usual.cases + (d.earthquake(s.max_kh),))
    say(f"yield acceleration: the usual loads, then k_h 0 → {s.max_kh:g} (or failure)")
    t0 = time.process_time()
    res = _solve(combo.model(site), "yield-acceleration")
    seconds = time.process_time() - t0
    quake = [g for g, (p, _, _) in enumerate(res.segments) if p == "earthquake"]
    mult = next((m for m in res.multipliers if m.segment in quake), None)
    last_seg = int(np.asarray(res.segment)[-1])
    safety = res.interface_safety(d.joint, heel=d.heel)
    k_y = mode = None
    if res.status == Status.EQUILIBRIUM_LOST:
        k_y = float(res.lam[-1]) if last_seg in quake else 0.0
        if mult is not None and mult.equilibrium_lost is not None:
            k_y = float(mult.equilibrium_lost)
        mode = safety.mechanism or "loss of equilibrium"
    k = _joint(res, d)
    water = 0.0 if res.water is None else float(np.asarray(res.water, float)[-1, k].sum())
    return YieldAcceleration(
        k_y=k_y, mode=mode, design=float(s.k_h), top=float(s.max_kh),
        margin=None if k_y is None else k_y / float(s.k_h),
        first_slip=None if mult is None else mult.first_slip,
        first_opening=None if mult is None else mult.first_opening,
        open_length=float(safety.open_length[-1]), crack_water=water, hand=d.hand_yield(),
        result=res, message=str(res.message), seconds=seconds)


def run_dam(section, *,
            progress: Callable[[str], None] | None = None, checks: bool = True) -> DamStudy:
    """Solve ``section`` (self-weight, tailwater, then the level raised through the normal
    and flood levels to ``section.top_level``) and read the joint's figures; with
    ``checks`` (default) also run the section's load combinations with their guideline
    verdicts (:func:`run_combinations`) and the incremental analysis to failure on k_h
    (:func:`run_yield`).  ``progress`` gets a line of text at each step.  A run that ends
    without an answer (not completed and not a loss of equilibrium) is a
    :class:`~stepcontact.errors.SolverError`.  ``section``: a
    :class:`~stepcontact.study.dam.DamSection`, or a model file's
    :class:`~stepcontact.study.dam_file.DamFile` (:mod:`stepcontact.study.dam_file`)."""

    say = progress or (lambda text: None)
    s = section
    d = dam_of(s)
    cells = (f"{s.cells[0]} × {s.cells[1]} cells" if isinstance(s, DamSection) else
             f"the mesh of {s.source}")
    say(f"building the model: a {s.height:g} m dam, base {s.base_length:g} m, {cells}")
    model = d.level_model()
    say(f"solving: self-weight, then the level 0 → {s.normal_level:g} → {s.flood_level:g} → "
        f"{s.top_level:g} m (or failure)")
    t0 = time.process_time()
    res = _solve(model, "level")
    say(f"reading the results: {len(res.events)} events, {len(res.lam)} states")
    safety = res.interface_safety(d.joint, design=s.normal_level, heel=d.heel)
    k = _joint(res, d)
    reservoir = [g for g, (p, _, _) in enumerate(res.segments) if p == "reservoir"]
    last_load = _segment_end(res, reservoir[0] - 1)  # self-weight (and tailwater)
    states = np.flatnonzero(np.isin(np.asarray(res.segment), reservoir))
    states = np.r_[last_load, states]
    level = np.where(np.isin(np.asarray(res.segment)[states], reservoir),
                     np.asarray(res.lam, float)[states], 0.0)
    ux = np.asarray(res.node_history(point=d.crest, quantity="ux", body=d.body),
                    float)[states]
    area = np.asarray(res.cfe["area"], float)[k]
    st = np.asarray(res.state)[states][:, k]
    open_length = (st == int(ContactState.OPEN)) @ area / max(area.sum(), 1e-300) * \
        float(safety.joint_length or safety.length)
    bonded = st == int(ContactState.BONDED)
    broken = (~bonded) @ area / max(area.sum(), 1e-300) * float(
        safety.joint_length or safety.length) if s.bonded else np.zeros(len(states))
    path = {"state": states, "level": level, "crest_ux": ux, "open_length": open_length,
            "broken_length": broken}

    first = _first_event(res, k)
    broke = _first_event(res, k, Transition.BROKEN) if s.bonded else None
    fail = None
    limits = [(v, m) for v, m in ((safety.lam_sliding, "sliding"),
                                  (safety.lam_overturning, "overturning")) if v is not None]
    if limits:
        fail = min(limits)
        if safety.mechanism and safety.mechanism != "sliding":
            fail = (fail[0], safety.mechanism if fail[1] == "overturning" else fail[1])
    elif res.status == Status.EQUILIBRIUM_LOST:
        fail = (float(res.lam[-1]), "loss of equilibrium")

    named = []

    def add(name: str, description: str, i: int | None, lv: float) -> None:
        if i is None:
            return
        vals = safety.at(i)
        named.append(NamedState(name, description, int(i), float(lv), vals,
                                d.hand_statics(lv)))

    add("self-weight", CASES["self-weight"], last_load, 0.0)
    add("normal", f"{CASES['normal']}, h = {s.normal_level:g} m",
        _level_state(res, s.normal_level), s.normal_level)
    if s.flood_level != s.normal_level:
        add("flood", f"{CASES['flood']}, h = {s.flood_level:g} m",
            _level_state(res, s.flood_level), s.flood_level)
    for what, ev in (("first break", broke), ("first opening", first)):
        if ev is not None:
            i = next(int(j) for j, lv in zip(states, level, strict=True) if lv >= ev[0])
            verb = "the bond first breaks" if what == "first break" else "the base first opens"
            add(what, f"{verb}, at x = {ev[1]:.2f} m from the heel", i, ev[0])
    if fail is not None:
        add("failure", f"the last state of equilibrium: {fail[1]}", len(res.lam) - 1,
            float(res.lam[-1]))
    margins: dict[str, float | None] = {}
    limits_found = ([("first break", broke[0] if broke else None)] if s.bonded else []) + [
        ("first opening", first[0] if first else None), ("failure", fail[0] if fail else None)]
    for what, lv in limits_found:
        for case, h in (("normal", s.normal_level), ("flood", s.flood_level)):
            margins[f"{what} / {case}"] = None if lv is None else lv / h
    notes = []
    if _level_state(res, s.flood_level) is None:
        notes.append(f"the dam failed before the flood level ({s.flood_level:g} m)")
    if _level_state(res, s.normal_level) is None:
        notes.append(f"the dam failed before the normal level ({s.normal_level:g} m)")
    if fail is None:
        notes.append(f"the dam did not fail up to the highest level of the run, "
                     f"{s.top_level:g} m: the margins against failure are at least "
                     f"{s.top_level / s.normal_level:.3g} (normal) and "
                     f"{s.top_level / s.flood_level:.3g} (flood)")
    study = DamStudy(s, res, safety, named, path, first, fail, d.hand_levels(), margins,
                     time.process_time() - t0, notes, broke)
    if checks:
        study.combinations, study.checks = run_combinations(s, say)
        study.yield_acceleration = y = run_yield(s, say)
        margins["yield k_h / design k_h"] = y.margin
        if y.k_y is None:
            notes.append(f"equilibrium was not lost up to k_h = {y.top:g}: the yield "
                         f"acceleration is above it (margin at least {y.top / y.design:.3g})")
        study.seconds = time.process_time() - t0
    if getattr(s, "record", None) is not None:  # the record (stepcontact.study.dam_quake;
        # a model file's dam has none)
        y = study.yield_acceleration or run_yield(s, say)
        if y.k_y == 0.0:
            notes.append("the dam loses equilibrium under the usual loads: the earthquake "
                         "record is not run")
        else:
            study.earthquake = run_quake(s, y.k_y, say=say)
        study.seconds = time.process_time() - t0
    return study


def summary(study: DamStudy) -> dict[str, Any]:
    """The study's figures as plain JSON-able values (``summary.json`` of the report)."""
    def clean(v):
        if isinstance(v, float | np.floating):
            return float(v) if math.isfinite(v) else None
        if isinstance(v, np.integer | np.bool_):
            return v.item()
        if isinstance(v, dict):
            return {k: clean(x) for k, x in v.items()}
        if isinstance(v, list | tuple):
            return [clean(x) for x in v]
        if isinstance(v, os.PathLike):  # the earthquake record's files
            return str(v)
        return v

    import dataclasses

    return clean({
        "section": {f.name: (dataclasses.asdict(getattr(study.section, f.name))
                             if dataclasses.is_dataclass(getattr(study.section, f.name))
                             else getattr(study.section, f.name))
                    for f in dataclasses.fields(study.section)}
        if isinstance(study.section, DamSection) else study.section.as_dict(),
        "units": {"length": "m", "force": "N per metre of dam", "moment": "N·m per metre",
                  "stress": "Pa (σ_n ≤ 0 in compression in 'values'; compression > 0 in "
                            "'hand')", "level": "m above the base"},
        "status": str(study.result.status), "message": study.result.message,
        "first_opening": study.first_opening, "first_break": study.first_break,
        "failure": study.failure,
        "hand_levels": study.hand_levels, "margins": study.margins,
        "named": [{"name": n.name, "description": n.description, "state": n.state,
                   "level": n.level, "values": n.values, "hand": n.hand}
                  for n in study.named],
        "notes": study.notes, "cpu_seconds": study.seconds,
        "verdict": study.verdict, "verdicts": study.verdicts,
        "checks": [] if study.checks is None else [
            {"combination": r.combination, "joint": r.joint, "check": r.check,
             "value": r.value, "unit": r.unit, "required": r.required,
             "relation": r.relation, "verdict": r.verdict, "source": r.source,
             "checked": r.checked, "note": r.note} for r in study.checks.rows],
        "yield_acceleration": None if study.yield_acceleration is None else {
            k: getattr(study.yield_acceleration, k)
            for k in ("k_y", "mode", "design", "top", "margin", "first_slip",
                      "first_opening", "open_length", "crack_water", "hand", "message",
                      "seconds")},
        "earthquake": None if study.earthquake is None else study.earthquake.figures(),
    })


__all__ = ["CASES", "CombinationRun", "DamStudy", "NamedState", "YieldAcceleration",
           "base_stresses", "dam_of", "hand_levels", "run_combinations", "run_dam", "run_yield",
           "summary"]
