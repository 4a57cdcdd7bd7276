"""The load program (segments, dynamic intervals) and :class:`Model`, which holds a 2D structure:
its bodies, supports, springs, interfaces, load patterns, program and stages.

Changing a model returns a new one (:meth:`Model.add`, :func:`dataclasses.replace`)."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import Literal, get_args

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model.bodies import E_RATIO_MIN, PLANE_KINDS, Body, Frame, _either
from stepcontact.model.interfaces import Interface
from stepcontact.model.loads import LoadPattern
from stepcontact.model.obstacle import ObstacleMotion, RigidObstacle, RigidPlane
from stepcontact.model.supports import NodeSet, Spring, Support, Tie, select_nodes
from stepcontact.model.timefunction import MASS_KINDS, MAX_STEPS, check_interval, check_newmark


@dataclass(frozen=True)
class Segment:
    """One segment of the load program: ``pattern``'s factor goes from ``start`` to ``end``.

    ``start`` None means "from where the pattern stands" (0 if never applied).  A segment whose
    ``start`` differs from the pattern's current factor does not chain and is an error.

    Non-proportional loading: with ``rates`` = {pattern: rate, …} several patterns move at once
    and ``pattern`` is the segment's own name (a label, not a pattern): its parameter goes from
    ``start`` to ``end`` and each pattern's factor changes by ``rate`` per unit of it.  Events
    and multipliers of the segment are given in that parameter.

    Example
    -------
    >>> Segment("flood", 2.0, rates={"water": 1.0, "uplift": 0.6})  # doctest: +SKIP
    """

    pattern: str
    end: float
    start: float | None = None
    rates: tuple[tuple[str, float], ...] | None = None

    def __post_init__(self):
        if self.rates is not None:
            items = self.rates.items() if isinstance(self.rates, dict) else self.rates
            object.__setattr__(self, "rates", tuple((str(k), float(v)) for k, v in items))


# --------------------------------------------------------------------------------------------
# the model
# --------------------------------------------------------------------------------------------
def _check_stiffness_ratio(bodies: Sequence) -> None:
    """Young's moduli of the bodies and frames at most 1/:data:`E_RATIO_MIN` apart."""
    moduli = []  # (item, label, E)
    for b in bodies:
        if isinstance(b, Frame):
            moduli.append((f"frame '{b.name}'.E", f"frame '{b.name}'", float(b.E)))
        elif isinstance(b, Body):
            moduli.append((f"body '{b.name}'.material", f"body '{b.name}'", float(b.material.E)))
    if len(moduli) < 2:
        return
    soft = min(moduli, key=lambda t: t[2])
    stiff = max(moduli, key=lambda t: t[2])
    if soft[2] < E_RATIO_MIN * stiff[2]:
        raise ModelError(
            soft[0],
            f"Young's modulus E = {soft[2]:g} is {soft[2] / stiff[2]:.1e} times that of "
            f"{stiff[1]} (E = {stiff[2]:g}): moduli more than {1 / E_RATIO_MIN:g} apart cannot "
            "be solved together in double precision; check the values and their units (Pa)",
        )


def _check_interface_dimension(model: Model, dim: int) -> None:
    """The interfaces' options of the other dimension are refused by name: a 2D model's
    interfaces take no facet options, axis or rigid plane; a 3D model's no moving obstacle."""
    for itf in model.interfaces:
        item = f"interface '{itf.name}'"
        if dim == 2:
            for key, given in (("facets", itf.facets is not None),
                               ("facet_angle", itf.facet_angle != 0.0),
                               ("axis", itf.axis is not None)):
                if given:
                    raise ModelError(f"{item}.{key}", "applies to interfaces between 3D bodies "
                                     "only (a 2D interface has the two facets slip+ and slip−)")
            if isinstance(itf.minus, RigidPlane):
                raise ModelError(f"{item}.minus", f"obstacle '{itf.minus.name}' is a plane, "
                                 "for 3D bodies: a 2D body meets a RigidObstacle (a polyline)")
        if itf.normal is not None and len(itf.normal) != dim:
            raise ModelError(f"{item}.normal", f"is a {len(itf.normal)}-vector, but the model "
                             f"is {dim}D: give a {dim}-vector")
    if dim == 3:
        for p in model.patterns:
            for i, ld in enumerate(p.loads):
                if isinstance(ld, ObstacleMotion):
                    raise ModelError(f"load pattern '{p.name}' load {i}", f"moves obstacle "
                                     f"'{ld.name}': moving obstacles of 3D models are not "
                                     "available yet (a RigidPlane is fixed)")


