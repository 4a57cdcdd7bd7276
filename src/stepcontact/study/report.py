"""Figures and report of the stilling-basin slab study (:mod:`stepcontact.study.basin`; the
article's Figs. 4–5, method.md §7).

* :func:`plot_limits` — Fig. 5: the limit thickness h_p/h_kr against the impulse position
  x/L_p, per direction, their envelope and the static-only limit;
* :func:`plot_edge_stresses` — Fig. 4: the contact stresses σ_n and τ (kPa) along the slab's
  base just before its first opening, for the static case and the governing impulse case;
* :func:`case_table` — the rows of the table of all cases;
* :func:`write_report` — ``report.md`` and a self-contained ``report.html`` (inline CSS, the
  figures as ``figures/*.png`` beside them): the software and run (version, git commit,
  Python/NumPy/SciPy, dates), inputs, hydraulics, formulas and their sources, assumptions,
  method, the mesh and its convergence check (:class:`~stepcontact.study.basin.MeshCheck`,
  kept in the dataset by :func:`~stepcontact.study.basin.run_basin`), figures, tables, why
  the limits differ from the design formulas, failed cases, the coefficients and whether they
  were checked against their sources, and caveats.

Input: the dataset of :func:`stepcontact.study.basin.run_basin` (one row per case along
``case``) and the :class:`~stepcontact.study.basin.BasinStudy` that produced it.  Units are SI
(m, s, Pa) except the stresses of the figures, in kPa.  Figures are drawn on the Agg canvas
like :mod:`stepcontact.post.plotting` and saved atomically.

Example
-------
>>> from stepcontact.study import basin as B, report as R
>>> st = B.quick()                                           # doctest: +SKIP
>>> ds = B.run_basin(st, "store")                            # doctest: +SKIP
>>> paths = R.write_report(ds, st, "store/report")           # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
import html
import math
import os
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from stepcontact.io.atomic import write_text
from stepcontact.post.common import DPI, figure_path, new_figure, save_figure
from stepcontact.study import hydraulics as hy
from stepcontact.study.basin import (
    MESH_RELATIVE,
    BasinStudy,
    MeshCheck,
    design_table,
    envelope,
    governing,
    mesh_info,
    refined,
)

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: colours of the impulse directions (and of the static case) in the figures
COLORS = {"up": "#d62728", "down": "#1f77b4", "static": "#2ca02c"}
#: the width of the window of Fig. 4's zoomed panels, as a fraction of L_p (centred on the
#: governing case's first opening)
ZOOM = 1.0 / 3.0
#: the figure files written by :func:`write_report`, relative to its ``out_dir``
FIGURES = {"limits": "figures/limits.png", "edge_stresses": "figures/edge_stresses.png"}
_DASH = "—"
_RECALLED = f"({hy.RECALLED})"
_SEEN = "(read in the source; not available here to check again)"


# ---------------------------------------------------------------------- reading the dataset ---

def _strings(ds: xr.Dataset, name: str, default: str = "") -> np.ndarray:
    """A string column along ``case`` (``default`` where the dataset lacks it)."""
    if name not in ds.variables:
        return np.full(ds.sizes["case"], default, dtype=object)
    return np.asarray(ds[name].values).astype(str)


def _floats(ds: xr.Dataset, name: str) -> np.ndarray:
    """A float column along ``case`` (NaN where the dataset lacks it)."""
    if name not in ds.variables:
        return np.full(ds.sizes["case"], np.nan)
    return np.asarray(ds[name].values, dtype=float)


def _quiet_envelope(ds: xr.Dataset) -> dict[str, np.ndarray]:
    """:func:`~stepcontact.study.basin.envelope` without the all-NaN warnings of failed
    cases (their entries stay NaN)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return envelope(ds)


