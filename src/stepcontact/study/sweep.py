"""Parameter sweeps: many runs of one function (or one model file) over a grid of parameters,
resumable, on a local process pool or a dask.distributed cluster.

The core is independent of the solver::

    cases = grid(friction=[0.4, 0.5, 0.6], scale=[1.0, 2.0])     # 6 cases, ids "friction=0.4,..."
    ds = run_sweep(cases, func, "store")                          # xarray.Dataset along "case"
    to_grid(ds).first_slip.plot(x="friction", hue="scale")        # the same, on the grid axes

``func(params) -> {name: float | int | str | bool | None | ndarray}`` is a top-level (picklable)
function called once per case; ``None`` is stored as NaN.  Each finished case is written at
once to ``store/cases/<id>.nc`` (a temporary file in the same directory, then
:func:`os.replace`), with its parameters (JSON attribute ``params``) and outputs; a re-run skips
the cases whose file holds the same parameters and status ``ok`` (a changed parameter, a
failed case or a missing file: the case runs again), so an interrupted sweep loses nothing
that finished.  The collected ``store/sweep.nc`` is written atomically at the end;
:func:`collect` rebuilds it from the case files.

The model-file front end (:mod:`stepcontact.study.studyfile`: ``stepcontact sweep``) sets
dotted paths of a model file's TOML dict (``interfaces.joint.friction``,
``patterns.push.loads.0.normal``) and runs each case as ``stepcontact run`` would.

Threads: every worker process (pool or dask) holds BLAS/OpenMP to one thread
(:func:`pin_threads`).  With W workers each starting as many BLAS threads as there are cores,
the machine is oversubscribed W-fold; on a 2-core machine that made the 256-column blocked
solves of a condensation 30–80× slower.  One thread per worker, one worker per core.
"""

from __future__ import annotations

import contextlib
import contextvars
import hashlib
import itertools
import json
import math
import os
import re
import time
import traceback
import uuid
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from stepcontact.errors import StepContactError
from stepcontact.io.atomic import write_netcdf, write_text

if TYPE_CHECKING:
    import xarray as xr


Scalar = float | int | str | bool
Output = float | int | str | bool | None | np.ndarray

#: ids longer than this are shortened to a readable prefix and a hash
MAX_ID_LENGTH = 64
#: a sweep of more cases is refused unless forced (``stepcontact sweep --force``): at a
#: second or more per case it would run for hours to days and hold a dataset of that size
MAX_CASES = 10_000
#: environment variables that hold BLAS/OpenMP to one thread in a worker
THREAD_VARIABLES = ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                    "BLIS_NUM_THREADS", "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")

STATUS_OK = "ok"
STATUS_FAILED = "failed"
STATUS_MISSING = "missing"  #: in a collected dataset: the case has not run (yet)


class StudyError(StepContactError, ValueError):
    """A study (grid, case list, study file or parameter path) is wrong; the message names the
    offending key."""


# --------------------------------------------------------------------------------------------
# cases
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Case:
    """One run of a sweep: ``id`` (file-system safe, unique in the sweep) and ``params``
    ({name: scalar}, the argument of the case function)."""

    id: str
    params: dict[str, Scalar]


def _check_scalar(key: str, v: Any) -> Scalar:
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, bool | int | str):
        return v
    if isinstance(v, float):
        if not math.isfinite(v):
            raise StudyError(f"parameter '{key}': {v} is not a finite number")
        return v
    raise StudyError(f"parameter '{key}': {v!r} is not a scalar (float, int, str or bool)")


def _fmt(v: Scalar) -> str:
    if isinstance(v, float):
        return repr(v)  # shortest round-trip form: 0.5, 2.0, 1e-05
    return str(v)


_UNSAFE = re.compile(r"[^A-Za-z0-9._=,+-]+")


def _short_keys(keys: Sequence[str]) -> dict[str, str]:
    """Each key's last dotted component when those are unique, else the whole key."""
    last = [k.rsplit(".", 1)[-1] for k in keys]
    return dict(zip(keys, last if len(set(last)) == len(last) else keys, strict=True))


