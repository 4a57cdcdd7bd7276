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

import contextlib
import functools
import hashlib
import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp

from stepcontact.contact.layout import ContactLayout
from stepcontact.errors import ModelError, SolverError
from stepcontact.fem.assembly import System
from stepcontact.model import size as _size
from stepcontact.solver.clock import Stopwatch
from stepcontact.solver.cluster import ColumnJob
from stepcontact.solver.linalg import Factor, factorize, one_blas_thread

#: share of the machine's physical memory that the dense contact matrices may take
DENSE_MEMORY_SHARE = 0.5


def dense_memory(n2m: int, c: int = 0, itemsize: int = 8) -> dict[str, int]:
    """Estimated bytes of the dense work of a run with 2m = ``n2m`` contact unknowns: G, and
    the scheme solver's LU, the LU of a refactorisation in flight (the old base is kept until
    the new scheme is known to be regular) and the update workspace (up to max(48, 2m/10)
    columns and rows): 2.25 more 2m × 2m arrays; and, for forming G as a
    Schur complement on ``c`` contact DOFs, the dense c × c block (PARDISO's Schur
    complement S, factorised in place, or SuperLU's trailing block of L, then of U) and two
    dense c × 2m arrays (B_cᵀ and its triangular solve, ``linalg.condensed_cholesky``), in
    float64.  ``itemsize``: 8 for float64 dense matrices, 4 for float32
    (``precision="float32"``)."""
    return {"G": itemsize * n2m**2, "schemes": int(2.25 * itemsize * n2m**2),
            "schur": 8 * (c**2 + 2 * c * n2m)}


def _gb(b: float) -> str:
    return f"{b / 2**30:.1f} GB"


#: precisions of the dense contact matrices, by name
PRECISIONS = {"float64": np.dtype(np.float64), "float32": np.dtype(np.float32)}


def _memory_limit(limit: float | None) -> float | None:
    if limit is not None:
        return limit
    phys = _size.physical_memory()
    return None if phys is None else DENSE_MEMORY_SHARE * phys


def dense_precision(n2m: int, precision: str = "auto", limit: float | None = None) -> np.dtype:
    """The precision of the dense contact matrices for 2m = ``n2m`` unknowns: ``float64``,
    ``float32`` (half the memory; every scheme solve refined to float64 accuracy against the
    sparse factorisation), or ``auto``: float64 while it fits in ``limit`` bytes (default:
    DENSE_MEMORY_SHARE of the physical memory), float32 beyond.  Raises a
    :class:`SolverError` with the estimate when the chosen (or every) precision does not fit:
    the size at which dense condensation stops being sensible on this machine."""
    if precision not in ("auto", *PRECISIONS):
        raise ModelError("precision", f"must be auto, float64 or float32, got '{precision}'")
    limit = _memory_limit(limit)
    names = ("float64", "float32") if precision == "auto" else (precision,)
    if limit is None:
        return PRECISIONS[names[0]]
    for name in names:
        est = dense_memory(n2m, itemsize=PRECISIONS[name].itemsize)
        if est["G"] + est["schemes"] <= limit:
            return PRECISIONS[name]
    m = ContactLayout.of_size(n2m).m
    need = est["G"] + est["schemes"]
    raise SolverError(
        f"the contact problem is too large for dense condensation on this machine: "
        f"{m} CFEs (2m = {n2m} contact unknowns) need about {_gb(need)} in {names[-1]} for G "
        f"({_gb(est['G'])}) and the scheme LU with its workspace ({_gb(est['schemes'])}), "
        f"more than the {_gb(limit)} allowed ({DENSE_MEMORY_SHARE:.0%} of physical "
        f"memory); coarsen the contact mesh, split the interface, or run on a machine "
        f"with at least {_gb(need / DENSE_MEMORY_SHARE)}")


