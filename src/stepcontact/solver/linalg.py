"""Sparse factorisation backends: one factorisation, many solves, and the condensed matrix.

``factorize(K, last=c)`` returns a :class:`Factor`: ``solve(b)`` for a vector or a block of
right-hand sides, and — when the DOFs ``c`` that a contact operator B touches were ordered
last — ``condensed(B)`` = B K⁻¹ Bᵀ read off the trailing block of the factors, without one
solve per row of B.

Why the trailing block gives G: order the n − c interior DOFs first and the c contact DOFs
last, K = [[K_ii, K_ic], [K_ci, K_cc]].  The LU factors' trailing blocks satisfy
L_cc U_cc = S = K_cc − K_ci K_ii⁻¹ K_ic (the Schur complement), and (K⁻¹)_cc = S⁻¹, so

    G = B K⁻¹ Bᵀ = B_c U_cc⁻¹ L_cc⁻¹ B_cᵀ

costs two dense triangular solves of size c with 2m right-hand sides, where the classical route
needs 2m full sparse solves.  The interface of a 2D model is a separator of the mesh, so
ordering it last costs almost no fill (on the block-on-base benchmark the constrained ordering
has 12 % less fill than minimum degree on the whole matrix).

Backends (``backend="auto"``: ``dense`` below :data:`DENSE_BELOW` DOFs, else the first
available of the sparse ones):

- ``dense``: LAPACK's Cholesky factorisation of K as a dense array (SciPy ``cho_factor``), G
  by one block solve.  Small systems never go through a sparse library: no ordering, no
  MKL (a 2-DOF discrete model once crashed in PARDISO's Schur-complement phase), and below a
  few hundred DOFs it is also the fastest (setup of factor + G measured on a block on a
  base, 2 cores: 374 DOFs 1.7 ms dense, 2.8 ms PARDISO, 3.4 ms SuperLU; 1 218 DOFs 156 ms
  dense, 18–52 ms sparse).
- ``pypardiso``: MKL PARDISO (``pip install "stepcontact[fast]"``; wheels of MKL exist for
  Linux and Windows on x86-64), nested-dissection ordering, multithreaded; G from PARDISO's own
  Schur complement on the contact DOFs, formed by the one factorisation that then serves the
  solves.
- ``scipy``: SciPy's SuperLU, always available: minimum degree on the compressed graph (one
  vertex per node) with the contact DOFs last, symmetric mode without pivoting; G from the
  trailing block of its factors.
- ``cholmod``: scikit-sparse's CHOLMOD when installed and asked for by name (G by blocks of
  right-hand sides).
"""

from __future__ import annotations

import contextlib
import functools
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from stepcontact.errors import SolverError


class Factor(Protocol):
    name: str

    def solve(self, b: np.ndarray) -> np.ndarray: ...


@dataclass
class _SuperLU:
    """SuperLU factors of P K Pᵀ (``perm``: position → original DOF; None: K itself)."""

    lu: object
    perm: np.ndarray | None = None
    n_last: int = 0
    name: str = "scipy-superlu"
    stats: dict[str, float] = field(default_factory=dict)

    def solve(self, b: np.ndarray) -> np.ndarray:
        """K⁻¹ b for a vector or a block (n, k); a block of up to :data:`FEW_RHS` columns
        with BLAS held to one thread (see there)."""
        b = np.asarray(b, dtype=float)
        few = b.ndim == 2 and 1 < b.shape[1] <= FEW_RHS
        with _blas_threads().limit(limits=1, user_api="blas") if few \
                else contextlib.nullcontext():
            if self.perm is None:
                return self.lu.solve(b)
            x = np.empty_like(b)
            x[self.perm] = self.lu.solve(b[self.perm])
            return x

    def can_condense(self, B: sp.spmatrix) -> bool:
        """Whether B touches only the DOFs ordered last (and SuperLU did not pivot there)."""
        if self.perm is None or self.n_last == 0:
            return False
        n = len(self.perm)
        head = self.perm[: n - self.n_last]
        if sp.csc_matrix(B)[:, head].nnz:
            return False
        return bool(np.array_equal(self.lu.perm_r[n - self.n_last:],
                                   np.arange(n - self.n_last, n)))

    def condensed(self, B: sp.spmatrix) -> np.ndarray:
        """G = B K⁻¹ Bᵀ from the trailing blocks of L and U (see the module docstring)."""
        n, c = len(self.perm), self.n_last
        Bc = sp.csr_matrix(B)[:, self.perm[n - c:]]
        with one_blas_thread(c):
            Lcc = self.lu.L.tocsc()[n - c:, n - c:].toarray()
            Y = sla.solve_triangular(Lcc, Bc.T.toarray(order="F"), lower=True,
                                     unit_diagonal=True, overwrite_b=True, check_finite=False)
            del Lcc
            Ucc = self.lu.U.tocsc()[n - c:, n - c:].toarray()
            Z = sla.solve_triangular(Ucc, Y, lower=False, overwrite_b=True,
                                     check_finite=False)
            del Ucc, Y
            return np.asarray(Bc @ Z)  # B_c sparse: a few entries per row


