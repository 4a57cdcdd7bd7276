"""Fields only when asked (issue 8).

A run stores the contact unknowns at every state but displacement fields and stresses only at
the start, the segment starts and ends and the last state (where the run completed or
stopped).  The path is piecewise linear, so any other state's fields are exact from its
contact unknowns: ``res.displacement(i)``, ``res.displacements(states)`` (one
multi-right-hand-side solve), ``res.stress(i)``, ``res.stresses_at(states)``.  References: the
fields a ``store_fields="all"`` run stores at every state (to 1e-10 relative).
"""

from __future__ import annotations

import json
import logging
import pickle

import meshio
import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import stepcontact as sc
import verification_models as vm
from stepcontact.cli import app
from stepcontact.demo import demo_text
from stepcontact.io.modelfile import load_model
from stepcontact.results.result import load_result

G = 9.81
RTOL = 1e-10
runner = CliRunner()


def block_on_base(E: float = 30e9) -> sc.Model:
    """examples/block_on_base.py: self-weight, then a push until the block slides."""
    return vm.pushed_block(E=E)


def pulled_block() -> sc.Model:
    """Prescribed displacements and three load patterns: weight, a pull imposed on the
    block's right side (it drags the block until it slides), then a push back by a force."""
    m = vm.block_on_base(friction=0.5, w=2.0, h=0.5, nx=4, ny=2)
    right, left = m.select("block", x=2.0), m.select("block", x=0.0)
    return m.add(
        sc.LoadPattern("weight", [sc.BodyForce((0.0, -G), bodies=("block",))]),
        sc.LoadPattern("pull", [sc.PrescribedDisplacement(right, "x", 1e-3)]),
        sc.LoadPattern("side", [sc.NodalLoad(left, fx=1.0 / len(left))]),
        sc.Segment("weight", 1.0), sc.Segment("pull", 1.0), sc.Segment("side", 50.0),
    )


MODELS = {"block_on_base": block_on_base, "pulled_block": pulled_block}


@pytest.fixture(scope="module", params=list(MODELS))
def runs(request):
    """(model, the default run, a run storing every state's fields)."""
    m = MODELS[request.param]()
    return m, sc.solve_static(m), sc.solve_static(m, store_fields="all")


def ends_of(res: sc.StaticResult) -> set[int]:
    """The states the default run stores: start, segment starts and ends, the last state."""
    return set(np.flatnonzero(np.asarray(res.kind) != "event").tolist()) | {res.n_states - 1}


def assert_same_fields(U, S, ref: sc.StaticResult, states) -> None:
    """Displacements U (k, ndof) and stresses S {state: {body: …}} equal ``ref``'s stored
    fields at ``states`` to RTOL (relative to the largest value of the run)."""
    u_max = max(np.abs(u).max() for u in ref.fields.values())
    for u, i in zip(U, states, strict=True):
        assert np.abs(u - ref.fields[i]).max() <= RTOL * u_max, i
    for body in ref.stresses[states[-1]]:
        s_max = max(np.abs(s[body]).max() for s in ref.stresses.values())
        for i in states:
            assert np.abs(S[i][body] - ref.stresses[i][body]).max() <= RTOL * s_max, (i, body)


# --------------------------------------------------------------------------------------------
# what a run stores
# --------------------------------------------------------------------------------------------
def test_default_run_stores_fields_only_at_ends(runs):
    m, res, full = runs
    assert res.n_states > len(ends_of(res)) + 2  # events in between
    assert set(res.fields) == set(res.stresses) == ends_of(res)
    assert set(full.fields) == set(full.stresses) == set(range(full.n_states))
    # the path does not depend on what is stored
    for k in ("lam", "N", "Q", "un", "ut", "state", "reactions", "factors"):
        assert np.array_equal(getattr(res, k), getattr(full, k)), k
    assert res.status == full.status
    # one solve per stored state instead of one per state
    assert full.counters["solves"] - res.counters["solves"] == full.n_states - len(res.fields)
    # residuals: the full check at stored states, the (equivalent) condensed one elsewhere
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-9
    stored = sorted(res.fields)
    assert np.array_equal(res.residual[stored], full.residual[stored])
    # "auto" is the default ("ends")
    auto = sc.solve_static(m, store_fields="auto")
    assert set(auto.fields) == set(res.fields)
    with pytest.raises(sc.ModelError, match="store_fields"):
        sc.solve_static(m, store_fields="some")


