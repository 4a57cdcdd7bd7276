"""Sweeps of a model file: a study file (``stepcontact sweep STUDY.toml``) names a base model
file and a grid (or list) of values of dotted paths into its TOML dict
(``interfaces.joint.friction``, ``patterns.push.loads.0.normal``); each case applies them to a
copy of the file, builds the model and runs it as ``stepcontact run`` would
(:class:`ModelCase`), on the sweep engine of :mod:`stepcontact.study.sweep`.  Cases that share
a mesh reuse one condensation per worker (:func:`cached_condensation`)."""

from __future__ import annotations

import copy
import hashlib
import json
import math
import os
import re
import threading
from collections import OrderedDict
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from stepcontact.errors import StepContactError
from stepcontact.study.sweep import (
    MAX_CASES,
    Case,
    Output,
    Scalar,
    StudyError,
    case_id,
    cases_from_list,
    current_case,
    grid,
    run_sweep,
)

if TYPE_CHECKING:
    import xarray as xr

    from stepcontact.model import Model
    from stepcontact.solver.condensation import Condensation

# --------------------------------------------------------------------------------------------
# model files: parameter paths into the TOML dict
# --------------------------------------------------------------------------------------------
#: condensations kept per worker thread (each holds a factorisation and a dense 2m × 2m G)
CACHE_SIZE = 2

_IDENT = re.compile(r"^[A-Za-z0-9_-]+$")


def _loc_text(loc: Sequence[str | int]) -> str:
    """A location as the model-file errors write it: ``interfaces[0].friction``."""
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            k = part if _IDENT.match(part) else f'"{part}"'
            out += f".{k}" if out else k
    return out


def _listing(node: Any) -> str:
    if isinstance(node, dict):
        return ", ".join(repr(k) for k in node) or "nothing"
    names = [f"{i} ({item['name']!r})" if isinstance(item, dict) and "name" in item
             else str(i) for i, item in enumerate(node)]
    return ", ".join(names) or "nothing (empty list)"


def resolve_path(doc: dict[str, Any], key: str) -> tuple[Any, str | int, list[str | int]]:
    """The container and the last key/index that a dotted parameter path addresses in a model
    file's TOML dict, and its location (``["interfaces", 0, "friction"]``).

    Tables are entered by key; arrays of tables by the ``name`` of an entry or by index
    (``interfaces.joint.friction``, ``program.1.end``).  The last component of a table may
    be a key the file does not set (a default of the format; checked when the model is
    validated).  An unknown component is a :class:`StudyError` naming the key and listing
    what exists at that level."""
    parts = key.split(".")
    if not key or any(not p for p in parts):
        raise StudyError(f"parameter '{key}': give a dotted path such as "
                         "interfaces.joint.friction")
    node: Any = doc
    loc: list[str | int] = []
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        where = ".".join(parts[:i]) or "the model file"
        if isinstance(node, dict):
            if part not in node and not last:
                raise StudyError(f"parameter '{key}': no '{part}' in {where}; it has "
                                 f"{_listing(node)}")
            if last:
                return node, part, [*loc, part]
            node, loc = node[part], [*loc, part]
        elif isinstance(node, list):
            named = [j for j, item in enumerate(node)
                     if isinstance(item, dict) and item.get("name") == part]
            if named:
                j = named[0]
            elif re.fullmatch(r"\d+", part) and int(part) < len(node):
                j = int(part)
            else:
                raise StudyError(f"parameter '{key}': no entry '{part}' in {where} (give its "
                                 f"name or index); it has {_listing(node)}")
            if last:
                return node, j, [*loc, j]
            node, loc = node[j], [*loc, j]
        else:
            raise StudyError(f"parameter '{key}': {where} is a value ({node!r}), not a table "
                             "or a list")
    raise AssertionError("unreachable")  # pragma: no cover


