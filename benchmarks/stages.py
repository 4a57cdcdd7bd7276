"""Benchmark: the cost of construction in stages (a dam raised lift by lift, then impounded).

The problem is the bonded dam of ``examples/bonded_dam.py`` (``cracked_base.dam_model``: a
30 m concrete gravity dam, base 18 m, crest 4 m, on rock, plane strain, quad4; the base bonded
through a compliant layer, c = 500 kPa, σ_t = 50 kPa, φ = 40°, uplift and crack water), cut
into ``n`` lifts of equal height (``--lifts``, default 1 2 5 10 15; 18 × 30/n cells each), the
lift joints matching and bonded (c = 1 MPa, σ_t = 0.5 MPa, φ = 45°).  Built in stages, one
lift per stage (each placed on the deformed lifts below, its joint made at once, its weight
ramped in by an automatic segment), then the reservoir filled to the design level 28 m; and
the same dam built at once (all lifts cast together, the weight in one segment).  The heel
cracks at h ≈ 27.32 m and the crack runs to x = 2 m by 28 m (a few events).

Printed per n: DOFs, CFEs, stages, segments, events, the seconds of the staged and of the
at-once run (``sc.solve_static``, assembly included; the median of ``--repeats`` runs, default
1, after one warm-up run), the staged run's seconds per stage, the level of first cracking
by both (the stresses locked in lift by lift move it by a few tenths of a metre at 10–15
lifts), the vertical displacement of the crest at the end of construction by both (built in
stages the crest's node is placed on the deformed lifts below and moves only under the loads
after that: its own lift's weight) and the largest residual and contact violation.  Last the
ratios: staged over at once per n, and the staged seconds per stage at the largest n over
those at 2 lifts (each stage refactorises the condensed system once: the cost per stage stays
flat while the contact set grows with the lift joints).

A dynamic interval between stages (``examples/data/staged_shock.toml``: a block struck
sideways between two static stages, 300 Newmark steps): the seconds of the whole run, of its
interval (setup and steps, from the interval's counters) and of the static stages with the
handover (the rest: the static run to the interval, the settle pattern's refactorisation and
the segments after it); its ratio whole / interval shows what the handover costs.

Every time is printed as wall, process CPU and main-thread CPU (``benchmarks/_timing.py``);
the ratios are from process CPU time (each stage's factorisation may use several threads), the
main-thread CPU and wall ratios beside them; the dynamic interval's share is from wall time
(the interval's counters, ``setup_seconds`` and ``run_seconds``, are the only record of its
time and are wall times).  The load average (``os.getloadavg()``) is printed at the start and
the end (the machine may be shared).

Run:  python benchmarks/stages.py [--lifts 1 2 5 10 15] [--repeats 1]
"""

from __future__ import annotations

import argparse
import os
import runpy
import sys
from pathlib import Path

import numpy as np

import stepcontact as sc
from stepcontact.enums import Transition

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:  # also when run by runpy
    sys.path.insert(0, str(HERE))
from _timing import Timer, Times, median  # noqa: E402  (benchmarks/_timing.py)

dam = runpy.run_path(str(HERE.parent / "examples" / "cracked_base.py"), run_name="cracked_base")
HEIGHT, CREST = dam["HEIGHT"], dam["CREST"]
BASE_BOND = sc.Bond.mohr_coulomb(500e3, 50e3, 40.0)
LIFT_BOND = sc.Bond.mohr_coulomb(1.0e6, 0.5e6, 45.0)
H_DESIGN = 28.0  # m


def model(n: int, staged: bool) -> sc.Model:
    """The dam in ``n`` lifts of equal height, built in stages or at once, then impounded."""
    lifts = tuple(HEIGHT * k / n for k in range(1, n))
    return dam["dam_model"](crack_water=True, bond=BASE_BOND, lift_bond=LIFT_BOND,
                            layer=sc.ContactLayer(thickness=0.5, E=2e9, nu=0.25),
                            levels=(H_DESIGN,), lifts=lifts, staged=staged)


def timed(m: sc.Model, repeats: int) -> tuple[sc.StaticResult, Times]:
    times, res = [], None
    for _ in range(repeats):
        with Timer() as t:
            res = sc.solve_static(m)
        times.append(t.times)
    return res, median(times)


