"""Earthquake ground motions from files (issue 29 §1, :mod:`stepcontact.model.records`).

Every figure is checked against a hand calculation or a closed form derived here:

* parsing — PEER .AT2 in both header forms, two-column (CSV, blanks, comments, a header
  line) and one-column with dt, in g, m/s² and gal: the values and the PGA by hand (exact to
  round-off, 1e-12);
* Arias intensity of a sine over whole cycles, I_a = π a₀² T/(4g) (1e-6 with dt = T₁/10 000);
  significant duration of a ramp a = c t (cumulative ∝ t³: t_p = T p^{1/3}, 1e-6 T) and of a
  constant (0.9 T exactly);
* scaling to a target PGA (exact), a scale factor, polarity;
* malformed input: one ModelError naming the file and its line, or the argument;
* the sign convention in the dynamic driver: a block on a frictionless base under a constant
  positive record moves relatively by −a t²/2 (Newmark's average acceleration is exact for a
  constant acceleration: 1e-9); horizontal and vertical records together on a rough base
  (relative deceleration A − f (g + a_v), closed form, 1e-9); x, y, z in 3D;
* the model file: ``[[dynamics.ground_motion]]``, ``validate``'s printed figures and errors
  naming the field;
* a real strong-motion record shipped by a test dependency (ObsPy's K-NET test file, LGPL-3):
  PGA against the value its header states.
"""

from __future__ import annotations

import importlib.util
import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import stepcontact as sc
from model_toml import block_on_floor
from stepcontact.cli.commands import app
from stepcontact.enums import Status
from stepcontact.errors import ModelError
from stepcontact.model.records import (
    G_RECORD,
    AccelerationRecord,
    GroundMotion,
    read_at2,
    read_one_column,
    read_two_column,
)

G = 9.81  # the models' gravity (BodyForce default); records in g use G_RECORD = 9.80665


def write_at2(path: Path, values, dt: float, header: str = "new", per_line: int = 5) -> Path:
    """A PEER .AT2 file of ``values`` (g): four header lines, ``per_line`` values a line."""
    n = len(values)
    npts = (f"NPTS= {n:6d}, DT= {dt:.4f} SEC" if header == "new"
            else f"{n:8d} {dt:9.4f}    NPTS, DT")
    lines = ["PEER NGA STRONG MOTION DATABASE RECORD", "TEST EVENT 1/1/00, STATION, 000",
             "ACCELERATION TIME SERIES IN UNITS OF G", npts]
    lines += ["".join(f"{x:15.7E}" for x in values[i:i + per_line])
              for i in range(0, n, per_line)]
    path.write_text("\n".join(lines) + "\n")
    return path


VALUES_G = [0.0, 0.01, -0.03, 0.125, -0.2, 0.05, 0.0]  # PGA 0.2 g at sample 4


# ---- parsing -----------------------------------------------------------------------------
@pytest.mark.parametrize("header", ["new", "old"])
def test_an_at2_file_is_read_in_both_header_forms(tmp_path, header):
    """Both forms of the 4th line ('NPTS= 7, DT= .0050 SEC', '7 .0050 NPTS, DT'): t_i = i Δt,
    values in g × 9.80665; PGA 0.2 g = 1.96133 m/s² at t = 4 Δt = 0.02 s (by hand,
    1e-12)."""
    path = write_at2(tmp_path / "rec.AT2", VALUES_G, 0.005, header)
    t, a = read_at2(path)
    np.testing.assert_allclose(t, 0.005 * np.arange(7), rtol=0, atol=1e-15)
    np.testing.assert_allclose(a, VALUES_G, rtol=1e-12)
    rec = AccelerationRecord.read(path)  # the format from the name, in g
    f = rec.figures()
    assert f.pga == pytest.approx(0.2 * 9.80665, rel=1e-12)
    assert f.pga_g == pytest.approx(0.2, rel=1e-12)
    assert f.t_pga == pytest.approx(0.02, abs=1e-15)
    assert (f.npts, f.dt, f.duration) == (7, pytest.approx(0.005), pytest.approx(0.03))


