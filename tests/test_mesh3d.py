"""3D meshes (issue 28 §1): the cylinder generator and Gmsh 3D input (physical volumes as
bodies, physical surfaces as node sets).

References: the volume of a prism on an N-gon inscribed in a circle of radius r,
(N/2) r² sin(2π/N) H (exact for straight-edged elements: 1e-12 relative); a uniaxial stress
state, a linear displacement field that every element reproduces to round-off (1e-10 of the
largest displacement); face areas of a box.
"""

from __future__ import annotations

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.fem.continuum import body_force

E, NU, RHO, G = 2.0e9, 0.3, 2500.0, 9.81


@pytest.mark.parametrize("element", ["hex8", "tet4", "hex20", "tet10", "hex27"])
def test_cylinder_weighs_its_polygonal_volume_at_its_axis(element):
    """Weight of a cylinder (r = 0.5, H = 2, N = 16 around) = ρ g (N/2) r² sin(2π/N) H on the
    axis (the resultant of its consistent nodal forces, force and moment, to 1e-12); the
    named faces cover the boundary exactly (a face inside the mesh or a non-matching one
    would be extra) and the side's nodes lie on the circle (1e-12 r)."""
    r, H, N, c0 = 0.5, 2.0, 16, np.array([1.0, 2.0, 3.0])
    cyl = sc.cylinder("c", tuple(c0), r, H, (N, 2, 3), sc.Material(E, NU, RHO), element)
    f = body_force(cyl, (0.0, 0.0, -G), 1.0).reshape(-1, 3)  # node-major: ux, uy, uz
    got = np.r_[f.sum(axis=0), np.cross(cyl.points, f).sum(axis=0)]
    W = RHO * G * N / 2 * r**2 * np.sin(2 * np.pi / N) * H
    force = np.array([0.0, 0.0, -W])
    np.testing.assert_allclose(got[:3], force, rtol=0, atol=1e-12 * W)
    np.testing.assert_allclose(got[3:], np.cross(c0 + [0, 0, H / 2], force), rtol=0,
                               atol=1e-12 * W * 4)
    rows = {k: cyl.boundary_rows(k) for k in ("bottom", "top", "side")}
    assert sum(len(v) for v in rows.values()) == len(cyl.boundary)
    assert len(np.unique(np.concatenate(list(rows.values())))) == len(cyl.boundary)
    per = 2 if element.startswith("tet") else 1
    k = N // 4
    assert len(rows["bottom"]) == len(rows["top"]) == per * (k * k + N * 2)
    assert len(rows["side"]) == per * N * 3
    side = cyl.points[np.unique(cyl.boundary[rows["side"], :3])]
    assert np.abs(np.hypot(*(side[:, :2] - c0[:2]).T) - r).max() <= 1e-12 * r
    top = cyl.points[np.unique(cyl.boundary[rows["top"]])]
    assert np.all(top[:, 2] == c0[2] + H)


@pytest.mark.parametrize("element", ["hex8", "tet10"])
def test_cylinder_under_uniform_pressure_is_a_linear_field(element):
    """A pressure p on the top face, the base on rollers (z) and two nodes holding the rigid
    motion: σ_zz = −p everywhere, u_z = −p (z − z₀)/E, u_x = ν p (x − x₀)/E,
    u_y = ν p (y − y₀)/E (a linear field: exact in every element, 1e-10 of the largest)."""
    r, H, p = 0.4, 1.5, 2.0e6
    cyl = sc.cylinder("c", (0, 0, 0), r, H, (8, 1, 2), sc.Material(E, NU), element)
    m = sc.Model(bodies=(cyl,))
    centre = m.select("c", where=lambda x, y, z: (np.hypot(x, y) < 1e-12) & (z == 0),
                      boundary="bottom", name="centre")
    rim = m.select("c", where=lambda x, y, z: (np.abs(x - r) < 1e-12) & (np.abs(y) < 1e-12)
                   & (z == 0), name="rim")
    m = m.add(sc.Support("base", m.select("c", boundary="bottom"), "z"),
              sc.Support("centre", centre, "xy"), sc.Support("rim", rim, "y"),
              sc.LoadPattern("p", [sc.EdgeLoad(m.select("c", boundary="top"), normal=p)]),
              sc.Segment("p", 1.0))
    res = sc.solve_static(m)
    assert res.status == sc.Status.COMPLETED, res.message
    u = res.displacement(-1).reshape(-1, 3)
    x, y, z = cyl.points.T
    exact = np.column_stack([NU * p * x / E, NU * p * y / E, -p * z / E])
    assert np.abs(u - exact).max() <= 1e-10 * p * H / E


