"""Figures and report of the dam study (:mod:`stepcontact.study.dam_study`).

* :func:`plot_section` — the section with its loads: the dam, the foundation, the reservoir at
  the normal and flood levels, the tailwater, the drains, the resultants W, H, U at the normal
  level, and below it the uplift head along the base;
* :func:`plot_base_stresses` — σ_n along the base at the named levels (the FE's contact
  stresses beside the rigid-base linear distribution);
* :func:`plot_crack_length` — the open (and, for a bonded joint, broken) length of the base
  against the level;
* :func:`plot_level_displacement` — the λ–u curve: the level against the crest's horizontal
  displacement;
* :func:`write_report` — ``report.md``, ``report.html`` (rendered by the slab study's
  machinery, :mod:`stepcontact.study.report`), ``summary.json``, the figures
  ``figures/*.png`` and the run's ``result.nc``, all written atomically.

Units: SI (m, N and N·m per metre of dam, Pa); the figures show stresses in MPa and
displacements in mm.  No guideline's criteria or verdicts: the report gives the figures and the
margins.
"""

from __future__ import annotations

import dataclasses
import json
import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from stepcontact.io.atomic import write_text
from stepcontact.post.common import DPI, figure_path, new_figure, save_figure
from stepcontact.study.dam import DamSection
from stepcontact.study.dam_quake import (
    QUAKE_FIGURES,
    describe_record,
    plot_quake,
    quake_blocks,
)
from stepcontact.study.dam_study import DamStudy, base_stresses, dam_of, summary
from stepcontact.study.report import (
    _Block,
    _Heading,
    _Image,
    _List,
    _modulus,
    _num,
    _Para,
    _Table,
    _to_html,
    _to_markdown,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: the figure files written by :func:`write_report`, relative to its ``out_dir``
FIGURES = {"section": "figures/section.png", "base_stresses": "figures/base_stresses.png",
           "crack_length": "figures/crack_length.png",
           "level_displacement": "figures/level_displacement.png",
           "yield": "figures/yield_acceleration.png"}
#: colours of the named states
COLORS = {"self-weight": "#7f7f7f", "normal": "#1f77b4", "flood": "#ff7f0e",
          "first break": "#9467bd", "first opening": "#2ca02c", "failure": "#d62728"}
_WATER = "#9ecae1"


# ---------------------------------------------------------------------------- figures ---

def plot_section(study: DamStudy, path: str | os.PathLike[str] | None = None, *,
                 dpi: float = DPI) -> Figure:
    """The section with its loads (m): dam, foundation block (or rigid base), reservoir at
    the normal and flood levels, tailwater, drain line, the resultants of the weight W, the
    reservoir's thrust H and the uplift U at the normal level (arrows, values in the legend,
    kN per metre); below, the uplift head along the base (m of water) at the normal and flood
    levels."""
    s = study.section
    if not isinstance(s, DamSection):  # a model file's dam: drawn from its mesh
        from stepcontact.study.dam_file import plot_model_section

        return plot_model_section(study, path, dpi=dpi)
    p = figure_path(path, dpi)
    H, B = s.height, s.base_length
    up, down = s.extents
    fig = new_figure(figsize=(9.0, 7.6))
    ax, axu = fig.subplots(2, 1, height_ratios=(3.0, 1.2), sharex=True)
    ax.set_aspect("equal", adjustable="datalim")
    left, right = -min(up, 0.6 * H), B + min(down, 0.6 * H)
    depth = min(s.depth, 0.35 * H)
    if s.rock is not None:
        ax.fill([left, right, right, left], [0, 0, -depth, -depth], color="#e5d8bd", lw=0,
                label=f"foundation ({s.depth:g} m deep, {up:g} m / {down:g} m beyond "
                      "heel / toe; cut)")
    else:
        ax.plot([left, right], [0, 0], color="0.2", lw=3, label="rigid base")
    xs, ys = zip(*s.corners, strict=True)
    ax.fill(xs, ys, color="0.82", ec="0.2", lw=1.2, label=f"dam, B = {B:g} m")
    x_face = s.upstream_slope
    for lv, name, alpha in ((s.flood_level, "flood", 0.35), (s.normal_level, "normal", 0.6)):
        d = min(lv, H)
        ax.fill([left, 0.0, x_face * d, left], [0, 0, d, d] if lv <= H else [0, 0, d, d],
                color=_WATER, alpha=alpha, lw=0)
        ax.plot([left, x_face * d], [lv, lv] if lv <= H else [d, d], color=COLORS[name],
                lw=1.4, ls="--", label=f"{name} level {lv:g} m")
    if s.tailwater > 0:
        t = s.tailwater
        ax.fill([B - s.downstream_slope * t, B, right, right], [t, 0, 0, t], color=_WATER,
                alpha=0.6, lw=0, label=f"tailwater {t:g} m")
    if s.drain_position is not None:
        ax.plot([s.drain_position] * 2, [0, -0.6 * depth], color="k", lw=1.5, ls=":",
                label=f"drains at {s.drain_position:g} m, E = {s.drain_efficiency:g}")
    hs = next((n.hand for n in study.named if n.name == "normal"), None)
    if hs is not None:  # the resultants as arrows of one length (their values in the legend)
        size = 0.18 * H
        xw = B - hs["W_lever"]
        arrows = [((xw, 0.4 * H + size), (0, -size), "#555555",
                   f"W = {hs['W'] / 1e3:.0f} kN at {hs['W_lever']:.2f} m from the toe"),
                  ((x_face * hs["H_up_arm"] - size, hs["H_up_arm"]), (size, 0),
                   COLORS["normal"],
                   f"H = {hs['H_up'] / 1e3:.0f} kN at {hs['H_up_arm']:.2f} m above the base"),
                  ((B - hs["U_lever"], -0.8 * depth), (0, 0.8 * depth), "#6a3d9a",
                   f"U = {hs['U'] / 1e3:.0f} kN at {hs['U_lever']:.2f} m from the toe")]
        for (x0, y0), (dx, dy), c, label in arrows:
            ax.annotate("", xy=(x0 + dx, y0 + dy), xytext=(x0, y0),
                        arrowprops={"arrowstyle": "-|>", "color": c, "lw": 2.0,
                                    "mutation_scale": 18})
            ax.plot([], [], color=c, lw=2.0, label=label + " (normal level)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"Gravity-dam section: H = {H:g} m, crest {s.crest_width:g} m, batters "
                 f"{s.upstream_slope:g} (upstream), {s.downstream_slope:g} (downstream)",
                 fontsize="medium")
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="x-small",
              frameon=False)
    x = np.linspace(0.0, B, 201)
    for lv, name in ((s.normal_level, "normal"), (s.flood_level, "flood")):
        axu.plot(x, s.uplift_head(x, lv), color=COLORS[name], lw=1.5,
                 label=f"{name} level {lv:g} m")
    from stepcontact.study.dam_file import finish_uplift_panel

    return finish_uplift_panel(fig, axu, (left, right), "x from the heel (m)", p, dpi)


