"""The dynamic driver's shortcuts (issue 27): a quiet step — no CFE at a limit at its start,
no event inside it — is decided and moved without the engine's rate problem, and the
projection after a cut keeps its Cholesky factor while its rows change.  Each is checked
against the path it shortcuts: the engine's full decision at every step, and a factorisation
of the row set from scratch."""

from __future__ import annotations

import numpy as np
import pytest

import stepcontact as sc
from stepcontact import solve_dynamic
from stepcontact.model.timefunction import Harmonic
from stepcontact.solver import dynamic


def _den_hartog(periods: float = 12.0):
    """Den Hartog's forced stick-slip block (tests/test_dynamics.py, r = 2): long slips and
    stops, two events every half period."""
    k, m_, N, F0, mu = 1e4, 1.0, 100.0, 100.0, 0.3
    dm = sc.DiscreteModel(K=[[k, 0.0], [0.0, 0.0]], normal_rows=[[0, 1]],
                          tangent_rows=[[1, 0]], loads={"weight": {"uy": -N},
                                                        "force": {"ux": 1.0}},
                          friction=mu, dof_names=("ux", "uy"),
                          program=[sc.Segment("weight", 1.0)])
    st = sc.solve_static(dm)
    w = 2.0 * np.sqrt(k / m_)
    T = 2 * np.pi / w
    return dm, dict(dt=T / 100, duration=periods * T, mass=np.diag([m_, m_]), initial=st,
                    loads={"force": Harmonic(F0, w / (2 * np.pi), np.pi / 2)})


def _lifted_block():
    """A rigid-contact block (2 CFEs, f = 0.5) pushed sideways and lifted by a harmonic
    force: it slips both ways, sticks, lifts off and lands again (an impact)."""
    # DOFs (ux, uy, θ), a rotational spring only; CFEs at x = ∓0.5: gaps u_y ∓ 0.5 θ,
    # slips u_x
    dm = sc.DiscreteModel(K=np.diag([0.0, 0.0, 1e3]),
                          normal_rows=[[0.0, 1.0, -0.5], [0.0, 1.0, 0.5]],
                          tangent_rows=[[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
                          loads={"weight": {"uy": -100.0},
                                 "push": {"ux": 1.0, "uy": 0.9}},
                          friction=0.5, dof_names=("ux", "uy", "th"),
                          program=[sc.Segment("weight", 1.0)])
    st = sc.solve_static(dm)
    return dm, dict(dt=2e-3, duration=0.6, mass=np.diag([1.0, 1.0, 0.1]), initial=st,
                    loads={"push": Harmonic(150.0, 2.5)})


def _engine_only(monkeypatch):
    """Every step's start decided by the engine's rate problem (no quiet steps)."""
    monkeypatch.setattr(dynamic, "_quiet_start", lambda *a, **k: None)


@pytest.mark.parametrize("case", [_den_hartog, _lifted_block])
def test_quiet_steps_follow_the_engines_decisions(case, monkeypatch):
    """Reference: the same run with the engine's full decision (rate problem) at the start
    of every step.  The quiet step makes the same calls on the same floats, so the events
    (CFE and transition) are the same and their times, the fields and the energy ledger
    agree to round-off: times to 1e-12 of the interval, fields to 1e-9 of their largest
    value, energies to 1e-9 of the largest work (measured: identical)."""
    model, kw = case()
    fast = solve_dynamic(model, **kw)
    with monkeypatch.context() as mp:
        _engine_only(mp)
        ref = solve_dynamic(model, **kw)
    assert fast.status == ref.status == sc.Status.COMPLETED
    assert len(fast.events) == len(ref.events) > 4
    assert [(e.cfe, e.transition) for e in fast.events] == [(e.cfe, e.transition)
                                                              for e in ref.events]
    span = kw["duration"]
    assert np.abs(np.array([e.lam for e in fast.events])
                  - np.array([e.lam for e in ref.events])).max() <= 1e-12 * span
    assert fast.u.shape == ref.u.shape
    for a, b in ((fast.u, ref.u), (fast.v, ref.v), (fast.Q, ref.Q), (fast.N, ref.N)):
        assert np.abs(a - b).max() <= 1e-9 * max(np.abs(b).max(), 1e-300)
    work = max(np.abs(ref.energy["external"]).max(), 1e-300)
    for term, vals in ref.energy.items():
        assert np.abs(fast.energy[term] - vals).max() <= 1e-9 * work, term


def test_the_projections_tracked_factor_solves_as_a_new_factorisation():
    """Reference: numpy's dense solve of W_r λ = b on each row set r (a factorisation from
    scratch), for a sequence of sets that lose and gain rows at the start, the middle and
    the end (the last row of the factor's order too, which leaves no trailing block), and a
    set with two equal rows (singular: the least-squares solution, as numpy's lstsq).
    Tolerance 1e-9 relative (W_r's condition is below 1e4 here)."""
    rng = np.random.default_rng(3)
    n = 30
    A = rng.standard_normal((n, 2 * n))
    GM = A @ A.T / n
    GM[:, 28] = GM[:, 27]  # rows 27 and 28 equal: a set with both is singular
    GM[28, :] = GM[27, :]
    tf = dynamic._TrackedFactor(GM)
    sets = [np.arange(0, 20), np.arange(1, 20), np.r_[1:10, 11:20], np.r_[1:10, 11:19],
            np.r_[1:10, 11:19, 25, 26], np.r_[0:10, 11:19, 25], np.r_[0:6, 8:12],
            np.r_[0:12], np.r_[0:6, 8:12, 27, 28], np.r_[0:6, 8:12, 29], np.r_[0:6, 8:13, 29]]
    for rows in sets:
        rows = np.asarray(rows, np.int64)
        b = rng.standard_normal(len(rows))
        W = GM[np.ix_(rows, rows)]
        x = tf.solve(rows, b)
        ref = np.linalg.lstsq(W, b, rcond=None)[0]
        assert np.abs(x - ref).max() <= 1e-9 * np.abs(ref).max(), rows
