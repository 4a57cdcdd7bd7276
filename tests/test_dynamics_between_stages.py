"""A dynamic interval in a stage before the last, static stages after it (issue 12).

The static run of the stages runs the interval on its stage's system, keeps its result
(``res.dynamics[stage]``), holds the force out of balance where the motion ends
(−(M a + C v)) as an automatic pattern and releases it by an automatic segment, and goes on.

References (a stiff block, 4 800 kg, on a rigid frictional base, f = 0.5, held sideways by
an anchor spring k with ω = √(k/M) = 2π·5 rad/s, struck by a force P = 2.5 f W applied at
once and held):

* rigid-block closed form of the motion: u(t) = (P − f W)(1 − cos ωt)/k while it slides; it
  stops at t = π/ω, u = 2 (P − f W)/k, and sticks (|P − k u| ≤ f W);
* statics exactly, from the state the motion left: unloading P → 0, the block slips back
  when P = k u − f W and ends where the anchor holds it against full friction,
  k u = f W (equilibrium of the horizontal forces with every CFE slipping: exact whatever
  the block's elasticity);
* an interval ending while the block still accelerates: releasing the out-of-balance force
  lets it slide on quasi-statically to where k u = P − f W, exactly;
* a frictionless block (its static state unique) lifted by a pulse between two stages ends
  the next stage exactly where the same block without the interval does (1e-9).

Equilibrium and the contact conditions are checked at every state of the static path.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import stepcontact as sc
from cli_checks import assert_one_line_error
from stepcontact.cli import app
from stepcontact.enums import Status, Transition
from stepcontact.errors import ModelError
from test_dynamic_stages import LIFT, _lift
from test_stages import _block_on_base

F, RHO, G = 0.5, 2400.0, 9.81
MASS = RHO * 2.0 * 1.0  # kg (per metre)
W = MASS * G  # N
OMEGA = 2 * np.pi * 5.0  # rad/s
K = MASS * OMEGA**2  # N/m
P = 2.5 * F * W  # N
STIFF = sc.Material(3e11, 0.2, RHO)  # a stiff block: rigid-block closed forms to ~1e-3
PERIOD = 2 * np.pi / OMEGA
BONDED = int(sc.ContactState.BONDED)
runner = CliRunner()


def _struck(duration: float, dt_per: int = 300):
    blk = sc.rectangle("block", (0, 0), (2.0, 1.0), 4, 2, STIFF)
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (3.0, 0.0)])
    m = sc.Model(name="struck").add(blk)
    anchor = int(np.flatnonzero(np.all(np.abs(blk.points - (0.0, 0.5)) < 1e-9, axis=1))[0])
    m = m.add(sc.Interface("base", m.select("block", y=0.0), ground, friction=F),
              sc.Spring("anchor", sc.NodeSet("block", [anchor], "anchor"), kx=K),
              sc.LoadPattern("weight", [sc.BodyForce()]),
              sc.LoadPattern("push", [sc.EdgeForce(m.select("block", x=0.0), fx=P)]))
    dyn = sc.DynamicInterval(dt=duration / dt_per, duration=duration,
                             loads=(("push", sc.Constant(1.0)),))
    m = m.add(sc.Stage("placed", [sc.Segment("weight", 1.0)]),
              sc.Stage("shock", dynamics=dyn),
              sc.Stage("unloaded", [sc.Segment("push", 0.0)]))
    return m, anchor


def _ux(res, node, states=None):
    dof = res.geometry["dof_of"][node][0]
    return res.displacements(states)[:, dof]


def _checked(res):
    assert res.status == Status.COMPLETED, res.message
    assert res.residual.max() <= 1e-9 and res.violation.max() <= 1e-9


@pytest.fixture(scope="module")
def stuck():
    m, anchor = _struck(0.75 * PERIOD)
    return m, anchor, sc.solve_static(m)


def test_a_block_struck_between_stages_stops_where_the_closed_form_says(stuck):
    m, anchor, res = stuck
    _checked(res)
    assert res.segments[1] == ("shock: settle after dynamics", 1.0, 0.0)
    assert res.segments[2] == ("push", 1.0, 0.0)  # the push stands at g(T) = 1 after it
    dres = res.dynamics["shock"]
    assert dres.status == Status.COMPLETED and dres.time[-1] == pytest.approx(0.75 * PERIOD)
    assert np.all(dres.stage == 1) and dres.stage_names == res.stage_names
    assert any(e.transition == Transition.SLIP_POS for e in dres.events)
    i = int(np.flatnonzero(res.kind == "dynamics")[0])
    assert res.stage[i] == 1 and res.segment[i] == 1
    # the static path takes the state where the motion ended: displacements, forces, states
    u_dyn = dres.u[-1]
    assert np.abs(res.displacement(i) - u_dyn).max() <= 1e-9 * np.abs(u_dyn).max()
    np.testing.assert_array_equal(res.state[i], dres.state[-1])
    np.testing.assert_allclose(res.N[i], dres.N[-1], rtol=0, atol=1e-12 * W)
    np.testing.assert_allclose(res.Q[i], dres.Q[-1], rtol=0, atol=1e-12 * W)
    # rigid-block closed form: it stopped at 2 (P − f W)/k
    u_stop = 2 * (P - F * W) / K
    assert _ux(res, anchor, [i])[0] == pytest.approx(u_stop, rel=2e-3)
    # the push's factor after the interval is g(T) = 1, then unloaded to 0
    j = res.pattern_names.index("push")
    assert res.factors[i, j] == 1.0 and res.factors[-1, j] == 0.0


def test_the_static_stage_after_the_shock_goes_on_from_where_the_block_stopped(stuck):
    m, anchor, res = stuck
    i = int(np.flatnonzero(res.kind == "dynamics")[0])
    u_i = _ux(res, anchor, [i])[0]
    # unloading: the block slips back once P λ = k u − f W (rigid statics from u_i), and
    # ends where the anchor holds it against full friction: k u = f W, exactly
    slips = [e for e in res.events if e.segment == 2 and e.transition == Transition.SLIP_NEG]
    assert len(slips) == res.m  # every base CFE, in turn
    assert max(e.lam for e in slips) < 1.0
    assert min(e.lam for e in slips) == pytest.approx((K * u_i - F * W) / P, abs=2e-3)
    assert _ux(res, anchor)[-1] == pytest.approx(F * W / K, rel=1e-8)
    assert np.sum(res.N[-1]) == pytest.approx(-W, rel=1e-9)  # (N < 0: compression)
    assert np.all(res.stage[i:] >= 1)


def test_an_interval_ending_while_the_block_accelerates_settles_where_friction_balances():
    m, anchor = _struck(0.2 * PERIOD, dt_per=100)
    res = sc.solve_static(m)
    _checked(res)
    i = int(np.flatnonzero(res.kind == "dynamics")[0])
    settled = int(np.flatnonzero((res.segment == 1) & (res.kind == "segment_end"))[0])
    u_t = _ux(res, anchor, [i])[0]
    wt = OMEGA * 0.2 * PERIOD  # still below (P − f W)/k and accelerating: a > 0
    assert u_t == pytest.approx((P - F * W) * (1 - np.cos(wt)) / K, rel=5e-3)
    # the out-of-balance force held at the interval's end is −M a (Newmark's equilibrium at
    # the step's end, no damping): its resultant along x is −1ₓᵀ M a
    from stepcontact.fem.mass import mass

    system = sc.assemble(m)
    ones = np.zeros(system.ndof)
    ones[system.dofs.of[:, 0][system.dofs.of[:, 0] >= 0]] = 1.0
    ma = ones @ (mass(m, system.dofs) @ res.dynamics["shock"].a[-1])
    assert ma > 0.1 * (P - F * W) * np.cos(wt)  # still accelerating forwards
    j = res.pattern_names.index("shock: settle after dynamics")
    assert res.load_resultants[j, 0] == pytest.approx(-ma, rel=1e-6)
    assert res.factors[i, j] == 1.0 and res.factors[settled, j] == 0.0
    # released: it slides on, every CFE slipping, to k u = P − f W exactly
    assert _ux(res, anchor, [settled])[0] == pytest.approx((P - F * W) / K, rel=1e-8)
    assert abs(np.sum(res.Q[settled])) == pytest.approx(F * W, rel=1e-9)  # full friction


def test_a_bond_broken_by_the_shock_stays_broken_in_the_static_stage_after_it():
    """The base bonded (c = 0.25 f W / A: the sudden push breaks it at once, a cascade), then
    plain friction f: the block slides and stops as the unbonded one does; unloaded, it ends
    at k u = f W exactly, which an intact bond (carrying shear with its cohesion) would not
    give."""
    m, anchor = _struck(0.75 * PERIOD)
    bond = sc.Bond.mohr_coulomb(0.25 * F * W / 2.0, 1e3, np.degrees(np.arctan(F)))
    m = dataclasses.replace(m, interfaces=(dataclasses.replace(m.interfaces[0], bond=bond),))
    res = sc.solve_static(m)
    _checked(res)
    dres = res.dynamics["shock"]
    broken = [e for e in dres.events if e.transition == Transition.BROKEN]
    assert sorted(e.cfe for e in broken) == list(range(res.m))  # each CFE once
    i = int(np.flatnonzero(res.kind == "dynamics")[0])
    assert np.all(res.state[:i] == BONDED) and not np.any(res.state[i:] == BONDED)
    assert _ux(res, anchor, [i])[0] == pytest.approx(2 * (P - F * W) / K, rel=5e-3)
    assert _ux(res, anchor)[-1] == pytest.approx(F * W / K, rel=1e-8)


def test_a_frictionless_block_lifted_between_stages_ends_as_if_never_lifted():
    # (long enough, and damped, for the block to land: a body still in flight or rocking on
    # one corner has no static path from there, which the run reports)
    dyn = sc.DynamicInterval(dt=2e-4, duration=2e-2, loads=(("lift", LIFT),), damping=(0, 1e-4))
    base = _lift(_block_on_base(prop=False))
    staged = base.add(sc.Stage("placed", [sc.Segment("weight", 1.0)]),
                      sc.Stage("lifted", [sc.Segment("weight", 1.2)], dynamics=dyn),
                      sc.Stage("loaded", [sc.Segment("weight", 1.5)]))
    ref = base.add(sc.Stage("placed", [sc.Segment("weight", 1.0)]),
                   sc.Stage("lifted", [sc.Segment("weight", 1.2)]),
                   sc.Stage("loaded", [sc.Segment("weight", 1.5)]))
    res, rres = sc.solve_static(staged), sc.solve_static(ref)
    _checked(res)
    dres = res.dynamics["lifted"]
    assert any(e.transition == Transition.OPENED for e in dres.events)  # the corner rose
    # the interval starts where the stage's own segment ends (weight at 1.2)
    assert dres.factors[0, dres.pattern_names.index("weight")] == 1.2
    assert [s[0] for s in res.segments] == ["weight", "weight", "lifted: settle after dynamics",
                                            "weight"]
    assert res.factors[-1, res.pattern_names.index("lift")] == 0.0  # the pulse is over
    u, ur = res.displacement(len(res.lam) - 1), rres.displacement(len(rres.lam) - 1)
    assert np.abs(u - ur).max() <= 1e-9 * np.abs(ur).max()
    np.testing.assert_allclose(res.N[-1], rres.N[-1], rtol=0, atol=1e-9 * np.abs(rres.N).max())


def test_a_block_left_in_flight_by_the_interval_is_a_reported_outcome():
    dyn = sc.DynamicInterval(dt=2e-4, duration=8e-3, loads=(("lift", LIFT),))
    m = _lift(_block_on_base(prop=False)).add(
        sc.Stage("placed", [sc.Segment("weight", 1.0)]), sc.Stage("lifted", dynamics=dyn),
        sc.Stage("loaded", [sc.Segment("weight", 1.5)]))
    res = sc.solve_static(m)
    assert res.status == Status.EQUILIBRIUM_LOST
    assert "stage 'lifted'" in res.message and "lengthen the interval" in res.message
    assert res.multipliers[-1].equilibrium_lost == 1.0 and res.dynamics["lifted"].status == \
        Status.COMPLETED
    assert res.residual.max() <= 1e-9


def test_a_damped_contact_layer_before_static_stages_is_refused():
    m, _ = _struck(0.1)
    layer = sc.ContactLayer(kn=1e10, kt=1e10, damping=1e6)
    itf = dataclasses.replace(m.interfaces[0], layer=layer)
    m = dataclasses.replace(m, interfaces=(itf,))
    with pytest.raises(ModelError) as exc:
        sc.solve_static(m)
    assert exc.value.item == "stage 'shock'.dynamics" and "'base'" in str(exc.value)


def test_a_residual_cohesion_before_the_interval_is_refused_before_any_work():
    m, _ = _struck(0.1)
    bond = sc.Bond.mohr_coulomb(1e4, 1e3, 30.0, residual_cohesion=500.0)
    m = dataclasses.replace(m, interfaces=(dataclasses.replace(m.interfaces[0], bond=bond),))
    with pytest.raises(ModelError) as exc:
        sc.solve_static(m)
    assert exc.value.item == "stage 'shock'.dynamics" and "residual" in str(exc.value)


def test_the_stage_of_an_earlier_interval_needs_the_run_of_the_stages():
    m, _ = _struck(0.1)
    with pytest.raises(ModelError) as exc:
        sc.solve_dynamic(m, stage="shock")
    assert exc.value.item == "initial"
    with pytest.raises(ModelError) as exc:
        sc.solve_dynamic(m, stage="nowhere")
    assert exc.value.item == "stage"
    with pytest.raises(ModelError) as exc:
        sc.solve_dynamic(m, stage=0)
    assert exc.value.item == "stage 'placed'.dynamics"


# ---- the model file and the command line ------------------------------------------------------
SHOCK = Path(__file__).parent.parent / "examples" / "data" / "staged_shock.toml"


def test_the_model_file_example_gives_the_hand_calculation(tmp_path):
    """examples/data/staged_shock.toml (E = 30 GPa, lumped mass, Δt = T/200), run by the
    command line:
    the block stops at 2 (P − f W)/k to the rigid block's 1e-3 … 2e-3, slips back at
    λ ≈ 0.8 and ends at k u = f W exactly; the interval's result file keeps its stage."""
    out = tmp_path / "shock.nc"
    result = runner.invoke(app, ["run", str(SHOCK), "--no-plot", "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert "dynamics of stage 'struck'" in result.output
    res = sc.load_result(out)
    dyn = sc.load_result(tmp_path / "shock-dynamic-struck.nc")
    assert res.status == dyn.status == Status.COMPLETED
    assert np.all(dyn.stage == 1) and dyn.stage_names == ("placed", "struck", "unloaded")
    fw, k, p = 0.5 * 4800 * 9.81, 4.737e6, 58860.0
    i = int(np.flatnonzero(res.kind == "dynamics")[0])
    model = sc.load_model(SHOCK)
    anchor = int(model.global_nodes(model.springs[0].a)[0])
    dof = res.geometry["dof_of"][anchor][0]
    assert res.displacement(i)[dof] == pytest.approx(2 * (p - fw) / k, rel=2e-3)
    assert np.abs(res.displacement(i) - dyn.displacement(len(dyn.lam) - 1)).max() <= 1e-9 * \
        np.abs(res.displacement(i)).max()
    slips = [e.lam for e in res.events if e.transition == Transition.SLIP_NEG]
    assert min(slips) == pytest.approx(0.8, abs=5e-3)
    assert res.displacement(len(res.lam) - 1)[dof] == pytest.approx(fw / k, rel=1e-6)


@pytest.mark.parametrize("edit, fragment", [
    (lambda t: t.replace('pattern = "push"\ntype = "constant"', 'pattern = "pusj"\ntype = '
                         '"constant"'), "stages[1].dynamics.loads[0].pattern: unknown load "
                                        "pattern 'pusj'"),
    (lambda t: t.replace("dt = 1e-3", "dt = -1e-3"), "stages[1].dynamics.dt"),
])
def test_a_bad_stage_dynamics_in_the_file_names_its_field(tmp_path, edit, fragment):
    path = tmp_path / "shock.toml"
    text = SHOCK.read_text(encoding="utf-8")
    assert edit(text) != text  # (the edit applies to the example as it is)
    path.write_text(edit(text), encoding="utf-8")
    result = runner.invoke(app, ["run", str(path), "--no-plot"])
    assert_one_line_error(result, fragment)
    assert not (tmp_path / "shock.nc").exists()
