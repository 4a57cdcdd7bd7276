"""Figures (deformed shape, contact stresses, load–displacement, event timeline), the
``plot`` and ``info`` commands and the notebook conversions, on small real runs."""

from __future__ import annotations

import json

import matplotlib.image as mpimg
import numpy as np
import pytest
from matplotlib.colors import to_rgba
from numpy.testing import assert_allclose, assert_array_equal
from typer.testing import CliRunner

import stepcontact as sc
import verification_models as vm
from stepcontact.cli import app
from stepcontact.enums import ContactState
from stepcontact.post.plotting import (
    STATE_COLORS,
    TRANSITION_MARKERS,
    plot_deformed,
    plot_event_timeline,
    plot_interfaces,
    plot_load_displacement,
)

runner = CliRunner()
DPI = 50  # small images: fast to write and read
CONCRETE = sc.Material(E=30e9, nu=0.2, density=2400)  # Pa, -, kg/m³
NX, NY = 4, 2  # block mesh


def block_model(element: str = "quad4") -> sc.Model:
    """A block on a base: self-weight, then a push at the block's left side until it slides."""
    return vm.pushed_block(base_cells=(8, 1), block_cells=(NX, NY), element=element,
                           name="block")


def frame_model() -> sc.Model:
    """A beam on frictionless supports; weight, then its right end is lifted."""
    return vm.beam_on_supports((0.0, 4.0, 8.0))


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """In-memory results and their files: block (all fields), block (segment ends only),
    frame (all fields)."""
    d = tmp_path_factory.mktemp("runs")
    block = sc.solve_static(block_model(), store_fields="all")
    ends = sc.solve_static(block_model(), store_fields="ends")
    frame = sc.solve_static(frame_model(), store_fields="all")
    for name, res in (("block", block), ("ends", ends), ("frame", frame)):
        res.save(d / f"{name}.nc")
    return {"block": block, "ends": ends, "frame": frame, "dir": d}


def check_png(path, fig, dpi=DPI):
    """``path`` is a non-blank PNG of ``fig`` at ``dpi``: the figure's size × dpi pixels."""
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG file"
    img = mpimg.imread(path)
    w, h = fig.get_size_inches()
    assert img.shape[:2] == (int(h * dpi), int(w * dpi))  # Agg truncates to whole pixels
    assert np.ptp(img[..., :3]) > 0.5


def figure_content(fig) -> dict:
    """What a figure draws: its size, titles and legends and, axis by axis, the labels,
    texts, legend entries, the data and style of every line, and the geometry, colours and
    values of every collection (cells, outlines, CFE dots, shaded diagrams, state strips)."""

    def collection(c) -> dict:
        out = {"type": type(c).__name__, "edge": c.get_edgecolor()}
        if c.get_array() is not None:  # colours mapped from values (set when drawn)
            out["face"] = c.to_rgba(np.ravel(c.get_array()))
        else:
            out["face"] = c.get_facecolor()
        if hasattr(c, "get_coordinates"):  # QuadMesh: the cells and their values
            out |= {"coordinates": c.get_coordinates(), "array": c.get_array()}
        elif type(c).__name__ == "Quiver":  # arrows: their paths are made when drawn
            out |= {"uv": np.c_[c.U, c.V], "offsets": c.get_offsets(), "scale": c.scale}
        else:
            out |= {"paths": [p.vertices for p in c.get_paths()], "offsets": c.get_offsets()}
        return out

    def texts(legend) -> list[str]:
        return [] if legend is None else [t.get_text() for t in legend.get_texts()]

    return {
        "size": fig.get_size_inches(),
        "suptitle": fig.get_suptitle(),
        "legends": [texts(lg) for lg in fig.legends],
        "axes": [
            {
                "title": ax.get_title(), "xlabel": ax.get_xlabel(), "ylabel": ax.get_ylabel(),
                "texts": [t.get_text() for t in ax.texts], "legend": texts(ax.get_legend()),
                "lines": [
                    {"x": np.asarray(ln.get_xdata(), float), "y": np.asarray(ln.get_ydata(), float),
                     "color": to_rgba(ln.get_color()), "marker": ln.get_marker(),
                     "linestyle": ln.get_linestyle()}
                    for ln in ax.get_lines()
                ],
                "collections": [collection(c) for c in ax.collections],
            }
            for ax in fig.axes
        ],
    }


