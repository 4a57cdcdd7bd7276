"""Gmsh mesh input (stepcontact.io.meshfile), mesh bodies in model files and `stepcontact validate`.

The committed example mesh (examples/data/gmsh_block.msh, made from gmsh_block.geo) is read
without gmsh; tests that mesh .geo files need the gmsh package and are skipped without it.
Small meshes with crafted defects are written with meshio (gmsh 2.2 format).
"""

from __future__ import annotations

import json
import shutil
import sys
import textwrap
from pathlib import Path

import meshio
import numpy as np
import pytest
from numpy.testing import assert_allclose
from typer.testing import CliRunner

import stepcontact as sc
from stepcontact import ModelError
from stepcontact.cli import app
from stepcontact.fem.continuum import stiffness
from stepcontact.io.meshfile import mesh_geo, read_mesh, read_msh
from stepcontact.io.modelfile import load_model, validate_model_file, validation_report

DATA = Path(__file__).resolve().parent.parent / "examples" / "data"
def _need_gmsh() -> None:
    """Skip unless gmsh imports (its wheel needs system GL/X libraries that may be missing)."""
    try:
        import gmsh  # noqa: F401
    except (ImportError, OSError) as e:
        pytest.skip(f"gmsh not usable here: {e}")


MSH = DATA / "gmsh_block.msh"
GEO = DATA / "gmsh_block.geo"
TOML = DATA / "gmsh_block.toml"
CONCRETE = sc.Material(30e9, 0.2, 2400)
runner = CliRunner()


def write_msh(path: Path, points, groups) -> Path:
    """A gmsh 2.2 file: ``groups`` is a list of (name, dim, cell type, cells)."""
    pts = np.asarray(points, dtype=float)
    cells, phys, field = [], [], {}
    for tag, (name, dim, kind, c) in enumerate(groups, start=1):
        c = np.asarray(c, dtype=np.int64)
        cells.append((kind, c))
        phys.append(np.full(len(c), tag))
        field[name] = np.array([tag, dim])
    mesh = meshio.Mesh(np.column_stack([pts, np.zeros(len(pts))]), cells,
                       cell_data={"gmsh:physical": phys, "gmsh:geometrical": phys},
                       field_data=field)
    meshio.write(path, mesh, file_format="gmsh22", binary=False)
    return path


def signed_areas(body) -> np.ndarray:
    xy = body.points[body.cells[:, :3]]
    d1, d2 = xy[:, 1] - xy[:, 0], xy[:, 2] - xy[:, 0]
    return 0.5 * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])


def area(body) -> float:
    """Area of a body of straight-sided triangles or quads, m² (shoelace over the corners)."""
    xy = body.points[body.mesh.t.T]
    x, y = xy[..., 0], xy[..., 1]
    return float(0.5 * np.abs((x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y)
                              .sum(axis=1)).sum())


def model_text(**replace: str) -> str:
    """The example model file with lines replaced (key: the start of the line)."""
    lines = TOML.read_text(encoding="utf-8").splitlines()
    for start, new in replace.items():
        idx = [i for i, line in enumerate(lines) if line.startswith(start)]
        assert idx, start
        lines[idx[0]] = new
    return "\n".join(lines) + "\n"


@pytest.fixture
def model_dir(tmp_path) -> Path:
    """A copy of the example's model and mesh files."""
    shutil.copy(TOML, tmp_path / "model.toml")
    shutil.copy(MSH, tmp_path / "gmsh_block.msh")
    return tmp_path