def test_the_state_where_a_run_stops_has_its_field():
    m = block_on_base()
    res = sc.solve_static(m, max_events=2)
    assert res.status == sc.Status.MAX_EVENTS and res.kind[-1] == "event"
    last = res.n_states - 1
    assert last in res.fields and last in res.stresses
    full = sc.solve_static(m, max_events=2, store_fields="all")
    assert np.abs(res.fields[last] - full.fields[last]).max() <= RTOL * np.abs(
        full.fields[last]).max()
    assert res.residual[last] == full.residual[last]

    seen = []

    class Interrupt:
        def after_event(self, info):
            if info.step == 3:
                raise KeyboardInterrupt

        def interrupted(self, result):
            seen.append(result)

    with pytest.raises(KeyboardInterrupt):
        sc.solve_static(m, hooks=(Interrupt(),))
    (cut,) = seen
    assert cut.status == sc.Status.INCOMPLETE and cut.kind[-1] == "event"
    assert cut.n_states - 1 in cut.fields


# --------------------------------------------------------------------------------------------
# fields on request
# --------------------------------------------------------------------------------------------
def test_recovered_fields_equal_the_stored_ones(runs):
    _, res, full = runs
    states = list(range(res.n_states))
    U = res.displacements()
    assert U.shape == (res.n_states, len(full.fields[0]))
    S = res.stresses_at()
    assert list(S) == states
    assert_same_fields(U, S, full, states)
    missing = [i for i in states if i not in res.fields]
    assert_same_fields([res.displacement(i) for i in missing],
                       {i: res.stress(i) for i in missing}, full, missing)
    # stored states are returned as stored
    i = min(res.fields)
    assert res.displacement(i) is res.fields[i] and res.stress(i) is res.stresses[i]


def test_batched_recovery_is_one_solve_and_equals_one_by_one(runs):
    _, res, _ = runs
    missing = [i for i in range(res.n_states) if i not in res.fields]
    rec = res._recover
    cond = rec.cond
    real = cond.factor
    calls = []

    class Counting:
        name = real.name

        def solve(self, b):
            calls.append(np.shape(b))
            return real.solve(b)

    cond.factor = Counting()
    try:
        U = res.displacements(missing[::-1])  # any order: rows follow the request
        S = res.stresses_at(missing, displacements=U[::-1])
    finally:
        cond.factor = real
    assert calls == [(len(cond.free), len(missing))]  # one multi-right-hand-side solve
    one = np.stack([res.displacement(i) for i in missing[::-1]])
    assert np.abs(U - one).max() <= 1e-12 * np.abs(one).max()
    for i in missing:
        for body, s in res.stress(i).items():
            assert np.abs(S[i][body] - s).max() <= 1e-12 * np.abs(s).max()
    # negative indices, repeated states, mixed stored and recovered states
    k = missing[0]
    V = res.displacements([-1, k, 0, k])
    assert np.array_equal(V[0], res.fields[res.n_states - 1]) and np.array_equal(V[2],
                                                                                 res.fields[0])
    assert np.array_equal(V[1], V[3])
    assert res.displacements([]).shape == (0, U.shape[1])
    with pytest.raises(IndexError, match="does not exist"):
        res.displacements([res.n_states])


