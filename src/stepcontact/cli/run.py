"""``stepcontact run`` and ``stepcontact demo``: check the arguments, run the model's program
(:mod:`stepcontact.cli.progress`), report it, write the result files and figures.

A run that ends with lost equilibrium is a result (exit code 0), not an error; a run that
stopped without a physical answer (contact conditions not met, no consistent scheme, cycling,
event budget) writes its result file and exits with code 3.
"""

from __future__ import annotations

import io
import json
import math
import tomllib
from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any
from warnings import catch_warnings, simplefilter

import numpy as np
import typer
from rich.console import Console
from rich.text import Text

from stepcontact.cli.common import (
    DEFAULT_WRITE_INTERVAL,
    EXIT_UNRESOLVED,
    PLOT_SUFFIXES,
    EpsOption,
    JsonOption,
    MaxEventsOption,
    Precision,
    PrecisionOption,
    QuietOption,
    SlipOption,
    WriteIntervalOption,
    _error_text,
    _fail,
    _Failure,
    _load,
    _warn,
    events_table,
    print_records,
)
from stepcontact.cli.progress import _run_program
from stepcontact.enums import SlipTreatment, Status
from stepcontact.errors import StepContactError
from stepcontact.results.summary import result_summary

if TYPE_CHECKING:
    from stepcontact.model import Model
    from stepcontact.results.file import ResultWriter
    from stepcontact.results.result import StaticResult


def _final_dynamics(model: Model, dres: Any, stop: Any, *, result_path: Path,
                    plot_path: Path | None, console: Console, as_json: bool,
                    attrs: dict[str, str] | None = None, table: bool = False) -> dict[str, Any]:
    """The model's dynamic interval after the static program, as run: write
    MODEL-dynamic.nc (and the energy ledger's figure), report.

    When SIGTERM or Ctrl-C ended it after a step (``stop``), the states so far are written
    (status ``incomplete``, no figure), then :class:`~stepcontact.io.interrupt.Terminated` is
    raised with the file's name (``dynamic_file``) for the run's exit."""
    from stepcontact.io.interrupt import Terminated

    summary = _dynamic_report(dres, model.dynamics, result_path=result_path,
                              plot_path=None if stop.stop_requested else plot_path,
                              console=console, as_json=as_json, attrs=attrs, table=table)
    if stop.stop_requested and stop.signum is not None:
        exc = Terminated(stop.signum)
        exc.dynamic_file = (summary["result_file"], float(dres.time[-1]))
        raise exc
    return summary


def _stage_file_tag(name: str) -> str:
    """A stage name as part of a file name."""
    import re

    return re.sub(r"[^A-Za-z0-9_-]+", "_", name).strip("_") or "stage"


def _dynamic_report(dres: Any, spec: Any, *, result_path: Path, plot_path: Path | None,
                    console: Console, as_json: bool, stage: str | None = None,
                    attrs: dict[str, str] | None = None, table: bool = False) -> dict[str, Any]:
    """Write a dynamic result to MODEL-dynamic.nc (the interval of an earlier ``stage``:
    MODEL-dynamic-STAGE.nc; ``attrs``: the model file of the run) with the energy ledger's
    figure, and report it (``table``: with its events and the impulses of its impacts)."""
    from stepcontact.io.interrupt import deferred
    from stepcontact.results.file import save_result

    tag = "-dynamic" if stage is None else f"-dynamic-{_stage_file_tag(stage)}"
    path = result_path.with_name(result_path.stem + tag + ".nc")
    with deferred():
        save_result(dres, path, attrs=attrs)
    written = [str(path)]
    if plot_path is not None:
        from stepcontact.post.plotting import plot_energy

        fig_path = plot_path.with_name(plot_path.stem + ("-energy" if stage is None else
                                                         f"-energy-{_stage_file_tag(stage)}")
                                       + plot_path.suffix)
        plot_energy(dres, fig_path)
        written.append(str(fig_path))
    e = dres.energy
    summary = {
        "status": dres.status.value, "message": dres.message, "time_s": float(dres.time[-1]),
        "events": len(dres.events), "impacts": int(dres.counters.get("impacts", 0)),
        "steps": int(dres.counters.get("steps", 0)),
        "energy_J": {k: float(v[-1]) for k, v in e.items()}, "result_file": str(path),
    }
    if not as_json:
        if table and dres.events:
            console.print(events_table(dres), crop=False)
        console.print(Text(
            ("dynamics" if stage is None else f"dynamics of stage '{stage}'") +
            f": {dres.message} at t = {dres.time[-1]:.6g} s; {len(dres.events)} "
            f"events ({summary['impacts']} impacts) in {summary['steps']} steps of "
            f"{spec.dt:g} s; energy (J): loads {e['external'][-1]:.6g}, friction "
            f"{e['friction'][-1]:.6g}, impacts {e['impact'][-1]:.6g}, numerical "
            f"{e['numerical'][-1]:.3g}, balance error {e['error'][-1]:.1e}"), soft_wrap=True)
        console.print(Text("written: " + ", ".join(written), style="green"), soft_wrap=True)
    return summary


