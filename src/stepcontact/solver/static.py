"""The quasi-static driver (method.md §3, article eqs. (1)–(6)): a load program on the event
engine.

Between two events the working scheme is fixed and the structure is linear, so every quantity
is linear in the load factor λ.  For each load segment the driver gives the engine the load
rates of the segment's patterns on the contact unknowns (the trial step of the article with
Δλ̃ = 1) and lets it run from event to event (:mod:`stepcontact.solver.engine`): event load
factors from the laws' event functions (eqs. (2), (3); article mode also the ε_p limit of
eq. (5)), the smallest of them and of what is left of the segment as the main step, the next
scheme by the rate problem, a correction at fixed λ (article mode: compensating forces,
eqs. (4), (6)).  It records every state, logs events, and reports the outcome: the program
completed, equilibrium lost (with the mechanism), or why the run could not go on.

Slip treatment ``"exact"`` writes Q = σ f (−N) into the scheme, so events are exact;
``"article"`` holds Q during a step limited by |ΔQ_p / Q_p| ≤ ε_p (eq. (5)) and then corrects it.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from stepcontact.contact.laws import BONDED, OPEN, STICK
from stepcontact.enums import SlipTreatment, Status, slipping, state_label
from stepcontact.errors import ModelError
from stepcontact.fem.assembly import System, assemble, load_moments, load_resultants
from stepcontact.model import DiscreteModel, Model
from stepcontact.results.build import build_result, cfe_arrays, stage_fields
from stepcontact.results.recorder import Recorder
from stepcontact.results.result import Multipliers, StaticResult
from stepcontact.solver.bonds import break_bonds, breaking
from stepcontact.solver.clock import Stopwatch
from stepcontact.solver.condensation import Condensation, Condensed
from stepcontact.solver.contactlaws import contact_law
from stepcontact.solver.engine import EventEngine
from stepcontact.solver.eventlog import EventLog
from stepcontact.solver.jump import DONE, RESTART, STOP, JumpState, follow_jump
from stepcontact.solver.levelpath import LevelPath
from stepcontact.solver.mechanism import (
    constraint_conflict,
    describe_mechanism,
    free_to_open,
)
from stepcontact.solver.rate import RateProblemFailure
from stepcontact.solver.recovery import FieldRecovery, StagedRecovery
from stepcontact.solver.reporting import VIOLATION_LIMIT, result_geometry
from stepcontact.solver.schemes import MechanismError, SchemeSolver


@dataclass
class StepInfo:
    """What hooks receive after every event point."""

    step: int
    segment: int
    pattern: str
    lam: float
    n_events: int
    n_open: int
    n_slip: int


def model_stage_bodies(plan, k: int) -> tuple[str, ...]:
    """The bodies built at stage ``k`` of a plan."""
    return tuple(b for b, j in plan.body_stage.items() if j == k)


#: size n (2m in 2D) of the scheme matrices up to which the event loop holds BLAS to one thread
#: (an LU of n = 2000 takes about 0.1 s on one core; beyond, the dense work is large enough for
#: threads to pay)
SMALL_DENSE = 2000

#: a decided scheme whose rates over the whole segment would grow the path's force or
#: displacement scale more than this many times at once looks ahead only to its next event
#: (:meth:`StaticSolver._reach`): a scheme near a mechanism, not the path's size
LOOKAHEAD_GROWTH = 10.0

#: a Taylor coefficient of a level path whose load over its piece is below this fraction of
#: the largest one's is round-off of the fit (:meth:`StaticSolver._level_rates`)
ROUNDOFF_COEFFICIENT = 1e-9


class StaticSolver:
    """Event-driven static analysis of one model.  Use :func:`solve_static`."""

    def __init__(
        self,
        system: System,
        *,
        slip: str | SlipTreatment = "exact",
        eps_p: float = 0.01,
        store_fields: str = "ends",
        max_events: int = 100_000,
        hooks: Sequence = (),
        backend: str = "auto",
        rtol: float = 1e-10,
        rate_solver: str = "pivoting",
        condensation: Condensation | None = None,
        precision: str = "auto",
        scheduler=None,
    ):
        #: construction stages (:mod:`stepcontact.solver.staging`): the stage systems, the
        #: automatic patterns and segments; None without stages
        self.plan = None
        self.stage = 0
        self.backend, self.precision = backend, precision
        #: where G is formed: None (here) or a dask scheduler's address or Client
        self.scheduler = scheduler
        if getattr(system.model, "stages", ()) and system.discrete is None:
            from stepcontact.solver.staging import StagePlan

            if condensation is not None:
                raise ModelError("condensation", "cannot be reused by a run in stages (each "
                                 "stage has its own factorisation)")
            self.plan = StagePlan(system)
            system = self.plan.system(0)
            # a state's field needs its stage's condensation: keep every field
            store_fields = "all"
        self.sys = system
        self.cfe = system.cfe
        self.slip = SlipTreatment(slip)
        self.article = self.slip == SlipTreatment.ARTICLE
        if self.article and not 0 < eps_p < 1:
            raise ModelError("eps_p", f"must lie in (0, 1), got {eps_p}")
        if store_fields not in ("auto", "all", "ends"):
            raise ModelError("store_fields", f"must be auto, all or ends, got '{store_fields}'")
        if rate_solver not in ("pivoting", "lemke"):
            raise ModelError("rate_solver", f"must be 'pivoting' or 'lemke', got '{rate_solver}'")
        #: "all": fields at every state; "ends" (and "auto", the same): at the start, every
        #: segment start and end and the state where the run stops, the others on request
        self.store_fields = "all" if store_fields == "all" else "ends"
        self.violation_limit = max(VIOLATION_LIMIT, eps_p) if self.article else VIOLATION_LIMIT
        self.max_events = max_events
        self.hooks = tuple(hooks)
        t0 = Stopwatch.start()
        self.cond = Condensed.from_system(system, backend, condensation, precision,
                                          scheduler)
        self.t_setup = t0.counters("setup")
        self._watch = t0  # (the run's clock: set again where the run starts)
        cfe = self.cfe
        #: the layout of the contact unknowns s = [Q; p], w = [u_τ; u_n] (the same at every
        #: stage: the stage systems share the CFEs)
        self.layout = system.layout
        self.law = contact_law(system, plan=self.plan, stage=self.stage, warn=True)
        self.schemes = SchemeSolver(self.cond.G, self.cond.d, product=self.cond.product)
        self.engine = EventEngine(self.schemes, [self.law], system.w0, rtol=rtol,
                                  article=self.article, eps_p=eps_p, rate_solver=rate_solver,
                                  layout=self.layout)
        self.c = {name: 0.0 for name in system.loads}
        self.rec = Recorder(self.layout, len(self.c), len(system.reaction_labels))
        self.events = EventLog(self.rec, cfe, self.layout)
        if self.plan is not None:
            self._segments, self._rates = self.plan.segments, self.plan.rates
        else:
            self._segments = system.model.segments_resolved()
            self._rates = system.model.segment_rates()
        self.status = Status.COMPLETED
        self.message = "load program completed"
        self.mechanism: dict | None = None
        self.step = 0
        if self.plan is None:
            self.fields = FieldRecovery.of_recorder(self.cond, self.rec, list(self.c))
        else:
            self.fields = StagedRecovery(self.rec, list(self.c))
            self.fields.plan = self.plan  # (a dynamic interval after the stages runs on it)
            self.fields.add(0, self.cond)
        #: water in opened joints (fem.crack) and the force W (m,) it applies now, N
        self.crack = system.crack
        self.sw = np.zeros(cfe.m)
        #: a wet set held at the current point (:meth:`_hold_water`), or None: the scheme's
        self._held_wet: np.ndarray | None = None
        #: joints with initial strength (eq. (12)): bonded CFEs start BONDED; ``ghost``
        #: (n,) is what broken bonds still transmit while their release is followed (N)
        self.bonds = bool(self.law.has_bond.any())
        self.engine.states = self.law.initial_states(self.engine.states)
        self.ghost = self.layout.zeros()
        #: whether broken bonds ever transmitted ghost forces (else s is all the CFEs carry)
        self._ghosts = False
        #: recorded states whose reactions are formed later (:meth:`_flush_reactions`)
        self._reactions_due: list[int] = []
        #: the results of the dynamic intervals of stages before the last, by stage name
        self.dynamics: dict = {}
        self._releasing = False
        #: the state index from which each CFE's residual cohesion is lost (−1: kept)
        self._cohesion_lost_at = np.full(cfe.m, -1, np.int64)

    # ---- construction in stages (stepcontact.solver.staging) ----------------------------------
    def _enter_stage(self, k: int) -> None:
        """Go from the current stage to stage ``k``: hold the removed supports' reactions and
        minus the loads standing on the bodies just built by their automatic patterns (at
        factor 1, released by the stage's automatic segments), hold supports placed on bodies
        in place where they are, make the new interfaces' CFEs (at once: stress-free, their
        current mutual displacements their zero; contacts: with their current gap), grout
        joints, and refactorise with the stage's system.  The contact state (s, w, states)
        and the factors are kept."""
        from stepcontact.fem.assembly import LoadVectors

        self._flush_reactions()  # (with the condensation of the stage they belong to)
        plan, eng, m, cfe, lay = self.plan, self.engine, self.cfe.m, self.cfe, self.layout
        old_k, old = self.stage, self.cond.system
        st = self._s_total(eng.s, self.sw) + self.ghost
        u = self.cond.displacement(self.c, st, eng.w)
        f = np.zeros(old.ndof)
        for name, c in self.c.items():
            if c:
                f += c * old.loads[name].f
        r = old.K @ u + old.B.T @ st - f  # reactions per DOF at the held DOFs
        new_fixed = plan.fixed(k)
        zero = np.zeros(old.ndof)
        none = np.zeros(0, np.int64)
        stage = plan.names[k]
        for name, (kk, kind, item) in plan.auto.items():
            if kk != k or kind == "settle":  # (set where the stage's dynamic interval ends)
                continue
            if kind == "release":
                d = plan.sup_dofs[item]
                d = d[~new_fixed[d]]  # the DOFs no other support or prescription holds
                vec = zero.copy()
                vec[d] = r[d]
                plan.vectors[name] = LoadVectors(vec, zero.copy(), none)
            elif kind == "ramp":
                vec = zero.copy()
                for b in model_stage_bodies(plan, k):
                    d = plan.body_dofs[b]
                    vec[d] = -f[d]
                    for pname, c in self.c.items():
                        lv = old.loads[pname]
                        if c and np.any(lv.u[d]):
                            raise ModelError(f"stage '{stage}'", f"body '{b}' is built while "
                                             f"pattern '{pname}' prescribes displacements of "
                                             f"its nodes at factor {c:g}: start that pattern "
                                             "after the body is built")
                plan.vectors[name] = LoadVectors(vec, zero.copy(), none)
            else:  # hold a support placed on a body in place where its DOFs are now
                d = plan.sup_dofs[item]
                d = d[~old.fixed[d]]
                uv = zero.copy()
                uv[d] = u[d]
                plan.vectors[name] = LoadVectors(zero.copy(), uv, d)
            self.c[name] = 1.0
        # the CFEs made at this stage, and grouted ones
        new = plan.active_cfes(k) & ~plan.active_cfes(old_k)
        names = np.asarray(cfe.names, dtype=object)[cfe.interface] if m else np.zeros(0)
        contact = np.array([n in plan.contact_itf for n in names], bool)
        at_once = new & ~contact
        grouted = plan.grouted_cfes(k)
        if grouted.any():
            plan.grout_stage(k)
        shift_t = at_once | (new & contact) | (grouted & (eng.states == OPEN))
        shift_n = (at_once | (new & contact & (lay.normal(eng.w) > 0))
                   | (grouted & (eng.states == OPEN)))
        for rows, mask in ((lay.tangential_rows, shift_t), (lay.normal_rows, shift_n)):
            j = rows[mask]
            plan.w0[j] -= eng.w[j]
            eng.w[j] = 0.0
        self.stage = k
        system = plan.system(k)
        self.sys = system
        self.cond = Condensed.from_system(system, self.backend, None, self.precision,
                                          self.scheduler)
        lost = self.law.cohesion_lost & ~grouted  # (a grouted joint has its cohesion again)
        self._cohesion_lost_at[grouted] = -1
        self.law = contact_law(system, plan=plan, stage=k)
        self.law.lose_cohesion(lost)
        self.schemes = SchemeSolver(self.cond.G, self.cond.d, product=self.cond.product)
        eng.schemes = self.schemes
        eng.laws = [self.law]
        eng._relations = {}
        law = self.law
        _, tw = eng.tolerances()
        touching = new & contact & (-lay.normal(eng.w) <= tw)
        states = eng.states.copy()
        states[at_once | touching] = law.closed_state()[at_once | touching]
        states[new & law.has_bond] = BONDED
        if grouted.any():
            tf, _ = eng.tolerances()
            bad = grouted & (law.bond_values(*lay.split(eng.s)).min(axis=1) < -tf)
            if bad.any():
                j = int(np.flatnonzero(bad)[0])
                raise ModelError(f"stage '{stage}'.grout['{cfe.names[cfe.interface[j]]}']",
                                 f"CFE {cfe.local[j]} carries forces beyond the bond's "
                                 f"strength when it is grouted (N = {-lay.normal(eng.s)[j]:g} N, "
                                 f"Q = {lay.tangential(eng.s)[j]:g} N)")
            states[grouted & law.has_bond] = BONDED
        eng.states = states
        self.bonds = bool(law.has_bond.any())
        self._load_resultants = self._load_moments = None
        self.fields.add(k, self.cond)

    def _dynamic_interval(self, seg: int, pattern: str, t0: float) -> bool:
        """Run the dynamic interval of the current stage (not the last) from the current
        state (:func:`~stepcontact.solver.dynamic.integrate` on the stage's system), keep
        its result in ``self.dynamics``, and take the state where it ends: the contact
        unknowns (s, w, states), the factors g(T) of its loads, and the force out of balance

            r = K u + Bᵀ s − Σ c_P f_P  (= −(M a + C v) where the motion stopped, N)

        on the free DOFs as the vector of the automatic pattern ``pattern`` at factor 1, so
        that (u, s) is a static equilibrium of the stage's system exactly; the segment that
        follows releases it.  The state is recorded (kind ``dynamics``).  False (status and
        message set) when the interval did not complete."""
        from stepcontact.fem.assembly import LoadVectors
        from stepcontact.solver.dynamic import dynamic_interval, integrate

        plan, eng = self.plan, self.engine
        k = self.stage
        name = plan.names[k]
        if int(self.rec.stage.view[-1]) != k:  # a stage that is only a dynamic interval
            self._record(0.0, seg, "segment_start")
        start = self.result(time.perf_counter() - t0)
        dres = integrate(plan.full, dynamic_interval(plan.full, stage=k), initial=start,
                         backend=self.backend,
                         hooks=[h for h in self.hooks if hasattr(h, "after_step")])
        self.dynamics[name] = dres
        if dres.status != Status.COMPLETED:
            self.status = dres.status
            self.message = (f"the dynamic interval of stage '{name}' stopped at "
                            f"t = {dres.time[-1]:.6g} s: {dres.message}")
            return False
        j = len(dres.lam) - 1
        c = dict(zip(dres.pattern_names, (float(x) for x in dres.factors[j]), strict=True))
        eng.s = self.layout.join(dres.Q[j], -dres.N[j])
        eng.w = self.layout.join(dres.ut[j], dres.un[j])
        eng.states = np.asarray(dres.state[j], np.int64).copy()
        eng.F_scale = max(eng.F_scale, float(np.abs(eng.s).max(initial=0.0)))
        eng.W_scale = max(eng.W_scale, float(np.abs(eng.w).max(initial=0.0)))
        if self.crack is not None and dres.water is not None:
            self.sw = np.asarray(dres.water[j], float).copy()
        u = np.asarray(dres.u[j], float)
        system = self.sys
        f = np.zeros(system.ndof)
        for pname, cp in c.items():
            if cp and pname != pattern:
                f += cp * system.loads[pname].f
        r = system.K @ u + system.B.T @ (self._s_total(eng.s, self.sw) + self.ghost) - f
        vec = np.where(system.fixed, 0.0, r)
        zero = np.zeros(system.ndof)
        plan.vectors[pattern] = LoadVectors(vec, zero, np.zeros(0, np.int64))
        for pname in self.c:
            self.c[pname] = c.get(pname, 0.0)
        self.c[pattern] = 1.0
        self.sys = plan.system(k)
        self._flush_reactions()
        self.cond = Condensed.from_system(self.sys, self.backend, self.cond.condensation,
                                          self.precision)
        self.schemes = SchemeSolver(self.cond.G, self.cond.d, product=self.cond.product)
        eng.schemes = self.schemes
        eng._relations = {}
        self.fields.add(k, self.cond)
        self._load_resultants = self._load_moments = None
        # (its field is u to round-off; its crack pressures the interval's own: with held
        # crack water an open CFE may be dry, not filled as by the static rule)
        held = (self.crack is not None and dres.crack_pressure is not None)
        self._record(1.0, seg, "dynamics",
                     pressure=np.asarray(dres.crack_pressure[j], float) if held else None)
        return self.status == Status.COMPLETED

    def _level_path(self, seg: int, pattern: str, rates: dict[str, float], lam0: float,
                    lam1: float) -> LevelPath | None:
        """The polynomial path of a segment that moves a water level (None for the others)."""
        levels = self.sys.levels
        moved = [name for name in rates if name in levels]
        if not moved:
            return None
        item = f"program segment {seg} ('{pattern}')"
        if len(rates) > 1:
            raise ModelError(item, f"pattern '{moved[0]}' has the water level as its factor: "
                             "move it by a segment of its own, not with rates")
        if self.article:
            raise ModelError(item, "the article's slip treatment works on proportional "
                             "segments; a segment that moves a water level needs slip='exact'")
        path = LevelPath(levels[pattern], self.cond, lam0, lam1)
        now = np.array([self.c[n] for n in path.basis.names])
        start = path.basis.factors(lam0)
        if np.abs(start - now).max(initial=0) > 1e-12 * max(np.abs(start).max(initial=0), 1.0):
            low = float(path.basis.levels.min())
            raise ModelError(item, f"the water level starts at {lam0:g} m, where it already "
                             f"loads the structure (its wetted faces reach down to y = {low:g} "
                             "m): start the level at or below that, or let an earlier segment "
                             "raise it")
        self.c.update(path.factors(0.0))
        return path

    def _level_rates(self, forcings, coefs, lead: int, ds, dw, reach: float = 1.0):
        """Rates of the current scheme under every Taylor coefficient of a level path (the
        decision's own for the leading one).  On a scheme with a mechanism the load does not
        drive (:meth:`EventEngine.rates_any`), a coefficient whose load over the piece
        (|c_j| reach^(j+1), ``reach`` the piece's length in m) is round-off of the Taylor fit
        (below :data:`ROUNDOFF_COEFFICIENT` of the largest) is zero: its direction is noise
        and may seem to drive the mechanism.  A significant coefficient that drives it raises
        :class:`MechanismError` with ``coefficient`` = j (the power μ^(j+1)): equilibrium is
        lost at this level (:meth:`_lose_equilibrium`), as on a load-factor path."""
        eng = self.engine
        size = np.array([np.abs(c).max(initial=0.0) for c in coefs]) * reach ** np.arange(
            1, len(coefs) + 1)
        dss, dws = [], []
        for j, fj in enumerate(forcings):
            if j == lead:
                a, b = ds, dw
            elif not (np.any(fj[0]) or np.any(fj[1])):
                a, b = np.zeros_like(ds), np.zeros_like(dw)
            else:
                try:
                    a, b = eng.rates_any(eng.states, fj)
                except MechanismError as exc:
                    if size[j] > ROUNDOFF_COEFFICIENT * size.max():
                        exc.coefficient = j  # the power μ^(j+1) whose load drives it
                        raise
                    a, b = np.zeros_like(ds), np.zeros_like(dw)
            dss.append(a)
            dws.append(b)
        return dss, dws

    @staticmethod
    def _combine(vectors: dict[str, np.ndarray], rates: dict[str, float]) -> np.ndarray:
        """Σ rate_P · vector_P over the patterns a segment moves."""
        return sum(rate * vectors[name] for name, rate in rates.items())

    # ---- water in opened joints (fem.crack) -------------------------------------------------
    def _s_total(self, s: np.ndarray, water: np.ndarray) -> np.ndarray:
        """The forces the structure feels across its CFEs: contact forces s = [Q; p] and the
        crack water's W, which acts as a compressive normal force p does."""
        if not np.any(water):
            return s
        out = np.array(s, dtype=float)
        self.layout.normal(out)[:] += water
        return out

    def _water_forcing(self, dW: np.ndarray):
        """Forcing (ĥ, e) of crack-water forces dW (m,): ĥ = −G [0; dW] (fem.crack)."""
        lay = self.layout
        z = lay.zeros()
        lay.normal(z)[:] = dW
        return -self.cond.product(z), lay.zeros()

    def _water_load(self, dW: np.ndarray) -> np.ndarray:
        """Nodal load (ndof,) of crack-water forces dW (m,): −Bᵀ [0; dW]."""
        z = self.layout.zeros()
        self.layout.normal(z)[:] = dW
        return -(self.sys.B.T @ z)

    def _water_jump(self, lam: float, seg: int, pattern: str, mult: dict) -> bool | None:
        """Apply the change of the crack-water forces that the current scheme calls for (water
        enters a CFE that opened, or leaves one that closed) at the fixed load factor λ.

        The jump ΔW is a load of its own: the engine follows it along a parameter τ ∈ [0, 1]
        (W = W₀ + τ ΔW) from event to event, exactly as a load segment; a CFE that opens (or
        closes) under it changes the wet set, and the rest of the jump is recomputed for the new
        set — a crack that runs along a joint at one λ, event by event, in its order.  Returns
        True if anything moved, False if nothing had to, None if the run stopped (equilibrium
        lost under the water, no progress).

        A wet set that recurs with no progress in between (water entering a CFE closes it and
        the dry CFE opens again: no consistent pair at this λ) is held: the water stays in the
        union of the cycle's wet sets for this jump (a closed CFE at zero gap keeps its
        water, as a bridged one does), and the result's ``nonunique`` records it."""
        crack, eng, m = self.crack, self.engine, self.cfe.m
        moved = False
        saved_f = self._f
        seen: list[np.ndarray] = []  # wet sets restarted for at this λ with no progress
        try:
            while True:
                target = crack.force_of(self._wet(eng.states), self.c)
                delta = target - self.sw
                size = max(float(np.abs(target).max(initial=0)),
                           float(np.abs(self.sw).max(initial=0)))
                if float(np.abs(delta).max(initial=0)) <= 1e-12 * max(size, eng.F_scale):
                    self.sw = target
                    return moved
                moved = True
                wet = self._wet(eng.states)
                forcing = self._water_forcing(delta)
                self._f = self._water_load(delta)
                eng.F_scale = max(eng.F_scale, float(np.abs(delta).max()))
                start = self.sw.copy()

                def point(state: JumpState, forcing=forcing, wet=wet):
                    ok, ds, dw = self._event_point(state.fired, forcing, lam, seg, pattern,
                                                   mult, False, 1.0, False)
                    if not ok or self.status != Status.COMPLETED:
                        return STOP
                    if not np.array_equal(self._wet(eng.states), wet):
                        return RESTART  # the wet set changed: the rest of the jump anew
                    return ds, dw

                progress = [False]

                def went(tau, start=start, delta=delta, progress=progress):
                    self.sw = start + tau * delta
                    progress[0] = progress[0] or tau > 0.0

                out = follow_jump(eng, point, JumpState(np.zeros(m, bool)), moved=went,
                                  stalled=self._stalled(lam, seg, "water enters the opened "
                                                        "joint"))
                if out == STOP:
                    return None
                if out == DONE:
                    self.sw = start + delta
                elif out == RESTART:
                    if progress[0]:
                        seen.clear()
                    seen.append(wet)
                    self._hold_water(seen, self._wet(eng.states), lam, seg, pattern)
        finally:
            self._f = saved_f

    def _wet(self, states: np.ndarray) -> np.ndarray:
        """The wet set: held at this point (:meth:`_hold_water`), else the scheme's."""
        return self._held_wet if self._held_wet is not None else self.crack.wet(states)

    def _hold_water(self, seen: list[np.ndarray], now: np.ndarray, lam: float, seg: int,
                    pattern: str) -> bool:
        """If the wet set ``now`` is one of the sets ``seen`` at this point (water entering a
        CFE closes it, and dry it opens again: no consistent wet set at this λ), hold the
        water in the union of the cycle's sets until the next event — a closed CFE at zero
        gap keeps its water, as a bridged one does — and record it in the result's
        ``nonunique`` (the CFEs whose water came and went).  Returns whether it held."""
        first = next((i for i, w in enumerate(seen) if np.array_equal(now, w)), None)
        if first is None:
            return False
        cycle = seen[first:]
        union = np.logical_or.reduce(cycle)
        flips = np.flatnonzero(union & ~np.logical_and.reduce(cycle))
        if not flips.size:  # (the same set again: no cycle)
            return False
        self._held_wet = union
        cfe = self.cfe
        self.rec.nonunique.append({
            "lam": float(lam), "segment": seg, "pattern": pattern,
            "cfes": [f"{cfe.names[cfe.interface[k]]}[{cfe.local[k]}]" for k in flips],
            "followed": ["wet"] * len(flips), "alternatives": [["dry"] * len(flips)],
            "why": "crack water: water entering these CFEs closes them and dry they open "
                   "again (no consistent wet set at this λ); the water is held in them "
                   "until the next event",
        })
        return True

    def _with_water(self, states, dc, base, base_f, path, forcings, coefs, base_lead):
        """The crack-water rate dW/dμ (m,) of the scheme ``states`` and the forcing with it
        (for a level path the first Taylor coefficient carries it, and leads when it moves);
        sets the load rate ``self._f`` to match."""
        wr = self.crack.force_of(self._wet(states), self.c, dc)
        self._wr = wr
        if not wr.any():
            if path is not None:
                forcings[0] = base
                self._f = path.load(coefs[base_lead], base_lead)
                return wr, forcings[base_lead]
            self._f = base_f
            return wr, base
        hw, ew = self._water_forcing(wr)
        forcing = (base[0] + hw, base[1] + ew)
        self._f = base_f + self._water_load(wr)
        if path is not None:
            forcings[0] = forcing
        return wr, forcing

    def _settle_water(self, lam, seg, pattern, mult, span, wr, ds, dw, forcing, dc, base,
                      base_f, path, forcings, coefs, base_lead):
        """After the scheme is decided at a point: let the water into the CFEs that opened
        (out of those that closed) at the same λ (:meth:`_water_jump`), and decide the scheme
        again with the crack-water rates of the new wet set, until both agree."""
        m = self.cfe.m
        seen: list[np.ndarray] = []  # the wet sets after each jump at this point
        for _ in range(50):
            if self._held_wet is None:
                seen.append(self._wet(self.engine.states))
            moved = self._water_jump(lam, seg, pattern, mult)
            if moved is None:
                return False, None, None, forcing
            if moved and self._held_wet is None:
                now = self._wet(self.engine.states)
                if self._hold_water(seen, now, lam, seg, pattern):
                    continue  # (the held water's jump, then the scheme decided with it)
                seen.append(now)
            wr_new, forcing = self._with_water(self.engine.states, dc, base, base_f, path,
                                               forcings, coefs, base_lead)
            if not moved and np.array_equal(wr_new, wr):
                break
            wr = wr_new
            n1 = len(self.rec)
            ok, ds, dw = self._event_point(np.zeros(m, bool), forcing, lam, seg, pattern, mult,
                                           False, span, False)
            if not ok or self.status != Status.COMPLETED:
                return False, None, None, forcing
            if moved and len(self.rec) == n1:
                self._record(lam, seg, "event")  # the state after the water entered
        return True, ds, dw, forcing

    # ---- joints with initial strength (eq. (12)) -------------------------------------------
    def _has_residual(self) -> bool:
        """Whether any CFE of the current law has a residual cohesion (asked once per law: a
        stage's own)."""
        law = self.law
        if getattr(self, "_residual_of", None) is not law:
            self._residual_of, self._any_residual = law, bool(np.any(law.residual > 0))
        return self._any_residual

    def _lose_cohesion(self, mask: np.ndarray) -> None:
        """The CFEs ``mask`` opened: those with a residual cohesion lose it for good (the
        state index where it happened is kept for the result)."""
        if not self._has_residual():
            return
        law = self.law
        new = mask & (law.residual > 0) & ~law.cohesion_lost & ~law.inert
        if new.any():
            law.lose_cohesion(new)
            self._cohesion_lost_at[new] = len(self.rec)

    def _breaks(self, brk: np.ndarray, lam: float, seg: int, pattern: str, mult: dict) -> None:
        """Break the bonds of the CFEs ``brk`` at the current point: each takes its Coulomb
        state (open in tension, else stuck or slipping), and what it can no longer carry is
        moved from its contact force into ``ghost`` (still transmitted, as a load, until
        :meth:`_release` has let it go) (:func:`~stepcontact.solver.bonds.break_bonds`; the
        event point of the breaks is the one recorded after the cascade).  Logs a ``broken``
        event per CFE; a bond that breaks open (slipping) is the segment's first opening
        (slip) if none came before.

        A closed Coulomb CFE in ``brk`` (one that reached p = 0 with its residual cohesion,
        :meth:`CoulombLaw.losing_cohesion`) opens the same way: its cohesion is lost and the
        shear it carried released."""
        g, _ = break_bonds(self.engine, self.law, brk, self.events, mult, step=self.step + 1,
                           state=len(self.rec), segment=seg, pattern=pattern, lam=lam)
        self._lose_cohesion(brk & (self.engine.states == OPEN))
        self._ghosts = True
        self.ghost += g

    def _release(self, lam: float, seg: int, pattern: str, mult: dict,
                 fired: np.ndarray) -> bool:
        """Release the forces of broken bonds at the fixed load factor λ: the ghost forces g
        go to zero along a parameter τ ∈ [0, 1] (g = g₀ (1 − τ), a load −Bᵀ g on the
        structure, forcing ĥ = G g₀ per unit τ), followed by the engine from event to event
        like a load segment.  A bonded neighbour that reaches its strength surface on the way
        breaks there (its own forces join the release, which restarts for the new ghost): a
        crack running along the joint at one λ, event by event, in its order.  Returns False
        if the run stopped (equilibrium lost while the forces were released, no progress)."""
        eng = self.engine
        saved_f = self._f
        self._releasing = True
        state = JumpState(fired)
        try:
            while np.any(self.ghost != 0):
                g0 = self.ghost.copy()
                forcing = (self.cond.product(g0), self.layout.zeros())
                self._f = self.sys.B.T @ g0
                eng.F_scale = max(eng.F_scale, float(np.abs(g0).max()))

                def moved(tau, g0=g0):
                    self.ghost = g0 * (1.0 - tau)

                out = follow_jump(eng, self._release_point(forcing, lam, seg, pattern, mult),
                                  state, moved=moved,
                                  stalled=self._stalled(lam, seg, "broken bonds release their "
                                                        "forces", record=True))
                if out == STOP:
                    return False
                if out == DONE:
                    self.ghost = self.layout.zeros()
            return True
        finally:
            self._f = saved_f
            self._releasing = False

    def _release_point(self, forcing, lam, seg, pattern, mult):
        """A point of the release (:meth:`_release` with
        :func:`~stepcontact.solver.jump.follow_jump`): residual cohesion lost where p reached
        0 and bonds that break here (:func:`~stepcontact.solver.bonds.breaking`) are broken
        and end the jump (a new one releases them with the rest); else the scheme decided and
        recorded (:meth:`_event_point`)."""
        eng, law, m = self.engine, self.law, self.cfe.m

        def point(state: JumpState):
            tf, _ = eng.tolerances()
            coh = state.fired & law.losing_cohesion(eng.states, self.layout.normal(eng.s), tf)
            if coh.any():  # residual cohesion lost where p reached 0: released too
                self._breaks(coh, lam, seg, pattern, mult)
                state.fired = state.fired & ~coh
                return RESTART
            ok, ds, dw = self._event_point(state.fired, forcing, lam, seg, pattern, mult,
                                           False, 1.0, False)
            if not ok or self.status != Status.COMPLETED:
                return STOP
            brk = breaking(eng, law, ds, state.fired)
            state.fired = np.zeros(m, bool)
            if brk.any():  # a neighbour breaks here: its forces join the release
                self._breaks(brk, lam, seg, pattern, mult)
                return RESTART
            return ds, dw

        return point

    def _stalled(self, lam: float, seg: int, what: str, record: bool = False):
        """The test of a jump at λ that makes no progress (events repeat: more than 100 steps
        of τ ≤ 1e-12 in a row) or exhausts the event budget: sets the status and message
        (and with ``record`` records the state where the run stops)."""

        def stalled(state: JumpState) -> bool:
            if not (state.small > 100 or self.step >= self.max_events):
                return False
            self.status = Status.CYCLING if state.small > 100 else Status.MAX_EVENTS
            self.message = (f"no progress at λ = {lam:.10g} while {what}: events repeat"
                            if state.small > 100 else
                            f"event budget of {self.max_events} exhausted at λ = {lam:.6g}")
            if record:
                self._record(lam, seg, "event", final=True)
            return True

        return stalled

    def _break(self, brk, lam, seg, pattern, mult, fired) -> bool:
        """Break the bonds ``brk`` here, release their forces (:meth:`_release`) and record
        the state after the cascade."""
        self._breaks(brk, lam, seg, pattern, mult)
        if not self._release(lam, seg, pattern, mult, fired & ~brk):
            return False
        self.step += 1
        self._record(lam, seg, "event")
        return self.status == Status.COMPLETED

    # ---- recording ---------------------------------------------------------------------------
    def _record(self, lam: float, seg: int, kind: str, final: bool = False,
                pressure: np.ndarray | None = None) -> int:
        """Record the current state.  Its displacement field and stresses are stored (one
        solve) at the start, segment starts and ends, the state where the run stops
        (``final``, or a violation found here) and, with ``store_fields="all"``, every state;
        the other states' fields are recomputed exactly on request from (factors, s, w).
        ``pressure``: the crack pressures (m,), Pa, to record instead of the static rule's
        (the end of a dynamic interval that held its crack water)."""
        eng = self.engine
        store = final or kind != "event" or self.store_fields == "all"
        if self.crack is None and not self._ghosts:  # s is all the CFEs transmit
            st = eng.s
        else:
            st = self._s_total(eng.s, self.sw) + self.ghost
        if store:  # full field: residual of the whole model and kinematics B u + w⁰ = w
            same = self._same_as_stored(st)
            if same is not None:  # the state just stored again (a segment's end and the next
                u, res, kin = same  # one's start): its field and full check
            else:
                u = self.cond.displacement(self.c, st, eng.w)
                res, kin = self.cond.check(self.c, st, eng.w, u, eng.W_scale)
        else:  # no solve: the condensed equations (exactly equivalent), with the G t that
            # the engine keeps current along the path (no pass over G; a bound of its error
            # is added: EventEngine.tracked_product)
            res = self.cond.condensed_residual(
                self.c, st, eng.w, eng.W_scale,
                product=lambda t: eng.tracked_product(t, self._g_times))
            kin = 0.0
        viol = max(kin, eng.violation())
        # the reactions (linear in the recorded s, w, factors) of a state whose s is all the
        # CFEs transmit are formed later, all at once (:meth:`_flush_reactions`)
        later = st is eng.s
        i = self.rec.append(
            lam=lam, segment=seg, kind=kind, factors=[self.c[n] for n in self.c], s=eng.s,
            w=eng.w, state=eng.states, residual=res, violation=viol,
            reactions=0.0 if later else self.cond.reactions(self.c, st, eng.w),
            water=self.sw, stage=self.stage,
            pressure=(0.0 if self.crack is None else
                      self.crack.pressure(eng.states, self.c, self.sw) if pressure is None
                      else pressure))
        if later:
            self._reactions_due.append(i)
        if store:
            self._keep_field(i, u, same is not None)
            self._stored = (i, self.stage, self.cond, res, kin)
        if viol > self.violation_limit and self.status == Status.COMPLETED:
            self.status = Status.VIOLATION
            self.message = (f"the contact conditions are violated by {viol:.2e} (relative) at "
                            f"λ = {lam:.10g} (segment {seg}); the run stops here"
                            + self._redundancy_note())
            self._store_field(i)  # the run stops here: its field and the full check
        return i

    def _g_times(self, t: np.ndarray) -> np.ndarray:
        """G t (float64) for a state's residual check: the scheme solver's symv (half a pass
        over G) when it holds the condensation's float64 G, else the condensation's product."""
        sch = self.engine.schemes
        if t.ndim == 1 and sch.G is self.cond.G and self.cond.G.dtype == np.float64:
            return sch.g_product(t)
        return self.cond.product(t)

    def _redundancy_note(self) -> str:
        """Where the closed CFEs, all stuck, share a self-stress (redundant rigid contacts: a
        rigid body held at more points than it has freedoms), the text that says so: their
        forces are not determined by the model, and a path that depends on their split (a
        slip that moves the normal forces) has no unique answer.  Empty otherwise (and for
        models beyond the self-stress check's size)."""
        eng = self.engine
        stuck = eng.states.copy()
        closed = (stuck != OPEN) & (stuck != BONDED)
        stuck[closed] = STICK
        Z = eng.self_stress(stuck)
        if Z.shape[1] == 0:
            return ""
        ZQ, Zp = eng.layout.split(Z)
        aq = np.abs(ZQ) if eng.layout.n_t == 1 else np.abs(ZQ).sum(axis=1)
        on = np.flatnonzero(((aq + np.abs(Zp)) > 1e-9 * max(np.abs(Z).max(), 1e-300))
                            .any(axis=1))
        cfe = self.cfe
        names = [f"{cfe.names[cfe.interface[k]]}[{cfe.local[k]}]" for k in on[:8]]
        more = f" and {on.size - 8} more" if on.size > 8 else ""
        return (f"; the forces of CFE {', '.join(names)}{more} are not determined by the "
                "model (redundant rigid contacts, e.g. a rigid body held at more points than "
                "it has freedoms: their split is one of many): give the joint a stiffness "
                "(kn, kt) or model the body as deformable")

    def _flush_reactions(self) -> None:
        """Form the reactions of the recorded states that wait for them (their s is all the
        CFEs transmitted), with the current stage's condensation, in one stacked product
        (:meth:`Condensed.reactions`); called before the condensation changes and before a
        result is taken."""
        due = self._reactions_due
        if not due:
            return
        r = self.rec
        idx = np.array(due)
        F = r.factors.view[idx]
        factors = {name: F[:, j] for j, name in enumerate(self.c)}
        r.reactions.view[idx] = self.cond.reactions(factors, r.s.view[idx], r.w.view[idx])
        due.clear()

    def _keep_field(self, i: int, u: np.ndarray, again: bool = False) -> None:
        """Keep the field u of recorded state ``i`` and its stresses (``again``: those of the
        state recorded just before, the same state)."""
        if again:  # (copies: the two states' arrays are not tied together)
            self.rec.fields[i] = u.copy()
            self.rec.stresses[i] = {k: np.array(v, copy=True)
                                    for k, v in self.rec.stresses[i - 1].items()}
        else:
            self.rec.fields[i] = u
            self.rec.stresses[i] = self.fields.stresses(u)

    def _same_as_stored(self, st: np.ndarray):
        """(u, residual, kinematic mismatch) of the last recorded state when it has its field
        and the current state is the same one (contact unknowns, load factors, water and the
        forces transmitted, at the same stage), else None: its field and its full check hold
        for the current state as they are (a segment's end and the next segment's start)."""
        last = getattr(self, "_stored", None)
        r, eng = self.rec, self.engine
        i = len(r) - 1
        if (last is None or last[0] != i or i not in r.fields or last[1] != self.stage
                or last[2] is not self.cond or st is not eng.s):
            return None
        if not (np.array_equal(r.s.view[i], eng.s) and np.array_equal(r.w.view[i], eng.w)
                and np.array_equal(r.factors.view[i], [self.c[n] for n in self.c])):
            return None
        return r.fields[i], last[3], last[4]

    def _store_field(self, i: int) -> None:
        """Store the field and stresses of recorded state ``i`` if it has none (a state where
        the run stopped), with the full equilibrium and kinematic check of a stored state."""
        r = self.rec
        if i in r.fields or not 0 <= i < len(r):
            return
        c = dict(zip(self.c, r.factors.view[i], strict=True))
        s, w = self._s_total(r.s.view[i], r.water.view[i]), r.w.view[i]
        u = self.cond.displacement(c, s, w)
        res, kin = self.cond.check(c, s, w, u, self.engine.W_scale)
        r.residual.view[i] = res
        r.violation.view[i] = max(float(r.violation.view[i]), kin)
        self._keep_field(i, u)

    def _log_events(self, old, new, lam, seg, pattern, state_index, step=None, first=None):
        """Log the CFEs whose state changed old → new at λ with the engine's forces
        (:class:`~stepcontact.solver.eventlog.EventLog`; ``first``: the segment's multipliers
        the transitions set, None: none)."""
        self.events.changes(old, new, self.engine.s, step=self.step if step is None else step,
                            state=state_index, segment=seg, pattern=pattern, lam=lam,
                            first=first)

    # ---- main loop ---------------------------------------------------------------------------
    def run(self) -> StaticResult:
        """Run the load program.  BLAS is held to one thread meanwhile when the event loop's
        dense work is small (n ≤ ``SMALL_DENSE``), where a second thread only costs
        synchronisation; large interfaces (refactorisations of thousands of unknowns) keep
        every thread."""
        import contextlib

        from threadpoolctl import threadpool_limits

        t0 = self._t0 = time.perf_counter()
        self._watch = Stopwatch.start()
        small = self.schemes.n <= SMALL_DENSE
        try:
            with (threadpool_limits(limits=1, user_api="blas") if small
                  else contextlib.nullcontext()):
                return self._run(t0)
        except KeyboardInterrupt:
            self.status = Status.INCOMPLETE
            self.message = "interrupted"
            res = self.result(time.perf_counter() - t0)
            for hk in self.hooks:
                if hasattr(hk, "interrupted"):
                    hk.interrupted(res)
            raise

    def _run(self, t0: float) -> StaticResult:
        segments = self._segments
        eng = self.engine
        m = self.cfe.m
        first = True
        all_rates = self._rates
        for hk in self.hooks:  # the program as run (a staged one with its automatic segments)
            if hasattr(hk, "before_run"):
                hk.before_run(list(segments))
        for seg, (pattern, lam0, lam1) in enumerate(segments):
            if self.plan is not None and self.plan.stage_of_segment[seg] != self.stage:
                self._enter_stage(self.plan.stage_of_segment[seg])
            if self.plan is not None and self.plan.auto.get(pattern, ("", ""))[1] == "settle":
                if not self._dynamic_interval(seg, pattern, t0):
                    break
            mult = {"first_slip": None, "first_opening": None, "first_closing": None,
                    "equilibrium_lost": None}
            rates = all_rates[seg]
            direction = 1.0 if lam1 >= lam0 else -1.0
            span = abs(lam1 - lam0)
            big = max(abs(lam0), abs(lam1))
            path = self._level_path(seg, pattern, rates, lam0, lam1)
            if path is None:
                self._f = self._combine({k: v.f for k, v in self.sys.loads.items()}, rates)
                f_rate = float(np.abs(self._f).max(initial=0))
                y_rate = float(np.abs(self._combine(self.cond.y, rates)).max(initial=0))
                y_max, f_max = self._segment_scales(
                    (y_rate * abs(lam0), f_rate * abs(lam0)), (y_rate * big, f_rate * big))
                far = f_max < f_rate * big  # the scales look only part of the way
                forcing = (direction * self._combine(self.cond.hhat, rates),
                           direction * self._combine(self.cond.e, rates))
            else:  # the load is a polynomial in the level: its forcings at every point
                y_whole, f_whole = path.scales()
                y_now, f_now = path.scales(start=True)
                y_max, f_max = self._segment_scales((y_now, f_now), (y_whole, f_whole))
                far = f_max < f_whole
                if far:
                    path.add_stops(path.far_stops(LOOKAHEAD_GROWTH))
                if self.crack is not None:  # crack water kinks where the level passes a CFE
                    path.add_stops(self.crack.kinks(pattern))
            # the factors' rates along μ (crack water follows them)
            dc = ({name: rate * direction for name, rate in rates.items()} if path is None
                  else {pattern: path.direction})
            base = forcing if path is None else None
            base_f = self._f if path is None else None
            eng.W_scale = max(eng.W_scale, y_max)
            eng.F_scale = max(eng.F_scale, f_max)
            c0 = dict(self.c)
            mu = 0.0
            stop = False
            fired = np.zeros(m, dtype=bool)
            small_steps = 0
            seg_start = True
            self._held_wet = None
            while True:
                lam = lam0 + direction * mu
                if path is not None:
                    forcings, coefs = path.forcings(mu)
                    lead = path.leading(forcings, coefs)
                    forcing = forcings[lead]
                    self._f = path.load(coefs[lead], lead)
                    base, base_f, base_lead = forcings[0], path.load(coefs[0], 0), lead
                wr = None
                if self.crack is not None:  # the crack water of the current scheme moves too
                    wr, forcing = self._with_water(eng.states, dc, base, base_f, path,
                                                   forcings if path else None, coefs if path
                                                   else None, base_lead if path else 0)
                    if path is not None:
                        lead = 0 if wr.any() else base_lead
                ok, ds, dw = self._event_point(fired, forcing, lam, seg, pattern, mult, first,
                                               span, seg_start)
                first = seg_start = False
                if ok and self.status == Status.COMPLETED and self.crack is not None:
                    ok, ds, dw, forcing = self._settle_water(
                        lam, seg, pattern, mult, span, wr, ds, dw, forcing, dc, base, base_f,
                        path, forcings if path else None, coefs if path else None,
                        base_lead if path else 0)
                    if path is not None:
                        lead = 0 if np.any(self._wr) else base_lead
                if not ok or self.status != Status.COMPLETED:
                    stop = True
                    break
                if mu >= span:
                    break
                end = span if path is None else path.piece_end(mu)
                remaining = end - mu
                look = self._look(span, far, f_rate if far and path is None else 0.0, path)
                grp = 1e-10 * max(abs(lam), look, 1.0)
                if path is None:
                    dmu, dmu_ev, fired = eng.next_event(ds, dw, remaining, grp)
                else:
                    try:
                        dss, dws = self._level_rates(forcings, coefs, lead, ds, dw, remaining)
                    except MechanismError as exc:  # a higher power of the level drives it
                        j = exc.coefficient
                        self._lose_equilibrium(exc, lam, seg, pattern, mult,
                                               path.load(coefs[j], j))
                        stop = True
                        break
                    dmu, dmu_ev, fired = eng.next_event_poly(dss, dws, remaining, grp)
                if self.article:
                    dmu_p = eng.article_step(ds)
                    if dmu_p < dmu:
                        dmu, fired = dmu_p, np.zeros(m, bool)
                if dmu <= 1e-12 * max(look, 1.0):
                    small_steps += 1
                    if small_steps > 100:
                        self.status = Status.CYCLING
                        self.message = f"no progress at λ = {lam:.10g}: events repeat"
                        stop = True
                        break
                else:
                    small_steps = 0
                if path is None:
                    eng.advance(dmu, ds, dw)
                else:
                    eng.advance_poly(dmu, dss, dws)
                if self.crack is not None:  # the crack water moved with the path (linear)
                    self.sw = self.sw + dmu * self._wr
                    if dmu > 0.0:
                        self._held_wet = None  # (held until the next event)
                mu = mu + dmu
                for name, rate in rates.items():
                    self.c[name] = c0[name] + rate * direction * mu
                if dmu == remaining or mu >= end * (1 - 1e-15):
                    mu = end
                    for name, rate in rates.items():
                        self.c[name] = c0[name] + rate * direction * end
                    if path is not None:
                        self.c.update(path.factors(mu))
                    if mu >= span and not np.count_nonzero(fired):
                        mu = span
                        for name, rate in rates.items():
                            self.c[name] = c0[name] + rate * (lam1 - lam0)
                        if path is not None:
                            self.c.update(path.factors(span))
                        if self.article:
                            eng.snap()
                        break
                elif path is not None:
                    self.c.update(path.factors(mu))
                if self.step >= self.max_events:
                    self.status = Status.MAX_EVENTS
                    self.message = f"event budget of {self.max_events} exhausted at λ = {lam:.6g}"
                    stop = True
                    break
            if not stop:
                self._record(lam1, seg, "segment_end")
                if self.status != Status.COMPLETED:
                    stop = True
            self.rec.multipliers.append(Multipliers(seg, pattern, **mult))
            if any(hasattr(hk, "after_segment") for hk in self.hooks):
                partial = self.result(time.perf_counter() - t0, partial=not stop and
                                      seg < len(segments) - 1)
                for hk in self.hooks:
                    if hasattr(hk, "after_segment"):
                        hk.after_segment(partial)
            if stop:
                break
        return self.result(time.perf_counter() - t0)

    def _event_point(self, fired, forcing, lam, seg, pattern, mult, first, span, seg_start):
        """Decide the scheme at the current point; record it if anything changed.  Bonds
        that break here (a facet reached, or the rates of the scheme decided drive a bonded
        CFE beyond its strength surface) are broken and released first (:meth:`_break`), and
        the point decided again."""
        eng = self.engine
        if self.bonds and not self._releasing:
            for _ in range(self.cfe.m + 1):
                brk = fired & (eng.states == BONDED)
                # closed CFEs that reach p = 0 with a residual cohesion lose it: released too
                tf, _ = eng.tolerances()
                brk |= (fired | first) & self.law.losing_cohesion(
                    eng.states, self.layout.normal(eng.s), tf)
                if brk.any():
                    if not self._break(brk, lam, seg, pattern, mult, fired):
                        return False, None, None
                    fired = np.zeros(self.cfe.m, bool)
                    first = False
                ok, ds, dw = self._decide_point(fired, forcing, lam, seg, pattern, mult, first,
                                                span, seg_start)
                if not ok:
                    return ok, ds, dw
                brk = breaking(eng, self.law, ds)
                if not brk.any():
                    return ok, ds, dw
                fired = brk
                first = seg_start = False
            return ok, ds, dw
        return self._decide_point(fired, forcing, lam, seg, pattern, mult, first, span,
                                  seg_start)

    def _decide_point(self, fired, forcing, lam, seg, pattern, mult, first, span, seg_start):
        """Decide the scheme at the current point; record it if anything changed."""
        eng = self.engine
        if first:  # CFEs in contact at rest (zero gap, not held by supports)
            _, tw = eng.tolerances()
            self._touching = (-self.layout.normal(eng.w) <= tw) & ~self.law.inert
        try:
            try:
                dec = eng.decide(fired, forcing, natural=first)
            except RateProblemFailure as exc:
                trial = self._opening_mechanism(exc.cfes, forcing)
                if trial is None:
                    raise
                raise MechanismError(None, None, trial) from exc
        except MechanismError as exc:
            return self._lose_equilibrium(exc, lam, seg, pattern, mult, self._f)
        except RateProblemFailure as exc:
            self.status = exc.status
            names = [f"{self.cfe.names[self.cfe.interface[k]]}[{self.cfe.local[k]}]"
                     for k in exc.cfes[:10]]
            self.message = f"{exc} at λ = {lam:.10g}; CFEs involved: {', '.join(names)}"
            self.step += 1
            self._record(lam, seg, "event", final=True)
            return False, None, None
        old, new, ds, dw = dec.old, dec.new, dec.ds, dec.dw
        if self._has_residual():
            self._lose_cohesion(new == OPEN)  # an opened joint has no residual cohesion
        switched = dec.switched
        if switched or first or np.count_nonzero(fired) or (self.article and np.any(
                slipping(new))):
            eng.snap()
        if self.article:
            ds, dw = eng.rates(new, forcing, article=True)
        eng.update_scales(ds, dw, self._reach(ds, dw, span))
        if first:
            # contact at rest (zero gaps at λ = 0) is the initial scheme, not an event: compare
            # with "closed" there, so that slips and openings at λ = 0 are events
            touching = self._touching & (old == OPEN)
            old = np.where(touching, np.where(self.law.frictional, STICK, new), old)
            old = np.where(touching & (new == OPEN), self.law.closed_state(), old)
            switched = bool(np.any(old != new))
        if seg_start and not switched and not self._releasing:
            # a state at the start of every segment, so that any λ of it can be interpolated
            self._record(lam, seg, "start" if first else "segment_start")
        if dec.outcome is not None and dec.outcome.alternatives:
            self._nonunique(dec, lam, seg, pattern)
        if switched:
            self.step += 1
            # (while broken bonds release their forces the state after the cascade is
            # recorded, not the ones on the way)
            i = len(self.rec) if self._releasing else self._record(lam, seg, "event")
            self._log_events(old, new, lam, seg, pattern, i, first=mult)
            told = self._hooks_with("after_event")
            if told:
                info = StepInfo(self.step, seg, pattern, lam, len(self.rec.events),
                                int(np.count_nonzero(new == OPEN)),
                                int(np.count_nonzero(slipping(new))))
                for hk in told:
                    hk.after_event(info)
            self._checkpoint()
        return True, ds, dw

    def _segment_scales(self, start: tuple[float, float], whole: tuple[float, float]
                        ) -> tuple[float, float]:
        """Displacement and force scales (m, N) a segment brings at its start, from the sizes
        (max |y|, max |f|) of its response and load at its start (``start``) and over the
        whole segment (``whole``: at its far end, or its node levels for a level path): the
        whole segment's, unless the path already has a size (a force scale) and that would
        grow a scale more than :data:`LOOKAHEAD_GROWTH` times at once — then at most that many
        times (never below the start's); the rates of the scheme decided at the start then
        look ahead to its next event (:meth:`_reach`), event by event.  A segment whose end
        lies absurdly far beyond the limit load (1e10 times) otherwise set limit tolerances
        (LIMIT_TOL · rtol of the scales) of the size of the real forces: a slip load off by
        1e-4, or equilibrium "lost" at once.  From zero (no force scale yet) the whole segment
        is looked at, as before."""
        eng = self.engine
        if eng.F_scale <= 1e-300:  # the start from zero: no size to compare with
            return whole
        w_cap = LOOKAHEAD_GROWTH * eng.W_scale if eng.W_scale > 1e-300 else np.inf
        return (min(whole[0], max(start[0], w_cap)),
                min(whole[1], max(start[1], LOOKAHEAD_GROWTH * eng.F_scale)))

    def _look(self, span: float, far: bool, f: float, path=None) -> float:
        """The length of load factor (λ, or level in m) that sets the relative tolerances of
        the event search (events grouped within 1e-10 of it, steps below 1e-12 of it small):
        the segment's span, or on a segment that runs far beyond the path's size
        (:meth:`_segment_scales`) the length over which its load grows to
        :data:`LOOKAHEAD_GROWTH` times the current force scale (load rate ``f``, max |f'|, N;
        on a level path to the first node level beyond, :meth:`LevelPath.reach`)."""
        if not far:
            return span
        limit = LOOKAHEAD_GROWTH * self.engine.F_scale
        if path is not None:
            return min(span, path.reach(limit))
        return min(span, limit / max(f, 1e-300))

    def _reach(self, ds, dw, span: float) -> float:
        """How far the path's scales look ahead along the rates (ds, dw) of the scheme just
        decided (:meth:`EventEngine.update_scales`): the whole segment (``span``), unless that
        would grow a scale more than :data:`LOOKAHEAD_GROWTH` times at once — then to the
        scheme's next event only.  Near a mechanism the schemes soften and their rates grow
        without bound (the structure approaches its limit load); their product with a segment
        that was to run far beyond the limit inflated the limit tolerances (LIMIT_TOL · rtol
        of the scales) until open CFEs with a real gap counted as closed and were snapped
        shut (a force jump: a violated state, or a rate problem without a solution)."""
        eng = self.engine
        grow = max(float(np.abs(ds).max(initial=0.0)) * span / max(eng.F_scale, 1e-300),
                   float(np.abs(dw).max(initial=0.0)) * span / max(eng.W_scale, 1e-300))
        if grow <= LOOKAHEAD_GROWTH:
            return span
        _, dmu_ev, _ = eng.next_event(ds, dw, span, 0.0)
        return min(span, dmu_ev)

    def _lose_equilibrium(self, exc: MechanismError, lam, seg, pattern, mult, f):
        """The point at ``lam`` is where equilibrium is lost: the scheme decided there (or
        ``exc.states``, the scheme found to be a driven mechanism) has no rates for the load
        rate ``f`` (ndof,) — on a load-factor path the segment's load, on a level path the
        Taylor coefficient of the load that drives the mechanism (:meth:`_level_rates`).
        Reports the mechanism (status ``equilibrium_lost``, the λ or level, the moving bodies)
        or, when two rigid constraints conflict instead, ``rate_problem``; returns
        ``(False, None, None)``, the run's end."""
        eng = self.engine
        old = eng.states.copy()
        states = exc.states if exc.states is not None else eng.states
        clash = constraint_conflict(eng, self.cond, states)
        if clash is not None:
            names = [f"{self.cfe.names[self.cfe.interface[k]]}[{self.cfe.local[k]}]"
                     for k in clash[:10]]
            self.status = Status.RATE_PROBLEM
            self.message = (
                f"rigid contacts conflict at λ = {lam:.10g}: CFEs {', '.join(names)} "
                "constrain the same motion and the load drives them apart (their forces "
                "would jump); give one of the interfaces a compliant layer (ContactLayer) "
                "or leave the shared node out of one of them")
            self.step += 1
            self._record(lam, seg, "event", final=True)
            return False, None, None
        tf, _ = eng.tolerances()
        states = free_to_open(eng, self.cond, self.sys, states, f,
                              self.layout.normal(eng.s), tf)
        self.status = Status.EQUILIBRIUM_LOST
        bodies = describe_mechanism(eng, self.cond, self.sys, states, f)
        modes = ", ".join(f"'{b['body']}' {b['mode']}" for b in bodies) or "mechanism"
        self.message = (f"equilibrium lost at λ = {lam:.10g} (pattern '{pattern}', segment "
                        f"{seg}): {modes}")
        if self.plan is not None and self.plan.auto.get(pattern, ("", ""))[1] == "settle":
            self.message += (
                f" — the dynamic interval of stage '{self.plan.names[self.stage]}' left "
                "the structure moving on a mechanism (a body in flight, or rocking or "
                "sliding with no static equilibrium without its inertia): no static path "
                "goes on from there; lengthen the interval or damp it, so that the "
                "motion ends in contact (the interval's result is in res.dynamics)")
        eng.states = states.copy()
        self.mechanism = {
            "lam": lam, "segment": seg, "pattern": pattern, "bodies": bodies,
            "n_open": int(np.sum(states == OPEN)),
            "n_slip": int(np.sum(slipping(states))),
            "n_cfe": self.cfe.m,
        }
        mult["equilibrium_lost"] = lam
        self.step += 1
        i = self._record(lam, seg, "event", final=True)
        self._log_events(old, eng.states, lam, seg, pattern, i)
        return False, None, None

    def _hooks_with(self, method: str) -> tuple:
        """The hooks that have ``method`` (looked up once per run: asked at every event)."""
        found = getattr(self, "_hooks_by_method", None)
        if found is None or found[0] is not self.hooks:
            found = self._hooks_by_method = (self.hooks, {})
        got = found[1].get(method)
        if got is None:
            got = found[1][method] = tuple(hk for hk in self.hooks if hasattr(hk, method))
        return got

    def _checkpoint(self) -> None:
        """Give hooks that ask for it (``checkpoint_due()``: a result file written at a
        bounded interval of wall time) the run so far, status ``incomplete``."""
        due = [hk for hk in self._hooks_with("checkpoint_due") if hk.checkpoint_due()]
        if due:
            res = self.result(time.perf_counter() - self._t0, partial=True)
            for hk in due:
                hk.checkpoint(res)

    def _opening_mechanism(self, cfes: np.ndarray, forcing) -> np.ndarray | None:
        """When the rate problem has no solution at CFEs that sit at their normal limit
        (N = 0): the scheme with them open, if it is a mechanism that the load drives (a block
        tipping over its last contact point: an overturning, not a failure of the rate
        problem), else None."""
        eng = self.engine
        tf, _ = eng.tolerances()
        cfes = np.asarray(cfes, dtype=np.int64)
        at = cfes[(self.layout.normal(eng.s)[cfes] <= tf) & (eng.states[cfes] != OPEN)]
        if at.size == 0:
            return None
        trial = eng.states.copy()
        trial[at] = OPEN
        try:
            eng.rates(trial, forcing, article=False)
            return None  # a regular scheme: not a mechanism
        except MechanismError:
            return trial if eng.drives(trial, forcing) else None

    def _nonunique(self, dec, lam, seg, pattern):
        out = dec.outcome
        cfe = self.cfe
        L = out.cfes
        self.rec.nonunique.append({
            "lam": lam, "segment": seg, "pattern": pattern,
            "cfes": [f"{cfe.names[cfe.interface[k]]}[{cfe.local[k]}]" for k in L],
            "followed": [state_label(v) for v in dec.new[L]],
            "alternatives": [[state_label(v) for v in alt] for alt in out.alternatives],
            "why": out.method,
        })

    def _resultants(self) -> np.ndarray:
        """(n_patterns, 3) resultant F_x, F_y (N), M_z about the origin (N·m) of every
        pattern's forces per unit λ, computed once; in 3D (n_patterns, 6): F_x, F_y, F_z,
        M_x, M_y, M_z (:func:`~stepcontact.fem.assembly.load_resultant`)."""
        if getattr(self, "_load_resultants", None) is None:
            # DOFs without coordinates (a discrete model): no resultants
            if self.sys.discrete is not None:
                self._load_resultants = np.zeros((0, 3))
                return self._load_resultants
            r = load_resultants(self.sys)
            width = 6 if self.sys.dofs.dim == 3 else 3
            self._load_resultants = np.array([r[n] for n in self.c]).reshape(len(self.c),
                                                                             width)
        return self._load_resultants

    def _moments(self) -> np.ndarray | None:
        """(n_patterns, n_bodies, 7) every pattern's force resultant, first-moment tensor and
        nodal moments per unit λ on every body (:func:`~stepcontact.fem.assembly.load_moments`),
        computed once; None for a discrete model (DOFs without coordinates)."""
        if getattr(self, "_load_moments", None) is None:
            if self.sys.discrete is not None or self.sys.dofs.dim == 3:
                return None
            names = list(self.sys.loads)
            lm = load_moments(self.sys)
            self._load_moments = lm[[names.index(n) for n in self.c]]
        return self._load_moments

    def result(self, elapsed: float, partial: bool = False) -> StaticResult:
        self._flush_reactions()
        if not partial:  # the last state of the run (where it ended or stopped) has its field
            self._store_field(len(self.rec) - 1)
        r, cfe = self.rec, self.cfe
        bond = cohesion_lost = None
        if self.bonds:  # the strengths of bonded joints (eq. (12)), grouted ones included
            bond = cfe.bond if self.plan is None else self.plan.bond
            if bond.shape[1] > 4 and np.any(bond[:, 4] > 0):  # residual cohesion lost
                cohesion_lost = self._cohesion_lost_at.copy()
        counters = (dict(self.cond.counters) | self.schemes.counters | self.engine.counters | {
            "events": len(r.events), "event_points": self.step,
            **self.t_setup, **self._watch.counters("run"), "run_seconds": elapsed,
            "ndof": self.sys.ndof, "cfes": cfe.m,
            "precision_bits": 8 * self.cond.G.dtype.itemsize,
        })
        status, message = self.status, self.message
        if hasattr(self.law, "limit_error"):  # a faceted Coulomb cone (3D): state its error
            message += (f"; friction cone as the inscribed {self.law.k}-gon: its limit is up to "
                        f"{100 * self.law.limit_error:.3g} % below f|N| (1 − cos(π/k)), "
                        "result.cone_ratio gives |Q| / (f|N|)")
        if partial:
            status = Status.INCOMPLETE
            message = (f"run in progress: reached λ = {r.lam.view[-1]:.10g} in segment "
                       f"{int(r.segment.view[-1])}" if len(r) else "run in progress")
        return build_result(
            r, cfe=cfe, cfe_data=cfe_arrays(cfe, bond=bond, cohesion_lost=cohesion_lost),
            pattern_names=tuple(self.c), segments=self._segments, status=status,
            message=message, counters=counters, geometry=result_geometry(self.sys),
            crack=self.crack is not None, mechanism=self.mechanism,
            reaction_labels=tuple(self.sys.reaction_labels),
            load_resultants=self._resultants(), load_moments=self._moments(),
            _recover=self.fields, **self._stage_arrays(),
        )

    def _stage_arrays(self) -> dict:
        """The stage of every state and what acts at each stage (a run in stages)."""
        if self.plan is None:
            return {}
        plan = self.plan
        n = len(plan.names)
        return stage_fields(
            self.rec.stage.view, plan.names,
            np.array([plan.active_cfes(k) for k in range(n)], bool).reshape(n, self.cfe.m),
            tuple(tuple(sorted(plan.active_bodies(k))) for k in range(n)),
            dynamics=dict(self.dynamics))


def solve_static(
    model: Model | DiscreteModel | System,
    *,
    slip: str = "exact",
    eps_p: float = 0.01,
    store_fields: str = "ends",
    max_events: int = 100_000,
    hooks: Sequence = (),
    backend: str = "auto",
    rate_solver: str = "pivoting",
    condensation: Condensation | None = None,
    precision: str = "auto",
    output=None,
    scheduler=None,
) -> StaticResult:
    """Trace the exact quasi-static load path of ``model`` through its load program.

    Parameters
    ----------
    model : Model, DiscreteModel or System
        The model (assembled here), a structure given by its matrices
        (:class:`~stepcontact.model.DiscreteModel`) or an already assembled
        :class:`~stepcontact.fem.System`.
    slip : "exact" or "article"
        Slip treatment: ``exact`` writes Q = σ f (−N) into the working scheme (all events exact);
        ``article`` uses the article's ε_p step limit and compensating forces, eqs. (4)–(6).
    eps_p : float
        ε_p of eq. (5) (article mode only): the largest relative change of a friction limit in
        one step.
    store_fields : "ends", "all" or "auto"
        Which states keep their displacement field and stresses.  ``ends`` (default; ``auto``
        is the same): the start, every segment start and end, and the last state of the run
        (where it completed or stopped); ``all``: every state (one extra solve per event).
        Any other state is exact from its contact unknowns and is recomputed on request:
        :meth:`StaticResult.displacement`, :meth:`StaticResult.displacements` (several states,
        one solve), :meth:`StaticResult.stress` — in memory, or after
        :meth:`StaticResult.recover_fields` for a result loaded from a file.
    max_events : int
        Event-point budget.
    hooks : sequence
        Objects with optional ``before_run(segments)`` (the program as run: (pattern, λ₀, λ₁)
        of every segment, a staged model's automatic ones included), ``after_event(StepInfo)``
        and ``after_segment(StaticResult)``
        (``interrupted(StaticResult)`` on Ctrl-C).
    backend : str
        Factorisation backend (``auto``: dense below 400 DOFs, else ``pypardiso`` when
        installed, else ``scipy``; or by name ``dense``, ``scipy``, ``cholmod``,
        ``pypardiso``).
    rate_solver : str
        First method for the rate problem (an LCP) at degenerate points: ``pivoting``
        (principal pivoting from the current scheme, then Lemke's method) or ``lemke``
        (lexicographic Lemke; where it ends on a secondary ray, principal pivoting takes over,
        counted in ``counters["lemke_fallbacks"]``).
    condensation : Condensation, optional
        A condensation from :func:`condense` for the same structure (checked): runs that
        differ only in friction, gaps, loads or program then share one factorisation.
    precision : "auto", "float64" or "float32"
        Precision of the dense contact matrices (G, the scheme LUs).  ``auto`` (default):
        float64 while they fit in half the physical memory, float32 beyond — the
        large-interface path: half the memory and time of the dense work, every scheme solve
        refined to float64 accuracy against the sparse factorisation (a few extra sparse
        solves per event; schemes with a condition number above about 1e5 count as
        mechanisms).  Too large for both is a :class:`~stepcontact.errors.SolverError` with
        the memory estimate, raised before any work.
    output : path or ResultWriter, optional
        Result file written as the run goes (status ``incomplete`` until it ends; at segment
        ends and at most :data:`~stepcontact.results.file.WRITE_INTERVAL` seconds apart; an
        interrupted run writes every state finished), and at the end.  A path is locked for
        the run (:func:`~stepcontact.atomic.output_lock`: a second run writing it is
        refused); a :class:`~stepcontact.results.file.ResultWriter` is used as it is (its
        interval, its attributes; the caller holds the lock).
    scheduler : str or distributed.Client, optional
        Form the condensed matrix G (of every stage) on a dask.distributed cluster: the
        scheduler's address (``"tcp://10.0.0.5:8786"``) or a Client; each worker factorises
        K₀ once and solves its column blocks (:mod:`stepcontact.solver.cluster`).  The same G
        to round-off, so the same run.  Default: here.

    Returns
    -------
    StaticResult
        Events, states, forces, fields; ``status`` tells whether the program completed or
        equilibrium was lost (with the load factor and the mechanism in ``message``).

    Example
    -------
    >>> import stepcontact as sc
    >>> res = sc.solve_static(sc.demo_model())          # doctest: +SKIP
    >>> res.multipliers[-1].equilibrium_lost            # doctest: +SKIP
    """
    system = model if isinstance(model, System) else assemble(model)
    if not system.model.effective_program and not getattr(system.model, "stages", ()):
        raise ModelError("model.program", "is empty: give at least one load segment")
    if isinstance(system.model, Model):  # what validate checks too, before any work
        from stepcontact.model.consistency import check_consistency

        check_consistency(system.model)
    writer = None
    lock: contextlib.AbstractContextManager = contextlib.nullcontext()
    if output is not None:  # (xarray is imported only for a result file)
        from stepcontact.atomic import output_lock
        from stepcontact.results.file import ResultWriter

        if isinstance(output, ResultWriter):
            writer = output
        else:
            writer = ResultWriter(output, min_interval=1.0)
            lock = output_lock(writer.path)
        hooks = (*hooks, writer)
    with lock:
        solver = StaticSolver(system, slip=slip, eps_p=eps_p, store_fields=store_fields,
                              max_events=max_events, hooks=hooks, backend=backend,
                              rate_solver=rate_solver, condensation=condensation,
                              precision=precision, scheduler=scheduler)
        res = solver.run()
        if writer is not None:
            writer.finish(res)
    return res
