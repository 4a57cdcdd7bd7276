"""The stilling-basin slab (apron) on its foundation: the application of the article
(method.md §7, Figs. 4–5) as a ready-made, parametric study.

A slab of length L_p and thickness h (concrete) rests on a soil foundation (an elastic
rectangle with its own, non-matching mesh, or a rigid base) through a frictional joint of
mortar CFEs, optionally with a compliant (Winkler-like) layer of eq. (11).  Loads, in this
order:

1. ``weight``: the slab's self-weight (the foundation's own weight is not applied: it loads only
   the foundation, whose initial stress does not enter the joint);
2. ``top`` and ``uplift`` together (one non-proportional segment): the mean pressure of the flow
   on the slab's top (Pa; e.g. hydrostatic under the jump's mean profile,
   :func:`stepcontact.study.hydraulics.top_pressure`) and the pressure in the joint under it
   (Pa; tailwater and seepage head, :func:`stepcontact.study.hydraulics.base_uplift`), which
   acts on both faces of the joint (:class:`~stepcontact.model.Uplift`) whether the joint is
   closed or open: where the contact opens, the gap holds that pressure (the "uplift pressure
   through the joints" choice of the study);
3. optionally the pulsating part of the flow's pressure as a dynamic impulse (:class:`Impulse`):
   a pressure over a footprint of the slab, down on its top or up under it (through the
   joints: on both faces of the joint), with a time shape, from the static state of 1–2
   (:func:`stepcontact.solve_dynamic`).

Criterion (:func:`check`): the slab neither lifts off nor slides, over the static loading and
the whole dynamic response.  *Lifts off*: with ``criterion="opening"`` (the default, the
article's) any CFE of the joint opens; with ``criterion="separation"`` the whole joint opens at
once (the slab floats).  *Slides*: the static run loses equilibrium while in contact, or, in
the response, every closed CFE of the joint slips the same way at once (the slab moves as a
body); with ``no_slip=True`` any slip fails.  The limit thickness (:func:`limit_thickness`) is
the smallest h that meets the criterion, bracketed and bisected to a tolerance.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from stepcontact.enums import Status
from stepcontact.errors import ModelError, SolverError
from stepcontact.model import (
    BodyForce,
    ContactLayer,
    CrackWater,
    EdgeLoad,
    Interface,
    LoadPattern,
    Material,
    Model,
    RigidObstacle,
    Segment,
    Support,
    Uplift,
    rectangle,
)
from stepcontact.model.timefunction import PULSE_SHAPES, Pulse

#: unit weight of water, N/m³
GAMMA_W = 9810.0
#: the name of the slab's joint with its foundation
JOINT = "base"
CRITERIA = ("opening", "separation")
DIRECTIONS = ("up", "down")

Pressure = float | tuple[float, float] | Callable[[np.ndarray], np.ndarray]


def _pressure(spec: Pressure, length: float, item: str) -> Callable:
    """p(x, y) in Pa from a constant, a pair (p at x = 0, p at x = L_p) or a function p(x)
    of the distance x (m) from the slab's upstream edge."""
    if callable(spec):
        def fun(x, y, _f=spec):
            return np.asarray(_f(np.asarray(x, float)), float) * np.ones(np.shape(x))
        return fun
    if isinstance(spec, tuple | list) and len(spec) == 2:
        a, b = (float(v) for v in spec)
        return lambda x, y: a + (b - a) * np.asarray(x, float) / length
    try:
        v = float(spec)
    except (TypeError, ValueError):
        raise ModelError(item, "give a pressure in Pa: a number, a pair (upstream, downstream) "
                         "or a function p(x) of the distance from the upstream edge") from None
    if not np.isfinite(v):
        raise ModelError(item, f"must be finite, got {v}")
    return lambda x, y: np.full(np.shape(x), v)


#: the pressures in the opened joint a slab study can take (:class:`Slab`)
GAP_PRESSURES = ("uplift", "joint")


