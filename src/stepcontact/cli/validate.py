"""``stepcontact validate`` (alias ``check``) and ``stepcontact schema``: a model file's
problems, all at once, and the JSON schema of the file format."""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path
from typing import Annotated, Any

import typer
from rich import box
from rich.console import Console
from rich.text import Text

from stepcontact.cli.common import EXIT_ERROR, JsonOption, Table, print_records


def problems_table(problems: Sequence[Any], title: str) -> Table:
    """Problems of a model file (:class:`~stepcontact.io.modelfile.Problem`) as a rich table."""
    table = Table(title=title, title_justify="left", box=box.SIMPLE_HEAD, show_edge=False,
                  pad_edge=False)
    table.add_column("", no_wrap=True)
    table.add_column("item", overflow="fold")
    table.add_column("problem", overflow="fold")
    for p in problems:
        style = "red" if p.severity == "error" else "yellow"
        table.add_row(Text(p.severity, style=style), p.item, p.message)
    return table


def validate(
    model_file: Annotated[Path, typer.Argument(metavar="MODEL.toml", help="TOML model file.")],
    as_json: JsonOption = False,
) -> None:
    """Check a model file and list all its problems at once (alias: check).

    Checks the schema, names, mesh groups, materials and element quality.

    Finds orphan nodes and bodies that overlap without an interface; assembles the model and
    checks, without solving, that it is no mechanism with every CFE stuck (names the bodies
    that can move); warns about empty or zero load patterns.

    A 3D mesh (volume cells or physical volumes) is an error naming the mesh file and its
    element types: 3D models are not supported yet.

    Earthquake records of a dynamic interval ([[dynamics.ground_motion]]) are read and their
    baseline figures printed: PGA (m/s² and g) and its time, Arias intensity, 5–95 %
    duration, sampling (--json: summary.ground_motion).

    Exit code 2 when there are errors (warnings alone exit with 0).

    Examples:

        stepcontact validate examples/data/gmsh_block.toml

        stepcontact validate dam.toml --json
    """
    from stepcontact.io.modelfile import validation_report

    console = Console(highlight=False, soft_wrap=True)
    report = validation_report(model_file)
    errors, warnings = report.errors, report.warnings
    if as_json:
        typer.echo(json.dumps({
            "status": "error" if errors else "ok",
            "file": str(model_file),
            "errors": len(errors),
            "warnings": len(warnings),
            "problems": [asdict(p) for p in report.problems],
            "summary": report.summary(),
        }, indent=2))
    elif report.problems:
        console.print(problems_table(report.problems, f"{model_file}: {len(errors)} errors, "
                                     f"{len(warnings)} warnings"))
    if errors:
        first = errors[0]
        # a problem of the file itself (not found, not TOML) is already named by the file
        msg = first.message if first.item == str(model_file) else f"{first.item}: {first.message}"
        if len(errors) > 1:
            msg = f"{len(errors)} errors, the first: {msg}"
        Console(stderr=True, soft_wrap=True, highlight=False).print(
            Text(f"error: {model_file}: {' '.join(msg.split())}", style="red")
        )
        raise typer.Exit(EXIT_ERROR)
    if not as_json:
        s = report.summary()
        console.print(Text(
            f"model OK: '{s['model']}': {s['bodies']} bodies, {s['nodes']} nodes, {s['dofs']} "
            f"DOFs, {s['cfes']} CFEs on {s['interfaces']} interfaces, {s['patterns']} load "
            f"patterns, {s['segments']} segments"
            + (f" in {s['stages']} stages" if s.get("stages") else "")
            + (f" ({len(warnings)} warnings)" if warnings else ""),
            style="green",
        ))
        print_records(report.model, console)


def check(
    model_file: Annotated[Path, typer.Argument(metavar="MODEL.toml", help="TOML model file.")],
    as_json: JsonOption = False,
) -> None:
    """Alias of validate."""
    validate(model_file, as_json=as_json)


def schema() -> None:
    """Print the JSON schema of the model file format.

    Examples:

        stepcontact schema > stepcontact.schema.json

    Point your editor at it (e.g. the "Even Better TOML" extension: a #:schema comment).
    """
    from stepcontact.io.modelfile import schema as file_schema

    typer.echo(json.dumps(file_schema(), indent=2))
