"""Results as plain data: picklable, written as the run goes (an interrupted run leaves a
readable file marked incomplete), fields recomputed exactly at states not stored, and one
condensation shared by runs that differ only in friction."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import stepcontact as sc
import verification_models as vm
from stepcontact.results.result import load_result


def test_result_pickles_without_the_factorisation():
    """pickle.dumps works (dask workers return results); the copy equals the original in its
    data; field recovery (which holds the factorisation) stays behind and says how to get it
    back, and recover_fields(model) gives the exact same field again."""
    model = vm.sliding_block(0.4, 10.0)
    res = sc.solve_static(model, store_fields="ends")
    missing = [i for i in range(res.n_states) if i not in res.fields]
    assert missing
    u_ref = res.displacement(missing[0])
    back = pickle.loads(pickle.dumps(res))
    for k in ("lam", "N", "Q", "un", "ut", "state", "residual", "reactions"):
        assert np.array_equal(getattr(back, k), getattr(res, k))
    assert back.events == res.events and back.status == res.status
    with pytest.raises(KeyError, match="recover_fields"):
        back.displacement(missing[0])
    back.recover_fields(model)
    assert np.allclose(back.displacement(missing[0]), u_ref, rtol=1e-10,
                       atol=1e-10 * np.abs(u_ref).max())


def test_fields_recomputed_exactly_at_states_not_stored():
    """A state without a stored field: the field from its contact unknowns equals the field a
    run storing every state computed (to round-off)."""
    model = vm.spring_held_block(0.5)
    a = sc.solve_static(model, store_fields="all")
    b = sc.solve_static(model, store_fields="ends")
    for i in range(a.n_states):
        ua = a.fields[i]
        assert np.allclose(b.displacement(i), ua, rtol=1e-9, atol=1e-9 * np.abs(ua).max())


class _Stop(Exception):
    pass


def test_interrupted_run_leaves_a_readable_incomplete_file(tmp_path):
    """The result file is written as the run goes: interrupted during its third segment, the
    file holds every state of the first two segments, status 'incomplete'; a finished run's
    file is complete and equals the returned result."""
    model = vm.random_frictional_model("stack", (0.3, 0.5), [(0.5, -1)] * 3, [(-0.7, -0.5)] * 3)
    path = tmp_path / "run.nc"
    full = sc.solve_static(model, output=path)
    done = load_result(path)
    assert done.status == full.status and np.array_equal(done.lam, full.lam)
    assert done.to_dataset().attrs["complete"] == 1

    class Interrupt:
        segments = 0

        def after_segment(self, result):
            self.segments += 1
            if self.segments == 2:
                raise KeyboardInterrupt

    path2 = tmp_path / "cut.nc"
    with pytest.raises(KeyboardInterrupt):
        sc.solve_static(model, output=path2, hooks=(Interrupt(),))
    cut = load_result(path2)
    assert cut.status == sc.Status.INCOMPLETE
    assert cut.to_dataset().attrs["complete"] == 0
    n = cut.n_states
    assert set(cut.segment) <= {0, 1}
    assert np.array_equal(cut.lam, full.lam[:n]) and np.array_equal(cut.N, full.N[:n])


def test_one_condensation_serves_a_friction_sweep():
    """Runs that differ only in friction share one factorisation (no new one per run) and give
    exactly the paths of independent runs; a condensation of another model is refused."""
    model = vm.sliding_block(0.4, 10.0)
    c = sc.condense(model)
    for f in (0.2, 0.4, 0.7):
        a = sc.solve_static(model.with_friction(f), condensation=c)
        b = sc.solve_static(model.with_friction(f))
        assert a.counters["factorizations"] == 0 and b.counters["factorizations"] == 1
        assert a.status == b.status == sc.Status.EQUILIBRIUM_LOST
        assert np.array_equal(a.lam, b.lam) and np.array_equal(a.N, b.N)
    other = vm.spring_held_block(0.5)
    with pytest.raises(sc.ModelError, match="condensation: was built for another model"):
        sc.solve_static(other, condensation=c)
    with pytest.raises(sc.ModelError, match="interface 'nope'"):
        model.with_friction(0.3, "nope")


def test_segments_do_not_rebuild_the_recorded_states():
    """A cyclic program of 200 segments: the recorded arrays grow in place (the result taken
    at a segment end shares memory with the recorder, no copy per segment)."""
    model = vm.sliding_block(0.4, 10.0)
    pats = [p.name for p in model.patterns]
    prog = [sc.Segment(pats[0], 1.0)] + [sc.Segment(pats[1], 0.5 * (k % 2)) for k in range(200)]
    model = model.replace(program=tuple(prog))
    seen = []

    class Watch:
        def after_segment(self, result):
            seen.append(result.lam)

    res = sc.solve_static(model, hooks=(Watch(),), store_fields="ends")
    assert res.status == sc.Status.COMPLETED and len(seen) == 201
    # views into buffers that double when full: a handful of buffers for ~400 states
    buffers = {id(s.base) for s in seen}
    assert all(s.base is not None for s in seen)
    assert len(buffers) <= 2 + int(np.log2(res.n_states))
