"""Impacts with restitution, the initial contact state, short steps at load breaks, and what a
dynamic result reports (impulses, extremes) — against closed forms.

* Newton's law of impact (restitution e): a point mass dropped from H onto a rigid floor
  lands at t₁ = √(2H/g) with v₁ = g t₁, leaves with e v₁ and lands again after 2 e v₁ / g:
  the landings t_k = t₁ (1 + 2e (1 + e + … + e^{k−2})) (a geometric series, the last at
  t₁ (1 + 2e/(1 − e))), the apexes H e^{2k}, each impact's impulse (1 + e) m v_k (m v₁ with
  e = 0) and its loss (1 − e²) ½ m v_k²;
* a rigid bar (m, J = m L²/12) on two corner CFEs: dropped flat, both corners close at
  once and the impulse problem gives the total (1 + e) m v; tilted, the first corner takes
  P = (1 + e) v⁻ / (1/m + (L/2)²/J);
* the initial contact state: the same problem started from a static result, from u0 equal
  to its displacement, and from both, gives the same events;
* a short step where a load jumps (a rectangular pulse ending off the step grid): the
  spring–mass closed form F/k (1 − cos ωt), F/k (cos ω(t − t_d) − cos ωt) after it, the
  integrator gaining no energy;
* the extremes of a free vibration: amplitude A at t = 0, −A at T/2, the velocity A ω.
"""

from __future__ import annotations

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.enums import Status, Transition
from stepcontact.errors import ModelError
from stepcontact.model.timefunction import Constant, Pulse
from stepcontact.solver.dynamic import DynamicResult
from stepcontact.solver.program import solve_dynamic

G = 9.81


def drop(e: float, H: float = 0.05, m_: float = 2.0, dt: float = 1e-3, duration: float = 0.5,
         f: float = 0.3):
    """A point mass (ux, uy) dropped from the height H onto a rigid floor under gravity."""
    dm = sc.DiscreteModel(K=np.zeros((2, 2)), normal_rows=[[0, 1]], tangent_rows=[[1, 0]],
                          loads={"weight": {"uy": -m_ * G}}, friction=f, gaps=H,
                          dof_names=("ux", "uy"), program=[])
    return solve_dynamic(dm, dt=dt, duration=duration, mass=np.diag([m_, m_]),
                         loads={"weight": Constant(1.0)}, restitution=e)


def landings(e: float, H: float, k: int) -> np.ndarray:
    """Times of the first k landings of a point dropped from H (Newton's law)."""
    t1 = np.sqrt(2 * H / G)
    return np.array([t1 * (1 + 2 * e * sum(e**j for j in range(i))) if i else t1
                     for i in range(k)])


