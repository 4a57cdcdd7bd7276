"""ParaView export: VTU series + .pvd and XDMF, read back with meshio and compared to the result."""

from __future__ import annotations

import json
import logging
import xml.etree.ElementTree as ET
from pathlib import Path
from types import SimpleNamespace

import h5py
import meshio
import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose, assert_array_equal
from typer.testing import CliRunner

import stepcontact as sc
import verification_models as vm
from cli_checks import assert_one_line_error
from stepcontact.cli import app
from stepcontact.io import export as ex
from stepcontact.results.result import load_result

MAT = sc.Material(1e9, 0.25, 2000.0)
STRESS = ("sigma_xx", "sigma_yy", "sigma_xy", "sigma_zz")
VTK_TYPES = {"tri3": "triangle", "tri6": "triangle6", "quad4": "quad", "quad8": "quad8",
             "quad9": "quad9"}


# --------------------------------------------------------------------------------------------
# models (small: every solve takes well under a second)
# --------------------------------------------------------------------------------------------
def block_model(block_el: str = "quad4", base_el: str = "quad4", *, push: bool = True,
                gap: float | None = None) -> sc.Model:
    """A block [0, 2] × [0, 1] on a base [-0.5, 2.5] × [-1, 0]; weight, then a push to sliding."""
    base = sc.rectangle("base", (-0.5, -1.0), (2.5, 0.0), 6, 2, MAT, element=base_el)
    block = sc.rectangle("block", (0.0, 0.0), (2.0, 1.0), 4, 2, MAT, element=block_el)
    m = sc.Model(bodies=[base, block], name="block")
    left = m.select("block", x=0.0)
    m = m.add(
        sc.Support("bed", m.select("base", y=-1.0), "xy"),
        sc.Interface("joint", plus=m.select("block", y=0.0), minus=m.select("base", y=0.0),
                     friction=0.5, gap=gap),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
        sc.LoadPattern("push", [sc.NodalLoad(left, fx=1.0 / len(left))]),
        sc.Segment("weight", 1.0),
    )
    return m.add(sc.Segment("push", 1e6)) if push else m


def frame_model() -> sc.Model:
    """A beam on frictionless supports; weight, then its right end is lifted."""
    return vm.beam_on_supports()


def with_cfe_ends(res: sc.StaticResult, model: sc.Model) -> sc.StaticResult:
    """The result with the interpolation of both CFE ends (exact S− points, end displacements)."""
    c = sc.assemble(model).cfe
    res.cfe = dict(res.cfe, plus_nodes=c.plus_nodes, plus_w=c.plus_w,
                   minus_nodes=c.minus_nodes, minus_w=c.minus_w, tangent=c.tangent)
    return res


@pytest.fixture(scope="module")
def block():
    m = block_model()
    return m, sc.solve_static(m, store_fields="all")


@pytest.fixture(scope="module")
def frame():
    m = frame_model()
    return m, sc.solve_static(m, store_fields="all")


# --------------------------------------------------------------------------------------------
# reading helpers
# --------------------------------------------------------------------------------------------
def read_pvd(path: Path) -> list[tuple[float, Path]]:
    coll = ET.parse(path).getroot().find("Collection")
    return [(float(d.get("timestep")), path.parent / d.get("file")) for d in coll]


def cat(cell_data: dict, key: str) -> np.ndarray:
    return np.concatenate(cell_data[key])


def nodal(res: sc.StaticResult, i: int) -> np.ndarray:
    """Displacements of the result at state i mapped to nodes (n_nodes, 2), m."""
    dof = np.asarray(res.geometry["dof_of"])
    return res.displacement(i)[dof[:, :2]]


def xdmf_mixed_cells(path: Path) -> tuple[np.ndarray, list[tuple[int, np.ndarray]]]:
    """Points and (XDMF type index, nodes) of every cell of an XDMF file, read directly."""
    root = ET.parse(path).getroot()
    grid = root.find("Domain").find("Grid[@Name='mesh']")

    def item(tag: str) -> np.ndarray:
        name = grid.find(tag).find("DataItem").text.strip()
        file, key = name.split(":")
        with h5py.File(path.parent / file) as f:
            return f[key][()]

    npe = {0x24: 6, 0x25: 8, 0x23: 9, 0x4: 3, 0x5: 4}
    topo, cells, r = item("Topology"), [], 0
    assert grid.find("Topology").get("TopologyType") == "Mixed"
    while r < len(topo):
        t = int(topo[r])
        k = int(topo[r + 1]) if t == 2 else npe[t]
        r += 2 if t == 2 else 1
        cells.append((t, topo[r:r + k]))
        r += k
    return item("Geometry"), cells


