"""Load cases of a gravity dam as engineers write them, and the combinations that group them.

A thin layer over the loads that exist: every case becomes items of
:mod:`stepcontact.model.water` and :mod:`stepcontact.model.loads` in a named load pattern, and
a :class:`Combination` becomes the load program of **one run** — its patterns and segments,
added to the model of a :class:`DamSite`:

==========================  ====================================================================
case                        what it adds (pattern; segment)
==========================  ====================================================================
:class:`SelfWeight`         ``BodyForce`` on the dam's bodies ("self-weight"; 0 → 1)
:class:`Reservoir`          ``WaterLoad(upstream, level=None)`` — the factor is the level h (m)
                            — with the reservoir part of :class:`BaseUplift` and, optionally,
                            ``CrackWater(base, level=None, entry=heel)`` ("reservoir"; 0 → h)
:class:`Tailwater`          ``WaterLoad(downstream, level=t)`` and the tailwater part of the
                            uplift ("tailwater"; 0 → 1)
:class:`BaseUplift`         the uplift under the base, linear from the heel head
                            H₁ = h − y_heel to the toe head H₂ = t − y_toe, through the drain
                            line's head H₂ + K (H₁ − H₂) (no pattern of its own)
:class:`Silt`               p = K γ'_s max(y_s − y, 0) on the upstream face ("silt"; 0 → 1)
:class:`Ice`                a line load F (N/m) at the ice level on the upstream face ("ice")
:class:`PostTensioning`     the anchor force (N/m) on the anchor heads, and its reaction on the
                            fixed anchor in the rock ("post-tensioning"; 0 → 1)
:class:`Earthquake`         a :class:`~stepcontact.model.seismic.SeismicCoefficient` per unit
                            k_h: inertia ρ (k_h g, k_v g) on the dam's bodies and Westergaard's
                            pseudo-static pressure of the reservoir (an ``AddedMass`` at the
                            combination's level) on the upstream face ("earthquake"; 0 → k_h;
                            then back to 0 in a post-earthquake combination)
==========================  ====================================================================

The segments run in the order self-weight, post-tensioning, tailwater, reservoir, silt, ice,
earthquake: the reservoir rises on the built, anchored dam; silt and ice act at the final
level; the earthquake last.  The run's last state is the combination's state (its checks:
:mod:`stepcontact.results.dam_checks`).

**Levels are elevations with the datum at the heel** (y_heel = 0): the reservoir's factor is
the level h, and the uplift's reservoir part is then exactly h · a(x) per metre of level, with
a(x) = 1 at the heel, K at the drains, 0 at the toe.  A site whose heel is not at y = 0 is
refused (translate the model, :func:`stepcontact.model.mesh.translate`).

Sources: the uplift with a drainage line, H₂ + K (H₁ − H₂) at the drains, is the usual rule
of USBR (1987) *Design of Small Dams* ch. 8 (K = 1/3) and of EM 1110-2-2100 (2005) ch. 3 /
EM 1110-2-2200 (1995) ch. 3 (K = (1 − E)(L − X)/L with drain efficiency E at distance X from
the heel) [to be checked]; the silt load as an equivalent fluid of lateral coefficient K and
submerged unit weight γ'_s: EM 1110-2-2200 (1995) ch. 3 (which quotes 85 pcf ≈ 13.4 kN/m³ of
equivalent fluid, horizontal) [to be checked]; the ice load as a line load at the reservoir
level: EM 1110-2-2200 (1995) ch. 3 and CDA (2007) Technical Bulletin "Structural considerations
for dam safety" [to be checked]; pseudo-static inertia k_h W:
EM 1110-2-2200 (1995) ch. 3 (seismic coefficient method) [to be checked]; the reservoir's
hydrodynamic pressure during the earthquake: Westergaard (1933), on a batter Kuo (1982)
(:mod:`stepcontact.model.seismic`; ``Earthquake(hydrodynamic=False)`` leaves it out).

Example
-------
>>> site = DamSite(m, base="base", heel=(0, 0), toe=(27, 0), dam=("dam",),    # doctest: +SKIP
...                upstream=m.select("dam", x=0.0), downstream=downstream)
>>> usual = Combination("usual", "usual", (SelfWeight(), Reservoir(33.0),     # doctest: +SKIP
...                      Tailwater(3.0), BaseUplift(drain=(5.0, 0.0), ratio=1 / 3)))
>>> res = solve_static(usual.model(site))                                     # doctest: +SKIP
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model import plausible
from stepcontact.model.loads import G_STANDARD, BodyForce, LoadPattern, NodalLoad
from stepcontact.model.seismic import AddedMass, SeismicCoefficient
from stepcontact.model.structure import Model, Segment
from stepcontact.model.supports import NodeSet
from stepcontact.model.water import (
    UNIT_WEIGHT_WATER,
    CrackWater,
    Uplift,
    WaterLoad,
)

#: the combinations' conditions (the guidelines map them onto their own classes)
CONDITIONS = ("usual", "unusual", "flood", "extreme", "earthquake", "post-earthquake")

#: the order of the patterns' segments in a combination's program
ORDER = ("self-weight", "post-tensioning", "tailwater", "reservoir", "silt", "ice", "earthquake")


def _finite(value, item: str, *, positive: bool = False, nonneg: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ModelError(item, f"must be a number, got {value!r}") from None
    if not np.isfinite(v) or (positive and v <= 0) or (nonneg and v < 0):
        what = "> 0" if positive else "≥ 0" if nonneg else "finite"
        raise ModelError(item, f"must be {what}, got {value!r}")
    return v


def _point(value, item: str) -> tuple[float, float]:
    try:
        p = np.asarray(value, dtype=float).ravel()
    except (TypeError, ValueError):
        p = np.zeros(0)
    if p.shape != (2,) or not np.all(np.isfinite(p)):
        raise ModelError(item, f"must be a point (x, y) in m, got {value!r}")
    return float(p[0]), float(p[1])


@dataclass(frozen=True, eq=False)
class DamSite:
    """Where the load cases act in ``model``: the base joint ``base`` (an interface name) from
    ``heel`` to ``toe`` (points (x, y), m; the heel at y = 0), the dam's ``dam`` bodies
    (self-weight, inertia), the ``upstream`` face (reservoir, silt, ice) and the
    ``downstream`` face (tailwater) as node sets — a tuple of node sets for a face across
    several bodies (a dam in lifts)."""

    model: Model
    base: str
    heel: tuple[float, float]
    toe: tuple[float, float]
    upstream: NodeSet | tuple[NodeSet, ...]
    dam: tuple[str, ...]
    downstream: NodeSet | tuple[NodeSet, ...] | None = None

    def __post_init__(self):
        for face in ("upstream", "downstream"):
            v = getattr(self, face)
            if v is None and face == "downstream":
                continue
            sets = (v,) if isinstance(v, NodeSet) else tuple(v)
            if not sets or not all(isinstance(n, NodeSet) for n in sets):
                raise ModelError(f"dam site.{face}", "give a node set or a tuple of node sets")
            object.__setattr__(self, face, sets)
        object.__setattr__(self, "heel", _point(self.heel, "dam site.heel"))
        object.__setattr__(self, "toe", _point(self.toe, "dam site.toe"))
        object.__setattr__(self, "dam", tuple(self.dam))
        if self.heel[1] != 0.0:
            raise ModelError("dam site.heel", f"is at y = {self.heel[1]:g} m: the levels of the "
                             "load cases are elevations with the datum at the heel; translate "
                             "the model so that the heel is at y = 0")
        if self.heel == self.toe:
            raise ModelError("dam site.toe", "coincides with the heel")
        names = {b.name for b in self.model.bodies}
        if not self.dam:
            raise ModelError("dam site.dam", "name the dam's bodies (self-weight, inertia)")
        for b in self.dam:
            if b not in names:
                raise ModelError("dam site.dam", f"no body '{b}' (bodies: "
                                 f"{', '.join(sorted(names))})")
        if self.base not in {i.name for i in self.model.interfaces}:
            known = ", ".join(repr(i.name) for i in self.model.interfaces) or "none"
            raise ModelError("dam site.base", f"no interface '{self.base}' (interfaces: {known})")

    @property
    def length(self) -> float:
        """Length of the base from the heel to the toe, m."""
        return float(np.hypot(self.toe[0] - self.heel[0], self.toe[1] - self.heel[1]))

    @property
    def downstream_sign(self) -> float:
        """+1 when the toe lies at larger x than the heel (the water pushes along +x)."""
        return 1.0 if self.toe[0] > self.heel[0] else -1.0


# ---- load cases ------------------------------------------------------------------------------
@dataclass(frozen=True)
class SelfWeight:
    """Self-weight of the dam's bodies, g in m/s² downwards."""

    g: float = G_STANDARD

    def __post_init__(self):
        _finite(self.g, "self-weight.g", positive=True)

    def items(self, site: DamSite, combo: Combination) -> dict[str, list]:
        return {"self-weight": [BodyForce(g=(0.0, -float(self.g)), bodies=site.dam)]}


