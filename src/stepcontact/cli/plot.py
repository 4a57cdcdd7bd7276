"""``stepcontact plot``: figures of a result file, one file per kind."""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer
from rich.console import Console
from rich.text import Text

from stepcontact.cli.common import (
    PLOT_SUFFIXES,
    JsonOption,
    ModelOption,
    _error_text,
    _fail,
    _Failure,
)
from stepcontact.cli.resultfile import _attach_model, _load_result_file
from stepcontact.results.result import StaticResult

PLOT_KINDS = ("deformed", "stresses", "load-displacement", "timeline", "safety", "energy",
              "history")
#: the kinds that need a dynamic result (MODEL-dynamic.nc)
_DYNAMIC_KINDS = ("energy", "history")
_NEEDS_FIELDS = ("deformed", "load-displacement")


def _parse_node(text: str | None) -> int | tuple[float, ...] | None:
    """``--node``: ``X,Y`` or, in 3D, ``X,Y,Z`` (m), or a node index."""
    if text is None:
        return None
    parts = [p.strip() for p in text.split(",")]
    try:
        if len(parts) == 1:
            return int(parts[0])
        if len(parts) in (2, 3):
            xyz = tuple(float(p) for p in parts)
            if all(math.isfinite(v) for v in xyz):
                return xyz
    except ValueError:
        pass
    raise _Failure(f"--node '{text}': give the coordinates X,Y in m (3D: X,Y,Z; e.g. --node "
                   "3,2) or a node index (e.g. --node 117)")


def _plot_targets(result_file: Path, kinds: Sequence[str], output: Path | None,
                  fmt: str) -> dict[str, Path]:
    """Figure file of each kind: ``-o`` itself (one kind, with a suffix) or
    ``DIR/RESULT-<kind>.<fmt>`` (``DIR``: ``-o`` or the result file's directory)."""
    if fmt not in ("png", "pdf", "svg"):
        raise _Failure(f"--format '{fmt}': use png, pdf or svg")
    is_dir = output is not None and (output.is_dir() or not output.suffix)
    if output is not None and not is_dir:
        if len(kinds) > 1:
            raise _Failure(f"-o {output}: --kind all writes one figure per kind, give a "
                           "directory")
        if output.suffix.lower() not in PLOT_SUFFIXES:
            raise _Failure(f"-o {output}: unsupported file type, use one of "
                           f"{', '.join(PLOT_SUFFIXES)} (or a directory)")
        return {kinds[0]: output}
    folder = output if output is not None else result_file.parent
    return {k: folder / f"{result_file.stem}-{k}.{fmt}" for k in kinds}


def _check_plot_options(kinds: Sequence[str], lam: Sequence[float] | None,
                        state: Sequence[int] | None, node: str | None,
                        reaction: str | None = None, stress: str | None = None,
                        node_set: str | None = None) -> None:
    if lam and "stresses" not in kinds:
        raise _Failure("--lam and --time apply to --kind stresses (use --state for the "
                       "deformed shape)")
    if node is not None and not {"load-displacement", "history"} & set(kinds):
        raise _Failure("--node applies to --kind load-displacement and history")
    if node_set is not None and "history" not in kinds:
        raise _Failure("--node-set applies to --kind history")
    if node_set is not None and node is not None:
        raise _Failure("give either --node or --node-set, not both")
    if reaction is not None and "load-displacement" not in kinds:
        raise _Failure("--reaction applies to --kind load-displacement")
    if stress is not None and "deformed" not in kinds:
        raise _Failure("--stress applies to --kind deformed")
    if reaction is not None and node is not None:
        raise _Failure("give either --node (a displacement) or --reaction (a support), not both")
    if state and len(state) > 1 and kinds == ["deformed"]:
        raise _Failure("--kind deformed draws one state: give a single --state")