def _gap_water(slab: Slab, p: Callable) -> list:
    """With ``gap_pressure="joint"``: the pressure ``p`` (Pa per unit factor) at the upstream
    joint (x = 0) in the gap opened from there (a :class:`CrackWater` entering at the
    slab's upstream edge); none otherwise."""
    if slab.gap_pressure != "joint":
        return []
    at = float(np.asarray(p(np.zeros(1), np.zeros(1)), float).reshape(-1)[0])
    return [CrackWater(JOINT, pressure=at, entry=(0.0, 0.0))]


def _uplift(slab: Slab) -> Callable:
    """The pressure in the joint at the slab's base, Pa: ``slab.uplift`` (referred to the
    top's level) plus γ_w h with buoyancy."""
    f = _pressure(slab.uplift, slab.length, "slab.uplift")
    if not slab.buoyancy:
        return f
    extra = GAMMA_W * slab.thickness
    return lambda x, y: f(x, y) + extra


@dataclass(frozen=True)
class Impulse:
    """The pulsating part of the flow pressure as an impulse (SI).

    ``amplitude`` (Pa) acts over a ``footprint`` (m) of the slab centred at ``position``·L_p
    from its upstream edge, ``direction`` "down" on the slab's top or "up" under it (in the
    joint, on both faces), with a time ``shape`` ("half_sine", "triangular", "rectangular") of
    ``duration`` s starting ``start`` s into the response."""

    position: float
    amplitude: float
    duration: float
    footprint: float = 5.0
    direction: str = "up"
    shape: str = "half_sine"
    start: float = 0.0

    def __post_init__(self):
        if not 0.0 <= self.position <= 1.0:
            raise ModelError("impulse.position", f"is x/L_p, in [0, 1]; got {self.position}")
        for key in ("amplitude", "duration", "footprint"):
            v = getattr(self, key)
            if not (np.isfinite(v) and v > 0):
                raise ModelError(f"impulse.{key}", f"must be positive, got {v}")
        if self.direction not in DIRECTIONS:
            raise ModelError("impulse.direction", f"'{self.direction}' is not one of "
                             f"{', '.join(DIRECTIONS)}")
        if self.shape not in PULSE_SHAPES:
            raise ModelError("impulse.shape", f"'{self.shape}' is not one of "
                             f"{', '.join(PULSE_SHAPES)}")
        if not (np.isfinite(self.start) and self.start >= 0):
            raise ModelError("impulse.start", f"must be ≥ 0, got {self.start}")

    def pressure(self, length: float) -> Callable:
        """The footprint's pressure per unit factor, p(x, y) (1 inside, 0 outside)."""
        c, half = self.position * length, 0.5 * self.footprint
        return lambda x, y: ((np.asarray(x) >= c - half - 1e-9)
                             & (np.asarray(x) <= c + half + 1e-9)).astype(float)

    def time_function(self) -> Pulse:
        return Pulse(self.amplitude, self.start, self.duration, self.shape)


