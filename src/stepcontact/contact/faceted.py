"""Coulomb friction on a faceted cone: the 3D contact law with exact events.

In 3D the Coulomb condition of a CFE, |Q| ≤ f p (Q the tangential force, a vector of the tangent
plane; p = −N ≥ 0 the compression, N), is a disc of radius f p, not a polyhedron, so its boundary
is not reached at a root of an affine function.  The disc is replaced by the regular polygon of
k facets inscribed in it (vertices on the circle): each facet i is a linear event function

    g_i = f cos(π/k) p − d_i · Q ≥ 0            (the stick → slip functions of eq. (2))

with d_i the facet's outward normal, at the angle θ₀ + (2i + 1) π/k from the CFE's first
tangent t₁ towards t₂ (θ₀ the direction of vertex 0), so that every event stays exact.  The
limit force of the polygon in a direction θ is f p cos(π/k) / cos(θ − θ_f) (θ_f the nearest
facet normal): f p at a vertex, f p cos(π/k) at a facet's middle, an error of at most
1 − cos(π/k) against the cone (:attr:`FacetedCoulombLaw.limit_error`).  In 2D the two
"facets" ±Q ≤ f p are the slip+/slip− of :class:`~stepcontact.contact.laws.CoulombLaw`.

States (codes of :mod:`stepcontact.enums`): OPEN (N = Q = 0), STICK (no slip, Q inside the
polygon), CLOSED (f = 0: Q = 0), slip on facet i (``FACET_SLIP + i``: Q on the facet, the slip
along d_i) and slip at vertex i (``VERTEX_SLIP + i``, between facets i − 1 and i: Q at the
vertex, the slip direction inside the vertex's normal cone, a d_{i−1} + b d_i, a, b ≥ 0).

Relations of a slipping CFE (per-CFE blocks over the components t₁, t₂, n; eqs. (1), (11)):

    facet i:   d_i · Q' − f cos(π/k) p' = 0           (Q stays on the facet)
               e_i · u_τ' = 0 (rigid), e_i · (Q' − C_τ u_τ') = 0 (layer)   e_i ⟂ d_i
    vertex i:  the facet rows of facets i − 1 and i

and the normal row as in stick (u_n' = 0, or p' − C_n u_n' = 0 with a compliant layer).

Orientation: θ₀ per CFE (``angle``), every other CFE turned by π/k (``stagger``), or
``adaptive``: at a CFE's first slip its polygon is turned so that a vertex lies on its
tangential force (the direction a cone would slip in), once, at that event point (never inside a
step); the CFE is then inside the new polygon and slips when Q reaches it.
"""

from __future__ import annotations

import numpy as np

from stepcontact.contact.laws import OPENING, SLIP_PLUS, RateVariables, Relations
from stepcontact.enums import (
    FACET_SLIP,
    MAX_FACETS,
    VERTEX_SLIP,
    ContactState,
)
from stepcontact.enums import slipping as _slipping
from stepcontact.errors import ModelError

OPEN, STICK, CLOSED = (int(s) for s in (ContactState.OPEN, ContactState.STICK,
                                        ContactState.CLOSED))
_INF = np.inf