def _params_hash(params: Mapping[str, Scalar]) -> str:
    return hashlib.blake2b(_params_json(params).encode(), digest_size=4).hexdigest()


def case_id(params: Mapping[str, Scalar], short: Mapping[str, str] | None = None) -> str:
    """A readable, file-system safe id: ``friction=0.5,thickness=2`` (characters other than
    letters, digits and ``._=,+-`` become ``_``); longer than :data:`MAX_ID_LENGTH`: a prefix
    of it and a hash of the parameters."""
    short = short or {k: k for k in params}
    text = ",".join(f"{short[k]}={_fmt(v)}" for k, v in params.items())
    text = _UNSAFE.sub("_", text).strip("._") or "case"
    if len(text) > MAX_ID_LENGTH:
        text = f"{text[:MAX_ID_LENGTH - 10].rstrip('._,=')}~{_params_hash(params)}"
    return text


def _unique(cases: list[Case]) -> list[Case]:
    """Ids made unique (a clash after sanitising: the clashing ids get a hash suffix)."""
    seen: dict[str, int] = {}
    for c in cases:
        seen[c.id] = seen.get(c.id, 0) + 1
    out = []
    for c in cases:
        if seen[c.id] > 1:
            c = Case(f"{c.id[:MAX_ID_LENGTH - 10]}~{_params_hash(c.params)}", c.params)
        out.append(c)
    ids = [c.id for c in out]
    if len(set(ids)) != len(ids):
        dup = next(i for i in ids if ids.count(i) > 1)
        raise StudyError(f"two cases have the same id and parameters: '{dup}'")
    return out


def grid(axes: Mapping[str, Iterable[Scalar]] | None = None, /,
         **more: Iterable[Scalar]) -> list[Case]:
    """The Cartesian product of parameter axes, the last axis varying fastest.

    ``grid(friction=[0.4, 0.6], scale=[1, 2])`` or, for dotted model-file keys,
    ``grid({"interfaces.joint.friction": [0.4, 0.6]})``.  Ids use each key's last dotted
    component when those are unique (``friction=0.4,scale=1``), else the whole key.
    """
    spec = {**(axes or {}), **more}
    if not spec:
        raise StudyError("grid: give at least one parameter axis")
    values: dict[str, list[Scalar]] = {}
    for key, vals in spec.items():
        if isinstance(vals, str | bytes) or not isinstance(vals, Iterable):
            raise StudyError(f"grid axis '{key}': give a list of values, got {vals!r}")
        vs = [_check_scalar(key, v) for v in vals]
        if not vs:
            raise StudyError(f"grid axis '{key}': no values")
        if len(set(map(_fmt, vs))) != len(vs):
            raise StudyError(f"grid axis '{key}': repeated values {vs}")
        values[key] = vs
    short = _short_keys(list(values))
    cases = []
    for combo in itertools.product(*values.values()):
        params = dict(zip(values, combo, strict=True))
        cases.append(Case(case_id(params, short), params))
    return _unique(cases)


def cases_from_list(rows: Iterable[Mapping[str, Scalar]]) -> list[Case]:
    """Cases from a list of parameter dicts; an ``id`` entry (optional) names the case."""
    rows = [dict(r) for r in rows]
    if not rows:
        raise StudyError("no cases")
    keys = list(dict.fromkeys(k for r in rows for k in r if k != "id"))
    short = _short_keys(keys)
    cases = []
    named: dict[str, int] = {}  # an id the user gave -> the first case that has it
    for i, r in enumerate(rows):
        given = r.pop("id", None)
        params = {k: _check_scalar(k, v) for k, v in r.items()}
        if given is not None:
            cid = _UNSAFE.sub("_", str(given)).strip("._")
            if not cid:
                raise StudyError(f"cases[{i}].id: {given!r} is not a usable file name")
            if cid in named:  # two cases the user named alike: not renamed behind their back
                j = named[cid]
                same = "" if cid == str(given) else f" (as a file name: '{cid}')"
                raise StudyError(f"cases[{i}].id: {given!r}{same} is also the id of "
                                 f"cases[{j}]: give every case its own id")
            named[cid] = i
        else:
            cid = case_id(params, short)
        cases.append(Case(cid, params))
    return _unique(cases)


