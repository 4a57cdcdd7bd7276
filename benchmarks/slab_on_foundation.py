"""Benchmark: a stilling-basin-like slab on an elastic foundation at several mesh sizes.

Load path: self-weight; a horizontal push on the slab's upstream face (slip spreads along the
joint); then uplift pressure under the slab, triangular (largest upstream), growing until the
slab lifts off (opening spreads along the joint).  Prints, per mesh: DOFs, CFEs, events, total
time T_total, the time T_F of one factorisation of the same matrix (ordering included), the time
T_G of forming the condensed contact matrix G by the chosen method (T_col = T_G / 2m per column),
T_S of one solve with the same backend, the peak memory of the run and of the factorisation alone
(above the memory held after assembly), and last the ratios

    T_total / (T_F + E·T_S)          (one factorisation + one solve per event)
    T_total / (T_F + 2m·T_col)       (target ≤ 1.5: the floor of forming G once)
    T_total / (E·(T_F + T_S))        (against refactorising at every event)
    M_run / M_F                      (target ≤ 2: peak memory against the factorisation's)

A friction sweep (``--sweep K``, default K = 2): 20 runs of the size-K model with friction
coefficients 0.3 … 1.0, once reusing one condensation (``sc.condense`` then
``solve_static(..., condensation=c)``) and once as 20 independent runs; the ratio of the two
times is printed last.

Run:  python benchmarks/slab_on_foundation.py [--sizes 1 2 4 8] [--sweep 2]
The size factor k gives a foundation mesh of 125k × 19k cells and a slab of 75k × 2k
(k = 8: 326 740 DOFs, 601 CFEs, about 860 events).  ``--backend`` picks the sparse backend
(default: the fastest installed); ``--save PREFIX`` writes each result file.
"""

from __future__ import annotations

import argparse
import os
import resource
import threading
import time

import numpy as np

import stepcontact as sc
from stepcontact.fem.assembly import assemble
from stepcontact.solver.condensation import (
    Condensation,
    contact_dofs,
    schur_pays,
    static_operator,
)
from stepcontact.solver.linalg import factorize


class PeakMemory:
    """Peak resident memory above the level at entry, MB, sampled every 2 ms from
    /proc/self/statm (Linux); elsewhere the process's ru_maxrss (a coarser high-water mark)."""

    def __enter__(self) -> PeakMemory:
        self.start = self.peak = self._rss()
        self._stop = threading.Event()
        self._t = threading.Thread(target=self._watch, daemon=True)
        self._t.start()
        return self

    def __exit__(self, *exc) -> None:
        self._stop.set()
        self._t.join()
        self.peak = max(self.peak, self._rss())

    @property
    def mb(self) -> float:
        return (self.peak - self.start) / 2**20

    def _watch(self) -> None:
        while not self._stop.wait(0.002):
            self.peak = max(self.peak, self._rss())

    @staticmethod
    def _rss() -> int:
        try:
            with open("/proc/self/statm") as f:
                return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
        except OSError:
            return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def slab_model(k: int) -> sc.Model:
    """Slab 30 m × 2 m (C25 concrete) on a 50 m × 20 m foundation (rock, E = 5 GPa)."""
    concrete = sc.Material(E=30e9, nu=0.2, density=2400)
    rock = sc.Material(E=5e9, nu=0.25, density=2200)
    n_joint = 75 * k  # cells along the joint
    slab = sc.rectangle("slab", (10, 0), (40, 2), n_joint, 2 * k, concrete)
    found = sc.rectangle("foundation", (0, -20), (50, 0), 125 * k, 19 * k, rock)
    m = sc.Model(bodies=[found, slab], plane="strain", thickness=1.0, name=f"slab-k{k}")
    bottom = m.select("foundation", y=-20)
    sides = m.select("foundation", where=lambda x, y: (x < 1e-9) | (x > 50 - 1e-9))
    joint_s = m.select("slab", y=0)
    joint_f = m.select("foundation", where=lambda x, y: (np.abs(y) < 1e-9) & (x > 9.99) &
                       (x < 40.01))
    upstream = m.select("slab", x=10)
    return m.add(
        sc.Support("bed", bottom, "xy"),
        sc.Support("sides", sides, "x"),
        sc.Interface("joint", plus=joint_s, minus=joint_f, friction=0.7),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("slab",))]),
        # flow drag on the upstream face, Pa per unit λ
        sc.LoadPattern("push", [sc.EdgeLoad(upstream, normal=1.0)]),
        # seepage uplift under the slab, triangular: 1 Pa upstream -> 0 downstream per unit λ
        sc.LoadPattern("uplift", [sc.EdgeLoad(joint_s, normal=(1.0, 0.0))]),
        sc.Segment("weight", 1.0),
        sc.Segment("push", 2.0e5),
        sc.Segment("uplift", 1.0e6),
    )