@dataclass(frozen=True)
class Reservoir:
    """The reservoir at elevation ``level`` (m) on the upstream face; the pattern's factor is
    the level (exact events in h).  ``crack_water``: full reservoir pressure in the base where
    it opens, entering at the heel (:class:`~stepcontact.model.water.CrackWater`)."""

    level: float
    crack_water: bool = False
    unit_weight: float = UNIT_WEIGHT_WATER

    def __post_init__(self):
        _finite(self.level, "reservoir.level", positive=True)
        _finite(self.unit_weight, "reservoir.unit_weight", positive=True)

    def items(self, site: DamSite, combo: Combination) -> dict[str, list]:
        out = [WaterLoad(n, level=None, unit_weight=self.unit_weight) for n in site.upstream]
        if self.crack_water:
            out.append(CrackWater(site.base, level=None, unit_weight=self.unit_weight,
                                  entry=site.heel))
        return {"reservoir": out}


@dataclass(frozen=True)
class Tailwater:
    """Tailwater at elevation ``level`` (m) on the downstream face."""

    level: float
    unit_weight: float = UNIT_WEIGHT_WATER

    def __post_init__(self):
        _finite(self.level, "tailwater.level", nonneg=True)

    def items(self, site: DamSite, combo: Combination) -> dict[str, list]:
        if site.downstream is None:
            raise ModelError(f"combination '{combo.name}'.tailwater", "the dam site has no "
                             "downstream face: give DamSite(downstream=...)")
        return {"tailwater": [WaterLoad(n, level=self.level, unit_weight=self.unit_weight)
                              for n in site.downstream]}