def check_dense_memory(n2m: int, limit: float | None = None, precision: str = "auto") -> None:
    """Raise a :class:`SolverError` with the estimate when the dense contact matrices of
    2m = ``n2m`` unknowns would take more than ``limit`` bytes in ``precision`` (see
    :func:`dense_precision`)."""
    dense_precision(n2m, precision, limit)


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
    read off the factors or computed by blocked multi-right-hand-side solves, in float64 or,
    for large interfaces, float32 (``precision``).  In float32 the array ``G`` holds the
    shifted matrix D G − I (``d``: the row weights D of the static condensation): the free
    rows of a scheme, e_j − d_j G_j, nearly cancel where d_j G_jj ≈ 1 (a stiff structure), and
    rounding G itself to float32 would leave them no correct digit; D G − I carries them, and
    the stuck rows −G_j = −(M_j + e_j)/d_j, to float32 precision.  :meth:`product` gives G t
    exactly, by one sparse solve, for the refinement of the float32 schemes.

    Nothing of the contact law, the gaps, the loads or the load program enters it: build it
    once and pass it to every run that shares the matrix
    (``solve_static(model, condensation=c)``); ``fingerprint`` identifies (A, B) so that a
    condensation is never applied to another model (a hash of both, computed when first
    asked for: a run that builds its own condensation never needs it).

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
    counters: dict[str, float] = field(default_factory=dict)
    #: row weights D of the shifted float32 form (None for float64 G)
    d: np.ndarray | None = None
    #: tangential components per CFE of the contact unknowns (1 in 2D, 2 in 3D)
    n_t: int = 1
    #: the fingerprint of (A, B) once computed (:attr:`fingerprint`)
    _fp: str | None = field(default=None, repr=False)

    @property
    def fingerprint(self) -> str:
        """A hash of (A, B) (their shapes, sparsity patterns and values), computed once when
        first asked for: what a reuse of the condensation is checked against."""
        if self._fp is None:
            self._fp = _fingerprint(self.A, self.B)
        return self._fp

    @classmethod
    def build(cls, A: sp.spmatrix, B: sp.spmatrix, backend: str = "auto", block: int = 256,
              factor: Factor | None = None, memory_limit: float | None = None,
              precision: str = "auto", d: np.ndarray | None = None,
              scheduler: Any = None, columns: ColumnJob | None = None) -> Condensation:
        """Factorise A (unless ``factor`` is given) with the DOFs that B touches ordered last,
        and read G off the trailing block of the factors (``Factor.condensed``, see
        :mod:`stepcontact.solver.linalg`) — or, for a backend without it or when that route
        costs more or would not fit (:func:`schur_pays`), form G with blocks of ``block``
        right-hand sides.
        ``precision`` (:func:`dense_precision`): ``auto`` keeps G in float64 while the dense
        work fits in ``memory_limit`` bytes (default: half the physical memory), float32
        beyond; too many contact unknowns for either is a :class:`SolverError` raised before
        any work.  Float32 holds D G − I (``d``: D's diagonal, default ones).

        ``scheduler``: a dask scheduler's address (``tcp://HOST:PORT``) or a
        ``distributed.Client``: G's column blocks are solved on that cluster, each worker
        factorising A once (:mod:`stepcontact.solver.cluster`), while A is factorised here for
        the solves of the runs; G equals the serial one to round-off.  ``columns``: such a job
        already submitted (:class:`~stepcontact.solver.cluster.ColumnJob`)."""
        t0 = Stopwatch.start()
        A = sp.csc_matrix(A)
        B = sp.csr_matrix(B)
        dtype = dense_precision(B.shape[0], precision, memory_limit)
        shifted = dtype != np.float64
        if shifted:
            d = np.ones(B.shape[0]) if d is None else np.asarray(d, dtype=float)
        fingerprint = None if columns is None else columns.fingerprint
        with contextlib.ExitStack() as own:
            if columns is None and scheduler is not None and B.shape[0]:
                fingerprint = _fingerprint(A, B)
                columns = own.enter_context(ColumnJob(scheduler, A, B, fingerprint, backend,
                                                      dtype, d if shifted else None, block))
            if factor is None:
                last = contact_dofs(B)
                schur = columns is None and schur_pays(A.shape[0], len(last), B.shape[0])
                factor = factorize(A, backend, last=last if schur else None)
            t1 = Stopwatch.start()
            G, counters = cls._form(A, B, factor, dtype, d, block, columns)
        counters.update({"factorizations": 1, **t0.counters("factor", t1),
                         **t1.counters("condense")})
        return cls(A, B, factor, G, counters, d if shifted else None, _fp=fingerprint)

    @staticmethod
    def _form(A: sp.csc_matrix, B: sp.csr_matrix, factor: Factor, dtype: np.dtype,
              d: np.ndarray | None, block: int,
              columns: ColumnJob | None) -> tuple[np.ndarray, dict[str, float]]:
        """G (float64, symmetrised) or D G − I (float32) from the cluster's ``columns``, the
        factors' trailing block, or blocks of ``block`` solves; with its counters."""
        n2m = B.shape[0]
        shifted = dtype != np.float64
        extra: dict[str, float] = {}
        can = getattr(factor, "can_condense", lambda B: True)
        if columns is not None:  # on a cluster: the serial blocked route's arithmetic
            G, extra = columns.result()
            solves = n2m
        elif hasattr(factor, "condensed") and can(B):  # Schur complement: no solve per row
            G = np.asarray(factor.condensed(B), dtype=float)
            if shifted:
                _symmetrise(G)
                G *= d[:, None]
                G[np.diag_indices(n2m)] -= 1.0
                G = G.astype(dtype)
            solves = 0
        else:
            G = np.zeros((n2m, n2m), dtype)
            BT = B.T.tocsc()

            def columns_of(s: int) -> None:
                X = factor.solve(BT[:, s : s + block].toarray())
                Gs = B @ X.reshape(A.shape[0], -1)
                if shifted:  # D G − I, column block by column block
                    Gs *= d[:, None]
                    Gs[np.arange(s, s + Gs.shape[1]), np.arange(Gs.shape[1])] -= 1.0
                G[:, s : s + block] = Gs

            starts = range(0, n2m, block)
            threads = solve_threads(factor, len(starts))
            if threads > 1:  # each block's arithmetic as in one thread: the same G
                # (BLAS held to one thread: the solver threads take the cores)
                with one_blas_thread(0), ThreadPoolExecutor(threads) as pool:
                    list(pool.map(columns_of, starts))
                extra["solve_threads"] = threads
            else:
                for s in starts:
                    columns_of(s)
            solves = n2m
        if not shifted:
            _symmetrise(G)
        return G, {"solves": solves, "condensed_columns": solves, **extra}

    def solve(self, b: np.ndarray) -> np.ndarray:
        """A⁻¹ b for a vector or a block of right-hand sides."""
        self.counters["solves"] = self.counters.get("solves", 0) + (
            1 if np.ndim(b) == 1 else np.shape(b)[1])
        return self.factor.solve(b)

    def product(self, t: np.ndarray) -> np.ndarray:
        """G t = B A⁻¹ Bᵀ t in float64 by one sparse solve (a vector or a block): the exact
        operator that float32 schemes are refined against."""
        x = np.asarray(self.solve(np.asarray(self.B.T @ t))).reshape(self.A.shape[0], -1)
        out = self.B @ x
        return out.ravel() if np.ndim(t) == 1 else out

    @property
    def precision(self) -> str:
        """``float64`` or ``float32``: the precision G is held in (float32: as D G − I)."""
        return str(self.G.dtype)

    @property
    def layout(self) -> ContactLayout:
        """The layout of the contact unknowns (the rows of G; ``n_t`` of the system)."""
        return ContactLayout.of_size(self.G.shape[0], self.n_t)

    @property
    def m(self) -> int:
        return self.layout.m

    def __getstate__(self):
        raise TypeError("a Condensation holds a sparse factorisation and is not picklable; "
                        "build it where it is used (workers: sc.condense(model))")


