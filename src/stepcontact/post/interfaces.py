"""The contact-stress diagrams of the interfaces (:func:`plot_interfaces`): σ_n, τ with its
limits and the CFE states along every interface at chosen load factors, times or reported
states, with the corner peaks of a diagram annotated.

Sign convention of the article: the normal contact stress σ_n = N/A is negative in
compression; the Coulomb condition is |τ| ≤ f |σ_n| with τ = Q/A (eq. (1)).
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from stepcontact.enums import ContactState
from stepcontact.post.common import (
    DPI,
    NOT_BUILT,
    STATE_COLORS,
    _active_cfes,
    _at_text,
    _is_level,
    _legend_below,
    _pattern_of,
    _say_only,
    _segment_stage,
    _stage_of,
    _stage_text,
    _state_index,
    _stress_scale,
    figure_path,
    new_figure,
    save_figure,
)
from stepcontact.post.mesh import _boundary_edges, _cell_edges

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from stepcontact.results.result import StaticResult

#: the default interface figure draws at most this many segment ends (the last ones): a cyclic
#: program of hundreds of segments would otherwise draw a diagram per half-cycle
MAX_DEFAULT_SNAPSHOTS = 8


def _default_lams(res: StaticResult, segment: int | None) -> list[tuple[int, float]]:
    """(segment, λ) at the end of each segment — the last :data:`MAX_DEFAULT_SNAPSHOTS` — or of
    the given one."""
    segs = np.asarray(res.segment)
    chosen = ([segment] if segment is not None
              else list(dict.fromkeys(segs.tolist()))[-MAX_DEFAULT_SNAPSHOTS:])
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
    # the last reported state at or before lam (what the CFEs have lost by then)
    seg = np.asarray(res.segment)
    start = res.segments[segment][1] if segment < len(res.segments) else 0.0
    passed = (seg < segment) | ((seg == segment)
                                & (np.abs(np.asarray(res.lam) - start) <= abs(lam - start)))
    idx = np.flatnonzero(passed)
    return snap | {"_index": int(idx[-1]) if idx.size else 0}


def _state_snapshot(res: StaticResult, i: int) -> tuple[int, float, dict[str, np.ndarray]]:
    """(segment, λ, CFE quantities) of reported state ``i`` (the scheme after the state)."""
    snap = {k: np.asarray(getattr(res, k))[i] for k in (*res._cfe_keys(), "state")}
    return int(res.segment[i]), float(res.lam[i]), snap | {"_index": i}


#: the corner peak of a contact-stress diagram: the end CFE of an interface at a body corner
#: carrying more than this times the mean |σ_n| of its next two CFEs
CORNER_RATIO = 2.0


#: (two lines: one would be wider than a narrow panel)
CORNER_NOTE = "corner singularity: refines with the mesh,\nnot a physical value"


def _body_corners(res: StaticResult) -> np.ndarray:
    """(k, 2) corners of the outlines of the continuum bodies, m: boundary nodes where the
    outline turns (by more than 10°); empty without geometry."""
    geo = res.geometry or {}
    if "points" not in geo or "bodies" not in geo:
        return np.zeros((0, 2))
    points = np.asarray(geo["points"], dtype=float)
    out = []
    for b in geo["bodies"]:
        cells = np.asarray(b["cells"], dtype=np.int64)
        if str(b.get("kind")) == "frame" or cells.ndim != 2 or cells.shape[1] < 3:
            continue
        ends = _boundary_edges(_cell_edges(cells, str(b.get("element", ""))))[:, [0, -1]]
        if not len(ends):
            continue
        nodes, inv = np.unique(ends.ravel(), return_inverse=True)
        inv = inv.reshape(-1, 2)
        # unit directions of the two outline edges at each node (a node on more than two
        # outline edges, or on one, is a corner)
        d = points[ends[:, 1]] - points[ends[:, 0]]
        d /= np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-300)
        count = np.bincount(inv.ravel(), minlength=len(nodes))
        first = np.full((len(nodes), 2), np.nan)
        turn = np.zeros(len(nodes))
        for e, (a, c) in enumerate(inv):
            for n in (a, c):
                if np.isnan(first[n, 0]):
                    first[n] = d[e]
                else:
                    turn[n] = abs(first[n, 0] * d[e, 1] - first[n, 1] * d[e, 0])
        corner = (count != 2) | (turn > math.sin(math.radians(10.0)))
        out.append(points[nodes[corner]])
    return np.concatenate(out) if out else np.zeros((0, 2))


def _corner_peaks(sig: np.ndarray, xc: np.ndarray, corners: np.ndarray) -> list[int]:
    """Positions (0 or −1) in ``sig`` (σ_n of one interface's CFEs, ordered along s) of the
    end CFEs at a body corner (within 3/4 of the spacing to the next CFE) whose |σ_n| is more
    than :data:`CORNER_RATIO` times the mean |σ_n| of the next two CFEs."""
    if sig.size < 3 or not len(corners):
        return []
    out = []
    peak = float(np.max(np.abs(sig)))
    for end, nxt in ((0, [1, 2]), (-1, [-2, -3])):
        here = abs(float(sig[end]))
        if here <= 1e-9 * peak or here <= CORNER_RATIO * float(np.mean(np.abs(sig[nxt]))):
            continue
        spacing = float(np.linalg.norm(xc[end] - xc[nxt[0]]))
        if float(np.min(np.linalg.norm(corners - xc[end], axis=1))) <= 0.75 * spacing:
            out.append(end)
    return out


def _note_corner_peaks(ax, sigmas: list[np.ndarray], s: np.ndarray, xc: np.ndarray,
                       corners: np.ndarray, scale: float) -> None:
    """Annotate each end of a σ_n diagram (``sigmas``: one array per drawn λ, Pa, CFEs in the
    order of ``s``) that peaks at a body corner in any of the drawn λ (:func:`_corner_peaks`),
    at its largest value."""
    ends: dict[int, float] = {}
    for sig in sigmas:
        for end in _corner_peaks(sig, xc, corners):
            if abs(sig[end]) > abs(ends.get(end, 0.0)):
                ends[end] = float(sig[end])
    for j, end in enumerate(e for e in (0, -1) if e in ends):
        ax.annotate(  # one text, an arrow to each end
            "" if j else CORNER_NOTE, (s[end], ends[end] / scale), xytext=(0.5, 0.96),
            textcoords="axes fraction", ha="center", va="top", fontsize=7, color="0.25",
            arrowprops={"arrowstyle": "->", "color": "0.4", "lw": 0.7},
            bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "0.7", "alpha": 0.85},
        )


def _picked_snapshots(
    res: StaticResult,
    lams: Sequence[float] | float | None,
    segment: int | None,
    states: Sequence[int] | int | None,
) -> tuple[list[tuple[int, float, dict[str, np.ndarray]]], list[int | None], list[np.ndarray]]:
    """The snapshots :func:`plot_interfaces` draws — (segment, λ, CFE quantities) at the
    ``lams`` of ``segment`` (default :func:`_default_lams`), then at the reported ``states`` —
    the construction stage of each and the (m,) bool CFEs made at it."""
    snaps = []
    at_states: list[int] = []
    if states is not None:
        picked = [states] if np.isscalar(states) else list(states)
        if not picked:
            raise ValueError("states: give at least one reported state (or None)")
        at_states = [_state_index(res, i) for i in picked]
        snaps = [_state_snapshot(res, i) for i in at_states]
    if lams is None and not snaps:
        picks = _default_lams(res, segment)
    elif lams is None:
        picks = []
    else:
        seg = int(res.segment[-1]) if segment is None else int(segment)
        lam_list = [float(lams)] if np.isscalar(lams) else [float(v) for v in lams]
        if not lam_list:
            raise ValueError("lams: give at least one load factor (or None for the default)")
        picks = [(seg, v) for v in lam_list]
    snaps = [(s, v, _snapshot(res, s, v)) for s, v in picks] + snaps
    # construction stages: the stage of each snapshot, the CFEs made by then
    stages = [_segment_stage(res, s) for s, _ in picks] + [_stage_of(res, i) for i in at_states]
    return snaps, stages, [_active_cfes(res, st) for st in stages]


def _snapshot_names(res: StaticResult, snaps: list, stages: list[int | None]
                    ) -> tuple[list[str], list[str]]:
    """(legend labels, state-strip row names) of the snapshots: ``'push' λ = 2.354e+04`` and
    ``push λ=23 544``, each named by its stage for a staged result."""
    labels = [_at_text(res, s, v) for s, v, _ in snaps]
    rows = [_at_text(res, sg, v, short=True) for sg, v, _ in snaps]
    if not any(st is not None for st in stages):
        return labels, rows

    # each snapshot named by its stage (an automatic pattern is named after its stage already,
    # "<stage>: release …": the stage is said once, in front)
    def named(st, t, text):
        if st is None:
            return t
        name = res.stage_names[st]
        t = t.replace(f"'{name}: ", "'", 1)
        t = t[len(name) + 2:] if t.startswith(f"{name}: ") else t
        return f"{text}: {t}"
    labels = [named(st, t, _stage_text(res, st)) for st, t in zip(stages, labels, strict=True)]
    rows = [named(st, t, res.stage_names[st] if st is not None else "")
            for st, t in zip(stages, rows, strict=True)]
    return labels, rows


class _Cfes(NamedTuple):
    """The CFE data of the diagrams, (m,) each unless said."""

    area: np.ndarray  #: CFE area A, m²
    fric: np.ndarray  #: friction coefficient f
    bond: np.ndarray | None  #: (m, 5) N_R, Q_R, α_R, 1/α_t, C_r A of bonded joints
    residual: np.ndarray  #: residual cohesion C_r A of a broken joint, N
    lost: np.ndarray  #: the state its cohesion was lost at (−1: never)
    pos: np.ndarray  #: position s along the interface, m
    iface: np.ndarray  #: interface index
    xc: np.ndarray  #: (m, 2) position, m


def _cfe_data(res: StaticResult) -> _Cfes:
    """The CFE data of ``res`` the diagrams read (:class:`_Cfes`)."""
    bond = res.cfe.get("bond")
    residual = (np.zeros(res.m) if bond is None or np.shape(bond)[1] < 5
                else np.nan_to_num(np.asarray(bond, dtype=float)[:, 4]))
    return _Cfes(
        area=np.asarray(res.cfe["area"], dtype=float),
        fric=np.asarray(res.cfe["friction"], dtype=float),
        bond=bond, residual=residual,
        lost=np.asarray(res.cfe.get("cohesion_lost", np.full(res.m, -1))),
        pos=np.asarray(res.cfe["s"], dtype=float),
        iface=np.asarray(res.cfe["interface"]),
        xc=np.asarray(res.cfe["x"], dtype=float).reshape(res.m, 2),
    )


def _tau_limit(cfe: _Cfes, k: np.ndarray, snap: dict, sig: np.ndarray, scale: float
               ) -> np.ndarray:
    """The limit of |τ| of CFEs ``k`` at a snapshot, in the unit of ``sig`` (σ_n / scale):
    f|σ_n| (eq. (1)); a bonded joint's shear strength τ_R − α_R σ_n (eq. (12)); a broken,
    closed joint that keeps residual cohesion f|σ_n| + c_r."""
    lim = cfe.fric[k] * np.abs(sig)
    if cfe.bond is None:
        return lim
    area = cfe.area[k]
    b = np.asarray(cfe.bond, dtype=float)[k]
    st = np.asarray(snap["state"])[k]
    bonded = st == int(ContactState.BONDED)
    # broken, closed, its residual cohesion kept: f|σ_n| + C_r
    kept = ((cfe.residual[k] > 0) & ~bonded & (st != int(ContactState.OPEN))
            & ((cfe.lost[k] < 0) | (cfe.lost[k] > snap.get("_index", 0))))
    lim = np.where(kept, lim + cfe.residual[k] / area / scale, lim)
    return np.where(bonded, b[:, 1] / area / scale - b[:, 2] * sig, lim)


def _draw_diagrams(ax_n, ax_t, cfe: _Cfes, k: np.ndarray, snaps: list, acts: list,
                   colors: list[str], scale: float) -> bool:
    """The σ_n and τ diagrams (τ with its limits dashed, :func:`_tau_limit`) of CFEs ``k``
    (ordered along s) at every snapshot, and the water pressure −p in an opened joint
    dotted; whether there was water."""
    s = cfe.pos[k]
    area = cfe.area[k]
    mk = "o" if k.size <= 40 else None
    shade = 0.15 if len(snaps) == 1 else 0.06  # the diagrams' fill, lighter when they overlap
    wet = False
    for j, (_, _, snap) in enumerate(snaps):
        made = acts[j][k]  # CFEs not yet made at the snapshot's stage are not drawn
        sig = np.where(made, snap["N"][k] / area / scale, np.nan)
        tau = np.where(made, snap["Q"][k] / area / scale, np.nan)
        lim = _tau_limit(cfe, k, snap, sig, scale)
        ax_n.plot(s, sig, color=colors[j], marker=mk, ms=3, lw=1.4)
        ax_n.fill_between(s, sig, color=colors[j], alpha=shade, lw=0)
        ax_t.plot(s, tau, color=colors[j], marker=mk, ms=3, lw=1.4)
        ax_t.fill_between(s, tau, color=colors[j], alpha=shade, lw=0)
        ax_t.plot(s, lim, color=colors[j], ls="--", lw=0.9)
        ax_t.plot(s, -lim, color=colors[j], ls="--", lw=0.9)
        cp = snap.get("crack_pressure")
        if cp is not None and np.any(cp[k] > 0):  # water in the opened joint
            wet = True
            ax_n.plot(s, np.where(cp[k] > 0, -cp[k], np.nan) / scale, color=colors[j],
                      ls=":", lw=1.6)
    return wet


def _strip_edges(s: np.ndarray) -> np.ndarray:
    """Cell edges of the state strip: one cell per CFE (positions ``s``, sorted) between
    mid-points; equal-width cells by order where positions coincide."""
    if s.size > 1:
        mid = 0.5 * (s[1:] + s[:-1])
        edges = np.r_[s[0] - (mid[0] - s[0]), mid, s[-1] + (s[-1] - mid[-1])]
    else:
        edges = np.array([s[0] - 0.5, s[0] + 0.5])
    if np.any(np.diff(edges) <= 0):  # coincident positions: equal-width cells by order
        edges = np.arange(s.size + 1) - 0.5
    return edges


def _draw_state_strip(ax_s, s: np.ndarray, k: np.ndarray, snaps: list, acts: list,
                      rows: list[str]) -> None:
    """The state strip of CFEs ``k`` (positions ``s``): one row per snapshot (named
    ``rows``), one cell per CFE coloured by its state; CFEs not yet made hatched."""
    from matplotlib.colors import BoundaryNorm, ListedColormap

    codes = [int(c) for c in ContactState]
    cmap = ListedColormap([STATE_COLORS[c] for c in ContactState])
    norm = BoundaryNorm(np.r_[np.array(codes) - 0.5, codes[-1] + 0.5], cmap.N)
    grid = np.ma.masked_array(
        [np.asarray(snap["state"])[k] for _, _, snap in snaps], dtype=float,
        mask=[~a[k] for a in acts])  # not yet made: blank over the hatched background
    if np.ma.is_masked(grid):
        ax_s.patch.set_facecolor("white")
        ax_s.patch.set_hatch("////")
        ax_s.patch.set_edgecolor("0.75")
    ax_s.pcolormesh(
        _strip_edges(s), np.arange(len(snaps) + 1) - 0.5, grid, cmap=cmap, norm=norm,
        edgecolors="white", linewidth=0.3,
    )
    ax_s.set_yticks(np.arange(len(snaps)), rows, fontsize=7)
    ax_s.set_ylim(len(snaps) - 0.5, -0.5)


def _draw_interface(axes, name: str, k: np.ndarray, cfe: _Cfes, snaps: list, acts: list,
                    colors: list[str], rows: list[str], stress: tuple[float, str],
                    corners: np.ndarray) -> bool:
    """One interface's column of panels (``axes``: σ_n, τ, states) for its CFEs ``k``;
    ``stress`` the divisor and unit of the stresses.  Whether a CFE of it keeps a residual
    cohesion."""
    ax_n, ax_t, ax_s = axes
    scale, unit = stress
    ax_n.set_title(f"interface '{name}'")
    if k.size == 0:
        ax_n.text(0.5, 0.5, "no CFEs", ha="center", va="center", transform=ax_n.transAxes)
        return False
    k = k[np.argsort(cfe.pos[k], kind="stable")]
    s = cfe.pos[k]
    wet = _draw_diagrams(ax_n, ax_t, cfe, k, snaps, acts, colors, scale)
    for ax in (ax_n, ax_t):
        ax.axhline(0.0, color="k", lw=0.6)
        ax.grid(True, alpha=0.3)
    if not any(a[k].any() for a in acts):
        ax_n.text(0.5, 0.5, NOT_BUILT, ha="center", va="center", color="0.4",
                  transform=ax_n.transAxes, gid="not_built")
    _note_corner_peaks(ax_n, [snap["N"][k] / cfe.area[k] for (_, _, snap), a
                              in zip(snaps, acts, strict=True) if a[k].all()], s,
                       cfe.xc[k], corners, scale)
    ax_n.set_ylabel(rf"$\sigma_n$ = N/A, {unit} (compression < 0)"
                    + (";\nwater in the crack −p dotted" if wet else ""))
    ax_t.set_ylabel(rf"$\tau$ = Q/A, {unit}")
    # state strip: one row per λ, one cell per CFE between mid-points
    _draw_state_strip(ax_s, s, k, snaps, acts, rows)
    ax_s.set_xlabel("position s along the interface, m")
    return bool(cfe.residual[k].any())


def _interfaces_legend(fig: Figure, snaps: list, acts: list, labels: list[str],
                       colors: list[str], bonded: bool, any_residual: bool, ncol: int) -> None:
    """The legend below the panels: the snapshots' colours, what the dashed limits are, the
    states shown (bonded and closed only when present) and "not yet built"."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles = [Line2D([], [], color=colors[j], lw=1.6, label=labels[j]) for j in range(len(snaps))]
    # what the dashed and dotted lines are (in the legend: axis labels stay short, so that
    # those of the σ_n and τ panels do not run into each other or the state strip's rows)
    limits = r"$\tau$ limits dashed: $\pm f|\sigma_n|$"
    if bonded:
        limits += r"; bonded $\pm(\tau_R - \alpha_R \sigma_n)$"
    if any_residual:
        limits += r"; broken, closed $\pm(f|\sigma_n| + c_r)$"
    handles.append(Line2D([], [], color="0.3", ls="--", lw=0.9, label=limits))
    shown = {int(v) for (_, _, snap), a in zip(snaps, acts, strict=True)
             for v in np.asarray(snap["state"])[a]}
    handles += [
        Patch(facecolor=STATE_COLORS[cs], edgecolor="0.4", label=cs.label)
        for cs in ContactState
        if cs not in (ContactState.BONDED, ContactState.CLOSED) or int(cs) in shown
    ]
    if not all(a.all() for a in acts):
        handles.append(Patch(facecolor="white", edgecolor="0.75", hatch="////",
                             label=NOT_BUILT))
    _legend_below(fig, handles, min(len(handles), max(4, 3 * ncol)), fontsize=8,
                  frameon=False)


def _interfaces_title(res: StaticResult, snaps: list) -> str:
    """``Contact stresses at pattern 'push' λ = 1, 2`` (``h = … m`` for a water level, one
    line per pattern; ``t = … s`` for a dynamic result)."""
    if getattr(res, "path_axis", "lam") == "time":
        return "Contact stresses at t = " + ", ".join(f"{v:.4g}" for _, v, _ in snaps) + " s"
    by_pattern: dict[tuple[str, bool], list[str]] = {}
    for sg, v, _ in snaps:
        by_pattern.setdefault((_pattern_of(res, sg), _is_level(res, sg)), []).append(
            f"{v:.4g}")
    return (
        "Contact stresses at "
        + ";\n".join(f"pattern '{p}' h = {', '.join(v)} m" if level
                     else f"pattern '{p}' λ = {', '.join(v)}"
                     for (p, level), v in by_pattern.items())
    )


def plot_interfaces(
    res: StaticResult,
    lams: Sequence[float] | float | None = None,
    path: str | os.PathLike[str] | None = None,
    segment: int | None = None,
    *,
    states: Sequence[int] | int | None = None,
    dpi: float = DPI,
) -> Figure:
    """Contact stresses and CFE states along every interface at chosen load factors.

    One column per interface (``res.interface_names``) with three panels against the position
    s along the interface (m), in the manner of the stress diagrams of the article (Fig. 4):

    * the normal contact stress σ_n = N/A (negative in compression), the diagram shaded,
    * the tangential stress τ = Q/A with the friction limits ±f|σ_n| dashed (eq. (1)); where a
      joint is still bonded, its shear strength ±(τ_R − α_R σ_n) (eq. (12)),
    * a strip with the state of each CFE (open / stick / slip+ / slip−) for each λ, its rows
      named by the pattern and λ (e.g. ``push λ=23 544``).

    Where a σ_n diagram peaks at a corner of a body (the end CFE of an interface at a body
    corner carries more than :data:`CORNER_RATIO` times the mean |σ_n| of the next two CFEs,
    as under a rigid or stiff block), the peak is annotated "corner singularity: refines
    with the mesh, not a physical value": the elastic corner stress is singular, the value
    drawn is the mean over the end CFE and grows as the mesh is refined.

    For a staged result each snapshot is named by its stage (``stage 'dam': …``) and the CFEs
    not yet made at it are left out: no σ_n, τ there, the strip hatched "not yet built".

    Stresses are shown in MPa, kPa or Pa (whichever reads best; the unit is in the axis label).
    The values at any λ come from :meth:`StaticResult.interpolate` (exact: the path is linear
    between events); at the λ of a reported state the strip shows the working scheme after
    the last state with that λ (e.g. including an event at the very end of a segment).

    Parameters
    ----------
    res : StaticResult
    lams : float or sequence of float, optional
        Load factors of the active pattern of ``segment``.  Default: the end of every segment,
        the last :data:`MAX_DEFAULT_SNAPSHOTS` of them (or of ``segment`` when given).  For a
        dynamic result (:func:`~stepcontact.solve_dynamic`) the times t, s: the diagrams at
        chosen instants, the forces between two recorded steps interpolated linearly in time
        (as Newmark's step does).
    path : str or PathLike, optional
        Save the figure there (``.png``, ``.pdf`` or ``.svg``); parent directories are created.
    segment : int, optional
        Load-program segment the ``lams`` belong to; default the last segment reached.
    states : int or sequence of int, optional
        Reported states to draw instead of (or besides) ``lams``: the forces of the state and
        the working scheme after it (negative indices count from the end).
    dpi : float
        Resolution of a saved raster figure, dots per inch.

    Returns
    -------
    matplotlib.figure.Figure
    """
    out = figure_path(path, dpi)
    snaps, stages, acts = _picked_snapshots(res, lams, segment, states)
    names = list(res.interface_names)
    ncol = max(1, len(names))
    fig = new_figure(figsize=(max(8.5, 4.8 * ncol), 7.5))
    if not names or res.m == 0:
        _say_only(fig, "no contact interfaces")
        save_figure(fig, out, dpi)
        return fig

    cfe = _cfe_data(res)
    all_sig = np.concatenate(
        [np.where(np.r_[a, a], np.r_[snap["N"] / cfe.area, snap["Q"] / cfe.area], 0.0)
         for (_, _, snap), a in zip(snaps, acts, strict=True)]
    )
    stress = _stress_scale(all_sig)
    colors = [f"C{j % 10}" for j in range(len(snaps))]
    labels, rows = _snapshot_names(res, snaps, stages)
    corners = _body_corners(res)

    axes = fig.subplots(3, ncol, squeeze=False, sharex="col", height_ratios=[3, 3, 1.2])
    any_residual = False
    for c, name in enumerate(names):
        k = np.flatnonzero(cfe.iface == c)
        any_residual |= _draw_interface(axes[:, c], name, k, cfe, snaps, acts, colors, rows,
                                        stress, corners)
        if c == 0 and k.size:
            axes[2, 0].set_ylabel("state")
    _interfaces_legend(fig, snaps, acts, labels, colors, cfe.bond is not None, any_residual,
                       ncol)
    fig.suptitle(_interfaces_title(res, snaps))
    save_figure(fig, out, dpi)
    return fig


__all__ = [
    "CORNER_NOTE",
    "CORNER_RATIO",
    "MAX_DEFAULT_SNAPSHOTS",
    "plot_interfaces",
]
