"""Support reactions: resultants at every state, from the condensed unknowns (no solve).

References: statics (the reactions balance the applied loads), and the direct computation
R = S (K u + Bᵀ s − f) from the full displacement field at the stored states.
"""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

import stepcontact as sc
import verification_models as vm
from stepcontact.cli import app
from stepcontact.fem.assembly import assemble

G = 9.81


def _direct(system, res, i):
    u = res.displacement(i)
    f = sum(c * system.loads[n].f for n, c in zip(res.pattern_names, res.factors[i], strict=True))
    s = np.r_[res.Q[i], -res.N[i]]
    return system.reaction_rows @ (system.K @ u + system.B.T @ s - f)


def test_sliding_block_reactions_balance_the_loads():
    system = assemble(vm.sliding_block(0.4, 10.0))
    res = sc.solve_static(system, store_fields="all")
    W = -system.loads["weight"].f.sum()
    assert res.reaction_labels == ("base_bottom:x", "base_bottom:y")
    ry, rx = res.reaction("base_bottom", "y"), res.reaction("base_bottom", "x")
    after_weight = res.segment == 1
    assert np.allclose(ry[after_weight], W, rtol=1e-12)
    # H = W λ / g along +x: the base pushes back with −H
    H = W * res.lam[after_weight] / G
    assert np.allclose(rx[after_weight], -H, rtol=1e-10, atol=1e-9 * W)
    assert rx[-1] == pytest.approx(-0.4 * W, rel=1e-9)  # sliding at f W
    for i in range(res.n_states):
        assert np.allclose(res.reactions[i], _direct(system, res, i), rtol=1e-9, atol=1e-9 * W)


def test_reactions_include_contact_forces_on_fixed_nodes():
    """The slab's base is fixed at every node, so the CFEs act on fixed DOFs (B_pᵀ s)."""
    system = assemble(vm.uplift_slab("top_pressure", 5.0))
    res = sc.solve_static(system)
    W = -system.loads["weight"].f.sum()
    U1 = system.loads["uplift"].f.sum()
    ry = res.reaction("rigid_base", "y")
    up = res.segment == 1
    assert np.allclose(ry[up], W - U1 * res.lam[up], rtol=1e-10)
    for i in np.flatnonzero(np.isin(res.kind, ["segment_end", "start"])):
        assert np.allclose(res.reactions[i], _direct(system, res, i), rtol=1e-9, atol=1e-9 * W)


def test_prescribed_displacement_reaction_and_round_trip(tmp_path):
    m = vm.block_on_base(friction=0.5, w=2.0, h=0.5, nx=4, ny=1)
    right = m.select("block", x=2.0)
    m = m.add(
        sc.LoadPattern("weight", [sc.BodyForce((0.0, -G), bodies=("block",))]),
        sc.LoadPattern("pull", [sc.PrescribedDisplacement(right, "x", 1e-3)]),
        sc.Segment("weight", 1.0), sc.Segment("pull", 1.0),
    )
    system = assemble(m)
    res = sc.solve_static(system, store_fields="all")
    W = -system.loads["weight"].f.sum()
    rp = res.reaction("pull", "x")
    # the imposed displacement drags the block until it slides: the force needed is f W
    assert res.status == sc.Status.COMPLETED
    assert abs(rp[-1]) == pytest.approx(0.5 * W, rel=1e-9)
    assert np.allclose(rp + res.reaction("base_bottom", "x"), 0.0, atol=1e-9 * W)
    path = tmp_path / "r.nc"
    res.save(path)
    back = sc.load_result(path)
    assert back.reaction_labels == res.reaction_labels
    assert np.array_equal(back.reactions, res.reactions)
    with pytest.raises(KeyError, match="no reaction 'bed'"):
        back.reaction("bed")
    out = CliRunner().invoke(app, ["plot", str(path), "--kind", "load-displacement",
                                   "--reaction", "pull", "--dof", "x", "-o",
                                   str(tmp_path / "p.png")])
    assert out.exit_code == 0, out.output
    assert (tmp_path / "p.png").stat().st_size > 1000
    out = CliRunner().invoke(app, ["plot", str(path), "--kind", "timeline", "--reaction", "pull"])
    assert out.exit_code == 2 and "--reaction applies to --kind load-displacement" in out.output


def test_plot_json_and_quiet(tmp_path):
    res = sc.solve_static(vm.sliding_block(0.4, 10.0), store_fields="all")
    path = tmp_path / "r.nc"
    res.save(path)
    out = CliRunner().invoke(app, ["plot", str(path), "--kind", "all", "-o", str(tmp_path),
                                   "--json"])
    assert out.exit_code == 0, out.output
    import json

    info = json.loads(out.stdout)
    assert info["status"] == "ok" and len(info["written"]) == 5 and info["skipped"] == []
    assert all((tmp_path / p).stat().st_size > 1000 for p in info["written"])
    out = CliRunner().invoke(app, ["plot", str(path), "-q", "-o", str(tmp_path / "q.png")])
    assert out.exit_code == 0 and out.stdout == "" and (tmp_path / "q.png").exists()
    out = CliRunner().invoke(app, ["plot", str(tmp_path / "missing.nc"), "--json"])
    assert out.exit_code == 2 and json.loads(out.stdout)["status"] == "error"
