"""3D dynamics (issue 28 §3, §5): the dynamic driver (Newmark/HHT-α, events located in time,
impacts, the energy ledger) runs 3D models — discrete models with two tangential directions
per CFE and continua on a rigid plane — through the same core, on the faceted Coulomb cone.

Closed forms (independent of the code) and tolerances, per test:

* the rigid block on the polygon of k facets (vertices on the circle f W, facet normals d_i at
  θ₀ + (2i + 1) π/k): pushed along θ by P > the polygon's limit f W cos(π/k) / cos(θ − θ_f)
  (θ_f the nearest facet normal), a block with one CFE slides by the polygon's normality rule
  — on facet f (|P sin(θ − θ_f)| ≤ f W sin(π/k)) along d_f with
  m a = P cos(θ − θ_f) − f W cos(π/k), the friction force on the facet balancing the rest of P;
  at a vertex (θ = its direction, between two facets) along θ with m a = P − f W.  After a
  rectangular pulse of length t_p it decelerates at the same friction (f g cos(π/k), f g) and
  stops at t_p + a t_p / a_d, having slid ½ a t_p² + (a t_p)² / (2 a_d).  Newmark's average
  acceleration is exact for piecewise-constant accelerations and the stop lies where the slip
  velocity (linear in time) vanishes: events and forces to 1e-9; the slide to the chord's
  bound a_d Δt² / 8 (the state at a stop inside a step is eq. (10)'s linear interpolation
  between the step's ends, the parabola's chord; exact where the stop ends a step);
* an elastic block (hex8, 2 × 2 × 1 cells, 9 CFEs) under a half-sine pulse against the same
  rigid-block closed form (its start t_s = t_p/π asin(μ W / P₀), slide of the rigid block):
  the slide to 1e-3 relative (measured 6.6e-5 and 1.9e-4: the block's elastic modes and the
  corner CFEs that start and stop slipping before the others), the last stop to 2 ms
  (measured 0.5 ms);
* the energy ledger: the balance error (kinetic + strain − initial − work of the loads +
  dissipations) within 1e-9 of the loads' work at every recorded state;
* impacts (Newton's law, Coulomb's impulse |T| ≤ f P on the cone): the normal velocity after
  is −e times the one before, the tangential impulse f P where it slides, to 1e-10; the free
  flights' impact times against t₁ = √(2h/g), t₂ = t₁ + 2 e v₁ / g within the chord's bound
  g Δt² / (8 v_n) (the impact is located by the linear interpolation of eq. (10));
* a rigid rotation of the whole model gives the same events in time (order and t to 1e-9);
* the degenerate start: loaded from zero with every CFE closed at N = Q = 0 (every facet of
  every CFE at its limit at once): ΣN = −W at t = 0 to 1e-9, no event there, then the slide;
* 3D mass matrices (scikit-fem): the total mass ρ V on each axis (1e-12), the consistent
  mass's second moment ∫ ρ x² dV = ρ A L³ / 3 exactly (1e-12), positive lumped diagonals.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.enums import FACET_SLIP, VERTEX_SLIP, ContactState, Status, Transition
from stepcontact.errors import ModelError
from stepcontact.fem.assembly import assemble
from stepcontact.fem.mass import mass
from stepcontact.model.timefunction import Constant, Pulse
from stepcontact.solver.program import solve_dynamic

G = 9.81
TOL = 1e-9
RHO = 2400.0
CONCRETE = sc.Material(30e9, 0.2, RHO)


# --------------------------------------------------------------------------------------------
# the rigid block: one CFE, DOFs ux, uy, uz (a point mass on a rough plane z = 0)
# --------------------------------------------------------------------------------------------
def point_block(m_: float, f: float, k: int, theta: float, R: np.ndarray | None = None,
                gap: float = 0.0, axes: bool = False) -> sc.DiscreteModel:
    """A block of mass m_ on the rough plane (normal +z, t₁ = x, t₂ = y, vertex 0 of the
    polygon along x), its weight the pattern ``weight``, a unit push along θ (from x towards
    y) the pattern ``push``; ``R``: the whole model turned rigidly (rows, loads); ``gap``: the
    block starts that high above the plane."""
    R = np.eye(3) if R is None else np.asarray(R, float)
    W = m_ * G
    names = ("ux", "uy", "uz")
    return sc.DiscreteModel(
        K=np.zeros((3, 3)), normal_rows=[R[:, 2]], tangent_rows=[R[:, 0]],
        tangent2_rows=[R[:, 1]], gaps=gap, friction=f, facets=k, dof_names=names,
        loads={"weight": dict(zip(names, R @ (0.0, 0.0, -W), strict=True)),
               "push": dict(zip(names, R @ (math.cos(theta), math.sin(theta), 0.0),
                                strict=True))},
        dof_axes={"ux": "x", "uy": "y", "uz": "z"} if axes else None,
        program=[sc.Segment("weight", 1.0)])


def polygon_slide(f: float, k: int, theta: float, P: float, m_: float, tp: float):
    """The rigid block's slide on the k-gon under a rectangular pulse P along θ (module
    docstring): (slip state, unit slip direction, friction force during the pulse (2,),
    acceleration a, deceleration a_d, stop time, slide)."""
    W = m_ * G
    a_f = 2 * np.pi / k * np.round((theta - np.pi / k) / (2 * np.pi / k)) + np.pi / k
    i = int(np.round((a_f - np.pi / k) / (2 * np.pi / k))) % k  # the nearest facet
    vertex = np.isclose(np.cos(k * theta), 1.0, atol=0.0, rtol=1e-14)
    if vertex:
        d = np.array([math.cos(theta), math.sin(theta)])
        a, a_d = (P - f * W) / m_, f * G
        state = VERTEX_SLIP + int(np.round(theta * k / (2 * np.pi))) % k
        Qf = f * W * d
    else:
        d = np.array([math.cos(a_f), math.sin(a_f)])
        e = np.array([-d[1], d[0]])
        Pv = P * np.array([math.cos(theta), math.sin(theta)])
        assert abs(Pv @ e) <= f * W * math.sin(math.pi / k)  # on the facet
        mu = f * math.cos(math.pi / k)
        a, a_d = (Pv @ d - mu * W) / m_, mu * G
        state = FACET_SLIP + i
        Qf = mu * W * d + (Pv @ e) * e
    assert a > 0
    v = a * tp
    return state, d, Qf, a, a_d, tp + v / a_d, 0.5 * a * tp**2 + v**2 / (2 * a_d)


def assert_ledger(res, tol: float = TOL) -> None:
    """The energy balance within ``tol`` of the loads' work at every state."""
    E = res.energy
    work = max(float(np.abs(np.asarray(E["external"])).max()), 1e-300)
    assert np.abs(np.asarray(E["error"])).max() <= tol * work, (
        np.abs(np.asarray(E["error"])).max() / work)


