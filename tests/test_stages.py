"""Construction in stages (issue 12, :class:`~stepcontact.model.stages.Stage`): one static run
through the stages, keeping locked-in stresses and contact forces.

References:

* a wall built in two halves (plane strain, quad8, rollers under it): the staged run is
  linear (the joint stays stuck), so its end state is the superposition of two runs of the
  library — the lower half alone under its own weight, and the whole wall under the upper
  half's weight (the upper half placed stress-free on the deformed lower half) — to round-off
  (1e-9).  Against the wall built at once the stresses agree and the top settles less by the
  lower half's compression under its own weight, δ = ρ g h₁² (1 − ν²) / (2E) (a uniaxial
  column in plane strain); the 2D mesh is not exactly uniaxial (a few 1e-3 of the stresses
  near the base), so these are checked to 1 %;
* a block on a rigid base (frictionless) and a prop: the prop removed at stage 2 releases
  its reaction by an automatic segment; the end state equals the block without the prop
  (frictionless elastic contact: unique), to 1e-9;
* a block on a rigid base with friction, its joint grouted at stage 2: it then carries a pull
  larger than its weight in tension (the ungrouted block lifts off), with the forces kept at
  grouting;
* bad inputs name the item.
"""

from __future__ import annotations

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.enums import Status
from stepcontact.errors import ModelError

E, NU, RHO, G = 30e9, 0.2, 2400.0, 9.81
B, H1, H2 = 2.0, 4.0, 3.0
MAT = sc.Material(E, NU, RHO)
OPEN, BONDED = int(sc.ContactState.OPEN), int(sc.ContactState.BONDED)


def _wall(lower=True, upper=True):
    bodies = []
    if lower:
        bodies.append(sc.rectangle("lower", (0, 0), (B, H1), 2, 4, MAT, "quad8"))
    if upper:
        bodies.append(sc.rectangle("upper", (0, H1), (B, H1 + H2), 2, 3, MAT, "quad8"))
    m = sc.Model(name="wall").add(*bodies)
    lo = m.body("lower")
    corner = int(np.flatnonzero(np.all(np.abs(lo.points) < 1e-9, axis=1))[0])
    m = m.add(sc.Support("base", m.select("lower", y=0.0), "y"),
              sc.Support("corner", sc.NodeSet("lower", [corner]), "x"))
    if upper:
        m = m.add(sc.Interface("joint", m.select("upper", y=H1), m.select("lower", y=H1),
                               friction=0.6))
    return m


def _end(res):
    i = len(res.lam) - 1
    return res.displacement(i), res.stress(i)


@pytest.fixture(scope="module")
def walls():
    weight = sc.LoadPattern("weight", [sc.BodyForce()])
    staged = _wall().add(weight, sc.Stage("first", [sc.Segment("weight", 1.0)]),
                         sc.Stage("second", bodies=("upper",), interfaces=("joint",)))
    at_once = _wall().add(weight, sc.Segment("weight", 1.0))
    alone = _wall(upper=False).add(weight, sc.Segment("weight", 1.0))
    top = _wall().add(sc.LoadPattern("top", [sc.BodyForce(bodies=("upper",))]),
                      sc.Segment("top", 1.0))
    return {name: sc.solve_static(m) for name, m in
            (("staged", staged), ("at_once", at_once), ("alone", alone), ("top", top))}


def test_a_wall_built_in_two_stages_is_the_superposition_of_its_two_stages(walls):
    res = walls["staged"]
    assert res.status == Status.COMPLETED
    assert res.stage_names == ("first", "second")
    # the automatic segment ramps the upper half's weight in
    assert res.segments == [("weight", 0.0, 1.0), ("second: loads on upper", 1.0, 0.0)]
    u, s = _end(res)
    ua, sa = _end(walls["alone"])
    ut, st = _end(walls["top"])
    n = len(ua)
    ref = ut.copy()
    ref[:n] += ua
    assert np.abs(u - ref).max() <= 1e-9 * np.abs(ref).max()
    for body, extra in (("lower", sa["lower"]), ("upper", 0.0)):
        want = st[body] + extra
        assert np.abs(s[body] - want).max() <= 1e-9 * np.abs(want).max()


