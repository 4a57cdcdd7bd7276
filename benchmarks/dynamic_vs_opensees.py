"""Benchmark: stepcontact's dynamic solver against OpenSeesPy on the slab-on-foundation model.

The model is ``slab_model(k)`` of ``slab_on_foundation.py``: a slab 30 m × 2 m (concrete,
E = 30 GPa, 2400 kg/m³) on a 50 m × 20 m rock foundation (E = 5 GPa, 2200 kg/m³), plane strain,
bilinear quads, a rigid frictional joint (f = 0.7) whose two sides match node to node (cells
of 0.4/k m along x: 75k + 1 node pairs); foundation bottom fixed in x and y, its sides in x.
The scenario is the one of ``dynamic_slab.py``: the slab rests under its own weight (a static
run), then the half-sine uplift pulse ``sc.Pulse(1.5e5, 0.01, 0.05, "half_sine")`` on the
pattern "uplift" (a triangular pressure on the slab's bottom, 1 Pa upstream → 0 downstream per
unit factor: 150 kPa at the peak, t = 35 ms; the slab weighs 47 kPa) throws most of the slab
off its foundation (k = 1: up to 67 of 76 pairs open, 23 mm at the upstream end at 92 ms), and
it lands again (impacts, sliding) until about 0.25 s.  Lumped mass, Δt = 1 ms,
HHT-α with α = 0.05 (γ = 1/2 + α, β = (1 + α)²/4), no Rayleigh damping, ``--duration`` of
response (default 1 s).

stepcontact: model building + assembly + ``sc.solve_static`` + ``sc.solve_dynamic(system,
dt, duration, initial=rest, mass="lumped", alpha=0.05, loads={"uplift": pulse})``, timed as a
whole (T_stepcontact).  Its contact is rigid and its events are located inside the steps: the
first "opened" event is its lift-off time; it also reports the last re-closing, the largest
number of CFEs open at once and the largest uplift (normal gap) of the slab's upstream end.

OpenSeesPy, set up as an OpenSees user would (``vs_opensees.py`` is reused for the import of
openseespy with a BLAS its Linux wheel can find, for silencing its messages and for the
counter-clockwise cell ordering):

* the same mesh: ``quad`` elements (thickness t = 1 m), ``ElasticIsotropic`` PlaneStrain
  (density 0; concrete for the slab, rock for the foundation), the masses as
  nodal masses (``ops.mass``) equal to stepcontact's lumped (HRZ) mass diagonal; the same
  supports; the self-weight and uplift loads as nodal loads equal to stepcontact's assembled
  load vectors (``system.loads[...].f``), so that both programs load the same nodes with the
  same forces;
* the joint: one ``zeroLengthContactASDimplex`` element (implicit, Coulomb f = 0.7, normal +y)
  between each pair of coincident foundation (i) / slab (j) nodes — separate nodes; its
  ``localDisplacement`` response is (normal jump, tangential jump), the normal one > 0 when the
  gap is open (checked: it is < 0, a penetration, at every pair under the self-weight);
* penalties a priori, as in ``vs_opensees.py``: K_n = K_t = α·E·t·L/h with α = 100
  (``--penalty``), L the pair's tributary length (stepcontact's CFE area / t), E and h the
  modulus and joint-cell height of the *slab's* concrete (E = 30 GPa, h = 1/k m; the stiffer
  side, closer to the rigid contact stepcontact solves; ``--penalty-side foundation`` uses the
  rock's E = 5 GPa and h = 20/(19k) m instead, six times softer);
* units N and mm (``--length-unit``; the reason is in ``vs_opensees.py``'s docstring: the
  element's tangent is a central difference with a fixed perturbation of 1e-9 length units);
* self-weight by load control (10 steps, ``Newton -intialThenCurrent``), ``loadConst -time 0``;
  then the transient: the uplift loads on a ``Trig`` time series (tStart 0.01 s, tEnd 0.06 s,
  period 0.1 s, factor 1.5e5: exactly the half sine), ``integrator HHT 0.95 0.55 0.275625``
  (OpenSees's α is 1 − α_HHT: α = 1 is Newmark's average acceleration; γ = 1.5 − α,
  β = (2 − α)²/4, the same scheme as stepcontact's, except that OpenSees takes the load at
  t_{n+1−α} where stepcontact takes (1 − α) F_{n+1} + α F_n), ``algorithm Newton``
  (``--algorithm``),
  ``test NormUnbalance`` 1e-6 × the slab's weight (1.4 N at every k) with at most 50
  iterations, ``numberer RCM``, ``system Mumps`` (the contact tangent is unsymmetric),
  ``analysis Transient``, ``analyze(1, dt)`` per step.  A step that fails (OpenSees reverts
  it) is retried with ``NewtonLineSearch``, then ``KrylovNewton``, then with the default
  algorithm in 2, 4, 8, 16 sub-steps (``--halvings``); if all fail the run stops there
  (reported).  Tried on the first 0.12 s at k = 1: plain Newton stalls at t = 42 ms (the
  unbalance cycles at 4.9 kN: contact states flip-flopping between iterations), and so do
  ``Newton -initialThenCurrent`` (iterations identical to plain Newton's), ``KrylovNewton``
  and the tests ``NormDispIncr`` 1e-6 mm and ``EnergyIncr`` 1e-6 N·mm; ``NewtonLineSearch``
  gets past it and stalls at 75 ms; ``ModifiedNewton`` stalls at 12 ms.  So OpenSees is run
  twice (``--contact``, default both): with the element's implicit integration as above, and
  with its IMPL-EX integration (``-intType 1``: the contact state extrapolated from the last
  steps, one iteration per step that never fails; the element's own remedy for this);
* lift-off: the first converged step (its end time) at which any contact element's normal
  gap is > 0; also the last step at which a pair re-closes, the largest number of open pairs
  and the largest uplift of the upstream end's pair.  These element queries are timed apart
  and left out of OpenSees's time (model building + self-weight + transient).
  ``--os-duration`` runs OpenSees for a shorter time and scales its time to ``--duration``
  linearly (said so in the output; a rough figure: the hard part, lift-off, flight and
  landing, is in the first 0.25 s).

Printed per size k (k = 1, 2, 4: 5 496, 21 k, 82 k DOFs): DOFs, contact pairs, both times,
steps, stepcontact's events (by kind) and impacts and status, OpenSees's Newton iterations and
failed / recovered steps (per contact integration), both lift-off times and their difference
in Δt, and last the ratios T_OpenSees / T_stepcontact (marked as a lower bound when OpenSees
stopped before the end: its time up to there against stepcontact's for the whole duration).
Every time is printed as wall, process CPU and main-thread CPU (``benchmarks/_timing.py``);
the ratios are from process CPU time, the main-thread CPU and wall ratios beside them.
``os.getloadavg()`` is printed at the start and the end (the machine may be shared).  The
programs run one after the other, never side by side.

Run:  python benchmarks/dynamic_vs_opensees.py --sizes 1 2
Needs openseespy (``pip install openseespy``).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import runpy
import sys
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

import numpy as np

import stepcontact as sc
from stepcontact.enums import ContactState, Transition
from stepcontact.fem.mass import mass as mass_matrix

_HERE = Path(__file__).parent
if str(_HERE.resolve()) not in sys.path:  # also when run by runpy
    sys.path.insert(0, str(_HERE.resolve()))
from _timing import Times  # noqa: E402  (benchmarks/_timing.py)

slab_model = runpy.run_path(str(_HERE / "slab_on_foundation.py"),
                            run_name="slab_on_foundation")["slab_model"]
_VS = runpy.run_path(str(_HERE / "vs_opensees.py"), run_name="vs_opensees")
load_opensees, quiet_stderr, counter_clockwise, analysis_base, add_opensees_options = (
    _VS["load_opensees"], _VS["quiet_stderr"], _VS["counter_clockwise"], _VS["analysis_base"],
    _VS["add_opensees_options"])

ALPHA = 0.05  # HHT-α (stepcontact's convention; OpenSees's is 1 − α)
PULSE = sc.Pulse(1.5e5, 0.01, 0.05, "half_sine")  # factor of the "uplift" pattern, Pa
FRICTION = 0.7
WEIGHT_STEPS = 10
#: tried in turn on a transient step that failed, before sub-steps
REMEDIES = ("NewtonLineSearch", "KrylovNewton")


# --------------------------------------------------------------------------- stepcontact side


def base_model(k: int) -> sc.Model:
    """The slab model with the self-weight as its only static segment."""
    return slab_model(k).replace(program=(sc.Segment("weight", 1.0),))


def run_stepcontact(k: int, dt: float, duration: float) -> dict:
    """Build, assemble, rest under the weight, then the pulse in time; all timed."""
    t0 = Times.now()
    system = sc.assemble(base_model(k))
    rest = sc.solve_static(system)
    t1 = Times.now()
    res = sc.solve_dynamic(system, dt=dt, duration=duration, initial=rest, mass="lumped",
                           alpha=ALPHA, loads={"uplift": PULSE})
    t2 = Times.now()
    opened = [e.lam for e in res.events if e.transition == Transition.OPENED]
    closed = [e.lam for e in res.events if e.transition == Transition.CLOSED]
    n_open = (np.asarray(res.state) == ContactState.OPEN).sum(axis=1)
    up = int(np.argmin(system.cfe.x[:, 0]))  # the upstream end's CFE (x = 10 m)
    gap = -res.un[:, up]  # stepcontact's u_n < 0 is an open gap
    c = res.counters
    return {
        "ndof": system.ndof, "pairs": system.m, "time": t2 - t0, "t_static": t1 - t0,
        "t_dynamic": t2 - t1, "steps": int(c["steps"]), "events": len(res.events),
        "kinds": Counter(str(e.transition) for e in res.events), "impacts": int(c["impacts"]),
        "status": res.status.value, "message": res.message,
        "end_time": float(res.lam[-1]),
        "lift_off": min(opened) if opened else None,
        "last_close": max(closed) if closed else None,
        "max_open": int(n_open.max()), "max_open_at": float(res.lam[int(n_open.argmax())]),
        "uplift": float(gap.max()), "uplift_at": float(res.lam[int(gap.argmax())]),
    }


# ------------------------------------------------------------------------------ OpenSees side


@dataclass(frozen=True)
class Mesh:
    """The stepcontact model as plain arrays for OpenSees (node tags are global index + 1)."""

    points: np.ndarray  # (n, 2) m
    cells: np.ndarray  # (n_el, 4) counter-clockwise
    cell_mat: np.ndarray  # (n_el,) index into materials
    materials: tuple[tuple[float, float], ...]  # (E Pa, ν) per body
    fix: np.ndarray  # (n, 2) bool: x, y fixed
    mass: np.ndarray  # (n, 2) lumped masses, kg
    weight: np.ndarray  # (n, 2) self-weight nodal forces, N
    uplift: np.ndarray  # (n, 2) uplift nodal forces per unit factor, N
    pairs: np.ndarray  # (m, 2) (foundation, slab) node indices, coincident
    k_pen: np.ndarray  # (m,) penalties, N/m
    upstream: int  # index into pairs of the upstream end (x = 10 m)
    slab_weight: float  # N

    @property
    def ndof(self) -> int:
        return 2 * len(self.points)


def joint_cell_height(body: sc.Body) -> float:
    """Mean height of the body's cells that touch y = 0 (the joint), m."""
    p = body.points[body.cells[:, :4]]  # (n_el, 4, 2)
    touch = np.isclose(p[..., 1], 0.0).any(axis=1)
    return float(np.mean(np.ptp(p[touch, :, 1], axis=1)))


