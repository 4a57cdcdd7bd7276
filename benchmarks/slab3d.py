"""Benchmark: a 3D slab on an elastic foundation block (hex8), frictional joint, run to the end.

Issue 28 §6.  The model (``slab3d_model(s)``, size factor s = ``--sizes``): a concrete slab
22 m × 22 m × 1 m (C25: E = 30 GPa, ν = 0.2, 2400 kg/m³; n × n × 2 cells, n = 11s) on a rock
block 20 m deep reaching about L/2 beyond the slab on every side (E = 5 GPa, ν = 0.25;
(n + 2⌈n/2⌉)² × 3s cells), the slab centred on the block's top.  The meshes match on the
joint (cells of 2/s m in plan on both sides), so the joint has
(11s + 1)² node-to-node CFEs (``--cfe``: any ``Interface.cfe``), f = 0.7 on the faceted cone
with ``--facets`` k = 8 facets.  The block is fixed at its bottom and held normally on its four
sides.  Load path:

1. the slab's self-weight (λ 0 → 1);
2. a horizontal push on the slab's upstream face x = 0: a pressure of λ Pa up to 1e5 Pa
   (2.2 MN, 0.19 of the weight): the joint's shear grows, the edges begin to slip;
3. uplift under the slab: a pressure λ (1 − x/L)(1 − y/2L) Pa on its bottom face (largest at
   the corner x = y = 0, an eccentric uplift that makes a moment about both axes), growing to
   ``--uplift`` (default 40 kPa at the corner, 1.7 times the slab's weight per area): the
   joint opens from that corner over about half its points while the rest slips and turns
   on the cone's facets (s = 2: 352 openings, 486 slips, 1 218 facet turns).  ``--uplift
   1e6`` runs on to the slab's mechanism: at s = 1 equilibrium is lost at 42.65 kPa (sliding
   with a rotation about z; tests/test_mechanism_paths.py).

Sizes: s = 1: 8 208 DOFs, 144 CFEs; s = 2: 47 286 DOFs, 529 CFEs; s = 3: 149 124 DOFs,
1 156 CFEs; s = 4: 327 144 DOFs and 2 025 CFEs (the issue's ≥ 2 000 contact points and
≥ 300 000 DOFs).

Printed per size: DOFs, CFEs, contact unknowns n = 3m, events (and event points), the status,
T_total (``solve_static`` on the assembled system), from the run's own counters
(``res.counters``, :mod:`stepcontact.solver.clock`) T_F (``factor_*``), T_G (``condense_*``),
the setup (factorisation, G, load solves: ``setup_*``) and the event loop (``run_*``), each as
wall, process CPU (every thread: PARDISO's and BLAS's pools) and main-thread CPU time; the
precision of the dense contact matrices the run chose (``precision_bits``), the peak memory of
the run and of the factorisation alone, events per second, and last the ratios

    T_total / (T_F + T_G)      (from process CPU; main-thread CPU and wall beside it)
    M_run / M_F                (peak memory of the run over the factorisation's)

Memory protocol (as ``benchmarks/slab_on_foundation.py``, whose sampler is reused): the run
and the factorisation alone are each measured in a fresh process (this script started again
with a hidden ``--child run|factor``): each assembles the system, warms the backend up, returns
the free heap to the OS and then measures the peak resident memory above that level (RSS
sampled every 2 ms, and the kernel's high-water mark ``ru_maxrss`` with VmHWM reset at the
window's start).  The factorisation child factorises K₀ exactly as the run does (the same
backend, the contact DOFs ordered last when the run does so) and forms G from it; its T_F and
T_G are printed beside the run's as a cross-check.

Precision: ``precision="auto"`` keeps the dense contact matrices (G and the scheme LUs with
their workspace, 3.25 n² items) in float64 while they fit in half the physical memory, float32
beyond (:func:`stepcontact.solver.condensation.dense_precision`, the same rule as in 2D with
n = 3m in 3D).  The script prints the largest m that stays in float64 and in float32 on this
machine, and (``--float32-check``, at the smallest size) shows the switch in 3D: the
condensation built with a memory limit just below the float64 need holds G in float32, and a
run in float32 gives the same events as the float64 run (λ compared, largest relative
difference printed).

Measured (docs/performance.md, "3D"): s = 4 (327 144 DOFs, 2 025 CFEs) completes: 8 697 events
at 6 679 event points. With the residual check's G t by symv: T_total 817 s wall (1 577 s
process CPU on both cores; setup 71 s, event loop 740 s) plus 11 s of assembly, 13.8 min in all
on the 2-core machine (the issue asks for under 15); without it, two runs took 907 and 912 s
(the machine varies by about 10 % between runs). T_total/(T_F + T_G) = 11.9 in all three,
M_run/M_F = 1.53 (9.2 GB against 6.0 GB), 5.5 events per second. The same loop before the rate
problem's core (``solver/rate.py`` ``_core_outcome``) had reached event point 3 035 after 1 714
s wall (0.56 s per point against 0.12 s); the first s = 4 attempt of this issue stopped at point
862 after 53 min (assembly and setup included). s = 2: T_total/(T_F + T_G) 22.7 at first, 9.5
after the responses were read from the update's products; the loop's CPU 44.6 → 27.9 → 18.3 s
with the core (the same 2 076 events each time). The assembly (outside T_total) takes 0.22, 1.0
and 8.8 s of process CPU at s = 1, 2 and 4 with the tet4/hex8 kernels (4.9, 25 and 362 s with
scikit-fem's generic form before). G is read off PARDISO's Schur complement on the 12 150
contact DOFs at s = 4 (G = Wᵀ W, W = L⁻¹ B_cᵀ with S = L Lᵀ).

``--setup-only``: the setup alone, each size in a fresh process, split into the model, the
assembly's steps (stiffness, loads, contact search, contact operator, restraint check), T_F,
T_G and the rest of the solver's setup, with the peak resident memory after each part.

Run:  python benchmarks/slab3d.py [--sizes 1 2] [--float32-check]
      python benchmarks/slab3d.py --sizes 4          # the ≥ 2 000-point, ≥ 300 000-DOF run
      python benchmarks/slab3d.py --sizes 2 4 --setup-only
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

import numpy as np

import stepcontact as sc
from stepcontact.fem.assembly import assemble
from stepcontact.model import size as _size
from stepcontact.solver.condensation import (
    DENSE_MEMORY_SHARE,
    Condensation,
    dense_memory,
    dense_precision,
    static_operator,
)

if os.path.dirname(os.path.abspath(__file__)) not in sys.path:  # also when run by runpy
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import Timer, Times  # noqa: E402  (benchmarks/_timing.py)
from slab_on_foundation import (  # noqa: E402  (its memory sampler and factorisation child)
    MB,
    PeakMemory,
    _less_watch,
    _nbytes,
    _settle,
    _warm_up,
    factor_and_condense,
)

#: prefix of the line on which a child process hands its figures back (JSON)
_MARK = "@@slab3d-child@@ "
L = 22.0  # slab side, m
H_FOUNDATION = 20.0  # foundation depth, m
FRICTION = 0.7
PUSH = 1.0e5  # the push segment's end, Pa on the upstream face
UPLIFT = 4.0e4  # the uplift segment's end, Pa at the corner (0, 0)


def slab3d_model(s: int, cfe: str = "auto", facets: int = 8,
                 uplift: float = UPLIFT) -> sc.Model:
    """The slab on its foundation block at size factor ``s`` (see the module docstring);
    ``uplift``: the uplift segment's end, Pa at the corner."""
    concrete = sc.Material(E=30e9, nu=0.2, density=2400)
    rock = sc.Material(E=5e9, nu=0.25, density=2200)
    n = 11 * s  # cells along each side of the joint
    e = -(-n // 2)  # the foundation's margin around the slab, cells: its nodes meet the slab's
    a = e * L / n
    slab = sc.box("slab", (0, 0, 0), (L, L, 1.0), (n, n, 2), concrete)
    found = sc.box("foundation", (-a, -a, -H_FOUNDATION), (L + a, L + a, 0.0),
                   (n + 2 * e, n + 2 * e, 3 * s), rock)
    m = sc.Model(bodies=[found, slab], name=f"slab3d-s{s}")
    eps = 1e-6 * L
    under = m.select("foundation", lambda x, y, z: (np.abs(z) < eps) & (x > -eps)
                     & (x < L + eps) & (y > -eps) & (y < L + eps))
    sides_x = m.select("foundation", lambda x, y, z: (np.abs(x + a) < eps)
                       | (np.abs(x - L - a) < eps))
    sides_y = m.select("foundation", lambda x, y, z: (np.abs(y + a) < eps)
                       | (np.abs(y - L - a) < eps))
    bottom = m.select("slab", boundary="bottom")
    return m.add(
        sc.Support("bed", m.select("foundation", boundary="bottom"), "xyz"),
        sc.Support("sides-x", sides_x, "x"),
        sc.Support("sides-y", sides_y, "y"),
        sc.Interface("joint", bottom, under, friction=FRICTION, facets=facets, cfe=cfe),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("slab",))]),
        sc.LoadPattern("push", [sc.EdgeLoad(m.select("slab", boundary="left"), normal=1.0)]),
        # eccentric uplift, 1 Pa at the corner (0, 0) per unit λ
        sc.LoadPattern("uplift", [sc.EdgeLoad(bottom, normal=lambda x, y, z:
                                              (1 - x / L) * (1 - 0.5 * y / L))]),
        sc.Segment("weight", 1.0),
        sc.Segment("push", PUSH),
        sc.Segment("uplift", uplift),
    )


