"""Sparse factorisation backends: one factorisation, many solves.

``factorize(K)`` returns an object with ``solve(b)`` for a vector or a block of right-hand
sides.  SciPy's SuperLU is the default; scikit-sparse's CHOLMOD and pypardiso are used when
installed (``backend="auto"``) or when asked for by name.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from stepcontact.errors import SolverError


class Factor(Protocol):
    name: str

    def solve(self, b: np.ndarray) -> np.ndarray: ...


@dataclass
class _SuperLU:
    lu: object
    name: str = "scipy-superlu"

    def solve(self, b: np.ndarray) -> np.ndarray:
        return self.lu.solve(np.asarray(b, dtype=float))


@dataclass
class _Cholmod:
    f: object
    name: str = "cholmod"

    def solve(self, b: np.ndarray) -> np.ndarray:
        return self.f(np.asarray(b, dtype=float))


@dataclass
class _Pardiso:
    solver: object
    A: sp.csr_matrix
    name: str = "pypardiso"

    def solve(self, b: np.ndarray) -> np.ndarray:
        # phase 33 (solve with the stored factors) directly: pypardiso's ``solve`` hashes the
        # whole matrix on every call to decide whether it is already factorised
        b = np.asfortranarray(b, dtype=float)
        try:
            self.solver.set_phase(33)
            return self.solver._call_pardiso(self.A, b)
        except AttributeError:  # a pypardiso without these internals
            return self.solver.solve(self.A, b)


def available_backends() -> list[str]:
    """Backends importable on this machine, fastest first."""
    out = []
    try:
        import sksparse.cholmod  # noqa: F401

        out.append("cholmod")
    except ImportError:
        pass
    try:
        import pypardiso  # noqa: F401

        out.append("pypardiso")
    except ImportError:
        pass
    out.append("scipy")
    return out


def factorize(K: sp.spmatrix, backend: str = "auto") -> Factor:
    """Factorise a symmetric positive definite sparse matrix once.

    Raises :class:`SolverError` if the matrix is singular (a structure that is a mechanism
    even with every contact element stuck).
    """
    K = sp.csc_matrix(K)
    name = available_backends()[0] if backend == "auto" else backend
    try:
        if name == "cholmod":
            from sksparse.cholmod import cholesky

            return _Cholmod(cholesky(K))
        if name == "pypardiso":
            import pypardiso

            solver = pypardiso.PyPardisoSolver()
            A = sp.csr_matrix(K)
            solver.factorize(A)
            return _Pardiso(solver, A)
        if name == "scipy":
            return _SuperLU(spla.splu(K, permc_spec="COLAMD", options={"SymmetricMode": True}))
    except RuntimeError as exc:  # SuperLU: "Factor is exactly singular"
        raise SolverError(f"stiffness matrix is singular ({exc})") from exc
    raise SolverError(f"unknown linear-solver backend '{backend}' (have {available_backends()})")
