"""Benchmark: a stilling-basin-like slab on an elastic foundation at several mesh sizes.

Load path: self-weight; a horizontal push on the slab's upstream face (slip spreads along the
joint); then uplift pressure under the slab, triangular (largest upstream), growing until the
slab lifts off (opening spreads along the joint).  Prints, per mesh: DOFs, CFEs, events, total
time T_total, the time T_F of one factorisation of the same matrix (ordering included), the time
T_G of forming the condensed contact matrix G by the chosen method (T_col = T_G / 2m per column),
T_S of one solve with the same backend, the peak memory M_run of the run and M_F of the
factorisation alone, what the run holds besides the factorisation, and last the ratios

    T_total / (T_F + E·T_S)          (one factorisation + one solve per event)
    T_total / (T_F + 2m·T_col)       (target ≤ 1.5: the floor of forming G once)
    T_total / (E·(T_F + T_S))        (against refactorising at every event)
    M_run / M_F                      (target ≤ 2: peak memory against the factorisation's)

Times (``benchmarks/_timing.py``): each is printed as wall time, process CPU time (every
thread) and main-thread CPU time; the ratios are from process CPU time (PARDISO factorises
with several threads; the event loop holds BLAS to one), with the main-thread and the wall
ratios beside them.  The CPU time of the memory windows' sampling thread is taken off.

Memory protocol.  M_run and M_F are measured in two fresh processes (this script started
again with a hidden ``--child run|factor``), one after the other, never in the process that
measured the other: memory a run frees stays in the process's heap and a later measurement
there reuses it (it used to show a factorisation of 0 MB).  Each child assembles the system,
warms the backend up on a 50 × 50 matrix (so library code that loads on first use is not
counted), collects garbage, returns the free heap to the OS (glibc ``malloc_trim``), and then
measures the peak resident memory (RSS from /proc/self/statm, sampled every 2 ms) above the
level reached at that point:

- the run child: ``solve_static(system, backend=...)`` (and ``--save``), timed as T_total;
- the factorisation child: K₀ = K_ff + B_fᵀ D B_f is formed first (its own peak is printed as
  "forming K0"; that memory is not part of M_F) and then factorised as the run factorises it
  — the same backend, the contact DOFs ordered last when the run does so, the same node
  groups for the ordering — timed as T_F.  MKL PARDISO allocates its factors inside MKL,
  which RSS sees.  T_G and T_S are then timed in this child (outside the memory window).

As a cross-check each window also reports the kernel's high-water mark (ru_maxrss, with VmHWM
reset through /proc/self/clear_refs at the window's start; where that reset is refused the
figure is only an upper bound, marked "≤"), which no sampling interval can miss; and the
factorisation child prints the backend's own count (PARDISO: iparm 15-17; SuperLU: nnz of
the factors × 8 B of values).  What the run holds besides the factorisation is printed from
sizes, not measured: dense G (2m × 2m × 8 B), the scheme solver's matrix, LU and update
workspace (``condensation.dense_memory``), the Schur route's dense block on the c contact
DOFs and its copies (3 c² × 8 B), the sparse operators the run keeps (K₀, K_fp, B_f, B_p) and
the result's arrays; and a transient of the Schur route with SuperLU: it copies L and then U to
CSC (≈ 12 B per non-zero each).  PARDISO forms the block with a factorisation of its own,
released before the main one (so the two never hold memory together); both are inside
``factorize`` and so inside M_F.

A friction sweep (``--sweep K``, default K = 2): 20 runs of the size-K model with friction
coefficients 0.3 … 1.0, once reusing one condensation (``sc.condense`` then
``solve_static(..., condensation=c)``) and once as 20 independent runs; the ratio of the two
times is printed last.  The load average (``os.getloadavg()``) is printed at the start and the
end: the times are only as good as the machine was quiet.

Run:  python benchmarks/slab_on_foundation.py [--sizes 1 2 4 8] [--sweep 2]
The size factor k gives a foundation mesh of 125k × 19k cells and a slab of 75k × 2k
(k = 8: 326 740 DOFs, 601 CFEs, about 860 events).  ``--backend`` picks the sparse backend
(default: the fastest installed); ``--save PREFIX`` writes each result file.
"""

from __future__ import annotations

import argparse
import ctypes
import ctypes.util
import dataclasses
import gc
import json
import os
import resource
import subprocess
import sys
import threading
import time

import numpy as np
import scipy.sparse as sp

