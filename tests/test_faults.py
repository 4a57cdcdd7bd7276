"""Faults during a run: SIGTERM/SIGINT and kill -9, two runs writing one file, a full disk, a
killed sweep, a staged model swept, and the export of a dynamic result.

References: the global equilibrium of the pushed block of the demo model (a free body: the
joint's forces balance the loads, ΣN = −W and |ΣQ| = λ·H with W = ρ g A and H the push per
unit λ, by hand from the model file), the bytes of the file written before the fault, the
process table (psutil) for the workers of a killed sweep, and separate runs for a sweep.

Subprocess tests are bounded: every wait has a deadline and every process started is killed in
a ``finally``.
"""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import stepcontact as sc
from cli_checks import assert_one_line_error
from stepcontact import atomic
from stepcontact.cli import app
from stepcontact.io.atomic import OutputLockedError, WriteError, output_lock
from stepcontact.results.file import ResultWriter, save_result
from stepcontact.results.result import load_result

SRC = Path(sc.__file__).resolve().parents[1]
DATA = Path(__file__).resolve().parents[1] / "examples" / "data"
DEMO = (SRC / "stepcontact" / "data" / "demo.toml").read_text(encoding="utf-8")
#: the demo block pushed to and fro below sliding: more cycles than any test waits for (about
#: 50 s of run on an idle machine; every test stops it long before — with 400 cycles, 10 s, a
#: loaded machine could see the run end before the signal was sent)
CYCLIC = DEMO.replace('pattern = "push"\nend = 5.0',
                      'pattern = "push"\namplitude = 2.4\ncycles = 2000')
W = 2400 * 9.81 * 2.0 * 1.0  # N, the block's weight (ρ g A, A = 2 m × 1 m)
H = 1.0e4 * 1.0  # N per unit λ: the push, 10 kPa on the 1 m high left face
runner = CliRunner()


def _equilibrium_holds(res) -> None:
    """The block is a free body on the joint: ΣN = −W (compression negative) and
    |ΣQ| = |λ_push| H at every state, to 1e-9 of W (round-off of a few thousand terms)."""
    push = res.factors[:, list(res.pattern_names).index("push")]
    weight = res.factors[:, list(res.pattern_names).index("weight")]
    np.testing.assert_allclose(res.N.sum(axis=1), -weight * W, rtol=0, atol=1e-9 * W)
    np.testing.assert_allclose(np.abs(res.Q.sum(axis=1)), np.abs(push) * H, rtol=0,
                               atol=1e-9 * W)


# --------------------------------------------------------------------------------------------
# subprocesses
# --------------------------------------------------------------------------------------------
def _cli(*args: str, **kw) -> subprocess.Popen:
    """``stepcontact ARGS`` in a subprocess importing this source tree."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(SRC), *filter(None, [os.environ.get("PYTHONPATH")])]))
    code = "import sys; from stepcontact.cli import app; sys.argv[0] = 'stepcontact'; app()"
    return subprocess.Popen([sys.executable, "-c", code, *args], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


def _until(cond, timeout: float, what: str, step: float = 0.1):
    """Wait until ``cond()`` is truthy (its value), at most ``timeout`` seconds."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        v = cond()
        if v:
            return v
        time.sleep(step)
    pytest.fail(f"timed out after {timeout} s waiting for {what}")


def _kill(*procs) -> None:
    """Kill what still runs and close the pipes."""
    for p in procs:
        if p is None:
            continue
        if p.poll() is None:
            p.kill()
            p.wait(10)
        for stream in (p.stdout, p.stderr):
            if stream is not None:
                stream.close()


def _states_in(path: Path) -> int:
    """States of the result file at ``path`` (0: none yet or being replaced)."""
    try:
        return load_result(path).n_states
    except (OSError, ValueError, KeyError):
        return 0


@pytest.fixture
def cyclic(tmp_path) -> Path:
    f = tmp_path / "cyc.toml"
    f.write_text(CYCLIC, encoding="utf-8")
    return f


# --------------------------------------------------------------------------------------------
# 1. periodic writes, SIGTERM, kill -9
# --------------------------------------------------------------------------------------------
def test_write_interval_is_bounded_and_its_cost_a_share():
    """wait = max(min_interval, min(c (1 − s)/s, interval)): never longer than the interval,
    whatever a write costs; a share s of the time while writes are short."""
    w = ResultWriter("x.nc", min_interval=1.0, interval=10.0)
    s = w.max_share
    for cost, want in ((0.0, 1.0), (0.5, 0.5 * (1 - s) / s), (7.5, 10.0), (1e4, 10.0)):
        w._cost = cost
        assert w._wait() == pytest.approx(want, rel=1e-12)
    assert ResultWriter("x.nc", min_interval=30.0, interval=10.0)._wait() == 10.0
    assert ResultWriter("x.nc", interval=10.0)._wait() == 0.0  # min_interval 0: every time
    with pytest.raises(ValueError, match="interval"):
        ResultWriter("x.nc", interval=0.0)


