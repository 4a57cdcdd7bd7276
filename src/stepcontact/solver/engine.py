"""The event engine: the contact state along a path, its events and the next working scheme.

It knows nothing of load factors or time.  A driver gives it the rates of the load on the
contact unknowns (the *forcing* (ĥ, e) of :mod:`stepcontact.solver.condensation`) and a step
parameter μ; between two events the working scheme is fixed and every contact unknown is
linear in μ, so the engine

1. finds the earliest root of all event functions of all laws along the current rates
   (vectorised; eqs. (2)–(3)); several CFEs whose roots lie within a relative 1e-10 of it form
   one event point (:meth:`EventEngine.next_event`);
2. advances the contact unknowns to it (:meth:`EventEngine.advance`);
3. decides the next scheme by the consistency check over every CFE at its limits and every
   slipping CFE (:meth:`EventEngine.decide`, the rate problem of
   :mod:`stepcontact.solver.rate`);
4. snaps the state onto the relations of the new scheme at the fixed point (round-off; in the
   article's slip treatment the compensating forces of eqs. (4), (6)).

Restart: a CFE whose function has just reached zero has, under the rates of the new scheme, a
rate that keeps it admissible (the consistency check guarantees it), and only functions with a
negative rate beyond round-off can fire; so no event fires twice at one point and none between
two points is skipped (the earliest root is always taken).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from stepcontact.contact.laws import OPEN, STICK, Relations
from stepcontact.contact.layout import ContactLayout
from stepcontact.enums import slipping
from stepcontact.solver.rate import RateOutcome, solve_rate_problem
from stepcontact.solver.schemes import (
    MechanismError,
    SchemeSolver,
    lu,
    norm2,
    null_modes,
    scheme_rhs,
)

#: a CFE whose event function is within LIMIT_TOL · rtol of the path's force (displacement)
#: scale is at its limit and joins the rate problem.  Its function is then snapped to the
#: limit, so this bounds the violation of conditions (1) that a reported state can carry.
LIMIT_TOL = 10.0
_INF = np.inf
#: the self-stresses of a singular scheme are found (by an SVD, O((2m)³)) up to this many
#: contact unknowns; beyond, a redundant scheme takes the minimum-norm rates
SELF_STRESS_MAX = 2000
#: a singular scheme that inverse iteration finds not driven is checked against its whole left
#: null space (an SVD, O((2m)³)) up to this many contact unknowns
DRIVES_SVD_MAX = 400
#: the G t kept current along the path (:meth:`EventEngine.tracked_product`) serves a check when
#: the bound of its error is at most this fraction of ‖G t‖∞, for this many checks in a row
#: before it is formed in full again
TRACK_TOL = 1e-13
TRACK_REFRESH = 32
#: a snap whose right-hand sides are all at most this fraction of the path's scales only
#: corrects round-off, and is made CFE by CFE (:meth:`EventEngine._snap_roundoff`)
SNAP_ROUNDOFF = 16 * np.finfo(float).eps


@dataclass
class Decision:
    """What :meth:`EventEngine.decide` settled at a point."""

    old: np.ndarray
    new: np.ndarray
    ds: np.ndarray
    dw: np.ndarray
    outcome: RateOutcome | None = None

    @property
    def switched(self) -> bool:
        return bool(np.count_nonzero(self.old != self.new))


class EventEngine:
    """Contact state (states, s = [Q; p], w = [u_τ; u_n]) of all CFEs, moved from event to
    event by a driver.

    Parameters
    ----------
    schemes : SchemeSolver
        Solves working schemes on the condensed contact unknowns.
    laws : list
        Contact laws (:class:`~stepcontact.contact.laws.CoulombLaw`, …), each over its CFEs.
    w0 : (2m,) float
        Mutual displacements at rest ([0; −g⁰]).
    rtol : float
        Relative tolerance of the path (event grouping, limits, rate signs).
    article : bool
        The article's slip treatment (eqs. (4)–(6)) instead of the exact one.
    rate_solver : "pivoting" or "lemke"
        First method for the rate problem's LCP.
    layout : ContactLayout, optional
        The layout of the contact unknowns (default: 2D, m = len(w0) / 2).
    """

    def __init__(self, schemes: SchemeSolver, laws: list, w0: np.ndarray, *, rtol: float = 1e-10,
                 article: bool = False, eps_p: float = 0.01, rate_solver: str = "pivoting",
                 layout: ContactLayout | None = None):
        self.schemes = schemes
        self.layout = ContactLayout.of_size(len(w0)) if layout is None else layout
        self.m = self.layout.m
        self.laws = laws
        self.rtol = rtol
        self.article = article
        self.eps_p = eps_p
        self.rate_solver = rate_solver
        self.states = np.full(self.m, OPEN, dtype=np.int64)
        self.s = self.layout.zeros()
        self.w = np.asarray(w0, float).copy()
        self.F_scale = 1e-300
        self.W_scale = float(np.max(np.abs(w0), initial=0.0)) or 1e-300
        self.counters = {"rate_solves": 0, "pivots": 0, "corrections": 0, "lemke": 0,
                         "lemke_fallbacks": 0}
        self._relations: dict[tuple, Relations] = {}
        self._self_stress: dict[bytes, np.ndarray] = {}
        #: load rates at or below this (absolute, m) are round-off: they drive nothing
        #: (:meth:`drives`; set by the dynamic driver per step, −1 on a static path)
        self.rest_scale = -1.0
        #: G t of the state kept current as the engine moves it (:meth:`tracked_product`):
        #: (solver, t, G t, products since the last full one) or None; and the recent rates
        #: with their scheme solutions y and products G y, ``(s', w', y, G y)``
        self._track: tuple | None = None
        self._pairs: list[tuple] = []
        self._views_sw: tuple | None = None
        #: max |s'|, max |w'| of the last rates asked (:meth:`_rate_scales`)
        self._scales_of: tuple = (None, None, 0.0, 0.0)

    # ---- the laws and their CFEs ------------------------------------------------------------
    @property
    def laws(self) -> list:
        """The contact laws, each over its CFEs (a driver may replace the list: a stage)."""
        return self._laws

    @laws.setter
    def laws(self, laws: list) -> None:
        self._laws = laws
        self._views = self._law_views(laws)

    def _law_views(self, laws) -> list[tuple]:
        """Per law: (law, its CFEs as an index — ``slice(None)`` when the law governs every
        CFE in order, the common case: its arrays are then views of the engine's, no copies —
        and the mask of its gap columns among its event functions)."""
        self._views_of = list(laws)  # (the laws the views are of, compared by identity)
        out = []
        for law in laws:
            c = np.asarray(law.cfes)
            full = len(c) == self.m and bool(np.array_equal(c, np.arange(self.m)))
            out.append((law, slice(None) if full else c,
                        np.asarray(law.column_kinds) == 1))
        return out

    def _views_now(self) -> list[tuple]:
        """:meth:`_law_views` of the current list of laws (rebuilt if the list was changed in
        place)."""
        laws = self._laws
        if (laws if type(laws) is list else list(laws)) != self._views_of:
            self._views = self._law_views(laws)
        return self._views

    # ---- scales and tolerances ---------------------------------------------------------------
    def update_scales(self, ds=None, dw=None, span: float = 1.0) -> None:
        """Force and displacement scales of the path so far (and of the coming step)."""
        self.F_scale = max(self.F_scale, _absmax(self.s))
        self.W_scale = max(self.W_scale, _absmax(self.w))
        if ds is not None:
            a, b = self._rate_scales(ds, dw)
            self.F_scale = max(self.F_scale, a * span)
            self.W_scale = max(self.W_scale, b * span)

    def _rate_scales(self, ds, dw) -> tuple[float, float]:
        """(max |s'|, max |w'|) of rates (s', w'), kept for the last pair asked: a point asks
        for those of the same rates in the consistency check, the scales and the next event
        (rates are never changed in place once formed: the engine tells them by identity,
        :meth:`_follow`)."""
        a, b, fa, fb = self._scales_of
        if a is ds and b is dw:
            return fa, fb
        fa, fb = _absmax(ds), _absmax(dw)
        self._scales_of = (ds, dw, fa, fb)
        return fa, fb

    def tolerances(self) -> tuple[float, float]:
        """Absolute limit tolerances (forces, displacements)."""
        return LIMIT_TOL * self.rtol * self.F_scale, LIMIT_TOL * self.rtol * self.W_scale

    # ---- per-law views ----------------------------------------------------------------------
    def _state_views(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(Q, p, u_n): views of the state's s and w, kept while s and w are the same arrays
        (the engine moves them in place)."""
        v = self._views_sw
        if v is not None and v[0] is self.s and v[1] is self.w:
            return v[2]
        Q, p = self.layout.split(self.s)
        out = (Q, p, self.layout.normal(self.w))
        self._views_sw = (self.s, self.w, out)
        return out

    def _parts(self, s, w):
        lay = self.layout
        Q, p = lay.split(s)
        ut, un = lay.split(w)
        for law, c, _gap in self._views_now():
            if type(c) is slice:  # every CFE, in order: views
                yield law, c, Q, p, ut, un
            else:
                yield law, c, Q[c], p[c], ut[c], un[c]

    def relations(self, states: np.ndarray, article: bool | None = None) -> Relations:
        """The relations of the scheme ``states`` (the last few are kept: a point asks for the
        same scheme's relations in the rate problem and in the correction)."""
        art = self.article if article is None else article
        key = (states.tobytes(), art)
        rel = self._relations.get(key)
        if rel is not None:
            return rel
        views = self._views_now()
        if (len(views) == 1 and type(views[0][1]) is slice
                and getattr(views[0][0], "writes_every_block", False)):  # no blocks to clear
            rel = Relations.blank(self.layout)
            views[0][0].relations(states, rel, self.layout, art)
        else:
            rel = Relations.empty(self.layout)
            for law in self.laws:
                law.relations(states[law.cfes], rel, self.layout, art)
        self._relations[key] = rel
        if len(self._relations) > 8:
            del self._relations[next(iter(self._relations))]
        return rel

    def factor(self, states: np.ndarray, article: bool | None = None):
        try:
            return self.schemes.factor(self.relations(states, article))
        except MechanismError as exc:
            exc.states = states.copy()
            raise

    def rates(self, states, forcing, r=None, article: bool | None = None):
        """Rates (s', w') of the scheme ``states`` under ``forcing`` = (ĥ, e) and relation
        right-hand sides r (default 0).  Raises :class:`MechanismError` if it is singular."""
        fact = self.factor(states, article)
        self.counters["rate_solves"] += 1
        h, e = forcing
        try:  # (a float32 update that does not refine is refactorised: maybe singular)
            out = fact.load_rates(h, e) if r is None else fact.solve(h, e, r)
        except MechanismError as exc:
            exc.states = states.copy()
            raise
        self._note(*out)
        return out

    # ---- G t of the state, kept current (the residual check of a recorded state) -------------
    def _note(self, ds, dw) -> None:
        """Keep (s', w') with the solution y and product G y the scheme solver formed for
        them (``SchemeSolver.last_product``), for :meth:`_follow`."""
        lp = self.schemes.last_product
        self.schemes.last_product = None
        if lp is not None and lp[0] is ds and np.ndim(ds) == 1:
            self._pairs.append((ds, dw, lp[1], lp[2]))
            if len(self._pairs) > 8:
                del self._pairs[0]

    def _follow(self, ds, dw, scale: float) -> None:
        """The state moved by ``scale`` (s', w'): t = s − D ŵ moves by ``scale`` y and G t by
        ``scale`` G y, with the y and G y of those rates (:meth:`_note`); rates without them
        end the tracking (the next check forms G t afresh)."""
        if self._track is None or scale == 0.0:
            return
        for a, b, y, gy in reversed(self._pairs):
            if a is ds and b is dw:
                _, t, gt, _ = self._track
                t += scale * y
                gt += scale * gy
                return
        self._track = None

    def tracked_product(self, t: np.ndarray, full) -> tuple[np.ndarray, float]:
        """G t for the residual check of the state, t = s − D ŵ (given by the driver from the
        state's s, w and load factors), and a bound of its error (0 when formed in full).

        The engine keeps G t current as it moves the state: every move along rates adds the
        step times the product G y that the scheme solver formed for them (y = t', the
        change of t per unit step, whatever the load moves; the snap's correction likewise),
        O(n) per move instead of a pass over G.  The tracked t is compared with the
        driver's: the product of their difference δ is bounded by ‖G‖∞ ‖δ‖∞ (both are sums
        of the same steps, so δ is round-off), and that bound is returned to be added to
        the residual — never an underestimate.  G t is formed in full (``full(t)``, one
        pass; then the bound is 0) at the first check, whenever the state moved other than
        along tracked rates (a stage, a dynamic interval, crack water, rates of a degenerate
        point's LCP), when the bound exceeds ``TRACK_TOL`` of ‖G t‖∞, and after
        ``TRACK_REFRESH`` tracked checks (the sum of the steps' products drifts by
        round-off, like the state itself)."""
        tr = self._track
        if tr is not None and tr[0] is self.schemes and tr[3] < TRACK_REFRESH:
            _, tt, gt, k = tr
            bound = self.schemes.g_norm() * _absmax(t - tt)
            if bound <= TRACK_TOL * _absmax(gt):
                self._track = (tr[0], tt, gt, k + 1)
                return gt.copy(), bound
        gt = np.asarray(full(t), float)
        self._track = (self.schemes, np.array(t, float), gt.copy(), 0)
        return gt, 0.0

    def rates_singular(self, states, forcing):
        """Rates of a singular scheme that the load does not drive: the minimum-norm solution
        (the force rates are unique where the scheme is statically determinate; a free
        mode's displacement rate is set to zero)."""
        import scipy.linalg as sla

        rel = self.relations(states, article=False)
        A, scale = self.schemes.dense(rel)
        h, e = forcing
        b = scale * scheme_rhs(self.schemes.d, rel, h, e, self.layout.zeros())
        cond = max(1e-10, 100 * np.finfo(A.dtype).eps)
        t = sla.lstsq(A, b.astype(A.dtype), cond=cond, check_finite=False)[0].astype(float)
        w_hat = h - self.schemes.product(t)
        return t + self.schemes.d * w_hat, w_hat + e

    def self_stress(self, states) -> np.ndarray:
        """Self-stress modes of the scheme ``states`` (columns, 2m × k): the force changes
        Δs ≠ 0 with Bᵀ Δs = 0 that its relations leave free — redundant constraints (a rigid
        body stuck on two corners: the split of the tangential force between them is
        indeterminate).  They change no displacement (Δŵ = −G Δt = 0); empty for a regular
        scheme or a mechanism without redundancy."""
        key = states.tobytes()
        hit = self._self_stress.get(key)
        if hit is not None:
            return hit
        import scipy.linalg as sla

        rel = self.relations(states, article=False)
        A, _ = self.schemes.dense(rel)
        A = np.asarray(A, float)
        m2 = self.layout.n
        out = np.zeros((m2, 0))
        if 0 < m2 <= SELF_STRESS_MAX and not self.schemes.shifted:  # (float32 G: large)
            _, sv, Vt = sla.svd(A, check_finite=False)
            tol = max(1e-10, 100 * np.finfo(float).eps) * max(float(sv[0]), 1e-300)
            T = Vt[sv <= tol].T  # null vectors in t = s − D ŵ
            if T.size:
                Gt = self.schemes.product(T)
                # combinations with no displacement, G Δt = 0: the self-stresses (not the
                # free modes of a mechanism)
                gs = float(np.abs(self.schemes.G).max(initial=0.0))
                _, sg, Ct = np.linalg.svd(Gt, full_matrices=True)
                sg = np.r_[sg, np.zeros(Ct.shape[0] - len(sg))]
                keep = Ct[sg <= 1e-9 * max(gs, 1e-300)].T
                if keep.size:
                    Tk = T @ keep
                    dS = Tk - self.schemes.d[:, None] * self.schemes.product(Tk)
                    out = np.linalg.qr(dS)[0]
        self._self_stress[key] = out
        if len(self._self_stress) > 8:
            del self._self_stress[next(iter(self._self_stress))]
        return out

    def rates_redundant(self, states, forcing, *, absolute: bool = False):
        """Rates of a singular scheme that the load does not drive, with the indeterminate
        part of the forces (its self-stresses, :meth:`self_stress`) resolved:

        * along a path (default): the stuck frictional CFEs that share a self-stress reach
          their friction facet together — their margins g_k = f p_k + C ∓ Q_k change at rates
          proportional to themselves, g_k' = κ g_k (one κ for all; the facet ∓ whose common
          root −1/κ comes first), so the group slips as one CFE would, at the instant its
          total friction force reaches Σ (f p_k + C), never one corner first by an arbitrary
          split; margins within the force tolerance are 0 (those CFEs stay on the facet);
        * where no facet is approached (κ ≥ 0 on both, or the whole group on the facet), and
          with ``absolute`` (the rates *are* the forces, the problem in accelerations): the
          split of least Σ Q_k'² / (f p_k + C) (proportional to each CFE's friction
          capacity), the other components least squares.

        Without self-stress: the minimum-norm rates of :meth:`rates_singular`."""
        ds, dw = self.rates_singular(states, forcing)
        Z = self.self_stress(states)
        if Z.shape[1] == 0:
            return ds, dw
        m = self.m
        cap = np.zeros(m)
        grip = np.zeros(m, bool)
        for law, c, _Q, p, _ut, _un in self._parts(self.s if not absolute else ds, self.w):
            cap[c] = law.friction_limit(p, states[c])
            grip[c] = (states[c] == STICK) & law.frictional
        ZQ, Zp = self.layout.split(Z)
        grp = grip & (np.abs(ZQ).reshape(m, -1).max(axis=1, initial=0.0) > 1e-9)
        if not grp.any():
            return ds, dw
        # the split of least Σ Q_k² / (f p_k + C) (Q_k proportional to each CFE's capacity),
        # the other components least squares: least Σ w_j (ds + Z c)_j²
        tf, _ = self.tolerances()
        wgt = np.ones(self.layout.n)
        cref = float(cap[grp].max())
        if cref > tf:  # (without normal force, e.g. a path from zero: equal shares)
            share = cref / np.maximum(cap[grp], 1e-3 * cref)
            wt = self.layout.tangential(wgt)
            wt[grp] = share if self.layout.n_t == 1 else share[:, None]
        c_w = np.linalg.lstsq(Z.T @ (wgt[:, None] * Z), -(Z.T @ (wgt * ds)), rcond=None)[0]
        if absolute or self.layout.n_t > 1:
            # (a faceted cone: the split by capacity; the facets' synchronisation below is
            # written for the two facets of 2D)
            return ds + Z @ c_w, dw
        Q = self.layout.tangential(self.s)
        dQ, dp = self.layout.split(ds)
        f = np.zeros(m)
        for law, c, *_ in self._parts(self.s, self.w):
            f[c] = law.f
        best = (np.inf, c_w)  # no facet approached: the split of the rates by capacity
        for sg in (1.0, -1.0):
            g = (cap - sg * Q)[grp]  # margins of the facet sg (at the facet within tf: 0)
            g = np.where(g > tf, g, 0.0)
            if not g.any():
                continue  # the whole group on this facet: nothing to synchronise
            rhs = -(f * dp - sg * dQ)[grp]
            # (f Zp − sg ZQ) c − κ g = −(f dp − sg dQ) on the group (g in units of its
            # largest: κ of the order of the rates)
            gs = float(g.max())
            Mx = np.c_[(f[:, None] * Zp - sg * ZQ)[grp], -g / gs]
            sol = np.linalg.lstsq(Mx, rhs, rcond=None)[0]
            kappa = float(sol[-1]) / gs
            root = -1.0 / kappa if kappa < 0 else np.inf
            if root < best[0]:
                best = (root, sol[:-1])
        return ds + Z @ best[1], dw

    def rates_any(self, states, forcing, *, absolute: bool = False):
        """Rates of the scheme ``states``: the unique ones, or those of a singular scheme that
        the load does not drive (:meth:`rates_redundant`); raises :class:`MechanismError`
        when the load drives its mechanism."""
        try:
            return self.rates(states, forcing, article=False)
        except MechanismError:
            if self.drives(states, forcing):
                raise
            return self.rates_redundant(states, forcing, absolute=absolute)

    def drives(self, states, forcing) -> bool:
        """Does the load drive the mechanism of the singular scheme ``states``?  True when the
        scheme's equations have no solution for the load rates: the right-hand side is not
        orthogonal to the left null space of the scheme matrix (Fredholm).  A load whose
        rates are at most ``rest_scale`` (the dynamic driver's round-off of the displacements
        over a step: a body at rest after it stopped, ĥ, e ~ 1e-19 m) drives nothing
        (normalised, its round-off would have a direction)."""
        h, e = forcing
        if max(float(np.abs(h).max(initial=0.0)), float(np.abs(e).max(initial=0.0))) <= (
                self.rest_scale):
            return False
        rel = self.relations(states, article=False)
        A, scale = self.schemes.dense(rel)
        b = scale * scheme_rhs(self.schemes.d, rel, h, e, self.layout.zeros())
        # a row of A that is exactly zero has a huge scale: normalise before the norm (its
        # squares would overflow)
        b = b / max(float(np.abs(b).max(initial=0)), 1e-300)
        bn = np.linalg.norm(b)
        if not bn > 0:
            return False
        Y = null_modes(A, lu(A), trans=1, apply=self.schemes.exact_apply(rel, scale, trans=1))
        if np.abs(Y.T @ b).max(initial=0) > 1e-7 * bn:
            return True
        if A.shape[0] > DRIVES_SVD_MAX or self.schemes.shifted:
            return False
        # not driven along the directions inverse iteration found: it finds one direction of
        # a null space of several (the later pivots of a rank-deficient LU are round-off of
        # any size), so a small scheme is checked against its whole left null space (SVD)
        import scipy.linalg as sla

        U, sv, _ = sla.svd(A, check_finite=False)
        tol = max(1e-10, 100 * np.finfo(float).eps) * max(float(sv[0]), 1e-300)
        return bool(np.abs(U[:, sv <= tol].T @ b).max(initial=0) > 1e-7 * bn)

    # ---- event functions ----------------------------------------------------------------------
    def event_values(self, states, s, w, affine: bool = True) -> list[np.ndarray]:
        """φ of every law's CFEs in ``states`` (one (k, n_columns) array per law, in the order
        of ``laws``; ``+inf`` where a function does not apply): the event functions of eqs.
        (2), (3), (12).  With ``affine=False`` and rates (s', w'): their rates."""
        return [law.event_values(states[c], Q, p, un, affine)
                for law, c, Q, p, _ut, un in self._parts(s, w)]

    def _column_scales(self, law, force: float, gap: float) -> np.ndarray:
        """Per column of ``law``: ``force`` for a force column, ``gap`` for a gap column."""
        return np.where(law.column_kinds == 1, gap, force)

    def tolerance_columns(self, law) -> np.ndarray:
        """Absolute tolerance of each event-function column of ``law`` (forces, gaps)."""
        tf, tw = self.tolerances()
        return self._column_scales(law, tf, tw)

    def next_event(self, ds, dw, remaining: float, group: float) -> tuple[float, float, np.ndarray]:
        """Earliest root of all event functions along the rates (ds, dw): the event load
        factors of eqs. (2), (3) (and of a bond's facets, eq. (12)); along the μ ∈ [0, 1] of a
        time step, the event times of eq. (10), t̂ = t + μ̂ Δt.

        Returns (Δμ, Δμ of the earliest event (inf if none), fired mask (m,)): CFEs whose
        functions reach zero within ``group`` of the earliest root form one event point.

        A function fires along the rates when it is finite (it applies in the current state)
        and its rate is below −1e3 rtol of the rates' scale (forces or gaps): the step to its
        root is max(φ, 0) / (−φ')."""
        lay = self.layout
        Q, p, un = self._state_views()
        dQ, dp = lay.split(ds)
        dun = lay.normal(dw)
        a, b = self._rate_scales(ds, dw)
        fs = 1e3 * self.rtol * max(a, 1e-300)
        gs = 1e3 * self.rtol * max(b, 1e-300)
        states = self.states
        all_steps = []
        dmu_ev = _INF
        for law, c, gap in self._views_now():
            if type(c) is slice:
                st, a, b, g, da, db, dg = states, Q, p, un, dQ, dp, dun
            else:
                st, a, b, g, da, db, dg = states[c], Q[c], p[c], un[c], dQ[c], dp[c], dun[c]
            phi = law.event_values(st, a, b, g)
            dphi = law.event_values(st, da, db, dg, False)
            active = np.isfinite(phi)
            active &= dphi < np.where(gap, -gs, -fs)
            steps = np.full(phi.shape, _INF)
            np.divide(np.maximum(phi, 0.0), np.negative(dphi), out=steps, where=active)
            all_steps.append((c, steps))
            if steps.size:
                dmu_ev = min(dmu_ev, float(steps.min()))
        dmu = min(dmu_ev, remaining)
        fired = np.zeros(self.m, bool)
        if dmu_ev <= dmu + group:
            for c, steps in all_steps:
                fired[c] = (steps <= dmu + group).any(axis=1)
        return dmu, dmu_ev, fired

    def next_event_poly(self, dss, dws, remaining: float, group: float
                        ) -> tuple[float, float, np.ndarray]:
        """Earliest root of all event functions along a polynomial path (a load that is a
        polynomial in the segment's parameter, e.g. water loads with the level as parameter):
        s(μ) = s + Σ_j μ^j ds_j, w(μ) = w + Σ_j μ^j dw_j (j = 1 … J, Taylor coefficients of the
        current scheme's response at the current point).

        The event functions are affine in (s, w), so each is a polynomial in μ; its smallest
        positive real root is found from the eigenvalues of its companion matrix and polished
        by Newton steps (exact, not a linearised path).  One coefficient (J = 1) is
        :meth:`next_event` itself.  Returns as :meth:`next_event`."""
        if len(dss) == 1:
            return self.next_event(dss[0], dws[0], remaining, group)
        phis = self.event_values(self.states, self.s, self.w)
        coefs = [self.event_values(self.states, ds, dw, affine=False)
                 for ds, dw in zip(dss, dws, strict=True)]
        scale_s = max((np.abs(ds).max(initial=0) for ds in dss), default=0.0)
        scale_w = max((np.abs(dw).max(initial=0) for dw in dws), default=0.0)
        R = max(remaining, 1e-300)
        all_steps = []
        for i, (law, phi) in enumerate(zip(self.laws, phis, strict=True)):
            rate_tol = 1e3 * self.rtol * self._column_scales(law, max(scale_s, 1e-300),
                                                             max(scale_w, 1e-300))
            fin = np.isfinite(phi)
            coef = np.stack([np.where(fin, c[i], 0.0) for c in coefs], axis=-1)  # (k, ncol, J)
            all_steps.append(_poly_steps(phi, coef, rate_tol, R))
        dmu_ev = min((float(st.min(initial=_INF)) for st in all_steps), default=_INF)
        dmu = min(dmu_ev, remaining)
        fired = np.zeros(self.m, bool)
        if dmu_ev <= dmu + group:
            for law, st in zip(self.laws, all_steps, strict=True):
                fired[law.cfes] = np.any(st <= dmu + group, axis=1)
        return dmu, dmu_ev, fired

    def advance_poly(self, dmu: float, dss, dws) -> None:
        """Move along a polynomial path (see :meth:`next_event_poly`) by Δμ."""
        for j, (ds, dw) in enumerate(zip(dss, dws, strict=True), start=1):
            self.s += dmu**j * ds
            self.w += dmu**j * dw
            if np.any(ds) or np.any(dw):
                self._follow(ds, dw, dmu**j)

    def article_step(self, ds) -> float:
        """Step limit of the article's slip treatment, eq. (5): |ΔQ_p / Q_p| ≤ ε_p (each law's
        :meth:`~stepcontact.contact.laws.CoulombLaw.article_step`)."""
        dp = self.layout.normal(ds)
        return min((law.article_step(self.states[c], p, dp[c], self.eps_p)
                    for law, c, _Q, p, _ut, _un in self._parts(self.s, self.w)), default=_INF)

    def advance(self, dmu: float, ds, dw) -> None:
        self.s += dmu * ds
        self.w += dmu * dw
        self._follow(ds, dw, dmu)

    # ---- the decision at a point ------------------------------------------------------------
    def at_limit(self, fired: np.ndarray):
        """CFEs at their limits (or that fired), the guess (natural transitions of the CFEs
        whose functions fired) and the limits (normal, two-sided) of every CFE."""
        self.update_scales()
        tf, tw = self.tolerances()
        states = self.states
        views = self._views_now()
        if len(views) == 1 and type(views[0][1]) is slice:  # one law over every CFE
            law, _, gap = views[0]
            Q, p, un = self._state_views()
            at, col = self._limit_columns(law, gap, law.event_values(states, Q, p, un), fired,
                                          tf, tw)
            guess = law.fire(states, col, Q)
            normal, two = law.limits(states, Q, p, un, tf, tw)
            slip = law.slip_mask(states) if hasattr(law, "slip_mask") else slipping(states)
            return (at | slip).nonzero()[0], guess, normal, two
        at = fired.copy()
        col = np.full(self.m, -1)
        guess = states.copy()
        normal = np.zeros(self.m, bool)
        two = np.zeros(self.m, bool)
        for (law, c, Q, p, _ut, un), (_, _, gap) in zip(self._parts(self.s, self.w), views,
                                                        strict=True):
            st = states[c]
            at[c], col[c] = self._limit_columns(law, gap, law.event_values(st, Q, p, un),
                                                at[c], tf, tw)
            guess[c] = law.fire(st, col[c], Q)
            normal[c], two[c] = law.limits(st, Q, p, un, tf, tw)
        L = np.flatnonzero(at | slipping(states))
        return L, guess, normal, two

    @staticmethod
    def _limit_columns(law, gap, phi, fired, tf: float, tw: float):
        """The CFEs of ``law`` at a limit (a function within its tolerance, or ``fired``) and,
        for those, the column nearest its limit relative to the tolerance (−1 elsewhere)."""
        tol = np.where(gap, tw, tf)
        at = fired | _ANY(phi <= tol, axis=1)
        if not np.count_nonzero(at):
            return at, np.full(len(at), -1)
        # (φ / tol: +inf stays +inf where a function does not apply, the tolerances are > 0)
        return at, np.where(at, np.divide(phi, tol).argmin(axis=1), -1)

    def consistent(self, trial, L, ds, dw, normal, two) -> np.ndarray:
        """States the rates (ds, dw) of scheme ``trial`` point to, for the CFEs in L."""
        lay = self.layout
        dQ, dp = lay.split(ds)
        dut, dun = lay.split(dw)
        a, b = self._rate_scales(ds, dw)
        rf = 1e3 * self.rtol * max(a, 1e-300)
        rw = 1e3 * self.rtol * max(b, 1e-300)
        tf, _ = self.tolerances()
        views = self._views_now()
        if len(views) == 1 and type(views[0][1]) is slice:  # one law over every CFE
            Q, p, _ = self._state_views()
            return views[0][0].consistent(trial, Q, dQ, dp, dun, dut, normal, two, rf, rw,
                                          p=p, tf=tf)[L]
        out = trial.copy()
        for law, c, Q, p, _ut, _un in self._parts(self.s, self.w):
            out[c] = law.consistent(trial[c], Q, dQ[c], dp[c], dun[c], dut[c], normal[c],
                                    two[c], rf, rw, p=p, tf=tf)
        return out[L]

    def decide(self, fired: np.ndarray, forcing, *, natural: bool = False) -> Decision:
        """The next scheme at the current point and its rates.

        ``natural``: apply the natural transitions of every CFE at a limit (the start of a
        path).  Raises :class:`MechanismError` (equilibrium lost, with evidence) or
        :class:`~stepcontact.solver.rate.RateProblemFailure`."""
        L, guess, normal, two = self.at_limit(fired)
        if not (np.count_nonzero(fired) or natural):
            guess = self.states.copy()
        old = self.states.copy()
        if L.size:
            out = solve_rate_problem(self, L, guess, forcing, normal, two, self.rate_solver)
            new, ds, dw = out.states, out.ds, out.dw
        else:
            out = None
            new = guess
            # a singular scheme that the load does not drive (redundant constraints: the
            # indeterminate forces resolved, :meth:`rates_redundant`); a driven one raises
            ds, dw = self.rates_any(new, forcing)
        self.states = new
        return Decision(old, new, ds, dw, out)

    def snap(self) -> None:
        """Move the state onto the relations of the current scheme at the fixed point (in the
        article's slip treatment: the corrected tangential forces of eq. (4), applied as the
        compensating forces of eq. (6))."""
        lay = self.layout
        views = self._views_now()
        if len(views) == 1 and type(views[0][1]) is slice:  # one law over every CFE
            Q, p, un = self._state_views()
            r = lay.join(*views[0][0].snap(self.states, Q, p, un))
        else:
            r = lay.zeros()
            rQ, rp = lay.split(r)
            for law, c, Q, p, _ut, un in self._parts(self.s, self.w):
                rQ[c], rp[c] = law.snap(self.states[c], Q, p, un)
        if not np.count_nonzero(np.abs(r) > 0):
            return
        if self._snap_roundoff(r):
            self.counters["corrections"] += 1
            return
        try:
            fact = self.factor(self.states)
        except MechanismError:
            return  # a singular scheme with consistent rates: nothing to snap onto uniquely
        try:
            ds, dw = fact.solve(lay.zeros(), lay.zeros(), r,
                                floor=float(np.abs(self.s).max(initial=0.0)))
        except MechanismError:
            return
        self._note(ds, dw)
        self.s += ds
        self.w += dw
        self._follow(ds, dw, 1.0)
        self.counters["corrections"] += 1

    def _snap_roundoff(self, r: np.ndarray) -> bool:
        """Snap a state that is off the relations by round-off only, in O(m): every row's
        right-hand side r_j at most ``SNAP_ROUNDOFF`` of the path's scale in that row's units
        (F_scale for a row with a force of its own, S_jj ≠ 0; W_scale for a displacement row,
        S_jj = 0).  Each CFE's block of relations is then satisfied exactly by changing, in
        each of its rows, the row's own unknown (s_j where S_jj ≠ 0, else w_j): per CFE the
        small system Σ_c M_ic x_c = r_i, M_ic the coefficient of component c's chosen unknown
        in row i.  Equilibrium moves by that round-off (ŵ and t change by O(ε) of their
        scales), as it does along any step, instead of a solve of the whole scheme (a pass
        over the factor and one over G) that would only move round-off.  False (nothing
        done) when a row is beyond round-off — a CFE snapped onto a limit it reached within
        the path's tolerance, the article's corrections of eq. (4) — or a block is singular:
        then the scheme's solve (:meth:`snap`)."""
        lay = self.layout
        m, nc = lay.m, lay.n_c
        rel = self.relations(self.states)
        S, Wr = rel.S, rel.W
        own = S.diagonal(axis1=1, axis2=2) != 0  # (m, nc): the row's chosen unknown is its force
        F, W = max(self.F_scale, 1e-300), max(self.W_scale, 1e-300)
        if nc == 2:  # (in the layout's row order (component, CFE): no transposes)
            own_r, r_r = own.T, r.reshape(nc, m)
            if np.count_nonzero(np.abs(r_r) > SNAP_ROUNDOFF * np.where(own_r, F, W)):
                return False
            M = np.where(own[:, None, :], S, Wr)  # M[k, i, c]
            a, b, c, d = M[:, 0, 0], M[:, 0, 1], M[:, 1, 0], M[:, 1, 1]
            det = a * d - b * c
            size = _MAXIMUM(np.abs(M).reshape(m, 4), axis=1)
            if np.count_nonzero(~(np.abs(det) > 1e-12 * size * size)):
                return False
            x = np.empty((2, m))
            np.divide(d * r_r[0] - b * r_r[1], det, out=x[0])
            np.divide(a * r_r[1] - c * r_r[0], det, out=x[1])
            self.s += np.where(own_r, x, 0.0).ravel()
            self.w += np.where(own_r, 0.0, x).ravel()
            return True
        rk = r.reshape(nc, m).T
        if np.any(np.abs(rk) > SNAP_ROUNDOFF * np.where(own, F, W)):
            return False
        M = np.where(own[:, None, :], S, Wr)  # M[k, i, c]
        try:
            x = np.linalg.solve(M, rk[:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:
            return False
        if not np.all(np.isfinite(x)):
            return False
        self.s += np.where(own, x, 0.0).T.ravel()
        self.w += np.where(own, 0.0, x).T.ravel()
        return True

    def violation(self) -> float:
        """Largest relative violation of every law's conditions at the current state."""
        F, W = max(self.F_scale, 1e-300), max(self.W_scale, 1e-300)
        views = self._views_now()
        if len(views) == 1 and type(views[0][1]) is slice:  # one law over every CFE
            Q, p, un = self._state_views()
            return views[0][0].violation(self.states, Q, p, un, F, W)
        return max((law.violation(self.states[c], Q, p, un, F, W)
                    for law, c, Q, p, _ut, un in self._parts(self.s, self.w)), default=0.0)


def _absmax(x) -> float:
    """max |x| over every entry (0 for an empty x), as ``float(np.abs(x).max(initial=0))``
    without its Python-level wrapper (called several times per event)."""
    return float(_MAXIMUM(np.abs(x), axis=None, initial=0.0))


_MAXIMUM = np.maximum.reduce
_ANY = np.logical_or.reduce


def _poly_steps(phi: np.ndarray, coef: np.ndarray, rate_tol: np.ndarray, R: float) -> np.ndarray:
    """The smallest positive root μ of each event function φ + Σ_j coef_j μ^j (``phi`` (k,
    ncol), ``coef`` (k, ncol, J)) within reach of a step of length R (inf: none): eigenvalues
    of the companion matrix polished by Newton steps; coefficients below ``rate_tol`` (per
    column) over the whole step are round-off."""
    fin = np.isfinite(phi)
    J = coef.shape[-1]
    powers = R ** np.arange(1, J + 1)
    coef = np.where(np.abs(coef) * powers[None, None, :] < rate_tol[None, :, None] * R,
                    0.0, coef)
    p0 = np.where(fin, np.maximum(phi, 0.0), 0.0)
    reach = np.abs(coef) @ powers
    cand = np.argwhere(fin & (reach >= p0) & np.any(coef != 0, axis=-1))
    steps = np.full(phi.shape, _INF)
    tiny = 1e-14 * max(R, 1.0)
    P = np.polynomial.polynomial
    for k, c in cand:
        cs = coef[k, c]
        if p0[k, c] == 0.0:
            lead = cs[np.flatnonzero(cs)[0]]
            if lead < 0:  # at its limit and moving past it: an event here
                steps[k, c] = 0.0
                continue
        poly = np.r_[p0[k, c], cs]
        roots = P.polyroots(np.trim_zeros(poly, "b"))
        real = roots.real[np.abs(roots.imag) <= 1e-7 * np.maximum(np.abs(roots.real), tiny)]
        real = np.sort(real[real > tiny])
        for r in real:
            for _ in range(3):  # Newton polish on the exact polynomial
                val = P.polyval(r, poly)
                der = P.polyval(r, P.polyder(poly))
                if der == 0:
                    break
                r = r - val / der
            if r > tiny:
                steps[k, c] = r
                break
    return steps


__all__ = ["LIMIT_TOL", "SELF_STRESS_MAX", "Decision", "EventEngine", "norm2", "null_modes"]
