"""Benchmark: the condensed matrix G = B_f K₀⁻¹ B_fᵀ of the slab model formed serially and on a
dask.distributed LocalCluster of 1 and of 2 worker processes (``sc.condense(system,
scheduler=...)``, :mod:`stepcontact.solver.cluster`).

For each size k of the slab benchmark (``slab_on_foundation.slab_model``) it prints, per way of
forming G:

- wall time of ``sc.condense`` (the client's factorisation of K₀ runs while the workers solve);
- CPU time of the client process (``time.process_time``) and of its main thread
  (``time.thread_time``);
- CPU time of each worker process over the call (``client.run(time.process_time)`` before and
  after): every worker factorises K₀ once and solves its column blocks;
- the largest difference from the serial G, relative to max |G|.

and last the ratios: the speed-up of 2 workers over 1 — from wall time (what this machine gave,
shared and loaded) and from CPU time (the critical path: the busiest worker's CPU time with 2
workers against the one worker's; what an idle machine with a core per worker would give) —
and the cluster's wall time over the serial one.

The workers are processes started by the cluster's nannies, which hold BLAS/MKL to one thread
each (``distributed.nanny.pre-spawn-environ``); the serial call uses the threads the process
has.  The cluster's start and a warm-up call (imports on the workers) are not timed.

Note: the serial path of the slab model reads G off the Schur block of the factors (a compact
joint: ``condensation.schur_pays``), which costs a fraction of one factorisation; the cluster
forms G by 2m sparse solves split over the workers, after a factorisation on each.  A cluster
pays where the serial path would need the 2m solves (a joint as long as the model, or many
CFEs), and with more machines than this benchmark's two shared cores.

``--long CELLS`` adds the long slab of ``large_interface.py`` (a joint as long as the model),
whose serial G is formed by 2m solves too: the case a cluster is for.

Run:  python benchmarks/condense_dask.py [--sizes 2 4] [--long 2000] [--precision float64]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

import stepcontact as sc
from stepcontact.fem.assembly import assemble

sys.path.insert(0, str(Path(__file__).resolve().parent))
from slab_on_foundation import slab_model  # noqa: E402


def _clocks() -> tuple[float, float, float]:
    return time.perf_counter(), time.process_time(), time.thread_time()


def _worker_cpu(client) -> dict[str, float]:
    return client.run(time.process_time)


def timed_serial(system, precision: str) -> dict:
    w0, p0, t0 = _clocks()
    c = sc.condense(system, precision=precision)
    w1, p1, t1 = _clocks()
    route = "Schur block" if c.counters["condensed_columns"] == 0 else "2m solves"
    return {"G": c.G, "wall": w1 - w0, "cpu": p1 - p0, "thread": t1 - t0, "workers": {},
            "route": route}


def timed_cluster(system, precision: str, client) -> dict:
    before = _worker_cpu(client)
    w0, p0, t0 = _clocks()
    c = sc.condense(system, precision=precision, scheduler=client)
    w1, p1, t1 = _clocks()
    after = _worker_cpu(client)
    workers = {a: after[a] - before[a] for a in after if a in before}
    k = c.counters
    return {"G": c.G, "wall": w1 - w0, "cpu": p1 - p0, "thread": t1 - t0, "workers": workers,
            "route": f"{int(k['cluster_blocks'])} column blocks on "
                     f"{int(k['cluster_workers_used'])} worker(s), "
                     f"{int(k['cluster_factorizations'])} factorisation(s) there"}


def _rel(G: np.ndarray, ref: np.ndarray) -> float:
    a, b = G.astype(np.float64), ref.astype(np.float64)
    return float(np.abs(a - b).max() / np.abs(b).max())


def _line(name: str, r: dict, ref: dict) -> str:
    wk = ", ".join(f"{v:.2f}" for v in sorted(r["workers"].values()))
    return (f"  {name:<12} wall {r['wall']:7.2f} s   CPU process {r['cpu']:7.2f} s, main thread "
            f"{r['thread']:7.2f} s   workers' CPU [{wk or '-'}] s   max |ΔG|/max|G| "
            f"{_rel(r['G'], ref['G']):.1e}   ({r['route']})")


def bench(name: str, system, precision: str) -> dict:
    import distributed

    n2m = system.B.shape[0]
    print(f"{name}: {system.ndof} DOFs, {system.m} CFEs (2m = {n2m}), "
          f"precision {precision}", flush=True)
    warm = assemble(slab_model(1))
    sc.condense(warm, precision=precision)  # the backend's libraries loaded, as on the workers
    out = {"serial": timed_serial(system, precision)}
    for n in (1, 2):
        t0 = time.perf_counter()
        with distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                      host="127.0.0.1", dashboard_address=":0") as lc, \
                distributed.Client(lc, set_as_default=False) as client:
            t_start = time.perf_counter() - t0
            sc.condense(warm, precision=precision, scheduler=client)  # imports on the workers
            out[n] = timed_cluster(system, precision, client)
        print(f"  (cluster of {n} worker{'s' * (n > 1)} started in {t_start:.1f} s)", flush=True)
    ref = out["serial"]
    print(_line("serial", ref, ref))
    for n in (1, 2):
        print(_line(f"{n} worker{'s' * (n > 1)}", out[n], ref))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[2, 4])
    ap.add_argument("--precision", choices=["float64", "float32"], default="float64")
    ap.add_argument("--long", type=int, nargs="*", default=[], metavar="CELLS",
                    help="also the long slab of large_interface.py with CELLS cells along its "
                    "joint (a joint as long as the model: the serial G by 2m solves too)")
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}", flush=True)
    models = {f"slab k = {k}": lambda k=k: slab_model(k) for k in args.sizes}
    if args.long:
        from large_interface import long_slab

        models.update({f"long slab, {n} cells": lambda n=n: long_slab(n, 2e5)
                       for n in args.long})
    results = {name: bench(name, assemble(build()), args.precision)
               for name, build in models.items()}
    print(f"load average at end: {os.getloadavg()}")
    print("ratios:")
    for k, r in results.items():
        one, two = r[1], r[2]
        cpu_one = max(one["workers"].values())
        cpu_two = max(two["workers"].values())
        print(f"  {k}: speed-up of 2 workers over 1: wall {one['wall'] / two['wall']:.2f}, "
              f"CPU critical path {cpu_one / cpu_two:.2f};  cluster of 2 over serial (wall) "
              f"{two['wall'] / r['serial']['wall']:.2f};  max |ΔG|/max|G| "
              f"{max(_rel(one['G'], r['serial']['G']), _rel(two['G'], r['serial']['G'])):.1e}")


if __name__ == "__main__":
    main()