def _stresses(ds: xr.Dataset, i: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """x (m), σ_n, τ (Pa) of case number ``i``, without the NaN padding."""
    x = np.asarray(ds["x"].values[i], float).ravel()
    sn = np.asarray(ds["sigma_n"].values[i], float).ravel()
    tau = np.asarray(ds["tau"].values[i], float).ravel()
    keep = np.isfinite(x) & np.isfinite(sn) & np.isfinite(tau)
    return x[keep], sn[keep], tau[keep]


def governing_case(ds: xr.Dataset) -> str | None:
    """The id of the impulse case with the largest h/h_kr (None if no impulse case has a
    limit)."""
    ratio = np.where(_strings(ds, "kind") == "impulse", _floats(ds, "h_ratio"), np.nan)
    if not np.any(np.isfinite(ratio)):
        return None
    return str(ds["case"].values[int(np.nanargmax(ratio))])


# ----------------------------------------------------------------------------- formatting ---

def _num(v: Any, spec: str = ".3f", unit: str = "") -> str:
    """``v`` formatted with ``spec`` (and `` unit``), or "—" for None/NaN."""
    if v is None:
        return _DASH
    try:
        f = float(v)
    except (TypeError, ValueError):
        return str(v) or _DASH
    if not math.isfinite(f):
        return _DASH
    return f"{f:{spec}}" + (f" {unit}" if unit else "")


def _modulus(E: float) -> str:
    """A modulus in Pa as GPa or MPa."""
    return f"{E / 1e9:g} GPa" if abs(E) >= 1e9 else f"{E / 1e6:g} MPa"


def _value(name: str, v: Any, study: BasinStudy) -> str:
    """The report's text for the value of the BasinStudy field ``name``."""
    if v is None and name == "soil_depth":
        return f"default L_p/2 = {study.length / 2:.2f}"
    if v is None and name == "h0":
        return f"default h_kr/2 = {study.h_kr / 2:.3g}"
    if v is None and name == "layer":
        return "none (rigid contact)"
    if hasattr(v, "E") and hasattr(v, "density") and hasattr(v, "nu"):  # a Material
        return f"E = {_modulus(v.E)}, ν = {v.nu:g}, ρ = {v.density:g} kg/m³"
    if dataclasses.is_dataclass(v):
        parts = [f"{f.name} = {getattr(v, f.name):g}" for f in dataclasses.fields(v)
                 if isinstance(getattr(v, f.name), int | float)]
        return ", ".join(parts) + " (Pa/m, m, Pa, Pa·s/m)"
    if isinstance(v, tuple):
        return ", ".join(f"{e:g}" if isinstance(e, float) else str(e) for e in v)
    if isinstance(v, float):
        return f"{v:g}"
    return str(v)


#: unit and meaning of each field of BasinStudy (fields not listed are still reported)
_FIELDS: dict[str, tuple[str, str]] = {
    "h_kr": ("m", "critical depth of the design unit discharge"),
    "E0": ("m", "energy head above the apron"),
    "phi": ("–", "velocity coefficient of the inflow"),
    "jump_length": ("–", "jump-length formula"),
    "slab_factor": ("–", "slab length L_p = factor · L_j"),
    "residual_head": ("m", "seepage head in the joint beyond the tailwater"),
    "concrete": ("", "the slab's material"),
    "soil": ("", "the foundation's material"),
    "soil_depth": ("m", "depth of the foundation"),
    "friction": ("–", "friction coefficient f of the joint"),
    "layer": ("", "compliant contact layer of the joint (eq. (11))"),
    "cells": ("–", "slab mesh: cells along, through the slab"),
    "added_mass": ("–", "the tailwater depth h2 of water above the slab as added mass"),
    "layer_thickness": ("m", "a compliant layer of the soil's E and ν this thick (no layer: "
                        "rigid contact)"),
    "end_joints": ("–", "friction of the joints against the neighbouring slabs (rigid); "
                   "None: free ends"),
    "gap_pressure": ("–", "pressure in the opened joint: the uplift, or the pressure at the "
                     "upstream joint (mean and impulse) following the opened length"),
    "positions": ("x/L_p", "impulse positions (centre of the footprint)"),
    "directions": ("–", "impulse directions: up in the joint, down on the top"),
    "durations": ("s", "impulse durations"),
    "amplitude": ("ρ_w V1²/2", "impulse amplitude as a fraction of the velocity head"),
    "footprint": ("m", "length of the slab loaded by the impulse"),
    "shape": ("–", "time shape of the impulse"),
    "tol": ("m", "tolerance of the bisection on the thickness"),
    "h0": ("m", "first trial thickness"),
    "criterion": ("–", "failure criterion (lift-off)"),
    "no_slip": ("–", "any slip fails (otherwise only sliding as a body)"),
    "steps": ("–", "time steps per impulse duration"),
    "alpha": ("–", "HHT-α parameter of the time integration"),
}

#: (formula, source) of each jump-length formula of hydraulics.jump_length
_JUMP_FORMULAS: dict[str, tuple[str, str]] = {
    "usbr": ("L_j = 6.1 h2", "USBR Engineering Monograph 25, type-I jump (coefficient 6.1 "
             "recalled, not checked against the source; “≈ 6 y2 for 4 < Fr1 < 20” read in a "
             "textbook)"),
    "russian": ("L_j = 6 (h2 − h1)", "the (5–6)(h″ − h′) rule of Russian teaching practice "
                f"{_SEEN}"),
    "pavlovsky": ("L_j = 2.5 (1.9 h2 − h1)", f"Pavlovsky {_RECALLED}"),
    "chertousov": ("L_j = 10.3 h1 (Fr1 − 1)^0.81", f"Chertousov {_RECALLED}"),
    "hager": ("L_j = L_r = h1 (−12 + 160 tanh(Fr1/20)), the roller length",
              f"Hager (1990) {_RECALLED}"),
    "given": ("L_j given as a number", "input"),
}


def _jump_formula(jump: hy.Jump) -> tuple[str, str]:
    return _JUMP_FORMULAS.get(jump.formula, (f"formula '{jump.formula}'", ""))


# -------------------------------------------------------------------------------- Fig. 5 ---

def _ratios_by_duration(ds: xr.Dataset, xs: np.ndarray, direction: str,
                        duration: float) -> np.ndarray:
    """h/h_kr of the impulse cases of one direction and duration at the positions ``xs``."""
    kind, dirs = _strings(ds, "kind"), _strings(ds, "direction")
    pos, dur, ratio = _floats(ds, "position"), _floats(ds, "duration"), _floats(ds, "h_ratio")
    out = np.full(xs.shape, np.nan)
    for k, x in enumerate(xs):
        sel = (kind == "impulse") & (dirs == direction) & (dur == duration) & (pos == x)
        if np.any(sel & np.isfinite(ratio)):
            out[k] = np.nanmax(ratio[sel])
    return out


def plot_limits(ds: xr.Dataset, study: BasinStudy,
                path: str | os.PathLike[str] | None = None, *, dpi: float = DPI) -> Figure:
    """The article's Fig. 5: the limit thickness h_p/h_kr (–, with h_p in m on the right axis)
    against the impulse position x/L_p (–).

    One line with markers per direction (the max over the durations; thin lines per duration
    when there are several), the envelope over all impulse cases (a thick grey band, label
    "envelope of all impulses"), the static-only limit (dashed horizontal line).  Saved to
    ``path`` (.png, .pdf, .svg) if given."""
    from matplotlib.ticker import MaxNLocator

    p = figure_path(path, dpi)
    env = _quiet_envelope(ds)
    xs = env["x"]
    durations = np.unique(_floats(ds, "duration")[_strings(ds, "kind") == "impulse"])
    fig = new_figure(figsize=(8.0, 5.6))
    ax = fig.add_subplot()
    for d in (k for k in env if k not in ("x", "envelope", "static")):
        color = COLORS.get(d)
        if durations.size > 1:
            for t in durations:
                ax.plot(xs, _ratios_by_duration(ds, xs, d, float(t)), color=color, lw=0.8,
                        alpha=0.6, ls=":", marker=".", label=f"{d}, T = {t:g} s")
        ax.plot(xs, env[d], color=color, lw=1.6, marker="o",
                label=f"impulse {d}" + (" (max over durations)" if durations.size > 1 else ""))
    if xs.size:
        ax.plot(xs, env["envelope"], color="0.55", lw=7.0, alpha=0.5, zorder=1,
                solid_capstyle="round", label="envelope of all impulses")
    static = float(env["static"][0])
    if math.isfinite(static):
        ax.axhline(static, color=COLORS["static"], ls="--", lw=1.6,
                   label=f"static loads only ({static:.2f})")
    ax.set_xlim(0.0, 1.0)
    ax.set_ylim(bottom=0.0)
    ax.set_xlabel("impulse position x/L_p (–)")
    ax.set_ylabel("limit thickness h_p/h_kr (–)")
    h_kr = study.h_kr
    right = ax.secondary_yaxis("right", functions=(lambda r: r * h_kr, lambda h: h / h_kr))
    right.set_ylabel("h_p (m)")
    top_m = ax.get_ylim()[1] * h_kr  # ticks only inside the view (none drawn past the edge)
    ticks = MaxNLocator(nbins=8).tick_values(0.0, top_m)
    right.set_yticks(ticks[(ticks >= 0.0) & (ticks <= top_m * (1 + 1e-9))])
    ax.grid(True, alpha=0.3)
    ncols = 3 if durations.size > 1 else 2
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncols=ncols,
               fontsize="small", frameon=False)
    amp = hy.impulse_amplitude(study.jump, study.amplitude)
    ax.set_title(f"Limit slab thickness: E0 = {study.E0:g} m, h_kr = {h_kr:g} m, L_p = "
                 f"{study.length:.1f} m\nimpulse {study.amplitude:g} ρ_w V1²/2 = "
                 f"{amp / 1e3:.0f} kPa over a {study.footprint:g} m footprint",
                 fontsize="medium")
    save_figure(fig, p, dpi)
    return fig


# -------------------------------------------------------------------------------- Fig. 4 ---

def _stress_cases(ds: xr.Dataset, cases: Sequence[str] | None) -> list[int]:
    """Row numbers of the cases of Fig. 4: the given ids, else the static case and the
    governing impulse case."""
    ids = [str(c) for c in ds["case"].values]
    if cases is not None:
        unknown = [c for c in cases if c not in ids]
        if unknown:
            raise ValueError(f"unknown case id(s) {', '.join(map(repr, unknown))}; the "
                             f"dataset has {', '.join(ids)}")
        return [ids.index(c) for c in cases]
    rows = [i for i, k in enumerate(_strings(ds, "kind")) if k == "static"][:1]
    gov = governing_case(ds)
    return rows + ([ids.index(gov)] if gov is not None else [])


def _case_label(ds: xr.Dataset, i: int) -> str:
    """Legend text of a case of Fig. 4: its id, failing thickness and the state's λ or t."""
    cid = str(ds["case"].values[i])
    static = _strings(ds, "kind")[i] == "static"
    h = _floats(ds, "h_failing")[i]
    before = _floats(ds, "before")[i]
    when = f"λ = {before:.3g}" if static else f"t = {before:.3g} s"
    return f"{'static loads' if static else cid}: h = {_num(h, '.2f', 'm')}, {when}"


def _case_color(ds: xr.Dataset, i: int, k: int) -> str:
    if _strings(ds, "kind")[i] == "static":
        return COLORS["static"]
    return COLORS.get(_strings(ds, "direction")[i], f"C{k + 2}")


