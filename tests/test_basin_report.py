"""The figures and report of the stilling-basin slab study (stepcontact.study.report), on a
synthetic dataset with the layout of basin.run_basin (no solver runs)."""

from __future__ import annotations

import dataclasses
import platform
import re
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
import scipy
import xarray as xr

import stepcontact
from figure_checks import assert_readable
from stepcontact.study import basin as B
from stepcontact.study import hydraulics as hy
from stepcontact.study import provenance as P
from stepcontact.study import report as R

PNG = b"\x89PNG\r\n\x1a\n"
DPI = 60  # enough to check the files, faster than the default
POSITIONS = (0.1, 0.5, 0.9)
DIRECTIONS = ("up", "down")
DURATIONS = (0.1, 1.0)
N_CFE = 21  # CFEs of the joint; the arrays are padded with one NaN like collect's


def synthetic(study: B.BasinStudy, failed: dict[str, str] | None = None) -> xr.Dataset:
    """A dataset laid out like run_basin's: the static case, then direction × duration ×
    position, with plausible made-up limits and stresses; ``failed``: id → message."""
    failed = failed or {}
    rng = np.random.default_rng(7)
    rows = [("static", "static", -1.0, "none", 0.0)]
    rows += [(f"{d}-t{t:g}-x{p:g}", "impulse", p, d, t)
             for d in DIRECTIONS for t in DURATIONS for p in POSITIONS]
    n = len(rows)
    L = study.length
    ratio = np.empty(n)
    x = np.full((n, N_CFE + 1), np.nan)
    sn, tau = np.full_like(x, np.nan), np.full_like(x, np.nan)
    for i, (_id, kind, p, d, t) in enumerate(rows):
        # "up" governs upstream, "down" downstream: the envelope follows neither alone
        shape = 0.8 * np.sin(np.pi * p) if d == "up" else 2.0 * p
        ratio[i] = 1.3 if kind == "static" else \
            (2.0 if d == "up" else 1.4) + shape * (0.5 + t) + 0.05 * rng.random()
        xi = np.linspace(0.0, L, N_CFE)
        x[i, :N_CFE] = xi
        sn[i, :N_CFE] = -1e3 * (200.0 * np.exp(-xi / 3.0) + 20.0 + 5.0 * i) \
            * (1.0 + 0.1 * np.cos(xi))
        tau[i, :N_CFE] = 0.3 * sn[i, :N_CFE] * np.exp(-xi / 5.0)
    status = np.array(["failed" if r[0] in failed else "ok" for r in rows])
    message = np.array([failed.get(r[0], "") for r in rows])
    bad = status == "failed"
    ratio[bad] = np.nan
    x[bad], sn[bad], tau[bad] = np.nan, np.nan, np.nan
    h = ratio * study.h_kr
    when = np.array([0.97 if r[1] == "static" else 0.4 * r[4] for r in rows])
    # where each joint first opens: the static case near the upstream end, an impulse under
    # its footprint's centre
    x_open = np.array([0.15 * L if r[1] == "static" else r[2] * L for r in rows])
    x_open[bad] = np.nan
    computed = np.array(["" if b else f"2026-01-0{1 + i % 3}T10:00:0{i % 10}Z"
                         for i, b in enumerate(bad)])
    software = np.where(bad, "", "stepcontact 0.0 (commit abc)")
    case = ("case", [r[0] for r in rows])
    return xr.Dataset(
        {"case_status": ("case", status), "case_message": ("case", message),
         "h_limit": ("case", h), "h_ratio": ("case", ratio),
         "h_failing": ("case", h - study.tol),
         "runs": ("case", np.where(bad, 0, 11).astype(np.int64)),
         "mode": ("case", np.where(bad, "", "lift-off")),
         "when": ("case", np.where(bad, np.nan, when)),
         "before": ("case", np.where(bad, np.nan, 0.95 * when)),
         "x_open": ("case", x_open), "computed": ("case", computed),
         "software": ("case", software),
         "x": (("case", "x_dim0"), x), "sigma_n": (("case", "sigma_n_dim0"), sn),
         "tau": (("case", "tau_dim0"), tau)},
        coords={"case": case, "kind": ("case", [r[1] for r in rows]),
                "position": ("case", [r[2] for r in rows]),
                "direction": ("case", [r[3] for r in rows]),
                "duration": ("case", [r[4] for r in rows])})


@pytest.fixture(scope="module")
def study() -> B.BasinStudy:
    return B.BasinStudy(positions=POSITIONS, directions=DIRECTIONS, durations=DURATIONS)