def mesh_arrays(k: int, penalty: float, side: str) -> Mesh:
    """The same mesh, supports, masses and loads as stepcontact's (built outside the timing)."""
    model = base_model(k)
    system = sc.assemble(model)
    off, of = model.node_offsets, system.dofs.of[:, :2]
    n = of.shape[0]
    points = np.zeros((n, 2))
    cells, cell_mat = [], []
    for i, b in enumerate(model.bodies):
        points[off[b.name]:off[b.name] + b.n_nodes] = b.points
        cells.append(b.cells[:, :4] + off[b.name])
        cell_mat.append(np.full(len(b.cells), i))
    cfe = system.cfe
    if (cfe.plus_w[:, 0] != 1.0).any() or (cfe.minus_w[:, 0] != 1.0).any():
        raise ValueError("the joint's CFEs are not node to node")
    pairs = np.column_stack([cfe.minus_nodes[:, 0], cfe.plus_nodes[:, 0]])
    if not np.allclose(points[pairs[:, 0]], points[pairs[:, 1]]):
        raise ValueError("joint nodes do not coincide")
    body = next(b for b in model.bodies if b.name == side)
    trib = cfe.area / model.thickness
    k_pen = penalty * float(body.material.E) * model.thickness * trib / joint_cell_height(body)
    M = mass_matrix(model, system.dofs, lumped=True).diagonal()
    w, q = system.loads["weight"].f, system.loads["uplift"].f
    return Mesh(points=points, cells=counter_clockwise(points, np.vstack(cells)),
                cell_mat=np.concatenate(cell_mat),
                materials=tuple((float(b.material.E), float(b.material.nu))
                                for b in model.bodies),
                fix=system.fixed[of], mass=M[of], weight=w[of], uplift=q[of], pairs=pairs,
                k_pen=k_pen, upstream=int(np.argmin(cfe.x[:, 0])),
                slab_weight=float(-w[of[:, 1]].sum()))


