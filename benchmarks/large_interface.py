"""Benchmark: a 2D model with a large contact interface (≥ 5 000 CFEs) run to the end.

A long concrete slab (length 0.1 m × n cells, 1 m thick) on a rock foundation (2 m deep), both
meshed with n cells along the joint, so the joint has n + 1 node-to-node CFEs (f = 0.7).  Load
path: self-weight, then an uplift force on the slab's left end growing to ``--lift`` N per metre
run, which lifts the end off (opening spreads along the first metres of the joint).

With m CFEs the dense condensed matrix G is 2m × 2m: at m = 5 001, 800 MB, and the scheme
matrix with its LU about three times that; the Schur route would need a dense block of the
4m contact DOFs (2.4 GB per copy), so :func:`stepcontact.solver.condensation.schur_fits` picks
G by blocks of solves instead.  Past the memory limit the run stops before any work with the
estimate (``check_dense_memory``).  Prints DOFs, CFEs, events, the time of each phase and peak
memory, and last the ratios T_total/T_F and T_total/(T_F + T_G).

Run:  python benchmarks/large_interface.py [--cells 5000] [--lift 2e5]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import stepcontact as sc
from stepcontact.fem.assembly import assemble
from stepcontact.solver.condensation import dense_memory

try:  # the slab benchmark's sampler of resident memory
    from slab_on_foundation import PeakMemory
except ImportError:  # run from elsewhere
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from slab_on_foundation import PeakMemory


def long_slab(n: int, lift: float) -> sc.Model:
    concrete = sc.Material(E=30e9, nu=0.2, density=2400)
    rock = sc.Material(E=5e9, nu=0.25, density=2200)
    L = 0.1 * n
    slab = sc.rectangle("slab", (0, 0), (L, 1), n, 2, concrete)
    found = sc.rectangle("foundation", (0, -2), (L, 0), n, 2, rock)
    m = sc.Model(bodies=[found, slab], plane="strain", thickness=1.0, name=f"long-slab-{n}")
    end = m.select("slab", x=0)
    return m.add(
        sc.Support("bed", m.select("foundation", y=-2), "xy"),
        sc.Interface("joint", plus=m.select("slab", y=0), minus=m.select("foundation", y=0),
                     friction=0.7),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("slab",))]),
        sc.LoadPattern("lift", [sc.NodalLoad(end, fy=1.0 / len(end))]),  # 1 N per unit λ
        sc.Segment("weight", 1.0),
        sc.Segment("lift", lift),
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cells", type=int, default=5000, help="cells along the joint (CFEs - 1)")
    ap.add_argument("--lift", type=float, default=2e5, help="end of the uplift segment, N")
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}", flush=True)
    t0 = time.perf_counter()
    model = long_slab(args.cells, args.lift)
    system = assemble(model)
    t_asm = time.perf_counter() - t0
    n2m = 2 * system.m
    est = dense_memory(n2m)
    print(f"{system.ndof} DOFs, {system.m} CFEs: dense G {est['G'] / 2**20:.0f} MB, scheme "
          f"matrices {est['schemes'] / 2**20:.0f} MB (estimates)", flush=True)
    t0 = time.perf_counter()
    with PeakMemory() as mem:
        c = sc.condense(system)
        t_cond = time.perf_counter() - t0
        res = sc.solve_static(system, condensation=c)
    t_total = time.perf_counter() - t0
    t_f = c.counters["factor_seconds"]
    t_g = c.counters["condense_seconds"]
    print(f"status {res.status.value}: {res.message}")
    print(f"events {len(res.events)}, first opening at λ = "
          f"{res.multipliers[-1].first_opening if res.multipliers else float('nan')}")
    print(f"assembly {t_asm:.1f} s; condensation {t_cond:.1f} s (T_F {t_f:.1f} s, T_G {t_g:.1f} s,"
          f" G by {'the Schur block' if c.counters['condensed_columns'] == 0 else '2m solves'})"
          f"; event loop {t_total - t_cond:.1f} s; T_total {t_total:.1f} s")
    print(f"max residual {np.max(res.residual):.1e}, max violation {np.max(res.violation):.1e}")
    print(f"peak memory above assembly {mem.mb:.0f} MB; load average at end {os.getloadavg()}")
    print(f"\nratios (last): T_total/T_F = {t_total / t_f:.1f}   "
          f"T_total/(T_F+T_G) = {t_total / (t_f + t_g):.2f}")


if __name__ == "__main__":
    main()