def test_a_two_column_file_with_comments_header_and_separators_is_read(tmp_path):
    """CSV with a comment, a header line, semicolons and blanks; in cm/s² (gal): values / 100
    (by hand, 1e-12); the same numbers in m/s² give the same record."""
    path = tmp_path / "rec.csv"
    path.write_text("# station ABC, component N-S\ntime, acc\n0.00, 0.0\n0.01; 25.0\n"
                    "0.02  -50.0   # the peak\n\n0.03, 10.0\n")
    t, a = read_two_column(path)
    np.testing.assert_allclose(t, [0.0, 0.01, 0.02, 0.03], atol=1e-15)
    rec = AccelerationRecord.read(path, "two_column", units="gal")
    np.testing.assert_allclose(rec.values, [0.0, 0.25, -0.5, 0.1], rtol=1e-12)
    assert rec.figures().pga == pytest.approx(0.5, rel=1e-12)
    assert rec.figures().t_pga == pytest.approx(0.02, abs=1e-15)
    si = tmp_path / "si.txt"
    si.write_text("0 0\n0.01 0.25\n0.02 -0.5\n0.03 0.1\n")
    np.testing.assert_allclose(AccelerationRecord.read(si, "two_column", units="m/s2").values,
                               rec.values, rtol=1e-12)


def test_a_one_column_file_is_read_with_its_time_step(tmp_path):
    """One value a line (several on a line read in order), dt given, in g: t_i = i dt, the
    values × 9.80665 (by hand, 1e-12)."""
    path = tmp_path / "rec.txt"
    path.write_text("# one column, g\n0.0\n0.1\n-0.3 0.2\n0.0\n")
    t, a = read_one_column(path, 0.02)
    np.testing.assert_allclose(t, [0.0, 0.02, 0.04, 0.06, 0.08], atol=1e-15)
    np.testing.assert_allclose(a, [0.0, 0.1, -0.3, 0.2, 0.0])
    rec = AccelerationRecord.read(path, "one_column", units="g", dt=0.02, axis="y")
    assert rec.figures().pga == pytest.approx(0.3 * G_RECORD, rel=1e-12)
    assert rec.figures().t_pga == pytest.approx(0.04)
    assert rec.components()[0][1] == "y"


# ---- baseline figures --------------------------------------------------------------------
def test_arias_intensity_of_a_sine_over_whole_cycles_is_the_closed_form():
    """a₀ sin(2π t/T₁) over 4 whole cycles (T = 4 T₁ = 2 s), a₀ = 3 m/s²: ∫ a² dt = a₀² T/2,
    I_a = π a₀² T/(4 g) (closed form); dt = T₁/10 000, tolerance 1e-6 relative (the
    piecewise-linear record's own integral differs from the sine's by ≈ (ω dt)²/12 ≈ 3e-8)."""
    a0, T1, cycles = 3.0, 0.5, 4
    t = np.linspace(0.0, cycles * T1, cycles * 10_000 + 1)
    f = AccelerationRecord(t, a0 * np.sin(2 * np.pi * t / T1)).figures()
    assert f.arias == pytest.approx(math.pi * a0**2 * cycles * T1 / (4 * G_RECORD), rel=1e-6)
    assert f.pga == pytest.approx(a0, rel=1e-8)


def test_significant_duration_of_a_ramp_and_of_a_constant():
    """a = c t on [0, T]: ∫₀^t a² ∝ t³, so t_p = T p^{1/3} and D_5–95 = T (0.95^{1/3} −
    0.05^{1/3}) (closed form; the cumulative linear between samples: 1e-6 T with 10 000
    steps).  A constant a on [0, T]: the cumulative is linear, D_5–95 = 0.9 T exactly (1e-12)."""
    T = 10.0
    t = np.linspace(0.0, T, 10_001)
    f = AccelerationRecord(t, 0.3 * t).figures()
    assert f.t5 == pytest.approx(T * 0.05 ** (1 / 3), abs=1e-6 * T)
    assert f.t95 == pytest.approx(T * 0.95 ** (1 / 3), abs=1e-6 * T)
    assert f.d5_95 == pytest.approx(T * (0.95 ** (1 / 3) - 0.05 ** (1 / 3)), abs=2e-6 * T)
    c = AccelerationRecord(np.linspace(2.0, 2.0 + T, 11), np.full(11, -1.5)).figures()
    assert (c.t5, c.t95) == (pytest.approx(2.5, rel=1e-12), pytest.approx(11.5, rel=1e-12))
    assert c.d5_95 == pytest.approx(0.9 * T, rel=1e-12)
    assert c.arias == pytest.approx(math.pi / (2 * G_RECORD) * 1.5**2 * T, rel=1e-12)


