"""Command line: ``stepcontact run MODEL.toml``, ``stepcontact demo``, ``stepcontact validate``,
``stepcontact sweep STUDY.toml``, ``stepcontact study slab``.

The CLI sits at the end of the data flow (model file -> model -> solver -> result -> files) and
only wires those pieces together; the progress bar is a solver hook.  Bad input never shows a
traceback: any :class:`~stepcontact.errors.StepContactError`, a missing file or a broken TOML
file prints one red line ``error: ...`` on stderr and exits with code 2.  A run that ends with
lost equilibrium is a result (exit code 0), not an error; a run that stopped without a physical
answer (contact conditions not met, no consistent scheme, cycling, event budget) writes its
result file and exits with code 3.

Example
-------
.. code-block:: console

    $ stepcontact run dam.toml -o dam.nc --plot dam.png --lam 1.5 --lam 2.0
    $ stepcontact run dam.toml --json --quiet     # machine-readable summary on stdout
    $ stepcontact sweep friction.toml --workers 4  # a parameter sweep (docs/sweeps.md)
    $ stepcontact study slab --quick -o slab-quick  # the stilling-basin slab (docs/slab-study.md)
    $ stepcontact demo -o demo-out
"""

from __future__ import annotations

import contextlib
import json
import math
import re
import tomllib
from collections.abc import Sequence
from dataclasses import asdict
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer
from rich import box
from rich.console import Console
from rich.markup import escape
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table as _RichTable
from rich.text import Text

from stepcontact import __version__
from stepcontact.enums import SlipTreatment, Status
from stepcontact.errors import StepContactError
from stepcontact.fem.level import is_virtual

if TYPE_CHECKING:
    from stepcontact.model import Model
    from stepcontact.results.file import ResultWriter
    from stepcontact.results.result import StaticResult
    from stepcontact.solver.program import ProgramResult

EXIT_ERROR = 2  #: exit code for bad input (model errors, missing files, solver errors)
#: exit code of a run that stopped without a physical answer: the contact conditions could not
#: be met, no consistent scheme, cycling or the event budget (the result file is written)
EXIT_UNRESOLVED = 3
PLOT_SUFFIXES = (".png", ".pdf", ".svg")
TABLE_ROWS = 50  #: at most this many events are printed (the first ones and the last 10)
_TAIL_ROWS = 10

