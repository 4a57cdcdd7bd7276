"""3D contact-surface geometry (stepcontact.contact.surface3d) against closed forms.

* Surfaces of boxes (tetrahedra and hexahedra, linear and quadratic): total area 2(ab + bc +
  ca) to 1e-13 relative, outward normals equal to the faces' axis normals to 1e-14, mid-side
  and centre nodes at the midpoints of straight sides to 1e-14 m; named boundaries.
* Tributary areas: h², h²/2, h²/4 on a uniform grid of squares, A/3 per corner of triangles,
  Σ = the area to 1e-13 relative.
* Node-to-facet: the foot of the perpendicular on a tilted triangle and quadrilateral, the
  closest point of a side or a corner (segment formulas), the closest point on a parabola
  z = x² represented exactly by a 9-node facet (the root of the cubic of its normal), all to
  1e-12 m or better; the basis t₁, t₂, n orthonormal and right-handed to 1e-14.
* Clipping: two squares turned by θ about their common centre (the octagon's area in closed
  form), a triangle cutting a square's corner, containment and no overlap, to 1e-14.
* Mortar on non-matching meshes (MeshTet / MeshHex init_tensor of different spacings, S−
  turned by 20°, quadrilaterals made trapezoidal, the whole pair turned into a tilted plane):
  Σ D = Σ M = the overlap area (closed form) to 1e-12; constant and linear fields on S− carried
  to S+ exactly (patch condition) to 1e-12, by the dual weights and by D⁻¹ M.
"""

from __future__ import annotations

import numpy as np
import pytest
import skfem
from numpy.testing import assert_allclose
from scipy.sparse.linalg import spsolve
from scipy.spatial.transform import Rotation

from stepcontact.contact.surface3d import (
    Surface,
    clip_polygons,
    local_basis,
    mortar,
    polygon_areas,
    project_points,
    surface_of_mesh,
)
from stepcontact.errors import ModelError

MESHES = {"tet4": skfem.MeshTet, "tet10": skfem.MeshTet, "hex8": skfem.MeshHex,
          "hex20": skfem.MeshHex, "hex27": skfem.MeshHex}


def _box(element, nx=3, ny=4, nz=3, a=1.0, b=2.0, c=3.0):
    """A box [0, a] × [0, b] × [0, c] with uneven node spacings, m."""
    xs = a * np.linspace(0, 1, nx) ** 1.3
    ys = b * np.linspace(0, 1, ny) ** 0.8
    zs = c * np.linspace(0, 1, nz)
    return MESHES[element].init_tensor(xs, ys, zs).with_defaults()


# ---- surfaces of meshes -----------------------------------------------------------------------
@pytest.mark.parametrize("element", list(MESHES))
def test_box_area_and_outward_normals(element):
    """A 1 × 2 × 3 m box: area 2(ab + bc + ca) = 22 m² (1e-13 relative), each facet's normal
    the outward normal of the box face it lies on (1e-14)."""
    S = surface_of_mesh(_box(element), element)
    assert_allclose(S.areas.sum(), 22.0, rtol=1e-13)
    c = S.centroids
    dims = np.array([1.0, 2.0, 3.0])
    on = np.isclose(c, 0.0, atol=1e-12, rtol=0) | np.isclose(c, dims, atol=1e-12, rtol=0)
    assert np.all(on.sum(axis=1) == 1)  # each centroid on exactly one face
    expect = np.where(on, np.where(np.isclose(c, 0.0, atol=1e-12, rtol=0), -1.0, 1.0), 0.0)
    assert_allclose(S.normals, expect, atol=1e-14, rtol=0)


@pytest.mark.parametrize("element", ["tet10", "hex20", "hex27"])
def test_quadratic_facet_nodes_at_midpoints(element):
    """Straight-sided meshes: mid-side nodes at the midpoints of their sides, the centre of a
    9-node facet at the mean of its corners (1e-14 m)."""
    S = surface_of_mesh(_box(element), element)
    P = S.points[S.facets]
    nc = 3 if element == "tet10" else 4
    corners = P[:, :nc]
    mid = 0.5 * (corners + np.roll(corners, -1, axis=1))
    assert_allclose(P[:, nc:2 * nc], mid, atol=1e-14, rtol=0)
    if element == "hex27":
        assert_allclose(P[:, 8], corners.mean(axis=1), atol=1e-14, rtol=0)


