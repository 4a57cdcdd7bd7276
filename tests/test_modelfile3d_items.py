"""The 3D items of a model file (issue 28 §1, §2, §4), with the names and options of the
Python API: space frames (``[[frames]]`` with 3D points, Iy, Iz, J, nu, orientation; supports
on rotations, nodal moments), ``cylinder`` and ``spherical_block`` bodies, rigid planes
(``[[obstacles]] kind = "plane"``), 3D interface options (facets, facet_angle, axis, a
3-vector normal) and the uplift through the CFEs; every wrong field named by its path.

References (closed forms and hand statics):
* a cantilever space frame along x (L = 2 m, 4 elements) fixed at x = 0: a tip force P along
  z deflects the tip by P L³ / (3 E I_z) (I_z about the local z' = x' × y', y' the default
  vertical orientation: the vertical plane), a tip torque T turns it by T L / (G J), G = E /
  (2 (1 + ν)) — Euler–Bernoulli and St Venant are exact at the nodes; to 1e-9 relative;
* a cylinder (N = 16 cells around, r = 0.5 m, H = 2 m) under its weight: the base reaction is
  ρ g V with the polygonal section's volume V = (N/2) r² sin(2π/N) H; to 1e-9 relative;
* a block on a rigid plane (k = 16, no facet_angle) pushed along θ = 0.3 slides at
  f W cos(π/k) / cos(θ − π/16) (the facet normals at (j + ½) 2π/k, π/16 the nearest); to 1e-9;
* a uniform uplift p through the CFEs (the 3D default) of a block resting on a base: the
  joint's normal force is −(W − p A) (A = 1 m², the block's base); to 1e-9 of W.
"""

from __future__ import annotations

import copy
import math
import tomllib

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.errors import ModelError
from stepcontact.io.modelfile.load import model_from_dict

E, NU, RHO, G = 2.1e11, 0.3, 7850.0, 9.81
TOL = 1e-9

FRAME = """
[[frames]]
name = "beam"
start = [0.0, 0.0, 0.0]
end = [2.0, 0.0, 0.0]
n = 4
E = 2.1e11
A = 0.01
Iy = 2e-5
Iz = 8e-5
J = 3e-5
nu = 0.3

[node_sets.root]
body = "beam"
index = [0]

[node_sets.tip]
body = "beam"
index = [4]

[[supports]]
nodes = "root"
dofs = "xyzrxryrz"

[patterns.tip]
loads = [{ type = "nodal", nodes = "tip", fz = -1e3, mx = 500.0 }]

[[program]]
pattern = "tip"
end = 1.0
"""


def test_space_frame_cantilever_tip_deflection_and_twist():
    """u_z = −P L³/(3 E I_z), φ_x = T L/(G J) at the tip (1e-9 relative)."""
    m = model_from_dict(tomllib.loads(FRAME))
    beam = m.body("beam")
    assert m.dim == 3 and beam.dof_names == ("x", "y", "z", "rx", "ry", "rz")
    assert np.allclose(beam.local_axes()[0], [[1, 0, 0], [0, 0, 1], [0, -1, 0]])
    res = sc.solve_static(m)
    assert res.status == sc.Status.COMPLETED, res.message
    dof = m.node_offsets["beam"] + 4
    u = res.displacement(-1)
    sysm = sc.assemble(m)
    uz, rx = u[sysm.dofs.of[dof, 2]], u[sysm.dofs.of[dof, 3]]
    L, P, T = 2.0, 1e3, 500.0
    assert uz == pytest.approx(-P * L ** 3 / (3 * E * 8e-5), rel=TOL)
    assert rx == pytest.approx(T * L / (E / (2 * (1 + NU)) * 3e-5), rel=TOL)
    np.testing.assert_allclose(res.load_resultant("tip"),
                               [0, 0, -P, T, P * L, 0], rtol=0, atol=1e-12 * P * L)


@pytest.mark.parametrize(("change", "item", "fragment"), [
    ({"J": None}, "frames[0].J", "is needed"),
    ({"nu": None}, "frames[0].G", "give the shear modulus G"),
    ({"G": 8e10}, "frames[0].G", "not both"),
    ({"orientation": [1.0, 0.0, 0.0]}, "frames[0]", "lies along its orientation vector"),
    ({"end": [2.0, 0.0]}, "frames[0]", "give both as (x, y) or both as (x, y, z)"),
])
def test_space_frame_errors_name_the_field(change, item, fragment):
    d = tomllib.loads(FRAME)
    for key, value in change.items():
        if value is None:
            d["frames"][0].pop(key)
        else:
            d["frames"][0][key] = value
    with pytest.raises(ModelError) as info:
        model_from_dict(d)
    assert info.value.item == item and fragment in info.value.problem, str(info.value)