def _check_dimension(model: Model) -> None:
    """All bodies of one dimension; a 3D model has no 2D-only items (plane frames, the plane and
    thickness options, moving obstacles and uplift on faces (an uplift acts through the
    CFEs): not available in 3D yet); interfaces of a 3D model join faces of its bodies or a
    body and a rigid plane."""
    solids = [b for b in model.bodies if getattr(b, "dim", 2) == 3]
    _check_interface_dimension(model, 3 if solids else 2)
    if not solids:
        return
    first = solids[0]
    for b in model.bodies:
        if isinstance(b, Frame) and b.dim != 3:
            raise ModelError(f"frame '{b.name}'", f"is a plane frame (2D points), but "
                             f"'{first.name}' is 3D: space frames take 3D points (x, y, z)")
        if b.dim != 3:
            raise ModelError(f"body '{b.name}'", f"is 2D, but body '{first.name}' is 3D: all "
                             "bodies of a model have one dimension")
    if model.plane != "strain":
        raise ModelError(f"body '{first.name}'", f"is 3D: model.plane = '{model.plane}' (plane "
                         "strain or stress) applies to 2D bodies only; leave it at its default")
    if model.thickness != 1.0:
        raise ModelError(f"body '{first.name}'", f"is 3D: model.thickness = {model.thickness:g} "
                         "applies to 2D bodies only; leave it at its default (1)")
    for p in model.patterns:
        for i, ld in enumerate(p.loads):
            item = f"load pattern '{p.name}' load {i}"
            if getattr(ld, "through", None) == "faces":  # an Uplift on the faces
                raise ModelError(f"{item}.through", "an uplift in a 3D joint acts through its "
                                 "CFEs: give through='cfes' (the pressure p(x, y) at each "
                                 "CFE's plan position, A_k p across each CFE)")


#: the choices of the crack water during a dynamic interval (:class:`DynamicInterval`
#: ``crack_water``; issue 29 §1): the static rule, the pre-earthquake water held, or held
#: with no pressure in the new openings
CrackWaterChoice = Literal["full", "unchanged", "none"]
CRACK_WATER_CHOICES: tuple[str, ...] = get_args(CrackWaterChoice)


def check_crack_water(choice, item: str) -> str:
    """``choice`` if it is one of :data:`CRACK_WATER_CHOICES`, else ModelError naming
    ``item``."""
    if not isinstance(choice, str) or choice not in CRACK_WATER_CHOICES:
        raise ModelError(item, f"must be {_either(CRACK_WATER_CHOICES)}, got {choice!r}")
    return choice


