"""Exceptions raised for bad input and for numerical situations that are not results.

A physically meaningful outcome (loss of equilibrium, lift-off) is *not* an exception: it is
reported in the result with its load factor.  Exceptions are for input that cannot be analysed.
"""

from __future__ import annotations


class StepContactError(Exception):
    """Base class of all stepcontact errors."""


class ModelError(StepContactError, ValueError):
    """The model is wrong; the message names the offending item (body, node set, field...).

    Attributes
    ----------
    item : str
        Name of the offending item, e.g. ``"body 'block'"`` or ``"segments[2].start"``.
    """

    def __init__(self, item: str, problem: str):
        self.item = item
        self.problem = problem
        super().__init__(f"{item}: {problem}")


class SolverError(StepContactError, RuntimeError):
    """The solver cannot go on for a numerical reason (not a physical outcome)."""


class ContactHeldWarning(UserWarning):
    """A CFE component whose relative motion is held by supports on both sides: the supports
    carry that component and the CFE does not (its row of the contact operator is zero)."""


class ContactMeshWarning(UserWarning):
    """The meshes of an interface give a correct but less accurate contact pressure than they
    could; the message says what to change.  (Mortar CFEs no longer warn about the finer side:
    they sit on the coarser side whichever one is S+.)"""


def error_text(exc: BaseException) -> str:
    """A one-line description of an input error (a missing file names the file)."""
    if isinstance(exc, FileNotFoundError):
        text = f"file not found: {exc.filename}" if exc.filename else str(exc)
    elif isinstance(exc, OSError) and exc.filename:
        text = f"{exc.strerror or exc}: {exc.filename}"
    else:
        text = str(exc)
    return " ".join(text.split())
