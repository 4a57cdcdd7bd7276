"""The event-driven static solver (method.md §3, article eqs. (1)–(6)).

Between two events the working scheme is fixed and the structure is linear, so every quantity
is linear in the load factor λ.  Each main step:

1. rates of the current scheme (one dense solve on the condensed contact unknowns,
   :mod:`stepcontact.condensation`; the trial step of the article with Δλ̃ = 1);
2. event load factors of every CFE from its event function, vectorised:
   stick → slip, eq. (2): f p − σQ reaches 0;  contact → open, eq. (3): −N reaches 0;
   open → contact, eq. (3): −u_n reaches 0;  (article mode also the ε_p limit, eq. (5));
3. main step Δλ = the smallest of them (and of what is left of the segment); several CFEs
   within a relative 1e-10 of it form one event point;
4. the new working scheme is decided by the *rate problem* over the CFEs at their limits
   (including every slipping CFE, whose slip may reverse): a principal-pivoting search with a
   least-index rule (Murty's method written on CFE states) finds the scheme whose rates satisfy
   all contact conditions; cycling and singular (mechanism) schemes are reported as results;
5. a correction at fixed λ makes the reported state satisfy the relations of the new scheme
   to round-off (in article mode this is the compensating-force correction, eqs. (4), (6)).

Slip treatment ``"exact"`` writes Q = σ f (−N) into the scheme, so events are exact;
``"article"`` holds Q during a step limited by |ΔQ_p / Q_p| ≤ ε_p (eq. (5)) and then corrects it.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from stepcontact.enums import ContactState, SlipTreatment, Status, Transition
from stepcontact.errors import ModelError
from stepcontact.fem.assembly import System, assemble
from stepcontact.model import Body, Model
from stepcontact.results.result import Event, Multipliers, StaticResult
from stepcontact.solver.condensation import (
    Condensed,
    MechanismError,
    SchemeSolver,
    scheme_relations,
)
from stepcontact.solver.lcp import lemke

OPEN, STICK, SLIP_POS, SLIP_NEG = (int(s) for s in (ContactState.OPEN, ContactState.STICK,
                                                    ContactState.SLIP_POS, ContactState.SLIP_NEG))
_INF = np.inf
#: a CFE whose event function is within LIMIT_TOL · rtol of the path's force (displacement)
#: scale is at its limit and joins the rate problem.  Its function is then snapped to the
#: limit, so this bounds the violation of conditions (1) that a reported state can carry.
LIMIT_TOL = 10.0


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


class _RateProblemFailure(Exception):
    def __init__(self, status: Status, cfes: np.ndarray, message: str):
        self.status = status
        self.cfes = cfes
        super().__init__(message)


# --------------------------------------------------------------------------------------------
# event functions (vectorised over CFEs)
# --------------------------------------------------------------------------------------------
def event_functions(states, s, w, f) -> np.ndarray:
    """Values of the event functions, (m, 4): columns
    0: −N (closed CFEs: contact → open, eq. (3)),
    1: f(−N) − Q (stick: → slip+, eq. (2)),  2: f(−N) + Q (stick: → slip−, eq. (2)),
    3: −u_n (open CFEs: open → contact, eq. (3)); +inf where a function does not apply."""
    m = len(states)
    Q, p, un = s[:m], s[m:], w[m:]
    closed = states != OPEN
    stick = states == STICK
    out = np.full((m, 4), _INF)
    out[closed, 0] = p[closed]
    fr = stick & (f > 0)
    out[fr, 1] = f[fr] * p[fr] - Q[fr]
    out[fr, 2] = f[fr] * p[fr] + Q[fr]
    out[~closed, 3] = -un[~closed]
    return out


def event_rates(states, ds, dw, f) -> np.ndarray:
    """Rates of the event functions for the given scheme's rates (same layout)."""
    return np.where(np.isfinite(event_functions(states, np.zeros_like(ds), np.zeros_like(dw), f)),
                    _rate_columns(states, ds, dw, f), 0.0)


def _rate_columns(states, ds, dw, f):
    m = len(states)
    dQ, dp, dun = ds[:m], ds[m:], dw[m:]
    return np.column_stack([dp, f * dp - dQ, f * dp + dQ, -dun])


