"""Assembly: model -> global stiffness, load vectors and contact operators.

Degrees of freedom: every node has ux, uy; frame nodes also rz.  In a 3D model (solid
bodies or space frames, :attr:`~stepcontact.model.Model.dim` = 3) every node has ux, uy, uz;
space-frame nodes also rx, ry, rz (numbered after all the translations, as the rotations of
plane frames are).  Tied nodes (:class:`~stepcontact.model.Tie`) share their translations.
All element matrices are built for all elements at once and scattered through one COO -> CSR
conversion (:func:`scatter`).

The contact operator B (2m × ndof) gives the mutual displacements of the CFEs,
w = B u + w⁰ with rows 0..m-1 = u_τ and rows m..2m-1 = u_n
(see :mod:`stepcontact.contact.geometry`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from stepcontact.contact.boundary import chain_order, continuum_edges, edge_facets
from stepcontact.contact.geometry import ContactElements, build_contact
from stepcontact.errors import ModelError
from stepcontact.fem import continuum as _fem
from stepcontact.fem.beam import add_self_weight, frame_stiffness
from stepcontact.fem.discrete import assemble_discrete
from stepcontact.fem.hydrodynamic import reservoir_forces
from stepcontact.fem.level import facet_water_forces, is_level_pattern, level_basis
from stepcontact.fem.system import DofMap, LoadVectors, System, reaction_rows
from stepcontact.model import (
    Body,
    BodyForce,
    DiscreteModel,
    EdgeForce,
    EdgeLoad,
    Frame,
    Model,
    NodalLoad,
    ObstacleMotion,
    PrescribedDisplacement,
)
from stepcontact.model.seismic import SeismicCoefficient

#: the columns of a 2D model's DofMap.of (a 3D model's: DofMap.column)
_DOF_INDEX = {"x": 0, "y": 1, "rz": 2}
#: every DOF name a load may prescribe (which of them the model's nodes have: DofMap.names)
_DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")


def _dof_column(dofs: DofMap, name: str, item: str, model: Model) -> int:
    """The column of ``dofs.of`` of the DOF ``name``; a ModelError naming ``item`` when the
    model's nodes have no such DOF (z on a 2D model, rz on a 3D one)."""
    c = dofs.column(name)
    if c is None:
        raise ModelError(item, f"names the DOF '{name}', but the model is {model.dim}D (its "
                         f"nodes have {', '.join(dofs.names)})")
    return c


def scatter(rows: np.ndarray, cols: np.ndarray, vals: np.ndarray, shape) -> sp.csr_matrix:
    """Sum COO triplets (any shape, flattened) into a CSR matrix; the one scatter helper."""
    r, c, v = (np.asarray(a).ravel() for a in (rows, cols, vals))
    if r.size and min(r.min(), c.min()) < 0:  # DOFs that do not exist (-1): dropped
        keep = (r >= 0) & (c >= 0)
        r, c, v = r[keep], c[keep], v[keep]
    return sp.coo_matrix((v, (r, c)), shape=shape).tocsr()


def dof_map(model: Model) -> DofMap:
    """Number the DOFs; ties merge translations (union-find over node pairs).  The vertex
    nodes of moving obstacles (after the bodies' nodes) have x, y DOFs, all prescribed."""
    n = model.n_nodes
    parent = np.arange(n)

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for tie in model.ties:
        a = model.global_nodes(tie.a)
        b = model.global_nodes(tie.b)
        if len(a) != len(b):
            raise ModelError(f"tie '{tie.name}'",
                             f"node sets differ in size ({len(a)} vs {len(b)})")
        for i, j in zip(a.tolist(), b.tolist(), strict=True):
            ri, rj = find(i), find(j)
            if ri != rj:
                parent[max(ri, rj)] = min(ri, rj)
    root = np.array([find(i) for i in range(n)]) if model.ties else parent
    uniq, inv = np.unique(root, return_inverse=True)
    if model.dim == 3:  # ux, uy, uz per node; rx, ry, rz of space-frame nodes after them
        of = (3 * inv[:, None] + np.arange(3)[None, :]).astype(np.int64)
        frames = [b for b in model.bodies if isinstance(b, Frame)]
        if not frames:
            return DofMap(of, 3 * len(uniq), ("x", "y", "z"))
        of = np.column_stack([of, np.full((n, 3), -1, dtype=np.int64)])
        ndof = 3 * len(uniq)
        for b in frames:
            ids = model.node_offsets[b.name] + np.arange(b.n_nodes)
            of[ids, 3:] = ndof + np.arange(3 * b.n_nodes).reshape(-1, 3)
            ndof += 3 * b.n_nodes
        return DofMap(of, ndof, b.dof_names)
    of = np.full((n, 3), -1, dtype=np.int64)
    of[:, 0] = 2 * inv
    of[:, 1] = 2 * inv + 1
    ndof = 2 * len(uniq)
    off = model.node_offsets
    for b in model.bodies:
        if isinstance(b, Frame):
            ids = off[b.name] + np.arange(b.n_nodes)
            of[ids, 2] = ndof + np.arange(b.n_nodes)
            ndof += b.n_nodes
    return DofMap(of, ndof)


