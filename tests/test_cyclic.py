"""Cyclic load programs: ``sc.cycles`` and the cyclic ``[[program]]`` entry, checked against
closed forms.

Reference: a rigid block of weight W pressed on a rigid base (friction f), tied to a fixed point
by a horizontal spring k and pushed by a horizontal force P (a discrete model: DOFs u_x, u_y;
the contact closed, N = −W).  Equilibrium k u = P − Q with |Q| ≤ f W: the block sticks while
|P − k u| < f W and slips when it reaches it.  Cycling P between ±P0 (P0 > f W) from rest:

* first slip at P = f W; at P0, u = u_max = (P0 − f W)/k;
* on unloading it sticks at once and slips back at P = P0 − 2 f W, to u = −u_max at −P0;
  on reloading it slips again at P = −P0 + 2 f W: the (P, u) loop is a parallelogram of
  corners (±P0, ±u_max), (±(P0 − 2 f W), ±u_max);
* its area, the work of P over a cycle, equals the energy dissipated by friction,
  f W × (the slip of a cycle, 4 u_max) = 4 f W (P0 − f W)/k, and it is the same loop at every
  cycle (no drift): checked after 100 cycles.

Unloading to zero keeps a residual displacement u_res = min(P0 − f W, f W)/k (it slips back only
when P0 > 2 f W) held by a locked-in friction force Q = −k u_res; reloading slips again at
P = k u_res + f W (the previous peak P0 when P0 ≤ 2 f W, earlier otherwise): path dependence.
All to round-off (rtol 1e-9).
"""

from __future__ import annotations

import importlib.util
import types
from pathlib import Path

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.io.modelfile import model_from_dict
from stepcontact.results import file as result_file

W, FRICTION, K = 1000.0, 0.3, 2.0e4  # N, -, N/m
FW = FRICTION * W
RTOL = 1e-9


def slider(*program: sc.Segment) -> sc.DiscreteModel:
    """The block on its spring: pattern 'press' (F_y = −1 N per unit λ), 'push' (F_x = +1 N);
    the program is prefixed by the press up to W."""
    return sc.DiscreteModel(
        K=[[K, 0.0], [0.0, K]], normal_rows=[[0.0, 1.0]], tangent_rows=[[1.0, 0.0]],
        loads={"press": {"uy": -1.0}, "push": {"ux": 1.0}}, friction=FRICTION,
        dof_names=("ux", "uy"), name="slider",
        program=(sc.Segment("press", W), *program))


def path(res: sc.StaticResult) -> tuple[np.ndarray, np.ndarray]:
    """(P, u_x) at every state."""
    push = list(res.pattern_names).index("push")
    return res.factors[:, push], res.displacements()[:, 0]


def cycle_states(res: sc.StaticResult, c: int) -> np.ndarray:
    """States of the loop of cycle c ≥ 2 (segments 2c − 1 to +P0 and 2c to −P0, after the
    press, segment 0): from the end of segment 2c − 2 (at −P0) to the end of segment 2c."""
    ends = np.flatnonzero(res.kind == "segment_end")  # ends[j]: the end of segment j
    return np.arange(ends[2 * c - 2], ends[2 * c] + 1)


def loop_area(P: np.ndarray, u: np.ndarray) -> float:
    """∮ P du over a closed path of straight pieces (exact: P and u are linear in between)."""
    return float(np.sum(0.5 * (P[1:] + P[:-1]) * np.diff(u)))


@pytest.fixture(scope="module")
def hundred_cycles() -> sc.StaticResult:
    P0 = 500.0
    res = sc.solve_static(slider(*sc.cycles("push", P0, 100)))
    assert res.status == sc.Status.COMPLETED
    return res


def test_slip_onset_loads_and_forces(hundred_cycles):
    """Every event of the 100 cycles at its closed-form load, with N = −W and |Q| = f W."""
    res, P0 = hundred_cycles, 500.0
    ev = res.events_table()
    assert (ev["segment"] >= 1).all()  # nothing happens under the press
    first = ev[ev["segment"] == 1]
    assert list(first["transition"]) == ["slip+"]
    assert first["lam"].iloc[0] == pytest.approx(FW, rel=RTOL)
    for seg in range(2, 201):
        rows = ev[ev["segment"] == seg]
        up = seg % 2 == 1  # odd segments push to +P0
        assert list(rows["transition"]) == ["stuck", "slip+" if up else "slip-"], seg
        peak = -P0 if up else P0  # where the segment starts: it sticks there at once
        onset = -P0 + 2 * FW if up else P0 - 2 * FW
        np.testing.assert_allclose(rows["lam"], [peak, onset], rtol=RTOL)
    np.testing.assert_allclose(ev["N"], -W, rtol=RTOL)
    np.testing.assert_allclose(ev["Q"].abs(), FW, rtol=RTOL)
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-9