# --------------------------------------------------------------------------------------------
# results files, pickles
# --------------------------------------------------------------------------------------------
def test_loaded_result_names_recover_fields(runs, tmp_path):
    m, res, full = runs
    path = tmp_path / "r.nc"
    res.save(path)
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert json.loads(ds.attrs["field_states"]) == sorted(res.fields)
        assert json.loads(ds.attrs["stress_states"]) == sorted(res.stresses)
        assert "recover_fields" in ds.attrs["fields_note"]
        assert ds.sizes["field_state"] == len(res.fields)
    back = load_result(path)
    assert set(back.fields) == set(res.fields)
    k = next(i for i in range(res.n_states) if i not in res.fields)
    for call in (lambda: back.displacement(k), lambda: back.displacements(),
                 lambda: back.stress(k), lambda: back.stresses_at([k])):
        with pytest.raises(KeyError, match=r"recover_fields\(model\)"):
            call()
    back.displacements(sorted(back.fields))  # the stored ones need no model
    back.recover_fields(m)
    states = list(range(res.n_states))
    assert_same_fields(back.displacements(), back.stresses_at(), full, states)
    unpickled = pickle.loads(pickle.dumps(back))
    assert unpickled._recover is None
    with pytest.raises(KeyError, match="recover_fields"):
        unpickled.displacement(k)


def test_recover_fields_refuses_another_model(tmp_path):
    res = sc.solve_static(block_on_base())
    back = pickle.loads(pickle.dumps(res))
    with pytest.raises(ValueError, match="not the one of this result"):
        back.recover_fields(block_on_base(E=20e9))
    with pytest.raises(ValueError, match="CFEs"):
        back.recover_fields(pulled_block())


# --------------------------------------------------------------------------------------------
# export and plots of every state
# --------------------------------------------------------------------------------------------
def nodal(res: sc.StaticResult, u: np.ndarray) -> np.ndarray:
    return u[np.asarray(res.geometry["dof_of"])[:, :2]]


def read_pvd(path):
    import xml.etree.ElementTree as ET

    coll = ET.parse(path).getroot().find("Collection")
    return [path.parent / d.get("file") for d in coll]


def check_frames(files, full: sc.StaticResult) -> None:
    """Every state is a frame, with the displacements and stresses of the all-fields run."""
    assert len(files) == full.n_states
    u_max = max(np.abs(u).max() for u in full.fields.values())
    s_max = max(np.abs(s).max() for st in full.stresses.values() for s in st.values())
    for i, f in enumerate(files):
        mesh = meshio.read(f)
        assert int(mesh.field_data["state"][0]) == i
        d = mesh.point_data["displacement"][:, :2]
        assert np.abs(d - nodal(full, full.fields[i])).max() <= RTOL * u_max
        body = np.concatenate(mesh.cell_data["body"])
        sig = np.column_stack([np.concatenate(mesh.cell_data[k]) for k in
                               ("sigma_xx", "sigma_yy", "sigma_xy", "sigma_zz")])
        assert not np.isnan(sig).any()
        for b, name in enumerate(str(b["name"]) for b in full.geometry["bodies"]):
            assert np.abs(sig[body == b] - full.stresses[i][name]).max() <= RTOL * s_max


def test_export_of_every_state_in_memory(tmp_path, caplog):
    m = block_on_base()
    res, full = sc.solve_static(m), sc.solve_static(m, store_fields="all")
    with caplog.at_level(logging.WARNING, logger="stepcontact.io.export"):
        pvd = sc.export_vtu(res, tmp_path / "pv")  # default: every state
        sc.export_xdmf(res, tmp_path / "x" / "r.xdmf")
    assert "skipped" not in caplog.text
    check_frames(read_pvd(pvd), full)
    with meshio.xdmf.TimeSeriesReader(tmp_path / "x" / "r.xdmf") as r:
        assert r.num_steps == res.n_states
    # loaded from a file: the stored states, and a warning naming the others and the remedy
    res.save(tmp_path / "r.nc")
    back = load_result(tmp_path / "r.nc")
    with caplog.at_level(logging.WARNING, logger="stepcontact.io.export"):
        pvd = sc.export_vtu(back, tmp_path / "pv2")
    assert len(read_pvd(pvd)) == len(back.fields)
    assert "skipped" in caplog.text and "recover_fields(model)" in caplog.text
    assert "--model" in caplog.text
    back.recover_fields(m)
    check_frames(read_pvd(sc.export_vtu(back, tmp_path / "pv3")), full)


