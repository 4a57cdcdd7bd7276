"""Model files (TOML -> Model), their error messages, the demo models and the CLI.

The CLI tests replace the solver, the result writer and the plotter by fakes, so they check
the command line itself (arguments, output, files, exit codes); end-to-end runs live with the
solver's tests.
"""

from __future__ import annotations

import copy
import json
import math
import tomllib
from importlib.resources import files
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose
from typer.testing import CliRunner

import stepcontact
from cli_checks import assert_one_line_error
from stepcontact import (
    BodyForce,
    EdgeLoad,
    Frame,
    ModelError,
    NodalLoad,
    PrescribedDisplacement,
    SolverError,
)
from stepcontact.cli import ProgressHook, app, events_table, result_summary
from stepcontact.demo import demo_model, demo_text, demo_uplift_model
from stepcontact.enums import ContactState, Status, Transition
from stepcontact.io.modelfile import load_model, model_from_dict, schema
from stepcontact.results.result import Event, Multipliers, StaticResult

DEMO = files("stepcontact") / "data" / "demo.toml"


def demo_dict() -> dict:
    return tomllib.loads(DEMO.read_text(encoding="utf-8"))


FULL = """
[model]
name = "full"
plane = "stress"
thickness = 0.5

[materials.steel]
E = 210e9
nu = 0.3
density = 7850

[[bodies]]
name = "base"
corner0 = [0.0, -1.0]
corner1 = [4.0, 0.0]
nx = 8
ny = 2
element = "tri3"
grading = [1.0, 1.5]
material = { E = 1e9, nu = 0.25 }

[[bodies]]
name = "plate"
kind = "rectangle"
corner0 = [1.0, 0.0]
corner1 = [3.0, 0.5]
nx = 4
ny = 1
element = "quad8"
material = "steel"

[[frames]]
name = "beam"
start = [1.0, 0.5]
end = [3.0, 0.5]
n = 4
E = 210e9
A = 1e-2
I = 1e-4

[node_sets.bottom]
body = "base"
y = -1.0

[node_sets.base_top]
body = "base"
y = 0.0
where = { xmin = 0.5, xmax = 3.5 }

[node_sets.plate_bottom]
body = "plate"
y = 0.0

[node_sets.plate_top_ends]
body = "plate"
y = 0.5
where = { xmax = 1.0 }

[node_sets.beam_start]
body = "beam"
index = [0]

[node_sets.plate_left]
body = "plate"
x = 1.0
boundary = true

[[supports]]
name = "fixed"
nodes = "bottom"
dofs = "xy"

[[ties]]
a = "beam_start"
b = "plate_top_ends"

[[springs]]
name = "ground"
a = "beam_start"
kx = 1e6

[[interfaces]]
name = "joint"
plus = "plate_bottom"
minus = "base_top"
friction = 0.4
gap = 0.0
normal = [0.0, 1.0]
layer = { thickness = 0.01, E = 1e9, nu = 0.2 }

[patterns.weight]
loads = [{ type = "gravity", bodies = ["plate", "beam"] }]

[patterns.side]
loads = [
    { type = "pressure", nodes = "plate_left", normal = [1e4, 2e4], tangential = -5e3 },
    { type = "nodal", nodes = "beam_start", fx = 1e3, mz = 10.0 },
    { type = "displacement", nodes = "beam_start", dof = "rz", value = 1e-4 },
]

[[program]]
pattern = "weight"
end = 1.0

[[program]]
pattern = "side"
end = 2.0

[[program]]
pattern = "side"
start = 2.0
end = 0.0
"""


