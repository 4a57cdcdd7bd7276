"""Joints with initial strength (article eq. (12)): the bond of an interface's CFEs until it
breaks into unilateral contact with Coulomb friction
(:class:`~stepcontact.contact.laws.CoulombLaw`).

While the bond of CFE k is intact the CFE carries tension and shear with no relative motion (or
the compliance of its layer, eq. (11)) inside the strength surface

.. math::

    N_k + |Q_k| / \\alpha_t \\le N_{Rk}, \\qquad |Q_k| \\le Q_{Rk} - \\alpha_R N_k

(N > 0 tension, N; N_Rk = A_k σ_R and Q_Rk = A_k τ_R from the strengths per unit area; the
article writes α_t = α_R).  Reaching a facet breaks the bond, an event located like the
others; the forces the CFE can no longer carry are released at the same load factor and its
neighbours may break in turn (a crack running along the joint, event by event).

After the break the CFE is a unilateral Coulomb contact with its own friction f and, optionally,
a residual cohesion C_r (per unit area): a closed CFE slips when |Q| = f p + C_r A_k.  The
residual cohesion is lost when the CFE opens (an opened joint has no cohesion): the shear it
still carried is released at the same load factor, and the CFE is purely frictional from then
on.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model.profile import as_function

#: the Mohr–Coulomb friction angle φ, degrees, lies in [0, 90)
FRICTION_ANGLE_RANGE: tuple[float, float] = (0, 90)


@dataclass(frozen=True, eq=False)
class Bond:
    """The initial strength of a joint (eq. (12)), per unit area (SI).

    Parameters
    ----------
    tensile : strength σ_R in tension, Pa (N_Rk = A_k σ_R)
    shear : strength τ_R in shear without normal force (the cohesion), Pa (Q_Rk = A_k τ_R)
        Each a constant, a :class:`~stepcontact.model.LinearProfile`, a list of
        ``(x, y, value)`` points (linear by coordinates along the joint) or a function
        ``v(x, y)`` of the CFE's point: strengths that vary along the joint.
    alpha : float
        α_R (–): the growth of the shear strength with compression, |Q| ≤ Q_R − α_R N
        (tan φ of Mohr–Coulomb).
    tension_alpha : float, optional
        α_t (–) of the tension facets N + |Q|/α_t ≤ N_R.  None: α_R, as the article's eq.
        (12) writes them (the two pairs of facets are then parallel, and the one with the
        smaller intercept governs); ``inf``: a tension cut-off N ≤ N_R (Mohr–Coulomb).
    friction : float, optional
        Friction coefficient of the joint after its bond breaks (None: the interface's).
    residual_cohesion : optional
        C_r, Pa: the cohesion the joint keeps after its bond breaks (a constant, profile,
        points or function like the strengths; default 0).  A broken, closed CFE slips at
        |Q| = f p + C_r A_k; it loses C_r for good when it opens.

    :meth:`mohr_coulomb` builds one from cohesion, tensile strength and friction angle.
    """

    tensile: object
    shear: object
    alpha: float = 0.0
    tension_alpha: float | None = None
    friction: float | None = None
    residual_cohesion: object = 0.0

    #: the strengths given per unit area (Pa), in the order of the law's columns
    STRENGTHS = ("tensile", "shear")

    def __post_init__(self):
        item = "bond"
        for key in (*self.STRENGTHS, "residual_cohesion"):
            self.function(key)  # checks the spec
        if not (np.isfinite(self.alpha) and self.alpha >= 0):
            raise ModelError(f"{item}.alpha", f"must be ≥ 0, got {self.alpha}")
        if self.tension_alpha is not None and not (self.tension_alpha > 0):
            raise ModelError(f"{item}.tension_alpha", f"must be > 0 (inf: a tension cut-off), "
                             f"got {self.tension_alpha}")
        if self.tension_alpha is None and self.alpha == 0:
            raise ModelError(f"{item}.alpha", "the tension facets N + |Q|/α_R ≤ N_R need "
                             "α_R > 0: give alpha, or tension_alpha (inf: a tension cut-off)")
        if self.friction is not None and not (np.isfinite(self.friction)
                                              and self.friction >= 0):
            raise ModelError(f"{item}.friction", f"must be ≥ 0, got {self.friction}")
        if self.friction is not None:
            from stepcontact.model import plausible

            plausible.warn("friction", self.friction, f"{item}.friction", stacklevel=4)
        if (text := self.residual_problem(self.residual_cohesion)) is not None:
            raise ModelError(f"{item}.residual_cohesion", text)

    @staticmethod
    def residual_problem(rc) -> str | None:
        """Why a constant residual cohesion C_r (Pa) is refused (None: it is not, or it
        varies along the joint and is checked at the CFEs)."""
        if np.ndim(rc) == 0 and not callable(rc) and not float(rc) >= 0:
            return f"must be ≥ 0 Pa, got {float(rc)!r}"
        return None

    @classmethod
    def mohr_coulomb(cls, cohesion, tensile_strength, friction_angle: float,
                     residual_friction: float | None = None,
                     residual_cohesion: object = 0.0) -> Bond:
        """The Mohr–Coulomb strength engineers use: shear τ ≤ c + σ tan φ (σ compression)
        with a tension cut-off σ_t, per unit area: eq. (12) with τ_R = c, α_R = tan φ,
        σ_R = σ_t and α_t = ∞.

        ``cohesion`` c and ``tensile_strength`` σ_t in Pa (constants, profiles or functions
        of (x, y)), ``friction_angle`` φ in degrees; ``residual_friction``: f after the break
        (default tan φ), ``residual_cohesion`` C_r after the break, Pa (default 0)."""
        lo, hi = FRICTION_ANGLE_RANGE
        if not (np.isfinite(friction_angle) and lo <= friction_angle < hi):
            raise ModelError("bond.friction_angle", f"must be in [{lo:g}, {hi:g}) degrees, got "
                             f"{friction_angle}")
        tan = math.tan(math.radians(friction_angle))
        text = apex_problem(cohesion, tensile_strength, friction_angle)
        if text is not None:
            from stepcontact.model import plausible

            warnings.warn(plausible.PlausibilityWarning(f"bond.tensile_strength = {text}"),
                          stacklevel=2)
        return cls(tensile=tensile_strength, shear=cohesion, alpha=tan, tension_alpha=math.inf,
                   friction=tan if residual_friction is None else residual_friction,
                   residual_cohesion=residual_cohesion)

    def function(self, key: str):
        """The strength ``key`` ("tensile", "shear" or "residual_cohesion") as a function
        v(x, y), Pa."""
        return as_function(getattr(self, key), f"bond.{key}", 1.0)

    def arrays(self, x: np.ndarray, area: np.ndarray, item: str) -> np.ndarray:
        """The law's bond columns (k, 5) — N_R, Q_R (N), α_R, 1/α_t, C_r A (N) — of CFEs at
        points ``x`` (k, 2) with areas ``area`` (m²); ``item`` names the interface in errors
        (:data:`~stepcontact.contact.laws.BOND_COLUMNS`)."""
        out = np.empty((len(area), 5))
        for j, key in zip((0, 1, 4), (*self.STRENGTHS, "residual_cohesion"), strict=True):
            v = np.broadcast_to(np.asarray(self.function(key)(x[:, 0], x[:, 1]), float),
                                area.shape)
            bad = ~np.isfinite(v) | (v < 0)
            if bad.any():
                k = int(np.flatnonzero(bad)[0])
                what = "a cohesion" if key == "residual_cohesion" else "a strength"
                raise ModelError(f"{item}.bond.{key}", f"gives {v[k]} Pa at CFE {k} "
                                 f"({x[k, 0]:g}, {x[k, 1]:g}): {what} must be ≥ 0")
            out[:, j] = area * v
        out[:, 2] = self.alpha
        at = self.alpha if self.tension_alpha is None else self.tension_alpha
        out[:, 3] = 0.0 if math.isinf(at) else 1.0 / at
        return out


def apex_problem(cohesion, tensile_strength, friction_angle: float) -> str | None:
    """Why a Mohr–Coulomb tension cut-off σ_t (Pa) lies beyond the apex of the envelope,
    c·cot φ (c in Pa, φ in degrees), where the shear strength c − σ tan φ reaches zero: the
    joint can carry no more tension than the apex, and the cut-off never acts.  None when it
    does not (or when c or σ_t vary along the joint)."""
    tan = math.tan(math.radians(friction_angle))
    c, t = cohesion, tensile_strength
    if not (tan > 0 and all(isinstance(v, int | float) and not isinstance(v, bool)
                            for v in (c, t))):
        return None
    apex = c / tan
    if t <= apex * (1 + 1e-9):
        return None
    return (f"{t:g} Pa is beyond the apex of the Mohr–Coulomb envelope, c·cot φ = {apex:g} "
            f"Pa (c = {c:g} Pa, φ = {friction_angle:g}°): the joint can carry no more tension "
            "than that, so the cut-off never acts; give a tensile strength ≤ c·cot φ (Pa)")


__all__ = ["FRICTION_ANGLE_RANGE", "Bond", "apex_problem"]
