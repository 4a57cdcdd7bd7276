"""Damped (Kelvin–Voigt) contact layers in dynamics, against closed forms.

* a mass striking a damped layer (C_n, c_n): the contact phase is the damped oscillator
  m ẍ + c ẋ + k x = 0, x(0) = 0, ẋ(0) = V, x(τ) = V/ω_d e^{−ζωτ} sin ω_d τ; the force
  k x + c ẋ jumps to c V at the touch, the layer lets go where that force returns to zero
  (τ_s: a root of the closed form, found by brentq), and the mass leaves with ẋ(τ_s)
  (Schwager & Pöschel 2007 give the same restitution coefficient in closed form);
* a body bouncing and sliding on a damped, frictional layer under gravity comes to rest on
  the layer's static compression, with the energy ledger balanced to round-off;
* the slab on a compliant (damped or undamped) joint under an uplift pulse: the contact
  conditions hold at every reported state and the ledger balances.
"""

from __future__ import annotations

import dataclasses
import runpy
from pathlib import Path

import numpy as np
import pytest
import scipy.optimize as so

import stepcontact as sc
from stepcontact.enums import Transition
from stepcontact.errors import ModelError

MASS, K, ZETA, V, GAP = 1.0, 1e4, 0.2, 1.0, 1e-3
C = 2 * ZETA * np.sqrt(K * MASS)


def _kelvin_voigt():
    """(contact duration τ_s, exit velocity ẋ(τ_s), force history p(τ)) of the closed form."""
    w = np.sqrt(K / MASS)
    wd = w * np.sqrt(1 - ZETA**2)

    def x(t):
        return V / wd * np.exp(-ZETA * w * t) * np.sin(wd * t)

    def xd(t):
        return V * np.exp(-ZETA * w * t) * (np.cos(wd * t) - ZETA * w / wd * np.sin(wd * t))

    def p(t):
        return K * x(t) + C * xd(t)

    ts = so.brentq(p, 1e-9, np.pi / wd, xtol=1e-15)
    return ts, xd(ts), p


def _strike(dt):
    dm = sc.DiscreteModel([[0.0]], [[1.0]], [[0.0]], gaps=GAP, kn=K, kt=np.inf, cn=C)
    return sc.solve_dynamic(dm, dt=dt, duration=0.05, mass=[[MASS]], v0=np.array([-V]))


def test_a_mass_striking_a_damped_layer_follows_the_kelvin_voigt_closed_form():
    ts, v_exit, p = _kelvin_voigt()
    t_touch = GAP / V
    errors = []
    for dt in (1e-3, 5e-4, 2.5e-4):
        res = _strike(dt)
        assert res.status == sc.Status.COMPLETED
        assert res.violation.max() < 1e-9
        tr = [(e.transition, e.lam) for e in res.events]
        assert [t for t, _ in tr] == [Transition.CLOSED, Transition.OPENED]
        assert tr[0][1] == pytest.approx(t_touch, abs=1e-12)
        # the dashpot's share of the impact: the force jumps to c V at the touch
        at_touch = np.flatnonzero(np.isclose(res.lam, t_touch, rtol=0, atol=1e-12))
        assert -res.N[at_touch[-1], 0] == pytest.approx(C * V, rel=1e-9)
        # the force history against the closed form, within (Δt ω)² of c V
        inside = (res.lam >= t_touch) & (res.lam <= tr[1][1])
        err_p = np.abs(-res.N[inside, 0] - p(res.lam[inside] - t_touch)).max() / (C * V)
        assert err_p < 0.5 * (dt * np.sqrt(K / MASS)) ** 2
        errors.append(abs(tr[1][1] - (t_touch + ts)))
        # the mass leaves with the closed form's velocity and keeps it (the layer relaxes
        # behind it: no second touch)
        assert res.v[-1, 0] == pytest.approx(-v_exit, rel=1e-3)
        # the ledger: what the mass lost went into the dashpot (and the layer that still
        # relaxes), the rest is the cuts' numerical share; the balance is round-off
        e = res.energy
        lost = 0.5 * MASS * (V**2 - res.v[-1, 0] ** 2)
        assert abs(e["error"]).max() < 1e-10 * 0.5 * MASS * V**2
        assert e["damping"][-1] + e["strain"][-1] == pytest.approx(lost, rel=2e-4)
        assert e["impact"][-1] == 0.0
    # the opening time converges at second order as Δt is halved (far less than Δt)
    assert errors[0] < 0.05 * 1e-3
    order = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(order > 1.8), order


