"""The stilling-basin study end to end on a tiny configuration: the hydraulic loads, the cases
as a resumable sweep, the physics of the answers, the design table and the command line."""

from __future__ import annotations

import dataclasses
import os

import numpy as np
import pytest
from typer.testing import CliRunner

from stepcontact.cli import app
from stepcontact.errors import ModelError
from stepcontact.study import basin as B
from stepcontact.study import hydraulics as hy

TINY = dict(cells=(10, 2), positions=(0.5,), directions=("up",), durations=(0.2,),
            steps=10, tol=0.1)


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    st = B.quick(**TINY)
    store = tmp_path_factory.mktemp("basin")
    return st, store, B.run_basin(st, store, executor="serial", progress=False)


def test_the_study_finds_each_cases_limit_and_the_impulse_needs_more(tiny):
    st, store, ds = tiny
    assert list(ds["case_status"].values) == ["ok", "ok"]
    kind = ds["kind"].values.astype(str)
    h = dict(zip(kind, ds["h_limit"].values, strict=True))
    # the static deficit of the jump needs a real slab; an upward impulse on top of it more
    assert 0.2 * st.h_kr < h["static"] < 3 * st.h_kr
    assert h["impulse"] >= h["static"] - st.tol
    assert np.allclose(ds["h_ratio"].values, ds["h_limit"].values / st.h_kr)
    # each limit is bracketed by a failing slab within the tolerance
    assert np.all(ds["h_limit"].values - ds["h_failing"].values <= st.tol + 1e-12)
    # the static case fails by lift-off near the upstream edge (the jump's deficit is largest
    # at the toe): just before it, a CFE in the upstream third carries nearly nothing while
    # the rest of the base is compressed (compression negative; the end CFE at the slab's
    # corner carries the corner's concentrated force)
    i = int(np.flatnonzero(kind == "static")[0])
    assert ds["mode"].values[i] == "lift-off"
    sn = ds["sigma_n"].values[i]
    x = ds["x"].values[i]
    assert x[0] == pytest.approx(0.0, abs=1e-9) and np.all(np.diff(x) > 0)
    assert np.all(sn <= 1e-6 * np.abs(sn).max())
    k = int(np.argmin(np.abs(sn)))
    assert x[k] < st.length / 3 and abs(sn[k]) < 0.05 * np.abs(sn).max()
    # every case kept its run at the failing thickness
    for case in ds["case"].values:
        assert (store / "results" / f"{case}.nc").is_file()


def test_a_second_run_of_the_study_runs_nothing_again(tiny):
    st, store, ds = tiny
    files = [*(store / "cases").glob("*.nc"), *(store / "mesh-check" / "cases").glob("*.nc")]
    assert len(files) == len(ds["case"]) + 1  # the cases and the mesh check's one
    stamps = {p: p.stat().st_mtime_ns for p in files}
    again = B.run_basin(st, store, executor="serial", progress=False)
    assert {p: p.stat().st_mtime_ns for p in files} == stamps
    assert np.array_equal(again["h_limit"].values, ds["h_limit"].values)
    assert B.MeshCheck.of(again) == B.MeshCheck.of(ds)


def test_the_mesh_check_solves_the_governing_case_again_on_a_finer_mesh(tiny):
    """The governing case (the impulse case: the largest limit) on the 20 × 4 mesh: its
    bracket checked independently — the slab of the fine limit passes and the thickest
    failing one fails (slab.check on the refined model) — and an independent search from the
    default start (halving/doubling instead of the check's steps from the coarse limit)
    lands within the tolerance.  The coarse values are the dataset's own."""
    from stepcontact.study import slab as S

    st, store, ds = tiny
    chk = B.MeshCheck.of(ds)
    ids = list(ds["case"].values)
    i = ids.index("up-t0.2-x0.5")
    assert chk.case == "up-t0.2-x0.5" == B.governing(ds) and chk.status == "ok"
    assert chk.cells == ((10, 2), (20, 4))
    assert chk.h[0] == float(ds["h_limit"].values[i])
    assert chk.x_open[0] == float(ds["x_open"].values[i])
    fine = B.refined(st)
    imp = fine.impulse(0.5, "up", 0.2)
    opts = dict(dt=0.2 / fine.steps, duration=1.5 * 0.2)
    assert S.check(fine.slab(chk.h[1]), imp, **opts).passes
    failed = S.check(fine.slab(chk.h_failing[1]), imp, keep=True, **opts)
    assert not failed.passes and failed.lifted
    assert 0 < chk.h[1] - chk.h_failing[1] <= st.tol + 1e-12
    assert chk.x_open[1] == B.first_opening(failed.result)
    alone = S.limit_thickness(fine.slab(0.5 * st.h_kr), imp, tol=st.tol, **opts)
    assert abs(alone.thickness - chk.h[1]) <= st.tol  # two brackets of width ≤ tol
    assert chk.difference == chk.h[1] - chk.h[0]