#: threads that solve G's column blocks at once with a factor whose solves may run
#: concurrently and release the GIL (SciPy's SuperLU: its triangular solves read the factors
#: only, with thread-local work memory); PARDISO's solves are threaded inside MKL and one
#: handle takes one solve at a time
SOLVE_THREADS = 2


def solve_threads(factor: Factor, blocks: int) -> int:
    """How many threads solve the ``blocks`` column blocks of G with ``factor``: up to
    :data:`SOLVE_THREADS` (no more than the cores) for SciPy's SuperLU, else 1."""
    if getattr(factor, "name", "") != "scipy-superlu" or blocks < 2:
        return 1
    return max(1, min(SOLVE_THREADS, os.cpu_count() or 1, blocks))


def _symmetrise(G: np.ndarray, block: int = 1024) -> None:
    """G ← (G + Gᵀ)/2 in place, by blocks (no 2m × 2m temporaries)."""
    n = G.shape[0]
    for i in range(0, n, block):
        for j in range(i, n, block):
            S = 0.5 * (G[i : i + block, j : j + block] + G[j : j + block, i : i + block].T)
            G[i : i + block, j : j + block] = S
            G[j : j + block, i : i + block] = S.T


def schur_fits(c: int, limit: float | None = None, n2m: int = 0) -> bool:
    """Whether the dense work of the Schur route on c contact DOFs for 2m = ``n2m`` contact
    unknowns (:func:`dense_memory`) fits in a quarter of ``limit`` (default:
    DENSE_MEMORY_SHARE of the physical memory)."""
    if limit is None:
        phys = _size.physical_memory()
        limit = DENSE_MEMORY_SHARE * phys if phys else float("inf")
    return dense_memory(n2m, c)["schur"] <= 0.25 * limit


