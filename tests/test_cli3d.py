"""``stepcontact validate / run / info / export / plot`` end to end on 3D model files (issue 28
§4): a box on a box joined by mortar CFEs on the faceted cone (facets, facet_angle), and the
same two blocks from a Gmsh .msh file (physical volumes as bodies, physical surfaces as node
sets and interface sides), written in the test with gmsh's Python API.

References (hand statics; independent of the code under test):
* the block (1 × 1 × 0.5 m, ρ = 2400 kg/m³, W = ρ g V) pushed along θ on its top slides at
  the inscribed k-gon's limit f W cos(π/k) / cos(θ − θ_v), θ_v the facet normal nearest θ:
  the normals at facet_angle + (j + ½) 2π/k; to 1e-9 relative;
* the load resultants of the run (force and moment about the origin, 3D): the push F = (cos θ,
  sin θ, 0) per unit λ acting on the top face centred at r = (0.5, 0.5, 0.5), M = r × F; the
  weight (0, 0, −W) at the centroid (0.5, 0.5, 0.25); to 1e-12 relative (round-off);
* the λ–u curve of a node along z: the values drawn equal the z displacement of that node
  in the result at every state (exactly: the same numbers);
* the event positions: every CFE of the joint lies on z = 0, so event z = 0 exactly; their
  (x, y, z) is the CFE's S+ point (the result's ``cfe["x"]``).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import meshio
import numpy as np
import pytest
from typer.testing import CliRunner

import stepcontact as sc
from cli_checks import assert_one_line_error
from figure_checks import assert_readable
from stepcontact.cli import app, events_table

runner = CliRunner()
F, K, THETA = 0.5, 8, 0.3
W = 2400.0 * 9.81 * 0.5  # the block's weight, N
TOL = 1e-9

HEAD = """\
[model]
name = "block on a base"

[materials.concrete]
E = 30e9
nu = 0.2
density = 2400
"""
BOXES = """
[[bodies]]
name = "block"
kind = "box"
corner0 = [0.0, 0.0, 0.0]
corner1 = [1.0, 1.0, 0.5]
nx = 2
ny = 2
nz = 1
material = "concrete"

[[bodies]]
name = "base"
kind = "box"
corner0 = [-0.5, -0.5, -0.5]
corner1 = [1.5, 1.5, 0.0]
nx = 3
ny = 3
nz = 1
material = "concrete"

[node_sets.block_bottom]
body = "block"
boundary = "bottom"

[node_sets.block_top]
body = "block"
boundary = "top"

[node_sets.base_top]
body = "base"
boundary = "top"

[node_sets.base_bottom]
body = "base"
boundary = "bottom"
"""
REST = f"""
[[supports]]
name = "bed"
nodes = "base_bottom"
dofs = "xyz"

[[interfaces]]
name = "joint"
plus = "block_bottom"
minus = "base_top"
friction = {F}
cfe = "mortar"
facets = {K}
FACET_ANGLE

[patterns.weight]
loads = [{{ type = "gravity", bodies = ["block"] }}]

[patterns.push]
loads = [
{{ type = "edge_force", nodes = "block_top", fx = {math.cos(THETA)!r}, fy = {math.sin(THETA)!r} }},
]

[[program]]
pattern = "weight"
end = 1.0

