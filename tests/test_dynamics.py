"""Dynamics (Newmark between events, events located in time, impacts, the energy ledger)
against closed forms.

* a rigid block on a rough floor under a rectangular pulse: slip distance and stop time of a
  rigid body (½ a₁ t_p² + (a₁ t_p)² / (2 f g), a₁ = (P − f W)/m);
* an elastic bar striking a rigid wall (plane strain, ν = 0, L = 0.2 m, E = 2e11 Pa,
  ρ = 8000 kg/m³, gap 2 mm, v₀ = 100 m/s): contact at 2e-5 s for 2L/c = 8e-5 s, stress ρ c v₀,
  rebound at −v₀;
* event times that converge as Δt is halved;
* a static load applied slowly through the dynamic solver: the static event load factor;
* the energy ledger balances to round-off.
"""

from __future__ import annotations

import numpy as np
import pytest

import stepcontact as sc
from model_toml import block_on_floor
from stepcontact.enums import Status, Transition
from stepcontact.errors import ModelError
from stepcontact.model.timefunction import Harmonic, Pulse, Tabulated
from stepcontact.solver.program import solve_dynamic

G = 9.81


def floor_block(mass=1000.0, f=0.3, k=0.0):
    """A rigid body (DOFs ux, uy) on a rough floor, optionally held by a spring k in x."""
    W = mass * G
    dm = sc.DiscreteModel(K=[[k, 0.0], [0.0, 0.0]], normal_rows=[[0, 1]],
                          tangent_rows=[[1, 0]],
                          loads={"weight": {"uy": -W}, "push": {"ux": 1.0}}, friction=f,
                          dof_names=("ux", "uy"), program=[sc.Segment("weight", 1.0)])
    return dm, sc.solve_static(dm), np.diag([mass, mass])


def test_rigid_block_under_a_pulse_slides_the_closed_form_distance():
    m_, f, tp = 1000.0, 0.3, 0.2
    dm, st, M = floor_block(m_, f)
    W = m_ * G
    P = 2 * f * W
    dt = 1e-3
    res = solve_dynamic(dm, dt=dt, duration=0.6, loads={"push": Pulse(P, 0.0, tp,
                                                                        "rectangular")},
                        mass=M, initial=st)
    assert res.status == Status.COMPLETED
    assert res.violation.max() < 1e-9  # the contact conditions at every reported state
    a1 = (P - f * W) / m_
    v1 = a1 * tp
    slip = 0.5 * a1 * tp**2 + v1**2 / (2 * f * G)
    # Newmark's trapezoidal rule ends a rectangular pulse half a step early: O(Δt / t_p)
    assert res.u[-1][0] == pytest.approx(slip, rel=1e-3)
    ev = [(e.lam, e.transition) for e in res.events]
    assert ev[0][1] == Transition.SLIP_POS and ev[0][0] < dt
    assert ev[-1][1] == Transition.STUCK
    assert abs(ev[-1][0] - (tp + v1 / (f * G))) <= dt
    # at rest afterwards, friction below its limit
    assert abs(res.v[-1][0]) < 1e-9 and abs(res.Q[-1][0]) <= f * W * (1 + 1e-12)
    # energy: the work of the pulse went into friction
    e = res.energy
    assert e["friction"][-1] == pytest.approx(e["external"][-1], rel=1e-9)
    assert abs(e["error"]).max() < 1e-9 * e["external"][-1]


@pytest.fixture(scope="module")
def bar():
    L, E, rho, v0, gap = 0.2, 2e11, 8000.0, 100.0, 2e-3
    ne = 40
    body = sc.rectangle("bar", (0, 0), (L, 0.005), ne, 1, sc.Material(E=E, nu=0.0,
                                                                     density=rho))
    m = sc.Model(bodies=[body])
    wall = sc.RigidObstacle("wall", [(L + gap, -1.0), (L + gap, 1.0)])
    m = m.add(sc.Interface("end", plus=m.select("bar", x=L), minus=wall, friction=0.0))
    sysm = sc.assemble(m)
    v = np.zeros(sysm.ndof)
    v[sysm.dofs.of[: body.n_nodes, 0]] = v0
    c = np.sqrt(E / rho)
    return sysm, v, dict(L=L, rho=rho, v0=v0, gap=gap, c=c, dt=L / ne / c, A=0.005,
                         xdofs=sysm.dofs.of[: body.n_nodes, 0])