import stepcontact as sc
from stepcontact.fem.assembly import assemble
from stepcontact.solver.condensation import (
    Condensation,
    contact_dofs,
    dense_memory,
    schur_pays,
    static_operator,
)
from stepcontact.solver.linalg import factorize

if os.path.dirname(os.path.abspath(__file__)) not in sys.path:  # also when run by runpy
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import Timer, Times, repeat  # noqa: E402  (benchmarks/_timing.py)

MB = 2**20
#: prefix of the line on which a child process hands its figures back (JSON)
_MARK = "@@slab-benchmark-child@@ "


class PeakMemory:
    """Peak resident memory above the level at entry, MB, sampled every 2 ms from
    /proc/self/statm (Linux); elsewhere the process's ru_maxrss (a coarser high-water mark).

    ``maxrss_mb``: the kernel's high-water mark at exit above the level at entry, MB — exact
    for this window when the high-water mark could be reset at entry (``hwm_reset``), else an
    upper bound (it may be an earlier peak of the process).

    ``watch_cpu``: the CPU time of the sampling thread so far (to its last sample), s, to take
    off the process CPU time of the work measured inside the window."""

    def __enter__(self) -> PeakMemory:
        self.hwm_reset = self._reset_hwm()
        self.start = self.peak = self._rss()
        self.watch_cpu = 0.0
        self._stop = threading.Event()
        self._t = threading.Thread(target=self._watch, daemon=True)
        self._t.start()
        return self

    def __exit__(self, *exc) -> None:
        self._stop.set()
        self._t.join()
        self.peak = max(self.peak, self._rss())
        self.maxrss = self._maxrss()

    @property
    def mb(self) -> float:
        return (self.peak - self.start) / MB

    @property
    def maxrss_mb(self) -> float:
        return (self.maxrss - self.start) / MB

    def _watch(self) -> None:
        while not self._stop.wait(0.002):
            self.peak = max(self.peak, self._rss())
            self.watch_cpu = time.thread_time()  # this thread's CPU time since it started
        self.watch_cpu = time.thread_time()

    @staticmethod
    def _maxrss() -> int:
        r = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        return r if sys.platform == "darwin" else r * 1024  # bytes on macOS, KiB on Linux

    @classmethod
    def _rss(cls) -> int:
        try:
            with open("/proc/self/statm") as f:
                return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
        except OSError:
            return cls._maxrss()

    @staticmethod
    def _reset_hwm() -> bool:
        """Reset the kernel's high-water mark of RSS (VmHWM, which ru_maxrss reads) to the
        current RSS (Linux ≥ 4.0)."""
        try:
            with open("/proc/self/clear_refs", "w") as f:
                f.write("5")
            return True
        except OSError:
            return False


def _settle() -> None:
    """Collect garbage and give the free heap back to the OS (glibc), so that a measurement
    that follows sees every page it touches as new."""
    gc.collect()
    try:
        ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):
        pass


def _warm_up(backend: str) -> None:
    """Factorise and solve a 50 × 50 SPD matrix with the backend: loads the code that a
    backend loads on first use (MKL's kernels), which is no memory of a run."""
    A = sp.diags([-1.0, 2.5, -1.0], [-1, 0, 1], shape=(50, 50), format="csc")
    factorize(A, backend).solve(np.ones(50))


def _nbytes(obj, seen: set[int]) -> int:
    """Bytes of the NumPy and SciPy-sparse arrays in ``obj`` (a dataclass, dict, list or
    array), each buffer once (a view counts its whole base: the recorder's capacity)."""
    if isinstance(obj, np.ndarray):
        base = obj
        while isinstance(base.base, np.ndarray):
            base = base.base
        if id(base) in seen:
            return 0
        seen.add(id(base))
        return base.nbytes
    if sp.issparse(obj):
        return sum(_nbytes(getattr(obj, a), seen) for a in ("data", "indices", "indptr", "row",
                                                            "col", "offsets")
                   if isinstance(getattr(obj, a, None), np.ndarray))
    if isinstance(obj, dict):
        return sum(_nbytes(v, seen) for v in obj.values())
    if isinstance(obj, (list, tuple)):
        return sum(_nbytes(v, seen) for v in obj)
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return sum(_nbytes(getattr(obj, f.name), seen) for f in dataclasses.fields(obj)
                   if not f.name.startswith("_"))
    return 0


