"""Load patterns that are probably not what the user meant: empty or zero.

A pattern without loads, or whose loads add up to nothing (zero forces, zero pressures, gravity
on bodies without density, prescribed displacements of zero), is legal but a segment that
applies it changes nothing: almost always a mistake (a missing load, a wrong node set, a density
left out).  :func:`zero_patterns` finds them from the assembled load vectors, so that
``stepcontact validate`` and ``stepcontact run`` can warn.

Example
-------
>>> import stepcontact as sc
>>> from stepcontact.fem.loadcheck import zero_patterns
>>> blk = sc.rectangle("blk", (0, 0), (1, 1), 1, 1, sc.Material(1e9, 0.2))
>>> m = sc.Model(bodies=[blk]).add(sc.LoadPattern("push", []), sc.Segment("push", 1.0))
>>> [name for name, _ in zero_patterns(m)]
['push']
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from stepcontact.fem.assembly import LoadVectors, dof_map, load_vectors
from stepcontact.fem.level import is_level_pattern
from stepcontact.model import Model


def _users(model: Model, name: str) -> list[int]:
    """Indices of the program segments that move pattern ``name``."""
    out = []
    for i, seg in enumerate(model.program):
        rates = dict(seg.rates) if seg.rates is not None else {seg.pattern: 1.0}
        if rates.get(name, 0.0) != 0.0:
            out.append(i)
    return out


def zero_patterns(model: Model,
                  loads: Mapping[str, LoadVectors] | None = None) -> list[tuple[str, str]]:
    """(pattern name, warning) for every load pattern that is empty or zero.

    ``loads``: the load vectors of the assembled system (``System.loads``), else computed
    here (no stiffness is assembled)."""
    if loads is None:
        dofs = dof_map(model)
        loads = {p.name: load_vectors(model, dofs, p.name) for p in model.patterns}
    out = []
    for pat in model.patterns:
        users = _users(model, pat.name)
        if users:
            seg = "segment" if len(users) == 1 else "segments"
            which = ", ".join(f"program[{i}]" for i in users)
            effect = (f"the {seg} that {'applies' if len(users) == 1 else 'apply'} it "
                      f"({which}) {'changes' if len(users) == 1 else 'change'} nothing")
        else:
            effect = "and no segment applies it"
        if not pat.loads:
            out.append((pat.name, f"load pattern '{pat.name}' has no loads: {effect}"))
            continue
        lv = loads.get(pat.name)
        if is_level_pattern(pat):  # its factor is a water level: its own vector holds only
            continue  # its other loads per metre of water (the water: virtual patterns)
        if lv is not None and not np.any(lv.f) and not np.any(lv.u):
            out.append((pat.name, f"load pattern '{pat.name}' is zero: its {len(pat.loads)} "
                        "load(s) add up to no force and no displacement (zero values, "
                        f"or gravity on bodies without density): {effect}"))
    return out


__all__ = ["zero_patterns"]
