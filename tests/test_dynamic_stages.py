"""A dynamic interval after construction stages (issue 12): Newmark integration on the last
stage's system, from the state the stages end in.

References:

* a block on a rigid frictionless base with a prop, the prop removed at stage 2, then lifted
  at one end by a half-sine pulse (its corner rises and lands again): the same as the block
  built without the prop (frictionless elastic contact: the static state is unique), run
  from its own static state — displacements, contact forces and events to 1e-9;
* a wall built in two halves, the joint made at once on the deformed lower half, with the
  dynamic interval given on the last stage and no dynamic load: the static end state is an
  equilibrium of the last stage's system (shifted w⁰ of the joint, the automatic patterns
  held), so nothing moves — to 1e-9 (a w⁰ not shifted, or a pattern dropped, would set the
  wall vibrating at the scale of the state itself);
* a block grouted to its base at stage 2 and pulled up by twice its weight: the grouted bond
  holds it at rest in the dynamic interval, and a further pulse breaks the bond, each CFE on
  its strength surface when it breaks.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.enums import ContactState, Status, Transition
from stepcontact.errors import ModelError
from stepcontact.model.timefunction import Pulse
from test_stages import _block_on_base, _pull_model, _wall

BONDED = int(ContactState.BONDED)
LIFT = Pulse(amplitude=1.0, start=0.0, duration=4e-3)


def _lift(m):
    right = m.select("block", x=2.0, name="right")
    return m.add(sc.LoadPattern("lift", [sc.EdgeForce(right, fy=6e4)]))


def _end(res):
    return res.displacement(len(res.lam) - 1)


def test_a_block_unpropped_in_stage_two_moves_as_the_block_built_without_the_prop():
    dyn = sc.DynamicInterval(dt=2e-4, duration=8e-3, loads=(("lift", LIFT),))
    staged = _lift(_block_on_base()).add(
        sc.Stage("props", [sc.Segment("weight", 1.0)]),
        sc.Stage("unprop", remove_supports=("prop",), dynamics=dyn))
    assert staged.dynamics is dyn  # the last stage's interval is the model's
    ref_model = dataclasses.replace(_lift(_block_on_base(prop=False)).add(
        sc.Segment("weight", 1.0)), dynamics=dyn)
    st = sc.solve_static(staged)
    res = sc.solve_dynamic(staged, initial=st)
    ref = sc.solve_dynamic(ref_model, initial=sc.solve_static(ref_model))
    assert res.status == ref.status == Status.COMPLETED, res.message
    assert any(e.transition == Transition.OPENED for e in res.events)  # the corner lifts
    assert [(e.cfe, e.transition) for e in res.events] == [(e.cfe, e.transition)
                                                            for e in ref.events]
    np.testing.assert_allclose([e.lam for e in res.events], [e.lam for e in ref.events],
                               rtol=0, atol=1e-9 * dyn.duration)
    assert np.abs(res.u - ref.u).max() <= 1e-9 * np.abs(ref.u).max()
    assert np.abs(res.N - ref.N).max() <= 1e-9 * np.abs(ref.N).max()
    # the stage coordinate goes on: every state in the last stage, with its masks
    assert res.stage_names == st.stage_names == ("props", "unprop")
    assert np.all(res.stage == 1) and res.stage[0] == st.stage[-1]
    assert np.array_equal(res.stage_cfes, st.stage_cfes)
    assert res.active_bodies(len(res.lam) - 1) == {"block"} and res.active_cfes(0).all()
    # the prop's released reaction stays released (factor 0), the weight held
    j = res.pattern_names.index("unprop: release prop")
    assert np.all(res.factors[:, j] == 0.0)
    assert np.all(res.factors[:, res.pattern_names.index("weight")] == 1.0)


@pytest.fixture(scope="module")
def wall():
    dyn = sc.DynamicInterval(dt=1e-4, duration=2e-3)
    model = _wall().add(sc.LoadPattern("weight", [sc.BodyForce()]),
                        sc.Stage("first", [sc.Segment("weight", 1.0)]),
                        sc.Stage("second", bodies=("upper",), interfaces=("joint",),
                                 dynamics=dyn))
    st = sc.solve_static(model)
    return model, st, sc.solve_dynamic(model, initial=st)


def test_a_wall_built_in_stages_stays_at_rest_in_a_dynamic_interval_without_load(wall):
    model, st, res = wall
    assert res.status == Status.COMPLETED, res.message
    assert not res.events
    u_st = _end(st)
    assert np.abs(res.u - u_st).max() <= 1e-9 * np.abs(u_st).max()
    assert np.abs(res.N - st.N[-1]).max() <= 1e-9 * np.abs(st.N[-1]).max()
    assert np.abs(res.un).max() <= 1e-9 * np.abs(u_st).max()  # the joint's zero: shifted
    assert np.all(res.stage == 1) and res.active_bodies(0) == {"lower", "upper"}


@pytest.fixture(scope="module")
def unpropped():
    dyn = sc.DynamicInterval(dt=2e-4, duration=2e-3, loads=(("lift", LIFT),))
    model = _lift(_block_on_base()).add(
        sc.Stage("props", [sc.Segment("weight", 1.0)]),
        sc.Stage("unprop", remove_supports=("prop",), dynamics=dyn))
    st = sc.solve_static(model)
    return model, st, sc.solve_dynamic(model, initial=st)


def test_without_an_initial_result_the_stages_are_run_first(unpropped, tmp_path):
    model, st, res = unpropped
    again = sc.solve_dynamic(model)  # the staged static program, then the interval
    np.testing.assert_array_equal(again.u, res.u)
    # a result loaded from a file does not keep the stage systems: they are rebuilt (the
    # program run again, checked against it)
    st.save(tmp_path / "block.nc")
    loaded = sc.solve_dynamic(model, initial=sc.load_result(tmp_path / "block.nc"))
    np.testing.assert_array_equal(loaded.u, res.u)
    # and the dynamic result's file keeps the stages
    res.save(tmp_path / "block-dynamic.nc")
    back = sc.load_result(tmp_path / "block-dynamic.nc")
    assert np.array_equal(back.stage, res.stage) and back.stage_names == ("props", "unprop")
    assert np.array_equal(back.stage_cfes, res.stage_cfes)


def test_an_initial_result_of_another_model_is_refused(unpropped, tmp_path):
    model = unpropped[0]
    other = _lift(_block_on_base()).add(
        sc.Stage("props", [sc.Segment("weight", 1.5)]),
        sc.Stage("unprop", remove_supports=("prop",)))
    sc.solve_static(other).save(tmp_path / "other.nc")
    with pytest.raises(ModelError) as exc:
        sc.solve_dynamic(model, initial=sc.load_result(tmp_path / "other.nc"))
    assert exc.value.item == "initial"


def test_a_grouted_joint_holds_in_the_dynamic_interval_and_a_pulse_breaks_it():
    model = _pull_model(grout=True)
    st = sc.solve_static(model)
    assert np.all(st.state[-1] == BONDED)
    rest = sc.solve_dynamic(model, initial=st, dt=1e-4, duration=1e-3)
    assert rest.status == Status.COMPLETED and not rest.events
    assert np.all(rest.state == BONDED)  # the grouted bond, not the ungrouted contact
    u_st = _end(st)
    assert np.abs(rest.u - u_st).max() <= 1e-9 * np.abs(u_st).max()
    kick = Pulse(amplitude=60.0, start=0.0, duration=2e-3)  # 60 × 2 W more pull
    res = sc.solve_dynamic(model, initial=st, dt=1e-4, duration=2e-3, loads={"pull": kick})
    assert res.status == Status.COMPLETED, res.message
    broken = [e for e in res.events if e.transition == Transition.BROKEN]
    assert broken and len({e.cfe for e in broken}) == len(broken)
    NR = res.cfe["area"] * 1e6  # the grout's tensile strength 1 MPa
    for e in broken:  # on its strength surface (tension cut-off) when it breaks
        assert e.N == pytest.approx(NR[e.cfe], rel=1e-6)


def test_a_dynamic_interval_given_twice_is_an_error():
    dyn = sc.DynamicInterval(dt=1e-3, duration=1e-2)
    m = _block_on_base().add(sc.Stage("props", [sc.Segment("weight", 1.0)]),
                             sc.Stage("unprop", remove_supports=("prop",), dynamics=dyn))
    with pytest.raises(ModelError) as exc:
        dataclasses.replace(m, dynamics=sc.DynamicInterval(dt=1e-3, duration=2e-2))
    assert exc.value.item == "stage 'unprop'.dynamics"
    with pytest.raises(ModelError) as exc:
        sc.Stage("s", dynamics="soon")
    assert exc.value.item == "stage 's'.dynamics"


def test_a_dynamic_interval_after_stages_that_did_not_complete_is_refused():
    loose = _pull_model(grout=False)  # the ungrouted block lifts off: equilibrium lost
    st = sc.solve_static(loose)
    assert st.status == Status.EQUILIBRIUM_LOST
    with pytest.raises(ModelError) as exc:
        sc.solve_dynamic(loose, initial=st, dt=1e-4, duration=1e-3)
    assert exc.value.item == "initial" and "stage 'grouted'" in str(exc.value)


def test_a_support_placed_on_a_moved_body_is_refused_in_the_dynamic_interval():
    """A support placed at a later stage holds its nodes where they are by a prescribed
    displacement; the dynamic interval does not follow prescribed displacements: said."""
    m = _block_on_base(prop=False)
    m = m.add(sc.Support("top", m.select("block", y=1.0, name="top"), "y"),
              sc.Stage("placed", [sc.Segment("weight", 1.0)]),
              sc.Stage("propped", [sc.Segment("weight", 1.0, 1.0)], supports=("top",)))
    with pytest.raises(ModelError) as exc:
        sc.solve_dynamic(m, dt=1e-4, duration=1e-3)
    assert exc.value.item == "pattern 'propped: hold top'"