def run(k: int, backend: str = "auto", save: str | None = None) -> dict:
    model = slab_model(k)
    t0 = time.perf_counter()
    system = assemble(model)
    t_asm = time.perf_counter() - t0
    t0 = time.perf_counter()
    with PeakMemory() as mem_run:
        res = sc.solve_static(system, backend=backend)
        if save:
            res.save(save)
    t_total = time.perf_counter() - t0
    # reference timings: one factorisation of the same matrix with the same backend (the
    # ordering included), forming G by the run's method, and one solve
    K0, Bf, *_ = static_operator(system)
    with PeakMemory() as mem_f:
        t0 = time.perf_counter()
        last = contact_dofs(Bf)
        F = factorize(K0, backend, last=last if schur_pays(K0.shape[0], len(last), Bf.shape[0])
                      else None)
        t_f = time.perf_counter() - t0
    c = Condensation.build(K0, Bf, backend, factor=F)
    t_g = c.counters["condense_seconds"]
    b = np.random.default_rng(0).standard_normal(K0.shape[0])
    reps = 5
    t0 = time.perf_counter()
    for _ in range(reps):
        F.solve(b)
    t_s = (time.perf_counter() - t0) / reps
    E = len(res.events)
    return {
        "k": k,
        "ndof": system.ndof,
        "cfes": system.m,
        "events": E,
        "event_points": res.counters["event_points"],
        "status": res.status.value,
        "t_assembly": t_asm,
        "t_total": t_total,
        "t_setup": res.counters["setup_seconds"],
        "T_F": t_f,
        "T_G": t_g,
        "T_col": t_g / (2 * system.m),
        "G_method": "Schur block of the factors" if c.counters["condensed_columns"] == 0
        else "2m solves",
        "T_S": t_s,
        "backend": F.name,
        "M_run": mem_run.mb,
        "M_F": mem_f.mb,
        "ratio": t_total / (t_f + E * t_s),
        "ratio_G": t_total / (t_f + t_g),
        "ratio_refactor": t_total / (E * (t_f + t_s)),
        "ratio_mem": mem_run.mb / max(mem_f.mb, 1e-9),
        "max_residual": float(res.residual.max()),
        "max_violation": float(res.violation.max()),
        "message": res.message,
    }


def sweep(k: int, n: int = 20, backend: str = "auto") -> dict:
    """Time of an n-case friction sweep reusing one condensation against n independent runs."""
    model = slab_model(k)
    fs = np.linspace(0.3, 1.0, n)
    t0 = time.perf_counter()
    c = sc.condense(model, backend)
    reused = [sc.solve_static(model.with_friction(f), condensation=c, backend=backend)
              for f in fs]
    t_reuse = time.perf_counter() - t0
    t0 = time.perf_counter()
    indep = [sc.solve_static(model.with_friction(f), backend=backend) for f in fs]
    t_indep = time.perf_counter() - t0
    # the same path: the same events, λ equal to round-off (a multithreaded backend does not
    # promise bitwise-equal factors from one factorisation to the next)
    same = all([(e.cfe, e.transition) for e in a.events] == [(e.cfe, e.transition)
                                                             for e in b.events]
               and np.allclose(a.lam, b.lam, rtol=1e-9, atol=0.0)
               for a, b in zip(reused, indep, strict=True))
    return {"k": k, "n": n, "t_reuse": t_reuse, "t_indep": t_indep, "same": same,
            "ndof": reused[0].counters["ndof"],
            "events": [len(r.events) for r in reused]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1, 2, 4, 8])
    ap.add_argument("--backend", default="auto",
                    help="sparse backend: auto, scipy, cholmod, pypardiso (default: auto)")
    ap.add_argument("--save", default=None, help="write each result to SAVE-k<k>.nc")
    ap.add_argument("--sweep", type=int, default=2,
                    help="size factor of the 20-case friction sweep (0: no sweep)")
    args = ap.parse_args()
    rows = []
    for k in args.sizes:
        r = run(k, args.backend, f"{args.save}-k{k}.nc" if args.save else None)
        rows.append(r)
        print(
            f"k={r['k']}: {r['ndof']} DOFs, {r['cfes']} CFEs, {r['events']} events "
            f"({r['event_points']} event points), status {r['status']}\n"
            f"    assembly {r['t_assembly']:.2f} s, T_total {r['t_total']:.2f} s "
            f"(setup {r['t_setup']:.2f} s), T_F {r['T_F']:.3f} s, T_G {r['T_G']:.3f} s "
            f"(T_col {r['T_col']:.2e} s, {r['G_method']}), T_S {r['T_S']:.4f} s "
            f"[{r['backend']}]\n"
            f"    peak memory above assembly: run {r['M_run']:.0f} MB, factorisation "
            f"{r['M_F']:.0f} MB\n"
            f"    max residual {r['max_residual']:.1e}, max violation {r['max_violation']:.1e}\n"
            f"    {r['message']}",
            flush=True,
        )
    sw = sweep(args.sweep, backend=args.backend) if args.sweep else None
    if sw:
        print(f"friction sweep, k={sw['k']} ({sw['ndof']} DOFs), {sw['n']} cases "
              f"(events {min(sw['events'])}–{max(sw['events'])}): one condensation "
              f"{sw['t_reuse']:.2f} s, independent runs {sw['t_indep']:.2f} s, the same paths "
              f"(events, λ to 1e-9): {sw['same']}", flush=True)
    print("\nratios (last):")
    for r in rows:
        print(
            f"k={r['k']}: T_total/(T_F+E*T_S) = {r['ratio']:.2f}   "
            f"T_total/(T_F+2m*T_col) = {r['ratio_G']:.2f} (target <= 1.5)   "
            f"T_total/(E*(T_F+T_S)) [vs refactorising per event] = {r['ratio_refactor']:.4f}   "
            f"M_run/M_F = {r['ratio_mem']:.2f} (target <= 2)"
        )
    if sw:
        print(f"friction sweep k={sw['k']}: T(one condensation)/T(20 independent runs) = "
              f"{sw['t_reuse'] / sw['t_indep']:.2f}")


if __name__ == "__main__":
    main()
