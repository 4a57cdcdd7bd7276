"""Working schemes on the condensed contact unknowns: the dense scheme matrix, its explicit
inverse updated by low-rank (Sherman–Morrison–Woodbury) row updates, and the rates of a scheme.

With t = s − D ŵ and ŵ = ĥ − G t (see :mod:`stepcontact.solver.condensation`), the relations
of a working scheme (per CFE a small block, :class:`stepcontact.contact.laws.Relations`: row j,
component i of CFE k, reads Σ_c S_jc s_c' + W_jc w_c' = r_j over the CFE's components c)
become one dense system A t' = b of size n = m (1 + n_t) with rows

    A_j = Σ_c S_jc e_c − Σ_c (S_jc d_c + W_jc) G_c
    b_j = r_j − Σ_c (W_jc (ĥ_c + e_c) + S_jc d_c ĥ_c)

In 2D the kinds of a row are FIXED (w_j' = r_j: S = 0, W_jj = 1), SPRING (s_j' − C_j w_j' = r_j:
S_jj = 1, W_jj = −C_j) and FREE (s_j' + c_j s_P' = r_j: S_jj = 1, S_jP = c_j, P the CFE's
other component).  The diagonal (rs_j = S_jj, rw_j = W_jj) is formed for every row in one pass
over G; only the rows with a coupling (an off-diagonal entry of their block) take a second
product with the coupled rows of G.  A singular A is a working scheme that is a mechanism.

Row j of A and of b depends on the relation row of component j alone (its block row S_j·,
W_j·), so two schemes differ only in the rows of the components whose relation changed: an
event changes the rows of the CFEs that fired (r = 2 in 2D for one CFE, more at a simultaneous
event).  That is what the event loop exploits (:class:`SchemeSolver`).  It keeps the explicit
inverse X = A₀⁻¹ of a *base* scheme (from one LU, LAPACK getrf + getri); a scheme A = A₀ + E V
that differs from it in the k rows E = I[:, idx] (V: the rows' differences) is, by the
Sherman–Morrison–Woodbury identity,

    A⁻¹ = X − Z C⁻¹ V X,    Z = X E (k columns of X),    C = I_k + V Z,    det A = det A₀ det C,

so that its load rates, from the base's solution y₀ = X b₀ of the same load, are

    y = A⁻¹ b = y₀ + Z C⁻¹ (δ − V y₀)      (δ = b_idx − b₀_idx),

O(k n), and ŵ' = ĥ − G y one product with G (BLAS symv, half a pass, for a symmetric G): per
event one read of G and O(k n).  A singular (or doubtful) C — rcond(C) ≤ ``RCOND_UPDATE`` —
sends the scheme to a full LU, whose condition estimate decides whether it is a mechanism.
A scheme may be *committed*: X ← X − Z (C⁻¹ (V X)), a k × n by n × n product and a rank-k
update (BLAS gemm, in place), two passes over X for k rows at once, and it becomes the base.
Whether a scheme is updated, committed or inverted afresh is decided by cost (weighted flops,
:meth:`SchemeSolver._commit_now`): the updates of a base are charged to it and a scheme is
committed once they have cost as much as its commit (rent or buy), and inverted afresh when
that is cheaper than its update and commit (k rows near n).  Solutions of the same load are
updated in O(k n) between commits.

A solve through an explicit inverse is not backward stable as an LU solve is: y = X b has the
forward error of an LU solve, but its residual b − A y may be as large as eps ‖A‖ ‖A⁻¹‖ ‖b‖
instead of eps ‖A‖ ‖y‖, and the force rates s' = y + D (ĥ − G y) are a difference of large
terms wherever the contacts are far stiffer than the structure, so they inherit the residual,
not the forward error.  Every float64 solve therefore has its backward error η = ‖b − A y‖∞ /
(‖A‖∞ ‖y‖∞ + ‖b‖∞) measured in O(n) from the G y it forms anyway; a solve with η above
``ETA_ACCEPT`` is refined with the same inverse (one more pass over X and over G), and an
inverse that the commits have moved away from its matrix — η beyond ``BACKWARD_TOL``, or a
refinement that stalls — is inverted afresh (:meth:`SchemeFactor._stable`).

For large interfaces the dense work runs in float32 (G held as D G − I, see
:func:`scheme_rows`), and every solve is refined to float64 accuracy against the exact operator
(G t by the float64 sparse factorisation): :meth:`SchemeFactor._refine`; a float32 scheme is a
mechanism only if the exact operator confirms it (:meth:`SchemeSolver._regular_after_all`).
"""

from __future__ import annotations

import warnings
import weakref
from collections import OrderedDict
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from stepcontact.contact.laws import Relations

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

#: the same two thresholds for a scheme matrix held in float32 (``precision="float32"``): its
#: entries carry a relative round-off of 6e-8, so a mechanism shows rcond of about 1e-7..1e-6.
#: A float32 scheme at or below RCOND_MECHANISM_F32 is a mechanism only if the exact operator
#: confirms it (:meth:`SchemeSolver._regular_after_all`); an update is refactorised (whose
#: rcond then decides) at or below RCOND_UPDATE_F32, or when its solves do not refine (updates
#: of regular schemes reach rcond 1e-6 on the 5 001-CFE benchmark: a higher threshold would
#: refactorise at nearly every event).
RCOND_MECHANISM_F32 = 1e-5
RCOND_UPDATE_F32 = 1e-7

#: iterative refinement of the float32 schemes against the exact float64 operator: at most
#: this many corrections; converged when the scaled residual is below REFINE_TOL of the
#: right-hand side's (or the solution's) size; a residual still above REFINE_ACCEPT when the
#: corrections stop shrinking is an error (the scheme is too ill-conditioned for float32)
REFINE_MAX = 12
REFINE_TOL = 4e-15
REFINE_ACCEPT = 1e-9

#: the normwise backward error η = ‖b − A y‖∞ / (‖A‖∞ ‖y‖∞ + ‖b‖∞) of the first float64 solve
#: on an inverse that has taken rank-k updates may grow to the larger of BACKWARD_TOL and
#: BACKWARD_GROWTH times that of the latest inverse fresh from an LU before the scheme is
#: inverted afresh (:meth:`SchemeFactor._stable`; below it the solve is refined).
BACKWARD_TOL = 1e-13
BACKWARD_GROWTH = 64.0

#: a float64 solve through the inverse is accepted when its backward error η is at most
#: ETA_ACCEPT, else refined with the same inverse (at most REFINE_MAX_F64 corrections;
#: :meth:`SchemeFactor._stable`).  Measured: the inverse, through its commits, gives η of
#: 3e-16..9e-15 on the slab benchmark (k = 4, 444 solves, median 1.1e-15); a fresh inverse
#: of the bonded block's schemes (a stiff block on compliant layers, cond(A) about 2e7,
#: test_bonded_joints.py) 3e-12 on some loads where an LU solve gives 4e-17..2e-16 — which
#: moved the force rates by 1.6e-5 relative (LU: 5e-10) — and one refinement step 2e-16
ETA_ACCEPT = 1e-14
REFINE_MAX_F64 = 3

#: the rank of a Woodbury update beyond which its scheme is committed into the base's inverse
#: when a solver is given ``max_rank`` (a fixed rule, for tests); by default the rank policy
#: is cost-based (:meth:`SchemeSolver._commit_now`)
MAX_RANK = 48

#: the cost model of the rank policy, in flops weighted by the rate they run at relative to
#: a BLAS-3 product (dgemm), measured single-threaded on the development machine (n = 602 …
#: 1 587): dgemm 48 GF/s (a commit, 4 k n² flops), getrf + getri 27 GF/s (an inversion,
#: 2 n³ flops: weight W_INVERT), dgemv and the other O(k n) passes of an update 6 GF/s
#: (weight W_PASS), a k × k LU (the capacitance) 16 GF/s at k = 325 (weight W_SMALL_LU)
W_INVERT = 1.8
W_PASS = 8.0
W_SMALL_LU = 3.0
#: a capacitance LU is extended by bordering (:func:`_border_lu`) from one of at least this
#: many rows; each base keeps its latest BORDER_KEEP capacitance LUs for that
BORDER_MIN = 32
BORDER_KEEP = 3
#: solves assumed per scheme for the O(k n) cost of each solve of an update, when an update is
#: weighed against an inversion before it is set up (the event loop makes about three per
#: event point: the rates, the rate problem, the correction)
SOLVES_PER_SCHEME = 3

#: a block of at least SPARSE_RHS_MIN right-hand sides with at most SPARSE_RHS_DENSITY of its
#: entries nonzero is multiplied by the inverse as a sparse matrix (O(n nnz) instead of a pass
#: over the inverse per column)
SPARSE_RHS_MIN = 8
SPARSE_RHS_DENSITY = 0.05

_LAPACK: dict[tuple[str, str], object] = {}


def _lapack(name: str, a: np.ndarray):
    """LAPACK routine ``name`` (getrs, gecon) for the dtype of ``a`` (float64 or float32)."""
    key = (name, a.dtype.char)
    fn = _LAPACK.get(key)
    if fn is None:
        fn = _LAPACK[key] = sla.lapack.get_lapack_funcs(name, (a,))
    return fn

