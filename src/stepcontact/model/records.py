r"""Earthquake ground motions read from files: acceleration records and the components that
act together (issue 29 §1).

A record is one component of a ground acceleration a_g(t), read from

* a PEER NGA ``.AT2`` file (:func:`read_at2`): four header lines, the fourth with the number
  of points and the time step in either of its usual forms, ``NPTS=  5590, DT= .0050 SEC``
  or the older ``5590 .0050 NPTS, DT``; then the values, in g, several per line;
* a two-column text file (:func:`read_two_column`): time (s) and acceleration on each line,
  separated by commas, semicolons or blanks; lines starting with ``#`` and a header line
  before the first numbers are skipped;
* a one-column text file (:func:`read_one_column`) with its time step given: one value per
  sample (several per line are read in order).

The samples are at t_i = i Δt from t = 0 (AT2 and one-column files) or at the file's times;
the ground acceleration between them is linear (the record is a
:class:`~stepcontact.model.timefunction.Tabulated` time function, zero after its end), so the
dynamic driver, whose steps land on every sample (the table's breaks), follows it exactly as
given.  Values are converted to m/s² (``units`` g, m/s² or cm/s² = gal; g is the standard
gravity :data:`G_RECORD` = 9.806 65 m/s², CGPM 1901), scaled by a factor or to a target PGA,
and their sign flipped with ``polarity = -1``.

**Sign convention.**  A positive value accelerates the ground along +x (+y, +z: the record's
``axis``).  The dynamic driver applies it as the effective load −M r a_g(t) (r the rigid
translation along the axis; :func:`stepcontact.solve_dynamic`), so the displacements,
velocities and accelerations it reports are relative to the ground: a rigid block on a
frictionless base under a constant a_g > 0 along x moves relatively by −a_g t²/2.

**Baseline figures** (:meth:`AccelerationRecord.figures`, :class:`RecordFigures`): the peak
ground acceleration PGA = max |a_i| and its time; the record's length and sampling; the Arias
intensity (Arias 1970, "A measure of earthquake intensity", in Seismic Design for Nuclear
Power Plants, MIT Press, eq. for the horizontal component)

.. math::  I_a = \frac{\pi}{2 g} \int_0^{T} a_g^2(t)\,dt  \quad (m/s),

integrated exactly for the piecewise-linear record (Σ Δt_i (a_i² + a_i a_{i+1} + a_{i+1}²)/3);
and the significant duration D_5–95 = t_95 − t_5 between the times at which the cumulative
integral reaches 5 % and 95 % of I_a (Trifunac & Brady 1975, "A study on the duration of
strong earthquake ground motion", BSSA 65(3), 581–626; the cumulative integral linear between
samples).

:class:`GroundMotion` holds the components that act together (a horizontal record along x and
a vertical one along y in 2D; x, y and z in 3D).  Either it or a single record is given to
:func:`stepcontact.solve_dynamic` as ``ground_acceleration`` (or to a model's dynamic interval,
:class:`~stepcontact.model.DynamicInterval` ``ground``): its :meth:`~GroundMotion.components`
are the (time function, axis) pairs the driver applies.

Example
-------
>>> import numpy as np, stepcontact as sc
>>> t = np.linspace(0.0, 2.0, 2001)                        # two cycles of 1 s, dt = 1 ms
>>> rec = sc.AccelerationRecord(t, 2.0 * np.sin(2 * np.pi * t), axis="x", name="sine")
>>> f = rec.figures()
>>> round(f.pga, 6), round(f.arias, 4)       # PGA 2 m/s²; I_a = π a₀² (2T)/(4g) = 0.6407 m/s
(2.0, 0.6407)
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal, get_args

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model.timefunction import Tabulated

#: standard gravity, m/s² (3rd CGPM, 1901): the g of records in g and of the Arias intensity
G_RECORD = 9.80665
#: the record file formats
RecordFormat = Literal["at2", "two_column", "one_column"]
RECORD_FORMATS: tuple[str, ...] = get_args(RecordFormat)
#: the units of a record's values and their factor to m/s²
RecordUnits = Literal["g", "m/s2", "cm/s2", "gal"]
RECORD_UNITS: dict[str, float] = dict(zip(get_args(RecordUnits), (G_RECORD, 1.0, 0.01, 0.01),
                                          strict=True))
#: the axes a component acts along (y is vertical in 2D, z in 3D)
AXES: tuple[str, ...] = ("x", "y", "z")
#: the largest deviation of a two-column file's time steps from their median, relative: a
#: record whose steps differ more is not uniformly sampled
DT_TOLERANCE = 0.01

_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][-+]?\d+)?")


def _float(token: str) -> float:
    """A number of a record file (Fortran's D exponent read as E)."""
    return float(token.replace("D", "E").replace("d", "e"))


def _lines(path: Path) -> list[str]:
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            return fh.read().splitlines()
    except OSError as e:  # the file's name and the system's reason, one line
        raise ModelError(str(path), f"cannot be read: {e.strerror or e}") from None


def _values(path: Path, lines: Sequence[str], first: int) -> tuple[np.ndarray, np.ndarray]:
    """The numbers of ``lines[first:]``, in order, and the (1-based) line of each; blank lines
    and ``#`` comments skipped; a token that is not a number names its line."""
    vals: list[float] = []
    where: list[int] = []
    for i in range(first, len(lines)):
        text = lines[i].split("#", 1)[0].replace(",", " ").replace(";", " ")
        for tok in text.split():
            try:
                x = _float(tok)
            except ValueError:
                raise ModelError(f"{path}", f"line {i + 1}: '{tok}' is not a number") from None
            if not math.isfinite(x):
                raise ModelError(f"{path}", f"line {i + 1}: '{tok}' is not a finite number")
            vals.append(x)
            where.append(i + 1)
    return np.asarray(vals, float), np.asarray(where, np.int64)


def _check_dt(path: Path, dt: float, what: str) -> float:
    try:
        dt = float(dt)
    except (TypeError, ValueError):
        raise ModelError(f"{path}", f"{what}: the time step must be a number, got "
                         f"{dt!r}") from None
    if not (math.isfinite(dt) and dt > 0):
        raise ModelError(f"{path}", f"{what}: the time step must be positive, got {dt:g} s")
    return dt


def read_at2(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """A PEER NGA ``.AT2`` file: (times (s), accelerations in g).

    Four header lines (title; event and station; ``ACCELERATION TIME SERIES IN UNITS OF G``;
    the number of points and the time step, ``NPTS=  5590, DT= .0050 SEC`` or
    ``5590 .0050 NPTS, DT``), then NPTS values, several per line; t_i = i Δt.  ModelError
    naming the file and the line: a header without NPTS and DT, a velocity or displacement
    file (.VT2, .DT2), a value that is not a number, a count of values other than NPTS."""
    path = Path(path)
    lines = _lines(path)
    if len(lines) < 4:
        raise ModelError(f"{path}", f"has {len(lines)} lines: a PEER .AT2 file has 4 header "
                         "lines (the 4th with NPTS and DT) and then the values")
    kind = lines[2].upper()
    if "VELOCITY" in kind or "DISPLACEMENT" in kind:
        raise ModelError(f"{path}", f"line 3: '{lines[2].strip()}': not an acceleration "
                         "record (a .VT2 or .DT2 file?)")
    head = lines[3]
    up = head.upper()
    m_n = re.search(r"NPTS\s*=\s*(\d+)", up)
    m_dt = re.search(r"DT\s*=\s*(" + _NUMBER.pattern + ")", up)
    if m_n and m_dt:
        npts, dt = int(m_n.group(1)), _float(m_dt.group(1))
    else:
        nums = _NUMBER.findall(up)
        if "NPTS" not in up or len(nums) < 2:
            raise ModelError(f"{path}", f"line 4: '{head.strip()}': expected the number of "
                             "points and the time step ('NPTS= 5590, DT= .0050 SEC' or "
                             "'5590 .0050 NPTS, DT')")
        try:
            npts = int(nums[0])
        except ValueError:
            raise ModelError(f"{path}", f"line 4: NPTS must be a whole number, got "
                             f"'{nums[0]}'") from None
        dt = _float(nums[1])
    dt = _check_dt(path, dt, "line 4")
    vals, where = _values(path, lines, 4)
    if npts < 2:
        raise ModelError(f"{path}", f"line 4: NPTS = {npts}: a record needs at least 2 points")
    if len(vals) != npts:
        last = int(where[-1]) if len(where) else 4
        raise ModelError(f"{path}", f"line {last}: the file has {len(vals)} values but line 4 "
                         f"says NPTS = {npts}")
    return np.arange(npts) * dt, vals


def read_two_column(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """A two-column text file: (times (s), values), one sample per line, the columns separated
    by commas, semicolons or blanks; ``#`` comments and header lines before the first numbers
    skipped.  ModelError naming the file and the line: a line without two numbers, times
    that do not increase, time steps that differ by more than :data:`DT_TOLERANCE` of their
    median (not uniformly sampled), fewer than two samples."""
    path = Path(path)
    rows: list[tuple[float, float]] = []
    where: list[int] = []
    for i, line in enumerate(_lines(path)):
        text = line.split("#", 1)[0].replace(",", " ").replace(";", " ").split()
        if not text:
            continue
        try:
            pair = [_float(tok) for tok in text]
        except ValueError:
            if not rows:  # a header line before the numbers
                continue
            raise ModelError(f"{path}", f"line {i + 1}: expected 'time, value', got "
                             f"'{line.strip()}'") from None
        if len(pair) != 2 or not all(math.isfinite(x) for x in pair):
            raise ModelError(f"{path}", f"line {i + 1}: expected two finite numbers "
                             f"(time, value), got '{line.strip()}'")
        rows.append((pair[0], pair[1]))
        where.append(i + 1)
    if len(rows) < 2:
        raise ModelError(f"{path}", "has no (time, value) rows" if not rows else
                         "has one (time, value) row: a record needs at least 2")
    t, v = (np.asarray(c, float) for c in zip(*rows, strict=True))
    d = np.diff(t)
    if np.any(d <= 0):
        k = int(np.flatnonzero(d <= 0)[0])
        raise ModelError(f"{path}", f"line {where[k + 1]}: time {t[k + 1]:g} s does not "
                         f"follow {t[k]:g} s (line {where[k]}): times must increase")
    med = float(np.median(d))
    dev = np.abs(d - med) > DT_TOLERANCE * med
    if np.any(dev):
        k = int(np.flatnonzero(dev)[0])
        raise ModelError(f"{path}", f"line {where[k + 1]}: the step {d[k]:g} s from "
                         f"{t[k]:g} s differs from the record's {med:g} s: the times must be "
                         "uniformly spaced (resample the record)")
    return t, v


def read_one_column(path: str | Path, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """A one-column text file with its time step ``dt`` (s): (times, values), t_i = i Δt;
    several values per line are read in order, ``#`` comments skipped.  ModelError naming
    the file and the line for a value that is not a number; fewer than two values."""
    path = Path(path)
    dt = _check_dt(path, dt, "dt")
    vals, _ = _values(path, _lines(path), 0)
    if len(vals) < 2:
        raise ModelError(f"{path}", f"has {len(vals)} values: a record needs at least 2")
    return np.arange(len(vals)) * dt, vals


def _format_of(path: Path, fmt: str | None) -> str:
    if fmt is None:
        if path.suffix.lower() == ".at2":
            return "at2"
        raise ModelError("format", f"give the format of '{path.name}' "
                         f"({', '.join(RECORD_FORMATS)}): only a .AT2 file is recognised by its "
                         "name")
    if fmt not in RECORD_FORMATS:
        raise ModelError("format", f"must be one of {', '.join(RECORD_FORMATS)}, got '{fmt}'")
    return fmt


def _units_factor(units: str) -> float:
    key = str(units).replace("²", "2").replace("^2", "2").replace(" ", "").lower()
    if key not in RECORD_UNITS:
        raise ModelError("units", f"must be one of {', '.join(RECORD_UNITS)}, got '{units}'")
    return RECORD_UNITS[key]


@dataclass(frozen=True)
class RecordFigures:
    """The baseline figures of a record (:meth:`AccelerationRecord.figures`), SI units.

    ``pga`` peak |a| (m/s²), ``pga_g`` the same in g, ``t_pga`` its time (s); ``duration``
    the record's length (s); ``arias`` the Arias intensity I_a = π/(2g) ∫ a² dt (m/s);
    ``t5``, ``t95`` the times where the cumulative ∫ a² dt reaches 5 % and 95 % of its total
    and ``d5_95`` = t95 − t5 the significant duration (s, Trifunac & Brady 1975); ``dt`` the
    time step (s, the median of the file's) and ``npts`` the number of samples."""

    name: str
    axis: str
    pga: float
    pga_g: float
    t_pga: float
    duration: float
    arias: float
    t5: float
    t95: float
    d5_95: float
    dt: float
    npts: int
    factor: float

    def line(self) -> str:
        """One line for a terminal: what an engineer checks before a run."""
        scale = "" if self.factor == 1.0 else f", × {self.factor:.6g}"
        return (f"ground motion {self.axis} '{self.name}'{scale}: PGA {self.pga:.4g} m/s² "
                f"({self.pga_g:.4g} g) at {self.t_pga:.4g} s; Arias intensity "
                f"{self.arias:.4g} m/s; 5–95 % duration {self.d5_95:.4g} s "
                f"({self.t5:.4g}–{self.t95:.4g} s); {self.npts} points at dt = {self.dt:g} s "
                f"({self.duration:g} s)")

    def as_dict(self) -> dict[str, object]:
        """The figures as a JSON-ready dict (SI units)."""
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


def arias_cumulative(times: np.ndarray, values: np.ndarray) -> np.ndarray:
    """∫₀^{t_i} a² dt at every sample (m²/s³) of the piecewise-linear record: exact,
    Σ Δt (a_i² + a_i a_{i+1} + a_{i+1}²)/3."""
    t, a = np.asarray(times, float), np.asarray(values, float)
    seg = np.diff(t) * (a[:-1] ** 2 + a[:-1] * a[1:] + a[1:] ** 2) / 3.0
    return np.concatenate(([0.0], np.cumsum(seg)))


def _crossing(t: np.ndarray, cum: np.ndarray, level: float) -> float:
    """The first time the cumulative ``cum`` (non-decreasing, at ``t``) reaches ``level``,
    linear between samples."""
    k = int(np.searchsorted(cum, level, side="left"))
    if k == 0:
        return float(t[0])
    c0, c1 = cum[k - 1], cum[k]
    return float(t[k - 1] + (level - c0) / (c1 - c0) * (t[k] - t[k - 1]))


@dataclass(frozen=True, eq=False)
class AccelerationRecord:
    """One component of a ground acceleration: ``values`` (m/s², after units, scaling and
    polarity) at ``times`` (s, increasing), acting along ``axis`` ("x", "y" or "z"; a
    positive value accelerates the ground along +axis).  ``name`` says where it came from
    (the file); ``factor`` is the factor applied to the file's values in m/s² (scale and
    polarity), for the record.  Read from a file with :meth:`read`."""

    times: np.ndarray
    values: np.ndarray
    axis: str = "x"
    name: str = "record"
    factor: float = 1.0

    def __post_init__(self):
        t = np.array(self.times, float)
        v = np.array(self.values, float)
        item = f"record '{self.name}'"
        if t.ndim != 1 or t.shape != v.shape or len(t) < 2:
            raise ModelError(item, "give at least two (time, value) samples of the same length")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))):
            raise ModelError(item, "times or values contain NaN or inf")
        if np.any(np.diff(t) <= 0):
            k = int(np.flatnonzero(np.diff(t) <= 0)[0])
            raise ModelError(item, f"times must increase: sample {k + 1} ({t[k + 1]:g} s) "
                             f"follows {t[k]:g} s")
        if not np.any(v):
            raise ModelError(item, "all values are zero: the record would not move the "
                             "ground")
        if self.axis not in AXES:
            raise ModelError(f"{item}.axis", f"must be one of {', '.join(AXES)}, got "
                             f"{self.axis!r}")
        t.flags.writeable = False
        v.flags.writeable = False
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "values", v)

    @classmethod
    def read(cls, path: str | Path, format: str | None = None, *, units: str | None = None,
             dt: float | None = None, scale: float | None = None,
             target_pga: float | None = None, target_pga_g: float | None = None,
             polarity: int = 1, axis: str = "x", name: str | None = None
             ) -> AccelerationRecord:
        """Read a record file: ``format`` ``at2`` (default for a ``.AT2`` name; in g),
        ``two_column`` or ``one_column`` (with ``dt``, s); ``units`` of the values of a text
        file: g, m/s2, cm/s2 or gal (required for text files: there is no default unit);
        then scaled by ``scale`` or to a peak ``target_pga`` (m/s²) or ``target_pga_g`` (g)
        — at most one of the three —, and its sign flipped with ``polarity = -1``.
        ModelError naming the argument (``format``, ``units``, ``dt``, ``scale``,
        ``target_pga``, ``polarity``) or the file and its line."""
        path = Path(path)
        fmt = _format_of(path, format)
        if fmt == "at2":
            if units is not None and _units_factor(units) != RECORD_UNITS["g"]:
                raise ModelError("units", f"a PEER .AT2 record is in g, got '{units}'")
            to_si = RECORD_UNITS["g"]
        else:
            if units is None:
                raise ModelError("units", f"give the units of '{path.name}' "
                                 f"({', '.join(RECORD_UNITS)})")
            to_si = _units_factor(units)
        if fmt == "one_column" and dt is None:
            raise ModelError("dt", f"give the time step (s) of the one-column file "
                             f"'{path.name}'")
        if fmt != "one_column" and dt is not None:
            raise ModelError("dt", f"a{'n AT2' if fmt == 'at2' else ' two-column'} file gives "
                             "its own time step: leave dt out")
        if fmt == "at2":
            t, raw = read_at2(path)
        elif fmt == "two_column":
            t, raw = read_two_column(path)
        else:
            t, raw = read_one_column(path, dt)
        if not np.any(raw):
            raise ModelError(f"{path}", "all values are zero: the record would not move the "
                             "ground")
        factor = scale_factor(float(np.abs(raw).max()) * to_si, scale=scale,
                              target_pga=target_pga, target_pga_g=target_pga_g,
                              polarity=polarity)
        return cls(t, raw * (to_si * factor), axis, str(path) if name is None else name,
                   factor)

    # ---- what a run and a reviewer need ------------------------------------------------------
    @property
    def dt(self) -> float:
        """The time step (median of the samples' spacing), s."""
        return float(np.median(np.diff(self.times)))

    def time_function(self) -> Tabulated:
        """a_g(t), m/s²: the samples, linear between them, zero before the first and after
        the last."""
        return Tabulated(self.times, self.values, hold=False)

    def components(self) -> tuple[tuple[Tabulated, str], ...]:
        """((a_g(t), axis),): the record as the one component of a ground acceleration
        (``solve_dynamic(ground_acceleration=record)``)."""
        return ((self.time_function(), self.axis),)

    def figures(self) -> RecordFigures:
        """The baseline figures (:class:`RecordFigures`): PGA and its time, length and
        sampling, Arias intensity I_a = π/(2g) ∫ a² dt (exact for the piecewise-linear
        record), and the 5–95 % significant duration."""
        t, a = self.times, self.values
        k = int(np.argmax(np.abs(a)))
        cum = arias_cumulative(t, a)
        total = float(cum[-1])
        t5, t95 = _crossing(t, cum, 0.05 * total), _crossing(t, cum, 0.95 * total)
        pga = float(abs(a[k]))
        return RecordFigures(self.name, self.axis, pga, pga / G_RECORD, float(t[k]),
                             float(t[-1] - t[0]), math.pi / (2 * G_RECORD) * total, t5, t95,
                             t95 - t5, self.dt, len(t), float(self.factor))