@pytest.mark.parametrize("mass", ["consistent", "lumped"])
def test_bar_striking_a_rigid_wall(bar, mass):
    sysm, v, p = bar
    res = solve_dynamic(sysm, dt=p["dt"], duration=2e-4, v0=v, mass=mass)
    assert res.status == Status.COMPLETED
    assert res.violation.max() < 1e-9  # the contact conditions at every reported state
    closed = [e.lam for e in res.events if e.transition == Transition.CLOSED]
    opened = [e.lam for e in res.events if e.transition == Transition.OPENED]
    t_hit = p["gap"] / p["v0"]
    assert closed[0] == pytest.approx(t_hit, rel=1e-9)
    duration = 2 * p["L"] / p["c"]
    assert opened[0] - closed[0] == pytest.approx(duration, rel=0.02)
    assert len(closed) == 2 and len(opened) == 2  # both end nodes, once each: no chatter
    # contact stress ρ c v₀ (median over the contact: Newmark's force oscillates about it)
    sig = -res.N.sum(axis=1) / p["A"]
    during = (res.time > closed[0] + 0.05 * duration) & (res.time < opened[0] - 0.05 * duration)
    assert np.median(sig[during]) == pytest.approx(p["rho"] * p["c"] * p["v0"], rel=0.02)
    # rebound: the mean velocity −v₀ within 4 %
    assert res.v[-1][p["xdofs"]].mean() == pytest.approx(-p["v0"], rel=0.04)
    e = res.energy
    e0 = e["kinetic"][0]
    assert abs(e["error"]).max() < 1e-9 * e0
    assert 0 <= e["impact"][-1] < 0.02 * e0  # what the impact and the constraint dissipate


def test_event_times_converge_as_the_step_is_halved(bar):
    sysm, v, p = bar
    t_open = []
    for k in (1, 2, 4):
        res = solve_dynamic(sysm, dt=p["dt"] / k, duration=1.2e-4, v0=v, mass="lumped")
        t_open.append([e.lam for e in res.events if e.transition == Transition.OPENED][0])
    d1, d2 = abs(t_open[0] - t_open[1]), abs(t_open[1] - t_open[2])
    assert d1 < 0.5 * p["dt"]  # far less than the step
    assert d2 < 0.6 * d1  # and converging (order ≥ ~0.7 here; the wave front is sharp)


def test_slow_loading_through_the_dynamic_solver_gives_the_static_event():
    """A spring-held block on a rough floor, pushed by a force growing slowly (a ramp over
    many natural periods, with damping): it starts to slip at the static load factor."""
    k, m_, f = 1e5, 10.0, 0.4
    dm = sc.DiscreteModel(K=[[k, 0.0], [0.0, 1e5]], normal_rows=[[0, 1]],
                          tangent_rows=[[1, 0]],
                          loads={"weight": {"uy": -m_ * G}, "push": {"ux": 1.0},
                                 "lift": {"uy": 1.0}},
                          friction=f, dof_names=("ux", "uy"),
                          program=[sc.Segment("weight", 1.0), sc.Segment("lift", 200.0)])
    st = sc.solve_static(dm)
    lam_open = st.multipliers[1].first_opening
    assert lam_open == pytest.approx(m_ * G, rel=1e-12)
    st0 = sc.solve_static(dm.replace(program=(sc.Segment("weight", 1.0),)))
    T = 2 * np.pi * np.sqrt(m_ / 1e5)
    ramp = Tabulated((0.0, 100 * T), (0.0, 200.0))
    res = solve_dynamic(dm, dt=T / 50, duration=100 * T, loads={"lift": ramp},
                        mass=np.diag([m_, m_]), initial=st0,
                        damping=(2 * 0.2 * 2 * np.pi / T, 0.0))
    t_open = [e.lam for e in res.events if e.transition == Transition.OPENED][0]
    assert ramp(t_open) == pytest.approx(lam_open, rel=2e-3)


def test_bad_dynamic_inputs():
    dm, st, M = floor_block()
    with pytest.raises(ModelError, match="dt"):
        solve_dynamic(dm, dt=0.0, duration=1.0, mass=M)
    with pytest.raises(ModelError, match="nope"):
        solve_dynamic(dm, dt=0.1, duration=1.0, mass=M, loads={"nope": Harmonic()})
    with pytest.raises(ModelError, match="mass matrix"):
        solve_dynamic(dm, dt=0.1, duration=1.0)
    with pytest.raises(ModelError, match="restitution"):
        solve_dynamic(dm, dt=0.1, duration=1.0, mass=M, restitution=2.0)
    with pytest.raises(ModelError, match="pulse.shape"):
        Pulse(1.0, 0.0, 1.0, "square")
    with pytest.raises(ModelError, match="increase"):
        Tabulated((0.0, 1.0, 0.5), (0.0, 1.0, 2.0))