def test_a_dropped_mass_rebounds_by_newtons_law():
    e, H, m_, dt = 0.8, 0.05, 2.0, 1e-3
    res = drop(e, H, m_, dt)
    assert res.status == Status.COMPLETED
    assert res.violation.max() < 1e-9
    closed = [ev for ev in res.events if ev.transition == Transition.CLOSED]
    opened = [ev for ev in res.events if ev.transition == Transition.OPENED]
    ref = landings(e, H, 4)
    got = np.array([ev.lam for ev in closed[:4]])
    # eq. (10)'s linear interpolation of the gap locates each landing to O(Δt²), and the
    # error of a flight adds up to the next: measured 1.3e-5 s at the 4th landing (Δt = 1 ms),
    # 2.5e-6 s at Δt/2
    np.testing.assert_allclose(got, ref, rtol=0, atol=2e-5)
    half = drop(e, H, m_, dt / 2)
    got2 = np.array([ev.lam for ev in half.events if ev.transition == Transition.CLOSED][:4])
    assert abs(got2[3] - ref[3]) < abs(got[3] - ref[3]) / 3  # converging (order ≥ 1.6)
    # each contact lasts an instant: it opens at its closing time
    np.testing.assert_allclose([ev.lam for ev in opened[:4]], got, rtol=0, atol=0)
    v1 = np.sqrt(2 * G * H)
    vk = v1 * e ** np.arange(4)  # approach velocities
    # the velocity after each impact: e v_k upwards (the state recorded at the impact); the
    # approach velocity is g times the located time, whose O(Δt²) errors add up: measured
    # 8.6e-5 relative at the 4th impact, 1e-4
    after = np.array([res.v[ev.state][1] for ev in closed[:4]])
    np.testing.assert_allclose(after, e * vk, rtol=1e-4)
    # the apexes H e^{2k}: the highest recorded state of each flight (sampled at the steps'
    # ends: ½ g (Δt/2)² = 1.2e-6 m below the apex at most)
    for k in range(3):
        inside = (res.time > got[k]) & (res.time < got[k + 1])
        h = (res.u[inside, 1] + H).max()
        assert h == pytest.approx(H * e ** (2 * (k + 1)), abs=2e-6)
    # impulses (1 + e) m v_k on the events and in the impulse table (N·s, compressive < 0)
    np.testing.assert_allclose([-ev.impulse_n for ev in closed[:4]], (1 + e) * m_ * vk,
                               rtol=1e-4)
    imp = res.impacts()
    np.testing.assert_allclose(-imp["normal"][:4], (1 + e) * m_ * vk, rtol=1e-4)
    assert np.all(imp["cfes"] == 1) and np.all(imp["tangential"] == 0.0)
    # the ledger: the impacts took (1 − e²) ½ m v_k²; the balance holds to round-off; the
    # integrator (cuts at the landings) neither gains energy nor takes more than 1e-3
    en = res.energy
    i4 = closed[3].state
    loss = (1 - e**2) * 0.5 * m_ * vk**2
    assert en["impact"][i4] == pytest.approx(loss.sum(), rel=1e-4)
    assert abs(en["error"]).max() < 1e-10 * en["external"].max()
    assert 0.0 <= en["numerical"][-1] < 1e-3 * en["external"][-1]


def test_the_bounces_end_at_rest_after_the_geometric_series():
    """Zeno's bounces: their total t₁ (1 + 2e/(1 − e)) is finite; a rebound whose flight
    would be shorter than Δt is not followed (the rest of the series lasts less than
    Δt / (1 − e)): the mass rests on the floor afterwards, all the work of gravity spent."""
    e, H, m_, dt = 0.8, 0.05, 2.0, 1e-3
    res = drop(e, H, m_, dt, duration=1.0)
    t_inf = np.sqrt(2 * H / G) * (1 + 2 * e / (1 - e))
    last = [ev.lam for ev in res.events if ev.transition == Transition.CLOSED][-1]
    # the bounces left out last less than Δt/(1 − e) = 5 ms; the landings' O(Δt²) errors
    # add up over the ~30 flights: measured 9.7 ms early in all
    assert t_inf - 0.015 < last <= t_inf
    after = res.time > last
    assert np.all(np.abs(res.v[after, 1]) < 1e-12)
    assert np.all(res.state[after][:, 0] != int(sc.ContactState.OPEN))
    np.testing.assert_allclose(res.u[after, 1], -H, atol=1e-12)
    en = res.energy
    assert en["impact"][-1] + en["numerical"][-1] == pytest.approx(m_ * G * H, rel=1e-9)
    assert en["numerical"][-1] >= 0.0
    # the weight at rest: N = −m g
    assert res.N[-1][0] == pytest.approx(-m_ * G, rel=1e-9)


def test_restitution_zero_lands_once_with_the_impulse_m_v():
    H, m_ = 0.05, 2.0
    res = drop(0.0, H, m_, duration=0.3)
    ev = res.events
    assert [e.transition for e in ev] == [Transition.CLOSED]
    v1 = np.sqrt(2 * G * H)
    assert ev[0].lam == pytest.approx(np.sqrt(2 * H / G), rel=2e-6)
    assert -ev[0].impulse_n == pytest.approx(m_ * v1, rel=1e-5)  # closed form m v, 1e-5
    assert res.energy["impact"][-1] == pytest.approx(0.5 * m_ * v1**2, rel=1e-5)
    assert np.all(res.u[res.time > ev[0].lam, 1] == pytest.approx(-H, abs=1e-12))