def test_the_report_of_a_run_states_the_software_and_the_mesh_check(tiny, tmp_path):
    """The report written from the run: the version equal to stepcontact.__version__, every
    case computed by the software that wrote it, and the mesh check's two limits with the
    difference equal to their subtraction (to the printed 1 mm)."""
    import stepcontact
    from stepcontact.study import report as R

    st, store, ds = tiny
    md = R.write_report(ds, st, tmp_path, dpi=50)["markdown"].read_text(encoding="utf-8")
    assert f"| stepcontact version | {stepcontact.__version__} |" in md
    assert "Every case was computed by the software that wrote this report." in md
    chk = B.MeshCheck.of(ds)
    (row,) = [ln for ln in md.splitlines() if ln.startswith("| limit thickness h_p (m) |")]
    coarse, fine, diff = (c.strip() for c in row.strip("|").split(" | ")[1:4])
    assert float(coarse) == pytest.approx(float(ds["h_limit"].values[1]), abs=5e-4)
    assert float(fine) == pytest.approx(chk.h[1], abs=5e-4)
    d = float(diff.split(" m")[0])
    assert d == pytest.approx(float(fine) - float(coarse), abs=1.5e-3)
    assert ("Acceptable:" in md) == (abs(d) <= st.tol or abs(d) <= 0.05 * chk.h[1])
    # the figures of the run: readable, Fig. 2's zoom around the impulse's first opening
    from figure_checks import assert_readable

    assert_readable(R.plot_limits(ds, st))
    fig = R.plot_edge_stresses(ds, st)
    assert_readable(fig)
    lo, hi = fig.axes[2].get_xlim()
    assert lo < chk.x_open[0] < hi


def test_the_design_table_beside_the_formulas():
    st = B.BasinStudy()
    rows = {name: h for name, h, _ in B.design_table(st)}
    jump = st.jump
    # Fiorotto–Rinaldo with the reference case's coefficients: 1.86 m (docs/slab-hydraulics)
    fr = rows["Fiorotto & Rinaldo (1992), Ω = 0.15, C⁺p + C⁻p = 0.8"]
    assert fr == pytest.approx(0.15 * 0.8 * jump.velocity_head * hy.GAMMA_W
                               / (2400 * 9.81 - hy.GAMMA_W), rel=1e-12)
    assert fr == pytest.approx(1.86, abs=0.01)
    # flotation: the thickness grows in proportion to the required safety factor
    usual = rows["USACE flotation, SF = 1.3 (usual)"]
    extreme = rows["USACE flotation, SF = 1.1 (extreme)"]
    assert usual / extreme == pytest.approx(1.3 / 1.1, rel=1e-12)
    # and is the thickness whose submerged weight is SF times the mean profile's net uplift
    x = np.linspace(0, st.length, 20001)
    net = hy.base_uplift(jump, x) - hy.top_pressure(jump, x)
    resultant = float(np.sum(0.5 * (net[1:] + net[:-1]) * np.diff(x)))  # N/m
    assert usual * (2400 * 9.81 - hy.GAMMA_W) * st.length == pytest.approx(1.3 * resultant,
                                                                           rel=1e-6)
    assert rows["Dombrovsky, t = 0.15 V1 √h1"] == pytest.approx(3.07, abs=0.01)


def test_a_compliant_layer_from_the_soil_and_joints_at_the_ends():
    st = B.BasinStudy(layer_thickness=0.5, end_joints=0.4)
    slab = st.slab(2.0)
    kn, kt = slab.layer.stiffness_per_area("layer")
    E, nu = st.soil.E, st.soil.nu
    assert kn == pytest.approx(E / ((1 - nu**2) * 0.5), rel=1e-12)  # eq. (11): C_n/A
    assert kt == pytest.approx(E / (2 * (1 + nu) * 0.5), rel=1e-12)
    assert slab.end_joints == 0.4
    assert B.BasinStudy().slab(2.0).layer is None


def test_bad_study_inputs_name_the_field():
    for bad, item in ((dict(criterion="cracks"), "criterion"), (dict(amplitude=-1.0),
                      "amplitude"), (dict(directions=("sideways",)), "directions"),
                      (dict(E0=1.0), "E0"), (dict(steps=2), "steps"),
                      (dict(positions=(0.5, 1.5)), "positions"),
                      (dict(durations=(0.0,)), "durations")):
        with pytest.raises(ModelError, match=item):
            dataclasses.replace(B.BasinStudy(), **bad)


def test_the_study_command(tiny, tmp_path, monkeypatch):
    st, store, ds = tiny
    # the command on the study of the fixture (its --quick study replaced by the tiny one):
    # the cases are done, so it resumes them and writes the report
    monkeypatch.setattr(B, "quick", lambda **changes: st)
    stamps = {p: p.stat().st_mtime_ns for p in (store / "cases").glob("*.nc")}
    runner = CliRunner()
    r = runner.invoke(app, ["study", "slab", "--quick", "--position", "0.5", "--duration",
                            "0.2", "-o", str(store), "--serial"],
                      env={**os.environ, "COLUMNS": "200"})
    assert r.exit_code == 0, r.output
    assert {p: p.stat().st_mtime_ns for p in (store / "cases").glob("*.nc")} == stamps
    for case in ds["case"].values:  # the table of cases
        assert str(case) in r.output
    assert "Fiorotto & Rinaldo" in r.output
    chk = B.MeshCheck.of(ds)
    assert (f"mesh check (up-t0.2-x0.5): h_p {chk.h[0]:.3f} m on 10 × 2, {chk.h[1]:.3f} m on "
            f"20 × 4: {chk.h[1] - chk.h[0]:+.3f} m") in r.output
    assert (store / "report" / "report.md").is_file()
    assert (store / "report" / "report.html").is_file()
    assert (store / "report" / "figures" / "limits.png").stat().st_size > 0
    md = (store / "report" / "report.md").read_text(encoding="utf-8")
    assert "## Mesh and its convergence" in md and "No mesh-convergence check" not in md
    bad = runner.invoke(app, ["study", "tunnel", "-o", str(tmp_path / "x")])
    assert bad.exit_code == 2
    assert "unknown study 'tunnel'" in bad.output and "Traceback" not in bad.output
