"""The CFEs of an interface between 3D bodies (or of a 3D body on a rigid plane): which points
they join and with which weights, their local bases (t₁, t₂, n), tributary areas and
geometric gaps, from the surface geometry of :mod:`stepcontact.contact.surface3d`.

The kinematics are those of 2D (method.md §2, :mod:`stepcontact.contact.geometry`) with two
tangents: u_τj = t_j · (u⁺ − u⁻) (j = 1, 2) and u_n = −n · (u⁺ − u⁻) − g⁰, n from S− to S+;
the forces N ≤ 0 in compression and Q = (Q₁, Q₂) on the faceted cone |Q| ≤ −f N of
:class:`~stepcontact.contact.faceted.FacetedCoulombLaw` (eq. (1)); compliant layers (eq. (11))
and bonds (eq. (12)) as in 2D.  How a CFE joins S+ to S− (``Interface.cfe``):

* ``"node-to-node"``: each S+ node to the S− node at its place (matching meshes); n is S−'s
  outward normal there;
* ``"node-to-segment"`` (node-to-facet in 3D): each S+ node to its closest point on an S−
  facet, interpolated from that facet's nodes (:func:`~stepcontact.contact.surface3d.
  project_points`); S+ nodes beyond S−'s border get none;
* ``"mortar"``: segment-based mortar with dual weights (:func:`~stepcontact.contact.
  surface3d.mortar`): a CFE at each node of the coarser side (larger mean facet area, as in
  2D), or of the other side when some facets of the coarser one face it only in part and
  none of its own do (a block's face on a larger base); its other end the row D⁻¹ M of the
  facets opposite, its area D_i = ∫ φ_i dA; a uniform pressure passes exactly between
  non-matching meshes.  Between two tri6/quad8 sides (tet10/hex20) in the transformed basis
  φ̂ = T φ (:data:`~stepcontact.contact.surface3d.TRANSFORMED_KINDS`), the CFE's own end
  the transformed nodal value d̂ = T⁻ᵀ d;
* ``"auto"``: node-to-node where the meshes match, mortar otherwise.

Against a :class:`~stepcontact.model.obstacle.RigidPlane` every S+ node gets a CFE to the
ground with the plane's normal and the gap (x⁺ − x₀) · n.  Areas in m², lengths in m.

The result is the input of :func:`stepcontact.contact.geometry._finish` (gaps given or
geometric, areas, layers, bonds), which is shared with 2D.
"""

from __future__ import annotations

import numpy as np

from stepcontact.contact.surface3d import (
    MORTAR_KINDS,
    Surface,
    local_basis,
    mortar,
    project_points,
    surface_of_mesh,
)
from stepcontact.errors import ModelError
from stepcontact.model import Body, Interface, Model, NodeSet
from stepcontact.model.obstacle import RigidObstacle, RigidPlane

#: columns of a CFE end's nodes at least (the width of 2D ends; wider ends are padded)
MIN_END_NODES = 3


def face_surface(body: Body, ns: NodeSet, item: str) -> Surface:
    """The boundary facets of 3D ``body`` whose nodes all lie in ``ns``, oriented outward
    (node ids local to the body); a ModelError naming ``item`` when there are none."""
    if not isinstance(body, Body) or body.dim != 3:
        raise ModelError(item, f"body '{body.name}' is not a 3D body: a 3D interface joins "
                         "faces of 3D bodies")
    surf = surface_of_mesh(body.mesh, body.element, name=f"{item} ({ns.label})")
    inset = np.zeros(body.n_nodes, dtype=bool)
    inset[ns.index] = True
    keep = np.all(inset[surf.facets], axis=1)
    if not keep.any():
        raise ModelError(f"{item} ({ns.label})", f"contains no boundary face of body "
                         f"'{body.name}' (a 3D interface needs whole faces)")
    return Surface(surf.points, surf.facets[keep], surf.kind, surf.mesh_facets[keep],
                   name=surf.name)


