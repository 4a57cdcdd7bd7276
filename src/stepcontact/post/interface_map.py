"""A 3D joint drawn in its own plane (:func:`plot_interface_map`): the normal contact stress
σ_n = N/A as a colour map, the shear stress τ = Q/A as arrows, and the state of every CFE
(stick, slip on the faceted cone, open, bonded) — one row of panels per chosen state.

The plane's axes are the joint's (:mod:`stepcontact.results.safety3d`): e₁ the interface's
first tangent (its ``axis``), e₂ = n̄ × e₁, origin at the joint's centroid; coordinates in m,
stresses in MPa, kPa or Pa (whichever reads best; the unit is in the colour bar's label).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from stepcontact.post.common import (
    DPI,
    _at_text,
    _state_handles,
    _state_index,
    _stress_scale,
    figure_path,
    new_figure,
    save_figure,
    state_colors,
)
from stepcontact.results.safety3d import cfe_geometry, joint_frame

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from stepcontact.results.result import StaticResult


def _cfes_of(res: StaticResult, interface: str) -> np.ndarray:
    names = list(res.interface_names)
    if interface not in names:
        raise KeyError(f"no interface '{interface}' (interfaces: "
                       f"{', '.join(map(repr, names)) or 'none'})")
    k = np.flatnonzero(np.asarray(res.cfe["interface"]) == names.index(interface))
    if k.size < 3:
        raise ValueError(f"interface '{interface}' has {k.size} CFEs: a map needs at least 3")
    return k


def plot_interface_map(res: StaticResult, interface: str, states: Sequence[int] = (-1,), *,
                       path: str | os.PathLike[str] | None = None, dpi: float = DPI,
                       arrows: bool = True) -> Figure:
    """The joint ``interface`` of a 3D result in its own plane at each of ``states`` (indices
    of the result's states, default the last): σ_n (colour, linear between the CFEs on a
    Delaunay triangulation of their points), τ = Q/A (arrows, ``arrows``, one scale for all
    states: the largest 0.8 of the CFEs' spacing) and the CFE states.

    Returns the figure; with ``path`` (.png, .pdf, .svg) it is also written (atomically)."""
    from matplotlib.tri import Triangulation

    if getattr(res, "n_t", 1) < 2:
        raise ValueError("plot_interface_map draws the joints of 3D results; for a 2D result "
                         "use plot_interfaces")
    out = figure_path(path, dpi)
    k = _cfes_of(res, interface)
    idx = [_state_index(res, s) for s in states]
    x, _, tan, area = cfe_geometry(res, k, f"plot_interface_map('{interface}')")
    centroid, axes = joint_frame(res, k)
    uv = (x - centroid) @ axes[:2].T  # (K, 2) in the joint's plane, m
    sig = np.asarray(res.N, float)[idx][:, k] / area
    Q = np.asarray(res.Q_t, float)[idx][:, k]  # (S, K, 2)
    tau = np.einsum("skj,kjd,ed->ske", Q, tan, axes[:2]) / area[None, :, None]
    scale, unit = _stress_scale(np.concatenate([sig.ravel(), tau.ravel()]))
    tri = Triangulation(uv[:, 0], uv[:, 1])
    spacing = float(np.sqrt(area.mean()))  # m, about the distance between CFEs
    top = float(np.linalg.norm(tau, axis=2).max(initial=0.0))  # the arrows' common scale
    lim = float(np.abs(sig).max(initial=0.0)) / scale or 1.0
    fig = new_figure(figsize=(10.0, 3.2 * len(idx) + 0.6))
    grid = fig.subplots(len(idx), 2, squeeze=False)
    states_now = np.asarray(res.state, dtype=np.int64)[idx][:, k]
    for r, i in enumerate(idx):
        ax_s, ax_c = grid[r]
        pc = ax_s.tripcolor(tri, sig[r] / scale, shading="gouraud", cmap="RdBu",
                            vmin=-lim, vmax=lim)
        if arrows and top > 0:  # the largest arrow 0.8 of the CFEs' spacing
            ax_s.quiver(uv[:, 0], uv[:, 1], tau[r, :, 0], tau[r, :, 1], color="k",
                        angles="xy", scale_units="xy", scale=top / (0.8 * spacing),
                        width=0.004)
        fig.colorbar(pc, ax=ax_s, shrink=0.85, aspect=25,
                     label=rf"$\sigma_n$ = N/A, {unit} (compression < 0)")
        ax_c.scatter(uv[:, 0], uv[:, 1], c=list(state_colors(states_now[r])), s=60,
                     edgecolors="0.3", linewidths=0.5)
        seg = int(np.asarray(res.segment)[i])
        lam = float(np.asarray(res.lam)[i])
        for ax, what in ((ax_s, r"$\sigma_n$ and $\tau$ (arrows)"), (ax_c, "CFE states")):
            ax.set_xlim(uv[:, 0].min() - spacing, uv[:, 0].max() + spacing)
            ax.set_ylim(uv[:, 1].min() - spacing, uv[:, 1].max() + spacing)
            ax.set_aspect("equal")
            ax.set_xlabel("e₁, m")
            ax.set_ylabel("e₂, m")
            ax.set_title(f"{what} — state {i}: {_at_text(res, seg, lam, short=True)}",
                         fontsize=9)
    handles = _state_handles(states_now.ravel(), bars=True)  # every state drawn
    fig.legend(handles=handles, loc="outside lower center", ncols=max(len(handles), 1),
               fontsize=8, frameon=False)
    fig.suptitle(f"interface '{interface}' in its plane (e₁ = t₁, e₂ = n × t₁)", fontsize=10)
    save_figure(fig, out, dpi)
    return fig


__all__ = ["plot_interface_map"]
