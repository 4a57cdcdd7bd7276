"""The earthquake record in the dam study (issue 29 §1 and §3): the section's seismic input
(:class:`QuakeRecord`) and its run (:func:`run_quake`).

One static run of three stages on the section's model (:func:`~stepcontact.study.dam.dam_site`
with the patterns of the usual combination, :func:`~stepcontact.study.dam.combinations`):

1. ``usual`` — self-weight, tailwater, the reservoir at the normal level with its uplift and
   crack water, silt: the usual combination's static state;
2. ``earthquake`` — a dynamic interval (:class:`~stepcontact.model.DynamicInterval`) under the
   record (horizontal along x, optional vertical along y; a positive value accelerates the
   ground along +x/+y: the displacements are relative to the ground), with the reservoir's
   Westergaard (1933) added mass at the normal level on the upstream face
   (:class:`~stepcontact.model.AddedMass`, part of M), Rayleigh damping C = a₀ M + a₁ K with
   the ratio ζ at two frequencies (:func:`~stepcontact.fem.mass.rayleigh_coefficients`), and
   the chosen crack water during the shaking (``"unchanged"``, ``"none"`` or ``"full"``: the
   user guide's *Crack water during an earthquake*);
3. ``post-earthquake`` — the static stage after it: the force out of balance where the
   shaking ended is released (the automatic segment ``"earthquake: settle after dynamics"``)
   and the crack water goes back to its static rule (full reservoir pressure in the crack
   joined to the reservoir), from the cracked, slid state.

What it reports (:class:`QuakeRun`): the base's permanent slip (mean over the joint and largest
CFE, :func:`~stepcontact.results.sliding.joint_slip`) beside Newmark's (1965) rigid-block
estimate for the same horizontal record and the study's yield acceleration k_y
(:func:`~stepcontact.results.sliding.sliding_comparison`): one-directional downstream (the
record negated, since a ground accelerating upstream, −x, drives the dam downstream relative
to it) and two-directional; the largest open length of the base during the shaking and its
time; the post-earthquake state's figures (:meth:`~stepcontact.results.result.StaticResult.
interface_safety`) and its guideline verdict
(:func:`~stepcontact.results.dam_checks.check_combination`, condition post-earthquake);
the CPU time.

The rigid-block estimate and the dynamic run agree for a rigid dam on a rigid frictional base
whose base stays closed: the pseudo-static k_y includes Westergaard's force k_y (7/12) γ_w h²,
the same inertia the added mass gives under the ground's acceleration, so a_y = k_y g is the
rigid block's yield acceleration with the added mass (``tests/test_dam_quake.py``).

Example
-------
>>> from stepcontact.study.dam import DamSection
>>> rec = QuakeRecord("record.AT2", target_pga=0.3)                    # doctest: +SKIP
>>> st = run_dam(DamSection(cell=2.0, record=rec))                     # doctest: +SKIP
>>> st.earthquake.slip.permanent_mean                                  # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
import math
import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from stepcontact.enums import ContactState, Status
from stepcontact.errors import ModelError, SolverError
from stepcontact.fem.mass import rayleigh_coefficients
from stepcontact.model import AddedMass, DynamicInterval, Segment, Stage
from stepcontact.model.combinations import Combination
from stepcontact.model.records import AccelerationRecord, GroundMotion
from stepcontact.model.structure import CRACK_WATER_CHOICES
from stepcontact.post.common import DPI, figure_path, new_figure, save_figure
from stepcontact.results.dam_checks import DamCheck, check_combination
from stepcontact.results.sliding import JointSlip, SlidingComparison, sliding_comparison

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from stepcontact.study.dam import DamSection

#: standard gravity of the records' g, m/s² (the records' unit, model/records.py)
G_RECORD = 9.80665
#: the crack water during the shaking by default: the pre-earthquake uplift unchanged
#: (USACE EM 1110-2-2200 (1995), FERC (1991) ch. III, as quoted by the CADAM manual
#: [to be checked]; the user guide's "Crack water during an earthquake")
DEFAULT_CRACK_WATER = "unchanged"
#: the figure files of the earthquake section, relative to the report's directory
QUAKE_FIGURES = {"quake": "figures/earthquake.png"}


def _positive(value, item: str, unit: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ModelError(item, f"must be a number{unit}, got {value!r}") from None
    if isinstance(value, bool) or not (math.isfinite(v) and v > 0):
        raise ModelError(item, f"must be a positive number{unit}, got {value!r}")
    return v


def fundamental_frequency(height: float, modulus: float) -> float:
    """An estimate of the dam's fundamental frequency, Hz, on a rigid base with an empty
    reservoir: T₁ = 1.4 H/√E with H in ft and E in psi (Fenves & Chopra 1987, the simplified
    procedure, as given in Chopra, *Dynamics of Structures*, ch. on concrete dams
    [to be checked]); the default lower frequency of the Rayleigh damping."""
    h_ft = float(height) / 0.3048
    e_psi = float(modulus) / 6894.757
    return math.sqrt(e_psi) / (1.4 * h_ft)


@dataclass(frozen=True)
class QuakeRecord:
    """The earthquake record of a dam section (SI; accelerations in g where named so).

    ``horizontal``: the file of the horizontal component (along x: +x downstream), read by
    :meth:`~stepcontact.model.records.AccelerationRecord.read` with ``format`` (default from
    the name: ``.AT2`` is PEER's, in g; ``two_column``, ``one_column``), ``units`` (text
    files: g, m/s2, cm/s2, gal) and ``file_dt`` (s, a one-column file's sampling);
    ``vertical``: the file of the vertical component (along y, + up), optional, same format;
    ``scale`` (a factor) or ``target_pga`` (the horizontal peak, g) — the same factor scales
    the vertical; ``polarity`` (+1, or −1 to flip the horizontal record: the other direction
    of shaking); ``crack_water`` in a crack during the shaking: ``"unchanged"`` (default;
    USACE 1995, FERC 1991 as quoted [to be checked]), ``"none"`` (USBR 1987) or ``"full"``
    (ICOLD 1986); ``dt``: the interval's time step (default the record's: give the record's
    step or a whole fraction of it); ``duration`` (default the record's length, s);
    ``damping_ratio`` ζ of Rayleigh damping at the two ``damping_frequencies`` (Hz; default
    f₁ of :func:`fundamental_frequency` and 5 f₁); ``mass``: "consistent" or "lumped".
    Errors name the field (``dam.record.<field>``)."""

    horizontal: str | os.PathLike
    vertical: str | os.PathLike | None = None
    format: str | None = None
    units: str | None = None
    file_dt: float | None = None
    scale: float | None = None
    target_pga: float | None = None
    polarity: int = 1
    crack_water: str = DEFAULT_CRACK_WATER
    dt: float | None = None
    duration: float | None = None
    damping_ratio: float = 0.05
    damping_frequencies: tuple[float, float] | None = None
    mass: str = "consistent"

    def __post_init__(self):
        item = "dam.record"
        if self.crack_water not in CRACK_WATER_CHOICES:
            raise ModelError(f"{item}.crack_water", f"must be one of "
                             f"{', '.join(CRACK_WATER_CHOICES)}, got {self.crack_water!r}")
        if isinstance(self.polarity, bool) or self.polarity not in (1, -1):
            raise ModelError(f"{item}.polarity", f"must be 1 or -1, got {self.polarity!r}")
        if self.scale is not None and self.target_pga is not None:
            raise ModelError(f"{item}.target_pga", "is given together with scale: give one")
        for key in ("scale", "target_pga", "dt", "duration", "file_dt"):
            if getattr(self, key) is not None:
                _positive(getattr(self, key), f"{item}.{key}",
                          {"target_pga": " (g)", "scale": ""}.get(key, " (s)"))
        z = self.damping_ratio
        if isinstance(z, bool) or not (isinstance(z, int | float) and math.isfinite(z)
                                       and 0 <= z < 1):
            raise ModelError(f"{item}.damping_ratio", f"must be a fraction in [0, 1), got {z!r}")
        if self.damping_frequencies is not None:
            fs = tuple(self.damping_frequencies)
            if len(fs) != 2:
                raise ModelError(f"{item}.damping_frequencies", f"give two frequencies (Hz), "
                                 f"got {self.damping_frequencies!r}")
            for f in fs:
                _positive(f, f"{item}.damping_frequencies", " (Hz)")
            if fs[0] == fs[1]:
                raise ModelError(f"{item}.damping_frequencies", f"the two frequencies must "
                                 f"differ (both {fs[0]} Hz)")
            object.__setattr__(self, "damping_frequencies", (float(fs[0]), float(fs[1])))
        if self.mass not in ("consistent", "lumped"):
            raise ModelError(f"{item}.mass", f"must be 'consistent' or 'lumped', got "
                             f"{self.mass!r}")
        for key in ("horizontal", "vertical"):
            p = getattr(self, key)
            if p is None and key == "vertical":
                continue
            if not isinstance(p, str | os.PathLike) or not Path(p).is_file():
                raise ModelError(f"{item}.{key}", f"no record file {str(p)!r}")

    def _read(self, path, axis: str, **scaling) -> AccelerationRecord:
        item = f"dam.record.{'horizontal' if axis == 'x' else 'vertical'}"
        try:
            return AccelerationRecord.read(path, self.format, units=self.units,
                                           dt=self.file_dt, axis=axis, **scaling)
        except ModelError as e:
            raise ModelError(f"{item} ({e.item})" if e.item else item, e.problem) from None

    def records(self) -> tuple[AccelerationRecord, AccelerationRecord | None]:
        """(horizontal, vertical or None): read, scaled (the vertical by the horizontal's
        factor) and the horizontal's polarity applied."""
        h = self._read(self.horizontal, "x", scale=self.scale,
                       target_pga_g=self.target_pga, polarity=self.polarity)
        v = None if self.vertical is None else self._read(
            self.vertical, "y", scale=abs(h.factor))
        return h, v

    def damping(self, section: DamSection) -> tuple[float, float, tuple[float, float]]:
        """(a₀ (1/s), a₁ (s), (f₁, f₂) Hz) of the Rayleigh damping."""
        fs = self.damping_frequencies
        if fs is None:
            f1 = fundamental_frequency(section.height, section.concrete.E)
            fs = (f1, 5.0 * f1)
        if self.damping_ratio == 0:
            return 0.0, 0.0, fs
        a0, a1 = rayleigh_coefficients(self.damping_ratio, fs[0], self.damping_ratio, fs[1])
        return float(a0), float(a1), fs


@dataclass
class QuakeRun:
    """What :func:`run_quake` found (SI: m, s, N per metre of dam; accelerations m/s² unless
    in g).

    ``record``, ``vertical``: the records as run (:class:`AccelerationRecord`); ``result``:
    the staged static run (its ``dynamics["earthquake"]`` the dynamic result); ``shaking``:
    that dynamic result; ``slip``: the base's :class:`~stepcontact.results.sliding.JointSlip`
    (m, along +x: downstream > 0); ``newmark_one``, ``newmark_two``: the
    :class:`~stepcontact.results.sliding.SlidingComparison` of the run with Newmark's
    one-directional (downstream) and two-directional estimates at a_y = k_y g (None without
    a yield acceleration); ``k_y`` (g); ``open_length`` (m, the base's open length at each
    state of the shaking), ``max_open`` and ``max_open_time`` (s); ``post``: the joint's
    figures at the last state (:meth:`InterfaceSafety.at`); ``checks``: the post-earthquake
    verdict (:class:`DamCheck`); ``damping`` (a₀, a₁, (f₁, f₂)); ``dt``, ``duration`` (s);
    ``seconds``: CPU time; ``notes``."""

    quake: QuakeRecord
    record: AccelerationRecord
    vertical: AccelerationRecord | None
    result: Any
    shaking: Any
    slip: JointSlip
    newmark_one: SlidingComparison | None
    newmark_two: SlidingComparison | None
    k_y: float | None
    open_length: np.ndarray
    max_open: float
    max_open_time: float
    post: dict[str, Any]
    checks: DamCheck | None
    damping: tuple
    dt: float
    duration: float
    seconds: float
    notes: list[str]

    @property
    def verdict(self) -> str:
        """The post-earthquake verdict: "pass", "FAIL" or "not evaluated"."""
        if self.checks is None:
            return "not evaluated"
        done = [r.passed for r in self.checks.rows if r.passed is not None]
        return "not evaluated" if not done else "pass" if all(done) else "FAIL"

    def figures(self) -> dict[str, Any]:
        """The figures of the run as plain values (``summary.json``)."""
        one = None if self.newmark_one is None else self.newmark_one.newmark.permanent
        two = None if self.newmark_two is None else self.newmark_two.newmark.permanent
        return {"record": self.record.figures().as_dict(),
                "vertical": None if self.vertical is None else self.vertical.figures().as_dict(),
                "crack_water": self.quake.crack_water, "dt": self.dt,
                "duration": self.duration, "damping_a0": self.damping[0],
                "damping_a1": self.damping[1], "damping_frequencies": list(self.damping[2]),
                "damping_ratio": self.quake.damping_ratio,
                "slip_mean": float(self.slip.permanent_mean),
                "slip_max": float(self.slip.permanent_max),
                "sliding_at_end": self.slip.sliding_at_end, "k_y": self.k_y,
                "newmark_one_directional": None if one is None else abs(one),
                "newmark_two_directional": two, "max_open_length": self.max_open,
                "max_open_time": self.max_open_time, "post_earthquake": self.post,
                "verdict": self.verdict, "status": str(self.result.status),
                "message": self.result.message, "cpu_seconds": self.seconds,
                "notes": self.notes}


def quake_model(s: DamSection, quake: QuakeRecord | None = None):
    """The staged model of the record run (module docstring), its ground motion and its
    interval: (model, site, usual combination, horizontal record, vertical record or None,
    DynamicInterval, damping)."""
    from stepcontact.study.dam import combinations, dam_site

    q = s.record if quake is None else quake
    if q is None:
        raise ModelError("dam.record", "the section has no earthquake record")
    h, v = q.records()
    ground = GroundMotion((h,) if v is None else (h, v))
    dt = h.dt if q.dt is None else float(q.dt)
    length = float(h.times[-1]) if v is None else max(float(h.times[-1]), float(v.times[-1]))
    duration = length if q.duration is None else float(q.duration)
    a0, a1, fs = q.damping(s)
    site = dam_site(s)
    usual = combinations(s)[0]
    water = tuple(AddedMass(n, level=float(s.normal_level), bottom=0.0,
                            density=1000.0) for n in site.upstream)
    try:
        interval = DynamicInterval(dt=dt, duration=duration, mass=q.mass, damping=(a0, a1),
                                   ground=ground, crack_water=q.crack_water)
    except ModelError as e:
        key = str(e.item).removeprefix("dynamics.").split(" ")[0]
        field = {"dt": "dt", "duration": "duration", "max_steps": "dt"}.get(key, key)
        raise ModelError(f"dam.record.{field}", e.problem) from None
    model = site.model.add(*usual.patterns(site), *water,
                           Stage("usual", tuple(usual.segments())),
                           Stage("earthquake", dynamics=interval),
                           # the reservoir held at its level: the stage's (empty) segment
                           Stage("post-earthquake", (Segment("self-weight",
                                                             1.0),)))
    return model, site, usual, h, v, interval, (a0, a1, fs)


def _joint_cfes(res, joint: str) -> np.ndarray:
    k = np.flatnonzero(np.asarray(res.cfe["interface"]) == list(res.interface_names).index(joint))
    return k[np.argsort(np.asarray(res.cfe["x"])[k, 0], kind="stable")]


def run_quake(s: DamSection, k_y: float | None, *,
              say: Callable[[str], None] = lambda t: None) -> QuakeRun:
    """Run the section's record (:attr:`DamSection.record`) as the stages of the module's
    docstring and compare the base's permanent slip with Newmark's estimate at the yield
    acceleration ``k_y`` (g; None: not reached, no estimate).  A run that ends without an
    answer is a :class:`~stepcontact.errors.SolverError`."""
    from stepcontact.solver.static import solve_static
    from stepcontact.study.dam import JOINT, G, earthquake, joint_strength

    q = s.record
    t0 = time.process_time()
    model, site, usual, h, v, interval, damping = quake_model(s)
    say(f"earthquake: {h.figures().line()}")
    say(f"earthquake: the usual loads, then {interval.duration:g} s of shaking at dt = "
        f"{interval.dt:g} s (crack water '{q.crack_water}'), then the post-earthquake stage")
    res = solve_static(model)
    shaking = res.dynamics.get("earthquake") if res.dynamics else None
    if shaking is None or shaking.status != Status.COMPLETED or res.status not in (
            Status.COMPLETED, Status.EQUILIBRIUM_LOST):
        raise SolverError(f"the dam's earthquake run {res.message or res.status}: no answer "
                          "to report")
    from stepcontact.results.sliding import joint_slip

    slip = joint_slip(shaking, JOINT)
    notes = []
    one = two = None
    if k_y is not None and k_y > 0:
        a_y = float(k_y) * G  # k_y in the model's g (its weight and SeismicCoefficient)
        rec = (h.times, h.values)
        one = sliding_comparison(shaking, (rec[0], -rec[1]), a_y, interfaces=JOINT)
        two = sliding_comparison(shaking, rec, a_y, interfaces=JOINT, two_way=True)
    elif k_y is None:
        notes.append("the yield acceleration was not reached on the yield run: no Newmark "
                     "estimate")
    else:
        notes.append("the dam loses equilibrium before the earthquake: no Newmark estimate")
    if k_y and s.k_v:
        notes.append(f"k_y is the yield run's, with the design ratio k_v/k_h = "
                     f"{s.k_v / s.k_h:g} of a pseudo-static vertical inertia; Newmark's "
                     "estimate takes it as it is and the horizontal record only")
    if res.status == Status.EQUILIBRIUM_LOST:
        notes.append(f"the dam loses equilibrium after the shaking ({res.message}): the "
                     "post-earthquake state is the last state of equilibrium")
    if slip.sliding_at_end:
        notes.append("the base still slides at the end of the shaking: the slip is not yet "
                     "permanent (give a longer duration)")
    k = _joint_cfes(shaking, JOINT)
    area = np.asarray(shaking.cfe["area"], float)[k]
    opened = (np.asarray(shaking.state)[:, k] == int(ContactState.OPEN)) @ area
    i = int(np.argmax(opened))
    post = res.interface_safety(JOINT, heel=(0.0, 0.0)).at(len(res.lam) - 1)
    # the check reads the run's last state, the combination's name, condition and uplift
    # case: the usual cases and the earthquake they follow (here the record)
    post_combo = Combination("post-earthquake (record)", "post-earthquake",
                             usual.cases + (earthquake(s),))
    checks = check_combination(res, post_combo, site, guideline=s.guideline,
                               variant=s.guideline_variant, joints=[JOINT],
                               strength=joint_strength(s))
    return QuakeRun(q, h, v, res, shaking, slip, one, two, k_y, opened, float(opened[i]),
                    float(np.asarray(shaking.time)[i]), post, checks, damping,
                    float(interval.dt), float(interval.duration),
                    time.process_time() - t0, notes)


def describe_record(q: QuakeRecord) -> str:
    """The record's fields that are given, in a line (the report's inputs)."""
    parts = [f"{f.name} = {getattr(q, f.name)}" for f in dataclasses.fields(q)
             if getattr(q, f.name) is not None and getattr(q, f.name) != f.default]
    return ", ".join(parts)


# --------------------------------------------------------------------------- figure ---

def plot_quake(run: QuakeRun, path: str | os.PathLike[str] | None = None, *,
               dpi: float = DPI, base_length: float | None = None) -> Figure:
    """Time histories of the shaking: the horizontal ground acceleration (g) with ±k_y
    dotted, the base's slip (mm, the mean and the largest CFE's, downstream > 0) with
    Newmark's one-directional estimate, and the open length of the base (m) with its
    largest marked."""
    p = figure_path(path, dpi)
    fig = new_figure(figsize=(9.0, 8.0))
    ax_a, ax_s, ax_o = fig.subplots(3, 1, sharex=True)
    t = np.asarray(run.shaking.time, float)
    ax_a.plot(run.record.times, run.record.values / G_RECORD, color="k", lw=0.8,
              label="ground acceleration (x)")
    if run.vertical is not None:
        ax_a.plot(run.vertical.times, run.vertical.values / G_RECORD, color="#7f7f7f", lw=0.6,
                  label="vertical (y)")
    if run.newmark_one is not None:
        a_y = run.newmark_one.a_yield / G_RECORD  # k_y g, in the records' g
        for sign in (1, -1):
            ax_a.axhline(sign * a_y, color="#d62728", lw=1.0, ls=":",
                         label=f"± k_y = {run.k_y:.4f} g" if sign > 0 else None)
    ax_a.set_ylabel("a_g (g)")
    slip = run.slip
    ax_s.plot(t, slip.mean * 1e3, color="#1f77b4", lw=1.4, label="mean slip of the base")
    j = int(np.flatnonzero(slip.cfes == slip.cfe_max)[0])
    ax_s.plot(t, slip.slip[:, j] * 1e3, color="#ff7f0e", lw=0.9, ls="--",
              label="largest CFE's slip")
    if run.newmark_one is not None:
        nm = run.newmark_one.newmark
        ax_s.plot(nm.time, np.abs(nm.displacement) * 1e3, color="#2ca02c", lw=1.0, ls="-.",
                  label="Newmark, one-directional")
    ax_s.set_ylabel("slip (mm, downstream > 0)")
    ax_o.step(t, run.open_length, where="post", color="#d62728", lw=1.2, label="open length")
    ax_o.plot([run.max_open_time], [run.max_open], "o", color="#d62728", ms=4,
              label=f"largest {run.max_open:.2f} m at {run.max_open_time:.3f} s")
    ax_o.set_ylabel("open length (m)")
    ax_o.set_xlabel("time t (s)")
    if base_length:
        ax_o.set_ylim(0.0, float(base_length))
    for a, where in ((ax_a, "upper right"), (ax_s, "lower right"), (ax_o, "upper right")):
        a.grid(True, alpha=0.3)
        a.legend(loc=where, fontsize="x-small", frameon=False)
    fig.suptitle(f"Earthquake record: crack water '{run.quake.crack_water}'",
                 fontsize="medium")
    save_figure(fig, p, dpi)
    return fig


# --------------------------------------------------------------------------- report ---

def quake_blocks(run: QuakeRun | None) -> list:
    """The report's earthquake section (blocks of :mod:`stepcontact.study.report`)."""
    from stepcontact.study.report import _Heading, _Image, _num, _Para, _Table

    if run is None:
        return []
    fig = run.record.figures()
    q = run.quake
    a0, a1, fs = run.damping
    inputs = [("horizontal record", fig.line()),
              ("vertical record", "none" if run.vertical is None
               else run.vertical.figures().line()),
              ("polarity", f"{q.polarity:+d} (a positive value accelerates the ground "
                           "along +x, downstream; displacements relative to the ground)"),
              ("crack water during the shaking", q.crack_water),
              ("time step, duration", f"{run.dt:g} s, {run.duration:g} s"),
              ("Rayleigh damping", f"ζ = {q.damping_ratio:g} at {fs[0]:.3g} and {fs[1]:.3g} Hz "
                                   f"(a₀ = {a0:.4g} 1/s, a₁ = {a1:.4g} s)"),
              ("mass", f"{q.mass}, with Westergaard's added mass at the normal level")]
    one = run.newmark_one
    two = run.newmark_two
    rows = [("permanent slip of the base, mean (mm)", _num(run.slip.permanent_mean * 1e3,
                                                          ".4g")),
            ("permanent slip, largest CFE (mm)", _num(run.slip.permanent_max * 1e3, ".4g")),
            ("yield acceleration k_y (g)", _num(run.k_y, ".4g")),
            ("Newmark, one-directional downstream (mm)",
             _num(None if one is None else abs(one.newmark.permanent) * 1e3, ".4g")),
            ("Newmark, two-directional (mm, along −x for a positive record)",
             _num(None if two is None else -two.newmark.permanent * 1e3, ".4g")),
            ("|mean slip| / Newmark one-directional",
             _num(None if one is None else one.rows[0]["ratio"], ".4g")),
            ("largest open length during the shaking (m)", _num(run.max_open, ".3g")),
            ("its time (s)", _num(run.max_open_time, ".4g"))]
    p = run.post
    post = [("open length (m)", _num(p.get("open_length"), ".3g")),
            ("compressed length (m)", _num(p.get("compressed_length"), ".3g")),
            ("sliding factor, friction only", _num(p.get("sliding_factor"), ".4g")),
            ("shear-friction factor", _num(p.get("shear_friction_factor"), ".4g")),
            ("resultant from the toe (m)", _num(p.get("resultant_from_toe"), ".4g")),
            ("ΣN (kN)", _num(None if p.get("normal_force") is None
                             else p["normal_force"] / 1e3, ".1f")),
            ("ΣQ (kN)", _num(None if p.get("shear_force") is None
                             else p["shear_force"] / 1e3, ".1f")),
            ("guideline verdict", run.verdict)]
    check_rows = [] if run.checks is None else [
        (r[2], r[3], r[4], r[5], r[6], r[7]) for r in run.checks.table_rows()
        if r[1] != "—" or r[6] != "—"]
    text = (f"The usual combination's static state, then {run.duration:g} s of shaking "
            f"under the record (Westergaard's added mass at the normal level, crack water "
            f"'{q.crack_water}'), then the post-earthquake static stage from the slid, "
            f"cracked state (the force out of balance released, full reservoir pressure in "
            f"the crack joined to the reservoir). The run: {run.result.message} "
            f"({run.seconds:.2f} s of CPU).")
    return [_Heading(2, "Earthquake record"), _Para(text),
            _Table(("input", "value"), inputs),
            _Para("Assumptions: the elastic dam and rock with the joint's exact contact "
                  "(opening, slip, the crack water chosen) during the shaking; Westergaard's "
                  "(1933) added mass at the normal level (rigid face, incompressible water, "
                  "no surface waves); the ground motion applied at the foundation's fixed "
                  "bottom (a rock block with its mass: no deconvolution, no radiation "
                  "damping) or at a rigid base; Rayleigh "
                  "damping as given. Sign convention: a positive record value accelerates "
                  "the ground along +x (downstream) or +y (up); displacements are relative "
                  "to the ground; the slip is the dam's relative to the rock, downstream > 0."),
            _Para("Newmark's rigid block (Newmark 1965) slides when the ground's acceleration "
                  "exceeds a_y = k_y g, k_y the study's yield acceleration (downstream; the "
                  "two-directional estimate takes the same a_y upstream). Assumptions: a "
                  "rigid block, constant a_y (no change of uplift or crack), the horizontal "
                  "record only."),
            _Table(("quantity", "value"), rows),
            *([_Para("Notes: " + "; ".join(run.notes) + ".")] if run.notes else []),
            _Heading(3, f"Post-earthquake state: {run.verdict}"),
            _Table(("quantity", "value"), post),
            *([_Table(("check", "value", "unit", "required", "verdict", "source / note"),
                      check_rows)] if check_rows else []),
            _Image(QUAKE_FIGURES["quake"], "earthquake time histories",
                   "The ground acceleration with ± k_y, the base's slip (mean and largest "
                   "CFE) beside Newmark's one-directional estimate, and the open length of "
                   "the base during the shaking.")]


__all__ = ["DEFAULT_CRACK_WATER", "QUAKE_FIGURES", "QuakeRecord", "QuakeRun", "describe_record",
           "fundamental_frequency", "plot_quake", "quake_blocks", "quake_model", "run_quake"]