#: work of one flop of a sparse triangular solve against one of dense BLAS-3 work (measured
#: on SuperLU: per column a solve runs 5-10× below the dense rate)
SPARSE_SOLVE_PENALTY = 5.0


def schur_pays(n: int, c: int, n2m: int) -> bool:
    """Whether G is cheaper as the Schur complement on the c contact DOFs ((2/3)c³ for the
    dense block's factorisation, 2c²m for the one triangular solve and 4cm² for the
    symmetric product G = Wᵀ W, :func:`~stepcontact.solver.linalg.condensed_cholesky`) than
    by 2m sparse solves (4·nnz(L) each, nnz(L) ≈ 4.5 n log₂ n on 2D meshes, at the sparse
    rate) — and fits (:func:`schur_fits`).  A compact joint (c ≪ n) takes the Schur route; a
    joint as long as the model (c ~ n^½ ... n) the solves.  (The 3D slab of
    ``benchmarks/slab3d.py`` at s = 4, 327 144 DOFs and c = 12 150, is near the balance and
    takes the Schur route: measured 152 s of process CPU for the factorisation with PARDISO's
    Schur complement and G, against 434 s for the plain factorisation and the 6 075 solves.)"""
    if c == 0:
        return False
    schur = 2.0 / 3.0 * c**3 + 1.0 * c**2 * n2m + 1.0 * c * n2m**2
    nnz_l = 4.5 * n * np.log2(max(n, 2))
    solves = SPARSE_SOLVE_PENALTY * n2m * 4.0 * nnz_l
    return schur <= solves and schur_fits(c, n2m=n2m)


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
    Kf = K[free]  # (the rows once, then their columns)
    Kff = Kf[:, free].tocsr()
    Kfp = Kf[:, presc].tocsr()
    del Kf
    Bf = system.B[:, free].tocsr()
    Bp = system.B[:, presc].tocsr()
    d = stabilisation(Kff, Bf)
    K0 = (Kff + Bf.T @ sp.diags(d) @ Bf).tocsc()
    return K0, Bf, d, free, presc, Kff, Kfp, Bp, K


def condense(model, backend: str = "auto", precision: str = "auto",
             scheduler: Any = None) -> Condensation:
    """The reusable condensation of a model (or assembled system) for the static solver:
    K₀ factorised once and G = B_f K₀⁻¹ B_fᵀ (in ``precision``: :func:`dense_precision`).
    Pass it to :func:`solve_static` for every run that differs only in friction, gaps, loads
    or load program.

    ``scheduler``: a dask scheduler's address (``"tcp://10.0.0.5:8786"``) or a
    ``distributed.Client``: G is formed on that cluster by column blocks, one factorisation
    per worker (:mod:`stepcontact.solver.cluster`); the same G to round-off.  Default: here.

    Example
    -------
    >>> with distributed.LocalCluster(n_workers=2) as cl, distributed.Client(cl) as client:
    ...     c = sc.condense(model, scheduler=client)                     # doctest: +SKIP
    """
    from stepcontact.fem.assembly import assemble

    system = model if isinstance(model, System) else assemble(model)
    K0, Bf, d, *_ = static_operator(system)
    return _condense_operator(system, K0, Bf, d, backend, precision, scheduler)[0]


