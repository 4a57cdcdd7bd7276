"""Regularity of K₀: factorise it once, or name the bodies that make it a mechanism.

K₀ = K_ff + B_fᵀ D B_f is singular exactly when the structure with every CFE stuck is a
mechanism.  A backend meets that in one of two ways: an exact zero pivot (SuperLU raises
"exactly singular", :func:`~stepcontact.solver.linalg.factorize` turns it into a
:class:`SolverError`), or a factorisation that "succeeds" with pivots at round-off level.
:func:`factorize_regular` treats both the same way: one diagnosis, computed from K₀ alone
(never from the failed or dubious factor), names the bodies that can move and their free mode.

The scale-aware singularity test
--------------------------------
With d = diag(K₀) the quantity measured is the smallest *Jacobi-scaled* Rayleigh quotient

    ρ = min_x  xᵀ K₀ x / xᵀ diag(K₀) x  =  λ_min(D^{-1/2} K₀ D^{-1/2}),      0 ≤ ρ ≤ 1,

i.e. the fraction of the diagonal stiffness of the softest mode that is real stiffness.  It is
independent of the units and the scale of every DOF (N/m against N·m/rad, 1 GPa against
30 GPa), unlike a condition number ‖K₀‖‖K₀⁻¹‖.  Round-off acts on that scaled matrix at the
level of eps: the stored stiffness annihilates a rigid mode only to about eps·K_ii per row, and
a Cholesky/LU factorisation is backward stable componentwise, |ΔK_ij| ≲ c·eps·√(K_ii K_jj),
which is invariant under diagonal scaling.  So

* a genuine mechanism gives ρ at round-off, ≲ eps (measured 1e-17…1e-16 for blocks held by one
  CFE, 38 to 25 000 DOFs; bounded by about (non-zeros per row)·eps ≈ 4e-15 even in the worst
  case of the matrix-vector product);
* a real stiffness k holding a mode gives ρ ≈ k / Σ(diagonal stiffness of the DOFs the mode
  moves): a 5 N/m spring holding a 3 × 3-node 30 GPa block (K_ii ≈ 6e10 N/m) gives 2e-11, the
  same spring holding a 65 × 65-node block 2e-14.

K₀ is declared singular when ρ < ``RHO_SINGULAR`` = 100·eps ≈ 2.2e-14: at least ~5× above
the worst-case round-off bound and ≥ 100× above the values met, while every real stiffness
whose share of its mode exceeds that level passes (the solve then still carries that mode with
a relative accuracy of about eps/ρ ≲ 1 %).  Below it a stiffness cannot be told from round-off
any more: the 5 N/m spring passes for blocks up to ~4 000 nodes (1089 nodes: ρ = 8e-14, 3.6×
the threshold) and the 65 × 65-node block (ρ = 2.0e-14, where the direct solve already misses
F/k by 0.2 %) is reported as a mechanism.  A fixed condition threshold cannot do this: the
weak spring above has a 1-norm condition estimate of 2.6e11 (3 × 3 nodes) to 1.3e14 (65 × 65),
across the former threshold of 1e13, while the block held by one CFE shows 4e17: where a
condition number lands depends on the mesh size and the units, not only on singularity.

ρ is obtained from the factor by a few steps of block inverse iteration on K₀ x = λ D x and a
Rayleigh–Ritz step evaluated with K₀ itself, so the value does not depend on how accurately
the backend factorised a nearly singular matrix (a non-finite solve counts as singular).  The
Rayleigh quotient is an upper bound of ρ: an unconverged iteration can only err towards
"regular", and a mechanism (ρ ≈ 0 against a next eigenvalue ≳ 1e-8) converges in one step.

When K₀ is clearly regular the check stops after two of the four steps (two solves fewer).
After j steps the smallest Ritz value obeys ρ_j ≤ c_j·λ_min·f₀^(−1/(2j)) for any spectrum
(c₂ = 4/3·3^(1/4) ≈ 1.76), f₀ being the largest share, in the D-norm, that a vector of the
random start block has in the softest mode (split the spectrum at σ: the modes above σ add at
most σ^(1−2j) to the numerator moment, those below at most σ times the denominator one, and
choose σ).  A K₀ with λ_min < RHO_SINGULAR can therefore show ρ₂ ≥ ``RHO_REGULAR`` = 10⁶·
RHO_SINGULAR only if f₀ < (1.76·10⁻⁶)⁴ ≈ 1e-23, whereas a random start gives f₀ of the order
of (diagonal stiffness of the mode's DOFs) / (trace of diag(K₀)): still ~1e-15 for 10⁸ DOFs
and a mode 10⁷ times softer than the average DOF, where f₀ < 1e-23 has a chance of ~1e-8.
So the early stop reaches the decision of the full iteration.  Below RHO_REGULAR (weak
springs, very soft structures) all four steps are made as before.

The diagnosis
-------------
The null modes are computed from the regularised matrix K₀ + δ·diag(K₀) (δ = 1e-10), which
factorises stably, by block inverse iteration with the generalised Rayleigh–Ritz step above
(a null vector of K₀ is an exact eigenvector of the regularised pencil, so δ does not bias it).
Per body, the motions of its DOFs (the body's rows of the D^{1/2}-scaled null basis) are
compared with its rigid-body motions u = T + θ ẑ×(x − x̄) (principal angles): the rigid
motions they contain are named as translation along x / y and rotation about a point, what is
left is an "internal mechanism".  Bodies whose DOFs do not move are not named.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from stepcontact.errors import ModelError, SolverError
from stepcontact.fem.assembly import System
from stepcontact.solver.linalg import Factor, factorize

#: K₀ is singular when its smallest Jacobi-scaled Rayleigh quotient is below this (see the
#: module docstring: round-off of a mechanism ≲ eps, real stiffness shares ≫ 100·eps)
RHO_SINGULAR = 100 * np.finfo(float).eps

#: after two inverse-iteration steps an estimate of ρ above this is final: K₀ is regular (a
#: ρ below RHO_SINGULAR cannot show such a value there, see the module docstring)
RHO_REGULAR = 1e6 * RHO_SINGULAR

#: relative diagonal shift δ of K₀ + δ·diag(K₀) used to find the null modes of a singular K₀
REGULARISATION = 1e-10

#: a body moves in the null space when its rows of the scaled, orthonormal null basis have a
#: singular value above this (the null vectors are accurate to ~1e-12 or better)
MOVE_TOL = 1e-6

#: a rigid motion belongs to a body's motions when the cosine of its principal angle with them
#: exceeds 1 − this (exact inclusion gives 1, a nearly rigid internal mode stays well below)
RIGID_TOL = 1e-6

_KNOWN_BACKENDS = ("auto", "cholmod", "dense", "pypardiso", "scipy")


def factorize_regular(system: System, K0: sp.spmatrix, free: np.ndarray,
                      backend: str = "auto", last: np.ndarray | None = None) -> Factor:
    """Factorise K₀ (free DOFs ``free`` of ``system``), or raise a :class:`ModelError`
    naming the bodies that can move if K₀ is singular.

    Singular means either an exact zero pivot (the backend raises) or a smallest
    Jacobi-scaled Rayleigh quotient below :data:`RHO_SINGULAR` (see the module docstring).
    Both give the same message, e.g. ``model: the structure is a mechanism even with every CFE
    stuck: body 'block' can move freely (translation along x); add supports, springs or
    contact interfaces``.  ``last``: DOFs to order last (see :func:`linalg.factorize`).
    """
    return factorize_regular_solving(system, K0, free, None, backend, last)[0]


def factorize_regular_solving(system: System, K0: sp.spmatrix, free: np.ndarray,
                              rhs: np.ndarray | None, backend: str = "auto",
                              last: np.ndarray | None = None
                              ) -> tuple[Factor, np.ndarray | None]:
    """:func:`factorize_regular`, and K₀⁻¹ ``rhs`` (n × k, or None) solved in the same call
    as the check's first step (:func:`stiffness_and_solve`)."""
    K0 = sp.csc_matrix(K0)
    try:
        factor = factorize(K0, backend, last=last, groups=system.dofs.node_of()[free])
    except _singular_errors():
        if backend not in _KNOWN_BACKENDS:  # "unknown backend" is not a singular matrix
            raise
        raise mechanism_error(system, K0, free, backend) from None
    rho, X = stiffness_and_solve(K0, factor, rhs, regular_above=RHO_REGULAR)
    if rho < RHO_SINGULAR:
        raise mechanism_error(system, K0, free, backend)
    return factor, X


