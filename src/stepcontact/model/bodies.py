"""Materials, continuum bodies and frames, and the kinds and ranges they are checked against.

Plain, immutable dataclasses (SI units: m, N, Pa, kg).  The allowed kinds (plane, element,
DOF names) and ranges (Poisson's ratio, Young's modulus) here are the one source of these rules.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal, get_args

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model import plausible
from stepcontact.model.elements import body_arrays

# The allowed kinds and ranges below are the one source of these rules: the dataclasses check
# them, and the model file's schema (:mod:`stepcontact.io.modelfile.schema`) takes its
# literals and bounds from them.
PlaneKind = Literal["strain", "stress"]
PLANE_KINDS: tuple[str, ...] = get_args(PlaneKind)
ElementKind = Literal["tri3", "tri6", "quad4", "quad8", "quad9"]
ELEMENT_KINDS: tuple[str, ...] = get_args(ElementKind)
#: the element kinds of 3D continua (scikit-fem's ElementTetP1, ElementTetP2, ElementHex1,
#: ElementHexS2, ElementHex2 on a MeshTet or MeshHex)
SolidKind = Literal["tet4", "tet10", "hex8", "hex20", "hex27"]
SOLID_KINDS: tuple[str, ...] = get_args(SolidKind)
DofName = Literal["x", "y", "rz"]
DOF_NAMES: tuple[str, ...] = get_args(DofName)
#: the DOFs of a node of a 3D continuum (translations along x, y, z)
DOF_NAMES_3D: tuple[str, ...] = ("x", "y", "z")


def _either(kinds: tuple) -> str:
    """``'a' or 'b'``, ``'a', 'b' or 'c'``: the allowed kinds for a message."""
    names = [repr(k) for k in kinds]
    return names[0] if len(names) == 1 else f"{', '.join(names[:-1])} or {names[-1]}"


#: Poisson's ratio of an isotropic material (and of a contact layer) lies in this open interval
NU_RANGE: tuple[float, float] = (-1.0, 0.5)


#: accepted range of Young's modulus (Pa): far beyond any material (foams ~1e3 Pa, diamond
#: ~1e12 Pa) in any unit system, and safely away from under- and overflow of the stiffness
E_RANGE: tuple[float, float] = (1e-10, 1e20)
#: two bodies whose Young's moduli are further apart than this cannot be solved together: the
#: softer stiffness is below the round-off of the stiffer one (double precision, eps ≈ 2e-16)
E_RATIO_MIN = 1e-15


def modulus_problem(E: float) -> str | None:
    """Why Young's modulus ``E`` (Pa, positive) is refused: outside :data:`E_RANGE` (None when
    it is inside)."""
    lo, hi = E_RANGE
    if lo <= E <= hi:
        return None
    return (f"Young's modulus E = {E:g} is outside {lo:g} … {hi:g} (Pa): no material is that "
            "soft or stiff in any unit system, and the stiffness matrix would under- or "
            "overflow; check the value")


# --------------------------------------------------------------------------------------------
# materials and bodies
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Material:
    """Isotropic linear-elastic material.

    Parameters
    ----------
    E : float
        Young's modulus, Pa.
    nu : float
        Poisson's ratio (-1 < nu < 0.5).
    density : float
        Mass density, kg/m³ (used for self-weight and, later, dynamics).
    """

    E: float
    nu: float
    density: float = 0.0

    def check(self, item: str) -> None:
        if not np.isfinite(self.E) or self.E <= 0:
            raise ModelError(item, f"Young's modulus E must be positive and finite, got {self.E}")
        if (text := modulus_problem(self.E)) is not None:
            raise ModelError(item, text)
        if not np.isfinite(self.nu) or not NU_RANGE[0] < self.nu < NU_RANGE[1]:
            raise ModelError(item, f"Poisson's ratio nu must lie in ({NU_RANGE[0]:g}, "
                             f"{NU_RANGE[1]:g}), got {self.nu}")
        if not np.isfinite(self.density) or self.density < 0:
            raise ModelError(item, f"density must be >= 0, got {self.density}")
        plausible.warn("E", self.E, f"{item}.E", stacklevel=4)
        plausible.warn("density", self.density, f"{item}.density", stacklevel=4)


@dataclass(frozen=True, eq=False)
class Body:
    """A linear-elastic continuum body meshed with one scikit-fem element kind.

    Use :func:`stepcontact.model.mesh.rectangle` (2D), :func:`stepcontact.model.mesh.box`
    (3D) or :meth:`Body.from_mesh` to make one.  The dimension follows from the mesh: a
    ``MeshTri``/``MeshQuad`` body is 2D (DOFs ux, uy per node), a ``MeshTet``/``MeshHex``
    body is 3D (ux, uy, uz).

    Attributes
    ----------
    name : str
        Unique name of the body.
    mesh : skfem.Mesh
        The scikit-fem mesh (its geometry; for quadratic elements the mid-side nodes are the
        degrees of freedom of the quadratic basis).
    element : str
        2D: ``"tri3"``, ``"tri6"``, ``"quad4"``, ``"quad8"`` or ``"quad9"``; 3D: ``"tet4"``,
        ``"tet10"``, ``"hex8"``, ``"hex20"`` or ``"hex27"``.
    material : Material
    points : ndarray (n, 2) or (n, 3)
        Coordinates of the body's nodes (the scalar degrees of freedom of the basis), m.
    cells : ndarray (n_elements, nodes_per_element)
        Local node indices of each element (scikit-fem's local DOF order).
    boundary : ndarray (n_facets, k)
        Local node indices of each boundary facet.  2D: the edge's two end nodes, then the
        mid-side node for quadratic elements.  3D: the face's corners, then its mid-edge nodes
        and its centre node for quadratic elements (scikit-fem's order).
    boundary_facets : ndarray (n_facets,)
        Indices of those facets among the mesh facets (scikit-fem numbering).
    """

    name: str
    mesh: object
    element: str
    material: Material
    points: np.ndarray
    cells: np.ndarray
    boundary: np.ndarray
    boundary_facets: np.ndarray
    kind: str = field(default="continuum", init=False)

    @classmethod
    def from_mesh(cls, name: str, mesh, element: str, material: Material) -> Body:
        """Build a body from a scikit-fem mesh (``MeshTri``/``MeshQuad``, ``MeshTet``/``MeshHex``
        or their quadratic variants).  Named boundaries of the mesh (``mesh.boundaries``) can be
        selected by name (:meth:`stepcontact.model.Model.select` with ``boundary="name"``)."""
        if element not in ELEMENT_KINDS + SOLID_KINDS:
            raise ModelError(f"body '{name}'", f"unknown element '{element}', use "
                             f"{ELEMENT_KINDS + SOLID_KINDS}")
        material.check(f"body '{name}'.material")
        pts, cells, bnd, bfac = body_arrays(name, mesh, element)
        return cls(name, mesh, element, material, pts, cells, bnd, bfac)

    @property
    def n_nodes(self) -> int:
        return len(self.points)

    @property
    def dim(self) -> int:
        """2 for a plane body, 3 for a solid."""
        return int(self.points.shape[1])

    @property
    def boundary_names(self) -> tuple[str, ...]:
        """The named boundaries of the body's mesh (``mesh.boundaries``), e.g. those of
        :func:`stepcontact.model.mesh.box`: left, right, front, back, bottom, top."""
        return tuple(getattr(self.mesh, "boundaries", None) or {})

    def boundary_rows(self, name: str) -> np.ndarray:
        """Rows of :attr:`boundary` (the body's boundary facets) of the named boundary
        ``name``; ModelError naming the body and the boundary when the mesh has no such
        boundary or it holds facets inside the body."""
        named = getattr(self.mesh, "boundaries", None) or {}
        item = f"body '{self.name}' boundary '{name}'"
        if name not in named:
            known = ", ".join(repr(k) for k in named) or "none"
            hint = ""
            if not named and type(self.mesh).__name__.endswith("2"):
                # skfem.io.meshio.from_meshio drops the boundaries of second-order meshes
                hint = ("; a second-order mesh converted by scikit-fem's from_meshio loses its "
                        "named boundaries: read the .msh with stepcontact.read_msh")
            raise ModelError(item, f"no such boundary (known: {known}){hint}")
        facets = np.asarray(named[name], dtype=np.int64)
        pos = np.full(int(max(facets.max(initial=-1), self.boundary_facets.max(initial=-1))) + 1,
                      -1, dtype=np.int64)
        pos[self.boundary_facets] = np.arange(len(self.boundary_facets))
        rows = pos[facets]
        if np.any(rows < 0):
            raise ModelError(item, f"facet {int(facets[rows < 0][0])} is not on the body's "
                                   "boundary (an inner facet)")
        return rows


#: the DOFs of a node of a space frame: translations x, y, z and rotations rx, ry, rz about
#: the global axes
DOF_NAMES_FRAME_3D: tuple[str, ...] = ("x", "y", "z", "rx", "ry", "rz")
#: a bar and its orientation vector closer to parallel than this (the sine of their angle) is
#: refused: the bar's local axes would be undefined or at the mercy of round-off
ORIENTATION_SINE_MIN = 1e-6


@dataclass(frozen=True, eq=False)
class Frame:
    """A group of Euler–Bernoulli frame elements: a plane frame (2D points, 3 DOFs per node:
    ux, uy, rz) or a space frame (3D points, 6 DOFs per node: ux, uy, uz, rx, ry, rz).

    The dimension is data: it follows from the points, (n, 2) or (n, 3).  A space frame's bar
    has the local axes x' along it (node 0 to node 1), y' the part of ``orientation`` normal to
    x' and z' = x' × y'; ``Iz`` is the second moment about z' (bending in the x'–y' plane),
    ``Iy`` about y' (bending in the x'–z' plane) and ``J`` the torsion constant (St Venant),
    with the shear modulus ``G`` (or ``nu``: G = E / (2 (1 + ν))).  ``orientation`` None: the
    global z (up) for a bar not along z, so that y' is vertical and Iz the strong axis of a
    beam; the global x for a bar along z (a column).

    Attributes
    ----------
    name : str
    points : ndarray (n, 2) or (n, 3)
        Node coordinates, m.
    cells : ndarray (n_elements, 2)
        Local node indices of each bar.
    E : float
        Young's modulus, Pa.
    A : float
        Cross-section area, m².
    I : float or None
        Second moment of area, m⁴ (a plane frame; a space frame: the default of Iy and Iz).
    density : float
        kg/m³.
    Iy, Iz : float or None
        Space frames: second moments about the local y' and z' axes, m⁴ (default ``I``).
    J : float or None
        Space frames: torsion constant, m⁴.
    G : float or None
        Space frames: shear modulus, Pa (or give ``nu``).
    nu : float or None
        Space frames: Poisson's ratio, for G = E / (2 (1 + ν)).
    orientation : (3,) or (n_elements, 3) array or None
        Space frames: a vector in each bar's local x'–y' plane (not along the bar).
    """

    name: str
    points: np.ndarray
    cells: np.ndarray
    E: float
    A: float
    I: float | None = None
    density: float = 0.0
    Iy: float | None = None
    Iz: float | None = None
    J: float | None = None
    G: float | None = None
    nu: float | None = None
    orientation: tuple | np.ndarray | None = None
    kind: str = field(default="frame", init=False)

    def __post_init__(self):
        raw = np.asarray(self.points, dtype=float)
        dim = 3 if raw.ndim == 2 and raw.shape[1] == 3 else 2
        pts = raw.reshape(-1, dim)
        cells = np.asarray(self.cells, dtype=np.int64).reshape(-1, 2)
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "cells", cells)
        item = f"frame '{self.name}'"
        if dim == 2:
            for key in ("Iy", "Iz", "J", "G", "nu", "orientation"):
                if getattr(self, key) is not None:
                    raise ModelError(f"{item}.{key}", "applies to space frames (3D points) "
                                     "only; a plane frame takes E, A and I")
            self._check_positive(("E", "A", "I"))
        else:
            self._space_section(item)
        if (text := modulus_problem(self.E)) is not None:
            raise ModelError(f"{item}.E", text)
        if not np.all(np.isfinite(pts)):
            raise ModelError(f"{item}.points", "contains NaN or inf")
        if cells.size and (cells.min() < 0 or cells.max() >= len(pts)):
            raise ModelError(f"{item}.cells", "refers to a node that does not exist")
        lengths = np.linalg.norm(pts[cells[:, 1]] - pts[cells[:, 0]], axis=1)
        bad = np.flatnonzero(lengths <= 1e-12 * max(1.0, np.ptp(pts) if pts.size else 1.0))
        if bad.size:
            raise ModelError(f"{item} element {bad[0]}", "has zero length")
        unused = np.setdiff1d(np.arange(len(pts)), cells.ravel())
        if unused.size:
            raise ModelError(f"{item} node {unused[0]}", "belongs to no element")
        if dim == 3:
            self.local_axes()  # an orientation along a bar is refused here
        plausible.warn("E", self.E, f"{item}.E", stacklevel=4)
        plausible.warn("density", self.density, f"{item}.density", stacklevel=4)

    def _check_positive(self, keys) -> None:
        for key in keys:
            v = getattr(self, key)
            if v is None:
                raise ModelError(f"frame '{self.name}'.{key}", "is needed (a positive number)")
            if not np.isfinite(v) or v <= 0:
                raise ModelError(f"frame '{self.name}'.{key}",
                                 f"must be positive and finite, got {v}")

    def _space_section(self, item: str) -> None:
        """A space frame's section: Iy, Iz (default I), J, and G from G or ν."""
        for key in ("Iy", "Iz"):
            if getattr(self, key) is None and self.I is not None:
                object.__setattr__(self, key, self.I)
        self._check_positive(("E", "A", "Iy", "Iz", "J"))
        if self.I is not None:
            self._check_positive(("I",))
        if self.G is not None and self.nu is not None:
            raise ModelError(f"{item}.G", "is given together with nu: give the shear modulus "
                             "G or Poisson's ratio nu, not both")
        if self.G is None:
            if self.nu is None:
                raise ModelError(f"{item}.G", "is needed for the torsion of a space frame: give "
                                 "the shear modulus G (Pa) or Poisson's ratio nu")
            if not np.isfinite(self.nu) or not NU_RANGE[0] < self.nu < NU_RANGE[1]:
                raise ModelError(f"{item}.nu", f"Poisson's ratio nu must lie in "
                                 f"({NU_RANGE[0]:g}, {NU_RANGE[1]:g}), got {self.nu}")
        else:
            self._check_positive(("G",))
        if self.orientation is not None:
            v = np.asarray(self.orientation, dtype=float)
            if v.shape not in ((3,), (len(self.cells), 3)) or not np.all(np.isfinite(v)):
                raise ModelError(f"{item}.orientation", "must be a finite vector (vx, vy, vz) "
                                 f"or one per element ({len(self.cells)} × 3), got "
                                 f"shape {v.shape}")
            object.__setattr__(self, "orientation", v)

    @property
    def n_nodes(self) -> int:
        return len(self.points)

    @property
    def shear_modulus(self) -> float | None:
        """A space frame's shear modulus, Pa: ``G``, or E / (2 (1 + ν)) from ``nu`` (None for
        a plane frame)."""
        if self.G is not None:
            return float(self.G)
        return None if self.nu is None else float(self.E) / (2.0 * (1.0 + float(self.nu)))

    @property
    def dim(self) -> int:
        """2 for a plane frame, 3 for a space frame (from the points)."""
        return int(self.points.shape[1])

    @property
    def dof_names(self) -> tuple[str, ...]:
        """The DOFs of a node: x, y, rz (plane frame) or x, y, z, rx, ry, rz (space frame)."""
        return DOF_NAMES if self.dim == 2 else DOF_NAMES_FRAME_3D

    def local_axes(self) -> np.ndarray:
        """(n_elements, 3, 3) the rows x', y', z' of every bar's local axes (unit vectors):
        x' from node 0 to node 1, y' the part of the orientation vector normal to x',
        z' = x' × y' (see the class).  A plane frame: x' in the plane, y' = ẑ × x', z' = ẑ.
        ModelError naming the element when the orientation is (nearly) along the bar."""
        d = self.points[self.cells[:, 1]] - self.points[self.cells[:, 0]]
        if self.dim == 2:
            d = np.column_stack([d, np.zeros(len(d))])
        ex = d / np.linalg.norm(d, axis=1)[:, None]
        if self.dim == 2:
            v = np.broadcast_to([0.0, 0.0, 1.0], ex.shape)
            return np.stack([ex, np.cross(v, ex), v], axis=1)
        if self.orientation is None:
            along_z = np.linalg.norm(np.cross(ex, [0.0, 0.0, 1.0]), axis=1) < ORIENTATION_SINE_MIN
            v = np.where(along_z[:, None], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0])
        else:
            v = np.broadcast_to(np.asarray(self.orientation, float), ex.shape)
        normal = v - np.einsum("ij,ij->i", v, ex)[:, None] * ex
        size = np.linalg.norm(normal, axis=1)
        bad = np.flatnonzero(size <= ORIENTATION_SINE_MIN * np.linalg.norm(v, axis=1))
        if bad.size:
            raise ModelError(f"frame '{self.name}' element {int(bad[0])}", "lies along its "
                             f"orientation vector {tuple(float(c) for c in v[bad[0]])}: give a "
                             "vector in the bar's local x'–y' plane, not along the bar")
        ey = normal / size[:, None]
        return np.stack([ex, ey, np.cross(ex, ey)], axis=1)

    @classmethod
    def line(
        cls, name: str, start, end, n: int, *, E: float, A: float, I: float | None = None,
        density: float = 0.0, **section
    ) -> Frame:
        """A straight frame from ``start`` to ``end`` divided into ``n`` elements; 3D points
        make a space frame (``section``: Iy, Iz, J, G or nu, orientation)."""
        s = np.linspace(0.0, 1.0, n + 1)[:, None]
        pts = (1 - s) * np.asarray(start, float) + s * np.asarray(end, float)
        cells = np.column_stack([np.arange(n), np.arange(1, n + 1)])
        return cls(name, pts, cells, E, A, I, density, **section)
