"""Working schemes on the condensed contact unknowns: the dense scheme matrix, its LU with
low-rank (Woodbury) row updates, and the rates of a scheme.

With t = s − D ŵ and ŵ = ĥ − G t (see :mod:`stepcontact.solver.condensation`), the relations
of a working scheme (one per CFE component, :class:`stepcontact.contact.laws.Relations`)::

    FIXED:   w_j' = r_j                 rw = 1,    rs = 0
    SPRING:  s_j' − C_j w_j' = r_j      rw = −C_j, rs = 1
    FREE:    s_j' + c_j s_P' = r_j      rw = 0,    rs = 1   (P: the CFE's other component)

become one dense system A t' = b of size 2m with rows

    A_j = rs_j e_j − (rw_j + d_j rs_j) G_j + c_j (e_P − d_P G_P)
    b_j = r_j − rw_j (ĥ_j + e_j) − rs_j d_j ĥ_j − c_j d_P ĥ_P

A singular A is a working scheme that is a mechanism.

Row j of A and of b depends on the relation of component j alone, so two schemes differ only
in the rows of the components whose relation changed.  That is what the event loop exploits
(:class:`SchemeSolver`): one LU of a base scheme, and every later scheme as a low-rank row
update of it, with what the updates share cached on the base.
"""

from __future__ import annotations

import warnings
import weakref
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from stepcontact.contact.laws import FIXED, SPRING, Relations

#: a scheme matrix whose reciprocal condition number (rows equilibrated) is below this is
#: singular: a mechanism.  G carries a relative round-off of about eps·cond(K₀), so exact
#: mechanisms of slender structures show rcond of 1e-12..1e-11, well below any stable scheme.
RCOND_MECHANISM = 1e-10

#: a row update whose capacitance matrix C = I + V Z has a reciprocal condition number (1-norm,
#: LAPACK gecon) at or below this is not used: the scheme is factorised in full instead (and
#: becomes the base).  det A = det A₀ · det C, so a mechanism makes C singular to round-off
#: (rcond 1e-16..1e-15 in every example) while the updates of regular schemes stay above 1e-5
#: (7.5e-5 the smallest seen): the margin of four decades over ``RCOND_MECHANISM`` leaves every
#: doubtful scheme to the full factorisation and its gecon estimate, and bounds the round-off
#: that the capacitance solve adds to the base solve's by a factor cond(C) < 1e6.
RCOND_UPDATE = 1e-6

_getrs = sla.lapack.dgetrs
_gecon = sla.lapack.dgecon

# the solver that factorised the last singular scheme: ``lu`` of that scheme's (read-only) matrix
# returns its LU instead of factorising it again (the mechanism's analysis asks for it)
_last_singular = weakref.ref(OrderedDict())  # a dead reference until a scheme is singular


def lu(A: np.ndarray):
    """Dense LU; a singular matrix is a mechanism the caller detects from rcond, not a warning.
    The LU of the last singular scheme matrix (a read-only array from
    :meth:`SchemeSolver.dense`) is not computed twice."""
    solver = _last_singular()
    sing = solver._singular if solver is not None else None
    if sing is not None and sing[1] is A:
        return sing[3]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sla.LinAlgWarning)
        return sla.lu_factor(A, check_finite=False)


def rcond(f, A: np.ndarray) -> float:
    """Reciprocal condition number (1-norm) of A from its LU ``f``: LAPACK gecon, O(n²)."""
    if A.shape[0] == 0:
        return 1.0
    anorm = float(np.abs(A).sum(axis=0).max())
    if not np.isfinite(anorm):
        return 0.0
    return float(_gecon(f[0], anorm, norm="1")[0])


def lu_solve(f, b: np.ndarray) -> np.ndarray:
    """x = A⁻¹ b from the LU ``f`` of A (LAPACK getrs; a block of a few right-hand sides is
    solved column by column, which OpenBLAS does faster than one narrow block)."""
    if b.size == 0:
        return np.zeros(b.shape)
    if b.ndim == 2 and 1 < b.shape[1] <= 4:
        return np.column_stack([_getrs(f[0], f[1], b[:, j])[0] for j in range(b.shape[1])])
    return _getrs(f[0], f[1], b)[0]


