"""3D contact surfaces: facets, outward normals, tributary areas, node-to-facet projection and
segment-based mortar weights, on plain arrays (coordinates in m, areas in m²).

The geometry a 3D CFE needs (method.md §2: a point of S+ joined to the opposite point of S−,
that end interpolated from the nodes of an S− facet when the meshes do not match):

* :class:`Surface` — linear or quadratic facets of a body's boundary (``tri3``, ``tri6``,
  ``quad4``, ``quad8``, ``quad9``), corners counter-clockwise seen from outside, so that
  ∂X/∂ξ₁ × ∂X/∂ξ₂ is the outward normal; :func:`surface_of_mesh` takes them from a
  scikit-fem tetrahedral or hexahedral mesh (all boundary facets or a named boundary).
* :meth:`Surface.nodal_areas` — the tributary area A_i = ∫ φ_i dA of every node (their sum is
  the surface's area), the area of a node-to-facet CFE on S+.
* :func:`project_points` — node-to-facet: the closest point of each S+ point on S−, its facet's
  nodes and shape-function weights (the CFE's end on S−), the gap along the normal and the local
  basis (t₁, t₂, n) with n from S− to S+ (:func:`local_basis`).
* :func:`mortar` — segment-based mortar on triangles and quadrilaterals: every pair of facing
  facets projected onto the S+ facet's plane, the polygons clipped (:func:`clip_polygons`,
  Sutherland–Hodgman), the overlap cut into triangles and integrated by Gauss points; the
  standard mortar matrices D = ∫ φ_i φ_j and M = ∫ φ_i ψ_l, and the dual (biorthogonal)
  weights that make D diagonal, so that each S+ node is one CFE whose S− end is the row
  D⁻¹ M (the 3D twin of the 2D mortar CFEs of :mod:`stepcontact.contact.geometry`).

The CFE kinematics are those of 2D with two tangents: u_τ = (t₁, t₂) · (u⁺ − u⁻),
u_n = −n · (u⁺ − u⁻) − g⁰, forces N ≤ 0 in compression and Q = (Q₁, Q₂) with |Q| ≤ −f N
(conditions (1) of the article, on the faceted cone of :mod:`stepcontact.contact.faceted`).

The CFEs of 3D interfaces are built on this module by :mod:`stepcontact.contact.interface3d`.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from stepcontact.contact.boundary import near_pairs
from stepcontact.errors import ModelError

#: facet kinds: (corners, nodes); the nodes are the corners (counter-clockwise seen from
#: outside), then the mid-side nodes (side i from corner i to corner i + 1), then the centre
FACET_KINDS = {"tri3": (3, 3), "tri6": (3, 6), "quad4": (4, 4), "quad8": (4, 8),
               "quad9": (4, 9)}
#: the 3D element kinds and the facet kinds of their boundary
ELEMENT_FACETS = {"tet4": "tri3", "tet10": "tri6", "hex8": "quad4", "hex20": "quad8",
                  "hex27": "quad9"}
#: relative tolerance of the geometric tests (inside a facet, snapped weights, slivers)
_EPS = 1e-12


# ---- shape functions --------------------------------------------------------------------------
def _line3(s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """1D quadratic Lagrange functions on [−1, 1] at nodes −1, 1, 0 and their derivatives."""
    n = np.stack([0.5 * s * (s - 1), 0.5 * s * (s + 1), 1 - s * s], axis=-1)
    d = np.stack([s - 0.5, s + 0.5, -2 * s], axis=-1)
    return n, d


def shape(kind: str, xi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Shape functions of a facet kind at local coordinates ``xi`` (..., 2) and their
    derivatives: ``(N (..., n), dN (..., n, 2))``.

    Triangles: ξ = (r, s) on the unit triangle r, s ≥ 0, r + s ≤ 1 (barycentric L = (1 − r −
    s, r, s)); quadrilaterals: ξ ∈ [−1, 1]², corners (−1, −1), (1, −1), (1, 1), (−1, 1).
    """
    xi = np.asarray(xi, dtype=float)
    r, s = xi[..., 0], xi[..., 1]
    if kind in ("tri3", "tri6"):
        L = np.stack([1 - r - s, r, s], axis=-1)
        dL = np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]])
        if kind == "tri3":
            return L, np.broadcast_to(dL, L.shape + (2,)).copy()
        i, j = np.array([0, 1, 2]), np.array([1, 2, 0])
        N = np.concatenate([L * (2 * L - 1), 4 * L[..., i] * L[..., j]], axis=-1)
        dN = np.concatenate([(4 * L - 1)[..., None] * dL,
                             4 * (L[..., j, None] * dL[i] + L[..., i, None] * dL[j])], axis=-2)
        return N, dN
    cr = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    if kind == "quad4":
        a = 1 + r[..., None] * cr[:, 0]
        b = 1 + s[..., None] * cr[:, 1]
        N = 0.25 * a * b
        dN = 0.25 * np.stack([cr[:, 0] * b, a * cr[:, 1]], axis=-1)
        return N, dN
    if kind == "quad8":
        a = 1 + r[..., None] * cr[:, 0]
        b = 1 + s[..., None] * cr[:, 1]
        c = r[..., None] * cr[:, 0] + s[..., None] * cr[:, 1] - 1
        Nc = 0.25 * a * b * c
        dNc = 0.25 * np.stack([cr[:, 0] * b * c + a * b * cr[:, 0],
                               a * cr[:, 1] * c + a * b * cr[:, 1]], axis=-1)
        one = np.ones_like(r)
        # mid-sides (0, −1), (1, 0), (0, 1), (−1, 0)
        Nm = np.stack([0.5 * (1 - r * r) * (1 - s), 0.5 * (1 + r) * (1 - s * s),
                       0.5 * (1 - r * r) * (1 + s), 0.5 * (1 - r) * (1 - s * s)], axis=-1)
        dNm = np.stack([
            np.stack([-r * (1 - s), -0.5 * (1 - r * r) * one], axis=-1),
            np.stack([0.5 * (1 - s * s) * one, -(1 + r) * s], axis=-1),
            np.stack([-r * (1 + s), 0.5 * (1 - r * r) * one], axis=-1),
            np.stack([-0.5 * (1 - s * s) * one, -(1 - r) * s], axis=-1)], axis=-2)
        return np.concatenate([Nc, Nm], axis=-1), np.concatenate([dNc, dNm], axis=-2)
    if kind == "quad9":
        nr, dr = _line3(r)
        ns, ds = _line3(s)
        # (i, j) indices into the 1D functions (nodes −1, 1, 0) of each of the nine nodes
        i = np.array([0, 1, 1, 0, 2, 1, 2, 0, 2])
        j = np.array([0, 0, 1, 1, 0, 2, 1, 2, 2])
        N = nr[..., i] * ns[..., j]
        dN = np.stack([dr[..., i] * ns[..., j], nr[..., i] * ds[..., j]], axis=-1)
        return N, dN
    raise ModelError("facet kind", f"'{kind}' is not one of {tuple(FACET_KINDS)}")