# --------------------------------------------------------------------------------------------
# time parameter and state selection
# --------------------------------------------------------------------------------------------
def test_load_path_parameter_accumulates_abs_dlambda():
    fake = SimpleNamespace(
        lam=np.array([0.0, 0.4, 1.0, 1.0, 0.7, 0.5, 0.0, 2.0]),
        segment=np.array([0, 0, 0, 1, 1, 1, 2, 2]),
        segments=[("a", 0.0, 1.0), ("b", 1.0, 0.5), ("c", 0.0, 2.0)],
    )
    t = ex.load_path_parameter(fake)
    assert_allclose(t, [0.0, 0.4, 1.0, 1.0, 1.3, 1.5, 1.5, 3.5])
    # = cumulative Σ|Δλ| along the states, continued across segment changes
    dl = np.abs(np.diff(fake.lam))
    dl[np.diff(fake.segment) != 0] = 0.0  # the next segment starts where the last one ended
    assert_allclose(t, np.r_[0.0, np.cumsum(dl)])
    times = ex.frame_times(t)
    assert np.all(np.diff(times) > 0)
    tied = np.r_[False, np.diff(t) == 0]
    assert_array_equal(times[~tied], t[~tied])
    assert_allclose(times, t, atol=10 * ex.TIME_SEPARATION * 3.5)


def test_select_states(block):
    _, res = block
    kinds = np.asarray(res.kind)
    kept, skipped = ex.select_states(res)
    assert_array_equal(kept, sorted(res.fields)) and skipped.size == 0
    assert_array_equal(ex.select_states(res, "events")[0], np.flatnonzero(kinds == "event"))
    assert_array_equal(ex.select_states(res, "ends")[0],
                       np.flatnonzero(kinds == "segment_end"))
    assert_array_equal(ex.select_states(res, [3, -1, 0, 3])[0], [0, 3, res.n_states - 1])
    assert_array_equal(ex.select_states(res, "0, 2,-1")[0], [0, 2, res.n_states - 1])
    for bad in ([res.n_states], "first", [0.5]):
        with pytest.raises(ValueError):
            ex.select_states(res, bad)


# --------------------------------------------------------------------------------------------
# VTU series
# --------------------------------------------------------------------------------------------
def test_vtu_series_matches_the_result(block, tmp_path):
    _, res = block
    pvd = sc.export_vtu(res, tmp_path / "pv", name="blk")
    assert pvd == tmp_path / "pv" / "blk.pvd"
    entries, cfe_entries = read_pvd(pvd), read_pvd(tmp_path / "pv" / "blk_cfe.pvd")
    states = np.array(sorted(res.fields))
    assert len(entries) == len(cfe_entries) == len(states) == res.n_states
    times = np.array([t for t, _ in entries])
    t = ex.load_path_parameter(res)[states]
    assert np.all(np.diff(times) > 0)
    assert_array_equal(times, ex.frame_times(t))
    assert_array_equal([t for t, _ in cfe_entries], times)
    seg0 = res.segment[states] == 0
    assert_allclose(t[seg0], res.lam[states][seg0])  # t = λ in the first segment (0 → 1)
    assert_allclose(t[~seg0], 1.0 + res.lam[states][~seg0])

    xy = np.asarray(res.geometry["points"])
    for (time, file), (_, cfile), i in zip(entries, cfe_entries, states, strict=True):
        mesh = meshio.read(file)
        assert_array_equal(mesh.points[:, :2], xy)
        assert_array_equal(mesh.points[:, 2], 0.0)
        u = mesh.point_data["displacement"]
        assert_array_equal(u[:, :2], nodal(res, i))
        assert_array_equal(u[:, 2], 0.0)
        fd = mesh.field_data
        assert fd["TimeValue"][0] == time and fd["load_path_t"][0] == t[states == i][0]
        assert fd["lam"][0] == res.lam[i] and fd["state"][0] == i
        assert fd["segment"][0] == res.segment[i]
        assert_array_equal(fd["factors"], res.factors[i])
        assert [c.type for c in mesh.cells] == ["quad"]  # meshio merges the two bodies
        body = cat(mesh.cell_data, "body")
        sig = np.column_stack([cat(mesh.cell_data, k) for k in STRESS])
        if i in res.stresses:  # segment ends, and every state of a small model
            for b, name in enumerate(("base", "block")):
                assert_array_equal(sig[body == b], res.stresses[i][name])
            assert_allclose(cat(mesh.cell_data, "von_mises"), ex.von_mises(sig))
        else:
            assert np.isnan(sig).all()

        c = meshio.read(cfile)
        assert [b.type for b in c.cells] == ["line"]
        for key in ("N", "Q", "un", "ut", "sigma_n", "tau"):
            assert_array_equal(cat(c.cell_data, key), getattr(res, key)[i], err_msg=key)
        assert_array_equal(cat(c.cell_data, "state"), res.state[i])
        assert_array_equal(cat(c.cell_data, "interface"), res.cfe["interface"])
        m = res.m
        assert_array_equal(c.points[:m, :2], res.cfe["x"])  # S+ ends
        assert_array_equal(c.cells[0].data, np.column_stack([np.arange(m), m + np.arange(m)]))
        assert "displacement" in c.point_data  # CFE ends move with their nodes
    # the slide is in the file: the last frame has slipping CFEs
    assert set(cat(meshio.read(cfe_entries[-1][1]).cell_data, "state")) & {2, 3}