class MechanismError(Exception):
    """The working scheme is a mechanism (singular condensed matrix ``A``; ``lu`` its LU)."""

    def __init__(self, A: np.ndarray, lu_, states: np.ndarray | None = None):
        self.A = A
        self.lu = lu_
        self.states = states
        super().__init__("working scheme is a mechanism")


def _coefficients(rel: Relations, idx=None):
    kind = rel.kind if idx is None else rel.kind[idx]
    stiff = rel.stiff if idx is None else rel.stiff[idx]
    rw = np.where(kind == FIXED, 1.0, np.where(kind == SPRING, -stiff, 0.0))
    rw = np.where(np.isfinite(rw), rw, 0.0)
    rs = np.where(kind == FIXED, 0.0, 1.0)
    return rw, rs


def partner(j: np.ndarray, m: int) -> np.ndarray:
    """The other component of the same CFE (tangential j ↔ normal m + j)."""
    return np.where(j < m, j + m, j - m)


def scheme_rows(G: np.ndarray, d: np.ndarray, rel: Relations, idx: np.ndarray):
    """Rows ``idx`` of A, each divided by its largest entry (stuck rows scale like 1/d, free
    rows like 1: equilibrated, the condition estimate measures a mechanism, not the units).
    Returns (rows (k, 2m), row scales (k,))."""
    m = G.shape[0] // 2
    rw, rs = _coefficients(rel, idx)
    rows = -(rw + d[idx] * rs)[:, None] * G[idx]
    rows[np.arange(len(idx)), idx] += rs
    c = rel.couple[idx]
    cp = np.flatnonzero(c != 0)
    if cp.size:
        P = partner(idx[cp], m)
        rows[cp, P] += c[cp]
        rows[cp] -= (d[P] * c[cp])[:, None] * G[P]
    scale = 1.0 / np.maximum(np.abs(rows).max(axis=1, initial=0.0), 1e-300)
    return rows * scale[:, None], scale


def scheme_rhs(d: np.ndarray, rel: Relations, hhat, e, r):
    """b (unscaled) of A t' = b for load rates (ĥ, e) and relation right-hand sides r (vectors
    or (2m, k) blocks)."""
    m = len(d) // 2
    rw, rs = _coefficients(rel)
    if np.ndim(r) == 2 or np.ndim(hhat) == 2:
        rw, rs, dd, c = rw[:, None], rs[:, None], d[:, None], rel.couple[:, None]
    else:
        dd, c = d, rel.couple
    dh = dd * hhat
    P = partner(np.arange(2 * m), m)
    return r - rw * (hhat + e) - rs * dh - c * dh[P]


