"""3D continua in the model, without contact (issue 28 §1): solids meshed with scikit-fem's
tetrahedra and hexahedra (linear and quadratic), supports on any of x, y, z, nodal and surface
loads, self-weight along −z, solved through the static driver with no CFEs (m = 0).

References (all closed forms, tolerances stated per test):

* a prismatic bar in uniaxial tension, supported on its three symmetry planes (free lateral
  contraction): u_x = P x / (E A), u_y = −ν P y / (E A), u_z = −ν P z / (E A) — a linear
  field, which every element reproduces to round-off (1e-10 of the end displacement);
* a column under its own weight, held by a pressure ρ g L on its base (the weight, no
  support force) and by its symmetry planes: σ_zz = ρ g (z − L), σ_xx = σ_yy = 0, so
  u_x = −ν k (z − L) x, u_y = −ν k (z − L) y, u_z = k (z²/2 − L z) + ν k (x² + y²)/2 + C with
  k = ρ g / E (Timoshenko & Goodier §97) — quadratic, reproduced to round-off by tet10, hex20
  and hex27; the top shortens by ρ g L² / (2E);
* a cantilever with a tip force: Euler–Bernoulli P L³ / (3 E I), and with Timoshenko's shear
  term P L / (κ G A), κ = 5/6;
* load resultants: the weight ρ g V at the centroid, a total force on a face at its centroid.
"""

from __future__ import annotations

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.fem.assembly import assemble, load_resultant

E, NU, RHO, G = 2.0e9, 0.3, 2500.0, 9.81


def _symmetric_supports(m: sc.Model, body: str) -> sc.Model:
    """Rollers on the planes x = x0 (x), y = y0 (y) and z = z0 (z): no rigid motion, no
    restraint of the lateral contraction."""
    return m.add(sc.Support("left", m.select(body, boundary="left"), "x"),
                 sc.Support("front", m.select(body, boundary="front"), "y"),
                 sc.Support("bottom", m.select(body, boundary="bottom"), "z"))


@pytest.mark.parametrize("element", ["tet4", "hex8", "tet10", "hex20", "hex27"])
def test_bar_in_uniaxial_tension_is_exact(element):
    """u = P L / (E A) at the loaded end and the lateral contraction −ν ε y, −ν ε z, exact to
    1e-10 of the end displacement at every node (a linear field: in every element's space);
    the element stresses σ_xx = P / A, all others 0 to 1e-10 P / A; the reaction −P to 1e-12."""
    L, W, H, P = 3.0, 0.5, 0.8, 3.0e4
    bar = sc.box("bar", (0, 0, 0), (L, W, H), (3, 2, 2), sc.Material(E, NU), element)
    m = _symmetric_supports(sc.Model(bodies=(bar,)), "bar")
    m = m.add(sc.LoadPattern("pull", [sc.EdgeForce(m.select("bar", boundary="right"), fx=P)]),
              sc.Segment("pull", 1.0))
    res = sc.solve_static(m)
    assert res.status == sc.Status.COMPLETED and len(res.events) == 0, res.message
    u = res.displacement(-1).reshape(-1, 3)
    eps = P / (E * W * H)
    x, y, z = bar.points.T
    exact = np.column_stack([eps * x, -NU * eps * y, -NU * eps * z])
    scale = eps * L
    assert np.abs(u - exact).max() <= 1e-10 * scale
    end = m.select("bar", boundary="right").index
    assert np.abs(u[end, 0] - P * L / (E * W * H)).max() <= 1e-10 * scale
    sigma = res.stress(-1)["bar"]  # (nel, 6): xx, yy, zz, xy, yz, xz
    assert sigma.shape[1] == 6
    np.testing.assert_allclose(sigma[:, 0], P / (W * H), rtol=1e-10)
    assert np.abs(sigma[:, 1:]).max() <= 1e-10 * P / (W * H)
    assert abs(res.reaction("left", "x")[-1] + P) <= 1e-12 * P


