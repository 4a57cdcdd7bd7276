"""Springs in any direction, mapped and half-disc meshes, rigid motions of bodies and models,
and the inclined-block example (closed forms, mesh quality, rotation invariance)."""

from __future__ import annotations

import runpy
from pathlib import Path

import meshio
import numpy as np
import pytest
from numpy.testing import assert_allclose
from skfem import MeshTri
from skfem.io.meshio import from_meshio

import stepcontact as sc
from stepcontact.fem.assembly import assemble
from stepcontact.io.modelfile import model_from_dict

MAT = sc.Material(E=30e9, nu=0.2, density=2400.0)
EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "inclined_block_springs.py"
ELEMENTS = ("tri3", "tri6", "quad4", "quad8", "quad9")


def signed_areas(body: sc.Body) -> np.ndarray:
    """Shoelace area of every cell of a body's (linear) scikit-fem mesh, m²."""
    x, y = body.mesh.p[:, body.mesh.t]
    return 0.5 * np.sum(x * np.roll(y, -1, axis=0) - np.roll(x, -1, axis=0) * y, axis=0)


def has_point(body, point) -> bool:
    """The body has a node exactly at ``point``."""
    return bool(np.any(np.all(body.points == np.asarray(point, float), axis=1)))


# --------------------------------------------------------------------------------------------
# springs
# --------------------------------------------------------------------------------------------
def two_blocks(*springs_of) -> sc.Model:
    """A fixed anchor block and a free block; ``springs_of(model)`` gives the springs."""
    anchor = sc.rectangle("anchor", (-2, 0), (-1, 1), 1, 1, MAT)
    block = sc.rectangle("block", (0, 0), (1, 1), 2, 2, MAT)
    m = sc.Model(bodies=[anchor, block])
    m = m.add(sc.Support("fix", m.select("anchor", boundary=True, where=lambda x, y: x > -9)))
    for f in springs_of:
        m = m.add(*f(m))
    return m


def test_spring_direction_is_normalised_and_stiffness_is_k_d_outer_d():
    s = sc.Spring("s", sc.NodeSet("b", [0]), k=4.0, direction=(3.0, -4.0), damping=2.5)
    assert s.direction == pytest.approx((0.6, -0.8), abs=1e-15)
    assert_allclose(s.stiffness_matrix(), 4.0 * np.outer([0.6, -0.8], [0.6, -0.8]), atol=1e-15)
    both = sc.Spring("t", sc.NodeSet("b", [0]), kx=1.0, ky=2.0, k=3.0, direction=(0.0, 5.0))
    assert_allclose(both.stiffness_matrix(), [[1.0, 0.0], [0.0, 5.0]], atol=0)
    assert sc.Spring("u", sc.NodeSet("b", [0]), kx=7.0).stiffness_matrix()[0, 0] == 7.0


@pytest.mark.parametrize("kwargs, item, text", [
    ({"k": 1.0, "direction": (0.0, 0.0)}, "spring 's'.direction", "is zero"),
    ({"k": 1.0}, "spring 's'.direction", "is needed with k"),
    ({"k": 1.0, "direction": (1.0, np.nan)}, "spring 's'.direction", "finite"),
    ({"k": 1.0, "direction": (1.0, 0.0, 0.0, 0.0)}, "spring 's'.direction", "finite vector"),
    ({"k": -1.0, "direction": (1.0, 0.0)}, "spring 's'.k", ">= 0"),
    ({"damping": -1.0}, "spring 's'.damping", ">= 0"),
])
def test_spring_errors_name_the_spring_and_field(kwargs, item, text):
    with pytest.raises(sc.ModelError) as info:
        sc.Spring("s", sc.NodeSet("b", [0]), **kwargs)
    assert info.value.item == item and text in info.value.problem


