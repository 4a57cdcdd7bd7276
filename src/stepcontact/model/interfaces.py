"""Contact interfaces (a pair of boundary curves joined by CFEs) and compliant contact layers
(article eq. (11))."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal, get_args

import numpy as np

from stepcontact.enums import MAX_FACETS
from stepcontact.errors import ModelError
from stepcontact.model import plausible
from stepcontact.model.bodies import NU_RANGE
from stepcontact.model.bond import Bond
from stepcontact.model.obstacle import RigidObstacle
from stepcontact.model.supports import NodeSet


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
    facets : int or None
        3D only: the number k of facets of the faceted Coulomb cone
        (:class:`~stepcontact.contact.faceted.FacetedCoulombLaw`, 3 … 128; None: 8).  The
        polygon is inscribed in the disc |Q| ≤ f p: its limit errs by at most 1 − cos(π/k).
        All interfaces of a model share one k.
    facet_angle : float
        3D only: the direction θ₀ of the polygon's vertex 0 from t₁ towards t₂, rad.
    axis : (3,) or None
        3D only: the direction of each CFE's first tangent t₁ (projected on the plane ⊥ n);
        None: the global axis along which n has its smallest component (+x for a horizontal
        joint, :func:`~stepcontact.contact.surface3d.local_basis`).  t₂ = n × t₁.

    In 3D (interfaces between 3D bodies, or a 3D body on a
    :class:`~stepcontact.model.obstacle.RigidPlane`) ``plus`` and ``minus`` are node sets of
    faces (triangles or quadrilaterals), ``"node-to-segment"`` ties each S+ node to its
    closest point on an S− facet (node-to-facet), mortar is segment-based on the facets
    (:mod:`stepcontact.contact.interface3d`), and ``gap`` as a function is g(x, y, z).
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
    facets: int | None = None
    facet_angle: float = 0.0
    axis: tuple[float, float, float] | None = None

    @staticmethod
    def normal_problem(normal) -> str | None:
        """Why a given normal is refused (None: it is not, or none is given); a 3-vector is a
        normal of a 3D interface."""
        if normal is None:
            return None
        n = np.asarray(normal, float)
        if n.shape not in ((2,), (3,)) or not np.all(np.isfinite(n)) or np.linalg.norm(n) == 0:
            return "must be a non-zero 2-vector (3-vector in 3D)"
        return None

    def facet_count(self) -> int:
        """k, the number of facets of the faceted Coulomb cone in 3D (8 when not given)."""
        return 8 if self.facets is None else int(self.facets)

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
        self._check_facet_options(item)
        if self.pairs and len(self.plus) != len(self.minus):  # (never an obstacle here)
            raise ModelError(
                f"{item}.pairs",
                f"plus has {len(self.plus)} nodes and minus {len(self.minus)}: node pairs need "
                "the same number on both sides",
            )

    def _check_facet_options(self, item: str) -> None:
        """``facets`` an integer 3 … MAX_FACETS, ``facet_angle`` finite, ``axis`` a non-zero
        finite 3-vector."""
        k = self.facets
        if k is not None and (isinstance(k, bool) or not isinstance(k, int | np.integer)
                              or not 3 <= k <= MAX_FACETS):
            raise ModelError(f"{item}.facets", f"a faceted Coulomb cone has 3 … {MAX_FACETS} "
                             f"facets (an integer), got {k!r}")
        if not np.isfinite(self.facet_angle):
            raise ModelError(f"{item}.facet_angle", f"must be finite (rad), got "
                             f"{self.facet_angle!r}")
        if self.axis is not None:
            a = np.asarray(self.axis, float)
            if a.shape != (3,) or not np.all(np.isfinite(a)) or not np.any(a):
                raise ModelError(f"{item}.axis", f"must be a non-zero 3-vector (the direction "
                                 f"of t1), got {self.axis!r}")