def failure_position(ds: xr.Dataset, i: int) -> float:
    """x (m) where the joint of case number ``i`` first opens at its failing thickness: the
    dataset's ``x_open``, else (a store written before it was kept) the least compressed CFE
    just before the opening; NaN without stresses."""
    x_open = _floats(ds, "x_open")[i]
    if math.isfinite(x_open):
        return float(x_open)
    x, sn, _tau = _stresses(ds, i)
    return float(x[int(np.argmax(sn))]) if x.size else float("nan")


def zoom_window(ds: xr.Dataset, study: BasinStudy, rows: Sequence[int]) -> tuple[float, float]:
    """The x-range (m) of Fig. 4's zoomed panels: :data:`ZOOM` · L_p wide, centred on the
    first opening of the governing case (the last of ``rows``; the first with a position if
    it has none), kept inside the slab [0, L_p]."""
    L = study.length
    width = ZOOM * L
    xs = [failure_position(ds, i) for i in reversed(rows)]
    centre = next((x for x in xs if math.isfinite(x)), 0.0)
    lo = min(max(centre - width / 2, 0.0), L - width)
    return lo, lo + width


def _short_label(ds: xr.Dataset, i: int) -> str:
    return "static loads" if _strings(ds, "kind")[i] == "static" else str(ds["case"].values[i])


def _draw_stresses(axes: tuple[Axes, Axes], ds: xr.Dataset, rows: list[int], friction: float,
                   *, light: bool) -> None:
    """σ_n (compression negative, shaded) and τ with ±f|σ_n| (dashed), kPa, on two axes; the
    light (whole-slab) version marks each case's first opening with a triangle."""
    ax_n, ax_t = axes
    lw, alpha = (0.9, 0.6) if light else (1.8, 1.0)
    for k, i in enumerate(rows):
        x, sn, tau = _stresses(ds, i)
        if not x.size:
            continue
        c = _case_color(ds, i, k)
        label = _short_label(ds, i) if light else _case_label(ds, i)
        ax_n.plot(x, sn / 1e3, color=c, lw=lw, alpha=alpha, marker=None if light else ".",
                  label=label)
        ax_n.fill_between(x, sn / 1e3, 0.0, where=sn < 0, color=c, alpha=0.08 if light
                          else 0.18, lw=0, interpolate=True)
        if light:  # where the joint first opens
            xf = failure_position(ds, i)
            if math.isfinite(xf):
                ax_n.plot(xf, float(np.interp(xf, x, sn)) / 1e3, marker="v", color=c, ms=7,
                          ls="none")
        ax_t.plot(x, tau / 1e3, color=c, lw=lw, alpha=alpha, marker=None if light else ".",
                  label=label)
        lim = friction * np.abs(sn) / 1e3
        for s in (1, -1):
            ax_t.plot(x, s * lim, color=c, lw=0.8 * lw, alpha=alpha, ls="--",
                      label=(f"±f|σ_n|, f = {friction:g}" if (s == 1 and k == 0) else None))
    if light and rows:  # one legend entry for the triangles of every case
        ax_n.plot([], [], marker="v", color="0.35", ms=7, ls="none",
                  label="first opening (case's colour)")
    for ax in axes:
        ax.axhline(0.0, color="0.3", lw=0.6)
        ax.grid(True, alpha=0.3)


def _zoom_ylim(ax_n: Axes, ax_t: Axes, ds: xr.Dataset, rows: list[int], friction: float,
               window: tuple[float, float]) -> None:
    """y-limits of the zoomed panels from the values in ``window`` (m) only (kPa)."""
    sn_all, lim_all = [np.zeros(1)], [np.zeros(1)]
    lo, hi = window
    for i in rows:
        x, sn, tau = _stresses(ds, i)
        pad = 1e-9 * max(abs(hi), 1.0)
        inside = (x >= lo - pad) & (x <= hi + pad)
        sn_all.append(sn[inside] / 1e3)
        lim_all += [tau[inside] / 1e3, friction * np.abs(sn[inside]) / 1e3]
    bottom, top = float(np.min(np.concatenate(sn_all))), float(np.max(np.concatenate(sn_all)))
    pad = 0.08 * max(top - bottom, 1.0)
    ax_n.set_ylim(bottom - pad, top + pad)
    peak = float(np.max(np.abs(np.concatenate(lim_all))))
    ax_t.set_ylim(-1.08 * max(peak, 1.0), 1.08 * max(peak, 1.0))


def plot_edge_stresses(ds: xr.Dataset, study: BasinStudy,
                       path: str | os.PathLike[str] | None = None,
                       cases: Sequence[str] | None = None, *, dpi: float = DPI) -> Figure:
    """The article's Fig. 4: the normal and tangential contact stresses σ_n and τ (kPa; σ_n
    negative in compression) against the distance x (m) from the slab's upstream edge, at the
    state just before the first opening of the joint of the slab at its failing thickness.

    Cases: ``cases`` (ids), default the static case and the governing impulse case (largest
    h/h_kr).  Two rows (σ_n with the compression shaded; τ with the friction limits ±f|σ_n|
    dashed, f = ``study.friction``); the left column shows the whole slab in light lines, with
    a triangle where each case's joint first opens, the zoomed window shaded and a legend;
    the right column zooms on a window :data:`ZOOM` · L_p wide around the governing case's
    first opening (:func:`zoom_window`).  Saved to ``path`` if given."""
    p = figure_path(path, dpi)
    rows = _stress_cases(ds, cases)
    fig = new_figure(figsize=(11.0, 7.6))
    grid = fig.add_gridspec(2, 2, width_ratios=(1.0, 1.5))
    ax_full_n = fig.add_subplot(grid[0, 0])
    ax_full_t = fig.add_subplot(grid[1, 0], sharex=ax_full_n)
    ax_n = fig.add_subplot(grid[0, 1])
    ax_t = fig.add_subplot(grid[1, 1], sharex=ax_n)
    L = study.length
    window = zoom_window(ds, study, rows)
    _draw_stresses((ax_full_n, ax_full_t), ds, rows, study.friction, light=True)
    _draw_stresses((ax_n, ax_t), ds, rows, study.friction, light=False)
    for ax in (ax_full_n, ax_full_t):
        ax.axvspan(*window, color="0.85", alpha=0.5, lw=0,
                   label="zoomed window" if ax is ax_full_n else None)
        ax.set_xlim(0.0, L)
    ax_n.set_xlim(*window)
    _zoom_ylim(ax_n, ax_t, ds, rows, study.friction, window)
    ax_full_n.set_title(f"whole slab, L_p = {L:.1f} m", fontsize="medium")
    gov = [failure_position(ds, i) for i in rows[-1:]]
    where = f", first opening at x = {gov[0]:.1f} m" if gov and math.isfinite(gov[0]) else ""
    ax_n.set_title(f"x = {window[0]:.1f}–{window[1]:.1f} m{where}", fontsize="medium")
    for ax in (ax_full_n, ax_n):
        ax.set_ylabel("σ_n (kPa)")
    for ax in (ax_full_t, ax_t):
        ax.set_ylabel("τ (kPa)")
        ax.set_xlabel("x from the upstream edge (m)")
    if any(_stresses(ds, i)[0].size for i in rows):
        for ax in (ax_full_n, ax_full_t, ax_n, ax_t):
            ax.legend(fontsize="x-small", loc="best")
    else:
        ax_n.text(0.5, 0.5, "no contact stresses to show", ha="center", va="center",
                  transform=ax_n.transAxes)
    fig.suptitle("Contact stresses under the slab just before its first lift-off "
                 "(at the failing thickness)", fontsize="medium")
    save_figure(fig, p, dpi)
    return fig


# ------------------------------------------------------------------------------- tables ---