def test_loop_corners_area_and_no_drift_after_100_cycles(hundred_cycles):
    """The (P, u) loop of cycles 2, 3 and 100 (the first starts from rest): the
    parallelogram's corners, area 4 f W (P0 − f W)/k = ∮ P du = ∮ Q du_τ (the energy
    dissipated by friction) to 1e-9."""
    res, P0 = hundred_cycles, 500.0
    u_max = (P0 - FW) / K
    area = 4 * FW * (P0 - FW) / K
    P, u = path(res)
    Q, ut = res.Q[:, 0], res.ut[:, 0]
    for c in (2, 3, 100):
        idx = cycle_states(res, c)
        Pc, uc = P[idx], u[idx]
        # corners: the peaks and the slip onsets, where the stuck branches end
        np.testing.assert_allclose(Pc[[0, -1]], -P0, rtol=RTOL)
        np.testing.assert_allclose(uc[[0, -1]], -u_max, rtol=RTOL)
        top = idx[np.isclose(Pc, P0, rtol=RTOL)]
        assert top.size
        np.testing.assert_allclose(u[top], u_max, rtol=RTOL)
        for onset, corner_u in ((P0 - 2 * FW, u_max), (-P0 + 2 * FW, -u_max)):
            at = idx[np.flatnonzero(np.isclose(Pc, onset, rtol=RTOL))]
            assert at.size
            np.testing.assert_allclose(u[at], corner_u, rtol=RTOL)
        # every state on the parallelogram: u = u_max·sign or (P ∓ f W)/k on the slip branches
        on_edge = (np.isclose(np.abs(uc), u_max, rtol=RTOL)
                   | np.isclose(uc, (Pc - FW) / K, rtol=RTOL, atol=1e-12 * u_max)
                   | np.isclose(uc, (Pc + FW) / K, rtol=RTOL, atol=1e-12 * u_max))
        assert on_edge.all()
        assert abs(loop_area(Pc, uc)) == pytest.approx(area, rel=RTOL)
        dissipated = float(np.sum(0.5 * (Q[idx][1:] + Q[idx][:-1]) * np.diff(ut[idx])))
        assert dissipated == pytest.approx(area, rel=RTOL)
        assert FW * np.abs(np.diff(ut[idx])).sum() == pytest.approx(area, rel=RTOL)
    # no drift: the last state is the end of cycle 100, at −P0 on the loop
    assert P[-1] == pytest.approx(-P0, rel=RTOL)
    assert u[-1] == pytest.approx(-u_max, rel=RTOL)


@pytest.mark.parametrize("P0", [500.0, 800.0])  # below and above 2 f W = 600 N
def test_unloading_to_zero_and_reloading(P0):
    """Push to P0, unload to 0, reload to P1 = 900 N: the residual displacement and locked-in
    friction force after unloading, the reloading's slip onset and the final displacement
    (the monotonic one: slip erases the memory), to 1e-9."""
    P1 = 900.0
    res = sc.solve_static(slider(sc.Segment("push", P0), sc.Segment("push", 0.0),
                                 sc.Segment("push", P1)))
    assert res.status == sc.Status.COMPLETED
    P, u = path(res)
    ends = np.flatnonzero(res.kind == "segment_end")
    u_res = min(P0 - FW, FW) / K
    i0 = ends[2]  # the end of the unloading
    assert P[i0] == pytest.approx(0.0, abs=1e-12 * P0)
    assert u[i0] == pytest.approx(u_res, rel=RTOL)
    assert res.Q[i0, 0] == pytest.approx(-K * u_res, rel=RTOL)
    ev = res.events_table()
    back = ev[(ev["segment"] == 2) & (ev["transition"] == "slip-")]
    if P0 <= 2 * FW:
        assert back.empty  # it sticks all the way back to zero
    else:
        np.testing.assert_allclose(back["lam"], [P0 - 2 * FW], rtol=RTOL)
    again = ev[(ev["segment"] == 3) & (ev["transition"] == "slip+")]
    np.testing.assert_allclose(again["lam"], [K * u_res + FW], rtol=RTOL)
    assert u[-1] == pytest.approx((P1 - FW) / K, rel=RTOL)