def apply_params(doc: dict[str, Any], params: Mapping[str, Scalar]) -> dict[str, Any]:
    """A deep copy of the TOML dict ``doc`` with each dotted parameter path set (see
    :func:`resolve_path`); a value replacing a table or a list is an error."""
    out = copy.deepcopy(doc)
    for key, value in params.items():
        parent, k, _ = resolve_path(out, key)
        old = parent[k] if (isinstance(parent, dict) and k in parent) or isinstance(
            parent, list) else None
        if isinstance(old, dict | list):
            kind = "table" if isinstance(old, dict) else "list"
            raise StudyError(f"parameter '{key}' names a {kind} ({_listing(old)}), not a value")
        parent[k] = value
    return out


def check_params(doc: dict[str, Any], params: Mapping[str, Scalar]) -> None:
    """Raise a :class:`StudyError` naming the parameter when ``params`` cannot be applied to
    ``doc`` or the result breaks the model file's schema (field types and ranges; the mesh
    and geometry are checked when the case runs)."""
    from stepcontact.io.modelfile import _validate

    d = apply_params(doc, params)
    try:
        _validate(d)
    except StepContactError as e:
        item = str(getattr(e, "item", ""))
        locs = {k: _loc_text(resolve_path(d, k)[2]) for k in params}
        blamed = [k for k, loc in locs.items() if item == loc or item.startswith(loc + ".")
                  or item.startswith(loc + "[")]
        text = " ".join(str(e).split())
        if blamed:
            k = blamed[0]
            parent, last, _ = resolve_path(d, k)
            hint = ""
            if "unknown field" in text and isinstance(parent, dict):
                known = [n for n in parent if n != last]
                hint = f"; {'.'.join(k.split('.')[:-1]) or 'the model file'} sets " \
                       f"{', '.join(map(repr, known)) or 'nothing'}"
            raise StudyError(f"parameter '{k}' = {params[k]!r}: {text}{hint}") from None
        raise StudyError(f"case {dict(params)}: {text}") from None


# --------------------------------------------------------------------------------------------
# model files: the case function
# --------------------------------------------------------------------------------------------
#: outputs a model-file case can report (units: λ of the segment's pattern; m; N; s)
MODEL_OUTPUTS: dict[str, str] = {
    "first_slip": "λ at the first slip in the last segment reached (NaN: none)",
    "first_opening": "λ at the first opening in the last segment reached (NaN: none)",
    "first_closing": "λ at the first closing in the last segment reached (NaN: none)",
    "equilibrium_lost": "λ at which equilibrium is lost (NaN: not lost)",
    "status": "run status (completed, equilibrium lost, …)",
    "message": "the run's closing message",
    "events": "number of events of the static run",
    "segment": "index of the last segment reached (the segment of the multipliers)",
    "lam_end": "load factor λ of the last state",
    "max_un": "max |u_n| over the CFEs and the states, m",
    "max_N": "max |N| over the CFEs and the states, N",
    "max_Q": "max |Q| over the CFEs and the states, N",
    "factorizations": "sparse factorisations of the static run (0: the worker's cached "
                      "condensation reused)",
    "dynamic_status": "status of the dynamic interval ('' without one)",
    "dynamic_events": "events of the dynamic interval",
    "dynamic_first_opening": "time of the first opening in the dynamic interval, s",
    "dynamic_max_un": "max |u_n| in the dynamic interval, m",
}
DEFAULT_OUTPUTS = ("first_slip", "first_opening", "first_closing", "equilibrium_lost",
                   "status", "events", "max_un", "max_N")
DYNAMIC_OUTPUTS = ("dynamic_status", "dynamic_events", "dynamic_first_opening")

_CACHE = threading.local()


def condensation_cache_info() -> dict[str, int]:
    """Hits, misses and size of this worker thread's condensation cache."""
    c = _cache()
    return {"hits": c["hits"], "misses": c["misses"], "size": len(c["lru"])}


def clear_condensation_cache() -> None:
    """Empty this worker thread's condensation cache and reset its counters."""
    for k in ("lru", "hits", "misses"):
        if hasattr(_CACHE, k):
            delattr(_CACHE, k)


def _cache() -> dict[str, Any]:
    if not hasattr(_CACHE, "lru"):
        _CACHE.lru, _CACHE.hits, _CACHE.misses = OrderedDict(), 0, 0
    return {"lru": _CACHE.lru, "hits": _CACHE.hits, "misses": _CACHE.misses}


