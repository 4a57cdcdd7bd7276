"""Benchmark: the per-step cost of the dynamic driver on the smallest models — a 2-DOF
block on a rough floor held by a spring and driven harmonically (Den Hartog's forced
stick-slip, tests/test_dynamics.py: k = 1e4 N/m, m = 1 kg, μN = 30 N, r = ω/ω₀ = 2; a slip
reversal, i.e. two events, every half period) and a 1-DOF spring–mass without contact, each
over a few thousand steps (Δt = T/100).

Prints per model: DOFs, CFEs, steps, events, the backend of K̂, and the run's CPU time per
step (process and main-thread CPU, and wall time) in ms; the ratios (last) are the CPU ms per
step against the target of issue 27 (≤ 0.3 ms per step on a 2-DOF model).

Run:  python benchmarks/dynamic_small.py [--periods 30] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import stepcontact as sc
from stepcontact.model.timefunction import Harmonic
from stepcontact.solver.linalg import auto_backend

TARGET_MS = 0.3


def den_hartog(periods: float, r: float = 2.0):
    """(model, solve_dynamic kwargs) of the forced stick-slip block (2 DOFs, 1 CFE)."""
    k, m_, N, F0, mu = 1e4, 1.0, 100.0, 100.0, 0.3
    dm = sc.DiscreteModel(K=[[k, 0.0], [0.0, 0.0]], normal_rows=[[0, 1]],
                          tangent_rows=[[1, 0]], loads={"weight": {"uy": -N},
                                                        "force": {"ux": 1.0}},
                          friction=mu, dof_names=("ux", "uy"),
                          program=[sc.Segment("weight", 1.0)])
    st = sc.solve_static(dm)
    w = r * np.sqrt(k / m_)
    T = 2 * np.pi / w
    return dm, dict(dt=T / 100, duration=periods * T, mass=np.diag([m_, m_]), initial=st,
                    loads={"force": Harmonic(F0, w / (2 * np.pi), np.pi / 2)})


def oscillator(periods: float):
    """(model, solve_dynamic kwargs) of a 1-DOF spring–mass under a harmonic force."""
    k, m_ = 1e4, 1.0
    dm = sc.DiscreteModel(K=[[k]], normal_rows=np.zeros((0, 1)), tangent_rows=np.zeros((0, 1)),
                          loads={"force": {"u": 1.0}}, dof_names=("u",))
    T = 2 * np.pi * np.sqrt(m_ / k)
    return dm, dict(dt=T / 100, duration=periods * T, mass=np.diag([m_]),
                    loads={"force": Harmonic(10.0, 0.5 / T)})


def timed(model, kwargs, repeat: int) -> dict:
    """The best of ``repeat`` runs: CPU (process, thread) and wall seconds, and the result."""
    best = None
    for _ in range(repeat):
        p0, t0, w0 = time.process_time(), time.thread_time(), time.perf_counter()
        res = sc.solve_dynamic(model, **kwargs)
        p1, t1, w1 = time.process_time(), time.thread_time(), time.perf_counter()
        row = {"process": p1 - p0, "thread": t1 - t0, "wall": w1 - w0, "res": res}
        if best is None or row["process"] < best["process"]:
            best = row
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--periods", type=float, default=30.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}")
    rows = []
    for name, make in (("2-DOF stick-slip (Den Hartog)", den_hartog),
                       ("1-DOF spring-mass", oscillator)):
        model, kw = make(args.periods)
        r = timed(model, kw, args.repeat)
        res = r["res"]
        steps = int(res.counters["steps"])
        backend = auto_backend(int(res.counters["ndof"]))
        rows.append((name, steps, r))
        print(f"{name}: {res.counters.get('ndof')} DOFs, {res.counters.get('cfes')} CFEs, "
              f"{steps} steps, {len(res.events)} events, backend {backend}, {res.status.value}; "
              f"CPU {r['process']:.3f} s process, {r['thread']:.3f} s main thread, "
              f"wall {r['wall']:.3f} s")
    print(f"load average at end: {os.getloadavg()}")
    print(f"\nratios (last): CPU ms per step, process (main thread, wall); target ≤ {TARGET_MS} "
          "ms on the 2-DOF model")
    for name, steps, r in rows:
        ms = 1e3 * r["process"] / steps
        print(f"{name}: {ms:.3f} ms/step ({1e3 * r['thread'] / steps:.3f}, "
              f"{1e3 * r['wall'] / steps:.3f}); {ms / TARGET_MS:.2f} × the target")


if __name__ == "__main__":
    main()
