"""Figures along the load path: the load factor and the CFE state counts at every reported
state (:func:`plot_load_path`), the load–displacement (or load–reaction) curve of one node
(:func:`plot_load_displacement`) and which CFE changed to which state at which λ
(:func:`plot_event_timeline`).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from stepcontact.enums import FACET_SLIP, ContactState, Transition
from stepcontact.post.common import (
    DPI,
    FACETED_SLIP_COLOR,
    FACETED_SLIP_LABEL,
    NOT_BUILT,
    STATE_COLORS,
    TRANSITION_MARKERS,
    _axis_text,
    _force_scale,
    _is_level,
    _lam_text,
    _legend_below,
    _length_scale,
    _made,
    _path_fraction,
    _pattern_of,
    _say_only,
    _segment_chain,
    _segment_stage,
    _segments_reached,
    _stage_text,
    _state_handles,
    _transition_handles,
    figure_path,
    new_figure,
    save_figure,
    state_colors,
)
from stepcontact.post.mesh import _all_fields, _geometry, _most_moving

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from stepcontact.results.result import StaticResult

def _mark_stages(res: StaticResult, ax, axes_lines: Sequence) -> None:
    """The construction stages along the reported-state axis: a solid line where each stage
    starts (on ``axes_lines``) and its name at the top of ``ax``."""
    stage = getattr(res, "stage", None)
    if stage is None:
        return
    stage = np.asarray(stage, int)
    # stages a few states apart: their names on staggered rows (estimated widths, 8 pt text
    # about 0.6 em a character, over the axes' width)
    width = max(float(ax.get_position().width * ax.figure.get_figwidth()) * 72.0, 1.0)
    span = max(len(stage), 1)
    ends: list[float] = []  # right end of the last name on each row, in states
    for k in dict.fromkeys(stage.tolist()):
        first = int(np.flatnonzero(stage == k)[0])
        if first > 0:
            for a in axes_lines:
                a.axvline(first - 0.5, color="0.25", lw=1.0)
        text = f" {_stage_text(res, k)}"
        row = next((r for r, e in enumerate(ends) if e <= first - 0.5), len(ends))
        end = first - 0.5 + 1.1 * len(text) * 0.6 * 8.0 / width * span
        ends[row:row + 1] = [end]
        ax.text(first - 0.5, 0.98 - 0.07 * row, text, transform=ax.get_xaxis_transform(),
                ha="left", va="top", fontsize=8, color="0.25", gid="stage_label")


def plot_load_path(
    res: StaticResult, path: str | os.PathLike[str] | None = None, *, dpi: float = DPI
) -> Figure:
    """The load path: λ at each reported state and the number of CFEs in each state.

    Top: the load factor λ of the active pattern against the reported state index, one line
    per segment, events marked by their transition (the number of events so far on the top
    axis).  Bottom: stacked bars of the numbers of open / stick / slip+ / slip− CFEs in the
    working scheme after each state.

    Parameters
    ----------
    res : StaticResult
    path : str or PathLike, optional
        Save the figure there (``.png``, ``.pdf`` or ``.svg``); parent directories are created.
    dpi : float
        Resolution of a saved raster figure, dots per inch.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.lines import Line2D
    from matplotlib.ticker import MaxNLocator

    out = figure_path(path, dpi)
    fig = new_figure(figsize=(8.0, 6.5))
    ax_l, ax_c = fig.subplots(2, 1, sharex=True, height_ratios=[3, 2])
    i = np.arange(res.n_states)
    segs = np.asarray(res.segment)
    lam = np.asarray(res.lam, dtype=float)

    seg_handles = []
    for j, s in enumerate(dict.fromkeys(segs.tolist())):
        idx = np.flatnonzero(segs == s)
        x, y = i[idx], lam[idx]
        if idx[0] > 0 and 0 <= s < len(res.segments):  # the segment starts at the state before
            x, y = np.r_[idx[0] - 1, x], np.r_[res.segments[s][1], y]
        ax_l.plot(x, y, color=f"C{j % 10}", lw=1.2, marker=".", ms=4)
        seg_handles.append(
            Line2D([], [], color=f"C{j % 10}", lw=1.2,
                   label=f"segment {s}: '{_pattern_of(res, int(s))}'")
        )
        if idx[0] > 0:
            ax_l.axvline(idx[0] - 0.5, color="0.6", lw=0.8, ls=":")
            ax_c.axvline(idx[0] - 0.5, color="0.6", lw=0.8, ls=":")
    seen: dict[Transition, None] = {}
    for e in res.events:
        marker, color = TRANSITION_MARKERS[e.transition]
        ax_l.plot([e.state], [e.lam], ls="none", marker=marker, color=color, ms=7, mec="k",
                  mew=0.4)
        seen[e.transition] = None
    ev_handles = [
        Line2D([], [], ls="none", marker=TRANSITION_MARKERS[t][0], color=TRANSITION_MARKERS[t][1],
               mec="k", mew=0.4, label=t.value)
        for t in seen
    ]
    ax_l.legend(handles=seg_handles + ev_handles, fontsize=8, loc="best")
    levels = sorted({_pattern_of(res, sg) for sg in _segments_reached(res) if _is_level(res, sg)})
    ax_l.set_ylabel("load factor λ of the active pattern"
                    + (f"\n(water level h in m for {', '.join(map(repr, levels))})"
                       if levels else ""))
    ax_l.grid(True, alpha=0.3)
    n_ev = np.array([sum(1 for e in res.events if e.state <= k) for k in i])
    if res.n_states:
        top = ax_l.secondary_xaxis("top")
        ticks = np.linspace(0, res.n_states - 1, min(res.n_states, 8)).round().astype(int)
        ticks = np.unique(ticks)
        top.set_xticks(ticks, [str(n_ev[t]) for t in ticks])
        top.set_xlabel("events so far")

    st = np.asarray(res.state)
    made = _made(res)  # construction stages: CFEs not yet made are counted apart
    # the 2D states, then a faceted cone's slip (3D: every facet and vertex as one)
    classes = [(cs.label, STATE_COLORS[cs], st == int(cs)) for cs in ContactState]
    classes.append((FACETED_SLIP_LABEL, FACETED_SLIP_COLOR, st >= FACET_SLIP))
    counts = (np.array([(sel & (True if made is None else made)).sum(axis=1)
                        for _, _, sel in classes]) if st.size else None)
    present = [j for j in range(len(classes)) if counts is not None and counts[j].any()]
    if counts is not None and present:
        bottom = np.zeros(res.n_states)
        for j in present:  # the scheme after state i, as a bar of width 1 centred on i
            ax_c.bar(i, counts[j], width=1.0, bottom=bottom, color=classes[j][1],
                     edgecolor="0.3", linewidth=0.3, label=classes[j][0])
            bottom += counts[j]
        if made is not None and not made.all():
            ax_c.bar(i, (~made).sum(axis=1), width=1.0, bottom=bottom, color="white",
                     hatch="////", edgecolor="0.6", linewidth=0.3, label=NOT_BUILT)
        ax_c.legend(fontsize=8, loc="upper left",
                    ncol=len(present) + int(made is not None and not made.all()))
        ax_c.set_ylim(0, res.m * 1.15)
    ax_c.set_xlim(-0.5, max(res.n_states, 1) - 0.5)
    _mark_stages(res, ax_l, (ax_l, ax_c))
    ax_c.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax_c.set_ylabel("number of CFEs")
    ax_c.set_xlabel("reported state i")
    ax_c.grid(True, alpha=0.3)
    fig.suptitle(
        f"Load path — {res.status.value}, {len(res.events)} events, {res.m} CFEs"
    )
    save_figure(fig, out, dpi)
    return fig