@pytest.mark.parametrize("element", list(VTK_TYPES))
def test_cell_types_and_node_order(element, tmp_path):
    """Each cell type, read back from VTU and XDMF: mid-edge nodes at the midpoints of its
    corners (straight edges), the centre at the centroid, counter-clockwise corners."""
    m = block_model(element, element, push=False)
    res = sc.solve_static(m, store_fields="all")
    sc.export_vtu(res, tmp_path, states="ends")
    xdmf = sc.export_xdmf(res, tmp_path / "r.xdmf", states="ends")
    (_, file), = read_pvd(tmp_path / "result.pvd")
    mesh = meshio.read(file)
    ctype = VTK_TYPES[element]
    assert [c.type for c in mesh.cells] == [ctype]  # both bodies (meshio merges blocks)
    p = mesh.points[:, :2]
    n_corner = 3 if ctype.startswith("tri") else 4
    for block in mesh.cells:
        c = block.data
        corners = p[c[:, :n_corner]]
        nxt = np.roll(corners, -1, axis=1)
        area2 = np.sum(corners[..., 0] * nxt[..., 1] - nxt[..., 0] * corners[..., 1], axis=1)
        assert np.all(area2 > 0)
        for j in range(c.shape[1] - n_corner - (ctype == "quad9")):
            mid = 0.5 * (p[c[:, j]] + p[c[:, (j + 1) % n_corner]])
            assert_allclose(p[c[:, n_corner + j]], mid, atol=1e-12)
        if ctype == "quad9":
            assert_allclose(p[c[:, 8]], corners.mean(axis=1), atol=1e-12)
    # every node of the body is used once per cell it belongs to
    body_cells = np.concatenate([np.asarray(b["cells"]) for b in res.geometry["bodies"]])
    vtk_cells = np.concatenate([b.data for b in mesh.cells])
    assert_array_equal(np.sort(vtk_cells, axis=1), np.sort(body_cells, axis=1))

    with meshio.xdmf.TimeSeriesReader(xdmf) as r:
        points, cells = r.read_points_cells()
        assert r.num_steps == 1
        time, pdata, cdata = r.read_data(0)
    assert_array_equal(points, mesh.points)
    assert [c.type for c in cells] == [ctype]
    assert_array_equal(cells[0].data, vtk_cells)
    assert_array_equal(pdata["displacement"], mesh.point_data["displacement"])
    assert_array_equal(cdata["sigma_xx"][0], cat(mesh.cell_data, "sigma_xx"))
    assert time == mesh.field_data["TimeValue"][0] == 1.0


def test_mixed_quadratic_bodies_in_xdmf(tmp_path):
    """A tri6 block on a quad8 base: one Mixed XDMF topology with the VTU's connectivity."""
    res = sc.solve_static(block_model("tri6", "quad8", push=False), store_fields="all")
    sc.export_vtu(res, tmp_path, states=[-1])
    xdmf = sc.export_xdmf(res, tmp_path / "mixed.xdmf", states=[-1])
    (_, file), = read_pvd(tmp_path / "result.pvd")
    mesh = meshio.read(file)
    assert [c.type for c in mesh.cells] == ["quad8", "triangle6"]
    points, cells = xdmf_mixed_cells(xdmf)
    assert_array_equal(points, mesh.points)
    assert [t for t, _ in cells] == [0x25] * len(mesh.cells[0]) + [0x24] * len(mesh.cells[1])
    assert_array_equal(np.concatenate([c for _, c in cells]),
                       np.concatenate([b.data.ravel() for b in mesh.cells]))


