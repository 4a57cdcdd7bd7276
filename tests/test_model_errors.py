"""Bad input through the Python API: a clear error naming the item, never a wrong answer.

(The model-file side of the same list is in test_modelfile_cli.py, meshes in test_meshfile.py.)
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from skfem import MeshTri

import stepcontact as sc

MAT = sc.Material(1e9, 0.2, 1000.0)
T = np.array([[0, 1, 2], [1, 3, 2]]).T


def _block_on_base(*, layer=None, load=None, material=MAT) -> sc.Model:
    base = sc.rectangle("base", (0, -1), (2, 0), 2, 1, MAT)
    blk = sc.rectangle("blk", (0, 0), (1, 1), 2, 2, material)
    m = sc.Model(bodies=[base, blk])
    top = m.select("blk", y=1.0)
    return m.add(
        sc.Support("s", m.select("base", y=-1)),
        sc.Interface("j", m.select("blk", y=0), m.select("base", y=0), 0.5, layer=layer),
        sc.LoadPattern("w", [sc.BodyForce(), load or sc.NodalLoad(top, fy=-1.0)]),
        sc.Segment("w", 1.0),
    )


def _raises(fn, item: str, fragment: str) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # scikit-fem on a degenerate mapping
        with pytest.raises(sc.ModelError) as info:
            fn()
    assert info.value.item == item, str(info.value)
    assert fragment in info.value.problem, str(info.value)


def test_degenerate_element():
    p = np.array([[0, 1, 2, 0], [0, 0, 0, 1.0]])
    _raises(lambda: sc.Body.from_mesh("b", MeshTri(p, np.array([[0, 1, 2], [0, 1, 3]]).T),
                                      "tri3", MAT), "body 'b' element 0", "degenerate")


def test_node_in_no_element():
    p = np.array([[0, 1, 0, 1, 5], [0, 0, 1, 1, 5.0]])
    _raises(lambda: sc.Body.from_mesh("b", MeshTri(p, T), "tri3", MAT), "body 'b' node 4",
            "belongs to no element")


def test_nan_coordinate():
    p = np.array([[0, 1, 0, np.nan], [0, 0, 1, 1.0]])
    _raises(lambda: sc.Body.from_mesh("b", MeshTri(p, T), "tri3", MAT), "body 'b' node 3",
            "NaN or inf")


def test_duplicate_node_ids():
    _raises(lambda: sc.NodeSet("b", [0, 3, 3], "edge"), "node set 'edge'",
            "node 3 is listed more than once")
    _raises(lambda: sc.NodeSet("b", [0, -1]), "node set on 'b'", "negative node id -1")


def test_negative_friction_and_stiffness():
    m = _block_on_base()
    itf = m.interfaces[0]
    _raises(lambda: sc.Interface("j", itf.plus, itf.minus, friction=-0.2), "interface 'j'.friction",
            ">= 0")
    _raises(lambda: sc.Spring("s", itf.plus, None, kx=-1.0), "spring 's'.kx", ">= 0")
    _raises(lambda: sc.assemble(_block_on_base(layer=sc.ContactLayer(kn=-1.0, kt=1.0))),
            "interface 'j'.layer.kn", "positive")
    _raises(lambda: sc.assemble(_block_on_base(material=sc.Material(-1.0, 0.2))),
            "body 'blk'.material", "Young's modulus E must be positive")


def test_nan_load():
    bad = sc.NodalLoad(sc.NodeSet("blk", [0]), fx=np.nan)
    _raises(lambda: sc.assemble(_block_on_base(load=bad)), "load pattern 'w' load 1", "nan")


def test_unknown_names():
    m = _block_on_base()
    _raises(lambda: m.select("blok", x=0.0), "body 'blok'", "no such body")
    _raises(lambda: sc.assemble(m).cfe.of("nope"), "interface 'nope'", "no such interface")
    _raises(lambda: sc.solve_static(m.add(sc.Segment("wind", 1.0))), "load pattern 'wind'", "")


def test_free_structure():
    b = sc.rectangle("b", (0, 0), (1, 1), 2, 2, MAT)
    m = sc.Model(bodies=[b]).add(sc.LoadPattern("w", [sc.BodyForce()]), sc.Segment("w", 1.0))
    _raises(lambda: sc.solve_static(m), "model", "no supports and no contact")


def test_program_segments_must_chain():
    m = _block_on_base().add(sc.Segment("w", 2.0, start=0.5))
    _raises(lambda: sc.solve_static(m), "program segment 1 ('w').start",
            "does not chain: pattern 'w' stands at λ = 1, segment starts at 0.5")


def test_empty_selection_explains_itself():
    m = sc.Model(bodies=[sc.rectangle("b", (0, 0), (2, 1), 4, 2, MAT)])
    _raises(lambda: m.select("b", x=1.0, y=0.5), "selection on body 'b'",
            "1 interior node(s) match: select them with boundary=False")
    _raises(lambda: m.select("b", x=5.0), "selection on body 'b'", "spans x 0 … 2")


def test_rectangle_grid_lines():
    _raises(lambda: sc.rectangle("r", (0, 0), (2, 1), 2, 1, MAT, xs=[0, 1, 3]), "body 'r'.xs",
            "must run from 0 to 2")
    _raises(lambda: sc.rectangle("r", (0, 0), (2, 1), 2, 1, MAT, ys=[0, 0.7, 0.5, 1]),
            "body 'r'.ys", "strictly increasing")


def test_mechanism_with_every_cfe_stuck_is_an_error():
    """A block held by one CFE can rotate about it: K₀ is singular although its LU meets no
    exact zero pivot.  The condition estimate catches it and names the body."""
    m = _block_on_base()
    blk = m.body("blk")
    one = sc.NodeSet("blk", [int(np.argmin(np.hypot(*(blk.points - [0.5, 0.0]).T)))])
    itf = m.interfaces[0]
    m2 = sc.Model(bodies=list(m.bodies)).add(
        *m.supports, sc.Interface("j", one, itf.minus, 0.5), *m.patterns, *m.program)
    _raises(lambda: sc.solve_static(m2), "model",
            "mechanism even with every CFE stuck")
    with pytest.raises(sc.ModelError, match="body 'blk' can move"):
        sc.solve_static(m2)


def test_model_without_interfaces_is_plain_linear_analysis():
    b = sc.rectangle("b", (0, 0), (1, 1), 2, 2, MAT)
    m = sc.Model(bodies=[b])
    m = m.add(sc.Support("s", m.select("b", y=0)), sc.LoadPattern("w", [sc.BodyForce()]),
              sc.Segment("w", 1.0), sc.Segment("w", 0.0))
    res = sc.solve_static(m)
    assert res.status == sc.Status.COMPLETED and res.m == 0 and not res.events
    assert res.residual.max() < 1e-12
    u1 = res.displacement(int(np.flatnonzero(res.kind == "segment_end")[0]))
    assert np.abs(u1).max() > 0 and np.allclose(res.displacement(res.n_states - 1), 0.0)
