"""``stepcontact export``: a result file as ParaView files (VTU series with .pvd, XDMF)."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.console import Console
from rich.text import Text

from stepcontact.cli.common import (
    JsonOption,
    ModelOption,
    _error_text,
    _fail,
    _Failure,
    _state_list,
)
from stepcontact.cli.resultfile import _attach_model, _load_result_file
from stepcontact.results.result import StaticResult


def _export_files(vtu: Path | None, xdmf: Path | None, name: str) -> list[Path]:
    """Every file the export wrote (collection/XDMF files; frames live beside them)."""
    out: list[Path] = []
    if vtu is not None:
        out += [vtu / f"{name}.pvd", vtu / f"{name}_cfe.pvd"]
    if xdmf is not None:
        cfe = xdmf.with_name(f"{xdmf.stem}_cfe.xdmf")
        out += [xdmf, xdmf.with_suffix(".h5"), cfe, cfe.with_suffix(".h5")]
    return [p for p in out if p.is_file()]


def export(
    result_file: Annotated[
        Path, typer.Argument(metavar="RESULT.nc", help="Result file written by 'run'.")
    ],
    vtu: Annotated[
        Path | None,
        typer.Option("--vtu", metavar="DIR", help="Write a VTU time series into DIR: "
                     "NAME.pvd (bodies), NAME_cfe.pvd (contact elements), frames in DIR/NAME/."),
    ] = None,
    xdmf: Annotated[
        Path | None,
        typer.Option("--xdmf", metavar="FILE.xdmf", help="Write XDMF time series FILE.xdmf + "
                     "FILE.h5 (bodies) and FILE_cfe.xdmf + FILE_cfe.h5 (contact elements)."),
    ] = None,
    states: Annotated[
        str,
        typer.Option("--states", help="States to export: all, stored (with displacements), "
                     "events, ends (segment ends) or indices such as 0,5,-1. States without "
                     "stored displacements are recomputed from the model file, or skipped "
                     "with a note when there is none."),
    ] = "all",
    model: ModelOption = None,
    name: Annotated[
        str | None,
        typer.Option("--name", help="Base name of the VTU files. Default: the result file's "
                     "name without .nc."),
    ] = None,
    quiet: Annotated[
        bool, typer.Option("--quiet", "-q", help="Print nothing but errors.")
    ] = False,
    as_json: JsonOption = False,
) -> None:
    """Export a result file for ParaView: VTU series (.pvd) and/or XDMF (.xdmf + .h5).

    One frame per reported state; the time of a frame is the load-path parameter
    t = Σ|Δλ| (λ itself, segment and state index are field data). Displacements in m,
    stresses in Pa, CFE forces N and Q in N (N < 0 compression). See docs/paraview.md.

    Examples:

        stepcontact export run.nc --vtu run-vtu

        stepcontact export run.nc --vtu out --xdmf out/run.xdmf --states events

        stepcontact export run.nc --vtu out --model dam.toml

    A result file stores displacement fields and stresses at the start, the segment starts and
    ends and the last state (every state if solved with store_fields='all'); the other states
    are recomputed exactly from the model file of the run (--model; by default the model file
    the run recorded, if unchanged, or RESULT.toml beside the result file): one
    factorisation, then one multi-right-hand-side solve.
    """
    try:
        if vtu is None and xdmf is None:
            raise _Failure("nothing to export: give --vtu DIR and/or --xdmf FILE.xdmf")
        if xdmf is not None and xdmf.suffix.lower() != ".xdmf":
            raise _Failure(f"--xdmf {xdmf}: the file name must end in .xdmf")
        base = name if name is not None else result_file.stem
        res = _load_result_file(result_file)
        kept, skipped, used_model = _export_states(res, result_file, states, model)
        written = _write_files(res, vtu, xdmf, base, kept)
    except _Failure as e:
        raise _fail(str(e), as_json) from None
    except OSError as e:
        raise _fail(_error_text(e), as_json) from None
    if as_json:
        typer.echo(json.dumps({
            "status": "ok", "result_file": str(result_file), "frames": int(kept.size),
            "states": kept.tolist(), "skipped": skipped.tolist(), "written": written,
            "model_file": None if used_model is None else str(used_model),
            "recomputed": [int(i) for i in kept if int(i) not in res.fields]
            if used_model is not None else [],
        }, indent=2, ensure_ascii=False))
    elif not quiet:
        _print_export(res, kept, skipped, used_model, written)


def _export_states(res: StaticResult, result_file: Path, states: str,
                   model: Path | None) -> tuple[np.ndarray, np.ndarray, Path | None]:
    """The states ``--states`` selects that can be exported (``kept``) and those without
    displacements (``skipped``), with the model file attached when some are not stored
    (the model file used, or None); a failure when none can be exported."""
    from stepcontact.io.export import select_states

    try:
        kept, skipped = select_states(res, states)
    except ValueError as e:
        raise _Failure(f"--states: {_error_text(e)}") from None
    used_model = None
    if skipped.size:
        used_model = _attach_model(res, result_file, model)
        if used_model is not None:
            kept, skipped = select_states(res, states)
    if kept.size == 0 and getattr(res, "path_axis", "lam") == "time":
        raise _Failure(f"{result_file}: the stresses of a dynamic result are recovered "
                       "from its model file, which was not found unchanged (the one the "
                       "result records, or MODEL.toml beside it); give it with --model "
                       "MODEL.toml")
    if kept.size == 0:
        raise _Failure(f"{result_file}: none of the selected states has stored "
                       "displacements; give the model file of the run with --model "
                       "MODEL.toml to recompute them (or solve with store_fields='all')")
    return kept, skipped, used_model


def _write_files(res: StaticResult, vtu: Path | None, xdmf: Path | None, base: str,
                 kept: np.ndarray) -> list[str]:
    """Write the VTU series and/or the XDMF files of the states ``kept``; the files."""
    from stepcontact.io.export import export_vtu, export_xdmf

    try:
        if vtu is not None:
            export_vtu(res, vtu, states=kept, name=base)
        if xdmf is not None:
            export_xdmf(res, xdmf, states=kept)
    except ValueError as e:
        raise _Failure(_error_text(e)) from None
    return [str(p) for p in _export_files(vtu, xdmf, base)]


def _print_export(res: StaticResult, kept: np.ndarray, skipped: np.ndarray,
                  used_model: Path | None, written: Sequence[str]) -> None:
    """What ``export`` did: the fields recomputed, the states skipped, the files written."""
    console = Console(highlight=False, soft_wrap=True)
    dynamic = getattr(res, "path_axis", "lam") == "time"
    if used_model is not None and dynamic:
        console.print(Text(f"stresses recovered from {used_model} (the displacements of "
                           "every state are in the result file)"))
    elif used_model is not None:
        n_rec = sum(int(i) not in res.fields for i in kept)
        console.print(Text(f"fields of {n_rec} state(s) not stored in the result file "
                           f"recomputed from {used_model}"))
    if skipped.size:
        which = _state_list(skipped.tolist(), count=False)
        console.print(Text(f"skipped {skipped.size} state(s) without stored displacements "
                           f"(states {which}); give the model file of the run with --model "
                           "MODEL.toml to recompute them exactly (or solve with "
                           "store_fields='all')", style="yellow"))
    console.print(Text(f"exported {kept.size} frame(s) of {res.n_states} states", style="green"))
    console.print(Text("written: " + ", ".join(written), style="green"))