@pytest.mark.parametrize("element", ["tet10", "hex20", "hex27"])
def test_column_under_self_weight_quadratic_elements_exact(element):
    """Self-weight along −z (the default of a 3D BodyForce) balanced by a base pressure ρ g L:
    the 3D closed form (module docstring) to 1e-10 of ρ g L² / (2E) at every node, so the top
    shortens by ρ g L² / (2E); the symmetry supports carry nothing (1e-9 of the weight)."""
    a, L = 1.0, 4.0
    col = sc.box("col", (0, 0, 0), (a, a, L), (1, 1, 3), sc.Material(E, NU, RHO), element)
    m = sc.Model(bodies=(col,))
    origin = m.select("col", where=lambda x, y, z: (x == 0) & (y == 0) & (z == 0),
                      name="origin")
    m = m.add(sc.Support("left", m.select("col", boundary="left"), "x"),
              sc.Support("front", m.select("col", boundary="front"), "y"),
              sc.Support("origin", origin, "z"),
              sc.LoadPattern("weight", [
                  sc.BodyForce(),
                  sc.EdgeLoad(m.select("col", boundary="bottom"), normal=RHO * G * L)]),
              sc.Segment("weight", 1.0))
    res = sc.solve_static(m)
    u = res.displacement(-1).reshape(-1, 3)
    k = RHO * G / E
    x, y, z = col.points.T
    exact = np.column_stack([-NU * k * (z - L) * x, -NU * k * (z - L) * y,
                             k * (z**2 / 2 - L * z) + NU * k * (x**2 + y**2) / 2])
    scale = RHO * G * L**2 / (2 * E)
    assert np.abs(u - exact).max() <= 1e-10 * scale
    top_axis = np.flatnonzero((x == 0) & (y == 0) & (z == L))
    assert abs(u[top_axis, 2][0] + scale) <= 1e-10 * scale
    weight = RHO * G * a * a * L
    for sup, dof in (("left", "x"), ("front", "y"), ("origin", "z")):
        assert abs(res.reaction(sup, dof)[-1]) <= 1e-9 * weight


@pytest.mark.parametrize("element", ["hex20", "hex27"])
def test_cantilever_tip_deflection(element):
    """A 10 × 1 × 1 m cantilever (ν = 0: the clamped face restrains no contraction), tip force
    P along −z spread over the end face: the deflection of the end face's centre line within
    1 % of Euler–Bernoulli P L³ / (3 E I) (measured +0.57 %: the shear deformation) and within
    0.1 % of Timoshenko's P L³ / (3 E I) + P L / (κ G A), κ = 5/6 (measured −0.03 %)."""
    L, b, h, P = 10.0, 1.0, 1.0, 1.0e3
    beam = sc.box("beam", (0, 0, 0), (L, b, h), (10, 1, 2), sc.Material(E, 0.0), element)
    m = sc.Model(bodies=(beam,))
    m = m.add(sc.Support("clamp", m.select("beam", boundary="left"), "xyz"),
              sc.LoadPattern("tip", [sc.EdgeForce(m.select("beam", boundary="right"), fz=-P)]),
              sc.Segment("tip", 1.0))
    res = sc.solve_static(m)
    u = res.displacement(-1).reshape(-1, 3)
    pts = beam.points
    centre = np.flatnonzero((np.abs(pts[:, 0] - L) < 1e-9) & (np.abs(pts[:, 2] - h / 2) < 1e-9))
    w = -u[centre, 2].mean()
    I = b * h**3 / 12
    euler = P * L**3 / (3 * E * I)
    timoshenko = euler + P * L / (5 / 6 * E / 2 * b * h)
    assert abs(w / euler - 1) < 0.01
    assert abs(w / timoshenko - 1) < 0.001
    assert abs(res.reaction("clamp", "z")[-1] - P) <= 1e-9 * P