# --------------------------------------------------------------------------------------------
# reading the committed mesh
# --------------------------------------------------------------------------------------------
def test_committed_msh_gives_bodies_and_node_sets():
    mf = read_msh(MSH)
    assert mf.surfaces == ["foundation", "block"]
    assert mf.curves == ["base", "foundation_top", "block_bottom", "push_face"]
    assert mf.point_groups == ["block_top_left"]
    found, block = mf.body("foundation", CONCRETE), mf.body("block", CONCRETE)
    assert (found.element, found.n_nodes, len(found.cells)) == ("quad4", 44, 30)  # 10 x 3
    assert (block.element, block.n_nodes, len(block.cells)) == ("tri3", 55, 84)
    # each body keeps only its own nodes; all cells counter-clockwise
    assert found.n_nodes + block.n_nodes == len(mf.points)
    assert (signed_areas(block) > 0).all() and (signed_areas(found) > 0).all()
    assert area(found) == pytest.approx(4.0, rel=1e-12)
    assert area(block) == pytest.approx(2.0, rel=1e-12)
    expected = {"base": ("foundation", 11), "foundation_top": ("foundation", 11),
                "block_bottom": ("block", 9), "push_face": ("block", 5),
                "block_top_left": ("block", 1)}
    bodies = {"foundation": found, "block": block}
    for group, (body, n) in expected.items():
        ns = mf.node_set(group)
        assert (ns.body, len(ns), ns.name) == (body, n, group)
        xy = bodies[body].points[ns.index]
        assert_allclose(xy, mf.points[mf.node_ids(group)])
        assert np.isin(ns.index, bodies[body].boundary).all()
    assert_allclose(found.points[mf.node_set("base").index, 1], 0.0)
    assert_allclose(block.points[mf.node_set("push_face").index, 0], 1.0)
    assert_allclose(block.points[mf.node_set("block_top_left").index], [[1.0, 2.0]])
    # ordered along the curve, and not matching across the joint
    xs = found.points[mf.node_set("base").index, 0]
    assert (np.diff(xs) > 0).all() or (np.diff(xs) < 0).all()
    top = found.points[mf.node_set("foundation_top").index, 0]
    bottom = block.points[mf.node_set("block_bottom").index, 0]
    assert not np.isin(np.round(bottom, 9), np.round(top, 9)).all()
    assert mf.orphan_nodes().size == 0


def test_model_from_msh_slides_at_f_times_weight():
    model = load_model(TOML)
    assert model.name == "gmsh-block"
    assert [b.name for b in model.bodies] == ["foundation", "block"]
    assert [len(s.nodes) for s in model.supports] == [11]
    res = sc.solve_static(model)
    block = model.body("block")
    W = area(block) * 2400 * 9.81 * model.thickness  # weight from the cell areas, N
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(0.5 * W, rel=1e-6)


def test_quadratic_and_quad8_meshes_match_the_rectangle_generator(tmp_path):
    """Crafted quad8 / triangle6 meshes of a 2 m × 1 m plate, with clockwise cells: the quad8
    one has the stiffness spectrum of the built-in rectangle; both have 3 rigid-body modes."""
    x, y = np.meshgrid([0.0, 0.5, 1.0, 1.5, 2.0], [0.0, 0.5, 1.0])
    pts = np.column_stack([x.ravel(), y.ravel()])
    n = lambda i, j: 5 * j + i  # noqa: E731 - grid node (i along x, j along y)
    quad8 = [[n(0, 0), n(0, 2), n(2, 2), n(2, 0), n(0, 1), n(1, 2), n(2, 1), n(1, 0)],  # cw
             [n(2, 0), n(4, 0), n(4, 2), n(2, 2), n(3, 0), n(4, 1), n(3, 2), n(2, 1)]]
    tri6 = [[n(0, 0), n(2, 0), n(2, 2), n(1, 0), n(2, 1), n(1, 1)],
            [n(0, 0), n(0, 2), n(2, 2), n(0, 1), n(1, 2), n(1, 1)],  # cw
            [n(2, 0), n(4, 0), n(4, 2), n(3, 0), n(4, 1), n(3, 1)],
            [n(2, 0), n(4, 2), n(2, 2), n(3, 1), n(3, 2), n(2, 1)]]
    for kind, cells, element in (("quad8", quad8, "quad8"), ("triangle6", tri6, "tri6")):
        used = np.unique(cells)
        path = write_msh(tmp_path / f"{kind}.msh", pts,
                         [("plate", 2, kind, cells), ("left", 1, "line3",
                                                      [[n(0, 0), n(0, 2), n(0, 1)]])])
        mf = read_msh(path)
        body = mf.body("plate", CONCRETE)
        assert body.element == element and body.n_nodes == len(used)
        ev = np.linalg.eigvalsh(stiffness(body, "strain", 1.0).toarray())
        if kind == "quad8":  # the same mesh as the generator's: the same spectrum
            ref = sc.rectangle("ref", (0, 0), (2, 1), 2, 1, CONCRETE, element)
            ev_ref = np.linalg.eigvalsh(stiffness(ref, "strain", 1.0).toarray())
            assert_allclose(ev, ev_ref, rtol=1e-9, atol=1e-6 * ev_ref.max())
        else:
            assert (signed_areas(body) > 0).all()
            assert_allclose(signed_areas(body), 0.5)
        assert (np.abs(ev) < 1e-6 * ev.max()).sum() == 3  # rigid-body modes only
        left = mf.node_set("left")
        assert_allclose(body.points[left.index], [[0, 0], [0, 0.5], [0, 1]])


