"""Hydraulics of a dam's stilling basin, for the study of its slab (apron): article §7.

Closed-form hydraulics of a free hydraulic jump on a horizontal apron and the loads on the slab
that follow from it.  All quantities are SI: lengths and heads in m, velocities in m/s, unit
discharges in m²/s, pressures in Pa, unit weights in N/m³, densities in kg/m³.  Functions take
floats or NumPy arrays of positions ``x`` (m, measured from the toe of the jump, i.e. from the
upstream edge of the slab) and return NumPy arrays of the same shape.

* the jump: :func:`unit_discharge`, :func:`contracted_depth`, :func:`conjugate_depth`,
  :func:`jump_length` and the frozen dataclass :class:`Jump` built by :func:`hydraulic_jump`;
  :func:`slab_length`;
* mean pressure on the slab's top: :func:`mean_depth` (Hager's profile), :func:`top_pressure`,
  :func:`deficit_pressure`, :func:`triangular_deficit` (Russian teaching practice);
* seepage uplift on its base: :func:`lane_creep_length`, :func:`lane_uplift`,
  :data:`LANE_RATIOS`, :func:`lane_check`, :func:`base_uplift`;
* pressure fluctuations: :func:`cp_rms`, :func:`rms_profile`, :func:`extreme_coefficients`,
  :func:`impulse_amplitude`;
* design thicknesses: :func:`fiorotto_rinaldo_thickness`, :func:`usace_flotation_factor`
  (:data:`USACE_FLOTATION_REQUIRED`), :func:`dombrovsky_thickness`,
  :func:`kern_liftoff_thickness`.

Sources and caveats
-------------------
The formulas' *structure* is standard; values flagged **[RECALLED]** in the docstrings (the
coefficients of Fiorotto & Rinaldo 1992, of Toso & Bowers 1988, the USACE required safety
factors, Dombrovsky's rule, Hager's profile and roller length, USBR EM-25's 6.1 y2) were
quoted from memory, not read in the papers: they are **defaults to be checked** before being
used as design values or test tolerances.  See ``docs/slab-hydraulics.md``.

Example
-------
>>> j = hydraulic_jump(h_kr=3.48, E0=25.0)
>>> round(j.q, 2), round(j.h1, 2), round(j.Fr1, 2), round(j.h2, 2), round(j.L_j, 1)
(20.33, 0.99, 6.63, 8.77, 53.5)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np
from scipy.optimize import brentq

from stepcontact.errors import ModelError

#: gravitational acceleration used by default, m/s²
G = 9.81
#: density of fresh water used by default, kg/m³
RHO_W = 1000.0
#: unit weight of concrete used by default, N/m³ (2400 kg/m³ × 9.81 m/s², γc/γw = 2.4)
GAMMA_C = 23544.0
#: unit weight of water used by default, N/m³ (1000 kg/m³ × 9.81 m/s²)
GAMMA_W = 9810.0

#: jump-length formulas known to :func:`jump_length`
JUMP_LENGTH_FORMULAS = ("usbr", "russian", "pavlovsky", "chertousov", "hager")

#: Lane's (1935) safe weighted-creep ratios C_w = L_w/ΔH per foundation soil (Trans. ASCE 100,
#: 1235–1272), as given in two public code tables citing Lane [SEEN]; some codes give 3.1 for
#: coarse gravel with cobbles and 2.1 for medium clay.
LANE_RATIOS: Mapping[str, float] = MappingProxyType({
    "very fine sand or silt": 8.5,
    "fine sand": 7.0,
    "medium sand": 6.0,
    "coarse sand": 5.0,
    "fine gravel": 4.0,
    "medium gravel": 3.5,
    "coarse gravel with cobbles": 3.0,
    "boulders": 2.5,
    "soft clay": 3.0,
    "medium clay": 2.0,
    "hard clay": 1.8,
    "very hard clay": 1.6,
})

#: Required flotation safety factors of USACE ETL 1110-2-307 (1987) for stilling basins,
#: spillway sills and aprons, per load condition — **[RECALLED]** (as in EM 1110-2-2100).
USACE_FLOTATION_REQUIRED: Mapping[str, float] = MappingProxyType(
    {"usual": 1.3, "unusual": 1.2, "extreme": 1.1})


#: how far a quoted coefficient was checked (:class:`Coefficient`), in the reports' words
CHECKED = "checked against the source"
SEEN = "read in a source when the code was written (not available here to check again)"
RECALLED = "recalled, not checked against the source"


@dataclass(frozen=True)
class Coefficient:
    """A coefficient the slab study quotes: ``name``, its ``values`` (numbers, in the order
    of ``formula``), the ``formula`` it enters, its ``source``, ``status`` (:data:`CHECKED`,
    :data:`SEEN` or :data:`RECALLED`) and, when checked, what it was checked ``against``."""

    name: str
    values: tuple[float, ...]
    formula: str
    source: str
    status: str
    against: str = ""


#: The coefficients of this module and of the slab study's defaults, with their sources.
#: Only the article's own h_kr could be checked against a source text available to the
#: project (the article, Lukashevich & Rozin 2013, §7); the papers and codes below were not
#: available: what was read in them when the code was written is marked SEEN, the rest
#: RECALLED (docs/slab-hydraulics.md keeps the same marks).
COEFFICIENTS: tuple[Coefficient, ...] = (
    Coefficient("critical depth of the design discharge h_kr (m)", (3.48,), "h_kr = 3.48 m",
                "Lukashevich & Rozin (2013), §7 (the Volga scheme's slab)", CHECKED,
                "the article's text, §7: “h_кр = 3,48 м – критическая глубина”"),
    Coefficient("velocity coefficient of the inflow φ", (0.95,),
                "E0 = h1 + q²/(2 g φ² h1²)", "usual value for a spillway face", RECALLED),
    Coefficient("USBR jump length", (6.1,), "L_j = 6.1 h2",
                "USBR Engineering Monograph 25 (Peterka), type-I jump (a textbook's “≈ 6 y2 "
                "for 4 < Fr1 < 20” was read)", RECALLED),
    Coefficient("Russian jump length", (6.0,), "L_j = 6 (h2 − h1)",
                "Russian teaching practice, (5–6)(h″ − h′)", SEEN),
    Coefficient("Pavlovsky jump length", (2.5, 1.9), "L_j = 2.5 (1.9 h2 − h1)", "Pavlovsky",
                RECALLED),
    Coefficient("Chertousov jump length", (10.3, 0.81), "L_j = 10.3 h1 (Fr1 − 1)^0.81",
                "Chertousov", RECALLED),
    Coefficient("Hager roller length", (-12.0, 160.0, 20.0),
                "L_r = h1 (−12 + 160 tanh(Fr1/20))", "Hager (1990)", RECALLED),
    Coefficient("Hager mean surface profile", (1.5,),
                "(y − h1)/(h2 − h1) = tanh(1.5 x/L_r)", "Hager (1990)", RECALLED),
    Coefficient("slab length factor", (1.0, 1.25, 0.8, 1.0),
                "L_p = (1–1.25) L_j without baffles, (0.8–1) L_j with them",
                "Russian teaching practice", SEEN),
    Coefficient("rms pressure coefficient C′p", (0.08, 10.0, 0.5),
                "C′p = 0.08 (X/10)^0.5 exp(0.5 (1 − X/10)), X = x/h1 (a smooth stand-in for "
                "measured maxima 0.05–0.10 at 5–20 h1)",
                "Toso & Bowers (1988), J. Hydraul. Eng. 114(8); Lopardo", RECALLED),
    Coefficient("extreme-value factors N⁺, N⁻", (4.0, 3.0), "C±p = N± C′p",
                "≈ the 99.9 %/0.1 % points of the pressure distribution", RECALLED),
    Coefficient("Fiorotto–Rinaldo reduction Ω and C⁺p + C⁻p", (0.15, 0.8),
                "s = Ω (C⁺p + C⁻p) V1²/2g · γ_w/(γ_c − γ_w), Ω = 0.15 (range 0.1–0.25), "
                "C⁺p + C⁻p = 0.8 (each 0.3–0.6)",
                "Fiorotto & Rinaldo (1992a), J. Hydraul. Eng. 118(4) 578–596", RECALLED),
    Coefficient("USACE required flotation factors", (1.3, 1.2, 1.1),
                "SF = 1.3 usual, 1.2 unusual, 1.1 extreme",
                "USACE ETL 1110-2-307 (1987), as in EM 1110-2-2100 (the formula "
                "SF = (W_s + W_c + S)/(U − W_G) was read)", RECALLED),
    Coefficient("Dombrovsky thickness", (0.15,), "t = 0.15 V1 √h1 (m, m/s)",
                "Dombrovsky, Russian empirical rule", RECALLED),
    Coefficient("impulse amplitude", (0.4,), "0.4 ρ_w V1²/2 (extremes near the toe "
                "0.3–0.6 ρ_w V1²/2)", "the pulsation's extremes of Toso & Bowers (1988) and "
                "Fiorotto & Rinaldo (1992b)", RECALLED),
    Coefficient("friction of concrete on sand f", (0.6,), "f = 0.6 (range 0.45–0.7)",
                "usual design range", RECALLED),
    Coefficient("Lane's weighted-creep ratios C_w", tuple(LANE_RATIOS.values()),
                "L_w = ΣL_v + ΣL_h/3 ≥ C_w ΔH, C_w = 8.5 (very fine sand) … 1.6 (very hard "
                "clay)", "Lane (1935), Trans. ASCE 100, as tabulated in two public codes",
                SEEN),
)


# --------------------------------------------------------------------------------- checks ---

def _num(v, item: str, *, positive: bool = False, nonnegative: bool = False) -> float:
    try:
        f = float(v)
    except (TypeError, ValueError):
        raise ModelError(item, f"must be a number, got {v!r}") from None
    if not math.isfinite(f):
        raise ModelError(item, f"must be finite, got {f}")
    if positive and f <= 0:
        raise ModelError(item, f"must be positive, got {f}")
    if nonnegative and f < 0:
        raise ModelError(item, f"must not be negative, got {f}")
    return f


def _arr(x, item: str) -> np.ndarray:
    try:
        a = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise ModelError(item, f"must be a number or an array of numbers, got {x!r}") from None
    if not np.all(np.isfinite(a)):
        raise ModelError(item, "contains NaN or inf")
    return a


# ---------------------------------------------------------------------------------- jump ---

def unit_discharge(h_kr: float, g: float = G) -> float:
    """Unit discharge q = √(g h_kr³) (m²/s) whose critical depth is ``h_kr`` (m).

    For the article's h_kr = 3.48 m: q = 20.33 m²/s.
    """
    h_kr = _num(h_kr, "h_kr", positive=True)
    g = _num(g, "g", positive=True)
    return math.sqrt(g * h_kr**3)


def contracted_depth(q: float, E0: float, phi: float = 0.95, g: float = G) -> float:
    """The contracted (supercritical) depth h1 (m) at the toe of the jump.

    The supercritical root of the energy equation with a velocity coefficient φ (losses on the
    spillway face):

    .. math::  E_0 = h_1 + \\frac{q^2}{2 g \\varphi^2 h_1^2}

    with ``q`` the unit discharge (m²/s) and ``E0`` the total energy head (m) above the apron
    (headwater level minus apron level plus the approach velocity head).  The right-hand side
    has its minimum 3/2·h_c at h_c = (q²/(g φ²))^(1/3); the root below h_c is found by
    ``brentq`` on [q/(φ√(2gE0)), h_c].  Raises :class:`~stepcontact.errors.ModelError`
    (naming ``E0``) when E0 < 3/2·h_c: the head cannot pass the discharge.
    """
    q = _num(q, "q", positive=True)
    E0 = _num(E0, "E0", positive=True)
    phi = _num(phi, "phi", positive=True)
    g = _num(g, "g", positive=True)
    if phi > 1:
        raise ModelError("phi", f"a velocity coefficient is at most 1, got {phi}")
    hc = (q * q / (g * phi * phi)) ** (1.0 / 3.0)
    e_min = 1.5 * hc
    if E0 < e_min * (1 - 1e-12):
        raise ModelError("E0", f"{E0} m is below the minimum specific energy 1.5·h_c = "
                         f"{e_min:.4g} m needed to pass q = {q:.4g} m²/s (phi = {phi})")
    if E0 <= e_min:
        return hc
    c = q * q / (2 * g * phi * phi)
    lo = q / (phi * math.sqrt(2 * g * E0))  # E(lo) = lo + E0 > E0

    def f(h: float) -> float:
        return h + c / (h * h) - E0

    return float(brentq(f, lo, hc, xtol=1e-14, rtol=1e-14, maxiter=200))


def conjugate_depth(h1: float, Fr1: float) -> float:
    """Bélanger's sequent depth h2 = h1 · ½ (√(1 + 8 Fr1²) − 1) (m) of a jump on a horizontal
    rectangular apron (momentum balance, no friction); ``h1`` in m, ``Fr1`` = V1/√(g h1)."""
    h1 = _num(h1, "h1", positive=True)
    Fr1 = _num(Fr1, "Fr1", positive=True)
    return h1 * 0.5 * (math.sqrt(1.0 + 8.0 * Fr1 * Fr1) - 1.0)


def jump_length(h1: float, h2: float, Fr1: float, formula: str = "usbr",
                coef: float = 6.0) -> float:
    """Length of the hydraulic jump (m) by one of several empirical formulas.

    ``formula``:

    * ``"usbr"`` (default) — L_j = 6.1 h2, USBR Engineering Monograph 25 (Peterka), the
      classical type-I jump for 4.5 < Fr1 < 13 [RECALLED coefficient; "≈ 6 y2 for 4 < Fr1 < 20"
      is SEEN in a textbook].  The default because it is the most widely used and the most
      conservative of the set for the slab length;
    * ``"russian"`` — L_j = ``coef`` · (h2 − h1), the (5–6)(h″ − h′) rule of Russian teaching
      practice [SEEN], ``coef`` = 6 by default;
    * ``"pavlovsky"`` — L_j = 2.5 (1.9 h2 − h1) [RECALLED];
    * ``"chertousov"`` — L_j = 10.3 h1 (Fr1 − 1)^0.81 [RECALLED];
    * ``"hager"`` — the *roller* length L_r = h1 (−12 + 160 tanh(Fr1/20)) (Hager 1990)
      [RECALLED]; the roller is shorter than the jump.

    The formulas differ by up to ≈ 35 %.  An unknown formula raises a ModelError listing the
    known ones.
    """
    h1 = _num(h1, "h1", positive=True)
    h2 = _num(h2, "h2", positive=True)
    Fr1 = _num(Fr1, "Fr1", positive=True)
    key = str(formula).strip().lower()
    if key == "usbr":
        return 6.1 * h2
    if key == "russian":
        return _num(coef, "coef", positive=True) * (h2 - h1)
    if key == "pavlovsky":
        return 2.5 * (1.9 * h2 - h1)
    if key == "chertousov":
        if Fr1 <= 1:
            raise ModelError("Fr1", f"Chertousov's formula needs a supercritical inflow "
                             f"(Fr1 > 1), got {Fr1}")
        return 10.3 * h1 * (Fr1 - 1.0) ** 0.81
    if key == "hager":
        L_r = h1 * (-12.0 + 160.0 * math.tanh(Fr1 / 20.0))
        if L_r <= 0:
            raise ModelError("Fr1", f"Hager's roller length is not positive for Fr1 = {Fr1} "
                             "(the fit is for developed jumps, Fr1 > 2)")
        return L_r
    raise ModelError("formula", f"unknown jump-length formula {formula!r} (known: "
                     f"{', '.join(JUMP_LENGTH_FORMULAS)})")


@dataclass(frozen=True)
class Jump:
    """A free hydraulic jump on a horizontal apron (build it with :func:`hydraulic_jump`).

    Attributes (SI)
    ---------------
    h_kr : critical depth of the unit discharge, m
    q : unit discharge, m²/s
    E0 : total energy head above the apron, m
    phi : velocity coefficient of the inflow
    h1 : contracted (supercritical) depth at the toe, m
    V1 : inflow velocity q/h1, m/s
    Fr1 : inflow Froude number V1/√(g h1)
    h2 : Bélanger's sequent (tailwater) depth, m
    L_j : jump length, m, by ``formula``
    formula : the jump-length formula (see :func:`jump_length`) or ``"given"``
    g : gravitational acceleration, m/s²
    rho_w : density of water, kg/m³
    """

    h_kr: float
    q: float
    E0: float
    phi: float
    h1: float
    V1: float
    Fr1: float
    h2: float
    L_j: float
    formula: str
    g: float = G
    rho_w: float = RHO_W

    @property
    def velocity_head(self) -> float:
        """V1²/(2g), m: the scale of the pressure fluctuations (C_p = Δp/(ρ V1²/2))."""
        return self.V1**2 / (2.0 * self.g)

    @property
    def gamma_w(self) -> float:
        """Unit weight of water ρ_w g, N/m³."""
        return self.rho_w * self.g

    @property
    def roller_length(self) -> float:
        """Hager's roller length L_r = h1 (−12 + 160 tanh(Fr1/20)), m [RECALLED]."""
        return jump_length(self.h1, self.h2, self.Fr1, "hager")

    def length(self, formula: str = "usbr", coef: float = 6.0) -> float:
        """The jump length (m) of this jump by another ``formula`` (see :func:`jump_length`)."""
        return jump_length(self.h1, self.h2, self.Fr1, formula, coef)


