"""Inputs of a dynamic interval that used to give silently wrong answers or hang (issue 24,
"Bad input and faults"), against closed forms or as errors naming the item:

* item 1 — loads the step cannot follow: a curved load (harmonic, half-sine pulse) with fewer
  than 10 steps per period, Δt longer than the interval, a load acting only outside [0, T]
  are refused; piecewise linear loads shorter than Δt (a rectangular pulse, a table) are
  followed exactly by the steps that land on their breaks (free mass: Δv = impulse / m);
* item 2 — ground acceleration on a DiscreteModel (its DOFs' axes) and on a continuum, against
  the rigid-block closed form of the slide under a rectangular ground pulse;
* item 3 — ``solve_dynamic(backend=...)`` reaches the factorisation;
* item 4 — an interval of too many steps is refused before any work, with the estimate and
  the limit ``max_steps`` (keyword, model file, one-line CLI error);
* item 5 — ``run`` says why a dynamic interval was not run (static program lost equilibrium,
  exit code 3; no density: a one-line error before any work) and ``validate`` finds a
  dynamic interval without mass.
"""

from __future__ import annotations

import json
import time

import numpy as np
import pytest
from typer.testing import CliRunner

import stepcontact as sc
from cli_checks import assert_one_line_error
from model_toml import block_on_floor
from stepcontact.cli.commands import app
from stepcontact.enums import Status
from stepcontact.errors import ModelError, StepContactError
from stepcontact.model.timefunction import Constant, Harmonic, Pulse, Tabulated
from stepcontact.solver.program import solve_dynamic

G = 9.81


def free_mass():
    """One DOF of mass 1 kg, no stiffness, its only CFE 1 km open: ü = F(t)."""
    return sc.DiscreteModel(K=[[0.0]], normal_rows=[[1.0]], tangent_rows=[[0.0]], gaps=1e3,
                            loads={"P": [1.0]})


def floor_block(mass=1000.0, f=0.3, axes=True):
    """A rigid block (DOFs ux, uy) on a rough floor, at rest under its weight."""
    dm = sc.DiscreteModel(K=np.zeros((2, 2)), normal_rows=[[0, 1]], tangent_rows=[[1, 0]],
                          loads={"weight": {"uy": -mass * G}}, friction=f,
                          dof_names=("ux", "uy"), program=[sc.Segment("weight", 1.0)],
                          dof_axes={"ux": "x", "uy": "y"} if axes else None)
    return dm, sc.solve_static(dm), np.diag([mass, mass])


def slide(A: float, f: float, tp: float) -> float:
    """Relative slide of a rigid block on a rough base (Coulomb, f) under a rectangular ground
    pulse A (m/s²) of tp (s), A > f g: relative deceleration A − f g during the pulse, f g
    after it, so s = (A − f g) A tp² / (2 f g)."""
    return (A - f * G) * A * tp**2 / (2 * f * G)


# ---- item 1: loads the step cannot follow --------------------------------------------------
@pytest.mark.parametrize(("g", "dt", "words"), [
    (Harmonic(1.0, 1e6), 1e-3, ("harmonic of 1e+06 Hz", "period 1e-06 s", "dt = 0.001 s")),
    (Pulse(1.0, 0.0, 1e-3, "half_sine"), 0.05, ("half-sine pulse of 0.001 s", "dt = 0.05 s",
                                                "dt ≤ 0.0002 s")),
    (Pulse(1.0, 0.01, 1e-3, "triangular"), 0.05, ("triangular pulse of 0.001 s",)),
    (Tabulated((0.01, 0.0105, 0.011), (0.0, 2.0, 0.0), hold=False), 0.05,
     ("table pulse of 0.001 s",)),
])
def test_a_varying_load_sampled_by_too_few_steps_is_refused(g, dt, words):
    """Item 1: a 1 MHz harmonic at Δt = 1 ms is seen only at its zeros, a 1 ms half-sine at
    Δt = 50 ms only at its zero ends; a 1 ms triangle (or table pulse) at 50 ms has the right
    impulse but its ramps, made by short steps with Δt's K̂, move the mass by O(Δt² Δa) (28 %
    off after the pulse) — refused, naming the pattern, the period and the step."""
    with pytest.raises(ModelError) as e:
        solve_dynamic(free_mass(), dt=dt, duration=1.0, mass=np.eye(1), loads={"P": g})
    assert e.value.item == "loads['P']"
    for w in words:
        assert w in e.value.problem
    # 10 steps per period are accepted
    p, end = g.period(), g.support()[1]
    res = solve_dynamic(free_mass(), dt=p / 10, duration=p if np.isinf(end) else end,
                        mass=np.eye(1), loads={"P": g})
    assert res.status == Status.COMPLETED


