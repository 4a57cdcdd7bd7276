"""Joints with initial strength (eq. (12)) in the drivers: which bonds break at a point, and
the break itself — for the static and the dynamic driver alike.

A bonded CFE carries tension and shear inside its strength surface, whose four facets are
event functions of the law
(:meth:`~stepcontact.contact.bond.BondedJointLaw.bond_values`).  A bond
breaks where the engine's path reaches a facet (the event fired) or where it sits on a facet
and the rates of the scheme decided there drive it beyond (:func:`breaking`).  It then takes
its Coulomb state (open in tension, else stuck or slipping) and drops the part of its forces
that state cannot carry (:func:`break_bonds`).  What the drivers do with the dropped forces g
differs and stays theirs: the static one keeps them as a load that its release takes to zero
at fixed λ, the dynamic one releases them in accelerations at fixed t (or, with compliant
layers, lets the layer's force drop) and books the energy a compliant layer loses.
"""

from __future__ import annotations

import numpy as np

from stepcontact.contact.laws import BONDED, OPEN
from stepcontact.enums import slipping
from stepcontact.solver.eventlog import EventLog


def breaking(eng, law, ds: np.ndarray, fired: np.ndarray | None = None) -> np.ndarray:
    """(m,) bool: the bonds of the engine ``eng``'s CFEs that break at its current point —
    those on a facet of their strength surface (within the engine's force tolerance) that
    the rates ``ds`` of the scheme decided drive beyond it (rate below 1e3 rtol max|ds|,
    :meth:`~stepcontact.contact.bond.BondedJointLaw.breaking`), and the bonded CFEs among
    ``fired`` (the events the engine met on its way here), if given."""
    tf, _ = eng.tolerances()
    rf = 1e3 * eng.rtol * max(float(np.abs(ds).max(initial=0)), 1e-300)
    lay = eng.layout
    brk = law.breaking(eng.states, *lay.split(eng.s), *lay.split(ds), tf, rf)
    if fired is None:
        return brk
    return (fired & (eng.states == BONDED)) | brk


def break_bonds(eng, law, brk: np.ndarray, events: EventLog, first: dict,
                **where) -> tuple[np.ndarray, np.ndarray]:
    """Break the bonds of the CFEs ``brk`` (m,) at the engine ``eng``'s current point: each
    takes its Coulomb state (:meth:`~stepcontact.contact.bond.BondedJointLaw.broken_state`: open
    where p ≤ the force tolerance, else stuck or slipping) and drops the forces g that state
    cannot carry (:meth:`~stepcontact.contact.bond.BondedJointLaw.released`): the engine's forces
    become s − g, its states the new ones.  A closed Coulomb CFE in ``brk`` that lost its
    residual cohesion at p = 0 opens the same way.

    Logs one event per CFE (``broken``; ``opened`` for a lost cohesion) in the order of the
    CFEs with the forces before the break (``events``, ``where``: the keywords of
    :meth:`EventLog.changes <stepcontact.solver.eventlog.EventLog.changes>`), and sets the
    multipliers ``first`` (first_opening: a CFE that breaks open; first_slip: one that breaks
    slipping) to ``where["lam"]`` where they are None.  Returns (g (n,), N, the forces before
    the break (n,), N)."""
    lay = eng.layout
    tf, _ = eng.tolerances()
    s_before = eng.s.copy()
    Q, p = lay.split(s_before)
    old = eng.states.copy()
    new = old.copy()
    new[brk] = law.broken_state(Q, p, tf)[brk]
    events.changes(old, new, s_before, first=first, **where)
    lam = where["lam"]
    for key, hit in (("first_opening", new[brk] == OPEN),
                     ("first_slip", slipping(new[brk]))):
        if first[key] is None and hit.any():
            first[key] = lam
    dQ, dp = law.released(new, Q, p)
    g = lay.join(np.where(brk.reshape((-1,) + (1,) * (np.ndim(dQ) - 1)), dQ, 0.0),
                 np.where(brk, dp, 0.0))
    eng.s = s_before - g
    eng.states = new
    return g, s_before


__all__ = ["break_bonds", "breaking"]