# the solver that factorised the last singular scheme: ``lu`` of that scheme's (read-only) matrix
# returns its LU instead of factorising it again (the mechanism's analysis asks for it)
_last_singular = weakref.ref(OrderedDict())  # a dead reference until a scheme is singular


def lu(A: np.ndarray, overwrite: bool = False):
    """Dense LU (in A's precision; in place with ``overwrite`` and a Fortran-ordered A); a
    singular matrix is a mechanism the caller detects from rcond, not a warning.
    The LU of the last singular scheme matrix (a read-only array from
    :meth:`SchemeSolver.dense`) is not computed twice."""
    solver = _last_singular()
    sing = solver._singular if solver is not None else None
    if sing is not None and sing[1] is A:
        return sing[3]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sla.LinAlgWarning)
        return sla.lu_factor(A, check_finite=False, overwrite_a=overwrite)


def norm1(A: np.ndarray) -> float:
    """‖A‖₁ (largest column sum), without a temporary copy of A."""
    if A.shape[0] == 0:
        return 0.0
    return float(max((np.abs(A[:, j : j + 512]).sum(axis=0).max()
                      for j in range(0, A.shape[1], 512)), default=0.0))


def rcond(f, A: np.ndarray | None = None, anorm: float | None = None) -> float:
    """Reciprocal condition number (1-norm) of A from its LU ``f``: LAPACK gecon, O(n²)
    (``anorm`` = ‖A‖₁ when A itself is no longer at hand)."""
    if f[0].shape[0] == 0:
        return 1.0
    if anorm is None:
        anorm = norm1(A)
    if not np.isfinite(anorm):
        return 0.0
    return float(_lapack("gecon", f[0])(f[0], anorm, norm="1")[0])


def lu_solve(f, b: np.ndarray) -> np.ndarray:
    """x = A⁻¹ b (float64) from the LU ``f`` of A (LAPACK getrs in the LU's precision; a
    block of a few right-hand sides is solved column by column, which OpenBLAS does faster
    than one narrow block)."""
    if b.size == 0:
        return np.zeros(b.shape)
    lu_m = f[0]
    getrs = _lapack("getrs", lu_m)
    if lu_m.dtype != np.float64:
        b = b.astype(lu_m.dtype)
    if b.ndim == 2 and 1 < b.shape[1] <= 4:
        x = np.column_stack([getrs(lu_m, f[1], b[:, j])[0] for j in range(b.shape[1])])
    else:
        x = getrs(lu_m, f[1], b)[0]
    return x if x.dtype == np.float64 else x.astype(np.float64)


def norm2(A: np.ndarray, iters: int = 30, rtol: float = 1e-3) -> float:
    """‖A‖₂ estimated by power iteration on AᵀA from a fixed start, until it changes by less
    than ``rtol``: a lower bound (‖A x‖ for a unit x), within a few per cent of ‖A‖₂, for
    O(n²) per step where an SVD of a scheme matrix costs 100× more."""
    n = A.shape[1]
    if n == 0 or A.shape[0] == 0:
        return 0.0
    x = 1.0 + 0.5 * np.random.default_rng(1).standard_normal(n)
    x = (x / np.linalg.norm(x)).astype(A.dtype)  # in A's precision: no upcast copy of A
    est = 0.0
    for _ in range(iters):
        y = A @ x
        new = float(np.linalg.norm(y))
        if new <= est * (1 + rtol):
            return max(est, new)
        est = new
        x = A.T @ y
        nx = float(np.linalg.norm(x))
        if not nx > 0:
            break
        x /= nx
    return est


def null_modes(A: np.ndarray, lu_, k: int = 3, trans: int = 0, apply=None) -> np.ndarray:
    """Null vectors (columns) of a singular matrix A (``trans=1``: of Aᵀ, the left null
    vectors) by block inverse iteration on its LU, then the combinations of the block that A
    maps to (near) zero (σ ≤ 1e-6 ‖A‖).

    ``apply`` (X ↦ A X, or Aᵀ X, of the exact float64 operator) refines the vectors of a
    float32 A: X ← X − P (A₃₂⁻¹ A X) with P the projector off X, a Newton step for the null
    space that the float32 LU resolves to 1e-7 only; the kept combinations are then those
    that the exact operator maps to near zero."""
    lu_m, piv = lu_
    d = np.abs(np.diag(lu_m))
    tiny = max(1e-14, np.finfo(lu_m.dtype).eps) * max(float(d.max(initial=0.0)), 1e-300)
    if np.any(d < tiny):  # exactly singular: lift the zero pivots to round-off level
        lu_m = lu_m.copy()
        j = np.flatnonzero(d < tiny)
        lu_m[j, j] = tiny
        lu_ = (lu_m, piv)

    def inv(X):
        return sla.lu_solve(lu_, X.astype(lu_m.dtype), trans=trans,
                            check_finite=False).astype(np.float64)

    n = A.shape[0]
    X = np.random.default_rng(0).standard_normal((n, min(k, n)))
    for _ in range(3):
        X = np.linalg.qr(inv(X))[0]
    AX = (A.T if trans else A) @ X.astype(A.dtype)
    _, sv, Vt = np.linalg.svd(AX, full_matrices=False)
    anorm = max(norm2(A), 1e-300)
    keep = sv <= max(1e-6, 100 * np.finfo(A.dtype).eps) * anorm
    if not keep.any():
        keep[np.argmin(sv)] = True
    X = X @ Vt[keep].T
    if apply is None:
        return X
    X = np.linalg.qr(X)[0]
    for _ in range(4):
        D = inv(apply(X))
        X = np.linalg.qr(X - (D - X @ (X.T @ D)))[0]
    _, sv, Vt = np.linalg.svd(apply(X), full_matrices=False)
    keep = sv <= 1e-6 * anorm
    if not keep.any():
        keep[np.argmin(sv)] = True
    return X @ Vt[keep].T


def _mv(M: np.ndarray, x: np.ndarray) -> np.ndarray:
    """M x in M's precision, as float64: a float32 M is not copied to float64 for the
    product (numpy would, for a float64 x: 80 MB per update product at 2m = 10 000)."""
    return np.asarray(M @ x.astype(M.dtype, copy=False), dtype=np.float64)


class _NotRefined(Exception):
    """A float32 update's solve did not refine: the scheme is refactorised instead."""


class _Reinverted(Exception):
    """A float64 solve found the inverse inaccurate and inverted the scheme afresh: the
    caller solves again."""


class MechanismError(Exception):
    """The working scheme is a mechanism (singular condensed matrix ``A``; ``lu`` its LU)."""

    def __init__(self, A: np.ndarray, lu_, states: np.ndarray | None = None):
        self.A = A
        self.lu = lu_
        self.states = states
        super().__init__("working scheme is a mechanism")


def _coefficients(rel: Relations, idx: np.ndarray | None = None):
    """The relations ``rel`` row by row (row j = i m + k of the component-major contact vector:
    component i of CFE k, :meth:`Relations.by_rows`), for all rows or the rows ``idx``: the
    diagonal coefficients rs = S_jj and rw = W_jj, and per offset o = 1 … n_c − 1 a triple
    (s, w, col) of the coefficients of component (i + o) mod n_c of the same CFE and its row
    col = (j + o m) mod n (in 2D the one partner component P)."""
    R = rel.by_rows()
    cols = _offset_rows(rel.layout.m, rel.layout.n_c)
    if idx is not None:
        R, cols = R[:, :, idx], cols[:, idx]
    return _unpack(R, cols)


def _unpack(R: np.ndarray, cols: np.ndarray):
    """(rs, rw, offsets) of :func:`_coefficients` from block rows R (2, n_c, k) (those of
    :meth:`Relations.by_rows`, of any rows of any schemes) and their offset rows (n_c, k)."""
    Sx, Wx = R
    return Sx[0], Wx[0], [(Sx[o], Wx[o], cols[o]) for o in range(1, len(Sx))]


@lru_cache(maxsize=16)
def _offset_rows(m: int, nc: int) -> np.ndarray:
    """The rows (j + o m) mod n (n_c, n) of the CFE's component at offset o from row j."""
    n = m * nc
    cols = (np.arange(n)[None, :] + np.arange(nc)[:, None] * m) % n
    cols.setflags(write=False)
    return cols


def _inverse_offsets(offs: list) -> list:
    """The rows that offset o's ``col`` maps back: col of offset n_c − o (a permutation)."""
    return [c for _, _, c in offs[::-1]]


def _check(rel: Relations, n: int) -> None:
    if rel.layout.n != n:
        raise ValueError(f"relations of {rel.layout.n} contact unknowns for a scheme of {n}")


def scheme_rows(G: np.ndarray, d: np.ndarray, rel: Relations, idx: np.ndarray,
                shifted: bool = False):
    """Rows ``idx`` of A, each divided by its largest entry (stuck rows scale like 1/d, free
    rows like 1: equilibrated, the condition estimate measures a mechanism, not the units).
    Returns (rows (k, n) in G's precision, Fortran-ordered so that an LU can overwrite them,
    row scales (k,)).  Every row is one pass over its row of G; a row that couples other
    components of its CFE (S_jc or W_jc ≠ 0, c ≠ j) a further pass over each of their rows.

    ``shifted``: the array is M = D G − I (the float32 form, see
    :class:`~stepcontact.solver.condensation.Condensation`); then, with G_c = (M_c + e_c)/d_c,

        A_j = −Σ_c (S_jc + W_jc/d_c) M_c − Σ_c (W_jc/d_c) e_c

    (2D: A_j = −(rw_j/d_j + rs_j) M_j − (rw_j/d_j) e_j − c_j M_P) in which no entry is a
    difference of nearly equal numbers."""
    _check(rel, G.shape[0])
    return _rows(G, d, idx, *_coefficients(rel, idx), shifted)