# --------------------------------------------------------------------------------------------
# model files
# --------------------------------------------------------------------------------------------
def test_demo_file_round_trips_to_a_model():
    model = load_model(DEMO)
    assert model.name == "block-slide"
    assert [b.name for b in model.bodies] == ["foundation", "block"]
    assert [b.n_nodes for b in model.bodies] == [19 * 7, 11 * 6]
    assert [i.name for i in model.interfaces] == ["joint"]
    assert model.interfaces[0].friction == 0.6
    assert len(model.interfaces[0].plus) == 11
    assert len(model.interfaces[0].minus) == 19
    assert [(s.pattern, s.start, s.end) for s in model.program] == [
        ("weight", None, 1.0),
        ("push", None, 5.0),
    ]
    assert model.segments_resolved() == [("weight", 0.0, 1.0), ("push", 0.0, 5.0)]
    assert model.supports[0].dofs == ("x", "y")
    (weight,) = model.pattern("weight").loads
    assert isinstance(weight, BodyForce) and weight.bodies == ("block",)
    (push,) = model.pattern("push").loads
    assert isinstance(push, EdgeLoad) and push.normal == 1.0e4
    assert_allclose(model.body("block").points[push.nodes.index, 0], 0.0, atol=1e-12)


def test_full_file_covers_every_section():
    with pytest.warns(FutureWarning, match="a pair \\[start, end\\] varies along the node set"):
        model = model_from_dict(tomllib.loads(FULL))  # the pair [1e4, 2e4] is deprecated
    assert (model.name, model.plane, model.thickness) == ("full", "stress", 0.5)
    base, plate, beam = model.bodies
    assert base.element == "tri3" and base.material.E == 1e9 and base.material.density == 0.0
    assert plate.element == "quad8" and plate.material.density == 7850
    assert isinstance(beam, Frame) and beam.n_nodes == 5
    # graded mesh: cell heights grow by 1.5 from bottom to top
    ys = np.unique(base.points[:, 1])
    assert_allclose(np.diff(ys)[1] / np.diff(ys)[0], 1.5)
    top = model.interfaces[0].minus
    assert_allclose(np.sort(base.points[top.index, 0]), [0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5])
    itf = model.interfaces[0]
    assert (itf.friction, itf.gap, itf.normal) == (0.4, 0.0, (0.0, 1.0))
    assert itf.layer is not None and itf.layer.thickness == 0.01 and itf.layer.nu == 0.2
    assert len(model.ties) == 1 and len(model.ties[0].a) == 1 == len(model.ties[0].b)
    assert model.springs[0].b is None and model.springs[0].kx == 1e6
    press, nodal, disp = model.pattern("side").loads
    assert isinstance(press, EdgeLoad) and press.normal == (1e4, 2e4)
    assert press.tangential == -5e3
    assert isinstance(nodal, NodalLoad) and (nodal.fx, nodal.fy, nodal.mz) == (1e3, 0.0, 10.0)
    assert isinstance(disp, PrescribedDisplacement) and (disp.dof, disp.value) == ("rz", 1e-4)
    assert model.pattern("weight").loads[0].g == (0.0, -9.81)
    assert model.segments_resolved()[2] == ("side", 2.0, 0.0)


def test_model_name_defaults_to_file_stem(tmp_path):
    d = demo_dict()
    text = DEMO.read_text(encoding="utf-8").replace('name = "block-slide"\n', "")
    path = tmp_path / "my_dam.toml"
    path.write_text(text, encoding="utf-8")
    assert "name" in d["model"]
    assert load_model(path).name == "my_dam"


def _set(path: list, value):
    """Mutation setting d[path...] = value."""

    def mutate(d):
        for key in path[:-1]:
            d = d[key]
        d[path[-1]] = value

    return mutate


def _drop(path: list):
    def mutate(d):
        for key in path[:-1]:
            d = d[key]
        del d[path[-1]]

    return mutate


def _append_segment(d):
    d["program"].append({"pattern": "push", "start": 0.0, "end": 1.0})


