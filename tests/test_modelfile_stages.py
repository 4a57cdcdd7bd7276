"""Construction stages in the TOML model file (``[[stages]]``, issue 12).

References: the same models built in Python with :class:`stepcontact.Stage` (the models of
``tests/test_stages.py``, themselves checked there against closed forms and superposition).
A file and its Python twin assemble the same system (same bodies, node order, CFEs), so the
runs must agree to round-off: the same segments, stages and events, and the same final
displacements and contact forces to 1e-12 (relative to the largest value).

Bad stages give one :class:`~stepcontact.errors.ModelError` whose item is the field path in the
file (``stages[1].bodies``) and whose message names the offending name; through the command
line, one ``error: ...`` line and exit code 2.
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import stepcontact as sc
from cli_checks import assert_one_line_error
from stepcontact.cli import app
from stepcontact.enums import Status
from stepcontact.errors import ModelError
from stepcontact.io.modelfile import model_from_dict, validate_model_file
from test_stages import RHO, G, _block_on_base, _pull_model, _wall

runner = CliRunner()
BONDED = int(sc.ContactState.BONDED)

MATERIAL = """
[materials.concrete]
E = 30e9
nu = 0.2
density = 2400
"""

#: the wall of test_stages: a lower half (4 m) and an upper half (3 m) joined at y = 4 m
WALL = MATERIAL + """
[model]
name = "wall"

[[bodies]]
name = "lower"
corner0 = [0.0, 0.0]
corner1 = [2.0, 4.0]
nx = 2
ny = 4
element = "quad8"
material = "concrete"

[[bodies]]
name = "upper"
corner0 = [0.0, 4.0]
corner1 = [2.0, 7.0]
nx = 2
ny = 3
element = "quad8"
material = "concrete"

[node_sets.lower_base]
body = "lower"
y = 0.0

[node_sets.lower_corner]
body = "lower"
where = { xmax = 0.0, ymax = 0.0 }

[node_sets.lower_top]
body = "lower"
y = 4.0

[node_sets.upper_bottom]
body = "upper"
y = 4.0

[[supports]]
name = "base"
nodes = "lower_base"
dofs = "y"

[[supports]]
name = "corner"
nodes = "lower_corner"
dofs = "x"

[[interfaces]]
name = "joint"
plus = "upper_bottom"
minus = "lower_top"
friction = 0.6

[patterns.weight]
loads = [{ type = "gravity" }]

[[stages]]
name = "first"

[[stages.program]]
pattern = "weight"
end = 1.0

[[stages]]
name = "second"
bodies = ["upper"]
interfaces = ["joint"]
"""

#: the block of test_stages on a rigid base, a side support and (optionally) a prop
BLOCK = MATERIAL + """
[[bodies]]
name = "block"
corner0 = [0.0, 0.0]
corner1 = [2.0, 1.0]
nx = 8
ny = 4
material = "concrete"

[node_sets.bottom]
body = "block"
y = 0.0

[node_sets.top]
body = "block"
y = 1.0

[node_sets.side]
body = "block"
where = { xmax = 0.0, ymin = 0.5, ymax = 0.5 }

[node_sets.prop_node]
body = "block"
where = { xmax = 0.0, ymin = 1.0 }

[[obstacles]]
name = "ground"
points = [[-1.0, 0.0], [3.0, 0.0]]

[[interfaces]]
name = "base"
plus = "bottom"
obstacle = "ground"
friction = FRICTION

[[supports]]
name = "left"
nodes = "side"
dofs = "x"

[patterns.weight]
loads = [{ type = "gravity" }]
"""

PROPPED = BLOCK.replace("FRICTION", "0.0") + """
[[supports]]
name = "prop"
nodes = "prop_node"
dofs = "y"

[[stages]]
name = "props"

[[stages.program]]
pattern = "weight"
end = 1.0