def test_named_boundary_and_its_errors():
    """``mesh.boundaries['top']`` (y = 2 in scikit-fem's defaults): area a c = 3 m² (1e-13),
    normals +y; an unknown name and an inner facet are errors naming the boundary."""
    m = _box("hex8")
    S = surface_of_mesh(m, boundary="top")
    assert_allclose(S.areas.sum(), 3.0, rtol=1e-13)
    assert_allclose(S.normals, np.tile([0.0, 1.0, 0.0], (len(S), 1)), atol=1e-14, rtol=0)
    assert_allclose(S.points[S.nodes, 1], 2.0, atol=1e-14, rtol=0)
    with pytest.raises(ModelError, match="boundary 'roof'"):
        surface_of_mesh(m, boundary="roof")
    inner = np.setdiff1d(np.arange(m.facets.shape[1]), m.boundary_facets())[:1]
    with pytest.raises(ModelError, match="inner facet"):
        surface_of_mesh(m.with_boundaries({"cut": inner}), boundary="cut")
    with pytest.raises(ModelError, match="MeshTet or MeshHex"):
        surface_of_mesh(skfem.MeshTri())


def test_orientation_check():
    """Surfaces from meshes are consistently oriented; one facet turned the other way is named
    (the facet found is one of the two running through the shared side alike)."""
    for element in MESHES:
        surface_of_mesh(_box(element), element).check_orientation()
    S = surface_of_mesh(_box("hex8"))
    fac = S.facets.copy()
    fac[5] = fac[5, ::-1]
    with pytest.raises(ModelError, match=r"facet (5|\d+).*not consistently oriented") as err:
        Surface(S.points, fac, "quad4").check_orientation()
    bad = int(err.value.item.split()[-1])
    assert bad == 5 or len(np.intersect1d(fac[bad], fac[5])) == 2


def test_plain_surface_errors_name_the_facet():
    """Bad arrays: a node id out of range and a degenerate facet, each named."""
    pts = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0]])
    with pytest.raises(ModelError, match="facet 1"):
        Surface(pts, np.array([[0, 1, 2], [0, 1, 7]]), "tri3")
    with pytest.raises(ModelError, match="facet 0.*degenerate"):
        Surface(pts, np.array([[0, 1, 3]]), "tri3")
    with pytest.raises(ModelError, match="kind"):
        Surface(pts, np.array([[0, 1, 2]]), "tri4")


# ---- tributary areas --------------------------------------------------------------------------
def test_nodal_areas_of_squares_and_triangles():
    """A 4 × 3 grid of h = 0.5 m squares (z = 0 face of a hex box): corners h²/4, sides h²/2,
    inside h² (exact, 1e-14 m²); triangles (tet box): each node a third of the areas of its
    facets (cross products); Σ = the face area to 1e-13 relative for every element kind."""
    h = 0.5
    m = skfem.MeshHex.init_tensor(np.arange(5) * h, np.arange(4) * h, np.arange(2) * h)
    S = surface_of_mesh(m.with_defaults(), boundary="front")  # z = 0
    A = S.nodal_areas()[S.nodes]
    x, y = S.points[S.nodes, 0], S.points[S.nodes, 1]
    edges = np.isclose(x, 0) | np.isclose(x, 2.0)
    edges_y = np.isclose(y, 0) | np.isclose(y, 1.5)
    expect = h * h / 2.0 ** (edges.astype(int) + edges_y.astype(int))
    assert_allclose(A, expect, atol=1e-14, rtol=0)

    T = surface_of_mesh(_box("tet4"))
    P = T.points[T.facets]
    fa = 0.5 * np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1)
    ref = np.zeros(len(T.points))
    np.add.at(ref, T.facets, fa[:, None] / 3)
    assert_allclose(T.nodal_areas(), ref, atol=1e-14, rtol=0)
    for element in MESHES:
        S = surface_of_mesh(_box(element), element)
        assert_allclose(S.nodal_areas().sum(), 22.0, rtol=1e-13)


