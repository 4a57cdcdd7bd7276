"""``stepcontact sweep`` (a parameter sweep of a model file) and ``stepcontact study`` (a
ready-made study): run the cases on a process pool or a dask cluster, print their table."""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Annotated, Any

import typer
from rich import box
from rich.console import Console
from rich.text import Text

from stepcontact.cli.common import (
    EXIT_UNRESOLVED,
    JsonOption,
    Table,
    _error_text,
    _fail,
    _Failure,
    _warn,
)
from stepcontact.enums import Status
from stepcontact.errors import StepContactError
from stepcontact.results.summary import jsonable as _jsonable


def _sweep_cell(v: Any) -> str:
    """A value of the sweep table (a Python scalar): floats to 6 digits, NaN as —."""
    if isinstance(v, float):
        return f"{v:.6g}" if math.isfinite(v) else "—"
    return str(v)


def sweep_table(ds: Any, outputs: Sequence[str], title: str) -> Table:
    """The cases of a collected sweep (:func:`stepcontact.study.sweep.collect`) as a rich
    table: the case (its index when the id is made of its parameters), parameters, case
    status and the outputs (NaN and missing values as —)."""
    from stepcontact.study.sweep import _short_keys, case_id

    keys = json.loads(ds.attrs.get("params", "[]"))
    short = _short_keys(keys)
    table = Table(title=title, title_justify="left", box=box.SIMPLE_HEAD, show_edge=False,
                  pad_edge=False)
    table.add_column("case", no_wrap=True)
    for k in keys:
        table.add_column(short[k], justify="right", no_wrap=True)
    table.add_column("case status", no_wrap=True)
    shown = [o for o in outputs if o in ds and o != "message" and ds[o].ndim == 1]
    for o in shown:
        table.add_column(o, justify="left" if ds[o].dtype.kind == "U" else "right",
                         no_wrap=True)
    for i in range(ds.sizes["case"]):
        cs = str(ds["case_status"].values[i])
        style = {"ok": "", "failed": "red"}.get(cs, "yellow")
        table.add_row(str(i) if str(ds["case"].values[i]) == case_id(
                          {k: ds[k].values[i].item() for k in keys}, short)
                      else str(ds["case"].values[i]),
                      *(_sweep_cell(ds[k].values[i].item()) for k in keys),
                      Text(cs, style=style),
                      *(_sweep_cell(ds[o].values[i].item()) if cs == "ok" else "—"
                        for o in shown))
    return table


def sweep(
    study_file: Annotated[
        Path, typer.Argument(metavar="STUDY.toml", help="Study file: [study] (base model "
                             "file, store directory, outputs) and [grid] or [[cases]].")
    ],
    scheduler: Annotated[
        str | None,
        typer.Option("--scheduler", metavar="ADDRESS", help="Run on a dask.distributed "
                     "cluster: the scheduler's address, e.g. tcp://10.0.0.5:8786. Default: a "
                     "local process pool."),
    ] = None,
    workers: Annotated[
        int | None,
        typer.Option("--workers", "-w", min=1, help="Processes of the local pool (default: "
                     "the CPU cores available)."),
    ] = None,
    serial: Annotated[
        bool, typer.Option("--serial", help="Run the cases one after another in this process "
                           "(debugging).")
    ] = False,
    rerun: Annotated[
        bool, typer.Option("--rerun", help="Run every case again, also those already done.")
    ] = False,
    quiet: Annotated[
        bool, typer.Option("--quiet", "-q", help="No progress bar and no table.")
    ] = False,
    as_json: JsonOption = False,
    force: Annotated[
        bool, typer.Option("--force", help="Run a sweep of more than 10 000 cases (refused "
                           "without it).")
    ] = False,
) -> None:
    """Run a parameter sweep of a model file: every case of a grid (or list) of parameter
    values, on a local process pool or a dask cluster. See docs/sweeps.md.

    Each finished case is stored at once (STORE/cases/<id>.nc, its result file in
    STORE/results/); a rerun skips the cases already done with the same parameters, and
    retries failed ones. At the end, prints a table of the cases and writes STORE/sweep.nc
    (the outputs along the dimension 'case'). Exit code 3 when a case failed or stopped
    without a physical answer.

    Examples:

        stepcontact sweep friction.toml

        stepcontact sweep friction.toml --workers 4 --quiet

        stepcontact sweep friction.toml --scheduler tcp://10.0.0.5:8786

        stepcontact sweep friction.toml --serial --rerun --json
    """
    from stepcontact.io.interrupt import Terminated

    console = Console(highlight=False, soft_wrap=True)
    study = None
    try:
        if serial and scheduler is not None:
            raise _Failure("give either --serial or --scheduler, not both")
        study = _load_study(study_file, force=force, announce=not quiet and not as_json)
        ds = _run_sweep(study, serial=serial, scheduler=scheduler, workers=workers,
                        progress=not quiet and not as_json, rerun=rerun)
    except Terminated as e:
        raise _sweep_interrupted(e, study, as_json) from None
    except _Failure as e:
        raise _fail(str(e), as_json) from None
    outputs = list(study.func.outputs)
    failed = [i for i, cs in enumerate(ds["case_status"].values) if cs != "ok"]
    unresolved = []
    if "status" in ds:
        unresolved = [i for i, st in enumerate(ds["status"].values) if i not in failed
                      and st not in (Status.COMPLETED.value, Status.EQUILIBRIUM_LOST.value)]
    path = study.store / "sweep.nc"
    if as_json:
        typer.echo(json.dumps({"status": "failed" if failed else "ok", "study": study.name,
                               "store": str(study.store), "dataset": str(path),
                               "failed": len(failed), "cases": _sweep_rows(ds, outputs)},
                              indent=2, ensure_ascii=False))
    elif not quiet:
        console = _print_wide(sweep_table(ds, outputs, f"sweep '{study.name}': "
                                          f"{ds.sizes['case']} cases, {len(failed)} failed"),
                              console)
    _print_failed(ds, failed)
    if not as_json:
        console.print(Text(f"written: {path}", style="green"))
    if failed or unresolved:
        raise typer.Exit(EXIT_UNRESOLVED)