def hydraulic_jump(h_kr: float = 3.48, E0: float = 25.0, phi: float = 0.95,
                   length: str | float = "usbr", g: float = G, rho_w: float = RHO_W) -> Jump:
    """The jump below a spillway: q from ``h_kr`` (m), h1 from the energy head ``E0`` (m) with
    velocity coefficient ``phi``, V1 = q/h1, Fr1 = V1/√(g h1), h2 by Bélanger and the jump
    length by the formula ``length`` (a name for :func:`jump_length`, default USBR 6.1 h2) or
    given directly as a number (m).

    The defaults are the article's h_kr = 3.48 m and E0 = 25 m (the middle case of the
    VOLGA-REF table: h1 ≈ 0.99 m, V1 ≈ 20.6 m/s, Fr1 ≈ 6.63, h2 ≈ 8.77 m, L_j ≈ 53.5 m).
    """
    g = _num(g, "g", positive=True)
    rho_w = _num(rho_w, "rho_w", positive=True)
    q = unit_discharge(h_kr, g)
    h1 = contracted_depth(q, E0, phi, g)
    V1 = q / h1
    Fr1 = V1 / math.sqrt(g * h1)
    h2 = conjugate_depth(h1, Fr1)
    if isinstance(length, str):
        L_j, formula = jump_length(h1, h2, Fr1, length), length.strip().lower()
    else:
        L_j, formula = _num(length, "length", positive=True), "given"
    return Jump(float(h_kr), q, float(E0), float(phi), h1, V1, Fr1, h2, L_j, formula, g, rho_w)


