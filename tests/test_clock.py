"""The clocks a run records in ``counters`` (issue 27 §5): wall time beside process and
main-thread CPU time, for the factorisation, G, the setup and the run."""

from __future__ import annotations

import numpy as np

import stepcontact as sc
from stepcontact.solver.clock import Stopwatch


def test_a_stopwatch_measures_cpu_work_on_all_three_clocks():
    """A loop of pure Python work on this thread: its thread CPU time is positive and at most
    the process's (which counts every thread) plus 1 ms of clock granularity."""
    t0 = Stopwatch.start()
    x = 0
    while time_spent(t0) < 0.02:
        x += 1
    c = t0.counters("work")
    assert set(c) == {"work_seconds", "work_cpu_seconds", "work_thread_seconds"}
    assert 0 < c["work_thread_seconds"] <= c["work_cpu_seconds"] + 1e-3
    assert c["work_seconds"] >= 0.02


def time_spent(t0: Stopwatch) -> float:
    return Stopwatch.start().thread - t0.thread


def test_a_run_records_wall_and_cpu_times_of_its_phases():
    """solve_static's counters hold the three clocks of the factorisation, of G, of the setup
    and of the run; each is non-negative and the setup includes the factorisation (its wall
    time is at least the factorisation's)."""
    dm = sc.DiscreteModel(K=np.array([[1e3]]), normal_rows=[[1.0]], tangent_rows=[[0.0]],
                          loads={"P": [-1.0]}, program=[sc.Segment("P", 10.0)])
    res = sc.solve_static(dm)
    c = res.counters
    for phase in ("factor", "condense", "setup", "run"):
        for clock in ("seconds", "cpu_seconds", "thread_seconds"):
            assert c[f"{phase}_{clock}"] >= 0.0, (phase, clock)
    assert c["setup_seconds"] >= c["factor_seconds"]
