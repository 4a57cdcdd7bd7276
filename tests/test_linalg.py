"""Sparse backends: every installed backend solves like SciPy's SuperLU and gives the same path."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import stepcontact as sc
import verification_models as vm
from stepcontact.errors import SolverError
from stepcontact.solver.linalg import available_backends, factorize


def _spd(n: int = 200, seed: int = 0) -> sp.csc_matrix:
    rng = np.random.default_rng(seed)
    A = sp.random(n, n, density=0.02, random_state=seed, data_rvs=rng.standard_normal)
    return (A @ A.T + n * sp.eye(n)).tocsc()


@pytest.mark.parametrize("backend", available_backends())
def test_backend_solves_vectors_and_blocks(backend):
    K = _spd()
    F = factorize(K, backend)
    b = np.random.default_rng(1).standard_normal((K.shape[0], 3))
    x = F.solve(b)
    assert x.shape == b.shape
    assert np.abs(K @ x - b).max() <= 1e-10 * np.abs(b).max()
    x0 = F.solve(b[:, 0])
    assert x0.shape == (K.shape[0],)
    assert np.allclose(x0, x[:, 0], rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("backend", [b for b in available_backends() if b != "scipy"])
def test_backend_gives_the_scipy_path(backend):
    model = vm.sliding_block(0.4, 10.0)
    a = sc.solve_static(model, backend="scipy")
    b = sc.solve_static(model, backend=backend)
    assert [(e.cfe, e.transition) for e in a.events] == [(e.cfe, e.transition) for e in b.events]
    assert np.allclose(a.lam, b.lam, rtol=1e-9)
    assert np.allclose(a.N, b.N, rtol=1e-8, atol=1e-8 * np.abs(a.N).max())


def test_unknown_backend_and_singular_matrix_are_errors():
    with pytest.raises(SolverError, match="unknown linear-solver backend 'mumps'"):
        factorize(_spd(), "mumps")
    K = sp.csc_matrix(np.diag([1.0, 0.0, 2.0]))
    with pytest.raises(SolverError, match="singular"):
        factorize(K, "scipy")