def case_table(ds: xr.Dataset, study: BasinStudy) -> list[dict[str, Any]]:
    """One dict per case, in the dataset's order: ``id``, ``kind``, ``direction`` (None for
    the static case), ``duration`` (s; None for static), ``position`` (x/L_p; None for
    static), ``h_limit`` (m), ``h_ratio`` (h/h_kr), ``mode`` ("lift-off", "sliding" or ""),
    ``when`` (λ of the static loading, or t in s, of the first failure at the failing
    thickness), ``when_unit`` ("λ" or "s"), ``runs`` (solver runs of the bisection),
    ``status`` ("ok", "failed", "missing") and ``message``.  Numbers are floats, NaN where
    a case has no value."""
    kind, dirs = _strings(ds, "kind"), _strings(ds, "direction")
    pos, dur = _floats(ds, "position"), _floats(ds, "duration")
    h, ratio, when = _floats(ds, "h_limit"), _floats(ds, "h_ratio"), _floats(ds, "when")
    runs = _floats(ds, "runs")
    mode = _strings(ds, "mode")
    status = _strings(ds, "case_status", "ok")
    message = _strings(ds, "case_message")
    rows = []
    for i, cid in enumerate(ds["case"].values):
        static = kind[i] == "static"
        rows.append({
            "id": str(cid), "kind": str(kind[i]),
            "direction": None if static else str(dirs[i]),
            "duration": None if static else float(dur[i]),
            "position": None if static else float(pos[i]),
            "h_limit": float(h[i]), "h_ratio": float(ratio[i]),
            "mode": "" if mode[i] == "nan" else str(mode[i]),
            "when": float(when[i]), "when_unit": "λ" if static else "s",
            "runs": int(runs[i]) if math.isfinite(runs[i]) else None,
            "status": str(status[i]), "message": str(message[i]),
        })
    return rows


_CASE_HEADER = ("case", "kind", "direction", "duration (s)", "x/L_p", "h_p (m)", "h_p/h_kr",
                "mode", "first failure at", "runs", "status")


def _case_cells(row: dict[str, Any]) -> tuple[str, ...]:
    when = row["when"]
    when_s = (f"λ = {when:.3f}" if row["when_unit"] == "λ" else f"t = {when:.3f} s") \
        if math.isfinite(when) else _DASH
    return (row["id"], row["kind"], row["direction"] or _DASH, _num(row["duration"], "g"),
            _num(row["position"], "g"), _num(row["h_limit"], ".3f"), _num(row["h_ratio"], ".3f"),
            row["mode"] or _DASH, when_s, _num(row["runs"], ".0f"), row["status"])


