"""The faceted Coulomb law on its own (no solver): the polygon's geometry against its closed
form, transitions, the rate variables and the states they stand for.

References: plane geometry of the regular k-gon inscribed in the circle of radius f p (vertices
on the circle): the distance of its boundary from the centre in direction θ is
f p cos(π/k) / cos(θ − θ_f), θ_f the nearest facet normal.  Tolerance 1e-12 (round-off).
"""

from __future__ import annotations

import numpy as np
import pytest

from stepcontact.contact.faceted import FacetedCoulombLaw
from stepcontact.contact.laws import OPENING
from stepcontact.enums import FACET_SLIP, VERTEX_SLIP, ContactState
from stepcontact.errors import ModelError

STICK, OPEN = int(ContactState.STICK), int(ContactState.OPEN)


def _law(k=8, angle=0.0, **kw):
    return FacetedCoulombLaw([0], 0.5, np.inf, np.inf, facets=k, angle=angle, **kw)


def _boundary(k, theta, theta0=0.0, fp=1.0):
    """|Q| on the polygon's boundary in direction θ (closed form, module docstring)."""
    normals = theta0 + (2 * np.arange(k) + 1) * np.pi / k
    dev = np.angle(np.exp(1j * (theta - normals)))
    return fp * np.cos(np.pi / k) / np.cos(np.abs(dev).min())


@pytest.mark.parametrize("k", [4, 8, 16, 32])
def test_boundary_in_every_direction(k):
    """Q on the closed-form boundary in direction θ has its smallest margin 0 and all others
    ≥ 0 (1e-12 of f p), over a full turn; a vertex is at f p, a facet's middle at f p cos(π/k)."""
    law = _law(k, angle=0.3)
    p = np.array([2.0])
    fp = 0.5 * 2.0
    for theta in np.linspace(0, 2 * np.pi, 97):
        r = _boundary(k, theta, 0.3, fp)
        Q = r * np.array([[np.cos(theta), np.sin(theta)]])
        g = law.margins(Q, p)[0]
        assert abs(g.min()) <= 1e-12 * fp
    vertex = fp * np.array([[np.cos(0.3), np.sin(0.3)]])
    g = law.margins(vertex, p)[0]
    assert np.sort(g)[:2] == pytest.approx([0, 0], abs=1e-12)
    mid = fp * np.cos(np.pi / k) * law.D[0, 0][None, :]
    assert law.margins(mid, p)[0].min() == pytest.approx(0, abs=1e-12)
    assert law.limit_error == pytest.approx(1 - np.cos(np.pi / k), rel=1e-15)


def test_fire_transitions():
    """Stick onto facet i; facet i onto vertex i + 1 or vertex i (its neighbours); gap closes."""
    law = _law(8)
    st = np.array([STICK])
    assert law.fire(st, np.array([1 + 3]))[0] == FACET_SLIP + 3
    face = np.array([FACET_SLIP + 3])
    assert law.fire(face, np.array([1 + 4]))[0] == VERTEX_SLIP + 4  # between facets 3 and 4
    assert law.fire(face, np.array([1 + 2]))[0] == VERTEX_SLIP + 3  # between facets 2 and 3
    wrap = np.array([FACET_SLIP + 7])
    assert law.fire(wrap, np.array([1 + 0]))[0] == VERTEX_SLIP + 0  # between facets 7 and 0
    assert law.fire(np.array([OPEN]), np.array([law.k + 1]))[0] == STICK
    assert law.fire(st, np.array([0]))[0] == OPEN


def test_adaptive_orientation_puts_a_vertex_on_the_force():
    """adaptive: the first facet event turns the polygon (vertex 0 on Q), the CFE stays stuck
    and is inside the new polygon (|Q| < f p at that direction)."""
    law = _law(8, adaptive=True)
    theta = 0.2
    fp = 1.0
    Q = _boundary(8, theta, 0.0, fp) * np.array([[np.cos(theta), np.sin(theta)]])
    g = law.margins(Q, np.array([2.0]))[0]
    col = np.array([1 + int(np.argmin(g))])
    new = law.fire(np.array([STICK]), col, Q)
    assert new[0] == STICK and law.oriented[0]
    assert law.theta[0] == pytest.approx(theta, abs=1e-15)
    assert law.margins(Q, np.array([2.0]))[0].min() > 0
    # a second facet event is a slip
    Q2 = fp * np.array([[np.cos(theta), np.sin(theta)]])
    g2 = law.margins(Q2, np.array([2.0]))[0]
    assert law.fire(np.array([STICK]), np.array([1 + int(np.argmin(g2))]), Q2)[0] >= FACET_SLIP


