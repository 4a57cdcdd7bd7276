"""Atomic file writes and output locks: :mod:`stepcontact.atomic` (a base module under results
and the solver, which write result files), under the name they have always had here."""

from stepcontact.atomic import (
    FREE_MARGIN_BYTES,
    FREE_MARGIN_SHARE,
    OutputLockedError,
    WriteError,
    atomic_path,
    check_free_space,
    lock_path,
    netcdf_bytes,
    output_lock,
    write_bytes,
    write_error,
    write_netcdf,
    write_text,
)

__all__ = [
    "FREE_MARGIN_BYTES", "FREE_MARGIN_SHARE", "OutputLockedError", "WriteError", "atomic_path",
    "check_free_space", "lock_path", "netcdf_bytes", "output_lock", "write_bytes",
    "write_error", "write_netcdf", "write_text",
]
