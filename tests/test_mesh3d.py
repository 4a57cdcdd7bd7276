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
