"""What the figure families of :mod:`stepcontact.post` share: figure creation and atomic
saving, the colours of the contact states and the markers of the transitions, the units
that make stresses, lengths and forces read well, the labels of a point on the load path
(``'push' λ = 23 544``, a water level h in m, a time t in s), the construction stages and
load segments of a result, and the legends of states and events.

matplotlib is imported inside the functions (``import stepcontact`` stays light).  Figures are
built on the Agg canvas without pyplot: nothing is shown, no global figure registry is touched;
the returned :class:`matplotlib.figure.Figure` displays in Jupyter and can be saved again.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from stepcontact.enums import FACET_SLIP, ContactState, Transition
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
#: colour and label of a CFE slipping on a faceted Coulomb cone (3D: state codes
#: ≥ :data:`~stepcontact.enums.FACET_SLIP`, any facet or vertex)
FACETED_SLIP_COLOR = "#ff7f0e"
FACETED_SLIP_LABEL = "slip (faceted)"
_PALETTE = np.array([STATE_COLORS[cs] for cs in ContactState])


def state_colors(codes) -> np.ndarray:
    """The colour of every state code (:data:`STATE_COLORS`; a faceted cone's slip codes
    :data:`FACETED_SLIP_COLOR`), an array of the shape of ``codes``."""
    c = np.asarray(codes, dtype=np.int64)
    return np.where(c >= FACET_SLIP, FACETED_SLIP_COLOR, _PALETTE[np.clip(c, 0, len(_PALETTE) - 1)])


TRANSITION_MARKERS: dict[Transition, tuple[str, str]] = {
    Transition.CLOSED: ("v", "#2ca02c"),
    Transition.OPENED: ("^", "#7f7f7f"),
    Transition.SLIP_POS: (">", "#d62728"),
    Transition.SLIP_NEG: ("<", "#1f77b4"),
    Transition.STUCK: ("o", "#17becf"),
    Transition.BROKEN: ("X", "#9467bd"),
    Transition.SLIP: ("D", "#d62728"),
    Transition.TURNED: ("d", "#ff7f0e"),
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


def _state_index(res: StaticResult, state: int) -> int:
    """A reported-state index checked against ``res.n_states`` (negative: from the end)."""
    n = res.n_states
    if isinstance(state, bool) or not isinstance(state, int | np.integer):
        raise ValueError(f"state={state!r}: give the index of a reported state (an integer)")
    if not -n <= int(state) < n:
        raise ValueError(f"state {state} does not exist: the result has states 0..{n - 1}")
    return int(state) % n


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


def _say_only(fig: Figure, text: str) -> None:
    """A figure with nothing to draw: ``text`` in the middle of one axes without axis."""
    ax = fig.add_subplot()
    ax.text(0.5, 0.5, text, ha="center", va="center")
    ax.set_axis_off()


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


def _ranges(values: Sequence[int]) -> str:
    """``[0, 1, 2, 5]`` → ``"0–2, 5"``."""
    out: list[str] = []
    for v in values:
        if out and out[-1].split("–")[-1] == str(v - 1):
            out[-1] = f"{out[-1].split('–')[0]}–{v}"
        else:
            out.append(str(v))
    return ", ".join(out)


def _length_scale(values: np.ndarray) -> tuple[float, str]:
    """Divisor and unit so that lengths (m) read well: m, mm or µm."""
    peak = float(np.max(np.abs(values), initial=0.0)) if values.size else 0.0
    if not np.isfinite(peak) or peak >= 0.1 or peak == 0:
        return 1.0, "m"
    return (1e-3, "mm") if peak >= 1e-4 else (1e-6, "µm")


def _state_handles(codes: np.ndarray, *, bars: bool = False) -> list:
    """Legend handles of the contact states present in ``codes``: dots with their counts, or
    (``bars``) patches named ``state …``."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    out = []
    classes = [(cs.label, STATE_COLORS[cs], int(np.sum(codes == int(cs))))
               for cs in ContactState]
    classes.append((FACETED_SLIP_LABEL, FACETED_SLIP_COLOR,
                    int(np.sum(np.asarray(codes) >= FACET_SLIP))))
    for label, color, n in classes:
        if n and bars:
            out.append(Patch(facecolor=color, edgecolor="0.4", label=f"state {label}"))
        elif n:
            out.append(Line2D([], [], ls="none", marker="o", ms=7, mfc=color,
                              mec="0.2", label=f"{label} ({n})"))
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


def _force_scale(values: np.ndarray, comp: int) -> tuple[float, str]:
    """Divisor and unit for forces (N, kN, MN) or moments (N·m, kN·m, MN·m)."""
    big = float(np.max(np.abs(values), initial=0.0))
    div, prefix = next(((d, p) for d, p in ((1e6, "M"), (1e3, "k")) if big >= d), (1.0, ""))
    return div, f"{prefix}N·m" if comp == 2 else f"{prefix}N"


__all__ = [
    "DPI",
    "MAX_PIXELS",
    "MAX_SIDE",
    "NOT_BUILT",
    "FACETED_SLIP_COLOR",
    "FACETED_SLIP_LABEL",
    "STATE_COLORS",
    "TRANSITION_MARKERS",
    "figure_path",
    "state_colors",
    "new_figure",
    "save_figure",
]