def test_load_resultants_are_the_applied_forces():
    """The assembled load vectors' resultants [F; M about the origin]: the weight ρ g V at the
    box's centroid, a total face force (fx, fy, fz) at the face's centroid, a nodal force n
    times on a set of n nodes — each to 1e-12 of its magnitude (sums of consistent nodal
    forces, exact in exact arithmetic)."""
    c0, c1 = np.array([1.0, -2.0, 0.5]), np.array([3.0, 1.0, 2.0])
    blk = sc.box("blk", c0, c1, (2, 3, 2), sc.Material(E, NU, RHO), "tet10")
    m = sc.Model(bodies=(blk,))
    top = m.select("blk", boundary="top")
    F = np.array([1.0e3, -2.0e3, 5.0e3])
    m = m.add(sc.Support("base", m.select("blk", boundary="bottom"), "xyz"),
              sc.LoadPattern("weight", [sc.BodyForce()]),
              sc.LoadPattern("face", [sc.EdgeForce(top, *F)]),
              sc.LoadPattern("nodes", [sc.NodalLoad(top, fx=1.0, fz=-2.0)]),
              sc.Segment("weight", 1.0))
    s = assemble(m)
    V = np.prod(c1 - c0)
    W = np.array([0.0, 0.0, -RHO * G * V])
    centroid = (c0 + c1) / 2
    face_centre = np.r_[centroid[:2], c1[2]]
    n = len(top)
    cases = {"weight": (W, centroid), "face": (F, face_centre)}
    for name, (force, at) in cases.items():
        r = load_resultant(m, s.dofs, s.loads[name].f)
        scale = np.linalg.norm(force) * max(1.0, np.linalg.norm(at))
        np.testing.assert_allclose(r[:3], force, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(r[3:], np.cross(at, force), rtol=0, atol=1e-12 * scale)
    r = load_resultant(m, s.dofs, s.loads["nodes"].f)
    np.testing.assert_allclose(r[:3], [n * 1.0, 0.0, -2.0 * n], rtol=0, atol=1e-12 * n)


def test_box_faces_are_named_and_placed():
    """box names its six faces (left/right: x, front/back: y, bottom/top: z) and each holds
    exactly the boundary nodes on its plane (counted: (2 nx + 1)(2 nz + 1) nodes of a hex27
    face normal to y, …)."""
    nx, ny, nz = 2, 3, 4
    b = sc.box("b", (0, 0, 0), (2, 3, 4), (nx, ny, nz), sc.Material(E, NU), "hex27")
    assert b.dim == 3 and b.boundary_names == ("left", "right", "front", "back", "bottom", "top")
    m = sc.Model(bodies=(b,))
    expected = {"left": (0, 0.0, (2 * ny + 1) * (2 * nz + 1)),
                "right": (0, 2.0, (2 * ny + 1) * (2 * nz + 1)),
                "front": (1, 0.0, (2 * nx + 1) * (2 * nz + 1)),
                "back": (1, 3.0, (2 * nx + 1) * (2 * nz + 1)),
                "bottom": (2, 0.0, (2 * nx + 1) * (2 * ny + 1)),
                "top": (2, 4.0, (2 * nx + 1) * (2 * ny + 1))}
    for face, (axis, value, count) in expected.items():
        idx = m.select("b", boundary=face).index
        assert len(idx) == count
        np.testing.assert_array_equal(b.points[idx, axis], value)
    on_z = m.select("b", z=4.0)
    assert set(on_z.index) == set(m.select("b", boundary="top").index)


def test_prescribed_uz_stretches_a_block_exactly():
    """A prescribed u_z = δ on the top face of a block on rollers: the linear field
    u_z = δ z / L, u_x = −ν δ x / L, u_y = −ν δ y / L, exact to 1e-12 δ on tet4; the pattern's
    reaction on the block is +E A δ / L along z (it pulls the top up) to 1e-10."""
    L, a, d = 2.0, 1.0, 1e-3
    b = sc.box("b", (0, 0, 0), (a, a, L), (1, 1, 2), sc.Material(E, NU), "tet4")
    m = _symmetric_supports(sc.Model(bodies=(b,)), "b")
    m = m.add(sc.LoadPattern("pull", [sc.PrescribedDisplacement(
                  m.select("b", boundary="top"), "z", d)]),
              sc.Segment("pull", 1.0))
    res = sc.solve_static(m)
    u = res.displacement(-1).reshape(-1, 3)
    x, y, z = b.points.T
    exact = np.column_stack([-NU * d / L * x, -NU * d / L * y, d / L * z])
    assert np.abs(u - exact).max() <= 1e-12 * d
    assert abs(res.reaction("pull", "z")[-1] - E * a * a * d / L) <= 1e-10 * E * a * a * d / L


# ---- bad input ---------------------------------------------------------------------------------
def _solid():
    return sc.box("solid", (0, 0, 0), (1, 1, 1), (1, 1, 1), sc.Material(E, NU, RHO))


def _raises(fn, item: str, text: str):
    with pytest.raises(sc.ModelError) as info:
        fn()
    assert info.value.item == item, info.value
    assert text in info.value.problem, info.value


def test_plane_or_thickness_on_a_3d_body_is_refused():
    _raises(lambda: sc.Model(bodies=(_solid(),), plane="stress"), "body 'solid'",
            "model.plane = 'stress'")
    _raises(lambda: sc.Model(bodies=(_solid(),), thickness=0.5), "body 'solid'",
            "model.thickness = 0.5")


def test_2d_and_3d_bodies_do_not_mix():
    plate = sc.rectangle("plate", (0, 0), (1, 1), 1, 1, sc.Material(E, NU))
    _raises(lambda: sc.Model(bodies=(_solid(), plate)), "body 'plate'", "is 2D")
    frame = sc.Frame.line("bar", (0, 0), (1, 0), 2, E=E, A=1.0, I=1.0)
    _raises(lambda: sc.Model(bodies=(_solid(), frame)), "frame 'bar'", "space frames")


def test_uz_on_a_2d_body_is_refused():
    plate = sc.rectangle("plate", (0, 0), (1, 1), 1, 1, sc.Material(E, NU))
    m = sc.Model(bodies=(plate,))
    m = m.add(sc.Support("base", m.select("plate", y=0.0), "yz"))
    _raises(lambda: assemble(m), "support 'base'.dofs", "names the DOF 'z', but the model is 2D")
    m2 = sc.Model(bodies=(plate,)).add(
        sc.Support("base", m.select("plate", y=0.0), "xy"),
        sc.LoadPattern("p", [sc.NodalLoad(m.select("plate", y=1.0), fz=1.0)]))
    _raises(lambda: assemble(m2), "load pattern 'p' load 0.fz", "the model is 2D")


def test_unknown_boundary_name_is_refused():
    m = sc.Model(bodies=(_solid(),))
    _raises(lambda: m.select("solid", boundary="roof"), "body 'solid' boundary 'roof'",
            "no such boundary (known: 'left', 'right', 'front', 'back', 'bottom', 'top')")


def test_2d_gravity_or_tangential_load_on_a_3d_body_is_refused():
    m = sc.Model(bodies=(_solid(),))
    base = sc.Support("base", m.select("solid", boundary="bottom"), "xyz")
    m1 = m.add(base, sc.LoadPattern("w", [sc.BodyForce(g=(0.0, -9.81 + 1.0))]))
    _raises(lambda: assemble(m1), "load pattern 'w' load 0 on body 'solid'",
            "has 2 components")
    m2 = m.add(base, sc.LoadPattern("t", [sc.EdgeLoad(m.select("solid", boundary="top"),
                                                      tangential=1.0)]))
    _raises(lambda: assemble(m2), "load pattern 't' load 0.tangential", "no direction")
    _raises(lambda: sc.box("b", (0, 0, 0), (1, 1, 1), (1, 1, 1), sc.Material(E, NU), "quad4"),
            "body 'b'.element", "unknown element 'quad4' for a box")
    _raises(lambda: sc.box("b", (0, 0, 0), (1, 1, 1), (1, 0, 1), sc.Material(E, NU)),
            "body 'b'.n[1]", "must be an integer >= 1")


# ---- extruded (prismatic) bodies ----------------------------------------------------------------
@pytest.mark.parametrize("element", ["quad4", "tri3", "quad8", "tri6", "quad9"])
def test_extruded_rectangle_is_a_conforming_bar(element):
    """A 3 × 2 rectangle swept along z in 2 layers: conforming (every inner face shared by two
    elements, so the boundary faces are exactly the 2 × 6 cells of the ends (× 2 for
    triangles) and 2 per perimeter edge and layer for triangles, 1 for quadrilaterals — a
    face that does not match its neighbour's would be counted as boundary), and pulled along z
    the linear field u_z = ε z, u_x = −ν ε x, u_y = −ν ε y to 1e-10 of the end displacement."""
    from stepcontact.model.mesh import extrude

    sec = sc.rectangle("sec", (0, 0), (2, 1), 3, 2, sc.Material(E, NU), element)
    bar = extrude(sec, (0.0, 1.5), 2, name="bar")
    tri = element.startswith("tri")
    assert len(bar.boundary) == 2 * 6 * (2 if tri else 1) + 2 * 10 * (2 if tri else 1)
    m = sc.Model(bodies=(bar,))
    m = m.add(sc.Support("x0", m.select("bar", x=0.0), "x"),
              sc.Support("y0", m.select("bar", y=0.0), "y"),
              sc.Support("start", m.select("bar", boundary="start"), "z"),
              sc.LoadPattern("pull", [sc.EdgeForce(m.select("bar", boundary="end"), fz=4e4)]),
              sc.Segment("pull", 1.0))
    u = sc.solve_static(m).displacement(-1).reshape(-1, 3)
    eps = 4e4 / (E * 2.0)
    x, y, z = bar.points.T
    exact = np.column_stack([-NU * eps * x, -NU * eps * y, eps * z])
    assert np.abs(u - exact).max() <= 1e-10 * eps * 1.5


def test_extruded_quad_region_weighs_its_volume():
    """A trapezoid (area 8 m²) swept 2 m along z: its weight under g = (0, −9.81, 0) (the
    section's y up) is ρ g × 16 m³ at the centroid, to 1e-12 (the resultant of the assembled
    load vector); the extruded mesh of triangles has 3 tetrahedra per prism."""
    from stepcontact.model.mesh import extrude

    sec = sc.quad_region("w", [(0, 0), (4, 0), (4, 1), (0, 3)], 4, 3,
                         sc.Material(E, NU, RHO), "tri3")
    body = extrude(sec, (0.0, 2.0), 3)
    assert body.element == "tet4" and len(body.cells) == 3 * 3 * len(sec.cells)
    m = sc.Model(bodies=(body,))
    m = m.add(sc.Support("base", m.select("w", y=0.0), "xyz"),
              sc.LoadPattern("w", [sc.BodyForce(g=(0.0, -G, 0.0))]))
    s = assemble(m)
    r = load_resultant(m, s.dofs, s.loads["w"].f)
    W = RHO * G * 8.0 * 2.0
    # the centroid of the section, from its two triangles (independent of the mesh)
    tris = np.array([[(0, 0), (4, 0), (4, 1)], [(0, 0), (4, 1), (0, 3)]], float)
    d1, d2 = tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    a = 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    assert a.sum() == 8.0
    cx, cy = (a[:, None] * tris.mean(axis=1)).sum(axis=0) / a.sum()
    force = np.array([0.0, -W, 0.0])
    at = np.array([cx, cy, 1.0])
    np.testing.assert_allclose(r[:3], force, rtol=0, atol=1e-12 * W)
    np.testing.assert_allclose(r[3:], np.cross(at, force), rtol=0, atol=1e-12 * W * 5)


def test_3d_stages_give_the_program_result_and_results_know_no_rotation():
    """Two construction stages (the weight, then a push) end where the same segments as one
    program end: displacements equal to 1e-12 of their largest (the same linear solves); a
    3D result refuses 'rz' (its third DOF is u_z) instead of returning u_z under that name."""
    b = sc.box("b", (0, 0, 0), (1, 1, 2), (1, 1, 2), sc.Material(E, NU, RHO), "hex20")
    m = sc.Model(bodies=(b,))
    common = [sc.Support("base", m.select("b", boundary="bottom"), "xyz"),
              sc.LoadPattern("w", [sc.BodyForce()]),
              sc.LoadPattern("push", [sc.EdgeForce(m.select("b", boundary="top"), fx=1e4)])]
    r1 = sc.solve_static(m.add(*common, sc.Segment("w", 1.0), sc.Segment("push", 1.0)))
    r2 = sc.solve_static(m.add(*common, sc.Stage("one", program=[sc.Segment("w", 1.0)]),
                               sc.Stage("two", program=[sc.Segment("push", 1.0)])))
    u1, u2 = r1.displacement(-1), r2.displacement(-1)
    assert np.abs(u1 - u2).max() <= 1e-12 * np.abs(u1).max()
    top = m.select("b", boundary="top")
    np.testing.assert_array_equal(r1.node_history(top, "ux")[-1], u1.reshape(-1, 3)[top.index, 0])
    with pytest.raises(ValueError, match="no rotation"):
        r1.node_history(top, "rz")
    with pytest.raises(ValueError, match="no rotation"):
        r1.reaction_history(top, "rz")


def test_crack_water_on_a_3d_body_is_accepted():
    """Water loads on faces work in 3D (tests/test_water3d.py), and water in joints too
    (tests/test_crack3d.py): a 3D model takes a CrackWater load."""
    m = sc.Model(bodies=(_solid(),))
    m = m.add(sc.LoadPattern("water", [sc.CrackWater("base")]))
    assert isinstance(m.patterns[0].loads[0], sc.CrackWater)


def test_pressure_function_on_faces_integrates_exactly():
    """A pressure p(x, y, z) = p0 (1 + x / 2) on the top face [0, 2] × [0, 1] of a hex8 box
    pushes down with ∫ p dA = p0 (2 + 1) · 1 = 3 p0 (a linear p, integrated exactly by the
    face quadrature), its line of action at x̄ = ∫ x p dA / ∫ p dA = (10/3) / 3 = 10/9; to
    1e-12."""
    p0 = 1.0e3
    b = sc.box("b", (0, 0, 0), (2, 1, 1), (4, 2, 1), sc.Material(E, NU), "hex8")
    m = sc.Model(bodies=(b,))
    m = m.add(sc.Support("base", m.select("b", boundary="bottom"), "xyz"),
              sc.LoadPattern("p", [sc.EdgeLoad(m.select("b", boundary="top"),
                                               normal=lambda x, y, z: p0 * (1 + x / 2))]))
    s = assemble(m)
    r = load_resultant(m, s.dofs, s.loads["p"].f)
    F = 3 * p0
    np.testing.assert_allclose(r[:3], [0.0, 0.0, -F], rtol=0, atol=1e-12 * F)
    # M = x̄ × F about the origin: M_x = y F_z, M_y = −x F_z with (x̄, ȳ) = (10/9, 1/2)
    np.testing.assert_allclose(r[3:5], [0.5 * -F, -(10 / 9) * -F], rtol=0, atol=1e-12 * F)


def test_degenerate_tetrahedron_is_refused_by_name():
    from skfem import MeshTet

    flat = MeshTet(np.array([[0.0, 1.0, 0.0, 1.0], [0.0, 0.0, 1.0, 1.0], [0.0, 0.0, 0.0, 0.0]]),
                   np.array([[0], [1], [2], [3]]))
    _raises(lambda: sc.Body.from_mesh("flat", flat, "tet4", sc.Material(E, NU)),
            "body 'flat' element 0", "is degenerate (zero volume)")