def test_scaling_to_a_target_pga_a_factor_and_the_polarity(tmp_path):
    """target_pga_g = 0.35: PGA 0.35 g exactly (1e-14) and every value × 0.35/0.2; target_pga
    = 2 m/s²; scale 2.5: values × 2.5; polarity −1: values × −1, the same PGA and time."""
    path = write_at2(tmp_path / "rec.AT2", VALUES_G, 0.01)
    raw = AccelerationRecord.read(path)
    to = AccelerationRecord.read(path, target_pga_g=0.35)
    assert to.figures().pga_g == pytest.approx(0.35, rel=1e-14)
    np.testing.assert_allclose(to.values, raw.values * 0.35 / 0.2, rtol=1e-14)
    assert AccelerationRecord.read(path, target_pga=2.0).figures().pga == pytest.approx(
        2.0, rel=1e-14)
    np.testing.assert_allclose(AccelerationRecord.read(path, scale=2.5).values,
                               2.5 * raw.values, rtol=1e-15)
    flip = AccelerationRecord.read(path, polarity=-1, target_pga_g=0.35)
    np.testing.assert_array_equal(flip.values, -to.values)
    assert (flip.figures().pga, flip.figures().t_pga) == (to.figures().pga, to.figures().t_pga)
    assert flip.factor == pytest.approx(-0.35 / 0.2 / 1.0, rel=1e-14)
    assert "PGA 3.432 m/s² (0.35 g) at 0.04 s" in flip.figures().line()


# ---- malformed input ---------------------------------------------------------------------
AT2_HEAD = ("PEER\nEVENT\nACCELERATION TIME SERIES IN UNITS OF G\n"
            "NPTS=     4, DT= .0100 SEC\n")


@pytest.mark.parametrize(("name", "text", "kwargs", "words"), [
    ("a.AT2", AT2_HEAD + "0.1 0.2 abc 0.3\n", {}, ("line 5", "'abc' is not a number")),
    ("a.AT2", AT2_HEAD + "0.1 0.2 0.3\n", {}, ("line 5", "3 values", "NPTS = 4")),
    ("a.AT2", AT2_HEAD.replace("NPTS=     4, DT= .0100 SEC", "4 points") + "0.1 0.2\n", {},
     ("line 4", "expected the number of points and the time step")),
    ("a.AT2", AT2_HEAD.replace("ACCELERATION", "VELOCITY") + "1 2 3 4\n", {},
     ("line 3", "not an acceleration record")),
    ("a.AT2", "", {}, ("has 0 lines",)),
    ("b.csv", "0 0\n0.01 1\n0.005 2\n", {"format": "two_column", "units": "g"},
     ("line 3", "does not follow", "times must increase")),
    ("b.csv", "0 0\n0.01 1\n0.03 2\n0.04 1\n", {"format": "two_column", "units": "g"},
     ("line 3", "uniformly spaced")),
    ("b.csv", "0 0\n0.01 1 7\n", {"format": "two_column", "units": "g"},
     ("line 2", "expected two finite numbers")),
    ("b.csv", "# nothing\n", {"format": "two_column", "units": "g"}, ("no (time, value) rows",)),
    ("c.txt", "0.1\n0.2\nx\n", {"format": "one_column", "units": "g", "dt": 0.01},
     ("line 3", "'x' is not a number")),
    ("c.txt", "\n", {"format": "one_column", "units": "g", "dt": 0.01}, ("has 0 values",)),
    ("c.txt", "0\n0\n0\n", {"format": "one_column", "units": "g", "dt": 0.01},
     ("all values are zero",)),
])
def test_malformed_files_are_refused_naming_the_file_and_line(tmp_path, name, text, kwargs,
                                                               words):
    """Each malformed file: one ModelError whose item is the file and whose message names
    the line and the fault."""
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(ModelError) as e:
        AccelerationRecord.read(path, **kwargs)
    assert e.value.item == str(path)
    for w in words:
        assert w in e.value.problem
    assert "\n" not in str(e.value)


