"""Condensation of the structure to the contact unknowns: one factorisation for the whole run.

Equilibrium and kinematics of the structure (free DOFs f, prescribed DOFs p):

    K_ff u_f + K_fp u_p + B_fᵀ s = f_f,        w = B_f u_f + B_p u_p + w⁰

with s = [Q; −N] the CFE forces and w = [u_τ; u_n] their mutual displacements.  A body held
only by contact makes K_ff singular, so the matrix that is factorised (once) is

    K₀ = K_ff + B_fᵀ D B_f,     D = diag(d_j),  d_j = Σ_a B_ja² K_aa > 0
    (any positive D cancels exactly)

which is regular whenever the structure with every CFE stuck is.  With t = s − D ŵ and
ŵ = B_f u_f, the structure is condensed exactly to

    (I − G D) ŵ + G s = Σ_P c_P ĥ_P,     G = B_f K₀⁻¹ B_fᵀ,   ĥ_P = B_f K₀⁻¹ (f_P − K_fp u_P)

Between two events the working scheme writes one linear relation per CFE component,
R_w w' + R_s s' = r (stuck: w' = 0; open: s' = 0; compliant: s' = C w'; slipping:
Q' = σ f (−N)'), so the rates along a load pattern follow from one dense solve of size 2m:

    A t' = r − R_w (ĥ + e) − R_s D ĥ,     A = R_s − (R_w + R_s D) G

A singular A is a working scheme that is a mechanism (equilibrium lost).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from stepcontact.enums import ContactState
from stepcontact.errors import ModelError
from stepcontact.fem.assembly import System
from stepcontact.solver.linalg import factorize

#: a scheme matrix whose reciprocal condition number (rows equilibrated) is below this is a
#: mechanism.  G carries a relative round-off of about eps·cond(K₀), so exact mechanisms of
#: slender structures show rcond of 1e-12..1e-11, well below any stable scheme met in practice.
RCOND_MECHANISM = 1e-10

#: relation kinds of one CFE component in a working scheme
FREE, FIXED, SPRING, FRICTION = 0, 1, 2, 3


#: K₀ whose 1-norm condition estimate exceeds this is singular: the structure is a mechanism
#: even with every CFE stuck (a rank deficiency shows as pivots at round-off, cond ≳ 1e15;
#: well-posed FE stiffness matrices, slender frames included, stay below about 1e12)
COND_SINGULAR = 1e13


def check_regular(system: System, K0: sp.spmatrix, factor, free: np.ndarray) -> None:
    """Raise a ModelError naming the bodies that are free to move if K₀ is singular.

    A sparse LU of a singular matrix often meets no exactly zero pivot (round-off), so the
    factorisation alone proves nothing: the condition number is estimated (Hager–Higham
    1-norm estimate of K₀⁻¹, a few solves) and the mechanism located from a solve, whose
    answer is dominated by the null mode.
    """
    n = K0.shape[0]
    if n == 0:
        return
    inv = spla.LinearOperator((n, n), matvec=factor.solve, rmatvec=factor.solve, dtype=float)
    with np.errstate(all="ignore"):
        cond = float(spla.onenormest(inv)) * float(spla.norm(K0, 1))
    if np.isfinite(cond) and cond < COND_SINGULAR:
        return
    with np.errstate(all="ignore"):
        x = np.zeros(system.ndof)
        x[free] = factor.solve(np.random.default_rng(0).standard_normal(n))
    x = np.nan_to_num(np.abs(x), nan=np.inf)
    model = system.model
    free_bodies = []
    for b in model.bodies:
        ids = model.node_offsets[b.name] + np.arange(b.n_nodes)
        d = system.dofs.of[ids]
        if np.max(x[d[d >= 0]], initial=0.0) > 1e-3 * np.max(x):
            free_bodies.append(f"'{b.name}'")
    where = (f"bod{'y' if len(free_bodies) == 1 else 'ies'} {', '.join(free_bodies)} can move "
             "as a mechanism" if free_bodies else "a mechanism")
    raise ModelError(
        "model",
        f"the structure is a mechanism even with every CFE stuck (stiffness condition "
        f"estimate {cond:.1e}): {where}; add supports, springs or contact interfaces",
    )


def _lu(A: np.ndarray):
    """Dense LU; a singular matrix is a mechanism the caller detects from rcond, not a warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sla.LinAlgWarning)
        return sla.lu_factor(A, check_finite=False)


