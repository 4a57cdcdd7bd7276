"""Enumerations of contact states, event transitions and run status (never magic numbers)."""

from __future__ import annotations

from enum import IntEnum, StrEnum


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


class Transition(StrEnum):
    """What happened to a CFE at an event."""

    CLOSED = "closed"  #: open -> contact
    OPENED = "opened"  #: contact -> open
    SLIP_POS = "slip+"  #: stick (or slip-) -> slip in + direction
    SLIP_NEG = "slip-"  #: stick (or slip+) -> slip in - direction
    STUCK = "stuck"  #: slip -> stick
    BROKEN = "broken"  #: bond broken (eq. (12)): the CFE becomes a Coulomb one

    @staticmethod
    def between(old: ContactState, new: ContactState) -> Transition:
        """The transition that takes a CFE from ``old`` to ``new`` (``old != new``)."""
        if old == ContactState.BONDED:
            return Transition.BROKEN
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