@pytest.mark.parametrize("r", [1.5, 2.0, 3.0])
def test_forced_stick_slip_amplitude_of_den_hartog(r):
    """Den Hartog (1931): m ẍ + k x ± μN = F₀ cos ωt without stops has the steady amplitude
    X/(F₀/k) = sqrt(1/(1 − r²)² − (μN/F₀ · U)²), U = sin(π/r) / (r (1 + cos(π/r)))."""
    k, m_, N, F0, mu = 1e4, 1.0, 100.0, 100.0, 0.3
    dm = sc.DiscreteModel(K=[[k, 0.0], [0.0, 0.0]], normal_rows=[[0, 1]],
                          tangent_rows=[[1, 0]], loads={"weight": {"uy": -N},
                                                        "force": {"ux": 1.0}},
                          friction=mu, dof_names=("ux", "uy"),
                          program=[sc.Segment("weight", 1.0)])
    st = sc.solve_static(dm)
    w = r * np.sqrt(k / m_)
    T = 2 * np.pi / w
    res = solve_dynamic(dm, dt=T / 100, duration=30 * T, mass=np.diag([m_, m_]), initial=st,
                        loads={"force": Harmonic(F0, w / (2 * np.pi), np.pi / 2)})
    assert res.status == Status.COMPLETED
    assert res.violation.max() < 1e-9  # the contact conditions at every reported state
    late = res.time > 20 * T
    x = res.u[late, 0]
    amp = 0.5 * (x.max() - x.min()) / (F0 / k)
    U = np.sin(np.pi / r) / (r * (1 + np.cos(np.pi / r)))
    ref = np.sqrt(1 / (1 - r**2) ** 2 - (mu * N / F0 * U) ** 2)
    assert amp == pytest.approx(ref, rel=0.01)
    # no stops: every reversal is a stick and a slip the other way at the same time
    ev = [e for e in res.events if e.lam > 20 * T]
    stuck = [e.lam for e in ev if e.transition == Transition.STUCK]
    slips = [e.lam for e in ev if e.transition in (Transition.SLIP_POS, Transition.SLIP_NEG)]
    assert len(stuck) >= 18 and np.allclose(stuck, slips[: len(stuck)], rtol=0, atol=1e-12)
    assert abs(res.energy["error"]).max() < 1e-9 * res.energy["external"][-1]


def test_a_dynamic_result_round_trips_through_the_result_file(tmp_path):
    dm, st, M = floor_block()
    res = solve_dynamic(dm, dt=1e-2, duration=0.3, mass=M, initial=st,
                        loads={"push": Pulse(2 * 0.3 * 1000 * G, 0.0, 0.1, "rectangular")})
    res.save(tmp_path / "dyn.nc")
    back = sc.load_result(tmp_path / "dyn.nc")
    assert isinstance(back, sc.DynamicResult) and back.dt == res.dt
    np.testing.assert_array_equal(back.time, res.time)
    for key in ("u", "v", "a"):
        np.testing.assert_array_equal(getattr(back, key), getattr(res, key))
    for key, vals in res.energy.items():
        np.testing.assert_array_equal(back.energy[key], vals)
    assert [e.transition for e in back.events] == [e.transition for e in res.events]


DYN_FILE = block_on_floor("dyn-block", 0.5, layer="{ kn = 1e10, kt = 1e10 }") + """
[node_sets.top]
body = "block"
y = 0.5

[patterns.push]
loads = [{ type = "edge_force", nodes = "top", fx = 2e4 }]

[dynamics]
dt = 1e-3
duration = 0.1
mass = "lumped"
damping = { ratios = [0.05, 0.05], frequencies = [10.0, 200.0] }

[[dynamics.loads]]
pattern = "push"
type = "pulse"
amplitude = 1.0
duration = 0.05
shape = "half_sine"
"""


