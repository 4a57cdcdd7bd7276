"""The pieces the static and the dynamic driver share (issue 26 §4): the jump follower
(solver/jump.py), the bond break (solver/bonds.py) and the event log (solver/eventlog.py),
each checked on its own against a hand calculation.  The drivers' answers with them are the
recorded event sequences (tests/test_event_sequences.py) and the bond and dynamic tests."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from stepcontact.contact.bond import BondedJointLaw
from stepcontact.contact.laws import BONDED, OPEN, SLIP_POS, STICK, CoulombLaw
from stepcontact.contact.layout import ContactLayout
from stepcontact.enums import Transition
from stepcontact.results.recorder import Recorder
from stepcontact.solver.bonds import break_bonds, breaking
from stepcontact.solver.eventlog import EventLog
from stepcontact.solver.jump import AGAIN, DONE, RESTART, STOP, JumpState, follow_jump


class _Line:
    """An engine along a line: events at the given τ (one CFE each), advance moves τ."""

    def __init__(self, events):
        self.events = list(events)
        self.tau = 0.0
        self.steps = []

    def next_event(self, ds, dw, remaining, group):
        ahead = [e for e in self.events if e > self.tau + 1e-15]
        ev = ahead[0] - self.tau if ahead else np.inf
        d = min(ev, remaining)
        return d, ev, np.array([ev <= d + group])

    def advance(self, d, ds, dw):
        self.tau += d
        self.steps.append(d)


def test_a_jump_stops_at_every_event_and_ends_at_one():
    """Events at τ = 0.25, 0.5: the points are at τ = 0, 0.25, 0.5 and the jump ends at τ = 1
    (hand count; τ exact to 1e-15)."""
    eng = _Line([0.25, 0.5])
    seen, moved = [], []

    def point(state):
        seen.append((eng.tau, bool(state.fired.any())))
        return np.zeros(2), np.zeros(2)

    out = follow_jump(eng, point, JumpState(np.zeros(1, bool)), moved=moved.append)
    assert out == DONE
    assert [t for t, _ in seen] == pytest.approx([0.0, 0.25, 0.5], abs=1e-15)
    assert [f for _, f in seen] == [False, True, True]
    assert moved == pytest.approx([0.25, 0.5, 1.0], abs=1e-15)


def test_a_point_says_again_restart_or_stop():
    """AGAIN decides again at the same τ with nothing fired; RESTART and STOP end the jump at
    once; ``stop_at_end`` ends it at τ = 1 without another event search; ``stalled`` stops
    it before the engine moves; ``max_points`` bounds the points."""
    eng = _Line([0.5])
    calls = []

    def point(state):
        calls.append(eng.tau)
        if len(calls) == 2:  # at τ = 0.5, where the event fired
            assert state.fired.any()
            return AGAIN
        if len(calls) == 3:
            assert not state.fired.any()  # cleared by AGAIN
        return np.zeros(2), np.zeros(2)

    assert follow_jump(eng, point, JumpState(np.zeros(1, bool))) == DONE
    assert calls == pytest.approx([0.0, 0.5, 0.5], abs=1e-15)
    for answer in (RESTART, STOP):
        eng = _Line([])
        assert follow_jump(eng, lambda s, a=answer: a, JumpState(np.zeros(1, bool))) == answer
        assert eng.steps == []
    eng = _Line([1.0])  # an event exactly at the end: one more point there, then done
    n = []
    follow_jump(eng, lambda s: n.append(1) or (np.zeros(2), np.zeros(2)),
                JumpState(np.zeros(1, bool)), stop_at_end=True)
    assert len(n) == 2 and eng.tau == pytest.approx(1.0, abs=1e-15)
    eng = _Line([])
    out = follow_jump(eng, lambda s: (np.zeros(2), np.zeros(2)), JumpState(np.zeros(1, bool)),
                      stalled=lambda s: True)
    assert out == STOP and eng.steps == []
    eng = _Line([0.1 * k for k in range(1, 10)])
    assert follow_jump(eng, lambda s: (np.zeros(2), np.zeros(2)), JumpState(np.zeros(1, bool)),
                       max_points=3) == DONE
    assert eng.tau == pytest.approx(0.3, abs=1e-15)


def _engine(Q, p, states):
    lay = ContactLayout(len(Q))
    return SimpleNamespace(layout=lay, s=lay.join(np.asarray(Q, float), np.asarray(p, float)),
                           states=np.asarray(states, np.int64), rtol=1e-10,
                           tolerances=lambda: (1e-9, 1e-12))


def _cfe(m):
    return SimpleNamespace(names=("joint",), interface=np.zeros(m, np.int64),
                           local=np.arange(m), s=np.arange(m, dtype=float),
                           x=np.column_stack([np.arange(m, dtype=float), np.zeros(m)]))


def test_a_bond_breaks_into_its_coulomb_state_and_drops_what_it_cannot_carry():
    """Three bonded CFEs (f = 0.5, strength N_R = Q_R = 10 N): CFE 0 in tension (p = −2 N)
    opens and drops (Q, p) = (3, −2) N; CFE 1 pressed (p = 4 N) with Q = 5 N > f p = 2 N slips
    and drops Q − f p = 3 N; CFE 2 is not in ``brk`` and keeps its bond (hand calculation,
    exact in binary floating point)."""
    law = BondedJointLaw(CoulombLaw(np.arange(3), [0.5] * 3, [np.inf] * 3, [np.inf] * 3),
                         np.array([[10.0, 10.0, 0.0, 0.0]] * 3))
    eng = _engine([3.0, 5.0, 1.0], [-2.0, 4.0, 1.0], [BONDED] * 3)
    rec = Recorder(eng.layout, 1, 0)
    first = {"first_slip": None, "first_opening": None, "first_closing": None}
    g, before = break_bonds(eng, law, np.array([True, True, False]),
                            EventLog(rec, _cfe(3), eng.layout), first, step=7, state=2,
                            segment=1, pattern="P", lam=0.75)
    assert list(eng.states) == [OPEN, SLIP_POS, BONDED]
    assert list(g) == [3.0, 3.0, 0.0, -2.0, 0.0, 0.0]
    assert list(eng.s) == [0.0, 2.0, 1.0, 0.0, 4.0, 1.0]
    assert list(before) == [3.0, 5.0, 1.0, -2.0, 4.0, 1.0]
    assert [(e.cfe, e.transition, e.N, e.Q, e.step, e.lam) for e in rec.events] == [
        (0, Transition.BROKEN, 2.0, 3.0, 7, 0.75), (1, Transition.BROKEN, -4.0, 5.0, 7, 0.75)]
    assert first == {"first_slip": 0.75, "first_opening": 0.75, "first_closing": None}


def test_a_bond_on_its_strength_surface_breaks_only_when_driven_beyond():
    """Q = Q_R = 10 N (on the shear facet Q_R − Q = 0): a rate dQ = +1 drives it beyond and
    breaks it, dQ = −1 does not; a bonded CFE among ``fired`` breaks whatever its rates."""
    law = BondedJointLaw(CoulombLaw(np.arange(1), [0.5], [np.inf], [np.inf]),
                         np.array([[10.0, 10.0, 0.0, 0.0]]))
    eng = _engine([10.0], [0.0], [BONDED])
    lay = eng.layout
    assert breaking(eng, law, lay.join(np.array([1.0]), np.array([0.0]))).tolist() == [True]
    assert breaking(eng, law, lay.join(np.array([-1.0]), np.array([0.0]))).tolist() == [False]
    assert breaking(eng, law, lay.join(np.array([-1.0]), np.array([0.0])),
                    np.array([True])).tolist() == [True]


def test_the_event_log_sets_a_first_multiplier_once():
    """The first slip is the λ of the first slip event; a later one does not change it, and
    ``first=None`` sets nothing."""
    lay = ContactLayout(2)
    rec = Recorder(lay, 1, 0)
    log = EventLog(rec, _cfe(2), lay)
    first = {"first_slip": None, "first_opening": None, "first_closing": None}
    s = lay.join(np.array([1.0, 2.0]), np.array([3.0, 4.0]))
    where = {"step": 1, "state": 0, "segment": 0, "pattern": "P"}
    log.changes(np.array([STICK, STICK]), np.array([SLIP_POS, STICK]), s, lam=0.5, first=first,
                **where)
    log.event(1, STICK, SLIP_POS, s, lam=0.9, first=first, **where)
    log.event(0, SLIP_POS, OPEN, s, lam=1.0, first=None, **where)
    assert first == {"first_slip": 0.5, "first_opening": None, "first_closing": None}
    assert [(e.cfe, e.N, e.Q, e.lam) for e in rec.events] == [
        (0, -3.0, 1.0, 0.5), (1, -4.0, 2.0, 0.9), (0, -3.0, 1.0, 1.0)]
