"""Result files of 3D results (issue 28 §4): 3D bodies (coordinates x, y, z, displacements
u_x, u_y, u_z, the six stress components) and 3D CFEs (two tangential components, |Q|, the
faceted cone's facet count) saved to netCDF and loaded back.

References, independent of the result code:

* a save → load round trip returns every array of the result exactly (the file stores the
  arrays as they are: 0 tolerance), compared field by field by :func:`assert_same_result`;
* the stress components are stored under the right labels: a block whose boundary nodes are
  moved by a constant strain ε (a linear field u = ε x, which every element reproduces) has
  in every element σ = λ tr(ε) I + 2μ ε (Hooke), each of the six components a different
  number; read back by label, each to 1e-9 of max|σ| (the element means of a linear field:
  round-off of the solve);
* |Q| stored in the file is the Euclidean norm of the two components, np.hypot (1e-15
  relative: one rounding);
* a 2D result's file keeps its layout (the axis ``xy``, the DOFs ux, uy, rz, the stress
  components xx, yy, xy, zz): written out by hand.
"""

from __future__ import annotations

import dataclasses
import math
from types import SimpleNamespace

import numpy as np
import pytest
from numpy.testing import assert_array_equal

import stepcontact as sc
from stepcontact.contact.layout import ContactLayout
from stepcontact.enums import FACET_SLIP, VERTEX_SLIP, ContactState, Status, Transition
from stepcontact.results.build import build_result, cfe_arrays
from stepcontact.results.events import Event
from stepcontact.results.file import read_dataset, save_result
from stepcontact.results.recorder import Recorder

E, NU = 30e9, 0.2
#: a constant strain (symmetric; every component different), 1
EPS = np.array([[2.0, 0.7, -0.4], [0.7, -1.1, 0.3], [-0.4, 0.3, 0.9]]) * 1e-4


# --------------------------------------------------------------------------------------------
# an exact comparison of two results
# --------------------------------------------------------------------------------------------
def _same(a, b, what: str) -> None:
    """``a`` and ``b`` equal exactly: arrays (dtype kind and shape too), dicts, lists, tuples,
    dataclasses, numbers (NaN equal to NaN)."""
    if dataclasses.is_dataclass(a):  # events, multipliers: field by field (NaN = NaN)
        assert type(a) is type(b), what
        for f in dataclasses.fields(a):
            _same(getattr(a, f.name), getattr(b, f.name), f"{what}.{f.name}")
    elif isinstance(a, dict):
        assert isinstance(b, dict) and list(a) == list(b), (what, list(a), list(b))
        for k in a:
            _same(a[k], b[k], f"{what}[{k!r}]")
    elif isinstance(a, list | tuple) and not isinstance(a, str):
        assert len(a) == len(b), what
        for j, (x, y) in enumerate(zip(a, b, strict=True)):
            _same(x, y, f"{what}[{j}]")
    elif isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        assert a.shape == b.shape, (what, a.shape, b.shape)
        assert a.dtype.kind == b.dtype.kind or {a.dtype.kind, b.dtype.kind} <= set("iu"), (
            what, a.dtype, b.dtype)
        assert_array_equal(a, b, err_msg=what)
    elif isinstance(a, float) and math.isnan(a):
        assert isinstance(b, float) and math.isnan(b), what
    else:
        assert a == b, (what, a, b)


#: the result's attributes a file keeps (``_recover`` and ``dynamics`` stay in memory)
KEPT = ("pattern_names", "segments", "cfe", "interface_names", "lam", "segment", "factors",
        "kind", "N", "Q", "un", "ut", "state", "residual", "violation", "events",
        "multipliers", "status", "message", "fields", "stresses", "counters", "mechanism",
        "geometry", "reactions", "reaction_labels", "load_resultants", "load_moments", "units",
        "water", "crack_pressure", "nonunique", "stage", "stage_names", "stage_cfes",
        "stage_bodies")


def assert_same_result(a, b) -> None:
    """Every attribute of the result that a file keeps, equal exactly."""
    for key in KEPT:
        _same(getattr(a, key), getattr(b, key), key)