@pytest.mark.parametrize("to_ground", [True, False])
def test_axis_directions_give_the_kx_ky_stiffness_matrix(to_ground):
    """k along ±x / ±y is the same matrix as kx / ky, to the ground and between two nodes."""
    def springs(kind):
        def make(m):
            a = m.select("block", x=1.0)  # three nodes
            # b: the anchor's two nodes on x = -1 and its corner (the anchor is fixed)
            b = None if to_ground else sc.NodeSet("anchor", [*m.select("anchor", x=-1).index, 0])
            if kind == "axes":
                return [sc.Spring("s", a, b, kx=3e6, ky=5e6)]
            return [sc.Spring("s1", a, b, k=3e6, direction=(-2.0, 0.0)),
                    sc.Spring("s2", a, b, k=5e6, direction=(0.0, 0.1))]
        return make

    Ka = assemble(two_blocks(springs("axes"))).K
    Ki = assemble(two_blocks(springs("inclined"))).K
    assert abs(Ka - Ki).max() <= 1e-15 * abs(Ka).max()
    assert abs(Ka - Ka.T).max() == 0 and Ka.nnz == Ki.nnz


def test_inclined_springs_give_the_closed_form_displacement():
    """A block hung on springs at 30° and 120° (different stiffnesses, to the ground at every
    node) under a vertical load on every node translates rigidly by
    u = (F·d1 / k1) d1 + (F·d2 / k2) d2, whatever its own stiffness (a real solve)."""
    k1, k2, P = 2e6, 7e6, 1e3
    d1 = np.array([np.cos(np.radians(30)), np.sin(np.radians(30))])
    d2 = np.array([np.cos(np.radians(120)), np.sin(np.radians(120))])

    def springs(m):
        every = sc.NodeSet("block", np.arange(m.body("block").n_nodes), "all")
        return [sc.Spring("s30", every, k=k1, direction=tuple(3 * d1)),
                sc.Spring("s120", every, k=k2, direction=tuple(-d2)),
                sc.LoadPattern("load", [sc.NodalLoad(every, fy=-P)]), sc.Segment("load", 1.0)]

    m = two_blocks(springs)
    res = sc.solve_static(m)
    assert res.status == sc.Status.COMPLETED
    F = np.array([0.0, -P])
    u_exact = F @ d1 / k1 * d1 + F @ d2 / k2 * d2
    sys_ = assemble(m)
    nodes = m.global_nodes(sc.NodeSet("block", np.arange(m.body("block").n_nodes)))
    u = res.displacement(res.n_states - 1)
    got = np.column_stack([u[sys_.dofs.of[nodes, 0]], u[sys_.dofs.of[nodes, 1]]])
    assert_allclose(got, np.broadcast_to(u_exact, got.shape), rtol=1e-9, atol=0)
    # the spring is not along the load: the block moves sideways too
    assert abs(u_exact[0]) > 0.1 * abs(u_exact[1])


def test_damping_is_stored_and_statics_ignore_it():
    def springs(c):
        def make(m):
            every = sc.NodeSet("block", np.arange(m.body("block").n_nodes))
            return [sc.Spring("s", every, k=1e6, direction=(1, 1), damping=c),
                    sc.Spring("t", every, k=1e6, direction=(1, -1)),
                    sc.LoadPattern("load", [sc.NodalLoad(every, fx=1.0)]),
                    sc.Segment("load", 1.0)]
        return make

    a, b = two_blocks(springs(0.0)), two_blocks(springs(5e3))
    assert b.springs[0].damping == 5e3
    ua = sc.solve_static(a).displacement(1)
    ub = sc.solve_static(b).displacement(1)
    assert_allclose(ua, ub, rtol=0, atol=0)


def test_restrained_check_sees_inclined_springs_to_ground():
    def inclined(m):
        corner = m.select("block", x=0.0, y=0.0)
        other = m.select("block", x=1.0, y=0.0)
        return [sc.Spring("a", corner, k=1e6, direction=(1, 2)),
                sc.Spring("b", other, k=1e6, direction=(-2, 1)),
                sc.Spring("c", corner, k=1e6, direction=(2, -1))]

    assemble(two_blocks(inclined))  # held by springs only: accepted
    with pytest.raises(sc.ModelError, match="body 'block'.*not restrained"):
        assemble(two_blocks())
    zero = two_blocks(lambda m: [sc.Spring("z", m.select("block", x=0.0), kx=0.0)])
    with pytest.raises(sc.ModelError, match="not restrained"):
        assemble(zero)  # a spring of no stiffness holds nothing


