"""Time functions: how a load pattern varies in time in a dynamic analysis (method.md §4).

A time function g(t) multiplies its pattern's load vector: F(t) = Σ_P g_P(t) F_P.  All are
plain frozen dataclasses, callable on a float or an array of times (s):

* :class:`Tabulated` — values at given times, linear between them (a CSV record:
  :meth:`Tabulated.from_csv`), 0 before the first time and the last value after the last one
  (or 0 with ``hold=False``);
* :class:`Pulse` — rectangular, triangular (symmetric) or half-sine pulse of ``amplitude`` from
  ``start`` during ``duration``;
* :class:`Harmonic` — ``amplitude`` · sin(2π f (t − start) + phase) from ``start`` on;
* :class:`Constant` — the same value at every time (a load held through the analysis).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from stepcontact.errors import ModelError


def _finite(v, item: str, positive: bool = False) -> float:
    v = float(v)
    if not np.isfinite(v) or (positive and v <= 0):
        raise ModelError(item, f"must be {'positive and ' if positive else ''}finite, got {v}")
    return v


@dataclass(frozen=True)
class Constant:
    """g(t) = value."""

    value: float = 1.0

    def __call__(self, t):
        return np.full(np.shape(t), float(self.value)) if np.ndim(t) else float(self.value)

    def breaks(self) -> np.ndarray:
        return np.zeros(0)


@dataclass(frozen=True)
class Tabulated:
    """Values ``values`` at times ``times`` (s, increasing), linear between them."""

    times: tuple[float, ...]
    values: tuple[float, ...]
    hold: bool = True

    def __post_init__(self):
        t = np.asarray(self.times, dtype=float)
        v = np.asarray(self.values, dtype=float)
        if t.ndim != 1 or t.shape != v.shape or len(t) < 2:
            raise ModelError("tabulated time function", "give at least two (time, value) pairs "
                             "of the same length")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))):
            raise ModelError("tabulated time function", "times or values contain NaN or inf")
        if np.any(np.diff(t) <= 0):
            k = int(np.flatnonzero(np.diff(t) <= 0)[0])
            raise ModelError("tabulated time function", f"times must increase: entry {k + 1} "
                             f"({t[k + 1]} s) follows {t[k]} s")
        object.__setattr__(self, "times", tuple(t.tolist()))
        object.__setattr__(self, "values", tuple(v.tolist()))

    @classmethod
    def from_csv(cls, path, hold: bool = True) -> Tabulated:
        """Two columns (time in s, value), comma separated; lines starting with # and a header
        line that does not parse are skipped."""
        rows = []
        with open(path, encoding="utf-8") as fh:
            for i, line in enumerate(fh):
                line = line.strip()
                if not line or line.startswith("#"):
                    continue
                parts = line.replace(";", ",").split(",")
                try:
                    rows.append((float(parts[0]), float(parts[1])))
                except (ValueError, IndexError):
                    if rows:
                        raise ModelError(f"{path}", f"line {i + 1}: expected 'time, value', "
                                         f"got {line!r}") from None
        if not rows:
            raise ModelError(f"{path}", "no (time, value) rows")
        t, v = zip(*rows, strict=True)
        return cls(tuple(t), tuple(v), hold)

    def __call__(self, t):
        tt = np.asarray(t, dtype=float)
        right = self.values[-1] if self.hold else 0.0
        out = np.interp(tt, self.times, self.values, left=0.0, right=right)
        return out if np.ndim(t) else float(out)

    def breaks(self) -> np.ndarray:
        return np.asarray(self.times)


PULSE_SHAPES = ("rectangular", "triangular", "half_sine")


@dataclass(frozen=True)
class Pulse:
    """A pulse of ``amplitude`` from ``start`` (s) during ``duration`` (s): ``shape``
    rectangular, triangular (peak at mid-duration) or half_sine."""

    amplitude: float = 1.0
    start: float = 0.0
    duration: float = 1.0
    shape: str = "half_sine"

    def __post_init__(self):
        if self.shape not in PULSE_SHAPES:
            raise ModelError("pulse.shape", f"must be one of {', '.join(PULSE_SHAPES)}, got "
                             f"'{self.shape}'")
        _finite(self.amplitude, "pulse.amplitude")
        _finite(self.start, "pulse.start")
        _finite(self.duration, "pulse.duration", positive=True)

    def __call__(self, t):
        tt = np.asarray(t, dtype=float)
        x = (tt - self.start) / self.duration
        inside = (x >= 0) & (x < 1) if self.shape == "rectangular" else (x >= 0) & (x <= 1)
        if self.shape == "rectangular":
            g = np.ones_like(x)
        elif self.shape == "triangular":
            g = 1.0 - np.abs(2 * x - 1)
        else:
            g = np.sin(np.pi * np.clip(x, 0, 1))
        out = np.where(inside, self.amplitude * g, 0.0)
        return out if np.ndim(t) else float(out)

    def breaks(self) -> np.ndarray:
        pts = [self.start, self.start + self.duration]
        if self.shape == "triangular":
            pts.insert(1, self.start + self.duration / 2)
        return np.asarray(pts)


@dataclass(frozen=True)
class Harmonic:
    """``amplitude`` · sin(2π ``frequency`` (t − ``start``) + ``phase``) for t ≥ start, 0
    before (frequency in Hz, phase in rad)."""

    amplitude: float = 1.0
    frequency: float = 1.0
    phase: float = 0.0
    start: float = 0.0

    def __post_init__(self):
        _finite(self.amplitude, "harmonic.amplitude")
        _finite(self.frequency, "harmonic.frequency", positive=True)
        _finite(self.phase, "harmonic.phase")
        _finite(self.start, "harmonic.start")

    def __call__(self, t):
        tt = np.asarray(t, dtype=float)
        out = np.where(tt >= self.start, self.amplitude * np.sin(
            2 * np.pi * self.frequency * (tt - self.start) + self.phase), 0.0)
        return out if np.ndim(t) else float(out)

    def breaks(self) -> np.ndarray:
        return np.asarray([self.start])


__all__ = ["PULSE_SHAPES", "Constant", "Harmonic", "Pulse", "Tabulated"]
