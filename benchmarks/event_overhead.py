"""Benchmark: the static event loop's per-event bookkeeping, the part that does not scale with m.

On models whose dense work is negligible (2m ≤ a few hundred contact unknowns: a scheme solve
or a product with G takes microseconds) the event loop's time per event is its bookkeeping:
the event functions, the consistency check, the rate problem's set-up, the snap, the
recording of the state and the event log (Python and NumPy calls whose cost does not grow
with m).  The models, each run as a user runs it (``solve_static`` on the assembled system,
default options):

- ``slab k``: the slab on its foundation of ``benchmarks/slab_on_foundation.py`` at size
  factor k (``--sizes``, default 1 and 4: 2m = 152 and 602);
- ``block``: a block 2 m × 2 m on a base, 40 cells along the joint (f = 0.8), pushed at
  its top corner until it tips over: the joint opens from the heel event by event
  (2m = 82).

Per model, ``--reps`` runs (default 5), each timed by a hook: from the first event point to
the last (``after_event``), so that neither the set-up nor the result's building enters;
T_event = that time / (event points − 1), the median over the runs (the fastest run is
printed beside it: on a loaded machine the median moves with the load).  Every time is wall,
process CPU and main-thread CPU (``benchmarks/_timing.py``); the loop runs single-threaded
(BLAS held to one thread at these sizes), so the figure to read is main-thread CPU.  The
time spent inside the scheme solver (``solver/schemes.py``: the factors of the working
schemes, their updates and solves) is measured beside it (wrappers on its public methods,
outermost calls) and printed apart from the rest (engine, laws, rate problem, recording,
event log).

Last the ratio: T_event (main-thread CPU) against the target of 0.5 ms per event for the part
that does not scale with m (issue 27), on each model with 2m ≤ 200.

Run:  python benchmarks/event_overhead.py [--sizes 1 4] [--reps 5] [--no-block]
"""

from __future__ import annotations

import argparse
import functools
import inspect
import os
import statistics
import sys
import time

import stepcontact as sc
from stepcontact.fem.assembly import assemble
from stepcontact.solver import schemes

if os.path.dirname(os.path.abspath(__file__)) not in sys.path:  # also when run by runpy
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import Times, median  # noqa: E402  (benchmarks/_timing.py)
from slab_on_foundation import slab_model  # noqa: E402

#: the target for the per-event bookkeeping (issue 27), s
TARGET = 0.5e-3


def block_model(cells: int = 40) -> sc.Model:
    """A concrete block [0, 2] × [0, 2] m on a base, ``cells`` cells along the joint (f = 0.8),
    self-weight then a horizontal push at its top-left corner (1 N per unit λ) up to 2 W: it
    tips about its toe (H h > W w / 2 at H = W / 2, before it slides at 0.8 W)."""
    concrete = sc.Material(E=30e9, nu=0.2, density=2400)
    base = sc.rectangle("base", (-1, -1), (3, 0), 2 * cells, 4, concrete)
    block = sc.rectangle("block", (0, 0), (2, 2), cells, 8, concrete)
    m = sc.Model(bodies=[base, block], plane="strain", thickness=1.0, name="tipping-block")
    corner = m.select("block", where=lambda x, y: (abs(x) < 1e-9) & (abs(y - 2) < 1e-9))
    weight = 2 * 2 * 2400 * 9.81
    return m.add(
        sc.Support("bed", m.select("base", y=-1), "xy"),
        sc.Interface("joint", plus=m.select("block", y=0), minus=m.select("base", y=0),
                     friction=0.8),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
        sc.LoadPattern("push", [sc.NodalLoad(corner, fx=1.0)]),
        sc.Segment("weight", 1.0),
        sc.Segment("push", 2 * weight),
    )