def plot_base_stresses(study: DamStudy, path: str | os.PathLike[str] | None = None, *,
                       dpi: float = DPI) -> Figure:
    """σ_n (MPa, ≤ 0 in compression) along the base against x from the heel (m) at the named
    levels: the contact stresses N/A of the run (solid, markers) and the rigid-base linear
    distribution of the uncracked base (dashed, −ΣV/B (1 ∓ 6e/B))."""
    p = figure_path(path, dpi)
    s = study.section
    B = s.base_length
    fig = new_figure(figsize=(9.0, 5.4))
    ax = fig.add_subplot()
    for n in study.named:
        c = COLORS.get(n.name, "k")
        x, sn = base_stresses(study, n.state)
        ax.plot(x, sn / 1e6, color=c, lw=1.5, marker=".", label=f"{n.name}, h = {n.level:.2f} m")
        if n.name != "failure" and n.hand:  # no hand statics for a model file's dam
            ax.plot([0.0, B], [-n.hand["sigma_heel"] / 1e6, -n.hand["sigma_toe"] / 1e6],
                    color=c, lw=1.0, ls="--")
    if any(n.hand for n in study.named):
        ax.plot([], [], color="0.3", lw=1.0, ls="--",
                label="rigid base, uncracked: linear (same colour)")
    ax.axhline(0.0, color="0.3", lw=0.6)
    ax.set_xlim(0.0, B)
    ax.set_xlabel("x from the heel (m)")
    ax.set_ylabel("σ_n (MPa), compression < 0")
    ax.grid(True, alpha=0.3)
    ax.set_title("Normal stress along the base at the named levels", fontsize="medium")
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncols=3,
               fontsize="x-small", frameon=False)
    save_figure(fig, p, dpi)
    return fig


def _level_marks(ax, study: DamStudy, *, vertical: bool) -> None:
    """Lines at the normal and flood levels, the first opening and the failure."""
    s = study.section
    marks = [(s.normal_level, "normal", f"normal level {s.normal_level:g} m"),
             (s.flood_level, "flood", f"flood level {s.flood_level:g} m")]
    if study.first_break is not None:
        marks.append((study.first_break[0], "first break",
                      f"bond first breaks {study.first_break[0]:.2f} m"))
    if study.first_opening is not None:
        marks.append((study.first_opening[0], "first opening",
                      f"first opening {study.first_opening[0]:.2f} m"))
    if study.failure is not None:
        marks.append((study.failure[0], "failure",
                      f"failure ({study.failure[1]}) {study.failure[0]:.2f} m"))
    for lv, key, label in marks:
        (ax.axvline if vertical else ax.axhline)(lv, color=COLORS[key], lw=1.0, ls=":",
                                                 label=label)


def plot_crack_length(study: DamStudy, path: str | os.PathLike[str] | None = None, *,
                      dpi: float = DPI) -> Figure:
    """The open length of the base (m; the open CFEs' share of B) against the reservoir level
    (m), and for a bonded joint the broken length; dotted: the named levels."""
    p = figure_path(path, dpi)
    pth = study.path
    fig = new_figure(figsize=(8.0, 5.0))
    ax = fig.add_subplot()
    ax.step(pth["level"], pth["open_length"], where="post", color="#d62728", lw=1.6,
            label="open length")
    if study.section.bonded:
        ax.step(pth["level"], pth["broken_length"], where="post", color="#9467bd", lw=1.2,
                ls="--", label="broken (cracked) length")
    _level_marks(ax, study, vertical=True)
    ax.set_xlim(0.0, float(pth["level"].max()) * 1.03 if pth["level"].size else 1.0)
    ax.set_ylim(0.0, study.section.base_length)
    ax.set_xlabel("reservoir level h (m above the base)")
    ax.set_ylabel("length along the base (m)")
    ax.grid(True, alpha=0.3)
    ax.set_title(f"Crack (open) length of the base against the level, B = "
                 f"{study.section.base_length:g} m", fontsize="medium")
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncols=3,
               fontsize="x-small", frameon=False)
    save_figure(fig, p, dpi)
    return fig


