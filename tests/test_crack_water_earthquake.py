"""Crack water during an earthquake (issue 29 §1): the choice of a dynamic interval
(``DynamicInterval(crack_water=...)``, ``solve_dynamic(crack_water=...)``) — ``"full"`` (the
static rule in time), ``"unchanged"`` (the pre-earthquake wet set and pressures held) and
``"none"`` (held, and no pressure in the joints the shaking opens) — and the post-earthquake
static check on the cracked, slid state.

References:

* the rule of each choice, checked at every reported state against the hand pressures of the
  block of ``test_crack_water`` (B = 8 m, reservoir 11 m × λ = 1.2, uplift head λ·11 m at the
  heel → 0 at the toe): p_c = λ γ_w 11 m in the crack, p_u = p_c (1 − x/B); wet CFEs are open
  and carry no contact force (1e-12 of the largest), hold the pressure of the choice (1e-9
  relative; "none": 0 to 1e-9 p_c in a new opening, where W = −A p_u), and the energy ledger
  balances (1e-8 of the work of the loads);
* the mean motion of a block lifted off its Winkler layer by a vertical ground pulse
  (−2 g for 0.04 s): once the whole base is open, its mass-weighted mean vertical velocity
  grows at (B p − m g)/m + 2 g exactly (Newmark's average acceleration is exact for a
  constant resultant), with p the choice's pressure in the base — p_c for "full", the
  uplift p_u for "unchanged" (no water enters: the uplift acts as before), 0 for "none"
  (1e-9 relative);
* the post-earthquake static stage: the water of the static rule enters the openings the
  interval left dry at the start of the stage's first segment (the release of the force out
  of balance, λ = 1 of the automatic pattern), with W = A (p_c − p_u) by hand (1e-9); after
  the earthquake's load is removed, the crack is the rigid-block hand crack of
  ``test_crack_water`` (the first two CFEs) and the friction-only sliding factor is
  f (W − U − Σ A (p_c − p_u)) / F_h by hand statics (vertical and horizontal equilibrium,
  1e-9), on a base that has slid.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.enums import Status
from stepcontact.errors import ModelError
from stepcontact.fem.mass import mass
from stepcontact.model.timefunction import Pulse
from test_crack_water import GW, HEIGHT, RHO, RigidBlock, dam_model

OPEN = int(sc.ContactState.OPEN)
B, H, LAM, F = 8.0, 11.0, 1.2, 0.8


def _dam(E=30e9):
    """The block of test_crack_water (B × 12 m on a Winkler layer, 9 CFEs 1 m apart) with the
    uplift, friction f = 0.8 and a horizontal inertia pattern "quake" (1 g downstream)."""
    m = dam_model(B=B, H=H, lam_end=LAM, nx=8, E=E, uplift=True)
    itf = dataclasses.replace(m.interfaces[0], friction=F)
    return m.replace(interfaces=(itf,)).add(
        sc.LoadPattern("quake", [sc.BodyForce(g=(9.81, 0.0), bodies=("dam",))]))


def _pc() -> float:
    return LAM * GW * H  # Pa, the crack pressure at y = 0


def _pu(x) -> np.ndarray:
    return _pc() * (1.0 - np.asarray(x) / B)  # Pa, the uplift


def _watered(res, i):
    """CFEs the crack water loads at state i: a recorded pressure or force."""
    return (res.crack_pressure[i] != 0) | (res.water[i] != 0)


@pytest.fixture(scope="module")
def quake():
    """The static crack at λ = 1.2 (the heel's two CFEs open and wet), then one and a half
    cycles of a 0.4 g, 2.5 Hz harmonic (downstream first), under each choice."""
    model = _dam()
    st = sc.solve_static(model)
    assert st.status == Status.COMPLETED
    shaking = sc.Harmonic(0.4, 2.5)
    runs = {ch: sc.solve_dynamic(model, dt=0.005, duration=0.6, loads={"quake": shaking},
                                 initial=st, crack_water=ch)
            for ch in sc.CRACK_WATER_CHOICES}
    return st, runs


def _common_checks(res, drains=None):
    """Completed, equilibrium and the contact conditions, the ledger balanced; the water acts
    in open CFEs only (no contact force there) — except, with "none", the ``drains``
    (closed before the shaking), which keep W = −A p_u once opened."""
    assert res.status == Status.COMPLETED, res.message
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-8
    e = res.energy
    assert np.abs(e["error"]).max() < 1e-8 * np.abs(e["external"]).max()
    scale = float(np.abs(res.N).max())
    for i in range(len(res.lam)):
        wet = _watered(res, i) & (True if drains is None else ~drains)
        assert np.all(res.state[i][wet] == OPEN)
        np.testing.assert_allclose(res.N[i][wet], 0.0, atol=1e-12 * scale)


def test_the_pre_earthquake_crack_is_the_heels_two_cfes(quake):
    st, _ = quake
    i = len(st.lam) - 1
    np.testing.assert_array_equal(np.flatnonzero(_watered(st, i)), [0, 1])
    # the hand crack of a rigid block at λ = 1.2: the first two CFEs (test_crack_water)
    ref, _ = RigidBlock(st, B, H, uplift=True).openings(0.0, LAM)
    assert [k for k, _ in ref] == [0, 1]


def test_full_lets_the_reservoir_into_every_opening_joined_to_the_heel(quake):
    _, runs = quake
    res = runs["full"]
    _common_checks(res)
    x = res.cfe["x"][:, 0]
    order = np.argsort(x)
    for i in range(len(res.lam)):
        op = (res.state[i] == OPEN)[order]
        run = np.cumprod(op).astype(bool)  # the open run from the heel
        np.testing.assert_array_equal(_watered(res, i)[order], run)
        wet = _watered(res, i)
        np.testing.assert_allclose(res.crack_pressure[i][wet], _pc(), rtol=1e-9)
        np.testing.assert_allclose(res.water[i][wet], res.cfe["area"][wet]
                                   * (_pc() - _pu(x[wet])), rtol=1e-9, atol=1e-9 * _pc())
    # the shaking opens CFEs beyond the static crack: water enters them
    assert _watered(res, slice(None)).any(axis=0)[2:].any()


@pytest.mark.parametrize("choice", ["unchanged", "none"])
def test_the_held_choices_keep_the_pre_earthquake_water_and_pressures(quake, choice):
    st, runs = quake
    res = runs[choice]
    x = res.cfe["x"][:, 0]
    held = _watered(st, len(st.lam) - 1)
    closed0 = st.state[-1] != OPEN
    pu = _pu(x)
    drains = closed0 & (pu > 0) if choice == "none" else None
    _common_checks(res, drains)
    drained = np.zeros(len(x), bool)
    for i in range(len(res.lam)):
        op = res.state[i] == OPEN
        wet = _watered(res, i)
        drained |= op & closed0  # opened by the shaking (closed before it)
        # the held set where it is open, with its pre-earthquake pressure
        np.testing.assert_array_equal(wet & held, op & held)
        np.testing.assert_allclose(res.crack_pressure[i][op & held], _pc(), rtol=1e-9)
        if choice == "unchanged":  # no water enters: the uplift acts there as before
            np.testing.assert_array_equal(wet, op & held)
        else:  # "none": no pressure at all in a crack the shaking opened, from its opening
            # on, open or closed again: W = −A p_u cancels the uplift there
            new = drained & drains
            np.testing.assert_array_equal(wet, (op & held) | new)
            np.testing.assert_allclose(res.crack_pressure[i][new], 0.0, atol=1e-9 * _pc())
            np.testing.assert_allclose(res.water[i][new], -res.cfe["area"][new] * pu[new],
                                       rtol=1e-9)
    assert drained[2:].any()  # the shaking opened CFEs beyond the static crack
    # and the held CFEs closed during the interval (carrying contact force) and reopened,
    # their pressure back (checked at every state above)
    shut = np.flatnonzero(np.any(res.state[:, held] != OPEN, axis=1))
    assert shut.size and np.all(res.state[shut[-1] + 1:, held] == OPEN)
    assert shut[-1] + 1 < len(res.lam)


def test_the_choices_differ_in_the_motion(quake):
    _, runs = quake
    slip = {ch: float(np.abs(r.ut[-1]).max()) for ch, r in runs.items()}
    # more water under the dam, less friction: "full" slides furthest
    assert slip["full"] > max(slip["unchanged"], slip["none"]) > 0
    assert slip["unchanged"] != pytest.approx(slip["none"], rel=1e-3)


def _lifted():
    """A block (4 m × 1 m, 9 600 kg/m) on a frictionless Winkler layer, with the uplift
    p_u = 20 kPa through its CFEs and crack water p_c = 40 kPa (no entry: every open CFE)
    in pattern "lift" (at factor 1; B p_u < m g: the base stays closed at rest)."""
    Bb, Hb = 4.0, 1.0
    conc = sc.Material(E=30e9, nu=0.2, density=RHO)
    m = sc.Model(bodies=[sc.rectangle("block", (0, 0), (Bb, Hb), 4, 1, conc)])
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (Bb + 1.0, 0.0)])
    base = sc.Interface("base", plus=m.select("block", y=0), minus=ground, friction=0.0,
                        layer=sc.ContactLayer(kn=1e9, kt=1e9))
    return m.add(base, sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
                 sc.LoadPattern("lift", [sc.Uplift(base, pressure=20e3, through="cfes"),
                                         sc.CrackWater(base, pressure=40e3)]),
                 sc.Segment("weight", 1.0), sc.Segment("lift", 1.0)), Bb, Hb


@pytest.mark.parametrize(("choice", "p", "g_drop"), [
    ("full", 40e3, 2.0), ("unchanged", 20e3, 2.0), ("none", 0.0, 2.0), ("none", 0.0, 0.5)])
def test_a_block_thrown_off_its_base_moves_under_the_pressure_of_the_choice(choice, p, g_drop):
    """The ground drops at ``g_drop`` g for 0.04 s.  At 0.5 g only the uplift's help opens
    the base (m a < m g < m a + B p_u): under "none" the opened base loses the uplift and
    falls back — it lands and stays drained (no chatter between the two pressures)."""
    m, Bb, Hb = _lifted()
    st = sc.solve_static(m)
    assert st.status == Status.COMPLETED and np.all(st.state[-1] != OPEN)
    A = g_drop * 9.81  # m/s²
    res = sc.solve_dynamic(m, dt=1e-3, duration=0.06, initial=st, crack_water=choice,
                           ground_acceleration=(Pulse(-A, 0.0, 0.04, "rectangular"),
                                                (0.0, 1.0)))
    assert res.status == Status.COMPLETED
    system = sc.assemble(m)
    M = mass(m, system.dofs)
    ydofs = system.dofs.of[:, 1]
    one = np.zeros(system.ndof)
    one[ydofs[ydofs >= 0]] = 1.0
    mtot = one @ (M @ one)
    assert mtot == pytest.approx(RHO * Bb * Hb, rel=1e-12)
    allopen = np.flatnonzero(np.all(res.state == OPEN, axis=1) & (res.time < 0.04 - 1e-9))
    assert allopen.size > 0
    run = allopen[: np.argmax(np.r_[np.diff(allopen) != 1, True]) + 1]  # the first flight
    assert run.size > (20 if g_drop > 1 else 1)
    i0, i1 = run[0], run[-1]
    vbar = res.v @ (M @ one) / mtot
    acc = (p * Bb - RHO * 9.81 * Bb * Hb) / mtot + A
    np.testing.assert_allclose(vbar[i1] - vbar[i0], acc * (res.time[i1] - res.time[i0]),
                               rtol=1e-9)
    np.testing.assert_allclose(res.crack_pressure[i1], p if choice == "full" else 0.0,
                               atol=1e-9 * 40e3)
    assert np.abs(res.energy["error"]).max() < 1e-8 * np.abs(res.energy["external"]).max()
    if choice == "none":  # drained from the first opening on, open or closed
        first = int(np.flatnonzero(np.all(res.state == OPEN, axis=1))[0])
        drained = np.broadcast_to(-20e3 * res.cfe["area"], res.water[first:].shape)
        np.testing.assert_allclose(res.water[first:], drained, rtol=1e-9)
        if g_drop < 1:  # it falls back: closed at the end, a bounded number of events
            assert np.all(res.state[-1] != OPEN) and len(res.events) < 100


def _staged(choice: str):
    """The dam filled (λ = 1.2, the static crack), an earthquake of 0.15 g (half sine of
    0.2 s) that the interval ends at its peak (T = 0.1 s: the load stands at 0.15 g after
    it, the heel rocked open), then the post-earthquake stage removing it."""
    m = _dam().replace(program=())
    dyn = sc.DynamicInterval(dt=0.005, duration=0.1, crack_water=choice,
                             loads=(("quake", Pulse(0.15, 0.0, 0.2, "half_sine")),))
    return m.add(sc.Stage("filled", [sc.Segment("weight", 1.0), sc.Segment("water", LAM)]),
                 sc.Stage("quake", dynamics=dyn),
                 sc.Stage("after", [sc.Segment("quake", 0.0)]))


@pytest.mark.parametrize("choice", ["unchanged", "none"])
def test_after_the_earthquake_the_water_enters_at_the_start_and_the_sliding_factor_is_the_hand_one(
        choice):
    res = sc.solve_static(_staged(choice))
    assert res.status == Status.COMPLETED, res.message
    assert res.residual.max() < 1e-6 and res.violation.max() < 1e-9
    x = res.cfe["x"][:, 0]
    area = res.cfe["area"]
    dres = res.dynamics["quake"]
    assert dres.status == Status.COMPLETED
    # the interval ends with the heel open beyond the pre-earthquake crack, dry there
    end_open = dres.state[-1] == OPEN
    assert end_open[2] and not (dres.crack_pressure[-1][2:] != 0).any()
    # the static stage: the state where the interval ended, then the water of the static rule
    # at the start of the release (the automatic pattern at factor 1), before it moves
    kinds = list(res.kind)
    i_dyn = kinds.index("dynamics")
    seg = int(res.segment[i_dyn])
    assert res.segments[seg][0] == "quake: settle after dynamics"
    np.testing.assert_allclose(res.water[i_dyn], dres.water[-1], rtol=0, atol=1e-9 * _pc())
    # its crack pressures are those of the held rule, by hand: p_c in the pre-earthquake
    # crack (CFEs 0, 1) where open (1e-9 relative), 0 in every other CFE (1e-9 p_c; "none":
    # W = −A p_u there) — the opening the interval left dry included, not the static rule's
    # p_u
    held_open = (res.state[i_dyn] == OPEN) & (np.arange(len(x)) < 2)
    np.testing.assert_allclose(res.crack_pressure[i_dyn][held_open], _pc(), rtol=1e-9)
    assert res.state[i_dyn][2] == OPEN and _pu(x[2]) > 0
    np.testing.assert_allclose(res.crack_pressure[i_dyn][~held_open], 0.0, atol=1e-9 * _pc())
    at_start = [i for i in range(i_dyn + 1, len(res.lam))
                if res.segment[i] == seg and res.lam[i] == 1.0]
    assert at_start
    j = at_start[-1]  # the last state at λ = 1: the water let in, nothing released yet
    op = res.state[j] == OPEN
    wet = np.cumprod(op[np.argsort(x)]).astype(bool)[np.argsort(np.argsort(x))]
    assert wet[2]  # the water entered the opening the interval left dry
    np.testing.assert_allclose(res.water[j][wet], area[wet] * (_pc() - _pu(x[wet])),
                               rtol=1e-9, atol=1e-9 * _pc())
    np.testing.assert_allclose(res.crack_pressure[j][wet], _pc(), rtol=1e-9)
    # the post-earthquake state: the load removed, the crack back to the hand crack of a
    # rigid block, the base slid
    last = len(res.lam) - 1
    wet_end = np.flatnonzero(_watered(res, last))
    np.testing.assert_array_equal(wet_end, [0, 1])
    assert np.all(res.ut[last] > 1e-3)  # every CFE slid ≥ 1 mm
    ref = RigidBlock(res, B, H, uplift=True).solve(2, LAM)
    assert np.all(ref[2:] > 0)  # the hand crack of two CFEs: the rest compressed
    # the sliding factor by hand statics: ΣN = W − U − Σ_wet A (p_c − p_u), |ΣQ| = F_h
    weight = RHO * 9.81 * B * HEIGHT
    uplift = _pc() * B / 2
    crack = float(np.sum(area[wet_end] * (_pc() - _pu(x[wet_end]))))
    thrust = LAM * GW * H**2 / 2
    fs_hand = F * (weight - uplift - crack) / thrust
    s = res.interface_safety("base", heel=(0.0, 0.0))
    assert s.sliding_factor[last] == pytest.approx(fs_hand, rel=1e-9)


def test_an_unknown_choice_is_refused_naming_the_item():
    with pytest.raises(ModelError, match=r"dynamics\.crack_water.*'dry'"):
        sc.DynamicInterval(dt=0.01, duration=0.1, crack_water="dry")
    m = _dam()
    with pytest.raises(ModelError, match=r"crack_water.*'full', 'unchanged' or 'none'"):
        sc.solve_dynamic(m, dt=0.01, duration=0.1, loads={"quake": sc.Constant(0.1)},
                         crack_water="partial")


def test_the_model_file_gives_the_choice_and_names_a_wrong_one(tmp_path):
    """``[dynamics] crack_water`` reaches the interval; an unknown value is a problem of
    ``dynamics.crack_water``."""
    from test_dynamic_inputs import DYN_FILE

    path = tmp_path / "m.toml"
    path.write_text(DYN_FILE.replace('mass = "lumped"', 'mass = "lumped"\n'
                                     'crack_water = "unchanged"'))
    assert sc.load_model(path).dynamics.crack_water == "unchanged"
    path.write_text(DYN_FILE)
    assert sc.load_model(path).dynamics.crack_water == "full"
    path.write_text(DYN_FILE.replace('mass = "lumped"', 'mass = "lumped"\n'
                                     'crack_water = "dry"'))
    problems = sc.validate_model_file(path)
    assert any(p.item.startswith("dynamics.crack_water") and p.severity == "error"
               for p in problems), problems


def test_the_interval_of_the_model_carries_its_choice_and_an_argument_overrides_it():
    from stepcontact.solver.dynamic import dynamic_interval

    dyn = sc.DynamicInterval(dt=0.01, duration=0.1, loads=(("quake", sc.Constant(0.1)),),
                             crack_water="none")
    m = _dam().replace(dynamics=dyn)
    assert dynamic_interval(m).crack_water == "none"
    assert dynamic_interval(m, crack_water="unchanged").crack_water == "unchanged"
    # the arguments' own interval (dt, duration given): the default unless given
    assert dynamic_interval(m, dt=0.01, duration=0.1).crack_water == "full"


def test_the_schema_offers_the_model_choices():
    from stepcontact.io.modelfile import schema

    p = schema()["$defs"]["DynamicsSpec"]["properties"]["crack_water"]
    assert tuple(p["enum"]) == sc.CRACK_WATER_CHOICES == ("full", "unchanged", "none")
    assert p["default"] == "full"


def test_the_result_records_the_choice_and_the_file_keeps_it(quake, tmp_path):
    """Each run's result names the choice it was run with (the three runs of the fixture, one
    per choice, set by hand there), kept through the .nc file and shown by `stepcontact
    info`."""
    from typer.testing import CliRunner

    from stepcontact.cli import app

    _, runs = quake
    for choice, res in runs.items():
        assert res.crack_water == choice
        path = tmp_path / f"{choice}.nc"
        res.save(path)
        assert sc.load_result(path).crack_water == choice
        out = CliRunner().invoke(app, ["info", str(path)], terminal_width=400)
        assert out.exit_code == 0, out.output
        assert f"crack_water {choice}:" in " ".join(out.output.split())