def _singular_errors() -> tuple[type[BaseException], ...]:
    """What a backend raises on a singular K₀: SolverError (SuperLU's exact zero pivot, as
    converted by linalg.factorize) and CHOLMOD's not-positive-definite error, which
    linalg.factorize lets through."""
    try:
        from sksparse.cholmod import CholmodNotPositiveDefiniteError
    except ImportError:
        return (SolverError,)
    return (SolverError, CholmodNotPositiveDefiniteError)


def _weights(K0: sp.spmatrix, diag: np.ndarray | None = None) -> np.ndarray:
    """diag(K₀) (``diag``, when already at hand), with DOFs of no stiffness at all weighted
    like an average DOF."""
    d = np.asarray(K0.diagonal() if diag is None else diag, dtype=float)
    pos = d > 0
    fallback = float(np.mean(d[pos])) if pos.any() else 1.0
    return np.where(pos, d, fallback)


def _start(n: int, p: int) -> np.ndarray:
    """The (fixed, random) start block of the inverse iteration, n × p."""
    return np.random.default_rng(0).standard_normal((n, p))


def _ritz(K0: sp.spmatrix, solve, d: np.ndarray, p: int, iterations: int = 4,
          stop_above: float = np.inf, first: np.ndarray | None = None):
    """Block inverse iteration X ← solve(D X) on the pencil (K₀, D) from X = :func:`_start`,
    then Rayleigh–Ritz with K₀: Ritz values ρ (ascending) and D-orthonormal Ritz vectors
    (columns).  None if the solves stop being finite.  With ``stop_above`` finite, the Ritz
    values are also formed after the second and later steps, and the iteration stops there
    once the smallest one is at least ``stop_above`` (see :data:`RHO_REGULAR`).  ``first``:
    the first step's solve(D X), made by the caller (solved with other right-hand sides)."""
    n = K0.shape[0]
    s = np.sqrt(d)
    with np.errstate(all="ignore"):
        for step in range(1, iterations + 1):
            if step == 1 and first is not None:
                X = np.asarray(first).reshape(n, p)
            else:
                X = np.asarray(solve(d[:, None] * (_start(n, p) if step == 1 else X)))
                X = X.reshape(n, p)
            if not np.all(np.isfinite(X)):
                return None
            X = np.linalg.qr(s[:, None] * X)[0] / s[:, None]  # XᵀDX = I
            if 2 <= step < iterations and np.isfinite(stop_above):
                H = X.T @ (K0 @ X)
                if np.all(np.isfinite(H)):
                    rho, V = np.linalg.eigh(0.5 * (H + H.T))
                    if rho[0] >= stop_above:
                        return rho, X @ V
        H = X.T @ (K0 @ X)
    if not np.all(np.isfinite(H)):
        return None
    rho, V = np.linalg.eigh(0.5 * (H + H.T))
    return rho, X @ V