@pytest.mark.parametrize(("kwargs", "item", "words"), [
    ({"format": "two_column"}, "units", "give the units"),
    ({"format": "one_column", "units": "g"}, "dt", "give the time step"),
    ({"format": "two_column", "units": "ft/s2"}, "units", "must be one of g, m/s2"),
    ({"format": "csv", "units": "g"}, "format", "must be one of at2"),
    ({"units": "g"}, "format", "give the format"),
    ({"format": "two_column", "units": "g", "scale": 2, "target_pga": 1}, "target_pga",
     "together with scale"),
    ({"format": "two_column", "units": "g", "polarity": 2}, "polarity", "1 or -1"),
    ({"format": "two_column", "units": "g", "scale": -1}, "scale", "positive"),
    ({"format": "two_column", "units": "g", "axis": "w"}, "record 'r.txt'.axis",
     "one of x, y, z"),
])
def test_bad_arguments_are_refused_naming_the_argument(tmp_path, kwargs, item, words):
    """A missing or wrong argument: ModelError whose item is the argument."""
    path = tmp_path / "r.txt"
    path.write_text("0 0\n0.01 1\n")
    with pytest.raises(ModelError, match=words) as e:
        AccelerationRecord.read(path, name="r.txt", **kwargs)
    assert e.value.item == item
    at2 = write_at2(tmp_path / "a.AT2", VALUES_G, 0.01)
    with pytest.raises(ModelError, match="in g") as e:
        AccelerationRecord.read(at2, units="m/s2")
    assert e.value.item == "units"


# ---- the record in the dynamic driver ----------------------------------------------------
def flat_block(m_: float, f: float) -> tuple[sc.DiscreteModel, object, np.ndarray]:
    """A rigid block (ux, uy) of m_ kg on a flat base (friction f), at rest under its
    weight."""
    dm = sc.DiscreteModel(K=np.zeros((2, 2)), normal_rows=[[0, 1]], tangent_rows=[[1, 0]],
                          loads={"weight": {"uy": -m_ * G}}, friction=f,
                          dof_names=("ux", "uy"), program=[sc.Segment("weight", 1.0)],
                          dof_axes={"ux": "x", "uy": "y"})
    return dm, sc.solve_static(dm), m_ * np.eye(2)


def test_a_positive_record_moves_a_block_on_a_frictionless_base_backwards(tmp_path):
    """The sign convention: a constant record a = +0.2 g along x for 0.5 s on a block on a
    frictionless base: the ground accelerates along +x, the block stays, so its displacement
    relative to the ground is −a t²/2 (closed form; Newmark's average acceleration is exact
    for a constant acceleration: 1e-9 relative); the result says so."""
    path = tmp_path / "const.csv"
    t = np.round(np.arange(0.0, 0.5 + 1e-9, 0.01), 10)
    path.write_text("".join(f"{x:.2f}, 0.2\n" for x in t))
    rec = AccelerationRecord.read(path, "two_column", units="g")
    a = 0.2 * G_RECORD
    dm, st, M = flat_block(100.0, 0.0)
    res = sc.solve_dynamic(dm, dt=0.01, duration=0.5, mass=M, initial=st,
                           ground_acceleration=rec)
    assert res.status == Status.COMPLETED
    np.testing.assert_allclose(res.u[:, 0], -a * res.time**2 / 2, rtol=1e-9, atol=1e-15)
    assert "relative to the ground" in res.units["ground_acceleration"]
    assert "+axis" in res.units["ground_acceleration"]