def _rows(G, d, idx, rs, rw, offs, shifted=False, order="F"):
    """:func:`scheme_rows` from the coefficients of the rows ``idx`` (:func:`_coefficients`;
    the rows may be of different schemes); ``order``: the rows' memory order ("F" for an LU
    to overwrite, "C" for rows kept as rows: the gathers of G's rows then write contiguously,
    the same numbers)."""
    if shifted:
        return _shifted_rows(G, d, idx, rs, rw, offs, order)
    dt = G.dtype
    coef = (-(rw + d[idx] * rs)).astype(dt)
    rows = np.empty((len(idx), G.shape[1]), dt, order=order)
    if len(idx) == G.shape[0] and np.array_equal(idx, np.arange(len(idx))):
        np.multiply(G, coef[:, None], out=rows)  # every row: no copy of G
    else:
        np.multiply(G[idx], coef[:, None], out=rows)
    rows[np.arange(len(idx)), idx] += rs.astype(dt)
    for s, w, col in offs:
        cp = np.flatnonzero((s != 0) | (w != 0))
        if not cp.size:
            continue
        P, c = col[cp], s[cp]
        rows[cp, P] += c.astype(dt)
        a = d[P] * c
        if w[cp].any():
            a = a + w[cp]
        rows[cp] -= a.astype(dt)[:, None] * G[P]
    return _equilibrate(rows, _force_size(rs, offs))


#: a free row whose entries are all below this multiple of float64's eps times its force
#: coefficients is round-off of a cancellation (e_j − d_j G_j with d_j G_j = e_j: the relation
#: of a component that the structure's other rows determine, e.g. the normals of a rigid body
#: on as many contacts as it has normal freedoms, K = 0): it is zero, not a row to equilibrate
ZERO_ROW = 64 * np.finfo(np.float64).eps


def _equilibrate(rows: np.ndarray, ref: np.ndarray):
    """Rows divided by their largest entries (row scales returned); a row below
    :data:`ZERO_ROW` of ``ref`` (the size of its force coefficients) is set to zero (its scale
    1/ref): scaled up, its round-off would pass for a relation."""
    big = np.maximum(rows.max(axis=1, initial=0.0), -rows.min(axis=1, initial=0.0))
    big = big.astype(np.float64)
    noise = big <= ZERO_ROW * ref
    if noise.any():
        rows[noise] = 0.0
        big = np.where(noise, ref, big)
    scale = 1.0 / np.maximum(big, 1e-300)
    rows *= scale.astype(rows.dtype)[:, None]
    return rows, scale


def _force_size(rs: np.ndarray, offs) -> np.ndarray:
    """|S_jj| + Σ_c≠j |S_jc| of each row: the size of its force terms (0 for a FIXED row)."""
    ref = np.abs(rs).astype(np.float64)
    for s, _w, _col in offs:
        ref = ref + np.abs(s)
    return ref


def _shifted_rows(M, d, idx, rs, rw, offs, order="F"):
    dt = M.dtype
    rwd = rw / d[idx]
    rows = np.empty((len(idx), M.shape[1]), dt, order=order)
    if len(idx) == M.shape[0] and np.array_equal(idx, np.arange(len(idx))):
        np.multiply(M, (-(rwd + rs)).astype(dt)[:, None], out=rows)
    else:
        np.multiply(M[idx], (-(rwd + rs)).astype(dt)[:, None], out=rows)
    rows[np.arange(len(idx)), idx] -= rwd.astype(dt)
    for s, w, col in offs:
        cp = np.flatnonzero((s != 0) | (w != 0))
        if not cp.size:
            continue
        P, a, wc = col[cp], s[cp], w[cp]
        if wc.any():
            a = a + wc / d[P]
        rows[cp] -= a.astype(dt)[:, None] * M[P]
        if wc.any():
            rows[cp, P] -= (wc / d[P]).astype(dt)
    return _equilibrate(rows, _force_size(rs, offs))


def scheme_apply(d: np.ndarray, rel: Relations, scale: np.ndarray, t: np.ndarray,
                 Gt: np.ndarray) -> np.ndarray:
    """A t for the scheme ``rel`` with row scales ``scale``, from t and the product G t (of
    the exact operator): the residual of the float32 schemes' refinement (vectors or
    (n, k) blocks)."""
    rs, rw, offs = _coefficients(rel)
    if t.ndim == 2:
        rw, rs, d, scale = rw[:, None], rs[:, None], d[:, None], scale[:, None]
    out = rs * t - (rw + d * rs) * Gt
    for s, w, P in offs:
        if t.ndim == 2:
            s, w = s[:, None], w[:, None]
        out = out + s * (t[P] - d[P] * Gt[P])
        if w.any():
            out = out - w * Gt[P]
    return scale * out


def scheme_rhs(d: np.ndarray, rel: Relations, hhat, e, r):
    """b (unscaled) of A t' = b for load rates (ĥ, e) and relation right-hand sides r (vectors
    or (n, k) blocks)."""
    rs, rw, offs = _coefficients(rel)
    two = np.ndim(r) == 2 or np.ndim(hhat) == 2
    if two:
        rw, rs, dd = rw[:, None], rs[:, None], d[:, None]
    else:
        dd = d
    dh = dd * hhat
    he = hhat + e
    b = r - rw * he - rs * dh
    for s, w, P in offs:
        if two:
            s, w = s[:, None], w[:, None]
        b = b - s * dh[P]
        if w.any():
            b = b - w * np.broadcast_to(he, np.broadcast_shapes(np.shape(he), dh.shape))[P]
    return b


def _load_vector(x, d: np.ndarray) -> np.ndarray:
    """x as a float64 vector of d's shape (a scalar broadcast; an array of that shape as is)."""
    if isinstance(x, np.ndarray) and x.shape == d.shape and x.dtype == np.float64:
        return x
    return np.broadcast_to(np.asarray(x, float), d.shape)


def _load_rhs_rows(d: np.ndarray, coef: tuple, idx: np.ndarray, hhat, e) -> np.ndarray:
    """Rows ``idx`` of :func:`scheme_rhs` for load rates (ĥ, e) and r = 0 (vectors), from
    the coefficients ``coef`` of those rows (:func:`_coefficients`)."""
    rs, rw, offs = coef
    b = -rw * (hhat[idx] + e[idx]) - rs * d[idx] * hhat[idx]
    for s, w, P in offs:
        b = b - s * d[P] * hhat[P]
        if w.any():
            b = b - w * (hhat[P] + e[P])
    return b


def scheme_apply_t(d: np.ndarray, rel: Relations, scale: np.ndarray, y: np.ndarray,
                   product) -> np.ndarray:
    """Aᵀ y for the scheme ``rel`` with row scales ``scale`` (G symmetric, ``product``:
    t ↦ G t exact).  With A = Sc [R + Σ_o C_o Π_o − (diag(a) + Σ_o diag(c_o d_o + w_o) Π_o) G]
    (Sc = diag(scale), R = diag(rs), a = rw + d·rs, Π_o the map of each row to its CFE's
    component at offset o, C_o = diag(c_o) and w_o its coefficients; 2D: one offset, Π the
    swap of each CFE's components, c the couple, w = 0):

        Aᵀ y = R u + Σ_o Π_oᵀ (c_o u) − G (a u + Σ_o Π_oᵀ ((c_o d_o + w_o) u)),   u = Sc y."""
    rs, rw, offs = _coefficients(rel)
    a = rw + d * rs
    two = y.ndim == 2
    if two:
        rs, a, scale = rs[:, None], a[:, None], scale[:, None]
    u = scale * y
    x, z = rs * u, a * u
    for (s, w, P), back in zip(offs, _inverse_offsets(offs), strict=True):
        cd = s * d[P]
        if w.any():
            cd = cd + w
        if two:
            s, cd = s[:, None], cd[:, None]
        x = x + (s * u)[back]
        z = z + (cd * u)[back]
    return x - product(z)


def _block_rows(rel: Relations, idx: np.ndarray) -> np.ndarray:
    """The block rows (S_j·, W_j·) of the rows ``idx``, (len(idx), 2 n_c) in the order of
    :meth:`Relations.by_rows`."""
    R = rel.by_rows()
    return R.reshape(-1, R.shape[2])[:, idx].T


def _changed_rows(rel: Relations, base: Relations) -> np.ndarray:
    """The rows (component-major, sorted) whose relation differs between two schemes."""
    R, R0 = rel.by_rows(), base.by_rows()
    return np.flatnonzero((R != R0).any(axis=(0, 1)))