def _load_rhs_rows(d: np.ndarray, rel: Relations, idx: np.ndarray, hhat, e) -> np.ndarray:
    """Rows ``idx`` of :func:`scheme_rhs` for load rates (ĥ, e) and r = 0 (vectors)."""
    rw, rs = _coefficients(rel, idx)
    P = partner(idx, len(d) // 2)
    return -rw * (hhat[idx] + e[idx]) - rs * d[idx] * hhat[idx] - rel.couple[idx] * d[P] * hhat[P]


class _Base:
    """A factorised base scheme and what the row updates of it share.

    For every row j that a scheme has changed so far (a *slot*): the column Z_j = A₀⁻¹ e_j,
    the row's difference V_j from the base for its latest relation (with the row's scale), and
    the products V Z over all slots, kept current as slots are added and rows change; per load
    rate (ĥ, e), the base solution y₀ = A₀⁻¹ b₀.  A scheme that differs in k rows then costs
    O(k n) to set up beyond its new columns (one solve each, reused while the base lives),
    and its load rates O(k n) plus one product with G."""

    def __init__(self, rel: Relations, A: np.ndarray, scale: np.ndarray, f, rc: float):
        n = A.shape[0]
        self.kind = rel.kind.copy()
        self.couple = rel.couple.copy()
        self.rel = Relations(self.kind, rel.stiff, self.couple)
        self.rows, self.scale, self.lu, self.rcond = A, scale, f, rc
        self.slot = np.full(n, -1, np.int64)
        self.k = 0
        cap = min(n, 32)
        self.Z = np.empty((n, cap), order="F")
        self.V = np.empty((cap, n))
        self.VZ = np.empty((cap, cap))
        self.vscale = np.empty(cap)
        self.vkind = np.empty(cap, rel.kind.dtype)
        self.vcouple = np.empty(cap)
        self.loads: OrderedDict[int, tuple] = OrderedDict()

    def _grow(self, need: int) -> None:
        cap = self.Z.shape[1]
        if need <= cap:
            return
        n = self.rows.shape[0]
        new = min(n, max(need, 2 * cap))
        k = self.k
        Z = np.empty((n, new), order="F")
        Z[:, :k] = self.Z[:, :k]
        self.Z = Z
        V = np.empty((new, n))
        V[:k] = self.V[:k]
        VZ = np.empty((new, new))
        VZ[:k, :k] = self.VZ[:k, :k]
        self.V, self.VZ = V, VZ
        for name in ("vscale", "vkind", "vcouple"):
            a = np.empty(new, getattr(self, name).dtype)
            a[:k] = getattr(self, name)[:k]
            setattr(self, name, a)

    def prepare(self, solver: SchemeSolver, rel: Relations, idx: np.ndarray) -> np.ndarray:
        """Slots of the rows ``idx`` (changed in ``rel``), with their columns, rows and the
        products V Z brought up to date."""
        new_rows = idx[self.slot[idx] < 0]
        k0 = self.k
        if new_rows.size:
            k1 = k0 + new_rows.size
            self._grow(k1)
            E = np.zeros((self.rows.shape[0], new_rows.size), order="F")
            E[new_rows, np.arange(new_rows.size)] = 1.0
            self.Z[:, k0:k1] = lu_solve(self.lu, E)
            self.slot[new_rows] = np.arange(k0, k1)
            self.k = k1
            solver.counters["scheme_columns"] += new_rows.size
        slots = self.slot[idx]
        k = self.k
        stale = ((slots >= k0) | (self.vkind[slots] != rel.kind[idx])
                 | (self.vcouple[slots] != rel.couple[idx]))
        rows_j, stale = idx[stale], slots[stale]
        if new_rows.size and k0:  # new columns of V Z (rows about to change are redone below)
            self.VZ[:k0, k0:k] = self.V[:k0] @ self.Z[:, k0:k]
        if stale.size:
            R, sc = scheme_rows(solver.G, solver.d, rel, rows_j)
            self.V[stale] = R - self.rows[rows_j]
            self.vscale[stale] = sc
            self.vkind[stale] = rel.kind[rows_j]
            self.vcouple[stale] = rel.couple[rows_j]
            self.VZ[stale, :k] = self.V[stale] @ self.Z[:, :k]
        return slots

    def load(self, solver: SchemeSolver, hhat: np.ndarray, e: np.ndarray):
        """(b₀, y₀ = A₀⁻¹ b₀) of the load rates (ĥ, e) on the base scheme (cached)."""
        key = hash((hhat.tobytes(), e.tobytes()))
        hit = self.loads.get(key)
        if hit is not None and np.array_equal(hit[0], hhat) and np.array_equal(hit[1], e):
            self.loads.move_to_end(key)
            return hit[2:]
        b0 = self.scale * scheme_rhs(solver.d, self.rel, hhat, e, 0.0)
        y0 = lu_solve(self.lu, b0)
        solver.counters["scheme_solves"] += 1
        out = (hhat.copy(), e.copy(), b0, y0)
        self.loads[key] = out
        if len(self.loads) > 4:
            self.loads.popitem(last=False)
        return out[2:]


@dataclass(eq=False)
class SchemeFactor:
    """A factorised working scheme: the base LU plus a low-rank (Woodbury) update of the rows
    ``idx`` (V: their differences from the base, Z = A₀⁻¹ E_idx, C = I + V Z)."""

    owner: SchemeSolver
    base: _Base
    idx: np.ndarray
    V: np.ndarray | None
    Z: np.ndarray | None
    C_lu: tuple | None
    scale: np.ndarray
    rel: Relations

    def solve(self, hhat, e, r):
        """Rates (s', w') of this scheme for load rates (ĥ, e) and relation right-hand sides
        r; each argument a vector (2m,) or a block (2m, k) (zeros broadcast)."""
        o = self.owner
        G, d = o.G, o.d
        b = scheme_rhs(d, self.rel, hhat, e, r)
        if b.ndim == 1:
            y = lu_solve(self.base.lu, self.scale * b)
            o.counters["scheme_solves"] += 1
        else:
            y = lu_solve(self.base.lu, self.scale[:, None] * b)
            o.counters["scheme_solves"] += b.shape[1]
        if self.V is not None:
            y = y - self.Z @ lu_solve(self.C_lu, self.V @ y)
        w_hat = hhat - G @ y
        dd = d if y.ndim == 1 else d[:, None]
        return y + dd * w_hat, w_hat + e

    def load_rates(self, hhat: np.ndarray, e: np.ndarray):
        """Rates (s', w') of this scheme for the load rates (ĥ, e) (vectors) and r = 0: from
        the base's cached solution of the same load, updated in the changed rows,

            y = y₀ + Z C⁻¹ (δ − V y₀)

        (δ: the change of the scaled right-hand side in those rows), O(k n); then ŵ = ĥ − G y.
        (G y is formed afresh: updating a cached G y₀ the same way cancels where ŵ ≪ G y₀ and
        moves events by round-off 10× larger.)"""
        o = self.owner
        d = o.d
        hhat = np.broadcast_to(np.asarray(hhat, float), d.shape)
        e = np.broadcast_to(np.asarray(e, float), d.shape)
        b0, y0 = self.base.load(o, hhat, e)
        if self.V is None:
            y = y0
        else:
            idx = self.idx
            delta = self.scale[idx] * _load_rhs_rows(d, self.rel, idx, hhat, e) - b0[idx]
            g = lu_solve(self.C_lu, delta - self.V @ y0)
            y = y0 + self.Z @ g
        w_hat = hhat - o.G @ y
        return y + d * w_hat, w_hat + e


class SchemeSolver:
    """Solves working schemes that differ from a factorised base scheme in a few rows.

    The dense scheme matrix A (2m × 2m) is LU-factorised for a base scheme, its condition
    estimated from the LU (LAPACK gecon, O(n²)): rcond ≤ ``RCOND_MECHANISM`` is a mechanism.
    A scheme that differs from the base in k rows is solved by the Woodbury identity with the
    columns A₀⁻¹ e_j of its changed rows, cached on the base as rows change (one solve per row
    that changes while the base lives), so that a new scheme costs O(n k) beyond its new
    columns, and its load rates O(n k) plus one product with G from the base's solution of the
    same load (:class:`_Base`).  The base is refactorised with the current scheme

    * when k exceeds ``max_rank``, default max(48, n/10): the work that grows with k (O(n k)
      products and copies per scheme, O(k³) for C) is then about what a refactorisation saves
      (an LU of n = 600 takes 24 ms single-threaded, an update 2–3 ms + 0.02 ms per changed
      row), the break-even of the slab and block benchmarks, m ≈ 150–300;
    * when the update's capacitance matrix C = I + V Z is ill-conditioned
      (rcond(C) ≤ ``RCOND_UPDATE``): accuracy, and the decision on a possible mechanism, go to
      the full factorisation.

    The factors of the last few schemes are kept, so a scheme met again (the rate problem, then
    the correction at the same point) is not factorised twice; a singular scheme is factorised
    once (its matrix and LU serve the analysis of the mechanism: :meth:`dense`, :func:`lu`).
    """

    def __init__(self, G: np.ndarray, d: np.ndarray, max_rank: int | None = None,
                 cache: int = 8):
        self.G = G
        self.d = d
        self.max_rank = max(G.shape[0] // 10, 48) if max_rank is None else max_rank
        self.base: _Base | None = None
        self._cache: OrderedDict[bytes, SchemeFactor] = OrderedDict()
        self._cache_size = cache
        self._singular: tuple | None = None
        self.counters = {"scheme_factorizations": 0, "scheme_updates": 0, "scheme_columns": 0,
                         "scheme_solves": 0}

    @property
    def n(self) -> int:
        return self.G.shape[0]

    def _refactor(self, rel: Relations) -> None:
        global _last_singular
        key = rel.key()
        A, scale = scheme_rows(self.G, self.d, rel, np.arange(self.n))
        f = lu(A)
        rc = rcond(f, A)
        self.counters["scheme_factorizations"] += 1
        if not rc > RCOND_MECHANISM:
            A.flags.writeable = False
            scale.flags.writeable = False
            self._singular = (key, A, scale, f)
            _last_singular = weakref.ref(self)
            raise MechanismError(A, f)
        self.base = _Base(rel, A, scale, f, rc)
        self._cache.clear()

    def factor(self, rel: Relations) -> SchemeFactor:
        """Factor of the scheme ``rel`` (raises :class:`MechanismError` if it is singular)."""
        key = rel.key()
        hit = self._cache.get(key)
        if hit is not None:
            self._cache.move_to_end(key)
            return hit
        fac = self._factor(rel)
        self._cache[key] = fac
        if len(self._cache) > self._cache_size:
            self._cache.popitem(last=False)
        return fac

    def _plain(self, rel: Relations) -> SchemeFactor:
        b = self.base
        return SchemeFactor(self, b, np.zeros(0, np.int64), None, None, None, b.scale, rel)

    def _factor(self, rel: Relations) -> SchemeFactor:
        if self._singular is not None and self._singular[0] == rel.key():
            raise MechanismError(self._singular[1], self._singular[3])
        if self.base is None:
            self._refactor(rel)
        b = self.base
        idx = np.flatnonzero((rel.kind != b.kind) | (rel.couple != b.couple))
        if idx.size > self.max_rank:
            self._refactor(rel)
            return self._plain(rel)
        if idx.size == 0:
            return self._plain(rel)
        slots = b.prepare(self, rel, idx)
        C = b.VZ[np.ix_(slots, slots)]
        C[np.diag_indices_from(C)] += 1.0
        C_lu = lu(C)
        self.counters["scheme_updates"] += 1
        if not rcond(C_lu, C) > RCOND_UPDATE:
            # ill-conditioned update, possibly singular: a full factorisation of this scheme
            self._refactor(rel)
            return self._plain(rel)
        scale = b.scale.copy()
        scale[idx] = b.vscale[slots]
        return SchemeFactor(self, b, idx, b.V[slots], b.Z[:, slots], C_lu, scale, rel)

    def dense(self, rel: Relations) -> tuple[np.ndarray, np.ndarray]:
        """The full equilibrated scheme matrix and its row scales (for tests and mechanisms;
        those of the last singular scheme are the read-only arrays that were factorised)."""
        if self._singular is not None and self._singular[0] == rel.key():
            return self._singular[1], self._singular[2]
        return scheme_rows(self.G, self.d, rel, np.arange(self.n))


__all__ = ["RCOND_MECHANISM", "RCOND_UPDATE", "MechanismError", "SchemeFactor", "SchemeSolver",
           "lu", "lu_solve", "rcond", "scheme_rhs", "scheme_rows"]
