"""An independent reference for the faceted Coulomb cone (pure NumPy; no stepcontact import).

The problem
-----------
A point on a rough rigid plane, pressed with a constant normal force N (|N| below), is held by
an isotropic tangential spring k_s (N/m) to a driver point d(t) that follows a prescribed path
in the plane.  x is the point's position (its slip), e = d − x the spring's stretch and
Q = k_s e the tangential force the plane resists.  The friction limit is the regular k-gon P
with its vertices on the circle of radius f|N| (the inner polygon of the disc, as in
``stepcontact.contact.faceted``):

* vertex i at angle α + 2πi/k (α = ``angle``), on the circle of radius f|N|;
* facet i between vertices i and i + 1, outward normal n_i at α + (2i + 1)π/k, at the
  distance h = f|N| cos(π/k) (the apothem) from the centre, half-length f|N| sin(π/k).

Quasi-static Coulomb friction with associated flow: Q ∈ P, and the slip rate ẋ lies in the
normal cone of P at Q (zero inside: stick; along n_i on facet i; in the cone between n_(i−1)
and n_i at vertex i).  With Q = k_s (d − x) this is Moreau's sweeping process of e = Q / k_s
in P / k_s.  The dissipated energy is ∫ Q · dx.

Integration (:func:`return_mapping`): per step, the trial force Q_tr = k_s (d_(j+1) − x_j)
is projected on P (closest point: the facet of Q_tr's angular sector, clamped to its two
vertices) and the slip increment is Δx = (Q_tr − Q) / k_s (backward Euler, the "return
mapping" of elastoplasticity).  For a straight driver increment it is exact while Q stays on
one facet, comes to rest at a vertex, or starts slipping on a facet (a half-plane or a fixed
point); it errs, by O(step), in the steps in which Q passes a vertex from one facet onto the
next (measured: 0.17 Δβ f|N| on a circular driver).  The dissipation increment
Q_(j+1) · Δx is exact where the step is (Q · n_i = h on facet i).

:func:`sweep` solves the same problem exactly (to round-off) for a piecewise-linear driver,
event by event inside each step: the reference for a model whose load program prescribes
the driver linearly per segment.

The state codes mirror ``stepcontact.enums`` (copied, not imported, to stay independent):
``STICK`` = 1, slip on facet i ``FACET_SLIP + i`` = 16 + i, slip at vertex i
``VERTEX_SLIP + i`` = 144 + i.

Closed forms (derivations in the docstrings):

* :func:`slip_limit` — the force |P| at which a load in direction θ starts slipping:
  |P| = f|N| cos(π/k) / cos(θ − θ_f), θ_f the **nearest facet normal** (|θ − θ_f| ≤ π/k); in
  terms of the nearest vertex θ_v, |P| = f|N| cos(π/k) / cos(π/k − |θ − θ_v|).  (The issue's
  text writes cos(θ − θ_v) with θ_v the nearest vertex: that would give f|N| cos(π/k) for a
  load on a vertex, while the vertex lies on the circle, |P| = f|N|.)
* :func:`straight_push` — a driver pushed along a straight line from rest: the slip path,
  the force path and the dissipation; in the end Q sits at the vertex nearest θ and the
  dissipation per unit slip is f|N| cos(θ − θ_v).
* :func:`circle_orbit` — the driver on a circle of radius R at constant speed: the
  steady-state orbit and the dissipation per revolution, with a = f|N| / k_s:
  W_rev = 2 k f|N| sin(π/k) (R − a sin(π/k)) for R ≥ a / sin(π/k) (Q rests at each vertex)
  and W_rev = k f|N| sin(2π/k) √(R² − a²) for a / cos(π/k) ≤ R ≤ a / sin(π/k) (Q never
  rests); the circle's 2π f|N| √(R² − a²) as k → ∞.
* :func:`hysteresis_dissipation` — a driver moving back and forth (amplitude A) along a line
  oblique to the facets: the stick–slip loop's dissipation per cycle, exact finite sums along
  the polygon; for even k with δ = θ − θ_v (|δ| < π/k)
  W = 4 f|N| A cos δ − 2 k_s (2a cos δ t_H − t_H²/2 + c²/2),
  t_H = 2a cos(π/k) / cos(π/k − |δ|), c = 2a [sin(π/k) − cos(π/k) tan(π/k − |δ|)]; the
  circle's 4 f|N| (A − a) as k → ∞.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

#: state codes, the values of stepcontact.enums (ContactState.STICK, FACET_SLIP, VERTEX_SLIP)
STICK, FACET_SLIP, VERTEX_SLIP = 1, 16, 144


# ---- the polygon ------------------------------------------------------------------------------
def vertices(fN: float, k: int, angle: float = 0.0) -> np.ndarray:
    """(k, 2): vertex i at angle α + 2πi/k on the circle of radius f|N|."""
    a = angle + 2.0 * np.pi * np.arange(k) / k
    return fN * np.column_stack([np.cos(a), np.sin(a)])


def facet_normal_angles(k: int, angle: float = 0.0) -> np.ndarray:
    """(k,): the angle α + (2i + 1)π/k of facet i's outward normal (its slip direction)."""
    return angle + (2.0 * np.arange(k) + 1.0) * np.pi / k