@dataclass(frozen=True)
class BaseUplift:
    """Uplift under the base: head H₁ = h − y_heel at the heel (h the reservoir level), H₂ =
    t − y_toe at the toe (t the tailwater level, 0 without tailwater), linear between, and with
    a ``drain`` line at the point (x, y) on the base the head H₂ + ``ratio`` (H₁ − H₂) there
    (``ratio`` K: 1/3 in USBR (1987) ch. 8; (1 − E)(L − X)/L for a drain efficiency E in EM
    1110-2-2100 (2005) [to be checked]).  Without a drain the head is linear from H₁ to H₂.

    ``through``: as :class:`~stepcontact.model.water.Uplift` (``"cfes"`` for non-matching
    meshes)."""

    drain: tuple[float, float] | None = None
    ratio: float = 1.0 / 3.0
    through: str = "faces"
    unit_weight: float = UNIT_WEIGHT_WATER

    def __post_init__(self):
        if self.drain is not None:
            object.__setattr__(self, "drain", _point(self.drain, "base uplift.drain"))
        r = _finite(self.ratio, "base uplift.ratio", nonneg=True)
        if r > 1:
            raise ModelError("base uplift.ratio", f"is {r:g}: the drains' head ratio K lies in "
                             "[0, 1] (0: perfect drains, 1: no drains)")

    def shapes(self, site: DamSite) -> tuple[list, list]:
        """The head profiles per metre of H₁ and per metre of H₂: [(x, y, a)], [(x, y, b)]."""
        h, t = site.heel, site.toe
        if self.drain is None:
            return [(*h, 1.0), (*t, 0.0)], [(*h, 0.0), (*t, 1.0)]
        d = np.asarray(self.drain) - np.asarray(h)
        u = (np.asarray(t) - np.asarray(h)) / site.length
        s = float(d @ u)
        off = abs(float(d[0] * u[1] - d[1] * u[0]))
        if not 0.0 < s < site.length or off > 1e-6 * site.length:
            raise ModelError("base uplift.drain", f"({self.drain[0]:g}, {self.drain[1]:g}) is "
                             "not on the base between the heel and the toe")
        k = float(self.ratio)
        return ([(*h, 1.0), (*self.drain, k), (*t, 0.0)],
                [(*h, 0.0), (*self.drain, 1.0 - k), (*t, 1.0)])

    def heads(self, site: DamSite, h1: float, h2: float) -> list[tuple[float, float, float]]:
        """The head profile (x, y, head in m) for heel head ``h1`` and toe head ``h2``."""
        a, b = self.shapes(site)
        return [(p[0], p[1], h1 * p[2] + h2 * q[2]) for p, q in zip(a, b, strict=True)]

    def force(self, site: DamSite, h1: float, h2: float) -> float:
        """Resultant of the uplift on the base, N per metre of dam: γ_w ∫ head ds (the
        trapezoids of the piecewise-linear head)."""
        pts = np.asarray(self.heads(site, h1, h2))
        s = np.r_[0.0, np.cumsum(np.hypot(*np.diff(pts[:, :2], axis=0).T))]
        return float(self.unit_weight * np.trapezoid(pts[:, 2], s))

    def items(self, site: DamSite, combo: Combination) -> dict[str, list]:
        a, b = self.shapes(site)
        if combo.find(Reservoir) is None:
            raise ModelError(f"combination '{combo.name}'.base uplift", "needs a reservoir "
                             "case (the heel head is the reservoir's)")
        out = {"reservoir": [Uplift(site.base, head=a, unit_weight=self.unit_weight,
                                    through=self.through)]}
        tw = combo.find(Tailwater)
        h2 = 0.0 if tw is None else float(tw.level) - site.toe[1]
        if h2 > 0:
            out["tailwater"] = [Uplift(site.base, head=[(x, y, h2 * v) for x, y, v in b],
                                       unit_weight=self.unit_weight, through=self.through)]
        return out