def cached_condensation(model: Model, precision: str = "auto") -> Condensation:
    """The static condensation of ``model`` from this worker thread's LRU cache (keyed by
    :attr:`Condensation.fingerprint`, i.e. K₀ and B: friction, gaps, loads and program do
    not enter it), built on a miss.  Costs one assembly of the model to compute the key."""
    from stepcontact.fem.assembly import assemble
    from stepcontact.solver.condensation import _fingerprint, condense, static_operator

    system = assemble(model)
    K0, Bf, *_ = static_operator(system)
    fp = (_fingerprint(K0, Bf), precision)
    _cache()
    lru: OrderedDict = _CACHE.lru
    if fp in lru:
        _CACHE.hits += 1
        lru.move_to_end(fp)
        return lru[fp]
    _CACHE.misses += 1
    c = condense(system, precision=precision)
    lru[fp] = c
    while len(lru) > CACHE_SIZE:
        lru.popitem(last=False)
    return c


def _finite(v: float | None) -> float:
    return math.nan if v is None else float(v)


@dataclass(frozen=True)
class ModelCase:
    """The case function of a model-file sweep (picklable): apply the case's parameters to a
    deep copy of the model file's TOML dict, build and validate the model, run it as
    ``stepcontact run`` does (:func:`stepcontact.run`: the static program, then the
    ``[dynamics]`` interval when the file has one), write ``results_dir/<id>.nc`` (and
    ``<id>-dynamic.nc``) at the end of the case when ``save_results``, and return the scalar
    ``outputs`` (:data:`MODEL_OUTPUTS`).

    The static condensation is reused from the worker's cache (:func:`cached_condensation`)
    when cases share the mesh and stiffness: a friction or load sweep factorises once per
    worker.  A model built in stages has one factorisation per stage, made by each case's
    run (none is shared)."""

    doc: dict[str, Any]
    base_dir: str
    results_dir: str
    outputs: tuple[str, ...] = DEFAULT_OUTPUTS
    model_name: str = "model"
    slip: str = "exact"
    eps_p: float = 0.01
    max_events: int = 100_000
    precision: str = "auto"
    save_results: bool = True

    @property
    def sweep_key(self) -> str:
        """Hash of everything but the parameters that decides the outputs (the base model,
        the outputs and the run options): stored cases of another key run again."""
        blob = json.dumps([self.doc, list(self.outputs), self.slip, self.eps_p,
                           self.max_events, self.precision, self.save_results], sort_keys=True,
                          default=str)
        return hashlib.blake2b(blob.encode(), digest_size=8).hexdigest()

    def __call__(self, params: dict[str, Scalar]) -> dict[str, Output]:
        from stepcontact.io.modelfile import model_from_dict
        from stepcontact.solver.program import run

        case = current_case()
        cid = case.id if case is not None else case_id(params)
        d = apply_params(self.doc, params)
        model = model_from_dict(d, base_dir=self.base_dir)
        if not (d.get("model") or {}).get("name"):
            model = model.replace(name=self.model_name)
        result_path = Path(self.results_dir) / f"{cid}.nc"
        dyn_path = result_path.with_name(result_path.stem + "-dynamic.nc")
        if self.save_results:  # a stale dynamic result of an earlier run must not survive
            result_path.parent.mkdir(parents=True, exist_ok=True)
            dyn_path.unlink(missing_ok=True)
        condensation, built = None, 0
        if not getattr(model, "stages", ()):  # a staged run factorises each stage itself
            misses = condensation_cache_info()["misses"]
            condensation = cached_condensation(model, self.precision)
            built = condensation_cache_info()["misses"] - misses  # 1: factorised for the case

        def save(res) -> None:  # (written before the final dynamic interval runs)
            if self.save_results:
                res.save(result_path)

        out = run(model, slip=self.slip, eps_p=self.eps_p, max_events=self.max_events,
                  precision=self.precision, condensation=condensation, after_static=save)
        res = out.static
        mu = res.multipliers[-1] if res.multipliers else None
        a_un, a_N, a_Q = (np.abs(getattr(res, n)) for n in ("un", "N", "Q"))
        values: dict[str, Output] = {
            "first_slip": _finite(mu.first_slip if mu else None),
            "first_opening": _finite(mu.first_opening if mu else None),
            "first_closing": _finite(mu.first_closing if mu else None),
            "equilibrium_lost": _finite(mu.equilibrium_lost if mu else None),
            "status": res.status.value, "message": res.message,
            "events": len(res.events),
            "segment": int(mu.segment) if mu else -1,
            "lam_end": float(res.lam[-1]) if len(res.lam) else math.nan,
            "max_un": float(a_un.max(initial=0.0)), "max_N": float(a_N.max(initial=0.0)),
            "max_Q": float(a_Q.max(initial=0.0)),
            "factorizations": int(res.counters.get("factorizations", 0)) + built,
            "dynamic_status": "", "dynamic_events": 0,
            "dynamic_first_opening": math.nan, "dynamic_max_un": math.nan,
        }
        if out.dynamic is not None:
            dres = out.dynamic
            if self.save_results:
                dres.save(dyn_path)
            dmu = dres.multipliers[-1] if dres.multipliers else None
            values |= {"dynamic_status": dres.status.value, "dynamic_events": len(dres.events),
                       "dynamic_first_opening": _finite(dmu.first_opening if dmu else None),
                       "dynamic_max_un": float(np.abs(dres.un).max(initial=0.0))}
        elif model.dynamics is not None:
            values["dynamic_status"] = "not run (the static program did not complete)"
        return {k: values[k] for k in self.outputs}