def test_model_file_dynamic_interval_runs_from_the_command_line(tmp_path):
    from typer.testing import CliRunner

    from stepcontact.cli.commands import app
    from stepcontact.io.modelfile import load_model

    f = tmp_path / "dyn.toml"
    f.write_text(DYN_FILE)
    m = load_model(f)
    assert m.dynamics is not None and m.dynamics.mass == "lumped"
    a0, a1 = m.dynamics.damping
    for zeta, fr in ((0.05, 10.0), (0.05, 200.0)):
        w = 2 * np.pi * fr
        assert a0 / (2 * w) + a1 * w / 2 == pytest.approx(zeta, rel=1e-12)
    out = CliRunner().invoke(app, ["run", str(f), "--no-plot", "--quiet"])
    assert out.exit_code == 0, out.output
    assert "dynamics:" in out.output
    back = sc.load_result(tmp_path / "dyn-dynamic.nc")
    assert isinstance(back, sc.DynamicResult)
    assert back.time[-1] == pytest.approx(0.1, rel=1e-9)
    assert abs(back.energy["error"]).max() < 1e-6 * back.energy["external"].max()
    # a bad entry names its item
    bad = DYN_FILE.replace('pattern = "push"\ntype', 'pattern = "nope"\ntype')
    f.write_text(bad)
    out = CliRunner().invoke(app, ["run", str(f), "--no-plot", "--quiet"])
    assert out.exit_code == 2
    assert "dynamics.loads[0].pattern" in out.output and "nope" in out.output


def test_dynamic_results_export_to_paraview_with_their_time(bar, tmp_path):
    sysm, v, p = bar
    res = solve_dynamic(sysm, dt=2 * p["dt"], duration=1.2e-4, v0=v, mass="lumped")
    sc.export_vtu(res, tmp_path / "bar")
    pvd = (tmp_path / "bar" / "result.pvd").read_text()
    assert "time of the dynamic analysis" in pvd
    steps = [float(x) for x in __import__("re").findall(r'timestep="([^"]+)"', pvd)]
    np.testing.assert_allclose(steps, res.time, rtol=0, atol=1e-15)
    # a loaded dynamic result recovers its stresses from the stored displacements
    res.save(tmp_path / "bar.nc")
    back = sc.load_result(tmp_path / "bar.nc")
    back.recover_fields(sysm)
    i = int(np.argmax(-res.N.sum(axis=1)))
    np.testing.assert_allclose(back.stresses_at([i])[i]["bar"], res.stresses_at([i])[i]["bar"],
                               rtol=1e-12)


@pytest.mark.parametrize("alpha", [0.0, 0.1, 0.3])
def test_hht_alpha_matches_its_recurrence_and_damps_the_high_modes(alpha):
    """A spring-mass sliding freely (frictionless contact) with ω Δt = 10: the displacements
    equal the HHT-α recurrence written out here, and over 200 steps the amplitude decays at
    the spectral radius of its amplification matrix ((1 − α)/(1 + α) as ω Δt → ∞)."""
    k, m_ = 1e6, 1.0
    dm = sc.DiscreteModel(K=[[k, 0.0], [0.0, 0.0]], normal_rows=[[0, 1]],
                          tangent_rows=[[1, 0]], loads={"weight": {"uy": -10.0}},
                          friction=0.0, dof_names=("ux", "uy"),
                          program=[sc.Segment("weight", 1.0)])
    st = sc.solve_static(dm)
    dt = 10.0 / np.sqrt(k / m_)
    res = solve_dynamic(dm, dt=dt, duration=200 * dt, mass=np.diag([m_, m_]), initial=st,
                        u0=np.array([1e-3, 0.0]), alpha=alpha)
    b, g = (1 + alpha) ** 2 / 4, 0.5 + alpha
    u, v, a = 1e-3, 0.0, -k * 1e-3 / m_
    ref = [u]
    A = np.zeros((3, 3))  # amplification matrix of (u, v, a)
    for j in range(3):
        x = np.eye(3)[j]
        a1 = (-(1 - alpha) * k * (x[0] + dt * x[1] + dt * dt * (0.5 - b) * x[2])
              - alpha * k * x[0]) / (m_ + (1 - alpha) * k * b * dt * dt)
        A[:, j] = [x[0] + dt * x[1] + dt * dt * ((0.5 - b) * x[2] + b * a1),
                   x[1] + dt * ((1 - g) * x[2] + g * a1), a1]
    state = np.array([u, v, a])
    for _ in range(200):
        state = A @ state
        ref.append(state[0])
    np.testing.assert_allclose(res.u[:, 0], ref, rtol=1e-9, atol=1e-12 * 1e-3)
    rho = max(abs(np.linalg.eigvals(A)))
    early, late = np.abs(res.u[1:21, 0]).max(), np.abs(res.u[181:201, 0]).max()
    assert late / early == pytest.approx(rho**180, rel=0.05)
    if alpha == 0:
        assert rho == pytest.approx(1.0, abs=1e-12)
    else:
        assert rho < 1.0