def relative_stiffness(K0: sp.spmatrix, factor: Factor, p: int = 2,
                       regular_above: float = np.inf) -> float:
    """ρ = min xᵀK₀x / xᵀdiag(K₀)x (dimensionless) estimated with the factor of K₀ (an upper
    bound that is sharp after the four inverse-iteration steps done here); 0 when K₀ has a
    DOF of no stiffness or the solves overflow.  K₀ is singular when ρ < :data:`RHO_SINGULAR`.
    ``regular_above`` (e.g. :data:`RHO_REGULAR`): stop after two steps when the estimate is
    already at least this — then a less sharp upper bound, only good for the decision."""
    return stiffness_and_solve(K0, factor, None, p, regular_above)[0]


def stiffness_and_solve(K0: sp.spmatrix, factor: Factor, rhs: np.ndarray | None,
                        p: int = 2, regular_above: float = np.inf
                        ) -> tuple[float, np.ndarray | None]:
    """:func:`relative_stiffness` ρ, and K₀⁻¹ ``rhs`` (n × k; None: none) solved together with
    the first inverse-iteration step (one multi-right-hand-side solve reads the factor once
    for both: a run's load cases cost no solve call of their own)."""
    n = K0.shape[0]
    if rhs is not None:
        rhs = np.asarray(rhs, dtype=float).reshape(n, -1)
    if n == 0:
        return np.inf, rhs
    diag = np.asarray(K0.diagonal(), dtype=float)
    if np.any(diag <= 0):  # (singular: the solutions are not needed)
        return 0.0, None if rhs is None else np.zeros_like(rhs)
    d = _weights(K0, diag)
    p = min(p, n)
    first = X = None
    if rhs is not None:
        Y = np.asarray(factor.solve(np.hstack([d[:, None] * _start(n, p), rhs])))
        Y = Y.reshape(n, p + rhs.shape[1])
        first, X = Y[:, :p], Y[:, p:]
    out = _ritz(K0, factor.solve, d, p, stop_above=regular_above, first=first)
    return (0.0 if out is None else max(float(out[0][0]), 0.0)), X


