"""Plots of a static result: contact stresses along the interfaces and the load path.

matplotlib is imported inside the functions (``import stepcontact`` stays light).  Figures are
built on the Agg canvas without pyplot: nothing is shown, no global figure registry is touched;
the returned :class:`matplotlib.figure.Figure` displays in Jupyter and can be saved again.

Sign convention of the article: the normal contact stress σ_n = N/A is negative in
compression; the Coulomb condition is |τ| ≤ f |σ_n| with τ = Q/A (eq. (1)).

Example
-------
>>> from stepcontact.plotting import plot_interfaces, plot_load_path
>>> fig = plot_interfaces(res, path="out/interfaces.png")   # doctest: +SKIP
>>> fig = plot_load_path(res, path="out/load_path.pdf")     # doctest: +SKIP
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .enums import ContactState, Transition

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .results import StaticResult

#: colours of the CFE states (open, stick, slip+, slip−, bonded)
STATE_COLORS: dict[ContactState, str] = {
    ContactState.OPEN: "#d9d9d9",
    ContactState.STICK: "#2ca02c",
    ContactState.SLIP_POS: "#d62728",
    ContactState.SLIP_NEG: "#1f77b4",
    ContactState.BONDED: "#9467bd",
}

TRANSITION_MARKERS: dict[Transition, tuple[str, str]] = {
    Transition.CLOSED: ("v", "#2ca02c"),
    Transition.OPENED: ("^", "#7f7f7f"),
    Transition.SLIP_POS: (">", "#d62728"),
    Transition.SLIP_NEG: ("<", "#1f77b4"),
    Transition.STUCK: ("o", "#17becf"),
    Transition.BROKEN: ("X", "#9467bd"),
}

_SUFFIXES = (".png", ".pdf", ".svg")


def _new_figure(**kw) -> Figure:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(layout="constrained", **kw)
    FigureCanvasAgg(fig)
    return fig


def _check_path(path: str | os.PathLike[str] | None) -> Path | None:
    if path is None:
        return None
    p = Path(path)
    if p.suffix.lower() not in _SUFFIXES:
        raise ValueError(
            f"path '{p}': unsupported suffix '{p.suffix}', use one of {', '.join(_SUFFIXES)}"
        )
    return p


def _save(fig: Figure, path: Path | None) -> None:
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=150)


def _stress_scale(values: np.ndarray) -> tuple[float, str]:
    """Divisor and unit label so that stresses (Pa) read well: MPa, kPa or Pa."""
    peak = float(np.max(np.abs(values), initial=0.0)) if values.size else 0.0
    if not np.isfinite(peak):
        peak = 0.0
    if peak >= 1e6:
        return 1e6, "MPa"
    if peak >= 1e3:
        return 1e3, "kPa"
    return 1.0, "Pa"


def _default_lams(res: StaticResult, segment: int | None) -> list[tuple[int, float]]:
    """(segment, λ) at the end of each segment (or of the given one)."""
    segs = np.asarray(res.segment)
    chosen = [segment] if segment is not None else list(dict.fromkeys(segs.tolist()))
    out = []
    for s in chosen:
        idx = np.flatnonzero(segs == s)
        if idx.size == 0:
            raise ValueError(f"segment={s}: no reported state in this segment")
        out.append((int(s), float(res.lam[idx[-1]])))
    return out


def _snapshot(res: StaticResult, segment: int, lam: float) -> dict[str, np.ndarray]:
    """CFE quantities at ``lam`` of ``segment``: :meth:`StaticResult.interpolate`, except that
    at the λ of a reported state the scheme is the one after the last state there."""
    snap = res.interpolate(lam, segment)
    at = np.flatnonzero((np.asarray(res.segment) == segment) & (np.asarray(res.lam) == lam))
    if at.size:
        snap = snap | {"state": np.asarray(res.state)[at[-1]]}
    return snap


def _pattern_of(res: StaticResult, seg: int) -> str:
    if 0 <= seg < len(res.segments):
        return str(res.segments[seg][0])
    return "?"


def plot_interfaces(
    res: StaticResult,
    lams: Sequence[float] | float | None = None,
    path: str | os.PathLike[str] | None = None,
    segment: int | None = None,
) -> Figure:
    """Contact stresses and CFE states along every interface at chosen load factors.

    One column per interface (``res.interface_names``) with three panels against the position
    s along the interface (m):

    * the normal contact stress σ_n = N/A (negative in compression),
    * the tangential stress τ = Q/A with the friction limits ±f|σ_n| dashed (eq. (1)),
    * a strip with the state of each CFE (open / stick / slip+ / slip−) for each λ.

    Stresses are shown in MPa, kPa or Pa (whichever reads best; the unit is in the axis label).
    The values at any λ come from :meth:`StaticResult.interpolate` (exact: the path is linear
    between events); at the λ of a reported state the strip shows the working scheme after
    the last state with that λ (e.g. including an event at the very end of a segment).

    Parameters
    ----------
    res : StaticResult
    lams : float or sequence of float, optional
        Load factors of the active pattern of ``segment``.  Default: the end of every segment
        (or of ``segment`` when given).
    path : str or PathLike, optional
        Save the figure there (``.png``, ``.pdf`` or ``.svg``); parent directories are created.
    segment : int, optional
        Load-program segment the ``lams`` belong to; default the last segment reached.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    out = _check_path(path)
    if lams is None:
        picks = _default_lams(res, segment)
    else:
        seg = int(res.segment[-1]) if segment is None else int(segment)
        lam_list = [float(lams)] if np.isscalar(lams) else [float(v) for v in lams]
        if not lam_list:
            raise ValueError("lams: give at least one load factor (or None for the default)")
        picks = [(seg, v) for v in lam_list]
    snaps = [(s, v, _snapshot(res, s, v)) for s, v in picks]

    names = list(res.interface_names)
    ncol = max(1, len(names))
    fig = _new_figure(figsize=(max(8.5, 4.8 * ncol), 7.5))
    if not names or res.m == 0:
        ax = fig.add_subplot()
        ax.text(0.5, 0.5, "no contact interfaces", ha="center", va="center")
        ax.set_axis_off()
        _save(fig, out)
        return fig

    area = np.asarray(res.cfe["area"], dtype=float)
    fric = np.asarray(res.cfe["friction"], dtype=float)
    pos = np.asarray(res.cfe["s"], dtype=float)
    iface = np.asarray(res.cfe["interface"])
    all_sig = np.concatenate(
        [np.r_[snap["N"] / area, snap["Q"] / area] for _, _, snap in snaps]
    )
    scale, unit = _stress_scale(all_sig)

    codes = [int(c) for c in ContactState]
    cmap = ListedColormap([STATE_COLORS[c] for c in ContactState])
    norm = BoundaryNorm(np.r_[np.array(codes) - 0.5, codes[-1] + 0.5], cmap.N)
    colors = [f"C{j % 10}" for j in range(len(snaps))]
    labels = [f"'{_pattern_of(res, s)}' λ = {v:.4g}" for s, v, _ in snaps]

    axes = fig.subplots(3, ncol, squeeze=False, sharex="col", height_ratios=[3, 3, 1.2])
    for c, name in enumerate(names):
        k = np.flatnonzero(iface == c)
        ax_n, ax_t, ax_s = axes[0, c], axes[1, c], axes[2, c]
        ax_n.set_title(f"interface '{name}'")
        if k.size == 0:
            ax_n.text(0.5, 0.5, "no CFEs", ha="center", va="center", transform=ax_n.transAxes)
            continue
        k = k[np.argsort(pos[k], kind="stable")]
        s = pos[k]
        mk = "o" if k.size <= 40 else None
        for j, (_, _, snap) in enumerate(snaps):
            sig = snap["N"][k] / area[k] / scale
            tau = snap["Q"][k] / area[k] / scale
            lim = fric[k] * np.abs(sig)
            ax_n.plot(s, sig, color=colors[j], marker=mk, ms=3, lw=1.4)
            ax_t.plot(s, tau, color=colors[j], marker=mk, ms=3, lw=1.4)
            ax_t.plot(s, lim, color=colors[j], ls="--", lw=0.9)
            ax_t.plot(s, -lim, color=colors[j], ls="--", lw=0.9)
        for ax in (ax_n, ax_t):
            ax.axhline(0.0, color="k", lw=0.6)
            ax.grid(True, alpha=0.3)
        ax_n.set_ylabel(rf"$\sigma_n$ = N/A, {unit} (compression < 0)")
        ax_t.set_ylabel(rf"$\tau$ = Q/A, {unit};  $\pm f|\sigma_n|$ dashed")

        # state strip: one row per λ, one cell per CFE between mid-points
        if s.size > 1:
            mid = 0.5 * (s[1:] + s[:-1])
            edges = np.r_[s[0] - (mid[0] - s[0]), mid, s[-1] + (s[-1] - mid[-1])]
        else:
            edges = np.array([s[0] - 0.5, s[0] + 0.5])
        if np.any(np.diff(edges) <= 0):  # coincident positions: equal-width cells by order
            edges = np.arange(k.size + 1) - 0.5
        grid = np.array([np.asarray(snap["state"])[k] for _, _, snap in snaps], dtype=float)
        ax_s.pcolormesh(
            edges, np.arange(len(snaps) + 1) - 0.5, grid, cmap=cmap, norm=norm,
            edgecolors="white", linewidth=0.3,
        )
        ax_s.set_yticks(np.arange(len(snaps)), [f"λ={v:.3g}" for _, v, _ in snaps], fontsize=7)
        ax_s.set_ylim(len(snaps) - 0.5, -0.5)
        ax_s.set_xlabel("position s along the interface, m")
        if c == 0:
            ax_s.set_ylabel("state")

    handles = [Line2D([], [], color=colors[j], lw=1.6, label=labels[j]) for j in range(len(snaps))]
    shown = {int(v) for _, _, snap in snaps for v in np.asarray(snap["state"])}
    handles += [
        Patch(facecolor=STATE_COLORS[cs], edgecolor="0.4", label=cs.label)
        for cs in ContactState
        if cs is not ContactState.BONDED or int(cs) in shown
    ]
    fig.legend(handles=handles, loc="outside lower center",
               ncol=min(len(handles), max(4, 3 * ncol)), fontsize=8, frameon=False)
    by_pattern: dict[str, list[str]] = {}
    for sg, v, _ in snaps:
        by_pattern.setdefault(_pattern_of(res, sg), []).append(f"{v:.4g}")
    fig.suptitle(
        "Contact stresses at "
        + ";\n".join(f"pattern '{p}' λ = {', '.join(v)}" for p, v in by_pattern.items())
    )
    _save(fig, out)
    return fig