class SchemeClock:
    """Main-thread CPU time spent inside the scheme solver (every public method of the classes
    of :mod:`stepcontact.solver.schemes`: the factors of the working schemes, their updates
    and solves, with their own bookkeeping), outermost calls only; installed for a run."""

    def __init__(self) -> None:
        self.total = 0.0
        self._depth = 0
        self._saved: list[tuple] = []

    def _wrap(self, fn):
        clock = self

        @functools.wraps(fn)
        def timed(*args, **kwargs):
            if clock._depth:
                return fn(*args, **kwargs)
            clock._depth += 1
            t0 = time.thread_time()
            try:
                return fn(*args, **kwargs)
            finally:
                clock.total += time.thread_time() - t0
                clock._depth -= 1

        return timed

    def __enter__(self) -> SchemeClock:
        for cls in vars(schemes).values():
            if isinstance(cls, type) and cls.__module__ == schemes.__name__:
                for name, fn in list(vars(cls).items()):
                    if inspect.isfunction(fn) and not name.startswith("_"):
                        self._saved.append((cls, name, fn))
                        setattr(cls, name, self._wrap(fn))
        return self

    def __exit__(self, *exc) -> None:
        for cls, name, fn in self._saved:
            setattr(cls, name, fn)
        self._saved.clear()


class EventClock:
    """Solver hook: the :class:`Times` (and the scheme solver's time so far) at the first and
    the last event point."""

    def __init__(self, schemes_clock: SchemeClock) -> None:
        self.first: Times | None = None
        self.last: Times | None = None
        self.points = 0
        self.schemes = schemes_clock
        self.in_schemes = (0.0, 0.0)

    def after_event(self, info) -> None:
        now = Times.now()
        if self.first is None:
            self.first = now
            self.in_schemes = (self.schemes.total, self.schemes.total)
        self.last = now
        self.in_schemes = (self.in_schemes[0], self.schemes.total)
        self.points += 1


def measure(name: str, model: sc.Model, reps: int) -> dict:
    """``reps`` runs of ``model``: T_event (median) and the run's figures."""
    system = assemble(model)
    sc.solve_static(system)  # warm-up (imports, caches of the first run)
    runs, in_schemes = [], []
    for _ in range(reps):
        with SchemeClock() as sch:
            clock = EventClock(sch)
            res = sc.solve_static(system, hooks=[clock])
        per = max(clock.points - 1, 1)
        runs.append((clock.last - clock.first) / per)
        in_schemes.append((clock.in_schemes[1] - clock.in_schemes[0]) / per)
    return {"name": name, "n": 2 * system.m, "events": len(res.events),
            "points": res.counters["event_points"], "status": res.status.value,
            "t_event": median(runs), "t_best": min(runs, key=lambda t: t.thread),
            "t_schemes": statistics.median(in_schemes)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1, 4],
                    help="size factors k of the slab model (default 1 4)")
    ap.add_argument("--reps", type=int, default=5, help="runs per model (median)")
    ap.add_argument("--no-block", action="store_true", help="leave the tipping block out")
    args = ap.parse_args()
    print(f"stepcontact from {os.path.dirname(sc.__file__)}")
    print(f"load average at start: {os.getloadavg()}", flush=True)
    rows = []
    models = [(f"slab k={k}", slab_model(k)) for k in args.sizes]
    if not args.no_block:
        models.append(("block", block_model()))
    for name, model in models:
        r = measure(name, model, args.reps)
        rows.append(r)
        print(f"{r['name']}: 2m = {r['n']}, {r['events']} events at {r['points']} event points, "
              f"status {r['status']}\n    T_event {r['t_event'].fmt('ms', 3)} (median of "
              f"{args.reps} runs; the fastest run {r['t_best'].thread * 1e3:.3f} ms main "
              f"thread)\n    of which in the scheme solver (solver/schemes.py) "
              f"{r['t_schemes'] * 1e3:.3f} ms, the rest (engine, laws, rate problem, "
              f"recording, event log) {(r['t_event'].thread - r['t_schemes']) * 1e3:.3f} ms "
              "main thread", flush=True)
    print("\nper-event time of the loop from main-thread CPU (target for the part that does not "
          f"scale with m: {TARGET * 1e3:.1f} ms, read on the models with 2m <= 200):")
    for r in rows:
        te = r["t_event"].thread
        rest = te - r["t_schemes"]
        note = (f", overhead per event / target = {te / TARGET:.2f} (outside the scheme "
                f"solver {rest * 1e3:.3f} ms: {rest / TARGET:.2f})" if r["n"] <= 200 else "")
        print(f"  {r['name']} (2m = {r['n']}): {te * 1e3:.3f} ms per event point{note}")
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