def stiffness(model: Model, dofs: DofMap) -> sp.csr_matrix:
    """Global stiffness of continua (element kernels or scikit-fem), frames and springs, N/m:
    the triplets of every body in one COO -> CSR conversion."""
    rows, cols, vals = [], [], []
    off = model.node_offsets
    for b in model.bodies:
        ids = off[b.name] + np.arange(b.n_nodes)
        if isinstance(b, Body):
            r, c, v = _fem.stiffness_triplets(b, model.plane, model.thickness)
            gd = dofs.of[ids][:, :b.dim].ravel()  # body-local vector DOF d·i+c -> global
            gd = gd.astype(np.int32) if dofs.ndof < 2**31 else gd  # half the index traffic
            rows.append(gd[r].ravel())
            cols.append(gd[c].ravel())
            vals.append(np.ravel(v))
        else:
            r, c, v = frame_stiffness(b, dofs.of[ids])  # (n, 3) plane, (n, 6) space
            rows.append(r.ravel())
            cols.append(c.ravel())
            vals.append(v.ravel())
    for r, c, v in _spring_triplets(model, dofs, lambda s: s.stiffness_matrix()):
        rows.append(r)
        cols.append(c)
        vals.append(v)
    if not rows:
        return sp.csr_matrix((dofs.ndof, dofs.ndof))
    return scatter(np.concatenate(rows), np.concatenate(cols), np.concatenate(vals),
                   (dofs.ndof, dofs.ndof))


def _spring_triplets(model: Model, dofs: DofMap, matrix_of):
    """(rows, cols, values) of every spring's 2 × 2 (3 × 3) matrix ``matrix_of(spring)`` (N/m
    or N·s/m) on its nodes' translations: [[k, −k], [−k, k]] per pair, k alone to the
    ground."""
    for s in model.springs:
        if s.dim > dofs.dim:
            raise ModelError(f"spring '{s.name}'", "has kz or a direction (dx, dy, dz), but the "
                             "model is 2D: give kx, ky and a direction (dx, dy)")
        a = model.global_nodes(s.a)
        if s.b is not None:
            bb = model.global_nodes(s.b)
            if len(bb) != len(a):
                raise ModelError(f"spring '{s.name}'", "node sets a and b differ in size")
        else:
            bb = None
        ks = matrix_of(s)
        for c, e in zip(*np.nonzero(ks), strict=True):
            da, ea = dofs.of[a, c], dofs.of[a, e]
            kce = ks[c, e]
            if bb is None:
                yield da, ea, np.full(len(da), kce)
            else:
                db, eb = dofs.of[bb, c], dofs.of[bb, e]
                yield (np.r_[da, db, da, db], np.r_[ea, eb, eb, ea],
                       np.r_[np.full(2 * len(da), kce), np.full(2 * len(da), -kce)])


def dashpots(model: Model, dofs: DofMap) -> sp.csr_matrix:
    """Global damping matrix of the springs' dashpots (``Spring.damping``), N·s/m."""
    trip = list(_spring_triplets(model, dofs, lambda s: s.damping_matrix()))
    if not trip:
        return sp.csr_matrix((dofs.ndof, dofs.ndof))
    r, c, v = (np.concatenate(x) for x in zip(*trip, strict=True))
    return scatter(r, c, v, (dofs.ndof, dofs.ndof))