ERROR_CASES = {
    "unknown material": (
        _set(["bodies", 1, "material"], "steel"), "bodies[1].material", "unknown material 'steel'"
    ),
    "inline material E": (
        _set(["bodies", 1, "material"], {"E": -1.0, "nu": 0.2}), "bodies[1].material.E",
        "greater than 0",
    ),
    "unknown node set": (
        _set(["interfaces", 0, "plus"], "nope"), "interfaces[0].plus", "unknown node set 'nope'"
    ),
    "unknown node set in a load": (
        _set(["patterns", "push", "loads", 0, "nodes"], "left"), "patterns.push.loads[0].nodes",
        "unknown node set 'left'",
    ),
    "NaN pressure": (
        _set(["patterns", "push", "loads", 0, "normal"], math.nan),
        "patterns.push.loads[0].normal", "finite",
    ),
    "inf in a pressure pair": (
        _set(["patterns", "push", "loads", 0, "normal"], [0.0, math.inf]),
        "patterns.push.loads[0].normal", "finite",
    ),
    "NaN gravity": (
        _set(["patterns", "weight", "loads", 0, "g"], [0.0, math.nan]),
        "patterns.weight.loads[0].g[1]", "finite",
    ),
    "negative friction": (
        _set(["interfaces", 0, "friction"], -0.1), "interfaces[0].friction",
        "must be greater than or equal to 0 (got -0.1)",
    ),
    "segments do not chain": (_append_segment, "program[2].start", "do not chain"),
    "unknown pattern": (
        _set(["program", 1, "pattern"], "wind"), "program[1].pattern", "unknown load pattern"
    ),
    "missing field": (_drop(["bodies", 0, "nx"]), "bodies[0].nx", "required field is missing"),
    "missing program": (_drop(["program"]), "program", "required field is missing"),
    "extra field": (_set(["bodies", 0, "colour"], "red"), "bodies[0].colour", "unknown field"),
    "extra section": (_set(["loads"], {}), "loads", "unknown field"),
    "unknown body of a node set": (
        _set(["node_sets", "block_left", "body"], "blok"), "node_sets.block_left.body",
        "unknown body 'blok'",
    ),
    "empty node set": (
        _set(["node_sets", "block_left", "x"], 9.0), "node_sets.block_left", "selects no node"
    ),
    "bad plane": (_set(["model", "plane"], "strian"), "model.plane", "'strain' or 'stress'"),
    "bad dofs": (_set(["supports", 0, "dofs"], "xz"), "supports[0].dofs", "degree of freedom"),
    "bad load type": (
        _set(["patterns", "push", "loads", 0, "type"], "wind"), "patterns.push.loads[0]",
        "type must be",
    ),
    "half a layer": (
        _set(["interfaces", 0, "layer"], {"kn": 1e9}), "interfaces[0].layer", "kn and kt"
    ),
    "mesh file in a body": (
        _set(["bodies", 0, "mesh"], "dam.msh"), "bodies[0].mesh", "in the [mesh] section"
    ),
    "unknown gravity body": (
        _set(["patterns", "weight", "loads", 0, "bodies"], ["blok"]),
        "patterns.weight.loads[0].bodies", "unknown body 'blok'",
    ),
    "pressure not a number": (
        _set(["patterns", "push", "loads", 0, "normal"], "big"),
        "patterns.push.loads[0].normal", "a number (Pa) or a pair",
    ),
    "duplicate interface": (
        lambda d: d["interfaces"].append(copy.deepcopy(d["interfaces"][0])),
        "interfaces[1].name", "duplicate interface name",
    ),
}


@pytest.mark.parametrize("case", list(ERROR_CASES))
def test_errors_name_the_field(case):
    mutate, item, fragment = ERROR_CASES[case]
    d = demo_dict()
    mutate(d)
    with pytest.raises(ModelError) as info:
        model_from_dict(d)
    assert info.value.item == item
    assert fragment in info.value.problem
    assert str(info.value).startswith(f"{item}: ")
    assert "\n" not in str(info.value)


def test_several_errors_are_collected_into_one():
    d = demo_dict()
    d["bodies"][0]["nx"] = 0
    d["interfaces"][0]["friction"] = -1.0
    d["model"]["thickness"] = math.inf
    with pytest.raises(ModelError) as info:
        model_from_dict(d)
    paths = [p for p, _ in info.value.errors]
    assert paths == ["model.thickness", "bodies[0].nx", "interfaces[0].friction"]
    assert info.value.item == "model.thickness"
    for p in paths[1:]:
        assert p in str(info.value)


