"""Independent references for verifying :mod:`stepcontact.solver.static` (helpers, no tests).

Frictionless unilateral contact is path independent: the final state is the minimiser of the
potential energy under the non-penetration constraints,

.. math::

    \\min_u \\tfrac12 u^T K u - f^T u
    \\quad\\text{s.t.}\\quad u_n = B_n u - g^0 \\le 0,
    \\quad u_P = \\bar u_P \\ (\\text{supports and prescribed displacements}),

with K, B_n = rows m..2m-1 of ``B`` and g⁰ = −w0[m:] taken from
:func:`stepcontact.fem.assembly.assemble`.  Its KKT conditions are the frictionless contact
conditions (1) of the article with p = −N ≥ 0:

.. math::

    K u + B_n^T p = f,\\quad u_n \\le 0,\\quad p \\ge 0,\\quad p\\,u_n = 0 .

A compliant contact layer (eq. (11), C_n = kn finite) is handled exactly by an extra variable
z = p / C_n per CFE: min ½uᵀKu + ½ Σ C_n z² − fᵀu s.t. B_n u − g⁰ − z ≤ 0, whose KKT conditions
are u_n + N/C_n ≤ 0, N ≤ 0, (u_n + N/C_n) N = 0.

How the reference is computed (two independent stages):

1. **Active-set identification** with a general QP solver that knows nothing about contact:
   ``quadprog`` (dense Goldfarb–Idnani, the default) or ``osqp`` (sparse ADMM).  Bodies held
   only by contact make K singular on the free DOFs; quadprog needs a strictly convex problem,
   so *in this stage only* K/k_s + δ I with δ = 1e-9 (k_s = largest diagonal entry of K) is
   used.  OSQP takes the singular K as it is.  ``"active_set"`` skips this stage and starts
   from all CFEs closed (used for the larger Hertz model where dense QP is too slow).
2. **Polishing** by a primal-dual active-set iteration on the exact (unregularised) problem:
   the saddle-point system [[K_FF, B_Aᵀ], [B_A, −D_A]] [u_F; p_A] = [f_F − K_FP ū_P;
   g⁰_A − B_AP ū_P] (D = 1/C_n, 0 for rigid contact) is solved by sparse LU, CFEs with p < 0
   leave the active set, open CFEs with u_n > 0 join it, until no sign is wrong.  The rigid
   modes of bodies held by contact are restrained by the active constraints, so the system is
   regular exactly when the contact state is statically admissible.

Tolerance: the polished solution satisfies the KKT conditions to round-off,
‖K u + B_nᵀp − f‖ / ‖f‖ ≲ 1e-13 · cond and sign violations ≤ 1e-12 (relative to the largest
|p| and |u|); see :func:`kkt_residuals`, which recomputes them independently of the solve.

Besides the frictionless reference this module has independent checks of a reported state of
a frictional path (:func:`equilibrium_residual`, :func:`contact_violation`) that use only the
assembled system and the reported u, N, Q and states.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from stepcontact.fem.assembly import System
from stepcontact.model import Model

#: relative regularisation of K used by the quadprog stage only (never in the final answer)
QUADPROG_DELTA = 1e-9


class ReferenceFailure(RuntimeError):
    """The reference could not be computed (mechanism, cycling of the active set)."""


# --------------------------------------------------------------------------------------------
# loads
# --------------------------------------------------------------------------------------------
def final_factors(model: Model) -> dict[str, float]:
    """Load factor of every pattern at the end of the load program (0 if never applied)."""
    out = {p.name: 0.0 for p in model.patterns}
    for name, _start, end in model.segments_resolved():
        out[name] = end
    return out


def load_at(system: System, factors: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
    """Total force vector f (N) and prescribed displacements ū (m; zero off ``fixed``)."""
    f = np.zeros(system.ndof)
    u = np.zeros(system.ndof)
    for name, lam in factors.items():
        lv = system.loads[name]
        f += lam * lv.f
        u += lam * lv.u
    u[~system.fixed] = 0.0
    return f, u


def _compliance(system: System) -> np.ndarray:
    """D = 1/C_n per CFE, m/N (0 for rigid contact)."""
    kn = np.asarray(system.cfe.kn, float)
    return np.where(np.isfinite(kn), 1.0 / np.where(np.isfinite(kn), kn, 1.0), 0.0)


# --------------------------------------------------------------------------------------------
# the frictionless reference
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ContactSolution:
    """Minimiser of the frictionless contact problem.

    Attributes
    ----------
    u : (ndof,) displacement, m (prescribed values on fixed DOFs)
    N : (m,) normal forces, N (≤ 0, compression)
    un : (m,) u_n = B_n u − g⁰, m (≤ 0; for a compliant layer u_n + N/C_n ≤ 0)
    active : (m,) bool, CFEs in contact
    method : str, the active-set identification stage used
    iterations : int, polishing iterations
    """

    u: np.ndarray
    N: np.ndarray
    un: np.ndarray
    active: np.ndarray
    method: str
    iterations: int

    @property
    def pressure(self) -> np.ndarray:
        """p = −N ≥ 0, N."""
        return -self.N


@dataclass(frozen=True)
class _Reduced:
    """The problem on the free DOFs, scaled by k_s (so forces become metres)."""

    free: np.ndarray
    K: sp.csr_matrix  # K_FF / k_s
    f: np.ndarray  # (f_F − K_FP ū_P) / k_s, m
    Bn: sp.csr_matrix  # B_nF
    g: np.ndarray  # g⁰ − B_nP ū_P, m
    D: np.ndarray  # k_s / C_n
    ks: float
    u_full: np.ndarray  # ū (prescribed values) in full numbering


def _reduce(system: System, factors: Mapping[str, float]) -> _Reduced:
    f, ubar = load_at(system, factors)
    free = np.flatnonzero(~system.fixed)
    fixed = np.flatnonzero(system.fixed)
    K = system.K.tocsr()
    ks = float(np.abs(K.diagonal()).max())
    m = system.m
    Bn = system.B.tocsr()[m:]
    g = -np.asarray(system.w0[m:], float)
    Kff = K[free][:, free] / ks
    rhs = (f[free] - K[free][:, fixed] @ ubar[fixed]) / ks
    Bf = Bn[:, free].tocsr()
    g_eff = g - Bn[:, fixed] @ ubar[fixed]
    return _Reduced(free, Kff.tocsr(), rhs, Bf, g_eff, _compliance(system) * ks, ks, ubar)


def _qp_active_quadprog(r: _Reduced) -> np.ndarray:
    import quadprog

    n = r.K.shape[0]
    comp = np.flatnonzero(r.D > 0)
    nz = len(comp)
    G = np.zeros((n + nz, n + nz))
    G[:n, :n] = r.K.toarray() + QUADPROG_DELTA * np.eye(n)
    G[n:, n:] = np.diag(1.0 / r.D[comp]) if nz else np.zeros((0, 0))
    G = 0.5 * (G + G.T)
    a = np.r_[r.f, np.zeros(nz)]
    # B_n x - z <= g  <=>  -B_n x + z >= -g
    C = np.zeros((n + nz, len(r.g)))
    C[:n] = -r.Bn.toarray().T
    C[n + np.arange(nz), comp] = 1.0
    _x, _obj, _xu, _it, lagr, _iact = quadprog.solve_qp(G, a, C, -r.g, 0)
    return lagr > 0


def _qp_active_osqp(r: _Reduced) -> np.ndarray:
    import osqp

    m = len(r.g)
    comp = np.flatnonzero(r.D > 0)
    nz = len(comp)
    P = sp.block_diag([r.K, sp.diags(1.0 / r.D[comp]) if nz else sp.csr_matrix((0, 0))])
    P = sp.triu(P, format="csc")
    q = -np.r_[r.f, np.zeros(nz)]
    Z = sp.csr_matrix((-np.ones(nz), (comp, np.arange(nz))), shape=(m, nz))
    A = sp.hstack([r.Bn, Z], format="csc")
    prob = osqp.OSQP()
    prob.setup(P, q, A, np.full(m, -np.inf), r.g, verbose=False, eps_abs=1e-10, eps_rel=1e-10,
               max_iter=200000, polishing=True)
    res = prob.solve()
    y = np.asarray(res.y, float)
    ymax = max(float(np.abs(y).max(initial=0.0)), 1e-300)
    return y > 1e-6 * ymax


def _solve_active(r: _Reduced, active: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Exact solution for a given active set: (x on free DOFs, p̂ = p / k_s on all CFEs)."""
    A = np.flatnonzero(active)
    BA = r.Bn[A]
    if len(A):
        M = sp.bmat([[r.K, BA.T], [BA, -sp.diags(r.D[A])]], format="csc")
    else:
        M = r.K.tocsc()
    rhs = np.r_[r.f, r.g[A]]
    n = r.K.shape[0]
    try:
        lu = spla.splu(M)
    except RuntimeError as exc:  # exactly singular: a mechanism for this active set
        raise ReferenceFailure(f"singular saddle-point system ({exc}): mechanism") from exc
    sol = lu.solve(rhs)
    piv = np.abs(lu.U.diagonal())
    resid = np.linalg.norm(M @ sol - rhs) / max(np.linalg.norm(rhs), 1e-300)
    if not np.all(np.isfinite(sol)) or piv.min() < 1e-13 * piv.max() or resid > 1e-8:
        raise ReferenceFailure(
            f"(numerically) singular saddle-point system: mechanism (smallest relative pivot "
            f"{piv.min() / piv.max():.1e}, residual {resid:.1e})")
    p = np.zeros(len(r.g))
    p[A] = sol[n:]
    return sol[:n], p