def test_linear_mesh_with_quadratic_elements(tmp_path):
    (tmp_path / "gmsh_block.msh").write_bytes(MSH.read_bytes())
    text = model_text(**{'group = "block"': 'group = "block"\nelement = "tri6"'})
    (tmp_path / "m.toml").write_text(text, encoding="utf-8")
    model = load_model(tmp_path / "m.toml")
    block = model.body("block")
    assert block.element == "tri6" and block.n_nodes > 55
    plus = model.interfaces[0].plus  # the mid-side nodes are on the joint too, in order
    assert len(plus) == 17
    x = block.points[plus.index, 0]
    assert_allclose(block.points[plus.index, 1], 1.0)
    assert (np.diff(x) > 0).all() or (np.diff(x) < 0).all()
    base = model.supports[0].nodes
    assert model.body(base.body).element == "quad4" and len(base) == 11
    res = sc.solve_static(model)
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(0.5 * 2 * 2400 * 9.81, rel=1e-6)
    with pytest.raises(ModelError, match="element 'tri3' cannot be used"):
        read_msh(MSH).body("foundation", CONCRETE, element="tri3")


def test_shared_curve_of_conforming_bodies_needs_the_body(tmp_path):
    pts = [[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]]
    path = write_msh(tmp_path / "two.msh", pts, [
        ("left", 2, "triangle", [[0, 1, 4], [0, 4, 3]]),
        ("right", 2, "quad", [[1, 2, 5, 4]]),
        ("mid", 1, "line", [[1, 4]]),
        ("bottom", 1, "line", [[0, 1], [1, 2]]),
    ])
    mf = read_msh(path)
    left, right = mf.body("left", CONCRETE), mf.body("right", CONCRETE)
    assert (left.n_nodes, right.n_nodes) == (4, 4)
    with pytest.raises(ModelError, match="lies on bodies 'left', 'right'") as info:
        mf.node_set("mid")
    assert info.value.item == "physical curve 'mid'"
    assert mf.node_set("mid", body="right").body == "right"
    assert len(mf.node_set("mid", body=left)) == 2
    with pytest.raises(ModelError, match="not on a single physical surface"):
        mf.node_set("bottom")
    # in a model file: the node set must say which body
    (tmp_path / "m.toml").write_text(textwrap.dedent("""
        [mesh]
        file = "two.msh"
        [materials.c]
        E = 1e9
        nu = 0.2
        [[bodies]]
        group = "left"
        material = "c"
        [[bodies]]
        group = "right"
        material = "c"
        [node_sets.joint]
        group = "mid"
        [[supports]]
        nodes = "mid"
        [patterns.p]
        loads = [{type = "nodal", nodes = "joint", fx = 1.0}]
        [[program]]
        pattern = "p"
        end = 1
        """), encoding="utf-8")
    with pytest.raises(ModelError) as info:
        load_model(tmp_path / "m.toml")
    items = dict(info.value.errors)
    assert "lies on bodies 'left', 'right'" in items["node_sets.joint.group"]
    assert 'add body = "..." to [node_sets.joint]' in items["node_sets.joint.group"]
    assert "lies on bodies" in items["supports[0].nodes"]
    fixed = (tmp_path / "m.toml").read_text().replace('group = "mid"\n',
                                                      'group = "mid"\nbody = "left"\n')
    fixed = fixed.replace('nodes = "mid"', 'nodes = "joint"')
    (tmp_path / "m.toml").write_text(fixed, encoding="utf-8")
    model = load_model(tmp_path / "m.toml")
    assert model.supports[0].nodes.body == "left"


