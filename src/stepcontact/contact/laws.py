"""Contact laws: what the state of a contact finite element (CFE) means.

A law owns, for its CFEs, everything the solver needs to know about their states — and nothing
about load factors, time or matrices:

* the **relation rows** of each state in the working scheme (article eqs. (1), (11)): one linear
  relation per CFE component between the rates of the mutual displacements w = [u_τ; u_n] and
  of the forces s = [Q; p] (p = −N ≥ 0 in compression) of the same CFE, a small block per CFE
  (:class:`Relations`); in 2D each row is of one kind::

      kind FIXED:   w_j' = r_j                      (rigid, no relative motion)
      kind SPRING:  s_j' − C_j w_j' = r_j           (compliant layer, eq. (11))
      kind FREE:    s_j' + c_j s_partner' = r_j     (c_j = 0: force prescribed; slip: Q' = σ f p')

* the **event functions** as values φ ≥ 0 that are affine in (s, w) for a fixed state, so that
  their rates along a path are the same forms applied to the rates (eqs. (2)–(3));
* the **transitions** each event function triggers;
* the **variables of the rate problem** at a degenerate point (opening and slip rates) with
  their complements, so that the engine can write the linear complementarity problem;
* the **measure of violation** of its conditions at a state.

The faceted form of friction: the Coulomb limit in 2D is two facets f p + C ∓ Q ≥ 0 (slip+ and
slip−; C the residual cohesion of a broken bond, 0 for plain Coulomb contact); a faceted cone in
3D is a further law with more facets (:mod:`stepcontact.contact.faceted`), and a bonded joint
(eq. (12)) a sibling law whose strength surface is more facets
(:mod:`stepcontact.contact.bond`), added without touching the engine.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache
from typing import Protocol

import numpy as np

from stepcontact.contact.layout import ContactLayout
from stepcontact.enums import MAX_FACETS, VERTEX_SLIP, ContactState

OPEN, STICK, SLIP_POS, SLIP_NEG, CLOSED, BONDED = (int(s) for s in (
    ContactState.OPEN, ContactState.STICK, ContactState.SLIP_POS, ContactState.SLIP_NEG,
    ContactState.CLOSED, ContactState.BONDED))

#: columns of a bond's strength (eq. (12); ``bond`` of
#: :class:`~stepcontact.contact.bond.BondedJointLaw`): N_R, Q_R (N), α_R,
#: 1/α_t (the slope of the tension facets; 0: a tension cut-off N ≤ N_R) and the residual
#: cohesion C_r A (N) that the CFE keeps after the break, until it opens
BOND_COLUMNS = ("tensile", "shear", "alpha", "inv_alpha_t", "residual_cohesion")

#: relation kinds of one CFE component in a working scheme
FREE, FIXED, SPRING = 0, 1, 2

#: kinds of rate-problem variables
OPENING, SLIP_PLUS, SLIP_MINUS = 0, 1, -1
_KINDS = np.array([OPENING, SLIP_PLUS, SLIP_MINUS])
_KINDS.setflags(write=False)

_INF = np.inf


def _layout(m: int | ContactLayout) -> ContactLayout:
    return m if isinstance(m, ContactLayout) else ContactLayout(m)


@dataclass(eq=False)
class Relations:
    """Relations of a working scheme as small per-CFE blocks (eqs. (1), (11), (12)): for CFE k
    and its component row i (i < n_t tangential, i = n_t normal; the order of ``layout``)

        Σ_c S[k, i, c] s_c' + W[k, i, c] w_c' = r_(i,k)        (c over the n_c = 1 + n_t
                                                                components of CFE k)

    with s = [Q; p] (N) and w = [u_τ; u_n] (m); S (m, n_c, n_c) is dimensionless, W (m, n_c,
    n_c) in N/m (or 1 in a row without forces: such a row's r is a displacement rate).
    The 2D relation kinds of one component i (partner P the CFE's other component) are

        FIXED:    w_i' = r                S[k,i,:] = 0,  W[k,i,i] = 1
        SPRING:   s_i' − C w_i' = r       S[k,i,i] = 1,  W[k,i,i] = −C   (C in N/m)
        FREE:     s_i' + c s_P' = r       S[k,i,i] = 1,  S[k,i,P] = c    (slip: Q' = σ f p')

    and a faceted cone writes rows that couple every component (a facet row
    d·Q' − f cos(π/k) p' = r, an along-facet row e·u_τ' = r)."""

    layout: ContactLayout
    S: np.ndarray
    W: np.ndarray
    _rows: tuple | None = field(default=None, init=False, repr=False)

    @staticmethod
    def empty(layout: int | ContactLayout) -> Relations:
        """Relations of the layout (or of m CFEs in 2D) with every row s_j' = r_j (S the
        identity, W zero: FREE with no coupling)."""
        lay = _layout(layout)
        S = np.zeros((lay.m, lay.n_c, lay.n_c))
        S[:, np.arange(lay.n_c), np.arange(lay.n_c)] = 1.0
        return Relations(lay, S, np.zeros_like(S))

    @staticmethod
    def blank(layout: int | ContactLayout) -> Relations:
        """Relations of the layout with blocks not yet written (uninitialised: for a law that
        writes every block, :meth:`CoulombLaw.relations`)."""
        lay = _layout(layout)
        return Relations(lay, np.empty((lay.m, lay.n_c, lay.n_c)),
                         np.empty((lay.m, lay.n_c, lay.n_c)))

    @staticmethod
    def from_kinds(kind, stiff, couple, layout: int | ContactLayout | None = None
                   ) -> Relations:
        """The blocks of 2D relations given per component (vectors (2m,) in the layout's order):
        ``kind`` (FREE, FIXED, SPRING), spring stiffness ``stiff`` (N/m; used by SPRING
        rows) and ``couple``, the coefficient c of the partner component's force rate in a
        FREE row (see the class docstring)."""
        kind, stiff, couple = (np.asarray(x) for x in (kind, stiff, couple))
        lay = _layout(layout) if layout is not None else ContactLayout.of_size(len(kind))
        if lay.n_t != 1 or len(kind) != lay.n:
            raise ValueError(f"Relations.from_kinds: {len(kind)} components do not fit a 2D "
                             f"layout of {lay.m} CFEs with n_t = {lay.n_t}")
        fixed, spring = kind == FIXED, kind == SPRING
        if not np.all(np.isfinite(stiff[spring])):
            raise ValueError("Relations.from_kinds: a SPRING row needs a finite stiffness")
        rel = Relations.empty(lay)
        k, i = lay.cfe_of(np.arange(lay.n)), lay.component_of(np.arange(lay.n))
        rel.S[k, i, i] = np.where(fixed, 0.0, 1.0)
        rel.W[k, i, i] = np.where(fixed, 1.0, np.where(spring, -stiff, 0.0))
        rel.S[k, i, 1 - i] = couple
        return rel

    def key(self) -> bytes:
        """The relations as bytes (the key of a scheme's factor)."""
        if self._rows is not None:
            return self._rows[0]
        return self.S.tobytes() + self.W.tobytes()

    def by_rows(self) -> np.ndarray:
        """The blocks row by row, (2, n_c, n) read-only: entry [0, o, j] (of S) and [1, o, j]
        (of W) is the coefficient, in row j = i m + k (component i of CFE k, the layout's
        order), of the CFE's component (i + o) mod n_c; o = 0 the diagonal.

        The first call freezes S and W (read-only): the relations of a scheme do not change
        once a solver has used them (change a copy instead)."""
        if self._rows is None:
            lay = self.layout
            m, nc = lay.m, lay.n_c
            take = _row_order(nc)
            rows = np.empty((2, nc, lay.n))
            for j, X in enumerate((self.S, self.W)):
                rows[j] = X.reshape(m, nc * nc).T[take].reshape(nc, lay.n)
            for x in (rows, self.S, self.W):
                x.setflags(write=False)
            self._rows = (self.S.tobytes() + self.W.tobytes(), rows)
        return self._rows[1]


@cache
def _row_order(nc: int) -> np.ndarray:
    """The entries (i, (i + o) mod n_c) of a raveled n_c × n_c block, in the order (o, i)
    (read-only: one array per n_c)."""
    i, o = np.arange(nc)[None, :], np.arange(nc)[:, None]
    out = (i * nc + (i + o) % nc).reshape(-1)
    out.setflags(write=False)
    return out


@dataclass
class RateVariables:
    """Variables z ≥ 0 of the rate problem of one law (global CFE ids, kinds, facets) with,
    per variable, its vector effect on the base scheme's relations and its complement.

    ``effect`` (nv, 1 + n_t): the relation right-hand sides over the components t₁[, t₂], n of
    the variable's CFE for z = 1; ``comp`` (nv, 1 + n_t): the complement
    w = Σ_c comp_c s'_c ≥ 0 (the rate of the event function the variable stands for);
    ``kind``: :data:`OPENING` or a slip variable (±1: 2D slip±, :data:`SLIP_PLUS` on a facet of
    a faceted cone); ``facet``: the facet of a slip variable of a faceted cone (−1 otherwise).
    """

    cfe: np.ndarray
    kind: np.ndarray
    effect: np.ndarray
    comp: np.ndarray
    facet: np.ndarray

    @staticmethod
    def concatenate(parts: list[RateVariables]) -> RateVariables:
        """The variables of several laws, one after the other."""
        n_c = max((p.effect.shape[1] for p in parts), default=2)
        return RateVariables(**{k: np.concatenate([getattr(p, k) for p in parts])
                                if parts else np.zeros((0, n_c) if k in ("effect", "comp")
                                                       else 0)
                                for k in ("cfe", "kind", "effect", "comp", "facet")})


class ContactLaw(Protocol):
    """What the engine, the rate problem and the drivers ask a contact law (its CFEs ``cfes``
    and their state codes; the law alone knows what a state means).

    * states: :meth:`closed_state`, :meth:`base_state`, :meth:`slipping`, :meth:`state_options`,
      and at given forces :meth:`state_at` with what that state cannot carry,
      :meth:`released` (a bond's break, eq. (12)); the facet normals of the friction limit,
      :meth:`facet_normals` (the directions a bond's strength surface is written in);
    * relations per state (eqs. (1), (11), (12)): :meth:`relations` writes the CFEs' blocks;
    * event functions (eqs. (2), (3), (12)): :meth:`event_values`, affine in (s, w), with
      ``column_kinds`` (0 a force, 1 a gap) and ``column_names``; :meth:`fire` the natural
      transitions;
    * the rate problem at a degenerate point: :meth:`limits`, :meth:`rate_variables` (vector
      effect and complement per variable), :meth:`active_for`, :meth:`basis_options`,
      :meth:`states_from_active`, :meth:`consistent`;
    * corrections: :meth:`snap`, :meth:`violation`, :meth:`article_step`;
    * the impulses of an impact: :meth:`impulse_pulls` (a normal impulse that may pull) and
      :meth:`impulse_limit` (the bound of the tangential impulse).
    """

    cfes: np.ndarray
    n_columns: int
    column_kinds: np.ndarray
    column_names: tuple[str, ...]

    def closed_state(self) -> np.ndarray: ...
    def base_state(self, states: np.ndarray) -> np.ndarray: ...
    def slipping(self, states: np.ndarray) -> np.ndarray: ...
    def facet_normals(self) -> tuple[np.ndarray, float]: ...
    def state_at(self, Q, p, tf: float = 0.0) -> np.ndarray: ...
    def released(self, states, Q, p): ...
    def relations(self, states, rel: Relations, m, article: bool = False) -> None: ...
    def event_values(self, states, Q, p, un, affine: bool = True) -> np.ndarray: ...
    def fire(self, states: np.ndarray, col: np.ndarray, Q=None) -> np.ndarray: ...
    def limits(self, states, Q, p, un, tf: float, tw: float): ...
    def rate_variables(self, local, states, Q, normal_lim, two_sided, *, p=None,
                       tf: float = 0.0) -> RateVariables: ...
    def active_for(self, states, kind, facet) -> np.ndarray: ...
    def basis_options(self, kind, facet) -> list[list[int]]: ...
    def states_from_active(self, base, var_local, var_kind, active, z, facet=None
                           ) -> np.ndarray: ...
    def state_options(self, j: int, normal_lim: bool, state: int, hint=None) -> list[int]: ...
    def consistent(self, trial, Q, dQ, dp, dun, dut, normal_lim, two_sided, rf, rw, *, p=None,
                   tf: float = 0.0) -> np.ndarray: ...
    def snap(self, states, Q, p, un): ...
    def violation(self, states, Q, p, un, F: float, W: float) -> float: ...
    def article_step(self, states, p, dp, eps_p: float) -> float: ...
    def impulse_pulls(self, states: np.ndarray) -> np.ndarray: ...
    def impulse_limit(self, states: np.ndarray, P: np.ndarray) -> np.ndarray: ...


#: state arrays whose masks a law keeps (:meth:`CoulombLaw._masks`)
_MASK_CACHE = 8
#: the state each event-function column of :class:`CoulombLaw` fires into (column 3, the
#: closing, into the CFE's closed state instead)
_FIRED = np.array([OPEN, SLIP_POS, SLIP_NEG, CLOSED])


def _mask_table() -> tuple[np.ndarray, np.ndarray]:
    """The masks of :class:`_StateMasks` for every pair (state code c, CFE flags g) as the
    columns 16 c + g of a table (one row per mask; flags g: 1 held by supports, 2 frictional,
    4 rigid normally, 8 rigid tangentially), and σ (+1 slip+, −1 else) per code: an array of
    states then gives every mask by one gather.  Codes up to the faceted cone's largest
    (codes a Coulomb law does not have behave as the original formulas treat them: closed,
    neither stick, slip nor frictionless)."""
    codes = np.repeat(np.arange(VERTEX_SLIP + MAX_FACETS), 16)
    g = np.tile(np.arange(16), VERTEX_SLIP + MAX_FACETS)
    held, fric, rigid, rigid_t = (g & 1) > 0, (g & 2) > 0, (g & 4) > 0, (g & 8) > 0
    op = codes == OPEN
    closed = ~op & ~held
    stick_state = codes == STICK
    slip = (codes == SLIP_POS) | (codes == SLIP_NEG)
    cl = codes == CLOSED
    rows = {"open": op & ~held, "closed": closed, "not_closed": ~closed,
            "stick": stick_state & closed & fric, "stick_state": stick_state, "slip": slip,
            "slip_closed": slip & closed, "cl": cl, "closed_rn": closed & rigid,
            "closed_sn": closed & ~rigid, "free_t": ~closed | cl,
            "held_t": closed & ~slip & fric, "held_t_rigid": closed & ~slip & fric & rigid_t,
            "couple": slip & closed & fric}
    table = np.array([rows[name] for name in _MASK_ROWS])
    sigma = np.where(np.arange(VERTEX_SLIP + MAX_FACETS) == SLIP_POS, 1.0, -1.0)
    for x in (table, sigma):
        x.setflags(write=False)
    return table, sigma


#: the rows of :func:`_mask_table` (the masks of :class:`_StateMasks`)
_MASK_ROWS = ("open", "closed", "not_closed", "stick", "stick_state", "slip", "slip_closed",
              "cl", "closed_rn", "closed_sn", "free_t", "held_t", "held_t_rigid", "couple")
_MASKS = _mask_table()


class _StateMasks:
    """The masks of one state array of a :class:`CoulombLaw` that its methods ask (read-only;
    formed once per scheme, :meth:`CoulombLaw._masks`, by one gather from
    :func:`_mask_table`).

    ``open``: OPEN and not held by supports; ``closed``: not OPEN and not held;
    ``not_closed`` its complement; ``stick``: closed, STICK and frictional; ``stick_state``:
    STICK; ``slip``: slip±; ``slip_closed``: slip± and closed; ``sigma``: +1 for slip+, −1
    else; ``cl``: CLOSED (frictionless); ``closed_rn``, ``closed_sn``: closed and rigid
    (compliant) normally; ``free_t``: a tangential force prescribed zero (not closed, or
    frictionless); ``held_t``: the tangential row held (closed, frictional, not slipping),
    ``held_t_rigid`` and rigidly so; ``couple``: the slip relation Q' = σ f p' (slipping,
    closed, frictional); ``any_open``, ``any_stick``, ``any_slip``: whether any CFE is open (and
    not held), stuck (closed, frictional), slipping."""

    __slots__ = ("any_open", "any_slip", "any_stick", "sigma", *_MASK_ROWS)

    def __init__(self, law: CoulombLaw, states: np.ndarray):
        table, sigma = _MASKS
        rows = table.take(np.multiply(states, 16, dtype=np.intp) + law._flags(), axis=1)
        rows.setflags(write=False)
        (self.open, self.closed, self.not_closed, self.stick, self.stick_state, self.slip,
         self.slip_closed, self.cl, self.closed_rn, self.closed_sn, self.free_t, self.held_t,
         self.held_t_rigid, self.couple) = rows  # (the order of _MASK_ROWS)
        self.sigma = sigma.take(states)
        self.sigma.setflags(write=False)
        self.any_open = bool(np.count_nonzero(self.open))
        self.any_stick = bool(np.count_nonzero(self.stick))
        self.any_slip = bool(np.count_nonzero(self.slip))


class CoulombLaw:
    """Unilateral contact with Coulomb friction, rigid or with a compliant layer (eqs. (1), (11)),
    in 2D (one tangential component).  A joint with initial strength (eq. (12)) is the sibling
    law :class:`~stepcontact.contact.bond.BondedJointLaw`, which hands its CFEs over to this one
    when their bonds break.

    States: OPEN (S3c: N = Q = 0, u_n ≤ 0), STICK (S1c: closed, |Q| ≤ −f N, no slip),
    SLIP_POS / SLIP_NEG (S2c: Q = ∓ f N … written Q = σ f p), CLOSED for frictionless CFEs
    (f = 0: closed, Q = 0; there is no stick or slip to tell apart).

    **Residual cohesion** (``cohesion``, C = C_r A_k; :data:`BOND_COLUMNS`
    ``residual_cohesion`` of a broken bond): the friction facets are then f p + C ∓ Q ≥ 0
    (slip at |Q| = f p + C; the slip relation's rate form Q' = σ f p' is unchanged).  The
    cohesion is lost when the CFE opens (an opened joint has none): ``cohesion_lost`` (k,)
    bool is part of the contact state, set by the driver (:meth:`lose_cohesion`; a closed CFE
    reaching p = 0 with cohesion, :meth:`losing_cohesion`, is handled like a break: the shear
    it carried is released at the same load factor).  A CFE with f = 0 but C > 0 sticks and
    slips like a frictional one until it loses C.

    Event functions (columns), each ≥ 0 while the state holds:

    0. p = −N                (closed → open, eq. (3))
    1. f p + C − Q           (stick → slip+, eq. (2))
    2. f p + C + Q           (stick → slip−, eq. (2))
    3. −u_n                  (open → closed, eq. (3))

    Parameters
    ----------
    cfes : (k,) int
        Global indices of the CFEs governed by this law.
    friction, kn, kt : (k,) float
        f, C_n, C_τ (N/m; ``inf`` for rigid contact) of those CFEs.
    held_normal, held_tangent : (k,) bool, optional
        Components whose relative motion is held by supports on both sides (their row of the
        contact operator is zero): the supports carry that component.  A CFE held normally
        carries nothing (it stays OPEN); one held tangentially is frictionless.
    cohesion : (k,) float, optional
        C (N), the residual cohesion of CFEs whose bond broke (0 or NaN: none).

    Two arrays that a driver may set between steps (zero by default, as in statics):
    ``offset`` (N), the closed compliant relation p = C_n u_n + offset, and ``surface`` (m),
    the position of the layer's free surface for an open CFE, which closes at u_n = surface.
    The dynamic driver's damped (Kelvin–Voigt) layers use them: a step's relation
    p = (C_n + c_n c₁) u_n + … and a layer that relaxes after it opened
    (:mod:`stepcontact.solver.dynamic`).
    """

    n_columns = 4
    #: :meth:`relations` writes every entry of the blocks of the CFEs it is given (those of a
    #: :meth:`Relations.blank` need no clearing first)
    writes_every_block = True
    #: the event-function columns: 0 a force, 1 a gap (their tolerances and rate scales)
    column_kinds = np.array([0, 0, 0, 1])
    column_names = ("p", "slip+", "slip-", "gap")

    def __init__(self, cfes, friction, kn, kt, held_normal=None, held_tangent=None,
                 cohesion=None):
        self.cfes = np.asarray(cfes, dtype=np.int64)
        k = len(self.cfes)
        self.inert = np.zeros(k, bool) if held_normal is None else np.asarray(held_normal, bool)
        ht = np.zeros(k, bool) if held_tangent is None else np.asarray(held_tangent, bool)
        self.f = np.where(ht | self.inert, 0.0, np.asarray(friction, dtype=float))
        self.kn = np.asarray(kn, dtype=float)
        self.kt = np.asarray(kt, dtype=float)
        self.rigid_n = ~np.isfinite(self.kn)
        self.rigid_t = ~np.isfinite(self.kt)
        self.offset = np.zeros(k)
        self.surface = np.zeros(k)
        #: no bonds in this law (a bonded joint is
        #: :class:`~stepcontact.contact.bond.BondedJointLaw` over it): what drivers read
        self.has_bond = np.zeros(k, bool)
        #: C_r A (N) of each CFE after its bond broke (0: none; held tangentially: none)
        self.residual = (np.zeros(k) if cohesion is None
                         else np.nan_to_num(np.asarray(cohesion, dtype=float)).copy())
        self.residual[ht | self.inert] = 0.0
        #: (k,) bool, part of the contact state: the CFE opened after its bond broke and has
        #: no residual cohesion any more (set by the driver, :meth:`lose_cohesion`)
        self.cohesion_lost = np.zeros(k, bool)
        self._fpos = self.f > 0
        self._any_residual = bool(np.any(self.residual > 0))
        #: what the event loop asks per event and does not change along a run (the law's
        #: parameters are fixed; only ``cohesion_lost``, ``offset`` and ``surface`` move)
        self._any_inert = bool(self.inert.any())
        self._kn0 = np.where(self.rigid_n, 0.0, self.kn)
        self._kt1 = np.where(self.rigid_t, 1.0, self.kt)
        self._w_t = np.where(self.rigid_t, 1.0, -self.kt)  # W of a held row: FIXED 1, SPRING −C
        self._w_n = np.where(self.rigid_n, 1.0, -self.kn)
        self._sel = (slice(0, k) if np.array_equal(self.cfes, np.arange(k)) else self.cfes)
        self._closed = np.where(self._fpos, STICK, CLOSED)
        self._flag_static = self.inert.astype(np.intp) + 4 * self.rigid_n + 8 * self.rigid_t
        self._flag0 = self._flag_static + 2 * self._fpos
        #: state masks of the last few state arrays (:meth:`_masks`)
        self._mask_cache: dict = {}
        self._no_cohesion = np.zeros(k)
        self._no_cohesion.setflags(write=False)

    @property
    def cohesion(self) -> np.ndarray:
        """C (k,): the residual cohesion (N) the CFEs have now (0 where lost or none)."""
        if not self._any_residual:
            return self._no_cohesion  # (read-only)
        return np.where(self.cohesion_lost, 0.0, self.residual)

    @property
    def frictional(self) -> np.ndarray:
        """CFEs that stick and slip (f > 0, or a residual cohesion C > 0)."""
        if not self._any_residual:
            return self._fpos
        return self._fpos | (self.cohesion > 0)

    def friction_limit(self, p, states=None) -> np.ndarray:
        """The friction limit f p + C (N) of closed CFEs at normal force p (an open CFE, in
        ``states``, has no cohesion)."""
        c = self.cohesion
        if states is not None and self._any_residual:
            c = np.where(states == OPEN, 0.0, c)
        return self.f * p + c

    # ---- residual cohesion ------------------------------------------------------------------
    def losing_cohesion(self, states, p, tf: float) -> np.ndarray:
        """Closed Coulomb CFEs that still have a residual cohesion and sit at p ≤ ``tf``: they
        open here and lose it (the driver releases the shear they carried)."""
        if not self._any_residual:
            return np.zeros(len(states), bool)
        coulomb = (states != OPEN) & ~self.inert
        return coulomb & (self.cohesion > 0) & (p <= tf)

    def lose_cohesion(self, mask) -> None:
        """The CFEs ``mask`` (k,) lose their residual cohesion for good (they opened)."""
        self.cohesion_lost |= np.asarray(mask, bool) & (self.residual > 0)

    # ---- states ----------------------------------------------------------------------------
    def _masks(self, states: np.ndarray) -> _StateMasks:
        """The masks of ``states`` that the law's methods ask (:class:`_StateMasks`), kept for
        the last few state arrays: an event point asks for those of the same two or three
        schemes many times.  The key is the states' bytes (with which CFEs lost their residual
        cohesion: it decides which are frictional)."""
        states = np.asarray(states)
        key = (states.dtype.char, states.tobytes())
        if self._any_residual:
            key += (self.cohesion_lost.tobytes(),)
        mk = self._mask_cache.get(key)
        if mk is None:
            mk = _StateMasks(self, states)
            cache = self._mask_cache
            cache[key] = mk
            if len(cache) > _MASK_CACHE:
                del cache[next(iter(cache))]
        return mk

    def _flags(self) -> np.ndarray:
        """Per CFE the flags of :func:`_mask_table`: 1 held by supports, 2 frictional (with
        a residual cohesion: until it is lost), 4 rigid normally, 8 rigid tangentially."""
        if not self._any_residual:
            return self._flag0
        return self._flag_static + 2 * self.frictional

    def closed_state(self) -> np.ndarray:
        """The state a CFE takes when it closes (and the base of the rate problem)."""
        if not self._any_residual:
            return self._closed.copy()
        return np.where(self.frictional, STICK, CLOSED)

    def base_state(self, states: np.ndarray) -> np.ndarray:
        """The base scheme of the rate problem: every CFE closed and stuck (the state it
        takes when it closes)."""
        return self.closed_state()

    @staticmethod
    def initial_states(states: np.ndarray) -> np.ndarray:
        """The states at the start of a run (unchanged: no bonds here)."""
        return states

    @staticmethod
    def slipping(states: np.ndarray) -> np.ndarray:
        return (states == SLIP_POS) | (states == SLIP_NEG)

    def slip_mask(self, states: np.ndarray) -> np.ndarray:
        """:meth:`slipping` of a state array from its kept masks (read-only)."""
        return self._masks(states).slip

    def facet_normals(self) -> tuple[np.ndarray, float]:
        """The outward normals d (k, 2, 1) of the friction limit's two facets, +1 (slip+) and
        −1 (slip−), and their distance factor c = 1: the limit is d · Q ≤ c (f p + C)."""
        D = np.empty((len(self.cfes), 2, 1))
        D[:, 0, 0], D[:, 1, 0] = 1.0, -1.0
        return D, 1.0

    def state_at(self, Q, p, tf: float = 0.0) -> np.ndarray:
        """The state a CFE takes at forces (Q, p) (a bond's break, eq. (12); eqs. (1), (11)
        from then on): open where it is in tension (p ≤ tf), else stuck or slipping
        (|Q| > f p + C: in the direction of Q), or closed where it is frictionless."""
        slip = np.where(Q > 0, SLIP_POS, SLIP_NEG)
        closed = np.where(self.frictional,
                          np.where(np.abs(Q) > self.friction_limit(p) + tf, slip, STICK), CLOSED)
        return np.where(p <= tf, OPEN, closed)

    def released(self, states, Q, p) -> tuple[np.ndarray, np.ndarray]:
        """The part (ΔQ, Δp) of the forces (Q, p) that the relations of Coulomb ``states``
        cannot carry (open: all of it; slipping: Q − σ (f p + C); frictionless: Q): what a
        broken bond (eq. (12), :class:`~stepcontact.contact.bond.BondedJointLaw`) or a lost
        residual cohesion releases."""
        op = states == OPEN
        sig = np.where(states == SLIP_POS, 1.0, -1.0)
        dQ = np.where(op | (states == CLOSED), Q,
                      np.where(self.slipping(states), Q - sig * self.friction_limit(p), 0.0))
        dp = np.where(op, p, 0.0)
        return dQ, dp

    # ---- relations (eqs. (1), (11), (12)) ------------------------------------------------------
    def relations(self, states: np.ndarray, rel: Relations, m: int | ContactLayout,
                  article: bool = False) -> None:
        """Write the relation rows of this law's CFEs in ``states`` into ``rel``: the
        working-scheme form of conditions (1) and of the compliant layer (eq. (11)).

        Open: both forces zero (FREE).  Stick: tangential fixed (or spring C_τ),
        normal fixed (or spring C_n).  Closed frictionless: Q = 0, normal as stick.  Slip
        (exact): Q' − σ f p' = 0 (the rate of Q = σ (f p + C)); slip (article, eqs. (4)–(6)):
        Q held during the step (FREE) and corrected afterwards by compensating forces.
        The rows are the blocks of :class:`Relations` (``rel.layout`` the layout; ``m`` is
        not used any more).
        """
        nt = rel.layout.n_t
        mk = self._masks(states)
        # (the CFE blocks of rel, written in place when the law has every CFE of rel)
        own = type(self._sel) is slice and len(rel.S) == len(states)
        S = rel.S if own else np.empty((len(states), nt + 1, nt + 1))
        W = rel.W if own else np.empty_like(S)
        S.fill(0.0)
        W.fill(0.0)
        # held rows: fixed (rigid) or spring (compliant); the tangential ones of closed
        # frictional CFEs that do not slip, the normal one of every closed CFE
        rows = ([(mk.held_t, mk.held_t_rigid, self._w_t)] * nt
                + [(mk.closed, mk.closed_rn, self._w_n)])
        for i, (held, fixed, w) in enumerate(rows):
            S[:, i, i] = np.where(fixed, 0.0, 1.0)  # FIXED: 0; SPRING, FREE: 1
            W[:, i, i] = np.where(held, w, 0.0)  # FIXED 1, SPRING −C
        if not article:  # FREE tangential: Q' − σ f p' = r
            S[:, :nt, nt] = np.where(mk.couple, -mk.sigma * self.f, 0.0)[:, None]
        if not own:
            rel.S[self._sel] = S
            rel.W[self._sel] = W

    # ---- event functions (eqs. (2), (3)) --------------------------------------------------------
    def event_values(self, states, Q, p, un, affine: bool = True) -> np.ndarray:
        """φ (k, 4) of the CFEs in ``states`` (``+inf`` where a function does not apply):
        the event functions of eqs. (2), (3) — columns 1, 2 stick → slip (eq. (2)), 0 and 3
        contact → open and open → contact (eq. (3)); the class docstring lists them.

        With ``affine=False`` the constant part is dropped, which turns values into rates
        when (Q, p, u_n) are rates: φ' = event_values(states, Q', p', u_n', affine=False).
        """
        mk = self._masks(states)
        out = np.full((len(states), self.n_columns), _INF)
        np.copyto(out[:, 0], p, where=mk.closed)
        if mk.any_stick:
            fp = self.f * p
            if affine and self._any_residual:
                fp = fp + self.cohesion
            np.copyto(out[:, 1], fp - Q, where=mk.stick)
            np.copyto(out[:, 2], fp + Q, where=mk.stick)
        if mk.any_open:
            np.copyto(out[:, 3], (self.surface if affine else 0.0) - un, where=mk.open)
        return out

    def fire(self, states: np.ndarray, col: np.ndarray, Q=None) -> np.ndarray:
        """The natural transition of each CFE whose event function ``col`` reached zero
        (col < 0: none)."""
        # (the type of the states and of the closed states')
        new = np.array(states, dtype=np.promote_types(states.dtype, self._closed.dtype))
        idx = np.flatnonzero(col >= 0)
        if idx.size:
            c = col[idx]
            new[idx] = np.where(c == 3, self.closed_state()[idx], _FIRED[c])
        return new

    # ---- the consistency check at a degenerate point ------------------------------------------
    def limits(self, states, Q, p, un, tf: float, tw: float):
        """Which CFEs sit at their normal limit (p = 0 closed, u_n = 0 open), and which are
        two-sided in friction as well (Q = 0 and f p + C = 0; at the normal limit without
        cohesion)."""
        mk = self._masks(states)
        # (an inert CFE is at no limit: the masks of the open ones leave it out)
        normal = np.where(mk.open, self.surface - un <= tw, p <= tf)
        if self._any_inert:
            normal &= ~self.inert
        if not self._any_residual:
            two_sided = normal | ((np.abs(Q) <= tf) & (self.f * p <= tf))
        else:
            c = np.where(states == OPEN, 0.0, self.cohesion)
            two_sided = (normal & (c <= tf)) | ((np.abs(Q) <= tf) & (self.f * p + c <= tf))
        if self._any_inert:
            two_sided &= ~self.inert
        return normal, two_sided

    def _at_friction(self, states, Q, p, tf: float) -> np.ndarray:
        """CFEs on a friction facet (|Q| ≥ f p + C − tf) or slipping; True everywhere without
        residual cohesion (where the CFEs a rate problem sees are on their facets anyway)."""
        if not self._any_residual or p is None:
            return np.ones(len(states), bool)
        c = np.where(states == OPEN, 0.0, self.cohesion)
        return ((c <= 0) | self.slipping(states)
                | (np.abs(Q) >= self.f * p + c - tf))

    @staticmethod
    def breaking(states, Q, p, dQ, dp, tf: float, rf: float) -> np.ndarray:
        """No bonds here (:class:`~stepcontact.contact.bond.BondedJointLaw` has them)."""
        return np.zeros(len(states), bool)

    def consistent(self, trial, Q, dQ, dp, dun, dut, normal_lim, two_sided, rf, rw, *, p=None,
                   tf: float = 0.0):
        """States that the rates of scheme ``trial`` point to (equal to ``trial`` where the
        rates satisfy the contact conditions (1) of the CFE at its limits).  With the normal
        forces ``p`` (and force tolerance ``tf``) a stuck CFE with residual cohesion that is
        not on its friction facet (|Q| < f p + C) is not driven to slip by its rates."""
        mk = self._masks(trial)
        new = trial.copy()
        pull = normal_lim & (dp < -rf)  # at the normal limit, pulled apart
        if mk.any_open:
            close = mk.open & (dun > rw)  # (the gap's rate −u_n' below −rw)
            new[close] = self.closed_state()[close]
        new[mk.cl & pull] = OPEN
        if np.count_nonzero(mk.stick_state):
            stick = mk.stick_state
            fdp = self.f * dp + rf
            v1 = stick & pull
            new[v1] = OPEN
            v2 = stick & ~v1 & two_sided & (np.abs(dQ) > fdp)
            new[v2] = np.where(dQ[v2] > 0, SLIP_POS, SLIP_NEG)
            sigma = np.sign(Q)
            v3 = stick & ~two_sided & (sigma * dQ > fdp)
            if self._any_residual and p is not None:
                v3 &= self._at_friction(trial, Q, p, tf)
            new[v3] = np.where(sigma[v3] > 0, SLIP_POS, SLIP_NEG)
        if mk.any_slip:
            slipping = mk.slip
            v4 = slipping & pull
            new[v4] = OPEN
            dslip = dut - np.where(self.rigid_t, 0.0, dQ / self._kt1)
            v5 = slipping & ~v4 & self.frictional & (mk.sigma * dslip < -rw)
            new[v5] = STICK
        return new

    def rate_variables(self, local, states, Q, normal_lim, two_sided, *, p=None,
                       tf: float = 0.0) -> RateVariables:
        """Variables of the rate problem for the CFEs ``local`` (indices into this law's CFEs):
        an opening rate o ≥ 0 where the CFE is at its normal limit (complement p' ≥ 0), and
        slip rates a± ≥ 0 on the friction facets it touches (complement f p' ∓ Q' ≥ 0: the
        rate of f p + C ∓ Q); with the normal forces ``p`` (tolerance ``tf``) a CFE with
        residual cohesion has slip rates only where it is on a facet.

        Their effect on the stuck base scheme enters through the right-hand side of the
        relations: rigid u_n' = −o, u_τ' = a⁺ − a⁻; compliant p' − C_n u_n' = C_n o,
        Q' − C_τ u_τ' = −C_τ (a⁺ − a⁻).
        """
        sigma = np.where(states == SLIP_NEG, -1.0,
                         np.where(states == SLIP_POS, 1.0, np.sign(Q)))[local]
        op = normal_lim[local]
        fr = self.frictional[local]
        if self._any_residual and p is not None:
            fr &= self._at_friction(states, Q, p, tf)[local]
        both = fr & (two_sided[local] | (sigma == 0))
        one = fr & ~both
        # per CFE: [opening?, slip+?, slip−?] (k, 3)
        take = np.array([op, both | (one & (sigma > 0)), both | (one & (sigma < 0))]).T
        rows, cols = np.nonzero(take)
        loc = local[rows]
        kind = _KINDS[cols]
        glob = self.cfes[loc]
        is_op = kind == OPENING
        kn, kt = self.kn[loc], self.kt[loc]
        value = np.where(is_op, np.where(self.rigid_n[loc], -1.0, kn),
                         kind * np.where(self.rigid_t[loc], 1.0, -kt))
        # components (t, n): an opening acts on the normal relation, a slip on the tangential
        effect = np.array([np.where(is_op, 0.0, value), np.where(is_op, value, 0.0)]).T
        comp = np.array([np.where(is_op, 0.0, -kind.astype(float)),
                         np.where(is_op, 1.0, self.f[loc])]).T
        return RateVariables(cfe=glob, kind=kind, effect=effect, comp=comp,
                             facet=np.full(len(glob), -1, dtype=np.int64))

    @staticmethod
    def active_for(states, kind, facet=None) -> np.ndarray:
        """Which variables (of ``kind``) are active in the scheme ``states`` of their CFEs: the
        complementary basis that stands for it (an opening where OPEN, slip± where slipping
        that way)."""
        return np.where(kind == OPENING, states == OPEN,
                        np.where(kind > 0, states == SLIP_POS, states == SLIP_NEG))

    @staticmethod
    def basis_options(kind, facet=None) -> list[list[int]]:
        """The complementary bases of one CFE's variables (positions in ``kind``) that stand
        for distinct states: none (stick), one slip rate, the opening alone, or the opening
        with a slip rate (an open CFE moves tangentially too: its Q' = 0 makes the slip
        complements zero)."""
        o = [i for i in range(len(kind)) if kind[i] == OPENING]
        slips = [i for i in range(len(kind)) if kind[i] != OPENING]
        opts: list[list[int]] = [[], *([i] for i in slips)]
        if o:
            opts += [o, *(o + [i] for i in slips)]
        return opts

    def state_options(self, j: int, normal_lim: bool, state: int, hint=None) -> list[int]:
        """The states CFE j (local) may take at a point where every scheme is tried: open (from
        its normal limit), closed, slip± where frictional.  (``hint``, the tangential force
        rate of a stuck scheme, is for the laws with many slip states.)"""
        opts = ([OPEN] if normal_lim or state == OPEN else []) + [int(self.closed_state()[j])]
        if self.frictional[j]:
            opts += [SLIP_POS, SLIP_NEG]
        return opts

    def article_step(self, states, p, dp, eps_p: float) -> float:
        """Step limit of the article's slip treatment, eq. (5): |ΔQ_p / Q_p| ≤ ε_p over the
        slipping CFEs (normal forces p, their rates dp)."""
        sl = self.slipping(states)
        dqp = self.f * dp
        qp = self.friction_limit(p, states)  # f p + C
        with np.errstate(divide="ignore", invalid="ignore"):
            v = np.where(sl & (np.abs(dqp) > 0), np.abs(eps_p * qp / dqp), _INF)
        return float(v.min(initial=_INF))

    def states_from_active(self, base, var_local, var_kind, active, z, facet=None
                           ) -> np.ndarray:
        """The scheme a solution of the rate problem stands for: openings first, then the
        net slip direction (a⁺ − a⁻) of each CFE whose slip rates are active."""
        new = base.copy()
        net = np.zeros(len(base))
        np.add.at(net, var_local, np.where(active & (var_kind != OPENING), var_kind * z, 0.0))
        slips = np.zeros(len(base), bool)
        slips[var_local[active & (var_kind != OPENING)]] = True
        new[slips & (net >= 0)] = SLIP_POS
        new[slips & (net < 0)] = SLIP_NEG
        opened = np.zeros(len(base), bool)
        opened[var_local[active & (var_kind == OPENING)]] = True
        new[opened] = OPEN
        return new

    # ---- the impulses of an impact (Newton's law with Coulomb friction) ----------------------
    @staticmethod
    def impulse_pulls(states: np.ndarray) -> np.ndarray:
        """(k,) bool: CFEs whose normal impulse at an impact may pull (none: contact pushes)."""
        return np.zeros(len(states), bool)

    def impulse_limit(self, states: np.ndarray, P: np.ndarray) -> np.ndarray:
        """The bound of each CFE's tangential impulse at an impact with normal impulses P
        (k,), N·s: Coulomb's |T| ≤ f P where P > 0 (the impulse form of eq. (1): the impact's
        forces are of unbounded size over no time, so a residual cohesion adds nothing);
        0 where no tangential impulse acts."""
        return np.where(P > 0, self.f * P, 0.0)

    # ---- corrections and violation ----------------------------------------------------------
    def snap(self, states, Q, p, un):
        """Right-hand side (r_τ, r_n) that moves the state onto the relations of ``states`` at
        a fixed load: open → N = Q = 0; closed rigid → u_n = 0; compliant →
        p = C_n u_n; slipping → Q = σ (f p + C) (in article mode this is the compensating
        correction δQ of eq. (4), which the engine applies as the compensating forces of
        eq. (6)); closed frictionless → Q = 0."""
        mk = self._masks(states)
        r_t = np.where(mk.free_t, -Q, 0.0)
        r_n = np.where(mk.not_closed, -p, 0.0)
        r_n = np.where(mk.closed_rn, -un, r_n)
        r_n = np.where(mk.closed_sn, self._kn0 * un + self.offset - p, r_n)
        if np.count_nonzero(mk.slip_closed):
            r_t = np.where(mk.slip_closed, mk.sigma * self.friction_limit(p) - Q, r_t)
        return r_t, r_n

    def violation(self, states, Q, p, un, F: float, W: float) -> float:
        """Largest relative violation of conditions (1) (and of the slip law) at a state:
        forces relative to ``F``, displacements relative to ``W``."""
        if len(states) == 0:
            return 0.0
        # (each term's largest over the CFEs, then over the terms: the division by the
        # positive scale is monotonic, so max(x) / F = max(x / F))
        mk = self._masks(states)
        lim = self.friction_limit(p, states)
        aQ = np.abs(Q)
        force = np.maximum(-p, 0.0)  # N ≤ 0
        np.maximum(force, aQ - lim, out=force)  # |Q| ≤ f(−N) + C
        if self._any_inert:
            force[self.inert] = 0.0
        np.maximum(force, np.where(mk.not_closed, np.abs(p) + aQ, 0.0), out=force)  # open
        if mk.any_slip:
            np.maximum(force, np.where(mk.slip_closed, np.abs(Q - mk.sigma * lim), 0.0),
                       out=force)
        gap = np.where(mk.closed_rn, np.abs(un), 0.0)  # closed rigid: u_n = 0
        if mk.any_open:  # open: u_n ≤ its surface
            np.maximum(gap, np.where(mk.open, np.maximum(un - self.surface, 0.0), 0.0),
                       out=gap)
        return float(max(_MAXIMUM(force, initial=0.0) / F, _MAXIMUM(gap, initial=0.0) / W))


_MAXIMUM = np.maximum.reduce


__all__ = ["BONDED", "BOND_COLUMNS", "CLOSED", "FIXED", "FREE", "OPEN", "SLIP_NEG", "SLIP_POS",
           "SPRING", "STICK", "ContactLaw", "CoulombLaw", "RateVariables", "Relations"]
