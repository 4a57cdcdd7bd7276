"""A rigid block resting on two corners: redundant stuck rows in dynamics and statics, and a
dynamic run that never says "completed" with its conditions broken.

The block (2 m × 1 m, m = 4 800 kg per metre, J = m (2² + 1²)/12) stands on its two bottom
corners (half-width b = 1 m, centre of mass h = 0.5 m above the base), f = 0.5.  As a 3-DOF
:class:`~stepcontact.DiscreteModel` (ux, uy, θ; K = 0) both corners have the same tangential
row ux + h θ: stuck, the split of the friction force between them is indeterminate (a
self-stress Q₁ = −Q₂), not a mechanism.  Pushed at its centre by a half-sine pulse
P(t) = 0.8 W sin(π t/t_p), t_p = 0.1 s, it sticks, slides and stops without tipping
(closed form of the rigid block):

* slip starts at t_s = t_p/π · asin(f g/a), a = 0.8 g (P = f W), 0.021490 s;
* it slides with m ẍ = P − f W, then decelerates at f g after the pulse: slide 5.5267 mm,
  stop at 0.112177 s;
* no rotation: with the rotation held, the moment of the friction about the centre of mass
  is carried by the normal forces, p₁,₂ = W/2 ∓ h Q/(2b) (Q the total friction force, = P
  while stuck): never below 0.375 W, no corner lifts.
"""

from __future__ import annotations

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.enums import Status, Transition
from stepcontact.model.timefunction import Pulse
from stepcontact.solver.dynamic import _broken_conditions
from stepcontact.solver.static import VIOLATION_LIMIT

G, F, TP, A = 9.81, 0.5, 0.1, 0.8 * 9.81
MASS, B, H = 4800.0, 1.0, 0.5
W = MASS * G
J = MASS * (2.0**2 + 1.0**2) / 12


def closed_form():
    """(t_s, slide, t_stop) of the rigid block under the half-sine push."""
    ts = TP / np.pi * np.arcsin(F * G / A)
    c0 = np.cos(np.pi * ts / TP)
    v1 = A * TP / np.pi * (c0 + 1.0) - F * G * (TP - ts)
    x1 = (A * TP / np.pi * (c0 * (TP - ts) + TP / np.pi * np.sin(np.pi * ts / TP))
          - 0.5 * F * G * (TP - ts) ** 2)
    return ts, x1 + v1**2 / (2 * F * G), TP + v1 / (F * G)


def corners(push: float = 0.0, n: int = 2):
    """The block on n CFEs along its base, at x = −b … b (n = 2: its two corners; 3 DOFs);
    the static program puts on the weight (and a push along x, N)."""
    program = [sc.Segment("weight", 1.0)] + ([sc.Segment("push", push)] if push else [])
    x = np.linspace(-B, B, n)
    return sc.DiscreteModel(np.zeros((3, 3)), [[0, 1, xk] for xk in x], [[1, 0, H]] * n,
                            loads={"weight": [0, -W, 0], "push": [1.0, 0, 0]}, friction=F,
                            dof_names=("ux", "uy", "th"), program=program)


def one_cfe():
    """The same block as one CFE (ux, uy): no redundancy, an independent model."""
    return sc.DiscreteModel(np.zeros((2, 2)), [[0, 1]], [[1, 0]],
                            loads={"weight": [0, -W], "push": [1.0, 0]}, friction=F,
                            dof_names=("ux", "uy"), program=[sc.Segment("weight", 1.0)])


def pushed(dm, dt, mass, duration=0.2):
    st = sc.solve_static(dm)
    assert st.status == Status.COMPLETED
    return sc.solve_dynamic(dm, dt=dt, duration=duration, initial=st, mass=mass,
                            loads={"push": Pulse(A * MASS, 0.0, TP, "half_sine")})


