"""Model size against this machine's memory: refuse a mesh before allocating it.

The peak memory of a model is dominated by the assembly of the stiffness (COO triplets of the
element matrices, then the CSR matrix) and the sparse factorisation of K₀; both grow about
linearly with the number of degrees of freedom on 2D meshes.  Measured on rectangles of tri3,
tri6, quad4 and quad8 elements with 2e4 to 2e5 DOFs (peak resident memory of assembly plus
factorisation): 3.0 to 4.1 kB per DOF, so :data:`BYTES_PER_DOF` = 4 kB.  A model is refused
when that estimate exceeds :data:`MEMORY_SHARE` of the physical memory.

Example
-------
>>> from stepcontact.model.size import rectangle_size
>>> rectangle_size(10, 5, "quad8")     # (nodes, cells)
(181, 50)
"""

from __future__ import annotations

import os

from stepcontact.errors import ModelError

#: estimated peak memory per degree of freedom, bytes (assembly and sparse factorisation)
BYTES_PER_DOF = 4096
#: share of the physical memory a model may need
MEMORY_SHARE = 0.5


def physical_memory() -> int | None:
    """Physical memory of this machine, bytes (None where the OS does not say)."""
    try:
        return int(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, ValueError, OSError):
        return None


def rectangle_size(nx: int, ny: int, element: str) -> tuple[int, int]:
    """Nodes and cells of an ``nx`` × ``ny`` rectangle mesh of ``element`` (exact, without
    building it)."""
    nx, ny = int(nx), int(ny)
    vertices = (nx + 1) * (ny + 1)
    edges = nx * (ny + 1) + ny * (nx + 1)
    if element.startswith("tri"):
        cells = 2 * nx * ny
        nodes = vertices + (edges + nx * ny if element == "tri6" else 0)
    else:
        cells = nx * ny
        nodes = {"quad8": vertices + edges, "quad9": vertices + edges + cells}.get(element,
                                                                                 vertices)
    return nodes, cells


def _bytes(b: float) -> str:
    for unit, size in (("TB", 2**40), ("GB", 2**30), ("MB", 2**20)):
        if b >= size:
            return f"{b / size:.3g} {unit}"
    return f"{b / 2**10:.3g} kB"


def check_size(ndof: int, item: str, what: str, limit: float | None = None) -> None:
    """Raise a :class:`ModelError` on ``item`` when ``ndof`` degrees of freedom need more than
    ``limit`` bytes (default: :data:`MEMORY_SHARE` of the physical memory; no check where the
    OS does not tell it).  ``what`` describes the mesh in the message (e.g. "the 2000 × 1000
    quad4 mesh of body 'block' (2e6 cells)")."""
    phys = None
    if limit is None:
        phys = physical_memory()
        if phys is None:
            return
        limit = MEMORY_SHARE * phys
    need = float(ndof) * BYTES_PER_DOF
    if need <= limit:
        return
    avail = (f"{MEMORY_SHARE:.0%} of this machine's {_bytes(phys)} of physical memory"
             if phys is not None else "the limit")
    raise ModelError(
        item,
        f"too large: {what} has {ndof:.3g} DOFs and needs about {_bytes(need)} of memory "
        f"(~{BYTES_PER_DOF // 1024} kB per DOF for assembly and factorisation), more than "
        f"{avail} ({_bytes(limit)}); use a coarser mesh",
    )


__all__ = ["BYTES_PER_DOF", "MEMORY_SHARE", "check_size", "physical_memory", "rectangle_size"]
