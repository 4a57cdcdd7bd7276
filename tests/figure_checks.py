"""Checks on a drawn matplotlib figure: no two text labels overlap, nothing is clipped.

Used by the figure tests of every figure family (the library's plots, the CLI's figures, the
studies' reports).  The figure is drawn with its own canvas (Agg) and the window extents of
its texts and legends are read from the renderer, in pixels:

* every visible, non-empty text (titles, axis labels, tick labels within the view, annotations,
  text placed in axes or figure coordinates, the suptitle) and every legend, taken whole, is
  one box;
* two boxes may not overlap by more than ``tol`` pixels in both directions;
* every box lies inside the figure (a legend or label cut by the figure's edge is clipped);
* the constrained layout succeeded (it gives up, with a warning, when labels leave the axes
  no room).

Example
-------
>>> fig = sc.plot_safety(res)                       # doctest: +SKIP
>>> assert_readable(fig)                            # doctest: +SKIP
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from matplotlib.figure import Figure
from matplotlib.legend import Legend
from matplotlib.text import Text
from matplotlib.transforms import Bbox

#: overlap allowed between two text boxes, and how far a box may reach past the figure, pixels
TOLERANCE_PX = 1.0


@dataclass(frozen=True)
class Box:
    """A drawn text or legend: what it says (first 60 characters) and its extent, px."""

    label: str
    bbox: Bbox


def _tick_texts(fig: Figure) -> tuple[set[int], list[Text]]:
    """ids of all tick-label texts, and those drawn (tick inside the axis' view interval)."""
    every: set[int] = set()
    drawn: list[Text] = []
    for ax in fig.get_axes():
        for axis in (ax.xaxis, ax.yaxis):
            lo, hi = sorted(axis.get_view_interval())
            span = max(hi - lo, 1e-300)
            for tick in [*axis.get_major_ticks(), *axis.get_minor_ticks()]:
                labels = (tick.label1, tick.label2)
                every.update(id(t) for t in labels)
                loc = tick.get_loc()
                if loc is None or not (lo - 1e-9 * span <= loc <= hi + 1e-9 * span):
                    continue
                if not (ax.get_visible() and axis.get_visible() and tick.get_visible()):
                    continue
                drawn.extend(t for t in labels if t.get_visible() and t.get_text().strip())
    return every, drawn


def text_boxes(fig: Figure) -> list[Box]:
    """The boxes of the drawn texts and legends of ``fig`` (drawing it first)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fig.canvas.draw()
    collapsed = [str(w.message) for w in caught if "collapsed" in str(w.message)]
    assert not collapsed, f"figure layout failed: {collapsed[0]}"
    renderer = fig.canvas.get_renderer()
    legends = [leg for leg in fig.findobj(Legend) if leg.get_visible()]
    in_legend = {id(t) for leg in legends for t in leg.findobj(Text)}
    ticks, drawn_ticks = _tick_texts(fig)
    texts = [t for t in fig.findobj(Text)
             if id(t) not in in_legend and id(t) not in ticks]
    out = []
    for t in [*texts, *drawn_ticks]:
        if not t.get_visible() or not t.get_text().strip():
            continue
        if t.axes is not None and not t.axes.get_visible():
            continue
        bb = t.get_window_extent(renderer)
        if bb.width <= 0 or bb.height <= 0 or not np.all(np.isfinite(bb.get_points())):
            continue
        out.append(Box(t.get_text()[:60], bb))
    for leg in legends:
        texts = [t.get_text() for t in leg.get_texts()]
        out.append(Box("legend: " + " | ".join(texts)[:52], leg.get_window_extent(renderer)))
    return out


def overlaps(fig: Figure, tol: float = TOLERANCE_PX) -> list[tuple[str, str]]:
    """Pairs of drawn texts/legends whose boxes overlap by more than ``tol`` px both ways."""
    boxes = text_boxes(fig)
    pts = np.array([b.bbox.get_points().ravel() for b in boxes]).reshape(-1, 4)
    if len(pts) < 2:
        return []
    x0, y0, x1, y1 = (pts[:, k] for k in range(4))
    dx = np.minimum(x1[:, None], x1[None, :]) - np.maximum(x0[:, None], x0[None, :])
    dy = np.minimum(y1[:, None], y1[None, :]) - np.maximum(y0[:, None], y0[None, :])
    hit = np.triu((dx > tol) & (dy > tol), k=1)
    return [(boxes[i].label, boxes[j].label) for i, j in zip(*np.nonzero(hit), strict=True)]


def clipped(fig: Figure, tol: float = TOLERANCE_PX) -> list[str]:
    """Drawn texts/legends that reach past the figure's edge by more than ``tol`` px."""
    fb = fig.bbox
    return [b.label for b in text_boxes(fig)
            if b.bbox.x0 < fb.x0 - tol or b.bbox.y0 < fb.y0 - tol
            or b.bbox.x1 > fb.x1 + tol or b.bbox.y1 > fb.y1 + tol]


def assert_readable(fig: Figure, tol: float = TOLERANCE_PX) -> None:
    """Fail, naming them, if two texts/legends overlap or one is clipped by the figure edge."""
    over, cut = overlaps(fig, tol), clipped(fig, tol)
    assert not over and not cut, (
        "figure not readable: "
        + "; ".join([*(f"{a!r} overlaps {b!r}" for a, b in over),
                     *(f"{c!r} clipped by the figure edge" for c in cut)]))