def test_horizontal_and_vertical_records_act_together(tmp_path):
    """A block (f = 0.4) under a horizontal record A = 0.6 g along x and a vertical one
    a_v = 0.3 g along y (the ground accelerates upwards: the block is pressed by m (g + a_v)),
    both constant for 0.4 s: it slides relatively by −(A − f (g + a_v)) t²/2 (closed form,
    1e-9); with the vertical record alone it does not slide (a_v along y moves nothing along
    x), and the normal force is m (g + a_v) (1e-9)."""
    t = np.linspace(0.0, 0.4, 41)
    A, av, f, m_ = 0.6 * G_RECORD, 0.3 * G_RECORD, 0.4, 100.0
    hor = AccelerationRecord(t, np.full_like(t, A), axis="x", name="h")
    ver = AccelerationRecord(t, np.full_like(t, av), axis="y", name="v")
    dm, st, M = flat_block(m_, f)
    res = sc.solve_dynamic(dm, dt=0.01, duration=0.4, mass=M, initial=st,
                           ground_acceleration=GroundMotion((hor, ver)))
    assert res.status == Status.COMPLETED
    rel = A - f * (G + av)
    np.testing.assert_allclose(res.u[:, 0], -rel * res.time**2 / 2, rtol=1e-9, atol=1e-15)
    only_v = sc.solve_dynamic(dm, dt=0.01, duration=0.4, mass=M, initial=st,
                              ground_acceleration=ver)
    assert np.abs(only_v.u[:, 0]).max() == 0.0
    assert abs(only_v.N[-1, 0]) == pytest.approx(m_ * (G + av), rel=1e-9)
    with pytest.raises(ModelError, match="axis of record 0"):
        GroundMotion((hor, hor))


def test_three_components_in_3d_move_a_free_block_by_the_closed_form():
    """A free block (3 DOFs along x, y, z, its only CFE 1 km away) under constant records
    along x, y and z: u = −a t²/2 per axis (closed form, 1e-9); a z record in 2D is refused
    naming the axis."""
    names = ("ux", "uy", "uz")
    dm = sc.DiscreteModel(K=np.zeros((3, 3)), normal_rows=[[0, 0, 1]], tangent_rows=[[1, 0, 0]],
                          tangent2_rows=[[0, 1, 0]], gaps=1e3, friction=0.5, facets=8,
                          dof_names=names, loads={"P": {"ux": 0.0}},
                          dof_axes={"ux": "x", "uy": "y", "uz": "z"})
    t = np.linspace(0.0, 0.3, 31)
    acc = {"x": 1.0, "y": -2.0, "z": 0.5}
    gm = GroundMotion(tuple(AccelerationRecord(t, np.full_like(t, v), axis=ax, name=ax)
                            for ax, v in acc.items()))
    res = sc.solve_dynamic(dm, dt=0.01, duration=0.3, mass=np.eye(3), ground_acceleration=gm)
    assert res.status == Status.COMPLETED
    for j, v in enumerate(acc.values()):
        np.testing.assert_allclose(res.u[:, j], -v * res.time**2 / 2, rtol=1e-9, atol=1e-15)
    dm2, st, M = flat_block(1.0, 0.0)
    with pytest.raises(ModelError, match="axis 'z' in a 2D model"):
        sc.solve_dynamic(dm2, dt=0.01, duration=0.3, mass=M, initial=st,
                         ground_acceleration=gm.records[2])


