"""Result files (save → load round trip, atomic writes) and plots, on a hand-built result."""

from __future__ import annotations

import dataclasses
import struct

import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose, assert_array_equal

from stepcontact.enums import ContactState, Status, Transition
from stepcontact.post.plotting import (
    STATE_COLORS,
    TRANSITION_MARKERS,
    _lam_text,
    plot_interfaces,
    plot_load_path,
)
from stepcontact.results.file import (
    _EVENT_SPEC,
    _MULT_SPEC,
    ResultWriter,
    result_to_dataset,
    save_result,
)
from stepcontact.results.result import Event, Multipliers, StaticResult, load_result

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

    def broken(self, path=None, *args, **kwargs):
        if path is not None:  # (the file is made in memory: path None)
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
    w.finish(res)  # the final result is on disk already: not written again
    assert w.writes == 2
    more = make_result(events=False)
    w.finish(more)  # a different end state is
    assert w.writes == 3
    assert_results_equal(more, load_result(tmp_path / "out" / "run.nc"))


def test_load_errors(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such result file"):
        load_result(tmp_path / "missing.nc")
    xr.Dataset({"a": ("x", np.zeros(2))}).to_netcdf(tmp_path / "other.nc", engine="h5netcdf")
    with pytest.raises(ValueError, match="not a stepcontact static result"):
        load_result(tmp_path / "other.nc")


# --------------------------------------------------------------------------------------------
# plots: what the figures draw (their matplotlib artists), checked against the result's data
# --------------------------------------------------------------------------------------------
def rgba(color) -> tuple[float, float, float, float]:
    from matplotlib.colors import to_rgba

    return to_rgba(color)


def png_size(path) -> tuple[int, int]:
    """(width, height) in pixels, read from the header of a PNG file."""
    head = path.read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG file"
    return struct.unpack(">II", head[16:24])


def assert_png_of(path, fig, dpi: float) -> None:
    """``path`` holds ``fig`` rendered at ``dpi``: a PNG of the figure's size × dpi pixels."""
    w, h = fig.get_size_inches()
    assert png_size(path) == (int(w * dpi), int(h * dpi))  # Agg truncates to whole pixels


def snapshot(res: StaticResult, segment: int, lam: float) -> dict:
    """What plot_interfaces draws at ``lam`` of ``segment``: the interpolated forces and, at
    the λ of a reported state, the working scheme after the last state with that λ."""
    snap = dict(res.interpolate(lam, segment), segment=segment, lam=lam)
    at = np.flatnonzero((res.segment == segment) & (res.lam == lam))
    if at.size:
        snap["state"] = res.state[at[-1]]
    return snap


def segment_ends(res: StaticResult) -> list[dict]:
    """The default of plot_interfaces: the end of every segment reached."""
    return [snapshot(res, s, float(res.lam[np.flatnonzero(res.segment == s)[-1]]))
            for s in dict.fromkeys(res.segment.tolist())]


def check_interfaces_figure(fig, res: StaticResult, snaps: list[dict]) -> None:
    """The panels of plot_interfaces against the CFE data.

    One column per interface: σ_n = N/A and τ = Q/A over the positions s of its CFEs (in
    order of s), one colour per snapshot, the friction limits ±f|σ_n| dashed, zero lines, the
    stress unit in the labels; a strip of CFE states coloured with STATE_COLORS; one legend
    entry per snapshot and per contact state.
    """
    names = list(res.interface_names)
    ncol = len(names)
    assert len(fig.axes) == 3 * ncol
    area, fric, pos = (np.asarray(res.cfe[k], dtype=float) for k in ("area", "friction", "s"))
    peak = max(np.abs(np.r_[sn["N"] / area, sn["Q"] / area]).max(initial=0) for sn in snaps)
    div, unit = (1e6, "MPa") if peak >= 1e6 else (1e3, "kPa") if peak >= 1e3 else (1.0, "Pa")
    for c, name in enumerate(names):
        ax_n, ax_t, ax_s = fig.axes[c], fig.axes[ncol + c], fig.axes[2 * ncol + c]
        assert ax_n.get_title() == f"interface '{name}'"
        assert ax_n.get_ylabel() == rf"$\sigma_n$ = N/A, {unit} (compression < 0)"
        assert ax_t.get_ylabel() == rf"$\tau$ = Q/A, {unit}"  # the dashed limits: legend
        assert ax_s.get_xlabel() == "position s along the interface, m"
        k = np.flatnonzero(np.asarray(res.cfe["interface"]) == c)
        k = k[np.argsort(pos[k], kind="stable")]
        n_lines, t_lines = ax_n.get_lines(), ax_t.get_lines()
        assert len(n_lines) == len(snaps) + 1 and len(t_lines) == 3 * len(snaps) + 1
        assert len(ax_n.collections) == len(ax_t.collections) == len(snaps)  # shaded diagrams
        for j, sn in enumerate(snaps):
            sig = sn["N"][k] / area[k] / div
            sig_line = n_lines[j]
            tau_line, upper, lower = t_lines[3 * j:3 * j + 3]
            for line in (sig_line, tau_line, upper, lower):
                assert_array_equal(line.get_xdata(), pos[k])
                assert rgba(line.get_color()) == rgba(f"C{j}")
            assert_allclose(sig_line.get_ydata(), sig, rtol=1e-12, atol=0)
            assert_allclose(tau_line.get_ydata(), sn["Q"][k] / area[k] / div, rtol=1e-12, atol=0)
            assert_allclose(upper.get_ydata(), fric[k] * np.abs(sig), rtol=1e-12, atol=0)
            assert_allclose(lower.get_ydata(), -fric[k] * np.abs(sig), rtol=1e-12, atol=0)
            assert upper.get_linestyle() == lower.get_linestyle() == "--"
            assert sig_line.get_linestyle() == tau_line.get_linestyle() == "-"
        for zero in (n_lines[-1], t_lines[-1]):
            assert_array_equal(zero.get_ydata(), [0, 0])
        strip = ax_s.collections[0]
        want = np.array([np.asarray(sn["state"])[k] for sn in snaps])
        assert_array_equal(strip.get_array().reshape(want.shape), want)
        for code in np.unique(want):
            assert strip.cmap(strip.norm(code)) == rgba(STATE_COLORS[ContactState(int(code))])
        assert [t.get_text() for t in ax_s.get_yticklabels()] == [
            f"{res.segments[sn['segment']][0]} λ={_lam_text(sn['lam'])}" for sn in snaps]
    legend = fig.legends[0]
    labels = [t.get_text() for t in legend.get_texts()]
    assert labels[:len(snaps)] == [
        f"'{res.segments[sn['segment']][0]}' λ = {sn['lam']:.4g}" for sn in snaps]
    for j, handle in enumerate(legend.legend_handles[:len(snaps)]):
        assert rgba(handle.get_color()) == rgba(f"C{j}")
    by_label = {cs.label: cs for cs in ContactState}
    limits = labels[len(snaps)]  # what the dashed lines are
    assert limits == r"$\tau$ limits dashed: $\pm f|\sigma_n|$"
    assert legend.legend_handles[len(snaps)].get_linestyle() == "--"
    shown = labels[len(snaps) + 1:]
    assert {"open", "stick", "slip+", "slip-"} <= set(shown)
    for label, handle in zip(shown, legend.legend_handles[len(snaps) + 1:], strict=True):
        assert handle.get_facecolor() == rgba(STATE_COLORS[by_label[label]])


def check_load_path_figure(fig, res: StaticResult) -> None:
    """The panels of plot_load_path against the result: λ per segment over the state index
    (from the state before the segment), events marked by transition, dotted segment
    boundaries, the events so far on the top axis, stacked bars of the CFE states."""
    ax_l, ax_c = fig.axes
    lines = ax_l.get_lines()
    segs = list(dict.fromkeys(res.segment.tolist()))
    seg_lines = [ln for ln in lines if ln.get_marker() == "."]
    assert len(seg_lines) == len(segs)
    for j, (s, line) in enumerate(zip(segs, seg_lines, strict=True)):
        idx = np.flatnonzero(res.segment == s)
        x, y = idx, res.lam[idx]
        if idx[0] > 0:
            x, y = np.r_[idx[0] - 1, x], np.r_[res.segments[s][1], y]
            for ax in (ax_l, ax_c):  # a dotted boundary before the segment's first state
                assert any(ln.get_linestyle() == ":" and np.all(ln.get_xdata() == idx[0] - 0.5)
                           for ln in ax.get_lines())
        assert_array_equal(line.get_xdata(), x)
        assert_allclose(line.get_ydata(), y, rtol=0, atol=0)
        assert rgba(line.get_color()) == rgba(f"C{j}")
    markers = {m for m, _ in TRANSITION_MARKERS.values()}
    marks = [(ln.get_xdata()[0], ln.get_ydata()[0], ln.get_marker(), rgba(ln.get_color()))
             for ln in lines if ln.get_marker() in markers]
    want = [(e.state, e.lam, TRANSITION_MARKERS[e.transition][0],
             rgba(TRANSITION_MARKERS[e.transition][1])) for e in res.events]
    assert sorted(marks) == sorted(want)
    transitions = list(dict.fromkeys(e.transition.value for e in res.events))
    assert [t.get_text() for t in ax_l.get_legend().get_texts()] == [
        f"segment {s}: '{res.segments[s][0]}'" for s in segs] + transitions
    assert ax_l.get_ylabel() == "load factor λ of the active pattern"
    (top,) = ax_l.child_axes
    assert top.get_xlabel() == "events so far"
    ticks = np.unique(np.linspace(0, res.n_states - 1, min(res.n_states, 8)).round().astype(int))
    n_ev = [sum(e.state <= t for e in res.events) for t in ticks]
    assert_array_equal(top.get_xticks(), ticks)
    assert [t.get_text() for t in top.get_xticklabels()] == [str(n) for n in n_ev]
    # bars: the CFEs in each state after state i, stacked, coloured by state
    present = [cs for cs in ContactState if np.any(res.state == int(cs))]
    assert [b.get_label() for b in ax_c.containers] == [cs.label for cs in present]
    total = np.zeros(res.n_states)
    for cs, bars in zip(present, ax_c.containers, strict=True):
        count = np.sum(res.state == int(cs), axis=1)
        assert_array_equal(bars.datavalues, count)
        assert_array_equal([p.get_y() for p in bars.patches], total)  # stacked
        assert {p.get_facecolor() for p in bars.patches} == {rgba(STATE_COLORS[cs])}
        total += count
    if present:
        assert_array_equal(total, res.m)
        assert [t.get_text() for t in ax_c.get_legend().get_texts()] == [
            cs.label for cs in present]
    assert ax_c.get_ylabel() == "number of CFEs" and ax_c.get_xlabel() == "reported state i"
    assert fig.get_suptitle() == (
        f"Load path — {res.status.value}, {len(res.events)} events, {res.m} CFEs")


def test_plot_interfaces_default(tmp_path):
    from matplotlib.figure import Figure

    res = make_result()
    out = tmp_path / "plots" / "itf.png"
    fig = plot_interfaces(res, path=out)
    assert isinstance(fig, Figure)
    assert_png_of(out, fig, dpi=150)  # the parent folder is created; the default resolution
    assert fig.get_suptitle() == "Contact stresses at pattern 'dead' λ = 1;\npattern 'live' λ = 0.7"
    snaps = segment_ends(res)
    # the ends of the segments are the reported states 2 and 4
    for sn, i in zip(snaps, (2, 4), strict=True):
        assert_array_equal(sn["N"], res.N[i])
        assert_array_equal(sn["state"], res.state[i])
    check_interfaces_figure(fig, res, snaps)  # 3 rows × 2 interfaces
    assert "kPa" in fig.axes[0].get_ylabel()  # the stresses are O(1e5) Pa
    # the frictionless-contact and bonded states are in the legend only when drawn
    assert [t.get_text() for t in fig.legends[0].get_texts()][3:] == [
        "open", "stick", "slip+", "slip-"]


def test_plot_interfaces_chosen_lams(tmp_path):
    res = make_result()
    fig = plot_interfaces(res, lams=[0.3, 0.5, 0.7], segment=1, path=tmp_path / "itf.svg")
    assert "<svg" in (tmp_path / "itf.svg").read_text()[:2000]
    lines = fig.axes[0].get_lines()  # σ_n of the first interface: one line per λ + zero line
    assert len(lines) == 4
    # σ_n at λ = 0.5 is the interpolated N / A, in kPa
    want = res.interpolate(0.5, 1)["N"][:3] / res.cfe["area"][:3] / 1e3
    assert_allclose(lines[1].get_ydata(), want, rtol=1e-12, atol=0)
    check_interfaces_figure(fig, res, [snapshot(res, 1, v) for v in (0.3, 0.5, 0.7)])
    assert fig.get_suptitle() == "Contact stresses at pattern 'live' λ = 0.3, 0.5, 0.7"
    fig2 = plot_interfaces(res, lams=0.2, segment=0, path=tmp_path / "itf.pdf")
    assert (tmp_path / "itf.pdf").read_bytes()[:4] == b"%PDF"
    assert "0.2" in fig2.get_suptitle()
    check_interfaces_figure(fig2, res, [snapshot(res, 0, 0.2)])


def test_plot_interfaces_bad_input(tmp_path):
    res = make_result()
    with pytest.raises(ValueError, match="unsupported suffix"):
        plot_interfaces(res, path=tmp_path / "x.jpg2")
    with pytest.raises(ValueError, match="outside segment"):
        plot_interfaces(res, lams=[2.0], segment=0)


def test_plot_load_path(tmp_path):
    res = make_result()
    out = tmp_path / "path.png"
    fig = plot_load_path(res, path=out, dpi=40)
    assert_png_of(out, fig, dpi=40)
    assert "5 events" in fig.get_suptitle()
    check_load_path_figure(fig, res)
    # segment 1 starts from the end of segment 0 (state 2) at its starting λ
    live = [ln for ln in fig.axes[0].get_lines() if ln.get_marker() == "."][1]
    assert_array_equal(live.get_xdata(), [2, 3, 4])
    assert_array_equal(live.get_ydata(), [0.0, 0.3, 0.7])
    # after a round trip the figures draw the same data
    back = load_result(save_result(res, tmp_path / "r.nc"))
    check_load_path_figure(plot_load_path(back), res)
    check_interfaces_figure(plot_interfaces(back), res, segment_ends(res))


def test_plot_load_path_no_events():
    res = make_result(events=False)
    fig = plot_load_path(res)
    check_load_path_figure(fig, res)
    markers = {m for m, _ in TRANSITION_MARKERS.values()}
    assert not [ln for ln in fig.axes[0].get_lines() if ln.get_marker() in markers]
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()] == [
        "segment 0: 'dead'", "segment 1: 'live'"]
    assert "0 events" in fig.get_suptitle()


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
    fig = plot_interfaces(back, path=tmp_path / "i.png", dpi=30)
    assert_png_of(tmp_path / "i.png", fig, dpi=30)
    (ax,) = fig.axes
    assert [t.get_text() for t in ax.texts] == ["no contact interfaces"]
    assert not ax.axison and not ax.get_lines()
    fig = plot_load_path(back, path=tmp_path / "p.png", dpi=30)
    assert_png_of(tmp_path / "p.png", fig, dpi=30)
    check_load_path_figure(fig, back)
    assert not fig.axes[1].containers and fig.axes[1].get_legend() is None  # no CFE: no bars
    assert fig.get_suptitle().endswith("0 events, 0 CFEs")


@pytest.mark.slow
def test_demo_run_round_trip_and_plots(tmp_path):
    """A real run: the writer hook saves at every segment end; the file round-trips exactly;
    the figures of the loaded result draw the run's data."""
    from stepcontact.demo import demo_uplift_model
    from stepcontact.solver.static import solve_static

    w = ResultWriter(tmp_path / "partial.nc")
    res = solve_static(demo_uplift_model(), hooks=[w])
    assert w.writes >= 1
    partial = load_result(tmp_path / "partial.nc")
    assert partial.n_states <= res.n_states
    back = load_result(save_result(res, tmp_path / "run.nc"))
    assert_results_equal(res, back)
    assert res.m > 0 and res.events
    check_interfaces_figure(plot_interfaces(back), res, segment_ends(res))
    check_load_path_figure(plot_load_path(back), res)
