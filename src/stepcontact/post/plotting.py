"""Plots of a static result: contact stresses, load path, deformed shape, load–displacement
curve and event timeline.

matplotlib is imported inside the functions (``import stepcontact`` stays light).  Figures are
built on the Agg canvas without pyplot: nothing is shown, no global figure registry is touched;
the returned :class:`matplotlib.figure.Figure` displays in Jupyter and can be saved again.

Sign convention of the article: the normal contact stress σ_n = N/A is negative in
compression; the Coulomb condition is |τ| ≤ f |σ_n| with τ = Q/A (eq. (1)).

Construction stages (``res.stage``): a figure of a state draws only the bodies built and the
CFEs made at it (:meth:`StaticResult.active_bodies`, :meth:`StaticResult.active_cfes`); CFEs
not yet made are left out of the diagrams and hatched :data:`NOT_BUILT` in the state strips,
and every snapshot, segment panel and the load path are labelled with their stage's name.

Example
-------
>>> from stepcontact.post.plotting import plot_interfaces, plot_load_path
>>> fig = plot_interfaces(res, path="out/interfaces.png")   # doctest: +SKIP
>>> fig = plot_load_path(res, path="out/load_path.pdf")     # doctest: +SKIP
>>> fig = plot_deformed(res, path="out/deformed.svg")       # doctest: +SKIP
>>> fig = plot_load_displacement(res, node=(3.0, 2.0), dof="x")  # doctest: +SKIP
>>> fig = plot_event_timeline(res, path="out/timeline.png")  # doctest: +SKIP
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from stepcontact.enums import ContactState, Transition
from stepcontact.io.atomic import atomic_path, write_error

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from stepcontact.results.result import StaticResult

#: colours of the CFE states (open, stick, slip+, slip−, bonded)
STATE_COLORS: dict[ContactState, str] = {
    ContactState.OPEN: "#d9d9d9",
    ContactState.STICK: "#2ca02c",
    ContactState.SLIP_POS: "#d62728",
    ContactState.SLIP_NEG: "#1f77b4",
    ContactState.BONDED: "#9467bd",
    ContactState.CLOSED: "#8c564b",
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
DPI = 150  #: default resolution of saved raster figures, dots per inch
MAX_PIXELS = 2e8  #: largest raster of a figure, pixels (about 800 MB of RGBA)
MAX_SIDE = 2**16  #: the Agg renderer's limit on each side, pixels


def new_figure(**kw) -> Figure:
    """A matplotlib figure (constrained layout, the Agg canvas: no GUI backend) for the
    plotting functions of this module and of the studies' reports."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(layout="constrained", **kw)
    FigureCanvasAgg(fig)
    return fig


def figure_path(path: str | os.PathLike[str] | None, dpi: float = DPI) -> Path | None:
    """``path`` as a Path checked for a supported image suffix (None stays None: the figure is
    returned, not written), and ``dpi`` checked to be positive."""
    if not (np.isfinite(dpi) and dpi > 0):
        raise ValueError(f"dpi={dpi}: must be a positive number of dots per inch")
    if path is None:
        return None
    p = Path(path)
    if p.suffix.lower() not in _SUFFIXES:
        raise ValueError(
            f"path '{p}': unsupported suffix '{p.suffix}', use one of {', '.join(_SUFFIXES)}"
        )
    return p


def _check_pixels(fig: Figure, dpi: float) -> None:
    """Refuse a figure whose raster at ``dpi`` would be absurdly large (the Agg renderer
    allocates it whole, whatever the file type: constrained layout draws with it)."""
    wi, hi = (float(v) for v in fig.get_size_inches())
    w, h = wi * dpi, hi * dpi
    if w * h > MAX_PIXELS or max(w, h) >= MAX_SIDE:
        top = min(math.sqrt(MAX_PIXELS / (wi * hi)), (MAX_SIDE - 1) / max(wi, hi))
        raise ValueError(
            f"dpi={dpi:g}: a {w:.0f} × {h:.0f} pixel figure ({w * h:.2g} pixels) is too large, "
            f"at most {MAX_PIXELS:.0e} pixels and {MAX_SIDE - 1} per side; lower the dpi "
            f"(at most {math.floor(top)} for this figure)"
        )


def save_figure(fig: Figure, path: Path | None, dpi: float = DPI) -> None:
    """Write the figure atomically: to a temporary file beside ``path``, renamed into place;
    a failed write leaves no partial figure (and an existing file untouched)."""
    if path is None:
        return
    _check_pixels(fig, dpi)
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format=path.suffix.lower().lstrip("."))
    except OSError as e:  # a full disk: an error naming the figure, the old one intact
        raise write_error(path, e, "figure") from None


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


def _state_index(res: StaticResult, state: int) -> int:
    """A reported-state index checked against ``res.n_states`` (negative: from the end)."""
    n = res.n_states
    if isinstance(state, bool) or not isinstance(state, int | np.integer):
        raise ValueError(f"state={state!r}: give the index of a reported state (an integer)")
    if not -n <= int(state) < n:
        raise ValueError(f"state {state} does not exist: the result has states 0..{n - 1}")
    return int(state) % n


def _state_snapshot(res: StaticResult, i: int) -> tuple[int, float, dict[str, np.ndarray]]:
    """(segment, λ, CFE quantities) of reported state ``i`` (the scheme after the state)."""
    snap = {k: np.asarray(getattr(res, k))[i] for k in (*res._cfe_keys(), "state")}
    return int(res.segment[i]), float(res.lam[i]), snap | {"_index": i}


def _stage_of(res: StaticResult, i: int) -> int | None:
    """Construction stage of reported state ``i`` (None for a result without stages)."""
    stage = getattr(res, "stage", None)
    return None if stage is None else int(stage[i])


def _segment_stage(res: StaticResult, seg: int) -> int | None:
    """Construction stage of load segment ``seg`` (that of its last reported state)."""
    idx = np.flatnonzero(np.asarray(res.segment) == seg)
    return _stage_of(res, int(idx[-1])) if idx.size else None


def _stage_text(res: StaticResult, stage: int | None) -> str:
    """``stage 'second'`` (empty for no stage)."""
    return "" if stage is None else f"stage '{res.stage_names[stage]}'"


def _active_cfes(res: StaticResult, stage: int | None) -> np.ndarray:
    """(m,) bool: the CFEs that exist at ``stage`` (all of them for None)."""
    if stage is None:
        return np.ones(res.m, bool)
    return np.asarray(res.stage_cfes, dtype=bool).reshape(-1, res.m)[stage]


def _made(res: StaticResult) -> np.ndarray | None:
    """(n_states, m) bool: the CFEs made at every state (None for a result without stages)."""
    stage = getattr(res, "stage", None)
    if stage is None:
        return None
    return np.asarray(res.stage_cfes, dtype=bool).reshape(-1, res.m)[np.asarray(stage, int)]


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


def _pattern_of(res: StaticResult, seg: int) -> str:
    if 0 <= seg < len(res.segments):
        return str(res.segments[seg][0])
    return "?"


def _is_level(res: StaticResult, seg: int) -> bool:
    """Whether the parameter of segment ``seg`` is a water level h, m (its pattern's factor
    is a level: :attr:`StaticResult.level_patterns`), not a load factor λ."""
    return (getattr(res, "path_axis", "lam") != "time"
            and _pattern_of(res, seg) in getattr(res, "level_patterns", {}))


def _at_text(res: StaticResult, seg: int, v: float, short: bool = False) -> str:
    """Where on the path a value is: ``'push' λ = 23 544`` (``push λ=23 544`` short),
    ``'reservoir' h = 28 m`` (``reservoir h=28 m``) when the parameter is a water level, or
    ``t = 0.035 s`` for a result in time (a dynamic run)."""
    if getattr(res, "path_axis", "lam") == "time":
        return f"t={v:.6g} s" if short else f"t = {v:.6g} s"
    if _is_level(res, seg):
        return (f"{_pattern_of(res, seg)} h={_lam_text(v)} m" if short
                else f"'{_pattern_of(res, seg)}' h = {v:.4g} m")
    if short:
        return f"{_pattern_of(res, seg)} λ={_lam_text(v)}"
    return f"'{_pattern_of(res, seg)}' λ = {v:.4g}"


def _axis_text(res: StaticResult, seg: int) -> str:
    """The label of a path axis: ``λ of 'push'``, ``water level h of 'reservoir', m`` when
    the parameter is a level, or ``time t, s`` for a dynamic result."""
    if getattr(res, "path_axis", "lam") == "time":
        return "time t, s"
    if _is_level(res, seg):
        return f"water level h of '{_pattern_of(res, seg)}', m"
    return f"λ of '{_pattern_of(res, seg)}'"


def _legend_below(fig: Figure, handles: list, ncol: int, **kw):
    """A figure legend below the axes (``outside lower center``) in at most ``ncol`` columns,
    fewer when its width would pass the figure's (a legend clipped on both sides)."""
    renderer = fig.canvas.get_renderer()
    ncol = max(1, min(int(ncol), len(handles)))
    while True:
        leg = fig.legend(handles=handles, loc="outside lower center", ncol=ncol, **kw)
        if ncol == 1 or leg.get_window_extent(renderer).width <= 0.98 * fig.bbox.width:
            return leg
        leg.remove()
        ncol -= 1


def _lam_text(v: float) -> str:
    """A load factor as a label reads it: 5 significant digits, thousands grouped by spaces
    from 10 000 on (``23544.0`` → ``"23 544"``, ``1.0`` → ``"1"``, ``0.25`` → ``"0.25"``)."""
    v = float(v)
    if not np.isfinite(v) or v == 0 or not 1e4 <= abs(v) < 1e9:
        return f"{v:.5g}"
    decimals = max(0, 5 - len(str(int(abs(v)))))
    text = f"{v:,.{decimals}f}".replace(",", " ")
    return text.rstrip("0").rstrip(".") if "." in text else text