def test_the_upper_half_is_placed_on_the_deformed_lower_half(walls):
    """Stresses as built at once; the top settles less by δ = ρ g h₁² (1 − ν²) / (2E)."""
    res, once = walls["staged"], walls["at_once"]
    u, s = _end(res)
    u1, s1 = _end(once)
    for body in ("lower", "upper"):
        assert np.abs(s[body] - s1[body]).max() <= 1e-2 * np.abs(s1[body]).max()
    model = _wall()
    up = model.body("upper")
    top = model.node_offsets["upper"] + np.flatnonzero(np.abs(up.points[:, 1] - H1 - H2) < 1e-9)
    delta = RHO * G * H1**2 * (1 - NU**2) / (2 * E)
    diff = np.mean(u[2 * top + 1] - u1[2 * top + 1])
    assert diff == pytest.approx(delta, rel=1e-2)


def test_an_interface_made_at_once_starts_stress_free_on_the_moved_bodies(walls):
    res = walls["staged"]
    i0 = int(np.flatnonzero(res.stage == 1)[0])  # the first state of stage 2
    assert res.active_bodies(0) == {"lower"} and res.active_bodies(i0) == {"lower", "upper"}
    assert not res.active_cfes(0).any() and res.active_cfes(i0).all()
    # end of stage 1: the upper half carries nothing, its nodes have not moved
    i1 = i0 - 1
    assert np.all(res.stress(i1)["upper"] == 0.0)
    u1 = res.displacement(i1)
    lower_top = res.displacement(i1)[1::2].min()
    assert lower_top < -0.9 * RHO * G * H1**2 * (1 - NU**2) / (2 * E)  # the lower half moved
    off = _wall().node_offsets["upper"]
    assert np.all(u1[2 * off:] == 0.0)
    # made at once: no force and no mutual displacement, though the lower half moved
    w_up = RHO * G * B * H2
    assert np.abs(res.N[i0]).max() <= 1e-12 * w_up and np.all(res.un[i0] == 0.0)
    assert np.all(res.state[i0] != OPEN)
    # then it carries the upper half's weight, in compression
    assert np.sum(res.N[-1]) == pytest.approx(-RHO * G * B * H2, rel=1e-9)


def _block_on_base(friction=0.0, prop=True):
    blk = sc.rectangle("block", (0, 0), (2.0, 1.0), 8, 4, MAT)
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (3.0, 0.0)])
    m = sc.Model(name="block").add(blk)
    pts = blk.points
    side = int(np.flatnonzero(np.all(np.abs(pts - (0.0, 0.5)) < 1e-9, axis=1))[0])
    top_left = int(np.flatnonzero(np.all(np.abs(pts - (0.0, 1.0)) < 1e-9, axis=1))[0])
    m = m.add(sc.Interface("base", m.select("block", y=0.0), ground, friction=friction),
              sc.Support("left", sc.NodeSet("block", [side]), "x"),
              sc.LoadPattern("weight", [sc.BodyForce()]))
    if prop:
        m = m.add(sc.Support("prop", sc.NodeSet("block", [top_left], "prop_node"), "y"))
    return m