def _condense_operator(system: System, K0, Bf, d, backend: str, precision: str,
                       scheduler: Any = None, rhs: np.ndarray | None = None
                       ) -> tuple[Condensation, np.ndarray | None]:
    """:func:`condense` from the pieces of :func:`static_operator` already at hand, and
    K₀⁻¹ ``rhs`` (free DOFs × k, or None), solved in one call with the regularity check's
    first step (:func:`~stepcontact.solver.regularity.factorize_regular_solving`).  On a
    cluster (``scheduler``) the column blocks are submitted first, so that the workers solve
    while K₀ is factorised (and checked) here."""
    free = np.flatnonzero(~system.fixed)
    with contextlib.ExitStack() as own:
        columns = None
        if scheduler is not None and Bf.shape[0]:
            dtype = dense_precision(Bf.shape[0], precision)  # (refused before any work)
            columns = own.enter_context(ColumnJob(
                scheduler, sp.csc_matrix(K0), sp.csr_matrix(Bf), _fingerprint(K0, Bf),
                backend, dtype, None if dtype == np.float64 else np.asarray(d, float)))
        t0 = Stopwatch.start()
        factor, X = factorize_checked(system, K0, free, backend, precision,
                                      schur=columns is None, rhs=rhs, Bf=Bf)
        t_factor = t0.counters("factor")
        c = Condensation.build(K0, Bf, backend, factor=factor, precision=precision, d=d,
                               columns=columns)
    c.n_t = system.layout.n_t
    c.counters.update(t_factor)
    return c, X