class MechanismError(Exception):
    """The working scheme is a mechanism (singular condensed matrix)."""

    def __init__(self, A: np.ndarray, lu):
        self.A = A
        self.lu = lu
        super().__init__("working scheme is a mechanism")


@dataclass
class Relations:
    """Per-component relations of a working scheme: kind, stiffness, slip direction.

    ``kind[j]`` for j < m is the tangential component of CFE j, ``kind[m + j]`` its normal.
    For FRICTION rows (tangential only) ``sigma[j]`` is the slip direction.  ``imposed`` marks
    components whose force (FREE rows) or displacement (FIXED rows) rate is prescribed.
    """

    kind: np.ndarray
    stiff: np.ndarray
    sigma: np.ndarray


def scheme_relations(states: np.ndarray, cfe, article: bool = False) -> Relations:
    """Relations of the working scheme given the CFE states (vectorised).

    Open: both components free.  Stick: tangential fixed (or spring C_τ), normal fixed (or
    spring C_n).  Slip (exact): Q = σ f (−N); slip (article, eqs. (4)–(6)): tangential force
    held during the step (free) and corrected afterwards by compensating forces.
    """
    m = len(states)
    kind = np.empty(2 * m, dtype=np.int8)
    stiff = np.r_[cfe.kt, cfe.kn].astype(float)
    closed = states != ContactState.OPEN
    slipping = (states == ContactState.SLIP_POS) | (states == ContactState.SLIP_NEG)
    rigid_t = ~np.isfinite(cfe.kt)
    rigid_n = ~np.isfinite(cfe.kn)
    kt = np.where(rigid_t, FIXED, SPRING)
    kn = np.where(rigid_n, FIXED, SPRING)
    kind[:m] = np.where(closed, np.where(slipping, FREE if article else FRICTION, kt), FREE)
    kind[m:] = np.where(closed, kn, FREE)
    sigma = np.where(states == ContactState.SLIP_POS, 1.0,
                     np.where(states == ContactState.SLIP_NEG, -1.0, 0.0))
    return Relations(kind, stiff, sigma)


def stabilisation(Kff: sp.spmatrix, Bf: sp.spmatrix) -> np.ndarray:
    """D of K₀ = K_ff + B_fᵀ D B_f: for each CFE component the stiffness of the DOFs it joins,
    d_j = Σ_a B_ja² K_aa, so that stuck and free rows of the scheme matrix stay comparable."""
    diag = Kff.diagonal()
    d = np.asarray(Bf.multiply(Bf) @ diag).ravel()
    fallback = float(np.mean(diag[diag > 0])) if np.any(diag > 0) else 1.0
    return np.where(d > 0, d, fallback)


