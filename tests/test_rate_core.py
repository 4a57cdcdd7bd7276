"""The rate problem of a point's core (:func:`stepcontact.solver.rate._core_outcome`).

A point with many CFEs in mid-slip first solves the rate problem of its core (the CFEs that
fired, the stuck and the open ones, those at a normal limit) with the others kept slipping,
and takes it when its rates leave every CFE in its state.  Reference: the same run with the
whole problem at every point (``CORE_MIN`` above any L): the same events (CFEs and
transitions) at the same λ (1e-9 relative) and the same final forces (1e-9 of max |N|).
"""

from __future__ import annotations

import numpy as np
import pytest

import stepcontact as sc
import stepcontact.solver.rate as rate
from stepcontact.enums import Status

L, DEPTH = 12.0, 8.0  # m


def slab(n: int = 6) -> sc.Model:
    """A concrete slab L × L × 1 m (n × n × 1 hex8) on a rock block (meshes matching on the
    joint, f = 0.7 on the 8-faceted cone): its weight, a push on one face (1e5 Pa), then an
    eccentric uplift from one corner (40 kPa there) that opens part of the joint while the
    rest slips and turns (the slab lifts off before the uplift's end)."""
    concrete = sc.Material(E=30e9, nu=0.2, density=2400)
    rock = sc.Material(E=5e9, nu=0.25)
    e = n // 2
    a = e * L / n
    m = sc.Model(bodies=[sc.box("foundation", (-a, -a, -DEPTH), (L + a, L + a, 0.0),
                                (n + 2 * e, n + 2 * e, 2), rock),
                         sc.box("slab", (0, 0, 0), (L, L, 1.0), (n, n, 1), concrete)])
    eps = 1e-6 * L
    under = m.select("foundation", lambda x, y, z: (np.abs(z) < eps) & (x > -eps)
                     & (x < L + eps) & (y > -eps) & (y < L + eps))
    bottom = m.select("slab", boundary="bottom")
    return m.add(
        sc.Support("bed", m.select("foundation", boundary="bottom"), "xyz"),
        sc.Interface("joint", bottom, under, friction=0.7, facets=8),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("slab",))]),
        sc.LoadPattern("push", [sc.EdgeLoad(m.select("slab", boundary="left"), normal=1.0)]),
        sc.LoadPattern("uplift", [sc.EdgeLoad(bottom, normal=lambda x, y, z:
                                              (1 - x / L) * (1 - 0.5 * y / L))]),
        sc.Segment("weight", 1.0), sc.Segment("push", 1e5), sc.Segment("uplift", 4e4))


@pytest.fixture(scope="module")
def system():
    return sc.assemble(slab())


def _run(system, monkeypatch, core_min: int):
    monkeypatch.setattr(rate, "CORE_MIN", core_min)
    taken = []
    orig = rate._core_outcome

    def counted(*args, **kw):
        out = orig(*args, **kw)
        taken.append(out is not None)
        return out

    monkeypatch.setattr(rate, "_core_outcome", counted)
    return sc.solve_static(system), taken


def test_the_core_problem_gives_the_whole_problems_events(system, monkeypatch):
    core, taken = _run(system, monkeypatch, 8)
    whole, none = _run(system, monkeypatch, 10**9)
    assert not none and sum(taken) >= 5  # (the core was decided at several points)
    assert core.status == whole.status
    assert core.status in (Status.COMPLETED, Status.EQUILIBRIUM_LOST)
    a, b = core.multipliers[-1], whole.multipliers[-1]
    assert (a.equilibrium_lost is None) == (b.equilibrium_lost is None)
    if a.equilibrium_lost is not None:
        assert a.equilibrium_lost == pytest.approx(b.equilibrium_lost, rel=1e-9)
    ev = [(e.cfe, e.transition) for e in core.events]
    assert ev == [(e.cfe, e.transition) for e in whole.events]
    assert len(ev) > 100 and {e.transition.value for e in core.events} >= {"opened", "turned"}
    lam = np.array([e.lam for e in core.events])
    np.testing.assert_allclose(lam, [e.lam for e in whole.events], rtol=1e-9)
    N = np.abs(np.asarray(whole.N)).max()
    np.testing.assert_allclose(core.N[-1], whole.N[-1], rtol=0, atol=1e-9 * N)
    np.testing.assert_allclose(core.Q[-1], whole.Q[-1], rtol=0, atol=1e-9 * N)
    assert core.residual.max() < 1e-6 and core.violation.max() < 1e-9