def test_frame_elements_are_line_cells(frame, tmp_path):
    _, res = frame
    sc.export_vtu(res, tmp_path)
    xdmf = sc.export_xdmf(res, tmp_path / "frame.xdmf", states="all")
    entries = read_pvd(tmp_path / "result.pvd")
    assert len(entries) == res.n_states
    dof = np.asarray(res.geometry["dof_of"])
    beam = next(b for b in res.geometry["bodies"] if b["name"] == "beam")
    with meshio.xdmf.TimeSeriesReader(xdmf) as r:
        points, cells = r.read_points_cells()
        assert r.num_steps == res.n_states
        xdmf_frames = [r.read_data(k) for k in range(r.num_steps)]
    assert [c.type for c in cells] == ["quad", "line"]
    assert_array_equal(cells[1].data, beam["cells"])
    for k, ((time, file), i) in enumerate(zip(entries, range(res.n_states), strict=True)):
        mesh = meshio.read(file)
        assert [c.type for c in mesh.cells] == ["quad", "line"]
        assert_array_equal(mesh.cells[1].data, beam["cells"])
        body = cat(mesh.cell_data, "body")
        assert_array_equal(body, np.r_[np.zeros(len(mesh.cells[0])), np.ones(len(beam["cells"]))])
        assert np.isnan(cat(mesh.cell_data, "sigma_xx")[body == 1]).all()
        rot = mesh.point_data["rotation"]
        has = dof[:, 2] >= 0
        assert_array_equal(rot[has], res.displacement(i)[dof[has, 2]])
        assert np.isnan(rot[~has]).all()
        assert_array_equal(mesh.point_data["displacement"][:, :2], nodal(res, i))
        t_x, pd_x, cd_x = xdmf_frames[k]
        assert t_x == time
        assert_array_equal(points, mesh.points)
        assert_array_equal(pd_x["displacement"], mesh.point_data["displacement"])
        assert_array_equal(pd_x["rotation"], rot)
        assert_array_equal(np.concatenate(cd_x["body"]), body)
    # CFE series from XDMF: the supports lift off one after another
    with meshio.xdmf.TimeSeriesReader(tmp_path / "frame_cfe.xdmf") as r:
        _, cells = r.read_points_cells()
        assert [c.type for c in cells] == ["line"] and len(cells[0]) == res.m
        for k in range(r.num_steps):
            _, _, cd = r.read_data(k)
            assert_array_equal(cd["N"][0], res.N[k])
            assert_array_equal(cd["state"][0], res.state[k])


def test_cfe_ends_interpolated_when_known(tmp_path):
    """With the CFE end nodes the S− points are exact and the ends carry displacements whose
    difference gives u_n and u_τ of the result."""
    m = block_model("quad4", "quad8", gap=1e-4)  # node-to-segment on a quadratic edge
    res = with_cfe_ends(sc.solve_static(m, store_fields="all"), m)
    c = sc.assemble(m).cfe
    sc.export_vtu(res, tmp_path, states="all")
    entries = read_pvd(tmp_path / "result_cfe.pvd")
    xy = np.asarray(res.geometry["points"])
    minus = np.einsum("kj,kjc->kc", np.where(c.minus_nodes >= 0, c.minus_w, 0.0),
                      xy[np.maximum(c.minus_nodes, 0)])
    mm = res.m
    for i, (_, file) in enumerate(entries):
        mesh = meshio.read(file)
        assert_allclose(mesh.points[mm:, :2], minus, atol=1e-14)
        assert_array_equal(mesh.points[:mm, :2], res.cfe["x"])
        u = mesh.point_data["displacement"][:, :2]
        du = u[:mm] - u[mm:]
        n = res.cfe["normal"]
        tan = np.column_stack([n[:, 1], -n[:, 0]])
        scale = np.abs(du).max() + 1e-30
        assert_allclose(-np.sum(n * du, axis=1) - res.cfe["gap"], res.un[i], atol=1e-9 * scale)
        assert_allclose(np.sum(tan * du, axis=1), res.ut[i], atol=1e-9 * scale)
    # without the end nodes the S− point is drawn at x − g n
    res.cfe = {k: v for k, v in res.cfe.items() if k not in ex._CFE_END_KEYS}
    sc.export_vtu(res, tmp_path, states=[0], name="plain")
    mesh = meshio.read(read_pvd(tmp_path / "plain_cfe.pvd")[0][1])
    assert_allclose(mesh.points[mm:, :2], res.cfe["x"] - 1e-4 * res.cfe["normal"])