#: label of the CFEs (and bodies) of a later construction stage
NOT_BUILT = "not yet built"

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
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    out = figure_path(path, dpi)
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
    acts = [_active_cfes(res, st) for st in stages]
    staged = any(st is not None for st in stages)

    names = list(res.interface_names)
    ncol = max(1, len(names))
    fig = new_figure(figsize=(max(8.5, 4.8 * ncol), 7.5))
    if not names or res.m == 0:
        ax = fig.add_subplot()
        ax.text(0.5, 0.5, "no contact interfaces", ha="center", va="center")
        ax.set_axis_off()
        save_figure(fig, out, dpi)
        return fig

    area = np.asarray(res.cfe["area"], dtype=float)
    fric = np.asarray(res.cfe["friction"], dtype=float)
    bond = res.cfe.get("bond")  # (m, 5): N_R, Q_R, α_R, 1/α_t of bonded joints, C_r A
    residual = (np.zeros(res.m) if bond is None or np.shape(bond)[1] < 5
                else np.nan_to_num(np.asarray(bond, dtype=float)[:, 4]))
    lost = np.asarray(res.cfe.get("cohesion_lost", np.full(res.m, -1)))  # state it was lost
    pos = np.asarray(res.cfe["s"], dtype=float)
    iface = np.asarray(res.cfe["interface"])
    xc = np.asarray(res.cfe["x"], dtype=float).reshape(res.m, 2)
    corners = _body_corners(res)
    all_sig = np.concatenate(
        [np.where(np.r_[a, a], np.r_[snap["N"] / area, snap["Q"] / area], 0.0)
         for (_, _, snap), a in zip(snaps, acts, strict=True)]
    )
    scale, unit = _stress_scale(all_sig)

    codes = [int(c) for c in ContactState]
    cmap = ListedColormap([STATE_COLORS[c] for c in ContactState])
    norm = BoundaryNorm(np.r_[np.array(codes) - 0.5, codes[-1] + 0.5], cmap.N)
    colors = [f"C{j % 10}" for j in range(len(snaps))]
    shade = 0.15 if len(snaps) == 1 else 0.06  # the diagrams' fill, lighter when they overlap
    labels = [_at_text(res, s, v) for s, v, _ in snaps]
    rows = [_at_text(res, sg, v, short=True) for sg, v, _ in snaps]
    if staged:  # each snapshot named by its stage
        # (an automatic pattern is named after its stage already, "<stage>: release …": the
        # stage is said once, in front)
        def named(st, t, text):
            if st is None:
                return t
            name = res.stage_names[st]
            t = t.replace(f"'{name}: ", "'", 1)
            t = t[len(name) + 2:] if t.startswith(f"{name}: ") else t
            return f"{text}: {t}"
        labels = [named(st, t, _stage_text(res, st)) for st, t in zip(stages, labels,
                                                                     strict=True)]
        rows = [named(st, t, res.stage_names[st] if st is not None else "")
                for st, t in zip(stages, rows, strict=True)]

    axes = fig.subplots(3, ncol, squeeze=False, sharex="col", height_ratios=[3, 3, 1.2])
    any_residual = False
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
        wet = False
        for j, (_, _, snap) in enumerate(snaps):
            made = acts[j][k]  # CFEs not yet made at the snapshot's stage are not drawn
            sig = np.where(made, snap["N"][k] / area[k] / scale, np.nan)
            tau = np.where(made, snap["Q"][k] / area[k] / scale, np.nan)
            lim = fric[k] * np.abs(sig)
            if bond is not None:  # a bonded CFE's limit is its shear strength (eq. (12))
                b = np.asarray(bond, dtype=float)[k]
                st = np.asarray(snap["state"])[k]
                bonded = st == int(ContactState.BONDED)
                # broken, closed, its residual cohesion kept: f|σ_n| + C_r
                kept = ((residual[k] > 0) & ~bonded & (st != int(ContactState.OPEN))
                        & ((lost[k] < 0) | (lost[k] > snap.get("_index", 0))))
                lim = np.where(kept, lim + residual[k] / area[k] / scale, lim)
                lim = np.where(bonded, b[:, 1] / area[k] / scale - b[:, 2] * sig, lim)
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
        for ax in (ax_n, ax_t):
            ax.axhline(0.0, color="k", lw=0.6)
            ax.grid(True, alpha=0.3)
        if not any(a[k].any() for a in acts):
            ax_n.text(0.5, 0.5, NOT_BUILT, ha="center", va="center", color="0.4",
                      transform=ax_n.transAxes, gid="not_built")
        _note_corner_peaks(ax_n, [snap["N"][k] / area[k] for (_, _, snap), a
                                  in zip(snaps, acts, strict=True) if a[k].all()], s,
                           xc[k], corners, scale)
        any_residual |= bool(residual[k].any())
        ax_n.set_ylabel(rf"$\sigma_n$ = N/A, {unit} (compression < 0)"
                        + (";\nwater in the crack −p dotted" if wet else ""))
        ax_t.set_ylabel(rf"$\tau$ = Q/A, {unit}")

        # state strip: one row per λ, one cell per CFE between mid-points
        if s.size > 1:
            mid = 0.5 * (s[1:] + s[:-1])
            edges = np.r_[s[0] - (mid[0] - s[0]), mid, s[-1] + (s[-1] - mid[-1])]
        else:
            edges = np.array([s[0] - 0.5, s[0] + 0.5])
        if np.any(np.diff(edges) <= 0):  # coincident positions: equal-width cells by order
            edges = np.arange(k.size + 1) - 0.5
        grid = np.ma.masked_array(
            [np.asarray(snap["state"])[k] for _, _, snap in snaps], dtype=float,
            mask=[~a[k] for a in acts])  # not yet made: blank over the hatched background
        if np.ma.is_masked(grid):
            ax_s.patch.set_facecolor("white")
            ax_s.patch.set_hatch("////")
            ax_s.patch.set_edgecolor("0.75")
        ax_s.pcolormesh(
            edges, np.arange(len(snaps) + 1) - 0.5, grid, cmap=cmap, norm=norm,
            edgecolors="white", linewidth=0.3,
        )
        ax_s.set_yticks(np.arange(len(snaps)), rows, fontsize=7)
        ax_s.set_ylim(len(snaps) - 0.5, -0.5)
        ax_s.set_xlabel("position s along the interface, m")
        if c == 0:
            ax_s.set_ylabel("state")

    handles = [Line2D([], [], color=colors[j], lw=1.6, label=labels[j]) for j in range(len(snaps))]
    # what the dashed and dotted lines are (in the legend: axis labels stay short, so that
    # those of the σ_n and τ panels do not run into each other or the state strip's rows)
    limits = r"$\tau$ limits dashed: $\pm f|\sigma_n|$"
    if bond is not None:
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
    by_pattern: dict[tuple[str, bool], list[str]] = {}
    for sg, v, _ in snaps:
        by_pattern.setdefault((_pattern_of(res, sg), _is_level(res, sg)), []).append(
            f"{v:.4g}")
    if getattr(res, "path_axis", "lam") == "time":
        fig.suptitle("Contact stresses at t = "
                     + ", ".join(f"{v:.4g}" for _, v, _ in snaps) + " s")
    else:
        fig.suptitle(
            "Contact stresses at "
            + ";\n".join(f"pattern '{p}' h = {', '.join(v)} m" if level
                         else f"pattern '{p}' λ = {', '.join(v)}"
                         for (p, level), v in by_pattern.items())
        )
    save_figure(fig, out, dpi)
    return fig


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
    counts = (np.array([((st == int(cs)) & (True if made is None else made)).sum(axis=1)
                        for cs in ContactState]) if st.size else None)
    present = [cs for cs in ContactState if counts is not None and counts[int(cs)].any()]
    if counts is not None and present:
        bottom = np.zeros(res.n_states)
        for cs in present:  # the scheme after state i, as a bar of width 1 centred on i
            ax_c.bar(i, counts[int(cs)], width=1.0, bottom=bottom, color=STATE_COLORS[cs],
                     edgecolor="0.3", linewidth=0.3, label=cs.label)
            bottom += counts[int(cs)]
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


# --------------------------------------------------------------------------------------------
# helpers of the mesh figures
# --------------------------------------------------------------------------------------------
#: outline node order of a cell in scikit-fem's local DOF order (corners, then the mid-side
#: nodes of the edges 01, 12, 23 (02 for triangles), 30)
_RING: dict[str, tuple[int, ...]] = {
    "tri3": (0, 1, 2),
    "tri6": (0, 3, 1, 4, 2, 5),
    "quad4": (0, 1, 2, 3),
    "quad8": (0, 4, 1, 5, 2, 6, 3, 7),
    "quad9": (0, 4, 1, 5, 2, 6, 3, 7),
}
_DOFS: dict[str, int] = {"x": 0, "ux": 0, "y": 1, "uy": 1, "rz": 2}
_DOF_LABEL = ("$u_x$", "$u_y$", r"$\varphi_z$")


def _geometry(res: StaticResult) -> tuple[np.ndarray, np.ndarray, list[dict]]:
    """(points (n, 2) m, dof_of (n, 3), bodies) of the result, or a ValueError."""
    geo = res.geometry or {}
    if not all(k in geo for k in ("points", "dof_of", "bodies")):
        raise ValueError(
            "this result has no mesh geometry (points, dof_of, bodies): it cannot be drawn"
        )
    return (np.asarray(geo["points"], dtype=float), np.asarray(geo["dof_of"]),
            list(geo["bodies"]))


