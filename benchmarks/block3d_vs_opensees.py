"""Benchmark: a 3D block on a base, frictional joint, stepcontact against OpenSeesPy.

Issue 28 §6.  The problem: a concrete block 1 m × 1 m × 0.5 m on a concrete base
2 m × 2 m × 0.5 m (the block centred on it) fixed at its bottom face, E = 30 GPa, ν = 0.2,
2400 kg/m³, trilinear hexahedra (hex8) of side 0.25/r (block 4r × 4r × 2r cells, base
8r × 8r × 2r), so that block and base nodes coincide on the joint; f = 0.5.  Load path: the
block's self-weight W = ρ g V (λ 0 → 1), then a horizontal push along θ (from +x towards +y,
``--theta``, default 0.3 rad), the same force on every node of the block's top face, growing
until the block slides.  Exact limits: on the true (circular) Coulomb cone H = f·W; on the
faceted cone of k facets inscribed in it (stepcontact) H_k = f·W cos(π/k) / cos(θ − θ_f), θ_f
the facet normal nearest θ (tests/faceted_reference.slip_limit).

stepcontact: model building + ``sc.solve_static(model)`` (assembly included), node-to-node CFEs
(``cfe="node-to-node"``) with k = ``--facets`` (default 8, 16 and 64): its slip limit against
H_k (to round-off) and against f·W (the facets' bound 1 − cos(π/k)).

OpenSeesPy (3.7), set up as ``benchmarks/vs_opensees.py`` sets up the 2D problem (its BLAS
loader, penalties, units, analysis options are reused): the same mesh as ``stdBrick`` elements
with ``nDMaterial ElasticIsotropic``, one zero-length contact element between each pair of
coincident block/base nodes (separate nodes), penalties K_n = K_t = α·E·A/h (A the node's
tributary area, h the cell height, α = ``--penalty`` 100), units N/mm, self-weight by load
control in 10 steps, ``loadConst``, then the push by load control in ``--steps`` steps up to
1.05·f·W, Newton (``-intialThenCurrent``), ``NormUnbalance`` 1e-6·f·W; the last converged push
is OpenSees's sliding limit.  Two 3D frictional contact elements are tried, each in turn
(``--elements``):

* ``zeroLengthContactASDimplex`` (3D: normal +z by ``-orient``; circular Coulomb cone,
  IMPL-EX integration);
* ``zeroLengthContact3D`` (normal along global z, ``dir`` 3; circular cone, no cohesion).

For each the script prints whether the weight and the push converged, the converged steps,
Newton iterations, the limit and its error against f·W, and OpenSees's CPU time; an element
that never converges is reported as such (the benchmark says so, with what was tried).

Protocol: ``--pairs`` alternating runs (stepcontact, then each OpenSees element), medians of
each; every time printed as wall, process CPU and main-thread CPU (``benchmarks/_timing.py``);
the ratios, last, are from process CPU time.

Run:  python benchmarks/block3d_vs_opensees.py [--sizes 1 2] [--pairs 1]
Needs openseespy (``pip install openseespy``).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from dataclasses import dataclass
from types import ModuleType

import numpy as np

import stepcontact as sc

if os.path.dirname(os.path.abspath(__file__)) not in sys.path:  # also when run by runpy
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
if os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests") not in sys.path:
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
from _timing import Times, median  # noqa: E402  (benchmarks/_timing.py)
from vs_opensees import (  # noqa: E402  (the 2D benchmark's OpenSees set-up)
    add_opensees_options,
    analysis_base,
    load_opensees,
    quiet_stderr,
)

import faceted_reference as fr  # noqa: E402  (tests/faceted_reference.py: the polygon limit)

E, NU, RHO, G = 30e9, 0.2, 2400.0, 9.81  # Pa, -, kg/m³, m/s²
FRICTION = 0.5
WEIGHT = 1.0 * 1.0 * 0.5 * RHO * G  # N
H_EXACT = FRICTION * WEIGHT  # sliding push on the true cone, N
PUSH_MAX = 1.05 * H_EXACT
WEIGHT_STEPS = 10
ELEMENTS = ("zeroLengthContactASDimplex", "zeroLengthContact3D")


def bodies(r: int) -> tuple[sc.Body, sc.Body]:
    concrete = sc.Material(E=E, nu=NU, density=RHO)
    base = sc.box("base", (-0.5, -0.5, -0.5), (1.5, 1.5, 0.0), (8 * r, 8 * r, 2 * r), concrete)
    block = sc.box("block", (0, 0, 0), (1, 1, 0.5), (4 * r, 4 * r, 2 * r), concrete)
    return base, block


def block3d(r: int, theta: float, facets: int) -> sc.Model:
    base, block = bodies(r)
    m = sc.Model(bodies=[base, block], name=f"block3d-r{r}")
    top = m.select("block", boundary="top")
    n_top = len(top.index)
    return m.add(
        sc.Support("bed", m.select("base", boundary="bottom"), "xyz"),
        sc.Interface("joint", m.select("block", boundary="bottom"),
                     m.select("base", boundary="top"), friction=FRICTION, facets=facets,
                     cfe="node-to-node"),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
        # 1 N in all per unit λ along θ, the same on every top node
        sc.LoadPattern("push", [sc.NodalLoad(top, fx=math.cos(theta) / n_top,
                                             fy=math.sin(theta) / n_top)]),
        sc.Segment("weight", 1.0),
        sc.Segment("push", 10 * H_EXACT),
    )


def run_stepcontact(r: int, theta: float, facets: int) -> dict:
    start = Times.now()
    res = sc.solve_static(block3d(r, theta, facets))
    t = Times.now() - start
    slips = [e.lam for e in res.events if e.segment == 1 and "slip" in str(e.transition)]
    return {"time": t, "status": res.status.value, "limit": float(res.lam[-1]),
            "events": len(res.events), "ndof": res.counters["ndof"], "cfes": res.m,
            "first_slip": min(slips) if slips else None,
            "exact": fr.slip_limit(FRICTION * WEIGHT, facets, theta)}


# ----------------------------------------------------------------------------- OpenSees side


@dataclass(frozen=True)
class Mesh:
    points: np.ndarray  # (n, 3), m: base nodes, then block nodes
    bricks: np.ndarray  # (e, 8), OpenSees stdBrick order (bottom CCW, then top CCW)
    fixed: np.ndarray  # base bottom nodes
    pairs: np.ndarray  # (p, 2): (base node, block node) coincident on the joint
    k_pen: np.ndarray  # (p,) penalty, N/m
    weight: np.ndarray  # (n,) downward nodal force of the block's weight, N
    top: np.ndarray  # block top nodes


def _brick_order(p: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Each hexahedron's 8 nodes in OpenSees's order: the bottom 4 counter-clockwise seen from
    +z, then the top 4 above them (cells of an axis-aligned box)."""
    xyz = p[t]  # (e, 8, 3)
    c = xyz.mean(axis=1, keepdims=True)
    d = xyz - c
    ang = np.arctan2(d[..., 1], d[..., 0])
    key = (d[..., 2] > 0) * 10.0 + ang  # bottom first, each layer by angle
    return np.take_along_axis(t, np.argsort(key, axis=1), axis=1)