def test_a_step_longer_than_the_interval_is_refused():
    """Item 1: Δt = 1 s for a 0.1 s interval."""
    with pytest.raises(ModelError, match="longer than the interval") as e:
        solve_dynamic(free_mass(), dt=1.0, duration=0.1, mass=np.eye(1),
                      loads={"P": Pulse(1.0, 0.0, 0.05, "rectangular")})
    assert e.value.item == "dt"
    with pytest.raises(ModelError, match="dynamics.dt"):
        sc.DynamicInterval(1.0, 0.1)


@pytest.mark.parametrize("g", [
    Pulse(1.0, 2.0, 0.1, "rectangular"), Pulse(1.0, -0.5, 0.5, "half_sine"),
    Harmonic(1.0, 1.0, start=1.5), Tabulated((1.2, 1.4), (1.0, 0.0)),
    Tabulated((-3.0, -2.0), (1.0, 0.0)), Tabulated((-3.0, -2.0), (1.0, 1.0), hold=False),
    Constant(0.0),
])
def test_a_load_outside_the_interval_is_refused(g):
    """Item 1: a pulse, harmonic or table that acts only outside [0, 1 s] (or never) would
    load nothing: refused, naming the pattern (as a keyword and in a DynamicInterval)."""
    with pytest.raises(ModelError) as e:
        solve_dynamic(free_mass(), dt=0.01, duration=1.0, mass=np.eye(1), loads={"P": g})
    assert e.value.item == "loads['P']"
    assert "would not load" in e.value.problem
    with pytest.raises(ModelError, match=r"dynamics\.loads\['P'\]"):
        sc.DynamicInterval(0.01, 1.0, (("P", g),))


@pytest.mark.parametrize("g", [Pulse(2.0, 0.01, 1e-3, "rectangular"),
                               Pulse(2.0, 0.013, 1.3e-3, "rectangular")])
def test_a_rectangular_pulse_shorter_than_five_steps_is_refused(g):
    """Item 1: a 1 ms rectangular pulse at Δt = 50 ms: its edges would be cuts of whole steps
    placed to within Δt²/8 of the pulse's acceleration in displacement — refused, naming the
    pattern and the step needed (5 steps in its duration)."""
    with pytest.raises(ModelError) as e:
        solve_dynamic(free_mass(), dt=0.05, duration=0.1, mass=np.eye(1), loads={"P": g})
    assert e.value.item == "loads['P']"
    assert "rectangular pulse" in e.value.problem and "too few steps" in e.value.problem


@pytest.mark.parametrize("g", [Pulse(2.0, 0.0113, 5.3e-3, "rectangular"),
                               Pulse(2.0, 0.01, 5e-3, "rectangular")])