def _assembled(s: int, backend: str, cfe: str, facets: int, uplift: float = UPLIFT):
    with Timer() as t:
        system = assemble(slab3d_model(s, cfe, facets, uplift))
    _warm_up(backend)
    _settle()
    return system, t.times


def _phase(counters: dict, name: str) -> dict:
    """A phase's :class:`Times` (as a dict) from the run's counters (``{name}_seconds``,
    ``_cpu_seconds``, ``_thread_seconds``)."""
    return Times(counters[f"{name}_seconds"], counters[f"{name}_cpu_seconds"],
                 counters[f"{name}_thread_seconds"]).as_dict()


class Progress:
    """Solver hook: a line on stderr every ``every`` s of process CPU time in the event loop
    (event points, events, λ, open and slipping CPU counts, CPU and wall time since the loop
    started), so that a long run shows where its time goes before it ends."""

    def __init__(self, every: float = 30.0, mem: PeakMemory | None = None) -> None:
        self.every = every
        self.start: Times | None = None
        self.next = every
        self.mem = mem
        #: the memory sampler's CPU time when the loop started, s
        self.watch_at_start = 0.0

    def before_run(self, segments) -> None:
        self.start = Times.now()
        if self.mem is not None:
            self.watch_at_start = self.mem.watch_cpu
        print(f"[progress] setup done, event loop starts ({len(segments)} segments)",
              file=sys.stderr, flush=True)

    def after_event(self, info) -> None:
        t = Times.now() - self.start
        if t.process >= self.next:
            self.next = t.process + self.every
            print(f"[progress] loop {t}: event point {info.step}, {info.n_events} events, "
                  f"segment {info.segment} ({info.pattern}) λ = {info.lam:.6g}, "
                  f"{info.n_open} open, {info.n_slip} slipping; "
                  f"{1e3 * t.process / max(info.step, 1):.1f} ms process CPU per event point",
                  file=sys.stderr, flush=True)


