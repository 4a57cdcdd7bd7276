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

Every time is printed as wall, process CPU and main-thread CPU (``benchmarks/_timing.py``):
T_total (condensation and run), T_cond (``sc.condense``: forming K₀, T_F and T_G) and the event
loop.  T_total/T_cond and float64 over float32 are from process CPU time (the factorisation
and large dense work use every thread), the main-thread CPU and wall ratios beside them.  The
library records T_F and T_G apart only in wall time (``counters["factor_seconds"]``,
``["condense_seconds"]``), so T_total/T_F and T_total/(T_F + T_G) are from wall time.

Run:  python benchmarks/large_interface.py [--cells 5000] [--lift 2e5] [--precision float32]
      python benchmarks/large_interface.py --cells 5000 --compare
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

import stepcontact as sc
from stepcontact.fem.assembly import assemble
from stepcontact.solver.condensation import dense_memory

if os.path.dirname(os.path.abspath(__file__)) not in sys.path:  # run from elsewhere
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import Timer, Times  # noqa: E402  (benchmarks/_timing.py)
from slab_on_foundation import PeakMemory  # noqa: E402  (its sampler of resident memory)


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
    with Timer() as t_asm:
        model = long_slab(cells, lift)
        system = assemble(model)
    n2m = 2 * system.m
    item = 4 if precision == "float32" else 8
    est = dense_memory(n2m, itemsize=item)
    print(f"[{precision}] {system.ndof} DOFs, {system.m} CFEs: dense G {est['G'] / 2**20:.0f} "
          f"MB, scheme LU and workspace {est['schemes'] / 2**20:.0f} MB (estimates)", flush=True)
    t0 = Times.now()
    with PeakMemory() as mem:
        c = sc.condense(system, precision=precision)
        t1, w1 = Times.now(), mem.watch_cpu
        res = sc.solve_static(system, condensation=c)
        t2 = Times.now()
    # the memory window's sampling thread is no work of the run
    t_cond, t_total = t1 - t0 - Times(process=w1), t2 - t0 - Times(process=mem.watch_cpu)
    t_f = c.counters["factor_seconds"]
    t_g = c.counters["condense_seconds"]
    out = {
        "precision": c.precision, "ndof": system.ndof, "cfes": system.m,
        "status": res.status.value, "message": res.message, "events": len(res.events),
        "lam": [float(e.lam) for e in res.events],
        "first_opening": (res.multipliers[-1].first_opening if res.multipliers else None),
        "t_asm": t_asm.times.as_dict(), "t_cond": t_cond.as_dict(), "t_f": t_f, "t_g": t_g,
        "t_total": t_total.as_dict(),
        "G_method": "the Schur block" if c.counters["condensed_columns"] == 0 else "2m solves",
        "residual": float(np.max(res.residual)), "violation": float(np.max(res.violation)),
        "mem_mb": mem.mb, "refinements": int(res.counters.get("refinements", 0)),
        "scheme_factorizations": int(res.counters["scheme_factorizations"]),
    }
    print(f"[{precision}] status {out['status']}: {out['message']}")
    print(f"[{precision}] events {out['events']}, first opening at λ = {out['first_opening']}")
    print(f"[{precision}] assembly {t_asm.times}\n"
          f"[{precision}] condensation T_cond {t_cond} (wall: T_F {t_f:.1f} s, T_G {t_g:.1f} s, "
          f"G by {out['G_method']})\n"
          f"[{precision}] event loop {t_total - t_cond} ({out['scheme_factorizations']} scheme "
          f"factorisations, {out['refinements']} refinement corrections)\n"
          f"[{precision}] T_total {t_total}")
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
            print(f"\nratios (last): {_ratios(out)}")
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
        print(f"{p}: {_ratios(r)}   peak memory {r['mem_mb']:.0f} MB")
    ta, tb = Times.from_dict(a["t_total"]), Times.from_dict(b["t_total"])
    print(f"float64/float32: time {ta.process / tb.process:.2f} from process CPU "
          f"[{ta.thread / tb.thread:.2f} main-thread CPU; {ta.wall / tb.wall:.2f} wall]   "
          f"peak memory {a['mem_mb'] / max(b['mem_mb'], 1e-9):.2f}")


def _ratios(r: dict) -> str:
    """T_total/T_cond from CPU time; T_total/T_F and T_total/(T_F + T_G) from wall time (the
    library records T_F and T_G in wall time only)."""
    t, c = Times.from_dict(r["t_total"]), Times.from_dict(r["t_cond"])
    return (f"T_total/T_cond = {t.process / c.process:.2f} from process CPU "
            f"[{t.thread / c.thread:.2f} main-thread CPU; {t.wall / c.wall:.2f} wall]   "
            f"from wall: T_total/T_F = {t.wall / r['t_f']:.1f}   "
            f"T_total/(T_F+T_G) = {t.wall / (r['t_f'] + r['t_g']):.2f}")


if __name__ == "__main__":
    main()
