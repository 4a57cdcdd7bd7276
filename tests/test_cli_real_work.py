"""The CLI on real work (issue 24 §4): a model file checked against its result with a tolerance
scaled to the model, user text shown as written in rich tables, numbers never truncated.

References: the stored field of a run (the model is the run's, by construction), the model
with another Young's modulus (a genuinely different model), the message text as the model file
spells it, and the numbers of the result (``info --json``) printed in full at 80 columns.
"""

from __future__ import annotations

import pickle
import re
from importlib.resources import files
from pathlib import Path

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


STAGED = Path(__file__).resolve().parents[1] / "examples" / "data" / "staged_wall.toml"


def test_validate_shows_brackets_of_user_text_as_written(tmp_path):
    """A stage naming the body '[upper]' (an unknown body): the error table shows the item
    'stages[1].bodies' and the name '[upper]' with their brackets (rich markup read
    '[upper]' as a style and dropped it)."""
    text = STAGED.read_text(encoding="utf-8")
    assert 'bodies = ["upper"]' in text
    model = tmp_path / "wall.toml"
    model.write_text(text.replace('bodies = ["upper"]', 'bodies = ["[upper]"]'), "utf-8")
    out = runner.invoke(app, ["validate", str(model)], env={"COLUMNS": "100"})
    assert out.exit_code == 2, out.output
    table = out.stdout
    assert "stages[1].bodies" in table
    assert "no such body '[upper]'" in " ".join(table.split())


def test_tables_never_truncate_numbers_at_80_columns(tmp_path):
    """Long pattern and interface names in an 80-column terminal: every λ, N and Q of the
    event table and the λ's of the info tables appear in full, as the result file has them
    (formatted as the CLI formats them: λ to 6 digits, forces in kN to 3 decimals); no cell
    ends in '…' after a digit."""
    from stepcontact.cli.commands import _kN
    from stepcontact.results.result import load_result

    long_joint = "the joint between the lower and the upper lift"
    text = (STAGED.read_text(encoding="utf-8").replace('"lift joint"', f'"{long_joint}"')
            .replace("[patterns.push]", "[patterns.push_from_the_upstream_side]")
            .replace('pattern = "push"', 'pattern = "push_from_the_upstream_side"'))
    model = tmp_path / "wall.toml"
    model.write_text(text, encoding="utf-8")
    env = {"COLUMNS": "80"}
    out = runner.invoke(app, ["run", str(model), "-o", str(tmp_path / "w.nc"), "--no-plot"],
                        env=env)
    assert out.exit_code == 0, out.output
    res = load_result(tmp_path / "w.nc")
    assert res.events
    cells = set(out.stdout.split())
    for e in res.events:
        assert f"{e.lam:.6g}" in cells and _kN(e.N) in cells and _kN(e.Q) in cells
    assert not re.search(r"[\d.]…", out.stdout)
    out = runner.invoke(app, ["info", str(tmp_path / "w.nc")], env=env)
    assert out.exit_code == 0, out.output
    cells = set(out.stdout.split())
    for m in res.multipliers:
        for v in (m.first_slip, m.first_opening, m.equilibrium_lost):
            assert v is None or f"{v:.6g}" in cells
    assert not re.search(r"[\d.]…", out.stdout)
