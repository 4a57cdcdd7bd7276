"""Gmsh mesh → model file → run → result file → VTU series → read back with meshio.

The committed example (examples/data/gmsh_block.*) has non-matching meshes along the joint.
References: the block slides as a whole at H = f·W, W from the cell areas of the block read
independently from the .msh file with meshio; the VTU values equal the result's arrays.
"""

from __future__ import annotations

from pathlib import Path

import meshio
import numpy as np
import pytest
from typer.testing import CliRunner

import stepcontact as sc
from stepcontact.cli import app
from stepcontact.io.modelfile import load_model

DATA = Path(__file__).resolve().parents[1] / "examples" / "data"
G = 9.81


def _block_weight() -> float:
    """W = ρ g A of the block from the raw .msh (shoelace areas of its triangles/quads)."""
    msh = meshio.read(DATA / "gmsh_block.msh")
    tag = msh.field_data["block"][0]
    area = 0.0
    for block, phys in zip(msh.cells, msh.cell_data["gmsh:physical"], strict=True):
        if block.type not in ("triangle", "quad"):
            continue
        cells = block.data[phys == tag]
        xy = msh.points[cells][..., :2]
        x, y = xy[..., 0], xy[..., 1]
        area += 0.5 * np.abs(np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y,
                                    axis=1)).sum()
    return 2400.0 * G * area


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("roundtrip")
    runner = CliRunner()
    r = runner.invoke(app, ["run", str(DATA / "gmsh_block.toml"), "-o", str(out / "res.nc"),
                            "--no-plot", "--quiet"])
    assert r.exit_code == 0, r.output
    r = runner.invoke(app, ["export", str(out / "res.nc"), "--vtu", str(out / "vtu")])
    assert r.exit_code == 0, r.output
    return out


def test_gmsh_model_slides_at_f_w(run_dir):
    res = sc.load_result(run_dir / "res.nc")
    W = _block_weight()
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(0.5 * W, rel=1e-9)
    # non-matching meshes: some CFE ends are interpolated (mortar: the end on the finer face,
    # S+ or S−)
    w = np.concatenate([res.cfe["plus_w"], res.cfe["minus_w"]], axis=1)
    assert np.any((w > 1e-6) & (w < 1 - 1e-6))


def test_vtu_series_reads_back_with_the_result_values(run_dir):
    res = sc.load_result(run_dir / "res.nc")
    pvd = sorted((run_dir / "vtu").glob("*.pvd"))
    assert pvd, "no .pvd written"
    frames = sorted((run_dir / "vtu").rglob("*.vtu"))
    body_frames = [f for f in frames if "_cfe" not in f.name]
    cfe_frames = [f for f in frames if "_cfe" in f.name]
    # export found the model file the run recorded: every state is exported, the states whose
    # fields the file does not store recomputed from it
    res.recover_fields(load_model(DATA / "gmsh_block.toml"))
    stored = list(range(res.n_states))
    assert len(body_frames) == len(stored) == len(cfe_frames)
    dof_of = np.asarray(res.geometry["dof_of"])
    for f_body, f_cfe in zip(body_frames, cfe_frames, strict=True):
        mesh = meshio.read(f_body)
        i = int(mesh.field_data["state"][0])
        u = res.displacement(i)
        expected = u[dof_of[:, :2]]
        assert np.allclose(mesh.point_data["displacement"][:, :2], expected, rtol=0,
                           atol=1e-12 * max(np.abs(expected).max(), 1e-300))
        assert np.allclose(mesh.points[:, :2], np.asarray(res.geometry["points"]))
        c = meshio.read(f_cfe)
        assert int(c.field_data["state"][0]) == i
        assert np.array_equal(c.cell_data["N"][0], res.N[i])
        assert np.array_equal(c.cell_data["state"][0], res.state[i])
