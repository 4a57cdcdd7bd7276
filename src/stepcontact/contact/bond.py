"""Joints with initial strength (eq. (12)): a contact law that holds a bonded CFE until its
strength surface is reached and then hands it over to a Coulomb law.

A bonded CFE carries tension and shear with no relative motion (or the compliance of its
layer, eq. (11)) inside the strength surface of eq. (12),

    N + |Q| / α_t ≤ N_R  (tension facets),     |Q| ≤ Q_R − α_R N  (shear facets)

(N_R, Q_R the CFE's limit tensile and shear forces, N; the article has α_t = α_R, the
Mohr–Coulomb form a tension cut-off, 1/α_t = 0).  |Q| is written with the facet normals
d_i of the Coulomb law the joint breaks into, as that law writes its own limit:

    c (N_R + p) − d_i · Q / α_t ≥ 0,      c (Q_R + α_R p) − d_i · Q ≥ 0

with c = 1 and d = ±1 in 2D (the four facets of the article) and, on a faceted cone of k
facets in 3D, c = cos(π/k) and the k facet normals (the polygon inscribed in the circle
|Q| = …, the same inner approximation as the cone's).  So every facet is an affine event
function and the break is located exactly.

:class:`BondedJointLaw` is a sibling of the Coulomb laws
(:class:`~stepcontact.contact.laws.CoulombLaw`,
:class:`~stepcontact.contact.faceted.FacetedCoulombLaw`): it owns the state BONDED, the
bond's relations, event columns and violation, and asks the Coulomb law ``after`` everything
else.  When a bond breaks the driver asks it for the CFE's Coulomb state
(:meth:`BondedJointLaw.broken_state`: the Coulomb law's state at those forces) and for the
forces that state cannot carry (:meth:`BondedJointLaw.released`), which it releases at the
same load factor or instant (:mod:`stepcontact.solver.bonds`).
"""

from __future__ import annotations

import numpy as np

from stepcontact.contact.laws import BONDED, STICK, RateVariables, Relations

_INF = np.inf


