"""``sc.run(model)``: the whole program of a model — stages, static segments, the dynamic
intervals between stages and at the end — in one call, as ``stepcontact run`` runs it.

References: the same program run by calling the drivers directly
(:func:`~stepcontact.solve_static`, then :func:`~stepcontact.solve_dynamic` from its result)
and by the command line (its result files read back).  All three are the same computation in
the same order, so every state and every event must agree *exactly* (tolerance 0: the arrays
and the event records compare equal bit for bit; a netCDF file stores float64 as it is).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import stepcontact as sc
from stepcontact.cli import app
from stepcontact.errors import ModelError
from test_dynamics import DYN_FILE

ROOT = Path(__file__).resolve().parents[1]
DEMO = ROOT / "src" / "stepcontact" / "data" / "demo.toml"
WALL = ROOT / "examples" / "data" / "staged_wall.toml"
SHOCK = ROOT / "examples" / "data" / "staged_shock.toml"
runner = CliRunner()

_ARRAYS = ("lam", "segment", "factors", "N", "Q", "un", "ut", "state")


def _event(e):
    return (e.step, e.segment, e.pattern, e.lam, e.cfe, e.interface, e.transition, e.N, e.Q)


def _same(a, b, events: bool = True) -> None:
    """Exactly the same states and events (tolerance 0); ``events``: the log is not empty."""
    assert type(a) is type(b)
    assert (a.status, a.message) == (b.status, b.message)
    for name in _ARRAYS:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert [_event(e) for e in a.events] == [_event(e) for e in b.events]
    assert len(a.lam) > 1
    assert len(a.events) > 0 or not events  # (comparing empty logs would prove nothing)


def _cli(path: Path, tmp_path: Path) -> Path:
    out = tmp_path / "cli" / "r.nc"
    result = runner.invoke(app, ["run", str(path), "-o", str(out), "--no-plot", "-q"])
    assert result.exit_code == 0, result.output
    return out


def _copy(src: Path | str, tmp_path: Path, name: str) -> Path:
    path = tmp_path / name
    path.write_text(src if isinstance(src, str) else src.read_text(encoding="utf-8"),
                    encoding="utf-8")
    return path


def test_a_static_model_runs_as_solve_static_and_the_cli(tmp_path):
    """The demo block pushed until it slides: ``run`` is ``solve_static``, no dynamics."""
    path = _copy(DEMO, tmp_path, "demo.toml")
    model = sc.load_model(path)
    out = sc.run(model)
    assert isinstance(out, sc.ProgramResult)
    assert out.dynamic is None and out.not_run == () and out.stage_dynamics == {}
    _same(out.static, sc.solve_static(model))
    _same(out.static, sc.load_result(_cli(path, tmp_path)))
    assert out.completed == (out.static.status == sc.Status.COMPLETED)


def test_a_staged_model_runs_its_stages_as_the_cli(tmp_path):
    """A wall built in stages (static only): the same states, stage by stage."""
    path = _copy(WALL, tmp_path, "wall.toml")
    model = sc.load_model(path)
    out = sc.run(model)
    assert out.dynamic is None and out.not_run == ()
    assert len(out.static.stage_names) == len(model.stages) > 1
    _same(out.static, sc.solve_static(model))
    back = sc.load_result(_cli(path, tmp_path))
    _same(out.static, back)
    np.testing.assert_array_equal(out.static.stage, back.stage)


def test_a_final_dynamic_interval_runs_from_the_static_state(tmp_path):
    """A block on a compliant base, its weight applied statically, then a half-sine pulse
    (``[dynamics]``): ``run`` is ``solve_static`` then ``solve_dynamic(initial=static)``,
    and the CLI's MODEL-dynamic.nc holds the same states and events."""
    path = _copy(DYN_FILE, tmp_path, "dyn.toml")
    model = sc.load_model(path)
    order: list[str] = []

    class Steps:
        def after_step(self, step, t, end):
            order.append("step")

    out = sc.run(model, after_static=lambda res: order.append("static"),
                 before_dynamics=lambda: order.append("dynamics"), dynamic_hooks=[Steps()])
    assert order[:2] == ["static", "dynamics"] and set(order[2:]) == {"step"}
    assert out.completed and out.not_run == ()
    static = sc.solve_static(model)
    _same(out.static, static, events=False)  # (the weight alone: no event)
    _same(out.dynamic, sc.solve_dynamic(model, initial=static))
    assert out.dynamic.time[-1] == pytest.approx(model.dynamics.duration, rel=1e-12)
    cli = _cli(path, tmp_path)
    _same(out.static, sc.load_result(cli), events=False)
    _same(out.dynamic, sc.load_result(cli.with_name("r-dynamic.nc")))


