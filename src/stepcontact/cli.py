"""Command line: ``stepcontact run MODEL.toml``, ``stepcontact demo``, ``stepcontact check``.

The CLI sits at the end of the data flow (model file -> model -> solver -> result -> files) and
only wires those pieces together; the progress bar is a solver hook.  Bad input never shows a
traceback: any :class:`~stepcontact.errors.StepContactError`, a missing file or a broken TOML
file prints one red line ``error: ...`` on stderr and exits with code 2.  A run that ends with
lost equilibrium is a result (exit code 0), not an error.

Example
-------
.. code-block:: console

    $ stepcontact run dam.toml -o dam.nc --plot dam.png --lam 1.5 --lam 2.0
    $ stepcontact run dam.toml --json --quiet     # machine-readable summary on stdout
    $ stepcontact demo -o demo-out
"""

from __future__ import annotations

import json
import math
import tomllib
from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer
from rich import box
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table
from rich.text import Text

from . import __version__
from .enums import SlipTreatment
from .errors import StepContactError

if TYPE_CHECKING:
    from .model import Model
    from .results import StaticResult

EXIT_ERROR = 2  #: exit code for bad input (model errors, missing files, solver errors)
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
    """Load a model file; errors name the file."""
    from .modelfile import load_model

    try:
        return load_model(path)
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

    def _describe(self, segment: int, lam: float, n_events: int) -> str:
        name = self.segments[segment][0] if 0 <= segment < len(self.segments) else "?"
        return f"segment {segment} '{name}'  λ = {lam:.4g}  events: {n_events}"

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

    def after_segment(self, result: Any) -> None:
        """A load segment is finished."""
        self.done += 1
        self.progress.update(self.task, completed=self.done)


def _solve(
    model: Model, *, slip: SlipTreatment, eps_p: float, max_events: int, progress_bar: bool
) -> StaticResult:
    """Run :func:`stepcontact.static.solve_static` with a progress bar on stderr."""
    from . import static

    segments = model.segments_resolved()
    with Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        TimeElapsedColumn(),
        console=Console(stderr=True),
        transient=True,
        disable=not progress_bar,
    ) as progress:
        task = progress.add_task(f"running '{model.name}'", total=max(len(segments), 1))
        hooks = (ProgressHook(progress, task, segments),) if progress_bar else ()
        return static.solve_static(
            model, slip=slip.value, eps_p=eps_p, max_events=max_events, hooks=hooks
        )


def events_table(res: StaticResult, max_rows: int = TABLE_ROWS) -> Table:
    """The event log as a rich table (forces in kN); the first and last events when long."""
    events = list(res.events)
    table = Table(title=f"events ({len(events)})", title_justify="left", box=box.SIMPLE_HEAD,
                  show_edge=False, pad_edge=False, collapse_padding=True)
    for name in ("step", "pattern", "λ", "interface", "s (m)", "CFE", "transition", "N (kN)",
                 "Q (kN)"):
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
            table.add_row("…", "", "", f"{len(events) - max_rows} more", "", "", "", "", "")
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
        )
    return table


def _plot(res: StaticResult, path: Path, lams: Sequence[float] | None) -> None:
    """Contact stresses along the interfaces, written to ``path`` (PNG, PDF or SVG)."""
    from . import plotting

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
    from .results import transition_counts

    return {
        "status": res.status.value,
        "message": res.message,
        "events": len(res.events),
        "states": int(res.n_states),
        "cfes": int(res.m),
        "transitions": transition_counts(res.events),
        "multipliers": [
            {k: _jsonable(v) for k, v in asdict(mu).items()} for mu in res.multipliers
        ],
        "counters": {k: _jsonable(v) for k, v in res.counters.items()},
        **extra,
    }


def _report(
    res: StaticResult,
    console: Console,
    *,
    title: str,
    table: bool,
) -> None:
    console.rule(title)
    if table and res.events:
        console.print(events_table(res))
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
) -> dict[str, Any]:
    """Solve, report, write the result file and the figure; return the JSON summary."""
    _check_plot_path(plot_path)
    res = _solve(model, slip=slip, eps_p=eps_p, max_events=max_events,
                 progress_bar=not quiet and not as_json)
    if not as_json:
        _report(res, console, title=f"stepcontact: {model.name}", table=not quiet)
    result_path.parent.mkdir(parents=True, exist_ok=True)
    res.save(result_path)
    written = [str(result_path)]
    if plot_path is not None:
        plot_path.parent.mkdir(parents=True, exist_ok=True)
        _plot(res, plot_path, lams)
        written.append(str(plot_path))
    if not as_json:
        console.print(Text("written: " + ", ".join(written), style="green"), soft_wrap=True)
    return result_summary(
        res,
        model=model.name,
        result_file=str(result_path),
        plot=None if plot_path is None else str(plot_path),
    )


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
QuietOption = Annotated[
    bool, typer.Option("--quiet", "-q", help="No progress bar and no event table.")
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
                     "Default: MODEL.png."),
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
) -> None:
    """Run the load program of a model file.

    Prints the events and the summary; writes the result file and a figure of the contact
    stresses.
    """
    console = Console(highlight=False)
    try:
        model = _load(model_file)
        summary = _analyse(
            model,
            result_path=output if output is not None else model_file.with_suffix(".nc"),
            plot_path=None if no_plot else (plot or model_file.with_suffix(".png")),
            lams=lam,
            slip=slip,
            eps_p=eps_p,
            max_events=max_events,
            quiet=quiet,
            as_json=as_json,
            console=console,
        )
    except _Failure as e:
        raise _fail(str(e), as_json) from None
    except (StepContactError, OSError, tomllib.TOMLDecodeError) as e:
        raise _fail(_error_text(e), as_json) from None
    if as_json:
        typer.echo(json.dumps(summary, indent=2))


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
    """
    from .demo import DEMO_FILES, demo_model, demo_text, demo_uplift_model

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


@app.command()
def check(
    model_file: Annotated[Path, typer.Argument(metavar="MODEL.toml", help="TOML model file.")],
) -> None:
    """Validate a model file and assemble it, without solving; print its size."""
    from .assembly import assemble

    console = Console(highlight=False, soft_wrap=True)
    try:
        model = _load(model_file)
        system = assemble(model)
        model.segments_resolved()
    except _Failure as e:
        raise _fail(str(e), False) from None
    except StepContactError as e:
        raise _fail(f"{model_file}: {_error_text(e)}", False) from None
    nodes = sum(b.n_nodes for b in model.bodies)
    console.print(
        Text(
            f"{model_file}: OK — model '{model.name}': {len(model.bodies)} bodies, {nodes} nodes, "
            f"{system.dofs.ndof} DOFs, {system.cfe.m} CFEs on {len(model.interfaces)} "
            f"interfaces, {len(model.patterns)} load patterns, {len(model.program)} segments"
        )
    )


@app.command()
def schema() -> None:
    """Print the JSON schema of the model file format."""
    from .modelfile import schema as file_schema

    typer.echo(json.dumps(file_schema(), indent=2))


__all__ = ["ProgressHook", "app", "events_table", "result_summary"]