@dataclass(frozen=True, eq=False)
class DynamicInterval:
    """A dynamic interval after the load program (method.md §4): Newmark time integration
    from the program's last state (:func:`stepcontact.solve_dynamic`); or at the end of a
    construction stage (:class:`~stepcontact.model.Stage` ``dynamics``; on a stage before the
    last, :func:`stepcontact.solve_static` runs it and the static stages go on from its end).

    ``loads``: (pattern name, time function) pairs (:mod:`stepcontact.model.timefunction`);
    ``dt``, ``duration`` in s; ``mass`` "consistent" or "lumped"; ``damping`` the Rayleigh
    coefficients (a₀ in 1/s, a₁ in s); ``restitution`` e of the impacts; ``record_every`` k:
    every k-th step is recorded (events and the end always); ``alpha`` the HHT-α numerical
    damping (0: Newmark's average acceleration); ``max_steps`` the limit of the number of
    time steps (the interval is refused, before any work, when duration / dt exceeds it);
    ``ground`` the ground acceleration of the interval: an earthquake record or the records
    that act together (:class:`~stepcontact.model.records.AccelerationRecord`,
    :class:`~stepcontact.model.records.GroundMotion`; a positive value accelerates the ground
    along +axis, the displacements are relative to the ground).

    Checked at once (:func:`~stepcontact.model.timefunction.check_newmark`: dt and duration
    positive, α ∈ :data:`~stepcontact.model.timefunction.HHT_ALPHA_RANGE`, e ∈ [0, 1];
    :func:`~stepcontact.model.timefunction.check_interval`): dt ≤ duration,
    the step count, loads that act inside [0, duration], and at least 10 steps per period of
    a varying load (a harmonic; 5 steps in the duration of a half-sine or triangular pulse or
    of a table that returns to zero).

    ``crack_water``: the water in the opened joints (:class:`~stepcontact.model.CrackWater`)
    during the interval, one of :data:`CRACK_WATER_CHOICES` (the guidelines differ on it:
    the user guide's *Crack water during an earthquake*): ``"full"`` (default) — water
    enters every opening joined to the entry at its crack pressure, which follows its time
    function, and leaves a CFE that closes; ``"unchanged"`` — the pre-earthquake wet set and
    its pressures (at the factors of the state the interval starts from) are held: no water
    enters a new opening (the joint's uplift acts there, as before the earthquake), a held
    CFE that closes carries contact force and gets its held pressure back when it reopens;
    ``"none"`` — as ``"unchanged"``, but a CFE closed at the start that opens during the
    interval carries no water pressure at all from then on, open or closed again (the
    joint's uplift is cancelled there, W = −A p_u)."""

    dt: float
    duration: float
    loads: tuple = ()
    mass: str = "consistent"
    damping: tuple[float, float] = (0.0, 0.0)
    restitution: float = 0.0
    record_every: int = 1
    alpha: float = 0.0
    max_steps: int = MAX_STEPS
    ground: object = None
    crack_water: str = "full"  # (issue 29 §1: crack water during an earthquake)

    def __post_init__(self):
        # dt, duration, HHT-α and e: the rules solve_dynamic applies to its own arguments
        check_newmark(self.dt, self.duration, alpha=self.alpha, restitution=self.restitution,
                      prefix="dynamics.")
        if self.mass not in MASS_KINDS:
            raise ModelError("dynamics.mass", f"must be {_either(MASS_KINDS)}, got "
                             f"'{self.mass}'")
        if len(tuple(self.damping)) != 2 or not all(np.isfinite(x) and x >= 0
                                                    for x in self.damping):
            raise ModelError("dynamics.damping", f"must be two non-negative Rayleigh "
                             f"coefficients (a0, a1), got {self.damping!r}")
        if int(self.record_every) < 1:
            raise ModelError("dynamics.record_every", "must be at least 1")
        check_crack_water(self.crack_water, "dynamics.crack_water")
        object.__setattr__(self, "loads", tuple((str(n), g) for n, g in self.loads))
        object.__setattr__(self, "damping", tuple(float(x) for x in self.damping))
        ground = None
        if self.ground is not None:
            if not hasattr(self.ground, "components"):
                raise ModelError("dynamics.ground", "must be a record (AccelerationRecord) or "
                                 f"a GroundMotion, got {type(self.ground).__name__}")
            ground = {f"dynamics.ground ({ax})": g for g, ax in self.ground.components()}
        check_interval(self.dt, self.duration, dict(self.loads), max_steps=self.max_steps,
                       prefix="dynamics.", ground=ground)


