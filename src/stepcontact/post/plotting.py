"""Plots of a result: contact stresses, load path, deformed shape, load–displacement curve,
event timeline, joint safety, time histories and the energy ledger.

This module gathers the figures of :mod:`stepcontact.post`, one module per family:

* :mod:`~stepcontact.post.common` — figure creation and saving, colours, units, labels;
* :mod:`~stepcontact.post.mesh` — the mesh of a result as the figures read it;
* :mod:`~stepcontact.post.interfaces` — :func:`plot_interfaces`;
* :mod:`~stepcontact.post.paths` — :func:`plot_load_path`, :func:`plot_load_displacement`,
  :func:`plot_event_timeline`;
* :mod:`~stepcontact.post.deformed` — :func:`plot_deformed`;
* :mod:`~stepcontact.post.safety` — :func:`plot_safety`;
* :mod:`~stepcontact.post.dynamics` — :func:`plot_time_history`, :func:`plot_energy`.

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

# besides __all__, the limits and labels the figures' docstrings name (tests import them from
# here): re-exported, marked "noqa: F401"
from stepcontact.post.common import (
    DPI,
    MAX_PIXELS,  # noqa: F401
    MAX_SIDE,  # noqa: F401
    NOT_BUILT,  # noqa: F401
    STATE_COLORS,
    TRANSITION_MARKERS,
    _lam_text,  # noqa: F401
    figure_path,
    new_figure,
    save_figure,
)
from stepcontact.post.deformed import plot_deformed
from stepcontact.post.dynamics import MAX_HISTORY_NODES, plot_energy, plot_time_history  # noqa: F401
from stepcontact.post.interface_map import plot_interface_map
from stepcontact.post.interfaces import (
    CORNER_NOTE,  # noqa: F401
    CORNER_RATIO,  # noqa: F401
    MAX_DEFAULT_SNAPSHOTS,  # noqa: F401
    plot_interfaces,
)
from stepcontact.post.paths import plot_event_timeline, plot_load_displacement, plot_load_path
from stepcontact.post.safety import MAX_SAFETY_PANELS, plot_safety  # noqa: F401

__all__ = [
    "DPI",
    "STATE_COLORS",
    "TRANSITION_MARKERS",
    "figure_path",
    "new_figure",
    "save_figure",
    "plot_deformed",
    "plot_event_timeline",
    "plot_interface_map",
    "plot_interfaces",
    "plot_load_displacement",
    "plot_load_path",
    "plot_safety",
    "plot_time_history",
    "plot_energy",
]