def assert_same_content(a, b, where="figure") -> None:
    """Two :func:`figure_content` trees are equal (arrays to 1e-12)."""
    if isinstance(a, dict):
        assert list(a) == list(b), where
        for k in a:
            assert_same_content(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), f"{where}: {len(a)} != {len(b)} items"
        for j, (x, y) in enumerate(zip(a, b, strict=True)):
            assert_same_content(x, y, f"{where}[{j}]")
    elif isinstance(a, str) or a is None:
        assert a == b, f"{where}: {a!r} != {b!r}"
    else:
        x, y = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        assert x.shape == y.shape, f"{where}: shape {x.shape} != {y.shape}"
        assert_allclose(x, y, rtol=1e-12, atol=0, err_msg=where)


def assert_same_figure(a, b) -> None:
    assert_same_content(figure_content(a), figure_content(b))


@pytest.fixture
def drawn(monkeypatch):
    """The figures the CLI draws: every figure returned by a plotting function of
    :mod:`stepcontact.post.plotting` during the test, as (function name, figure)."""
    from stepcontact.post import plotting

    figures: list[tuple[str, object]] = []

    def recording(name, draw):
        def wrapper(*args, **kwargs):
            fig = draw(*args, **kwargs)
            figures.append((name, fig))
            return fig

        return wrapper

    for name in ("plot_deformed", "plot_interfaces", "plot_load_displacement",
                 "plot_event_timeline"):
        monkeypatch.setattr(plotting, name, recording(name, getattr(plotting, name)))
    return figures


def without_model(res):
    """The run in memory as the CLI has it from its file: without the model (so the deformed
    shape draws each load pattern as its resultant, not the assembled nodal forces)."""
    import dataclasses

    return dataclasses.replace(res, _recover=None)


def nodal_u(res, i):
    dof = np.asarray(res.geometry["dof_of"])[:, :2]
    return res.displacement(i)[dof]


def test_runs_have_events(runs):
    for key in ("block", "frame"):
        res = runs[key]
        assert res.status is sc.Status.EQUILIBRIUM_LOST and res.events
        assert set(res.fields) == set(range(res.n_states))
    assert set(runs["ends"].fields) != set(range(runs["ends"].n_states))


# --------------------------------------------------------------------------------------------
# deformed shape
# --------------------------------------------------------------------------------------------
def test_plot_deformed_geometry_scale_and_states(runs, tmp_path):
    res = runs["block"]
    i = res.n_states - 2
    fig = plot_deformed(res, state=i, path=tmp_path / "d.png", dpi=DPI)
    check_png(tmp_path / "d.png", fig)
    title = fig.get_suptitle()
    scale = float(title.split("×")[1].split(",")[0])
    mant = scale / 10 ** np.floor(np.log10(scale))
    assert any(np.isclose(mant, c) for c in (1, 2, 5))  # a round magnification
    un = nodal_u(res, i)
    pts = np.asarray(res.geometry["points"])
    umax = np.linalg.norm(un, axis=1).max()
    assert 0.02 * 4 < scale * umax <= 0.1 * 4 * (1 + 1e-12)  # model size 4 m
    ax = fig.axes[0]
    # cells of the block: NX·NY polygons at the displaced nodes
    cells = np.asarray(res.geometry["bodies"][1]["cells"])
    polys = [c for c in ax.collections if type(c).__name__ == "PolyCollection"]
    want = pts[cells] + scale * un[cells]
    verts = [np.array([v.vertices[:4] for v in p.get_paths()]) for p in polys
             if len(p.get_paths()) == NX * NY]
    assert any(v.shape == want.shape and np.allclose(v, want, rtol=0, atol=1e-12)
               for v in verts)
    # outline of the block: the 2(NX + NY) boundary edges
    lines = [c for c in ax.collections if type(c).__name__ == "LineCollection"]
    assert 2 * (NX + NY) in [len(c.get_segments()) for c in lines]
    # CFEs coloured by their state after state i
    dots = [c for c in ax.collections if type(c).__name__ == "PathCollection"][0]
    want = [STATE_COLORS[ContactState(int(v))] for v in res.state[i]]
    assert_allclose(dots.get_facecolors(), [to_rgba(c) for c in want])
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    n_slip = int(np.sum(res.state[i] == int(ContactState.SLIP_POS)))
    assert f"slip+ ({n_slip})" in labels
    # explicit scale, negative state index, SVG
    fig = plot_deformed(res, state=-1, scale=1234.0, path=tmp_path / "d.svg")
    assert "× 1234" in fig.get_suptitle() and f"state {res.n_states - 1}" in fig.get_suptitle()
    assert "<svg" in (tmp_path / "d.svg").read_text()[:2000]