@dataclass(frozen=True)
class Slab:
    """The slab, its foundation and the static loads of the study (SI units).

    ``length``, ``thickness``: L_p and h, m.  ``concrete``, ``soil``: materials (Pa, kg/m³);
    ``soil=None`` puts the slab on a rigid base (with a ``layer``: a Winkler foundation).
    ``soil_depth`` and ``soil_margin`` (m): the foundation's depth and its extent beyond each
    end of the slab (default L_p/2 each).  ``friction``: f of the joint; ``layer``: its
    compliant layer (eq. (11)), None for rigid contact.  ``top``, ``uplift``: the mean
    pressure on the top and in the joint, Pa (a number, a pair (upstream, downstream), or a
    function of the distance x from the upstream edge).  ``cells``: the slab's mesh (along,
    through); the foundation's cells are ``soil_ratio`` times the slab's (non-matching
    meshes; the mortar CFEs sit on the coarser of the two faces whichever is S+, see the
    user guide).
    ``water_depth``: depth of water above the slab taken as added mass (m; 0: none).

    The slab's top stays at its level as the thickness changes (the basin's floor is set by
    the hydraulics; a thicker slab reaches deeper), so ``uplift`` is the pressure in the joint
    referred to the top's level, and with ``buoyancy`` (default) the model adds γ_w h, the
    hydrostatic increase across the slab: the net uplift against the submerged weight
    (γ_c − γ_w) h is then ``uplift − top``.

    ``end_joints`` (a friction coefficient, or None: none): the joints at the slab's ends,
    against the neighbouring slabs (or the basin's walls) taken as rigid — interfaces
    ``upstream`` and ``downstream`` with that friction, closed at zero gap, which hold the
    slab's ends horizontally and resist their vertical slip by friction.

    ``gap_pressure``: the pressure in the joint where it has opened.  ``"uplift"`` (default):
    the joint's uplift, which acts on the base whether the joint is open or not.
    ``"joint"``: the pressure that reaches the gap through the upstream joint (at x = 0) —
    where the contact has opened in a run from the upstream edge, the pressure at that joint
    (the mean uplift there, plus the impulse's pressure at x = 0 while it acts) replaces the
    uplift, as a load that follows the opened length event by event
    (:class:`~stepcontact.model.CrackWater` with an entry point, in statics and in the dynamic
    interval): the mechanism of slab failure of Fiorotto & Rinaldo (1992).
    """

    length: float = 40.0
    thickness: float = 2.0
    concrete: Material = field(default_factory=lambda: Material(30e9, 0.2, 2400.0))
    soil: Material | None = field(default_factory=lambda: Material(200e6, 0.3, 2000.0))
    soil_depth: float | None = None
    soil_margin: float | None = None
    friction: float = 0.6
    layer: ContactLayer | None = None
    top: Pressure = 0.0
    uplift: Pressure = 0.0
    cells: tuple[int, int] = (40, 4)
    soil_ratio: float = 0.6
    water_depth: float = 0.0
    buoyancy: bool = True
    end_joints: float | None = None
    gap_pressure: str = "uplift"

    def __post_init__(self):
        for key in ("length", "thickness"):
            v = getattr(self, key)
            if not (np.isfinite(v) and v > 0):
                raise ModelError(f"slab.{key}", f"must be positive (m), got {v}")
        if self.friction < 0 or not np.isfinite(self.friction):
            raise ModelError("slab.friction", f"must be ≥ 0, got {self.friction}")
        if self.concrete.density <= 0:
            raise ModelError("slab.concrete.density", "the slab needs a density (its weight)")
        if len(self.cells) != 2 or min(self.cells) < 1:
            raise ModelError("slab.cells", f"give (along, through) ≥ 1, got {self.cells}")
        if self.end_joints is not None and not (np.isfinite(self.end_joints)
                                                and self.end_joints >= 0):
            raise ModelError("slab.end_joints", f"is a friction coefficient ≥ 0 (or None), "
                             f"got {self.end_joints}")
        if self.gap_pressure not in GAP_PRESSURES:
            raise ModelError("slab.gap_pressure", f"'{self.gap_pressure}' is not one of "
                             f"{', '.join(map(repr, GAP_PRESSURES))}")
        if self.water_depth < 0:
            raise ModelError("slab.water_depth", f"must be ≥ 0, got {self.water_depth}")
        _pressure(self.top, self.length, "slab.top")
        _pressure(self.uplift, self.length, "slab.uplift")

    def with_thickness(self, h: float) -> Slab:
        return dataclasses.replace(self, thickness=float(h))

    @property
    def net_unit_weight(self) -> float:
        """γ_c − γ_w, N/m³: the submerged unit weight of the slab."""
        return self.concrete.density * 9.81 - GAMMA_W