def scale_factor(pga: float, *, scale: float | None = None, target_pga: float | None = None,
                 target_pga_g: float | None = None, polarity: int = 1) -> float:
    """The factor on a record of peak ``pga`` (m/s²): ``scale``, or target / pga for a
    target peak (``target_pga`` m/s², ``target_pga_g`` in g), times the ``polarity`` (+1, or
    −1 to flip the sign).  ModelError naming the argument: more than one of the three, a
    factor or target that is not positive and finite, a polarity other than ±1."""
    given = [k for k, v in (("scale", scale), ("target_pga", target_pga),
                            ("target_pga_g", target_pga_g)) if v is not None]
    if len(given) > 1:
        raise ModelError(given[1], f"is given together with {given[0]}: give one of scale, "
                         "target_pga (m/s²) and target_pga_g (g)")
    if isinstance(polarity, bool) or polarity not in (1, -1):
        raise ModelError("polarity", f"must be 1 or -1 (flip the sign), got {polarity!r}")
    factor = 1.0
    for key, v in (("scale", scale), ("target_pga", target_pga),
                   ("target_pga_g", target_pga_g)):
        if v is None:
            continue
        try:
            x = float(v)
        except (TypeError, ValueError):
            raise ModelError(key, f"must be a number, got {v!r}") from None
        if not (math.isfinite(x) and x > 0):
            raise ModelError(key, f"must be positive and finite, got {x:g}")
        factor = x if key == "scale" else (x if key == "target_pga" else x * G_RECORD) / pga
    return factor * polarity


