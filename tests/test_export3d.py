"""ParaView export of 3D results (issue 28 §4): 3D bodies (VTK tetrahedra and hexahedra, linear
and quadratic) with their displacements and six stress components per state, and 3D CFEs as
points (N, Q1, Q2, |Q|, the tangential force as a vector, the state with its facet or vertex,
the facet count, the true-cone ratio), read back with meshio.

References, independent of the export code:

* the values written are the result's own: displacements (u at each node's DOFs), stresses
  per element and component, λ — compared exactly (the files hold float64);
* von Mises from the six components by its formula, written out here (1e-12 relative);
* the node order of each exported cell is VTK's: every node lies at VTK's parametric point
  of the cell (vtkTetra/vtkQuadraticTetra, vtkHexahedron/vtkQuadraticHexahedron/
  vtkTriQuadraticHexahedron documentation: corners, the mid-edge nodes on the edges (0,1),
  (1,2), … in that order, the face centres x−, x+, y−, y+, z−, z+, the centre) mapped through
  the cell's corners (linear map for a tetrahedron, trilinear for a hexahedron), to 1e-12 m,
  and every cell has a positive volume (VTK's right-handed corner order);
* the CFE quantities by hand: |Q| = hypot(Q1, Q2), Q as a vector Q1 t1 + Q2 t2 with
  t2 = n × t1, the facet i = code − 16 / the vertex i = code − 144 of the state codes
  (stepcontact.enums, written out), the cone ratio |Q| / (f |N|) (1e-15 relative).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path
from types import SimpleNamespace

import meshio
import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import stepcontact as sc
from stepcontact.contact.layout import ContactLayout
from stepcontact.enums import Status
from stepcontact.results.build import build_result, cfe_arrays
from stepcontact.results.recorder import Recorder

MAT = sc.Material(30e9, 0.2, 2400.0)
STRESS_3D = ("sigma_xx", "sigma_yy", "sigma_zz", "sigma_xy", "sigma_yz", "sigma_xz")
VTK_3D = {"tet4": "tetra", "tet10": "tetra10", "hex8": "hexahedron", "hex20": "hexahedron20",
          "hex27": "hexahedron27"}
#: VTK's parametric node coordinates (its documentation, see the module docstring)
HEX = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1),
       (.5, 0, 0), (1, .5, 0), (.5, 1, 0), (0, .5, 0), (.5, 0, 1), (1, .5, 1), (.5, 1, 1),
       (0, .5, 1), (0, 0, .5), (1, 0, .5), (1, 1, .5), (0, 1, .5),
       (0, .5, .5), (1, .5, .5), (.5, 0, .5), (.5, 1, .5), (.5, .5, 0), (.5, .5, 1),
       (.5, .5, .5)]
TET = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (.5, 0, 0), (.5, .5, 0), (0, .5, 0),
       (0, 0, .5), (.5, 0, .5), (0, .5, .5)]


def block(element: str) -> sc.Model:
    """A 2 × 1 × 1.5 m block (2 × 1 × 2 cells) on its base under its weight, then a shear
    push on its top (every stress component non-zero)."""
    b = sc.box("blk", (0, 0, 0), (2.0, 1.0, 1.5), (2, 1, 2), MAT, element)
    m = sc.Model(bodies=(b,))
    top = m.select("blk", boundary="top")
    return m.add(sc.Support("base", m.select("blk", boundary="bottom"), "xyz"),
                 sc.LoadPattern("weight", [sc.BodyForce()]),
                 sc.LoadPattern("push", [sc.EdgeForce(top, fx=2e5, fy=1e5)]),
                 sc.Segment("weight", 1.0), sc.Segment("push", 1.0))


def read_pvd(path: Path) -> list[tuple[float, Path]]:
    coll = ET.parse(path).getroot().find("Collection")
    return [(float(d.get("timestep")), path.parent / d.get("file")) for d in coll]


def assert_vtk_node_order(ctype: str, points: np.ndarray, cells: np.ndarray) -> None:
    """Every node at VTK's parametric point of its cell (1e-12 m), every volume positive."""
    X = points[cells]  # (n_el, k, 3)
    if ctype.startswith("tetra"):
        pc = np.array(TET[:cells.shape[1]], float)
        c = X[:, :4]
        expect = c[:, :1] + np.einsum("vj,ejc->evc", pc, c[:, 1:4] - c[:, :1])
        edges = c[:, 1:4] - c[:, :1]
    else:
        pc = np.array(HEX[:cells.shape[1]], float)
        a, b, g = pc.T
        N = np.stack([(1 - a) * (1 - b) * (1 - g), a * (1 - b) * (1 - g), a * b * (1 - g),
                      (1 - a) * b * (1 - g), (1 - a) * (1 - b) * g, a * (1 - b) * g, a * b * g,
                      (1 - a) * b * g], axis=1)  # trilinear shape functions at VTK's points
        expect = np.einsum("vk,ekc->evc", N, X[:, :8])
        edges = X[:, [1, 3, 4]] - X[:, :1]
    assert np.abs(X - expect).max() <= 1e-12
    assert np.all(np.linalg.det(edges) > 0)


