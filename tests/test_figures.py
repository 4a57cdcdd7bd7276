"""Figure content: stress contours, body labels and load arrows on the deformed shape; the
default node and direction of the load–displacement curve; the loss of equilibrium marked;
state-strip rows named by pattern and λ; the corner singularity of a stiff block noted.

Every check reads the matplotlib objects (labels, texts, collections, lines) and compares
them with values computed independently from the result.
"""

from __future__ import annotations

import dataclasses
import re

import matplotlib
import numpy as np
import pytest
from numpy.testing import assert_allclose
from typer.testing import CliRunner

import stepcontact as sc
import verification_models as vm
from stepcontact import EdgeLoad, Interface, LoadPattern, Material, Model, Segment, Support
from stepcontact.cli import app
from stepcontact.fem.assembly import assemble
from stepcontact.post.plotting import (
    CORNER_NOTE,
    _lam_text,
    plot_deformed,
    plot_event_timeline,
    plot_interfaces,
    plot_load_displacement,
)

matplotlib.use("Agg")
UNITS = {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "N": 1.0, "kN": 1e3, "MN": 1e6,
         "m": 1.0, "mm": 1e-3, "µm": 1e-6}


def pushed_model() -> Model:
    """Block 2 m × 1 m on a base: weight, then a push on its left side until it slides."""
    return vm.pushed_block(base_cells=(8, 1), block_cells=(4, 2), name="block")


def stiff_block_model() -> Model:
    """A very stiff block [0, 2] × [0, 0.5] pressed by 100 kPa on a soft base (a nearly
    rigid punch: the contact stress is singular at the block's corners)."""
    stiff, soft = Material(3e12, 0.2, 2400.0), Material(1e9, 0.25, 2000.0)
    base = sc.rectangle("base", (-1.0, -1.0), (3.0, 0.0), 12, 3, soft)
    block = sc.rectangle("block", (0.0, 0.0), (2.0, 0.5), 8, 2, stiff)
    m = Model().add(base, block)
    return m.add(
        Support("bed", m.select("base", y=-1.0)),
        Interface("joint", m.select("block", y=0.0), m.select("base", y=0.0), friction=0.6),
        LoadPattern("press", [EdgeLoad(m.select("block", y=0.5), normal=1e5)]),
        Segment("press", 1.0),
    )


@pytest.fixture(scope="module")
def pushed():
    model = pushed_model()
    return model, sc.solve_static(model, store_fields="all")


def without_model(res):
    """The result as loaded from its file: no model, no field recovery."""
    return dataclasses.replace(res, _recover=None)


def texts(fig) -> list[str]:
    return [t.get_text() for ax in fig.axes for t in ax.texts]


def legend_texts(fig) -> list[str]:
    return [t.get_text() for lg in fig.legends for t in lg.get_texts()]


# --------------------------------------------------------------------------------------------
# deformed shape: stress contours, body labels, load arrows
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("component", "label"), [("syy", r"$\sigma_{yy}$"),
                                                  ("von_mises", "von Mises")])
def test_stress_contours_with_colorbar_and_unit(pushed, component, label):
    _, res = pushed
    i = res.n_states - 1
    fig = plot_deformed(res, stress=component)
    assert len(fig.axes) == 2  # the mesh and its colour bar
    cbar = fig.axes[1].get_ylabel()
    assert cbar.startswith(label)
    unit = cbar.rsplit(", ", 1)[1]
    assert unit in ("Pa", "kPa", "MPa")
    filled = [c for c in fig.axes[0].collections if type(c).__name__ == "PolyCollection"
              and c.get_array() is not None]
    assert len(filled) == 1
    sig = res.stress(i)
    want = []
    for b in res.geometry["bodies"]:  # base then block, one value per cell
        sx, sy, txy, sz = np.asarray(sig[b["name"]]).T
        want.append(sy if component == "syy" else np.sqrt(
            ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2) / 2 + 3 * txy**2))
    want = np.concatenate(want)
    assert_allclose(filled[0].get_array(), want / UNITS[unit], rtol=1e-12)
    peak = np.abs(want).max() / UNITS[unit]
    assert 1.0 <= peak < 1000.0  # the unit makes the values read well
    lo, hi = filled[0].get_clim()
    assert hi == pytest.approx(peak) and lo == pytest.approx(0.0 if label == "von Mises"
                                                              else -peak)