@dataclass
class Condensed:
    """The structure condensed to its 2m contact unknowns (see module docstring).

    Build with :meth:`from_system`.  Holds the one factorisation of K₀.
    """

    system: System
    free: np.ndarray
    presc: np.ndarray
    factor: object
    Bf: sp.csr_matrix
    Bp: sp.csr_matrix
    Kff: sp.csr_matrix
    Kfp: sp.csr_matrix
    d: np.ndarray
    G: np.ndarray
    hhat: dict[str, np.ndarray]
    e: dict[str, np.ndarray]
    y: dict[str, np.ndarray]
    counters: dict[str, float] = field(default_factory=dict)
    #: reaction resultants R = Σ_P c_P r_P + R_s s + R_t t (see :meth:`reactions`)
    r_load: dict[str, np.ndarray] = field(default_factory=dict)
    R_s: np.ndarray | None = None
    R_t: np.ndarray | None = None

    @classmethod
    def from_system(cls, system: System, backend: str = "auto", block: int = 256) -> Condensed:
        """Factorise K₀ once and condense to the contact unknowns (2m block solves)."""
        fixed = system.fixed
        free = np.flatnonzero(~fixed)
        presc = np.flatnonzero(fixed)
        K = system.K.tocsr()
        Kff = K[free][:, free].tocsr()
        Kfp = K[free][:, presc].tocsr()
        Bf = system.B[:, free].tocsr()
        Bp = system.B[:, presc].tocsr()
        d = stabilisation(Kff, Bf)
        K0 = (Kff + Bf.T @ sp.diags(d) @ Bf).tocsc()
        factor = factorize(K0, backend)
        check_regular(system, K0, factor, free)
        n2m = Bf.shape[0]
        G = np.zeros((n2m, n2m))
        BfT = Bf.T.tocsc()
        nsolve = 0
        for s in range(0, n2m, block):
            cols = BfT[:, s : s + block].toarray()
            X = factor.solve(cols)
            G[:, s : s + block] = Bf @ X
            nsolve += cols.shape[1]
        G = 0.5 * (G + G.T)
        hhat, e, y = {}, {}, {}
        for name, lv in system.loads.items():
            rhs = lv.f[free] - Kfp @ lv.u[presc]
            y[name] = factor.solve(rhs)
            hhat[name] = Bf @ y[name]
            e[name] = Bp @ lv.u[presc]
            nsolve += 1
        # reaction resultants: one solve per resultant, then every state costs a matvec
        Sp = system.reaction_rows[:, presc] if system.reaction_rows is not None else None
        r_load: dict[str, np.ndarray] = {}
        R_s = R_t = None
        if Sp is not None and Sp.shape[0]:
            Kpf = K[presc][:, free].tocsr()
            Kpp = K[presc][:, presc].tocsr()
            V = factor.solve((Kfp @ Sp.T).toarray())
            V = V.reshape(len(free), Sp.shape[0])
            nsolve += Sp.shape[0]
            R_t = -(Bf @ V).T
            R_s = (Sp @ Bp.T).toarray()
            for name, lv in system.loads.items():
                up = lv.u[presc]
                r_load[name] = Sp @ (Kpf @ y[name] + Kpp @ up - lv.f[presc])
        counters = {"factorizations": 1, "solves": nsolve, "condensed_columns": n2m}
        return cls(system, free, presc, factor, Bf, Bp, Kff, Kfp, d, G, hhat, e, y, counters,
                   r_load, R_s, R_t)

    def reactions(self, factors: dict[str, float], s: np.ndarray, w: np.ndarray) -> np.ndarray:
        """Reaction resultants of the supports (and prescribed DOFs) on the structure, N (N·m
        for rz), at any state — no solve:

            R = S_p (K_pf u_f + K_pp u_p + B_pᵀ s − f_p)
              = Σ_P c_P S_p (K_pf y_P + K_pp u_P − f_P) − (B_f K₀⁻¹ K_fp S_pᵀ)ᵀ t + S_p B_pᵀ s

        with t = s − D ŵ as in :meth:`displacement` (``system.reaction_rows`` gives S)."""
        if self.R_s is None:
            return np.zeros(0)
        R = self.R_s @ s
        e = np.zeros(2 * self.m)
        for name, c in factors.items():
            if c != 0.0:
                R = R + c * self.r_load[name]
                e += c * self.e[name]
        w_hat = w - self.system.w0 - e
        return R + self.R_t @ (s - self.d * w_hat)

    @property
    def m(self) -> int:
        return self.G.shape[0] // 2

    # ---- the scheme matrix -----------------------------------------------------------------
    def scheme_matrix(self, rel: Relations, cfe) -> tuple[sp.csr_matrix, sp.csr_matrix]:
        """Sparse R_w, R_s of the relations R_w w' + R_s s' = r."""
        m = self.m
        n = 2 * m
        j = np.arange(n)
        rw = np.where(rel.kind == FIXED, 1.0, np.where(rel.kind == SPRING, -rel.stiff, 0.0))
        rw = np.where(np.isfinite(rw), rw, 0.0)
        rs = np.where(rel.kind == FIXED, 0.0, 1.0)
        Rw = sp.csr_matrix((rw, (j, j)), shape=(n, n))
        fr = np.flatnonzero(rel.kind[:m] == FRICTION)
        rows = np.r_[j, fr]
        cols = np.r_[j, m + fr]
        vals = np.r_[rs, -rel.sigma[fr] * cfe.friction[fr]]
        Rs = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
        return Rw, Rs

    def scheme_rows(self, rel: Relations, cfe, idx: np.ndarray):
        """Rows ``idx`` of the scheme matrix A = R_s − (R_w + d R_s) G, equilibrated.

        Rows of stuck components scale like 1/d and rows of free ones like 1, so each row is
        divided by its largest entry: the condition estimate then measures a mechanism, not the
        choice of units.  Returns (rows (k, 2m), row scales (k,)).
        """
        m = self.m
        kind = rel.kind[idx]
        rw = np.where(kind == FIXED, 1.0, np.where(kind == SPRING, -rel.stiff[idx], 0.0))
        rw = np.where(np.isfinite(rw), rw, 0.0)
        rs = np.where(kind == FIXED, 0.0, 1.0)
        rows = -(rw + self.d[idx] * rs)[:, None] * self.G[idx]
        rows[np.arange(len(idx)), idx] += rs
        fr = np.flatnonzero(kind == FRICTION)
        if fr.size:
            j = idx[fr]
            c = -rel.sigma[j] * cfe.friction[j]
            rows[fr, m + j] += c
            rows[fr] -= (self.d[m + j] * c)[:, None] * self.G[m + j]
        scale = 1.0 / np.maximum(np.abs(rows).max(axis=1, initial=0.0), 1e-300)
        return rows * scale[:, None], scale

    def factor_scheme(self, rel: Relations, cfe):
        """LU of the scheme matrix A; raises MechanismError if A is (numerically) singular."""
        Rw, Rs = self.scheme_matrix(rel, cfe)
        A, rscale = self.scheme_rows(rel, cfe, np.arange(2 * self.m))
        lu = _lu(A)
        anorm = np.linalg.norm(A, 1)
        rcond = sla.lapack.dgecon(lu[0], anorm, norm="1")[0] if A.size else 1.0
        self.counters["scheme_factorizations"] = self.counters.get("scheme_factorizations", 0) + 1
        if not rcond > RCOND_MECHANISM:
            raise MechanismError(A, lu)
        return Rw, Rs, lu, rscale

    def solve(self, fact, hhat: np.ndarray, e: np.ndarray, r: np.ndarray):
        """Rates (s', w') for load rate (ĥ, e) and relation right-hand side r."""
        Rw, Rs, lu, rscale = fact
        rhs = rscale * (r - Rw @ (hhat + e) - Rs @ (self.d * hhat))
        t = sla.lu_solve(lu, rhs, check_finite=False)
        w_hat = hhat - self.G @ t
        s = t + self.d * w_hat
        return s, w_hat + e

    # ---- fields ----------------------------------------------------------------------------
    def displacement(self, factors: dict[str, float], s: np.ndarray, w: np.ndarray) -> np.ndarray:
        """Full displacement vector (ndof,) of a state: one solve with the K₀ factorisation."""
        sysm = self.system
        u = np.zeros(sysm.ndof)
        up = np.zeros(len(self.presc))
        rhs_load = np.zeros(len(self.free))
        e = np.zeros(2 * self.m)
        for name, c in factors.items():
            if c == 0.0:
                continue
            lv = sysm.loads[name]
            up += c * lv.u[self.presc]
            rhs_load += c * lv.f[self.free]
            e += c * self.e[name]
        w_hat = w - sysm.w0 - e
        t = s - self.d * w_hat
        rhs = rhs_load - self.Kfp @ up - self.Bf.T @ t
        u[self.free] = self.factor.solve(rhs)
        u[self.presc] = up
        self.counters["solves"] = self.counters.get("solves", 0) + 1
        return u

    def check(self, factors: dict[str, float], s: np.ndarray, w: np.ndarray, u: np.ndarray,
              w_scale: float = 0.0):
        """Relative equilibrium residual and kinematic mismatch of a state.

        residual = ‖K_ff u_f + K_fp u_p + B_fᵀ s − f_f‖ / ‖f_f + |B_fᵀ s|‖ (max norms);
        kinematic = ‖B u + w⁰ − w‖ / max(‖w‖, ‖u‖, w_scale).
        """
        sysm = self.system
        f = np.zeros(sysm.ndof)
        for name, c in factors.items():
            f += c * sysm.loads[name].f
        uf, up = u[self.free], u[self.presc]
        Ku = self.Kff @ uf + self.Kfp @ up
        Bs = self.Bf.T @ s
        r = Ku + Bs - f[self.free]
        scale = max(np.abs(Ku).max(initial=0), np.abs(Bs).max(initial=0),
                    np.abs(f[self.free]).max(initial=0), 1e-300)
        wk = sysm.B @ u + sysm.w0
        kscale = max(np.abs(w).max(initial=0), np.abs(u).max(initial=0), w_scale, 1e-300)
        kin = float(np.abs(wk - w).max(initial=0) / kscale)
        return float(np.abs(r).max(initial=0) / scale), kin

    def condensed_residual(self, factors: dict[str, float], s: np.ndarray, w: np.ndarray,
                           w_scale: float = 0.0) -> float:
        """Relative residual of the condensed equilibrium equations (no solve):

            ‖ŵ + G (s − D ŵ) − Σ_P c_P ĥ_P‖ / max(‖ŵ‖, ‖Σ c ĥ‖, w_scale),   ŵ = w − w⁰ − Σ c e_P

        Exactly equivalent to ‖K u + Bᵀ s − f‖ = 0 with u recovered from (s, w); used at the
        states whose displacement field is not computed (large models, intermediate events).
        """
        e = np.zeros(2 * self.m)
        h = np.zeros(2 * self.m)
        for name, c in factors.items():
            if c != 0.0:
                e += c * self.e[name]
                h += c * self.hhat[name]
        w_hat = w - self.system.w0 - e
        r = w_hat + self.G @ (s - self.d * w_hat) - h
        scale = max(np.abs(w_hat).max(initial=0), np.abs(h).max(initial=0), w_scale, 1e-300)
        return float(np.abs(r).max(initial=0) / scale)

    def null_modes(self, A: np.ndarray, lu, k: int = 3) -> np.ndarray:
        """Null vectors t (columns) of a singular scheme matrix: block inverse iteration on its
        LU, then the combinations of the block that A maps to (near) zero (σ ≤ 1e-6 ‖A‖)."""
        lu_m, piv = lu
        d = np.abs(np.diag(lu_m))
        tiny = 1e-14 * max(float(d.max(initial=0.0)), 1e-300)
        if np.any(d < tiny):  # exactly singular: lift the zero pivots to round-off level
            lu_m = lu_m.copy()
            j = np.flatnonzero(d < tiny)
            lu_m[j, j] = tiny
            lu = (lu_m, piv)
        n = A.shape[0]
        X = np.random.default_rng(0).standard_normal((n, min(k, n)))
        for _ in range(3):
            X = np.linalg.qr(sla.lu_solve(lu, X, check_finite=False))[0]
        _, sv, Vt = np.linalg.svd(A @ X, full_matrices=False)
        keep = sv <= 1e-6 * max(np.linalg.norm(A, 2), 1e-300)
        if not keep.any():
            keep[np.argmin(sv)] = True
        return X @ Vt[keep].T

    def null_mode(self, A: np.ndarray, lu) -> np.ndarray:
        """One null vector t of a singular scheme matrix."""
        return self.null_modes(A, lu, 1)[:, 0]

    def mode_displacement(self, t: np.ndarray) -> np.ndarray:
        """Displacement of a mechanism mode t of the condensed unknowns."""
        u = np.zeros(self.system.ndof)
        u[self.free] = -self.factor.solve(self.Bf.T @ t)
        return u