def test_a_record_off_the_step_grid_is_warned_about_and_damped():
    """An oscillator (f = 2 Hz) under a record sampled at 5 ms: with dt = 5 ms or 2.5 ms the
    steps pass through the samples and the ledger's numerical term stays 0 (to 1e-15 of the
    input); with dt = 10 ms every step is cut at a sample and the landings remove energy
    (numerical > 1 % of the work put in; measured 30 % over 2 s) — what
    :func:`grid_problem` and ``solve_dynamic`` (RecordGridWarning) warn about."""
    from stepcontact.model.records import RecordGridWarning, grid_problem

    k = (2 * np.pi * 2.0) ** 2
    dm = sc.DiscreteModel(K=[[k]], normal_rows=[[1.0]], tangent_rows=[[0.0]], gaps=1e3,
                          loads={"P": [0.0]}, dof_axes=np.array([[1.0, 0.0]]))
    t = np.arange(401) * 0.005
    rec = AccelerationRecord(t, np.sin(2 * np.pi * 1.3 * t) * np.exp(-0.3 * t), name="r")
    for dt, off in ((0.005, False), (0.0025, False), (0.01, True)):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            res = sc.solve_dynamic(dm, dt=dt, duration=2.0, mass=np.eye(1),
                                   ground_acceleration=rec)
        said = [str(w.message) for w in caught if w.category is RecordGridWarning]
        assert len(said) == int(off)  # solve_dynamic warns where the steps cut the record
        assert res.status == Status.COMPLETED
        work = np.abs(res.energy["external"]).max()
        assert bool(res.energy["numerical"][-1] > 0.01 * work) is off
        if not off:
            assert abs(res.energy["numerical"][-1]) <= 1e-15 * work
        text = grid_problem(rec, dt)
        assert bool(text) is off
    assert "give dt = 0.005 s or a whole fraction of it" in grid_problem(rec, 0.01)


# ---- the model file ----------------------------------------------------------------------
BLOCK = block_on_floor("record-block") + """
[dynamics]
dt = 0.002
duration = 0.6
mass = "lumped"
"""


def test_a_model_file_record_slides_the_block_and_validate_prints_its_figures(tmp_path):
    """``[[dynamics.ground_motion]]`` with an AT2 record of 0.5 g for 0.2 s (then zero),
    scaled from 0.25 g by target_pga_g: the elastic block on a rough floor (f = 0.3) slides
    relative to the ground by −(A − f g) A t_p²/(2 f g) (the rigid-block closed form; 1 % for
    the block's elasticity, as tests/test_dynamic_inputs.py); ``validate`` prints the PGA
    (0.5 g), the Arias intensity π/(2g) A² t_p and the sign convention; ``--json`` carries
    them."""
    from stepcontact.io.modelfile import load_model

    n = 101  # 0 … 0.2 s in steps of 2 ms, then the record ends (zero after it)
    write_at2(tmp_path / "pulse.AT2", [0.25] * n, 0.002)
    path = tmp_path / "block.toml"
    path.write_text(BLOCK + '\n[[dynamics.ground_motion]]\nfile = "pulse.AT2"\n'
                    'target_pga_g = 0.5\n')
    model = load_model(path)
    res = sc.solve_dynamic(model, initial=sc.solve_static(model))
    assert res.status == Status.COMPLETED
    A, f, tp = 0.5 * G_RECORD, 0.3, 0.2
    slide = (A - f * G) * A * tp**2 / (2 * f * G)
    assert res.u[-1][0::2].mean() == pytest.approx(-slide, rel=1e-2)
    out = CliRunner().invoke(app, ["validate", str(path)])
    assert out.exit_code == 0, out.output
    text = " ".join(out.output.split())
    arias = math.pi / (2 * G_RECORD) * A**2 * tp
    assert "PGA 4.903 m/s² (0.5 g)" in text
    assert f"Arias intensity {arias:.4g} m/s" in text
    assert "relative to the ground" in text
    js = json.loads(CliRunner().invoke(app, ["validate", str(path), "--json"]).stdout)
    (fig,) = js["summary"]["ground_motion"]
    assert fig["pga_g"] == pytest.approx(0.5, rel=1e-14)
    assert fig["arias"] == pytest.approx(arias, rel=1e-12)


