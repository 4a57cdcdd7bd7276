"""What happened along a run, event by event: :class:`Event` (one CFE changing state) and
:class:`Multipliers` (the stability multipliers of a load segment) — plain records of the
result types (:mod:`stepcontact.results.result`) and of the result file
(:mod:`stepcontact.results.file`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from stepcontact.enums import Transition


@dataclass(frozen=True)
class Event:
    """One CFE changing state.

    Attributes
    ----------
    step : int
        Number of the main step (event point) in the run, from 1.
    state : int
        Index of the reported state at this event point.
    segment : int
        Load-program segment.
    pattern : str
        Load pattern of that segment.
    lam : float
        Load factor of that pattern at the event.
    cfe : int
        Global CFE index.
    interface : str
        Interface name.
    local : int
        Index of the CFE along its interface.
    position : float
        Arc length along the interface, m (2D; in 3D the CFE's index along its interface:
        its place is x, y, z).
    x, y : float
        Coordinates of the CFE's S+ end, m.
    transition : Transition
    N : float
        Normal force at the event, N (N ≤ 0 compression).
    Q : float, or tuple of float in 3D
        Tangential force at the event, N, as ``result.Q`` holds it: the signed force along
        t₁ in 2D (a number), the vector of its components along t₁, t₂ with two tangential
        components (3D, n_t = 2; its magnitude is :attr:`Q_abs`).
    impulse_n, impulse_t : float
        Normal and tangential impulse of an impact on the CFE at the event (dynamics, rigid
        contact closing), N·s (per metre of thickness in plane strain), in the sign
        convention of N and Q (impulse_n ≤ 0 compressive); 0 at other events.
    Q_t : tuple of float
        The tangential force as a vector of its n_t components along the CFE's tangents
        t₁[, t₂], N, in every dimension: ``(Q,)`` in 2D (filled in from ``Q`` when not
        given).  Given (or ``Q`` given as a vector, e.g. ``lay.tangential(s)[k]``), it sets
        ``Q``.
    z : float or None
        z coordinate of the CFE's S+ end in a 3D model, m; None in 2D (absent: the result file
        of a 2D run has no ``event_z``, a table shows NaN; :attr:`point` has the coordinates
        the model has).

    ``Q`` has the shape of ``result.Q``'s entries: a number in 2D, so that 2D event logs keep
    what they print, compare and tabulate (``f"{e.Q:.3f}"``, a pandas column of numbers),
    and a vector in 3D; ``Q_t`` carries the tangential axis in every dimension.
    """

    step: int
    state: int
    segment: int
    pattern: str
    lam: float
    cfe: int
    interface: str
    local: int
    position: float
    x: float
    y: float
    transition: Transition
    N: float
    Q: float | tuple[float, ...]
    impulse_n: float = 0.0
    impulse_t: float = 0.0
    Q_t: tuple[float, ...] | None = None
    z: float | None = None

    def __post_init__(self):
        # Q_t from Q when not given: a number (2D), or Q given as the vector of n_t components
        q = np.ravel(self.Q if self.Q_t is None else self.Q_t).astype(float)
        object.__setattr__(self, "Q_t", tuple(q.tolist()))
        object.__setattr__(self, "Q", tuple(q.tolist()) if len(q) > 1 else float(q[0]))

    @property
    def n_t(self) -> int:
        """Number of tangential components (1 in 2D, 2 in 3D)."""
        return len(self.Q_t)

    @property
    def point(self) -> tuple[float, ...]:
        """The CFE's S+ end, m: (x, y) in 2D, (x, y, z) in 3D."""
        return (self.x, self.y) if self.z is None else (self.x, self.y, self.z)

    @property
    def Q_abs(self) -> float:
        """|Q| = ‖Q_t‖, the magnitude of the tangential force, N (≥ 0)."""
        return float(np.linalg.norm(self.Q_t))


@dataclass(frozen=True)
class Multipliers:
    """Stability multipliers of one load segment (load factors of its pattern, None if the
    thing did not happen in the segment)."""

    segment: int
    pattern: str
    first_slip: float | None = None
    first_opening: float | None = None
    first_closing: float | None = None
    equilibrium_lost: float | None = None


__all__ = ["Event", "Multipliers"]
