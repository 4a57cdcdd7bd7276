"""Every bad input gets a clean error, and nothing is silently wrong.

Each case goes through the command line: a one-line ``error: ...`` on stderr with exit code 2
and no traceback (:func:`cli_checks.assert_one_line_error`), or a ``warning: ...`` line when
the answer is probably not what the user meant.  The solver is not run where the case must be
refused before solving (it is replaced by a function that fails the test).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import stepcontact as sc
from cli_checks import assert_one_line_error
from stepcontact.cli import app
from stepcontact.io.modelfile import load_model
from stepcontact.model.plausible import PlausibilityWarning
from stepcontact.results.file import result_to_dataset

runner = CliRunner()
ROOT = Path(__file__).resolve().parents[1]

#: a block (1 m, one quad4) on a base (2 m, two quad4): S+ and S- edges of equal length
TINY = """
[model]
name = "tiny"

[materials.concrete]
E = 30e9
nu = 0.2
density = 2400

[[bodies]]
name = "base"
corner0 = [-0.5, -1.0]
corner1 = [1.5, 0.0]
nx = 2
ny = 1
material = "concrete"

[[bodies]]
name = "block"
corner0 = [0.0, 0.0]
corner1 = [1.0, 1.0]
nx = 1
ny = 1
material = "concrete"

[node_sets.base_bottom]
body = "base"
y = -1.0

[node_sets.base_top]
body = "base"
y = 0.0

[node_sets.block_bottom]
body = "block"
y = 0.0

[node_sets.block_left]
body = "block"
x = 0.0

[node_sets.corner]
body = "block"
index = [0]

[[supports]]
nodes = "base_bottom"

[[interfaces]]
name = "joint"
plus = "block_bottom"
minus = "base_top"
friction = 0.6

[patterns.weight]
loads = [{ type = "gravity", g = [0.0, -9.81], bodies = ["block"] }]

[patterns.push]
loads = [{ type = "nodal", nodes = "block_left", fx = 1e3 }]

[[program]]
pattern = "weight"
end = 1.0

