"""Parameter sweeps (:mod:`stepcontact.study.sweep`, ``stepcontact sweep``): case ids, the
store (resuming, changed parameters, failures, atomic files), the executors (serial, process
pool, dask LocalCluster: the same dataset), the condensation cache and the command line."""

from __future__ import annotations

import json
import shutil
import time
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from stepcontact.cli.commands import EXIT_ERROR, app
from stepcontact.study import studyfile as sf
from stepcontact.study import sweep as sw

DEMO = Path(str(files("stepcontact") / "data" / "demo.toml"))
STUDY = """
[study]
name = "friction sweep"
model = "demo.toml"
output = "store"
results = {results}

[grid]
"interfaces.joint.friction" = [0.4, 0.6]
"patterns.push.loads.0.normal" = [1.0e4, 2.0e4]
"""
#: closed form of the demo (docs in demo.toml): the block slides at λ = f W / (p · 1 m)
W = 2400 * 9.81 * 2 * 1  # N per metre run


def _study(tmp_path: Path, results: bool = False, text: str = STUDY) -> Path:
    shutil.copy(DEMO, tmp_path / "demo.toml")
    path = tmp_path / "study.toml"
    path.write_text(text.replace("{results}", "true" if results else "false"))
    return path


def _tmp_files(store: Path) -> list[Path]:
    return [p for p in store.rglob("*") if p.name.endswith(".tmp")]


# --------------------------------------------------------------------------------------------
# case functions (top level: picklable)
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Counting:
    """Appends the case's parameters to a log file (calls counted across processes); fails
    for x == fail_x while the file ``flag`` exists."""

    log: str
    flag: str = ""
    fail_x: int = -1

    def __call__(self, params):
        with open(self.log, "a", encoding="utf-8") as fh:
            fh.write(json.dumps(params) + "\n")
        if params["x"] == self.fail_x and self.flag and Path(self.flag).exists():
            raise ValueError(f"x = {params['x']} is not allowed")
        n = int(params["x"])
        return {"square": float(n * n), "label": f"x{n}", "parity": n % 2,
                "ramp": np.arange(n + 1, dtype=float), "nothing": None}

    def calls(self) -> list[dict]:
        p = Path(self.log)
        return [json.loads(x) for x in p.read_text().splitlines()] if p.exists() else []


class Interrupt:
    """Raises KeyboardInterrupt at the third case (an interrupted sweep)."""

    def __init__(self):
        self.n = 0

    def __call__(self, params):
        self.n += 1
        if self.n == 3:
            raise KeyboardInterrupt
        return {"y": params["x"] + 1}


# --------------------------------------------------------------------------------------------
# cases
# --------------------------------------------------------------------------------------------
def test_grid_ids_and_params():
    cases = sw.grid(friction=[0.5, 0.6], thickness=[2, 3])
    assert [c.id for c in cases] == ["friction=0.5,thickness=2", "friction=0.5,thickness=3",
                                     "friction=0.6,thickness=2", "friction=0.6,thickness=3"]
    assert cases[1].params == {"friction": 0.5, "thickness": 3}
    assert isinstance(cases[1].params["thickness"], int)
    # dotted keys: the last component while unique, else the whole key
    cases = sw.grid({"interfaces.joint.friction": [0.4], "patterns.push.loads.0.normal": [1e4]})
    assert cases[0].id == "friction=0.4,normal=10000.0"
    cases = sw.grid({"interfaces.a.friction": [0.4], "interfaces.b.friction": [0.5]})
    assert cases[0].id == "interfaces.a.friction=0.4,interfaces.b.friction=0.5"
    # file-system safe; long ids are shortened with a hash of the parameters (stable)
    assert sw.grid(name=["a/b c:d"])[0].id == "name=a_b_c_d"
    long = sw.grid(very_long_parameter_name=[1.0, 2.0], another_very_long_one=["x" * 40])
    assert all(len(c.id) <= sw.MAX_ID_LENGTH and "~" in c.id for c in long)
    assert len({c.id for c in long}) == 2
    assert [c.id for c in long] == [c.id for c in sw.grid(
        very_long_parameter_name=[1.0, 2.0], another_very_long_one=["x" * 40])]
    # ids that clash after sanitising get a hash each
    clash = sw.cases_from_list([{"s": "a/b"}, {"s": "a:b"}])
    assert len({c.id for c in clash}) == 2
    listed = sw.cases_from_list([{"id": "soft", "f": 0.3}, {"f": 0.9}])
    assert [c.id for c in listed] == ["soft", "f=0.9"]
    with pytest.raises(sw.StudyError, match="repeated"):
        sw.grid(f=[0.5, 0.5])
    with pytest.raises(sw.StudyError, match="not a scalar"):
        sw.grid(f=[[1, 2]])
    with pytest.raises(sw.StudyError, match="finite"):
        sw.grid(f=[float("nan")])


