"""Loading a model file: TOML read, validated and built into a
:class:`~stepcontact.model.Model` (:func:`load_model`, :func:`model_from_dict`), or checked
for every problem at once (:func:`validation_report`, :func:`validate_model_file`).
"""

from __future__ import annotations

import tomllib
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from stepcontact.errors import ModelError, StepContactError
from stepcontact.io.modelfile.build import _Builder
from stepcontact.io.modelfile.checks import check_geometry
from stepcontact.io.modelfile.errors import Problem, _Problems, _validate
from stepcontact.model.items import Model


def model_from_dict(d: dict[str, Any], base_dir: str | Path | None = None) -> Model:
    """Build a :class:`~stepcontact.model.Model` from the parsed contents of a model file.

    Parameters
    ----------
    d : dict
        The TOML document as a dict (what :func:`tomllib.load` returns).
    base_dir : path, optional
        Directory against which relative file names in the model (the mesh file) are
        resolved; default: the current directory.

    Raises
    ------
    ModelError
        Whose ``item`` is the field path of the first problem, e.g. ``bodies[1].material.E``;
        all problems are listed in the message and in its ``errors`` attribute.

    Example
    -------
    >>> import tomllib
    >>> from stepcontact.io.modelfile import model_from_dict
    >>> text = '''
    ... [materials.steel]
    ... E = 210e9
    ... nu = 0.3
    ... [[bodies]]
    ... name = "plate"
    ... corner0 = [0, 0]
    ... corner1 = [1, 1]
    ... nx = 2
    ... ny = 2
    ... material = "steel"
    ... [node_sets.bottom]
    ... body = "plate"
    ... y = 0
    ... [[supports]]
    ... nodes = "bottom"
    ... [patterns.push]
    ... loads = [{type = "nodal", nodes = "bottom", fx = 1e3}]
    ... [[program]]
    ... pattern = "push"
    ... end = 1
    ... '''
    >>> model_from_dict(tomllib.loads(text)).bodies[0].n_nodes
    9
    """
    spec = _validate(d)
    problems = _Problems()
    base = Path(base_dir) if base_dir is not None else Path.cwd()
    model = _Builder(spec, base, problems).model()
    problems.raise_if_any()
    assert model is not None
    for path, message in problems.warnings:  # deprecations, implausible values (validate
        # lists them too)
        category = problems.category.get((path, message), FutureWarning)
        warnings.warn(f"{path}: {message}", category, stacklevel=2)
    return model


def _read_toml(path: Path) -> dict[str, Any]:
    """The parsed TOML file; a missing file raises FileNotFoundError, anything else that is not
    a readable UTF-8 TOML file (a directory, a binary or UTF-16 file, bad syntax) a ModelError
    whose item is the file name."""
    if path.is_dir():
        raise ModelError(str(path), "is a directory, not a model file")
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise
    except OSError as e:
        raise ModelError(str(path), f"cannot be read: {e.strerror or e}") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        if data[:2] in (b"\xff\xfe", b"\xfe\xff"):
            raise ModelError(str(path), "is UTF-16 text: save it as UTF-8 (a model file is "
                             "TOML text in UTF-8)") from None
        raise ModelError(str(path), f"is not a UTF-8 text file (byte 0x{data[e.start]:02x} at "
                         f"offset {e.start}): a model file is TOML text in UTF-8") from None
    if "\x00" in text:
        raise ModelError(str(path), "not a text file (it contains NUL bytes): a model file is "
                         "TOML text in UTF-8")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ModelError(str(path), f"not a valid TOML file: {e}") from None


def load_model(path: str | Path) -> Model:
    """Read a TOML model file and build the :class:`~stepcontact.model.Model`.

    The model's name defaults to the file's stem when ``[model] name`` is not given; the mesh
    file of ``[mesh]`` is relative to the model file.

    Raises
    ------
    FileNotFoundError
        When the file does not exist.
    ModelError
        When the file is not valid TOML (``item`` is the file name) or the model is wrong
        (``item`` is the field path, e.g. ``interfaces[0].plus``).

    Example
    -------
    >>> from importlib.resources import files
    >>> from stepcontact.io.modelfile import load_model
    >>> model = load_model(files("stepcontact") / "data" / "demo.toml")
    >>> [itf.name for itf in model.interfaces]
    ['joint']
    """
    path = Path(str(path))
    d = _read_toml(path)
    model = model_from_dict(d, base_dir=path.parent)
    if not (d.get("model") or {}).get("name"):
        model = model.replace(name=path.stem)
    return model


# --------------------------------------------------------------------------------------------
# validation
# --------------------------------------------------------------------------------------------
@dataclass
class Validation:
    """What :func:`validation_report` found: every problem, and the model's size when it
    could be assembled."""

    path: Path
    problems: list[Problem] = field(default_factory=list)
    model: Model | None = None
    ndof: int | None = None
    n_cfes: int | None = None

    @property
    def errors(self) -> list[Problem]:
        return [p for p in self.problems if p.severity == "error"]

    @property
    def warnings(self) -> list[Problem]:
        return [p for p in self.problems if p.severity == "warning"]

    @property
    def ok(self) -> bool:
        return not self.errors

    def summary(self) -> dict[str, Any]:
        """Size of the model (what ``stepcontact validate --json`` prints)."""
        m = self.model
        if m is None:
            return {}
        return {
            "model": m.name,
            "bodies": len(m.bodies),
            "nodes": int(sum(b.n_nodes for b in m.bodies)),
            "elements": int(sum(len(b.cells) for b in m.bodies)),
            "dofs": self.ndof,
            "cfes": self.n_cfes,
            "interfaces": len(m.interfaces),
            "patterns": len(m.patterns),
            "segments": len(m.effective_program),
            "stages": len(m.stages),
            **_ground_motion_summary(m),
        }