def test_rotations_of_frames_and_continua_are_told_apart():
    """A moment on a space frame's node is a load; on a 3D body's node an error naming it."""
    d = tomllib.loads(FRAME)
    d["patterns"]["tip"]["loads"][0]["my"] = 1.0
    model_from_dict(copy.deepcopy(d))  # a space frame turns about y
    d["bodies"] = [{"name": "pier", "kind": "box", "corner0": [-1, -1, -1], "corner1": [0, 1, 1],
                    "nx": 1, "ny": 1, "nz": 1, "material": {"E": 3e10, "nu": 0.2}}]
    d["node_sets"]["face"] = {"body": "pier", "boundary": "left"}
    d["patterns"]["tip"]["loads"].append({"type": "nodal", "nodes": "face", "mz": 1.0})
    d["supports"].append({"nodes": "face", "dofs": "xyzrx"})
    with pytest.raises(ModelError) as info:
        model_from_dict(d)
    items = [p for p, _ in info.value.errors]
    assert items == ["supports[1].dofs", "patterns.tip.loads[1].mz"], items
    assert "'rx' is not a degree of freedom of a 3D model's body nodes" in str(info.value)


BLOCK_ON_PLANE = """
[materials.concrete]
E = 30e9
nu = 0.2
density = 2400

[[bodies]]
name = "block"
kind = "box"
corner0 = [0.0, 0.0, 0.0]
corner1 = [1.0, 1.0, 0.5]
nx = 2
ny = 2
nz = 1
material = "concrete"

[node_sets.bottom]
body = "block"
boundary = "bottom"

[node_sets.top]
body = "block"
boundary = "top"

[[obstacles]]
name = "ground"
kind = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 2.0]

[[interfaces]]
name = "joint"
plus = "bottom"
obstacle = "ground"
friction = 0.5
facets = 16
axis = [1.0, 0.0, 0.0]

[patterns.weight]
loads = [{ type = "gravity" }]

[patterns.push]
loads = [{ type = "edge_force", nodes = "top", fx = 0.955336489125606, fy = 0.29552020666133955 }]

[[program]]
pattern = "weight"
end = 1.0

[[program]]
pattern = "push"
end = 1e5
"""
W = 2400.0 * G * 0.5


def test_block_on_a_rigid_plane_slides_at_the_polygon_limit():
    m = model_from_dict(tomllib.loads(BLOCK_ON_PLANE))
    itf = m.interfaces[0]
    assert isinstance(itf.minus, sc.RigidPlane) and itf.facets == 16 and itf.axis == (1, 0, 0)
    res = sc.solve_static(m)
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    k, theta = 16, 0.3
    assert res.lam[-1] == pytest.approx(
        0.5 * W * math.cos(math.pi / k) / math.cos(theta - math.pi / k), rel=TOL)


def test_uplift_through_the_cfes_is_the_3d_default():
    """A block on a base, weight then a uniform uplift of 1 kPa: ΣN = −(W − p·1 m²)."""
    d = tomllib.loads(BLOCK_ON_PLANE)
    d["obstacles"] = []
    d["bodies"].append({"name": "base", "kind": "box", "corner0": [-0.5, -0.5, -0.5],
                        "corner1": [1.5, 1.5, 0.0], "nx": 3, "ny": 3, "nz": 1,
                        "material": "concrete"})
    d["node_sets"] |= {"base_top": {"body": "base", "boundary": "top"},
                       "bed": {"body": "base", "boundary": "bottom"}}
    d["supports"] = [{"nodes": "bed", "dofs": "xyz"}]
    itf = d["interfaces"][0]
    itf.pop("obstacle")
    itf |= {"minus": "base_top", "cfe": "mortar"}
    d["patterns"] = {"weight": {"loads": [{"type": "gravity", "bodies": ["block"]}]},
                     "water": {"loads": [{"type": "uplift", "interface": "joint",
                                          "pressure": 1e3}]}}
    d["program"] = [{"pattern": "weight", "end": 1.0}, {"pattern": "water", "end": 1.0}]
    m = model_from_dict(copy.deepcopy(d))
    assert m.patterns[1].loads[0].through == "cfes"
    res = sc.solve_static(m)
    assert res.status == sc.Status.COMPLETED, res.message
    assert abs(np.sum(res.N[-1]) + (W - 1e3)) <= TOL * W
    d["patterns"]["water"]["loads"][0]["through"] = "faces"
    with pytest.raises(ModelError) as info:
        model_from_dict(d)
    assert info.value.item == "patterns.water.loads[0].through", str(info.value)
    assert "acts through its CFEs" in info.value.problem