# --------------------------------------------------------------------------------------------
# study files
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Study:
    """A loaded study file: its name, the base model file, the store directory, the cases
    and the case function."""

    name: str
    path: Path
    model_path: Path
    store: Path
    cases: list[Case]
    func: ModelCase


def _study_schema():
    from pydantic import BaseModel, ConfigDict, Field, model_validator

    class _Spec(BaseModel):
        model_config = ConfigDict(extra="forbid", allow_inf_nan=False, frozen=True)

    class StudySection(_Spec):
        """``[study]``: name, base model file, store directory, outputs and run options."""

        name: str | None = None
        model: str = Field(description="base model file, relative to the study file")
        output: str | None = Field(None, description="store directory, relative to the study "
                                   "file (default: the study file's name without .toml)")
        outputs: list[str] | None = None
        slip: Literal["exact", "article"] = "exact"
        eps_p: float = Field(0.01, ge=0)
        max_events: int = Field(100_000, ge=1)
        precision: Literal["auto", "float64", "float32"] = "auto"
        results: bool = Field(True, description="write each case's result file to "
                              "STORE/results/<id>.nc")

        @model_validator(mode="after")
        def _known_outputs(self) -> StudySection:
            for i, o in enumerate(self.outputs or []):
                if o not in MODEL_OUTPUTS:
                    raise ValueError(f"outputs[{i}]: unknown output '{o}'; use "
                                     f"{', '.join(MODEL_OUTPUTS)}")
            if self.outputs is not None and not self.outputs:
                raise ValueError("outputs: give at least one output (or leave it out)")
            return self

    ScalarT = float | int | str | bool

    class StudyFile(_Spec):
        """The study file: ``[study]`` and either ``[grid]`` or ``[[cases]]``."""

        study: StudySection
        grid: dict[str, list[ScalarT]] | None = None
        cases: list[dict[str, ScalarT]] | None = None

        @model_validator(mode="after")
        def _one_form(self) -> StudyFile:
            if (self.grid is None) == (self.cases is None):
                raise ValueError("give either a [grid] table or [[cases]] tables")
            return self

    return StudyFile


#: from this many cases on, ``load_study`` announces their number before checking them
ANNOUNCE_CASES = 1000


def _case_count(spec: Any) -> tuple[int, str]:
    """The number of cases of a study file and how it comes about (before making them)."""
    if spec.grid is not None:
        n = math.prod(len(v) for v in spec.grid.values())
        return n, " × ".join(f"{len(v)} values of {k}" for k, v in spec.grid.items())
    return len(spec.cases or []), "[[cases]] tables"