def project(q, fN: float, k: int, angle: float = 0.0) -> tuple[np.ndarray, int]:
    """The closest point of the polygon to the force q (2,) and its state code.

    q·n_i is largest for the facet i whose normal is nearest q's direction, i.e. the sector
    between vertices i and i + 1 that contains q.  Inside (q·n_i ≤ h): q itself, STICK.
    Outside, the closest point lies on that facet clamped to its vertices (a point in the
    normal cone of vertex i + 1 has its largest q·n on facet i or i + 1, both clamp to it)."""
    p, c = _project(float(q[0]), float(q[1]), fN, k, angle)
    return np.array(p), c


def _project(q0: float, q1: float, fN: float, k: int, angle: float):
    i = int(math.floor((math.atan2(q1, q0) - angle) * k / (2.0 * math.pi))) % k
    th = angle + (2 * i + 1) * math.pi / k
    cn, sn = math.cos(th), math.sin(th)
    h, half = fN * math.cos(math.pi / k), fN * math.sin(math.pi / k)
    if q0 * cn + q1 * sn <= h:
        return (q0, q1), STICK
    t = -q0 * sn + q1 * cn  # along τ_i = (−sin θ, cos θ), from vertex i to vertex i + 1
    if t >= half:
        j = (i + 1) % k
        a = angle + 2.0 * math.pi * j / k
        return (fN * math.cos(a), fN * math.sin(a)), VERTEX_SLIP + j
    if t <= -half:
        a = angle + 2.0 * math.pi * i / k
        return (fN * math.cos(a), fN * math.sin(a)), VERTEX_SLIP + i
    return (h * cn - t * sn, h * sn + t * cn), FACET_SLIP + i


# ---- the return mapping -----------------------------------------------------------------------
@dataclass
class Path:
    """A quasi-static path: per driver position j, the point's position x (slip), the force
    Q = k_s (d − x), the dissipated energy W = ∫ Q · dx so far (J) and the state code."""

    d: np.ndarray  # (n + 1, 2) driver, m
    x: np.ndarray  # (n + 1, 2) point (its slip from the start), m
    Q: np.ndarray  # (n + 1, 2) tangential force, N
    W: np.ndarray  # (n + 1,) dissipation, J
    code: np.ndarray  # (n + 1,) state codes
    events: list = field(default_factory=list)  # (position in steps, old code, new code)

    @property
    def slip_length(self) -> np.ndarray:
        """(n + 1,) the length of the slip path ∫ |dx| so far, m."""
        return np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(self.x, axis=0), axis=1))]

    @property
    def driver_work(self) -> np.ndarray:
        """(n + 1,) ∫ Q · dd so far by the trapezoidal rule, J."""
        dW = 0.5 * np.einsum("ij,ij->i", self.Q[1:] + self.Q[:-1], np.diff(self.d, axis=0))
        return np.r_[0.0, np.cumsum(dW)]