def _factor_bytes(F) -> tuple[float, str, float]:
    """The backend's own count of its factorisation's memory, bytes, how it was read, and the
    transient memory of reading G off the factors, bytes (0: not estimated): SuperLU builds
    L, then U, as a CSC matrix (8 B of value and 4 B of row index per non-zero, about half of
    nnz(L+U) each) to take their trailing blocks."""
    iparm = getattr(F, "iparm", None)
    if iparm is not None:  # PARDISO, KiB: peak of the analysis; permanent + numerical phase
        return (1024.0 * max(int(iparm[14]), int(iparm[15]) + int(iparm[16])),
                "PARDISO iparm 15-17", 0.0)
    lu = getattr(F, "lu", None)
    if lu is not None and hasattr(lu, "nnz"):
        return (8.0 * lu.nnz, f"SuperLU nnz(L+U) = {lu.nnz} × 8 B",
                12.0 * (lu.nnz + lu.shape[0]) / 2)
    return float("nan"), "not reported", 0.0


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


def _assembled(k: int, backend: str):
    model = slab_model(k)
    with Timer() as t:
        system = assemble(model)
    _warm_up(backend)
    _settle()
    return model, system, t.times


def _less_watch(t: Times, mem: PeakMemory) -> dict:
    """``t`` without the CPU time of the memory window's sampling thread (process CPU)."""
    return dataclasses.replace(t, process=t.process - mem.watch_cpu).as_dict()


def child_run(k: int, backend: str = "auto", save: str | None = None) -> dict:
    """In a fresh process: the run's time and its peak memory above the level after
    assembly, and the sizes of what it holds."""
    _model, system, t_asm = _assembled(k, backend)
    with Timer() as t, PeakMemory() as mem:
        res = sc.solve_static(system, backend=backend)
        if save:
            res.save(save)
    return {
        "ndof": system.ndof,
        "cfes": system.m,
        "events": len(res.events),
        "event_points": res.counters["event_points"],
        "status": res.status.value,
        "t_assembly": t_asm.as_dict(),
        "t_total": _less_watch(t.times, mem),
        "t_setup": res.counters["setup_seconds"],
        "condensed_columns": res.counters.get("condensed_columns", 0),
        "M_run": mem.mb,
        "M_run_maxrss": mem.maxrss_mb,
        "hwm_reset": mem.hwm_reset,
        "result_bytes": _nbytes(res, set()),
        "max_residual": float(res.residual.max()),
        "max_violation": float(res.violation.max()),
        "message": res.message,
    }


def child_factor(k: int, backend: str = "auto") -> dict:
    """In a fresh process: forming K₀, then one factorisation of it exactly as the run does
    it (peak memory above the level before it, time), then T_G and T_S."""
    system = _assembled(k, backend)[1]
    out, _c = factor_and_condense(system, backend)
    return out


def factor_and_condense(system, backend: str = "auto"):
    """One factorisation of K₀ of ``system`` exactly as the run factorises it (peak memory
    above the level before it; :class:`Times` T_F), G formed from it as the run forms it
    (T_G: ``Condensation.build`` with the factor given) and one solve (T_S, the mean of 5);
    the figures (times as dicts of wall, process and thread seconds) and the condensation."""
    with PeakMemory() as mem_k0:
        K0, Bf, _d, free, _presc, Kff, Kfp, Bp, _K = static_operator(system)
        del _K, Kff  # the run keeps neither K nor K_ff
    K0 = sp.csc_matrix(K0)  # what factorize_regular hands the backend (K0 is CSC already)
    last = contact_dofs(Bf)
    schur = schur_pays(K0.shape[0], len(last), Bf.shape[0])
    groups = system.dofs.node_of()[free]  # the node of each DOF: the run's ordering
    sparse_bytes = _nbytes([K0, Kfp, Bf, Bp], set())
    _settle()
    with PeakMemory() as mem_f, Timer() as t_f:
        F = factorize(K0, backend, last=last if schur else None, groups=groups)
    f_bytes, f_how, transient = _factor_bytes(F)
    with Timer() as t_g:
        c = Condensation.build(K0, Bf, backend, factor=F)
    b = np.random.default_rng(0).standard_normal(K0.shape[0])
    t_s = repeat(lambda: F.solve(b), 5)
    return {
        "backend": F.name,
        "T_F": _less_watch(t_f.times, mem_f),
        "T_G": t_g.times.as_dict(),
        "T_S": t_s.as_dict(),
        "G_method": "Schur block of the factors" if c.counters["condensed_columns"] == 0
        else "2m solves",
        "schur": schur,
        "c": len(last),
        "M_F": mem_f.mb,
        "M_F_maxrss": mem_f.maxrss_mb,
        "hwm_reset": mem_f.hwm_reset and mem_k0.hwm_reset,
        "M_K0": mem_k0.mb,
        "factor_bytes_reported": f_bytes,
        "factor_reported_how": f_how,
        "transient_bytes": transient,
        "sparse_bytes": sparse_bytes,
    }, c


