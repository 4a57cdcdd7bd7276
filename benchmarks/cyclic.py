"""Benchmark: the cost of cyclic load programs of hundreds of segments (linear in their number).

The problem is ``examples/block_on_base.py`` (its ``block_model()``: a concrete block 2 m × 1 m,
10 × 5 cells, on a base 4 m × 1 m, 16 × 4 cells, E = 30 GPa, ν = 0.2, 2400 kg/m³, plane strain,
a frictional joint f = 0.5 of 11 mortar CFEs; 302 DOFs).  Program: the self-weight (λ 0 → 1,
held), then ``sc.cycles("push", P0, n)``: the horizontal push on the block's left face swings
between +P0 and −P0 = ∓20 000 N (85 % of f·W = 23 544 N), n cycles, 2n segments.  Each
half-cycle makes the joint stick at once (the push reverses) and then slip back CFE by CFE from
the heel or the toe (partial slip: the block does not slide), about 9 events per segment.

Protocol: one warm-up run (1 cycle, not timed), then per n (``--cycles``, default 10 50 200)
``--repeats`` runs (default 1; the median is printed) of ``sc.solve_static(model)`` (assembly,
condensation and the event loop; the model built beforehand).  Printed per n: segments (2n + 1,
the weight's included), events, states, the time (wall, process CPU, main-thread CPU:
``benchmarks/_timing.py``), main-thread CPU per segment and per event, the event loop's per
segment (from the solver's ``before_run`` hook on, without the fixed set-up: assembly and
factorisation), the largest residual and contact violation of the run, and the horizontal
displacement of the block's top-left corner at the last positive and negative peaks (the loop
is stable: the same after 10 and 200 cycles).  Last the ratios: per-segment time of the largest
n over the smallest (total, and event loop only; 1 means a linear total cost), and within one
more run of the largest n (timed segment by segment by an ``after_segment`` hook, so less
exposed to the machine's load varying between runs) the median time per segment over its last
10 % of segments over that of its first 10 %.  The ratios are from main-thread CPU time (the
run is single-threaded: the dense backend, BLAS held to one thread), the process CPU and wall
ratios beside them; T_OpenSees / T_stepcontact from process CPU time.

``--output``: the same runs also with ``output=`` (the result file written as the run goes,
:class:`stepcontact.results.file.ResultWriter`: at most one write per second, and writing at
most about 20 % of the run's time however long the result grows).

``--opensees``: OpenSeesPy on the same block with matching joint meshes (the model and the
OpenSees set-up of ``benchmarks/vs_opensees.py`` at r = 1: block 8 × 4, base 16 × 4 cells,
9 ``zeroLengthContactASDimplex`` elements, penalty α = 100, N and mm, Newton,
``--steps`` load steps per unit change of the push factor, default 20, i.e. 40 steps per
half-cycle), and stepcontact on the same mesh, for ``--opensees-cycles`` (default 10 50):
times, per-segment times, OpenSees's failed steps and Newton iterations, and the corner's
displacement at the last peaks by both.  Needs openseespy.

The load average (``os.getloadavg()``) is printed at the start and the end (the machine may
be shared).

Run:  python benchmarks/cyclic.py [--cycles 10 50 200] [--repeats 1] [--output] [--opensees]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import stepcontact as sc

HERE = Path(__file__).resolve().parent
for _d in (HERE, HERE.parent / "examples"):  # block_on_base.py, vs_opensees.py
    if str(_d) not in sys.path:
        sys.path.insert(0, str(_d))

from _timing import LoopStart, Times, median  # noqa: E402  (benchmarks/_timing.py)
from block_on_base import block_model  # noqa: E402

WEIGHT = 2.0 * 1.0 * 2400.0 * 9.81  # N per metre run
FRICTION = 0.5
P0 = 20_000.0  # N: the push's amplitude, 85 % of f·W
CORNER = (1.0, 2.0)  # m: the block's top-left corner


def cyclic(model: sc.Model, n: int, amplitude: float = P0) -> sc.Model:
    """``model`` with the program: its weight, then ``n`` cycles of the push (±``amplitude``)."""
    return model.replace(program=(sc.Segment("weight", 1.0),
                                  *sc.cycles("push", amplitude, n)))


def peaks(res: sc.StaticResult) -> tuple[float, float]:
    """u_x (m) of the block's top-left corner at the last +P0 and −P0 peaks (segment ends)."""
    ux = res.node_history(point=CORNER, body="block")
    ends = np.flatnonzero(res.kind == "segment_end")
    return float(ux[ends[-2]]), float(ux[ends[-1]])


