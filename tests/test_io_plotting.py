"""Result files (save → load round trip, atomic writes) and plots, on a hand-built result."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose, assert_array_equal

from stepcontact.enums import ContactState, Status, Transition
from stepcontact.post.plotting import plot_interfaces, plot_load_path
from stepcontact.results.file import (
    _EVENT_SPEC,
    _MULT_SPEC,
    ResultWriter,
    load_result,
    result_to_dataset,
    save_result,
)
from stepcontact.results.result import Event, Multipliers, StaticResult

OPEN, STICK, SP, SN = (int(c) for c in (ContactState.OPEN, ContactState.STICK,
                                          ContactState.SLIP_POS, ContactState.SLIP_NEG))


def _event(step, state, seg, pattern, lam, k, res_cfe, names, tr, N, Q):
    i = int(res_cfe["interface"][k])
    return Event(
        step=step, state=state, segment=seg, pattern=pattern, lam=lam, cfe=k,
        interface=names[i], local=int(res_cfe["local"][k]), position=float(res_cfe["s"][k]),
        x=float(res_cfe["x"][k, 0]), y=float(res_cfe["x"][k, 1]), transition=tr, N=N, Q=Q,
    )


def make_result(*, events: bool = True, geometry: bool = True) -> StaticResult:
    """Two interfaces of 3 CFEs each; segment 0 'dead' 0 → 1, segment 1 'live' 0 → 0.7."""
    rng = np.random.default_rng(7)
    m = 6
    names = ("base", "joint ä/1")
    s = np.r_[0.0, 0.5, 1.0, 0.0, 0.25, 0.5]
    cfe = {
        "interface": np.array([0, 0, 0, 1, 1, 1]),
        "local": np.array([0, 1, 2, 0, 1, 2]),
        "s": s,
        "x": np.column_stack([s + np.r_[0, 0, 0, 2, 2, 2], np.r_[0, 0, 0, 1, 1, 1.0]]),
        "normal": np.tile([0.0, 1.0], (m, 1)),
        "plus_nodes": np.tile([4, -1, -1], (m, 1)),
        "area": np.r_[0.25, 0.5, 0.25, 0.125, 0.25, 0.125],
        "friction": np.full(m, 0.6),
        "gap": np.zeros(m),
        "kn": np.r_[np.inf, np.inf, np.inf, 1e9, 1e9, 1e9],
        "names": names,  # a non-array entry (kept as it is)
    }
    # states: 0 start, 1 event (seg 0), 2 end seg 0, 3 event (seg 1), 4 end seg 1
    lam = np.r_[0.0, 0.4, 1.0, 0.3, 0.7]
    segment = np.r_[0, 0, 0, 1, 1]
    factors = np.array([[0, 0], [0.4, 0], [1, 0], [1, 0.3], [1, 0.7]], dtype=float)
    kind = np.array(["start", "event", "segment_end", "event", "segment_end"])
    N = -1e5 * np.abs(rng.random((5, m))) * np.r_[0, 1, 1, 1, 1][:, None]
    N[3:, 0] = 0.0
    Q = 0.3 * N * rng.uniform(-1, 1, (5, m))
    Q[3:, 1] = -0.6 * N[3:, 1]
    un = np.where(N == 0, -1e-4 * rng.random((5, m)), 0.0)
    ut = 1e-5 * rng.standard_normal((5, m))
    state = np.full((5, m), STICK, dtype=np.int8)
    state[0] = OPEN
    state[3:, 0] = OPEN
    state[3:, 1] = SP
    state[4, 4] = SN
    ev = []
    if events:
        ev = [
            _event(1, 1, 0, "dead", 0.4, 2, cfe, names, Transition.CLOSED, -1.0e4, 2.0e3),
            _event(1, 1, 0, "dead", 0.4, 3, cfe, names, Transition.CLOSED, -2.5e4, 0.0),
            _event(2, 3, 1, "live", 0.3, 0, cfe, names, Transition.OPENED, 0.0, 0.0),
            _event(2, 3, 1, "live", 0.3, 1, cfe, names, Transition.SLIP_POS, -3e4, 1.8e4),
            _event(3, 4, 1, "live", 0.7, 4, cfe, names, Transition.SLIP_NEG, -1e4, 6e3),
        ]
    geo: dict[str, object] = {}
    if geometry:
        pts = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]], dtype=float)
        geo = {
            "points": pts,
            "dof_of": np.column_stack([np.arange(0, 10, 2), np.arange(1, 10, 2), np.full(5, -1)]),
            "bodies": [
                {"name": "slab/1", "kind": "continuum", "element": "ElementTriP1",
                 "cells": np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])},
            ],
        }
    return StaticResult(
        pattern_names=("dead", "live"),
        segments=[("dead", 0.0, 1.0), ("live", 0.0, 0.7)],
        cfe=cfe,
        interface_names=names,
        lam=lam,
        segment=segment,
        factors=factors,
        kind=kind,
        N=N,
        Q=Q,
        un=un,
        ut=ut,
        state=state,
        residual=np.r_[0.0, 1e-15, 3e-16, 2.2e-16, 1e-14],
        violation=np.r_[0.0, 0.0, 1e-17, 0.0, 5e-16],
        events=ev,
        multipliers=[
            Multipliers(0, "dead"),
            Multipliers(1, "live", first_slip=0.3, first_opening=0.3 + 1e-17),
        ],
        status=Status.COMPLETED,
        message="the whole load program was applied — λ = 0.7",
        fields={0: np.zeros(10), 4: rng.standard_normal(10) * 1e-3},
        stresses={2: {"slab/1": rng.standard_normal((4, 4)) * 1e6},
                  4: {"slab/1": rng.standard_normal((4, 4)) * 1e6}},
        counters={"events": 5, "rate_solves": 3, "factorisations": 2, "seconds": 0.1 + 0.2},
        mechanism={"bodies": ("slab/1",), "mode": np.array([1.0, -0.5, 1 / 3]), "rank": 2},
        geometry=geo,
        _recover=lambda i: np.zeros(10),
    )


def assert_results_equal(a: StaticResult, b: StaticResult) -> None:
    for name in ("lam", "segment", "factors", "kind", "N", "Q", "un", "ut", "state",
                 "residual", "violation"):
        x, y = getattr(a, name), getattr(b, name)
        assert_array_equal(x, y, err_msg=name)
        assert np.asarray(x).dtype.kind == np.asarray(y).dtype.kind, name
    assert_array_equal(a.state.dtype, b.state.dtype)
    assert a.pattern_names == b.pattern_names and type(b.pattern_names) is tuple
    assert a.interface_names == b.interface_names and type(b.interface_names) is tuple
    assert a.segments == b.segments
    assert all(type(s) is tuple for s in b.segments)
    assert set(a.cfe) == set(b.cfe)
    for k, v in a.cfe.items():
        if isinstance(v, np.ndarray):
            assert_array_equal(b.cfe[k], v, err_msg=f"cfe[{k}]")
            assert b.cfe[k].dtype == v.dtype
        else:
            assert b.cfe[k] == v
    assert a.events == b.events
    for e in b.events:
        assert isinstance(e.transition, Transition)
        assert all(type(getattr(e, f)) is int for f in ("step", "state", "segment", "cfe"))
    assert a.multipliers == b.multipliers
    assert b.status is a.status
    assert b.message == a.message
    assert set(b.fields) == set(a.fields)
    assert all(type(k) is int for k in b.fields)
    for k in a.fields:
        assert_array_equal(b.fields[k], a.fields[k])
    assert list(b.stresses) == list(a.stresses)
    for k in a.stresses:
        assert set(b.stresses[k]) == set(a.stresses[k])
        for body in a.stresses[k]:
            assert_array_equal(b.stresses[k][body], a.stresses[k][body])
    assert b.counters == a.counters
    assert b.units == a.units
    if a.mechanism is None:
        assert b.mechanism is None
    else:
        assert set(b.mechanism) == set(a.mechanism)
        for k, v in a.mechanism.items():
            if isinstance(v, np.ndarray):
                assert_array_equal(b.mechanism[k], v)
            else:
                assert b.mechanism[k] == v and type(b.mechanism[k]) is type(v)
    assert list(b.geometry) == list(a.geometry)
    for k, v in a.geometry.items():
        if k == "bodies":
            assert len(b.geometry[k]) == len(v)
            for bb, ba in zip(b.geometry[k], v, strict=True):
                assert set(bb) == set(ba)
                assert_array_equal(bb["cells"], ba["cells"])
                assert {x: bb[x] for x in ("name", "kind", "element")} == {
                    x: ba[x] for x in ("name", "kind", "element")
                }
        else:
            assert_array_equal(b.geometry[k], v)
    assert b._recover is None


# --------------------------------------------------------------------------------------------
# io
# --------------------------------------------------------------------------------------------
def test_specs_cover_dataclasses():
    assert set(_EVENT_SPEC) == {f.name for f in dataclasses.fields(Event)}
    assert set(_MULT_SPEC) == {f.name for f in dataclasses.fields(Multipliers)}


def test_dataset_layout_and_units():
    res = make_result()
    ds = result_to_dataset(res)
    assert ds.sizes["state"] == 5
    assert ds.sizes["cfe"] == 6
    assert ds.sizes["event"] == 5
    assert ds.sizes["pattern"] == 2
    assert ds.sizes["segment_index"] == 2
    assert ds.sizes["field_state"] == 2 and ds.sizes["dof"] == 10
    assert ds.sizes["node"] == 5
    for name, var in ds.variables.items():
        assert "units" in var.attrs, name
        assert "long_name" in var.attrs, name
    assert ds["N"].attrs["units"] == "N"
    assert ds["un"].attrs["units"] == "m"
    assert ds["cfe_area"].attrs["units"] == "m2"
    assert ds["u"].attrs["units"] == "m"
    stress_vars = [v for v in ds.data_vars if str(v).startswith("stress__")]
    assert len(stress_vars) == 1 and ds[stress_vars[0]].attrs["units"] == "Pa"
    cells = [v for v in ds.data_vars if str(v).startswith("cells__")]
    assert len(cells) == 1
    assert ds[cells[0]].attrs["body"] == "slab/1"
    assert ds[cells[0]].attrs["element"] == "ElementTriP1"
    assert ds["contact_state"].attrs["flag_meanings"].split()[:4] == [
        "open", "stick", "slip_pos", "slip_neg"
    ]
    assert list(ds["event_transition"].values) == ["closed", "closed", "opened", "slip+", "slip-"]
    assert_allclose(ds["lam"].values, res.lam, rtol=0, atol=0)


def test_round_trip(tmp_path):
    res = make_result()
    p = save_result(res, tmp_path / "run.nc")
    back = load_result(p)
    assert_results_equal(res, back)
    # derived quantities agree as well
    assert_allclose(back.sigma_n, res.sigma_n, rtol=0, atol=0)
    assert back.states_of(4) == res.states_of(4)
    got = back.interpolate(0.5, 1)
    want = res.interpolate(0.5, 1)
    for k in ("N", "Q", "un", "ut", "state"):
        assert_allclose(got[k], want[k], rtol=1e-15, atol=0)
    assert_array_equal(back.displacement(4), res.fields[4])
    with pytest.raises(KeyError, match="not stored"):
        back.displacement(2)
    # and the methods on the result object go through the same functions
    res.save(tmp_path / "again.nc")
    assert_results_equal(res, StaticResult.load(tmp_path / "again.nc"))


def test_round_trip_minimal(tmp_path):
    """No events, no fields, no stresses, no geometry, no mechanism, empty message."""
    res = dataclasses.replace(
        make_result(events=False, geometry=False), fields={}, stresses={}, mechanism=None,
        multipliers=[], message="", counters={},
    )
    back = load_result(save_result(res, tmp_path / "r.nc"))
    assert_results_equal(res, back)
    assert back.events == [] and back.geometry == {} and back.fields == {}


def test_atomic_write_creates_parents_and_leaves_no_temp(tmp_path):
    target = tmp_path / "a" / "b" / "run.nc"
    save_result(make_result(), target)
    assert target.is_file()
    assert [p.name for p in target.parent.iterdir()] == ["run.nc"]
    # overwriting works and leaves one file
    save_result(make_result(events=False), target)
    assert [p.name for p in target.parent.iterdir()] == ["run.nc"]
    assert load_result(target).events == []


def test_failed_write_keeps_old_file(tmp_path, monkeypatch):
    target = tmp_path / "run.nc"
    save_result(make_result(), target)
    before = target.read_bytes()

    def broken(self, path, *args, **kwargs):
        with open(path, "wb") as fh:  # a half-written file ...
            fh.write(b"\x89HDF partial")
        raise OSError("disk full")  # ... and the writer dies

    monkeypatch.setattr(xr.Dataset, "to_netcdf", broken)
    with pytest.raises(OSError, match="disk full"):
        save_result(make_result(events=False), target)
    assert target.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["run.nc"]
    monkeypatch.undo()
    assert len(load_result(target).events) == 5


def test_result_writer_hook(tmp_path):
    w = ResultWriter(tmp_path / "out" / "run.nc")
    res = make_result()
    w.after_segment(res)
    w.after_segment(res)
    assert w.writes == 2
    assert_results_equal(res, load_result(tmp_path / "out" / "run.nc"))


def test_load_errors(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such result file"):
        load_result(tmp_path / "missing.nc")
    xr.Dataset({"a": ("x", np.zeros(2))}).to_netcdf(tmp_path / "other.nc", engine="h5netcdf")
    with pytest.raises(ValueError, match="not a stepcontact static result"):
        load_result(tmp_path / "other.nc")


# --------------------------------------------------------------------------------------------
# plots
# --------------------------------------------------------------------------------------------
def _check_png(path):
    import matplotlib.image as mpimg

    assert path.is_file() and path.stat().st_size > 10_000
    img = mpimg.imread(path)
    assert img.ndim == 3 and img.shape[0] > 300 and img.shape[1] > 300
    assert np.ptp(img[..., :3]) > 0.5  # not a blank image
    assert len(np.unique(img[..., :3].reshape(-1, 3), axis=0)) > 20


def test_plot_interfaces_default(tmp_path):
    from matplotlib.figure import Figure

    res = make_result()
    out = tmp_path / "plots" / "itf.png"
    fig = plot_interfaces(res, path=out)
    assert isinstance(fig, Figure)
    _check_png(out)
    assert "'dead'" in fig.get_suptitle() and "'live'" in fig.get_suptitle()
    # 3 rows × 2 interfaces
    assert len(fig.axes) == 6
    ylabel = fig.axes[0].get_ylabel()
    assert "kPa" in ylabel  # the stresses are O(1e5) Pa


def test_plot_interfaces_chosen_lams(tmp_path):
    res = make_result()
    fig = plot_interfaces(res, lams=[0.3, 0.5, 0.7], segment=1, path=tmp_path / "itf.svg")
    assert "<svg" in (tmp_path / "itf.svg").read_text()[:2000]
    lines = fig.axes[0].get_lines()  # σ_n of the first interface: one line per λ + zero line
    assert len(lines) == 4
    # σ_n at λ = 0.5 is the interpolated N / A, in kPa
    want = res.interpolate(0.5, 1)["N"][:3] / res.cfe["area"][:3] / 1e3
    assert_allclose(lines[1].get_ydata(), want, rtol=1e-12, atol=0)
    fig2 = plot_interfaces(res, lams=0.2, segment=0, path=tmp_path / "itf.pdf")
    assert (tmp_path / "itf.pdf").read_bytes()[:4] == b"%PDF"
    assert "0.2" in fig2.get_suptitle()


def test_plot_interfaces_bad_input(tmp_path):
    res = make_result()
    with pytest.raises(ValueError, match="unsupported suffix"):
        plot_interfaces(res, path=tmp_path / "x.jpg2")
    with pytest.raises(ValueError, match="outside segment"):
        plot_interfaces(res, lams=[2.0], segment=0)


def test_plot_load_path(tmp_path):
    res = make_result()
    out = tmp_path / "path.png"
    fig = plot_load_path(res, path=out)
    _check_png(out)
    assert "5 events" in fig.get_suptitle()
    # after a round trip the plots still work
    back = load_result(save_result(res, tmp_path / "r.nc"))
    plot_load_path(back, path=tmp_path / "path2.png")
    plot_interfaces(back, path=tmp_path / "itf2.png")
    _check_png(tmp_path / "itf2.png")


def test_plot_load_path_no_events(tmp_path):
    res = make_result(events=False)
    plot_load_path(res, path=tmp_path / "p.png")
    _check_png(tmp_path / "p.png")


def test_state_strip_shows_scheme_after_last_state(tmp_path):
    res = make_result()
    fig = plot_interfaces(res)  # default: end of each segment
    strip = fig.axes[5].collections[0].get_array().reshape(2, 3)  # interface 'joint ä/1'
    assert_array_equal(strip[1], res.state[4, 3:])  # includes the slip- event at λ = 0.7
    assert_array_equal(strip[0], res.state[2, 3:])


def test_no_contact_elements(tmp_path):
    """A run without CFEs round-trips and plots."""
    res = make_result(events=False)
    empty = {k: v[:0] if isinstance(v, np.ndarray) else v for k, v in res.cfe.items()}
    res = dataclasses.replace(
        res, cfe=empty, interface_names=(), N=res.N[:, :0], Q=res.Q[:, :0], un=res.un[:, :0],
        ut=res.ut[:, :0], state=res.state[:, :0],
    )
    back = load_result(save_result(res, tmp_path / "r.nc"))
    assert_results_equal(res, back)
    assert back.m == 0
    plot_interfaces(back, path=tmp_path / "i.png")
    plot_load_path(back, path=tmp_path / "p.png")
    assert (tmp_path / "i.png").stat().st_size > 1000
    _check_png(tmp_path / "p.png")


@pytest.mark.slow
def test_demo_run_round_trip_and_plots(tmp_path):
    """A real run: the writer hook saves at every segment end; the file round-trips exactly."""
    from stepcontact.demo import demo_uplift_model
    from stepcontact.solver.static import solve_static

    w = ResultWriter(tmp_path / "partial.nc")
    res = solve_static(demo_uplift_model(), hooks=[w])
    assert w.writes >= 1
    partial = load_result(tmp_path / "partial.nc")
    assert partial.n_states <= res.n_states
    back = load_result(save_result(res, tmp_path / "run.nc"))
    assert_results_equal(res, back)
    plot_interfaces(back, path=tmp_path / "itf.png")
    plot_load_path(back, path=tmp_path / "path.png")
    _check_png(tmp_path / "itf.png")
    _check_png(tmp_path / "path.png")