[[program]]
pattern = "push"
end = 1e5
"""


def hand_limit(k: int, theta: float, angle: float) -> float:
    """f W cos(π/k) / cos(θ − θ_v), θ_v the facet normal angle + (j + ½) 2π/k nearest θ."""
    step = 2 * math.pi / k
    j = round((theta - angle) / step - 0.5)
    normal = angle + (j + 0.5) * step
    return F * W * math.cos(math.pi / k) / math.cos(theta - normal)


def boxes_file(folder: Path, facet_angle: float | None = math.pi / 8) -> Path:
    path = folder / "bob.toml"
    angle = "" if facet_angle is None else f"facet_angle = {facet_angle!r}"
    path.write_text(HEAD + BOXES + REST.replace("FACET_ANGLE", angle))
    return path


@pytest.fixture(scope="module")
def boxes(tmp_path_factory):
    """validate and run of the box-on-box file: (model file, result file, run output)."""
    tmp = tmp_path_factory.mktemp("boxes3d")
    path = boxes_file(tmp)
    out = runner.invoke(app, ["validate", str(path)])
    assert out.exit_code == 0, out.output
    assert "model OK" in out.output and "9 CFEs" in out.output and "150 DOFs" in out.output
    result = tmp / "bob.nc"
    out = runner.invoke(app, ["run", str(path), "-o", str(result)])  # and its figure
    assert out.exit_code == 0, out.output
    return path, result, out.output


def test_run_draws_the_joint_and_refuses_lam_before_solving(boxes, tmp_path):
    """The run's figure is the joint in its own plane (bob.png beside the result); --lam of
    a 3D run is refused before any work."""
    path, result, output = boxes
    assert result.with_suffix(".png").stat().st_size > 0 and "bob.png" in output
    out = runner.invoke(app, ["run", str(path), "-o", str(tmp_path / "r.nc"), "--lam", "3"])
    assert_one_line_error(out, "--kind stresses --state")
    assert not (tmp_path / "r.nc").exists()


def test_run_slides_at_the_hand_limit_of_the_faceted_cone(boxes):
    """facet_angle = π/8 puts a facet normal along x: θ_v = 0 for θ = 0.3 (1e-9)."""
    _, result, output = boxes
    res = sc.load_result(result)
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert res.lam[-1] == pytest.approx(hand_limit(K, THETA, math.pi / 8), rel=TOL)
    assert res.lam[-1] == pytest.approx(F * W * math.cos(math.pi / 8) / math.cos(THETA),
                                        rel=TOL)
    assert "inscribed 8-gon" in res.message and "equilibrium_lost" in output


def test_events_have_their_3d_position_in_the_result_file(boxes):
    _, result, _ = boxes
    res = sc.load_result(result)
    x = np.asarray(res.cfe["x"], float)
    assert res.events and all(e.z == 0.0 for e in res.events)
    for e in res.events:
        assert e.point == tuple(x[e.cfe])
    table = res.events_table()
    assert np.array_equal(table["z"].to_numpy(float), np.zeros(len(res.events)))
    table = events_table(res)  # the run's event table shows the CFE's point
    assert str(table.columns[4].header) == "x, y, z (m)"
    first = str(list(table.columns[4].cells)[0])
    assert first == "({:.4g}, {:.4g}, 0)".format(*res.events[0].point)


def test_load_resultants_are_force_and_moment_vectors(boxes):
    _, result, output = boxes
    res = sc.load_result(result)
    F_push = np.array([math.cos(THETA), math.sin(THETA), 0.0])
    push = np.r_[F_push, np.cross([0.5, 0.5, 0.5], F_push)]
    weight = np.r_[0.0, 0.0, -W, np.cross([0.5, 0.5, 0.25], [0.0, 0.0, -W])]
    np.testing.assert_allclose(res.load_resultant("push"), push, rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.load_resultant("weight"), weight, rtol=0, atol=1e-12 * W)
    np.testing.assert_allclose(res.load_resultant("push", -1), res.lam[-1] * push, rtol=1e-12)
    assert "Fx, Fy, Fz in N; Mx, My, Mz about the origin" in output
    assert f"Fz = {-W:.6g}, Mx = {-W / 2:.6g}, My = {W / 2:.6g}" in output


def test_info_and_export(boxes, tmp_path):
    path, result, _ = boxes
    out = runner.invoke(app, ["info", str(result)])
    assert out.exit_code == 0, out.output
    assert "block (4 hex8), base (9 hex8)" in out.output and "bed:z" in out.output
    assert "inscribed 8-gon" in out.output and "eccentricities" in out.output
    out = runner.invoke(app, ["info", str(result), "--json"])
    assert out.exit_code == 0, out.output
    (sf,) = json.loads(out.output)["interface_safety"]
    res = sc.load_result(result)
    P = res.lam[-1]  # the push at the last state, N: its moment about the joint's centroid
    # (0.5, 0.5, 0) is balanced by the normal force W at (e₁, e₂) (e₁ along t₁ = x)
    e = (0.5 * P * math.cos(THETA) / W, 0.5 * P * math.sin(THETA) / W)
    assert sf["eccentricity"] == pytest.approx(e, rel=TOL)
    assert sf["normal_force"] == pytest.approx(-W, rel=TOL)
    assert sf["lam_sliding"] == res.lam[-1] and sf["facets"] == K
    for opt in (["--design", "1.0"], ["--cohesion", "2e5"]):  # not silently ignored in 3D
        out = runner.invoke(app, ["info", str(result), *opt])
        assert out.exit_code != 0 and f"{opt[0]}: the design-state check" in out.output
        assert "3D joints" in out.output and "Traceback" not in out.output
    out = runner.invoke(app, ["export", str(result), "--vtu", str(tmp_path / "pv"), "--model",
                              str(path)])
    assert out.exit_code == 0, out.output
    frames = sorted((tmp_path / "pv" / "bob").glob("bob_[0-9]*.vtu"))
    assert len(frames) == res.n_states
    mesh = meshio.read(frames[-1])
    assert [c.type for c in mesh.cells] == ["hexahedron"] and len(mesh.cells[0]) == 4 + 9
    assert (tmp_path / "pv" / "bob_cfe.pvd").exists()


def test_plot_kinds_of_a_3d_result(boxes, tmp_path):
    path, result, _ = boxes
    out = runner.invoke(app, ["plot", str(result), "--kind", "all", "-o", str(tmp_path),
                              "--model", str(path)])
    assert out.exit_code == 0, out.output
    drawn = sorted(p.name for p in tmp_path.glob("*.png"))
    assert drawn == ["bob-load-displacement.png", "bob-stresses.png", "bob-timeline.png"]
    out = runner.invoke(app, ["plot", str(result), "--kind", "stresses", "--interface", "joint",
                              "--state", "3", "--state", "-1", "-o", str(tmp_path / "m.png")])
    assert out.exit_code == 0 and (tmp_path / "m.png").stat().st_size > 0, out.output
    out = runner.invoke(app, ["plot", str(result), "--kind", "load-displacement", "--node",
                              "1,1,0.5", "--dof", "z", "--model", str(path), "-o",
                              str(tmp_path / "uz.png")])
    assert out.exit_code == 0 and (tmp_path / "uz.png").exists(), out.output


@pytest.mark.parametrize(("args", "fragment"), [
    (["--kind", "deformed"], "stepcontact export RESULT.nc --vtu"),
    (["--kind", "safety"], "stepcontact info RESULT.nc"),
    (["--kind", "stresses", "--interface", "seam"], "--interface 'seam': no such interface"),
    (["--kind", "stresses", "--lam", "10"], "give --state"),
    (["--kind", "load-displacement", "--node", "1,1", "--dof", "z"], "X,Y,Z in m (a 3D"),
    (["--kind", "load-displacement", "--node", "1,1,0.5", "--dof", "rz"], "'x', 'y', 'z'"),
])
def test_plot_errors_of_a_3d_result(boxes, args, fragment):
    path, result, _ = boxes
    out = runner.invoke(app, ["plot", str(result), *args, "--model", str(path)])
    assert_one_line_error(out, fragment)


def test_load_displacement_figure_of_a_node_along_z(boxes):
    """The curve drawn is u_z of the node nearest (1, 1, 0.5) at every state (the same
    numbers, in µm), labelled with its 3D place."""
    path, result, _ = boxes
    res = sc.load_result(result)
    res.recover_fields(sc.load_model(path))
    fig = sc.plot_load_displacement(res, node=(1.0, 1.0, 0.5), dof="z")
    assert_readable(fig)
    ax = fig.axes[-1]
    assert ax.get_xlabel().startswith("$u_z$ of node") and "z = 0.5 m" in ax.get_xlabel()
    pts = np.asarray(res.geometry["points"])
    k = int(np.argmin(np.linalg.norm(pts - [1.0, 1.0, 0.5], axis=1)))
    uz = res.displacements()[:, np.asarray(res.geometry["dof_of"])[k, 2]]
    line = ax.get_lines()[0]
    idx = np.flatnonzero(np.asarray(res.segment) == 1)
    drawn = np.asarray(line.get_xdata(), float)
    assert np.allclose(drawn, uz[idx] / 1e-6, rtol=1e-12, atol=0)  # µm


# --------------------------------------------------------------------------------------------
# the two blocks from a Gmsh file
# --------------------------------------------------------------------------------------------
def write_two_boxes_msh(path: Path) -> Path:
    """The block and the base as two separate gmsh volumes (not conforming: the joint's
    nodes are twice), transfinite hexahedra 2 × 2 × 1 and 3 × 3 × 1; physical volumes
    'block', 'base' and physical surfaces 'block_bottom', 'block_top', 'base_top',
    'base_bottom'."""
    gmsh = pytest.importorskip("gmsh")
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("two")
        occ = gmsh.model.occ
        block = occ.addBox(0, 0, 0, 1, 1, 0.5)
        base = occ.addBox(-0.5, -0.5, -0.5, 2, 2, 0.5)
        occ.synchronize()
        for vol, cells, name in ((block, (2, 2, 1), "block"), (base, (3, 3, 1), "base")):
            gmsh.model.addPhysicalGroup(3, [vol], name=name)
            faces = [t for _, t in gmsh.model.getBoundary([(3, vol)], oriented=False)]
            for _, c in gmsh.model.getBoundary([(2, f) for f in faces], combined=False,
                                               oriented=False):
                bb = gmsh.model.getBoundingBox(1, abs(c))
                axis = int(np.argmax(np.subtract(bb[3:], bb[:3])))
                gmsh.model.mesh.setTransfiniteCurve(abs(c), cells[axis] + 1)
            for f in faces:
                gmsh.model.mesh.setTransfiniteSurface(f)
                gmsh.model.mesh.setRecombine(2, f)
            gmsh.model.mesh.setTransfiniteVolume(vol)
            z = {f: occ.getCenterOfMass(2, f)[2] for f in faces}
            low, high = min(z, key=z.get), max(z, key=z.get)
            gmsh.model.addPhysicalGroup(2, [low], name=f"{name}_bottom")
            gmsh.model.addPhysicalGroup(2, [high], name=f"{name}_top")
        gmsh.model.mesh.generate(3)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    return path


GMSH_FILE = HEAD + """
[mesh]
file = "two.msh"

