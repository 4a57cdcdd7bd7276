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

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal, get_args

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

    def support(self) -> tuple[float, float]:
        """(t₀, t₁): g = 0 outside [t₀, t₁] (s); (nan, nan) when g is zero everywhere."""
        return (-np.inf, np.inf) if self.value else (np.nan, np.nan)


@dataclass(frozen=True)
class Tabulated:
    """Values ``values`` at times ``times`` (s, increasing), linear between them."""

    times: tuple[float, ...]
    values: tuple[float, ...]
    hold: bool = True

    def __post_init__(self):
        t = np.array(self.times, dtype=float)  # (copies: kept read-only below)
        v = np.array(self.values, dtype=float)
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
        # the arrays np.interp reads at every call (a record of thousands of samples would be
        # converted from the tuples at every time step otherwise)
        t.flags.writeable = v.flags.writeable = False
        object.__setattr__(self, "_t", t)
        object.__setattr__(self, "_v", v)

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
        out = np.interp(tt, self._t, self._v, left=0.0, right=right)
        return out if np.ndim(t) else float(out)

    def breaks(self) -> np.ndarray:
        return np.asarray(self.times)

    def support(self) -> tuple[float, float]:
        """(t₀, t₁): g = 0 outside [t₀, t₁] (s); (nan, nan) when g is zero everywhere."""
        t, v = np.asarray(self.times), np.asarray(self.values)
        nz = np.flatnonzero(v != 0.0)
        if nz.size == 0:
            return (np.nan, np.nan)
        i, j = int(nz[0]), int(nz[-1])
        lo = t[max(i - 1, 0)]
        hi = np.inf if self.hold and j == len(v) - 1 else t[min(j + 1, len(t) - 1)]
        return (float(lo), float(hi))

    def period(self) -> float | None:
        """A table that returns to zero is a pulse: twice the length of its nonzero part, s
        (None when it holds a nonzero value)."""
        lo, hi = self.support()
        return 2.0 * (hi - lo) if np.isfinite(hi) and np.isfinite(lo) else None

    def describe(self) -> str:
        lo, hi = self.support()
        return f"a table pulse of {hi - lo:g} s (from {lo:g} s to {hi:g} s)"


PulseShape = Literal["rectangular", "triangular", "half_sine"]
PULSE_SHAPES: tuple[str, ...] = get_args(PulseShape)


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
        # inside by the break times themselves (not x, whose round-off could put the end
        # break t = start + duration inside a rectangular pulse: the step landing there would
        # see no jump)
        end = self.start + self.duration
        inside = ((tt >= self.start) & (tt < end) if self.shape == "rectangular"
                  else (tt >= self.start) & (tt <= end))
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

    def support(self) -> tuple[float, float]:
        """(t₀, t₁): g = 0 outside [t₀, t₁] (s); (nan, nan) when g is zero everywhere."""
        if not self.amplitude:
            return (np.nan, np.nan)
        return (float(self.start), float(self.start + self.duration))

    def period(self) -> float | None:
        """The period of the pulse's variation: 2 × duration, s (every shape: a rectangular
        pulse's edges off the step grid are cuts of whole steps, interpolated linearly like
        events, which moves the structure by up to |Δa| dt²/8 per edge — small only when the
        pulse spans several steps)."""
        return 2.0 * self.duration

    def describe(self) -> str:
        return f"a {self.shape.replace('_', '-')} pulse of {self.duration:g} s"


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

    def support(self) -> tuple[float, float]:
        """(t₀, t₁): g = 0 outside [t₀, t₁] (s); (nan, nan) when g is zero everywhere."""
        return (float(self.start), np.inf) if self.amplitude else (np.nan, np.nan)

    def period(self) -> float:
        """1 / f, s."""
        return 1.0 / self.frequency

    def describe(self) -> str:
        return f"a harmonic of {self.frequency:g} Hz"


#: time steps per period a curved load (a harmonic, a half-sine pulse) needs at least: Newmark
#: samples the load at the steps' ends and takes it linear between them
STEPS_PER_PERIOD = 10
#: default limit of the number of time steps of a dynamic interval (``max_steps``)
MAX_STEPS = 10_000_000
#: the mass matrices of a dynamic interval (consistent, or HRZ-lumped)
MassKind = Literal["consistent", "lumped"]
MASS_KINDS: tuple[str, ...] = get_args(MassKind)
#: HHT-α numerical damping: α ∈ [0, 1/3] keeps the scheme unconditionally stable and second-
#: order accurate (0: Newmark's average acceleration, no numerical dissipation)
HHT_ALPHA_RANGE: tuple[float, float] = (0, 1 / 3)
#: Newton's coefficient of restitution e of the impacts of rigid contacts
RESTITUTION_RANGE: tuple[float, float] = (0, 1)