@dataclass(frozen=True)
class Setup:
    """OpenSees analysis options."""

    unit: float = 1e-3  # model length unit, m (1e-3: N, mm, MPa, t)
    max_iter: int = 50
    rel_tol: float = 1e-6  # NormUnbalance tolerance / the slab's weight
    solver: str = "Mumps"
    algorithm: str = "Newton"
    halvings: int = 4
    implex: bool = False  # the contact elements' IMPL-EX integration (-intType 1)


def build_opensees(ops: ModuleType, mesh: Mesh, u: float, implex: bool = False) -> list[int]:
    """Nodes, masses, supports, quads, contact elements and the self-weight pattern (series 1).
    Returns the contact element tags."""
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 2)
    for i, ((x, y), (mx, my)) in enumerate(zip((mesh.points / u).tolist(),
                                               (mesh.mass * u).tolist(), strict=True), start=1):
        ops.node(i, x, y)
        if mx or my:
            ops.mass(i, mx, my)  # kg → N·s²/mm (u = 1e-3)
    for i in np.flatnonzero(mesh.fix.any(axis=1)).tolist():
        ops.fix(i + 1, *(int(f) for f in mesh.fix[i]))
    for tag, (E, nu) in enumerate(mesh.materials, start=1):  # density 0: nodal masses
        ops.nDMaterial("ElasticIsotropic", tag, E * u**2, nu, 0.0)
    for e, (c, mat) in enumerate(zip(mesh.cells.tolist(), mesh.cell_mat.tolist(), strict=True),
                                 start=1):
        ops.element("quad", e, *(i + 1 for i in c), 1.0 / u, "PlaneStrain", mat + 1)
    first = len(mesh.cells) + 1
    for t, ((i, j), kp) in enumerate(zip(mesh.pairs.tolist(), (mesh.k_pen * u).tolist(),
                                         strict=True), start=first):
        ops.element("zeroLengthContactASDimplex", t, i + 1, j + 1, kp, kp, FRICTION,
                    "-orient", 0.0, 1.0, 0.0, "-intType", int(implex))
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    for i in np.flatnonzero(mesh.weight.any(axis=1)).tolist():
        ops.load(i + 1, *mesh.weight[i].tolist())
    return list(range(first, first + len(mesh.pairs)))


