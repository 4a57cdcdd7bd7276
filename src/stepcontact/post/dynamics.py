"""Figures of a dynamic result (:func:`~stepcontact.solve_dynamic`): the time histories of
chosen nodes or DOFs with the contact events marked (:func:`plot_time_history`) and the
energy ledger (:func:`plot_energy`).  Units: m, m/s, m/s², J, s (rad … for rotations).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from stepcontact.post.common import (
    DPI,
    TRANSITION_MARKERS,
    _legend_below,
    _length_scale,
    _transition_handles,
    figure_path,
    new_figure,
    save_figure,
)
from stepcontact.post.mesh import _most_moving

if TYPE_CHECKING:
    from matplotlib.figure import Figure

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
    "MAX_HISTORY_NODES",
    "plot_energy",
    "plot_time_history",
]