@pytest.fixture(scope="module")
def ds(study) -> xr.Dataset:
    return synthetic(study)


@pytest.fixture(scope="module")
def report(study, ds, tmp_path_factory) -> dict[str, Path]:
    return R.write_report(ds, study, tmp_path_factory.mktemp("report"), dpi=DPI)


def _line(fig, label: str):
    lines = [ln for ax in fig.axes for ln in ax.get_lines() if ln.get_label() == label]
    assert len(lines) == 1, [ln.get_label() for ax in fig.axes for ln in ax.get_lines()]
    return lines[0]


def test_figures_are_written_as_png(study, ds, report, tmp_path):
    for key in ("limits", "edge_stresses"):  # written by write_report through the path
        data = report[key].read_bytes()
        assert data.startswith(PNG) and len(data) > 5000
    assert sorted(p.name for p in report["limits"].parent.iterdir()) == [
        "edge_stresses.png", "limits.png"]  # written atomically: no temporary files left
    with pytest.raises(ValueError, match="suffix"):
        R.plot_limits(ds, study, tmp_path / "limits.bmp")
    assert not list(tmp_path.iterdir())


def test_limits_envelope_is_the_max_over_the_cases(study, ds):
    fig = R.plot_limits(ds, study)
    imp = ds["kind"].values == "impulse"
    pos, ratio = ds["position"].values, ds["h_ratio"].values
    dirs = ds["direction"].values
    env = _line(fig, "envelope of all impulses")
    np.testing.assert_allclose(env.get_xdata(), POSITIONS)
    expected = [ratio[imp & (pos == p)].max() for p in POSITIONS]
    np.testing.assert_allclose(env.get_ydata(), expected, rtol=1e-12)
    for d in DIRECTIONS:  # each direction: the max over its durations
        line = _line(fig, f"impulse {d} (max over durations)")
        np.testing.assert_allclose(
            line.get_ydata(), [ratio[imp & (pos == p) & (dirs == d)].max() for p in POSITIONS])
    for d in DIRECTIONS:  # and one thin line per duration
        for t in DURATIONS:
            line = _line(fig, f"{d}, T = {t:g} s")
            sel = imp & (dirs == d) & (ds["duration"].values == t)
            np.testing.assert_allclose(line.get_ydata(), ratio[sel])
    static = ratio[~imp][0]
    dashed = _line(fig, f"static loads only ({static:.2f})")
    assert dashed.get_linestyle() == "--"
    np.testing.assert_allclose(dashed.get_ydata(), static)
    title = fig.axes[0].get_title()
    assert "E0 = 25 m" in title and "h_kr = 3.48 m" in title and "5 m footprint" in title


def test_limits_skip_a_failed_case(study):
    ds = synthetic(study, failed={"up-t1-x0.5": "diverged"})
    fig = R.plot_limits(ds, study)
    env = _line(fig, "envelope of all impulses").get_ydata()
    imp = (ds["kind"].values == "impulse") & (ds["case_status"].values == "ok")
    sel = imp & (ds["position"].values == 0.5)
    assert env[1] == pytest.approx(ds["h_ratio"].values[sel].max())
    assert np.all(np.isfinite(env))


def test_edge_stresses_show_static_and_governing_case(study, ds):
    gov = R.governing_case(ds)
    ratio = np.where(ds["kind"].values == "impulse", ds["h_ratio"].values, -np.inf)
    assert gov == ds["case"].values[int(np.argmax(ratio))]
    fig = R.plot_edge_stresses(ds, study)
    labels = [ln.get_label() for ln in fig.axes[2].get_lines()]
    assert any(lb.startswith("static loads: h = ") for lb in labels)
    (g_label,) = [lb for lb in labels if lb.startswith(f"{gov}: h = ")]
    i = list(ds["case"].values).index(gov)
    (line,) = [ln for ln in fig.axes[2].get_lines() if ln.get_label() == g_label]  # σ_n
    n = np.isfinite(ds["x"].values[i])
    np.testing.assert_allclose(line.get_xdata(), ds["x"].values[i][n])
    np.testing.assert_allclose(line.get_ydata(), ds["sigma_n"].values[i][n] / 1e3)  # kPa
    # the zoomed panels show a third of the slab around the governing case's first opening
    # (x_open = its position · L_p), the left ones the whole slab
    lo, hi = fig.axes[2].get_xlim()
    x_gov = float(ds["x_open"].values[i])
    assert hi - lo == pytest.approx(study.length / 3, rel=1e-9)
    assert 0.0 <= lo and hi <= study.length * (1 + 1e-12)
    assert lo + 0.1 * (hi - lo) < x_gov < hi - 0.1 * (hi - lo)
    assert fig.axes[0].get_xlim() == pytest.approx((0.0, study.length))
    # friction limits ±f|σ_n| in the τ panel
    lim = [ln for ln in fig.axes[3].get_lines() if ln.get_linestyle() == "--"]
    peak = study.friction * np.abs(ds["sigma_n"].values[i][n]) / 1e3
    assert any(np.allclose(ln.get_ydata(), peak) for ln in lim)
    assert any(np.allclose(ln.get_ydata(), -peak) for ln in lim)


