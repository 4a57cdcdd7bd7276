"""Timing of a run's phases as the drivers record them in ``counters``: wall time beside the
CPU time of the process (every thread: PARDISO's and BLAS's pools included) and of the
calling thread, so that figures measured on a shared, loaded machine stay comparable (a run
that waits for a core loses wall time, not CPU time)."""

from __future__ import annotations

import time
from dataclasses import dataclass


@dataclass(frozen=True)
class Stopwatch:
    """The three clocks at a moment: ``wall`` (time.perf_counter), ``cpu``
    (time.process_time) and ``thread`` (time.thread_time), s."""

    wall: float
    cpu: float
    thread: float

    @staticmethod
    def start() -> Stopwatch:
        return Stopwatch(time.perf_counter(), time.process_time(), time.thread_time())

    def counters(self, name: str, until: Stopwatch | None = None) -> dict[str, float]:
        """``{name}_seconds`` (wall), ``{name}_cpu_seconds`` (process) and
        ``{name}_thread_seconds`` from this moment to ``until`` (default now), s."""
        end = Stopwatch.start() if until is None else until
        return {f"{name}_seconds": end.wall - self.wall,
                f"{name}_cpu_seconds": end.cpu - self.cpu,
                f"{name}_thread_seconds": end.thread - self.thread}


__all__ = ["Stopwatch"]