def spring_file(spring: dict) -> dict:
    return {
        "materials": {"c": {"E": 30e9, "nu": 0.2, "density": 2400.0}},
        "bodies": [{"name": "block", "kind": "rectangle", "corner0": [0, 0], "corner1": [1, 1],
                    "nx": 1, "ny": 1, "material": "c"}],
        "node_sets": {"bottom": {"body": "block", "y": 0.0}},
        "supports": [{"name": "bed", "nodes": "bottom", "dofs": "y"}],
        "springs": [spring],
        "patterns": {"w": {"loads": [{"type": "gravity"}]}},
        "program": [{"pattern": "w", "end": 1.0}],
    }


def test_model_file_springs_in_any_direction():
    m = model_from_dict(spring_file({"name": "strut", "a": "bottom", "k": 2e6,
                                     "direction": [1.0, 1.0], "damping": 10.0, "kx": 1.0}))
    s = m.springs[0]
    assert s.direction == pytest.approx((2**-0.5, 2**-0.5), abs=1e-15)
    assert (s.k, s.damping, s.kx, s.ky) == (2e6, 10.0, 1.0, 0.0)
    with pytest.raises(sc.ModelError, match=r"springs\[0\]\.direction.*is zero"):
        model_from_dict(spring_file({"a": "bottom", "k": 2e6, "direction": [0.0, 0.0]}))
    with pytest.raises(sc.ModelError, match=r"springs\[0\]\.direction.*needed"):
        model_from_dict(spring_file({"a": "bottom", "k": 2e6}))
    with pytest.raises(sc.ModelError, match=r"springs\[0\]\.damping"):
        model_from_dict(spring_file({"a": "bottom", "kx": 1.0, "damping": -1.0}))


# --------------------------------------------------------------------------------------------
# quad_region
# --------------------------------------------------------------------------------------------
CORNERS = [(0.0, 0.0), (4.0, 0.5), (4.5, 2.0), (0.5, 3.0)]


def polygon_area(P) -> float:
    x, y = np.asarray(P, float).T
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


@pytest.mark.parametrize("element", ELEMENTS)
def test_quad_region_nodes_corners_and_areas(element):
    nx, ny = 6, 4
    b = sc.quad_region("w", CORNERS, nx, ny, MAT, element, grading={"bottom": 3.0, "left": 2.0})
    expected = {"tri3": (nx + 1) * (ny + 1), "quad4": (nx + 1) * (ny + 1),
                "tri6": (2 * nx + 1) * (2 * ny + 1), "quad9": (2 * nx + 1) * (2 * ny + 1),
                "quad8": (2 * nx + 1) * (2 * ny + 1) - nx * ny}[element]
    assert b.n_nodes == expected
    assert all(has_point(b, c) for c in CORNERS)  # the corners are nodes, exactly
    a = signed_areas(b)
    assert a.min() > 0  # counter-clockwise, none folded
    assert a.sum() == pytest.approx(polygon_area(CORNERS), rel=1e-12)
    assert len(a) == nx * ny * (2 if element.startswith("tri") else 1)


def edge_steps(b, start, end, n) -> np.ndarray:
    """Lengths of the n steps between the nodes on the straight edge start -> end (linear
    element nodes, sorted along the edge)."""
    P0, P1 = np.asarray(start, float), np.asarray(end, float)
    d = P1 - P0
    L = np.linalg.norm(d)
    rel = b.mesh.p.T - P0
    on = np.abs(rel[:, 0] * d[1] - rel[:, 1] * d[0]) / L < 1e-9
    s = np.sort(rel[on] @ d / L)
    assert len(s) == n + 1
    return np.diff(s)