def _pressure_function(spec, body, ns, item: str):
    """Turn a pressure spec (constant, (start, end) pair, callable) into p(x, y) (p(x, y, z)
    on a 3D body, where a (start, end) pair along a curve has no meaning)."""
    if spec is None:
        return None
    if callable(spec):
        return spec
    if np.ndim(spec) == 0:
        v = float(spec)
        if not np.isfinite(v):
            raise ModelError(item, f"pressure is {v}")
        return lambda x, *yz: v + 0.0 * x
    if body.dim == 3:
        raise ModelError(item, f"a (start, end) pair {tuple(spec)!r} varies along a curve; on "
                         "the faces of a 3D body give a constant or a function p(x, y, z)")
    p0, p1 = (float(v) for v in spec)
    if not (np.isfinite(p0) and np.isfinite(p1)):
        raise ModelError(item, "pressure is NaN or inf")
    order, s = chain_order(body, ns)
    pts = body.points[order]
    total = s[-1] if s[-1] > 0 else 1.0

    def linear(x, y):
        # arc-length coordinate of (x, y): position along the nearest chain segment
        xy = np.stack([np.ravel(x), np.ravel(y)], axis=1)
        a, b = pts[:-1], pts[1:]
        ab = b - a
        L2 = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
        t = np.clip(np.einsum("pjk,jk->pj", xy[:, None] - a[None], ab) / L2, 0, 1)
        d = np.linalg.norm(xy[:, None] - (a[None] + t[..., None] * ab[None]), axis=2)
        j = np.argmin(d, axis=1)
        sa = s[:-1][j] + t[np.arange(len(xy)), j] * np.sqrt(L2[j])
        return (p0 + (p1 - p0) * sa / total).reshape(np.shape(x))

    return linear


def _add_body_force(f: np.ndarray, model: Model, dofs: DofMap, ld: BodyForce,
                    item: str) -> None:
    """Add the consistent nodal forces of the body force ``ld`` (ρ g on its bodies) to f."""
    off = model.node_offsets
    names = ld.bodies or tuple(b.name for b in model.bodies)
    if not np.all(np.isfinite(ld.g)):
        raise ModelError(item, "gravity vector is NaN or inf")
    for bn in names:
        b = model.body(bn)
        ids = off[b.name] + np.arange(b.n_nodes)
        try:
            g = ld.vector(b.dim)
        except ModelError as err:
            raise ModelError(f"{item} on body '{b.name}'", err.problem) from None
        if isinstance(b, Body):
            fb = _fem.body_force(b, g, model.thickness)
            np.add.at(f, dofs.of[ids][:, :b.dim].ravel(), fb)
        else:  # consistent loads of the uniform line load ρ A g (fem.beam)
            add_self_weight(f, b, dofs.of[ids], g)


