"""Mutate the example model files in realistic bad ways; list what ``validate`` passes but
``run`` rejects (issue 24, §4: "validate passes what run rejects").

Every model file of examples/data and of the package's data (the demos) is read, changed by
each mutation that applies to it, written to a temporary folder, and given to
``stepcontact validate`` and ``stepcontact run`` (in this process, through typer's runner;
``run`` with ``--no-plot -q`` and a time limit).  A mutation is listed when

* ``validate`` exits 0 but ``run`` exits 2 (an input error found only by solving), or
* either command ends in a traceback (an exception that is not a clean error).

Usage::

    python benchmarks/bad_input_mutations.py            # the table, one line per case
    python benchmarks/bad_input_mutations.py --all      # every case with both exit codes
    python benchmarks/bad_input_mutations.py --json out.json

The cases found are the parametrised test ``test_validate_and_run_agree`` of
tests/test_bad_inputs.py (the mutations are imported from here).
"""

from __future__ import annotations

import argparse
import copy
import json
import signal
import sys
import tempfile
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
MODELS = {
    "staged_wall": ROOT / "examples" / "data" / "staged_wall.toml",
    "staged_shock": ROOT / "examples" / "data" / "staged_shock.toml",
    "gmsh_block": ROOT / "examples" / "data" / "gmsh_block.toml",
    "demo": ROOT / "src" / "stepcontact" / "data" / "demo.toml",
    "demo_uplift": ROOT / "src" / "stepcontact" / "data" / "demo_uplift.toml",
}

Mutation = Callable[[dict[str, Any]], bool]  # changes the dict in place; False: not applicable


def _first_interface(d: dict) -> dict | None:
    return (d.get("interfaces") or [None])[0]


def _materials(d: dict) -> list[dict]:
    out = list((d.get("materials") or {}).values())
    out += [b["material"] for b in d.get("bodies", []) if isinstance(b.get("material"), dict)]
    return out


def _patterns(d: dict) -> dict[str, dict]:
    return d.get("patterns") or {}


def _segments(d: dict) -> list[dict]:
    return list(d.get("program", [])) + [s for st in d.get("stages", [])
                                         for s in st.get("program", [])]


def no_supports(d):
    """every support removed (the structure floats)"""
    if not d.get("supports") or d.get("stages"):
        return False
    d["supports"] = []
    return True


def stage_removes_every_support(d):
    """a later stage removes every support"""
    if not d.get("stages") or len(d["stages"]) < 2 or not d.get("supports"):
        return False
    names = [s.get("name") or s["nodes"] for s in d["supports"]]
    stage = next((st for st in d["stages"] if st.get("remove_supports")), d["stages"][-1])
    for st in d["stages"]:
        st.pop("supports", None)
    stage["remove_supports"] = names
    return True


def _lowest_set(d: dict) -> str | None:
    """The node set of a rectangle body at the lowest y (by its ``y`` or the body's corner)."""
    best, low = None, float("inf")
    bodies = {b.get("name"): b for b in d.get("bodies", [])}
    for n, ns in (d.get("node_sets") or {}).items():
        y = ns.get("y")
        b = bodies.get(ns.get("body"))
        if y is None or b is None or "corner0" not in b:
            continue
        if y < low:
            best, low = n, y
    return best


def level_pattern_starts_high(d):
    """a water-level pattern on faces below y = 0, raised from level 0 (already wet there)"""
    face = _lowest_set(d)
    if face is None or not d.get("program") or d["node_sets"][face]["y"] >= 0:
        return False
    d["patterns"]["reservoir"] = {"loads": [{"type": "water", "nodes": face}]}
    d["program"].append({"pattern": "reservoir", "end": 5.0})
    return True


def level_pattern_two_rates(d):
    """a water-level pattern moved together with another pattern by a segment with rates"""
    face = _lowest_set(d)
    segs = d.get("program")
    if face is None or not segs:
        return False
    other = segs[0]["pattern"]
    d["patterns"]["reservoir"] = {"loads": [{"type": "water", "nodes": face}]}
    segs.append({"pattern": "flood", "end": 1.0, "rates": {"reservoir": 1.0, other: 0.1}})
    return True


