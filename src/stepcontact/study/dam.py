"""A parametric 2D gravity-dam section and its model (the dam study's section, issue 29 §3).

:class:`DamSection` holds a few parameters, SI units (m, Pa, kg/m³, degrees for angles), plane
strain per metre of dam:

* the section: ``height`` H, ``crest_width`` b_c, the batters of the faces (horizontal per
  vertical) ``upstream_slope`` n_u (0: a vertical upstream face) and ``downstream_slope``
  n_d; the heel is at (0, 0), the base B = b_c + (n_u + n_d) H long, the toe at (B, 0), the
  crest from (n_u H, H) to (n_u H + b_c, H);
* the foundation: a block ``foundation_depth`` deep reaching ``upstream_extent`` beyond the
  heel and ``downstream_extent`` beyond the toe, of ``rock``, fixed at its bottom, meshed with
  cells of ``foundation_cell`` (a mesh that does not match the dam's: mortar CFEs); or a rigid
  base (``rock=None``);
* the dam's ``concrete``; the joint between them (the interface ``base``): friction angle φ
  (``friction_angle``), and, when ``cohesion`` c or ``tensile_strength`` σ_t is positive, a
  bond (eq. (12), :meth:`~stepcontact.model.bond.Bond.mohr_coulomb`: τ ≤ c + σ tan φ, σ ≤ σ_t)
  that breaks into friction with the residual angle ``residual_friction_angle`` and cohesion
  ``residual_cohesion``;
* the water: reservoir levels ``normal_level`` and ``flood_level`` (m above the base), the
  ``tailwater`` level, a line of drains ``drain_position`` m from the heel with efficiency
  ``drain_efficiency`` (E), the crack water (``crack_water``), and ``max_level``, the level up
  to which the study raises the reservoir looking for failure;
* the mesh: ``cell`` (m), the dam's cell size; ``level_step`` (m): the reservoir's segments
  end every so many metres (the reported states of the λ–u curve).

:func:`dam_model` builds the :class:`~stepcontact.model.Model`: the dam meshed with
:func:`~stepcontact.model.mesh.quad_region`, the rock with
:func:`~stepcontact.model.mesh.rectangle`, the joint ``base``, the patterns ``weight``
(self-weight, :class:`~stepcontact.model.BodyForce`), ``tailwater`` (the tailwater on the
downstream face and its share of the uplift, factor 1) and ``reservoir`` — its factor is the
reservoir level h (m): :class:`~stepcontact.model.WaterLoad` with ``level=None`` on the upstream
face, the uplift's share of h, and :class:`~stepcontact.model.CrackWater` entering at the heel
(full reservoir pressure γ_w h where the joint has opened from the heel, replacing the uplift:
the cracked-base assumption, USACE EM 1110-2-2200 (1995) and FERC Engineering Guidelines ch. 3
(2016) [to be checked: sections]).

Uplift (a linear drop between the drain line and the ends; USACE EM 1110-2-2100 (2005) §3-3
and Fig. 3-2 [to be checked: section and figure numbers]): full reservoir head h at the heel,
the tailwater head t at the toe and, at the drain line x_d,

    h_d = t + (1 − E) (h − t) (B − x_d)/B,

linear between; without drains linear from h to t.  Since h_d is linear in h and t, the uplift
splits into the share of the reservoir (per metre of level, in the pattern ``reservoir``) and
the share of the tailwater (pattern ``tailwater``), each a :class:`~stepcontact.model.Uplift`
of ``(x, y, head)`` points.

:func:`hand_statics` gives the rigid-base limit-equilibrium figures of the section at a level
(weight and its lever, water forces, uplift and its lever, sums of forces and moments about the
toe, the resultant's position, the linear base pressures) — the numbers a reviewer checks by
hand.

Example
-------
>>> from stepcontact.study.dam import DamSection, dam_model
>>> s = DamSection(height=12, crest_width=2, downstream_slope=0.5)
>>> round(s.base_length, 6)
8.0
>>> m = dam_model(s)                                   # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model import (
    BodyForce,
    CrackWater,
    Interface,
    LoadPattern,
    Material,
    Model,
    RigidObstacle,
    Segment,
    Support,
    Uplift,
    WaterLoad,
)
from stepcontact.model.bond import Bond
from stepcontact.model.combinations import (
    BaseUplift,
    Combination,
    DamSite,
    Earthquake,
    Reservoir,
    SelfWeight,
    Silt,
    Tailwater,
)
from stepcontact.model.mesh import quad_region, rectangle
from stepcontact.model.supports import NodeSet
from stepcontact.results.dam_checks import JointStrength

#: unit weight of water γ_w, N/m³ (the model's default of WaterLoad and Uplift)
GAMMA_W = 9810.0
#: gravity, m/s² (the model's BodyForce)
G = 9.81
#: the joint's name in the model
JOINT = "base"
#: names of the bodies
DAM, ROCK = "dam", "rock"
#: most cells along a side of the dam's mesh (a guard against a cell size given in mm)
MAX_CELLS = 400


@dataclass(frozen=True)
class DamSection:
    """A 2D gravity-dam section on its foundation (SI: m, Pa, kg/m³; angles in degrees).

    Defaults: a 30 m dam with a 5 m crest, vertical upstream face and a 0.75 downstream batter
    (B = 27.5 m), on a rock block 30 m deep reaching 30 m beyond heel and toe; φ = 45°, no
    cohesion, no drains, no tailwater; normal level 27 m, flood level 30 m.
    """

    height: float = 30.0
    crest_width: float = 5.0
    upstream_slope: float = 0.0
    downstream_slope: float = 0.75
    concrete: Material = field(default_factory=lambda: Material(25e9, 0.2, 2400.0))
    rock: Material | None = field(default_factory=lambda: Material(15e9, 0.25, 2650.0))
    foundation_depth: float | None = None
    upstream_extent: float | None = None
    downstream_extent: float | None = None
    friction_angle: float = 45.0
    cohesion: float = 0.0
    tensile_strength: float = 0.0
    residual_friction_angle: float | None = None
    residual_cohesion: float = 0.0
    drain_position: float | None = None
    drain_efficiency: float = 0.0
    normal_level: float = 27.0
    flood_level: float = 30.0
    tailwater: float = 0.0
    max_level: float | None = None
    crack_water: bool = True
    cell: float = 1.0
    foundation_cell: float | None = None
    level_step: float | None = None
    guideline: str = "usace"
    guideline_variant: str | None = None
    k_h: float = 0.1
    k_v: float = 0.0
    max_kh: float = 1.0
    silt_level: float | None = None
    silt_unit_weight: float = 13.4e3
    compressive_strength: float | None = None
    #: the earthquake record (issue 29 §1: stepcontact.study.dam_quake.QuakeRecord), or None
    record: object = None

    def __post_init__(self):
        for key in ("height", "crest_width", "cell"):
            _positive(self, key)
        for key in ("upstream_slope", "downstream_slope", "cohesion", "tensile_strength",
                    "residual_cohesion", "tailwater"):
            _non_negative(self, key)
        for key in ("foundation_depth", "upstream_extent", "downstream_extent",
                    "foundation_cell", "max_level", "level_step"):
            if getattr(self, key) is not None:
                _positive(self, key)
        if self.concrete.density <= 0:
            raise ModelError("dam.concrete.density", "the dam needs a density (its weight)")
        for key in ("friction_angle", "residual_friction_angle"):
            v = getattr(self, key)
            if v is not None and not (math.isfinite(v) and 0.0 < v < 90.0):
                raise ModelError(f"dam.{key}", f"must be in (0, 90) degrees, got {v}")
        if not (0.0 <= self.drain_efficiency <= 1.0):
            raise ModelError("dam.drain_efficiency", f"is a fraction in [0, 1], got "
                             f"{self.drain_efficiency}")
        if self.drain_position is not None and not (0.0 < self.drain_position
                                                    < self.base_length):
            raise ModelError("dam.drain_position", f"must lie on the base, between the heel "
                             f"and the toe (0 < x < {self.base_length:g} m), got "
                             f"{self.drain_position}")
        _positive(self, "normal_level")
        if not self.flood_level >= self.normal_level:
            raise ModelError("dam.flood_level", f"must be at or above the normal level "
                             f"({self.normal_level:g} m), got {self.flood_level}")
        if not self.tailwater < self.normal_level:
            raise ModelError("dam.tailwater", f"must be below the normal level "
                             f"({self.normal_level:g} m), got {self.tailwater}")
        if self.tailwater >= self.height:
            raise ModelError("dam.tailwater", f"must be below the crest ({self.height:g} m), "
                             f"got {self.tailwater}")
        if not self.top_level > self.flood_level:
            raise ModelError("dam.max_level", f"must be above the flood level "
                             f"({self.flood_level:g} m), got {self.max_level}")
        self._check_combinations()
        if self.record is not None and type(self.record).__name__ != "QuakeRecord":
            raise ModelError("dam.record", f"must be a QuakeRecord "
                             f"(stepcontact.study.dam_quake), got {type(self.record).__name__}")
        cells = max(self.base_length, self.height) / self.cell
        if cells > MAX_CELLS:
            raise ModelError("dam.cell", f"{self.cell:g} m makes {cells:.0f} cells along a "
                             f"side of the dam (at most {MAX_CELLS}): give the size in m")

    def _check_combinations(self) -> None:
        """The fields of the combinations and the guideline checks (errors name the field)."""
        check_guideline(self.guideline, self.guideline_variant)
        _positive(self, "k_h", "")
        if not (isinstance(self.k_v, int | float) and math.isfinite(self.k_v)
                and abs(self.k_v) < 1):
            raise ModelError("dam.k_v", f"must be a number in (−1, 1) (> 0: the inertia "
                             f"upwards), got {self.k_v}")
        _positive(self, "max_kh", "")
        if not self.max_kh > self.k_h:
            raise ModelError("dam.max_kh", f"must be above the design k_h ({self.k_h:g}): "
                             f"the run to the yield acceleration goes beyond it, got "
                             f"{self.max_kh}")
        if self.silt_level is not None:
            _positive(self, "silt_level")
            if self.silt_level > self.height:
                raise ModelError("dam.silt_level", f"must be at most the dam's height "
                                 f"({self.height:g} m), got {self.silt_level}")
        _positive(self, "silt_unit_weight", " (N/m³)")
        if self.compressive_strength is not None:
            _positive(self, "compressive_strength", " (Pa)")

    # ------------------------------------------------------------------ geometry ---
    @property
    def base_length(self) -> float:
        """B = b_c + (n_u + n_d) H, m."""
        return self.crest_width + (self.upstream_slope + self.downstream_slope) * self.height

    @property
    def corners(self) -> tuple[tuple[float, float], ...]:
        """Heel, toe, downstream and upstream crest corners (counter-clockwise), m."""
        H, B = self.height, self.base_length
        x_up = self.upstream_slope * H
        return ((0.0, 0.0), (B, 0.0), (x_up + self.crest_width, H), (x_up, H))

    @property
    def area(self) -> float:
        """Area of the section, m² (a trapezoid: (B + b_c) H / 2)."""
        return 0.5 * (self.base_length + self.crest_width) * self.height

    @property
    def friction(self) -> float:
        """f = tan φ."""
        return math.tan(math.radians(self.friction_angle))

    @property
    def residual_friction(self) -> float:
        """tan φ_r after a bond breaks (φ_r defaults to φ)."""
        phi = self.friction_angle if self.residual_friction_angle is None else \
            self.residual_friction_angle
        return math.tan(math.radians(phi))

    @property
    def bonded(self) -> bool:
        """Whether the joint has initial strength (c > 0 or σ_t > 0): a bond."""
        return self.cohesion > 0 or self.tensile_strength > 0

    @property
    def top_level(self) -> float:
        """The highest level of the run to failure, m (``max_level``, default 3 H)."""
        return 3.0 * self.height if self.max_level is None else float(self.max_level)

    @property
    def depth(self) -> float:
        """Depth of the foundation block, m (default H)."""
        return self.height if self.foundation_depth is None else float(self.foundation_depth)

    @property
    def extents(self) -> tuple[float, float]:
        """The foundation beyond the heel and beyond the toe, m (default H each)."""
        up = self.height if self.upstream_extent is None else float(self.upstream_extent)
        down = self.height if self.downstream_extent is None else float(self.downstream_extent)
        return up, down

    @property
    def rock_cell(self) -> float:
        """Cell size of the foundation, m (default 1.6 × the dam's: the meshes do not match)."""
        return 1.6 * self.cell if self.foundation_cell is None else float(self.foundation_cell)

    @property
    def cells(self) -> tuple[int, int]:
        """The dam's cells along the base and up the height."""
        return (max(2, round(self.base_length / self.cell)), max(2, round(self.height / self.cell)))

    @property
    def levels(self) -> tuple[float, ...]:
        """The levels at which the reservoir's segments end, m: every ``level_step`` (default
        H/20: the points of the λ–u curve, the states between events being polynomials in the
        level) and the normal, flood and top levels."""
        step = self.height / 20 if self.level_step is None else float(self.level_step)
        n = int(math.floor(self.top_level / step + 1e-9))
        stops = {round(k * step, 12) for k in range(1, n + 1)}
        stops |= {float(self.normal_level), float(self.flood_level), self.top_level}
        return tuple(sorted(v for v in stops if 0 < v <= self.top_level))

    def replace(self, **changes) -> DamSection:
        return dataclasses.replace(self, **changes)

    # -------------------------------------------------------------------- uplift ---
    def uplift_heads(self) -> tuple[list[tuple[float, float]], list[tuple[float, float]]]:
        """(x, head) points of the uplift's share per metre of reservoir level and of the
        tailwater level (m of head per m of level), heel to toe: the drain-line head
        h_d = t + (1 − E)(h − t)(B − x_d)/B split into its parts in h and in t."""
        B = self.base_length
        if self.drain_position is None:
            return [(0.0, 1.0), (B, 0.0)], [(0.0, 0.0), (B, 1.0)]
        xd = float(self.drain_position)
        k = (1.0 - self.drain_efficiency) * (B - xd) / B
        return [(0.0, 1.0), (xd, k), (B, 0.0)], [(0.0, 0.0), (xd, 1.0 - k), (B, 1.0)]

    def uplift_head(self, x, level: float) -> np.ndarray:
        """Uplift head (m) at x (m from the heel) at the reservoir ``level``."""
        res, tail = self.uplift_heads()
        xs = [p[0] for p in res]
        return (level * np.interp(x, xs, [p[1] for p in res])
                + self.tailwater * np.interp(x, xs, [p[1] for p in tail]))


def check_guideline(guideline: str, variant: str | None) -> None:
    """A ModelError naming ``dam.guideline`` or ``dam.guideline_variant`` when the guideline
    is not in the data file (:func:`~stepcontact.results.dam_checks.load_guidelines`) or the
    variant is not one of its variants."""
    from stepcontact.results.dam_checks import load_guidelines

    gs = load_guidelines()
    if guideline not in gs:
        raise ModelError("dam.guideline", f"'{guideline}' is not a guideline "
                         f"(known: {', '.join(gs)})")
    g = gs[guideline]
    if variant is not None and variant not in g.variants:
        raise ModelError("dam.guideline_variant", f"'{variant}' is not a variant of "
                         f"{g.title} (variants: {', '.join(repr(v) for v in g.variants)})")


def _positive(s: DamSection, key: str, unit: str = " (m)") -> None:
    v = getattr(s, key)
    if isinstance(v, bool) or not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
        raise ModelError(f"dam.{key}", f"must be a positive number{unit}, got {v}")


def _non_negative(s: DamSection, key: str) -> None:
    v = getattr(s, key)
    if not (isinstance(v, int | float) and math.isfinite(v) and v >= 0):
        raise ModelError(f"dam.{key}", f"must be ≥ 0, got {v}")


def _on_line(p0, p1, tol: float):
    """A node filter: the points on the segment p0–p1 (within ``tol`` m)."""
    (x0, y0), (x1, y1) = p0, p1
    L = math.hypot(x1 - x0, y1 - y0)

    def where(x, y):
        return np.abs((x - x0) * (y1 - y0) - (y - y0) * (x1 - x0)) / L < tol

    return where


def joint_bond(s: DamSection) -> Bond | None:
    """The joint's bond (Mohr–Coulomb, eq. (12)), or None without cohesion and tension."""
    if not s.bonded:
        return None
    phi_r = s.friction_angle if s.residual_friction_angle is None else \
        s.residual_friction_angle
    return Bond.mohr_coulomb(s.cohesion, s.tensile_strength, s.friction_angle,
                             residual_friction=math.tan(math.radians(phi_r)),
                             residual_cohesion=s.residual_cohesion)


def _bare(s: DamSection) -> tuple[Model, list, Interface, NodeSet, NodeSet]:
    """The bodies of the section, its supports and joint, and its upstream and downstream
    faces (node sets of the dam): (model of the bodies, [supports], joint, upstream,
    downstream)."""
    heel, toe, crest_down, crest_up = s.corners
    nx, ny = s.cells
    dam = quad_region(DAM, list(s.corners), nx, ny, s.concrete)
    bodies = [dam]
    up, down = s.extents
    B = s.base_length
    if s.rock is not None:
        c = s.rock_cell
        bodies.insert(0, rectangle(ROCK, (-up, -s.depth), (B + down, 0.0),
                                   max(2, round((up + B + down) / c)),
                                   max(2, round(s.depth / c)), s.rock))
    m = Model(bodies=bodies, name=f"gravity dam H={s.height:g} m")
    tol = 1e-6 * max(B, s.height)
    if s.rock is not None:
        minus = m.select(ROCK, y=0.0)
        items: list = [Support("deep rock", m.select(ROCK, y=-s.depth), "xy")]
    else:
        minus = RigidObstacle("rigid base", [(-up, 0.0), (B + down, 0.0)])
        items = []
    bond = joint_bond(s)
    base = Interface(JOINT, plus=m.select(DAM, y=0.0), minus=minus,
                     friction=s.residual_friction if bond is not None else s.friction,
                     bond=bond)
    return (m, items, base, m.select(DAM, where=_on_line(heel, crest_up, tol)),
            m.select(DAM, where=_on_line(toe, crest_down, tol)))


def dam_model(s: DamSection, levels: tuple[float, ...] | None = None) -> Model:
    """The model of the section ``s`` (see the module's docstring): bodies ``dam`` (and
    ``rock``), interface ``base``, patterns ``weight``, ``tailwater`` (with a tailwater) and
    ``reservoir`` (its factor is the level, m); the program: the weight, the tailwater, then
    the reservoir raised through ``levels`` (m; default :attr:`DamSection.levels`: every
    ``level_step``, the normal and flood levels, up to :attr:`DamSection.top_level`)."""
    m, items, base, upstream, downstream = _bare(s)
    per_level, per_tail = s.uplift_heads()
    reservoir = [WaterLoad(upstream, level=None),
                 Uplift(base, head=[(x, 0.0, v) for x, v in per_level])]
    if s.crack_water:
        reservoir.append(CrackWater(base, level=None, entry=(0.0, 0.0)))
    items += [base, LoadPattern("weight", [BodyForce(bodies=(DAM,))]),
              LoadPattern("reservoir", reservoir)]
    program = [Segment("weight", 1.0)]
    if s.tailwater > 0:
        items.append(LoadPattern("tailwater", [
            WaterLoad(downstream, level=s.tailwater),
            Uplift(base, head=[(x, 0.0, s.tailwater * v) for x, v in per_tail])]))
        program.append(Segment("tailwater", 1.0))
    if levels is None:
        levels = s.levels
    program += [Segment("reservoir", float(h)) for h in levels]
    return m.add(*items, *program)


# ------------------------------------------------------------------- combinations ---

def dam_site(s: DamSection) -> DamSite:
    """The section's model without loads (bodies, supports, the joint ``base``) as a
    :class:`~stepcontact.model.combinations.DamSite`: heel (0, 0), toe (B, 0), the upstream
    and downstream faces, the dam's body — where the load cases of
    :mod:`stepcontact.model.combinations` act."""
    m, items, base, upstream, downstream = _bare(s)
    return DamSite(m.add(*items, base), base=JOINT, heel=(0.0, 0.0),
                   toe=(s.base_length, 0.0), upstream=upstream, dam=(DAM,),
                   downstream=downstream)


def drain_ratio(s: DamSection) -> float:
    """The drains' head ratio K of :class:`~stepcontact.model.combinations.BaseUplift`:
    the drain-line head t + (1 − E)(h − t)(B − x_d)/B is H₂ + K (H₁ − H₂) with
    K = (1 − E)(B − x_d)/B (1 without drains)."""
    if s.drain_position is None:
        return 1.0
    B = s.base_length
    return (1.0 - s.drain_efficiency) * (B - float(s.drain_position)) / B


def _static_cases(s: DamSection, level: float) -> tuple:
    """Self-weight, the reservoir at ``level`` (with the crack water if the section has it),
    the tailwater, the uplift (drained or not) and the silt."""
    cases: list = [SelfWeight(g=G), Reservoir(float(level), crack_water=s.crack_water,
                                              unit_weight=GAMMA_W)]
    if s.tailwater > 0:
        cases.append(Tailwater(float(s.tailwater), unit_weight=GAMMA_W))
    drain = None if s.drain_position is None else (float(s.drain_position), 0.0)
    cases.append(BaseUplift(drain=drain, ratio=drain_ratio(s) if drain else 1.0 / 3.0,
                            unit_weight=GAMMA_W))
    if s.silt_level is not None:
        cases.append(Silt(float(s.silt_level), float(s.silt_unit_weight), 1.0))
    return tuple(cases)


def earthquake(s: DamSection, k_h: float | None = None) -> Earthquake:
    """The pseudo-static earthquake of the section at ``k_h`` (default the design
    ``s.k_h``), k_v in the section's ratio k_v/k_h, with the reservoir's Westergaard
    pressure (:class:`~stepcontact.model.combinations.Earthquake`)."""
    kh = float(s.k_h if k_h is None else k_h)
    return Earthquake(kh, k_v=float(s.k_v) * kh / float(s.k_h), g=G)


def combinations(s: DamSection) -> list[Combination]:
    """The section's load combinations (:mod:`stepcontact.model.combinations`):

    * ``usual`` (condition usual): self-weight, the reservoir at the normal level, the
      tailwater, the uplift, the silt;
    * ``unusual (flood)`` (condition flood): the same at the flood level (left out when it
      equals the normal level);
    * ``extreme (earthquake)`` (condition earthquake): the usual loads and the pseudo-static
      earthquake k_h, k_v with the reservoir's hydrodynamic pressure;
    * ``post-earthquake``: the same earthquake applied and removed — the cracked, slid state
      under the usual loads."""
    usual = _static_cases(s, s.normal_level)
    out = [Combination("usual", "usual", usual)]
    if s.flood_level != s.normal_level:
        out.append(Combination("unusual (flood)", "flood", _static_cases(s, s.flood_level)))
    quake = earthquake(s)
    out += [Combination("extreme (earthquake)", "earthquake", usual + (quake,)),
            Combination("post-earthquake", "post-earthquake", usual + (quake,))]
    return out


def joint_strength(s: DamSection) -> JointStrength:
    """The joint's strength for the checks: peak c, φ; residual c_r, φ_r when
    ``residual_friction_angle`` is given; the ``compressive_strength``."""
    return JointStrength(cohesion=float(s.cohesion), friction_angle=float(s.friction_angle),
                         residual_cohesion=float(s.residual_cohesion),
                         residual_friction_angle=s.residual_friction_angle,
                         compressive_strength=s.compressive_strength)


# ------------------------------------------------------------------ hand statics ---

def _linear_load(points: list[tuple[float, float]], B: float) -> tuple[float, float]:
    """(resultant, moment about x = B) of a load piecewise linear through ``points`` (x, q),
    per unit q: ∫ q dx and ∫ q (B − x) dx, exact piece by piece."""
    F = M = 0.0
    for (x0, q0), (x1, q1) in zip(points[:-1], points[1:], strict=True):
        L = x1 - x0
        F += 0.5 * (q0 + q1) * L
        # ∫ q (B − x) dx over the piece: q linear, (B − x) linear: Simpson is exact
        xm, qm = 0.5 * (x0 + x1), 0.5 * (q0 + q1)
        M += L / 6.0 * (q0 * (B - x0) + 4 * qm * (B - xm) + q1 * (B - x1))
    return F, M


def _face_water(level: float, top: float, slope: float,
                gamma: float = GAMMA_W) -> tuple[float, float, float]:
    """Hydrostatic load on a face of batter ``slope`` (horizontal per vertical) wetted from
    y = 0 to d = min(level, top): (horizontal force γ_w ∫(h − y) dy, its moment arm ∫(h−y) y dy
    / ∫(h−y) dy, the vertical force n ∫ γ_w (h − y) dy), per metre; zeros when dry.
    ``gamma``: the fluid's unit weight, N/m³ (the silt's equivalent fluid K γ'_s)."""
    d = min(max(level, 0.0), top)
    if d <= 0:
        return 0.0, 0.0, 0.0
    F = gamma * (level * d - d * d / 2)
    Fy = gamma * (level * d * d / 2 - d ** 3 / 3)  # ∫ γ (h − y) y dy
    return F, Fy / F, slope * F


def hand_statics(s: DamSection, level: float) -> dict[str, float]:
    """Rigid-base limit-equilibrium statics of the section at the reservoir ``level`` (m), per
    metre of dam, the uncracked base (uplift by :meth:`DamSection.uplift_head`, no crack water):
    the figures a reviewer checks by hand.

    Forces N, moments N·m about the toe, positive when they resist overturning (press the
    heel down); levers in m from the toe.  Keys: ``W`` and ``W_lever`` (the weight and the
    horizontal distance of the section's centroid from the toe), ``H_up`` (the reservoir's
    horizontal thrust γ_w (h d − d²/2), d = min(h, H)) and ``H_up_arm`` (its height above the
    base), ``V_up`` (the water's weight on an upstream batter) and ``V_up_lever``, ``H_down``,
    ``H_down_arm``, ``V_down``, ``V_down_lever`` (the tailwater's), ``H_silt``, ``H_silt_arm``,
    ``V_silt`` (the silt's, an equivalent fluid of unit weight ``silt_unit_weight`` = K γ'_s
    normal to the upstream face; zeros without silt), ``U`` (uplift force ∫ γ_w h_u dx) and
    ``U_lever``, ``sum_V`` (net downward force on the base, W + V_up + V_down + V_silt − U),
    ``sum_H`` (net downstream force, H_up + H_silt − H_down), ``M_resisting``, ``M_overturning``,
    ``sum_M`` (their difference), ``resultant_from_toe`` = ΣM/ΣV, ``eccentricity`` e = B/2 −
    ΣM/ΣV (> 0: the resultant downstream of the base's centre), the linear
    base pressures ``sigma_heel``, ``sigma_toe`` = ΣV/B (1 ∓ 6e/B) (Pa, compression positive;
    the heel's is negative when the resultant leaves the middle third), the friction-only
    factor ``sliding_factor`` = tan φ ΣV/ΣH and the shear-friction factor
    ``shear_friction_factor`` = (c B + tan φ ΣV)/ΣH (USACE EM 1110-2-2100 (2005) §4-4 [to be
    checked]), and ``overturning_factor`` = M_resisting/M_overturning."""
    H, B, bc = s.height, s.base_length, s.crest_width
    nu, nd = s.upstream_slope, s.downstream_slope
    W = s.concrete.density * G * s.area
    # centroid of the trapezoid (heel, toe, crest corners) from the heel, by triangles
    x_up = nu * H
    parts = [(0.5 * x_up * H, 2 * x_up / 3),  # the upstream wedge
             (bc * H, x_up + bc / 2),  # the rectangle under the crest
             (0.5 * nd * H * H, x_up + bc + nd * H / 3)]  # the downstream wedge
    x_w = sum(a * x for a, x in parts) / sum(a for a, _ in parts)
    Hu, Hu_arm, Vu = _face_water(level, H, nu)
    # the vertical water load on a batter acts where the horizontal one does, moved along the
    # face: x = n_u y from the heel (x = B − n_d y on the downstream face)
    Vu_x = nu * Hu_arm
    t = s.tailwater
    Hd, Hd_arm, Vd = _face_water(t, H, nd)
    Vd_from_toe = nd * Hd_arm
    res, tail = s.uplift_heads()
    pts = [(x, GAMMA_W * (level * a + t * b)) for (x, a), (_, b) in zip(res, tail, strict=True)]
    U, MU = _linear_load(pts, B)
    # silt: an equivalent fluid K γ'_s = silt_unit_weight, normal to the upstream face
    Hs, Hs_arm, Vs = (0.0, 0.0, 0.0) if s.silt_level is None else _face_water(
        float(s.silt_level), H, nu, float(s.silt_unit_weight))
    sum_V = W + Vu + Vd + Vs - U
    sum_H = Hu + Hs - Hd
    resisting = (W * (B - x_w) + Vu * (B - Vu_x) + Vd * Vd_from_toe + Hd * Hd_arm
                 + Vs * (B - nu * Hs_arm))
    overturning = Hu * Hu_arm + MU + Hs * Hs_arm
    sum_M = resisting - overturning
    from_toe = sum_M / sum_V if sum_V else float("nan")
    e = B / 2 - from_toe
    tan = s.friction
    with np.errstate(divide="ignore"):
        sf = tan * sum_V / sum_H if sum_H > 0 else float("inf")
        sff = (s.cohesion * B + tan * sum_V) / sum_H if sum_H > 0 else float("inf")
        ov = resisting / overturning if overturning > 0 else float("inf")
    return {"level": float(level), "W": W, "W_lever": B - x_w, "H_up": Hu, "H_up_arm": Hu_arm,
            "V_up": Vu, "V_up_lever": B - Vu_x, "H_down": Hd, "H_down_arm": Hd_arm,
            "V_down": Vd, "V_down_lever": Vd_from_toe, "H_silt": Hs, "H_silt_arm": Hs_arm,
            "V_silt": Vs, "U": U,
            "U_lever": MU / U if U else 0.0, "sum_V": sum_V, "sum_H": sum_H,
            "M_resisting": resisting, "M_overturning": overturning, "sum_M": sum_M,
            "resultant_from_toe": from_toe, "eccentricity": e,
            "sigma_heel": sum_V / B * (1 - 6 * e / B), "sigma_toe": sum_V / B * (1 + 6 * e / B),
            "sliding_factor": sf, "shear_friction_factor": sff, "overturning_factor": ov}


def hand_yield(s: DamSection, level: float | None = None) -> dict[str, float]:
    """The rigid-base, friction-and-cohesion limit equilibrium of the section's pseudo-static
    yield acceleration at the reservoir ``level`` (default the normal level), per metre of
    dam, with the **exact load set of the study** (:func:`combinations`): the static loads of
    :func:`hand_statics` (uncracked base, no crack water) and, per unit k_h, the inertia
    W (1, r) (r = k_v/k_h, + up) at the centroid and the reservoir's pseudo-static pressure
    (Westergaard 1933 in Kuo's (1982) normal form on a face of batter n_u): with the face wet
    to d = min(h, H),

        P = ∫₀ᵈ (7/8) γ_w √(h (h − y)) dy · (1 − r n_u)/√(1 + n_u²)
          = (7/12) γ_w (h^{3/2} − (h − d)^{3/2}) √h · (1 − r n_u)/√(1 + n_u²)

    horizontal (downstream), and n_u P vertical (down).  Sliding of the whole base,
    c B + tan φ ΣV(k) = ΣH(k) with ΣV(k) = ΣV₀ − k r W + k n_u P and ΣH(k) = ΣH₀ + k (W + P):

        k_y = (c B + tan φ ΣV₀ − ΣH₀) / (W + P + tan φ (r W − n_u P))

    (EM 1110-2-2100 (2005) eq. (3-1) with the seismic coefficient method of EM 1110-2-2200
    (1995) ch. 3 [to be checked]).  It equals the elastic run's yield acceleration when the
    whole base stays compressed up to it (no crack, no crack water) and the dam slides before
    it overturns; it is a check of the load set, not of the cracked answer.  Keys: the
    :func:`hand_statics` figures ``W``, ``sum_V`` (ΣV₀), ``sum_H`` (ΣH₀), and ``P``,
    ``r``, ``n_u``, ``tan_phi``, ``c``, ``B``, ``k_y`` (dimensionless)."""
    h = float(s.normal_level if level is None else level)
    st = hand_statics(s, h)
    nu, B = s.upstream_slope, s.base_length
    d = min(h, s.height)
    r = float(s.k_v) / float(s.k_h)
    P = (7.0 / 12.0 * GAMMA_W * (h ** 1.5 - (h - d) ** 1.5) * math.sqrt(h)
         * (1.0 - r * nu) / math.sqrt(1.0 + nu * nu))
    W, tan, c = st["W"], s.friction, float(s.cohesion)
    k_y = (c * B + tan * st["sum_V"] - st["sum_H"]) / (W + P + tan * (r * W - nu * P))
    return {"level": h, "W": W, "sum_V": st["sum_V"], "sum_H": st["sum_H"], "P": P, "r": r,
            "n_u": nu, "tan_phi": tan, "c": c, "B": B, "k_y": k_y}


__all__ = ["DAM", "GAMMA_W", "JOINT", "ROCK", "DamSection", "combinations", "dam_model",
           "dam_site", "drain_ratio", "earthquake", "hand_statics", "hand_yield", "joint_bond",
           "joint_strength"]