def load_vectors(model: Model, dofs: DofMap, name: str) -> LoadVectors:
    """Force vector and prescribed displacements of one load pattern (per unit λ)."""
    pat = model.pattern(name)
    f = np.zeros(dofs.ndof)
    u = np.zeros(dofs.ndof)
    pdofs: list[np.ndarray] = []
    off = model.node_offsets
    for i, ld in enumerate(pat.loads):
        item = f"load pattern '{name}' load {i}"
        if isinstance(ld, NodalLoad):
            ids = model.global_nodes(ld.nodes)
            for dname, key, v in (("x", "fx", ld.fx), ("y", "fy", ld.fy), ("rz", "mz", ld.mz),
                                  ("z", "fz", ld.fz), ("rx", "mx", ld.mx),
                                  ("ry", "my", ld.my)):
                if v == 0:
                    continue
                c = _dof_column(dofs, dname, f"{item}.{key}", model)
                if not np.isfinite(v):
                    raise ModelError(item, f"nodal force component {c} is {v}")
                d = dofs.of[ids, c]
                if np.any(d < 0):
                    raise ModelError(f"{item}.{key}", "moment on a node without rotation (not a "
                                     "frame node)")
                np.add.at(f, d, v)
        elif isinstance(ld, EdgeLoad | EdgeForce):
            b, edges = continuum_edges(model, ld.nodes, item, "edge loads")
            facets = edge_facets(b, edges)
            if isinstance(ld, EdgeForce):
                # the total force as a uniform traction F / (L · thickness) over the edges
                # (F / A over the faces of a 3D body)
                if not (np.isfinite(ld.fx) and np.isfinite(ld.fy) and np.isfinite(ld.fz)):
                    raise ModelError(item, f"edge force ({ld.fx}, {ld.fy}, {ld.fz}) is NaN or "
                                     "inf")
                if b.dim == 2 and ld.fz != 0:
                    _dof_column(dofs, "z", f"{item}.fz", model)  # raises: a 2D model
                area = _fem.edge_length(b, facets) * (model.thickness if b.dim == 2 else 1.0)
                pn = pt = None
                trac = tuple(_pressure_function(v / area, b, ld.nodes, item)
                             for v in (ld.fx, ld.fy, ld.fz)[:b.dim])
            else:
                if b.dim == 3 and ld.tangential is not None:
                    raise ModelError(f"{item}.tangential", "has no direction on the faces of "
                                     f"3D body '{b.name}': give a pressure (normal) or a total "
                                     "force (EdgeForce with fx, fy, fz)")
                if b.dim == 3 and ld.traction is not None:
                    raise ModelError(f"{item}.traction", f"is a 2D traction (tx, ty); on the "
                                     f"faces of 3D body '{b.name}' give a pressure (normal) or "
                                     "a total force (EdgeForce with fx, fy, fz)")
                pn = _pressure_function(ld.normal, b, ld.nodes, item)
                pt = _pressure_function(ld.tangential, b, ld.nodes, item)
                trac = None if ld.traction is None else tuple(
                    _pressure_function(v, b, ld.nodes, f"{item}.traction[{c}]")
                    for c, v in enumerate(ld.traction))
            fb = _fem.edge_load(b, facets, pn, pt, model.thickness, trac)
            if not np.all(np.isfinite(fb)):
                raise ModelError(item, "pressure function gives NaN or inf")
            ids = off[b.name] + np.arange(b.n_nodes)
            np.add.at(f, dofs.of[ids][:, :b.dim].ravel(), fb)
        elif getattr(ld, "follows_level", False):
            continue  # a water load whose level is the factor: stepcontact.fem.level
        elif getattr(ld, "in_crack", False):
            continue  # water in opened joints: a load of the contact state (fem.crack)
        elif getattr(ld, "through", "faces") == "cfes":
            continue  # an uplift through the CFEs: added with the contact operator (assemble)
        elif hasattr(ld, "follows_level") and model.body(ld.nodes.body).dim == 3:
            f += facet_water_forces(model, dofs, ld, item)  # exact on the wet facets
        elif hasattr(ld, "edge_loads"):  # WaterLoad, Uplift (stepcontact.model.water)
            from stepcontact.fem._edge_kinks import water_forces

            f += water_forces(model, dofs, ld, item)
        elif isinstance(ld, BodyForce):
            _add_body_force(f, model, dofs, ld, item)
        elif isinstance(ld, SeismicCoefficient):  # inertia of the bodies and the reservoirs
            _add_body_force(f, model, dofs, ld.body_force(), item)
            f += reservoir_forces(model, dofs, ld, item)
        elif isinstance(ld, PrescribedDisplacement):
            if ld.dof not in _DOF_NAMES:
                raise ModelError(item, f"unknown dof '{ld.dof}'")
            c = _dof_column(dofs, ld.dof, item, model)
            if not np.isfinite(ld.value):
                raise ModelError(item, f"prescribed value is {ld.value}")
            ids = model.global_nodes(ld.nodes)
            d = dofs.of[ids, c]
            if np.any(d < 0):
                raise ModelError(item, f"rotation {ld.dof} prescribed on a node without "
                                 "rotation (not a frame node)")
            u[d] = ld.value
            pdofs.append(d)
        elif isinstance(ld, ObstacleMotion):
            # the rigid motion of the obstacle's vertex nodes (stepcontact.model.obstacle)
            obs = model.obstacle(ld.name)
            ids = model.obstacle_offsets[obs.name] + np.arange(obs.n_nodes)
            disp = ld.displacements(obs)
            for c in (0, 1):
                d = dofs.of[ids, c]
                u[d] += disp[:, c]
                pdofs.append(d)
        else:
            raise ModelError(item, f"unknown load type {type(ld).__name__}")
    pd = np.unique(np.concatenate(pdofs)) if pdofs else np.zeros(0, dtype=np.int64)
    return LoadVectors(f, u, pd)