def _dynamics(d: dict) -> dict | None:
    """The model's dynamic interval (a stage's, or a top-level one added to a model with
    neither)."""
    dyn = d.get("dynamics") or next((s["dynamics"] for s in d.get("stages", [])
                                     if "dynamics" in s), None)
    if dyn is None and not d.get("stages"):
        dyn = d["dynamics"] = {"dt": 1e-3, "duration": 0.01}
    return dyn


def dynamics_moves_level_pattern(d):
    """a dynamic interval whose time function multiplies a water-level pattern"""
    face = _lowest_set(d)
    dyn = _dynamics(d)
    if face is None or dyn is None:
        return False
    d["patterns"]["reservoir"] = {"loads": [{"type": "water", "nodes": face}]}
    dyn.setdefault("loads", []).append({"pattern": "reservoir", "type": "constant",
                                        "amplitude": 1.0})
    return True


def dynamics_moves_prescribed_displacement(d):
    """a dynamic interval whose time function multiplies a prescribed displacement"""
    ns = _lowest_set(d) or next(iter(d.get("node_sets") or {}), None)
    dyn = _dynamics(d)
    if ns is None or dyn is None:
        return False
    d["patterns"]["jack"] = {"loads": [{"type": "displacement", "nodes": ns, "dof": "x",
                                        "value": 1e-4}]}
    dyn.setdefault("loads", []).append({"pattern": "jack", "type": "pulse", "duration": 0.005})
    return True


def dynamics_moves_obstacle(d):
    """a dynamic interval whose time function moves a rigid obstacle"""
    obs = [i["obstacle"] for i in d.get("interfaces", []) if "obstacle" in i]
    dyn = _dynamics(d)
    if not obs or dyn is None:
        return False
    d["patterns"]["quake"] = {"loads": [{"type": "obstacle_motion", "obstacle": obs[0],
                                         "dx": 1e-3}]}
    dyn.setdefault("loads", []).append({"pattern": "quake", "type": "pulse", "duration": 0.005})
    return True


def damped_bonded_joint_with_dynamics(d):
    """a bonded joint with a damped contact layer in a model with a dynamic interval"""
    itf = _first_interface(d)
    dyn = _dynamics(d)
    if itf is None or dyn is None:
        return False
    itf.pop("gap", None)
    itf["layer"] = {"kn": 1e12, "kt": 1e12, "damping": 1e6}
    itf["bond"] = {"tensile": 1e7, "shear": 1e7, "alpha": 0.7}
    return True


def top_dynamics_without_mass(d):
    """a top-level dynamic interval on bodies without density"""
    if d.get("stages") or _dynamics(d) is None:
        return False
    for m in _materials(d):
        m["density"] = 0.0
    for p in _patterns(d).values():
        p["loads"] = [ld for ld in p.get("loads", []) if ld.get("type") != "gravity"] or [
            {"type": "nodal", "nodes": next(iter(d["node_sets"])), "fy": -1e3}]
    return True


def residual_cohesion_with_dynamics(d):
    """a bond with a residual cohesion in a model with a dynamic interval"""
    dyn = d.get("dynamics") or next((s["dynamics"] for s in d.get("stages", [])
                                     if "dynamics" in s), None)
    itf = _first_interface(d)
    if dyn is None or itf is None:
        return False
    itf["bond"] = {"tensile": 1e5, "shear": 2e5, "alpha": 0.7, "residual_cohesion": 1e4}
    return True


def displacement_standing_before_dynamics(d):
    """a prescribed displacement at a nonzero factor when a stage's dynamic interval starts"""
    stages = d.get("stages") or []
    if not any("dynamics" in st for st in stages):
        return False
    ns = next(iter(d.get("node_sets") or {}), None)
    d["patterns"]["settle"] = {"loads": [{"type": "displacement", "nodes": ns, "dof": "x",
                                          "value": 1e-4}]}
    stages[0].setdefault("program", []).append({"pattern": "settle", "end": 1.0})
    return True