def test_a_signal_during_a_write_waits_for_its_end(tmp_path):
    """SIGTERM under signals_interrupt is a Terminated (a KeyboardInterrupt, exit code 143);
    inside deferred() (a file being written) it is raised only when the block ends."""
    from stepcontact.io.interrupt import Terminated, deferred, signals_interrupt

    done = []
    before = signal.getsignal(signal.SIGTERM)
    with signals_interrupt(), pytest.raises(Terminated) as e:
        with deferred():
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.2)  # the handler has run by now (main thread, between bytecodes)
            done.append(1)
    assert done == [1] and e.value.name == "SIGTERM" and e.value.exit_code == 143
    assert isinstance(e.value, KeyboardInterrupt)
    with signals_interrupt(), pytest.raises(Terminated):  # outside a write: at once
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(5)
    assert signal.getsignal(signal.SIGTERM) == before  # restored


def test_write_interval_must_be_positive(tmp_path):
    f = tmp_path / "demo.toml"
    f.write_text(DEMO, encoding="utf-8")
    for bad in ("0", "-1", "nan"):
        r = runner.invoke(app, ["run", str(f), "--write-interval", bad, "-q"])
        assert_one_line_error(r, f"--write-interval {float(bad)}: give a positive number")
    assert not list(tmp_path.glob("*.nc*"))


@pytest.mark.slow
def test_a_long_segment_is_written_within_it(tmp_path):
    """One segment with many events (the demo block pushed to sliding): when a write is due
    (here after every second event) the file is written inside the segment, each write a whole
    file whose states hold equilibrium."""
    from stepcontact.io.modelfile import load_model

    f = tmp_path / "demo.toml"
    f.write_text(DEMO, encoding="utf-8")
    seen: list[int] = []

    class Spy(ResultWriter):
        asked = 0

        def checkpoint_due(self):
            self.asked += 1
            return self.asked % 2 == 0

        def checkpoint(self, result):
            super().checkpoint(result)
            back = load_result(self.path)
            assert back.status == sc.Status.INCOMPLETE
            _equilibrium_holds(back)
            assert back.segment[-1] == 1 and back.kind[-1] == "event"  # inside the push
            seen.append(back.n_states)

    out = tmp_path / "r.nc"
    w = Spy(out)
    res = sc.solve_static(load_model(f), output=w)
    assert len(seen) >= 3 and seen == sorted(seen)
    assert max(seen) < res.n_states
    assert w.writes > len(res.segments)
    assert load_result(out).status == res.status


@pytest.mark.slow
def test_sigterm_writes_the_states_finished(cyclic):
    out = cyclic.with_suffix(".nc")
    p = None
    try:
        p = _cli("run", str(cyclic), "--no-plot", "-q", "--write-interval", "0.5")
        first = _until(lambda: _states_in(out), 25, "the first write")
        _until(lambda: _states_in(out) > first, 10, "a second periodic write")
        p.send_signal(signal.SIGTERM)
        _, err = p.communicate(timeout=20)
    finally:
        _kill(p)
    assert p.returncode == 128 + signal.SIGTERM, err
    assert "Traceback" not in err
    assert "interrupted by SIGTERM" in err and str(out) in err and "incomplete" in err
    res = load_result(out)
    assert res.status == sc.Status.INCOMPLETE and res.message == "interrupted"
    assert res.n_states > first
    _equilibrium_holds(res)
    assert not atomic.lock_path(out).exists()


@pytest.mark.slow
def test_kill_9_keeps_the_last_periodic_write(cyclic):
    out = cyclic.with_suffix(".nc")
    p = None
    try:
        p = _cli("run", str(cyclic), "--no-plot", "-q", "--write-interval", "0.5")
        first = _until(lambda: _states_in(out), 25, "the first write")
        # the writes go on at the interval (not at a growing one)
        last = _until(lambda: (n := _states_in(out)) > first and n, 10, "a periodic write")
        p.send_signal(signal.SIGKILL)
        p.wait(10)
    finally:
        _kill(p)
    res = load_result(out)
    assert res.status == sc.Status.INCOMPLETE
    assert res.n_states >= last
    _equilibrium_holds(res)
    with output_lock(out):  # the dead run's lock went with it
        pass