def plot_level_displacement(study: DamStudy, path: str | os.PathLike[str] | None = None, *,
                            dpi: float = DPI) -> Figure:
    """The λ–u curve: the reservoir level (m) against the horizontal displacement of the
    upstream crest corner (mm, downstream > 0), one point per reported state."""
    p = figure_path(path, dpi)
    pth = study.path
    fig = new_figure(figsize=(8.0, 5.0))
    ax = fig.add_subplot()
    ax.plot(pth["crest_ux"] * 1e3, pth["level"], color="k", lw=1.4, marker=".",
            label="reported states")
    _level_marks(ax, study, vertical=False)
    ax.set_xlabel("crest displacement u_x (mm, downstream > 0)")
    ax.set_ylabel("reservoir level h (m)")
    ax.grid(True, alpha=0.3)
    ax.set_title("Level against crest displacement (λ–u)", fontsize="medium")
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncols=3,
               fontsize="x-small", frameon=False)
    save_figure(fig, p, dpi)
    return fig


def yield_path(study: DamStudy) -> dict[str, np.ndarray]:
    """The states of the yield run's k_h segment (and the last state before it, k_h = 0):
    ``k_h``, ``crest_ux`` (m, the upstream crest corner), ``open_length`` (m)."""
    y = study.yield_acceleration
    res = y.result
    seg = np.asarray(res.segment)
    quake = [g for g, (pt, _, _) in enumerate(res.segments) if pt == "earthquake"]
    on = np.flatnonzero(np.isin(seg, quake))
    states = np.r_[on[0] - 1, on] if on.size and on[0] > 0 else on
    k_h = np.where(np.isin(seg[states], quake), np.asarray(res.lam, float)[states], 0.0)
    d = dam_of(study.section)
    ux = np.asarray(res.node_history(point=d.crest, quantity="ux", body=d.body),
                    float)[states]
    opened = np.asarray(res.interface_safety(d.joint, heel=d.heel).open_length,
                        float)[states]
    return {"k_h": k_h, "crest_ux": ux, "open_length": opened}


def plot_yield(study: DamStudy, path: str | os.PathLike[str] | None = None, *,
               dpi: float = DPI) -> Figure:
    """The incremental analysis to failure on k_h: left, k_h against the crest's horizontal
    displacement (mm) after the usual loads; right, the open length of the base (m) against
    k_h; dotted: the design k_h, the first slip and first opening, the yield acceleration
    k_y."""
    p = figure_path(path, dpi)
    y = study.yield_acceleration
    pth = yield_path(study)
    fig = new_figure(figsize=(9.0, 5.0))
    ax, axo = fig.subplots(1, 2)
    ax.plot(pth["crest_ux"] * 1e3, pth["k_h"], color="k", lw=1.4, marker=".",
            label="reported states")
    axo.step(pth["k_h"], pth["open_length"], where="post", color="#d62728", lw=1.6,
             label="open length")
    marks = [(y.design, "#1f77b4", f"design k_h = {y.design:g}")]
    if y.first_slip is not None:
        marks.append((y.first_slip, "#7f7f7f", f"first slip {y.first_slip:.3f}"))
    if y.first_opening is not None:
        marks.append((y.first_opening, "#2ca02c", f"first opening {y.first_opening:.3f}"))
    if y.k_y is not None:
        marks.append((y.k_y, "#d62728", f"k_y = {y.k_y:.4f} ({y.mode})"))
    for v, c, label in marks:
        ax.axhline(v, color=c, lw=1.0, ls=":", label=label)
        axo.axvline(v, color=c, lw=1.0, ls=":")
    ax.set_xlabel("crest displacement u_x (mm, downstream > 0)")
    ax.set_ylabel("seismic coefficient k_h (g)")
    axo.set_xlabel("seismic coefficient k_h (g)")
    axo.set_ylabel("open length of the base (m)")
    axo.set_ylim(0.0, study.section.base_length)
    axo.set_xlim(0.0, max(float(pth["k_h"].max(initial=0.0)), y.design) * 1.05)
    for a in (ax, axo):
        a.grid(True, alpha=0.3)
    fig.suptitle("Yield acceleration: k_h raised after the usual loads", fontsize="medium")
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncols=3,
               fontsize="x-small", frameon=False)
    save_figure(fig, p, dpi)
    return fig


# ----------------------------------------------------------------------------- report ---