def child_run(s: int, backend: str, cfe: str, facets: int, uplift: float = UPLIFT) -> dict:
    """In a fresh process: the run's times (its own counters) and its peak memory above the
    level after assembly."""
    system, t_asm = _assembled(s, backend, cfe, facets, uplift)
    print(f"[progress] s={s}: assembled {system.ndof} DOFs, {system.m} CFEs in {t_asm}",
          file=sys.stderr, flush=True)
    with Timer() as t, PeakMemory() as mem:
        progress = Progress(mem=mem)
        res = sc.solve_static(system, backend=backend, hooks=[progress])
    c = dict(res.counters)
    # the memory sampler's thread is part of the process CPU time: off the setup and the loop
    c["setup_cpu_seconds"] -= progress.watch_at_start
    c["run_cpu_seconds"] -= mem.watch_cpu - progress.watch_at_start
    transitions: dict[str, int] = {}
    for e in res.events:
        transitions[str(e.transition)] = transitions.get(str(e.transition), 0) + 1
    return {
        "ndof": system.ndof, "cfes": system.m, "n": int(dense_n(system)),
        "events": len(res.events), "event_points": c["event_points"],
        "transitions": transitions,
        "status": res.status.value, "message": res.message,
        "lam_end": float(res.lam[-1]),
        "t_assembly": t_asm.as_dict(), "t_total": _less_watch(t.times, mem),
        **{f"T_{p}": _phase(c, p) for p in ("factor", "condense", "setup", "run")},
        "condensed_columns": c.get("condensed_columns", 0),
        "precision_bits": c["precision_bits"],
        "M_run": mem.mb, "M_run_maxrss": mem.maxrss_mb, "hwm_reset": mem.hwm_reset,
        "result_bytes": _nbytes(res, set()),
        "max_residual": float(res.residual.max()),
        "max_violation": float(res.violation.max()),
    }