def test_plot_deformed_frame_and_quadratic(runs, tmp_path):
    fig = plot_deformed(runs["frame"], path=tmp_path / "f.pdf")
    assert (tmp_path / "f.pdf").read_bytes()[:4] == b"%PDF"
    beam = [c for c in fig.axes[0].collections
            if type(c).__name__ == "LineCollection" and len(c.get_segments()) == 8]
    assert len(beam) == 2  # the beam, undeformed (dashed) and deformed
    res = sc.solve_static(block_model("quad8"), store_fields="ends")
    fig = plot_deformed(res, state=-1)
    outline = [c for c in fig.axes[0].collections if type(c).__name__ == "LineCollection"]
    assert max(np.asarray(s).shape[0] for c in outline for s in c.get_segments()) == 3


def test_plot_deformed_errors(runs, tmp_path):
    res = runs["block"]
    with pytest.raises(ValueError, match="does not exist"):
        plot_deformed(res, state=res.n_states)
    with pytest.raises(ValueError, match="magnification"):
        plot_deformed(res, scale=-1.0)
    with pytest.raises(ValueError, match="unsupported suffix"):
        plot_deformed(res, path=tmp_path / "d.jpg")
    ends = sc.StaticResult.load(runs["dir"] / "ends.nc")
    missing = next(i for i in range(ends.n_states) if i not in ends.fields)
    with pytest.raises(ValueError, match=r"store_fields='all'"):
        plot_deformed(ends, state=missing)


# --------------------------------------------------------------------------------------------
# contact stresses at chosen states
# --------------------------------------------------------------------------------------------
def test_plot_interfaces_at_states(runs, tmp_path):
    res = runs["block"]
    fig = plot_interfaces(res, states=[3, -1], path=tmp_path / "s.png", dpi=DPI)
    check_png(tmp_path / "s.png", fig)
    area = res.cfe["area"]
    order = np.argsort(res.cfe["s"], kind="stable")
    lines = fig.axes[0].get_lines()
    scale = {"kPa": 1e3, "MPa": 1e6, "Pa": 1.0}[fig.axes[0].get_ylabel().split(", ")[1][:3]
                                                 .strip()]
    assert_allclose(lines[0].get_ydata(), (res.N[3] / area)[order] / scale, rtol=1e-12)
    assert_allclose(lines[1].get_ydata(), (res.N[-1] / area)[order] / scale, rtol=1e-12)
    assert len(fig.axes[0].collections) == 2  # the shaded diagrams
    strip = fig.axes[2].collections[0].get_array().reshape(2, -1)
    assert_array_equal(strip, res.state[[3, -1]][:, order])
    both = plot_interfaces(res, lams=[1e4], states=2)
    assert len(both.axes[0].get_lines()) == 3  # two λ + zero line