[[bodies]]
kind = "mesh"
group = "block"
material = "concrete"

[[bodies]]
kind = "mesh"
group = "base"
material = "concrete"
""" + REST


def test_gmsh_file_runs_end_to_end(tmp_path):
    """Physical volumes → bodies of hex8, physical surfaces → the support's nodes, the
    interface's sides and the push's faces (named directly, no [node_sets]); the default
    facet_angle 0 puts the facet normals at π/8 + jπ/4: the block slides at
    f W cos(π/8) / cos(θ − π/8) (1e-9)."""
    write_two_boxes_msh(tmp_path / "two.msh")
    path = tmp_path / "two.toml"
    path.write_text(GMSH_FILE.replace("FACET_ANGLE", ""))
    out = runner.invoke(app, ["validate", str(path)])
    assert out.exit_code == 0, out.output
    assert "model OK" in out.output and "150 DOFs" in out.output
    model = sc.load_model(path)
    assert model.dim == 3 and [b.element for b in model.bodies] == ["hex8", "hex8"]
    result = tmp_path / "two.nc"
    out = runner.invoke(app, ["run", str(path), "-o", str(result), "--no-plot"])
    assert out.exit_code == 0, out.output
    res = sc.load_result(result)
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert res.lam[-1] == pytest.approx(hand_limit(K, THETA, 0.0), rel=TOL)
    assert res.lam[-1] == pytest.approx(
        F * W * math.cos(math.pi / 8) / math.cos(THETA - math.pi / 8), rel=TOL)
    out = runner.invoke(app, ["info", str(result)])
    assert out.exit_code == 0 and "block (4 hex8), base (9 hex8)" in out.output, out.output


def test_gmsh_file_errors_name_the_group(tmp_path):
    """A physical volume that is no body, and a group name that does not exist, are named."""
    write_two_boxes_msh(tmp_path / "two.msh")
    path = tmp_path / "two.toml"
    text = GMSH_FILE.replace("FACET_ANGLE", "")
    path.write_text(text.replace(
        '[[bodies]]\nkind = "mesh"\ngroup = "base"\nmaterial = "concrete"\n', ""))
    out = runner.invoke(app, ["validate", str(path)])
    assert out.exit_code != 0
    assert "physical volume 'base' is not a body" in out.output, out.output
    path.write_text(text.replace('minus = "base_top"', 'minus = "base_topp"'))
    out = runner.invoke(app, ["validate", str(path)])
    assert out.exit_code != 0 and "interfaces[0].minus" in out.output, out.output
    assert "unknown node set 'base_topp'" in out.output and "'base_top'" in out.output
