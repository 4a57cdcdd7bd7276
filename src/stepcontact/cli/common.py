"""What every command shares: exit codes, the table and console conventions, one-line errors
(``error: ...`` on stderr, exit code 2) and warnings, loading a model file, the event table,
number formats, and the options several commands take."""

from __future__ import annotations

import json
import re
import tomllib
from collections.abc import Sequence
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer
from rich import box
from rich.console import Console
from rich.table import Table as _RichTable
from rich.text import Text

from stepcontact.enums import SlipTreatment
from stepcontact.errors import StepContactError
from stepcontact.errors import error_text as _error_text

if TYPE_CHECKING:
    from stepcontact.model import Model
    from stepcontact.results.result import StaticResult

EXIT_ERROR = 2  #: exit code for bad input (model errors, missing files, solver errors)
#: exit code of a run that stopped without a physical answer: the contact conditions could not
#: be met, no consistent scheme, cycling or the event budget (the result file is written)
EXIT_UNRESOLVED = 3
PLOT_SUFFIXES = (".png", ".pdf", ".svg")
TABLE_ROWS = 50  #: at most this many events are printed (the first ones and the last 10)
_TAIL_ROWS = 10



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


def _warn(texts: Sequence[str]) -> None:
    """Each warning as one yellow line ``warning: ...`` on stderr (also with --json, whose
    summary lists them under "warnings")."""
    err = Console(stderr=True, soft_wrap=True, highlight=False)
    for text in texts:
        err.print(Text(f"warning: {' '.join(text.split())}", style="yellow"))


def _kN(force: float) -> str:
    """A force in N shown in kN with 3 decimals (no "-0.000")."""
    return f"{round(force / 1e3, 3) + 0.0:.3f}"


def events_table(res: StaticResult, max_rows: int = TABLE_ROWS) -> Table:
    """The event log as a rich table (forces in kN; the impulses of impacts in kN·s where a
    dynamic run has any; the place of the CFE: its arc length s along the interface in 2D,
    its S+ point (x, y, z) in 3D); the first and last events when long."""
    events = list(res.events)
    in_space = getattr(res, "n_t", 1) > 1
    impulses = any(getattr(e, "impulse_n", 0.0) or getattr(e, "impulse_t", 0.0)
                   for e in events)
    table = Table(title=f"events ({len(events)})", title_justify="left", box=box.SIMPLE_HEAD,
                  show_edge=False, pad_edge=False, collapse_padding=True)
    for name in ("step", "pattern", "t (s)" if res.path_axis == "time" else "λ", "interface",
                 "x, y, z (m)" if in_space else "s (m)", "CFE", "transition", "N (kN)",
                 "Q (kN)",
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
            (f"({', '.join(f'{c:.4g}' for c in e.point)})" if in_space
             else f"{e.position:.4g}"),
            str(e.local),
            e.transition.value,
            _kN(e.N),
            _kN(e.Q) if e.n_t == 1 else f"({', '.join(_kN(q) for q in e.Q_t)})",
            *((f"{e.impulse_n / 1e3:.4g}", f"{e.impulse_t / 1e3:.4g}") if impulses else ()),
        )
    return table


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


def print_records(model: Model | None, console: Console) -> list[dict[str, Any]]:
    """Print the baseline figures of the earthquake records of ``model``'s dynamic intervals
    (PGA, Arias intensity, 5–95 % duration, sampling; one line each,
    :meth:`~stepcontact.model.records.RecordFigures.line`) and return them for the JSON
    summary (``ground_motion``); nothing without records."""
    from stepcontact.model.records import model_records

    figs = model_records(model) if model is not None else []
    for where, f in figs:
        console.print(Text(f"{where}: {f.line()}"), soft_wrap=True)
    if figs:
        console.print(Text("sign convention: a positive record value accelerates the ground "
                           "along +axis; displacements, velocities and accelerations are "
                           "relative to the ground"), soft_wrap=True)
    return [{"interval": where, **f.as_dict()} for where, f in figs]
