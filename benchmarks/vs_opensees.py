"""Benchmark: stepcontact against OpenSeesPy on the block-on-base sliding problem.

The problem (as ``examples/block_on_base.py``): a concrete base 4 m × 1 m fixed on its bottom
edge and a concrete block 2 m × 1 m on top of it (x from 1 to 3), E = 30 GPa, ν = 0.2,
2400 kg/m³, plane strain, 1 m thick, bilinear quads; a frictional joint (f = 0.5) between the
block's bottom and the base's top.  Load path: the block's self-weight (λ 0 → 1), then a
horizontal push on the block's left face, spread equally over its nodes, growing until the block
slides.  The exact limit is H = f·W, W = 2 · 1 · 2400 · 9.81 N per metre run.

Mesh: square cells of side h = 0.25/r (base 16r × 4r cells, block 8r × 4r), so that block and
base nodes coincide on the joint (the example's block mesh, 10 × 5 cells, does not match the
base's; OpenSees needs node-to-node contact, and stepcontact then makes node-to-node CFEs too).
r = 2, 4, 8, 16 give 900, 3 332, 12 804 and 50 180 DOFs (fixed ones included).

stepcontact: model building + ``sc.solve_static(model)`` (assembly included), default backend
and options.  Its events are located exactly for the discrete rigid-contact model, so its first
slip and first opening are the reference values; the reference limit is the closed form f·W.

OpenSeesPy (3.7), as an OpenSees user would set it up:

* the same mesh: ``quad`` elements, ``nDMaterial ElasticIsotropic``, PlaneStrain; the joint by
  one ``zeroLengthContactASDimplex`` element (Coulomb friction, implicit integration, normal +y)
  between each pair of coincident base/block nodes (separate nodes);
* penalties chosen a priori, not tuned to the answer: K_n = K_t = α·E·t·L/h, the axial stiffness
  of a column of the adjacent concrete of the CFE's tributary length L and one cell height h,
  times α = 100 (``--penalty``; the usual advice is 10–100 times the adjacent element stiffness,
  the upper end being closer to the rigid contact that stepcontact solves);
* units N and mm (``--length-unit``): the element's implicit tangent is a central difference with
  a fixed perturbation of 1e-9 length units, far larger in metres than this stiff model's
  sub-nanometre contact displacements (in metres Newton stalled at 60 % of f·W at r = 1 and at
  42 % at r = 2, just after the first slip);
* self-weight as consistent nodal loads (ρ·g·h²/4 per cell corner) by load control in 10 steps,
  ``loadConst``, then the push by load control in ``--steps`` equal steps (default 100) up to
  1.05·f·W; ``algorithm Newton -intialThenCurrent`` (OpenSees's spelling; the contact's current
  tangent is singular in shear while its gap is exactly zero, so the first iteration of a step
  uses the elastic initial stiffness), ``test NormUnbalance`` 1e-6·f·W with at most
  ``--max-iter`` iterations, ``numberer RCM``, ``system Mumps`` (``--solver``; in this build
  the fastest of Mumps / UmfPack / SuperLU at 13k and 50k DOFs, all about equal at 1k; the
  joint tangent is unsymmetric, so no SPD solver);
* the run stops at the first step that fails to converge: the last converged push is OpenSees's
  sliding limit (at best one step, 1.05·f·W/steps, below f·W);
* first slip: the first converged step at which an element's slip multiplier (response
  ``slip``) is > 0; first opening: the first converged step at which an element's normal
  displacement jump (``localDisplacement``) is > 0 (gap open, no normal force).  Both are the
  pushes of those steps, i.e. the events rounded up to the step grid (or the self-weight factor
  when it happens under self-weight, as at the block's corners on fine meshes with penalties).
  These element queries are timed apart and left out of OpenSees's time (model building +
  analysis).

OpenSees's Linux wheel ships a reference BLAS that its library path misses: the system's
libblas.so.3 (e.g. Debian's OpenBLAS, ``apt-get install libopenblas0-pthread``) is preloaded
when there is one, else the bundled one (``--blas``); the one used is printed.

Protocol: per size, ``--pairs`` alternating pairs of runs (stepcontact, then OpenSees), medians
of each; every time is printed as wall, process CPU and main-thread CPU time
(``benchmarks/_timing.py``; both programs run in this process), and the ratios are from the
process's CPU time (``time.process_time``: every thread, both programs' solvers may use
several; a loaded machine's waits do not count), with the main-thread CPU and wall ratios
beside them. Printed per size: DOFs, CFEs, stepcontact
events, OpenSees converged push steps and Newton iterations (all steps: the self-weight's and
the last, failed one included), both median times, both programs' first slip / first opening /
limit (N) against the reference values with relative errors; last, the speed ratios T_OpenSees
/ T_stepcontact (target, issue 27: ≥ 40 at 13k and ≥ 100 at 50k DOFs). ``os.getloadavg()`` is
printed at the start and the end (the machine may be shared; hence the alternation and the
medians).

Run:  python benchmarks/vs_opensees.py --sizes 2 4 8 16 --pairs 3
Needs openseespy (``pip install openseespy``).
"""