def null_modes(K0: sp.spmatrix, backend: str = "auto", p: int = 6) -> np.ndarray:
    """Basis (columns, D-orthonormal, D = diag(K₀)) of the null space of a singular K₀:
    the Ritz vectors with ρ < :data:`RHO_SINGULAR`, from the factor of the regularised
    K₀ + δ·diag(K₀) (the smallest one if none is that small).  The block grows until it holds
    a non-null vector."""
    K0 = sp.csr_matrix(K0)
    n = K0.shape[0]
    d = _weights(K0)
    factor = factorize((K0 + sp.diags(REGULARISATION * d)).tocsc(), backend)
    p = max(1, min(p, n))
    while True:
        out = _ritz(K0, factor.solve, d, p)
        if out is None:  # cannot happen for a PSD K₀; report the block as it stands
            return np.zeros((n, 0))
        rho, Z = out
        null = rho < RHO_SINGULAR
        if not null.all() or p == n:
            break
        p = min(n, 2 * p)
    if not null.any():
        null[0] = True
    return Z[:, null]


def _rigid_basis(system: System, body) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Global DOFs of a body and its rigid motions on them: columns translation x,
    translation y, rotation about the centroid x̄ (u = θ ẑ×(x − x̄), rz = θ); x̄ and the
    body's size L (rms distance of its nodes from x̄)."""
    ids = system.model.node_offsets[body.name] + np.arange(body.n_nodes)
    of = system.dofs.of[ids]
    pts = np.asarray(body.points, dtype=float)
    xbar = pts.mean(axis=0)
    dx = pts - xbar
    L = float(np.sqrt(np.mean(np.sum(dx**2, axis=1))))
    if not L > 0:
        L = 1.0
    n = len(ids)
    zero, one = np.zeros(n), np.ones(n)
    cols = (np.column_stack([one, zero, -dx[:, 1]]),  # ux
            np.column_stack([zero, one, dx[:, 0]]),  # uy
            np.column_stack([zero, zero, one]))  # rz (frames)
    has = of >= 0
    dofs = np.concatenate([of[has[:, c], c] for c in range(3)])
    R = np.concatenate([cols[c][has[:, c]] for c in range(3)])
    dofs, first = np.unique(dofs, return_index=True)
    return dofs, R[first], xbar, L


def _fmt(v: float, L: float) -> str:
    """A coordinate rounded to 1e-4 of the body size (stable across round-off)."""
    q = 10.0 ** (np.floor(np.log10(L)) - 4)
    s = f"{round(v / q) * q:.6g}"
    return "0" if s == "-0" else s


def _rigid_text(C: np.ndarray, xbar: np.ndarray, L: float) -> list[str]:
    """Name the rigid motions spanned by the columns of C = (T_x, T_y, θ)."""
    if C.shape[1] == 0:
        return []
    V = C * np.array([1.0, 1.0, L])[:, None]  # comparable units (T, θL)
    U, sv, _ = np.linalg.svd(V, full_matrices=False)
    V = U[:, sv > 1e-8 * sv[0]]
    r = V.shape[1]
    if r == 3:
        return ["any rigid-body motion: translation along x and y, rotation"]
    e = V[2]
    parts = []
    if np.linalg.norm(e) < 1e-6:
        trans, rot = V, None
    else:
        trans = V @ sla.null_space(e[None, :]) if r > 1 else V[:, :0]
        rot = V @ (e / np.linalg.norm(e))
    if trans.shape[1] == 2:
        parts.append("translation along x and y")
    elif trans.shape[1] == 1:
        t = trans[:2, 0] / np.linalg.norm(trans[:2, 0])
        t = t if t[np.argmax(np.abs(t))] > 0 else -t
        if abs(t[1]) < 1e-6:
            parts.append("translation along x")
        elif abs(t[0]) < 1e-6:
            parts.append("translation along y")
        else:
            parts.append(f"translation along ({t[0]:.3g}, {t[1]:.3g})")
    if rot is not None:
        theta = rot[2] / L
        c = xbar + np.array([-rot[1], rot[0]]) / theta
        parts.append(f"rotation about ({_fmt(c[0], L)}, {_fmt(c[1], L)})")
    return parts