def test_edge_stresses_given_cases(study, ds):
    fig = R.plot_edge_stresses(ds, study, cases=["down-t0.1-x0.9"])
    labels = [ln.get_label() for ln in fig.axes[2].get_lines()]
    assert [lb for lb in labels if not lb.startswith("_")] == [
        lb for lb in labels if lb.startswith("down-t0.1-x0.9: h = ")]
    with pytest.raises(ValueError, match="nope"):
        R.plot_edge_stresses(ds, study, cases=["nope"])


def test_case_table(study, ds):
    rows = R.case_table(ds, study)
    assert [r["id"] for r in rows] == list(ds["case"].values)
    static = rows[0]
    assert static["kind"] == "static" and static["position"] is None
    assert static["direction"] is None and static["when_unit"] == "λ"
    r = rows[1]
    assert r == {**r, "kind": "impulse", "direction": "up", "duration": 0.1, "position": 0.1,
                 "mode": "lift-off", "runs": 11, "status": "ok", "when_unit": "s"}
    assert r["h_limit"] == pytest.approx(float(ds["h_limit"].values[1]))
    assert r["h_ratio"] == pytest.approx(float(ds["h_ratio"].values[1]))


class _Checker(HTMLParser):
    """Collects img sources and checks that the tags nest (void tags aside)."""

    VOID = {"meta", "img", "br", "hr", "link", "input"}

    def __init__(self):
        super().__init__()
        self.stack: list[str] = []
        self.images: list[str] = []
        self.errors: list[str] = []
        self.text: list[str] = []

    def handle_starttag(self, tag, attrs):
        if tag == "img":
            self.images.append(dict(attrs)["src"])
        if tag not in self.VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag):
        if not self.stack or self.stack.pop() != tag:
            self.errors.append(tag)

    def handle_data(self, data):
        self.text.append(data)


def test_report_files_and_markdown(study, ds, report):
    md = report["markdown"].read_text(encoding="utf-8")
    assert report["html"].is_file()
    for key in ("limits", "edge_stresses"):
        assert report[key].read_bytes().startswith(PNG)
    for cid in ds["case"].values:
        assert f"| {cid} |" in md
    for name, s, note in B.design_table(study, ds):
        assert f"| {name} | {s:.2f} | {s / study.h_kr:.2f} | {note} |" in md
    for f in dataclasses.fields(study):
        assert f"| {f.name} |" in md
    j = study.jump
    assert f"| unit discharge q | {j.q:.2f} | m²/s |" in md
    assert f"| sequent depth h2 | {j.h2:.2f} | m |" in md
    assert "recalled, not checked against the source" in md
    assert "![Fig. 1" in md and "(figures/limits.png)" in md
    assert "## Failed cases" not in md


def test_report_html_parses_and_images_exist(report):
    text = report["html"].read_text(encoding="utf-8")
    checker = _Checker()
    checker.feed(text)
    checker.close()
    assert checker.errors == [] and checker.stack == []
    assert text.startswith("<!DOCTYPE html>") and "<style>" in text
    assert len(checker.images) == 2
    for src in checker.images:
        assert (report["html"].parent / src).is_file()
    assert "4 < Fr1 < 20" in "".join(checker.text)  # escaped in the source, text when parsed
    assert "4 < Fr1" not in text


def test_failed_case_section(study, tmp_path):
    msg = "SolverError: <no convergence> at λ = 0.31"
    ds = synthetic(study, failed={"down-t1-x0.5": msg})
    paths = R.write_report(ds, study, tmp_path, dpi=DPI)
    md = paths["markdown"].read_text(encoding="utf-8")
    section = md.split("## Failed cases", 1)[1].split("\n## ", 1)[0]
    assert f"- down-t1-x0.5 (failed): {msg}" in section
    assert "up-t1-x0.5" not in section
    page = paths["html"].read_text(encoding="utf-8")
    assert "&lt;no convergence&gt;" in page and "<no convergence>" not in page
    row = [ln for ln in md.splitlines() if ln.startswith("| down-t1-x0.5 |")][0]
    assert row.endswith("| failed |") and "| — |" in row