@dataclass(frozen=True, eq=False)
class Model:
    """A structural model, 2D or 3D (the dimension follows from the bodies' meshes,
    :attr:`dim`).

    Parameters
    ----------
    bodies : tuple of Body or Frame
        Global node numbering follows this order: the nodes of ``bodies[0]`` first, etc.
    plane : "strain" or "stress"
        2D only (a 3D model leaves it at its default).
    thickness : float
        Out-of-plane thickness, m (1 m for plane strain per metre run); 2D only.
    """

    bodies: tuple = ()
    plane: str = "strain"
    thickness: float = 1.0
    supports: tuple[Support, ...] = ()
    ties: tuple[Tie, ...] = ()
    springs: tuple[Spring, ...] = ()
    interfaces: tuple[Interface, ...] = ()
    patterns: tuple[LoadPattern, ...] = ()
    program: tuple[Segment, ...] = ()
    name: str = "model"
    #: a dynamic interval after the program (:class:`DynamicInterval`), or None
    dynamics: DynamicInterval | None = None
    #: construction stages (:class:`~stepcontact.model.stages.Stage`); with stages the
    #: program is theirs and ``program`` must be empty
    stages: tuple = ()
    #: the reservoirs' added masses on faces (:class:`~stepcontact.model.seismic.AddedMass`),
    #: added to the mass matrix of a dynamic interval
    added_masses: tuple = ()

    def __post_init__(self):
        for key in ("bodies", "supports", "ties", "springs", "interfaces", "patterns", "program",
                    "stages", "added_masses"):
            object.__setattr__(self, key, tuple(getattr(self, key)))
        for i, am in enumerate(self.added_masses):
            if getattr(type(am), "model_field", None) != "added_masses":
                raise ModelError(f"model.added_masses[{i}]", f"must be an AddedMass (a "
                                 f"reservoir on a face), got {type(am).__name__}")
        if self.stages and self.program:
            raise ModelError("model.program", "is given together with stages: with stages the "
                             "load program is the stages' own (Stage(program=...))")
        names = [st.name for st in self.stages]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ModelError(f"stage '{sorted(dup)[0]}'", "duplicate stage name")
        last = getattr(self.stages[-1], "dynamics", None) if self.stages else None
        if last is not None and self.dynamics is not last:
            if self.dynamics is not None:
                raise ModelError(f"stage '{self.stages[-1].name}'.dynamics", "is given together "
                                 "with model.dynamics: give the dynamic interval once")
            object.__setattr__(self, "dynamics", last)  # the model's dynamic interval
        if self.plane not in PLANE_KINDS:
            raise ModelError("model.plane", f"must be {_either(PLANE_KINDS)}, got '{self.plane}'")
        if not np.isfinite(self.thickness) or self.thickness <= 0:
            raise ModelError("model.thickness", f"must be positive, got {self.thickness}")
        seen: set[str] = set()
        for b in self.bodies:
            if b.name in seen:
                raise ModelError(f"body '{b.name}'", "duplicate body name")
            seen.add(b.name)
        _check_stiffness_ratio(self.bodies)
        _check_dimension(self)
        for kind, items in (("pattern", self.patterns), ("interface", self.interfaces)):
            names = [it.name for it in items]
            dup = {n for n in names if names.count(n) > 1}
            if dup:
                raise ModelError(f"{kind} '{sorted(dup)[0]}'", f"duplicate {kind} name")
        obstacles: dict[str, RigidObstacle] = {}
        for itf in self.interfaces:
            obs = itf.minus
            if isinstance(obs, RigidObstacle):
                if obs.name in obstacles and not obstacles[obs.name].same_as(obs):
                    raise ModelError(f"obstacle '{obs.name}'", "two different obstacles have "
                                     f"this name (interface '{itf.name}' and an earlier one)")
                obstacles.setdefault(obs.name, obs)

    # ---- construction -----------------------------------------------------------------------
    def add(self, *items) -> Model:
        """Return a new model with ``items`` added (bodies, frames, supports, ties, springs,
        interfaces, load patterns, segments, stages), dispatched on their type: one of this
        module's, or a type that names its field of the model in ``model_field`` (a
        :class:`~stepcontact.model.Stage`, whose module builds on this one)."""
        groups: dict[str, list] = {
            k: list(getattr(self, k))
            for k in ("bodies", "supports", "ties", "springs", "interfaces", "patterns", "program",
                      "stages")
        }
        kinds = {
            Body: "bodies",
            Frame: "bodies",
            Support: "supports",
            Tie: "ties",
            Spring: "springs",
            Interface: "interfaces",
            LoadPattern: "patterns",
            Segment: "program",
        }
        for it in items:
            key = kinds.get(type(it)) or getattr(type(it), "model_field", None)
            if isinstance(it, RigidObstacle | ObstacleMotion):
                raise ModelError("model.add", f"obstacle '{it.name}' enters a model as the minus "
                                 "side of an Interface (and its motion as a load of a "
                                 "LoadPattern), not by itself")
            if key is None:
                raise ModelError("model.add", f"cannot add an object of type {type(it).__name__}")
            groups.setdefault(key, list(getattr(self, key))).append(it)
        return dataclasses.replace(self, **{k: tuple(v) for k, v in groups.items()})

    def replace(self, **changes) -> Model:
        """A copy with fields replaced (``dataclasses.replace``)."""
        return dataclasses.replace(self, **changes)

    def with_friction(self, friction: float, interface: str | None = None) -> Model:
        """A copy with the friction coefficient of ``interface`` (every interface when None)
        set to ``friction``: the stiffness and contact operator are unchanged, so a
        condensation (:func:`stepcontact.condense`) of this model serves the copy too."""
        names = [i.name for i in self.interfaces]
        if interface is not None and interface not in names:
            raise ModelError(f"interface '{interface}'",
                             f"no such interface (known: {', '.join(map(repr, names)) or 'none'})")
        return self.replace(interfaces=tuple(
            dataclasses.replace(i, friction=friction) if interface in (None, i.name) else i
            for i in self.interfaces))

    # ---- lookup -------------------------------------------------------------------------------
    def body(self, name: str) -> Body | Frame:
        for b in self.bodies:
            if b.name == name:
                return b
        known = ", ".join(repr(b.name) for b in self.bodies) or "none"
        raise ModelError(f"body '{name}'", f"no such body (known: {known})")

    def pattern(self, name: str) -> LoadPattern:
        for p in self.patterns:
            if p.name == name:
                return p
        known = ", ".join(repr(p.name) for p in self.patterns) or "none"
        raise ModelError(f"load pattern '{name}'", f"no such pattern (known: {known})")

    @property
    def node_offsets(self) -> dict[str, int]:
        """Global index of local node 0 of every body."""
        out, k = {}, 0
        for b in self.bodies:
            out[b.name] = k
            k += b.n_nodes
        return out

    # ---- rigid obstacles ----------------------------------------------------------------------
    @property
    def obstacles(self) -> tuple[RigidObstacle, ...]:
        """The rigid obstacles of the interfaces (``Interface.minus``), in order of first use."""
        out: dict[str, RigidObstacle] = {}
        for itf in self.interfaces:
            if isinstance(itf.minus, RigidObstacle):
                out.setdefault(itf.minus.name, itf.minus)
        return tuple(out.values())

    def obstacle(self, name: str) -> RigidObstacle:
        for o in self.obstacles:
            if o.name == name:
                return o
        known = ", ".join(repr(o.name) for o in self.obstacles) or "none"
        raise ModelError(f"obstacle '{name}'", "no interface of the model has it as its minus "
                         f"side (obstacles: {known})")

    @property
    def moving_obstacles(self) -> tuple[RigidObstacle, ...]:
        """The obstacles some load pattern moves (:class:`ObstacleMotion`): they have nodes."""
        moved = {ld.name for p in self.patterns for ld in p.loads
                 if isinstance(ld, ObstacleMotion)}
        return tuple(o for o in self.obstacles if o.name in moved)

    @property
    def obstacle_offsets(self) -> dict[str, int]:
        """Global index of the first vertex node of every moving obstacle (after all the
        bodies' nodes; a fixed obstacle has no nodes)."""
        out, k = {}, sum(b.n_nodes for b in self.bodies)
        for o in self.moving_obstacles:
            out[o.name] = k
            k += o.n_nodes
        return out

    @property
    def n_nodes(self) -> int:
        """Number of nodes: those of the bodies and the vertices of moving obstacles."""
        return (sum(b.n_nodes for b in self.bodies)
                + sum(o.n_nodes for o in self.moving_obstacles))

    @property
    def dim(self) -> int:
        """The model's dimension, from its bodies' meshes: 3 when its bodies are solids
        (``MeshTet``/``MeshHex``), else 2."""
        return 3 if any(getattr(b, "dim", 2) == 3 for b in self.bodies) else 2

    @property
    def points(self) -> np.ndarray:
        """Coordinates of all nodes, (n_nodes, dim), m, in global numbering (the bodies' nodes,
        then the vertices of the moving obstacles)."""
        parts = [b.points for b in self.bodies] + [o.points for o in self.moving_obstacles]
        if not parts:
            return np.zeros((0, 2))
        return np.vstack(parts)

    def global_nodes(self, ns: NodeSet) -> np.ndarray:
        """Global node indices of a node set (checks that the set is valid)."""
        b = self.body(ns.body)
        if ns.index.size and (ns.index.min() < 0 or ns.index.max() >= b.n_nodes):
            raise ModelError(ns.label, f"refers to nodes that body '{b.name}' does not have")
        return self.node_offsets[b.name] + ns.index

    def select(
        self,
        body: str,
        where: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None,
        *,
        x: float | None = None,
        y: float | None = None,
        z: float | None = None,
        boundary: bool | str = True,
        name: str = "",
        atol: float | None = None,
    ) -> NodeSet:
        """Nodes of ``body`` by a predicate ``where(x, y)`` (``where(x, y, z)`` for a 3D body)
        or by coordinate (``x=``/``y=``/``z=``).

        With ``boundary=True`` (default) only nodes on the body's boundary are returned,
        which is what loads, supports and interfaces need.  ``boundary="top"`` takes the nodes
        of a named boundary of the body's mesh (those of :func:`~stepcontact.model.mesh.box`:
        ``left``/``right`` at x min/max, ``front``/``back`` at y min/max, ``bottom``/``top`` at
        z min/max); an unknown name is an error naming the body and the boundary.  An empty
        selection is an error.

        Example
        -------
        >>> base = m.select("column", boundary="bottom")               # doctest: +SKIP
        """
        b = self.body(body)
        return select_nodes(b, where, x=x, y=y, z=z, boundary=boundary, name=name, atol=atol)

    def segments_resolved(self) -> list[tuple[str, float, float]]:
        """The load program as (pattern or segment name, start, end), with starts filled in and
        chaining checked: ``start`` must equal the factor the pattern has reached (a segment
        with rates moves each of its patterns by rate × its span).

        Resolved once per model (it is immutable): a solver hook that gets a result after
        every segment must not cost O(segments) each time, i.e. O(segments²) in all."""
        cached = self.__dict__.get("_program_resolved")
        if cached is not None:
            return list(cached)
        out = []
        for i, seg, now, start in self.program_walk():
            if abs(start - now) > 1e-12 * max(1.0, abs(now)):
                raise ModelError(
                    f"program segment {i} ('{seg.pattern}').start",
                    f"does not chain: pattern '{seg.pattern}' stands at λ = {now:g}, "
                    f"segment starts at {start:g}",
                )
            out.append((seg.pattern, start, float(seg.end)))
        object.__setattr__(self, "_program_resolved", tuple(out))
        return out

    def program_walk(self) -> Iterator[tuple[int, Segment, float, float]]:
        """Each segment of the program (:attr:`effective_program`) as (index, segment, the
        factor its pattern stands at before it, its start: given, or that factor).  The one
        place of the chaining rule (:meth:`segments_resolved` refuses a start that is not where
        the pattern stands; a model file reports it at the entry's path): a pattern stands where
        its last segment ended, a segment with rates moves each of its patterns by rate × its
        span, and the dynamic interval of an earlier stage by g(T).  ModelError for a pattern
        that does not exist, empty or non-finite rates, a label of rates that is a pattern."""
        current: dict[str, float] = {}
        jumps = self.dynamic_jumps()
        for i, seg in enumerate(self.effective_program):
            for name, dg in jumps.get(i, {}).items():  # a dynamic interval moved these
                current[name] = current.get(name, 0.0) + dg
            item = f"program segment {i} ('{seg.pattern}')"
            if seg.rates is None:
                self.pattern(seg.pattern)  # raises with the name
            else:
                if not seg.rates:
                    raise ModelError(f"{item}.rates", "is empty: give {pattern: rate, …}")
                if seg.pattern in {p.name for p in self.patterns}:
                    raise ModelError(item, "a segment with rates is named by a label that is "
                                     "not a load pattern")
                for name, rate in seg.rates:
                    self.pattern(name)
                    if not np.isfinite(rate):
                        raise ModelError(f"{item}.rates['{name}']", "is not finite")
            now = current.get(seg.pattern, 0.0)
            start = now if seg.start is None else float(seg.start)
            if not np.isfinite(seg.end) or not np.isfinite(start):
                raise ModelError(item, "start/end not finite")
            yield i, seg, now, start
            current[seg.pattern] = float(seg.end)
            for name, rate in seg.rates or ():  # the patterns a segment with rates moved
                current[name] = current.get(name, 0.0) + rate * (float(seg.end) - start)

    def dynamic_jumps(self) -> dict[int, dict[str, float]]:
        """The factor changes g(T) of the load patterns of the dynamic intervals of stages
        before the last, keyed by the number of program segments before them (the static
        program goes on from the factors the interval ends at)."""
        out: dict[int, dict[str, float]] = {}
        n = 0
        for st in self.stages[:-1]:
            n += len(st.program)
            dyn = getattr(st, "dynamics", None)
            if dyn is None:
                continue
            jump = out.setdefault(n, {})
            for name, g in dyn.loads:
                item = f"stage '{st.name}'.dynamics.loads['{name}']"
                if name not in {p.name for p in self.patterns}:
                    raise ModelError(item, f"no such load pattern (known: "
                                     f"{', '.join(repr(p.name) for p in self.patterns) or 'none'})")
                if not callable(g):
                    raise ModelError(item, "must be a time function g(t)")
                value = float(g(float(dyn.duration)))
                if not np.isfinite(value):
                    raise ModelError(item, f"is not finite at the interval's end "
                                     f"(t = {dyn.duration:g} s)")
                jump[name] = jump.get(name, 0.0) + value
        return out

    def segment_rates(self) -> list[dict[str, float]]:
        """For every segment of the program, the rate of each pattern it moves per unit of the
        segment's parameter ({pattern: 1} for a single-pattern segment)."""
        return [{seg.pattern: 1.0} if seg.rates is None else dict(seg.rates)
                for seg in self.effective_program]

    @property
    def effective_program(self) -> tuple[Segment, ...]:
        """The load program: ``program``, or with stages their programs in order."""
        if self.stages:
            return tuple(seg for st in self.stages for seg in st.program)
        return self.program
