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

Between two events the working scheme writes one linear relation per CFE component, so the
rates along a load pattern follow from one dense solve of size 2m
(:mod:`stepcontact.solver.schemes`).

:class:`Condensation` is the reusable part: any sparse SPD operator A (K₀ here; K + 4M/Δt² +
2C/Δt or M for dynamics) with its one factorisation and its condensed matrix G = B A⁻¹ Bᵀ.
Friction, gaps, loads and the load program do not enter it, so runs that differ only in those
(a sweep of friction coefficients or load cases) share one factorisation.
"""

from __future__ import annotations

import hashlib
import os
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from stepcontact.errors import ModelError, SolverError
from stepcontact.fem.assembly import System
from stepcontact.solver.linalg import Factor, factorize

#: share of the machine's physical memory that the dense contact matrices may take
DENSE_MEMORY_SHARE = 0.5


def physical_memory() -> int | None:
    """Physical memory of this machine, bytes (None where the OS does not say)."""
    try:
        return int(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, ValueError, OSError):
        return None


def dense_memory(n2m: int, c: int = 0) -> dict[str, int]:
    """Estimated bytes of the dense work of a run with 2m = ``n2m`` contact unknowns: G, and
    the scheme solver's matrix, LU and update workspace (three more 2m × 2m arrays); and, for
    forming G as a Schur complement on ``c`` contact DOFs, the trailing dense block of the
    sparse factors with its extracted copies (three c × c arrays)."""
    return {"G": 8 * n2m**2, "schemes": 3 * 8 * n2m**2, "schur": 3 * 8 * c**2}


def _gb(b: float) -> str:
    return f"{b / 2**30:.1f} GB"


def check_dense_memory(n2m: int, limit: float | None = None) -> None:
    """Raise a :class:`SolverError` with the estimate when the dense contact matrices of
    2m = ``n2m`` unknowns would take more than ``limit`` bytes (default: DENSE_MEMORY_SHARE of
    the physical memory): the size at which dense G stops being sensible on this machine."""
    if limit is None:
        phys = physical_memory()
        if phys is None:
            return
        limit = DENSE_MEMORY_SHARE * phys
    est = dense_memory(n2m)
    need = est["G"] + est["schemes"]
    if need > limit:
        m = n2m // 2
        raise SolverError(
            f"the contact problem is too large for dense condensation on this machine: "
            f"{m} CFEs (2m = {n2m} contact unknowns) need about {_gb(need)} for G "
            f"({_gb(est['G'])}) and the scheme matrix with its LU ({_gb(est['schemes'])}), "
            f"more than the {_gb(limit)} allowed ({DENSE_MEMORY_SHARE:.0%} of physical "
            f"memory); coarsen the contact mesh, split the interface, or run on a machine "
            f"with at least {_gb(need / DENSE_MEMORY_SHARE)}")


def _fingerprint(*mats: sp.spmatrix) -> str:
    h = hashlib.blake2b(digest_size=16)
    for M in mats:
        M = sp.csr_matrix(M)
        M.sort_indices()
        h.update(np.asarray(M.shape, np.int64).tobytes())
        for a in (M.indptr, M.indices, M.data):
            h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


@dataclass(eq=False)
class Condensation:
    """A sparse SPD operator A (n × n) condensed onto 2m contact unknowns through B (2m × n).

    Holds the one factorisation of A and the dense condensed matrix G = B A⁻¹ Bᵀ (2m × 2m),
    computed by blocked multi-right-hand-side solves.  Nothing of the contact law, the gaps,
    the loads or the load program enters it: build it once and pass it to every run that
    shares the matrix (``solve_static(model, condensation=c)``); ``fingerprint`` identifies
    (A, B) so that a condensation is never applied to another model.

    Example
    -------
    >>> c = sc.condense(model)                                   # doctest: +SKIP
    >>> runs = [sc.solve_static(model.with_friction(f), condensation=c) for f in (0.3, 0.6)]
    ... # doctest: +SKIP
    """

    A: sp.csc_matrix
    B: sp.csr_matrix
    factor: Factor
    G: np.ndarray
    fingerprint: str
    counters: dict[str, float] = field(default_factory=dict)

    @classmethod
    def build(cls, A: sp.spmatrix, B: sp.spmatrix, backend: str = "auto", block: int = 256,
              factor: Factor | None = None, memory_limit: float | None = None) -> Condensation:
        """Factorise A (unless ``factor`` is given) with the DOFs that B touches ordered last,
        and read G off the trailing block of the factors (``Factor.condensed``, see
        :mod:`stepcontact.solver.linalg`) — or, for a backend without it or when that route
        costs more or would not fit (:func:`schur_pays`), form G with blocks of ``block``
        right-hand sides.
        Too many contact unknowns for dense G (:func:`check_dense_memory`, ``memory_limit``
        in bytes) is a :class:`SolverError` raised before any work."""
        t0 = time.perf_counter()
        A = sp.csc_matrix(A)
        B = sp.csr_matrix(B)
        check_dense_memory(B.shape[0], memory_limit)
        if factor is None:
            last = contact_dofs(B)
            factor = factorize(A, backend, last=last if schur_pays(A.shape[0], len(last),
                                                                     B.shape[0]) else None)
        t1 = time.perf_counter()
        n2m = B.shape[0]
        can = getattr(factor, "can_condense", lambda B: True)
        if hasattr(factor, "condensed") and can(B):  # Schur complement: no solve per row of B
            G = np.asarray(factor.condensed(B), dtype=float)
            solves = 0
        else:
            G = np.zeros((n2m, n2m))
            BT = B.T.tocsc()
            for s in range(0, n2m, block):
                X = factor.solve(BT[:, s : s + block].toarray())
                G[:, s : s + block] = B @ X.reshape(A.shape[0], -1)
            solves = n2m
        G = 0.5 * (G + G.T)
        counters = {"factorizations": 1, "solves": solves, "condensed_columns": solves,
                    "factor_seconds": t1 - t0, "condense_seconds": time.perf_counter() - t1}
        return cls(A, B, factor, G, _fingerprint(A, B), counters)

    def solve(self, b: np.ndarray) -> np.ndarray:
        """A⁻¹ b for a vector or a block of right-hand sides."""
        self.counters["solves"] = self.counters.get("solves", 0) + (
            1 if np.ndim(b) == 1 else np.shape(b)[1])
        return self.factor.solve(b)

    @property
    def m(self) -> int:
        return self.G.shape[0] // 2

    def __getstate__(self):
        raise TypeError("a Condensation holds a sparse factorisation and is not picklable; "
                        "build it where it is used (workers: sc.condense(model))")


def schur_fits(c: int, limit: float | None = None) -> bool:
    """Whether the dense trailing block of c contact DOFs (and its copies) fits in a quarter
    of ``limit`` (default: DENSE_MEMORY_SHARE of the physical memory)."""
    if limit is None:
        phys = physical_memory()
        limit = DENSE_MEMORY_SHARE * phys if phys else float("inf")
    return dense_memory(0, c)["schur"] <= 0.25 * limit


#: work of one flop of a sparse triangular solve against one of dense BLAS-3 work (measured
#: on SuperLU: per column a solve runs 5-10× below the dense rate)
SPARSE_SOLVE_PENALTY = 5.0


def schur_pays(n: int, c: int, n2m: int) -> bool:
    """Whether G is cheaper as the Schur complement on the c contact DOFs ((2/3)c³ for the
    trailing block and 4c²m for the two triangular solves, dense) than by 2m sparse solves
    (4·nnz(L) each, nnz(L) ≈ 4.5 n log₂ n on 2D meshes, at the sparse rate) — and fits.
    A compact joint (c ≪ n) takes the Schur route; a joint as long as the model (c ~ n^½ ... n)
    the solves."""
    if c == 0:
        return False
    schur = 2.0 / 3.0 * c**3 + 2.0 * c**2 * n2m
    nnz_l = 4.5 * n * np.log2(max(n, 2))
    solves = SPARSE_SOLVE_PENALTY * n2m * 4.0 * nnz_l
    return schur <= solves and schur_fits(c)


def contact_dofs(B: sp.spmatrix) -> np.ndarray:
    """The DOFs (columns) that the contact operator B touches, to be ordered last."""
    return np.flatnonzero(sp.csc_matrix(B).getnnz(axis=0))


def static_operator(system: System):
    """K₀ = K_ff + B_fᵀ D B_f and the pieces of the static condensation of ``system``:
    (K0, Bf, d, free, presc, Kff, Kfp, Bp, K)."""
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
    return K0, Bf, d, free, presc, Kff, Kfp, Bp, K


def condense(model, backend: str = "auto") -> Condensation:
    """The reusable condensation of a model (or assembled system) for the static solver:
    K₀ factorised once and G = B_f K₀⁻¹ B_fᵀ.  Pass it to :func:`solve_static` for every run
    that differs only in friction, gaps, loads or load program."""
    from stepcontact.fem.assembly import assemble

    system = model if isinstance(model, System) else assemble(model)
    K0, Bf, *_ = static_operator(system)
    free = np.flatnonzero(~system.fixed)
    t0 = time.perf_counter()
    factor = factorize_checked(system, K0, free, backend)
    t_factor = time.perf_counter() - t0
    c = Condensation.build(K0, Bf, backend, factor=factor)
    c.counters["factor_seconds"] = t_factor
    return c


def factorize_checked(system: System, K0, free, backend: str) -> Factor:
    """Factorise K₀ and make sure the structure with every CFE stuck is not a mechanism (one
    diagnosis naming the free bodies, whether the factorisation met a zero pivot or not)."""
    from stepcontact.solver.regularity import factorize_regular

    check_dense_memory(2 * system.m)
    last = contact_dofs(system.B[:, free])
    return factorize_regular(system, K0, free, backend,
                             last=last if schur_pays(len(free), len(last), 2 * system.m)
                             else None)


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
    condensation: Condensation | None = None

    @classmethod
    def from_system(cls, system: System, backend: str = "auto",
                    condensation: Condensation | None = None) -> Condensed:
        """Condense ``system`` (one factorisation, 2m block solves), or reuse
        ``condensation`` when it was built for the same K₀ and B (checked)."""
        K0, Bf, d, free, presc, Kff, Kfp, Bp, K = static_operator(system)
        if condensation is None:
            condensation = condense(system, backend)
            reused = 0
        else:
            if condensation.fingerprint != _fingerprint(K0, Bf):
                raise ModelError("condensation", "was built for another model: its stiffness or "
                                 "contact operator differ (build it with sc.condense(model))")
            reused = 1
        factor = condensation.factor
        nsolve = 0
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
        c = condensation.counters
        counters = {"factorizations": 0 if reused else 1,
                    "solves": nsolve + (0 if reused else c.get("condensed_columns", 0)),
                    "condensed_columns": 0 if reused else c.get("condensed_columns", 0),
                    "condensation_reused": reused}
        return cls(system, free, presc, factor, Bf, Bp, Kff, Kfp, d, condensation.G, hhat, e, y,
                   counters, r_load, R_s, R_t, condensation)

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

    # ---- fields ----------------------------------------------------------------------------
    def displacement(self, factors, s: np.ndarray, w: np.ndarray) -> np.ndarray:
        """Full displacement vector (ndof,) of a state, exact from its contact unknowns: one
        solve with the K₀ factorisation.  A stack of k states gives (k, ndof) with one
        multi-right-hand-side solve.

        ``factors``: {pattern: c} (c a number, or a (k,) array for a stack), or an array
        (k, P) of the factors in the order of ``system.loads``; ``s``, ``w``: (2m,) for one
        state or (k, 2m) for a stack.
        """
        sysm = self.system
        names = list(sysm.loads)
        single = np.ndim(s) == 1
        S = np.atleast_2d(np.asarray(s, dtype=float))
        W = np.atleast_2d(np.asarray(w, dtype=float))
        k = S.shape[0]
        if isinstance(factors, dict):
            unknown = [str(n) for n in factors if n not in sysm.loads]
            if unknown:
                raise KeyError(f"unknown load pattern(s): {', '.join(unknown)}")
            C = np.zeros((k, len(names)))
            for j, name in enumerate(names):
                if name in factors:
                    C[:, j] = factors[name]
        else:
            C = np.asarray(factors, dtype=float).reshape(k, len(names))
        if k == 0:
            return np.zeros((0, sysm.ndof))
        up = np.zeros((len(self.presc), k))
        rhs = np.zeros((len(self.free), k))
        e = np.zeros((2 * self.m, k))
        for j, name in enumerate(names):
            c = C[:, j]
            if not c.any():
                continue
            lv = sysm.loads[name]
            up += np.outer(lv.u[self.presc], c)
            rhs += np.outer(lv.f[self.free], c)
            e += np.outer(self.e[name], c)
        w_hat = W.T - sysm.w0[:, None] - e
        t = S.T - self.d[:, None] * w_hat
        rhs = rhs - self.Kfp @ up - self.Bf.T @ t
        x = np.asarray(self.factor.solve(np.ascontiguousarray(rhs[:, 0]) if k == 1 else rhs))
        u = np.zeros((k, sysm.ndof))
        u[:, self.free] = x.reshape(len(self.free), k).T
        u[:, self.presc] = up.T
        self.counters["solves"] = self.counters.get("solves", 0) + k
        return u[0] if single else u

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

    def mode_displacement(self, t: np.ndarray) -> np.ndarray:
        """Displacement of a mechanism mode t of the condensed unknowns."""
        u = np.zeros(self.system.ndof)
        u[self.free] = -self.factor.solve(self.Bf.T @ t)
        return u