_DOFS: dict[str, int] = {"x": 0, "ux": 0, "y": 1, "uy": 1, "rz": 2}
#: a 3D result's nodal DOFs (continua: x, y, z; space frames also rx, ry, rz)
_DOFS_3D: dict[str, int] = {"x": 0, "ux": 0, "y": 1, "uy": 1, "z": 2, "uz": 2, "rx": 3,
                            "ry": 4, "rz": 5}


_DOF_LABEL = ("$u_x$", "$u_y$", r"$\varphi_z$")
_DOF_LABEL_3D = ("$u_x$", "$u_y$", "$u_z$", r"$\varphi_x$", r"$\varphi_y$", r"$\varphi_z$")


def _in_space(res: StaticResult) -> bool:
    """The result's nodes have three coordinates (a 3D model)."""
    pts = (res.geometry or {}).get("points")
    return pts is not None and np.ndim(pts) == 2 and np.shape(pts)[1] == 3


def _mark_equilibrium_lost(ax, x: float, y: float, lam: float, level: bool = False) -> None:
    """The star and text "equilibrium lost, λ = …" (``h = … m`` when the parameter is a
    water level) at (x, y) of a λ–u curve."""
    ax.plot([x], [y], ls="none", marker="*", ms=15, mfc="gold", mec="k", mew=0.6, zorder=5,
            gid="equilibrium_lost")
    at = f"h = {_lam_text(lam)} m" if level else f"λ = {_lam_text(lam)}"
    ax.annotate(f"equilibrium lost, {at}", (x, y), xytext=(0.98, 0.04),
                textcoords="axes fraction", ha="right", va="bottom", fontsize=8,
                arrowprops={"arrowstyle": "->", "color": "0.4", "lw": 0.7},
                bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "0.6", "alpha": 0.9})