@dataclass(frozen=True, eq=False)
class GroundMotion:
    """The components of a ground acceleration that act together: records along distinct
    axes (a horizontal one along x and a vertical one along y in 2D; x, y, z in 3D).  Give
    it to :func:`stepcontact.solve_dynamic` as ``ground_acceleration``, or to a model's
    :class:`~stepcontact.model.DynamicInterval` as ``ground``."""

    records: tuple[AccelerationRecord, ...]

    def __post_init__(self):
        recs = tuple(self.records) if isinstance(self.records, Iterable) else (self.records,)
        if not recs:
            raise ModelError("ground motion", "give at least one record")
        for i, r in enumerate(recs):
            if not isinstance(r, AccelerationRecord):
                raise ModelError(f"ground motion record {i}", f"must be an AccelerationRecord, "
                                 f"got {type(r).__name__}")
        axes = [r.axis for r in recs]
        for i, ax in enumerate(axes):
            if ax in axes[:i]:
                raise ModelError(f"ground motion record {i}.axis", f"'{ax}' is the axis of "
                                 f"record {axes.index(ax)} too: give one record per axis")
        object.__setattr__(self, "records", recs)

    def components(self) -> tuple[tuple[Tabulated, str], ...]:
        """The (a_g(t) in m/s², axis) pairs the dynamic driver applies together."""
        return tuple(c for r in self.records for c in r.components())

    def figures(self) -> tuple[RecordFigures, ...]:
        """Every record's baseline figures."""
        return tuple(r.figures() for r in self.records)


