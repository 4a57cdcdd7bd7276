"""Benchmark: the static event loop's CPU time per event against the two-pass floor.

The model is the slab on its foundation of ``benchmarks/slab_on_foundation.py`` at size
factors k (``--sizes``, default 4 and 8: 2m = 602 and 1 202 contact unknowns).  In one process,
per k and backend:

1. the run as a user runs it, ``solve_static(system, backend=...)`` on the assembled system,
   timed as T_total; a hook's ``before_run`` marks where the event loop starts (after the
   factorisation, G and the load solves), so the loop's time T_loop is from there to the
   result (recording included) and T_event = T_loop / events;
2. T_F, one factorisation of K₀ as the run factorises it, and T_G, G = B_f K₀⁻¹ B_fᵀ formed
   from it as the run forms it (``factor_and_condense`` of slab_on_foundation.py), which gives
   the G of the run;
3. the two-pass floor on that G (n = 2m; the scheme matrix of every working scheme is n × n,
   :class:`stepcontact.solver.schemes.SchemeSolver`, so a factor of the scheme has G's size):

   - one rank-one update of a dense n × n factor: A ← A + α u vᵀ (BLAS ``dger`` in place on a
     Fortran-ordered copy of G: one read and one write of n² numbers, the least any rank-one
     update of a dense factor costs);
   - one dense matrix–vector product G x (BLAS ``dgemv``: one read of G), the rates of all
     unknowns at once;

   T_floor = T_update + T_product, each the median over ``--batches`` batches of the mean of
   ``--reps`` calls, with BLAS held to one thread as the event loop holds it (n ≤
   ``SMALL_DENSE``).  For reference the script also times a Givens rank-one update of a QR
   factor (``scipy.linalg.qr_update``: a complete factor update; Givens rotations of Q and R,
   several passes) and prints T_event / (T_qr_update + T_product) beside the ratio.

Every time is printed as wall, process CPU and main-thread CPU (``benchmarks/_timing.py``).
The event loop and the floor run single-threaded, so their ratio is from main-thread CPU;
T_total / (T_F + T_G) involves a multithreaded factorisation (PARDISO) and is given from
process CPU (every thread: the work) and from main-thread CPU.  Last the ratios:

    T_event / T_floor          (target ≤ 2.5; passes over G per event: T_event / T_product)
    T_total / (T_F + T_G)      (target ≤ 1.5)

Run:  python benchmarks/event_floor.py [--sizes 4 8] [--backend auto scipy]
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys

import numpy as np
import scipy.linalg as sla
from scipy.linalg.blas import get_blas_funcs
from threadpoolctl import threadpool_limits

import stepcontact as sc
from stepcontact.fem.assembly import assemble
from stepcontact.solver.static import SMALL_DENSE

if os.path.dirname(os.path.abspath(__file__)) not in sys.path:  # also when run by runpy
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import LoopStart, Timer, Times, repeat  # noqa: E402  (benchmarks/_timing.py)
from slab_on_foundation import _warm_up, factor_and_condense, slab_model  # noqa: E402


def _median(fn, reps: int, batches: int) -> Times:
    """The batch with the median main-thread CPU time among ``batches`` batches of ``reps``
    calls of ``fn()`` (each the mean of its calls)."""
    runs = sorted((repeat(fn, reps) for _ in range(batches)), key=lambda t: t.thread)
    return runs[len(runs) // 2]


def floor(G: np.ndarray, reps: int = 20, batches: int = 5) -> dict[str, Times]:
    """The two-pass floor on G (n × n): one rank-one update of a dense n × n factor (``dger``
    in place) and one product G x (``dgemv``), and for reference one Givens rank-one update
    of a QR factor of G (``qr_update``); BLAS held to one thread when n ≤ SMALL_DENSE, as the
    event loop holds it."""
    n = G.shape[0]
    rng = np.random.default_rng(0)
    u, v, x = (rng.standard_normal(n) for _ in range(3))
    alpha = 1e-6 * float(np.abs(G).max())  # the values stay G's scale over the repetitions
    with (threadpool_limits(limits=1, user_api="blas") if n <= SMALL_DENSE
          else contextlib.nullcontext()):
        A = np.array(G, dtype=np.float64, order="F")  # a copy, in the order BLAS updates
        ger = get_blas_funcs("ger", (A,))
        t_update = _median(lambda: ger(alpha, u, v, a=A, overwrite_a=True), reps, batches)
        Gc = np.ascontiguousarray(G, dtype=np.float64)
        t_product = _median(lambda: Gc @ x, reps, batches)
        Q, R = sla.qr(Gc)
        Q, R, au = np.asfortranarray(Q), np.asfortranarray(R), alpha * u
        t_qr = _median(lambda: sla.qr_update(Q, R, au, v, overwrite_qruv=True,
                                            check_finite=False), max(reps // 4, 1), batches)
    return {"update": t_update, "product": t_product, "qr_update": t_qr,
            "floor": t_update + t_product}


def measure(k: int, backend: str = "auto", reps: int = 20, batches: int = 5) -> dict:
    """One k and backend: the run, T_F and T_G, and the floor on the run's G."""
    with Timer() as t_asm:
        system = assemble(slab_model(k))
    _warm_up(backend)
    clock = LoopStart()
    start = Times.now()
    res = sc.solve_static(system, backend=backend, hooks=[clock])
    end = Times.now()
    t_total, loop = end - start, end - clock.start
    events = len(res.events)
    f, c = factor_and_condense(system, backend)
    fl = floor(c.G, reps, batches)
    t_f, t_g = Times.from_dict(f["T_F"]), Times.from_dict(f["T_G"])
    return {
        "k": k, "backend": f["backend"], "ndof": system.ndof, "cfes": system.m,
        "n": c.G.shape[0], "events": events, "event_points": res.counters["event_points"],
        "status": res.status.value, "message": res.message,
        "max_residual": float(res.residual.max()),
        "t_assembly": t_asm.times, "t_total": t_total, "t_loop": loop,
        "t_setup": t_total - loop, "T_F": t_f, "T_G": t_g,
        "t_event": loop / max(events, 1), **fl,
        "scheme_counters": {key: res.counters[key] for key in
                            ("scheme_factorizations", "scheme_inversions", "scheme_commits",
                             "scheme_reinversions", "scheme_policy_inversions",
                             "scheme_updates", "scheme_columns", "scheme_solves",
                             "refinements") if key in res.counters},
    }