def test_toml_errors_and_missing_files(tmp_path):
    broken = tmp_path / "broken.toml"
    broken.write_text("[model\nname = 1\n", encoding="utf-8")
    with pytest.raises(ModelError, match="not a valid TOML file") as info:
        load_model(broken)
    assert info.value.item == str(broken)
    with pytest.raises(FileNotFoundError):
        load_model(tmp_path / "missing.toml")


def test_schema_is_json():
    s = schema()
    assert s["type"] == "object"
    assert {"model", "materials", "bodies", "interfaces", "patterns", "program"} <= set(
        s["properties"]
    )
    # a load program is required: top-level segments, or construction stages with theirs
    assert {"required": ["program"]} in s["anyOf"] and {"required": ["stages"]} in s["anyOf"]
    json.dumps(s)


def test_demo_models():
    slide, uplift = demo_model(), demo_uplift_model()
    assert [p.name for p in slide.patterns] == ["weight", "push"]
    assert [p.name for p in uplift.patterns] == ["weight", "uplift"]
    assert [s.pattern for s in uplift.program] == ["weight", "uplift"]
    for model in (slide, uplift):
        ndof = 2 * sum(b.n_nodes for b in model.bodies)
        assert 200 <= ndof <= 600  # small: the demo runs in seconds
        # non-matching meshes on the two faces of the joint
        itf = model.interfaces[0]
        xs_plus = model.body(itf.plus.body).points[itf.plus.index, 0]
        xs_minus = model.body(itf.minus.body).points[itf.minus.index, 0]
        assert not np.isin(np.round(xs_plus, 9), np.round(xs_minus, 9)).all()
    # uplift acts on the left half of the joint, on both faces
    up = uplift.pattern("uplift").loads
    for ld in up:
        x = uplift.body(ld.nodes.body).points[ld.nodes.index, 0]
        assert x.min() >= 0.0 and x.max() <= 1.0 + 1e-12
    assert {ld.nodes.body for ld in up} == {"block", "foundation"}
    assert "[[program]]" in demo_text("uplift")


# --------------------------------------------------------------------------------------------
# CLI with a fake solver
# --------------------------------------------------------------------------------------------
def fake_result(n_events: int = 3, status: Status = Status.EQUILIBRIUM_LOST) -> StaticResult:
    """A hand-made result: 2 CFEs, one state per event plus start and end."""
    m = 2
    n = n_events + 2
    lam = np.linspace(0.0, 2.0, n)
    events = [
        Event(step=k + 1, state=k + 1, segment=1, pattern="push", lam=float(lam[k + 1]),
              cfe=k % m, interface="joint", local=k % m, position=0.5 * (k % m),
              x=0.5 * (k % m), y=0.0, transition=Transition.SLIP_POS,
              N=-1.5e4 - k, Q=9e3 + k)
        for k in range(n_events)
    ]
    N = -np.ones((n, m)) * 1e4
    return StaticResult(
        pattern_names=("weight", "push"),
        segments=[("weight", 0.0, 1.0), ("push", 0.0, 5.0)],
        cfe={"area": np.full(m, 0.5), "s": np.array([0.0, 0.5]), "x": np.zeros((m, 2)),
             "interface": np.zeros(m, dtype=int), "local": np.arange(m),
             "friction": np.full(m, 0.6)},
        interface_names=("joint",),
        lam=lam,
        segment=np.ones(n, dtype=int),
        factors=np.column_stack([np.ones(n), lam]),
        kind=np.array(["start"] + ["event"] * n_events + ["segment_end"]),
        N=N,
        Q=-0.6 * N,
        un=np.zeros((n, m)),
        ut=np.zeros((n, m)),
        state=np.full((n, m), int(ContactState.SLIP_POS)),
        residual=np.full(n, 1e-15),
        violation=np.zeros(n),
        events=events,
        multipliers=[
            Multipliers(0, "weight"),
            Multipliers(1, "push", first_slip=0.5, equilibrium_lost=2.0),
        ],
        status=status,
        message="equilibrium lost at λ = 2 (pattern 'push', segment 1): 'block' sliding",
        counters={"events": n_events, "run_seconds": np.float64(0.01)},
    )