def check_newmark(dt: float, duration: float, *, alpha: float = 0.0, restitution: float = 0.0,
                  prefix: str = "") -> None:
    """The parameters of a dynamic interval's time integration, before any work: ``dt`` and
    ``duration`` (s) positive and finite, the HHT-α ``alpha`` in :data:`HHT_ALPHA_RANGE`, the
    coefficient of restitution in :data:`RESTITUTION_RANGE`.  The one place of these rules:
    :class:`~stepcontact.model.DynamicInterval` and :func:`stepcontact.solve_dynamic` call it
    (ModelError whose item is the parameter, after ``prefix``, e.g. ``"dynamics."``), and the
    model file takes its bounds from the same constants."""
    for key, v in (("dt", dt), ("duration", duration)):
        v = float(v)
        if not np.isfinite(v) or v <= 0:
            raise ModelError(f"{prefix}{key}", f"must be positive and finite, got {v}")
    lo, hi = HHT_ALPHA_RANGE
    if not lo <= float(alpha) <= hi:
        raise ModelError(f"{prefix}alpha", f"HHT-α must lie in [{lo:g}, 1/3], got {alpha}")
    lo, hi = RESTITUTION_RANGE
    if not lo <= float(restitution) <= hi:
        raise ModelError(f"{prefix}restitution", f"must lie in [{lo:g}, {hi:g}], got "
                         f"{restitution}")


def check_interval(dt: float, duration: float, loads: Mapping[str, object], *,
                   max_steps: int = MAX_STEPS, prefix: str = "", ground=None) -> int:
    """Check, before any work, that a dynamic interval of ``duration`` in steps of ``dt`` (s)
    can follow its loads (pattern → time function; ``ground`` the time function of a ground
    acceleration, or {item: time function} of its components) and ends; returns the
    estimated number of steps.  ModelError (items named with ``prefix``, e.g.
    ``"dynamics."``) when

    * ``dt`` is longer than the interval (a single stretched step follows nothing);
    * the steps (duration / dt, plus one per break of a load inside the interval) exceed
      ``max_steps`` — a run that would not end in reasonable time (or memory);
    * a load acts only outside [0, duration] (or is zero everywhere): it would not load the
      structure;
    * a varying load (a harmonic, a half-sine or triangular pulse, a table that returns to
      zero) has fewer than :data:`STEPS_PER_PERIOD` steps per period (a pulse: 5 steps in
      its duration): sampled at the steps' ends only, it would be seen where it happens to
      be (a 1 MHz harmonic at dt = 1 ms: always at its zeros; a 1 ms half-sine at 50 ms: at
      its zero ends).  A rectangular pulse too: its edges off the step grid are cuts of whole
      steps (linear interpolation, as at events: no energy gained), exact in velocity but
      off by up to |Δa| dt²/8 in displacement per edge, which is small only when the pulse
      spans several steps (a 1 ms pulse at dt = 50 ms would be placed to within 25 ms).
    """
    dt, duration = float(dt), float(duration)
    if isinstance(max_steps, bool) or not isinstance(max_steps, int | np.integer) \
            or max_steps < 1:
        raise ModelError(f"{prefix}max_steps", f"must be a positive integer, got {max_steps!r}")
    if dt > duration:
        raise ModelError(f"{prefix}dt", f"{dt:g} s is longer than the interval "
                         f"({prefix}duration = {duration:g} s): give dt ≤ duration (a step "
                         "that long follows neither the loads nor the motion)")
    funcs = {f"{prefix}loads['{n}']": g for n, g in loads.items()}
    if isinstance(ground, Mapping):  # the components of a ground motion, by item
        funcs.update(ground)
    elif ground is not None:
        funcs["ground_acceleration"] = ground
    n_breaks = 0
    for g in funcs.values():
        if hasattr(g, "breaks"):
            b = np.asarray(g.breaks(), float)
            n_breaks += int(np.count_nonzero((b > 0) & (b < duration)))
    estimate = duration / dt + n_breaks
    if estimate > max_steps:
        raise ModelError(f"{prefix}dt", f"the interval of {duration:g} s in steps of {dt:g} s "
                         f"takes about {estimate:.3g} time steps, more than max_steps = "
                         f"{max_steps:g}: give a longer dt or a shorter duration, or raise "
                         "the limit (solve_dynamic(max_steps=...), or max_steps in the "
                         "dynamics table of a model file)")
    for item, g in funcs.items():
        if hasattr(g, "support"):
            lo, hi = g.support()
            if np.isnan(lo):
                raise ModelError(item, "is zero at every time: it would not load the "
                                 "structure")
            if hi <= 0.0 or lo >= duration:
                raise ModelError(item, f"acts only from {lo:g} s to {hi:g} s, outside the "
                                 f"interval [0, {duration:g}] s: it would not load the "
                                 "structure (times count from the start of the interval)")
        p = g.period() if hasattr(g, "period") else None
        if p is not None and p < STEPS_PER_PERIOD * dt * (1 - 1e-9):
            what = g.describe() if hasattr(g, "describe") else "a varying load"
            raise ModelError(item, f"{what} (period {p:g} s) is sampled by too few steps of "
                             f"dt = {dt:g} s: a varying load needs at least "
                             f"{STEPS_PER_PERIOD} steps per period, a pulse "
                             f"{STEPS_PER_PERIOD // 2} in its duration (dt ≤ "
                             f"{p / STEPS_PER_PERIOD:g} s); longer steps see it only at "
                             "their ends and miss its work")
    return int(np.ceil(estimate))


__all__ = ["HHT_ALPHA_RANGE", "MASS_KINDS", "MAX_STEPS", "PULSE_SHAPES", "RESTITUTION_RANGE",
           "STEPS_PER_PERIOD", "Constant", "Harmonic", "Pulse", "Tabulated", "check_interval",
           "check_newmark"]