def _params_json(params: Mapping[str, Scalar]) -> str:
    return json.dumps(dict(params), sort_keys=True)


# --------------------------------------------------------------------------------------------
# workers: thread pinning, the case being run, the wrapper
# --------------------------------------------------------------------------------------------
_PINNED = False
_LIMITS: Any = None
_CURRENT: contextvars.ContextVar[Case | None] = contextvars.ContextVar("case", default=None)


def pin_threads() -> None:
    """Hold BLAS and OpenMP to one thread in this process (idempotent): sets
    OMP/MKL/OPENBLAS_NUM_THREADS=1 (for libraries loaded later) and applies
    ``threadpoolctl.threadpool_limits(1)`` to those already loaded.  Run in every worker of
    the process pool (its initializer) and in dask tasks: W workers × (cores) BLAS threads
    oversubscribe the machine and made blocked solves 30–80× slower."""
    global _PINNED, _LIMITS
    if _PINNED:
        return
    for var in THREAD_VARIABLES:
        os.environ[var] = "1"
    from threadpoolctl import threadpool_limits

    _LIMITS = threadpool_limits(1)
    _PINNED = True


#: seconds between two checks of a pool worker that its parent still lives
PARENT_POLL = 0.5

# what a pool worker runs first (its initializer): standard library only, so that it runs
# before the worker imports stepcontact (seconds on a busy machine, during which a parent
# killed outright would otherwise leave the worker to compute its case for nobody)
_DIE_WITH_PARENT = """
import os, signal, sys, threading, time
parent = {parent}
if os.getppid() != parent:
    os._exit(1)
signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C: the parent ends its workers
if sys.platform.startswith("linux"):
    try:
        import ctypes
        ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL), 0, 0, 0)
    except Exception:
        pass
    if os.getppid() != parent:
        os._exit(1)
def _watch():
    while True:
        time.sleep({poll})
        if os.getppid() != parent:
            os._exit(1)
threading.Thread(target=_watch, name="stepcontact-parent-watch", daemon=True).start()
"""


def _worker_initializer(parent: int) -> Callable[[], Any]:
    """The pool workers' initializer: they die with their parent ``parent``
    (:func:`die_with_parent`) and leave Ctrl-C (SIGINT, sent to the whole terminal's process
    group) to it, which ends them (:func:`_stop_pool`); a picklable callable of the standard
    library only (BLAS is pinned to one thread by each case, :func:`_run_case`)."""
    import functools

    return functools.partial(exec, _DIE_WITH_PARENT.format(parent=int(parent),
                                                           poll=float(PARENT_POLL)), {})


def die_with_parent(parent: int) -> None:
    """End this process (a pool worker) when its parent ``parent`` dies: on Linux the kernel
    sends SIGKILL at once (``prctl(PR_SET_PDEATHSIG)``), elsewhere (and as a fallback) a
    daemon thread checks every :data:`PARENT_POLL` seconds that the parent still lives.  A
    parent killed outright (SIGKILL) then leaves no worker computing on for nobody.  SIGINT
    is ignored from then on (the parent ends its workers on Ctrl-C)."""
    _worker_initializer(parent)()


@contextlib.contextmanager
def _pinned_environment() -> Iterator[None]:
    """Set the thread variables in this process while workers are started (they inherit the
    environment, so BLAS starts with one thread before NumPy is imported there)."""
    old = {v: os.environ.get(v) for v in THREAD_VARIABLES}
    for v in THREAD_VARIABLES:
        os.environ[v] = "1"
    try:
        yield
    finally:
        for v, val in old.items():
            if val is None:
                os.environ.pop(v, None)
            else:
                os.environ[v] = val


def current_case() -> Case | None:
    """The case being run by this thread (inside a case function), else None."""
    return _CURRENT.get()


