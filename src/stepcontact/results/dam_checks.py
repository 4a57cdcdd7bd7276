"""Gravity-dam checks per load combination and per joint, with a guideline's required values.

The required values of USACE EM 1110-2-2100 (2005), FERC Engineering Guidelines ch. 3 (2016)
and the CDA Dam Safety Guidelines 2007 (2013 ed.) are data (``stepcontact/data/
guidelines/dam_guidelines.toml``), every value with its source and whether it was confirmed
(:func:`load_guidelines`; the docs table is :func:`guideline_table`).  A value not confirmed
against the document is shown "[to be checked]" wherever it is used.

:func:`check_combination` reads the last state of a combination's run
(:meth:`stepcontact.model.combinations.Combination.model`) through
:func:`stepcontact.results.safety.interface_safety` — no new computation of the joint's
forces — and checks, for each joint (default: every interface):

==================  =======================================================================
check               value (state of the combination)
==================  =======================================================================
sliding (peak)      F = (c A_c + N' tan φ) / H, EM 1110-2-2100 eq. (3-1), with the joint's
                    peak strength c, φ (:class:`JointStrength`; N' = −ΣN, H = |ΣQ|, A_c the
                    compressed area — the elastic model's, not an assumed linear pressure)
sliding (residual)  the same with the residual c_r, φ_r
sliding (friction)  N' tan φ / H (the guideline's factor without cohesion)
resultant           |e| / L, e = L/2 − a, a the resultant's distance from the toe: ≤ 1/6
                    (middle third, 100 % of the base compressed), ≤ 1/4 (75 %), < 1/2
                    (within the base) — the linear-pressure equivalent of the guideline's
                    compressed base, 1/2 − f/3 for a fraction f
compressed length   L_c / L of the elastic model (the closed CFEs' share) ≥ f (> 0 for f = 0)
compressive stress  strength / the largest compressive stress of the linear (gravity-method)
                    distribution, :meth:`InterfaceSafety.linear_stresses` (the CFE stresses at
                    the heel and toe are reported, not checked: at a re-entrant corner they
                    depend on the mesh)
uplift              (N' + U) / U on the base: the downward loads over the uplift U (the
                    :class:`~stepcontact.model.combinations.BaseUplift` profile at the
                    combination's levels plus the crack water, ``res.water``)
crack length        the open length of the joint, m (reported; no required value)
==================  =======================================================================

A check passes when its value meets the required value (≥ for factors and fractions, ≤ for
|e|/L); it is "not evaluated" (``passed`` None) when the guideline has no value for it, the
joint has no strength for it or the quantity does not exist (no uplift on a lift joint).  A
run that did not reach the combination's state (the dam slid or overturned first) fails.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from importlib.resources import files
from typing import Any

import numpy as np

from stepcontact.enums import Status
from stepcontact.errors import ModelError
from stepcontact.model.combinations import BaseUplift, Reservoir, Tailwater

#: a run's result (a StaticResult), read through its attributes
Result = Any

#: the checks with a required value in the guideline file, and how they read
CHECKS = {
    "sliding_peak": "sliding factor (peak)",
    "sliding_residual": "sliding factor (residual)",
    "sliding_friction_only": "sliding factor (friction only)",
    "compressed_base": "compressed base (fraction)",
    "compressive_stress": "compressive stress factor",
    "uplift": "uplift factor",
}
#: the mark of a value not confirmed against its document
TO_BE_CHECKED = "[to be checked]"


@dataclass(frozen=True)
class Criterion:
    """A required value: ``value`` (None: the document sets one, its number was not found) of
    ``check`` under the guideline's load condition ``condition`` for ``variant`` (site
    information, structure class; "" when the guideline has none), with its ``source`` and
    whether it was ``checked`` against the document."""

    guideline: str
    check: str
    condition: str
    variant: str
    value: float | None
    source: str
    checked: bool
    note: str = ""


@dataclass(frozen=True)
class Guideline:
    """One guideline's required values (:func:`load_guidelines`)."""

    key: str
    title: str
    document: str
    conditions: tuple[str, ...]
    variants: tuple[str, ...]
    default_variant: str
    variant_meaning: str
    condition_of: dict
    criteria: tuple[Criterion, ...]

    def condition_class(self, condition: str) -> tuple[str, str, bool]:
        """(the guideline's class, source, checked) of a combination's ``condition``."""
        if condition not in self.condition_of:
            raise KeyError(f"guideline '{self.key}' has no class for the condition "
                           f"'{condition}' (it has: {', '.join(self.condition_of)})")
        c = self.condition_of[condition]
        return str(c["value"]), str(c["source"]), bool(c.get("checked", False))

    def required(self, check: str, condition: str, variant: str | None = None
                 ) -> Criterion | None:
        """The criterion of ``check`` for the guideline's class ``condition`` and ``variant``
        (default: the guideline's default variant); None when the guideline has none."""
        v = self.default_variant if variant is None else variant
        for c in self.criteria:
            if c.check == check and c.condition == condition and c.variant in (v, ""):
                return c
        return None


