"""The dam study on a user's model file (issue 29 §3; stepcontact.study.dam_file): the ``[dam]``
table, its errors, the CLI's ``--model``, and the equivalence with the parametric study of the
same section.

The reference of the equivalence is the parametric study (stepcontact.study.dam_study.run_dam
on a DamSection), built by a different path: the section's own model (dam_model, dam_site)
against the file's bodies, node sets and interface and the [dam] table's builders.  The
example file (examples/data/dam_study.toml) meshes the section exactly as the section does
(the same corners and cell counts: the node coordinates are compared), so every figure must
agree to round-off: verdicts equal, the yield acceleration, the levels of first opening and
failure and the margins to 1e-9 relative.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from cli_checks import assert_one_line_error
from figure_checks import assert_readable
from stepcontact.cli import app
from stepcontact.errors import ModelError
from stepcontact.io.modelfile import validate_model_file
from stepcontact.study.dam import DamSection, dam_site
from stepcontact.study.dam_file import DamFileWarning, dam_file
from stepcontact.study.dam_study import run_dam

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "data" / "dam_study.toml"
TEXT = EXAMPLE.read_text(encoding="utf-8")
REL = 1e-9  # the meshes are the same: round-off only


def _file(tmp_path: Path, text: str, name: str = "dam.toml") -> Path:
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def _close(a, b, what: str) -> None:
    if a is None or b is None:
        assert a is b, f"{what}: {a} vs {b}"
        return
    assert abs(a - b) <= REL * max(abs(a), abs(b), 1e-300), f"{what}: {a!r} vs {b!r}"


def _compare(par, fil) -> None:
    """Verdicts equal; k_y, first opening, failure, margins and every check's value to
    1e-9 relative."""
    assert fil.verdicts == par.verdicts and fil.verdict == par.verdict
    _close(fil.yield_acceleration.k_y, par.yield_acceleration.k_y, "k_y")
    assert fil.yield_acceleration.mode == par.yield_acceleration.mode
    for key in ("first_opening", "failure"):
        a, b = getattr(par, key), getattr(fil, key)
        assert (a is None) == (b is None), key
        if a is not None:
            _close(b[0], a[0], f"{key} level")
    assert fil.margins.keys() == par.margins.keys()
    for k, v in par.margins.items():
        _close(fil.margins[k], v, f"margin {k}")
    rows_p, rows_f = par.checks.rows, fil.checks.rows
    assert [(r.combination, r.check) for r in rows_f] == [(r.combination, r.check)
                                                           for r in rows_p]
    for rp, rf in zip(rows_p, rows_f, strict=True):
        if isinstance(rp.value, float):
            _close(rf.value, rp.value, f"{rp.combination}: {rp.check}")
        assert rf.passed == rp.passed, (rp.combination, rp.check)


@pytest.fixture(scope="module")
def studies():
    """The parametric study of the default section on the --quick mesh and the study of the
    example file."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", DamFileWarning)  # the example has no patterns
        d = dam_file(EXAMPLE)
    return run_dam(DamSection(cell=2.0)), run_dam(d), d


def test_the_example_meshes_the_section_as_the_parametric_study(studies):
    """Same bodies and node coordinates (exact), same faces and CFE count: the equivalence
    below is to round-off."""
    _, _, d = studies
    site = dam_site(DamSection(cell=2.0))
    for a in site.model.bodies:
        b = next(x for x in d.model.bodies if x.name == a.name)
        np.testing.assert_array_equal(b.points, a.points)
    assert [list(n.index) for n in d.upstream] == [list(n.index) for n in site.upstream]
    assert [list(n.index) for n in d.downstream] == [list(n.index) for n in site.downstream]
    assert d.height == 30.0 and d.base_length == 27.5 and d.crest == (0.0, 30.0)


def test_the_file_study_gives_the_parametric_verdicts_yield_and_margins(studies):
    par, fil, _ = studies
    _compare(par, fil)
    assert fil.yield_acceleration.hand is None and par.yield_acceleration.hand is not None
    for k, v in par.hand_levels.items():
        _close(fil.hand_levels[k], v, f"hand level {k}")


HAND_KEYS = ("W", "W_lever", "H_up", "H_up_arm", "V_up", "H_down", "H_down_arm", "V_down",
             "V_down_lever", "H_silt", "H_silt_arm", "V_silt", "U", "U_lever", "sum_V",
             "sum_H", "M_resisting", "M_overturning", "sum_M", "resultant_from_toe",
             "eccentricity", "sigma_heel", "sigma_toe", "sliding_factor",
             "shear_friction_factor", "overturning_factor")