@pytest.mark.parametrize("element", ["tri3", "quad4"])
def test_prism_on_a_polygon_weighs_its_volume(element):
    """A prism on an L-shaped polygon (area 3 m², centroid (5/6, 5/6)) meshed by gmsh and
    swept 1.5 m along z (extrude): its weight ρ g × 4.5 m³ at the centroid (the resultant of
    the consistent nodal forces, 1e-12); the end faces are its named boundaries."""
    pytest.importorskip("gmsh")
    L = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
    sec = sc.polygon_region("L", L, sc.Material(E, NU, RHO), element, size=0.5)
    prism = sc.extrude(sec, (0.0, 1.5), 3)
    assert prism.element == {"tri3": "tet4", "quad4": "hex8"}[element]
    f = body_force(prism, (0.0, 0.0, -G), 1.0).reshape(-1, 3)
    W = RHO * G * 3.0 * 1.5
    force = np.array([0.0, 0.0, -W])
    np.testing.assert_allclose(f.sum(axis=0), force, rtol=0, atol=1e-12 * W)
    np.testing.assert_allclose(np.cross(prism.points, f).sum(axis=0),
                               np.cross([5 / 6, 5 / 6, 0.75], force), rtol=0, atol=1e-12 * W * 3)
    assert prism.boundary_names == ("start", "end")
    assert np.all(prism.points[np.unique(prism.boundary[prism.boundary_rows("end")]), 2] == 1.5)


def test_cylinder_arguments_are_checked_by_name():
    mat = sc.Material(E, NU)
    for kwargs, item, text in (
        ({"n": (10, 1, 1)}, "body 'c'.n[0]", "multiple of 4"),
        ({"n": (4, 1, 1)}, "body 'c'.n[0]", ">= 8"),
        ({"n": (8, 0, 1)}, "body 'c'.n[1]", ">= 1"),
        ({"n": (8, 1)}, "body 'c'.n", "three cell counts"),
        ({"radius": -1.0}, "body 'c'.radius", "positive"),
        ({"element": "quad4"}, "body 'c'.element", "unknown element"),
    ):
        args = {"name": "c", "centre": (0, 0, 0), "radius": 1.0, "height": 1.0,
                "n": (8, 1, 1), "material": mat, **kwargs}
        with pytest.raises(sc.ModelError) as info:
            sc.cylinder(**args)
        assert info.value.item == item and text in info.value.problem, info.value


# --------------------------------------------------------------------------------------------
# Gmsh 3D input
# --------------------------------------------------------------------------------------------
BOX_FACES = {"left": (0, 0.0), "right": (0, 2.0), "front": (1, 0.0), "bottom": (2, 0.0)}


def _inside_box(bb, tol=1e-6) -> bool:
    """A bounding box (xmin, ymin, zmin, xmax, ymax, zmax) inside [0, 2] × [0, 1] × [0, 1]."""
    return (min(bb[:3]) >= -tol and bb[3] <= 2 + tol and bb[4] <= 1 + tol
            and bb[5] <= 1 + tol)