# --------------------------------------------------------------------------------------------
# 2. one output, two runs
# --------------------------------------------------------------------------------------------
def test_output_lock_refuses_a_second_holder(tmp_path):
    out = tmp_path / "r.nc"
    with output_lock(out) as lock:
        assert lock.read_text().strip() == str(os.getpid())
        with pytest.raises(OutputLockedError, match=f"'{out}'.*process {os.getpid()}"):
            with output_lock(out):
                pass
    assert not lock.exists()
    with output_lock(out):  # free again
        pass


@pytest.mark.slow
def test_second_run_on_one_output_is_refused(cyclic):
    out = cyclic.with_suffix(".nc")
    first = second = None
    try:
        first = _cli("run", str(cyclic), "--no-plot", "-q", "--write-interval", "0.5")
        _until(lambda: _states_in(out), 25, "the first run's first write")
        t0 = time.monotonic()
        second = _cli("run", str(cyclic), "--no-plot", "-q")
        _, err = second.communicate(timeout=25)
        assert second.returncode == 2, err
        assert f"'{out}' is being written by another run (process {first.pid}" in err
        assert "Traceback" not in err
        assert time.monotonic() - t0 < 20  # refused at once (start-up of Python aside)
        assert first.poll() is None  # the first run goes on
        first.send_signal(signal.SIGTERM)
        first.communicate(timeout=20)
    finally:
        _kill(first, second)
    assert first.returncode == 128 + signal.SIGTERM
    _equilibrium_holds(load_result(out))


# --------------------------------------------------------------------------------------------
# 3. a full disk
# --------------------------------------------------------------------------------------------
def _disk_fills(monkeypatch, after: int = 0) -> list[int]:
    """Make file writes fail with ENOSPC half-way, after ``after`` good writes."""
    calls = [0]
    real = atomic._write_file

    def write(path, data):
        calls[0] += 1
        if calls[0] <= after:
            return real(path, data)
        Path(path).write_bytes(data[: len(data) // 2])
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))

    monkeypatch.setattr(atomic, "_write_file", write)
    return calls


@pytest.fixture(scope="module")
def demo_result(tmp_path_factory):
    from stepcontact.io.modelfile import load_model

    d = tmp_path_factory.mktemp("demo")
    (d / "demo.toml").write_text(DEMO, encoding="utf-8")
    return d / "demo.toml", sc.solve_static(load_model(d / "demo.toml"))


def test_full_disk_leaves_the_previous_result_intact(tmp_path, monkeypatch, demo_result):
    _, res = demo_result
    out = tmp_path / "r.nc"
    save_result(res, out)
    before = out.read_bytes()
    _disk_fills(monkeypatch)
    with pytest.raises(WriteError) as e:
        save_result(res, out)
    msg = str(e.value)
    assert f"'{out}'" in msg and "the device is full" in msg
    assert "the previous file 'r.nc' is intact" in msg
    assert out.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.nc"]  # no temporary file left
    np.testing.assert_array_equal(load_result(out).N, res.N)


def test_free_space_is_checked_before_writing(tmp_path, monkeypatch, demo_result):
    from collections import namedtuple

    _, res = demo_result
    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(atomic.shutil, "disk_usage", lambda p: usage(10**9, 10**9 - 1000, 1000))
    out = tmp_path / "r.nc"
    with pytest.raises(WriteError, match=r"not enough free space .* 1000 B|not enough free"):
        save_result(res, out)
    assert not list(tmp_path.iterdir())  # nothing written
    # the size asked for is the file's: it fits when that much is free
    size = len(atomic.netcdf_bytes(sc.results.file.result_to_dataset(res)))
    free = size + atomic.FREE_MARGIN_BYTES + int(atomic.FREE_MARGIN_SHARE * size) + 1
    monkeypatch.setattr(atomic.shutil, "disk_usage", lambda p: usage(10**12, 0, free))
    save_result(res, out)
    assert out.stat().st_size == size


def test_full_disk_in_run_is_one_line(tmp_path, monkeypatch, demo_result):
    model_file, _ = demo_result
    out = tmp_path / "r.nc"
    r = runner.invoke(app, ["run", str(model_file), "-o", str(out), "--no-plot", "-q"])
    assert r.exit_code == 0, r.output
    before = out.read_bytes()
    _disk_fills(monkeypatch)
    r = runner.invoke(app, ["run", str(model_file), "-o", str(out), "--no-plot", "-q"])
    assert_one_line_error(r, "the device is full")
    assert "the previous file 'r.nc' is intact" in r.stderr
    assert out.read_bytes() == before


