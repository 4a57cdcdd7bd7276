"""Plausible values: one table of ranges per physical quantity, with its unit.

A value outside its range is allowed (the model is still solved) but is almost surely a
mistake of units or of sign — a density of 2.4 kg/m³ given in g/cm³, a unit weight of water
of 9.81 N/m³ given in kN/m³, g = −9 810 m/s² given in mm/s² — so it is warned about, naming
the item, the value and its unit, with the likely intended value where a unit slip explains
it.  The ranges are wide: they hold every real structure, not only typical ones.  Values that
can only be mistakes are refused where they are checked (e.g. Young's modulus outside
:data:`~stepcontact.model.items.E_RANGE`); this module only warns.

The Python API warns with a :class:`PlausibilityWarning` (``warnings.warn``) when the item is
made; a model file lists the same warnings with the field path (``stepcontact validate``,
and ``stepcontact run`` prints them as ``warning: …`` lines).  The table is documented in
docs/model-file.md ("Plausible values").

Example
-------
>>> from stepcontact.model.plausible import message
>>> print(message("density", 2.4, "materials.concrete.density"))  # doctest: +ELLIPSIS
materials.concrete.density = 2.4 kg/m³ is far below any solid (...): did you mean 2400 kg/m³...
>>> message("density", 2400.0, "materials.concrete.density") is None
True
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass


class PlausibilityWarning(UserWarning):
    """A value outside what any real structure has (probably a unit or sign slip); the
    message names the item, the value and its unit."""


@dataclass(frozen=True)
class Range:
    """The plausible range ``lo`` … ``hi`` of one quantity in ``unit``, what it means to be
    below or above it, and the unit slip that explains such a value (the factor the value
    was probably to be multiplied by, and the unit it was given in)."""

    name: str
    unit: str
    lo: float
    hi: float
    below: str
    above: str
    slip_low: tuple[tuple[float, str], ...] = ()
    slip_high: tuple[tuple[float, str], ...] = ()
    text: str = ""  # the range as printed (default: lo … hi)
    #: where a suggested value must land (default: lo … hi)
    typical: tuple[float, float] | None = None

    def describe(self) -> str:
        return self.text or f"{self.lo:g} … {self.hi:g} {self.unit}"


#: the plausible range of each quantity (SI units); zero is always allowed where it means
#: "none" (a massless body, no friction, no damping)
RANGES: dict[str, Range] = {
    "density": Range(
        "mass density", "kg/m³", 100.0, 25_000.0, "is far below any solid",
        "is above the densest metal (osmium, 22 600 kg/m³)",
        slip_low=((1000.0, "the value in g/cm³ or t/m³"),), text="100 … 25 000 kg/m³"),
    "E": Range(
        "Young's modulus", "Pa", 1e5, math.inf,
        "is softer than any structural material or soil (rubber, soft clay: ~1e6 Pa)",
        "", slip_low=((1e9, "the value in GPa"), (1e6, "the value in MPa")), text="≥ 1e5 Pa",
        typical=(1e6, 1.2e12)),
    "friction": Range(
        "friction coefficient", "–", 0.0, 10.0, "",
        "is above any real friction coefficient (rock and concrete 0.5 … 1.5, rubber up to "
        "~3); a joint that must not slip needs a bond, not friction", text="0 … 10"),
    "gravity": Range(
        "acceleration |g|", "m/s²", 0.0, 100.0, "",
        "is more than 10 g", slip_high=((1e-3, "the value in mm/s²"),), text="≤ 100 m/s²"),
    "unit_weight_water": Range(
        "unit weight of water γ_w", "N/m³", 9_000.0, 15_000.0,
        "is far below that of water (9 810 N/m³; sea water 10 050, muddy water up to 14 000)",
        "is above that of any muddy water (≤ 14 000 N/m³)",
        slip_low=((1000.0, "the value in kN/m³"),), text="9 000 … 15 000 N/m³"),
    "head": Range(
        "pressure head", "m of water", 0.0, 2_000.0,
        "is negative: a joint holds no suction (a head is measured above the point, the "
        "pressure is γ_w · head ≥ 0)", "is above any reservoir (the highest dams hold ~300 m)",
        text="0 … 2 000 m"),
    "water_pressure": Range(
        "water pressure", "Pa", 0.0, 2e7,
        "is negative: a joint holds no suction", "is above 2 000 m of water",
        text="0 … 2e7 Pa"),
    "damping_ratio": Range(
        "damping ratio ζ", "–", 0.0, 1.0, "",
        "is above critical damping (ζ = 1; structures have 0.01 … 0.2)",
        slip_high=((0.01, "the value in per cent"),), text="0 … 1"),
}


def _fmt(v: float) -> str:
    return f"{v:.6g}"


def message(quantity: str, value: float, item: str) -> str | None:
    """The warning for ``value`` of ``quantity`` (a key of :data:`RANGES`) at ``item``, or
    None when it is plausible.  Zero, NaN and infinities are left to the checks of the item
    (zero means "none"; the others are errors there)."""
    r = RANGES[quantity]
    v = float(value)
    if not math.isfinite(v) or v == 0.0:
        return None
    if r.lo <= v <= r.hi:
        return None
    low = v < r.lo
    what = r.below if low else r.above
    unit = "" if r.unit == "–" else f" {r.unit}"
    text = f"{item} = {_fmt(v)}{unit} {what} (plausible {r.name}: {r.describe()})"
    lo, hi = r.typical or (r.lo, r.hi)
    for factor, given in (r.slip_low if low else r.slip_high) if v > 0 else ():
        meant = v * factor
        if lo <= meant <= hi:
            return f"{text}: did you mean {_fmt(meant)}{unit} ({given})?"
    return text + (": check the value" if r.unit == "–" else ": check the value and its unit")


def warn(quantity: str, value: float, item: str, stacklevel: int = 3) -> None:
    """Warn (:class:`PlausibilityWarning`) when ``value`` is outside the range of
    ``quantity``."""
    text = message(quantity, value, item)
    if text is not None:
        warnings.warn(PlausibilityWarning(text), stacklevel=stacklevel)


__all__ = ["RANGES", "PlausibilityWarning", "Range", "message", "warn"]