def return_mapping(d, k_s: float, fN: float, k: int, angle: float = 0.0,
                   x0=None) -> Path:
    """Integrate the point's path for the driver positions d (n + 1, 2) by the return mapping
    (module docstring); x0: the point's start (default d[0]: no force)."""
    d = np.asarray(d, dtype=float)
    n = len(d) - 1
    X, Q, W = np.zeros((n + 1, 2)), np.zeros((n + 1, 2)), np.zeros(n + 1)
    code = np.zeros(n + 1, dtype=np.int64)
    x0_, x1_ = (float(d[0, 0]), float(d[0, 1])) if x0 is None else (float(x0[0]), float(x0[1]))
    (q0, q1), c = _project(k_s * (d[0, 0] - x0_), k_s * (d[0, 1] - x1_), fN, k, angle)
    if c != STICK:
        raise ValueError("the start is outside the friction polygon")
    X[0], Q[0], code[0] = (x0_, x1_), (q0, q1), c
    w = 0.0
    dl = d.tolist()
    for j in range(1, n + 1):
        t0, t1 = k_s * (dl[j][0] - x0_), k_s * (dl[j][1] - x1_)
        (q0, q1), c = _project(t0, t1, fN, k, angle)
        dx0, dx1 = (t0 - q0) / k_s, (t1 - q1) / k_s
        w += q0 * dx0 + q1 * dx1
        x0_ += dx0
        x1_ += dx1
        X[j] = (x0_, x1_)
        Q[j] = (q0, q1)
        W[j] = w
        code[j] = c
    return Path(d, X, Q, W, code)


def sweep(d, k_s: float, fN: float, k: int, angle: float = 0.0, x0=None) -> Path:
    """The exact path for a driver moving along straight lines between the positions d
    (n + 1, 2) (a piecewise-linear driver, as the load program of a model prescribes it):
    Moreau's sweeping process solved event by event inside each step.

    Per step the force moves with the rate v = k_s Δd (per unit of the step) projected on the
    tangent cone of the polygon at Q: inside, straight along v until a facet is hit; on facet
    i with v · n_i ≥ 0, along the facet at (v · τ_i) τ_i with the slip rate (v · n_i) n_i / k_s
    until a vertex; at vertex j, resting (slip v / k_s) while v lies in its normal cone
    cone(n_(j−1), n_j), else sliding onto the facet whose region holds v, or moving inside.
    Every piece is linear, so the result is exact to round-off; Q is kept exactly on its
    facet or vertex.  Same output as :func:`return_mapping`, and the events: ``path.events``,
    a list of (position, old code, new code), the position in steps (step j − 1 + the
    fraction of step j at which the state changed: with one step per leg of the driver, the
    load factor within the leg).  A state of no duration is no event of its own: a vertex
    passed from one facet onto the next is one event, facet i → facet i + 1."""
    d = np.asarray(d, dtype=float)
    n = len(d) - 1
    th = facet_normal_angles(k, angle)
    nrm = np.column_stack([np.cos(th), np.sin(th)])
    tau = np.column_stack([-nrm[:, 1], nrm[:, 0]])
    Vx = vertices(fN, k, angle)
    h, half = fN * math.cos(math.pi / k), fN * math.sin(math.pi / k)
    tol = 1e-13 * max(fN, 1e-300)
    x = np.array(d[0] if x0 is None else x0, dtype=float)
    q = k_s * (d[0] - x)
    if np.any(nrm @ q > h + tol):
        raise ValueError("the start is outside the friction polygon")
    X, Q, W = np.zeros((n + 1, 2)), np.zeros((n + 1, 2)), np.zeros(n + 1)
    code = np.zeros(n + 1, dtype=np.int64)
    X[0], Q[0], code[0] = x, q, STICK
    where, idx, w = "in", -1, 0.0  # location of Q: "in", ("facet", i), ("vertex", j)
    events: list[tuple[float, int, int]] = []

    def code_of(wh: str, i: int) -> int:
        return STICK if wh == "in" else FACET_SLIP + i if wh == "facet" else VERTEX_SLIP + i

    def go(wh: str, i: int) -> tuple[str, int]:
        old, new = code_of(where, idx), code_of(wh, i)
        at = step - 1 + 1.0 - rem
        if events and events[-1][0] == at:  # a state of no duration (a vertex passed)
            old = events.pop()[1]
        if new != old:
            events.append((at, old, new))
        return wh, i

    for step in range(1, n + 1):
        v = k_s * (d[step] - d[step - 1])
        rem = 1.0
        for _ in range(4 * k + 8):
            if rem <= 0.0:
                break
            if where == "vertex":
                j, i0 = idx, (idx - 1) % k
                if v @ nrm[j] >= 0.0 and v @ tau[j] > 0.0:
                    where, idx = go("facet", j)
                elif v @ nrm[i0] >= 0.0 and v @ tau[i0] < 0.0:
                    where, idx = go("facet", i0)
                elif v @ nrm[i0] <= 0.0 and v @ nrm[j] <= 0.0:
                    where, idx = go("in", -1)
                else:  # v in the normal cone: rest, the point follows the driver
                    x = x + rem * v / k_s
                    w += rem * float(Vx[j] @ v) / k_s
                    rem = 0.0
                    break
            if where == "facet":
                i = idx
                vn, vt = float(v @ nrm[i]), float(v @ tau[i])
                if vn < 0.0:
                    where, idx = go("in", -1)
                else:
                    c = float(q @ tau[i])
                    to = (half - c) / vt if vt > 0 else (-half - c) / vt if vt < 0 else np.inf
                    reached = to <= rem
                    dt = max(to, 0.0) if reached else rem
                    x = x + dt * vn / k_s * nrm[i]
                    w += dt * h * vn / k_s
                    rem -= dt
                    if reached:
                        where, idx = go("vertex", (i + 1) % k if vt > 0 else i)
                        q = Vx[idx].copy()
                    else:
                        q = h * nrm[i] + (c + dt * vt) * tau[i]
                    continue
            if where == "in":
                vn = nrm @ v
                gap = h - nrm @ q
                with np.errstate(divide="ignore", invalid="ignore"):
                    t = np.where(vn > 0.0, np.maximum(gap, 0.0) / vn, np.inf)
                j = int(np.argmin(t))
                dt = min(rem, float(t[j]))
                q = q + dt * v
                rem -= dt
                if float(t[j]) <= dt + 1e-15:  # on facet j (or at one of its ends)
                    c = float(q @ tau[j])
                    if c >= half - tol:
                        (where, idx), q = go("vertex", (j + 1) % k), Vx[(j + 1) % k].copy()
                    elif c <= -half + tol:
                        (where, idx), q = go("vertex", j), Vx[j].copy()
                    else:
                        (where, idx), q = go("facet", j), h * nrm[j] + c * tau[j]
        else:
            raise AssertionError("sweep: too many pieces in one step")
        X[step], Q[step], W[step] = x, q, w
        code[step] = code_of(where, idx)
    return Path(d, X, Q, W, code, events)


