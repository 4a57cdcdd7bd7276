"""Every figure family read from its drawn artists: no two texts or legends overlap, none is
clipped by the figure's edge (tests/figure_checks.py, extents from the Agg renderer), and
what issue 25 names is checked on the artists:

* the deformed shape draws a body force (self-weight) as one resultant arrow per body, at the
  body's centroid, its resultant W = ρ g A in the legend; water pressure stays distributed;
* the interface diagrams of a bonded joint with and without a residual cohesion: short σ_n
  and τ labels, the limits' line styles in the legend;
* the safety figure draws the whole path, each segment against its own parameter (the
  level h in m);
* the time histories name their curves by node set, node and direction, and a node chosen
  by a point or a node set gives the curve of :meth:`StaticResult.node_history`;
* the event timeline's legend stays inside the figure (it was clipped on both sides for a
  dynamic result);
* the CLI's figures (``stepcontact plot``, ``stepcontact demo``).

References: the centroid of a polygon (shoelace formula) and W = ρ g A t by hand; the
curves of ``node_history`` and the stored accelerations; the λ or level of each reported
state.  Tolerances are stated at each assertion.
"""

from __future__ import annotations

import re
import runpy
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from numpy.testing import assert_allclose
from typer.testing import CliRunner

import stepcontact as sc
from figure_checks import assert_readable, text_boxes
from stepcontact.cli import app
from stepcontact.post import plotting
from test_bonded_joints import COHESION, PHI, bonded_dam

matplotlib.use("Agg")
runner = CliRunner()
EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
UNITS = {"N": 1.0, "kN": 1e3, "MN": 1e6, "m": 1.0, "mm": 1e-3, "µm": 1e-6}

# the small gravity dam: trapezoid heel (0, 0), toe (8, 0), crest 2 m wide, 12 m high, on a
# rock block 20 m × 4 m; g = 10 m/s² so that the weights are short decimals (exact in the
# legend's 6 significant digits)
G, RHO_DAM, RHO_ROCK = 10.0, 2400.0, 2500.0  # m/s², kg/m³
DAM = [(0.0, 0.0), (8.0, 0.0), (2.0, 12.0), (0.0, 12.0)]  # m
ROCK = [(-6.0, -4.0), (14.0, -4.0), (14.0, 0.0), (-6.0, 0.0)]  # m
H_DESIGN = 10.0  # m


def polygon_area_centroid(poly) -> tuple[float, np.ndarray]:
    """Area (m²) and centroid (m) of a simple polygon by the shoelace formula."""
    p = np.asarray(poly, float)
    q = np.roll(p, -1, axis=0)
    cross = p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]
    area = cross.sum() / 2
    return area, ((p + q) * cross[:, None]).sum(axis=0) / (6 * area)


def level_dam() -> sc.Model:
    """Weight of both bodies (g = 10 m/s²), then the reservoir: its level h (m) is the
    factor (hydrostatic pressure on the upstream face, uplift h at the heel to 0 at the toe),
    raised to the design level and on until the dam slides (f = 0.7)."""
    concrete = sc.Material(E=25e9, nu=0.2, density=RHO_DAM)
    rock = sc.Material(E=15e9, nu=0.25, density=RHO_ROCK)
    dam = sc.quad_region("dam", DAM, 4, 6, concrete)
    found = sc.rectangle("rock", ROCK[0], ROCK[2], 10, 2, rock)
    m = sc.Model(bodies=[found, dam], name="small-dam")
    base = sc.Interface("base", plus=m.select("dam", y=0), minus=m.select("rock", y=0),
                        friction=0.7)
    return m.add(
        sc.Support("deep rock", m.select("rock", y=-4.0, name="deep rock"), "xy"),
        base,
        sc.LoadPattern("weight", [sc.BodyForce(g=(0.0, -G))]),
        sc.LoadPattern("reservoir", [sc.WaterLoad(m.select("dam", x=0.0), level=None),
                                     sc.Uplift(base, head=[(0.0, 0.0, 1.0), (8.0, 0.0, 0.0)])]),
        sc.Segment("weight", 1.0),
        sc.Segment("reservoir", H_DESIGN),
        sc.Segment("reservoir", 20.0),
    )


@pytest.fixture(scope="module")
def dam():
    model = level_dam()
    res = sc.solve_static(model, store_fields="all")
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    return model, res


