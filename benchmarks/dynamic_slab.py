"""Benchmark: the stilling-basin-like slab of `slab_on_foundation.py` under a pressure pulse,
in time (`sc.solve_dynamic`).

The slab (30 m × 2 m, rigid frictional contact with its foundation, f = 0.7) rests under its
weight (a static run), then a half-sine uplift pulse (peak 1.5e5 Pa upstream, triangular along
the joint, 50 ms from t = 10 ms; at its peak three times the slab's weight per m² upstream)
throws most of it off its foundation, to land again; Newmark–HHT (α = 0.05), lumped mass,
Δt = 1 ms, 0.1 s.  Prints per mesh size k: DOFs, CFEs, steps, events and impacts, the run
time T_total, the time T_F of the one factorisation of K̂ (and T_setup with the condensed
contact matrix), the time T_S of one solve (with one thread, as the run solves: see
``solve_dynamic``; and with all threads), the energy ledger's numerical share and balance
error, and last the ratio

    T_total / (T_F + (steps + events) · T_S)      (target ≤ 2: one factorisation, one solve
                                                   per step and per event)

Every time is printed as wall, process CPU and main-thread CPU (``benchmarks/_timing.py``).
The run holds every thread pool to one thread, its factorisation included, so the ratio is
from main-thread CPU time with T_F and T_S measured with one thread as the run does them (the
process-CPU and wall ratios beside it); in brackets from wall time, as before this script
measured CPU time: with T_F measured with all threads, and against T_S with all threads too
(with all threads, CPU time counts the pools' spinning).

The load average is printed at the end: the times are only as good as the machine was quiet.
``--repeat N`` runs the dynamic interval N times and keeps the run of least main-thread CPU
time, and takes T_S as the least of N means of 10 solves (each clock apart): on a busy machine
the best of a few holds where one run does not.
The same model against OpenSeesPy: ``benchmarks/dynamic_vs_opensees.py``.
Run:  python benchmarks/dynamic_slab.py [--sizes 1 2 4] [--repeat 3]   (k = 4: 82 572 DOFs)
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import runpy
import sys
from pathlib import Path

import numpy as np

import stepcontact as sc

_slab = runpy.run_path(str(Path(__file__).with_name("slab_on_foundation.py")),
                       run_name="slab_on_foundation")
slab_model, factor_and_condense = _slab["slab_model"], _slab["factor_and_condense"]
_warm_up = _slab["_warm_up"]
if os.path.dirname(os.path.abspath(__file__)) not in sys.path:  # also when run by runpy
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import Timer, Times, repeat  # noqa: E402  (benchmarks/_timing.py)


def _least(times: list[Times]) -> Times:
    """The least of each clock over ``times``."""
    return Times(*(min(getattr(t, c) for t in times) for c in ("wall", "process", "thread")))


def solve_times(system, model, dt: float, reps: int = 1) -> dict[str, Times]:
    """T_F and T_setup (T_F + forming G) of K̂ = c₀M + (1 − α)K, factorised apart from the run
    as the static run factorises (``factor_and_condense`` of slab_on_foundation.py), with all
    threads and with one thread (``T_F1``, ``T_setup1``: as the run, which holds every pool to
    one thread); T_S with all threads and with one thread (the mean of 10 solves each).  The
    all-threads figures are measured first: once a thread pool has been held to one thread,
    MKL's solves stay slower after it is released (seen on this machine), which would flatter
    them.  ``reps``: T_S is the least of that many means (each clock apart)."""
    from threadpoolctl import threadpool_limits

    from stepcontact.fem.mass import mass

    K, M = system.K.tocsr(), mass(model, system.dofs, lumped=True)
    a = 4.0 / ((1 + 0.05) ** 2 * dt**2)
    hat = dataclasses.replace(system, K=(a * M + (1 - 0.05) * K).tocsr())
    _warm_up("auto")  # the backend's code loaded on first use is no part of T_F
    f, cond = factor_and_condense(hat)
    rhs = np.ones(cond.A.shape[0])
    cond.factor.solve(rhs)
    t_s_all = _least([repeat(lambda: cond.factor.solve(rhs), 10) for _ in range(reps)])
    with threadpool_limits(limits=1):  # as the run factorises and solves (solve_dynamic)
        t_s = _least([repeat(lambda: cond.factor.solve(rhs), 10) for _ in range(reps)])
        f1, _ = factor_and_condense(hat)
    t_f, t_f1 = Times.from_dict(f["T_F"]), Times.from_dict(f1["T_F"])
    return {"T_F": t_f, "T_setup": t_f + Times.from_dict(f["T_G"]), "T_F1": t_f1,
            "T_setup1": t_f1 + Times.from_dict(f1["T_G"]), "T_S": t_s, "T_S_all": t_s_all}


def run(k: int, dt: float = 1e-3, duration: float = 0.1, reps: int = 1) -> dict:
    model = slab_model(k).replace(program=(sc.Segment("weight", 1.0),))
    system = sc.assemble(model)
    times = solve_times(system, model, dt, reps)
    rest = sc.solve_static(system)
    best = None
    for _ in range(reps):  # (the run of least main-thread CPU time)
        with Timer() as t_run:
            res = sc.solve_dynamic(system, dt=dt, duration=duration, initial=rest,
                                   mass="lumped", alpha=0.05,
                                   loads={"uplift": sc.Pulse(1.5e5, 0.01, 0.05, "half_sine")})
        if best is None or t_run.times.thread < best[1].thread:
            best = (res, t_run.times)
    res, t_total = best
    c = res.counters
    e = res.energy
    work = float(np.abs(e["external"]).max())
    return {"k": k, "ndof": system.ndof, "cfes": system.m, "steps": int(c["steps"]),
            "events": len(res.events), "impacts": int(c["impacts"]), "T_total": t_total,
            **times, "status": res.status.value, "numerical": float(e["numerical"][-1]) / work,
            "error": float(np.abs(e["error"]).max()) / work}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--repeat", type=int, default=1,
                    help="runs per size: the least CPU time is kept (and T_S likewise)")
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}")
    rows = []
    for k in args.sizes:
        r = run(k, reps=max(1, args.repeat))
        rows.append(r)
        print(f"k={k}: {r['ndof']} DOFs, {r['cfes']} CFEs, {r['steps']} steps, {r['events']} "
              f"events ({r['impacts']} impacts), {r['status']}\n"
              f"    T_total {r['T_total']}\n"
              f"    one thread (as the run): T_F {r['T_F1'].fmt(digits=3)} (setup with G "
              f"{r['T_setup1'].fmt(digits=3)}), T_S {r['T_S'].fmt('ms', 2)}\n"
              f"    all threads: T_F {r['T_F'].fmt(digits=3)} (setup with G "
              f"{r['T_setup'].fmt(digits=3)}), T_S {r['T_S_all'].fmt('ms', 2)}\n"
              f"    energy: numerical {r['numerical']:.1%} of the work, "
              f"balance error {r['error']:.1e}", flush=True)
    print(f"load average at end: {os.getloadavg()}")
    print("\nratios (last): T_total / (T_F + (steps + events) · T_S)  (target ≤ 2; T_F and T_S "
          "as the run does them, one thread) from main-thread CPU [process CPU; wall]; "
          "(wall, T_F with all threads; and T_S with all threads too)")
    for r in rows:
        n = r["steps"] + r["events"]
        ratio = {c: getattr(r["T_total"], c) / (getattr(r["T_F1"], c) + n * getattr(r["T_S"], c))
                 for c in ("thread", "process", "wall")}
        ratio_f = r["T_total"].wall / (r["T_F"].wall + n * r["T_S"].wall)
        ratio_all = r["T_total"].wall / (r["T_F"].wall + n * r["T_S_all"].wall)
        print(f"k={r['k']} ({r['ndof']} DOFs): {ratio['thread']:.2f} [{ratio['process']:.2f}; "
              f"{ratio['wall']:.2f}] ({ratio_f:.2f}; {ratio_all:.2f})")


if __name__ == "__main__":
    main()