def _polish(r: _Reduced, active: np.ndarray, max_iter: int) -> tuple[np.ndarray, np.ndarray,
                                                                       np.ndarray, int]:
    """Primal-dual active-set iteration on the exact problem, from ``active``.

    All sign violations are corrected at once; if that gives a mechanism or an active set
    already visited, only the worst violation is corrected.
    """
    try:
        x, p = _solve_active(r, active)
    except ReferenceFailure:  # the identification stage left a mechanism: start bonded
        active = np.ones_like(active)
        x, p = _solve_active(r, active)
    seen = {active.tobytes()}
    for it in range(1, max_iter + 1):
        gapv = r.Bn @ x - r.g - r.D * p  # u_n + N/C_n  (≤ 0 wanted)
        x_scale = max(float(np.abs(x).max(initial=0.0)), float(np.abs(r.g).max(initial=0.0)),
                      1e-300)
        p_scale = max(float(np.abs(p).max(initial=0.0)), 1e-300)
        drop = active & (p < -1e-12 * p_scale)
        add = ~active & (gapv > 1e-12 * x_scale)
        if not drop.any() and not add.any():
            return x, p, active, it
        worst = active.copy()
        bad_p = np.where(drop, -p / p_scale, 0.0)
        bad_g = np.where(add, gapv / x_scale, 0.0)
        if bad_p.max() >= bad_g.max():
            worst[np.argmax(bad_p)] = False
        else:
            worst[np.argmax(bad_g)] = True
        for new in (active & ~drop | add, worst):
            if new.tobytes() in seen:
                continue
            try:
                x, p = _solve_active(r, new)
            except ReferenceFailure:
                continue
            active = new
            seen.add(new.tobytes())
            break
        else:
            raise ReferenceFailure("no admissible active set: mechanism or cycling")
    raise ReferenceFailure(f"no consistent active set after {max_iter} iterations")