def _draw_figure(res: StaticResult, kind: str, path: Path, opts: dict[str, Any]) -> None:
    """One figure of ``kind`` written to ``path``; plotting errors become one-line failures."""
    from stepcontact.post import plotting

    states = opts["state"] or None
    try:
        if kind == "deformed":
            plotting.plot_deformed(res, state=states[-1] if states else None,
                                   scale=opts["scale"], path=path, dpi=opts["dpi"],
                                   stress=opts.get("stress"))
        elif kind == "stresses" and _in_space(res):
            plotting.plot_interface_map(res, _map_interface(res, opts.get("interface")),
                                        states or (-1,), path=path, dpi=opts["dpi"])
        elif kind == "stresses":
            plotting.plot_interfaces(res, lams=opts["lam"] or None, segment=opts["segment"],
                                     states=states, path=path, dpi=opts["dpi"])
        elif kind == "load-displacement":
            plotting.plot_load_displacement(res, node=opts["node"], dof=opts["dof"],
                                            body=opts["body"], path=path, dpi=opts["dpi"],
                                            reaction=opts["reaction"])
        elif kind == "safety":
            plotting.plot_safety(res, path=path, dpi=opts["dpi"])
        elif kind == "energy":
            plotting.plot_energy(res, path=path, dpi=opts["dpi"])
        elif kind == "history":
            node = opts["node"]
            plotting.plot_time_history(
                res, path=path, dpi=opts["dpi"], body=opts["body"],
                point=node if isinstance(node, tuple) else None,
                nodes=opts.get("node_set") if node is None or isinstance(node, tuple) else node,
                direction=opts["dof"] or ("x", "y"))
        else:
            plotting.plot_event_timeline(res, path=path, dpi=opts["dpi"])
    except ValueError as e:
        raise _Failure(f"plot {kind}: {_error_text(e)}") from None


def _in_space(res: StaticResult) -> bool:
    """A result of a 3D model (two tangential components per CFE, or 3D nodes)."""
    pts = (res.geometry or {}).get("points")
    return getattr(res, "n_t", 1) > 1 or (pts is not None and np.ndim(pts) == 2
                                          and np.shape(pts)[1] == 3)


def _map_interface(res: StaticResult, name: str | None) -> str:
    """The interface a 3D ``--kind stresses`` draws: ``--interface`` or the first."""
    names = list(res.interface_names)
    if not names:
        raise _Failure("plot stresses: the result has no contact interface")
    if name is None:
        return names[0]
    if name not in names:
        raise _Failure(f"--interface '{name}': no such interface (interfaces: "
                       f"{', '.join(repr(n) for n in names)})")
    return name


#: kinds that draw 2D results only, and what to use for a 3D one
_PLANE_KINDS = {
    "deformed": "a 3D result's deformed shape and stresses are viewed in ParaView: "
                "stepcontact export RESULT.nc --vtu DIR",
    "safety": "the safety of a 3D joint is in stepcontact info RESULT.nc (resultant force "
              "and moment, eccentricities, sliding factor) and res.interface_safety(name)",
}


def _check_dimension(res: StaticResult, kind: str, lam: Sequence[float] | None,
                     targets: dict[str, Path], interface: str | None,
                     node: str | None = None) -> None:
    """The kinds and options of a 3D result: no deformed or safety figure (``--kind all``:
    left out of ``targets``), ``--state`` not ``--lam`` for the interface maps;
    ``--interface`` is for 3D results; ``--node`` coordinates as many as the result's."""
    dim = 3 if _in_space(res) else 2
    given = _parse_node(node)
    if isinstance(given, tuple) and len(given) != dim:
        raise _Failure(f"--node '{node}': give the coordinates "
                       f"{'X,Y,Z' if dim == 3 else 'X,Y'} in m (a {dim}D result) or a node "
                       "index")
    if dim == 2:
        if interface is not None:
            raise _Failure("--interface applies to --kind stresses of a 3D result (a 2D "
                           "result draws every interface)")
        return
    if kind in _PLANE_KINDS:
        raise _Failure(f"--kind {kind} draws 2D results: {_PLANE_KINDS[kind]}")
    if kind == "all":
        for k in _PLANE_KINDS:
            targets.pop(k, None)
    if lam:
        raise _Failure("--lam: the interface map of a 3D result is drawn at reported states: "
                       "give --state (see stepcontact info RESULT.nc)")


def _plot_missing_fields(res: StaticResult, kind: str, state: Sequence[int] | None,
                         reaction: str | None = None) -> bool:
    """True when a loaded result lacks the displacements ``kind`` needs (neither stored nor
    recoverable)."""
    if kind not in _NEEDS_FIELDS or res._recover is not None:
        return False
    if getattr(res, "u", None) is not None and len(res.u) == res.n_states:
        return False  # a dynamic result stores the displacements of every state
    if kind == "load-displacement" and reaction is not None:
        return False  # reactions are known at every state
    wanted = range(res.n_states) if kind == "load-displacement" else [
        (state[-1] if state else -1) % max(res.n_states, 1)]
    return any(i not in res.fields for i in wanted)