def slab_length(jump: Jump, factor: float = 1.0) -> float:
    """Length of the basin slab L_p = ``factor`` · L_j (m).

    Russian teaching practice [SEEN]: factor 1–1.25 for a basin without baffles, 0.8–1 with
    baffle blocks.  Any positive factor is accepted.
    """
    return _num(factor, "factor", positive=True) * jump.L_j


# ------------------------------------------------------------------- pressure on the top ---

def mean_depth(jump: Jump, x, L_r: float | None = None) -> np.ndarray:
    """Mean water depth y(x) (m) over the apron, Hager's surface profile [RECALLED]:

    .. math::  \\frac{y - h_1}{h_2 - h_1} = \\tanh\\left(\\frac{1.5\\,x}{L_r}\\right)

    ``x`` (m, scalar or array) from the toe; L_r is Hager's roller length
    (:attr:`Jump.roller_length`) unless given.  y rises from h1 at the toe and tends to h2
    beyond the roller (y = h1 + 0.905 (h2 − h1) at x = L_r).  Upstream of the toe (x < 0) the
    depth is h1.
    """
    x = _arr(x, "x")
    L_r = jump.roller_length if L_r is None else _num(L_r, "L_r", positive=True)
    return jump.h1 + (jump.h2 - jump.h1) * np.tanh(1.5 * np.maximum(x, 0.0) / L_r)