#: unit and meaning of each field of DamSection
FIELDS: dict[str, tuple[str, str]] = {
    "height": ("m", "height H of the dam"),
    "crest_width": ("m", "crest width b_c"),
    "upstream_slope": ("H:V", "batter n_u of the upstream face (0: vertical)"),
    "downstream_slope": ("H:V", "batter n_d of the downstream face"),
    "concrete": ("", "the dam's concrete"),
    "rock": ("", "the foundation's rock (none: a rigid base)"),
    "foundation_depth": ("m", "depth of the foundation block (default H)"),
    "upstream_extent": ("m", "foundation beyond the heel (default H)"),
    "downstream_extent": ("m", "foundation beyond the toe (default H)"),
    "friction_angle": ("°", "peak friction angle φ of the joint"),
    "cohesion": ("Pa", "peak cohesion c of the joint (> 0: a bond, eq. (12))"),
    "tensile_strength": ("Pa", "tensile strength σ_t of the joint's bond"),
    "residual_friction_angle": ("°", "friction angle after the bond breaks (default φ)"),
    "residual_cohesion": ("Pa", "cohesion after the bond breaks"),
    "drain_position": ("m", "drain line's distance from the heel (none: no drains)"),
    "drain_efficiency": ("–", "drain efficiency E"),
    "normal_level": ("m", "normal reservoir level above the base (usual case)"),
    "flood_level": ("m", "flood level above the base (unusual case)"),
    "tailwater": ("m", "tailwater level above the base"),
    "max_level": ("m", "highest level of the run to failure (default 3 H)"),
    "crack_water": ("–", "full reservoir pressure in the crack opened from the heel"),
    "cell": ("m", "cell size of the dam's mesh"),
    "foundation_cell": ("m", "cell size of the foundation's mesh (default 1.6 × cell)"),
    "guideline": ("", "the guideline of the verdicts: usace, ferc or cda"),
    "guideline_variant": ("", "the guideline's variant (USACE: structure class, site "
                          "information)"),
    "k_h": ("g", "design horizontal seismic coefficient (extreme combination)"),
    "k_v": ("g", "design vertical seismic coefficient, > 0 upwards (ratio k_v/k_h kept on "
            "the yield run)"),
    "max_kh": ("g", "the yield run's highest k_h"),
    "silt_level": ("m", "silt against the upstream face up to this level (none: no silt)"),
    "silt_unit_weight": ("N/m³", "the silt's equivalent fluid K γ'_s"),
    "compressive_strength": ("Pa", "the joint's compressive strength (none: no stress check)"),
    "level_step": ("m", "the reservoir's segments end every so many metres (default H/20)"),
    "record": ("", "the earthquake record (none: no time history; see 'Earthquake record')"),
}


def _field_value(name: str, v) -> str:
    if v is None:
        return {"rock": "none: rigid base", "drain_position": "none: no drains",
                "guideline_variant": "the guideline's default", "silt_level": "none: no silt",
                "compressive_strength": "none: no stress check",
                "record": "none"}.get(name, "default")
    if name == "record":  # the earthquake record (stepcontact.study.dam_quake)
        return describe_record(v)
    if hasattr(v, "E") and hasattr(v, "density"):
        return f"E = {_modulus(v.E)}, ν = {v.nu:g}, ρ = {v.density:g} kg/m³"
    if isinstance(v, float):
        return f"{v:g}"
    return str(v)


def _inputs(s: DamSection) -> list[_Block]:
    if not isinstance(s, DamSection):
        from stepcontact.study.dam_file import report_inputs

        return report_inputs(s)
    rows = [(f.name, _field_value(f.name, getattr(s, f.name)), *FIELDS.get(f.name, ("", "")))
            for f in dataclasses.fields(s)]
    up, down = s.extents
    derived = [("base length B", f"{s.base_length:g}", "m", "b_c + (n_u + n_d) H"),
               ("area of the section", f"{s.area:g}", "m²", "(B + b_c) H / 2"),
               ("f = tan φ", f"{s.friction:.4f}", "–", ""),
               ("foundation", "rigid" if s.rock is None else
                f"{up + s.base_length + down:g} × {s.depth:g}", "m", "width × depth"),
               ("dam mesh", f"{s.cells[0]} × {s.cells[1]} quad4", "cells",
                "along the base × up the height")]
    return [_Heading(2, "Section and inputs"),
            _Para("Every field of the DamSection (SI units; plane strain, per metre of "
                  "dam). The heel is at (0, 0), the toe at (B, 0); levels are heights above "
                  "the base."),
            _Table(("field", "value", "unit", "meaning"), rows),
            _Table(("derived", "value", "unit", "how"), derived)]