def _design_rows(study: BasinStudy, ds: xr.Dataset) -> list[tuple[str, str, str, str]]:
    """(name, thickness m, h/h_kr, note) of :func:`~stepcontact.study.basin.design_table`,
    thicknesses to 0.01 m."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        table = design_table(study, ds)
    return [(name, _num(s, ".2f"), _num(s / study.h_kr, ".2f"), note)
            for name, s, note in table]


# -------------------------------------------------------------------- the report's content ---

@dataclass(frozen=True)
class _Heading:
    level: int
    text: str


@dataclass(frozen=True)
class _Para:
    text: str


@dataclass(frozen=True)
class _Table:
    header: tuple[str, ...]
    rows: list[tuple[str, ...]]


@dataclass(frozen=True)
class _Image:
    src: str
    alt: str
    caption: str


@dataclass(frozen=True)
class _List:
    items: list[str]


_Block = _Heading | _Para | _Table | _Image | _List


def _inputs(study: BasinStudy) -> list[_Block]:
    rows = []
    for f in dataclasses.fields(study):
        unit, meaning = _FIELDS.get(f.name, ("", ""))
        rows.append((f.name, _value(f.name, getattr(study, f.name), study), unit, meaning))
    return [_Heading(2, "Inputs"),
            _Para("Every field of the BasinStudy (SI units; per metre width of the slab)."),
            _Table(("field", "value", "unit", "meaning"), rows)]


def _hydraulics(study: BasinStudy) -> list[_Block]:
    j, L = study.jump, study.length
    amp = hy.impulse_amplitude(j, study.amplitude)
    lj, _src = _jump_formula(j)
    rows = [
        ("unit discharge q", f"{j.q:.2f}", "m²/s", "q = √(g h_kr³)"),
        ("contracted depth h1", f"{j.h1:.3f}", "m",
         "supercritical root of E0 = h1 + q²/(2 g φ² h1²)"),
        ("inflow velocity V1", f"{j.V1:.2f}", "m/s", "V1 = q/h1"),
        ("inflow Froude number Fr1", f"{j.Fr1:.2f}", "–", "Fr1 = V1/√(g h1)"),
        ("sequent depth h2", f"{j.h2:.2f}", "m", "h2 = h1 · ½(√(1 + 8 Fr1²) − 1)"),
        (f"jump length L_j ({j.formula})", f"{j.L_j:.1f}", "m", lj),
        ("roller length L_r (Hager)", f"{j.roller_length:.1f}", "m",
         "L_r = h1 (−12 + 160 tanh(Fr1/20))"),
        ("slab length L_p", f"{L:.1f}", "m", f"L_p = {study.slab_factor:g} · L_j"),
        ("velocity head V1²/2g", f"{j.velocity_head:.2f}", "m", "V1²/(2g)"),
        ("impulse amplitude", f"{amp:.0f}", "Pa", f"{study.amplitude:g} · ρ_w V1²/2"),
        ("impulse amplitude, head", f"{amp / j.gamma_w:.2f}", "m of water",
         f"{study.amplitude:g} · V1²/2g"),
    ]
    return [_Heading(2, "Hydraulics derived from the inputs"),
            _Table(("quantity", "value", "unit", "formula"), rows)]


def _formulas(study: BasinStudy) -> list[_Block]:
    lj, lj_src = _jump_formula(study.jump)
    pulse = ("sin(π t/T)" if study.shape == "half_sine" else f"the '{study.shape}' pulse")
    rows = [
        ("unit discharge", "q = √(g h_kr³)", "definition of the critical depth"),
        ("contracted depth h1", "supercritical root of E0 = h1 + q²/(2 g φ² h1²)",
         "energy equation with a velocity coefficient φ"),
        ("sequent depth h2", "h2 = h1 · ½(√(1 + 8 Fr1²) − 1)", "Bélanger (momentum balance), "
         "derived, no coefficient"),
        ("jump length", lj, lj_src),
        ("slab length", "L_p = factor · L_j", "Russian practice: factor 1–1.25 without "
         f"baffles, 0.8–1 with {_SEEN}"),
        ("mean surface of the jump", "(y − h1)/(h2 − h1) = tanh(1.5 x/L_r)",
         f"Hager's profile {_RECALLED}"),
        ("pressure on the slab's top", "p_top = ρ_w g y(x)",
         "hydrostatic under the mean surface (an assumption, recalled practice)"),
        ("pressure in the joint", "p_joint = ρ_w g (h2 + h_s), referred to the top's level, "
         "plus the buoyancy γ_w h of the slab", "tailwater reaching the base through joints "
         f"and drains, Alberta Transportation, Water Control Structures (2004) §12 {_SEEN}; "
         "residual seepage head h_s = residual_head (an input, e.g. from Lane's weighted "
         "creep, Lane (1935) Trans. ASCE 100: recalled practice, not checked against the "
         "source)"),
        ("net uplift", "p_joint − p_top = ρ_w g (h2 − y(x) + h_s) against (γ_c − γ_w) h",
         "docs/slab-hydraulics.md, reference level"),
        ("impulse", f"p = a · ρ_w V1²/2 · {pulse} for 0 ≤ t ≤ T on |x − x_c| ≤ b/2 "
         f"(a = {study.amplitude:g}, b = {study.footprint:g} m)",
         "a = 0.3–0.5, derived from the extreme coefficients below "
         f"{_RECALLED}"),
        ("extreme pressure coefficients", "C±p = N± C′p, C′p(X) = C′max (X/X_m)^k "
         "exp(k(1 − X/X_m)), X = x/h1; N⁺ = 4, N⁻ = 3, C′max = 0.08, X_m = 10, k = 0.5",
         f"Toso & Bowers (1988), J. Hydraul. Eng. 114(8) 829–843; Lopardo {_RECALLED}"),
        ("Fiorotto–Rinaldo thickness", "s = Ω (C⁺p + C⁻p) · V1²/2g · γ_w/(γ_c − γ_w)",
         "Fiorotto & Rinaldo (1992a), J. Hydraul. Eng. 118(4) 578–596; Ω ≈ 0.1–0.25, "
         "C±p ≈ 0.3–0.6 (recalled with low confidence, not checked against the source)"),
        ("USACE flotation", "SF = (W_s + W_c + S)/(U − W_G); s = SF · U_net/((γ_c − γ_w) L_p)",
         "USACE ETL 1110-2-307 (1987): the formula read in the source (not available here to "
         "check again); SF = 1.3/1.2/1.1 usual/unusual/extreme recalled, not checked against "
         "the source"),
        ("Dombrovsky thickness", "t = 0.15 V1 √h1", f"Russian empirical rule {_RECALLED}"),
        ("kern lift-off thickness", "s = [q0 ξ(2 − ξ) + 2 q1 ξ(1 − ξ)]/(γ_c − γ_w), ξ = a/L",
         "rigid slab on a Winkler bed, resultant at the kern's edge e = L/6 (derived in "
         "docs/slab-hydraulics.md)"),
    ]
    return [_Heading(2, "Formulas and sources"),
            _Para("The structure of every formula is standard. Coefficients said to be "
                  "“recalled, not checked against the source” were quoted from memory, not read "
                  "in the sources: they are defaults to be checked before use as design values "
                  "(the section “Coefficients and their sources” lists each)."),
            _Table(("quantity", "formula", "source"), rows)]


def _method(study: BasinStudy) -> list[_Block]:
    fail = ("any contact finite element (CFE) of the joint opens" if study.criterion
            == "opening" else "the whole joint opens at once (the slab floats)")
    slide = "any CFE slips" if study.no_slip else \
        "every closed CFE of the joint slips the same way at once (the slab slides as a body)"
    text = (
        "Each case is an exact event-driven contact analysis (the step-by-step method of the "
        "article): the slab and its foundation are plane-strain finite elements joined by "
        "frictional CFEs, and the loading (self-weight, then the mean pressures on the top and "
        "in the joint, then the impulse, integrated in time by HHT-α with α = "
        f"{study.alpha:g} and {study.steps} steps per duration) is followed from one change "
        "of contact state to the next. "
        "The limit thickness h_p of a case is the smallest thickness that meets the criterion, "
        f"bracketed from a first trial and bisected to tol = {study.tol:g} m; the stresses of "
        "Fig. 2 are those of the failing end of the final bracket. "
        f"Criterion '{study.criterion}': the slab fails if {fail} (lift-off) or if {slide}, "
        "over the static loading and the whole dynamic response.")
    return [_Heading(2, "Method"), _Para(text)]


def _summary(ds: xr.Dataset, study: BasinStudy) -> str:
    env = _quiet_envelope(ds)
    static = float(env["static"][0])
    parts = [f"{ds.sizes['case']} cases", f"static limit h_p = "
             f"{_num(static * study.h_kr, '.2f', 'm')} ({_num(static, '.2f')} h_kr)"]
    gov = governing_case(ds)
    if gov is not None:
        i = [str(c) for c in ds["case"].values].index(gov)
        r = _floats(ds, "h_ratio")[i]
        parts.append(f"largest impulse limit h_p = {_num(r * study.h_kr, '.2f', 'm')} "
                     f"({_num(r, '.2f')} h_kr), case {gov}")
    bad = int(np.sum(_strings(ds, "case_status", "ok") != "ok"))
    if bad:
        parts.append(f"{bad} case(s) failed or missing")
    return "; ".join(parts) + "."


def _results(ds: xr.Dataset, study: BasinStudy) -> list[_Block]:
    rows = [_case_cells(r) for r in case_table(ds, study)]
    gov = governing_case(ds)
    return [
        _Heading(2, "Results"), _Para(_summary(ds, study)),
        _Image(FIGURES["limits"], "Fig. 1: limit thickness",
               "Fig. 1 (the article's Fig. 5): limit thickness h_p/h_kr against the impulse "
               "position x/L_p, per direction, their envelope and the limit under the static "
               "loads alone (dashed)."),
        _Image(FIGURES["edge_stresses"], "Fig. 2: contact stresses",
               "Fig. 2 (the article's Fig. 4): contact stresses "
               "σ_n and τ along the slab's base just before its first lift-off, for the static "
               f"case and the governing impulse case ({gov or 'none'}); compression negative, "
               f"friction limits ±f|σ_n| dashed (f = {study.friction:g})."),
        _Heading(2, "All cases"),
        _Para("h_p: limit thickness (passing end of the bisection); 'first failure at': the "
              "load factor λ (static) or time t (impulse) of the first failure at the failing "
              "thickness."),
        _Table(_CASE_HEADER, rows),
        _Heading(2, "Design comparison"),
        _Table(("method", "thickness (m)", "h/h_kr", "note"), _design_rows(study, ds)),
    ]


def _failed(ds: xr.Dataset, study: BasinStudy) -> list[_Block]:
    bad = [r for r in case_table(ds, study) if r["status"] != "ok"]
    if not bad:
        return []
    items = [f"{r['id']} ({r['status']}): {r['message'] or 'no message (not run)'}"
             for r in bad]
    return [_Heading(2, "Failed cases"),
            _Para("These cases have no limit thickness; they are left out of the figures."),
            _List(items)]


def all_failed(ds: xr.Dataset) -> bool:
    """True when no case of the study has a result (every one failed or is missing)."""
    return not np.any(_strings(ds, "case_status", "ok") == "ok")


def failure_reasons(ds: xr.Dataset) -> list[tuple[str, int, str]]:
    """The distinct reasons the cases failed: (message, how many cases, the first case's
    id), most frequent first."""
    status, message = _strings(ds, "case_status", "ok"), _strings(ds, "case_message")
    reasons: dict[str, list[str]] = {}
    for cid, st, msg in zip(ds["case"].values, status, message, strict=True):
        if st != "ok":
            reasons.setdefault(str(msg) or f"{st} (no message: not run)", []).append(str(cid))
    return sorted(((m, len(ids), ids[0]) for m, ids in reasons.items()),
                  key=lambda r: -r[1])


def _all_failed(ds: xr.Dataset) -> list[_Block]:
    n = ds.sizes["case"]
    items = [f"{k} case(s), e.g. {cid}: {msg}" for msg, k, cid in failure_reasons(ds)]
    return [_Heading(2, "All cases failed"),
            _Para(f"All {n} cases of the study failed: there is no limit thickness and no "
                  "figure. The reasons:"), _List(items)]


def _caveats(study: BasinStudy) -> list[_Block]:
    water = ("the tailwater depth h2 of water above the slab moves with it (added mass)"
             if study.added_mass else "no added mass of the water above the slab")
    return [_Heading(2, "Caveats"), _List([
        "2D plane strain, per metre width of the slab: no three-dimensional effects (slab "
        "width, joints between neighbouring slabs, anchors, waterstops).",
        f"The limit thickness is found to {study.tol:g} m and the stresses are CFE averages; "
        "the mesh's effect on the governing limit is in “Mesh and its convergence”.",
        "Coefficients “recalled, not checked against the source” (jump length and profile, "
        "pressure coefficients, design-rule factors) are unchecked defaults.",
        "The impulse is a deterministic pulse of given shape, amplitude and footprint, not a "
        "random pressure field: no spatial correlation or statistics of extremes.",
        f"The joint's pressure acts in the open gaps as well (full transmission through the "
        f"joints); {water}.",
    ])]


# -------------------------------------------------------- what a reviewer needs to accept ---

def _case_values(ds: xr.Dataset, name: str) -> list[str]:
    """The distinct non-empty values of a string output over the cases, in order."""
    return list(dict.fromkeys(v for v in _strings(ds, name) if v and v != "nan"))


def _software(ds: xr.Dataset) -> list[_Block]:
    """Section 'Software and run': the software that wrote the report and computed the
    cases, the versions of Python, NumPy and SciPy, and the dates."""
    from stepcontact.study.provenance import NOT_A_CHECKOUT, provenance

    now = provenance()
    dirty = {True: "yes: the tracked files differ from the commit",
             False: "no", None: "unknown" if now["commit"] != NOT_A_CHECKOUT
             else f"— ({NOT_A_CHECKOUT})"}[now["dirty"]]
    computed = sorted(_case_values(ds, "computed"))
    by = _case_values(ds, "software")
    rows = [("stepcontact version", str(now["version"])),
            ("git commit", str(now["commit"])),
            ("uncommitted changes", dirty),
            ("Python", str(now["python"])), ("NumPy", str(now["numpy"])),
            ("SciPy", str(now["scipy"])),
            ("report written", str(now["date"])),
            ("cases computed", f"{computed[0]} to {computed[-1]}" if computed
             else "— (not recorded in this dataset)"),
            ("cases computed by", "; ".join(by) if by else "— (not recorded in this dataset)")]
    note = ("Every case was computed by the software that wrote this report."
            if by == [now["software"]] else
            "Some cases were computed by other software than the one that wrote this report "
            "(a resumed study reuses the finished cases): rerun with --rerun for one version."
            if by else "The dataset does not record which software computed its cases.")
    return [_Heading(2, "Software and run"), _Table(("item", "value"), rows), _Para(note)]


def _assumptions(study: BasinStudy) -> list[_Block]:
    """Section 'Assumptions': foundation, materials, joint, water, criterion and why."""
    L = study.length
    depth = L / 2 if study.soil_depth is None else float(study.soil_depth)
    soil, conc = study.soil, study.concrete
    if study.layer is not None:
        lay = study.layer
        contact = (f"a compliant contact layer (eq. (11)) of "
                   f"{_value('layer', lay, study)}")
    elif study.layer_thickness is not None:
        contact = (f"a compliant contact layer (eq. (11)) {study.layer_thickness:g} m thick of "
                   f"the soil's E and ν")
    else:
        contact = "rigid contact (no interpenetration, no contact layer)"
    ends = ("free (no joints against the neighbouring slabs)" if study.end_joints is None
            else f"held by rigid neighbours through joints of friction {study.end_joints:g}")
    gap = ("the uplift pressure of the joint at its place" if study.gap_pressure == "uplift"
           else "the pressure at the upstream joint (mean and impulse), following the opened "
           "length from the upstream edge")
    if study.criterion == "opening":
        crit = ("lift-off = the first opening of any CFE of the joint (its normal force reaches "
                "zero), anywhere along the slab, at any instant of the static loading or the "
                "response to the impulse")
        why = ("The design question is whether the flow can lift the slab. Once the joint "
               "opens, the water pressure of the joint enters the gap and acts where the "
               "contact held the slab before (the mechanism of slab failure of Fiorotto & "
               "Rinaldo 1992), and the pulsation repeats the load, so an opening grows; the "
               "article's criterion is the slab's “non-admission of lift-off and of "
               "sliding”. The first opening is therefore the limit, not the flotation of the "
               "whole slab, which comes later and is what the flotation rule checks.")
    else:
        crit = "lift-off = the whole joint open at once (the slab floats)"
        why = ("This reads lift-off as whole-slab flotation, as the flotation rule does: a "
               "local opening is tolerated. It is less strict than the article's criterion "
               "(the first opening), and it ignores the water entering the opened gap.")
    slide = ("sliding = any slip of a CFE" if study.no_slip else
             "sliding = every closed CFE of the joint slipping the same way at once (the slab "
             "moves as a body); local slip near the ends only redistributes the shear")
    items = [
        f"Foundation: an elastic block of soil in plane strain, {depth:.2f} m deep "
        f"(soil_depth) and extending {L / 2:.2f} m (L_p/2) beyond each end of the slab; its "
        "bottom is fixed (u = v = 0), its sides are on rollers (u = 0); its own weight is not "
        "applied (its initial stresses do not act on the joint).",
        f"Soil: linear elastic, E = {_modulus(soil.E)}, ν = {soil.nu:g} (assumed typical of a "
        "dense sand, not from a site investigation; no plasticity, consolidation or "
        "erosion).",
        f"Slab: linear elastic, uncracked concrete, E = {_modulus(conc.E)}, ν = {conc.nu:g}, "
        f"ρ = {conc.density:g} kg/m³; its ends are {ends}.",
        f"Joint: Coulomb friction f = {study.friction:g}, no cohesion (c = 0) and no tensile "
        f"strength (it opens at zero normal stress); {contact}.",
        "Water on the top: hydrostatic under the jump's mean surface (Hager's profile). In "
        f"the joint: the tailwater depth h2 = {study.jump.h2:.2f} m plus a residual seepage "
        f"head of {study.residual_head:g} m, referred to the top's level, plus the buoyancy "
        "γ_w h of the slab; it acts on both faces of the joint through the CFEs (the "
        f"effective stress while closed). In the opened gap: {gap}.",
        f"Impulse: {study.amplitude:g} ρ_w V1²/2 over {study.footprint:g} m, a "
        f"{study.shape.replace('_', ' ')} in time, on the static state; lumped mass, HHT-α = "
        f"{study.alpha:g} (numerical damping of the mesh's high modes), no other damping.",
        f"Failure criterion: {crit}; {slide}. {why}",
        "A thicker slab is assumed safer (heavier): the limit is bisected on that basis.",
    ]
    return [_Heading(2, "Assumptions"), _List(items)]


def _cells_text(info: dict) -> str:
    parts = [f"{name}: {nx} × {ny} cells of {dx:.2f} × {dy:.2f} m ({n} elements)"
             for name, (nx, ny, dx, dy, n, _nodes) in info["bodies"].items()]
    return "; ".join(parts)


def _mesh(ds: xr.Dataset, study: BasinStudy) -> list[_Block]:
    """Section 'Mesh and its convergence': the meshes, and the governing case solved on
    both (:class:`~stepcontact.study.basin.MeshCheck`)."""
    chk = MeshCheck.of(ds)
    gov = chk.case if chk is not None else governing(ds)
    h_ref = chk.h[0] if chk is not None else (
        float(_floats(ds, "h_limit")[[str(c) for c in ds["case"].values].index(gov)])
        if gov is not None else 0.5 * study.h_kr)
    if not math.isfinite(h_ref) or h_ref <= 0:
        h_ref = 0.5 * study.h_kr
    meshes = [("the study's mesh", study)]
    if chk is not None:
        meshes.append(("the check's mesh", refined(study)))
    rows = []
    for name, st in meshes:
        info = mesh_info(st, h_ref)
        rows.append((name, f"{st.cells[0]} × {st.cells[1]}", _cells_text(info),
                     f"{info['cfes']} (length {info['cfe_length']:.2f} m)", f"{info['dofs']}"))
    blocks: list[_Block] = [
        _Heading(2, "Mesh and its convergence"),
        _Para(f"Elements: 4-node bilinear quadrilaterals (quad4, full integration: 3 × 3 "
              f"Gauss points), plane strain, in the slab and the soil, with non-matching "
              f"meshes on the joint; the "
              f"CFEs are mortar CFEs on the slab's face, one per slab node (the end ones half "
              f"as long). Fully integrated bilinear elements are too stiff in bending with few "
              f"cells through the thickness (shear locking): the check below halves the "
              f"cells through the slab as well as along it. The sizes below are for the slab "
              f"thickness h = {h_ref:.2f} m (the cells through the slab scale with h)."),
        _Table(("mesh", "slab cells (along × through)", "cells per body", "CFEs of the joint",
                "DOFs"), rows)]
    if chk is None:
        blocks.append(_Para("No mesh-convergence check was run for this dataset (run_basin "
                            "with mesh_check=False, or no case has a limit): the study's "
                            "limits are those of one mesh only."))
        return blocks
    d, rel = chk.difference, chk.relative
    crows = [("limit thickness h_p (m)", _num(chk.h[0], ".3f"), _num(chk.h[1], ".3f"),
              f"{_num(d, '+.3f')} m ({_num(100 * rel, '+.1f')} %)"),
             ("first opening at x (m)", _num(chk.x_open[0], ".2f"), _num(chk.x_open[1], ".2f"),
              f"{_num(chk.x_open[1] - chk.x_open[0], '+.2f')} m"),
             ("mode of failure", chk.mode[0] or _DASH, chk.mode[1] or _DASH, "")]
    if chk.status != "ok":
        verdict = (f"The search on the finer mesh failed ({chk.message or chk.status}): the "
                   "limits below are not checked against a second mesh.")
    elif chk.acceptable:
        within = ("within the bisection's tolerance" if abs(d) <= chk.tol * (1 + 1e-9)
                  else f"within {100 * MESH_RELATIVE:g} % of h_p")
        verdict = (f"Acceptable: the difference, {abs(d):.3f} m ({100 * abs(rel):.1f} %), is "
                   f"{within} (tol = {chk.tol:g} m), so the study's mesh resolves the "
                   "governing limit to that accuracy; the finer mesh's value is the better "
                   "estimate.")
    else:
        verdict = (f"Not acceptable: the difference, {abs(d):.3f} m ({100 * abs(rel):.1f} %), "
                   f"exceeds both the bisection's tolerance (tol = {chk.tol:g} m) and "
                   f"{100 * MESH_RELATIVE:g} % of h_p: the study's mesh is too coarse for "
                   "this result. Refine the mesh (BasinStudy.cells) and run again before "
                   "relying on the limits.")
    blocks += [
        _Para(f"Check: the governing case ({chk.case}, the largest limit of the study) solved "
              f"again with the cells halved in both directions, {chk.cells[0][0]} × "
              f"{chk.cells[0][1]} → {chk.cells[1][0]} × {chk.cells[1][1]} in the slab (the "
              f"soil's cells follow), starting the search at the first mesh's limit "
              f"({chk.runs} runs, {_num(chk.seconds, '.1f', 's')}). Acceptance: |Δh_p| ≤ "
              f"tol = {chk.tol:g} m or ≤ {100 * MESH_RELATIVE:g} % of h_p."),
        _Table(("governing result", f"{chk.cells[0][0]} × {chk.cells[0][1]} mesh",
                f"{chk.cells[1][0]} × {chk.cells[1][1]} mesh", "difference (fine − study)"),
               crows),
        _Para(verdict)]
    return blocks


def _design_value(rows: list[tuple[str, float, str]], prefix: str) -> float:
    return next((h for name, h, _n in rows if name.startswith(prefix)), float("nan"))


def _differences(ds: xr.Dataset, study: BasinStudy) -> list[_Block]:
    """Section 'Why the study's limits differ from the design formulas', with numbers."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        rows = design_table(study, ds)
    static = _design_value(rows, "this study, static")
    impulse = _design_value(rows, "this study, envelope")
    jump, L = study.jump, study.length
    net_w = study.concrete.density * hy.G - hy.GAMMA_W
    x = np.linspace(0.0, L, 2001)
    net = hy.base_uplift(jump, x, residual_head=study.residual_head) - hy.top_pressure(jump, x)
    U = float(np.sum(0.5 * (net[1:] + net[:-1]) * np.diff(x)))
    U_lin = 0.5 * float(net[0] + net[-1]) * L
    float_1 = U / (net_w * L)
    kern = _design_value(rows, "kern rule")
    fr = _design_value(rows, "Fiorotto & Rinaldo (1992), Ω = 0.15, C")
    fr_study = study.amplitude * jump.velocity_head * hy.GAMMA_W / net_w
    dombrovsky = _design_value(rows, "Dombrovsky")
    x_static = float("nan")
    kinds = _strings(ds, "kind")
    if np.any(kinds == "static"):
        x_static = failure_position(ds, int(np.flatnonzero(kinds == "static")[0]))

    def ratio(a: float, b: float) -> str:
        return _num(a / b, ".2f") if math.isfinite(a) and math.isfinite(b) and b else _DASH

    items = [
        f"USACE flotation ({_num(float_1, '.2f', 'm')} at SF = 1): the whole slab, rigid, "
        "floats when its submerged weight equals the resultant of the mean profile's net "
        f"uplift ({U / 1e3:.0f} kN/m), wherever that uplift acts. The study's static limit "
        f"({_num(static, '.2f', 'm')}, {ratio(static, float_1)} × it) is larger because the "
        "net uplift is concentrated at the upstream end (the jump's deficit is largest at "
        "the toe) and the study fails at the first local opening "
        f"(x = {_num(x_static, '.1f', 'm')}) of a slab that bends, long before the whole "
        "slab would float.",
        f"Kern rule ({_num(kern, '.2f', 'm')}): a rigid slab on a Winkler bed (independent "
        "springs) whose upstream edge lifts when the resultant leaves the kern, under a net "
        f"uplift taken linear between its end values (resultant {U_lin / 1e3:.0f} kN/m "
        f"against {U / 1e3:.0f} kN/m of the actual tanh profile, whose deficit falls off "
        "within the roller). The study resolves the slab's bending on an elastic foundation "
        "block and the actual profile: its static limit is "
        f"{_num(static, '.2f', 'm')} ({ratio(static, kern)} × the kern rule's), and the "
        f"joint opens at x = {_num(x_static, '.1f', 'm')}, where the deficit and the "
        "bending meet, not necessarily at the edge.",
        f"Fiorotto & Rinaldo ({_num(fr, '.2f', 'm')} with Ω = 0.15, C⁺p + C⁻p = 0.8): a "
        "rigid slab whose submerged weight balances the fluctuating net pressure averaged "
        "over its area (Ω < 1 for the non-simultaneity of the extremes), with no mean "
        f"uplift. The study's impulse ({study.amplitude:g} ρ_w V1²/2 over a "
        f"{study.footprint:g} m strip, {100 * study.footprint / L:.0f} % of the slab) is not "
        f"averaged (their formula with Ω (C⁺p + C⁻p) = {study.amplitude:g}, the study's "
        f"amplitude, gives {fr_study:.2f} m), acts on top of "
        "the static loads and is resisted by the slab's bending and weight: the study's "
        f"envelope is {_num(impulse, '.2f', 'm')} ({ratio(impulse, fr)} × their value). "
        "The amplitude, footprint and Ω are the inputs to revisit.",
        f"Dombrovsky ({_num(dombrovsky, '.2f', 'm')}): an empirical rule from V1 and h1 "
        "alone — no slab length, foundation, uplift model or pulsation: comparable in "
        "magnitude only.",
        "All formulas treat the slab as rigid and the uplift as known; the study also "
        "couples the pressure in the joint to the contact (the opened gap holds water) and, "
        "for the impulse, the slab's inertia (a short pulse can lift it less than a slow "
        "one, a sudden one up to twice as much).",
    ]
    return [_Heading(2, "Why the study's limits differ from the design formulas"),
            _Para("The design formulas idealise the slab and its support; the study solves "
                  "the slab and its foundation as elastic bodies in frictional contact. "
                  "Each formula against the study's limits:"), _List(items)]