# --------------------------------------------------------------------------------------------
# gmsh
# --------------------------------------------------------------------------------------------
def test_geo_to_msh_with_gmsh(tmp_path):
    _need_gmsh()
    out = mesh_geo(GEO, out=tmp_path / "block.msh")
    mf = read_msh(out)
    committed = read_msh(MSH)
    assert mf.groups == committed.groups
    assert mf.body("foundation", CONCRETE).n_nodes == 44  # structured: independent of gmsh
    # order 2, quads: the whole file meshed in a temporary directory from the model file
    shutil.copy(GEO, tmp_path / "gmsh_block.geo")
    text = model_text(**{"file =": 'file = "gmsh_block.geo"\norder = 2\nelement = "quad"'})
    (tmp_path / "quad.toml").write_text(text, encoding="utf-8")
    model = load_model(tmp_path / "quad.toml")
    assert not (tmp_path / "gmsh_block.msh").exists()
    assert {b.element for b in model.bodies} == {"quad9"}
    res = sc.solve_static(model)
    W = 2.0 * 2400 * 9.81
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(0.5 * W, rel=1e-6)


def test_gmsh_python_script(tmp_path):
    _need_gmsh()
    script = tmp_path / "plate.py"
    script.write_text(textwrap.dedent("""
        import sys
        import gmsh
        gmsh.initialize(readConfigFiles=False, interruptible=False)
        gmsh.option.setNumber("General.Terminal", 0)
        s = gmsh.model.occ.addRectangle(0, 0, 0, 2, 1)
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(2, [s], name="plate")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.5)
        gmsh.model.mesh.generate(2)
        gmsh.write(sys.argv[1])
        gmsh.finalize()
        """), encoding="utf-8")
    mf = read_mesh(script)
    assert mf.surfaces == ["plate"]
    assert area(mf.body("plate", CONCRETE)) == pytest.approx(2.0)


def test_missing_gmsh_is_a_clear_error(monkeypatch):
    monkeypatch.setitem(sys.modules, "gmsh", None)
    with pytest.raises(ModelError, match="pip install gmsh"):
        mesh_geo(GEO, out=Path("never.msh"))


# --------------------------------------------------------------------------------------------
# errors
# --------------------------------------------------------------------------------------------
def load_text(model_dir: Path, text: str):
    path = model_dir / "model.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ModelError) as info:
        load_model(path)
    return dict(info.value.errors), info.value


def test_unknown_group(model_dir):
    errors, err = load_text(model_dir, model_text(**{'group = "block"': 'group = "blok"',
                                                     'group = "push_face"': 'group = "left"'}))
    msg = errors["bodies[1].group"]
    assert "physical group 'blok' not found in gmsh_block.msh" in msg
    assert "surfaces 'foundation', 'block'" in msg
    assert "physical group 'left' not found" in errors["node_sets.left_face.group"]
    assert "physical surface 'block' is not a body" in errors["mesh"]
    with pytest.raises(ModelError, match="physical group 'blok' not found; groups are"):
        read_msh(MSH).body("blok", CONCRETE)
    with pytest.raises(ModelError, match="is a physical curve, a surface is needed"):
        read_msh(MSH).body("base", CONCRETE)
    errors, _ = load_text(model_dir, model_text(**{'plus = "block_bottom"': 'plus = "block"'}))
    assert "'block' is a physical surface" in errors["interfaces[0].plus"]


def test_missing_material_for_a_surface(model_dir):
    text = model_text(**{'material = "concrete"': "", 'material = "rock"': ""})
    errors, err = load_text(model_dir, text)
    assert err.item == "bodies[0].material"
    assert "physical surface 'foundation' has no material" in errors["bodies[0].material"]
    assert "physical surface 'block' has no material" in errors["bodies[1].material"]
    # a physical surface that is no body at all
    text = model_text().replace('[[bodies]]\nkind = "mesh"\ngroup = "block"\n'
                                'material = "concrete"\n', "")
    text = text.replace('bodies = ["block"]', 'bodies = ["foundation"]')
    text = text.replace('plus = "block_bottom"', 'plus = "base"')
    errors, _ = load_text(model_dir, text)
    assert "physical surface 'block' is not a body" in errors["mesh"]
    ok = text.replace('file = "gmsh_block.msh"', 'file = "gmsh_block.msh"\nignore = ["block"]')
    assert "mesh" not in load_text_ok_or_errors(model_dir, ok)


def load_text_ok_or_errors(model_dir: Path, text: str) -> dict:
    path = model_dir / "model.toml"
    path.write_text(text, encoding="utf-8")
    return {p.item: p.message for p in validate_model_file(path)}