def _load_study(study_file: Path, *, force: bool, announce: bool) -> Any:
    """The study of a study file (:func:`stepcontact.study.studyfile.load_study`); its notes
    on stderr when ``announce``."""
    from stepcontact.study.studyfile import load_study
    from stepcontact.study.sweep import StudyError

    err = Console(stderr=True, soft_wrap=True, highlight=False)
    try:
        return load_study(study_file, force=force,
                          announce=(lambda text: err.print(Text(text))) if announce else None)
    except StudyError as e:
        raise _Failure(_error_text(e)) from None


def _run_sweep(study: Any, *, serial: bool, scheduler: str | None, workers: int | None,
               progress: bool, rerun: bool) -> Any:
    """Run the cases of a study (serially, on a local pool or on the cluster of
    ``scheduler``), its store locked and SIGTERM/Ctrl-C an orderly interrupt; the dataset."""
    from stepcontact.io.atomic import OutputLockedError, output_lock
    from stepcontact.io.interrupt import signals_interrupt
    from stepcontact.study.studyfile import run_study
    from stepcontact.study.sweep import StudyError

    executor = "serial" if serial else scheduler if scheduler is not None else "process"
    try:
        with signals_interrupt(), output_lock(study.store / "sweep.nc", "sweep store"):
            return run_study(study, executor=executor, workers=workers, progress=progress,
                             rerun=rerun)
    except OutputLockedError as e:
        raise _Failure(_error_text(e)) from None
    except (StudyError, OSError, TimeoutError) as e:
        where = f"--scheduler {scheduler}: " if scheduler is not None else ""
        raise _Failure(where + _error_text(e)) from None


def _sweep_rows(ds: Any, outputs: Sequence[str]) -> list[dict[str, Any]]:
    """The cases of a collected sweep as ``sweep --json`` lists them."""
    keys = json.loads(ds.attrs["params"])
    rows = []
    for i in range(ds.sizes["case"]):
        row = {"id": str(ds["case"].values[i]),
               "params": {k: _jsonable(ds[k].values[i]) for k in keys},
               "case_status": str(ds["case_status"].values[i]),
               "case_message": str(ds["case_message"].values[i])}
        row |= {o: _jsonable(ds[o].values[i]) for o in outputs
                if o in ds and ds[o].ndim == 1}
        rows.append(row)
    return rows


def _print_wide(table: Table, console: Console) -> Console:
    """Print a table on ``console``, or on one as wide as the table when the terminal is
    narrower (a wide table is not squeezed); the console printed on."""
    from rich.measure import Measurement

    wide = Console(width=1000)
    need = Measurement.get(wide, wide.options, table).maximum
    if need > console.width:  # a wide table is not squeezed into the terminal
        console = Console(highlight=False, soft_wrap=True, width=need)
    console.print(table)
    return console