def _curve_quantity(res: StaticResult, node: int | Sequence[float] | None,
                    body: str | None, dof: str | None, reaction: str | None
                    ) -> tuple[np.ndarray, float, str]:
    """(values at every reported state, the divisor of their unit, the axis label) of the
    quantity :func:`plot_load_displacement` draws: the reaction of support ``reaction``
    along ``dof`` (N, kN, MN; N·m … for rz), or the displacement u_x, u_y (m, mm, µm) or
    rotation φ_z (rad) of ``node`` (default the node and direction that move most)."""
    space = _in_space(res)
    comp = -1 if dof is None else (_DOFS_3D if space else _DOFS)[dof]
    if reaction is not None:
        try:
            u = res.reaction(reaction, dof)
        except KeyError as e:
            raise ValueError(str(e.args[0])) from None
        turn = comp >= 3 if space else comp == 2
        div, unit = _force_scale(u, 2 if turn else 0)
        return u, div, f"reaction of '{reaction}' along {dof} (on the structure), {unit}"
    points, dof_of, bodies = _geometry(res)
    if comp >= dof_of.shape[1]:
        raise ValueError(f"dof={dof!r}: the nodes of this result move along 'x', 'y', 'z' "
                         "only (rotations are DOFs of space frames)")
    U = _all_fields(res)
    peak = np.abs(U).max(axis=0, initial=0.0)  # |u| of every DOF over the path
    k, comp = _most_moving(res, node, body, comp, peak)
    u = U[:, dof_of[k, comp]]
    turn = comp >= 3 if space else comp == 2
    div, unit = (1.0, "rad") if turn else _length_scale(u)
    owner = next((str(b["name"]) for b in bodies if np.any(np.asarray(b["cells"]) == k)),
                 "?")
    why = ("; moves most over the path" if node is None and dof is None else
           "; largest |u| over the path" if node is None else "")
    at = ", ".join(f"{c} = {v:.4g} m" for c, v in zip("xyz", points[k], strict=False))
    label = (_DOF_LABEL_3D if space else _DOF_LABEL)[comp]
    return u, div, f"{label} of node {k} ('{owner}', {at}{why}), {unit}"