def test_every_input_of_the_study_is_described_in_the_report():
    import dataclasses

    from stepcontact.study import report
    from stepcontact.study.basin import BasinStudy

    missing = {f.name for f in dataclasses.fields(BasinStudy)} - set(report._FIELDS)
    assert not missing, f"BasinStudy fields without a unit and meaning in the report: {missing}"


# ------------------------------------------------------------ what a reviewer needs to accept ---

def _section(md: str, heading: str) -> str:
    """The text of the report's section ``## heading`` (to the next ``## ``)."""
    assert f"## {heading}\n" in md, heading
    return md.split(f"## {heading}\n", 1)[1].split("\n## ", 1)[0]


def _row(section: str, first: str) -> list[str]:
    """The cells of the table row whose first cell is ``first``."""
    (line,) = [ln for ln in section.splitlines() if ln.startswith(f"| {first} |")]
    return [c.strip() for c in line.strip("|").split(" | ")]


def test_every_figure_of_the_report_is_readable(study, ds):
    """No two texts or legends overlap and none leaves the figure (tests/figure_checks.py),
    for both figures; the left panels of Fig. 2 have legends naming the cases, the
    triangles of the first openings and the zoomed window."""
    assert_readable(R.plot_limits(ds, study))
    fig = R.plot_edge_stresses(ds, study)
    assert_readable(fig)
    gov = R.governing_case(ds)
    for ax in fig.axes[:2]:  # left column: σ_n, τ over the whole slab
        leg = ax.get_legend()
        assert leg is not None
        texts = [t.get_text() for t in leg.get_texts()]
        assert "static loads" in texts and gov in texts
    assert {"first opening (case's colour)", "zoomed window"} <= {
        t.get_text() for t in fig.axes[0].get_legend().get_texts()}
    # a triangle at each case's first opening (x_open), on the whole-slab σ_n panel
    marks = [ln for ln in fig.axes[0].get_lines() if ln.get_marker() == "v"
             and len(ln.get_xdata())]
    i_gov = list(ds["case"].values).index(gov)
    assert sorted(float(m.get_xdata()[0]) for m in marks) == pytest.approx(
        sorted([float(ds["x_open"].values[0]), float(ds["x_open"].values[i_gov])]))


def test_the_zoom_follows_the_governing_case_to_any_part_of_the_slab(study, ds):
    """The zoom window (L_p/3 wide) is centred on the governing case's first opening, and
    kept inside the slab near its ends."""
    L = study.length
    gov = list(ds["case"].values).index(R.governing_case(ds))
    for x, expected in ((0.5 * L, (L / 3, 2 * L / 3)), (0.02 * L, (0.0, L / 3)),
                        (0.99 * L, (2 * L / 3, L))):
        d = ds.copy(deep=True)
        d["x_open"].values[gov] = x
        assert R.zoom_window(d, study, [0, gov]) == pytest.approx(expected, rel=1e-12)
    # a store without x_open (written before it was kept): the least compressed CFE
    d = ds.drop_vars("x_open")
    x, sn, _tau = R._stresses(d, gov)
    assert R.failure_position(d, gov) == x[int(np.argmax(sn))]


def _git(*args, cwd):
    return subprocess.run(["git", *args], cwd=cwd, capture_output=True, text=True,
                          check=True).stdout.strip()


def test_the_report_names_the_software_and_the_run(study, ds, report):
    """Version equal to stepcontact.__version__, the commit equal to git's own answer for the
    package's directory (or "not a git checkout"), Python/NumPy/SciPy versions, the dates
    of the cases (the dataset's earliest and latest) and who computed them."""
    md = report["markdown"].read_text(encoding="utf-8")
    sec = _section(md, "Software and run")
    assert _row(sec, "stepcontact version")[1] == stepcontact.__version__
    pkg = Path(stepcontact.__file__).parent
    commit, dirty = P.git_commit(pkg)
    assert _row(sec, "git commit")[1] == commit
    if shutil.which("git") and commit != P.NOT_A_CHECKOUT:
        assert commit == _git("rev-parse", "HEAD", cwd=pkg)
    assert _row(sec, "Python")[1] == platform.python_version()
    assert _row(sec, "NumPy")[1] == np.__version__
    assert _row(sec, "SciPy")[1] == scipy.__version__
    computed = sorted(c for c in ds["computed"].values if c)
    assert _row(sec, "cases computed")[1] == f"{computed[0]} to {computed[-1]}"
    assert _row(sec, "cases computed by")[1] == "stepcontact 0.0 (commit abc)"
    assert "other software than the one that wrote this report" in sec
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ",
                        _row(sec, "report written")[1])
    assert _row(sec, "uncommitted changes")[1].startswith(
        {True: "yes", False: "no", None: ("—", "unknown")}[dirty])