from __future__ import annotations

import argparse
import contextlib
import ctypes
import ctypes.util
import importlib.util
import os
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

import numpy as np
import pandas as pd

import stepcontact as sc

if os.path.dirname(os.path.abspath(__file__)) not in sys.path:  # also when run by runpy
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _timing import Timer, Times, median  # noqa: E402  (benchmarks/_timing.py)

E, NU, RHO, G = 30e9, 0.2, 2400.0, 9.81  # Pa, -, kg/m³, m/s²
FRICTION = 0.5
THICKNESS = 1.0  # m
WEIGHT = 2.0 * 1.0 * RHO * G  # N per metre run
H_EXACT = FRICTION * WEIGHT  # sliding push, N
PUSH_MAX = 1.05 * H_EXACT  # OpenSees pushes up to this
WEIGHT_STEPS = 10
SLIPS = ("slip+", "slip-")  # stepcontact Transition values
OPENED = "opened"

Event = tuple[str, float]  # (load pattern, its load factor: N for the push)


# --------------------------------------------------------------------------- stepcontact side


def block_on_base(r: int) -> sc.Model:
    """The block-on-base model with square cells of side 0.25/r (matching joint meshes)."""
    concrete = sc.Material(E=E, nu=NU, density=RHO)
    base = sc.rectangle("base", (0, 0), (4, 1), 16 * r, 4 * r, concrete)
    block = sc.rectangle("block", (1, 1), (3, 2), 8 * r, 4 * r, concrete)
    m = sc.Model(bodies=[base, block], plane="strain", thickness=THICKNESS,
                 name=f"block-on-base-r{r}")
    left = m.select("block", x=1)
    return m.add(
        sc.Support("bed", m.select("base", y=0), "xy"),
        sc.Interface("joint", plus=m.select("block", y=1), minus=m.select("base", y=1),
                     friction=FRICTION),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
        sc.LoadPattern("push", [sc.NodalLoad(left, fx=1.0 / len(left))]),  # 1 N per unit λ
        sc.Segment("weight", 1.0),
        sc.Segment("push", 1e6),
    )


def run_stepcontact(r: int) -> dict:
    """Build and solve the size-r model (timed); its events of the push segment (not timed)."""
    with Timer() as t:
        res = sc.solve_static(block_on_base(r))
    ev = res.events_table()
    lost = res.multipliers[-1].equilibrium_lost
    return {
        "time": t.times,
        "ndof": res.counters["ndof"],
        "cfes": res.counters["cfes"],
        "events": len(ev),
        "transitions": ev["transition"].value_counts().to_dict(),
        "status": res.status.value,
        "slip": first_event(ev, ev["transition"].isin(SLIPS)),
        "open": first_event(ev, ev["transition"] == OPENED),
        "limit": None if lost is None else ("push", lost),
    }