# ---- closed forms -----------------------------------------------------------------------------
def nearest_facet_normal(theta, k: int, angle: float = 0.0):
    """θ_f, the facet normal nearest the direction θ (rad): |θ − θ_f| ≤ π/k."""
    theta = np.asarray(theta, dtype=float)
    step = 2.0 * np.pi / k
    first = angle + np.pi / k
    return first + step * np.round((theta - first) / step)


def slip_limit(fN: float, k: int, theta, angle: float = 0.0):
    """The load |P| in direction θ at which slip starts (from stick at Q = 0).

    The ray Q = |P| e_θ leaves the polygon through the facet whose normal θ_f is nearest θ
    (facet i spans the directions between its vertices, θ_f ± π/k), at the distance
    h / cos(θ − θ_f) with h = f|N| cos(π/k):  |P| = f|N| cos(π/k) / cos(θ − θ_f).  A load on a
    vertex (|θ − θ_f| = π/k) gives f|N|.  Under a prescribed force the point then slips (no
    bounded equilibrium) in the direction θ_f (the facet's normal): direction error
    |θ − θ_f| ≤ π/k, limit error f|N| − |P| ≤ f|N| (1 − cos(π/k))."""
    delta = np.asarray(theta, dtype=float) - nearest_facet_normal(theta, k, angle)
    return fN * np.cos(np.pi / k) / np.cos(delta)


def ray_exit(fN: float, k: int, theta: float, angle: float = 0.0) -> float:
    """|P| where the ray from 0 in direction θ crosses the polygon's boundary, from the
    vertices (segment intersections): an independent check of :func:`slip_limit`."""
    V = vertices(fN, k, angle)
    u = np.array([math.cos(theta), math.sin(theta)])
    best = np.inf
    for i in range(k):
        a, b = V[i], V[(i + 1) % k]
        # s u = a + t (b − a), 0 ≤ t ≤ 1, s > 0
        M = np.column_stack([u, a - b])
        if abs(np.linalg.det(M)) < 1e-300:
            continue
        s, t = np.linalg.solve(M, a)
        if s > 0 and -1e-12 <= t <= 1 + 1e-12:
            best = min(best, s)
    return float(best)