@pytest.mark.parametrize("extra, section", [
    ("", {}),
    ("cohesion = 1e5\ntailwater = 4.0\ndrain = [5.0, 0.0]\ndrain_efficiency = 0.5\n"
     "silt_level = 6.0\n", {"cohesion": 1e5, "tailwater": 4.0, "drain_position": 5.0,
                            "drain_efficiency": 0.5, "silt_level": 6.0}),
])
def test_hand_statics_from_the_mesh_equal_the_sections_closed_forms(tmp_path, extra, section):
    """The file's hand statics, summed from its mesh (cell polygons, the faces' edges, the
    uplift along the base), against stepcontact.study.dam.hand_statics's closed forms
    (trapezoid, triangles of pressure) for the same section: 1e-12 relative (round-off of
    sums over cells and edges; measured 2e-15), at levels below, at and above the crest."""
    from stepcontact.study.dam import hand_statics

    text = TEXT.replace("cohesion = 0.0\n", "") + extra
    d = dam_file(_file(tmp_path, text))
    s = DamSection(cell=2.0, **section)
    for h in (10.0, 27.0, 30.0, 35.3, 45.0):
        a, b = hand_statics(s, h), d.hand_statics(h)
        for k in HAND_KEYS:
            assert abs(b[k] - a[k]) <= 1e-12 * max(abs(a[k]), 1.0), (h, k, a[k], b[k])


def test_drains_tailwater_silt_and_kv_from_the_file_as_the_section(tmp_path):
    """The drain line as a point with its efficiency E (K = (1 − E)(L − X)/L), the tailwater
    on the downstream face, silt and k_v: the parametric section with the same inputs
    (reference), to 1e-9."""
    text = TEXT.replace('k_v = 0.0', 'k_v = 0.05\ntailwater = 4.0\ndrain = [5.0, 0.0]\n'
                        'drain_efficiency = 0.5\nsilt_level = 6.0')
    d = dam_file(_file(tmp_path, text))
    K = 0.5 * (27.5 - 5.0) / 27.5  # by hand
    assert abs(d.drain_ratio - K) <= 1e-15
    par = run_dam(DamSection(cell=2.0, k_v=0.05, tailwater=4.0, drain_position=5.0,
                             drain_efficiency=0.5, silt_level=6.0))
    _compare(par, run_dam(d))


def test_validate_accepts_the_file_with_a_dam_table_and_no_program():
    assert [p for p in validate_model_file(EXAMPLE) if p.severity == "error"] == []
    r = CliRunner().invoke(app, ["validate", str(EXAMPLE)])
    assert r.exit_code == 0, r.output


@pytest.mark.parametrize("change, field, words", [
    ('upstream_face = "nope"', "dam.upstream_face", "unknown node set 'nope'"),
    ('joint = "crack"', "dam.joint", "no interface 'crack'"),
    ('bodies = ["concrete"]', "dam.bodies[0]", "no body 'concrete'"),
    ('heel = [1.0, 0.0]', "dam.heel", "is not on the joint"),
    ('toe = [27.5, 1.0]', "dam.toe", "is not on the joint"),
    ('heel = [0.0, 2.0]', "dam.heel", "datum"),
    ('upstream_face = "inner"', "dam.upstream_face", "not on a boundary"),
    ('upstream_face = "rock_top"', "dam.upstream_face", "not on the dam's bodies"),
    ('guideline = "eurocode"', "dam.guideline", "not a guideline"),
    ('normal_level = -3', "dam.normal_level", "greater than 0"),
    ('drain = [40.0, 0.0]\ndrain_ratio = 0.3', "dam.drain", "not on the base"),
    ('drain_efficiency = 0.5', "dam", "drain"),
    ('tailwater = 2.0\ndownstream_face = []', "dam.downstream_face", "tailwater"),
    ('upstream_face = []', "dam.upstream_face", "is empty"),
    ('k_h = 0.2\nmax_kh = 0.1', "dam", "max_kh"),
    ('spillway = 3', "dam.spillway", ""),
])
def test_a_bad_dam_entry_is_an_error_naming_its_field(tmp_path, change, field, words):
    key = change.split("=")[0].strip()
    lines = [ln for ln in TEXT.splitlines() if not ln.startswith(f"{key} =")]
    text = "\n".join(lines) + "\n" + change + "\n"
    text = text.replace("\n[dam]\n", '\n[node_sets.inner]\nbody = "dam"\nindex = [20]\n\n[dam]\n')
    if "downstream_face = []" in change:
        text = text.replace('downstream_face = "downstream"', "")
    with pytest.raises(ModelError) as e:
        dam_file(_file(tmp_path, text))
    assert e.value.item == field, str(e.value)
    assert words in str(e.value)


