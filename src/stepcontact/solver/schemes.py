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
"""

from __future__ import annotations

import warnings
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from stepcontact.contact.laws import FIXED, SPRING, Relations

#: a scheme matrix whose reciprocal condition number (rows equilibrated) is below this is
#: singular: a mechanism.  G carries a relative round-off of about eps·cond(K₀), so exact
#: mechanisms of slender structures show rcond of 1e-12..1e-11, well below any stable scheme.
RCOND_MECHANISM = 1e-10


def lu(A: np.ndarray):
    """Dense LU; a singular matrix is a mechanism the caller detects from rcond, not a warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sla.LinAlgWarning)
        return sla.lu_factor(A, check_finite=False)


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


@dataclass
class SchemeFactor:
    """A factorised working scheme: the base LU plus a low-rank (Woodbury) row update."""

    owner: SchemeSolver
    lu0: tuple
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
        sc = self.scale if b.ndim == 1 else self.scale[:, None]
        y = sla.lu_solve(self.lu0, sc * b, check_finite=False)
        if self.V is not None:
            y = y - self.Z @ sla.lu_solve(self.C_lu, self.V @ y, check_finite=False)
        w_hat = hhat - G @ y
        dd = d if y.ndim == 1 else d[:, None]
        return y + dd * w_hat, w_hat + e


class SchemeSolver:
    """Solves working schemes that differ from a factorised base scheme in a few rows.

    The dense scheme matrix A (2m × 2m) is LU-factorised for a base scheme; a scheme that
    differs in k rows is solved by the Woodbury identity with the cached columns A₀⁻¹ e_j
    (O(m² k) instead of O(m³)).  The base is refactorised when k exceeds ``max_rank``.  A
    possibly singular capacitance matrix is confirmed by a full factorisation before a
    mechanism is reported.  The factors of the last few schemes are kept, so a scheme met
    again (the rate problem, then the correction at the same point) is not factorised twice.
    """

    def __init__(self, G: np.ndarray, d: np.ndarray, max_rank: int = 48, cache: int = 8):
        self.G = G
        self.d = d
        self.max_rank = max_rank
        self.base: Relations | None = None
        self.lu = None
        self.rows0: np.ndarray | None = None
        self.scale0: np.ndarray | None = None
        self.Zcache: dict[int, np.ndarray] = {}
        self._cache: OrderedDict[bytes, SchemeFactor] = OrderedDict()
        self._cache_size = cache
        self.counters = {"scheme_factorizations": 0, "scheme_updates": 0}

    @property
    def n(self) -> int:
        return self.G.shape[0]

    def _refactor(self, rel: Relations) -> None:
        n = self.n
        A, scale = scheme_rows(self.G, self.d, rel, np.arange(n))
        f = lu(A)
        rcond = sla.lapack.dgecon(f[0], np.linalg.norm(A, 1), norm="1")[0] if n else 1.0
        self.counters["scheme_factorizations"] += 1
        if not rcond > RCOND_MECHANISM:
            raise MechanismError(A, f)
        self.base = Relations(rel.kind.copy(), rel.stiff, rel.couple.copy())
        self.lu, self.rows0, self.scale0 = f, A, scale
        self.Zcache = {}
        self._cache.clear()

    def _z(self, idx: np.ndarray) -> np.ndarray:
        missing = [int(j) for j in idx if int(j) not in self.Zcache]
        if missing:
            E = np.zeros((self.n, len(missing)))
            E[missing, np.arange(len(missing))] = 1.0
            Zm = sla.lu_solve(self.lu, E, check_finite=False)
            for i, j in enumerate(missing):
                self.Zcache[j] = Zm[:, i]
        return np.column_stack([self.Zcache[int(j)] for j in idx])

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

    def _factor(self, rel: Relations) -> SchemeFactor:
        if self.base is None:
            self._refactor(rel)
        b = self.base
        idx = np.flatnonzero((rel.kind != b.kind) | (rel.couple != b.couple))
        if idx.size > self.max_rank:
            self._refactor(rel)
            idx = idx[:0]
        if idx.size == 0:
            return SchemeFactor(self, self.lu, None, None, None, self.scale0, rel)
        rows, scale_new = scheme_rows(self.G, self.d, rel, idx)
        V = rows - self.rows0[idx]
        Z = self._z(idx)
        C = np.eye(idx.size) + V @ Z
        self.counters["scheme_updates"] += 1
        C_lu = lu(C)
        rc = sla.lapack.dgecon(C_lu[0], np.linalg.norm(C, 1), norm="1")[0]
        if not rc > 10 * RCOND_MECHANISM:
            # possibly singular: decide with a full factorisation of this scheme
            self._refactor(rel)
            return SchemeFactor(self, self.lu, None, None, None, self.scale0, rel)
        scale = self.scale0.copy()
        scale[idx] = scale_new
        return SchemeFactor(self, self.lu, V, Z, C_lu, scale, rel)

    def dense(self, rel: Relations) -> tuple[np.ndarray, np.ndarray]:
        """The full equilibrated scheme matrix and its row scales (for tests and mechanisms)."""
        return scheme_rows(self.G, self.d, rel, np.arange(self.n))


__all__ = ["RCOND_MECHANISM", "MechanismError", "SchemeFactor", "SchemeSolver", "scheme_rhs",
           "scheme_rows"]