[[program]]
pattern = "push"
end = 5.0
"""


def write(tmp_path: Path, text: str, name: str = "m.toml", **replace: str) -> Path:
    for old, new in replace.items():
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def tiny(tmp_path: Path, *pairs: tuple[str, str], name: str = "m.toml") -> Path:
    text = TINY
    for old, new in pairs:
        assert old in text, old
        text = text.replace(old, new)
    return write(tmp_path, text, name)


@pytest.fixture
def no_solver(monkeypatch):
    """The run must stop before solving."""
    def solve_static(*args, **kwargs):
        raise AssertionError("the solver was called")

    monkeypatch.setattr("stepcontact.solver.static.solve_static", solve_static)


@pytest.fixture
def solver_without_files(monkeypatch):
    """The real solver, without the (slow) result file: ``run`` stays end to end."""
    from stepcontact.solver import static

    real = static.solve_static

    def solve_static(model, *, output=None, **kwargs):
        return real(model, **kwargs)

    monkeypatch.setattr(static, "solve_static", solve_static)


@pytest.fixture(scope="module")
def tiny_result(tmp_path_factory):
    """The tiny model solved in memory."""
    folder = tmp_path_factory.mktemp("result")
    return sc.solve_static(load_model(write(folder, TINY, "tiny.toml")))


# --------------------------------------------------------------------------------------------
# files that are not model files
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("command", ["run", "validate"])
def test_binary_and_utf16_model_files(tmp_path, command, no_solver):
    utf16 = tmp_path / "utf16.toml"
    utf16.write_bytes(TINY.encode("utf-16"))
    result = runner.invoke(app, [command, str(utf16)])
    assert_one_line_error(result, f"{utf16}: is UTF-16 text: save it as UTF-8")
    binary = tmp_path / "binary.toml"
    binary.write_bytes(bytes(range(256)))
    result = runner.invoke(app, [command, str(binary)])
    assert_one_line_error(result, f"{binary}: is not a UTF-8 text file (byte 0x80 at offset 128)")
    nul = tmp_path / "nul.toml"
    nul.write_bytes(b"a = 1\n\x00\x00")
    result = runner.invoke(app, [command, str(nul)])
    assert_one_line_error(result, "not a text file (it contains NUL bytes)")


@pytest.mark.parametrize("command", ["run", "validate"])
def test_directory_as_model_file(tmp_path, command, no_solver):
    folder = tmp_path / "model.toml"
    folder.mkdir()
    result = runner.invoke(app, [command, str(folder)])
    assert_one_line_error(result, f"{folder}: is a directory, not a model file")
    assert "not found" not in result.stderr


@pytest.mark.parametrize("command", ["run", "validate"])
def test_missing_file_is_named_once(tmp_path, monkeypatch, command, no_solver):
    monkeypatch.chdir(tmp_path)
    result = runner.invoke(app, [command, "nope.toml"])
    assert_one_line_error(result, "nope.toml")
    assert result.stderr.count("nope.toml") == 1, result.stderr
    assert "not found" in result.stderr


# --------------------------------------------------------------------------------------------
# materials and mesh sizes
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("command", ["run", "validate"])
def test_absurd_young_modulus(tmp_path, command, no_solver):
    path = tiny(tmp_path, ("E = 30e9", "E = 1e-300"))
    result = runner.invoke(app, [command, str(path)])
    assert_one_line_error(result, "materials.concrete.E: Young's modulus E = 1e-300 is outside")
    inline = tiny(tmp_path, ('ny = 1\nmaterial = "concrete"',
                             'ny = 1\nmaterial = { E = 1e-300, nu = 0.2 }'), name="inline.toml")
    result = runner.invoke(app, [command, str(inline)])
    assert_one_line_error(result, "bodies[0].material.E: Young's modulus E = 1e-300")


def test_young_modulus_through_the_api():
    mat = sc.Material(30e9, 0.2)
    with pytest.raises(sc.ModelError) as info:
        sc.rectangle("blk", (0, 0), (1, 1), 1, 1, sc.Material(1e-300, 0.2))
    assert info.value.item == "body 'blk'.material"
    assert "outside 1e-10" in info.value.problem
    base = sc.rectangle("base", (0, -1), (1, 0), 1, 1, mat)
    with pytest.warns(PlausibilityWarning, match=r"body 'blk'.material.E = 1e-06 Pa is "
                      "softer than any structural material"):
        soft = sc.rectangle("blk", (0, 0), (1, 1), 1, 1, sc.Material(1e-6, 0.2))
    with pytest.raises(sc.ModelError) as info:
        sc.Model(bodies=[base, soft])
    assert info.value.item == "body 'blk'.material"
    assert "3.3e-17 times that of body 'base'" in info.value.problem
    with pytest.raises(sc.ModelError, match=r"frame 'f'.E: Young's modulus E = 1e\+30"):
        sc.Frame.line("f", (0, 0), (1, 0), 2, E=1e30, A=1.0, I=1.0)


@pytest.mark.parametrize("command", ["run", "validate"])
def test_mesh_of_1e9_cells_is_refused_before_allocation(tmp_path, command, no_solver):
    path = tiny(tmp_path, ("nx = 1\nny = 1", "nx = 31623\nny = 31623"))
    result = runner.invoke(app, [command, str(path)])
    assert_one_line_error(result, "bodies[1]: too large: the 31623 × 31623 quad4 mesh of body "
                          "'block' (1e+09 cells) has 2e+09 DOFs and needs about 7.45 TB")


def test_mesh_of_2e6_cells_against_the_physical_memory(tmp_path, monkeypatch, no_solver):
    monkeypatch.setattr("stepcontact.model.size.physical_memory", lambda: 16 * 2**30)
    path = tiny(tmp_path, ("nx = 1\nny = 1", "nx = 2000\nny = 1000"))
    result = runner.invoke(app, ["run", str(path)])
    assert_one_line_error(result, "bodies[1]: too large: the 2000 × 1000 quad4 mesh of body "
                          "'block' (2e+06 cells) has 4.01e+06 DOFs and needs about 15.3 GB of "
                          "memory (~4 kB per DOF for assembly and factorisation), more than 50% "
                          "of this machine's 16 GB of physical memory (8 GB)")
    with pytest.raises(sc.ModelError, match="body 'b'.*tri6 mesh of body 'b'"):
        sc.rectangle("b", (0, 0), (1, 1), 1000, 1000, sc.Material(1e9, 0.2), "tri6")
    # the whole model: two bodies that fit one by one, not together
    monkeypatch.setattr("stepcontact.model.size.physical_memory", lambda: 40 * 2**20)
    both = tiny(tmp_path, ("nx = 1\nny = 1", "nx = 40\nny = 40"),
                ("nx = 2\nny = 1", "nx = 40\nny = 40"), name="both.toml")
    result = runner.invoke(app, ["validate", str(both)])
    assert_one_line_error(result, "model: too large: the model (2 bodies, 3362 nodes) has "
                          "6.72e+03 DOFs and needs about 26.3 MB")


# --------------------------------------------------------------------------------------------
# validate finds what run rejects, without solving
# --------------------------------------------------------------------------------------------
HINGE_MSH = """$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
2
1 1 "base"
2 2 "block"
$EndPhysicalNames
$Nodes
7
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
5 1 0 0
6 2 0 0
7 2 1 0
$EndNodes
$Elements
3
1 1 2 1 1 1 2
2 3 2 2 2 1 2 3 4
3 3 2 2 2 5 6 7 3
$EndElements
"""

MESH_MODEL = """
[mesh]
file = "hinge.msh"

[materials.c]
E = 30e9
nu = 0.2
density = 2400

[[bodies]]
kind = "mesh"
group = "block"
material = "c"

[[supports]]
nodes = "base"

[patterns.w]
loads = [{ type = "gravity", g = [0.0, -9.81] }]