@pytest.fixture(scope="module")
def pulse():
    """The slab of examples/slab_uplift.py hit by an uplift pulse (dynamics), with a named
    node set 'corner' (its downstream top corner) for the time histories."""
    slab_model = runpy.run_path(str(EXAMPLES / "slab_uplift.py"),
                                run_name="slab_uplift")["slab_model"]
    m = slab_model()
    m = m.add(sc.LoadPattern("probe", [sc.NodalLoad(
        m.select("slab", x=12.0, y=1.0, name="corner"), fx=0.0)]))
    p_open = sc.solve_static(m).multipliers[-1].first_opening
    rest = sc.solve_static(m.replace(program=(sc.Segment("weight", 1.0),)))
    res = sc.solve_dynamic(m, dt=1e-3, duration=0.06, initial=rest, mass="lumped",
                           loads={"uplift": sc.Pulse(2.0 * p_open, 0.005, 0.04, "half_sine")})
    assert len({e.transition for e in res.events}) >= 4  # a legend of many entries
    return m, res


def legend_texts(fig) -> list[str]:
    return [t.get_text() for lg in fig.legends for t in lg.get_texts()]


def quivers(ax) -> dict:
    return {c.get_gid(): c for c in ax.collections if type(c).__name__ == "Quiver"}


# --------------------------------------------------------------------------------------------
# deformed shape
# --------------------------------------------------------------------------------------------
def test_deformed_draws_one_weight_arrow_per_body_at_its_centroid(dam):
    """One arrow per body with a body force, its tail at the body's centroid (shoelace; the
    figure drawn at a magnification of 1e-6: the displaced centroid within 1e-6 m), the
    arrows' lengths in the ratio of the weights (1e-9 relative), the legend's resultant
    W = g (ρ_dam A_dam + ρ_rock A_rock) to 1e-9 relative; the water loads still nodal."""
    _, res = dam
    i = int(np.flatnonzero((res.segment == 1) & (res.kind == "segment_end"))[0])
    fig = plotting.plot_deformed(res, state=i, scale=1e-6)
    assert_readable(fig)
    arrows = quivers(fig.axes[0])
    weight = arrows["body force:weight"]
    ref = {name: polygon_area_centroid(poly) for name, poly in (("rock", ROCK), ("dam", DAM))}
    W = {"rock": RHO_ROCK * G * ref["rock"][0], "dam": RHO_DAM * G * ref["dam"][0]}  # N/m
    assert W == {"rock": 2.0e6, "dam": 1.44e6}
    offsets = weight.get_offsets()
    assert len(offsets) == 2  # both bodies carry the body force (no `bodies`: all of them)
    assert_allclose(offsets, [ref["rock"][1], ref["dam"][1]], atol=1e-6)
    assert_allclose(weight.U, 0.0, atol=1e-12)
    assert np.all(np.asarray(weight.V) < 0)  # downwards, along g
    assert weight.V[1] / weight.V[0] == pytest.approx(W["dam"] / W["rock"], rel=1e-9)
    entry = next(t for t in legend_texts(fig) if t.startswith("'weight'"))
    fx, fy, unit = re.search(r"F = \(([-\d.e+]+), ([-\d.e+]+)\) (\w+)", entry).groups()
    assert float(fx) == 0.0
    assert float(fy) * UNITS[unit] == pytest.approx(-(W["rock"] + W["dam"]), rel=1e-9)
    assert "one arrow per body at its centre of mass" in entry
    # the reservoir: pressure and uplift stay distributed, one arrow per loaded node
    assert "load:weight" not in arrows
    assert len(arrows["load:reservoir"].get_offsets()) > 5
    assert any(t.startswith("'reservoir': resultant F = ") for t in legend_texts(fig))
    assert "h = 10 m" in fig.get_suptitle()  # the level, in m