K_THETA = [(4, 0.0, "vertex"), (4, math.pi / 4, "facet"), (4, 0.6 * math.pi / 4, "between"),
           (8, 0.0, "vertex"), (8, math.pi / 8, "facet"), (8, 0.6 * math.pi / 8, "between"),
           (8, 1.0 + 4 * math.pi / 8, "vertex 2")]


@pytest.mark.parametrize("k, theta, where", K_THETA)
def test_a_rigid_block_slides_under_an_oblique_pulse_as_the_polygon_closed_form(k, theta, where):
    """A block of 1000 kg (f = 0.3) pushed along θ by a rectangular pulse 1.5 f W for 0.3 s:
    it slips at t = 0 in the state the normality rule gives (a vertex, a facet), slides
    along d with the polygon's friction and stops at the closed form's time; events, slide,
    the friction force during the pulse and the energy ledger against the closed form
    (module docstring) to 1e-9.  ("vertex 2": θ at vertex 2 of the 8-gon turned by
    facet_angle = 1 rad.)"""
    m_, f, tp, dt = 1000.0, 0.3, 0.3, 3e-3
    W = m_ * G
    P = 1.5 * f * W
    dm = point_block(m_, f, k, theta)
    angle = 1.0 if where == "vertex 2" else 0.0
    if angle:
        dm = dm.replace(facet_angle=angle)
    st = sc.solve_static(dm)
    res = solve_dynamic(dm, dt=dt, duration=0.9, mass=m_ * np.eye(3), initial=st,
                        loads={"push": Pulse(P, 0.0, tp, "rectangular")})
    assert res.status == Status.COMPLETED, res.message
    state, d, Qf, a, a_d, t_stop, slide = polygon_slide(f, k, theta - angle, P, m_, tp)
    rot = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    d, Qf = rot @ d, rot @ Qf
    ev = [(e.transition, e.lam) for e in res.events]
    assert [t for t, _ in ev] == [Transition.SLIP, Transition.STUCK], ev
    assert ev[0][1] == 0.0
    assert ev[1][1] == pytest.approx(t_stop, rel=TOL)
    assert int(res.state[1][0]) == state
    u = np.asarray(res.u[-1])
    np.testing.assert_allclose(u[:2], slide * d, rtol=0, atol=a_d * dt**2 / 8)
    assert abs(u[2]) <= TOL * slide
    mid = int(np.searchsorted(np.asarray(res.lam), 0.5 * tp))
    np.testing.assert_allclose(np.asarray(res.Q[mid][0]), Qf, rtol=0, atol=TOL * f * W)
    assert float(res.N[mid][0]) == pytest.approx(-W, rel=TOL)
    after = np.asarray(res.lam) > t_stop + 1e-6
    assert np.abs(np.asarray(res.Q)[after]).max() <= TOL * f * W  # at rest, no load
    assert_ledger(res)
    E = res.energy  # at rest at the end: the work went into friction (and the share the
    # cut at the stop removed, booked as numerical: never a gain)
    assert E["friction"][-1] + E["numerical"][-1] == pytest.approx(E["external"][-1], rel=TOL)
    assert E["numerical"][-1] >= -TOL * E["external"][-1]
    # the push's work P · x(t_p), x(t_p) = ½ a t_p² d (a step end: exact)
    assert E["external"][-1] == pytest.approx(P * (0.5 * a * tp**2) * (
        np.array([math.cos(theta), math.sin(theta)]) @ d), rel=TOL)


