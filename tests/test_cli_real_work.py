"""The CLI on real work (issue 24 §4): a model file checked against its result with a tolerance
scaled to the model, user text shown as written in rich tables, numbers never truncated.

References: the stored field of a run (the model is the run's, by construction), the model
with another Young's modulus (a genuinely different model), the message text as the model file
spells it, and the numbers of the result (``info --json``) printed in full at 80 columns.
"""

from __future__ import annotations

import pickle
from importlib.resources import files

import numpy as np
import pytest
from typer.testing import CliRunner

import stepcontact as sc
import verification_models as vm
from stepcontact.cli import app

runner = CliRunner()


def _pushed(E: float = 30e9) -> sc.Model:
    return vm.pushed_block(E=E, base_cells=(8, 2), block_cells=(4, 2))


def test_recover_fields_accepts_its_model_whatever_its_conditioning():
    """A recomputed field of an ill-conditioned model differs from the stored one in its soft
    modes (κ·eps between two factorisations).  Modelled here by the stored field moved along
    the block's rigid translation by 1e-4 of its largest displacement: the forward difference
    (1e-4 > RECOVERY_RTOL = 1e-6) refused the run's own model before; the stored field still
    satisfies the model's equilibrium to round-off (< RECOVERY_RESIDUAL = 1e-8), so the model
    is accepted.  The model with E × 2/3 leaves a residual of order 1 and is refused."""
    from stepcontact.fem.assembly import assemble
    from stepcontact.results.result import RECOVERY_RESIDUAL, RECOVERY_RTOL

    model = _pushed()
    res = sc.solve_static(model)
    back = pickle.loads(pickle.dumps(res))
    i = max(back.fields, key=lambda k: float(np.abs(back.fields[k]).max()))
    u = np.asarray(back.fields[i], float)
    block = model.select("block", boundary=False)  # every node of the block
    block_x = assemble(model).dofs.nodes(model.global_nodes(block), 0)
    shift = np.zeros_like(u)
    shift[block_x] = 1e-4 * np.abs(u).max()
    back.fields[i] = u + shift
    assert 1e-4 / 2 > RECOVERY_RTOL and RECOVERY_RESIDUAL <= 1e-8
    back.recover_fields(model)  # accepted
    k = next(j for j in range(back.n_states) if j not in back.fields)  # recomputed
    assert np.allclose(back.displacement(k), res.displacement(k), rtol=0,
                       atol=1e-9 * np.abs(u).max())
    with pytest.raises(ValueError, match="not the one of this result"):
        pickle.loads(pickle.dumps(res)).recover_fields(_pushed(E=20e9))


DEMO = files("stepcontact") / "data" / "demo.toml"


def test_cli_plot_with_the_run_model_file_and_another(tmp_path):
    """run, then plot --model with the very model file: accepted (exit 0, the figure written);
    the same file with the block's E = 20 GPa instead of 30 GPa: refused, naming the
    difference (exit 2, one line, no traceback)."""
    model = tmp_path / "dam.toml"
    text = DEMO.read_text(encoding="utf-8")
    model.write_text(text, encoding="utf-8")
    out = runner.invoke(app, ["run", str(model), "-o", str(tmp_path / "r.nc"), "--no-plot",
                              "-q"])
    assert out.exit_code == 0, out.output
    args = ["plot", str(tmp_path / "r.nc"), "--kind", "deformed", "--state", "3"]
    out = runner.invoke(app, [*args, "--model", str(model), "-o", str(tmp_path / "d.png")])
    assert out.exit_code == 0, out.output
    assert (tmp_path / "d.png").stat().st_size > 0
    assert "E = 30e9" in text
    other = tmp_path / "other.toml"
    other.write_text(text.replace("E = 30e9", "E = 20e9", 1), encoding="utf-8")
    out = runner.invoke(app, [*args, "--model", str(other), "-o", str(tmp_path / "e.png")])
    assert out.exit_code == 2, out.output
    assert "not the one of this result" in out.output and "Traceback" not in out.output
    assert not (tmp_path / "e.png").exists()