@dataclass
class _SchemeFactor:
    """A factorised working scheme: a base LU plus a low-rank (Woodbury) row update."""

    owner: SchemeSolver
    idx: np.ndarray
    V: np.ndarray | None
    Z: np.ndarray | None
    C_lu: tuple | None
    scale: np.ndarray
    rel: Relations

    def solve(self, hhat: np.ndarray, e: np.ndarray, r: np.ndarray):
        """Rates (s', w') of this scheme for load rate (ĥ, e) and relation right-hand side r."""
        o = self.owner
        cond = o.cond
        rel = self.rel
        m = cond.m
        kind = rel.kind
        rw = np.where(kind == FIXED, 1.0, np.where(kind == SPRING, -rel.stiff, 0.0))
        rw = np.where(np.isfinite(rw), rw, 0.0)
        rs = np.where(kind == FIXED, 0.0, 1.0)
        dh = cond.d * hhat
        rsh = rs * dh
        fr = np.flatnonzero(kind[:m] == FRICTION)
        rsh[fr] += -rel.sigma[fr] * o.cfe.friction[fr] * dh[m + fr]
        rhs = self.scale * (r - rw * (hhat + e) - rsh)
        y = sla.lu_solve(o.lu, rhs, check_finite=False)
        if self.V is not None:
            y = y - self.Z @ sla.lu_solve(self.C_lu, self.V @ y, check_finite=False)
        w_hat = hhat - cond.G @ y
        s = y + cond.d * w_hat
        return s, w_hat + e


