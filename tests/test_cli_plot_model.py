"""``stepcontact plot/export RESULT.nc --model MODEL.toml`` recompute every state from the model
file of the run (issue 25, docs item: user-guide "Results" promises it).

The run that was refused: a block on a brittle bonded base, pushed at its top corner; the crack
runs through the joint in one cascade and the run stops (equilibrium lost) while the broken
bonds still release their forces.  Its last stored field carries those forces, which are not
among the recorded contact forces, so checking the model against that field refused the run's
own model file.  Reference: the same model solved with ``store_fields="all"`` (every field
solved and stored by the run itself); tolerance 1e-9 of the largest displacement (two
factorisations of the same matrix).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from typer.testing import CliRunner

import stepcontact as sc
from model_toml import concrete_block
from stepcontact.cli import app
from stepcontact.io.modelfile import load_model

runner = CliRunner()

BRITTLE = concrete_block("bonded block", material="concrete", corner1=(2.0, 2.0), nx=8,
                         ny=8) + """
[[obstacles]]
name = "ground"
points = [[-1.0, 0.0], [3.0, 0.0]]

[node_sets.bottom]
body = "block"
y = 0.0

[node_sets.corner]
body = "block"
x = 0.0
y = 2.0

[[interfaces]]
name = "base"
plus = "bottom"
obstacle = "ground"
layer = { kn = 1e9, kt = 1e9 }
bond = { cohesion = 200e3, tensile_strength = 50e3, friction_angle = 35.0 }

[patterns.weight]
loads = [{ type = "gravity" }]

[patterns.push]
loads = [{ type = "nodal", nodes = "corner", fx = 1.0 }]

[[program]]
pattern = "weight"
end = 1.0

[[program]]
pattern = "push"
end = 1e5
"""


def _run(tmp_path: Path) -> tuple[Path, Path]:
    model = tmp_path / "brittle.toml"
    model.write_text(BRITTLE, encoding="utf-8")
    result = tmp_path / "out" / "brittle.nc"
    out = runner.invoke(app, ["run", str(model), "-o", str(result), "--no-plot", "-q"])
    assert out.exit_code == 0, out.output
    return model, result


def test_plot_and_export_accept_the_model_file_of_a_run_stopped_mid_release(tmp_path):
    model, result = _run(tmp_path)
    back = sc.load_result(result)
    # the case of the refusal: the run stopped, and its largest stored field is its last state
    assert back.status == sc.Status.EQUILIBRIUM_LOST
    assert any(e.transition == sc.Transition.BROKEN for e in back.events)
    last = back.n_states - 1
    assert max(back.fields, key=lambda k: np.abs(back.fields[k]).max()) == last
    assert len(back.fields) < back.n_states  # states to recompute

    fig = tmp_path / "ld.png"
    out = runner.invoke(app, ["plot", str(result), "--kind", "load-displacement",
                              "--model", str(model), "-o", str(fig)])
    assert out.exit_code == 0, out.output
    assert "recomputed from" in out.output and fig.stat().st_size > 0
    out = runner.invoke(app, ["export", str(result), "--vtu", str(tmp_path / "pv"),
                              "--model", str(model)])
    assert out.exit_code == 0, out.output
    assert f"exported {back.n_states} frame(s) of {back.n_states} states" in out.output

    # the recomputed fields are the run's: against every field solved by the run itself
    ref = sc.solve_static(load_model(model), store_fields="all")
    back.recover_fields(load_model(model))
    U = back.displacements()
    R = np.array([ref.fields[i] for i in range(ref.n_states)])
    assert U.shape == R.shape
    assert np.abs(U - R).max() <= 1e-9 * np.abs(R).max()


def test_plot_finds_the_recorded_model_file_without_model_option(tmp_path):
    """The result lies in another folder than its model file (``-o out/…``): plot finds the
    model file the run recorded; once that file has changed it is not used (the
    load-displacement figure then needs --model: one-line error, exit 2)."""
    model, result = _run(tmp_path)
    assert not result.with_suffix(".toml").exists()
    out = runner.invoke(app, ["plot", str(result), "--kind", "load-displacement",
                              "-o", str(tmp_path / "a.png")])
    assert out.exit_code == 0, out.output
    assert f"recomputed from {model.resolve()}" in " ".join(out.output.split())
    model.write_text(BRITTLE.replace("E = 30e9", "E = 20e9"), encoding="utf-8")
    out = runner.invoke(app, ["plot", str(result), "--kind", "load-displacement",
                              "-o", str(tmp_path / "b.png")])
    assert out.exit_code == 2, out.output
    assert "--model" in out.output and "Traceback" not in out.output
    assert not (tmp_path / "b.png").exists()


def test_recover_fields_of_a_staged_result_needs_nothing(tmp_path):
    """A staged run stores every field: recover_fields with its model does nothing (it
    refused the model before: the stages' automatic load patterns are not the model's)."""
    path = Path(__file__).resolve().parents[1] / "examples" / "data" / "staged_wall.toml"
    res = sc.solve_static(load_model(path))
    res.save(tmp_path / "w.nc")
    back = sc.load_result(tmp_path / "w.nc")
    assert len(back.fields) == back.n_states
    assert set(back.pattern_names) != {p.name for p in load_model(path).patterns}
    back.recover_fields(load_model(path))
    for i in range(back.n_states):
        assert np.array_equal(back.displacement(i), res.displacement(i))