@dataclass
class Outcome:
    """What a case produced: ``status`` "ok" or "failed", the ``message`` of a failure, the
    ``outputs`` and the wall time ``seconds`` (s)."""

    case: Case
    status: str
    outputs: dict[str, Output] = field(default_factory=dict)
    message: str = ""
    seconds: float = 0.0
    attempts: int = 1


def _normalise(outputs: Any) -> dict[str, Output]:
    if not isinstance(outputs, Mapping):
        raise TypeError(f"the case function must return a dict of outputs, got "
                        f"{type(outputs).__name__}")
    out: dict[str, Output] = {}
    for k, v in outputs.items():
        if not isinstance(k, str) or not k or "/" in k:
            raise TypeError(f"output name {k!r}: give a non-empty string without '/'")
        if k in ("case", "case_status", "case_message"):
            raise TypeError(f"output name '{k}' is reserved")
        if isinstance(v, np.generic):
            v = v.item()
        if v is None or isinstance(v, bool | int | float | str):
            out[k] = v
        elif isinstance(v, np.ndarray | list | tuple):
            a = np.asarray(v)
            if a.dtype.kind not in "biuf":
                raise TypeError(f"output '{k}': arrays must be numeric, got {a.dtype}")
            out[k] = a
        else:
            raise TypeError(f"output '{k}': {type(v).__name__} is not a float, int, str, "
                            "bool, None or numeric array")
    return out


def _run_case(func: Callable[[dict[str, Scalar]], Mapping[str, Output]], case: Case,
              retries: int = 0, pin: bool = False) -> Outcome:
    """Run ``func`` on one case (``retries`` more attempts after an exception); an exception
    becomes a failed outcome carrying its message."""
    if pin:
        pin_threads()
    t0 = time.perf_counter()
    token = _CURRENT.set(case)
    try:
        message = ""
        for attempt in range(1, retries + 2):
            try:
                outputs = _normalise(func(dict(case.params)))
                return Outcome(case, STATUS_OK, outputs, "", time.perf_counter() - t0, attempt)
            except Exception as e:  # noqa: BLE001 - a failing case is a result
                message = " ".join(f"{type(e).__name__}: {e}".split())
                if not isinstance(e, StepContactError | TypeError):
                    tb = traceback.extract_tb(e.__traceback__)
                    if tb:
                        message += f" (at {Path(tb[-1].filename).name}:{tb[-1].lineno})"
        return Outcome(case, STATUS_FAILED, {}, message, time.perf_counter() - t0, retries + 1)
    finally:
        _CURRENT.reset(token)


# --------------------------------------------------------------------------------------------
# the store: case files, manifest, collected dataset
# --------------------------------------------------------------------------------------------
def _atomic_netcdf(ds: xr.Dataset, path: Path) -> None:
    write_netcdf(ds, path)


def _atomic_text(text: str, path: Path) -> None:
    write_text(path, text)


def case_path(store: str | os.PathLike[str], case: Case | str) -> Path:
    """``store/cases/<id>.nc``."""
    cid = case.id if isinstance(case, Case) else case
    return Path(store) / "cases" / f"{cid}.nc"


def _case_dataset(outcome: Outcome, key: str) -> xr.Dataset:
    import xarray as xr

    data_vars = {}
    for name, v in outcome.outputs.items():
        if isinstance(v, np.ndarray):
            data_vars[name] = ([f"{name}_dim{i}" for i in range(v.ndim)], v)
        elif v is None:
            data_vars[name] = ((), np.nan)
        elif isinstance(v, bool):
            data_vars[name] = ((), np.int8(v))
        else:
            data_vars[name] = ((), v)
    return xr.Dataset(data_vars, attrs={
        "case": outcome.case.id, "params": _params_json(outcome.case.params),
        "status": outcome.status, "message": outcome.message, "key": key,
        "seconds": float(outcome.seconds), "attempts": int(outcome.attempts),
        "outputs": json.dumps(list(outcome.outputs)),
    })


def _write_case(store: Path, outcome: Outcome, key: str) -> Path:
    path = case_path(store, outcome.case)
    path.parent.mkdir(parents=True, exist_ok=True)
    _atomic_netcdf(_case_dataset(outcome, key), path)
    return path