def _in_child(which: str, k: int, backend: str, save: str | None = None) -> dict:
    """Run ``child_run`` or ``child_factor`` in a fresh Python process (this script with the
    hidden ``--child``) and return its figures."""
    cmd = [sys.executable, os.path.abspath(__file__), "--child", which, "--sizes", str(k),
           "--backend", backend]
    if save:
        cmd += ["--save", save]
    out = subprocess.run(cmd, stdout=subprocess.PIPE, text=True, check=False)
    lines = [ln for ln in out.stdout.splitlines() if ln.startswith(_MARK)]
    if out.returncode != 0 or not lines:
        raise RuntimeError(f"the {which} child for k={k} failed (exit {out.returncode}):\n"
                           f"{out.stdout}")
    return json.loads(lines[-1][len(_MARK):])


def run(k: int, backend: str = "auto", save: str | None = None) -> dict:
    r = _in_child("run", k, backend, save)
    f = _in_child("factor", k, backend)
    E, n2m = r["events"], 2 * r["cfes"]
    dense = dense_memory(n2m, f["c"] if f["schur"] else 0)
    t_total, t_f, t_g, t_s = (Times.from_dict(x) for x in (r["t_total"], f["T_F"], f["T_G"],
                                                          f["T_S"]))

    def ratios(clock: str) -> dict:  # the time ratios from one clock
        T, F, G, S = (getattr(x, clock) for x in (t_total, t_f, t_g, t_s))
        return {"ratio": T / (F + E * S), "ratio_G": T / (F + G),
                "ratio_refactor": T / (E * (F + S))}

    return r | f | {
        "k": k,
        "hwm_reset": r["hwm_reset"] and f["hwm_reset"],
        "t_assembly": Times.from_dict(r["t_assembly"]),
        "t_total": t_total, "T_F": t_f, "T_G": t_g, "T_S": t_s,
        "T_col": t_g / n2m,
        "ratios": {c: ratios(c) for c in ("process", "thread", "wall")},
        "ratio_mem": r["M_run"] / max(f["M_F"], 1e-9),
        "ratio_mem_maxrss": r["M_run_maxrss"] / max(f["M_F_maxrss"], 1e-9),
        "bytes_G": dense["G"],
        "bytes_schemes": dense["schemes"],
        "bytes_schur": dense["schur"],
    }


def sweep(k: int, n: int = 20, backend: str = "auto") -> dict:
    """Time of an n-case friction sweep reusing one condensation against n independent runs."""
    model = slab_model(k)
    fs = np.linspace(0.3, 1.0, n)
    with Timer() as t_reuse:
        c = sc.condense(model, backend)
        reused = [sc.solve_static(model.with_friction(f), condensation=c, backend=backend)
                  for f in fs]
    with Timer() as t_indep:
        indep = [sc.solve_static(model.with_friction(f), backend=backend) for f in fs]
    # the same path: the same events, λ equal to round-off (a multithreaded backend does not
    # promise bitwise-equal factors from one factorisation to the next)
    same = all([(e.cfe, e.transition) for e in a.events] == [(e.cfe, e.transition)
                                                             for e in b.events]
               and np.allclose(a.lam, b.lam, rtol=1e-9, atol=0.0)
               for a, b in zip(reused, indep, strict=True))
    return {"k": k, "n": n, "t_reuse": t_reuse.times, "t_indep": t_indep.times, "same": same,
            "ndof": reused[0].counters["ndof"],
            "events": [len(r.events) for r in reused]}


