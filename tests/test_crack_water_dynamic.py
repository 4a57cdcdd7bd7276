"""Water in the opened parts of a joint during a dynamic interval (CrackWater with the Newmark
driver): the crack pressure follows its time function into the gap, event by event.

References:

* quasi-static: a reservoir that rises slowly (over 40 periods of the block's rocking) cracks
  the heel at the load factor of the hand reference of ``test_crack_water`` (a rigid block on a
  Winkler layer), within 1 % (the dynamic part of the response);
* the mean motion: once the whole base is open and wet, the block's mass-weighted mean
  vertical velocity grows at (B p_c − m g)/m exactly (Newmark's average acceleration is exact
  for a constant resultant; a rigid translation carries no strain) — with p_c, not the uplift
  that the crack pressure replaces;
* at every reported state: the wet CFEs are open, carry no contact force and hold the crack
  pressure of their time function to round-off; the wet set is a run from the entry; the
  energy ledger balances.
"""

from __future__ import annotations

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.enums import Status, Transition
from stepcontact.fem.mass import mass
from stepcontact.model.timefunction import Pulse
from test_crack_water import GW, RHO, RigidBlock, dam_model

OPEN = int(sc.ContactState.OPEN)


def _ramp(lam: float, T: float):
    """λ (1 − cos πt/T)/2, held at λ after T (smooth: no jump of the rate)."""
    return lambda t: lam * 0.5 * (1.0 - np.cos(np.pi * min(float(t), T) / T))


def _check_wet_states(res, pressure, heel=True):
    """Wet CFEs open and unloaded, the crack pressure ``pressure(i)`` there, (``heel``) a run
    from the heel (CFE 0, the nearest to the entry)."""
    scale = float(np.abs(res.N).max())
    for i in range(len(res.lam)):
        wet = res.water[i] != 0
        if not wet.any():
            continue
        assert np.all(res.state[i][wet] == OPEN)
        np.testing.assert_allclose(res.N[i][wet], 0.0, atol=1e-12 * scale)
        np.testing.assert_allclose(res.crack_pressure[i][wet], pressure(i), rtol=1e-9)
        assert np.all(res.crack_pressure[i][~wet] == 0.0)
        if heel:
            run = wet[np.argsort(res.cfe["x"][:, 0])]
            assert run[0] and np.all(run[: run.sum()])  # joined to the heel


@pytest.fixture(scope="module")
def rising():
    """The dam of test_crack_water (concrete E = 30 GPa) at rest under its weight, then the
    reservoir raised smoothly to 1.6 × 11 m of head over 4 s (the rocking period ≈ 0.1 s)."""
    model = dam_model(lam_end=1.6, nx=8, E=30e9)
    st = sc.solve_static(model.replace(program=(sc.Segment("weight", 1.0),)))
    g = _ramp(1.6, 4.0)
    res = sc.solve_dynamic(model, dt=0.01, duration=4.0, loads={"water": g}, initial=st)
    dry = sc.solve_dynamic(dam_model(lam_end=1.6, nx=8, E=30e9, crack=False), dt=0.01,
                           duration=4.0, loads={"water": g}, initial=st)
    return model, st, g, res, dry


def test_a_slowly_rising_reservoir_cracks_the_heel_at_the_static_load_factor(rising):
    _, st, g, res, dry = rising
    assert res.status == Status.COMPLETED
    ref, _ = RigidBlock(st, 8.0, 11.0).openings(0.0, 1.6)
    first = [e for e in res.events if e.transition == Transition.OPENED][0]
    assert first.local == ref[0][0] == 0
    assert g(first.lam) == pytest.approx(ref[0][1], rel=1e-2)
    # the water drives the crack: it runs further than without crack water
    opened = {e.cfe for e in res.events if e.transition == Transition.OPENED}
    opened_dry = {e.cfe for e in dry.events if e.transition == Transition.OPENED}
    assert len(opened) > len(opened_dry) >= 1
    assert res.water.max() > 0 and dry.water is None