[[program]]
pattern = "w"
end = 1.0
"""


def test_validate_finds_mechanisms(tmp_path, no_solver):
    held_x = tiny(tmp_path, ('nodes = "base_bottom"', 'nodes = "base_bottom"\ndofs = "x"'))
    result = runner.invoke(app, ["validate", str(held_x)])
    assert_one_line_error(result, "model: the structure is a mechanism even with every CFE "
                          "stuck: body 'base' can move freely (translation along y and rotation "
                          "about (0.5, -1))")
    one_cfe = tiny(tmp_path, ('plus = "block_bottom"', 'plus = "corner"'), name="one.toml")
    result = runner.invoke(app, ["validate", str(one_cfe)])
    assert_one_line_error(result, "body 'block' can move freely (rotation about (0, 0))")
    (tmp_path / "hinge.msh").write_text(HINGE_MSH, encoding="utf-8")
    hinge = write(tmp_path, MESH_MODEL, "hinge.toml")
    result = runner.invoke(app, ["validate", str(hinge)])
    assert_one_line_error(result, "body 'block' can move freely (internal mechanism)")
    assert re.search(r"duplicate\s+node", result.stdout), result.stdout  # the warning
    result = runner.invoke(app, ["validate", str(tiny(tmp_path, name="ok.toml"))])
    assert result.exit_code == 0, result.output
    assert "model OK" in result.stdout


def test_mesh_that_falls_apart_is_named(tmp_path, no_solver):
    (tmp_path / "hinge.msh").write_text(HINGE_MSH.replace("5 6 7 3", "5 6 7 8").replace(
        "7\n1 0 0 0", "8\n1 0 0 0").replace("7 2 1 0\n", "7 2 1 0\n8 1 1 0\n"),
        encoding="utf-8")
    path = write(tmp_path, MESH_MODEL, "apart.toml")
    result = runner.invoke(app, ["validate", str(path)])
    assert_one_line_error(result, "body 'block': part of it is not restrained: 4 of its 8 "
                          "nodes (e.g. node 4 at (1, 0)) are connected to no support")


def test_interface_with_the_same_node_set_on_both_sides(tmp_path, no_solver):
    path = tiny(tmp_path, ('minus = "base_top"', 'minus = "block_bottom"'))
    for command in ("validate", "run"):
        result = runner.invoke(app, [command, str(path)])
        assert_one_line_error(result, "interfaces[0]: plus and minus of interface 'joint' are "
                              "the same nodes (node set 'block_bottom' of body 'block')")
        assert "not restrained" not in result.stderr


# --------------------------------------------------------------------------------------------
# warnings: probably not what the user meant
# --------------------------------------------------------------------------------------------
def test_empty_and_zero_load_patterns_warn(tmp_path, solver_without_files):
    empty = tiny(tmp_path, ('loads = [{ type = "nodal", nodes = "block_left", fx = 1e3 }]',
                            "loads = []"))
    result = runner.invoke(app, ["validate", str(empty)])
    assert result.exit_code == 0, result.output
    assert "model OK" in result.stdout and "(1 warnings)" in result.stdout
    zero = tiny(tmp_path, ("fx = 1e3", "fx = 0.0"), name="zero.toml")
    result = runner.invoke(app, ["run", str(zero), "-q", "--no-plot"])
    assert result.exit_code == 0, result.output
    lines = result.stderr.strip().splitlines()
    assert lines == ["warning: load pattern 'push' is zero: its 1 load(s) add up to no force "
                     "and no displacement (zero values, or gravity on bodies without density): "
                     "the segment that applies it (program[1]) changes nothing"], result.stderr
    result = runner.invoke(app, ["run", str(empty), "--no-plot", "--json"])
    assert "has no loads" in result.stderr
    assert any("has no loads" in w for w in json.loads(result.stdout)["warnings"])


def test_displacements_larger_than_the_model_warn(tmp_path, solver_without_files):
    gpa = tiny(tmp_path, ("E = 30e9", "E = 30"))  # meant: 30 GPa
    result = runner.invoke(app, ["run", str(gpa), "-q", "--no-plot"])
    assert "Traceback" not in result.output
    warn = [ln for ln in result.stderr.splitlines() if ln.startswith("warning: ")]
    assert len(warn) == 2, result.stderr
    # the implausible modulus, when the file is read; the displacement, after the run
    assert warn[0].startswith("warning: materials.concrete.E: 30 Pa is softer than any")
    assert "did you mean 3e+10 Pa (the value in GPa)?" in warn[0]
    assert "is larger than the model itself (2 m across)" in warn[1]
    assert "check the units (E in Pa, e.g. 30e9 for 30 GPa" in warn[1]
    result = runner.invoke(app, ["run", str(tiny(tmp_path, name="ok.toml")), "-q", "--no-plot"])
    assert result.exit_code == 0 and "warning" not in result.stderr, result.stderr


# --------------------------------------------------------------------------------------------
# arguments checked before solving; figures
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("value", "fragment"), [
    ("nan", "--lam nan: give a finite load factor"),
    ("1e9", "--lam 1e+09: outside the last segment of the program ('push', λ from 0 to 5)"),
])
def test_run_lam_is_checked_before_solving(tmp_path, no_solver, value, fragment):
    path = tiny(tmp_path)
    result = runner.invoke(app, ["run", str(path), "--lam", value])
    assert_one_line_error(result, fragment)
    assert not path.with_suffix(".nc").exists()
    assert not path.with_suffix(".png").exists()


def test_plot_refuses_an_absurd_dpi(tiny_result, tmp_path, monkeypatch):
    nc = tmp_path / "run.nc"  # the result as loaded from it (reading files is tested elsewhere)
    nc.write_bytes(b"")
    monkeypatch.setattr("stepcontact.results.result.load_result", lambda path: tiny_result)
    out = tmp_path / "big.png"
    result = runner.invoke(app, ["plot", str(nc), "--dpi", "100000", "-o", str(out)])
    assert_one_line_error(result, "plot stresses: dpi=100000: a 850000 × 750000 pixel figure "
                          "(6.4e+11 pixels) is too large")
    assert "lower the dpi (at most" in result.stderr
    assert list(tmp_path.iterdir()) == [nc]


def test_failed_plot_leaves_no_partial_figure(tiny_result, tmp_path, monkeypatch):
    from matplotlib.figure import Figure

    from stepcontact.post import plotting

    res = tiny_result
    out = tmp_path / "s.png"

    def broken_savefig(self, fname, **kwargs):
        Path(fname).write_bytes(b"\x89PNG half")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Figure, "savefig", broken_savefig)
    with pytest.raises(OSError, match="No space left"):
        plotting.plot_interfaces(res, path=out)
    assert list(tmp_path.iterdir()) == []
    out.write_bytes(b"old figure")
    with pytest.raises(OSError):
        plotting.plot_event_timeline(res, path=out)
    assert out.read_bytes() == b"old figure"
    assert list(tmp_path.iterdir()) == [out]


# --------------------------------------------------------------------------------------------
# result files whose arrays disagree
# --------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def inconsistent_file(tiny_result, tmp_path_factory):
    ds = result_to_dataset(tiny_result)
    n = ds.sizes["state"]
    short = ds["N"].isel(state=slice(0, n - 2)).rename(state="state_short")
    path = tmp_path_factory.mktemp("bad") / "bad.nc"
    ds.drop_vars("N").assign(N=short).to_netcdf(path, engine="h5netcdf")
    return path, n


@pytest.mark.parametrize("command", [["info"], ["plot", "--kind", "stresses"]])
def test_result_file_with_arrays_of_different_shapes(inconsistent_file, command, tmp_path):
    path, n = inconsistent_file
    out = ["-o", str(tmp_path / "f.png")] if command[0] == "plot" else []
    result = runner.invoke(app, [*command, str(path), *out])
    assert_one_line_error(result, f"{path}: inconsistent result file: variable 'N' has shape "
                          f"({n - 2}, 2), expected ({n}, 2) ({n} states of 'lam' × 2 CFEs)")


def test_result_checks_name_the_variable(tiny_result):
    from stepcontact.results.file import check_dataset

    ds = result_to_dataset(tiny_result)
    check_dataset(ds)
    bad = ds.assign(event_cfe=ds["event_cfe"] + 10)
    with pytest.raises(ValueError, match="variable 'event_cfe' refers to CFE 10, but there are 2"):
        check_dataset(bad)
    u = ds["u"].isel(dof=slice(0, 5)).rename(dof="dof_short")
    with pytest.raises(ValueError, match=r"variable 'u' has shape \(4, 5\), expected \(4, 20\)"):
        check_dataset(ds.drop_vars("u").assign(u=u))
    with pytest.raises(ValueError, match="variable 'Q' is missing"):
        check_dataset(ds.drop_vars("Q"))
    cells = ds["cells__block"].copy(data=ds["cells__block"].values + 100)
    with pytest.raises(ValueError, match="variable 'cells__block' refers to node 10"):
        check_dataset(ds.assign(cells__block=cells))


# --------------------------------------------------------------------------------------------
# mesh files outside the model's folder
# --------------------------------------------------------------------------------------------
def test_unreadable_mesh_outside_the_model_folder(tmp_path, no_solver):
    model_dir, mesh_dir = tmp_path / "model", tmp_path / "meshes"
    model_dir.mkdir()
    mesh_dir.mkdir()
    path = write(model_dir, MESH_MODEL, "m.toml", **{"hinge.msh": "../meshes/block.msh"})
    where = (f"mesh.file: '../meshes/block.msh' ({mesh_dir.resolve() / 'block.msh'}, outside "
             f"the model file's folder {model_dir.resolve()})")
    result = runner.invoke(app, ["run", str(path)])
    assert_one_line_error(result, f"{where}: file not found")
    (mesh_dir / "block.msh").mkdir()
    result = runner.invoke(app, ["validate", str(path)])
    assert_one_line_error(result, f"{where}: is a directory, not a mesh file")
    (mesh_dir / "block.msh").rmdir()
    (mesh_dir / "block.msh").write_text(HINGE_MSH[:150], encoding="utf-8")  # truncated
    result = runner.invoke(app, ["run", str(path)])
    assert_one_line_error(result, f"{where}: cannot read the mesh")
    inside = write(model_dir, MESH_MODEL, "in.toml", **{"hinge.msh": "sub/../none.msh"})
    result = runner.invoke(app, ["run", str(inside)])
    assert_one_line_error(result, f"mesh.file: {model_dir / 'none.msh'}: file not found")


# --------------------------------------------------------------------------------------------
# the documentation says what the code does
# --------------------------------------------------------------------------------------------
def test_paraview_doc_names_the_frames_as_export_writes_them(tiny_result, tmp_path):
    sc.export_vtu(tiny_result, tmp_path, name="run")
    frames = sorted(p.name for p in (tmp_path / "run").iterdir())
    assert frames[:2] == ["run_0000.vtu", "run_0001.vtu"], frames
    assert "run_cfe_0000.vtu" in frames
    doc = (ROOT / "docs" / "paraview.md").read_text(encoding="utf-8")
    assert "`DIR/NAME/NAME_0007.vtu`" in doc and "zero-padded to four digits" in doc


def test_user_guide_names_the_gmsh_extra():
    guide = (ROOT / "docs" / "user-guide.md").read_text(encoding="utf-8")
    workflow = guide[guide.index("## Workflow"):]
    step1 = workflow[:workflow.index("**2. Model file")]
    assert 'pip install "stepcontact[gmsh]"' in step1
    trouble = guide[guide.index("## Troubleshooting"):]
    assert "**Checks of bad input.**" in trouble
    assert np.all([k in trouble for k in ("--lam", "--dpi", "inconsistent", "too large")])


# --------------------------------------------------------------------------------------------
# crack water: refused where it would be silently wrong (issue 24 §4)
# --------------------------------------------------------------------------------------------
def _dam_with_crack_water(nx: int = 8, lam_end: float = 1.5, **crack):
    """test_crack_water's dam (B = 8 m, water 11 m deep, CFEs every 8/nx m along y = 0 from
    x = 0 to 8 m) with the crack water ``crack`` (level 11 m unless given)."""
    from test_crack_water import dam_model

    m = dam_model(lam_end=lam_end, nx=nx, crack=False)
    base = m.interfaces[0]
    water = m.pattern("water")
    cw = sc.CrackWater(base, **({"level": 11.0} | crack))
    return m.replace(patterns=(m.pattern("weight"),
                               sc.LoadPattern("water", (*water.loads, cw))))


def test_crack_water_entry_off_the_joint_is_refused_with_the_joints_extent():
    """An entry 5 m upstream of the heel (hand: 5 m from the nearest CFE, at x = 0; the joint
    spans x = 0 … 8 m on y = 0) is refused instead of being moved to the nearest CFE."""
    with pytest.raises(sc.ModelError) as info:
        sc.assemble(_dam_with_crack_water(entry=(-5.0, 0.0)))
    assert info.value.item == "crack water in interface 'base'.entry"
    assert info.value.problem.startswith("(-5, 0) is 5 m from the joint, which spans x = 0 … 8 "
                                         "m, y = 0 … 0 m")


def test_crack_water_entry_within_a_cfe_spacing_is_the_heel_and_matches_hand_statics():
    """An entry 0.4 m off the heel (less than the CFE spacing, 1 m) is the heel: the crack runs
    from it at the λ of the rigid-block hand solution (test_crack_water.RigidBlock: vertical
    and moment equilibrium of the closed CFEs' springs), relative tolerance 1e-5 as there."""
    from test_crack_water import RigidBlock, openings_of

    res = sc.solve_static(_dam_with_crack_water(entry=(-0.4, 0.0), lam_end=2.0))
    ref, _ = RigidBlock(res, 8.0, 11.0).openings(0.0, 2.0)
    got = openings_of(res)
    assert len(ref) >= 2 and [k for k, _ in got[:len(ref)]] == [k for k, _ in ref]
    np.testing.assert_allclose([t for _, t in got[:len(ref)]], [t for _, t in ref], rtol=1e-5)


def test_crack_water_negative_pressure_and_level_below_the_joint_are_refused():
    base = _dam_with_crack_water().interfaces[0]
    with pytest.raises(sc.ModelError) as info:
        sc.CrackWater(base, pressure=-1e4)
    assert info.value.item == "crack water in interface 'base'.pressure"
    assert "is -10000 Pa: water in a crack pushes its faces apart" in info.value.problem
    with pytest.raises(sc.ModelError) as info:
        sc.assemble(_dam_with_crack_water(level=-2.0, entry=(0.0, 0.0)))
    assert info.value.item == ("load pattern 'water': crack water in interface 'base'.level")
    assert info.value.problem.startswith("is -2 m, at or below the whole joint (its CFEs lie at "
                                         "y = 0 … 0 m): the crack would hold no water")


CRACK = ('loads = [{ type = "nodal", nodes = "block_left", fx = 1e3 }]',
         'loads = [{ type = "nodal", nodes = "block_left", fx = 1e3 }, '
         '{ type = "crack_water", interface = "joint", LEVEL }]')


@pytest.mark.parametrize(("spec", "fragment"), [
    ("level = 2.0, entry = [-3.0, 0.0]", "crack water in interface 'joint'.entry: (-3, 0) is "
     "3 m from the joint, which spans x = 0 … 1 m, y = 0 … 0 m"),
    ("pressure = -5e3", "is -5000 Pa: water in a crack pushes its faces apart"),
    ("level = -1.0", "crack water in interface 'joint'.level: is -1 m, at or below the whole "
     "joint (its CFEs lie at y = 0 … 0 m)"),
])
@pytest.mark.parametrize("command", ["validate", "run"])
def test_bad_crack_water_in_a_model_file(tmp_path, no_solver, command, spec, fragment):
    path = tiny(tmp_path, (CRACK[0], CRACK[1].replace("LEVEL", spec)))
    result = runner.invoke(app, [command, str(path)])
    assert_one_line_error(result, fragment)


# --------------------------------------------------------------------------------------------
# implausible values: warned about, naming the item and its unit (model/plausible.py)
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("pairs", "warning"), [
    ([("density = 2400", "density = 2.4")], "materials.concrete.density: 2.4 kg/m³ is far "
     "below any solid (plausible mass density: 100 … 25 000 kg/m³): did you mean 2400 kg/m³"),
    ([("friction = 0.6", "friction = 1e6")], "interfaces[0].friction: 1e+06 is above any real "
     "friction coefficient"),
    ([("g = [0.0, -9.81]", "g = [0.0, -9810]")], "patterns.weight.loads[0].g: 9810 m/s² is "
     "more than 10 g (plausible acceleration |g|: ≤ 100 m/s²): did you mean 9.81 m/s²"),
    ([("E = 30e9", "E = 3e4")], "materials.concrete.E: 30000 Pa is softer than any structural "
     "material or soil"),
    ([(CRACK[0], CRACK[1].replace("type = \"crack_water\", interface = \"joint\", LEVEL",
                                  "type = \"uplift\", interface = \"joint\", head = -20.0"))],
     "patterns.push.loads[1].head: -20 m of water is negative: a joint holds no suction"),
    ([(CRACK[0], CRACK[1].replace("LEVEL", "level = 2.0, unit_weight = 9.81"))],
     "patterns.push.loads[1].unit_weight: 9.81 N/m³ is far below that of water (9 810 N/m³; "
     "sea water 10 050, muddy water up to 14 000) (plausible unit weight of water γ_w: 9 000 … "
     "15 000 N/m³): did you mean 9810 N/m³ (the value in kN/m³)?"),
])
def test_implausible_values_warn_naming_the_item_and_unit(tmp_path, no_solver, pairs, warning):
    path = tiny(tmp_path, *pairs)
    result = runner.invoke(app, ["validate", "--json", str(path)])
    problems = json.loads(result.stdout)["problems"]
    texts = [f"{p['item']}: {p['message']}" for p in problems if p["severity"] == "warning"]
    assert any(t.startswith(warning) for t in texts), texts
    assert result.exit_code == 0, result.output