def _read_case(path: Path) -> xr.Dataset | None:
    """A case file's dataset, or None when it is missing or unreadable."""
    import xarray as xr

    if not path.is_file():
        return None
    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            return ds.load()
    except (OSError, ValueError, KeyError):
        return None


def is_done(store: str | os.PathLike[str], case: Case, key: str = "") -> bool:
    """True when the store holds a finished (status ok) result of ``case`` with the same
    parameters (and function ``key``)."""
    ds = _read_case(case_path(store, case))
    return ds is not None and _matches(ds, case, key) and ds.attrs.get("status") == STATUS_OK


def _matches(ds: xr.Dataset, case: Case, key: str) -> bool:
    return (ds.attrs.get("params") == _params_json(case.params)
            and ds.attrs.get("key", "") == key)


def _write_manifest(store: Path, cases: Sequence[Case], key: str) -> None:
    store.mkdir(parents=True, exist_ok=True)
    _atomic_text(json.dumps({"key": key, "cases": [{"id": c.id, "params": c.params}
                                                   for c in cases]}, indent=1),
                 store / "sweep.json")


def _read_manifest(store: Path) -> tuple[list[Case], str] | None:
    path = store / "sweep.json"
    if not path.is_file():
        return None
    data = json.loads(path.read_text(encoding="utf-8"))
    return [Case(c["id"], c["params"]) for c in data["cases"]], data.get("key", "")


def _column(values: list[Any]) -> tuple[np.ndarray, dict[str, Any]]:
    """One output over the cases (None: missing) as an array: strings ("" missing), integers
    (when none is missing), else float64 with NaN."""
    present = [v for v in values if v is not None]
    if present and all(isinstance(v, str) for v in present):
        return np.array(["" if v is None else v for v in values], dtype=str), {}
    if present and all(isinstance(v, int | np.integer) for v in present) \
            and len(present) == len(values):
        return np.array(values, dtype=np.int64), {}
    return np.array([np.nan if v is None else float(v) for v in values], dtype=float), {}


def _param_column(values: list[Any]) -> np.ndarray:
    if all(isinstance(v, str) for v in values):
        return np.array(values, dtype=str)
    if all(isinstance(v, bool) for v in values):
        return np.array(values, dtype=bool)
    if all(isinstance(v, int) and not isinstance(v, bool) for v in values):
        return np.array(values, dtype=np.int64)
    if all(isinstance(v, int | float) and not isinstance(v, bool) for v in values):
        return np.array(values, dtype=float)
    return np.array([_fmt(v) for v in values], dtype=str)