def _print_failed(ds: Any, failed: Sequence[int]) -> None:
    """One red line ``failed: CASE: message`` on stderr per failed case."""
    err = Console(stderr=True, soft_wrap=True, highlight=False)
    for i in failed:
        err.print(Text(f"failed: {ds['case'].values[i]}: {ds['case_message'].values[i]}",
                       style="red"))


def _sweep_interrupted(e: Any, study: Any, as_json: bool) -> typer.Exit:
    """A sweep ended by SIGTERM or SIGINT (its workers are ended with it): say how many cases
    are stored; the exit to raise (128 + the signal's number)."""
    from stepcontact.study.sweep import is_done

    done = sum(is_done(study.store, c, study.func.sweep_key) for c in study.cases)
    text = (f"interrupted by {e.name}: {done} of {len(study.cases)} cases are stored in "
            f"'{study.store}'; run the sweep again to run the others")
    Console(stderr=True, soft_wrap=True, highlight=False).print(
        Text(f"error: {text}", style="red"))
    if as_json:
        typer.echo(json.dumps({"status": "interrupted", "signal": e.name, "message": text}))
    return typer.Exit(e.exit_code)


STUDIES = ("slab", "dam")


def study(
    name: Annotated[str, typer.Argument(metavar="STUDY", help="The study: slab (the "
                                        "stilling-basin slab of the article, Figs. 4–5) or "
                                        "dam (a gravity-dam section, static).")],
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Directory of the study: the cases, "
                                  "their result files, the dataset, the figures and the "
                                  "report (default: slab-study or dam-study).")
    ] = None,
    quick: Annotated[
        bool, typer.Option("--quick", help="A coarse version (7 cases: three positions, one "
                           "duration, a 20 × 2 slab mesh, tolerance 5 cm; its mesh check on "
                           "40 × 4): about 30 s on two idle cores (the full study, 29 cases "
                           "and its mesh check: about 7 min with --workers 2). dam: cells of "
                           "H/15 (2 m for the default dam), with its combinations and yield "
                           "run: 5.6 s of CPU, 18 s on two cores under a load of 12 (the "
                           "full study, H/60: 12 s of CPU, 39 s).")
    ] = False,
    E0: Annotated[
        float | None, typer.Option("--E0", min=0.0, help="Energy head above the apron, m "
                                   "(default 25).")
    ] = None,
    h_kr: Annotated[
        float | None, typer.Option("--h-kr", min=0.0, help="Critical depth of the design "
                                   "unit discharge, m (default 3.48).")
    ] = None,
    amplitude: Annotated[
        float | None, typer.Option("--amplitude", min=0.0, help="Impulse amplitude as a "
                                   "fraction of the velocity head ρV1²/2 (default 0.4).")
    ] = None,
    positions: Annotated[
        list[float] | None, typer.Option("--position", help="Impulse position x/L_p "
                                         "(repeatable; default 0.05 … 0.95).")
    ] = None,
    durations: Annotated[
        list[float] | None, typer.Option("--duration", help="Impulse duration, s "
                                         "(repeatable; default 0.1 and 1).")
    ] = None,
    friction: Annotated[
        float | None, typer.Option("--friction", min=0.0, help="Friction coefficient of "
                                   "the slab's base (default 0.6); dam: tan φ of the joint "
                                   "(instead of --friction-angle).")
    ] = None,
    gap_pressure: Annotated[
        str | None, typer.Option("--gap-pressure", metavar="uplift|joint", help="Pressure in "
                                 "the opened joint: 'uplift' (default), or 'joint': the "
                                 "pressure at the upstream joint, mean and impulse, in the gap "
                                 "opened from there (Fiorotto & Rinaldo's mechanism).")
    ] = None,
    scheduler: Annotated[
        str | None,
        typer.Option("--scheduler", metavar="ADDRESS", help="Run the cases on a "
                     "dask.distributed cluster (its scheduler's address)."),
    ] = None,
    workers: Annotated[
        int | None, typer.Option("--workers", "-w", min=1, help="Processes of the local pool "
                                 "(default: the CPU cores available).")
    ] = None,
    serial: Annotated[
        bool, typer.Option("--serial", help="Run the cases one after another in this process.")
    ] = False,
    rerun: Annotated[
        bool, typer.Option("--rerun", help="Run every case again, also those already done.")
    ] = False,
    quiet: Annotated[
        bool, typer.Option("--quiet", "-q", help="No progress bar and no tables.")
    ] = False,
    height: Annotated[
        float | None, typer.Option("--height", help="dam: height H, m (default 30).")
    ] = None,
    crest_width: Annotated[
        float | None, typer.Option("--crest-width", help="dam: crest width, m (default 5).")
    ] = None,
    upstream_slope: Annotated[
        float | None, typer.Option("--upstream-slope", help="dam: batter of the upstream "
                                   "face, horizontal per vertical (default 0: vertical).")
    ] = None,
    downstream_slope: Annotated[
        float | None, typer.Option("--downstream-slope", help="dam: batter of the downstream "
                                   "face (default 0.75).")
    ] = None,
    normal_level: Annotated[
        float | None, typer.Option("--normal-level", help="dam: normal reservoir level above "
                                   "the base, m (default 27).")
    ] = None,
    flood_level: Annotated[
        float | None, typer.Option("--flood-level", help="dam: flood level, m (default 30).")
    ] = None,
    tailwater: Annotated[
        float | None, typer.Option("--tailwater", help="dam: tailwater level, m (default 0).")
    ] = None,
    friction_angle: Annotated[
        float | None, typer.Option("--friction-angle", help="dam: friction angle φ of the "
                                   "joint, degrees (default 45; or --friction tan φ).")
    ] = None,
    cohesion: Annotated[
        float | None, typer.Option("--cohesion", help="dam: cohesion of the joint, Pa (default "
                                   "0; > 0 makes a bond that breaks).")
    ] = None,
    tensile_strength: Annotated[
        float | None, typer.Option("--tensile-strength", help="dam: tensile strength of the "
                                   "joint's bond, Pa (default 0).")
    ] = None,
    drain: Annotated[
        float | None, typer.Option("--drain", help="dam: drain line's distance from the heel, "
                                   "m (default: no drains).")
    ] = None,
    drain_efficiency: Annotated[
        float | None, typer.Option("--drain-efficiency", help="dam: drain efficiency E, 0…1 "
                                   "(default 0).")
    ] = None,
    cell: Annotated[
        float | None, typer.Option("--cell", help="dam: cell size of the dam's mesh, m "
                                   "(default H/60, --quick H/15).")
    ] = None,
    rigid_base: Annotated[
        bool, typer.Option("--rigid-base", help="dam: a rigid base instead of the rock block.")
    ] = False,
    kh: Annotated[
        float | None, typer.Option("--kh", help="dam: design horizontal seismic coefficient "
                                   "k_h of the extreme combination, g (default 0.1).")
    ] = None,
    kv: Annotated[
        float | None, typer.Option("--kv", help="dam: design vertical seismic coefficient "
                                   "k_v, g, > 0 upwards (default 0).")
    ] = None,
    guideline: Annotated[
        str | None, typer.Option("--guideline", metavar="usace|ferc|cda", help="dam: the "
                                 "guideline of the verdicts (default usace).")
    ] = None,
    silt_level: Annotated[
        float | None, typer.Option("--silt-level", help="dam: silt against the upstream face "
                                   "up to this level, m (default: no silt).")
    ] = None,
    record: Annotated[
        Path | None, typer.Option("--record", help="dam: an earthquake record, the horizontal "
                                  "component (PEER .AT2 in g, or a text file with "
                                  "--record-units): run it after the usual loads, then the "
                                  "post-earthquake stage.")
    ] = None,
    record_vertical: Annotated[
        Path | None, typer.Option("--record-vertical", help="dam: the record's vertical "
                                  "component (+ up), scaled as the horizontal.")
    ] = None,
    record_format: Annotated[
        str | None, typer.Option("--record-format", metavar="at2|two_column|one_column",
                                 help="dam: the record files' format (default: .AT2 by the "
                                 "name).")
    ] = None,
    record_dt: Annotated[
        float | None, typer.Option("--record-dt", help="dam: the sampling of a one-column "
                                   "record file, s.")
    ] = None,
    record_units: Annotated[
        str | None, typer.Option("--record-units", metavar="g|m/s2|cm/s2|gal",
                                 help="dam: units of a text record file.")
    ] = None,
    target_pga: Annotated[
        float | None, typer.Option("--target-pga", help="dam: scale the record to this peak "
                                   "horizontal acceleration, g.")
    ] = None,
    polarity: Annotated[
        int | None, typer.Option("--polarity", help="dam: 1, or -1 to flip the horizontal "
                                 "record (the other direction of shaking).")
    ] = None,
    crack_water: Annotated[
        str | None, typer.Option("--crack-water", metavar="unchanged|none|full",
                                 help="dam: the water in a crack during the shaking (default "
                                 "unchanged: USACE, FERC; none: USBR; full: ICOLD).")
    ] = None,
    model_file: Annotated[
        Path | None, typer.Option("--model", help="dam: the study on a model file with a "
                                  "[dam] table (its bodies, meshes, materials, supports and "
                                  "interfaces; its own loads and program are not used), "
                                  "instead of the parametric section (docs/dam-study.md).")
    ] = None,
) -> None:
    """Run a ready-made study and write its figures and report. See docs/slab-study.md and
    docs/dam-study.md.

    slab: the limit thickness of a stilling-basin slab (apron) on its soil foundation against
    the position of a pressure impulse (the article's Fig. 5), beside the static-only limit,
    with the contact stresses just before lift-off (Fig. 4), a table of all cases and the
    design formulas for the same inputs; every case is one case of a sweep (resumable: a
    rerun skips the finished cases).

    dam: a gravity-dam section on its foundation under self-weight, the reservoir at the normal
    and flood levels and raised until the dam fails: the joint's figures at each level, the
    margins as factors on the level, and the hand statics a reviewer checks; the load
    combinations (usual, flood, extreme with the pseudo-static earthquake --kh/--kv,
    post-earthquake) with the verdicts of a guideline (--guideline), and the yield
    acceleration k_y (k_h raised until the dam fails) with its margin k_y / k_h; with
    --record, the earthquake record as a time history after the usual loads (Westergaard's
    added mass, the crack water of --crack-water) and the post-earthquake stage: the base's
    permanent slip beside Newmark's estimate at k_y and the post-earthquake verdict.

    Examples:

        stepcontact study slab --quick -o slab-quick

        stepcontact study slab --E0 30 --amplitude 0.3 --workers 4

        stepcontact study slab --scheduler tcp://10.0.0.5:8786

        stepcontact study dam --quick -o dam-quick

        stepcontact study dam --height 40 --drain 4 --drain-efficiency 0.5 --cohesion 3e5

        stepcontact study dam --quick --kh 0.15 --kv 0.05 --guideline ferc

        stepcontact study dam --quick --record record.AT2 --target-pga 0.3
        stepcontact study dam --model examples/data/dam_study.toml -o dam-file
    """
    from stepcontact.study import basin
    from stepcontact.study.report import write_report

    console = Console(highlight=False, soft_wrap=True)
    dam = {"height": height, "crest_width": crest_width, "upstream_slope": upstream_slope,
           "downstream_slope": downstream_slope, "normal_level": normal_level,
           "flood_level": flood_level, "tailwater": tailwater,
           "friction_angle": friction_angle, "cohesion": cohesion,
           "tensile_strength": tensile_strength, "drain_position": drain,
           "drain_efficiency": drain_efficiency, "cell": cell, "k_h": kh, "k_v": kv,
           "guideline": guideline, "silt_level": silt_level}
    quake = {"horizontal": record, "vertical": record_vertical, "format": record_format,
             "file_dt": record_dt, "units": record_units,
             "target_pga": target_pga, "polarity": polarity, "crack_water": crack_water}
    if name == "dam":
        slab_only = {"--E0": E0, "--h-kr": h_kr, "--amplitude": amplitude,
                     "--position": positions or None, "--duration": durations or None,
                     "--gap-pressure": gap_pressure, "--scheduler": scheduler,
                     "--workers": workers, "--serial": serial or None, "--rerun": rerun or None}
        _dam_study(dam, quick=quick, friction=friction, rigid_base=rigid_base, quake=quake,
                   output=Path("dam-study") if output is None else output, quiet=quiet,
                   console=console, unused=[k for k, v in slab_only.items() if v is not None],
                   model=model_file)
        return
    output = Path("slab-study") if output is None else output
    try:
        if name not in STUDIES:
            raise _Failure(f"unknown study '{name}' (known: {', '.join(STUDIES)})")
        dam_only = ([k for k, v in dam.items() if v is not None]
                    + (["rigid_base"] if rigid_base else []) + _quake_flags(quake)
                    + (["model"] if model_file else []))
        if dam_only:
            flag = {"k_h": "kh", "k_v": "kv"}.get(dam_only[0], dam_only[0])
            raise _Failure(f"--{flag.replace('_', '-')} applies to the dam study, not "
                           f"to the {name} study")
        if serial and scheduler is not None:
            raise _Failure("give either --serial or --scheduler, not both")
        st = _basin_study(quick, {"E0": E0, "h_kr": h_kr, "amplitude": amplitude,
                                  "friction": friction, "gap_pressure": gap_pressure},
                          positions, durations)
        executor = "serial" if serial else scheduler if scheduler is not None else "process"
        try:
            ds = basin.run_basin(st, output, executor=executor, workers=workers,
                                 progress=not quiet, rerun=rerun)
        except (StepContactError, OSError, TimeoutError) as e:
            raise _Failure(_error_text(e)) from None
    except _Failure as e:
        raise _fail(str(e), False) from None
    files = write_report(ds, st, output / "report")
    failed = [i for i, cs in enumerate(ds["case_status"].values) if cs != "ok"]
    _check_not_all_failed(ds, files, name, console)
    if not quiet:
        _print_study(ds, st, failed, console)
    _print_failed(ds, failed)
    for f in files.values():
        console.print(Text(f"written: {f}", style="green"))
    if failed:
        raise typer.Exit(EXIT_UNRESOLVED)


