"""Event logging of the drivers (static and dynamic): one :class:`~stepcontact.results.Event`
per CFE that changes state, with its forces there, and the first slip, opening and closing of
a segment (a dynamic interval) for its :class:`~stepcontact.results.Multipliers`.

The two drivers differ only in what they pass: the static one its event point (``step``), the
index of the state recorded there, the segment, its pattern and the load factor λ; the dynamic
one the step number, the index of the next state, segment 0, pattern ``"dynamic"``, the time
of the event (s) and, at an impact, the CFE's impulses.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from stepcontact.contact.layout import ContactLayout
from stepcontact.enums import Transition
from stepcontact.results.events import Event

#: the multiplier a transition is the first of (a bond that breaks is none: the breaking
#: CFE's new state is, :func:`~stepcontact.solver.bonds.break_bonds`)
FIRST_OF = {Transition.OPENED: "first_opening", Transition.CLOSED: "first_closing",
            Transition.SLIP_POS: "first_slip", Transition.SLIP_NEG: "first_slip",
            Transition.SLIP: "first_slip"}


class EventLog:
    """Appends the events of a run to its recorder's list (``rec.events``).

    ``cfe``: the CFEs (names, positions); ``layout``: the layout of the contact forces s."""

    def __init__(self, rec, cfe, layout: ContactLayout):
        self.rec, self.cfe, self.layout = rec, cfe, layout

    def event(self, k: int, was, now, s: np.ndarray, *, step: int, state: int, segment: int,
              pattern: str, lam: float, impulse: tuple[float, float] | None = None,
              first: dict | None = None) -> Event:
        """Log CFE k's transition ``was`` → ``now`` at ``lam`` (a load factor, or a time in
        s) with the forces ``s`` (N = −p, Q) and an impact's (normal, tangential) impulse
        (N·s); ``first``: the multipliers {first_slip, first_opening, first_closing, …} whose
        entry for this transition (:data:`FIRST_OF`) is set to ``lam`` if it is None (None:
        none is set)."""
        lay = self.layout
        tr = _transition(int(was), int(now))
        pn, qt = (0.0, 0.0) if impulse is None else impulse
        interface, local, position, x, y, z = self._where()[k]
        ev = Event(
            step=step, state=state, segment=segment, pattern=pattern, lam=lam, cfe=int(k),
            interface=interface, local=local, position=position, x=x, y=y,
            transition=tr, N=float(-lay.normal(s)[k]),
            Q=float(lay.tangential(s)[k]) if lay.n_t == 1 else lay.tangential(s)[k].copy(),
            impulse_n=pn, impulse_t=qt, z=z)
        self.rec.events.append(ev)
        if first is not None:
            key = FIRST_OF.get(tr)
            if key and first[key] is None:
                first[key] = lam
        return ev

    def _where(self) -> list[tuple]:
        """Per CFE (interface name, index along it, arc length (m), x, y, z (m; z None in
        2D)), as Python values, formed once (the CFEs do not change along a run)."""
        got = getattr(self, "_where_of", None)
        if got is None or got[0] is not self.cfe:
            cfe = self.cfe
            m = len(cfe.local)
            names = ([cfe.names[i] for i in np.asarray(cfe.interface).tolist()] if cfe.names
                     else [""] * m)
            x = np.asarray(cfe.x, float)
            xy = x[:, :2].tolist() if x.size else [[0.0, 0.0]] * m
            zs = (x[:, 2].tolist() if x.ndim == 2 and x.shape[1] == 3 and x.size
                  else [None] * m)
            got = self._where_of = (cfe, [
                (nm, int(loc), float(pos), float(p[0]), float(p[1]), z)
                for nm, loc, pos, p, z in
                zip(names, np.asarray(cfe.local).tolist(), np.asarray(cfe.s, float).tolist(), xy,
                    zs, strict=True)])
        return got[1]

    def changes(self, old: np.ndarray, new: np.ndarray, s: np.ndarray, **where) -> None:
        """Log every CFE whose state differs between ``old`` and ``new`` (m,), in the order of
        the CFEs, with the forces ``s``; ``where``: the keywords of :meth:`event` but the
        impulse."""
        for k in np.flatnonzero(old != new).tolist():
            self.event(k, old[k], new[k], s, **where)


@lru_cache(maxsize=4096)
def _transition(was: int, now: int) -> Transition:
    """:meth:`Transition.between` of two state codes, looked up once per pair."""
    return Transition.between(was, now)


__all__ = ["FIRST_OF", "EventLog"]