# --------------------------------------------------------------------------------------------
# load–displacement
# --------------------------------------------------------------------------------------------
def test_plot_load_displacement(runs, tmp_path):
    res = runs["block"]
    pts = np.asarray(res.geometry["points"])
    fig = plot_load_displacement(res, node=(3.0, 2.0), dof="x", path=tmp_path / "ld.png",
                                 dpi=DPI)
    check_png(tmp_path / "ld.png", fig)
    k = int(np.flatnonzero(np.all(np.isclose(pts, [3.0, 2.0]), axis=1))[0])
    assert f"node {k}" in fig.axes[-1].get_xlabel()
    unit = fig.axes[-1].get_xlabel().rsplit(", ", 1)[1]
    div = {"m": 1.0, "mm": 1e-3, "µm": 1e-6}[unit]
    ux = np.array([nodal_u(res, i)[k, 0] for i in range(res.n_states)])
    push = fig.axes[1].get_lines()[0]  # segment 1: from its start to the end
    idx = np.flatnonzero(res.segment == 1)
    assert_allclose(push.get_xdata()[-len(idx):], ux[idx] / div, rtol=1e-12)
    assert_allclose(push.get_ydata()[-len(idx):], res.lam[idx])
    assert fig.axes[1].get_ylabel() == "λ of 'push'"
    n_marks = len({(e.state, e.transition) for e in res.events})
    markers = [ln for ax in fig.axes for ln in ax.get_lines()[1:] if ln.get_marker() in
               {m for m, _ in TRANSITION_MARKERS.values()}]
    assert len(markers) == n_marks
    # the same node by index; the whole path on one axis
    fig2 = plot_load_displacement(res, node=k, dof="x", axis="path")
    assert len(fig2.axes) == 1
    y = np.concatenate([ln.get_ydata() for ln in fig2.axes[0].get_lines()])
    assert y.min() == 0.0 and y.max() == pytest.approx(2.0)
    # default node in y: the one that moves most in y over the path
    fig3 = plot_load_displacement(res, dof="y")
    peak = np.max([np.abs(nodal_u(res, i)) for i in range(res.n_states)], axis=0)
    k3 = int(np.argmax(peak[:, 1]))
    assert f"$u_y$ of node {k3} " in fig3.axes[-1].get_xlabel()
    # frame rotation
    fig4 = plot_load_displacement(runs["frame"], node=(8.0, 0.5), body="beam", dof="rz")
    assert "rad" in fig4.axes[-1].get_xlabel()


def test_plot_load_displacement_errors(runs):
    res = runs["block"]
    with pytest.raises(ValueError, match="shared by bodies 'base', 'block'"):
        plot_load_displacement(res, node=(2.0, 1.0))
    plot_load_displacement(res, node=(2.0, 1.0), body="block")
    with pytest.raises(ValueError, match="no node near"):
        plot_load_displacement(res, node=(40.0, 1.0))
    with pytest.raises(ValueError, match="dof='z'"):
        plot_load_displacement(res, dof="z")
    with pytest.raises(ValueError, match="does not exist"):
        plot_load_displacement(res, node=10**6)
    with pytest.raises(ValueError, match="has no DOF rz"):
        plot_load_displacement(res, node=0, dof="rz")
    with pytest.raises(ValueError, match="body 'nope'"):
        plot_load_displacement(res, body="nope")
    ends = sc.StaticResult.load(runs["dir"] / "ends.nc")
    with pytest.raises(ValueError, match=r"not in this result .*store_fields='all'"):
        plot_load_displacement(ends)
    plot_load_displacement(runs["ends"])  # in memory: the states are recovered


# --------------------------------------------------------------------------------------------
# event timeline
# --------------------------------------------------------------------------------------------
def test_plot_event_timeline(runs, tmp_path):
    res = runs["block"]
    fig = plot_event_timeline(res, path=tmp_path / "t.png", dpi=DPI)
    check_png(tmp_path / "t.png", fig)
    assert len(fig.axes) == 2  # one interface × two segments
    marks = [(ln.get_xdata()[0], ln.get_ydata()[0], ln.get_marker())
             for ax in fig.axes for ln in ax.get_lines()]
    want = [(e.lam, e.position, TRANSITION_MARKERS[e.transition][0]) for e in res.events]
    assert sorted(marks) == sorted(want)
    # state bars: segment 1 from its start, one bar per CFE and interval between states
    bars = fig.axes[1].collections[0]
    n_states_1 = int(np.sum(res.segment == 1))
    assert len(bars.get_segments()) == res.m * (n_states_1 - 1)
    last = bars.get_colors()[-res.m:]
    i = np.flatnonzero(res.segment == 1)[-2]
    assert_allclose(last, [to_rgba(STATE_COLORS[ContactState(int(v))]) for v in res.state[i]])
    assert [t.get_text() for t in fig.legends[0].get_texts()] == [
        f"state {cs.label}" for cs in ContactState if np.any(res.state == int(cs))
    ] + [f"→ {t.value}" for t in TRANSITION_MARKERS if t in {e.transition for e in res.events}]
    assert fig.axes[0].get_ylabel() == "s along 'joint', m"
    assert [ax.get_xlabel() for ax in fig.axes] == ["λ of 'weight'", "λ of 'push'"]
    frame = runs["frame"]
    fig = plot_event_timeline(frame, path=tmp_path / "t.svg")
    assert "<svg" in (tmp_path / "t.svg").read_text()[:2000]
    marks = [(ln.get_xdata()[0], ln.get_ydata()[0], ln.get_marker())
             for ax in fig.axes for ln in ax.get_lines()]
    assert sorted(marks) == sorted(
        (e.lam, e.position, TRANSITION_MARKERS[e.transition][0]) for e in frame.events)
    assert fig.get_suptitle() == (f"Event timeline — {len(frame.events)} events, {frame.m} CFEs, "
                                  f"{frame.status.value}")