def collect(store: str | os.PathLike[str], cases: Sequence[Case] | None = None,
            key: str | None = None, write: bool = True) -> xr.Dataset:
    """The sweep's dataset rebuilt from its case files (and written to ``store/sweep.nc``
    atomically when ``write``).

    ``cases``: default the sweep's manifest (``store/sweep.json``, written by
    :func:`run_sweep`), else every case file of the store.  Layout: dimension ``case`` (the
    ids, in the order of the cases); one coordinate per parameter along ``case``; variables
    ``status`` ("ok", "failed" or "missing": not run or run with other parameters),
    ``message`` (of a failure) and every output — scalars along ``case`` (float64 with NaN
    where a case has no value, int64 or str), arrays along ``case`` and ``<name>_dim<i>``
    (padded with NaN).  Attributes: ``params`` (JSON list of the parameter names) and
    ``grid`` (1 when the cases are a full Cartesian grid: :func:`to_grid`).
    """
    import xarray as xr

    store = Path(store)
    manifest = _read_manifest(store)
    if cases is None:
        if manifest is not None:
            cases, mkey = manifest
            key = mkey if key is None else key
        else:
            cases = []
            for p in sorted((store / "cases").glob("*.nc")):
                ds = _read_case(p)
                if ds is not None:
                    cases.append(Case(str(ds.attrs["case"]), json.loads(ds.attrs["params"])))
                    if key is None:
                        key = str(ds.attrs.get("key", ""))
    key = key or ""
    cases = list(cases)
    status, message = [], []
    rows: list[dict[str, Any]] = []
    names: dict[str, None] = {}
    for c in cases:
        ds = _read_case(case_path(store, c))
        if ds is None or not _matches(ds, c, key):
            status.append(STATUS_MISSING)
            message.append("")
            rows.append({})
            continue
        status.append(str(ds.attrs.get("status", STATUS_FAILED)))
        message.append(str(ds.attrs.get("message", "")))
        order = json.loads(ds.attrs.get("outputs", "[]"))
        row = {}
        for n in order:
            v = ds[n].values
            row[n] = v.item() if v.ndim == 0 else v
            names[n] = None
        rows.append(row)
    keys = list(dict.fromkeys(k for c in cases for k in c.params))
    coords: dict[str, Any] = {"case": ("case", np.array([c.id for c in cases], dtype=str))}
    for k in keys:
        if any(k not in c.params for c in cases):
            coords[k] = ("case", np.array([_fmt(c.params[k]) if k in c.params else ""
                                           for c in cases], dtype=str))
        else:
            coords[k] = ("case", _param_column([c.params[k] for c in cases]))
    data_vars: dict[str, Any] = {"case_status": ("case", np.array(status, dtype=str)),
                                 "case_message": ("case", np.array(message, dtype=str))}
    for n in names:
        values = [r.get(n) for r in rows]
        arrays = [v for v in values if isinstance(v, np.ndarray)]
        if arrays:
            ndim = max(a.ndim for a in arrays)
            shape = tuple(max(a.shape[i] if i < a.ndim else 1 for a in arrays)
                          for i in range(ndim))
            out = np.full((len(cases), *shape), np.nan)
            for i, v in enumerate(values):
                if isinstance(v, np.ndarray):
                    a = v.reshape(v.shape + (1,) * (ndim - v.ndim))
                    out[(i, *(slice(0, s) for s in a.shape))] = a
                elif v is not None:
                    out[i] = float(v)
            data_vars[n] = (("case", *(f"{n}_dim{i}" for i in range(ndim))), out)
        else:
            data_vars[n] = ("case", _column(values)[0])
    ds = xr.Dataset(data_vars, coords=coords, attrs={
        "params": json.dumps(keys), "grid": int(_is_full_grid(cases, keys)),
        "cases": len(cases), "failed": status.count(STATUS_FAILED),
        "missing": status.count(STATUS_MISSING),
    })
    if write:
        store.mkdir(parents=True, exist_ok=True)
        _atomic_netcdf(ds, store / "sweep.nc")
    return ds


def _is_full_grid(cases: Sequence[Case], keys: Sequence[str]) -> bool:
    if not cases or not keys or any(set(c.params) != set(keys) for c in cases):
        return False
    combos = {tuple(_fmt(c.params[k]) for k in keys) for c in cases}
    sizes = [len({_fmt(c.params[k]) for c in cases}) for k in keys]
    return len(combos) == len(cases) == math.prod(sizes)


def to_grid(ds: xr.Dataset) -> xr.Dataset:
    """A collected sweep of a full grid reshaped onto its parameter axes: the dimension
    ``case`` becomes one dimension per parameter (sorted values), ready to plot, e.g.
    ``to_grid(ds).first_slip.plot(x="friction", hue="scale")``; the case ids stay as the
    variable ``case_id``."""
    keys = json.loads(ds.attrs.get("params", "[]"))
    if not keys or not int(ds.attrs.get("grid", 0)):
        raise StudyError("to_grid: the cases are not a full Cartesian grid of their "
                         "parameters (use the flat dataset, dimension 'case')")
    flat = ds.assign(case_id=("case", ds["case"].values)).drop_vars("case")
    out = flat.set_index(case=list(keys)).unstack("case")
    return out.transpose(*keys, ...)


# --------------------------------------------------------------------------------------------
# running a sweep
# --------------------------------------------------------------------------------------------
Executor = Literal["process", "serial"] | str | Any