def test_stress_component_errors_leave_no_file(pushed, tmp_path):
    _, res = pushed
    out = tmp_path / "d.png"
    with pytest.raises(ValueError, match=r"stress='tau': use one of sxx, syy, sxy, szz, mises"):
        plot_deformed(res, stress="tau", path=out)
    assert not out.exists() and not list(tmp_path.iterdir())
    plot_deformed(res, stress="σxy", path=out)  # the other spellings
    assert out.stat().st_size > 1000


def test_body_labels_at_centroids(pushed):
    _, res = pushed
    fig = plot_deformed(res, scale=1.0)  # displacements ~ µm: the centroids of the rectangles
    labels = {t.get_text(): t.get_position() for t in fig.axes[0].texts}
    assert_allclose(labels["base"], (2.0, 0.5), atol=1e-4)
    assert_allclose(labels["block"], (2.0, 1.5), atol=1e-4)
    assert not plot_deformed(res, labels=False).axes[0].texts


def test_load_arrows_from_assembled_vectors(pushed):
    """The push as nodal arrows parallel to the assembled nodal forces; the weight (a body
    force) as one arrow at the block's centroid (2, 1.5) m (displaced by at most the largest
    drawn displacement), its resultant W = ρ g A = 2400 · 9.81 · 2 · 1 = 47 088 N per metre
    in the legend (6 significant digits: exact here)."""
    model, res = pushed
    i = res.n_states - 1
    fig = plot_deformed(res)
    ax = fig.axes[0]
    arrows = {c.get_gid(): c for c in ax.collections if type(c).__name__ == "Quiver"}
    assert set(arrows) == {"body force:weight", "load:push"}
    system = assemble(model)
    dof_of = np.asarray(res.geometry["dof_of"])
    pts = np.asarray(res.geometry["points"])
    size = np.ptp(pts, axis=0).max()
    for name in ("push",):
        lam = res.factors[i, res.pattern_names.index(name)]
        f = lam * system.loads[name].f
        F = np.where(dof_of[:, :2] >= 0, f[np.maximum(dof_of[:, :2], 0)], 0.0)
        # tied nodes share DOFs: count each DOF once
        _, first = np.unique(dof_of[:, 1], return_index=True)
        loaded = np.flatnonzero(np.linalg.norm(F, axis=1) > 0)
        loaded = loaded[np.isin(loaded, first)]
        q = arrows[f"load:{name}"]
        uv = np.c_[q.U, q.V]
        assert len(uv) == len(loaded)
        # parallel to the nodal forces, the longest 10 % of the model size
        assert_allclose(uv / np.abs(uv).max(), F[loaded] / np.abs(F[loaded]).max(), atol=1e-12)
        assert np.linalg.norm(uv, axis=1).max() == pytest.approx(0.1 * size)
        # the legend gives the resultant, from the assembled vector
        R = F[loaded].sum(axis=0)
        entry = next(t for t in legend_texts(fig) if t.startswith(f"'{name}'"))
        assert f"λ = {_lam_text(lam)}" in entry
        fx, fy, unit = re.search(r"F = \(([-\d.e+]+), ([-\d.e+]+)\) (\w+)", entry).groups()
        assert_allclose([float(fx), float(fy)], R / UNITS[unit], rtol=1e-5, atol=1e-9)
    q = arrows["body force:weight"]
    (at,) = q.get_offsets()
    umax = np.abs(res.displacement(i)).max() * float(
        re.search(r"× ([\d.e+]+)", fig.get_suptitle()).group(1))
    assert_allclose(at, (2.0, 1.5), atol=umax + 1e-9)
    assert q.U[0] == pytest.approx(0.0, abs=1e-12) and q.V[0] == pytest.approx(-0.15 * size)
    W = 2400 * 9.81 * 2.0 * 1.0  # the block's weight, N
    assert W == pytest.approx(47088.0)
    assert ("'weight' at λ = 1: resultant F = (0, -47.088) kN, self-weight of 'block' at its "
            "centre of mass") in legend_texts(fig)
    assert not [c for c in plot_deformed(res, loads=False).axes[0].collections
                if type(c).__name__ == "Quiver"]


