"""Model files of 3D models (issue 28 §4): a box body of tetrahedra or hexahedra, supports on
x, y, z, node sets by a named boundary and by z, nodal and face loads with fz, gravity along −z,
a face pressure and water on a face with the level as the load factor; ``stepcontact validate
/ run / info / export`` on such a file; a field of the other dimension is a one-line error
naming it.

References (hand statics of the file's block, 4 × 3 × 10 m, ρ = 2400 kg/m³, fixed at its
base): the base reactions balance the applied loads — the weight ρ g V, 9 crest nodes × the
nodal force, the pressure p × 3 m × 10 m on the upstream face, the total edge force and the
water γ_w W h² / 2 at the level h — to 1e-9 of the largest (the run's equilibrium residual is
~1e-14).
"""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import meshio
import numpy as np
import pytest
from typer.testing import CliRunner

import stepcontact as sc
from cli_checks import assert_one_line_error
from stepcontact.cli import app
from stepcontact.errors import ModelError
from stepcontact.io.modelfile import load_model
from stepcontact.io.modelfile.build import _build_node_set
from stepcontact.io.modelfile.load import model_from_dict
from stepcontact.io.modelfile.schema import BoxSpec, NodeSetSpec

BLOCK = """\
[model]
name = "block under water"

[materials.concrete]
E = 25e9
nu = 0.2
density = 2400

[[bodies]]
name = "dam"
kind = "box"
corner0 = [0.0, 0.0, 0.0]
corner1 = [4.0, 3.0, 10.0]
nx = 2
ny = 2
nz = 5
element = "ELEMENT"
material = "concrete"

[node_sets.base]
body = "dam"
boundary = "bottom"

[node_sets.upstream]
body = "dam"
boundary = "left"

[node_sets.crest]
body = "dam"
z = 10.0

[[supports]]
nodes = "base"
dofs = "xyz"

[patterns.weight]
loads = [{ type = "gravity" }]

[patterns.push]
loads = [{ type = "nodal", nodes = "crest", fx = 2e3, fz = -1e3 },
         { type = "pressure", nodes = "upstream", normal = 1e4 },
         { type = "edge_force", nodes = "crest", fy = 5e3 }]

[patterns.water]
loads = [{ type = "water", nodes = "upstream" }]

[[program]]
pattern = "weight"
end = 1.0

[[program]]
pattern = "push"
end = 1.0

[[program]]
pattern = "water"
end = 8.0
"""
RHO, G, GAMMA, H = 2400.0, 9.81, 9810.0, 8.0
runner = CliRunner()


def block_file(tmp_path: Path, element: str = "hex8") -> Path:
    path = tmp_path / "block.toml"
    path.write_text(BLOCK.replace("ELEMENT", element))
    return path


def test_node_sets_and_dimension_of_a_3d_file(tmp_path):
    """The sets by named boundary, by z and by a 3D box hold the nodes counted by hand on the
    2 × 2 × 5 hex8 mesh ((2 + 1)(5 + 1) on the face x = 0, 3 × 3 on a z face, one corner)."""
    assert load_model(block_file(tmp_path, "tet10")).body("dam").element == "tet10"
    m = load_model(block_file(tmp_path))
    assert m.dim == 3
    x = m.body("dam").points
    base = m.supports[0].nodes
    assert len(base) == 9 and np.all(x[base.index, 2] == 0.0)
    loads = {p.name: p.loads for p in m.patterns}
    upstream, crest = loads["water"][0].nodes, loads["push"][0].nodes
    assert len(upstream) == 3 * 6 and np.all(x[upstream.index, 0] == 0.0)
    assert len(crest) == 9 and np.all(x[crest.index, 2] == 10.0)
    corner = _build_node_set("corner", NodeSetSpec(
        body="dam", where=BoxSpec(xmax=0.0, ymax=0.0, zmin=10.0)), m.body("dam"))
    assert len(corner) == 1 and np.array_equal(x[corner.index[0]], [0.0, 0.0, 10.0])


@pytest.fixture(scope="module")
def block_result(tmp_path_factory):
    """``stepcontact validate`` and ``run`` of the hex8 block file: the result file."""
    tmp = tmp_path_factory.mktemp("block3d")
    path = block_file(tmp)
    out = runner.invoke(app, ["validate", str(path)])
    assert out.exit_code == 0, out.output
    assert "model OK" in out.output and "warning" not in out.output
    assert "162 DOFs" in out.output  # 54 nodes × 3
    result = tmp / "block.nc"
    out = runner.invoke(app, ["run", str(path), "-o", str(result), "--no-plot"])
    assert out.exit_code == 0, out.output
    return result