#: the states a 3D run's joint map shows at most (the last segment ends)
MAP_STATES = 4
_LAM_3D = ("--lam: a 3D run's figure is its joint at the ends of the segments; draw other "
           "states with stepcontact plot RESULT.nc --kind stresses --state i")


def _plot(res: StaticResult, path: Path, lams: Sequence[float] | None) -> None:
    """Contact stresses along the interfaces, written to ``path`` (PNG, PDF or SVG); a 3D
    result's first joint in its own plane at the ends of the last segments reached (at most
    :data:`MAP_STATES`; ``stepcontact plot --kind stresses`` draws any joint and state)."""
    from stepcontact.post import plotting

    try:
        if getattr(res, "n_t", 1) > 1:
            if lams:
                raise _Failure(_LAM_3D)
            ends = np.flatnonzero(np.asarray(res.kind) == "segment_end").tolist()
            if not ends or ends[-1] != res.n_states - 1:
                ends.append(res.n_states - 1)
            plotting.plot_interface_map(res, res.interface_names[0], ends[-MAP_STATES:],
                                        path=path)
            return
        plotting.plot_interfaces(res, lams=list(lams) if lams else None, path=path)
    except ValueError as e:  # e.g. a --lam outside the last segment reached
        raise _Failure(f"plot: {e}") from None


def _check_plot_path(path: Path | None) -> None:
    if path is not None and path.suffix.lower() not in PLOT_SUFFIXES:
        raise _Failure(
            f"--plot {path}: unsupported file type, use one of {', '.join(PLOT_SUFFIXES)}"
        )


def _report(
    res: StaticResult,
    console: Console,
    *,
    title: str,
    table: bool,
) -> None:
    console.rule(title)
    if table and res.events:
        console.print(events_table(res), crop=False)  # a table wider than the terminal: whole
    console.print(Text(res.summary()), soft_wrap=True)