def test_deformed_weight_of_one_body(dam):
    """A body force on one body of two: one arrow, at that body's centroid (1e-6 m)."""
    model, _ = dam
    weight = model.pattern("weight")
    only = model.replace(patterns=tuple(
        sc.LoadPattern("weight", [sc.BodyForce(g=(0.0, -G), bodies=("dam",))])
        if p is weight else p for p in model.patterns))
    res = sc.solve_static(only.replace(program=(sc.Segment("weight", 1.0),)))
    fig = plotting.plot_deformed(res, scale=1e-6)
    assert_readable(fig)
    (at,) = quivers(fig.axes[0])["body force:weight"].get_offsets()
    assert_allclose(at, polygon_area_centroid(DAM)[1], atol=1e-6)
    assert "self-weight of 'dam' at its centre of mass" in legend_texts(fig)[-1]


def test_deformed_weight_of_tied_bodies():
    """Two blocks 2 m × 0.5 m tied along y = 0.5 (their nodes there share DOFs): one weight
    arrow each, at (1, 0.25) and (1, 0.75) m (1e-6 m), no weight left over as nodal arrows
    at the tied nodes, the resultant 2 · 2400 · 9.81 · 1 = 47 088 N (1e-9 relative)."""
    mat = sc.Material(30e9, 0.2, 2400.0)
    m = sc.Model(bodies=[sc.rectangle("base", (-1, -1), (3, 0), 8, 2, mat),
                         sc.rectangle("lower", (0, 0), (2, 0.5), 4, 1, mat),
                         sc.rectangle("upper", (0, 0.5), (2, 1.0), 4, 1, mat)])
    m = m.add(sc.Support("bed", m.select("base", y=-1.0)),
              sc.Tie("glue", m.select("upper", y=0.5), m.select("lower", y=0.5)),
              sc.Interface("joint", m.select("lower", y=0.0), m.select("base", y=0.0),
                           friction=0.6),
              sc.LoadPattern("weight", [sc.BodyForce(bodies=("lower", "upper"))]),
              sc.Segment("weight", 1.0))
    fig = plotting.plot_deformed(sc.solve_static(m), scale=1e-6)
    assert_readable(fig)
    arrows = quivers(fig.axes[0])
    assert set(arrows) == {"body force:weight"}
    assert_allclose(arrows["body force:weight"].get_offsets(), [(1.0, 0.25), (1.0, 0.75)],
                    atol=1e-6)
    (entry,) = legend_texts(fig)
    fy, unit = re.search(r"F = \(0, ([-\d.e+]+)\) (\w+)", entry).groups()
    assert float(fy) * UNITS[unit] == pytest.approx(-2 * 2400 * 9.81 * 1.0, rel=1e-9)


# --------------------------------------------------------------------------------------------
# interfaces, load path, load–displacement, timeline
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("residual", [0.0, 100e3])
def test_interfaces_of_a_bonded_joint_are_readable(residual):
    """The bonded block of test_bonded_joints (its base cracks under the water): labels of
    σ_n and τ short, the limits' line styles in the legend (the residual cohesion's only
    when there is one)."""
    bond = sc.Bond.mohr_coulomb(COHESION, 50e3, PHI, residual_cohesion=residual)
    res = sc.solve_static(bonded_dam(bond=bond, nx=8))
    assert any(e.transition == sc.Transition.BROKEN for e in res.events)
    fig = plotting.plot_interfaces(res)
    assert_readable(fig)
    assert fig.axes[1].get_ylabel() == r"$\tau$ = Q/A, MPa"
    (limits,) = [t for t in legend_texts(fig) if t.startswith(r"$\tau$ limits dashed")]
    assert r"bonded $\pm(\tau_R - \alpha_R \sigma_n)$" in limits
    assert (r"broken, closed $\pm(f|\sigma_n| + c_r)$" in limits) == (residual > 0)
    assert_readable(plotting.plot_load_path(res))
    assert_readable(plotting.plot_event_timeline(res))


@pytest.fixture(scope="module")
def staged_bonded():
    """The staged bonded dam of examples/bonded_dam.py (two lifts, crack water) with a
    residual cohesion of 100 kPa in the base."""
    base = runpy.run_path(str(EXAMPLES / "cracked_base.py"), run_name="cracked_base")
    m = base["dam_model"](
        crack_water=True,
        bond=sc.Bond.mohr_coulomb(500e3, 50e3, 40.0, residual_cohesion=100e3),
        layer=sc.ContactLayer(thickness=0.5, E=2e9, nu=0.25), levels=(28.0, 60.0),
        lifts=(15.0,), lift_bond=sc.Bond.mohr_coulomb(1.0e6, 0.5e6, 45.0))
    return sc.solve_static(m)