def analysis_options(ops: ModuleType, mesh: Mesh, setup: Setup) -> None:
    analysis_base(ops, setup.solver)
    ops.test("NormUnbalance", setup.rel_tol * mesh.slab_weight, setup.max_iter)


class Gaps:
    """Per converged step: the contact elements' normal gaps (m), timed apart."""

    def __init__(self, ops: ModuleType, tags: list[int], u: float, upstream: int) -> None:
        self.ops, self.tags, self.u, self.upstream = ops, tags, u, upstream
        self.seconds = Times()
        self.lift_off: float | None = None
        self.last_close: float | None = None
        self.max_open, self.max_open_at = 0, 0.0
        self.uplift, self.uplift_at = 0.0, 0.0
        self.openings = 0
        self._open = np.zeros(len(tags), dtype=bool)

    def gaps(self) -> np.ndarray:
        resp = self.ops.eleResponse
        return np.array([resp(t, "localDisplacement")[0] for t in self.tags]) * self.u

    def check(self, t: float) -> None:
        t0 = Times.now()
        g = self.gaps()
        is_open = g > 0.0
        if is_open.any() and self.lift_off is None:
            self.lift_off = t
        self.openings += int((is_open & ~self._open).sum())
        if (self._open & ~is_open).any():
            self.last_close = t
        self._open = is_open
        if is_open.sum() > self.max_open:
            self.max_open, self.max_open_at = int(is_open.sum()), t
        if g[self.upstream] > self.uplift:
            self.uplift, self.uplift_at = float(g[self.upstream]), t
        self.seconds += Times.now() - t0