# --------------------------------------------------------------------------------------------
# CLI: plot
# --------------------------------------------------------------------------------------------
API = {
    "deformed": lambda res: plot_deformed(res),
    "stresses": lambda res: plot_interfaces(res),
    "load-displacement": lambda res: plot_load_displacement(res, node=(3.0, 2.0), dof="x"),
    "timeline": lambda res: plot_event_timeline(res),
}


@pytest.mark.parametrize("kind", list(API))
def test_cli_plot_each_kind(runs, tmp_path, kind, drawn):
    out = tmp_path / f"{kind}.png"
    args = ["plot", str(runs["dir"] / "block.nc"), "--kind", kind, "-o", str(out),
            "--dpi", str(DPI)]
    if kind == "load-displacement":
        args += ["--node", "3,2", "--dof", "x"]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    assert str(out) in result.stdout
    # one figure, written to -o at --dpi, drawing what the API draws from the run in memory
    ((_, fig),) = drawn
    check_png(out, fig)
    assert_same_figure(fig, API[kind](without_model(runs["block"])))


def test_cli_plot_all_and_formats(runs, tmp_path, drawn):
    res = runs["block"]
    nc = runs["dir"] / "block.nc"
    result = runner.invoke(app, ["plot", str(nc), "--kind", "all", "-o", str(tmp_path / "f"),
                                 "--format", "pdf"])
    assert result.exit_code == 0, result.output
    for kind in API:
        assert (tmp_path / "f" / f"block-{kind}.pdf").read_bytes()[:4] == b"%PDF"
    # every kind with its defaults (load-displacement: the node and direction that move most;
    # deformed: the file has no model, so the loads are drawn as their resultants)
    defaults = {"deformed": plot_deformed, "stresses": plot_interfaces,
                "load-displacement": plot_load_displacement, "timeline": plot_event_timeline}
    assert [name for name, _ in drawn] == [f.__name__ for f in defaults.values()]
    for (_, fig), draw in zip(drawn, defaults.values(), strict=True):
        assert_same_figure(fig, draw(without_model(res)))
    peak = np.max([np.abs(nodal_u(res, i)) for i in range(res.n_states)], axis=0)
    k, c = np.unravel_index(np.argmax(peak), peak.shape)
    assert f"{('$u_x$', '$u_y$')[c]} of node {k} " in drawn[2][1].axes[-1].get_xlabel()
    drawn.clear()
    result = runner.invoke(app, ["plot", str(nc), "-k", "deformed", "--state", "2",
                                 "--scale", "500", "-o", str(tmp_path / "d.svg")])
    assert result.exit_code == 0, result.output
    text = (tmp_path / "d.svg").read_text()
    assert "<svg" in text[:2000]
    ((_, fig),) = drawn
    assert fig.get_suptitle().startswith("Deformed shape at state 2 (")
    assert "displacements × 500," in fig.get_suptitle()
    assert_same_figure(fig, plot_deformed(without_model(res), state=2, scale=500.0))
    drawn.clear()
    result = runner.invoke(app, ["plot", str(nc), "--lam", "1e4", "--lam", "2e4",
                                 "-o", str(tmp_path / "s.png"), "--dpi", str(DPI)])
    assert result.exit_code == 0, result.output
    ((_, fig),) = drawn
    check_png(tmp_path / "s.png", fig)
    assert_same_figure(fig, plot_interfaces(res, lams=[1e4, 2e4]))
    # σ_n at the two λ of the last segment ('push'), in the unit of the axis label
    assert fig.get_suptitle() == "Contact stresses at pattern 'push' λ = 1e+04, 2e+04"
    unit = fig.axes[0].get_ylabel().split(", ")[1].split()[0]
    div = {"MPa": 1e6, "kPa": 1e3, "Pa": 1.0}[unit]
    order = np.argsort(res.cfe["s"], kind="stable")
    for line, lam in zip(fig.axes[0].get_lines()[:2], (1e4, 2e4), strict=True):
        want = res.interpolate(lam, 1)["N"] / res.cfe["area"]
        assert_allclose(line.get_ydata(), want[order] / div, rtol=1e-12)


