"""The progress of a run on stderr: a rich bar fed by the solver's hooks, one unit per load
segment, then the dynamic interval in simulated time; the whole program of a model run with
it (:func:`stepcontact.run`)."""

from __future__ import annotations

import contextlib
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from rich.console import Console
from rich.markup import escape
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

from stepcontact.enums import SlipTreatment

if TYPE_CHECKING:
    from stepcontact.model import Model
    from stepcontact.results.file import ResultWriter
    from stepcontact.results.result import StaticResult
    from stepcontact.solver.program import ProgramResult


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
    after_static: Any = None, stop: Any = None, scheduler: str | None = None,
) -> ProgramResult:
    """Run the whole program of the model (:func:`stepcontact.run`) with a progress bar on
    stderr: one unit per load segment, then the final dynamic interval in simulated time.
    ``after_static(res)``: called when the static program ends (its bar gone), before the
    final interval; ``stop``: a :class:`~stepcontact.io.interrupt.StopRequest` that SIGTERM
    and Ctrl-C set during the final interval (polled before every step) instead of raising;
    ``scheduler``: a dask scheduler's address to form the condensed matrix G on."""
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
                           scheduler=scheduler, dynamic_hooks=dynamic_hooks,
                           after_static=static_done, before_dynamics=dynamics_start)