def top_pressure(jump: Jump, x, L_r: float | None = None) -> np.ndarray:
    """Mean pressure on the slab's top ρ_w g y(x) (Pa): hydrostatic under the mean surface
    profile of :func:`mean_depth` (the mean bottom pressure of a jump is close to
    hydrostatic [RECALLED])."""
    return jump.gamma_w * mean_depth(jump, x, L_r)


def deficit_pressure(jump: Jump, x, L_r: float | None = None) -> np.ndarray:
    """The "deficit" ρ_w g (h2 − y(x)) (Pa) of the mean top pressure against the tailwater
    depth h2: the net static uplift when the tailwater pressure reaches the slab's base through
    the joints and drains (Alberta Transportation 2004 §12: the area between the tailwater
    level and the jump profile [SEEN])."""
    return jump.gamma_w * (jump.h2 - mean_depth(jump, x, L_r))


def triangular_deficit(jump: Jump, x, L_p: float, peak: float = 0.6,
                       extent: float = 2.0 / 3.0) -> np.ndarray:
    """Russian-practice "deficit pressure" diagram (Pa) [SEEN-partial: a teaching page with
    symbols partly stripped, reconstructed]:

    a triangle with the peak ``peak`` · (h2 − h1) · ρ_w g at the slab's upstream edge x = 0,
    falling linearly to zero at x = ``extent`` · L_p (2/3 of the slab length ``L_p``, m), and
    zero elsewhere.  Its force per metre run is W_d = ½ · 0.6 (h2 − h1) · (2/3) L_p · γ_w.
    """
    x = _arr(x, "x")
    L_p = _num(L_p, "L_p", positive=True)
    peak = _num(peak, "peak", nonnegative=True)
    extent = _num(extent, "extent", positive=True)
    a = extent * L_p
    p0 = peak * (jump.h2 - jump.h1) * jump.gamma_w
    return np.where((x >= 0) & (x <= a), p0 * (1.0 - x / a), 0.0)