def dense_n(system) -> int:
    """The number n of contact unknowns (3m in 3D: N, Q₁, Q₂ per CFE): G is n × n."""
    return static_operator(system)[1].shape[0]


def child_factor(s: int, backend: str, cfe: str, facets: int, uplift: float = UPLIFT) -> dict:
    """In a fresh process: one factorisation of K₀ as the run does it (peak memory above the
    level before it, T_F) and G formed from it (T_G)."""
    system = _assembled(s, backend, cfe, facets, uplift)[0]
    out, _c = factor_and_condense(system, backend)
    return out


#: the assembly's steps timed by ``--setup-only`` (functions of stepcontact.fem.assembly)
_ASSEMBLY_STEPS = ("stiffness", "load_vectors", "build_contact", "contact_operator",
                   "_check_restrained")


def child_setup(s: int, backend: str, cfe: str, facets: int, uplift: float = UPLIFT) -> dict:
    """In a fresh process: the setup alone, up to the event loop, split into the model (meshes
    and node sets), the assembly by step (:data:`_ASSEMBLY_STEPS`; the rest as ``other``) and
    the solver's setup (``StaticSolver``: the factorisation with the regularity check T_F,
    G T_G, the load solves and the rest), each as wall, process and main-thread CPU time; the
    process's peak resident memory (ru_maxrss) after each part.  No event is run."""
    import resource

    from stepcontact.fem import assembly as asm_mod
    from stepcontact.solver.static import StaticSolver

    def maxrss() -> float:
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # kB -> MB

    steps = {name: Times(0.0, 0.0, 0.0) for name in _ASSEMBLY_STEPS}

    def timed_step(name, fn):
        def wrapper(*a, **k):
            with Timer() as t:
                out = fn(*a, **k)
            steps[name] = steps[name] + t.times
            return out
        return wrapper

    for name in _ASSEMBLY_STEPS:
        setattr(asm_mod, name, timed_step(name, getattr(asm_mod, name)))
    _warm_up(backend)
    with Timer() as t_model:
        model = slab3d_model(s, cfe, facets, uplift)
    rss_model = maxrss()
    with Timer() as t_asm:
        system = assemble(model)
    rss_asm = maxrss()
    with Timer() as t_solver:
        drv = StaticSolver(system, backend=backend)
    c = drv.cond.counters
    t_f = Times(c["factor_seconds"], c["factor_cpu_seconds"], c["factor_thread_seconds"])
    t_g = Times(c["condense_seconds"], c["condense_cpu_seconds"], c["condense_thread_seconds"])
    split = {k: v.as_dict() for k, v in steps.items()}
    split["other"] = (t_asm.times - sum(steps.values(), Times(0.0, 0.0, 0.0))).as_dict()
    return {
        "ndof": system.ndof, "cfes": system.m, "n": int(drv.cond.G.shape[0]),
        "precision_bits": 8 * drv.cond.G.dtype.itemsize,
        "t_model": t_model.times.as_dict(), "t_assembly": t_asm.times.as_dict(),
        "assembly_split": split, "t_solver_setup": t_solver.times.as_dict(),
        "T_F": t_f.as_dict(), "T_G": t_g.as_dict(),
        "t_solver_rest": (t_solver.times - t_f - t_g).as_dict(),
        "rss_model": rss_model, "rss_assembly": rss_asm, "rss_setup": maxrss(),
    }