def slab_model(slab: Slab, impulse: Impulse | None = None) -> Model:
    """The model of ``slab``: bodies ``slab`` (and ``soil``), the joint ``base``, patterns
    ``weight``, ``top``, ``uplift`` (and ``impulse``, 1 Pa per unit factor over the footprint),
    and the static program weight → top + uplift."""
    L, h = slab.length, slab.thickness
    nx, ny = slab.cells
    body = rectangle("slab", (0.0, 0.0), (L, h), nx, ny, slab.concrete)
    bodies: list = [body]
    items: list = []
    if slab.soil is not None:
        depth = L / 2 if slab.soil_depth is None else float(slab.soil_depth)
        margin = L / 2 if slab.soil_margin is None else float(slab.soil_margin)
        size = slab.soil_ratio * L / nx
        sx = max(2, int(round((L + 2 * margin) / size)))
        sy = max(2, int(round(depth / size)))
        bodies.insert(0, rectangle("soil", (-margin, -depth), (L + margin, 0.0), sx, sy,
                                   slab.soil))
    m = Model(bodies=bodies, name=f"slab L={L:g} h={h:g}")
    bottom = m.select("slab", y=0.0)
    if slab.soil is not None:
        minus = m.select("soil", where=lambda x, y: np.abs(y) < 1e-9)
        items += [Support("bed", m.select("soil", y=-depth), "xy"),
                  Support("sides", m.select("soil", where=lambda x, y: (
                      np.abs(x + margin) < 1e-9) | (np.abs(x - L - margin) < 1e-9)), "x")]
    else:
        minus = RigidObstacle("ground", [(-0.5 * L, 0.0), (1.5 * L, 0.0)])
    joint = Interface(JOINT, plus=bottom, minus=minus, friction=slab.friction,
                      layer=slab.layer)
    top = m.select("slab", y=h)
    if slab.end_joints is not None:  # the neighbours as rigid walls, bodies between them
        for name, x, side in (("upstream", 0.0, "right"), ("downstream", L, "left")):
            wall = RigidObstacle(f"{name} neighbour", [(x, -h), (x, 2 * h)], side=side)
            items.append(Interface(name, plus=m.select("slab", x=x), minus=wall,
                                   friction=float(slab.end_joints)))
    items += [
        joint,
        LoadPattern("weight", [BodyForce(bodies=("slab",))]),
        LoadPattern("top", [EdgeLoad(top, normal=_pressure(slab.top, L, "slab.top"))]),
        LoadPattern("uplift", [Uplift(JOINT, pressure=_uplift(slab), through="cfes")]
                    + _gap_water(slab, _uplift(slab))),
    ]
    if impulse is not None:
        f = impulse.pressure(L)
        load = (Uplift(JOINT, pressure=f, through="cfes") if impulse.direction == "up"
                else EdgeLoad(top, normal=f))
        items.append(LoadPattern("impulse", [load] + _gap_water(slab, f)))
    items += [Segment("weight", 1.0),
              Segment("hydraulic", 1.0, rates={"top": 1.0, "uplift": 1.0})]
    return m.add(*items)


@dataclass
class Outcome:
    """The criterion for one slab and load case.

    ``passes``: neither lifted nor slid.  ``lifted``, ``slid``: what failed, and ``when``: the
    load parameter (static: the segment's factor) or time (s) of the first failure, ``phase``
    "static" or "dynamic".  ``result`` holds the run (the dynamic one if any)."""

    thickness: float
    passes: bool
    lifted: bool
    slid: bool
    phase: str = ""
    when: float | None = None
    status: str = ""
    events: int = 0
    result: object = field(default=None, repr=False)


def _joint_cfes(res) -> np.ndarray:
    names = list(res.interface_names)
    return np.flatnonzero(res.cfe["interface"] == names.index(JOINT))