@dataclass(frozen=True)
class Silt:
    """Silt against the upstream face up to elevation ``level`` (m): an equivalent fluid of
    pressure p = ``coefficient`` · ``submerged_unit_weight`` · max(level − y, 0) (Pa; K the
    lateral earth pressure coefficient, γ'_s in N/m³), normal to the face.  On an inclined
    face the weight of the silt above it is not included."""

    level: float
    submerged_unit_weight: float
    coefficient: float

    def __post_init__(self):
        _finite(self.level, "silt.level", positive=True)
        _finite(self.submerged_unit_weight, "silt.submerged_unit_weight", positive=True)
        _finite(self.coefficient, "silt.coefficient", positive=True)

    def items(self, site: DamSite, combo: Combination) -> dict[str, list]:
        # a WaterLoad of the equivalent fluid: its edges are split at the silt's level, so
        # the nodal forces are exact (an EdgeLoad's Gauss rule is not, across the kink); the
        # check of a water's unit weight does not apply to the silt's K γ'_s
        gamma = float(self.coefficient * self.submerged_unit_weight)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", plausible.PlausibilityWarning)
            return {"silt": [WaterLoad(n, level=float(self.level), unit_weight=gamma)
                             for n in site.upstream]}


def _face_pair(site: DamSite, y: float, item: str) -> tuple[list[tuple], list[float]]:
    """The nodes (body, index) of the upstream face around elevation ``y`` and the weights
    that put a force at y on them by the lever rule (statically exact: same resultant and
    moment)."""
    pts = np.concatenate([site.model.body(n.body).points[n.index] for n in site.upstream])
    idx = [(n.body, int(i)) for n in site.upstream for i in n.index]
    order = np.argsort(pts[:, 1], kind="stable")
    ys, idx = pts[order, 1], [idx[i] for i in order]
    tol = 1e-9 * max(1.0, float(np.ptp(ys)))
    if not ys[0] - tol <= y <= ys[-1] + tol:
        raise ModelError(item, f"elevation {y:g} m is outside the upstream face (y = "
                         f"{ys[0]:g} … {ys[-1]:g} m)")
    j = int(np.argmin(np.abs(ys - y)))
    if abs(ys[j] - y) <= tol:
        return [idx[j]], [1.0]
    k = int(np.searchsorted(ys, y))
    w = (y - ys[k - 1]) / (ys[k] - ys[k - 1])
    return [idx[k - 1], idx[k]], [1.0 - w, w]


