"""Results per node along the path: displacements (velocities: none in statics) and reactions
of a node, a node set or the node nearest a point; when prescribed displacements act.

References: the stored displacement arrays, a closed-form elastic column (uniform stress under
a total end force), equilibrium of the reactions with the load resultants, and a save → load
round trip.
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from numpy.testing import assert_allclose

import stepcontact as sc
import verification_models as vm

E, NU, RHO = 2.0e9, 0.25, 2000.0
W, H, TH = 0.5, 2.0, 0.3  # column width, height, thickness (m)
P = 1.0e5  # total downward force on its top per unit λ, N


def column(program=None) -> sc.Model:
    """A column [0, W] × [0, H] in plane stress on rollers (y) at its bottom, one corner held in
    x; a total force P down on its top (EdgeForce), its self-weight, and a prescribed lift of
    its right side in pattern 'lift'."""
    body = sc.rectangle("col", (0.0, 0.0), (W, H), 2, 6, sc.Material(E, NU, RHO))
    m = sc.Model(bodies=[body], plane="stress", thickness=TH, name="column")
    top = m.select("col", y=H, name="top")
    m = m.add(
        sc.Support("bed", m.select("col", y=0.0, name="bottom"), "y"),
        sc.Support("pin", m.select("col", x=0.0, y=0.0, name="corner"), "x"),
        sc.LoadPattern("P", [sc.EdgeForce(top, fy=-P)]),
        sc.LoadPattern("weight", [sc.BodyForce()]),
    )
    return m.add(*(program or [sc.Segment("P", 2.0)]))


@pytest.fixture(scope="module")
def col_res():
    return sc.solve_static(column([sc.Segment("P", 1.0), sc.Segment("P", 3.0)]),
                           store_fields="all")


# --------------------------------------------------------------------------------------------
# displacements
# --------------------------------------------------------------------------------------------
def test_node_history_reads_the_displacement_arrays(col_res):
    res = col_res
    U = res.displacements()
    dof_of = np.asarray(res.geometry["dof_of"])
    top = res.node_ids("top")
    assert_allclose(res.node_history("top", "uy"), U[:, dof_of[top, 1]], rtol=0, atol=0)
    k = int(top[-1])
    x, y = res.geometry["points"][k]
    assert_allclose(res.node_history(k, "ux"), U[:, dof_of[k, 0]], rtol=0, atol=0)
    assert_allclose(res.node_history(point=(x + 1e-3, y - 1e-3), quantity="ux"),
                    U[:, dof_of[k, 0]], rtol=0, atol=0)
    assert_allclose(res.node_history((float(x), float(y)), "uy"), U[:, dof_of[k, 1]])
    ns = sc.NodeSet("col", [0, 1])
    assert res.node_history(ns, "uy").shape == (res.n_states, 2)
    assert res.node_history([k], "uy").shape == (res.n_states, 1)
    assert res.node_history(body="col", quantity="ux").shape == (res.n_states, 3 * 7)
    assert_allclose(res.history("uy", "top"), res.node_history("top", "uy"))
    assert_allclose(res.history("N"), res.N)
    assert_allclose(res.history("path"), res.lam)


def test_elastic_column_in_closed_form(col_res):
    """Uniform stress σ_yy = −λP/(W·TH): u_y = −λ P y/(E W TH), u_x = ν λ P x/(E W TH)
    (rollers at the bottom, lateral expansion free), at every state of the path."""
    res = col_res
    lam = res.factors[:, res.pattern_names.index("P")]
    eps = P / (E * W * TH)
    pts = np.asarray(res.geometry["points"])
    every = res.node_ids(body="col")
    assert_allclose(res.node_history(body="col", quantity="uy"),
                    -lam[:, None] * eps * pts[every, 1][None, :], rtol=1e-9, atol=1e-15)
    assert_allclose(res.node_history(body="col", quantity="ux"),
                    NU * lam[:, None] * eps * pts[every, 0][None, :], rtol=1e-9, atol=1e-15)
    top_centre = res.node_history(point=(W / 2, H), quantity="uy")
    assert_allclose(top_centre, -lam * P * H / (E * W * TH), rtol=1e-9, atol=1e-15)


def test_statics_have_no_velocities(col_res):
    assert col_res.velocities() is None
    assert col_res.node_history("top", "vy") is None
    assert col_res.history("vx", point=(0.0, H)) is None


def test_node_lookup_errors(col_res):
    res = col_res
    with pytest.raises(KeyError, match="no node set 'nope'.*'top'"):
        res.node_history("nope", "ux")
    with pytest.raises(ValueError, match="no node near"):
        res.node_history(point=(10.0, 10.0))
    with pytest.raises(ValueError, match="quantity"):
        res.node_history("top", "uz")
    with pytest.raises(ValueError, match="no DOF rz"):
        res.node_history("top", "rz")
    with pytest.raises(IndexError, match="does not exist"):
        res.node_history(10_000, "ux")


def test_frame_rotation_history():
    """rz of a frame node: a cantilever with a tip moment M has φ = M L/(E I) at its tip."""
    L, EI, M = 2.0, 2e11 * 1e-4, 1e3
    fr = sc.Frame.line("beam", (0, 0), (L, 0), 4, E=2e11, A=1e-2, I=1e-4)
    m = sc.Model(bodies=[fr]).add(
        sc.Support("clamp", sc.NodeSet("beam", [0], "root"), "xyrz"),
        sc.LoadPattern("M", [sc.NodalLoad(sc.NodeSet("beam", [4], "tip"), mz=M)]),
        sc.Segment("M", 1.0))
    res = sc.solve_static(m)
    assert_allclose(res.node_history(point=(L, 0.0), quantity="rz"), [0.0, M * L / EI],
                    rtol=1e-9, atol=1e-15)
    assert_allclose(res.reaction_history("clamp", "rz"), [0.0, -M], atol=1e-9)
    assert_allclose(res.reaction_history("root", "rz"), [0.0, -M], atol=1e-9)


# --------------------------------------------------------------------------------------------
# reactions
# --------------------------------------------------------------------------------------------
def test_reactions_balance_the_load_resultants(col_res):
    """Σ reactions + Σ λ_P R_P = 0 at every state: the support resultants, and the reactions
    summed over node sets (the same DOFs, or a set of free nodes: zero)."""
    res = col_res
    lam = res.factors[:, res.pattern_names.index("P")]
    assert_allclose(res.load_resultant("P"), [0.0, -P, -P * W / 2], rtol=1e-12, atol=1e-9)
    assert_allclose(res.reaction_history("bed", "y"), lam * P, rtol=1e-9, atol=1e-9 * P)
    assert_allclose(res.reaction_history("bottom", "y"), lam * P, rtol=1e-9, atol=1e-9 * P)
    assert_allclose(res.reaction_history(res.node_ids(body="col"), "y"), lam * P, rtol=1e-9,
                    atol=1e-9 * P)
    assert_allclose(res.reaction_history("top", "y"), 0.0, atol=1e-9 * P)
    assert_allclose(res.reaction_history("bottom", "x"), 0.0, atol=1e-9 * P)  # only 'pin' in x
    with pytest.raises(KeyError, match="no reaction 'bed' along x"):
        res.reaction_history("bed", "x")  # a support name: its stored resultants only
    assert_allclose(res.history("reaction", "pin", dof="x"), 0.0, atol=1e-9 * P)


def test_reactions_of_a_block_on_a_base():
    """Block on base: the base support carries the weight and the push (equilibrium to 1e-9
    of the loads) at every state, its moment too: Σ(x R_y − y R_x) + M_loads = 0."""
    m = vm.block_on_base(friction=0.5, nx=4, ny=2)
    m = m.add(sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
              sc.LoadPattern("push", [sc.EdgeLoad(m.select("block", x=0.0), normal=1.0)]),
              sc.Segment("weight", 1.0), sc.Segment("push", 2000.0))
    res = sc.solve_static(m)
    c = res.factors
    F = c @ np.asarray(res.load_resultants)  # applied resultant at every state
    scale = np.abs(F).max()
    Rx = res.reaction_history("base_bottom", "x")
    Ry = res.reaction_history("base_bottom", "y")
    assert_allclose(Rx + F[:, 0], 0.0, atol=1e-9 * scale)
    assert_allclose(Ry + F[:, 1], 0.0, atol=1e-9 * scale)
    assert_allclose(res.reaction("base_bottom", "x"), Rx, atol=1e-9 * scale)
    # moment of the reactions: node by node
    ids = res.node_ids(m.supports[0].nodes)
    xy = np.asarray(res.geometry["points"])[ids]
    rx = np.stack([res.reaction_history([k], "x") for k in ids], axis=1)
    ry = np.stack([res.reaction_history([k], "y") for k in ids], axis=1)
    Mz = (ry * xy[:, 0] - rx * xy[:, 1]).sum(axis=1)
    assert_allclose(Mz + F[:, 2], 0.0, atol=1e-9 * scale * 3.0)


# --------------------------------------------------------------------------------------------
# prescribed displacements: when they act
# --------------------------------------------------------------------------------------------
def test_prescribed_displacement_holds_its_dofs_from_the_start():
    """A prescribed displacement fixes its DOFs for the whole program, at λ_P × value: before
    its pattern's segment (λ_P = 0) they are held at zero and carry a reaction, like a
    support; in its segment they move with λ_P."""
    m = column()
    lift = sc.LoadPattern("lift", [sc.PrescribedDisplacement(m.select("col", y=H), "y", 1e-3)])
    m = m.replace(program=()).add(lift, sc.Segment("weight", 1.0), sc.Segment("lift", 1.0))
    res = sc.solve_static(m, store_fields="all")
    assert res.status == sc.Status.COMPLETED, res.message
    seg = res.segment
    uy_top = res.node_history("top", "uy")
    weight = RHO * 9.81 * W * H * TH
    # segment 0 (self-weight only): the top is held at u_y = 0 and carries part of the weight
    assert_allclose(uy_top[seg == 0], 0.0, atol=0)
    R_lift = res.reaction("lift", "y")
    end0 = np.flatnonzero(seg == 0)[-1]
    assert R_lift[end0] > 0.1 * weight
    assert_allclose(R_lift[end0] + res.reaction("bed", "y")[end0], weight, rtol=1e-9)
    # segment 1: u_y of the top follows λ × 1 mm
    lam1 = res.factors[seg == 1, res.pattern_names.index("lift")]
    assert_allclose(uy_top[seg == 1], np.repeat(lam1[:, None] * 1e-3, uy_top.shape[1], 1),
                    rtol=1e-12, atol=1e-18)
    # prescribed displacements are not forces: the pattern's resultant is zero
    assert_allclose(res.load_resultant("lift"), 0.0, atol=0)


# --------------------------------------------------------------------------------------------
# plain data: pickle and the result file
# --------------------------------------------------------------------------------------------
def test_node_results_survive_pickle_and_the_result_file(col_res, tmp_path):
    res = col_res
    ref_u = res.node_history("top", "uy")
    ref_r = res.reaction_history("bottom", "y")
    back = pickle.loads(pickle.dumps(res))
    assert_allclose(back.load_resultants, res.load_resultants, rtol=0, atol=0)
    assert_allclose(back.node_history("top", "uy"), ref_u, rtol=0, atol=0)
    res.save(tmp_path / "col.nc")
    loaded = sc.load_result(tmp_path / "col.nc")
    assert_allclose(loaded.load_resultants, res.load_resultants, rtol=0, atol=0)
    assert set(loaded.node_sets) == {"top", "bottom", "corner"}
    assert_allclose(loaded.node_sets["top"], res.node_sets["top"], rtol=0, atol=0)
    assert_allclose(loaded.node_history("top", "uy"), ref_u, rtol=0, atol=0)  # all stored
    assert_allclose(loaded.reaction_history("bed", "y"), res.reaction("bed", "y"))
    with pytest.raises(KeyError, match="recover_fields"):
        loaded.reaction_history("bottom", "y")
    loaded.recover_fields(column([sc.Segment("P", 1.0), sc.Segment("P", 3.0)]))
    assert_allclose(loaded.reaction_history("bottom", "y"), ref_r, rtol=1e-12, atol=1e-9)
    assert "load resultants" in loaded.summary()


def test_node_history_of_a_loaded_result_needs_its_fields(tmp_path):
    """Fields stored at the segment ends only: the loaded result names recover_fields; with
    the model attached every state is exact again."""
    model = column([sc.Segment("weight", 1.0), sc.Segment("P", 2.0)])
    res = sc.solve_static(model)
    ref = res.node_history("top", "uy")
    res.save(tmp_path / "c.nc")
    loaded = sc.load_result(tmp_path / "c.nc")
    if len(loaded.fields) < loaded.n_states:
        with pytest.raises(KeyError, match="recover_fields"):
            loaded.node_history("top", "uy")
    loaded.recover_fields(model)
    assert_allclose(loaded.node_history("top", "uy"), ref, rtol=1e-12, atol=1e-18)
