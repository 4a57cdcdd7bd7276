"""The gmsh Python API, imported on demand (an optional dependency: `pip install gmsh`).

Used by the mesh generators that need a general mesher (:func:`stepcontact.polygon_region`
for a polygon of more than three vertices) and by :mod:`stepcontact.io.meshfile` (``.geo``
files)."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

from stepcontact.errors import ModelError


def gmsh_module():
    """The gmsh Python package, or a ModelError that says how to install it."""
    try:
        import gmsh
    except ImportError:  # pragma: no cover - depends on the environment
        raise ModelError(
            "gmsh",
            "the gmsh Python package is needed to mesh .geo files: `pip install gmsh` "
            "(or `pip install stepcontact[gmsh]`), or give the .msh file instead",
        ) from None
    except OSError as e:  # pragma: no cover - the wheel's library needs system libraries
        raise ModelError(
            "gmsh",
            f"the gmsh package is installed but its library cannot be loaded ({e}); install "
            "the system libraries it needs (e.g. libglu1-mesa, libxcursor1, libxft2, "
            "libxinerama1) or give the .msh file instead",
        ) from None
    return gmsh


@contextlib.contextmanager
def gmsh_session(options: dict[str, float], gmsh=None, *, set_now: bool = True
                 ) -> Iterator[object]:
    """The gmsh module with ``options`` set (``set_now=False``: the caller sets them, e.g.
    after opening a file whose own options they override).  A session started here is
    finalised on exit; in a session the caller had running, the options are set back to what
    they were."""
    gmsh = gmsh_module() if gmsh is None else gmsh
    started = not gmsh.isInitialized()
    if started:
        gmsh.initialize(readConfigFiles=False, interruptible=False)
    saved = {k: gmsh.option.getNumber(k) for k in options}
    try:
        for k, v in options.items() if set_now else ():
            gmsh.option.setNumber(k, v)
        yield gmsh
    finally:
        if started:
            gmsh.finalize()
        else:
            for k, v in saved.items():
                gmsh.option.setNumber(k, v)
