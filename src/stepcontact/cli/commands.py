"""Command line: ``stepcontact run MODEL.toml``, ``stepcontact demo``, ``stepcontact validate``,
``stepcontact sweep STUDY.toml``, ``stepcontact study slab``.

The CLI sits at the end of the data flow (model file -> model -> solver -> result -> files) and
only wires those pieces together; the progress bar is a solver hook.  Bad input never shows a
traceback: any :class:`~stepcontact.errors.StepContactError`, a missing file or a broken TOML
file prints one red line ``error: ...`` on stderr and exits with code 2.  A run that ends with
lost equilibrium is a result (exit code 0), not an error; a run that stopped without a physical
answer (contact conditions not met, no consistent scheme, cycling, event budget) writes its
result file and exits with code 3.

This module is the typer application: it registers the commands, in the order ``--help``
lists them, from their modules (:mod:`~stepcontact.cli.run`, :mod:`~stepcontact.cli.validate`,
:mod:`~stepcontact.cli.study`, :mod:`~stepcontact.cli.plot`, :mod:`~stepcontact.cli.info`,
:mod:`~stepcontact.cli.export`; what they share is in :mod:`~stepcontact.cli.common`).

Example
-------
.. code-block:: console

    $ stepcontact run dam.toml -o dam.nc --plot dam.png --lam 1.5 --lam 2.0
    $ stepcontact run dam.toml --json --quiet     # machine-readable summary on stdout
    $ stepcontact sweep friction.toml --workers 4  # a parameter sweep (docs/sweeps.md)
    $ stepcontact study slab --quick -o slab-quick  # the stilling-basin slab (docs/slab-study.md)
    $ stepcontact demo -o demo-out
"""

from __future__ import annotations

from typing import Annotated

import typer

from stepcontact import __version__
from stepcontact.cli.common import (
    EXIT_ERROR,
    EXIT_UNRESOLVED,
    PLOT_SUFFIXES,
    TABLE_ROWS,
    Table,
    _kN,
    events_table,
)
from stepcontact.cli.export import export
from stepcontact.cli.info import _clean_pair, info
from stepcontact.cli.plot import PLOT_KINDS, plot
from stepcontact.cli.progress import ProgressHook
from stepcontact.cli.run import demo, run
from stepcontact.cli.study import STUDIES, study, sweep, sweep_table
from stepcontact.cli.validate import check, problems_table, schema, validate
from stepcontact.results.summary import result_info, result_summary

app = typer.Typer(
    name="stepcontact",
    help="Event-driven static analysis of 2D and 3D structures with unilateral contact and "
    "Coulomb friction (contact finite elements, step-by-step method).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"stepcontact {__version__}")
        raise typer.Exit()


@app.callback()
def main(
    version: Annotated[
        bool,
        typer.Option("--version", callback=_version, is_eager=True,
                     help="Show the version and exit."),
    ] = False,
) -> None:
    """Event-driven static analysis of 2D and 3D structures with unilateral contact and
    friction."""


# the commands in the order --help lists them (check: the hidden alias of validate)
for _command in (run, demo, validate, sweep, study):
    app.command()(_command)
app.command(hidden=True)(check)
for _command in (schema, plot, info, export):
    app.command()(_command)

__all__ = ["EXIT_ERROR", "EXIT_UNRESOLVED", "PLOT_KINDS", "PLOT_SUFFIXES", "STUDIES",
           "TABLE_ROWS", "ProgressHook", "Table", "_clean_pair", "_kN", "app", "events_table",
           "problems_table", "result_info", "result_summary", "sweep_table"]