def run_opensees(ops: ModuleType, mesh: Mesh, setup: Setup, dt: float,
                 duration: float) -> dict:
    """Self-weight (load control), then HHT steps of dt until ``duration``; timed."""
    u = setup.unit
    t0 = Times.now()
    tags = build_opensees(ops, mesh, u, setup.implex)
    watch = Gaps(ops, tags, u, mesh.upstream)
    iters = 0
    # --- self-weight
    analysis_options(ops, mesh, setup)
    ops.algorithm("Newton", "-intialThenCurrent")  # sic: OpenSees's spelling
    ops.integrator("LoadControl", 1.0 / WEIGHT_STEPS)
    ops.analysis("Static")
    weight_ok = True
    for _ in range(WEIGHT_STEPS):
        weight_ok = ops.analyze(1) == 0
        iters += ops.testIter()
        if not weight_ok:
            break
    q0 = Times.now()
    g0 = watch.gaps()
    watch.seconds += Times.now() - q0
    out = {"weight_ok": weight_ok, "gap_weight": (float(g0.min()), float(g0.max()))}
    steps = failed = sub_steps = 0
    remedied: Counter = Counter()
    stopped = None
    if weight_ok:
        ops.loadConst("-time", 0.0)
        ops.timeSeries("Trig", 2, PULSE.start, PULSE.start + PULSE.duration,
                       2 * PULSE.duration, "-factor", PULSE.amplitude)
        ops.pattern("Plain", 2, 2)
        for i in np.flatnonzero(mesh.uplift.any(axis=1)).tolist():
            ops.load(i + 1, *mesh.uplift[i].tolist())
        analysis_options(ops, mesh, setup)
        ops.algorithm(setup.algorithm)
        a_os = 1.0 - ALPHA
        ops.integrator("HHT", a_os, 1.5 - a_os, (2.0 - a_os) ** 2 / 4)
        ops.analysis("Transient")
        n = round(duration / dt)
        for s in range(1, n + 1):
            target = s * dt
            ok = ops.analyze(1, dt) == 0
            iters += ops.testIter()
            if not ok:  # the failed step was reverted: other algorithms, then sub-steps
                failed += 1
                for alg in REMEDIES:
                    ops.algorithm(alg)
                    ok = ops.analyze(1, dt) == 0
                    iters += ops.testIter()
                    ops.algorithm(setup.algorithm)
                    if ok:
                        remedied[alg] += 1
                        break
                h = dt
                for _ in range(0 if ok else setup.halvings):
                    h /= 2
                    while ops.getTime() < target - 1e-3 * h:
                        ok = ops.analyze(1, h) == 0
                        iters += ops.testIter()
                        sub_steps += 1
                        if not ok:
                            break
                    if ok:
                        remedied[f"{round(dt / h)} sub-steps"] += 1
                        break
            if not ok:
                stopped = ops.getTime()
                break
            steps += 1
            watch.check(target)
    t = Times.now() - t0 - watch.seconds
    ops.wipe()
    return out | {
        "time": t, "steps": steps, "iters": iters, "failed": failed, "sub_steps": sub_steps,
        "stopped": stopped, "remedied": remedied, "query_seconds": watch.seconds,
        "lift_off": watch.lift_off,
        "last_close": watch.last_close, "max_open": watch.max_open,
        "max_open_at": watch.max_open_at, "uplift": watch.uplift,
        "uplift_at": watch.uplift_at, "openings": watch.openings,
    }