# --------------------------------------------------------------------------------------------
# 3D bodies
# --------------------------------------------------------------------------------------------
def strained_block(element: str) -> sc.Model:
    """A 2 × 1.5 × 1 m block (2 × 2 × 2 cells) whose boundary nodes are moved by u = ε x (one
    prescribed displacement per node and direction), loaded in one segment; gravity in a second
    pattern that is not applied (it enters the load resultants only)."""
    blk = sc.box("blk", (0, 0, 0), (2.0, 1.5, 1.0), (2, 2, 2), sc.Material(E, NU, 2400),
                 element)
    m = sc.Model(bodies=(blk,))
    x = blk.points
    on_boundary = np.flatnonzero(
        np.any(np.isclose(x, 0.0) | np.isclose(x, [2.0, 1.5, 1.0]), axis=1))
    loads = []
    for i in on_boundary:
        nodes = m.select("blk", where=lambda a, b, c, i=i: (a == x[i, 0]) & (b == x[i, 1])
                         & (c == x[i, 2]), name=f"n{i}")
        loads += [sc.PrescribedDisplacement(nodes, d, float(EPS[c] @ x[i]))
                  for c, d in enumerate("xyz")]
    return m.add(sc.LoadPattern("strain", loads), sc.LoadPattern("weight", [sc.BodyForce()]),
                 sc.Segment("strain", 1.0))


@pytest.mark.parametrize("element", ["tet10"])
def test_3d_body_result_round_trips_with_labelled_stresses(element, tmp_path):
    res = sc.solve_static(strained_block(element))
    assert res.status == Status.COMPLETED, res.message
    path = save_result(res, tmp_path / "block.nc")
    ds = read_dataset(path)
    # the six components under their labels: Hooke's law of the constant strain, every element
    lam_, mu = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    sigma = lam_ * np.trace(EPS) * np.eye(3) + 2 * mu * EPS
    assert list(ds["stress_component"].values) == ["xx", "yy", "zz", "xy", "yz", "xz"]
    st = ds["stress__blk"]
    assert st.attrs["units"] == "Pa" and st.sizes["stress_component"] == 6
    scale = np.abs(sigma).max()
    for label, (a, b) in {"xx": (0, 0), "yy": (1, 1), "zz": (2, 2), "xy": (0, 1),
                          "yz": (1, 2), "xz": (0, 2)}.items():
        got = st.sel(stress_component=label).isel(stress_state__blk=-1).values
        assert np.abs(got - sigma[a, b]).max() <= 1e-9 * scale, label
    # the coordinates and DOFs of a 3D model
    assert ds["points"].dims == ("node", "xyz") and list(ds["xyz"].values) == ["x", "y", "z"]
    assert list(ds["node_dof"].values) == ["ux", "uy", "uz"]
    u = ds["u"].values[-1][ds["dof_of"].values]  # (n_nodes, 3): u = ε x at every node
    assert np.abs(u - ds["points"].values @ EPS.T).max() <= 1e-12 * np.abs(EPS).max() * 2.0
    back = sc.load_result(path)
    assert_same_result(res, back)
    assert back.stresses[res.n_states - 1]["blk"].shape[1] == 6


# --------------------------------------------------------------------------------------------
# 3D CFEs
# --------------------------------------------------------------------------------------------
def pushed_point(k: int, theta: float) -> sc.DiscreteModel:
    """A point pressed with 100 N on a rough plane (f = 0.5, k facets), then pushed along θ up
    to 2 f N (springs of 1 kN/m hold it once it slips)."""
    return sc.DiscreteModel(
        K=np.diag([1e3, 1e3, 1e3]), normal_rows=[[0, 0, 1]], tangent_rows=[[1, 0, 0]],
        tangent2_rows=[[0, 1, 0]], friction=0.5, facets=k,
        loads={"press": {"uz": -1.0}, "push": {"ux": math.cos(theta), "uy": math.sin(theta)}},
        dof_names=("ux", "uy", "uz"),
        program=[sc.Segment("press", 100.0), sc.Segment("push", 100.0)])


def test_faceted_result_round_trips_with_its_facets_and_magnitude(tmp_path):
    res = sc.solve_static(pushed_point(8, 0.3))
    assert res.n_t == 2 and np.any(res.state >= FACET_SLIP), res.state
    path = save_result(res, tmp_path / "point.nc")
    ds = read_dataset(path)
    Q = ds["Q"].values
    assert ds["Q"].dims == ("state", "cfe", "tangent") and Q.shape[2] == 2
    np.testing.assert_allclose(ds["Q_abs"].values, np.hypot(Q[..., 0], Q[..., 1]),
                               rtol=1e-15, atol=0)
    assert ds["Q_abs"].attrs["units"] == "N"
    back = sc.load_result(path)
    assert_same_result(res, back)
    assert back.cfe["facets"] == 8