@pytest.mark.slow
def test_staged_bonded_dam_figures_are_readable(staged_bonded):
    """The figures the issue found unreadable on the bonded dam: the σ_n and τ labels and the
    state strip's rows (named by stage) do not overlap; the safety figure has a column per
    run of segments, the level axis in m."""
    res = staged_bonded
    fig = plotting.plot_interfaces(res)
    assert_readable(fig)
    rows = [t.get_text() for t in fig.axes[4].get_yticklabels()]
    assert rows[-1].startswith("impounding: reservoir h=") and rows[-1].endswith(" m")
    fig = plotting.plot_safety(res, design=28.0)
    assert_readable(fig)
    xlabels = [ax.get_xlabel() for ax in fig.axes if ax.get_xlabel()]
    assert xlabels == ["λ\nof 'weight'", "λ\nof 'lift 2: loads on lift 2'",
                       "water level h of 'reservoir', m"]
    # the lift joint, just made (stress-free), carries round-off forces only: no limit read
    # there (its resultant's "eccentricity" is meaningless)
    sf = res.interface_safety("joint 1", 28.0)
    if sf.lam_overturning is not None:
        i = int(np.flatnonzero(sf.lam == sf.lam_overturning)[0])
        assert abs(sf.normal_force[i]) <= 1e-9 * np.abs(sf.normal_force).max()
    (entry,) = [t for t in legend_texts(fig) if t.startswith("'joint 1'")]
    assert "overturns" not in entry
    for draw in (plotting.plot_event_timeline, plotting.plot_load_path,
                 plotting.plot_deformed):
        assert_readable(draw(res))


def test_load_path_and_load_displacement_are_readable(dam):
    """Both readable; the level named as such (in m) on the axes and at the loss of
    equilibrium (the run's sliding level, 5 significant digits)."""
    _, res = dam
    fig = plotting.plot_load_path(res)
    assert_readable(fig)
    assert fig.axes[0].get_ylabel().endswith("(water level h in m for 'reservoir')")
    fig = plotting.plot_load_displacement(res)
    assert_readable(fig)
    # one panel per segment, the reservoir's on the level axis in m
    assert [ax.get_ylabel() for ax in fig.axes] == [
        "λ of 'weight'", "water level h of 'reservoir', m", "water level h of 'reservoir', m"]
    h = res.multipliers[-1].equilibrium_lost
    assert f"equilibrium lost, h = {h:.5g} m" in [t.get_text() for t in fig.axes[-1].texts]


def legend_inside(fig) -> None:
    """Each figure legend lies inside the figure (1 px), and is not wider than it."""
    fig.canvas.draw()
    for lg in fig.legends:
        bb = lg.get_window_extent(fig.canvas.get_renderer())
        assert bb.x0 >= fig.bbox.x0 - 1 and bb.x1 <= fig.bbox.x1 + 1, (bb, fig.bbox)


def test_event_timeline_legend_inside_the_figure(dam, pulse):
    """A dynamic result's timeline is one narrow column: its legend (4 states, 5
    transitions) was clipped on both sides; it now wraps into rows."""
    _, dyn = pulse
    for res in (dam[1], dyn):
        fig = plotting.plot_event_timeline(res)
        legend_inside(fig)
        assert_readable(fig)
    assert len(fig.legends[0].get_texts()) >= 8  # every state and transition still named
    # the static dam's columns: the reservoir's segments titled by the level in m
    h = dam[1].multipliers[-1].equilibrium_lost
    titles = [ax.get_title() for ax in plotting.plot_event_timeline(dam[1]).axes]
    assert titles == ["segment 0: weight λ=0 → 1", "segment 1: reservoir h=0 → 10 m",
                      f"segment 2: reservoir h=10 → {h:.5g} m"]