def test_a_file_without_dam_and_the_ignored_parts(tmp_path):
    no_dam = TEXT[:TEXT.index("\n[dam]\n")]
    with pytest.raises(ModelError, match=r"has no \[dam\] table"):
        dam_file(_file(tmp_path, no_dam + '[patterns.w]\nloads = [{type = "gravity"}]\n'
                       '[[program]]\npattern = "w"\nend = 1\n', "plain.toml"))
    loaded = TEXT + '\n[patterns.w]\nloads = [{type = "gravity", bodies = ["dam"]}]\n' \
        '[[program]]\npattern = "w"\nend = 1\n'
    with pytest.warns(DamFileWarning, match="patterns, program not used by the dam study"):
        d = dam_file(_file(tmp_path, loaded))
    assert not d.model.patterns and not d.model.program


def test_the_cli_writes_the_report_of_a_model_file(tmp_path):
    out = tmp_path / "rep"
    r = CliRunner().invoke(app, ["study", "dam", "--model", str(EXAMPLE), "-o", str(out),
                                 "--quiet"])
    assert r.exit_code == 0, r.output
    for f in ("report.md", "report.html", "summary.json", "result.nc",
              "figures/section.png", "figures/base_stresses.png", "figures/crack_length.png",
              "figures/level_displacement.png", "figures/yield_acceleration.png"):
        assert (out / f).stat().st_size > 0, f
    md = (out / "report.md").read_text(encoding="utf-8")
    assert "## Model and inputs" in md and str(EXAMPLE) in md
    assert "### Hand statics for a reviewer" in md and "ΣM = ΣM_r − ΣM_o" in md
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["section"]["joint"] == "base" and summary["verdict"] == "pass"


def test_the_cli_refuses_quick_and_the_sections_options_with_a_model(tmp_path):
    runner = CliRunner()
    out = str(tmp_path / "x")
    assert_one_line_error(runner.invoke(app, ["study", "dam", "--model", str(EXAMPLE),
                                              "--quick", "-o", out]), "--quick")
    assert_one_line_error(runner.invoke(app, ["study", "dam", "--model", str(EXAMPLE),
                                              "--height", "20", "-o", out]), "[dam] table")
    assert_one_line_error(runner.invoke(app, ["study", "dam", "--model",
                                              str(tmp_path / "none.toml"), "-o", out]),
                          "file not found")
    assert not (tmp_path / "x").exists()


def test_the_section_figure_of_a_model_file(studies, tmp_path):
    from stepcontact.study.dam_report import plot_section

    _, fil, _ = studies
    fig = plot_section(fil, tmp_path / "s.png")
    assert_readable(fig)
    ax = fig.axes[0]
    heel = next(ln for ln in ax.lines if ln.get_label().startswith("heel"))
    toe = next(ln for ln in ax.lines if ln.get_label().startswith("toe"))
    assert (heel.get_xdata()[0], heel.get_ydata()[0]) == (0.0, 0.0)
    assert (toe.get_xdata()[0], toe.get_ydata()[0]) == (27.5, 0.0)
    up = next(ln for ln in fig.axes[1].lines if ln.get_label().startswith("normal"))
    # the uplift head: 27 m at the heel, 0 at the toe (no drains, no tailwater)
    assert up.get_ydata()[0] == 27.0 and up.get_ydata()[-1] == 0.0


def test_a_friction_angle_other_than_the_joints_is_a_warning(tmp_path):
    text = TEXT.replace("friction_angle = 45.0", "friction_angle = 40.0")
    with pytest.warns(DamFileWarning, match="dam.friction_angle"):
        d = dam_file(_file(tmp_path, text))
    assert d.friction_angle == 40.0


def test_a_gmsh_model_names_its_faces_by_physical_curves(tmp_path):
    """The Gmsh example (a block on a foundation, examples/data/gmsh_block.toml) with a [dam]
    table whose face is a physical curve: the names resolve (no unknown node set), and the
    block's joint at y = 1 m is refused at the heel (the levels' datum is y = 0)."""
    data = EXAMPLE.parent
    (tmp_path / "gmsh_block.msh").write_bytes((data / "gmsh_block.msh").read_bytes())
    text = (data / "gmsh_block.toml").read_text(encoding="utf-8") + (
        '\n[dam]\nbodies = ["block"]\njoint = "joint"\nupstream_face = "push_face"\n'
        "heel = [1.0, 1.0]\ntoe = [3.0, 1.0]\nnormal_level = 0.8\n")
    with pytest.raises(ModelError) as e:
        dam_file(_file(tmp_path, text))
    assert e.value.item == "dam.heel" and "datum" in str(e.value)
    assert "push_face" not in str(e.value)  # the physical curve is a node set: no problem


def test_validate_reports_the_dam_tables_geometry(tmp_path):
    """`stepcontact validate` lists the [dam] geometry problems with their fields (the same
    checks as the study's)."""
    text = TEXT.replace("heel = [0.0, 0.0]", "heel = [1.0, 0.0]").replace(
        'upstream_face = "upstream"', 'upstream_face = "rock_top"')
    problems = {p.item for p in validate_model_file(_file(tmp_path, text))
                if p.severity == "error"}
    assert problems == {"dam.heel", "dam.upstream_face"}