def _ends(nodes: np.ndarray, weights: np.ndarray, offset: int) -> tuple[np.ndarray, np.ndarray]:
    """Global node ids (−1 padding) and weights of CFE ends, at least MIN_END_NODES wide."""
    width = max(MIN_END_NODES, nodes.shape[1])
    n = np.full((len(nodes), width), -1, dtype=np.int64)
    w = np.zeros((len(nodes), width))
    n[:, :nodes.shape[1]] = np.where(nodes >= 0, nodes + offset, -1)
    w[:, :nodes.shape[1]] = np.where(nodes >= 0, weights, 0.0)
    return n, w


def _given_normal(itf: Interface, m: int) -> np.ndarray | None:
    """The interface's given normal tiled over m CFEs (None when not given)."""
    if itf.normal is None:
        return None
    n = np.asarray(itf.normal, float)
    if n.shape != (3,):
        raise ModelError(f"interface '{itf.name}'.normal", f"is a {n.size}-vector; a 3D "
                         "interface needs (n_x, n_y, n_z)")
    return np.tile(n / np.linalg.norm(n), (m, 1))


def _coincident(x: np.ndarray, y: np.ndarray, tol: float) -> np.ndarray:
    """For each point x, the index of the point of y at its place (within tol), or −1."""
    from scipy.spatial import cKDTree

    dist, j = cKDTree(y).query(x)
    return np.where(dist <= tol, j, -1)


def _positive_areas(item: str, surf: Surface, nodes: np.ndarray) -> np.ndarray:
    """The tributary areas ∫ φ_i dA of the S+ nodes; their corners' ∫ φ ≤ 0 on tri6/quad8
    faces is refused by name."""
    a = surf.nodal_areas()[nodes]
    if np.any(a <= 0):
        raise ModelError(item, f"its CFEs sit on '{surf.kind}' faces, whose corner nodes "
                         "have no positive tributary area (∫ φ ≤ 0): use cfe = 'mortar' (its "
                         "transformed basis), or linear or hex27 elements")
    return a


def _partly_faced(overlap: np.ndarray, areas: np.ndarray) -> bool:
    """Does a facet face the other side only in part (its ``overlap`` neither its whole area
    nor nothing, to 1e-9; m²)?  Its dual functions are then fitted to that part."""
    return bool(np.any((overlap > 1e-9 * areas) & (overlap < (1 - 1e-9) * areas)))


def _mortar_sides(splus: Surface, sminus: Surface, axis):
    """The mortar CFEs on one side: (on S+?, :class:`~stepcontact.contact.surface3d.Mortar`).

    Among the sides whose facets can carry them (:data:`MORTAR_KINDS`), the coarser one (the
    larger mean facet area, S+ on a tie, as in 2D), unless some of its facets face the other
    side only in part and none of the other's do (a block's face on a larger base): then the
    other one, so that no dual function is fitted to a sliver of a facet."""
    ok_p, ok_m = splus.kind in MORTAR_KINDS, sminus.kind in MORTAR_KINDS
    if not (ok_p or ok_m):  # both tri6/quad8: either, in the transformed basis
        ok_p = ok_m = True
    if ok_p != ok_m:
        first = ok_p
    else:
        first = float(splus.areas.mean()) >= float(sminus.areas.mean()) * (1 - 1e-9)
    order = (True, False) if first else (False, True)
    tries = []
    for on_plus in order if ok_p == ok_m else order[:1]:
        mo = mortar(splus, sminus, axis) if on_plus else mortar(sminus, splus, axis)
        side = splus if on_plus else sminus
        if not _partly_faced(mo.facet_overlap, side.areas):
            return on_plus, mo
        tries.append((on_plus, mo))
    return tries[0]


