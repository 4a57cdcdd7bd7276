"""Times for the benchmarks that hold on a busy machine: wall, process CPU and main-thread CPU.

The machine the benchmarks run on is shared: wall time grows with the load, CPU time much less
(a process that waits for a core is not charged).  Every benchmark therefore measures three
clocks at once and computes its ratios from CPU time:

- ``wall``: ``time.perf_counter``;
- ``process``: ``time.process_time``, the CPU time of every thread of this process (BLAS,
  MKL PARDISO, OpenMP and OpenSees's threads included): the work done;
- ``thread``: ``time.thread_time``, the CPU time of the calling (main) thread only: the
  figure to compare single-threaded work with (the static event loop, a dynamic run, a
  solve held to one thread), which other threads' spinning does not inflate.

Use::

    with Timer() as t:
        work()
    print(t.times)                      # "1.23 s wall, CPU 2.10 s process, 1.20 s main thread"
    ratio = a.thread / b.thread         # say in the printout which CPU the ratio is from

or ``result, t = timed(fn, *args)``.  ``Times`` add, subtract and divide by a number (a mean
over repetitions), so per-event or per-step figures keep all three clocks.
"""

from __future__ import annotations

import os
import statistics
import time
from dataclasses import dataclass

#: the clocks, in the order they are printed
CLOCKS = ("wall", "process", "thread")


@dataclass(frozen=True)
class Times:
    """Wall time and CPU times (process, main thread) of one piece of work, s."""

    wall: float = 0.0
    process: float = 0.0
    thread: float = 0.0

    @classmethod
    def now(cls) -> Times:
        return cls(time.perf_counter(), time.process_time(), time.thread_time())

    def __add__(self, other: Times) -> Times:
        return Times(*(getattr(self, c) + getattr(other, c) for c in CLOCKS))

    def __sub__(self, other: Times) -> Times:
        return Times(*(getattr(self, c) - getattr(other, c) for c in CLOCKS))

    def __truediv__(self, n: float) -> Times:
        return Times(*(getattr(self, c) / n for c in CLOCKS))

    def __mul__(self, n: float) -> Times:
        return Times(*(getattr(self, c) * n for c in CLOCKS))

    __rmul__ = __mul__

    def as_dict(self) -> dict[str, float]:
        return {c: getattr(self, c) for c in CLOCKS}

    @classmethod
    def from_dict(cls, d: dict[str, float]) -> Times:
        """From :meth:`as_dict` (e.g. a child process's figures sent back as JSON)."""
        return cls(*(float(d[c]) for c in CLOCKS))

    def fmt(self, unit: str = "s", digits: int = 2) -> str:
        """``1.23 s wall, CPU 2.10 s process, 1.20 s main thread`` (unit ``s`` or ``ms``)."""
        k = 1e3 if unit == "ms" else 1.0
        return (f"{self.wall * k:.{digits}f} {unit} wall, CPU {self.process * k:.{digits}f} "
                f"{unit} process, {self.thread * k:.{digits}f} {unit} main thread")

    def __str__(self) -> str:
        return self.fmt()


class Timer:
    """Context manager measuring :class:`Times` of its block; ``times`` (and ``wall``,
    ``process``, ``thread``) after exit, or the time so far while inside.  Measure on the
    thread that does the work: ``thread`` is the CPU time of the thread that entered."""

    def __enter__(self) -> Timer:
        self._start = Times.now()
        self._times: Times | None = None
        return self

    def __exit__(self, *exc) -> None:
        self._times = Times.now() - self._start

    @property
    def times(self) -> Times:
        return self._times if self._times is not None else Times.now() - self._start

    @property
    def wall(self) -> float:
        return self.times.wall

    @property
    def process(self) -> float:
        return self.times.process

    @property
    def thread(self) -> float:
        return self.times.thread


class LoopStart:
    """Solver hook (``solve_static(..., hooks=[LoopStart()])``): the :class:`Times` at which
    the event loop starts (``before_run``: after the factorisation, G and the load solves), so
    that ``Times.now() - hook.start`` after the run is the time of the loop and of building the
    result.  It has no ``after_segment``: the solver builds no result per segment for it."""

    start: Times | None = None

    def before_run(self, segments) -> None:
        self.start = Times.now()


def children_cpu() -> float:
    """CPU time (user + system) of this process's child processes that have been waited for
    (and of theirs), s (``os.times``; clock ticks of 10 ms): the work of a process pool or a
    local cluster once it has been shut down."""
    t = os.times()
    return t.children_user + t.children_system


def median(times) -> Times:
    """The median of each clock over ``times`` (an iterable of :class:`Times`)."""
    times = list(times)
    return Times(*(statistics.median(getattr(t, c) for t in times) for c in CLOCKS))


def timed(fn, *args, **kwargs):
    """``(fn(*args, **kwargs), Times of the call)``."""
    with Timer() as t:
        out = fn(*args, **kwargs)
    return out, t.times


def repeat(fn, reps: int) -> Times:
    """Mean :class:`Times` of ``reps`` calls of ``fn()`` (timed together: one clock read per
    clock, so that short operations are not swamped by the clocks' own cost)."""
    with Timer() as t:
        for _ in range(reps):
            fn()
    return t.times / reps
