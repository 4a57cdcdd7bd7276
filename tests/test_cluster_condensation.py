"""The condensed matrix G = B K₀⁻¹ Bᵀ formed on a dask.distributed cluster
(:mod:`stepcontact.solver.cluster`) against the serial G of the same model.

The reference is always the serial path of this process (``sc.condense`` or
``Condensation.build`` without a scheduler), which may take another route (the Schur block of
the factors) and another ordering than the workers' blocked solves: the two agree to round-off.
Tolerances:

* float64: max |G_cluster − G_serial| ≤ 1e-12 · max |G_serial| (measured: ≤ 2e-15);
* float32 (D G − I): both are roundings to float32 of the same float64 numbers (equal to
  round-off), so elementwise |a − b| ≤ one float32 spacing of max(|a|, |b|) + 1e-12 · max |b|;
* a run: the same events, their load factors λ equal to 1e-12 relative.

The cluster is a LocalCluster of 2 workers with threads (``processes=False``: seconds to start;
the workers' factor caches are then visible to the test) and one test on a cluster of 2
processes (each worker pickles A and B, factorises in its own process).
"""

from __future__ import annotations

import json

import dask
import distributed
import numpy as np
import pytest
from typer.testing import CliRunner

import stepcontact as sc
from cli_checks import assert_one_line_error
from stepcontact.cli import app
from stepcontact.errors import ModelError, SolverError
from stepcontact.fem.assembly import assemble
from stepcontact.solver import cluster
from stepcontact.solver.condensation import Condensation, static_operator

#: relative agreement of the cluster's and the serial G (float64): round-off
G_RTOL = 1e-12


@pytest.fixture(scope="module")
def client():
    with (distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                   dashboard_address=":0") as lc,
          distributed.Client(lc, set_as_default=False) as c):
        yield c


def block_on_base(n: int = 24) -> sc.Model:
    """A concrete block (2 m × 0.5 m, n cells along the joint) on a rock base (3 m × 1 m,
    n + 6 cells): node-to-segment CFEs; weight, then a push on the left face until it slides."""
    concrete = sc.Material(E=30e9, nu=0.2, density=2400)
    rock = sc.Material(E=10e9, nu=0.25, density=2600)
    block = sc.rectangle("block", (0.5, 0.0), (2.5, 0.5), n, 3, concrete)
    base = sc.rectangle("base", (0.0, -1.0), (3.0, 0.0), n + 6, 4, rock)
    m = sc.Model(bodies=[base, block], plane="strain", thickness=1.0, name="block-on-base")
    return m.add(
        sc.Support("bed", m.select("base", y=-1.0), "xy"),
        sc.Interface("joint", plus=m.select("block", y=0.0), minus=m.select("base", y=0.0),
                     friction=0.6),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
        sc.LoadPattern("push", [sc.EdgeLoad(m.select("block", x=0.5), normal=1.0e4)]),
        sc.Segment("weight", 1.0),
        sc.Segment("push", 5.0),
    )


@pytest.fixture(scope="module")
def system():
    return assemble(block_on_base())


def _close32(a: np.ndarray, b: np.ndarray) -> bool:
    """float32 arrays equal to their rounding: |a − b| ≤ spacing(max(|a|, |b|)) + 1e-12 max|b|."""
    a64, b64 = a.astype(np.float64), b.astype(np.float64)
    big = np.maximum(np.abs(a), np.abs(b)).astype(np.float32)
    tol = np.spacing(big).astype(np.float64) + 1e-12 * np.abs(b64).max()
    return bool(np.all(np.abs(a64 - b64) <= tol))


def test_condense_on_cluster_equals_serial_float64(client, system):
    """sc.condense(system, scheduler=client): G equal to the serial G to G_RTOL; K₀ factorised
    once here and once on each worker that solved a block; the workers' factors dropped."""
    serial = sc.condense(system)
    dist = sc.condense(system, scheduler=client)
    assert dist.G.dtype == np.float64 and dist.G.shape == serial.G.shape
    err = np.abs(dist.G - serial.G).max() / np.abs(serial.G).max()
    assert err <= G_RTOL, err
    assert np.array_equal(dist.G, dist.G.T)  # symmetrised like the serial G
    k = dist.counters
    assert k["factorizations"] == 1 and k["condensed_columns"] == serial.G.shape[0]
    assert k["cluster_workers"] == 2
    assert 1 <= k["cluster_factorizations"] == k["cluster_workers_used"] <= 2
    assert dist.fingerprint == serial.fingerprint
    assert not cluster._FACTORS  # nothing left on the workers


def test_condense_on_cluster_equals_serial_float32(client, system):
    """precision="float32": the shifted D G − I in float32, equal to the serial float32 one
    and to the float64 G shifted and rounded (to one float32 spacing, module docstring)."""
    K0, Bf, d, *_ = static_operator(system)
    serial = sc.condense(system, precision="float32")
    dist = sc.condense(system, precision="float32", scheduler=client)
    assert dist.G.dtype == np.float32 and dist.precision == "float32"
    assert np.array_equal(dist.d, serial.d)
    assert _close32(dist.G, serial.G)
    G64 = sc.condense(system, precision="float64").G
    shifted = (d[:, None] * G64 - np.eye(len(d))).astype(np.float32)
    assert _close32(dist.G, shifted)