@dataclass(frozen=True)
class Ice:
    """Ice thrust ``force`` (N per metre of dam) at elevation ``level`` (m, the reservoir's
    level), horizontal, on the upstream face towards the toe: put on the face's two nodes
    around the level by the lever rule (same resultant and moment about any point)."""

    force: float
    level: float

    def __post_init__(self):
        _finite(self.force, "ice.force", positive=True)
        _finite(self.level, "ice.level", positive=True)

    def items(self, site: DamSite, combo: Combination) -> dict[str, list]:
        nodes, w = _face_pair(site, float(self.level), f"combination '{combo.name}'.ice.level")
        fx = site.downstream_sign * float(self.force)
        return {"ice": [NodalLoad(NodeSet(b, [n], name=f"ice node {n} of '{b}'"), fx=fx * wi)
                        for (b, n), wi in zip(nodes, w, strict=True)]}


@dataclass(frozen=True)
class PostTensioning:
    """Anchors: the force ``force`` (N per metre of dam) on the anchor heads ``head`` (a node
    set of the dam, shared equally), along ``direction`` (default (0, −1): down), and the
    opposite force on the fixed anchors ``anchor`` (a node set of the rock; None: the reaction
    is not modelled — the anchors are then an external load)."""

    force: float
    head: NodeSet
    anchor: NodeSet | None = None
    direction: tuple[float, float] = (0.0, -1.0)

    def __post_init__(self):
        _finite(self.force, "post-tensioning.force", positive=True)
        d = np.asarray(_point(self.direction, "post-tensioning.direction"))
        if np.hypot(*d) == 0:
            raise ModelError("post-tensioning.direction", "must not be zero")
        object.__setattr__(self, "direction", tuple(float(v) for v in d / np.hypot(*d)))

    def items(self, site: DamSite, combo: Combination) -> dict[str, list]:
        f = float(self.force) * np.asarray(self.direction)
        out = [NodalLoad(self.head, fx=f[0] / len(self.head), fy=f[1] / len(self.head))]
        if self.anchor is not None:
            out.append(NodalLoad(self.anchor, fx=-f[0] / len(self.anchor),
                                 fy=-f[1] / len(self.anchor)))
        return {"post-tensioning": out}


@dataclass(frozen=True)
class Earthquake:
    """Pseudo-static earthquake through :class:`~stepcontact.model.seismic.SeismicCoefficient`
    (one path for the coefficient method): the inertia ρ g (k_h, k_v) of the dam's bodies,
    the horizontal part towards the toe (downstream: the critical direction with a full
    reservoir), k_v > 0 upwards (it lightens the dam), and — with ``hydrodynamic`` (default)
    and a :class:`Reservoir` case — the reservoir's pseudo-static pressure on the upstream
    face, an :class:`~stepcontact.model.seismic.AddedMass` at the combination's level (the
    reservoir's bottom at the heel, y = 0) times the same acceleration: on a vertical face
    Westergaard's p(z) = (7/8) k_h γ_w √(h z), resultant (7/12) k_h γ_w h² at 0.4 h above the
    base (Westergaard 1933); on a batter its normal form (Kuo 1982).

    The pattern is ``SeismicCoefficient(k_h=1, k_v=k_v/k_h)``: per unit k_h, k_v in the fixed
    ratio k_v/k_h, and its segment goes to ``k_h`` (the result's λ is k_h; a longer segment
    locates the yield acceleration, :mod:`stepcontact.study.dam_study`).
    ``reservoir_items``: further loads per unit k_h in the same pattern.  In a
    post-earthquake combination the earthquake is applied and then removed (the checks read
    the state after it, cracked and slid)."""

    k_h: float
    k_v: float = 0.0
    reservoir_items: tuple = ()
    g: float = G_STANDARD
    hydrodynamic: bool = True

    def __post_init__(self):
        _finite(self.k_h, "earthquake.k_h", positive=True)
        _finite(self.k_v, "earthquake.k_v")
        object.__setattr__(self, "reservoir_items", tuple(self.reservoir_items))

    def coefficient(self, site: DamSite, combo: Combination) -> SeismicCoefficient:
        """The pattern's item: the inertia per unit k_h of the dam's bodies and, with
        ``hydrodynamic`` and a reservoir case, of the reservoir's added mass on each upstream
        face at the reservoir's level."""
        res = combo.find(Reservoir) if self.hydrodynamic else None
        water = () if res is None else tuple(
            AddedMass(n, level=float(res.level), bottom=site.heel[1],
                      density=float(res.unit_weight) / float(self.g)) for n in site.upstream)
        return SeismicCoefficient(k_h=1.0, k_v=float(self.k_v) / float(self.k_h),
                                  bodies=site.dam, reservoir=water,
                                  direction=site.downstream_sign, g=float(self.g))

    def items(self, site: DamSite, combo: Combination) -> dict[str, list]:
        return {"earthquake": [self.coefficient(site, combo), *self.reservoir_items]}