def test_missing_mesh_file(model_dir):
    (model_dir / "gmsh_block.msh").unlink()
    errors, err = load_text(model_dir, model_text())
    assert err.item == "mesh.file"
    assert str(model_dir / "gmsh_block.msh") in errors["mesh.file"]
    assert "file not found" in errors["mesh.file"]
    assert len(errors) == 1  # the names of its groups are not reported as unknown
    errors, _ = load_text(model_dir, model_text(**{"[mesh]": "", "file =": ""}))
    assert "needs a mesh: add [mesh]" in errors["bodies[0]"]
    errors, _ = load_text(model_dir, model_text(**{"file =": 'file = "x.msh"\norder = 2'}))
    assert "only apply when meshing a .geo file" in errors["mesh"]


def test_inverted_element_names_group_and_element(tmp_path):
    pts = [[0, 0], [1, 0], [1, 1], [0, 1], [1.5, 0.5]]  # the fan's centre dragged outside
    fan = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    path = write_msh(tmp_path / "bad.msh", pts, [("plate", 2, "triangle", fan)])
    with pytest.raises(ModelError) as info:
        read_msh(path).body("plate", CONCRETE)
    assert info.value.item == "physical surface 'plate' element 1"
    assert "inverted (folded over element 0)" in info.value.problem
    # clockwise cells alone are reordered, not errors
    pts[4] = [0.5, 0.5]
    path = write_msh(tmp_path / "cw.msh", pts, [("plate", 2, "triangle", [[0, 4, 1]] + fan[1:])])
    assert (signed_areas(read_msh(path).body("plate", CONCRETE)) > 0).all()
    # a self-crossing quad, a zero-area triangle, mixed cell types
    q = [[0, 0], [1, 0], [1, 1], [0, 1]]
    path = write_msh(tmp_path / "bow.msh", q, [("plate", 2, "quad", [[0, 1, 3, 2]])])
    with pytest.raises(ModelError, match="element 0: is inverted"):
        read_msh(path).body("plate", CONCRETE)
    path = write_msh(tmp_path / "flat.msh", [[0, 0], [1, 0], [2, 0], [0, 1]],
                     [("plate", 2, "triangle", [[0, 1, 3], [0, 1, 2]])])
    with pytest.raises(ModelError, match="'plate' element 1: is degenerate"):
        read_msh(path).body("plate", CONCRETE)
    path = tmp_path / "mixed.msh"
    mesh = meshio.Mesh(np.zeros((5, 3)) + np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0],
                                                     [0, 1, 0], [2, 0, 0]]),
                       [("quad", np.array([[0, 1, 2, 3]])), ("triangle", np.array([[1, 4, 2]]))],
                       cell_data={"gmsh:physical": [np.array([1]), np.array([1])],
                                  "gmsh:geometrical": [np.array([1]), np.array([2])]},
                       field_data={"plate": np.array([1, 2])})
    meshio.write(path, mesh, file_format="gmsh22", binary=False)
    with pytest.raises(ModelError, match="mixes cell types quad, triangle"):
        read_msh(path).body("plate", CONCRETE)


def test_unreadable_and_empty_meshes(tmp_path):
    with pytest.raises(ModelError, match="file not found"):
        read_msh(tmp_path / "none.msh")
    (tmp_path / "junk.msh").write_text("not a mesh", encoding="utf-8")
    with pytest.raises(ModelError, match="cannot read the mesh"):
        read_msh(tmp_path / "junk.msh")
    mesh = meshio.Mesh(np.zeros((3, 3)) + np.eye(3), [("triangle", np.array([[0, 1, 2]]))])
    meshio.write(tmp_path / "nogroups.msh", mesh, file_format="gmsh22", binary=False)
    with pytest.raises(ModelError, match="not planar|no physical groups"):
        read_msh(tmp_path / "nogroups.msh")


# --------------------------------------------------------------------------------------------
# validate
# --------------------------------------------------------------------------------------------
LID = """
[[bodies]]
name = "lid"
kind = "rectangle"
corner0 = [1.5, 1.5]
corner1 = [2.5, 2.5]
nx = 2
ny = 2
material = "steel"
"""