@pytest.mark.parametrize("n", [2, 3])
def test_a_block_on_two_corners_sticks_slides_and_stops_as_one_cfe(n):
    """Both corners start to slip at one instant and stop at one instant, and nothing else
    happens (no corner opens, no zero-duration pairs): 4 events.  Against the closed form:
    slip start within 0.05 Δt (measured 0.003 Δt at Δt = 1 ms, 0.0001 Δt at 0.5 ms), stop
    within 0.05 Δt (measured 0.014, 0.004), slide to 1e-3 (measured 7.0e-4 and 1.4e-4: the
    error falls by 4.9 as Δt halves, second order; asserted ≥ 3).  While stuck the friction
    force is the push and the normal forces those of the moment balance,
    p₁,₂ = W/2 ∓ h P/(2b), to 1e-9 W (measured 4e-14 W); the rotation stays at round-off
    (≤ 1e-12 rad); after the stop, with no load, the total friction force is zero to
    1e-8 f W and each CFE's to 1e-6 f W (measured 3e-9 and 1.7e-7 f W at Δt = 0.5 ms:
    round-off at the stop that Newmark's alternating accelerations of the held DOFs carry
    on, growing with the steps).  Every state satisfies the contact conditions
    (violation ≤ 1e-9) and the run completes.  With a third CFE at mid-base (n = 3) the
    normal rows are redundant too (the split of N indeterminate): the same events and
    times, the normal forces' sum W and moment h P about the centre (their split, a least-
    squares one, is linear along the base)."""
    ts, slide, t_stop = closed_form()
    x = np.linspace(-B, B, n)
    errors = []
    for dt in (1e-3, 5e-4):
        res = pushed(corners(n=n), dt, np.diag([MASS, MASS, J]))
        assert res.status == Status.COMPLETED, res.message
        assert res.violation.max() <= 1e-9
        ev = [(e.cfe, e.transition) for e in res.events]
        assert sorted(ev) == sorted([(k, tr) for k in range(n)
                                     for tr in (Transition.SLIP_POS, Transition.STUCK)])
        start = {e.lam for e in res.events if e.transition == Transition.SLIP_POS}
        stop = {e.lam for e in res.events if e.transition == Transition.STUCK}
        assert len(start) == 1 and len(stop) == 1  # each pair at one instant
        assert abs(start.pop() - ts) <= 0.05 * dt
        t_s = stop.pop()
        assert abs(t_s - t_stop) <= 0.05 * dt
        err = abs(res.u[-1, 0] - slide) / slide
        assert err <= 1e-3
        errors.append(err)
        assert np.abs(res.u[:, 2]).max() <= 1e-12
        stuck = np.all(res.state == 1, axis=1) & (res.lam < ts)
        P = A * MASS * np.sin(np.pi * res.lam[stuck] / TP)
        p = -res.N[stuck]
        np.testing.assert_allclose(res.Q[stuck].sum(axis=1), P, rtol=0, atol=1e-9 * W)
        np.testing.assert_allclose(p.sum(axis=1), W, rtol=0, atol=1e-9 * W)
        np.testing.assert_allclose(p @ x, H * P, rtol=0, atol=1e-9 * W)
        if n == 2:
            np.testing.assert_allclose(p[:, 0], W / 2 - H * P / (2 * B), rtol=0, atol=1e-9 * W)
        after = res.lam > t_s + 1e-9
        assert np.abs(res.Q[after].sum(axis=1)).max() <= 1e-8 * F * W
        assert np.abs(res.Q[after]).max() <= 1e-6 * F * W
    assert errors[0] / errors[1] >= 3.0


def test_two_corners_give_the_answer_of_one_cfe():
    """The redundancy changes nothing the block does: the two-corner model's slip start, stop
    and slide equal those of the same block on one CFE (no redundant row, an independent
    model) — times to 1e-3 Δt, slide to 1e-8 relative (measured: equal to 1e-7 s, 1.5e-10)."""
    dt = 1e-3
    two = pushed(corners(), dt, np.diag([MASS, MASS, J]))
    one = pushed(one_cfe(), dt, np.diag([MASS, MASS]))
    assert two.status == one.status == Status.COMPLETED
    for tr in (Transition.SLIP_POS, Transition.STUCK):
        (t1,) = [e.lam for e in one.events if e.transition == tr]
        t2 = {e.lam for e in two.events if e.transition == tr}
        assert len(t2) == 1 and abs(t2.pop() - t1) <= 1e-3 * dt
    assert two.u[-1, 0] == pytest.approx(one.u[-1, 0], rel=1e-8)


def test_the_static_solver_holds_the_block_on_two_corners():
    """Statics of the same model: pushed by 0.4 W it stays stuck (completed, no events), the
    total friction force is the push and the normal forces those of the moment balance, to
    1e-9 W; each corner within its cone.  Pushed towards 0.6 W, both corners reach the cone
    together at P = f W (to 1e-9 relative) and the block, a rigid body on a rigid base, loses
    equilibrium there (a mechanism the push drives)."""
    st = sc.solve_static(corners(push=0.4 * W))
    assert st.status == Status.COMPLETED, st.message
    assert not st.events
    Q, p = st.Q[-1], -st.N[-1]
    assert Q.sum() == pytest.approx(0.4 * W, rel=1e-9)
    np.testing.assert_allclose(p, [W / 2 - H * 0.4 * W / (2 * B), W / 2 + H * 0.4 * W / (2 * B)],
                               rtol=0, atol=1e-9 * W)
    assert np.all(np.abs(Q) <= F * p * (1 + 1e-12))
    st = sc.solve_static(corners(push=0.6 * W))
    assert st.status == Status.EQUILIBRIUM_LOST
    assert {e.cfe for e in st.events} == {0, 1}
    assert all(e.lam == pytest.approx(F * W, rel=1e-9) for e in st.events)