# ------------------------------------------------------------------------ seepage uplift ---

def lane_creep_length(vertical=(), horizontal=()) -> float:
    """Lane's weighted creep length L_w = ΣL_v + ΣL_h / 3 (m).

    ``vertical``: lengths (m) of the creep path's vertical (and steeper than 45°) parts, e.g.
    cutoffs, both faces; ``horizontal``: lengths of its horizontal (flatter than 45°) parts.
    Each a number or a sequence of numbers ≥ 0.
    """
    v = _arr(vertical, "vertical")
    h = _arr(horizontal, "horizontal")
    if np.any(v < 0):
        raise ModelError("vertical", "creep lengths must not be negative")
    if np.any(h < 0):
        raise ModelError("horizontal", "creep lengths must not be negative")
    return float(np.sum(v) + np.sum(h) / 3.0)


def lane_uplift(x, H: float, L_w_upstream: float, L_w_total: float,
                x0: float = 0.0, horizontal_weight: float = 1.0 / 3.0) -> np.ndarray:
    """Residual seepage head h_s(x) (m of water above the tailwater) under a horizontal slab
    base, by linear head loss along Lane's weighted creep path [RECALLED design practice]:

    .. math::  h_s(x) = H \\left(1 - \\frac{L_{w,up} + (x - x_0)/3}{L_w}\\right)

    ``H``: head difference headwater − tailwater (m); ``L_w_upstream``: weighted creep length
    (m) from the upstream entry of the seepage to the slab's upstream edge at x = ``x0``;
    ``L_w_total``: the weighted length of the whole path to the exit (from
    :func:`lane_creep_length`).  Along the base the path is horizontal, weight
    ``horizontal_weight`` = 1/3.  The head is clipped to [0, H] (no negative residual head
    beyond the exit, none above the headwater before the entry).
    """
    x = _arr(x, "x")
    H = _num(H, "H", nonnegative=True)
    up = _num(L_w_upstream, "L_w_upstream", nonnegative=True)
    tot = _num(L_w_total, "L_w_total", positive=True)
    if up > tot:
        raise ModelError("L_w_upstream", f"{up} m exceeds the total weighted creep length "
                         f"L_w_total = {tot} m")
    w = _num(horizontal_weight, "horizontal_weight", positive=True)
    x0 = _num(x0, "x0")
    lw = up + w * (x - x0)
    return np.clip(H * (1.0 - lw / tot), 0.0, H)


def _soil_key(soil: str) -> str:
    return " ".join(str(soil).strip().lower().replace("_", " ").replace("-", " ").split())


