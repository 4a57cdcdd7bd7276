"""The safety of the joints along the load path (:func:`plot_safety`): eccentricity of the
normal resultant, sliding factor and open length of each interface
(:meth:`~stepcontact.results.result.StaticResult.interface_safety`), one column of panels per
run of segments on one parameter axis (a load factor λ or a water level h), the limits and
their margins over a design value in the legend.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from stepcontact.post.common import (
    DPI,
    _at_text,
    _axis_text,
    _is_level,
    _lam_text,
    _legend_below,
    _made,
    _pattern_of,
    _ranges,
    _say_only,
    _segment_chain,
    _segment_stage,
    _segments_reached,
    _stage_text,
    figure_path,
    new_figure,
    save_figure,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from stepcontact.results.result import StaticResult

#: at most this many panels (groups of segments) side by side in :func:`plot_safety`
MAX_SAFETY_PANELS = 6


def _segment_groups(res: StaticResult, segs: Sequence[int]) -> list[list[int]]:
    """Consecutive segments that continue one another on one parameter axis: the same
    pattern, each starting where the previous one ended, in the same direction (the level
    raised 0 → 28 m then 28 → 60 m is one axis; the weight 0 → 1 before it another)."""
    groups: list[list[int]] = []
    for sg in segs:
        if groups and 0 <= sg < len(res.segments):
            prev = groups[-1][-1]
            if 0 <= prev < len(res.segments):
                (p0, a0, b0), (p1, a1, b1) = res.segments[prev], res.segments[sg]
                if p0 == p1 and a1 == b0 and (b0 - a0) * (b1 - a1) > 0:
                    groups[-1].append(sg)
                    continue
        groups.append([sg])
    return groups


def _loaded(sf) -> np.ndarray:
    """(n_states,) bool: the joint carries a normal force beyond round-off (|ΣN| above
    1e-9 of its largest along the path): its eccentricity and sliding factor mean
    something."""
    n = np.abs(np.asarray(sf.normal_force, dtype=float))
    return n > 1e-9 * float(n.max(initial=0.0))


def _limit_text(res: StaticResult, sf, what: str, v: float, margin: float | None,
                built: np.ndarray) -> str | None:
    """``slides at h = 11.67 m (h/h_d = 1.17)``: a limit of :class:`InterfaceSafety` in the
    unit of the segment where it is reached, and its load margin over the design value;
    None when it is reached only at states where the interface is not built (``built``:
    (n_states,) bool)."""
    hit = np.flatnonzero(np.asarray(sf.lam) == v)
    if hit.size and not built[hit].any():
        return None
    hit = hit[built[hit]]
    if hit.size and not _loaded(sf)[hit].any():
        return None  # a "limit" of round-off forces (a joint just made, stress-free)
    seg = int(res.segment[hit[0]]) if hit.size else int(res.segment[-1])
    if _pattern_of(res, seg) != _pattern_of(res, int(res.segment[-1])):
        margin = None  # the design value is one of the last segment's parameter
    level = _is_level(res, seg)
    at = f"h = {v:.4g} m" if level else f"λ = {v:.4g}"
    ratio = "h/h_d" if level else "λ/λ_d"
    return f"{what} at {at}" + ("" if margin is None else f" ({ratio} = {margin:.3g})")


def _draw_safety_column(res: StaticResult, axes, group: list[int], safety: list,
                        built: list[np.ndarray], wide: bool, design: float | None,
                        pattern: str) -> float:
    """One column of :func:`plot_safety` (``axes``: eccentricity, sliding factor, open
    length) for the run of segments ``group``; the largest sliding factor drawn (at least
    1)."""
    chains = [_segment_chain(res, sg) for sg in group]
    idx = np.concatenate([c[0] for c in chains])
    lam = np.concatenate([c[1] for c in chains])
    ax_e, ax_s, ax_o = axes
    peak = 1.0
    for c, sf in enumerate(safety):
        color = f"C{c % 10}"
        B = sf.length if sf.length > 0 else 1.0
        on = built[c][idx]
        loaded = on & _loaded(sf)[idx]  # e and the sliding factor of round-off: none
        ax_e.plot(lam, np.where(loaded, sf.eccentricity[idx] / B, np.nan), color=color,
                  marker=".", ms=4)
        sliding = np.where(np.isfinite(sf.sliding_factor[idx]) & loaded,
                           sf.sliding_factor[idx], np.nan)
        ax_s.plot(lam, sliding, color=color, marker=".", ms=4)
        if np.isfinite(sliding).any():
            peak = max(peak, float(np.nanmax(sliding)))
        ax_o.plot(lam, np.where(on, sf.open_length[idx], np.nan), color=color,
                  marker=".", ms=4, drawstyle="steps-post")  # open until the next state
    ax_e.axhspan(-1 / 6, 1 / 6, color="0.9", zorder=0)
    ax_e.axhline(0.0, color="k", lw=0.5)
    ax_s.axhline(1.0, color="k", lw=0.8, ls="--")
    for ax in (ax_e, ax_s, ax_o):
        ax.grid(True, alpha=0.3)
        if design is not None and _pattern_of(res, group[0]) == pattern:
            ax.axvline(design, color="0.3", lw=1.0, ls=":", gid="design")
    stage = _segment_stage(res, group[0])
    what = (f"segment {group[0]}" if len(group) == 1
            else f"segments {group[0]}–{group[-1]}")
    span = (_at_text(res, group[0], float(lam[0]), short=True) + " → "
            + (f"{_lam_text(lam[-1])} m" if _is_level(res, group[0])
               else _lam_text(lam[-1])))
    title = f"{what}:\n{span}" if not wide else f"{what}: {span}"
    if stage is not None:
        title = f"{_stage_text(res, stage)}\n{title}"
    ax_e.set_title(title, fontsize=8)
    ax_o.set_xlabel(_axis_text(res, group[0]) if wide
                    else _axis_text(res, group[0]).replace(" of ", "\nof ", 1))
    if 0 <= group[0] < len(res.segments) and (
            res.segments[group[0]][2] < res.segments[group[0]][1]):
        ax_o.invert_xaxis()
    return peak


def _safety_legend(fig: Figure, res: StaticResult, safety: list, built: list[np.ndarray],
                   design: float | None, last: int, pattern: str) -> None:
    """The legend below the panels: each interface with its limits and margins, the kern
    and the design value."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles = []
    for c, sf in enumerate(safety):
        limits = [t for what, v, margin in (("slides", sf.lam_sliding, sf.margin_sliding),
                                            ("overturns", sf.lam_overturning,
                                             sf.margin_overturning))
                  if v is not None
                  and (t := _limit_text(res, sf, what, v, margin, built[c])) is not None]
        handles.append(Line2D([], [], color=f"C{c % 10}", marker=".", ms=4,
                              label=f"'{sf.interface}'"
                              + (": " + ", ".join(limits) if limits else "")))
    handles.append(Patch(facecolor="0.9", label="kern |e| ≤ B/6"))
    if design is not None:
        level = _is_level(res, last)
        handles.append(Line2D([], [], color="0.3", lw=1.0, ls=":",
                              label=f"design level h_d = {design:g} m" if level
                              else f"design λ_d = {design:g} of '{pattern}'"))
    _legend_below(fig, handles, 2, fontsize=8, frameon=False)


