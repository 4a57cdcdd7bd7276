"""Figures and ParaView series of a staged result show only what exists at each state
(issue 12, construction stages).

The model: a wall in two halves on a rigid ground (friction).  Stage 'first' builds the lower
half and its base interface and loads it by its weight; stage 'second' places the upper half
and makes the joint between the halves at once (its weight ramped in by the automatic
segment).  So a state of stage 1 has one body and the base's CFEs, a state of stage 2 both
bodies and all CFEs.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET

import matplotlib
import meshio
import numpy as np
import pytest
from meshio.xdmf import TimeSeriesReader
from typer.testing import CliRunner

import stepcontact as sc
from stepcontact.cli.commands import app
from stepcontact.enums import Status
from stepcontact.post import plotting

matplotlib.use("Agg")

E, NU, RHO = 30e9, 0.2, 2400.0
B, H1, H2 = 2.0, 2.0, 1.5
MAT = sc.Material(E, NU, RHO)


def _wall(stages: bool = True) -> sc.Model:
    lower = sc.rectangle("lower", (0, 0), (B, H1), 2, 2, MAT, "quad8")
    upper = sc.rectangle("upper", (0, H1), (B, H1 + H2), 2, 2, MAT, "quad8")
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (B + 1.0, 0.0)])
    m = sc.Model(name="wall").add(lower, upper)
    side = int(np.flatnonzero(np.all(np.abs(lower.points - (0.0, H1 / 2)) < 1e-9, axis=1))[0])
    m = m.add(sc.Interface("base", m.select("lower", y=0.0), ground, friction=0.6),
              sc.Support("side", sc.NodeSet("lower", [side]), "x"),
              sc.Interface("joint", m.select("upper", y=H1), m.select("lower", y=H1),
                           friction=0.6),
              sc.LoadPattern("weight", [sc.BodyForce()]))
    if not stages:
        return m.add(sc.Segment("weight", 1.0))
    return m.add(sc.Stage("first", [sc.Segment("weight", 1.0)]),
                 sc.Stage("second", bodies=("upper",), interfaces=("joint",)))


@pytest.fixture(scope="module")
def res():
    r = sc.solve_static(_wall(), store_fields="all")
    assert r.status == Status.COMPLETED, r.message
    assert r.stage_names == ("first", "second")
    return r


def _states(res):
    """(a state of stage 1 — its last —, the first and the last state of stage 2)."""
    i0 = int(np.flatnonzero(res.stage == 1)[0])
    return i0 - 1, i0, res.n_states - 1


def _body_cells(res) -> dict[str, int]:
    return {b["name"]: len(b["cells"]) for b in res.geometry["bodies"]}


def _body_nodes(res, name: str) -> np.ndarray:
    b = next(b for b in res.geometry["bodies"] if b["name"] == name)
    return np.unique(np.asarray(b["cells"]))


# --------------------------------------------------------------------------------------------
# ParaView: VTU series
# --------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def vtu(res, tmp_path_factory):
    out = tmp_path_factory.mktemp("vtu")
    return sc.export_vtu(res, out, name="wall")


def _frame(pvd, i: int, cfe: bool = False) -> meshio.Mesh:
    return meshio.read(pvd.parent / "wall" / f"wall{'_cfe' if cfe else ''}_{i:04d}.vtu")


def test_a_vtu_frame_holds_the_bodies_built_at_its_state(res, vtu):
    ncell = _body_cells(res)
    xy = np.asarray(res.geometry["points"], float)
    lower, upper = _body_nodes(res, "lower"), _body_nodes(res, "upper")
    for i in range(res.n_states):
        mesh = _frame(vtu, i)
        here = res.active_bodies(i)
        assert here == ({"lower"} if res.stage[i] == 0 else {"lower", "upper"})
        assert sum(len(c.data) for c in mesh.cells) == sum(ncell[b] for b in here)
        body = np.concatenate(mesh.cell_data["body"])
        assert set(body.tolist()) == {["lower", "upper"].index(b) for b in here}
        # the points: the nodes of the bodies built, with their displacements
        nodes = lower if here == {"lower"} else np.union1d(lower, upper)
        assert len(mesh.points) == nodes.size
        assert np.array_equal(mesh.points[:, :2], xy[nodes])
        u = np.asarray(res.displacement(i))
        dof = np.asarray(res.geometry["dof_of"])[nodes, :2]
        assert np.array_equal(mesh.point_data["displacement"][:, :2], u[dof])
        # every cell refers to a written point
        assert max(int(c.data.max()) for c in mesh.cells) == nodes.size - 1
        assert mesh.field_data["stage"].tolist() == [int(res.stage[i])]
        assert np.all(np.concatenate(mesh.cell_data["active"]) == 1)
        built = np.concatenate(mesh.cell_data["built_stage"])
        assert np.array_equal(built, np.where(body == 0, 0, 1))


def test_a_vtu_frame_holds_the_cfes_made_at_its_state(res, vtu):
    base = np.flatnonzero(np.asarray(res.cfe["interface"]) == 0)
    for i in range(res.n_states):
        act = res.active_cfes(i)
        mesh = _frame(vtu, i, cfe=True)
        (lines,) = mesh.cells
        assert len(lines.data) == act.sum()
        assert len(mesh.points) == 2 * act.sum()
        (cfe,) = mesh.cell_data["cfe"]
        assert np.array_equal(cfe, np.flatnonzero(act))
        assert np.array_equal(mesh.cell_data["N"][0], res.N[i][act])
        assert np.array_equal(mesh.cell_data["state"][0], res.state[i][act])
        assert np.array_equal(mesh.cell_data["built_stage"][0],
                              np.where(np.isin(cfe, base), 0, 1))
        assert mesh.field_data["stage"].tolist() == [int(res.stage[i])]
    i1, i0, _ = _states(res)
    assert res.active_cfes(i1).sum() == base.size < res.active_cfes(i0).sum() == res.m


def test_the_pvd_names_the_stages(vtu):
    text = vtu.read_text()
    assert "stage ids: 0 first, 1 second" in text
    assert "stage ids" in (vtu.parent / "wall_cfe.pvd").read_text()


def test_a_frame_without_cfes_is_an_empty_grid_with_its_stage(tmp_path):
    """The joint alone, made at stage 2: the frames of stage 1 have no CFE at all."""
    m = _wall()
    m = m.replace(interfaces=tuple(x for x in m.interfaces if x.name == "joint"))
    m = m.add(sc.Support("base", m.select("lower", y=0.0), "y"))
    r = sc.solve_static(m)
    assert r.status == Status.COMPLETED, r.message
    pvd = sc.export_vtu(r, tmp_path, name="wall", states=[0, r.n_states - 1])
    root = ET.parse(tmp_path / "wall" / "wall_cfe_0000.vtu").getroot()
    piece = root.find("UnstructuredGrid/Piece")
    assert (piece.get("NumberOfPoints"), piece.get("NumberOfCells")) == ("0", "0")
    stage = root.find("UnstructuredGrid/FieldData/DataArray[@Name='stage']")
    assert stage.text.strip() == "0"
    last = _frame(pvd, r.n_states - 1, cfe=True)
    assert len(last.cells[0].data) == r.m and last.field_data["stage"].tolist() == [1]


def test_an_unstaged_result_has_no_stage_arrays(tmp_path):
    r = sc.solve_static(_wall(stages=False))
    pvd = sc.export_vtu(r, tmp_path, name="wall", states=[0, -1])
    mesh = _frame(pvd, r.n_states - 1)
    assert sum(len(c.data) for c in mesh.cells) == sum(_body_cells(r).values())
    assert "stage" not in mesh.field_data and "active" not in mesh.cell_data
    assert "stage ids" not in pvd.read_text()


# --------------------------------------------------------------------------------------------
# ParaView: XDMF (one mesh for all frames: the cell data `active` says what exists)
# --------------------------------------------------------------------------------------------
def test_the_xdmf_series_marks_what_exists(res, tmp_path):
    path = sc.export_xdmf(res, tmp_path / "wall.xdmf")
    with TimeSeriesReader(path) as reader:
        _, cells = reader.read_points_cells()
        assert sum(len(c.data) for c in cells) == sum(_body_cells(res).values())
        for i in range(reader.num_steps):
            _, _, cd = reader.read_data(i)
            body = np.concatenate(cd["body"])
            here = res.active_bodies(i)
            want = np.isin(body, [["lower", "upper"].index(b) for b in here])
            assert np.array_equal(np.concatenate(cd["active"]) == 1, want)
    with TimeSeriesReader(tmp_path / "wall_cfe.xdmf") as reader:
        reader.read_points_cells()
        for i in range(reader.num_steps):
            _, _, cd = reader.read_data(i)
            assert np.array_equal(cd["active"][0] == 1, res.active_cfes(i))
    text = path.read_text()
    names = re.findall(r'<Information Name="stage_name" Value="(\w+)"', text)
    assert names == [res.stage_names[s] for s in res.stage]


# --------------------------------------------------------------------------------------------
# figures
# --------------------------------------------------------------------------------------------
def _drawn_y(fig) -> float:
    """The highest y of the bodies drawn (polygons and outlines), m."""
    from matplotlib.collections import LineCollection, PolyCollection

    ax = fig.axes[0]
    ys = [np.asarray(p)[:, 1].max() for c in ax.collections
          if isinstance(c, PolyCollection | LineCollection) for p in c.get_paths()
          for p in [p.vertices]]
    return float(max(ys))


def test_the_deformed_shape_draws_the_bodies_built(res):
    i1, i0, last = _states(res)
    for i, bodies in ((i1, {"lower"}), (i0, {"lower", "upper"}), (last, {"lower", "upper"})):
        fig = plotting.plot_deformed(res, state=i, stress="syy", loads=False)
        labels = {t.get_text() for t in fig.axes[0].texts if t.get_gid() == "body_label"}
        assert labels == bodies
        top = _drawn_y(fig)
        if bodies == {"lower"}:
            assert top < H1 + 0.05 * H1  # nothing of the upper half (up to H1 + H2)
            assert f"stage '{res.stage_names[0]}'" in fig.get_suptitle()
        else:
            assert top > H1 + 0.9 * H2
        # the CFE dots: the CFEs made
        (dots,) = [c for c in fig.axes[0].collections if c.get_offsets().shape[0]
                   and type(c).__name__ == "PathCollection"]
        assert len(dots.get_offsets()) == res.active_cfes(i).sum()
        # the stress cells: those of the bodies built
        cells = sum(_body_cells(res)[b] for b in bodies)
        (pc,) = [c for c in fig.axes[0].collections if c.get_array() is not None
                 and type(c).__name__ == "PolyCollection"]
        assert len(pc.get_array()) == cells


def test_the_loads_drawn_at_stage_1_are_those_on_the_lower_half(res):
    i1, _, _ = _states(res)
    fig = plotting.plot_deformed(res, state=i1)
    text = " ".join(t.get_text() for t in fig.legends[0].get_texts())
    weight = RHO * 9.81 * B * H1  # the lower half's weight, N
    assert f"-{weight / 1e3:.6g}) kN" in text  # (6 significant digits)


def test_the_interface_figure_leaves_out_the_cfes_not_made(res):
    i1, _, last = _states(res)
    fig = plotting.plot_interfaces(res, states=[i1, last])
    names = list(res.interface_names)
    ax_n = fig.axes[names.index("joint")]  # σ_n panel of the joint: first row
    # the two σ_n diagrams (the zero line has two points, the joint five CFEs)
    first, second = [ln for ln in ax_n.get_lines() if len(ln.get_ydata()) > 2]
    assert np.all(np.isnan(first.get_ydata()))  # stage 1: the joint is not made
    assert np.all(np.isfinite(second.get_ydata())) and np.all(second.get_ydata() < 0)
    ax_base = fig.axes[names.index("base")]
    assert all(np.all(np.isfinite(ln.get_ydata())) for ln in ax_base.get_lines())
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert legend[0].startswith("stage 'first': ") and legend[1].startswith("stage 'second': ")
    assert plotting.NOT_BUILT in legend
    strip = fig.axes[2 * len(names) + names.index("joint")]
    rows = [t.get_text() for t in strip.get_yticklabels()]
    assert rows[0].startswith("first: ") and rows[1].startswith("second: ")
    grid = strip.collections[0].get_array()
    assert np.ma.getmaskarray(grid).reshape(2, -1)[0].all()
    assert not np.ma.getmaskarray(grid).reshape(2, -1)[1].any()


def test_the_load_path_counts_the_cfes_not_made_apart(res):
    fig = plotting.plot_load_path(res)
    ax_l, ax_c = fig.axes[:2]
    stages = [t.get_text().strip() for t in ax_l.texts if t.get_gid() == "stage_label"]
    assert stages == ["stage 'first'", "stage 'second'"]
    bars = {c.get_label(): [p.get_height() for p in c.patches] for c in ax_c.containers}
    want = [res.m - res.active_cfes(i).sum() for i in range(res.n_states)]
    assert bars[plotting.NOT_BUILT] == want
    made = sum(np.array(h) for k, h in bars.items() if k != plotting.NOT_BUILT)
    assert np.array_equal(made, [res.active_cfes(i).sum() for i in range(res.n_states)])


def test_the_timeline_and_the_load_displacement_name_the_stages(res):
    fig = plotting.plot_event_timeline(res)
    titles = [ax.get_title() for ax in fig.axes if ax.get_title()]
    assert titles[0].startswith("stage 'first'\n") and titles[1].startswith("stage 'second'\n")
    joint = list(res.interface_names).index("joint")
    ax = fig.axes[joint * 2]  # the joint's row, stage 1
    assert any(t.get_gid() == "not_built" for t in ax.texts)
    fig = plotting.plot_load_displacement(res)
    assert [ax.get_title(loc="left") for ax in fig.axes] == ["stage 'first'", "stage 'second'"]


# --------------------------------------------------------------------------------------------
# command line: a result file through export and plot
# --------------------------------------------------------------------------------------------
def test_the_cli_exports_and_plots_a_staged_result_file(res, tmp_path, monkeypatch):
    nc = tmp_path / "wall.nc"
    res.save(nc)
    runner = CliRunner()
    out = runner.invoke(app, ["export", str(nc), "--vtu", str(tmp_path / "vtu")])
    assert out.exit_code == 0, out.output
    i1, _, last = _states(res)
    ncell = _body_cells(res)
    for i, cells in ((i1, ncell["lower"]), (last, ncell["lower"] + ncell["upper"])):
        mesh = meshio.read(tmp_path / "vtu" / "wall" / f"wall_{i:04d}.vtu")
        assert sum(len(c.data) for c in mesh.cells) == cells
    drawn = []
    draw = plotting.plot_deformed
    monkeypatch.setattr(plotting, "plot_deformed",
                        lambda *a, **k: drawn.append(draw(*a, **k)) or drawn[-1])
    out = runner.invoke(app, ["plot", str(nc), "--kind", "deformed", "--state", str(i1),
                              "-o", str(tmp_path / "d.png")])
    assert out.exit_code == 0, out.output
    assert (tmp_path / "d.png").stat().st_size > 0
    (fig,) = drawn
    labels = {t.get_text() for t in fig.axes[0].texts if t.get_gid() == "body_label"}
    assert labels == {"lower"} and _drawn_y(fig) < 1.05 * H1