def test_a_rectangular_pulse_of_five_steps_gives_its_impulse(g):
    """Item 1: a free 1 kg mass, Δt = 1 ms, a rectangular pulse of 5 steps (on and off the
    step grid): v = A t_p / m to 1e-8 (the jumps resolved in accelerations); u = A t_p²/2 +
    A t_p (T − t_end) within A Δt²/4 (an edge off the grid is a cut of a whole step: the
    linear interpolation is off by at most A Δt²/8 in displacement per edge), and to 1e-8 of
    it on the grid; the ledger gains no energy (numerical ≥ 0 is energy removed)."""
    T, dt = 0.1, 1e-3
    res = solve_dynamic(free_mass(), dt=dt, duration=T, mass=np.eye(1), loads={"P": g})
    assert res.status == Status.COMPLETED
    impulse = g.amplitude * g.duration
    assert res.v[-1][0] == pytest.approx(impulse, rel=1e-8)
    u = 0.5 * g.amplitude * g.duration**2 + impulse * (T - g.start - g.duration)
    assert abs(res.u[-1][0] - u) <= g.amplitude * dt**2 / 4
    on_grid = np.allclose(np.array([g.start, g.start + g.duration]) / dt,
                          np.round(np.array([g.start, g.start + g.duration]) / dt))
    if on_grid:
        assert res.u[-1][0] == pytest.approx(u, rel=1e-8)
    assert res.energy["numerical"][-1] >= -1e-12 * res.energy["external"][-1]


def test_a_half_sine_pulse_of_ten_steps_gives_its_impulse():
    """Item 1: the shortest half-sine accepted (10 steps per period: 5 in its duration of
    20 ms) on the free mass: v = 2 A t_p / π after it; the load, linear between the steps'
    ends, is the trapezoidal rule of the sine: relative error ≈ (π/5)²/12 = 3.3 %
    (tolerance 4 %)."""
    A, tp = 1.0, 0.02
    res = solve_dynamic(free_mass(), dt=tp / 5, duration=0.1, mass=np.eye(1),
                        loads={"P": Pulse(A, 0.01, tp, "half_sine")})
    assert res.v[-1][0] == pytest.approx(2 * A * tp / np.pi, rel=0.04)


# ---- item 2: ground acceleration -----------------------------------------------------------
def test_ground_acceleration_slides_a_discrete_block_by_the_closed_form():
    """Item 2: a rigid block (1000 kg, f = 0.3) under a rectangular ground pulse of 0.5 g for
    0.2 s slides relative to the ground by (A − f g) A t_p² / (2 f g) = 65.4 mm, backwards
    (closed form; Δt = 2 ms, tolerance 1e-3 relative, measured 2e-5)."""
    dm, st, M = floor_block()
    A, f, tp = 0.5 * G, 0.3, 0.2
    res = solve_dynamic(dm, dt=2e-3, duration=0.6, mass=M, initial=st,
                        ground_acceleration=(Pulse(A, 0.0, tp, "rectangular"), (1.0, 0.0)))
    assert res.status == Status.COMPLETED
    assert res.u[-1][0] == pytest.approx(-slide(A, f, tp), rel=1e-3)
    assert abs(res.u[-1][1]) < 1e-12  # no lift (the ground moves along x)
    # friction dissipated f W s (the block at rest relative to the ground at the end)
    assert res.energy["friction"][-1] == pytest.approx(f * 1000.0 * G * slide(A, f, tp),
                                                       rel=1e-3)


def test_ground_acceleration_on_a_discrete_model_without_axes_is_refused():
    """Item 2: without dof_axes the effective load would be zero (the block used to slide
    0 m under a 0.2 g pulse without a word)."""
    dm, st, M = floor_block(axes=False)
    ga = (Pulse(0.2 * G, 0.0, 0.1, "half_sine"), (1.0, 0.0))
    with pytest.raises(ModelError, match="dof_axes") as e:
        solve_dynamic(dm, dt=1e-3, duration=0.2, mass=M, initial=st, ground_acceleration=ga)
    assert e.value.item == "ground_acceleration"
    # axes, but none along the ground's direction
    dm_y = dm.replace(dof_axes={"uy": "y"})
    with pytest.raises(ModelError, match="no DOF of the discrete model translates"):
        solve_dynamic(dm_y, dt=1e-3, duration=0.2, mass=M, initial=st, ground_acceleration=ga)
    with pytest.raises(ModelError, match=r"dof_axes\['ux'\]"):
        dm.replace(dof_axes={"ux": "z"})
    with pytest.raises(ModelError, match="dof_axes"):
        dm.replace(dof_axes=np.ones((3, 2)))
    # an inclined axis is normalised; an array of axes is the same as the mapping
    assert np.allclose(dm.replace(dof_axes={"ux": (3.0, 4.0)}).dof_axes[0], (0.6, 0.8))
    assert np.array_equal(dm.replace(dof_axes=[[1, 0], [0, 1]]).dof_axes,
                          floor_block()[0].dof_axes)