def gram(W: np.ndarray, block: int = 1024) -> np.ndarray:
    """G = Wᵀ W (k × k, exactly symmetric) by BLAS's symmetric rank-k product (``dsyrk``:
    half the work of a general product), its upper triangle mirrored by blocks."""
    k = W.shape[1]
    if k == 0 or W.shape[0] == 0:
        return np.zeros((k, k))
    G = sla.blas.dsyrk(1.0, np.asfortranarray(W), trans=1, lower=0)
    for i in range(0, k, block):  # lower ← upperᵀ, block by block (no k × k temporary)
        for j in range(i, k, block):
            U = G[i : i + block, j : j + block]
            if i == j:
                low = np.tril_indices(U.shape[0], -1)
                U[low] = U.T[low]
            else:
                G[j : j + block, i : i + block] = U.T
    return G


def condensed_cholesky(L: np.ndarray, Bc: sp.spmatrix) -> np.ndarray:
    """G = B_c S⁻¹ B_cᵀ = Wᵀ W for S = L Lᵀ (L dense lower triangular, e.g. the first item
    of ``cho_factor(S, lower=True)``; its upper triangle is not read) and W = L⁻¹ B_cᵀ: one
    triangular solve (c²·2m/2 multiply-adds) and a symmetric product (c·(2m)²/2), where
    ``cho_solve`` and a product with B_c take two solves and a full product (c²·2m +
    c·(2m)²): 6 (2m)³ against 3 (2m)³ multiply-adds for c = 2·2m.  The same quantity, its
    round-off in another order; G comes out exactly symmetric."""
    Bc = sp.csr_matrix(Bc)
    W = sla.solve_triangular(L, Bc.T.toarray(order="F"), lower=True, overwrite_b=True,
                             check_finite=False)
    return gram(W)


#: SuperLU solves a block of up to this many right-hand sides with BLAS held to one thread:
#: its supernodal triangular solves are memory-bound, and a second BLAS thread only costs
#: synchronisation (measured at 327k DOFs on 2 busy cores: 8 columns in one call 0.54–0.59 s
#: CPU on one thread, 1.45–1.63 s with two; 8 single-column solves 0.82–1.0 s)
FEW_RHS = 32

#: dense factorisations (and their block solves) of up to this many unknowns run with BLAS
#: held to one thread: a Cholesky factorisation of 2000 takes about 0.1 s on one core, and on
#: a loaded machine a second BLAS thread makes smaller ones erratic (measured on 2 busy cores:
#: 400 unknowns 3 ms on one thread, up to 0.26 s CPU on two; 516, the Schur block of the
#: 50k-DOF block-on-base model, 2–5 ms against up to 0.55 s); the same bound as the static
#: event loop's (``solver.static.SMALL_DENSE``)
ONE_THREAD_UP_TO = 2000


