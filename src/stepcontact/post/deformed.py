"""The deformed shape (:func:`plot_deformed`): the bodies' cells and outlines at their
displaced nodes over the undeformed outlines, the CFEs coloured by their state, the cells
optionally coloured by a stress component, each body named at its centroid, and the loads
of the patterns at the state as arrows (nodal forces, a body's self-weight as one arrow at
its centre of mass, or a pattern's resultant on its line of action).
"""

from __future__ import annotations

import math
import os
from typing import TYPE_CHECKING

import numpy as np

from stepcontact.post.common import (
    DPI,
    _active_cfes,
    _at_text,
    _force_scale,
    _lam_text,
    _legend_below,
    _stage_of,
    _stage_text,
    _state_handles,
    _state_index,
    _stress_scale,
    figure_path,
    new_figure,
    save_figure,
    state_colors,
)
from stepcontact.post.mesh import (
    _boundary_edges,
    _cell_edges,
    _extent,
    _field,
    _geometry,
    _node_u,
    _ring,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from stepcontact.results.result import StaticResult

def _nice_floor(x: float) -> float:
    """The largest 1, 2 or 5 × 10^k not above ``x`` (> 0)."""
    k = np.floor(np.log10(x))
    mant = x / 10**k
    return float(max(c for c in (1.0, 2.0, 5.0, 10.0) if c <= mant * (1 + 1e-12)) * 10**k)


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


def _drawn_box(points: np.ndarray, xy: np.ndarray, arrows: list[dict]
               ) -> tuple[np.ndarray, np.ndarray]:
    """(lower left, upper right) corners, m, of what :func:`plot_deformed` draws: the
    undeformed nodes ``points``, the displaced ones ``xy`` and the load arrows (tips and
    tails)."""
    tips = [xy] + [np.concatenate([
        a["at"], a["at"] - a["vec"],
        np.reshape([c + v for (_, c, _), v in zip(a["body"], a["body_vec"], strict=True)],
                   (-1, 2))]) for a in arrows]
    lo = np.minimum(points.min(0), np.min([v.min(0) for v in tips], axis=0))
    hi = np.maximum(points.max(0), np.max([v.max(0) for v in tips], axis=0))
    return lo, hi


def _draw_cfe_states(ax, res: StaticResult, i: int, act: np.ndarray, points: np.ndarray,
                     un: np.ndarray, scale: float) -> list:
    """The CFEs made at state ``i`` (``act``) as dots at their displaced positions
    (displacements ``un`` magnified by ``scale``), coloured by their state; the legend
    handles of the states shown."""
    if not (res.m and act.any()):
        return []
    codes = np.asarray(res.state)[i][act]
    xc = np.asarray(res.cfe["x"], dtype=float).reshape(res.m, 2)[act]
    pc = xc + scale * _cfe_displacement(points, un, xc)
    ax.scatter(pc[:, 0], pc[:, 1], s=22, c=list(state_colors(codes)),
               edgecolors="0.15", linewidths=0.5, zorder=4)
    return _state_handles(codes)


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

    lo, hi = _drawn_box(points[shown], xy[shown], arrows)
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
    handles = _draw_cfe_states(ax, res, i, _active_cfes(res, stage), points, un, scale)
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


__all__ = [
    "plot_deformed",
]
