"""SIGTERM and SIGINT as an orderly interrupt: the run writes what it has finished, then ends.

:func:`signals_interrupt` turns SIGTERM (``kill``, a batch system's time limit) and SIGINT
(Ctrl-C) into a :class:`Terminated` exception — a :class:`KeyboardInterrupt`, so that the
solver's interrupt path (write the states finished, status ``incomplete``) runs for both.  A
signal that arrives while a file is being written (:func:`deferred`) waits until the write is
done, so that it never ends a write half-way.

Example
-------
>>> with signals_interrupt():                                  # doctest: +SKIP
...     res = sc.solve_static(model, output="run.nc")
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager

#: signals turned into :class:`Terminated`
SIGNALS = (signal.SIGTERM, signal.SIGINT)

_state = threading.local()
_pending: list[int] = []


class Terminated(KeyboardInterrupt):
    """The process received SIGTERM or SIGINT (``signum``)."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = int(signum)

    @property
    def name(self) -> str:
        """The signal's name, e.g. ``SIGTERM``."""
        return signal.Signals(self.signum).name

    @property
    def exit_code(self) -> int:
        """The exit status of a process ended by the signal: 128 + its number."""
        return 128 + self.signum


def _depth() -> int:
    return getattr(_state, "depth", 0)


def _handler(signum: int, frame) -> None:  # noqa: ARG001 - the signal module's signature
    if _depth() > 0:
        _pending.append(signum)  # raised when the write ends
        return
    raise Terminated(signum)


@contextmanager
def deferred() -> Iterator[None]:
    """A block (a file write) that a SIGTERM or SIGINT under :func:`signals_interrupt` does
    not interrupt: the signal is raised as :class:`Terminated` when the block ends."""
    _state.depth = _depth() + 1
    try:
        yield
    finally:
        _state.depth = _depth() - 1
    if _depth() == 0 and _pending:
        signum = _pending[0]
        _pending.clear()
        raise Terminated(signum)


@contextmanager
def signals_interrupt(signals: tuple[int, ...] = SIGNALS) -> Iterator[None]:
    """Raise :class:`Terminated` on ``signals`` while the block runs (main thread only;
    elsewhere the block runs unchanged); the previous handlers are restored after it."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = {s: signal.signal(s, _handler) for s in signals}
    _pending.clear()
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, h)


class StopRequest:
    """A solver hook that asks a time integration to stop at the end of its current step:
    :func:`signals_stop` sets ``stop_requested`` (and ``signum``) on SIGTERM or SIGINT, and
    :func:`~stepcontact.solve_dynamic` polls it before every step, ending with status
    ``incomplete`` and every state up to there (which the caller then writes)."""

    def __init__(self) -> None:
        self.stop_requested = False
        self.signum: int | None = None


@contextmanager
def signals_stop(request: StopRequest, signals: tuple[int, ...] = SIGNALS) -> Iterator[None]:
    """While the block runs, SIGTERM and SIGINT only set ``request.stop_requested`` (main
    thread only; elsewhere the block runs unchanged): the solver finishes its step and
    returns what it has, instead of losing it to an exception; the previous handlers are
    restored after it."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def _ask(signum: int, frame) -> None:  # noqa: ARG001 - the signal module's signature
        request.stop_requested, request.signum = True, int(signum)

    old = {s: signal.signal(s, _ask) for s in signals}
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, h)


__all__ = ["SIGNALS", "StopRequest", "Terminated", "deferred", "signals_interrupt",
           "signals_stop"]