def _assumptions(s: DamSection) -> list[_Block]:
    if not isinstance(s, DamSection):
        from stepcontact.study.dam_file import report_assumptions

        return report_assumptions(s)
    res_k = (1.0 - s.drain_efficiency) * (s.base_length - s.drain_position) / s.base_length \
        if s.drain_position is not None else None
    uplift = ("Uplift under the base: full reservoir head h at the heel, the tailwater head t "
              "at the toe, linear between" if res_k is None else
              f"Uplift under the base: full head h at the heel, t at the toe, and at the drain "
              f"line (x_d = {s.drain_position:g} m) h_d = t + (1 − E)(h − t)(B − x_d)/B = t + "
              f"{res_k:.4f} (h − t), linear between (USACE EM 1110-2-2100 (2005) §3-3 "
              "[to be checked: section])")
    items = [
        "Plane strain, per metre of dam; linear elastic dam and foundation (small "
        "displacements); the only nonlinearity is the joint (unilateral contact with Coulomb "
        "friction, solved exactly event by event: Lukashevich & Rozin 2013).",
        f"Concrete E = {_modulus(s.concrete.E)}, ν = {s.concrete.nu:g}, ρ = "
        f"{s.concrete.density:g} kg/m³ (unit weight ρ g, g = 9.81 m/s²). " + (
            "Rigid base (no foundation deformation)." if s.rock is None else
            f"Rock E = {_modulus(s.rock.E)}, ν = {s.rock.nu:g}; the block is fixed at its "
            "bottom, its sides free, its own weight not applied (the dam's weight is the "
            "first load on the joint)."),
        f"The joint: friction angle φ = {s.friction_angle:g}° (f = {s.friction:.4f})"
        + (f", a Mohr–Coulomb bond (eq. (12)): c = {s.cohesion / 1e3:g} kPa, σ_t = "
           f"{s.tensile_strength / 1e3:g} kPa, breaking into friction tan φ_r = "
           f"{s.residual_friction:.4f} with residual cohesion {s.residual_cohesion / 1e3:g} "
           "kPa" if s.bonded else ", no cohesion, no tensile strength")
        + "; the meshes of dam and rock do not match (mortar CFEs).",
        "Water: γ_w = 9810 N/m³. The reservoir's hydrostatic pressure on the upstream face "
        "follows the level exactly (the level is the load parameter); above the crest only "
        "the upstream face is loaded (no overflow). The water's weight on the foundation's "
        "surface is not applied.",
        uplift + "; the uplift acts on both faces of the joint, whether closed or open.",
        ("Crack water: where the joint has opened in a run connected to the heel, the full "
         "reservoir pressure γ_w h replaces the uplift (the cracked-base assumption: USACE "
         "EM 1110-2-2100, FERC Engineering Guidelines ch. 3 [to be checked: sections])."
         if s.crack_water else "No crack water: the uplift stays as given where the joint "
         "opens."),
        (f"Tailwater t = {s.tailwater:g} m: hydrostatic on the downstream face and its "
         "share of the uplift, applied after the self-weight and held constant."
         if s.tailwater > 0 else "No tailwater."),
        "Loading: self-weight (factor 0 → 1), the tailwater, then the reservoir from the "
        f"base up through the normal ({s.normal_level:g} m) and flood ({s.flood_level:g} m) "
        f"levels and on to {s.top_level:g} m or until the dam loses equilibrium.",
        "Margins are factors on the level (level at the limit / named level), not the "
        "guidelines' factors of safety; the factors of the table are those of the joint at "
        "each state (stepcontact.results.safety).",
        "Hand statics: rigid base, uncracked base, the uplift as above, no crack water; "
        "moments about the toe, positive when they resist (press the heel down).",
        f"One mesh (dam cells of {s.cell:g} m): the levels of first opening and of failure "
        "depend on it (the heel is a singular corner of the elastic solution); run the study "
        "again with the cells halved to see by how much.",
        *_combination_assumptions(s),
    ]
    return [_Heading(2, "Assumptions"), _List(items)]


def _combination_assumptions(s: DamSection) -> list[str]:
    from stepcontact.results.dam_checks import load_guidelines

    g = load_guidelines()[s.guideline]
    variant = s.guideline_variant or g.default_variant
    silt = ("" if s.silt_level is None else
            f", silt to {s.silt_level:g} m (an equivalent fluid of {s.silt_unit_weight:g} "
            "N/m³ normal to the upstream face: EM 1110-2-2200 (1995) ch. 3 [to be checked])")
    return [
        "Load combinations (stepcontact.model.combinations), each its own run from the "
        f"unloaded dam: usual — self-weight, reservoir at the normal level "
        f"({s.normal_level:g} m), tailwater, uplift{silt}"
        + ("" if s.flood_level == s.normal_level else
           f"; unusual (flood) — the same at the flood level ({s.flood_level:g} m)")
        + f"; extreme (earthquake) — the usual loads and the pseudo-static earthquake k_h = "
        f"{s.k_h:g}, k_v = {s.k_v:g} (+ up); post-earthquake — the same earthquake applied "
        "and removed, the checks read the cracked, slid state under the usual loads.",
        "Pseudo-static earthquake (seismic coefficient method, EM 1110-2-2200 (1995) ch. 3 "
        "[to be checked]): inertia ρ g (k_h, k_v) of the dam towards the toe, and the "
        "reservoir's hydrodynamic pressure p(z) = (7/8) k_h γ_w √(h z) on the upstream face "
        "(Westergaard 1933; resultant (7/12) k_h γ_w h² at 0.4 h on a vertical face; on a "
        "batter the normal-direction form of Kuo 1982): rigid face, incompressible water, no "
        "hydrodynamic pressure on the tailwater face, the hydrostatic loads unchanged by k_v.",
        f"Guideline verdicts: {g.title} ({g.document}), variant "
        f"'{variant or '—'}' ({g.variant_meaning}). Each combination's condition is read as "
        "the guideline's load class (the verdict table's first row, with its source); every "
        "required value carries its source and is marked [to be checked] where it was not "
        "confirmed against the document — check those before relying on a verdict.",
        "The checks read the joint's state at the end of each combination's run: the "
        "sliding factor (c A_c + N' tan φ)/H with the compressed area A_c of the elastic "
        "model (EM 1110-2-2100 eq. 3-1), the resultant's position and the compressed "
        "fraction of the base, the uplift factor, the compressive stress factor when a "
        "compressive strength is given (stepcontact.results.dam_checks). A combination whose "
        "run loses equilibrium fails.",
        f"Yield acceleration: after the usual loads, k_h raised on one segment from 0 to "
        f"{s.max_kh:g} (k_v in the ratio {s.k_v:g}/{s.k_h:g}, the hydrodynamic pressure "
        "with it, cracks and crack water as they develop); k_y is the k_h at which "
        "equilibrium is lost, an exact event of the run, and its margin is k_y / k_h.",
    ]