def _coefficients(study: BasinStudy) -> list[_Block]:
    """Section 'Coefficients and their sources': every quoted coefficient, its source and
    whether it was checked against the source (in words)."""
    defaults = BasinStudy()
    study_values = {"velocity coefficient of the inflow φ": (study.phi, defaults.phi),
                    "impulse amplitude": (study.amplitude, defaults.amplitude),
                    "friction of concrete on sand f": (study.friction, defaults.friction),
                    "critical depth of the design discharge h_kr (m)": (study.h_kr,
                                                                        defaults.h_kr)}
    rows = []
    for c in hy.COEFFICIENTS:
        status = c.status + (f": {c.against}" if c.against else "")
        if c.name in study_values:
            used, default = study_values[c.name]
            if used != default:
                status = f"not used: this study gives {used:g} (an input)"
        values = ", ".join(f"{v:g}" for v in c.values) if len(c.values) <= 4 else \
            f"{len(c.values)} values"
        rows.append((c.name, values, c.formula, c.source, status))
    return [_Heading(2, "Coefficients and their sources"),
            _Para("Every coefficient the study quotes. Only the article's own text was at hand "
                  "to check against; the papers and codes cited were not, so their "
                  "coefficients are marked “recalled, not checked against the source” (or "
                  "“read in a source …” when they were read when the code was written)."),
            _Table(("coefficient", "value(s)", "formula", "source", "checked?"), rows)]