def _row_sums(A: np.ndarray) -> np.ndarray:
    """|A| 1 (each row's absolute sum, float64), by blocks of rows: no copy of A."""
    out = np.empty(A.shape[0])
    for i in range(0, A.shape[0], 256):
        out[i : i + 256] = np.abs(A[i : i + 256]).sum(axis=1, dtype=np.float64)
    return out


def _invert(f) -> np.ndarray:
    """A⁻¹ from the LU ``f`` of A (LAPACK getri, in place: the LU's array becomes the
    inverse, Fortran-ordered; (4/3) n³ flops after the LU's (2/3) n³)."""
    lu_m, piv = f
    n = lu_m.shape[0]
    if n == 0:
        return lu_m
    lwork = int(_lapack("getri_lwork", lu_m)(n)[0])
    X, info = _lapack("getri", lu_m)(lu_m, piv, lwork=max(lwork, 1), overwrite_lu=1)
    if info != 0:  # (a zero pivot: rcond is 0 and the scheme was reported as a mechanism)
        raise np.linalg.LinAlgError(f"getri: zero pivot {info} of a scheme matrix")
    return X


class _Base:
    """The explicit inverse X = A₀⁻¹ of a base scheme and what the row updates of it share.

    For every row j that a scheme has changed so far (a *slot*): the column Z_j = X e_j (a
    copy of X's column: no solve), the row's difference V_j from the base for its latest
    relation (with the row's scale), that row's absolute sum, and the products V Z over all
    slots, kept current as slots are added and rows change; per load rate (ĥ, e), the base
    solution y₀ = X b₀ (one pass over X).  A scheme that differs in k rows then costs O(k n)
    to set up and its load rates O(k n) plus one product with G.

    The base lives until the solver commits a scheme's update into X in place
    (:meth:`SchemeSolver._commit`): it is then dead (``alive`` False, ``X`` None), and the
    factors of it solve through the new base (:meth:`SchemeFactor._live`).  ``commits``
    counts the rank-k updates X has taken since it was inverted from an LU; ``checked``
    whether a solve of this base has had its backward error measured
    (:meth:`SchemeFactor._stable`)."""

    def __init__(self, rel: Relations, n: int, scale: np.ndarray, X: np.ndarray, rc: float,
                 rowsum: np.ndarray, commits: int = 0):
        rel.by_rows()  # S and W are read-only from now on: the base keeps the relations
        self.rel = rel
        # the base matrix itself is not kept (X overwrote its LU): a changed row's difference
        # from it is formed from G, as it was
        self.n, self.scale, self.X, self.rcond = n, scale, X, rc
        #: |A₀| 1 and ‖A₀‖∞ (the backward error's norm)
        self.rowsum = rowsum
        self.anorm = float(rowsum.max(initial=0.0))
        self.commits = commits
        self.alive = True
        self.checked = False
        self.dtype = X.dtype
        self.slot = np.full(n, -1, np.int64)
        self.k = 0
        cap = min(n, 32)
        self.Z = np.empty((n, cap), self.dtype, order="F")
        self.V = np.empty((cap, n), self.dtype)
        #: each slot's row of the base scheme (formed once; V = R − R0 as the row changes)
        self.R0 = np.empty((cap, n), self.dtype)
        self.VZ = np.empty((cap, cap), self.dtype)
        self.vscale = np.empty(cap)
        #: |R| 1 of each slot's latest row
        self.vsum = np.empty(cap)
        #: the block row (S_j·, W_j·) of each slot's latest relation (:func:`_block_rows`)
        self.vrow = np.empty((cap, 2 * rel.layout.n_c))
        #: how many times each slot's row has changed (a capacitance LU formed with a slot's
        #: row is reused only while its version stands: :meth:`SchemeSolver._bordered`)
        self.version = np.zeros(cap, np.int64)
        #: LUs of recent capacitances (slots in their order, their versions, (lu, piv))
        self.caps: list[tuple[np.ndarray, np.ndarray, tuple]] = []
        #: each slot's previous row (its V, scale, |R| 1, block row, and its products V Z
        #: with the first ``vz2k`` columns): a row that changes back to it (a rate problem's
        #: stuck scheme, then the next scheme near the base) is swapped in, not formed again
        self.V2 = np.empty((cap, n), self.dtype)
        self.VZ2 = np.empty((cap, cap), self.dtype)
        self.vscale2 = np.empty(cap)
        self.vsum2 = np.empty(cap)
        self.vrow2 = np.full((cap, 2 * rel.layout.n_c), np.nan)
        self.vz2k = np.zeros(cap, np.int64)
        self.loads: OrderedDict[int, tuple] = OrderedDict()
        #: the rank policy's account: weighted flops the updates of this base have cost, and
        #: the rows the latest :meth:`prepare` formed (:meth:`SchemeSolver._commit_now`)
        self.spent = 0.0
        self.formed = 0

    def _grow(self, need: int) -> None:
        cap = self.Z.shape[1]
        if need <= cap:
            return
        n = self.n
        new = min(n, max(need, 2 * cap))
        k = self.k
        Z = np.empty((n, new), self.dtype, order="F")
        Z[:, :k] = self.Z[:, :k]
        self.Z = Z
        for name in ("VZ", "VZ2"):
            VZ = np.empty((new, new), self.dtype)
            VZ[:k, :k] = getattr(self, name)[:k, :k]
            setattr(self, name, VZ)
        for name in ("V", "R0", "vscale", "vsum", "vrow", "V2", "vscale2", "vsum2", "vrow2",
                     "vz2k", "version"):
            old = getattr(self, name)
            a = np.empty((new,) + old.shape[1:], old.dtype)
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
            self.Z[:, k0:k1] = self.X[:, new_rows]  # Z_j = X e_j
            self.slot[new_rows] = np.arange(k0, k1)
            self.vrow2[k0:k1] = np.nan  # (no previous row)
            self.k = k1
            solver.counters["scheme_columns"] += new_rows.size
        slots = self.slot[idx]
        k = self.k
        row = _block_rows(rel, idx)
        stale = (slots >= k0) | (self.vrow[slots] != row).any(axis=1)
        rows_j, row, stale = idx[stale], row[stale], slots[stale]
        if new_rows.size and k0:  # new columns of V Z (rows about to change are redone below)
            self.VZ[:k0, k0:k] = self.V[:k0] @ self.Z[:, k0:k]
        self.version[stale] += 1  # (formed below or swapped back: the row changes)
        if stale.size:
            rows_j, row, stale = self._swap(rows_j, row, stale, k0)
        self.formed = int(stale.size)  # (the new slots are stale too)
        solver.counters["scheme_rows"] += self.formed
        if stale.size:
            # the changed rows, and the base rows of the new slots (formed once), together
            lay = self.rel.layout
            new_slot = stale >= k0
            fresh = rows_j[new_slot]
            both = np.concatenate([rows_j, fresh])
            blocks = np.concatenate([rel.by_rows()[:, :, rows_j],
                                     self.rel.by_rows()[:, :, fresh]], axis=2)
            R, sc = _rows(solver.G, solver.d, both,
                          *_unpack(blocks, _offset_rows(lay.m, lay.n_c)[:, both]),
                          solver.shifted, order="C")
            ks = rows_j.size
            self.R0[stale[new_slot]] = R[ks:]
            R, sc = R[:ks], sc[:ks]
            self.V[stale] = R - self.R0[stale]
            self.vscale[stale] = sc
            self.vsum[stale] = _row_sums(R)
            self.vrow[stale] = row
            self.VZ[stale, :k] = self.V[stale] @ self.Z[:, :k]
        return slots

    def _swap(self, rows_j, row, stale, k0):
        """Of the slots ``stale`` whose rows change (to the block rows ``row``): the existing
        ones keep their current row as the previous one, and those whose new row is their
        previous row take it back (with its products V Z; those with the columns added
        since it was kept are formed, a k-column product).  Returns the rows still to be
        formed (rows_j, row, stale) of the rest."""
        old = np.flatnonzero(stale < k0)
        if not old.size:
            return rows_j, row, stale
        so = stale[old]
        back = (self.vrow2[so] == row[old]).all(axis=1)
        k = self.k
        keep = (self.V[so].copy(), self.vscale[so].copy(), self.vsum[so].copy(),
                self.vrow[so].copy(), self.VZ[so, :k].copy())
        sb = so[back]
        if sb.size:
            self.V[sb] = self.V2[sb]
            self.vscale[sb] = self.vscale2[sb]
            self.vsum[sb] = self.vsum2[sb]
            self.vrow[sb] = self.vrow2[sb]
            kv = int(self.vz2k[sb].min())
            self.VZ[sb, :kv] = self.VZ2[sb, :kv]
            if kv < k:
                self.VZ[sb, kv:k] = self.V[sb] @ self.Z[:, kv:k]
        self.V2[so], self.vscale2[so], self.vsum2[so], self.vrow2[so] = keep[:4]
        self.VZ2[so, :k] = keep[4]
        self.vz2k[so] = k
        rest = np.ones(len(stale), bool)
        rest[old[back]] = False
        return rows_j[rest], row[rest], stale[rest]

    def load(self, solver: SchemeSolver, hhat: np.ndarray, e: np.ndarray):
        """(b₀, y₀ = X b₀) of the load rates (ĥ, e) on the base scheme (cached)."""
        key = hash((hhat.tobytes(), e.tobytes()))
        hit = self.loads.get(key)
        if hit is not None and np.array_equal(hit[0], hhat) and np.array_equal(hit[1], e):
            self.loads.move_to_end(key)
            return hit[2:]
        b0 = self.scale * scheme_rhs(solver.d, self.rel, hhat, e, 0.0)
        y0 = _mv(self.X, b0)
        solver.counters["scheme_solves"] += 1
        out = (hhat.copy(), e.copy(), b0, y0)
        self.loads[key] = out
        if len(self.loads) > 4:
            self.loads.popitem(last=False)
        return out[2:]