[[stages]]
name = "unprop"
remove_supports = ["prop"]
"""

PULL = 2.0 * RHO * G * 2.0 * 1.0  # twice the block's weight, N
GROUTED = BLOCK.replace("FRICTION", "0.6") + f"""
[patterns.pull]
loads = [{{ type = "edge_force", nodes = "top", fy = {PULL!r} }}]

[[stages]]
name = "placed"

[[stages.program]]
pattern = "weight"
end = 1.0

[[stages]]
name = "grouted"
grout.base = {{ cohesion = 1e6, tensile_strength = 1e6, friction_angle = 35.0 }}

[[stages.program]]
pattern = "pull"
end = 1.0
"""


def _load(text: str) -> sc.Model:
    return model_from_dict(tomllib.loads(text))


def _assert_same_run(a, b) -> None:
    """Two runs of the same staged model: same segments, stages and events; same final
    displacements and contact forces to 1e-12 of the largest value."""
    assert a.status == b.status == Status.COMPLETED, (a.message, b.message)
    assert a.segments == b.segments
    assert a.stage_names == b.stage_names
    assert np.array_equal(a.stage, b.stage) and np.array_equal(a.stage_cfes, b.stage_cfes)
    assert [(e.segment, e.cfe, e.transition) for e in a.events] == [
        (e.segment, e.cfe, e.transition) for e in b.events]
    lam = np.array([e.lam for e in b.events])
    np.testing.assert_allclose([e.lam for e in a.events], lam, rtol=0,
                               atol=1e-12 * max(1.0, np.abs(lam).max(initial=0.0)))
    ua, ub = a.displacement(len(a.lam) - 1), b.displacement(len(b.lam) - 1)
    assert np.abs(ua - ub).max() <= 1e-12 * np.abs(ub).max()
    scale = np.abs(b.N).max()
    assert np.abs(a.N - b.N).max() <= 1e-12 * scale
    assert np.abs(a.Q - b.Q).max() <= 1e-12 * scale
    assert np.array_equal(a.state, b.state)


def test_a_wall_built_in_two_stages_from_the_file_is_the_python_model():
    model = _load(WALL)
    assert [st.name for st in model.stages] == ["first", "second"]
    assert model.program == ()
    weight = sc.LoadPattern("weight", [sc.BodyForce()])
    python = _wall().add(weight, sc.Stage("first", [sc.Segment("weight", 1.0)]),
                         sc.Stage("second", bodies=("upper",), interfaces=("joint",)))
    res, ref = sc.solve_static(model), sc.solve_static(python)
    _assert_same_run(res, ref)
    assert res.segments[-1] == ("second: loads on upper", 1.0, 0.0)
    # the joint then carries the upper half's weight
    assert np.sum(res.N[-1]) == pytest.approx(-RHO * G * 2.0 * 3.0, rel=1e-9)


def test_a_prop_removed_by_a_stage_of_the_file_is_the_python_model():
    res = sc.solve_static(_load(PROPPED))
    ref = sc.solve_static(_block_on_base().add(
        sc.Stage("props", [sc.Segment("weight", 1.0)]),
        sc.Stage("unprop", remove_supports=("prop",))))
    _assert_same_run(res, ref)
    assert res.segments[-1] == ("unprop: release prop", 1.0, 0.0)
    assert res.reactions[-1, res.reaction_labels.index("prop:y")] == 0.0


def test_a_joint_grouted_by_a_stage_of_the_file_is_the_python_model():
    model = _load(GROUTED)
    bond = model.stages[1].grout["base"]
    assert isinstance(bond, sc.Bond)
    res, ref = sc.solve_static(model), sc.solve_static(_pull_model(grout=True))
    _assert_same_run(res, ref)
    assert np.all(res.state[-1] == BONDED)
    assert res.N[-1].max() > 0  # the grouted joint carries tension


def test_a_cyclic_push_after_the_stages_gives_the_events_of_the_python_model():
    """Three stages (placed on props, props removed, a cyclic push at the top): the contact
    slips, opens and closes; the file's run has the Python model's events."""
    weight = RHO * G * 2.0 * 1.0
    d = tomllib.loads(PROPPED.replace("friction = 0.0", "friction = 0.6"))
    d["patterns"]["push"] = {"loads": [{"type": "edge_force", "nodes": "top", "fx": 1.0}]}
    d["stages"].append({"name": "cycles", "program": [
        {"pattern": "push", "amplitude": 0.5 * weight, "cycles": 1}]})
    model = model_from_dict(d)
    assert model.stages[2].program == sc.cycles("push", 0.5 * weight, 1)
    python = _block_on_base(friction=0.6)
    top = python.select("block", y=1.0, name="top")
    python = python.add(sc.LoadPattern("push", [sc.EdgeForce(top, fx=1.0)]),
                        sc.Stage("props", [sc.Segment("weight", 1.0)]),
                        sc.Stage("unprop", remove_supports=("prop",)),
                        sc.Stage("cycles", sc.cycles("push", 0.5 * weight, 1)))
    res, ref = sc.solve_static(model), sc.solve_static(python)
    _assert_same_run(res, ref)
    kinds = {e.transition for e in res.events}
    assert len(res.events) >= 5 and {sc.Transition.OPENED, sc.Transition.CLOSED} <= kinds
    assert {res.stage[e.state] for e in res.events} == {2}  # all in the push stage


def _wall_dict() -> dict:
    return tomllib.loads(WALL)


def _set(path: list, value):
    def mutate(d):
        for key in path[:-1]:
            d = d[key]
        d[path[-1]] = value
    return mutate


def _add_stage(**stage):
    def mutate(d):
        d["stages"].append(stage)
    return mutate


BAD_STAGES = {
    "unknown body": (_set(["stages", 1, "bodies"], ["upper", "uper"]), "stages[1].bodies",
                     "no such body 'uper' (known: 'lower', 'upper')"),
    "unknown interface": (_set(["stages", 1, "interfaces"], ["jiont"]), "stages[1].interfaces",
                          "no such interface 'jiont' (known: 'joint')"),
    "unknown contact": (_set(["stages", 1, "contacts"], ["gap"]), "stages[1].contacts",
                        "no such interface 'gap'"),
    "unknown support": (_set(["stages", 1, "remove_supports"], ["prop"]),
                        "stages[1].remove_supports", "no such support 'prop' (known: 'base', "
                        "'corner')"),
    "body listed by two stages": (
        _add_stage(name="third", bodies=["upper"], program=[{"pattern": "weight", "end": 2.0}]),
        "stages[2].bodies", "body 'upper' is already listed by stages[1] ('second')"),
    "interface listed by two stages": (
        _add_stage(name="third", contacts=["joint"], program=[{"pattern": "weight", "end": 2.0}]),
        "stages[2].contacts", "interface 'joint' is already listed by stages[1]"),
    "interface made at once and a contact": (
        _set(["stages", 1, "contacts"], ["joint"]), "stages[1].contacts",
        "interface 'joint' is listed in interfaces too"),
    "body listed twice by a stage": (_set(["stages", 1, "bodies"], ["upper", "upper"]),
                                     "stages[1].bodies", "lists body 'upper' twice"),
    "duplicate stage names": (_set(["stages", 1, "name"], "first"), "stages[1].name",
                              "duplicate stage name 'first'"),
    "grout of an unknown interface": (
        _set(["stages", 1, "grout"], {"jont": {"tensile": 1e5, "shear": 1e5, "alpha": 0.7}}),
        "stages[1].grout", "no such interface 'jont' (known: 'joint')"),
    "grout by the first stage": (
        _set(["stages", 0, "grout"], {"joint": {"tensile": 1e5, "shear": 1e5, "alpha": 0.7}}),
        "stages[0].grout", "the first stage cannot grout interface 'joint'"),
    "incomplete grout bond": (_set(["stages", 1, "grout"], {"joint": {"tensile": 1e5}}),
                              "stages[1].grout.joint", "give {tensile, shear, alpha}"),
    "negative grout strength": (
        _set(["stages", 1, "grout"], {"joint": {"tensile": -1e5, "shear": 1e5, "alpha": 0.7}}),
        'stages[1].grout.joint', "gives a tensile strength of -100000 Pa: a strength must be "
        "≥ 0"),
    "unknown field of a stage": (_set(["stages", 1, "build"], ["upper"]), "stages[1].build",
                                 "unknown field"),
    "top-level program with stages": (
        _set(["program"], [{"pattern": "weight", "end": 1.0}]), "program",
        "move these segments into the [[stages.program]] of the first stage"),
    "no program at all": (_set(["stages"], []), "program", "required field is missing"),
    "unknown pattern in a stage program": (_set(["stages", 0, "program", 0, "pattern"], "wind"),
                                           "stages[0].program[0].pattern",
                                           "unknown load pattern 'wind'"),
    "stage programs do not chain": (
        _add_stage(name="third", program=[{"pattern": "weight", "start": 0.0, "end": 2.0}]),
        "stages[2].program[0].start", "pattern 'weight' stands at λ = 1"),
    "a later stage without a segment": (_add_stage(name="third", contacts=[]),
                                        "stages[2].program",
                                        "stage 'third' has no load segment"),
    "support removed by the first stage": (_set(["stages", 0, "remove_supports"], ["corner"]),
                                           "stages[0].remove_supports",
                                           "support 'corner' is removed before or when it is "
                                           "placed (in place from the start)"),
    "support placed and removed by a stage": (
        lambda d: d["stages"][1].update(supports=["corner"], remove_supports=["corner"]),
        "stages[1].remove_supports", "support 'corner' is removed before or when it is placed "
        "(placed by stages[1] ('second'))"),
}


@pytest.mark.parametrize("case", list(BAD_STAGES))
def test_a_bad_stage_names_its_field_and_the_offending_name(case):
    mutate, item, fragment = BAD_STAGES[case]
    d = _wall_dict()
    mutate(d)
    with pytest.raises(ModelError) as info:
        model_from_dict(d)
    assert info.value.item == item, str(info.value)
    assert fragment in info.value.problem, info.value.problem
    assert "\n" not in str(info.value)


def test_grouting_an_interface_made_by_a_later_stage_is_an_error():
    d = _wall_dict()
    d["stages"][1]["interfaces"] = []
    d["stages"][1]["grout"] = {"joint": {"tensile": 1e5, "shear": 1e5, "alpha": 0.7}}
    d["stages"].append({"name": "third", "interfaces": ["joint"],
                        "program": [{"pattern": "weight", "end": 2.0}]})
    with pytest.raises(ModelError) as info:
        model_from_dict(d)
    assert info.value.item == "stages[1].grout"
    assert "interface 'joint' is made later, by stages[2] ('third')" in info.value.problem


def test_every_stage_problem_is_listed_at_once():
    d = _wall_dict()
    d["stages"][1]["bodies"] = ["uper"]
    d["stages"][1]["remove_supports"] = ["prop"]
    with pytest.raises(ModelError) as info:
        model_from_dict(d)
    assert [p for p, _ in info.value.errors] == ["stages[1].bodies",
                                                 "stages[1].remove_supports"]


def test_validate_reports_what_the_solver_checks_of_the_stages(tmp_path):
    """The upper half built at stage 2, its joint (not listed) would act from the start:
    ``validate`` says so without solving."""
    path = tmp_path / "wall.toml"
    path.write_text(WALL.replace('interfaces = ["joint"]\n', ""), encoding="utf-8")
    problems = validate_model_file(path)
    assert [p.item for p in problems] == ["interface 'joint'"]
    assert "body 'upper' is built later" in problems[0].message
    path.write_text(WALL, encoding="utf-8")
    assert validate_model_file(path) == []
    # a grout strength varying along the joint, negative at one end: found at its CFEs
    grout = ('grout.joint = { tensile = { from = [0.0, 4.0, -1e5], to = [2.0, 4.0, 1e5] }, '
             'shear = 1e5, alpha = 0.7 }\n')
    path.write_text(WALL + '\n[[stages]]\nname = "grouted"\n' + grout
                    + '[[stages.program]]\npattern = "weight"\nend = 2.0\n', encoding="utf-8")
    problems = validate_model_file(path)
    assert [p.item for p in problems] == ["stage 'grouted'.grout['joint'].bond.tensile"]
    assert "gives -100000.0 Pa at CFE 0 (0, 4)" in problems[0].message


def test_the_command_line_runs_a_staged_model_file(tmp_path):
    path = tmp_path / "wall.toml"
    path.write_text(WALL, encoding="utf-8")
    out = tmp_path / "wall.nc"
    result = runner.invoke(app, ["run", str(path), "--no-plot", "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert "segment 1 ('second: loads on upper') in stage 'second'" in result.stdout
    with xr.open_dataset(out) as ds:
        assert "stage" in ds and ds["stage"].dims == ("state",)
    back = sc.load_result(out)
    assert back.stage_names == ("first", "second")
    assert back.stage.tolist() == [0, 0, 1, 1]
    assert back.active_bodies(0) == {"lower"} and back.active_bodies(3) == {"lower", "upper"}
    result = runner.invoke(app, ["validate", str(path)])
    assert result.exit_code == 0 and "in 2 stages" in result.stdout


def test_the_command_line_runs_a_dynamic_interval_after_the_stages(tmp_path):
    """[dynamics] in a staged file runs after the last stage, from its static state: the
    wall stands at rest (no dynamic load: velocities stay at round-off), and the dynamic
    result file keeps the stages."""
    path = tmp_path / "wall.toml"
    path.write_text(WALL + '\n[dynamics]\ndt = 1e-4\nduration = 2e-3\nmass = "lumped"\n',
                    encoding="utf-8")
    out = tmp_path / "wall.nc"
    result = runner.invoke(app, ["run", str(path), "--no-plot", "-o", str(out)])
    assert result.exit_code == 0, result.output
    dyn = sc.load_result(tmp_path / "wall-dynamic.nc")
    assert dyn.stage_names == ("first", "second")
    assert np.all(dyn.stage == 1)
    assert dyn.active_bodies(len(dyn.lam) - 1) == {"lower", "upper"}
    static = sc.load_result(out)
    n = len(static.lam) - 1
    u0, u1 = static.displacement(n), dyn.displacement(len(dyn.lam) - 1)
    assert np.abs(u1 - u0).max() <= 1e-9 * np.abs(u0).max()


@pytest.mark.parametrize("text, fragment", [
    (WALL.replace('bodies = ["upper"]', 'bodies = ["uper"]'),
     "stages[1].bodies: no such body 'uper'"),
    (WALL.replace('interfaces = ["joint"]\n', ""), "interface 'joint': acts from stage 'first' "
     "but body 'upper' is built later"),
])
def test_a_bad_staged_model_file_is_a_one_line_error(tmp_path, text, fragment):
    path = tmp_path / "wall.toml"
    path.write_text(text, encoding="utf-8")
    result = runner.invoke(app, ["run", str(path), "--no-plot"])
    assert_one_line_error(result, fragment)
    assert not (tmp_path / "wall.nc").exists()


def test_the_progress_bar_follows_the_program_as_run_with_the_automatic_segments():
    """The command line's progress hook learns the staged program as the solver runs it (the
    model's own segments lack the automatic ones): one unit of the bar per segment."""
    from rich.progress import Progress

    from stepcontact.cli import ProgressHook

    model = model_from_dict(_wall_dict())
    with Progress(disable=True) as progress:
        task = progress.add_task("run", total=1)
        hook = ProgressHook(progress, task, model.segments_resolved())
        assert len(hook.segments) == 1  # the model's own segments only
        res = sc.solve_static(model, hooks=(hook,))
        assert hook.segments == [tuple(s) for s in res.segments]
        assert hook.segments[1][0] == "second: loads on upper"
        assert progress.tasks[0].total == len(res.segments) == hook.done == 2