CONTINUUM_BLOCK = block_on_floor("ground-block")


def test_ground_acceleration_slides_a_continuum_block_by_the_closed_form(tmp_path):
    """Item 2: an elastic concrete block (1 m × 0.5 m, E = 30 GPa) on a rigid rough floor
    (f = 0.3, rigid contact), the same ground pulse: its mean displacement follows the
    rigid-block slide (closed form, 65.4 mm; tolerance 1 % for the block's elasticity and
    Δt = 2 ms, measured 0.25 %)."""
    from stepcontact.io.modelfile import load_model

    path = tmp_path / "block.toml"
    path.write_text(CONTINUUM_BLOCK)
    model = load_model(path)
    st = sc.solve_static(model)
    A, f, tp = 0.5 * G, 0.3, 0.2
    res = solve_dynamic(model, dt=2e-3, duration=0.6, mass="lumped", initial=st,
                        ground_acceleration=(Pulse(A, 0.0, tp, "rectangular"), (1.0, 0.0)))
    assert res.status == Status.COMPLETED
    assert res.u[-1][0::2].mean() == pytest.approx(-slide(A, f, tp), rel=1e-2)


# ---- item 3: backend -----------------------------------------------------------------------
def test_solve_dynamic_takes_the_factorisation_backend():
    """Item 3: ``backend`` reaches the factorisation of K̂ (an unknown one is named) and the
    scipy backend gives the answer of the default (the closed-form slide, 1e-3)."""
    dm, st, M = floor_block()
    A, f, tp = 0.5 * G, 0.3, 0.2
    ga = (Pulse(A, 0.0, tp, "rectangular"), (1.0, 0.0))
    with pytest.raises(StepContactError, match="nope"):
        solve_dynamic(dm, dt=2e-3, duration=0.3, mass=M, initial=st, ground_acceleration=ga,
                      backend="nope")
    res = solve_dynamic(dm, dt=2e-3, duration=0.6, mass=M, initial=st, ground_acceleration=ga,
                        backend="scipy")
    assert res.u[-1][0] == pytest.approx(-slide(A, f, tp), rel=1e-3)


# ---- item 4: intervals that would not end --------------------------------------------------
@pytest.mark.parametrize(("dt", "duration", "estimate"), [
    (1e-12, 1.0, "1e+12"), (0.01, 1000 * 365.25 * 86400, "3.16e+12")])
def test_an_interval_of_too_many_steps_is_refused_at_once(dt, duration, estimate):
    """Item 4: Δt = 1e-12 s, or a 1000-year interval: refused before any work (< 1 s), with
    the estimate of the steps and the limit max_steps; a lower max_steps is honoured."""
    t0 = time.perf_counter()
    with pytest.raises(ModelError, match="max_steps = 1e\\+07") as e:
        solve_dynamic(free_mass(), dt=dt, duration=duration, mass=np.eye(1))
    assert estimate in e.value.problem
    assert time.perf_counter() - t0 < 1.0
    with pytest.raises(ModelError, match="max_steps = 50"):
        solve_dynamic(free_mass(), dt=0.01, duration=1.0, mass=np.eye(1), max_steps=50)
    with pytest.raises(ModelError, match="max_steps = 50"):
        sc.DynamicInterval(0.01, 1.0, max_steps=50)


DYN_FILE = CONTINUUM_BLOCK + """
[node_sets.top]
body = "block"
y = 0.5

[patterns.push]
loads = [{ type = "edge_force", nodes = "top", fx = 2e4 }]

[dynamics]
dt = 1e-3
duration = 0.02
mass = "lumped"

[[dynamics.loads]]
pattern = "push"
type = "pulse"
amplitude = 1.0
duration = 0.01
shape = "rectangular"
"""