def _setup_report(r: dict) -> str:
    T = {k: Times.from_dict(r[k]) for k in ("t_model", "t_assembly", "t_solver_setup", "T_F",
                                            "T_G", "t_solver_rest")}
    total = T["t_model"] + T["t_assembly"] + T["t_solver_setup"]
    steps = "\n".join(f"        {k:18s} {Times.from_dict(v)}"
                      for k, v in r["assembly_split"].items())
    return (
        f"s={r['s']}: setup only, {r['ndof']} DOFs, {r['cfes']} CFEs (n = {r['n']}, "
        f"float{r['precision_bits']})\n"
        f"    model (meshes, node sets) {T['t_model']}   [peak RSS {r['rss_model']:.0f} MB]\n"
        f"    assembly {T['t_assembly']}   [peak RSS {r['rss_assembly']:.0f} MB]\n{steps}\n"
        f"    solver setup {T['t_solver_setup']}   [peak RSS {r['rss_setup']:.0f} MB]\n"
        f"        T_F (factorisation, regularity check) {T['T_F'].fmt(digits=3)}\n"
        f"        T_G {T['T_G'].fmt(digits=3)}\n"
        f"        the rest (load solves, reactions, laws) {T['t_solver_rest']}\n"
        f"    setup total {total}"
    )


def _in_child(which: str, s: int, args) -> dict:
    cmd = [sys.executable, os.path.abspath(__file__), "--child", which, "--sizes", str(s),
           "--backend", args.backend, "--cfe", args.cfe, "--facets", str(args.facets),
           "--uplift", repr(args.uplift)]
    out = subprocess.run(cmd, stdout=subprocess.PIPE, text=True, check=False)
    lines = [ln for ln in out.stdout.splitlines() if ln.startswith(_MARK)]
    if out.returncode != 0 or not lines:
        raise RuntimeError(f"the {which} child for s={s} failed (exit {out.returncode}):\n"
                           f"{out.stdout}")
    return json.loads(lines[-1][len(_MARK):])


