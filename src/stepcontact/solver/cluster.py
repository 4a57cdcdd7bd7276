"""The condensed matrix G = B A⁻¹ Bᵀ formed on a dask.distributed cluster.

The columns of G are independent of each other: for any set J of contact unknowns (rows of B)

    G[:, J] = B X_J,     A X_J = (Bᵀ)[:, J] = B[J, :]ᵀ

so the 2m columns split into blocks that the workers solve in parallel.  Each worker factorises
A once (the factor is kept in a worker-local cache keyed by the fingerprint of (A, B) and the
backend, :data:`_FACTORS`, and dropped when G is assembled) and solves every block it is given
with that factor; the client scatters A and B once to every worker, submits the blocks and
writes each block into G as it arrives.  The arithmetic of a block is that of the serial blocked
route of :meth:`~stepcontact.solver.condensation.Condensation.build` (including the shifted
float32 form D G − I), so G agrees with the serial G to round-off whatever the number of
workers.

This pays where the serial route forms G by 2m sparse solves (a joint as long as the model, or a
large model: ``condensation.schur_pays`` is False); where the serial route reads G off the
factors' trailing block (a compact joint), that costs less than one factorisation and a cluster
cannot beat it.  The client still factorises A itself (its runs need the solves), while the
workers work: :class:`ColumnJob` is submitted first and gathered after.
"""

from __future__ import annotations

import math
import re
import threading
import time
import uuid
from typing import Any

import numpy as np
import scipy.sparse as sp

from stepcontact.errors import ModelError, SolverError, StepContactError
from stepcontact.solver.linalg import Factor, factorize

#: columns of G per task at most (as the serial blocked route)
BLOCK = 256

#: factors held by the workers of this process: (worker address, fingerprint, backend) → factor
_FACTORS: dict[tuple[str, str, str], Factor] = {}
#: one lock per factor key: a factor is formed once per worker and solves do not overlap on it
#: (a PARDISO handle is not safe for concurrent solves)
_LOCKS: dict[tuple[str, str, str], threading.Lock] = {}
_GUARD = threading.Lock()


def _lock(key: tuple[str, str, str]) -> threading.Lock:
    with _GUARD:
        return _LOCKS.setdefault(key, threading.Lock())


def _worker_address() -> str:
    from distributed import get_worker

    try:
        return str(get_worker().address)
    except ValueError:  # not in a worker (called directly): one cache for this process
        return "local"


def _block(A: sp.csc_matrix, B: sp.csr_matrix, fingerprint: str, backend: str, start: int,
           stop: int, d: np.ndarray | None, dtype: str) -> tuple[int, np.ndarray, str, int]:
    """Columns ``start:stop`` of G = B A⁻¹ Bᵀ, computed on a worker with its factor of A
    (formed here at the worker's first block): float64, or in float32 as the shifted columns
    of D G − I (``d``: D's diagonal).  Returns (start, columns, worker address, 1 if this
    block factorised A else 0)."""
    address = _worker_address()
    key = (address, fingerprint, backend)
    with _lock(key):
        factor = _FACTORS.get(key)
        fresh = factor is None
        if fresh:
            factor = factorize(A, backend)
            _FACTORS[key] = factor
        X = factor.solve(B[start:stop].T.toarray())
    Gs = B @ X.reshape(A.shape[0], -1)
    if d is not None:  # D G − I, as Condensation.build's blocked route
        Gs *= d[:, None]
        Gs[np.arange(start, stop), np.arange(stop - start)] -= 1.0
    return start, Gs.astype(np.dtype(dtype), copy=False), address, int(fresh)


def _forget(fingerprint: str, backend: str) -> int:
    """Drop the factors of (``fingerprint``, ``backend``) held in this process; how many."""
    with _GUARD:
        keys = [k for k in _FACTORS if k[1:] == (fingerprint, backend)]
        for k in keys:
            del _FACTORS[k]
            _LOCKS.pop(k, None)
    return len(keys)


def client_of(scheduler: Any) -> tuple[Any, bool]:
    """The ``distributed.Client`` of ``scheduler`` (a scheduler's address such as
    ``tcp://10.0.0.5:8786``, connected here, or a Client) and whether it was opened here (then
    the caller closes it).  A bad address is a :class:`ModelError` naming ``scheduler``, a
    scheduler that cannot be reached a :class:`SolverError`."""
    import distributed

    if isinstance(scheduler, distributed.Client):
        return scheduler, False
    if not isinstance(scheduler, str) or not (re.match(r"^[a-z]+://", scheduler)
                                              or ":" in scheduler):
        raise ModelError("scheduler", f"give a dask scheduler's address (tcp://HOST:PORT) or a "
                         f"distributed.Client, got {scheduler!r}")
    try:
        return distributed.Client(scheduler, set_as_default=False), True
    except (OSError, TimeoutError) as e:
        raise SolverError(f"scheduler '{scheduler}': cannot connect ({' '.join(str(e).split())})"
                          ) from None