@pytest.mark.slow
def test_run_prints_the_records_figures_and_the_sign_convention(tmp_path):
    """``stepcontact run`` on a model file with a record (a constant 0.2 g for 0.1 s): the
    record's PGA (0.2 g = 1.961 m/s², by hand) and the sign convention are printed before the
    run, and the result file carries the convention; ``--json`` carries the figures under
    ``ground_motion`` and the run completes."""
    write_at2(tmp_path / "short.AT2", [0.2] * 51, 0.002)
    path = tmp_path / "block.toml"
    path.write_text(BLOCK.replace("duration = 0.6", "duration = 0.1")
                    + '\n[[dynamics.ground_motion]]\nfile = "short.AT2"\n')
    out = CliRunner().invoke(app, ["run", str(path), "-o", str(tmp_path / "r.nc"),
                                   "--no-plot", "--quiet"])
    assert out.exit_code == 0, out.output
    text = " ".join(out.output.split())
    assert "dynamics: ground motion x 'short.AT2': PGA 1.961 m/s² (0.2 g) at 0 s" in text
    assert "relative to the ground" in text
    dres = sc.load_result(tmp_path / "r-dynamic.nc")  # the result file says it too
    assert "relative to the ground" in dres.units["ground_acceleration"]
    js = CliRunner().invoke(app, ["run", str(path), "-o", str(tmp_path / "j.nc"), "--no-plot",
                                  "--json", "--quiet"])
    assert js.exit_code == 0, js.output
    summary = json.loads(js.stdout)
    (fig,) = summary["ground_motion"]
    assert (fig["interval"], fig["axis"], fig["npts"]) == ("dynamics", "x", 51)
    assert fig["pga_g"] == pytest.approx(0.2, rel=1e-12)
    assert summary["dynamics"]["status"] == "completed"


def test_a_record_longer_than_its_interval_is_warned_about(tmp_path):
    """A record of 0.2 s in an interval of 0.1 s: ``validate`` warns (exit 0), naming the
    table and both lengths — the rest of the record would not be applied."""
    write_at2(tmp_path / "long.AT2", [0.1] * 101, 0.002)
    path = tmp_path / "block.toml"
    path.write_text(BLOCK.replace("duration = 0.6", "duration = 0.1")
                    + '\n[[dynamics.ground_motion]]\nfile = "long.AT2"\n')
    out = CliRunner().invoke(app, ["validate", str(path), "--json"])
    assert out.exit_code == 0, out.output
    (warning,) = json.loads(out.stdout)["problems"]
    assert warning["item"] == "dynamics.ground_motion[0]"
    assert "lasts until 0.2 s, the interval only 0.1 s" in warning["message"]


def test_a_stage_interval_takes_a_record(tmp_path):
    """``[[stages.dynamics.ground_motion]]`` in examples/data/staged_shock.toml (a block
    struck sideways in the stage 'struck'): ``validate`` prints the record under
    ``stages[1].dynamics``; the stage's dynamic result carries the sign convention (the
    record acted), and the same run without the record does not."""
    from stepcontact.io.modelfile import load_model

    text = (Path(__file__).parents[1] / "examples" / "data" / "staged_shock.toml").read_text()
    write_at2(tmp_path / "q.AT2", list(0.1 * np.sin(2 * np.pi * np.arange(101) / 100)), 0.001)
    k = text.index("\n\n", text.index("[stages.dynamics]"))
    path = tmp_path / "st.toml"
    path.write_text(text[:k] + '\n\n[[stages.dynamics.ground_motion]]\nfile = "q.AT2"\n'
                    + text[k:])
    out = CliRunner().invoke(app, ["validate", str(path)])
    assert out.exit_code == 0, out.output
    assert "stages[1].dynamics: ground motion x 'q.AT2': PGA 0.9807 m/s² (0.1 g)" in " ".join(
        out.output.split())
    res = sc.solve_static(load_model(path))
    assert "relative to the ground" in res.dynamics["struck"].units["ground_acceleration"]
    plain = tmp_path / "plain.toml"
    plain.write_text(text)
    assert "ground_acceleration" not in sc.solve_static(
        load_model(plain)).dynamics["struck"].units