@dataclass
class Push:
    """The closed form of a straight push from rest (:func:`straight_push`)."""

    s0: float  # driver travel at the first slip, m
    s1: float  # driver travel when Q reaches the vertex, m
    n_f: np.ndarray  # (2,) facet normal: the slip direction of the facet phase
    vertex: np.ndarray  # (2,) the final force, N (|vertex| = f|N|)
    x: np.ndarray  # (n, 2) the point's slip at the requested s, m
    Q: np.ndarray  # (n, 2) the force, N
    W: np.ndarray  # (n,) the dissipation, J
    dissipation_per_slip: float  # dW/d|x| in the final phase, N


def straight_push(fN: float, k: int, k_s: float, theta: float, s, angle: float = 0.0) -> Push:
    """A driver pushed from rest along u = e_θ: d = s u, s ≥ 0 (the point starts at 0, Q = 0).

    With φ = θ − θ_f (θ_f the nearest facet normal, n_f, τ_f = n_f turned by +90°,
    u = cos φ n_f + sin φ τ_f) and h = f|N| cos(π/k):

    * stick, s ≤ s0 = |P_lim| / k_s (:func:`slip_limit`): Q = k_s s u, x = 0;
    * facet phase, s0 ≤ s ≤ s1: Q = h n_f + c τ_f on the facet; the slip rate is λ n_f
      with λ = u · n_f = cos φ (Q · n_f stays h), so dc/ds = k_s sin φ:
      c = h tan φ + k_s sin φ (s − s0), x = cos φ (s − s0) n_f, W = h cos φ (s − s0);
    * c reaches the vertex c_v = sign(φ) f|N| sin(π/k) at
      s1 = s0 + (f|N| sin(π/k) − h |tan φ|) / (k_s |sin φ|) (s1 = ∞ for φ = 0: Q stays at
      the facet's middle);
    * vertex phase, s ≥ s1: Q = V (|V| = f|N|) and u lies in V's normal cone, so the point
      follows the driver, x = x(s1) + (s − s1) u, W = W(s1) + (V · u)(s − s1) with
      V · u = f|N| cos(π/k − |φ|) = f|N| cos(θ − θ_v) (θ_v the nearest vertex): the
      dissipation per unit slip, → f|N| as k → ∞ (relative error ≤ 1 − cos(π/k))."""
    s = np.atleast_1d(np.asarray(s, dtype=float))
    th_f = float(nearest_facet_normal(theta, k, angle))
    phi = theta - th_f
    n_f = np.array([math.cos(th_f), math.sin(th_f)])
    t_f = np.array([-n_f[1], n_f[0]])
    u = np.array([math.cos(theta), math.sin(theta)])
    h, half = fN * math.cos(math.pi / k), fN * math.sin(math.pi / k)
    s0 = float(slip_limit(fN, k, theta, angle)) / k_s
    sphi = math.sin(phi)
    if abs(sphi) < 1e-15:
        s1, c_v = math.inf, 0.0
    else:
        s1 = s0 + max(half - h * abs(math.tan(phi)), 0.0) / (k_s * abs(sphi))
        c_v = math.copysign(half, phi)
    V = h * n_f + c_v * t_f
    x, Q, W = np.zeros((s.size, 2)), np.zeros((s.size, 2)), np.zeros(s.size)
    stick = s <= s0
    Q[stick] = k_s * s[stick, None] * u
    fac = (s > s0) & (s <= s1)
    c = h * math.tan(phi) + k_s * sphi * (s[fac] - s0)
    Q[fac] = h * n_f + c[:, None] * t_f
    x[fac] = (math.cos(phi) * (s[fac] - s0))[:, None] * n_f
    W[fac] = h * math.cos(phi) * (s[fac] - s0)
    ver = s > s1
    if ver.any():
        x1 = math.cos(phi) * (s1 - s0) * n_f
        W1 = h * math.cos(phi) * (s1 - s0)
        Q[ver] = V
        x[ver] = x1 + (s[ver] - s1)[:, None] * u
        W[ver] = W1 + float(V @ u) * (s[ver] - s1)
    per_slip = float(V @ u) if math.isfinite(s1) else h
    return Push(s0, s1, n_f, V, x, Q, W, per_slip)


