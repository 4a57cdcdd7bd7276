"""Assembly of a :class:`~stepcontact.model.discrete.DiscreteModel`: its matrices as a
:class:`~stepcontact.fem.system.System`, the input of the same solvers.

The contact operator stacks the rows as w = B u + w⁰ with B = [T; −A] (T the tangent rows, A
the normal rows) and w⁰ = [0; −g⁰], so u_τ = T u and u_n = −A u − g⁰ as for the CFEs of a
mesh (:mod:`stepcontact.contact.geometry`).  With two tangential directions (3D) B = [T₁; T₂;
−A] and w⁰ = [0; 0; −g⁰], in the component-major order of
:class:`~stepcontact.contact.layout.ContactLayout` (m, 2).  The CFEs have no nodes and no
geometry: NaN coordinates and normals, the position ``s`` is the CFE's number within its name
(interface) and the area is 1 (so σ_n = N and τ = Q in value); the DOFs belong to no node.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from stepcontact.contact.geometry import ContactElements
from stepcontact.fem.system import DofMap, LoadVectors, System, reaction_rows
from stepcontact.model.discrete import DiscreteModel


def discrete_contact(dm: DiscreteModel) -> ContactElements:
    """The CFEs of a discrete model: names, friction, gaps and layers; no geometry (position
    = number within the interface, area 1)."""
    m = dm.m
    names = tuple(dict.fromkeys(dm.names))
    interface = np.array([names.index(v) for v in dm.names], dtype=np.int64)
    local = np.zeros(m, dtype=np.int64)
    for j in range(len(names)):
        at = np.flatnonzero(interface == j)
        local[at] = np.arange(at.size)
    nodes = np.full((m, 3), -1, dtype=np.int64)
    nan2 = np.full((m, 2), np.nan)
    return ContactElements(
        names, interface, local, nodes, np.zeros((m, 3)), nodes.copy(), np.zeros((m, 3)),
        nan2, nan2.copy(), nan2.copy(), local.astype(float), np.ones(m),
        dm.friction.copy(), dm.gaps.copy(), dm.kn.copy(), dm.kt.copy(), dm.cn.copy(),
        dm.bond.copy(), n_t=dm.n_t, facets=dm.facets if dm.n_t > 1 else 2,
        facet_angle=dm.facet_angle.copy(), facet_stagger=dm.facet_stagger,
        facet_adaptive=dm.facet_adaptive,
    )


def assemble_discrete(dm: DiscreteModel) -> System:
    """The :class:`System` of a discrete model (its ``model`` is :meth:`DiscreteModel.as_model`:
    the patterns and the program, no bodies; ``discrete`` is the discrete model itself).

    Reactions: one per fixed DOF (``"fixed:<dof name>"``) and per DOF a pattern prescribes
    (``"<pattern> (prescribed):<dof name>"``).
    """
    n, m = dm.ndof, dm.m
    fixed = dm.fixed.copy()
    groups = [(f"fixed:{dm.dof_names[d]}", np.array([d])) for d in np.flatnonzero(fixed)]
    loads = {}
    for p in dm.pattern_names:
        f = dm.loads.get(p, np.zeros(n)).copy()
        u, dofs = dm.prescribed_vectors(p)
        fixed[dofs] = True
        groups += [(f"{p} (prescribed):{dm.dof_names[d]}", np.array([d])) for d in dofs]
        loads[p] = LoadVectors(f, u, dofs)
    cfe = discrete_contact(dm)
    lay = cfe.layout  # rows [u_τ1; (u_τ2;) u_n]: B = [T1; (T2;) −A], w0 = [0; (0;) −g⁰]
    tangents = [dm.tangent_rows] + ([] if dm.tangent2_rows is None else [dm.tangent2_rows])
    B = sp.vstack([*tangents, -dm.normal_rows]).tocsr() if m else sp.csr_matrix((0, n))
    w0 = lay.join(np.zeros((m,) if lay.n_t == 1 else (m, lay.n_t)), -dm.gaps)
    rows, labels = reaction_rows(groups, n)
    return System(dm.as_model(), DofMap(np.zeros((0, 3), dtype=np.int64), n), dm.K.copy(),
                  fixed, loads, cfe, B, w0, rows, labels, discrete=dm)