def _gmsh_box(path, *, hexa=False, order=1, incomplete=False, size=0.7, inner=False):
    """The box [0, 2] × [0, 1] × [0, 1] meshed by gmsh's Python API into ``path``: physical
    volume 'block', physical surfaces left, right, front, bottom (and, ``inner``, the plane
    x = 1 cutting the box, fragments kept conforming)."""
    gmsh = pytest.importorskip("gmsh")
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("box")
        v = gmsh.model.occ.addBox(0, 0, 0, 2, 1, 1)
        if inner:
            cut = gmsh.model.occ.addRectangle(-1, -1, 0, 4, 3)
            gmsh.model.occ.rotate([(2, cut)], 0, 0, 0, 0, 1, 0, -np.pi / 2)
            gmsh.model.occ.translate([(2, cut)], 1, 0, 0)
            gmsh.model.occ.fragment([(3, v)], [(2, cut)])
        gmsh.model.occ.synchronize()
        vols = [t for _, t in gmsh.model.getEntities(3)]
        gmsh.model.addPhysicalGroup(3, vols, name="block")
        faces = dict(BOX_FACES, **({"cut": (0, 1.0)} if inner else {}))
        for name, (axis, value) in faces.items():
            tags = [t for _, t in gmsh.model.getEntities(2)
                    if abs(gmsh.model.occ.getCenterOfMass(2, t)[axis] - value) < 1e-9
                    and _inside_box(gmsh.model.getBoundingBox(2, t))]
            gmsh.model.addPhysicalGroup(2, tags, name=name)
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        if hexa:  # one hexahedron per metre
            for _, c in gmsh.model.getEntities(1):
                bb = gmsh.model.getBoundingBox(1, c)
                length = max(bb[3] - bb[0], bb[4] - bb[1], bb[5] - bb[2])
                gmsh.model.mesh.setTransfiniteCurve(c, int(round(length)) + 1)
            for d in (2, 3):
                for _, t in gmsh.model.getEntities(d):
                    (gmsh.model.mesh.setTransfiniteSurface if d == 2
                     else gmsh.model.mesh.setTransfiniteVolume)(t)
            gmsh.option.setNumber("Mesh.RecombineAll", 1)
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 1 if incomplete else 0)
        gmsh.model.mesh.generate(3)
        if order == 2:
            gmsh.model.mesh.setOrder(2)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    return path


def _bar_in_tension(mf, element=None):
    """The box of a mesh file pulled by P on 'right', on rollers on left (x), front (y) and
    bottom (z): the linear field of uniaxial tension (module docstring) at every node."""
    bar = mf.body("block", sc.Material(E, NU), element=element)
    m = sc.Model(bodies=(bar,))
    P = 3.0e4
    m = m.add(sc.Support("left", mf.node_set("left"), "x"),
              sc.Support("front", mf.node_set("front"), "y"),
              sc.Support("bottom", m.select("block", boundary="bottom"), "z"),
              sc.LoadPattern("pull", [sc.EdgeForce(mf.node_set("right"), fx=P)]),
              sc.Segment("pull", 1.0))
    res = sc.solve_static(m)
    assert res.status == sc.Status.COMPLETED, res.message
    u = res.displacement(-1).reshape(-1, 3)
    eps = P / E  # the section is 1 m²
    x, y, z = bar.points.T
    exact = np.column_stack([eps * x, -NU * eps * y, -NU * eps * z])
    assert np.abs(u - exact).max() <= 1e-10 * eps * 2.0
    return bar