# ---------------------------------------------------------------------------------- protocol


def fmt_t(t: float | None) -> str:
    return "none" if t is None else f"{t * 1e3:.3f} ms"


def report_stepcontact(k: int, s: dict, mesh: Mesh, dt: float, duration: float) -> str:
    kinds = ", ".join(f"{n} {kind}" for kind, n in sorted(s["kinds"].items()))
    return (
        f"k={k}: {s['ndof']} DOFs (OpenSees {mesh.ndof}), {s['pairs']} contact pairs; "
        f"{round(duration / dt)} steps of {dt * 1e3:g} ms\n"
        f"    stepcontact: T = {s['time']} (build + assembly + static "
        f"{s['t_static'].process:.2f} s, dynamic {s['t_dynamic'].process:.2f} s process CPU); "
        f"{s['steps']} steps (event cuts included), "
        f"{s['events']} events ({kinds}), {s['impacts']} impacts; status {s['status']} at "
        f"t = {s['end_time']:.4f} s ({s['message']})\n"
        f"        lift-off (first opening) {fmt_t(s['lift_off'])}, last re-closing "
        f"{fmt_t(s['last_close'])}, most CFEs open at once {s['max_open']} (t = "
        f"{fmt_t(s['max_open_at'])}), largest uplift of the upstream end (x = 10 m) "
        f"{s['uplift'] * 1e3:.3f} mm at {fmt_t(s['uplift_at'])}"
    )