def test_cylinder_weighs_its_polygonal_volume():
    text = """
    [[bodies]]
    name = "pier"
    kind = "cylinder"
    centre = [0.0, 0.0, 0.0]
    radius = 0.5
    height = 2.0
    n = [16, 1, 2]
    material = { E = 30e9, nu = 0.2, density = 2400 }

    [node_sets.base]
    body = "pier"
    boundary = "bottom"

    [[supports]]
    nodes = "base"
    dofs = "xyz"

    [patterns.weight]
    loads = [{ type = "gravity" }]

    [[program]]
    pattern = "weight"
    end = 1.0
    """
    m = model_from_dict(tomllib.loads(text))
    assert m.body("pier").boundary_names == ("bottom", "top", "side")
    res = sc.solve_static(m)
    V = 16 / 2 * 0.5 ** 2 * math.sin(2 * math.pi / 16) * 2.0
    z = list(res.reaction_labels).index("base:z")
    assert res.reactions[-1, z] == pytest.approx(2400 * G * V, rel=TOL)


def test_spherical_block_touches_the_plane_at_the_origin():
    """The tip of the docstring's example: 27 nodes, the lowest at the origin, the bottom
    nodes on the sphere z = R − √(R² − x² − y²) (1e-15 m)."""
    d = {"bodies": [{"name": "tip", "kind": "spherical_block", "radius": 0.1,
                     "xs": [0, 0.02, 0.05], "ys": [0, 0.02, 0.05], "top": 0.05, "layers": 2,
                     "material": {"E": 210e9, "nu": 0.3}}],
         "node_sets": {"top": {"body": "tip", "boundary": "top"}},
         "supports": [{"nodes": "top", "dofs": "xyz"}],
         "patterns": {"p": {"loads": [{"type": "edge_force", "nodes": "top", "fz": 1.0}]}},
         "program": [{"pattern": "p", "end": 1.0}]}
    b = model_from_dict(d).body("tip")
    assert b.n_nodes == 27 and np.array_equal(b.points[np.argmin(b.points[:, 2])], [0, 0, 0])
    x, y, z = b.points[b.points[:, 2] < 0.01].T
    assert np.abs(z - (0.1 - np.sqrt(0.01 - x * x - y * y))).max() <= 1e-15


def _plane_model(**changes) -> dict:
    d = tomllib.loads(BLOCK_ON_PLANE)
    for path, value in changes.items():
        table, key = path.split(".")
        target = d[table][0] if isinstance(d[table], list) else d[table]
        if value is None:
            target.pop(key)
        else:
            target[key] = value
    return d


@pytest.mark.parametrize(("changes", "item", "fragment"), [
    ({"interfaces.facets": 2}, "interfaces[0].facets", "greater than or equal to 3"),
    ({"interfaces.facets": 200}, "interfaces[0].facets", "less than or equal to 128"),
    ({"interfaces.axis": [0.0, 0.0, 0.0]}, "interfaces[0].axis", "zero vector"),
    ({"interfaces.normal": [0.0, 1.0]}, "interfaces[0].normal", "has 2 components"),
    ({"interfaces.facet_angle": "pi"}, "interfaces[0].facet_angle", "valid number"),
    ({"obstacles.normal": [0.0, 0.0, 0.0]}, "obstacles[0].normal", "zero vector"),
    ({"obstacles.kind": "line", "obstacles.point": None, "obstacles.normal": None,
      "obstacles.points": [[0, 0], [1, 0]]}, "obstacles[0].kind", "a 3D body meets a rigid "
                                                                  "plane"),
    ({"obstacles.kind": "disc"}, "obstacles[0]", "kind must be 'line'"),
    ({"bodies.kind": "cylinder", "bodies.corner0": None, "bodies.corner1": None,
      "bodies.nx": None, "bodies.ny": None, "bodies.nz": None, "bodies.centre": [0, 0, 0],
      "bodies.radius": 1.0, "bodies.height": 1.0, "bodies.n": [10, 1, 1]}, "bodies[0].n",
     "multiple of 4"),
])
def test_3d_interface_obstacle_and_body_errors_name_the_field(changes, item, fragment):
    with pytest.raises(ModelError) as info:
        model_from_dict(_plane_model(**changes))
    assert item in [p for p, _ in info.value.errors], str(info.value)
    assert fragment in str(info.value), str(info.value)