# --------------------------------------------------------------------------------------------
# the solver
# --------------------------------------------------------------------------------------------
class StaticSolver:
    """Event-driven static analysis of one model.  Use :func:`solve_static`."""

    def __init__(
        self,
        system: System,
        *,
        slip: str | SlipTreatment = "exact",
        eps_p: float = 0.01,
        store_fields: str = "auto",
        max_events: int = 100_000,
        hooks: Sequence = (),
        backend: str = "auto",
        rtol: float = 1e-10,
        rate_solver: str = "pivoting",
    ):
        self.sys = system
        self.cfe = system.cfe
        self.slip = SlipTreatment(slip)
        self.article = self.slip == SlipTreatment.ARTICLE
        if self.article and not 0 < eps_p < 1:
            raise ModelError("eps_p", f"must lie in (0, 1), got {eps_p}")
        self.eps_p = eps_p
        if store_fields not in ("auto", "all", "ends"):
            raise ModelError("store_fields", f"must be auto, all or ends, got '{store_fields}'")
        self.store_fields = store_fields
        if rate_solver not in ("pivoting", "lemke"):
            raise ModelError("rate_solver", f"must be 'pivoting' or 'lemke', got '{rate_solver}'")
        self.rate_solver = rate_solver
        self.max_events = max_events
        self.hooks = tuple(hooks)
        self.rtol = rtol
        t0 = time.perf_counter()
        self.cond = Condensed.from_system(system, backend)
        self.schemes = SchemeSolver(self.cond, system.cfe)
        self.t_setup = time.perf_counter() - t0
        self.f = self.cfe.friction
        self.kt = self.cfe.kt
        m = self.cfe.m
        # state of the path at contact level
        self.c = {name: 0.0 for name in system.loads}
        self.s = np.zeros(2 * m)
        self.w = system.w0.copy()
        self.states = np.full(m, OPEN, dtype=np.int64)
        self.F_scale = 1e-300
        self.W_scale = float(np.max(np.abs(system.w0), initial=0.0)) or 1e-300
        # records
        self._rec: dict[str, list] = {k: [] for k in ("lam", "segment", "factors", "kind", "s", "w",
                                                      "state", "residual", "violation",
                                                      "reactions")}
        self.fields: dict[int, np.ndarray] = {}
        self.stresses: dict[int, dict[str, np.ndarray]] = {}
        self.events: list[Event] = []
        self.multipliers: list[Multipliers] = []
        self.status = Status.COMPLETED
        self.message = "load program completed"
        self.mechanism: dict | None = None
        self.step = 0
        self.counters = {"rate_solves": 0, "pivots": 0, "corrections": 0, "lemke": 0}

    # ---- scales and tolerances ---------------------------------------------------------------
    def _update_scales(self, ds=None, dw=None, span=1.0):
        self.F_scale = max(self.F_scale, float(np.abs(self.s).max(initial=0)))
        self.W_scale = max(self.W_scale, float(np.abs(self.w).max(initial=0)))
        if ds is not None:
            self.F_scale = max(self.F_scale, float(np.abs(ds).max(initial=0)) * span)
            self.W_scale = max(self.W_scale, float(np.abs(dw).max(initial=0)) * span)

    def _tol_phi(self) -> np.ndarray:
        """Absolute tolerance of each event-function column (forces, forces, forces, gaps)."""
        tf, tw = LIMIT_TOL * self.rtol * self.F_scale, LIMIT_TOL * self.rtol * self.W_scale
        return np.array([tf, tf, tf, tw])

    # ---- rates --------------------------------------------------------------------------------
    def _rates(self, states, pattern, article=None, r=None):
        rel = scheme_relations(states, self.cfe, self.article if article is None else article)
        try:
            fact = self.schemes.factor(rel)
        except MechanismError as exc:
            exc.states = states.copy()  # the scheme that is a mechanism, reported with it
            raise
        self.counters["rate_solves"] += 1
        if pattern is None:
            h = np.zeros(2 * self.cfe.m)
            e = h
        else:
            h, e = pattern
        rr = np.zeros(2 * self.cfe.m) if r is None else r
        ds, dw = fact.solve(h, e, rr)
        return ds, dw, fact, rel

    def _limits(self, L: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Which CFEs of L sit at their normal limit (p = 0 closed, or u_n = 0 open), and which
        are two-sided in friction as well (Q = 0 and f p = 0): boolean arrays over all CFEs."""
        m = self.cfe.m
        Q, p = self.s[:m], self.s[m:]
        tf = LIMIT_TOL * self.rtol * self.F_scale
        normal_lim = np.zeros(m, dtype=bool)
        normal_lim[L] = np.where(self.states[L] == OPEN, -self.w[m + L] <= LIMIT_TOL * self.rtol *
                                 self.W_scale, p[L] <= tf)
        two_sided = np.zeros(m, dtype=bool)
        two_sided[L] = normal_lim[L] | ((np.abs(Q[L]) <= tf) & (self.f[L] * p[L] <= tf))
        return normal_lim, two_sided

    def _inconsistent(self, trial, L, ds, dw, normal_lim, two_sided) -> np.ndarray:
        """States the rates of scheme ``trial`` point to for the CFEs in L (equal to
        ``trial[L]`` where the rates satisfy the contact conditions (1) of the CFE)."""
        m = self.cfe.m
        f = self.f
        sigma = np.sign(self.s[:m])
        dQ, dp = ds[:m], ds[m:]
        dg = -dw[m:]
        finite_kt = np.isfinite(self.kt)
        dslip = dw[:m] - np.where(finite_kt, dQ / np.where(finite_kt, self.kt, 1.0), 0.0)
        rf = 1e3 * self.rtol * max(np.abs(ds).max(initial=0), 1e-300)
        rw = 1e3 * self.rtol * max(np.abs(dw).max(initial=0), 1e-300)
        st = trial[L]
        new = st.copy()
        # open: the gap must not close
        viol_open = (st == OPEN) & (dg[L] < -rw)
        new[viol_open] = np.where(f[L][viol_open] > 0, STICK, SLIP_POS)
        # stick
        stick = st == STICK
        nl = normal_lim[L]
        ts = two_sided[L]
        v1 = stick & nl & (dp[L] < -rf)
        new[v1] = OPEN
        v2 = stick & ~v1 & ts & (np.abs(dQ[L]) > f[L] * dp[L] + rf)
        new[v2] = np.where(dQ[L][v2] > 0, SLIP_POS, SLIP_NEG)
        v3 = stick & ~ts & (sigma[L] * dQ[L] > f[L] * dp[L] + rf)
        new[v3] = np.where(sigma[L][v3] > 0, SLIP_POS, SLIP_NEG)
        # slip
        slipping = (st == SLIP_POS) | (st == SLIP_NEG)
        sg = np.where(st == SLIP_POS, 1.0, -1.0)
        v4 = slipping & nl & (dp[L] < -rf)
        new[v4] = OPEN
        v5 = slipping & ~v4 & (f[L] > 0) & (sg * dslip[L] < -rw)
        new[v5] = STICK
        return new

    def _rate_problem(self, L: np.ndarray, guess: np.ndarray, pattern) -> tuple:
        """Choose states of the CFEs in L (ascending) so that the rates are consistent.

        Murty's least-index principal pivoting written on CFE states: solve the rates of the
        trial scheme, find the lowest-index CFE whose rates violate its contact conditions,
        switch it to the state the violation points to, repeat.  If the pivoting cycles or does
        not converge (the rate problem is not a P-problem, e.g. large f), the rate problem is
        written as an LCP and solved by Lemke's method (:meth:`_rate_problem_lemke`).  With
        ``rate_solver="lemke"`` Lemke's method is used whenever the guessed scheme (the current
        one with the natural transitions of the CFEs that fired) is not consistent.  When the
        rate problem has several solutions the one nearest the guess is kept.  Returns
        (states, ds, dw).
        """
        normal_lim, two_sided = self._limits(L)
        if self.rate_solver == "lemke":
            try:  # the guessed scheme is kept when its rates are consistent (as in pivoting)
                ds, dw, *_ = self._rates(guess, pattern, article=False)
                if np.all(self._inconsistent(guess, L, ds, dw, normal_lim, two_sided) ==
                          guess[L]):
                    return guess, ds, dw
            except MechanismError:
                pass
            try:
                return self._rate_problem_lemke(L, guess, pattern, normal_lim, two_sided)
            except _RateProblemFailure:
                pass
        trial = guess.copy()
        visited: set[bytes] = set()
        tried_revert = False
        first_mechanism: MechanismError | None = None
        failure = None
        for _ in range(20 * max(len(L), 1) + 20):
            key = trial[L].tobytes()
            if key in visited:
                failure = _RateProblemFailure(
                    Status.CYCLING, L,
                    "the working schemes cycle: no consistent scheme found by pivoting",
                )
                break
            visited.add(key)
            try:
                ds, dw, fact, rel = self._rates(trial, pattern, article=False)
            except MechanismError as exc:
                if not tried_revert and np.any(trial[L] != self.states[L]):
                    tried_revert = True
                    first_mechanism = exc
                    trial = guess.copy()
                    trial[L] = np.where(self.states[L] == OPEN, OPEN, self.states[L])
                    visited.clear()
                    continue
                if first_mechanism is not None:  # report the natural scheme's mechanism
                    raise first_mechanism from None
                raise
            new = self._inconsistent(trial, L, ds, dw, normal_lim, two_sided)
            bad = np.flatnonzero(new != trial[L])
            if bad.size == 0:
                return trial, ds, dw
            i = bad[0]  # least index rule
            trial = trial.copy()
            trial[L[i]] = new[i]
            self.counters["pivots"] += 1
        if failure is None:
            failure = _RateProblemFailure(
                Status.RATE_PROBLEM, L,
                "pivoting did not find a consistent scheme")
        if self.rate_solver == "lemke":
            raise failure
        try:
            return self._rate_problem_lemke(L, guess, pattern, normal_lim, two_sided)
        except _RateProblemFailure as exc:
            raise _RateProblemFailure(failure.status, L, f"{failure} ({exc})") from None

    def _rate_problem_lemke(self, L, guess, pattern, normal_lim, two_sided) -> tuple:
        """The rate problem over the CFEs in L as an LCP, solved by Lemke's method.

        Base scheme: every CFE of L closed and stuck (frictionless ones: closed, Q = 0), the
        others as in ``guess``.  The LCP variables z ≥ 0 are, per CFE of L, the opening rate o
        (only at the normal limit) and the slip rates a⁺, a⁻ (both when two-sided, else the one
        in the direction of Q), entered through the right-hand side r of the relations (rigid:
        w' = r; compliant layer: s' = C (w' − slip) …).  Their complements are w = (p', f p' − Q',
        f p' + Q') ≥ 0.  One rate solve per variable gives the columns of M.
        """
        m = self.cfe.m
        f = self.f
        fric = f[L] > 0
        base = guess.copy()
        base[L] = np.where(fric, STICK, SLIP_POS)
        # the stiffest choice for L; if it is a mechanism, every scheme is: MechanismError
        ds0, dw0, fact, rel = self._rates(base, pattern, article=False)
        sigma = np.where(self.states == SLIP_NEG, -1.0,
                         np.where(self.states == SLIP_POS, 1.0, np.sign(self.s[:m])))
        var_cfe, var_kind = [], []  # kind: 0 opening, +1 slip+, −1 slip−
        for k, is_fric in zip(L.tolist(), fric.tolist(), strict=True):
            if normal_lim[k]:
                var_cfe.append(k)
                var_kind.append(0)
            if not is_fric:
                continue
            if two_sided[k] or sigma[k] == 0:
                var_cfe += [k, k]
                var_kind += [1, -1]
            else:
                var_cfe.append(k)
                var_kind.append(int(sigma[k]))
        var_cfe = np.asarray(var_cfe, dtype=int)
        var_kind = np.asarray(var_kind, dtype=int)
        nv = len(var_cfe)
        if nv == 0:
            raise _RateProblemFailure(Status.RATE_PROBLEM, L, "Lemke's method: no variables")
        # right-hand sides of the relations for a unit value of each variable
        kt, kn = self.cfe.kt[var_cfe], self.cfe.kn[var_cfe]
        R = np.zeros((2 * m, nv))
        cols = np.arange(nv)
        op = var_kind == 0
        R[m + var_cfe[op], cols[op]] = np.where(np.isfinite(kn[op]), kn[op], -1.0)
        sl = ~op
        R[var_cfe[sl], cols[sl]] = var_kind[sl] * np.where(np.isfinite(kt[sl]), -kt[sl], 1.0)
        zero = np.zeros(2 * m)
        dS = np.empty((2 * m, nv))
        for j in range(nv):
            dS[:, j], _ = fact.solve(zero, zero, R[:, j])
        self.counters["rate_solves"] += nv

        # complements w = c_p p' + c_Q Q' of every variable, for the base rates and each column
        cp = np.where(op, 1.0, f[var_cfe])[:, None]
        cq = np.where(op, 0.0, -var_kind)[:, None]
        W = cp * np.c_[ds0, dS][m + var_cfe] + cq * np.c_[ds0, dS][var_cfe]
        q, Mx = W[:, 0], W[:, 1:]
        sol = lemke(Mx, q)
        self.counters["lemke"] += 1
        if sol.solved:
            active = sol.z > 1e-9 * max(np.abs(sol.z).max(initial=0), 1e-300)
        elif sol.ray is not None:
            active = sol.ray  # the rates grow without bound along this scheme: a mechanism?
        else:
            raise _RateProblemFailure(Status.RATE_PROBLEM, L, f"Lemke's method: {sol.message}")
        trial = base.copy()
        # slips first, then openings override (an opening CFE carries no force)
        for kind, state in ((1, SLIP_POS), (-1, SLIP_NEG), (0, OPEN)):
            sel = active & (var_kind == kind)
            trial[var_cfe[sel]] = state
        # consistent rates exist unless this scheme is a mechanism: equilibrium is lost
        ds, dw, *_ = self._rates(trial, pattern, article=False)
        if not sol.solved:
            raise _RateProblemFailure(Status.RATE_PROBLEM, L, f"Lemke's method: {sol.message}")
        new = self._inconsistent(trial, L, ds, dw, normal_lim, two_sided)
        if np.any(new != trial[L]):
            raise _RateProblemFailure(Status.RATE_PROBLEM, L,
                                      "Lemke's method: its scheme is not consistent")
        return trial, ds, dw

    # ---- corrections at fixed λ (snap to the scheme; article: compensating forces (4)-(6)) ---
    def _correct(self, states):
        m = self.cfe.m
        rel = scheme_relations(states, self.cfe, self.article)
        Q, p = self.s[:m], self.s[m:]
        un = self.w[m:]
        closed = states != OPEN
        slipping = (states == SLIP_POS) | (states == SLIP_NEG)
        sig = np.where(states == SLIP_POS, 1.0, -1.0)
        r = np.zeros(2 * m)
        # open: zero forces
        r[:m] = np.where(~closed, -Q, 0.0)
        r[m:] = np.where(~closed, -p, 0.0)
        # closed rigid normal: u_n = 0; compliant: p = C_n u_n
        rigid_n = ~np.isfinite(self.cfe.kn)
        r[m:] = np.where(closed & rigid_n, -un, r[m:])
        kn = np.where(rigid_n, 0.0, self.cfe.kn)
        r[m:] = np.where(closed & ~rigid_n, kn * un - p, r[m:])
        # slipping: Q = σ f p (article: the compensating correction δQ of eq. (4))
        r[:m] = np.where(slipping, sig * self.f * p - Q, r[:m])
        if not np.any(np.abs(r) > 0):
            return
        fact = self.schemes.factor(rel)
        ds, dw = fact.solve(np.zeros(2 * m), np.zeros(2 * m), r)
        self.s += ds
        self.w += dw
        self.counters["corrections"] += 1

    # ---- recording ----------------------------------------------------------------------------
    def _store_all_fields(self) -> bool:
        if self.store_fields == "all":
            return True
        if self.store_fields == "ends":
            return False
        return self.sys.ndof <= 20_000

    def _record(self, lam: float, seg: int, kind: str):
        i = len(self._rec["lam"])
        store = kind != "event" or self._store_all_fields()
        if store:  # full field: residual of the whole model and kinematics B u + w⁰ = w
            u = self.cond.displacement(self.c, self.s, self.w)
            res, kin = self.cond.check(self.c, self.s, self.w, u, self.W_scale)
        else:  # no solve: the condensed equations (equivalent), field recoverable on request
            res, kin = self.cond.condensed_residual(self.c, self.s, self.w, self.W_scale), 0.0
        viol = max(kin, self._violation())
        r = self._rec
        r["lam"].append(lam)
        r["segment"].append(seg)
        r["factors"].append([self.c[n] for n in self.c])
        r["kind"].append(kind)
        r["s"].append(self.s.copy())
        r["w"].append(self.w.copy())
        r["state"].append(self.states.copy())
        r["residual"].append(res)
        r["violation"].append(viol)
        r["reactions"].append(self.cond.reactions(self.c, self.s, self.w))
        if store:
            self.fields[i] = u
            self.stresses[i] = self._stresses(u)
        return i

    def _violation(self) -> float:
        """Largest relative violation of conditions (1) (and of the slip law) at the state."""
        m = self.cfe.m
        if m == 0:
            return 0.0
        Q, p = self.s[:m], self.s[m:]
        un = self.w[m:]
        F, W = max(self.F_scale, 1e-300), max(self.W_scale, 1e-300)
        closed = self.states != OPEN
        rigid_n = ~np.isfinite(self.cfe.kn)
        v = [
            np.maximum(-p, 0) / F,  # N <= 0
            np.where(~closed, np.abs(p) + np.abs(Q), 0) / F,  # open: N = Q = 0
            np.where(~closed, np.maximum(un, 0), 0) / W,  # open: u_n <= 0
            np.where(closed & rigid_n, np.abs(un), 0) / W,  # closed rigid: u_n = 0
            np.maximum(np.abs(Q) - self.f * p, 0) / F,  # |Q| <= f(-N)
        ]
        sl = (self.states == SLIP_POS) | (self.states == SLIP_NEG)
        sig = np.where(self.states == SLIP_POS, 1.0, -1.0)
        v.append(np.where(sl, np.abs(Q - sig * self.f * p), 0) / F)
        return float(max(x.max(initial=0) for x in v))

    def _stresses(self, u):
        out = {}
        from stepcontact.fem import continuum as _fem

        off = self.sys.model.node_offsets
        for b in self.sys.model.bodies:
            if isinstance(b, Body):
                ids = off[b.name] + np.arange(b.n_nodes)
                ub = u[self.sys.dofs.of[ids][:, :2].ravel()]
                out[b.name] = _fem.stresses(b, ub, self.sys.model.plane)
        return out

    def _log_events(self, old, new, lam, seg, pattern, state_index):
        m = self.cfe.m
        changed = np.flatnonzero(old != new)
        cfe = self.cfe
        for k in changed:
            o, n = ContactState(int(old[k])), ContactState(int(new[k]))
            tr = Transition.between(o, n)
            if cfe.friction[k] == 0 and n.closed and o.closed:
                continue  # frictionless: slip direction changes are not events
            if cfe.friction[k] == 0 and n.closed:
                tr = Transition.CLOSED
            self.events.append(Event(
                step=self.step, state=state_index, segment=seg, pattern=pattern, lam=lam,
                cfe=int(k), interface=cfe.names[cfe.interface[k]], local=int(cfe.local[k]),
                position=float(cfe.s[k]), x=float(cfe.x[k, 0]), y=float(cfe.x[k, 1]),
                transition=tr, N=float(-self.s[m + k]), Q=float(self.s[k]),
            ))

    # ---- mechanism description ----------------------------------------------------------------
    def _describe_mechanism(self, exc: MechanismError, lam: float, pattern: str, seg: int):
        # the mechanism in which the load does the most work: among the null modes of the
        # scheme, the combination along f (a slab freed of all contact can translate and
        # rotate; the load lifts it)
        T = self.cond.null_modes(exc.A, exc.lu)
        U = np.column_stack([self.cond.mode_displacement(T[:, j]) for j in range(T.shape[1])])
        lv = self.sys.loads[pattern]
        work = lv.f @ U
        if np.any(work != 0):  # u ∝ projection of f on the modes: largest work per ‖u‖
            u = U @ np.linalg.lstsq(U.T @ U, work, rcond=None)[0]
        else:
            u = U[:, 0]
        model = self.sys.model
        off = model.node_offsets
        umax = np.abs(u).max() or 1.0
        bodies = []
        for b in model.bodies:
            ids = off[b.name] + np.arange(b.n_nodes)
            ub = u[self.sys.dofs.of[ids][:, :2]] / umax
            if np.abs(ub).max() < 1e-3:
                continue
            xc = b.points.mean(axis=0)
            x = b.points - xc
            # rigid fit u = T + θ ẑ × (x − x̄)
            A = np.zeros((2 * len(x), 3))
            A[0::2, 0] = 1
            A[1::2, 1] = 1
            A[0::2, 2] = -x[:, 1]
            A[1::2, 2] = x[:, 0]
            sol = np.linalg.lstsq(A, ub.ravel(), rcond=None)[0]
            size = float(np.ptp(b.points, axis=0).max())
            tx, ty, th = sol
            # centre of rotation P (u(P) = 0): a rotation about a point near the body is
            # overturning; a far centre is a translation (sliding, lift-off)
            centre = None
            if abs(th) * size > 1e-9 * max(abs(tx), abs(ty), 1e-300):
                centre = xc + np.array([-ty, tx]) / th
                centre[np.abs(centre) < 1e-9 * size] = 0.0  # round-off off a zero coordinate
            if centre is not None and np.linalg.norm(centre - xc) <= 5.0 * size:
                mode = f"rotation (overturning) about ({centre[0]:.4g}, {centre[1]:.4g})"
            elif abs(tx) >= abs(ty):
                mode = "sliding"
            else:
                mode = "lift-off" if ty > 0 else "sinking"
            bodies.append({"body": b.name, "mode": mode, "translation": [float(tx), float(ty)],
                           "rotation": float(th),
                           "centre": None if centre is None else [float(c) for c in centre]})
        m = self.cfe.m
        return {
            "lam": lam,
            "segment": seg,
            "pattern": pattern,
            "bodies": bodies,
            "n_open": int(np.sum(self.states == OPEN)),
            "n_slip": int(np.sum((self.states == SLIP_POS) | (self.states == SLIP_NEG))),
            "n_cfe": m,
        }

    # ---- main loop ----------------------------------------------------------------------------
    def run(self) -> StaticResult:
        t0 = time.perf_counter()
        segments = self.sys.model.segments_resolved()
        m = self.cfe.m
        first = True
        for seg, (pattern, lam0, lam1) in enumerate(segments):
            mult = {"first_slip": None, "first_opening": None, "first_closing": None,
                    "equilibrium_lost": None}
            direction = 1.0 if lam1 >= lam0 else -1.0
            span = abs(lam1 - lam0)
            big = max(abs(lam0), abs(lam1))
            y_max = float(np.abs(self.cond.y[pattern]).max(initial=0))
            f_max = float(np.abs(self.sys.loads[pattern].f).max(initial=0))
            self.W_scale = max(self.W_scale, y_max * big)
            self.F_scale = max(self.F_scale, f_max * big)
            h = direction * self.cond.hhat[pattern]
            e = direction * self.cond.e[pattern]
            mu = 0.0
            lam = lam0
            stop = False
            # start of segment: rate problem over everything at its limit
            fired = np.zeros(m, dtype=bool)
            small_steps = 0
            seg_start = True
            while True:
                lam = lam0 + direction * mu
                ok, ds, dw = self._event_point(fired, (h, e), lam, seg, pattern, mult, first, span,
                                               seg_start)
                first = seg_start = False
                if not ok:
                    stop = True
                    break
                if mu >= span:
                    break
                # event search
                phi = event_functions(self.states, self.s, self.w, self.f)
                dphi = _rate_columns(self.states, ds, dw, self.f)
                rate_tol = 1e3 * self.rtol * np.array(
                    [max(np.abs(ds).max(initial=0), 1e-300)] * 3
                    + [max(np.abs(dw).max(initial=0), 1e-300)])
                active = np.isfinite(phi) & (dphi < -rate_tol)
                steps = np.where(active, np.maximum(phi, 0.0) / np.where(active, -dphi, 1.0), _INF)
                if self.article:
                    sl = (self.states == SLIP_POS) | (self.states == SLIP_NEG)
                    dqp = self.f * ds[m:]
                    qp = self.f * self.s[m:]
                    lim = np.where(sl & (np.abs(dqp) > 0),
                                   np.abs(self.eps_p * qp / np.where(dqp != 0, dqp, 1.0)), _INF)
                    dmu_p = float(lim.min(initial=_INF))
                else:
                    dmu_p = _INF
                dmu_ev = float(steps.min(initial=_INF))
                remaining = span - mu
                dmu = min(dmu_ev, dmu_p, remaining)
                if dmu <= 1e-12 * max(span, 1.0):
                    small_steps += 1
                    if small_steps > 100:
                        self.status = Status.CYCLING
                        self.message = f"no progress at λ = {lam:.10g}: events repeat"
                        stop = True
                        break
                else:
                    small_steps = 0
                grp = 1e-10 * max(abs(lam), span, 1.0)
                fired = np.any(steps <= dmu + grp, axis=1) & (dmu_ev <= dmu + grp)
                self.s += dmu * ds
                self.w += dmu * dw
                self.c[pattern] += direction * dmu
                mu = mu + dmu
                if dmu == remaining or mu >= span * (1 - 1e-15):
                    mu = span
                    self.c[pattern] = lam1
                    if not fired.any():
                        if self.article:
                            self._correct(self.states)
                        break
                if self.step >= self.max_events:
                    self.status = Status.MAX_EVENTS
                    self.message = f"event budget of {self.max_events} exhausted at λ = {lam:.6g}"
                    stop = True
                    break
            lam = lam0 + direction * mu
            if not stop or self.status == Status.EQUILIBRIUM_LOST:
                if not stop:
                    self._record(lam1, seg, "segment_end")
            self.multipliers.append(Multipliers(seg, pattern, **mult))
            for hk in self.hooks:
                if hasattr(hk, "after_segment"):
                    hk.after_segment(self._result(time.perf_counter() - t0, partial=True))
            if stop:
                break
        return self._result(time.perf_counter() - t0)

    def _event_point(self, fired, pattern_rates, lam, seg, pattern, mult, first, span,
                     seg_start=False):
        """Decide the scheme at the current point; record it if anything changed."""
        self._update_scales()
        tol = self._tol_phi()
        phi = event_functions(self.states, self.s, self.w, self.f)
        at_limit = np.any(phi <= tol[None, :], axis=1) | fired
        slipping = (self.states == SLIP_POS) | (self.states == SLIP_NEG)
        L = np.flatnonzero(at_limit | slipping)
        guess = self.states.copy()
        # natural transitions of the CFEs whose functions fired
        if fired.any() or first:
            col = np.argmin(np.where(np.isfinite(phi), phi / tol[None, :], _INF), axis=1)
            lim = at_limit  # slipping CFEs have only column 0 (p → 0: open)
            guess = np.where(lim & (col == 0), OPEN, guess)
            guess = np.where(lim & (col == 1), SLIP_POS, guess)
            guess = np.where(lim & (col == 2), SLIP_NEG, guess)
            guess = np.where(lim & (col == 3), np.where(self.f > 0, STICK, SLIP_POS), guess)
        old = self.states.copy()
        try:
            if L.size:
                new, ds, dw = self._rate_problem(L, guess, pattern_rates)
            else:
                new = guess
                ds, dw, *_ = self._rates(new, pattern_rates, article=False)
        except MechanismError as exc:
            self.status = Status.EQUILIBRIUM_LOST
            info = self._describe_mechanism(exc, lam, pattern, seg)
            modes = ", ".join(f"'{b['body']}' {b['mode']}" for b in info["bodies"]) or "mechanism"
            self.message = (f"equilibrium lost at λ = {lam:.10g} (pattern '{pattern}', segment "
                            f"{seg}): {modes}")
            self.mechanism = info
            mult["equilibrium_lost"] = lam
            if getattr(exc, "states", None) is not None:
                # report the scheme that is the mechanism (e.g. the last CFEs slipping)
                self.states = exc.states
            self.step += 1
            i = self._record(lam, seg, "event")
            self._log_events(old, self.states, lam, seg, pattern, i)
            return False, None, None
        except _RateProblemFailure as exc:
            self.status = exc.status
            names = [f"{self.cfe.names[self.cfe.interface[k]]}[{self.cfe.local[k]}]"
                     for k in exc.cfes[:10]]
            self.message = f"{exc} at λ = {lam:.10g}; CFEs involved: {', '.join(names)}"
            self.step += 1
            self._record(lam, seg, "event")
            return False, None, None
        self.states = new
        switched = bool(np.any(old != new))
        changed = switched or first
        if changed or fired.any() or (self.article and np.any((new == SLIP_POS) |
                                                              (new == SLIP_NEG))):
            self._correct(new)
        if self.article:
            ds, dw, *_ = self._rates(new, pattern_rates, article=True)
        self._update_scales(ds, dw, span)
        if first and switched:
            # contact made at the very start (zero gaps at λ = 0) is the initial scheme, not an
            # event: compare with "closed and stuck" there, so only slips at λ = 0 are events
            made = (old == OPEN) & (new != OPEN)
            old = np.where(made, np.where(self.f > 0, STICK, new), old)
            switched = bool(np.any(old != new))
        if seg_start and not switched:
            # a state at the start of every segment, so that any λ of it can be interpolated
            self._record(lam, seg, "start" if first else "segment_start")
        if switched:
            self.step += 1
            i = self._record(lam, seg, "event")
            n_before = len(self.events)
            self._log_events(old, new, lam, seg, pattern, i)
            for ev in self.events[n_before:]:
                key = {Transition.OPENED: "first_opening", Transition.CLOSED: "first_closing",
                       Transition.SLIP_POS: "first_slip", Transition.SLIP_NEG: "first_slip"}.get(
                           ev.transition)
                if key and mult[key] is None:
                    mult[key] = lam
            info = StepInfo(self.step, seg, pattern, lam, len(self.events),
                            int(np.sum(new == OPEN)), int(np.sum((new == SLIP_POS) |
                                                                 (new == SLIP_NEG))))
            for hk in self.hooks:
                if hasattr(hk, "after_event"):
                    hk.after_event(info)
        return True, ds, dw

    def _result(self, elapsed: float, partial: bool = False) -> StaticResult:
        r = self._rec
        m = self.cfe.m
        n = len(r["lam"])
        S = np.array(r["s"]).reshape(n, 2 * m)
        W = np.array(r["w"]).reshape(n, 2 * m)
        cfe = self.cfe
        cfe_arrays = {
            "interface": cfe.interface, "local": cfe.local, "s": cfe.s, "x": cfe.x,
            "normal": cfe.normal, "area": cfe.area, "friction": cfe.friction, "gap": cfe.gap,
            "kn": cfe.kn, "kt": cfe.kt, "tangent": cfe.tangent,
            "plus_nodes": cfe.plus_nodes, "plus_w": cfe.plus_w,
            "minus_nodes": cfe.minus_nodes, "minus_w": cfe.minus_w,
        }
        model = self.sys.model
        geometry = {
            "points": model.points,
            "dof_of": self.sys.dofs.of,
            "bodies": [
                {"name": b.name, "kind": b.kind, "element": getattr(b, "element", "frame2"),
                 "cells": b.cells + model.node_offsets[b.name]}
                for b in model.bodies
            ],
        }
        counters = dict(self.cond.counters) | self.counters | {
            "events": len(self.events), "event_points": self.step,
            "setup_seconds": self.t_setup, "run_seconds": elapsed,
            "ndof": self.sys.ndof, "cfes": m,
        }
        res = StaticResult(
            pattern_names=tuple(self.c), segments=self.sys.model.segments_resolved(),
            cfe=cfe_arrays, interface_names=cfe.names,
            lam=np.array(r["lam"], float), segment=np.array(r["segment"], np.int64),
            factors=np.array(r["factors"], float).reshape(n, len(self.c)),
            kind=np.array(r["kind"], dtype=object).astype(str),
            N=-S[:, m:], Q=S[:, :m], un=W[:, m:], ut=W[:, :m],
            state=np.array(r["state"], np.int64).reshape(n, m),
            residual=np.array(r["residual"], float), violation=np.array(r["violation"], float),
            events=list(self.events), multipliers=list(self.multipliers),
            status=self.status if not partial else self.status, message=self.message,
            fields=dict(self.fields), stresses=dict(self.stresses), counters=counters,
            mechanism=self.mechanism, geometry=geometry,
            reactions=np.array(r["reactions"], float).reshape(n, len(self.sys.reaction_labels)),
            reaction_labels=tuple(self.sys.reaction_labels),
        )
        factors = r["factors"]
        names = list(self.c)
        S_ = [s.copy() for s in r["s"]]
        W_ = [w.copy() for w in r["w"]]
        cond = self.cond

        def recover(i: int) -> np.ndarray:
            return cond.displacement(dict(zip(names, factors[i], strict=True)), S_[i], W_[i])

        res._recover = recover
        return res


def solve_static(
    model: Model | System,
    *,
    slip: str = "exact",
    eps_p: float = 0.01,
    store_fields: str = "auto",
    max_events: int = 100_000,
    hooks: Sequence = (),
    backend: str = "auto",
    rate_solver: str = "pivoting",
) -> StaticResult:
    """Trace the exact quasi-static load path of ``model`` through its load program.

    Parameters
    ----------
    model : Model or System
        The model (assembled here) or an already assembled :class:`~stepcontact.assembly.System`.
    slip : "exact" or "article"
        Slip treatment: ``exact`` writes Q = σ f (−N) into the working scheme (all events exact);
        ``article`` uses the article's ε_p step limit and compensating forces, eqs. (4)–(6).
    eps_p : float
        ε_p of eq. (5) (article mode only): the largest relative change of a friction limit in
        one step.
    store_fields : "auto", "all" or "ends"
        Which states keep full displacement fields and stresses (the start, segment starts and
        segment ends always do; ``auto`` stores all states for models up to 20 000 DOFs).  Any
        other state can be recovered afterwards with :meth:`StaticResult.displacement` while
        the result is in memory.
    max_events : int
        Event-point budget.
    hooks : sequence
        Objects with optional ``after_event(StepInfo)`` and ``after_segment(StaticResult)``.
    backend : str
        Sparse factorisation backend (``auto``, ``scipy``, ``cholmod``, ``pypardiso``).
    rate_solver : str
        Rate problem of a new scheme: ``pivoting`` (least-index principal pivoting on CFE
        states, Lemke's method when it cycles) or ``lemke`` (Lemke's method first).

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
    if not system.model.program:
        raise ModelError("model.program", "is empty: give at least one load segment")
    solver = StaticSolver(system, slip=slip, eps_p=eps_p, store_fields=store_fields,
                          max_events=max_events, hooks=hooks, backend=backend,
                          rate_solver=rate_solver)
    return solver.run()