# ---- node-to-facet ----------------------------------------------------------------------------
def _tilted():
    """A rotation taking the xy-plane into a tilted plane (fixed seed)."""
    return Rotation.from_euler("zyx", [0.4, 0.7, -0.3]).as_matrix()


def test_projection_on_a_tilted_triangle():
    """A right triangle (legs 2 m) turned into a tilted plane: a point over its inside projects
    to the foot of the perpendicular (barycentric weights (1 − r − s, r, s) of the untilted
    coordinates), a point beyond the hypotenuse to its closest point on that side, a point
    beyond a corner to the corner; gaps and distances by the formulas, to 1e-14 m."""
    R = _tilted()
    local = np.array([[0.0, 0, 0], [2, 0, 0], [0, 2, 0]])
    S = Surface(local @ R.T + [1.0, -2.0, 0.5], np.array([[0, 1, 2]]), "tri3")
    q_local = np.array([[0.5, 0.25, 0.3], [1.5, 1.5, -0.2], [-1.0, -0.5, 0.4]])
    q = q_local @ R.T + [1.0, -2.0, 0.5]
    r = project_points(q, S)
    foot = np.array([[0.5, 0.25, 0], [1.0, 1.0, 0], [0.0, 0.0, 0]])
    assert_allclose(r.x_minus, foot @ R.T + [1.0, -2.0, 0.5], atol=1e-14, rtol=0)
    assert_allclose(r.weights, [[0.625, 0.25, 0.125], [0.0, 0.5, 0.5], [1.0, 0.0, 0.0]],
                    atol=1e-14, rtol=0)
    assert_allclose(r.normal, np.tile(R[:, 2], (3, 1)), atol=1e-14, rtol=0)
    assert_allclose(r.gap, [0.3, -0.2, 0.4], atol=1e-14, rtol=0)
    assert_allclose(r.distance, [0.3, np.sqrt(0.5 + 0.04), np.sqrt(1.25 + 0.16)], atol=1e-14,
                    rtol=0)


def test_projection_on_a_tilted_trapezoid():
    """A planar trapezoid (quad4, not a parallelogram) in a tilted plane: the point found is
    the foot of the perpendicular (1e-13 m), its bilinear weights reproduce it, and the gap is
    the signed distance to the plane."""
    R = _tilted()
    local = np.array([[0.0, 0, 0], [3, 0, 0], [2, 1.5, 0], [0.5, 1.5, 0]])
    S = Surface(local @ R.T, np.array([[0, 1, 2, 3]]), "quad4")
    ql = np.array([[1.2, 0.9, 0.7], [2.3, 0.2, -0.1]])
    r = project_points(ql @ R.T, S)
    assert_allclose(r.x_minus, ql * [1, 1, 0] @ R.T, atol=1e-13, rtol=0)
    assert_allclose(np.einsum("pk,kd->pd", r.weights, S.points), r.x_minus, atol=1e-13, rtol=0)
    assert_allclose(r.gap, ql[:, 2], atol=1e-13, rtol=0)
    assert np.all(np.abs(r.xi) < 1)