@pytest.mark.parametrize(("backend", "n"), [("scipy", 24), ("dense", 8)])
def test_build_in_many_blocks(client, backend, n):
    """Condensation.build(K₀, B_f, block=8, scheduler=client): many blocks per worker, still
    one factorisation per worker; the same G as the serial build with the same backend."""
    K0, Bf, *_ = static_operator(assemble(block_on_base(n)))
    serial = Condensation.build(K0, Bf, backend)
    dist = Condensation.build(K0, Bf, backend, block=8, scheduler=client)
    err = np.abs(dist.G - serial.G).max() / np.abs(serial.G).max()
    assert err <= G_RTOL, err
    k = dist.counters
    assert k["cluster_blocks"] == len(cluster.blocks(Bf.shape[0], 2, 8))
    assert k["cluster_blocks"] >= Bf.shape[0] / 8 and k["cluster_blocks"] > 2
    assert k["cluster_factorizations"] == k["cluster_workers_used"] <= 2  # one per worker
    assert dist.factor.name == serial.factor.name
    assert not cluster._FACTORS


def test_blocks_cover_the_columns_evenly():
    """Column blocks: contiguous, covering 0..2m, a multiple of the workers, widths ±1."""
    for n2m, workers, block in [(1, 2, 256), (7, 2, 3), (602, 2, 256), (1204, 3, 100)]:
        b = cluster.blocks(n2m, workers, block)
        assert b[0][0] == 0 and b[-1][1] == n2m
        assert all(b[i][1] == b[i + 1][0] for i in range(len(b) - 1))
        widths = [e - s for s, e in b]
        assert max(widths) <= block and max(widths) - min(widths) <= 1
        assert len(b) % workers == 0 or len(b) == n2m
    assert cluster.blocks(0, 2) == []


def test_solve_static_on_cluster_same_events(client):
    """A run whose G is formed on the cluster: the same events (kind, CFE) at the same λ
    (1e-12 relative) as the serial run."""
    model = block_on_base(12)
    ref = sc.solve_static(model)
    res = sc.solve_static(model, scheduler=client)
    assert res.status == ref.status
    assert ([(e.transition, e.cfe) for e in res.events]
            == [(e.transition, e.cfe) for e in ref.events])
    lam, lam_ref = (np.array([e.lam for e in r.events]) for r in (res, ref))
    assert len(lam) > 3
    assert np.allclose(lam, lam_ref, rtol=1e-12, atol=0.0)
    assert res.counters["condensed_columns"] == 2 * res.counters["cfes"]


def test_bad_scheduler_is_named():
    """An address that is none is a ModelError naming ``scheduler``; a scheduler that does not
    answer (a closed port, connect timeout 1 s) a SolverError naming the address."""
    system = assemble(block_on_base(4))
    with pytest.raises(ModelError, match="scheduler: give a dask scheduler's address"):
        sc.condense(system, scheduler="nowhere")
    with pytest.raises(ModelError, match="scheduler"):
        sc.condense(system, scheduler=42)
    with (dask.config.set({"distributed.comm.timeouts.connect": "1s"}),
          pytest.raises(SolverError, match=r"scheduler 'tcp://127\.0\.0\.1:9': cannot connect")):
        sc.condense(system, scheduler="tcp://127.0.0.1:9")


def test_cli_run_scheduler(client, tmp_path):
    """``stepcontact run demo.toml --scheduler ADDRESS`` (the demo on coarser meshes): the
    run's JSON summary (events, transitions, every load multiplier to 1e-12 relative) equals
    the serial run's; a bad address is one line ``error: scheduler: …`` with exit code 2."""
    from stepcontact.demo import demo_text

    runner = CliRunner()
    path = tmp_path / "demo.toml"
    text = demo_text("slide")
    coarse = text.replace("nx = 18\nny = 6", "nx = 6\nny = 2").replace("nx = 10\nny = 5",
                                                                        "nx = 4\nny = 2")
    assert coarse.count("ny = 2") == 2  # (the demo, coarser: a faster run)
    path.write_text(coarse, encoding="utf-8")
    args = ["run", str(path), "--json", "--quiet", "--no-plot"]
    ref = runner.invoke(app, [*args, "-o", str(tmp_path / "serial.nc")])
    assert ref.exit_code == 0, ref.output
    address = client.scheduler.address
    res = runner.invoke(app, [*args, "-o", str(tmp_path / "dask.nc"), "--scheduler", address])
    assert res.exit_code == 0, res.output
    a, b = json.loads(res.stdout), json.loads(ref.stdout)
    assert a["status"] == b["status"] == "equilibrium_lost"
    assert a["events"] == b["events"] and a["transitions"] == b["transitions"]
    for mu_a, mu_b in zip(a["multipliers"], b["multipliers"], strict=True):
        for key, v in mu_b.items():
            if isinstance(v, float):
                assert mu_a[key] == pytest.approx(v, rel=1e-12), key
            else:
                assert mu_a[key] == v, key
    bad = runner.invoke(app, [*args, "-o", str(tmp_path / "bad.nc"), "--scheduler", "nowhere"])
    assert_one_line_error(bad, "scheduler: give a dask scheduler's address")


@pytest.mark.slow
def test_condense_on_process_cluster(system):
    """A LocalCluster of 2 worker processes (A and B pickled to each, a factor per process,
    BLAS held to one thread by the nanny): G equal to the serial G to G_RTOL, float64 and
    float32 (one float32 spacing)."""
    serial = sc.condense(system)
    serial32 = sc.condense(system, precision="float32")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=":0") as lc:
        dist = sc.condense(system, scheduler=lc.scheduler_address)
        dist32 = sc.condense(system, precision="float32", scheduler=lc.scheduler_address)
    err = np.abs(dist.G - serial.G).max() / np.abs(serial.G).max()
    assert err <= G_RTOL, err
    assert _close32(dist32.G, serial32.G)
    k = dist.counters
    assert k["cluster_workers"] == 2
    assert k["cluster_factorizations"] == k["cluster_workers_used"] >= 1