def _basin_study(quick: bool, values: dict[str, Any], positions: Sequence[float] | None,
                 durations: Sequence[float] | None) -> Any:
    """The slab study of the options given (``values``: E0, h_kr, amplitude, friction,
    gap_pressure, None where not given; ``--quick``: its coarse version); an implausible
    friction coefficient is a warning."""
    import dataclasses

    from stepcontact.study import basin

    changes = {k: v for k, v in values.items() if v is not None}
    if values["friction"] is not None:
        from stepcontact.model.plausible import message

        _warn([w for w in (message("friction", values["friction"], "--friction"),) if w])
    if positions:
        changes["positions"] = tuple(positions)
    if durations:
        changes["durations"] = tuple(durations)
    try:
        return (basin.quick(**changes) if quick
                else dataclasses.replace(basin.BasinStudy(), **changes))
    except StepContactError as e:
        raise _Failure(_error_text(e)) from None


def _check_not_all_failed(ds: Any, files: dict[str, Any], name: str, console: Console) -> None:
    """When every case of the study failed: the report's files, then the exit with the first
    reason (code 2)."""
    from stepcontact.study.report import all_failed, failure_reasons

    if not all_failed(ds):
        return
    for f in files.values():
        console.print(Text(f"written: {f}", style="green"))
    reasons = failure_reasons(ds)
    msg, k, cid = reasons[0]
    more = f" ({len(reasons) - 1} other reason(s) in the report)" if len(reasons) > 1 else ""
    raise _fail(f"all {ds.sizes['case']} cases of the {name} study failed; {k} of them "
                f"(e.g. {cid}): {msg}{more}", False)