def _extent(points: np.ndarray) -> float:
    """Largest side of the bounding box of the nodes, m (1 when degenerate)."""
    size = float(np.max(np.ptp(points, axis=0))) if len(points) else 0.0
    return size if size > 0 and np.isfinite(size) else 1.0


def _missing_fields(res: StaticResult, i: int) -> ValueError:
    """The error for displacements a result neither stores nor can recompute."""
    stored = sorted(res.fields)
    have = (f"stored for states {_ranges(stored)}" if stored else "no field is stored")
    return ValueError(
        f"the displacements of state {i} are not in this result ({have}); give the result "
        "its model with res.recover_fields(model) (command line: --model MODEL.toml) to "
        "recompute any state exactly, or re-run with solve_static(model, "
        "store_fields='all') (an in-memory result recovers any state)"
    )


def _field(res: StaticResult, i: int) -> np.ndarray:
    """Displacement vector of state ``i``; a ValueError that says how to get it if missing."""
    try:
        return np.asarray(res.displacement(i), dtype=float)
    except KeyError:
        raise _missing_fields(res, i) from None


def _all_fields(res: StaticResult) -> np.ndarray:
    """Displacements (n_states, ndof) of every state: stored, the others recomputed in one
    solve; a ValueError that says how to get them if the result cannot."""
    try:
        return np.asarray(res.displacements(), dtype=float)
    except KeyError:
        missing = next(i for i in range(res.n_states) if i not in res.fields)
        raise _missing_fields(res, missing) from None


def _ranges(values: Sequence[int]) -> str:
    """``[0, 1, 2, 5]`` → ``"0–2, 5"``."""
    out: list[str] = []
    for v in values:
        if out and out[-1].split("–")[-1] == str(v - 1):
            out[-1] = f"{out[-1].split('–')[0]}–{v}"
        else:
            out.append(str(v))
    return ", ".join(out)


def _node_u(dof_of: np.ndarray, u: np.ndarray, comps: Sequence[int] = (0, 1)) -> np.ndarray:
    """Nodal values (n_nodes, len(comps)) of the DOF components ``comps`` (0 where none)."""
    d = dof_of[:, list(comps)]
    return np.where(d >= 0, u[np.maximum(d, 0)], 0.0)


def _nice_floor(x: float) -> float:
    """The largest 1, 2 or 5 × 10^k not above ``x`` (> 0)."""
    k = np.floor(np.log10(x))
    mant = x / 10**k
    return float(max(c for c in (1.0, 2.0, 5.0, 10.0) if c <= mant * (1 + 1e-12)) * 10**k)


def _length_scale(values: np.ndarray) -> tuple[float, str]:
    """Divisor and unit so that lengths (m) read well: m, mm or µm."""
    peak = float(np.max(np.abs(values), initial=0.0)) if values.size else 0.0
    if not np.isfinite(peak) or peak >= 0.1 or peak == 0:
        return 1.0, "m"
    return (1e-3, "mm") if peak >= 1e-4 else (1e-6, "µm")


def _ring(element: str, n_per_cell: int) -> tuple[np.ndarray, int]:
    """Outline node order of a cell and the number of nodes per edge (2, or 3 if quadratic)."""
    ring = _RING.get(element)
    if ring is None or max(ring) >= n_per_cell:
        ring = tuple(range(min(n_per_cell, 4)))  # unknown element: its corners
    return np.asarray(ring), 3 if len(ring) in (6, 8) else 2


def _cell_edges(cells: np.ndarray, element: str) -> np.ndarray:
    """(n_cells · n_edges, 2 or 3) node ids of every cell edge: end, [mid-side,] end."""
    ring, per = _ring(element, cells.shape[1])
    r = cells[:, ring]
    starts = np.arange(0, r.shape[1], per - 1)
    cols = (starts[:, None] + np.arange(per)[None, :]) % r.shape[1]
    return r[:, cols].reshape(-1, per)


def _boundary_edges(edges: np.ndarray) -> np.ndarray:
    """The edges that belong to one cell only (the outline of the body)."""
    if not len(edges):
        return edges
    key = np.sort(edges[:, [0, -1]], axis=1)
    _, inv, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    return edges[counts[inv.ravel()] == 1]


def _shown_nodes(bodies: list[dict], n: int, only: set[str] | None) -> np.ndarray:
    """(n,) bool: the nodes drawn when only the bodies ``only`` are (all for None): those of
    their cells, and the nodes of no body's cells."""
    if only is None:
        return np.ones(n, bool)
    on, off = np.zeros(n, bool), np.zeros(n, bool)
    for b in bodies:
        cells = np.asarray(b["cells"], dtype=np.int64).ravel()
        (on if str(b["name"]) in only else off)[cells] = True
    return on | ~off


def _draw_bodies(ax, bodies: list[dict], xy: np.ndarray, *, reference: bool = False,
                 only: set[str] | None = None) -> None:
    """Cells (light edges), outlines and frames of all bodies at node positions ``xy`` (m).

    ``reference``: the undeformed configuration as thin dashed grey outlines only.
    ``only``: draw just these bodies (those built at a construction stage); each body keeps
    its colour.
    """
    from matplotlib.collections import LineCollection, PolyCollection

    for j, b in enumerate(bodies):
        cells = np.asarray(b["cells"], dtype=np.int64)
        if not cells.size or (only is not None and str(b["name"]) not in only):
            continue
        color = "0.6" if reference else f"C{j % 10}"
        style = {"linestyles": "--", "linewidths": 0.7, "zorder": 1} if reference else {}
        if str(b.get("kind")) == "frame" or cells.shape[1] == 2:
            ax.add_collection(LineCollection(
                xy[cells[:, :2]], colors=color,
                **(style or {"linewidths": 2.4, "capstyle": "round", "zorder": 3}),
            ))
            continue
        element = str(b.get("element", ""))
        if not reference:
            ring, _ = _ring(element, cells.shape[1])
            ax.add_collection(PolyCollection(
                xy[cells[:, ring]], facecolors=color, alpha=0.12, edgecolors="none", zorder=1,
            ))
            ax.add_collection(PolyCollection(
                xy[cells[:, ring]], facecolors="none", edgecolors="0.55", linewidths=0.3,
                zorder=2,
            ))
        edges = _boundary_edges(_cell_edges(cells, element))
        ax.add_collection(LineCollection(
            xy[edges], colors=color, **(style or {"linewidths": 1.3, "zorder": 3}),
        ))


def _cfe_displacement(points: np.ndarray, un: np.ndarray, xc: np.ndarray) -> np.ndarray:
    """Displacements (m, 2) at the CFE positions ``xc``: the mean of the (at most two,
    coincident) nodes nearest to each CFE (its S+ and S− nodes), ``un`` nodal (n, 2)."""
    from scipy.spatial import cKDTree

    if not len(xc):
        return np.zeros((0, 2))
    k = min(2, len(points))
    d, j = cKDTree(points).query(xc, k=k)
    d, j = d.reshape(len(xc), k), j.reshape(len(xc), k)
    both = d[:, -1] <= d[:, 0] + 1e-9 * _extent(points)
    w = np.column_stack([np.ones(len(xc)), both.astype(float)])[:, :k]
    return np.einsum("mk,mkc->mc", w, un[j]) / w.sum(axis=1)[:, None]