def test_cli_plot_default_output_and_skips(runs, tmp_path, drawn):
    import shutil

    ends = runs["ends"]
    nc = tmp_path / "ends.nc"
    shutil.copy(runs["dir"] / "ends.nc", nc)
    result = runner.invoke(app, ["plot", str(nc)])
    assert result.exit_code == 0, result.output
    # default: the contact stresses at the segment ends, next to the result file, 150 dpi
    ((_, fig),) = drawn
    check_png(tmp_path / "ends-stresses.png", fig, dpi=150)
    assert_same_figure(fig, plot_interfaces(ends))
    drawn.clear()
    result = runner.invoke(app, ["plot", str(nc), "--kind", "all", "--state", "1",
                                 "--dpi", str(DPI)])
    assert result.exit_code == 0, result.output
    assert "skipped load-displacement" in result.stdout
    # the displacements of every state are not stored: no load-displacement figure
    assert [name for name, _ in drawn] == ["plot_deformed", "plot_interfaces",
                                           "plot_event_timeline"]
    (_, deformed), (_, stresses), (_, timeline) = drawn
    check_png(tmp_path / "ends-deformed.png", deformed)
    check_png(tmp_path / "ends-stresses.png", stresses)
    check_png(tmp_path / "ends-timeline.png", timeline)
    assert not (tmp_path / "ends-load-displacement.png").exists()
    assert deformed.get_suptitle().startswith("Deformed shape at state 1 (")
    assert_same_figure(deformed, plot_deformed(without_model(ends), state=1))
    assert_same_figure(stresses, plot_interfaces(ends, states=[1]))
    assert_same_figure(timeline, plot_event_timeline(ends))
    result = runner.invoke(app, ["plot", str(nc), "--kind", "load-displacement"])
    assert result.exit_code == 2
    assert "store_fields='all'" in result.stderr


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["missing.nc"], "result file not found: missing.nc"),
        (["model.toml"], "not a stepcontact result file"),
        (["other.nc"], "not a stepcontact static result"),
        (["RES", "--kind", "contour"], "unknown --kind 'contour'"),
        (["RES", "-k", "load-displacement", "--node", "1,2,3"], "--node '1,2,3'"),
        (["RES", "-k", "load-displacement", "--node", "a"], "--node 'a'"),
        (["RES", "-k", "load-displacement", "--node", "2,1"], "shared by bodies"),
        (["RES", "-k", "load-displacement", "--dof", "q"], "dof='q'"),
        (["RES", "-k", "deformed", "--lam", "1"], "--lam and --time apply to --kind stresses"),
        (["RES", "-k", "timeline", "--node", "1,1"], "--node applies"),
        (["RES", "-k", "deformed", "--state", "99"], "state 99 does not exist"),
        (["RES", "--lam", "5e6"], "outside segment"),
        (["RES", "-o", "x.jpg"], "unsupported file type"),
        (["RES", "-k", "all", "-o", "x.png"], "give a directory"),
        (["RES", "--format", "gif"], "--format 'gif'"),
    ],
)
def test_cli_plot_errors(runs, tmp_path, monkeypatch, args, message):
    import xarray as xr

    monkeypatch.chdir(tmp_path)
    (tmp_path / "model.toml").write_text("[model]\n")
    xr.Dataset({"a": ("x", np.zeros(2))}).to_netcdf(tmp_path / "other.nc", engine="h5netcdf")
    args = [str(runs["dir"] / "block.nc") if a == "RES" else a for a in args]
    result = runner.invoke(app, ["plot", *args])
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    assert message in lines[0]