def last_stage_dynamics(d):
    """the dynamic interval on the last stage with a prescribed displacement standing"""
    stages = d.get("stages") or []
    k = next((k for k, s in enumerate(stages) if "dynamics" in s), None)
    if k is None or k == len(stages) - 1:
        return False
    dyn = stages[k].pop("dynamics")
    if not stages[k].get("program"):
        del stages[k]
    for st in stages:
        for seg in st.get("program", []):
            seg.pop("start", None)
    stages[-1]["dynamics"] = dyn
    ns = next(iter(d.get("node_sets") or {}), None)
    d["patterns"]["settle"] = {"loads": [{"type": "displacement", "nodes": ns, "dof": "x",
                                          "value": 1e-4}]}
    stages[0].setdefault("program", []).append({"pattern": "settle", "end": 1.0})
    stages[-1]["program"] = [{"pattern": "settle", "end": 2.0}]
    return True


def body_built_under_displacement(d):
    """a body built at a stage while a displacement of its nodes stands"""
    stages = d.get("stages") or []
    k = next((k for k, st in enumerate(stages) if st.get("bodies")), None)
    if k is None or k == 0:
        return False
    body = stages[k]["bodies"][0]
    ns = next(n for n, s in d["node_sets"].items() if s.get("body") == body)
    d["patterns"]["jack"] = {"loads": [{"type": "displacement", "nodes": ns, "dof": "x",
                                        "value": 1e-4}]}
    stages[0].setdefault("program", []).append({"pattern": "jack", "end": 1.0})
    return True


def grout_weaker_than_its_forces(d):
    """a joint grouted with a strength below the forces it carries (needs the solution)"""
    stages = d.get("stages") or []
    st = next((st for st in stages if st.get("grout")), None)
    if st is None:
        return False
    for name in st["grout"]:
        st["grout"][name] = {"tensile": 1.0, "shear": 1.0, "alpha": 0.0, "tension_alpha": 1.0}
    return True


def stage_dynamics_without_mass(d):
    """a stage's dynamic interval on bodies without density"""
    if not any("dynamics" in st for st in d.get("stages", [])):
        return False
    for m in _materials(d):
        m["density"] = 0.0
    for p in _patterns(d).values():
        p["loads"] = [ld for ld in p.get("loads", []) if ld.get("type") != "gravity"]
    return True


def stage_dynamics_on_first_stage_without_mass(d):
    """a dynamic interval on bodies without density, the weight kept by a nodal load"""
    if not any("dynamics" in st for st in d.get("stages", [])):
        return False
    for m in _materials(d):
        m["density"] = 0.0
    return True


def friction_negative(d):
    """a negative friction coefficient"""
    itf = _first_interface(d)
    if itf is None:
        return False
    itf["friction"] = -0.5
    return True


def zero_length_segment(d):
    """a program segment that ends where it starts"""
    segs = _segments(d)
    if not segs:
        return False
    segs[0]["start"] = 0.0
    segs[0]["end"] = 0.0
    return True


def segment_back_to_zero_first(d):
    """the first segment of a pattern is unloading from 0 (end = 0 on a pattern at 0)"""
    segs = _segments(d)
    if len(segs) < 2:
        return False
    segs[-1]["end"] = 0.0 if segs[-1].get("end", 1) != 0 else 1.0
    segs[-1].pop("start", None)
    return True


def gap_on_bonded_joint(d):
    """a bonded joint (grout or bond) with a gap"""
    itf = _first_interface(d)
    if itf is None:
        return False
    itf["gap"] = 0.01
    itf["bond"] = {"tensile": 1e5, "shear": 2e5, "alpha": 0.7}
    return True


def grout_open_obstacle(d):
    """grouting an interface against a rigid obstacle"""
    itfs = [i for i in d.get("interfaces", []) if "obstacle" in i]
    if not itfs or len(d.get("stages", [])) < 2:
        return False
    d["stages"][-1].setdefault("grout", {})[itfs[0]["name"]] = {
        "tensile": 1e5, "shear": 2e5, "alpha": 0.7}
    return True


def stage_builds_body_unsupported(d):
    """a body built at a stage with no interface to what stands"""
    if len(d.get("stages", [])) < 2 or not d.get("stages")[1].get("bodies"):
        return False
    d["stages"][1]["interfaces"] = []
    d["interfaces"] = [i for i in d["interfaces"]
                       if i["name"] not in ("lift joint",)]
    return True