def test_implausible_values_warn_in_run_and_in_the_python_api(tmp_path, solver_without_files):
    path = tiny(tmp_path, ("density = 2400", "density = 2.4"))
    result = runner.invoke(app, ["run", str(path), "-q", "--no-plot"])
    assert result.exit_code == 0, result.output
    assert result.stderr.splitlines()[0].startswith(
        "warning: materials.concrete.density: 2.4 kg/m³ is far below any solid"), result.stderr
    with pytest.warns(PlausibilityWarning, match=r"body 'b'.material.density = 2.4 kg/m³ is "
                      r"far below any solid .*did you mean 2400 kg/m³"):
        sc.rectangle("b", (0, 0), (1, 1), 1, 1, sc.Material(30e9, 0.2, 2.4))
    with pytest.warns(PlausibilityWarning, match=r"body force \|g\| = 9810 m/s² is more than"):
        sc.BodyForce(g=(0.0, -9810.0))
    with pytest.warns(PlausibilityWarning, match=r"rayleigh damping.zeta1 = 50 is above "
                      r"critical damping .*did you mean 0.5 \(the value in per cent\)"):
        from stepcontact.fem.mass import rayleigh_coefficients

        rayleigh_coefficients(50.0, 1.0, 0.05, 10.0)
    ok = sc.rectangle("b", (0, 0), (1, 1), 1, 1, sc.Material(30e9, 0.2, 2400.0))
    assert ok.material.density == 2400.0  # (no warning: pytest turns warnings into errors)


