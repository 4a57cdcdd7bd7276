"""The figures and report of the stilling-basin slab study (stepcontact.study.report), on a
synthetic dataset with the layout of basin.run_basin (no solver runs)."""

from __future__ import annotations

import dataclasses
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from stepcontact.study import basin as B
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
    case = ("case", [r[0] for r in rows])
    return xr.Dataset(
        {"case_status": ("case", status), "case_message": ("case", message),
         "h_limit": ("case", h), "h_ratio": ("case", ratio),
         "h_failing": ("case", h - study.tol),
         "runs": ("case", np.where(bad, 0, 11).astype(np.int64)),
         "mode": ("case", np.where(bad, "", "lift-off")),
         "when": ("case", np.where(bad, np.nan, when)),
         "before": ("case", np.where(bad, np.nan, 0.95 * when)),
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
    # the zoomed panels show the upstream third, the left ones the whole slab
    assert fig.axes[2].get_xlim()[1] == pytest.approx(study.length / 3)
    assert fig.axes[0].get_xlim()[1] == pytest.approx(study.length)
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
    assert "[RECALLED]" in md and "![Fig. 1" in md and "(figures/limits.png)" in md
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