def _report_blocks(ds: xr.Dataset, study: BasinStudy) -> tuple[str, list[_Block]]:
    """The title and the content blocks of the report (rendered by :func:`write_report`)."""
    title = "Stilling-basin slab study: limit thickness of the apron slab"
    blocks: list[_Block] = [_Para("Source: stepcontact.study.basin (method.md §7, the "
                                  "article's Figs. 4–5).")]
    blocks += _software(ds)
    blocks += _inputs(study) + _hydraulics(study) + _formulas(study) + _assumptions(study)
    blocks += _method(study) + _mesh(ds, study)
    if all_failed(ds):
        return title, blocks + _all_failed(ds) + _coefficients(study) + _caveats(study)
    blocks += _results(ds, study) + _differences(ds, study) + _failed(ds, study)
    blocks += _coefficients(study) + _caveats(study)
    return title, blocks


# ------------------------------------------------------------------------------ rendering ---

def _md_cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _to_markdown(title: str, blocks: Sequence[_Block]) -> str:
    """The report as Markdown (GitHub tables)."""
    out = [f"# {title}", ""]
    for b in blocks:
        if isinstance(b, _Heading):
            out += ["#" * b.level + " " + b.text, ""]
        elif isinstance(b, _Para):
            out += [b.text, ""]
        elif isinstance(b, _Table):
            out.append("| " + " | ".join(map(_md_cell, b.header)) + " |")
            out.append("|" + "---|" * len(b.header))
            out += ["| " + " | ".join(map(_md_cell, r)) + " |" for r in b.rows]
            out.append("")
        elif isinstance(b, _Image):
            out += [f"![{b.alt}]({b.src})", "", f"*{b.caption}*", ""]
        elif isinstance(b, _List):
            out += [f"- {item}" for item in b.items] + [""]
    return "\n".join(out)