def displacement_on_support(d):
    """a prescribed displacement on a supported degree of freedom"""
    sup = (d.get("supports") or [None])[0]
    if sup is None or not _patterns(d):
        return False
    name = next(iter(_patterns(d)))
    dof = "x" if "x" in sup.get("dofs", "xy") else "y"
    _patterns(d)[name].setdefault("loads", []).append(
        {"type": "displacement", "nodes": sup["nodes"], "dof": dof, "value": 0.01})
    return True


def uplift_on_obstacle(d):
    """uplift in a joint against a rigid obstacle"""
    itfs = [i for i in d.get("interfaces", []) if "obstacle" in i]
    if not itfs or not _patterns(d):
        return False
    name = next(iter(_patterns(d)))
    _patterns(d)[name]["loads"].append({"type": "uplift", "interface": itfs[0]["name"],
                                        "head": 2.0})
    return True


def crack_water_entry_outside(d):
    """crack water whose entry point is far outside the joint"""
    itf = _first_interface(d)
    if itf is None or not _patterns(d):
        return False
    name = next(iter(_patterns(d)))
    _patterns(d)[name]["loads"].append({"type": "crack_water", "interface": itf["name"],
                                        "level": 5.0, "entry": [-100.0, 0.0]})
    return True


def crack_water_negative_pressure(d):
    """crack water with a negative pressure"""
    itf = _first_interface(d)
    if itf is None or not _patterns(d):
        return False
    name = next(iter(_patterns(d)))
    _patterns(d)[name]["loads"].append({"type": "crack_water", "interface": itf["name"],
                                        "pressure": -1e4})
    return True


def crack_water_level_below(d):
    """crack water with its level below the joint"""
    itf = _first_interface(d)
    if itf is None or not _patterns(d):
        return False
    name = next(iter(_patterns(d)))
    _patterns(d)[name]["loads"].append({"type": "crack_water", "interface": itf["name"],
                                        "level": -50.0})
    return True


def level_pattern_with_rates(d):
    """a pattern whose factor is a water level, moved by a segment with rates"""
    segs = d.get("program")
    ns = next(iter(d.get("node_sets") or {}), None)
    if not segs or ns is None:
        return False
    d["patterns"]["reservoir"] = {"loads": [{"type": "water", "nodes": ns}]}
    segs.append({"pattern": "flood", "end": 1.0, "rates": {"reservoir": 1.0}})
    return True


def level_pattern_mixed(d):
    """a water load without a level mixed with a nodal load in one pattern"""
    ns = next(iter(d.get("node_sets") or {}), None)
    segs = _segments(d)
    if ns is None or not segs:
        return False
    pat = _patterns(d)[segs[-1]["pattern"]] if segs[-1]["pattern"] in _patterns(d) else None
    if pat is None:
        return False
    pat["loads"].append({"type": "water", "nodes": ns})
    return True


def dynamics_unknown_time(d):
    """a dynamic interval whose time function's pattern is applied by no load"""
    if "dynamics" not in d and not any("dynamics" in s for s in d.get("stages", [])):
        return False
    d["patterns"]["empty"] = {"loads": []}
    dyn = d.get("dynamics") or next(s["dynamics"] for s in d["stages"] if "dynamics" in s)
    dyn.setdefault("loads", []).append({"pattern": "empty", "type": "constant"})
    return True


def spring_on_supported(d):
    """a ground spring with zero stiffness in every direction"""
    ns = next(iter(d.get("node_sets") or {}), None)
    if ns is None:
        return False
    d.setdefault("springs", []).append({"name": "nothing", "a": ns})
    return True


def tie_to_itself(d):
    """a tie joining a node set to itself"""
    ns = next(iter(d.get("node_sets") or {}), None)
    if ns is None:
        return False
    d.setdefault("ties", []).append({"a": ns, "b": ns})
    return True


def interface_normal_reversed(d):
    """an interface normal that points into S− (from S+ to S−)"""
    itf = _first_interface(d)
    if itf is None:
        return False
    itf["normal"] = [0.0, -1.0]
    return True