def test_a_body_bouncing_and_sliding_on_a_damped_frictional_layer_comes_to_rest():
    m_, kn, kt, cn, f, g0 = 1.0, 1e4, 5e3, 20.0, 0.3, 0.01
    dm = sc.DiscreteModel(np.zeros((2, 2)), [[0.0, 1.0]], [[1.0, 0.0]], gaps=g0, kn=kn, kt=kt,
                          cn=cn, friction=f, dof_names=("ux", "uy"),
                          loads={"g": {"uy": -9.81 * m_}})
    res = sc.solve_dynamic(dm, dt=1e-3, duration=1.2, mass=np.eye(2) * m_,
                           loads={"g": sc.Constant(1.0)}, v0=np.array([0.5, 0.0]))
    assert res.status == sc.Status.COMPLETED
    assert res.violation.max() < 1e-9
    kinds = {e.transition for e in res.events}
    assert {Transition.CLOSED, Transition.OPENED, Transition.STUCK} <= kinds
    assert kinds & {Transition.SLIP_POS, Transition.SLIP_NEG}
    # at rest on the layer's static compression m g / C_n below the touch
    assert res.u[-1, 1] == pytest.approx(-g0 - 9.81 * m_ / kn, rel=1e-6)
    assert abs(res.v[-1, 1]) < 1e-4  # (against 0.44 m/s at the first touch)
    e = res.energy
    assert abs(e["error"]).max() < 1e-9 * e["external"].max()
    assert e["damping"][-1] > 0.1 * e["external"][-1]  # the dashpot took a real share
    assert e["friction"][-1] > 0


@pytest.fixture(scope="module")
def slab():
    here = Path(__file__).resolve().parents[1] / "examples" / "slab_uplift.py"
    return runpy.run_path(str(here), run_name="slab_uplift")["slab_model"]()


@pytest.mark.parametrize("damping", [0.0, 1e7])
def test_a_slab_on_a_compliant_joint_keeps_the_contact_conditions(slab, damping, tmp_path):
    itf = dataclasses.replace(slab.interfaces[0],
                              layer=sc.ContactLayer(kn=5e9, kt=2e9, damping=damping))
    m = slab.replace(interfaces=(itf,) + slab.interfaces[1:])
    p_open = sc.solve_static(m).multipliers[-1].first_opening
    rest = sc.solve_static(m.replace(program=(sc.Segment("weight", 1.0),)))
    res = sc.solve_dynamic(m, dt=5e-4, duration=0.08, initial=rest, mass="lumped",
                           loads={"uplift": sc.Pulse(2.0 * p_open, 0.005, 0.04, "half_sine")})
    assert res.status == sc.Status.COMPLETED
    assert any(e.transition == Transition.OPENED for e in res.events)
    assert res.violation.max() < 1e-9
    e = res.energy
    assert abs(e["error"]).max() < 1e-10 * e["external"].max()
    assert (e["damping"][-1] > 0) == (damping > 0)
    assert abs(e["impact"][-1]) < 1e-10 * e["external"].max()  # compliant: no impacts
    res.save(tmp_path / "slab.nc")  # the layer's damping is kept with the CFEs
    back = sc.load_result(tmp_path / "slab.nc")
    assert np.array_equal(back.cfe["cn"], res.cfe["cn"])
    assert (back.cfe["cn"].max() > 0) == (damping > 0)


def test_layer_damping_in_the_model_file_and_its_errors(tmp_path, slab):
    itf = dataclasses.replace(slab.interfaces[0],
                              layer=sc.ContactLayer(kn=5e9, kt=2e9, damping=3e6))
    sys_ = sc.assemble(slab.replace(interfaces=(itf,) + slab.interfaces[1:]))
    joint = sys_.cfe.interface == 0
    assert np.allclose(sys_.cfe.cn[joint], 3e6 * sys_.cfe.area[joint])
    with pytest.raises(ModelError, match="damping"):
        sc.assemble(slab.replace(interfaces=(dataclasses.replace(
            itf, layer=sc.ContactLayer(kn=5e9, kt=2e9, damping=-1.0)),) + slab.interfaces[1:]))
    with pytest.raises(ModelError, match=r"cn\[0\]"):
        sc.DiscreteModel([[1.0]], [[1.0]], [[0.0]], cn=1.0)  # a dashpot on rigid contact
    from stepcontact.io.modelfile import LayerSpec

    assert LayerSpec(kn=1e9, kt=1e9, damping=2e5).build().damping == 2e5
    assert LayerSpec(thickness=0.1, E=1e8, nu=0.2, damping=5.0).build().damping == 5.0
    with pytest.raises(ValueError, match="damping"):
        LayerSpec(kn=1e9, kt=1e9, damping=-2.0)