@pytest.mark.parametrize("vx", [0.5, 0.1])
def test_an_impact_with_friction_takes_at_most_f_times_the_normal_impulse(vx):
    """A point falling at 1 m/s onto a floor (f = 0.3) while moving at v_x: the landing
    stops the fall; friction's impulse takes min(v_x, f·1 m/s) off v_x — it slides on at
    v_x − 0.3 (v_x = 0.5) or sticks (v_x = 0.1)."""
    m_, f = 2.0, 0.3
    dm = sc.DiscreteModel(K=[[0.0, 0.0], [0.0, 0.0]], normal_rows=[[0, 1]],
                          tangent_rows=[[1, 0]], loads={"push": {"ux": 1.0}}, friction=f,
                          gaps=0.01, dof_names=("ux", "uy"), program=[])
    dt = 1e-4
    res = solve_dynamic(dm, dt=dt, duration=0.0125, mass=np.diag([m_, m_]),
                        v0=np.array([vx, -1.0]))
    closed = [e for e in res.events if e.transition != Transition.OPENED]
    assert closed[0].lam == pytest.approx(0.01, rel=1e-9)  # no gravity: the gap / 1 m/s
    i = int(np.searchsorted(res.time, closed[0].lam))
    after = res.v[i]
    assert after[1] == pytest.approx(0.0, abs=1e-12)
    assert after[0] == pytest.approx(max(vx - f * 1.0, 0.0), abs=1e-9)
    assert closed[0].transition == (Transition.SLIP_POS if vx > f else Transition.CLOSED)


def test_slow_push_on_an_elastic_block_slips_at_the_static_load_factor():
    """An elastic block on an elastic base (mortar CFEs, rigid contact, f = 0.5), its weight,
    then a push on its top ramped over 1 s (slow against its periods, light damping): the
    dynamic run's first slip happens at the static run's load factor (1e-6)."""
    from verification_models import block_on_base

    m = block_on_base(friction=0.5, nx=4, ny=2)
    W = m.bodies[1].material.density * G * 2.0 * 0.5
    m = m.add(sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
              sc.LoadPattern("push", [sc.EdgeForce(m.select("block", y=0.5), fx=1.0)]),
              sc.Segment("weight", 1.0), sc.Segment("push", 0.8 * W))
    lam_slip = sc.solve_static(m).multipliers[1].first_slip
    rest = sc.solve_static(m.replace(program=(sc.Segment("weight", 1.0),)))
    ramp = Tabulated((0.0, 1.0), (0.0, 0.8 * W))
    res = solve_dynamic(m, dt=1 / 400, duration=1.0, initial=rest, mass="lumped",
                        damping=(0.0, 2 * 0.05 / (2 * np.pi * 50)), loads={"push": ramp})
    assert res.violation.max() < 1e-9
    t_slip = next(e.lam for e in res.events
                  if e.transition in (Transition.SLIP_POS, Transition.SLIP_NEG))
    assert ramp(t_slip) == pytest.approx(lam_slip, rel=1e-6)
    e = res.energy
    assert abs(e["error"]).max() < 1e-9 * e["external"].max()
    # Newmark's whole steps conserve energy; the last step lands on the end (events shifted
    # the grid) as a cut of a whole step, its interpolation dissipative: measured 7e-6 of
    # the work
    assert abs(e["numerical"][-1]) < 2e-5 * e["external"].max()


