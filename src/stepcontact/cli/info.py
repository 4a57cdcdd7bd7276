"""``stepcontact info``: the summary of a result file
(:func:`stepcontact.results.summary.result_info`) as rich tables or JSON."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated, Any

import typer
from rich import box
from rich.console import Console
from rich.text import Text

from stepcontact.cli.common import JsonOption, Table, _fail, _Failure, _state_list
from stepcontact.cli.resultfile import _load_result_file
from stepcontact.results.summary import result_info


def _safety_tables(sf: dict[str, Any], opts: dict[str, Any]) -> list[Table]:
    """The tables of one joint's safety
    (:func:`stepcontact.results.summary.interface_safety`): at the last state, and at the
    design state with the load margins."""
    if sf.get("dimension") == 3:
        return [_safety_table_3d(sf, opts)]
    level = bool(sf.get("parameter_is_level"))
    unit = " m" if level else ""
    tab = Table(title=f"interface '{sf['interface']}' at the last state (λ = "
                f"{sf['lam']:.6g}, segment {sf['segment']})", show_header=False, **opts)
    tab.add_column(justify="left", no_wrap=True, min_width=42)
    tab.add_column(justify="right")
    ecc = sf["eccentricity"]
    for label, value in (
        ("ΣN, ΣQ (N)", f"{_info_fmt(sf['normal_force'])}, {_info_fmt(sf['shear_force'])}"),
        ("normal resultant from the heel CFE (m)", _info_fmt(sf["position"])),
        ("eccentricity e (m), CFE span B", f"{_info_fmt(ecc)} (e/B = "
         f"{_info_fmt(None if ecc is None else ecc / sf['length'] if sf['length'] else None)}"
         f"), B = {_info_fmt(sf['length'])}"),
        ("in the kern (|e| ≤ B/6)", "yes" if sf["in_kern"] else "no"),
        ("σn heel, toe (Pa)", ", ".join(_info_fmt(v) for v in _clean_pair(
            sf["sigma_heel"], sf["sigma_toe"]))),
        ("friction-only factor N'·tanφ/H", _info_fmt(sf["friction_only_factor"])),
        ("shear-friction factor (c·A_c + N'·tanφ)/H", _info_fmt(sf["shear_friction_factor"])),
        ("overturning factor ΣM_r/ΣM_o about the toe", _info_fmt(sf["overturning_factor"])),
        ("open length (m)", _info_fmt(sf["open_length"])),
        (f"{'level' if level else 'λ'} at sliding, at overturning{unit and ' (m)'}",
         f"{_info_fmt(sf['lam_sliding'])}, {_info_fmt(sf['lam_overturning'])}"),
    ):
        tab.add_row(label, value)
    return [tab, *_design_tables(sf, opts)]


def _safety_table_3d(sf: dict[str, Any], opts: dict[str, Any]) -> Table:
    """One 3D joint's safety at the last state
    (:func:`stepcontact.results.summary.interface_safety`, 3D rows)."""
    tab = Table(title=f"interface '{sf['interface']}' at the last state (λ = {sf['lam']:.6g}, "
                f"segment {sf['segment']})", show_header=False, **opts)
    tab.add_column(justify="left", no_wrap=True, min_width=42)
    tab.add_column(justify="right")

    def vec(v) -> str:
        return "(" + ", ".join(_info_fmt(x) for x in v) + ")"

    k = sf["facets"]
    for label, value in (
        ("ΣN, |S| (N)", f"{_info_fmt(sf['normal_force'])}, {_info_fmt(sf['shear_force'])}"),
        ("resultant force on S+ (x, y, z; N)", vec(sf["resultant"])),
        ("moment about the centroid (x, y, z; N·m)", vec(sf["moment"])),
        ("normal resultant's point (m)", vec(sf["point"])),
        ("eccentricities e₁, e₂ (m)", vec(sf["eccentricity"])),
        ("in the kern, in the base", f"{'yes' if sf['in_kern'] else 'no'}, "
         f"{'yes' if sf['in_base'] else 'no'}"),
        ("compressed area (m²)", f"{_info_fmt(sf['compressed_area'])} of "
         f"{_info_fmt(sf['area'])}"),
        ("sliding factor Σf·|N|/|S|", _info_fmt(sf["sliding_factor"])),
        ("friction cone", f"inscribed {k}-gon, up to {100 * sf['cone_bound']:.3g} % below "
         "f|N|" if k else "—"),
        ("λ at sliding, at overturning",
         f"{_info_fmt(sf['lam_sliding'])}, {_info_fmt(sf['lam_overturning'])}"),
    ):
        tab.add_row(label, value)
    return tab


def _design_tables(sf: dict[str, Any], opts: dict[str, Any]) -> list[Table]:
    """The tables of one joint at the design state (``--design``): the engineers' factors
    and the load margins, and the notes on them; none without a design state."""
    d = sf.get("design_state")
    if not d:
        return []
    level = bool(sf.get("parameter_is_level"))
    unit = " m" if level else ""
    tables = []
    what = (f"the design level h = {d['design']:.6g} m" if level
            else f"the design λ_d = {d['design']:.6g}")
    where = (f"state {d['state']}" if d.get("state") is not None else
             f"interpolated between states {d['between_states'][0]} and "
             f"{d['between_states'][1]}" if d.get("between_states") else "no state")
    des = Table(title=f"interface '{sf['interface']}' at {what} of '{d['pattern']}' ({where})",
                show_header=False, **opts)
    des.add_column(justify="left", no_wrap=True, min_width=44)
    des.add_column(justify="right")
    if "normal_force" in d:
        coh, third = d["cohesion"], d["in_middle_third"]
        for label, value in (
            ("ΣN, ΣQ (N)", f"{_info_fmt(d['normal_force'])}, {_info_fmt(d['shear_force'])}"),
            ("compressed length (m)", f"{_info_fmt(d['compressed_length'])} of "
             f"{_info_fmt(d['joint_length'])}"),
            ("cohesion c (Pa)", _info_fmt(coh)),
            ("cohesion from", d["cohesion_source"]),
            ("shear-friction factor (c·A_c + N'·tanφ)/H", _info_fmt(d["shear_friction_factor"])),
            ("friction-only factor N'·tanφ/H", _info_fmt(d["friction_only_factor"])),
            ("overturning factor ΣM_r/ΣM_o about the toe", _info_fmt(d["overturning_factor"])),
            ("ΣM_r, ΣM_o about the toe (N·m)",
             f"{_info_fmt(d['resisting_moment'])}, {_info_fmt(d['overturning_moment'])}"),
            ("resultant from the toe (m)", _info_fmt(d["resultant_from_toe"])),
            ("e/B, in the middle third", f"{_info_fmt(d['e_over_B'])}, "
             f"{'—' if third is None else 'yes' if third else 'no'}"),
        ):
            des.add_row(label, value)
    name = "level" if level else "λ"
    for kind in ("sliding", "overturning"):
        lim, margin = sf[f"lam_{kind}"], sf[f"margin_{kind}"]
        des.add_row(f"margin: {name} at {kind} / design {name}",
                    "—" if margin is None else
                    f"{lim:.6g}{unit} / {d['design']:.6g}{unit} = {margin:.4g}")
    tables.append(des)
    if d.get("notes"):
        notes = Table(title=f"notes on interface '{sf['interface']}' at the design state",
                      show_header=False, **opts)
        notes.add_column(justify="left")
        for note in d["notes"]:
            notes.add_row(f"— {note}")
        tables.append(notes)
    return tables


def _info_fmt(v: Any) -> str:
    return "—" if v is None else f"{v:.6g}" if isinstance(v, float) else str(v)


def _clean_pair(a: float, b: float) -> tuple[float, float]:
    """Two stresses with the round-off of an open end (below 1e-9 of the larger) shown as 0."""
    big = max(abs(a), abs(b))
    return tuple(0.0 if abs(v) <= 1e-9 * big else v for v in (a, b))


def _info_sci(v: float | None) -> str:
    return "—" if v is None else f"{v:.2e}"


def _info_tables(info: dict[str, Any]) -> list[Table]:
    """Rich tables of :func:`result_info`: model, segments, multipliers, transitions."""
    opts = {"title_justify": "left", "box": box.SIMPLE_HEAD, "show_edge": False,
            "pad_edge": False}
    mdl = info["model"]
    size = Table(title="model", show_header=False, **opts)
    size.add_column(justify="left")
    size.add_column(justify="left")
    for label, value in (
        ("nodes", mdl["nodes"]), ("DOFs", mdl["dofs"]), ("CFEs", mdl["cfes"]),
        ("interfaces", ", ".join(f"{i['name']} ({i['cfes']} CFEs)" for i in mdl["interfaces"])
         or "none"),
        ("bodies", ", ".join(f"{b['name']} ({b['elements']} {b['element'] or b['kind']})"
                             for b in mdl["bodies"]) or "—"),
        ("load patterns", ", ".join(mdl["patterns"]) or "none"),
        ("states", f"{info['states']} (displacement fields stored at "
                   f"{_state_list(info['field_states'])}; any other state: export/plot "
                   "--model MODEL.toml)" if info["fields_stored"] < info["states"] else
                   f"{info['states']} (all with displacement fields)"),
        ("max residual", _info_sci(info["max_residual"])),
        ("max violation", _info_sci(info["max_violation"])),
        ("units", ", ".join(f"{k} {v}" for k, v in info["units"].items())),
    ):
        size.add_row(label, _info_fmt(value))
    segs = Table(title="segments (λ of the segment's pattern)", **opts)
    mult = Table(title="stability multipliers (λ; — : did not happen)", **opts)
    for table, columns in (
        (segs, {"segment": "segment", "pattern": "pattern", "λ start": "lam_start",
                "λ end": "lam_end", "λ reached": "lam_reached", "states": "states",
                "events": "events"}),
        (mult, {"segment": "segment", "pattern": "pattern", "first slip": "first_slip",
                "first opening": "first_opening", "first closing": "first_closing",
                "equilibrium lost": "equilibrium_lost"}),
    ):
        for h in columns:
            table.add_column(h, justify="left" if h == "pattern" else "right")
        for r in info["segments"]:
            table.add_row(*(_info_fmt(r[k]) for k in columns.values()))
    trans = Table(title=f"events by transition ({info['events']})", **opts)
    trans.add_column("transition")
    trans.add_column("count", justify="right")
    for t, n in info["transitions"].items():
        if n:
            trans.add_row(t, str(n))
    tables = [size, segs, mult, trans]
    for sf in info.get("interface_safety", []):
        tables += _safety_tables(sf, opts)
    if info.get("reactions_last_state"):
        reac = Table(title="support reactions on the structure at the last state (N; N·m for rz)",
                     **opts)
        reac.add_column("support:dof")
        reac.add_column("reaction", justify="right")
        for lb, v in info["reactions_last_state"].items():
            reac.add_row(lb, _info_fmt(v))
        tables.append(reac)
    return tables


def info(
    result_file: Annotated[
        Path, typer.Argument(metavar="RESULT.nc", help="Result file written by 'run'.")
    ],
    as_json: JsonOption = False,
    design: Annotated[
        float | None,
        typer.Option("--design", help="Design value of the last segment's parameter (a load "
                     "factor λ_d, or a water level in m): the joints' shear-friction, "
                     "friction-only and overturning factors at that state, and the load margins "
                     "λ_limit / λ_d."),
    ] = None,
    cohesion: Annotated[
        float | None,
        typer.Option("--cohesion", min=0.0, help="Design cohesion c of the joints, Pa, on the "
                     "compressed length (replaces the joint's own: its bond's τ_R or residual "
                     "C_r)."),
    ] = None,
) -> None:
    """Summarise a result file: status, model size, segments, events, multipliers, and the
    safety of every joint at the last state.

    Examples:

        stepcontact info run.nc

        stepcontact info run.nc --design 1.0

        stepcontact info dam.nc --design 40 --cohesion 200e3

        stepcontact info run.nc --json | jq .multipliers
    """
    try:
        res = _load_result_file(result_file)
    except _Failure as e:
        raise _fail(str(e), as_json) from None
    if design is not None and not (math.isfinite(design) and design != 0):
        raise _fail(f"--design {design}: give a finite, non-zero design load factor", as_json)
    if cohesion is not None and not math.isfinite(cohesion):
        raise _fail(f"--cohesion {cohesion}: give a finite cohesion ≥ 0 Pa", as_json)
    if (design is not None or cohesion is not None) and getattr(res, "n_t", 1) > 1:
        opt = "--design" if design is not None else "--cohesion"
        raise _fail(f"{opt}: the design-state check (engineers' factors, load margins) is not "
                    "available for 3D joints yet; `stepcontact info` without it shows each 3D "
                    "joint's force, moment, eccentricities, compressed area and sliding "
                    "factor", as_json)
    summary = result_info(res, result_file, design, cohesion)
    if as_json:
        typer.echo(json.dumps(summary, indent=2, ensure_ascii=False))
        return
    console = Console(highlight=False, soft_wrap=True)
    console.rule(f"stepcontact result: {result_file}")
    console.print(Text(f"status: {summary['status']} — {summary['message']}"))
    for table in _info_tables(summary):
        console.print(table)