def _judge(res, criterion: str, no_slip: bool) -> tuple[bool, bool, float | None]:
    """(lifted, slid, parameter of the first failure) of a run."""
    from stepcontact.contact.laws import OPEN, SLIP_NEG, SLIP_POS

    k = _joint_cfes(res)
    st = np.asarray(res.state)[:, k]
    lam = np.asarray(res.lam)
    if criterion == "opening":
        bad_lift = np.any(st == OPEN, axis=1)
    else:
        bad_lift = np.all(st == OPEN, axis=1)
    closed = st != OPEN
    pos, neg = (st == SLIP_POS), (st == SLIP_NEG)
    if no_slip:
        bad_slide = np.any(pos | neg, axis=1)
    else:  # every closed CFE slips the same way: the slab slides as a body
        bad_slide = closed.any(axis=1) & ((pos == closed).all(axis=1)
                                          | (neg == closed).all(axis=1))
    lost = res.status == Status.EQUILIBRIUM_LOST
    if res.status not in (Status.COMPLETED, Status.EQUILIBRIUM_LOST):
        raise SolverError(f"the run of the slab {res.message or res.status}: no answer to "
                          "judge (see the result's status)")
    if lost:
        last = st[-1]
        if np.all(last == OPEN) or criterion == "opening" and np.any(last == OPEN):
            bad_lift[-1] = True
        else:
            bad_slide[-1] = True
    lifted, slid = bool(bad_lift.any()), bool(bad_slide.any())
    first = [lam[np.argmax(b)] for b in (bad_lift, bad_slide) if b.any()]
    return lifted, slid, (float(min(first)) if first else None)


def _added_mass(system, slab: Slab):
    """The lumped mass of the bodies plus the water above the slab (ρ_w · depth per unit
    area of the top, on the vertical DOFs of the top's nodes), kg."""
    import scipy.sparse as sp

    from stepcontact.fem.mass import mass

    model = system.model
    M = mass(model, system.dofs, lumped=True)
    if slab.water_depth <= 0:
        return M
    top = model.global_nodes(model.select("slab", y=slab.thickness))
    x = model.points[top, 0]
    order = np.argsort(x)
    xs = x[order]
    trib = np.zeros(len(xs))
    seg = np.diff(xs)
    trib[:-1] += seg / 2
    trib[1:] += seg / 2
    extra = np.zeros(system.ndof)
    dof = system.dofs.of[top[order], 1]
    extra[dof] = 1000.0 * slab.water_depth * trib * model.thickness
    return (M + sp.diags(extra)).tocsr()


def check(slab: Slab, impulse: Impulse | None = None, *, criterion: str = "opening",
          no_slip: bool = False, dt: float | None = None, duration: float | None = None,
          alpha: float = 0.05, keep: bool = False) -> Outcome:
    """Run ``slab`` (static loads, then ``impulse`` if given) and judge the criterion.

    ``dt`` (s, default duration/200) and ``duration`` (s, default: the impulse's start plus
    twice its duration) of the response; HHT ``alpha`` damps the mesh's spurious high modes.
    ``keep``: return the results in the outcome."""
    from stepcontact.solver.program import solve_dynamic
    from stepcontact.solver.static import solve_static

    if criterion not in CRITERIA:
        raise ModelError("criterion", f"'{criterion}' is not one of {', '.join(CRITERIA)}")
    from stepcontact.fem.assembly import assemble

    system = assemble(slab_model(slab, impulse))  # once, for the static and dynamic runs
    static = solve_static(system)
    lifted, slid, when = _judge(static, criterion, no_slip)
    out = Outcome(slab.thickness, not (lifted or slid), lifted, slid, "static", when,
                  str(static.status), len(static.events), static if keep else None)
    if not out.passes or impulse is None:
        return out
    T = impulse.start + 2.0 * impulse.duration if duration is None else float(duration)
    step = T / 200.0 if dt is None else float(dt)
    res = solve_dynamic(system, dt=step, duration=T, initial=static,
                        mass=_added_mass(system, slab), alpha=alpha,
                        loads={"impulse": impulse.time_function()})
    lifted, slid, when = _judge(res, criterion, no_slip)
    return Outcome(slab.thickness, not (lifted or slid), lifted, slid,
                   "dynamic" if (lifted or slid) else "", when, str(res.status),
                   len(res.events), res if keep else None)