def run(model: sc.Model, repeats: int = 1, output: bool = False) -> dict:
    """Solve ``model`` ``repeats`` times (with a result file written as it goes when
    ``output``); the median time and the last run's figures."""
    times, loops = [], []
    res = None
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as tmp:
            kw = {"output": Path(tmp) / "run.nc"} if output else {}
            clock = LoopStart()
            start = Times.now()
            res = sc.solve_static(model, hooks=(clock,), **kw)
            end = Times.now()
        times.append(end - start)
        loops.append(end - clock.start)
    assert res is not None
    segments = len(model.program)
    t, loop = median(times), median(loops)
    return {
        "segments": segments, "events": len(res.events), "states": res.n_states,
        "status": res.status.value, "seconds": t, "per_segment": t / segments,
        "per_event": t / max(len(res.events), 1), "loop_per_segment": loop / segments,
        "residual": float(res.residual.max()), "violation": float(res.violation.max()),
        "peaks": peaks(res), "times": times,
    }


class SegmentClock:
    """Solver hook: the time at the end of every segment (``after_segment``)."""

    def __init__(self) -> None:
        self.t: list[float] = [time.thread_time()]

    def after_segment(self, result: sc.StaticResult) -> None:
        self.t.append(time.thread_time())


def within_run(model: sc.Model, share: float = 0.1) -> tuple[float, float]:
    """Median main-thread CPU seconds per segment over the first and the last ``share`` of the
    segments of one run of ``model`` (the weight's segment left out): flat when the cost per
    segment does not grow along the run (the same run, so the machine's load matters less)."""
    clock = SegmentClock()
    sc.solve_static(model, hooks=(clock,))
    dt = np.diff(clock.t)[1:]
    k = max(1, int(share * len(dt)))
    return float(np.median(dt[:k])), float(np.median(dt[-k:]))


def report(n: int, r: dict, label: str = "") -> str:
    up, down = r["peaks"]
    return (f"{n:5d} cycles{label}: {r['segments']:4d} segments, {r['events']:5d} events, "
            f"{r['states']:5d} states, {r['status']}, {r['seconds']}; main-thread CPU "
            f"{r['per_segment'].thread * 1e3:6.2f} ms/segment "
            f"({r['loop_per_segment'].thread * 1e3:6.2f} in the event loop), "
            f"{r['per_event'].thread * 1e3:5.2f} ms/event; residual "
            f"{r['residual']:.1e}, violation {r['violation']:.1e}; corner u_x at the last peaks "
            f"{up * 1e6:+.6f} / {down * 1e6:+.6f} µm")


# ------------------------------------------------------------------------------ OpenSees side
def run_opensees_cycles(ops, mesh, setup, n: int, amplitude: float = P0) -> dict:
    """Weight (10 load steps), then ``n`` push cycles ±``amplitude`` by load control with
    ``setup.steps`` steps per unit change of the push factor; the corner's u_x at the peaks."""
    from vs_opensees import WEIGHT_STEPS, build_opensees, load_control

    start = Times.now()
    build_opensees(ops, mesh, setup)
    load_control(ops, 1.0 / WEIGHT_STEPS, setup)
    fails = iters = 0
    for _ in range(WEIGHT_STEPS):
        fails += ops.analyze(1) != 0
        iters += ops.testIter()
    ops.loadConst("-time", 0.0)
    ops.timeSeries("Linear", 2)
    ops.pattern("Plain", 2, 2)
    for i in mesh.left.tolist():
        ops.load(i + 1, amplitude / len(mesh.left), 0.0)
    corner = int(np.argmin(np.hypot(*(mesh.points[mesh.left] - CORNER).T)))
    node = int(mesh.left[corner]) + 1
    lam, ux = 0.0, []
    for k in range(2 * n):
        target = 1.0 if k % 2 == 0 else -1.0
        steps = round(abs(target - lam) * setup.steps)
        load_control(ops, (target - lam) / steps, setup)
        for _ in range(steps):
            fails += ops.analyze(1) != 0
            iters += ops.testIter()
        lam = target
        ux.append(ops.nodeDisp(node, 1) * setup.unit)
    t = Times.now() - start
    ops.wipe()
    return {"seconds": t, "segments": 2 * n + 1, "fails": fails, "iters": iters,
            "peaks": (ux[-2], ux[-1])}


