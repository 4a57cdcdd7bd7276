"""The large-interface path: dense contact matrices in float32 (``precision="float32"``),
every scheme solve refined to float64 accuracy against the sparse factorisation.

* the exact scheme operator (:func:`scheme_apply` and its transpose) equals the dense scheme
  matrix, and the shifted float32 form M = D G − I gives the same rows as G (in float64);
* over random schemes (open, stuck, slipping, compliant) the refined float32 rates equal the
  float64 rates to 1e-10 relative, and the same schemes are mechanisms;
* every example's run and the slab benchmark model reproduce, in float32, the recorded event
  sequences of ``test_event_sequences`` (same tolerance);
* ``auto`` takes float32 only when float64 does not fit; too large for both is a SolverError
  with the estimate; a refinement that cannot converge is a SolverError, never an inaccurate
  rate; the CLI's ``--precision``.
"""

from __future__ import annotations

import dataclasses
import runpy

import numpy as np
import pytest

import stepcontact as sc
import test_event_sequences as seq
import verification_models as vm
from stepcontact.contact.laws import OPEN, STICK, CoulombLaw
from stepcontact.errors import ModelError, SolverError
from stepcontact.fem.assembly import assemble
from stepcontact.solver.condensation import Condensed, dense_memory, dense_precision
from stepcontact.solver.engine import EventEngine
from stepcontact.solver.schemes import (
    MechanismError,
    SchemeSolver,
    scheme_apply,
    scheme_apply_t,
    scheme_rows,
)


def _compliant_stack():
    mdl = vm.random_frictional_model("stack", (0.4, 0.6), [(0, -1)] * 3, [(0, -1)] * 3)
    itf = mdl.interfaces[0]
    return mdl.replace(interfaces=(dataclasses.replace(
        itf, layer=sc.ContactLayer(E=1e8, nu=0.3, thickness=0.01)),) + mdl.interfaces[1:])


#: relative agreement of float32 and float64 rates: round-off of the float64 rates themselves
#: (the slender frame on stiff supports carries 1e-9 of it: its residual, see
#: test_event_sequences)
RATE_TOL = {"stack": 1e-10, "compliant": 1e-10, "frame": 1e-7}

MODELS = {"stack": lambda: vm.random_frictional_model("stack", (0.4, 0.6), [(0, -1)] * 3,
                                                       [(0, -1)] * 3),
          "compliant": _compliant_stack,
          "frame": vm.beam_on_supports}


def _engines(model):
    system = assemble(model)
    c64 = Condensed.from_system(system, precision="float64")
    c32 = Condensed.from_system(system, precision="float32")
    cfe = system.cfe
    out = []
    for c in (c64, c32):
        law = CoulombLaw(np.arange(cfe.m), cfe.friction, cfe.kn, cfe.kt)
        out.append(EventEngine(SchemeSolver(c.G, c.d, product=c.product, max_rank=3), [law],
                               system.w0))
    return out, c64, c32


