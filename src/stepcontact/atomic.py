"""Atomic file writes: the content goes to a temporary file beside the target, which is then
renamed into place (:func:`os.replace`), so that an interrupted write leaves no partial file
and an existing one untouched (result files, sweep cases, figures, reports).

Faults of the file system are errors that name the file, never a crash: a netCDF file is made
in memory first (HDF5 never writes to the disk itself: a full disk there ended in a
segmentation fault), the free space is checked against its size before anything is written
(:func:`check_free_space`), and a write that fails anyway (the disk filled up meanwhile, a
quota, no permission) is a :class:`WriteError` — the temporary file is removed and the previous
file at the path is left intact.

:func:`output_lock` holds an exclusive lock on an output file for the length of a run, so that
two runs writing one file do not silently lose one result."""

from __future__ import annotations

import errno
import os
import shutil
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

from stepcontact.errors import StepContactError

if TYPE_CHECKING:
    import xarray as xr

#: bytes that a write must leave free on the device beyond the file itself (the file system's
#: own metadata, the rename): 1 MiB plus this share of the file's size
FREE_MARGIN_BYTES = 1 << 20
FREE_MARGIN_SHARE = 0.05

_FULL = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG)


class WriteError(StepContactError, OSError):
    """A file could not be written (full disk, quota, permission): the message names the file
    and says that the previous file there, if any, is intact (``reason``: why, in words)."""

    def __init__(self, message: str, *, path: str | os.PathLike[str] | None = None,
                 code: int | None = None, reason: str = "") -> None:
        super().__init__(message)
        self.message = message
        self.path = None if path is None else Path(path)
        self.errno = code
        self.reason = reason or message

    def __str__(self) -> str:
        return self.message


class OutputLockedError(StepContactError):
    """Another run holds the lock of an output file (:func:`output_lock`)."""


def _mb(n: float) -> str:
    return f"{n / 1e6:.3g} MB"


def _existing_dir(path: Path) -> Path:
    """The nearest existing directory at or above ``path`` (what ``disk_usage`` can ask)."""
    p = path
    while not p.exists() and p != p.parent:
        p = p.parent
    return p if p.is_dir() else p.parent


def _write_error(path: Path, reason: str, code: int | None, what: str) -> WriteError:
    full = code in _FULL
    kept = f"the previous file '{path.name}' is intact" if path.exists() else \
        "no partial file was left"
    hint = "free some space or write elsewhere" if full else "check the path and its permissions"
    return WriteError(f"could not write the {what} '{path}': {reason}; {kept}; {hint}",
                      path=path, code=code, reason=reason)


def check_free_space(path: str | os.PathLike[str], size: int, what: str = "file") -> None:
    """Raise a :class:`WriteError` when the device of ``path`` has less free space than
    ``size`` bytes plus a margin (:data:`FREE_MARGIN_BYTES` + :data:`FREE_MARGIN_SHARE` ×
    size), before anything is written.  ``what`` names the content in the message."""
    path = Path(path)
    try:
        free = shutil.disk_usage(_existing_dir(path.parent)).free
    except OSError:  # the device cannot say: the write itself will tell
        return
    need = int(size) + FREE_MARGIN_BYTES + int(FREE_MARGIN_SHARE * size)
    if free < need:
        raise _write_error(path, f"not enough free space on the device (it needs about "
                           f"{_mb(need)}, {_mb(free)} are free); nothing was written",
                           errno.ENOSPC, what)


def write_error(path: str | os.PathLike[str], exc: OSError, what: str = "file") -> WriteError:
    """A :class:`WriteError` naming ``path`` for an OS error met while writing it (or a
    :class:`WriteError` of a file written for it, e.g. in a temporary directory)."""
    path = Path(path)
    if isinstance(exc, WriteError):
        if exc.path == path:
            return exc
        return _write_error(path, exc.reason, exc.errno, what)
    if exc.errno == errno.ENOSPC:
        reason = f"the device is full ({exc.strerror or os.strerror(errno.ENOSPC)})"
    else:
        reason = (exc.strerror or str(exc)).lower()
    return _write_error(path, reason, exc.errno, what)


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