def _state_handles(codes: np.ndarray, *, bars: bool = False) -> list:
    """Legend handles of the contact states present in ``codes``: dots with their counts, or
    (``bars``) patches named ``state …``."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    out = []
    for cs in ContactState:
        n = int(np.sum(codes == int(cs)))
        if n and bars:
            out.append(Patch(facecolor=STATE_COLORS[cs], edgecolor="0.4",
                             label=f"state {cs.label}"))
        elif n:
            out.append(Line2D([], [], ls="none", marker="o", ms=7, mfc=STATE_COLORS[cs],
                              mec="0.2", label=f"{cs.label} ({n})"))
    return out


def _transition_handles(transitions: Sequence[Transition], prefix: str = "") -> list:
    """Legend handles of the event markers of the transitions present."""
    from matplotlib.lines import Line2D

    return [
        Line2D([], [], ls="none", marker=TRANSITION_MARKERS[t][0],
               color=TRANSITION_MARKERS[t][1], mec="k", mew=0.4, label=prefix + t.value)
        for t in Transition if t in set(transitions)
    ]


def _segment_chain(res: StaticResult, seg: int) -> tuple[np.ndarray, np.ndarray]:
    """Reported states along segment ``seg`` and their λ, from the segment's start.

    When the segment has no ``segment_start`` state of its own, the state before it (the end of
    the previous segment) is prepended at the segment's starting λ: it is the same state.
    """
    idx = np.flatnonzero(np.asarray(res.segment) == seg)
    lam = np.asarray(res.lam, dtype=float)[idx]
    first = str(np.asarray(res.kind)[idx[0]]) if idx.size else "start"
    if idx.size and idx[0] > 0 and first not in ("start", "segment_start") and (
        0 <= seg < len(res.segments)
    ):
        idx, lam = np.r_[idx[0] - 1, idx], np.r_[float(res.segments[seg][1]), lam]
    return idx, lam


def _path_fraction(lam: np.ndarray) -> np.ndarray:
    """Fraction 0 → 1 of the λ range a segment covered (from its start; 1 if it has none)."""
    span = np.max(np.abs(lam - lam[0]), initial=0.0)
    return np.abs(lam - lam[0]) / span if span > 0 else np.ones_like(lam)


def _segments_reached(res: StaticResult) -> list[int]:
    return [int(s) for s in dict.fromkeys(np.asarray(res.segment).tolist())]


# --------------------------------------------------------------------------------------------
# deformed shape
# --------------------------------------------------------------------------------------------
#: stress components of :func:`plot_deformed`: column of the (n_el, 4) element stresses
#: σxx, σyy, σxy, σzz (−1: von Mises) and label
_STRESS: dict[str, tuple[int, str]] = {
    "sxx": (0, r"$\sigma_{xx}$"),
    "syy": (1, r"$\sigma_{yy}$"),
    "sxy": (2, r"$\sigma_{xy}$"),
    "szz": (3, r"$\sigma_{zz}$"),
    "mises": (-1, r"von Mises stress $\sigma_{vM}$"),
}
_STRESS_ALIASES = {"von_mises": "mises", "vm": "mises", "von mises": "mises", "svm": "mises"}
#: the (at most) five load patterns' arrow colours
_LOAD_COLORS = ("#e6194b", "#f58231", "#911eb4", "#000075", "#808000")


def _stress_component(name: str) -> tuple[int, str]:
    """(column, label) of a stress component name, or a ValueError listing the names."""
    key = str(name).strip().lower()
    key = _STRESS_ALIASES.get(key, key).replace("σ", "s").replace("sigma", "s")
    key = key.replace("_", "").replace(" ", "")
    if key in ("xx", "yy", "xy", "zz"):
        key = "s" + key
    if key not in _STRESS:
        raise ValueError(f"stress={name!r}: use one of {', '.join(_STRESS)} (Pa)")
    return _STRESS[key]


def _cell_stress(bodies: list[dict], per_body: dict[str, np.ndarray], xy: np.ndarray,
                 column: int) -> tuple[list[np.ndarray], np.ndarray]:
    """(cell polygons at ``xy``, value of each cell, Pa) of the continuum bodies that have
    element stresses: component ``column`` of σxx, σyy, σxy, σzz, or von Mises (−1)."""
    polys: list[np.ndarray] = []
    values = []
    for b in bodies:
        cells = np.asarray(b["cells"], dtype=np.int64)
        sig = per_body.get(str(b["name"]))
        if (sig is None or str(b.get("kind")) == "frame" or cells.ndim != 2
                or cells.shape[1] < 3 or len(sig) != len(cells)):
            continue
        sig = np.asarray(sig, dtype=float)
        if column >= 0:
            v = sig[:, column]
        else:
            sx, sy, txy, sz = sig.T
            v = np.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2)
                        + 3.0 * txy**2)
        ring, _ = _ring(str(b.get("element", "")), cells.shape[1])
        polys.extend(xy[cells[:, ring]])
        values.append(v)
    if not polys:
        raise ValueError("no continuum body with element stresses to colour")
    return polys, np.concatenate(values)


def _draw_stress(fig: Figure, ax, polys: list[np.ndarray], values: np.ndarray,
                 component: tuple[int, str]) -> None:
    """Cells filled by ``values`` (Pa, one per cell) with a colour bar in MPa, kPa or Pa:
    a diverging map symmetric about 0 for a component, a sequential one for von Mises."""
    from matplotlib.collections import PolyCollection

    div, unit = _stress_scale(values)
    v = values / div
    column, label = component
    peak = float(np.max(np.abs(v), initial=0.0)) or 1.0
    lim = (0.0, peak) if column < 0 else (-peak, peak)
    pc = PolyCollection(polys, array=v, cmap="viridis" if column < 0 else "RdBu_r",
                        edgecolors="none", zorder=1.5)
    pc.set_clim(*lim)
    ax.add_collection(pc)
    fig.colorbar(pc, ax=ax, label=f"{label}, {unit}", shrink=0.9)


def _body_centroid(b: dict, xy: np.ndarray) -> np.ndarray:
    """Centroid (2,) of one body of ``geometry["bodies"]`` at node positions ``xy`` (m):
    area-weighted over the cells (the centre of mass of a body of uniform density); frames:
    the mean of the element mid-points weighted by length."""
    cells = np.asarray(b["cells"], dtype=np.int64)
    if str(b.get("kind")) == "frame" or cells.shape[1] == 2:
        ends = xy[cells[:, :2]]
        w = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)
        mid = ends.mean(axis=1)
    else:
        ring, _ = _ring(str(b.get("element", "")), cells.shape[1])
        poly = xy[cells[:, ring]]
        nxt = np.roll(poly, -1, axis=1)
        cross = poly[..., 0] * nxt[..., 1] - nxt[..., 0] * poly[..., 1]
        w = 0.5 * cross.sum(axis=1)  # signed areas of the cells
        with np.errstate(invalid="ignore", divide="ignore"):
            mid = np.einsum("cr,crk->ck", cross, poly + nxt) / (6.0 * w[:, None])
    ok = np.isfinite(mid).all(axis=1) & (np.abs(w) > 0)
    return (np.average(mid[ok], axis=0, weights=np.abs(w[ok])) if ok.any()
            else xy[np.unique(cells)].mean(axis=0))


def _label_bodies(ax, bodies: list[dict], xy: np.ndarray, only: set[str] | None = None
                  ) -> None:
    """Each body's name at its centroid (:func:`_body_centroid`), positions ``xy`` (m);
    ``only`` these bodies."""
    for j, b in enumerate(bodies):
        cells = np.asarray(b["cells"], dtype=np.int64)
        if not cells.size or (only is not None and str(b["name"]) not in only):
            continue
        c = _body_centroid(b, xy)
        ax.text(c[0], c[1], str(b["name"]), ha="center", va="center", fontsize=9,
                fontweight="bold", color=f"C{j % 10}", zorder=6, gid="body_label",
                bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.75})


def _nodal_forces(f: np.ndarray, dof_of: np.ndarray) -> np.ndarray:
    """Nodal forces (n_nodes, 2), N, of a load vector ``f``: a DOF shared by tied nodes
    counts once (at its first node)."""
    out = np.zeros((len(dof_of), 2))
    for c in (0, 1):
        d = dof_of[:, c]
        nodes = np.flatnonzero(d >= 0)
        _, first = np.unique(d[nodes], return_index=True)
        nodes = nodes[first]
        out[nodes, c] = f[d[nodes]]
    return out


def _body_force_parts(system, pattern: str) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """The body forces (:class:`~stepcontact.model.BodyForce`, self-weight) of load pattern
    ``pattern`` of an assembled ``system``, per unit λ, one entry per continuum body:
    (body name, its global node ids (k,), its consistent nodal forces (k, 2), N) — the
    vectors the assembly adds (:func:`stepcontact.fem.continuum.body_force`).  Frames keep
    their weight among the distributed loads (their consistent loads carry end moments)."""
    from stepcontact.fem import continuum as _fem
    from stepcontact.model import Body, BodyForce

    model = getattr(system, "model", None)
    if model is None or not any(p.name == pattern for p in model.patterns):
        return []  # (a discrete model, or a pattern of a construction stage)
    loads = model.pattern(pattern).loads
    off = model.node_offsets
    out: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for ld in loads:
        if not isinstance(ld, BodyForce):
            continue
        for bn in ld.bodies or tuple(b.name for b in model.bodies):
            b = model.body(bn)
            if not isinstance(b, Body):
                continue
            fb = np.asarray(_fem.body_force(b, ld.g, model.thickness), float).reshape(-1, 2)
            ids = off[b.name] + np.arange(b.n_nodes)
            prev = out.get(b.name, (ids, np.zeros_like(fb)))[1]
            out[b.name] = (ids, prev + fb)
    return [(name, ids, fb) for name, (ids, fb) in out.items()]


def _load_arrows(res: StaticResult, i: int, xy: np.ndarray, dof_of: np.ndarray,
                 size: float, shown: np.ndarray | None = None) -> list[dict]:
    """Arrows of the load patterns at state ``i`` (factor ≠ 0): for each, ``name``, ``lam``
    (its factor; None for a water level), ``at`` (k, 2) arrow tips and ``vec`` (k, 2) arrow
    vectors (m, scaled for visibility) of its distributed loads, ``F`` (F_x, F_y), N, the
    pattern's resultant, ``nodal`` (from the assembled load vectors, else one arrow on the
    line of action of the resultant), and its body forces (self-weight) as one resultant
    arrow per body: ``body`` a list of (body name, centroid (2,) at ``xy``, resultant (2,),
    N) and ``body_vec`` (j, 2) those arrows' vectors (m; tails at the centroids).

    With the assembled load vectors (an in-memory result, or one given its model with
    ``res.recover_fields(model)``), a pattern's body forces are split from its other loads:
    each body's weight W = Σ of its consistent nodal forces (= ρ g A t exactly) is drawn at
    the body's centroid (its centre of mass, the centroid of a uniform body force), the rest
    (water pressure, tractions, nodal forces) as nodal arrows.  Without them, one arrow per
    pattern on the line of action x F_y − y F_x = M_z of its stored resultant.
    ``shown``: (n_nodes,) bool, the nodal forces at the other nodes (of bodies not yet built
    at a construction stage, which carry no load) are left out."""
    names = list(res.pattern_names)
    factors = np.asarray(res.factors, dtype=float).reshape(res.n_states, -1)[i]
    groups: dict[str, list[int]] = {}
    virtual = {v: p for p, vs in res.level_patterns.items() for v in vs}
    for j, name in enumerate(names):
        groups.setdefault(virtual.get(name, name), []).append(j)
    system = getattr(getattr(res._recover, "cond", None), "system", None)
    loads = getattr(system, "loads", None)
    nodal = isinstance(loads, dict) and all(n in loads for n in names)
    R = np.asarray(res.load_resultants, dtype=float)
    centre = 0.5 * (xy.min(axis=0) + xy.max(axis=0))
    geo_bodies = {str(b["name"]): b for b in (res.geometry or {}).get("bodies", [])}
    out = []
    for name, idx in groups.items():
        if not np.any(factors[idx] != 0):
            continue
        lam = None if name in res.level_patterns else float(factors[idx[0]])
        if nodal:
            f = sum(factors[j] * np.asarray(loads[names[j]].f, float) for j in idx)
            F = _nodal_forces(f, dof_of)
            if shown is not None:
                F = np.where(shown[:, None], F, 0.0)
            total = F.sum(axis=0)
            body = []
            if lam is not None:  # self-weight: one resultant per body, at its centroid
                rest = np.array(f, dtype=float)
                for bname, ids, fb in _body_force_parts(system, name):
                    if (shown is not None and not shown[ids].all()) or bname not in geo_bodies:
                        continue
                    # what remains: the pattern's other loads (in DOFs, as the assembly adds
                    # it: tied nodes share theirs)
                    np.add.at(rest, dof_of[ids][:, :2].ravel(), -lam * fb.ravel())
                    body.append((bname, _body_centroid(geo_bodies[bname], xy),
                                 lam * fb.sum(axis=0)))
                if body:
                    F = _nodal_forces(rest, dof_of)
                    if shown is not None:
                        F = np.where(shown[:, None], F, 0.0)
            mag = np.linalg.norm(F, axis=1)
            big = float(mag.max(initial=0.0))
            keep = (np.flatnonzero(mag > 1e-9 * max(big, float(np.linalg.norm(total))))
                    if big > 0 else np.zeros(0, int))
            if body:  # round-off of the subtraction is no load
                keep = keep[mag[keep] > 1e-9 * max(np.linalg.norm(w) for _, _, w in body)]
            if not keep.size and not body:
                continue
            peak = max((float(np.linalg.norm(w)) for _, _, w in body), default=0.0)
            bvec = (np.array([w for _, _, w in body]) * (0.15 * size / peak) if peak > 0
                    else np.zeros((0, 2)))
            out.append({"name": name, "lam": lam, "at": xy[keep],
                        "vec": F[keep] * (0.1 * size / big) if keep.size else np.zeros((0, 2)),
                        "F": total, "nodal": True, "body": body, "body_vec": bvec})
            continue
        if R.shape != (len(names), 3):
            continue  # a result written before the resultants were stored
        Fx, Fy, Mz = factors[idx] @ R[idx]
        F2 = Fx * Fx + Fy * Fy
        if not (np.isfinite(F2) and F2 > 0):
            continue
        # the point of the line of action x F_y − y F_x = M_z nearest the model's centre
        s = (Mz - (centre[0] * Fy - centre[1] * Fx)) / F2
        at = centre + s * np.array([Fy, -Fx])
        if not np.all(np.isfinite(at)) or np.linalg.norm(at - centre) > size:
            at = centre
        vec = np.array([Fx, Fy]) * (0.15 * size / math.sqrt(F2))
        out.append({"name": name, "lam": lam, "at": at[None, :], "vec": vec[None, :],
                    "F": np.array([Fx, Fy]), "nodal": False, "body": [],
                    "body_vec": np.zeros((0, 2))})
    return out


def _force_text(F: np.ndarray) -> str:
    """``(0, -1.41264) MN``: a force (F_x, F_y), N, in N, kN or MN to 6 significant digits."""
    F = np.asarray(F, dtype=float)
    F = np.where(np.abs(F) <= 1e-12 * np.abs(F).max(initial=0.0), 0.0, F)  # round-off: 0
    div, unit = _force_scale(F, 0)
    return f"({F[0] / div:.6g}, {F[1] / div:.6g}) {unit}"


def _draw_load_arrows(ax, arrows: list[dict]) -> list:
    """The arrows of :func:`_load_arrows` (distributed loads: tips at the points of
    application; body forces: tails at the bodies' centroids, gid ``body force:<pattern>``)
    and their legend handles: pattern, λ and the resultant (F_x, F_y)."""
    from matplotlib.lines import Line2D

    handles = []
    for j, a in enumerate(arrows):
        color = _LOAD_COLORS[j % len(_LOAD_COLORS)]
        if len(a["at"]):
            ax.quiver(a["at"][:, 0], a["at"][:, 1], a["vec"][:, 0], a["vec"][:, 1],
                      angles="xy", scale_units="xy", scale=1.0, pivot="tip", color=color,
                      width=0.004 if a["nodal"] else 0.007, zorder=5, gid=f"load:{a['name']}")
        if a["body"]:
            at = np.array([c for _, c, _ in a["body"]])
            ax.quiver(at[:, 0], at[:, 1], a["body_vec"][:, 0], a["body_vec"][:, 1],
                      angles="xy", scale_units="xy", scale=1.0, pivot="tail", color=color,
                      width=0.008, zorder=5.5, gid=f"body force:{a['name']}")
        lam = "" if a["lam"] is None else f" at λ = {_lam_text(a['lam'])}"
        where = "" if a["nodal"] else " (its line of action)"
        if a["body"]:
            where = (", self-weight as one arrow per body at its centre of mass"
                     if len(a["body"]) > 1 else
                     f", self-weight of '{a['body'][0][0]}' at its centre of mass")
        handles.append(Line2D(
            [], [], color=color, lw=2.0, marker=">", ms=6,
            label=f"'{a['name']}'{lam}: resultant F = {_force_text(a['F'])}{where}"))
    return handles


def plot_deformed(
    res: StaticResult,
    state: int | None = None,
    scale: float | None = None,
    path: str | os.PathLike[str] | None = None,
    *,
    dpi: float = DPI,
    stress: str | None = None,
    labels: bool = True,
    loads: bool = True,
) -> Figure:
    """The deformed mesh of every body with the CFEs coloured by their contact state.

    Continuum bodies are drawn as their cells (light edges, tinted by body) and outline;
    frames as lines between their displaced nodes.  The undeformed outlines are dashed grey.
    Each CFE is a dot at its displaced position (mean of its S+ and S− nodes), coloured by
    its state in the working scheme after the state (open / stick / slip+ / slip− / bonded).

    For a staged result only the bodies built at the state, the CFEs made by then and the
    loads on those bodies are drawn (the extent of the figure is theirs), and the title names
    the stage.

    Optionally the cells are coloured by a stress component of the state (``stress``: the
    element stresses of :meth:`StaticResult.stress`, with a colour bar in MPa, kPa or Pa).
    Each body is named at its centroid.  The loads of the patterns at the state (factor ≠ 0)
    are drawn as arrows, one colour per pattern, each pattern scaled for visibility (its
    longest arrow 10 % of the model size), its resultant (F_x, F_y) in the legend below: the
    nodal forces of the assembled load vectors when the model is available (an in-memory
    result, or after ``res.recover_fields(model)``) — a body force (self-weight,
    :class:`~stepcontact.model.BodyForce`) as one arrow per body from its centroid (its
    centre of mass), of length 15 % of the model size for the heaviest body, the other loads
    (water pressure, tractions, nodal forces) at their nodes — else one arrow per pattern on
    the line of action of its stored resultant (:meth:`StaticResult.load_resultant`).

    Parameters
    ----------
    res : StaticResult
        Needs ``geometry`` and the displacements of ``state`` (stored fields, or an in-memory
        result that recovers them).
    state : int, optional
        Reported state (negative: from the end); default the last one.
    scale : float, optional
        Displacement magnification (dimensionless); default automatic: the largest 1, 2 or
        5 × 10^k that makes the largest displacement at most 10 % of the model size.  Stated
        in the title.
    path : str or PathLike, optional
        Save the figure there (``.png``, ``.pdf`` or ``.svg``); parent directories are created.
    dpi : float
        Resolution of a saved raster figure, dots per inch.
    stress : str, optional
        Colour the cells of the continuum bodies by this stress component (Pa): ``"sxx"``,
        ``"syy"``, ``"sxy"``, ``"szz"`` (also ``"xx"``, ``"σyy"``, …) or ``"mises"`` (von
        Mises equivalent stress, also ``"von_mises"``, ``"vm"``).
    labels : bool
        Name each body at its (deformed) centroid.
    loads : bool
        Draw the load arrows of the patterns at the state.

    Returns
    -------
    matplotlib.figure.Figure

    Example
    -------
    >>> fig = plot_deformed(res, stress="mises", path="out/mises.png")  # doctest: +SKIP
    """
    out = figure_path(path, dpi)
    i = _state_index(res, res.n_states - 1 if state is None else state)
    if scale is not None and not (np.isfinite(scale) and scale > 0):
        raise ValueError(f"scale={scale}: the magnification must be a positive number")
    component = None if stress is None else _stress_component(stress)
    points, dof_of, bodies = _geometry(res)
    stage = _stage_of(res, i)
    only = None if stage is None else set(res.stage_bodies[stage])  # built at the state
    shown = _shown_nodes(bodies, len(points), only)
    un = _node_u(dof_of, _field(res, i))
    size = _extent(points[shown])
    umax = float(np.max(np.linalg.norm(un[shown], axis=1), initial=0.0))
    if scale is None:
        scale = _nice_floor(0.1 * size / umax) if umax > 0 else 1.0
    xy = points + scale * un
    cells_stress = None
    if component is not None:
        try:
            per_body = res.stress(i)
        except KeyError as e:
            raise ValueError(str(e.args[0])) from None
        drawn = [b for b in bodies if only is None or str(b["name"]) in only]
        cells_stress = _cell_stress(drawn, per_body, xy, component[0])
    arrows = _load_arrows(res, i, xy, dof_of, size, shown) if loads else []

    tips = [xy[shown]] + [np.concatenate([
        a["at"], a["at"] - a["vec"],
        np.reshape([c + v for (_, c, _), v in zip(a["body"], a["body_vec"], strict=True)],
                   (-1, 2))]) for a in arrows]
    lo = np.minimum(points[shown].min(0), np.min([v.min(0) for v in tips], axis=0))
    hi = np.maximum(points[shown].max(0), np.max([v.max(0) for v in tips], axis=0))
    w, h = np.maximum(hi - lo, 1e-3 * size)
    fig = new_figure(figsize=(9.0, round(float(np.clip(9.0 * h / w + 1.2, 3.0, 9.0)), 1)))
    ax = fig.add_subplot()
    _draw_bodies(ax, bodies, points, reference=True, only=only)
    _draw_bodies(ax, bodies, xy, only=only)
    if cells_stress is not None and component is not None:
        _draw_stress(fig, ax, *cells_stress, component)
    if labels:
        _label_bodies(ax, bodies, xy, only)
    load_handles = _draw_load_arrows(ax, arrows)
    handles = []
    act = _active_cfes(res, stage)  # the CFEs made at the state
    if res.m and act.any():
        codes = np.asarray(res.state)[i][act]
        xc = np.asarray(res.cfe["x"], dtype=float).reshape(res.m, 2)[act]
        pc = xc + scale * _cfe_displacement(points, un, xc)
        ax.scatter(pc[:, 0], pc[:, 1], s=22, c=[STATE_COLORS[ContactState(int(v))] for v in codes],
                   edgecolors="0.15", linewidths=0.5, zorder=4)
        handles = _state_handles(codes)
    pad = 0.04 * max(w, h)
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x, m")
    ax.set_ylabel("y, m")
    ax.grid(True, alpha=0.2)
    if handles:
        ax.legend(handles=handles, title="CFE state", fontsize=8, title_fontsize=8, loc="best")
    if load_handles:
        _legend_below(fig, load_handles, 1 if len(load_handles) > 2 else len(load_handles),
                      fontsize=8, title="loads (arrows scaled for visibility)",
                      title_fontsize=8, frameon=False)
    seg = int(res.segment[i])
    built = ("" if only is None else f"\n{_stage_text(res, stage)}: bodies built "
             + ", ".join(str(b["name"]) for b in bodies if str(b["name"]) in only))
    fig.suptitle(
        f"Deformed shape at state {i} ({res.kind[i]}, "
        f"{_at_text(res, seg, float(res.lam[i]))})\ndisplacements × {scale:g}, "
        f"max |u| = {umax:.3g} m{built}"
    )
    # the equal aspect shrinks the axes after the constrained layout placed the labels and
    # the legend below: one draw settles the layout (else the first one, a saved file's,
    # may put the x label on the legend)
    fig.draw_without_rendering()
    save_figure(fig, out, dpi)
    return fig


# --------------------------------------------------------------------------------------------
# load–displacement curve
# --------------------------------------------------------------------------------------------
def _resolve_node(
    res: StaticResult,
    node: int | Sequence[float] | None,
    body: str | None,
    comp: int,
    u_last: np.ndarray,
) -> int:
    """Global node index from an index, coordinates (m) or None (the largest value of
    ``u_last`` — a displacement vector, or |u| of each DOF over the path — in ``comp``)."""
    points, dof_of, bodies = _geometry(res)
    names = [str(b["name"]) for b in bodies]
    owner = np.full(len(points), -1)
    for j, b in enumerate(bodies):
        owner[np.asarray(b["cells"], dtype=np.int64).ravel()] = j
    if body is not None and body not in names:
        raise ValueError(f"body '{body}' does not exist; bodies: {', '.join(names)}")
    cand = np.flatnonzero(owner == names.index(body)) if body is not None else np.arange(
        len(points))
    if isinstance(node, int | np.integer) and not isinstance(node, bool):
        if not 0 <= int(node) < len(points):
            raise ValueError(f"node {node} does not exist: nodes are 0..{len(points) - 1}")
        if dof_of[int(node), comp] < 0:
            raise ValueError(f"node {node} has no DOF {('ux', 'uy', 'rz')[comp]}")
        return int(node)
    cand = cand[dof_of[cand, comp] >= 0]
    if not cand.size:
        raise ValueError(f"no node{'' if body is None else f' of {body!r}'} has DOF "
                         f"{('ux', 'uy', 'rz')[comp]}")
    if node is None:
        return int(cand[np.argmax(np.abs(_node_u(dof_of, u_last, (comp,))[cand, 0]))])
    try:
        xy = np.asarray(node, dtype=float).reshape(2)
    except (TypeError, ValueError):
        raise ValueError(
            f"node={node!r}: give a node index or its coordinates (x, y) in m"
        ) from None
    d = np.linalg.norm(points[cand] - xy, axis=1)
    size = _extent(points)
    if d.min() > 0.05 * size:
        k = int(cand[np.argmin(d)])
        raise ValueError(f"no node near ({xy[0]:g}, {xy[1]:g}): the nearest, node {k} at "
                         f"({points[k, 0]:g}, {points[k, 1]:g}), is {d.min():.3g} m away")
    near = cand[d <= d.min() + 1e-9 * size]
    shared = sorted({names[owner[k]] for k in near})
    if len(shared) > 1:
        raise ValueError(f"the node at ({xy[0]:g}, {xy[1]:g}) is shared by bodies "
                         f"{', '.join(map(repr, shared))}: choose one (body=...; CLI: --body)")
    return int(near[0])


def _most_moving(res: StaticResult, node: int | Sequence[float] | None, body: str | None,
                 comp: int, peak: np.ndarray) -> tuple[int, int]:
    """(node, component) of the load–displacement curve: ``node`` (or the node with the
    largest ``peak`` — |u| of each DOF over the path — in ``comp``) and ``comp`` (or, when
    −1, the one of u_x, u_y in which it moves most)."""
    if comp >= 0:
        return _resolve_node(res, node, body, comp, peak), comp
    _, dof_of, _ = _geometry(res)
    best: tuple[float, int, int] | None = None
    for c in (0, 1):
        try:
            k = _resolve_node(res, node, body, c, peak)
        except ValueError:
            if c == 0:
                continue
            if best is None:
                raise
            break
        if best is None or peak[dof_of[k, c]] > best[0]:
            best = (float(peak[dof_of[k, c]]), k, c)
    assert best is not None
    return best[1], best[2]


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


def _force_scale(values: np.ndarray, comp: int) -> tuple[float, str]:
    """Divisor and unit for forces (N, kN, MN) or moments (N·m, kN·m, MN·m)."""
    big = float(np.max(np.abs(values), initial=0.0))
    div, prefix = next(((d, p) for d, p in ((1e6, "M"), (1e3, "k")) if big >= d), (1.0, ""))
    return div, f"{prefix}N·m" if comp == 2 else f"{prefix}N"


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
        coincident nodes of different bodies).  Default: the node with the largest |u| in
        ``dof`` over the path (at any reported state).
    dof : "x", "y" or "rz", optional
        Displacement component u_x, u_y (m) or the rotation φ_z of a frame node (rad).
        Default: the one of u_x, u_y that moves most over the path (of ``node``, or of the
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
    if dof is not None and dof not in _DOFS:
        raise ValueError(f"dof={dof!r}: use 'x', 'y' or 'rz'")
    if axis not in ("lam", "path"):
        raise ValueError(f"axis={axis!r}: use 'lam' or 'path'")
    if reaction is not None and dof is None:
        dof = "y"
    comp = -1 if dof is None else _DOFS[dof]
    if reaction is not None:
        try:
            u = res.reaction(reaction, dof)
        except KeyError as e:
            raise ValueError(str(e.args[0])) from None
        div, unit = _force_scale(u, comp)
        xlabel = f"reaction of '{reaction}' along {dof} (on the structure), {unit}"
    else:
        U = _all_fields(res)
        points, dof_of, bodies = _geometry(res)
        peak = np.abs(U).max(axis=0, initial=0.0)  # |u| of every DOF over the path
        k, comp = _most_moving(res, node, body, comp, peak)
        u = U[:, dof_of[k, comp]]
        div, unit = (1.0, "rad") if comp == 2 else _length_scale(u)
        owner = next((str(b["name"]) for b in bodies if np.any(np.asarray(b["cells"]) == k)),
                     "?")
        why = ("; moves most over the path" if node is None and dof is None else
               "; largest |u| over the path" if node is None else "")
        xlabel = (f"{_DOF_LABEL[comp]} of node {k} ('{owner}', x = {points[k, 0]:.4g} m, "
                  f"y = {points[k, 1]:.4g} m{why}), {unit}")

    segs = _segments_reached(res)
    panels = len(segs) if axis == "lam" else 1
    fig = new_figure(figsize=(7.5, min(3.0 * panels + 1.2, 11.0)))
    axes = np.atleast_1d(fig.subplots(panels, 1, sharex=True, squeeze=False)[:, 0])
    seen: list[Transition] = []
    for j, s in enumerate(segs):
        ax = axes[j if axis == "lam" else 0]
        idx, lam = _segment_chain(res, s)
        if axis == "path":
            lam = s + _path_fraction(lam)
        stage = _segment_stage(res, s)
        ax.plot(u[idx] / div, lam, color=f"C{j % 10}", lw=1.3, marker=".", ms=4,
                label=f"segment {s}: '{_pattern_of(res, s)}'"
                + ("" if stage is None else f" ({_stage_text(res, stage)})"))
        if axis == "lam" and stage is not None:
            ax.set_title(_stage_text(res, stage), fontsize=8, loc="left")
        y_of = dict(zip(idx.tolist(), lam.tolist(), strict=True))
        marks = {(e.state, e.transition) for e in res.events if e.segment == s}
        for i, tr in sorted(marks, key=lambda m: (m[0], m[1].value)):
            marker, color = TRANSITION_MARKERS[tr]
            ax.plot([u[i] / div], [y_of.get(i, float(res.lam[i]))], ls="none",
                    marker=marker, color=color, ms=8, mec="k", mew=0.4, zorder=4)
            seen.append(tr)
        if axis == "lam":
            ax.set_ylabel(_axis_text(res, s))
        lost = next((mu.equilibrium_lost for mu in res.multipliers
                     if mu.segment == s and mu.equilibrium_lost is not None), None)
        if lost is not None and idx.size:
            _mark_equilibrium_lost(ax, u[idx[-1]] / div, lost if axis == "lam" else lam[-1],
                                   lost, _is_level(res, s))
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


# --------------------------------------------------------------------------------------------
# event timeline
# --------------------------------------------------------------------------------------------
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
    from matplotlib.collections import LineCollection

    out = figure_path(path, dpi)
    names = list(res.interface_names)
    segs = _segments_reached(res)
    nrow, ncol = max(1, len(names)), max(1, len(segs))
    fig = new_figure(figsize=(min(3.8 * ncol + 2.0, 16.0), min(2.6 * nrow + 1.6, 12.0)))
    fig.suptitle(f"Event timeline — {len(res.events)} events, {res.m} CFEs, "
                 f"{res.status.value}")
    if not names or res.m == 0 or not segs:
        ax = fig.add_subplot()
        ax.text(0.5, 0.5, "no contact interfaces", ha="center", va="center")
        ax.set_axis_off()
        save_figure(fig, out, dpi)
        return fig
    axes = fig.subplots(nrow, ncol, squeeze=False, sharey="row")
    iface = np.asarray(res.cfe["interface"])
    pos = np.asarray(res.cfe["s"], dtype=float)
    st = np.asarray(res.state)
    made = _made(res)
    palette = np.array([STATE_COLORS[cs] for cs in ContactState])
    for c, s in enumerate(segs):
        idx, lam = _segment_chain(res, s)
        for r, name in enumerate(names):
            ax = axes[r, c]
            k = np.flatnonzero(iface == r)
            lw = float(np.clip(150.0 / max(k.size, 1), 0.8, 6.0))
            if k.size and idx.size > 1:
                shape = (idx.size - 1, k.size)  # (intervals between states, CFEs)
                y = np.broadcast_to(pos[k][None, :], shape)
                ends = [np.stack([np.broadcast_to(v[:, None], shape), y], -1)
                        for v in (lam[:-1], lam[1:])]
                segments = np.stack(ends, axis=2)  # (intervals, CFEs, 2 ends, xy)
                # CFEs not yet made (construction stages): no bar
                on = (np.ones(shape, bool) if made is None else made[idx[:-1]][:, k]).ravel()
                ax.add_collection(LineCollection(
                    segments.reshape(-1, 2, 2)[on],
                    colors=palette[st[idx[:-1]][:, k].ravel()][on],
                    linewidths=lw, capstyle="butt", zorder=1,
                ))
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
                span = (f"t = {lam[0]:.6g} → {lam[-1]:.6g} s"
                        if getattr(res, "path_axis", "lam") == "time" else
                        f"segment {s}: {_pattern_of(res, s)} h={_lam_text(lam[0])} → "
                        f"{_lam_text(lam[-1])} m" if _is_level(res, s) else
                        f"segment {s}: {_pattern_of(res, s)} λ={_lam_text(lam[0])} → "
                        f"{_lam_text(lam[-1])}")
                stage = _segment_stage(res, s)
                ax.set_title(span if stage is None else f"{_stage_text(res, stage)}\n{span}",
                             fontsize=9)
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


# --------------------------------------------------------------------------------------------
# safety of the joints
# --------------------------------------------------------------------------------------------
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
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

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
        ax = fig.add_subplot()
        ax.set_axis_off()
        ax.text(0.5, 0.5, "no contact interfaces" if not names else "no state reported",
                ha="center", va="center")
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
    peak = 1.0
    for col, group in enumerate(groups):
        chains = [_segment_chain(res, sg) for sg in group]
        idx = np.concatenate([c[0] for c in chains])
        lam = np.concatenate([c[1] for c in chains])
        ax_e, ax_s, ax_o = axes[:, col]
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
        title = f"{what}:\n{span}" if not wide[col] else f"{what}: {span}"
        if stage is not None:
            title = f"{_stage_text(res, stage)}\n{title}"
        ax_e.set_title(title, fontsize=8)
        ax_o.set_xlabel(_axis_text(res, group[0]) if wide[col]
                        else _axis_text(res, group[0]).replace(" of ", "\nof ", 1))
        if 0 <= group[0] < len(res.segments) and (
                res.segments[group[0]][2] < res.segments[group[0]][1]):
            ax_o.invert_xaxis()
    axes[0, 0].set_ylabel("eccentricity e / B")
    axes[1, 0].set_ylabel("sliding factor f·|ΣN|/|ΣQ|")
    axes[1, 0].set_ylim(0.0, min(max(2.0, 1.1 * peak), 10.0))
    axes[2, 0].set_ylabel("open length, m")

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
    fig.suptitle("Joint safety along the load path"
                 + (f" (the last {len(groups)} runs of segments)" if cut else "")
                 + f" — {res.status.value}")
    save_figure(fig, out, dpi)
    return fig


# --------------------------------------------------------------------------------------------
# dynamics: time histories and the energy ledger
# --------------------------------------------------------------------------------------------
def _dof_index(res, dof) -> tuple[int, str]:
    """A DOF of a dynamic result: a discrete model's DOF name or a global DOF index; its
    label names the node and direction for a finite-element model (:func:`_dof_label`)."""
    names = list(np.asarray(res.geometry.get("dof_names", []), dtype=str))
    if isinstance(dof, str):
        if dof not in names:
            raise ValueError(f"unknown DOF '{dof}' (known: {', '.join(names) or 'none'}; "
                             "give a global DOF index for a finite-element model, or choose "
                             "a node by point=(x, y), nodes=<node set or node id>)")
        return names.index(dof), dof
    i = int(dof)
    if not 0 <= i < res.u.shape[1]:
        raise ValueError(f"DOF {i} does not exist: the result has DOFs 0..{res.u.shape[1] - 1}")
    if i < len(names):
        return i, names[i]
    return i, f"DOF {i}"


def _dof_curves(res, dofs) -> list[tuple[str, np.ndarray, str, tuple]]:
    """The curves of :func:`plot_time_history` for DOF names or indices (its old input): the
    displacement and velocity of each, labelled by the DOF's node and direction for a
    finite-element model (``node 5 (x = 2, y = 0 m): u_y``), by its name for a discrete
    one."""
    dof_of = np.asarray(res.geometry.get("dof_of", np.zeros((0, 3))), dtype=np.int64)
    out = []
    for i, name in [_dof_index(res, d) for d in ([dofs] if isinstance(dofs, str | int)
                                                  else dofs)]:
        node, comp = np.nonzero(dof_of == i)
        for q in ("u", "v"):
            label = (_node_label(res, int(node[0]), int(comp[0]), q) if node.size
                     else name)
            out.append((q, np.asarray(getattr(res, q))[:, i], label, (i,)))
    return out


#: the quantities of a time history: displacement, velocity, acceleration — attribute of
#: the dynamic result, axis label (m, m/s, m/s²; rad, rad/s, rad/s² for rotations)
_HISTORY_PANELS = {"u": ("u", "displacement, m"), "v": ("v", "velocity, m/s"),
                   "a": ("a", "acceleration, m/s²")}
_COMPONENTS = {"x": 0, "y": 1, "rz": 2}
_COMPONENT_TEXT = ("x", "y", "rz")


def _node_sets_of(res, node: int) -> list[str]:
    """The named node sets (:attr:`StaticResult.node_sets`) that hold ``node``."""
    return [name for name, ids in res.node_sets.items() if node in set(np.asarray(ids).tolist())]


def _node_label(res, node: int, comp: int, what: str, node_set: str | None = None) -> str:
    """``crest (node 412, x = 0, y = 12 m): u_x`` — the node set (``node_set``, else the
    first named set holding the node), the node, its coordinates and the quantity."""
    pts = np.asarray(res.geometry["points"], dtype=float)
    sets = [node_set] if node_set else _node_sets_of(res, node)[:1]
    where = f"node {node}, x = {pts[node, 0]:.4g}, y = {pts[node, 1]:.4g} m"
    sub = "φ_z" if comp == 2 else f"{what}_{_COMPONENT_TEXT[comp]}"
    if comp == 2 and what != "u":
        sub = {"v": "dφ_z/dt", "a": "d²φ_z/dt²"}[what]
    if not sets:
        return f"node {node} (x = {pts[node, 0]:.4g}, y = {pts[node, 1]:.4g} m): {sub}"
    return f"{sets[0]} ({where}): {sub}"


def _history_requests(direction) -> list[tuple[str | None, int]]:
    """(quantity "u"/"v"/"a" or None for every panel, component 0/1/2) of ``direction``:
    ``"x"``, ``"y"``, ``"rz"`` (each panel), or ``"ux"``, ``"vy"``, ``"ax"``, ``"rz"`` …
    (one quantity)."""
    items = [direction] if isinstance(direction, str) else list(direction)
    out = []
    for d in items:
        key = str(d).strip().lower().replace("_", "")
        if key in _COMPONENTS:
            out.append((None, _COMPONENTS[key]))
        elif key[:1] in _HISTORY_PANELS and key[1:] in _COMPONENTS:
            out.append((key[0], _COMPONENTS[key[1:]]))
        else:
            raise ValueError(f"direction={d!r}: use x, y or rz (displacement and velocity), or "
                             "ux, uy, vx, vy, ax, ay (u: displacement, v: velocity, a: "
                             "acceleration)")
    if not out:
        raise ValueError("direction: give at least one of x, y, ux, uy, vx, vy, ax, ay")
    return out


def _node_histories(res, nodes, point, body, direction) -> list[tuple]:
    """(quantity, values (n_states,), label, (node, component)) of the nodes chosen by
    ``nodes`` (a node-set name, a node id or ids, a NodeSet) or ``point`` (the nearest
    node), in ``direction``: the nodes found by :meth:`StaticResult.node_ids`, the
    displacements and velocities read by :meth:`StaticResult.node_history` (the
    accelerations from the same DOFs of ``a``)."""
    try:
        ids = res.node_ids(nodes, point=point, body=body)
    except (KeyError, IndexError, TypeError) as e:
        raise ValueError(str(e.args[0]) if e.args else str(e)) from None
    if len(ids) > MAX_HISTORY_NODES:
        what = f"node set '{nodes}'" if isinstance(nodes, str) else "the selection"
        raise ValueError(f"{what} has {len(ids)} nodes: at most {MAX_HISTORY_NODES} curves "
                         "per direction; choose one node by point=(x, y) or its id")
    set_name = nodes if isinstance(nodes, str) else None
    dof_of = np.asarray(res.geometry["dof_of"], dtype=np.int64)
    out = []
    for what, comp in _history_requests(direction):
        for q in ([what] if what else ["u", "v"]):
            name = ("u", "v", "a").index(q)
            if q == "a":
                if np.size(getattr(res, "a", ())) == 0:
                    raise ValueError("this result has no accelerations")
                d = dof_of[ids, comp]
                if np.any(d < 0):
                    raise ValueError(f"node {int(ids[d < 0][0])} has no DOF "
                                     f"{_COMPONENT_TEXT[comp]}")
                values = np.asarray(res.a)[:, d]
            else:
                quantity = ("u", "v")[name] if comp < 2 else ("rz", "vrz")[name]
                if comp < 2:
                    quantity += _COMPONENT_TEXT[comp]
                try:
                    values = np.asarray(res.node_history(ids, quantity)).reshape(len(res.lam),
                                                                                 -1)
                except (KeyError, IndexError) as e:
                    raise ValueError(str(e.args[0])) from None
            for j, k in enumerate(ids):
                out.append((q, values[:, j], _node_label(res, int(k), comp, q, set_name),
                            (int(k), comp)))
    return out


#: the most nodes a time history draws (per direction): a larger node set is an error
MAX_HISTORY_NODES = 12


def _mark_events(ax, res) -> list:
    """Event times as thin vertical lines in the transition's colour; legend handles."""
    from matplotlib.transforms import blended_transform_factory

    seen: list = []
    by: dict = {}
    for ev in res.events:
        by.setdefault(ev.transition, []).append(ev.lam)
        if ev.transition not in seen:
            seen.append(ev.transition)
    # one collection per transition (hundreds of events draw as fast as one line)
    trans = blended_transform_factory(ax.transData, ax.transAxes)
    for tr, times in by.items():
        color = TRANSITION_MARKERS.get(tr, ("|", "0.5"))[1]
        ax.vlines(times, 0.0, 1.0, transform=trans, colors=color, lw=0.8, alpha=0.7)
    return seen


def plot_time_history(res, dofs: Sequence | None = None,
                      path: str | os.PathLike[str] | None = None, *,
                      point: Sequence[float] | None = None, nodes=None,
                      direction: str | Sequence[str] = ("x", "y"), body: str | None = None,
                      dpi: float = DPI) -> Figure:
    """Displacements, velocities (and accelerations) of chosen nodes against time, with every
    contact event marked by a vertical line in its transition's colour (a dynamic result,
    :func:`~stepcontact.solve_dynamic`).  Units: m, m/s, m/s², s (rad … for rotations).

    Choose what to plot by

    * ``point=(x, y)``: the node nearest the point, m (``body`` chooses among coincident nodes
      of different bodies);
    * ``nodes``: the name of a named node set of the model (``res.node_sets``: those its
      supports, loads, springs, ties and interfaces use; at most
      :data:`MAX_HISTORY_NODES` nodes), a global node id or a sequence of them, or a
      :class:`~stepcontact.model.NodeSet`;
    * ``direction``: ``"x"``, ``"y"``, ``"rz"`` (the displacement and the velocity, one panel
      each), or one quantity ``"ux"``, ``"uy"``, ``"vx"``, ``"vy"``, ``"ax"``, ``"ay"`` (u:
      displacement, v: velocity, a: acceleration), or a sequence of these;
    * or, as before, ``dofs``: a discrete model's DOF names or global DOF indices (the
      displacement and velocity of each).

    Default (none of these): the node that moves most (the largest |u_x| or |u_y| over the
    run).  Displacements are drawn in m, mm or µm, whichever reads best (the axis label
    says which).

    The nodes are found by :meth:`StaticResult.node_ids` and their values read by
    :meth:`StaticResult.node_history` (the same curves).  Every curve is named by its node
    set, node, coordinates and direction, e.g. ``crest (node 412, x = 0, y = 12 m): u_x``;
    the legend is below the panels.

    Example
    -------
    >>> plot_time_history(res, point=(2.0, 0.0), direction="uy")   # doctest: +SKIP
    >>> plot_time_history(res, nodes="crest", direction=("x", "ax"))  # doctest: +SKIP
    """
    out = figure_path(path, dpi)
    if not hasattr(res, "v"):
        raise ValueError("plot_time_history needs a dynamic result (sc.solve_dynamic)")
    if dofs is not None and (point is not None or nodes is not None):
        raise ValueError("give either dofs (DOF names or indices) or point/nodes, not both")
    if dofs is None and point is None and nodes is None:
        if "points" not in (res.geometry or {}):
            raise ValueError("choose what to plot: dofs=<DOF names or indices>")
        peak = np.abs(np.asarray(res.u)).max(axis=0, initial=0.0)  # |u| of every DOF
        nodes, _ = _most_moving(res, None, body, -1, peak)  # the node that moves most
    if dofs is not None:
        curves = _dof_curves(res, dofs)
    else:
        curves = _node_histories(res, nodes, point, body, direction)
    panels = [q for q in ("u", "v", "a") if any(c[0] == q for c in curves)]
    fig = new_figure(figsize=(8.5, 2.4 * len(panels) + 2.0))
    axes = np.atleast_1d(fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0])
    t = np.asarray(res.time)
    # displacements in m, mm or µm (whichever reads best; not with rotations, in rad)
    u_all = [c[1] for c in curves if c[0] == "u"]
    rotation = any(c[0] == "u" and len(c[3]) == 2 and c[3][1] == 2 for c in curves)
    div, unit = (1.0, "m") if rotation or not u_all else _length_scale(np.concatenate(u_all))
    color: dict[tuple, str] = {}  # one colour per node and direction, in every panel
    for q, values, label, key in curves:
        color.setdefault(key, f"C{len(color) % 10}")
        axes[panels.index(q)].plot(t, values / (div if q == "u" else 1.0), lw=1.3,
                                   color=color[key], label=label)
    handles = [ln for ax in axes for ln in ax.get_lines()]
    seen = []
    for ax, q in zip(axes, panels, strict=True):
        seen = _mark_events(ax, res)
        ax.grid(True, alpha=0.3)
        ax.set_ylabel(f"displacement, {unit}" + (" (rad for φ_z)" if rotation else "")
                      if q == "u" else _HISTORY_PANELS[q][1])
    axes[-1].set_xlabel("time t, s")
    _legend_below(fig, [*handles, *_transition_handles(seen, "event: ")], 2,
                  fontsize=8, frameon=False)
    fig.suptitle(f"Time history ({len(res.events)} contact events, Δt = {res.dt:g} s)")
    save_figure(fig, out, dpi)
    return fig


