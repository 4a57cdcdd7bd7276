"""The stilling-basin slab study's model and criterion against closed forms.

* uniform net uplift Δp on a slab of unit weight γ_c: the slab floats exactly at
  h = Δp / (γ_c − γ_w), whatever the stiffness of the slab and of the soil;
* the same pressure as a pulse on a slab on a compliant (Winkler) layer: a slowly rising pulse
  gives the static thickness, a step doubles it (dynamic amplification 2 of a suddenly applied
  load on a spring–mass system);
* a triangular deficit load (peak q₀ at the upstream edge, zero at 2L/3) on a slab on a
  Winkler layer: the upstream edge lifts off at the kern-rule thickness of a rigid slab
  (:func:`stepcontact.study.hydraulics.kern_liftoff_thickness`), approached as the slab's
  stiffness grows;
* the limit found by bisection: a slab thicker than it passes, one thinner by the tolerance
  fails.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.errors import ModelError
from stepcontact.study import hydraulics as hy
from stepcontact.study.slab import GAMMA_W, Impulse, Slab, check, limit_thickness, slab_model

CONCRETE = sc.Material(30e9, 0.2, 2400.0)


@pytest.mark.parametrize("slab_E, soil_E", [(30e9, 200e6), (3e9, 2e9)])
def test_uniform_net_uplift_floats_the_slab_at_the_closed_form_thickness(slab_E, soil_E):
    dp = 25.5e3  # Pa: Ω (C⁺ + C⁻) γ_w V1²/2g of the reference case (2.60 m of water)
    slab = Slab(length=20.0, thickness=1.0, concrete=sc.Material(slab_E, 0.2, 2400.0),
                soil=sc.Material(soil_E, 0.3, 2000.0), cells=(20, 2), uplift=dp)
    lim = limit_thickness(slab, tol=1e-3, criterion="separation")
    exact = dp / (2400.0 * 9.81 - GAMMA_W)
    assert lim.failing < exact <= lim.passing + 1e-12
    assert lim.passing - lim.failing <= 1e-3
    # the thinner slab's run ends with the slab afloat: equilibrium lost by lift-off
    thin = [t for t in lim.trials if t.thickness == lim.failing][0]
    assert thin.lifted and not thin.slid and thin.status == "equilibrium_lost"


def _sdof_limit(dp: float, impulse: Impulse, kn: float, T_end: float) -> float:
    """The thickness at which a rigid slab (mass ρ h per m²) on a Winkler layer (kn, Pa/m)
    just lifts off under the pulse Δp g(t) from rest: k max u(t) = (γ_c − γ_w) h, with the
    closed-form response of the undamped spring–mass system within the pulse (Biggs):
    half-sine sin(Ωt), Ω = π/t_d: u/u_st = (sin Ωt − r sin ωt)/(1 − r²), r = Ω/ω;
    a step from t₀: u/u_st = 1 − cos ω(t − t₀).  The root by brentq."""
    from scipy.optimize import brentq

    t = np.linspace(0.0, T_end, 400_001)
    assert T_end <= impulse.start + impulse.duration  # (the window lies within the pulse)

    def excess(h):
        w = np.sqrt(kn / (2400.0 * h))
        tau = np.clip(t - impulse.start, 0.0, None)
        if impulse.shape == "half_sine":
            r = (np.pi / impulse.duration) / w
            ratio = (np.sin(r * w * tau) - r * np.sin(w * tau)) / (1 - r**2)
        else:
            ratio = 1 - np.cos(w * tau)
        return dp * ratio.max() - (2400.0 * 9.81 - GAMMA_W) * h

    return brentq(excess, 0.5, 5.0, xtol=1e-6)


def test_joints_against_the_neighbours_hold_the_ends_but_not_the_uplift():
    dp = 25.5e3
    free = Slab(length=20.0, thickness=1.0, cells=(20, 2), uplift=dp)
    exact = dp / free.net_unit_weight
    walls = dataclasses.replace(free, end_joints=0.0)
    m = slab_model(walls)
    assert [i.name for i in m.interfaces] == ["upstream", "downstream", "base"]
    # frictionless end joints push only horizontally: the slab floats at the same thickness
    lim = limit_thickness(walls, tol=1e-3, criterion="separation")
    assert lim.failing < exact <= lim.passing + 1e-12
    # with friction they can only hold it down more
    rough = limit_thickness(dataclasses.replace(free, end_joints=0.6), tol=1e-3,
                            criterion="separation")
    assert rough.passing >= lim.failing


def test_a_pulse_of_uplift_lifts_the_slab_as_a_spring_mass_system_predicts():
    dp, kn = 20e3, 50e6
    slab = Slab(length=20.0, thickness=2.0, concrete=sc.Material(300e9, 0.2, 2400.0),
                soil=None, layer=sc.ContactLayer(kn=kn, kt=20e6), cells=(10, 2))
    static = dp / slab.net_unit_weight
    # the slab on the layer: ω = sqrt(k/(ρ h)) ≈ 120 rad/s, T ≈ 0.05 s.  A slow half-sine
    # (3 s) needs about the static thickness; a step twice it (amplification 2)
    slow = Impulse(0.5, dp, 3.0, footprint=21.0, shape="half_sine")
    lim = limit_thickness(slab, slow, tol=0.005, h0=1.5, dt=0.02, duration=1.6, alpha=0.0)
    ref = _sdof_limit(dp, slow, kn, 1.6)
    assert ref / static == pytest.approx(1.0, abs=0.02)
    assert lim.thickness == pytest.approx(ref, abs=0.01)
    step = Impulse(0.5, dp, 0.1, footprint=21.0, shape="rectangular", start=0.005)
    lim = limit_thickness(slab, step, tol=0.005, h0=3.0, dt=1e-3, duration=0.08, alpha=0.0)
    ref = _sdof_limit(dp, step, kn, 0.08)
    assert ref / static == pytest.approx(2.0, abs=0.01)
    assert lim.thickness == pytest.approx(ref, abs=0.01)
    # what failed: the dynamic response lifted the slab, after the step
    failed = [t for t in lim.trials if not t.passes]
    assert all(t.phase == "dynamic" and t.lifted and t.when > 0.005 for t in failed)


def test_a_triangular_deficit_lifts_the_upstream_edge_at_the_kern_thickness():
    L = 40.0
    q0 = 0.6 * (8.77 - 0.99) * GAMMA_W  # 0.6 (h2 − h1) of water at the upstream edge, Pa
    a = 2 * L / 3
    kern = hy.kern_liftoff_thickness(q0, a, L)
    errors = []
    for E in (30e9, 300e9, 3e12):
        slab = Slab(length=L, thickness=3.0, concrete=sc.Material(E, 0.2, 2400.0), soil=None,
                    layer=sc.ContactLayer(kn=50e6, kt=20e6), cells=(40, 3),
                    uplift=lambda x: q0 * np.clip(1 - x / a, 0, None))
        lim = limit_thickness(slab, tol=2e-3)
        errors.append(lim.thickness / kern - 1)
        first = [t for t in lim.trials if t.thickness == lim.failing][0]
        assert first.lifted and first.phase == "static"
    # a flexible slab needs more than the rigid kern rule; the gap closes as EI grows
    assert errors[0] > errors[1] > errors[2] > 0
    assert errors[2] < 0.01


def test_the_limit_brackets_a_slab_that_passes_and_one_that_fails():
    slab = Slab(length=20.0, thickness=1.0, concrete=CONCRETE, soil=sc.Material(200e6, 0.3,
                2000.0), cells=(16, 2), top=(15e3, 40e3), uplift=60e3)
    tol = 0.01
    lim = limit_thickness(slab, tol=tol)
    assert check(slab.with_thickness(lim.thickness + 0.2 * tol)).passes
    thinner = check(slab.with_thickness(lim.thickness - tol))
    assert not thinner.passes and thinner.lifted
    assert thinner.when is not None and 0 < thinner.when <= 1


def test_the_model_of_the_slab_and_bad_inputs():
    slab = Slab(length=12.0, thickness=1.5, cells=(12, 2), top=10e3, uplift=(30e3, 20e3),
                water_depth=5.0)
    m = slab_model(slab, Impulse(0.25, 5e3, 0.5, footprint=3.0, direction="down"))
    assert {p.name for p in m.patterns} == {"weight", "top", "uplift", "impulse"}
    system = sc.assemble(m)
    # the resultants: the slab's weight, the top pressure, the uplift on the slab only where
    # the joint is (and its reaction on the soil), the impulse's footprint on the top
    fy = {name: system.loads[name].f[system.dofs.of[:, 1][system.dofs.of[:, 1] >= 0]].sum()
          for name in system.loads}
    assert fy["weight"] == pytest.approx(-2400 * 9.81 * 12 * 1.5, rel=1e-12)
    assert fy["top"] == pytest.approx(-10e3 * 12, rel=1e-12)
    assert fy["uplift"] == pytest.approx(0.0, abs=1e-6)  # both faces: equal and opposite
    assert fy["impulse"] == pytest.approx(-3.0, rel=0.35)  # 1 Pa on a 3 m footprint (mesh)
    # the water above as added mass: ρ_w · depth per unit area of the top, vertical only
    from stepcontact.study.slab import _added_mass

    dry = _added_mass(system, dataclasses.replace(slab, water_depth=0.0)).diagonal()
    wet = _added_mass(system, slab).diagonal()
    ydof = system.dofs.of[:, 1][system.dofs.of[:, 1] >= 0]
    xdof = system.dofs.of[:, 0][system.dofs.of[:, 0] >= 0]
    assert (wet - dry)[ydof].sum() == pytest.approx(1000.0 * 5.0 * 12.0, rel=1e-12)
    assert np.array_equal(wet[xdof], dry[xdof])
    for bad, item in ((dict(thickness=-1.0), "slab.thickness"),
                      (dict(friction=-0.1), "slab.friction"),
                      (dict(uplift="high"), "slab.uplift"),
                      (dict(cells=(0, 2)), "slab.cells"),
                      (dict(end_joints=-0.5), "slab.end_joints")):
        with pytest.raises(ModelError, match=item.replace(".", r"\.")):
            dataclasses.replace(slab, **bad)
    with pytest.raises(ModelError, match="impulse.direction"):
        Impulse(0.5, 1e3, 0.1, direction="sideways")
    with pytest.raises(ModelError, match="impulse.position"):
        Impulse(1.5, 1e3, 0.1)
    with pytest.raises(ModelError, match="criterion"):
        check(slab, criterion="cracks")


def test_with_the_joints_pressure_in_the_gap_an_impulse_at_the_upstream_joint_lifts_the_slab():
    """gap_pressure="joint": where the base has opened in a run from the upstream edge, the
    pressure at the upstream joint (the mean uplift there, p₀, plus the impulse's pressure at
    x = 0) acts in the gap instead of the uplift, following the opened length in time.  An
    impulse under the upstream end opens the edge; the joint's pressure then lifts the whole
    slab, which the uplift alone (falling from p₀ to p₁ downstream) does not."""
    p0, p1, amp = 30e3, 5e3, 20e3
    base = Slab(length=20.0, thickness=1.5, cells=(20, 2), soil=None,
                layer=sc.ContactLayer(kn=2e8, kt=2e8), uplift=(p0, p1), buoyancy=False)
    imp = Impulse(position=0.0, amplitude=amp, duration=0.2, footprint=4.0, direction="up")
    held = check(base, imp, criterion="separation")
    assert held.passes
    slab = dataclasses.replace(base, gap_pressure="joint")
    out = check(slab, imp, criterion="separation", keep=True)
    assert not out.passes and out.lifted and out.phase == "dynamic"
    res = out.result
    g = imp.time_function()
    wet = res.crack_pressure != 0  # (W = A (p_c − p_u) is 0 where p_c = p_u: at x = 0)
    assert wet[-1].all()  # the whole base is open and wet: the slab is afloat
    scale = float(np.abs(res.N).max())
    for i in np.flatnonzero(wet.any(axis=1)):
        np.testing.assert_allclose(res.crack_pressure[i][wet[i]], p0 + g(res.time[i]),
                                   rtol=1e-9)
        np.testing.assert_allclose(res.N[i][wet[i]], 0.0, atol=1e-12 * scale)
        run = wet[i][np.argsort(res.cfe["x"][:, 0])]
        assert run[0] and np.all(run[: run.sum()])  # a run from the upstream edge
    # the model: crack water entering at the upstream edge, p₀ and the impulse's pressure
    waters = {p.name: [ld for ld in p.loads if isinstance(ld, sc.CrackWater)]
              for p in slab_model(slab, imp).patterns}
    assert waters["uplift"][0].pressure == pytest.approx(p0)
    assert waters["impulse"][0].pressure == 1.0 and waters["impulse"][0].entry == (0.0, 0.0)
    assert not any(waters[n] for n in ("weight", "top"))
    with pytest.raises(ModelError, match="slab.gap_pressure"):
        dataclasses.replace(base, gap_pressure="tailwater")


def test_a_search_near_a_known_limit_steps_from_it():
    """limit_thickness(step=…): moving by step, 2 step, … from h0 instead of halving or
    doubling.  A uniform net uplift floats the slab at Δp/(γ_c − γ_w) (closed form): started
    0.05 m above it with step = tol = 0.01 m, the search brackets the closed form within tol
    in 4 bracket trials and a short bisection (halving from h0 would need more); a bad step
    names itself."""
    dp = 25.5e3
    slab = Slab(length=20.0, thickness=2.0, concrete=CONCRETE,
                soil=sc.Material(200e6, 0.3, 2000.0), cells=(10, 2), uplift=dp)
    exact = dp / (2400.0 * 9.81 - GAMMA_W)
    lim = limit_thickness(slab, tol=0.01, h0=exact + 0.05, step=0.01, criterion="separation")
    # (at exactly the closed-form thickness the slab just floats: a failing trial)
    assert lim.failing <= exact + 1e-12 and exact < lim.passing
    assert lim.passing - lim.failing <= 0.01 + 1e-12
    # h0 = exact + 0.05 passes, then − 0.01, − 0.02 pass, − 0.04 fails: 4 trials, then the
    # bracket of 0.04 m bisected to 0.01 m in 2 (3 with the round-off of 0.01 > tol)
    assert len(lim.trials) <= 7
    with pytest.raises(ModelError, match="step"):
        limit_thickness(slab, tol=0.01, step=-1.0)