def load_study(path: str | os.PathLike[str], *, force: bool = False,
               announce: Callable[[str], None] | None = None) -> Study:
    """Read and validate a study file (TOML): ``[study]`` (``model``, ``name``, ``output``,
    ``outputs``, ``slip``, ``eps_p``, ``max_events``, ``precision``) and either ``[grid]``
    ({dotted key = [values]}, their Cartesian product) or ``[[cases]]`` (one table of
    {dotted key = value} per case, optional ``id``).  Every case's parameters are applied to
    the base model file and checked against its schema here, so that a wrong key or value is
    a :class:`StudyError` naming it before anything runs.

    A study of more than :data:`~stepcontact.study.sweep.MAX_CASES` cases is refused (with
    their count) unless ``force``; ``announce`` (e.g. a print to stderr) is told the number
    of cases before they are made and checked, when there are more than
    :data:`ANNOUNCE_CASES` (the sweep's progress bar counts them as they run)."""
    import tomllib

    from pydantic import ValidationError

    from stepcontact.io.modelfile import _message, _path, _read_toml

    path = Path(path)
    if not path.is_file():
        raise StudyError(f"study file not found: {path}")
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as e:
        raise StudyError(f"{path}: not a valid TOML file: {e}") from None
    try:
        spec = _study_schema().model_validate(data)
    except ValidationError as e:
        err = e.errors()[0]
        more = f" (and {len(e.errors()) - 1} more problems)" if len(e.errors()) > 1 else ""
        raise StudyError(f"{path}: {_path(err['loc'])}: {_message(err)}{more}") from None
    s = spec.study
    model_path = (path.parent / s.model).resolve()
    if not model_path.is_file():
        raise StudyError(f"{path}: study.model: model file not found: {model_path}")
    try:
        doc = _read_toml(model_path)
    except StepContactError as e:
        raise StudyError(f"{path}: study.model: {' '.join(str(e).split())}") from None
    n, how = _case_count(spec)
    if n > MAX_CASES and not force:
        raise StudyError(f"{path}: {n:,} cases ({how}): more than {MAX_CASES:,}, which would "
                         "run for hours or days; give fewer values, or --force (force=True) "
                         "to run them all")
    if announce is not None and n > ANNOUNCE_CASES:  # their checks take a while
        announce(f"sweep '{s.name or path.stem}': {n:,} cases ({how}); checking their "
                 "parameters")
    try:
        cases = grid(spec.grid) if spec.grid is not None else cases_from_list(spec.cases or [])
        for c in cases:
            check_params(doc, c.params)
    except StudyError as e:
        raise StudyError(f"{path}: {e}") from None
    outputs = tuple(s.outputs) if s.outputs else DEFAULT_OUTPUTS + (
        DYNAMIC_OUTPUTS if doc.get("dynamics") is not None else ())
    store = path.parent / s.output if s.output else path.with_suffix("")
    model_name = (doc.get("model") or {}).get("name") or model_path.stem
    func = ModelCase(doc=doc, base_dir=str(model_path.parent),
                     results_dir=str((store / "results").resolve()), outputs=outputs,
                     model_name=model_name, slip=s.slip, eps_p=s.eps_p,
                     max_events=s.max_events, precision=s.precision,
                     save_results=s.results)
    return Study(name=s.name or path.stem, path=path, model_path=model_path, store=store,
                 cases=cases, func=func)


def run_study(study: Study | str | os.PathLike[str], **kwargs: Any) -> xr.Dataset:
    """Run a study file (or a loaded :class:`Study`) with :func:`run_sweep`: ``kwargs`` are
    its executor options (``executor``, ``workers``, ``progress``, ``retries``, ``rerun``)."""
    if not isinstance(study, Study):
        study = load_study(study)
    return run_sweep(study.cases, study.func, study.store, name=study.name, **kwargs)


__all__ = [
    "DEFAULT_OUTPUTS", "DYNAMIC_OUTPUTS", "MODEL_OUTPUTS", "ModelCase", "Study",
    "apply_params", "cached_condensation", "check_params", "clear_condensation_cache",
    "condensation_cache_info", "load_study", "resolve_path", "run_study",
]
