"""Following the event engine along a jump at a fixed load factor (static) or time (dynamic),
for both drivers.

A jump is a change of the load that happens at one instant of the program — the forces of
broken bonds (eq. (12)) released, the crack water let into the CFEs that opened, a load
that jumps in a dynamic interval — followed along a parameter τ ∈ [0, 1] from event to event
exactly like a load segment (the engine's forcing is the jump's per unit τ): at every point
the scheme is decided, then the next event along the rest of the jump found and the engine
advanced to it, until τ reaches 1 with no event there.

What the drivers do at a point (decide, log, record; break bonds; stop) is theirs, given as
``point``.  Where a bond breaks on the way the two differ on purpose: the static driver ends
the jump (:data:`RESTART`) and starts a new one for everything still to release, the broken
bond's forces included; the dynamic one releases the broken bond's forces first in a jump of
their own (nested, in accelerations) and then goes on with the rest of its jump at the same
point (:data:`AGAIN`).  Both orders are the drivers' recorded event sequences.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

#: what a point may say instead of the rates: decide again here with no event fired
#: (after a nested release), end the jump for the caller to recompute it, the run stopped
AGAIN, RESTART, STOP = "again", "restart", "stop"
#: the jump reached τ = 1 with no event there (or its budget of points ran out)
DONE = "done"

#: a step of τ at most this long made no progress
NO_PROGRESS = 1e-12


@dataclass
class JumpState:
    """What a jump carries from point to point (and, for the static release, from one jump
    to the next): the CFEs whose event fired at the current point (m,) and the count of
    consecutive steps that made no progress (≤ :data:`NO_PROGRESS`)."""

    fired: np.ndarray
    small: int = 0


def follow_jump(eng, point: Callable, state: JumpState, *,
                moved: Callable[[float], None] | None = None,
                stalled: Callable[[JumpState], bool] | None = None,
                stop_at_end: bool = False, max_points: int | None = None) -> str:
    """Follow the engine ``eng`` along a jump τ ∈ [0, 1] (its forcing set by ``point``).

    At each point ``point(state)`` decides the scheme (given ``state.fired``, which it may
    change) and returns its rates (ds, dw), or :data:`AGAIN` (decide again at this point,
    nothing fired), :data:`RESTART` or :data:`STOP` (returned at once).  With the rates: at
    τ ≥ 1 and ``stop_at_end`` the jump is done; else the next event along the rest of the
    jump (:meth:`~stepcontact.solver.engine.EventEngine.next_event`, its fired CFEs into
    ``state.fired``), ``stalled(state)`` asked (True: :data:`STOP`), the engine advanced and
    ``moved(τ)`` told; done where τ reaches 1 − 1e-15 with no event fired there.
    ``max_points``: at most that many points, then done.  Returns :data:`DONE`,
    :data:`RESTART` or :data:`STOP`."""
    tau = 0.0
    for _ in itertools.count() if max_points is None else range(max_points):
        out = point(state)
        if isinstance(out, str):
            if out != AGAIN:
                return out
            state.fired = np.zeros(len(state.fired), bool)
            continue
        ds, dw = out
        if stop_at_end and tau >= 1.0:
            return DONE
        dtau, _, state.fired = eng.next_event(ds, dw, 1.0 - tau, 1e-10)
        state.small = state.small + 1 if dtau <= NO_PROGRESS else 0
        if stalled is not None and stalled(state):
            return STOP
        eng.advance(dtau, ds, dw)
        tau += dtau
        if moved is not None:
            moved(tau)
        if tau >= 1.0 - 1e-15 and not state.fired.any():
            return DONE
    return DONE


__all__ = ["AGAIN", "DONE", "RESTART", "STOP", "JumpState", "follow_jump"]
