"""Results with a tangential axis (issue 26 §6) and the result file's format version 2.

References, all independent of the result code:

* the layout of the contact unknowns (docs of :mod:`stepcontact.contact.layout`): a vector of
  m CFEs with n_t tangential components is component-major, [t1 (m); t2 (m); n (m)], so
  Q[i, k, j] is entry j·m + k of the forces s recorded at state i and N[i, k] = −s[2m + k];
  the test vectors are written by hand in that order;
* a save → load round trip is exact (the file stores float64; 0 tolerance);
* the state codes of a faceted cone (DESIGN: slip on facet i = 16 + i, at vertex i = 144 + i)
  and their labels, written out by hand;
* a version-1 file: the layout the code of format version 1 wrote (``Q``, ``ut`` on
  (state, cfe), no ``event_Q_t``, no ``tangent`` dimension, int64 codes), made here from the
  current dataset by :func:`v1_dataset` — checked once against a file written by the
  version-1 code (same variables, dimensions and values);
* the dynamic result keeps the CFEs' end nodes, weights and bonds of the static result of the
  same model (the same ``ContactElements``), and each CFE's S+ end interpolated from its
  nodes lies at its stored coordinates (geometry, to 1e-12 m).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from numpy.testing import assert_array_equal

import stepcontact as sc
from stepcontact.contact.layout import ContactLayout
from stepcontact.enums import FACET_SLIP, VERTEX_SLIP, ContactState, Status, Transition
from stepcontact.results.build import build_result, cfe_arrays
from stepcontact.results.events import Event
from stepcontact.results.file import read_dataset, result_to_dataset, save_result
from stepcontact.results.recorder import Recorder
from stepcontact.results.result import load_result

STICK, OPEN = int(ContactState.STICK), int(ContactState.OPEN)


def fake_cfe(m: int) -> SimpleNamespace:
    """The CFE arrays a result keeps, for m CFEs on one interface."""
    s = np.linspace(0.0, 1.0, m)
    return SimpleNamespace(
        names=("joint",), m=m, interface=np.zeros(m, np.int64), local=np.arange(m), s=s,
        x=np.column_stack([s, np.zeros(m)]), normal=np.tile([0.0, 1.0], (m, 1)),
        area=np.full(m, 0.5), friction=np.full(m, 0.6), gap=np.zeros(m),
        kn=np.full(m, np.inf), kt=np.full(m, np.inf), tangent=np.tile([1.0, 0.0], (m, 1)),
        plus_nodes=np.arange(m)[:, None], plus_w=np.ones((m, 1)),
        minus_nodes=-np.ones((m, 1), np.int64), minus_w=np.zeros((m, 1)))


def recorded(layout: ContactLayout, S: np.ndarray, W: np.ndarray, codes: np.ndarray,
             events=()) -> Recorder:
    """A recorder with the states (S, W, codes) on one segment of pattern 'push'."""
    rec = Recorder(layout, 1, 0)
    for i, (s, w, st) in enumerate(zip(S, W, codes, strict=True)):
        rec.append(lam=0.1 * i, segment=0, kind="event" if i else "start", factors=[0.1 * i],
                   s=s, w=w, state=st, residual=0.0, violation=0.0, reactions=np.zeros(0),
                   water=np.zeros(layout.m), pressure=np.zeros(layout.m))
    rec.events.extend(events)
    return rec


def result_of(rec: Recorder, m: int):
    cfe = fake_cfe(m)
    return build_result(rec, cfe=cfe, cfe_data=cfe_arrays(cfe), pattern_names=("push",),
                        segments=[("push", 0.0, 0.2)], status=Status.COMPLETED,
                        message="done", counters={"events": len(rec.events)}, geometry={})


def event(k: int, state: int, Q, N: float, tr: Transition, **kw) -> Event:
    return Event(step=state, state=state, segment=0, pattern="push", lam=0.1 * state, cfe=k,
                 interface="joint", local=k, position=0.5 * k, x=0.5 * k, y=0.0,
                 transition=tr, N=N, Q=Q, **kw)


# --------------------------------------------------------------------------------------------
# 3D: two tangential components
# --------------------------------------------------------------------------------------------
#: m = 2 CFEs, n_t = 2: s = [Q1 of CFE 0, 1; Q2 of CFE 0, 1; p of CFE 0, 1] per state
S3 = np.array([[0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
               [3.0, 1.5, -4.0, 2.0, 10.0, 5.0],
               [6.0, -0.25, 8.0, 0.125, 20.0, 0.0]])
W3 = np.array([[0.0, 0.0, 0.0, 0.0, -1e-3, -2e-3],
               [1e-4, 0.0, -2e-4, 0.0, 0.0, -5e-4],
               [3e-4, 7e-5, 4e-4, -1e-5, 0.0, -1e-3]])
CODES3 = np.array([[OPEN, OPEN], [STICK, FACET_SLIP + 3], [VERTEX_SLIP + 0, OPEN]])


@pytest.fixture
def result3d():
    events = [event(1, 1, 0.0, -5.0, Transition.SLIP, Q_t=(1.5, 2.0)),
              event(0, 2, 0.0, -20.0, Transition.SLIP, Q_t=(6.0, 8.0))]
    return result_of(recorded(ContactLayout(2, 2), S3, W3, CODES3, events), 2)


def test_a_3d_result_has_a_tangential_axis_in_the_layout_order(result3d):
    res = result3d
    assert res.n_t == 2 and res.layout == ContactLayout(2, 2)
    assert res.Q.shape == res.ut.shape == (3, 2, 2) and res.N.shape == res.un.shape == (3, 2)
    # Q[i, k, j] = s_i[j m + k], N = −s_i[2m + k]: the hand-written vectors, exactly
    assert_array_equal(res.Q[1], [[3.0, -4.0], [1.5, 2.0]])
    assert_array_equal(res.Q[2], [[6.0, 8.0], [-0.25, 0.125]])
    assert_array_equal(res.N[1], [-10.0, -5.0])
    assert_array_equal(res.ut[2], [[3e-4, 4e-4], [7e-5, -1e-5]])
    assert_array_equal(res.Q_t, res.Q) and np.shares_memory(res.Q_t, res.Q)
    assert_array_equal(res.tau_t[1], [[6.0, -8.0], [3.0, 4.0]])  # Q / 0.5 m²
    assert_array_equal(res.tau, res.tau_t)
    assert res.state.dtype == np.int16
    assert res.state_labels(1) == ["stick", "slip (facet 3)"]
    assert res.state_labels(2) == ["slip (vertex 0)", "open"]
    assert res.states_of(1) == [ContactState.STICK, FACET_SLIP + 3]
    ext = res.extremes().loc["Q"]  # |Q| largest: 8 N, state 2, CFE 0 component t2 (0·2 + 1)
    assert (ext["absmax"], ext["state"], ext["index"]) == (8.0, 2, 1)
    # the event's vector (Q like result.Q: the components in 3D) and its magnitude (3-4-5
    # and 6-8-10 triangles)
    assert res.events[0].Q_t == res.events[0].Q == (1.5, 2.0) and res.events[0].Q_abs == 2.5
    assert res.events[1].Q_abs == 10.0 and res.events[1].n_t == 2


def test_a_3d_result_round_trips_through_the_result_file(result3d, tmp_path):
    res = result3d
    path = save_result(res, tmp_path / "r3.nc")
    ds = read_dataset(path)
    assert int(ds.attrs["format_version"]) == 2 and int(ds.attrs["tangential_components"]) == 2
    assert ds["Q"].dims == ("state", "cfe", "tangent") and ds.sizes["tangent"] == 2
    assert list(ds["tangent"].values) == ["t1", "t2"]
    assert ds["event_Q_t"].dims == ("event", "tangent")
    assert ds["contact_state"].dtype == np.int16
    flags = ds["contact_state"].attrs
    assert list(flags["flag_values"])[-2:] == [FACET_SLIP + 3, VERTEX_SLIP]
    assert flags["flag_meanings"].split()[-2:] == ["slip_facet_3", "slip_vertex_0"]
    assert "16 + i" in flags["facet_codes"] and "144 + i" in ds.attrs["state_codes"]
    back = load_result(path)
    for key in ("Q", "ut", "N", "un", "state", "lam", "factors"):  # exact: 0 tolerance
        assert_array_equal(getattr(back, key), getattr(res, key), err_msg=key)
        assert getattr(back, key).shape == getattr(res, key).shape, key
    assert back.state.dtype == np.int16 and back.state[1, 1] == FACET_SLIP + 3
    assert back.state_labels(2) == ["slip (vertex 0)", "open"]
    assert back.events == res.events
    assert back.cfe_history()["Q"].dims == ("state", "cfe", "tangent")


# --------------------------------------------------------------------------------------------
# 2D: shapes unchanged, the file in version 2, a version-1 file
# --------------------------------------------------------------------------------------------
S2 = np.array([[0.0, 0.0, 0.0, 0.0], [1.0, -2.0, 4.0, 6.0], [2.4, -3.6, 4.0, 6.0]])
W2 = np.array([[0.0, 0.0, -1e-3, 0.0], [0.0, 0.0, 0.0, 0.0], [5e-4, -1e-4, 0.0, 0.0]])
CODES2 = np.array([[OPEN, STICK], [STICK, STICK],
                   [int(ContactState.SLIP_POS), int(ContactState.SLIP_NEG)]])


@pytest.fixture
def result2d():
    events = [event(0, 1, 1.0, -4.0, Transition.CLOSED),
              event(0, 2, 2.4, -4.0, Transition.SLIP_POS),
              event(1, 2, -3.6, -6.0, Transition.SLIP_NEG)]
    return result_of(recorded(ContactLayout(2), S2, W2, CODES2, events), 2)


def test_2d_shapes_are_unchanged_and_the_axis_is_a_view(result2d, tmp_path):
    res = result2d
    assert res.n_t == 1 and res.Q.shape == res.ut.shape == res.tau.shape == (3, 2)
    assert_array_equal(res.Q[2], [2.4, -3.6]) and assert_array_equal(res.N[2], [-4.0, -6.0])
    assert res.Q_t.shape == res.ut_t.shape == (3, 2, 1) and np.shares_memory(res.Q_t, res.Q)
    assert_array_equal(res.Q_t[..., 0], res.Q)
    assert res.events[1].Q == 2.4 and res.events[1].Q_t == (2.4,)
    assert res.state_labels(2) == ["slip+", "slip-"]
    ds = result_to_dataset(res)
    assert ds["Q"].dims == ("state", "cfe", "tangent") and ds.sizes["tangent"] == 1
    back = load_result(save_result(res, tmp_path / "r2.nc"))
    assert back.Q.shape == back.ut.shape == (3, 2)
    for key in ("Q", "ut", "N", "un", "state"):
        assert_array_equal(getattr(back, key), getattr(res, key), err_msg=key)
    assert back.events == res.events


def v1_dataset(ds):
    """The dataset of a 2D result as format version 1 wrote it: no tangent dimension (Q, ut on
    (state, cfe)), no event_Q_t, int64 state codes with the six 2D flags, no n_t."""
    out = ds.drop_vars(["event_Q_t"]).assign(
        Q=ds["Q"].isel(tangent=0, drop=True), ut=ds["ut"].isel(tangent=0, drop=True))
    out = out.drop_vars("tangent")
    out["event_Q"].attrs["long_name"] = "tangential CFE force at the event"
    st = ds["contact_state"]
    out["contact_state"] = st.astype(np.int64)
    out["contact_state"].attrs = {
        "units": "1", "long_name": st.attrs["long_name"],
        "flag_values": np.arange(6, dtype=np.int64),
        "flag_meanings": "open stick slip_pos slip_neg bonded closed"}
    out.attrs = {k: v for k, v in ds.attrs.items()
                 if k not in ("tangential_components", "state_codes")} | {"format_version": 1}
    return out


def test_a_version_1_file_loads_with_the_arrays_of_before(result2d, tmp_path):
    res = result2d
    path = tmp_path / "v1.nc"
    v1_dataset(result_to_dataset(res)).to_netcdf(path, engine="h5netcdf")
    ds = read_dataset(path)
    assert "tangent" not in ds.dims and ds["Q"].dims == ("state", "cfe")
    assert int(ds.attrs["format_version"]) == 1 and ds["contact_state"].dtype == np.int64
    back = load_result(path)
    assert back.n_t == 1 and back.Q.shape == back.ut.shape == (3, 2)
    for key in ("Q", "ut", "N", "un", "state", "lam", "residual"):  # exact: 0 tolerance
        assert_array_equal(getattr(back, key), getattr(res, key), err_msg=key)
    assert back.state.dtype == np.int64  # as the file stores it
    assert back.events == res.events and back.events[2].Q_t == (-3.6,)


def test_a_file_of_a_newer_version_is_refused(result2d, tmp_path):
    ds = result_to_dataset(result2d)
    ds.attrs["format_version"] = 3
    ds.to_netcdf(tmp_path / "v3.nc", engine="h5netcdf")
    with pytest.raises(ValueError, match="format version 3 is newer"):
        load_result(tmp_path / "v3.nc")


# --------------------------------------------------------------------------------------------
# one result builder: the dynamic result keeps what the static one keeps
# --------------------------------------------------------------------------------------------
def bonded_block():
    """A 1 m × 0.5 m block on a rough floor, its base bonded to it through a stiff layer."""
    conc = sc.Material(E=30e9, nu=0.2, density=2400.0)
    m = sc.Model(bodies=[sc.rectangle("block", (0, 0), (1.0, 0.5), 2, 1, conc)])
    floor = sc.RigidObstacle("floor", [(-1.0, 0.0), (2.0, 0.0)])
    base = sc.Interface("base", plus=m.select("block", y=0.0), minus=floor, friction=0.5,
                        layer=sc.ContactLayer(kn=1e10, kt=1e10),
                        bond=sc.Bond(tensile=1e5, shear=1e5, alpha=0.5))
    return m.add(base, sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
                 sc.Segment("weight", 1.0))


def test_the_dynamic_result_keeps_the_cfe_ends_and_bonds_of_the_static_one(tmp_path):
    model = bonded_block()
    st = sc.solve_static(model)
    dyn = sc.solve_dynamic(model, dt=1e-4, duration=5e-4, mass="lumped", initial=st)
    assert st.status == dyn.status == Status.COMPLETED, (st.message, dyn.message)
    for key in ("plus_nodes", "plus_w", "minus_nodes", "minus_w", "bond", "x", "area"):
        assert key in dyn.cfe, key
        assert_array_equal(dyn.cfe[key], st.cfe[key], err_msg=key)
    assert "cn" in dyn.cfe and "cn" not in st.cfe  # the layers' damping: a dynamic run's
    # the S+ end interpolated from its nodes lies at the CFE's coordinates (geometry)
    pts = np.asarray(dyn.geometry["points"])
    nodes, w = dyn.cfe["plus_nodes"], dyn.cfe["plus_w"]
    xp = np.einsum("kj,kjd->kd", np.where(nodes >= 0, w, 0.0), pts[np.maximum(nodes, 0)])
    assert np.abs(xp - dyn.cfe["x"]).max() <= 1e-12
    assert np.all(dyn.cfe["minus_nodes"] == -1)  # the floor has no nodes
    assert np.all(np.isfinite(dyn.cfe["bond"][:, 0]))  # every base CFE bonded
    back = load_result(save_result(dyn, tmp_path / "dyn.nc"))
    for key in ("plus_nodes", "minus_nodes", "bond"):
        assert_array_equal(back.cfe[key], dyn.cfe[key], err_msg=key)


# --------------------------------------------------------------------------------------------
# figures of a result with faceted-cone states
# --------------------------------------------------------------------------------------------
def test_the_path_figures_count_and_colour_a_faceted_cones_slip(result3d):
    """The state bars of the load path count a faceted cone's slip (facet or vertex) as
    ``slip (faceted)`` — one CFE at states 1 and 2 by the hand-written codes — and the event
    timeline colours its CFE bars so."""
    from matplotlib.colors import to_hex

    from figure_checks import assert_readable
    from stepcontact.post.common import FACETED_SLIP_COLOR
    from stepcontact.post.paths import plot_event_timeline, plot_load_path

    fig = plot_load_path(result3d)
    assert_readable(fig)
    ax_c = fig.axes[1]
    bars = {c.get_label(): [p.get_height() for p in c.patches] for c in ax_c.containers}
    assert bars["slip (faceted)"] == [0, 1, 1] and bars["stick"] == [0, 1, 0]
    assert bars["open"] == [2, 0, 1]
    fig = plot_event_timeline(result3d)
    assert_readable(fig)
    colours = {to_hex(c) for ax in fig.axes for coll in ax.collections
               for c in np.atleast_2d(coll.get_colors())}
    assert to_hex(FACETED_SLIP_COLOR) in colours


def test_a_discrete_3d_result_has_no_joint_plane_for_its_safety(result3d):
    """A 3D joint's safety sums the CFE forces in its plane: a discrete model's CFEs have no
    geometry, and the 2D-only options are refused by name."""
    with pytest.raises(ValueError, match=r"interface_safety\('joint'\).*no 3D geometry"):
        result3d.interface_safety("joint")
    with pytest.raises(ValueError, match=r"design.*2D models"):
        result3d.interface_safety("joint", design=1.0)


def test_an_event_given_its_tangential_force_as_a_vector(result2d):
    """Q given as the vector of components (any dimension): Q_t is it, Q the vector too in
    3D (its magnitude Q_abs, 3-4-5), the number itself in 2D."""
    three = event(0, 1, np.array([-3.0, 4.0]), -10.0, Transition.SLIP)
    assert three.Q_t == three.Q == (-3.0, 4.0) and three.Q_abs == 5.0
    two = event(0, 1, np.array([-2.5]), -10.0, Transition.SLIP_NEG)
    assert two.Q_t == (-2.5,) and two.Q == -2.5 and isinstance(two.Q, float)