_FIGURE_ROWS = (
    ("level h (m)", lambda n: _num(n.level, ".3f")),
    ("state", lambda n: str(n.state)),
    ("ΣN (kN, compression < 0)", lambda n: _num(n.values["normal_force"] / 1e3, ".1f")),
    ("ΣQ (kN)", lambda n: _num(n.values["shear_force"] / 1e3, ".1f")),
    ("friction-only factor f ΣN'/ΣQ", lambda n: _num(n.values["friction_only_factor"], ".4f")),
    ("shear-friction factor (cA_c + ΣN' tan φ)/ΣQ",
     lambda n: _num(n.values["shear_friction_factor"], ".4f")),
    ("overturning factor ΣM_r/ΣM_o (toe)", lambda n: _num(n.values["overturning_factor"], ".4f")),
    ("resultant from the toe (m)", lambda n: _num(n.values["resultant_from_toe"], ".3f")),
    ("in the middle third", lambda n: "yes" if n.values["in_kern"] else "no"),
    ("compressed length (m)", lambda n: _num(n.values["compressed_length"], ".2f")),
    ("open length (m)", lambda n: _num(n.values["open_length"], ".2f")),
    ("σ_n at the heel (kPa)", lambda n: _num(n.values["sigma_heel"] / 1e3, ".1f")),
    ("σ_n at the toe (kPa)", lambda n: _num(n.values["sigma_toe"] / 1e3, ".1f")),
)

_HAND_ROWS = (
    ("W, weight (kN)", "W", 1e3, ".1f"), ("lever of W from the toe (m)", "W_lever", 1, ".4f"),
    ("H, reservoir thrust (kN)", "H_up", 1e3, ".1f"),
    ("arm of H above the base (m)", "H_up_arm", 1, ".4f"),
    ("V, water on the upstream batter (kN)", "V_up", 1e3, ".1f"),
    ("lever of V from the toe (m)", "V_up_lever", 1, ".4f"),
    ("H_t, tailwater thrust (kN)", "H_down", 1e3, ".1f"),
    ("arm of H_t (m)", "H_down_arm", 1, ".4f"),
    ("V_t, tailwater on the downstream batter (kN)", "V_down", 1e3, ".1f"),
    ("lever of V_t from the toe (m)", "V_down_lever", 1, ".4f"),
    ("U, uplift (kN)", "U", 1e3, ".1f"), ("lever of U from the toe (m)", "U_lever", 1, ".4f"),
    ("ΣV = W + V + V_t − U (kN)", "sum_V", 1e3, ".1f"), ("ΣH = H − H_t (kN)", "sum_H", 1e3, ".1f"),
    ("ΣM_r about the toe (kN·m)", "M_resisting", 1e3, ".1f"),
    ("ΣM_o about the toe (kN·m)", "M_overturning", 1e3, ".1f"),
    ("ΣM = ΣM_r − ΣM_o (kN·m)", "sum_M", 1e3, ".1f"),
    ("resultant from the toe ΣM/ΣV (m)", "resultant_from_toe", 1, ".4f"),
    ("eccentricity e = B/2 − ΣM/ΣV (m)", "eccentricity", 1, ".4f"),
    ("σ heel = ΣV/B (1 − 6e/B) (kPa, compression > 0)", "sigma_heel", 1e3, ".1f"),
    ("σ toe = ΣV/B (1 + 6e/B) (kPa, compression > 0)", "sigma_toe", 1e3, ".1f"),
    ("friction-only factor tan φ ΣV/ΣH", "sliding_factor", 1, ".4f"),
    ("shear-friction factor (c B + tan φ ΣV)/ΣH", "shear_friction_factor", 1, ".4f"),
    ("overturning factor ΣM_r/ΣM_o", "overturning_factor", 1, ".4f"),
)


def _results(study: DamStudy) -> list[_Block]:
    s, res = study.section, study.result
    first = study.first_opening
    fail = study.failure
    text = [f"The run: {res.message or res.status} ({len(res.events)} events, "
            f"{len(res.lam)} reported states; max equilibrium residual "
            f"{float(np.max(res.residual)):.1e}, max contact-condition violation "
            f"{float(np.max(res.violation)):.1e}; {study.seconds:.2f} s of CPU)."]
    text.append("The base first opens at h = " + (f"{first[0]:.3f} m, at x = {first[1]:.2f} m "
                                                  "from the heel." if first else
                                                  "— (it does not open)."))
    if study.first_break is not None:
        text.append(f"The joint's bond first breaks at h = {study.first_break[0]:.3f} m, at "
                    f"x = {study.first_break[1]:.2f} m from the heel.")
    text.append("The dam fails at h = " + (f"{fail[0]:.3f} m ({fail[1]})." if fail else
                                           f"— (not up to {s.top_level:g} m)."))
    hl = study.hand_levels
    text.append("Rigid-base hand statics (uncracked base, no crack water): the resultant "
                "leaves the middle third (linear heel stress 0) at h = "
                f"{_num(hl['heel_tension'], '.3f', 'm')}; the shear-friction factor falls to "
                f"1 at h = {_num(hl['sliding'], '.3f', 'm')}.")
    margins = [(k, _num(v, ".4f")) for k, v in study.margins.items()]
    blocks: list[_Block] = [_Heading(2, "Results"), _Para(" ".join(text))]
    blocks += [_Heading(3, "Margins as factors on the level"),
               _Para("Level at the limit over the named level (m/m), and the yield "
                     "acceleration over the design k_h. Not the guidelines' factors of "
                     "safety."),
               _Table(("limit / named level", "factor"), margins)]
    blocks += [_List(study.notes)] if study.notes else []
    named = study.named
    blocks += [_Heading(3, "The joint's figures at the named levels"),
               _Para("From the run (stepcontact.results.safety.interface_safety at each "
                     "state): forces per metre of dam, σ_n of the end CFEs (compression < 0). "
                     + "; ".join(f"{n.name}: {n.description}" for n in named) + "."),
               _Table(("figure", *(n.name for n in named)),
                      [(label, *(f(n) for n in named)) for label, f in _FIGURE_ROWS])]
    hand = [n for n in named if n.name != "failure"]
    if not all(n.hand for n in hand):  # no hand statics for this dam
        return blocks
    blocks += [_Heading(3, "Hand statics for a reviewer"),
               _Para("Rigid base, uncracked base, per metre of dam; moments about the toe, "
                     "positive when they resist. With the base fully compressed the run's ΣN, "
                     "ΣQ, resultant position and factors equal these (equilibrium of the dam "
                     "alone); once it cracks, the run's differ (crack water, redistribution)."),
               _Table(("quantity", *(f"{n.name} (h = {n.level:.3f} m)" for n in hand)),
                      [(label, *(_num(n.hand[key] / scale, spec) for n in hand))
                       for label, key, scale, spec in _HAND_ROWS])]
    return blocks


