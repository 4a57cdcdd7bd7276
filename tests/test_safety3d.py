"""The safety of a 3D joint (``res.interface_safety`` on a 3D result,
:mod:`stepcontact.results.safety3d`) against hand statics.

A 2 × 1 × 1 m block (hex8) of weight W on a rough rigid plane z = 0 (f = 0.6, the cone as an
8-gon), pushed on its top face (z = 1 m) by λ N along θ.  The CFE forces balance the loads on the
block whatever its elasticity, so at every state (to 1e-9 relative):

* ΣN = −W, the shear on the joint S = λ (cos θ, sin θ), the resultant of the CFE forces on
  the block R = (−λ cos θ, −λ sin θ, W);
* the normal resultant's eccentricity from the joint's centroid (1, 0.5, 0) is e = λ z_top / W
  along θ (the push's moment about the joint plane over the normal force);
* the sliding factor is f W / λ; the kern check |e₁|/2 + |e₂|/1 ≤ 1/6 and the base check
  |e₁| ≤ 1, |e₂| ≤ 0.5 follow from e;
* the run loses equilibrium by sliding at the 8-gon's limit (``lam_sliding``), or — pushed
  across, θ = π/2 — by tipping about the long edge where e₂ = 1/2 m, λ = W/2
  (``lam_overturning``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import faceted_reference as fr
import stepcontact as sc
from stepcontact.model.mesh import box

RHO, G, F, K = 2400.0, 9.81, 0.6, 8
W = RHO * G * 2.0
TOL = 1e-9


def pushed_block(theta: float) -> sc.Model:
    blk = box("block", (0, 0, 0), (2.0, 1.0, 1.0), (4, 2, 2), sc.Material(25e9, 0.2, RHO))
    m = sc.Model(bodies=[blk])
    return m.add(
        sc.Interface("joint", m.select("block", boundary="bottom"), sc.RigidPlane("ground"),
                     friction=F, facets=K),
        sc.LoadPattern("weight", [sc.BodyForce(g=(0, 0, -G))]),
        sc.LoadPattern("push", [sc.EdgeForce(m.select("block", boundary="top"),
                                             fx=math.cos(theta), fy=math.sin(theta))]),
        sc.Segment("weight", 1.0), sc.Segment("push", 1e5))


@pytest.mark.parametrize("theta", [0.0, 0.4, math.pi / 2])
def test_joint_safety_matches_hand_statics(theta):
    res = sc.solve_static(pushed_block(theta))
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    sf = res.interface_safety("joint")
    fac = np.asarray(res.factors)
    lw, lp = fac[:, 0], fac[:, 1]
    d = np.array([math.cos(theta), math.sin(theta)])
    assert np.allclose(sf.centroid, [1.0, 0.5, 0.0], atol=1e-12)
    assert np.allclose(sf.axes, np.eye(3), atol=1e-12)
    assert np.allclose(sf.extent, [2.0, 1.0], atol=1e-12)
    assert np.abs(sf.normal_force + W * lw).max() <= TOL * W
    assert np.abs(sf.shear - lp[:, None] * d).max() <= TOL * W
    assert np.abs(sf.resultant - np.column_stack([-lp * d[0], -lp * d[1], W * lw])).max() <= TOL * W
    on = lw == 1.0  # the weight is on: the resultant's point exists
    e = (lp[on] * 1.0 / W)[:, None] * d
    assert np.abs(sf.eccentricity[on] - e).max() <= TOL
    pushed = on & (lp > 0)
    assert np.abs(sf.sliding_factor[pushed] - F * W / lp[pushed]).max() <= TOL * F * W / lp[
        pushed].min()
    kern = (np.abs(e) / [2.0, 1.0]).sum(axis=1) <= 1 / 6
    assert np.array_equal(sf.in_kern[on], kern)
    assert np.array_equal(sf.in_base[on], np.all(np.abs(e) <= [1.0, 0.5], axis=1))
    assert sf.friction == F
    assert sf.facets == K and sf.cone_bound == pytest.approx(1 - math.cos(math.pi / K), rel=1e-15)
    slide, tip = fr.slip_limit(F * W, K, theta), 0.5 * W  # tipping about the long edge: e₂ = 1/2
    if theta == math.pi / 2:  # pushed across: the block tips over before it slides
        assert tip < slide and sf.lam_sliding is None
        assert sf.lam_overturning == pytest.approx(tip, rel=TOL)
    else:
        assert sf.lam_sliding == pytest.approx(slide, rel=TOL) and sf.lam_overturning is None
        assert sf.at(-1)["sliding_factor"] == pytest.approx(F * W / slide, rel=TOL)


def test_unknown_interface_is_a_key_error_naming_the_known():
    res = sc.solve_static(pushed_block(0.0))
    with pytest.raises(KeyError, match="'joint'"):
        res.interface_safety("base")


def test_cone_ratio_is_nan_on_open_cfes():
    """Pushed across until it tips, the block's open CFEs carry round-off forces: their
    true-cone ratio |Q|/(f|N|) is NaN (not a ratio of two round-off numbers); a closed
    slipping CFE's lies in [cos(π/k), 1] (1e-12)."""
    res = sc.solve_static(pushed_block(math.pi / 2))
    ratio = np.asarray(res.cone_ratio)
    state = np.asarray(res.state)
    is_open = state == int(sc.ContactState.OPEN)
    assert is_open[-1].any() and np.all(np.isnan(ratio[is_open]))
    closed = ~is_open & np.isfinite(ratio)
    assert np.all(ratio[closed] <= 1 + 1e-12)