def precision_thresholds() -> dict:
    """The largest m (3D: n = 3m contact unknowns) whose dense work (G and the scheme LUs
    with workspace, :func:`dense_memory`) fits in float64 and in float32 under the limit of
    ``precision="auto"`` on this machine (DENSE_MEMORY_SHARE of the physical memory)."""
    phys = _size.physical_memory()
    limit = DENSE_MEMORY_SHARE * phys
    out = {"physical_GB": phys / 2**30, "limit_GB": limit / 2**30}
    for name, item in (("float64", 8), ("float32", 4)):
        per = sum(dense_memory(1, itemsize=item)[k] for k in ("G", "schemes"))  # bytes / n²
        n = int(np.sqrt(limit / per))
        while n > 0 and dense_precision(3 * (n // 3), "auto", limit).itemsize > item:
            n -= 3
        out[name] = n // 3
    # the rule applied to 3D sizes, checked through the library's own function
    m64 = out["float64"]
    out["auto_at_m64"] = str(dense_precision(3 * m64, "auto"))
    out["auto_at_m64+1"] = str(dense_precision(3 * (m64 + 1), "auto"))
    return out


def float32_check(s: int, backend: str, cfe: str, facets: int,
                  uplift: float = UPLIFT) -> dict:
    """At size ``s``: the condensation built with a memory limit just below the float64 need
    of its 3m unknowns chooses float32 (``precision="auto"``), and a float32 run gives the
    float64 run's events (the same CFEs and transitions; λ's largest relative difference)."""
    system = assemble(slab3d_model(s, cfe, facets, uplift))
    K0, Bf = static_operator(system)[:2]
    n = Bf.shape[0]
    need64 = sum(dense_memory(n)[k] for k in ("G", "schemes"))
    c_lim = Condensation.build(K0, Bf, backend, memory_limit=need64 - 1)
    c_fit = Condensation.build(K0, Bf, backend, memory_limit=need64)
    r64 = sc.solve_static(system, backend=backend, precision="float64")
    r32 = sc.solve_static(system, backend=backend, precision="float32")
    same = ([(e.cfe, str(e.transition)) for e in r64.events]
            == [(e.cfe, str(e.transition)) for e in r32.events])
    lam64, lam32 = np.asarray(r64.lam), np.asarray(r32.lam)
    dl = (float(np.max(np.abs(lam32 - lam64) / np.maximum(np.abs(lam64), 1.0)))
          if lam64.shape == lam32.shape else float("nan"))
    return {"s": s, "n": n, "need64_MB": need64 / MB,
            "dtype_below": str(c_lim.G.dtype), "dtype_at": str(c_fit.G.dtype),
            "bits64": r64.counters["precision_bits"], "bits32": r32.counters["precision_bits"],
            "events64": len(r64.events), "events32": len(r32.events), "same_events": same,
            "max_dlam": dl, "status32": r32.status.value}


def run(s: int, args) -> dict:
    r = _in_child("run", s, args)
    f = _in_child("factor", s, args)
    t_total = Times.from_dict(r["t_total"])
    t_f, t_g = Times.from_dict(r["T_factor"]), Times.from_dict(r["T_condense"])
    ratios = {c: getattr(t_total, c) / (getattr(t_f, c) + getattr(t_g, c))
              for c in ("process", "thread", "wall")}
    dense = dense_memory(r["n"], f["c"] if f["schur"] else 0, r["precision_bits"] // 8)
    return r | {"factor_child": f} | {
        "s": s, "ratios": ratios, "ratio_mem": r["M_run"] / max(f["M_F"], 1e-9),
        "ratio_mem_maxrss": r["M_run_maxrss"] / max(f["M_F_maxrss"], 1e-9),
        "events_per_s": r["events"] / max(t_total.process, 1e-12),
        "events_per_s_loop": r["events"] / max(r["T_run"]["process"], 1e-12),
        "bytes_G": dense["G"], "bytes_schemes": dense["schemes"], "bytes_schur": dense["schur"],
    }


def _report(r: dict) -> str:
    f = r["factor_child"]
    T = {k: Times.from_dict(r[k]) for k in ("t_assembly", "t_total", "T_factor", "T_condense",
                                            "T_setup", "T_run")}
    le = "" if r["hwm_reset"] and f["hwm_reset"] else "≤ "
    tr = ", ".join(f"{k} {v}" for k, v in sorted(r["transitions"].items()))
    schur = (f", Schur block on c = {f['c']} contact DOFs ≈ {r['bytes_schur'] / MB:.0f} MB"
             if f["schur"] and r["condensed_columns"] == 0 else "")
    return (
        f"s={r['s']}: {r['ndof']} DOFs, {r['cfes']} CFEs (n = 3m = {r['n']} contact unknowns), "
        f"{r['events']} events ({r['event_points']} event points; {tr}), status {r['status']} "
        f"at λ = {r['lam_end']:.6g} [{f['backend']}]\n"
        f"    assembly {T['t_assembly']}\n"
        f"    T_total {T['t_total']}\n"
        f"      setup (factorisation, G, load solves) {T['T_setup']}\n"
        f"        T_F {T['T_factor'].fmt(digits=3)}\n"
        f"        T_G {T['T_condense'].fmt(digits=3)} ({f['G_method']})\n"
        f"      event loop {T['T_run']}\n"
        f"    factorisation alone (fresh process): T_F {Times.from_dict(f['T_F']).fmt(digits=3)};"
        f" T_G {Times.from_dict(f['T_G']).fmt(digits=3)}\n"
        f"    precision of the dense contact matrices: float{r['precision_bits']} "
        f"(G {r['bytes_G'] / MB:.0f} MB, scheme LU + workspace ≈ "
        f"{r['bytes_schemes'] / MB:.0f} MB{schur})\n"
        f"    peak memory above assembly, each in a fresh process: run {r['M_run']:.0f} MB "
        f"(ru_maxrss {le}{r['M_run_maxrss']:.0f} MB), factorisation alone {f['M_F']:.0f} MB "
        f"(ru_maxrss {le}{f['M_F_maxrss']:.0f} MB; {f['factor_reported_how']}: "
        f"{f['factor_bytes_reported'] / MB:.0f} MB); result arrays "
        f"{r['result_bytes'] / MB:.0f} MB\n"
        f"    events per second (process CPU): {r['events_per_s']:.1f} over T_total, "
        f"{r['events_per_s_loop']:.1f} in the event loop\n"
        f"    max residual {r['max_residual']:.1e}, max violation {r['max_violation']:.1e}\n"
        f"    {r['message']}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1, 2],
                    help="size factors s (s = 4: 2 025 CFEs, 327 063 DOFs)")
    ap.add_argument("--backend", default="auto", help="sparse backend (default: auto)")
    ap.add_argument("--cfe", default="auto", help="the interface's cfe (default: auto)")
    ap.add_argument("--facets", type=int, default=8, help="facets of the cone (default 8)")
    ap.add_argument("--uplift", type=float, default=UPLIFT,
                    help=f"the uplift segment's end, Pa at the corner (default {UPLIFT:g}; "
                         f"1e6: on to the slab's mechanism)")
    ap.add_argument("--float32-check", action="store_true",
                    help="show the automatic float32 switch in 3D at the smallest size")
    ap.add_argument("--setup-only", action="store_true",
                    help="only the setup, split (model, assembly steps, T_F, T_G, the rest), "
                         "each size in a fresh process; no event loop")
    ap.add_argument("--child", choices=("run", "factor", "setup"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        s = args.sizes[0]
        fn = {"run": child_run, "factor": child_factor, "setup": child_setup}[args.child]
        out = fn(s, args.backend, args.cfe, args.facets, args.uplift)
        print(_MARK + json.dumps(out, default=float), flush=True)
        return
    print(f"load average at start: {os.getloadavg()}", flush=True)
    if args.setup_only:
        for s in args.sizes:
            print(_setup_report(_in_child("setup", s, args) | {"s": s}), flush=True)
        print(f"load average at end: {os.getloadavg()}")
        return
    th = precision_thresholds()
    print(f"precision='auto' on this machine ({th['physical_GB']:.1f} GB physical, dense "
          f"limit {th['limit_GB']:.1f} GB): float64 up to m = {th['float64']} CFEs "
          f"(n = 3m = {3 * th['float64']}), float32 up to m = {th['float32']} "
          f"(n = {3 * th['float32']}); dense_precision gives {th['auto_at_m64']} at "
          f"m = {th['float64']} and {th['auto_at_m64+1']} at m = {th['float64'] + 1}",
          flush=True)
    if args.float32_check:
        c = float32_check(min(args.sizes), args.backend, args.cfe, args.facets, args.uplift)
        print(f"float32 check at s={c['s']} (n = {c['n']}, float64 dense work "
              f"{c['need64_MB']:.1f} MB): memory limit 1 B below it -> G in {c['dtype_below']}"
              f", at it -> {c['dtype_at']}; runs in float{c['bits64']} / float{c['bits32']}: "
              f"{c['events64']} / {c['events32']} events, the same CFEs and transitions: "
              f"{c['same_events']}, largest relative difference of λ {c['max_dlam']:.1e} "
              f"(float32 run: {c['status32']})", flush=True)
    rows = []
    for s in args.sizes:
        r = run(s, args)
        rows.append(r)
        print(_report(r), flush=True)
    print("\nratios (last); time ratios from process CPU time (every thread) "
          "[main-thread CPU; wall]:")
    for r in rows:
        p = r["ratios"]
        print(f"s={r['s']} ({r['ndof']} DOFs, {r['cfes']} CFEs, {r['events']} events, "
              f"float{r['precision_bits']}): T_total/(T_F+T_G) = {p['process']:.2f} "
              f"[{p['thread']:.2f}; {p['wall']:.2f}]   M_run/M_F = {r['ratio_mem']:.2f} "
              f"(from ru_maxrss {r['ratio_mem_maxrss']:.2f})   events/s = "
              f"{r['events_per_s']:.1f}")
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