def test_3d_file_runs_and_balances_the_hand_statics(block_result):
    res = sc.load_result(block_result)
    assert res.status == sc.Status.COMPLETED
    weight = RHO * G * 4.0 * 3.0 * 10.0
    n_crest = int(np.sum(np.isclose(np.asarray(res.geometry["points"])[:, 2], 10.0)))
    assert n_crest == 9
    push_x = 2e3 * n_crest + 1e4 * 3.0 * 10.0
    water = GAMMA * 3.0 * H ** 2 / 2
    expected = {  # after each segment: base:x, base:y, base:z (N)
        1: (0.0, 0.0, weight),
        2: (-push_x, -5e3, weight + 1e3 * n_crest),
        3: (-push_x - water, -5e3, weight + 1e3 * n_crest),
    }
    labels = list(res.reaction_labels)
    ends = np.flatnonzero(np.asarray(res.kind) == "segment_end")
    assert len(ends) == 3 and res.lam[ends[-1]] == H
    for seg, i in enumerate(ends, start=1):
        got = [res.reactions[i, labels.index(f"base:{c}")] for c in "xyz"]
        assert np.allclose(got, expected[seg], rtol=0, atol=1e-9 * (weight + water)), (seg, got)
    assert res.stresses[int(ends[-1])]["dam"].shape[1] == 6


def test_info_and_export_of_a_3d_run(block_result, tmp_path):
    out = runner.invoke(app, ["info", str(block_result)])
    assert out.exit_code == 0, out.output
    assert "dam (20 hex8)" in out.output and "162" in out.output  # 54 nodes × 3 DOFs
    out = runner.invoke(app, ["export", str(block_result), "--vtu", str(tmp_path / "pv")])
    assert out.exit_code == 0, out.output
    res = sc.load_result(block_result)
    frames = sorted((tmp_path / "pv" / "block").glob("block_*.vtu"))
    assert len(frames) == res.n_states
    mesh = meshio.read(frames[-1])
    assert [c.type for c in mesh.cells] == ["hexahedron"]
    dof = np.asarray(res.geometry["dof_of"])
    np.testing.assert_array_equal(mesh.point_data["displacement"], res.displacement(-1)[dof])
    np.testing.assert_array_equal(mesh.cell_data["sigma_zz"][0],
                                  res.stresses[res.n_states - 1]["dam"][:, 2])


# --------------------------------------------------------------------------------------------
# errors: one line naming the field
# --------------------------------------------------------------------------------------------
def _load(d, key, value):
    d["patterns"]["push"]["loads"][key[0]][key[1]] = value


def _rectangle_too(d):
    d["bodies"].append({"name": "slab", "kind": "rectangle", "corner0": [10, 0],
                        "corner1": [11, 1], "nx": 1, "ny": 1, "material": "concrete"})


ERRORS = {
    "unknown box field": (lambda d: d["bodies"][0].update(nw=2), "bodies[0].nw",
                          "unknown field"),
    "2D element on a box": (lambda d: d["bodies"][0].update(element="quad4"),
                            "bodies[0].element", "'hex8'"),
    "empty box": (lambda d: d["bodies"][0].update(corner1=[4.0, 0.0, 1.0]), "bodies[0]",
                  "corner1 must exceed corner0"),
    "cells": (lambda d: d["bodies"][0].update(nz=0), "bodies[0].nz", "greater than or equal"),
    "unknown dof": (lambda d: d["supports"][0].update(dofs="xyw"), "supports[0].dofs",
                    "unknown degree of freedom 'w'"),
    "rz on a 3D support": (lambda d: d["supports"][0].update(dofs="xyzrz"), "supports[0].dofs",
                           "'rz' is not a degree of freedom of a 3D model"),
    "unknown boundary": (lambda d: d["node_sets"]["base"].update(boundary="botom"),
                         "node_sets.base", "no such boundary"),
    "2D gravity": (lambda d: d["patterns"]["weight"]["loads"][0].update(g=[0.0, -9.81]),
                   "patterns.weight.loads[0].g", "has 2 components, the model is 3D"),
    "4 gravity components": (
        lambda d: d["patterns"]["weight"]["loads"][0].update(g=[0.0, 0.0, -9.81, 0.0]),
        "patterns.weight.loads[0].g", "at most 3 items"),
    "tangential pressure": (lambda d: _load(d, (1, "tangential"), 1e3),
                            "patterns.push.loads[1].tangential", "normal pressure"),
    "moment on a 3D node": (lambda d: _load(d, (0, "mz"), 1e3), "patterns.push.loads[0].mz",
                            "no rotation"),
    "rz displacement": (lambda d: d["patterns"]["push"]["loads"].append(
        {"type": "displacement", "nodes": "crest", "dof": "rz", "value": 0.0}),
        "patterns.push.loads[3].dof", "the model is 3D"),
    "unknown load field": (lambda d: _load(d, (0, "fzz"), 1.0), "patterns.push.loads[0].fzz",
                           "unknown field"),
    "plane option": (lambda d: d["model"].update(plane="stress"), "model.plane",
                     "2D bodies only"),
    "zmin on a 2D body": (
        lambda d: (_rectangle_too(d), d["node_sets"].update(s={"body": "slab",
                                                               "where": {"zmin": 0.0}})),
        "node_sets.s.where.zmin", "body 'slab' is 2D"),
}