def _report(r: dict) -> str:
    le = "" if r["hwm_reset"] else "≤ "
    schur = (f", Schur block on c = {r['c']} contact DOFs ≈ {r['bytes_schur'] / MB:.0f} MB"
             + (f" (+ transient CSC copy of L, then of U, ≈ {r['transient_bytes'] / MB:.0f} MB)"
                if r["transient_bytes"] else "")
             if r["schur"] and r["condensed_columns"] == 0 else "")
    return (
        f"k={r['k']}: {r['ndof']} DOFs, {r['cfes']} CFEs, {r['events']} events "
        f"({r['event_points']} event points), status {r['status']}\n"
        f"    assembly {r['t_assembly']}\n"
        f"    T_total {r['t_total']} (setup {r['t_setup']:.2f} s wall) [{r['backend']}]\n"
        f"    T_F {r['T_F'].fmt(digits=3)}\n"
        f"    T_G {r['T_G'].fmt(digits=3)} ({r['G_method']}; T_col = T_G/2m "
        f"{r['T_col'].process:.2e} s process CPU)\n"
        f"    T_S {r['T_S'].fmt('ms', 2)}\n"
        f"    peak memory above assembly, each in a fresh process: run {r['M_run']:.0f} MB "
        f"(ru_maxrss {le}{r['M_run_maxrss']:.0f} MB), factorisation {r['M_F']:.0f} MB "
        f"(ru_maxrss {le}{r['M_F_maxrss']:.0f} MB; {r['factor_reported_how']}: "
        f"{r['factor_bytes_reported'] / MB:.0f} MB); forming K0 before it {r['M_K0']:.0f} MB\n"
        f"    held by the run besides the factorisation (sizes): G {r['bytes_G'] / MB:.0f} MB, "
        f"scheme matrix + LU + workspace ≈ {r['bytes_schemes'] / MB:.0f} MB{schur}, "
        f"sparse K0, Kfp, Bf, Bp {r['sparse_bytes'] / MB:.0f} MB, "
        f"result arrays {r['result_bytes'] / MB:.0f} MB\n"
        f"    max residual {r['max_residual']:.1e}, max violation {r['max_violation']:.1e}\n"
        f"    {r['message']}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1, 2, 4, 8])
    ap.add_argument("--backend", default="auto",
                    help="sparse backend: auto, scipy, cholmod, pypardiso (default: auto)")
    ap.add_argument("--save", default=None, help="write each result to SAVE-k<k>.nc")
    ap.add_argument("--sweep", type=int, default=2,
                    help="size factor of the 20-case friction sweep (0: no sweep)")
    ap.add_argument("--child", choices=("run", "factor"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:  # one measurement in this fresh process: figures back on stdout
        k = args.sizes[0]
        out = (child_run(k, args.backend, args.save) if args.child == "run"
               else child_factor(k, args.backend))
        print(_MARK + json.dumps(out, default=float), flush=True)
        return
    print(f"load average at start: {os.getloadavg()}", flush=True)
    rows = []
    for k in args.sizes:
        r = run(k, args.backend, f"{args.save}-k{k}.nc" if args.save else None)
        rows.append(r)
        print(_report(r), flush=True)
    sw = sweep(args.sweep, backend=args.backend) if args.sweep else None
    if sw:
        print(f"friction sweep, k={sw['k']} ({sw['ndof']} DOFs), {sw['n']} cases "
              f"(events {min(sw['events'])}–{max(sw['events'])}): one condensation "
              f"{sw['t_reuse']}; independent runs {sw['t_indep']}; the same paths "
              f"(events, λ to 1e-9): {sw['same']}", flush=True)
    print("\nratios (last), time ratios from process CPU time (every thread: PARDISO's "
          "factorisation is multithreaded) [from main-thread CPU; from wall]:")
    for r in rows:
        p, t, w = (r["ratios"][c] for c in ("process", "thread", "wall"))
        print(
            f"k={r['k']}: T_total/(T_F+E*T_S) = {p['ratio']:.2f} [{t['ratio']:.2f}; "
            f"{w['ratio']:.2f}]   "
            f"T_total/(T_F+2m*T_col) = {p['ratio_G']:.2f} [{t['ratio_G']:.2f}; "
            f"{w['ratio_G']:.2f}] (target <= 1.5)   "
            f"T_total/(E*(T_F+T_S)) [vs refactorising per event] = {p['ratio_refactor']:.4f} "
            f"[{t['ratio_refactor']:.4f}; {w['ratio_refactor']:.4f}]   "
            f"M_run/M_F = {r['ratio_mem']:.2f} (target <= 2; from ru_maxrss "
            f"{r['ratio_mem_maxrss']:.2f}) [{r['backend']}]"
        )
    if sw:
        print(f"friction sweep k={sw['k']}: T(one condensation)/T(20 independent runs) = "
              f"{sw['t_reuse'].process / sw['t_indep'].process:.2f} (process CPU) "
              f"[{sw['t_reuse'].thread / sw['t_indep'].thread:.2f} main-thread CPU; "
              f"{sw['t_reuse'].wall / sw['t_indep'].wall:.2f} wall]")
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
