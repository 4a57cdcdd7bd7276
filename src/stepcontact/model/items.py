"""The model: bodies, frames, springs, supports, loads, contact interfaces and load program.

Everything here is a plain, immutable dataclass.  Changing a model returns a new one
(:meth:`Model.add`, :func:`dataclasses.replace`).  Node sets are stored relative to a body
(body name + local node indices), so they stay valid when other bodies are added.

Units are SI throughout: metres, newtons, pascals, kilograms.  In 2D a force "per node" is a
force on the whole thickness of the model (N); pressures are in Pa and are multiplied by the
thickness when integrated.

Data flows one way: model -> :mod:`stepcontact.fem` -> :mod:`stepcontact.solver` ->
:mod:`stepcontact.results` -> post-processing.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Literal, get_args

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model import plausible
from stepcontact.model.bond import Bond
from stepcontact.model.elements import body_arrays
from stepcontact.model.obstacle import ObstacleMotion, RigidObstacle
from stepcontact.model.timefunction import MASS_KINDS, MAX_STEPS, check_interval, check_newmark

# The allowed kinds and ranges below are the one source of these rules: the dataclasses check
# them, and the model file's schema (:mod:`stepcontact.io.modelfile.schema`) takes its
# literals and bounds from them.
PlaneKind = Literal["strain", "stress"]
PLANE_KINDS: tuple[str, ...] = get_args(PlaneKind)
ElementKind = Literal["tri3", "tri6", "quad4", "quad8", "quad9"]
ELEMENT_KINDS: tuple[str, ...] = get_args(ElementKind)
DofName = Literal["x", "y", "rz"]
DOF_NAMES: tuple[str, ...] = get_args(DofName)


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

    Use :func:`stepcontact.model.mesh.rectangle` or :meth:`Body.from_mesh` to make one.

    Attributes
    ----------
    name : str
        Unique name of the body.
    mesh : skfem.Mesh
        The scikit-fem mesh (its geometry; for quadratic elements the mid-side nodes are the
        degrees of freedom of the quadratic basis).
    element : str
        ``"tri3"``, ``"tri6"``, ``"quad4"``, ``"quad8"`` or ``"quad9"``.
    material : Material
    points : ndarray (n, 2)
        Coordinates of the body's nodes (the scalar degrees of freedom of the basis), m.
    cells : ndarray (n_elements, nodes_per_element)
        Local node indices of each element (scikit-fem's local DOF order).
    boundary : ndarray (n_facets, 2 or 3)
        Local node indices of each boundary edge: two end nodes, then the mid-side node for
        quadratic elements.
    boundary_facets : ndarray (n_facets,)
        Indices of those edges among the mesh facets (scikit-fem numbering).
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
        """Build a body from a scikit-fem mesh (``MeshTri``/``MeshQuad`` or their P2 variants)."""
        if element not in ELEMENT_KINDS:
            raise ModelError(f"body '{name}'", f"unknown element '{element}', use {ELEMENT_KINDS}")
        material.check(f"body '{name}'.material")
        pts, cells, bnd, bfac = body_arrays(name, mesh, element)
        return cls(name, mesh, element, material, pts, cells, bnd, bfac)

    @property
    def n_nodes(self) -> int:
        return len(self.points)


@dataclass(frozen=True, eq=False)
class Frame:
    """A group of 2D Euler–Bernoulli frame elements (3 DOFs per node: ux, uy, rz).

    Attributes
    ----------
    name : str
    points : ndarray (n, 2)
        Node coordinates, m.
    cells : ndarray (n_elements, 2)
        Local node indices of each bar.
    E : float
        Young's modulus, Pa.
    A : float
        Cross-section area, m².
    I : float
        Second moment of area, m⁴.
    density : float
        kg/m³.
    """

    name: str
    points: np.ndarray
    cells: np.ndarray
    E: float
    A: float
    I: float
    density: float = 0.0
    kind: str = field(default="frame", init=False)

    def __post_init__(self):
        pts = np.asarray(self.points, dtype=float).reshape(-1, 2)
        cells = np.asarray(self.cells, dtype=np.int64).reshape(-1, 2)
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "cells", cells)
        item = f"frame '{self.name}'"
        for key in ("E", "A", "I"):
            v = getattr(self, key)
            if not np.isfinite(v) or v <= 0:
                raise ModelError(f"{item}.{key}", f"must be positive and finite, got {v}")
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
        plausible.warn("E", self.E, f"{item}.E", stacklevel=4)
        plausible.warn("density", self.density, f"{item}.density", stacklevel=4)

    @property
    def n_nodes(self) -> int:
        return len(self.points)

    @classmethod
    def line(
        cls, name: str, start, end, n: int, *, E: float, A: float, I: float, density: float = 0.0
    ) -> Frame:
        """A straight frame from ``start`` to ``end`` divided into ``n`` elements."""
        s = np.linspace(0.0, 1.0, n + 1)[:, None]
        pts = (1 - s) * np.asarray(start, float) + s * np.asarray(end, float)
        cells = np.column_stack([np.arange(n), np.arange(1, n + 1)])
        return cls(name, pts, cells, E, A, I, density)


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
def _parse_dofs(dofs: str | Sequence[str], item: str) -> tuple[str, ...]:
    """"xy", "x", "rz", "xyrz" or a sequence of names -> tuple of DOF names."""
    if isinstance(dofs, str):
        text = dofs.replace(",", "").replace(" ", "")
        rz = "rz" in text
        text = text.replace("rz", "")
        bad = set(text) - {"x", "y"}
        if bad:
            raise ModelError(item, f"unknown degree of freedom '{sorted(bad)[0]}', use "
                             f"{', '.join(DOF_NAMES)}")
        dofs = [d for d in ("x", "y") if d in text] + (["rz"] if rz else [])
    out = tuple(dict.fromkeys(dofs))
    for d in out:
        if d not in DOF_NAMES:
            raise ModelError(item, f"unknown degree of freedom '{d}', use {', '.join(DOF_NAMES)}")
    return out


@dataclass(frozen=True, eq=False)
class Support:
    """Fixed degrees of freedom (``dofs`` any of ``"x"``, ``"y"``, ``"rz"``) of a node set."""

    name: str
    nodes: NodeSet
    dofs: tuple[str, ...] = ("x", "y")

    def __post_init__(self):
        object.__setattr__(self, "dofs", _parse_dofs(self.dofs, f"support '{self.name}'.dofs"))


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
    direction: tuple[float, float] | None = None
    damping: float = 0.0

    def __post_init__(self):
        item = f"spring '{self.name}'"
        for key in ("kx", "ky", "k", "damping"):
            v = getattr(self, key)
            if not np.isfinite(v) or v < 0:
                raise ModelError(f"{item}.{key}", f"must be >= 0, got {v}")
        if self.direction is not None:
            d = np.asarray(self.direction, dtype=float)
            if d.shape != (2,) or not np.all(np.isfinite(d)):
                raise ModelError(f"{item}.direction",
                                 f"must be a finite vector (dx, dy), got {self.direction}")
            norm = float(np.hypot(d[0], d[1]))
            if norm == 0.0:
                raise ModelError(f"{item}.direction", "is zero: give the spring's axis (dx, dy)")
            object.__setattr__(self, "direction", (float(d[0] / norm), float(d[1] / norm)))
        elif self.k > 0:
            raise ModelError(f"{item}.direction",
                             f"is needed with k = {self.k:g} N/m (the axis of the spring)")

    def stiffness_matrix(self) -> np.ndarray:
        """The 2 × 2 stiffness k_x e_x⊗e_x + k_y e_y⊗e_y + k d⊗d of each spring, N/m."""
        K = np.diag([float(self.kx), float(self.ky)])
        if self.direction is not None and self.k:
            d = np.asarray(self.direction)
            K += self.k * np.outer(d, d)
        return K

    def damping_matrix(self) -> np.ndarray:
        """The 2 × 2 dashpot matrix of each spring, N·s/m: c d⊗d along ``direction``, c I
        (x and y alike) without one."""
        if self.direction is None:
            return float(self.damping) * np.eye(2)
        return float(self.damping) * np.outer(self.direction, self.direction)


# --------------------------------------------------------------------------------------------
# loads
# --------------------------------------------------------------------------------------------
PressureSpec = float | tuple[float, float] | Callable[[np.ndarray, np.ndarray], np.ndarray] | None


@dataclass(frozen=True, eq=False)
class NodalLoad:
    """The same force on **every** node of a node set: fx, fy in N, mz in N·m (frames only).

    A set of n nodes receives n × (fx, fy) in total.  For a *total* force spread along the
    edges of a set (consistent nodal forces of a uniform traction) use :class:`EdgeForce`.
    """

    nodes: NodeSet
    fx: float = 0.0
    fy: float = 0.0
    mz: float = 0.0


@dataclass(frozen=True, eq=False)
class EdgeLoad:
    """Tractions on the boundary edges of a body whose nodes all lie in ``nodes``, Pa.

    The traction on an edge with outward unit normal n is

        q = −p_n n + p_t t + (q_x, q_y),        t = (n_y, −n_x),

    integrated over the thickness into consistent nodal forces.

    * ``normal`` p_n: pressure, positive pushing *into* the body (against n).
    * ``tangential`` p_t: shear along the edge tangent t = (n_y, −n_x), the outward normal
      turned **clockwise** — the same rule as the CFE tangent (n from S− to S+, see
      :mod:`stepcontact.contact.geometry`).  On a top face (n = +y) t = +x, on a bottom face
      (n = −y) t = −x, on a right face (n = +x) t = −y, on a left face (n = −x) t = +y.
      For a joint, the tangent of the top edge of S− is the CFE tangent.
    * ``traction`` (q_x, q_y): a traction given in global x, y components, whatever the edge's
      orientation.

    ``normal``, ``tangential`` and each component of ``traction`` can be a constant, a pair
    ``(p_start, p_end)`` varying linearly along the node set (from its first to its last node,
    by arc length), or a function ``p(x, y)`` of position (vectorised, arrays in m, returns
    Pa).

    Example
    -------
    >>> top = m.select("block", y=2.0)                         # doctest: +SKIP
    >>> EdgeLoad(top, tangential=1e3)          # 1 kPa along +x on a top face  # doctest: +SKIP
    >>> EdgeLoad(top, traction=(1e3, 0.0))     # the same load                 # doctest: +SKIP
    """

    nodes: NodeSet
    normal: PressureSpec = None
    tangential: PressureSpec = None
    traction: tuple[PressureSpec, PressureSpec] | None = None

    def __post_init__(self):
        if self.traction is not None:
            if not isinstance(self.traction, tuple | list | np.ndarray) or len(self.traction) != 2:
                raise ModelError("edge load.traction",
                                 "give the two components (tx, ty), Pa (numbers, [start, end] "
                                 "pairs or functions of (x, y))")
            object.__setattr__(self, "traction", tuple(self.traction))


@dataclass(frozen=True, eq=False)
class EdgeForce:
    """A **total** force (fx, fy) in N spread along the boundary edges of a body whose nodes
    all lie in ``nodes``: the uniform traction (fx, fy) / (L · thickness) over the edges'
    total length L, turned into consistent nodal forces.  The nodal forces sum exactly to
    (fx, fy) whatever the mesh; compare :class:`NodalLoad`, which puts its value on every node.

    Example
    -------
    >>> EdgeForce(m.select("block", x=0.0), fx=1e4)   # 10 kN in all: left face  # doctest: +SKIP
    """

    nodes: NodeSet
    fx: float = 0.0
    fy: float = 0.0


@dataclass(frozen=True, eq=False)
class BodyForce:
    """Self-weight: density × acceleration ``g`` (m/s²) on the named bodies (all when empty)."""

    g: tuple[float, float] = (0.0, -9.81)
    bodies: tuple[str, ...] = ()

    def __post_init__(self):
        g = np.asarray(self.g, dtype=float)
        if g.shape != (2,) or not np.all(np.isfinite(g)):
            raise ModelError("body force.g", f"must be a finite vector (gx, gy), m/s², got "
                             f"{self.g!r}")
        plausible.warn("gravity", float(np.hypot(*g)), "body force |g|", stacklevel=4)


@dataclass(frozen=True, eq=False)
class PrescribedDisplacement:
    """Prescribed displacement ``value`` (m, or rad for rz) of ``dof`` of each node of a set.

    Scaled by the load factor λ_P of its pattern, like any load: the DOFs are at
    u = λ_P · ``value``.  They are fixed **from the start of the program**, not only from the
    first segment of their pattern: before it (λ_P = 0) they are held at zero and act as a
    support (their reaction is ``res.reaction(pattern, dof)``).  To leave a DOF free until
    later, give it no prescribed displacement and load it by forces instead.
    """

    nodes: NodeSet
    dof: str
    value: float


Load = NodalLoad | EdgeLoad | EdgeForce | BodyForce | PrescribedDisplacement | ObstacleMotion


@dataclass(frozen=True, eq=False)
class LoadPattern:
    """A named set of loads applied together with one load factor λ."""

    name: str
    loads: tuple = ()

    def __post_init__(self):
        object.__setattr__(self, "loads", tuple(self.loads))


@dataclass(frozen=True)
class Segment:
    """One segment of the load program: ``pattern``'s factor goes from ``start`` to ``end``.

    ``start`` None means "from where the pattern stands" (0 if never applied).  A segment whose
    ``start`` differs from the pattern's current factor does not chain and is an error.

    Non-proportional loading: with ``rates`` = {pattern: rate, …} several patterns move at once
    and ``pattern`` is the segment's own name (a label, not a pattern): its parameter goes from
    ``start`` to ``end`` and each pattern's factor changes by ``rate`` per unit of it.  Events
    and multipliers of the segment are given in that parameter.

    Example
    -------
    >>> Segment("flood", 2.0, rates={"water": 1.0, "uplift": 0.6})  # doctest: +SKIP
    """

    pattern: str
    end: float
    start: float | None = None
    rates: tuple[tuple[str, float], ...] | None = None

    def __post_init__(self):
        if self.rates is not None:
            items = self.rates.items() if isinstance(self.rates, dict) else self.rates
            object.__setattr__(self, "rates", tuple((str(k), float(v)) for k, v in items))


# --------------------------------------------------------------------------------------------
# contact interfaces
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ContactLayer:
    """Compliant contact layer, article eq. (11).

    Either stiffnesses per unit area ``kn``, ``kt`` (Pa/m) are given directly, or the layer's
    thickness ``thickness`` (ζ_n⁰, m), modulus ``E`` (E_c, Pa) and Poisson ratio ``nu`` (μ_c),
    giving ρ_n = (1-μ_c²) ζ_n⁰ / E_c, ρ_τ = 2(1+μ_c) ζ_n⁰ / E_c and C = A_k / ρ.

    ``damping`` (Pa·s/m, ≥ 0) is the layer's normal damping per unit area: in a dynamic run
    the layer is a Kelvin–Voigt one, N = −(C_n u_n + c_n u̇_n) while closed, that opens when
    that force reaches zero and then relaxes (:mod:`stepcontact.solver.dynamic`).  Static runs
    ignore it.
    """

    kn: float | None = None
    kt: float | None = None
    thickness: float | None = None
    E: float | None = None
    nu: float = 0.0
    damping: float = 0.0

    @staticmethod
    def form_problem(kn, kt, thickness, E, nu) -> str | None:
        """Why the given parameters (None: not given) are not one form of a layer, ``{kn, kt}``
        or ``{thickness, E[, nu]}`` (None when they are)."""
        direct = kn is not None or kt is not None
        physical = any(v is not None for v in (thickness, E, nu))
        if direct and physical:
            return "give either {kn, kt} or {thickness, E, nu}, not both"
        if direct and (kn is None or kt is None):
            return "give both kn and kt"
        if not direct and (thickness is None or E is None):
            return "give {kn, kt} or {thickness, E, nu}"
        return None

    def stiffness_per_area(self, item: str) -> tuple[float, float]:
        """(C_n/A, C_τ/A) in Pa/m."""
        direct = self.kn is not None or self.kt is not None
        text = self.form_problem(self.kn, self.kt, None if direct else self.thickness,
                                 None if direct else self.E, None)
        if text is not None:
            raise ModelError(item, text)
        if direct:
            kn, kt = self.kn, self.kt
        else:
            if self.thickness <= 0 or self.E <= 0 or not NU_RANGE[0] < self.nu < NU_RANGE[1]:
                raise ModelError(item, f"layer thickness and E must be > 0, nu in "
                                 f"({NU_RANGE[0]:g}, {NU_RANGE[1]:g})")
            kn = self.E / ((1 - self.nu**2) * self.thickness)
            kt = self.E / (2 * (1 + self.nu) * self.thickness)
        for key, v in (("kn", kn), ("kt", kt)):
            if not np.isfinite(v) or v <= 0:
                raise ModelError(f"{item}.{key}", f"stiffness must be positive, got {v}")
        if not (np.isfinite(self.damping) and self.damping >= 0):
            raise ModelError(f"{item}.damping", f"must be ≥ 0 and finite (Pa·s/m), got "
                             f"{self.damping}")
        return float(kn), float(kt)


#: How the CFEs of an interface join S+ to S−: see :class:`Interface`.
CfeKind = Literal["auto", "mortar", "node-to-segment", "node-to-node"]
CFE_KINDS: tuple[str, ...] = get_args(CfeKind)


@dataclass(frozen=True, eq=False)
class Interface:
    """A pair of boundary curves joined by frame-type contact finite elements (CFEs).

    One CFE is made at every node of ``plus`` (S+) (mortar: of the coarser face).  How it joins
    S− (``cfe``):

    * ``"node-to-node"``: to the S− node at the same place (matching meshes);
    * ``"mortar"`` (segment-to-segment): its mutual displacements are the gap and slip
      weighted by the shape function of a node of the coarser face (S+ or S−) and integrated
      over the overlap of the S+ and S− edges; its forces act on both sides through the same
      weights.  A uniform contact pressure is reproduced exactly on meshes that do not match
      (the contact patch test), and swapping S+ and S− changes nothing but the face on which
      the CFEs' points are reported (:func:`stepcontact.contact.geometry._mortar_elements`);
    * ``"node-to-segment"`` (the article's CFE): to the closest point of S−, interpolated from
      that edge's nodes; on meshes that do not match the pressure errs by a few per cent;
    * ``"auto"`` (default): node-to-node where the meshes match, mortar otherwise.

    Parameters
    ----------
    name : str
    plus, minus : NodeSet
        Nodes on S+ and S− (any order; the curve order is rebuilt from the mesh edges).
        ``minus`` may be a :class:`~stepcontact.model.obstacle.RigidObstacle`: contact
        against a fixed (or rigidly moving) line or polyline, no body meshed for it.  Every
        S+ node then gets one CFE to its closest point on the obstacle, with the normal of
        that segment (at a vertex between two segments where the ends coincide: the mean of
        their normals); S+ nodes beyond the ends of the polyline get none.
    friction : float
        Coulomb friction coefficient f_k >= 0.
    gap : float or callable
        Initial gap (m, >= 0); a function g(x, y) of the S+ point is allowed.  When None the
        geometric distance between the two ends along the normal is used.
    normal : (2,) or None
        Unit normal pointing from S− towards S+.  When None the outward normal of S− at the
        projected point is used (needed when the ends of a CFE coincide).
    layer : ContactLayer or None
        Compliant layer (eq. (11)); None means rigid contact enforced exactly.
    pairs : bool
        Join ``plus[i]`` to ``minus[i]`` node to node, in the given order, instead of
        projecting S+ on S− (point supports with uplift, nodes that form no curve, bearings).
        The normal is then ``normal`` or, when not given, the direction from the S− node to the
        S+ node (an error if they coincide).
    area : float or None
        Contact area of every CFE, m² (default: tributary length along S+ × thickness; for
        mortar CFEs along the coarser face, the part of it facing the other; for a single
        isolated node, 1 m × thickness).
    cfe : str
        ``"auto"``, ``"mortar"``, ``"node-to-segment"`` or ``"node-to-node"`` (see above).
    bond : Bond or None
        Initial strength of the joint in tension and shear (eq. (12),
        :class:`~stepcontact.model.bond.Bond`): its CFEs start bonded and break into
        unilateral contact with friction (``friction``, or the bond's own).  The joint must be
        closed (zero gap).
    """

    name: str
    plus: NodeSet
    minus: NodeSet | RigidObstacle
    friction: float = 0.0
    gap: float | Callable | None = None
    normal: tuple[float, float] | None = None
    layer: ContactLayer | None = None
    pairs: bool = False
    area: float | None = None
    cfe: str = "auto"
    bond: object = None

    @staticmethod
    def normal_problem(normal) -> str | None:
        """Why a given normal is refused (None: it is not, or none is given)."""
        if normal is None:
            return None
        n = np.asarray(normal, float)
        if n.shape != (2,) or not np.all(np.isfinite(n)) or np.linalg.norm(n) == 0:
            return "must be a non-zero 2-vector"
        return None

    def __post_init__(self):
        item = f"interface '{self.name}'"
        if self.bond is not None:
            if not isinstance(self.bond, Bond):
                raise ModelError(f"{item}.bond", f"must be a Bond, got {type(self.bond).__name__}")
        if self.cfe not in CFE_KINDS:
            raise ModelError(f"{item}.cfe", f"unknown CFE kind '{self.cfe}', use one of "
                                            + ", ".join(repr(k) for k in CFE_KINDS))
        if self.pairs and self.cfe not in ("auto", "node-to-node"):
            raise ModelError(f"{item}.cfe", f"'{self.cfe}' does not apply to node pairs "
                                            "(pairs = true joins nodes node to node)")
        if not np.isfinite(self.friction) or self.friction < 0:
            raise ModelError(f"{item}.friction", f"must be >= 0, got {self.friction}")
        plausible.warn("friction", self.friction, f"{item}.friction", stacklevel=4)
        if isinstance(self.plus, RigidObstacle):
            raise ModelError(f"{item}.plus", f"is obstacle '{self.plus.name}': an obstacle is "
                             "the minus side (S−) of an interface, the body's nodes are plus")
        if isinstance(self.minus, RigidObstacle):
            if self.pairs:
                raise ModelError(f"{item}.pairs", f"does not apply to obstacle "
                                 f"'{self.minus.name}' (it has no nodes to pair)")
            if self.cfe not in ("auto", "node-to-segment"):
                raise ModelError(f"{item}.cfe", f"'{self.cfe}' does not apply to obstacle "
                                 f"'{self.minus.name}': its CFEs join each S+ node to its "
                                 "closest point (use 'auto' or 'node-to-segment')")
        elif self.plus.body == self.minus.body:  # self-contact (a crack): the sets must differ
            shared = np.intersect1d(self.plus.index, self.minus.index)
            if shared.size:
                same = (shared.size == len(self.plus) == len(self.minus))
                sets = (self.plus.label if self.plus.label == self.minus.label else
                        f"{self.plus.label} and {self.minus.label}")
                sides = (f"plus and minus of {item} are the same nodes ({sets} of body "
                         f"'{self.plus.body}')" if same else
                         f"{shared.size} node(s) of body '{self.plus.body}' are on both sides "
                         f"of {item} (e.g. node {int(shared[0])})")
                raise ModelError(item, f"{sides}: a CFE would join a node to itself; give "
                                 "the two faces of the joint as two different node sets")
        if isinstance(self.gap, int | float) and (not np.isfinite(self.gap) or self.gap < 0):
            raise ModelError(f"{item}.gap", f"must be >= 0, got {self.gap}")
        if (text := self.normal_problem(self.normal)) is not None:
            raise ModelError(f"{item}.normal", text)
        if self.area is not None and not (np.isfinite(self.area) and self.area > 0):
            raise ModelError(f"{item}.area", f"must be > 0 m², got {self.area}")
        if self.pairs and len(self.plus) != len(self.minus):  # (never an obstacle here)
            raise ModelError(
                f"{item}.pairs",
                f"plus has {len(self.plus)} nodes and minus {len(self.minus)}: node pairs need "
                "the same number on both sides",
            )


# --------------------------------------------------------------------------------------------
# the model
# --------------------------------------------------------------------------------------------
def _check_stiffness_ratio(bodies: Sequence) -> None:
    """Young's moduli of the bodies and frames at most 1/:data:`E_RATIO_MIN` apart."""
    moduli = []  # (item, label, E)
    for b in bodies:
        if isinstance(b, Frame):
            moduli.append((f"frame '{b.name}'.E", f"frame '{b.name}'", float(b.E)))
        elif isinstance(b, Body):
            moduli.append((f"body '{b.name}'.material", f"body '{b.name}'", float(b.material.E)))
    if len(moduli) < 2:
        return
    soft = min(moduli, key=lambda t: t[2])
    stiff = max(moduli, key=lambda t: t[2])
    if soft[2] < E_RATIO_MIN * stiff[2]:
        raise ModelError(
            soft[0],
            f"Young's modulus E = {soft[2]:g} is {soft[2] / stiff[2]:.1e} times that of "
            f"{stiff[1]} (E = {stiff[2]:g}): moduli more than {1 / E_RATIO_MIN:g} apart cannot "
            "be solved together in double precision; check the values and their units (Pa)",
        )


@dataclass(frozen=True, eq=False)
class DynamicInterval:
    """A dynamic interval after the load program (method.md §4): Newmark time integration
    from the program's last state (:func:`stepcontact.solve_dynamic`); or at the end of a
    construction stage (:class:`~stepcontact.model.Stage` ``dynamics``; on a stage before the
    last, :func:`stepcontact.solve_static` runs it and the static stages go on from its end).

    ``loads``: (pattern name, time function) pairs (:mod:`stepcontact.model.timefunction`);
    ``dt``, ``duration`` in s; ``mass`` "consistent" or "lumped"; ``damping`` the Rayleigh
    coefficients (a₀ in 1/s, a₁ in s); ``restitution`` e of the impacts; ``record_every`` k:
    every k-th step is recorded (events and the end always); ``alpha`` the HHT-α numerical
    damping (0: Newmark's average acceleration); ``max_steps`` the limit of the number of
    time steps (the interval is refused, before any work, when duration / dt exceeds it).

    Checked at once (:func:`~stepcontact.model.timefunction.check_newmark`: dt and duration
    positive, α ∈ :data:`~stepcontact.model.timefunction.HHT_ALPHA_RANGE`, e ∈ [0, 1];
    :func:`~stepcontact.model.timefunction.check_interval`): dt ≤ duration,
    the step count, loads that act inside [0, duration], and at least 10 steps per period of
    a varying load (a harmonic; 5 steps in the duration of a half-sine or triangular pulse or
    of a table that returns to zero)."""

    dt: float
    duration: float
    loads: tuple = ()
    mass: str = "consistent"
    damping: tuple[float, float] = (0.0, 0.0)
    restitution: float = 0.0
    record_every: int = 1
    alpha: float = 0.0
    max_steps: int = MAX_STEPS

    def __post_init__(self):
        # dt, duration, HHT-α and e: the rules solve_dynamic applies to its own arguments
        check_newmark(self.dt, self.duration, alpha=self.alpha, restitution=self.restitution,
                      prefix="dynamics.")
        if self.mass not in MASS_KINDS:
            raise ModelError("dynamics.mass", f"must be {_either(MASS_KINDS)}, got "
                             f"'{self.mass}'")
        if len(tuple(self.damping)) != 2 or not all(np.isfinite(x) and x >= 0
                                                    for x in self.damping):
            raise ModelError("dynamics.damping", f"must be two non-negative Rayleigh "
                             f"coefficients (a0, a1), got {self.damping!r}")
        if int(self.record_every) < 1:
            raise ModelError("dynamics.record_every", "must be at least 1")
        object.__setattr__(self, "loads", tuple((str(n), g) for n, g in self.loads))
        object.__setattr__(self, "damping", tuple(float(x) for x in self.damping))
        check_interval(self.dt, self.duration, dict(self.loads), max_steps=self.max_steps,
                       prefix="dynamics.")


@dataclass(frozen=True, eq=False)
class Model:
    """A 2D structural model.

    Parameters
    ----------
    bodies : tuple of Body or Frame
        Global node numbering follows this order: the nodes of ``bodies[0]`` first, etc.
    plane : "strain" or "stress"
    thickness : float
        Out-of-plane thickness, m (1 m for plane strain per metre run).
    """

    bodies: tuple = ()
    plane: str = "strain"
    thickness: float = 1.0
    supports: tuple[Support, ...] = ()
    ties: tuple[Tie, ...] = ()
    springs: tuple[Spring, ...] = ()
    interfaces: tuple[Interface, ...] = ()
    patterns: tuple[LoadPattern, ...] = ()
    program: tuple[Segment, ...] = ()
    name: str = "model"
    #: a dynamic interval after the program (:class:`DynamicInterval`), or None
    dynamics: DynamicInterval | None = None
    #: construction stages (:class:`~stepcontact.model.stages.Stage`); with stages the
    #: program is theirs and ``program`` must be empty
    stages: tuple = ()

    def __post_init__(self):
        for key in ("bodies", "supports", "ties", "springs", "interfaces", "patterns", "program",
                    "stages"):
            object.__setattr__(self, key, tuple(getattr(self, key)))
        if self.stages and self.program:
            raise ModelError("model.program", "is given together with stages: with stages the "
                             "load program is the stages' own (Stage(program=...))")
        names = [st.name for st in self.stages]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ModelError(f"stage '{sorted(dup)[0]}'", "duplicate stage name")
        last = getattr(self.stages[-1], "dynamics", None) if self.stages else None
        if last is not None and self.dynamics is not last:
            if self.dynamics is not None:
                raise ModelError(f"stage '{self.stages[-1].name}'.dynamics", "is given together "
                                 "with model.dynamics: give the dynamic interval once")
            object.__setattr__(self, "dynamics", last)  # the model's dynamic interval
        if self.plane not in PLANE_KINDS:
            raise ModelError("model.plane", f"must be {_either(PLANE_KINDS)}, got '{self.plane}'")
        if not np.isfinite(self.thickness) or self.thickness <= 0:
            raise ModelError("model.thickness", f"must be positive, got {self.thickness}")
        seen: set[str] = set()
        for b in self.bodies:
            if b.name in seen:
                raise ModelError(f"body '{b.name}'", "duplicate body name")
            seen.add(b.name)
        _check_stiffness_ratio(self.bodies)
        for kind, items in (("pattern", self.patterns), ("interface", self.interfaces)):
            names = [it.name for it in items]
            dup = {n for n in names if names.count(n) > 1}
            if dup:
                raise ModelError(f"{kind} '{sorted(dup)[0]}'", f"duplicate {kind} name")
        obstacles: dict[str, RigidObstacle] = {}
        for itf in self.interfaces:
            obs = itf.minus
            if isinstance(obs, RigidObstacle):
                if obs.name in obstacles and not obstacles[obs.name].same_as(obs):
                    raise ModelError(f"obstacle '{obs.name}'", "two different obstacles have "
                                     f"this name (interface '{itf.name}' and an earlier one)")
                obstacles.setdefault(obs.name, obs)

    # ---- construction -----------------------------------------------------------------------
    def add(self, *items) -> Model:
        """Return a new model with ``items`` added (bodies, frames, supports, ties, springs,
        interfaces, load patterns, segments, stages), dispatched on their type: one of this
        module's, or a type that names its field of the model in ``model_field`` (a
        :class:`~stepcontact.model.Stage`, whose module builds on this one)."""
        groups: dict[str, list] = {
            k: list(getattr(self, k))
            for k in ("bodies", "supports", "ties", "springs", "interfaces", "patterns", "program",
                      "stages")
        }
        kinds = {
            Body: "bodies",
            Frame: "bodies",
            Support: "supports",
            Tie: "ties",
            Spring: "springs",
            Interface: "interfaces",
            LoadPattern: "patterns",
            Segment: "program",
        }
        for it in items:
            key = kinds.get(type(it)) or getattr(type(it), "model_field", None)
            if isinstance(it, RigidObstacle | ObstacleMotion):
                raise ModelError("model.add", f"obstacle '{it.name}' enters a model as the minus "
                                 "side of an Interface (and its motion as a load of a "
                                 "LoadPattern), not by itself")
            if key is None:
                raise ModelError("model.add", f"cannot add an object of type {type(it).__name__}")
            groups[key].append(it)
        return dataclasses.replace(self, **{k: tuple(v) for k, v in groups.items()})

    def replace(self, **changes) -> Model:
        """A copy with fields replaced (``dataclasses.replace``)."""
        return dataclasses.replace(self, **changes)

    def with_friction(self, friction: float, interface: str | None = None) -> Model:
        """A copy with the friction coefficient of ``interface`` (every interface when None)
        set to ``friction``: the stiffness and contact operator are unchanged, so a
        condensation (:func:`stepcontact.condense`) of this model serves the copy too."""
        names = [i.name for i in self.interfaces]
        if interface is not None and interface not in names:
            raise ModelError(f"interface '{interface}'",
                             f"no such interface (known: {', '.join(map(repr, names)) or 'none'})")
        return self.replace(interfaces=tuple(
            dataclasses.replace(i, friction=friction) if interface in (None, i.name) else i
            for i in self.interfaces))

    # ---- lookup -------------------------------------------------------------------------------
    def body(self, name: str) -> Body | Frame:
        for b in self.bodies:
            if b.name == name:
                return b
        known = ", ".join(repr(b.name) for b in self.bodies) or "none"
        raise ModelError(f"body '{name}'", f"no such body (known: {known})")

    def pattern(self, name: str) -> LoadPattern:
        for p in self.patterns:
            if p.name == name:
                return p
        known = ", ".join(repr(p.name) for p in self.patterns) or "none"
        raise ModelError(f"load pattern '{name}'", f"no such pattern (known: {known})")

    @property
    def node_offsets(self) -> dict[str, int]:
        """Global index of local node 0 of every body."""
        out, k = {}, 0
        for b in self.bodies:
            out[b.name] = k
            k += b.n_nodes
        return out

    # ---- rigid obstacles ----------------------------------------------------------------------
    @property
    def obstacles(self) -> tuple[RigidObstacle, ...]:
        """The rigid obstacles of the interfaces (``Interface.minus``), in order of first use."""
        out: dict[str, RigidObstacle] = {}
        for itf in self.interfaces:
            if isinstance(itf.minus, RigidObstacle):
                out.setdefault(itf.minus.name, itf.minus)
        return tuple(out.values())

    def obstacle(self, name: str) -> RigidObstacle:
        for o in self.obstacles:
            if o.name == name:
                return o
        known = ", ".join(repr(o.name) for o in self.obstacles) or "none"
        raise ModelError(f"obstacle '{name}'", "no interface of the model has it as its minus "
                         f"side (obstacles: {known})")

    @property
    def moving_obstacles(self) -> tuple[RigidObstacle, ...]:
        """The obstacles some load pattern moves (:class:`ObstacleMotion`): they have nodes."""
        moved = {ld.name for p in self.patterns for ld in p.loads
                 if isinstance(ld, ObstacleMotion)}
        return tuple(o for o in self.obstacles if o.name in moved)

    @property
    def obstacle_offsets(self) -> dict[str, int]:
        """Global index of the first vertex node of every moving obstacle (after all the
        bodies' nodes; a fixed obstacle has no nodes)."""
        out, k = {}, sum(b.n_nodes for b in self.bodies)
        for o in self.moving_obstacles:
            out[o.name] = k
            k += o.n_nodes
        return out

    @property
    def n_nodes(self) -> int:
        """Number of nodes: those of the bodies and the vertices of moving obstacles."""
        return (sum(b.n_nodes for b in self.bodies)
                + sum(o.n_nodes for o in self.moving_obstacles))

    @property
    def points(self) -> np.ndarray:
        """Coordinates of all nodes, (n_nodes, 2), m, in global numbering (the bodies' nodes,
        then the vertices of the moving obstacles)."""
        parts = [b.points for b in self.bodies] + [o.points for o in self.moving_obstacles]
        if not parts:
            return np.zeros((0, 2))
        return np.vstack(parts)

    def global_nodes(self, ns: NodeSet) -> np.ndarray:
        """Global node indices of a node set (checks that the set is valid)."""
        b = self.body(ns.body)
        if ns.index.size and (ns.index.min() < 0 or ns.index.max() >= b.n_nodes):
            raise ModelError(ns.label, f"refers to nodes that body '{b.name}' does not have")
        return self.node_offsets[b.name] + ns.index

    def select(
        self,
        body: str,
        where: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None,
        *,
        x: float | None = None,
        y: float | None = None,
        boundary: bool = True,
        name: str = "",
        atol: float | None = None,
    ) -> NodeSet:
        """Nodes of ``body`` by a predicate ``where(x, y)`` or by coordinate (``x=``/``y=``).

        With ``boundary=True`` (default) only nodes on the body's boundary are returned,
        which is what loads, supports and interfaces need.  An empty selection is an error.
        """
        b = self.body(body)
        return select_nodes(b, where, x=x, y=y, boundary=boundary, name=name, atol=atol)

    def segments_resolved(self) -> list[tuple[str, float, float]]:
        """The load program as (pattern or segment name, start, end), with starts filled in and
        chaining checked: ``start`` must equal the factor the pattern has reached (a segment
        with rates moves each of its patterns by rate × its span).

        Resolved once per model (it is immutable): a solver hook that gets a result after
        every segment must not cost O(segments) each time, i.e. O(segments²) in all."""
        cached = self.__dict__.get("_program_resolved")
        if cached is not None:
            return list(cached)
        out = []
        for i, seg, now, start in self.program_walk():
            if abs(start - now) > 1e-12 * max(1.0, abs(now)):
                raise ModelError(
                    f"program segment {i} ('{seg.pattern}').start",
                    f"does not chain: pattern '{seg.pattern}' stands at λ = {now:g}, "
                    f"segment starts at {start:g}",
                )
            out.append((seg.pattern, start, float(seg.end)))
        object.__setattr__(self, "_program_resolved", tuple(out))
        return out

    def program_walk(self) -> Iterator[tuple[int, Segment, float, float]]:
        """Each segment of the program (:attr:`effective_program`) as (index, segment, the
        factor its pattern stands at before it, its start: given, or that factor).  The one
        place of the chaining rule (:meth:`segments_resolved` refuses a start that is not where
        the pattern stands; a model file reports it at the entry's path): a pattern stands where
        its last segment ended, a segment with rates moves each of its patterns by rate × its
        span, and the dynamic interval of an earlier stage by g(T).  ModelError for a pattern
        that does not exist, empty or non-finite rates, a label of rates that is a pattern."""
        current: dict[str, float] = {}
        jumps = self.dynamic_jumps()
        for i, seg in enumerate(self.effective_program):
            for name, dg in jumps.get(i, {}).items():  # a dynamic interval moved these
                current[name] = current.get(name, 0.0) + dg
            item = f"program segment {i} ('{seg.pattern}')"
            if seg.rates is None:
                self.pattern(seg.pattern)  # raises with the name
            else:
                if not seg.rates:
                    raise ModelError(f"{item}.rates", "is empty: give {pattern: rate, …}")
                if seg.pattern in {p.name for p in self.patterns}:
                    raise ModelError(item, "a segment with rates is named by a label that is "
                                     "not a load pattern")
                for name, rate in seg.rates:
                    self.pattern(name)
                    if not np.isfinite(rate):
                        raise ModelError(f"{item}.rates['{name}']", "is not finite")
            now = current.get(seg.pattern, 0.0)
            start = now if seg.start is None else float(seg.start)
            if not np.isfinite(seg.end) or not np.isfinite(start):
                raise ModelError(item, "start/end not finite")
            yield i, seg, now, start
            current[seg.pattern] = float(seg.end)
            for name, rate in seg.rates or ():  # the patterns a segment with rates moved
                current[name] = current.get(name, 0.0) + rate * (float(seg.end) - start)

    def dynamic_jumps(self) -> dict[int, dict[str, float]]:
        """The factor changes g(T) of the load patterns of the dynamic intervals of stages
        before the last, keyed by the number of program segments before them (the static
        program goes on from the factors the interval ends at)."""
        out: dict[int, dict[str, float]] = {}
        n = 0
        for st in self.stages[:-1]:
            n += len(st.program)
            dyn = getattr(st, "dynamics", None)
            if dyn is None:
                continue
            jump = out.setdefault(n, {})
            for name, g in dyn.loads:
                item = f"stage '{st.name}'.dynamics.loads['{name}']"
                if name not in {p.name for p in self.patterns}:
                    raise ModelError(item, f"no such load pattern (known: "
                                     f"{', '.join(repr(p.name) for p in self.patterns) or 'none'})")
                if not callable(g):
                    raise ModelError(item, "must be a time function g(t)")
                value = float(g(float(dyn.duration)))
                if not np.isfinite(value):
                    raise ModelError(item, f"is not finite at the interval's end "
                                     f"(t = {dyn.duration:g} s)")
                jump[name] = jump.get(name, 0.0) + value
        return out

    def segment_rates(self) -> list[dict[str, float]]:
        """For every segment of the program, the rate of each pattern it moves per unit of the
        segment's parameter ({pattern: 1} for a single-pattern segment)."""
        return [{seg.pattern: 1.0} if seg.rates is None else dict(seg.rates)
                for seg in self.effective_program]

    @property
    def effective_program(self) -> tuple[Segment, ...]:
        """The load program: ``program``, or with stages their programs in order."""
        if self.stages:
            return tuple(seg for st in self.stages for seg in st.program)
        return self.program


def select_nodes(
    b: Body | Frame,
    where=None,
    *,
    x: float | None = None,
    y: float | None = None,
    boundary: bool = True,
    name: str = "",
    atol: float | None = None,
) -> NodeSet:
    """Node set of one body by predicate or coordinates; see :meth:`Model.select`."""
    pts = b.points
    if atol is None:
        atol = 1e-9 * max(1.0, float(np.ptp(pts, axis=0).max()) if len(pts) else 1.0)
    mask = np.ones(len(pts), dtype=bool)
    if where is not None:
        mask &= np.asarray(where(pts[:, 0], pts[:, 1]), dtype=bool)
    if x is not None:
        mask &= np.abs(pts[:, 0] - x) <= atol
    if y is not None:
        mask &= np.abs(pts[:, 1] - y) <= atol
    interior = 0
    if boundary and isinstance(b, Body):
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
        raise ModelError(label, f"selects no node (the body spans x {lo[0]:g} … {hi[0]:g}, "
                                f"y {lo[1]:g} … {hi[1]:g} m){hint}")
    return NodeSet(b.name, idx, name)


def iter_loads(pattern: LoadPattern) -> Iterable:
    return iter(pattern.loads)