@pytest.mark.parametrize("model", sorted(MODELS))
def test_exact_operator_and_shifted_rows(model):
    """A t and Aᵀ y from G t equal the dense scheme matrix's products, and the rows of the
    shifted form D G − I equal those of G, to 1e-12 relative, over random schemes."""
    (eng, _), c64, _ = _engines(MODELS[model]())
    G, d = c64.G, c64.d
    n = G.shape[0]
    M = d[:, None] * G - np.eye(n)
    rng = np.random.default_rng(7)
    for _ in range(10):
        rel = eng.relations(vm.random_states(rng, n // 2), article=False)
        A, scale = scheme_rows(G, d, rel, np.arange(n))
        As, scale_s = scheme_rows(M, d, rel, np.arange(n), shifted=True)
        assert np.allclose(As, A, rtol=0, atol=1e-12)
        assert np.allclose(scale_s, scale, rtol=1e-12)
        T = rng.standard_normal((n, 3))
        ref = A @ T
        got = scheme_apply(d, rel, scale, T, G @ T)
        assert np.abs(got - ref).max() <= 1e-12 * np.abs(ref).max()
        got1 = scheme_apply(d, rel, scale, T[:, 0], G @ T[:, 0])
        assert np.abs(got1 - ref[:, 0]).max() <= 1e-12 * np.abs(ref).max()
        refT = A.T @ T
        gotT = scheme_apply_t(d, rel, scale, T, lambda X: G @ X)
        assert np.abs(gotT - refT).max() <= 1e-12 * np.abs(refT).max()


@pytest.mark.parametrize("model", sorted(MODELS))
def test_refined_float32_rates_equal_float64(model):
    """40 random schemes in a row with Woodbury updates and refactorisations (max_rank 3):
    float32 schemes, refined, give the float64 rates to RATE_TOL relative; a scheme is a
    mechanism in float32 exactly when it is in float64."""
    (e64, e32), c64, c32 = _engines(MODELS[model]())
    assert c32.G.dtype == np.float32 and c64.G.dtype == np.float64
    m = e64.m
    rng = np.random.default_rng(11)
    h, e = vm.first_forcing(c64)
    checked = singular = 0
    for states, r in vm.random_scheme_cases(rng, m):
        out = []
        for eng in (e64, e32):
            try:
                out.append((eng.rates(states, (h, e), r), eng.rates(states, (h, e))))
            except MechanismError:
                out.append(None)
        assert (out[0] is None) == (out[1] is None), states
        if out[0] is None:
            singular += 1
            continue
        for (a, b) in zip(out[0], out[1], strict=True):
            for x, y in zip(a, b, strict=True):
                assert np.abs(y - x).max() <= RATE_TOL[model] * max(np.abs(x).max(), 1e-300)
        checked += 1
    assert checked >= 10
    assert e32.schemes.counters["refinements"] > 0


# ---- the recorded event sequences, in float32 -------------------------------------------------
#: runs whose last event point lies at a mechanism (the whole body starts to slide): CFEs
#: turn between the faceted cone's facets there, on a scheme that is nearly singular, so the
#: float32 scheme's refinement locates them to about cond × 6e-8 of the operator's scale
#: (measured 2.5e-11 relative) — λ to 1e-9 relative; the order and the states of every event
#: must still be the recorded ones, except the facet turns at the mechanism's point itself
#: (which slipping CFEs turn before the body slides is round-off's choice there: a relative
#: perturbation of 3e-16 of K's entries adds these four turns on the code before the 3D
#: stiffness kernels, which changed K's round-off)
NEAR_MECHANISM = {"dam_monolith_3d#0": 1e-9}
_FLOAT32_RUNS: dict[str, list[dict]] = {}


def _float32_calls(stem: str, tmp_path_factory) -> list[dict]:
    """The example's solve_static calls in float32, run once per session per example (each
    of its calls is one test; the script runs once for all of them)."""
    if stem in _FLOAT32_RUNS:
        return _FLOAT32_RUNS[stem]
    original = sc.solve_static

    def f32(model, *args, **kwargs):
        kwargs.setdefault("precision", "float32")
        return original(model, *args, **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(sc, "solve_static", f32)
        calls = seq.run_example(seq.EXAMPLES_DIR / f"{stem}.py",
                                tmp_path_factory.mktemp(stem + "-f32"))
    _FLOAT32_RUNS[stem] = calls
    return calls


def _example_runs():
    for name in seq.REFERENCE:
        stem, _, which = name.partition("#")
        if stem != seq.BENCHMARK.stem:
            yield pytest.param(stem, int(which), id=name)


@pytest.mark.parametrize(("stem", "index"), list(_example_runs()))
def test_examples_in_float32_reproduce_recorded_sequences(stem, index, tmp_path_factory):
    """Each example run with precision="float32" (runs given a float64 condensation keep it)
    has the recorded status, events and λ (to 1e-12, or 100× the run's residual; the runs of
    :data:`NEAR_MECHANISM` to their stated tolerance)."""
    calls = _float32_calls(stem, tmp_path_factory)
    res = calls[index]["result"]
    name = f"{stem}#{index}"
    seq.compare(name, seq.REFERENCE[name], res, floor=NEAR_MECHANISM.get(name, seq.REL),
                last_turns=name not in NEAR_MECHANISM)
    if "condensation" not in calls[index]["kwargs"]:
        assert res.counters["precision_bits"] == 32


def test_slab_benchmark_in_float32_reproduces_recorded_sequence():
    """The slab benchmark model (k = 1, 151 CFEs) in float32: the recorded event sequence,
    residual and violation at round-off."""
    slab = runpy.run_path(str(seq.BENCHMARK), run_name="slab_on_foundation")["slab_model"]
    res = sc.solve_static(slab(1), store_fields="ends", precision="float32")
    seq.compare(seq.benchmark_name(1), seq.REFERENCE[seq.benchmark_name(1)], res)
    assert res.counters["precision_bits"] == 32
    assert res.residual.max() < 1e-11 and res.violation.max() < 1e-12


# ---- choice of precision and errors -----------------------------------------------------------
def test_precision_choice_and_memory_errors():
    n2m = 2000
    need64 = dense_memory(n2m)["G"] + dense_memory(n2m)["schemes"]
    need32 = dense_memory(n2m, itemsize=4)["G"] + dense_memory(n2m, itemsize=4)["schemes"]
    assert need32 * 2 == need64
    assert dense_precision(n2m, "auto", need64) == np.float64
    assert dense_precision(n2m, "auto", 0.75 * need64) == np.float32
    assert dense_precision(n2m, "float32", need64) == np.float32
    with pytest.raises(SolverError, match=r"1000 CFEs .* float64"):
        dense_precision(n2m, "float64", 0.75 * need64)
    with pytest.raises(SolverError, match=r"1000 CFEs .* float32"):
        dense_precision(n2m, "auto", 0.75 * need32)
    with pytest.raises(ModelError, match="precision"):
        dense_precision(n2m, "float16")
    with pytest.raises(ModelError, match="precision"):
        sc.solve_static(vm.pushed_block(), precision="double")


def test_refinement_that_cannot_converge_is_an_error():
    """A float32 scheme refined against an operator it does not approximate (G of another
    structure) raises a SolverError naming the precision, instead of returning a rate."""
    system = assemble(vm.pushed_block())
    c32 = Condensed.from_system(system, precision="float32")
    schemes = SchemeSolver(c32.G, c32.d, product=lambda t: 3.0 * c32.product(t))
    law = CoulombLaw(np.arange(system.cfe.m), system.cfe.friction, system.cfe.kn,
                     system.cfe.kt)
    eng = EventEngine(schemes, [law], system.w0)
    name = next(iter(c32.hhat))
    with pytest.raises(SolverError, match="float32"):
        eng.rates(np.full(eng.m, STICK), (c32.hhat[name], c32.e[name]))


def test_cli_precision_option(tmp_path):
    """``stepcontact run --precision float32`` solves in float32 (counters in the JSON
    summary) with the float64 run's events; an unknown precision is refused by name."""
    import json
    from importlib.resources import files

    from typer.testing import CliRunner

    from stepcontact.cli import app

    demo = files("stepcontact") / "data" / "demo.toml"
    runner = CliRunner()
    summaries = {}
    for p in ("float64", "float32"):
        out = runner.invoke(app, ["run", str(demo), "-o", str(tmp_path / f"{p}.nc"),
                                  "--no-plot", "--json", "--quiet", "--precision", p])
        assert out.exit_code == 0, out.output
        summaries[p] = json.loads(out.stdout)
    assert summaries["float32"]["counters"]["precision_bits"] == 32
    assert summaries["float64"]["counters"]["precision_bits"] == 64
    for key in ("status", "events", "transitions"):
        assert summaries["float32"][key] == summaries["float64"][key]
    bad = runner.invoke(app, ["run", str(demo), "--precision", "half"])
    assert bad.exit_code != 0 and "half" in bad.output


def _spd(n: int, spectrum: np.ndarray, seed: int = 5) -> np.ndarray:
    Q = np.linalg.qr(np.random.default_rng(seed).standard_normal((n, n)))[0]
    return (Q * spectrum) @ Q.T


@pytest.mark.parametrize("smallest", [3e-6, 0.0])
def test_float32_mechanism_decided_by_the_exact_operator(smallest):
    """All-stuck schemes of G with eigenvalues from 1 down to ``smallest``: at 3e-6 the float32
    LU's rcond is below RCOND_MECHANISM_F32 but the exact operator is regular, so the scheme
    is used and its refined rates equal a float64 dense solve to 1e-9; a zero eigenvalue (a
    true mechanism) is a MechanismError in float32 as in float64."""
    from stepcontact.contact.laws import FIXED, Relations
    from stepcontact.solver.schemes import RCOND_MECHANISM_F32, lu, rcond, scheme_rhs

    n = 40
    spectrum = np.geomspace(1.0, max(smallest, 1e-300), n)
    if smallest == 0.0:
        spectrum[-1] = 0.0
    G = _spd(n, spectrum)
    d = np.ones(n)
    M32 = (d[:, None] * G - np.eye(n)).astype(np.float32)
    rel = Relations.from_kinds(np.full(n, FIXED, np.int8), np.zeros(n), np.zeros(n))
    s32 = SchemeSolver(M32, d, product=lambda t: G @ t)
    A32, _ = scheme_rows(M32, d, rel, np.arange(n), shifted=True)
    if smallest == 0.0:
        with pytest.raises(MechanismError):
            SchemeSolver(G, d).factor(rel)
        with pytest.raises(MechanismError):
            s32.factor(rel)
        return
    assert rcond(lu(A32), A32) <= RCOND_MECHANISM_F32  # float32 alone would say mechanism
    fac = s32.factor(rel)
    rng = np.random.default_rng(2)
    h, e, r = rng.standard_normal((3, n))
    ds, dw = fac.solve(h, e, r)
    A, scale = scheme_rows(G, d, rel, np.arange(n))
    t = np.linalg.solve(A, scale * scheme_rhs(d, rel, h, e, r))
    w_hat = h - G @ t
    assert np.abs(ds - (t + d * w_hat)).max() <= 1e-9 * np.abs(t).max()
    assert np.abs(dw - (w_hat + e)).max() <= 1e-9 * np.abs(w_hat + e).max()


def test_update_that_does_not_refine_is_refactorised(monkeypatch):
    """A float32 low-rank update whose solve does not refine is replaced by a full
    factorisation of its scheme (in the cache too), with the same rates as float64."""
    from stepcontact.solver import schemes as sch

    (e64, e32), c64, _ = _engines(MODELS["stack"]())
    m = e64.m
    name = next(iter(c64.hhat))
    forcing = (c64.hhat[name], c64.e[name])
    base = np.full(m, STICK)
    e32.rates(base, forcing)  # the base scheme
    states = base.copy()
    states[0] = OPEN
    original = sch.SchemeFactor._refine
    failed = []

    def refine_once(self, bs, y, floor=0.0):
        if self.V is not None and not failed:
            failed.append(True)
            raise sch._NotRefined
        return original(self, bs, y, floor)

    monkeypatch.setattr(sch.SchemeFactor, "_refine", refine_once)
    before = e32.schemes.counters["scheme_factorizations"]
    ds, dw = e32.rates(states, forcing)
    assert failed and e32.schemes.counters["scheme_factorizations"] == before + 1
    fac = e32.schemes.factor(e32.relations(states, article=False))
    assert fac.V is None  # the cache holds the full factorisation now
    ds64, dw64 = e64.rates(states, forcing)
    assert np.abs(ds - ds64).max() <= 1e-10 * np.abs(ds64).max()
    assert np.abs(dw - dw64).max() <= 1e-10 * np.abs(dw64).max()
