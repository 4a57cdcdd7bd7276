"""Benchmark: the stilling-basin slab study (`stepcontact.study.basin`) as a sweep, and one
dynamic case at the default mesh.

The sweep: ``--cases`` impulse cases of the quick study (``basin.quick()``: a 20 × 2 slab,
tolerance 0.05 m, 30 steps per impulse; default 6 cases: positions 0.1, 0.5, 0.9 × directions
up, down, duration 0.5 s; the static case is left out), each a limit-thickness search
(``BasinCase``: bisection on the thickness, then the failing slab once more with its
results), run with ``rerun=True`` into a fresh store per executor:

* serial (in this process, one case after another; with ``--pinned`` also once more with BLAS
  held to one thread, as the pool's and the cluster's workers hold it, to tell the pool's
  parallelism from its pinning);
* the local process pool of ``run_sweep`` with ``--workers`` processes (spawned by the sweep:
  their start-up is part of its wall time);
* a ``distributed.LocalCluster`` of ``--workers`` worker processes, one thread each, through a
  ``Client`` (its start-up is timed apart from the sweep and printed beside it).

Per executor: wall time, cases per minute, and the sum of the cases' own times (measured in
the workers) against workers × wall time (the share of the wall time the workers spent in
cases); the CPU time of this process (process and main thread, ``benchmarks/_timing.py``) and
of its child processes (the pool's workers, the cluster's; ``os.times``, counted once they have
been shut down: the cluster's over its whole life, start and close included); then whether the
three datasets agree (h_limit to 1e-12 relative).

The dynamic case: ``BasinStudy()`` (40 × 4 slab cells), one impulse (x/L_p = 0.5, up, 1.0 s),
one ``check`` at a fixed thickness 2·h_kr with the options ``BasinCase`` uses (Δt = duration /
``steps``, response 1.5 × duration, HHT α, criterion): DOFs, CFEs, steps, events and seconds,
and the static run alone (assembly and ``solve_static``).

Printed first: the machine (CPUs, load average, and how much work ``--workers`` concurrent
pure-Python busy loops get done against one alone: the parallel capacity the machine offers
at the moment, ``--workers`` on a quiet machine; again at the end); last the ratios: the
pool's and the LocalCluster's speed-up over serial, and the dynamic case's cost against a
quick case: seconds of one check × the mean number of runs of a limit search (the quick
study's ``runs`` output) over the measured serial seconds per case (with ``--full``, the
same mesh on both sides: the share of a limit search that the checks explain).  Speed-ups
are wall-time ratios (what parallel execution is for), each followed by the CPU time of
every process of the run over the serial run's (the work that the parallel run adds); the
dynamic case's ratio is from process CPU time [main-thread CPU; wall].

Run:  python benchmarks/slab_study.py [--cases 6] [--workers 2] [--skip-dask] [--pinned]
                                      [--full] [--store DIR]
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from stepcontact.study.basin import BasinCase, BasinStudy, quick
from stepcontact.study.slab import check, slab_model
from stepcontact.study.sweep import run_sweep

if os.path.dirname(os.path.abspath(__file__)) not in sys.path:  # also when run by runpy
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import Timer, children_cpu  # noqa: E402  (benchmarks/_timing.py)


def _spin(barrier, queue, n: int) -> None:
    """A pure-Python busy loop of ``n`` iterations, started with the others (``barrier``)."""
    barrier.wait()
    t0 = time.perf_counter()
    s = 0
    for i in range(n):
        s += i * i
    queue.put(time.perf_counter() - t0)


def capacity(workers: int, n: int = 10_000_000) -> tuple[float, float]:
    """(seconds of the loop alone, cores' worth of work that ``workers`` concurrent loops
    did): how much parallel capacity the machine offers at the moment (``workers`` on a quiet
    machine with as many free cores)."""
    import multiprocessing

    ctx = multiprocessing.get_context("spawn")
    times = {}
    for k in (1, workers):
        barrier, queue = ctx.Barrier(k + 1), ctx.Queue()
        procs = [ctx.Process(target=_spin, args=(barrier, queue, n)) for _ in range(k)]
        for p in procs:
            p.start()
        barrier.wait()
        times[k] = [queue.get() for _ in procs]
        for p in procs:
            p.join()
    return times[1][0], workers * times[1][0] / max(times[workers])


def study_cases(args: argparse.Namespace) -> tuple[BasinStudy, list]:
    """The quick study (or its ``--full`` mesh) and its first ``--cases`` impulse cases."""
    n = max(1, args.cases)
    npos = math.ceil(n / 2)
    positions = (0.1, 0.5, 0.9) if npos == 3 else tuple(
        float(p) for p in np.round(np.linspace(0.1, 0.9, npos) if npos > 1 else [0.5], 4))
    changes: dict = {"positions": positions}
    if args.full:
        changes["cells"] = BasinStudy().cells
    study = quick(**changes)
    cases = [c for c in study.cases() if c.params["kind"] == "impulse"][:n]
    return study, cases


def sweep(study: BasinStudy, cases: list, store: Path, executor, workers: int | None) -> dict:
    """Run the cases into a fresh ``store`` (``rerun=True``); wall time and case times."""
    if store.exists():
        shutil.rmtree(store)
    seconds: list[float] = []
    func = BasinCase(study, str(store / "results"))
    c0 = children_cpu()
    with Timer() as t:
        ds = run_sweep(cases, func, store, executor=executor, workers=workers, progress=False,
                       rerun=True, name="slab study",
                       on_result=lambda o: seconds.append(o.seconds))
    return {"ds": ds, "wall": t.wall, "times": t.times, "children": children_cpu() - c0,
            "case_seconds": float(sum(seconds)),
            "failed": int(ds.attrs["failed"]), "missing": int(ds.attrs["missing"])}


def dask_sweep(study: BasinStudy, cases: list, store: Path, workers: int) -> dict:
    from distributed import Client, LocalCluster

    c0 = children_cpu()
    t0 = time.perf_counter()
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           host="127.0.0.1", dashboard_address=None)
    client = Client(cluster)
    try:
        client.wait_for_workers(workers)
        start = time.perf_counter() - t0
        r = sweep(study, cases, store, client, None)
    finally:
        t1 = time.perf_counter()
        client.close()
        cluster.close()
        close = time.perf_counter() - t1
    # the workers' CPU over the cluster's life (start, sweep, close), once they are reaped
    return r | {"start": start, "close": close, "children": children_cpu() - c0}


def dynamic_case() -> dict:
    """One check of the default study's slab at 2·h_kr under one impulse, as BasinCase runs
    it; and the static run alone."""
    from stepcontact.fem.assembly import assemble
    from stepcontact.solver.static import solve_static

    st = BasinStudy()
    imp = st.impulse(0.5, "up", 1.0)
    slab = st.slab(2.0 * st.h_kr)
    opts = {"criterion": st.criterion, "no_slip": st.no_slip, "alpha": st.alpha,
            "dt": imp.duration / st.steps, "duration": imp.start + 1.5 * imp.duration}
    with Timer() as t_assemble:
        system = assemble(slab_model(slab, imp))
    with Timer() as t_static:
        static = solve_static(system)
    with Timer() as t_check:
        out = check(slab, imp, keep=True, **opts)
    res = out.result
    c = res.counters if out.phase != "static" else {}
    return {"ndof": system.ndof, "cfes": system.m, "h": slab.thickness, "dt": opts["dt"],
            "duration": opts["duration"], "alpha": st.alpha, "t_assemble": t_assemble.times,
            "t_static": t_static.times, "static_events": len(static.events),
            "t_check": t_check.times,
            "steps": int(c.get("steps", 0)), "events": len(res.events),
            "impacts": int(c.get("impacts", 0)), "run_seconds": float(c.get("run_seconds",
                                                                             math.nan)),
            "outcome": out}


def identical(results: dict[str, dict], rtol: float = 1e-12) -> bool:
    ref = None
    for r in results.values():
        ds = r["ds"]
        if r["failed"] or r["missing"]:
            return False
        h = np.asarray(ds["h_limit"].values, float)
        if ref is None:
            ref = h
        elif h.shape != ref.shape or not np.all(np.abs(h - ref) <= rtol * np.abs(ref)):
            return False
    return True


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=6, help="impulse cases of the quick study")
    ap.add_argument("--workers", type=int, default=2,
                    help="processes of the local pool and workers of the LocalCluster")
    ap.add_argument("--pinned", action="store_true",
                    help="also run serial with BLAS held to one thread, as the pool's workers")
    ap.add_argument("--skip-dask", action="store_true", help="leave out the LocalCluster")
    ap.add_argument("--full", action="store_true",
                    help="the default BasinStudy() mesh (40 × 4) instead of quick()'s (20 × 2)")
    ap.add_argument("--store", type=Path, default=None,
                    help="directory of the stores (default: a temporary one, removed at the end)")
    args = ap.parse_args()

    try:
        cpus = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        cpus = os.cpu_count() or 1
    load = ", ".join(f"{v:.2f}" for v in os.getloadavg())
    t1, cap = capacity(args.workers)
    print(f"machine: {os.cpu_count()} CPUs ({cpus} available), load average {load}; "
          f"{args.workers} concurrent busy loops did {cap:.2f} loops' worth of work in the "
          f"time of the slowest (one alone: {t1:.2f} s)")

    study, cases = study_cases(args)
    tmp = args.store is None
    root = Path(tempfile.mkdtemp(prefix="slab-study-")) if tmp else args.store
    root.mkdir(parents=True, exist_ok=True)
    print(f"study: {len(cases)} impulse cases ({', '.join(c.id for c in cases)}), slab cells "
          f"{study.cells}, tol {study.tol:g} m, {study.steps} steps per impulse; store {root}")
    results: dict[str, dict] = {}
    try:
        results["serial"] = sweep(study, cases, root / "serial", "serial", None)
        if args.pinned:
            from threadpoolctl import threadpool_limits

            with threadpool_limits(limits=1):
                results["pinned"] = sweep(study, cases, root / "pinned", "serial", None)
        results["pool"] = sweep(study, cases, root / "pool", "process", args.workers)
        if not args.skip_dask:
            results["dask"] = dask_sweep(study, cases, root / "dask", args.workers)
        dyn = dynamic_case()
    finally:
        if tmp:
            shutil.rmtree(root, ignore_errors=True)

    n = len(cases)
    print()
    labels = {"serial": "serial", "pinned": "serial, BLAS held to one thread",
              "pool": f"local pool, {args.workers} processes",
              "dask": f"LocalCluster, {args.workers} workers × 1 thread"}
    for name, r in results.items():
        w = 1 if name in ("serial", "pinned") else args.workers
        extra = ""
        if name == "dask":
            extra = (f"; cluster start {r['start']:.1f} s, close {r['close']:.1f} s (with "
                     f"start: {n / (r['wall'] + r['start']) * 60:.2f} cases/min)")
        print(f"{labels[name]}: {r['wall']:.1f} s for {n} cases, {n / r['wall'] * 60:.2f} "
              f"cases/min; cases' own time {r['case_seconds']:.1f} s = "
              f"{r['case_seconds'] / (w * r['wall']):.0%} of {w} × wall; "
              f"failed {r['failed']}{extra}\n"
              f"    this process: {r['times']}; child processes: CPU {r['children']:.1f} s")
    ds = results["serial"]["ds"]
    runs = np.asarray(ds["runs"].values, float)
    failing = np.asarray(ds["h_failing"].values, float)
    checks = runs + (failing > 0)
    print("h_limit (m): " + ", ".join(f"{c}: {h:.4f}" for c, h in
                                      zip(ds["case"].values, ds["h_limit"].values,
                                          strict=True)))
    print(f"runs per limit search: mean {runs.mean():.2f} (min {runs.min():.0f}, max "
          f"{runs.max():.0f}); checks per case with the failing slab's re-run: mean "
          f"{checks.mean():.2f}")
    print(f"results identical: {'yes' if identical(results) else 'no'}")
    o = dyn["outcome"]
    print(f"\ndynamic case (BasinStudy() mesh, impulse x/L_p = 0.5 up 1.0 s, h = 2·h_kr = "
          f"{dyn['h']:.2f} m, Δt {dyn['dt'] * 1e3:.2f} ms, {dyn['duration']:g} s, "
          f"α {dyn['alpha']:g}): {dyn['ndof']} DOFs, {dyn['cfes']} CFEs, {dyn['steps']} steps, "
          f"{dyn['events']} events ({dyn['impacts']} impacts); check {dyn['t_check']} "
          f"(dynamic run {dyn['run_seconds']:.2f} s wall); outcome: "
          f"{'passes' if o.passes else 'lifts off' if o.lifted else 'slides'}"
          + (f" at t = {o.when:.3f} s" if o.when is not None else ""))
    print(f"static run alone: assembly {dyn['t_assemble']}; solve_static "
          f"{dyn['t_static']} ({dyn['static_events']} events)")
    t1, cap = capacity(args.workers)
    print(f"load average at end: {', '.join(f'{v:.2f}' for v in os.getloadavg())}; "
          f"{args.workers} busy loops: {cap:.2f} loops' worth (one alone: {t1:.2f} s)")

    serial = results["serial"]["wall"]

    def cpu(r: dict) -> float:  # the CPU time of every process of a sweep, s
        return r["times"].process + r["children"]

    def work(r: dict) -> str:
        return f"CPU of all processes / serial's {cpu(r) / cpu(results['serial']):.2f}"

    print("\nratios (last): speed-ups from wall time, each with its CPU time against the "
          "serial run's; the dynamic case from process CPU time [main-thread CPU; wall]")
    print(f"pool speed-up over serial ({args.workers} processes): "
          f"{serial / results['pool']['wall']:.2f} ({work(results['pool'])})")
    if "pinned" in results:
        print(f"serial with BLAS on one thread, speed-up over serial: "
              f"{serial / results['pinned']['wall']:.2f} ({work(results['pinned'])})")
    if "dask" in results:
        r = results["dask"]
        print(f"LocalCluster speed-up over serial ({args.workers} workers): "
              f"{serial / r['wall']:.2f} (with its start-up: "
              f"{serial / (r['wall'] + r['start']):.2f}; {work(r)}, the workers' over the "
              f"cluster's life)")
    side = "same mesh" if args.full else "default mesh against the quick study's"
    chk, per_case = dyn["t_check"], results["serial"]["times"] / n
    ratio = {c: getattr(chk, c) * runs.mean() / getattr(per_case, c)
             for c in ("process", "thread", "wall")}
    print(f"dynamic case × mean runs / serial s per case ({side}): {chk.process:.2f} s × "
          f"{runs.mean():.2f} / {per_case.process:.2f} s = {ratio['process']:.2f} "
          f"[{ratio['thread']:.2f}; {ratio['wall']:.2f}] (with the re-run, × "
          f"{checks.mean():.2f}: {ratio['process'] / runs.mean() * checks.mean():.2f})")


if __name__ == "__main__":
    main()