def test_load_arrows_without_model_on_the_line_of_action(pushed):
    _, res = pushed
    i = res.n_states - 1
    fig = plot_deformed(without_model(res))
    arrows = {c.get_gid(): c for c in fig.axes[0].collections if type(c).__name__ == "Quiver"}
    assert set(arrows) == {"load:weight", "load:push"}
    for name, q in arrows.items():
        Fx, Fy, Mz = res.load_resultant(name.split(":")[1], state=i)
        (x, y), = q.get_offsets()
        assert x * Fy - y * Fx == pytest.approx(Mz, rel=1e-9, abs=1e-9 * abs(Mz) + 1e-6)
        assert q.U[0] * Fy - q.V[0] * Fx == pytest.approx(0.0, abs=1e-9 * np.hypot(Fx, Fy))
        assert q.U[0] * Fx + q.V[0] * Fy > 0  # along the force
    assert all("(its line of action)" in t for t in legend_texts(fig))


# --------------------------------------------------------------------------------------------
# load–displacement: default node and direction, loss of equilibrium
# --------------------------------------------------------------------------------------------
def peak_motion(res) -> np.ndarray:
    """(n_nodes, 2): the largest |u_x|, |u_y| of every node over all reported states."""
    U = res.displacements()
    dof = np.asarray(res.geometry["dof_of"])[:, :2]
    return np.where(dof >= 0, np.abs(U[:, np.maximum(dof, 0)]), 0.0).max(axis=0)


def chosen(fig) -> tuple[int, int, str]:
    label = fig.axes[-1].get_xlabel()
    comp, node = re.match(r"\$u_(x|y)\$ of node (\d+) ", label).groups()
    return int(node), "xy".index(comp), label


def test_default_node_and_direction_move_most(pushed):
    _, res = pushed
    A = peak_motion(res)
    fig = plot_load_displacement(res)
    k, c, label = chosen(fig)
    assert A[k, c] == A.max()
    assert "moves most over the path" in label
    # the curve is that DOF's displacement at every state
    unit = label.rsplit(", ", 1)[1]
    dof = int(np.asarray(res.geometry["dof_of"])[k, c])
    push = fig.axes[1].get_lines()[0]
    idx = np.flatnonzero(res.segment == 1)
    assert_allclose(push.get_xdata()[-len(idx):], res.displacements()[idx, dof] / UNITS[unit],
                    rtol=1e-12)
    # a given direction: the node that moves most in it over the path
    k, c, label = chosen(plot_load_displacement(res, dof="y"))
    assert c == 1 and A[k, 1] == A[:, 1].max() and "largest |u| over the path" in label
    # a given node: the direction in which it moves most
    top_right = int(np.flatnonzero(np.all(np.isclose(res.geometry["points"], [3.0, 2.0]),
                                          axis=1))[0])
    k, c, label = chosen(plot_load_displacement(res, node=top_right))
    assert k == top_right and c == int(np.argmax(A[k])) and "over the path" not in label


def test_equilibrium_lost_marked(pushed):
    _, res = pushed
    lost = res.multipliers[-1].equilibrium_lost
    assert res.status is sc.Status.EQUILIBRIUM_LOST and lost is not None
    for axis in ("lam", "path"):
        fig = plot_load_displacement(res, axis=axis)
        stars = [(ax, ln) for ax in fig.axes for ln in ax.get_lines()
                 if ln.get_gid() == "equilibrium_lost"]
        assert len(stars) == 1
        ax, star = stars[0]
        assert ax is fig.axes[-1]  # the panel of the last segment ('push')
        assert star.get_ydata()[0] == (lost if axis == "lam" else pytest.approx(2.0))
        curve = next(ln for ln in ax.get_lines() if ln.get_label().startswith("segment 1"))
        assert star.get_xdata()[0] == curve.get_xdata()[-1]  # at the last state
        assert f"equilibrium lost, λ = {_lam_text(lost)}" in [t.get_text() for t in ax.texts]
    assert "equilibrium lost, λ = 23 544" in texts(plot_load_displacement(res))
    # on a reaction curve too
    fig = plot_load_displacement(res, reaction="bed", dof="x")
    star = [ln for ln in fig.axes[-1].get_lines() if ln.get_gid() == "equilibrium_lost"]
    assert len(star) == 1 and star[0].get_ydata()[0] == lost
    # a completed run: no marker
    done = sc.solve_static(vm.uplift_slab("top_pressure", 0.5), store_fields="all")
    assert done.status is sc.Status.COMPLETED
    fig = plot_load_displacement(done)
    assert not [ln for ax in fig.axes for ln in ax.get_lines()
                if ln.get_gid() == "equilibrium_lost"]
    assert not any("equilibrium lost" in t for t in texts(fig))