def _criteria(key: str, raw: list[dict], conditions) -> tuple[Criterion, ...]:
    out = []
    for c in raw:
        if c["check"] not in CHECKS:
            raise ValueError(f"dam_guidelines.toml: guideline '{key}': unknown check "
                             f"'{c['check']}'")
        values = c.get("values", {})
        for cond in conditions:
            if cond in values or not values:
                v = values.get(cond)
                out.append(Criterion(key, c["check"], cond, c.get("variant", ""),
                                     None if v is None else float(v), c["source"],
                                     bool(c.get("checked", False)), c.get("note", "")))
        for cond in values:
            if cond not in conditions:
                raise ValueError(f"dam_guidelines.toml: guideline '{key}': condition '{cond}'"
                                 f" is not one of its classes {conditions}")
    return tuple(out)


def load_guidelines(text: str | None = None) -> dict[str, Guideline]:
    """The guidelines of ``stepcontact/data/guidelines/dam_guidelines.toml`` (or of the TOML
    ``text``), by key: "usace", "ferc", "cda"."""
    if text is None:
        path = files("stepcontact") / "data" / "guidelines" / "dam_guidelines.toml"
        text = path.read_text("utf-8")
    data = tomllib.loads(text)
    out = {}
    for key, g in data["guideline"].items():
        conds = tuple(g["conditions"])
        out[key] = Guideline(key=key, title=g["title"], document=g["document"],
                             conditions=conds, variants=tuple(g["variants"]),
                             default_variant=g["default_variant"],
                             variant_meaning=g["variant_meaning"],
                             condition_of=dict(g["condition_of"]),
                             criteria=_criteria(key, g.get("criterion", []), conds))
    return out


def _fmt(v: float | None, digits: int = 3) -> str:
    if v is None:
        return "—"
    if np.isinf(v):
        return "∞"
    return f"{v:.{digits}g}"


def guideline_table(guidelines: dict[str, Guideline] | None = None) -> str:
    """The Markdown table of every guideline's required values with their sources (the docs'
    "Guideline criteria" table)."""
    gs = load_guidelines() if guidelines is None else guidelines
    lines = ["| guideline | check | variant | " + "condition: required value | source |",
             "|---|---|---|---|---|"]
    for g in gs.values():
        groups: dict[tuple, list[Criterion]] = {}
        for c in g.criteria:
            groups.setdefault((c.check, c.variant, c.source, c.checked, c.note), []).append(c)
        for (check, variant, source, checked, note), cs in groups.items():
            vals = ", ".join(f"{c.condition} {_fmt(c.value)}" for c in cs
                             if c.value is not None) or "not found"
            mark = "" if checked else f" {TO_BE_CHECKED}"
            extra = f" ({note})" if note else ""
            lines.append(f"| {g.title} | {CHECKS[check]} | {variant or '—'} | {vals}{mark} | "
                         f"{source}{extra} |")
    return "\n".join(lines)


# ---- the checks ------------------------------------------------------------------------------
@dataclass(frozen=True)
class JointStrength:
    """The strength of a joint for the checks: peak ``cohesion`` (Pa) and ``friction_angle``
    (degrees; None: the joint's own friction coefficient, tan φ = f), residual ones (None: no
    residual check), and the ``compressive_strength`` (Pa; None: no stress check) the
    compressive stress factor divides."""

    cohesion: float = 0.0
    friction_angle: float | None = None
    residual_cohesion: float = 0.0
    residual_friction_angle: float | None = None
    compressive_strength: float | None = None

    def __post_init__(self):
        for name in ("cohesion", "residual_cohesion"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v >= 0):
                raise ModelError(f"joint strength.{name}", f"is {v!r}: give a cohesion ≥ 0 Pa")
        for name in ("friction_angle", "residual_friction_angle"):
            v = getattr(self, name)
            if v is not None and not (np.isfinite(v) and 0 <= v < 90):
                raise ModelError(f"joint strength.{name}", f"is {v!r}: give an angle in "
                                 "[0, 90) degrees")
        v = self.compressive_strength
        if v is not None and not (np.isfinite(v) and v > 0):
            raise ModelError("joint strength.compressive_strength", f"is {v!r}: give a "
                             "strength > 0 Pa")