def plot_energy(res, path: str | os.PathLike[str] | None = None, *, dpi: float = DPI
                ) -> Figure:
    """The energy ledger of a dynamic result against time: kinetic, strain, the work of the
    loads and what damping, friction, the impacts, broken bonds (fracture) and the integrator
    dissipated (J), and the balance error."""
    out = figure_path(path, dpi)
    if not getattr(res, "energy", None):
        raise ValueError("plot_energy needs a dynamic result (sc.solve_dynamic)")
    fig = new_figure(figsize=(8.5, 5.5))
    ax = fig.subplots()
    t = np.asarray(res.time)
    for key in ("kinetic", "strain", "external", "damping", "friction", "impact",
                "fracture", "numerical"):
        if key not in res.energy:  # (a result file written before the term existed)
            continue
        vals = np.asarray(res.energy[key])
        if np.any(vals != 0):
            ax.plot(t, vals, lw=1.4, label=key)
    err = float(np.abs(res.energy["error"]).max(initial=0.0))
    _mark_events(ax, res)
    ax.grid(True, alpha=0.3)
    ax.set_xlabel("time t, s")
    ax.set_ylabel("energy, J (per metre of thickness in plane strain)")
    ax.legend(fontsize=8, loc="best")
    fig.suptitle(f"Energy ledger (largest balance error {err:.1e} J)")
    save_figure(fig, out, dpi)
    return fig


__all__ = [
    "DPI",
    "STATE_COLORS",
    "TRANSITION_MARKERS",
    "figure_path",
    "new_figure",
    "save_figure",
    "plot_deformed",
    "plot_event_timeline",
    "plot_interfaces",
    "plot_load_displacement",
    "plot_load_path",
    "plot_safety",
    "plot_time_history",
    "plot_energy",
]
