"""Summaries of a result as plain JSON-ready data: what ``stepcontact run --json`` and
``stepcontact info`` report (status, events, multipliers, the load resultants, the model size,
the segments, residuals and the safety of every joint), and a result file read with one-line
errors that name the file."""

from __future__ import annotations

import math
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from stepcontact.errors import StepContactError, error_text
from stepcontact.fem.level import is_virtual
from stepcontact.results import result as _result
from stepcontact.results.result import StaticResult, transition_counts


class ResultFileError(StepContactError):
    """A result file that is missing or is no stepcontact result file; the message names it."""


def read_result(path: Path) -> StaticResult:
    """Load the result file ``path`` (static or dynamic).

    Raises
    ------
    ResultFileError
        One line naming the file: not found, or not a stepcontact result file (and why).
    """
    if not path.is_file():
        raise ResultFileError(f"result file not found: {path}")
    try:
        return _result.load_result(path)  # (looked up when called: tests replace it)
    except (OSError, ValueError, KeyError, TypeError) as e:
        msg = error_text(e)
        if not msg.startswith(("not a stepcontact", "inconsistent result file")):
            msg = f"not a stepcontact result file ({msg})"
        raise ResultFileError(f"{path}: {msg}") from None


def jsonable(v: Any) -> Any:
    """A value as JSON takes it: numpy scalars as Python numbers, NaN and ±inf as None,
    anything else that is no number, string or bool as its text."""
    if hasattr(v, "item"):  # numpy scalar
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, int | float | str | bool) or v is None:
        return v
    return str(v)


def result_summary(res: StaticResult, **extra: Any) -> dict[str, Any]:
    """Machine-readable summary of a run (what ``--json`` prints)."""
    return {
        "status": res.status.value,
        "message": res.message,
        "nonunique": res.nonunique,
        "events": len(res.events),
        "states": int(res.n_states),
        "cfes": int(res.m),
        "transitions": transition_counts(res.events),
        "multipliers": [
            {k: jsonable(v) for k, v in asdict(mu).items()} for mu in res.multipliers
        ],
        "counters": {k: jsonable(v) for k, v in res.counters.items()},
        "load_resultants": load_resultants(res),
        **extra,
    }


def load_resultants(res: StaticResult) -> dict[str, dict[str, Any]]:
    """{pattern: {"Fx": N, "Fy": N, "Mz": N·m about the origin}} per unit λ; in 3D
    {"Fx", "Fy", "Fz", "Mx", "My", "Mz"}."""
    out = {}
    levels = res.level_patterns
    for name in res.pattern_names:
        if is_virtual(name):
            continue
        r = res.load_resultant(name, -1) if name in levels else res.load_resultant(name)
        keys = _result.RESULTANT_NAMES.get(len(r), _result.RESULTANT_NAMES[3])
        out[name] = {k: jsonable(float(v)) for k, v in zip(keys, r, strict=True)}
        if name in levels:  # the factor is a water level: the load at the last state
            out[name]["at"] = "last state (water level)"
    return out


def _interface_safety_3d(res: StaticResult) -> list[dict[str, Any]]:
    """The safety of every joint of a 3D result at the last state
    (:func:`~stepcontact.results.safety3d.interface_safety_3d`: resultant force and moment,
    the normal resultant's point and eccentricities (e₁, e₂), kern, compressed area, sliding
    factor, the faceted cone's k and bound, the λ of sliding and overturning)."""
    out = []
    for name in res.interface_names:
        try:
            s = res.interface_safety(name)
        except ValueError:  # an interface without CFEs
            continue
        row: dict[str, Any] = {"interface": name, "dimension": 3}
        for k, v in s.at(-1).items():
            row[k] = [jsonable(float(x)) for x in v] if isinstance(v, list) else jsonable(v)
        row |= {"segment": int(s.segment[-1]), "resultant": [jsonable(float(x)) for x in
                                                              s.resultant[-1]],
                "moment": [jsonable(float(x)) for x in s.moment[-1]],
                "area": jsonable(float(s.area)), "extent": [float(x) for x in s.extent],
                "friction": jsonable(float(s.friction)), "facets": int(s.facets),
                "cone_bound": jsonable(float(s.cone_bound)),
                "lam_sliding": jsonable(s.lam_sliding),
                "lam_overturning": jsonable(s.lam_overturning)}
        out.append(row)
    return out