def _analyse(
    model: Model,
    *,
    result_path: Path,
    plot_path: Path | None,
    lams: Sequence[float] | None,
    slip: SlipTreatment,
    eps_p: float,
    max_events: int,
    quiet: bool,
    as_json: bool,
    console: Console,
    precision: str = "auto",
    writer: ResultWriter | None = None,
    scheduler: str | None = None,
) -> dict[str, Any]:
    """Solve, report, write the result file and the figure; return the JSON summary.

    The arguments are checked before solving; warnings (an empty or zero load pattern,
    displacements larger than the model) go to stderr, one line each.  ``writer``: the
    :class:`~stepcontact.results.file.ResultWriter` of ``result_path`` (its interval and
    attributes; default: one with the default interval); ``scheduler``: a dask scheduler's
    address to form the condensed matrix G on.  The static program is reported,
    drawn and its stages' dynamic intervals written as soon as it ends, before the final
    dynamic interval runs."""
    from stepcontact.fem.loadcheck import zero_patterns
    from stepcontact.io.interrupt import StopRequest
    from stepcontact.model.consistency import check_consistency, program_warnings
    from stepcontact.model.records import RecordGridWarning, record_warnings
    from stepcontact.results.file import ResultWriter
    from stepcontact.solver.program import check_dynamic_mass

    if writer is None:
        writer = ResultWriter(result_path, min_interval=1.0)

    _check_plot_path(plot_path)
    _check_lams(model, lams)
    check_consistency(model)  # what validate finds too, before any work
    check_dynamic_mass(model)  # (a free body without density: needs the assembled DOFs)
    warnings = [text for _, text in zero_patterns(model)]
    warnings += [f"{item}: {text}" for item, text in program_warnings(model)]
    warnings += [f"{item}: {text}" for item, text in record_warnings(model)]
    _warn(warnings)
    # the earthquake records' baseline figures, before any work (JSON: in the summary)
    records = print_records(model, Console(file=io.StringIO()) if as_json else console)
    result_path.parent.mkdir(parents=True, exist_ok=True)
    summaries: list[dict[str, Any]] = []

    def static_done(res: StaticResult) -> None:
        summaries.append(_static_report(model, res, result_path=result_path,
                                        plot_path=plot_path, lams=lams, quiet=quiet,
                                        as_json=as_json, console=console, warnings=warnings,
                                        attrs=writer.attrs))

    stop = StopRequest()
    with catch_warnings():  # (said above, by record_warnings)
        simplefilter("ignore", RecordGridWarning)
        out = _run_program(model, slip=slip, eps_p=eps_p, max_events=max_events,
                           progress_bar=not quiet and not as_json, output=writer,
                           precision=precision, after_static=static_done, stop=stop,
                           scheduler=scheduler)
    (summary,) = summaries
    if records:
        summary["ground_motion"] = records
    if out.dynamic is not None:
        summary["dynamics"] = _final_dynamics(model, out.dynamic, stop,
                                              result_path=result_path, plot_path=plot_path,
                                              console=console, as_json=as_json,
                                              attrs=writer.attrs, table=not quiet)
    _report_not_run(model, out.not_run, summary)
    return summary


def _report_not_run(model: Model, items: Sequence[Any], summary: dict[str, Any]) -> None:
    """Dynamic intervals asked for and not run (the program did not complete): said on
    stderr, in the summary (``dynamics_not_run``), and by the exit code."""
    not_run = [asdict(item) for item in items]
    if not not_run:
        return
    err = Console(stderr=True, soft_wrap=True, highlight=False)
    for item in not_run:
        err.print(Text(f"{item['interval']} not run: {item['reason']}", style="red"))
    summary["dynamics_not_run"] = not_run
    if model.dynamics is not None and "dynamics" not in summary:
        summary["dynamics"] = {"status": "not_run", "reason": not_run[-1]["reason"]}


def _static_report(model: Model, res: StaticResult, *, result_path: Path,
                   plot_path: Path | None, lams: Sequence[float] | None, quiet: bool,
                   as_json: bool, console: Console, warnings: list[str],
                   attrs: dict[str, str] | None) -> dict[str, Any]:
    """Report the static program's result, warn of large displacements, draw the figure,
    write the dynamic intervals of its stages; the JSON summary so far."""
    from stepcontact.results.checks import displacement_warnings

    if not as_json:
        _report(res, console, title=f"stepcontact: {model.name}", table=not quiet)
    late = displacement_warnings(res)
    _warn(late)
    warnings += late
    written = [str(result_path)]
    if plot_path is not None:
        plot_path.parent.mkdir(parents=True, exist_ok=True)
        _plot(res, plot_path, lams)
        written.append(str(plot_path))
    if not as_json:
        console.print(Text("written: " + ", ".join(written), style="green"), soft_wrap=True)
    summary = result_summary(
        res,
        model=model.name,
        result_file=str(result_path),
        plot=None if plot_path is None else str(plot_path),
        warnings=warnings,
    )
    if res.dynamics:  # the dynamic intervals of stages before the last (run in the run)
        specs = {st.name: st.dynamics for st in model.stages}
        summary["stage_dynamics"] = {
            name: _dynamic_report(dres, specs[name], result_path=result_path,
                                  plot_path=plot_path, console=console, as_json=as_json,
                                  stage=name, attrs=attrs, table=not quiet)
            for name, dres in res.dynamics.items()}
    return summary


