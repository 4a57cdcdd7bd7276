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

The load average is printed at the end: the times are only as good as the machine was quiet.
The same model against OpenSeesPy: ``benchmarks/dynamic_vs_opensees.py``.
Run:  python benchmarks/dynamic_slab.py [--sizes 1 2 4]   (k = 4: 82 572 DOFs)
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import runpy
import time
from pathlib import Path

import numpy as np

import stepcontact as sc

slab_model = runpy.run_path(str(Path(__file__).with_name("slab_on_foundation.py")),
                            run_name="slab_on_foundation")["slab_model"]


def solve_times(system, model, dt: float) -> tuple[float, float, float, float]:
    """(T_F, T_setup, T_S with all threads, T_S with one thread) of K̂ = c₀M + (1 − α)K,
    factorised apart from the run (the mean of 10 solves each).  Measured before the run:
    once a thread pool has been held to one thread, MKL's solves stay slower after it is
    released (seen on this machine), which would flatter the all-threads figure."""
    from threadpoolctl import threadpool_limits

    from stepcontact.fem.mass import mass
    from stepcontact.solver.condensation import Condensed

    K, M = system.K.tocsr(), mass(model, system.dofs, lumped=True)
    a = 4.0 / ((1 + 0.05) ** 2 * dt**2)
    t1 = time.perf_counter()
    cond = Condensed.from_system(dataclasses.replace(system, K=(a * M + (1 - 0.05) * K).tocsr()))
    t_setup = time.perf_counter() - t1
    t_f = float(cond.condensation.counters.get("factor_seconds", t_setup))
    rhs = np.ones(len(cond.free))
    cond.factor.solve(rhs)
    t1 = time.perf_counter()
    for _ in range(10):
        cond.factor.solve(rhs)
    t_s_all = (time.perf_counter() - t1) / 10
    with threadpool_limits(limits=1):  # as the run solves (solve_dynamic does so)
        t1 = time.perf_counter()
        for _ in range(10):
            cond.factor.solve(rhs)
        t_s = (time.perf_counter() - t1) / 10
    return t_f, t_setup, t_s_all, t_s


def run(k: int, dt: float = 1e-3, duration: float = 0.1) -> dict:
    model = slab_model(k).replace(program=(sc.Segment("weight", 1.0),))
    system = sc.assemble(model)
    t_f, t_setup, t_s_all, t_s = solve_times(system, model, dt)
    rest = sc.solve_static(system)
    t0 = time.perf_counter()
    res = sc.solve_dynamic(system, dt=dt, duration=duration, initial=rest, mass="lumped",
                           alpha=0.05,
                           loads={"uplift": sc.Pulse(1.5e5, 0.01, 0.05, "half_sine")})
    t_total = time.perf_counter() - t0
    c = res.counters
    e = res.energy
    work = float(np.abs(e["external"]).max())
    return {"k": k, "ndof": system.ndof, "cfes": system.m, "steps": int(c["steps"]),
            "events": len(res.events), "impacts": int(c["impacts"]), "T_total": t_total,
            "T_F": t_f, "T_setup": t_setup, "T_S": t_s, "T_S_all": t_s_all,
            "status": res.status.value, "numerical": float(e["numerical"][-1]) / work,
            "error": float(np.abs(e["error"]).max()) / work}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1, 2])
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}")
    rows = []
    for k in args.sizes:
        r = run(k)
        rows.append(r)
        print(f"k={k}: {r['ndof']} DOFs, {r['cfes']} CFEs, {r['steps']} steps, {r['events']} "
              f"events ({r['impacts']} impacts), {r['status']}; T_total {r['T_total']:.2f} s, "
              f"T_F {r['T_F']:.3f} s (setup with G {r['T_setup']:.3f} s), T_S "
              f"{r['T_S'] * 1e3:.2f} ms one thread ({r['T_S_all'] * 1e3:.2f} ms all threads); "
              f"energy: numerical {r['numerical']:.1%} of the work, "
              f"balance error {r['error']:.1e}")
    print(f"load average at end: {os.getloadavg()}")
    print("\nratios (last): T_total / (T_F + (steps + events) · T_S)  (target ≤ 2; T_S as the "
          "run solves, one thread; in brackets against T_S with all threads)")
    for r in rows:
        n = r["steps"] + r["events"]
        ratio = r["T_total"] / (r["T_F"] + n * r["T_S"])
        ratio_all = r["T_total"] / (r["T_F"] + n * r["T_S_all"])
        print(f"k={r['k']} ({r['ndof']} DOFs): {ratio:.2f} ({ratio_all:.2f})")


if __name__ == "__main__":
    main()
