"""Building a run's result from its :class:`~stepcontact.results.recorder.Recorder`: one builder
for the static and the dynamic drivers (:mod:`stepcontact.solver.static`,
:mod:`stepcontact.solver.dynamic`), so that both results keep the same things — the CFEs'
geometry with their S+ and S− end nodes and weights, the strengths of bonded joints
(eq. (12)), the contact unknowns of every state with their tangential axis, the events and
multipliers, the construction stages.

The recorded contact unknowns s = [Q; p] (N, p = −N ≥ 0 in compression) and
w = [u_τ; u_n] (m) of every state (:mod:`stepcontact.contact.layout`) become the result's
``N``, ``un`` (n_states, m) and ``Q``, ``ut`` — (n_states, m) in 2D, (n_states, m, n_t) with
n_t = 2 tangential components in 3D (``res.Q_t``, ``res.ut_t`` have that axis always).

Plain functions of plain data: no solver is imported here.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from stepcontact.contact.layout import ContactLayout
from stepcontact.enums import Status
from stepcontact.results.recorder import Recorder
from stepcontact.results.result import StaticResult

#: the CFE arrays every result keeps (attributes of
#: :class:`~stepcontact.contact.geometry.ContactElements`), in their order in the result file
CFE_KEYS = ("interface", "local", "s", "x", "normal", "area", "friction", "gap", "kn", "kt",
            "tangent", "plus_nodes", "plus_w", "minus_nodes", "minus_w")


def by_state(layout: ContactLayout, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The tangential and normal components of recorded contact unknowns X (n_states, n), as
    views with the state axis first: (n_states, m) each in 2D (X[:, :m], X[:, m:]); the
    tangential ones (n_states, m, n_t) in 3D."""
    t, n = layout.split(X.T)
    return np.moveaxis(t, -1, 0), n.T


def cfe_arrays(cfe, *, bond: np.ndarray | None = None,
               cohesion_lost: np.ndarray | None = None, damping: bool = False) -> dict:
    """The CFE arrays of a result (:data:`CFE_KEYS`; those ``cfe`` has).

    ``bond``: the strengths of the bonded joints of the run (eq. (12); the columns of
    ``ContactElements.bond``), kept when the run has any; ``cohesion_lost``: the state from
    which each CFE's residual cohesion is lost (−1: kept), kept when given; ``damping``: keep
    the contact layers' damping c_n (N·s/m; a dynamic run).  With two tangential components
    (3D) the number k of facets of the faceted Coulomb cone is kept too (``facets``, an int).
    """
    keys = CFE_KEYS if not damping else (*CFE_KEYS[:_AFTER_KT], "cn", *CFE_KEYS[_AFTER_KT:])
    out = {k: getattr(cfe, k) for k in keys if getattr(cfe, k, None) is not None}
    if getattr(cfe, "n_t", 1) > 1:  # a faceted Coulomb cone (3D): its number of facets k
        out["facets"] = int(cfe.facets)
    if bond is not None:
        out["bond"] = bond
    if cohesion_lost is not None:
        out["cohesion_lost"] = cohesion_lost
    return out


#: where a dynamic run's damping c_n goes among :data:`CFE_KEYS` (after kt)
_AFTER_KT = CFE_KEYS.index("kt") + 1


def stage_fields(stage: np.ndarray, names, cfes, bodies, **more) -> dict:
    """The result's arrays of a run in construction stages: the stage of every state
    (n_states,), the stages' names, the CFEs active at each stage (n_stages, m) and the
    bodies built by each stage (``more``: the dynamic intervals of a static run)."""
    return {"stage": np.asarray(stage, np.int64), "stage_names": names,
            "stage_cfes": np.asarray(cfes, bool), "stage_bodies": bodies, **more}


def build_result(rec: Recorder, *, cls: type[StaticResult] = StaticResult, cfe,
                 cfe_data: dict, pattern_names, segments, status: Status, message: str,
                 counters: dict, geometry: dict, crack: bool = False,
                 **extra: Any) -> StaticResult:
    """The result (``cls``: :class:`StaticResult` or
    :class:`~stepcontact.results.result.DynamicResult`) of the states, events and logs in
    ``rec``.

    Parameters
    ----------
    rec : Recorder
        The run's recorder (its layout gives the tangential axis).
    cfe : ContactElements
        The CFEs (their interface names).
    cfe_data : dict
        The CFE arrays (:func:`cfe_arrays`).
    pattern_names, segments, status, message, counters, geometry
        As the result's attributes.
    crack : bool
        The model has water in opened joints: keep the recorded water forces (N) and
        pressures (Pa) of every state.
    extra
        The result's other attributes (reaction labels, load resultants, stage arrays
        (:func:`stage_fields`), a dynamic result's fields in time and energy ledger …).
    """
    r = rec.arrays()
    (Q, p), (ut, un) = by_state(rec.layout, r["s"]), by_state(rec.layout, r["w"])
    return cls(
        pattern_names=tuple(pattern_names), segments=list(segments), cfe=cfe_data,
        interface_names=cfe.names, lam=r["lam"], segment=r["segment"], factors=r["factors"],
        kind=r["kind"], N=-p, Q=Q, un=un, ut=ut, state=r["state"], residual=r["residual"],
        violation=r["violation"], events=list(rec.events), multipliers=list(rec.multipliers),
        status=status, message=message, fields=dict(rec.fields), stresses=dict(rec.stresses),
        counters=counters, geometry=geometry, reactions=r["reactions"],
        nonunique=list(rec.nonunique),
        water=r["water"] if crack else None, crack_pressure=r["pressure"] if crack else None,
        **extra,
    )


__all__ = ["CFE_KEYS", "build_result", "by_state", "cfe_arrays", "stage_fields"]
