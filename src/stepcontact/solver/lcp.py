"""Linear complementarity problems: Lemke's method.

Find z ≥ 0 with w = M z + q ≥ 0 and zᵀw = 0.  The static solver uses it for the rate problem
of a new working scheme when the least-index principal pivoting over CFE states cycles
(matrices that are not P-matrices: large friction coefficients, several CFEs touching at once).
Lemke's method with the covering vector d = 1 and a lexicographic ratio test terminates for any
M; it finds a solution whenever M is copositive-plus (and in practice for the rate problems of
frictional contact), and otherwise ends on a secondary ray, which is reported, not guessed over.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class LCPResult:
    """Outcome of :func:`lemke`: z, w = M z + q, whether it solved, pivots, a message.

    On a secondary ray, ``ray`` marks the z variables that grow along it (the basic ones and
    the entering one): for a rate problem this is the scheme that is a mechanism.
    """

    z: np.ndarray
    w: np.ndarray
    solved: bool
    pivots: int
    message: str
    ray: np.ndarray | None = None


def _lex_min_row(T: np.ndarray, rows: np.ndarray, col: np.ndarray, n: int) -> int:
    """Lexicographic minimum ratio test among ``rows`` (degeneracy-proof tie breaking).

    Compares rows of [q, B⁻¹] divided by the pivot column entry; B⁻¹ sits in the columns of the
    initial basis (the w variables, columns 0..n−1).
    """
    cand = rows
    keys = np.column_stack([T[cand, -1], T[cand, :n]]) / col[cand, None]
    for k in range(keys.shape[1]):
        v = keys[:, k]
        best = v.min()
        scale = max(np.abs(v).max(), 1.0)
        keep = v <= best + 1e-12 * scale
        cand, keys = cand[keep], keys[keep]
        if len(cand) == 1:
            break
    return int(cand[0])


def lemke(M: np.ndarray, q: np.ndarray, max_pivots: int | None = None,
          tol: float = 1e-12) -> LCPResult:
    """Solve the LCP (M, q) by Lemke's complementary pivoting (dense tableau).

    Variables are numbered w_i = i, z_i = n + i, the artificial z₀ = 2n.  Columns of M are
    scaled to unit largest entry first (a positive diagonal scaling keeps complementarity).
    """
    M = np.asarray(M, dtype=float)
    q = np.asarray(q, dtype=float)
    n = len(q)
    if n == 0 or np.all(q >= 0):
        return LCPResult(np.zeros(n), q.copy(), True, 0, "trivial solution z = 0")
    cs = np.abs(M).max(axis=0)
    cs = np.where(cs > 0, 1.0 / cs, 1.0)
    Ms = M * cs[None, :]
    qs_scale = max(np.abs(q).max(), 1e-300)
    # tableau: w − Ms z − d z0 = q   ->  [I, −Ms, −d | q]
    T = np.zeros((n, 2 * n + 2))
    T[:, :n] = np.eye(n)
    T[:, n:2 * n] = -Ms
    T[:, 2 * n] = -1.0
    T[:, -1] = q / qs_scale
    basis = np.arange(n)

    def pivot(r: int, c: int) -> None:
        T[r] /= T[r, c]
        others = np.arange(n) != r
        T[others] -= np.outer(T[others, c], T[r])
        basis[r] = c

    r = int(np.argmin(T[:, -1]))
    pivot(r, 2 * n)
    leaving = r  # w_r left the basis
    entering = n + leaving
    max_pivots = max_pivots or 50 * (n + 1) ** 2
    for k in range(1, max_pivots + 1):
        col = T[:, entering]
        rows = np.flatnonzero(col > tol * max(np.abs(col).max(), 1.0))
        if rows.size == 0:
            ray = np.zeros(n, dtype=bool)
            zb = (basis >= n) & (basis < 2 * n)
            ray[basis[zb] - n] = True
            if n <= entering < 2 * n:
                ray[entering - n] = True
            return LCPResult(np.zeros(n), q.copy(), False, k,
                             "Lemke's method ended on a secondary ray (no solution found)", ray)
        ratios = T[rows, -1] / col[rows]
        best = ratios.min()
        ties = rows[ratios <= best + 1e-12 * max(abs(best), 1.0)]
        z0_rows = ties[basis[ties] == 2 * n]
        r = int(z0_rows[0]) if z0_rows.size else _lex_min_row(T, ties, col, n)
        leaving_var = int(basis[r])
        pivot(r, entering)
        if leaving_var == 2 * n:
            z = np.zeros(n)
            zb = basis >= n
            z[basis[zb] - n] = np.maximum(T[zb, -1], 0.0)
            z = z * cs * qs_scale
            return LCPResult(z, M @ z + q, True, k, "solved")
        entering = leaving_var + n if leaving_var < n else leaving_var - n
    return LCPResult(np.zeros(n), q.copy(), False, max_pivots, "pivot budget exhausted")


__all__ = ["LCPResult", "lemke"]