def _write_file(path: Path, data: bytes) -> None:
    """Write ``data`` to a new file ``path`` (plain Python I/O: a full disk is an OSError)."""
    with open(path, "wb") as fh:
        fh.write(data)
        fh.flush()


def write_bytes(path: str | os.PathLike[str], data: bytes, *, fsync: bool = True,
                what: str = "file") -> None:
    """Write ``data`` to ``path`` atomically, after checking the free space for it
    (:func:`check_free_space`); an OS error is a :class:`WriteError` naming ``path``, and the
    previous file there stays intact."""
    path = Path(path)
    if path.is_dir():
        raise IsADirectoryError(f"path '{path}' is a directory, expected a file name")
    data = bytes(data)
    check_free_space(path, len(data), what)
    try:
        with atomic_path(path, fsync=fsync) as tmp:
            _write_file(tmp, data)
    except OSError as e:
        raise write_error(path, e, what) from None


def write_text(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    write_bytes(path, text.encode("utf-8"), fsync=False)


def netcdf_bytes(ds: xr.Dataset) -> bytes:
    """The netCDF-4 file (h5netcdf) of a dataset, made in memory.  (Under a dask.distributed
    client, xarray would ask the cluster for a write lock named after the in-memory buffer,
    which fails: the dataset is in memory, so dask's synchronous scheduler is used.)"""
    import contextlib
    import sys

    quiet = contextlib.nullcontext()
    if "dask" in sys.modules:
        import dask

        quiet = dask.config.set(scheduler="synchronous")
    with quiet:
        return bytes(ds.to_netcdf(engine="h5netcdf"))


def write_netcdf(ds: xr.Dataset, path: str | os.PathLike[str], what: str = "result file") -> None:
    """Write a dataset to a netCDF-4 file (h5netcdf) atomically, its data synced to disk.
    The file is made in memory, its size checked against the free space, then written with
    plain file I/O (:func:`write_bytes`)."""
    write_bytes(path, netcdf_bytes(ds), fsync=True, what=what)


# --------------------------------------------------------------------------------------------
# an exclusive lock on an output file
# --------------------------------------------------------------------------------------------
def lock_path(path: str | os.PathLike[str]) -> Path:
    """The lock file of an output file: ``OUTPUT.lock`` beside it."""
    path = Path(path)
    return path.with_name(path.name + ".lock")


@contextmanager
def output_lock(path: str | os.PathLike[str], what: str = "result file") -> Iterator[Path]:
    """Hold an exclusive lock on the output file ``path`` while the block runs: an advisory
    :func:`fcntl.flock` on ``OUTPUT.lock`` beside it, which holds the process id of the run.
    A second run that asks for the same lock gets an :class:`OutputLockedError` at once,
    naming the file and the other run's process id.  The lock is released (and its file
    removed) when the block ends, also when the process is killed (the kernel drops it).
    Without :mod:`fcntl` (Windows) the block runs unlocked."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not on POSIX
        yield lock_path(path)
        return

    path = Path(path)
    lock = lock_path(path)
    while True:
        try:
            lock.parent.mkdir(parents=True, exist_ok=True)
            fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as e:
            raise write_error(path, e, what) from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as e:
            if e.errno not in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                os.close(fd)
                raise
            try:
                other = os.pread(fd, 64, 0).decode("ascii", "replace").strip()
            finally:
                os.close(fd)
            who = f"process {other}" if other.isdigit() else "another process"
            raise OutputLockedError(
                f"the {what} '{path}' is being written by another run ({who}; lock file "
                f"'{lock}'): wait for it to end, or write elsewhere (-o/--output)") from None
        try:  # a run that ended meanwhile may have removed the file we locked: lock anew
            same = os.stat(lock).st_ino == os.fstat(fd).st_ino
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    try:
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n".encode("ascii"), 0)
        yield lock
    finally:
        try:
            lock.unlink(missing_ok=True)  # while still holding it
        finally:
            os.close(fd)


__all__ = [
    "OutputLockedError", "WriteError", "atomic_path", "check_free_space", "lock_path",
    "netcdf_bytes", "output_lock", "write_bytes", "write_error", "write_netcdf", "write_text",
]