def test_damping_ratio_in_percent_warns_in_a_model_file(tmp_path, no_solver):
    path = tiny(tmp_path, ("[[program]]\npattern = \"weight\"",
                           "[dynamics]\ndt = 1e-3\nduration = 0.01\n"
                           "damping = { ratios = [50.0, 5.0], frequencies = [1.0, 10.0] }\n\n"
                           "[[program]]\npattern = \"weight\""))
    result = runner.invoke(app, ["validate", "--json", str(path)])
    texts = [f"{p['item']}: {p['message']}" for p in json.loads(result.stdout)["problems"]]
    assert any(t.startswith("dynamics.damping.ratios[0]: 50 is above critical damping") and
               "did you mean 0.5 (the value in per cent)?" in t for t in texts), texts
    assert any(t.startswith("dynamics.damping.ratios[1]: 5 is above critical damping") and
               "did you mean 0.05" in t for t in texts), texts


def test_tension_cut_off_beyond_the_mohr_coulomb_apex_warns(tmp_path, no_solver):
    """c = 100 kPa, φ = 35°: the apex c·cot φ = 1e5 / tan 35° = 142 815 Pa (hand); a cut-off of
    10 MPa beyond it never acts and is warned about; one at 100 kPa is not."""
    bond = ('friction = 0.6\nbond = { cohesion = 1e5, tensile_strength = SIGMA, '
            'friction_angle = 35.0 }')
    path = tiny(tmp_path, ("friction = 0.6", bond.replace("SIGMA", "1e7")))
    result = runner.invoke(app, ["validate", "--json", str(path)])
    problems = json.loads(result.stdout)["problems"]
    assert [(p["severity"], p["item"]) for p in problems] == [
        ("warning", "interfaces[0].bond.tensile_strength")]
    assert problems[0]["message"].startswith("1e+07 Pa is beyond the apex of the Mohr–Coulomb "
                                             "envelope, c·cot φ = 142815 Pa (c = 100000 Pa, "
                                             "φ = 35°)")
    with pytest.warns(PlausibilityWarning, match=r"bond.tensile_strength = 2e\+06 Pa is beyond "
                      r"the apex .* c·cot φ = 1e\+06 Pa"):
        sc.Bond.mohr_coulomb(1e6, 2e6, 45.0)
    ok = tiny(tmp_path, ("friction = 0.6", bond.replace("SIGMA", "1e5")), name="ok.toml")
    result = runner.invoke(app, ["validate", "--json", str(ok)])
    assert json.loads(result.stdout)["problems"] == [], result.output