# --------------------------------------------------------------------------------------------
# safety along the whole path
# --------------------------------------------------------------------------------------------
def test_safety_draws_every_segment_on_its_own_axis(dam):
    """The weight 0 → 1 in a narrow column (λ), the reservoir's two segments 0 → 10 → 11.7 m
    in a wide one on a level axis in m: the x data of each column are the λ or levels of the
    reported states of its segments (exact); the design level marked in the level column
    only; the sliding level in the legend (4 digits, from the run's loss of equilibrium)."""
    _, res = dam
    fig = plotting.plot_safety(res, design=H_DESIGN)
    assert_readable(fig)
    axes = np.array(fig.axes).reshape(3, 2)
    assert axes[2, 0].get_xlabel() == "λ\nof 'weight'"
    assert axes[2, 1].get_xlabel() == "water level h of 'reservoir', m"
    seg = np.asarray(res.segment)
    for col, segs in ((0, [0]), (1, [1, 2])):
        drawn = np.unique(np.concatenate([ln.get_xdata() for ln in axes[2, col].get_lines()
                                          if ln.get_marker() == "."]))  # the data lines
        want = np.unique(np.r_[[0.0], res.lam[np.isin(seg, segs)]])
        assert_allclose(drawn, want, rtol=0, atol=0)
    design = [ln for ax in fig.axes for ln in ax.get_lines() if ln.get_gid() == "design"]
    assert len(design) == 3 and all(ln.axes in axes[:, 1] for ln in design)
    assert all(ln.get_xdata()[0] == H_DESIGN for ln in design)
    h_slide = res.multipliers[-1].equilibrium_lost
    assert 10.0 < h_slide < 20.0
    entry = next(t for t in legend_texts(fig) if t.startswith("'base'"))
    assert f"slides at h = {h_slide:.4g} m (h/h_d = {h_slide / H_DESIGN:.3g})" in entry
    assert "design level h_d = 10 m" in legend_texts(fig)
    # one segment on its own, as before
    one = plotting.plot_safety(res, segment=2)
    assert len(one.axes) == 3 and one.axes[2].get_xlabel() == "water level h of 'reservoir', m"


# --------------------------------------------------------------------------------------------
# time histories and the energy ledger
# --------------------------------------------------------------------------------------------
def lines_of(fig) -> dict[str, tuple]:
    return {ln.get_label(): (ax, ln) for ax in fig.axes for ln in ax.get_lines()
            if not ln.get_label().startswith("_")}


def test_time_history_by_node_set_and_point(pulse):
    """By node set and by the nearest node to a point: the same curves as node_history
    (after the axis unit, rtol 1e-12), named by node set, node, coordinates and direction."""
    m, res = pulse
    (k,) = res.node_sets["corner"]
    fig = plotting.plot_time_history(res, nodes="corner")
    assert_readable(fig)
    lines = lines_of(fig)
    label = f"corner (node {k}, x = 12, y = 1 m): "
    assert set(lines) >= {label + s for s in ("u_x", "u_y", "v_x", "v_y")}
    unit = fig.axes[0].get_ylabel().split(", ")[1]
    for q, div in (("ux", UNITS[unit]), ("uy", UNITS[unit]), ("vx", 1.0), ("vy", 1.0)):
        want = res.node_history("corner", q)[:, 0]
        _, ln = lines[label + q[0] + "_" + q[1]]
        assert_allclose(np.asarray(ln.get_ydata()) * div, want, rtol=1e-12, atol=0)
    by_point = plotting.plot_time_history(res, point=(12.0, 1.0), direction="uy")
    assert_readable(by_point)
    (name,) = lines_of(by_point)
    assert name == label + "u_y"  # the nearest node, named by the set that holds it
    unit = by_point.axes[0].get_ylabel().split(", ")[1]
    assert_allclose(lines_of(by_point)[name][1].get_ydata() * np.float64(UNITS[unit]),
                    res.node_history(point=(12.0, 1.0), quantity="uy"), rtol=1e-12)
    # an acceleration, read from the stored accelerations of the node's DOF
    acc = plotting.plot_time_history(res, nodes=int(k), direction=["ay"])
    (name,) = lines_of(acc)
    assert name == label + "a_y" and acc.axes[0].get_ylabel() == "acceleration, m/s²"
    dof = np.asarray(res.geometry["dof_of"])[k, 1]
    assert_allclose(lines_of(acc)[name][1].get_ydata(), res.a[:, dof], rtol=0, atol=0)