def rigid_bar(theta0: float, H: float, m_: float, L: float):
    """A rigid bar (ux, uy, rz about its centre) whose ends are CFEs over a rigid floor,
    tilted by θ₀ (small: the corners' gaps H ∓ θ₀ L/2)."""
    return sc.DiscreteModel(K=np.zeros((3, 3)), normal_rows=[[0, 1, -L / 2], [0, 1, L / 2]],
                            tangent_rows=[[1, 0, 0], [1, 0, 0]],
                            loads={"weight": {"uy": -m_ * G}}, friction=0.0,
                            gaps=[H - theta0 * L / 2, H + theta0 * L / 2],
                            dof_names=("ux", "uy", "rz"), program=[])


@pytest.mark.parametrize("theta0", [0.0, 0.01])
def test_a_bar_landing_on_two_corners_takes_newtons_impulses(theta0):
    m_, L, H, e = 3.0, 1.0, 0.02, 0.6
    J = m_ * L**2 / 12
    res = solve_dynamic(rigid_bar(theta0, H, m_, L), dt=1e-3, duration=0.08,
                        mass=np.diag([m_, m_, J]), loads={"weight": Constant(1.0)},
                        restitution=e)
    assert res.status == Status.COMPLETED
    first = res.impacts().iloc[0]
    if theta0 == 0.0:  # flat: both corners at once, the bar leaves at e v, not rotating
        v = np.sqrt(2 * G * H)
        assert first["cfes"] == 2
        # (the approach velocity at the located landing: O(Δt²), measured 1.5e-5)
        assert -first["normal"] == pytest.approx((1 + e) * m_ * v, rel=1e-4)
        i = int(first["state"])
        assert res.v[i][1] == pytest.approx(e * v, rel=1e-4)
        assert abs(res.v[i][2]) < 1e-9
    else:  # one corner: P = (1 + e) v⁻ / (1/m + (L/2)²/J)
        v = np.sqrt(2 * G * (H - theta0 * L / 2))
        assert first["cfes"] == 1
        # (measured 3.4e-5)
        assert -first["normal"] == pytest.approx((1 + e) * v / (1 / m_ + (L / 2) ** 2 / J),
                                                 rel=1e-4)
        i = int(first["state"])
        v_corner = res.v[i][1] - L / 2 * res.v[i][2]  # the landing corner leaves at e v⁻
        assert v_corner == pytest.approx(e * v, rel=1e-4)
    assert abs(res.energy["error"]).max() < 1e-10 * res.energy["external"].max()  # round-off


def test_impulses_and_extremes_round_trip_through_the_result_file(tmp_path):
    res = drop(0.8, duration=0.3)
    path = tmp_path / "drop.nc"
    res.save(path)
    back = DynamicResult.load(path)
    assert isinstance(back, DynamicResult)
    for k in ("state", "time", "cfe", "normal", "tangential"):
        np.testing.assert_array_equal(back.impulses[k], res.impulses[k])
    assert [e.impulse_n for e in back.events] == [e.impulse_n for e in res.events]
    assert back.impacts().equals(res.impacts())
    assert back.extremes().equals(res.extremes())
    assert back.extremes("u").equals(res.extremes("u"))


def test_a_static_result_file_without_impulse_columns_still_loads(tmp_path):
    """Files written before the impulse columns existed load with impulses 0."""
    res = drop(0.0, duration=0.15)
    ds = res.to_dataset().drop_vars(["event_impulse_n", "event_impulse_t"])
    from stepcontact.results.result import dataset_to_result

    back = dataset_to_result(ds.load())
    assert [e.impulse_n for e in back.events] == [0.0] * len(res.events)


def sdof(k: float = 1e4, m_: float = 1.0):
    """A spring–mass in x (and in y, unloaded) with a CFE far away (never closes)."""
    dm = sc.DiscreteModel(K=[[k, 0.0], [0.0, k]], normal_rows=[[0, 1]], tangent_rows=[[1, 0]],
                          loads={"push": {"ux": 1.0}}, friction=0.0, gaps=1.0,
                          dof_names=("ux", "uy"), program=[])
    return dm, np.diag([m_, m_]), np.sqrt(k / m_)