# --------------------------------------------------------------------------------------------
# tracebacks and hangs: refused with the count and the limit
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("command", ["validate", "run"])
def test_a_billion_cycles_are_refused_with_the_count_and_the_limit(tmp_path, no_solver,
                                                                   command):
    path = tiny(tmp_path, ("pattern = \"push\"\nend = 5.0",
                           "pattern = \"push\"\namplitude = 1.0\ncycles = 1000000000"))
    result = runner.invoke(app, [command, str(path)])
    assert_one_line_error(result, "program[1].cycles: is 1,000,000,000: that many cycles are "
                          "2,000,000,000 load segments, more than a run can hold; at most "
                          "10,000 cycles (20,000 segments)")
    with pytest.raises(sc.ModelError, match=r"cycles\('push'\).n: is 100,000,000"):
        sc.cycles("push", 1.0, 100_000_000)


def test_slab_study_whose_cases_all_fail_says_so_and_why(tmp_path, monkeypatch):
    """`study slab --friction 1e6` once ended in a KeyError in the report after every case
    failed: the report and the command now say that every case failed, and why."""
    import xarray as xr

    from stepcontact.study import basin

    ids = ["static", "up-t1-x0.5", "down-t1-x0.5"]
    why = "case failed: the bisection found no failing thickness up to 10 h_kr"

    def run_basin(st, out, **kwargs):
        assert st.friction == 1e6
        return xr.Dataset({"case_status": ("case", ["failed"] * 3),
                           "case_message": ("case", [why] * 3)}, coords={"case": ids})

    monkeypatch.setattr(basin, "run_basin", run_basin)
    result = runner.invoke(app, ["study", "slab", "--quick", "--friction", "1e6", "-o",
                                 str(tmp_path / "s")])
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output and result.exception is None or \
        isinstance(result.exception, SystemExit)
    err = [ln for ln in result.stderr.splitlines() if ln.startswith("error")]
    assert err == [f"error: all 3 cases of the slab study failed; 3 of them (e.g. static): "
                   f"{why}"], result.stderr
    assert "warning: --friction = 1e+06 is above any real friction coefficient" in result.stderr
    report = (tmp_path / "s" / "report" / "report.md").read_text(encoding="utf-8")
    assert "## All cases failed" in report
    assert f"3 case(s), e.g. static: {why}" in report