GEO = """\
// the default section of the dam study on a rock block (m)
Point(1) = {-30, -30, 0};
Point(2) = {57.5, -30, 0};
Point(3) = {57.5, 0, 0};
Point(4) = {27.5, 0, 0};
Point(5) = {0, 0, 0};
Point(6) = {-30, 0, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};
Point(7) = {0, 0, 0};
Point(8) = {27.5, 0, 0};
Point(9) = {5, 30, 0};
Point(10) = {0, 30, 0};
Line(7) = {7, 8};
Line(8) = {8, 9};
Line(9) = {9, 10};
Line(10) = {10, 7};
Curve Loop(2) = {7, 8, 9, 10};
Plane Surface(2) = {2};
Physical Surface("rock") = {1};
Physical Surface("dam") = {2};
Physical Curve("rock_bottom") = {1};
Physical Curve("rock_top") = {3, 4, 5};
Physical Curve("dam_base") = {7};
Physical Curve("downstream") = {8};
Physical Curve("upstream") = {10};
"""

GMSH_MODEL = """\
[mesh]
file = "dam.geo"
size = 3.0

[materials.concrete]
E = 25e9
nu = 0.2
density = 2400

[materials.rock]
E = 15e9
nu = 0.25
density = 2650

[[bodies]]
kind = "mesh"
group = "rock"
material = "rock"

[[bodies]]
kind = "mesh"
group = "dam"
material = "concrete"

[[supports]]
nodes = "rock_bottom"
dofs = "xy"

[[interfaces]]
name = "base"
plus = "dam_base"
minus = "rock_top"
friction = 1.0

[dam]
bodies = ["dam"]
joint = "base"
upstream_face = "upstream"
downstream_face = "downstream"
heel = [0.0, 0.0]
toe = [27.5, 0.0]
normal_level = 27.0
flood_level = 30.0
friction_angle = 45.0
"""


def test_a_gmsh_dam_gives_the_hand_statics_and_the_runs_equilibrium(tmp_path):
    """The default section meshed by Gmsh (triangles of about 3 m, a .geo in the file's
    [mesh]): a different mesh from the parametric study's, so its elastic answers differ
    (first opening, failure); compared instead with hand statics.  (1) The hand statics summed
    from the Gmsh mesh equal the section's closed forms (stepcontact.study.dam.hand_statics)
    to 1e-12 (straight edges: exact); (2) at the normal level, with the base fully compressed,
    the run's ΣN and ΣQ on the joint equal −ΣV and ΣH of the hand statics (equilibrium of the
    dam alone, the uplift on both faces of the joint) to 1e-9 relative, and the resultant's
    position from the toe too."""
    pytest.importorskip("gmsh")
    from stepcontact.study.dam import hand_statics

    (tmp_path / "dam.geo").write_text(GEO, encoding="utf-8")
    d = dam_file(_file(tmp_path, GMSH_MODEL))
    assert {b.name: b.element for b in d.model.bodies} == {"rock": "tri3", "dam": "tri3"}
    s = DamSection()
    for h in (10.0, 27.0, 35.0):
        a, b = hand_statics(s, h), d.hand_statics(h)
        for k in HAND_KEYS:
            assert abs(b[k] - a[k]) <= 1e-12 * max(abs(a[k]), 1.0), (h, k, a[k], b[k])
    st = run_dam(d, checks=False)
    n = st.row("normal")
    assert n.values["open_length"] == 0.0
    _close(-n.values["normal_force"], n.hand["sum_V"], "ΣN")
    _close(n.values["shear_force"], n.hand["sum_H"], "ΣQ")
    _close(n.values["resultant_from_toe"], n.hand["resultant_from_toe"], "resultant")


def test_a_bonded_joint_from_the_file_as_the_section(tmp_path):
    """The file's interface with a Mohr–Coulomb bond (c = 300 kPa, σ_t = 100 kPa, φ = 45°)
    and [dam] cohesion for the checks: the parametric section with the same cohesion and
    tensile strength (reference), to 1e-9 — the first break too."""
    text = TEXT.replace("friction = 1.0                 # tan 45°",
                        "friction = 1.0\nbond = { cohesion = 3e5, tensile_strength = 1e5, "
                        "friction_angle = 45.0, friction = 1.0 }").replace(
        "cohesion = 0.0\n", "cohesion = 3e5\n")
    d = dam_file(_file(tmp_path, text))
    assert d.bonded
    par = run_dam(DamSection(cell=2.0, cohesion=3e5, tensile_strength=1e5))
    fil = run_dam(d)
    _compare(par, fil)
    _close(fil.first_break[0], par.first_break[0], "first break")