def test_parameter_paths_into_the_model_file():
    import tomllib

    doc = tomllib.loads(DEMO.read_text())
    d = sf.apply_params(doc, {"interfaces.joint.friction": 0.3, "program.1.end": 7.0,
                              "materials.rock.E": 5e9, "model.thickness": 2.0})
    assert d["interfaces"][0]["friction"] == 0.3 and d["program"][1]["end"] == 7.0
    assert d["materials"]["rock"]["E"] == 5e9 and d["model"]["thickness"] == 2.0
    assert doc["interfaces"][0]["friction"] == 0.6  # a deep copy
    with pytest.raises(sw.StudyError, match=r"'interfaces.jont.friction'.*0 \('joint'\)"):
        sf.apply_params(doc, {"interfaces.jont.friction": 0.3})
    with pytest.raises(sw.StudyError, match="no 'materialz'.*'model', 'materials'"):
        sf.apply_params(doc, {"materialz.rock.E": 1.0})
    with pytest.raises(sw.StudyError, match="names a table"):
        sf.apply_params(doc, {"materials.rock": 1.0})
    with pytest.raises(sw.StudyError, match=r"'interfaces.joint.frction'.*unknown field"):
        sf.check_params(doc, {"interfaces.joint.frction": 0.3})
    with pytest.raises(sw.StudyError, match=r"'interfaces.joint.friction' = -1.*greater"):
        sf.check_params(doc, {"interfaces.joint.friction": -1.0})


# --------------------------------------------------------------------------------------------
# the store
# --------------------------------------------------------------------------------------------
def test_resume_rerun_changed_params_and_failures(tmp_path):
    store = tmp_path / "store"
    flag = tmp_path / "fail"
    flag.touch()
    func = Counting(str(tmp_path / "calls.log"), str(flag), fail_x=2)
    cases = sw.grid(x=[0, 1, 2, 3])
    ds = sw.run_sweep(cases, func, store, executor="serial", progress=False)
    assert len(func.calls()) == 4
    assert list(ds.case_status.values) == ["ok", "ok", "failed", "ok"]
    assert "ValueError: x = 2 is not allowed" in str(ds.case_message.values[2])
    assert np.isnan(ds.square.values[2]) and ds.square.values[3] == 9.0
    assert list(ds.label.values) == ["x0", "x1", "", "x3"]
    assert ds.parity.dtype == float  # a failed case leaves a hole: NaN
    assert ds.ramp.shape == (4, 4) and np.isnan(ds.ramp.values[0, 1:]).all()
    assert np.isnan(ds.nothing.values).all()
    assert ds.attrs["failed"] == 1 and ds.attrs["grid"] == 1
    # a rerun runs only the failed case (still failing)
    sw.run_sweep(cases, func, store, executor="serial", progress=False)
    assert [c["x"] for c in func.calls()[4:]] == [2]
    # fixed: the failed case runs and succeeds, nothing else runs
    flag.unlink()
    ds = sw.run_sweep(cases, func, store, executor="serial", progress=False)
    assert [c["x"] for c in func.calls()[5:]] == [2]
    assert list(ds.case_status.values) == ["ok"] * 4 and ds.parity.dtype == np.int64
    # a deleted case file: only that case runs
    sw.case_path(store, cases[1]).unlink()
    sw.run_sweep(cases, func, store, executor="serial", progress=False)
    assert [c["x"] for c in func.calls()[6:]] == [1]
    # a changed parameter (same id, other params): that case runs again
    changed = [sw.Case(cases[0].id, {"x": 5}), *cases[1:]]
    ds = sw.run_sweep(changed, func, store, executor="serial", progress=False)
    assert [c["x"] for c in func.calls()[7:]] == [5]
    assert ds.square.values[0] == 25.0
    # --rerun: everything
    sw.run_sweep(cases, func, store, executor="serial", progress=False, rerun=True)
    assert len(func.calls()) == 12
    # the collected file is the returned dataset, rebuilt from the case files
    assert not _tmp_files(store)
    on_disk = xr.load_dataset(store / "sweep.nc", engine="h5netcdf")
    rebuilt = sw.collect(store, write=False)
    final = sw.run_sweep(cases, func, store, executor="serial", progress=False)
    assert len(func.calls()) == 12
    xr.testing.assert_identical(on_disk, final)
    xr.testing.assert_identical(rebuilt, final)
    case_file = xr.load_dataset(sw.case_path(store, cases[3]), engine="h5netcdf")
    assert json.loads(case_file.attrs["params"]) == {"x": 3}
    assert case_file.attrs["status"] == "ok"