def _print_study(ds: Any, st: Any, failed: Sequence[int], console: Console) -> None:
    """The tables of the slab study: its cases, its limits beside the design formulas, and
    its mesh check."""
    from stepcontact.study import basin

    console.print(sweep_table(ds, ["h_limit", "h_ratio", "mode", "when", "runs"],
                              f"slab study: {ds.sizes['case']} cases (h in m, h_kr = "
                              f"{st.h_kr:g} m), {len(failed)} failed"))
    table = Table(title="the study's limits beside the design formulas", box=box.SIMPLE_HEAD,
                  title_justify="left")
    for col in ("", "thickness, m", "h/h_kr", "note"):
        table.add_column(col, justify="right" if col.startswith(("th", "h/")) else "left")
    for label, h, note in basin.design_table(st, ds):
        table.add_row(label, f"{h:.2f}", f"{h / st.h_kr:.2f}", note)
    console.print(table)
    chk = basin.MeshCheck.of(ds)
    if chk is not None:
        console.print(chk.summary())


# ---------------------------------------------------------------------------- the dam study ---

def _quake_flags(quake: dict[str, Any]) -> list[str]:
    """The earthquake-record options given, by their flags' names (without --)."""
    flags = {"horizontal": "record", "vertical": "record_vertical", "units": "record_units",
             "format": "record_format", "file_dt": "record_dt"}
    return [flags.get(k, k) for k, v in quake.items() if v is not None]