def mesh_arrays(r: int, alpha: float) -> Mesh:
    base, block = bodies(r)
    pb, pk = base.mesh.p.T, block.mesh.p.T
    nb = len(pb)
    points = np.vstack([pb, pk])
    bricks = np.vstack([_brick_order(pb, base.mesh.t.T),
                        _brick_order(pk, block.mesh.t.T) + nb])
    h = 0.25 / r
    bottom_k = np.flatnonzero(np.isclose(pk[:, 2], 0.0))
    top_b = np.flatnonzero(np.isclose(pb[:, 2], 0.0))
    key = {tuple(np.round(pb[i, :2] / h).astype(int)): i for i in top_b}
    pairs = np.array([(key[tuple(np.round(pk[j, :2] / h).astype(int))], j + nb)
                      for j in bottom_k])
    # tributary area of each joint node: h² × (1/2 per edge of the block's footprint)
    xy = pk[bottom_k, :2]
    fx = np.where(np.isclose(xy[:, 0], 0) | np.isclose(xy[:, 0], 1), 0.5, 1.0)
    fy = np.where(np.isclose(xy[:, 1], 0) | np.isclose(xy[:, 1], 1), 0.5, 1.0)
    k_pen = alpha * E * h * h * fx * fy / h
    weight = np.zeros(len(points))
    np.add.at(weight, (block.mesh.t.T + nb).ravel(), RHO * G * h**3 / 8)
    return Mesh(points, bricks, np.flatnonzero(np.isclose(pb[:, 2], -0.5)), pairs, k_pen,
                weight, np.flatnonzero(np.isclose(pk[:, 2], 0.5)) + nb)