def _draw_segment_curve(ax, res: StaticResult, j: int, s: int, x: np.ndarray,
                        along_path: bool) -> list[Transition]:
    """The curve of segment ``s`` (the ``j``-th reached): ``x`` (the quantity at every
    reported state, in its unit) against λ of its pattern (``along_path``: the load-path
    parameter t), its events marked, a lost equilibrium starred; the transitions marked."""
    idx, lam = _segment_chain(res, s)
    if along_path:
        lam = s + _path_fraction(lam)
    stage = _segment_stage(res, s)
    ax.plot(x[idx], lam, color=f"C{j % 10}", lw=1.3, marker=".", ms=4,
            label=f"segment {s}: '{_pattern_of(res, s)}'"
            + ("" if stage is None else f" ({_stage_text(res, stage)})"))
    if not along_path and stage is not None:
        ax.set_title(_stage_text(res, stage), fontsize=8, loc="left")
    y_of = dict(zip(idx.tolist(), lam.tolist(), strict=True))
    marks = {(e.state, e.transition) for e in res.events if e.segment == s}
    seen = []
    for i, tr in sorted(marks, key=lambda m: (m[0], m[1].value)):
        marker, color = TRANSITION_MARKERS[tr]
        ax.plot([x[i]], [y_of.get(i, float(res.lam[i]))], ls="none",
                marker=marker, color=color, ms=8, mec="k", mew=0.4, zorder=4)
        seen.append(tr)
    if not along_path:
        ax.set_ylabel(_axis_text(res, s))
    lost = next((mu.equilibrium_lost for mu in res.multipliers
                 if mu.segment == s and mu.equilibrium_lost is not None), None)
    if lost is not None and idx.size:
        _mark_equilibrium_lost(ax, x[idx[-1]], lam[-1] if along_path else lost, lost,
                               _is_level(res, s))
    return seen


def plot_load_displacement(
    res: StaticResult,
    node: int | Sequence[float] | None = None,
    dof: str | None = None,
    path: str | os.PathLike[str] | None = None,
    *,
    body: str | None = None,
    axis: str = "lam",
    dpi: float = DPI,
    reaction: str | None = None,
) -> Figure:
    """Load factor against the displacement of one node (or a support reaction), with the
    events marked.

    Between consecutive reported states the working scheme is fixed and the structure linear,
    so the curve through the states is exact.  Each event is marked at its state by its
    transition.  Needs the displacements of every state: an in-memory result (or one given its
    model with ``res.recover_fields(model)``) recomputes those not stored in one solve; a
    result loaded from a file without its model has them only with ``store_fields='all'``.

    By default the curve is that of the node and direction (u_x or u_y) that moves most over
    the whole path (the largest |u| at any reported state), stated in the axis label.  Where a
    segment lost equilibrium (``res.multipliers[s].equilibrium_lost``) its last state is marked
    by a star and the text "equilibrium lost, λ = …".

    Parameters
    ----------
    res : StaticResult
    node : int or (x, y), optional
        Global node index, or coordinates in m (the nearest node; ``body`` chooses between
        coincident nodes of different bodies; (x, y, z) in 3D).  Default: the node with the
        largest |u| in ``dof`` over the path (at any reported state).
    dof : "x", "y" or "rz", optional
        Displacement component u_x, u_y (m) or the rotation φ_z of a frame node (rad); in 3D
        "x", "y", "z" (and "rx", "ry", "rz" of a space frame's node).  Default: the one of
        u_x, u_y (3D: u_x, u_y, u_z) that moves most over the path (of ``node``, or of the
        node that moves most); for ``reaction``, "y".
    path : str or PathLike, optional
        Save the figure there (``.png``, ``.pdf`` or ``.svg``); parent directories are created.
    body : str, optional
        Body the node belongs to.
    axis : "lam" or "path"
        ``lam``: one panel per segment with the load factor λ of its pattern; ``path``: one
        panel with the load-path parameter t = segment + |λ − λ_start| / (the λ range the
        segment covered), so that every segment reached spans one unit.
    dpi : float
        Resolution of a saved raster figure, dots per inch.
    reaction : str, optional
        Plot against the resultant reaction of this support (or of the DOFs a load pattern
        prescribes) along ``dof`` instead of a displacement: N (kN, MN), or N·m for rz.  Known
        at every state, so no stored fields are needed.

    Returns
    -------
    matplotlib.figure.Figure
    """
    out = figure_path(path, dpi)
    known = _DOFS_3D if _in_space(res) else _DOFS
    if dof is not None and dof not in known:
        raise ValueError(f"dof={dof!r}: use " + ("'x', 'y', 'z' (or 'rx', 'ry', 'rz' of a "
                         "space frame's node)" if known is _DOFS_3D else "'x', 'y' or 'rz'"))
    if axis not in ("lam", "path"):
        raise ValueError(f"axis={axis!r}: use 'lam' or 'path'")
    if reaction is not None and dof is None:
        dof = "y"
    u, div, xlabel = _curve_quantity(res, node, body, dof, reaction)
    segs = _segments_reached(res)
    panels = len(segs) if axis == "lam" else 1
    fig = new_figure(figsize=(7.5, min(3.0 * panels + 1.2, 11.0)))
    axes = np.atleast_1d(fig.subplots(panels, 1, sharex=True, squeeze=False)[:, 0])
    x = u / div  # in its unit
    seen: list[Transition] = []
    for j, s in enumerate(segs):
        seen += _draw_segment_curve(axes[j if axis == "lam" else 0], res, j, s, x,
                                    axis == "path")
    for ax in axes:
        ax.grid(True, alpha=0.3)
        ax.axvline(0.0, color="k", lw=0.5)
    if axis == "path":
        axes[0].set_ylabel("load-path parameter t")
        axes[0].legend(fontsize=8, loc="best")
    axes[-1].set_xlabel(xlabel)
    if seen:
        _legend_below(fig, _transition_handles(seen), len(set(seen)), fontsize=8,
                      frameon=False, title="events")
    what = "reaction" if reaction is not None else "displacement"
    fig.suptitle(f"Load–{what} — {res.status.value}, {len(res.events)} events")
    save_figure(fig, out, dpi)
    return fig