def first_event(ev: pd.DataFrame, mask: pd.Series) -> Event | None:
    """(pattern, λ) of the first event of an events table among the rows of ``mask``."""
    rows = ev[mask]
    if not len(rows):
        return None
    first = rows.sort_values("step").iloc[0]
    return str(first["pattern"]), float(first["lam"])


# ------------------------------------------------------------------------------ OpenSees side


@dataclass(frozen=True)
class Mesh:
    """The same mesh as stepcontact's, as plain arrays (OpenSees node tags are index + 1)."""

    points: np.ndarray  # (n, 2) coordinates, m
    cells: np.ndarray  # (n_el, 4) node indices, counter-clockwise
    fixed: np.ndarray  # nodes on y = 0
    pairs: np.ndarray  # (m, 2) coincident (base, block) nodes on the joint
    k_pen: np.ndarray  # (m,) penalty stiffness of each pair, N/m
    weight: np.ndarray  # (n,) downward nodal self-weight loads, N
    left: np.ndarray  # block nodes on x = 1

    @property
    def ndof(self) -> int:
        return 2 * len(self.points)


@dataclass(frozen=True)
class Setup:
    """OpenSees analysis options."""

    steps: int = 100
    max_iter: int = 50
    solver: str = "Mumps"
    unit: float = 1e-3  # model length unit in metres (1e-3: N, mm, MPa)