class FacetedCoulombLaw:
    """Unilateral contact with Coulomb friction on a faceted cone (module docstring), rigid or
    with a compliant layer (eqs. (1), (11)), for CFEs with two tangential components.

    Parameters
    ----------
    cfes : (K,) int
        Global indices of the CFEs governed by this law.
    friction, kn, kt : (K,) float
        f, C_n, C_τ (N/m; ``inf`` for rigid contact).
    facets : int
        k, the number of facets (3 ≤ k ≤ :data:`~stepcontact.enums.MAX_FACETS`; default 8).
    angle : float or (K,) float
        θ₀, the direction of vertex 0 from t₁ towards t₂, rad.
    stagger : bool
        Turn every other CFE's polygon by π/k (neighbouring CFEs then err in different
        directions).
    adaptive : bool
        Turn a CFE's polygon at its first slip so that a vertex lies on its tangential force.
    held_normal, held_tangent : (K,) bool, optional
        As for :class:`~stepcontact.contact.laws.CoulombLaw`.

    Event functions (columns): 0 the compression p (closed → open, eq. (3)); 1 … k the facets'
    margins g_i (stick → slip, eq. (2); for a CFE slipping on a facet, the other facets: its
    force reaching a vertex); k + 1 the gap −u_n (open → closed, eq. (3)).
    """

    def __init__(self, cfes, friction, kn, kt, *, facets: int = 8, angle=0.0,
                 stagger: bool = False, adaptive: bool = False, held_normal=None,
                 held_tangent=None):
        self.cfes = np.asarray(cfes, dtype=np.int64)
        K = len(self.cfes)
        if int(facets) != facets or not 3 <= facets <= MAX_FACETS:
            raise ModelError("facets", f"the number of facets of the friction cone must be an "
                             f"integer 3 … {MAX_FACETS}, got {facets}")
        self.k = int(facets)
        self.inert = np.zeros(K, bool) if held_normal is None else np.asarray(held_normal, bool)
        ht = np.zeros(K, bool) if held_tangent is None else np.asarray(held_tangent, bool)
        self.f = np.where(ht | self.inert, 0.0, np.broadcast_to(
            np.asarray(friction, dtype=float), (K,)))
        self.kn = np.broadcast_to(np.asarray(kn, dtype=float), (K,)).copy()
        self.kt = np.broadcast_to(np.asarray(kt, dtype=float), (K,)).copy()
        self.rigid_n = ~np.isfinite(self.kn)
        self.rigid_t = ~np.isfinite(self.kt)
        #: f cos(π/k): the facets' distance from the centre per unit compression
        self.mu = self.f * np.cos(np.pi / self.k)
        self.offset = np.zeros(K)
        self.surface = np.zeros(K)
        theta = np.broadcast_to(np.asarray(angle, dtype=float), (K,)).copy()
        if stagger:
            theta[1::2] += np.pi / self.k
        self.adaptive = bool(adaptive)
        #: (K,) bool: the CFE's polygon was turned at its first slip (``adaptive``)
        self.oriented = np.zeros(K, bool)
        self.has_bond = np.zeros(K, bool)
        #: no bonds and no residual cohesion on a faceted cone (yet): what drivers read
        self.residual = np.zeros(K)
        self.cohesion_lost = np.zeros(K, bool)
        self.n_columns = self.k + 2
        self.column_kinds = np.r_[np.zeros(self.k + 1, int), 1]
        self.column_names = ("p", *(f"facet {i}" for i in range(self.k)), "gap")
        self.orient(np.arange(K), theta)

    # ---- geometry of the polygon ------------------------------------------------------------
    def orient(self, local, theta) -> None:
        """Set θ₀ (rad) of the CFEs ``local`` (indices into this law's CFEs): their facet
        normals d_i at θ₀ + (2i + 1) π/k."""
        if not hasattr(self, "theta"):
            self.theta = np.zeros(len(self.cfes))
            self.D = np.zeros((len(self.cfes), self.k, 2))
        self.theta[local] = theta
        phi = self.theta[local, None] + (2 * np.arange(self.k) + 1) * np.pi / self.k
        self.D[local] = np.stack([np.cos(phi), np.sin(phi)], axis=-1)

    def facet_normals(self) -> tuple[np.ndarray, float]:
        """The facets' outward normals d (K, k, 2) and their distance factor c = cos(π/k): the
        polygon is d_i · Q ≤ c f p (the directions a bond's strength surface is written in,
        :class:`~stepcontact.contact.bond.BondedJointLaw`)."""
        return self.D, float(np.cos(np.pi / self.k))

    def vertices(self, p) -> np.ndarray:
        """The polygon's vertices (K, k, 2) at compression p (K,): vertex i at f p on the
        direction θ₀ + 2πi/k."""
        phi = self.theta[:, None] + 2 * np.arange(self.k) * np.pi / self.k
        return (self.f * p)[:, None, None] * np.stack([np.cos(phi), np.sin(phi)], axis=-1)

    def _nearest(self, Q, p) -> tuple[np.ndarray, np.ndarray]:
        """The point of each CFE's polygon nearest to Q (K, 2) and the slip state it lies on
        (``FACET_SLIP + i`` on facet i, ``VERTEX_SLIP + i`` at vertex i; STICK where Q is
        inside: the point is Q itself)."""
        K = len(self.cfes)
        g = self.margins(Q, p)
        tol = 1e-12 * np.maximum(np.abs(self.f * p), np.linalg.norm(Q, axis=-1))
        out = g.min(axis=1, initial=_INF) < -tol
        x = np.array(Q, dtype=float, copy=True).reshape(K, 2)
        state = np.full(K, STICK, dtype=np.int64)
        if not out.any():
            return x, state
        # the foot of Q on each facet's line, and whether it lies on the facet
        foot = Q[:, None, :] + g[:, :, None] * self.D  # (K, k, 2): Q − (d·Q − c f p) d
        gf = self.mu[:, None, None] * p[:, None, None] - np.einsum("kij,klj->kli", self.D,
                                                                   foot)
        on = (g < -tol[:, None]) & (gf.min(axis=2) >= -tol[:, None])
        face = out & on.any(axis=1)
        i = np.argmax(np.where(on, -g, -_INF), axis=1)
        x[face] = foot[face, i[face]]
        state[face] = FACET_SLIP + i[face]
        vert = out & ~face
        if vert.any():
            V = self.vertices(p)
            j = np.argmin(np.linalg.norm(V - Q[:, None, :], axis=-1), axis=1)
            x[vert] = V[vert, j[vert]]
            state[vert] = VERTEX_SLIP + j[vert]
        return x, state

    def state_at(self, Q, p, tf: float = 0.0) -> np.ndarray:
        """The state a CFE takes at forces (Q (K, 2), p) (a bond's break, eq. (12)): open where
        it is in tension (p ≤ tf), closed where frictionless, stuck where Q is inside the
        polygon, else slipping on the facet or at the vertex nearest to Q."""
        Q = np.asarray(Q, dtype=float).reshape(len(self.cfes), 2)
        st = np.where(self.frictional, self._nearest(Q, np.maximum(p, 0.0))[1], CLOSED)
        return np.where(p <= tf, OPEN, st)

    def released(self, states, Q, p) -> tuple[np.ndarray, np.ndarray]:
        """The part (ΔQ (K, 2), Δp) of the forces (Q, p) that ``states`` cannot carry (open:
        all of it; frictionless: Q; slipping: Q less its nearest point on the polygon): what
        a broken bond (eq. (12)) releases."""
        Q = np.asarray(Q, dtype=float).reshape(len(self.cfes), 2)
        op = states == OPEN
        dQ = np.zeros_like(Q)
        sl = self.slipping(states) & ~op
        if sl.any():
            x, _ = self._nearest(Q, np.maximum(p, 0.0))
            dQ[sl] = Q[sl] - x[sl]
        dQ[op | (states == CLOSED)] = Q[op | (states == CLOSED)]
        return dQ, np.where(op, p, 0.0)

    @property
    def limit_error(self) -> float:
        """1 − cos(π/k): the largest relative error of the polygon's limit against the cone."""
        return 1.0 - float(np.cos(np.pi / self.k))

    @property
    def frictional(self) -> np.ndarray:
        return self.f > 0

    @property
    def cohesion(self) -> np.ndarray:
        return np.zeros(len(self.cfes))

    def friction_limit(self, p, states=None) -> np.ndarray:
        """f p (N): the cone's limit (the polygon's vertices)."""
        return self.f * p

    def true_cone_ratio(self, Q, p) -> np.ndarray:
        """|Q| / (f p) per CFE (NaN where f p = 0): how far the force is along the cone."""
        fp = self.f * p
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(fp > 0, np.linalg.norm(Q, axis=-1) / np.where(fp > 0, fp, 1.0),
                            np.nan)

    def margins(self, Q, p, affine: bool = True) -> np.ndarray:
        """g (K, k): f cos(π/k) p − d_i · Q of every facet (rates with ``affine=False``: the
        same form, linear)."""
        return self.mu[:, None] * p[:, None] - np.einsum("kij,kj->ki", self.D, Q)

    def _facets(self, states) -> tuple[np.ndarray, np.ndarray]:
        """The facets (a, b) a slip state holds Q on: (i, i) for facet i, (i − 1, i) for
        vertex i; (−1, −1) for the other states."""
        st = np.asarray(states)
        fa = np.where(st >= VERTEX_SLIP, (st - VERTEX_SLIP - 1) % self.k,
                      np.where(st >= FACET_SLIP, st - FACET_SLIP, -1))
        fb = np.where(st >= VERTEX_SLIP, st - VERTEX_SLIP,
                      np.where(st >= FACET_SLIP, st - FACET_SLIP, -1))
        return fa, fb

    def slip_directions(self, states, local=None) -> np.ndarray:
        """(K, 2) unit vectors in the tangent plane (t₁, t₂): the slip direction of each
        slipping CFE's state — d_i on facet i, the bisector of d_{i−1} and d_i at vertex i —
        and zero for the other states (the dynamic driver's slip rates and stops along it).
        ``local``: the CFEs (indices into this law's) that ``states`` are of (default all)."""
        fa, fb = self._facets(states)
        r = np.arange(len(fa)) if local is None else np.asarray(local, dtype=np.int64)
        d = np.where((fa >= 0)[:, None], self.D[r, np.maximum(fa, 0)]
                     + self.D[r, np.maximum(fb, 0)], 0.0)
        n = np.linalg.norm(d, axis=-1)
        return d / np.where(n > 0, n, 1.0)[:, None]

    def vanishing_rate(self, local, old, new, v) -> np.ndarray:
        """The slip rate (k,) of the CFEs ``local`` with slip velocity ``v`` (k, 2) that
        vanishes where their state ``old`` turns into ``new`` (a stop in time, eq. (10)): at
        vertex i (facets a = i − 1, b = i) onto facet b, the rate λ_a of v = λ_a d_a + λ_b d_b
        (onto facet a: λ_b); otherwise (a stop) v along the slip direction of ``old``."""
        local = np.asarray(local, dtype=np.int64)
        old, new = np.asarray(old), np.asarray(new)
        v = np.asarray(v, dtype=float)
        fa, fb = self._facets(old)
        Da, Db = self.D[local, np.maximum(fa, 0)], self.D[local, np.maximum(fb, 0)]
        det = Da[:, 0] * Db[:, 1] - Da[:, 1] * Db[:, 0]
        vertex = (old >= VERTEX_SLIP) & (det != 0)
        det = np.where(vertex, det, 1.0)
        la = (v[:, 0] * Db[:, 1] - v[:, 1] * Db[:, 0]) / det
        lb = (Da[:, 0] * v[:, 1] - Da[:, 1] * v[:, 0]) / det
        along = np.einsum("kj,kj->k", v, self.slip_directions(old, local))
        return np.where(vertex & (new == FACET_SLIP + fb), la,
                        np.where(vertex & (new == FACET_SLIP + fa), lb, along))

    def slip_state_towards(self, local, direction) -> np.ndarray:
        """The slip states of the CFEs ``local`` (indices into this law's CFEs) that slip in
        ``direction`` (len(local), 2), by the polygon's normality rule: on facet i where the
        direction is its normal d_i (to 1e-9 rad), else at the vertex whose normal cone (between
        d_{i−1} and d_i) holds it (a slip after an impact, along its velocity)."""
        local = np.asarray(local, dtype=np.int64)
        d = np.asarray(direction, dtype=float).reshape(len(local), 2)
        a = (np.arctan2(d[:, 1], d[:, 0]) - self.theta[local]) * self.k / (2 * np.pi)
        vertex = np.rint(a).astype(np.int64)
        half = np.floor(a).astype(np.int64)  # facet i lies at i + 1/2
        on_facet = np.abs(a - half - 0.5) * 2 * np.pi / self.k <= 1e-9
        return np.where(on_facet, FACET_SLIP + half % self.k, VERTEX_SLIP + vertex % self.k)

    # ---- states -----------------------------------------------------------------------------
    def closed_state(self) -> np.ndarray:
        return np.where(self.frictional, STICK, CLOSED)

    def base_state(self, states: np.ndarray) -> np.ndarray:
        return self.closed_state()

    def initial_states(self, states: np.ndarray) -> np.ndarray:
        return states

    @staticmethod
    def slipping(states: np.ndarray) -> np.ndarray:
        return _slipping(states)

    def state_options(self, j: int, normal_lim: bool, state: int, hint=None) -> list[int]:
        """The states CFE j (local) may take where every scheme is tried: open (from its normal
        limit), closed, and where it is frictional the slip states — with ``hint`` (its
        tangential force rate in a stuck scheme, (2,)) the facet nearest that direction and
        its two vertices (a slip follows the force; nothing else is tried), without it the
        state it slips in now, if any, else every facet and vertex."""
        opts = ([OPEN] if normal_lim or state == OPEN else []) + [int(self.closed_state()[j])]
        if not self.frictional[j]:
            return opts
        if hint is not None and np.linalg.norm(hint) > 0:
            i = int(np.argmax(self.D[j] @ np.asarray(hint, float)))
            return opts + [FACET_SLIP + i, VERTEX_SLIP + i, VERTEX_SLIP + (i + 1) % self.k]
        if state >= FACET_SLIP:
            return opts + [int(state)]
        return (opts + [FACET_SLIP + i for i in range(self.k)]
                + [VERTEX_SLIP + i for i in range(self.k)])

    # ---- relations (eqs. (1), (11)) ---------------------------------------------------------
    def relations(self, states: np.ndarray, rel: Relations, m, article: bool = False) -> None:
        """Write the blocks of this law's CFEs in ``states`` into ``rel`` (module docstring):
        open: Q = p = 0 rates free (s' = r); stick: u_τ' = 0 (or Q' − C_τ u_τ' = 0) and
        u_n' = 0 (or p' − C_n u_n' = 0); closed frictionless: Q' = r; slip: the facet rows."""
        if article:
            raise ModelError("slip_treatment", "the article's slip treatment (eqs. (4)–(6)) is "
                             "written for 2D; a faceted cone needs the exact one")
        c = self.cfes
        S = np.zeros((len(c), 3, 3))
        W = np.zeros((len(c), 3, 3))
        eye = np.eye(3)
        closed = (states != OPEN) & ~self.inert
        sl = self.slipping(states) & closed
        stick = closed & ~sl & (states != CLOSED) & self.frictional
        # open (and inert): every row s' = r
        S[:] = eye
        # the normal row of a closed CFE
        rn = closed & self.rigid_n
        S[rn, 2, :] = 0.0
        W[rn, 2, 2] = 1.0
        sn = closed & ~self.rigid_n
        W[sn, 2, 2] = -self.kn[sn]
        # stuck: both tangential rows kinematic
        for i in (0, 1):
            rt = stick & self.rigid_t
            S[rt, i, :] = 0.0
            W[rt, i, i] = 1.0
            st_ = stick & ~self.rigid_t
            W[st_, i, i] = -self.kt[st_]
        # slipping: row 0 facet a, row 1 the second facet (vertex) or the along-facet row
        fa, fb = self._facets(states)
        idx = np.flatnonzero(sl)
        if idx.size:
            Da = self.D[idx, fa[idx]]
            Db = self.D[idx, fb[idx]]
            S[idx, 0, :2] = Da
            S[idx, 0, 2] = -self.mu[idx]
            vertex = states[idx] >= VERTEX_SLIP
            S[idx, 1, :] = 0.0
            S[idx[vertex], 1, :2] = Db[vertex]
            S[idx[vertex], 1, 2] = -self.mu[idx[vertex]]
            e = np.stack([-Da[:, 1], Da[:, 0]], axis=-1)  # along the facet
            face = idx[~vertex]
            ef = e[~vertex]
            rig = self.rigid_t[face]
            W[face[rig], 1, :2] = ef[rig]
            S[face[~rig], 1, :2] = ef[~rig]
            W[face[~rig], 1, :2] = -self.kt[face[~rig], None] * ef[~rig]
        rel.S[c] = S
        rel.W[c] = W

    # ---- event functions (eqs. (2), (3)) ----------------------------------------------------
    def event_values(self, states, Q, p, un, affine: bool = True) -> np.ndarray:
        """φ (K, k + 2): the facets of eq. (2) and the opening and closing of eq. (3) (class
        docstring; ``+inf`` where a function does not apply); rates with ``affine=False`` for
        rates (Q', p', u_n')."""
        K = len(states)
        out = np.full((K, self.n_columns), _INF)
        closed = (states != OPEN) & ~self.inert
        out[closed, 0] = p[closed]
        g = self.margins(Q, p)
        stick = closed & (states == STICK) & self.frictional
        out[stick, 1:self.k + 1] = g[stick]
        fa, fb = self._facets(states)
        face = closed & (states >= FACET_SLIP) & (states < VERTEX_SLIP)
        if face.any():
            gf = g[face]
            gf[np.arange(gf.shape[0]), fa[face]] = _INF  # its own facet holds (the relation)
            out[face, 1:self.k + 1] = gf
        op = (states == OPEN) & ~self.inert
        out[op, -1] = (self.surface[op] if affine else 0.0) - un[op]
        return out

    def fire(self, states: np.ndarray, col: np.ndarray, Q=None) -> np.ndarray:
        """The natural transition of each CFE whose event function ``col`` reached zero
        (col < 0: none): open; a stuck CFE onto the facet; a slipping one onto the vertex
        it reached; an open one closes.  ``adaptive``: a CFE's first slip turns its polygon
        (a vertex on its force ``Q``) instead, and it stays stuck."""
        new = states.copy()
        new = np.where(col == 0, OPEN, new)
        facet = (col >= 1) & (col <= self.k)
        i = col - 1
        stick = facet & (states == STICK)
        if self.adaptive and Q is not None:
            turn = stick & ~self.oriented & (np.linalg.norm(Q, axis=-1) > 0)
            if turn.any():
                loc = np.flatnonzero(turn)
                self.orient(loc, np.arctan2(Q[loc, 1], Q[loc, 0]))
                self.oriented[loc] = True
                stick &= ~turn
        new = np.where(stick, FACET_SLIP + i, new)
        fa, _ = self._facets(states)
        face = facet & (states >= FACET_SLIP) & (states < VERTEX_SLIP)
        up = face & (i == (fa + 1) % self.k)  # facet fa + 1 reached: vertex fa + 1
        down = face & (fa == (i + 1) % self.k)  # facet fa − 1 reached: vertex fa
        new = np.where(up, VERTEX_SLIP + i, new)
        new = np.where(down, VERTEX_SLIP + fa, new)
        new = np.where(face & ~up & ~down, FACET_SLIP + i, new)
        return np.where(col == self.k + 1, self.closed_state(), new)

    # ---- the rate problem at a degenerate point ---------------------------------------------
    def limits(self, states, Q, p, un, tf: float, tw: float):
        """Normal limit (p = 0 closed, u_n = 0 open) and two-sided friction (|Q| = 0 and f p = 0:
        every facet at once)."""
        free = ~self.inert
        normal = np.where(states == OPEN, self.surface - un <= tw, p <= tf) & free
        two_sided = normal | ((np.linalg.norm(Q, axis=-1) <= tf) & (self.f * p <= tf))
        return normal, two_sided & free

    def rate_variables(self, local, states, Q, normal_lim, two_sided, *, p=None,
                       tf: float = 0.0) -> RateVariables:
        """An opening rate o ≥ 0 where a CFE is at its normal limit (complement p' ≥ 0) and a
        slip rate a_i ≥ 0 on each facet it touches (g_i ≤ tf; every facet where it is
        two-sided), complement g_i' = f cos(π/k) p' − d_i · Q' ≥ 0.

        Effects on the stuck base scheme: u_n' = −o, u_τ' = Σ a_i d_i (rigid);
        p' − C_n u_n' = C_n o, Q' − C_τ u_τ' = −C_τ Σ a_i d_i (layer)."""
        local = np.asarray(local, dtype=np.int64)
        pl = np.zeros(len(states)) if p is None else p
        g = self.margins(Q, pl)[local]
        fr = self.frictional[local]
        touch = fr[:, None] & ((g <= tf) | two_sided[local][:, None])
        op = normal_lim[local]
        ro, co = np.nonzero(touch)
        lo = local[np.flatnonzero(op)]
        ls = local[ro]
        nv_o, nv_s = len(lo), len(ls)
        effect = np.zeros((nv_o + nv_s, 3))
        comp = np.zeros((nv_o + nv_s, 3))
        effect[:nv_o, 2] = np.where(self.rigid_n[lo], -1.0, self.kn[lo])
        comp[:nv_o, 2] = 1.0
        d = self.D[ls, co]
        effect[nv_o:, :2] = d * np.where(self.rigid_t[ls], 1.0, -self.kt[ls])[:, None]
        comp[nv_o:, :2] = -d
        comp[nv_o:, 2] = self.mu[ls]
        return RateVariables(
            cfe=self.cfes[np.r_[lo, ls]],
            kind=np.r_[np.full(nv_o, OPENING), np.full(nv_s, SLIP_PLUS)].astype(np.int64),
            effect=effect, comp=comp,
            facet=np.r_[np.full(nv_o, -1), co].astype(np.int64))

    def active_for(self, states, kind, facet) -> np.ndarray:
        """The variables the states stand for: an opening where OPEN, the slip rates of the
        facet (or the two of the vertex) a CFE slips on."""
        fa, fb = self._facets(states)
        return np.where(kind == OPENING, states == OPEN, (facet == fa) | (facet == fb))

    def basis_options(self, kind, facet) -> list[list[int]]:
        """Bases of one CFE's variables that stand for distinct states: stick, one facet, two
        neighbouring facets (a vertex), each with or without the opening (an open CFE moves
        tangentially in any direction)."""
        o = [i for i in range(len(kind)) if kind[i] == OPENING]
        sl = [i for i in range(len(kind)) if kind[i] != OPENING]
        pairs = [[a, b] for x, a in enumerate(sl) for b in sl[x + 1:]
                 if (facet[a] - facet[b]) % self.k in (1, self.k - 1)]
        slips: list[list[int]] = [[], *([i] for i in sl), *pairs]
        return slips + ([o + s for s in slips] if o else [])

    def states_from_active(self, base, var_local, var_kind, active, z, facet=None
                           ) -> np.ndarray:
        """The scheme a solution stands for: openings; one active facet: slip on it; two
        neighbouring ones: the vertex between them (more: the largest rate and its larger
        neighbour)."""
        new = base.copy()
        sl = active & (var_kind != OPENING)
        cf, pos = np.unique(var_local[sl], return_inverse=True)
        if cf.size:  # (per CFE a row of its facets' rates, −∞ where a facet is not active)
            k = self.k
            zf = np.full((cf.size, k), -np.inf)
            zf[pos, facet[sl]] = z[sl]
            r = np.arange(cf.size)
            top = np.argmax(zf, axis=1)  # (ties: the lowest facet, the variables' order)
            left, right = (top - 1) % k, (top + 1) % k
            zl, zr = zf[r, left], zf[r, right]
            # the active neighbour with the larger rate (a tie: the lower facet)
            other = np.where((zr > zl) | ((zr == zl) & (right < left)), right, left)
            alone = np.isneginf(np.maximum(zl, zr))
            v = np.where((top - other) % k == 1, top, other)  # vertex v between v − 1 and v
            new[cf] = np.where(alone, FACET_SLIP + top, VERTEX_SLIP + v)
        opened = np.zeros(len(base), bool)
        opened[var_local[active & (var_kind == OPENING)]] = True
        new[opened] = OPEN
        return new

    def consistent(self, trial, Q, dQ, dp, dun, dut, normal_lim, two_sided, rf, rw, *, p=None,
                   tf: float = 0.0) -> np.ndarray:
        """States that the rates of scheme ``trial`` point to (equal to ``trial`` where the
        rates satisfy the conditions of the CFE at its limits)."""
        new = trial.copy()
        closed = trial != OPEN
        new[(trial == OPEN) & (dun > rw) & ~self.inert] = self.closed_state()[
            (trial == OPEN) & (dun > rw) & ~self.inert]
        opening = closed & normal_lim & (dp < -rf)
        pl = np.zeros(len(trial)) if p is None else p
        g = self.margins(Q, pl)
        dg = self.margins(dQ, dp, affine=False)
        at = (g <= tf) | two_sided[:, None]
        crossing = at & (dg < -rf) & self.frictional[:, None]
        worst = np.argmin(np.where(crossing, dg, _INF), axis=1)
        stick = (trial == STICK) & ~opening
        go = stick & crossing.any(axis=1)
        new[go] = FACET_SLIP + worst[go]
        # slipping: the slip (the displacement rate less the layer's) along the facet normals
        sl = self.slipping(trial) & ~opening
        fa, fb = self._facets(trial)
        if sl.any():
            slip = dut - np.where(self.rigid_t[:, None], 0.0,
                                  dQ / np.where(self.rigid_t, 1.0, self.kt)[:, None])
            idx = np.flatnonzero(sl)
            Da, Db = self.D[idx, np.maximum(fa[idx], 0)], self.D[idx, np.maximum(fb[idx], 0)]
            vertex = trial[idx] >= VERTEX_SLIP
            # slip = λa d_a + λb d_b (vertex), or λ d_a (facet)
            det = Da[:, 0] * Db[:, 1] - Da[:, 1] * Db[:, 0]
            s_ = slip[idx]
            la = np.where(vertex, (s_[:, 0] * Db[:, 1] - s_[:, 1] * Db[:, 0])
                          / np.where(vertex, det, 1.0), np.einsum("ij,ij->i", s_, Da))
            lb = np.where(vertex, (Da[:, 0] * s_[:, 1] - Da[:, 1] * s_[:, 0])
                          / np.where(vertex, det, 1.0), _INF)
            back = (la < -rw) & (lb < -rw) | (~vertex & (la < -rw))
            new[idx[back]] = STICK
            only_b = vertex & (la < -rw) & ~(lb < -rw)
            new[idx[only_b]] = FACET_SLIP + fb[idx[only_b]]
            only_a = vertex & (lb < -rw) & ~(la < -rw)
            new[idx[only_a]] = FACET_SLIP + fa[idx[only_a]]
            # a facet slip whose force leaves the polygon across another facet it touches
            cross = ~vertex & ~back & crossing[idx].any(axis=1)
            own = np.zeros_like(crossing[idx])
            own[np.arange(len(idx)), fa[idx]] = True
            cross &= (crossing[idx] & ~own).any(axis=1)
            new[idx[cross]] = FACET_SLIP + np.argmin(
                np.where(crossing[idx] & ~own, dg[idx], _INF), axis=1)[cross]
        new[opening] = OPEN
        return new

    # ---- corrections and violation ----------------------------------------------------------
    def snap(self, states, Q, p, un):
        """Right-hand sides (r_τ (K, 2), r_n (K,)) that move the state onto the relations of
        ``states`` at a fixed load: open → N = Q = 0; closed rigid → u_n = 0; compliant →
        p = C_n u_n; frictionless → Q = 0; slipping → Q on its facet(s) (g = 0)."""
        closed = (states != OPEN) & ~self.inert
        r_t = np.where((~closed | (states == CLOSED))[:, None], -Q, 0.0)
        r_n = np.where(~closed, -p, 0.0)
        r_n = np.where(closed & self.rigid_n, -un, r_n)
        kn = np.where(self.rigid_n, 0.0, self.kn)
        r_n = np.where(closed & ~self.rigid_n, kn * un + self.offset - p, r_n)
        sl = self.slipping(states) & closed
        if sl.any():
            g = self.margins(Q, p)
            fa, fb = self._facets(states)
            idx = np.flatnonzero(sl)
            r_t[idx, 0] = g[idx, fa[idx]]
            vertex = states[idx] >= VERTEX_SLIP
            r_t[idx, 1] = np.where(vertex, g[idx, fb[idx]], 0.0)
        return r_t, r_n

    def violation(self, states, Q, p, un, F: float, W: float) -> float:
        """Largest relative violation of conditions (1) on the polygon at a state (forces
        relative to ``F``, displacements to ``W``)."""
        if len(states) == 0:
            return 0.0
        closed = (states != OPEN) & ~self.inert
        g = self.margins(Q, p)
        fa, fb = self._facets(states)
        sl = self.slipping(states) & closed
        on = np.zeros(len(states))
        if sl.any():
            r = np.arange(len(states))
            on = np.where(sl, np.maximum(np.abs(g[r, np.maximum(fa, 0)]),
                                         np.abs(g[r, np.maximum(fb, 0)])), 0.0)
        qn = np.linalg.norm(Q, axis=-1)
        v = [
            np.where(~self.inert, np.maximum(-p, 0), 0.0) / F,
            np.where(~closed, np.abs(p) + qn, 0) / F,
            np.where(~closed & ~self.inert, np.maximum(un - self.surface, 0), 0) / W,
            np.where(closed & self.rigid_n, np.abs(un), 0) / W,
            np.where(~self.inert, np.maximum(-g.min(axis=1, initial=_INF), 0), 0) / F,
            on / F,
        ]
        return float(max(x.max(initial=0) for x in v))

    def article_step(self, states, p, dp, eps_p: float) -> float:
        return _INF

    # ---- the impulses of an impact -------------------------------------------------------------
    @staticmethod
    def impulse_pulls(states: np.ndarray) -> np.ndarray:
        return np.zeros(len(states), bool)

    def impulse_limit(self, states: np.ndarray, P: np.ndarray) -> np.ndarray:
        """|T| ≤ f P: an impact's tangential impulse within the cone's radius (the impulse
        form of eq. (1), :func:`~stepcontact.solver.dynamic._cone_impulse`)."""
        return np.where(P > 0, self.f * P, 0.0)

    # ---- what the drivers ask of every law (no bonds, no cohesion on a faceted cone yet) ----
    def losing_cohesion(self, states, p, tf: float) -> np.ndarray:
        return np.zeros(len(states), bool)

    def lose_cohesion(self, mask) -> None:
        return None

    def breaking(self, states, Q, p, dQ, dp, tf: float, rf: float) -> np.ndarray:
        return np.zeros(len(states), bool)


__all__ = ["FacetedCoulombLaw"]