def test_an_interval_between_stages_is_kept_with_the_static_result(tmp_path):
    """The block struck between two static stages (examples/data/staged_shock.toml): the
    interval's result is ``stage_dynamics['struck']``, the static path goes on from it, as
    in ``solve_static`` and in the CLI's MODEL-dynamic-struck.nc."""
    path = _copy(SHOCK, tmp_path, "shock.toml")
    model = sc.load_model(path)
    out = sc.run(model)
    assert out.completed and out.dynamic is None
    assert list(out.stage_dynamics) == ["struck"]
    direct = sc.solve_static(model)
    _same(out.static, direct)
    _same(out.stage_dynamics["struck"], direct.dynamics["struck"])
    cli = _cli(path, tmp_path)
    _same(out.static, sc.load_result(cli))
    _same(out.stage_dynamics["struck"], sc.load_result(cli.with_name("r-dynamic-struck.nc")))


def test_an_interval_the_program_does_not_reach_is_listed_with_its_reason(tmp_path):
    """The demo block pushed until equilibrium is lost, with a ``[dynamics]`` interval: the
    interval is not run, ``not_run`` says so with the static status, ``completed`` is False;
    the CLI's JSON summary gives the same reason."""
    text = DEMO.read_text(encoding="utf-8") + (
        '\n[dynamics]\ndt = 1e-3\nduration = 0.01\n'
        '[[dynamics.loads]]\npattern = "push"\ntype = "constant"\namplitude = 1.0\n')
    path = _copy(text, tmp_path, "lost.toml")
    out = sc.run(sc.load_model(path))
    assert out.static.status == sc.Status.EQUILIBRIUM_LOST
    assert out.dynamic is None and not out.completed
    (item,) = out.not_run
    assert item.interval == "dynamics" and "equilibrium_lost" in item.reason
    result = runner.invoke(app, ["run", str(path), "-o", str(tmp_path / "r.nc"), "--no-plot",
                                 "-q", "--json"])
    assert result.exit_code == 3
    import json

    summary = json.loads(result.stdout)
    assert summary["dynamics_not_run"] == [{"interval": item.interval, "reason": item.reason}]


def test_a_body_without_mass_is_refused_before_the_static_program(tmp_path, monkeypatch):
    """A dynamic interval needs the density of every body that can move: ModelError naming
    the body before any static work (the static driver must not be called)."""
    from stepcontact.solver import static

    def never(*args, **kwargs):
        raise AssertionError("the static program ran")

    monkeypatch.setattr(static, "solve_static", never)
    model = sc.load_model(_copy(DYN_FILE.replace("density = 2400\n", "density = 0\n"),
                                tmp_path, "massless.toml"))
    with pytest.raises(ModelError, match="has no mass"):
        sc.run(model)


def test_the_study_layer_does_not_import_the_command_line():
    """study/ calls the library (``sc.run``), not the CLI: importing it loads no CLI module."""
    code = ("import sys, stepcontact.study.studyfile, stepcontact.study.sweep; "
            "print(sorted(m for m in sys.modules if m.startswith('stepcontact.cli')))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip() == "[]"