def counter_clockwise(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Cells reordered counter-clockwise where their signed area is negative."""
    p = points[cells]  # (n_el, 4, 2)
    x, y = p[..., 0], p[..., 1]
    area2 = np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1)
    return np.where((area2 < 0)[:, None], cells[:, ::-1], cells)


def joint_pairs(base: sc.Body, block: sc.Body) -> tuple[np.ndarray, np.ndarray]:
    """Coincident (base, block) node indices on y = 1, by x, and their x."""
    on_base = np.flatnonzero(np.isclose(base.points[:, 1], 1.0))
    on_block = np.flatnonzero(np.isclose(block.points[:, 1], 1.0))
    on_block = on_block[np.argsort(block.points[on_block, 0])]
    xs = block.points[on_block, 0]
    partner = on_base[np.argmin(np.abs(base.points[on_base, 0][None, :] - xs[:, None]), axis=1)]
    if not np.allclose(base.points[partner, 0], xs):
        raise ValueError("joint meshes do not match node to node")
    return np.column_stack([partner, on_block]), xs


def mesh_arrays(r: int, alpha: float) -> Mesh:
    """Node/cell arrays of the size-r model for OpenSees (built once, outside the timing)."""
    model = block_on_base(r)
    base, block = (next(b for b in model.bodies if b.name == n) for n in ("base", "block"))
    nb = len(base.points)
    points = np.vstack([base.points, block.points])
    cells = counter_clockwise(points, np.vstack([base.cells[:, :4], block.cells[:, :4] + nb]))
    h = 0.25 / r
    pairs, _ = joint_pairs(base, block)
    trib = np.full(len(pairs), h)
    trib[[0, -1]] = h / 2
    weight = np.zeros(len(points))
    np.add.at(weight, block.cells[:, :4].ravel() + nb, RHO * G * h * h / 4 * THICKNESS)
    return Mesh(
        points=points,
        cells=cells,
        fixed=np.flatnonzero(np.isclose(points[:, 1], 0.0)),
        pairs=pairs + [0, nb],
        k_pen=alpha * E * THICKNESS * trib / h,
        weight=weight,
        left=np.flatnonzero(np.isclose(block.points[:, 0], 1.0)) + nb,
    )


def bundled_blas() -> Path | None:
    """The reference BLAS shipped inside openseespy's Linux wheel (not on its library path)."""
    spec = importlib.util.find_spec("openseespylinux")
    if spec is None or not spec.submodule_search_locations:
        return None
    path = Path(spec.submodule_search_locations[0]) / "lib" / "libblas.so.3"
    return path if path.exists() else None


def loaded_blas() -> str:
    """Path of the libblas mapped into this process (Linux), or "?"."""
    with contextlib.suppress(OSError):
        for line in Path("/proc/self/maps").read_text().splitlines():
            if "libblas" in line:
                return str(Path(line.split()[-1]).resolve())
    return "?"


def load_opensees(blas: str = "auto") -> tuple[ModuleType, str]:
    """Import openseespy with a BLAS its Linux build can find; returns it and the BLAS used.

    ``blas``: "auto" (the system's libblas.so.3, else the bundled one), "bundled" (openseespy's
    own reference BLAS) or the path of a libblas.so.3.
    """
    choice: str | Path | None = blas
    if blas == "auto":
        choice = "libblas.so.3" if ctypes.util.find_library("blas") else bundled_blas()
    elif blas == "bundled":
        choice = bundled_blas()
    if choice is not None:
        ctypes.CDLL(str(choice), mode=ctypes.RTLD_GLOBAL)
    try:
        import openseespy.opensees as ops
    except (ImportError, RuntimeError) as err:
        raise SystemExit(f"openseespy is needed for this benchmark: pip install openseespy "
                         f"({err})") from err
    return ops, loaded_blas()


def build_opensees(ops: ModuleType, mesh: Mesh, setup: Setup) -> list[int]:
    """Define the model and the self-weight pattern; returns the contact element tags."""
    u = setup.unit
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 2)
    for i, (x, y) in enumerate((mesh.points / u).tolist(), start=1):
        ops.node(i, x, y)
    for i in mesh.fixed.tolist():
        ops.fix(i + 1, 1, 1)
    ops.nDMaterial("ElasticIsotropic", 1, E * u**2, NU, 0.0)
    for e, c in enumerate(mesh.cells.tolist(), start=1):
        ops.element("quad", e, *(n + 1 for n in c), THICKNESS / u, "PlaneStrain", 1)
    first = len(mesh.cells) + 1
    for k, ((i, j), kp) in enumerate(zip(mesh.pairs.tolist(), (mesh.k_pen * u).tolist(),
                                         strict=True)):
        ops.element("zeroLengthContactASDimplex", first + k, i + 1, j + 1, kp, kp, FRICTION,
                    "-orient", 0.0, 1.0, 0.0)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    for i in np.flatnonzero(mesh.weight).tolist():
        ops.load(i + 1, 0.0, -float(mesh.weight[i]))
    return list(range(first, first + len(mesh.pairs)))


def analysis_base(ops: ModuleType, solver: str) -> None:
    """Clear the analysis and set what every analysis of these benchmarks shares: plain
    constraints, RCM numbering, the linear system ``solver``."""
    ops.wipeAnalysis()
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system(solver)


def load_control(ops: ModuleType, dlam: float, setup: Setup) -> None:
    """(Re)define the static load-controlled Newton analysis."""
    analysis_base(ops, setup.solver)
    ops.test("NormUnbalance", 1e-6 * H_EXACT, setup.max_iter)
    ops.algorithm("Newton", "-intialThenCurrent")  # sic: OpenSees's spelling
    ops.integrator("LoadControl", dlam)
    ops.analysis("Static")


class Watch:
    """Per-step detection of the first slip and first opening among the contact elements."""

    def __init__(self, ops: ModuleType, tags: list[int]) -> None:
        self.ops, self.tags = ops, tags
        self.slip: Event | None = None
        self.open: Event | None = None
        self.seconds = Times()

    def check(self, pattern: str, lam: float) -> None:
        """Look at the converged state at load factor ``lam`` (N for the push) of ``pattern``."""
        with Timer() as clock:
            resp = self.ops.eleResponse
            if self.slip is None and any(resp(t, "slip")[0] > 0.0 for t in self.tags):
                self.slip = (pattern, lam)
            if self.open is None and any(resp(t, "localDisplacement")[0] > 0.0
                                         for t in self.tags):
                self.open = (pattern, lam)
        self.seconds += clock.times