class Info:
    def __init__(self, step, segment, lam, n_events):
        self.step, self.segment, self.lam, self.n_events = step, segment, lam, n_events


@pytest.fixture
def fake_solver(monkeypatch):
    """Replace solve_static, StaticResult.save and plot_interfaces; record the calls."""
    calls: dict[str, list] = {"solve": [], "save": [], "plot": []}
    state = {"n_events": 3, "raise": None}

    def solve_static(model, *, slip="exact", eps_p=0.01, store_fields="auto",
                     max_events=100000, hooks=(), output=None, precision="auto"):
        calls["solve"].append({"model": model, "slip": slip, "eps_p": eps_p,
                               "max_events": max_events, "hooks": hooks, "output": output,
                               "precision": precision})
        if state["raise"] is not None:
            raise state["raise"]
        for k, (_, a, b) in enumerate(model.segments_resolved()):
            for h in hooks:
                if hasattr(h, "after_event"):
                    h.after_event(Info(k + 1, k, 0.5 * (a + b), k))
            res = fake_result(state["n_events"])
            for h in hooks:
                if hasattr(h, "after_segment"):
                    h.after_segment(res)
        res = fake_result(state["n_events"])
        if output is not None:  # the real solver writes the result file as it goes
            res.save(output)
        return res

    def save(self, path):
        calls["save"].append(Path(path))
        Path(path).write_text("fake result", encoding="utf-8")

    def plot_interfaces(res, lams=None, path=None, segment=None):
        calls["plot"].append({"path": Path(path), "lams": lams})
        Path(path).write_bytes(b"\x89PNG fake")

    monkeypatch.setattr("stepcontact.solver.static.solve_static", solve_static)
    monkeypatch.setattr(StaticResult, "save", save)
    monkeypatch.setattr("stepcontact.post.plotting.plot_interfaces", plot_interfaces)
    calls["state"] = [state]
    return calls


@pytest.fixture
def model_file(tmp_path):
    path = tmp_path / "block.toml"
    path.write_text(DEMO.read_text(encoding="utf-8"), encoding="utf-8")
    return path


runner = CliRunner()


def test_help_and_version():
    result = runner.invoke(app, ["--help"])
    assert result.exit_code == 0
    for command in ("run", "demo", "check", "schema"):
        assert command in result.output
    result = runner.invoke(app, ["run", "--help"])
    assert result.exit_code == 0
    for option in ("--output", "--slip", "--eps-p", "--plot", "--lam", "--quiet", "--json"):
        assert option in result.output
    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0
    assert stepcontact.__version__ in result.output


def test_run_bad_model_file_is_one_line(tmp_path, fake_solver):
    bad = tmp_path / "bad.toml"
    d = DEMO.read_text(encoding="utf-8").replace('material = "concrete"', 'material = "steel"')
    bad.write_text(d, encoding="utf-8")
    result = runner.invoke(app, ["run", str(bad)])
    assert_one_line_error(result, "bodies[1].material: unknown material 'steel'")
    assert str(bad) in result.stderr
    assert fake_solver["solve"] == []


def test_run_missing_and_broken_files(tmp_path, fake_solver):
    result = runner.invoke(app, ["run", str(tmp_path / "nothere.toml")])
    assert_one_line_error(result, "not found")
    broken = tmp_path / "broken.toml"
    broken.write_text("[model\n", encoding="utf-8")
    result = runner.invoke(app, ["run", str(broken), "--json"])
    assert_one_line_error(result, "not a valid TOML file")
    assert json.loads(result.stdout)["status"] == "error"


def test_run_solver_error_is_one_line(model_file, fake_solver):
    fake_solver["state"][0]["raise"] = SolverError("singular scheme\nat λ = 1")
    result = runner.invoke(app, ["run", str(model_file), "-q"])
    assert_one_line_error(result, "singular scheme at λ = 1")