def test_3d_options_in_a_2d_file_are_named():
    d = {"materials": {"c": {"E": 3e10, "nu": 0.2}},
         "bodies": [{"name": "a", "corner0": [0, 0], "corner1": [1, 1], "nx": 1, "ny": 1,
                     "material": "c"}],
         "node_sets": {"bottom": {"body": "a", "y": 0.0}},
         "obstacles": [{"name": "g", "kind": "plane", "point": [0, 0, 0]}],
         "interfaces": [{"name": "j", "plus": "bottom", "obstacle": "g", "facets": 8,
                         "axis": [1, 0, 0]}],
         "patterns": {"p": {"loads": [{"type": "nodal", "nodes": "bottom", "fy": -1.0}]}},
         "program": [{"pattern": "p", "end": 1.0}]}
    with pytest.raises(ModelError) as info:
        model_from_dict(d)
    items = [p for p, _ in info.value.errors]
    assert items == ["obstacles[0].kind", "interfaces[0].facets", "interfaces[0].axis"], items


def test_water_at_a_fixed_level_on_a_3d_face():
    """The block of test_modelfile3d (4 × 3 × 10 m, fixed at its base) under water at a fixed
    level h = 6 m on its face x = 0: the base reaction along x is −γ_w W h²/2 (W = 3 m, hand
    statics, 1e-9 relative)."""
    d = {"materials": {"c": {"E": 25e9, "nu": 0.2}},
         "bodies": [{"name": "dam", "kind": "box", "corner0": [0, 0, 0], "corner1": [4, 3, 10],
                     "nx": 2, "ny": 2, "nz": 5, "material": "c"}],
         "node_sets": {"base": {"body": "dam", "boundary": "bottom"},
                       "upstream": {"body": "dam", "x": 0.0}},
         "supports": [{"nodes": "base", "dofs": "xyz"}],
         "patterns": {"water": {"loads": [{"type": "water", "nodes": "upstream",
                                           "level": 6.0}]}},
         "program": [{"pattern": "water", "end": 1.0}]}
    res = sc.solve_static(model_from_dict(d))
    x = list(res.reaction_labels).index("base:x")
    assert res.reactions[-1, x] == pytest.approx(-9810.0 * 3.0 * 6.0 ** 2 / 2, rel=TOL)


@pytest.mark.parametrize(("load", "item"), [
    ({"type": "obstacle_motion", "obstacle": "ground", "dx": 1e-3}, "patterns.push.loads[1]"),
])
def test_what_a_3d_model_refuses_is_named_by_its_path(load, item):
    """The model's own refusals (not available in 3D) reported at the file's field path."""
    d = tomllib.loads(BLOCK_ON_PLANE)
    d["patterns"]["push"]["loads"].append(load)
    with pytest.raises(ModelError) as info:
        model_from_dict(d)
    assert info.value.item == item and "3D" in info.value.problem, str(info.value)


def test_crack_water_in_a_3d_file_takes_its_entry_as_a_polyline():
    """A 3D joint's crack water from the file: the entry as an (x, y, z) polyline reaches the
    model as its 3D entry line (the wet-region rule is tests/test_crack3d.py's)."""
    d = tomllib.loads(BLOCK_ON_PLANE)
    line = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    d["patterns"]["push"]["loads"].append({"type": "crack_water", "interface": "joint",
                                           "level": 1.0, "entry": line})
    model = model_from_dict(d)
    cw = [ld for p in model.patterns for ld in p.loads if isinstance(ld, sc.CrackWater)]
    assert len(cw) == 1 and cw[0].entry_dim == 3
    assert [ln.tolist() for ln in cw[0].entry_lines] == [line]
