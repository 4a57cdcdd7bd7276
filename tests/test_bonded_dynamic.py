"""Joints with initial strength (eq. (12)) in a dynamic interval: a bond that reaches its
strength surface breaks at a located time, what it carried is released at that instant, and
its neighbours may break in turn.

References (all independent of the library's integrator):

* a mass on a bonded compliant layer (stiffness k) under a step load P, undamped:
  N(t) = P (1 − cos ωt) in the layer, ω² = k/M; the bond breaks where N = N_R, then the
  mass flies free under P (u = u_b + v_b τ + P τ²/(2M)).  Started from the exact state at
  phase ωt₀ (a few steps before the break) to keep the test short.  Newmark's period error
  (ωΔt)²/12 and the linear location of the event within a step (eq. (10)) are O((ωΔt)²):
  with ωΔt = 1e-3 the break time agrees to 1e-6 (relative to the time elapsed), the motion
  after it likewise; the ledger's ``fracture`` is ½ N_R²/k exactly and the balance holds to
  round-off;
* a rigid bonded block pressed by W and pushed by H = r t: Q = H while bonded, so the bond
  breaks at t = (Q_R + α_R W)/r (exact: the load is linear in each step); it then slides
  with M ü = H − f W: the velocity (trapezoidal rule, exact for a linear acceleration) to
  round-off, the displacement to Newmark's O(Δt²) (stated below);
* a rigid bar with a large rotary inertia on two rigid bonded supports, pulled up off
  centre by a rising force: the farther bond breaks where the statics give N = N_R; the
  bar then pivots about the other, whose force jumps (closed form in accelerations) beyond
  N_R: it breaks at the same instant, second — the cascade at fixed t; then free flight;
* a bar on three bonded compliant springs under an eccentric step load against the exact
  modal solution between breaks (eigenvectors of (K, M) for the springs still bonded,
  break times by root finding): order and times of the breaks to 1e-5 (ωΔt = 6e-3);
* a bonded dam on a compliant layer (tests/test_bonded_joints.py) hit by a water pulse: each
  CFE on its strength surface when it breaks, the ledger balanced.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import eigh
from scipy.optimize import brentq

import stepcontact as sc
from stepcontact.enums import ContactState, Status, Transition
from stepcontact.errors import ModelError
from stepcontact.model.timefunction import Constant, Pulse, Tabulated
from test_bonded_joints import COHESION, PHI, TENSILE, B, bonded_dam

OPEN, SLIP_POS, BONDED = (int(s) for s in (ContactState.OPEN, ContactState.SLIP_POS,
                                           ContactState.BONDED))


def _broken(res):
    return [e for e in res.events if e.transition == Transition.BROKEN]


def test_a_bonded_layer_under_a_step_load_breaks_at_the_closed_form_time():
    k, M, P, NR = 1e4, 1.0, 1.0, 1.5
    om = np.sqrt(k / M)
    dm = sc.DiscreteModel(K=np.zeros((2, 2)), normal_rows=[[0, 1]], tangent_rows=[[1, 0]],
                          loads={"P": [0.0, 1.0]}, kn=k, kt=k, friction=0.5,
                          bond=sc.Bond(tensile=NR, shear=10.0, alpha=0.5))
    phase0 = 1.8  # start from the exact state at ωt₀ (the layer in tension, N = P(1−cos))
    t0 = phase0 / om
    u0 = np.array([0.0, P / k * (1 - np.cos(phase0))])
    v0 = np.array([0.0, P / k * om * np.sin(phase0)])
    dt = 1e-3 / om
    tb = np.arccos(1 - NR / P) / om  # N(t_b) = N_R
    res = sc.solve_dynamic(dm, dt=dt, duration=tb - t0 + 30 * dt, loads={"P": Constant(P)},
                           mass=M * np.eye(2), u0=u0, v0=v0, record_every=20)
    assert res.status == Status.COMPLETED, res.message
    assert res.state[0][0] == BONDED and res.N[0][0] == pytest.approx(P * (1 - np.cos(phase0)),
                                                                      rel=1e-12)
    (ev,) = _broken(res)
    assert ev.cfe == 0 and ev.N == pytest.approx(NR, rel=1e-9)  # on the tension facet
    assert abs(t0 + ev.lam - tb) <= 1e-6 * (tb - t0)
    assert res.state[-1][0] == OPEN and res.N[-1][0] == 0.0
    # free flight after the break under P
    tau = t0 + res.time[-1] - tb
    ub, vb = P / k * (1 - np.cos(om * tb)), P / k * om * np.sin(om * tb)
    u_ref, v_ref = ub + vb * tau + P / (2 * M) * tau**2, vb + P / M * tau
    assert res.u[-1][1] == pytest.approx(u_ref, rel=1e-6)
    assert res.v[-1][1] == pytest.approx(v_ref, rel=1e-6)
    # the layer's elastic energy at the break, released: ½ N_R²/k; the ledger balances
    assert res.energy["fracture"][-1] == pytest.approx(0.5 * NR**2 / k, rel=1e-6)
    assert np.all(res.energy["fracture"][res.time < ev.lam] == 0.0)
    scale = max(np.abs(res.energy["external"]).max(), res.energy["kinetic"].max())
    assert np.abs(res.energy["error"]).max() <= 1e-9 * scale
    # the ledger's figure draws the fracture term
    import matplotlib

    matplotlib.use("Agg")
    fig = sc.plot_energy(res)
    lines = {ln.get_label(): ln for ln in fig.axes[0].get_lines()}
    assert "fracture" in lines
    assert lines["fracture"].get_ydata()[-1] == pytest.approx(0.5 * NR**2 / k, rel=1e-6)


def test_a_rigid_bond_breaks_in_shear_at_its_strength_under_compression_then_slides():
    M, W, QR, al, f, r = 2.0, 10.0, 3.0, 0.5, 0.3, 100.0
    dm = sc.DiscreteModel(K=np.zeros((2, 2)), normal_rows=[[0, 1]], tangent_rows=[[1, 0]],
                          loads={"W": [0.0, -1.0], "H": [1.0, 0.0]}, friction=f,
                          bond=sc.Bond(tensile=1e3, shear=QR, alpha=al,
                                       tension_alpha=np.inf))
    tb = (QR + al * W) / r
    dt = tb / 100
    res = sc.solve_dynamic(dm, dt=dt, duration=1.5 * tb, mass=M * np.eye(2),
                           loads={"W": Constant(W),
                                  "H": Tabulated((0.0, 1.0), (0.0, r), hold=False)})
    assert res.status == Status.COMPLETED, res.message
    (ev,) = _broken(res)
    assert ev.lam == pytest.approx(tb, rel=1e-12)
    assert ev.Q == pytest.approx(QR + al * W, rel=1e-12) and ev.N == pytest.approx(-W, rel=1e-12)
    before = res.time < tb * (1 - 1e-9)  # (the state at t_b is the one after the break)
    np.testing.assert_allclose(res.Q[before, 0], r * res.time[before], rtol=1e-12,
                               atol=1e-12 * QR)
    assert np.all(res.state[before, 0] == BONDED)
    assert np.abs(res.u[before]).max() <= 1e-12 * QR / r * tb  # held (round-off)
    # then Coulomb slip: Q = f W, M ü = r t − f W
    assert res.state[-1][0] == SLIP_POS and res.Q[-1][0] == pytest.approx(f * W, rel=1e-12)
    tau, t = res.time[-1] - tb, res.time[-1]
    v_ref = (r * (t**2 - tb**2) / 2 - f * W * tau) / M
    u_ref = (r * tau**3 / 6 + (QR + al * W - f * W) * tau**2 / 2) / M
    assert res.v[-1][0] == pytest.approx(v_ref, rel=1e-10)
    assert res.u[-1][0] == pytest.approx(u_ref, rel=1e-4)  # Newmark: O(Δt²), 3e-5 here
    assert res.energy["friction"][-1] > 0 and res.energy["fracture"][-1] == 0.0  # rigid
    assert np.abs(res.energy["error"]).max() <= 1e-9 * res.energy["external"][-1]


def test_bonds_holding_a_rigid_bar_break_in_a_cascade_at_one_instant():
    m_, J, a, xP, r, NR = 1.0, 10.0, 1.0, 0.1, 100.0, 0.55
    # DOFs: lift y, rotation θ, and one slip DOF per support (shear rows of their own)
    dm = sc.DiscreteModel(K=np.zeros((4, 4)), normal_rows=[[1, -a, 0, 0], [1, a, 0, 0]],
                          tangent_rows=[[0, 0, 1, 0], [0, 0, 0, 1]],
                          loads={"P": [1.0, xP, 0.0, 0.0]}, friction=0.5,
                          bond=sc.Bond(tensile=NR, shear=100.0, alpha=0.5))
    # statics: N₂ = P (1 + x_P/a)/2 reaches N_R at P₁
    P1 = 2 * NR / (1 + xP / a)
    t1 = P1 / r
    # pivoting about support 1 at rest: m ÿ = P − N₁, J θ̈ = P x_P + N₁ a, ÿ − a θ̈ = 0
    N1_after = P1 * (1 / m_ - a * xP / J) / (1 / m_ + a * a / J)
    assert N1_after > NR  # (the reference's premise: support 1 cannot hold the pivot)
    res = sc.solve_dynamic(dm, dt=t1 / 20, duration=1.5 * t1, mass=np.diag([m_, J, 1.0, 1.0]),
                           loads={"P": Tabulated((0.0, 1.0), (0.0, r), hold=False)})
    assert res.status == Status.COMPLETED, res.message
    br = _broken(res)
    assert [e.cfe for e in br] == [1, 0]  # the far support first, then the pivot
    for e in br:
        assert e.lam == pytest.approx(t1, rel=1e-12)
        assert e.N == pytest.approx(NR, rel=1e-9)  # each on its facet when it breaks
    assert np.all(res.state[-1] == OPEN)
    # free flight from rest at t₁ under P = r t: y = r (t − t₁)² (t + 2t₁)/(6m)
    t = res.time[-1]
    assert res.v[-1][0] == pytest.approx(r * (t * t - t1 * t1) / (2 * m_), rel=1e-10)
    assert res.v[-1][1] == pytest.approx(xP * r * (t * t - t1 * t1) / (2 * J), rel=1e-10)
    y_ref = r * (t - t1) ** 2 * (t + 2 * t1) / (6 * m_)
    assert res.u[-1][0] == pytest.approx(y_ref, rel=1e-2)  # Newmark O(Δt²), 7e-4 here
    assert np.abs(res.energy["error"]).max() <= 1e-9 * res.energy["external"][-1]


def _modal_breaks(M, rows, k, f, NR, t_end, per_period=400):
    """Exact response of M ü + K u = f from rest, K = k Σ a aᵀ over the springs still bonded;
    spring i breaks where k a_i·u reaches N_R (root by brentq).  Returns [(t, i)], u(t)."""
    active = np.ones(len(rows), bool)
    t0, u0, v0 = 0.0, np.zeros(M.shape[0]), np.zeros(M.shape[0])
    out = []
    while True:
        K = k * sum((np.outer(a, a) for a, on in zip(rows, active, strict=True) if on),
                    np.zeros_like(M))
        lam, Phi = eigh(K, M)
        om = np.sqrt(np.where(lam < 1e-9 * max(lam.max(), 1.0), 0.0, lam))
        rig = om == 0
        w = np.where(rig, 1.0, om)
        q0, qd0, fq = Phi.T @ M @ u0, Phi.T @ M @ v0, Phi.T @ f

        def u_of(t, Phi=Phi, q0=q0, qd0=qd0, fq=fq, t0=t0, w=w, rig=rig):
            tau = t - t0
            st = fq / w**2
            q = np.where(rig, q0 + qd0 * tau + 0.5 * fq * tau**2,
                         st + (q0 - st) * np.cos(w * tau) + qd0 / w * np.sin(w * tau))
            qd = np.where(rig, qd0 + fq * tau, -(q0 - st) * w * np.sin(w * tau)
                          + qd0 * np.cos(w * tau))
            return Phi @ q, Phi @ qd

        if not active.any():
            return out, u_of
        ts = np.arange(t0, t_end, 2 * np.pi / om.max() / per_period)
        g = np.array([[k * rows[i] @ u_of(t)[0] - NR if active[i] else -1.0
                       for i in range(len(rows))] for t in ts])
        hit = np.argwhere(g[1:] > 0)
        if hit.size == 0:
            return out, u_of
        j = hit[:, 0].min()
        tb, i = min((brentq(lambda t, i=i: k * rows[i] @ u_of(t)[0] - NR, ts[j], ts[j + 1],
                            xtol=1e-15), int(i)) for i in hit[hit[:, 0] == j, 1])
        out.append((tb, i))
        active[i] = False
        t0, (u0, v0) = tb, u_of(tb)


def test_a_bar_on_bonded_springs_breaks_them_in_the_order_and_at_the_times_of_the_modal_solution():
    m_, J, k, P, xP, NR = 1.0, 0.5, 1e4, 1.0, 0.5, 0.8
    rows = [np.array([1.0, x]) for x in (-1.0, 0.0, 1.0)]
    M, f = np.diag([m_, J]), P * np.array([1.0, xP])
    ref, u_of = _modal_breaks(M, rows, k, f, NR, 0.05)
    assert [i for _, i in ref] == [2, 1]  # (the reference: two of the three break)
    dm = sc.DiscreteModel(K=np.zeros((2, 2)), normal_rows=np.array(rows),
                          tangent_rows=np.zeros((3, 2)), loads={"P": list(f / P)}, kn=k,
                          kt=k, bond=sc.Bond(tensile=NR, shear=100.0, alpha=0.5,
                                             tension_alpha=np.inf))
    om_max = np.sqrt(eigh(k * sum(np.outer(a, a) for a in rows), M, eigvals_only=True).max())
    res = sc.solve_dynamic(dm, dt=6e-3 / om_max, duration=1.05 * ref[-1][0],
                           loads={"P": Constant(P)}, mass=M, record_every=100)
    assert res.status == Status.COMPLETED, res.message
    br = _broken(res)
    assert [e.cfe for e in br] == [i for _, i in ref]
    for e, (tb, _) in zip(br, ref, strict=True):
        assert e.lam == pytest.approx(tb, rel=1e-5)
        assert e.N == pytest.approx(NR, rel=1e-6)
    u_ref = u_of(res.time[-1])[0]
    assert np.abs(res.u[-1] - u_ref).max() <= 1e-4 * np.abs(u_ref).max()
    assert res.energy["fracture"][-1] == pytest.approx(2 * 0.5 * NR**2 / k, rel=1e-5)
    assert np.abs(res.energy["error"]).max() <= 1e-9 * res.energy["external"][-1]


def test_a_bonded_damped_layer_is_refused_naming_the_interface():
    dm = sc.DiscreteModel(K=np.zeros((2, 2)), normal_rows=[[0, 1]], tangent_rows=[[1, 0]],
                          loads={"P": [0.0, 1.0]}, kn=1e4, kt=1e4, cn=10.0, names="glue",
                          bond=sc.Bond(tensile=1.0, shear=1.0, alpha=0.5))
    with pytest.raises(ModelError) as exc:
        sc.solve_dynamic(dm, dt=1e-3, duration=1e-2, loads={"P": Constant(1.0)},
                         mass=np.eye(2))
    assert exc.value.item == "interface 'glue'.bond"


def test_a_residual_cohesion_in_a_dynamic_interval_is_refused_naming_the_field():
    dm = sc.DiscreteModel(K=np.zeros((2, 2)), normal_rows=[[0, 1]], tangent_rows=[[1, 0]],
                          loads={"P": [0.0, 1.0]}, kn=1e4, kt=1e4, names="glue",
                          bond=sc.Bond(tensile=1.0, shear=1.0, alpha=0.5,
                                       residual_cohesion=0.5))
    with pytest.raises(ModelError) as exc:
        sc.solve_dynamic(dm, dt=1e-3, duration=1e-2, loads={"P": Constant(1.0)},
                         mass=np.eye(2))
    assert exc.value.item == "interface 'glue'.bond.residual_cohesion"


def test_a_water_pulse_runs_a_crack_along_a_bonded_dam_base_each_cfe_on_its_surface():
    """The bonded dam of tests/test_bonded_joints.py (a stiff block on a compliant bonded
    layer, Mohr–Coulomb strength with a tension cut-off) after its static program, hit by
    a water pulse: the crack runs along the base, CFE after CFE at increasing times (the
    layers' forces follow the displacements: no two break at one instant), each on its
    strength surface (to 1e-9 of Q_R) when it breaks; the ledger books the layers' released
    energy and balances."""
    m = bonded_dam(lam_end=2.0)
    st = sc.solve_static(m)
    res = sc.solve_dynamic(m, initial=st, dt=2e-4, duration=2e-2, record_every=10,
                           loads={"water": Pulse(60.0, 0.0, 0.02)})
    assert res.status == Status.COMPLETED, res.message
    br = _broken(res)
    assert len(br) == int(np.sum(st.state[-1] == BONDED)) > 5  # every bond breaks
    times = np.array([e.lam for e in br])
    assert np.all(np.diff(times) > 0)
    pos = np.array([res.cfe["x"][e.cfe, 0] for e in br])
    assert np.all(np.diff(pos) < 0) or np.all(np.diff(pos) > 0)  # a crack running
    A, x = res.cfe["area"], res.cfe["x"][:, 0]
    NR, QR = A * np.interp(x, [0.0, B], TENSILE), A * COHESION
    al = np.tan(np.radians(PHI))
    for e in br:
        k = e.cfe
        margin = min(NR[k] - e.N, QR[k] - al * e.N - abs(e.Q))
        assert abs(margin) <= 1e-9 * QR[k]
    assert res.energy["fracture"][-1] > 0
    assert np.abs(res.energy["error"]).max() <= 1e-8 * res.energy["external"].max()