def _verdicts(study: DamStudy) -> list[_Block]:
    """The guideline verdicts: a summary per combination, then each one's checks."""
    if not study.combinations:
        return []
    from stepcontact.results.dam_checks import load_guidelines

    chk = study.checks
    g = load_guidelines()[study.section.guideline]
    blocks: list[_Block] = [
        _Heading(2, "Guideline verdicts"),
        _Para(f"Overall verdict: {study.verdict} ({chk.guideline}"
              + (f", {chk.variant}" if chk.variant else "") + "). A check passes when its "
              "value meets the required value; '—' is not evaluated (the guideline has no "
              "value, the joint no strength for it, or the quantity does not exist). "
              "Required values marked [to be checked] were not confirmed against the "
              "document."),
        _Table(("combination", "condition", "guideline class", "verdict", "failed checks",
                "run", "CPU s"),
               [(c.combination.name, c.combination.condition,
                 g.condition_class(c.combination.condition)[0], c.verdict,
                 ", ".join(r.check for r in c.checks.failed()) or "—",
                 str(c.result.message or c.result.status), f"{c.seconds:.2f}")
                for c in study.combinations])]
    for c in study.combinations:
        rows = [(r[2], r[3], r[4], r[5], r[6], r[7]) for r in c.checks.table_rows()
                if r[1] != "—" or r[6] != "—"]
        blocks += [_Heading(3, f"{c.combination.name}: {c.verdict}"),
                   _Table(("check", "value", "unit", "required", "verdict", "source / note"),
                          rows)]
    return blocks


def _yield(study: DamStudy) -> list[_Block]:
    """The yield acceleration and its hand check."""
    y = study.yield_acceleration
    if y is None:
        return []
    h = y.hand or {}
    found = (f"k_y = {y.k_y:.6g} ({y.mode}), the design k_h = {y.design:g}: margin "
             f"k_y / k_h = {y.margin:.4g}." if y.k_y is not None else
             f"Equilibrium was not lost up to k_h = {y.top:g}: k_y > {y.top:g} (margin at "
             f"least {y.top / y.design:.3g}).")
    text = (f"{found} On the k_h segment the first CFE of the base slips at k_h = "
            f"{_num(y.first_slip, '.4g')} and the first opens at k_h = "
            f"{_num(y.first_opening, '.4g')}; at the last state the base is open over "
            f"{y.open_length:.3g} m with a crack-water force of {y.crack_water / 1e3:.4g} kN. "
            f"The run: {y.message} ({y.seconds:.2f} s of CPU).")
    if not h:  # a model file's dam: no hand check
        return [_Heading(2, "Yield acceleration (incremental analysis to failure on k_h)"),
                _Para(text + " No rigid-base hand check for a model file's dam (it needs the "
                      "parametric section's geometry)."),
                _Image(FIGURES["yield"], "yield acceleration",
                       "k_h against the crest's displacement after the usual loads, and the "
                       "open length of the base against k_h.")]
    rows = [("W, weight (kN)", _num(h["W"] / 1e3, ".1f")),
            ("ΣV₀, net downward load of the usual loads (kN)", _num(h["sum_V"] / 1e3, ".1f")),
            ("ΣH₀, net downstream load of the usual loads (kN)",
             _num(h["sum_H"] / 1e3, ".1f")),
            ("P, hydrodynamic force per unit k_h (kN), (7/12) γ_w h² on a vertical face",
             _num(h["P"] / 1e3, ".1f")),
            ("r = k_v / k_h", _num(h["r"], ".4g")), ("n_u, upstream batter", _num(h["n_u"], "g")),
            ("tan φ", _num(h["tan_phi"], ".4f")), ("c (kPa)", _num(h["c"] / 1e3, "g")),
            ("B (m)", _num(h["B"], "g")),
            ("hand k_y = (c B + tan φ ΣV₀ − ΣH₀) / (W + P + tan φ (r W − n_u P))",
             _num(h["k_y"], ".6g")),
            ("the run's k_y", _num(y.k_y, ".6g")),
            ("run / hand", _num(None if y.k_y is None else y.k_y / h["k_y"], ".6g"))]
    return [_Heading(2, "Yield acceleration (incremental analysis to failure on k_h)"),
            _Para(text),
            _Para("Hand check (stepcontact.study.dam.hand_yield): rigid base, the whole base "
                  "compressed, no crack water, sliding of the whole base, per metre of dam; "
                  "sliding c B + tan φ ΣV(k) = ΣH(k) with ΣV(k) = ΣV₀ − k r W + k n_u P and "
                  "ΣH(k) = ΣH₀ + k (W + P). It equals the run's k_y when the base stays "
                  "compressed up to it; a cracked base (crack water, a lost compressed area) "
                  "or a bond that breaks progressively gives a lower k_y."),
            _Table(("quantity", "value"), rows),
            _Image(FIGURES["yield"], "yield acceleration",
                   "k_h against the crest's displacement after the usual loads, and the open "
                   "length of the base against k_h (the design k_h, the first slip and "
                   "opening and k_y dotted).")]