def test_projection_on_a_parabolic_facet():
    """A 9-node facet with nodes on z = x² (x, y ∈ [−1, 1]) is that parabolic cylinder exactly;
    the closest point to (x₀, y₀, z₀) has x the real root of 2(x − x₀) + 4x(x² − z₀) = 0 that
    minimises the distance (np.roots), y = y₀ (1e-12 m)."""
    g = np.array([-1.0, 1.0, 0.0])
    i = np.array([0, 1, 1, 0, 2, 1, 2, 0, 2])
    j = np.array([0, 0, 1, 1, 0, 2, 1, 2, 2])
    pts = np.column_stack([g[i], g[j], g[i] ** 2])
    S = Surface(pts, np.arange(9)[None], "quad9")
    q = np.array([[0.3, 0.2, 0.8], [-0.6, -0.4, 0.1], [0.1, 0.7, -0.5]])
    r = project_points(q, S)
    for k, (x0, y0, z0) in enumerate(q):
        roots = np.roots([4.0, 0.0, 2 - 4 * z0, -2 * x0])
        roots = roots[np.abs(roots.imag) < 1e-12].real
        x = roots[np.argmin((roots - x0) ** 2 + (roots ** 2 - z0) ** 2)]
        assert_allclose(r.x_minus[k], [x, y0, x * x], atol=1e-12, rtol=0)
        n = np.array([-2 * x, 0.0, 1.0]) / np.hypot(2 * x, 1.0)
        assert_allclose(r.normal[k], n, atol=1e-12, rtol=0)


def test_projection_on_a_box_and_matching_nodes():
    """Points around a hex box's top (z = 0) face: inside → straight down; beyond the side
    x = 1 → the edge point (1, y, 0); a point inside the block goes to the nearest face.
    Points at S− nodes (matching meshes) get one weight 1, the rest 0 (exact)."""
    m = skfem.MeshHex.init_tensor(np.linspace(0, 1, 4), np.linspace(0, 1, 4),
                                  np.linspace(-0.5, 0, 2))
    S = surface_of_mesh(m)
    q = np.array([[0.2, 0.3, 0.1], [0.5, 0.5, -0.01], [1.5, 0.5, 0.2]])
    r = project_points(q, S)
    assert_allclose(r.x_minus, [[0.2, 0.3, 0], [0.5, 0.5, 0], [1.0, 0.5, 0]], atol=1e-15, rtol=0)
    assert_allclose(r.distance, [0.1, 0.01, np.hypot(0.5, 0.2)], atol=1e-15, rtol=0)
    assert_allclose(r.gap[:2], [0.1, -0.01], atol=1e-15, rtol=0)
    top = S.nodes[np.isclose(S.points[S.nodes, 2], 0.0)]
    r = project_points(S.points[top], S)
    assert np.all(np.sort(r.weights, axis=1)[:, :-1] == 0.0)
    assert np.all(r.weights.max(axis=1) == 1.0)
    hit = np.take_along_axis(r.nodes, r.weights.argmax(axis=1)[:, None], axis=1)[:, 0]
    assert_allclose(S.points[hit], S.points[top], atol=0, rtol=0)


@pytest.mark.parametrize("kind", ["tet4", "hex27"])
def test_closest_facet_search_is_exact(kind):
    """The k-d tree search finds the closest facet: 300 random points within 0.5 m of a
    sphere's surface (MeshTet.init_ball, tri3) or of a box's (quad9), against the minimum over
    all facets (every pair tried); distances to 1e-14 m."""
    from stepcontact.contact.surface3d import _closest_on_facets, closest_facets

    rng = np.random.default_rng(3)
    if kind == "tet4":
        S = surface_of_mesh(skfem.MeshTet.init_ball(2))
        x = rng.normal(size=(300, 3))
        x *= (1 + rng.uniform(-0.5, 0.5, 300) / np.linalg.norm(x, axis=1))[:, None]
    else:
        S = surface_of_mesh(_box("hex27"), "hex27")
        x = rng.uniform(-0.5, 1.0, size=(300, 3)) * [2.0, 3.0, 4.0]
    f, _, X, d = closest_facets(S, x)
    rows = np.repeat(np.arange(len(x)), len(S))
    _, _, d_all = _closest_on_facets(S, x[rows], np.tile(np.arange(len(S)), len(x)))
    assert_allclose(d, d_all.reshape(len(x), -1).min(axis=1), atol=1e-14, rtol=0)
    assert_allclose(np.linalg.norm(x - X, axis=1), d, atol=1e-14, rtol=0)


