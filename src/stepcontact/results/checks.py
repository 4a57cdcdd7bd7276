"""Results that are probably not what the user meant.

:func:`displacement_warnings`: a displacement larger than the model itself.  The analysis is
linear (small displacements), so such an answer is meaningless; it almost always means wrong
units — typically Young's modulus given in GPa or MPa (``E = 30``) in a model whose loads are
in N and lengths in m.  ``stepcontact run`` prints it after the run.

Example
-------
>>> from stepcontact.results.checks import displacement_warnings
>>> displacement_warnings(res)          # doctest: +SKIP
["the largest displacement, 8.3e+03 m (node 12 at (1, 1), state 13), is larger than ..."]
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from stepcontact.results.result import StaticResult

#: a displacement larger than this multiple of the model's size is warned about
LARGE_DISPLACEMENT = 1.0


def displacement_warnings(res: StaticResult) -> list[str]:
    """A warning when a stored displacement field moves a node by more than the size of the
    model (the largest extent of its nodes); empty otherwise or without geometry/fields."""
    geo = res.geometry or {}
    if "points" not in geo or "dof_of" not in geo or not res.fields:
        return []
    pts = np.asarray(geo["points"], dtype=float)
    of = np.asarray(geo["dof_of"])[:, :2]
    if not len(pts):
        return []
    size = float(np.ptp(pts, axis=0).max())
    if not size > 0:
        return []
    worst = (0.0, -1, -1)  # (|u|, node, state)
    for state, u in res.fields.items():
        u = np.asarray(u, dtype=float)
        uv = np.where(of >= 0, u[np.maximum(of, 0)], 0.0)
        norm = np.hypot(uv[:, 0], uv[:, 1])
        if not np.all(np.isfinite(norm)):
            k = int(np.flatnonzero(~np.isfinite(norm))[0])
            return [f"the displacement of node {k} is not finite at state {state}: the answer "
                    "is meaningless; check the units and the stiffness of the model"]
        k = int(np.argmax(norm)) if norm.size else -1
        if k >= 0 and norm[k] > worst[0]:
            worst = (float(norm[k]), k, int(state))
    umax, k, state = worst
    if umax <= LARGE_DISPLACEMENT * size:
        return []
    x, y = pts[k]
    return [f"the largest displacement, {umax:.3g} m (node {k} at ({x:.6g}, {y:.6g}), state "
            f"{state}), is larger than the model itself ({size:.3g} m across): a small-"
            "displacement analysis means nothing there; check the units (E in Pa, e.g. "
            "30e9 for 30 GPa; loads in N; lengths in m)"]


__all__ = ["LARGE_DISPLACEMENT", "displacement_warnings"]