class SchemeSolver:
    """Solves working schemes that differ from a factorised base scheme in a few rows.

    The dense scheme matrix A (2m × 2m) is LU-factorised for a base scheme; a scheme that
    differs in k rows is solved by the Woodbury identity with the cached columns A₀⁻¹ e_j
    (O(m² k) instead of O(m³)).  The base is refactorised when k exceeds ``max_rank``.  A
    singular capacitance matrix is confirmed by a full factorisation before a mechanism is
    reported.
    """

    def __init__(self, cond: Condensed, cfe, max_rank: int = 48):
        self.cond = cond
        self.cfe = cfe
        self.max_rank = max_rank
        self.base: Relations | None = None
        self.lu = None
        self.rows0: np.ndarray | None = None
        self.scale0: np.ndarray | None = None
        self.Zcache: dict[int, np.ndarray] = {}
        self.n_full = 0
        self.n_update = 0

    def _refactor(self, rel: Relations) -> None:
        n = 2 * self.cond.m
        A, scale = self.cond.scheme_rows(rel, self.cfe, np.arange(n))
        lu = _lu(A)
        rcond = sla.lapack.dgecon(lu[0], np.linalg.norm(A, 1), norm="1")[0] if n else 1.0
        self.n_full += 1
        self.cond.counters["scheme_factorizations"] = self.n_full
        if not rcond > RCOND_MECHANISM:
            raise MechanismError(A, lu)
        self.base = Relations(rel.kind.copy(), rel.stiff, rel.sigma.copy())
        self.lu, self.rows0, self.scale0 = lu, A, scale
        self.Zcache = {}

    def _z(self, j: int) -> np.ndarray:
        z = self.Zcache.get(j)
        if z is None:
            e = np.zeros(self.rows0.shape[0])
            e[j] = 1.0
            z = sla.lu_solve(self.lu, e, check_finite=False)
            self.Zcache[j] = z
        return z

    def factor(self, rel: Relations) -> _SchemeFactor:
        """Factor of the scheme ``rel`` (raises MechanismError if it is a mechanism)."""
        n = 2 * self.cond.m
        if self.base is None:
            self._refactor(rel)
        b = self.base
        m = self.cond.m
        diff = rel.kind != b.kind
        diff[:m] |= (rel.kind[:m] == FRICTION) & (rel.sigma != b.sigma)
        idx = np.flatnonzero(diff)
        if idx.size > self.max_rank:
            self._refactor(rel)
            idx = idx[:0]
        if idx.size == 0:
            return _SchemeFactor(self, idx, None, None, None, self.scale0, rel)
        rows, scale_new = self.cond.scheme_rows(rel, self.cfe, idx)
        V = rows - self.rows0[idx]
        Z = np.column_stack([self._z(int(j)) for j in idx])
        C = np.eye(idx.size) + V @ Z
        self.n_update += 1
        if np.linalg.cond(C) > 0.1 / RCOND_MECHANISM:
            # possibly singular: decide with a full factorisation of this scheme
            self._refactor(rel)
            return _SchemeFactor(self, idx[:0], None, None, None, self.scale0, rel)
        scale = self.scale0.copy()
        scale[idx] = scale_new
        del n
        return _SchemeFactor(self, idx, V, Z, _lu(C), scale, rel)
