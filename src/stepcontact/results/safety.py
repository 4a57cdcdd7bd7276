"""Safety of a joint along the load path: the factors a dam engineer reads, and load margins.

For one interface at every reported state (plain arrays along the path axis, from the CFE forces
and the stored loads of the result — no new solve):

* ΣN and ΣQ, the sums of the CFE forces (N; ΣN ≤ 0 in compression);
* the position of the normal resultant along the joint, s_R = Σ N_k s_k / Σ N_k (m from the
  first CFE), its eccentricity e = s_R − B/2 (B from the first to the last CFE) and whether it
  lies in the middle third (|e| ≤ B/6); its distance from the joint's toe and heel (the ends of
  the joint's face S+, which may lie beyond the first and last CFE of a mortar joint);
* the normal stress σ_n = N/A of the CFE at each end (heel and toe, Pa);
* the compressed area A_c = Σ_{N_k<0} A_k over the closed CFEs (m²) and length
  L_c = L A_c / ΣA_k (m; L the length of the joint between its ends), and the open length (the
  open CFEs' share);
* the **shear-friction factor** (c·A_c + N'·tan φ)/H, per CFE

      SFF = (Σ_{N_k<0} c_k A_k + Σ_k tanφ_k (−N_k)) / |ΣQ|

  with c_k the joint's cohesion — an intact bond's shear strength τ_R = Q_R/A_k and tan φ_k =
  α_R (eq. (12)); after the break the residual cohesion C_r while the CFE keeps it
  (:mod:`stepcontact.model.bond`) and tan φ_k = f_k; 0 without a bond — or a design cohesion
  given by the user (``cohesion``, Pa, on every compressed CFE);
* the **friction-only factor** Σ f_k (−N_k) / |ΣQ| (= f·|ΣN|/|ΣQ| for one friction
  coefficient; ``sliding_factor``): ≥ 1 and 1 exactly when every CFE in contact slips, for a
  joint without cohesion;
* the **overturning factor** ΣM_r / ΣM_o about the toe: the moments of the loads on the part
  above the joint (the bodies on its S+ side and those joined to them by other joints), split
  per load pattern (and per virtual pattern of a water level, one per wetted node) into the
  components normal and tangential to the joint, plus the crack water on the joint; a moment
  that presses the heel down resists, one that lifts it overturns.  The moments come from the
  patterns' first-moment tensors S = Σ x_i ⊗ f_i (``StaticResult.load_moments``), checked at
  every state against the moment of the joint's forces about the toe (the part must be held by
  the joint alone); where they disagree (another support of the part) or the result has no
  such tensors (written before they were stored, or a discrete model), NaN and a note why.

At a design value λ_d of the parameter being read (a load factor, or a water level in m):
the **design state** (:meth:`InterfaceSafety.design_values`) — the state recorded at λ_d, or
the interpolation between the two states around it on a linear segment; a segment that moves a
water level is not linear in it, so there it must have a state at λ_d (end a segment at the
design level) or the design values are None with a note.

Over the path: the load factor (or level) λ at which the joint slides and at which the body
overturns — the loss of equilibrium of the run when its mechanism moves a body of this
interface (sliding, or rotation about a point), otherwise the first state where the joint's own
shear-friction factor reaches 1 or the normal resultant reaches an end of the joint — and the
**load margins** λ_limit / λ_d (``margin_sliding``, ``margin_overturning``; "level at
sliding / design level" when the parameter is a level).  They are not the engineers' factors of
safety: a margin is how far the load (or the level) can grow, a factor how much the strength
exceeds the action at the design state.

The formulas hold for a straight joint (ΣN and ΣQ are then the resultant's components normal
and tangential to it).  The heel is the first CFE along the interface unless ``heel`` names a
point: the end nearest to it is the heel (order-independent).

Example
-------
>>> s = res.interface_safety("base", design=40.0, cohesion=200e3)     # doctest: +SKIP
>>> d = s.design_values()                                             # doctest: +SKIP
>>> d["shear_friction_factor"], d["overturning_factor"], s.margin_sliding  # doctest: +SKIP
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from stepcontact.enums import ContactState, Status

#: a :class:`~stepcontact.results.result.StaticResult`, read here through its attributes (the
#: result type builds on this module for its ``interface_safety``)
Result = Any

#: a sliding factor within this of 1 counts as "every CFE in contact slips"
SLIDING_RTOL = 1e-9
#: the moments of the loads on the part above a joint and of the joint's forces must balance to
#: this (relative to the sum of their magnitudes) for the overturning factor to be reported
MOMENT_RTOL = 1e-7
#: BOND_COLUMNS of :mod:`stepcontact.contact.laws`: Q_R (N), α_R, C_r A_k (N)
_QR, _ALPHA, _CR = 1, 2, 4


@dataclass(frozen=True)
class InterfaceSafety:
    """Safety quantities of one interface along the path (arrays: one entry per state).

    Attributes
    ----------
    interface : str
    lam : (n,) load factor of the active segment's pattern (the result's path axis)
    segment : (n,) segment of each state
    normal_force : (n,) ΣN, N (≤ 0 in compression)
    shear_force : (n,) ΣQ, N (along the CFE tangent t)
    position : (n,) s_R, position of the normal resultant from the heel CFE along the joint, m
        (NaN where ΣN = 0)
    point : (n, 2) coordinates of the normal resultant on S+, m
    eccentricity : (n,) e = s_R − B/2, m (> 0: towards the toe)
    in_kern : (n,) bool, |e| ≤ B/6 (the resultant in the middle third)
    sigma_heel, sigma_toe : (n,) σ_n = N/A of the CFE at the heel and at the toe, Pa
    sliding_factor : (n,) friction-only factor Σ f_k (−N_k) / |ΣQ| (inf where ΣQ = 0 to
        round-off); also ``friction_only_factor``
    open_length : (n,) sum of the tributary lengths of the open CFEs, m
    length : B, length of the joint from the first to the last CFE, m
    heel, toe : (2,) coordinates of the end CFEs, m
    friction : friction coefficient (the largest of the interface's CFEs)
    design : design value λ_d of the parameter (None: not given)
    lam_sliding, lam_overturning : λ at which the joint slides / the body overturns (None: not
        reached on the path)
    mechanism : the mode of the interface's bodies when the run lost equilibrium (None if
        it did not, or moved other bodies)
    compressed_area : (n,) A_c = Σ_{N_k<0} A_k, m²
    compressed_length : (n,) L_c = L A_c / ΣA_k, m
    cohesion_force : (n,) Σ_{N_k<0} c_k A_k, N
    shear_friction_factor : (n,) (Σ_{N_k<0} c_k A_k + Σ tanφ_k (−N_k)) / |ΣQ| (inf where ΣQ = 0)
    resisting_moment, overturning_moment : (n,) ΣM_r, ΣM_o about the toe, N·m (NaN: not
        computable, see ``overturning_note``)
    overturning_factor : (n,) ΣM_r / ΣM_o (inf where ΣM_o = 0; NaN: not computable)
    overturning_note : why the overturning factor is NaN at some states (None: never)
    from_toe, from_heel : (n,) distance of the normal resultant from the joint's toe and heel
        along the joint, m
    joint_length : L, length of the joint between its ends (the ends of S+), m
    joint_heel, joint_toe : (2,) the ends of the joint, m
    cohesion : the design cohesion given, Pa (None: the joint's own)
    cohesion_source : where the cohesion comes from (text)
    pattern : the load pattern whose factor is the parameter (the last segment's)
    is_level : whether that factor is a water level (m)
    design_state : the design state's values (:meth:`design_values`)
    limit_patterns : {"sliding", "overturning": the pattern of the segment where the limit was
        found} (a margin needs the parameter's pattern)
    """

    interface: str
    lam: np.ndarray
    segment: np.ndarray
    normal_force: np.ndarray
    shear_force: np.ndarray
    position: np.ndarray
    point: np.ndarray
    eccentricity: np.ndarray
    in_kern: np.ndarray
    sigma_heel: np.ndarray
    sigma_toe: np.ndarray
    sliding_factor: np.ndarray
    open_length: np.ndarray
    length: float
    heel: np.ndarray
    toe: np.ndarray
    friction: float
    design: float | None = None
    lam_sliding: float | None = None
    lam_overturning: float | None = None
    mechanism: str | None = None
    compressed_area: np.ndarray | None = None
    compressed_length: np.ndarray | None = None
    cohesion_force: np.ndarray | None = None
    shear_friction_factor: np.ndarray | None = None
    resisting_moment: np.ndarray | None = None
    overturning_moment: np.ndarray | None = None
    overturning_factor: np.ndarray | None = None
    overturning_note: str | None = None
    from_toe: np.ndarray | None = None
    from_heel: np.ndarray | None = None
    joint_length: float | None = None
    joint_heel: np.ndarray | None = None
    joint_toe: np.ndarray | None = None
    cohesion: float | None = None
    cohesion_source: str = ""
    pattern: str | None = None
    is_level: bool = False
    design_state: dict = field(default_factory=dict)
    limit_patterns: dict = field(default_factory=dict)
    #: ΣA_k, the area of the joint's CFEs, m² (the joint length times the thickness)
    joint_area: float | None = None

    @property
    def friction_only_factor(self) -> np.ndarray:
        """Friction-only factor N'·tan φ / H = Σ f_k (−N_k) / |ΣQ| (``sliding_factor``)."""
        return self.sliding_factor

    def _margin(self, kind: str) -> float | None:
        lim = getattr(self, f"lam_{kind}")
        if self.limit_patterns.get(kind, self.pattern) != self.pattern:
            return None  # reached in a segment of another pattern: not a λ of the parameter
        return _ratio(lim, self.design)

    @property
    def margin_sliding(self) -> float | None:
        """Load margin against sliding, λ_sliding / λ_d (a level: level at sliding / design
        level); None if either is unknown, or the joint slid in a segment of another pattern
        than the parameter's.  Not a factor of safety."""
        return self._margin("sliding")

    @property
    def margin_overturning(self) -> float | None:
        """Load margin against overturning, λ_overturning / λ_d (as ``margin_sliding``)."""
        return self._margin("overturning")

    #: former names of the margins (kept for existing callers)
    fs_sliding = margin_sliding
    fs_overturning = margin_overturning

    def design_values(self) -> dict[str, object]:
        """The factors at the design state (plain Python numbers; None where not computable,
        with the reasons in ``notes``); ``{}`` without a design value."""
        return dict(self.design_state)

    # ---- the guideline checks' quantities (stepcontact.results.dam_checks) ------------------
    def strength_factor(self, cohesion: float, tan_phi: float, i: int = -1) -> float:
        """The sliding factor of state ``i`` with a given strength, EM 1110-2-2100 (2005)
        eq. (3-1): F = (c A_c + N' tan φ) / H, with N' = −ΣN (N), H = |ΣQ| (N), A_c the
        compressed area (m²), ``cohesion`` c in Pa and ``tan_phi`` tan φ uniform over the joint
        (peak or residual strength, whatever the joint's own law); inf without shear."""
        n_eff, h = -float(self.normal_force[i]), abs(float(self.shear_force[i]))
        a_c = 0.0 if self.compressed_area is None else float(self.compressed_area[i])
        resist = cohesion * a_c + tan_phi * n_eff
        if h <= 1e-12 * max(abs(n_eff), cohesion * a_c, 1e-300):
            return float("inf")
        return resist / h

    def linear_stresses(self, i: int = -1) -> tuple[float, float]:
        """(σ_heel, σ_toe), Pa (compression negative), of state ``i`` by the gravity method: a
        linear pressure under the joint with the resultant N' at a = ``from_toe`` from the toe
        (the gravity method: e.g. USACE EM 1110-2-2200 (1995), *Gravity Dam Design*, ch. 4
        [to be checked]): σ = −N'/A (1 ± 6e/L), e = L/2 − a, inside the kern; outside it the
        compressed length 3a (or 3(L − a)) carries the triangle of peak 2N'/(3 a t), t = A/L.
        NaN when the resultant is outside the joint or there is no normal force."""
        L, A = self.joint_length, self.joint_area
        a = np.nan if self.from_toe is None else float(self.from_toe[i])
        n_eff = -float(self.normal_force[i])
        if not (L and A and np.isfinite(a) and n_eff > 0 and 0.0 < a < L):
            return float("nan"), float("nan")
        t = A / L
        if L / 3 <= a <= 2 * L / 3:
            e = L / 2 - a  # > 0: the resultant towards the toe
            return -n_eff / A * (1 - 6 * e / L), -n_eff / A * (1 + 6 * e / L)
        if a < L / 3:
            return 0.0, -2 * n_eff / (3 * a * t)
        return -2 * n_eff / (3 * (L - a) * t), 0.0

    def at(self, i: int = -1) -> dict[str, object]:
        """The quantities of state ``i`` (default the last) and the path's limits, as plain
        Python numbers (what ``stepcontact info`` prints)."""
        n = len(self.lam)
        j = i + n if i < 0 else i

        def num(a) -> float | None:
            if a is None:
                return None
            v = float(a[j])
            return v if np.isfinite(v) else None

        return {
            "interface": self.interface, "state": int(j), "lam": float(self.lam[j]),
            "segment": int(self.segment[j]),
            "normal_force": float(self.normal_force[j]),
            "shear_force": float(self.shear_force[j]),
            "position": num(self.position), "eccentricity": num(self.eccentricity),
            "in_kern": bool(self.in_kern[j]), "length": float(self.length),
            "sigma_heel": float(self.sigma_heel[j]), "sigma_toe": float(self.sigma_toe[j]),
            "sliding_factor": num(self.sliding_factor),
            "friction_only_factor": num(self.sliding_factor),
            "shear_friction_factor": num(self.shear_friction_factor),
            "overturning_factor": num(self.overturning_factor),
            "resultant_from_toe": num(self.from_toe),
            "compressed_length": num(self.compressed_length),
            "open_length": float(self.open_length[j]),
            "lam_sliding": self.lam_sliding, "lam_overturning": self.lam_overturning,
            "design": self.design, "margin_sliding": self.margin_sliding,
            "margin_overturning": self.margin_overturning,
            "fs_sliding": self.margin_sliding, "fs_overturning": self.margin_overturning,
            "mechanism": self.mechanism, "parameter_pattern": self.pattern,
            "parameter_is_level": self.is_level,
        }


def _ratio(a: float | None, b: float | None) -> float | None:
    return None if a is None or b is None or b == 0 else float(a) / float(b)


def _body_of_nodes(res: Result) -> tuple[list[str], np.ndarray]:
    """The bodies' names and the body index of every global node (−1: none)."""
    geo = res.geometry or {}
    bodies = list(geo.get("bodies", []))
    n = len(np.asarray(geo.get("points", np.zeros((0, 2)))))
    of = np.full(n, -1, np.int64)
    for j, b in enumerate(bodies):
        cells = np.asarray(b["cells"]).ravel()
        cells = cells[(cells >= 0) & (cells < n)]
        of[cells] = j
    return [str(b["name"]) for b in bodies], of


def _bodies_of_nodes(res: Result, nodes: np.ndarray) -> set[str]:
    """Names of the bodies the global nodes belong to (from the result's geometry)."""
    nodes = np.unique(nodes[nodes >= 0])
    out = set()
    for b in (res.geometry or {}).get("bodies", []):
        if np.isin(nodes, np.asarray(b["cells"]).ravel()).any():
            out.add(str(b["name"]))
    return out


def _upstream_end(res: Result, k: np.ndarray, x: np.ndarray, side: int = 1) -> np.ndarray:
    """The end of the joint the loads push away from (the heel of a dam): the loads on the part
    above the joint push it along ±ΣQ t (its contact forces are ±(−N n − Q t); + for a part on
    S+, − on S−), at the state of the largest |ΣQ|; the first CFE if there is no shear."""
    Q = np.asarray(res.Q, dtype=float)[:, k]
    t = np.asarray(res.cfe.get("tangent", np.tile([1.0, 0.0], (res.m, 1))), float)[k]
    if Q.size == 0:
        return x[0]
    i = int(np.argmax(np.abs(Q.sum(axis=1))))
    push = side * (Q[i] @ t)  # the loads' push along the joint
    return x[-1] if float(push @ (x[-1] - x[0])) < 0 else x[0]


def _joint_ends(res: Result, k: np.ndarray, x: np.ndarray,
                face: str = "plus") -> tuple[np.ndarray, np.ndarray]:
    """The heel and toe ends of the joint: the extreme nodes of its CFEs on ``face`` ("plus"
    or "minus") projected on the line from the first to the last CFE point (the first and last
    CFE points when the result has no node coordinates)."""
    e = x[-1] - x[0]
    size = float(np.linalg.norm(e))
    pts = np.asarray((res.geometry or {}).get("points", np.zeros((0, 2))), dtype=float)
    nodes = np.asarray(res.cfe.get(f"{face}_nodes", np.zeros((0, 0), int)))
    if size == 0 or pts.size == 0 or nodes.size == 0:
        return x[0].copy(), x[-1].copy()
    e = e / size
    nodes = nodes[k].ravel()
    nodes = nodes[(nodes >= 0) & (nodes < len(pts))]
    proj = (pts[nodes] - x[0]) @ e
    lo, hi = min(float(proj.min(initial=0.0)), 0.0), max(float(proj.max(initial=0.0)), size)
    return x[0] + lo * e, x[0] + hi * e


def _face_points(res: Result, k: np.ndarray, x: np.ndarray, face: str) -> np.ndarray:
    """(K, 2) the points where the CFEs ``k`` act on ``face``: x on S+; on S− the weighted
    mean of the S− nodes (it differs from x by an initial gap), m."""
    pts = np.asarray((res.geometry or {}).get("points", np.zeros((0, 2))), dtype=float)
    nodes = np.asarray(res.cfe.get(f"{face}_nodes", np.zeros((0, 0), int)))
    w = np.asarray(res.cfe.get(f"{face}_w", np.zeros((0, 0))), dtype=float)
    if face == "plus" or pts.size == 0 or nodes.size == 0 or w.shape != nodes.shape:
        return x
    nodes, w = nodes[k], w[k]
    ok = (nodes >= 0) & (nodes < len(pts))
    return np.einsum("kj,kjc->kc", np.where(ok, w, 0.0), pts[np.where(ok, nodes, 0)])


def _part_above(res: Result, j: int,
                side: int = 1) -> tuple[np.ndarray | None, str | None]:
    """(n_bodies,) bool: the bodies on the S+ side (``side`` −1: the S− side) of interface
    ``j`` and those joined to them by other joints or shared DOFs — the part the joint holds;
    or None and why."""
    names, body = _body_of_nodes(res)
    if not names:
        return None, "the result has no bodies with node coordinates (a discrete model)"
    iface = np.asarray(res.cfe["interface"])
    plus = np.asarray(res.cfe.get("plus_nodes", np.zeros((0, 0), int)))
    minus = np.asarray(res.cfe.get("minus_nodes", np.zeros((0, 0), int)))
    if plus.size == 0:
        return None, "the result does not store the CFEs' nodes"

    def bodies(rows) -> np.ndarray:
        n = rows[rows >= 0]
        b = body[n[n < len(body)]]
        return np.unique(b[b >= 0])

    def body_of_cfe(nodes: np.ndarray) -> np.ndarray:
        """(m,) the body of each CFE's first valid node on one face (−1: none)."""
        ok = (nodes >= 0) & (nodes < len(body))
        b = np.where(ok, body[np.where(ok, nodes, 0)], -1)
        first = np.argmax(b >= 0, axis=1)
        return b[np.arange(len(b)), first]

    nb = len(names)
    link = np.eye(nb, dtype=bool)
    if minus.size:  # the CFEs of the other joints join their bodies
        other = iface != j
        a, b = body_of_cfe(plus[other]), body_of_cfe(minus[other])
        ok = (a >= 0) & (b >= 0)
        link[a[ok], b[ok]] = link[b[ok], a[ok]] = True
    dof_of = np.asarray((res.geometry or {}).get("dof_of", np.zeros((0, 3), int)))
    if dof_of.size and len(dof_of) == len(body):  # tied nodes share DOFs
        dofs = [set(np.unique(dof_of[(body == b)][dof_of[body == b] >= 0]).tolist())
                for b in range(nb)]
        for a in range(nb):
            for b in range(a + 1, nb):
                if dofs[a] & dofs[b]:
                    link[a, b] = link[b, a] = True
    mine = iface == j
    part = np.zeros(nb, bool)
    seed, other_side = (plus, minus) if side > 0 else (minus, plus)
    part[bodies(seed[mine].ravel())] = True
    while True:  # the connected component of the S+ bodies
        grown = part | link[part].any(axis=0)
        if (grown == part).all():
            break
        part = grown
    below = bodies(other_side[mine].ravel()) if other_side.size else np.zeros(0, int)
    if below.size and part[below].any():
        return None, (f"the bodies on both sides of the joint are joined by other joints "
                      f"({', '.join(names[b] for b in below if part[b])}): the joint does not "
                      "cut off a part")
    return part, None


def _cohesion_per_cfe(res: Result, k: np.ndarray, area: np.ndarray, fric: np.ndarray,
                      states: np.ndarray, index: np.ndarray,
                      cohesion: float | None) -> tuple[np.ndarray, np.ndarray, str]:
    """(c_k A_k (n, K) in N, tan φ_k (n, K), source) of the CFEs ``k`` in the contact states
    ``states`` (n, K) of the reported states ``index`` (n,)."""
    bonded = states == int(ContactState.BONDED)
    bond = res.cfe.get("bond")
    tan = np.broadcast_to(fric, states.shape).copy()
    force = np.zeros(states.shape)
    has_bond = False
    if bond is not None:
        bond = np.asarray(bond, dtype=float)[k]
        has = np.isfinite(bond[:, _QR])
        has_bond = bool(has.any())
        alpha = np.where(has, np.nan_to_num(bond[:, _ALPHA]), fric)
        tan = np.where(bonded, alpha, tan)
        force = np.where(bonded & has, np.nan_to_num(bond[:, _QR]), 0.0)
        if bond.shape[1] > _CR:
            lost_at = np.asarray(res.cfe.get("cohesion_lost", np.full(res.m, -1)))[k]
            lost = (lost_at >= 0) & (index[:, None] >= lost_at)
            keep = ~bonded & has & ~lost
            force = force + np.where(keep, np.nan_to_num(bond[:, _CR]), 0.0)
    if cohesion is not None:
        return np.broadcast_to(cohesion * area, states.shape).copy(), tan, (
            f"design cohesion {cohesion:.6g} Pa (given)")
    if has_bond:
        return force, tan, "the joint's bond (τ_R intact; C_r broken, until it opens)"
    return force, tan, "none: the joint has no cohesion"


def _zero_to(a: np.ndarray, b: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """a / b, inf where b is 0 to round-off of ``scale`` (NaN where a is too)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        none = np.abs(b) <= 1e-12 * np.abs(scale)
        q = np.where(none, np.inf, a / np.where(none, 1.0, b))
        return np.where(none & (np.abs(a) <= 1e-12 * np.abs(scale)), np.nan, q)


@dataclass(frozen=True)
class _Joint:
    """What the factors need of one interface: its CFEs in order and its geometry."""

    k: np.ndarray
    x: np.ndarray
    area: np.ndarray
    fric: np.ndarray
    normal: np.ndarray  # (K, 2) of every CFE
    tangent: np.ndarray  # (K, 2)
    axis: np.ndarray  # (2,) the joint's normal (the mean of the CFEs'): the moment split
    heel: np.ndarray
    toe: np.ndarray
    part: np.ndarray | None
    part_note: str | None
    side: int = 1  # the part is on S+ (1) or S− (−1)
    at: np.ndarray | None = None  # (K, 2) where the CFE forces act on the part (x on S+)


def _load_weights(res: Result, part: np.ndarray, factors: np.ndarray,
                  index: np.ndarray, LM: np.ndarray) -> np.ndarray:
    """(n, P, n_bodies) the factor of every pattern's loads on every body of the part at the
    reported states ``index`` (0 on bodies not built yet).  A construction stage ramps the
    weight of its new bodies in with an automatic pattern "<stage>: loads on <bodies>" equal to
    minus their loads at its start, factor 1 → 0: its loads are counted as (1 − its factor)
    times the other patterns' loads on those bodies, so that each load keeps its own pattern
    (its direction) in the moment split."""
    names = [str(b["name"]) for b in (res.geometry or {}).get("bodies", [])]
    if res.stage is None:
        built = np.ones((len(index), len(names)), dtype=bool)
    else:  # the bodies built at each stage, at the stage of every state
        per_stage = np.array([[b in set(bs) for b in names] for bs in res.stage_bodies],
                             dtype=bool).reshape(-1, len(names))
        built = per_stage[np.asarray(res.stage, np.int64)[index]]
    w = factors[:, :, None] * (built & part)[:, None, :]
    ramps = [p for p, name in enumerate(res.pattern_names)
             if any(name.startswith(f"{st}: loads on ") for st in res.stage_names)]
    for r in ramps:
        on = np.abs(LM[r]).max(axis=1) > 0  # the bodies the ramp acts on
        w[:, :, on] *= (1.0 - factors[:, r])[:, None, None]
        w[:, r, :] = 0.0
    return w


def _load_groups(res: Result) -> np.ndarray:
    """(P, G) indicator of the loads the moment split keeps apart: every pattern on its own,
    except the virtual patterns of a water level (:mod:`stepcontact.fem.level`), which are
    pieces of one pressure — their basis functions of the level have either sign, so split one
    by one they would put parts of the water's thrust among the resisting moments."""
    virtual = {v: p for p, vs in res.level_patterns.items() for v in vs}
    keys = [virtual[n] + " (water)" if n in virtual else n for n in res.pattern_names]
    uniq = list(dict.fromkeys(keys))
    ind = np.zeros((len(keys), len(uniq)))
    ind[np.arange(len(keys)), [uniq.index(k) for k in keys]] = 1.0
    return ind


def _moments(res: Result, jt: _Joint, factors: np.ndarray, N, Q, water,
             index: np.ndarray) -> tuple:
    """ΣM_r, ΣM_o about the toe of the loads on the part above the joint (n,), N·m, and the
    imbalance of the part's moments with the joint's forces (n,), relative; or Nones and why.
    Rows of reported states ``index``: the bodies built at each (construction stages)."""
    LM = res.load_moments
    n = len(N)
    if jt.part is None:
        return None, None, None, jt.part_note
    if res.units.get("lam") == "s":  # a DynamicResult: its path axis is the time
        return None, None, None, ("a dynamic result: inertia forces act on the part, the "
                                  "moments of its loads alone do not balance the joint's")
    if LM is None:
        return None, None, None, (
            "the result does not store the loads' first moments (a discrete model, or a "
            "file written before they were stored): run the model again")
    LM = np.asarray(LM, dtype=float)
    if LM.shape[:2] != (len(res.pattern_names), len(jt.part)):
        return None, None, None, "the stored load moments do not match the result's patterns"
    on = np.einsum("npb,pbc->npc", _load_weights(res, jt.part, factors, index, LM), LM)
    on = np.einsum("npc,pg->ngc", on, _load_groups(res))
    F, S, mz = on[..., 0:2], on[..., 2:6].reshape(n, -1, 2, 2), on[..., 6]  # (n, P, ...)
    T = jt.toe
    nrm = jt.axis / np.linalg.norm(jt.axis)
    tng = np.array([-nrm[1], nrm[0]])

    def cross(a, b):
        return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]

    items = []
    for d in (nrm, tng):  # M_d = (S d) × d − (x_0 × d)(F · d) per pattern
        items.append(cross(S @ d, d) - cross(T, d) * (F @ d))
    items.append(mz)
    M = np.stack(items, axis=-1).reshape(n, -1)  # (n, P × 3): the items of every pattern
    lever = (jt.x if jt.at is None else jt.at) - T
    if water is not None:  # the crack water pushes the joint's faces apart, along ±n_k
        M = np.concatenate([M, jt.side * (water * cross(lever, jt.normal)).sum(axis=1)[:, None]],
                           axis=1)
    # the overturning sense: the one that lifts the heel off the other face (about the toe)
    sense = np.sign(cross(jt.heel - T, jt.side * nrm))
    if sense == 0:
        return None, None, None, "the joint has no length"
    M_o = np.clip(sense * M, 0.0, None).sum(axis=1)
    M_r = np.clip(-sense * M, 0.0, None).sum(axis=1)
    # the joint's contact forces on the part, ±(−N n − Q t) at x_k (+ on S+), balance the
    # loads (the crack water among them)
    pn = -N
    M_joint = jt.side * (pn * cross(lever, jt.normal) - Q * cross(lever, jt.tangent)).sum(axis=1)
    scale = M_r + M_o + np.abs(pn * cross(lever, jt.normal)).sum(axis=1) + np.abs(
        Q * cross(lever, jt.tangent)).sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        imbalance = np.where(scale > 0, np.abs(M.sum(axis=1) + M_joint) / scale, 0.0)
    return M_r, M_o, imbalance, None


def _factors(res: Result, jt: _Joint, N, Q, states, index, factors, water,
             cohesion: float | None) -> dict:
    """The engineers' factors of rows of CFE forces ``N``, ``Q`` (n, K) with their contact
    ``states``, reported-state ``index`` (n,), pattern ``factors`` (n, P) and crack ``water``
    (n, K) or None: arrays (n,)."""
    sN, sQ = N.sum(axis=1), Q.sum(axis=1)
    comp = (N < 0) & (states != int(ContactState.OPEN))  # (an open CFE's N is 0 to round-off)
    A_c = comp @ jt.area if N.size else np.zeros(len(N))
    L = float(np.linalg.norm(jt.toe - jt.heel))
    c_force, tan, source = _cohesion_per_cfe(res, jt.k, jt.area, jt.fric, states, index,
                                             cohesion)
    cA = np.where(comp, c_force, 0.0).sum(axis=1)
    resist = cA - (tan * N).sum(axis=1)
    sff = _zero_to(resist, np.abs(sQ), np.abs(sN) + cA)
    # the joint's own cohesion (the design cohesion aside): when it slides
    own = cA if cohesion is None else np.where(
        comp, _cohesion_per_cfe(res, jt.k, jt.area, jt.fric, states, index, None)[0],
        0.0).sum(axis=1)
    sff_own = _zero_to(own - (tan * N).sum(axis=1), np.abs(sQ), np.abs(sN) + own)
    u = (jt.heel - jt.toe) / L if L > 0 else np.zeros(2)
    with np.errstate(divide="ignore", invalid="ignore"):
        point = np.where((sN != 0)[:, None], (N @ jt.x) / sN[:, None], np.nan)
    from_toe = (point - jt.toe) @ u
    M_r, M_o, imbalance, note = _moments(res, jt, factors, N, Q, water, index)
    if M_r is None:
        over = np.full(len(N), np.nan)
        M_r = M_o = over
    else:
        bad = ~(imbalance <= MOMENT_RTOL)
        over = _zero_to(M_r, M_o, M_r + M_o)
        over = np.where(bad, np.nan, over)
        M_r, M_o = np.where(bad, np.nan, M_r), np.where(bad, np.nan, M_o)
        if bad.any():
            worst = int(np.argmax(np.where(bad, np.nan_to_num(imbalance, nan=np.inf), -1.0)))
            note = (f"the loads on the part above the joint are not held by the joint alone "
                    f"(a support, spring or other joint on it, or loads that change with the "
                    f"state): their moment about the toe and the joint's differ by "
                    f"{imbalance[worst]:.1e} (relative) at {int(bad.sum())} state(s)")
    return {"compressed_area": A_c, "compressed_length": L * A_c / jt.area.sum()
            if jt.area.sum() > 0 else 0.0 * sN, "cohesion_force": cA,
            "shear_friction_factor": sff, "own_sff": sff_own, "resisting_moment": M_r,
            "overturning_moment": M_o, "overturning_factor": over, "note": note,
            "from_toe": from_toe, "from_heel": L - from_toe, "cohesion_source": source,
            "normal_force": sN, "shear_force": sQ, "joint_length": L,
            "friction_only": _zero_to(-(jt.fric * N).sum(axis=1), np.abs(sQ), np.abs(sN))}


def _design_row(res: Result, pattern: str | None, design: float, is_level: bool):
    """(state index, t, b) of the design state: the state at λ_d, or the fraction t between
    states index and b of a linear segment of ``pattern``; or (None, note)."""
    seg_of = np.asarray(res.segment)
    lam = np.asarray(res.lam, dtype=float)
    tol = 1e-12 * max(1.0, abs(design))
    segs = [s for s, (p, _, _) in enumerate(res.segments) if p == pattern]
    what = f"level {design:g} m" if is_level else f"λ_d = {design:g}"
    for s in segs:
        idx = np.flatnonzero(seg_of == s)
        at = idx[np.abs(lam[idx] - design) <= tol]
        if at.size:
            return (int(at[0]), 0.0, int(at[0])), None
        if idx.size < 2 or not lam[idx].min() - tol <= design <= lam[idx].max() + tol:
            continue
        if is_level:
            return None, (f"no state recorded at the design {what} (segment {s} moves the water "
                          f"level of '{pattern}': its states are not linear in the level "
                          f"between events): end a segment at {design:g} m to have it")
        for a, b in zip(idx[:-1], idx[1:], strict=True):
            if min(lam[a], lam[b]) - tol <= design <= max(lam[a], lam[b]) + tol:
                t = 0.0 if lam[b] == lam[a] else (design - lam[a]) / (lam[b] - lam[a])
                return (int(a), float(t), int(b)), None
    return None, f"the path does not reach the design {what} of '{pattern}'"


def _design_state(res, jt, design, pattern, is_level, cohesion, N, Q, water, info) -> dict:
    """The design state's values (plain numbers; None where not computable)."""
    out: dict[str, object] = {"design": design, "pattern": pattern,
                              "parameter": "water level (m)" if is_level else "time (s)"
                              if res.units.get("lam") == "s" else "load factor"}
    row, why = _design_row(res, pattern, design, is_level)
    if row is None:
        return out | {"state": None, "notes": [why]}
    a, t, b = row
    f = np.asarray(res.factors, dtype=float)

    def mix(arr):
        return None if arr is None else ((1 - t) * arr[a] + t * arr[b])[None]

    st = np.asarray(res.state)[a][jt.k][None]
    vals = _factors(res, jt, mix(N), mix(Q), st, np.array([a]), mix(f), mix(water), cohesion)

    def num(key):
        v = float(np.asarray(vals[key]).ravel()[0])
        return v if np.isfinite(v) else None

    L = vals["joint_length"]
    from_toe = num("from_toe")
    ecc = None if from_toe is None else (L - from_toe) - L / 2
    cA, A_c = num("cohesion_force"), num("compressed_area")
    notes = []
    for key, name in (("shear_friction_factor", "shear-friction"),
                      ("friction_only", "friction-only")):
        v = float(np.asarray(vals[key]).ravel()[0])
        if np.isinf(v):
            notes.append(f"the {name} factor is infinite: no shear on the joint")
        elif np.isnan(v):
            notes.append(f"the {name} factor is undefined: no force on the joint")
    ov = float(vals["overturning_factor"][0])
    if vals["note"] and np.isnan(ov):
        notes.append(f"overturning factor: {vals['note']}")
    elif np.isinf(ov):
        notes.append("the overturning factor is infinite: no overturning moment")
    elif np.isnan(ov):
        notes.append("the overturning factor is undefined: no moment about the toe")
    if from_toe is None:
        notes.append("no normal force on the joint: no resultant position")
    return out | {
        "state": None if t else a, "interpolated": bool(t),
        "between_states": [a, b] if t else None,
        "lam": float(res.lam[a] + t * (res.lam[b] - res.lam[a])),
        "normal_force": num("normal_force"), "shear_force": num("shear_force"),
        "compressed_length": num("compressed_length"), "compressed_area": A_c,
        "joint_length": L, "cohesion_force": cA,
        "cohesion": None if not A_c else cA / A_c,
        "cohesion_source": vals["cohesion_source"],
        "shear_friction_factor": num("shear_friction_factor"),
        "friction_only_factor": num("friction_only"),
        "overturning_factor": num("overturning_factor"),
        "resisting_moment": num("resisting_moment"),
        "overturning_moment": num("overturning_moment"),
        "resultant_from_toe": from_toe, "resultant_from_heel": num("from_heel"),
        "eccentricity": ecc, "e_over_B": None if ecc is None or L == 0 else ecc / L,
        "in_middle_third": None if ecc is None else bool(abs(ecc) <= L / 6 + 1e-12 * L),
        "notes": notes,
    }


def _held_part(res: Result, j: int, k: np.ndarray, x: np.ndarray,
               water: np.ndarray | None, cohesion: float | None,
               sides=(1, -1)) -> tuple[_Joint, dict]:
    """The joint ``j`` (its CFEs ``k`` in order, at ``x``) and its factors along the path
    (:func:`_factors`), for the part it holds: the bodies on its S+ side, else on its S− side
    (the side whose loads the joint's forces balance alone; the S+ side's reason if none)."""
    normals = np.asarray(res.cfe.get("normal", np.tile([0.0, 1.0], (res.m, 1))), float)[k]
    tangents = np.asarray(res.cfe.get("tangent", np.tile([1.0, 0.0], (res.m, 1))), float)[k]
    area = np.asarray(res.cfe["area"], dtype=float)[k]
    fric = np.asarray(res.cfe["friction"], dtype=float)[k]
    N = np.asarray(res.N, dtype=float)[:, k]
    Q = np.asarray(res.Q, dtype=float)[:, k]
    states = np.asarray(res.state)[:, k]
    factors = np.asarray(res.factors, dtype=float)
    index = np.arange(len(N))
    wk = None if water is None else water[:, k]
    first = None
    for side in sides:
        face = "plus" if side > 0 else "minus"
        j_heel, j_toe = _joint_ends(res, k, x, face)
        part, part_note = _part_above(res, j, side)
        jt = _Joint(k=k, x=x, area=area, fric=fric, normal=normals, tangent=tangents,
                    axis=normals.mean(axis=0), heel=j_heel, toe=j_toe, part=part,
                    part_note=part_note, side=side, at=_face_points(res, k, x, face))
        vals = _factors(res, jt, N, Q, states, index, factors, wk, cohesion)
        if first is None:
            first = (jt, vals)
        if vals["note"] is None:
            return jt, vals
    return first


def interface_safety(res: Result, interface: str, design: float | None = None,
                     heel=None, *, cohesion: float | None = None,
                     pattern: str | None = None) -> InterfaceSafety:
    """The :class:`InterfaceSafety` of ``interface`` along the path of ``res``.

    Parameters
    ----------
    res : StaticResult
    interface : str
        Interface name.
    design : float, optional
        Design value λ_d of the parameter (the factor of ``pattern``: a load factor, or a
        water level in m): the design state's factors, and the load margins λ_limit / λ_d.
    heel : (x, y) or "auto", optional
        A point near the heel: the end of the joint nearest to it is the heel; "auto": the end
        the loads push away from (along the joint's shear at the state of the largest |ΣQ|).
        Default: the first CFE along the interface.
    cohesion : float, optional
        Design cohesion c, Pa, on every compressed CFE: replaces the joint's own (its bond's
        τ_R or residual C_r) in the shear-friction factor.
    pattern : str, optional
        The load pattern whose factor is the parameter (default: the last segment's).
    """
    names = list(res.interface_names)
    if interface not in names:
        raise KeyError(f"no interface '{interface}' (interfaces: "
                       f"{', '.join(map(repr, names)) or 'none'})")
    if design is not None and not (np.isfinite(design) and design != 0):
        raise ValueError(f"design={design}: give a finite, non-zero design load factor")
    if cohesion is not None and not (np.isfinite(cohesion) and cohesion >= 0):
        raise ValueError(f"cohesion={cohesion}: give a finite cohesion ≥ 0 Pa")
    if pattern is None and res.segments:
        pattern = res.segments[int(res.segment[-1]) if len(res.segment) else -1][0]
    elif pattern is not None and pattern not in res.pattern_names:
        raise KeyError(f"no load pattern '{pattern}' (patterns: "
                       f"{', '.join(map(repr, res.pattern_names)) or 'none'})")
    is_level = pattern in res.level_patterns
    j = names.index(interface)
    iface = np.asarray(res.cfe["interface"])
    k = np.flatnonzero(iface == j)
    if k.size == 0:
        raise ValueError(f"interface '{interface}' has no CFE")
    s = np.asarray(res.cfe["s"], dtype=float)[k]
    k, s = k[np.argsort(s, kind="stable")], np.sort(s)
    x = np.asarray(res.cfe["x"], dtype=float).reshape(-1, 2)[k]
    water = None if res.water is None else np.asarray(res.water, dtype=float)
    jt, vals = _held_part(res, j, k, x, water, cohesion)
    if isinstance(heel, str):
        if heel != "auto":
            raise ValueError(f"heel={heel!r}: give a point (x, y) or 'auto'")
        heel = _upstream_end(res, k, x, jt.side)
    if heel is not None:
        h = np.asarray(heel, dtype=float)
        if np.linalg.norm(x[-1] - h) < np.linalg.norm(x[0] - h):
            k, s, x = k[::-1], s[::-1], x[::-1]
    pos = np.abs(s - s[0])
    length = float(pos.max())
    area = np.asarray(res.cfe["area"], dtype=float)[k]
    fric = np.asarray(res.cfe["friction"], dtype=float)[k]
    N = np.asarray(res.N, dtype=float)[:, k]
    Q = np.asarray(res.Q, dtype=float)[:, k]
    sN, sQ = N.sum(axis=1), Q.sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        loaded = sN != 0
        position = np.where(loaded, (N @ pos) / sN, np.nan)
        point = np.where(loaded[:, None], (N @ x) / sN[:, None], np.nan)
        capacity = -(N @ fric)
        no_shear = np.abs(sQ) <= 1e-12 * np.abs(sN)  # round-off of a zero shear
        sliding = np.where(no_shear, np.inf, capacity / np.where(no_shear, 1.0, np.abs(sQ)))
    ecc = position - 0.5 * length
    tol = 1e-12 * max(length, 1.0)
    in_kern = np.abs(np.nan_to_num(ecc, nan=np.inf)) <= length / 6.0 + tol
    is_open = np.asarray(res.state)[:, k] == int(ContactState.OPEN)
    open_length = length * (is_open @ area) / area.sum() if area.sum() > 0 else 0.0 * sN
    lam = np.asarray(res.lam, dtype=float)

    if jt.k[0] != k[0]:  # the heel chosen at the other end: the factors in this order
        jt, vals = _held_part(res, j, k, x, water, cohesion, sides=(jt.side,))
    water = None if water is None else water[:, k]

    lam_sliding = lam_overturning = None
    mechanism = None
    seg_pattern = [res.segments[g][0] if 0 <= g < len(res.segments) else None
                   for g in np.asarray(res.segment, dtype=np.int64).tolist()]
    found: dict[str, str | None] = {}  # the pattern whose λ each limit is
    mech = res.mechanism if res.status == Status.EQUILIBRIUM_LOST else None
    if mech:
        moving = {str(b["body"]): str(b["mode"]) for b in mech.get("bodies", [])}
        sides = [{moving.get(b) for b in _bodies_of_nodes(res, np.asarray(res.cfe[key])[k])}
                 for key in ("plus_nodes", "minus_nodes") if key in res.cfe]
        # the mechanism slips or opens this joint when its two faces do not move alike (a
        # lift joint inside a dam that slides as one body is not where it slides)
        modes = sorted(m for m in set().union(*sides) if m) if sides else []
        if len(sides) == 2 and sides[0] == sides[1]:
            modes = []
        if modes:
            mechanism = modes[0]
            kind = ("sliding" if mechanism == "sliding" else "overturning"
                    if mechanism.startswith("rotation") else None)
            if kind == "sliding":
                lam_sliding = float(mech["lam"])
            elif kind == "overturning":
                lam_overturning = float(mech["lam"])
            if kind:
                found[kind] = seg_pattern[-1]
    # a joint that carries a normal force (not the round-off of a joint just made)
    pressed = sN < -1e-9 * float(np.abs(sN).max(initial=0.0))
    if lam_sliding is None:  # every CFE in contact slips: the joint's own shear friction = 1
        hit = np.flatnonzero(pressed & (vals["own_sff"] <= 1.0 + SLIDING_RTOL))
        lam_sliding = float(lam[hit[0]]) if hit.size else None
        found["sliding"] = seg_pattern[hit[0]] if hit.size else None
    if lam_overturning is None and length > 0:
        hit = np.flatnonzero(pressed & (np.abs(np.nan_to_num(ecc)) >= 0.5 * length - tol))
        lam_overturning = float(lam[hit[0]]) if hit.size else None
        found["overturning"] = seg_pattern[hit[0]] if hit.size else None
    design_state = {} if design is None else _design_state(
        res, jt, float(design), pattern, is_level, cohesion, N, Q, water,
        vals)
    return InterfaceSafety(
        interface=interface, lam=lam, segment=np.asarray(res.segment, dtype=np.int64),
        normal_force=sN, shear_force=sQ, position=position, point=point, eccentricity=ecc,
        in_kern=in_kern, sigma_heel=N[:, 0] / area[0], sigma_toe=N[:, -1] / area[-1],
        sliding_factor=sliding, open_length=np.asarray(open_length, dtype=float),
        length=length, heel=x[0].copy(), toe=x[-1].copy(), friction=float(fric.max()),
        design=None if design is None else float(design), lam_sliding=lam_sliding,
        lam_overturning=lam_overturning, mechanism=mechanism,
        compressed_area=vals["compressed_area"], compressed_length=vals["compressed_length"],
        cohesion_force=vals["cohesion_force"],
        shear_friction_factor=vals["shear_friction_factor"],
        resisting_moment=vals["resisting_moment"],
        overturning_moment=vals["overturning_moment"],
        overturning_factor=vals["overturning_factor"], overturning_note=vals["note"],
        from_toe=vals["from_toe"], from_heel=vals["from_heel"],
        joint_length=vals["joint_length"], joint_heel=jt.heel, joint_toe=jt.toe,
        cohesion=None if cohesion is None else float(cohesion),
        cohesion_source=vals["cohesion_source"], pattern=pattern, is_level=is_level,
        design_state=design_state, limit_patterns=found, joint_area=float(area.sum()),
    )


__all__ = ["InterfaceSafety", "interface_safety"]
