"""Contact between 3D bodies through the static driver (issue 28 §2, §3 static, §5): interfaces
between faces of hexahedral or tetrahedral bodies and of a body on a rigid plane, on the
faceted Coulomb cone, built in Python (``sc.Model``) and solved by ``sc.solve_static``.

References (independent of the code under test) and tolerances, per test:

* the slip limit of a block on a rough plane pushed along θ: the global sliding load
  f W cos(π/k) / cos(θ − θ_f) (θ_f the facet normal nearest θ; the pure-NumPy
  ``faceted_reference.slip_limit``, checked there against the polygon's ray exit), to 1e-9;
* the 2D block-on-base model (plane strain, its own solver path: ``CoulombLaw``) against the
  same model extruded one element through the thickness: the event sequence, order and λ to
  1e-9, each 2D CFE's forces split equally between its two 3D CFEs;
* a rigid rotation R of a 3D model (loads, t₁ axis rotated with it): the same events, λ to 1e-9;
* equilibrium of the block from statics alone (the CFE forces in global axes, −N n − Q_j t_j,
  against the applied loads, force and moment) at every recorded state, to 1e-9 of the
  weight; contact conditions (1) at every state to 1e-9 (N ≤ 0, |Q| ≤ f|N|, u_n ≤ 0);
* the contact patch test: a uniform pressure p through non-matching meshes, σ_n = N/A = −p at
  every mortar CFE and σ_zz = −p in every element, to 1e-6 relative (tet10/hex20 on both
  sides too, in the transformed basis, Σ N = −p A to 1e-9); the transformed tri6/quad8 basis
  against its hand-integrated ∫ φ̂ (1e-12).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import faceted_reference as fr
import stepcontact as sc
from stepcontact.enums import ContactState, Transition
from stepcontact.fem.assembly import assemble, load_resultant
from stepcontact.model.mesh import extrude

RHO, G = 2400.0, 9.81
CONCRETE = sc.Material(30e9, 0.2, RHO)
F = 0.5
TOL = 1e-9


def _rotated(body: sc.Body, R: np.ndarray) -> sc.Body:
    """The body turned by the rotation matrix R about the origin (its named faces kept)."""
    mesh = dataclasses.replace(body.mesh, doflocs=R @ body.mesh.doflocs)
    return sc.Body.from_mesh(body.name, mesh, body.element, body.material)


def block_model(k: int, theta: float, *, base: tuple | None = None, cfe: str = "auto",
                R: np.ndarray | None = None, element: str = "hex8",
                push_end: float = 1e5) -> sc.Model:
    """A 1 × 1 × 0.5 m block (2 × 2 × 1 cells) on a rough rigid plane z = 0, or on a base
    block 2 × 2 × 0.5 m of ``base`` cells fixed at its bottom; weight W = ρ g V, then a total
    force of 1 N per unit λ on its top along θ (from +x towards +y) until it slides.  ``R``:
    the whole model turned rigidly (bodies, loads, plane, the CFEs' t₁ axis)."""
    R = np.eye(3) if R is None else np.asarray(R, float)
    blk = sc.box("block", (0, 0, 0), (1, 1, 0.5), (2, 2, 1), CONCRETE, element)
    bodies = [_rotated(blk, R)]
    if base is not None:
        bb = sc.box("base", (-0.5, -0.5, -0.5), (1.5, 1.5, 0.0), base, CONCRETE, element)
        bodies.append(_rotated(bb, R))
    m = sc.Model(bodies=tuple(bodies))
    if base is None:
        minus = sc.RigidPlane("ground", point=(0, 0, 0), normal=R @ (0, 0, 1.0))
    else:
        minus = m.select("base", boundary="top")
        m = m.add(sc.Support("bed", m.select("base", boundary="bottom"), "xyz"))
    push = R @ np.array([math.cos(theta), math.sin(theta), 0.0])
    return m.add(
        sc.Interface("joint", m.select("block", boundary="bottom"), minus, friction=F,
                     facets=k, cfe=cfe, axis=tuple(R @ (1.0, 0, 0))),
        sc.LoadPattern("weight", [sc.BodyForce(g=tuple(R @ (0, 0, -G)), bodies=("block",))]),
        sc.LoadPattern("push", [sc.EdgeForce(m.select("block", boundary="top"),
                                             fx=push[0], fy=push[1], fz=push[2])]),
        sc.Segment("weight", 1.0), sc.Segment("push", push_end))


W = RHO * G * 0.5  # the block's weight, N


def assert_block_statics(model: sc.Model, res, tol: float = TOL) -> None:
    """At every recorded state, the block's applied loads and its CFE forces in global axes
    (−N n − Q₁ t₁ − Q₂ t₂ on S+, at the S+ point) balance: force and moment about the origin,
    to ``tol`` × W (× 1 m); and the contact conditions (1): N ≤ 0, |Q| ≤ f|N|, to tol."""
    sysm = assemble(model)
    per_pattern = np.array([load_resultant(model, sysm.dofs, sysm.loads[p].f)
                            for p in res.pattern_names])  # (P, 6)
    applied = np.asarray(res.factors) @ per_pattern  # (n_states, 6)
    n, t, x = (np.asarray(res.cfe[k], float) for k in ("normal", "tangent", "x"))
    N, Q = np.asarray(res.N), np.asarray(res.Q_t)
    force = -N[..., None] * n[None] - np.einsum("skj,kjd->skd", Q, t)  # (n_states, m, 3)
    total = np.concatenate([force.sum(axis=1), np.cross(x[None], force).sum(axis=1)], axis=1)
    assert np.abs(applied + total).max() <= tol * W, np.abs(applied + total).max() / W
    assert N.max() <= tol * W
    assert (np.linalg.norm(Q, axis=2) - F * np.abs(N)).max() <= tol * W


# --------------------------------------------------------------------------------------------
# the slip limit of the faceted cone
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("k", [4, 8, 16])
def test_block_on_a_rough_plane_slides_at_the_polygon_limit(k):
    """A block on a rigid plane pushed along θ (a vertex θ = 0, a facet's middle θ = π/k and
    two directions between) loses equilibrium at f W cos(π/k) / cos(θ − θ_f) to 1e-9
    relative (fr.slip_limit), with statics and the contact conditions at every state (1e-9)
    and the facet count stated in the result."""
    for theta in (0.0, math.pi / k, 0.3, 2.0):
        model = block_model(k, theta)
        res = sc.solve_static(model)
        assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
        assert res.lam[-1] == pytest.approx(fr.slip_limit(F * W, k, theta), rel=TOL)
        assert f"inscribed {k}-gon" in res.message
        assert res.residual.max() < TOL and res.violation.max() < TOL
        assert_block_statics(model, res)


@pytest.mark.parametrize("base, cfe, element", [
    ((2, 2, 1), "node-to-node", "hex8"), ((2, 2, 1), "auto", "hex8"),
    ((3, 3, 1), "mortar", "hex8"), ((3, 3, 1), "node-to-segment", "hex8"),
    ((4, 4, 1), "auto", "hex8"), ((3, 3, 1), "mortar", "tet4"),
    pytest.param((3, 3, 1), "mortar", "hex27", marks=pytest.mark.slow)])
def test_block_on_a_base_slides_at_the_polygon_limit(base, cfe, element):
    """The block on an elastic base fixed at its bottom, CFEs node-to-node (a base whose top
    matches the block: also what 'auto' chooses), mortar and node-to-facet (non-matching), and
    'auto' on a larger base (mortar: S− has nodes S+ has not, as in 2D), on hexahedra,
    tetrahedra and hex27: sliding at f W cos(π/k) / cos(θ − θ_f), k = 8, θ = 0.3, to 1e-9
    relative, with equilibrium and the contact conditions to 1e-9 at every state; the kind
    chosen is the one asked for (node-to-node: one node at each end; otherwise an end
    interpolated).  The mortar CFEs sit on the block's face: the base's coarser facets face
    it only in part (a dual basis fitted to slivers of quad9 facets lost equilibrium to
    ~1e-7 here)."""
    k, theta = 8, 0.3
    if base == (2, 2, 1):  # a base of the block's own footprint: the meshes match
        model = block_model(k, theta, base=None)
        bb = sc.box("base", (0, 0, -0.5), (1, 1, 0.0), (2, 2, 1), CONCRETE)
        model = model.replace(bodies=model.bodies + (bb,), interfaces=())
        model = model.add(
            sc.Support("bed", model.select("base", boundary="bottom"), "xyz"),
            sc.Interface("joint", model.select("block", boundary="bottom"),
                         model.select("base", boundary="top"), friction=F, facets=k, cfe=cfe))
    else:
        model = block_model(k, theta, base=base, cfe=cfe, element=element)
    res = sc.solve_static(model)
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert res.lam[-1] == pytest.approx(fr.slip_limit(F * W, k, theta), rel=TOL)
    assert res.residual.max() < TOL and res.violation.max() < TOL
    ends = np.maximum(*(np.count_nonzero(np.asarray(res.cfe[k]) >= 0, axis=1)
                        for k in ("plus_nodes", "minus_nodes")))
    if base == (2, 2, 1):
        assert np.all(ends == 1)
    else:
        assert ends.max() > 1
    if cfe == "mortar":  # on the block's nodes: S+ ends are single nodes
        assert np.all(np.count_nonzero(np.asarray(res.cfe["plus_nodes"]) >= 0, axis=1) == 1)


@pytest.mark.parametrize("element", ["tet10", "hex20"])
def test_tet10_and_hex20_block_on_a_base_slides_at_the_polygon_limit(element):
    """A tet10/hex20 block on a base of its own kind (mortar in the transformed basis, on the
    block's face, since the base's facets face it only in part): sliding at
    f W cos(π/k) / cos(θ − θ_f), k = 8, θ = 0.3, to 1e-9 relative, with equilibrium and the
    contact conditions to 1e-9 at every state (measured ~1e-14); the CFEs at mid-side nodes
    act on the transformed value (three S+ nodes), those at corners on the corner alone."""
    k, theta = 8, 0.3
    model = block_model(k, theta, base=(3, 3, 1), cfe="mortar", element=element)
    res = sc.solve_static(model)
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert res.lam[-1] == pytest.approx(fr.slip_limit(F * W, k, theta), rel=TOL)
    assert res.residual.max() < TOL and res.violation.max() < TOL
    assert_block_statics(model, res)
    ends = np.count_nonzero(np.asarray(res.cfe["plus_nodes"]) >= 0, axis=1)
    assert set(ends.tolist()) == {1, 3}


def test_loading_from_zero_every_cfe_closed_and_stuck():
    """From λ = 0 every CFE is closed with N = Q = 0 (every facet of every CFE at its limit at
    once: the degenerate start); after the weight all CFEs stick with Σ N = −W (1e-9) and
    Σ Q = 0 (1e-9 W); the run finds the slip limit (1e-9) without a false mechanism."""
    model = block_model(8, 0.3)
    res = sc.solve_static(model)
    N, Q, state = np.asarray(res.N), np.asarray(res.Q_t), np.asarray(res.state)
    assert np.all(N[0] == 0.0) and np.all(Q[0] == 0.0)
    assert np.all(state[0] != ContactState.OPEN)
    weighed = int(np.flatnonzero(np.asarray(res.segment) == 0)[-1])
    assert np.all(state[weighed] == ContactState.STICK)
    assert N[weighed].sum() == pytest.approx(-W, rel=TOL)
    assert np.abs(Q[weighed].sum(axis=0)).max() <= TOL * W
    assert [b["mode"] for b in res.mechanism["bodies"]] == ["sliding"]
    assert res.lam[-1] == pytest.approx(fr.slip_limit(F * W, 8, 0.3), rel=TOL)


def test_results_per_cfe_have_the_3d_shapes():
    """res.N (n_states, m), res.Q (n_states, m, 2) along t₁, t₂; the local bases are
    orthonormal and right-handed with n = +z on the plane and t₁ = +x (the interface's axis),
    the areas add up to the block's footprint (1 m², 1e-12)."""
    res = sc.solve_static(block_model(8, 0.3))
    m = res.m
    assert np.asarray(res.N).shape == (len(res.lam), m)
    assert np.asarray(res.Q).shape == (len(res.lam), m, 2)
    n, t = np.asarray(res.cfe["normal"]), np.asarray(res.cfe["tangent"])
    np.testing.assert_allclose(n, np.tile([0, 0, 1.0], (m, 1)), atol=1e-15)
    np.testing.assert_allclose(t[:, 0], np.tile([1.0, 0, 0], (m, 1)), atol=1e-15)
    np.testing.assert_allclose(np.cross(t[:, 0], t[:, 1]), n, atol=1e-15)
    assert np.asarray(res.cfe["area"]).sum() == pytest.approx(1.0, rel=1e-12)


# --------------------------------------------------------------------------------------------
# the 2D block on its base, extruded; and a rigid rotation
# --------------------------------------------------------------------------------------------
PRISM = sc.Material(E=30e9, nu=0.0, density=RHO)


def block_on_base_2d() -> sc.Model:
    """The 2D block on base (tests/verification_models.pushed_block, coarser and with ν = 0):
    a 2 m × 1 m block (6 × 3 quad4) on a 4 m × 1 m base (8 × 2) fixed at its bottom,
    f = 0.5; its weight, then a push of 1 N per unit λ on its left side until it slides."""
    base = sc.rectangle("base", (0, 0), (4, 1), 8, 2, PRISM)
    block = sc.rectangle("block", (1, 1), (3, 2), 6, 3, PRISM)
    m = sc.Model(bodies=[base, block])
    left = m.select("block", x=1)
    return m.add(
        sc.Support("bed", m.select("base", y=0), "xy"),
        sc.Interface("joint", plus=m.select("block", y=1), minus=m.select("base", y=1),
                     friction=F),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
        sc.LoadPattern("push", [sc.NodalLoad(left, fx=1.0 / len(left))]),
        sc.Segment("weight", 1.0), sc.Segment("push", 1e6))


def block_on_base_prism(k: int = 8) -> sc.Model:
    """The same model extruded 1 m along z, one hex8 layer: u_z = 0 at every node but those of
    the block's bottom face (held by the CFEs' t₂ rows; with ν = 0 the plane-strain field
    puts no force on them along z, so this is plane strain), gravity along −y, the push on
    the left face's 12 nodes; node-to-node CFEs (the meshes match), k = 8 with a vertex on
    t₁ = +x (slip along ±x reaches the polygon at a vertex: f|N|, as in 2D)."""
    base = extrude(sc.rectangle("base", (0, 0), (4, 1), 8, 2, PRISM), (0, 1), 1)
    block = extrude(sc.rectangle("block", (1, 1), (3, 2), 6, 3, PRISM), (0, 1), 1)
    m = sc.Model(bodies=[base, block])
    left = m.select("block", x=1)
    above = m.select("block", lambda x, y, z: y > 1 + 1e-9, boundary=False)
    return m.add(
        sc.Support("bed", m.select("base", y=0), "xyz"),
        sc.Support("base_z", m.select("base", lambda x, y, z: y > 1e-9, boundary=False), "z"),
        sc.Support("block_z", above, "z"),
        sc.Interface("joint", plus=m.select("block", y=1), minus=m.select("base", y=1),
                     friction=F, facets=k),
        sc.LoadPattern("weight", [sc.BodyForce(g=(0.0, -G, 0.0), bodies=("block",))]),
        sc.LoadPattern("push", [sc.NodalLoad(left, fx=1.0 / len(left))]),
        sc.Segment("weight", 1.0), sc.Segment("push", 1e6))


def test_prismatic_model_reproduces_the_2d_event_sequence():
    """Every 2D event (a CFE at x starting to slip at λ) is two 3D events at the same λ (to
    1e-9 relative), the CFEs at x on the front and back faces, in the same order; their N and
    Q₁ are half the 2D CFE's (1e-9 of W), Q₂ = 0 (1e-9 W); both runs end in the same loss of
    equilibrium (λ to 1e-9)."""
    r2 = sc.solve_static(block_on_base_2d())
    r3 = sc.solve_static(block_on_base_prism())
    assert r2.status == r3.status == sc.Status.EQUILIBRIUM_LOST, (r2.message, r3.message)
    assert len(r2.events) >= 3 and len(r3.events) == 2 * len(r2.events)
    Wb = RHO * G * 2.0
    for i, e2 in enumerate(r2.events):
        pair = r3.events[2 * i: 2 * i + 2]
        for e3 in pair:
            assert e3.lam == pytest.approx(e2.lam, rel=TOL)
            assert e3.segment == e2.segment
            assert e3.x == pytest.approx(e2.x, abs=1e-12)
            assert (e2.transition, e3.transition) == (Transition.SLIP_POS, Transition.SLIP)
            assert e3.N == pytest.approx(e2.N / 2, abs=TOL * Wb)
            assert e3.Q_t[0] == pytest.approx(e2.Q / 2, abs=TOL * Wb)
            assert abs(e3.Q_t[1]) <= TOL * Wb
        z = sorted(float(np.asarray(r3.cfe["x"])[e.cfe, 2]) for e in pair)
        assert z == pytest.approx([0.0, 1.0], abs=1e-12)
    assert r3.lam[-1] == pytest.approx(r2.lam[-1], rel=TOL)
    assert r3.residual.max() < TOL and r3.violation.max() < TOL


def _rotation(a: float, b: float, c: float) -> np.ndarray:
    """R = R_z(c) R_y(b) R_x(a)."""
    ca, sa, cb, sb, cc, sc_ = (math.cos(a), math.sin(a), math.cos(b), math.sin(b),
                               math.cos(c), math.sin(c))
    Rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    Ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    Rz = np.array([[cc, -sc_, 0], [sc_, cc, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


@pytest.mark.parametrize("base, cfe", [(None, "auto"), ((3, 3, 1), "mortar")])
def test_a_rigid_rotation_gives_the_same_events(base, cfe):
    """The block on the plane and on a base with mortar CFEs, turned by an arbitrary rotation
    (its loads, plane and t₁ axis turned with it): the same events (CFE, transition) in the
    same order at the same λ (1e-9 relative), the same Q (along the turned t₁, t₂) and N at
    each (1e-9 W), and the same λ of the loss of equilibrium.  The events at that last point
    are left out: there the scheme is a mechanism, and which of the CFEs reaching a new facet
    at once is reported is a round-off tie."""
    R = _rotation(0.4, -0.7, 1.1)
    a = sc.solve_static(block_model(8, 0.3, base=base, cfe=cfe))
    b = sc.solve_static(block_model(8, 0.3, base=base, cfe=cfe, R=R))
    assert a.status == b.status == sc.Status.EQUILIBRIUM_LOST
    last = a.events[-1].step
    ea_, eb_ = ([e for e in r.events if e.step < last] for r in (a, b))
    assert len(ea_) == len(eb_) > 2
    for ea, eb in zip(ea_, eb_, strict=True):
        assert (ea.cfe, ea.transition) == (eb.cfe, eb.transition)
        assert eb.lam == pytest.approx(ea.lam, rel=TOL, abs=TOL)
        assert eb.N == pytest.approx(ea.N, abs=TOL * W)
        assert np.asarray(eb.Q_t) == pytest.approx(np.asarray(ea.Q_t), abs=TOL * W)
    assert b.lam[-1] == pytest.approx(a.lam[-1], rel=TOL)
    np.testing.assert_allclose(np.asarray(b.cfe["normal"]), np.asarray(a.cfe["normal"]) @ R.T,
                               atol=1e-12)


# --------------------------------------------------------------------------------------------
# compliant layers, refusals
# --------------------------------------------------------------------------------------------
def test_a_compliant_layer_settles_by_the_weight_over_its_stiffness():
    """A block on a plane through a layer kn (Pa/m, eq. (11)): under its weight alone every
    CFE's normal force is its layer's C_n = kn A_k times its node's settlement, so
    Σ_k kn A_k u_z,k = −W (1e-9), and the CFEs carry W (1e-9), with no event."""
    kn = 1e8
    blk = sc.box("block", (0, 0, 0), (1, 1, 0.5), (2, 2, 1), CONCRETE)
    m = sc.Model(bodies=(blk,))
    m = m.add(sc.Interface("joint", m.select("block", boundary="bottom"),
                           sc.RigidPlane("ground"), friction=F,
                           layer=sc.ContactLayer(kn=kn, kt=kn)),
              sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
              sc.Segment("weight", 1.0))
    res = sc.solve_static(m)
    assert res.status == sc.Status.COMPLETED, res.message
    uz = res.displacement(-1).reshape(-1, 3)[:, 2]
    nodes = np.asarray(res.cfe["plus_nodes"])[:, 0]
    area = np.asarray(res.cfe["area"])
    assert (kn * area * uz[nodes]).sum() == pytest.approx(-W, rel=TOL)
    np.testing.assert_allclose(np.asarray(res.N)[-1], kn * area * uz[nodes], rtol=1e-9,
                               atol=1e-9 * W)
    assert len(res.events) == 0
    assert np.asarray(res.N)[-1].sum() == pytest.approx(-W, rel=TOL)


def test_a_bonded_cube_pulled_off_breaks_at_its_tensile_strength():
    """A one-element cube bonded to a plane (eq. (12), a tension cut-off σ_R), pulled up by a
    uniform traction on its top: by symmetry each of its 4 corner CFEs carries P/4, so all
    bonds break together at P = σ_R · 1 m² (1e-9 relative) and the cube lifts off (the
    mechanism: a translation along +z, 6 rigid modes of a 3D body)."""
    sig = 2e5
    cube = sc.box("cube", (0, 0, 0), (1, 1, 1), (1, 1, 1), CONCRETE)
    m = sc.Model(bodies=(cube,))
    m = m.add(sc.Interface("glue", m.select("cube", boundary="bottom"), sc.RigidPlane("ground"),
                           friction=0.6, bond=sc.Bond(tensile=sig, shear=3e5, alpha=0.6,
                                                      tension_alpha=math.inf)),
              sc.LoadPattern("pull", [sc.EdgeForce(m.select("cube", boundary="top"), fz=1.0)]),
              sc.Segment("pull", 1e6))
    res = sc.solve_static(m)
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert [e.transition for e in res.events] == [Transition.BROKEN] * 4
    for e in res.events:
        assert e.lam == pytest.approx(sig * 1.0, rel=TOL)
    assert res.lam[-1] == pytest.approx(sig, rel=TOL)
    assert [b["mode"] for b in res.mechanism["bodies"]] == ["lift-off"]


def test_3d_refusals_name_the_item():
    """What 3D interfaces do not do yet is refused by name: a 2D obstacle under a 3D body,
    node pairs, a moving plane; a 2D interface refuses the 3D options (facets, axis) and a
    plane.  (A dynamic interval of a 3D model is accepted: tests/test_dynamics3d.py.)"""
    model = block_model(8, 0.3)
    assert model.replace(dynamics=sc.DynamicInterval(dt=1e-3, duration=1e-2)).dynamics.dt == 1e-3
    blk = model.body("block")
    m = sc.Model(bodies=(blk,))
    line = sc.RigidObstacle("line", [(-1, 0), (2, 0)])
    with pytest.raises(sc.ModelError, match="2D polyline"):
        sc.solve_static(m.add(sc.Interface("j", m.select("block", boundary="bottom"), line),
                              sc.LoadPattern("w", [sc.BodyForce()]), sc.Segment("w", 1.0)))
    with pytest.raises(sc.ModelError, match="pairs"):
        assemble(m.add(sc.Interface("j", m.select("block", boundary="bottom"),
                                    m.select("block", boundary="top"), pairs=True)))
    with pytest.raises(sc.ModelError, match="moving obstacles"):
        model.add(sc.LoadPattern("lift", [sc.ObstacleMotion("ground", dy=1.0)]))
    two = sc.Model(bodies=(sc.rectangle("b", (0, 0), (1, 1), 1, 1, CONCRETE),))
    with pytest.raises(sc.ModelError, match="facets"):
        two.add(sc.Interface("j", two.select("b", y=0), line, facets=8))
    with pytest.raises(sc.ModelError, match="plane"):
        two.add(sc.Interface("j", two.select("b", y=0), sc.RigidPlane("p")))
    with pytest.raises(sc.ModelError, match="facets"):
        sc.Interface("j", two.select("b", y=0), line, facets=2)
    with pytest.raises(sc.ModelError, match="normal"):
        two.add(sc.Interface("j", two.select("b", y=0), line, normal=(0, 0, 1)))
    with pytest.raises(sc.ModelError, match="normal"):
        m.add(sc.Interface("j", m.select("block", boundary="bottom"), sc.RigidPlane("p"),
                           normal=(0, 1)))


# --------------------------------------------------------------------------------------------
# the contact patch test (mortar)
# --------------------------------------------------------------------------------------------
def pressed_blocks(lower: tuple[str, int], upper: tuple[str, int], P: float = 1e6) -> sc.Model:
    """Two 1 × 1 × 0.5 m blocks one on the other, n × n × 1 cells of the given elements each
    (non-matching meshes), mortar CFEs (f = 0.5), pressed by a total force P (N) spread
    uniformly over the top; rollers on the planes x = 0, y = 0 and under the lower block:
    uniaxial stress σ_zz = −P / 1 m² in both, no friction needed (same material)."""
    mat = sc.Material(30e9, 0.25, RHO)
    lo = sc.box("lower", (0, 0, -0.5), (1, 1, 0), (lower[1], lower[1], 1), mat, lower[0])
    up = sc.box("upper", (0, 0, 0), (1, 1, 0.5), (upper[1], upper[1], 1), mat, upper[0])
    m = sc.Model(bodies=(lo, up))
    rollers = [sc.Support(f"{b}_{face}", m.select(b, boundary=face), d)
               for b in ("lower", "upper") for face, d in (("left", "x"), ("front", "y"))]
    return m.add(
        sc.Support("bed", m.select("lower", boundary="bottom"), "z"), *rollers,
        sc.Interface("joint", m.select("upper", boundary="bottom"),
                     m.select("lower", boundary="top"), friction=F, cfe="mortar"),
        sc.LoadPattern("press", [sc.EdgeForce(m.select("upper", boundary="top"), fz=-P)]),
        sc.Segment("press", 1.0))


@pytest.mark.parametrize("lower, upper", [
    (("hex8", 2), ("hex8", 3)), (("hex8", 3), ("hex8", 2)),
    (("tet4", 2), ("tet4", 3)), (("tet4", 3), ("tet4", 2)),
    (("hex8", 3), ("tet4", 2)), (("hex27", 1), ("hex27", 2))])
def test_contact_patch_test_non_matching_meshes(lower, upper):
    """A uniform pressure p = P / 1 m² passes exactly through non-matching meshes, the finer
    side on top or below, hexahedra and tetrahedra (and quadratic hex27): at every mortar CFE
    σ_n = N / A_k = −p, the CFE areas add up to the 1 m² overlap, Q = 0, and every element of
    both blocks has σ_zz = −p and no other stress — all to 1e-6 of p (measured: ~1e-14)."""
    P = 1e6
    res = sc.solve_static(pressed_blocks(lower, upper, P))
    assert res.status == sc.Status.COMPLETED, res.message
    N, A, Q = np.asarray(res.N)[-1], np.asarray(res.cfe["area"]), np.asarray(res.Q_t)[-1]
    assert np.abs(N / A / P + 1).max() <= 1e-6
    assert A.sum() == pytest.approx(1.0, rel=1e-12)
    assert np.abs(Q).max() <= 1e-6 * P * A.min()
    for body, sigma in res.stress(-1).items():
        assert np.abs(sigma[:, 2] / P + 1).max() <= 1e-6, body
        assert np.abs(sigma[:, [0, 1, 3, 4, 5]]).max() <= 1e-6 * P, body


@pytest.mark.parametrize("lower, upper", [
    (("tet10", 1), ("tet10", 2)), (("tet10", 2), ("tet10", 1)),
    (("hex20", 2), ("hex20", 3)), (("hex20", 3), ("hex20", 2)), (("hex20", 2), ("tet10", 1))])
def test_contact_patch_test_between_tet10_and_hex20_faces(lower, upper):
    """tri6/quad8 faces on both sides (their corners have ∫ φ ≤ 0): the mortar CFEs sit on the
    coarser side in the transformed basis φ̂ = T φ (Popp et al. 2012), and a uniform pressure
    p = P / 1 m² still passes exactly, the coarser side on top or below: at every CFE
    N / A_k = −p (1e-6 relative), Σ N = −p · 1 m² (1e-9 relative), the areas add up to the
    1 m² overlap (1e-12), every CFE has a positive area, and both blocks carry σ_zz = −p and
    no other stress (1e-6 of p) — measured ~1e-14."""
    P = 1e6
    res = sc.solve_static(pressed_blocks(lower, upper, P))
    assert res.status == sc.Status.COMPLETED, res.message
    N, A, Q = np.asarray(res.N)[-1], np.asarray(res.cfe["area"]), np.asarray(res.Q_t)[-1]
    assert A.min() > 0
    assert np.abs(N / A / P + 1).max() <= 1e-6
    assert N.sum() == pytest.approx(-P, rel=1e-9)
    assert A.sum() == pytest.approx(1.0, rel=1e-12)
    assert np.abs(Q).max() <= 1e-6 * P * A.min()
    for body, sigma in res.stress(-1).items():
        assert np.abs(sigma[:, 2] / P + 1).max() <= 1e-6, body
        assert np.abs(sigma[:, [0, 1, 3, 4, 5]]).max() <= 1e-6 * P, body


@pytest.mark.parametrize("kind, corner, mid", [("tri6", 2 / 15, 1 / 5), ("quad8", 1 / 20, 1 / 5)])
def test_transformed_quadratic_basis_is_a_positive_partition_of_unity(kind, corner, mid):
    """φ̂ = T φ with α = 1/5 on a flat tri6/quad8 facet of area A: Σ φ̂ = 1 at random points,
    ∫ φ̂_corner = 2αA/3 = 2A/15 (tri6) or (8α − 1)A/12 = A/20 (quad8), ∫ φ̂_mid = (1 − 2α)A/3 =
    A/5 (hand integration of the quadratic shape functions; 1e-12)."""
    from stepcontact.contact.surface3d import (
        FACET_KINDS,
        _gauss_reference,
        _transformation,
        shape,
    )

    k = FACET_KINDS[kind][0]
    xi, w = _gauss_reference(kind)
    phi = shape(kind, xi)[0] @ _transformation(kind).T
    integral = w @ phi / w.sum()
    assert np.allclose(integral[:k], corner, rtol=0, atol=1e-12)
    assert np.allclose(integral[k:], mid, rtol=0, atol=1e-12)
    r = np.random.default_rng(1).random((50, 2))
    r = r / 2 if kind == "tri6" else 2 * r - 1
    assert np.allclose((shape(kind, r)[0] @ _transformation(kind).T).sum(1), 1, atol=1e-12)


def test_gaps_and_normals_come_from_the_geometry():
    """Initial gaps g⁰ of the CFEs from the geometry (assembled, no run): above a tilted
    plane the distance (x⁺ − x₀) · n̂ of each node (1e-12 m); a block 2 mm above a
    non-matching base, node-to-facet and mortar CFEs, 2 mm at every CFE with n = +z
    (1e-12); w⁰ = [0; 0; −g⁰] in the contact layout."""
    blk = sc.box("block", (0, 0, 0.002), (1, 1, 0.5), (2, 2, 1), CONCRETE)
    m = sc.Model(bodies=(blk,))
    x0, nrm = np.array([0.0, 0.0, -0.01]), np.array([0.1, 0.0, 1.0])
    plane = sc.RigidPlane("tilted", point=tuple(x0), normal=tuple(nrm))
    sysm = assemble(m.add(sc.Interface("j", m.select("block", boundary="bottom"), plane)))
    xb = blk.points[np.asarray(sysm.cfe.plus_nodes)[:, 0]]
    np.testing.assert_allclose(sysm.cfe.gap, (xb - x0) @ (nrm / np.linalg.norm(nrm)),
                               atol=1e-12)
    lay = sysm.layout
    np.testing.assert_array_equal(lay.normal(sysm.w0), -sysm.cfe.gap)
    assert not np.any(lay.tangential(sysm.w0))
    base = sc.box("base", (-0.5, -0.5, -0.5), (1.5, 1.5, 0.0), (3, 3, 1), CONCRETE)
    m2 = sc.Model(bodies=(blk, base))
    m2 = m2.add(sc.Support("bed", m2.select("base", boundary="bottom"), "xyz"))
    for cfe in ("node-to-segment", "mortar"):
        s2 = assemble(m2.add(sc.Interface("j", m2.select("block", boundary="bottom"),
                                          m2.select("base", boundary="top"), cfe=cfe)))
        np.testing.assert_allclose(s2.cfe.gap, 0.002, atol=1e-12)
        np.testing.assert_allclose(s2.cfe.normal, np.tile([0, 0, 1.0], (s2.m, 1)), atol=1e-12)


def test_node_to_facet_makes_no_cfe_beyond_the_border():
    """A block (4 × 4 faces) overhanging a base that covers x ≤ 0.5 of it: node-to-facet CFEs
    only at the 3 × 5 block nodes over the base (x ≤ 0.5 m), none on the overhang."""
    blk = sc.box("block", (0, 0, 0), (1, 1, 0.5), (4, 4, 1), CONCRETE)
    base = sc.box("base", (0, 0, -0.5), (0.5, 1, 0), (3, 3, 1), CONCRETE)
    m = sc.Model(bodies=(blk, base))
    m = m.add(sc.Support("bed", m.select("base", boundary="bottom"), "xyz"),
              sc.Interface("j", m.select("block", boundary="bottom"),
                           m.select("base", boundary="top"), cfe="node-to-segment"))
    sysm = assemble(m)
    assert sysm.m == 15
    assert np.asarray(sysm.cfe.x)[:, 0].max() == pytest.approx(0.5, abs=1e-12)


def test_program_path_stages_and_a_shared_condensation():
    """The same 3D model through the program path (sc.run), in two construction stages (the
    base, then the block with its joint and the program) and with another friction on one
    condensation (sc.condense, Model.with_friction): each slides at f W cos(π/k) /
    cos(θ − θ_f) for its f (1e-9 relative)."""
    k, theta = 8, 0.3
    model = block_model(k, theta, base=(3, 3, 1), cfe="mortar")
    ref = fr.slip_limit(F * W, k, theta)
    assert sc.run(model).static.lam[-1] == pytest.approx(ref, rel=TOL)
    staged = model.replace(program=(), stages=(
        sc.Stage("base", bodies=("base",), supports=("bed",)),
        sc.Stage("block", bodies=("block",), interfaces=("joint",), program=model.program)))
    assert sc.solve_static(staged).lam[-1] == pytest.approx(ref, rel=TOL)
    cond = sc.condense(model)
    res = sc.solve_static(model.with_friction(0.3), condensation=cond)
    assert res.lam[-1] == pytest.approx(fr.slip_limit(0.3 * W, k, theta), rel=TOL)