def test_elastic_block_shakes_down_to_a_repeating_cycle():
    """The example's elastic block on its base (9 CFEs, on the coarser base; f = 0.5) under push
    cycles of ±20 000 N (85 % of f W): partial slip from the heel and the toe; from the second
    cycle on every cycle repeats the same events at the same loads and the same corner
    displacements (no ratcheting), and the run stays in equilibrium (residual, violation ≤ 1e-9)."""
    spec = importlib.util.spec_from_file_location(
        "block_on_base", Path(__file__).resolve().parents[1] / "examples" / "block_on_base.py")
    assert spec is not None and spec.loader is not None
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    m = example.block_model()
    res = sc.solve_static(m.replace(program=(sc.Segment("weight", 1.0),
                                             *sc.cycles("push", 2.0e4, 3))))
    assert res.status == sc.Status.COMPLETED
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-9
    ev = res.events_table()

    def events(seg: int) -> tuple[list, np.ndarray]:
        rows = ev[ev["segment"] == seg]
        return list(zip(rows["cfe"], rows["transition"], strict=True)), rows["lam"].to_numpy()

    for a, b in ((3, 5), (4, 6)):  # cycle 2 = cycle 3, half-cycle by half-cycle
        (ka, la), (kb, lb) = events(a), events(b)
        assert ka == kb and len(ka) >= 6
        np.testing.assert_allclose(la, lb, rtol=RTOL)
    ux = res.node_history(point=(1.0, 2.0), body="block")
    ends = np.flatnonzero(res.kind == "segment_end")
    np.testing.assert_allclose(ux[ends[[3, 4]]], ux[ends[[5, 6]]], rtol=RTOL)


def test_helper_expands_to_half_cycles():
    segs = sc.cycles("push", 2.0, 3, mean=1.0, start=0.0)
    assert [s.end for s in segs] == [3.0, -1.0, 3.0, -1.0, 3.0, -1.0]
    assert segs[0].start == 0.0 and all(s.start is None for s in segs[1:])
    assert all(s.pattern == "push" and s.rates is None for s in segs)
    assert [s.end for s in sc.cycles("push", [1.0, 2.0, 3.0])] == [1, -1, 2, -2, 3, -3]
    assert [s.end for s in sc.cycles("push", -1.0, 1)] == [-1.0, 1.0]  # first half-cycle down
    both = sc.cycles("both", 1.0, 1, rates={"push": 2.0, "lift": 0.5})
    assert both[0].rates == (("push", 2.0), ("lift", 0.5))
    m = slider(sc.Segment("push", 5.0), *sc.cycles("push", 1.0, 2, mean=5.0))
    assert m.segments_resolved()[1:] == [("push", 0.0, 5.0), ("push", 5.0, 6.0),
                                         ("push", 6.0, 4.0), ("push", 4.0, 6.0),
                                         ("push", 6.0, 4.0)]


@pytest.mark.parametrize("kwargs, item, text", [
    ({"amplitude": 1.0}, r"cycles\('push'\)\.n", "number of cycles"),
    ({"amplitude": 1.0, "n": 0}, r"cycles\('push'\)\.n", "≥ 1"),
    ({"amplitude": 1.0, "n": 2.5}, r"cycles\('push'\)\.n", "whole number"),
    ({"amplitude": 1.0, "n": True}, r"cycles\('push'\)\.n", "whole number"),
    ({"amplitude": [1.0, 2.0], "n": 3}, r"cycles\('push'\)\.n", "2 amplitudes"),
    ({"amplitude": 0.0, "n": 1}, r"cycles\('push'\)\.amplitude", "nonzero"),
    ({"amplitude": [1.0, -2.0]}, r"cycles\('push'\)\.amplitude\[1\]", "one sign"),
    ({"amplitude": float("nan"), "n": 1}, r"cycles\('push'\)\.amplitude", "finite"),
    ({"amplitude": "big", "n": 1}, r"cycles\('push'\)\.amplitude", "number"),
    ({"amplitude": [], "n": None}, r"cycles\('push'\)\.amplitude", "empty"),
    ({"amplitude": 1.0, "n": 1, "mean": float("inf")}, r"cycles\('push'\)\.mean", "finite"),
])
def test_helper_bad_inputs_name_the_item(kwargs, item, text):
    with pytest.raises(sc.ModelError, match=item + ".*" + text):
        sc.cycles("push", **kwargs)


def test_cycles_that_do_not_chain_are_named():
    with pytest.raises(sc.ModelError, match=r"program segment 2.*start.*does not chain"):
        slider(sc.Segment("push", 1.0), *sc.cycles("push", 1.0, 1, start=0.0))
    with pytest.raises(sc.ModelError, match="cycles.pattern"):
        sc.cycles("", 1.0, 1)