def test_the_same_rigid_block_turned_gives_the_same_events_in_time():
    """The block and its loads turned by an arbitrary rotation R (its CFE's basis with it):
    the same events at the same times (1e-9), the slide turned by R (1e-9) — the dynamic
    driver has no preferred axes."""
    R = _rotation(0.4, -0.7, 1.1)
    m_, f, tp, dt, k, theta = 1000.0, 0.3, 0.3, 3e-3, 8, 0.2
    P = 1.5 * f * m_ * G
    out = []
    for Rm in (np.eye(3), R):
        dm = point_block(m_, f, k, theta, R=Rm)
        res = solve_dynamic(dm, dt=dt, duration=0.9, mass=m_ * np.eye(3),
                            initial=sc.solve_static(dm),
                            loads={"push": Pulse(P, 0.0, tp, "rectangular")})
        assert res.status == Status.COMPLETED, res.message
        out.append(res)
    a, b = out
    assert [(e.cfe, e.transition) for e in a.events] == [(e.cfe, e.transition)
                                                         for e in b.events]
    for ea, eb in zip(a.events, b.events, strict=True):
        assert eb.lam == pytest.approx(ea.lam, rel=TOL, abs=TOL)
    slide = np.linalg.norm(np.asarray(a.u[-1]))
    np.testing.assert_allclose(np.asarray(b.u[-1]), R @ np.asarray(a.u[-1]), rtol=0,
                               atol=TOL * slide)