class BondedJointLaw:
    """The bonds of eq. (12) over the CFEs of a Coulomb law ``after`` (same CFEs), which
    governs each CFE once its bond is broken, and every CFE without a bond.

    Parameters
    ----------
    after : CoulombLaw or FacetedCoulombLaw
        The law after the break (with its friction f, compliant layers, residual cohesion).
    bond : (K, ≥4) float
        N_R, Q_R (N), α_R, 1/α_t per CFE (:data:`~stepcontact.contact.laws.BOND_COLUMNS`;
        a fifth column, the residual cohesion, is the Coulomb law's); rows of NaN for CFEs
        without a bond.

    Event functions (columns): those of ``after`` (a bonded CFE has none of them), then the
    tension facets of the bond, one per facet normal of ``after``, then its shear facets
    (in 2D: tension+, tension−, shear+, shear−; module docstring).  Reaching one leaves the
    CFE BONDED in :meth:`fire`: the break, which releases forces, is the driver's.

    What a driver reads of the law and is not the bond's (f, C_n, C_τ, ``inert``,
    ``offset``, ``surface``, the residual cohesion …) is the Coulomb law's: attributes not
    defined here are looked up on ``after``.
    """

    def __init__(self, after, bond):
        self.after = after
        self.cfes = after.cfes
        K = len(self.cfes)
        b = np.asarray(bond, dtype=float)
        if b.ndim != 2 or b.shape[0] != K or b.shape[1] < 4:
            raise ValueError(f"BondedJointLaw: bond must be ({K}, ≥4), got {b.shape}")
        #: (K,) bool: CFEs with a bond (not held by supports)
        self.has_bond = ~np.isnan(b[:, 0]) & ~after.inert
        b = np.where(self.has_bond[:, None], b[:, :4], 0.0)
        self.NR, self.QR, self.alpha, self.iat = b.T.copy()
        #: the facet normals d_i (K, n_f, n_t) and their distance c of the Coulomb law
        self.D, self.c = after.facet_normals()
        nf = self.D.shape[1]
        self.n_after = after.n_columns
        self.n_columns = self.n_after + 2 * nf
        self.column_kinds = np.r_[after.column_kinds, np.zeros(2 * nf, int)]
        if nf == 2 and self.D.shape[2] == 1:
            names = ("tension+", "tension-", "shear+", "shear-")
        else:
            names = (*(f"tension {i}" for i in range(nf)), *(f"shear {i}" for i in range(nf)))
        self.column_names = (*after.column_names, *names)

    def __getattr__(self, name: str):
        # the Coulomb law's parameters and state (f, kn, kt, inert, offset, surface, …)
        after = self.__dict__.get("after")
        if after is None or name.startswith("__"):
            raise AttributeError(name)
        return getattr(after, name)

    # ---- the strength surface (eq. (12)) -------------------------------------------------------
    def bond_values(self, Q, p, affine: bool = True) -> np.ndarray:
        """The facets' values (K, 2 n_f) of eq. (12) at forces (Q (K,) in 2D or (K, n_t), p):
        the tension facets c (N_R + p) − d_i · Q / α_t, then the shear facets
        c (Q_R + α_R p) − d_i · Q; rates with ``affine=False``."""
        NR = self.NR if affine else 0.0
        QR = self.QR if affine else 0.0
        Qv = np.asarray(Q, dtype=float).reshape(len(self.cfes), -1)
        dq = np.einsum("kij,kj->ki", self.D, Qv)
        c = self.c
        return np.concatenate([c * (NR + p)[:, None] - dq * self.iat[:, None],
                               c * (QR + self.alpha * p)[:, None] - dq], axis=1)

    def breaking(self, states, Q, p, dQ, dp, tf: float, rf: float) -> np.ndarray:
        """Bonded CFEs on their strength surface (a facet within ``tf``) that the rates
        (dQ, dp) drive beyond it (rate below −``rf``): their bonds break here."""
        bonded = (states == BONDED) & self.has_bond
        if not bonded.any():
            return bonded
        phi = self.bond_values(Q, p)
        dphi = self.bond_values(dQ, dp, affine=False)
        return bonded & np.any((phi <= tf) & (dphi < -rf), axis=1)

    def broken_state(self, Q, p, tf: float = 0.0) -> np.ndarray:
        """The Coulomb state a CFE takes when its bond breaks at forces (Q, p) (eq. (12) holds
        no more): the state of ``after`` at those forces (open in tension, else stuck,
        slipping or closed)."""
        return self.after.state_at(Q, p, tf)

    def released(self, states, Q, p):
        """The part (ΔQ, Δp) of the forces (Q, p) that the Coulomb ``states`` cannot carry
        (``after``'s rule): what a broken bond (eq. (12)) releases."""
        return self.after.released(states, Q, p)

    def losing_cohesion(self, states, p, tf: float) -> np.ndarray:
        return self.after.losing_cohesion(states, p, tf) & (states != BONDED)

    # ---- states ------------------------------------------------------------------------------
    def _coulomb(self, states: np.ndarray) -> np.ndarray:
        """``states`` with the bonded CFEs stuck (what ``after`` is asked about them; their
        answers are then replaced)."""
        return np.where(states == BONDED, STICK, states)

    def base_state(self, states: np.ndarray) -> np.ndarray:
        """Bonded CFEs stay bonded; the others as ``after``."""
        return np.where(states == BONDED, BONDED, self.after.base_state(self._coulomb(states)))

    def initial_states(self, states: np.ndarray) -> np.ndarray:
        """``states`` with the bonded CFEs BONDED (the start of a run)."""
        return np.where(self.has_bond, BONDED, self.after.initial_states(states))

    def state_options(self, j: int, normal_lim: bool, state: int, hint=None) -> list[int]:
        """A bond holds (its break is the driver's); otherwise ``after``'s options."""
        if state == BONDED:
            return [BONDED]
        return self.after.state_options(j, normal_lim, state, hint)

    # ---- relations (eqs. (11), (12)) -----------------------------------------------------------
    def relations(self, states: np.ndarray, rel: Relations, m, article: bool = False) -> None:
        """``after``'s rows, and for bonded CFEs (an intact bond, eq. (12)) every component
        held: fixed (rigid, w_i' = r) or a spring (compliant layer, s_i' − C w_i' = r,
        eq. (11))."""
        bonded = (states == BONDED) & ~self.after.inert
        self.after.relations(self._coulomb(states), rel, m, article)
        if not bonded.any():
            return
        k = self.cfes[bonded]
        nt = rel.layout.n_t
        for i, (rigid, stiff) in enumerate([(self.after.rigid_t, self.after.kt)] * nt
                                           + [(self.after.rigid_n, self.after.kn)]):
            r, C = rigid[bonded], stiff[bonded]
            rel.S[k, i, :] = 0.0
            rel.W[k, i, :] = 0.0
            rel.S[k, i, i] = np.where(r, 0.0, 1.0)
            rel.W[k, i, i] = np.where(r, 1.0, -C)

    # ---- event functions (eqs. (2), (3), (12)) -------------------------------------------------
    def event_values(self, states, Q, p, un, affine: bool = True) -> np.ndarray:
        """φ (K, n_columns): ``after``'s columns (eqs. (2), (3); ``+inf`` for bonded CFEs),
        then the bond's facets (eq. (12); ``+inf`` for the others)."""
        bonded = (states == BONDED) & ~self.after.inert
        out = np.full((len(states), self.n_columns), _INF)
        out[:, :self.n_after] = self.after.event_values(self._coulomb(states), Q, p, un, affine)
        if bonded.any():
            out[bonded, :self.n_after] = _INF
            out[bonded, self.n_after:] = self.bond_values(Q, p, affine)[bonded]
        return out

    def fire(self, states: np.ndarray, col: np.ndarray, Q=None) -> np.ndarray:
        """``after``'s transitions; a bond's facet leaves the CFE BONDED (the driver breaks
        it: :meth:`broken_state`, :meth:`released`)."""
        own = np.where(col < self.n_after, col, -1)
        return np.where(states == BONDED, states, self.after.fire(states, own, Q))

    # ---- the rate problem at a degenerate point --------------------------------------------
    def limits(self, states, Q, p, un, tf: float, tw: float):
        """``after``'s limits; a bonded CFE has none."""
        normal, two = self.after.limits(self._coulomb(states), Q, p, un, tf, tw)
        free = states != BONDED
        return normal & free, two & free

    def rate_variables(self, local, states, Q, normal_lim, two_sided, *, p=None,
                       tf: float = 0.0) -> RateVariables:
        """``after``'s variables of the CFEs ``local`` that are not bonded (a bond breaks, a
        jump the driver follows, instead of moving at a rate)."""
        local = np.asarray(local)
        keep = local[states[local] != BONDED]
        return self.after.rate_variables(keep, self._coulomb(states), Q, normal_lim, two_sided,
                                         p=p, tf=tf)

    def consistent(self, trial, Q, dQ, dp, dun, dut, normal_lim, two_sided, rf, rw, *, p=None,
                   tf: float = 0.0) -> np.ndarray:
        new = self.after.consistent(self._coulomb(trial), Q, dQ, dp, dun, dut, normal_lim,
                                    two_sided, rf, rw, p=p, tf=tf)
        return np.where(trial == BONDED, BONDED, new)

    def active_for(self, states, kind, facet=None) -> np.ndarray:
        return self.after.active_for(states, kind, facet)

    def basis_options(self, kind, facet=None) -> list[list[int]]:
        return self.after.basis_options(kind, facet)

    def states_from_active(self, base, var_local, var_kind, active, z, facet=None):
        return self.after.states_from_active(base, var_local, var_kind, active, z, facet)

    def article_step(self, states, p, dp, eps_p: float) -> float:
        return self.after.article_step(self._coulomb(states), p, dp, eps_p)

    # ---- the impulses of an impact -------------------------------------------------------------
    def impulse_pulls(self, states: np.ndarray) -> np.ndarray:
        """An intact bond holds both ways: its normal impulse may pull."""
        return (states == BONDED) & ~self.after.inert

    def impulse_limit(self, states: np.ndarray, P: np.ndarray) -> np.ndarray:
        """A bond rigid in shear carries any tangential impulse (its strength is checked on
        the forces after the impact); the others as ``after``."""
        lim = self.after.impulse_limit(self._coulomb(states), P)
        return np.where((states == BONDED) & self.after.rigid_t & ~self.after.inert, _INF, lim)

    # ---- corrections and violation ----------------------------------------------------------
    def snap(self, states, Q, p, un):
        """``after``'s corrections; a bonded CFE keeps its tangential force and is moved onto
        its normal relation (rigid: u_n = 0; layer: p = C_n u_n)."""
        r_t, r_n = self.after.snap(self._coulomb(states), Q, p, un)
        bonded = (states == BONDED) & ~self.after.inert
        r_t[bonded] = 0.0
        return r_t, r_n

    def violation(self, states, Q, p, un, F: float, W: float) -> float:
        """The larger of ``after``'s violation over the CFEs that are not bonded and, over the
        bonded ones, of the strength surface (forces relative to ``F``) and of a rigid
        layer's u_n = 0 (relative to ``W``)."""
        if len(states) == 0:
            return 0.0
        bonded = (states == BONDED) & ~self.after.inert
        if not bonded.any():
            return self.after.violation(states, Q, p, un, F, W)
        Qb = np.where(bonded.reshape((-1,) + (1,) * (np.ndim(Q) - 1)), 0.0, Q)
        v = self.after.violation(self._coulomb(states), Qb, np.where(bonded, 0.0, p),
                                 np.where(bonded, 0.0, un), F, W)
        rigid = bonded & self.after.rigid_n
        return max(v, float(np.where(rigid, np.abs(un), 0).max(initial=0)) / W,
                   float(np.where(bonded, np.maximum(-self.bond_values(Q, p).min(axis=1), 0),
                                  0).max(initial=0)) / F)


__all__ = ["BondedJointLaw"]