def _model_intervals(model):
    """(name, dynamic interval, its records) of every dynamic interval of ``model`` with
    records (``model.dynamics`` and the stages' ``dynamics``, each once)."""
    seen: set[int] = set()
    intervals = [(f"stages[{k}].dynamics", st.dynamics)
                 for k, st in enumerate(getattr(model, "stages", ()))]
    intervals.append(("dynamics", getattr(model, "dynamics", None)))
    for where, dyn in intervals:
        ground = getattr(dyn, "ground", None)
        if ground is None or id(dyn) in seen:
            continue
        seen.add(id(dyn))
        recs = ground.records if isinstance(ground, GroundMotion) else (
            (ground,) if isinstance(ground, AccelerationRecord) else ())
        if recs:
            yield where, dyn, recs


def model_records(model) -> list[tuple[str, RecordFigures]]:
    """The records of a model's dynamic intervals (``model.dynamics``, and the stages'
    ``dynamics``) with their baseline figures: [(interval, figures)], the interval named
    ``dynamics`` or ``stages[k].dynamics`` (as in a model file) — what ``stepcontact
    validate`` and ``run`` print before any work."""
    return [(where, r.figures()) for where, _, recs in _model_intervals(model) for r in recs]


class RecordGridWarning(UserWarning):
    """A record whose samples are off the step grid of its dynamic interval
    (:func:`grid_problem`): every step is cut at them, which damps the motion numerically."""