def test_the_commit_is_found_in_a_checkout_and_nothing_fails_outside_one(tmp_path,
                                                                        monkeypatch):
    """git_commit against git itself on a fresh repository: HEAD, then the uncommitted
    change; a directory outside any repository, an untracked package and a missing git give
    "not a git checkout"."""
    assert P.git_commit(tmp_path) == (P.NOT_A_CHECKOUT, None)
    if shutil.which("git"):
        repo = tmp_path / "repo"
        repo.mkdir()
        _git("init", "-q", cwd=repo)
        (repo / "__init__.py").write_text("x = 1\n")
        assert P.git_commit(repo) == (P.NOT_A_CHECKOUT, None)  # not tracked yet
        _git("add", "__init__.py", cwd=repo)
        _git("-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "one", cwd=repo)
        head = _git("rev-parse", "HEAD", cwd=repo)
        assert P.git_commit(repo) == (head, False)
        (repo / "__init__.py").write_text("x = 2\n")
        assert P.git_commit(repo) == (head, True)
        assert P.software_text("9.9", head, True) == \
            f"stepcontact 9.9 (commit {head}, with uncommitted changes)"
    monkeypatch.setenv("PATH", str(tmp_path / "nowhere"))  # no git at all
    assert P.git_commit() == (P.NOT_A_CHECKOUT, None)
    assert P.provenance()["software"] == f"stepcontact {stepcontact.__version__} " \
        "(not a git checkout)"


def test_the_report_states_every_assumption(study, report):
    """Foundation block and supports, soil E and ν, the joint's friction and cohesion, the
    water pressures and the criterion with its reason, with the study's values."""
    sec = _section(report["markdown"].read_text(encoding="utf-8"), "Assumptions")
    L = study.length
    assert f"{L / 2:.2f} m deep" in sec and f"extending {L / 2:.2f} m (L_p/2)" in sec
    assert "bottom is fixed (u = v = 0)" in sec and "sides are on rollers (u = 0)" in sec
    assert "E = 100 MPa, ν = 0.3" in sec and "E = 30 GPa, ν = 0.2" in sec
    assert f"Coulomb friction f = {study.friction:g}, no cohesion (c = 0)" in sec
    assert f"tailwater depth h2 = {study.jump.h2:.2f} m" in sec
    assert "Failure criterion: lift-off = the first opening of any CFE" in sec
    assert "The design question is whether the flow can lift the slab" in sec
    other = dataclasses.replace(study, criterion="separation", friction=0.45)
    sec = _section(R._to_markdown("t", R._assumptions(other)), "Assumptions")
    assert "the whole joint open at once (the slab floats)" in sec and "f = 0.45" in sec


def _with_check(ds: xr.Dataset, study: B.BasinStudy, h_fine: float) -> xr.Dataset:
    """The synthetic dataset with a mesh check of its governing case giving ``h_fine``."""
    gov = B.governing(ds)
    i = list(ds["case"].values).index(gov)
    h0 = float(ds["h_limit"].values[i])
    chk = B.MeshCheck(case=gov, cells=(study.cells, B.refined(study).cells), h=(h0, h_fine),
                      h_failing=(h0 - study.tol, h_fine - study.tol),
                      x_open=(float(ds["x_open"].values[i]), 40.0),
                      mode=("lift-off", "lift-off"), tol=study.tol, runs=4, seconds=12.5)
    out = ds.copy()
    out.attrs["mesh_check"] = chk.to_json()
    return out


@pytest.mark.parametrize("change, verdict", [
    (lambda h, tol: 0.5 * tol, "Acceptable"),  # within the bisection's tolerance
    (lambda h, tol: 0.03 * h, "Acceptable"),  # 3 %: more than tol, within 5 %
    (lambda h, tol: -0.08 * h, "Not acceptable")])  # 8 %
def test_the_mesh_section_states_both_meshes_and_the_difference(study, ds, tmp_path, change,
                                                                 verdict):
    """The governing limit on both meshes and their difference (absolute and relative) as
    the hand subtraction gives them, with the verdict of the stated rule (|Δ| ≤ tol or
    ≤ 5 %); the mesh table's CFE count is the slab's cells along + 1 (node CFEs)."""
    gov = B.governing(ds)
    h0 = float(ds["h_limit"].values[list(ds["case"].values).index(gov)])
    d = _with_check(ds, study, h0 + change(h0, study.tol))
    md = R.write_report(d, study, tmp_path, dpi=DPI)["markdown"].read_text(encoding="utf-8")
    sec = _section(md, "Mesh and its convergence")
    chk = B.MeshCheck.of(d)
    coarse, fine = (float(v) for v in _row(sec, "limit thickness h_p (m)")[1:3])
    assert coarse == pytest.approx(h0, abs=5e-4) and fine == pytest.approx(chk.h[1], abs=5e-4)
    diff = _row(sec, "limit thickness h_p (m)")[3]
    dh = chk.h[1] - chk.h[0]
    assert diff == f"{dh:+.3f} m ({100 * dh / chk.h[1]:+.1f} %)"
    assert f"Check: the governing case ({gov}" in sec
    assert f"{study.cells[0]} × {study.cells[1]} → {2 * study.cells[0]} × " \
           f"{2 * study.cells[1]}" in sec
    assert sec.count(verdict + ":") == 1
    ok = abs(dh) <= study.tol or abs(dh) <= 0.05 * chk.h[1]
    assert (verdict == "Acceptable") == ok
    for name, n in (("the study's mesh", study.cells[0]), ("the check's mesh",
                                                             2 * study.cells[0])):
        assert _row(sec, name)[3].startswith(f"{n + 1} (length ")
    assert "quad4" in sec


def test_without_a_mesh_check_the_report_says_so(report):
    sec = _section(report["markdown"].read_text(encoding="utf-8"), "Mesh and its convergence")
    assert "No mesh-convergence check was run" in sec


def test_the_report_explains_where_the_design_formulas_differ(study, ds, report):
    """In the report itself, each design formula's idealisation and its value against the
    study's: the flotation thickness at SF = 1 from an independent integral of the net
    uplift, the ratio of the static limit to it and to the kern rule."""
    md = report["markdown"].read_text(encoding="utf-8")
    sec = _section(md, "Why the study's limits differ from the design formulas")
    jump, L = study.jump, study.length
    x = np.linspace(0.0, L, 40001)
    net = hy.base_uplift(jump, x) - hy.top_pressure(jump, x)
    U = float(np.sum(0.5 * (net[1:] + net[:-1]) * np.diff(x)))  # trapezoids, 40 000 of them
    float_1 = U / ((2400 * 9.81 - hy.GAMMA_W) * L)
    assert f"USACE flotation ({float_1:.2f} m at SF = 1)" in sec
    static = float(ds["h_limit"].values[0])
    assert f"({static:.2f} m, {static / float_1:.2f} × it)" in sec
    kern = {n: h for n, h, _ in B.design_table(study, ds)}[
        "kern rule, rigid slab on a Winkler bed, deficit of the mean profile"]
    assert f"Kern rule ({kern:.2f} m): a rigid slab on a Winkler bed" in sec
    assert f"({static / kern:.2f} × the kern rule's)" in sec
    assert "Fiorotto & Rinaldo (1.86 m" in sec and "Dombrovsky (3.07 m)" in sec
    assert "treat the slab as rigid" in sec


def test_every_coefficient_is_in_the_report_with_its_check_in_words(report):
    """Each coefficient of hydraulics.COEFFICIENTS, with its status spelled out; no bare
    [RECALLED]/[SEEN] tags are left anywhere in the report."""
    md = report["markdown"].read_text(encoding="utf-8")
    sec = _section(md, "Coefficients and their sources")
    for c in hy.COEFFICIENTS:
        cells = _row(sec, c.name)
        assert cells[4].startswith(c.status)
    assert _row(sec, "Dombrovsky thickness")[4] == "recalled, not checked against the source"
    assert _row(sec, "critical depth of the design discharge h_kr (m)")[4].startswith(
        "checked against the source: the article's text")
    assert "[RECALLED" not in md and "[SEEN" not in md and "[DERIVED" not in md
    assert "recalled, not checked against the source" in _section(md, "Formulas and sources")