def run_opensees(ops: ModuleType, mesh: Mesh, setup: Setup) -> dict:
    """Weight, then the push in ``setup.steps`` load steps until a step fails to converge."""
    start = Times.now()
    watch = Watch(ops, build_opensees(ops, mesh, setup))
    iters, converged, limit = 0, 0, None
    load_control(ops, 1.0 / WEIGHT_STEPS, setup)
    weight_ok = True
    for _ in range(WEIGHT_STEPS):
        weight_ok = ops.analyze(1) == 0
        iters += ops.testIter()
        if not weight_ok:
            break
        watch.check("weight", ops.getLoadFactor(1))
    if weight_ok:
        ops.loadConst("-time", 0.0)
        ops.timeSeries("Linear", 2)
        ops.pattern("Plain", 2, 2)
        for i in mesh.left.tolist():
            ops.load(i + 1, PUSH_MAX / len(mesh.left), 0.0)
        load_control(ops, 1.0 / setup.steps, setup)
        for _ in range(setup.steps):
            ok = ops.analyze(1) == 0
            iters += ops.testIter()
            if not ok:
                break
            converged += 1
            limit = ("push", ops.getLoadFactor(2) * PUSH_MAX)
            watch.check(*limit)
    t = Times.now() - start - watch.seconds
    ops.wipe()
    return {"time": t, "steps": converged, "iters": iters, "weight_ok": weight_ok,
            "slip": watch.slip, "open": watch.open, "limit": limit,
            "query_seconds": watch.seconds}


@contextlib.contextmanager
def quiet_stderr() -> Iterator[None]:
    """Silence OpenSees's C++ messages on file descriptor 2 (convergence failures etc.)."""
    saved = os.dup(2)
    with open(os.devnull, "w") as null:
        os.dup2(null.fileno(), 2)
        try:
            yield
        finally:
            os.dup2(saved, 2)
            os.close(saved)


# ---------------------------------------------------------------------------------- protocol


def compare(r: int, pairs: int, alpha: float, setup: Setup, ops: ModuleType) -> dict:
    """``pairs`` alternating runs of both programs at size r; medians and last results."""
    mesh = mesh_arrays(r, alpha)
    sc_runs, os_runs = [], []
    for _ in range(pairs):
        sc_runs.append(run_stepcontact(r))
        with quiet_stderr():
            os_runs.append(run_opensees(ops, mesh, setup))
    return {
        "r": r,
        "sc": sc_runs[-1] | {"time": median(x["time"] for x in sc_runs)},
        "os": os_runs[-1] | {"time": median(x["time"] for x in os_runs)},
        "os_ndof": mesh.ndof,
        "sc_times": [x["time"] for x in sc_runs],
        "os_times": [x["time"] for x in os_runs],
    }


def fmt_event(event: Event | None, ref: Event | None = None) -> str:
    """A push in N, with its relative error against the reference push; or λ of the weight."""
    if event is None:
        return "none"
    pattern, lam = event
    if pattern != "push":
        return f"under self-weight (λ = {lam:.2f})"
    if ref is None or ref[0] != "push":
        return f"{lam:.1f} N"
    return f"{lam:.1f} N ({lam / ref[1] - 1:+.2e})"