def _draw_state_bars(ax, res: StaticResult, idx: np.ndarray, lam: np.ndarray, k: np.ndarray,
                     made: np.ndarray | None) -> None:
    """Every CFE ``k`` as a horizontal bar at its position s, coloured by its state between
    consecutive reported states ``idx`` (at ``lam``); none where it is not yet made."""
    from matplotlib.collections import LineCollection

    pos = np.asarray(res.cfe["s"], dtype=float)
    st = np.asarray(res.state)
    lw = float(np.clip(150.0 / max(k.size, 1), 0.8, 6.0))
    shape = (idx.size - 1, k.size)  # (intervals between states, CFEs)
    y = np.broadcast_to(pos[k][None, :], shape)
    ends = [np.stack([np.broadcast_to(v[:, None], shape), y], -1)
            for v in (lam[:-1], lam[1:])]
    segments = np.stack(ends, axis=2)  # (intervals, CFEs, 2 ends, xy)
    # CFEs not yet made (construction stages): no bar
    on = (np.ones(shape, bool) if made is None else made[idx[:-1]][:, k]).ravel()
    ax.add_collection(LineCollection(
        segments.reshape(-1, 2, 2)[on],
        colors=state_colors(st[idx[:-1]][:, k].ravel())[on],
        linewidths=lw, capstyle="butt", zorder=1,
    ))


def _timeline_title(res: StaticResult, s: int, lam: np.ndarray) -> str:
    """``segment 1: push λ=0 → 23 544`` (``h=… → … m`` for a water level, ``t = … → … s``
    for a dynamic result), below its stage's name for a staged result."""
    span = (f"t = {lam[0]:.6g} → {lam[-1]:.6g} s"
            if getattr(res, "path_axis", "lam") == "time" else
            f"segment {s}: {_pattern_of(res, s)} h={_lam_text(lam[0])} → "
            f"{_lam_text(lam[-1])} m" if _is_level(res, s) else
            f"segment {s}: {_pattern_of(res, s)} λ={_lam_text(lam[0])} → "
            f"{_lam_text(lam[-1])}")
    stage = _segment_stage(res, s)
    return span if stage is None else f"{_stage_text(res, stage)}\n{span}"