@dataclass(frozen=True)
class CheckRow:
    """One check of one joint in one combination: its ``value`` against ``required`` (with
    ``relation`` "≥", ">" or "≤"), ``passed`` (None: not evaluated, see ``note``), the
    criterion's ``source`` and whether it was confirmed (``checked``)."""

    combination: str
    joint: str
    check: str
    value: float | None
    required: float | None = None
    relation: str = ""
    passed: bool | None = None
    unit: str = "-"
    source: str = ""
    checked: bool = True
    note: str = ""

    @property
    def verdict(self) -> str:
        """"pass", "FAIL" or "—" (not evaluated)."""
        return "—" if self.passed is None else "pass" if self.passed else "FAIL"

    @property
    def required_text(self) -> str:
        if self.required is None:
            return "—"
        mark = "" if self.checked else f" {TO_BE_CHECKED}"
        return f"{self.relation} {_fmt(self.required)}{mark}"


@dataclass(frozen=True)
class DamCheck:
    """The checks of one or more combinations: one :class:`CheckRow` per check, joint and
    combination, with the guideline they were read against."""

    guideline: str
    variant: str
    rows: tuple[CheckRow, ...]

    @property
    def passed(self) -> bool:
        """True when every evaluated check passes (and at least one was evaluated)."""
        done = [r.passed for r in self.rows if r.passed is not None]
        return bool(done) and all(done)

    def failed(self) -> list[CheckRow]:
        """The checks that fail."""
        return [r for r in self.rows if r.passed is False]

    def row(self, combination: str, joint: str, check: str) -> CheckRow:
        """The row of ``check`` (its label, e.g. "sliding factor (peak)") of a joint."""
        for r in self.rows:
            if (r.combination, r.joint, r.check) == (combination, joint, check):
                return r
        raise KeyError(f"no check '{check}' of joint '{joint}' in combination "
                       f"'{combination}'")

    def verdicts(self) -> dict[str, bool]:
        """{combination: True when all its evaluated checks pass}."""
        out: dict[str, bool] = {}
        for r in self.rows:
            if r.passed is not None:
                out[r.combination] = out.get(r.combination, True) and r.passed
        return out

    def __add__(self, other: DamCheck) -> DamCheck:
        return DamCheck(self.guideline, self.variant, self.rows + other.rows)

    def table_rows(self) -> list[list[str]]:
        """The rows as text cells: combination, joint, check, value, unit, required, verdict,
        source (what the Markdown and a terminal table show)."""
        return [[r.combination, r.joint, r.check, _fmt(r.value, 4), r.unit, r.required_text,
                 r.verdict, "; ".join(t for t in (r.source, r.note) if t)] for r in self.rows]

    def to_markdown(self) -> str:
        """The checks as a Markdown table, then the overall verdict of each combination."""
        head = ["combination", "joint", "check", "value", "unit", "required", "verdict",
                "source / note"]
        lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        lines += ["| " + " | ".join(c.replace("|", "\\|") for c in row) + " |"
                  for row in self.table_rows()]
        lines.append("")
        for name, ok in self.verdicts().items():
            lines.append(f"- **{name}**: {'pass' if ok else 'FAIL'} ({self.guideline}"
                         f"{', ' + self.variant if self.variant else ''})")
        return "\n".join(lines)


def _tan(angle: float | None, own: float) -> float:
    return own if angle is None else float(np.tan(np.radians(angle)))


def _compare(value: float | None, crit: Criterion | None, relation: str
             ) -> tuple[float | None, bool | None, str, bool, str]:
    """(required, passed, source, checked, note) of ``value`` against ``crit``."""
    if crit is None:
        return None, None, "", True, "no required value in the guideline"
    if crit.value is None:
        return None, None, crit.source, crit.checked, crit.note or "required value not found"
    if value is None or np.isnan(value):
        return crit.value, None, crit.source, crit.checked, "not computable at this state"
    ok = {"≥": value >= crit.value, ">": value > crit.value, "≤": value <= crit.value,
          "<": value < crit.value}[relation]
    return crit.value, bool(ok), crit.source, crit.checked, crit.note