SWEEP = """
[study]
model = "tiny.toml"
{cases}
"""


def test_a_million_case_sweep_is_refused_at_once_with_its_count(tmp_path):
    import time

    (tmp_path / "tiny.toml").write_text(TINY, encoding="utf-8")
    values = ", ".join(str(0.1 + i * 1e-3) for i in range(1000))
    study = tmp_path / "big.toml"
    study.write_text(SWEEP.format(cases=f'[grid]\n"interfaces.0.friction" = [{values}]\n'
                                        f'"patterns.push.loads.0.fx" = [{values}]\n'),
                     encoding="utf-8")
    t0 = time.perf_counter()
    result = runner.invoke(app, ["sweep", str(study), "--serial"])
    assert time.perf_counter() - t0 < 20.0  # no case made or checked (it took minutes)
    assert_one_line_error(result, "1,000,000 cases (1000 values of interfaces.0.friction × "
                          "1000 values of patterns.push.loads.0.fx): more than 10,000, which "
                          "would run for hours or days; give fewer values, or --force")


def test_two_sweep_cases_with_one_id_are_refused(tmp_path):
    (tmp_path / "tiny.toml").write_text(TINY, encoding="utf-8")
    study = tmp_path / "dup.toml"
    study.write_text(SWEEP.format(cases='[[cases]]\nid = "soft"\n"interfaces.0.friction" = 0.3\n'
                                        '[[cases]]\nid = "soft"\n"interfaces.0.friction" = 0.9\n'),
                     encoding="utf-8")
    result = runner.invoke(app, ["sweep", str(study), "--serial"])
    assert_one_line_error(result, "cases[1].id: 'soft' is also the id of cases[0]: give every "
                          "case its own id")


# --------------------------------------------------------------------------------------------
# validate and run agree: the mutations of benchmarks/bad_input_mutations.py that validate
# passed and run rejected (or that hung); each is now refused by both, before solving, with
# the same error naming the stage or item
# --------------------------------------------------------------------------------------------
def _mutations():
    import sys

    sys.path.insert(0, str(ROOT / "benchmarks"))
    import bad_input_mutations

    return bad_input_mutations