app = typer.Typer(
    name="stepcontact",
    help="Event-driven static analysis of 2D structures with unilateral contact and "
    "Coulomb friction (contact finite elements, step-by-step method).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


#: a number in a table cell (never split or cut: its column is at least this wide)
_NUMBER = re.compile(r"[+\-−]?(?:\d[\d.,]*|\.\d+)(?:[eE][+\-−]?\d+)?%?")


class Table(_RichTable):
    """rich's Table as the CLI prints it: text given as ``str`` (cells, headers, the title) is
    shown as written — never read as rich markup, so ``stages[1]`` or ``loads[water]`` keep
    their brackets — and no number is ever truncated ("4.6…") or split: a column is at least
    as wide as the longest number in it, text wraps (or folds) instead, and a table whose
    numbers alone need more than the terminal's width is printed that wide."""

    def __init__(self, *headers: Any, title: Any = None, **kw: Any) -> None:
        super().__init__(*headers, title=Text(title) if isinstance(title, str) else title, **kw)

    def add_column(self, header: Any = "", *args: Any, **kw: Any) -> None:
        kw["no_wrap"] = False
        kw.setdefault("overflow", "fold")
        if kw["overflow"] == "ellipsis":
            kw["overflow"] = "fold"
        super().add_column(Text(header) if isinstance(header, str) else header, *args, **kw)

    def add_row(self, *cells: Any, **kw: Any) -> None:
        out = []
        for col, cell in zip(self.columns, cells, strict=False):
            plain = cell if isinstance(cell, str) else cell.plain if isinstance(cell, Text) \
                else None
            if plain is not None:
                widest = max((len(t) for t in _NUMBER.findall(plain)), default=0)
                col.min_width = max(col.min_width or 0, widest) or None
            out.append(Text(cell) if isinstance(cell, str) else cell)
        super().add_row(*out, *cells[len(out):], **kw)

    def __rich_console__(self, console: Any, options: Any) -> Any:
        need = self._extra_width + sum((c.min_width or 1) + self._get_padding_width(i)
                                       for i, c in enumerate(self.columns))
        if options.max_width < need:
            options = options.update(width=need)
        yield from super().__rich_console__(console, options)


class _Failure(Exception):
    """Raised inside a command to end it with ``error: message`` and exit code 2."""


# --------------------------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------------------------
def _error_text(exc: BaseException) -> str:
    """A one-line description of an input error."""
    if isinstance(exc, FileNotFoundError):
        text = f"file not found: {exc.filename}" if exc.filename else str(exc)
    elif isinstance(exc, OSError) and exc.filename:
        text = f"{exc.strerror or exc}: {exc.filename}"
    else:
        text = str(exc)
    return " ".join(text.split())


def _fail(message: str, as_json: bool) -> typer.Exit:
    """Print ``error: message`` (red, one line) on stderr; return the exit to raise."""
    Console(stderr=True, soft_wrap=True, highlight=False).print(
        Text(f"error: {message}", style="red")
    )
    if as_json:
        typer.echo(json.dumps({"status": "error", "message": message}))
    return typer.Exit(EXIT_ERROR)


def _load(path: Path) -> Model:
    """Load a model file; errors name the file; its warnings (implausible values,
    deprecations) are printed as ``warning: …`` lines on stderr."""
    import warnings

    from stepcontact.io.modelfile import load_model

    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            model = load_model(path)
        _warn([str(w.message) for w in caught
               if issubclass(w.category, UserWarning | FutureWarning)])
        return model
    except FileNotFoundError as e:
        raise _Failure(f"model file not found: {e.filename or path}") from None
    except (StepContactError, tomllib.TOMLDecodeError) as e:
        msg = _error_text(e)
        raise _Failure(msg if msg.startswith(str(path)) else f"{path}: {msg}") from None


class ProgressHook:
    """Solver hook feeding a rich progress bar: one unit of the bar per load segment.

    Within a segment the bar follows λ from the segment's start to its end.
    """

    def __init__(self, progress: Progress, task: Any, segments: Sequence[tuple[str, float, float]]):
        self.progress = progress
        self.task = task
        self.segments = list(segments)
        self.done = 0

    def before_run(self, segments: Sequence[tuple[str, float, float]]) -> None:
        """The program as the solver runs it (a staged model's automatic segments too)."""
        self.segments = list(segments)
        self.progress.update(self.task, total=max(len(self.segments), 1))

    def _describe(self, segment: int, lam: float, n_events: int) -> str:
        name = self.segments[segment][0] if 0 <= segment < len(self.segments) else "?"
        return f"segment {segment} '{escape(name)}'  λ = {lam:.4g}  events: {n_events}"

    def after_event(self, info: Any) -> None:
        """Move the bar to the event's λ (``info``: step, segment, lam, n_events)."""
        seg = int(info.segment)
        frac = 0.0
        if 0 <= seg < len(self.segments):
            _, a, b = self.segments[seg]
            frac = 1.0 if b == a else min(max((info.lam - a) / (b - a), 0.0), 1.0)
        self.progress.update(
            self.task,
            completed=seg + frac,
            description=self._describe(seg, float(info.lam), int(info.n_events)),
        )

    def after_step(self, step: int, t: float, end: float) -> None:
        """A time step of the dynamic interval of a stage (run inside the static run)."""
        self.progress.update(self.task, description=f"dynamics t = {t:.4g} of {end:.4g} s")

    def after_segment(self, result: Any) -> None:
        """A load segment is finished."""
        self.done += 1
        self.progress.update(self.task, completed=self.done)


def _progress_bar(progress_bar: bool) -> Progress:
    """A transient progress bar on stderr (disabled: shows nothing)."""
    return Progress(TextColumn("{task.description}"), BarColumn(), TimeElapsedColumn(),
                    console=Console(stderr=True), transient=True, disable=not progress_bar)


class _TimeProgress:
    """Progress of a dynamic interval in simulated time."""

    def __init__(self, progress: Progress, task) -> None:
        self.progress, self.task = progress, task

    def after_step(self, step: int, t: float, end: float) -> None:
        self.progress.update(self.task, completed=min(t, end),
                             description=f"dynamics t = {t:.4g} s")


def _run_program(
    model: Model, *, slip: SlipTreatment, eps_p: float, max_events: int, progress_bar: bool,
    output: Path | ResultWriter | None = None, precision: str = "auto",
    after_static: Any = None, stop: Any = None,
) -> ProgramResult:
    """Run the whole program of the model (:func:`stepcontact.run`) with a progress bar on
    stderr: one unit per load segment, then the final dynamic interval in simulated time.
    ``after_static(res)``: called when the static program ends (its bar gone), before the
    final interval; ``stop``: a :class:`~stepcontact.io.interrupt.StopRequest` that SIGTERM
    and Ctrl-C set during the final interval (polled before every step) instead of raising."""
    from stepcontact.io.interrupt import signals_stop
    from stepcontact.solver.program import run as run_program

    segments = model.segments_resolved()
    static_bar = _progress_bar(progress_bar)
    task = static_bar.add_task(f"running '{escape(model.name)}'", total=max(len(segments), 1))
    hooks = (ProgressHook(static_bar, task, segments),) if progress_bar else ()
    dynamic_bar = _progress_bar(progress_bar)
    dynamic_hooks: tuple = () if stop is None else (stop,)
    if model.dynamics is not None:
        dtask = dynamic_bar.add_task("dynamics", total=model.dynamics.duration)
        dynamic_hooks = ((_TimeProgress(dynamic_bar, dtask),) if progress_bar else ()) + \
            dynamic_hooks
    with contextlib.ExitStack() as stack, contextlib.ExitStack() as static_part:
        static_part.enter_context(static_bar)

        def static_done(res: StaticResult) -> None:
            static_part.close()  # (the bar goes before the report)
            if after_static is not None:
                after_static(res)

        def dynamics_start() -> None:
            if stop is not None:
                stack.enter_context(signals_stop(stop))
            stack.enter_context(dynamic_bar)

        return run_program(model, slip=slip.value, eps_p=eps_p, max_events=max_events,
                           hooks=hooks, output=output, precision=precision,
                           dynamic_hooks=dynamic_hooks, after_static=static_done,
                           before_dynamics=dynamics_start)


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


def events_table(res: StaticResult, max_rows: int = TABLE_ROWS) -> Table:
    """The event log as a rich table (forces in kN; the impulses of impacts in kN·s where a
    dynamic run has any); the first and last events when long."""
    events = list(res.events)
    impulses = any(getattr(e, "impulse_n", 0.0) or getattr(e, "impulse_t", 0.0)
                   for e in events)
    table = Table(title=f"events ({len(events)})", title_justify="left", box=box.SIMPLE_HEAD,
                  show_edge=False, pad_edge=False, collapse_padding=True)
    for name in ("step", "pattern", "t (s)" if res.path_axis == "time" else "λ", "interface",
                 "s (m)", "CFE", "transition", "N (kN)", "Q (kN)",
                 *(("impulse N (kN·s)", "impulse Q (kN·s)") if impulses else ())):
        left = name in ("pattern", "interface", "transition")
        table.add_column(name, justify="left" if left else "right", no_wrap=True)
    if len(events) > max_rows:
        head = max_rows - _TAIL_ROWS
        shown: list[Any] = events[:head] + [None] + events[-_TAIL_ROWS:]
        table.caption = (
            f"showing the first {head} and the last {_TAIL_ROWS} of {len(events)} events; "
            "all are in the result file"
        )
    else:
        shown = events
    for e in shown:
        if e is None:
            table.add_row("…", "", "", f"{len(events) - max_rows} more",
                          *[""] * (len(table.columns) - 4))
            continue
        table.add_row(
            str(e.step),
            e.pattern,
            f"{e.lam:.6g}",
            e.interface,
            f"{e.position:.4g}",
            str(e.local),
            e.transition.value,
            _kN(e.N),
            _kN(e.Q),
            *((f"{e.impulse_n / 1e3:.4g}", f"{e.impulse_t / 1e3:.4g}") if impulses else ()),
        )
    return table


def _plot(res: StaticResult, path: Path, lams: Sequence[float] | None) -> None:
    """Contact stresses along the interfaces, written to ``path`` (PNG, PDF or SVG)."""
    from stepcontact.post import plotting

    try:
        plotting.plot_interfaces(res, lams=list(lams) if lams else None, path=path)
    except ValueError as e:  # e.g. a --lam outside the last segment reached
        raise _Failure(f"plot: {e}") from None


def _check_plot_path(path: Path | None) -> None:
    if path is not None and path.suffix.lower() not in PLOT_SUFFIXES:
        raise _Failure(
            f"--plot {path}: unsupported file type, use one of {', '.join(PLOT_SUFFIXES)}"
        )


def _kN(force: float) -> str:
    """A force in N shown in kN with 3 decimals (no "-0.000")."""
    return f"{round(force / 1e3, 3) + 0.0:.3f}"


def _jsonable(v: Any) -> Any:
    if hasattr(v, "item"):  # numpy scalar
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, int | float | str | bool) or v is None:
        return v
    return str(v)


def result_summary(res: StaticResult, **extra: Any) -> dict[str, Any]:
    """Machine-readable summary of a run (what ``--json`` prints)."""
    from stepcontact.results.result import transition_counts

    return {
        "status": res.status.value,
        "message": res.message,
        "nonunique": res.nonunique,
        "events": len(res.events),
        "states": int(res.n_states),
        "cfes": int(res.m),
        "transitions": transition_counts(res.events),
        "multipliers": [
            {k: _jsonable(v) for k, v in asdict(mu).items()} for mu in res.multipliers
        ],
        "counters": {k: _jsonable(v) for k, v in res.counters.items()},
        "load_resultants": _load_resultants(res),
        **extra,
    }