@pytest.mark.parametrize("case", list(ERRORS))
def test_3d_errors_name_the_field(case):
    mutate, item, fragment = ERRORS[case]
    d = tomllib.loads(BLOCK.replace("ELEMENT", "hex8"))
    mutate(d)
    with pytest.raises(ModelError) as info:
        model_from_dict(copy.deepcopy(d))
    assert info.value.item == item, str(info.value)
    assert fragment in info.value.problem, info.value.problem
    assert "\n" not in str(info.value)


def test_fz_in_a_2d_model_is_named(tmp_path):
    """In a 2D file the z fields are errors at their path (CLI: one line, exit code 2)."""
    text = BLOCK.replace('kind = "box"', 'kind = "rectangle"').replace(
        "corner0 = [0.0, 0.0, 0.0]", "corner0 = [0.0, 0.0]").replace(
        "corner1 = [4.0, 3.0, 10.0]", "corner1 = [4.0, 10.0]").replace(
        "nz = 5\n", "").replace('element = "ELEMENT"', 'element = "quad4"')
    text = text.replace('boundary = "bottom"', "y = 0.0").replace(
        'boundary = "left"', "x = 0.0").replace("z = 10.0", "y = 10.0").replace(
        'dofs = "xyz"', 'dofs = "xy"').replace("fy = 5e3", "fx = 5e3")
    path = tmp_path / "flat.toml"
    path.write_text(text)
    out = runner.invoke(app, ["validate", str(path)])
    assert_one_line_error(out, "patterns.push.loads[0].fz: the model is 2D: no force along z")


# --------------------------------------------------------------------------------------------
# an extruded body
# --------------------------------------------------------------------------------------------
def extruded(section: dict | None = None, **body) -> dict:
    """The block file with the block as a 4 × 3 m quad8 section swept from z = 0 to 10 m."""
    d = tomllib.loads(BLOCK.replace("ELEMENT", "hex8"))
    d["bodies"][0] = {"name": "dam", "kind": "extrude", "z": [0.0, 10.0], "nz": 5,
                      "material": "concrete",
                      "section": section or {"corner0": [0.0, 0.0], "corner1": [4.0, 3.0],
                                             "nx": 2, "ny": 2, "element": "quad8"}, **body}
    d["node_sets"]["base"] = {"body": "dam", "boundary": "start"}
    d["node_sets"]["upstream"] = {"body": "dam", "x": 0.0}
    return d


def test_extruded_body_of_a_file_weighs_its_volume():
    """quad8 → hex20, its end faces 'start' and 'end'; the base reaction after the weight is
    ρ g V (hand statics, 1e-9 relative)."""
    m = model_from_dict(extruded())
    b = m.body("dam")
    assert b.element == "hex20" and b.boundary_names == ("start", "end") and m.dim == 3
    assert np.all(b.points[m.supports[0].nodes.index, 2] == 0.0)
    res = sc.solve_static(m.replace(program=m.program[:1]))
    z = list(res.reaction_labels).index("base:z")
    weight = RHO * G * 4.0 * 3.0 * 10.0
    assert abs(res.reactions[-1, z] - weight) <= 1e-9 * weight


@pytest.mark.parametrize(("body", "item", "fragment"), [
    ({"z": [1.0, 0.0]}, "bodies[0]", "z1 > z0"),
    ({"nz": 0}, "bodies[0].nz", "greater than or equal to 1"),
])
def test_extrusion_errors_name_the_field(body, item, fragment):
    with pytest.raises(ModelError) as info:
        model_from_dict(extruded(**body))
    assert info.value.item == item and fragment in info.value.problem, str(info.value)


def test_section_errors_name_the_field():
    sec = {"corner0": [0.0, 0.0], "corner1": [4.0, 3.0], "nx": 0, "ny": 2}
    with pytest.raises(ModelError) as info:
        model_from_dict(extruded(sec))
    assert info.value.item == "bodies[0].section.nx"
    with pytest.raises(ModelError) as info:
        model_from_dict(extruded({**sec, "nx": 2, "name": "s"}))
    assert info.value.item == "bodies[0]" and "not in its section" in info.value.problem