def compare_opensees(args: argparse.Namespace) -> None:
    from vs_opensees import Setup, block_on_base, load_opensees, mesh_arrays, quiet_stderr

    ops, blas = load_opensees(args.blas)
    setup = Setup(steps=args.steps)
    mesh = mesh_arrays(1, args.penalty)
    print(f"\nOpenSees (BLAS {blas}): matching meshes (r = 1, {mesh.ndof} DOFs), "
          f"zeroLengthContactASDimplex, penalty α = {args.penalty:g}, N/mm, "
          f"{setup.steps} load steps per unit change of the push factor "
          f"({2 * setup.steps} per half-cycle)")
    base = block_on_base(1)
    sc.solve_static(cyclic(base, 1))  # warm-up
    rows = []
    for n in args.opensees_cycles:
        s = run(cyclic(base, n))
        with quiet_stderr():
            o = run_opensees_cycles(ops, mesh, setup, n)
        rows.append((n, s, o))
        print(report(n, s, " (stepcontact, matching meshes)"))
        up, down = o["peaks"]
        su, sd = s["peaks"]
        print(f"{n:5d} cycles (OpenSees):                  {o['segments']:4d} segments, "
              f"{o['iters']} Newton iterations, {o['fails']} failed steps, "
              f"{o['seconds']}, {o['seconds'].thread / o['segments'] * 1e3:6.2f} ms/segment "
              f"(main-thread CPU); "
              f"corner u_x at the last peaks {up * 1e6:+.6f} / {down * 1e6:+.6f} µm "
              f"({up / su - 1:+.1e} / {down / sd - 1:+.1e} from stepcontact)")
    for n, s, o in rows:
        so, ss = o["seconds"], s["seconds"]
        print(f"ratio T_OpenSees / T_stepcontact at {n} cycles: {so.process / ss.process:.2f} "
              f"from process CPU (OpenSees's BLAS may be threaded) [main-thread CPU "
              f"{so.thread / ss.thread:.2f}; wall {so.wall / ss.wall:.2f}]")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=int, nargs="+", default=[10, 50, 200],
                    help="numbers of push cycles (default 10 50 200)")
    ap.add_argument("--repeats", type=int, default=1, help="runs per size (median; default 1)")
    ap.add_argument("--output", action="store_true",
                    help="also time the runs writing their result file as they go")
    ap.add_argument("--opensees", action="store_true", help="compare with OpenSeesPy")
    ap.add_argument("--opensees-cycles", type=int, nargs="+", default=[10, 50],
                    help="numbers of cycles of the OpenSees comparison (default 10 50)")
    ap.add_argument("--steps", type=int, default=20,
                    help="OpenSees load steps per unit change of the push factor (default 20)")
    ap.add_argument("--penalty", type=float, default=100.0,
                    help="α in the OpenSees penalty K_n = K_t = α·E·t·L/h (default 100)")
    ap.add_argument("--blas", default="auto",
                    help="BLAS for OpenSees: auto, bundled or a libblas.so.3 path")
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}", flush=True)
    base = block_model()
    print(f"block on base: push cycles ±{P0:.0f} N (f·W = {FRICTION * WEIGHT:.1f} N), "
          f"{args.repeats} run(s) per size, median")
    sc.solve_static(cyclic(base, 1))  # warm-up: imports, first factorisation
    results = {}
    for n in args.cycles:
        results[n] = run(cyclic(base, n), args.repeats)
        print(report(n, results[n]), flush=True)
    written = {}
    if args.output:
        for n in args.cycles:
            written[n] = run(cyclic(base, n), args.repeats, output=True)
            print(report(n, written[n], " with output="), flush=True)
    lo, hi = min(args.cycles), max(args.cycles)
    a, b = results[lo], results[hi]
    first, last = within_run(cyclic(base, hi))
    print("ratios (last), from main-thread CPU time (the run is single-threaded: dense "
          "backend, BLAS held to one thread) [process CPU; wall]:")

    def ratio(key: str, x: dict, y: dict) -> str:  # x[key] / y[key]
        p, q = x[key], y[key]
        return (f"{p.thread / q.thread:.3f} [{p.process / q.process:.3f}; "
                f"{p.wall / q.wall:.3f}]")

    print(f"time per segment, {hi} over {lo} cycles: {ratio('per_segment', b, a)} (total), "
          f"{ratio('loop_per_segment', b, a)} (event loop); per event "
          f"{ratio('per_event', b, a)}")
    print(f"within one run of {hi} cycles: median {first * 1e3:.2f} ms/segment over its first "
          f"10 % of segments, {last * 1e3:.2f} over its last 10 %: ratio {last / first:.3f}")
    if args.output:
        a, b = written[lo], written[hi]
        print(f"time per segment with output=, {hi} over {lo} cycles: "
              f"{ratio('per_segment', b, a)}; "
              f"{hi} cycles with output= over without: "
              f"{ratio('seconds', written[hi], results[hi])}")
    if args.opensees:
        compare_opensees(args)
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