def test_local_basis_is_orthonormal_and_right_handed():
    """Random normals: B Bᵀ = I and det B = +1 to 1e-14, the last row n; n = +z gives
    t₁ = +x, t₂ = +y exactly; a given axis is followed (its projection); an axis along n is
    an error."""
    rng = np.random.default_rng(7)
    n = rng.normal(size=(200, 3))
    B = local_basis(n)
    assert_allclose(np.einsum("mij,mkj->mik", B, B), np.tile(np.eye(3), (200, 1, 1)),
                    atol=1e-14, rtol=0)
    assert_allclose(np.linalg.det(B), 1.0, atol=1e-14, rtol=0)
    assert_allclose(B[:, 2], n / np.linalg.norm(n, axis=1)[:, None], atol=1e-15, rtol=0)
    assert np.array_equal(local_basis([0.0, 0.0, 1.0])[0], np.eye(3))
    Bx = local_basis(np.tile([0.0, 0.6, 0.8], (2, 1)), axis=[0.0, 1.0, 0.0])
    assert_allclose(Bx[0, 0], [0.0, 0.8, -0.6], atol=1e-15, rtol=0)
    with pytest.raises(ModelError, match="parallel"):
        local_basis([0.0, 0.0, 1.0], axis=[0.0, 0.0, 2.0])


# ---- clipping ---------------------------------------------------------------------------------
def _square(theta, half=1.0, centre=(0.0, 0.0)):
    c = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], float) * half
    R = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
    return c @ R.T + centre


def test_clipping_two_turned_squares():
    """Squares of side 2 with a common centre, one turned by θ ∈ (0, π/2): each side of the
    turned one cuts a corner triangle of legs 1 − tan(θ/2) and (cos θ + sin θ − 1)/cos θ off
    the other, so the overlap is 4 − 2 · legs' product (θ = π/4: the regular octagon
    8 tan(π/8)); to 1e-14 m².  Every vertex of the overlap lies in both squares."""
    th = np.array([0.1, 0.5, np.pi / 4, 1.2, 1.5])
    subj = np.stack([_square(t) for t in th])
    clip = np.tile(_square(0.0), (len(th), 1, 1))
    poly, cnt = clip_polygons(subj, np.full(5, 4), clip, np.full(5, 4))
    leg1 = 1 - np.tan(th / 2)
    leg2 = (np.cos(th) + np.sin(th) - 1) / np.cos(th)
    assert_allclose(polygon_areas(poly, cnt), 4 - 2 * leg1 * leg2, atol=1e-14, rtol=0)
    assert_allclose(polygon_areas(poly[2:3], cnt[2:3]), 8 * np.tan(np.pi / 8), atol=1e-14, rtol=0)
    assert np.all(cnt == 8)
    for p, k, t in zip(poly, cnt, th, strict=True):
        v = p[:k]
        assert np.all(np.abs(v).max(axis=1) <= 1 + 1e-14)
        R = np.array([[np.cos(t), np.sin(t)], [-np.sin(t), np.cos(t)]])
        assert np.all(np.abs(v @ R.T).max(axis=1) <= 1 + 1e-14)


def test_clipping_triangle_containment_and_no_overlap():
    """The unit square clipped by the triangle x + y ≤ 1.5 (corner triangle 0.5²/2 cut off):
    0.875; a square inside a larger one: its own area; squares apart: no polygon (1e-15)."""
    tri = np.array([[0.0, 0], [1.5, 0], [0, 1.5], [0, 0]])
    unit = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1]])
    subj = np.stack([unit, _square(0.3, 0.2), _square(0.0, 0.4, (3.0, 0.0))])
    clip = np.stack([tri, _square(0.0), _square(0.0)])
    poly, cnt = clip_polygons(subj, np.array([4, 4, 4]), clip, np.array([3, 4, 4]))
    assert_allclose(polygon_areas(poly, cnt), [0.875, 0.16, 0.0], atol=1e-15, rtol=0)
    assert cnt[2] == 0