def report_opensees(s: dict, o: dict, mesh: Mesh, dt: float, duration: float,
                    os_duration: float, setup: Setup, penalty_note: str) -> str:
    scaled = os_duration < duration
    name = "IMPL-EX" if setup.implex else "implicit"
    lines = [
        f"    OpenSees, contact {name}: T = {o['time']} over {os_duration:g} s of "
        f"response"
        + (f" -> SCALED to {duration:g} s: {o['time'].process * duration / os_duration:.2f} s "
           f"process CPU (not measured)" if scaled else "")
        + f"; {o['steps']} converged steps, {o['iters']} Newton iterations in all "
        f"(self-weight's included; {setup.algorithm}, NormUnbalance "
        f"{setup.rel_tol * mesh.slab_weight:.2g} N); {o['failed']} steps failed with "
        f"{setup.algorithm}, recovered by: "
        f"{', '.join(f'{k} {n}' for k, n in o['remedied'].items()) or 'none needed'} "
        f"({o['sub_steps']} sub-steps tried); "
        + (f"STOPPED: no convergence at t = {o['stopped'] * 1e3:.3f} ms, the rest of the "
           f"{os_duration:g} s not run" if o["stopped"] is not None else "no step given up")
        + f"; self-weight converged: {o['weight_ok']}, normal gaps under it "
        f"{o['gap_weight'][0]:.2e} … {o['gap_weight'][1]:.2e} m; gap queries "
        f"{o['query_seconds'].process:.2f} s process CPU, not counted; {penalty_note}",
        f"        lift-off {fmt_t(o['lift_off'])} (end of the first step with a gap > 0)"
        + (f", {(o['lift_off'] - s['lift_off']) / dt:+.2f} Δt from stepcontact's"
           if s["lift_off"] is not None and o["lift_off"] is not None else "")
        + f"; last re-closing {fmt_t(o['last_close'])}, most pairs open at once "
        f"{o['max_open']} (t = {fmt_t(o['max_open_at'])}), openings {o['openings']} "
        f"(stepcontact {s['kinds'].get('opened', 0)}); largest uplift of the upstream end "
        f"{o['uplift'] * 1e3:.3f} mm at {fmt_t(o['uplift_at'])}",
    ]
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1],
                    help="mesh size factors k (cells of 0.4/k m along the joint; default 1)")
    ap.add_argument("--duration", type=float, default=1.0, help="response time, s (default 1)")
    ap.add_argument("--dt", type=float, default=1e-3, help="time step, s (default 1e-3)")
    ap.add_argument("--os-duration", type=float, default=None,
                    help="run OpenSees only this long and scale its time to --duration")
    ap.add_argument("--contact", choices=("implicit", "implex"), nargs="+",
                    default=["implicit", "implex"],
                    help="OpenSees contact integrations to run (default both, in turn)")
    ap.add_argument("--penalty-side", choices=("slab", "foundation"), default="slab",
                    help="E and h of the penalty: the slab's concrete (default) or the rock")
    ap.add_argument("--algorithm", default="Newton", help="OpenSees algorithm (default Newton)")
    ap.add_argument("--max-iter", type=int, default=50, help="OpenSees iterations per step")
    ap.add_argument("--halvings", type=int, default=4,
                    help="OpenSees: a failed step is retried in 2, 4, … 2^halvings sub-steps")
    add_opensees_options(ap)  # --penalty, --solver, --length-unit, --blas
    args = ap.parse_args()
    os_duration = min(args.os_duration or args.duration, args.duration)
    setup = Setup(unit={"m": 1.0, "mm": 1e-3}[args.length_unit], max_iter=args.max_iter,
                  solver=args.solver, algorithm=args.algorithm, halvings=args.halvings)
    ops, blas = load_opensees(args.blas)
    print(f"load average at start: {os.getloadavg()}", flush=True)
    print(f"pulse {PULSE}, HHT α = {ALPHA} (OpenSees HHT {1 - ALPHA:g}), Δt = {args.dt:g} s, "
          f"{args.duration:g} s of response; OpenSees: penalty α = {args.penalty:g} "
          f"({args.penalty_side}), units N/{args.length_unit}, {setup.algorithm}, contact "
          f"{' then '.join(args.contact)}, system {setup.solver}, BLAS {blas}", flush=True)
    rows = []
    for k in args.sizes:
        mesh = mesh_arrays(k, args.penalty, args.penalty_side)
        s = run_stepcontact(k, args.dt, args.duration)
        print(report_stepcontact(k, s, mesh, args.dt, args.duration), flush=True)
        note = (f"K_n = K_t = {np.median(mesh.k_pen):.3g} N/m (interior pairs; "
                f"{args.penalty_side})")
        for variant in args.contact:
            su = dataclasses.replace(setup, implex=variant == "implex")
            with quiet_stderr():
                o = run_opensees(ops, mesh, su, args.dt, os_duration)
            print(report_opensees(s, o, mesh, args.dt, args.duration, os_duration, su, note),
                  flush=True)
            rows.append((k, s["ndof"], variant, o, s["time"]))
    print(f"load average at end: {os.getloadavg()}")
    print(f"\nratio (last): T_OpenSees / T_stepcontact for {args.duration:g} s of response, "
          f"from process CPU time (both programs in this process; OpenSees's solver and BLAS "
          f"may use several threads) [main-thread CPU; wall]")
    for k, ndof, variant, o, t_sc in rows:
        t_os = o["time"] * (args.duration / os_duration)
        note = ""
        if o["stopped"] is not None:
            t_os = o["time"]
            note = (f"  LOWER BOUND: OpenSees stopped at t = {o['stopped'] * 1e3:.3f} ms (its "
                    f"time up to there against stepcontact's for {args.duration:g} s)")
        elif os_duration < args.duration:
            note = f"  (OpenSees time SCALED from {os_duration:g} s)"
        print(f"k={k} ({ndof} DOFs), OpenSees contact {variant}: "
              f"{t_os.process / t_sc.process:.2f} [{t_os.thread / t_sc.thread:.2f}; "
              f"{t_os.wall / t_sc.wall:.2f}]{note}")


if __name__ == "__main__":
    main()