def test_run_writes_result_and_figure(model_file, fake_solver):
    result = runner.invoke(app, ["run", str(model_file)])
    assert result.exit_code == 0, result.output
    (call,) = fake_solver["solve"]
    assert call["slip"] == "exact" and call["eps_p"] == 0.01 and call["precision"] == "auto"
    assert call["model"].name == "block-slide"
    assert len(call["hooks"]) == 1 and isinstance(call["hooks"][0], ProgressHook)
    assert call["hooks"][0].done == 2  # after_segment reached for both segments
    assert fake_solver["save"] == [model_file.with_suffix(".nc")]
    assert fake_solver["plot"] == [{"path": model_file.with_suffix(".png"), "lams": None}]
    assert model_file.with_suffix(".nc").exists() and model_file.with_suffix(".png").exists()
    out = result.stdout
    assert "slip+" in out and "joint" in out
    assert "-15.000" in out and "9.000" in out  # N, Q of the first event, kN
    assert "status: equilibrium_lost" in out
    assert "Traceback" not in result.output


def test_run_options(model_file, tmp_path, fake_solver):
    out_nc = tmp_path / "sub" / "r.nc"
    out_png = tmp_path / "fig" / "r.svg"
    result = runner.invoke(
        app,
        ["run", str(model_file), "-o", str(out_nc), "--slip", "article", "--eps-p", "0.001",
         "--plot", str(out_png), "--lam", "1.5", "--lam", "2", "--quiet"],
    )
    assert result.exit_code == 0, result.output
    (call,) = fake_solver["solve"]
    assert (call["slip"], call["eps_p"], call["hooks"]) == ("article", 0.001, ())
    assert fake_solver["save"] == [out_nc]
    assert fake_solver["plot"] == [{"path": out_png, "lams": [1.5, 2.0]}]
    assert "transition" not in result.stdout  # --quiet: no event table
    assert "status:" in result.stdout
    result = runner.invoke(app, ["run", str(model_file), "--no-plot", "-q"])
    assert result.exit_code == 0 and len(fake_solver["plot"]) == 1
    result = runner.invoke(app, ["run", str(model_file), "--plot", "x.jpg"])
    assert_one_line_error(result, "unsupported file type")