def test_full_disk_in_export_is_one_line(tmp_path, monkeypatch, demo_result):
    from collections import namedtuple

    model_file, res = demo_result
    nc = tmp_path / "r.nc"
    save_result(res, nc)
    r = runner.invoke(app, ["export", str(nc), "--vtu", str(tmp_path / "v"), "--xdmf",
                            str(tmp_path / "x" / "r.xdmf"), "-m", str(model_file)])
    assert r.exit_code == 0, r.output
    files = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    # XDMF: its HDF5 file is made in memory, then written with plain I/O
    _disk_fills(monkeypatch)
    r = runner.invoke(app, ["export", str(nc), "--xdmf", str(tmp_path / "x" / "r.xdmf"),
                            "-m", str(model_file)])
    assert_one_line_error(r, "the device is full")
    assert f"XDMF export '{tmp_path / 'x' / 'r.xdmf'}'" in r.stderr
    # VTU: the free space for all frames is checked after the first one
    usage = namedtuple("usage", "total used free")
    first = min(p.stat().st_size for p in (tmp_path / "v" / "r").iterdir())
    monkeypatch.setattr(atomic.shutil, "disk_usage", lambda p: usage(10**9, 0, first))
    r = runner.invoke(app, ["export", str(nc), "--vtu", str(tmp_path / "v"), "-m",
                            str(model_file)])
    assert_one_line_error(r, "not enough free space")
    assert {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()} == files


def test_full_disk_in_sweep_is_one_line(tmp_path, monkeypatch, demo_result):
    model_file, _ = demo_result
    study = tmp_path / "s.toml"
    study.write_text(f'[study]\nmodel = "{model_file}"\noutput = "store"\n\n'
                     '[grid]\n"interfaces.joint.friction" = [0.5]\n', encoding="utf-8")
    _disk_fills(monkeypatch, after=1)  # the manifest, then nothing
    r = runner.invoke(app, ["sweep", str(study), "--serial", "-q"])
    assert_one_line_error(r, "the device is full")


# --------------------------------------------------------------------------------------------
# 4. a killed sweep takes its workers with it
# --------------------------------------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL], ids=["TERM", "KILL"])
def test_killed_sweep_leaves_no_worker(tmp_path, cyclic, sig):
    psutil = pytest.importorskip("psutil")
    study = tmp_path / "s.toml"
    study.write_text(f'[study]\nmodel = "{cyclic}"\noutput = "store"\n\n'
                     '[grid]\n"interfaces.joint.friction" = [0.5, 0.6, 0.7]\n',
                     encoding="utf-8")
    p = None
    workers: list = []
    try:
        p = _cli("sweep", str(study), "-w", "2", "-q")
        main = psutil.Process(p.pid)

        def started():
            kids = [c for c in main.children(recursive=True)
                    if "resource_tracker" not in " ".join(c.cmdline())]
            return kids if len(kids) >= 2 else None

        workers = _until(started, 40, "two pool workers")
        time.sleep(1.0)
        p.send_signal(sig)
        _, alive = psutil.wait_procs(workers, timeout=5)
        assert not alive, f"workers survive their parent: {[w.pid for w in alive]}"
        _, err = p.communicate(timeout=20)
        if sig == signal.SIGTERM:
            assert p.returncode == 128 + signal.SIGTERM, err
            assert "interrupted by SIGTERM: 0 of 3 cases are stored" in err
    finally:
        for w in workers:
            if w.is_running():
                w.kill()
        _kill(p)


# --------------------------------------------------------------------------------------------
# 5. a staged model swept
# --------------------------------------------------------------------------------------------
def test_staged_model_sweeps_as_separate_runs(tmp_path):
    """A sweep of the staged wall over the base's friction gives, case by case, the result
    of a separate run of the model file with that friction (the same events; forces equal to
    1e-9 of the largest: the sweep runs with BLAS on one thread)."""
    from stepcontact.io.modelfile import load_model

    base = (DATA / "staged_wall.toml").read_text(encoding="utf-8")
    (tmp_path / "wall.toml").write_text(base, encoding="utf-8")
    study = tmp_path / "s.toml"
    study.write_text('[study]\nmodel = "wall.toml"\noutput = "store"\n\n'
                     '[grid]\n"interfaces.base.friction" = [0.05, 0.7]\n', encoding="utf-8")
    r = runner.invoke(app, ["sweep", str(study), "--serial", "-q"])
    assert r.exit_code == 0, r.output
    for f in (0.05, 0.7):
        text = base.replace("friction = 0.7", f"friction = {f}", 1)
        assert text != base or f == 0.7
        (tmp_path / f"wall-{f}.toml").write_text(text, encoding="utf-8")
        ref = sc.solve_static(load_model(tmp_path / f"wall-{f}.toml"))
        got = load_result(tmp_path / "store" / "results" / f"friction={f}.nc")
        assert got.status == ref.status == sc.Status.COMPLETED
        assert [(e.cfe, e.transition) for e in got.events] == \
            [(e.cfe, e.transition) for e in ref.events]
        scale = np.abs(ref.N).max()
        np.testing.assert_allclose(got.N, ref.N, rtol=0, atol=1e-9 * scale)
        np.testing.assert_allclose(got.Q, ref.Q, rtol=0, atol=1e-9 * scale)


