"""Errors of a model file: pydantic's locations as field paths (``bodies[1].material.E``),
one message per problem, and every problem of a file collected and raised as one
:class:`~stepcontact.errors.ModelError` (:class:`Problem`, :class:`_Problems`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any, Literal

from pydantic import ValidationError

from stepcontact.errors import ModelError
from stepcontact.io.modelfile.schema import _TAGS, ModelFile
from stepcontact.model import plausible

_MAX_LISTED = 8
_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _path(loc: tuple[str | int, ...] | list[str | int]) -> str:
    """pydantic location -> field path as written in the file, e.g. ``bodies[1].material.E``."""
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        elif part in _TAGS:
            continue
        else:
            key = part if _KEY.match(part) else f'"{part}"'
            out += f".{key}" if out else key
    return out or "model file"


def _message(err: dict[str, Any]) -> str:
    kind = err["type"]
    if kind == "missing":
        return "required field is missing"
    if kind == "extra_forbidden":
        return "unknown field (not part of the model file format)"
    if kind == "finite_number":
        msg = "must be a finite number (NaN and inf are not allowed)"
    elif kind in ("value_error", "assertion_error"):
        msg = str(err["msg"]).removeprefix("Value error, ").removeprefix("Assertion failed, ")
    else:
        msg = str(err["msg"])
        msg = msg[:1].lower() + msg[1:]
        msg = re.sub(r"^input should (be|have)", r"must \1", msg)
    value = err.get("input")
    if isinstance(value, str | int | float | bool) and repr(value) not in msg:
        msg += f" (got {value!r})"
    return msg


@dataclass(frozen=True)
class Problem:
    """One problem of a model file.

    ``item`` names the field (``bodies[1].material``), the physical group or the bodies
    concerned; ``severity`` is ``"error"`` (the model cannot be run) or ``"warning"``.
    """

    item: str
    message: str
    severity: Literal["error", "warning"] = "error"

    def __str__(self) -> str:
        return f"{self.item}: {self.message}"


class _Problems:
    """Collects (path, message) pairs and raises them as one :class:`ModelError`."""

    def __init__(self) -> None:
        self.items: list[tuple[str, str]] = []
        self.warnings: list[tuple[str, str]] = []
        #: the warning class of each warning (default: FutureWarning, a deprecation)
        self.category: dict[tuple[str, str], type[Warning]] = {}

    def add(self, path: str, problem: str) -> None:
        if (path, problem) not in self.items:
            self.items.append((path, problem))

    def warn(self, path: str, problem: str, category: type[Warning] = FutureWarning) -> None:
        self.warnings.append((path, problem))
        self.category[(path, problem)] = category

    def implausible(self, quantity: str, value: float, path: str) -> None:
        """A warning when ``value`` is outside the plausible range of ``quantity``
        (:data:`stepcontact.model.plausible.RANGES`)."""
        text = plausible.message(quantity, value, path)
        if text is not None:
            self.warn(path, text.removeprefix(f"{path} = ").strip(),
                      plausible.PlausibilityWarning)

    def raise_if_any(self) -> None:
        if self.items:
            raise _model_error(self.items)

    def problems(self) -> list[Problem]:
        return [Problem(p, m) for p, m in self.items] + [
            Problem(p, m, "warning") for p, m in self.warnings
        ]


def _model_error(items: list[tuple[str, str]]) -> ModelError:
    (path, problem), rest = items[0], items[1:]
    if rest:
        listed = "; ".join(f"{p}: {m}" for p, m in rest[:_MAX_LISTED])
        more = f"; and {len(rest) - _MAX_LISTED} more" if len(rest) > _MAX_LISTED else ""
        problem = f"{problem} (also {listed}{more})"
    err = ModelError(path, problem)
    err.errors = list(items)  # type: ignore[attr-defined]
    return err


def _validate(d: dict[str, Any]) -> ModelFile:
    try:
        spec = ModelFile.model_validate(d)
        items = []
    except ValidationError as e:
        items = [(_path(err["loc"]), _message(err)) for err in e.errors()]
    items += _program_problems(d)
    if items:
        raise _model_error(items) from None
    return spec


def _program_problems(d: Any) -> list[tuple[str, str]]:
    """A load program is given: top-level ``[[program]]`` segments, or ``[[stages]]`` each with
    its own (not both)."""
    if not isinstance(d, dict):
        return []
    program, stages = d.get("program"), d.get("stages")
    if isinstance(d.get("dam"), dict) and not program and not stages:
        return []  # the dam study writes its own programs (stepcontact.io.modelfile.dam)
    if stages:
        if program:
            return [("program", "is given together with [[stages]]: with stages the load "
                     "program is the stages' own; move these segments into the "
                     "[[stages.program]] of the first stage")]
        return []
    how = ("give the load program as [[program]] segments (or construction stages, "
           "[[stages]], each with its [[stages.program]])")
    if program is None:
        return [("program", f"required field is missing: {how}")]
    if isinstance(program, list) and not program:
        return [("program", f"is empty: {how}")]
    return []


def _known(names) -> str:
    names = list(names)
    return ", ".join(repr(n) for n in names) if names else "none defined"