def frictionless_reference(
    system: System,
    factors: Mapping[str, float] | None = None,
    *,
    method: str = "quadprog",
    max_iter: int = 200,
) -> ContactSolution:
    """Minimiser of the frictionless contact problem at the load ``factors``.

    ``factors`` maps pattern names to load factors (default: the end of the model's program).
    ``method`` is the active-set identification stage: ``"quadprog"``, ``"osqp"`` or
    ``"active_set"`` (start from all CFEs closed).  Friction coefficients of the model are
    ignored: the problem solved is the frictionless one.
    """
    if factors is None:
        factors = final_factors(system.model)
    r = _reduce(system, factors)
    m = system.m
    if m == 0:
        x = spla.spsolve(r.K.tocsc(), r.f)
        active0 = np.zeros(0, bool)
    elif method == "quadprog":
        active0 = _qp_active_quadprog(r)
    elif method == "osqp":
        active0 = _qp_active_osqp(r)
    elif method == "active_set":
        active0 = np.ones(m, bool)
    else:
        raise ValueError(f"unknown method '{method}'")
    if m:
        x, p, active, it = _polish(r, active0, max_iter)
    else:
        p, active, it = np.zeros(0), active0, 0
    u = r.u_full.copy()
    u[r.free] = x
    N = -p * r.ks
    un = system.B.tocsr()[m:] @ u + system.w0[m:]
    return ContactSolution(u, N, un, active, method, it)


