"""Node sets (a body's name + local node indices) and what holds nodes: supports, ties and
springs (SI units: N/m, N·s/m)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model.bodies import DOF_NAMES, DOF_NAMES_3D, DOF_NAMES_FRAME_3D, Body, Frame

#: every DOF name a support may give (which of them a node has follows from its body: x, y,
#: rz in 2D, x, y, z in 3D, x, y, z, rx, ry, rz on a space frame; checked on assembly)
_ALL_DOFS: tuple[str, ...] = tuple(dict.fromkeys(DOF_NAMES + DOF_NAMES_FRAME_3D))
#: the rotations, as they may be written in a string of DOF names ("xyzrxryrz")
_ROTATIONS: tuple[str, ...] = ("rx", "ry", "rz")


# --------------------------------------------------------------------------------------------
# node sets
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class NodeSet:
    """Nodes of one body (or frame), as local indices into its ``points``.

    The order is kept: for contact curves it is the order along the curve.
    """

    body: str
    index: np.ndarray
    name: str = ""

    def __post_init__(self):
        index = np.asarray(self.index).ravel()
        label = f"node set '{self.name}'" if self.name else f"node set on '{self.body}'"
        if index.size and not np.issubdtype(index.dtype, np.integer):
            raise ModelError(label, f"node ids must be integers, got {index.dtype}")
        index = index.astype(np.int64)
        if np.any(index < 0):
            raise ModelError(label, f"negative node id {int(index[index < 0][0])}")
        uniq, counts = np.unique(index, return_counts=True)
        if np.any(counts > 1):
            raise ModelError(label, f"node {int(uniq[counts > 1][0])} is listed more than once "
                                    "(a load or CFE would be applied twice)")
        object.__setattr__(self, "index", index)

    def __len__(self) -> int:
        return len(self.index)

    @property
    def label(self) -> str:
        return f"node set '{self.name}'" if self.name else f"node set on '{self.body}'"


# --------------------------------------------------------------------------------------------
# supports, ties, springs
# --------------------------------------------------------------------------------------------
def _parse_dofs(dofs: str | Sequence[str], item: str,
                names: tuple[str, ...] = DOF_NAMES) -> tuple[str, ...]:
    """"xy", "x", "rz", "xyrz" (and "z", "xyz", "rx", "xyzrxryrz" when ``names`` has them) or
    a sequence of names -> tuple of DOF names, each one of ``names`` (default: those of a 2D
    node)."""
    use = ", ".join(DOF_NAMES) if names == DOF_NAMES else \
        (f"{', '.join(DOF_NAMES)} (2D), {', '.join(DOF_NAMES_3D)} (3D) or "
         f"{', '.join(DOF_NAMES_FRAME_3D)} (space frames)")
    letters = [d for d in ("x", "y", "z") if d in names]
    if isinstance(dofs, str):
        text = dofs.replace(",", "").replace(" ", "")
        turns = [r for r in _ROTATIONS if r in text and r in names]
        for r in turns:
            text = text.replace(r, "")
        bad = set(text) - set(letters)
        if bad:
            raise ModelError(item, f"unknown degree of freedom '{sorted(bad)[0]}', use {use}")
        dofs = [d for d in letters if d in text] + turns
    out = tuple(dict.fromkeys(dofs))
    for d in out:
        if d not in names:
            raise ModelError(item, f"unknown degree of freedom '{d}', use {use}")
    return out


@dataclass(frozen=True, eq=False)
class Support:
    """Fixed degrees of freedom of a node set: ``dofs`` any of ``"x"``, ``"y"``, ``"rz"`` (2D),
    of ``"x"``, ``"y"``, ``"z"`` (3D bodies) or of ``"x"``, ``"y"``, ``"z"``, ``"rx"``,
    ``"ry"``, ``"rz"`` (space frames), e.g. ``"xy"``, ``"z"``, ``"xyz"``, ``"xyzrxryrz"``
    (clamped)."""

    name: str
    nodes: NodeSet
    dofs: tuple[str, ...] = ("x", "y")

    def __post_init__(self):
        object.__setattr__(self, "dofs", _parse_dofs(self.dofs, f"support '{self.name}'.dofs",
                                                     _ALL_DOFS))


@dataclass(frozen=True, eq=False)
class Tie:
    """Ties the translations of node set ``a`` to those of node set ``b`` (pairwise).

    Used to connect frames to continuum nodes.  The tied nodes share their ux, uy DOFs.
    """

    name: str
    a: NodeSet
    b: NodeSet


@dataclass(frozen=True, eq=False)
class Spring:
    r"""Linear springs between pairs of nodes ``a[i]``–``b[i]`` (``b`` None: to the ground).

    Each spring acts on the translations of its nodes with the 2 × 2 stiffness (N/m, per
    spring, for the whole thickness)

    .. math::  \mathbf{k} = k_x\,\mathbf{e}_x \otimes \mathbf{e}_x
               + k_y\,\mathbf{e}_y \otimes \mathbf{e}_y + k\,\mathbf{d} \otimes \mathbf{d},

    i.e. the force on node ``a[i]`` is −k (u_a − u_b) (u_b = 0 for the ground).  ``kx``, ``ky``
    are springs along the axes; ``k`` is a spring along ``direction`` d (any non-zero vector,
    stored normalised), e.g. a strut along a slope.  Both kinds may be given together.

    In a 3D model a spring may also have ``kz`` (along z) and a direction (dx, dy, dz): its
    stiffness is then the 3 × 3 k_x e_x⊗e_x + k_y e_y⊗e_y + k_z e_z⊗e_z + k d⊗d (a spring with
    neither acts on x and y only, as in 2D); in a 2D model they are refused.

    ``damping`` is a dashpot coefficient c, N·s/m, acting along ``direction`` (along x and y
    alike when no direction is given), in parallel with the spring: dynamic analyses
    (:func:`stepcontact.solve_dynamic`) add it to the damping matrix; static analyses do not
    use it.

    Example
    -------
    >>> import numpy as np
    >>> from stepcontact import NodeSet, Spring
    >>> s = Spring("strut", NodeSet("block", [0]), k=2e6, direction=(np.sqrt(3), 1.0))
    >>> s.direction  # doctest: +ELLIPSIS
    (0.866..., 0.5...)
    >>> s.stiffness_matrix().round()
    array([[1500000.,  866025.],
           [ 866025.,  500000.]])
    """

    name: str
    a: NodeSet
    b: NodeSet | None = None
    kx: float = 0.0
    ky: float = 0.0
    k: float = 0.0
    direction: tuple[float, ...] | None = None
    damping: float = 0.0
    kz: float = 0.0

    def __post_init__(self):
        item = f"spring '{self.name}'"
        for key in ("kx", "ky", "kz", "k", "damping"):
            v = getattr(self, key)
            if not np.isfinite(v) or v < 0:
                raise ModelError(f"{item}.{key}", f"must be >= 0, got {v}")
        if self.direction is not None:
            d = np.asarray(self.direction, dtype=float)
            if d.shape not in ((2,), (3,)) or not np.all(np.isfinite(d)):
                raise ModelError(f"{item}.direction", "must be a finite vector (dx, dy) or "
                                 f"(dx, dy, dz), got {self.direction}")
            norm = float(np.linalg.norm(d))
            if norm == 0.0:
                raise ModelError(f"{item}.direction", "is zero: give the spring's axis (dx, dy)")
            object.__setattr__(self, "direction", tuple(float(c / norm) for c in d))
        elif self.k > 0:
            raise ModelError(f"{item}.direction",
                             f"is needed with k = {self.k:g} N/m (the axis of the spring)")

    @property
    def dim(self) -> int:
        """3 when the spring has ``kz`` or a 3D direction (it needs a 3D model), else 2."""
        return 3 if self.kz or (self.direction is not None and len(self.direction) == 3) else 2

    def stiffness_matrix(self) -> np.ndarray:
        """The 2 × 2 (3 × 3, :attr:`dim` 3) stiffness k_x e_x⊗e_x + k_y e_y⊗e_y (+ k_z e_z⊗e_z)
        + k d⊗d of each spring, N/m."""
        K = np.diag([float(self.kx), float(self.ky), float(self.kz)][:self.dim])
        if self.direction is not None and self.k:
            d = np.zeros(self.dim)
            d[:len(self.direction)] = self.direction
            K += self.k * np.outer(d, d)
        return K

    def damping_matrix(self) -> np.ndarray:
        """The 2 × 2 (3 × 3) dashpot matrix of each spring, N·s/m: c d⊗d along ``direction``,
        c I (every axis alike) without one."""
        if self.direction is None:
            return float(self.damping) * np.eye(self.dim)
        d = np.zeros(self.dim)
        d[:len(self.direction)] = self.direction
        return float(self.damping) * np.outer(d, d)


def select_nodes(
    b: Body | Frame,
    where=None,
    *,
    x: float | None = None,
    y: float | None = None,
    z: float | None = None,
    boundary: bool | str = True,
    name: str = "",
    atol: float | None = None,
) -> NodeSet:
    """Node set of one body by predicate or coordinates; see :meth:`Model.select`."""
    pts = b.points
    dim = pts.shape[1]
    if atol is None:
        atol = 1e-9 * max(1.0, float(np.ptp(pts, axis=0).max()) if len(pts) else 1.0)
    mask = np.ones(len(pts), dtype=bool)
    if z is not None and dim < 3:
        raise ModelError(f"node set '{name}'" if name else f"selection on body '{b.name}'",
                         f"selects by z, but body '{b.name}' is 2D")
    if where is not None:
        mask &= np.asarray(where(*(pts[:, c] for c in range(dim))), dtype=bool)
    for c, v in enumerate((x, y, z)):
        if v is not None:
            mask &= np.abs(pts[:, c] - v) <= atol
    interior = 0
    if isinstance(boundary, str):  # the nodes of a named boundary of the mesh
        if not isinstance(b, Body):
            raise ModelError(f"frame '{b.name}'", f"has no boundary '{boundary}'")
        on_b = np.zeros(len(pts), dtype=bool)
        on_b[b.boundary[b.boundary_rows(boundary)].ravel()] = True
        mask &= on_b
    elif boundary and isinstance(b, Body):
        on_b = np.zeros(len(pts), dtype=bool)
        on_b[b.boundary.ravel()] = True
        interior = int(np.sum(mask & ~on_b))
        mask &= on_b
    idx = np.flatnonzero(mask)
    label = f"node set '{name}'" if name else f"selection on body '{b.name}'"
    if idx.size == 0:
        hint = (f"; {interior} interior node(s) match: select them with boundary=False"
                if interior else "")
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        span = ", ".join(f"{a} {lo[c]:g} … {hi[c]:g}" for c, a in enumerate("xyz"[:dim]))
        on = f" on boundary '{boundary}'" if isinstance(boundary, str) else ""
        raise ModelError(label, f"selects no node{on} (the body spans {span} m){hint}")
    return NodeSet(b.name, idx, name)
