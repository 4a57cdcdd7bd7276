"""The 3D joint in its own plane (``sc.plot_interface_map``): what is drawn equals the result's
CFE data at the chosen states (σ_n = N/A in the colour map, τ = Q/A as arrows in the joint's
axes, the states' colours; exactly, or to 1e-12 after the unit scaling), and the figure reads
(no overlapping or clipped texts: figure_checks.assert_readable)."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.collections import PathCollection, PolyCollection, TriMesh
from matplotlib.colors import to_rgba
from matplotlib.quiver import Quiver

import stepcontact as sc
from figure_checks import assert_readable
from stepcontact.post.common import state_colors
from test_safety3d import pushed_block


@pytest.fixture(scope="module")
def res():
    return sc.solve_static(pushed_block(0.4))


def test_map_draws_the_result_data(res, tmp_path):
    states = (1, len(res.lam) - 2)
    fig = sc.plot_interface_map(res, "joint", states, path=tmp_path / "joint.png")
    assert (tmp_path / "joint.png").stat().st_size > 0
    assert_readable(fig)
    k = np.arange(res.m)
    area = np.asarray(res.cfe["area"])
    axes = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
    assert len(axes) == 4
    for r, i in enumerate(states):
        ax_s, ax_c = axes[2 * r], axes[2 * r + 1]
        sig = np.asarray(res.N)[i, k] / area
        mesh = [c for c in ax_s.collections if isinstance(c, TriMesh | PolyCollection)]
        drawn = np.asarray(mesh[0].get_array(), float)
        scale = 1e3 if np.abs(sig).max() < 1e6 else 1e6
        assert np.abs(drawn * scale - sig).max() <= 1e-12 * np.abs(sig).max()
        quiver = [c for c in ax_s.collections if isinstance(c, Quiver)]
        tau = np.asarray(res.Q_t)[i] / area[:, None]  # joint axes = global x, y here
        if np.abs(tau).max() > 0:
            assert np.abs(quiver[0].U - tau[:, 0]).max() <= 1e-12 * np.abs(tau).max()
            assert np.abs(quiver[0].V - tau[:, 1]).max() <= 1e-12 * np.abs(tau).max()
        pts = [c for c in ax_c.collections if isinstance(c, PathCollection)][0]
        want = [tuple(np.round(to_rgba(c), 6)) for c in state_colors(np.asarray(res.state)[i])]
        got = [tuple(np.round(c, 6)) for c in pts.get_facecolors()]
        assert got == want
        assert f"state {i}" in ax_s.get_title()


def test_map_refuses_2d_results_and_unknown_joints(res):
    with pytest.raises(KeyError, match="'joint'"):
        sc.plot_interface_map(res, "base")
    two_d = sc.solve_static(sc.demo_model())
    with pytest.raises(ValueError, match="plot_interfaces"):
        sc.plot_interface_map(two_d, two_d.interface_names[0])