def _is_tri(kind: str) -> bool:
    return kind.startswith("tri")


def _centre(kind: str) -> np.ndarray:
    """Local coordinates of a facet's centre."""
    return np.array([1 / 3, 1 / 3]) if _is_tri(kind) else np.zeros(2)


def _gauss_triangle(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss points (n², 2) and weights (sum 1/2) on the unit triangle: n × n Gauss–Legendre
    collapsed onto it (r = u, s = v (1 − u)); exact for polynomials of degree ≤ 2n − 2."""
    x, w = np.polynomial.legendre.leggauss(n)
    u, wu = 0.5 * (x + 1), 0.5 * w
    U, V = np.meshgrid(u, u, indexing="ij")
    W = np.outer(wu, wu) * (1 - U)
    return np.column_stack([U.ravel(), (V * (1 - U)).ravel()]), W.ravel()


def _gauss_reference(kind: str, n: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """Gauss points and weights on a facet's reference domain (n per direction)."""
    if _is_tri(kind):
        return _gauss_triangle(n)
    x, w = np.polynomial.legendre.leggauss(n)
    X, Y = np.meshgrid(x, x, indexing="ij")
    return np.column_stack([X.ravel(), Y.ravel()]), np.outer(w, w).ravel()


def _inside(kind: str, xi: np.ndarray, tol: float = 1e-10) -> np.ndarray:
    """Is ξ in the facet's reference domain (within ``tol``)?"""
    r, s = xi[..., 0], xi[..., 1]
    if _is_tri(kind):
        return (r >= -tol) & (s >= -tol) & (r + s <= 1 + tol)
    return (np.abs(r) <= 1 + tol) & (np.abs(s) <= 1 + tol)


def _clamp(kind: str, xi: np.ndarray) -> np.ndarray:
    """ξ moved into the reference domain (the nearest point of it in ξ)."""
    if not _is_tri(kind):
        return np.clip(xi, -1.0, 1.0)
    r, s = np.maximum(xi[..., 0], 0.0), np.maximum(xi[..., 1], 0.0)
    over = r + s - 1
    r, s = np.where(over > 0, r - over / 2, r), np.where(over > 0, s - over / 2, s)
    return np.clip(np.stack([r, s], axis=-1), 0.0, 1.0)


def _reference_sides(kind: str) -> tuple[np.ndarray, np.ndarray]:
    """The sides of the reference domain: start and end corner coordinates, (sides, 2) each."""
    if _is_tri(kind):
        c = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    else:
        c = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    return c, np.roll(c, -1, axis=0)


# ---- a surface --------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Surface:
    """Facets of a 3D body's boundary (linear or quadratic), oriented outward.

    Attributes
    ----------
    points : (n, 3) float
        Node coordinates, m (all the body's nodes: facets index into them).
    facets : (F, k) int
        Node ids of each facet: corners counter-clockwise seen from outside the body, then
        mid-side nodes (side i from corner i to corner i + 1), then the centre (``quad9``).
    kind : str
        ``"tri3"``, ``"tri6"``, ``"quad4"``, ``"quad8"`` or ``"quad9"``.
    mesh_facets : (F,) int or None
        The scikit-fem facet index of each facet, when taken from a mesh.
    name : str
        What the surface is, for error messages.
    """

    points: np.ndarray
    facets: np.ndarray
    kind: str
    mesh_facets: np.ndarray | None = None
    name: str = "surface"

    def __post_init__(self):
        item = self.name
        if self.kind not in FACET_KINDS:
            raise ModelError(f"{item}.kind", f"'{self.kind}' is not one of {tuple(FACET_KINDS)}")
        pts = np.asarray(self.points, dtype=float)
        fac = np.asarray(self.facets)
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise ModelError(f"{item}.points", f"must be (n, 3) coordinates, got {pts.shape}")
        bad = ~np.all(np.isfinite(pts), axis=1)
        if np.any(bad):
            raise ModelError(f"{item} node {int(np.flatnonzero(bad)[0])}",
                             "coordinate is NaN or inf")
        k = FACET_KINDS[self.kind][1]
        if fac.ndim != 2 or fac.shape[1] != k or not np.issubdtype(fac.dtype, np.integer):
            raise ModelError(f"{item}.facets", f"'{self.kind}' facets must be (F, {k}) integer "
                                               f"node ids, got {fac.shape} {fac.dtype}")
        out = np.flatnonzero(np.any((fac < 0) | (fac >= len(pts)), axis=1))
        if out.size:
            raise ModelError(f"{item} facet {int(out[0])}",
                             f"node id outside 0 … {len(pts) - 1}: {fac[out[0]].tolist()}")
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "facets", fac.astype(np.int64))
        degenerate = np.flatnonzero(self.areas <= _EPS * self.size ** 2)
        if degenerate.size:
            raise ModelError(f"{item} facet {int(degenerate[0])}", "has no area (degenerate)")

    def __len__(self) -> int:
        return len(self.facets)

    @property
    def corners(self) -> np.ndarray:
        """(F, 3|4) node ids of the facets' corners."""
        return self.facets[:, : FACET_KINDS[self.kind][0]]

    @cached_property
    def size(self) -> float:
        """The extent of the surface's nodes (largest side of their bounding box), m."""
        used = self.points[np.unique(self.facets)]
        return float(np.ptp(used, axis=0).max()) if len(used) else 0.0

    @cached_property
    def nodes(self) -> np.ndarray:
        """The ids of the nodes on the surface, sorted."""
        return np.unique(self.facets)

    def geometry(self, xi: np.ndarray, facets: np.ndarray | None = None):
        """Points X(ξ) (F, P, 3) in m and tangents ∂X/∂ξ (F, P, 3, 2) at local coordinates
        ``xi``: (P, 2) for every facet, or (F, P, 2) per facet (``facets`` selects them)."""
        fac = self.facets if facets is None else self.facets[facets]
        N, dN = shape(self.kind, xi)
        Xe = self.points[fac]  # (F, k, 3)
        if N.ndim == 2:
            return np.einsum("pk,fkd->fpd", N, Xe), np.einsum("pka,fkd->fpda", dN, Xe)
        return np.einsum("fpk,fkd->fpd", N, Xe), np.einsum("fpka,fkd->fpda", dN, Xe)

    @cached_property
    def centroids(self) -> np.ndarray:
        """(F, 3) the mean of each facet's corners, m."""
        return self.points[self.corners].mean(axis=1)

    @cached_property
    def radii(self) -> np.ndarray:
        """(F,) the largest distance from a facet's centroid to its nodes, m."""
        return np.linalg.norm(self.points[self.facets] - self.centroids[:, None], axis=2).max(1)

    @cached_property
    def normals(self) -> np.ndarray:
        """(F, 3) outward unit normals at the facets' centres (exact for flat facets)."""
        _, dX = self.geometry(_centre(self.kind)[None])
        n = np.cross(dX[:, 0, :, 0], dX[:, 0, :, 1])
        return n / np.linalg.norm(n, axis=1)[:, None]

    def _jacobians(self, n: int = 4):
        xi, w = _gauss_reference(self.kind, n)
        _, dX = self.geometry(xi)
        J = np.linalg.norm(np.cross(dX[..., 0], dX[..., 1]), axis=-1)  # (F, P) dA/dξ
        return xi, w[None] * J

    @cached_property
    def areas(self) -> np.ndarray:
        """(F,) facet areas ∫ dA, m² (Gauss, 4 points per direction: exact for flat linear
        facets and flat quadratic ones with straight sides)."""
        return self._jacobians()[1].sum(axis=1)

    def check_orientation(self) -> None:
        """Raise a ModelError naming the first facet whose corners turn the other way than a
        neighbour's (consistently oriented facets run through each shared side in opposite
        directions), or a side shared by more than two facets."""
        c = self.corners
        a, b = c.ravel(), np.roll(c, -1, axis=1).ravel()
        n = len(self.points)
        directed = a * n + b
        undirected = np.minimum(a, b) * n + np.maximum(a, b)
        _, inv, cnt = np.unique(undirected, return_inverse=True, return_counts=True)
        _, dinv, dcnt = np.unique(directed, return_inverse=True, return_counts=True)
        bad = np.flatnonzero((cnt[inv] > 2) | (dcnt[dinv] > 1))
        if bad.size:
            f = int(bad[0] // c.shape[1])
            raise ModelError(f"{self.name} facet {f}",
                             f"side ({int(a[bad[0]])}, {int(b[bad[0]])}) is run through in "
                             "the same direction by another facet, or shared by more than two: "
                             "the facets are not consistently oriented")

    def nodal_areas(self) -> np.ndarray:
        """(n,) tributary areas A_i = Σ_facets ∫ φ_i dA of every node (0 off the surface), m².

        The same Gauss rule as :attr:`areas`, so Σ_i A_i = Σ_facets area (partition of unity).
        A flat ``tri3`` gives A/3 to each corner, a flat ``quad4`` parallelogram A/4.  The
        corners of a flat ``tri6`` get 0 (∫ φ = 0 there) and those of a ``quad8`` −A/12: the
        known property of these elements, for which node-to-facet CFEs on S+ need other
        weights (not done here)."""
        xi, wJ = self._jacobians()
        N, _ = shape(self.kind, xi)
        out = np.zeros(len(self.points))
        np.add.at(out, self.facets, np.einsum("fp,pk->fk", wJ, N))
        return out


def _ordered_kind(mesh, element: str | None) -> tuple[str, str]:
    """The element kind of a scikit-fem mesh and its facet kind (checked)."""
    name = type(mesh).__name__
    family = "tet" if name.startswith("MeshTet") else "hex" if name.startswith("MeshHex") else None
    if family is None:
        raise ModelError("mesh", f"a 3D contact surface needs a MeshTet or MeshHex mesh, got "
                                 f"{name}")
    if element is None:
        quadratic = name.endswith("2")
        element = {"tet": ("tet4", "tet10"), "hex": ("hex8", "hex27")}[family][quadratic]
    if element not in ELEMENT_FACETS or not element.startswith(family):
        ok = tuple(k for k in ELEMENT_FACETS if k.startswith(family))
        raise ModelError("element", f"'{element}' does not fit a {name} mesh (one of {ok})")
    return element, ELEMENT_FACETS[element]


def surface_of_mesh(mesh, element: str | None = None, boundary: str | None = None,
                    name: str | None = None) -> Surface:
    """The boundary facets of a scikit-fem 3D mesh as a :class:`Surface`, oriented outward.

    Parameters
    ----------
    mesh : skfem MeshTet, MeshHex, MeshTet2 or MeshHex2
    element : str, optional
        ``"tet4"``, ``"tet10"``, ``"hex8"``, ``"hex20"`` or ``"hex27"``: which nodes the body
        has (default: linear for MeshTet/MeshHex, ``tet10``/``hex27`` for MeshTet2/MeshHex2).
        The node ids and ``points`` are those of the scikit-fem basis of that element (its
        ``doflocs``): vertices first, then edge, facet and interior nodes.
    boundary : str, optional
        Only the facets of ``mesh.boundaries[boundary]`` (they must lie on the boundary).

    Each facet's corners are turned counter-clockwise seen from outside: its normal at the
    centre points away from the centroid of the element that owns it.
    """
    from skfem import (
        Basis,
        ElementHex1,
        ElementHex2,
        ElementHexS2,
        ElementTetP1,
        ElementTetP2,
    )

    element, kind = _ordered_kind(mesh, element)
    item = name or (f"boundary '{boundary}'" if boundary else "mesh boundary")
    bfacets = mesh.boundary_facets()
    if boundary is None:
        fsel = bfacets
    else:
        named = mesh.boundaries or {}
        if boundary not in named:
            raise ModelError(f"boundary '{boundary}'",
                             f"the mesh has no such boundary (known: {tuple(named)})")
        fsel = np.asarray(named[boundary], dtype=np.int64)
        off = np.setdiff1d(fsel, bfacets)
        if off.size:
            raise ModelError(f"boundary '{boundary}' facet {int(off[0])}",
                             "is not on the mesh's boundary (an inner facet)")
    if fsel.size == 0:
        raise ModelError(item, "has no facets")
    elem = {"tet4": ElementTetP1, "tet10": ElementTetP2, "hex8": ElementHex1,
            "hex20": ElementHexS2, "hex27": ElementHex2}[element]()
    basis = Basis(mesh, elem, intorder=1)
    points = np.ascontiguousarray(basis.doflocs.T)
    corners = mesh.facets[:, fsel].T.copy()  # cyclic order (scikit-fem)
    p = mesh.p.T
    owner = mesh.f2t[0, fsel]
    centroid = p[mesh.t[:, owner].T].mean(axis=1)
    c = p[corners]
    if corners.shape[1] == 3:
        nrm = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
        rev = np.array([0, 2, 1])
    else:
        nrm = np.cross(c[:, 2] - c[:, 0], c[:, 3] - c[:, 1])
        rev = np.array([0, 3, 2, 1])
    flip = np.einsum("ij,ij->i", c.mean(axis=1) - centroid, nrm) < 0
    corners[flip] = corners[flip][:, rev]
    parts = [corners]
    if FACET_KINDS[kind][1] > FACET_KINDS[kind][0]:  # mid-side nodes from the mesh's edges
        nv = p.shape[0]
        e = np.sort(mesh.edges, axis=0)
        key = e[0] * nv + e[1]
        order = np.argsort(key)
        a, b = corners, np.roll(corners, -1, axis=1)
        want = np.minimum(a, b) * nv + np.maximum(a, b)
        edge = order[np.searchsorted(key[order], want)]
        parts.append(basis.edge_dofs[0, edge])
    if kind == "quad9":
        parts.append(basis.facet_dofs[0, fsel][:, None])
    return Surface(points, np.column_stack(parts).astype(np.int64), kind,
                   mesh_facets=np.asarray(fsel, dtype=np.int64), name=item)


# ---- local bases ------------------------------------------------------------------------------
def local_basis(normal: np.ndarray, axis: np.ndarray | None = None) -> np.ndarray:
    """Orthonormal right-handed bases (m, 3, 3) with rows t₁, t₂, n for unit normals (m, 3).

    t₁ is the projection of ``axis`` ((3,) or (m, 3)) on the plane ⊥ n, normalised; by default
    the global axis e_j along which n has its smallest component (the first such j on a tie
    within 1e-12), so a horizontal joint (n = ±z) has t₁ = +x.  t₂ = n × t₁.
    """
    n = np.atleast_2d(np.asarray(normal, dtype=float))
    n = n / np.linalg.norm(n, axis=1)[:, None]
    if axis is None:
        a = np.abs(n)
        j = np.argmax(a <= a.min(axis=1, keepdims=True) + 1e-12, axis=1)
        ref = np.eye(3)[j]
    else:
        ref = np.broadcast_to(np.asarray(axis, dtype=float), n.shape)
    t1 = ref - np.einsum("ij,ij->i", ref, n)[:, None] * n
    norm = np.linalg.norm(t1, axis=1)
    bad = norm <= 1e-8 * np.linalg.norm(ref, axis=1)
    if np.any(bad):
        k = int(np.flatnonzero(bad)[0])
        raise ModelError(f"axis of contact point {k}", "is parallel to the normal there: it "
                                                       "gives no tangent t1")
    t1 /= norm[:, None]
    t2 = np.cross(n, t1)
    t2 /= np.linalg.norm(t2, axis=1)[:, None]
    return np.stack([t1, t2, n], axis=1)


# ---- node-to-facet ----------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class NodeToFacet:
    """The closest points on S− of m points of S+ (node-to-facet CFEs).

    Attributes
    ----------
    facet : (m,) int
        The S− facet of each closest point.
    xi : (m, 2) float
        Its local coordinates on that facet.
    nodes : (m, k) int
        That facet's node ids (the CFE's end on S−).
    weights : (m, k) float
        The shape functions there (sum 1): x⁻ = Σ w_l X_l, u⁻ = Σ w_l u_l.
    x_minus : (m, 3) float
        The closest points, m.
    normal : (m, 3) float
        Unit normal from S− to S+: S−'s outward normal at x⁻.
    gap : (m,) float
        The signed distance along it, (x⁺ − x⁻) · n, m: > 0 apart, < 0 penetrating.
    distance : (m,) float
        |x⁺ − x⁻|, m.
    basis : (m, 3, 3) float
        The local basis, rows t₁, t₂, n (:func:`local_basis`).
    """

    facet: np.ndarray
    xi: np.ndarray
    nodes: np.ndarray
    weights: np.ndarray
    x_minus: np.ndarray
    normal: np.ndarray
    gap: np.ndarray
    distance: np.ndarray
    basis: np.ndarray


def _newton_matrix(J: np.ndarray, r: np.ndarray, H2: np.ndarray) -> np.ndarray:
    """The Hessian JᵀJ − r · ∂²X of ½ |x − X(ξ)|² where it is positive definite, else the
    Gauss–Newton matrix JᵀJ (far from a minimum on a curved facet)."""
    JtJ = np.einsum("pda,pdb->pab", J, J)
    H = JtJ - np.einsum("pd,pdab->pab", r, H2)
    det = H[:, 0, 0] * H[:, 1, 1] - H[:, 0, 1] * H[:, 1, 0]
    ok = (H[:, 0, 0] > 0) & (det > 1e-12 * np.einsum("paa->p", JtJ) ** 2)
    return np.where(ok[:, None, None], H, JtJ)


def _closest_on_facets(surf: Surface, x: np.ndarray, f: np.ndarray):
    """Closest points of x[i] on facets f[i]: (ξ (P, 2), X (P, 3), distance (P,)).

    The foot of the perpendicular, by Newton's method on ½ |x − X(ξ)|² (one step for a flat
    triangle, quadratic convergence otherwise; the second derivatives of X by central
    differences of ∂X/∂ξ, exact for the quadratic facets), kept where it lies in the facet;
    and the closest point of each side (Newton along it, clamped to its ends).  The nearest of
    these is the closest point."""
    kind = surf.kind
    P = len(x)
    Xe = surf.points[surf.facets[f]]  # (P, k, 3)
    hd = 1e-4

    def at(xi):
        N, dN = shape(kind, xi)
        return np.einsum("pk,pkd->pd", N, Xe), np.einsum("pka,pkd->pda", dN, Xe)

    def at_some(xi, rows):
        N, dN = shape(kind, xi)
        Xr = Xe[rows]
        return np.einsum("pk,pkd->pd", N, Xr), np.einsum("pka,pkd->pda", dN, Xr)

    def second_some(xi, rows):  # ∂²X/∂ξ_a∂ξ_b, (P, 3, 2, 2); 0 on a triangle
        if kind == "tri3":
            return np.zeros((len(xi), 3, 2, 2))
        cols = []
        for b in range(2):
            e = np.zeros(2)
            e[b] = hd
            cols.append((at_some(xi + e, rows)[1] - at_some(xi - e, rows)[1]) / (2 * hd))
        return np.stack(cols, axis=-1)

    def second(xi):
        return second_some(xi, slice(None))

    xi = np.broadcast_to(_centre(kind), (P, 2)).copy()
    active = np.arange(P)  # points still moving; those that leave the facet stop
    for _ in range(50):
        Xa, Ja = at_some(xi[active], active)
        r = x[active] - Xa
        H = _newton_matrix(Ja, r, second_some(xi[active], active))
        step = np.linalg.solve(H, np.einsum("pda,pd->pa", Ja, r)[..., None])[..., 0]
        xi[active] += step
        moving = np.any(np.abs(step) > _EPS, axis=1) & _inside(kind, xi[active], 1.0)
        active = active[moving]
        if active.size == 0:
            break
    inside = _inside(kind, xi)
    xi = np.where(inside[:, None], xi, _clamp(kind, xi))
    X, _ = at(xi)
    d = np.where(inside, np.linalg.norm(x - X, axis=1), np.inf)
    a, b = _reference_sides(kind)
    for s in range(len(a)):  # 3 or 4 sides, vectorised over the points
        ab = b[s] - a[s]
        t = np.full(P, 0.5)
        for _ in range(50):
            p = a[s] + t[:, None] * ab
            Xs, J = at(p)
            d1 = J @ ab
            d2 = np.einsum("pdab,a,b->pd", second(p), ab, ab)
            r = x - Xs
            g = np.einsum("pd,pd->p", r, d1)
            h = np.einsum("pd,pd->p", d1, d1)
            hn = h - np.einsum("pd,pd->p", r, d2)
            t_new = np.clip(t + g / np.where(hn > 1e-12 * h, hn, h), 0.0, 1.0)
            done = np.all(np.abs(t_new - t) <= _EPS)
            t = t_new
            if done:
                break
        p = a[s] + t[:, None] * ab
        Xs, _ = at(p)
        ds = np.linalg.norm(x - Xs, axis=1)
        better = ds < d * (1 - _EPS) - _EPS * surf.size  # the foot inside wins a tie
        d = np.where(better, ds, d)
        xi = np.where(better[:, None], p, xi)
        X = np.where(better[:, None], Xs, X)
    return xi, X, d


def closest_facets(surf: Surface, x: np.ndarray):
    """The closest point of each x (m, 3) on the surface: (facet, ξ, X, distance).

    Exact search, O(m log F): the facets' centroids in a k-d tree give candidates at distance
    d (the best of the 8 nearest centroids); any closer facet has its centroid within d + the
    largest facet radius, and all of those are tried.  Ties (a point over a shared side or a
    node) go to the lowest facet index."""
    from scipy.spatial import cKDTree

    x = np.asarray(x, dtype=float).reshape(-1, 3)
    tree = cKDTree(surf.centroids)
    k = min(8, len(surf))
    _, cand = tree.query(x, k=k)
    cand = np.asarray(cand).reshape(len(x), -1)
    rows = np.repeat(np.arange(len(x)), cand.shape[1])
    _, _, d = _closest_on_facets(surf, x[rows], cand.ravel())
    best = d.reshape(len(x), -1).min(axis=1)
    rmax = float(surf.radii.max())
    slack = 1e-12 * (best + rmax + surf.size)
    rows, cols = near_pairs(tree, x, best + rmax + slack)
    # a facet can hold a point within ``best`` of x only if its centroid is within best + r_f
    near = (np.linalg.norm(x[rows] - surf.centroids[cols], axis=1)
            <= best[rows] + surf.radii[cols] + slack[rows])
    rows, cols = rows[near], cols[near]
    xi, X, d = _closest_on_facets(surf, x[rows], cols)
    tie = _EPS * (surf.size + 1.0)
    dq = np.round(d / tie)  # equal within round-off: the lowest facet index wins
    order = np.lexsort((cols, dq, rows))
    pick = order[np.searchsorted(rows[order], np.arange(len(x)))]
    return cols[pick], xi[pick], X[pick], d[pick]


def _snap(w: np.ndarray) -> np.ndarray:
    """Weights within 1e-12 of 0 set to 0, the rest rescaled to sum 1 (a point on a side or a
    node of S− is tied to that side's or node's nodes only)."""
    w = np.where(np.abs(w) <= _EPS, 0.0, w)
    return w / w.sum(axis=1, keepdims=True)


def project_points(x: np.ndarray, minus: Surface, axis: np.ndarray | None = None) -> NodeToFacet:
    """Node-to-facet CFEs: each point x (m, 3) of S+ tied to its closest point on S− (method.md
    §2: a CFE end inside an S− facet, interpolated from its nodes).

    Triangles by barycentric coordinates, quadrilaterals by the inverse of their bilinear (or
    quadratic) map, both by vectorised Newton steps; a point beyond S−'s border goes to the
    border's closest point.  n is S−'s outward normal at x⁻ (∂X/∂ξ₁ × ∂X/∂ξ₂), pointing from
    S− to S+; the gap (x⁺ − x⁻) · n in m; t₁, t₂ from :func:`local_basis` (``axis``).
    """
    x = np.asarray(x, dtype=float).reshape(-1, 3)
    if not np.all(np.isfinite(x)):
        k = int(np.flatnonzero(~np.all(np.isfinite(x), axis=1))[0])
        raise ModelError(f"contact point {k}", "coordinate is NaN or inf")
    f, xi, X, d = closest_facets(minus, x)
    N, dN = shape(minus.kind, xi)
    Xe = minus.points[minus.facets[f]]
    J = np.einsum("pka,pkd->pda", dN, Xe)
    n = np.cross(J[..., 0], J[..., 1])
    n /= np.linalg.norm(n, axis=1)[:, None]
    return NodeToFacet(facet=f, xi=xi, nodes=minus.facets[f], weights=_snap(N), x_minus=X,
                       normal=n, gap=np.einsum("ij,ij->i", x - X, n), distance=d,
                       basis=local_basis(n, axis))


# ---- polygon clipping -------------------------------------------------------------------------
def polygon_areas(poly: np.ndarray, count: np.ndarray) -> np.ndarray:
    """Signed areas (shoelace) of planar polygons (P, K, 2) with ``count`` (P,) vertices each
    (counter-clockwise > 0), m²."""
    K = poly.shape[1]
    valid = np.arange(K)[None] < count[:, None]
    nxt = np.where(np.arange(K)[None] + 1 < count[:, None], np.arange(K)[None] + 1, 0)
    q = np.take_along_axis(poly, nxt[..., None], axis=1)
    cross = poly[..., 0] * q[..., 1] - poly[..., 1] * q[..., 0]
    return 0.5 * np.where(valid, cross, 0.0).sum(axis=1)


def clip_polygons(subject: np.ndarray, n_subject: np.ndarray, clip: np.ndarray,
                  n_clip: np.ndarray, tol: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Sutherland–Hodgman clipping of P planar polygons at once.

    ``subject`` (P, Ks, 2) with ``n_subject`` vertices each (any polygon, counter-clockwise),
    ``clip`` (P, Kc, 2) with ``n_clip`` vertices (convex, counter-clockwise).  Returns the
    clipped polygons (P, Ks + Kc, 2) and their vertex counts (0: no overlap).  A vertex within
    ``tol`` (m) of a clip side counts as inside.  Vectorised over the pairs; a loop over the
    clip sides (at most Kc)."""
    P, Ks = subject.shape[:2]
    Kmax = Ks + clip.shape[1]
    poly = np.zeros((P, Kmax, 2))
    poly[:, :Ks] = subject
    cnt = np.asarray(n_subject, dtype=np.int64).copy()
    n_clip = np.asarray(n_clip, dtype=np.int64)
    rows = np.arange(P)
    for s in range(clip.shape[1]):
        active = s < n_clip
        a = clip[:, s]
        b = clip[rows, np.where(s + 1 < n_clip, s + 1, 0)]
        e = b - a
        L = np.linalg.norm(e, axis=1) + 1e-300
        # signed distance of each vertex from the side, > 0 inside (to the left)
        dist = (e[:, None, 0] * (poly[..., 1] - a[:, None, 1])
                - e[:, None, 1] * (poly[..., 0] - a[:, None, 0])) / L[:, None]
        K = np.arange(Kmax)[None]
        valid = K < cnt[:, None]
        prev = np.where(K > 0, K - 1, cnt[:, None] - 1)
        prev = np.maximum(prev, 0)
        d_prev = np.take_along_axis(dist, prev, axis=1)
        p_prev = np.take_along_axis(poly, prev[..., None], axis=1)
        ins, ins_prev = dist >= -tol, d_prev >= -tol
        cross = valid & (ins != ins_prev)
        t = d_prev / np.where(cross, d_prev - dist, 1.0)
        xcut = p_prev + t[..., None] * (poly - p_prev)
        # each vertex emits [intersection if the side is crossed] then [itself if inside]
        emit = np.stack([cross, valid & ins], axis=2).reshape(P, 2 * Kmax)
        pts = np.stack([xcut, poly], axis=2).reshape(P, 2 * Kmax, 2)
        pos = np.cumsum(emit, axis=1) - 1
        new = np.zeros_like(poly)
        r, c = np.nonzero(emit & (pos < Kmax))
        new[r, pos[r, c]] = pts[r, c]
        new_cnt = np.minimum(emit.sum(axis=1), Kmax)
        poly = np.where(active[:, None, None], new, poly)
        cnt = np.where(active, new_cnt, cnt)
    cnt = np.where(cnt >= 3, cnt, 0)
    return poly, cnt


# ---- mortar -----------------------------------------------------------------------------------
#: Gauss points per direction on each triangle of an overlap (collapsed rule, exact for
#: polynomials of degree 4: the products φ_i ψ_l of linear facets have degree 2); one more
#: (degree 6) where a facet is quadratic
MORTAR_GAUSS = 3
#: facet kinds of the side that carries mortar CFEs: those whose ∫ φ_i > 0 at every node
#: (a flat tri6 has 0 at its corners, a quad8 −A/12)
MORTAR_KINDS = ("tri3", "quad4", "quad9")
#: facet kinds that carry mortar CFEs in the transformed basis of Popp et al. (2012), "Dual
#: quadratic mortar finite element methods for 3D finite deformation contact":
#: φ̂_c = φ_c + α Σ φ_m (the two mid-sides next to corner c), φ̂_m = (1 − 2α) φ_m
TRANSFORMED_KINDS = ("tri6", "quad8")
#: α of the transformation: Σ φ̂ = Σ φ = 1 for any α (each mid-side gives α to each of its two
#: corners); on a flat facet of area A, ∫ φ̂_c = 2αA/3 (tri6) or (8α − 1)A/12 (quad8) and
#: ∫ φ̂_m = (1 − 2α)A/3, all > 0 for 1/8 < α < 1/2; α = 1/5 gives 2A/15, A/20 and A/5
ALPHA = 0.2


def _transformation(kind: str) -> np.ndarray:
    """T (n, n) of a tri6/quad8 facet, φ̂ = T φ (φ̂_i = Σ_j T_ij φ_j)."""
    k, n = FACET_KINDS[kind]
    T = np.eye(n)
    side = np.arange(k)
    T[side, k + side] = ALPHA
    T[(side + 1) % k, k + side] = ALPHA
    T[k + side, k + side] = 1 - 2 * ALPHA
    return T


def _own_ends(plus: Surface, nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The S+ ends of mortar CFEs on tri6/quad8 facets: the nodal values of the transformed
    basis, d̂ = T⁻ᵀ d: d̂_c = d_c at a corner, d̂_m = (d_m − α (d_c1 + d_c2)) / (1 − 2α) at a
    mid-side node between corners c1, c2 (node ids (m, 3), −1 padding; weights, Σ = 1)."""
    k = FACET_KINDS[plus.kind][0]
    side = np.arange(k)
    own = np.full((len(plus.points), 3), -1, dtype=np.int64)
    own[:, 0] = np.arange(len(plus.points))
    wts = np.zeros((len(plus.points), 3))
    wts[:, 0] = 1.0
    mids = plus.facets[:, k + side].ravel()
    own[mids, 1] = plus.facets[:, side].ravel()
    own[mids, 2] = plus.facets[:, (side + 1) % k].ravel()
    wts[mids] = np.array([1.0, -ALPHA, -ALPHA]) / (1 - 2 * ALPHA)
    return own[nodes], wts[nodes]


@dataclass(frozen=True, eq=False)
class Mortar:
    """Segment-based mortar coupling of S+ (the multiplier side) to S−.

    Attributes
    ----------
    D, M : scipy.sparse.csr_matrix, (n⁺, n⁺) and (n⁺, n⁻)
        The standard mortar matrices D_ij = ∫ φ_i φ_j dA, M_il = ∫ φ_i ψ_l dA over the
        overlap of S+ and S− (φ on S+, ψ on S−; node ids of ``plus.points`` and
        ``minus.points``), m².
    M_dual : scipy.sparse.csr_matrix, (n⁺, n⁻)
        M with the dual (biorthogonal) functions φ*_i of S+ for φ_i, which make D diagonal:
        ∫ φ*_i φ_j dA = δ_ij D_i.
    nodes : (m,) int
        The S+ nodes that face S− (one mortar CFE each).
    area : (m,) float
        D_i = ∫ φ_i dA over the overlap, m²: the CFE's contact area (Σ = overlap area).
    cols, weights : (m, c) int, float
        The CFE's end on S−: row i of D⁻¹ M_dual (S− node ids, weights; −1, 0 padding).
        Σ weights = 1, and a field linear on a flat S− is carried to S+ exactly.
    normal : (m, 3) float
        Unit normal from S− to S+ (−S+'s outward normals averaged with the weights D_i).
    basis : (m, 3, 3) float
        Rows t₁, t₂, n (:func:`local_basis`).
    overlap_area : float
        The area of the overlap, m².
    x : (m, 3) float
        The S+ nodes' coordinates, m.
    gap : (m,) float
        The initial gap at each node, its signed distance to S− (:func:`project_points`: > 0
        apart), m; at the node, not a weighted mean, as for the 2D mortar CFEs.
    facet_overlap : (F⁺,) float
        The area of each S+ facet that faces S−, m² (its area when wholly faced, 0 when not
        at all): facets faced only in part have dual functions fitted to a part of them.
    own_cols, own_weights : (m, 3) int, float or None
        On tri6/quad8 facets (:data:`TRANSFORMED_KINDS`), the CFE's own end on S+: the
        nodal value d̂_i of the transformed basis (:func:`_own_ends`); None otherwise (the
        node itself).
    """

    D: object
    M: object
    M_dual: object
    nodes: np.ndarray
    area: np.ndarray
    cols: np.ndarray
    weights: np.ndarray
    normal: np.ndarray
    basis: np.ndarray
    overlap_area: float
    x: np.ndarray
    gap: np.ndarray
    facet_overlap: np.ndarray | None = None
    own_cols: np.ndarray | None = None
    own_weights: np.ndarray | None = None


def _inverse_map(kind: str, corners: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Local coordinates ξ (T, G, 2) of plane points y (T, G, 2) in facets whose nodes are
    projected to the plane (T, k, 2): barycentric (one Newton step) for linear triangles, the
    bilinear (or quadratic) inverse otherwise (Newton to round-off)."""
    xi = np.broadcast_to(_centre(kind), y.shape).copy()
    for _ in range(25):
        N, dN = shape(kind, xi)
        X = np.einsum("tgk,tkd->tgd", N, corners)
        J = np.einsum("tgka,tkd->tgda", dN, corners)
        step = np.linalg.solve(J, (y - X)[..., None])[..., 0]
        xi += step
        if np.all(np.abs(step) <= _EPS):
            break
    return xi


def _pairs(plus: Surface, minus: Surface) -> tuple[np.ndarray, np.ndarray]:
    """Candidate (S+ facet, S− facet) pairs: S− centroids within d + r⁺ + r⁻_max of each S+
    facet's centroid (d its distance to S−, r the facet radii; a k-d tree), facing each
    other (outward normals opposed)."""
    from scipy.spatial import cKDTree

    _, _, _, d = closest_facets(minus, plus.centroids)
    tol = _EPS * max(plus.size, minus.size, 1.0)
    radius = d + plus.radii + float(minus.radii.max()) + tol
    e, f = near_pairs(cKDTree(minus.centroids), plus.centroids, radius)
    near = (np.linalg.norm(plus.centroids[e] - minus.centroids[f], axis=1)
            <= d[e] + plus.radii[e] + minus.radii[f] + tol)
    facing = np.einsum("ij,ij->i", plus.normals[e], minus.normals[f]) < -1e-9
    return e[near & facing], f[near & facing]


def mortar(plus: Surface, minus: Surface, axis: np.ndarray | None = None) -> Mortar:
    """Mortar CFEs on the nodes of S+ (segment-based integration): S+ of ``tri3``, ``quad4``
    or ``quad9`` facets (:data:`MORTAR_KINDS`), or of ``tri6``/``quad8`` facets in the
    transformed basis φ̂ = T φ (:data:`TRANSFORMED_KINDS`, whose corners have ∫ φ ≤ 0: the
    dual functions are built on φ̂, and each CFE's own end is the transformed nodal value
    d̂ = T⁻ᵀ d, ``own_cols``/``own_weights``), S− of any kind.

    For every pair of facing facets (e on S+, f on S−): both are projected onto the auxiliary
    plane of e (through its centroid, ⊥ its normal at the centre, exact for flat facets), the
    projection of f clipped by that of e (:func:`clip_polygons`), the overlap cut into a fan of
    triangles, and on each MORTAR_GAUSS² Gauss points the shape functions φ of e and ψ of f
    evaluated at the points of e and f that project there (barycentric / bilinear inverse).
    The polygons are the facets' corners: exact for flat facets with straight sides (curved
    quadratic facets are cut along their chords).  Where S− facets lie at several distances
    under e (the far side of a body), only those within one facet size of the nearest are
    kept.

    D, M are the standard mortar matrices.  The CFEs use the dual functions
    φ*_i = Σ_j A_ij φ_j of each S+ facet, A = D_e M_e⁻¹ with M_e = ∫ φ φᵀ and D_e =
    diag(∫ φ) over the facet's overlap, so that ∫ φ*_i φ_j = δ_ij D_i: D is diagonal exactly,
    not lumped, and the S− end of CFE i is the row D_i⁻¹ ∫ φ*_i ψ_l.  Then Σ_l M_il = D_i
    (a constant is carried exactly) and Σ_l M_il u_l = D_i u_i for any field linear on flat
    coincident surfaces (the patch condition; quadratic too where both sides are quadratic),
    whatever the Gauss rule.  For CFEs on S−,
    call ``mortar(minus, plus)`` and reverse the normal.
    """
    from scipy.sparse import coo_matrix

    if plus.kind not in MORTAR_KINDS + TRANSFORMED_KINDS:
        raise ModelError(f"plus surface '{plus.name}'",
                         f"mortar CFEs on '{plus.kind}' facets are not implemented (one of "
                         f"{MORTAR_KINDS}): their corners have ∫ φ ≤ 0, so the dual basis "
                         "gives them no CFE; put the CFEs on the other side or use "
                         "node-to-facet")
    n_p, n_m = len(plus.points), len(minus.points)
    tol = _EPS * max(plus.size, minus.size, 1.0)
    e, f = _pairs(plus, minus)
    if e.size == 0:
        raise ModelError(f"plus surface '{plus.name}'", f"no facet faces the minus surface "
                                                        f"'{minus.name}' (no overlap)")
    # the auxiliary plane of each S+ facet: origin its centroid, axes t₁, t₂ ⊥ its normal
    B = local_basis(plus.normals)
    ax = B[e, :2]  # (P, 2, 3)
    c0 = plus.centroids[e]
    cp = np.einsum("pkd,pad->pka", plus.points[plus.corners[e]] - c0[:, None], ax)
    cm = np.einsum("pkd,pad->pka", minus.points[minus.corners[f]] - c0[:, None], ax)
    n_p_c, n_m_c = cp.shape[1], cm.shape[1]
    side = np.roll(cp, -1, axis=1) - cp
    turn = side[..., 0] * np.roll(side, -1, axis=1)[..., 1] - side[..., 1] * np.roll(
        side, -1, axis=1)[..., 0]
    bad = np.flatnonzero(np.any(turn <= 0, axis=1))
    if bad.size:
        raise ModelError(f"plus surface '{plus.name}' facet {int(e[bad[0]])}",
                         "is not convex in its own plane")
    # projections whose bounding boxes do not meet cannot overlap
    meet = np.all((cm.min(axis=1) < cp.max(axis=1) - tol) & (cp.min(axis=1) < cm.max(axis=1)
                                                              - tol), axis=1)
    e, f, cp, cm, c0, ax = e[meet], f[meet], cp[meet], cm[meet], c0[meet], ax[meet]
    poly, cnt = clip_polygons(cm[:, ::-1], np.full(len(e), n_m_c), cp,
                              np.full(len(e), n_p_c), tol)
    area = polygon_areas(poly, cnt)
    keep = area > _EPS * plus.areas[e]
    # normal distance at the overlap's centre; keep S− facets within a facet size of the nearest
    K = np.arange(poly.shape[1])[None]
    ctr = np.where((K < cnt[:, None])[..., None], poly, 0).sum(1) / np.maximum(cnt, 1)[:, None]
    xm = c0 + np.einsum("pa,pad->pd", ctr, ax)
    h = np.einsum("pd,pd->p", minus.centroids[f] - xm, minus.normals[f])
    h = np.abs(h / np.einsum("pd,pd->p", minus.normals[f], plus.normals[e]))
    hmin = np.full(len(plus), np.inf)
    np.minimum.at(hmin, e[keep], h[keep])
    keep &= h <= hmin[e] + np.maximum(plus.radii[e], minus.radii[f]) + tol
    e, f, poly, cnt, c0, ax = e[keep], f[keep], poly[keep], cnt[keep], c0[keep], ax[keep]
    # all the facets' nodes in the auxiliary planes, for the inverse maps
    cp = np.einsum("pkd,pad->pka", plus.points[plus.facets[e]] - c0[:, None], ax)
    cm = np.einsum("pkd,pad->pka", minus.points[minus.facets[f]] - c0[:, None], ax)
    # fan triangles (0, j, j + 1) of each overlap, and their Gauss points
    j = np.arange(1, poly.shape[1] - 1)
    tp, tj = np.nonzero(j[None] < cnt[:, None] - 1)
    tri = np.stack([poly[tp, 0], poly[tp, j[tj]], poly[tp, j[tj] + 1]], axis=1)  # (T, 3, 2)
    quadratic = FACET_KINDS[plus.kind][1] > 4 or FACET_KINDS[minus.kind][1] > 4
    g, wg = _gauss_triangle(MORTAR_GAUSS + quadratic)
    L = np.column_stack([1 - g.sum(1), g])
    y = np.einsum("gk,tkd->tgd", L, tri)
    at = 2 * polygon_areas(tri, np.full(len(tri), 3))
    w = at[:, None] * wg[None]  # (T, G), m²
    phi = shape(plus.kind, _inverse_map(plus.kind, cp[tp], y))[0]  # (T, G, n⁺)
    transformed = plus.kind in TRANSFORMED_KINDS
    if transformed:
        phi = np.einsum("ij,tgj->tgi", _transformation(plus.kind), phi)  # φ̂ = T φ
    psi = shape(minus.kind, _inverse_map(minus.kind, cm[tp], y))[0]  # (T, G, n⁻)
    ep, fm = plus.facets[e[tp]], minus.facets[f[tp]]
    k_p, k_m = phi.shape[2], psi.shape[2]

    def sparse(vals, r, c, shape_):
        return coo_matrix((vals.ravel(), (r.ravel(), c.ravel())), shape=shape_).tocsr()

    Dt = np.einsum("tg,tgi,tgj->tij", w, phi, phi)
    Mt = np.einsum("tg,tgi,tgl->til", w, phi, psi)
    rr = np.repeat(ep[:, :, None], k_p, 2)
    D = sparse(Dt, rr, np.swapaxes(rr, 1, 2), (n_p, n_p))
    M = sparse(Mt, np.repeat(ep[:, :, None], k_m, 2), np.repeat(fm[:, None, :], k_p, 1),
               (n_p, n_m))
    # the dual functions of each S+ facet over its overlap
    ue, inv = np.unique(e[tp], return_inverse=True)
    Me = np.zeros((len(ue), k_p, k_p))
    np.add.at(Me, inv, Dt)
    De = np.zeros((len(ue), k_p))
    np.add.at(De, inv, np.einsum("tg,tgi->ti", w, phi))
    A = np.swapaxes(np.linalg.solve(Me, np.eye(k_p)[None] * De[:, :, None]), 1, 2)  # D_e M_e⁻¹
    dual = np.einsum("tij,tgj->tgi", A[inv], phi)
    Md = sparse(np.einsum("tg,tgi,tgl->til", w, dual, psi), np.repeat(ep[:, :, None], k_m, 2),
                np.repeat(fm[:, None, :], k_p, 1), (n_p, n_m))
    Dd = np.zeros(n_p)
    np.add.at(Dd, plus.facets[ue], De)
    nd = np.zeros((n_p, 3))
    np.add.at(nd, plus.facets[ue], De[..., None] * -plus.normals[ue][:, None, :])
    # S+ nodes whose facets face S− over more than 1e-9 of their tributary area
    nodes = np.flatnonzero(Dd > 1e-9 * np.abs(plus.nodal_areas()))
    rows = Md[nodes].tocsr()
    rows.eliminate_zeros()
    width = int(np.diff(rows.indptr).max(initial=0))
    cols = np.full((len(nodes), width), -1, dtype=np.int64)
    wts = np.zeros((len(nodes), width))
    r = np.repeat(np.arange(len(nodes)), np.diff(rows.indptr))
    pos = np.arange(len(rows.indices)) - rows.indptr[r]
    cols[r, pos] = rows.indices
    wts[r, pos] = rows.data / Dd[nodes][r]
    nrm = nd[nodes] / np.linalg.norm(nd[nodes], axis=1)[:, None]
    x = plus.points[nodes]
    own = own_w = None
    if transformed:
        own, own_w = _own_ends(plus, nodes)
        used = np.unique(own[own >= 0])
        g_all = np.zeros(n_p)
        g_all[used] = project_points(plus.points[used], minus).gap
        gap = np.einsum("mc,mc->m", np.where(own >= 0, g_all[own], 0.0), own_w)
    else:
        gap = project_points(x, minus).gap
    return Mortar(D=D, M=M, M_dual=Md, nodes=nodes, area=Dd[nodes], cols=cols, weights=wts,
                  normal=nrm, basis=local_basis(nrm, axis), overlap_area=float(w.sum()), x=x,
                  gap=gap, facet_overlap=np.bincount(e[tp], w.sum(axis=1), minlength=len(plus)),
                  own_cols=own, own_weights=own_w)


__all__ = ["ELEMENT_FACETS", "FACET_KINDS", "Mortar", "NodeToFacet", "Surface", "clip_polygons",
           "closest_facets", "local_basis", "mortar", "polygon_areas", "project_points",
           "shape", "surface_of_mesh"]