def model_size(res: StaticResult) -> dict[str, Any]:
    """The size of a result's model: nodes, DOFs, CFEs, interfaces (with their CFEs), bodies
    (with their elements) and load patterns."""
    geo = res.geometry or {}
    iface = np.asarray(res.cfe.get("interface", np.zeros(0, int)), dtype=np.int64)
    dof_of = np.asarray(geo.get("dof_of", np.zeros((0, 3), int)))
    ndof = res.counters.get("ndof", int(dof_of.max()) + 1 if dof_of.size else None)
    return {
        "nodes": len(geo["points"]) if "points" in geo else None,
        "dofs": jsonable(ndof),
        "cfes": int(res.m),
        "interfaces": [
            {"name": name, "cfes": int(np.sum(iface == j))}
            for j, name in enumerate(res.interface_names)
        ],
        "bodies": [
            {"name": str(b["name"]), "kind": str(b.get("kind", "")),
             "element": str(b.get("element", "")), "elements": int(len(b["cells"]))}
            for b in geo.get("bodies", [])
        ],
        "patterns": [p for p in res.pattern_names if not is_virtual(p)],
    }


def result_info(res: StaticResult, path: Path | None = None,
                design: float | None = None, cohesion: float | None = None) -> dict[str, Any]:
    """What ``stepcontact info --json`` prints: :func:`result_summary` plus the model size,
    the segments with their λ ranges and multipliers, residuals and units, and the safety of
    every joint (at the design value ``design`` of the last segment's parameter, with the
    design ``cohesion`` in Pa if given)."""
    return result_summary(
        res,
        **({} if path is None else {"file": str(path)}),
        model=model_size(res),
        segments=[{k: jsonable(v) for k, v in r.items()} for r in res.segments_summary()],
        max_residual=jsonable(float(np.max(res.residual, initial=0.0))),
        max_violation=jsonable(float(np.max(res.violation, initial=0.0))),
        fields_stored=len(res.fields),
        field_states=sorted(int(k) for k in res.fields),
        reactions_last_state={lb: jsonable(float(v)) for lb, v in
                              zip(res.reaction_labels, res.reactions[-1], strict=True)}
        if res.n_states and len(res.reaction_labels) else {},
        units=dict(res.units),
        interface_safety=interface_safety(res, design, cohesion),
    )


def interface_safety(res: StaticResult, design: float | None = None,
                     cohesion: float | None = None) -> list[dict[str, Any]]:
    """Safety of every interface at the last state (:meth:`StaticResult.interface_safety`;
    the heel at the end the loads push away from) and, with the design value ``design`` of
    the parameter, at the design state (``design_state``: the engineers' factors) with the
    load margins λ_limit / λ_d."""
    if not res.n_states:
        return []
    if res.n_t > 1:
        return _interface_safety_3d(res)
    out = []
    for name in res.interface_names:
        try:
            s = res.interface_safety(name, design, cohesion=cohesion, heel="auto")
        except ValueError:  # an interface without CFEs
            continue
        row = {k: jsonable(v) for k, v in s.at(-1).items()}
        row["cohesion_source"] = s.cohesion_source
        row["overturning_note"] = s.overturning_note
        if design is not None:
            row["design_state"] = {k: [jsonable(x) for x in v] if isinstance(v, list)
                                   else jsonable(v) for k, v in s.design_values().items()}
        out.append(row)
    return out