def plot_event_timeline(
    res: StaticResult, path: str | os.PathLike[str] | None = None, *, dpi: float = DPI
) -> Figure:
    """Which CFE changed to which state at which λ.

    One row of panels per interface (y: position s along it, m) and one column per segment
    reached (x: λ of its pattern; titled with the pattern and the λ range it covered, e.g.
    ``segment 1: push λ=0 → 23 544``).  Every CFE is a horizontal bar coloured by its state between
    consecutive reported states; each event is a marker at (λ, s) shaped and coloured by its
    transition.

    Parameters
    ----------
    res : StaticResult
    path : str or PathLike, optional
        Save the figure there (``.png``, ``.pdf`` or ``.svg``); parent directories are created.
    dpi : float
        Resolution of a saved raster figure, dots per inch.

    Returns
    -------
    matplotlib.figure.Figure
    """
    out = figure_path(path, dpi)
    names = list(res.interface_names)
    segs = _segments_reached(res)
    nrow, ncol = max(1, len(names)), max(1, len(segs))
    fig = new_figure(figsize=(min(3.8 * ncol + 2.0, 16.0), min(2.6 * nrow + 1.6, 12.0)))
    fig.suptitle(f"Event timeline — {len(res.events)} events, {res.m} CFEs, "
                 f"{res.status.value}")
    if not names or res.m == 0 or not segs:
        _say_only(fig, "no contact interfaces")
        save_figure(fig, out, dpi)
        return fig
    axes = fig.subplots(nrow, ncol, squeeze=False, sharey="row")
    iface = np.asarray(res.cfe["interface"])
    pos = np.asarray(res.cfe["s"], dtype=float)
    st = np.asarray(res.state)
    made = _made(res)
    for c, s in enumerate(segs):
        idx, lam = _segment_chain(res, s)
        for r, name in enumerate(names):
            ax = axes[r, c]
            k = np.flatnonzero(iface == r)
            if k.size and idx.size > 1:
                _draw_state_bars(ax, res, idx, lam, k, made)
            for e in res.events:
                if e.segment == s and e.interface == name:
                    marker, color = TRANSITION_MARKERS[e.transition]
                    ax.plot([e.lam], [e.position], ls="none", marker=marker, color=color,
                            ms=7, mec="k", mew=0.4, zorder=3)
            ax.autoscale_view()
            if made is not None and k.size and idx.size and not made[idx][:, k].any():
                # the interface is not made yet in this segment's stage
                if np.ptp(lam) > 0:
                    ax.set_xlim(lam.min(), lam.max())
                ax.text(0.5, 0.5, NOT_BUILT, ha="center", va="center", color="0.4",
                        transform=ax.transAxes, gid="not_built")
            if k.size:
                span = np.ptp(pos[k]) or 1.0
                ax.set_ylim(pos[k].min() - 0.05 * span, pos[k].max() + 0.05 * span)
            if 0 <= s < len(res.segments) and res.segments[s][2] < res.segments[s][1]:
                ax.invert_xaxis()  # unloading: λ decreases along the path
            ax.grid(True, alpha=0.3)
            if r == 0 and lam.size:
                ax.set_title(_timeline_title(res, s, lam), fontsize=9)
            if r == nrow - 1:
                ax.set_xlabel(_axis_text(res, s))
            if c == 0:
                ax.set_ylabel(f"s along '{name}', m")
    handles = _state_handles(st.ravel() if made is None else st[made], bars=True)
    handles += _transition_handles(
        [e.transition for e in res.events], prefix="→ ")
    _legend_below(fig, handles, 6, fontsize=8, frameon=False)
    save_figure(fig, out, dpi)
    return fig


__all__ = [
    "plot_event_timeline",
    "plot_load_displacement",
    "plot_load_path",
]