@dataclass
class Orbit:
    """The steady state of a driver on a circle (:func:`circle_orbit`)."""

    regime: str  # "dwell" (Q rests at every vertex) or "pass" (Q never rests)
    dissipation_per_revolution: float  # J
    start0: float  # driver angle β at which Q enters facet 0 (its vertex 0 end)
    facet_span: float  # driver angle during which Q slides on one facet
    fN: float
    k: int
    k_s: float
    R: float
    angle: float

    def force(self, beta) -> np.ndarray:
        """(n, 2) the steady-state force Q at the driver angles β (rad), N."""
        beta = np.atleast_1d(np.asarray(beta, dtype=float))
        k, fN, R = self.k, self.fN, self.R
        step = 2.0 * np.pi / k
        i = np.floor((beta - self.start0) / step).astype(np.int64)
        b0 = self.start0 + i * step  # when Q left vertex i along facet i
        th_n = self.angle + (2 * (i % k) + 1) * np.pi / k
        gam = th_n + np.pi / 2  # τ_i: from vertex i to vertex i + 1
        n = np.column_stack([np.cos(th_n), np.sin(th_n)])
        tau = np.column_stack([np.cos(gam), np.sin(gam)])
        # on the facet, Q's coordinate along τ_i follows the driver's: dc = k_s dd · τ_i
        c = -fN * math.sin(np.pi / k) + self.k_s * R * (np.cos(beta - gam) - np.cos(b0 - gam))
        c = np.minimum(c, fN * math.sin(np.pi / k))  # resting at vertex i + 1 (dwell)
        return fN * math.cos(np.pi / k) * n + c[:, None] * tau

    def slip(self, beta) -> np.ndarray:
        """(n, 2) the point's position x = d − Q / k_s at the driver angles β, m."""
        beta = np.atleast_1d(np.asarray(beta, dtype=float))
        d = self.R * np.column_stack([np.cos(beta), np.sin(beta)])
        return d - self.force(beta) / self.k_s


def circle_orbit(fN: float, k: int, k_s: float, R: float, angle: float = 0.0) -> Orbit:
    """The steady state of a driver d(β) = R (cos β, sin β), β = ω t increasing (counter-
    clockwise), when the point slips for ever.

    Write a = f|N| / k_s (the circumradius of P / k_s) and L = 2a sin(π/k) (a facet's length
    in e = Q / k_s).  By the k-fold symmetry the orbit repeats every 2π/k of β, one facet
    after the other.  On facet i (normal n_i at θ_i, τ_i at γ_i = θ_i + π/2) the slip is
    along n_i at the rate λ = ḋ · n_i ≥ 0 and e slides with ė = (ḋ · τ_i) τ_i, so its
    coordinate along the facet follows the driver's: c(β) − c(β_s) = (d(β) − d(β_s)) · τ_i
    = R [cos(β − γ_i) − cos(β_s − γ_i)].  At a vertex e rests while ḋ (direction β + π/2) lies
    in the vertex's normal cone.  Two regimes:

    * dwell, R ≥ a / sin(π/k) (and R ≥ L, which holds for k ≥ 4): e leaves vertex i when ḋ
      turns past n_i, β_s = γ_i − π, crosses the facet in Δβ* = arccos(1 − L/R) ≤ 2π/k and
      rests at vertex i + 1 for 2π/k − Δβ*.  Per revolution the facet phases dissipate
      k h R sin Δβ* (h = f|N| cos(π/k), ∫ λ = Δ(d · n_i)) and the rests
      k f|N| R [sin(π/k) − sin(Δβ* − π/k)] (Q · Δd at the vertex); the sum simplifies to

          W_rev = 2 k f|N| sin(π/k) (R − a sin(π/k));

    * pass, a / cos(π/k) ≤ R ≤ a / sin(π/k) (the slip rate on a facet stays ≥ 0): e never
      rests; each facet takes exactly 2π/k, so R [cos(β_s + 2π/k − γ_i) − cos(β_s − γ_i)] = L,
      i.e. sin μ = −a/R with μ = β_s + π/k − γ_i; the branch μ = π + arcsin(a/R) is the one
      that tends to the circle's orbit.  Per revolution k h Δ(d · n_i):

          W_rev = k f|N| sin(2π/k) √(R² − a²).

    Both give 2 k f|N| a cos²(π/k) at R = a / sin(π/k), and as k → ∞ W_rev → 2π f|N| √(R² − a²),
    the circle's orbit (the point on a circle of radius √(R² − a²), |Q| = f|N| along its
    velocity).  Below a / cos(π/k) the point sticks part of the time: not covered (ValueError).
    """
    a = fN / k_s
    L = 2.0 * a * math.sin(math.pi / k)
    s, c = math.sin(math.pi / k), math.cos(math.pi / k)
    gam0 = angle + np.pi / k + np.pi / 2
    if R >= a / s and R >= L:
        db = math.acos(1.0 - L / R)
        W = 2.0 * k * fN * s * (R - a * s)
        return Orbit("dwell", W, gam0 - np.pi, db, fN, k, k_s, R, angle)
    if a / c <= R <= a / s:
        mu = np.pi + math.asin(a / R)
        W = k * fN * math.sin(2.0 * np.pi / k) * math.sqrt(R * R - a * a)
        return Orbit("pass", W, gam0 + mu - np.pi / k, 2.0 * np.pi / k, fN, k, k_s, R, angle)
    raise ValueError(f"R = {R:g} m: the point does not slip for ever (k = {k}, a = {a:g} m)")