def _workers(workers: int | None, n: int) -> int:
    if workers is None:
        try:
            workers = len(os.sched_getaffinity(0))
        except AttributeError:  # pragma: no cover - not on Linux
            workers = os.cpu_count() or 1
    return max(1, min(int(workers), max(n, 1)))


class _Progress:
    """Rich progress bar on stderr: cases done / total, failures, time left (mean wall time
    of a finished case × cases remaining / workers)."""

    def __init__(self, total: int, skipped: int, workers: int, enabled: bool, name: str):
        from rich.console import Console
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn

        self.workers, self.total, self.ran, self.failed = workers, total, 0, 0
        self.seconds = 0.0  # wall time of the finished cases, s
        self.progress = Progress(
            TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
            TextColumn("failed: {task.fields[failed]}"), TextColumn("{task.fields[left]}"),
            console=Console(stderr=True), transient=True, disable=not enabled)
        self.task = self.progress.add_task(f"sweep '{name}'" if name else "sweep",
                                           total=total, completed=skipped, failed=0, left="")

    def __enter__(self) -> _Progress:
        self.progress.__enter__()
        return self

    def __exit__(self, *exc: Any) -> None:
        self.progress.__exit__(*exc)

    def done(self, outcome: Outcome) -> None:
        self.ran += 1
        self.failed += outcome.status != STATUS_OK
        self.seconds += outcome.seconds
        task = self.progress.tasks[0]
        remaining = self.total - (task.completed + 1)
        left = self.seconds / self.ran * remaining / self.workers
        self.progress.update(self.task, advance=1, failed=self.failed,
                             left=f"left ~{left:.0f} s" if remaining else "")


def run_sweep(
    cases: Sequence[Case],
    func: Callable[[dict[str, Scalar]], Mapping[str, Output]],
    store: str | os.PathLike[str],
    *,
    executor: Executor = "process",
    workers: int | None = None,
    progress: bool = True,
    retries: int = 0,
    rerun: bool = False,
    key: str | None = None,
    name: str = "",
    on_result: Callable[[Outcome], None] | None = None,
) -> xr.Dataset:
    """Run ``func(case.params)`` for every case not already done and return the collected
    dataset (also written to ``store/sweep.nc``; layout: :func:`collect`).

    Parameters
    ----------
    cases : sequence of Case
        From :func:`grid` or :func:`cases_from_list` (ids unique).
    func : callable
        ``func(params) -> {name: value}``, a top-level (picklable) function or object; values
        float, int, str, bool, None (stored as NaN) or numeric arrays.  An exception marks
        the case failed (its message is stored) and the sweep goes on.
    store : path
        Directory of the sweep: ``cases/<id>.nc`` (one per finished case, written as soon as
        it finishes), ``sweep.json`` (the cases), ``sweep.nc`` (the collected dataset).
    executor : "process", "serial", a dask scheduler address or a ``distributed.Client``
        ``process`` (default): a local pool of ``workers`` processes (spawn context, BLAS
        pinned to one thread each); ``serial``: in this process, one case after another
        (debugging, tests); an address such as ``"tcp://10.0.0.5:8786"`` or a Client: the
        dask.distributed cluster (tasks pin BLAS to one thread in their worker).  The results
        do not depend on the executor.
    workers : int, optional
        Processes of the local pool (default: the CPU cores available).
    progress : bool
        Show a progress bar on stderr.
    retries : int
        Further attempts of a failing case within this run (a failed case is also retried
        by the next run of the sweep).
    rerun : bool
        Run every case again, even those already done.
    key : str, optional
        Identifies what ``func`` computes: stored with each case, and a case stored under
        another key runs again.  Default: ``func.sweep_key`` if it has one, else "".
    name : str
        Shown in the progress bar.
    on_result : callable, optional
        Called in this process with each :class:`Outcome` as it is stored.
    """
    store = Path(store)
    cases = list(cases)
    ids = [c.id for c in cases]
    if len(set(ids)) != len(ids):
        raise StudyError("the cases' ids are not unique")
    if retries < 0:
        raise StudyError(f"retries: {retries} must be ≥ 0")
    key = key if key is not None else str(getattr(func, "sweep_key", ""))
    _write_manifest(store, cases, key)
    todo = [c for c in cases if rerun or not is_done(store, c, key)]
    n_workers = 1 if executor == "serial" else _workers(workers, len(todo))

    def finish(outcome: Outcome) -> None:
        _write_case(store, outcome, key)
        bar.done(outcome)
        if on_result is not None:
            on_result(outcome)

    with _Progress(len(cases), len(cases) - len(todo), n_workers, progress, name) as bar:
        if not todo:
            pass
        elif executor == "serial":
            from threadpoolctl import threadpool_limits

            with threadpool_limits(limits=1):  # as in a worker: one thread per case
                for c in todo:
                    finish(_run_case(func, c, retries))
        elif executor == "process":
            _run_pool(func, todo, retries, n_workers, finish)
        else:
            _run_dask(func, todo, retries, executor, finish)
    return collect(store, cases, key)


