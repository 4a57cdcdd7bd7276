"""SIGTERM and SIGINT as an orderly interrupt: :mod:`stepcontact.interrupt` (a base module
under results and the solver, which defer signals while they write), under the name it has
always had here."""

from stepcontact.interrupt import (
    SIGNALS,
    StopRequest,
    Terminated,
    deferred,
    signals_interrupt,
    signals_stop,
)

__all__ = ["SIGNALS", "StopRequest", "Terminated", "deferred", "signals_interrupt",
           "signals_stop"]
