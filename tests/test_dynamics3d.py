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
  the slide to 1e-3 relative (measured ≤ 1.4e-4: the block's elastic modes and the corner
  CFEs that start and stop slipping before the others);
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