def _obstacle(model: Model, itf: Interface, splus: Surface, nodes: np.ndarray) -> dict:
    """CFEs of S+ nodes against a fixed rigid plane (S− ends: the ground)."""
    plane = itf.minus
    m = len(nodes)
    xp = splus.points[nodes]
    nrm = np.tile(plane.normal, (m, 1))
    gap = (xp - plane.point) @ plane.normal
    n_m = np.full((m, MIN_END_NODES), -1, dtype=np.int64)
    return dict(order=nodes, xp=xp, xm=xp - gap[:, None] * nrm, nrm=nrm,
                trib=_positive_areas(f"interface '{itf.name}'", splus, nodes), n_m=n_m,
                wm=np.zeros((m, MIN_END_NODES)), geo_gap=gap)


def _mortar(model: Model, itf: Interface, splus: Surface, sminus: Surface) -> dict:
    """Mortar CFEs on one side's nodes (:func:`_mortar_sides`; dual weights, D_i their
    areas)."""
    bp, bm = model.body(itf.plus.body), model.body(itf.minus.body)
    off = model.node_offsets
    axis = None if itf.axis is None else np.asarray(itf.axis, float)
    on_plus, mo = _mortar_sides(splus, sminus, axis)
    # the CFE's own end: its node, or on tri6/quad8 facets the transformed nodal value
    own = ((mo.nodes[:, None], np.ones((len(mo.nodes), 1))) if mo.own_cols is None
           else (mo.own_cols, mo.own_weights))
    if on_plus:
        n_m, wm = _ends(mo.cols, mo.weights, off[bm.name])
        parts = dict(order=mo.nodes, xp=mo.x, xm=mo.x - mo.gap[:, None] * mo.normal,
                     nrm=mo.normal, trib=mo.area, n_m=n_m, wm=wm, geo_gap=mo.gap)
        if mo.own_cols is not None:
            parts["plus"] = _ends(*own, off[bp.name])
        return parts
    # CFEs on the S− nodes: their S+ end the weighted row
    n_p, wp = _ends(mo.cols, mo.weights, off[bp.name])
    n_m, wm = _ends(*own, off[bm.name])
    nrm = -mo.normal  # S−'s outward normal: from S− to S+
    return dict(order=mo.nodes, xp=mo.x, xm=mo.x, nrm=nrm, trib=mo.area, n_m=n_m, wm=wm,
                plus=(n_p, wp), geo_gap=mo.gap)


def interface_parts(model: Model, itf: Interface, tol: float) -> dict:
    """The CFEs of one 3D interface before gaps, areas and layers: a dict with ``order`` (the
    body-local ids of the nodes that carry the CFEs), ``xp`` (m, 3) their points, ``xm`` the
    S− ends, ``nrm`` (m, 3) unit normals S− → S+, ``tan`` (m, 2, 3) the tangents t₁, t₂,
    ``s`` the CFE's number, ``trib`` (m,) its area, m², ``n_m``, ``wm`` the S− end's global
    nodes and weights, ``geo_gap`` the geometric gap (m) and, for mortar CFEs on S−,
    ``plus`` = (nodes, weights) of the S+ end.  ``tol``: the model's length tolerance, m."""
    item = f"interface '{itf.name}'"
    if itf.pairs:
        raise ModelError(f"{item}.pairs", "node pairs between 3D bodies are not available "
                         "yet: give the faces (plus and minus node sets)")
    bp = model.body(itf.plus.body)
    model.global_nodes(itf.plus)
    splus = face_surface(bp, itf.plus, f"{item}.plus")
    nodes = splus.nodes
    axis = None if itf.axis is None else np.asarray(itf.axis, float)
    if isinstance(itf.minus, RigidObstacle):
        if not isinstance(itf.minus, RigidPlane):
            raise ModelError(f"{item}.minus", f"obstacle '{itf.minus.name}' is a 2D polyline: "
                             "a 3D body meets a RigidPlane")
        parts = _obstacle(model, itf, splus, nodes)
    else:
        bm = model.body(itf.minus.body)
        model.global_nodes(itf.minus)
        sminus = face_surface(bm, itf.minus, f"{item}.minus")
        parts = None
        if itf.cfe in ("auto", "node-to-node"):
            match = _coincident(splus.points[nodes], sminus.points[sminus.nodes], tol)
            back = _coincident(sminus.points[sminus.nodes], splus.points[nodes], tol)
            if itf.cfe == "node-to-node" or (np.all(match >= 0) and np.all(back >= 0)):
                parts = _node_to_node(model, itf, splus, sminus, nodes, match)
        if parts is None and itf.cfe in ("auto", "mortar"):
            parts = _mortar(model, itf, splus, sminus)
        if parts is None:
            parts = _node_to_facet(model, itf, splus, sminus, nodes, tol)
    m = len(parts["order"])
    given = _given_normal(itf, m)
    if given is not None:
        parts["nrm"] = given
        if "plus" not in parts:  # (mortar CFEs on S−: the gap stays the distance to S+)
            parts["geo_gap"] = np.einsum("ij,ij->i", parts["xp"] - parts["xm"], given)
    basis = local_basis(parts["nrm"], axis) if m else np.zeros((0, 3, 3))
    parts["nrm"] = basis[:, 2]
    parts["tan"] = basis[:, :2]
    parts["s"] = np.arange(m, dtype=float)
    return parts