@pytest.mark.parametrize(("table", "item", "words"), [
    ('file = "none.AT2"', "dynamics.ground_motion[0].file", "none.AT2"),
    ('file = "r.txt"', "dynamics.ground_motion[0].format", "give the format"),
    ('file = "r.txt"\nformat = "two_column"', "dynamics.ground_motion[0].units",
     "give the units"),
    ('file = "r.txt"\nformat = "two_column"\nunits = "g"', "dynamics.ground_motion[0].file",
     "r.txt: line 3"),
    ('file = "p.AT2"\naxis = "z"', "dynamics.ground_motion[0].axis", "in a 2D model"),
    ('file = "p.AT2"\nscale = 2.0\ntarget_pga = 1.0', "dynamics.ground_motion[0]",
     "give one of scale"),
    ('file = "p.AT2"\npolarity = 2', "dynamics.ground_motion[0].polarity", ""),
])
def test_model_file_record_errors_name_the_field(tmp_path, table, item, words):
    """A wrong record table: ``validate`` exits 2 with one line naming the field (and the
    file's line where the file is at fault)."""
    (tmp_path / "r.txt").write_text("0 0\n0.01 1\n0.02 x\n")
    write_at2(tmp_path / "p.AT2", [0.1, 0.2, 0.1], 0.01)
    path = tmp_path / "m.toml"
    path.write_text(BLOCK + f"\n[[dynamics.ground_motion]]\n{table}\n")
    out = CliRunner().invoke(app, ["validate", str(path), "--json"])
    assert out.exit_code == 2, out.output
    probs = json.loads(out.stdout)["problems"]
    assert [p["item"] for p in probs] == [item]
    assert words in probs[0]["message"]


# ---- a real record shipped by a test dependency ------------------------------------------
def knet_test_record() -> Path:
    """ObsPy's K-NET test record (obspy/io/nied/tests/data/test.knet: AKT013 E-W, 1996/08/11
    M5.9, 100 Hz; shipped in the obspy wheel, LGPL-3), located without importing ObsPy."""
    spec = importlib.util.find_spec("obspy")
    if spec is None or spec.origin is None:
        pytest.skip("obspy (a test dependency shipping a strong-motion record) is not installed")
    path = Path(spec.origin).parent / "io" / "nied" / "tests" / "data" / "test.knet"
    if not path.is_file():
        pytest.skip(f"obspy does not ship {path}")
    return path


def test_a_real_strong_motion_record_has_the_pga_its_header_states(tmp_path):
    """The K-NET record parsed independently here (counts × 2000 gal / 8388608 less their
    mean, K-NET's convention) and written as a one-column file in gal and as an AT2 file in
    g: read back, its PGA is the header's "Max. Acc. (gal) 4.383" (to the header's rounding,
    5e-4 gal), the same from both files (1e-12), at the independent parse's time; its Arias
    intensity equals Simpson's rule on each linear segment (exact for a², 1e-12)."""
    lines = knet_test_record().read_text().splitlines()
    head = {ln[:18].strip(): ln[18:].strip() for ln in lines[:17]}
    hz = float(head["Sampling Freq(Hz)"].removesuffix("Hz"))
    num, den = head["Scale Factor"].split("(gal)/")
    counts = np.array([float(x) for ln in lines[17:] for x in ln.split()])
    gal = counts * float(num) / float(den)
    gal -= gal.mean()
    dt = 1.0 / hz
    one = tmp_path / "knet.txt"
    one.write_text("\n".join(f"{x:.12e}" for x in gal) + "\n")
    rec = AccelerationRecord.read(one, "one_column", units="gal", dt=dt)
    f = rec.figures()
    assert f.npts == len(counts) == 5900
    assert f.pga * 100 == pytest.approx(float(head["Max. Acc. (gal)"]), abs=5e-4)
    assert f.t_pga == pytest.approx(int(np.argmax(np.abs(gal))) * dt, abs=1e-12)
    at2 = write_at2(tmp_path / "knet.AT2", gal / 100 / G_RECORD, dt)
    assert AccelerationRecord.read(at2).figures().pga == pytest.approx(f.pga, rel=1e-6)
    a = gal / 100
    mid = (a[:-1] + a[1:]) / 2
    simpson = np.sum(dt / 6 * (a[:-1] ** 2 + 4 * mid**2 + a[1:] ** 2))
    assert f.arias == pytest.approx(math.pi / (2 * G_RECORD) * simpson, rel=1e-12)