def _check_lams(model: Model, lams: Sequence[float] | None) -> None:
    """``run --lam``: finite load factors inside the last segment of the program (the one a
    complete run ends in), checked before solving."""
    if not lams:
        return
    if model.dim == 3 and model.interfaces:
        raise _Failure(_LAM_3D)
    segments = model.segments_resolved()
    for v in lams:
        if not math.isfinite(v):
            raise _Failure(f"--lam {v}: give a finite load factor λ of the last segment")
        if segments:
            name, a, b = segments[-1]
            if not min(a, b) <= v <= max(a, b):
                raise _Failure(f"--lam {v:g}: outside the last segment of the program "
                               f"('{name}', λ from {a:g} to {b:g}); --lam draws load factors "
                               "of the last segment reached")


def _model_attrs(model_file: Path) -> dict[str, str]:
    """What a result file records of its model file: the absolute path and a SHA-256 hash of
    its content (``export``/``plot`` find the model by it; a changed file is not used)."""
    import hashlib

    attrs = {"model_file": str(model_file.resolve())}
    try:
        attrs["model_sha256"] = hashlib.sha256(model_file.read_bytes()).hexdigest()
    except OSError:  # reported when the model is loaded
        pass
    return attrs


def _interrupted(e: BaseException, writer: ResultWriter | None, as_json: bool) -> typer.Exit:
    """The run was ended by SIGTERM or SIGINT: say what the result file holds; the exit to
    raise (code 128 + the signal's number)."""
    from stepcontact.io.interrupt import Terminated

    name = e.name if isinstance(e, Terminated) else "SIGINT"
    code = e.exit_code if isinstance(e, Terminated) else 130
    written = None if writer is None else writer.written
    dyn = getattr(e, "dynamic_file", None)
    if dyn is not None:
        text = (f"interrupted by {name} in the dynamic interval at t = {dyn[1]:.6g} s: "
                f"'{dyn[0]}' holds its states up to there (status incomplete), "
                f"'{writer.path}' the static program's result")
    elif written is None:
        text = f"interrupted by {name} before the run wrote anything: no result file written"
    elif written[1] == Status.INCOMPLETE.value:
        text = (f"interrupted by {name}: '{writer.path}' holds the {written[0]} states "
                "finished (status incomplete); run again to complete it")
    else:
        text = (f"interrupted by {name} after the static program: '{writer.path}' holds its "
                f"result ({written[0]} states, status {written[1]}); a dynamic interval or "
                "figure after it was not written")
    Console(stderr=True, soft_wrap=True, highlight=False).print(
        Text(f"error: {text}", style="red"))
    if as_json:
        typer.echo(json.dumps({"status": "interrupted", "signal": name, "message": text,
                               "result_file": None if written is None else str(writer.path)}))
    return typer.Exit(code)