def test_rate_variables_and_states_they_stand_for():
    """A two-sided CFE (N = Q = 0) has an opening and k slip variables; their effects are the
    facet normals, their complements the facets' margin rates; a vertex's basis maps back."""
    k = 6
    law = _law(k)
    st = np.array([STICK])
    var = law.rate_variables(np.array([0]), st, np.zeros((1, 2)), np.array([True]),
                             np.array([True]), p=np.zeros(1), tf=1e-12)
    assert (var.kind == OPENING).sum() == 1 and (var.kind != OPENING).sum() == k
    slip = var.kind != OPENING
    assert np.allclose(var.effect[slip, :2], law.D[0, var.facet[slip]], atol=1e-15)
    assert np.allclose(var.comp[slip, 2], law.mu[0])
    assert np.all(var.effect[var.kind == OPENING] == [0, 0, -1])
    for state in (FACET_SLIP + 2, VERTEX_SLIP + 0, VERTEX_SLIP + 4, OPEN):
        active = law.active_for(np.full(len(var.cfe), state), var.kind, var.facet)
        back = law.states_from_active(st, np.zeros(len(var.cfe), int), var.kind, active,
                                      np.ones(len(var.cfe)), facet=var.facet)
        assert back[0] == state
    # the bases: stick, k facets, k vertices, each with and without the opening
    assert len(law.basis_options(var.kind, var.facet)) == 2 * (1 + 2 * k)


def test_consistency_of_slipping_cfes():
    """A facet slip whose slip rate reverses sticks; at a vertex, a slip rate outside the
    vertex's normal cone leaves onto the facet it points to."""
    law = _law(8)
    d0 = law.D[0, 0]
    z1, z2 = np.zeros(1), np.zeros((1, 2))
    args = dict(normal_lim=np.array([False]), two_sided=np.array([False]), rf=1e-9, rw=1e-9)
    p = np.array([2.0])
    Q = law.mu[0] * 2.0 * d0[None, :]
    face = np.array([FACET_SLIP + 0])
    ok = law.consistent(face, Q, z2, z1, z1, d0[None, :], p=p, tf=1e-12, **args)
    assert ok[0] == FACET_SLIP + 0
    back = law.consistent(face, Q, z2, z1, z1, -d0[None, :], p=p, tf=1e-12, **args)
    assert back[0] == STICK
    vtx = np.array([VERTEX_SLIP + 1])  # between facets 0 and 1
    d1 = law.D[0, 1]
    Qv = 1.0 * np.array([[np.cos(2 * np.pi / 8), np.sin(2 * np.pi / 8)]])
    inside = law.consistent(vtx, Qv, z2, z1, z1, (d0 + d1)[None, :], p=p, tf=1e-12, **args)
    assert inside[0] == VERTEX_SLIP + 1
    e = np.array([-d1[1], d1[0]])  # beyond d1, away from d0
    out = law.consistent(vtx, Qv, z2, z1, z1, (d1 + 0.5 * e)[None, :], p=p, tf=1e-12, **args)
    assert out[0] == FACET_SLIP + 1


def test_snap_and_violation_on_a_facet():
    """A slipping CFE slightly off its facet: the snap's facet row is its margin; the violation
    measures it."""
    law = _law(8)
    p = np.array([2.0])
    Q = (law.mu[0] * 2.0 + 1e-3) * law.D[0, 0][None, :]
    st = np.array([FACET_SLIP + 0])
    r_t, r_n = law.snap(st, Q, p, np.zeros(1))
    assert r_t[0, 0] == pytest.approx(-1e-3, rel=1e-9) and r_t[0, 1] == 0 and r_n[0] == 0
    assert law.violation(st, Q, p, np.zeros(1), 1.0, 1.0) == pytest.approx(1e-3, rel=1e-9)


def test_bad_facet_counts_are_refused():
    for k in (2, 0, 3.5, 1000):
        with pytest.raises(ModelError, match="facets"):
            _law(k)