def _workers(client: Any, name: str) -> int:
    """Workers of the cluster (waiting up to the connect timeout for a first one)."""
    n = len(client.scheduler_info().get("workers", {}))
    if n:
        return n
    import dask

    timeout = dask.config.get("distributed.comm.timeouts.connect")
    try:
        client.wait_for_workers(1, timeout=timeout)
    except TimeoutError:
        raise SolverError(f"scheduler '{name}' has no workers (waited {timeout}): start "
                          "some with 'dask worker ADDRESS'") from None
    return len(client.scheduler_info()["workers"])


def blocks(n2m: int, workers: int, block: int = BLOCK) -> list[tuple[int, int]]:
    """Column blocks (start, stop) of a 2m × 2m G: a multiple of ``workers`` blocks of equal
    width (± 1), each at most ``block`` columns wide."""
    if n2m == 0:
        return []
    k = max(1, workers) * math.ceil(math.ceil(n2m / block) / max(1, workers))
    k = min(k, n2m)
    edges = np.linspace(0, n2m, k + 1).round().astype(int)
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:], strict=True) if b > a]


class ColumnJob:
    """The columns of G = B A⁻¹ Bᵀ submitted to a cluster (in ``dtype``; float32: D G − I with
    ``d``), gathered by :meth:`result`.  Use as a context manager: leaving it cancels what is
    still pending, drops the workers' factors and closes a client it opened."""

    def __init__(self, scheduler: Any, A: sp.spmatrix, B: sp.spmatrix, fingerprint: str,
                 backend: str = "auto", dtype: Any = np.float64,
                 d: np.ndarray | None = None, block: int = BLOCK):
        self.client, self._own = client_of(scheduler)
        self.name = scheduler if isinstance(scheduler, str) else str(
            getattr(self.client.scheduler, "address", "the client's"))
        self.fingerprint, self.backend = fingerprint, backend
        self.n2m = B.shape[0]
        self.dtype = np.dtype(dtype)
        self._futures: list[Any] = []
        self._open = True
        try:
            self.workers = _workers(self.client, self.name)
            token = uuid.uuid4().hex[:8]
            A_f, B_f = self.client.scatter([sp.csc_matrix(A), sp.csr_matrix(B)],
                                           broadcast=True, hash=False)
            self._futures = [
                self.client.submit(_block, A_f, B_f, fingerprint, backend, s, e, d,
                                   self.dtype.str, pure=False,
                                   key=f"stepcontact-condense-{token}-{i}")
                for i, (s, e) in enumerate(blocks(self.n2m, self.workers, block))]
            self._data = (A_f, B_f)
        except BaseException:
            self.close()
            raise

    def result(self) -> tuple[np.ndarray, dict[str, float]]:
        """G (2m × 2m, not yet symmetrised) and the job's counters: ``cluster_workers`` (of
        the cluster), ``cluster_workers_used`` (that solved a block), ``cluster_factorizations``
        (of A on the workers: one per worker used), ``cluster_blocks``, ``cluster_seconds``
        (waiting for the blocks)."""
        from distributed import as_completed

        t0 = time.perf_counter()
        G = np.empty((self.n2m, self.n2m), self.dtype)
        per_worker: dict[str, int] = {}
        done = as_completed(self._futures, loop=self.client.loop, with_results=True)
        try:
            for fut, (start, Gs, address, fresh) in done:
                G[:, start : start + Gs.shape[1]] = Gs
                per_worker[address] = per_worker.get(address, 0) + fresh
                fut.release()
        except StepContactError:
            raise
        except Exception as e:  # a lost worker, a task that failed there
            why = " ".join(f"{type(e).__name__}: {e}".split())
            raise SolverError(f"scheduler '{self.name}': a block of the condensed matrix G "
                              f"failed on the cluster ({why})") from e
        counters = {"cluster_workers": self.workers,
                    "cluster_factorizations": sum(per_worker.values()),
                    "cluster_workers_used": len(per_worker),
                    "cluster_blocks": len(self._futures),
                    "cluster_seconds": time.perf_counter() - t0}
        self.per_worker = per_worker
        self._futures = []
        self.close()
        return G, counters

    def close(self) -> None:
        """Cancel what is pending, drop the workers' factors, close an own client (once)."""
        if not self._open:
            return
        self._open = False
        try:
            pending = [f for f in self._futures if not f.done()]
            if pending:
                self.client.cancel(pending)
            self._data = None
            self.client.run(_forget, self.fingerprint, self.backend)
        except Exception:  # noqa: BLE001 - a lost cluster: nothing left to release on it
            pass
        finally:
            self._futures = []
            if self._own:
                self.client.close()

    def __enter__(self) -> ColumnJob:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