def test_retries_within_a_run(tmp_path):
    flag = tmp_path / "fail"
    flag.touch()
    func = Counting(str(tmp_path / "calls.log"), str(flag), fail_x=1)
    ds = sw.run_sweep(sw.grid(x=[0, 1]), func, tmp_path / "s", executor="serial",
                      progress=False, retries=2)
    assert [c["x"] for c in func.calls()] == [0, 1, 1, 1]
    assert list(ds.case_status.values) == ["ok", "failed"]


def test_an_interrupted_sweep_keeps_the_finished_cases(tmp_path):
    store = tmp_path / "store"
    cases = sw.grid(x=[0, 1, 2, 3])
    with pytest.raises(KeyboardInterrupt):
        sw.run_sweep(cases, Interrupt(), store, executor="serial", progress=False)
    assert sorted(p.name for p in (store / "cases").iterdir()) == ["x=0.nc", "x=1.nc"]
    assert not (store / "sweep.nc").exists() and not _tmp_files(store)
    partial = sw.collect(store)
    assert list(partial.case_status.values) == ["ok", "ok", "missing", "missing"]
    func = Counting(str(tmp_path / "calls.log"))
    ds = sw.run_sweep(cases, func, store, executor="serial", progress=False)
    assert [c["x"] for c in func.calls()] == [2, 3]  # the finished cases did not run again
    assert list(ds.case_status.values) == ["ok"] * 4


def test_to_grid_reshapes_a_full_grid(tmp_path):
    func = Counting(str(tmp_path / "calls.log"))
    cases = sw.grid(x=[3, 1], z=["a", "b", "c"])
    ds = sw.run_sweep(cases, func, tmp_path / "s", executor="serial", progress=False)
    g = sw.to_grid(ds)
    assert dict(g.square.sizes) == {"x": 2, "z": 3}
    assert list(g.x.values) == [1, 3]
    assert g.square.sel(x=3, z="b").item() == 9.0
    assert g.case_id.sel(x=1, z="c").item() == "x=1,z=c"
    part = sw.run_sweep(cases[:5], func, tmp_path / "t", executor="serial", progress=False)
    with pytest.raises(sw.StudyError, match="not a full Cartesian grid"):
        sw.to_grid(part)


# --------------------------------------------------------------------------------------------
# model-file sweeps: executors, condensation cache, dynamics
# --------------------------------------------------------------------------------------------
OUTPUTS = ["first_slip", "equilibrium_lost", "status", "events", "max_un", "max_N"]


def test_serial_pool_and_dask_give_the_same_dataset(tmp_path):
    distributed = pytest.importorskip("distributed")
    study = sf.load_study(_study(tmp_path))
    assert [c.id for c in study.cases][0] == "friction=0.4,normal=10000.0"
    times = {}
    results = {}
    for name, executor in (("serial", "serial"), ("process", "process")):
        t0 = time.perf_counter()
        results[name] = sf.run_study(study, executor=executor, workers=2, progress=False,
                                     rerun=True)
        times[name] = time.perf_counter() - t0
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=None) as cluster:
        t0 = time.perf_counter()
        results["dask"] = sf.run_study(study, executor=cluster.scheduler_address,
                                       progress=False, rerun=True)
        times["dask"] = time.perf_counter() - t0
        # a Client of one's own: the case whose file is gone runs on the (warm) workers
        sw.case_path(study.store, study.cases[2]).unlink()
        with distributed.Client(cluster) as client:
            results["client"] = sf.run_study(study, executor=client, progress=False)
    print("sweep wall times (s):", {k: round(v, 2) for k, v in times.items()})
    ref = results["serial"]
    assert list(ref.case_status.values) == ["ok"] * 4
    for name, ds in results.items():
        assert ds.identical(ref), name
    # the closed form of the demo: sliding at λ = f W / p (to the mortar's round-off)
    g = sw.to_grid(ref)
    f = g["interfaces.joint.friction"]
    p = g["patterns.push.loads.0.normal"]
    np.testing.assert_allclose(g.equilibrium_lost, f * W / p, rtol=1e-6)
    assert set(ref.status.values) == {"equilibrium_lost"}