def lane_check(L_w: float, H: float, soil: str) -> float:
    """Safety against piping by Lane's method: (L_w / H) / C_w, ≥ 1 is safe.

    ``L_w``: weighted creep length (m); ``H``: head difference (m); ``soil``: a key of
    :data:`LANE_RATIOS` (case, underscores and hyphens are ignored).  An unknown soil raises a
    ModelError listing the known ones.
    """
    L_w = _num(L_w, "L_w", nonnegative=True)
    H = _num(H, "H", positive=True)
    key = _soil_key(soil)
    if key not in LANE_RATIOS:
        raise ModelError("soil", f"unknown soil {soil!r} (known: {', '.join(LANE_RATIOS)})")
    return (L_w / H) / LANE_RATIOS[key]


def base_uplift(jump: Jump, x, tailwater: float | None = None, residual_head=0.0,
                thickness: float = 0.0) -> np.ndarray:
    """Uplift pressure on the slab's base ρ_w g (tailwater + thickness + residual_head) (Pa).

    ``tailwater``: tailwater depth over the slab's top (m), default the sequent depth h2 (the
    tailwater pressure reaches the base through the joints and drains); ``residual_head``: the
    residual seepage head (m), a number or an array broadcast against ``x`` (e.g. from
    :func:`lane_uplift`); ``thickness``: the slab thickness s (m).

    With ``thickness=0`` (default) the pressure is referred to the level of the slab's top,
    as :func:`top_pressure` is: the base uplift minus the top pressure is then the *net* uplift
    ρ_w g (h2 − y(x) + h_s), to be resisted by the **submerged** weight (γc − γw) s of the slab
    (the buoyancy γw s of its own thickness is in that weight).  Give the thickness for the
    full hydrostatic pressure on the base together with the full weight γc s.
    """
    x = _arr(x, "x")
    tw = jump.h2 if tailwater is None else _num(tailwater, "tailwater", nonnegative=True)
    s = _num(thickness, "thickness", nonnegative=True)
    hs = _arr(residual_head, "residual_head")
    try:
        return jump.gamma_w * (tw + s + hs + np.zeros_like(x))
    except ValueError:
        raise ModelError("residual_head", f"shape {hs.shape} does not match x of shape "
                         f"{x.shape}") from None


# ------------------------------------------------------------------ pressure fluctuations ---

def cp_rms(x_over_h1, peak: float = 0.08, x_peak: float = 10.0,
           shape: float = 0.5) -> np.ndarray:
    """Default rms pressure coefficient C′p = σ_p / (ρ V1²/2) along the jump [RECALLED shape].

    .. math::  C'_p(X) = C'_{max} \\left(\\frac{X}{X_m}\\right)^k
               \\exp\\left(k\\left(1 - \\frac{X}{X_m}\\right)\\right), \\quad X = x/h_1 \\ge 0

    with ``peak`` C′max = 0.08 at ``x_peak`` X_m = 10 and ``shape`` k = 0.5: a smooth shape
    that rises from 0 at the toe to its maximum 0.08 at x = 10 h1 and decays to ≈ 0.02 at
    x ≈ 54 h1 (the end of the jump for Fr1 ≈ 6.6: 6.1 h2/h1 ≈ 54) and ≈ 0.005 at 80 h1.  It is
    an analytic stand-in for the measured profiles (Toso & Bowers 1988, J. Hydraul. Eng.
    114(8) 829–843; Lopardo; maximum ≈ 0.05–0.10 at x ≈ 5–20 h1, ≈ 0.01–0.02 at the end of
    the jump), all [RECALLED]: check it against the data for the case at hand, or give your
    own profile through :func:`rms_profile`.  Zero upstream of the toe (X < 0).
    """
    X = _arr(x_over_h1, "x_over_h1")
    peak = _num(peak, "peak", nonnegative=True)
    x_peak = _num(x_peak, "x_peak", positive=True)
    shape = _num(shape, "shape", positive=True)
    r = np.maximum(X, 0.0) / x_peak
    return peak * r**shape * np.exp(shape * (1.0 - r))


def rms_profile(spec=None) -> Callable[[np.ndarray], np.ndarray]:
    """A C′p profile as a function of x/h1, from ``spec``:

    * ``None`` — the default :func:`cp_rms`;
    * a callable ``f(x_over_h1)`` — used as is (its result taken as an array);
    * a pair ``(x_over_h1, values)`` of tabulated arrays (x increasing) — linear between the
      points, the end values held beyond them.
    """
    if spec is None:
        return cp_rms
    if callable(spec):
        return lambda X: np.asarray(spec(X), dtype=float)
    try:
        xs, vs = spec
    except (TypeError, ValueError):
        raise ModelError("rms profile", "give None, a function of x/h1 or a pair "
                         "(x_over_h1, values) of arrays") from None
    xs, vs = _arr(xs, "rms profile x_over_h1"), _arr(vs, "rms profile values")
    if xs.ndim != 1 or xs.shape != vs.shape or len(xs) < 2:
        raise ModelError("rms profile", "give two 1-D arrays of the same length, at least two "
                         "points")
    if np.any(np.diff(xs) <= 0):
        raise ModelError("rms profile x_over_h1", "must increase")
    if np.any(vs < 0):
        raise ModelError("rms profile values", "an rms coefficient must not be negative")
    return lambda X: np.interp(_arr(X, "x_over_h1"), xs, vs)