# --------------------------------------------------------------------------------------------
# CLI: info
# --------------------------------------------------------------------------------------------
def test_cli_info_text_and_json(runs):
    res = runs["block"]
    nc = runs["dir"] / "block.nc"
    result = runner.invoke(app, ["info", str(nc)])
    assert result.exit_code == 0, result.output
    out = result.stdout
    n_nodes = len(res.geometry["points"])
    for text in (res.status.value, f"{n_nodes}", f"{res.counters['ndof']}",
                 f"joint ({res.m} CFEs)", f"events by transition ({len(res.events)})",
                 f"{res.multipliers[-1].equilibrium_lost:.6g}",
                 f"{res.multipliers[-1].first_slip:.6g}", "weight", "push", "1e+06"):
        assert text in out, text
    result = runner.invoke(app, ["info", str(nc), "--json"])
    assert result.exit_code == 0, result.output
    info = json.loads(result.stdout)
    assert info["status"] == res.status.value and info["message"] == res.message
    assert info["events"] == len(res.events) and info["states"] == res.n_states
    assert info["model"]["nodes"] == n_nodes and info["model"]["cfes"] == res.m
    assert info["model"]["dofs"] == res.counters["ndof"]
    assert info["model"]["interfaces"] == [{"name": "joint", "cfes": res.m}]
    assert [b["elements"] for b in info["model"]["bodies"]] == [8, NX * NY]
    for got, mu in zip(info["multipliers"], res.multipliers, strict=True):
        for key in ("first_slip", "first_opening", "first_closing", "equilibrium_lost"):
            assert got[key] == getattr(mu, key)
    seg = info["segments"][1]
    assert seg["pattern"] == "push" and seg["lam_end"] == 1e6
    assert seg["lam_reached"] == res.lam[-1] == seg["equilibrium_lost"]
    assert sum(s["events"] for s in info["segments"]) == len(res.events)
    assert info["fields_stored"] == res.n_states and info["units"]["N"] == "N"
    assert info["max_residual"] == float(res.residual.max())


def test_cli_info_errors(tmp_path):
    result = runner.invoke(app, ["info", str(tmp_path / "none.nc"), "--json"])
    assert result.exit_code == 2
    assert "result file not found" in result.stderr
    assert json.loads(result.stdout)["status"] == "error"
    (tmp_path / "x.nc").write_text("not netCDF")
    result = runner.invoke(app, ["info", str(tmp_path / "x.nc")])
    assert result.exit_code == 2 and "not a stepcontact result file" in result.stderr


# --------------------------------------------------------------------------------------------
# notebook conversions
# --------------------------------------------------------------------------------------------
def test_cfe_history(runs):
    res = runs["block"]
    for r in (res, sc.StaticResult.load(runs["dir"] / "block.nc")):
        h = r.cfe_history()
        assert dict(h.sizes) == {"state": res.n_states, "cfe": res.m}
        for key in ("N", "Q", "sigma_n", "tau", "un", "ut"):
            assert_array_equal(h[key].values, getattr(res, key), err_msg=key)
        assert_array_equal(h.contact_state.values, res.state)
        assert_array_equal(h.lam.values, res.lam)
        assert_array_equal(h.segment.values, res.segment)
        assert list(h.pattern.values[[0, -1]]) == ["weight", "push"]
        assert_array_equal(h.position.values, res.cfe["s"])
        assert_array_equal(h.x.values, res.cfe["x"][:, 0])
        assert set(h.interface.values) == {"joint"}
        assert h.sigma_n.attrs["units"] == "Pa" and h.N.attrs["units"] == "N"
    df = res.cfe_history(as_frame=True)
    assert len(df) == res.n_states * res.m
    assert df.loc[(res.n_states - 1, 2), "Q"] == res.Q[-1, 2]


def test_repr_and_html(runs):
    res = runs["block"]
    text = repr(res)
    assert text.startswith(f"<StaticResult {res.status.value}: {res.n_states} states, "
                           f"{len(res.events)} events")
    assert "segment 1 'push' λ 0 → 1e+06" in text
    assert f"equilibrium lost {res.multipliers[-1].equilibrium_lost:.6g}" in text
    assert res.message in text
    html = res._repr_html_()
    assert "<table>" in html and "equilibrium lost" in html and "push" in html
    rows = res.segments_summary()
    assert [r["states"] for r in rows] == [int(np.sum(res.segment == j)) for j in range(2)]