def test_quad_region_grading_towards_edges_and_corners():
    P = CORNERS
    # (gx, gy): last / first cell along each direction, as for rectangle
    b = sc.quad_region("w", P, 5, 4, MAT, grading=(4.0, 0.5))
    h = edge_steps(b, P[0], P[1], 5)
    assert h[-1] / h[0] == pytest.approx(4.0, rel=1e-12)
    assert np.all(np.diff(h) > 0)
    h = edge_steps(b, P[0], P[3], 4)
    assert h[-1] / h[0] == pytest.approx(0.5, rel=1e-12)
    # towards the bottom edge: cells shrink towards it along both side edges, ratio 6
    b = sc.quad_region("w", P, 3, 8, MAT, grading={"bottom": 6.0})
    for side in ((P[0], P[3]), (P[1], P[2])):
        h = edge_steps(b, *side, 8)
        assert h.max() / h.min() == pytest.approx(6.0, rel=1e-12) and h.argmin() == 0
    assert np.allclose(np.diff(edge_steps(b, P[0], P[1], 3)), 0.0, atol=1e-12)
    # towards corner 2 (right and top edges)
    b = sc.quad_region("w", P, 6, 5, MAT, grading={"right": 3.0, "top": 2.0})
    h = edge_steps(b, P[3], P[2], 6)
    assert h[0] / h[-1] == pytest.approx(3.0, rel=1e-12) and h.argmin() == 5
    h = edge_steps(b, P[1], P[2], 5)
    assert h[0] / h[-1] == pytest.approx(2.0, rel=1e-12) and h.argmin() == 4
    # towards both side edges: symmetric, smallest at both ends
    b = sc.quad_region("w", [(0, 0), (2, 0), (2, 1), (0, 1)], 8, 1, MAT,
                       grading={"left": 5.0, "right": 5.0})
    h = edge_steps(b, (0, 0), (2, 0), 8)
    assert_allclose(h, h[::-1], rtol=1e-12)
    assert h.max() / h.min() == pytest.approx(5.0, rel=1e-12)
    assert h[0] == pytest.approx(h.min(), rel=1e-12) and h[-1] == pytest.approx(h[0], rel=1e-12)


def test_quad_region_of_a_rectangle_is_the_rectangle():
    b = sc.quad_region("r", [(0, 0), (3, 0), (3, 2), (0, 2)], 6, 4, MAT, "quad8",
                       grading=(2.0, 3.0))
    r = sc.rectangle("r", (0, 0), (3, 2), 6, 4, MAT, "quad8", grading=(2.0, 3.0))
    assert b.n_nodes == r.n_nodes
    assert_allclose(b.points[np.lexsort(b.points.T)], r.points[np.lexsort(r.points.T)],
                    atol=1e-14)


@pytest.mark.parametrize("kwargs, item, text", [
    ({"corners": CORNERS[::-1]}, "body 'w'.corners", "clockwise"),
    ({"corners": [(0, 0), (4, 0), (1, 1), (0, 4)]}, "body 'w'.corners", "convex"),
    ({"corners": [(0, 0), (1, 0), (1, 1)]}, "body 'w'.corners", "four finite points"),
    ({"corners": [(0, 0), (1, 0), (1, np.inf), (0, 1)]}, "body 'w'.corners", "finite"),
    ({"nx": 0}, "body 'w'.nx", "integer >= 1"),
    ({"ny": 2.5}, "body 'w'.ny", "integer >= 1"),
    ({"element": "hex8"}, "body 'w'.element", "unknown element"),
    ({"grading": {"bottom": 0.5}}, "body 'w'.grading['bottom']", ">= 1"),
    ({"grading": {"north": 2.0}}, "body 'w'.grading", "unknown edge 'north'"),
    ({"grading": (1.0, -2.0)}, "body 'w'.grading", "factors > 0"),
])
def test_quad_region_errors_name_body_and_field(kwargs, item, text):
    args = {"corners": CORNERS, "nx": 2, "ny": 2, "element": "quad4", "grading": (1.0, 1.0)}
    args.update(kwargs)
    with pytest.raises(sc.ModelError) as info:
        sc.quad_region("w", args["corners"], args["nx"], args["ny"], MAT, args["element"],
                       grading=args["grading"])
    assert info.value.item == item and text in info.value.problem