@dataclass(frozen=True)
class Setup:
    steps: int
    max_iter: int
    solver: str
    unit: float  # model length unit in m
    element: str


def build_opensees(ops: ModuleType, mesh: Mesh, s: Setup) -> list[int]:
    u = s.unit
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 3)
    for i, (x, y, z) in enumerate((mesh.points / u).tolist(), start=1):
        ops.node(i, x, y, z)
    for i in mesh.fixed.tolist():
        ops.fix(i + 1, 1, 1, 1)
    ops.nDMaterial("ElasticIsotropic", 1, E * u**2, NU, 0.0)
    for e, c in enumerate(mesh.bricks.tolist(), start=1):
        ops.element("stdBrick", e, *(n + 1 for n in c), 1)
    first = len(mesh.bricks) + 1
    for k, ((i, j), kp) in enumerate(zip(mesh.pairs.tolist(), (mesh.k_pen * u).tolist(),
                                         strict=True)):
        if s.element == "zeroLengthContactASDimplex":
            ops.element(s.element, first + k, i + 1, j + 1, kp, kp, FRICTION,
                        "-orient", 0.0, 0.0, 1.0)
        else:  # zeroLengthContact3D: constrained (slave) node, retained (master) node
            ops.element(s.element, first + k, j + 1, i + 1, kp, kp, FRICTION, 0.0, 3)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    for i in np.flatnonzero(mesh.weight).tolist():
        ops.load(i + 1, 0.0, 0.0, -float(mesh.weight[i]))
    return list(range(first, first + len(mesh.pairs)))


def load_control(ops: ModuleType, dlam: float, s: Setup) -> None:
    analysis_base(ops, s.solver)
    ops.test("NormUnbalance", 1e-6 * H_EXACT, s.max_iter)
    ops.algorithm("Newton", "-intialThenCurrent")  # sic: OpenSees's spelling
    ops.integrator("LoadControl", dlam)
    ops.analysis("Static")


def run_opensees(ops: ModuleType, mesh: Mesh, s: Setup, theta: float) -> dict:
    start = Times.now()
    build_opensees(ops, mesh, s)
    iters, converged, limit, weight_ok = 0, 0, None, True
    load_control(ops, 1.0 / WEIGHT_STEPS, s)
    for _ in range(WEIGHT_STEPS):
        weight_ok = ops.analyze(1) == 0
        iters += ops.testIter()
        if not weight_ok:
            break
    if weight_ok:
        ops.loadConst("-time", 0.0)
        ops.timeSeries("Linear", 2)
        ops.pattern("Plain", 2, 2)
        f = PUSH_MAX / len(mesh.top)
        for i in mesh.top.tolist():
            ops.load(i + 1, f * math.cos(theta), f * math.sin(theta), 0.0)
        load_control(ops, 1.0 / s.steps, s)
        for _ in range(s.steps):
            ok = ops.analyze(1) == 0
            iters += ops.testIter()
            if not ok:
                break
            converged += 1
            limit = ops.getLoadFactor(2) * PUSH_MAX
    t = Times.now() - start
    ops.wipe()
    return {"time": t, "weight_ok": weight_ok, "steps": converged, "iters": iters,
            "limit": limit, "ndof": 3 * len(mesh.points)}