def grid_problem(record: AccelerationRecord, dt: float) -> str:
    """Why the samples of ``record`` are not on the step grid of a dynamic interval of time
    step ``dt`` (s), or "": the driver lands a step on every sample (a break of the record's
    time function), so samples between the steps cut every step — each landing a
    convex combination of a whole step's ends, which the ledger books as numerical
    dissipation — where a time step equal to the record's, or a whole fraction of it, steps
    through the samples exactly."""
    t = np.asarray(record.times)
    on = np.abs(t / dt - np.round(t / dt)) <= 1e-6 * np.maximum(1.0, np.abs(t / dt))
    if np.all(on):
        return ""
    k = int(np.flatnonzero(~on)[0])
    return (f"the record '{record.name}' (dt = {record.dt:g} s) has samples off the steps of "
            f"dt = {dt:g} s (the first at {t[k]:g} s): every step is cut at them, which "
            f"damps the motion numerically; give dt = {record.dt:g} s or a whole fraction of "
            "it")


def record_warnings(model) -> list[tuple[str, str]]:
    """(item, text) of every record whose samples are off the interval's step grid
    (:func:`grid_problem`), and of every record that outlasts its dynamic interval: the part
    after the interval's end is not applied (a run of a shorter interval is legitimate — the
    strong phase only — but should be a choice).  Items ``dynamics.ground_motion[j]``."""
    out = []
    for where, dyn, recs in _model_intervals(model):
        for j, r in enumerate(recs):
            text = grid_problem(r, float(dyn.dt))
            if text:
                out.append((f"{where}.ground_motion[{j}]", text))
            end = float(r.times[-1])
            if end > float(dyn.duration) * (1 + 1e-9):
                out.append((f"{where}.ground_motion[{j}]", (
                    f"the record '{r.name}' lasts until {end:g} s, the interval only "
                    f"{float(dyn.duration):g} s: the record after {float(dyn.duration):g} s "
                    f"is not applied (its 95 % Arias time is {r.figures().t95:.4g} s)")))
    return out


__all__ = ["AXES", "DT_TOLERANCE", "G_RECORD", "RECORD_FORMATS", "RECORD_UNITS",
           "AccelerationRecord", "GroundMotion", "RecordFigures", "RecordUnits",
           "arias_cumulative", "model_records", "read_at2", "read_one_column",
           "RecordGridWarning", "grid_problem", "read_two_column", "record_warnings",
           "scale_factor"]