# --------------------------------------------------------------------------------------------
# half disc
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("element", ELEMENTS)
def test_half_disc_contact_node_boundary_and_areas(element):
    c, R = np.array([1.0, 0.5]), 0.5
    b = sc.half_disc("roller", tuple(c), R, 6, 20, MAT, element, ratio=10.0)
    assert has_point(b, (1.0, 0.0))  # the contact point is a node, exactly
    a = signed_areas(b)
    assert a.min() > 0
    # a polygon inscribed in the half disc: slightly less than its area
    assert 0.99 * np.pi * R**2 / 2 < a.sum() < np.pi * R**2 / 2
    # the mesh's boundary vertices lie on the flat face (exactly) or on the arc (to round-off)
    vertices = b.mesh.p.T[np.unique(b.mesh.facets[:, b.mesh.boundary_facets()])]
    flat = vertices[:, 1] == c[1]
    on_arc = np.isclose(np.linalg.norm(vertices - c, axis=1), R, rtol=1e-12, atol=0)
    assert np.all(flat | on_arc)
    assert on_arc.sum() == 20 + 1  # n_around + 1 spokes
    assert flat.sum() >= 2 * 6 + 3  # the end spokes' rings and the core's top
    assert np.all(np.abs(vertices[flat, 0] - c[0]) <= R) and b.points[:, 1].max() == c[1]


