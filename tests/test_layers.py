"""The package keeps its layers: the import-linter contracts of pyproject.toml
([tool.importlinter]) hold on the source under test.

- ``layers``: cli, study and the demo on top; post; io; solver; results; fem and contact;
  model; the base modules (atomic, interrupt; enums, errors) — each imports only the layers
  below it (every module of the package is in a layer: the contract is exhaustive);
- ``study-calls-the-library``: no study imports the CLI;
- ``no-cycles``: no import cycle between the modules of any package (imports inside functions
  and under ``TYPE_CHECKING`` count).

The reference is import-linter's own analysis of the import graph (grimp); a broken contract
fails with import-linter's report, naming each offending import and its line.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from importlinter import api
from importlinter.application import use_cases

CONFIG = str(Path(__file__).resolve().parents[1] / "pyproject.toml")
CONTRACTS = [c["id"] for c in api.read_configuration(CONFIG)["contracts_options"]]


def test_the_contracts_are_there():
    assert {"layers", "study-calls-the-library", "no-cycles"} <= set(CONTRACTS)


@pytest.mark.parametrize("contract", CONTRACTS)
def test_import_contract_is_kept(contract, capsys):
    kept = use_cases.lint_imports(CONFIG, limit_to_contracts=(contract,), cache_dir=None,
                                  no_logo=True)
    report = capsys.readouterr().out
    assert kept, f"import contract '{contract}' is broken:\n{report}"