def ratio(a: Times, b: Times) -> str:
    """a / b from process CPU time [main-thread CPU; wall]."""
    return f"{a.process / b.process:.2f} [{a.thread / b.thread:.2f}; {a.wall / b.wall:.2f}]"


def first_crack(res: sc.StaticResult) -> float:
    return min(e.lam for e in res.events if e.transition == Transition.BROKEN)


def crest_settlement(res: sc.StaticResult, n: int) -> float:
    """u_y (m) of the crest's upstream corner at the end of construction (the state before
    the reservoir's first segment)."""
    first = next(k for k, (name, _, _) in enumerate(res.segments) if name == "reservoir")
    i = int(np.flatnonzero(res.segment == first)[0])
    top = "dam" if n == 1 else f"lift {n}"
    return float(res.node_history(point=(0.0, HEIGHT), body=top, quantity="uy")[i])


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--lifts", type=int, nargs="+", default=[1, 2, 5, 10, 15])
    p.add_argument("--repeats", type=int, default=1)
    a = p.parse_args(argv)
    if any(n < 1 or 30 % n for n in a.lifts):
        p.error("--lifts: each n must divide the dam's 30 rows of cells (1, 2, 3, 5, 6, 10, "
                "15, 30)")
    print(f"load average at start: {os.getloadavg()[0]:.2f}")
    sc.solve_static(model(2, True))  # warm-up
    rows, per_stage = [], {}
    for n in a.lifts:
        staged, t_s = timed(model(n, True), a.repeats)
        once, t_1 = timed(model(n, False), a.repeats)
        assert staged.status == sc.Status.COMPLETED, staged.message
        assert once.status == sc.Status.COMPLETED, once.message
        stages = max(len(staged.stage_names), 1)
        per_stage[n] = t_s / stages
        rows.append((n, staged, once, t_s, t_1, stages))
        sys_ = sc.assemble(model(n, True))
        print(f"{n:3d} lifts: {sys_.ndof} DOFs, {staged.m} CFEs, {stages} stages, "
              f"{len(staged.segments)} segments, {len(staged.events)} events; staged "
              f"{t_s} ({t_s.process / stages:.3f} s process CPU per stage), at once {t_1}; first "
              f"cracking h = {first_crack(staged):.4f} m staged, {first_crack(once):.4f} m at "
              f"once; crest u_y after construction {crest_settlement(staged, n) * 1e3:.3f} mm "
              f"staged, {crest_settlement(once, n) * 1e3:.3f} mm at once; residual "
              f"{max(staged.residual.max(), once.residual.max()):.1e}, violation "
              f"{max(staged.violation.max(), once.violation.max()):.1e}", flush=True)
    shock, t_shock = timed(sc.load_model(HERE.parent / "examples" / "data" /
                                         "staged_shock.toml"), a.repeats)
    assert shock.status == sc.Status.COMPLETED, shock.message
    dres = shock.dynamics["struck"]
    t_dyn = dres.counters["setup_seconds"] + dres.counters["run_seconds"]
    print(f"dynamic interval between stages (staged_shock.toml): {len(shock.segments)} "
          f"segments, {len(shock.events)} static events, {dres.counters['steps']} steps and "
          f"{len(dres.events)} events in the interval; whole run {t_shock}; interval "
          f"{t_dyn:.2f} s wall, static stages and handover {t_shock.wall - t_dyn:.2f} s wall; "
          f"residual "
          f"{shock.residual.max():.1e}", flush=True)
    print(f"load average at end: {os.getloadavg()[0]:.2f}")
    print("ratios (last), from process CPU time [main-thread CPU; wall]:")
    print(f"  dynamic interval between stages: whole run / interval = "
          f"{t_shock.wall / t_dyn:.2f} (wall only: the interval's own times are wall)")
    for n, _, _, t_s, t_1, _ in rows:
        print(f"  {n:3d} lifts: staged / at once = {ratio(t_s, t_1)}")
    big = max(a.lifts)
    if 2 in per_stage and big > 2:
        print(f"  seconds per stage, {big} lifts / 2 lifts = "
              f"{ratio(per_stage[big], per_stage[2])}")


if __name__ == "__main__":
    main()
