"""A load segment that was to run absurdly far beyond the limit load gives the same limit as one
that ends near it (the segment-start scales look ahead only as far as the path's size allows,
``StaticSolver._segment_scales``; before, the tolerances LIMIT_TOL · rtol × the load at the
segment's nominal end were of the size of the real forces: a slip load off by 6e-5, or
equilibrium "lost" at once at the segment's start).

References (independent of the code under test) and tolerances:

* a 2 m × 1 m slab (2 × 2 cells, plane strain) on an elastic base with friction f = 0.6, under
  its weight W = ρ g A (per metre) and then a horizontal force of 1 N per unit λ on its top
  corner: rigid-body statics gives the sliding load f W; the limit λ equals it to 1e-9 relative
  for segment ends 1e3, 1e6, 1e10 and 1e13 times the slip load;
* a 1 × 1 × 0.5 m block on a rough rigid plane (and on an elastic base block through a
  non-matching mortar interface), faceted k-gon cone, pushed along θ: the limit
  f W cos(π/k) / cos(θ − θ_f) (``faceted_reference.slip_limit``) to 1e-9 relative for the same
  segment ends, with statics (force and moment) and the contact conditions at every recorded
  state to 1e-9 of W (``test_contact3d.assert_block_statics``);
* every reported state's equilibrium residual and contact violation ≤ 1e-9.
"""

from __future__ import annotations

import math

import pytest

import faceted_reference as fr
import stepcontact as sc
from test_contact3d import F, W, assert_block_statics, block_model
from test_water_level import CONCRETE as DAM_CONCRETE
from test_water_level import GAMMA, dam

TOL = 1e-9
ENDS = (1e3, 1e6, 1e10, 1e13)  # segment end / slip load

CONCRETE = sc.Material(E=25e9, nu=0.2, density=2400)
F2D = 0.6
W2D = 2400 * 9.81 * 2.0  # the slab's weight per metre, N


def pushed_slab(end: float) -> sc.Model:
    """The 2 m × 1 m slab (2 × 2 cells) on a 4 m × 1 m base (fixed at its bottom), friction
    0.6; its weight, then 1 N per unit λ along +x at its top-left corner up to λ = ``end``."""
    slab = sc.rectangle("slab", (0, 0), (2.0, 1.0), 2, 2, CONCRETE)
    rock = sc.rectangle("rock", (-1, -1), (3, 0), 4, 1, CONCRETE)
    m = sc.Model(bodies=[rock, slab], name="pushed slab")
    return m.add(
        sc.Support("deep", m.select("rock", y=-1), "xy"),
        sc.Interface("base", m.select("slab", y=0), m.select("rock", y=0), friction=F2D),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("slab",))]),
        sc.LoadPattern("push", [sc.NodalLoad(m.select("slab", x=0.0, y=1.0), fx=1.0)]),
        sc.Segment("weight", 1.0), sc.Segment("push", end))


@pytest.mark.parametrize("ratio", ENDS)
def test_2d_slab_slides_at_f_w_whatever_the_segment_end(ratio):
    """The slab loses equilibrium at f W (1e-9 relative) for a push segment ending 1e3 … 1e13
    times beyond it; every state exact to 1e-9."""
    slip = F2D * W2D
    res = sc.solve_static(pushed_slab(ratio * slip))
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert res.segment[-1] == 1
    assert res.lam[-1] == pytest.approx(slip, rel=TOL)
    assert res.residual.max() <= TOL and res.violation.max() <= TOL


@pytest.mark.parametrize("k, theta, base", [
    (8, 0.3, None), (4, 0.0, None), (8, math.pi / 8, (3, 3, 1))])
def test_3d_block_slides_at_the_polygon_limit_whatever_the_segment_end(k, theta, base):
    """A block on a rigid plane (or on a base through a non-matching mortar interface) loses
    equilibrium at f W cos(π/k) / cos(θ − θ_f) (1e-9 relative) for push segments ending 1e3 …
    1e13 times beyond it; statics and contact conditions at every state to 1e-9."""
    slip = fr.slip_limit(F * W, k, theta)
    for ratio in ENDS:
        model = block_model(k, theta, base=base, cfe="auto" if base is None else "mortar",
                            push_end=ratio * slip)
        res = sc.solve_static(model)
        assert res.status == sc.Status.EQUILIBRIUM_LOST, (ratio, res.message)
        assert res.lam[-1] == pytest.approx(slip, rel=TOL), ratio
        assert res.residual.max() <= TOL and res.violation.max() <= TOL, ratio
        assert_block_statics(model, res)


@pytest.mark.parametrize("top", [1e3, 1e7, 1e9, 1e11, 1e13])
def test_dam_slides_at_the_hand_level_whatever_the_segment_end(top):
    """A level path to 1e3 … 1e13 m: sliding at h = f W / (γ H_d) + H_d / 2 (above the crest,
    hand statics) to 1e-9 relative; every state exact to 1e-9."""
    f, height = 0.7, 10.0
    weight = DAM_CONCRETE.density * 9.81 * 8.0 * height
    h_star = f * weight / (GAMMA * height) + height / 2
    res = sc.solve_static(dam(f, height, top))
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(h_star, rel=TOL)
    assert res.residual.max() <= TOL and res.violation.max() <= TOL