def test_a_continuum_block_on_its_corners_slides_as_the_rigid_block():
    """The block as a stiff continuum (E = 3e11 Pa, 4 × 2 elements, lumped mass; 5 CFEs on a
    rigid base) under the same push as a body force: its elastic CFEs take the friction force
    in shares set by the elasticity and start to slip one after another (partial slip), the
    last (gross slip) within 1e-4 s of t_s (measured 4.8e-5 s; the elastic split, not the
    step); all stop within 5e-5 s of the rigid block's stop (measured 1.2e-5 s); the slide
    to 1e-3 at Δt = 1 ms (measured 4.9e-4); no CFE opens; violation ≤ 1e-9."""
    ts, slide, t_stop = closed_form()
    blk = sc.rectangle("block", (0, 0), (2.0, 1.0), 4, 2, sc.Material(3e11, 0.2, 2400.0))
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (3.0, 0.0)])
    m = sc.Model(name="block-on-corners").add(blk)
    m = m.add(sc.Interface("base", m.select("block", y=0.0), ground, friction=F),
              sc.LoadPattern("weight", [sc.BodyForce()]),
              sc.LoadPattern("push", [sc.BodyForce(g=(1.0, 0.0))]), sc.Segment("weight", 1.0))
    st = sc.solve_static(m)
    res = sc.solve_dynamic(m, dt=1e-3, duration=0.15, initial=st, mass="lumped",
                           loads={"push": Pulse(A, 0.0, TP, "half_sine")})
    assert res.status == Status.COMPLETED, res.message
    assert res.violation.max() <= 1e-9
    xdofs = sc.assemble(m).dofs.of[:, 0]
    assert res.u[-1][xdofs].mean() == pytest.approx(slide, rel=1e-3)
    assert not [e for e in res.events if e.transition in (Transition.OPENED, Transition.CLOSED)]
    slips = [e.lam for e in res.events if e.transition == Transition.SLIP_POS]
    stops = [e.lam for e in res.events if e.transition == Transition.STUCK]
    assert len(slips) == len(stops) == res.m
    assert abs(max(slips) - ts) <= 1e-4
    assert max(abs(t - t_stop) for t in stops) <= 5e-5


def test_broken_conditions_are_named_with_the_static_limit():
    """The check every recorded dynamic state goes through: below the static solver's limit
    (VIOLATION_LIMIT = 1e-6) nothing; above it, or a NaN, a message naming the violation, its
    size, the limit and the time; an equilibrium residual likewise."""
    assert _broken_conditions(0.0, 0.0, 0.1) == ""
    assert _broken_conditions(0.5 * VIOLATION_LIMIT, 0.5 * VIOLATION_LIMIT, 0.1) == ""
    msg = _broken_conditions(1.04, 0.0, 0.0187)
    assert "contact conditions" in msg and "1.04e+00" in msg and "0.0187" in msg
    assert f"{VIOLATION_LIMIT:.0e}" in msg
    assert "contact conditions" in _broken_conditions(float("nan"), 0.0, 0.0)
    assert "equilibrium" in _broken_conditions(0.0, 3e-5, 1.0)


def test_a_run_whose_conditions_hold_completes_and_one_that_breaks_them_does_not():
    """A run completes only when every recorded state meets the static limit: the two-corner
    block (violation ≤ 1e-9 everywhere: completed); and a run that starts from a static state
    of the one-CFE block (pushed by 0.2 W) whose friction force was doubled beyond its cone
    (|Q| = 2 f p, relative violation 0.5) ends with status ``violation`` at t = 0, its message
    naming the violation and the limit, with nothing recorded after that state (before: it
    "completed", its first state's violation 2e304 against an unset force scale)."""
    res = pushed(corners(), 1e-3, np.diag([MASS, MASS, J]), duration=0.03)
    assert res.status == Status.COMPLETED
    assert res.violation.max() <= VIOLATION_LIMIT
    dm = sc.DiscreteModel(np.zeros((2, 2)), [[0, 1]], [[1, 0]],
                          loads={"weight": [0, -W], "push": [1.0, 0]}, friction=F,
                          dof_names=("ux", "uy"),
                          program=[sc.Segment("weight", 1.0), sc.Segment("push", 0.2 * W)])
    st = sc.solve_static(dm)
    assert st.status == Status.COMPLETED
    bad = st.Q.copy()
    bad[-1, 0] = 2 * F * -st.N[-1, 0]  # beyond its cone: |Q| = 2 f p
    st.Q = bad
    res = sc.solve_dynamic(dm, dt=1e-3, duration=0.01, initial=st, mass=np.diag([MASS, MASS]))
    assert res.status == Status.VIOLATION
    assert "contact conditions are violated" in res.message
    assert f"{VIOLATION_LIMIT:.0e}" in res.message
    assert res.n_states == 1
    assert res.violation[0] == pytest.approx(0.5, rel=1e-9)