@pytest.mark.parametrize("hexa, order, incomplete, element, kind", [
    (False, 1, False, None, "tet4"),
    (False, 2, False, None, "tet10"),
    (False, 1, False, "tet10", "tet10"),
    (True, 1, False, None, "hex8"),
    (True, 2, True, None, "hex20"),
    (True, 2, False, None, "hex27"),
])
def test_gmsh_volume_is_a_body_and_its_surfaces_node_sets(tmp_path, hexa, order, incomplete,
                                                          element, kind):
    """A gmsh box (tetrahedra or transfinite hexahedra, order 1 or 2): the physical volume is
    a body of the file's element kind, its physical surfaces are node sets (with their
    mid-edge and centre nodes) and named boundaries; pulled on 'right' it gives the exact
    uniaxial field (1e-10); each named face's nodes lie on its plane, and it has every body
    node of that plane."""
    path = _gmsh_box(tmp_path / "box.msh", hexa=hexa, order=order, incomplete=incomplete,
                     size=0.7)
    mf = sc.read_msh(path)
    assert mf.dim == 3 and mf.volumes == ["block"] and mf.points.shape[1] == 3
    bar = _bar_in_tension(mf, element)
    assert bar.element == kind and bar.dim == 3
    assert set(bar.boundary_names) == set(BOX_FACES)
    for name, (axis, value) in BOX_FACES.items():
        ns = mf.node_set(name)
        on_plane = np.flatnonzero(np.abs(bar.points[:, axis] - value) <= 1e-12)
        np.testing.assert_array_equal(np.sort(ns.index), on_plane)
        rows = bar.boundary_rows(name)
        np.testing.assert_array_equal(np.unique(bar.boundary[rows]), on_plane)


def test_geo_file_with_a_volume_is_meshed_in_3d(tmp_path):
    """A .geo file with a Box and physical groups is meshed in 3D (read_mesh: tetrahedra) and
    gives the uniaxial field (1e-10)."""
    pytest.importorskip("gmsh")
    geo = tmp_path / "box.geo"
    geo.write_text('SetFactory("OpenCASCADE");\nBox(1) = {0, 0, 0, 2, 1, 1};\n'
                   'Physical Volume("block") = {1};\n'
                   'Physical Surface("left") = {1};\nPhysical Surface("right") = {2};\n'
                   'Physical Surface("front") = {3};\nPhysical Surface("bottom") = {5};\n'
                   'Mesh.MeshSizeMax = 0.8;\n', encoding="utf-8")
    from stepcontact.io.meshfile import read_mesh

    mf = read_mesh(geo)
    assert mf.dim == 3 and mf.cell_counts.get("tetra", 0) > 0
    _bar_in_tension(mf)


def test_conforming_volumes_share_a_surface_that_names_its_body(tmp_path):
    """Two physical volumes sharing the face x = 1 (fragments of one box): two bodies, the
    shared surface a node set of either (the body must be named), with the same points."""
    path = _gmsh_box(tmp_path / "two.msh", inner=True, size=0.8)
    import gmsh  # noqa: F401 (the file exists: gmsh is installed)

    mf = sc.read_msh(path)
    # one physical volume of two entities: split into two groups by their entity tags
    blocks = mf.blocks["block"]
    assert len(blocks) == 2
    from stepcontact.io.meshfile import PhysicalGroup

    for k, name in enumerate(("a", "b")):
        mf.groups[name] = PhysicalGroup(name, 3, 100 + k)
        mf.blocks[name] = (blocks[k],)
    a, b = mf.body("a", sc.Material(E, NU)), mf.body("b", sc.Material(E, NU))
    with pytest.raises(sc.ModelError) as info:
        mf.node_set("cut")
    assert "lies on bodies 'a', 'b'" in info.value.problem
    na, nb = mf.node_set("cut", body="a"), mf.node_set("cut", body=b)
    pa, pb = a.points[na.index], b.points[nb.index]
    assert len(pa) == len(pb) > 3
    assert np.allclose(pa[:, 0], 1.0, atol=1e-12)
    np.testing.assert_allclose(pa[np.lexsort(pa.T)], pb[np.lexsort(pb.T)], atol=1e-12)


def _meshio_cube(path, cells, groups):
    meshio = pytest.importorskip("meshio")
    pts = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                    [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1], [2, 0, 0], [2, 1, 0],
                    [2, 0, 1], [2, 1, 1]], dtype=float)
    tags = [np.full(len(c), groups[k]) for k, (_, c) in enumerate(cells)]
    field = {"block": np.array([1, 3]), "inner": np.array([2, 2]), "bottom": np.array([3, 2])}
    mesh = meshio.Mesh(pts, [(t, np.asarray(c)) for t, c in cells],
                       cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
                       field_data=field)
    meshio.write(path, mesh, file_format="gmsh22", binary=False)
    return sc.read_msh(path)