def _quake_record(quake: dict[str, Any]) -> Any:
    """The QuakeRecord of the --record options (None without --record)."""
    from stepcontact.study.dam_quake import QuakeRecord

    given = {k: v for k, v in quake.items() if v is not None}
    if "horizontal" not in given:
        if given:
            flag = _quake_flags(given)[0].replace("_", "-")
            raise _Failure(f"--{flag} needs an earthquake record: give --record FILE")
        return None
    try:
        rec = QuakeRecord(**given)
        rec.records()  # read now: a bad file is an error before the static runs
        return rec
    except StepContactError as e:
        raise _Failure(_error_text(e)) from None


def _dam_section(values: dict[str, Any], *, quick: bool, friction: float | None,
                 rigid_base: bool) -> Any:
    """The DamSection of the options given (None: the default); --quick: cells of H/15,
    otherwise H/60, unless --cell is given."""
    import dataclasses

    from stepcontact.study.dam import DamSection

    changes = {k: v for k, v in values.items() if v is not None}
    if friction is not None:
        if "friction_angle" in changes:
            raise _Failure("give either --friction (tan φ) or --friction-angle (φ), not both")
        if not (math.isfinite(friction) and friction > 0):
            raise _Failure(f"--friction: must be a positive coefficient tan φ, got {friction}")
        changes["friction_angle"] = math.degrees(math.atan(friction))
    if rigid_base:
        changes["rock"] = None
    base = DamSection()
    height = changes.get("height", base.height)
    if "cell" not in changes and isinstance(height, int | float) and height > 0:
        changes["cell"] = height / (15.0 if quick else 60.0)
    try:
        return dataclasses.replace(base, **changes)
    except StepContactError as e:
        raise _Failure(_error_text(e)) from None