def test_half_disc_refines_towards_the_contact_point():
    c, R, ratio = np.array([0.0, 1.0]), 1.0, 12.0
    b = sc.half_disc("roller", tuple(c), R, 10, 32, MAT, "quad4", ratio=ratio)
    p = b.mesh.p.T
    # arc nodes by angle from the downward vertical
    r = np.linalg.norm(p - c, axis=1)
    arc = p[np.isclose(r, R, rtol=1e-12)]
    psi = np.sort(np.arctan2(arc[:, 0] - c[0], c[1] - arc[:, 1]))
    steps = np.diff(psi)
    bottom = np.abs(psi[:-1] + 0.5 * steps) < np.pi / 4  # the bottom quarters
    assert steps[bottom].argmin() in (bottom.sum() // 2 - 1, bottom.sum() // 2)
    assert steps[bottom].max() / steps[bottom].min() == pytest.approx(ratio, rel=1e-9)
    assert steps.min() == pytest.approx(steps[bottom].min(), rel=1e-12)
    # the spoke below the centre: radial steps shrink towards the contact point by `ratio`
    spoke = np.sort(p[p[:, 0] == c[0], 1])
    below = spoke[spoke <= c[1] - R / 2]  # from the contact point to the core's bottom
    h = np.diff(below)
    assert len(h) == 10 and h.argmin() == 0
    assert h.max() / h.min() == pytest.approx(ratio, rel=1e-9)
    # the cells at the contact point are the smallest of the mesh
    a = signed_areas(b)
    touching = np.any(b.mesh.t == np.flatnonzero(np.all(p == c - (0, R), axis=1))[0], axis=0)
    assert a[touching].max() <= np.sort(a)[3]
    assert a.max() / a[touching].min() > ratio


def test_half_disc_uniform_node_count():
    M, N = 5, 24  # n1 = 6 steps on each side quarter, n2 = 12 on the bottom quarters
    b = sc.half_disc("d", (0, 0), 2.0, M, N, MAT, "quad4", refine_toward=None)
    assert b.n_nodes == 13 * 7 + M * (N + 1)
    assert len(b.mesh.t.T) == 12 * 6 + M * N
    p = b.mesh.p.T
    arc = p[np.isclose(np.linalg.norm(p, axis=1), 2.0, rtol=1e-12)]
    psi = np.sort(np.arctan2(arc[:, 0], -arc[:, 1]))
    assert_allclose(np.diff(psi), np.pi / N, rtol=1e-12)


@pytest.mark.parametrize("kwargs, item, text", [
    ({"n_around": 7}, "body 'd'.n_around", "even"),
    ({"n_around": 2}, "body 'd'.n_around", ">= 4"),
    ({"n_radial": 0}, "body 'd'.n_radial", ">= 1"),
    ({"radius": 0.0}, "body 'd'.radius", "positive"),
    ({"center": (0.0, np.nan)}, "body 'd'.center", "finite"),
    ({"ratio": 0.5}, "body 'd'.ratio", ">= 1"),
    ({"refine_toward": "top"}, "body 'd'.refine_toward", "'bottom'"),
    ({"element": "tri4"}, "body 'd'.element", "unknown element"),
])
def test_half_disc_errors_name_body_and_field(kwargs, item, text):
    args = {"center": (0.0, 0.0), "radius": 1.0, "n_radial": 3, "n_around": 8,
            "element": "quad4", "refine_toward": "bottom", "ratio": 4.0}
    args.update(kwargs)
    with pytest.raises(sc.ModelError) as info:
        sc.half_disc("d", args["center"], args["radius"], args["n_radial"], args["n_around"],
                     MAT, args["element"], refine_toward=args["refine_toward"],
                     ratio=args["ratio"])
    assert info.value.item == item and text in info.value.problem


def test_body_from_any_skfem_or_meshio_mesh():
    disc = sc.Body.from_mesh("disc", MeshTri.init_circle(2), "tri6", MAT)
    assert disc.n_nodes > 0
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    mio = meshio.Mesh(points, [("triangle", np.array([[0, 1, 2], [0, 2, 3]]))])
    b = sc.Body.from_mesh("two", from_meshio(mio), "tri3", MAT)
    assert b.n_nodes == 4 and len(b.boundary) == 4


# --------------------------------------------------------------------------------------------
# rotate and translate
# --------------------------------------------------------------------------------------------
def turn(p, angle, about):
    Q = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    return (np.asarray(p) - about) @ Q.T + about


@pytest.mark.parametrize("element", ["tri6", "quad8"])
def test_rotate_and_translate_bodies_and_frames(element):
    b = sc.quad_region("w", CORNERS, 3, 2, MAT, element)
    a, about = 0.7, np.array([1.0, -2.0])
    rb = sc.rotate(b, a, about=tuple(about))
    assert_allclose(rb.points, turn(b.points, a, about), atol=1e-14)
    assert np.array_equal(rb.cells, b.cells) and np.array_equal(rb.boundary, b.boundary)
    assert_allclose(signed_areas(rb), signed_areas(b), rtol=1e-12)
    assert b.points[0].tolist() == [0.0, 0.0]  # the original is unchanged
    tb = sc.translate(b, (2.0, -1.0))
    assert_allclose(tb.points, b.points + (2.0, -1.0), atol=0)
    fr = sc.Frame.line("beam", (0, 0), (2, 0), 4, E=1e9, A=0.1, I=1e-3)
    assert_allclose(sc.rotate(fr, np.pi / 2).points[-1], (0.0, 2.0), atol=1e-15)
    assert_allclose(sc.translate(fr, (1, 1)).points[0], (1.0, 1.0), atol=0)


def test_rotate_model_turns_geometry_not_the_world():
    m = block_on_base()
    m = m.add(sc.Spring("strut", m.select("block", x=1.0, y=1.5), k=1e6, direction=(1.0, 0.0)),
              sc.Spring("axes", m.select("block", x=3.0, y=1.5), kx=4e6, ky=1e6),
              sc.Interface("pad", m.select("block", y=2.0), m.select("base", y=1.0),
                           normal=(0.0, 1.0), friction=0.1))
    a = np.radians(30)
    r = sc.rotate(m, a)
    Q = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    assert_allclose(r.springs[0].direction, Q @ (1.0, 0.0), atol=1e-15)
    # a spring with kx != ky turns into min(kx, ky) on both axes + |kx − ky| along Q ex
    K = np.diag([4e6, 1e6])
    assert_allclose(r.springs[1].stiffness_matrix(), Q @ K @ Q.T, rtol=1e-12, atol=1e-6)
    assert_allclose(r.interfaces[1].normal, Q @ (0.0, 1.0), atol=1e-15)
    assert r.interfaces[0].normal is None
    # the world does not turn: gravity and the support stay
    g = r.pattern("weight").loads[0].g
    assert tuple(g) == (0.0, -9.81) and r.supports[0].dofs == ("x", "y")
    turned = sc.rotate(m, a, rotate_loads=True)
    assert_allclose(turned.pattern("weight").loads[0].g, Q @ (0.0, -9.81), atol=1e-15)
    # node sets are local indices: the same nodes, at turned positions
    ns = m.select("block", y=1.0)
    assert_allclose(r.body("block").points[ns.index], turn(m.body("block").points[ns.index],
                                                           a, np.zeros(2)), atol=1e-14)


def test_rotate_errors():
    m = block_on_base()
    with pytest.raises(sc.ModelError, match=r"rotate\.angle"):
        sc.rotate(m, np.nan)
    with pytest.raises(sc.ModelError, match=r"rotate\.about"):
        sc.rotate(m, 0.1, about=(0.0,))
    with pytest.raises(sc.ModelError, match=r"translate\.offset"):
        sc.translate(m, (1.0, np.inf))
    with pytest.raises(sc.ModelError, match="expects a Body, Frame or Model"):
        sc.rotate("block", 0.1)
    both = m.add(sc.Spring("s", m.select("block", x=1.0, y=1.5), kx=1.0, ky=2.0, k=1.0,
                           direction=(1.0, 1.0)))
    with pytest.raises(sc.ModelError, match="spring 's'.*kx != ky"):
        sc.rotate(both, 0.1)
    pd = m.add(sc.LoadPattern("move", [sc.PrescribedDisplacement(m.select("base", y=0.0),
                                                                  "x", 1e-3)]))
    sc.rotate(pd, 0.1)  # the world does not turn: fine
    with pytest.raises(sc.ModelError, match="load pattern 'move' load 0.*prescribed x"):
        sc.rotate(pd, 0.1, rotate_loads=True)


def block_on_base(friction: float = 0.5) -> sc.Model:
    """The block of examples/block_on_base.py (coarser): weight, then a push until it slides."""
    base = sc.rectangle("base", (0, 0), (4, 1), 8, 2, MAT)
    block = sc.rectangle("block", (1, 1), (3, 2), 4, 2, MAT)
    m = sc.Model(bodies=[base, block], name="block-on-base")
    return m.add(
        sc.Support("bed", m.select("base", y=0), "xy"),
        sc.Interface("joint", plus=m.select("block", y=1), minus=m.select("base", y=1),
                     friction=friction),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
        sc.LoadPattern("push", [sc.EdgeLoad(m.select("block", x=1), normal=1.0)]),
        sc.Segment("weight", 1.0),
        sc.Segment("push", 1e5),
    )


def test_rotated_and_translated_block_slides_at_the_same_load_factors():
    """The whole problem turned (rotate_loads=True) and moved: the same events, in the same
    order, at the same load factors (1e-9), and the same sliding load f·W."""
    m = block_on_base()
    ref = sc.solve_static(m)
    W = 2.0 * 1.0 * MAT.density * 9.81
    assert ref.multipliers[-1].equilibrium_lost == pytest.approx(0.5 * W, rel=1e-9)
    for moved in (sc.rotate(m, np.radians(35.0), about=(1.0, -2.0), rotate_loads=True),
                  sc.translate(sc.rotate(m, -2.0, rotate_loads=True), (10.0, 5.0))):
        res = sc.solve_static(moved)
        assert res.status == ref.status
        assert [(e.cfe, e.transition) for e in res.events] == \
            [(e.cfe, e.transition) for e in ref.events]
        assert_allclose([e.lam for e in res.events], [e.lam for e in ref.events], rtol=1e-9)
        for a, b in zip(res.multipliers, ref.multipliers, strict=True):
            for key in ("first_slip", "first_opening", "equilibrium_lost"):
                va, vb = getattr(a, key), getattr(b, key)
                assert (va is None) == (vb is None)
                if va is not None:
                    assert va == pytest.approx(vb, rel=1e-9)


# --------------------------------------------------------------------------------------------
# the example
# --------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def example():
    return runpy.run_path(str(EXAMPLE), run_name="inclined_block_springs")


@pytest.mark.parametrize("degrees, friction", [(30.0, 0.3), (20.0, 0.2)])
def test_inclined_block_slides_at_the_hand_statics(example, degrees, friction):
    """Rope force + friction f W cos α = W sin α when the block starts to slide (1e-8), and the
    rope spring (along the slope) carries the winch force at every state."""
    alpha = np.radians(degrees)
    m = example["inclined_model"](alpha, friction)
    res = sc.solve_static(m)
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    T = example["slide_force"](res)
    hand = example["hand_slide_force"](alpha, friction)
    W = example["block_weight"]()
    assert T == pytest.approx(hand, rel=1e-8)
    assert T + friction * W * np.cos(alpha) == pytest.approx(W * np.sin(alpha), rel=1e-8)
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(
        friction * W * np.cos(alpha), rel=1e-8)
    # the rope: k d·(u_sled − u_block) equals the winch factor at every state
    rope = m.springs[0]
    assert_allclose(rope.direction, (np.cos(alpha), np.sin(alpha)), atol=1e-15)
    sys_ = assemble(m)
    a, b = m.global_nodes(rope.a)[0], m.global_nodes(rope.b)[0]
    iw = list(res.pattern_names).index("winch")
    for i in range(res.n_states):
        u = res.displacement(i)
        du = u[sys_.dofs.of[b, :2]] - u[sys_.dofs.of[a, :2]]
        force = rope.k * float(np.dot(rope.direction, du))
        assert force == pytest.approx(res.factors[i, iw], rel=1e-7, abs=1e-6 * W)


def test_model_file_quad_and_half_disc_bodies_match_the_api():
    """``kind = "quad"`` and ``kind = "half_disc"`` in a model file make the same meshes as
    :func:`quad_region` and :func:`half_disc`; a clockwise quad is an error naming the body."""
    from stepcontact.io.modelfile import model_from_dict

    mat = {"E": 30e9, "nu": 0.2, "density": 2400}
    corners = [[0, 0], [8, 0], [2, 12], [0, 12]]
    d = {
        "materials": {"c": mat},
        "bodies": [
            {"name": "dam", "kind": "quad", "corners": corners, "nx": 4, "ny": 6,
             "grading": {"bottom": 3.0}, "material": "c"},
            {"name": "roller", "kind": "half_disc", "center": [20.0, 1.0], "radius": 1.0,
             "n_radial": 3, "n_around": 8, "element": "quad8", "ratio": 4.0, "material": "c"},
        ],
        "supports": [{"nodes": "base"}, {"nodes": "flat"}],
        "node_sets": {"base": {"body": "dam", "y": 0.0}, "flat": {"body": "roller", "y": 1.0}},
        "patterns": {"w": {"loads": [{"type": "gravity"}]}},
        "program": [{"pattern": "w", "end": 1.0}],
    }
    m = model_from_dict(d)
    material = sc.Material(**mat)
    ref_q = sc.quad_region("dam", corners, 4, 6, material, grading={"bottom": 3.0})
    ref_d = sc.half_disc("roller", (20.0, 1.0), 1.0, 3, 8, material, "quad8", ratio=4.0)
    np.testing.assert_allclose(m.body("dam").points, ref_q.points, atol=1e-12)
    np.testing.assert_allclose(m.body("roller").points, ref_d.points, atol=1e-12)
    d["bodies"][0]["corners"] = corners[::-1]
    with pytest.raises(sc.ModelError, match=r"bodies\[0\]"):
        model_from_dict(d)