def test_validate_reports_overlap_and_touching_is_fine(model_dir):
    assert validate_model_file(model_dir / "model.toml") == []
    report = validation_report(model_dir / "model.toml")
    # mortar CFEs on the coarser foundation (0.4 m cells): its 5 nodes under the block [1, 3]
    assert report.ok and report.n_cfes == 5 and report.summary()["bodies"] == 2
    text = model_text() + LID.replace('"steel"', '"concrete"')
    path = model_dir / "model.toml"
    path.write_text(text, encoding="utf-8")
    problems = validate_model_file(path)
    assert [p.item for p in problems] == ["bodies 'block' and 'lid'"]
    assert "overlap without an interface" in problems[0].message
    assert "physical surface 'block'" in problems[0].message
    load_model(path)  # overlapping is a validation error, not a load error
    # a lid resting on the block (touching along its top) is fine
    text = text.replace("[1.5, 1.5]", "[1.5, 2.0]").replace("[2.5, 2.5]", "[2.5, 3.0]")
    text += '[node_sets.lid_top]\nbody = "lid"\ny = 3.0\n[[supports]]\nnodes = "lid_top"\n'
    path.write_text(text, encoding="utf-8")
    assert validate_model_file(path) == []


def test_validate_element_quality_and_orphan_nodes(tmp_path):
    pts = [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 1e-3], [5, 5]]  # a sliver; node 5 unused
    write_msh(tmp_path / "poor.msh", pts, [
        ("plate", 2, "triangle", [[0, 4, 3], [4, 1, 2], [4, 2, 3], [0, 1, 4]]),
        ("bottom", 1, "line", [[0, 4], [4, 1]]),
    ])
    (tmp_path / "m.toml").write_text(textwrap.dedent("""
        [mesh]
        file = "poor.msh"
        [[bodies]]
        group = "plate"
        material = {E = 1e9, nu = 0.2}
        [[supports]]
        nodes = "bottom"
        [patterns.p]
        loads = [{type = "nodal", nodes = "bottom", fy = 1.0}]
        [[program]]
        pattern = "p"
        end = 1
        """), encoding="utf-8")
    report = validation_report(tmp_path / "m.toml")
    assert report.ok  # warnings only
    found = {p.item: p for p in report.problems}
    assert set(found) == {"bodies[0]", "mesh"}
    assert found["bodies[0]"].severity == "warning"
    assert "physical surface 'plate' element 3 is nearly degenerate" in found["bodies[0]"].message
    assert "aspect ratio" in found["bodies[0]"].message
    assert "1 node of poor.msh belong" in found["mesh"].message
    assert "node 5 at (5, 5)" in found["mesh"].message


def test_cli_validate_good_file(model_dir):
    result = runner.invoke(app, ["validate", str(model_dir / "model.toml")])
    assert result.exit_code == 0, result.output
    assert "model OK" in result.stdout
    assert "2 bodies, 99 nodes" in result.stdout and "5 CFEs" in result.stdout
    result = runner.invoke(app, ["validate", str(model_dir / "model.toml"), "--json"])
    data = json.loads(result.stdout)
    assert data["status"] == "ok" and data["problems"] == []
    assert data["summary"]["cfes"] == 5
    result = runner.invoke(app, ["check", str(model_dir / "model.toml")])  # hidden alias
    assert result.exit_code == 0 and "model OK" in result.stdout


def test_cli_validate_lists_every_problem(model_dir):
    text = model_text(**{'material = "rock"': 'material = "granite"',
                         'group = "push_face"': 'group = "left"',
                         'minus = "foundation_top"': 'minus = "foundation_topp"'})
    text += LID
    path = model_dir / "model.toml"
    path.write_text(text, encoding="utf-8")
    result = runner.invoke(app, ["validate", str(path), "--json"])
    assert result.exit_code == 2, result.output
    data = json.loads(result.stdout)
    items = [p["item"] for p in data["problems"]]
    assert items == ["bodies[0].material", "bodies[2].material", "node_sets.left_face.group",
                     "interfaces[0].minus"]
    assert data["status"] == "error" and data["errors"] == 4
    assert "4 errors, the first: bodies[0].material: unknown material 'granite'" in result.stderr
    # overlap is found too once the lid has a material
    path.write_text(text.replace('material = "steel"', 'material = "concrete"'),
                    encoding="utf-8")
    result = runner.invoke(app, ["validate", str(path), "--json"])
    items = [p["item"] for p in json.loads(result.stdout)["problems"]]
    assert "bodies 'block' and 'lid'" in items and len(items) == 4
    # the table
    result = runner.invoke(app, ["validate", str(path)], terminal_width=200)
    assert result.exit_code == 2
    for item in items:
        assert item in result.stdout
    assert "Traceback" not in result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ")