def test_time_history_dof_input_and_errors(pulse):
    """The old input (global DOF indices) still draws, now named by node and direction;
    a wrong node set or direction is an error naming it."""
    _, res = pulse
    (k,) = res.node_sets["corner"]
    dof = int(np.asarray(res.geometry["dof_of"])[k, 0])
    fig = plotting.plot_time_history(res, [dof])
    assert_readable(fig)
    assert set(lines_of(fig)) == {f"corner (node {k}, x = 12, y = 1 m): u_x",
                                  f"corner (node {k}, x = 12, y = 1 m): v_x"}
    with pytest.raises(ValueError, match="no node set 'crest'"):
        plotting.plot_time_history(res, nodes="crest")
    with pytest.raises(ValueError, match="direction='uz'"):
        plotting.plot_time_history(res, nodes="corner", direction="uz")
    with pytest.raises(ValueError, match="shared by bodies"):
        plotting.plot_time_history(res, point=(2.0, 0.0))
    with pytest.raises(ValueError, match="either dofs"):
        plotting.plot_time_history(res, [0], point=(2.0, 1.0))


def test_energy_is_readable(pulse):
    _, res = pulse
    fig = plotting.plot_energy(res)
    assert_readable(fig)
    assert {"kinetic", "strain", "external"} <= {ln.get_label() for ln in fig.axes[0].lines}


# --------------------------------------------------------------------------------------------
# the CLI's figures
# --------------------------------------------------------------------------------------------
@pytest.fixture
def drawn(monkeypatch):
    """The figures the CLI draws (function name, figure), recorded from the plotting module."""
    figures: list[tuple[str, object]] = []

    def recording(name, draw):
        def wrapper(*args, **kwargs):
            fig = draw(*args, **kwargs)
            figures.append((name, fig))
            return fig
        return wrapper

    for name in plotting.__all__:
        if name.startswith("plot_"):
            monkeypatch.setattr(plotting, name, recording(name, getattr(plotting, name)))
    return figures


@pytest.mark.slow
def test_cli_plot_figures_are_readable(dam, pulse, tmp_path, drawn):
    """``stepcontact plot --kind all`` of a static result (every static figure) and the
    dynamic figures, among them ``--kind history --node-set corner``."""
    _, res = dam
    res.save(tmp_path / "dam.nc")
    out = runner.invoke(app, ["plot", str(tmp_path / "dam.nc"), "--kind", "all", "-o",
                              str(tmp_path / "figs"), "--dpi", "40"])
    assert out.exit_code == 0, out.output
    assert {n for n, _ in drawn} == {"plot_deformed", "plot_interfaces", "plot_event_timeline",
                                     "plot_safety", "plot_load_displacement"}
    _, dyn = pulse
    dyn.save(tmp_path / "slab-dynamic.nc")
    for args in (["--kind", "history", "--node-set", "corner", "--dof", "y"],
                 ["--kind", "history", "--node", "12,1", "--dof", "ay"],
                 ["--kind", "timeline"], ["--kind", "energy"]):
        out = runner.invoke(app, ["plot", str(tmp_path / "slab-dynamic.nc"), *args, "-o",
                                  str(tmp_path / "d.png"), "--dpi", "40"])
        assert out.exit_code == 0, out.output
    for _, fig in drawn:
        assert_readable(fig)
    histories = [fig for name, fig in drawn if name == "plot_time_history"]
    (k,) = dyn.node_sets["corner"]
    assert set(lines_of(histories[0])) == {f"corner (node {k}, x = 12, y = 1 m): u_y",
                                           f"corner (node {k}, x = 12, y = 1 m): v_y"}
    assert set(lines_of(histories[1])) == {f"corner (node {k}, x = 12, y = 1 m): a_y"}
    out = runner.invoke(app, ["plot", str(tmp_path / "dam.nc"), "--kind", "history"])
    assert out.exit_code == 2 and "needs a dynamic result" in out.stderr
    out = runner.invoke(app, ["plot", str(tmp_path / "dam.nc"), "--kind", "timeline",
                              "--node-set", "corner"])
    assert out.exit_code == 2 and "--node-set applies to --kind history" in out.stderr


def test_cli_demo_figures_are_readable(tmp_path, drawn):
    out = runner.invoke(app, ["demo", "-o", str(tmp_path), "--quiet"])
    assert out.exit_code == 0, out.output
    assert [n for n, _ in drawn] == ["plot_interfaces", "plot_interfaces"]
    for _, fig in drawn:
        assert_readable(fig)
        assert text_boxes(fig)  # (the check saw the drawn texts)
