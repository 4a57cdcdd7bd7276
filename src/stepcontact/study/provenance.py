"""Where a study's numbers come from: the software that computed them and when.

:func:`provenance` gives stepcontact's version, the git commit of the checkout the package runs
from (and whether its tracked files have uncommitted changes), the versions of Python, NumPy
and SciPy, and the date (UTC).  The commit is found with ``git -C <package directory>`` under
a timeout; when git is missing, times out, or the package is not a tracked file of a git
repository (an installed wheel, a copy, a virtual environment inside some other repository),
the commit is "not a git checkout" — never an error.

Example
-------
>>> p = provenance()
>>> sorted(p)                                          # doctest: +NORMALIZE_WHITESPACE
['commit', 'date', 'dirty', 'numpy', 'python', 'scipy', 'software', 'version']
"""

from __future__ import annotations

import datetime
import platform
import subprocess
from pathlib import Path

#: the commit text when the package does not run from a git checkout
NOT_A_CHECKOUT = "not a git checkout"
#: seconds allowed to each git call
GIT_TIMEOUT = 5.0


def _git(directory: Path, *args: str) -> str | None:
    """stdout of ``git -C directory args`` (stripped), or None if git fails, is missing or
    times out."""
    try:
        r = subprocess.run(["git", "-C", str(directory), *args], capture_output=True,
                           text=True, timeout=GIT_TIMEOUT, check=False,
                           stdin=subprocess.DEVNULL)
    except (OSError, subprocess.SubprocessError):
        return None
    return r.stdout.strip() if r.returncode == 0 else None


def git_commit(directory: str | Path | None = None) -> tuple[str, bool | None]:
    """(commit, dirty) of the git checkout holding ``directory`` (default: this package's
    directory): the full hash of HEAD and whether tracked files differ from it (staged or
    not; untracked files are ignored).  (:data:`NOT_A_CHECKOUT`, None) when the directory's
    ``__init__.py`` is not a file tracked by a git repository, or git is unavailable."""
    d = Path(__file__).resolve().parent.parent if directory is None else Path(directory)
    if _git(d, "ls-files", "--error-unmatch", "--", "__init__.py") is None:
        return NOT_A_CHECKOUT, None
    head = _git(d, "rev-parse", "HEAD")
    if not head:
        return NOT_A_CHECKOUT, None
    status = _git(d, "status", "--porcelain", "--untracked-files=no")
    return head, (None if status is None else bool(status))


def software_text(version: str, commit: str, dirty: bool | None) -> str:
    """One line naming the software: ``stepcontact <version> (commit <hash>[, with
    uncommitted changes])`` or ``stepcontact <version> (not a git checkout)``."""
    if commit == NOT_A_CHECKOUT:
        return f"stepcontact {version} ({NOT_A_CHECKOUT})"
    state = {True: ", with uncommitted changes", False: "",
             None: ", uncommitted changes unknown"}[dirty]
    return f"stepcontact {version} (commit {commit}{state})"


def provenance() -> dict[str, object]:
    """The software and date of a run: ``version`` (stepcontact.__version__), ``commit``
    (git hash or :data:`NOT_A_CHECKOUT`), ``dirty`` (True/False, None when unknown),
    ``software`` (:func:`software_text`), ``python``, ``numpy``, ``scipy`` (versions) and
    ``date`` (UTC, ISO 8601 to the second)."""
    import numpy
    import scipy

    from stepcontact import __version__

    commit, dirty = git_commit()
    return {
        "version": __version__, "commit": commit, "dirty": dirty,
        "software": software_text(__version__, commit, dirty),
        "python": platform.python_version(), "numpy": numpy.__version__,
        "scipy": scipy.__version__,
        "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
    }


__all__ = ["GIT_TIMEOUT", "NOT_A_CHECKOUT", "git_commit", "provenance", "software_text"]
