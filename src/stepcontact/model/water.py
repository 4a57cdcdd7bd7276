"""Water loads: hydrostatic pressure on a face, uplift in a joint, pressures given by coordinates.

All three follow the geometry (the coordinates of the points), never the order of the nodes in
a node set, so reversing a gmsh curve changes nothing.

* :class:`WaterLoad` — hydrostatic pressure p = γ_w · max(h_w − y, 0) (Pa) on the boundary
  edges of a node set, pushing into the body, with the free surface at y = h_w (``level``, m)
  and γ_w the unit weight of water (N/m³).
* :class:`Uplift` — a pore pressure in a joint: the same pressure pushes the S+ body and the
  S− body apart (equal and opposite resultants when the two faces coincide).  Given as a
  pressure head (m of water) or a pressure (Pa): a constant, a :class:`LinearProfile` by
  coordinates (e.g. from the heel head to the toe head, or through a drainage line) or a
  function of (x, y).
* :meth:`Uplift.drained` — the guidelines' bilinear uplift with a line of drains (full head at
  the heel, the drained head at the drain line, the tailwater's at the toe; :class:`Drains`).
* :class:`CrackWater` — water in the opened part of a joint (the crack), with the rule for the
  uplift beyond the crack's tip (``rule``) and the crack's connection to the reservoir
  (``bridge``).
* :class:`LinearProfile` — a value varying linearly between points given by coordinates, for
  :class:`~stepcontact.model.EdgeLoad` pressures too (``EdgeLoad(nodes, normal=profile)``).

The edge integration is that of :class:`~stepcontact.model.EdgeLoad` (consistent nodal
forces); where the pressure has a kink inside an element edge (the water level, a point of a
profile) the edge is split there, so the nodal forces are exact for straight edges:
resultant γ_w d²/2 and line of action at d/3 above the bottom of a vertical face of depth d.

Example
-------
>>> import stepcontact as sc
>>> rock = sc.Material(E=10e9, nu=0.25, density=2600)
>>> dam = sc.rectangle("dam", (0, 0), (8, 10), 4, 5, rock)
>>> m = sc.Model(bodies=[dam])
>>> face = m.select("dam", x=0.0)
>>> water = sc.WaterLoad(face, level=9.0)            # γ_w = 9810 N/m³
>>> float(water.pressure(0.0, 0.0))                 # Pa at the heel
88290.0
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model import plausible
from stepcontact.model.interfaces import Interface
from stepcontact.model.loads import EdgeLoad
from stepcontact.model.profile import LinearProfile
from stepcontact.model.profile import as_function as _as_function
from stepcontact.model.profile import finite as _finite
from stepcontact.model.structure import Model
from stepcontact.model.supports import NodeSet

#: unit weight of fresh water γ_w = ρ_w g, N/m³
UNIT_WEIGHT_WATER = 9810.0


def _given_values(spec) -> list[float]:
    """The numbers a pressure or head spec gives: the constant, or the values of the points
    of a profile (none for a function of (x, y))."""
    if isinstance(spec, LinearProfile):
        return [p[2] for p in spec.points]
    if callable(spec) or spec is None:
        return []
    if np.ndim(spec) == 0:
        return [float(spec)]
    try:
        return [float(p[2]) for p in spec]
    except (TypeError, ValueError, IndexError):
        return []


@dataclass(frozen=True, eq=False)
class HydrostaticPressure:
    """p(x, y) = γ_w · max(level − y, 0), Pa: water with its free surface at y = ``level``."""

    level: float
    unit_weight: float = UNIT_WEIGHT_WATER

    def __call__(self, x, y) -> np.ndarray:
        return self.unit_weight * np.maximum(self.level - np.asarray(y, float), 0.0) + 0.0 * x

    def breaks(self, a: np.ndarray, b: np.ndarray) -> list[np.ndarray]:
        """Where each straight segment a[i] → b[i] crosses the level (t ∈ (0, 1))."""
        ya, yb = a[:, 1], b[:, 1]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (self.level - ya) / (yb - ya)
        cut = (yb != ya) & (t > 1e-12) & (t < 1 - 1e-12)
        return [np.array([ti]) if c else np.zeros(0) for ti, c in zip(t, cut, strict=True)]


@dataclass(frozen=True, eq=False)
class _Window:
    """``f`` where a point's coordinate ξ along ``direction`` lies in [lo, hi], 0 elsewhere:
    the uplift acts on the part of S− that faces S+ (the joint), not on the rest of S−."""

    f: Callable
    origin: np.ndarray
    direction: np.ndarray
    lo: float
    hi: float

    def _xi(self, x, y) -> np.ndarray:
        return ((np.asarray(x, float) - self.origin[0]) * self.direction[0]
                + (np.asarray(y, float) - self.origin[1]) * self.direction[1])

    def __call__(self, x, y) -> np.ndarray:
        xi = self._xi(x, y)
        tol = 1e-12 * max(1.0, self.hi - self.lo)
        inside = (xi >= self.lo - tol) & (xi <= self.hi + tol)
        return np.where(inside, np.asarray(self.f(x, y), dtype=float), 0.0)

    def breaks(self, a: np.ndarray, b: np.ndarray) -> list[np.ndarray]:
        inner = getattr(self.f, "breaks", None)
        own = inner(a, b) if inner is not None else [np.zeros(0)] * len(a)
        xa, xb = self._xi(a[:, 0], a[:, 1]), self._xi(b[:, 0], b[:, 1])
        out = []
        for t0, u, v in zip(own, xa, xb, strict=True):
            t = np.array([(e - u) / (v - u) for e in (self.lo, self.hi)]) if v != u else []
            t = np.asarray(t, dtype=float)
            t = t[(t > 1e-12) & (t < 1 - 1e-12)]
            out.append(np.unique(np.r_[np.asarray(t0, float), t]))
        return out

    @classmethod
    def along(cls, f: Callable, points: np.ndarray) -> _Window:
        """The window spanned by ``points`` (S+) along their principal direction."""
        c = points.mean(axis=0)
        if len(points) < 2:
            return cls(f, c, np.array([1.0, 0.0]), -np.inf, np.inf)
        d = np.linalg.svd(points - c, full_matrices=False)[2][0]
        xi = (points - c) @ d
        return cls(f, c, d, float(xi.min()), float(xi.max()))


@dataclass(frozen=True, eq=False)
class WaterLoad:
    """Hydrostatic pressure on the boundary edges of a body whose nodes all lie in ``nodes``.

    .. math::  p(x, y) = \\gamma_w \\, \\max(h_w - y, 0)

    normal to the edges and pushing into the body (like a positive
    :class:`~stepcontact.model.EdgeLoad` ``normal``), with ``level`` = h_w the elevation of the
    free surface (m, y is up) and ``unit_weight`` = γ_w in N/m³.  Edges above the level carry
    nothing; an edge the level cuts is integrated exactly (split at the level).  On a vertical
    face of depth d = h_w − y_bottom the resultant is γ_w d²/2 (per metre of thickness) at d/3
    above the bottom; on an inclined face it is normal to the face, γ_w d² / (2 sin α).

    Per unit λ of its load pattern: λ = 1 is the given level (scaling λ scales the pressure,
    not the level).

    **The level as the load parameter**: with ``level=None`` the factor of the load pattern
    *is* the water level h_w (m): a program segment of that pattern moves the free surface from
    its ``start`` to its ``end`` (a reservoir filling or drawn down), and the load follows the
    level exactly — it is not proportional to it.  The load is a piecewise polynomial in the
    level (cubic on linear edges, quartic on quadratic ones, between the levels of the nodes),
    so every event is located exactly in the level.  Such a pattern holds only water loads
    with ``level=None`` and is moved by segments of its own (not by a segment with rates).
    """

    nodes: NodeSet
    level: float | None
    unit_weight: float = UNIT_WEIGHT_WATER

    def __post_init__(self):
        if self.level is not None:
            _finite(self.level, "water load.level")
        _finite(self.unit_weight, "water load.unit_weight", positive=True)
        plausible.warn("unit_weight_water", self.unit_weight, "water load.unit_weight",
                       stacklevel=4)

    @property
    def follows_level(self) -> bool:
        """True when the level is the factor of the load pattern (``level=None``)."""
        return self.level is None

    @property
    def pressure(self) -> HydrostaticPressure:
        if self.level is None:
            raise ModelError("water load.level", "follows the load factor (level=None): its "
                             "pressure exists only at a given level")
        return HydrostaticPressure(float(self.level), float(self.unit_weight))

    def edge_loads(self, model: Model | None = None) -> tuple[EdgeLoad, ...]:
        """The load as edge pressures (what the assembly integrates)."""
        return (EdgeLoad(self.nodes, normal=self.pressure),)


#: how the head at a drain line is taken (:meth:`Uplift.drained`)
DRAIN_REFERENCES = ("line", "tailwater")
#: the uplift beyond a crack's tip (:class:`CrackWater` ``rule``)
CRACK_RULES = ("connected", "em1110")


@dataclass(frozen=True)
class Drains:
    """A line of foundation drains under a joint (:meth:`Uplift.drained`).

    ``at`` (x, y), m: where the drain line meets the joint; ``efficiency`` E ∈ [0, 1]; and
    ``reference``: the head the drains reduce, ``"line"`` (the undrained heel–toe line at the
    drains, USACE EM 1110-2-2200 (1995) [section to be checked]) or ``"tailwater"``
    (the full head difference h_up − h_down, the form for drains near the upstream face in the
    same section, and USBR (1976)'s h_down + (h_up − h_down)/3, E = 2/3 [to be checked]).  The crack
    water's EM 1110-2-2100 rule (:class:`CrackWater` ``rule="em1110"``) reads it: the drains
    act beyond the crack tip while the crack has not reached them.
    """

    at: tuple[float, float]
    efficiency: float
    reference: str = "line"

    def head(self, h_up: float, h_down: float, remaining: float) -> float:
        """Pressure head at the drain line (m): h_down + (1 − E)(h_up − h_down)·r, with
        r = (L − X)/L (``remaining``: the fraction of the seepage path from the heel, or the
        crack tip, to the toe that lies beyond the drains) for ``"line"`` and r = 1 for
        ``"tailwater"``."""
        r = remaining if self.reference == "line" else 1.0
        return h_down + (1.0 - self.efficiency) * (h_up - h_down) * r


@dataclass(frozen=True, eq=False)
class Uplift:
    """Uplift (pore) pressure in a joint: it pushes the S+ body and the S− body apart.

    The pressure acts normal to the faces of both sides of ``interface`` (its ``plus`` and
    ``minus`` node sets), pushing into each body: the two resultants are equal and opposite
    when the faces coincide.  Give exactly one of

    * ``head`` — pressure head in m of water (p = γ_w · head), or
    * ``pressure`` — in Pa,

    each a constant, a :class:`LinearProfile` or a list of ``(x, y, value)`` points (linear by
    coordinates, e.g. ``[(x_heel, 0, h_heel), (x_toe, 0, h_toe)]``, through a drainage line
    with more points), or a function ``v(x, y)``.  Per unit λ of its load pattern.

    On S− the pressure acts only on the part facing S+ (between the ends of S+ along the
    joint), so a foundation face longer than the dam's base is loaded only under the base.
    ``interface`` is an :class:`~stepcontact.model.Interface` or its name.  The uplift is a
    given load: it does not follow the opening of the joint.

    ``through``: ``"faces"`` (default) integrates the pressure over each face's own mesh;
    ``"cfes"`` applies it through the joint's CFEs, the force A_k p(x_k) across each CFE
    (x_k its S+ end) pushing the two sides apart by the CFE's own force distribution, like a
    compressive contact force.  Then a closed CFE's normal force drops by exactly A_k p (the
    effective stress) whatever the meshes, and an open one is pushed apart by it; with
    ``"faces"`` on non-matching meshes the two faces' nodal forces do not cancel CFE by CFE,
    and a uniform uplift on a closed joint can open it locally.  Use ``"cfes"`` for joints
    between non-matching meshes (the slab study does).

    In a 3D joint the uplift acts through the CFEs (``through="cfes"``; ``"faces"`` is
    refused), with p evaluated at the plan coordinates (x, y) of each CFE's S+ point.

    ``drains``: the line of drains the profile was built with (:meth:`drained`; None: no
    drains) — what the EM 1110-2-2100 crack rule of :class:`CrackWater` needs to move the
    drained profile with the crack tip.
    """

    interface: Interface | str
    head: object = None
    pressure: object = None
    unit_weight: float = UNIT_WEIGHT_WATER
    through: str = "faces"
    drains: Drains | None = None

    @classmethod
    def drained(cls, interface: Interface | str, *, heel: tuple[float, float],
                toe: tuple[float, float], drain: tuple[float, float], efficiency: float,
                head_up: float = 1.0, head_down: float = 0.0, reference: str = "line",
                **kw) -> Uplift:
        """The guidelines' uplift with a line of drains: bilinear, the full head ``head_up``
        at the ``heel``, h_d at the ``drain`` line, ``head_down`` (the tailwater's pressure
        head) at the ``toe`` (points (x, y), m; heads in m of water, per unit λ):

        .. math::  h_d = h_{down} + (1 - E)\\,(h_{up} - h_{down})\\, r

        with E the drains' ``efficiency`` and r = (L − X)/L (``reference="line"``: the drains
        reduce the undrained heel–toe line's head at the drains, L the base length and X the
        drains' distance from the heel: USACE EM 1110-2-2200 (1995), kept by EM 1110-2-2100
        (2005) [sections to be checked]; Ebeling et al. (2000) ERDC/ITL TR-00-1) or r = 1
        (``"tailwater"``: the form for drains near the upstream face, and USBR (1976) Design of
        Gravity Dams [section to be checked]: h_d = h_down + (h_up − h_down)/3, i.e. E = 2/3
        [to be checked]).  With the level as the factor of the pattern
        (``WaterLoad(level=None)``), give ``head_up=1`` (per metre of level, the heel at
        y = 0) and no tailwater (``head_down=0``): the uplift then scales with the level, like
        the single-segment profile of ``examples/cracked_base.py``.
        ``kw`` goes to :class:`Uplift` (``unit_weight``, ``through``)."""
        name = interface if isinstance(interface, str) else interface.name
        item = f"uplift on interface '{name}'"
        e = _finite(efficiency, f"{item}.efficiency")
        if not 0.0 <= e <= 1.0:
            raise ModelError(f"{item}.efficiency", f"is {e:g}: a drain efficiency E lies "
                             "between 0 (no drains) and 1 (the drains take the head to the "
                             "tailwater's)")
        if reference not in DRAIN_REFERENCES:
            raise ModelError(f"{item}.reference", f"'{reference}' is not one of "
                             f"{', '.join(map(repr, DRAIN_REFERENCES))}")
        pts = {}
        for key, v in (("heel", heel), ("toe", toe), ("drain", drain)):
            a = np.asarray(v, dtype=float)
            if a.shape != (2,) or not np.all(np.isfinite(a)):
                raise ModelError(f"{item}.{key}", f"must be a point (x, y), got {v!r}")
            pts[key] = a
        h_up = _finite(head_up, f"{item}.head_up")
        h_down = _finite(head_down, f"{item}.head_down")
        d = pts["toe"] - pts["heel"]
        L = float(np.hypot(*d))
        if L == 0:
            raise ModelError(f"{item}.toe", "coincides with the heel")
        X = float((pts["drain"] - pts["heel"]) @ d) / L
        if not 0.0 < X < L:
            raise ModelError(f"{item}.drain", f"lies {X:g} m along the base from the heel, "
                             f"outside the base (0 … {L:g} m): the drains cross the joint "
                             "between the heel and the toe")
        drains = Drains((float(pts["drain"][0]), float(pts["drain"][1])), e, reference)
        h_d = drains.head(h_up, h_down, (L - X) / L)
        head = [(*map(float, pts["heel"]), h_up), (*map(float, pts["drain"]), h_d),
                (*map(float, pts["toe"]), h_down)]
        return cls(interface, head=head, drains=drains, **kw)

    @staticmethod
    def form_problem(head, pressure) -> str | None:
        """Why an uplift is not given by one of head and pressure (None when it is)."""
        if (head is None) == (pressure is None):
            return "give either head (m of water) or pressure (Pa)"
        return None

    def __post_init__(self):
        name = self.interface if isinstance(self.interface, str) else self.interface.name
        item = f"uplift on interface '{name}'"
        if (text := self.form_problem(self.head, self.pressure)) is not None:
            raise ModelError(item, text)
        _finite(self.unit_weight, f"{item}.unit_weight", positive=True)
        if self.through not in ("faces", "cfes"):
            raise ModelError(f"{item}.through", f"'{self.through}' is not 'faces' or 'cfes'")
        self.function()  # checks the spec
        plausible.warn("unit_weight_water", self.unit_weight, f"{item}.unit_weight",
                       stacklevel=4)
        key, spec = ("head", self.head) if self.head is not None else ("pressure",
                                                                       self.pressure)
        quantity = "head" if key == "head" else "water_pressure"
        for v in _given_values(spec):
            plausible.warn(quantity, v, f"{item}.{key}", stacklevel=4)

    @property
    def name(self) -> str:
        return self.interface if isinstance(self.interface, str) else self.interface.name

    def function(self) -> Callable:
        """The uplift pressure p(x, y), Pa."""
        item = f"uplift on interface '{self.name}'"
        if self.head is not None:
            return _as_function(self.head, f"{item}.head", float(self.unit_weight))
        return _as_function(self.pressure, f"{item}.pressure", 1.0)

    def edge_loads(self, model: Model | None = None) -> tuple[EdgeLoad, ...]:
        """The load as edge pressures on the S+ and S− faces (what the assembly integrates)."""
        itf = self.interface
        if isinstance(itf, str):
            if model is None:
                raise ModelError(f"uplift on interface '{itf}'", "needs the model to find the "
                                 "interface by name")
            found = [i for i in model.interfaces if i.name == itf]
            if not found:
                known = ", ".join(repr(i.name) for i in model.interfaces) or "none"
                raise ModelError(f"uplift on interface '{itf}'",
                                 f"no such interface (known: {known})")
            itf = found[0]
        p = self.function()
        plus = model.body(itf.plus.body).points[itf.plus.index] if model is not None else None
        pm = p if plus is None else _Window.along(p, plus)
        if not isinstance(itf.minus, NodeSet):  # a rigid obstacle takes its part itself
            return (EdgeLoad(itf.plus, normal=p),)
        return (EdgeLoad(itf.plus, normal=p), EdgeLoad(itf.minus, normal=pm))


@dataclass(frozen=True, eq=False)
class CrackWater:
    """Water in the opened parts of a joint: where a CFE of ``interface`` is open, the pressure

    .. math::  p_c(x, y) = \\gamma_w \\, \\max(h_w - y, 0)

    (Pa; ``level`` = h_w, m, y up; z in 3D) acts on both faces of the gap, pushing them apart — the
    cracked-base analysis of dam codes (full reservoir or tailwater pressure in the crack).
    Where the joint is closed, nothing changes (the :class:`Uplift` given for it, if any, acts
    there); where it is open, the crack pressure *replaces* that uplift: the load on the CFE is
    (p_c − p_uplift) · A_k, applied through the CFE's own force distribution (it acts like a
    compressive normal force the water carries across the gap).

    The load jumps when a CFE opens (and drops when it closes, the contact taking the water's
    force over): the solver applies the jump at the same load factor, and a CFE that opens under
    it is loaded in turn — a crack that runs along the joint at one λ shows as a sequence of
    events with equal λ, in their order (``res.water`` holds the crack force of every CFE at
    every state, N).

    Per unit λ of its load pattern, like :class:`WaterLoad`: λ = 1 is the given level, and
    with ``level=None`` the pattern's factor is the level itself (a pattern that moves a
    water level, :class:`WaterLoad` with ``level=None``).

    ``pressure`` (Pa per unit λ), instead of a level: the pressure that reaches the gap
    through the joint, uniform in the crack (the pressure at the joint's entry: a stilling-basin
    slab's joint under the flow, whose pattern a time function makes fluctuate in a dynamic
    interval).  Give a level or a pressure, not both.

    ``entry`` (x, y), optional: the point where water reaches the joint (the heel of a dam's
    base), or several points ``[(x₁, y₁), (x₂, y₂)]`` (the joints at both ends of a slab).
    Only open CFEs joined to the CFE nearest an entry by a run of open CFEs along the joint are
    wet; without it every open CFE of the joint is wet.

    **3D joints**: the heights are z (z up, as for :class:`WaterLoad`), and ``entry`` is the
    edge where water reaches the joint: a polyline ``[(x₁, y₁, z₁), (x₂, y₂, z₂), …]`` (the
    heel edge across the monolith), several polylines ``[[…], […]]``, or a point (x, y, z).
    The entry CFEs are the row of CFEs along each polyline (those within half the shortest
    neighbour spacing of the nearest one's distance); the wet CFEs are the open CFEs joined to
    an open entry CFE through open neighbours, two CFEs being neighbours when their nodes
    belong to one facet of the face that carries them (:mod:`stepcontact.fem.crack`).  The
    uplift it replaces is the joint's ``Uplift(through="cfes")``.

    ``bridge`` (m, ≥ 0; 2D joints with an entry): closed CFEs within this distance of an
    entry point, and not bonded (an intact bond of a bonded joint keeps the water out), do not
    cut the crack from the reservoir — the water reaches the open CFEs
    beyond them, and acts on them too (as an effective stress: their contact force drops by
    A (p_c − p_u)).  At the re-entrant corner of a heel the elastic solution is singular, and
    the heel CFE may stay closed (slipping under compression) while the CFEs behind it open;
    with a bridge of about one element at the heel, water enters the crack as soon as it opens
    behind the heel instead of waiting for the heel to open (then in a cascade of events at
    one level).  A bridged CFE is wet only when an open CFE lies beyond it (a closed heel alone
    holds no water).  ``0`` (default) is the strict rule: only open CFEs conduct water, the
    entry CFE included.

    ``rule``: the uplift *beyond the crack tip* (2D joints with an entry):

    * ``"connected"`` (default) — beyond the wet CFEs the given :class:`Uplift` acts
      unchanged; the crack water replaces it only in the crack;
    * ``"em1110"`` — the cracked-base rule of USACE EM 1110-2-2200 (1995), carried into
      EM 1110-2-2100 (2005) [sections to be checked], as compared for the three federal
      agencies by Ebeling et al. (2000), ERDC/ITL TR-00-1, and drawn in the CADAM3D help
      ("USACE uplift distribution with cracking not extending / extending beyond
      drains"): full reservoir pressure in the crack to its tip, then linear from the tip
      to the uplift at the toe (the far end of the joint from the entry).  With drains (an
      ``Uplift.drained`` on the joint) not yet reached by the crack: linear from the tip to
      the drained head at the drain line, h_toe + (1 − E)(h_tip − h_toe)·(L − X)/(L − T)
      (``"line"``; L the base length, X the drains' and T the tip's distance from the heel)
      or h_toe + (1 − E)(h_tip − h_toe) (``"tailwater"``), then linear to the toe.  Once
      the tip reaches the drain line the drains are ineffective: linear from the tip to the
      toe.  The profile beyond the tip moves with the tip, at every event that changes
      the wet set (:mod:`stepcontact.fem.crack`).
    """

    interface: Interface | str
    level: float | None = None
    unit_weight: float = UNIT_WEIGHT_WATER
    entry: tuple | None = None
    pressure: float | None = None
    bridge: float = 0.0
    rule: str = "connected"

    @staticmethod
    def form_problem(level, pressure) -> str | None:
        """Why crack water is not given by a level or a pressure, at most one (None: it is,
        or neither: the pattern's factor is the level)."""
        if level is not None and pressure is not None:
            return "give the water level or the pressure in the crack, not both"
        return None

    def __post_init__(self):
        item = f"crack water in interface '{self.name}'"
        if self.level is not None:
            _finite(self.level, f"{item}.level")
        if self.pressure is not None:
            _finite(self.pressure, f"{item}.pressure")
            if self.pressure < 0:
                raise ModelError(f"{item}.pressure", f"is {self.pressure:g} Pa: water in a "
                                 "crack pushes its faces apart, a negative pressure (suction) "
                                 "would pull them together; give a pressure ≥ 0 Pa per unit "
                                 "factor")
            plausible.warn("water_pressure", self.pressure, f"{item}.pressure", stacklevel=4)
            if (text := self.form_problem(self.level, self.pressure)) is not None:
                raise ModelError(item, text)
            object.__setattr__(self, "pressure", float(self.pressure))
        _finite(self.unit_weight, f"{item}.unit_weight", positive=True)
        plausible.warn("unit_weight_water", self.unit_weight, f"{item}.unit_weight",
                       stacklevel=4)
        if self.entry is not None:
            object.__setattr__(self, "entry", self._normal_entry(self.entry, f"{item}.entry"))
        b = _finite(self.bridge, f"{item}.bridge")
        if b < 0:
            raise ModelError(f"{item}.bridge", f"is {b:g} m: give a distance ≥ 0 m from the "
                             "entry (0: only open CFEs conduct water)")
        object.__setattr__(self, "bridge", b)
        if self.rule not in CRACK_RULES:
            raise ModelError(f"{item}.rule", f"'{self.rule}' is not one of "
                             f"{', '.join(map(repr, CRACK_RULES))}")
        if self.rule == "em1110" and (self.entry is None or self.entry_dim != 2):
            raise ModelError(f"{item}.rule", "'em1110' moves the uplift beyond the crack tip, "
                             "which needs the point where water enters the 2D joint: give "
                             "entry=(x, y) (the heel)")

    @staticmethod
    def _normal_entry(entry, item: str) -> tuple:
        """``entry`` as tuples of floats: a 2D point (x, y) or points ((x, y), …); a 3D point
        (x, y, z), a polyline ((x, y, z), …) or polylines (((x, y, z), …), …)."""
        def array(v):
            try:
                return np.asarray(v, dtype=float)
            except (TypeError, ValueError):
                return np.zeros(0)

        e = array(entry)
        lines = None
        if e.size == 0 and isinstance(entry, list | tuple) and entry:  # polylines of 3D points
            lines = [array(line) for line in entry]
            lines = [np.atleast_2d(a) for a in lines]
            if not all(a.ndim == 2 and a.shape[-1] == 3 and a.size for a in lines):
                lines = None
        elif e.ndim == 3 and e.shape[-1] == 3 and e.size:
            lines = list(e)
        if lines is not None and all(np.all(np.isfinite(a)) for a in lines):
            return tuple(tuple(tuple(float(v) for v in pt) for pt in a) for a in lines)
        if (e.ndim not in (1, 2) or e.shape[-1] not in (2, 3) or e.size == 0
                or not np.all(np.isfinite(e))):
            raise ModelError(item, "must be a point (x, y) or a list of points (2D), or a point "
                             "(x, y, z), a polyline of points or a list of polylines (3D), "
                             f"got {entry!r}")
        if e.ndim == 1:
            return tuple(float(v) for v in e)
        return tuple(tuple(float(v) for v in pt) for pt in e)

    def check_level(self, y: np.ndarray, item: str) -> None:
        """A given water level must be above the lowest point ``y`` (m) of the joint: below
        it the crack is dry (p_c = 0 everywhere), and where the joint opened the crack water
        would *replace* the uplift by nothing — the opening would close again at once, and a
        heel would open and close at one load factor without end."""
        if self.level is None or self.pressure is not None or not len(y):
            return
        lo, hi = float(np.min(y)), float(np.max(y))
        if self.level <= lo:
            raise ModelError(f"{item}.level", f"is {self.level:g} m, at or below the whole "
                             f"joint (its CFEs lie at y = {lo:g} … {hi:g} m): the crack would "
                             "hold no water and an opening would lose its uplift; give the "
                             "elevation of the water surface that reaches the joint (above "
                             f"y = {lo:g} m), or no crack water")

    @staticmethod
    def check_entries(points: np.ndarray, x: np.ndarray, item: str) -> None:
        """Every entry point lies on the joint: within one CFE spacing of a CFE (``x``: the
        joint's CFEs in order along it, m).  An entry elsewhere would be moved to the nearest
        CFE, which may be the wrong end of the joint: the crack would fill from there, or not
        at all, and the dam slide later than it should."""
        x = np.asarray(x, dtype=float).reshape(-1, 2)
        if not len(x):
            return
        seg = np.hypot(*np.diff(x, axis=0).T) if len(x) > 1 else np.zeros(0)
        extent = float(np.ptp(x, axis=0).max()) if len(x) > 1 else 0.0
        tol = max(float(seg.max()) if seg.size else 0.0, 1e-9 * max(extent, 1.0))
        for pt in np.atleast_2d(points):
            d = np.hypot(*(x - pt).T)
            if d.min() > tol:
                lo, hi = x.min(axis=0), x.max(axis=0)
                raise ModelError(item, f"({pt[0]:g}, {pt[1]:g}) is {d.min():.3g} m from the "
                                 f"joint, which spans x = {lo[0]:g} … {hi[0]:g} m, y = "
                                 f"{lo[1]:g} … {hi[1]:g} m: water enters a crack at a point of "
                                 "its joint (e.g. the heel); give that point")

    @property
    def entry_dim(self) -> int | None:
        """2 or 3: the dimension of the entry's points (None: no entry)."""
        if self.entry is None:
            return None
        e = self.entry
        while isinstance(e[0], tuple):
            e = e[0]
        return len(e)

    @property
    def entries(self) -> np.ndarray:
        """The 2D entry points as an array (k, 2), m (empty: no entry, every open CFE is wet;
        3D entries: :attr:`entry_lines`)."""
        if self.entry is None or self.entry_dim != 2:
            return np.zeros((0, 2))
        return np.atleast_2d(np.asarray(self.entry, float))

    @property
    def entry_lines(self) -> list[np.ndarray]:
        """The 3D entry as polylines, each (k, 3), m (a point: one of one point; empty: no
        3D entry)."""
        if self.entry is None or self.entry_dim != 3:
            return []
        if not isinstance(self.entry[0], tuple):  # a point
            return [np.asarray([self.entry], float)]
        if not isinstance(self.entry[0][0], tuple):  # one polyline
            return [np.asarray(self.entry, float)]
        return [np.asarray(line, float) for line in self.entry]

    #: a load of the contact state, not of the nodes (the assembly skips it: fem.crack)
    in_crack = True

    @property
    def name(self) -> str:
        return self.interface if isinstance(self.interface, str) else self.interface.name

    def crack_pressure(self, y: np.ndarray, level: float | None = None) -> np.ndarray:
        """p_c (Pa) at heights ``y``: the given pressure, or the hydrostatic pressure of the
        water level ``level`` (default: the given one)."""
        y = np.asarray(y, dtype=float)
        if self.pressure is not None and level is None:
            return np.full(y.shape, self.pressure)
        h = self.level if level is None else level
        return self.unit_weight * np.maximum(h - y, 0.0)


__all__ = ["CRACK_RULES", "DRAIN_REFERENCES", "UNIT_WEIGHT_WATER", "CrackWater", "Drains",
           "HydrostaticPressure", "LinearProfile", "Uplift", "WaterLoad"]