# --------------------------------------------------------------------------------------------
# 6. a dynamic result finds its model
# --------------------------------------------------------------------------------------------
def test_export_of_a_dynamic_result_finds_its_model(tmp_path):
    import meshio

    from test_dynamics import DYN_FILE

    f = tmp_path / "dyn.toml"
    f.write_text(DYN_FILE, encoding="utf-8")
    r = runner.invoke(app, ["run", str(f), "--no-plot", "-q"])
    assert r.exit_code == 0, r.output
    res = load_result(tmp_path / "dyn-dynamic.nc")
    # moved away from its model file: the path it records finds it
    moved = tmp_path / "elsewhere" / "shock.nc"
    moved.parent.mkdir()
    os.replace(tmp_path / "dyn-dynamic.nc", moved)
    r = runner.invoke(app, ["export", str(moved), "--vtu", str(tmp_path / "v"), "--json"])
    assert r.exit_code == 0, r.output
    assert f"{f}" in r.stdout  # the model file used
    frames = sorted((tmp_path / "v" / "shock").glob("shock_[0-9]*.vtu"))
    assert len(frames) == res.n_states
    # the exported displacements are the stored ones (exact), stresses recovered
    mesh = meshio.read(frames[-1])
    dof_of = np.asarray(res.geometry["dof_of"])
    u = res.u[-1]
    np.testing.assert_array_equal(mesh.point_data["displacement"][:, 0], u[dof_of[:, 0]])
    assert any("sigma" in k for k in mesh.cell_data)
    # a model file changed since the run is not used
    f.write_text(DYN_FILE.replace("E = 30e9", "E = 20e9"), encoding="utf-8")
    r = runner.invoke(app, ["export", str(moved), "--vtu", str(tmp_path / "v2")])
    assert_one_line_error(r, "the stresses of a dynamic result are recovered from its model")
    f.write_text(DYN_FILE, encoding="utf-8")  # as it was: found again
    r = runner.invoke(app, ["export", str(moved), "--vtu", str(tmp_path / "v2")])
    assert r.exit_code == 0, r.output


@pytest.mark.slow
def test_sigterm_in_the_dynamic_interval_writes_its_states_so_far(tmp_path):
    """SIGTERM while `run` integrates the model's dynamic interval: the step under way ends,
    the interval's states so far are written to MODEL-dynamic.nc (status incomplete, its last
    time before the end), the static result stays as written, exit 143 with one line naming
    both files.  The states written are solutions: the contact conditions hold to 1e-9 and
    the energy ledger balances to 1e-9 of the work (its own closed check)."""
    from test_dynamics import DYN_FILE

    f = tmp_path / "dyn.toml"  # the same block and pulse, integrated for 2 000 s of steps
    f.write_text(DYN_FILE.replace("duration = 0.1\n", "duration = 2000.0\nmax_steps = 3000000\n"),
                 encoding="utf-8")
    static, dyn = tmp_path / "dyn.nc", tmp_path / "dyn-dynamic.nc"
    p = None
    try:
        p = _cli("run", str(f), "--no-plot", "-q")
        _until(lambda: _states_in(static), 25, "the static result (the interval then starts)")
        time.sleep(1.5)
        p.send_signal(signal.SIGTERM)
        _, err = p.communicate(timeout=20)
    finally:
        _kill(p)
    assert p.returncode == 128 + signal.SIGTERM, err
    assert "Traceback" not in err
    assert "in the dynamic interval at t =" in err and str(dyn) in err and str(static) in err
    res = load_result(dyn)
    assert res.status == sc.Status.INCOMPLETE and "interrupted at t =" in res.message
    assert 0.0 < res.time[-1] < 2000.0 and res.n_states > 10
    assert res.violation.max() < 1e-9
    e = res.energy
    assert abs(e["error"]).max() <= 1e-9 * max(abs(e["external"]).max(), 1e-300)
    assert load_result(static).status == sc.Status.COMPLETED