def load_resultant(model: Model, dofs: DofMap, f: np.ndarray) -> np.ndarray:
    """Resultant of a nodal force vector ``f`` (ndof,): [F_x, F_y, M_z].

    F_x = Σ f_x, F_y = Σ f_y in N; M_z = Σ (x f_y − y f_x) + Σ m_z in N·m, about the origin,
    with (x, y) the coordinates of the node of each DOF and m_z the nodal moments of frames.
    Prescribed displacements are not forces and do not count.

    In a 3D model: [F_x, F_y, F_z, M_x, M_y, M_z], F = Σ f_i and M = Σ x_i × f_i + Σ m_i
    about the origin (m_i the nodal moments of space frames).

    Example
    -------
    >>> sysm = assemble(model)                                           # doctest: +SKIP
    >>> load_resultant(sysm.model, sysm.dofs, sysm.loads["push"].f)      # doctest: +SKIP
    array([10000., 0., -15000.])
    """
    f = np.asarray(f, dtype=float)
    has = dofs.of >= 0
    node, comp = np.nonzero(has)
    d = dofs.of[has]
    d, first = np.unique(d, return_index=True)  # tied nodes share a DOF: count it once
    node, comp = node[first], comp[first]
    xy = model.points[node]
    fd = f[d]
    if dofs.dim == 3:  # forces, then the nodal moments of space frames (columns 3-5)
        F = np.zeros((len(model.points), 6))
        np.add.at(F, (node, comp), fd)
        return np.r_[F[:, :3].sum(axis=0),
                     np.cross(model.points, F[:, :3]).sum(axis=0) + F[:, 3:].sum(axis=0)]
    fx = float(np.sum(fd[comp == 0]))
    fy = float(np.sum(fd[comp == 1]))
    mz = float(np.sum(xy[comp == 1, 0] * fd[comp == 1]) - np.sum(xy[comp == 0, 1] * fd[comp == 0])
               + np.sum(fd[comp == 2]))
    return np.array([fx, fy, mz])


def load_resultants(system: System) -> dict[str, np.ndarray]:
    """{pattern: [F_x, F_y, M_z]} of every load pattern per unit λ (see :func:`load_resultant`)."""
    return {name: load_resultant(system.model, system.dofs, lv.f)
            for name, lv in system.loads.items()}


#: the columns of :func:`load_moments`: the force resultant, the first-moment tensor
#: S_ab = Σ x_a f_b of the nodal forces and the sum of the nodal moments of frames
LOAD_MOMENT_COMPONENTS = ("Fx", "Fy", "Sxx", "Sxy", "Syx", "Syy", "Mz_nodal")


def load_moments(system: System) -> np.ndarray:
    """(n_patterns, n_bodies, 7) the loads of every pattern per unit λ on every body, in the
    order of ``system.loads`` and ``system.model.bodies`` (:data:`LOAD_MOMENT_COMPONENTS`):

    F = Σ_i f_i (N), the first-moment tensor S = Σ_i x_i ⊗ f_i (N·m; S_ab = Σ x_a f_b) of the
    nodal forces f_i at the nodes x_i of the body, and the sum of its nodal moments m_z (N·m,
    frames).  With them the moment of a body's loads about any point x_0, of their component
    along any unit direction d, is

        M_d = Σ_i ((x_i − x_0) × d)(f_i · d) = (S d) × d − (x_0 × d)(F · d)

    (a × b = a_x b_y − a_y b_x); M_z about x_0 is S_xy − S_yx − x_0 × F + Σ m_z.  A DOF shared
    by tied nodes counts once (for the body of its first node).  Prescribed displacements are
    not forces and do not count.
    """
    model, dofs = system.model, system.dofs
    bodies = list(model.bodies)
    out = np.zeros((len(system.loads), len(bodies), len(LOAD_MOMENT_COMPONENTS)))
    if not bodies:
        return out
    has = dofs.of >= 0
    node, comp = np.nonzero(has)
    d, first = np.unique(dofs.of[has], return_index=True)
    node, comp = node[first], comp[first]
    starts = np.array([model.node_offsets[b.name] for b in bodies])
    ends = starts + np.array([b.n_nodes for b in bodies])
    order = np.argsort(starts)
    j = np.searchsorted(starts[order], node, side="right") - 1
    body = order[np.clip(j, 0, None)]
    inside = (j >= 0) & (node < ends[body])
    node, comp, d, body = node[inside], comp[inside], d[inside], body[inside]
    xy = model.points[node]
    nb = len(bodies)
    for p, lv in enumerate(system.loads.values()):
        fd = np.asarray(lv.f, dtype=float)[d]
        for c in (0, 1):  # the force component c: F_c and the column S_·c
            on = comp == c
            out[p, :, c] = np.bincount(body[on], fd[on], nb)
            out[p, :, 2 + c] = np.bincount(body[on], xy[on, 0] * fd[on], nb)
            out[p, :, 4 + c] = np.bincount(body[on], xy[on, 1] * fd[on], nb)
        on = comp == 2
        out[p, :, 6] = np.bincount(body[on], fd[on], nb)
    return out


