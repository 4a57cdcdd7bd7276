"""Discrete models with two tangential directions per CFE (3D: the faceted Coulomb cone).

References: the contact operator and the initial mutual displacements built by hand from the
rows t₁, t₂, a and the gaps (B = [T₁; T₂; −A], w⁰ = [0; 0; −g⁰], component-major as in
:class:`stepcontact.contact.layout.ContactLayout`); the forces on the structure written
out as a (−N) − t₁ Q₁ − t₂ Q₂.  All comparisons are exact (copies of the same numbers, or a
few float operations: 1e-14 relative where stated).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import stepcontact as sc
from stepcontact.contact.layout import ContactLayout
from stepcontact.enums import MAX_FACETS, Status
from stepcontact.errors import ModelError
from stepcontact.fem.discrete import assemble_discrete

RNG = np.random.default_rng(26)
N_DOF, M = 7, 3
K = np.diag(np.arange(1.0, N_DOF + 1)) * 1e3  # N/m, positive definite
A = RNG.normal(size=(M, N_DOF))  # opening rows
T1 = RNG.normal(size=(M, N_DOF))
T2 = RNG.normal(size=(M, N_DOF))
GAPS = np.array([0.0, 1e-3, 2e-3])  # m


def model3d(**kw) -> sc.DiscreteModel:
    args = dict(K=K, normal_rows=A, tangent_rows=T1, tangent2_rows=T2, gaps=GAPS,
                friction=0.4, loads={"P": -A[0]}, program=[sc.Segment("P", 1.0)])
    args.update(kw)
    return sc.DiscreteModel(**args)


def test_operator_and_initial_displacements_against_hand_built():
    """B = [T₁; T₂; −A] and w⁰ = [0; 0; −g⁰] (exact: the same numbers)."""
    dm = model3d()
    sysm = assemble_discrete(dm)
    assert dm.n_t == 2
    assert sysm.layout == ContactLayout(M, 2)
    assert sysm.cfe.layout == ContactLayout(M, 2)
    np.testing.assert_array_equal(sysm.B.toarray(), np.vstack([T1, T2, -A]))
    np.testing.assert_array_equal(sysm.w0, np.r_[np.zeros(2 * M), -GAPS])


def test_layout_views_of_the_operator():
    """Row (j, k) of B is component j of CFE k: the views give u_τ = (t₁·u, t₂·u) per CFE and
    u_n = −a·u − g⁰ (1e-14 relative: one matrix product each)."""
    dm = model3d()
    sysm = assemble_discrete(dm)
    lay = sysm.layout
    u = RNG.normal(size=N_DOF)
    w = sysm.B @ u + sysm.w0
    ut, un = lay.split(w)
    assert ut.shape == (M, 2) and un.shape == (M,)
    np.testing.assert_allclose(ut, np.column_stack([T1 @ u, T2 @ u]), rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(un, -A @ u - GAPS, rtol=1e-14, atol=1e-14)
    for k in range(M):
        rows = lay.rows(k)
        np.testing.assert_array_equal(sysm.B.toarray()[rows], np.vstack([T1[k], T2[k], -A[k]]))


def test_contact_forces_on_the_structure():
    """−Bᵀ s with s = [Q₁; Q₂; p] (p = −N) is Σ a (−N) − t₁ Q₁ − t₂ Q₂, the class docstring's
    K u = f + a (−N) − t₁ Q₁ − t₂ Q₂ (1e-13 relative)."""
    sysm = assemble_discrete(model3d())
    Q = RNG.normal(size=(M, 2))
    N = -np.abs(RNG.normal(size=M))
    s = sysm.layout.join(Q, -N)
    hand = A.T @ (-N) - T1.T @ Q[:, 0] - T2.T @ Q[:, 1]
    np.testing.assert_allclose(-(sysm.B.T @ s), hand, rtol=1e-13, atol=1e-13)


def test_facet_options_reach_the_contact_elements():
    dm = model3d(facets=16, facet_angle=[0.1, 0.2, 0.3], facet_stagger=True,
                 facet_adaptive=True)
    cfe = assemble_discrete(dm).cfe
    assert (cfe.n_t, cfe.facets, cfe.facet_stagger, cfe.facet_adaptive) == (2, 16, True, True)
    np.testing.assert_array_equal(cfe.facet_angle, [0.1, 0.2, 0.3])
    cfe = assemble_discrete(model3d(facet_angle=0.25)).cfe
    assert cfe.facets == 8 and not cfe.facet_stagger and not cfe.facet_adaptive
    np.testing.assert_array_equal(cfe.facet_angle, np.full(M, 0.25))
    # no geometry: NaN coordinates, normals and tangents of the 2D shapes, also with n_t = 2
    for a in (cfe.x, cfe.normal, cfe.tangent):
        assert a.shape == (M, 2) and np.isnan(a).all()
    np.testing.assert_array_equal(cfe.area, np.ones(M))


def test_replace_keeps_the_second_direction():
    dm = model3d(facets=12, facet_angle=0.5).replace(program=[sc.Segment("P", 2.0)])
    assert dm.n_t == 2 and dm.facets == 12
    np.testing.assert_array_equal(dm.tangent2_rows.toarray(), T2)
    np.testing.assert_array_equal(dm.facet_angle, np.full(M, 0.5))


def test_sparse_rows_accepted():
    dm = model3d(tangent2_rows=sp.csr_matrix(T2))
    np.testing.assert_array_equal(assemble_discrete(dm).B.toarray()[M:2 * M], T2)


def test_2d_unchanged():
    """Without tangent2_rows: n_t = 1, B = [T; −A], w⁰ = [0; −g⁰], two facets (slip±)."""
    dm = sc.DiscreteModel(K=K, normal_rows=A, tangent_rows=T1, gaps=GAPS, friction=0.4,
                          loads={"P": -A[0]}, program=[sc.Segment("P", 1.0)])
    sysm = assemble_discrete(dm)
    assert dm.n_t == 1 and dm.tangent2_rows is None
    assert sysm.layout == ContactLayout(M, 1)
    np.testing.assert_array_equal(sysm.B.toarray(), np.vstack([T1, -A]))
    np.testing.assert_array_equal(sysm.w0, np.r_[np.zeros(M), -GAPS])
    assert sysm.cfe.n_t == 1 and sysm.cfe.facets == 2 and not sysm.cfe.facet_stagger
    assert not sysm.cfe.facet_adaptive


@pytest.mark.parametrize(("kw", "item"), [
    (dict(facets=2), "facets"),
    (dict(facets=MAX_FACETS + 1), "facets"),
    (dict(facets=8.0), "facets"),
    (dict(facets=True), "facets"),
    (dict(facet_angle=[0.0, 1.0]), "facet_angle"),
    (dict(facet_angle=[0.0, np.nan, 0.0]), "facet_angle[1]"),
    (dict(facet_angle="north"), "facet_angle"),
    (dict(facet_stagger="yes"), "facet_stagger"),
    (dict(facet_adaptive=1), "facet_adaptive"),
    (dict(tangent2_rows=T2[:2]), "tangent2_rows"),
    (dict(tangent2_rows=np.vstack([T2[:2], np.zeros(N_DOF)])), "tangent2_rows[2]"),
    (dict(tangent2_rows=np.vstack([T2[0], 3.0 * T1[1], T2[2]])), "tangent2_rows[1]"),
    (dict(bond=[None, sc.Bond(tensile=1.0, shear=1.0, alpha=0.5, residual_cohesion=0.5), None],
          gaps=0.0), "bond[1]"),
    (dict(dof_axes={"u0": "w"}), "dof_axes['u0']"),
])
def test_3d_validation_names_the_field(kw, item):
    with pytest.raises(ModelError) as err:
        model3d(**kw)
    assert err.value.item == item, err.value


def test_3d_accepts_the_limits_of_facets_and_frictionless_parallel_rows():
    assert model3d(facets=3).facets == 3
    assert model3d(facets=MAX_FACETS).facets == MAX_FACETS
    assert model3d(facets=np.int64(5)).facets == 5
    # a frictionless CFE needs no independent tangents (its forces Q vanish)
    dm = model3d(tangent2_rows=np.vstack([T2[0], T1[1], T2[2]]), friction=[0.4, 0.0, 0.4])
    assert dm.n_t == 2


@pytest.mark.parametrize(("kw", "item"), [
    (dict(facets=16), "facets"),
    (dict(facet_angle=0.3), "facet_angle"),
    (dict(facet_stagger=True), "facet_stagger"),
    (dict(facet_adaptive=True), "facet_adaptive"),
])
def test_2d_refuses_facet_options(kw, item):
    with pytest.raises(ModelError, match="two tangential directions") as err:
        sc.DiscreteModel(K=K, normal_rows=A, tangent_rows=T1, friction=0.4, **kw)
    assert err.value.item == item


def test_facet_options_build_the_faceted_law_of_the_reference():
    """The options carried by the ContactElements build the faceted law with the reference's
    polygon (tests/faceted_reference.py): vertex 0 at ``facet_angle`` from t₁ towards t₂, odd
    CFEs turned by π/k with ``facet_stagger``.  The law's facet normals equal the
    reference's (1e-15; measured 0) and the reference's vertices lie on the law's polygon
    (margin 0 on their two facets, ≥ 0 on the others; 1e-12 f p, measured 7e-16 f p)."""
    import faceted_reference as fr
    from stepcontact.contact.faceted import FacetedCoulombLaw

    k, angles = 6, np.array([0.1, -0.4, 2.0])
    cfe = assemble_discrete(model3d(facets=k, facet_angle=angles, facet_stagger=True)).cfe
    law = FacetedCoulombLaw(np.arange(cfe.m), cfe.friction, cfe.kn, cfe.kt, facets=cfe.facets,
                            angle=cfe.facet_angle, stagger=cfe.facet_stagger)
    p = 3.0  # compression, N
    fp = 0.4 * p
    for c in range(M):
        turned = angles[c] + (np.pi / k if c % 2 else 0.0)
        th = fr.facet_normal_angles(k, turned)
        np.testing.assert_allclose(law.D[c], np.column_stack([np.cos(th), np.sin(th)]),
                                   rtol=0, atol=1e-15)
        V = fr.vertices(fp, k, turned)
        for i in range(k):
            Q = np.zeros((M, 2))
            Q[c] = V[i]
            gi = law.margins(Q, np.full(M, p))[c]
            assert gi.min() >= -1e-12 * fp
            np.testing.assert_allclose(gi[[(i - 1) % k, i]], 0.0, atol=1e-12 * fp)


def test_the_solver_builds_the_faceted_law_from_the_options():
    """The solver's law builder (solver/contactlaws.py) reads k, θ₀, stagger and adaptive
    from the ContactElements of a 3D discrete model (exact)."""
    from stepcontact.contact.faceted import FacetedCoulombLaw
    from stepcontact.solver.contactlaws import contact_law

    dm = model3d(facets=12, facet_angle=0.2, facet_stagger=True, facet_adaptive=True)
    law = contact_law(assemble_discrete(dm), held_by_supports=False)
    assert isinstance(law, FacetedCoulombLaw)
    assert law.k == 12 and law.adaptive
    np.testing.assert_array_equal(law.theta, [0.2, 0.2 + np.pi / 12, 0.2])


def test_the_supports_held_components_in_3d():
    """CFE 1's rows touch only a fixed DOF: its normal and tangential components are held;
    the law is built with held masks of m entries."""
    from stepcontact.solver.contactlaws import contact_law

    a, t1, t2 = np.zeros((M, N_DOF)), np.zeros((M, N_DOF)), np.zeros((M, N_DOF))
    for k in range(M):
        a[k, k], t1[k, k + 3], t2[k, (k + 4) % N_DOF] = 1.0, 1.0, 1.0
    a[1] = t1[1] = t2[1] = 0.0
    a[1, 6] = t1[1, 6] = 1.0
    t2[1, 6] = 0.5
    dm = model3d(normal_rows=a, tangent_rows=t1, tangent2_rows=t2, friction=[0.4, 0.0, 0.4],
                 fixed=[6], loads={"P": np.ones(N_DOF)})
    law = contact_law(assemble_discrete(dm))
    np.testing.assert_array_equal(law.inert, [False, True, False])


def test_static_runs_match_the_faceted_reference():
    """A point on a rough plane pulled by a spring along piecewise-linear driver paths
    (a line back and forth oblique to the facets, k = 8 and 5; a polygonal circle, k = 8,
    R = 2a, 64 legs per revolution; 30 random legs): every event of the solver is an event
    of the exact sweep of tests/faceted_reference.py, in order, at the same load factor within
    its leg (1e-10; measured ≤ 3e-14 in the scratch run) with the same state code, and the
    force at every leg's end is the sweep's (1e-10 f|N|; measured 2e-15 N)."""
    import faceted_reference as fr
    from test_faceted_cone import driven_point

    ks, P, f = 100.0, 10.0, 0.2
    fN, a = f * P, f * P / ks
    cases = []
    for k, th in ((8, 0.2), (5, 0.7)):
        u = np.array([np.cos(th), np.sin(th)])
        cases.append((k, 0.0, np.array([c * 5 * a * u for c in (0, 1, -1, 1, -1, 1)])))
    beta = 2 * np.pi * np.arange(2 * 64 + 1) / 64
    cases.append((8, 0.1, np.vstack([[0, 0], 2 * a * np.column_stack([np.cos(beta),
                                                                    np.sin(beta)])])))
    legs = np.cumsum(np.random.default_rng(3).normal(scale=2 * a, size=(31, 2)), axis=0)
    legs[0] = 0.0
    cases.append((8, 0.1, legs))
    for k, angle, steps in cases:
        res = sc.solve_static(driven_point(steps, k, angle=angle, ks=ks, P=P, f=f))
        ref = fr.sweep(steps, ks, fN, k, angle)
        codes = np.asarray(res.state)[:, 0]
        ev = res.events_table()
        got = [(int(r.segment) - 1 + float(r.lam), int(codes[int(r.state)]))
               for r in ev.itertuples()]
        assert [c for _, c in got] == [new for _, _, new in ref.events]
        np.testing.assert_allclose([p for p, _ in got], [p for p, _, _ in ref.events],
                                   rtol=0, atol=1e-10)
        factors, names = np.asarray(res.factors), list(res.pattern_names)
        for leg in range(len(steps) - 1):
            done = np.isclose(factors[:, names.index(f"leg{leg}")], 1.0)
            if f"leg{leg + 1}" in names:
                done &= np.isclose(factors[:, names.index(f"leg{leg + 1}")], 0.0)
            j = int(np.flatnonzero(done)[-1])
            np.testing.assert_allclose(np.asarray(res.Q)[j, 0], ref.Q[leg + 1], rtol=0,
                                       atol=1e-10 * fN)


def _block_on_four_corners(**kw) -> sc.DiscreteModel:
    """A rigid block (u_x, u_y, u_z, θ_x, θ_y, θ_z; springs of 1 kN/m to the ground) on four
    corner CFEs at (±1, ±0.5, 0) m, f = 0.5 on the 8-faceted cone: 10 kN of weight, then a
    push (1, 0.3) kN with a 0.2 kN·m torque about z per unit λ."""
    corners = [(1.0, 0.5), (-1.0, 0.5), (-1.0, -0.5), (1.0, -0.5)]

    def rows(d):  # d·u_p of the corner p: d·u + θ·(r × d)
        return np.array([np.concatenate([d, np.cross([x, y, 0.0], d)]) for x, y in corners])

    return sc.DiscreteModel(
        K=np.eye(6) * 1e3, normal_rows=rows(np.array([0.0, 0.0, 1.0])),
        tangent_rows=rows(np.array([1.0, 0.0, 0.0])),
        tangent2_rows=rows(np.array([0.0, 1.0, 0.0])), gaps=np.zeros(4), friction=0.5,
        loads={"W": np.array([0, 0, -1e4, 0, 0, 0.0]),
               "H": np.array([1e3, 300.0, 0, 0, 0, 200.0])},
        program=[sc.Segment("W", 1.0), sc.Segment("H", 10.0)], **kw)


def test_a_rigid_block_on_four_rigid_corners_names_the_redundant_contacts():
    """Four rigid corners under a rigid body: their forces are not determined (a split of
    many).  Where the path depends on the split the run stops on the contact check and says
    why, naming the CFEs; with a stiffness on the joint it completes, and the first slip is
    the closed form: Q_i = F/4 + M/Σr²·(−y_i, x_i) on equal springs, N = W/4, the corner
    (1, −0.5) first, at f N cos(π/8)/cos(θ − 22.5°) (tolerance 1e-9)."""
    res = sc.solve_static(_block_on_four_corners())
    if res.status != Status.COMPLETED:  # (whether a split shows depends on the path)
        assert res.status == Status.VIOLATION
        assert "not determined by the model" in res.message
        assert all(f"[{k}]" in res.message for k in range(4))
    res = sc.solve_static(_block_on_four_corners(kn=1e9, kt=1e9))
    assert res.status == Status.COMPLETED
    # (the springs to the ground, k_g = 1 kN/m, take their shares: 4 k / (4 k + k_g) of the
    # forces, k Σr² / (k Σr² + k_g) of the torque)
    kg, k = 1e3, 1e9
    ct, cr = 4 * k / (4 * k + kg), 5 * k / (5 * k + kg)
    q = ct * np.array([250.0, 75.0]) + cr * 200.0 / 5.0 * np.array([0.5, 1.0])  # per unit λ
    theta = np.arctan2(q[1], q[0])
    N = 2500.0 * ct
    lam = 0.5 * N * np.cos(np.pi / 8) / np.cos(theta - np.pi / 8) / np.hypot(*q)
    assert res.multipliers[-1].first_slip == pytest.approx(lam, rel=1e-9)
