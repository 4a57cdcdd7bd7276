"""Result objects of a static run: the event log, the state after every event, fields.

A :class:`StaticResult` has named fields (never numbered columns) and is saved to / loaded from
one netCDF4/HDF5 file through xarray (:mod:`stepcontact.results.file`).  Units: forces N,
stresses Pa, displacements m; contact stresses are N/A_k and Q/A_k in Pa.

Reported states are indexed by ``i``: state 0 is the start of the program; every event point
gives one state (the working scheme *after* the switch, forces at the event); the end of every
load segment gives one state.  Between two consecutive states the path is linear in λ.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from stepcontact.contact.layout import ContactLayout
from stepcontact.enums import FACET_SLIP, ContactState, Status, Transition, state_label
from stepcontact.fem.level import VIRTUAL, is_virtual
from stepcontact.results.events import Event, Multipliers
from stepcontact.results.file import (
    dataset_arguments,
    read_dataset,
    result_to_dataset,
    save_result,
    state_flag_attrs,
    tangent_labels,
)
from stepcontact.results.safety import interface_safety
from stepcontact.results.safety3d import interface_safety_3d

#: a model is the one of a result when a stored displacement field, recomputed from its contact
#: unknowns, agrees to this (relative to the largest displacement) ...
RECOVERY_RTOL = 1e-6
#: ... or else — an ill-conditioned model, whose recomputation differs in its soft modes by
#: κ·eps between two factorisations (threads, backends) — when the stored field satisfies the
#: model's equilibrium with the stored contact forces to this relative residual (at least; 100 ×
#: the run's own residual at that state), a backward error free of the conditioning; another
#: material or geometry leaves residuals of the order of the change (1e-2 for 1 % in E)
RECOVERY_RESIDUAL = 1e-8


#: the solver's field recovery, ``recover(result, model)``: results know no solver, the solver
#: provides it (:func:`stepcontact.solver.recovery.recover_fields`, given here by
#: :func:`provide_field_recovery` when :mod:`stepcontact.solver` is imported, as
#: ``import stepcontact`` does)
_FIELD_RECOVERY: list[Callable] = []


def provide_field_recovery(recover: Callable) -> None:
    """Make ``recover(result, model)`` the field recovery of :meth:`StaticResult.recover_fields`
    (the solver's: :mod:`stepcontact.solver.recovery`)."""
    _FIELD_RECOVERY[:] = [recover]


def field_recovery() -> Callable:
    """The field recovery the solver provided (:func:`provide_field_recovery`)."""
    if not _FIELD_RECOVERY:
        raise RuntimeError("no field recovery: import stepcontact (its solver recovers fields)")
    return _FIELD_RECOVERY[0]


@dataclass
class StaticResult:
    """Everything a static run produced.

    Arrays with a leading ``n_states`` axis hold one row per reported state; arrays with an
    ``m`` axis one column per CFE.

    Attributes
    ----------
    lam : (n_states,) load factor of the active segment's pattern
    segment : (n_states,) segment index
    factors : (n_states, n_patterns) factors of all patterns
    kind : (n_states,) "start", "segment_start", "event", "segment_end" or "dynamics" (the
        state where the dynamic interval of a stage before the last ends, see ``dynamics``)
    N : (n_states, m) normal CFE force, N (≤ 0 compression)
    Q : (n_states, m) tangential CFE force, N, in 2D; (n_states, m, n_t) with n_t = 2
        tangential components (3D).  :attr:`Q_t` has the tangential axis in every dimension
    un : (n_states, m) mutual normal displacement u_n, m
    ut : (n_states, m) mutual tangential displacement u_τ, m, in 2D; (n_states, m, n_t) in
        3D (:attr:`ut_t`: the tangential axis always)
    state : (n_states, m) state codes (scheme after the state): the :class:`ContactState`
        values in 2D; a faceted Coulomb cone (3D) adds ``FACET_SLIP + i`` and
        ``VERTEX_SLIP + i`` (:mod:`stepcontact.enums`; :func:`~stepcontact.enums.state_label`
        names any code, :meth:`state_labels` those of a state).  Stored as int16 by a run
    residual : (n_states,) relative equilibrium residual ‖K u + Bᵀs − f‖ / ‖f‖ at states with a
        stored displacement field; at the other states the residual of the condensed
        equations, which are exactly equivalent (see ``Condensed.condensed_residual``)
    violation : (n_states,) largest relative violation of conditions (1)
    events : list of Event
    multipliers : list of Multipliers (one per segment reached)
    status : Status
    message : str
    fields : dict state index -> displacement vector (ndof,), m, of the states with a stored
        field (by default the start, segment starts and ends and the last state; every state
        with ``store_fields="all"``).  Any state: :meth:`displacement`, :meth:`displacements`.
    stresses : dict state index -> {body name: (n_el, 4) σxx, σyy, σxy, σzz, Pa; a 3D body's
        (n_el, 6) σxx, σyy, σzz, σxy, σyz, σxz}, stored at the same states as ``fields``.
        Any state: :meth:`stress`, :meth:`stresses_at`.
    counters : dict of run statistics (events, rate solves, factorisations, solves, seconds)
    mechanism : description of the mechanism when equilibrium is lost (bodies, mode)
    geometry : "points" (n_nodes, 2) (3D: (n_nodes, 3)), "dof_of" (n_nodes, 3), "bodies" list of
        {"name", "kind", "element", "cells"} — enough to draw and export fields
    reactions : (n_states, n_r) resultant reactions of the supports on the structure, N
        (N·m for rz), at every state: one column per ``reaction_labels`` entry
        (``"support:x"``, ``"support:y"``, ``"support:rz"``; DOFs prescribed by a load pattern:
        ``"pattern (prescribed):x"``)
    water : (n_states, m) or None
        Force of the water in the opened parts of joints on each CFE beyond the joint's uplift,
        N (:class:`~stepcontact.model.CrackWater`): A_k (p_crack − p_uplift) where the water
        acts, 0 elsewhere; it acts like a compressive normal force across the gap.  None for a
        model without crack water.
    crack_pressure : (n_states, m) or None
        Water pressure in the opened parts of joints, Pa (≥ 0): γ_w (h_w − y) where the water
        has entered, 0 where the joint is closed or dry.  None without crack water.
    load_resultants : (n_patterns, 3) resultant of every load pattern's forces per unit λ, in
        the order of ``pattern_names``: F_x, F_y in N and M_z = Σ (x f_y − y f_x) (+ nodal
        moments) about the origin in N·m (:meth:`load_resultant`; prescribed displacements
        are not forces and do not count); a 3D model's (n_patterns, 6): F_x, F_y, F_z, M_x,
        M_y, M_z (M = Σ x × f + nodal moments about the origin)

    Tangential quantities (``Q``, ``ut``, ``tau``) have a tangential axis of n_t components
    (:attr:`n_t`: 1 in 2D, 2 in 3D) along the CFE's tangents t₁[, t₂]: :attr:`Q_t`,
    :attr:`ut_t`, :attr:`tau_t` are (n_states, m, n_t) in every dimension (views of ``Q``,
    ``ut``: the 2D arrays are the same numbers without that axis, which 2D code keeps using).

    Node results along the path: :meth:`node_history` (ux, uy, rz of a node, a node set or
    the node nearest a point; velocities — None in statics), :meth:`reaction_history` (the
    reaction summed over a support or a node set) and :meth:`history` (any of these, or a CFE
    quantity, by name).
    """

    pattern_names: tuple[str, ...]
    segments: list[tuple[str, float, float]]
    cfe: dict[str, np.ndarray]
    interface_names: tuple[str, ...]
    lam: np.ndarray
    segment: np.ndarray
    factors: np.ndarray
    kind: np.ndarray
    N: np.ndarray
    Q: np.ndarray
    un: np.ndarray
    ut: np.ndarray
    state: np.ndarray
    residual: np.ndarray
    violation: np.ndarray
    events: list[Event]
    multipliers: list[Multipliers]
    status: Status
    message: str
    fields: dict[int, np.ndarray] = field(default_factory=dict)
    stresses: dict[int, dict[str, np.ndarray]] = field(default_factory=dict)
    counters: dict[str, float] = field(default_factory=dict)
    mechanism: dict[str, object] | None = None
    geometry: dict[str, object] = field(default_factory=dict)
    reactions: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    reaction_labels: tuple[str, ...] = ()
    load_resultants: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    #: (n_patterns, n_bodies, 7) or None: the loads of every pattern per unit λ on every body
    #: (bodies in the order of ``geometry["bodies"]``), columns
    #: :data:`~stepcontact.fem.assembly.LOAD_MOMENT_COMPONENTS`: F_x, F_y (N), the first-moment
    #: tensor S_ab = Σ x_a f_b (N·m) and the nodal moments Σ m_z (N·m) — the moment of a body's
    #: loads about any point along any direction (the overturning factor of
    #: :meth:`interface_safety`).  None: a discrete model, or a result written before it was
    #: stored
    load_moments: np.ndarray | None = None
    units: dict[str, str] = field(
        default_factory=lambda: {
            "lam": "1", "N": "N", "Q": "N", "un": "m", "ut": "m", "sigma_n": "Pa",
            "tau": "Pa", "u": "m", "stress": "Pa", "position": "m", "area": "m2",
        }
    )
    water: np.ndarray | None = None
    crack_pressure: np.ndarray | None = None
    #: rate problems with several admissible schemes: {"lam", "segment", "pattern", "cfes",
    #: "followed", "alternatives", "why"} (state labels per CFE)
    nonunique: list[dict[str, object]] = field(default_factory=list)
    #: recomputes the fields of states from their contact unknowns (in memory only: it holds
    #: the run's factorisation; dropped when pickled or saved): a
    #: :class:`~stepcontact.solver.recovery.FieldRecovery` (``displacements(states)`` in one
    #: solve, ``stresses(u)``), or any callable state index -> displacement vector
    _recover: Callable[[int], np.ndarray] | None = field(default=None, repr=False)
    #: construction stages (:class:`~stepcontact.model.stages.Stage`): the stage of every
    #: state (n_states,), the stages' names, the CFEs active at each stage (n_stages, m) and
    #: the bodies built by each stage; None / empty for a run without stages
    stage: np.ndarray | None = None
    stage_names: tuple[str, ...] = ()
    stage_cfes: np.ndarray | None = None
    stage_bodies: tuple[tuple[str, ...], ...] = ()
    #: the dynamic intervals of stages before the last (:class:`~stepcontact.model.Stage`
    #: ``dynamics``), by stage name: each a
    #: :class:`DynamicResult` (time axis, velocities, energy
    #: ledger, its events located in time).  The path of this result holds the state where
    #: each interval ends (kind ``dynamics``) in the segment ``"<stage>: settle after
    #: dynamics"`` that follows it.  In memory (the CLI writes each to its own file)
    dynamics: dict = field(default_factory=dict, repr=False)

    def active_cfes(self, i: int) -> np.ndarray:
        """(m,) bool: the CFEs that act at state ``i`` (all of them without stages)."""
        if self.stage is None:
            return np.ones(self.m, bool)
        return np.asarray(self.stage_cfes[int(self.stage[i])], bool)

    def active_bodies(self, i: int) -> set[str]:
        """The names of the bodies built at state ``i`` (every body without stages)."""
        if self.stage is None:
            return {b["name"] for b in self.geometry.get("bodies", [])}
        return set(self.stage_bodies[int(self.stage[i])])

    def __getstate__(self) -> dict:
        state = dict(self.__dict__)
        state["_recover"] = None
        return state

    def recover_fields(self, model) -> None:
        """Attach field recovery to a result loaded from a file or unpickled: ``model`` (the
        model of the run, or its assembled system) is condensed once more (one
        factorisation); :meth:`displacement`, :meth:`displacements`, :meth:`stress` and
        :meth:`stresses_at` then recompute any state exactly from its contact unknowns.

        The model is checked against the result: the same CFEs, load patterns and DOFs, and
        the field recomputed at a stored state equal to the stored one to
        :data:`RECOVERY_RTOL`, or else the stored field in this model's equilibrium with the
        stored contact forces to :data:`RECOVERY_RESIDUAL` (a tolerance scaled to the model:
        its conditioning does not enter); otherwise ValueError.  A staged run stores the field of
        every state and needs no recovery: nothing is done.  A :class:`DynamicResult` stores
        the displacements of every state: its model gives the stresses.

        Recovering fields is the solver's: this is
        :func:`stepcontact.solver.recovery.recover_fields` (``recover_fields(res, model)``).
        """
        field_recovery()(self, model)

    # ---- convenience -----------------------------------------------------------------------
    #: the path axis of the states: the load factor of the active segment here; a time (s) or
    #: a stage for the drivers to come (the file records it as ``path_axis``)
    path_axis = "lam"

    @property
    def path(self) -> np.ndarray:
        """The path parameter of every state (``path_axis``: λ of the active segment)."""
        return getattr(self, self.path_axis)

    @property
    def n_states(self) -> int:
        return len(self.lam)

    @property
    def m(self) -> int:
        return self.N.shape[1]

    @property
    def n_t(self) -> int:
        """Number of tangential components per CFE: 1 in 2D, 2 in 3D (``Q`` with a third
        axis)."""
        Q = np.asarray(self.Q)
        return int(Q.shape[2]) if Q.ndim == 3 else 1

    @property
    def layout(self) -> ContactLayout:
        """The layout of the contact unknowns of the run: m CFEs with n_t tangential
        components (:class:`~stepcontact.contact.layout.ContactLayout`)."""
        return ContactLayout(self.m, self.n_t)

    @staticmethod
    def _with_tangent_axis(x: np.ndarray) -> np.ndarray:
        """``x`` (n_states, m) or (n_states, m, n_t) as (n_states, m, n_t): a view."""
        x = np.asarray(x)
        return x if x.ndim == 3 else x[..., None]

    @property
    def Q_t(self) -> np.ndarray:
        """Tangential CFE forces with the tangential axis always present, (n_states, m, n_t),
        N: component j along the CFE's tangent t_(j+1); in 2D a view of ``Q`` (n_t = 1)."""
        return self._with_tangent_axis(self.Q)

    @property
    def ut_t(self) -> np.ndarray:
        """Mutual tangential displacements with the tangential axis always present,
        (n_states, m, n_t), m; in 2D a view of ``ut`` (n_t = 1)."""
        return self._with_tangent_axis(self.ut)

    @property
    def tau_t(self) -> np.ndarray:
        """Tangential contact stress Q_t/A_k with the tangential axis, (n_states, m, n_t), Pa."""
        return self.Q_t / self.cfe["area"][None, :, None]

    @property
    def cone_ratio(self) -> np.ndarray:
        """The true-cone ratio |Q| / (f |N|) of every CFE at every state, (n_states, m): 1 on
        the Coulomb cone; a faceted cone's polygon (3D, k facets) reaches it at its vertices
        and cos(π/k) in its facets' middles, so a slipping CFE's ratio lies in
        [cos(π/k), 1].  NaN where f |N| = 0 (frictionless) and where the CFE is open (its
        forces are round-off there)."""
        f = np.asarray(self.cfe.get("friction", np.full(self.Q_t.shape[1], np.nan)), float)
        fN = f[None, :] * np.abs(np.asarray(self.N))
        fN = np.where(np.asarray(self.state) == int(ContactState.OPEN), 0.0, fN)
        q = np.linalg.norm(self.Q_t, axis=2)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(fN > 0, q / np.where(fN > 0, fN, 1.0), np.nan)

    def state_labels(self, i: int) -> list[str]:
        """What users see for the state of every CFE at state ``i`` (``"stick"``,
        ``"slip+"``, ``"slip (facet 3)"`` …: :func:`~stepcontact.enums.state_label`)."""
        return [state_label(v) for v in np.asarray(self.state[i]).tolist()]

    @property
    def sigma_n(self) -> np.ndarray:
        """Normal contact stress N/A_k, Pa (≤ 0 compression)."""
        return self.N / self.cfe["area"][None, :]

    @property
    def tau(self) -> np.ndarray:
        """Tangential contact stress Q/A_k, Pa: the shape of ``Q`` ((n_states, m) in 2D,
        (n_states, m, n_t) in 3D)."""
        Q = np.asarray(self.Q)
        area = np.asarray(self.cfe["area"])
        return Q / (area[None, :, None] if Q.ndim == 3 else area[None, :])

    def states_of(self, i: int) -> list[ContactState | int]:
        """The state of every CFE at state ``i``: a :class:`ContactState` (2D codes), the
        plain code of a faceted cone's slip (≥ :data:`~stepcontact.enums.FACET_SLIP`; named by
        :meth:`state_labels`)."""
        return [v if v >= FACET_SLIP else ContactState(v)
                for v in np.asarray(self.state[i]).tolist()]

    def _cfe_keys(self) -> tuple[str, ...]:
        """The CFE quantities of a state: N, Q, u_n, u_τ (and the crack pressure)."""
        return ("N", "Q", "un", "ut") + (("crack_pressure",) if self.crack_pressure is not None
                                         else ())

    def interpolate(self, lam: float, segment: int | None = None) -> dict[str, np.ndarray]:
        """CFE quantities at any λ of a segment (exact: the path is linear between events).

        Not for a segment that moves a water level (its path is a polynomial in the level
        between events): end a segment at the level you need instead."""
        seg = self.segment[-1] if segment is None else segment
        pattern = self.segments[int(seg)][0] if int(seg) < len(self.segments) else None
        if pattern in self.level_patterns:
            idx = np.flatnonzero(self.segment == seg)
            at = idx[np.abs(self.lam[idx] - lam) <= 1e-12 * max(1.0, abs(lam))]
            if at.size:  # a recorded state: exact
                i = at[-1]
                return ({k: getattr(self, k)[i] for k in self._cfe_keys()}
                        | {"state": self.state[i]})
            raise ValueError(f"segment {seg} moves the water level of '{pattern}': its states "
                             "are not linear in the level between events; end a segment at "
                             f"λ = {lam} to have the state there")
        idx = np.flatnonzero(self.segment == seg)
        lams = self.lam[idx]
        lo, hi = min(lams), max(lams)
        if not lo - 1e-12 <= lam <= hi + 1e-12:
            raise ValueError(f"λ = {lam} outside segment {seg} range [{lo}, {hi}]")
        # consecutive states bracket lam (events are ordered along the segment's path)
        for a, b in zip(idx[:-1], idx[1:], strict=True):
            la, lb = self.lam[a], self.lam[b]
            if min(la, lb) - 1e-12 <= lam <= max(la, lb) + 1e-12:
                t = 0.0 if lb == la else (lam - la) / (lb - la)
                return {
                    k: (1 - t) * getattr(self, k)[a] + t * getattr(self, k)[b]
                    for k in self._cfe_keys()
                } | {"state": self.state[a]}
        i = idx[-1]
        return {k: getattr(self, k)[i] for k in self._cfe_keys()} | {"state": self.state[i]}

    def reaction(self, support: str, dof: str = "y") -> np.ndarray:
        """History (n_states,) of the resultant reaction of ``support`` on the structure along
        ``dof`` ("x", "y": N; "rz": N·m).  ``support`` is a support name, or a load pattern's
        name for the DOFs it prescribes."""
        for label in (f"{support}:{dof}", f"{support} (prescribed):{dof}"):
            if label in self.reaction_labels:
                return self.reactions[:, self.reaction_labels.index(label)]
        known = sorted({lb.rsplit(":", 1)[0] for lb in self.reaction_labels})
        raise KeyError(f"no reaction '{support}' along {dof} (reactions: "
                       f"{', '.join(f'{k!r}' for k in known) or 'none'})")

    def load_resultant(self, pattern: str, state: int | None = None) -> np.ndarray:
        """Resultant of the forces of load pattern ``pattern`` about the origin: [F_x, F_y,
        M_z] (N, N, N·m) in 2D; in 3D the force and moment vectors [F_x, F_y, F_z, M_x, M_y,
        M_z] (N and N·m, M = Σ x_i × f_i + Σ m_i, :func:`stepcontact.fem.assembly.
        load_resultant`).  Per unit λ, or with ``state`` the load applied at that state
        (factor × the per-unit resultant).  A pattern whose factor is a water level has no
        per-unit resultant: give ``state``.  NaN for a result written before the resultants
        were stored."""
        if pattern not in self.pattern_names:
            raise KeyError(f"no load pattern '{pattern}' (patterns: "
                           f"{', '.join(map(repr, self.pattern_names)) or 'none'})")
        R = np.asarray(self.load_resultants, dtype=float)
        if R.ndim != 2 or R.shape[0] != len(self.pattern_names) or R.shape[1] not in (3, 6):
            return np.full(6 if self.n_t > 1 else 3, np.nan)  # not stored (older files)
        if state is None:
            return R[self.pattern_names.index(pattern)]
        names = self.level_patterns.get(pattern, (pattern,))
        idx = [self.pattern_names.index(n) for n in names]
        return np.asarray(self.factors)[state, idx] @ R[idx]

    @property
    def level_patterns(self) -> dict[str, tuple[str, ...]]:
        """Patterns whose factor is a water level, with the virtual patterns that carry their
        loads (:mod:`stepcontact.fem.level`)."""
        out: dict[str, list[str]] = {}
        for name in self.pattern_names:
            if is_virtual(name):
                out.setdefault(name.split(VIRTUAL)[0], []).append(name)
        return {k: tuple(v) for k, v in out.items()}

    # ---- results per node along the path ---------------------------------------------------
    def _bodies(self) -> list[dict]:
        return list(self.geometry.get("bodies", []) or [])

    @property
    def node_sets(self) -> dict[str, np.ndarray]:
        """{name: global node ids} of the named node sets the model's supports, ties,
        springs, interfaces and loads use (from ``geometry``: ``node_set_names``,
        ``node_set_offsets``, ``node_set_nodes``)."""
        geo = self.geometry
        names = [str(n) for n in np.asarray(geo.get("node_set_names", []))]
        off = np.asarray(geo.get("node_set_offsets", [0]), dtype=np.int64)
        nodes = np.asarray(geo.get("node_set_nodes", []), dtype=np.int64)
        return {n: nodes[off[j]:off[j + 1]] for j, n in enumerate(names)}

    @property
    def _dim(self) -> int:
        """3 when the result's nodes have three coordinates (a 3D model), else 2."""
        pts = self.geometry.get("points") if isinstance(self.geometry, dict) else None
        return 3 if pts is not None and np.ndim(pts) == 2 and np.shape(pts)[1] == 3 else 2

    def node_ids(self, nodes=None, *, point=None, body: str | None = None) -> np.ndarray:
        """Global node indices (k,) of ``nodes``, or of the node nearest ``point``.

        ``nodes``: a :class:`~stepcontact.model.NodeSet` (body and local indices), the name of
        a named node set of the model (those its supports, loads, springs, ties and
        interfaces use), a global node index or a sequence of them; a pair of floats is read
        as a point.  ``point``: coordinates (x, y) in m, giving the nearest node (``body``
        chooses among coincident nodes of different bodies, which is otherwise an error).
        ``body`` alone: every node of that body.
        """
        if "points" not in self.geometry and "dof_names" in self.geometry:
            raise ValueError("the result of a discrete model has no nodes: its DOFs are the "
                             "columns of res.displacements(), named by "
                             "res.geometry['dof_names']")
        points = np.asarray(self.geometry.get("points", np.zeros((0, 2))), dtype=float)
        n = len(points)
        bodies = self._bodies()
        names = [str(b["name"]) for b in bodies]
        if body is not None and body not in names:
            raise KeyError(f"no body '{body}' (bodies: {', '.join(map(repr, names)) or 'none'})")
        if nodes is not None and point is not None:
            raise TypeError("give nodes or point, not both")
        if (point is None and nodes is not None and not isinstance(nodes, str)
                and not hasattr(nodes, "body") and np.ndim(nodes) == 1
                and np.asarray(nodes).dtype.kind == "f"):
            nodes, point = None, nodes  # (x, y) in floats: a point
        if point is not None:
            return np.array([self._nearest_node(point, body, points, bodies)], dtype=np.int64)
        if nodes is None:
            if body is None:
                raise TypeError("give nodes, point or body")
            return self._body_range(bodies[names.index(body)])
        if isinstance(nodes, str):
            sets = self.node_sets
            if nodes not in sets:
                raise KeyError(f"no node set '{nodes}' in the result (named node sets: "
                               f"{', '.join(map(repr, sets)) or 'none'})")
            ids = np.asarray(sets[nodes], dtype=np.int64).reshape(-1)
        elif hasattr(nodes, "body") and hasattr(nodes, "index"):  # a NodeSet
            if nodes.body not in names:
                raise KeyError(f"node set on body '{nodes.body}': no such body in the result "
                               f"(bodies: {', '.join(map(repr, names)) or 'none'})")
            rng = self._body_range(bodies[names.index(nodes.body)])
            idx = np.asarray(nodes.index, dtype=np.int64)
            if idx.size and (idx.min() < 0 or idx.max() >= len(rng)):
                raise IndexError(f"node set on body '{nodes.body}' refers to nodes the body "
                                 f"does not have (it has {len(rng)})")
            ids = rng[idx]
        else:
            arr = np.asarray(nodes)
            if arr.size and arr.dtype.kind not in "iu":
                raise TypeError(f"nodes: expected node indices, a NodeSet or a node-set name, "
                                f"got {arr.dtype}")
            ids = arr.astype(np.int64).reshape(-1)
        bad = (ids < 0) | (ids >= n)
        if bad.any():
            raise IndexError(f"node {int(ids[bad][0])} does not exist (nodes 0…{n - 1})")
        return ids

    @staticmethod
    def _body_range(b: dict) -> np.ndarray:
        """Global node indices of one body of ``geometry["bodies"]`` (its nodes are numbered
        consecutively from its offset; results written before ``offset`` was stored read it
        off the cells, which use every node)."""
        cells = np.asarray(b["cells"], dtype=np.int64)
        lo = int(b.get("offset", cells.min() if cells.size else 0))
        count = int(b.get("n_nodes", cells.max() + 1 - lo if cells.size else 0))
        return np.arange(lo, lo + count, dtype=np.int64)

    def _nearest_node(self, point, body, points, bodies) -> int:
        try:
            xy = np.asarray(point, dtype=float).reshape(2)
        except (TypeError, ValueError):
            raise TypeError(f"point={point!r}: give the coordinates (x, y) in m") from None
        names = [str(b["name"]) for b in bodies]
        owner = np.full(len(points), -1)
        for j, b in enumerate(bodies):
            owner[self._body_range(b)] = j
        cand = (np.flatnonzero(owner == names.index(body)) if body is not None
                else np.arange(len(points)))
        if not cand.size:
            raise ValueError("the result has no nodes (no geometry)")
        d = np.linalg.norm(points[cand] - xy, axis=1)
        size = float(np.ptp(points, axis=0).max()) if len(points) else 1.0
        if d.min() > 0.05 * size:
            k = int(cand[np.argmin(d)])
            raise ValueError(f"no node near ({xy[0]:g}, {xy[1]:g}): the nearest, node {k} at "
                             f"({points[k, 0]:g}, {points[k, 1]:g}), is {d.min():.3g} m away")
        near = cand[d <= d.min() + 1e-9 * max(size, 1e-300)]
        shared = sorted({names[owner[k]] for k in near if owner[k] >= 0})
        if len(shared) > 1:
            raise ValueError(f"the node at ({xy[0]:g}, {xy[1]:g}) is shared by bodies "
                             f"{', '.join(map(repr, shared))}: choose one with body=...")
        return int(near[0])

    def velocities(self, states=None) -> np.ndarray | None:
        """Velocity vectors (k, ndof), m/s (rad/s for rz), of ``states``: None for a static
        run, which has none (a dynamic result, on a time path axis, returns them)."""
        return None

    def node_history(self, nodes=None, quantity: str = "ux", *, point=None,
                     body: str | None = None) -> np.ndarray | None:
        """A nodal quantity at every reported state, along the path (:attr:`path`).

        Parameters
        ----------
        nodes : NodeSet, str, int or sequence of int, optional
            The nodes (see :meth:`node_ids`): a node set, a named node set of the model, global
            node indices; a pair of floats is a point.
        quantity : str
            ``"ux"``, ``"uy"`` (m), ``"rz"`` (rad, frame nodes): displacements;
            ``"vx"``, ``"vy"`` (m/s), ``"vrz"`` (rad/s): velocities.
        point : (x, y), optional
            The node nearest this point, m.
        body : str, optional
            Body of the node nearest ``point`` (coincident nodes of two bodies), or every
            node of the body when neither ``nodes`` nor ``point`` is given.

        Returns
        -------
        (n_states,) for a single node (an index or a point), (n_states, k) for a set or a
        sequence of k nodes; None for velocities of a static run (it has none).

        Needs the displacements of every state: an in-memory result (or one given its model
        with :meth:`recover_fields`) recomputes those not stored in one solve.

        Example
        -------
        >>> res.node_history(point=(2.0, 2.0), quantity="ux")        # doctest: +SKIP
        >>> res.node_history(top, "uy").mean(axis=1)                 # doctest: +SKIP
        """
        if quantity not in _NODE_QUANTITIES:
            raise ValueError(f"quantity={quantity!r}: use one of "
                             f"{', '.join(map(repr, _NODE_QUANTITIES))}")
        kind, comp = _NODE_QUANTITIES[quantity]
        if comp == 2 and self._dim == 3:  # column 2 of a 3D model's DOFs is u_z, no rotation
            raise ValueError(f"quantity={quantity!r}: the nodes of a 3D model have no rotation "
                             "(their third DOF is u_z, not a nodal quantity yet: take it from "
                             "res.displacements())")
        single = point is not None or (
            nodes is not None and not isinstance(nodes, str) and not hasattr(nodes, "body")
            and np.ndim(nodes) in (0, 1) and (np.ndim(nodes) == 0
                                              or np.asarray(nodes).dtype.kind == "f"))
        ids = self.node_ids(nodes, point=point, body=body)
        dof_of = np.asarray(self.geometry["dof_of"], dtype=np.int64)
        d = dof_of[ids, comp]
        if np.any(d < 0):
            k = int(ids[d < 0][0])
            raise ValueError(f"node {k} has no DOF {('ux', 'uy', 'rz')[comp]} (rotations exist "
                             "only at frame nodes)")
        if kind == "v":
            V = self.velocities()
            if V is None:
                return None
            out = np.asarray(V)[:, d]
        else:
            out = self.displacements()[:, d]
        return out[:, 0] if single else out

    def reaction_history(self, nodes, dof: str = "y", *, point=None,
                         body: str | None = None) -> np.ndarray:
        """The reaction on the structure along ``dof`` summed over ``nodes``, at every state:
        (n_states,), N ("x", "y") or N·m ("rz", the nodal moments only).

        ``nodes`` is a support's name (or a load pattern's, for the DOFs it prescribes): its
        stored resultant, :meth:`reaction`, no solve.  Otherwise a node set, a named node set,
        node indices or a point as in :meth:`node_ids`: the reaction r = K u + Bᵀ s − f of
        their DOFs (zero at free DOFs, so a set may be larger than the supported nodes; DOFs
        shared by tied nodes count once).  That needs the run's stiffness: an in-memory
        result, or one given its model with :meth:`recover_fields`.
        """
        if dof not in ("x", "y", "rz"):
            raise ValueError(f"dof={dof!r}: use 'x', 'y' or 'rz'")
        if dof == "rz" and self._dim == 3:
            raise ValueError("dof='rz': the nodes of a 3D model have no rotation (reactions "
                             "at nodes of 3D models are not available yet; a support's is "
                             "res.reaction(support, 'z'))")
        if isinstance(nodes, str) and point is None:
            try:
                return self.reaction(nodes, dof)
            except KeyError:
                if nodes not in self.node_sets:
                    raise
        ids = self.node_ids(nodes, point=point, body=body)
        dof_of = np.asarray(self.geometry["dof_of"], dtype=np.int64)
        d = np.unique(dof_of[ids, ("x", "y", "rz").index(dof)])
        d = d[d >= 0]
        system = getattr(getattr(self._recover, "cond", None), "system", None)
        if system is None:
            raise KeyError("the reaction at given nodes needs the run's stiffness: call "
                           "res.recover_fields(model) with the model of the run (the stored "
                           "support resultants are res.reaction(support, dof))")
        U = self.displacements()
        S = self.layout.join(np.moveaxis(np.asarray(self.Q), 0, -1), -np.asarray(self.N).T).T
        F = np.asarray(self.factors, dtype=float).reshape(self.n_states, -1)
        f = np.stack([system.loads[name].f for name in self.pattern_names], axis=1) \
            if self.pattern_names else np.zeros((system.ndof, 0))
        K_d = system.K[d]  # the rows of those DOFs only (K symmetric)
        B_d = system.B[:, d].T.tocsr()
        R = np.asarray(K_d @ U.T).T + np.asarray(B_d @ S.T).T - F @ f[d].T
        return R.sum(axis=1)

    def history(self, quantity: str, nodes=None, *, point=None, body: str | None = None,
                dof: str | None = None) -> np.ndarray | None:
        """Any quantity at every reported state, as an array along the path (:attr:`path`).

        * ``"lam"``, ``"path"``: (n_states,); ``"factors"``: (n_states, n_patterns).
        * CFE quantities ``"N"``, ``"Q"`` (N), ``"sigma_n"``, ``"tau"`` (Pa), ``"un"``,
          ``"ut"`` (m): (n_states, m) — every CFE (:meth:`cfe_history` for labelled data);
          ``"Q"``, ``"tau"``, ``"ut"`` are (n_states, m, n_t) in 3D.
        * nodal quantities ``"ux"``, ``"uy"``, ``"rz"``, ``"vx"``, ``"vy"``, ``"vrz"`` of
          ``nodes`` / ``point`` / ``body``: :meth:`node_history`.
        * ``"reaction"`` along ``dof`` (default "y") of a support or of nodes:
          :meth:`reaction_history`.

        Example
        -------
        >>> res.history("uy", point=(2.0, 2.0))                # doctest: +SKIP
        >>> res.history("reaction", "bed", dof="x")            # doctest: +SKIP
        """
        if quantity in ("lam", "path"):
            return np.asarray(getattr(self, quantity))
        if quantity == "factors":
            return np.asarray(self.factors)
        if quantity in ("N", "Q", "un", "ut", "sigma_n", "tau"):
            return np.asarray(getattr(self, quantity))
        if quantity in _NODE_QUANTITIES:
            return self.node_history(nodes, quantity, point=point, body=body)
        if quantity == "reaction":
            return self.reaction_history(nodes, dof or "y", point=point, body=body)
        raise ValueError(f"quantity={quantity!r}: use 'lam', 'path', 'factors', a CFE quantity "
                         "(N, Q, sigma_n, tau, un, ut), a nodal one (ux, uy, rz, vx, vy, vrz) "
                         "or 'reaction'")

    def extremes(self, quantity: str | None = None, nodes=None, *, point=None,
                 body: str | None = None, dof: str | None = None):
        """The extremes along the path of the recorded quantities: value and where on the
        path (:attr:`path`: λ, or the time t in s of a dynamic result) each is reached.

        * ``quantity`` None: one row per quantity (``N``, ``Q``, ``un``, ``ut``; a dynamic
          result adds ``u``, ``v``, ``a`` — every DOF), with the largest magnitude over all
          CFEs (DOFs) and states: ``absmax`` (≥ 0), the signed ``value`` there, ``at`` (the
          path: λ or t), ``state``, and ``index`` (the CFE or DOF where it is reached; for
          ``Q``, ``ut`` of a 3D result the pair (CFE k, component j) as k·n_t + j).
        * a quantity of :meth:`history` (``"N"``, ``"Q"``, ``"sigma_n"``, ``"tau"``, ``"un"``,
          ``"ut"``, nodal ``"ux"`` … ``"vrz"`` of ``nodes``/``point``/``body``,
          ``"reaction"``) or ``"u"``, ``"v"``, ``"a"`` (every DOF, dynamic results): one row
          per CFE, node or DOF with ``max``, ``max_at``, ``min``, ``min_at``, ``absmax``,
          ``absmax_at`` and ``absmax_state``.

        Only the reported states count (a dynamic result records every step unless
        ``record_every`` > 1; between them the extremes are not sought).  Returns a
        :class:`pandas.DataFrame` (its ``attrs["at"]`` names the path axis).

        Example
        -------
        >>> res.extremes()                                      # doctest: +SKIP
        >>> res.extremes("uy", point=(2.0, 4.0)).absmax_at      # doctest: +SKIP
        """
        import pandas as pd

        at = np.asarray(self.path, dtype=float)
        if quantity is None:
            rows = []
            for q in self._extreme_quantities():
                h = np.asarray(self._extreme_history(q), dtype=float).reshape(self.n_states, -1)
                if h.size == 0:
                    continue
                i, j = np.unravel_index(int(np.argmax(np.abs(h))), h.shape)
                rows.append({"quantity": q, "absmax": float(abs(h[i, j])),
                             "value": float(h[i, j]), "at": float(at[i]), "state": int(i),
                             "index": int(j), "units": self.units.get(q, _EXTREME_UNITS.get(q,
                                                                                      ""))})
            out = pd.DataFrame(rows, columns=["quantity", "absmax", "value", "at", "state",
                                              "index", "units"]).set_index("quantity")
        else:
            h = self._extreme_history(quantity, nodes, point=point, body=body, dof=dof)
            if h is None:
                raise ValueError(f"quantity={quantity!r} is not recorded in this result")
            h = np.asarray(h, dtype=float).reshape(self.n_states, -1)
            imax, imin = np.argmax(h, axis=0), np.argmin(h, axis=0)
            iabs = np.argmax(np.abs(h), axis=0)
            cols = np.arange(h.shape[1])
            out = pd.DataFrame({
                "max": h[imax, cols], "max_at": at[imax], "min": h[imin, cols],
                "min_at": at[imin], "absmax": np.abs(h[iabs, cols]), "absmax_at": at[iabs],
                "absmax_state": iabs})
            out.index.name = ("cfe" if quantity in _CFE_QUANTITIES
                              else "dof" if quantity in ("u", "v", "a") else "column")
        out.attrs["at"] = self.path_axis
        return out

    def _extreme_quantities(self) -> tuple[str, ...]:
        return ("N", "Q", "un", "ut")

    def _extreme_history(self, quantity: str, nodes=None, *, point=None, body=None, dof=None):
        """The history of ``quantity`` for :meth:`extremes` (``u``, ``v``, ``a``: every DOF)."""
        if quantity == "u":
            return self.displacements()
        if quantity in ("v", "a"):
            return None
        return self.history(quantity, nodes, point=point, body=body, dof=dof)

    # ---- fields: stored, or recomputed exactly on request ----------------------------------
    def _state_indices(self, states) -> np.ndarray:
        """States (int or sequence; negative from the end; None: all) as indices 0…n−1."""
        n = self.n_states
        if states is None:
            return np.arange(n, dtype=np.int64)
        idx = np.atleast_1d(np.asarray(states))
        if idx.size and idx.dtype.kind not in "iu":
            raise TypeError(f"states: expected integer state indices, got {idx.dtype}")
        idx = idx.astype(np.int64).reshape(-1)
        bad = (idx < -n) | (idx >= n)
        if bad.any():
            raise IndexError(f"state {int(idx[bad][0])} does not exist (the result has {n} "
                             f"states, 0…{n - 1})")
        return np.where(idx < 0, idx + n, idx)

    def _not_stored(self, what: str, states) -> KeyError:
        """The KeyError for fields that are neither stored nor recoverable."""
        return KeyError(
            f"{what} of state{'s' if len(states) > 1 else ''} {_short(states)} were not "
            f"stored (stored: {_short(sorted(self.fields)) or 'none'}); call "
            "res.recover_fields(model) with the model of the run to recompute any state exactly, "
            "or re-run with store_fields='all'"
        )

    def displacement(self, i: int) -> np.ndarray:
        """Displacement vector (ndof,) at reported state ``i``, m: the stored field, or
        recomputed exactly from the state's contact unknowns (one solve; in memory, or after
        :meth:`recover_fields`)."""
        if i in self.fields:
            return self.fields[i]
        return self.displacements([i])[0]

    def displacements(self, states=None) -> np.ndarray:
        """Displacement vectors (k, ndof), m, of ``states`` (indices, negative from the end;
        default every state), in that order: the stored fields, and all the others
        recomputed exactly with one multi-right-hand-side solve.

        Raises KeyError (naming :meth:`recover_fields`) when a state is not stored and the
        result has no field recovery (loaded from a file or unpickled).
        """
        idx = self._state_indices(states)
        missing = [i for i in dict.fromkeys(idx.tolist()) if i not in self.fields]
        got: dict[int, np.ndarray] = {}
        if missing:
            rec = self._recover
            if rec is None:
                raise self._not_stored("displacements", missing)
            if hasattr(rec, "displacements"):
                U = rec.displacements(np.asarray(missing, dtype=np.int64))
            else:
                U = np.stack([np.asarray(rec(i), dtype=float) for i in missing])
            got = dict(zip(missing, U, strict=True))
        if idx.size == 0:
            return np.zeros((0, self._ndof()))
        return np.stack([self.fields[i] if i in self.fields else got[i] for i in idx.tolist()])

    def stress(self, i: int) -> dict[str, np.ndarray]:
        """Element stresses at reported state ``i``: {body: (n_el, 4) σxx, σyy, σxy, σzz}, Pa —
        stored, or recomputed exactly from the displacement field (see :meth:`stresses_at`)."""
        return self.stresses_at([i])[int(self._state_indices([i])[0])]

    def stresses_at(self, states=None, *, displacements=None) -> dict[int, dict[str, np.ndarray]]:
        """Element stresses {state: {body: (n_el, 4) σxx, σyy, σxy, σzz}}, Pa, of ``states``
        (default every state): the stored ones, the others from their displacements (one
        multi-right-hand-side solve, then one sparse product per body).

        Parameters
        ----------
        states : int or sequence of int, optional
        displacements : (k, ndof) array, optional
            The displacements of ``states`` (from :meth:`displacements`), to avoid solving
            again.

        Raises KeyError (naming :meth:`recover_fields`) when a state is not stored and the
        result has no field recovery.
        """
        idx = self._state_indices(states)
        order = list(dict.fromkeys(idx.tolist()))
        missing = [i for i in order if i not in self.stresses]
        got: dict[int, dict[str, np.ndarray]] = {}
        if missing:
            rec = self._recover
            if rec is None or not hasattr(rec, "stresses"):
                raise self._not_stored("stresses", missing)
            if displacements is not None:
                U = np.asarray(displacements, dtype=float).reshape(len(idx), -1)
                first = {int(i): j for j, i in reversed(list(enumerate(idx.tolist())))}
                U = U[[first[i] for i in missing]]
            else:
                U = self.displacements(missing)
            per_body = rec.stresses(U)
            got = {i: {b: a[j] for b, a in per_body.items()} for j, i in enumerate(missing)}
        return {i: self.stresses[i] if i in self.stresses else got[i] for i in order}

    def _ndof(self) -> int:
        if self.fields:
            return len(next(iter(self.fields.values())))
        if "ndof" in self.counters:
            return int(self.counters["ndof"])
        dof_of = np.asarray(self.geometry.get("dof_of", np.zeros((0, 3), int)))
        return int(dof_of.max()) + 1 if dof_of.size else 0

    def summary(self) -> str:
        """A short text summary: status, counts, multipliers, worst residuals."""
        lines = [
            f"status: {self.status.value} — {self.message}",
            f"CFEs: {self.m}, events: {len(self.events)}, states: {self.n_states}",
            f"max equilibrium residual: {np.max(self.residual, initial=0):.2e}, "
            f"max contact-condition violation: {np.max(self.violation, initial=0):.2e}",
        ]
        for mu in self.multipliers:
            def fmt(v):
                return "—" if v is None else f"{v:.6g}"

            lines.append(
                f"segment {mu.segment} ('{mu.pattern}'){self._stage_of_segment(mu.segment)}: "
                f"first slip λ={fmt(mu.first_slip)}, "
                f"first opening λ={fmt(mu.first_opening)}, "
                f"equilibrium lost λ={fmt(mu.equilibrium_lost)}"
            )
        R = np.asarray(self.load_resultants, dtype=float)
        if len(self.pattern_names) and R.ndim == 2 and R.shape[0] == len(self.pattern_names) \
                and R.shape[1] in (3, 6):
            names = RESULTANT_NAMES[R.shape[1]]
            lines.append("load resultants per unit λ (" + (
                "Fx, Fy in N; Mz about the origin in N·m):" if R.shape[1] == 3 else
                "Fx, Fy, Fz in N; Mx, My, Mz about the origin in N·m):"))

            every = float(np.nanmax(np.abs(R), initial=0.0))  # round-off: of all patterns

            def fmt3(r):
                big = max(float(np.max(np.abs(r), initial=0.0)), every)
                r = np.where(np.abs(r) <= 1e-12 * big, 0.0, r) + 0.0  # no "-0"
                return ", ".join(f"{k} = {v:.6g}" for k, v in zip(names, r, strict=True))

            levels = self.level_patterns
            for name, r in zip(self.pattern_names, R, strict=True):
                if is_virtual(name):
                    continue
                if name in levels:
                    h = float(self.factors[-1, self.pattern_names.index(name)])
                    lines.append(f"  '{name}' (its factor is the water level, m): at the last "
                                 f"state, h = {h:.6g} m: {fmt3(self.load_resultant(name, -1))}")
                else:
                    lines.append(f"  '{name}': {fmt3(r)}")
        return "\n".join(lines)

    def _stage_of_segment(self, j: int) -> str:
        """`` in stage 'NAME'`` for segment ``j`` of a run in stages, else ``""``."""
        if self.stage is None:
            return ""
        idx = np.flatnonzero(np.asarray(self.segment) == j)
        return f" in stage '{self.stage_names[int(self.stage[idx[-1]])]}'" if idx.size else ""

    def segments_summary(self) -> list[dict[str, object]]:
        """One record per load-program segment: its pattern, λ range (start, end, reached —
        None if not reached), numbers of states and events, and its stability multipliers."""
        mult = {mu.segment: mu for mu in self.multipliers}
        segs = np.asarray(self.segment)
        ev_seg = np.array([e.segment for e in self.events], dtype=np.int64)
        rows: list[dict[str, object]] = []
        for j, (pattern, a, b) in enumerate(self.segments):
            idx = np.flatnonzero(segs == j)
            mu = mult.get(j, Multipliers(j, pattern))
            rows.append({
                "segment": j, "pattern": pattern, "lam_start": float(a), "lam_end": float(b),
                "lam_reached": float(self.lam[idx[-1]]) if idx.size else None,
                "states": int(idx.size), "events": int(np.sum(ev_seg == j)),
                **{k: getattr(mu, k) for k in _MULTIPLIER_KEYS},
            })
        return rows

    def __repr__(self) -> str:
        counts = ", ".join(f"{k} {v}" for k, v in transition_counts(self.events).items() if v)
        n_if = len(self.interface_names)
        lines = [
            f"<StaticResult {self.status.value}: {self.n_states} states, {len(self.events)} "
            f"events{f' ({counts})' if counts else ''}, {self.m} CFEs on {n_if} "
            f"interface{'' if n_if == 1 else 's'}, fields at {len(self.fields)} states",
        ]
        rows = self.segments_summary()
        for r in rows[:_REPR_SEGMENTS]:
            reached = "not reached" if r["lam_reached"] is None else (
                f"reached {r['lam_reached']:.6g}")
            mults = "".join(
                f"; {k.replace('_', ' ')} {r[k]:.6g}" for k in _MULTIPLIER_KEYS
                if r[k] is not None
            )
            lines.append(f"  segment {r['segment']} '{r['pattern']}' λ {r['lam_start']:.6g} → "
                         f"{r['lam_end']:.6g}: {reached}{mults}")
        if len(rows) > _REPR_SEGMENTS:
            lines.append(f"  … {len(rows) - _REPR_SEGMENTS} more segments")
        lines.append(f"  {self.message}>")
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        """Jupyter display: the counts and a table of the segments and their multipliers."""
        from html import escape

        def cell(v: object) -> str:
            return "—" if v is None else escape(f"{v:.6g}" if isinstance(v, float) else str(v))

        rows = self.segments_summary()
        head = "".join(f"<th>{escape(k.replace('_', ' '))}</th>" for k in rows[0]) if rows else ""
        body = "".join(
            "<tr>" + "".join(f"<td>{cell(v)}</td>" for v in r.values()) + "</tr>" for r in rows
        )
        return (
            f"<div><b>StaticResult</b> — <code>{escape(self.status.value)}</code>: "
            f"{escape(self.message)}<br>{self.n_states} states, {len(self.events)} events, "
            f"{self.m} CFEs, {len(self.interface_names)} interface(s), fields at "
            f"{len(self.fields)} states<table><tr>{head}</tr>{body}</table></div>"
        )

    # ---- safety of a joint (implemented in stepcontact.results.safety) ---------------------
    def interface_safety(self, interface: str, design: float | None = None, *, heel=None,
                         cohesion: float | None = None, pattern: str | None = None):
        """Safety of ``interface`` along the path: ΣN, ΣQ, the normal resultant's position
        (from the heel and the toe), eccentricity and kern check, the stresses at heel and
        toe, the compressed length, the shear-friction factor (c·A_c + N'·tan φ)/H, the
        friction-only factor f·|ΣN|/|ΣQ|, the overturning factor ΣM_r/ΣM_o about the toe,
        the open length, and at the design value ``design`` of the parameter (the factor of
        ``pattern``, default the last segment's: a load factor or a water level, m) the design
        state's factors and the load margins λ_limit / λ_d (see
        :mod:`stepcontact.results.safety`).

        Returns an :class:`~stepcontact.results.safety.InterfaceSafety` (plain arrays along
        the path; ``design_values()`` at the design state).  ``heel``: a point (x, y) near the
        heel (default: the first CFE); ``cohesion``: a design cohesion, Pa, replacing the
        joint's own.
        """
        if self.n_t > 1:  # a joint between 3D bodies: stepcontact.results.safety3d
            given = {"design": design, "heel": heel, "cohesion": cohesion, "pattern": pattern}
            extra = [k for k, v in given.items() if v is not None]
            if extra:
                raise ValueError(f"interface_safety('{interface}'): {', '.join(extra)} apply to "
                                 "the joints of 2D models; a 3D joint's safety takes none")
            return interface_safety_3d(self, interface)
        return interface_safety(self, interface, design, heel=heel, cohesion=cohesion,
                                pattern=pattern)

    # ---- I/O (implemented in stepcontact.results.file) ------------------------------------
    def to_dataset(self):
        """The result as an :class:`xarray.Dataset` (what is written to the result file)."""
        return result_to_dataset(self)

    def save(self, path) -> None:
        """Write the result atomically to a netCDF4/HDF5 file."""
        save_result(self, path)

    @classmethod
    def load(cls, path) -> StaticResult:
        """Load a result written by :meth:`save` (a :class:`DynamicResult` for a dynamic
        run)."""
        return load_result(path)

    def cfe_history(self, *, as_frame: bool = False):
        """Per-CFE histories: every reported state × every CFE, for notebooks.

        The CFE variables of :meth:`to_dataset` (``N``, ``Q`` in N; ``un``, ``ut`` in m;
        ``contact_state`` as state codes, :class:`ContactState` and the faceted cone's) plus
        ``sigma_n`` and ``tau`` (Pa), on the dimensions ``state`` and ``cfe`` (``Q``, ``ut``,
        ``tau`` also on ``tangent`` in 3D, coordinate "t1", "t2"), without the rest of the
        result file.
        Coordinates: ``lam``, ``segment``, ``pattern``, ``kind`` of each state; ``interface``
        (name), ``local``, ``position`` (arc length, m), ``x``, ``y`` (and ``z`` in 3D) (m),
        ``area`` (m²) and ``friction`` of each CFE.

        Parameters
        ----------
        as_frame : bool
            Return a long :class:`pandas.DataFrame` (index ``state``, ``cfe``) instead.

        Returns
        -------
        xarray.Dataset or pandas.DataFrame

        Example
        -------
        >>> h = res.cfe_history()                                   # doctest: +SKIP
        >>> h.sigma_n.sel(cfe=h.interface == "joint").isel(state=-1)  # doctest: +SKIP
        """
        import xarray as xr

        n, m = self.n_states, self.m
        units = {**_HISTORY_UNITS, **{k: v for k, v in self.units.items() if k in _HISTORY_UNITS}}
        data = {"N": self.N, "Q": self.Q, "sigma_n": self.sigma_n, "tau": self.tau,
                "un": self.un, "ut": self.ut}
        n_t = self.n_t
        dv = {}
        for k, v in data.items():  # the tangential ones with a "tangent" axis in 3D
            along = n_t > 1 and k in _TANGENTIAL
            dv[k] = ((("state", "cfe", "tangent") if along else ("state", "cfe")),
                     np.asarray(v, dtype=float).reshape((n, m, n_t) if along else (n, m)),
                     {"units": units[k], "long_name": _HISTORY_NAMES[k]})
        st = np.asarray(self.state).reshape(n, m)
        dv["contact_state"] = (("state", "cfe"), st, {
            "units": "1", "long_name": "contact state of the CFE after the state",
            **state_flag_attrs(st)})
        seg = np.asarray(self.segment, dtype=np.int64)
        pattern = np.array([self.segments[s][0] if 0 <= s < len(self.segments) else ""
                            for s in seg.tolist()], dtype=str)
        xy = np.asarray(self.cfe.get("x", np.zeros((m, 2))), dtype=float).reshape(m, -1)
        iface = np.asarray(self.cfe.get("interface", np.zeros(m, int)), dtype=np.int64)
        names = np.array(self.interface_names, dtype=str)[iface] if m else np.array([], str)
        cfe_coords = {
            "interface": names, "local": self.cfe.get("local", np.arange(m)),
            "position": self.cfe.get("s", np.full(m, np.nan)), "x": xy[:, 0], "y": xy[:, 1],
            **({"z": xy[:, 2]} if xy.shape[1] == 3 else {}),
            "area": self.cfe.get("area", np.full(m, np.nan)),
            "friction": self.cfe.get("friction", np.full(m, np.nan)),
        }
        coords = {
            "state": np.arange(n), "lam": ("state", np.asarray(self.lam, dtype=float)),
            "segment": ("state", seg), "pattern": ("state", pattern),
            "kind": ("state", np.asarray(self.kind).astype(str)), "cfe": np.arange(m),
            **{k: ("cfe", np.asarray(v)) for k, v in cfe_coords.items()},
            **({"tangent": tangent_labels(n_t)} if n_t > 1 else {}),
        }
        ds = xr.Dataset(dv, coords=coords, attrs={"status": self.status.value})
        return ds.to_dataframe() if as_frame else ds

    def events_table(self):
        """The event log as a :class:`pandas.DataFrame`."""
        import pandas as pd

        rows = [
            {**e.__dict__, "transition": e.transition.value} for e in self.events
        ]
        cols = list(Event.__dataclass_fields__)
        return pd.DataFrame(rows, columns=cols)


#: nodal quantities of :meth:`StaticResult.node_history`: (displacement "u" or velocity "v",
#: component)
_NODE_QUANTITIES = {"ux": ("u", 0), "uy": ("u", 1), "rz": ("u", 2),
                    "vx": ("v", 0), "vy": ("v", 1), "vrz": ("v", 2)}
_CFE_QUANTITIES = ("N", "Q", "un", "ut", "sigma_n", "tau")
_EXTREME_UNITS = {"u": "m", "v": "m/s", "a": "m/s2"}
_MULTIPLIER_KEYS = ("first_slip", "first_opening", "first_closing", "equilibrium_lost")
_REPR_SEGMENTS = 8  #: segments listed by ``repr`` (the rest are counted)
#: the CFE quantities with a tangential axis (n_t components) in 3D
_TANGENTIAL = ("Q", "ut", "tau")
#: the components of a load resultant (:meth:`StaticResult.load_resultant`) by their number
RESULTANT_NAMES = {3: ("Fx", "Fy", "Mz"), 6: ("Fx", "Fy", "Fz", "Mx", "My", "Mz")}
_HISTORY_UNITS = {"N": "N", "Q": "N", "sigma_n": "Pa", "tau": "Pa", "un": "m", "ut": "m"}
_HISTORY_NAMES = {
    "N": "normal CFE force (negative in compression)",
    "Q": "tangential CFE force",
    "sigma_n": "normal contact stress N/A (negative in compression)",
    "tau": "tangential contact stress Q/A",
    "un": "mutual normal displacement u_n (negative: open gap)",
    "ut": "mutual tangential displacement u_t",
}


#: the energy ledger's columns (J per metre of thickness in plane strain)
ENERGY_TERMS = ("kinetic", "strain", "external", "damping", "friction", "impact", "fracture",
                "numerical", "error")


@dataclass
class DynamicResult(StaticResult):
    """A dynamic run: a :class:`StaticResult` whose path axis ``lam`` is the time t (s).

    Extra attributes: ``u``, ``v``, ``a`` (n_states, ndof) displacements, velocities and
    accelerations at every reported state (m, m/s, m/s²); ``energy`` {term: (n_states,)} the
    energy ledger (J; :data:`ENERGY_TERMS`); ``dt`` the time step (s); ``impulses`` the
    impulses of the impacts, one entry per CFE and impact: {"state", "time" (s), "cfe",
    "normal", "tangential" (N·s per metre of thickness; the sign convention of N and Q:
    normal ≤ 0 compressive)} — the CFEs that close at the impact carry theirs on their
    events too (``Event.impulse_n``, ``impulse_t``), the others (closed before) only here;
    :meth:`impacts` sums them per impact.  :meth:`extremes` gives the largest values of
    the recorded quantities (u, v, a of every DOF, N, Q …) and their times."""

    u: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    v: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    a: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    energy: dict[str, np.ndarray] = field(default_factory=dict)
    dt: float = 0.0
    impulses: dict[str, np.ndarray] = field(default_factory=lambda: {
        "state": np.zeros(0, np.int64), "time": np.zeros(0), "cfe": np.zeros(0, np.int64),
        "normal": np.zeros(0), "tangential": np.zeros(0)})

    #: the path axis of the states is the time (s)
    path_axis = "time"

    @property
    def time(self) -> np.ndarray:
        """Time of every state, s."""
        return self.lam

    @property
    def crack_water(self) -> str | None:
        """The crack-water choice of the interval ("full", "unchanged" or "none";
        :class:`~stepcontact.model.DynamicInterval`), kept in ``units["crack_water"]`` (saved
        with the result); None for a model without crack water."""
        note = self.units.get("crack_water")
        return None if note is None else note.partition(":")[0]

    def velocities(self, states=None) -> np.ndarray:
        idx = np.arange(self.n_states) if states is None else np.asarray(states)
        return self.v[idx]

    def impacts(self):
        """The impacts of the run, one row per impact (a :class:`pandas.DataFrame`):
        ``time`` (s), ``state`` (the reported state after it), ``cfes`` (how many CFEs took
        an impulse), ``normal`` and ``tangential`` — the total impulses on the contacts,
        N·s per metre of thickness (normal ≤ 0 compressive, as N).  Per CFE:
        :attr:`impulses`."""
        import pandas as pd

        imp = {k: np.asarray(v) for k, v in self.impulses.items()}
        df = pd.DataFrame({k: imp[k] for k in ("state", "time", "cfe", "normal",
                                               "tangential")})
        out = df.groupby(["state", "time"], sort=True).agg(
            cfes=("cfe", "size"), normal=("normal", "sum"), tangential=("tangential", "sum"))
        return out.reset_index()[["time", "state", "cfes", "normal", "tangential"]]

    def _extreme_quantities(self) -> tuple[str, ...]:
        return ("u", "v", "a") + super()._extreme_quantities()

    def _extreme_history(self, quantity: str, nodes=None, *, point=None, body=None, dof=None):
        if quantity in ("u", "v", "a"):
            return getattr(self, quantity)
        return super()._extreme_history(quantity, nodes, point=point, body=body, dof=dof)

    def displacement(self, i: int) -> np.ndarray:
        return self.u[i]

    def displacements(self, states=None) -> np.ndarray:
        idx = np.arange(self.n_states) if states is None else np.asarray(states)
        return self.u[idx]


def dataset_to_result(ds) -> StaticResult:
    """Inverse of :func:`~stepcontact.results.file.result_to_dataset`: a :class:`StaticResult`,
    or a :class:`DynamicResult` for a dynamic run (``ds`` must be loaded in memory).  A dataset
    whose arrays do not fit together raises a ValueError naming the variable
    (:func:`~stepcontact.results.file.check_dataset`)."""
    dynamic, arguments = dataset_arguments(ds)
    return (DynamicResult if dynamic else StaticResult)(**arguments)


def load_result(path) -> StaticResult:
    """Load a result written by :func:`~stepcontact.results.file.save_result` (exact inverse;
    ``_recover`` is None): a :class:`StaticResult` or a :class:`DynamicResult`."""
    return dataset_to_result(read_dataset(path))


def _short(values, limit: int = 12) -> str:
    """``[0, 1, 2, 5, 7, 8]`` → ``"0–2, 5, 7–8"`` (at most ``limit`` runs, then "…")."""
    runs: list[list[int]] = []
    for v in sorted(int(x) for x in values):
        if runs and v == runs[-1][1] + 1:
            runs[-1][1] = v
        else:
            runs.append([v, v])
    text = [f"{a}" if a == b else f"{a}–{b}" for a, b in runs[:limit]]
    return ", ".join(text) + (", …" if len(runs) > limit else "")


def transition_counts(events: list[Event]) -> dict[str, int]:
    out: dict[str, int] = {t.value: 0 for t in Transition}
    for e in events:
        out[e.transition.value] += 1
    return out


__all__ = ["ENERGY_TERMS", "DynamicResult", "Event", "Multipliers", "StaticResult", "Status",
           "dataset_to_result", "load_result", "transition_counts"]
