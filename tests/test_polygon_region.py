"""``sc.polygon_region``: a triangle meshed without gmsh, any simple polygon by gmsh.

References (independent of the mesh): the polygon's own area and centroid by the shoelace
formula (a mesh of straight-sided cells fills it exactly: to 1e-12 relative), the weight of
the polygon ρ g A t and its moment about the origin −ρ g A t x_c (to 1e-12), the shape
quality 4√3 A/Σl² of the triangle itself (the structured triangles are all similar to it: to
1e-12), and the vertices' coordinates (nodes exactly there).
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.io.modelfile import model_from_dict
from stepcontact.model.meshcheck import QUALITY_WARN, corners, quality

CONCRETE = sc.Material(E=30e9, nu=0.2, density=2400.0)
ELEMENTS = ("tri3", "tri6", "quad4", "quad8", "quad9")
DAM = [(0.0, 0.0), (8.0, 0.0), (0.0, 10.0)]  # a triangular dam section, heel at the origin
#: a non-convex pentagon (a notch in its top), meshed by gmsh
NOTCHED = [(0.0, 0.0), (6.0, 0.0), (6.0, 6.0), (3.0, 2.0), (0.0, 6.0)]


def _area_centroid(P) -> tuple[float, np.ndarray]:
    """Shoelace area and centroid of the polygon P (counter-clockwise)."""
    P = np.asarray(P, float)
    x, y = P.T
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    c = x * yn - xn * y
    A = 0.5 * c.sum()
    return A, np.array([((x + xn) * c).sum(), ((y + yn) * c).sum()]) / (6 * A)


def _mesh_area_centroid(body) -> tuple[float, np.ndarray, np.ndarray]:
    pts, cells = corners(body)
    P = pts[cells]  # (n_cells, k, 2)
    x, y = P[..., 0], P[..., 1]
    xn, yn = np.roll(x, -1, axis=1), np.roll(y, -1, axis=1)
    c = x * yn - xn * y
    a = 0.5 * c.sum(axis=1)
    cx = ((x + xn) * c).sum(axis=1) / 6
    cy = ((y + yn) * c).sum(axis=1) / 6
    return a.sum(), np.array([cx.sum(), cy.sum()]) / a.sum(), a


def _needs_gmsh():
    pytest.importorskip("gmsh")


@pytest.mark.parametrize("element", ELEMENTS)
@pytest.mark.parametrize("shape", ["triangle", "notched"])
def test_area_centroid_and_vertices(shape, element):
    if shape == "notched":
        _needs_gmsh()
    V = DAM if shape == "triangle" else NOTCHED
    body = sc.polygon_region("dam", V, CONCRETE, element, size=1.0)
    A, c = _area_centroid(V)
    a, cm, cells = _mesh_area_centroid(body)
    assert (cells > 0).all()  # every cell counter-clockwise, none degenerate
    assert abs(a / A - 1) < 1e-12
    assert np.abs(cm - c).max() < 1e-12 * np.ptp(np.asarray(V), axis=0).max()
    for v in V:  # a node exactly at every vertex
        assert (body.points == v).all(axis=1).sum() == 1, v
    q = quality(*corners(body))
    assert q.quality.min() > QUALITY_WARN  # nothing `validate` would report


@pytest.mark.parametrize("n", [1, 2, 5, 12])
def test_structured_triangles_are_similar_to_the_triangle(n):
    """n cells along each edge: n² triangles, each of the triangle's shape (quality) and of
    area A/n²; the quadratic mesh has (2n + 1)(2n + 2)/2 nodes."""
    body = sc.polygon_region("dam", DAM, CONCRETE, "tri3", n=n)
    A, _ = _area_centroid(DAM)
    P = np.asarray(DAM)
    q_ref = 4 * np.sqrt(3) * A / (np.hypot(*(np.roll(P, -1, axis=0) - P).T) ** 2).sum()
    q = quality(*corners(body)).quality
    assert len(body.cells) == n * n and body.n_nodes == (n + 1) * (n + 2) // 2
    assert np.abs(q - q_ref).max() < 1e-12
    _, _, cells = _mesh_area_centroid(body)
    assert np.abs(cells / (A / n**2) - 1).max() < 1e-12
    six = sc.polygon_region("dam", DAM, CONCRETE, "tri6", n=n)
    assert six.n_nodes == (2 * n + 1) * (2 * n + 2) // 2


def test_quads_split_the_triangle_in_three_regions():
    """quads: n (even) cells along every edge, three regions of (n/2)² quads."""
    body = sc.polygon_region("dam", DAM, CONCRETE, "quad4", n=6)
    assert len(body.cells) == 3 * 3**2
    odd = sc.polygon_region("dam", DAM, CONCRETE, "quad4", n=5)  # rounded up to 6
    assert np.array_equal(odd.points, body.points)
    bottom = body.points[body.points[:, 1] == 0.0]
    assert len(bottom) == 7  # n + 1 nodes on the base


@pytest.mark.parametrize("element", ["tri3", "quad8"])
def test_gravity_resultant_is_the_weight_at_the_centroid(element):
    """Self-weight of the triangular dam on a fixed base: F_y = −ρ g A t and M_z about the
    origin = −ρ g A t x_c (x_c = B/3), from the assembled nodal forces (1e-12)."""
    body = sc.polygon_region("dam", DAM, CONCRETE, element, n=8)
    m = sc.Model(bodies=[body], thickness=2.0)
    m = m.add(sc.Support("base", m.select("dam", y=0.0)),
              sc.LoadPattern("weight", [sc.BodyForce()]), sc.Segment("weight", 1.0))
    res = sc.solve_static(m)
    Fx, Fy, Mz = res.load_resultant("weight")
    W = 2400.0 * 9.81 * 0.5 * 8.0 * 10.0 * 2.0
    assert abs(Fx) < 1e-12 * W
    assert abs(Fy / -W - 1) < 1e-12
    assert abs(Mz / (-W * 8.0 / 3.0) - 1) < 1e-12
    assert abs(res.reaction("base", "y")[-1] / W - 1) < 1e-9  # the base carries it


def test_vertices_can_be_selected():
    """The crest (0, H) and the toe (B, 0) are nodes that node sets select by coordinates."""
    body = sc.polygon_region("dam", DAM, CONCRETE, "quad4", n=4)
    m = sc.Model(bodies=[body])
    assert len(m.select("dam", x=0.0, y=10.0).index) == 1
    assert len(m.select("dam", x=8.0, y=0.0).index) == 1
    assert len(m.select("dam", x=0.0).index) == 5  # the upstream face: n + 1 nodes


def test_clockwise_vertices_give_the_same_mesh():
    ccw = sc.polygon_region("dam", DAM, CONCRETE, "tri3", n=4)
    cw = sc.polygon_region("dam", DAM[::-1], CONCRETE, "tri3", n=4)
    assert sorted(map(tuple, ccw.points)) == sorted(map(tuple, cw.points))
    assert (_mesh_area_centroid(cw)[2] > 0).all()


@pytest.mark.parametrize(("vertices", "kw", "item", "fragment"), [
    ([(0, 0), (4, 0), (0, 4), (4, 4)], {"n": 2}, "vertices",
     "crosses itself: edge 1 (vertices 1–2) meets edge 3"),
    ([(0, 0), (4, 0), (4, 0), (0, 4)], {"n": 2}, "vertices", "vertices 1 and 2 coincide"),
    ([(0, 0), (1, 1), (2, 2)], {"n": 2}, "vertices", "no area"),
    ([(0, 0), (1, 0)], {"n": 2}, "vertices", "at least three points"),
    ([(0, 0), (1, 0), (0, float("nan"))], {"n": 2}, "vertices", "finite"),
    (DAM, {}, "n", "either n"),
    (DAM, {"n": 2, "size": 1.0}, "n", "either n"),
    (DAM, {"n": 0}, "n", "integer >= 1"),
    (DAM, {"size": -1.0}, "size", "positive cell size"),
])
def test_bad_polygons_are_refused_naming_the_field(vertices, kw, item, fragment):
    with pytest.raises(sc.ModelError) as e:
        sc.polygon_region("dam", vertices, CONCRETE, "tri3", **kw)
    assert e.value.item == f"body 'dam'.{item}"
    assert fragment in e.value.problem


MODEL = """
[model]
name = "triangular dam"