def test_run_json(model_file, fake_solver):
    result = runner.invoke(app, ["run", str(model_file), "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["status"] == "equilibrium_lost"
    assert data["events"] == 3
    assert data["multipliers"][1] == {
        "segment": 1, "pattern": "push", "first_slip": 0.5, "first_opening": None,
        "first_closing": None, "equilibrium_lost": 2.0,
    }
    assert data["result_file"] == str(model_file.with_suffix(".nc"))
    assert data["transitions"]["slip+"] == 3
    assert call_hooks_empty(fake_solver)


def call_hooks_empty(calls) -> bool:
    return all(c["hooks"] == () for c in calls["solve"])


def test_event_table_is_capped():
    res = fake_result(n_events=120)
    table = events_table(res, max_rows=50)
    assert table.row_count == 51  # 40 first, one "…" row, 10 last
    assert "showing the first 40 and the last 10 of 120 events" in str(table.caption)
    assert events_table(fake_result(5)).row_count == 5
    assert result_summary(res)["counters"]["run_seconds"] == 0.01


def test_long_run_prints_capped_table(model_file, fake_solver):
    fake_solver["state"][0]["n_events"] = 80
    result = runner.invoke(app, ["run", str(model_file), "-q", "--no-plot"])
    assert result.exit_code == 0
    result = runner.invoke(app, ["run", str(model_file), "--no-plot"])
    assert result.exit_code == 0
    assert "showing the first 40" in result.stdout
    assert "30 more" in result.stdout


def test_demo_command(tmp_path, fake_solver):
    out = tmp_path / "demo"
    result = runner.invoke(app, ["demo", "-o", str(out), "--quiet"])
    assert result.exit_code == 0, result.output
    names = sorted(p.name for p in out.iterdir())
    assert names == [
        "demo.nc", "demo.png", "demo.toml", "demo_uplift.nc", "demo_uplift.png",
        "demo_uplift.toml",
    ]
    assert [c["model"].name for c in fake_solver["solve"]] == ["block-slide", "block-uplift"]
    # the copied model files are runnable as they are
    assert load_model(out / "demo_uplift.toml").name == "block-uplift"
    result = runner.invoke(app, ["demo", "-o", str(out), "--json"])
    assert set(json.loads(result.stdout)) == {"slide", "uplift"}


def test_check_and_schema_commands(model_file, tmp_path):
    result = runner.invoke(app, ["check", str(model_file)])
    assert result.exit_code == 0, result.output
    assert "398 DOFs" in result.stdout and "7 CFEs" in result.stdout  # on the coarser face
    bad = tmp_path / "bad.toml"
    bad.write_text(DEMO.read_text(encoding="utf-8").replace("friction = 0.6", "friction = nan"),
                   encoding="utf-8")
    result = runner.invoke(app, ["check", str(bad)])
    assert_one_line_error(result, "interfaces[0].friction: must be a finite number")
    result = runner.invoke(app, ["schema"])
    assert result.exit_code == 0
    assert "program" in json.loads(result.stdout)["properties"]


def test_run_without_a_physical_answer_exits_3(model_file):
    """A run stopped by the event budget (no physical answer) writes its result file and exits
    with code 3 — not 0 ("completed"), not 2 (bad input)."""
    out = model_file.with_suffix(".nc")
    result = runner.invoke(app, ["run", str(model_file), "--max-events", "1", "--no-plot", "-q"])
    assert result.exit_code == 3, result.output
    assert "status: max_events" in result.stdout
    from stepcontact.results.result import load_result

    res = load_result(out)
    assert res.status == Status.MAX_EVENTS and res.to_dataset().attrs["complete"] == 1


def test_demo_writes_into_its_output_folder_only(tmp_path, monkeypatch, fake_solver):
    """``stepcontact demo`` run in a checkout's working directory (default ``-o``): every file
    it writes is inside ``stepcontact-demo/``, and git ignores that folder (its .png and .toml
    were left untracked)."""
    import shutil
    import subprocess

    work = tmp_path / "checkout"
    work.mkdir()
    monkeypatch.chdir(work)
    result = runner.invoke(app, ["demo", "--quiet"])
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in work.iterdir()) == ["stepcontact-demo"]
    written = sorted(p.relative_to(work).as_posix() for p in work.rglob("*") if p.is_file())
    assert written == [f"stepcontact-demo/{n}" for n in (
        "demo.nc", "demo.png", "demo.toml", "demo_uplift.nc", "demo_uplift.png",
        "demo_uplift.toml")]
    root = Path(__file__).resolve().parents[1]
    if shutil.which("git") is None or not (root / ".git").exists():
        pytest.skip("not a git checkout")
    for name in written:  # --no-index: the rules of .gitignore, whether or not the file exists
        check = subprocess.run(["git", "-C", str(root), "check-ignore", "-q", "--no-index",
                                name], check=False)
        assert check.returncode == 0, f"{name} is not ignored by .gitignore"


def test_run_writes_its_figure_beside_the_result_file(model_file, fake_solver, tmp_path):
    """``run MODEL.toml -o out/r.nc``: the figure is out/r.png; nothing is written beside the
    model file (a model in a checkout is left alone)."""
    before = sorted(p.name for p in model_file.parent.iterdir())
    out = tmp_path / "runs" / "r.nc"
    result = runner.invoke(app, ["run", str(model_file), "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert fake_solver["plot"] == [{"path": out.with_suffix(".png"), "lams": None}]
    assert sorted(p.name for p in out.parent.iterdir()) == ["r.nc", "r.png"]
    assert sorted(p.name for p in model_file.parent.iterdir()) == sorted([*before, "runs"])