def _dam_study(values: dict[str, Any], *, quick: bool, friction: float | None,
               rigid_base: bool, output: Path, quiet: bool, console: Console,
               unused: Sequence[str], quake: dict[str, Any] | None = None,
               model: Path | None = None) -> None:
    """``stepcontact study dam``: build the section (or read the model file ``model``), run
    it, write the report."""
    from stepcontact.study.dam_report import write_report
    from stepcontact.study.dam_study import run_dam

    err = Console(stderr=True, soft_wrap=True, highlight=False)
    try:
        if unused:
            raise _Failure(f"{unused[0]} applies to the slab study, not to the dam study")
        section = (_dam_section(values, quick=quick, friction=friction, rigid_base=rigid_base)
                   if model is None else _dam_file(model, values, quick=quick,
                                                   friction=friction, rigid_base=rigid_base))
        rec = _quake_record(quake or {})
        if rec is not None and model is not None:
            raise _Failure("--record applies to the parametric section; a model file's dam is "
                           "studied under its combinations and the yield acceleration only")
        if rec is not None:
            section = section.replace(record=rec)
        say = None if quiet else (lambda text: err.print(Text(f"dam study: {text}",
                                                               style="cyan")))
        try:
            st = run_dam(section, progress=say)
            if say:
                say(f"writing the report into {output}")
            files = write_report(st, output)
        except (StepContactError, OSError) as e:
            raise _Failure(_error_text(e)) from None
    except _Failure as e:
        raise _fail(str(e), False) from None
    if not quiet:
        _print_dam(st, console)
    for f in files.values():
        console.print(Text(f"written: {f}", style="green"))


def _dam_file(path: Path, values: dict[str, Any], *, quick: bool, friction: float | None,
              rigid_base: bool) -> Any:
    """The dam of a model file (``--model``): the section's options do not apply (its
    [dam] table gives them), nor --quick (the mesh is the file's); the file's warnings
    (e.g. its own patterns, not used) are printed."""
    import warnings

    from stepcontact.study.dam_file import dam_file

    if quick:
        raise _Failure("--quick does not apply with --model: the mesh is the model file's "
                       "(coarsen it there)")
    given = [k for k, v in values.items() if v is not None] + (
        ["friction"] if friction is not None else []) + (["rigid_base"] if rigid_base else [])
    if given:
        flag = {"k_h": "kh", "k_v": "kv", "drain_position": "drain"}.get(given[0], given[0])
        raise _Failure(f"--{flag.replace('_', '-')} applies to the parametric section, not "
                       "with --model: give it in the model file's [dam] table")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            section = dam_file(path)
        except FileNotFoundError:
            raise _Failure(f"{path}: file not found") from None
        except StepContactError as e:
            text = _error_text(e)
            raise _Failure(text if text.startswith(str(path)) else f"{path}: {text}") from None
    _warn([str(w.message) for w in caught])
    return section


