"""The assembled system of a model: its DOF map, load vectors and the :class:`System` the
solvers take (built by :func:`stepcontact.fem.assembly.assemble` for a mesh model and by
:func:`stepcontact.fem.discrete.assemble_discrete` for a discrete one).

Plain data (no assembly here), so that both assemblies build on it without importing each
other.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from stepcontact.contact.geometry import ContactElements
from stepcontact.contact.layout import ContactLayout
from stepcontact.model import Model


@dataclass(frozen=True, eq=False)
class DofMap:
    """Global DOF numbers: ``of[node, c]`` for the DOF named ``names[c]`` (−1 where the node has
    none): c = x, y, rz in 2D, c = x, y, z in 3D.  The first ``dim`` columns are the
    translations."""

    of: np.ndarray
    ndof: int
    names: tuple[str, ...] = ("x", "y", "rz")

    @property
    def dim(self) -> int:
        """Number of translation components per node: 2 or 3."""
        return 3 if "z" in self.names else 2

    def column(self, name: str) -> int | None:
        """The column of ``of`` of the DOF called ``name``, None when no node has it."""
        return self.names.index(name) if name in self.names else None

    def nodes(self, nodes: np.ndarray, c: int) -> np.ndarray:
        return self.of[nodes, c]

    def node_of(self) -> np.ndarray:
        """The node of every DOF (ndof,)."""
        out = np.full(self.ndof, -1)
        has = self.of >= 0
        out[self.of[has]] = np.nonzero(has)[0]
        return out


@dataclass(frozen=True, eq=False)
class LoadVectors:
    """A load pattern as vectors: forces ``f`` (N, per unit λ) and prescribed displacements
    ``u`` (m, per unit λ, nonzero only on prescribed DOFs listed in ``dofs``)."""

    f: np.ndarray
    u: np.ndarray
    dofs: np.ndarray


@dataclass(frozen=True, eq=False)
class System:
    """The assembled linear system of a model (input to the solvers).

    Attributes
    ----------
    model : Model
    dofs : DofMap
    K : csr_matrix (ndof, ndof)
        Stiffness of bodies, frames and springs, N/m.
    fixed : (ndof,) bool
        DOFs with a support or a prescribed displacement.
    loads : dict[str, LoadVectors]
    cfe : ContactElements
    B : csr_matrix (2m, ndof)
        Contact operator, w = B u + w0, rows [u_τ; u_n].
    w0 : (2m,) float
        [0; −g⁰].
    reaction_rows : csr_matrix (n_r, ndof)
        Row r sums the DOFs of one reaction resultant (a support's x, y or rz DOFs; the DOFs a
        load pattern prescribes): R = reaction_rows · (K u + Bᵀ s − f).
    reaction_labels : tuple of str
        ``"support:x"``, ``"support:y"``, ``"support:rz"``, ``"pattern (prescribed):x"`` …
    levels : dict[str, LevelBasis]
        Patterns whose factor is a water level, with their virtual patterns (which ``loads``
        also holds, see :mod:`stepcontact.fem.level`).
    discrete : DiscreteModel or None
        The discrete model a system was built from (:mod:`stepcontact.fem.discrete`): then
        ``model`` has no bodies (only its load patterns and program), the DOFs belong to no
        node and the CFEs have no geometry.
    crack : CrackWaterData or None
        Water in the opened parts of joints (:mod:`stepcontact.fem.crack`), None without.
    """

    model: Model
    dofs: DofMap
    K: sp.csr_matrix
    fixed: np.ndarray
    loads: dict
    cfe: ContactElements
    B: sp.csr_matrix
    w0: np.ndarray
    reaction_rows: sp.csr_matrix | None = None
    reaction_labels: tuple[str, ...] = ()
    levels: dict = field(default_factory=dict)
    discrete: object | None = None
    crack: object | None = None

    @property
    def ndof(self) -> int:
        return self.dofs.ndof

    @property
    def m(self) -> int:
        return self.cfe.m

    @property
    def layout(self) -> ContactLayout:
        """The layout of the contact unknowns s = [Q; p], w = [u_τ; u_n]."""
        return self.cfe.layout



def reaction_rows(groups: list[tuple[str, np.ndarray]], ndof: int):
    """0/1 rows summing each group's DOFs; a DOF in several groups counts in the first only."""
    seen = np.zeros(ndof, dtype=bool)
    r, c, labels = [], [], []
    for label, d in groups:
        d = np.unique(d[~seen[d]])
        if d.size == 0:
            continue
        seen[d] = True
        r.append(np.full(d.size, len(labels)))
        c.append(d)
        labels.append(label)
    if not labels:
        return sp.csr_matrix((0, ndof)), ()
    r_all, c_all = np.concatenate(r), np.concatenate(c)
    rows = sp.csr_matrix((np.ones(r_all.size), (r_all, c_all)), shape=(len(labels), ndof))
    return rows, tuple(labels)


__all__ = ["DofMap", "LoadVectors", "System", "reaction_rows"]