def fake_cfe_3d(m: int) -> SimpleNamespace:
    """m CFEs of one interface in the plane z = 1 with 3D vectors (as a 3D interface has them),
    a faceted cone of 6 facets."""
    x = np.column_stack([np.linspace(0.0, 1.0, m), np.full(m, 0.5), np.ones(m)])
    return SimpleNamespace(
        names=("base",), m=m, interface=np.zeros(m, np.int64), local=np.arange(m),
        s=np.zeros(m), x=x, normal=np.tile([0.0, 0.0, 1.0], (m, 1)), area=np.full(m, 0.25),
        friction=np.full(m, 0.6), gap=np.zeros(m), kn=np.full(m, np.inf),
        kt=np.full(m, np.inf), tangent=np.tile([1.0, 0.0, 0.0], (m, 1)),
        plus_nodes=np.arange(4 * m).reshape(m, 4), plus_w=np.full((m, 4), 0.25),
        minus_nodes=-np.ones((m, 4), np.int64), minus_w=np.zeros((m, 4)), n_t=2, facets=6)


def test_3d_cfe_vectors_round_trip_on_the_xyz_axis(tmp_path):
    """CFEs with 3D coordinates, normals and tangents: stored on the axis ``xyz`` and back
    exactly, with their forces (hand-written, component-major [t1; t2; n] per state)."""
    m = 2
    lay = ContactLayout(m, 2)
    S = np.array([[0.0] * 6, [3.0, 1.5, -4.0, 2.0, 10.0, 5.0]])
    W = np.array([[0.0] * 6, [1e-4, 0.0, -2e-4, 0.0, 0.0, -5e-4]])
    rec = Recorder(lay, 1, 0)
    for i, (s, w, st) in enumerate(zip(S, W, [[int(ContactState.OPEN)] * 2,
                                               [int(ContactState.STICK), VERTEX_SLIP + 2]],
                                       strict=True)):
        rec.append(lam=0.5 * i, segment=0, kind="event" if i else "start", factors=[0.5 * i],
                   s=s, w=w, state=np.array(st), residual=0.0, violation=0.0,
                   reactions=np.zeros(0), water=np.zeros(m), pressure=np.zeros(m))
    rec.events.append(Event(step=1, state=1, segment=0, pattern="push", lam=0.5, cfe=1,
                            interface="base", local=1, position=0.0, x=1.0, y=0.5,
                            transition=Transition.SLIP, N=-5.0, Q=(1.5, 2.0)))
    cfe = fake_cfe_3d(m)
    res = build_result(rec, cfe=cfe, cfe_data=cfe_arrays(cfe), pattern_names=("push",),
                       segments=[("push", 0.0, 0.5)], status=Status.COMPLETED, message="ok",
                       counters={}, geometry={})
    ds = read_dataset(save_result(res, tmp_path / "cfe3d.nc"))
    for key in ("x", "normal", "tangent"):
        assert ds[f"cfe_{key}"].dims == ("cfe", "xyz"), key
    assert_array_equal(ds["Q_abs"].values[1], [5.0, 2.5])  # the 3-4-5 and 1.5-2-2.5 triangles
    back = sc.load_result(tmp_path / "cfe3d.nc")
    assert_same_result(res, back)
    assert back.cfe["facets"] == 6 and back.state_labels(1) == ["stick", "slip (vertex 2)"]


# --------------------------------------------------------------------------------------------
# 2D: the layout as before
# --------------------------------------------------------------------------------------------
def test_2d_file_layout_is_unchanged(tmp_path):
    mat = sc.Material(E, NU, 2400)
    b = sc.rectangle("slab", (0, 0), (2, 1), 2, 1, mat)
    m = sc.Model(bodies=(b,))
    m = m.add(sc.Support("base", m.select("slab", y=0.0), "xy"),
              sc.LoadPattern("weight", [sc.BodyForce()]), sc.Segment("weight", 1.0))
    res = sc.solve_static(m)
    ds = read_dataset(save_result(res, tmp_path / "slab.nc"))
    assert ds["points"].dims == ("node", "xy") and "xyz" not in ds.dims
    assert list(ds["node_dof"].values) == ["ux", "uy", "rz"]
    assert list(ds["stress_component"].values) == ["xx", "yy", "xy", "zz"]
    assert list(ds["resultant_component"].values) == ["Fx", "Fy", "Mz"]
    assert "Q_abs" not in ds and "facets" not in ds.attrs["cfe_extra"]
    assert_same_result(res, sc.load_result(tmp_path / "slab.nc"))