def run(
    model_file: Annotated[Path, typer.Argument(metavar="MODEL.toml", help="TOML model file.")],
    output: Annotated[
        Path | None,
        typer.Option("--output", "-o", help="Result file (netCDF4). Default: MODEL.nc."),
    ] = None,
    slip: SlipOption = SlipTreatment.EXACT,
    eps_p: EpsOption = 0.01,
    plot: Annotated[
        Path | None,
        typer.Option("--plot", help="Figure of the contact stresses (.png, .pdf or .svg; a "
                     "3D model: its first joint in its own plane at the segment ends). "
                     "Default: beside the result file, RESULT.png (MODEL.png without -o)."),
    ] = None,
    no_plot: Annotated[bool, typer.Option("--no-plot", help="Do not draw the figure.")] = False,
    lam: Annotated[
        list[float] | None,
        typer.Option("--lam", help="Load factor λ of the last segment reached to draw "
                     "(repeat for several). Default: the end of every segment."),
    ] = None,
    max_events: MaxEventsOption = 100000,
    quiet: QuietOption = False,
    as_json: JsonOption = False,
    precision: PrecisionOption = Precision.AUTO,
    write_interval: WriteIntervalOption = DEFAULT_WRITE_INTERVAL,
    scheduler: Annotated[
        str | None,
        typer.Option("--scheduler", metavar="ADDRESS", help="Form the condensed contact "
                     "matrix G on a dask.distributed cluster: the scheduler's address, e.g. "
                     "tcp://10.0.0.5:8786 (each worker factorises once and solves a share of "
                     "G's columns; the same result). Default: in this process."),
    ] = None,
) -> None:
    """Run the load program of a model file.

    Prints the events and the summary; writes the result file and a contact-stress figure.

    A dynamic interval (the dynamics table) runs after the load program and writes
    MODEL-dynamic.nc; its earthquake records' baseline figures (PGA, Arias intensity, 5–95 %
    duration) and their sign convention are printed first (--json: ground_motion).
    When the program does not complete (lost equilibrium, no answer), the interval cannot
    start: 'dynamics not run: <reason>' is printed on stderr, the JSON summary lists it under
    "dynamics_not_run", and the exit code is 3 (the static result is still written).
    The result file is written as the run goes (at segment ends, and at least every
    --write-interval seconds), locked against a second run writing it, and on SIGTERM or
    Ctrl-C the states finished are written before the run ends (exit code 128 + the signal's
    number). See "Faults" in docs/cli.md.

    Examples:

        stepcontact run dam.toml                  # writes dam.nc and dam.png

        stepcontact run dam.toml -o r.nc --plot r.pdf --lam 1.5 --lam 2

        stepcontact run dam.toml --slip article --eps-p 0.01

        stepcontact run dam.toml --json --quiet   # JSON summary only

        stepcontact run dam.toml --scheduler tcp://10.0.0.5:8786   # G on a dask cluster
    """
    from stepcontact.io.atomic import output_lock
    from stepcontact.io.interrupt import Terminated, signals_interrupt
    from stepcontact.results.file import ResultWriter

    console = Console(highlight=False)
    result_path = output if output is not None else model_file.with_suffix(".nc")
    writer = None
    try:
        with signals_interrupt():
            if not (math.isfinite(write_interval) and write_interval > 0):
                raise _Failure(f"--write-interval {write_interval}: give a positive number "
                               "of seconds")
            writer = ResultWriter(result_path, min_interval=1.0, interval=write_interval,
                                  attrs=_model_attrs(model_file))
            with output_lock(result_path):
                model = _load(model_file)
                summary = _analyse(
                    model, result_path=result_path,
                    plot_path=None if no_plot else (plot or result_path.with_suffix(".png")),
                    lams=lam, slip=slip, eps_p=eps_p, max_events=max_events, quiet=quiet,
                    as_json=as_json, console=console, precision=precision.value,
                    writer=writer, scheduler=scheduler)
    except Terminated as e:
        raise _interrupted(e, writer, as_json) from None
    except _Failure as e:
        raise _fail(str(e), as_json) from None
    except (StepContactError, OSError, tomllib.TOMLDecodeError) as e:
        raise _fail(_error_text(e), as_json) from None
    if as_json:
        typer.echo(json.dumps(summary, indent=2))
    if (summary.get("status") not in (Status.COMPLETED.value, Status.EQUILIBRIUM_LOST.value)
            or summary.get("dynamics_not_run")):
        raise typer.Exit(EXIT_UNRESOLVED)


def demo(
    output: Annotated[
        Path, typer.Option("--output", "-o", help="Directory for the model and result files.")
    ] = Path("stepcontact-demo"),
    slip: SlipOption = SlipTreatment.EXACT,
    eps_p: EpsOption = 0.01,
    quiet: QuietOption = False,
    as_json: JsonOption = False,
) -> None:
    """Run the two demo models: a block sliding under a push, a block tipping under uplift.

    Writes their model files, result files and figures into a directory.

    Examples:

        stepcontact demo                       # into ./stepcontact-demo/

        stepcontact demo -o /tmp/demo --quiet
    """
    from stepcontact.demo import DEMO_FILES, demo_model, demo_text, demo_uplift_model

    console = Console(highlight=False)
    builders = {"slide": demo_model, "uplift": demo_uplift_model}
    summaries = {}
    try:
        output.mkdir(parents=True, exist_ok=True)
        for variant, build in builders.items():
            toml_path = output / DEMO_FILES[variant]
            toml_path.write_text(demo_text(variant), encoding="utf-8")
            summaries[variant] = _analyse(
                build(),
                result_path=toml_path.with_suffix(".nc"),
                plot_path=toml_path.with_suffix(".png"),
                lams=None,
                slip=slip,
                eps_p=eps_p,
                max_events=100000,
                quiet=quiet,
                as_json=as_json,
                console=console,
            )
    except (StepContactError, OSError) as e:
        raise _fail(_error_text(e), as_json) from None
    if as_json:
        typer.echo(json.dumps(summaries, indent=2))