def describe_free_bodies(system: System, Z: np.ndarray, free: np.ndarray,
                         K0: sp.spmatrix) -> list[str]:
    """``"body 'b' can move freely (<modes>)"`` for every body moved by the null modes Z
    (columns over the free DOFs ``free``, D-orthonormal with D = diag(K₀))."""
    K = system.K.tocsr()
    w = np.asarray(K.diagonal(), dtype=float)  # fixed DOFs: weight of their own stiffness
    w[free] = _weights(K0)
    w = np.sqrt(np.where(w > 0, w, float(np.mean(w[w > 0])) if np.any(w > 0) else 1.0))
    Y = np.zeros((system.ndof, Z.shape[1]))
    Y[free] = w[free, None] * Z  # orthonormal: the null modes in D^{1/2}-scaled DOFs
    out = []
    if system.discrete is not None and Y.shape[1]:  # DOFs without nodes: name the DOFs
        moving = np.flatnonzero(np.linalg.norm(Y, axis=1) > MOVE_TOL)
        names = [system.discrete.dof_names[d] for d in moving[:12]]
        more = f" and {moving.size - 12} more" if moving.size > 12 else ""
        out.append(f"DOFs {', '.join(names)}{more} can move freely ({Y.shape[1]} "
                   f"mode{'s' if Y.shape[1] > 1 else ''})")
    for body in system.model.bodies:
        dofs, R, xbar, L = _rigid_basis(system, body)
        if Y.shape[1] == 0 or dofs.size == 0:
            continue
        Ub, sb, _ = np.linalg.svd(Y[dofs], full_matrices=False)
        M = Ub[:, sb > MOVE_TOL]  # the motions of this body's DOFs
        if M.shape[1] == 0:
            continue
        Ur, sr, Vtr = np.linalg.svd(w[dofs, None] * R, full_matrices=False)
        keep = sr > 1e-12 * sr[0]
        Q = Ur[:, keep]
        Ua, cos, _ = np.linalg.svd(Q.T @ M, full_matrices=False)
        rigid = Ua[:, cos > 1.0 - RIGID_TOL]  # rigid motions inside the body's motions
        C = Vtr[keep].T @ (rigid / sr[keep, None])  # back to (T_x, T_y, θ)
        parts = _rigid_text(C, xbar, L)
        if M.shape[1] > rigid.shape[1]:
            parts.append("internal mechanism")
        modes = parts[0] if len(parts) == 1 else ", ".join(parts[:-1]) + " and " + parts[-1]
        out.append(f"body '{body.name}' can move freely ({modes})")
    return out


def mechanism_error(system: System, K0: sp.spmatrix, free: np.ndarray,
                    backend: str = "auto") -> ModelError:
    """The one diagnosis of a singular K₀ (whichever way it was found): a ModelError naming
    the bodies that can move and their free modes."""
    try:
        Z = null_modes(K0, backend)
    except SolverError:  # the regularised matrix too (cannot happen for a PSD K₀)
        Z = np.zeros((K0.shape[0], 0))
    where = describe_free_bodies(system, Z, np.asarray(free), K0)
    text = ": " + ", ".join(where) if where else ""
    return ModelError(
        "model",
        f"the structure is a mechanism even with every CFE stuck{text}; add supports, "
        "springs or contact interfaces",
    )


__all__ = ["RHO_REGULAR", "RHO_SINGULAR", "describe_free_bodies", "factorize_regular",
           "factorize_regular_solving", "mechanism_error", "null_modes", "relative_stiffness",
           "stiffness_and_solve"]