@dataclass(eq=False)
class SchemeFactor:
    """A working scheme ready to solve: the base's inverse X = A₀⁻¹ plus a low-rank
    (Woodbury) update of the rows ``idx`` (V: their differences from the base, Z = X E_idx,
    C = I + V Z; ``row_sums``: |A_j| 1 of the changed rows), or the base itself (``V`` None)."""

    owner: SchemeSolver
    base: _Base
    idx: np.ndarray
    V: np.ndarray | None
    Z: np.ndarray | None
    C_lu: tuple | None
    scale: np.ndarray
    rel: Relations
    row_sums: np.ndarray | None = None
    #: the coefficients of the rows ``idx`` (:func:`_coefficients`), once needed
    coef: tuple | None = None

    def _live(self) -> SchemeFactor | None:
        """None while the base lives; else the factor of the same scheme on the solver's
        current base (a commit made this one's X the next scheme's, in place)."""
        if self.base.alive:
            return None
        return self.owner.factor(self.rel)

    def _approx(self, bs: np.ndarray) -> np.ndarray:
        """A⁻¹ bs for a scaled right-hand side: one pass over X (a product; for a block of
        right-hand sides one matrix product, or, for a sparse block — the rate problem's
        columns, each a unit rate on one CFE's rows — a sparse one, O(n nnz)) and the row
        update."""
        o = self.owner
        X = self.base.X
        if bs.ndim == 2 and bs.shape[1] >= SPARSE_RHS_MIN:
            Bt = sp.csr_matrix(bs.T.astype(X.dtype, copy=False))
            if Bt.nnz <= SPARSE_RHS_DENSITY * bs.size:
                y = np.asarray((Bt @ X.T).T, dtype=np.float64)  # Σ over nonzeros: X[:, j] b_j
            else:
                y = _mv(X, bs)
        else:
            y = _mv(X, bs)
        o.counters["scheme_solves"] += 1 if bs.ndim == 1 else bs.shape[1]
        if self.V is not None:
            y = y - _mv(self.Z, lu_solve(self.C_lu, _mv(self.V, y)))
            self.base.spent += W_PASS * 4.0 * self.V.size * (1 if bs.ndim == 1 else bs.shape[1])
        return y

    def solve_rows(self, rows: np.ndarray, bs: np.ndarray) -> np.ndarray:
        """(A⁻¹ b)[rows] for a block of scaled right-hand sides b that vanish outside ``rows``
        (``bs``: their entries in ``rows``, (r, c), each column with a few nonzeros: the rate
        problem's, a unit rate on one CFE's rows), float64, without a pass over X:

            (A⁻¹ b)[R] = X[R, R] b_R − Z[R] C⁻¹ (V X b)   (O(r n) to gather X[R, R]),

        V X b from the base's products V Z for the rows of R that have a slot there (Z_j =
        X e_j; the slots' rows still this scheme's) and one product V (X[:, R'] b_R') for the
        rest R'; O(k (r + k) c) for k changed rows instead of the O(k n c) of a block solve."""
        live = self._live()
        if live is not None:
            return live.solve_rows(rows, bs)
        b = self.base
        X = b.X
        B = sp.csc_matrix(bs.astype(X.dtype, copy=False))
        # (X b)[R] = X[R, R] b_R: the rows R of X only (a pass over r of its n rows)
        Xrr = X[rows][:, rows]
        out = np.asarray((B.T @ Xrr.T).T, dtype=np.float64)  # Σ over nonzeros: X[R, j] b_j
        if self.V is None:
            return out
        fs = b.slot[self.idx]
        sl = b.slot[rows]
        has = np.zeros(len(rows), bool)
        if np.array_equal(b.vrow[fs], _block_rows(self.rel, self.idx)):
            has = sl >= 0
        VXb = np.zeros((len(fs), bs.shape[1]))
        if has.any():  # (V Z)[:, has] b_has, sparse in b
            Bh = sp.csr_matrix(B[has])
            VXb += np.asarray((Bh.T @ b.VZ[np.ix_(fs, sl[has])].T).T, dtype=np.float64)
        rest = np.flatnonzero(~has)
        if rest.size:
            Br = sp.csc_matrix(B[rest])
            cols = np.flatnonzero(np.diff(Br.indptr))
            if cols.size:
                Ur = (Br[:, cols].T @ X[:, rows[rest]].T).T  # X[:, R'] b_R', (n, c')
                VXb[:, cols] += _mv(self.V, np.asarray(Ur))
                b.spent += 2.0 * self.V.size * cols.size  # (BLAS-3: weight 1)
        b.spent += 2.0 * len(fs) * (len(fs) + len(rows)) * bs.shape[1]
        return out - _mv(self.Z[rows], lu_solve(self.C_lu, VXb))

    def _refine(self, bs: np.ndarray, y: np.ndarray,
                floor: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """Iterative refinement of y ≈ A⁻¹ bs (float32 schemes) against the exact operator:
        r = bs − A y with A y from G y of the float64 sparse factorisation
        (:func:`scheme_apply`), y += A₃₂⁻¹ r, until r is at round-off of the larger of y, bs
        and ``floor`` (a correction of a state of size ``floor`` needs no digits below the
        state's round-off: one float32 solve of a round-off drift is already exact to it).
        Returns (y, G y).
        A residual that stops shrinking above ``REFINE_ACCEPT`` raises a SolverError: the
        scheme is too ill-conditioned for float32 (never a silently inaccurate rate); an
        update, or a base whose inverse has taken rank-k updates, is inverted afresh instead
        (``_NotRefined``)."""
        o = self.owner
        Gy = o.product(y)
        size = max(np.abs(bs).max(initial=0.0), floor, 1e-300)
        prev = np.inf
        for _ in range(REFINE_MAX):
            r = bs - scheme_apply(o.d, self.rel, self.scale, y, Gy)
            rn = np.abs(r).max(initial=0.0)
            size = max(size, np.abs(y).max(initial=0.0))
            if rn <= REFINE_TOL * size or rn >= 0.5 * prev:
                break
            prev = rn
            y = y + self._approx(r)
            Gy = o.product(y)
            o.counters["refinements"] += 1
        if rn > REFINE_ACCEPT * size:
            if self.V is not None or self.base.commits:  # refactorise, then decide
                raise _NotRefined
            from stepcontact.errors import SolverError

            raise SolverError(
                f"the float32 scheme matrix does not refine to float64 accuracy (relative "
                f"residual {rn / size:.1e} after {REFINE_MAX} corrections at most): the working "
                f"scheme is too ill-conditioned for precision='float32'; run with "
                f"precision='float64' (needs twice the memory of the dense contact matrices)")
        return y, Gy

    def _backward(self, bs: np.ndarray, y: np.ndarray, Gy: np.ndarray):
        """The residual r = bs − A y (A y from G y, O(n): :func:`scheme_apply`) and the
        normwise backward error of each solution (column) y,

            η = ‖bs − A y‖∞ / (‖A‖∞ ‖y‖∞ + ‖bs‖∞)

        (‖A‖∞ bounded by the base's and the changed rows' largest absolute row sum)."""
        o, b = self.owner, self.base
        r = bs - scheme_apply(o.d, self.rel, self.scale, y, Gy)
        anorm = b.anorm if self.row_sums is None else max(b.anorm, float(self.row_sums.max()))
        den = anorm * np.abs(y).max(axis=0, initial=0.0) + np.abs(bs).max(axis=0, initial=0.0)
        return r, np.abs(r).max(axis=0, initial=0.0) / np.maximum(den, 1e-300)

    def _stable(self, bs: np.ndarray, y: np.ndarray, Gy: np.ndarray):
        """A float64 solution y ≈ A⁻¹ bs (a vector or a block) made backward stable: its
        backward error η (:meth:`_backward`, O(n) from the G y the rates form anyway) is
        measured on *every* solve.  A solution through an explicit inverse has the forward
        error of an LU solve but not its backward error: y = X b leaves a residual up to
        eps ‖A‖ ‖A⁻¹‖ ‖b‖, i.e. η up to eps cond(A) where an LU leaves η ≈ eps — and the force
        rates s' = y + D (ĥ − G y) are a difference of large terms wherever the contacts are
        much stiffer than the structure, so they carry η, not the forward error (a stiff block
        on a compliant layer: η = 3e-12 moved s' by 1.6e-5 relative).  A solution with
        η > ``ETA_ACCEPT`` is refined, y ← y + A⁻¹ r with the same inverse and its update (a
        pass over X and one over G per step; fixed-precision refinement, which gives an
        η of eps·(1 + κ eps) after one step while cond(A) eps ≪ 1); one that stops improving
        on a base that has taken rank-k commits, or an update of such a base (its inverse
        has drifted from its matrix), and a committed base whose first η exceeds
        max(``BACKWARD_TOL``, ``BACKWARD_GROWTH`` η₀) (η₀: that of the latest fresh
        inverse), is inverted afresh from an LU (``scheme_reinversions``) and
        ``_Reinverted`` raised (the caller solves again with the fresh inverse).  Returns
        (y, G y)."""
        o, b = self.owner, self.base
        r, eta = self._backward(bs, y, Gy)
        first = not b.checked
        b.checked = True
        worst = float(eta.max(initial=0.0))
        if first and not b.commits and self.V is None:
            o.eta_fresh = worst
        if worst <= ETA_ACCEPT:
            return y, Gy
        drifted = b.commits > 0
        if drifted and first and worst > max(BACKWARD_TOL, BACKWARD_GROWTH * o.eta_fresh):
            self._reinvert()
        prev = np.inf
        for _ in range(REFINE_MAX_F64):
            if y.ndim == 1:
                y = y + self._approx(r)
                Gy = o.g_product(y)
            else:
                bad = np.flatnonzero(eta > ETA_ACCEPT)
                y = y.copy()
                y[:, bad] += self._approx(r[:, bad])
                Gy = Gy.copy()
                Gy[:, bad] = o.G @ y[:, bad]
            o.counters["refinements"] += 1
            r, eta = self._backward(bs, y, Gy)
            prev, worst = worst, float(eta.max(initial=0.0))
            if worst <= ETA_ACCEPT:
                return y, Gy
            if worst > 0.5 * prev:
                break
        if drifted or self.V is not None:
            self._reinvert()
        # a fresh inverse whose refinement stalls: cond(A) eps is not small (a scheme next to
        # a mechanism); the solution is as good as this precision makes it
        return y, Gy

    def _reinvert(self) -> None:
        """Invert this scheme afresh from an LU (its inverse lost accuracy) and make the
        caller solve again (``_Reinverted``)."""
        o = self.owner
        o.counters["scheme_reinversions"] += 1
        o._refactor(self.rel)
        o._cache[self.rel.key()] = o._plain(self.rel)
        raise _Reinverted

    def solve(self, hhat, e, r, floor: float = 0.0):
        """Rates (s', w') of this scheme for load rates (ĥ, e) and relation right-hand sides
        r; each argument a vector (2m,) or a block (2m, k) (zeros broadcast).  ``floor``
        (N): the size of the forces the result is added to, when it is a correction (float32
        schemes refine it to that size's round-off, see :meth:`_refine`)."""
        live = self._live()
        if live is not None:
            return live.solve(hhat, e, r, floor)
        o = self.owner
        d = o.d
        b = scheme_rhs(d, self.rel, hhat, e, r)
        bs = self.scale * b if b.ndim == 1 else self.scale[:, None] * b
        y = self._approx(bs)
        if o.refine:
            try:
                y, Gy = self._refine(bs, y, floor)
            except _NotRefined:
                return o.refactored(self).solve(hhat, e, r, floor)
        else:
            Gy = o.g_product(y)
            try:
                y, Gy = self._stable(bs, y, Gy)
            except _Reinverted:
                return o.factor(self.rel).solve(hhat, e, r, floor)
        return self._rates(y, Gy, hhat, e)

    def _rates(self, y: np.ndarray, Gy: np.ndarray, hhat, e):
        """(s', w') from the scheme's solution y = t' and its product G y: ŵ' = ĥ − G y,
        s' = y + D ŵ', w' = ŵ' + e.  The solver keeps (s', y, G y) of the last rates
        (``last_product``): y is the change of t = s − D ŵ per unit step, whatever e is, so
        a driver that moves along s' can keep G t current without a product
        (:meth:`~stepcontact.solver.engine.EventEngine.tracked_product`)."""
        d = self.owner.d
        w_hat = hhat - Gy
        dd = d if y.ndim == 1 else d[:, None]
        ds = y + dd * w_hat
        self.owner.last_product = (ds, y, Gy)
        return ds, w_hat + e

    def load_rates(self, hhat: np.ndarray, e: np.ndarray):
        """Rates (s', w') of this scheme for the load rates (ĥ, e) (vectors) and r = 0: from
        the base's cached solution of the same load, updated in the changed rows,

            y = y₀ + Z C⁻¹ (δ − V y₀)

        (δ: the change of the scaled right-hand side in those rows), O(k n); then ŵ = ĥ − G y
        (one pass over G, the only one of a scheme met between commits).  (G y is formed
        afresh: updating a cached G y₀ the same way cancels where ŵ ≪ G y₀ and moves events by
        round-off 10× larger.)  Float32 schemes refine that solution."""
        live = self._live()
        if live is not None:
            return live.load_rates(hhat, e)
        o = self.owner
        d = o.d
        hhat, e = _load_vector(hhat, d), _load_vector(e, d)
        b0, y0 = self.base.load(o, hhat, e)
        if self.V is None:
            y = y0
        else:
            idx = self.idx
            if self.coef is None:
                self.coef = _coefficients(self.rel, idx)
            delta = self.scale[idx] * _load_rhs_rows(d, self.coef, idx, hhat, e) - b0[idx]
            g = lu_solve(self.C_lu, delta - _mv(self.V, y0))
            self.base.spent += W_PASS * 4.0 * self.V.size
            y = y0 + _mv(self.Z, g)
        if o.refine:  # the cached float32 solution is the start of the refinement
            try:
                y, Gy = self._refine(self.scale * scheme_rhs(d, self.rel, hhat, e, 0.0), y)
            except _NotRefined:
                return o.refactored(self).load_rates(hhat, e)
        else:
            Gy = o.g_product(y)
            try:
                y, Gy = self._stable(self.scale * scheme_rhs(d, self.rel, hhat, e, 0.0), y, Gy)
            except _Reinverted:
                return o.factor(self.rel).load_rates(hhat, e)
        return self._rates(y, Gy, hhat, e)


class SchemeSolver:
    """Solves working schemes as low-rank row updates of the explicit inverse of a base scheme.

    The dense scheme matrix A (n × n, n = m (1 + n_t)) of a first scheme is LU-factorised, its
    condition estimated from the LU (LAPACK gecon, O(n²)): rcond ≤ ``RCOND_MECHANISM`` is a
    mechanism; a regular scheme's LU is turned into its inverse X = A₀⁻¹ in place (getri):
    the *base*.  A scheme that differs from the base in the k rows E = I[:, idx] (A = A₀ +
    E V) is solved by the Woodbury identity

        A⁻¹ = X − Z C⁻¹ V X,   Z = X E (k columns of X),   C = I_k + V Z,

    whose pieces are cached on the base as rows change (:class:`_Base`: a column costs a
    copy, a changed row one row of G), so that a scheme met between commits costs O(k n) and
    its load rates O(k n) plus one product with G; det A = det A₀ · det C, so a mechanism
    makes C singular.  A scheme asked for may be *committed* (by default when the updates of
    the base have cost as much as its commit, :meth:`_commit_now`; with ``max_rank`` given,
    when k exceeds it): X takes its update in place,

        W = V X  (one read of X: a k × n by n × n product),
        X ← X − Z (C⁻¹ W)  (one read and write of X: a rank-k update, BLAS gemm),

    and the scheme becomes the base.  Per changed row that is 2 n² flops per pass, the cost
    of a rank-one update of a dense factor, in BLAS-3 blocks of k rows; a full inversion,
    (2/3 + 4/3) n³ flops, is made only for the first scheme, for a scheme whose update and
    commit would cost more (:meth:`_invert_instead`), for a doubtful update and when the
    commits have cost accuracy:

    * a doubtful update: its capacitance C is ill-conditioned (rcond(C) ≤ ``RCOND_UPDATE``):
      the scheme is LU-factorised in full, whose gecon estimate decides whether it is a
      mechanism (:class:`MechanismError`), and inverted if it is not;
    * lost accuracy: every solve has its normwise backward error measured in O(n) from the
      G y it forms anyway and is refined beyond ``ETA_ACCEPT`` (:meth:`SchemeFactor._stable`);
      a committed base whose first error has grown past ``BACKWARD_TOL`` (and
      ``BACKWARD_GROWTH`` times that of a fresh inverse), or whose refinement stalls, is
      inverted afresh.

    Factors of the last few schemes are kept, so a scheme met again (the rate problem, then
    the correction at the same point) is not set up twice; a singular scheme is factorised
    once (its matrix and LU serve the analysis of the mechanism: :meth:`dense`, :func:`lu`).

    A float32 G (the large-interface path, ``precision="float32"``) gives a float32 inverse
    and updates, half the memory and time of the dense work; every solve is then refined to
    float64 accuracy against ``product`` (t ↦ G t by the float64 sparse factorisation, one
    solve per correction): :meth:`SchemeFactor._refine`, whose convergence is the accuracy
    guard there (a solve that does not refine on an update or a committed base inverts the
    scheme afresh).
    """

    def __init__(self, G: np.ndarray, d: np.ndarray, max_rank: int | None = None,
                 cache: int = 8, product=None):
        self.G = G
        self.d = d
        #: t ↦ G t in float64 (the exact operator; for float64 G the dense product)
        self.product = product if product is not None else (lambda t: G @ t)
        self.refine = G.dtype != np.float64
        #: float32 G is the shifted form D G − I (:func:`scheme_rows`)
        self.shifted = self.refine
        if self.refine and product is None:
            raise ValueError("a float32 G needs the exact operator (product) to refine against")
        self.rcond_mechanism = RCOND_MECHANISM_F32 if self.refine else RCOND_MECHANISM
        self.rcond_update = RCOND_UPDATE_F32 if self.refine else RCOND_UPDATE
        #: a fixed rank rule (``max_rank`` given, and for float32 schemes, whose updates must
        #: refine against the exact operator: small ranks) or the cost-based policy
        #: (:meth:`_commit_now`)
        self.fixed_rank = max_rank is not None or self.refine
        self.max_rank = MAX_RANK if max_rank is None else max_rank
        self.base: _Base | None = None
        self._cache: OrderedDict[bytes, SchemeFactor] = OrderedDict()
        self._cache_size = cache
        self._singular: tuple | None = None
        #: scheme_factorizations: factors formed for a new base scheme, by an LU and its
        #: inverse (scheme_inversions, O(n³); scheme_reinversions of them for lost accuracy)
        #: or by a rank-k commit into the inverse (scheme_commits, two passes over it);
        #: scheme_updates: Woodbury updates set up; scheme_columns: changed rows given a slot;
        #: scheme_rows: changed rows formed from G (a row changed back to its previous
        #: relation is not formed again: :meth:`_Base._swap`); scheme_bordered: capacitance
        #: LUs extended from a recent one by bordering (:func:`_border_lu`);
        #: scheme_solves: right-hand sides solved with the inverse (a pass over it each)
        self.counters = {"scheme_factorizations": 0, "scheme_inversions": 0,
                         "scheme_commits": 0, "scheme_reinversions": 0,
                         "scheme_policy_inversions": 0, "scheme_updates": 0,
                         "scheme_columns": 0, "scheme_rows": 0, "scheme_bordered": 0,
                         "scheme_solves": 0,
                         "refinements": 0}
        #: (s', y, G y) of the rates solved last (:meth:`SchemeFactor._rates`)
        self.last_product: tuple | None = None
        #: the backward error of the first solve on the latest inverse from an LU
        self.eta_fresh = 0.0
        self._gnorm: float | None = None
        self._symv = None

    def g_norm(self) -> float:
        """‖G‖∞ (largest absolute row sum of G, float64; of (M + I)/d for the shifted float32
        form M = D G − I), computed once by blocks of rows: it bounds the product of a small
        difference, ‖G δ‖∞ ≤ ‖G‖∞ ‖δ‖∞."""
        if self._gnorm is None:
            G, n, out = self.G, self.n, 0.0
            for i in range(0, n, 256):
                blk = np.abs(np.asarray(G[i : i + 256], np.float64))
                if self.shifted:
                    j = np.arange(blk.shape[0])
                    blk[j, i + j] = np.abs(np.asarray(G[i + j, i + j], np.float64) + 1.0)
                    blk /= self.d[i : i + 256, None]
                out = max(out, float(blk.sum(axis=1).max(initial=0.0)))
            self._gnorm = out
        return self._gnorm

    @property
    def n(self) -> int:
        return self.G.shape[0]

    def g_product(self, y: np.ndarray) -> np.ndarray:
        """G y (float64 G) for the rates: BLAS symv, which reads one triangle of G (half a pass,
        twice as fast as the full product), when G is exactly symmetric (checked once: G =
        B K₀⁻¹ Bᵀ is, as the Schur complement and the block solves form it); else, and for a
        block of right-hand sides, the full product."""
        G = self.G
        if self._symv is None:
            self._symv = False
            if G.dtype == np.float64 and G.flags.c_contiguous and np.array_equal(G, G.T):
                self._symv = sla.blas.get_blas_funcs("symv", (G,))
        if y.ndim == 1 and y.size and self._symv:
            # (G C-ordered: G.T is the same memory in Fortran order, the order BLAS reads)
            return self._symv(1.0, G.T, y, lower=1)
        return G @ y

    def _install(self, base: _Base) -> None:
        """Make ``base`` the base: the previous one dies (its factors re-derive themselves)."""
        old = self.base
        if old is not None and old is not base:
            old.alive = False
            old.X = None
        self.base = base
        self._cache.clear()

    def _refactor(self, rel: Relations) -> None:
        global _last_singular
        key = rel.key()
        A, scale = scheme_rows(self.G, self.d, rel, np.arange(self.n), self.shifted)
        anorm = norm1(A)
        rowsum = _row_sums(A)
        f = lu(A, overwrite=True)  # in place: A is gone, its rows are formed again from G
        del A
        rc = rcond(f, anorm=anorm)
        self.counters["scheme_factorizations"] += 1
        self.counters["scheme_inversions"] += 1
        if not rc > self.rcond_mechanism and not self._regular_after_all(rel, scale, f):
            A, _ = scheme_rows(self.G, self.d, rel, np.arange(self.n), self.shifted)
            A.flags.writeable = False
            scale.flags.writeable = False
            self._singular = (key, A, scale, f)
            _last_singular = weakref.ref(self)
            raise MechanismError(A, f)
        self._install(_Base(rel, self.n, scale, _invert(f), rc, rowsum))

    def _commit(self, fac: SchemeFactor) -> None:
        """Make the scheme of the update ``fac`` the base: its Woodbury update taken into X
        in place, X ← X − Z C⁻¹ (V X) (two passes over X)."""
        b = fac.base
        W = _lu_solve_block(fac.C_lu, fac.V @ b.X)  # C⁻¹ V X, (k, n)
        X = sla.blas.get_blas_funcs("gemm", (b.X,))(-1.0, fac.Z, W, beta=1.0, c=b.X, overwrite_c=1)
        rowsum = b.rowsum.copy()
        rowsum[fac.idx] = fac.row_sums
        self.counters["scheme_commits"] += 1
        self.counters["scheme_factorizations"] += 1
        self._install(_Base(fac.rel, self.n, fac.scale, X, b.rcond, rowsum, b.commits + 1))

    def exact_apply(self, rel: Relations, scale: np.ndarray, trans: int = 0):
        """X ↦ A X (``trans=1``: Aᵀ X) of the scheme ``rel`` with row scales ``scale``, by
        the exact float64 operator (:func:`scheme_apply`, :func:`scheme_apply_t`); None for
        float64 schemes, whose dense matrix is that operator."""
        if not self.refine:
            return None
        if trans:
            return lambda Y: scheme_apply_t(self.d, rel, scale, Y, self.product)
        return lambda X: scheme_apply(self.d, rel, scale, X, self.product(X))

    def _regular_after_all(self, rel: Relations, scale: np.ndarray, f) -> bool:
        """For a float32 scheme whose rcond is at or below ``RCOND_MECHANISM_F32``: whether
        the exact operator is regular after all, i.e. its best null-vector candidate, refined
        against the exact operator, is not mapped to near zero (σ > 1e-6 ‖A‖, the float64
        criterion of :func:`null_modes`).  Such a scheme is used (its solves refine, or
        raise a SolverError if they cannot).  Float64 schemes: False (rcond decides)."""
        if not self.refine:
            return False
        A, _ = scheme_rows(self.G, self.d, rel, np.arange(self.n), self.shifted)
        anorm = max(norm2(A), 1e-300)
        del A
        apply = self.exact_apply(rel, scale)
        # f is the LU of this scheme; one candidate from inverse iteration, refined
        lu_m, piv = f
        dpiv = np.abs(np.diag(lu_m))
        tiny = np.finfo(lu_m.dtype).eps * max(float(dpiv.max(initial=0.0)), 1e-300)
        if np.any(dpiv < tiny):
            return False  # a zero pivot: singular beyond doubt
        x = np.random.default_rng(0).standard_normal((self.n, 1))
        for _ in range(3):
            x = np.linalg.qr(lu_solve(f, x))[0]
        for _ in range(4):
            dx = lu_solve(f, apply(x))
            x = np.linalg.qr(x - (dx - x @ (x.T @ dx)))[0]
        sigma = float(np.linalg.norm(apply(x)))
        return sigma > 1e-6 * anorm

    def factor(self, rel: Relations) -> SchemeFactor:
        """Factor of the scheme ``rel`` (raises :class:`MechanismError` if it is singular)."""
        key = rel.key()
        hit = self._cache.get(key)
        if hit is not None and hit.base.alive:
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
        idx = _changed_rows(rel, b.rel)
        if idx.size == 0:
            return self._plain(rel)
        if self._invert_instead(b, idx):
            self.counters["scheme_policy_inversions"] += 1
            self._refactor(rel)
            return self._plain(rel)
        slots = b.prepare(self, rel, idx)
        prev, order = self._bordered(b, slots)
        if order is not None:  # (the rows in the order of the capacitance reused)
            idx, slots = idx[order], slots[order]
        C = b.VZ[slots][:, slots]
        C.flat[:: len(slots) + 1] += 1.0
        # (measured against ‖I‖ = 1 at least: C = I + V Z and det A = det A₀ det C, so a
        # C far below the identity is singular even where it is 1 × 1 — whose own condition
        # number is always 1)
        cnorm = max(float(np.abs(C).sum(axis=0).max()), 1.0)
        if prev is not None:
            C_lu = _border_lu(prev, C)
            if not rcond(C_lu, anorm=cnorm) > self.rcond_update:
                prev = None  # (no pivoting across the border: the plain LU decides)
            else:
                self.counters["scheme_bordered"] += 1
        if prev is None:
            C_lu = _lapack("getrf", C)(C, overwrite_a=1)[:2]  # (small: LAPACK directly)
        self.counters["scheme_updates"] += 1
        if not rcond(C_lu, anorm=cnorm) > self.rcond_update:
            # ill-conditioned update, possibly singular: a full factorisation of this scheme
            self._refactor(rel)
            return self._plain(rel)
        b.caps.append((slots.copy(), b.version[slots], C_lu))
        if len(b.caps) > BORDER_KEEP:
            b.caps.pop(0)
        scale = b.scale.copy()
        scale[idx] = b.vscale[slots]
        fac = SchemeFactor(self, b, idx, b.V[slots], b.Z[:, slots], C_lu, scale, rel,
                           b.vsum[slots])
        if self._commit_now(b, idx.size):
            self._commit(fac)
            return self._plain(rel)
        return fac

    def _bordered(self, b: _Base, slots: np.ndarray):
        """A recent capacitance LU of the base ``b`` to extend to the slots ``slots`` (the
        changed rows of a new scheme): the largest one whose slots are all among them with
        their rows unchanged since (versions), at least ``BORDER_MIN`` of them and at least
        half of the new ones.  Returns (its (lu, piv), the order of ``slots`` that puts its
        slots first, in its order) or (None, None)."""
        best, bk = None, BORDER_MIN - 1
        where = None
        for cs, cv, lu in b.caps:
            k = len(cs)
            if k <= bk or 2 * k < len(slots) or k > len(slots):
                continue
            if where is None:
                where = np.full(b.k, -1)
                where[slots] = np.arange(len(slots))
            p = where[cs]
            if np.count_nonzero(p < 0) or not np.array_equal(b.version[cs], cv):
                continue
            best, bk = (lu, p), k
        if best is None:
            return None, None
        lu, p = best
        rest = np.ones(len(slots), bool)
        rest[p] = False
        return lu, np.concatenate([p, np.flatnonzero(rest)])

    def _costs(self, k: int) -> tuple[float, float]:
        """(commit, inversion) cost of a scheme k rows from the base, weighted flops
        (:data:`W_INVERT`): a commit 4 k n² (two BLAS-3 passes over X, at least two passes'
        worth of memory traffic), an inversion 2 n³ plus the rows of A formed from G."""
        n = self.n
        commit = 4.0 * k * n * n + W_PASS * 2.0 * n * n
        invert = W_INVERT * 2.0 * n ** 3 + W_PASS * 2.0 * n * n
        return commit, invert

    def _invert_instead(self, b: _Base, idx: np.ndarray) -> bool:
        """Default policy, before an update of the rows ``idx`` is set up: whether inverting
        the scheme afresh is cheaper than the update's set-up (its new rows: their columns,
        rows and products V Z, O(r K n); the capacitance's LU, (2/3) k³) followed by its
        commit — then the scheme is inverted without either."""
        if self.fixed_rank:
            return False
        k, n = idx.size, self.n
        r = int(np.count_nonzero(b.slot[idx] < 0))
        setup = self._setup_cost(b, r, b.k + r, k)
        commit, invert = self._costs(k)
        return min(setup + commit, setup + W_PASS * 4.0 * k * n * SOLVES_PER_SCHEME) > invert

    def _commit_now(self, b: _Base, k: int) -> bool:
        """Whether the update just set up (k rows from the base ``b``) is committed.

        With ``max_rank`` given, and for float32 schemes: when k exceeds it or the base has
        slots for more than twice it.  Float64 schemes by default: cost-based, a rent-or-buy
        rule (at most twice the cost of the best choice in hindsight).  Every update charges
        the base the weighted flops it adds over the base's own solves as they are spent —
        set-up (new rows' columns, rows and V Z: 2 r K n; the capacitance LU, (2/3) k³) and
        its solves (4 k n each) — and the scheme is committed once the charges since
        the base was made reach the price of that commit (4 k n², and the set-up of the
        other slots it drops), or when the slots cover half the rows (Z and V Z as large as
        X).  Schemes met on an excursion (a rate problem's stiff scheme hundreds of rows
        away, then back near the base) stay updates; schemes that have moved on are
        committed."""
        if self.fixed_rank:
            return k > self.max_rank or b.k > 2 * self.max_rank
        n = self.n
        b.spent += self._setup_cost(b, b.formed, b.k, k)
        b.formed = 0
        # a commit also drops the slots of the other K − k rows (an excursion's, formed again
        # when it recurs): their set-up is part of its price
        price = self._costs(k)[0] + self._setup_cost(b, b.k - k, b.k - k, 0)
        return b.spent >= price or 2 * b.k > n

    def _setup_cost(self, b: _Base, r: int, slots: int, k: int) -> float:
        """Weighted flops of an update's set-up: r rows formed from G and their columns of X
        copied (memory-bound, 2 r n (n_c + 1)), their products with the ``slots`` columns
        and rows of V Z (BLAS-3, 4 r K n) and the k × k capacitance's LU ((2/3) k³)."""
        n, nc = self.n, b.rel.layout.n_c
        return (W_PASS * 2.0 * r * n * (nc + 1) + 4.0 * r * slots * n
                + W_SMALL_LU * (2.0 / 3.0) * k ** 3)

    def refactored(self, fac: SchemeFactor) -> SchemeFactor:
        """A full factorisation of the scheme of ``fac`` (an update, or a base that has taken
        commits, whose float32 solves did not refine), which replaces it in the cache (raises
        :class:`MechanismError` if the scheme is singular)."""
        hit = self._cache.get(fac.rel.key())
        if (hit is not None and hit is not fac and hit.V is None and hit.base is self.base
                and not self.base.commits):
            return hit
        self._refactor(fac.rel)
        plain = self._plain(fac.rel)
        self._cache[fac.rel.key()] = plain
        return plain

    def dense(self, rel: Relations) -> tuple[np.ndarray, np.ndarray]:
        """The full equilibrated scheme matrix and its row scales (for tests and mechanisms;
        those of the last singular scheme are the read-only arrays that were factorised)."""
        if self._singular is not None and self._singular[0] == rel.key():
            return self._singular[1], self._singular[2]
        return scheme_rows(self.G, self.d, rel, np.arange(self.n), self.shifted)


def _border_lu(prev: tuple, C: np.ndarray) -> tuple:
    """The LU (LAPACK's form: (lu, piv), 0-based pivots) of C from that ``prev`` = (lu, piv)
    of its leading k × k block, by bordering: with P C₁₁ = L U,

        P C₁₂ = L Y,   X U = C₂₁,   S = C₂₂ − X Y,   P_s S = L_s U_s,

    C = [[Pᵀ L, 0], [P_sᵀ (P_s X), P_sᵀ L_s]] [[U, Y], [0, U_s]]: lu = [[lu₁₁, Y], [P_s X,
    lu_s]], piv = [piv, piv_s + k].  O(k² a + a³) for a new rows instead of O((k + a)³); no
    pivoting across the border (the caller checks the result's condition number)."""
    lu_p, piv_p = prev
    k, n = lu_p.shape[0], C.shape[0]
    if n == k:
        return prev
    dt = lu_p.dtype
    laswp = _lapack("laswp", lu_p)
    PB = laswp(np.array(C[:k, k:], dtype=dt, order="F"), piv_p)
    Y = sla.solve_triangular(lu_p, PB, lower=True, unit_diagonal=True, check_finite=False)
    X = sla.solve_triangular(lu_p, np.array(C[k:, :k].T, dtype=dt), lower=False, trans="T",
                             check_finite=False).T
    S = np.array(C[k:, k:] - X @ Y, dtype=dt, order="F")
    lu_s, piv_s = _lapack("getrf", S)(S, overwrite_a=1)[:2]
    out = np.empty((n, n), dt, order="F")
    out[:k, :k] = lu_p
    out[:k, k:] = Y
    out[k:, :k] = laswp(np.asfortranarray(X), piv_s)
    out[k:, k:] = lu_s
    return out, np.concatenate([piv_p, piv_s + k]).astype(piv_p.dtype)


def _lu_solve_block(f, B: np.ndarray) -> np.ndarray:
    """A⁻¹ B in the LU's precision (LAPACK getrs on a block; no conversion to float64)."""
    if B.size == 0:
        return B
    return _lapack("getrs", f[0])(f[0], f[1], B.astype(f[0].dtype, copy=False))[0]


__all__ = ["BACKWARD_GROWTH", "BACKWARD_TOL", "ETA_ACCEPT", "RCOND_MECHANISM",
           "RCOND_MECHANISM_F32", "RCOND_UPDATE", "RCOND_UPDATE_F32", "MechanismError",
           "SchemeFactor", "SchemeSolver",
           "lu", "lu_solve", "norm1", "norm2", "null_modes", "rcond", "scheme_apply",
           "scheme_apply_t", "scheme_rhs", "scheme_rows"]