def contact_operator(cfe: ContactElements, dofs: DofMap) -> tuple[sp.csr_matrix, np.ndarray]:
    """B (n × ndof, n = m (1 + n_t)) with rows [u_τ; u_n] in the CFEs' layout, built from
    their local bases (rows t, n; :class:`~stepcontact.contact.layout.ContactLayout`), and
    w0 = [0; −g⁰] (see the geometry module)."""
    lay = cfe.layout
    m = lay.m
    rows_of = lay.operator_rows(cfe.basis)  # (m, 1 + n_t, dim): +t_j, −n
    nodes = np.concatenate([cfe.plus_nodes, cfe.minus_nodes], axis=1)  # (m, 6)
    w = np.concatenate([cfe.plus_w, -cfe.minus_w], axis=1)  # u⁺ − u⁻
    valid = nodes >= 0
    safe = np.where(valid, nodes, 0)
    rows, cols, vals = [], [], []
    k = np.repeat(np.arange(m)[:, None], nodes.shape[1], 1)
    for c in range(rows_of.shape[2]):
        d = np.where(valid, dofs.of[safe, c], -1)
        for j in range(lay.n_c):
            rows.append(j * m + k)
            cols.append(d)
            vals.append(w * rows_of[:, j, c : c + 1])
    B = scatter(np.concatenate([r.ravel() for r in rows]),
                np.concatenate([c.ravel() for c in cols]),
                np.concatenate([v.ravel() for v in vals]), (lay.n, dofs.ndof))
    w0 = lay.join(np.zeros((m,) + ((lay.n_t,) if lay.n_t > 1 else ())), -cfe.gap)
    return B, w0


def assemble(model: Model | DiscreteModel) -> System:
    """Assemble the whole model (stiffness, supports, loads, CFEs); a
    :class:`~stepcontact.model.DiscreteModel` is taken as it is
    (:func:`stepcontact.fem.discrete.assemble_discrete`)."""
    if isinstance(model, DiscreteModel):
        return assemble_discrete(model)
    if not model.bodies:
        raise ModelError("model", "has no body")
    dofs = dof_map(model)
    K = stiffness(model, dofs)
    fixed = np.zeros(dofs.ndof, dtype=bool)
    groups: list[tuple[str, np.ndarray]] = []  # (label, DOFs) of each reaction resultant
    for s in model.supports:
        ids = model.global_nodes(s.nodes)
        for dname in s.dofs:
            d = dofs.of[ids, _dof_column(dofs, dname, f"support '{s.name}'.dofs", model)]
            if np.any(d < 0):
                raise ModelError(f"support '{s.name}'", f"fixes {dname} of a node without "
                                 "rotation (not a frame node)")
            groups.append((f"{s.name}:{dname}", d))
            fixed[d] = True
    for obs in model.moving_obstacles:  # vertex nodes, prescribed: the obstacle's reaction
        ids = model.obstacle_offsets[obs.name] + np.arange(obs.n_nodes)
        for c, dname in enumerate(("x", "y")):
            d = dofs.of[ids, c]
            groups.append((f"{obs.name}:{dname}", d))
            fixed[d] = True
    loads, levels = {}, {}
    for p in model.patterns:
        if is_level_pattern(p):  # the factor is a water level: virtual patterns (fem.level)
            basis = level_basis(model, dofs, p)
            levels[p.name] = basis
            # its other loads act per metre of water: the pattern's own vector (factor h)
            loads[p.name] = load_vectors(model, dofs, p.name)
            for name, v in zip(basis.names, basis.vectors, strict=True):
                loads[name] = LoadVectors(v, np.zeros(dofs.ndof), np.zeros(0, dtype=np.int64))
        else:
            loads[p.name] = load_vectors(model, dofs, p.name)
    comp_of = np.full(dofs.ndof, -1)
    has = dofs.of >= 0
    comp_of[dofs.of[has]] = np.nonzero(has)[1]
    for name, lv in loads.items():
        fixed[lv.dofs] = True
        if len(lv.dofs):
            comp = comp_of[lv.dofs]
            for c, dname in enumerate(dofs.names):
                if np.any(comp == c):
                    groups.append((f"{name} (prescribed):{dname}", lv.dofs[comp == c]))
    cfe = build_contact(model)
    B, w0 = contact_operator(cfe, dofs)
    for p in model.patterns:
        for ld in p.loads:
            if getattr(ld, "through", "faces") != "cfes":
                continue
            # in a pattern whose factor is a water level it acts per metre of water (the
            # pattern's own vector, factor h), as an uplift on the faces does
            lv = loads[p.name]
            loads[p.name] = LoadVectors(lv.f + uplift_through_cfes(cfe, B, ld), lv.u, lv.dofs)
    if not fixed.any() and cfe.m == 0 and not any(sp_.b is None for sp_ in model.springs):
        raise ModelError("model", "has no supports and no contact: it is free to move")
    _check_restrained(model, dofs, K, B, fixed, cfe)
    rows, labels = reaction_rows(groups, dofs.ndof)
    from stepcontact.fem.crack import crack_water

    crack = crack_water(model, cfe, levels)
    return System(model, dofs, K, fixed, loads, cfe, B, w0, rows, labels, levels, crack=crack)