# ---- mortar -----------------------------------------------------------------------------------
def _plane_meshes(plus_el, minus_el, n_plus, n_minus, turn=0.0, trapez=False, shift=(0, 0)):
    """S−: the top (z = 0) of a block under the plane, bigger than S+ (its xy [−0.5, 1.5]²
    turned by ``turn`` about z, shifted); S+: the bottom of a unit block [0, 1]² above it.
    ``trapez`` makes the quadrilaterals trapezoids (x moved by 0.1 x (1 − x) y)."""
    def mesh(el, n, lo, hi, zs):
        m = MESHES[el].init_tensor(np.linspace(lo, hi, n), np.linspace(lo, hi, n + 1), zs)
        p = m.p.copy()
        if trapez:
            p[0] += 0.1 * (p[0] - lo) * (hi - p[0]) * (p[1] - lo) / (hi - lo) ** 2
        return type(m)(p, m.t)

    mm = mesh(minus_el, n_minus, -0.5, 1.5, np.array([-0.4, 0.0]))
    c, s = np.cos(turn), np.sin(turn)
    p = mm.p.copy()
    p[:2] = np.array([[c, -s], [s, c]]) @ (p[:2] - 0.5) + 0.5 + np.asarray(shift)[:, None]
    minus = surface_of_mesh(type(mm)(p, mm.t))  # the whole boundary: its far side must drop
    mp = mesh(plus_el, n_plus, 0.0, 1.0, np.array([0.0, 0.3]))
    plus = surface_of_mesh(mp.with_defaults(), boundary="front")  # z = 0, normal −z
    return plus, minus


def _linear(p):
    return 1.0 + 2.0 * p[:, 0] - 3.0 * p[:, 1] + 0.5 * p[:, 2]


def _check_patch(plus, minus, area, tol=1e-12, std_tol=1e-12):
    mo = mortar(plus, minus)
    assert_allclose(mo.overlap_area, area, rtol=tol)
    assert_allclose([mo.D.sum(), mo.M.sum(), mo.M_dual.sum(), mo.area.sum()], area, rtol=tol)
    assert_allclose(mo.weights.sum(axis=1), 1.0, atol=tol, rtol=0)
    u = _linear(minus.points)
    carried = (mo.weights * u[np.maximum(mo.cols, 0)] * (mo.cols >= 0)).sum(axis=1)
    assert_allclose(carried, _linear(plus.points[mo.nodes]), atol=tol, rtol=0)
    idx = mo.nodes
    std = spsolve(mo.D[idx][:, idx].tocsc(), mo.M[idx] @ u)
    assert_allclose(std, _linear(plus.points[idx]), atol=std_tol, rtol=0)
    return mo


@pytest.mark.parametrize("plus_el, minus_el, n_plus, n_minus", [
    ("tet4", "hex8", 7, 4),    # S+ finer
    ("hex8", "tet4", 3, 9),    # S+ coarser
    ("hex8", "hex8", 5, 7),
    ("tet4", "tet4", 4, 6),
])
def test_mortar_patch_on_non_matching_meshes(plus_el, minus_el, n_plus, n_minus):
    """S+ = [0, 1]² fully covered by S− (turned by 20°, trapezoidal quadrilaterals): Σ D =
    Σ M = overlap area 1 m², rows of weights sum to 1, a linear field carried exactly, by the
    dual weights and by D⁻¹ M (1e-12); normals from S− to S+ (+z) and bases right-handed."""
    plus, minus = _plane_meshes(plus_el, minus_el, n_plus, n_minus, turn=np.radians(20),
                                trapez=True)
    mo = _check_patch(plus, minus, 1.0)
    assert len(mo.nodes) == len(plus.nodes)
    assert_allclose(mo.normal, np.tile([0.0, 0.0, 1.0], (len(mo.nodes), 1)), atol=1e-14, rtol=0)
    assert_allclose(np.linalg.det(mo.basis), 1.0, atol=1e-14, rtol=0)