def test_plots_of_every_state_after_recover_fields(tmp_path):
    from stepcontact.post.plotting import plot_deformed, plot_load_displacement

    m = block_on_base()
    res = sc.solve_static(m)
    res.save(tmp_path / "r.nc")
    back = load_result(tmp_path / "r.nc")
    k = next(i for i in range(res.n_states) if i not in res.fields)
    with pytest.raises(ValueError, match=r"recover_fields\(model\)"):
        plot_deformed(back, state=k)
    with pytest.raises(ValueError, match=r"recover_fields\(model\)"):
        plot_load_displacement(back)
    back.recover_fields(m)
    a = plot_load_displacement(back, node=(3.0, 2.0), dof="x")
    b = plot_load_displacement(res, node=(3.0, 2.0), dof="x")
    for la, lb in zip(a.axes[-1].get_lines(), b.axes[-1].get_lines(), strict=True):
        assert np.allclose(la.get_xdata(), lb.get_xdata(), rtol=1e-10)
    plot_deformed(back, state=k)


def test_cli_export_and_plot_recompute_from_the_model_file(tmp_path):
    model_file = tmp_path / "demo.toml"
    model_file.write_text(demo_text("slide"), encoding="utf-8")
    out = runner.invoke(app, ["run", str(model_file), "--no-plot", "-q"])
    assert out.exit_code == 0, out.output
    nc = tmp_path / "demo.nc"
    res = load_result(nc)
    assert len(res.fields) < res.n_states
    full = sc.solve_static(load_model(model_file), store_fields="all")
    # the model file beside the result file is used
    out = runner.invoke(app, ["export", str(nc), "--vtu", str(tmp_path / "a"), "--json"])
    assert out.exit_code == 0, out.output
    info = json.loads(out.stdout)
    assert info["frames"] == res.n_states and info["skipped"] == []
    assert info["model_file"] == str(model_file)
    assert info["recomputed"] == [i for i in range(res.n_states) if i not in res.fields]
    check_frames(read_pvd(tmp_path / "a" / "demo.pvd"), full)
    # elsewhere, without the model (not beside it, and not where the run recorded it): the
    # stored states, and how to get the others
    other = tmp_path / "elsewhere"
    other.mkdir()
    (other / "run.nc").write_bytes(nc.read_bytes())
    kept = tmp_path / "kept"
    kept.mkdir()
    model_file = model_file.rename(kept / model_file.name)
    out = runner.invoke(app, ["export", str(other / "run.nc"), "--vtu", str(tmp_path / "b")])
    assert out.exit_code == 0, out.output
    assert "skipped" in out.stdout and "--model MODEL.toml" in out.stdout
    assert len(read_pvd(tmp_path / "b" / "run.pvd")) == len(res.fields)
    # --model gives them
    out = runner.invoke(app, ["export", str(other / "run.nc"), "--vtu", str(tmp_path / "c"),
                              "--model", str(model_file)])
    assert out.exit_code == 0, out.output
    assert "recomputed from" in out.stdout and "skipped" not in out.stdout
    check_frames(read_pvd(tmp_path / "c" / "run.pvd"), full)
    # the wrong model is refused
    wrong = tmp_path / "uplift.toml"
    wrong.write_text(demo_text("uplift"), encoding="utf-8")
    out = runner.invoke(app, ["export", str(other / "run.nc"), "--vtu", str(tmp_path / "d"),
                              "--model", str(wrong)])
    assert out.exit_code == 2 and "--model" in out.stderr
    # plots: load-displacement needs every state
    args = ["plot", str(other / "run.nc"), "--kind", "load-displacement", "-o",
            str(tmp_path / "ld.png")]
    out = runner.invoke(app, args)
    assert out.exit_code == 2 and "--model MODEL.toml" in out.stderr
    out = runner.invoke(app, [*args, "--json", "--model", str(model_file)])
    assert out.exit_code == 0, out.output
    info = json.loads(out.stdout)
    assert info["written"] == [str(tmp_path / "ld.png")] and info["model_file"] == str(model_file)
    # info lists the stored states
    out = runner.invoke(app, ["info", str(nc), "--json"])
    assert json.loads(out.stdout)["field_states"] == sorted(res.fields)