runner = CliRunner()


def test_cli_refuses_too_many_steps_in_one_line(tmp_path):
    """Item 4: the CLI shows the refusal as a one-line error (exit 2), from the model file's
    own max_steps too, before the static run (no result file)."""
    path = tmp_path / "m.toml"
    path.write_text(DYN_FILE.replace("dt = 1e-3", "dt = 1e-12"))
    out = runner.invoke(app, ["run", str(path), "--no-plot", "--quiet"])
    assert_one_line_error(out, "dynamics.dt: the interval of 0.02 s in steps of 1e-12 s takes "
                          "about 2e+10 time steps, more than max_steps = 1e+07")
    assert not (tmp_path / "m.nc").exists()
    path.write_text(DYN_FILE.replace("mass = \"lumped\"", "mass = \"lumped\"\nmax_steps = 10"))
    out = runner.invoke(app, ["run", str(path), "--no-plot", "--quiet"])
    assert_one_line_error(out, "max_steps = 10")
    out = runner.invoke(app, ["validate", str(path)])
    assert out.exit_code == 2 and "max_steps = 10" in out.stderr


# ---- item 5: a dynamic interval that is not run ---------------------------------------------
def test_cli_says_why_a_dynamic_interval_was_not_run(tmp_path):
    """Item 5: the static program loses equilibrium (the push on a frictionless floor): the
    static result is written, 'dynamics not run' and the reason are on stderr, the JSON
    summary lists it, no dynamic result is written, exit code 3."""
    path = tmp_path / "m.toml"
    path.write_text(DYN_FILE.replace("friction = 0.3", "friction = 0.0")
                    + '\n[[program]]\npattern = "push"\nend = 1.0\n')
    out = runner.invoke(app, ["run", str(path), "--no-plot", "--json"])
    assert out.exit_code == 3, out.output
    assert "dynamics not run: the load program before it stopped (equilibrium_lost" \
        in out.stderr
    assert (tmp_path / "m.nc").exists() and not (tmp_path / "m-dynamic.nc").exists()
    summary = json.loads(out.stdout)
    assert summary["status"] == "equilibrium_lost"
    assert summary["dynamics"]["status"] == "not_run"
    assert summary["dynamics_not_run"][0]["interval"] == "dynamics"


def test_cli_and_validate_find_a_dynamic_interval_without_mass(tmp_path):
    """Item 5: no density: ``run`` refuses in one line naming the body before any work (no
    result file), ``validate`` reports it without solving (exit 2); the model without the
    dynamic interval stays valid."""
    path = tmp_path / "m.toml"
    path.write_text(DYN_FILE.replace("density = 2400\n", ""))
    out = runner.invoke(app, ["run", str(path), "--no-plot", "--quiet"])
    assert_one_line_error(out, "body 'block': has no mass")
    assert not (tmp_path / "m.nc").exists()
    out = runner.invoke(app, ["validate", str(path), "--json"])
    assert out.exit_code == 2
    problems = json.loads(out.stdout)["problems"]
    assert any(p["item"] == "body 'block'" and "no mass" in p["message"]
               and p["severity"] == "error" for p in problems)
    static_only = DYN_FILE.split("[dynamics]")[0].replace("density = 2400\n", "")
    path.write_text(static_only)
    out = runner.invoke(app, ["validate", str(path)])
    assert out.exit_code == 0, out.output


def test_the_model_file_interval_runs_from_the_command_line(tmp_path):
    """The checks do not refuse a sound interval: the push of 10 ms at Δt = 1 ms runs and
    writes its result (exit 0)."""
    path = tmp_path / "m.toml"
    path.write_text(DYN_FILE)
    out = runner.invoke(app, ["run", str(path), "--no-plot", "--quiet"])
    assert out.exit_code == 0, out.output
    assert (tmp_path / "m-dynamic.nc").exists()