@dataclass
class Limit:
    """The limit thickness: the smallest h (m) that passes, within ``tol``, with the bracket
    (``failing`` < h ≤ ``passing``) and every outcome computed (``trials``)."""

    thickness: float
    failing: float
    passing: float
    trials: list[Outcome]

    def __repr__(self) -> str:
        return (f"Limit(thickness={self.thickness:.4g} m, bracket=({self.failing:.4g}, "
                f"{self.passing:.4g}], {len(self.trials)} runs)")


def limit_thickness(slab: Slab, impulse: Impulse | None = None, *, tol: float = 0.01,
                    h0: float | None = None, h_max: float = 50.0, step: float | None = None,
                    progress: Callable[[Outcome], None] | None = None, **kwargs) -> Limit:
    """The smallest slab thickness (m) that meets the criterion (:func:`check`; ``kwargs``
    pass to it), by bracketing from ``h0`` (default: the slab's thickness) and bisection to
    ``tol`` m.  Assumes a thicker slab is safer (heavier); a slab that still fails at
    ``h_max`` is a :class:`ModelError`.

    The bracket halves or doubles the trial thickness; with ``step`` (m) it moves from ``h0``
    by ``step``, 2 ``step``, 4 ``step``, … instead — for a search that starts near the
    answer (e.g. from another mesh's limit): a limit within ``step`` of ``h0`` then costs two
    trials (and the bisection)."""
    if not (tol > 0):
        raise ModelError("tol", f"must be positive (m), got {tol}")
    if step is not None and not (np.isfinite(step) and step > 0):
        raise ModelError("step", f"must be positive (m), got {step}")
    trials: list[Outcome] = []
    moves = [0]  # bracket moves so far

    def down(h: float) -> float:
        if step is None:
            return h / 2.0
        moves[0] += 1
        return max(h - step * 2.0 ** (moves[0] - 1), h / 2.0)

    def up(h: float) -> float:
        if step is None:
            return 2.0 * h
        moves[0] += 1
        return h + step * 2.0 ** (moves[0] - 1)

    def run(h: float) -> bool:
        o = check(slab.with_thickness(h), impulse, **kwargs)
        trials.append(o)
        if progress is not None:
            progress(o)
        return o.passes

    h = float(slab.thickness if h0 is None else h0)
    if run(h):
        passing, failing = h, None
        while failing is None:
            h = down(h)
            if h < tol:
                return Limit(passing if passing <= tol else tol, 0.0, passing, trials)
            if run(h):
                passing = h
            else:
                failing = h
    else:
        failing, passing = h, None
        while passing is None:
            h = up(h)
            if h > h_max:
                raise ModelError("h_max", f"the slab still fails at {failing:g} m "
                                 f"(limit {h_max:g} m): no thickness up to it passes")
            if run(h):
                passing = h
            else:
                failing = h
    while passing - failing > tol:
        mid = 0.5 * (passing + failing)
        if run(mid):
            passing = mid
        else:
            failing = mid
    return Limit(passing, failing, passing, trials)


def cases(positions: Sequence[float], directions: Sequence[str] = DIRECTIONS,
          durations: Sequence[float] = (0.1,), **impulse) -> list[Impulse]:
    """The impulse cases of a study: every position × direction × duration (``impulse``:
    the other fields of :class:`Impulse`, e.g. amplitude and footprint)."""
    return [Impulse(position=p, direction=d, duration=t, **impulse)
            for d in directions for t in durations for p in positions]


__all__ = ["CRITERIA", "DIRECTIONS", "GAMMA_W", "GAP_PRESSURES", "JOINT", "Impulse", "Limit",
           "Outcome", "Slab", "cases", "check", "limit_thickness", "slab_model"]