def _load_resultants(res: StaticResult) -> dict[str, dict[str, Any]]:
    """{pattern: {"Fx": N, "Fy": N, "Mz": N·m about the origin}} per unit λ."""
    out = {}
    levels = res.level_patterns
    for name in res.pattern_names:
        if is_virtual(name):
            continue
        if name in levels:  # the factor is a water level: the load at the last state
            fx, fy, mz = (_jsonable(float(v)) for v in res.load_resultant(name, -1))
            out[name] = {"Fx": fx, "Fy": fy, "Mz": mz, "at": "last state (water level)"}
            continue
        fx, fy, mz = (_jsonable(float(v)) for v in res.load_resultant(name))
        out[name] = {"Fx": fx, "Fy": fy, "Mz": mz}
    return out


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
) -> dict[str, Any]:
    """Solve, report, write the result file and the figure; return the JSON summary.

    The arguments are checked before solving; warnings (an empty or zero load pattern,
    displacements larger than the model) go to stderr, one line each.  ``writer``: the
    :class:`~stepcontact.results.file.ResultWriter` of ``result_path`` (its interval and
    attributes; default: one with the default interval).  The static program is reported,
    drawn and its stages' dynamic intervals written as soon as it ends, before the final
    dynamic interval runs."""
    from stepcontact.fem.loadcheck import zero_patterns
    from stepcontact.io.interrupt import StopRequest
    from stepcontact.model.consistency import check_consistency, program_warnings
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
    _warn(warnings)
    result_path.parent.mkdir(parents=True, exist_ok=True)
    summaries: list[dict[str, Any]] = []

    def static_done(res: StaticResult) -> None:
        summaries.append(_static_report(model, res, result_path=result_path,
                                        plot_path=plot_path, lams=lams, quiet=quiet,
                                        as_json=as_json, console=console, warnings=warnings,
                                        attrs=writer.attrs))

    stop = StopRequest()
    out = _run_program(model, slip=slip, eps_p=eps_p, max_events=max_events,
                       progress_bar=not quiet and not as_json, output=writer,
                       precision=precision, after_static=static_done, stop=stop)
    (summary,) = summaries
    if out.dynamic is not None:
        summary["dynamics"] = _final_dynamics(model, out.dynamic, stop,
                                              result_path=result_path, plot_path=plot_path,
                                              console=console, as_json=as_json,
                                              attrs=writer.attrs, table=not quiet)
    not_run = [asdict(item) for item in out.not_run]
    if not_run:  # asked for, not run: said on stderr, in the summary, and by the exit code
        err = Console(stderr=True, soft_wrap=True, highlight=False)
        for item in not_run:
            err.print(Text(f"{item['interval']} not run: {item['reason']}", style="red"))
        summary["dynamics_not_run"] = not_run
        if model.dynamics is not None and "dynamics" not in summary:
            summary["dynamics"] = {"status": "not_run", "reason": not_run[-1]["reason"]}
    return summary


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


def _warn(texts: Sequence[str]) -> None:
    """Each warning as one yellow line ``warning: ...`` on stderr (also with --json, whose
    summary lists them under "warnings")."""
    err = Console(stderr=True, soft_wrap=True, highlight=False)
    for text in texts:
        err.print(Text(f"warning: {' '.join(text.split())}", style="yellow"))


def _check_lams(model: Model, lams: Sequence[float] | None) -> None:
    """``run --lam``: finite load factors inside the last segment of the program (the one a
    complete run ends in), checked before solving."""
    if not lams:
        return
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


# --------------------------------------------------------------------------------------------
# commands
# --------------------------------------------------------------------------------------------
def _version(value: bool) -> None:
    if value:
        typer.echo(f"stepcontact {__version__}")
        raise typer.Exit()


@app.callback()
def main(
    version: Annotated[
        bool,
        typer.Option("--version", callback=_version, is_eager=True,
                     help="Show the version and exit."),
    ] = False,
) -> None:
    """Event-driven static analysis of 2D structures with unilateral contact and friction."""


SlipOption = Annotated[
    SlipTreatment,
    typer.Option("--slip", help="Slip in the working scheme: 'exact' (Q = σfN, every event "
                 "exact) or 'article' (ε_p step limit with compensating forces)."),
]
EpsOption = Annotated[
    float,
    typer.Option("--eps-p", min=0.0, help="ε_p: allowed relative change of the friction "
                 "limit per step (--slip article only), eq. (5)."),
]
MaxEventsOption = Annotated[
    int, typer.Option("--max-events", min=1, help="Stop after this many events.")
]


class Precision(StrEnum):
    AUTO = "auto"
    FLOAT64 = "float64"
    FLOAT32 = "float32"


PrecisionOption = Annotated[
    Precision,
    typer.Option("--precision", help="Precision of the dense contact matrices: 'auto' "
                 "(float64 while they fit in half the memory, float32 beyond), 'float64', or "
                 "'float32' (half the memory; every solve refined to float64 accuracy)."),
]
QuietOption = Annotated[
    bool, typer.Option("--quiet", "-q", help="No progress bar and no event table.")
]
DEFAULT_WRITE_INTERVAL = 15.0  #: s, as stepcontact.results.file.WRITE_INTERVAL
WriteIntervalOption = Annotated[
    float,
    typer.Option("--write-interval", metavar="SECONDS", help="Longest wall time between two "
                 "writes of the result file during the run, s: a run killed outright loses "
                 "at most about this much work."),
]
JsonOption = Annotated[
    bool, typer.Option("--json", help="Print a machine-readable JSON summary on stdout only.")
]


