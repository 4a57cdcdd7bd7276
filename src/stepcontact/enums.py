"""Enumerations of contact states, event transitions and run status (never magic numbers)."""

from __future__ import annotations

from enum import IntEnum, StrEnum

import numpy as np


class ContactState(IntEnum):
    """State of one contact finite element (CFE), method.md §2.

    The integer values are stored in result files; names are what users see.
    """

    OPEN = 0  #: S3c: separated, u_n < 0, N = 0, Q = 0
    STICK = 1  #: S1c: contact with adhesion, u_n = 0, N <= 0, |Q| <= -f N, no slip
    SLIP_POS = 2  #: S2c: slipping, Q = -f N, slip increment > 0
    SLIP_NEG = 3  #: S2c: slipping, Q = +f N, slip increment < 0
    BONDED = 4  #: joint with initial strength, bond intact (eq. (12)): tension and shear
    CLOSED = 5  #: frictionless contact: u_n = 0, N <= 0, Q = 0 (no stick/slip distinction)

    @property
    def closed(self) -> bool:
        return self in (ContactState.STICK, ContactState.SLIP_POS, ContactState.SLIP_NEG,
                        ContactState.CLOSED, ContactState.BONDED)

    @property
    def slipping(self) -> bool:
        return self in (ContactState.SLIP_POS, ContactState.SLIP_NEG)

    @property
    def sigma(self) -> int:
        """Slip direction σ: +1, -1, or 0 when not slipping."""
        return {ContactState.SLIP_POS: 1, ContactState.SLIP_NEG: -1}.get(self, 0)

    @property
    def label(self) -> str:
        return {0: "open", 1: "stick", 2: "slip+", 3: "slip-", 4: "bonded", 5: "closed"}[int(self)]


#: the largest number of facets k of a faceted Coulomb cone (3D, :mod:`stepcontact.contact.faceted`)
MAX_FACETS = 128
#: state code of a CFE slipping on facet i of a faceted cone: ``FACET_SLIP + i`` (Q on the facet,
#: the slip along its outward normal)
FACET_SLIP = 16
#: state code of a CFE slipping at vertex i of a faceted cone, between facets i − 1 and i (Q at
#: the vertex, the slip direction inside the vertex's normal cone): ``VERTEX_SLIP + i``
VERTEX_SLIP = FACET_SLIP + MAX_FACETS


def slipping(codes) -> np.ndarray:
    """Which state codes are slip states: slip± in 2D, a facet or a vertex of a faceted cone."""
    c = np.asarray(codes)
    # (plain ints: an enum member's lookup costs more than the comparison on the event
    # loop's small arrays)
    return (c == _SLIP_POS) | (c == _SLIP_NEG) | (c >= FACET_SLIP)


_SLIP_POS, _SLIP_NEG = int(ContactState.SLIP_POS), int(ContactState.SLIP_NEG)


def closed(codes) -> np.ndarray:
    """Which state codes are closed (in contact): every state but OPEN."""
    return np.asarray(codes) != ContactState.OPEN


def state_label(code) -> str:
    """What users see for a state code: the :class:`ContactState` label, ``slip (facet i)`` or
    ``slip (vertex i)`` on a faceted cone."""
    code = int(code)
    if code >= VERTEX_SLIP:
        return f"slip (vertex {code - VERTEX_SLIP})"
    if code >= FACET_SLIP:
        return f"slip (facet {code - FACET_SLIP})"
    return ContactState(code).label


class Transition(StrEnum):
    """What happened to a CFE at an event."""

    CLOSED = "closed"  #: open -> contact
    OPENED = "opened"  #: contact -> open
    SLIP_POS = "slip+"  #: stick (or slip-) -> slip in + direction
    SLIP_NEG = "slip-"  #: stick (or slip+) -> slip in - direction
    STUCK = "stuck"  #: slip -> stick
    BROKEN = "broken"  #: bond broken (eq. (12)): the CFE becomes a Coulomb one
    SLIP = "slip"  #: stick -> slip on a faceted cone (3D: a facet or a vertex)
    TURNED = "turned"  #: slip on a faceted cone moved to another facet or vertex

    @staticmethod
    def between(old: ContactState | int, new: ContactState | int) -> Transition:
        """The transition that takes a CFE from state code ``old`` to ``new`` (``old != new``;
        faceted-cone slip codes ≥ :data:`FACET_SLIP` included)."""
        if old == ContactState.BONDED:
            return Transition.BROKEN
        if int(new) >= FACET_SLIP:
            return Transition.TURNED if int(old) >= FACET_SLIP else Transition.SLIP
        if new == ContactState.OPEN:
            return Transition.OPENED
        if old == ContactState.OPEN and new in (ContactState.STICK, ContactState.CLOSED):
            return Transition.CLOSED
        if new == ContactState.SLIP_POS:
            return Transition.SLIP_POS
        if new == ContactState.SLIP_NEG:
            return Transition.SLIP_NEG
        return Transition.STUCK


class Status(StrEnum):
    """How a run ended."""

    COMPLETED = "completed"  #: the whole load program was applied
    EQUILIBRIUM_LOST = "equilibrium_lost"  #: the working scheme became a mechanism
    RATE_PROBLEM = "rate_problem"  #: no (or no unique) consistent scheme: large friction
    CYCLING = "cycling"  #: the working schemes cycle at one load factor
    MAX_EVENTS = "max_events"  #: the event budget was exhausted
    VIOLATION = "violation"  #: the contact conditions could not be met to the tolerance
    INCOMPLETE = "incomplete"  #: a partial result written while the run was going on


class SlipTreatment(StrEnum):
    """How slip is written into the working scheme (method.md §3)."""

    EXACT = "exact"  #: Q = σ f N in the scheme; every event exact
    ARTICLE = "article"  #: the article's ε_p step limit with compensating forces, eqs. (4)-(6)