def test_mortar_partial_overlap():
    """S− (unturned, [−0.5, 1.5]² shifted by (0.83, 0.61)) covers only [0.33, 1] × [0.11, 1] of
    S+: overlap area 0.67 × 0.89 m² (1e-12); the patch condition holds on the CFEs there, which
    are the nodes of the S+ facets reaching into that rectangle: by the dual weights to 1e-12,
    by D⁻¹ M to 1e-10 (D restricted to the overlap is ill-conditioned at the barely covered
    facets' nodes; measured 2e-12)."""
    plus, minus = _plane_meshes("hex8", "tet4", 6, 5, shift=(0.83, 0.61))
    mo = _check_patch(plus, minus, 0.67 * 0.89, std_tol=1e-10)
    far = plus.points[plus.facets].max(axis=1)
    reach = (far[:, 0] > 0.33 + 1e-9) & (far[:, 1] > 0.11 + 1e-9)
    assert np.array_equal(mo.nodes, np.unique(plus.facets[reach]))


def test_mortar_in_a_tilted_plane():
    """The pair of the first case turned rigidly into a tilted plane (plain arrays): the same
    areas and patch condition (1e-12), the normals turned with it."""
    plus, minus = _plane_meshes("tet4", "hex8", 5, 4, turn=0.3)
    R = _tilted()
    plus_r = Surface(plus.points @ R.T, plus.facets, plus.kind)
    minus_r = Surface(minus.points @ R.T, minus.facets, minus.kind)
    mo = _check_patch(plus_r, minus_r, 1.0)
    assert_allclose(mo.normal, np.tile(R[:, 2], (len(mo.nodes), 1)), atol=1e-14, rtol=0)


def test_mortar_on_matching_meshes_ties_node_to_node():
    """Matching hex grids: each S+ node's weights are 1 at the S− node at its place and 0
    elsewhere (1e-14), the areas the tributary areas h_x h_y / 4 · (facets at the node), the
    gaps 0 (1e-15 m)."""
    xs, ys = np.linspace(0, 1, 5), np.linspace(0, 1, 6)
    m = skfem.MeshHex.init_tensor(xs, ys, np.array([-0.4, 0.0])).with_defaults()
    minus = surface_of_mesh(m, boundary="back")  # z = 0, normal +z
    mp = skfem.MeshHex.init_tensor(xs, ys, np.array([0.0, 0.3])).with_defaults()
    plus = surface_of_mesh(mp, boundary="front")
    mo = mortar(plus, minus)
    hit = np.take_along_axis(mo.cols, mo.weights.argmax(axis=1)[:, None], axis=1)[:, 0]
    assert_allclose(minus.points[hit], plus.points[mo.nodes], atol=0, rtol=0)
    assert_allclose(mo.weights.max(axis=1), 1.0, atol=1e-14, rtol=0)
    assert_allclose(np.sort(mo.weights, axis=1)[:, :-1], 0.0, atol=1e-14, rtol=0)
    assert_allclose(mo.area, plus.nodal_areas()[mo.nodes], atol=1e-15, rtol=0)
    assert_allclose(mo.gap, 0.0, atol=1e-15, rtol=0)


def _turned_pair(plus_el: str, minus_el: str):
    """(S+, S−): the "front" face of a 1 m × 1 m block of ``plus_el`` cells (2 × 3 in plan,
    0 ≤ z ≤ 0.3) and the surface of a 2 m × 2 m block of ``minus_el`` cells (3 × 4 in plan,
    −0.4 ≤ z ≤ 0) turned by 20° in plan about (0.5, 0.5): facets that cross each other."""
    def mesh(el, n, lo, hi, zs):
        return MESHES[el].init_tensor(np.linspace(lo, hi, n), np.linspace(lo, hi, n + 1), zs)

    mm = mesh(minus_el, 4, -0.5, 1.5, np.array([-0.4, 0.0]))
    c, s = np.cos(np.radians(20)), np.sin(np.radians(20))
    p = mm.p.copy()
    p[:2] = np.array([[c, -s], [s, c]]) @ (p[:2] - 0.5) + 0.5
    minus = surface_of_mesh(type(mm)(p, mm.t), minus_el)
    plus = surface_of_mesh(mesh(plus_el, 3, 0.0, 1.0, np.array([0.0, 0.3])).with_defaults(),
                           plus_el, boundary="front")
    return plus, minus


