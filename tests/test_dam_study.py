"""The dam study (issue 29 §3, static): the parametric section's model against the hand statics
of examples/gravity_dam.py, the study's figures at a named level against a hand calculation
derived here, its figures and report, the command ``stepcontact study dam``, and the errors of
bad parameters."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
from typer.testing import CliRunner

import stepcontact as sc
from cli_checks import assert_one_line_error
from figure_checks import assert_readable
from stepcontact.cli import app
from stepcontact.errors import ModelError
from stepcontact.results.dam_checks import CHECKS, load_guidelines
from stepcontact.study import dam_report as R
from stepcontact.study.dam import DamSection, dam_model, hand_statics
from stepcontact.study.dam_study import run_dam, run_yield

GAMMA_W, G = 9810.0, 9.81  # N/m³, m/s²


def _example_section(**changes) -> DamSection:
    """The dam of examples/gravity_dam.py: H = 12 m, B = 8 m, crest 2 m, vertical upstream
    face, f = 0.7, no cohesion, on a 28 m × 8 m rock block (0.8 m cells), dam cells 0.5 m."""
    kw = dict(height=12.0, crest_width=2.0, downstream_slope=0.5,
              concrete=sc.Material(E=25e9, nu=0.2, density=2400),
              rock=sc.Material(E=15e9, nu=0.25, density=2650), foundation_depth=8.0,
              upstream_extent=10.0, downstream_extent=10.0,
              friction_angle=math.degrees(math.atan(0.7)), crack_water=False,
              normal_level=10.0, flood_level=10.0, max_level=20.0, cell=0.5,
              foundation_cell=0.8)
    return DamSection(**(kw | changes))


def test_the_builder_reproduces_the_gravity_dam_example():
    """The section's model is the example's dam: the same meshes (16 × 24 and 35 × 10 cells)
    and the same sliding level.  Hand statics (the example's docstring): the dam slides when
    γ_w h²/2 = f (W − γ_w h B/2), W = ρ g (B + b_c) H / 2; the run's level to 1e-9 relative
    (the example asserts the same; measured 1e-14)."""
    s = _example_section()
    m = dam_model(s)
    bodies = {b.name: b for b in m.bodies}
    assert bodies["dam"].n_nodes == 17 * 25 and bodies["rock"].n_nodes == 36 * 11
    res = sc.solve_static(m)
    f, B, H, bc = 0.7, 8.0, 12.0, 2.0
    W = 2400 * G * (B + bc) / 2 * H
    a, b, c = GAMMA_W / 2, f * GAMMA_W * B / 2, -f * W
    h_slide = (-b + math.sqrt(b * b - 4 * a * c)) / (2 * a)
    lam = res.multipliers[-1].equilibrium_lost
    assert res.status == sc.Status.EQUILIBRIUM_LOST and "sliding" in res.message
    assert abs(lam / h_slide - 1) < 1e-9


def _hand(h: float, *, H, bc, nu, nd, rho, xd, E, t, f):
    """ΣV, ΣH (N/m) and ΣM about the toe (N·m/m, positive resisting) of a trapezoidal dam on
    a rigid, uncracked base at level h ≤ H, derived from triangles: the section as the upstream
    wedge, the crest block and the downstream wedge; water on the upstream batter (a wedge
    n_u h²/2 at n_u h/3 from the heel); tailwater t on the downstream batter (H_t = γ t²/2 at
    t/3, V_t = γ n_d t²/2 at n_d t/3 from the toe); uplift through h (heel), the drain head
    h_d = t + (1 − E)(h − t)(B − x_d)/B and t (toe), as trapezoids."""
    B = bc + (nu + nd) * H
    wedges = [(nu * H * H / 2, B - 2 * nu * H / 3), (bc * H, B - nu * H - bc / 2),
              (nd * H * H / 2, nd * H * 2 / 3)]  # (area, lever from the toe)
    W = rho * G * sum(a for a, _ in wedges)
    MW = rho * G * sum(a * x for a, x in wedges)
    V, MV = GAMMA_W * nu * h * h / 2, GAMMA_W * nu * h * h / 2 * (B - nu * h / 3)
    Hr, MH = GAMMA_W * h * h / 2, GAMMA_W * h * h / 2 * h / 3
    Ht, MHt = GAMMA_W * t * t / 2, GAMMA_W * t * t / 2 * t / 3
    Vt, MVt = GAMMA_W * nd * t * t / 2, GAMMA_W * nd * t * t / 2 * nd * t / 3
    hd = t + (1 - E) * (h - t) * (B - xd) / B
    # uplift trapezoids heel–drain and drain–toe: force and moment about the toe
    U = MU = 0.0
    for (x0, p0), (x1, p1) in (((0.0, h), (xd, hd)), ((xd, hd), (B, t))):
        L = x1 - x0
        rect, tri = min(p0, p1) * L, abs(p0 - p1) * L / 2
        x_tri = x0 + L / 3 if p0 > p1 else x0 + 2 * L / 3
        U += GAMMA_W * (rect + tri)
        MU += GAMMA_W * (rect * (B - (x0 + x1) / 2) + tri * (B - x_tri))
    sum_V = W + V + Vt - U
    sum_H = Hr - Ht
    sum_M = MW + MV + MVt + MHt - MH - MU
    return {"sum_V": sum_V, "sum_H": sum_H, "sum_M": sum_M, "B": B, "W": W, "U": U,
            "f": f}


@pytest.mark.parametrize("rock", [None, sc.Material(E=100e9, nu=0.25, density=2650)],
                         ids=["rigid base", "stiff rock"])
def test_the_figures_at_the_normal_level_against_hand_statics(rock):
    """A dam with an upstream batter, drains and tailwater on a rigid base (and on stiff rock,
    non-matching meshes), its base fully compressed at the normal level: the run's ΣN, ΣQ, the
    resultant's distance from the toe and the friction-only factor against the hand statics
    of :func:`_hand` (equilibrium of the dam alone, whatever the foundation; tolerance 1e-9
    relative, the round-off of the solve: measured ≤ 1e-12), and the module's own hand statics
    (the report's reviewer table) against the same numbers (1e-12)."""
    p = dict(H=20.0, bc=4.0, nu=0.1, nd=0.7, rho=2400.0, xd=3.0, E=0.5, t=2.0, f=0.8)
    s = DamSection(height=p["H"], crest_width=p["bc"], upstream_slope=p["nu"],
                   downstream_slope=p["nd"], rock=rock, drain_position=p["xd"],
                   drain_efficiency=p["E"], tailwater=p["t"], normal_level=17.0,
                   flood_level=19.0, friction_angle=math.degrees(math.atan(p["f"])), cell=2.0)
    st = run_dam(s, checks=False)
    n = st.row("normal")
    hand = _hand(17.0, **p)
    v = n.values
    assert v["open_length"] == 0.0 and abs(v["compressed_length"] - hand["B"]) < 1e-9
    assert abs(-v["normal_force"] / hand["sum_V"] - 1) < 1e-9
    assert abs(v["shear_force"] / hand["sum_H"] - 1) < 1e-9
    assert abs(v["resultant_from_toe"] - hand["sum_M"] / hand["sum_V"]) < 1e-9 * hand["B"]
    assert abs(v["friction_only_factor"] / (p["f"] * hand["sum_V"] / hand["sum_H"]) - 1) < 1e-9
    mine = hand_statics(s, 17.0)
    for key in ("sum_V", "sum_H", "sum_M", "W", "U"):
        assert abs(mine[key] / hand[key] - 1) < 1e-12, key


def test_the_drained_dam_slides_at_the_hand_level():
    """Without crack water, the uplift (with drains and tailwater) acts whether the joint is
    open or closed, so when every CFE in contact slips f ΣV(h) = ΣH(h) whatever the base's
    stresses: the sliding level on the rock (non-matching meshes) against the root of the hand
    statics' quadratic, below the crest (tolerance 1e-9 relative; measured ~1e-14)."""
    p = dict(H=20.0, bc=4.0, nu=0.0, nd=0.7, rho=2400.0, xd=3.0, E=0.5, t=2.0, f=0.45)
    s = DamSection(height=p["H"], crest_width=p["bc"], downstream_slope=p["nd"],
                   drain_position=p["xd"], drain_efficiency=p["E"], tailwater=p["t"],
                   normal_level=15.0, flood_level=17.0, crack_water=False,
                   friction_angle=math.degrees(math.atan(p["f"])), cell=2.0)
    st = run_dam(s, checks=False)
    assert st.failure is not None and st.failure[1] == "sliding"
    hs = np.array([10.0, 15.0, 20.0])
    g = [p["f"] * _hand(h, **p)["sum_V"] - _hand(h, **p)["sum_H"] for h in hs]
    roots = [r.real for r in np.roots(np.polyfit(hs, g, 2)) if abs(r.imag) < 1e-12]
    h_slide = min(r for r in roots if r > s.tailwater)
    assert abs(st.failure[0] / h_slide - 1) < 1e-9
    assert abs(st.margins["failure / normal"] - h_slide / 15.0) < 1e-9
    assert abs(st.margins["failure / flood"] - h_slide / 17.0) < 1e-9
    assert abs(st.hand_levels["sliding"] / h_slide - 1) < 1e-9  # the report's hand level


@pytest.fixture(scope="module")
def quick_study():
    return run_dam(DamSection(cell=3.0, drain_position=4.0, drain_efficiency=0.4,
                              tailwater=2.0, cohesion=100e3, tensile_strength=50e3),
                   checks=False)


def test_the_figures_are_readable(quick_study):
    """Each figure: no overlapping or clipped text, and what it shows (limits, labels)."""
    st = quick_study
    B = st.section.base_length
    fig = R.plot_section(st)
    assert_readable(fig)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    w = st.row("normal").hand["W"]
    assert any(lb.startswith(f"W = {w / 1e3:.0f} kN") for lb in labels)
    assert any("drains at 4 m" in lb for lb in labels)
    fig = R.plot_base_stresses(st)
    assert_readable(fig)
    assert fig.axes[0].get_xlim() == (0.0, B)
    fig = R.plot_crack_length(st)
    assert_readable(fig)
    assert fig.axes[0].get_ylim() == (0.0, B)
    fig = R.plot_level_displacement(st)
    assert_readable(fig)
    line = fig.axes[0].get_lines()[0]
    np.testing.assert_array_equal(line.get_ydata(), st.path["level"])


def test_the_quick_command_writes_the_report(tmp_path):
    """``stepcontact study dam --quick``: the report (md, html, json) and its four figures,
    with the section's parameters and the margins."""
    out = tmp_path / "dam"
    r = CliRunner().invoke(app, ["study", "dam", "--quick", "-o", str(out), "--height", "24",
                                 "--drain", "3", "--drain-efficiency", "0.5"],
                           env={**os.environ, "COLUMNS": "200"})
    assert r.exit_code == 0, r.output
    md = (out / "report.md").read_text(encoding="utf-8")
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "| height | 24 | m |" in md and "<td>height</td><td>24</td>" in html
    assert "| drain_position | 3 | m |" in md and "<td>drain_position</td><td>3</td>" in html
    for text in (md, html):
        assert "failure / normal" in text and "first opening / flood" in text
    for rel in R.FIGURES.values():
        assert (out / rel).stat().st_size > 0
        assert rel in md
    assert (out / "summary.json").is_file()
    res = sc.load_result(out / "result.nc")  # the run, for stepcontact info/plot/export
    assert res.status == sc.Status.EQUILIBRIUM_LOST and "base" in res.interface_names
    assert "margins on the level" in r.output and "written:" in r.output


def test_bad_parameters_name_the_field():
    for bad, field in ((dict(height=-1.0), "dam.height"),
                       (dict(drain_position=40.0), "dam.drain_position"),
                       (dict(drain_efficiency=1.5), "dam.drain_efficiency"),
                       (dict(flood_level=20.0), "dam.flood_level"),
                       (dict(tailwater=28.0), "dam.tailwater"),
                       (dict(friction_angle=95.0), "dam.friction_angle"),
                       (dict(cohesion=-1.0), "dam.cohesion"),
                       (dict(cell=0.001), "dam.cell"),
                       (dict(max_level=29.0), "dam.max_level")):
        with pytest.raises(ModelError, match=field.replace(".", r"\.")):
            DamSection(**bad)


def test_the_command_refuses_bad_options(tmp_path):
    runner = CliRunner()
    out = str(tmp_path / "x")
    assert_one_line_error(runner.invoke(app, ["study", "dam", "--height", "-5", "-o", out]),
                          "dam.height")
    assert_one_line_error(runner.invoke(app, ["study", "dam", "--E0", "3", "-o", out]),
                          "--E0 applies to the slab study")
    assert_one_line_error(runner.invoke(app, ["study", "slab", "--height", "3", "-o", out]),
                          "--height applies to the dam study")
    assert_one_line_error(runner.invoke(app, ["study", "dam", "--friction", "0.7",
                                              "--friction-angle", "30", "-o", out]),
                          "either --friction")
    assert not (tmp_path / "x").exists()


# ---- combinations, guideline verdicts and the yield acceleration (issue 29 §2–§3) ----------

def _hand_yield(*, H, bc, nu, nd, rho, f, h, r=0.0, silt=None):
    """The pseudo-static yield acceleration of a trapezoidal dam on a rigid, uncracked base by
    limit equilibrium (sliding of the whole base, no cohesion, no drains, no tailwater, no
    crack water), per metre, derived here: the weight W = ρ g (B + b_c) H / 2; the reservoir
    h ≤ H on a face of batter n_u — horizontal γ_w h²/2, vertical n_u γ_w h²/2 (the water
    over the batter); the silt (level s, equivalent fluid γ_s) likewise γ_s s²/2 and
    n_u γ_s s²/2; the uplift γ_w h B / 2.  Per unit k_h: the inertia W (1, r) (r = k_v/k_h,
    + up) and Westergaard's force, the added mass (7/8) ρ_w √(h z) per unit area along the
    face's normal n = (−1, n_u)/√(1 + n_u²) (Kuo's form) times the acceleration
    g (1, r): with ds = √(1 + n_u²) dz its resultant is
    (7/12) γ_w h² (1 − r n_u)/√(1 + n_u²) · (1, −n_u) — on a vertical face (7/12) γ_w h².
    Sliding: f ΣV(k) = ΣH(k) is linear in k."""
    B = bc + (nu + nd) * H
    W = rho * G * (B + bc) * H / 2
    gs, s = (0.0, 0.0) if silt is None else silt
    V0 = W + nu * GAMMA_W * h * h / 2 + nu * gs * s * s / 2 - GAMMA_W * h * B / 2
    H0 = GAMMA_W * h * h / 2 + gs * s * s / 2
    P = 7 / 12 * GAMMA_W * h * h * (1 - r * nu) / math.sqrt(1 + nu * nu)
    dV, dH = -r * W + nu * P, W + P  # per unit k
    return (f * V0 - H0) / (dH - f * dV)


@pytest.mark.parametrize("case", ["rock, vertical face", "rigid base, batter, k_v, silt"])
def test_the_yield_acceleration_against_limit_equilibrium(case):
    """The study's yield acceleration k_y — the k_h at which equilibrium is lost on the k_h
    segment after the usual loads — against the limit equilibrium of :func:`_hand_yield`
    (derived above, independent of the library), tolerance 1e-9 relative (the event is exact;
    measured ~1e-13).

    * on the default rock (non-matching meshes), φ = 35°, a vertical face: the base is still
      fully compressed when the dam slides (asserted: no CFE open), so the hand's uncracked
      statics is the run's;
    * on a rigid base, an upstream batter 0.2, k_v = 0.05 (ratio 0.5), silt 5 m deep (the
      level between nodes) and no crack water: the heel opens, but without crack water the
      uplift does not change and global limit equilibrium holds whatever the stresses.

    Also the module's own hand check (``hand_yield``, the report's table) against the same
    number, the margin k_y / k_h, and the mode."""
    phi = 35.0
    if case.startswith("rock"):
        s = DamSection(cell=2.0, friction_angle=phi)
        ref = _hand_yield(H=30.0, bc=5.0, nu=0.0, nd=0.75, rho=2400.0,
                          f=math.tan(math.radians(phi)), h=27.0)
    else:
        s = DamSection(cell=2.0, friction_angle=phi, rock=None, crack_water=False,
                       upstream_slope=0.2, k_h=0.1, k_v=0.05, silt_level=5.0,
                       silt_unit_weight=9000.0)
        ref = _hand_yield(H=30.0, bc=5.0, nu=0.2, nd=0.75, rho=2400.0,
                          f=math.tan(math.radians(phi)), h=27.0, r=0.5, silt=(9000.0, 5.0))
    y = run_yield(s)
    assert y.k_y is not None and y.mode == "sliding"
    if case.startswith("rock"):
        assert y.open_length == 0.0 and y.first_opening is None  # the precondition
    assert abs(y.k_y / ref - 1) < 1e-9
    assert abs(y.hand["k_y"] / ref - 1) < 1e-12
    assert abs(y.margin - y.k_y / s.k_h) < 1e-15


@pytest.fixture(scope="module")
def checked_study():
    """The default dam, 2 m cells, k_h = 0.3 (above its yield acceleration ≈ 0.27)."""
    return run_dam(DamSection(cell=2.0, k_h=0.3, max_kh=1.0, silt_level=4.0))


def test_the_combinations_and_their_verdicts(checked_study):
    """The study's combinations are those of the section (usual at the normal level, flood
    at the flood level, extreme and post-earthquake with k_h), each checked against the
    guideline: the usual combination's base forces equal the hand statics with the silt
    (1e-9 relative, the base fully compressed), each verdict is the comparison of its value
    with the guideline's required value read from the data file, and a k_h above the yield
    acceleration fails the extreme and post-earthquake combinations (the run loses
    equilibrium) and so the overall verdict."""
    st = checked_study
    names = [c.combination.name for c in st.combinations]
    assert names == ["usual", "unusual (flood)", "extreme (earthquake)", "post-earthquake"]
    usual = st.combinations[0]
    levels = [c.combination.cases[1].level for c in st.combinations]
    assert levels == [27.0, 30.0, 27.0, 27.0]
    s = usual.result.interface_safety("base", heel=(0, 0))
    hs = hand_statics(st.section, 27.0)
    assert s.open_length[-1] == 0.0  # the precondition
    assert abs(-s.normal_force[-1] / hs["sum_V"] - 1) < 1e-9
    assert abs(s.shear_force[-1] / hs["sum_H"] - 1) < 1e-9
    # the silt's thrust, by hand: γ_s s²/2 (a vertical face)
    assert abs(hs["H_silt"] - 13.4e3 * 4.0**2 / 2) < 1e-6
    g = load_guidelines()["usace"]
    row = usual.checks.row("usual", "base", CHECKS["sliding_peak"])
    f_req = g.required("sliding_peak", "usual").value
    assert row.required == f_req and row.passed == (row.value >= f_req)
    assert abs(row.value / (math.tan(math.radians(45.0)) * hs["sum_V"] / hs["sum_H"]) - 1) \
        < 1e-9
    assert st.verdicts["extreme (earthquake)"] == "FAIL"
    assert st.verdicts["post-earthquake"] == "FAIL"
    bad = st.combinations[2].checks.row("extreme (earthquake)", "—",
                                        "run reached the combination's state")
    assert bad.passed is False and "sliding" in bad.note
    assert st.verdict == "FAIL"
    for c in st.combinations:
        done = [r.passed for r in c.checks.rows if r.passed is not None]
        assert c.verdict == ("pass" if all(done) else "FAIL")
    # the extreme run lost equilibrium at the yield acceleration of the yield run
    lost = st.combinations[2].result.multipliers[-1].equilibrium_lost
    assert abs(lost / st.yield_acceleration.k_y - 1) < 1e-9
    assert abs(st.margins["yield k_h / design k_h"] - st.yield_acceleration.k_y / 0.3) < 1e-12


def test_the_report_has_the_verdicts_and_the_yield_acceleration(checked_study, tmp_path):
    """The report: the verdict tables (with [to be checked] and the sources), the overall
    verdict, the yield acceleration and its hand numbers, the guideline named in the
    assumptions; summary.json carries the same."""
    import json

    st = checked_study
    files = R.write_report(st, tmp_path / "rep")
    md = files["markdown"].read_text(encoding="utf-8")
    assert "## Guideline verdicts" in md and "Overall verdict: FAIL (USACE" in md
    html = files["html"].read_text(encoding="utf-8")
    assert "Overall verdict: FAIL (USACE" in html and "<td>FAIL</td>" in html
    assert "### extreme (earthquake): FAIL" in md and "[to be checked]" in md
    assert "EM 1110-2-2100 Table 3-2" in md
    assert "## Yield acceleration" in md
    assert f"| the run's k_y | {st.yield_acceleration.k_y:.6g} |" in md
    assert "USACE EM 1110-2-2100" in md and "Westergaard 1933" in md
    assert R.FIGURES["yield"] in md and (tmp_path / "rep" / R.FIGURES["yield"]).is_file()
    js = json.loads(files["summary"].read_text(encoding="utf-8"))
    assert js["verdict"] == "FAIL" and js["verdicts"]["usual"] == st.verdicts["usual"]
    assert js["yield_acceleration"]["k_y"] == pytest.approx(st.yield_acceleration.k_y,
                                                            rel=1e-15)


def test_the_command_prints_the_verdicts(tmp_path):
    """``--kh``, ``--guideline``: the verdicts and the yield acceleration in the output, and
    the section's fields in the report."""
    out = tmp_path / "dam"
    r = CliRunner().invoke(app, ["study", "dam", "--quick", "-o", str(out), "--kh", "0.12",
                                 "--guideline", "cda", "--silt-level", "3"],
                           env={**os.environ, "COLUMNS": "200"})
    assert r.exit_code == 0, r.output
    assert "guideline verdicts: CDA" in r.output and "overall" in r.output
    assert "yield acceleration: k_y = " in r.output and "k_h = 0.12" in r.output
    md = (out / "report.md").read_text(encoding="utf-8")
    assert "| k_h | 0.12 | g |" in md and "| guideline | cda |" in md
    assert "| silt_level | 3 | m |" in md
    runner = CliRunner()
    assert_one_line_error(runner.invoke(app, ["study", "dam", "--guideline", "abc", "-o",
                                              str(tmp_path / "x")]), "dam.guideline")
    assert_one_line_error(runner.invoke(app, ["study", "slab", "--kh", "0.1", "-o",
                                              str(tmp_path / "x")]), "--kh applies to the dam")


def test_bad_combination_fields_name_the_field():
    for bad, field in ((dict(guideline="eurocode"), "dam.guideline"),
                       (dict(guideline_variant="critical, excellent"), "dam.guideline_variant"),
                       (dict(k_h=0.0), "dam.k_h"), (dict(k_v=1.5), "dam.k_v"),
                       (dict(k_h=0.5, max_kh=0.4), "dam.max_kh"),
                       (dict(silt_level=31.0), "dam.silt_level"),
                       (dict(silt_unit_weight=-1.0), "dam.silt_unit_weight"),
                       (dict(compressive_strength=0.0), "dam.compressive_strength")):
        with pytest.raises(ModelError, match=field.replace(".", r"\.")):
            DamSection(**bad)


def test_the_yield_figure_is_readable(checked_study):
    """The yield figure: readable, its curve ends at k_y (the last state of the k_h segment),
    the design k_h and k_y marked in its legend, the open length within the base."""
    st = checked_study
    y = st.yield_acceleration
    fig = R.plot_yield(st)
    assert_readable(fig)
    ax, axo = fig.axes[:2]
    line = ax.get_lines()[0]
    assert line.get_ydata()[-1] == y.k_y and line.get_ydata()[0] == 0.0
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert f"k_y = {y.k_y:.4f} (sliding)" in labels and "design k_h = 0.3" in labels
    assert axo.get_ylim() == (0.0, st.section.base_length)