def model_file(*program: dict) -> dict:
    """A block on a base in the model-file form: patterns 'w' (its weight) and 'push'."""
    from test_program import block_file

    return block_file({"type": "nodal", "fx": 1.0}, *program)


def test_model_file_cyclic_entry_expands_to_the_helper():
    """``[[program]] pattern = "push", amplitude = …, cycles = …`` is ``sc.cycles``; segments
    after it chain from where the cycles leave the pattern."""
    m = model_from_dict(model_file(
        {"pattern": "push", "amplitude": 2000.0, "cycles": 3, "mean": 500.0},
        {"pattern": "push", "amplitude": [100.0, 200.0]},
        {"pattern": "push", "end": 0.0, "start": -200.0}))
    want = (sc.Segment("w", 1.0), *sc.cycles("push", 2000.0, 3, mean=500.0),
            *sc.cycles("push", [100.0, 200.0]), sc.Segment("push", 0.0, -200.0))
    assert m.program == want
    assert len(m.segments_resolved()) == 12
    res = sc.solve_static(m)
    assert res.status == sc.Status.COMPLETED and len(res.multipliers) == 12


@pytest.mark.parametrize("entry, item, text", [
    ({"amplitude": 0.0, "cycles": 2}, r"program\[1\]\.amplitude", "nonzero"),
    ({"amplitude": [1.0, -1.0]}, r"program\[1\]\.amplitude\[1\]", "one sign"),
    ({"amplitude": 1.0}, r"program\[1\]\.cycles", "number of cycles"),
    ({"amplitude": [1.0, 2.0], "cycles": 3}, r"program\[1\]\.cycles", "2 amplitudes"),
    ({"amplitude": 1.0, "cycles": 0}, r"program\[1\]\.cycles", "greater than or equal to 1"),
    ({"amplitude": "big", "cycles": 1}, r"program\[1\]\.amplitude", "finite number"),
    ({"amplitude": [], "cycles": 1}, r"program\[1\]\.amplitude", "empty"),
    ({"amplitude": 1.0, "cycles": 2, "end": 1.0}, r"program\[1\]", "not both"),
    ({"cycles": 2}, r"program\[1\]", "cycles belongs to a cyclic entry"),
    ({}, r"program\[1\]", "give end"),
])
def test_model_file_bad_cyclic_entries_name_the_item(entry, item, text):
    with pytest.raises(sc.ModelError, match=item + ".*" + text):
        model_from_dict(model_file({"pattern": "push", **entry}))


def test_model_file_segments_after_cycles_must_chain():
    bad = model_file({"pattern": "push", "amplitude": 1.0, "cycles": 2},
                     {"pattern": "push", "end": 5.0, "start": 1.0})
    with pytest.raises(sc.ModelError, match=r"program\[2\]\.start.*stands at λ = -1"):
        model_from_dict(bad)


def test_program_resolved_once_per_model():
    """A hook that gets a result after every segment costs O(1) per segment for the program
    (it used to resolve the whole program each time: O(segments²) in all)."""
    m = slider(*sc.cycles("push", 1.0, 50))
    first = m.segments_resolved()
    first.append(("junk", 0.0, 0.0))  # the caller's list: the model's is not touched
    assert m.segments_resolved() == first[:-1]
    assert len(m.segments_resolved()) == 101


def test_result_writer_spends_a_bounded_share_writing(monkeypatch, tmp_path):
    """With min_interval > 0 the writer waits at least (1 − s)/s times its last write's
    duration (s = max_share): a write of 1 s and segments of 0.5 s give one write per 4 s."""
    clock = types.SimpleNamespace(now=0.0)
    monkeypatch.setattr(result_file, "time", types.SimpleNamespace(monotonic=lambda: clock.now))

    def slow_save(result, path):  # a write that takes 1 s
        clock.now += 1.0

    monkeypatch.setattr(result_file, "save_result", slow_save)
    partial = types.SimpleNamespace(status="incomplete")
    w = result_file.ResultWriter(tmp_path / "run.nc", min_interval=0.1)
    for _ in range(80):  # 80 segments of 0.5 s: 40 s of work
        clock.now += 0.5
        w.after_segment(partial)
    spent = w.writes * 1.0
    assert spent <= w.max_share * clock.now + 1.0
    assert w.writes >= 5
    w0 = result_file.ResultWriter(tmp_path / "every.nc")  # 0: every segment, as before
    for _ in range(3):
        w0.after_segment(partial)
    assert w0.writes == 3