def circle_driver(R: float, revolutions: float, steps_per_revolution: int,
                  beta0: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(β (n + 1,), d (n + 1, 2)): driver positions on the circle of radius R."""
    n = int(round(revolutions * steps_per_revolution))
    beta = beta0 + 2.0 * np.pi * np.arange(n + 1) / steps_per_revolution
    return beta, R * np.column_stack([np.cos(beta), np.sin(beta)])


def _half_cycle(a: float, k: int, angle: float, u: np.ndarray, start: int):
    """The sweeping of e (in P / k_s, circumradius a) from vertex ``start`` under a driver
    moving along u: stick along u to the boundary, then sliding facet after facet to the
    vertex that maximises u · e.  Returns (end vertex, driver travel to reach it,
    I = ∫ (V_end − e) · u ds), exact (e is piecewise linear in s)."""
    V = vertices(a, k, angle)
    th = facet_normal_angles(k, angle)
    n = np.column_stack([np.cos(th), np.sin(th)])
    tau = np.column_stack([-n[:, 1], n[:, 0]])
    h = a * math.cos(math.pi / k)
    proj = V @ u
    end = int(np.argmax(proj))
    if np.sum(proj >= proj[end] - 1e-12 * a) > 1:
        raise ValueError("the line is along a facet normal (not oblique): Q stops on the facet")
    e0 = V[start]
    top = float(proj[end])
    nu = n @ u
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(nu > 1e-14, (h - n @ e0) / nu, np.inf)
    t = np.where(t > 1e-12 * a, t, np.inf)
    j = int(np.argmin(t))
    tH = float(t[j])
    if not np.isfinite(tH) or np.any(nu[[(start - 1) % k, start]] > 1e-14):
        raise ValueError("the stick phase does not cross the polygon (k < 4?)")
    s_total = tH
    I = tH * (top - float(e0 @ u)) - 0.5 * tH * tH
    p = e0 + tH * u
    for _ in range(k + 1):
        ut = float(tau[j] @ u)
        nxt = (j + 1) % k if ut > 0 else j
        q = V[nxt]
        ds = float(np.linalg.norm(q - p)) / abs(ut)
        I += ds * (2.0 * top - float(p @ u) - float(q @ u)) / 2.0
        s_total += ds
        if nxt == end:
            return end, s_total, I
        p = q
        j = (j + 1) % k if ut > 0 else (j - 1) % k
    raise AssertionError("the slide did not reach the end vertex")


def hysteresis_dissipation(fN: float, k: int, k_s: float, theta: float, A: float,
                           angle: float = 0.0) -> tuple[float, float]:
    """(dissipation per cycle W (J), least amplitude A_min (m) for which it holds; a
    ValueError below it) of the
    steady stick–slip loop under a driver d = s u, u = e_θ, s going back and forth between
    −A and +A (k ≥ 4; θ oblique: not along a facet normal).

    Forward (ḋ = u) e = Q / k_s goes from V− (the vertex maximising −u · V) straight along u
    (stick) to the boundary, then slides along the facets to V+ (the vertex maximising u · V,
    whose normal cone contains u) and rests there; backwards the same with −u.  The elastic
    energy k_s |e|² / 2 is the same at V+ and V− (both on the circle), so a cycle dissipates
    the driver's work k_s ∮ e · dd:

        W = k_s [2A (V+ − V−) · u − I+ − I−],   I± = ∫ (V± − e) · (±u) ds over the half-cycle,

    I± exact sums over the stick segment, t_H ((V+ − V−) · u) − t_H² / 2, and each facet
    segment, Δs ((V+ − p) · u + (V+ − q) · u) / 2 with Δs = |q − p| / |u · τ|.  It holds when
    each half travel 2A reaches V±: A ≥ A_min.

    For even k (V− = −V+) with δ = θ − θ_(V+), |δ| < π/k, this is

        t_H = 2a cos(π/k) / cos(π/k − |δ|),  c = 2a [sin(π/k) − cos(π/k) tan(π/k − |δ|)],
        W = 4 f|N| A cos δ − 2 k_s (2a cos δ t_H − t_H² / 2 + c² / 2),   a = f|N| / k_s

    (t_H the stick travel, c the slide along the facet next to V+), see
    :func:`hysteresis_even`; for the circle (k → ∞) W → 4 f|N| (A − a)."""
    a = fN / k_s
    u = np.array([math.cos(theta), math.sin(theta)])
    V = vertices(a, k, angle)
    vm = int(np.argmax(V @ -u))
    vp, s_f, I_f = _half_cycle(a, k, angle, u, vm)
    back, s_b, I_b = _half_cycle(a, k, angle, -u, vp)
    assert back == vm
    A_min = max(s_f, s_b) / 2.0
    if A < A_min:
        raise ValueError(f"A = {A:g} m: a half travel 2A does not reach the vertex "
                         f"(A_min = {A_min:g} m)")
    return k_s * (2.0 * A * float((V[vp] - V[vm]) @ u) - I_f - I_b), A_min


def hysteresis_even(fN: float, k: int, k_s: float, theta: float, A: float,
                    angle: float = 0.0) -> float:
    """The explicit form of :func:`hysteresis_dissipation` for even k (its docstring)."""
    if k % 2:
        raise ValueError("the explicit form needs an even k (V− = −V+)")
    a = fN / k_s
    step = 2.0 * np.pi / k
    delta = theta - (angle + step * round((theta - angle) / step))  # from the nearest vertex
    d = abs(delta)
    pk = math.pi / k
    tH = 2.0 * a * math.cos(pk) / math.cos(pk - d)
    c = 2.0 * a * (math.sin(pk) - math.cos(pk) * math.tan(pk - d))
    I = 2.0 * a * math.cos(d) * tH - tH * tH / 2.0 + c * c / 2.0
    return 4.0 * fN * A * math.cos(d) - 2.0 * k_s * I


def line_driver(theta: float, A: float, cycles: float, steps_per_quarter: int) -> np.ndarray:
    """(n + 1, 2) driver positions s e_θ with s: 0 → A → −A → A … (``cycles`` full cycles
    after the first quarter), ``steps_per_quarter`` steps per travel A."""
    quarter = np.linspace(0.0, A, steps_per_quarter + 1)
    down = np.linspace(A, -A, 2 * steps_per_quarter + 1)[1:]
    s = [quarter]
    for _ in range(int(cycles)):
        s += [down, -down]
    s = np.concatenate(s)
    return s[:, None] * np.array([math.cos(theta), math.sin(theta)])


__all__ = [
    "FACET_SLIP", "STICK", "VERTEX_SLIP", "Orbit", "Path", "Push", "circle_driver",
    "circle_orbit", "facet_normal_angles", "hysteresis_dissipation", "hysteresis_even",
    "line_driver", "nearest_facet_normal", "project", "ray_exit", "return_mapping",
    "slip_limit", "straight_push", "sweep", "vertices",
]