def plot(
    result_file: Annotated[
        Path, typer.Argument(metavar="RESULT.nc", help="Result file written by 'run'.")
    ],
    kind: Annotated[
        str,
        typer.Option("--kind", "-k", help="deformed, stresses, load-displacement, timeline, "
                     "safety (eccentricity, sliding factor and open length of the joints "
                     "along the path), energy (the energy ledger of a dynamic result), "
                     "history (displacements and velocities of a node of a dynamic result "
                     "against time) or all (one file per kind)."),
    ] = "stresses",
    lam: Annotated[
        list[float] | None,
        typer.Option("--lam", help="stresses: load factor λ to draw, of the last segment "
                     "reached or of --segment (repeat for several), e.g. --lam 1e4."),
    ] = None,
    segment: Annotated[
        int | None, typer.Option("--segment", help="stresses: the segment --lam refers to.")
    ] = None,
    at_time: Annotated[
        list[float] | None,
        typer.Option("--time", help="stresses of a dynamic result (MODEL-dynamic.nc): time t "
                     "in s to draw (repeat for several), e.g. --time 0.02 --time 0.05."),
    ] = None,
    state: Annotated[
        list[int] | None,
        typer.Option("--state", help="Reported state to draw (negative: from the end); "
                     "deformed: one state (default the last), stresses: repeat for several."),
    ] = None,
    node: Annotated[
        str | None,
        typer.Option("--node", help="load-displacement, history: node X,Y in m (3D: X,Y,Z; "
                     "the nearest node) or its index, e.g. --node 3,2. Default: the node that "
                     "moves most."),
    ] = None,
    node_set: Annotated[
        str | None,
        typer.Option("--node-set", help="history: the nodes of this named node set of the "
                     "model (at most 12), e.g. --node-set crest."),
    ] = None,
    dof: Annotated[
        str | None,
        typer.Option("--dof", help="load-displacement: x, y or rz (3D: x, y, z; rx, ry, rz "
                     "of space-frame nodes). Default: the direction (x or y; 3D: x, y or z) "
                     "that moves most over the path (y for --reaction). history: "
                     "x, y, rz (displacement and velocity) or one of ux, uy, vx, vy, ax, ay "
                     "(u displacement, v velocity, a acceleration); default x and y."),
    ] = None,
    body: Annotated[
        str | None,
        typer.Option("--body", help="load-displacement, history: body of --node when bodies "
                     "share the point."),
    ] = None,
    reaction: Annotated[
        str | None,
        typer.Option("--reaction", help="load-displacement: plot λ against the resultant "
                     "reaction of this support along --dof instead of a displacement."),
    ] = None,
    scale: Annotated[
        float | None,
        typer.Option("--scale", help="deformed: displacement magnification (default "
                     "automatic)."),
    ] = None,
    stress: Annotated[
        str | None,
        typer.Option("--stress", help="deformed: colour the cells by a stress component, "
                     "Pa: sxx, syy, sxy, szz or mises (von Mises)."),
    ] = None,
    output: Annotated[
        Path | None,
        typer.Option("--output", "-o", help="Figure file (.png, .pdf, .svg), or a directory. "
                     "Default: RESULT-<kind>.png next to the result file."),
    ] = None,
    fmt: Annotated[
        str, typer.Option("--format", help="File type when -o is a directory: png, pdf, svg.")
    ] = "png",
    dpi: Annotated[
        float, typer.Option("--dpi", min=1.0, help="Resolution of PNG figures, dots per inch.")
    ] = 150.0,
    interface: Annotated[
        str | None,
        typer.Option("--interface", help="stresses of a 3D result: the interface drawn in its "
                     "own plane (σn, shear arrows, CFE states; default the first)."),
    ] = None,
    model: ModelOption = None,
    quiet: Annotated[
        bool, typer.Option("--quiet", "-q", help="Print nothing but errors.")
    ] = False,
    as_json: JsonOption = False,
) -> None:
    """Draw figures of a result file.

    Examples:

        stepcontact plot run.nc                 # writes run-stresses.png

        stepcontact plot run.nc --kind stresses --lam 1e4 --lam 2e4 -o s.pdf

        stepcontact plot run.nc --kind deformed --state -1 --scale 500 -o d.svg

        stepcontact plot run.nc --kind deformed --stress mises

        stepcontact plot run.nc --kind load-displacement --node 3,2 --dof x

        stepcontact plot run.nc --kind load-displacement --reaction bed --dof x

        stepcontact plot run.nc --kind timeline --dpi 300

        stepcontact plot run.nc --kind safety

        stepcontact plot run-dynamic.nc --kind stresses --time 0.02 --time 0.05

        stepcontact plot run-dynamic.nc --kind energy

        stepcontact plot run-dynamic.nc --kind history --node 2,0 --body slab --dof uy

        stepcontact plot run-dynamic.nc --kind history --node-set crest

        stepcontact plot run.nc --kind all -o figures/ --format pdf

        stepcontact plot run.nc --kind load-displacement --model dam.toml

        stepcontact plot run3d.nc --kind load-displacement --node 1,1,0.5 --dof z

        stepcontact plot run3d.nc --kind stresses --interface joint --state 3 --state -1

    A 3D result: --kind stresses draws an interface in its own plane (--interface, at
    --state); deformed shapes are for ParaView (stepcontact export --vtu).

    The deformed shape and the load–displacement curve need displacement fields: those the
    result file does not store (by default it stores the start, the segment starts and ends
    and the last state) are recomputed exactly from the model file (--model; by default the
    model file the run recorded, if unchanged, or RESULT.toml beside the result file).
    """
    try:
        kinds = _plot_kinds(kind, lam, at_time)
        _check_plot_options(kinds, lam or at_time, state, node, reaction, stress, node_set)
        opts = {"lam": lam, "segment": segment, "state": state, "node": _parse_node(node),
                "dof": dof, "body": body, "scale": scale, "dpi": dpi, "reaction": reaction,
                "stress": stress, "node_set": node_set, "interface": interface}
        targets = _plot_targets(result_file, kinds, output, fmt)
        res = _load_result_file(result_file)
        _check_path_axis(res, kind, lam, at_time, targets)
        _check_dimension(res, kind, lam, targets, interface, node)
        if at_time:
            opts["lam"] = at_time
        written, skipped, used_model = _draw_figures(res, result_file, kind, kinds, targets,
                                                     opts, model)
    except _Failure as e:
        raise _fail(str(e), as_json) from None
    except OSError as e:
        raise _fail(_error_text(e), as_json) from None
    if as_json:
        typer.echo(json.dumps({"status": "ok", "written": written, "skipped": skipped,
                               "model_file": None if used_model is None else str(used_model)}))
    elif not quiet:
        _print_written(written, skipped, used_model)