def test_extremes_of_a_free_vibration_are_the_closed_form_amplitude_and_times():
    dm, M, w = sdof()
    T, A = 2 * np.pi / w, 1e-3
    dt = T / 400
    res = solve_dynamic(dm, dt=dt, duration=T, mass=M, u0=np.array([A, 0.0]))
    ex = res.extremes("u")
    # Newmark's average acceleration conserves the amplitude; its period is longer by
    # (ω Δt)²/12 = 2e-5; the steps sample the extremes within (ω Δt/2)²/2 = 3e-5 of A
    assert ex.loc[0, "max"] == pytest.approx(A, rel=1e-12) and ex.loc[0, "max_at"] == 0.0
    assert ex.loc[0, "min"] == pytest.approx(-A, rel=5e-5)
    assert ex.loc[0, "min_at"] == pytest.approx(T / 2, abs=dt)
    vx = res.extremes("v").loc[0]
    assert vx["min"] == pytest.approx(-A * w, rel=5e-5)
    assert vx["min_at"] == pytest.approx(T / 4, abs=dt)
    assert vx["max_at"] == pytest.approx(3 * T / 4, abs=dt)
    summary = res.extremes()
    assert summary.loc["u", "absmax"] == pytest.approx(A, rel=1e-12)
    assert summary.loc["u", "index"] == 0 and summary.loc["u", "at"] == 0.0
    assert summary.loc["a", "absmax"] == pytest.approx(A * w**2, rel=5e-5)
    # the nodal and CFE quantities of history() too (ux of DOF 0: the CFE's ut here)
    assert res.extremes("ut").loc[0, "absmax"] == pytest.approx(A, rel=1e-12)
    with pytest.raises(ValueError, match="quantity"):
        res.extremes("nonsense")


@pytest.mark.parametrize("start", [0.0, 0.37])
def test_a_rectangular_pulse_off_the_step_grid_follows_the_closed_form(start):
    """F₀ from t_s for t_d (ends between the steps' ends: the step lands there): the
    closed form, second order in Δt (Newmark's period error dominates: (ωΔt)²/12 per radian),
    and no step gains energy (the ledger's numerical never decreases)."""
    dm, M, w = sdof()
    T, F0, k = 2 * np.pi / w, 100.0, 1e4
    ts, td = start * T / 100, 0.3137 * T
    errs = []
    for div in (100, 200):
        dt = T / div
        res = solve_dynamic(dm, dt=dt, duration=1.5 * T, mass=M,
                            loads={"push": Pulse(F0, ts, td, "rectangular")})
        t = res.time - ts
        ref = np.where(t < 0, 0.0, np.where(t < td, F0 / k * (1 - np.cos(w * t)),
                                            F0 / k * (np.cos(w * (t - td)) - np.cos(w * t))))
        errs.append(np.abs(res.u[:, 0] - ref).max() / (F0 / k))
        en = res.energy
        assert np.diff(en["numerical"]).min() >= -1e-12 * en["external"].max()
        assert abs(en["error"]).max() < 1e-10 * en["external"].max()
        # the pulse's edges are states of the result
        for edge in (ts, ts + td):
            assert np.min(np.abs(res.time - edge)) < 1e-12
    assert errs[0] < 6e-3  # measured 5.1e-3 at T/100
    assert errs[0] / errs[1] == pytest.approx(4.0, rel=0.1)  # second order


def test_crack_water_and_a_pulse_end_gain_no_energy_in_short_steps():
    """The dam of test_crack_water with a crack at the heel and a pulse of crack pressure
    (the water entering and leaving CFEs, the pulse ending between steps, the interval's end
    between steps): the integrator's share never grows the energy (increments of
    ``numerical`` ≥ −1e-9 of the work; the stretched short step gained 130 J of 1.2 kJ)."""
    from test_crack_water import dam_model

    base = dam_model(lam_end=1.5, nx=8, E=30e9)
    itf = [i for i in base.interfaces if i.name == "base"][0]
    model = base.replace(patterns=(*base.patterns, sc.LoadPattern(
        "joint", [sc.CrackWater(itf, pressure=1.0, entry=(0.0, 0.0))])))
    st = sc.solve_static(model)
    res = sc.solve_dynamic(model, dt=0.005, duration=0.2987,
                           loads={"joint": Pulse(60e3, 0.02, 0.1997, "half_sine")}, initial=st)
    assert res.status == Status.COMPLETED
    en = res.energy
    scale = np.abs(en["external"]).max()
    assert np.diff(en["numerical"]).min() >= -1e-9 * scale
    assert abs(en["error"]).max() < 1e-8 * scale
    assert res.time[-1] == pytest.approx(0.2987, abs=1e-12)