def _events(study: DamStudy) -> list[_Block]:
    res = study.result
    reservoir = {g for g, (p, _, _) in enumerate(res.segments) if p == "reservoir"}
    events = [e for e in res.events if e.segment in reservoir]
    rows = [(_num(e.lam, ".4f"), _num(e.x, ".2f"),
             str(e.transition.name).lower().replace("_", " ")) for e in events[:60]]
    more = len(events) - len(rows)
    return [_Heading(2, "Events of the base while the level rises"),
            _Para("Each change of a CFE's state, in order (level h in m, x of the CFE from "
                  "the heel in m)" + (f"; {more} more not listed" if more > 0 else "") + "."),
            _Table(("h (m)", "x (m)", "transition"), rows)]


def _software(study: DamStudy) -> list[_Block]:
    from stepcontact.study.provenance import provenance

    p = provenance()
    rows = [("software", str(p["software"])), ("Python", str(p["python"])),
            ("NumPy", str(p["numpy"])), ("SciPy", str(p["scipy"])),
            ("report written", str(p["date"])),
            ("CPU time of the run", f"{study.seconds:.2f} s")]
    return [_Heading(2, "Software and run"), _Table(("item", "value"), rows)]


def _figures() -> list[_Block]:
    return [_Heading(2, "Figures"),
            _Image(FIGURES["base_stresses"], "base stresses",
                   "Normal stress along the base at the named levels (MPa, compression < 0): "
                   "the run's contact stresses (solid) and the rigid-base linear "
                   "distribution of the uncracked base (dashed)."),
            _Image(FIGURES["crack_length"], "crack length",
                   "Open length of the base against the reservoir level (m)."),
            _Image(FIGURES["level_displacement"], "level against crest displacement",
                   "Reservoir level against the crest's horizontal displacement (λ–u).")]


def report_blocks(study: DamStudy) -> tuple[str, list[_Block]]:
    """The report's title and blocks."""
    s = study.section
    title = f"Gravity-dam study: a {s.height:g} m section, static and pseudo-static"
    blocks: list[_Block] = [
        _Para("Source: stepcontact.study.dam_study (docs/dam-study.md). The dam on its "
              "foundation under self-weight, the reservoir at the normal level (usual case) "
              "and the flood level (unusual case), and the level raised until the dam fails; "
              "the load combinations with the guideline's verdicts, and the seismic "
              "coefficient raised until the dam fails (the yield acceleration). "
              "Units SI: m, N and N·m per metre of dam, Pa; seismic coefficients in g."),
        *_software(study), *_inputs(s),
        _Image(FIGURES["section"], "the section and its loads",
               "The section with its loads at the normal level and the uplift head along "
               "the base."),
        *_assumptions(s), *_verdicts(study), *_results(study), *_yield(study),
        *quake_blocks(study.earthquake), *_figures(),
        *_events(study)]
    return title, blocks


def write_report(study: DamStudy, out_dir: str | os.PathLike[str], *,
                 dpi: float = DPI) -> dict[str, Path]:
    """Write the report into ``out_dir``: ``report.md``, ``report.html``, ``summary.json``,
    the figures of :data:`FIGURES` and the run's result file ``result.nc`` (for
    ``stepcontact info``, ``plot`` and ``export``), all atomically; their paths by key."""
    out = Path(out_dir)
    plots = [("section", plot_section), ("base_stresses", plot_base_stresses),
             ("crack_length", plot_crack_length),
             ("level_displacement", plot_level_displacement)]
    if study.yield_acceleration is not None:
        plots.append(("yield", plot_yield))
    paths = {key: out / FIGURES[key] for key, _ in plots}
    for key, plot in plots:
        plot(study, paths[key], dpi=dpi)
    if study.earthquake is not None:  # the earthquake record (stepcontact.study.dam_quake)
        paths["quake"] = out / QUAKE_FIGURES["quake"]
        plot_quake(study.earthquake, paths["quake"], dpi=dpi,
                   base_length=study.section.base_length)
    title, blocks = report_blocks(study)
    paths["markdown"], paths["html"] = out / "report.md", out / "report.html"
    paths["summary"] = out / "summary.json"
    write_text(paths["markdown"], _to_markdown(title, blocks))
    write_text(paths["html"], _to_html(title, blocks))
    write_text(paths["summary"], json.dumps(summary(study), indent=2, ensure_ascii=False))
    paths["result"] = out / "result.nc"
    study.result.save(paths["result"])
    return paths


__all__ = ["COLORS", "FIELDS", "FIGURES", "plot_base_stresses", "plot_crack_length",
           "plot_level_displacement", "plot_section", "plot_yield", "report_blocks",
           "write_report", "yield_path"]