_CSS = """
body { font-family: system-ui, sans-serif; max-width: 72rem; margin: 2rem auto;
       padding: 0 1rem; line-height: 1.45; color: #222; }
h1 { font-size: 1.6rem; } h2 { font-size: 1.25rem; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 0.8rem 0; font-size: 0.9rem; }
th, td { border: 1px solid #ccc; padding: 0.25rem 0.5rem; text-align: left;
         vertical-align: top; }
th { background: #f2f2f2; } tr:nth-child(even) td { background: #fafafa; }
figure { margin: 1rem 0; } img { max-width: 100%; border: 1px solid #eee; }
figcaption { font-size: 0.9rem; color: #555; }
"""


def _to_html(title: str, blocks: Sequence[_Block]) -> str:
    """The report as one self-contained HTML page (inline CSS; images by relative path)."""
    e = html.escape
    out = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
           f"<title>{e(title)}</title>", f"<style>{_CSS}</style>", "</head>", "<body>",
           f"<h1>{e(title)}</h1>"]
    for b in blocks:
        if isinstance(b, _Heading):
            out.append(f"<h{b.level}>{e(b.text)}</h{b.level}>")
        elif isinstance(b, _Para):
            out.append(f"<p>{e(b.text)}</p>")
        elif isinstance(b, _Table):
            out.append("<table>")
            out.append("<thead><tr>" + "".join(f"<th>{e(h)}</th>" for h in b.header)
                       + "</tr></thead>")
            out.append("<tbody>")
            out += ["<tr>" + "".join(f"<td>{e(c)}</td>" for c in r) + "</tr>" for r in b.rows]
            out.append("</tbody></table>")
        elif isinstance(b, _Image):
            out.append(f'<figure><img src="{e(b.src)}" alt="{e(b.alt)}">'
                       f"<figcaption>{e(b.caption)}</figcaption></figure>")
        elif isinstance(b, _List):
            out.append("<ul>" + "".join(f"<li>{e(i)}</li>" for i in b.items) + "</ul>")
    out += ["</body>", "</html>", ""]
    return "\n".join(out)


def _write_text(path: Path, text: str) -> None:
    """Write ``text`` (UTF-8) atomically."""
    write_text(path, text)


def write_report(ds: xr.Dataset, study: BasinStudy, out_dir: str | os.PathLike[str], *,
                 dpi: float = DPI) -> dict[str, Path]:
    """Write the study's report into ``out_dir``: ``report.md``, ``report.html`` (self-
    contained, inline CSS) and the figures ``figures/limits.png`` (:func:`plot_limits`) and
    ``figures/edge_stresses.png`` (:func:`plot_edge_stresses`) at ``dpi``, all atomically.
    Returns their paths: keys ``markdown``, ``html``, ``limits``, ``edge_stresses``.  When
    every case failed, only the report is written: it says so and lists the reasons.  The
    mesh check is the dataset's (``ds.attrs["mesh_check"]``, :func:`run_basin
    <stepcontact.study.basin.run_basin>`); without one the report says that none was run."""
    out = Path(out_dir)
    if all_failed(ds):  # no figure: the report says that and why
        title, blocks = _report_blocks(ds, study)
        paths = {"markdown": out / "report.md", "html": out / "report.html"}
        _write_text(paths["markdown"], _to_markdown(title, blocks))
        _write_text(paths["html"], _to_html(title, blocks))
        return paths
    paths = {key: out / rel for key, rel in FIGURES.items()}
    plot_limits(ds, study, paths["limits"], dpi=dpi)
    plot_edge_stresses(ds, study, paths["edge_stresses"], dpi=dpi)
    title, blocks = _report_blocks(ds, study)
    paths["markdown"] = out / "report.md"
    paths["html"] = out / "report.html"
    _write_text(paths["markdown"], _to_markdown(title, blocks))
    _write_text(paths["html"], _to_html(title, blocks))
    return paths


__all__ = ["COLORS", "FIGURES", "ZOOM", "case_table", "failure_position", "governing_case",
           "plot_edge_stresses", "plot_limits", "write_report", "zoom_window"]