def _row(combo: str, joint: str, check: str, value, crit, relation: str, unit: str = "-",
         override: float | None = None, note: str = "") -> CheckRow:
    if override is not None:  # a required value given by the user
        crit = Criterion("user", "", "", "", float(override), "given", True)
    req, ok, src, checked, why = _compare(value, crit, relation)
    return CheckRow(combo, joint, check, None if value is None else float(value), req,
                    relation if req is not None else "", ok, unit, src, checked,
                    "; ".join(t for t in (why, note) if t))


def _joint_rows(res: Result, combo, site, joint: str, g: Guideline, cls: str, variant: str,
                strength: JointStrength, required: dict) -> list[CheckRow]:
    s = res.interface_safety(joint, heel=site.heel if joint == site.base else "auto")
    name = combo.name

    def crit(check):
        return g.required(check, cls, variant)

    def over(check):
        return required.get(check)

    rows = []
    own = float(s.friction)
    own_note = "" if strength.friction_angle is not None else (
        f"tan φ = the joint's friction coefficient {own:g}")
    f_peak = s.strength_factor(strength.cohesion, _tan(strength.friction_angle, own))
    rows.append(_row(name, joint, CHECKS["sliding_peak"], f_peak, crit("sliding_peak"), "≥",
                     override=over("sliding_peak"),
                     note=f"c = {strength.cohesion:g} Pa" + (f", {own_note}" if own_note
                                                             else "")))
    if strength.residual_friction_angle is not None:
        f_res = s.strength_factor(strength.residual_cohesion,
                                  _tan(strength.residual_friction_angle, own))
        rows.append(_row(name, joint, CHECKS["sliding_residual"], f_res,
                         crit("sliding_residual"), "≥", override=over("sliding_residual")))
    elif crit("sliding_residual") is not None or over("sliding_residual") is not None:
        rows.append(CheckRow(name, joint, CHECKS["sliding_residual"], None,
                             note="no residual strength given (JointStrength)"))
    if crit("sliding_friction_only") is not None or over("sliding_friction_only"):
        f_fr = s.strength_factor(0.0, _tan(strength.friction_angle, own))
        rows.append(_row(name, joint, CHECKS["sliding_friction_only"], f_fr,
                         crit("sliding_friction_only"), "≥",
                         override=over("sliding_friction_only")))
    L = float(s.joint_length)
    a = float(s.from_toe[-1]) if s.from_toe is not None else float("nan")
    e_rel = abs(L / 2 - a) / L if np.isfinite(a) else None
    cb = crit("compressed_base")
    f_min = over("compressed_base") if over("compressed_base") is not None else (
        None if cb is None else cb.value)
    limit = None if f_min is None else 0.5 - f_min / 3.0
    res_crit = None if cb is None and f_min is None else Criterion(
        g.key, "resultant", cls, variant, limit,
        "given" if over("compressed_base") is not None else cb.source,
        True if over("compressed_base") is not None else cb.checked,
        "" if cb is None else cb.note)
    rows.append(_row(name, joint, "resultant |e|/L", e_rel, res_crit,
                     "<" if f_min == 0 else "≤",  # within the base: strictly inside
                     note=f"resultant {a:.4g} m from the toe of L = {L:.4g} m"
                     if np.isfinite(a) else ""))
    frac = float(s.compressed_length[-1]) / L if s.compressed_length is not None else None
    rows.append(_row(name, joint, CHECKS["compressed_base"], frac, cb,
                     ">" if f_min == 0 else "≥", override=over("compressed_base"),
                     note="closed CFEs of the elastic model"))
    sh, st = s.linear_stresses(-1)
    peak = max(-sh, -st) if np.isfinite(sh) else float("nan")
    cs = crit("compressive_stress")
    if strength.compressive_strength is not None and peak > 0:
        rows.append(_row(name, joint, CHECKS["compressive_stress"],
                         strength.compressive_strength / peak, cs, "≥",
                         override=over("compressive_stress"),
                         note=f"largest compression {peak:.4g} Pa (linear distribution)"))
    else:
        rows.append(CheckRow(name, joint, CHECKS["compressive_stress"], None,
                             note="no compressive strength given (JointStrength)"
                             if strength.compressive_strength is None else
                             "no compressive stress (linear distribution)"))
    rows.append(CheckRow(name, joint, "heel stress (linear)", sh, unit="Pa",
                         note="compression negative; reported"))
    rows.append(CheckRow(name, joint, "toe stress (linear)", st, unit="Pa",
                         note="compression negative; reported"))
    rows.append(CheckRow(name, joint, "heel stress (CFE)", float(s.sigma_heel[-1]), unit="Pa",
                         note="N/A of the end CFE; mesh-dependent at a corner; reported"))
    rows.append(CheckRow(name, joint, "toe stress (CFE)", float(s.sigma_toe[-1]), unit="Pa",
                         note="N/A of the end CFE; reported"))
    rows.append(CheckRow(name, joint, "crack length", float(s.open_length[-1]), unit="m",
                         note="open CFEs; reported"))
    rows.append(_uplift_row(res, combo, site, joint, s, crit("uplift"), over("uplift")))
    return rows