def plot_safety(
    res: StaticResult,
    interfaces: Sequence[str] | None = None,
    path: str | os.PathLike[str] | None = None,
    *,
    segment: int | None = None,
    design: float | None = None,
    dpi: float = DPI,
) -> Figure:
    """Safety of the joints along the whole load path: eccentricity of the normal resultant
    (over the joint's length B, with the kern |e| ≤ B/6 shaded), sliding factor f·|ΣN|/|ΣQ|
    (1: the joint slides) and open length (m).

    Every segment reached is drawn against its own parameter, one column of panels per run
    of segments that continue one another (the same pattern, in the same direction): a load
    factor λ, or the water level h in m when the pattern's factor is a level — e.g. the
    weight λ = 0 → 1 in a narrow column, then the reservoir h = 0 → 40 m in a wide one on a
    level axis.  The rows share their y axes.  The limits (the λ or level at which each
    joint slides or its body overturns) and their load margins over ``design`` are in the
    legend; ``design`` is drawn as a vertical line in the columns of the last segment's
    pattern.  At most :data:`MAX_SAFETY_PANELS` columns (the last ones) are drawn.  States
    where a joint is not built, or carries only round-off forces (|ΣN| ≤ 1e-9 of its largest,
    e.g. a lift joint just made stress-free), have no eccentricity or sliding factor drawn,
    and no limit is read there.

    See :meth:`~stepcontact.results.result.StaticResult.interface_safety`.

    Parameters
    ----------
    res : StaticResult
    interfaces : names, optional
        Default every interface.
    path : str or PathLike, optional
        Save the figure there (``.png``, ``.pdf`` or ``.svg``).
    segment : int, optional
        Draw only this segment (default every segment reached).
    design : float, optional
        Design value of the last segment's parameter (λ_d, or the design level h_d in m),
        drawn as a vertical line (the load margin λ_limit / λ_d in the legend).
    dpi : float

    Returns
    -------
    matplotlib.figure.Figure
    """
    out = figure_path(path, dpi)
    names = list(res.interface_names if interfaces is None else interfaces)
    for name in names:
        if name not in res.interface_names:
            raise ValueError(f"no interface '{name}' (interfaces: "
                             f"{', '.join(map(repr, res.interface_names)) or 'none'})")
    segs = _segments_reached(res)
    if segment is not None and segment not in segs:
        raise ValueError(f"segment={segment}: not reached (segments reached: "
                         f"{_ranges(segs) or 'none'})")
    groups = _segment_groups(res, [segment] if segment is not None else segs)
    cut = len(groups) > MAX_SAFETY_PANELS
    groups = groups[-MAX_SAFETY_PANELS:]
    if not names or not groups:
        fig = new_figure(figsize=(7.5, 7.5))
        _say_only(fig, "no contact interfaces" if not names else "no state reported")
        save_figure(fig, out, dpi)
        return fig
    # wide columns for the levels and the last run of segments, narrow ones for the others
    wide = [_is_level(res, g[0]) or j == len(groups) - 1 for j, g in enumerate(groups)]
    ratios = [3.0 if w else 1.0 for w in wide]
    fig = new_figure(figsize=(min(5.5 + 2.0 * sum(ratios[:-1]), 16.0), 8.0))
    axes = fig.subplots(3, len(groups), squeeze=False, sharey="row", sharex="col",
                        width_ratios=ratios)
    last = groups[-1][-1]
    pattern = _pattern_of(res, last)
    safety = [res.interface_safety(name, design, heel="auto") for name in names]
    made = _made(res)  # construction stages: no values where an interface is not built
    iface = np.asarray(res.cfe["interface"])
    built = [np.ones(res.n_states, bool) if made is None
             else made[:, iface == res.interface_names.index(n)].any(axis=1) for n in names]
    peak = max([_draw_safety_column(res, axes[:, col], group, safety, built, wide[col],
                                    design, pattern) for col, group in enumerate(groups)])
    axes[0, 0].set_ylabel("eccentricity e / B")
    axes[1, 0].set_ylabel("sliding factor f·|ΣN|/|ΣQ|")
    axes[1, 0].set_ylim(0.0, min(max(2.0, 1.1 * peak), 10.0))
    axes[2, 0].set_ylabel("open length, m")
    _safety_legend(fig, res, safety, built, design, last, pattern)
    fig.suptitle("Joint safety along the load path"
                 + (f" (the last {len(groups)} runs of segments)" if cut else "")
                 + f" — {res.status.value}")
    save_figure(fig, out, dpi)
    return fig


__all__ = [
    "MAX_SAFETY_PANELS",
    "plot_safety",
]