def test_a_removed_support_releases_its_reaction_onto_the_contact():
    weight = RHO * G * 2.0 * 1.0
    staged = _block_on_base().add(
        sc.Stage("props", [sc.Segment("weight", 1.0)]),
        sc.Stage("unprop", remove_supports=("prop",)))
    res = sc.solve_static(staged)
    assert res.status == Status.COMPLETED, res.message
    assert res.segments[-1] == ("unprop: release prop", 1.0, 0.0)
    j = res.reaction_labels.index("prop:y")
    i1 = int(np.flatnonzero(res.stage == 1)[0]) - 1  # end of stage 1
    r1 = res.reactions[i1, j]
    assert r1 > 0.01 * weight  # the prop carried part of the weight
    # vertical equilibrium all along: contact + prop (+ its reaction held as a load, released
    # from factor 1 to 0 by the automatic segment) = weight
    c = res.factors[:, res.pattern_names.index("unprop: release prop")]
    assert c[i1 + 1] == 1.0 and c[-1] == 0.0
    total = -res.N.sum(axis=1) + res.reactions[:, j] + c * r1
    assert np.allclose(total[1:], weight, rtol=1e-9)
    assert res.reactions[-1, j] == 0.0
    # events of the release are located inside its segment
    for ev in res.events:
        if ev.segment == 1:
            assert 0.0 <= ev.lam <= 1.0
    ref = sc.solve_static(_block_on_base(prop=False).add(sc.Segment("weight", 1.0)))
    assert ref.status == Status.COMPLETED
    scale = np.abs(ref.N[-1]).max()
    assert np.abs(res.N[-1] - ref.N[-1]).max() <= 1e-9 * scale
    assert np.array_equal(res.state[-1], ref.state[-1])
    u, u_ref = res.displacement(len(res.lam) - 1), ref.displacement(len(ref.lam) - 1)
    assert np.abs(u - u_ref).max() <= 1e-9 * np.abs(u_ref).max()


def _propped_pair(together: bool):
    """The propped block of :func:`_block_on_base` with a second block placed on it (a joint
    with friction made at once) and the prop removed: in one stage, or in two."""
    m = _block_on_base()
    m = m.add(sc.rectangle("top", (0.0, 1.0), (2.0, 1.5), 8, 2, MAT))
    m = m.add(sc.Interface("joint", m.select("top", y=1.0), m.select("block", y=1.0),
                           friction=0.6))
    first = sc.Stage("props", [sc.Segment("weight", 1.0)])
    if together:
        return m.add(first, sc.Stage("top, unprop", bodies=("top",), interfaces=("joint",),
                                     remove_supports=("prop",)))
    return m.add(first, sc.Stage("top", bodies=("top",), interfaces=("joint",)),
                 sc.Stage("unprop", remove_supports=("prop",)))


def test_a_stage_that_builds_and_removes_a_support_ramps_the_loads_in_first():
    """The new block's weight ramps in before the prop is released (a weightless block on a
    joint could float off): the same segments in the same order as building and unpropping
    in two stages, so the same end state (1e-9), with the weight of both on the ground."""
    one = sc.solve_static(_propped_pair(True))
    two = sc.solve_static(_propped_pair(False))
    assert one.status == two.status == Status.COMPLETED, (one.message, two.message)
    assert [s[0] for s in one.segments[1:]] == ["top, unprop: loads on top",
                                                 "top, unprop: release prop"]
    scale = np.abs(two.N[-1]).max()
    assert np.abs(one.N[-1] - two.N[-1]).max() <= 1e-9 * scale
    u1, u2 = one.displacement(len(one.lam) - 1), two.displacement(len(two.lam) - 1)
    assert np.abs(u1 - u2).max() <= 1e-9 * np.abs(u2).max()
    w = RHO * G * 2.0 * 1.5  # both blocks on the ground at the end
    ground = one.cfe["interface"] == one.interface_names.index("base")
    assert -one.N[-1][ground].sum() == pytest.approx(w, rel=1e-9)


def _pull_model(grout: bool):
    m = _block_on_base(friction=0.6, prop=False)
    top = m.select("block", y=1.0, name="top")
    pull = 2.0 * RHO * G * 2.0 * 1.0  # twice the weight, upwards
    m = m.add(sc.LoadPattern("pull", [sc.EdgeForce(top, fy=pull)]))
    bond = sc.Bond.mohr_coulomb(cohesion=1e6, tensile_strength=1e6, friction_angle=35.0)
    second = sc.Stage("grouted", [sc.Segment("pull", 1.0)],
                      grout={"base": bond} if grout else {})
    return m.add(sc.Stage("placed", [sc.Segment("weight", 1.0)]), second)