@pytest.mark.parametrize("direction", [None, (1.0, 1.0)])
def test_spring_dashpots_damp_free_vibration_by_the_closed_form(direction):
    """A very stiff 1 m × 1 m block (2400 kg) on springs to the ground at its four corners,
    each k and a dashpot c, moving off at v₀ along x: u(t) = v₀/ω_d e^(−ζω t) sin ω_d t with
    ω² = 4k/m, ζ = 4c/(2 m ω) — the dashpots are in the damping matrix (1e-3 of the peak;
    with an inclined axis d = (1, 1)/√2 the x motion sees k/2, c/2 per corner and couples
    with y: started along d instead, it stays along d)."""
    mat = sc.Material(E=1e13, nu=0.0, density=2400.0)
    m = sc.Model(bodies=[sc.rectangle("b", (0, 0), (1, 1), 1, 1, mat)], plane="stress",
                 thickness=1.0)
    k, c = 1e6, 4e3
    corners = m.select("b")
    m = m.add(sc.Spring("s", corners, kx=0.0 if direction else k, ky=0.0 if direction else k,
                        k=k if direction else 0.0, direction=direction, damping=c))
    mass = 2400.0
    omega = np.sqrt(4 * k / mass)
    zeta = 4 * c / (2 * mass * omega)
    wd = omega * np.sqrt(1 - zeta**2)
    d = np.array([1.0, 0.0]) if direction is None else np.array([1.0, 1.0]) / np.sqrt(2)
    v0 = np.tile(d, 4) * 0.1
    dt = 2 * np.pi / omega / 400
    res = solve_dynamic(m, dt=dt, duration=2 * np.pi / omega * 1.5, mass="lumped", v0=v0)
    t = res.time
    exact = 0.1 / wd * np.exp(-zeta * omega * t) * np.sin(wd * t)
    along = res.u[:, 0::2].mean(axis=1) * d[0] + res.u[:, 1::2].mean(axis=1) * d[1]
    peak = 0.1 / omega
    assert np.abs(along - exact).max() < 1e-3 * peak
    assert zeta > 0.05  # the damping is felt: an undamped oscillation differs by far more
    across = res.u[:, 0::2].mean(axis=1) * d[1] - res.u[:, 1::2].mean(axis=1) * d[0]
    assert np.abs(across).max() < 1e-8 * peak  # round-off of 600 steps
    e = res.energy
    assert e["damping"][-1] == pytest.approx(0.5 * 4 * mass / 4 * 0.01 - e["kinetic"][-1]
                                             - e["strain"][-1], rel=1e-6)


def test_contact_stresses_of_a_dynamic_result_at_chosen_times(bar, tmp_path):
    """The contact stress diagrams at chosen instants (Python and ``stepcontact plot
    --time``): during the bar's contact the drawn σ_n is the wall's −ρ c v₀ (median within
    2 %), between two recorded steps it is their linear interpolation in time; --lam on a
    result in time, and --time on a static one, are refused with a message."""
    from typer.testing import CliRunner

    from stepcontact.cli.commands import app

    sysm, v, p = bar
    res = solve_dynamic(sysm, dt=p["dt"], duration=1.2e-4, v0=v, mass="lumped")
    t_mid = 2e-5 + 0.5 * 2 * p["L"] / p["c"]  # half-way through the contact
    fig = sc.plot_interfaces(res, [t_mid], path=tmp_path / "s.png")
    assert "t = " in fig._suptitle.get_text() and "λ" not in fig._suptitle.get_text()
    line = fig.axes[0].get_lines()[0]
    sigma = np.asarray(line.get_ydata(), float)  # in the axis' unit: GPa, MPa, kPa or Pa
    unit = fig.axes[0].get_ylabel().split(",")[-1].split("(")[0].strip()
    scale = {"GPa": 1e9, "MPa": 1e6, "kPa": 1e3, "Pa": 1.0}[unit]
    assert np.median(sigma) * scale == pytest.approx(-p["rho"] * p["c"] * p["v0"], rel=0.02)
    i = int(np.searchsorted(res.time, t_mid))
    w = (t_mid - res.time[i - 1]) / (res.time[i] - res.time[i - 1])
    N = (1 - w) * res.N[i - 1] + w * res.N[i]
    np.testing.assert_allclose(sigma * scale, N / res.cfe["area"], rtol=1e-9)  # N < 0: press
    res.save(tmp_path / "bar.nc")
    run = CliRunner().invoke
    out = run(app, ["plot", str(tmp_path / "bar.nc"), "--time", "3e-5", "--time", "6e-5",
                    "-o", str(tmp_path / "t.png")])
    assert out.exit_code == 0 and (tmp_path / "t.png").stat().st_size > 0, out.output
    out = run(app, ["plot", str(tmp_path / "bar.nc"), "--kind", "energy",
                    "-o", str(tmp_path / "e.png")])
    assert out.exit_code == 0 and (tmp_path / "e.png").stat().st_size > 0, out.output
    out = run(app, ["plot", str(tmp_path / "bar.nc"), "--lam", "1"])
    assert out.exit_code != 0 and "--time" in out.output
    dm, st, _ = floor_block()
    st.save(tmp_path / "static.nc")
    out = run(app, ["plot", str(tmp_path / "static.nc"), "--time", "1"])
    assert out.exit_code != 0 and "--lam" in out.output
