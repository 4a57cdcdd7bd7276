"""Benchmark: a 2D model with a large contact interface (≥ 5 000 CFEs) run to the end.

A long concrete slab (length 0.1 m × n cells, 1 m thick) on a rock foundation (2 m deep), both
meshed with n cells along the joint, so the joint has n + 1 node-to-node CFEs (f = 0.7).  Load
path: self-weight, then an uplift force on the slab's left end growing to ``--lift`` N per metre
run, which lifts the end off (opening spreads along the first metres of the joint).

With m CFEs the dense condensed matrix G is 2m × 2m: at m = 5 001, 800 MB in float64, and the
scheme LU with its workspace about twice that; the Schur route would need a dense block of the
4m contact DOFs (2.4 GB per copy), so :func:`stepcontact.solver.condensation.schur_fits` picks
G by blocks of solves instead.  ``--precision float32`` (the default here) runs the
large-interface path: G (as D G − I) and the scheme LUs in float32, every scheme solve refined
to float64 accuracy against the sparse factorisation — half the dense memory and work, so twice
the interface fits (``precision="auto"`` takes it by itself when float64 would not fit).  Past
the memory limit of both the run stops before any work with the estimate.

``--compare`` runs float64 and float32 one after the other, each in a fresh process (so that
each peak of resident memory is its own), and prints both and the largest difference of their
event load factors.  Prints DOFs, CFEs, events, the time of each phase and peak memory, and
last the ratios (T_total/T_F, T_total/(T_F + T_G), float64 over float32).

Run:  python benchmarks/large_interface.py [--cells 5000] [--lift 2e5] [--precision float32]
      python benchmarks/large_interface.py --cells 5000 --compare
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

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


def run(cells: int, lift: float, precision: str) -> dict:
    t0 = time.perf_counter()
    model = long_slab(cells, lift)
    system = assemble(model)
    t_asm = time.perf_counter() - t0
    n2m = 2 * system.m
    item = 4 if precision == "float32" else 8
    est = dense_memory(n2m, itemsize=item)
    print(f"[{precision}] {system.ndof} DOFs, {system.m} CFEs: dense G {est['G'] / 2**20:.0f} "
          f"MB, scheme LU and workspace {est['schemes'] / 2**20:.0f} MB (estimates)", flush=True)
    t0 = time.perf_counter()
    with PeakMemory() as mem:
        c = sc.condense(system, precision=precision)
        t_cond = time.perf_counter() - t0
        res = sc.solve_static(system, condensation=c)
    t_total = time.perf_counter() - t0
    t_f = c.counters["factor_seconds"]
    t_g = c.counters["condense_seconds"]
    out = {
        "precision": c.precision, "ndof": system.ndof, "cfes": system.m,
        "status": res.status.value, "message": res.message, "events": len(res.events),
        "lam": [float(e.lam) for e in res.events],
        "first_opening": (res.multipliers[-1].first_opening if res.multipliers else None),
        "t_asm": t_asm, "t_cond": t_cond, "t_f": t_f, "t_g": t_g, "t_total": t_total,
        "G_method": "the Schur block" if c.counters["condensed_columns"] == 0 else "2m solves",
        "residual": float(np.max(res.residual)), "violation": float(np.max(res.violation)),
        "mem_mb": mem.mb, "refinements": int(res.counters.get("refinements", 0)),
        "scheme_factorizations": int(res.counters["scheme_factorizations"]),
    }
    print(f"[{precision}] status {out['status']}: {out['message']}")
    print(f"[{precision}] events {out['events']}, first opening at λ = {out['first_opening']}")
    print(f"[{precision}] assembly {t_asm:.1f} s; condensation {t_cond:.1f} s (T_F {t_f:.1f} s, "
          f"T_G {t_g:.1f} s, G by {out['G_method']}); event loop {t_total - t_cond:.1f} s "
          f"({out['scheme_factorizations']} scheme factorisations, {out['refinements']} "
          f"refinement corrections); T_total {t_total:.1f} s")
    print(f"[{precision}] max residual {out['residual']:.1e}, max violation "
          f"{out['violation']:.1e}; peak memory above assembly {mem.mb:.0f} MB", flush=True)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cells", type=int, default=5000, help="cells along the joint (CFEs - 1)")
    ap.add_argument("--lift", type=float, default=2e5, help="end of the uplift segment, N")
    ap.add_argument("--precision", default="float32", choices=["float32", "float64", "auto"])
    ap.add_argument("--compare", action="store_true",
                    help="run float64 and float32, each in a fresh process, and compare")
    ap.add_argument("--json", default=None, help=argparse.SUPPRESS)  # a child's output file
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}", flush=True)
    if not args.compare:
        out = run(args.cells, args.lift, args.precision)
        if args.json:
            Path(args.json).write_text(json.dumps(out))
        else:
            print(f"load average at end {os.getloadavg()}")
            print(f"\nratios (last): T_total/T_F = {out['t_total'] / out['t_f']:.1f}   "
                  f"T_total/(T_F+T_G) = {out['t_total'] / (out['t_f'] + out['t_g']):.2f}")
        return
    runs = {}
    for p in ("float64", "float32"):
        path = Path(f".large_interface_{p}_{os.getpid()}.json")
        subprocess.run([sys.executable, __file__, "--cells", str(args.cells), "--lift",
                        str(args.lift), "--precision", p, "--json", str(path)], check=True)
        runs[p] = json.loads(path.read_text())
        path.unlink()
    a, b = runs["float64"], runs["float32"]
    same = a["status"] == b["status"] and a["events"] == b["events"]
    dlam = (max((abs(x - y) / max(abs(x), 1.0) for x, y in zip(a["lam"], b["lam"], strict=True)),
                default=0.0) if same else float("nan"))
    print(f"load average at end {os.getloadavg()}")
    print(f"same status and events: {same}; largest relative difference of event λ: {dlam:.1e}")
    print("\nratios (last):")
    for p, r in runs.items():
        print(f"{p}: T_total/T_F = {r['t_total'] / r['t_f']:.1f}   T_total/(T_F+T_G) = "
              f"{r['t_total'] / (r['t_f'] + r['t_g']):.2f}   peak memory {r['mem_mb']:.0f} MB")
    print(f"float64/float32: time {a['t_total'] / b['t_total']:.2f}   peak memory "
          f"{a['mem_mb'] / max(b['mem_mb'], 1e-9):.2f}")


if __name__ == "__main__":
    main()
