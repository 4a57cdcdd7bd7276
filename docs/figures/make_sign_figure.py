"""Draw docs/figures/sign-convention.png: one tangent rule for CFEs and edge loads.

A block (S+) on a base (S−).  Every tangent is its normal turned clockwise, t = (n_y, −n_x):
the CFE's (n from S− to S+), and the outward normal of each edge for ``EdgeLoad(tangential=)``.
Run:  python docs/figures/make_sign_figure.py
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import FancyArrowPatch, Rectangle  # noqa: E402

OUT = Path(__file__).resolve().parent / "sign-convention.png"
N_COLOR, T_COLOR, LOAD_COLOR = "#1f5fa8", "#c0392b", "#2e8b57"


def arrow(ax, xy, d, color, label=None, offset=(0.0, 0.0), lw=2.0, size=0.55):
    """An arrow of length ``size`` from ``xy`` along ``d`` with a label at its tip."""
    x0, y0 = xy
    d = np.asarray(d, float) / np.linalg.norm(d)
    tip = (x0 + size * d[0], y0 + size * d[1])
    ax.add_patch(FancyArrowPatch((x0, y0), tip, arrowstyle="-|>", mutation_scale=16,
                                 color=color, lw=lw, zorder=5))
    if label:
        ax.annotate(label, tip, xytext=offset, textcoords="offset points", color=color,
                    fontsize=10, ha="center", va="center", zorder=6)


def pair(ax, xy, n, name, n_off, t_off):
    """Normal n and tangent t = (n_y, −n_x) at ``xy``; label offsets in points."""
    t = (n[1], -n[0])
    arrow(ax, xy, n, N_COLOR, f"n{name}", offset=n_off)
    arrow(ax, xy, t, T_COLOR, f"t{name}", offset=t_off)
    ax.plot(*xy, "ko", ms=3, zorder=7)


def main() -> Path:
    fig, ax = plt.subplots(figsize=(8.0, 5.2))
    ax.add_patch(Rectangle((-0.6, -1.0), 5.8, 1.0, fc="#d9d9d9", ec="k", lw=1.2))
    ax.add_patch(Rectangle((1.0, 0.0), 2.0, 1.6, fc="#f2e6c9", ec="k", lw=1.2))
    ax.text(2.0, 0.8, "block (S+)", ha="center", va="center", fontsize=11)
    ax.text(0.2, -0.5, "base (S−)", ha="left", va="center", fontsize=11)
    # the CFE at the joint: n from S− to S+, t = (n_y, −n_x) = +x
    pair(ax, (1.5, 0.0), (0.0, 1.0), " (CFE)", (0, 9), (28, 9))
    # edge tangents of the block: outward normal turned clockwise
    pair(ax, (2.6, 1.6), (0.0, 1.0), " top", (0, 9), (22, 0))
    pair(ax, (3.0, 0.75), (1.0, 0.0), " right", (30, 0), (26, 2))
    pair(ax, (1.0, 0.75), (-1.0, 0.0), " left", (-24, 0), (-20, 2))
    # a tangential load on the top face, tangential = +p: along +x
    for x in np.linspace(1.1, 1.95, 4):
        arrow(ax, (x, 1.85), (1.0, 0.0), LOAD_COLOR, size=0.25, lw=1.5)
    ax.text(1.55, 2.05, "EdgeLoad(top, tangential=+p)\n= EdgeLoad(top, traction=(p, 0))",
            color=LOAD_COLOR, ha="center", va="bottom", fontsize=9)
    ax.text(5.15, 2.6, "t = (n_y, −n_x): the normal\nturned clockwise\n"
            "edges: n = outward normal\nCFE: n from S− to S+",
            ha="right", va="top", fontsize=9,
            bbox={"boxstyle": "round", "fc": "white", "ec": "0.6"})
    ax.set_xlim(-0.7, 5.3)
    ax.set_ylim(-1.1, 2.75)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.annotate("", (-0.05, -0.85), (-0.5, -0.85), arrowprops={"arrowstyle": "->", "lw": 0.8})
    ax.annotate("", (-0.5, -0.4), (-0.5, -0.85), arrowprops={"arrowstyle": "->", "lw": 0.8})
    ax.text(0.0, -0.85, "x", va="center", fontsize=9)
    ax.text(-0.5, -0.33, "y", ha="center", fontsize=9)
    fig.tight_layout()
    fig.savefig(OUT, dpi=110)
    plt.close(fig)
    return OUT


if __name__ == "__main__":
    print(main())
