"""Linear complementarity problems: principal pivoting, Lemke's method, enumeration.

Find z ≥ 0 with w = M z + q ≥ 0 and zᵀw = 0.  The rate problem at a degenerate point of the
load path (CFEs at their limits) is such an LCP (:mod:`stepcontact.solver.rate`):

* :func:`principal_pivoting` — Murty's least-index method from a given starting basis (the
  current working scheme); it terminates and is unique-answer for P-matrices (frictionless
  contact, small friction), and reports cycling otherwise;
* :func:`lemke` — Lemke's method with the covering vector d = 1 and a lexicographic ratio
  test, which terminates for any M: it finds a solution whenever M is copositive-plus (and in
  practice for the rate problems of frictional contact), and otherwise ends on a secondary
  ray, which is reported, not guessed over;
* :func:`enumerate_solutions` — every solution of a small LCP (batched over complementary
  bases), to tell whether the rate problem has one answer or several.
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


def _lex_min_row(T: np.ndarray, rows: np.ndarray, col: np.ndarray, n: int,
                 tol: float = 1e-12) -> int:
    """Lexicographic minimum ratio test among ``rows`` (degeneracy-proof tie breaking).

    The row r chosen minimises, lexicographically, the row [q̄_r, (B⁻¹)_r] / col_r of the
    current tableau (B⁻¹ sits in the columns of the initial basis, the w variables, columns
    0..n−1).  The rows of B⁻¹ are linearly independent, so exactly one row is the minimum:
    every basis met keeps [q̄, B⁻¹] lexicographically positive row by row, the lexicographic
    value of the objective row strictly increases, and no basis can repeat — Lemke's method
    cannot cycle at a degenerate point (ties q̄_i/col_i equal, e.g. several q̄_i = 0), however
    many there are (Cottle, Pang & Stone, *The Linear Complementarity Problem*, §4.9).

    Two keys count as equal within ``tol`` times the largest of that key among the candidates
    (round-off of the tableau), so a tie broken in round-off is broken by the next column.
    """
    cand = np.asarray(rows)
    keys = np.column_stack([T[cand, -1], T[cand, :n]]) / col[cand, None]
    for k in range(keys.shape[1]):
        v = keys[:, k]
        best = v.min()
        keep = v <= best + tol * max(np.abs(v).max(), np.finfo(float).tiny)
        cand, keys = cand[keep], keys[keep]
        if len(cand) == 1:
            break
    return int(cand[0])


def _first_row(q: np.ndarray, tol: float = 1e-12) -> int:
    """The row the artificial z₀ enters in (covering vector d = 1): the most negative q_i,
    ties broken lexicographically.  After that pivot row i holds [q_i − q_r, e_i − e_r], which
    is lexicographically positive for every tied i only if r is the *largest* tied index."""
    qmin = q.min()
    ties = np.flatnonzero(q <= qmin + tol * max(abs(qmin), np.finfo(float).tiny))
    return int(ties[-1])


def lemke(M: np.ndarray, q: np.ndarray, max_pivots: int | None = None,
          tol: float = 1e-12) -> LCPResult:
    """Solve the LCP (M, q) by Lemke's complementary pivoting (dense tableau), with the
    lexicographic minimum-ratio test (:func:`_lex_min_row`, :func:`_first_row`): it never
    cycles at a degenerate point, and ends in a solution (always when M is copositive-plus and
    the LCP is feasible) or on a secondary ray, which is reported with the variables growing
    along it.

    Variables are numbered w_i = i, z_i = n + i, the artificial z₀ = 2n.  Columns of M are
    scaled to unit largest entry first (a positive diagonal scaling keeps complementarity).
    When z₀ ties in the ratio test it leaves (that pivot ends the method with a solution).
    """
    M = np.asarray(M, dtype=float)
    q = np.asarray(q, dtype=float)
    n = len(q)
    if n == 0 or np.all(q >= 0):
        return LCPResult(np.zeros(n), q.copy(), True, 0, "trivial solution z = 0")
    cs = np.abs(M).max(axis=0)
    cs = np.divide(1.0, cs, out=np.ones_like(cs), where=cs > 0)
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

    r = _first_row(T[:, -1], tol)
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
        ties = rows[ratios <= best + tol * max(np.abs(ratios).max(), np.finfo(float).tiny)]
        z0_rows = ties[basis[ties] == 2 * n]
        r = int(z0_rows[0]) if z0_rows.size else _lex_min_row(T, rows, col, n, tol)
        leaving_var = int(basis[r])
        pivot(r, entering)
        if leaving_var == 2 * n:
            z = np.zeros(n)
            zb = basis >= n
            z[basis[zb] - n] = np.maximum(T[zb, -1], 0.0)
            z = z * cs * qs_scale
            w = M @ z + q
            # a tableau carried through nearly singular pivots can end on a "solution" that
            # is not one: it is checked against M and q before it is reported as solved
            scale = max(qs_scale, float(np.abs(M).max(initial=0.0) * np.abs(z).max(initial=0.0)))
            if w.min(initial=0.0) < -1e-7 * scale or np.abs(z * w).max(initial=0.0) > (
                    1e-7 * scale * max(np.abs(z).max(initial=0.0), 1e-300)):
                return LCPResult(np.zeros(n), q.copy(), False, k,
                                 "Lemke's method ended on a point that fails w = Mz + q ≥ 0 "
                                 "(nearly singular pivots)")
            return LCPResult(z, w, True, k, "solved")
        entering = leaving_var + n if leaving_var < n else leaving_var - n
    return LCPResult(np.zeros(n), q.copy(), False, max_pivots, "pivot budget exhausted")


def principal_pivoting(M: np.ndarray, q: np.ndarray, start: np.ndarray | None = None,
                       max_pivots: int | None = None, tol: float = 1e-12) -> LCPResult:
    """Murty's least-index principal pivoting from the basis ``start`` (boolean: z_i basic).

    Each pass solves M_αα z_α = −q_α, w_ᾱ = q_ᾱ + M_ᾱα z_α and flips the least index whose z
    or w is negative.  Terminates for P-matrices; a repeated basis (cycling) or a singular
    principal block is reported as not solved.
    """
    M = np.asarray(M, dtype=float)
    q = np.asarray(q, dtype=float)
    n = len(q)
    alpha = np.zeros(n, bool) if start is None else np.asarray(start, bool).copy()
    scale = max(np.abs(q).max(initial=0.0), 1e-300)
    seen: set[bytes] = set()
    max_pivots = max_pivots or 20 * (n + 1)
    for k in range(max_pivots):
        key = alpha.tobytes()
        if key in seen:
            return LCPResult(np.zeros(n), q.copy(), False, k, "principal pivoting cycles")
        seen.add(key)
        z = np.zeros(n)
        a = np.flatnonzero(alpha)
        if a.size:
            try:
                z[a] = np.linalg.solve(M[np.ix_(a, a)], -q[a])
            except np.linalg.LinAlgError:
                return LCPResult(np.zeros(n), q.copy(), False, k,
                                 "principal pivoting met a singular principal block")
        w = M @ z + q
        zs = max(np.abs(z).max(initial=0.0) * np.abs(M).max(initial=0.0), scale)
        bad = np.flatnonzero((alpha & (z < -tol * zs / max(np.abs(M).max(initial=0), 1e-300)))
                             | (~alpha & (w < -tol * zs)))
        if bad.size == 0:
            z = np.where(alpha, np.maximum(z, 0.0), 0.0)
            return LCPResult(z, np.where(alpha, 0.0, w), True, k, "solved")
        alpha[bad[0]] = ~alpha[bad[0]]
    return LCPResult(np.zeros(n), q.copy(), False, max_pivots, "pivot budget exhausted")


class BasisGroups:
    """Complementary bases (a boolean array (n_bases, n)) grouped by their size, in the
    order :func:`enumerate_solutions` tries them (size ascending, the given order within a
    size), with the gather indices of each group's principal blocks of an n × n M: formed
    once per set of bases (a rate problem's bases depend only on its pattern of variables):
    ``parts`` holds per size k (start, stop) of its rows, the basic variables ``idx``
    (n_k, k) and their entries in the raveled (n_bases, n) array of solutions."""

    __slots__ = ("bases", "order", "parts")

    def __init__(self, bases: np.ndarray):
        bases = np.asarray(bases, bool)
        n = bases.shape[1]
        sizes = bases.sum(axis=1)
        order = np.argsort(sizes, kind="stable")
        self.order = order
        self.bases = bases[order]
        self.bases.setflags(write=False)
        parts = []
        start = 0
        for k in np.unique(sizes):
            nb = int(np.count_nonzero(sizes == k))
            stop = start + nb
            if k:
                idx = np.nonzero(self.bases[start:stop])[1].reshape(nb, k)
                rows = np.arange(start, stop)[:, None] * n + idx  # Z[row, idx], raveled
                parts.append((int(k), start, stop, idx, rows))
            start = stop
        self.parts = tuple(parts)


def enumerate_solutions(M: np.ndarray, q: np.ndarray, bases, tol: float = 1e-9
                        ) -> list[np.ndarray]:
    """Every solution z of the LCP (M, q) among the complementary bases ``bases`` (a boolean
    array (n_bases, n): z_i basic; or its :class:`BasisGroups`), batched by basis size.  A
    solution is kept when z ≥ −tol·scale and w ≥ −tol·scale; returns the list of z (solutions
    may repeat when the LCP is degenerate: the caller compares what they stand for), by basis
    size, then in the order of ``bases``."""
    groups = bases if isinstance(bases, BasisGroups) else BasisGroups(bases)
    M = np.asarray(M, dtype=float)
    q = np.asarray(q, dtype=float)
    n = len(q)
    mscale = max(float(np.abs(M).max(initial=0.0)), 1e-300)
    qscale = max(float(np.abs(q).max(initial=0.0)), 1e-300)
    B = groups.bases
    Z = np.zeros((len(B), n))
    valid = np.ones(len(B), bool)
    Mr, Zr = M.ravel(), Z.reshape(-1)
    for k, start, stop, idx, rows in groups.parts:
        Mk = Mr.take(idx[:, :, None] * n + idx[:, None, :])  # the blocks M[idx, idx]
        ok = np.abs(np.linalg.det(Mk)) > 1e-12 * mscale ** k
        if not ok.all():
            valid[start:stop] = ok
            if not ok.any():
                continue
            idx, Mk, rows = idx[ok], Mk[ok], rows[ok]
        zk = np.linalg.solve(Mk, -q.take(idx)[..., None])[..., 0]
        Zr[rows.ravel()] = zk.ravel()
    W = Z @ M.T + q
    zs = np.maximum(np.abs(Z).max(axis=1) * mscale, qscale)
    good = valid & np.all(Z >= -tol * zs[:, None] / mscale, axis=1) & np.all(
        B | (W >= -tol * zs[:, None]), axis=1)
    return list(np.maximum(Z[good], 0.0))


__all__ = ["BasisGroups", "LCPResult", "enumerate_solutions", "lemke", "principal_pivoting"]