def _plot_kinds(kind: str, lam: Sequence[float] | None,
                at_time: Sequence[float] | None) -> list[str]:
    """The kinds of figure ``--kind`` asks for (``all``: every kind)."""
    if kind != "all" and kind not in PLOT_KINDS:
        raise _Failure(f"unknown --kind '{kind}': use {', '.join(PLOT_KINDS)} or all")
    if at_time and lam:
        raise _Failure("give either --lam (a static result) or --time (a dynamic one)")
    return list(PLOT_KINDS) if kind == "all" else [kind]


def _check_path_axis(res: StaticResult, kind: str, lam: Sequence[float] | None,
                     at_time: Sequence[float] | None, targets: dict[str, Path]) -> None:
    """``--lam`` for a static result, ``--time`` for a dynamic one; the kinds of a dynamic
    result need one (``--kind all`` of a static result: they are left out of ``targets``)."""
    dynamic = getattr(res, "path_axis", "lam") == "time"
    if at_time and not dynamic:
        raise _Failure("--time applies to a dynamic result (MODEL-dynamic.nc); this one "
                       "is static: use --lam")
    if lam and dynamic:
        raise _Failure("this result is in time: give --time t (s), not --lam")
    if kind in _DYNAMIC_KINDS and not dynamic:
        raise _Failure(f"--kind {kind} needs a dynamic result (MODEL-dynamic.nc)")
    if kind == "all" and not dynamic:
        for k in _DYNAMIC_KINDS:
            targets.pop(k, None)


def _draw_figures(res: StaticResult, result_file: Path, kind: str, kinds: Sequence[str],
                  targets: dict[str, Path], opts: dict[str, Any],
                  model: Path | None) -> tuple[list[str], list[str], Path | None]:
    """Draw every figure of ``targets``, the model file attached first when a kind needs
    fields the result file does not store (``--kind all``: such kinds are skipped when there
    is no model); the files written, the kinds skipped and the model file used."""
    state, reaction = opts["state"], opts["reaction"]
    used_model = None
    if any(_plot_missing_fields(res, k, state, reaction) for k in kinds):
        used_model = _attach_model(res, result_file, model)
    written: list[str] = []
    skipped: list[str] = []
    for k, path in targets.items():
        if kind == "all" and _plot_missing_fields(res, k, state, reaction):
            skipped.append(k)
            continue
        _draw_figure(res, k, path, opts)
        written.append(str(path))
    return written, skipped, used_model


def _print_written(written: Sequence[str], skipped: Sequence[str],
                   used_model: Path | None) -> None:
    """What ``plot`` did: the model file used, the kinds skipped, the files written."""
    console = Console(highlight=False, soft_wrap=True)
    if used_model is not None:
        console.print(Text(f"fields not stored in the result file recomputed from {used_model}"))
    if skipped:
        console.print(Text(f"skipped {', '.join(skipped)}: the displacements of every state are "
                           "not stored in the result file; give the model file of the run with "
                           "--model MODEL.toml to recompute them (or solve with "
                           "store_fields='all')", style="yellow"))
    console.print(Text("written: " + ", ".join(written), style="green"))