[materials.concrete]
E = 30e9
nu = 0.2
density = 2400

[[bodies]]
name = "dam"
kind = "polygon"
vertices = [[0.0, 0.0], [8.0, 0.0], [0.0, 10.0]]
n = 6
element = "quad8"
material = "concrete"

[node_sets.base]
body = "dam"
y = 0.0

[[supports]]
nodes = "base"

[patterns.weight]
loads = [{ type = "gravity" }]

[[program]]
pattern = "weight"
end = 1.0
"""


def test_model_file_polygon_is_the_python_body():
    m = model_from_dict(tomllib.loads(MODEL))
    ref = sc.polygon_region("dam", DAM, CONCRETE, "quad8", n=6)
    assert np.array_equal(m.bodies[0].points, ref.points)
    assert np.array_equal(m.bodies[0].cells, ref.cells)


@pytest.mark.parametrize(("change", "path", "fragment"), [
    ('vertices = [[0.0, 0.0], [8.0, 0.0], [0.0, 10.0]]',
     "bodies[0].vertices", "crosses itself"),
    ("n = 6", "bodies[0]", "either n"),
])
def test_model_file_polygon_errors_name_the_field(change, path, fragment, tmp_path):
    from stepcontact.io.modelfile import validate_model_file

    bad = {"bodies[0].vertices": "vertices = [[0, 0], [8, 0], [0, 10], [8, 10]]",
           "bodies[0]": "size = 1.0\nn = 6"}[path]
    file = tmp_path / "dam.toml"
    file.write_text(MODEL.replace(change, bad), encoding="utf-8")
    problems = validate_model_file(file)
    assert any(p.item == path and fragment in p.message for p in problems), problems


def test_a_mesh_too_large_is_refused_before_it_is_made():
    """10⁷ cells along each edge: 10¹⁴ triangles, beyond any machine's memory."""
    with pytest.raises(sc.ModelError, match="too large"):
        sc.polygon_region("dam", DAM, CONCRETE, "tri3", n=10**7)