# --------------------------------------------------------------------------------------------
# independent checks of a state
# --------------------------------------------------------------------------------------------
def equilibrium_residual(
    system: System, factors: Mapping[str, float], u: np.ndarray, N: np.ndarray, Q: np.ndarray
) -> float:
    """‖K u + Bᵀ s − f‖ on the free DOFs / max(‖f‖, ‖Bᵀ s‖, ‖K u‖), s = [Q; −N].

    Also 0 only if u takes the prescribed values on the fixed DOFs (their error, relative to
    max |u|, is added).
    """
    f, ubar = load_at(system, factors)
    s = np.r_[np.asarray(Q, float), -np.asarray(N, float)]
    Bts = system.B.T @ s if system.m else np.zeros(system.ndof)
    Ku = system.K @ u
    free = ~system.fixed
    r = Ku + Bts - f
    scale = max(np.linalg.norm(f[free]), np.linalg.norm(Bts[free]), np.linalg.norm(Ku[free]),
                1e-300)
    u_scale = max(float(np.abs(u).max(initial=0.0)), 1e-300)
    presc = float(np.abs(u[system.fixed] - ubar[system.fixed]).max(initial=0.0)) / u_scale
    return float(np.linalg.norm(r[free]) / scale + presc)


def contact_violation(
    system: System,
    u: np.ndarray,
    N: np.ndarray,
    Q: np.ndarray,
    state: np.ndarray | None = None,
    *,
    force_scale: float,
    length_scale: float,
) -> dict[str, float]:
    """Relative violations of the contact conditions (1) at one state (rigid contact).

    Forces are divided by ``force_scale`` (N) and displacements by ``length_scale`` (m).
    With ``state`` (ContactState ints: OPEN=0, STICK=1, SLIP_POS=2, SLIP_NEG=3) the
    conditions of each CFE's state are checked too: open ⇒ N = Q = 0; closed ⇒ u_n = 0;
    slip± ⇒ Q = ∓ f N (Q = −σ f N, σ = ±1 the slip direction).
    """
    m = system.m
    f = system.cfe.friction
    w = system.B @ u + system.w0 if m else np.zeros(0)
    un = w[m:]
    N = np.asarray(N, float)
    Q = np.asarray(Q, float)
    F, L = force_scale, length_scale
    out = {
        "penetration": float(np.max(un, initial=0.0)) / L,
        "tension": float(np.max(N, initial=0.0)) / F,
        "complementarity": float(np.max(np.abs(un * N), initial=0.0)) / (F * L),
        "friction": float(np.max(np.abs(Q) + f * N, initial=0.0)) / F,
    }
    if state is not None:
        st = np.asarray(state, int)
        opn = st == 0
        closed = (st == 1) | (st == 2) | (st == 3)
        sigma = np.where(st == 2, 1.0, np.where(st == 3, -1.0, 0.0))
        slip = sigma != 0
        out["open_forces"] = float(np.max(np.abs(np.r_[N[opn], Q[opn]]), initial=0.0)) / F
        out["closed_gap"] = float(np.max(np.abs(un[closed]), initial=0.0)) / L
        out["slip_law"] = float(
            np.max(np.abs(Q[slip] + sigma[slip] * f[slip] * N[slip]), initial=0.0)) / F
    return out


def kkt_residuals(
    system: System, factors: Mapping[str, float], u: np.ndarray, N: np.ndarray
) -> dict[str, float]:
    """Relative KKT residuals of a frictionless solution (recomputed from scratch).

    ``equilibrium``: :func:`equilibrium_residual` with Q = 0; ``penetration``: max(u_n + N/C_n)
    / max|u|; ``tension``: max(N) / max|N|; ``complementarity``: max|N (u_n + N/C_n)| /
    (max|N| max|u|).
    """
    m = system.m
    D = _compliance(system)
    un = system.B.tocsr()[m:] @ u + system.w0[m:] + D * N
    F = max(float(np.abs(N).max(initial=0.0)), 1e-300)
    L = max(float(np.abs(u).max(initial=0.0)), 1e-300)
    return {
        "equilibrium": equilibrium_residual(system, factors, u, N, np.zeros(m)),
        "penetration": float(np.max(un, initial=0.0)) / L,
        "tension": float(np.max(N, initial=0.0)) / F,
        "complementarity": float(np.max(np.abs(N * un), initial=0.0)) / (F * L),
    }


__all__ = [
    "ContactSolution",
    "ReferenceFailure",
    "contact_violation",
    "equilibrium_residual",
    "final_factors",
    "frictionless_reference",
    "kkt_residuals",
    "load_at",
]