def factorize_checked(system: System, K0, free, backend: str,
                      precision: str = "auto", schur: bool = True,
                      rhs: np.ndarray | None = None, Bf=None
                      ) -> tuple[Factor, np.ndarray | None]:
    """Factorise K₀ and make sure the structure with every CFE stuck is not a mechanism (one
    diagnosis naming the free bodies, whether the factorisation met a zero pivot or not).
    ``schur``: order the contact DOFs last when G is cheaper read off the factors
    (:func:`schur_pays`); False when G is formed elsewhere (on a cluster).  Returns the
    factor and K₀⁻¹ ``rhs`` (free DOFs × k; None without), solved with the check's first
    step.  ``Bf``: B's free columns, when at hand."""
    from stepcontact.solver.regularity import factorize_regular_solving

    check_dense_memory(system.layout.n, precision=precision)
    last = contact_dofs(system.B[:, free] if Bf is None else Bf)
    schur = schur and schur_pays(len(free), len(last), system.layout.n)
    return factorize_regular_solving(system, K0, free, rhs, backend,
                                     last=last if schur else None)


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
                    condensation: Condensation | None = None,
                    precision: str = "auto", scheduler: Any = None) -> Condensed:
        """Condense ``system`` (one factorisation; G read off it or by 2m block solves, or on
        the dask cluster ``scheduler``), or reuse ``condensation`` when it was built for the
        same K₀ and B (checked)."""
        K0, Bf, d, free, presc, Kff, Kfp, Bp, K = static_operator(system)
        del Kff  # K_ff u = K₀ u − B_fᵀ D B_f u: K₀ (held by the condensation) serves
        # the right-hand sides of the run, solved in one call: every load pattern's
        # f_f − K_fp u_P, then K_fp S_pᵀ of the reaction resultants (one column each: every
        # state's reactions then cost a product, see reactions())
        Sp = system.reaction_rows[:, presc] if system.reaction_rows is not None else None
        if Sp is not None and not Sp.shape[0]:
            Sp = None
        rhs = np.zeros((len(free), len(system.loads) + (0 if Sp is None else Sp.shape[0])))
        for j, lv in enumerate(system.loads.values()):
            rhs[:, j] = lv.f[free] - Kfp @ lv.u[presc]
        if Sp is not None:
            rhs[:, len(system.loads):] = (Kfp @ Sp.T).toarray()
        nsolve = rhs.shape[1]
        if condensation is None:  # (solved with the regularity check's first step)
            condensation, X = _condense_operator(system, K0, Bf, d, backend, precision,
                                                 scheduler, rhs=rhs)
            reused = 0
        else:
            if condensation.fingerprint != _fingerprint(K0, Bf):
                raise ModelError("condensation", "was built for another model: its stiffness or "
                                 "contact operator differ (build it with sc.condense(model))")
            reused = 1
            X = condensation.factor.solve(rhs) if nsolve else rhs
        factor = condensation.factor
        X = np.asarray(X).reshape(len(free), nsolve)
        hhat, e, y = {}, {}, {}
        for j, (name, lv) in enumerate(system.loads.items()):
            y[name] = np.ascontiguousarray(X[:, j])
            hhat[name] = Bf @ y[name]
            e[name] = Bp @ lv.u[presc]
        r_load: dict[str, np.ndarray] = {}
        R_s = R_t = None
        if Sp is not None:
            Kp = K[presc]
            Kpf, Kpp = Kp[:, free].tocsr(), Kp[:, presc].tocsr()
            R_t = -(Bf @ X[:, len(system.loads):]).T
            R_s = (Sp @ Bp.T).toarray()
            for name, lv in system.loads.items():
                up = lv.u[presc]
                r_load[name] = Sp @ (Kpf @ y[name] + Kpp @ up - lv.f[presc])
        c = condensation.counters
        counters = {"factorizations": 0 if reused else 1,
                    "solves": nsolve + (0 if reused else c.get("condensed_columns", 0)),
                    "condensed_columns": 0 if reused else c.get("condensed_columns", 0),
                    "condensation_reused": reused,
                    # the clocks of the factorisation and of G (not when reused: none ran)
                    **({} if reused else {k: v for k, v in c.items()
                                          if k.endswith("seconds")})}
        return cls(system, free, presc, factor, Bf, Bp, Kfp, d, condensation.G, hhat, e, y,
                   counters, r_load, R_s, R_t, condensation)

    def reactions(self, factors: dict[str, float], s: np.ndarray, w: np.ndarray) -> np.ndarray:
        """Reaction resultants of the supports (and prescribed DOFs) on the structure, N (N·m
        for rz), at any state — no solve:

            R = S_p (K_pf u_f + K_pp u_p + B_pᵀ s − f_p)
              = Σ_P c_P S_p (K_pf y_P + K_pp u_P − f_P) − (B_f K₀⁻¹ K_fp S_pᵀ)ᵀ t + S_p B_pᵀ s

        with t = s − D ŵ as in :meth:`displacement` (``system.reaction_rows`` gives S).
        A stack of k states (``s``, ``w`` (k, 2m), ``factors`` {pattern: (k,) array}) gives
        (k, n_reactions) at once."""
        if np.ndim(s) == 2:
            return self._reactions_stack(factors, s, w)
        if self.R_s is None:
            return np.zeros(0)
        R = self.R_s @ s
        e = self.layout.zeros()
        for name, c in factors.items():
            if c != 0.0:
                R = R + c * self.r_load[name]
                e += c * self.e[name]
        w_hat = w - self.system.w0 - e
        return R + self.R_t @ (s - self.d * w_hat)

    def _reactions_stack(self, factors, S: np.ndarray, W: np.ndarray) -> np.ndarray:
        """:meth:`reactions` of the states that are the rows of S, W."""
        S, W = np.asarray(S, float), np.asarray(W, float)
        if self.R_s is None:
            return np.zeros((len(S), 0))
        R = S @ self.R_s.T
        E = np.zeros_like(S)
        for name, c in factors.items():
            c = np.asarray(c, float)
            if c.any():
                R = R + np.outer(c, self.r_load[name])
                E += np.outer(c, self.e[name])
        w_hat = W - self.system.w0 - E
        return R + (S - self.d * w_hat) @ self.R_t.T

    @property
    def layout(self) -> ContactLayout:
        """The layout of the contact unknowns (the rows of G): the system's."""
        return self.system.layout

    @property
    def m(self) -> int:
        return self.layout.m

    def Kff_times(self, uf: np.ndarray) -> np.ndarray:
        """K_ff u_f = K₀ u_f − B_fᵀ D B_f u_f (K_ff itself is not kept: K₀ is)."""
        return self.condensation.A @ uf - self.Bf.T @ (self.d * (self.Bf @ uf))

    def product(self, t: np.ndarray) -> np.ndarray:
        """G t in float64: the dense product, or (float32 G) by one sparse solve."""
        if self.G.dtype == np.float64:
            return self.G @ t
        return self.condensation.product(t)

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
        e = self.layout.zeros(k)
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
        if hasattr(self.factor, "solve_last"):  # u_f = Σ_P c_P y_P − K₀⁻¹ B_fᵀ t
            x = (self._load_solutions @ C.T) - self._solve_contact(self.Bf.T @ t)
        else:  # one solve of the whole right-hand side
            rhs = rhs - self.Kfp @ up - self.Bf.T @ t
            x = np.asarray(self.factor.solve(np.ascontiguousarray(rhs[:, 0]) if k == 1
                                             else rhs))
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
        Ku = self.Kff_times(uf) + self.Kfp @ up
        Bs = self.Bf.T @ s
        r = Ku + Bs - f[self.free]
        scale = max(np.abs(Ku).max(initial=0), np.abs(Bs).max(initial=0),
                    np.abs(f[self.free]).max(initial=0), 1e-300)
        wk = sysm.B @ u + sysm.w0
        kscale = max(np.abs(w).max(initial=0), np.abs(u).max(initial=0), w_scale, 1e-300)
        kin = float(np.abs(wk - w).max(initial=0) / kscale)
        return float(np.abs(r).max(initial=0) / scale), kin

    def condensed_residual(self, factors: dict[str, float], s: np.ndarray, w: np.ndarray,
                           w_scale: float = 0.0, product=None) -> float:
        """Relative residual of the condensed equilibrium equations (no solve):

            ‖ŵ + G (s − D ŵ) − Σ_P c_P ĥ_P‖ / max(‖ŵ‖, ‖Σ c ĥ‖, w_scale),   ŵ = w − w⁰ − Σ c e_P

        Exactly equivalent to ‖K u + Bᵀ s − f‖ = 0 with u recovered from (s, w); used at the
        states whose displacement field is not computed (large models, intermediate events).
        ``product``: t ↦ (G t, a bound of its error, added to the residual's norm), e.g. the
        G t an event engine keeps current (default: G t formed, bound 0).
        """
        e = self.layout.zeros()
        h = self.layout.zeros()
        for name, c in factors.items():
            if c != 0.0:
                e += c * self.e[name]
                h += c * self.hhat[name]
        w_hat = w - self.system.w0 - e
        t = s - self.d * w_hat
        gt, bound = (self.product(t), 0.0) if product is None else product(t)
        r = w_hat + gt - h
        scale = max(_absmax(w_hat), _absmax(h), w_scale, 1e-300)
        return float((_absmax(r) + bound) / scale)

    def mode_displacement(self, t: np.ndarray) -> np.ndarray:
        """Displacement of a mechanism mode t of the condensed unknowns."""
        u = np.zeros(self.system.ndof)
        u[self.free] = -self._solve_contact(self.Bf.T @ t)
        return u

    @functools.cached_property
    def _load_solutions(self) -> np.ndarray:
        """The load patterns' y_P = K₀⁻¹ (f_P − K_fp u_P) as columns (free DOFs × patterns),
        in the order of ``system.loads``."""
        return np.column_stack([self.y[n] for n in self.system.loads]) if self.y else \
            np.zeros((len(self.free), 0))

    def _solve_contact(self, b: np.ndarray) -> np.ndarray:
        """K₀⁻¹ b for b = B_fᵀ t (a vector or a block): a right-hand side on the contact DOFs
        only, which a factor with those DOFs ordered last solves without its forward sweep
        (``solve_last``)."""
        solve = getattr(self.factor, "solve_last", self.factor.solve)
        b = np.asarray(b, dtype=float)
        return np.asarray(solve(np.ascontiguousarray(b[:, 0]) if b.ndim == 2 and
                                b.shape[1] == 1 else b)).reshape(b.shape)


def _absmax(x) -> float:
    """max |x| over every entry (0 for an empty x), ``float(np.abs(x).max(initial=0))``
    without the method's Python wrapper (a residual check per recorded state)."""
    return float(np.maximum.reduce(np.abs(x), axis=None, initial=0.0))