def interface_on_the_same_body(d):
    """an interface between two node sets of the same body that share nodes"""
    sets = d.get("node_sets") or {}
    by_body: dict[str, list[str]] = {}
    for n, s in sets.items():
        if "body" in s:
            by_body.setdefault(s["body"], []).append(n)
    pair = next((v for v in by_body.values() if len(v) >= 2), None)
    if pair is None:
        return False
    d.setdefault("interfaces", []).append({"name": "self", "plus": pair[0], "minus": pair[1]})
    return True


def prescribed_rotation_on_continuum(d):
    """a prescribed rotation rz of continuum nodes (they have no rotation)"""
    ns = next(iter(d.get("node_sets") or {}), None)
    if ns is None or not _patterns(d):
        return False
    name = next(iter(_patterns(d)))
    _patterns(d)[name]["loads"].append({"type": "displacement", "nodes": ns, "dof": "rz",
                                        "value": 0.01})
    return True


def nodal_moment_on_continuum(d):
    """a nodal moment mz on continuum nodes (they have no rotation)"""
    ns = next(iter(d.get("node_sets") or {}), None)
    if ns is None or not _patterns(d):
        return False
    name = next(iter(_patterns(d)))
    _patterns(d)[name]["loads"].append({"type": "nodal", "nodes": ns, "mz": 1e3})
    return True


def support_rz_on_continuum(d):
    """a support holding rz of continuum nodes"""
    sup = (d.get("supports") or [None])[0]
    if sup is None:
        return False
    sup["dofs"] = "xyrz"
    return True


def gravity_on_massless(d):
    """gravity on bodies without density, the only load of the first segment"""
    if not _materials(d):
        return False
    for m in _materials(d):
        m["density"] = 0.0
    return True


def pressure_on_interior(d):
    """a pressure on a node set with no boundary edge (a single node)"""
    ns = next((n for n, s in (d.get("node_sets") or {}).items() if "body" in s), None)
    if ns is None or not _patterns(d):
        return False
    d["node_sets"]["one"] = {"body": d["node_sets"][ns]["body"], "index": [0]}
    name = next(iter(_patterns(d)))
    _patterns(d)[name]["loads"].append({"type": "pressure", "nodes": "one", "normal": 1e3})
    return True


def dynamics_dt_longer_than_duration(d):
    """a dynamic time step longer than the interval"""
    dyn = d.get("dynamics") or next((s["dynamics"] for s in d.get("stages", [])
                                     if "dynamics" in s), None)
    if dyn is None:
        return False
    dyn["dt"] = 10 * dyn["duration"]
    return True


def cycles_huge(d):
    """a cyclic program of 10⁹ cycles"""
    segs = _segments(d)
    if not segs:
        return False
    seg = segs[-1]
    seg.pop("end", None)
    seg.pop("start", None)
    seg["amplitude"] = 1.0
    seg["cycles"] = 1_000_000_000
    return True


def obstacle_side_wrong(d):
    """an obstacle whose bodies lie on the wrong side"""
    obs = d.get("obstacles")
    if not obs:
        return False
    obs[0]["side"] = "right"
    return True


def bond_tension_beyond_apex(d):
    """a Mohr–Coulomb tension cut-off beyond the apex c·cot φ"""
    itf = _first_interface(d)
    if itf is None:
        return False
    itf.pop("gap", None)
    itf["bond"] = {"cohesion": 1e5, "tensile_strength": 1e7, "friction_angle": 35.0}
    return True


