"""Earthquake loads of a dam: the reservoir's added mass and pseudo-static seismic coefficients.

* :class:`AddedMass` — the hydrodynamic added mass of a reservoir on an upstream face, for the
  dynamic driver (:func:`stepcontact.solve_dynamic`): Westergaard's parabola (Westergaard
  1933) per unit area of the face,

  .. math::  m_a(z) = \\tfrac78 \\, \\rho_w \\sqrt{H z}

  (kg/m²; z the depth below the free surface, m; H the reservoir depth at the face, m),
  acting along the face's normal (Kuo 1982): a wet edge with unit normal n adds
  m_a n nᵀ per unit area — only in x on a vertical face.  Lumped on the face's nodes
  (:mod:`stepcontact.fem.hydrodynamic`).  An item of the model (``model.added_masses``,
  :meth:`~stepcontact.model.Model.add`): the driver adds it to the mass matrix M of eq. (7).
* :class:`SeismicCoefficient` — the pseudo-static earthquake as a load pattern: the inertia
  body forces ρ g k_h (horizontal) and ρ g k_v (vertical, + up) on the bodies and the
  reservoir's hydrodynamic force, the added mass times the same acceleration (Westergaard's
  pseudo-static pressure p(z) = (7/8) k_h γ_w √(H z) on a vertical face), per unit λ of its
  pattern.  With ``k_h = 1`` the pattern's factor *is* the seismic coefficient: a segment of
  it after the static loads locates the **yield acceleration** k_y g (the joint slides
  throughout, or equilibrium is lost) as an exact event.

Sources
-------
* H.M. Westergaard (1933), "Water pressures on dams during earthquakes", Transactions of the
  ASCE 98, 418–433: the hydrodynamic pressure on a rigid vertical face of a reservoir of
  depth H, incompressible water, under a horizontal ground acceleration α g, is
  p(z) = (7/8) α γ_w √(H z) (his parabolic approximation); its resultant
  (7/12) α γ_w H² acts at 0.4 H above the base.  Equivalently, a mass (7/8) ρ_w √(H z) per
  unit area moving with the face.
* J.S.-H. Kuo (1982), "Fluid–structure interactions: added mass computations for
  incompressible fluid", Report UCB/EERC-82/09, University of California, Berkeley: the
  "generalized Westergaard" added mass on a face of any slope, m_a(z) A n nᵀ at each node
  (depth z of the node, tributary area A, unit normal n) [to be checked: the report's section
  and its exact nodal rule]; USACE EM 1110-2-6051 (2003), *Time-history dynamic analysis of
  concrete hydraulic structures*, describes the same form [to be checked: chapter].

Units: kg, m, N, Pa, m/s².
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model import plausible
from stepcontact.model.loads import G_STANDARD, BodyForce
from stepcontact.model.supports import NodeSet

#: density of fresh water ρ_w, kg/m³ (γ_w = ρ_w g = 9810 N/m³ with g = 9.81 m/s²)
RHO_WATER = 1000.0
#: Westergaard's coefficient of the parabola: m_a(z) = 7/8 ρ_w √(H z)
WESTERGAARD_COEFFICIENT = 7.0 / 8.0
#: the height of the resultant of Westergaard's pressure above the base, as a fraction of H
WESTERGAARD_LEVER = 0.4


def westergaard_mass(depth, height: float, density: float = RHO_WATER) -> np.ndarray:
    """Westergaard's added mass per unit area of a vertical face, kg/m²:
    m_a(z) = (7/8) ρ_w √(H z) for 0 ≤ z ≤ H (z the depth below the free surface, m; H the
    reservoir depth, m), 0 above the water (Westergaard 1933)."""
    z = np.clip(np.asarray(depth, float), 0.0, None)
    return WESTERGAARD_COEFFICIENT * density * np.sqrt(height * z)


def westergaard_force(height: float, acceleration: float, density: float = RHO_WATER) -> float:
    """The hydrodynamic force on a rigid vertical face per metre of face, N/m:
    F = ∫₀ᴴ m_a(z) a dz = (7/12) ρ_w a H² (Westergaard 1933), acting at
    :data:`WESTERGAARD_LEVER` · H above the base; ``acceleration`` a in m/s²."""
    return 7.0 / 12.0 * density * acceleration * height**2


def _number(value, item: str) -> float:
    if isinstance(value, bool):
        raise ModelError(item, f"must be a number, got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ModelError(item, f"must be a number, got {value!r}") from None
    if not np.isfinite(v):
        raise ModelError(item, f"must be finite, got {v}")
    return v


@dataclass(frozen=True, eq=False)
class AddedMass:
    """The hydrodynamic added mass of a reservoir on the face ``face`` (the boundary edges of
    a 2D continuum body whose nodes all lie in the node set), kg/m² (Westergaard 1933, in the
    normal-direction form of Kuo 1982):

    .. math::  m_a(z) = \\tfrac78 \\, \\rho_w \\sqrt{H z}, \\qquad z = h_w - y,
               \\qquad H = h_w - y_b

    along the face's unit normal n (m_a n nᵀ per unit area: on a vertical face only u_x),
    lumped on the face's nodes by the exact integral of m_a times each node's shape
    function over the wet edges (:mod:`stepcontact.fem.hydrodynamic`).

    ``level`` h_w: the elevation of the free surface, m (y up); ``bottom`` y_b: the
    elevation of the reservoir bottom at the face, m (default: the face's lowest point);
    ``density`` ρ_w, kg/m³.  Edges above the level carry nothing.

    Assumptions (Westergaard's): a rigid dam face, incompressible water (the earthquake's
    periods longer than the reservoir's fundamental period 4H/C, C ≈ 1440 m/s the speed of
    sound in water), an infinitely long reservoir of constant depth, no surface waves; the
    normal-direction form extends it to inclined faces by the depth of each point (Kuo
    1982) — the hydrodynamic pressure on an inclined face is then taken as Westergaard's
    times the normal component of the acceleration.

    An item of the model: ``model.add(sc.AddedMass(face, level=95.0))``; the dynamic driver
    adds it to the mass matrix (M of eq. (7), "consistent" and "lumped" alike), so a ground
    acceleration a_g loads the face with the hydrodynamic force −M_a r a_g.  The level is the
    item's: a reservoir at another level is another model (``model.replace``).

    Example
    -------
    >>> import stepcontact as sc
    >>> dam = sc.rectangle("dam", (0, 0), (8, 10), 2, 5, sc.Material(E=25e9, nu=0.2,
    ...                                                             density=2400))
    >>> m = sc.Model(bodies=[dam])
    >>> water = sc.AddedMass(m.select("dam", x=0.0), level=10.0)
    >>> float(water.mass_per_area(0.0, 10.0))      # at the bottom: 7/8 ρ_w H, kg/m²
    8750.0
    """

    face: NodeSet
    level: float
    bottom: float | None = None
    density: float = RHO_WATER

    #: the field of :class:`~stepcontact.model.Model` the item goes to (``Model.add``)
    model_field: ClassVar[str] = "added_masses"

    def __post_init__(self):
        if not isinstance(self.face, NodeSet):
            raise ModelError("added mass.face", f"must be a node set (model.select(...)), got "
                             f"{type(self.face).__name__}")
        item = self.label
        object.__setattr__(self, "level", _number(self.level, f"{item}.level"))
        if self.bottom is not None:
            bottom = _number(self.bottom, f"{item}.bottom")
            object.__setattr__(self, "bottom", bottom)
            if bottom >= self.level:
                raise ModelError(f"{item}.level", f"is {self.level:g} m, not above the "
                                 f"reservoir bottom ({bottom:g} m): the reservoir is empty")
        rho = _number(self.density, f"{item}.density")
        if rho <= 0:
            raise ModelError(f"{item}.density", f"must be positive (kg/m³), got {rho:g}")
        object.__setattr__(self, "density", rho)
        if not 900.0 <= rho <= 1500.0:  # a unit slip (t/m³) or not water
            warnings.warn(plausible.PlausibilityWarning(
                f"{item}.density = {rho:g} kg/m³ is not that of water (1000 kg/m³; sea water "
                "1025, muddy water up to ~1400): check the value and its unit"), stacklevel=4)

    @property
    def label(self) -> str:
        """The item's name in messages: ``added mass on node set 'upstream'``."""
        return f"added mass on {self.face.label}"

    def height(self, y_face, item: str | None = None) -> float:
        """The reservoir depth H = level − bottom, m (bottom: the lowest of ``y_face``, the
        elevations of the face's nodes, when not given); a ModelError naming ``item``
        (default: :attr:`label`) when the face lies below the bottom or the level is not
        above it."""
        item = self.label if item is None else item
        y = np.asarray(y_face, float)
        low = float(y.min()) if y.size else self.level
        bottom = low if self.bottom is None else float(self.bottom)
        if low < bottom - 1e-9 * max(1.0, abs(bottom)):
            raise ModelError(f"{item}.bottom", f"is {bottom:g} m, above the face's lowest "
                             f"point ({low:g} m): the face cannot reach below the reservoir")
        H = self.level - bottom
        if H <= 0:
            raise ModelError(f"{item}.level", f"is {self.level:g} m, not above the "
                             f"reservoir bottom ({bottom:g} m, the face's lowest point): the "
                             "reservoir is empty")
        return H

    def mass_per_area(self, y, height: float) -> np.ndarray:
        """m_a at elevations ``y`` (m) for a reservoir of depth ``height`` H (m), kg/m²."""
        return westergaard_mass(self.level - np.asarray(y, float), height, self.density)


@dataclass(frozen=True, eq=False)
class SeismicCoefficient:
    """The pseudo-static earthquake, per unit λ of its load pattern: the inertia forces of a
    ground acceleration −g (k_h d, k_v) on the bodies and the reservoirs.

    * on the bodies ``bodies`` (all when empty): the body force ρ g (k_h d, k_v), N/m³ —
      d = ``direction`` (+1: along +x, downstream for a section with its reservoir on the
      left; −1: along −x), k_v > 0 upwards (the ground accelerating downwards: the weight
      is relieved, W (1 − k_v) with the self-weight);
    * on each reservoir of ``reservoir`` (:class:`AddedMass` items): the added mass times
      the same acceleration, f = M_a g (k_h d, k_v) — on a vertical upstream face the
      pseudo-static pressure of Westergaard (1933), p(z) = (7/8) k_h γ_w √(H z), pushing on
      the face when the inertia acts downstream, with the resultant (7/12) k_h γ_w H² at
      0.4 H above the base; on an inclined face its normal component (Kuo 1982).  The
      nodal forces are exact (the same integrals as the added mass,
      :mod:`stepcontact.fem.hydrodynamic`).

    With ``k_h = 1`` (the default) the factor λ of the pattern is the horizontal seismic
    coefficient: a segment of the pattern after the static loads (weight, reservoir,
    uplift) raises k_h until the joint slides throughout or equilibrium is lost — the
    **yield acceleration** k_y g, the λ of ``res.multipliers[-1].equilibrium_lost``, exact.
    ``k_v`` moves with λ (k_v = λ · ``k_v``: a fixed ratio k_v / k_h); a constant vertical
    coefficient is a pattern of its own (``SeismicCoefficient(k_h=0, k_v=0.1)`` applied at
    λ = 1 before the k_h segment).

    The change of the hydrostatic pressure under a vertical acceleration and the
    hydrodynamic pressure on a tailwater face are not included.

    Example
    -------
    >>> import stepcontact as sc
    >>> quake = sc.SeismicCoefficient(k_h=1.0, bodies=("dam",))
    >>> quake.acceleration()                       # m/s² per unit λ, inertia along +x
    (9.81, 0.0)
    """

    k_h: float = 1.0
    k_v: float = 0.0
    bodies: tuple[str, ...] = ()
    reservoir: tuple[AddedMass, ...] = ()
    direction: float = 1.0
    g: float = G_STANDARD

    label: ClassVar[str] = "seismic coefficient"

    def __post_init__(self):
        item = self.label
        kh = _number(self.k_h, f"{item}.k_h")
        kv = _number(self.k_v, f"{item}.k_v")
        if kh == 0.0 and kv == 0.0:
            raise ModelError(f"{item}.k_h", "k_h and k_v are both 0: the load is zero")
        d = _number(self.direction, f"{item}.direction")
        if d not in (1.0, -1.0):
            raise ModelError(f"{item}.direction", f"must be +1 (inertia along +x) or −1 "
                             f"(along −x), got {d:g}")
        g = _number(self.g, f"{item}.g")
        if g <= 0:
            raise ModelError(f"{item}.g", f"must be positive (m/s²), got {g:g}")
        plausible.warn("gravity", g, f"{item}.g", stacklevel=4)
        bodies = (self.bodies,) if isinstance(self.bodies, str) else tuple(self.bodies)
        res = self.reservoir
        res = () if res is None else (res,) if isinstance(res, AddedMass) else tuple(res)
        for i, r in enumerate(res):
            if not isinstance(r, AddedMass):
                raise ModelError(f"{item}.reservoir[{i}]", f"must be an AddedMass (the face, "
                                 f"its level), got {type(r).__name__}")
        for key, v in (("k_h", kh), ("k_v", kv), ("direction", d), ("g", g)):
            object.__setattr__(self, key, v)
        object.__setattr__(self, "bodies", tuple(str(b) for b in bodies))
        object.__setattr__(self, "reservoir", res)

    def acceleration(self) -> tuple[float, float]:
        """The inertia acceleration per unit λ, (g k_h d, g k_v), m/s² (the ground's is its
        opposite)."""
        return (self.g * self.k_h * self.direction, self.g * self.k_v)

    def body_force(self) -> BodyForce:
        """The bodies' part: a :class:`~stepcontact.model.BodyForce` with ``g`` the inertia
        acceleration."""
        return BodyForce(g=self.acceleration(), bodies=self.bodies)


__all__ = ["RHO_WATER", "WESTERGAARD_COEFFICIENT", "WESTERGAARD_LEVER", "AddedMass",
           "SeismicCoefficient", "westergaard_force", "westergaard_mass"]