def test_a_grouted_joint_is_bonded_and_carries_tension_it_could_not_before():
    res = sc.solve_static(_pull_model(grout=True))
    assert res.status == Status.COMPLETED, res.message
    i0 = int(np.flatnonzero(res.stage == 1)[0])
    # grouting keeps the forces the joint carried
    assert np.array_equal(res.N[i0], res.N[i0 - 1])
    assert np.all(res.state[i0] == BONDED) and np.all(res.state[-1] == BONDED)
    # the result keeps the grouted strengths (N_R = σ_t A)
    np.testing.assert_allclose(res.cfe["bond"][:, 0], 1e6 * res.cfe["area"], rtol=1e-12)
    weight = RHO * G * 2.0 * 1.0
    assert np.sum(res.N[-1]) == pytest.approx(weight, rel=1e-9)  # net tension = the pull − W
    assert res.N[-1].max() > 0
    loose = sc.solve_static(_pull_model(grout=False))
    assert loose.status == Status.EQUILIBRIUM_LOST


@pytest.mark.parametrize("stage, item", [
    (sc.Stage("s", [sc.Segment("weight", 1.0)], bodies=("nothing",)), "stage 's'.bodies"),
    (sc.Stage("s", [sc.Segment("weight", 1.0)], interfaces=("nothing",)),
     "stage 's'.interfaces"),
    (sc.Stage("s", [sc.Segment("weight", 1.0)], remove_supports=("nothing",)),
     "stage 's'.remove_supports"),
])
def test_a_stage_naming_an_unknown_item_is_an_error(stage, item):
    m = _wall().add(sc.LoadPattern("weight", [sc.BodyForce()]), stage)
    with pytest.raises(ModelError) as exc:
        sc.solve_static(m)
    assert exc.value.item == item
    assert "nothing" in str(exc.value)


def test_grouting_at_the_first_stage_is_an_error():
    bond = sc.Bond.mohr_coulomb(cohesion=1e6, tensile_strength=1e6, friction_angle=35.0)
    m = _block_on_base(prop=False).add(
        sc.Stage("placed", [sc.Segment("weight", 1.0)], grout={"base": bond}))
    with pytest.raises(ModelError) as exc:
        sc.solve_static(m)
    assert exc.value.item == "stage 'placed'.grout" and "'base'" in str(exc.value)


def test_a_program_with_stages_is_an_error():
    m = _wall().add(sc.LoadPattern("weight", [sc.BodyForce()]), sc.Segment("weight", 1.0))
    with pytest.raises(ModelError, match="model.program"):
        m.add(sc.Stage("s", [sc.Segment("weight", 1.0)]))


def test_an_interface_to_a_body_built_later_and_a_tie_across_stages_are_errors():
    m = _wall().add(sc.LoadPattern("weight", [sc.BodyForce()]),
                    sc.Stage("first", [sc.Segment("weight", 1.0)]),
                    sc.Stage("second", [sc.Segment("weight", 1.0, 1.0)], bodies=("upper",)))
    with pytest.raises(ModelError, match="interface 'joint'.*'upper'"):
        sc.solve_static(m)
    tied = _wall().replace(interfaces=()).add(
        sc.Tie("glue", m.select("upper", y=H1), m.select("lower", y=H1)),
        sc.LoadPattern("weight", [sc.BodyForce()]),
        sc.Stage("first", [sc.Segment("weight", 1.0)]),
        sc.Stage("second", [sc.Segment("weight", 1.0, 1.0)], bodies=("upper",)))
    with pytest.raises(ModelError) as exc:
        sc.solve_static(tied)
    assert exc.value.item == "tie 'glue'"


def test_the_stages_are_kept_in_the_result_file(walls, tmp_path):
    res = walls["staged"]
    res.save(tmp_path / "wall.nc")
    back = sc.load_result(tmp_path / "wall.nc")
    assert np.array_equal(back.stage, res.stage) and back.stage_names == res.stage_names
    assert np.array_equal(back.stage_cfes, res.stage_cfes)
    assert back.active_bodies(0) == {"lower"} and back.active_cfes(len(back.lam) - 1).all()