@app.command()
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
        typer.Option("--plot", help="Figure of the contact stresses (.png, .pdf or .svg). "
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
) -> None:
    """Run the load program of a model file.

    Prints the events and the summary; writes the result file and a contact-stress figure.

    A dynamic interval (the dynamics table) runs after the load program and writes
    MODEL-dynamic.nc.
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
                    model,
                    result_path=result_path,
                    plot_path=None if no_plot else (plot or result_path.with_suffix(".png")),
                    lams=lam,
                    slip=slip,
                    eps_p=eps_p,
                    max_events=max_events,
                    quiet=quiet,
                    as_json=as_json,
                    console=console,
                    precision=precision.value,
                    writer=writer,
                )
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


@app.command()
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


def problems_table(problems: Sequence[Any], title: str) -> Table:
    """Problems of a model file (:class:`~stepcontact.io.modelfile.Problem`) as a rich table."""
    table = Table(title=title, title_justify="left", box=box.SIMPLE_HEAD, show_edge=False,
                  pad_edge=False)
    table.add_column("", no_wrap=True)
    table.add_column("item", overflow="fold")
    table.add_column("problem", overflow="fold")
    for p in problems:
        style = "red" if p.severity == "error" else "yellow"
        table.add_row(Text(p.severity, style=style), p.item, p.message)
    return table


@app.command()
def validate(
    model_file: Annotated[Path, typer.Argument(metavar="MODEL.toml", help="TOML model file.")],
    as_json: JsonOption = False,
) -> None:
    """Check a model file and list all its problems at once (alias: check).

    Checks the schema, names, mesh groups, materials and element quality.

    Finds orphan nodes and bodies that overlap without an interface; assembles the model and
    checks, without solving, that it is no mechanism with every CFE stuck (names the bodies
    that can move); warns about empty or zero load patterns.

    A 3D mesh (volume cells or physical volumes) is an error naming the mesh file and its
    element types: 3D models are not supported yet.

    Exit code 2 when there are errors (warnings alone exit with 0).

    Examples:

        stepcontact validate examples/data/gmsh_block.toml

        stepcontact validate dam.toml --json
    """
    from stepcontact.io.modelfile import validation_report

    console = Console(highlight=False, soft_wrap=True)
    report = validation_report(model_file)
    errors, warnings = report.errors, report.warnings
    if as_json:
        typer.echo(json.dumps({
            "status": "error" if errors else "ok",
            "file": str(model_file),
            "errors": len(errors),
            "warnings": len(warnings),
            "problems": [asdict(p) for p in report.problems],
            "summary": report.summary(),
        }, indent=2))
    elif report.problems:
        console.print(problems_table(report.problems, f"{model_file}: {len(errors)} errors, "
                                     f"{len(warnings)} warnings"))
    if errors:
        first = errors[0]
        # a problem of the file itself (not found, not TOML) is already named by the file
        msg = first.message if first.item == str(model_file) else f"{first.item}: {first.message}"
        if len(errors) > 1:
            msg = f"{len(errors)} errors, the first: {msg}"
        Console(stderr=True, soft_wrap=True, highlight=False).print(
            Text(f"error: {model_file}: {' '.join(msg.split())}", style="red")
        )
        raise typer.Exit(EXIT_ERROR)
    if not as_json:
        s = report.summary()
        console.print(Text(
            f"model OK: '{s['model']}': {s['bodies']} bodies, {s['nodes']} nodes, {s['dofs']} "
            f"DOFs, {s['cfes']} CFEs on {s['interfaces']} interfaces, {s['patterns']} load "
            f"patterns, {s['segments']} segments"
            + (f" in {s['stages']} stages" if s.get("stages") else "")
            + (f" ({len(warnings)} warnings)" if warnings else ""),
            style="green",
        ))


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


@app.command()
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
    from stepcontact.io.atomic import OutputLockedError, output_lock
    from stepcontact.io.interrupt import Terminated, signals_interrupt
    from stepcontact.study.studyfile import load_study, run_study
    from stepcontact.study.sweep import StudyError

    console = Console(highlight=False, soft_wrap=True)
    study = None
    try:
        if serial and scheduler is not None:
            raise _Failure("give either --serial or --scheduler, not both")
        err = Console(stderr=True, soft_wrap=True, highlight=False)
        announce = None if quiet or as_json else (lambda text: err.print(Text(text)))
        try:
            study = load_study(study_file, force=force, announce=announce)
        except StudyError as e:
            raise _Failure(_error_text(e)) from None
        executor = "serial" if serial else scheduler if scheduler is not None else "process"
        try:
            with signals_interrupt(), output_lock(study.store / "sweep.nc", "sweep store"):
                ds = run_study(study, executor=executor, workers=workers,
                               progress=not quiet and not as_json, rerun=rerun)
        except OutputLockedError as e:
            raise _Failure(_error_text(e)) from None
        except (StudyError, OSError, TimeoutError) as e:
            where = f"--scheduler {scheduler}: " if scheduler is not None else ""
            raise _Failure(where + _error_text(e)) from None
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
        typer.echo(json.dumps({"status": "failed" if failed else "ok", "study": study.name,
                               "store": str(study.store), "dataset": str(path),
                               "failed": len(failed), "cases": rows}, indent=2,
                              ensure_ascii=False))
    elif not quiet:
        from rich.measure import Measurement

        table = sweep_table(ds, outputs, f"sweep '{study.name}': {ds.sizes['case']} cases, "
                            f"{len(failed)} failed")
        wide = Console(width=1000)
        need = Measurement.get(wide, wide.options, table).maximum
        if need > console.width:  # a wide table is not squeezed into the terminal
            console = Console(highlight=False, soft_wrap=True, width=need)
        console.print(table)
    err = Console(stderr=True, soft_wrap=True, highlight=False)
    for i in failed:
        err.print(Text(f"failed: {ds['case'].values[i]}: {ds['case_message'].values[i]}",
                       style="red"))
    if not as_json:
        console.print(Text(f"written: {path}", style="green"))
    if failed or unresolved:
        raise typer.Exit(EXIT_UNRESOLVED)


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


STUDIES = ("slab",)


@app.command()
def study(
    name: Annotated[str, typer.Argument(metavar="STUDY", help="The study: slab (the "
                                        "stilling-basin slab of the article, Figs. 4–5).")],
    output: Annotated[
        Path, typer.Option("--output", "-o", help="Directory of the study: the cases, their "
                           "result files, the dataset, the figures and the report.")
    ] = Path("slab-study"),
    quick: Annotated[
        bool, typer.Option("--quick", help="A coarse version (7 cases: three positions, one "
                           "duration, a 20 × 2 slab mesh, tolerance 5 cm; its mesh check on "
                           "40 × 4): about 30 s on two idle cores (the full study, 29 cases "
                           "and its mesh check: about 7 min with --workers 2).")
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
                                   "the slab's base (default 0.6).")
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
) -> None:
    """Run a ready-made study and write its figures and report. See docs/slab-study.md.

    slab: the limit thickness of a stilling-basin slab (apron) on its soil foundation against
    the position of a pressure impulse (the article's Fig. 5), beside the static-only limit,
    with the contact stresses just before lift-off (Fig. 4), a table of all cases and the
    design formulas for the same inputs; every case is one case of a sweep (resumable: a
    rerun skips the finished cases).

    Examples:

        stepcontact study slab --quick -o slab-quick

        stepcontact study slab --E0 30 --amplitude 0.3 --workers 4

        stepcontact study slab --scheduler tcp://10.0.0.5:8786
    """
    import dataclasses

    from stepcontact.study import basin

    console = Console(highlight=False, soft_wrap=True)
    try:
        if name not in STUDIES:
            raise _Failure(f"unknown study '{name}' (known: {', '.join(STUDIES)})")
        if serial and scheduler is not None:
            raise _Failure("give either --serial or --scheduler, not both")
        changes = {k: v for k, v in (("E0", E0), ("h_kr", h_kr), ("amplitude", amplitude),
                                     ("friction", friction), ("gap_pressure", gap_pressure))
                   if v is not None}
        if friction is not None:
            from stepcontact.model.plausible import message

            _warn([w for w in (message("friction", friction, "--friction"),) if w])
        if positions:
            changes["positions"] = tuple(positions)
        if durations:
            changes["durations"] = tuple(durations)
        try:
            st = (basin.quick(**changes) if quick
                  else dataclasses.replace(basin.BasinStudy(), **changes))
        except StepContactError as e:
            raise _Failure(_error_text(e)) from None
        executor = "serial" if serial else scheduler if scheduler is not None else "process"
        try:
            ds = basin.run_basin(st, output, executor=executor, workers=workers,
                                 progress=not quiet, rerun=rerun)
        except (StepContactError, OSError, TimeoutError) as e:
            raise _Failure(_error_text(e)) from None
    except _Failure as e:
        raise _fail(str(e), False) from None
    from stepcontact.study.report import all_failed, failure_reasons, write_report

    files = write_report(ds, st, output / "report")
    failed = [i for i, cs in enumerate(ds["case_status"].values) if cs != "ok"]
    if all_failed(ds):
        for f in files.values():
            console.print(Text(f"written: {f}", style="green"))
        reasons = failure_reasons(ds)
        msg, k, cid = reasons[0]
        more = f" ({len(reasons) - 1} other reason(s) in the report)" if len(reasons) > 1 else ""
        raise _fail(f"all {ds.sizes['case']} cases of the {name} study failed; {k} of them "
                    f"(e.g. {cid}): {msg}{more}", False)
    if not quiet:
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
    err = Console(stderr=True, soft_wrap=True, highlight=False)
    for i in failed:
        err.print(Text(f"failed: {ds['case'].values[i]}: {ds['case_message'].values[i]}",
                       style="red"))
    for f in files.values():
        console.print(Text(f"written: {f}", style="green"))
    if failed:
        raise typer.Exit(EXIT_UNRESOLVED)


@app.command(hidden=True)
def check(
    model_file: Annotated[Path, typer.Argument(metavar="MODEL.toml", help="TOML model file.")],
    as_json: JsonOption = False,
) -> None:
    """Alias of validate."""
    validate(model_file, as_json=as_json)


@app.command()
def schema() -> None:
    """Print the JSON schema of the model file format.

    Examples:

        stepcontact schema > stepcontact.schema.json

    Point your editor at it (e.g. the "Even Better TOML" extension: a #:schema comment).
    """
    from stepcontact.io.modelfile import schema as file_schema

    typer.echo(json.dumps(file_schema(), indent=2))


__all__ = ["ProgressHook", "app", "events_table", "result_summary"]


# --------------------------------------------------------------------------------------------
# plot and info: figures and a summary of a result file
# --------------------------------------------------------------------------------------------
PLOT_KINDS = ("deformed", "stresses", "load-displacement", "timeline", "safety", "energy",
              "history")
#: the kinds that need a dynamic result (MODEL-dynamic.nc)
_DYNAMIC_KINDS = ("energy", "history")
_NEEDS_FIELDS = ("deformed", "load-displacement")


def _load_result_file(path: Path) -> StaticResult:
    """Load a result file; errors are one line naming the file."""
    from stepcontact.results.result import load_result

    if not path.is_file():
        raise _Failure(f"result file not found: {path}")
    try:
        return load_result(path)
    except (OSError, ValueError, KeyError, TypeError) as e:
        msg = _error_text(e)
        if not msg.startswith(("not a stepcontact", "inconsistent result file")):
            msg = f"not a stepcontact result file ({msg})"
        raise _Failure(f"{path}: {msg}") from None


ModelOption = Annotated[
    Path | None,
    typer.Option("--model", "-m", metavar="MODEL.toml",
                 help="Model file of the run: the states whose fields the result file does not "
                 "store are recomputed exactly from it (one factorisation). Default: the "
                 "model file the run recorded in the result file, if it is unchanged, else "
                 "RESULT.toml next to the result file, if there is one. It must be the run's "
                 "model: a stored field recomputed from it agrees to 1e-6, or (an "
                 "ill-conditioned model) satisfies its equilibrium to 1e-8."),
]


def _attach_model(res: StaticResult, result_file: Path, model_file: Path | None) -> Path | None:
    """Give a loaded result its model (:meth:`StaticResult.recover_fields`), so that the
    fields of every state can be recomputed; returns the model file used.

    ``model_file`` (``--model``) must load and match the result (else a failure); without
    it the model files of :func:`_default_model_files` are tried in turn (RESULT.toml beside
    it; for a dynamic result the model file it records, then MODEL.toml), each quietly not
    used if it does not load or match.  None: no model.
    """
    if model_file is None:
        for path in _default_model_files(result_file, res):
            try:
                res.recover_fields(_load(path))
            except (_Failure, ValueError, StepContactError):
                continue
            return path
        return None
    path = model_file
    try:
        model = _load(path)
        res.recover_fields(model)
    except _Failure:
        raise
    except (ValueError, StepContactError) as e:
        raise _Failure(f"--model {path}: {_error_text(e)}") from None
    return path


def _default_model_files(result_file: Path, res: StaticResult) -> list[Path]:
    """The model files a result file may come from, most likely first: the model file it
    records (``run`` stores its path and a SHA-256 hash of its content), RESULT.toml beside
    it and, for a dynamic result (MODEL-dynamic.nc, MODEL-dynamic-STAGE.nc), MODEL.toml
    beside it; each used only when its content has the recorded hash (files written before
    the hash was recorded: any) — for a static result, whose model is checked against its
    stored fields (:meth:`StaticResult.recover_fields`), RESULT.toml whatever its hash."""
    import hashlib
    import re

    from stepcontact.results.file import result_attrs

    out = [result_file.with_suffix(".toml")]
    try:
        attrs = result_attrs(result_file)
    except (OSError, ValueError):
        attrs = {}
    sha = attrs.get("model_sha256")
    recorded = Path(attrs["model_file"]) if attrs.get("model_file") else None
    if recorded is not None:
        out.insert(0, recorded)
    dynamic = getattr(res, "path_axis", "lam") == "time"
    if dynamic:
        stem = re.fullmatch(r"(.+)-dynamic(-[A-Za-z0-9_-]+)?", result_file.stem)
        if stem:
            out.append(result_file.with_name(stem.group(1) + ".toml"))
    kept: list[Path] = []
    for p in out:
        try:
            if not p.is_file() or any(p.samefile(q) for q in kept):
                continue
            hashed = dynamic or p == recorded
            if hashed and sha and hashlib.sha256(p.read_bytes()).hexdigest() != sha:
                continue
        except OSError:
            continue
        kept.append(p)
    return kept


def _parse_node(text: str | None) -> int | tuple[float, float] | None:
    """``--node``: ``X,Y`` (m) or a node index."""
    if text is None:
        return None
    parts = [p.strip() for p in text.split(",")]
    try:
        if len(parts) == 1:
            return int(parts[0])
        if len(parts) == 2:
            x, y = float(parts[0]), float(parts[1])
            if math.isfinite(x) and math.isfinite(y):
                return x, y
    except ValueError:
        pass
    raise _Failure(f"--node '{text}': give the coordinates X,Y in m (e.g. --node 3,2) or a "
                   "node index (e.g. --node 117)")


def _plot_targets(result_file: Path, kinds: Sequence[str], output: Path | None,
                  fmt: str) -> dict[str, Path]:
    """Figure file of each kind: ``-o`` itself (one kind, with a suffix) or
    ``DIR/RESULT-<kind>.<fmt>`` (``DIR``: ``-o`` or the result file's directory)."""
    if fmt not in ("png", "pdf", "svg"):
        raise _Failure(f"--format '{fmt}': use png, pdf or svg")
    is_dir = output is not None and (output.is_dir() or not output.suffix)
    if output is not None and not is_dir:
        if len(kinds) > 1:
            raise _Failure(f"-o {output}: --kind all writes one figure per kind, give a "
                           "directory")
        if output.suffix.lower() not in PLOT_SUFFIXES:
            raise _Failure(f"-o {output}: unsupported file type, use one of "
                           f"{', '.join(PLOT_SUFFIXES)} (or a directory)")
        return {kinds[0]: output}
    folder = output if output is not None else result_file.parent
    return {k: folder / f"{result_file.stem}-{k}.{fmt}" for k in kinds}


def _check_plot_options(kinds: Sequence[str], lam: Sequence[float] | None,
                        state: Sequence[int] | None, node: str | None,
                        reaction: str | None = None, stress: str | None = None,
                        node_set: str | None = None) -> None:
    if lam and "stresses" not in kinds:
        raise _Failure("--lam and --time apply to --kind stresses (use --state for the "
                       "deformed shape)")
    if node is not None and not {"load-displacement", "history"} & set(kinds):
        raise _Failure("--node applies to --kind load-displacement and history")
    if node_set is not None and "history" not in kinds:
        raise _Failure("--node-set applies to --kind history")
    if node_set is not None and node is not None:
        raise _Failure("give either --node or --node-set, not both")
    if reaction is not None and "load-displacement" not in kinds:
        raise _Failure("--reaction applies to --kind load-displacement")
    if stress is not None and "deformed" not in kinds:
        raise _Failure("--stress applies to --kind deformed")
    if reaction is not None and node is not None:
        raise _Failure("give either --node (a displacement) or --reaction (a support), not both")
    if state and len(state) > 1 and kinds == ["deformed"]:
        raise _Failure("--kind deformed draws one state: give a single --state")


def _draw_figure(res: StaticResult, kind: str, path: Path, opts: dict[str, Any]) -> None:
    """One figure of ``kind`` written to ``path``; plotting errors become one-line failures."""
    from stepcontact.post import plotting

    states = opts["state"] or None
    try:
        if kind == "deformed":
            plotting.plot_deformed(res, state=states[-1] if states else None,
                                   scale=opts["scale"], path=path, dpi=opts["dpi"],
                                   stress=opts.get("stress"))
        elif kind == "stresses":
            plotting.plot_interfaces(res, lams=opts["lam"] or None, segment=opts["segment"],
                                     states=states, path=path, dpi=opts["dpi"])
        elif kind == "load-displacement":
            plotting.plot_load_displacement(res, node=opts["node"], dof=opts["dof"],
                                            body=opts["body"], path=path, dpi=opts["dpi"],
                                            reaction=opts["reaction"])
        elif kind == "safety":
            plotting.plot_safety(res, path=path, dpi=opts["dpi"])
        elif kind == "energy":
            plotting.plot_energy(res, path=path, dpi=opts["dpi"])
        elif kind == "history":
            node = opts["node"]
            plotting.plot_time_history(
                res, path=path, dpi=opts["dpi"], body=opts["body"],
                point=node if isinstance(node, tuple) else None,
                nodes=opts.get("node_set") if node is None or isinstance(node, tuple) else node,
                direction=opts["dof"] or ("x", "y"))
        else:
            plotting.plot_event_timeline(res, path=path, dpi=opts["dpi"])
    except ValueError as e:
        raise _Failure(f"plot {kind}: {_error_text(e)}") from None


def _plot_missing_fields(res: StaticResult, kind: str, state: Sequence[int] | None,
                         reaction: str | None = None) -> bool:
    """True when a loaded result lacks the displacements ``kind`` needs (neither stored nor
    recoverable)."""
    if kind not in _NEEDS_FIELDS or res._recover is not None:
        return False
    if getattr(res, "u", None) is not None and len(res.u) == res.n_states:
        return False  # a dynamic result stores the displacements of every state
    if kind == "load-displacement" and reaction is not None:
        return False  # reactions are known at every state
    wanted = range(res.n_states) if kind == "load-displacement" else [
        (state[-1] if state else -1) % max(res.n_states, 1)]
    return any(i not in res.fields for i in wanted)


@app.command()
def plot(
    result_file: Annotated[
        Path, typer.Argument(metavar="RESULT.nc", help="Result file written by 'run'.")
    ],
    kind: Annotated[
        str,
        typer.Option("--kind", "-k", help="deformed, stresses, load-displacement, timeline, "
                     "safety (eccentricity, sliding factor and open length of the joints "
                     "along the path), energy (the energy ledger of a dynamic result), "
                     "history (displacements and velocities of a node of a dynamic result "
                     "against time) or all (one file per kind)."),
    ] = "stresses",
    lam: Annotated[
        list[float] | None,
        typer.Option("--lam", help="stresses: load factor λ to draw, of the last segment "
                     "reached or of --segment (repeat for several), e.g. --lam 1e4."),
    ] = None,
    segment: Annotated[
        int | None, typer.Option("--segment", help="stresses: the segment --lam refers to.")
    ] = None,
    at_time: Annotated[
        list[float] | None,
        typer.Option("--time", help="stresses of a dynamic result (MODEL-dynamic.nc): time t "
                     "in s to draw (repeat for several), e.g. --time 0.02 --time 0.05."),
    ] = None,
    state: Annotated[
        list[int] | None,
        typer.Option("--state", help="Reported state to draw (negative: from the end); "
                     "deformed: one state (default the last), stresses: repeat for several."),
    ] = None,
    node: Annotated[
        str | None,
        typer.Option("--node", help="load-displacement, history: node X,Y in m (the nearest "
                     "node) or its index, e.g. --node 3,2. Default: the node that moves "
                     "most."),
    ] = None,
    node_set: Annotated[
        str | None,
        typer.Option("--node-set", help="history: the nodes of this named node set of the "
                     "model (at most 12), e.g. --node-set crest."),
    ] = None,
    dof: Annotated[
        str | None,
        typer.Option("--dof", help="load-displacement: x, y or rz. Default: the direction "
                     "(x or y) that moves most over the path (y for --reaction). history: "
                     "x, y, rz (displacement and velocity) or one of ux, uy, vx, vy, ax, ay "
                     "(u displacement, v velocity, a acceleration); default x and y."),
    ] = None,
    body: Annotated[
        str | None,
        typer.Option("--body", help="load-displacement, history: body of --node when bodies "
                     "share the point."),
    ] = None,
    reaction: Annotated[
        str | None,
        typer.Option("--reaction", help="load-displacement: plot λ against the resultant "
                     "reaction of this support along --dof instead of a displacement."),
    ] = None,
    scale: Annotated[
        float | None,
        typer.Option("--scale", help="deformed: displacement magnification (default "
                     "automatic)."),
    ] = None,
    stress: Annotated[
        str | None,
        typer.Option("--stress", help="deformed: colour the cells by a stress component, "
                     "Pa: sxx, syy, sxy, szz or mises (von Mises)."),
    ] = None,
    output: Annotated[
        Path | None,
        typer.Option("--output", "-o", help="Figure file (.png, .pdf, .svg), or a directory. "
                     "Default: RESULT-<kind>.png next to the result file."),
    ] = None,
    fmt: Annotated[
        str, typer.Option("--format", help="File type when -o is a directory: png, pdf, svg.")
    ] = "png",
    dpi: Annotated[
        float, typer.Option("--dpi", min=1.0, help="Resolution of PNG figures, dots per inch.")
    ] = 150.0,
    model: ModelOption = None,
    quiet: Annotated[
        bool, typer.Option("--quiet", "-q", help="Print nothing but errors.")
    ] = False,
    as_json: JsonOption = False,
) -> None:
    """Draw figures of a result file.

    Examples:

        stepcontact plot run.nc                 # writes run-stresses.png

        stepcontact plot run.nc --kind stresses --lam 1e4 --lam 2e4 -o s.pdf

        stepcontact plot run.nc --kind deformed --state -1 --scale 500 -o d.svg

        stepcontact plot run.nc --kind deformed --stress mises

        stepcontact plot run.nc --kind load-displacement --node 3,2 --dof x

        stepcontact plot run.nc --kind load-displacement --reaction bed --dof x

        stepcontact plot run.nc --kind timeline --dpi 300

        stepcontact plot run.nc --kind safety

        stepcontact plot run-dynamic.nc --kind stresses --time 0.02 --time 0.05

        stepcontact plot run-dynamic.nc --kind energy

        stepcontact plot run-dynamic.nc --kind history --node 2,0 --body slab --dof uy

        stepcontact plot run-dynamic.nc --kind history --node-set crest

        stepcontact plot run.nc --kind all -o figures/ --format pdf

        stepcontact plot run.nc --kind load-displacement --model dam.toml

    The deformed shape and the load–displacement curve need displacement fields: those the
    result file does not store (by default it stores the start, the segment starts and ends
    and the last state) are recomputed exactly from the model file (--model; by default the
    model file the run recorded, if unchanged, or RESULT.toml beside the result file).
    """
    console = Console(highlight=False, soft_wrap=True)
    skipped: list[str] = []
    try:
        if kind != "all" and kind not in PLOT_KINDS:
            raise _Failure(f"unknown --kind '{kind}': use {', '.join(PLOT_KINDS)} or all")
        kinds = list(PLOT_KINDS) if kind == "all" else [kind]
        if at_time and lam:
            raise _Failure("give either --lam (a static result) or --time (a dynamic one)")
        _check_plot_options(kinds, lam or at_time, state, node, reaction, stress, node_set)
        opts = {"lam": lam, "segment": segment, "state": state, "node": _parse_node(node),
                "dof": dof, "body": body, "scale": scale, "dpi": dpi, "reaction": reaction,
                "stress": stress, "node_set": node_set}
        targets = _plot_targets(result_file, kinds, output, fmt)
        res = _load_result_file(result_file)
        dynamic = getattr(res, "path_axis", "lam") == "time"
        if at_time and not dynamic:
            raise _Failure("--time applies to a dynamic result (MODEL-dynamic.nc); this one "
                           "is static: use --lam")
        if lam and dynamic:
            raise _Failure("this result is in time: give --time t (s), not --lam")
        if at_time:
            opts["lam"] = at_time
        if kind in _DYNAMIC_KINDS and not dynamic:
            raise _Failure(f"--kind {kind} needs a dynamic result (MODEL-dynamic.nc)")
        if kind == "all" and not dynamic:
            for k in _DYNAMIC_KINDS:
                targets.pop(k, None)
        used_model = None
        if any(_plot_missing_fields(res, k, state, reaction) for k in kinds):
            used_model = _attach_model(res, result_file, model)
        written = []
        for k, path in targets.items():
            if kind == "all" and _plot_missing_fields(res, k, state, reaction):
                skipped.append(k)
                continue
            _draw_figure(res, k, path, opts)
            written.append(str(path))
    except _Failure as e:
        raise _fail(str(e), as_json) from None
    except OSError as e:
        raise _fail(_error_text(e), as_json) from None
    if as_json:
        typer.echo(json.dumps({"status": "ok", "written": written, "skipped": skipped,
                               "model_file": None if used_model is None else str(used_model)}))
        return
    if quiet:
        return
    if used_model is not None:
        console.print(Text(f"fields not stored in the result file recomputed from {used_model}"))
    if skipped:
        console.print(Text(f"skipped {', '.join(skipped)}: the displacements of every state are "
                           "not stored in the result file; give the model file of the run with "
                           "--model MODEL.toml to recompute them (or solve with "
                           "store_fields='all')", style="yellow"))
    console.print(Text("written: " + ", ".join(written), style="green"))


def result_info(res: StaticResult, path: Path | None = None,
                design: float | None = None, cohesion: float | None = None) -> dict[str, Any]:
    """What ``stepcontact info --json`` prints: :func:`result_summary` plus the model size,
    the segments with their λ ranges and multipliers, residuals and units, and the safety of
    every joint (at the design value ``design`` of the last segment's parameter, with the
    design ``cohesion`` in Pa if given)."""
    import numpy as np

    geo = res.geometry or {}
    iface = np.asarray(res.cfe.get("interface", np.zeros(0, int)), dtype=np.int64)
    dof_of = np.asarray(geo.get("dof_of", np.zeros((0, 3), int)))
    ndof = res.counters.get("ndof", int(dof_of.max()) + 1 if dof_of.size else None)
    model = {
        "nodes": len(geo["points"]) if "points" in geo else None,
        "dofs": _jsonable(ndof),
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
    return result_summary(
        res,
        **({} if path is None else {"file": str(path)}),
        model=model,
        segments=[{k: _jsonable(v) for k, v in r.items()} for r in res.segments_summary()],
        max_residual=_jsonable(float(np.max(res.residual, initial=0.0))),
        max_violation=_jsonable(float(np.max(res.violation, initial=0.0))),
        fields_stored=len(res.fields),
        field_states=sorted(int(k) for k in res.fields),
        reactions_last_state={lb: _jsonable(float(v)) for lb, v in
                              zip(res.reaction_labels, res.reactions[-1], strict=True)}
        if res.n_states and len(res.reaction_labels) else {},
        units=dict(res.units),
        interface_safety=_interface_safety(res, design, cohesion),
    )


def _interface_safety(res: StaticResult, design: float | None = None,
                      cohesion: float | None = None) -> list[dict[str, Any]]:
    """Safety of every interface at the last state (:meth:`StaticResult.interface_safety`;
    the heel at the end the loads push away from) and, with the design value ``design`` of
    the parameter, at the design state (``design_state``: the engineers' factors) with the
    load margins λ_limit / λ_d."""
    if not res.n_states:
        return []
    out = []
    for name in res.interface_names:
        try:
            s = res.interface_safety(name, design, cohesion=cohesion, heel="auto")
        except ValueError:  # an interface without CFEs
            continue
        row = {k: _jsonable(v) for k, v in s.at(-1).items()}
        row["cohesion_source"] = s.cohesion_source
        row["overturning_note"] = s.overturning_note
        if design is not None:
            row["design_state"] = {k: [_jsonable(x) for x in v] if isinstance(v, list)
                                   else _jsonable(v) for k, v in s.design_values().items()}
        out.append(row)
    return out


def _safety_tables(sf: dict[str, Any], opts: dict[str, Any]) -> list[Table]:
    """The tables of one joint's safety (:func:`_interface_safety`): at the last state, and
    at the design state with the load margins."""
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
    tables = [tab]
    d = sf.get("design_state")
    if not d:
        return tables
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


def _state_list(states: Sequence[int], limit: int = 8, count: bool = True) -> str:
    """``[0, 1, 2, 7]`` → ``"4 states: 0–2, 7"`` (``count=False``: ``"0–2, 7"``)."""
    runs: list[list[int]] = []
    for v in states:
        if runs and v == runs[-1][1] + 1:
            runs[-1][1] = v
        else:
            runs.append([v, v])
    text = ", ".join(f"{a}" if a == b else f"{a}–{b}" for a, b in runs[:limit])
    more = ", …" if len(runs) > limit else ""
    if not count:
        return text + more
    return f"{len(states)} state{'' if len(states) == 1 else 's'}: {text}{more}" if states \
        else "no state"


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


@app.command()
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
    summary = result_info(res, result_file, design, cohesion)
    if as_json:
        typer.echo(json.dumps(summary, indent=2, ensure_ascii=False))
        return
    console = Console(highlight=False, soft_wrap=True)
    console.rule(f"stepcontact result: {result_file}")
    console.print(Text(f"status: {summary['status']} — {summary['message']}"))
    for table in _info_tables(summary):
        console.print(table)


# --------------------------------------------------------------------------------------------
# export: ParaView files (VTU series with .pvd, XDMF)
# --------------------------------------------------------------------------------------------
def _export_files(vtu: Path | None, xdmf: Path | None, name: str) -> list[Path]:
    """Every file the export wrote (collection/XDMF files; frames live beside them)."""
    out: list[Path] = []
    if vtu is not None:
        out += [vtu / f"{name}.pvd", vtu / f"{name}_cfe.pvd"]
    if xdmf is not None:
        cfe = xdmf.with_name(f"{xdmf.stem}_cfe.xdmf")
        out += [xdmf, xdmf.with_suffix(".h5"), cfe, cfe.with_suffix(".h5")]
    return [p for p in out if p.is_file()]


@app.command()
def export(
    result_file: Annotated[
        Path, typer.Argument(metavar="RESULT.nc", help="Result file written by 'run'.")
    ],
    vtu: Annotated[
        Path | None,
        typer.Option("--vtu", metavar="DIR", help="Write a VTU time series into DIR: "
                     "NAME.pvd (bodies), NAME_cfe.pvd (contact elements), frames in DIR/NAME/."),
    ] = None,
    xdmf: Annotated[
        Path | None,
        typer.Option("--xdmf", metavar="FILE.xdmf", help="Write XDMF time series FILE.xdmf + "
                     "FILE.h5 (bodies) and FILE_cfe.xdmf + FILE_cfe.h5 (contact elements)."),
    ] = None,
    states: Annotated[
        str,
        typer.Option("--states", help="States to export: all, stored (with displacements), "
                     "events, ends (segment ends) or indices such as 0,5,-1. States without "
                     "stored displacements are recomputed from the model file, or skipped "
                     "with a note when there is none."),
    ] = "all",
    model: ModelOption = None,
    name: Annotated[
        str | None,
        typer.Option("--name", help="Base name of the VTU files. Default: the result file's "
                     "name without .nc."),
    ] = None,
    quiet: Annotated[
        bool, typer.Option("--quiet", "-q", help="Print nothing but errors.")
    ] = False,
    as_json: JsonOption = False,
) -> None:
    """Export a result file for ParaView: VTU series (.pvd) and/or XDMF (.xdmf + .h5).

    One frame per reported state; the time of a frame is the load-path parameter
    t = Σ|Δλ| (λ itself, segment and state index are field data). Displacements in m,
    stresses in Pa, CFE forces N and Q in N (N < 0 compression). See docs/paraview.md.

    Examples:

        stepcontact export run.nc --vtu run-vtu

        stepcontact export run.nc --vtu out --xdmf out/run.xdmf --states events

        stepcontact export run.nc --vtu out --model dam.toml

    A result file stores displacement fields and stresses at the start, the segment starts and
    ends and the last state (every state if solved with store_fields='all'); the other states
    are recomputed exactly from the model file of the run (--model; by default the model file
    the run recorded, if unchanged, or RESULT.toml beside the result file): one
    factorisation, then one multi-right-hand-side solve.
    """
    from stepcontact.io.export import export_vtu, export_xdmf, select_states

    console = Console(highlight=False, soft_wrap=True)
    try:
        if vtu is None and xdmf is None:
            raise _Failure("nothing to export: give --vtu DIR and/or --xdmf FILE.xdmf")
        if xdmf is not None and xdmf.suffix.lower() != ".xdmf":
            raise _Failure(f"--xdmf {xdmf}: the file name must end in .xdmf")
        base = name if name is not None else result_file.stem
        res = _load_result_file(result_file)
        try:
            kept, skipped = select_states(res, states)
        except ValueError as e:
            raise _Failure(f"--states: {_error_text(e)}") from None
        used_model = None
        if skipped.size:
            used_model = _attach_model(res, result_file, model)
            if used_model is not None:
                kept, skipped = select_states(res, states)
        dynamic = getattr(res, "path_axis", "lam") == "time"
        if kept.size == 0 and dynamic:
            raise _Failure(f"{result_file}: the stresses of a dynamic result are recovered "
                           "from its model file, which was not found unchanged (the one the "
                           "result records, or MODEL.toml beside it); give it with --model "
                           "MODEL.toml")
        if kept.size == 0:
            raise _Failure(f"{result_file}: none of the selected states has stored "
                           "displacements; give the model file of the run with --model "
                           "MODEL.toml to recompute them (or solve with store_fields='all')")
        try:
            if vtu is not None:
                export_vtu(res, vtu, states=kept, name=base)
            if xdmf is not None:
                export_xdmf(res, xdmf, states=kept)
        except ValueError as e:
            raise _Failure(_error_text(e)) from None
        written = [str(p) for p in _export_files(vtu, xdmf, base)]
    except _Failure as e:
        raise _fail(str(e), as_json) from None
    except OSError as e:
        raise _fail(_error_text(e), as_json) from None
    if as_json:
        typer.echo(json.dumps({
            "status": "ok", "result_file": str(result_file), "frames": int(kept.size),
            "states": kept.tolist(), "skipped": skipped.tolist(), "written": written,
            "model_file": None if used_model is None else str(used_model),
            "recomputed": [int(i) for i in kept if int(i) not in res.fields]
            if used_model is not None else [],
        }, indent=2, ensure_ascii=False))
        return
    if quiet:
        return
    if used_model is not None and dynamic:
        console.print(Text(f"stresses recovered from {used_model} (the displacements of "
                           "every state are in the result file)"))
    elif used_model is not None:
        n_rec = sum(int(i) not in res.fields for i in kept)
        console.print(Text(f"fields of {n_rec} state(s) not stored in the result file "
                           f"recomputed from {used_model}"))
    if skipped.size:
        which = _state_list(skipped.tolist(), count=False)
        console.print(Text(f"skipped {skipped.size} state(s) without stored displacements "
                           f"(states {which}); give the model file of the run with --model "
                           "MODEL.toml to recompute them exactly (or solve with "
                           "store_fields='all')", style="yellow"))
    console.print(Text(f"exported {kept.size} frame(s) of {res.n_states} states", style="green"))
    console.print(Text("written: " + ", ".join(written), style="green"))
