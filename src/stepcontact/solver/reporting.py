"""What both drivers put into their results, one copy for the static
(:mod:`stepcontact.solver.static`) and the dynamic (:mod:`stepcontact.solver.dynamic`) driver:
the limit of a reported state's violation of the contact conditions (:data:`VIOLATION_LIMIT`)
and the part of the model a result keeps to draw and export its fields
(:func:`result_geometry`)."""

from __future__ import annotations

import numpy as np

from stepcontact.fem.assembly import System
from stepcontact.model import Model

#: a reported state whose relative violation of the contact conditions exceeds this ends the run
#: with status VIOLATION (the conditions could not be met): never "completed" with them broken.
#: The article's slip treatment is approximate by design: its limit is ε_p instead.
VIOLATION_LIMIT = 1e-6


def _named_node_sets(model: Model) -> dict[str, np.ndarray]:
    """The named node sets the model's supports, ties, springs, interfaces and loads use (the
    first of a name wins), for results per node, as plain arrays: ``node_set_names`` (k,),
    ``node_set_offsets`` (k + 1,) and ``node_set_nodes`` (global node ids of set j at
    offsets[j]:offsets[j + 1])."""
    from stepcontact.model import NodeSet

    sets = [s.nodes for s in model.supports]
    sets += [ns for t in model.ties for ns in (t.a, t.b)]
    sets += [ns for sp in model.springs for ns in (sp.a, sp.b) if ns is not None]
    sets += [ns for i in model.interfaces for ns in (i.plus, i.minus)
             if isinstance(ns, NodeSet)]  # (not a rigid obstacle)
    sets += [ld.nodes for p in model.patterns for ld in p.loads if hasattr(ld, "nodes")]
    named: dict[str, np.ndarray] = {}
    for ns in sets:
        if ns.name and ns.name not in named:
            named[ns.name] = model.global_nodes(ns)
    sizes = [len(v) for v in named.values()]
    return {
        "node_set_names": np.array(list(named), dtype=str) if named else np.zeros(0, "<U1"),
        "node_set_offsets": np.r_[0, np.cumsum(sizes, dtype=np.int64)].astype(np.int64),
        "node_set_nodes": (np.concatenate(list(named.values())).astype(np.int64) if named
                           else np.zeros(0, np.int64)),
    }


def result_geometry(system: System) -> dict:
    """What a result keeps of the model to draw and export its fields: points, DOF map,
    bodies and named node sets (a discrete model: its DOF names)."""
    model = system.model
    if system.discrete is not None:
        return {"dof_names": np.array(system.discrete.dof_names, dtype=str)}
    return {
        "points": model.points,
        "dof_of": system.dofs.of,
        "bodies": [
            {"name": b.name, "kind": b.kind, "element": getattr(b, "element", "frame2"),
             "cells": b.cells + model.node_offsets[b.name],
             "offset": int(model.node_offsets[b.name]), "n_nodes": int(b.n_nodes)}
            for b in model.bodies
        ],
        **_named_node_sets(model),
    }


__all__ = ["VIOLATION_LIMIT", "result_geometry"]
