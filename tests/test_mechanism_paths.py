"""Lost equilibrium is a result, on every kind of path (issue 28: no crash, no 'violation' stop
where the structure becomes a mechanism).

References and tolerances:

* a block on a frictionless base, under its weight and then a rising water level whose pattern
  also carries a vertical load of its own (per metre of water): the wetted face starts at
  y = b, so the water's horizontal thrust γ_w (h − b)² / 2 (per metre) starts with its
  quadratic term while the linear term of the level's load (the pattern's own vertical load)
  does not drive the sliding mode.  By hand, no horizontal force can be resisted: equilibrium
  is lost at h = b exactly (1e-12), by sliding; every state in equilibrium with the contact
  conditions to 1e-9;
* the 3D slab of ``benchmarks/slab3d.py`` (s = 1: 144 CFEs on the faceted 8-gon) pushed and then
  lifted by an eccentric uplift on to its mechanism (sliding with a rotation about z): near the
  limit the schemes soften and their rates grow without bound, which inflated the path's
  tolerances (rates × the whole segment, to 1e6 Pa) until open CFEs with a real gap were
  snapped shut (a force jump: status ``violation``, 1.25e-5).  Reference: the same model with
  the uplift segment ending just beyond the limit (43 kPa, 23 times shorter: scales of the
  path's own size) loses equilibrium at the same λ (1e-9 relative); every reported state in
  equilibrium with the contact conditions to 1e-9.
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np
import pytest

import stepcontact as sc

CONCRETE = sc.Material(E=25e9, nu=0.2, density=2400)
ROCK = sc.Material(E=20e9, nu=0.25, density=2600)


def frictionless_block_with_water(b: float) -> sc.Model:
    """A 4 m × 6 m block (1 m cells) on a rock base, frictionless joint; its upstream face
    x = 0 is wetted from y = ``b`` up; the level pattern also pushes down 1 kN per metre of
    water on the block's top (its own load); the level rises from 0 to 5 m."""
    body = sc.rectangle("block", (0, 0), (4.0, 6.0), 4, 6, CONCRETE)
    rock = sc.rectangle("rock", (-2, -2), (6, 0), 8, 2, ROCK)
    m = sc.Model(bodies=[rock, body], name="frictionless block")
    face = m.select("block", lambda x, y: (np.abs(x) < 1e-9) & (y >= b - 1e-9))
    return m.add(
        sc.Support("deep", m.select("rock", y=-2), "xy"),
        sc.Interface("base", m.select("block", y=0), m.select("rock", y=0), friction=0.0),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
        sc.LoadPattern("reservoir", [
            sc.WaterLoad(face, level=None),
            sc.NodalLoad(m.select("block", x=2.0, y=6.0), fy=-1000.0)]),
        sc.Segment("weight", 1.0),
        sc.Segment("reservoir", 5.0),
    )


@pytest.mark.parametrize("b", [2.0, 3.0])
def test_level_path_loses_equilibrium_where_a_higher_power_drives_it(b):
    """The quadratic term of the level drives the sliding mode that the linear term does not:
    equilibrium lost at h = b (1e-12), reported as such (not an exception out of the loop)."""
    res = sc.solve_static(frictionless_block_with_water(b))
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert "sliding" in res.message and "'reservoir'" in res.message
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(b, rel=1e-12)
    assert res.lam[-1] == pytest.approx(b, rel=1e-12) and res.segment[-1] == 1
    assert res.mechanism["lam"] == pytest.approx(b, rel=1e-12)
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-9


SLAB3D = Path(__file__).parents[1] / "benchmarks" / "slab3d.py"


@pytest.mark.slow
def test_3d_slab_lifted_on_to_its_mechanism_reports_it():
    """The slab loses equilibrium at the same λ whether its uplift segment was to end at 1e6 Pa
    or just beyond the limit (43 kPa): 1e-9; no 'violation' stop; states exact to 1e-9."""
    slab3d_model = runpy.run_path(str(SLAB3D), run_name="slab3d")["slab3d_model"]
    far = sc.solve_static(slab3d_model(1, uplift=1e6))
    near = sc.solve_static(slab3d_model(1, uplift=4.3e4))
    for res in (far, near):
        assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
        assert "'uplift', segment 2" in res.message
        assert res.residual.max() < 1e-9 and res.violation.max() < 1e-9
    lam = far.multipliers[-1].equilibrium_lost
    assert lam == pytest.approx(near.multipliers[-1].equilibrium_lost, rel=1e-9)
    assert 4.2e4 < lam < 4.3e4