def test_the_crack_pressure_is_the_reservoirs_at_every_state_and_the_ledger_balances(rising):
    _, _, g, res, _ = rising
    _check_wet_states(res, lambda i: g(res.time[i]) * GW * 11.0)
    assert res.residual.max() < 1e-9
    assert res.violation.max() < 1e-8
    e = res.energy
    assert np.abs(e["error"]).max() < 1e-8 * e["external"][-1]


def test_the_joints_pressure_follows_its_time_function_into_the_opened_gap():
    """A static crack at the heel (reservoir at 1.5 × 11 m), then a pulse of pressure at the
    joint (CrackWater with a pressure, entering at the heel): the gap holds the reservoir's
    pressure plus the pulse at every state; CFEs that the pulse opens are wet in turn."""
    base = dam_model(lam_end=1.5, nx=8, E=30e9)
    itf = [i for i in base.interfaces if i.name == "base"][0]
    pulse = Pulse(60e3, 0.02, 0.2, "half_sine")
    model = base.replace(patterns=(*base.patterns, sc.LoadPattern(
        "joint", [sc.CrackWater(itf, pressure=1.0, entry=(0.0, 0.0))])))
    st = sc.solve_static(model)
    assert st.status == Status.COMPLETED
    wet0 = st.water[-1] > 0
    assert wet0.any()
    res = sc.solve_dynamic(model, dt=0.005, duration=0.3, loads={"joint": pulse}, initial=st)
    assert res.status == Status.COMPLETED
    _check_wet_states(res, lambda i: 1.5 * GW * 11.0 + pulse(res.time[i]))
    # the pulse opens the crack further; after it the gap closes back towards the static one
    wet = res.water != 0
    assert wet.sum(axis=1).max() > wet0.sum()
    assert res.residual.max() < 1e-9
    assert np.abs(res.energy["error"]).max() < 1e-8 * np.abs(res.energy["external"]).max()


def test_a_lifted_block_moves_under_the_crack_pressure_not_the_uplift_it_replaces():
    """Uplift p_u through the CFEs lifts a block off its layer; the water entering every
    opened CFE replaces it by p_c: once the whole base is open, the mean vertical acceleration
    is (B p_c − m g)/m exactly."""
    B, H, pu, pc = 4.0, 1.0, 60e3, 40e3
    conc = sc.Material(E=30e9, nu=0.2, density=RHO)
    m = sc.Model(bodies=[sc.rectangle("block", (0, 0), (B, H), 4, 1, conc)])
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (B + 1.0, 0.0)])
    base = sc.Interface("base", plus=m.select("block", y=0), minus=ground, friction=0.0,
                        layer=sc.ContactLayer(kn=1e9, kt=1e9))
    m = m.add(base, sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
              sc.LoadPattern("lift", [sc.Uplift(base, pressure=pu, through="cfes"),
                                      sc.CrackWater(base, pressure=pc)]),
              sc.Segment("weight", 1.0))
    st = sc.solve_static(m)
    res = sc.solve_dynamic(m, dt=1e-3, duration=0.05,
                           loads={"lift": Pulse(1.0, 0.0, 1.0, "rectangular")}, initial=st)
    assert res.status == Status.COMPLETED
    weight = RHO * 9.81 * B * H
    assert pc * B > weight  # it flies on with the crack pressure too
    allopen = np.flatnonzero(np.all(res.state == OPEN, axis=1))
    assert allopen.size > 10
    i0, i1 = allopen[0], len(res.lam) - 1
    assert np.all(np.diff(allopen) == 1)  # once open, it stays open
    system = sc.assemble(m)
    M = mass(m, system.dofs)
    ydofs = system.dofs.of[:, 1]
    ydofs = ydofs[ydofs >= 0]
    one = np.zeros(system.ndof)
    one[ydofs] = 1.0
    mtot = one @ (M @ one)
    assert mtot == pytest.approx(RHO * B * H, rel=1e-12)
    vbar = res.v @ (M @ one) / mtot
    acc = (pc * B - weight) / mtot
    np.testing.assert_allclose(vbar[i1] - vbar[i0], acc * (res.time[i1] - res.time[i0]),
                               rtol=1e-9)
    _check_wet_states(res, lambda i: pc, heel=False)