def _run_pool(func: Callable, todo: list[Case], retries: int, workers: int,
              finish: Callable[[Outcome], None]) -> None:
    import multiprocessing

    ctx = multiprocessing.get_context("spawn")
    with _pinned_environment(), ProcessPoolExecutor(workers, mp_context=ctx,
                                                    initializer=_worker_initializer(
                                                        os.getpid())) as pool:
        pending = {pool.submit(_run_case, func, c, retries, True): c for c in todo}
        try:
            while pending:
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for fut in done:
                    case = pending.pop(fut)
                    finish(_outcome_of(fut, case))
        except BaseException:  # Ctrl-C, SIGTERM (stepcontact.io.interrupt), an error
            _stop_pool(pool, pending)
            raise


def _stop_pool(pool: ProcessPoolExecutor, pending: Iterable[Any]) -> None:
    """Cancel the cases not started and end the workers at once (the cases running are
    lost; the finished ones are stored): the pool's exit then does not wait for them."""
    for fut in pending:
        fut.cancel()
    procs = list((getattr(pool, "_processes", None) or {}).values())
    for p in procs:
        with contextlib.suppress(Exception):
            p.terminate()
    for p in procs:
        with contextlib.suppress(Exception):
            p.join(5)
            if p.is_alive():
                p.kill()
    pool.shutdown(wait=False, cancel_futures=True)


def _outcome_of(fut: Any, case: Case) -> Outcome:
    """The outcome a worker's future holds; a future that raises (a dead or lost worker,
    unpicklable data) is a failed case with the error's message."""
    try:
        return fut.result()
    except Exception as e:  # noqa: BLE001 - the sweep goes on
        return Outcome(case, STATUS_FAILED, {}, " ".join(f"{type(e).__name__}: {e}".split()))


def _run_dask(func: Callable, todo: list[Case], retries: int, executor: Any,
              finish: Callable[[Outcome], None]) -> None:
    try:
        import distributed
    except ImportError as e:  # pragma: no cover - distributed is a dependency
        raise StudyError(f"a dask scheduler needs the package 'distributed' ({e})") from None
    own = isinstance(executor, str)
    if own and not re.match(r"^[a-z]+://", executor) and ":" not in executor:
        raise StudyError(f"executor '{executor}': use 'process', 'serial', a dask scheduler "
                         "address (tcp://HOST:PORT) or a distributed.Client")
    client = distributed.Client(executor, timeout="30s") if own else executor
    token = uuid.uuid4().hex[:8]
    try:
        futures = {client.submit(_run_case, func, c, retries, True, pure=False,
                                 key=f"stepcontact-sweep-{token}-{i}"): c
                   for i, c in enumerate(todo)}
        for fut in distributed.as_completed(list(futures)):
            case = futures[fut]
            finish(_outcome_of(fut, case))
            fut.release()
    finally:
        if own:
            client.close()


__all__ = [
    "MAX_CASES", "Case", "Outcome", "StudyError", "case_id", "case_path", "cases_from_list",
    "collect", "current_case", "grid", "is_done", "pin_threads", "run_sweep", "to_grid",
]