def test_cli_validate_missing_and_broken_files(tmp_path):
    result = runner.invoke(app, ["validate", str(tmp_path / "none.toml")])
    assert result.exit_code == 2 and "file not found" in result.stderr
    (tmp_path / "b.toml").write_text("[model\n", encoding="utf-8")
    result = runner.invoke(app, ["validate", str(tmp_path / "b.toml")])
    assert result.exit_code == 2 and "not a valid TOML file" in result.stderr


# --------------------------------------------------------------------------------------------
# 3D meshes in a model file: their problems named (no traceback)
# --------------------------------------------------------------------------------------------
CUBE = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                 [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=float)
#: the unit cube cut into five tetrahedra (a corner-cut decomposition)
CUBE_TETS = np.array([[0, 1, 3, 4], [1, 2, 3, 6], [1, 4, 5, 6], [3, 4, 6, 7], [1, 3, 4, 6]])
MODEL_3D = """
[model]
name = "cube"
[mesh]
file = "{mesh}"
[materials.concrete]
E = 30e9
nu = 0.2
density = 2400
[[bodies]]
kind = "mesh"
group = "block"
material = "concrete"
[[supports]]
name = "bed"
nodes = "bottom"
dofs = "xy"
[patterns.weight]
loads = [{{ type = "gravity", g = [0.0, -9.81] }}]
[[program]]
pattern = "weight"
end = 1.0
"""


def write_3d_msh(path: Path, planar: bool = False) -> Path:
    """A gmsh 2.2 file with a physical volume 'block' and a physical surface 'bottom': the unit
    cube in five tetrahedra (``planar``: two triangles in z = 0, the volume group only named,
    as a 2D export of a 3D model can carry it)."""
    if planar:
        pts = CUBE[:4]
        cells = [("triangle", np.array([[0, 1, 2], [0, 2, 3]]))]
        tags = [np.array([2, 2])]
    else:
        pts = CUBE
        cells = [("tetra", CUBE_TETS), ("triangle", np.array([[0, 1, 2], [0, 2, 3]]))]
        tags = [np.full(5, 1), np.array([2, 2])]
    mesh = meshio.Mesh(pts, cells, cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
                       field_data={"block": np.array([1, 3]), "bottom": np.array([2, 2])})
    meshio.write(path, mesh, file_format="gmsh22", binary=False)
    return path


@pytest.mark.parametrize("planar", [False, True])
def test_a_3d_mesh_is_read_and_its_problems_named(tmp_path, planar):
    """A 3D mesh is a 3D model (issue 28 §4; tests/test_cli3d.py runs one): validate and run
    end with the errors of this file (exit code 2, no traceback), each naming its item — the
    physical surface 'bottom' whose triangles are no faces of the five tetrahedra (the cube's
    bottom split along the other diagonal), the 2D gravity of a 3D model; a planar export
    whose volume group has no volume cells; read_msh reads it as a 3D mesh."""
    write_3d_msh(tmp_path / "cube.msh", planar)
    model = tmp_path / "cube.toml"
    model.write_text(MODEL_3D.format(mesh="cube.msh"), encoding="utf-8")
    for cmd in ("validate", "run"):
        result = runner.invoke(app, [cmd, str(model), "-o", str(tmp_path / "r.nc")]
                               if cmd == "run" else [cmd, str(model)])
        out = " ".join(result.output.split())
        assert result.exit_code == 2, out
        assert result.exception is None or isinstance(result.exception, SystemExit), out
        assert "Traceback" not in out
        if planar:
            assert "physical volume 'block' has no cells" in out
        else:
            assert "is not a face on the boundary of body 'block'" in out
            if cmd == "validate":
                assert "patterns.weight.loads[0].g" in out and "the model is 3D" in out
    # in Python the mesh is read as 3D: its physical volume is the body (tests/test_mesh3d.py)
    mf = read_msh(tmp_path / "cube.msh")
    assert mf.dim == 3 and mf.volumes == ["block"] and mf.points.shape[1] == 3
