"""Load programs built from a few numbers: cyclic loading.

:func:`cycles` turns "n cycles of amplitude a about a mean" into the chain of
:class:`~stepcontact.model.items.Segment` s the solver runs, one segment per half-cycle.  The
segments are ordinary ones: they chain with those before and after them, may be mixed with any
other segment, and each half-cycle is traced exactly (every stick/slip/opening event located).

Example
-------
>>> import stepcontact as sc
>>> program = (sc.Segment("weight", 1.0), *sc.cycles("push", 2.0e4, 2))
>>> [(s.pattern, s.end) for s in program]
[('weight', 1.0), ('push', 20000.0), ('push', -20000.0), ('push', 20000.0), ('push', -20000.0)]
"""

from __future__ import annotations

import math
import operator
from collections.abc import Mapping, Sequence

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model.structure import Segment

#: the most cycles a cyclic program may have (two load segments each): a program beyond it
#: would take hours to days to run and gigabytes to hold (each segment has its own events and
#: states); split a longer history into runs, or give the cycles that matter
MAX_CYCLES = 10_000


def _number(value: object, item: str) -> float:
    """``value`` as a finite float, else a ModelError naming ``item``."""
    if isinstance(value, bool):
        raise ModelError(item, f"must be a number, got {value!r}")
    try:
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ModelError(item, f"must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ModelError(item, f"must be finite, got {x}")
    return x


def _per_cycle(amplitude: object) -> tuple[bool, object]:
    """(whether ``amplitude`` is one value per cycle, the value as a list or a scalar)."""
    if isinstance(amplitude, np.ndarray):
        amplitude = amplitude.tolist()  # a 0-d array gives a number
    return isinstance(amplitude, Sequence) and not isinstance(amplitude, str | bytes), amplitude


def cycle_amplitudes(amplitude: float | Sequence[float], n: int | None,
                     item: str = "cycles", count: str = "n") -> tuple[float, ...]:
    """The amplitude of every cycle, checked: ``amplitude`` is one number (then ``n`` ≥ 1
    cycles are required) or one number per cycle (then ``n`` is None or their count); all are
    finite, nonzero and of one sign.  Problems raise :class:`ModelError` naming
    ``{item}.amplitude`` (``{item}.amplitude[i]``) or ``{item}.{count}`` (the name of the
    number of cycles where it was given: ``n``, or ``cycles`` in a model file)."""
    per_cycle, amplitude = _per_cycle(amplitude)
    if per_cycle:
        amps = tuple(_number(a, f"{item}.amplitude[{i}]")
                     for i, a in enumerate(amplitude))  # type: ignore[arg-type]
        if not amps:
            raise ModelError(f"{item}.amplitude", "is empty: give one amplitude, or one per cycle")
    else:
        amps = (_number(amplitude, f"{item}.amplitude"),)
    if n is None:
        if not per_cycle:
            raise ModelError(f"{item}.{count}", "give the number of cycles (or one amplitude "
                             "per cycle)")
    else:
        if isinstance(n, bool):
            raise ModelError(f"{item}.{count}", f"must be a whole number of cycles, got {n!r}")
        try:
            number = operator.index(n)
        except TypeError:
            raise ModelError(f"{item}.{count}",
                             f"must be a whole number of cycles, got {n!r}") from None
        if number < 1:
            raise ModelError(f"{item}.{count}", f"must be ≥ 1, got {number}")
        if number > MAX_CYCLES:
            raise ModelError(f"{item}.{count}", f"is {number:,}: that many cycles are "
                             f"{2 * number:,} load segments, more than a run can hold; at most "
                             f"{MAX_CYCLES:,} cycles ({2 * MAX_CYCLES:,} segments)")
        if not per_cycle:
            amps = amps * number
        elif len(amps) != number:
            raise ModelError(f"{item}.{count}", f"is {number} but {len(amps)} amplitudes are "
                             "given (one per cycle)")
    for i, a in enumerate(amps):
        where = f"{item}.amplitude" + (f"[{i}]" if per_cycle else "")
        if a == 0.0:
            raise ModelError(where, "must be nonzero (a cycle of amplitude 0 does nothing)")
        if (a > 0) != (amps[0] > 0):
            raise ModelError(where, f"is {a:g} but the first cycle's is {amps[0]:g}: the "
                             "amplitudes must have one sign (its sign sets the direction of "
                             "the first half-cycle)")
    if len(amps) > MAX_CYCLES:
        raise ModelError(f"{item}.amplitude", f"gives {len(amps):,} cycles: at most "
                         f"{MAX_CYCLES:,} ({2 * MAX_CYCLES:,} load segments)")
    return amps


def cycles(
    pattern: str,
    amplitude: float | Sequence[float],
    n: int | None = None,
    *,
    mean: float = 0.0,
    start: float | None = None,
    rates: Mapping[str, float] | None = None,
) -> tuple[Segment, ...]:
    """A cyclic load program: ``n`` cycles of ``pattern``'s factor λ about ``mean``.

    Cycle i is two segments (half-cycles): λ goes to ``mean + a_i``, then to ``mean − a_i``.
    The first segment starts where the pattern stands (``start``, default: where the segments
    before leave it, 0 if none); the last ends at ``mean − a_n``.  Append
    ``Segment(pattern, mean)`` (or any other value) to come back.  A negative amplitude makes
    the first half-cycle go down.

    Parameters
    ----------
    pattern : str
        The load pattern whose factor cycles (with ``rates``: the segments' label, as in
        :class:`~stepcontact.model.items.Segment`).
    amplitude : float or sequence of float
        Half the swing of λ in the pattern's units per unit factor (N when the pattern is
        1 N per unit λ; m for a water-level pattern).  One value for all cycles, or one per
        cycle (e.g. increasing amplitudes); nonzero, finite, all of one sign.
    n : int, optional
        Number of cycles (≥ 1); required with one amplitude, else the number of amplitudes.
    mean : float
        The value of λ the cycles swing about (same units as ``amplitude``).
    start : float, optional
        The factor at the start of the first segment: checked to chain (as
        ``Segment.start``).
    rates : {pattern: rate}, optional
        Non-proportional cycles: every pattern's factor moves by ``rate`` per unit of the
        segments' parameter, which cycles as above (``pattern`` is then a label).

    Returns
    -------
    tuple of Segment
        ``2 n`` segments, to be put in a model's ``program`` (``model.add(*cycles(...))``).

    Raises
    ------
    ModelError
        Naming the bad argument: ``cycles('push').amplitude``, ``cycles('push').n``, ….

    Example
    -------
    >>> [s.end for s in cycles("push", [1.0, 2.0], mean=5.0)]
    [6.0, 4.0, 7.0, 3.0]
    """
    if not isinstance(pattern, str) or not pattern:
        raise ModelError("cycles.pattern", f"must be a non-empty pattern name, got {pattern!r}")
    item = f"cycles('{pattern}')"
    amps = cycle_amplitudes(amplitude, n, item)
    centre = _number(mean, f"{item}.mean")
    first = None if start is None else _number(start, f"{item}.start")
    if rates is not None and not isinstance(rates, Mapping):
        try:
            rates = dict(rates)
        except (TypeError, ValueError):
            raise ModelError(f"{item}.rates", "give {pattern: rate, …}") from None
    out: list[Segment] = []
    for a in amps:
        for end in (centre + a, centre - a):
            out.append(Segment(pattern, end, first if not out else None, rates))
    return tuple(out)


__all__ = ["MAX_CYCLES", "cycle_amplitudes", "cycles"]