def _print_dam(st: Any, console: Console) -> None:
    """The dam study's figures at the named levels and its margins."""
    table = Table(title=f"dam study: {st.section.height:g} m dam, base "
                  f"{st.section.base_length:g} m (forces kN per metre, σ_n kPa, < 0 "
                  "compression)", box=box.SIMPLE_HEAD, title_justify="left")
    cols = ("case", "level m", "ΣN", "ΣQ", "SFF", "overturning", "resultant from toe m",
            "open m", "σ heel", "σ toe")
    for c in cols:
        table.add_column(c, justify="left" if c == "case" else "right", no_wrap=True)

    def f(v: Any, spec: str, scale: float = 1.0) -> str:
        return "—" if v is None or not math.isfinite(v) else f"{v / scale + 0.0:{spec}}"

    for n in st.named:
        v = n.values
        table.add_row(n.name, f(n.level, ".3f"), f(v["normal_force"], ".1f", 1e3),
                      f(v["shear_force"], ".1f", 1e3), f(v["shear_friction_factor"], ".3f"),
                      f(v["overturning_factor"], ".3f"), f(v["resultant_from_toe"], ".2f"),
                      f(v["open_length"], ".2f"), f(v["sigma_heel"], ".1f", 1e3),
                      f(v["sigma_toe"], ".1f", 1e3))
    _print_wide(table, console)
    first, fail = st.first_opening, st.failure
    if st.first_break is not None:
        console.print(f"the joint's bond first breaks: h = {st.first_break[0]:.3f} m at x = "
                      f"{st.first_break[1]:.2f} m")
    console.print("first opening of the base: " + (f"h = {first[0]:.3f} m at x = "
                                                   f"{first[1]:.2f} m" if first else "none"))
    console.print("failure: " + (f"h = {fail[0]:.3f} m ({fail[1]})" if fail else
                                 f"none up to {st.section.top_level:g} m"))
    console.print("margins on the level: " + ", ".join(
        f"{k} = {f(v, '.3f')}" for k, v in st.margins.items() if "k_h" not in k))
    y = st.yield_acceleration
    if y is not None:
        console.print("yield acceleration: " + (
            f"k_y = {y.k_y:.4f} ({y.mode}); margin k_y / k_h = {y.margin:.3f} (k_h = "
            f"{y.design:g})" + (f"; hand, base compressed: {y.hand['k_y']:.4f}" if y.hand
                                else "") if y.k_y is not None
            else f"not reached up to k_h = {y.top:g} (margin > {y.top / y.design:.3g})"))
    if st.combinations:
        verdicts = Table(title=f"guideline verdicts: {st.checks.guideline}"
                         + (f", {st.checks.variant}" if st.checks.variant else "")
                         + " (required values [to be checked]: see the report)",
                         box=box.SIMPLE_HEAD, title_justify="left")
        for c in ("combination", "condition", "verdict", "failed checks"):
            verdicts.add_column(c, no_wrap=c != "failed checks")
        for c in st.combinations:
            verdicts.add_row(c.combination.name, c.combination.condition, c.verdict,
                             ", ".join(r.check for r in c.checks.failed()) or "—")
        verdicts.add_row("overall", "", st.verdict, "")
        _print_wide(verdicts, console)
    if st.earthquake is not None:
        _print_quake(st.earthquake, console)


def _print_quake(q: Any, console: Console) -> None:
    """The earthquake record's run: the permanent slip beside Newmark's estimates."""
    table = Table(title=f"earthquake record: {q.record.figures().line()}; crack water "
                  f"'{q.quake.crack_water}', {q.seconds:.1f} s of CPU", box=box.SIMPLE_HEAD,
                  title_justify="left")
    for c in ("quantity", "value"):
        table.add_column(c, justify="left" if c == "quantity" else "right", no_wrap=True)
    one, two = q.newmark_one, q.newmark_two

    def mm(v: float | None) -> str:
        return "—" if v is None else f"{v * 1e3:.2f}"

    table.add_row("permanent slip, mean (mm, downstream > 0)", mm(q.slip.permanent_mean))
    table.add_row("permanent slip, largest CFE (mm)", mm(q.slip.permanent_max))
    table.add_row("Newmark one-directional, downstream (mm)",
                  mm(None if one is None else abs(one.newmark.permanent)))
    table.add_row("Newmark two-directional (mm, along −x)",
                  mm(None if two is None else -two.newmark.permanent))
    table.add_row("yield acceleration k_y (g)", "—" if q.k_y is None else f"{q.k_y:.4f}")
    table.add_row("largest open length during the shaking (m)",
                  f"{q.max_open:.2f} at {q.max_open_time:.3f} s")
    sf = q.post.get("sliding_factor")
    table.add_row("post-earthquake sliding factor", "—" if sf is None else f"{sf:.3f}")
    table.add_row("post-earthquake verdict", q.verdict)
    _print_wide(table, console)
    for note in q.notes:
        console.print(f"note: {note}")