def _ground_motion_summary(model: Model) -> dict[str, Any]:
    """{"ground_motion": [the baseline figures of every record, with its interval]} of a
    model whose dynamic intervals have earthquake records ({} without)."""
    from stepcontact.model.records import model_records

    figs = model_records(model)
    return {"ground_motion": [{"interval": where, **f.as_dict()} for where, f in figs]
            } if figs else {}


def validation_report(path: str | Path) -> Validation:
    """Check a model file and report *all* its problems (see :func:`validate_model_file`)."""
    path = Path(str(path))
    out = Validation(path)
    try:
        d = _read_toml(path)
    except FileNotFoundError:
        out.problems.append(Problem(str(path), "file not found"))
        return out
    except ModelError as e:
        out.problems.append(Problem(e.item, e.problem))
        return out
    try:
        spec = _validate(d)
    except ModelError as e:
        out.problems = [Problem(p, m) for p, m in getattr(e, "errors", [(e.item, e.problem)])]
        return out
    problems = _Problems()
    builder = _Builder(spec, path.parent, problems)
    model = builder.model()
    if model is not None:
        if not spec.model.name:
            model = model.replace(name=path.stem)
        check_geometry(builder, model)
        out.model = model
    if model is not None and not problems.items:
        from stepcontact.fem.assembly import assemble

        try:
            system = assemble(model)
            model.segments_resolved()
            from stepcontact.model.consistency import check_consistency, program_warnings

            check_consistency(model)  # what run refuses, seen in the model itself
            for item, text in program_warnings(model):
                problems.warn(item, text)
            from stepcontact.model.records import record_warnings

            for item, text in record_warnings(model):  # records cut by their interval
                problems.warn(item, text)
            out.ndof, out.n_cfes = int(system.dofs.ndof), int(system.cfe.m)
            if model.added_masses:  # the reservoirs' faces and levels (fem.hydrodynamic)
                from stepcontact.fem.hydrodynamic import face_masses

                for i, am in enumerate(model.added_masses):
                    face_masses(model, am, f"added_masses[{i}]")
            from stepcontact.fem.loadcheck import zero_patterns

            for name, text in zero_patterns(model, system.loads):
                problems.warn(f"patterns.{name}", text)
            if model.stages:  # what a run checks of the stages before solving
                from stepcontact.solver.staging import StagePlan

                plan = StagePlan(system)
                for k in range(len(model.stages)):  # grout strengths at the joints' CFEs
                    plan.grout_stage(k)
            _check_mechanism(system)
            dyn_stages = [st.name for st in model.stages if st.dynamics is not None]
            if model.dynamics is not None or dyn_stages:  # mass for the dynamic interval
                from stepcontact.fem.mass import check_mass

                check_mass(system, "dynamics" if not dyn_stages else
                           f"stage '{dyn_stages[0]}'.dynamics")
        except StepContactError as e:
            problems.add(getattr(e, "item", "model"), getattr(e, "problem", str(e)))
    out.problems = problems.problems()
    return out


def _check_mechanism(system: Any) -> None:
    """What ``run`` checks first, without solving the contact problem: K₀ (the stiffness with
    the supports and every CFE stuck) is regular; else a ModelError naming the bodies that can
    move and how (:func:`stepcontact.solver.regularity.factorize_regular`)."""
    from stepcontact.solver.condensation import check_dense_memory, static_operator
    from stepcontact.solver.regularity import factorize_regular

    check_dense_memory(2 * system.m)  # the dense contact matrices fit (SolverError if not)
    K0, _, _, free, *_ = static_operator(system)
    factorize_regular(system, K0, free)


def validate_model_file(path: str | Path) -> list[Problem]:
    """Every problem of a model file at once, each naming its field or physical group.

    Checks the TOML syntax and the schema, unknown names (materials, bodies, node sets,
    physical groups, patterns), that every physical surface of the mesh is a body with a
    material, element quality (inverted elements are errors; nearly degenerate or elongated
    ones warnings, with the worst element's index, quality and aspect ratio), mesh nodes that
    belong to no element (warning), duplicate nodes of a body (warning), bodies that overlap
    without an interface between them, that the model assembles, that no load pattern is
    empty or zero (warning), and, without solving, what ``run`` checks first: that the dense
    contact matrices fit in memory and that the structure with every CFE stuck is not a
    mechanism (the error names the bodies that can move).  An empty list means the model is
    OK.

    Example
    -------
    >>> from importlib.resources import files
    >>> from stepcontact.io.modelfile import validate_model_file
    >>> validate_model_file(files("stepcontact") / "data" / "demo.toml")
    []
    """
    return validation_report(path).problems