def compare(r: int, args, ops: ModuleType) -> dict:
    mesh = mesh_arrays(r, args.penalty)
    out = {"r": r, "sc": {}, "os": {}}
    for _ in range(args.pairs):
        for k in args.facets:
            out["sc"].setdefault(k, []).append(run_stepcontact(r, args.theta, k))
        for el in args.elements:
            s = Setup(args.steps, args.max_iter, args.solver,
                      {"m": 1.0, "mm": 1e-3}[args.length_unit], el)
            with quiet_stderr():
                out["os"].setdefault(el, []).append(run_opensees(ops, mesh, s, args.theta))
    for side in ("sc", "os"):
        for key, runs in out[side].items():
            out[side][key] = runs[-1] | {"time": median(x["time"] for x in runs)}
    return out


def report(c: dict, theta: float) -> str:
    lines = []
    for k, s in c["sc"].items():
        lines.append(
            f"r={c['r']} stepcontact k={k}: {s['ndof']} DOFs, {s['cfes']} CFEs, {s['events']} "
            f"events, {s['status']} at H = {s['limit']:.6f} N; exact H_k = {s['exact']:.6f} N "
            f"(error {abs(s['limit'] / s['exact'] - 1):.1e}); against f·W = {H_EXACT:.3f} N: "
            f"{s['limit'] / H_EXACT - 1:+.3%}; time {s['time']}")
    for el, o in c["os"].items():
        if not o["weight_ok"]:
            verdict = "did NOT converge under the self-weight"
        elif o["limit"] is None:
            verdict = "converged under the weight, NOT at the first push step"
        else:
            verdict = (f"last converged push H = {o['limit']:.3f} N after {o['steps']} steps "
                       f"(against f·W: {o['limit'] / H_EXACT - 1:+.2%}; a step is "
                       f"{PUSH_MAX / 100:.1f} N at 100 steps)")
        lines.append(f"r={c['r']} OpenSees {el}: {o['ndof']} DOFs, {verdict}, {o['iters']} "
                     f"Newton iterations; time {o['time']}")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1, 2],
                    help="refinement factors r (cells of side 0.25/r; default 1 2)")
    ap.add_argument("--theta", type=float, default=0.3, help="push direction, rad (0.3)")
    ap.add_argument("--facets", type=int, nargs="+", default=[8, 16, 64],
                    help="stepcontact's facet counts k (default 8 16 64)")
    ap.add_argument("--elements", nargs="+", default=list(ELEMENTS),
                    help="OpenSees contact elements to try")
    ap.add_argument("--pairs", type=int, default=1, help="alternating run pairs (default 1)")
    ap.add_argument("--steps", type=int, default=100,
                    help="OpenSees load steps of the push up to 1.05·f·W (default 100)")
    ap.add_argument("--max-iter", type=int, default=50,
                    help="OpenSees Newton iterations per step (default 50)")
    add_opensees_options(ap)
    args = ap.parse_args()
    ops, blas = load_opensees(args.blas)
    print(f"load average at start: {os.getloadavg()}", flush=True)
    print(f"W = {WEIGHT:.3f} N, f·W = {H_EXACT:.3f} N, θ = {args.theta} rad.  OpenSees: "
          f"{', '.join(args.elements)}, penalty α = {args.penalty:g}, units N/"
          f"{args.length_unit}, Newton, system {args.solver}, {args.steps} push steps up to "
          f"{PUSH_MAX:.1f} N, BLAS {blas}", flush=True)
    rows = []
    for r in args.sizes:
        rows.append(compare(r, args, ops))
        print(report(rows[-1], args.theta), flush=True)
    print(f"load average at end: {os.getloadavg()}")
    print("\nratios (last): T_OpenSees / T_stepcontact (k = first facet count) from process "
          "CPU time [main-thread CPU; wall]; only for elements that reached the push")
    for c in rows:
        ss = next(iter(c["sc"].values()))["time"]
        for el, o in c["os"].items():
            if o["limit"] is None:
                print(f"r={c['r']} {el}: no converged push, no ratio")
                continue
            so = o["time"]
            short = (f" (its run stopped at {o['limit'] / H_EXACT:.0%} of f·W: not the same "
                     f"work)" if o["limit"] < 0.95 * H_EXACT else "")
            print(f"r={c['r']} {el}: {so.process / ss.process:.2f} "
                  f"[{so.thread / ss.thread:.2f}; {so.wall / ss.wall:.2f}]{short}")


if __name__ == "__main__":
    main()