def extreme_coefficients(x_over_h1, n_plus: float = 4.0, n_minus: float = 3.0,
                         profile=None) -> tuple[np.ndarray, np.ndarray]:
    """Extreme pressure coefficients (C⁺p, C⁻p) = (N⁺ C′p, N⁻ C′p), both ≥ 0.

    The extreme positive and negative deviations from the mean pressure in units of ρ V1²/2:
    p± = p̄ ± C±p ρ V1²/2.  Defaults N⁺ = 4, N⁻ = 3 (≈ the 99.9 %/0.1 % points of the skewed
    distribution [RECALLED]); point extremes grow with the record length (C±p ≈ 0.3–0.6 near
    the toe for long records [RECALLED]).  ``profile`` is a C′p spec for :func:`rms_profile`.
    """
    n_plus = _num(n_plus, "n_plus", nonnegative=True)
    n_minus = _num(n_minus, "n_minus", nonnegative=True)
    c = rms_profile(profile)(x_over_h1)
    return n_plus * c, n_minus * c


def impulse_amplitude(jump: Jump, fraction: float) -> float:
    """Pressure amplitude ``fraction`` · ρ_w g · V1²/(2g) = fraction · ρ_w V1²/2 (Pa) of a
    local pulsation impulse; §7 of the study suggests fractions 0.3–0.5 [DERIVED from the
    [RECALLED] extreme coefficients]."""
    return _num(fraction, "fraction") * jump.gamma_w * jump.velocity_head


# ------------------------------------------------------------------- design thicknesses ---

def fiorotto_rinaldo_thickness(V1: float, Omega: float, cp_plus: float, cp_minus: float,
                               gamma_c: float = GAMMA_C, gamma_w: float = GAMMA_W,
                               g: float = G) -> float:
    """Slab thickness (m) of Fiorotto & Rinaldo (1992a, J. Hydraul. Eng. 118(4) 578–596):

    .. math::  s = \\Omega\\,(C_p^+ + C_p^-)\\,\\frac{V_1^2}{2g}\\,
               \\frac{\\gamma_w}{\\gamma_c - \\gamma_w}

    the submerged weight balancing the worst net uplift: the extreme positive pressure
    transmitted under the slab through the joints against the extreme negative one on its top,
    reduced by Ω ≤ 1 for their non-simultaneity over the slab's area.  Formula structure
    certain; typical values Ω ≈ 0.1–0.25 for slabs a few h1 long and C±p ≈ 0.3–0.6 [RECALLED,
    low confidence].  ``V1`` in m/s, unit weights in N/m³.
    """
    V1 = _num(V1, "V1", nonnegative=True)
    Omega = _num(Omega, "Omega", nonnegative=True)
    cp_plus = _num(cp_plus, "cp_plus", nonnegative=True)
    cp_minus = _num(cp_minus, "cp_minus", nonnegative=True)
    gamma_c = _num(gamma_c, "gamma_c", positive=True)
    gamma_w = _num(gamma_w, "gamma_w", positive=True)
    g = _num(g, "g", positive=True)
    if gamma_c <= gamma_w:
        raise ModelError("gamma_c", f"the slab must be heavier than water: gamma_c = {gamma_c}"
                         f" ≤ gamma_w = {gamma_w}")
    return Omega * (cp_plus + cp_minus) * V1**2 / (2 * g) * gamma_w / (gamma_c - gamma_w)


def usace_flotation_factor(W_s: float, W_c: float, S: float, U: float, W_G: float) -> float:
    """Flotation safety factor of USACE ETL 1110-2-307 (1987) [formula SEEN]:

    .. math::  SF_f = \\frac{W_s + W_c + S}{U - W_G}

    ``W_s``: weight of the structure (with the soil above it), ``W_c``: weight of water
    contained in it under the operator's control, ``S``: surcharge, ``U``: uplift force,
    ``W_G``: weight of the water above the structure [RECALLED] — all forces in N (or N/m per
    metre run, consistently).  Compare with :data:`USACE_FLOTATION_REQUIRED` (1.3 usual,
    1.2 unusual, 1.1 extreme [RECALLED]).  Returns ``inf`` when U ≤ W_G (no net uplift).
    """
    num = (_num(W_s, "W_s", nonnegative=True) + _num(W_c, "W_c", nonnegative=True)
           + _num(S, "S", nonnegative=True))
    den = _num(U, "U", nonnegative=True) - _num(W_G, "W_G", nonnegative=True)
    return math.inf if den <= 0 else num / den


def dombrovsky_thickness(V1: float, h1: float) -> float:
    """Dombrovsky's empirical slab thickness t = 0.15 V1 √h1 (m; V1 in m/s, h1 in m), a
    Russian rule for low and medium-head basins [RECALLED]."""
    return 0.15 * _num(V1, "V1", nonnegative=True) * math.sqrt(_num(h1, "h1",
                                                                      nonnegative=True))