CUBE_TETS = [[0, 1, 3, 4], [1, 2, 3, 6], [1, 4, 5, 6], [3, 4, 6, 7], [1, 3, 4, 6]]


def test_what_meshio_mishandles_is_refused_in_one_line(tmp_path):
    """Mixed volume cell types in one physical volume, wedges, a named surface inside the
    body, a curved second-order element: one ModelError each, naming the group."""
    mf = _meshio_cube(tmp_path / "mixed.msh",
                      [("tetra", CUBE_TETS), ("hexahedron", [[1, 8, 9, 2, 5, 10, 11, 6]]),
                       ("triangle", [[1, 3, 4]]), ("triangle", [[0, 1, 2]])], [1, 1, 2, 3])
    with pytest.raises(sc.ModelError) as info:
        mf.body("block", sc.Material(E, NU))
    assert info.value.item == "physical volume 'block'"
    assert "mixes cell types hexahedron, tetra" in info.value.problem
    mf = _meshio_cube(tmp_path / "inner.msh",
                      [("tetra", CUBE_TETS), ("triangle", [[1, 3, 4]]),
                       ("triangle", [[0, 1, 3], [1, 2, 3]])], [1, 2, 3])
    body = mf.body("block", sc.Material(E, NU))
    assert body.boundary_names == ("bottom",) and len(mf.node_set("bottom")) == 4
    with pytest.raises(sc.ModelError) as info:
        mf.node_set("inner")
    assert info.value.item == "physical surface 'inner'"
    assert "is not a face on the boundary of body 'block'" in info.value.problem
    mf = _meshio_cube(tmp_path / "wedge.msh", [("wedge", [[0, 1, 3, 4, 5, 7]])], [1])
    with pytest.raises(sc.ModelError, match="has 'wedge' cells; supported: tetra"):
        mf.body("block", sc.Material(E, NU))


def test_curved_second_order_elements_are_refused(tmp_path):
    """A cylinder meshed at order 2 by gmsh has its boundary mid-edge nodes on the circle,
    off the straight edges: a ModelError naming the volume and the node."""
    gmsh = pytest.importorskip("gmsh")
    path = tmp_path / "cyl.msh"
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        v = gmsh.model.occ.addCylinder(0, 0, 0, 0, 0, 1, 0.5)
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(3, [v], name="pier")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.5)
        gmsh.model.mesh.generate(3)
        gmsh.model.mesh.setOrder(2)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    with pytest.raises(sc.ModelError) as info:
        sc.read_msh(path).body("pier", sc.Material(E, NU))
    assert info.value.item == "physical volume 'pier'"
    assert "curved second-order elements are not supported" in info.value.problem


def test_second_order_mesh_through_scikit_fem_says_where_its_boundaries_went(tmp_path):
    """A tet10 gmsh box: scikit-fem's from_meshio gives a MeshTet2 without the named surfaces
    (its reader takes no quadratic facets); selecting one is a ModelError that says so and
    names read_msh, which keeps them (the same file)."""
    from skfem.io.meshio import from_meshio

    meshio = pytest.importorskip("meshio")
    path = _gmsh_box(tmp_path / "box.msh", order=2, size=1.0)
    body = sc.Body.from_mesh("block", from_meshio(meshio.read(path)), "tet10",
                             sc.Material(E, NU))
    with pytest.raises(sc.ModelError) as info:
        body.boundary_rows("left")
    assert "from_meshio loses its named boundaries" in info.value.problem
    assert "read_msh" in info.value.problem
    assert "left" in sc.read_msh(path).body("block", sc.Material(E, NU)).boundary_names