#: (model, mutation, the item the error names): validate passed these and run refused them
#: (or both hung), before the checks of model/consistency.py, crack water and cycles
VALIDATE_PASSED_RUN_REJECTED = [
    ("staged_wall", "body_built_under_displacement", "stage 'second lift': body 'upper' is "
     "built while pattern 'jack' prescribes displacements of its nodes at factor 1"),
    ("staged_shock", "stage_dynamics_without_mass", "stage 'struck'.dynamics: body 'block' "
     "has no mass"),
    ("staged_shock", "stage_dynamics_on_first_stage_without_mass", "stage 'struck'.dynamics: "
     "body 'block' has no mass"),
    ("staged_shock", "gravity_on_massless", "stage 'struck'.dynamics: body 'block' has no "
     "mass"),
    ("staged_shock", "level_pattern_mixed", "stage 'struck'.dynamics.loads['push']: pattern "
     "'push' has the water level as its factor: a dynamic interval cannot move it"),
    ("demo", "level_pattern_mixed", "program segment 1 ('push'): the water level starts at 0 "
     "m, where it already loads the structure (its wetted faces reach down to y = -2 m)"),
    ("staged_shock", "crack_water_negative_pressure", "patterns.weight.loads[1].pressure: is "
     "-10000 Pa: water in a crack pushes its faces apart"),
    ("staged_wall", "cycles_huge", "stages[3].program[0].cycles: is 1,000,000,000"),
    ("staged_shock", "cycles_huge", "stages[2].program[0].cycles: is 1,000,000,000"),
    ("gmsh_block", "cycles_huge", "program[1].cycles: is 1,000,000,000"),
    ("demo", "cycles_huge", "program[1].cycles: is 1,000,000,000"),
    ("demo_uplift", "crack_water_negative_pressure", "patterns.weight.loads[1].pressure: is "
     "-10000 Pa"),
    ("demo_uplift", "level_pattern_mixed", "program segment 1 ('uplift'): the water level "
     "starts at 0 m, where it already loads the structure (its wetted faces reach down to "
     "y = -2 m)"),
    ("staged_shock", "displacement_standing_before_dynamics", "pattern 'settle': prescribes "
     "nonzero displacements when the dynamic interval of stage 'struck' starts (factor 1)"),
    ("staged_shock", "last_stage_dynamics", "pattern 'settle': prescribes nonzero "
     "displacements when the dynamic interval of stage 'unloaded' starts (factor 2)"),
    ("gmsh_block", "damped_bonded_joint_with_dynamics", "interface 'joint'.bond: a bonded "
     "joint with a damped contact layer (Kelvin–Voigt, c_n > 0) is not supported"),
    ("demo", "damped_bonded_joint_with_dynamics", "interface 'joint'.bond: a bonded joint "
     "with a damped contact layer"),
    ("demo_uplift", "damped_bonded_joint_with_dynamics", "interface 'joint'.bond: a bonded "
     "joint with a damped contact layer"),
    # these runs lost equilibrium before the segment that the solver refuses (or fails on
    # with a KeyError: a level pattern moved by one rate), or ran a level pattern in a dynamic
    # interval without a word, so the script saw no gap
    ("staged_shock", "dynamics_moves_level_pattern", "stage 'struck'.dynamics.loads"
     "['reservoir']: pattern 'reservoir' has the water level as its factor"),
    ("demo_uplift", "level_pattern_two_rates", "program segment 2 ('flood'): pattern "
     "'reservoir' has the water level as its factor: move it by a segment of its own"),
    ("gmsh_block", "level_pattern_with_rates", "program segment 2 ('flood'): pattern "
     "'reservoir' has the water level as its factor: move it by a segment of its own"),
    ("demo", "level_pattern_starts_high", "program segment 2 ('reservoir'): the water level "
     "starts at 0 m, where it already loads the structure (its wetted faces reach down to "
     "y = -2 m)"),
]


@pytest.mark.parametrize(("model", "mutation", "fragment"), VALIDATE_PASSED_RUN_REJECTED,
                         ids=[f"{m}-{k}" for m, k, _ in VALIDATE_PASSED_RUN_REJECTED])
def test_validate_and_run_agree(tmp_path, no_solver, model, mutation, fragment):
    path = _mutations().write_case(model, mutation, tmp_path)
    assert path is not None, f"{mutation} does not apply to {model}"
    errors = []
    for command in ("validate", "run"):
        result = runner.invoke(app, [command, str(path), *(["--no-plot"] * (command == "run"))])
        assert_one_line_error(result, fragment)
        errors.append(result.stderr.strip().removeprefix(f"error: {path}: ")
                      .removeprefix("error: "))
    v, r = errors  # the same error (validate may count several: "N errors, the first: …")
    assert v.endswith(r) or r.endswith(v) or fragment in v and fragment in r, (v, r)


def test_a_level_pattern_moved_by_one_rate_is_refused_not_a_key_error():
    """`Segment("flood", 0.5, rates={"reservoir": 1.0})` on a pattern whose factor is the water
    level ended in KeyError: 'flood' inside the solver once the segment was reached."""
    c = sc.Material(30e9, 0.2, 2400.0)
    m = sc.Model(bodies=[sc.rectangle("base", (-0.5, -1), (1.5, 0), 2, 1, c),
                         sc.rectangle("block", (0, 0), (1, 1), 1, 1, c)])
    m = m.add(sc.Interface("joint", m.select("block", y=0), m.select("base", y=0), friction=0.6),
              sc.Support("s", m.select("base", y=-1)),
              sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
              sc.LoadPattern("reservoir", [sc.WaterLoad(m.select("block", x=0.0), None)]),
              sc.Segment("weight", 1.0), sc.Segment("flood", 0.5, rates={"reservoir": 1.0}))
    with pytest.raises(sc.ModelError) as info:
        sc.solve_static(m)
    assert info.value.item == "program segment 1 ('flood')"
    assert info.value.problem.startswith("pattern 'reservoir' has the water level as its "
                                         "factor: move it by a segment of its own")