MUTATIONS: dict[str, Mutation] = {f.__name__: f for f in (
    level_pattern_two_rates, dynamics_moves_level_pattern,
    dynamics_moves_prescribed_displacement, dynamics_moves_obstacle,
    damped_bonded_joint_with_dynamics, top_dynamics_without_mass,
    level_pattern_starts_high, residual_cohesion_with_dynamics,
    displacement_standing_before_dynamics, last_stage_dynamics, body_built_under_displacement,
    grout_weaker_than_its_forces,
    no_supports, stage_removes_every_support, stage_dynamics_without_mass,
    stage_dynamics_on_first_stage_without_mass, friction_negative, zero_length_segment,
    segment_back_to_zero_first, gap_on_bonded_joint, grout_open_obstacle,
    stage_builds_body_unsupported, displacement_on_support, uplift_on_obstacle,
    crack_water_entry_outside, crack_water_negative_pressure, crack_water_level_below,
    level_pattern_with_rates, level_pattern_mixed, dynamics_unknown_time, spring_on_supported,
    tie_to_itself, interface_normal_reversed, interface_on_the_same_body,
    prescribed_rotation_on_continuum, nodal_moment_on_continuum, support_rz_on_continuum,
    gravity_on_massless, pressure_on_interior, dynamics_dt_longer_than_duration, cycles_huge,
    obstacle_side_wrong, bond_tension_beyond_apex,
)}


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v) if v == v and abs(v) != float("inf") else str(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{json.dumps(k)} = {_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def dump(d: dict) -> str:
    """The model dict as TOML: every top-level value inline (TOML allows inline tables and
    arrays of inline tables anywhere)."""
    return "\n".join(f"{json.dumps(k)} = {_value(v)}" for k, v in d.items()) + "\n"


def mutated(model: str, mutation: str) -> dict | None:
    """The model's dict changed by the mutation (None: it does not apply)."""
    d = tomllib.loads(MODELS[model].read_text(encoding="utf-8"))
    d = copy.deepcopy(d)
    return d if MUTATIONS[mutation](d) else None


def write_case(model: str, mutation: str, folder: Path) -> Path | None:
    d = mutated(model, mutation)
    if d is None:
        return None
    mesh = (d.get("mesh") or {}).get("file")
    if mesh is not None:
        d["mesh"]["file"] = str((MODELS[model].parent / mesh).resolve())
    path = folder / f"{model}-{mutation}.toml"
    path.write_text(dump(d), encoding="utf-8")
    return path


class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout


def invoke(args: list[str], timeout: int = 60) -> tuple[int | str, str]:
    """Exit code (or "traceback"/"timeout") and the last stderr line of a CLI call."""
    from typer.testing import CliRunner

    from stepcontact.cli import app

    signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(timeout)
    try:
        result = CliRunner().invoke(app, args)
    except _Timeout:
        return "timeout", ""
    finally:
        signal.alarm(0)
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        if isinstance(result.exception, _Timeout):
            return "timeout", ""
        return "traceback", f"{type(result.exception).__name__}: {result.exception}"
    lines = [ln for ln in result.stderr.splitlines() if ln.startswith("error")]
    return result.exit_code, (lines[-1] if lines else "")


def check(model: str, mutation: str, folder: Path) -> dict | None:
    path = write_case(model, mutation, folder)
    if path is None:
        return None
    v_code, v_msg = invoke(["validate", str(path)])
    r_code, r_msg = invoke(["run", str(path), "--no-plot", "-q", "-o",
                            str(folder / f"{path.stem}.nc")])
    return {"model": model, "mutation": mutation, "validate": v_code, "run": r_code,
            "validate_error": v_msg, "run_error": r_msg,
            "gap": (v_code == 0 and r_code == 2)
            or bool({"traceback", "timeout"} & {v_code, r_code})}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--all", action="store_true", help="list every case")
    ap.add_argument("--json", type=Path, help="write the cases as JSON")
    ap.add_argument("--model", action="append", help="only these models")
    ap.add_argument("--mutation", action="append", help="only these mutations")
    args = ap.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for model in args.model or MODELS:
            for mutation in args.mutation or MUTATIONS:
                row = check(model, mutation, Path(tmp))
                if row is None:
                    continue
                rows.append(row)
                if row["gap"] or args.all:
                    print(f"{'GAP ' if row['gap'] else 'ok  '}{model:13s} {mutation:42s} "
                          f"validate={row['validate']!s:9s} run={row['run']!s:9s} "
                          f"{row['run_error'] or row['validate_error']}"[:400], flush=True)
    gaps = [r for r in rows if r["gap"]]
    print(f"{len(rows)} cases, {len(gaps)} where validate passes and run rejects "
          "(or a traceback)")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1), encoding="utf-8")
    return 1 if gaps else 0


if __name__ == "__main__":
    sys.exit(main())
