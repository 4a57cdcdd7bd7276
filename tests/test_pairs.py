"""Explicit node-pair CFEs (``Interface(pairs=True)``): a two-span beam on unilateral bearings.

Reference (closed form, Euler–Bernoulli beam, two equal spans L under a uniform load q): the
bearing reactions are 3qL/8, 10qL/8, 3qL/8 (the frame's self-weight uses consistent loads, so these
are exact).  An upward point load P at the middle bearing goes straight into that bearing, so it
lifts off exactly at P = 10qL/8; after that the end bearings carry qL − P/2 each.
"""

from __future__ import annotations

import numpy as np
import pytest

import stepcontact as sc

G = 9.81
SPAN = 2.0
RHO, AREA = 2500.0, 0.1
Q_LINE = RHO * AREA * G  # N/m


def _nodes(m: sc.Model, body: str, xs, y: float) -> sc.NodeSet:
    b = m.body(body)
    idx = [int(np.argmin(np.hypot(b.points[:, 0] - x, b.points[:, 1] - y))) for x in xs]
    return sc.NodeSet(body, np.array(idx), f"{body}@{xs}")


def beam_on_bearings(normal=None, gap_y: float = -0.1, p_up: float = 1.0) -> sc.Model:
    beam = sc.Frame.line("beam", (0.0, 0.0), (2 * SPAN, 0.0), 8, E=30e9, A=AREA, I=2e-3,
                         density=RHO)
    ground = sc.Frame.line("ground", (0.0, gap_y), (2 * SPAN, gap_y), 2, E=30e9, A=AREA,
                           I=2e-3)
    m = sc.Model(bodies=[beam, ground])
    xs = [0.0, SPAN, 2 * SPAN]
    mid = _nodes(m, "beam", [SPAN], 0.0)
    return m.add(
        sc.Support("ground", m.select("ground", where=lambda x, y: x > -1), "xyrz"),
        sc.Support("beam_x", mid, "x"),
        sc.Interface("bearings", _nodes(m, "beam", xs, 0.0), _nodes(m, "ground", xs, gap_y),
                     gap=0.0, pairs=True, normal=normal, area=0.04),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("beam",))]),
        sc.LoadPattern("lift", [sc.NodalLoad(mid, fy=p_up)]),
        sc.Segment("weight", 1.0),
        sc.Segment("lift", 1.5 * Q_LINE * SPAN),
    )


def test_bearing_reactions_and_lift_off_match_the_closed_form():
    res = sc.solve_static(beam_on_bearings())
    q_l = Q_LINE * SPAN
    # state at the end of the weight segment
    i = int(np.flatnonzero((res.segment == 0) & (res.kind == "segment_end"))[0])
    assert np.allclose(-res.N[i], [3 / 8 * q_l, 10 / 8 * q_l, 3 / 8 * q_l], rtol=1e-9)
    opened = [e for e in res.events if e.transition == sc.Transition.OPENED]
    assert [e.cfe for e in opened] == [1]
    assert opened[0].lam == pytest.approx(10 / 8 * q_l, rel=1e-9)
    # a lifted middle bearing leaves a single span 2L: the ends carry q L − P/2 each
    assert np.allclose(-res.N[-1][[0, 2]], [0.25 * q_l, 0.25 * q_l], rtol=1e-9)
    assert np.all(res.cfe["area"] == 0.04)
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-9


def test_given_normal_is_used_and_gap_is_along_it():
    # ends 0.1 m apart vertically; a normal (0, 1) gives the same answer as the direction
    a = sc.solve_static(beam_on_bearings(normal=(0.0, 1.0)))
    b = sc.solve_static(beam_on_bearings())
    assert np.allclose(a.cfe["normal"], [[0.0, 1.0]] * 3)
    assert np.allclose(a.N, b.N, rtol=1e-12, atol=1e-9)


def test_coincident_ends_without_normal_is_an_error():
    with pytest.raises(sc.ModelError, match=r"bearings.*CFE 0.*ends coincide and no normal"):
        sc.assemble(beam_on_bearings(gap_y=0.0))
    # with a normal it is fine
    sc.assemble(beam_on_bearings(gap_y=0.0, normal=(0.0, 1.0)))


def test_pairs_need_equal_counts_and_positive_area():
    m = beam_on_bearings()
    itf = m.interfaces[0]
    with pytest.raises(sc.ModelError, match=r"bearings'.pairs.*3 nodes.*2"):
        sc.Interface("bearings", itf.plus, sc.NodeSet("ground", itf.minus.index[:2]),
                     pairs=True)
    with pytest.raises(sc.ModelError, match=r"bearings'.area.*> 0"):
        sc.Interface("bearings", itf.plus, itf.minus, pairs=True, area=-1.0)
