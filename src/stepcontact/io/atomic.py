"""Atomic file writes: the content goes to a temporary file beside the target, which is then
renamed into place (:func:`os.replace`), so that an interrupted write leaves no partial file
and an existing one untouched (result files, sweep cases, figures, reports)."""

from __future__ import annotations

import os
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import xarray as xr


@contextmanager
def atomic_path(path: str | os.PathLike[str], *, fsync: bool = False) -> Iterator[Path]:
    """A temporary path to write to; renamed to ``path`` when the block ends without an
    exception (after an fsync of its data with ``fsync``), removed when it raises.  Creates
    ``path``'s directory."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex}.tmp")
    try:
        yield tmp
        if fsync:
            with open(tmp, "rb+") as fh:
                os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_text(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")


def write_netcdf(ds: xr.Dataset, path: str | os.PathLike[str]) -> None:
    """Write a dataset to a netCDF-4 file (h5netcdf) atomically, its data synced to disk."""
    with atomic_path(path, fsync=True) as tmp:
        ds.to_netcdf(tmp, engine="h5netcdf")


__all__ = ["atomic_path", "write_netcdf", "write_text"]