def _rotation(a: float, b: float, c: float) -> np.ndarray:
    """R = R_z(c) R_y(b) R_x(a)."""
    ca, sa, cb, sb, cc, sc_ = (math.cos(a), math.sin(a), math.cos(b), math.sin(b),
                               math.cos(c), math.sin(c))
    Rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    Ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    Rz = np.array([[cc, -sc_, 0], [sc_, cc, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def test_a_ground_acceleration_along_an_oblique_direction_is_the_push_of_the_inertia():
    """A rectangular ground acceleration a_g along (cos θ, sin θ, 0) for t_p (DOF axes x, y,
    z): the block's slide relative to the ground is that of the push −m a_g (the closed form
    with P = m a_g along θ + π, 1e-9), ended at rest on the ground."""
    m_, f, tp, dt, k, theta = 1000.0, 0.3, 0.3, 3e-3, 8, 0.2
    ag = 1.5 * f * G
    dm = point_block(m_, f, k, theta, axes=True)
    res = solve_dynamic(dm, dt=dt, duration=0.9, mass=m_ * np.eye(3),
                        initial=sc.solve_static(dm),
                        ground_acceleration=(Pulse(ag, 0.0, tp, "rectangular"),
                                             (math.cos(theta), math.sin(theta), 0.0)))
    assert res.status == Status.COMPLETED, res.message
    _, d, _, _, a_d, t_stop, slide = polygon_slide(f, k, theta + math.pi, m_ * ag, m_, tp)
    assert [e.transition for e in res.events] == [Transition.SLIP, Transition.STUCK]
    assert res.events[1].lam == pytest.approx(t_stop, rel=TOL)
    np.testing.assert_allclose(np.asarray(res.u[-1])[:2], slide * d, rtol=0,
                               atol=a_d * dt**2 / 8)  # (the chord's bound, as above)
    assert_ledger(res)
    with pytest.raises(ModelError, match="ground_acceleration"):  # 2 components in 3D
        solve_dynamic(dm, dt=dt, duration=0.1, mass=m_ * np.eye(3),
                      ground_acceleration=(Constant(1.0), (1.0, 0.0)))


# --------------------------------------------------------------------------------------------
# impacts in 3D
# --------------------------------------------------------------------------------------------
def test_an_oblique_drop_rebounds_by_newtons_law_with_coulombs_impulse_on_the_cone():
    """A block dropped from h = 0.1 m with a horizontal velocity 2 m/s along vertex 0 (x),
    restitution e = 0.5, f = 0.3: at each impact the normal velocity jumps to −e times the
    approach velocity v_n and, sliding, the tangential impulse is f P with P = m (1 + e) v_n
    (the cone's bound), so u̇_x drops by f P / m — to 1e-10 (the impulses' solves'
    round-off; measured 2e-11); the impact times against the
    free flights' t₁ = √(2h/g), t₂ − t₁ = 2 u̇_z⁺ / g and t₂ = t₁ + 2 e v₁ / g within the
    chord's bound g Δt² / (8 v_n) of eq. (10)'s location (measured 6e-7, 1.2e-6, 2.4e-6 s
    against 8.8e-7, 1.8e-6, 3.5e-6 s); each impact a closing and a rebound (opening) at one instant;
    the energy ledger to 1e-9."""
    m_, f, e, h, vx, dt = 10.0, 0.3, 0.5, 0.1, 2.0, 1e-3
    dm = point_block(m_, f, 8, 0.0, gap=h)
    res = solve_dynamic(dm, dt=dt, duration=0.3, mass=m_ * np.eye(3), restitution=e,
                        loads={"weight": Constant(1.0)}, v0=np.array([vx, 0.0, 0.0]))
    assert res.status == Status.COMPLETED, res.message
    imp = res.impulses
    assert len(imp["time"]) == 2
    t1 = math.sqrt(2 * h / G)
    t2 = t1 + 2 * e * G * t1 / G
    v = np.asarray(res.v)
    # the impact is the root of the chord of the gap's parabola over its step (eq. (10)):
    # off by at most g Δt² / 8 over the approach velocity v_n
    v1 = G * t1
    bound1, bound2 = G * dt**2 / (8 * v1), G * dt**2 / (8 * e * v1)
    assert imp["time"][0] == pytest.approx(t1, abs=bound1)
    # the second flight from the recorded rebound velocity, and from the drop (t₁'s error
    # moves the rebound velocity by e g δt₁: δt₂ ≤ (1 + 2e) δt₁ + the second location's)
    flight = 2 * v[int(imp["state"][0])][2] / G
    assert imp["time"][1] - imp["time"][0] == pytest.approx(flight, abs=bound2)
    assert imp["time"][1] == pytest.approx(t2, abs=(1 + 2 * e) * bound1 + bound2)
    ux_dot = vx
    for j in range(2):
        i = int(imp["state"][j])  # the state recorded after the impact
        P = -float(imp["normal"][j])  # N·s, compressive
        vn_before = v[i][2] - P / m_  # M Δu̇ = −Bᵀ P: u̇_z jumps by P / m
        assert vn_before < 0
        assert v[i][2] == pytest.approx(-e * vn_before, abs=1e-10 * abs(vn_before))
        assert P == pytest.approx(m_ * (1 + e) * -vn_before, rel=1e-10)
        assert float(imp["tangential"][j]) == pytest.approx(f * P, rel=1e-10)
        ux_dot -= f * P / m_
        assert v[i][0] == pytest.approx(ux_dot, rel=1e-10)
        assert abs(v[i][1]) <= 1e-10 * vx
    kinds = [(ev.lam, ev.transition) for ev in res.events]
    assert [t for _, t in kinds] == [Transition.SLIP, Transition.OPENED] * 2
    assert_ledger(res)


@pytest.mark.parametrize("theta, where", [(math.pi / 8, "facet"), (0.2, "vertex")])
def test_a_plastic_impact_while_sliding_slips_on_by_the_normality_rule(theta, where):
    """A block dropped from h = 0.1 m with 2 m/s along θ, e = 0 (8-gon, f = 0.3): the impact's
    tangential impulse is f P (P = m v_n, the cone's bound), so the block slides on with
    v⁺ = 2 − f P / m along θ (1e-10) in the slip state whose normal cone holds θ.

    * θ = π/8, facet 0's normal: it slides on facet 0, decelerates at μ g (μ = f cos(π/8))
      and stops v⁺ / (μ g) after the impact;
    * θ = 0.2, inside vertex 0's cone (−π/8, π/8): at vertex 0 the force f W along x slows
      u̇_x alone (at f g) until the velocity lies along d₀ (u̇_x = u̇_y / tan(π/8)), where the
      slip turns onto facet 0 and goes on as above.

    Turn and stop times against these closed forms to 1e-9 (constant accelerations); at rest
    at the end; the ledger to 1e-9."""
    m_, f, h, vx, dt, k = 10.0, 0.3, 0.1, 2.0, 1e-3, 8
    dm = point_block(m_, f, k, 0.0, gap=h)
    v0 = np.array([vx * math.cos(theta), vx * math.sin(theta), 0.0])
    res = solve_dynamic(dm, dt=dt, duration=1.0, mass=m_ * np.eye(3), restitution=0.0,
                        loads={"weight": Constant(1.0)}, v0=v0)
    assert res.status == Status.COMPLETED, res.message
    imp = res.impulses
    assert len(imp["time"]) == 1
    i, t_imp = int(imp["state"][0]), float(imp["time"][0])
    P = -float(imp["normal"][0])
    v = np.asarray(res.v)
    assert float(imp["tangential"][0]) == pytest.approx(f * P, rel=1e-10)
    vt = vx - f * P / m_
    np.testing.assert_allclose(v[i][:2], vt * v0[:2] / vx, rtol=0, atol=1e-10 * vx)
    assert abs(v[i][2]) <= 1e-10 * vx
    mu = f * math.cos(math.pi / k)
    ev = [(e.transition, e.lam) for e in res.events]
    if where == "facet":
        assert int(res.state[i][0]) == FACET_SLIP + 0
        assert [t for t, _ in ev] == [Transition.SLIP, Transition.STUCK]
        t_stop = t_imp + vt / (mu * G)
    else:
        assert int(res.state[i][0]) == VERTEX_SLIP + 0
        assert [t for t, _ in ev] == [Transition.SLIP, Transition.TURNED, Transition.STUCK]
        vx1, vy = vt * math.cos(theta), vt * math.sin(theta)
        vx2 = vy / math.tan(math.pi / k)
        t_turn = t_imp + (vx1 - vx2) / (f * G)
        assert ev[1][1] == pytest.approx(t_turn, rel=TOL)
        t_stop = t_turn + math.hypot(vx2, vy) / (mu * G)
    assert ev[0][1] == t_imp
    assert ev[-1][1] == pytest.approx(t_stop, rel=TOL)
    assert int(res.state[-1][0]) == ContactState.STICK
    assert np.abs(v[-1]).max() <= 1e-9 * vx
    assert_ledger(res)


def test_the_slip_state_towards_a_direction_follows_the_normality_rule():
    """Facet normals d_i at θ₀ + (2i + 1) π/k give facet i; a direction strictly between
    d_{i−1} and d_i gives vertex i (at θ₀ + 2πi/k), for θ₀ = 0 and 1 rad, k = 8."""
    from stepcontact.contact.faceted import FacetedCoulombLaw

    for theta0 in (0.0, 1.0):
        law = FacetedCoulombLaw(np.arange(16), 0.5, np.inf, np.inf, facets=8, angle=theta0)
        i = np.arange(8)
        normals = theta0 + (2 * i + 1) * np.pi / 8
        between = theta0 + 2 * np.pi * i / 8 + np.where(i % 2, 0.3, -0.3) * np.pi / 8
        ang = np.r_[normals, between]
        got = law.slip_state_towards(np.arange(16), np.c_[np.cos(ang), np.sin(ang)])
        assert list(got) == [FACET_SLIP + j for j in i] + [VERTEX_SLIP + j for j in i]


# --------------------------------------------------------------------------------------------
# an elastic block (hex8 continuum) on a rough rigid plane
# --------------------------------------------------------------------------------------------
def _rotated(body: sc.Body, R: np.ndarray) -> sc.Body:
    """The body turned by the rotation matrix R about the origin (its named faces kept)."""
    mesh = dataclasses.replace(body.mesh, doflocs=R @ body.mesh.doflocs)
    return sc.Body.from_mesh(body.name, mesh, body.element, body.material)


F = 0.5
W_BLOCK = RHO * G * 0.5  # the 1 × 1 × 0.5 m block's weight, N
M_BLOCK = RHO * 0.5  # its mass, kg


def continuum_block(k: int, theta: float, R: np.ndarray | None = None,
                    element: str = "hex8", base: tuple | None = None,
                    cfe: str = "auto") -> sc.Model:
    """A 1 × 1 × 0.5 m concrete block (2 × 2 × 1 cells: 9 CFEs on its bottom nodes) on the
    rough rigid plane z = 0 (f = 0.5, k facets, t₁ = x), or on a 2 × 2 × 0.5 m base block of
    ``base`` cells fixed at its bottom (CFEs of kind ``cfe``); its weight the pattern
    ``weight``, a horizontal body force of 1 N in all along θ the pattern ``push`` (no moment
    about the centroid); ``R``: the whole model turned rigidly."""
    R = np.eye(3) if R is None else np.asarray(R, float)
    blk = _rotated(sc.box("block", (0, 0, 0), (1, 1, 0.5), (2, 2, 1), CONCRETE, element), R)
    bodies = [blk]
    if base is not None:
        bodies.append(_rotated(sc.box("base", (-0.5, -0.5, -0.5), (1.5, 1.5, 0.0), base,
                                      CONCRETE, element), R))
    m = sc.Model(bodies=tuple(bodies))
    if base is None:
        minus = sc.RigidPlane("ground", point=(0, 0, 0), normal=R @ (0, 0, 1.0))
    else:
        minus = m.select("base", boundary="top")
        m = m.add(sc.Support("bed", m.select("base", boundary="bottom"), "xyz"))
    push = R @ np.array([math.cos(theta), math.sin(theta), 0.0]) / M_BLOCK
    return m.add(
        sc.Interface("joint", m.select("block", boundary="bottom"), minus, friction=F,
                     facets=k, cfe=cfe, axis=tuple(R @ (1.0, 0, 0))),
        sc.LoadPattern("weight", [sc.BodyForce(g=tuple(R @ (0, 0, -G)), bodies=("block",))]),
        sc.LoadPattern("push", [sc.BodyForce(g=tuple(push), bodies=("block",))]),
        sc.Segment("weight", 1.0))


def half_sine_slide(mu: float, P0: float, tp: float) -> tuple[float, float, float]:
    """The rigid block (mass M_BLOCK, friction μ W along its slip) pushed by P₀ sin(π t/t_p)
    (P₀ > μ W), stopping after the pulse: start t_s = t_p/π asin(μ W/P₀); m v(t) = P₀ t_p/π
    (cos(π t_s/t_p) − cos(π t/t_p)) − μ W (t − t_s); after t_p the deceleration μ g.
    Returns (t_s, stop time, slide)."""
    W, m_ = W_BLOCK, M_BLOCK
    ts = tp / np.pi * np.arcsin(mu * W / P0)
    c0 = np.cos(np.pi * ts / tp)
    v1 = (P0 * tp / np.pi * (c0 + 1.0) - mu * W * (tp - ts)) / m_
    x1 = (P0 * tp / np.pi * (c0 * (tp - ts) + tp / np.pi * np.sin(np.pi * ts / tp))
          - 0.5 * mu * W * (tp - ts) ** 2) / m_
    assert v1 > 0
    return ts, tp + v1 / (mu * G), x1 + v1**2 / (2 * mu * G)


@pytest.mark.parametrize("theta, where", [(0.0, "vertex"), (math.pi / 8, "facet")])
def test_an_elastic_block_slides_as_the_rigid_block_under_a_half_sine_pulse(theta, where):
    """The hex8 block (lumped mass) pushed along θ by 1.5 W sin(π t / 0.2 s): every CFE
    slips and stops; the mean slide of its nodes against the rigid block's on the polygon
    (friction f W at a vertex, f W cos(π/8) on a facet, along θ) to 1e-3 relative (measured
    6.6e-5 and 1.9e-4: the block's elastic modes, corner CFEs that slip and stop before the
    others) and its last stop to 2 ms (measured 0.5 ms), no slip across θ (1e-9 of the
    slide); the conditions (1) at every state (1e-9) and the energy ledger to 1e-9 of the
    work (measured 2.7e-10)."""
    k, tp = 8, 0.2
    model = continuum_block(k, theta)
    res = solve_dynamic(model, dt=2e-3, duration=0.6, mass="lumped",
                        initial=sc.solve_static(model),
                        loads={"push": Pulse(1.5 * W_BLOCK, 0.0, tp, "half_sine")})
    assert res.status == Status.COMPLETED, res.message
    assert res.violation.max() <= TOL
    mu = F if where == "vertex" else F * math.cos(math.pi / k)
    _, t_stop, slide = half_sine_slide(mu, 1.5 * W_BLOCK, tp)
    u = res.displacement(-1).reshape(-1, 3)
    d = np.array([math.cos(theta), math.sin(theta)])
    assert float((u[:, :2] @ d).mean()) == pytest.approx(slide, rel=1e-3)
    assert abs(float((u[:, :2] @ np.array([-d[1], d[0]])).mean())) <= TOL * slide
    stops = [e.lam for e in res.events if e.transition == Transition.STUCK]
    assert len(stops) >= 9 and max(stops) == pytest.approx(t_stop, abs=2e-3)
    assert np.all(np.asarray(res.state[-1]) == ContactState.STICK)
    assert_ledger(res)


@pytest.mark.parametrize("base, cfe, element, kind", [
    ((3, 3, 1), "mortar", "hex8", "consistent"), ((2, 2, 1), "auto", "tet4", "lumped")])
def test_a_block_on_an_elastic_base_slides_with_the_ledger_balanced(base, cfe, element, kind):
    """The block on an elastic base fixed at its bottom (mortar CFEs between non-matching
    hex8 faces with the consistent mass; node-to-facet CFEs on tetrahedra with the lumped
    mass) under the half-sine push along θ = 0.3: the run completes, the contact conditions
    (1) hold at every state (1e-9), the energy ledger balances to 1e-9 of the work, the
    block slips (every CFE) and ends stuck, moved along the push (its mean displacement
    within 15° of θ — the base's deformation and the polygon's facet turn it a little)."""
    model = continuum_block(8, 0.3, base=base, cfe=cfe, element=element)
    res = solve_dynamic(model, dt=2e-3, duration=0.5, mass=kind,
                        initial=sc.solve_static(model),
                        loads={"push": Pulse(1.5 * W_BLOCK, 0.0, 0.2, "half_sine")})
    assert res.status == Status.COMPLETED, res.message
    assert res.violation.max() <= TOL
    assert_ledger(res)
    m = np.asarray(res.state).shape[1]
    assert {e.cfe for e in res.events if e.transition == Transition.SLIP} == set(range(m))
    assert np.all(np.asarray(res.state[-1]) == ContactState.STICK)
    blk = model.node_offsets["block"] + np.arange(model.body("block").n_nodes)
    u = res.displacement(-1).reshape(-1, 3)[blk].mean(axis=0)
    assert abs(math.atan2(u[1], u[0]) - 0.3) <= math.radians(15)


def test_the_elastic_block_turned_gives_the_same_events_in_time():
    """The block, its plane, loads and t₁ axis turned by an arbitrary rotation R: the same
    events (CFE, transition) in the same order at the same times (1e-9 s), the final slide
    turned by R (1e-9 of it)."""
    R = _rotation(0.4, -0.7, 1.1)
    runs = []
    for Rm in (None, R):
        model = continuum_block(8, 0.3, Rm)
        res = solve_dynamic(model, dt=2e-3, duration=0.6, mass="lumped",
                            initial=sc.solve_static(model),
                            loads={"push": Pulse(1.5 * W_BLOCK, 0.0, 0.2, "half_sine")})
        assert res.status == Status.COMPLETED, res.message
        runs.append(res)
    a, b = runs
    assert len(a.events) > 9
    assert [(e.cfe, e.transition) for e in a.events] == [(e.cfe, e.transition)
                                                         for e in b.events]
    for ea, eb in zip(a.events, b.events, strict=True):
        assert abs(eb.lam - ea.lam) <= TOL
    ua = a.displacement(-1).reshape(-1, 3)
    ub = b.displacement(-1).reshape(-1, 3)
    np.testing.assert_allclose(ub, ua @ R.T, rtol=0, atol=TOL * np.abs(ua).max())


def test_loaded_from_zero_every_cfe_closed_at_zero_force():
    """The degenerate start: from u = 0 with every CFE closed at N = Q = 0 (all facets of all
    CFEs at their limits at once) the weight and a push are switched on at t = 0.

    * the point block (one CFE): its initial state (the contact problem in accelerations
      under the loads at t = 0, not an event) is the slip the closed form gives, and it
      slides and stops as from the static start — the closed form (stop and force 1e-9, the
      slide to the chord's bound, as above);
    * the hex8 block (9 CFEs, lumped mass): at t = 0 every CFE is closed and stuck with no
      event, and the contact forces are the contact problem's in accelerations: the
      bottom nodes held, the others falling freely, so Σ N = −W/2 (HRZ on the regular hex8:
      each node 1/8 of its element's mass, the bottom ones half the block's) and Σ Q = 0,
      to 1e-9 W; the run completes with the conditions (1) at every state (1e-9) and the
      energy ledger to 1e-9 of the work."""
    m_, f, tp, dt, k, theta = 1000.0, 0.3, 0.3, 3e-3, 8, 0.2
    P = 1.5 * f * m_ * G
    dm = point_block(m_, f, k, theta)
    res = solve_dynamic(dm, dt=dt, duration=0.9, mass=m_ * np.eye(3), u0=np.zeros(3),
                        loads={"weight": Constant(1.0),
                               "push": Pulse(P, 0.0, tp, "rectangular")})
    assert res.status == Status.COMPLETED, res.message
    state, d, Qf, _, a_d, t_stop, slide = polygon_slide(f, k, theta, P, m_, tp)
    assert int(res.state[0][0]) == state  # (the initial state: slipping from t = 0)
    assert [e.transition for e in res.events] == [Transition.STUCK]
    assert res.events[0].lam == pytest.approx(t_stop, rel=TOL)
    np.testing.assert_allclose(np.asarray(res.u[-1])[:2], slide * d, rtol=0,
                               atol=a_d * dt**2 / 8)
    mid = int(np.searchsorted(np.asarray(res.lam), 0.5 * tp))
    np.testing.assert_allclose(np.asarray(res.Q[mid][0]), Qf, rtol=0, atol=TOL * f * m_ * G)
    assert_ledger(res)

    model = continuum_block(8, 0.3)
    ndof = assemble(model).ndof
    res = solve_dynamic(model, dt=2e-3, duration=0.3, mass="lumped", u0=np.zeros(ndof),
                        loads={"weight": Constant(1.0),
                               "push": Pulse(1.5 * W_BLOCK, 0.0, 0.2, "half_sine")})
    assert res.status == Status.COMPLETED, res.message
    assert np.all(np.asarray(res.state[0]) == ContactState.STICK)
    assert not [e for e in res.events if e.lam == 0.0]
    assert float(np.sum(res.N[0])) == pytest.approx(-W_BLOCK / 2, rel=TOL)
    assert np.abs(np.asarray(res.Q[0]).sum(axis=0)).max() <= TOL * W_BLOCK
    assert res.violation.max() <= TOL
    assert len(res.events) > 9
    assert_ledger(res)


# --------------------------------------------------------------------------------------------
# 3D mass matrices
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("element", ["tet4", "hex8", "tet10", "hex20", "hex27"])
def test_3d_mass_matrices_carry_the_mass_and_its_second_moment(element):
    """A 3 × 0.5 × 0.8 m bar: the rigid translation along each axis carries ρ V (1e-12), the
    consistent mass integrates ρ x² exactly (∫ ρ x² dV = ρ A L³ / 3, 1e-12: x² lies in the
    product of two linear shape functions' space), no coupling between the axes; the
    HRZ-lumped mass is diagonal, positive, with the same total."""
    L, B, H = 3.0, 0.5, 0.8
    bar = sc.box("bar", (0, 0, 0), (L, B, H), (2, 1, 1), CONCRETE, element)
    model = sc.Model(bodies=(bar,))
    model = model.add(sc.Support("end", model.select("bar", boundary="left"), "xyz"))
    dofs = assemble(model).dofs
    x = bar.points[:, 0]
    for lumped in (False, True):
        M = mass(model, dofs, lumped=lumped)
        r = [np.zeros(dofs.ndof) for _ in range(3)]
        for c in range(3):
            r[c][dofs.of[:, c]] = 1.0
            assert r[c] @ M @ r[c] == pytest.approx(RHO * L * B * H, rel=1e-12)
        assert abs(r[0] @ M @ r[2]) <= 1e-12 * RHO * L * B * H
        if lumped:
            assert M.nnz == dofs.ndof and M.diagonal().min() > 0
        else:
            rx = np.zeros(dofs.ndof)
            rx[dofs.of[:, 2]] = x
            assert rx @ M @ rx == pytest.approx(RHO * B * H * L**3 / 3, rel=1e-12)


def test_a_space_frame_mass_is_lumped_on_its_three_translations():
    """A space-frame bar of length L: ρ A L on each of x, y, z (1e-12), none on rotations."""
    fr = sc.Frame.line("bar", (0, 0, 0), (2.0, 1.0, 2.0), 4, E=2e11, A=0.01, Iy=1e-5,
                       Iz=2e-5, J=3e-5, nu=0.3, density=7850.0)
    model = sc.Model(bodies=(fr,))
    model = model.add(sc.Support("end", model.select("bar", x=0.0), "xyzrxryrz"))
    dofs = assemble(model).dofs
    M = mass(model, dofs)
    for c in range(3):
        r = np.zeros(dofs.ndof)
        r[dofs.of[:, c]] = 1.0
        assert r @ M @ r == pytest.approx(7850.0 * 0.01 * 3.0, rel=1e-12)
    assert np.all(M.diagonal()[dofs.of[:, 3:].ravel()] == 0.0)


# --------------------------------------------------------------------------------------------
# 3D against the 2D driver path (CoulombLaw): motion in one vertical plane
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("layer", ["rigid", "damped"])
def test_a_drop_along_a_vertex_repeats_the_2d_run(layer):
    """A block dropped from h = 0.1 m with 2 m/s along vertex 0 of the 8-gon (x), where the
    polygon's friction is f N along the slip as in 2D: the 3D run (faceted cone, DOFs ux, uy,
    uz) against the 2D run of the same block (DOFs ux, uy; CoulombLaw) — rigid contact with
    restitution e = 0.5, or a Kelvin–Voigt layer (kn, kt, cn): the same events at the same
    times (1e-9 s), the same impulses (1e-9), the same final state (1e-9 of the motion) and
    the ledger to 1e-9."""
    m_, f, h, vx, dt = 10.0, 0.3, 0.1, 2.0, 1e-3
    W = m_ * G
    kw = (dict(kn=1e6, kt=1e6, cn=2e3) if layer == "damped" else {})
    e = 0.5 if layer == "rigid" else 0.0
    dm2 = sc.DiscreteModel(K=np.zeros((2, 2)), normal_rows=[[0, 1]], tangent_rows=[[1, 0]],
                           gaps=h, friction=f, dof_names=("ux", "uy"),
                           loads={"weight": {"uy": -W}}, **kw)
    dm3 = point_block(m_, f, 8, 0.0, gap=h).replace(**kw)
    runs = [solve_dynamic(dm, dt=dt, duration=0.4, mass=m_ * np.eye(n), restitution=e,
                          loads={"weight": Constant(1.0)}, v0=np.r_[vx, np.zeros(n - 1)])
            for dm, n in ((dm2, 2), (dm3, 3))]
    r2, r3 = runs
    assert r2.status == r3.status == Status.COMPLETED
    assert len(r3.events) == len(r2.events) >= 4
    slips = (Transition.SLIP_POS, Transition.SLIP)
    for e2, e3 in zip(r2.events, r3.events, strict=True):
        assert (e2.transition in slips and e3.transition in slips) or (
            e2.transition == e3.transition)
        assert e3.lam == pytest.approx(e2.lam, abs=TOL)
    assert np.asarray(r3.impulses["normal"]) == pytest.approx(
        np.asarray(r2.impulses["normal"]), rel=TOL)
    assert np.abs(np.asarray(r3.impulses["tangential"])) == pytest.approx(
        np.abs(np.asarray(r2.impulses["tangential"])), rel=TOL)
    u2, u3 = np.asarray(r2.u[-1]), np.asarray(r3.u[-1])
    np.testing.assert_allclose(u3[[0, 2]], u2, rtol=0, atol=TOL * np.abs(u2).max())
    assert abs(u3[1]) <= TOL * np.abs(u2).max()
    assert_ledger(r3)
