"""Joints with initial strength (eq. (12)) on a faceted cone (3D): the bond law
(:class:`stepcontact.contact.bond.BondedJointLaw`) writes its strength surface with the facet
normals of the Coulomb law it breaks into and hands its CFEs over to it at the break.

References are closed forms of the inscribed polygon (stated in each docstring): a strength
|Q| ≤ R on the polygon of k facets (normals d_i at θ₀ + (2i + 1)π/k, at distance R cos(π/k))
is reached along the direction θ at |Q| = R cos(π/k) / cos(θ − θ_f), θ_f the nearest facet
normal (tests/faceted_reference.slip_limit).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import faceted_reference as fr
import stepcontact as sc
from stepcontact.contact.bond import BondedJointLaw
from stepcontact.contact.faceted import FacetedCoulombLaw
from stepcontact.contact.laws import BONDED, OPEN, STICK, CoulombLaw
from stepcontact.enums import FACET_SLIP, VERTEX_SLIP, Transition, slipping

TOL = 1e-9


def bonded_point(k: int, theta: float, *, f: float = 0.5, N: float = 100.0,
                 tensile: float = 40.0, shear: float = 60.0, alpha: float = 0.4,
                 tension_alpha: float = math.inf,
                 lift: bool = False, angle: float = 0.0, end: float | None = None,
                 **layer) -> sc.DiscreteModel:
    """A point (u_x, u_y, u_z; u_z > 0 lifts it) bonded to a rigid plane (area 1: N_R, Q_R
    equal σ_R, τ_R; a tension cut-off unless ``tension_alpha``), pressed with N, then pushed
    along θ up to twice the bond's strength (or lifted, ``lift``, with no push); springs of
    1 kN/m to the ground take what the joint drops at the break (``end``: the push's end
    instead; ``layer``: kn, kt of a compliant contact layer, N/m)."""
    push = ({"uz": 1.0} if lift else {"ux": math.cos(theta), "uy": math.sin(theta)})
    if end is None:
        end = 2 * (tensile + N) if lift else 2 * (shear + alpha * N)
    return sc.DiscreteModel(
        K=np.diag([1e3, 1e3, 1e3]), normal_rows=[[0, 0, 1]], tangent_rows=[[1, 0, 0]],
        tangent2_rows=[[0, 1, 0]], friction=f, facets=k, facet_angle=angle,
        bond=sc.Bond(tensile=tensile, shear=shear, alpha=alpha, tension_alpha=tension_alpha),
        loads={"press": {"uz": -1.0}, "push": push}, dof_names=("ux", "uy", "uz"),
        program=[sc.Segment("press", N), sc.Segment("push", end)], **layer)


def broken(res):
    return [e for e in res.events if e.transition == Transition.BROKEN]


def assert_admissible(res, tol: float = TOL) -> None:
    assert res.residual.max() < tol, res.residual.max()
    assert res.violation.max() < tol, res.violation.max()


@pytest.mark.parametrize("k", [4, 8, 16])
@pytest.mark.parametrize(("tension_alpha", "R"), [(math.inf, 60.0 + 0.4 * 100.0),
                                                  (0.4, (40.0 + 100.0) * 0.4)])
def test_a_bond_breaks_on_its_polygon_and_hands_over_to_the_faceted_cone(k, tension_alpha, R):
    """Bonded point (N = 100 N, N_R = 40 N, Q_R = 60 N, α_R = 0.4) pushed along θ.  With a
    tension cut-off the shear facets govern, |Q| ≤ R = Q_R + α_R N = 100 N; with the
    article's α_t = α_R the tension facets N + |Q|/α_t ≤ N_R do, R = (N_R + N) α_t = 56 N.
    The bond breaks at |P| = R cos(π/k) / cos(θ − θ_f) (the polygon's closed form, 1e-9
    relative); the friction polygon's limit f N = 50 N is below it, so the CFE slips at
    once: its force is on the friction polygon (max_i d_i · Q = f N cos(π/k), 1e-9), and
    equilibrium and the contact conditions hold at every state (1e-9)."""
    for theta in np.linspace(0.0, 2 * np.pi, 9)[:-1] + 0.05:
        res = sc.solve_static(bonded_point(k, theta, angle=0.3, tension_alpha=tension_alpha))
        assert res.status == sc.Status.COMPLETED, res.message
        (brk,) = broken(res)
        assert brk.lam == pytest.approx(fr.slip_limit(R, k, theta, 0.3), rel=TOL)
        st = np.asarray(res.state)[:, 0]
        assert st[0] == BONDED
        assert slipping(st[-1:]).all()
        Q = np.asarray(res.Q_t)[-1, 0]
        phi = 0.3 + (2 * np.arange(k) + 1) * np.pi / k
        d = np.column_stack([np.cos(phi), np.sin(phi)])
        assert (d @ Q).max() == pytest.approx(50.0 * math.cos(math.pi / k), rel=TOL)
        assert_admissible(res)


def test_a_bonded_compliant_layer_breaks_where_its_share_reaches_the_strength():
    """The same point on a compliant layer (C_n = C_τ = C = 1e5 N/m, eq. (11)) in parallel
    with the ground springs (1e3 N/m): the layer carries the share c = C / (C + 1e3) of the
    press and of the push, Q = c P, p = c N, so the bond (Q_R = 60 N, α_R = 0.4, cut-off in
    tension) breaks at |P| = R' cos(π/k) / cos(θ − θ_f) with R' = (Q_R + α_R c N) / c
    (1e-9 relative, k = 8); before it the point has moved |u_τ| = |Q| / C (1e-9)."""
    theta, C = 0.7, 1e5
    c = C / (C + 1e3)
    res = sc.solve_static(bonded_point(8, theta, kn=C, kt=C))
    assert res.status == sc.Status.COMPLETED, res.message
    (brk,) = broken(res)
    assert brk.lam == pytest.approx(fr.slip_limit((60.0 + 0.4 * c * 100.0) / c, 8, theta, 0.0),
                                    rel=TOL)
    bonded = np.flatnonzero(np.asarray(res.state)[:, 0] == BONDED)
    Q = np.linalg.norm(np.asarray(res.Q_t)[bonded, 0], axis=-1)
    u = np.linalg.norm(np.asarray(res.ut_t)[bonded, 0], axis=-1)
    np.testing.assert_allclose(u, Q / C, rtol=TOL, atol=1e-15)
    assert_admissible(res)


def test_a_bond_pulled_off_opens_at_its_tensile_strength():
    """Pressed with N = 100 N then lifted: the tension facet c (N_R + p) = 0 (Q = 0) is
    reached at p = −N_R, i.e. at a lift of N + N_R = 140 N (1e-9 relative); the CFE opens
    (N = Q = 0 afterwards, the springs carry the lift)."""
    res = sc.solve_static(bonded_point(8, 0.0, lift=True))
    assert res.status == sc.Status.COMPLETED, res.message
    (brk,) = broken(res)
    assert brk.lam == pytest.approx(140.0, rel=TOL)
    assert np.asarray(res.state)[-1, 0] == OPEN
    assert abs(np.asarray(res.N)[-1, 0]) < 1e-9
    assert_admissible(res)


def test_a_strong_bond_keeps_the_point_stuck_where_friction_alone_would_slip():
    """Q_R = 60 N with α_R = 0.4 against f = 0.5 at N = 100 N: friction alone slips at
    |P| ≤ 50 N, the bond holds to |P| = 100 cos(π/8)/cos(θ − θ_f) ≥ 92 N: at P = 80 N the
    point is still bonded and has not moved (u_τ = 0 to 1e-12)."""
    res = sc.solve_static(bonded_point(8, 0.2, end=80.0))
    assert res.status == sc.Status.COMPLETED, res.message
    assert not broken(res)
    assert (np.asarray(res.state)[:, 0] == BONDED).all()
    assert np.abs(np.asarray(res.ut_t)[-1, 0]).max() < 1e-12


def test_the_bond_law_in_2d_writes_the_articles_four_facets():
    """In 2D the facet normals are ±1 and c = 1: the values are N_R + p ∓ Q/α_t and
    Q_R + α_R p ∓ Q exactly (eq. (12); hand values, exact in binary floating point)."""
    law = BondedJointLaw(CoulombLaw([0], [0.5], [np.inf], [np.inf]),
                         np.array([[10.0, 20.0, 0.5, 0.25]]))
    v = law.bond_values(np.array([4.0]), np.array([2.0]))
    assert v.tolist() == [[11.0, 13.0, 17.0, 25.0]]
    assert law.column_names[-4:] == ("tension+", "tension-", "shear+", "shear-")


def test_the_faceted_law_states_and_releases_at_given_forces():
    """FacetedCoulombLaw.state_at / released (the hand-over at a break), k = 4, vertex 0 on
    t₁ (facet normals at ±45°, ±135°), f p = 10 N (facets at 10 cos(π/4) from the centre):
    Q = (3, 1) is inside (stick, nothing released); Q = (20, 0) points at vertex 0 (slip
    there, released (10, 0)); Q = (8, 8) is beyond facet 0 (slip on it, released the part
    along d_0, (8 − 5, 8 − 5)); p ≤ 0 opens and releases everything (hand values, 1e-12)."""
    law = FacetedCoulombLaw(np.arange(4), 0.5, np.inf, np.inf, facets=4)
    Q = np.array([[3.0, 1.0], [20.0, 0.0], [8.0, 8.0], [1.0, 2.0]])
    p = np.array([20.0, 20.0, 20.0, -1.0])
    st = law.state_at(Q, p)
    assert st.tolist() == [STICK, VERTEX_SLIP + 0, FACET_SLIP + 0, OPEN]
    dQ, dp = law.released(st, Q, p)
    np.testing.assert_allclose(dQ, [[0, 0], [10, 0], [3, 3], [1, 2]], atol=1e-12)
    np.testing.assert_allclose(dp, [0, 0, 0, -1], atol=1e-12)
