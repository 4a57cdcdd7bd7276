"""A result file as ``plot``, ``info`` and ``export`` read it: loaded with one-line errors,
and given its model file (``--model``, or the one the run recorded, or RESULT.toml beside it)
when fields it does not store are asked for."""

from __future__ import annotations

from pathlib import Path

from stepcontact.cli.common import _error_text, _Failure, _load
from stepcontact.errors import StepContactError
from stepcontact.results.result import StaticResult
from stepcontact.results.summary import ResultFileError, read_result


def _load_result_file(path: Path) -> StaticResult:
    """Load a result file (:func:`stepcontact.results.summary.read_result`); errors are one
    line naming the file."""
    try:
        return read_result(path)
    except ResultFileError as e:
        raise _Failure(str(e)) from None


def _attach_model(res: StaticResult, result_file: Path, model_file: Path | None) -> Path | None:
    """Give a loaded result its model (:meth:`StaticResult.recover_fields`), so that the
    fields of every state can be recomputed; returns the model file used.

    ``model_file`` (``--model``) must load and match the result (else a failure); without
    it the model files of :func:`_default_model_files` are tried in turn (RESULT.toml beside
    it; for a dynamic result the model file it records, then MODEL.toml), each quietly not
    used if it does not load or match.  None: no model.
    """
    if model_file is None:
        for path in _default_model_files(result_file, res):
            try:
                res.recover_fields(_load(path))
            except (_Failure, ValueError, StepContactError):
                continue
            return path
        return None
    path = model_file
    try:
        model = _load(path)
        res.recover_fields(model)
    except _Failure:
        raise
    except (ValueError, StepContactError) as e:
        raise _Failure(f"--model {path}: {_error_text(e)}") from None
    return path


def _default_model_files(result_file: Path, res: StaticResult) -> list[Path]:
    """The model files a result file may come from, most likely first: the model file it
    records (``run`` stores its path and a SHA-256 hash of its content), RESULT.toml beside
    it and, for a dynamic result (MODEL-dynamic.nc, MODEL-dynamic-STAGE.nc), MODEL.toml
    beside it; each used only when its content has the recorded hash (files written before
    the hash was recorded: any) — for a static result, whose model is checked against its
    stored fields (:meth:`StaticResult.recover_fields`), RESULT.toml whatever its hash."""
    import hashlib
    import re

    from stepcontact.results.file import result_attrs

    out = [result_file.with_suffix(".toml")]
    try:
        attrs = result_attrs(result_file)
    except (OSError, ValueError):
        attrs = {}
    sha = attrs.get("model_sha256")
    recorded = Path(attrs["model_file"]) if attrs.get("model_file") else None
    if recorded is not None:
        out.insert(0, recorded)
    dynamic = getattr(res, "path_axis", "lam") == "time"
    if dynamic:
        stem = re.fullmatch(r"(.+)-dynamic(-[A-Za-z0-9_-]+)?", result_file.stem)
        if stem:
            out.append(result_file.with_name(stem.group(1) + ".toml"))
    kept: list[Path] = []
    for p in out:
        try:
            if not p.is_file() or any(p.samefile(q) for q in kept):
                continue
            hashed = dynamic or p == recorded
            if hashed and sha and hashlib.sha256(p.read_bytes()).hexdigest() != sha:
                continue
        except OSError:
            continue
        kept.append(p)
    return kept