@functools.cache
def _blas_threads():
    """One threadpoolctl controller per process (its creation scans the loaded libraries,
    about 3 ms; a limit through it costs about 20 µs)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


def one_blas_thread(n: int):
    """Context holding BLAS to one thread for dense work of size n ≤ :data:`ONE_THREAD_UP_TO`
    (else nothing)."""
    if n > ONE_THREAD_UP_TO:
        return contextlib.nullcontext()
    return _blas_threads().limit(limits=1, user_api="blas")


#: below this many DOFs ``backend="auto"`` factorises K densely (:class:`_Dense`): the dense
#: Cholesky setup (n³/3 flops) is faster than a sparse one up to about 400 DOFs (module
#: docstring), and a larger model keeps its sparse backend (PARDISO when installed)
DENSE_BELOW = 400


@dataclass
class _Dense:
    """Dense Cholesky factor L Lᵀ = K (lower, SciPy ``cho_factor``) of a small SPD matrix."""

    cf: tuple | None
    n: int
    name: str = "dense"

    def solve(self, b: np.ndarray) -> np.ndarray:
        b = np.asarray(b, dtype=float)
        if self.cf is None:  # no DOF
            return b.copy()
        return sla.cho_solve(self.cf, b, check_finite=False)

    def can_condense(self, B: sp.spmatrix) -> bool:
        return True

    def condensed(self, B: sp.spmatrix) -> np.ndarray:
        """G = B K⁻¹ Bᵀ by one dense block solve."""
        Bd = sp.csr_matrix(B).toarray()
        with one_blas_thread(self.n):
            return Bd @ self.solve(Bd.T)


def _dense(K: sp.spmatrix) -> _Dense:
    """Cholesky factorisation of K as a dense array; a matrix that is not positive definite
    (a zero or negative pivot: singular, or a mechanism in round-off) raises RuntimeError,
    turned into a singular-matrix :class:`SolverError` by :func:`factorize`."""
    n = K.shape[0]
    if n == 0:
        return _Dense(None, 0)
    try:
        with one_blas_thread(n):
            cf = sla.cho_factor(K.toarray(), lower=True, overwrite_a=True, check_finite=True)
    except np.linalg.LinAlgError as exc:
        raise RuntimeError(f"dense Cholesky: {exc}") from exc
    return _Dense(cf, n)


@dataclass
class _Cholmod:
    f: object
    name: str = "cholmod"

    def solve(self, b: np.ndarray) -> np.ndarray:
        return self.f(np.asarray(b, dtype=float))


class _Pardiso:
    """MKL PARDISO from the MKL runtime pypardiso uses (``pip install "stepcontact[fast]"``;
    located and loaded once per process by :func:`_mkl_pardiso`):
    K is SPD (matrix type 2, upper triangle), factorised once with PARDISO's nested dissection.

    With DOFs ``last`` (c of them, the rest i) that one factorisation is PARDISO's partial one
    (iparm[35] = 1): the Cholesky factor L of K_ii and the dense Schur complement
    S = K_cc − K_ci K_ii⁻¹ K_ic, of which this keeps the dense Cholesky factor.  S gives
    G = B_c S⁻¹ B_cᵀ (:meth:`condensed`), and a solve K x = b is block elimination through
    the same factors (:meth:`solve`): PARDISO's forward substitution (phase 331) gives
    y_i = L⁻¹ b_i and y_c = b_c − K_ci K_ii⁻¹ b_i, then x_c = S⁻¹ y_c (dense), and its
    backward substitution (phase 333) x_i = L⁻ᵀ (y_i − L⁻¹ K_ic x_c).  The contact DOFs come
    last in PARDISO's ordering: on the block-on-base benchmark (50k DOFs) the factors have as
    many entries (within 1.5 %) as with an unconstrained nested dissection.  (PARDISO can also
    factorise S itself and keep the whole factorisation, iparm[35] = 2, but on a loaded machine
    its threaded dense factorisation of S took 3× the CPU time in about half of the runs.)"""

    name = "pypardiso"

    def __init__(self, K: sp.spmatrix, last: np.ndarray | None = None):
        self._lib = _mkl_pardiso()  # mkl_rt located once per process (see _mkl_rt)
        if self._lib is None:
            raise ImportError("the pypardiso backend needs pypardiso and the MKL runtime mkl_rt "
                              '(pip install "stepcontact[fast]"); none found')
        self.n = K.shape[0]
        self.U = sp.triu(K, format="csr")
        self.U.sort_indices()
        self._ia = self.U.indptr.astype(np.int32) + 1
        self._ja = self.U.indices.astype(np.int32) + 1
        self.last = None if last is None else np.unique(last)
        #: how often each route ran (``condensed_cholesky``: G from the Schur factor)
        self.stats: dict[str, int] = {}
        self.pt, self.iparm = self._handle()
        self._perm = np.zeros(0, np.int32)  # no Schur complement: perm is not read
        self._schur = None
        self._full = None  # a second, full factorisation for the solves (for_many_solves)
        try:
            if self.last is None or not len(self.last):
                self._call(self.pt, self.iparm, 12, self._perm, np.zeros(1), np.zeros(1), 1)
            else:
                self._schur = self._factor_with_schur()
        except BaseException:
            self._release()
            raise

    def _factor_with_schur(self):
        """The partial factorisation (phases 11–22, iparm[35] = 1) and the Schur complement
        S on the DOFs ``last``; returns S's dense Cholesky factor (kept: solves need it)."""
        c = len(self.last)
        self.iparm[35] = 1  # Schur complement on the rows marked in perm, dense in x
        self._perm = np.zeros(self.n, np.int32)
        self._perm[self.last] = 1
        S = np.zeros((c, c))
        self._call(self.pt, self.iparm, 12, self._perm, np.zeros(self.n), S, 0)
        try:
            with one_blas_thread(c):
                return sla.cho_factor(S, lower=True, overwrite_a=True, check_finite=False)
        except np.linalg.LinAlgError as exc:  # reported like a singular factorisation
            raise RuntimeError("PARDISO error -4 (matrix not positive definite: singular): "
                               "its Schur complement on the contact DOFs is not") from exc

    @staticmethod
    def _handle() -> tuple[np.ndarray, np.ndarray]:
        iparm = np.zeros(64, np.int32)
        iparm[0] = 1  # no solver defaults
        iparm[1] = 2  # nested dissection (METIS)
        iparm[9] = 13  # pivot perturbation 1e-13 (never met on an SPD matrix)
        # iparm[34] = 0: one-based ia, ja
        return np.zeros(64, np.int64), iparm

    def _call(self, pt, iparm, phase: int, perm, b, x, nrhs: int) -> None:
        import ctypes

        i32, f64 = ctypes.POINTER(ctypes.c_int32), ctypes.POINTER(ctypes.c_double)
        err = ctypes.c_int32(0)
        one = ctypes.byref(ctypes.c_int32(1))
        self._lib(pt.ctypes.data_as(ctypes.POINTER(ctypes.c_int64)), one, one,
                  ctypes.byref(ctypes.c_int32(2)), ctypes.byref(ctypes.c_int32(phase)),
                  ctypes.byref(ctypes.c_int32(self.n)), self.U.data.ctypes.data_as(f64),
                  self._ia.ctypes.data_as(i32), self._ja.ctypes.data_as(i32),
                  perm.ctypes.data_as(i32), ctypes.byref(ctypes.c_int32(nrhs)),
                  iparm.ctypes.data_as(i32), ctypes.byref(ctypes.c_int32(0)),
                  b.ctypes.data_as(f64), x.ctypes.data_as(f64), ctypes.byref(err))
        if err.value != 0:
            raise RuntimeError(f"PARDISO error {err.value}"
                               + (" (matrix not positive definite: singular)"
                                  if err.value == -4 else ""))

    def for_many_solves(self) -> None:
        """Keep, beside the partial factorisation, a full one that serves the solves (phase 33:
        one call instead of the block elimination's three and a dense solve): a driver that
        solves at every step (dynamics) pays a second factorisation once to halve the cost of
        each solve (measured on the dynamic slab: 0.59 → 0.32 ms per solve at 5.5k DOFs)."""
        if self._schur is None or self._full is not None:
            return
        pt, iparm = self._handle()
        try:
            self._call(pt, iparm, 12, np.zeros(0, np.int32), np.zeros(1), np.zeros(1), 1)
        except BaseException:
            if pt.any():
                self._call(pt, iparm, -1, np.zeros(0, np.int32), np.zeros(1), np.zeros(1), 1)
            raise
        self._full = (pt, iparm)

    def solve(self, b: np.ndarray) -> np.ndarray:
        """K⁻¹ b for a vector or a block (n, k): phase 33, or with a Schur complement the
        block elimination of the class docstring (phases 331 and 333 around x_c = S⁻¹ y_c)
        unless a full factorisation is kept for the solves (:meth:`for_many_solves`)."""
        b = np.asarray(b, dtype=float)
        bf = np.asfortranarray(b.reshape(self.n, -1))
        k = bf.shape[1]
        x = np.zeros_like(bf)
        if self._schur is None or self._full is not None:
            pt, iparm = self._full if self._full is not None else (self.pt, self.iparm)
            perm = self._perm if self._full is None else np.zeros(0, np.int32)
            self._call(pt, iparm, 33, perm, bf, x, k)
            return x.reshape(b.shape)
        y = np.zeros_like(bf)
        self._call(self.pt, self.iparm, 331, self._perm, bf, y, k)
        with one_blas_thread(len(self.last)):
            y[self.last] = sla.cho_solve(self._schur, y[self.last], check_finite=False)
        self._call(self.pt, self.iparm, 333, self._perm, y, x, k)
        return x.reshape(b.shape)

    def solve_last(self, b: np.ndarray) -> np.ndarray:
        """K⁻¹ b for a b that vanishes outside the DOFs ``last`` (B_fᵀ t: contact forces):
        the block elimination of :meth:`solve` without its forward substitution, which is the
        identity on such a b (y_i = L⁻¹ 0 = 0, y_c = b_c − K_ci K_ii⁻¹ 0 = b_c): x_c = S⁻¹ b_c
        and PARDISO's backward substitution (phase 333) only.  The entries of b outside
        ``last`` are not read."""
        if self._schur is None or self._full is not None:
            return self.solve(b)
        b = np.asarray(b, dtype=float)
        y = np.zeros((self.n, b.size // self.n), order="F")
        with one_blas_thread(len(self.last)):
            y[self.last] = sla.cho_solve(self._schur, b.reshape(self.n, -1)[self.last],
                                         check_finite=False)
        x = np.zeros_like(y)
        self._call(self.pt, self.iparm, 333, self._perm, y, x, y.shape[1])
        return x.reshape(b.shape)

    def can_condense(self, B: sp.spmatrix) -> bool:
        if self.last is None or not len(self.last):
            return False
        outside = np.ones(self.n, bool)
        outside[self.last] = False
        return sp.csc_matrix(B)[:, np.flatnonzero(outside)].nnz == 0

    def condensed(self, B: sp.spmatrix) -> np.ndarray:
        """G = B_c S⁻¹ B_cᵀ = Wᵀ W from the Schur factor S = L Lᵀ of the factorisation,
        W = L⁻¹ B_cᵀ (:func:`condensed_cholesky`)."""
        self.stats["condensed_cholesky"] = self.stats.get("condensed_cholesky", 0) + 1
        with one_blas_thread(len(self.last)):
            return condensed_cholesky(self._schur[0], sp.csr_matrix(B)[:, self.last])

    def _release(self) -> None:
        """Free PARDISO's memory of this factorisation (phase −1), once."""
        if self.pt.any():
            self._call(self.pt, self.iparm, -1, self._perm, np.zeros(1), np.zeros(1), 1)
            self.pt[:] = 0
        if self._full is not None and self._full[0].any():
            pt, iparm = self._full
            self._call(pt, iparm, -1, np.zeros(0, np.int32), np.zeros(1), np.zeros(1), 1)
            pt[:] = 0

    def __del__(self) -> None:
        try:
            self._release()
        except Exception:  # noqa: BLE001 - interpreter shutdown: nothing to release into
            pass


def _mkl_rt_candidates() -> list[str]:
    """Quick places of the MKL runtime, in pypardiso's order: the ``PYPARDISO_MKL_RT``
    variable (then the only one), the system's library search (``mkl_rt``, ``mkl_rt.1``),
    then the files the ``mkl`` wheel installed (shorter paths first).  Only if none of them
    loads does :func:`_mkl_pardiso` make pypardiso's slow directory walk
    (:func:`_mkl_rt_search`)."""
    import os
    from ctypes.util import find_library

    env = os.environ.get("PYPARDISO_MKL_RT")
    if env is not None:
        return [env]  # as pypardiso: a given path is the only one tried
    out = [p for p in (find_library("mkl_rt"), find_library("mkl_rt.1")) if p is not None]
    try:
        from importlib.metadata import PackageNotFoundError, files

        try:
            found = files("mkl") or []
        except PackageNotFoundError:
            found = []
        out += sorted((os.path.normpath(f.locate()) for f in found if "mkl_rt" in f.name),
                      key=len)
    except Exception:  # noqa: BLE001 - broken metadata: fall through to the directory search
        pass
    return out


def _mkl_rt_search() -> list[str]:
    """pypardiso's fallback: ``*mkl_rt*`` below ``sys.prefix/[Ll]ib*`` (else the user base)."""
    import glob
    import site
    import sys

    hits = (glob.glob(f"{sys.prefix}/[Ll]ib*/**/*mkl_rt*", recursive=True)
            or glob.glob(f"{site.USER_BASE}/[Ll]ib*/**/*mkl_rt*", recursive=True))
    return sorted(hits, key=len)


#: how long (ms) MKL's OpenMP threads spin-wait after a PARDISO call before they sleep
#: (``KMP_BLOCKTIME``; Intel's default is 200 ms), unless the environment sets it.  A run calls
#: PARDISO a few times between long stretches of single-threaded work (the regularity check,
#: the event loop): with the default the idle threads spin through them and charge up to
#: 200 ms of CPU per call, a core taken from the other processes of a busy machine (measured
#: at 82k DOFs: a 0.5 s pause after a solve cost 0.16–0.20 s of CPU with the default, none
#: with 0, and the factorisation was no slower).  Wake-up after a sleep costs microseconds.
MKL_BLOCKTIME = "0"


@functools.cache
def _mkl_pardiso():
    """MKL's ``pardiso`` entry point (a ctypes function with pypardiso's argument types),
    or None when pypardiso is not installed or no MKL runtime loads.  Looked up once per
    process: the library is found and loaded with ctypes here, without constructing a
    ``pypardiso.PyPardisoSolver`` (whose constructor walks the directory tree every time)."""
    import ctypes
    import importlib.util
    import os

    try:
        if importlib.util.find_spec("pypardiso") is None:
            return None
    except (ImportError, ValueError):
        return None
    # MKL's OpenMP threads sleep as soon as a call is done (unless the user set the wait):
    # read by the OpenMP runtime when MKL starts it, so set before the library loads
    os.environ.setdefault("KMP_BLOCKTIME", MKL_BLOCKTIME)
    searches = [_mkl_rt_candidates]
    if os.environ.get("PYPARDISO_MKL_RT") is None:
        searches.append(_mkl_rt_search)
    lib = None
    for search in searches:
        for path in search():
            try:
                lib = ctypes.CDLL(path)
                break
            except OSError:
                pass
        if lib is not None:
            break
    if lib is None:
        return None
    try:
        fn = lib.pardiso
    except AttributeError:
        return None
    i32, vp = ctypes.POINTER(ctypes.c_int32), ctypes.c_void_p
    fn.argtypes = [ctypes.POINTER(ctypes.c_int64),  # pt
                   i32, i32, i32, i32, i32,  # maxfct, mnum, mtype, phase, n
                   vp, i32, i32, i32,  # a, ia, ja, perm
                   i32, i32, i32,  # nrhs, iparm, msglvl
                   vp, vp, i32]  # b, x, error
    fn.restype = None
    return fn


def _pardiso_available() -> bool:
    return _mkl_pardiso() is not None


def auto_backend(n: int) -> str:
    """The backend ``"auto"`` takes for an n × n matrix: ``dense`` below :data:`DENSE_BELOW`
    DOFs, else the first of :func:`available_backends`."""
    return "dense" if n < DENSE_BELOW else available_backends()[0]


def available_backends() -> list[str]:
    """Sparse backends usable on this machine, the one ``"auto"`` picks first for a matrix of
    :data:`DENSE_BELOW` DOFs or more: pypardiso (MKL PARDISO, the ``fast`` extra) when
    installed, else SciPy's SuperLU.  (``"dense"`` is always usable too, by name, and is what
    ``"auto"`` takes below that size: :func:`auto_backend`.)"""
    out = ["pypardiso"] if _pardiso_available() else []
    out.append("scipy")
    try:
        import sksparse.cholmod  # noqa: F401

        out.append("cholmod")
    except ImportError:
        pass
    return out


def node_groups(K: sp.spmatrix) -> np.ndarray:
    """Group DOFs of equal two-step pattern (the pattern of |K|²: the DOFs of one node, even
    where an entry of K vanishes by symmetry of the mesh): group id per DOF.  A random weight
    per column makes equal patterns give equal sums; a collision or a split group only costs
    ordering quality, never accuracy."""
    P = sp.csr_matrix(K, copy=True)
    P.data = np.ones_like(P.data)
    P = P + sp.eye(P.shape[0], format="csr")
    P.data[:] = 1.0
    P = P @ P
    P.data[:] = 1.0
    w = np.random.default_rng(12345).random(P.shape[1]) + 0.5
    key = np.round(P @ w, 8) + P.getnnz(axis=1) * 1e-3
    _, groups = np.unique(key, return_inverse=True)
    return groups.ravel()


def fill_reducing_order(K: sp.spmatrix, last: np.ndarray | None = None,
                        groups: np.ndarray | None = None) -> np.ndarray:
    """A fill-reducing order of K's DOFs (position → DOF), with the DOFs ``last`` at the end.

    Minimum degree (SuperLU's MMD on AᵀA + A) on the compressed graph, one vertex per group
    of DOFs (``groups``: the node of each DOF; by default DOFs with equal pattern): about an
    eighth of the work of factorising K.
    """
    n = K.shape[0]
    groups = node_groups(K) if groups is None else np.unique(groups, return_inverse=True)[1]
    ng = int(groups.max()) + 1 if n else 0
    P = sp.csr_matrix((np.ones(n), (groups, np.arange(n))), shape=(ng, n))
    A = (P @ abs(sp.csr_matrix(K)) @ P.T).tocsr()
    A.data[:] = -1.0
    A.setdiag(0.0)
    A.eliminate_zeros()
    A = (A + sp.diags(np.asarray(-A.sum(axis=1)).ravel() + 1.0)).tocsc()
    lu = spla.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                   options={"SymmetricMode": True})
    rank = lu.perm_c  # group → its position in the order
    is_last = np.zeros(n, bool)
    if last is not None:
        is_last[last] = True
    return np.lexsort((np.arange(n), rank[groups], is_last))


def factorize(K: sp.spmatrix, backend: str = "auto", last: np.ndarray | None = None,
              groups: np.ndarray | None = None) -> Factor:
    """Factorise a symmetric positive definite sparse matrix once.

    ``backend``: ``"auto"`` (:func:`auto_backend`: dense below :data:`DENSE_BELOW` DOFs, else
    PARDISO when installed, else SuperLU), ``"dense"``, ``"scipy"``, ``"pypardiso"`` or
    ``"cholmod"``.  ``last``: DOFs to order last (those a contact operator B touches), so that
    the factor can form B K⁻¹ Bᵀ itself (``condensed``); ``groups``: the node of each DOF, for
    the ordering.
    Raises :class:`SolverError` if the matrix is singular (a structure that is a mechanism
    even with every contact element stuck).
    """
    K = sp.csc_matrix(K)
    name = auto_backend(K.shape[0]) if backend == "auto" else backend
    try:
        if name == "dense":
            return _dense(K)
        if name == "cholmod":
            from sksparse.cholmod import cholesky

            return _Cholmod(cholesky(K))
        if name == "pypardiso":
            return _Pardiso(K, last)
        if name == "scipy":
            return _superlu(K, last, groups)
    except RuntimeError as exc:  # SuperLU: "Factor is exactly singular"
        raise SolverError(f"stiffness matrix is singular ({exc})") from exc
    raise SolverError(f"unknown linear-solver backend '{backend}' "
                      f"(have {[*available_backends(), 'dense']})")


def _superlu(K: sp.csc_matrix, last: np.ndarray | None,
             groups: np.ndarray | None = None) -> _SuperLU:
    """SuperLU in symmetric mode (no pivoting: K is SPD) on K ordered by
    :func:`fill_reducing_order`."""
    if K.shape[0] == 0:
        return _SuperLU(spla.splu(K, permc_spec="NATURAL"))
    perm = fill_reducing_order(K, last, groups)
    Kp = K[perm][:, perm].tocsc()
    lu = spla.splu(Kp, permc_spec="NATURAL", diag_pivot_thresh=0.0,
                   options={"SymmetricMode": True})
    n_last = 0 if last is None else len(np.unique(last))
    return _SuperLU(lu, perm, n_last)