LoadCase = (SelfWeight | Reservoir | Tailwater | BaseUplift | Silt | Ice | PostTensioning
            | Earthquake)


@dataclass(frozen=True)
class Combination:
    """A load combination: its ``name``, its ``condition`` (one of :data:`CONDITIONS`: the
    guideline's required values are those of the class it maps onto) and its load ``cases``."""

    name: str
    condition: str
    cases: tuple

    def __post_init__(self):
        object.__setattr__(self, "cases", tuple(self.cases))
        item = f"combination '{self.name}'"
        if self.condition not in CONDITIONS:
            raise ModelError(f"{item}.condition", f"'{self.condition}' is not one of "
                             f"{', '.join(CONDITIONS)}")
        seen = set()
        for c in self.cases:
            if not isinstance(c, LoadCase):
                raise ModelError(f"{item}.cases", f"{c!r} is not a load case")
            if type(c) in seen:
                raise ModelError(f"{item}.cases", f"two {type(c).__name__} cases")
            seen.add(type(c))
        if self.condition == "post-earthquake" and Earthquake not in seen:
            raise ModelError(f"{item}.cases", "a post-earthquake combination needs the "
                             "earthquake it follows (an Earthquake case)")

    def find(self, kind: type):
        """The case of type ``kind``, or None."""
        return next((c for c in self.cases if isinstance(c, kind)), None)

    def patterns(self, site: DamSite) -> list[LoadPattern]:
        """The load patterns of the combination, in program order."""
        items: dict[str, list] = {}
        for c in self.cases:
            for name, loads in c.items(site, self).items():
                items.setdefault(name, []).extend(loads)
        return [LoadPattern(name, items[name]) for name in ORDER if name in items]

    def segments(self) -> list[Segment]:
        """The segments of the program: each pattern from 0 to its value (the reservoir to its
        level, the earthquake to k_h and, post-earthquake, back to 0)."""
        ends = {}
        for c in self.cases:
            if isinstance(c, SelfWeight):
                ends["self-weight"] = [1.0]
            elif isinstance(c, Reservoir):
                ends["reservoir"] = [float(c.level)]
            elif isinstance(c, Earthquake):
                ends["earthquake"] = [float(c.k_h)] + (
                    [0.0] if self.condition == "post-earthquake" else [])
        present = {_PATTERN[type(c)] for c in self.cases if type(c) in _PATTERN}
        return [Segment(name, end) for name in ORDER if name in present
                for end in ends.get(name, [1.0])]

    def model(self, site: DamSite) -> Model:
        """``site.model`` with the combination's patterns and program (it must have none)."""
        if site.model.patterns or site.model.program or site.model.stages:
            raise ModelError(f"combination '{self.name}'", "the dam site's model already has "
                             "load patterns, segments or stages: give the model without loads")
        return site.model.add(*self.patterns(site), *self.segments())


#: the pattern of each case (:class:`BaseUplift` adds to the reservoir's and tailwater's)
_PATTERN = {SelfWeight: "self-weight", Reservoir: "reservoir", Tailwater: "tailwater",
            Silt: "silt", Ice: "ice", PostTensioning: "post-tensioning",
            Earthquake: "earthquake"}


__all__ = ["CONDITIONS", "BaseUplift", "Combination", "DamSite", "Earthquake", "Ice",
           "LoadCase", "PostTensioning", "Reservoir", "SelfWeight", "Silt", "Tailwater"]