def kern_liftoff_thickness(q0: float, a: float, L: float, q1: float = 0.0,
                           gamma_c: float = GAMMA_C, gamma_w: float = GAMMA_W,
                           edge: str = "upstream") -> float:
    """Thickness s (m) at which the upstream edge of a rigid slab on a Winkler bed lifts off.

    A rigid slab of length ``L`` (m; per metre of width) carries its submerged weight
    w = (γc − γw) s (N/m², downward, uniform: the hydrostatic part of the pressures on its top
    and base is its buoyancy γw s) and an upward net pressure q(x) (Pa: the part of the uplift
    beyond hydrostatic, e.g. a deficit) linear on [0, a], from ``q0`` at the upstream
    edge x = 0 to ``q1`` at x = ``a`` (0 < a ≤ L), zero beyond: a triangle (q1 = 0, e.g.
    :func:`triangular_deficit`) or a trapezoid.  On a Winkler bed the base pressure of a rigid
    slab is linear while it is in full contact:

    .. math::  p(x) = \\frac{R}{L} + \\frac{12 M}{L^3}\\left(x - \\frac{L}{2}\\right)

    with R the net downward resultant and M its moment about the slab's centre (positive
    downstream).  Writing ξ = a/L, the triangle q0(1 − x/a) gives R = wL − q0 a/2 and
    M = (q0 a/2)(L/2 − a/3), the triangle q1 x/a gives R = −q1 a/2 and M = (q1 a/2)(L/2 − 2a/3),
    so that

    .. math::  p(0) = w - q_0\\,\\xi(2 - \\xi) - 2 q_1\\,\\xi(1 - \\xi)

    and p(0) = 0 (the resultant at the downstream edge of the kern, e = L/6) gives

    .. math::  s = \\frac{q_0\\,\\xi(2 - \\xi) + 2 q_1\\,\\xi(1 - \\xi)}{\\gamma_c - \\gamma_w}

    independent of the bed modulus.  For the Russian triangular deficit (q1 = 0, ξ = 2/3)
    s = (8/9) q0/(γc − γw) = 0.889 · h_d / (γc/γw − 1) with h_d = q0/γw the peak in m of water:
    for E0 = 25 m (h_d = 0.6 (h2 − h1) = 4.67 m, γc/γw = 2.4) s = 2.96 m, as the study notes
    state (they write the peak head h_d as "a"; here ``a`` is the loaded length).  A thicker
    slab stays in full contact.  The criterion is stricter than flotation of the whole slab
    (R = 0: s = (q0 + q1) ξ / (2 (γc − γw)), 1.11 m for that case) and than overturning about
    the downstream edge (1.73 m).

    ``edge="downstream"``: the thickness below which the *downstream* edge lifts off instead,
    from p(L) = w + q0 ξ(1 − ξ) + q1 ξ(1 − 2ξ) = 0, i.e.
    s = (q1 ξ(2ξ − 1) − q0 ξ(1 − ξ))/(γc − γw), 0 when negative (the net load alone never lifts
    it: always so for a triangle, q1 = 0).  The slab stays in full contact for s above the
    larger of the two.
    """
    q0 = _num(q0, "q0", nonnegative=True)
    q1 = _num(q1, "q1", nonnegative=True)
    a = _num(a, "a", positive=True)
    L = _num(L, "L", positive=True)
    if a > L * (1 + 1e-12):
        raise ModelError("a", f"the loaded length {a} m exceeds the slab length L = {L} m")
    gamma_c = _num(gamma_c, "gamma_c", positive=True)
    gamma_w = _num(gamma_w, "gamma_w", positive=True)
    if gamma_c <= gamma_w:
        raise ModelError("gamma_c", f"the slab must be heavier than water: gamma_c = {gamma_c}"
                         f" ≤ gamma_w = {gamma_w}")
    xi = min(a / L, 1.0)
    if edge == "upstream":
        w = q0 * xi * (2.0 - xi) + 2.0 * q1 * xi * (1.0 - xi)
    elif edge == "downstream":
        w = max(q1 * xi * (2.0 * xi - 1.0) - q0 * xi * (1.0 - xi), 0.0)
    else:
        raise ModelError("edge", f"unknown edge {edge!r} (known: upstream, downstream)")
    return w / (gamma_c - gamma_w)


__all__ = [
    "CHECKED", "COEFFICIENTS", "RECALLED", "SEEN", "Coefficient",
    "G", "GAMMA_C", "GAMMA_W", "JUMP_LENGTH_FORMULAS", "LANE_RATIOS", "RHO_W",
    "USACE_FLOTATION_REQUIRED", "Jump", "base_uplift", "conjugate_depth", "contracted_depth",
    "cp_rms", "deficit_pressure", "dombrovsky_thickness", "extreme_coefficients",
    "fiorotto_rinaldo_thickness", "hydraulic_jump", "impulse_amplitude", "jump_length",
    "kern_liftoff_thickness", "lane_check", "lane_creep_length", "lane_uplift", "mean_depth",
    "rms_profile", "slab_length", "top_pressure", "triangular_deficit", "unit_discharge",
    "usace_flotation_factor",
]