# --------------------------------------------------------------------------------------------
# result file round trip, skipped states, atomic writes
# --------------------------------------------------------------------------------------------
def _series(path: Path) -> list[dict[str, np.ndarray]]:
    out = []
    for time, file in read_pvd(path):
        mesh = meshio.read(file)
        arrays = {"time": np.array([time]), "points": mesh.points}
        arrays |= {f"p_{k}": v for k, v in mesh.point_data.items()}
        arrays |= {f"c_{k}": np.concatenate(v) for k, v in mesh.cell_data.items()}
        arrays |= {f"f_{k}": v for k, v in mesh.field_data.items()}
        out.append(arrays)
    return out


def test_round_trip_through_the_result_file(block, tmp_path):
    model, res = block
    res = with_cfe_ends(res, model)
    res.save(tmp_path / "run.nc")
    loaded = load_result(tmp_path / "run.nc")
    sc.export_vtu(res, tmp_path / "a")
    sc.export_vtu(loaded, tmp_path / "b")
    for name in ("result.pvd", "result_cfe.pvd"):
        a, b = _series(tmp_path / "a" / name), _series(tmp_path / "b" / name)
        assert len(a) == len(b) == res.n_states
        for fa, fb in zip(a, b, strict=True):
            assert fa.keys() == fb.keys()
            for k in fa:
                assert_array_equal(fa[k], fb[k], err_msg=k)
    sc.export_xdmf(loaded, tmp_path / "b.xdmf")
    with meshio.xdmf.TimeSeriesReader(tmp_path / "b_cfe.xdmf") as r:
        r.read_points_cells()
        frames = [r.read_data(k) for k in range(r.num_steps)]
    assert [t for t, _, _ in frames] == [f["time"][0] for f in a]
    for (_, pd, cd), fa in zip(frames, a, strict=True):
        assert_array_equal(pd["displacement"], fa["p_displacement"])
        for key in ("N", "Q", "state", "un", "ut"):
            assert_array_equal(cd[key][0], fa[f"c_{key}"])


def test_states_without_fields_are_skipped(tmp_path, caplog):
    res = sc.solve_static(block_model(), store_fields="ends")
    res.save(tmp_path / "ends.nc")
    loaded = load_result(tmp_path / "ends.nc")
    stored = sorted(loaded.fields)
    assert len(stored) < loaded.n_states
    with caplog.at_level(logging.WARNING, logger="stepcontact.io.export"):
        sc.export_vtu(loaded, tmp_path / "v", states="all")
    assert "skipped" in caplog.text
    entries = read_pvd(tmp_path / "v" / "result.pvd")
    assert [int(meshio.read(f).field_data["state"][0]) for _, f in entries] == stored
    not_stored = [i for i in range(loaded.n_states) if i not in loaded.fields]
    with pytest.raises(ValueError, match="no selected state has stored displacements"):
        sc.export_xdmf(loaded, tmp_path / "x.xdmf", states=not_stored)
    # in memory, the solver recomputes any state: all of them are exported
    sc.export_vtu(res, tmp_path / "w", states="events")
    n_events = int(np.sum(np.asarray(res.kind) == "event"))
    assert len(read_pvd(tmp_path / "w" / "result.pvd")) == n_events > 0