# --------------------------------------------------------------------------------------------
# state strip and timeline: rows named by pattern and λ
# --------------------------------------------------------------------------------------------
def test_lam_text():
    assert [_lam_text(v) for v in (1.0, 0.25, 0.0, -3.5, 1234.5, 23544.00000000002,
                                   123456.7, -10000.0, 1e10)] == [
        "1", "0.25", "0", "-3.5", "1234.5", "23 544", "123 457", "-10 000", "1e+10"]


def test_strip_rows_and_timeline_named_with_pattern_and_lam(pushed):
    _, res = pushed
    fig = plot_interfaces(res)
    rows = [t.get_text() for t in fig.axes[2].get_yticklabels()]
    assert rows == ["weight λ=1", "push λ=23 544"]
    fig = plot_interfaces(res, lams=[1e4, 2e4], states=[1])
    rows = [t.get_text() for t in fig.axes[2].get_yticklabels()]
    assert rows == ["push λ=10 000", "push λ=20 000", "weight λ=1"]
    titles = [ax.get_title() for ax in plot_event_timeline(res).axes]
    assert titles == ["segment 0: weight λ=0 → 1", "segment 1: push λ=0 → 23 544"]


# --------------------------------------------------------------------------------------------
# contact stresses: the corner singularity
# --------------------------------------------------------------------------------------------
def test_corner_singularity_noted_on_a_stiff_block():
    res = sc.solve_static(stiff_block_model())
    fig = plot_interfaces(res)
    ax = fig.axes[0]
    notes = [t for t in ax.texts if t.get_text() in (CORNER_NOTE, "")]
    assert [t.get_text() for t in notes] == [CORNER_NOTE, ""]  # one text, an arrow per end
    # the arrows point at the two end CFEs, the block's corners x = 0 and x = 2
    order = np.argsort(res.cfe["s"], kind="stable")
    sig = (res.N[-1] / res.cfe["area"])[order]
    s = res.cfe["s"][order]
    x = res.cfe["x"].reshape(-1, 2)[order]
    assert_allclose(x[[0, -1]], [[0.0, 0.0], [2.0, 0.0]], atol=1e-12)
    assert abs(sig[0]) > 2 * np.mean(np.abs(sig[1:3]))  # the criterion, independently
    div = UNITS[ax.get_ylabel().split(", ")[1].split()[0]]
    assert_allclose([t.xy for t in notes], [(s[0], sig[0] / div), (s[-1], sig[-1] / div)],
                    rtol=1e-12)


def test_no_corner_note_on_a_uniform_patch():
    res = sc.solve_static(vm.uplift_slab("top_pressure", 0.5))
    sig = res.N[-1] / res.cfe["area"]
    assert_allclose(sig, sig.mean(), rtol=1e-6)  # a uniform contact stress
    assert CORNER_NOTE not in texts(plot_interfaces(res))


# --------------------------------------------------------------------------------------------
# command line
# --------------------------------------------------------------------------------------------
def test_cli_stress(pushed, tmp_path, monkeypatch):
    """``plot --stress``; the default --dof (None: the direction that moves most) is checked
    with ``--kind all`` in test_plots_info."""
    from stepcontact.post import plotting

    _, res = pushed
    nc = tmp_path / "r.nc"
    res.save(nc)
    drawn = []

    def recording(*a, _draw=plotting.plot_deformed, **kw):
        drawn.append(_draw(*a, **kw))
        return drawn[-1]

    monkeypatch.setattr(plotting, "plot_deformed", recording)
    runner = CliRunner()
    out = runner.invoke(app, ["plot", str(nc), "-k", "deformed", "--stress", "mises",
                              "-o", str(tmp_path / "d.png"), "--dpi", "30"])
    assert out.exit_code == 0, out.output
    assert drawn[-1].axes[1].get_ylabel().startswith("von Mises stress")
    assert (tmp_path / "d.png").stat().st_size > 1000
    out = runner.invoke(app, ["plot", str(nc), "-k", "timeline", "--stress", "syy"])
    assert out.exit_code == 2 and "--stress applies to --kind deformed" in out.output