def report(c: dict, wall: float) -> str:
    s, o = c["sc"], c["os"]
    times = {k: ", ".join(f"{t.process:.3f}" for t in c[k]) for k in ("sc_times", "os_times")}
    kinds = ", ".join(f"{n} {k}" for k, n in sorted(s["transitions"].items()))
    lines = [
        f"r={c['r']}: {s['ndof']} DOFs (OpenSees {c['os_ndof']}), {s['cfes']} CFEs, "
        f"{wall:.0f} s for this size",
        f"    stepcontact: {s['events']} events ({kinds}), status {s['status']}, "
        f"median {s['time'].fmt(digits=3)} (runs, process CPU: {times['sc_times']})",
        f"    OpenSees:    {o['steps']} converged push steps, {o['iters']} Newton iterations "
        f"in all (weight converged: {o['weight_ok']}), median {o['time'].fmt(digits=3)} "
        f"(runs, process CPU: {times['os_times']}; slip/opening queries "
        f"{o['query_seconds'].process:.3f} s, not counted)",
    ]
    refs = {"slip": ("first slip", s["slip"], "stepcontact"),
            "open": ("first opening", s["open"], "stepcontact"),
            "limit": ("limit push", ("push", H_EXACT), "f·W")}
    for key, (name, ref, label) in refs.items():
        lines.append(
            f"    {name:14s} reference ({label}) {fmt_event(ref)}; "
            f"stepcontact {fmt_event(s[key], ref)}; OpenSees {fmt_event(o[key], ref)}"
        )
    return "\n".join(lines)


def add_opensees_options(ap: argparse.ArgumentParser) -> None:
    """The OpenSees options the OpenSees benchmarks share: penalty, system, units, BLAS."""
    ap.add_argument("--penalty", type=float, default=100.0,
                    help="α in the OpenSees penalty K_n = K_t = α·E·t·L/h (default 100)")
    ap.add_argument("--solver", default="Mumps", help="OpenSees system (default Mumps)")
    ap.add_argument("--length-unit", choices=("m", "mm"), default="mm",
                    help="OpenSees model length unit (default mm)")
    ap.add_argument("--blas", default="auto",
                    help="BLAS for OpenSees: auto, bundled or a libblas.so.3 path")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[2, 4, 8],
                    help="mesh refinement factors r (cells of side 0.25/r; default 2 4 8)")
    ap.add_argument("--pairs", type=int, default=3,
                    help="alternating stepcontact/OpenSees run pairs per size (default 3)")
    ap.add_argument("--steps", type=int, default=100,
                    help="OpenSees load steps of the push up to 1.05·f·W (default 100)")
    ap.add_argument("--max-iter", type=int, default=50,
                    help="OpenSees Newton iterations per step (default 50)")
    add_opensees_options(ap)
    args = ap.parse_args()
    setup = Setup(steps=args.steps, max_iter=args.max_iter, solver=args.solver,
                  unit={"m": 1.0, "mm": 1e-3}[args.length_unit])
    ops, blas = load_opensees(args.blas)
    print(f"load average at start: {os.getloadavg()}", flush=True)
    print(f"f·W = {H_EXACT:.3f} N.  OpenSees: zeroLengthContactASDimplex, penalty α = "
          f"{args.penalty:g}, units N/{args.length_unit}, Newton, system {setup.solver}, "
          f"{setup.steps} push steps of {PUSH_MAX / setup.steps:.1f} N up to {PUSH_MAX:.1f} N, "
          f"BLAS {blas}", flush=True)
    rows = []
    for r in args.sizes:
        t0 = time.perf_counter()
        rows.append(compare(r, args.pairs, args.penalty, setup, ops))
        print(report(rows[-1], time.perf_counter() - t0), flush=True)
    print(f"load average at end: {os.getloadavg()}")
    print("\nspeed ratios (last): T_OpenSees / T_stepcontact from process CPU time [main-thread "
          "CPU; wall] (target >= 40 at 13k and >= 100 at 50k DOFs)")
    for c in rows:
        so, ss = c["os"]["time"], c["sc"]["time"]
        print(f"r={c['r']} ({c['sc']['ndof']} DOFs): {so.process / ss.process:.2f} "
              f"[{so.thread / ss.thread:.2f}; {so.wall / ss.wall:.2f}]")


if __name__ == "__main__":
    main()