def test_writes_are_atomic(block, tmp_path, monkeypatch):
    _, res = block
    out = tmp_path / "pv"
    sc.export_vtu(res, out, states="ends")
    sc.export_xdmf(res, out / "r.xdmf", states="ends")
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    calls = []
    real = ex._write_vtu

    def failing(*args, **kwargs):
        calls.append(1)
        if len(calls) > 3:
            raise KeyboardInterrupt
        real(*args, **kwargs)

    monkeypatch.setattr(ex, "_write_vtu", failing)
    with pytest.raises(KeyboardInterrupt):
        sc.export_vtu(res, out, states="all")
    monkeypatch.setattr(ex, "_iter_frames", lambda *a: iter([(0, 0.0, 0.0, None, None)]))
    with pytest.raises(TypeError):
        sc.export_xdmf(res, out / "r.xdmf", states="all")
    after = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    assert after == before  # the old series are untouched, no temporary files are left
    assert sorted(p.name for p in out.iterdir()) == sorted(
        ["result", "result.pvd", "result_cfe.pvd", "r.xdmf", "r.h5", "r_cfe.xdmf", "r_cfe.h5"])
    # a folder of the series' name that holds other files is never replaced
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("keep", encoding="utf-8")
    monkeypatch.undo()
    with pytest.raises(FileExistsError):
        sc.export_vtu(res, tmp_path, name="mine")
    assert (tmp_path / "mine" / "notes.txt").read_text(encoding="utf-8") == "keep"
    # a new export replaces the series: fewer frames leave no stale files
    sc.export_vtu(res, out, states=[0])
    assert len(list((out / "result").iterdir())) == 2


# --------------------------------------------------------------------------------------------
# command line
# --------------------------------------------------------------------------------------------
runner = CliRunner()


@pytest.fixture(scope="module")
def result_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("cli") / "run.nc"
    sc.solve_static(block_model(), store_fields="ends").save(path)
    return path


def test_cli_export(result_file, tmp_path):
    res = load_result(result_file)
    vtu, xdmf = tmp_path / "vtu", tmp_path / "x" / "run.xdmf"
    out = runner.invoke(app, ["export", str(result_file), "--vtu", str(vtu), "--xdmf", str(xdmf)])
    assert out.exit_code == 0, out.output
    assert "skipped" in out.stdout and "written:" in out.stdout
    assert len(read_pvd(vtu / "run.pvd")) == len(res.fields)
    assert xdmf.is_file() and xdmf.with_suffix(".h5").is_file()
    out = runner.invoke(app, ["export", str(result_file), "--vtu", str(vtu), "--states", "ends",
                              "--name", "ends", "--json"])
    assert out.exit_code == 0, out.output
    summary = json.loads(out.stdout)
    ends = np.flatnonzero(np.asarray(res.kind) == "segment_end").tolist()
    assert summary["status"] == "ok" and summary["states"] == ends and summary["skipped"] == []
    assert summary["written"] == [str(vtu / "ends.pvd"), str(vtu / "ends_cfe.pvd")]
    out = runner.invoke(app, ["export", str(result_file), "--vtu", str(vtu), "-q"])
    assert out.exit_code == 0 and out.stdout == ""


def test_cli_export_errors(result_file, tmp_path):
    vtu = ["--vtu", str(tmp_path / "v")]
    out = runner.invoke(app, ["export", str(tmp_path / "nothere.nc"), *vtu])
    assert_one_line_error(out, "result file not found")
    text = tmp_path / "notes.txt"
    text.write_text("not a result\n", encoding="utf-8")
    out = runner.invoke(app, ["export", str(text), *vtu])
    assert_one_line_error(out, "not a stepcontact result file")
    other = tmp_path / "other.nc"
    xr.Dataset({"a": ("x", np.arange(3))}).to_netcdf(other, engine="h5netcdf")
    out = runner.invoke(app, ["export", str(other), *vtu, "--json"])
    assert_one_line_error(out, "not a stepcontact")
    assert json.loads(out.stdout)["status"] == "error"
    out = runner.invoke(app, ["export", str(result_file)])
    assert_one_line_error(out, "nothing to export")
    out = runner.invoke(app, ["export", str(result_file), "--xdmf", str(tmp_path / "r.vtu")])
    assert_one_line_error(out, "must end in .xdmf")
    out = runner.invoke(app, ["export", str(result_file), *vtu, "--states", "most"])
    assert_one_line_error(out, "--states")
    res = load_result(result_file)
    not_stored = ",".join(str(i) for i in range(res.n_states) if i not in res.fields)
    out = runner.invoke(app, ["export", str(result_file), *vtu, "--states", not_stored])
    assert_one_line_error(out, "none of the selected states has stored displacements")
    assert not (tmp_path / "v").exists()


def test_cli_export_help():
    out = runner.invoke(app, ["export", "--help"])
    assert out.exit_code == 0
    for fragment in ("--vtu", "--xdmf", "--states", "--json", "stepcontact export run.nc"):
        assert fragment in out.output