@pytest.mark.parametrize("element", ["tet4", "tet10", "hex8", "hex20", "hex27"])
def test_3d_bodies_as_vtu_series(element, tmp_path):
    res = sc.solve_static(block(element), store_fields="all")
    assert res.status == Status.COMPLETED, res.message
    pvd = sc.export_vtu(res, tmp_path / "pv", name="blk")
    entries = read_pvd(pvd)
    assert len(entries) == res.n_states and not (tmp_path / "pv" / "blk_cfe.pvd").exists()
    pts = np.asarray(res.geometry["points"])
    dof = np.asarray(res.geometry["dof_of"])
    for i, (_, file) in enumerate(entries):
        mesh = meshio.read(file)
        assert_array_equal(mesh.points, pts)
        assert [c.type for c in mesh.cells] == [VTK_3D[element]]
        assert_vtk_node_order(VTK_3D[element], mesh.points, mesh.cells[0].data)
        assert_array_equal(mesh.point_data["displacement"], res.displacement(i)[dof])
        assert mesh.field_data["lam"][0] == res.lam[i] and mesh.field_data["state"][0] == i
        s = np.column_stack([mesh.cell_data[k][0] for k in STRESS_3D])
        assert_array_equal(s, res.stresses[i]["blk"])
        assert_array_equal(mesh.cell_data["stress"][0], res.stresses[i]["blk"])
        sxx, syy, szz, sxy, syz, sxz = s.T
        vm = np.sqrt(((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) / 2
                     + 3 * (sxy ** 2 + syz ** 2 + sxz ** 2))
        assert_allclose(mesh.cell_data["von_mises"][0], vm, rtol=1e-12)
        assert "rotation" not in mesh.point_data
    assert np.all(np.abs(res.stresses[res.n_states - 1]["blk"]).max(axis=0) > 0)


def test_3d_bodies_as_xdmf(tmp_path):
    res = sc.solve_static(block("hex20"), store_fields="all")
    path = sc.export_xdmf(res, tmp_path / "blk.xdmf")
    dof = np.asarray(res.geometry["dof_of"])
    with meshio.xdmf.TimeSeriesReader(path) as reader:
        points, cells = reader.read_points_cells()
        assert_array_equal(points, res.geometry["points"])
        assert [c.type for c in cells] == ["hexahedron20"]
        assert_vtk_node_order("hexahedron20", points, cells[0].data)
        for i in range(reader.num_steps):
            _, pd, cd = reader.read_data(i)
            assert_array_equal(pd["displacement"], res.displacement(i)[dof])
            assert_array_equal(np.column_stack([cd[k][0] for k in STRESS_3D]),
                               res.stresses[i]["blk"])


# --------------------------------------------------------------------------------------------
# 3D CFEs as points
# --------------------------------------------------------------------------------------------
def with_cfes(res: sc.StaticResult, top: np.ndarray) -> sc.StaticResult:
    """The block's result with 3 CFEs of a faceted cone (k = 8) at three of its top nodes
    (their S+ ends), normal +z, t1 = +x, and hand-written forces at its two states (the
    contact unknowns s = [Q1; Q2; p] per state, component-major)."""
    m = 3
    pts = np.asarray(res.geometry["points"])
    cfe = SimpleNamespace(
        names=("top",), m=m, interface=np.zeros(m, np.int64), local=np.arange(m),
        s=np.zeros(m), x=pts[top], normal=np.tile([0.0, 0.0, 1.0], (m, 1)),
        area=np.array([0.5, 0.25, 1.0]), friction=np.full(m, 0.6), gap=np.zeros(m),
        kn=np.full(m, np.inf), kt=np.full(m, np.inf), tangent=np.tile([1.0, 0.0, 0.0], (m, 1)),
        plus_nodes=top[:, None], plus_w=np.ones((m, 1)), minus_nodes=-np.ones((m, 1), int),
        minus_w=np.zeros((m, 1)), n_t=2, facets=8)
    S = np.array([[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 10.0, 0.0, 20.0],
                  [3.0, -1.0, 6.0, 4.0, 0.5, -8.0, 10.0, 0.0, 20.0]])
    codes = np.array([[1, 0, 1], [1, 0, 16 + 5]], dtype=np.int16)
    rec = Recorder(ContactLayout(m, 2), 2, 0)
    for i, (s, st) in enumerate(zip(S, codes, strict=True)):
        rec.append(lam=float(res.lam[i]), segment=int(res.segment[i]), kind=str(res.kind[i]),
                   factors=res.factors[i], s=s, w=np.zeros(3 * m), state=st, residual=0.0,
                   violation=0.0, reactions=np.zeros(0), water=np.zeros(m),
                   pressure=np.zeros(m))
    out = build_result(rec, cfe=cfe, cfe_data=cfe_arrays(cfe), pattern_names=res.pattern_names,
                       segments=res.segments, status=Status.COMPLETED, message="ok",
                       counters={}, geometry=res.geometry)
    out.fields = {i: res.fields[i] for i in range(2)}
    out.stresses = {i: res.stresses[i] for i in range(2)}
    out.state[1, 1] = 144 + 3  # CFE 1 slips at vertex 3 of its polygon
    return out


def test_3d_cfes_as_points(tmp_path):
    model = block("hex8")
    res0 = sc.solve_static(model, store_fields="all")
    top = np.flatnonzero(np.isclose(np.asarray(res0.geometry["points"])[:, 2], 1.5))[:3]
    res = with_cfes(res0, top)
    sc.export_vtu(res, tmp_path / "pv", name="blk")
    entries = read_pvd(tmp_path / "pv" / "blk_cfe.pvd")
    assert len(entries) == 2
    dof = np.asarray(res.geometry["dof_of"])
    xdmf = sc.export_xdmf(res, tmp_path / "blk.xdmf")
    with meshio.xdmf.TimeSeriesReader(xdmf.with_name("blk_cfe.xdmf")) as reader:
        points, cells = reader.read_points_cells()
        from_xdmf = [reader.read_data(i)[1] for i in range(reader.num_steps)]
    assert [c.type for c in cells] == ["vertex"]
    assert_array_equal(points, np.asarray(res.geometry["points"])[top])
    Q1 = [[0.0, 0.0, 0.0], [3.0, -1.0, 6.0]]
    Q2 = [[0.0, 0.0, 0.0], [4.0, 0.5, -8.0]]
    N = [-10.0, 0.0, -20.0]
    for i, (_, file) in enumerate(entries):
        mesh = meshio.read(file)
        assert [c.type for c in mesh.cells] == ["vertex"]
        assert_array_equal(mesh.points, np.asarray(res.geometry["points"])[top])
        for pd in (mesh.point_data, from_xdmf[i]):
            assert_array_equal(pd["N"], N)
            assert_array_equal(pd["Q1"], Q1[i]) and assert_array_equal(pd["Q2"], Q2[i])
            assert_allclose(pd["Q_abs"], np.hypot(Q1[i], Q2[i]), rtol=1e-15)
            # t1 = x, t2 = n × t1 = y: the vector (Q1, Q2, 0)
            assert_array_equal(pd["Q_vector"], np.column_stack([Q1[i], Q2[i], np.zeros(3)]))
            assert_array_equal(pd["state"], [[1, 0, 1], [1, 144 + 3, 16 + 5]][i])
            assert_array_equal(pd["facet"], [[-1, -1, -1], [-1, -1, 5]][i])
            assert_array_equal(pd["vertex"], [[-1, -1, -1], [-1, 3, -1]][i])
            assert_array_equal(pd["facets"], 8)
            with np.errstate(divide="ignore", invalid="ignore"):
                ratio = np.where(np.array(N) < 0, np.hypot(Q1[i], Q2[i]) / (0.6 * 10.0 * np.array(
                    [1.0, 0.0, 2.0])), np.nan)
            assert_allclose(pd["cone_ratio"], ratio, rtol=1e-15)
            assert_array_equal(pd["sigma_n"], np.array(N) / [0.5, 0.25, 1.0])
            assert_array_equal(pd["displacement"], res.displacement(i)[dof][top])
            assert_array_equal(pd["normal"], np.tile([0.0, 0.0, 1.0], (3, 1)))
    notes = (tmp_path / "pv" / "blk_cfe.pvd").read_text()
    assert "faceted Coulomb cone of 8 facets" in notes


def test_staged_3d_cfes_keep_only_those_made(tmp_path):
    """A staged result (stage 0 makes CFEs 0 and 2, stage 1 all three): a VTU frame holds the
    points of the CFEs made at its state, XDMF all of them with ``active`` 1 / 0."""
    res0 = sc.solve_static(block("hex8"), store_fields="all")
    top = np.flatnonzero(np.isclose(np.asarray(res0.geometry["points"])[:, 2], 1.5))[:3]
    res = with_cfes(res0, top)
    res.stage = np.array([0, 1])
    res.stage_names = ("first", "second")
    res.stage_cfes = np.array([[True, False, True], [True, True, True]])
    res.stage_bodies = (("blk",), ("blk",))
    sc.export_vtu(res, tmp_path / "pv", name="blk")
    entries = read_pvd(tmp_path / "pv" / "blk_cfe.pvd")
    first, second = (meshio.read(f) for _, f in entries)
    pts = np.asarray(res.geometry["points"])[top]
    assert_array_equal(first.points, pts[[0, 2]])
    assert_array_equal(first.point_data["N"], [-10.0, -20.0])
    assert_array_equal(first.point_data["active"], 1)
    assert_array_equal(first.point_data["built_stage"], [0, 0])
    assert_array_equal(second.points, pts)
    assert_array_equal(second.point_data["built_stage"], [0, 1, 0])
    xdmf = sc.export_xdmf(res, tmp_path / "blk.xdmf")
    with meshio.xdmf.TimeSeriesReader(xdmf.with_name("blk_cfe.xdmf")) as reader:
        reader.read_points_cells()
        assert_array_equal(reader.read_data(0)[1]["active"], [1, 0, 1])
        assert_array_equal(reader.read_data(1)[1]["active"], [1, 1, 1])