def _node_to_node(model: Model, itf: Interface, splus: Surface, sminus: Surface,
                  nodes: np.ndarray, match: np.ndarray) -> dict:
    """Each S+ node joined to the S− node at its place; n: S−'s outward normal there."""
    bad = np.flatnonzero(match < 0)
    xp = splus.points[nodes]
    if bad.size:
        k = int(bad[0])
        raise ModelError(f"interface '{itf.name}' CFE {k} at {tuple(np.round(xp[k], 6))}",
                         "cfe = 'node-to-node' needs an S- node at every S+ node; none is there "
                         "(use 'mortar' for meshes that do not match)")
    bm = model.body(itf.minus.body)
    mn = sminus.nodes[match]
    n_m, wm = _ends(mn[:, None], np.ones((len(mn), 1)), model.node_offsets[bm.name])
    proj = project_points(xp, sminus)
    return dict(order=nodes, xp=xp, xm=sminus.points[mn], nrm=proj.normal,
                trib=_positive_areas(f"interface '{itf.name}'", splus, nodes), n_m=n_m, wm=wm,
                geo_gap=np.einsum("ij,ij->i", xp - sminus.points[mn], proj.normal))


def _node_to_facet(model: Model, itf: Interface, splus: Surface, sminus: Surface,
                   nodes: np.ndarray, tol: float) -> dict:
    """Each S+ node joined to its closest point on S−, interpolated from that facet's nodes.
    S+ nodes whose closest point is on S−'s border but not along its normal (beyond the
    border, an overhang) get no CFE, as S+ nodes beyond the ends of a 2D obstacle."""
    item = f"interface '{itf.name}'"
    bm = model.body(itf.minus.body)
    trib = _positive_areas(item, splus, nodes)
    proj = project_points(splus.points[nodes], sminus)
    off = (splus.points[nodes] - proj.x_minus) - proj.gap[:, None] * proj.normal
    keep = np.linalg.norm(off, axis=1) <= tol
    if not keep.any():
        raise ModelError(f"{item}.plus", "no node of S+ lies over S- (every one is beyond its "
                         "border)")
    nodes, trib = nodes[keep], trib[keep]
    n_m, wm = _ends(proj.nodes[keep], proj.weights[keep], model.node_offsets[bm.name])
    return dict(order=nodes, xp=splus.points[nodes], xm=proj.x_minus[keep],
                nrm=proj.normal[keep], trib=trib, n_m=n_m, wm=wm, geo_gap=proj.gap[keep])


__all__ = ["face_surface", "interface_parts"]