@pytest.mark.parametrize("plus_el, minus_el", [("hex27", "tet10"), ("hex27", "hex20"),
                                               ("hex8", "tet10")])
def test_mortar_patch_quadratic(plus_el, minus_el):
    """Quadratic facets (quad9 on S+, tri6 or quad8 on S−), S− turned by 20°: Σ D = Σ M = 1 m²,
    a linear field carried exactly, and the quadratic field x² + xy − y² too where both sides
    hold it (1e-12)."""
    plus, minus = _turned_pair(plus_el, minus_el)
    mo = _check_patch(plus, minus, 1.0)
    if plus_el == "hex27":  # quad9, tri6 and quad8 all hold the full quadratics
        def quad(q):
            return q[:, 0] ** 2 + q[:, 0] * q[:, 1] - q[:, 1] ** 2
        u = quad(minus.points)
        carried = (mo.weights * u[np.maximum(mo.cols, 0)] * (mo.cols >= 0)).sum(axis=1)
        assert_allclose(carried, quad(plus.points[mo.nodes]), atol=1e-12, rtol=0)


@pytest.mark.parametrize("plus_el, minus_el", [("tet10", "hex20"), ("hex20", "tet10"),
                                               ("hex20", "hex20")])
def test_mortar_on_tri6_and_quad8_in_the_transformed_basis(plus_el, minus_el):
    """tri6/quad8 facets on S+ (corners with ∫ φ ≤ 0), S− turned by 20°: in the transformed
    basis every CFE has a positive area, Σ D = 1 m², each end's weights add up to 1, and a
    linear and the quadratic field x² + xy − y² (held by tri6 and quad8 alike) are carried
    exactly to the CFE's own end, the transformed nodal value d̂ = T⁻ᵀ d (hand formula:
    d̂_mid = (d_m − (d_c1 + d_c2)/5) · 5/3; 1e-12)."""
    plus, minus = _turned_pair(plus_el, minus_el)
    mo = mortar(plus, minus)
    assert mo.area.min() > 0
    assert_allclose(mo.area.sum(), 1.0, atol=1e-12, rtol=0)
    assert_allclose(mo.weights.sum(axis=1), 1.0, atol=1e-12, rtol=0)
    assert_allclose(mo.own_weights.sum(axis=1), 1.0, atol=1e-12, rtol=0)
    for field in (lambda q: 2 * q[:, 0] - 3 * q[:, 1] + 0.5,
                  lambda q: q[:, 0] ** 2 + q[:, 0] * q[:, 1] - q[:, 1] ** 2):
        u = field(minus.points)
        carried = (mo.weights * u[np.maximum(mo.cols, 0)] * (mo.cols >= 0)).sum(axis=1)
        v = field(plus.points)
        own = (mo.own_weights * v[np.maximum(mo.own_cols, 0)] * (mo.own_cols >= 0)).sum(axis=1)
        assert_allclose(carried, own, atol=1e-12, rtol=0)


def test_curved_quadratic_sphere_area_converges():
    """MeshTet2.init_ball(n) (tet10, nodes on the unit sphere): the surface area of its tri6
    facets tends to 4π at the rate of the quadratic isoparametric surface, h⁴: the slope of
    log error on log h (np.polyfit, h ∝ 2⁻ⁿ) is 3.5 … 4.5, the finest error below 1e-3
    relative; normals point outward (n · x > 0.9 at the facets' centroids on the finest)."""
    errs, hs = [], []
    for n in (1, 2, 3):
        S = surface_of_mesh(skfem.MeshTet2.init_ball(n))
        assert S.kind == "tri6"
        errs.append(abs(S.areas.sum() - 4 * np.pi) / (4 * np.pi))
        hs.append(2.0 ** -n)
    slope = np.polyfit(np.log(hs), np.log(errs), 1)[0]
    assert 3.5 <= slope <= 4.5, slope
    assert errs[-1] < 1e-3
    assert np.min(np.einsum("ij,ij->i", S.normals, S.centroids)) > 0.9
    S.check_orientation()