def _uplift_row(res, combo, site, joint, s, crit, override) -> CheckRow:
    up = combo.find(BaseUplift)
    if joint != site.base or up is None:
        return CheckRow(combo.name, joint, CHECKS["uplift"], None,
                        note="no uplift given for this joint")
    h1 = float(combo.find(Reservoir).level) - site.heel[1]
    tw = combo.find(Tailwater)
    h2 = 0.0 if tw is None else max(float(tw.level) - site.toe[1], 0.0)
    U = up.force(site, h1, h2)
    if res.water is not None:
        k = np.flatnonzero(np.asarray(res.cfe["interface"]) ==
                           list(res.interface_names).index(joint))
        U += float(np.asarray(res.water, dtype=float)[-1, k].sum())
    if U <= 0:
        return CheckRow(combo.name, joint, CHECKS["uplift"], None, note="no uplift")
    n_eff = -float(s.normal_force[-1])
    return _row(combo.name, joint, CHECKS["uplift"], (n_eff + U) / U, crit, "≥",
                override=override, note=f"U = {U:.6g} N (profile and crack water)")


def check_combination(res: Result, combination, site, *, guideline: str = "usace",
                      variant: str | None = None, joints=None,
                      strength: JointStrength | dict | None = None,
                      required: dict | None = None) -> DamCheck:
    """The checks of ``combination`` (its run ``res``, of ``combination.model(site)``) for
    every joint in ``joints`` (default: all interfaces) against ``guideline`` ("usace",
    "ferc", "cda") for ``variant`` (USACE: structure class and site information, e.g.
    "critical, ordinary", the default).

    ``strength``: a :class:`JointStrength` for every joint, or {joint: JointStrength} (a joint
    not named: its own friction, no cohesion).  ``required``: {check: value} overriding the
    guideline's value (keys of :data:`CHECKS`, e.g. ``{"compressive_stress": 3.0}``)."""
    gs = load_guidelines()
    if guideline not in gs:
        raise KeyError(f"no guideline '{guideline}' (guidelines: {', '.join(gs)})")
    g = gs[guideline]
    v = g.default_variant if variant is None else variant
    if v not in g.variants:
        raise KeyError(f"guideline '{guideline}' has no variant '{v}' (variants: "
                       f"{', '.join(map(repr, g.variants))})")
    required = dict(required or {})
    for key in required:
        if key not in CHECKS:
            raise KeyError(f"required: unknown check '{key}' (checks: {', '.join(CHECKS)})")
    cls, cls_source, cls_checked = g.condition_class(combination.condition)
    names = list(res.interface_names) if joints is None else list(joints)
    rows = [CheckRow(combination.name, "—", "load condition", None, source=cls_source,
                     checked=cls_checked,
                     note=f"'{combination.condition}' read as the guideline's '{cls}'"
                     + ("" if cls_checked else f" {TO_BE_CHECKED}"))]
    if res.status != Status.COMPLETED:
        rows.append(CheckRow(combination.name, "—", "run reached the combination's state",
                             None, passed=False, note=str(res.message)))
    for joint in names:
        st = strength.get(joint, JointStrength()) if isinstance(strength, dict) else (
            strength or JointStrength())
        rows += _joint_rows(res, combination, site, joint, g, cls, v, st, required)
    return DamCheck(guideline=g.title, variant=v, rows=tuple(rows))


__all__ = ["CHECKS", "CheckRow", "Criterion", "DamCheck", "Guideline", "JointStrength",
           "check_combination", "guideline_table", "load_guidelines"]
