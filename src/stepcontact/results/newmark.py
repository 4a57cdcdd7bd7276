"""Newmark's rigid-block sliding displacement under a ground-acceleration record.

Newmark, N.M. (1965) "Effects of earthquakes on dams and embankments", Géotechnique 15(2),
139–160 (the fifth Rankine lecture), the sliding-block analysis: a rigid block on a plane
resists sliding up to a **yield acceleration** a_y (m/s²; N g in Newmark's notation, N the
yield coefficient); while the ground accelerates beyond it, the block lags behind the ground
and slides relative to it, decelerated by the friction, until the relative velocity returns
to zero.  Per unit mass, with s = ẋ ≥ 0 the sliding velocity in the direction a positive
ground acceleration a(t) drives the block,

    ds/dt = a(t) − a_y     while s > 0          (one-directional: the block slides one way)
    ds/dt = a(t) + a_y     while s < 0          (two-directional: the same a_y both ways)

and the block sticks (s = 0) while −a_y ≤ a(t) ≤ a_y (one-directional: a(t) ≤ a_y).

**Exact integration of a tabulated record.** A record is linear between its samples, so on
each piece s is a quadratic and x a cubic in time: the start of a slide is the crossing of a_y
by the linear a(t) (located exactly), the stop the first zero of the quadratic s (the
numerically stable root), and the velocity and displacement are integrated in closed form per
piece — no time step, the answer exact to round-off.  After the last sample the ground
acceleration is zero (the record has ended): a block still sliding decelerates at a_y and
stops after |s|/a_y, adding s²/(2 a_y).

**Sign convention** (the dynamic driver's, :func:`stepcontact.solve_dynamic` with
``ground_acceleration=(a, d)``, whose displacements are relative to the ground): a positive
record accelerates the ground along +d; the block's displacement and velocity relative to the
ground along d are u = −x, v = −s.  A positive ground acceleration beyond a_y thus slides the
block towards −d (it lags behind the ground): its relative displacement is negative.

Rectangular pulse of amplitude A > a_y and duration t₀ (Newmark 1965, the rigid block under a
single pulse): |u| = V²/(2 a_y) (1 − a_y/A), V = A t₀ — in Newmark's units V²/(2gN)(1 − N/A)
with N, A in g.  Units SI: s, m/s², m/s, m.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from stepcontact.errors import ModelError

#: the smallest window of samples scanned at once; it doubles while a phase goes on, so a
#: record of n samples costs O(n) whatever the number of slides
_CHUNK = 256


@dataclass(frozen=True)
class NewmarkSliding:
    """The sliding of a rigid block under a ground-acceleration record
    (:func:`newmark_sliding`).

    Attributes
    ----------
    time : (n,) s — the record's samples, every start and stop of a slide, and the stop after
        the record's end when the block still slides there
    a_ground : (n,) m/s² — the ground acceleration at those times (0 after the record's end)
    velocity : (n,) m/s — the block's velocity relative to the ground along the record's axis
        (−s: negative while a positive ground acceleration drives it)
    displacement : (n,) m — the block's displacement relative to the ground along the axis
    permanent : float, m — the displacement at the end (the block at rest)
    a_yield : float, m/s²
    two_way : bool — two-directional (symmetric) sliding, else one-directional
    slides : tuple of (start, stop, direction) — each slide's times (s) and the direction of
        the relative motion along the axis (−1: driven by a positive ground acceleration)
    """

    time: np.ndarray
    a_ground: np.ndarray
    velocity: np.ndarray
    displacement: np.ndarray
    permanent: float
    a_yield: float
    two_way: bool
    slides: tuple[tuple[float, float, int], ...]

    @property
    def magnitude(self) -> float:
        """|permanent|, m: Newmark's sliding displacement."""
        return abs(self.permanent)

    def __repr__(self) -> str:
        return (f"NewmarkSliding(permanent={self.permanent:.6g} m, a_yield={self.a_yield:.6g} "
                f"m/s², {'two' if self.two_way else 'one'}-directional, "
                f"{len(self.slides)} slide(s))")


def _checked(t, a_ground, a_yield) -> tuple[np.ndarray, np.ndarray, float]:
    """The record and the yield acceleration, checked: errors name the argument."""
    try:
        t = np.asarray(t, dtype=float)
    except (TypeError, ValueError):
        raise ModelError("t", "give the record's times as numbers (s)") from None
    try:
        a = np.asarray(a_ground, dtype=float)
    except (TypeError, ValueError):
        raise ModelError("a_ground", "give the ground accelerations as numbers (m/s²)") from None
    if t.ndim != 1 or t.size < 2:
        raise ModelError("t", f"give the record's times as a 1-D array of at least two "
                         f"samples (s), got shape {t.shape}")
    if a.shape != t.shape:
        raise ModelError("a_ground", f"give one acceleration per time: {a.shape} values for "
                         f"{t.size} times")
    for name, x in (("t", t), ("a_ground", a)):
        bad = np.flatnonzero(~np.isfinite(x))
        if bad.size:
            raise ModelError(name, f"entry {int(bad[0])} is {x[bad[0]]} (NaN or inf)")
    step = np.diff(t)
    if np.any(step <= 0):
        k = int(np.flatnonzero(step <= 0)[0])
        raise ModelError("t", f"times must increase: entry {k + 1} ({t[k + 1]} s) follows "
                         f"entry {k} ({t[k]} s)")
    try:
        ay = float(a_yield)
    except (TypeError, ValueError):
        raise ModelError("a_yield", f"give the yield acceleration in m/s², got "
                         f"{a_yield!r}") from None
    if not np.isfinite(ay) or ay <= 0:
        raise ModelError("a_yield", f"must be a positive finite acceleration (m/s²), got "
                         f"{ay}: a block without resistance (a_y = 0) never stops")
    return t, a, ay


def _first_zero(S: float, c: float, b: float, h: float) -> float:
    """The first τ in (0, h] where S + c τ + b τ²/2 = 0 (S ≥ 0; the piece is known to hold
    one), by the numerically stable roots of the quadratic, clamped to [0, h]."""
    half = 0.5 * b
    if half == 0.0:
        return min(max(-S / c, 0.0), h) if c != 0.0 else h
    if S == 0.0:  # the slide starts at τ = 0: the other root
        return min(max(-c / half, 0.0), h)
    disc = max(c * c - 4.0 * half * S, 0.0)
    q = -0.5 * (c + np.copysign(np.sqrt(disc), c))
    roots = [r for r in ((q / half, S / q) if q != 0.0 else (-c / half,)) if r > 0.0]
    return min(min(roots, default=h), h)


def _slide(T: np.ndarray, W: np.ndarray, ay: float, s0: float):
    """A forward slide (ds/dt = a − a_y while s > 0) over the window T, W (the record's
    times and values, linear between them; W[0] ≥ a_y when s0 = 0) from the sliding velocity
    s0 ≥ 0 at T[0]: s at the window's nodes, x − x(T[0]) there, and the stop — (piece i, τ)
    of the first zero of s after T[0] — or None when s stays positive over the window."""
    h = np.diff(T)
    w0, w1 = W[:-1], W[1:]
    S = s0 + np.concatenate(([0.0], np.cumsum(h * (0.5 * (w0 + w1) - ay))))
    X = np.concatenate(([0.0], np.cumsum(S[:-1] * h + h * h * ((2.0 * w0 + w1) / 6.0
                                                                 - 0.5 * ay))))
    # s reaches 0 in a piece at its end, or at its minimum inside (a crossing a_y upwards)
    with np.errstate(divide="ignore", invalid="ignore"):
        up = (w0 < ay) & (w1 > ay)
        tau = np.where(up, h * (ay - w0) / (w1 - w0), 0.0)
        s_min = S[:-1] + 0.5 * (w0 - ay) * tau
    hit = np.flatnonzero((S[1:] <= 0.0) | (up & (s_min <= 0.0)))
    if hit.size == 0:
        return S, X, None
    i = int(hit[0])
    b = (w1[i] - w0[i]) / h[i]
    return S, X, (i, _first_zero(S[i], w0[i] - ay, b, h[i]))


def _crossing(W: np.ndarray, ay: float, two_way: bool):
    """The first node of the window W where the ground acceleration is beyond the band
    [−a_y, a_y] (one-directional: beyond a_y): (node j, direction +1 forward / −1
    backward), or None."""
    beyond = (W > ay) | (W < -ay) if two_way else W > ay
    hit = np.flatnonzero(beyond)
    if hit.size == 0:
        return None
    j = int(hit[0])
    return j, (1 if W[j] > ay else -1)


class _Path:
    """The points of a block's path as they are found: times, sliding velocity s, sliding
    displacement x (along the driving direction) and the ground acceleration."""

    def __init__(self, t0: float, a0: float):
        self.parts = [(np.array([t0]), np.zeros(1), np.zeros(1), np.array([a0]))]

    def add(self, t, s, x, a) -> None:
        t = np.atleast_1d(np.asarray(t, float))
        if t.size:
            self.parts.append((t, np.broadcast_to(s, t.shape), np.broadcast_to(x, t.shape),
                               np.broadcast_to(a, t.shape)))

    def arrays(self):
        return [np.concatenate([p[q] for p in self.parts]) for q in range(4)]


def newmark_sliding(t, a_ground, a_yield: float, *, two_way: bool = False) -> NewmarkSliding:
    """Newmark's (1965) rigid-block sliding displacement under the record ``a_ground``
    (module docstring: the equations, the exact piecewise-linear integration and the sign
    convention).

    Parameters
    ----------
    t : (n,) array, s
        The record's times, increasing; the block is at rest relative to the ground at t[0].
    a_ground : (n,) array, m/s²
        The ground acceleration at those times, linear between them, zero after the last
        (a record in g: multiply by g = 9.81 m/s²).
    a_yield : float, m/s²
        The yield acceleration a_y > 0 (a rigid block on a horizontal plane with friction
        coefficient f: a_y = f g).
    two_way : bool
        False (default): one-directional — the block slides only the way a positive ground
        acceleration drives it (a dam downstream, when a positive record accelerates the
        ground upstream; reverse the record for the other polarity); True: two-directional,
        the same a_y both ways.

    Returns
    -------
    NewmarkSliding
        The time history of the relative velocity and displacement and the permanent
        displacement (m; negative for a slide driven by positive ground accelerations).

    Raises
    ------
    ModelError
        Naming ``t`` (not 1-D, fewer than two samples, NaN, not increasing), ``a_ground`` (a
        different length, NaN) or ``a_yield`` (not positive and finite).

    Example
    -------
    >>> import stepcontact as sc
    >>> r = sc.newmark_sliding([0.0, 0.5], [4.905, 4.905], 0.2 * 9.81)  # 0.5 g for 0.5 s
    >>> print(f"{r.permanent:.5f} m")   # −V²/(2 a_y)(1 − a_y/A), V = 2.4525 m/s
    -0.91969 m
    """
    t, a, ay = _checked(t, a_ground, a_yield)
    n = t.size
    path = _Path(float(t[0]), float(a[0]))
    slides: list[tuple[float, float, int]] = []
    # the state: time tc in the record's piece k (t[k] ≤ tc < t[k+1]), a(tc), x(tc)
    k, tc, ac, x = 0, float(t[0]), float(a[0]), 0.0

    def window(size: int):
        stop = min(n, k + 1 + size)
        return (np.concatenate(([tc], t[k + 1:stop])), np.concatenate(([ac], a[k + 1:stop])),
                stop == n)

    def at(T, W, i: int, tau: float):
        """(piece k, time, a) at τ into the window's piece i: a node when τ reaches it."""
        tn = T[i] + tau
        if tn >= T[i + 1]:
            return k + i + 1, float(T[i + 1]), float(W[i + 1])
        return k + i, float(tn), float(W[i] + (W[i + 1] - W[i]) * tau / (T[i + 1] - T[i]))

    while k < n - 1:
        # ---- stuck (s = 0) until the ground acceleration leaves the band ----------------
        size, found = _CHUNK, None
        while True:
            T, W, last = window(size)
            found = _crossing(W, ay, two_way)
            if found is not None:
                break
            path.add(T[1:], 0.0, x, W[1:])
            if last:
                break
            k, tc, ac, size = k + T.size - 1, float(T[-1]), float(W[-1]), 2 * size
        if found is None:
            break
        j, d = found
        if j > 0:  # the crossing of d a_y inside the window's piece j − 1
            i = j - 1
            tau = (d * ay - W[i]) / (W[j] - W[i]) * (T[j] - T[i])
            k_new, tx, _ = at(T, W, i, max(tau, 0.0))
            path.add(T[1:i + 1][T[1:i + 1] < tx], 0.0, x, W[1:i + 1][T[1:i + 1] < tx])
            if tx > tc:  # (τ = 0 in the first piece: the crossing is tc itself)
                path.add(tx, 0.0, x, d * ay if tx < T[j] else float(W[j]))
            k, tc, ac = k_new, tx, d * ay if tx < T[j] else float(W[j])
            if k >= n - 1:  # the record ends at the crossing: a = 0 after it, no slide
                break
        # ---- a slide in direction d: the forward slide of d·a -----------------------------
        t_start, s0, x0, size = tc, 0.0, x, _CHUNK
        while True:
            T, W, last = window(size)
            Wd = d * W
            if s0 == 0.0:
                Wd[0] = max(Wd[0], ay)  # it starts at the crossing, a = a_y exactly
            S, X, stop = _slide(T, Wd, ay, s0)
            if stop is None:
                path.add(T[1:], d * S[1:], x0 + d * X[1:], W[1:])
                k, tc, ac = k + T.size - 1, float(T[-1]), float(W[-1])
                s0, x0, size = float(S[-1]), x0 + d * float(X[-1]), 2 * size
                if last:
                    break
                continue
            i, tau = stop
            h = T[i + 1] - T[i]
            xs = (X[i] + S[i] * tau + 0.5 * (Wd[i] - ay) * tau**2
                  + (Wd[i + 1] - Wd[i]) / h * tau**3 / 6.0)
            k_new, ts, a_s = at(T, W, i, tau)
            keep = T[1:i + 1] < ts
            path.add(T[1:i + 1][keep], d * S[1:i + 1][keep], x0 + d * X[1:i + 1][keep],
                     W[1:i + 1][keep])
            x = x0 + d * float(xs)
            # stopped: d·a ≤ a_y there (round-off must not restart the slide at once)
            k, tc, ac, s0 = k_new, ts, d * min(d * a_s, ay), 0.0
            if tc > t_start:
                path.add(tc, 0.0, x, ac)
            break
        if s0 > 0.0:  # still sliding when the record ends: a = 0, decelerating at a_y
            x = x0 + d * s0**2 / (2.0 * ay)
            t_stop = float(t[-1]) + s0 / ay
            path.add(t_stop, 0.0, x, 0.0)
            slides.append((t_start, t_stop, -d))
            break
        if tc > t_start:
            slides.append((t_start, tc, -d))
    time, s, xs, ag = path.arrays()
    # (0.0 − x: no −0.0 where the block never slid)
    return NewmarkSliding(time=time, a_ground=ag, velocity=0.0 - s, displacement=0.0 - xs,
                          permanent=0.0 - x, a_yield=ay, two_way=bool(two_way),
                          slides=tuple(slides))


__all__ = ["NewmarkSliding", "newmark_sliding"]