@pytest.fixture(scope="module")
def block():
    """An elastic block on an elastic base (mortar CFEs, rigid contact, f = 0.5) at rest
    under its weight (the static result), and a half-sine push that makes it slide."""
    from verification_models import block_on_base

    m = block_on_base(friction=0.5, nx=4, ny=2)
    W = m.bodies[1].material.density * G * 2.0 * 0.5
    m = m.add(sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
              sc.LoadPattern("push", [sc.EdgeForce(m.select("block", y=0.5), fx=1.0)]),
              sc.Segment("weight", 1.0))
    return m, sc.solve_static(m), Pulse(0.8 * W, 0.05, 0.1, "half_sine")


def test_the_initial_state_from_a_static_result_from_u0_or_both_gives_one_answer(block):
    m, st, pulse = block
    u_st = st.displacement(len(st.lam) - 1)
    kw = dict(dt=1 / 400, duration=0.2, mass="lumped")
    ra = solve_dynamic(m, initial=st, loads={"push": pulse}, **kw)
    rb = solve_dynamic(m, u0=u_st, loads={"weight": Constant(1.0), "push": pulse}, **kw)
    rc = solve_dynamic(m, initial=st, u0=u_st, loads={"push": pulse}, **kw)
    assert ra.status == Status.COMPLETED
    assert any(e.transition == Transition.SLIP_POS for e in ra.events)
    scale = np.abs(ra.u).max()
    for r in (rb, rc):
        assert r.status == Status.COMPLETED
        # the same events at the same times (1e-9 relative; measured 3e-15)
        assert [(e.cfe, e.transition) for e in r.events] == [(e.cfe, e.transition)
                                                            for e in ra.events]
        np.testing.assert_allclose([e.lam for e in r.events], [e.lam for e in ra.events],
                                   rtol=1e-9)
        np.testing.assert_allclose(r.u, ra.u, atol=1e-9 * scale)
        # at t = 0: the static contact state and forces, no event (no chatter)
        np.testing.assert_array_equal(r.state[0], st.state[-1])
        np.testing.assert_allclose(r.N[0], st.N[-1], atol=1e-9 * np.abs(st.N[-1]).max())
        assert min(e.lam for e in r.events) > 0.05  # nothing before the push starts


def test_u0_that_is_not_the_static_results_or_penetrates_is_refused(block):
    m, st, pulse = block
    u = st.displacement(len(st.lam) - 1).copy()
    sysm = sc.assemble(m)
    body = next(b for b in m.bodies if b.name == "block")
    off = m.node_offsets["block"]
    ydofs = sysm.dofs.of[off:off + body.n_nodes, 1]  # the block's vertical DOFs
    u_up = u.copy()
    u_up[ydofs] += 1e-3  # lifted by 1 mm: the static result's closed CFEs open
    with pytest.raises(ModelError, match="u0.*not the displacement of `initial`"):
        solve_dynamic(m, initial=st, u0=u_up, dt=1e-3, duration=1e-3, mass="lumped")
    u_down = u.copy()
    u_down[ydofs] -= 1e-3
    with pytest.raises(ModelError, match="u0.*penetrate"):
        solve_dynamic(m, u0=u_down, dt=1e-3, duration=1e-3, mass="lumped")


def test_the_events_table_shows_the_impulse_of_an_impact():
    """The CLI's events table of a dynamic result (run prints it after the interval) has the
    time axis and, where impacts happened, their impulses in kN·s: a 2 000 kg mass dropped
    0.05 m with e = 0 lands with the impulse m v = 2000 √(2 g H) = 1.981 kN·s (closed form,
    to the 4 digits shown)."""
    from rich.console import Console

    from stepcontact.cli.commands import events_table

    H, m_ = 0.05, 2000.0
    res = drop(0.0, H, m_, duration=0.2)
    con = Console(record=True, width=200)
    con.print(events_table(res), crop=False)
    text = con.export_text()
    assert "t (s)" in text and "impulse N (kN·s)" in text
    assert f"{-m_ * np.sqrt(2 * G * H) / 1e3:.4g}" in text  # compressive: negative
    assert text.count("closed") == 1