def uplift_through_cfes(cfe, B: sp.csr_matrix, ld) -> np.ndarray:
    """Force vector (ndof,) of an :class:`~stepcontact.model.Uplift` with ``through="cfes"``:
    W_k = A_k p(x_k) across each CFE of its interface, acting like a compressive normal force
    s_w = [0; W] of the CFEs, whose load on the structure is −Bᵀ s_w (N, per unit λ)."""
    k = cfe.of(ld.name)
    p = np.asarray(ld.function()(cfe.x[k, 0], cfe.x[k, 1]), float) * np.ones(len(k))
    if not np.all(np.isfinite(p)):
        raise ModelError(f"uplift on interface '{ld.name}'", "pressure function gives NaN "
                         "or inf")
    return -(B[cfe.layout.normal_rows[k]].T @ (cfe.area[k] * p))


def _check_restrained(model: Model, dofs: DofMap, K, B, fixed,
                      cfe: ContactElements | None = None) -> None:
    """Every body must be connected (elements, ties, springs, CFEs) to a support (or by CFEs
    to a fixed obstacle)."""
    A = (abs(K) + abs(B.T @ B)).tocsr()
    A = A + sp.diags(np.ones(dofs.ndof))
    ncomp, lab = sp.csgraph.connected_components(A, directed=False)
    grounded = np.zeros(ncomp, dtype=bool)
    grounded[lab[fixed]] = True
    if cfe is not None and cfe.m:  # CFEs against a fixed obstacle: their S− end is the ground
        ground = np.all(cfe.minus_nodes < 0, axis=1)
        nodes = cfe.plus_nodes[ground]
        d = dofs.of[nodes[nodes >= 0], :2]
        grounded[lab[d.ravel()]] = True
    for s in model.springs:  # springs to the ground restrain their components
        if s.b is None and s.stiffness_matrix().any():
            ids = model.global_nodes(s.a)
            grounded[lab[dofs.of[ids, :2]]] = True
    off = model.node_offsets
    for b in model.bodies:
        d = dofs.of[off[b.name] : off[b.name] + b.n_nodes, 0]
        loose = ~grounded[lab[d]]
        if loose.any() and not loose.all():  # the mesh falls apart (e.g. duplicate nodes)
            k = int(np.flatnonzero(loose)[0])
            at = ", ".join(f"{v:.6g}" for v in np.asarray(b.points)[k])
            raise ModelError(
                f"body '{b.name}'",
                f"part of it is not restrained: {int(loose.sum())} of its {b.n_nodes} nodes "
                f"(e.g. node {k} at ({at})) are connected to no support; its mesh "
                "falls apart into pieces (duplicate nodes along a line?)",
            )
        if loose.any():
            raise ModelError(
                f"body '{b.name}'",
                "is not restrained: no support, spring or contact connects it to a support",
            )