def test_cases_sharing_a_mesh_reuse_the_condensation(tmp_path):
    text = STUDY.replace('"patterns.push.loads.0.normal" = [1.0e4, 2.0e4]\n', "").replace(
        "[study]\n", '[study]\noutputs = ["equilibrium_lost", "factorizations"]\n')
    study = sf.load_study(_study(tmp_path, text=text))
    sf.clear_condensation_cache()
    ds = sf.run_study(study, executor="serial", progress=False)
    assert list(ds.factorizations.values) == [1, 0]  # the second case did not refactorise
    assert sf.condensation_cache_info() == {"hits": 1, "misses": 1, "size": 1}
    # another mesh is another condensation
    mesh = sw.cases_from_list([{"bodies.block.nx": 8}])
    ds = sw.run_sweep(mesh, study.func, tmp_path / "mesh", executor="serial", progress=False)
    assert list(ds.factorizations.values) == [1]
    assert sf.condensation_cache_info()["misses"] == 2
    sf.clear_condensation_cache()


def test_a_dynamic_model_file_sweep(tmp_path):
    from test_dynamics import DYN_FILE

    (tmp_path / "dyn.toml").write_text(DYN_FILE.replace("duration = 0.1", "duration = 0.01"))
    (tmp_path / "study.toml").write_text(
        '[study]\nmodel = "dyn.toml"\n[[cases]]\n"dynamics.loads.0.amplitude" = 0.5\n'
        '[[cases]]\nid = "strong"\n"dynamics.loads.0.amplitude" = 3.0\n')
    study = sf.load_study(tmp_path / "study.toml")
    assert study.store == tmp_path / "study"
    assert set(sf.DYNAMIC_OUTPUTS) <= set(study.func.outputs)
    ds = sf.run_study(study, executor="serial", progress=False)
    assert list(ds.case.values) == ["amplitude=0.5", "strong"]
    assert list(ds.case_status.values) == ["ok", "ok"]
    assert list(ds.dynamic_status.values) == ["completed", "completed"]
    assert (tmp_path / "study" / "results" / "strong-dynamic.nc").is_file()
    assert ds.attrs["grid"] == 1  # one parameter, two values: a (1-D) grid


# --------------------------------------------------------------------------------------------
# command line
# --------------------------------------------------------------------------------------------
runner = CliRunner()


def test_cli_sweep_runs_a_study_file(tmp_path):
    path = _study(tmp_path, results=True, text=STUDY.replace("[0.4, 0.6]", "[0.5]"))
    out = runner.invoke(app, ["sweep", str(path), "--serial"])
    assert out.exit_code == 0, out.output
    assert "sweep 'friction sweep': 2 cases, 0 failed" in out.output
    assert "equilibrium_lost" in out.output and "written:" in out.output
    store = tmp_path / "store"
    ds = xr.load_dataset(store / "sweep.nc", engine="h5netcdf")
    assert list(ds.case.values) == ["friction=0.5,normal=10000.0", "friction=0.5,normal=20000.0"]
    for cid in ds.case.values:
        assert (store / "results" / f"{cid}.nc").is_file()
    assert not _tmp_files(store)
    res = json.loads(runner.invoke(app, ["sweep", str(path), "--json", "--serial"]).stdout)
    assert res["status"] == "ok" and res["failed"] == 0
    assert res["cases"][1]["params"] == {"interfaces.joint.friction": 0.5,
                                         "patterns.push.loads.0.normal": 20000.0}
    assert res["cases"][1]["equilibrium_lost"] == pytest.approx(0.5 * W / 2e4, rel=1e-6)


@pytest.mark.parametrize(("change", "named"), [
    (('"interfaces.joint.friction"', '"interfaces.joint.frction"'),
     "parameter 'interfaces.joint.frction'"),
    (('"interfaces.joint.friction"', '"interfaces.jont.friction"'),
     "parameter 'interfaces.jont.friction': no entry 'jont' in interfaces"),
    (("[0.4, 0.6]", "[-0.4, 0.6]"), "parameter 'interfaces.joint.friction' = -0.4"),
    (('model = "demo.toml"', 'model = "nope.toml"'), "study.model: model file not found"),
    (("[grid]", "[gird]"), "gird: unknown field"),
    (('output = "store"', 'outputs = ["max_x"]'), "unknown output 'max_x'"),
])
def test_cli_sweep_bad_input_is_one_line_naming_the_key(tmp_path, change, named):
    path = _study(tmp_path, text=STUDY.replace(*change))
    out = runner.invoke(app, ["sweep", str(path), "--serial"])
    assert out.exit_code == EXIT_ERROR, out.output
    lines = out.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ")
    assert named in lines[0] and "Traceback" not in out.output
    assert not (tmp_path / "store").exists()


def test_cli_sweep_option_conflict(tmp_path):
    out = runner.invoke(app, ["sweep", str(_study(tmp_path)), "--serial", "--scheduler",
                              "tcp://127.0.0.1:1"])
    assert out.exit_code == EXIT_ERROR and "either --serial or --scheduler" in out.output