def report(r: dict) -> str:
    sc_ = ", ".join(f"{key} {int(v)}" for key, v in r["scheme_counters"].items())
    return (
        f"k={r['k']}: {r['ndof']} DOFs, {r['cfes']} CFEs (2m = {r['n']}), {r['events']} events "
        f"({r['event_points']} event points), status {r['status']} [{r['backend']}]\n"
        f"    assembly {r['t_assembly']}\n"
        f"    T_total {r['t_total']}\n"
        f"      setup (factorisation, G, load solves) {r['t_setup']}\n"
        f"      event loop {r['t_loop']}\n"
        f"    T_F {r['T_F'].fmt(digits=3)}\n"
        f"    T_G {r['T_G'].fmt(digits=3)}\n"
        f"    T_event {r['t_event'].fmt('ms', 3)}\n"
        f"    floor on the run's G ({r['n']} × {r['n']}, BLAS "
        f"{'one thread' if r['n'] <= SMALL_DENSE else 'all threads'}):\n"
        f"      rank-one update (dger) {r['update'].fmt('ms', 3)}\n"
        f"      product G x (dgemv)    {r['product'].fmt('ms', 3)}\n"
        f"      T_floor                {r['floor'].fmt('ms', 3)}\n"
        f"      (for reference: qr_update, a Givens rank-one update of a QR factor, "
        f"{r['qr_update'].thread * 1e3:.3f} ms main-thread CPU)\n"
        f"    scheme work: {sc_}\n"
        f"    max residual {r['max_residual']:.1e}; {r['message']}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[4, 8],
                    help="size factors k of the slab model (default 4 8)")
    ap.add_argument("--backend", nargs="+", default=["auto"],
                    help="sparse backends, each in turn: auto, scipy, cholmod, pypardiso")
    ap.add_argument("--reps", type=int, default=20, help="calls per timed batch of the floor")
    ap.add_argument("--batches", type=int, default=5, help="batches of the floor (median)")
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}", flush=True)
    rows = []
    for k in args.sizes:
        for backend in args.backend:
            rows.append(measure(k, backend, args.reps, args.batches))
            print(report(rows[-1]), flush=True)
    print("\nratios (last): T_event/T_floor from main-thread CPU (both single-threaded); "
          "passes over G per event = T_event/T_product; T_total/(T_F+T_G) from process CPU "
          "[main-thread CPU; wall]")
    for r in rows:
        te, tf, tp = r["t_event"].thread, r["floor"].thread, r["product"].thread
        tq = r["qr_update"].thread + tp
        tg = {c: getattr(r["t_total"], c) / (getattr(r["T_F"], c) + getattr(r["T_G"], c))
              for c in ("process", "thread", "wall")}
        print(f"k={r['k']} [{r['backend']}]: events {r['events']}, T_event {te * 1e3:.2f} ms, "
              f"T_floor {tf * 1e3:.2f} ms, T_event/T_floor = {te / tf:.2f} (target <= 2.5; "
              f"{te / tq:.2f} with qr_update as the update), "
              f"passes over G per event {te / tp:.1f}   "
              f"T_total/(T_F+T_G) = {tg['process']:.2f} [{tg['thread']:.2f}; {tg['wall']:.2f}] "
              f"(target <= 1.5)")
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