def plot_load_path(
    res: StaticResult, path: str | os.PathLike[str] | None = None
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

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.lines import Line2D
    from matplotlib.ticker import MaxNLocator

    out = _check_path(path)
    fig = _new_figure(figsize=(8.0, 6.5))
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
    ax_l.set_ylabel("load factor λ of the active pattern")
    ax_l.grid(True, alpha=0.3)
    n_ev = np.array([sum(1 for e in res.events if e.state <= k) for k in i])
    if res.n_states:
        top = ax_l.secondary_xaxis("top")
        ticks = np.linspace(0, res.n_states - 1, min(res.n_states, 8)).round().astype(int)
        ticks = np.unique(ticks)
        top.set_xticks(ticks, [str(n_ev[t]) for t in ticks])
        top.set_xlabel("events so far")

    st = np.asarray(res.state)
    counts = np.array([(st == int(cs)).sum(axis=1) for cs in ContactState]) if st.size else None
    present = [cs for cs in ContactState if counts is not None and counts[int(cs)].any()]
    if counts is not None and present:
        bottom = np.zeros(res.n_states)
        for cs in present:  # the scheme after state i, as a bar of width 1 centred on i
            ax_c.bar(i, counts[int(cs)], width=1.0, bottom=bottom, color=STATE_COLORS[cs],
                     edgecolor="0.3", linewidth=0.3, label=cs.label)
            bottom += counts[int(cs)]
        ax_c.legend(fontsize=8, loc="upper left", ncol=len(present))
        ax_c.set_ylim(0, res.m * 1.15)
    ax_c.set_xlim(-0.5, max(res.n_states, 1) - 0.5)
    ax_c.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax_c.set_ylabel("number of CFEs")
    ax_c.set_xlabel("reported state i")
    ax_c.grid(True, alpha=0.3)
    fig.suptitle(
        f"Load path — {res.status.value}, {len(res.events)} events, {res.m} CFEs"
    )
    _save(fig, out)
    return fig


__all__ = ["STATE_COLORS", "TRANSITION_MARKERS", "plot_interfaces", "plot_load_path"]
