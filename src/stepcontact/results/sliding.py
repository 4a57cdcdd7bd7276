"""The permanent slip of each joint in a dynamic run, beside Newmark's rigid-block estimate.

From a :class:`~stepcontact.results.result.DynamicResult` (plain arrays, no new solve):

* the **slip** of every CFE of a joint relative to the start of the run (t = 0): the change of
  its mutual tangential displacement u_τ = t·(u⁺ − u⁻) (m; the S+ side relative to the S−
  side along the CFE's tangent t) less the elastic part of a compliant tangential layer,

      slip_k(t) = [u_τk(t) − u_τk(0)] − [Q_k(t) − Q_k(0)] / C_τk      (C_τk = ∞: rigid)

  (the Jenkins element of eq. (11): Q = C_τ (u_τ − slip)), so a stuck CFE's slip is constant
  and the slip at the end of the run is the joint's permanent displacement;
* its **mean over the joint**, weighted by the CFEs' tributary areas A_k (m², per metre of
  thickness in 2D): s̄(t) = Σ A_k slip_k(t) / Σ A_k, and the **largest** |slip_k| at the end
  (open CFEs count too: their u_τ is the tangential motion across the gap);
* a **comparison** (:func:`sliding_comparison`) of each joint's permanent slip with Newmark's
  (1965) rigid-block sliding displacement (:func:`~stepcontact.results.newmark.newmark_sliding`)
  for the same ground-acceleration record and a yield acceleration a_y, given, or computed by
  :func:`rigid_block_yield` from the joint's forces at the start of the run and the mass it
  carries.

Signs: the slip is along each CFE's tangent (for a horizontal joint whose S+ side is the body
above, t = +x when its normal is +y: the body's displacement relative to the base along +x);
Newmark's displacement is the block's relative to the ground along the record's axis (a
positive record beyond a_y slides it towards −axis).  The comparison sets their magnitudes
side by side and keeps both signs.  Units SI: m, m/s², s.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from stepcontact.enums import slipping
from stepcontact.errors import ModelError
from stepcontact.model.timefunction import Pulse
from stepcontact.results.newmark import NewmarkSliding, newmark_sliding


@dataclass(frozen=True)
class JointSlip:
    """The slip of one joint in a dynamic run (:func:`joint_slip`).

    Attributes
    ----------
    interface : str
    time : (n_states,) s
    slip : (n_states, m_j) m — every CFE's slip relative to t = 0 (3D: (n_states, m_j, 2),
        along the CFE's two tangents), CFEs in the order of the result
    cfes : (m_j,) int — the CFEs' indices in the result
    mean : (n_states,) m — the area-weighted mean slip over the joint (3D: (n_states, 2))
    permanent_mean : float, m — the mean slip at the end of the run (3D: (2,))
    permanent_max : float, m — the largest |slip| of a CFE at the end (3D: of its norm)
    cfe_max : int — that CFE's index in the result
    sliding_at_end : bool — a CFE of the joint still slips at the last state (the slip is then
        not yet permanent: run longer)
    """

    interface: str
    time: np.ndarray
    slip: np.ndarray
    cfes: np.ndarray
    mean: np.ndarray
    permanent_mean: float | np.ndarray
    permanent_max: float
    cfe_max: int
    sliding_at_end: bool

    def __repr__(self) -> str:
        mean = np.linalg.norm(np.atleast_1d(self.permanent_mean))
        return (f"JointSlip('{self.interface}': permanent slip {mean:.6g} m (mean), "
                f"{self.permanent_max:.6g} m (max, CFE {self.cfe_max})"
                + (", still sliding at the end" if self.sliding_at_end else "") + ")")


def _interface_cfes(res, interface: str) -> np.ndarray:
    names = list(res.interface_names)
    if interface not in names:
        raise ModelError("interface", f"no interface '{interface}' (interfaces: "
                         f"{', '.join(map(repr, names)) or 'none'})")
    k = np.flatnonzero(np.asarray(res.cfe["interface"]) == names.index(interface))
    if k.size == 0:
        raise ModelError(f"interface '{interface}'", "has no CFE")
    return k


def joint_slip(res, interface: str) -> JointSlip:
    """The slip of the joint ``interface`` along the dynamic run ``res`` (module docstring:
    slip_k(t) = Δu_τk − ΔQ_k/C_τk, its area-weighted mean and the largest at the end), m."""
    if not hasattr(res, "time"):
        raise ModelError("result", "is not a dynamic result (stepcontact.solve_dynamic): "
                         "a slip in time needs the run's states in time")
    if res.n_states == 0:
        raise ModelError("result", "has no state")
    k = _interface_cfes(res, interface)
    ut = np.asarray(res.ut_t, dtype=float)[:, k]
    Q = np.asarray(res.Q_t, dtype=float)[:, k]
    kt = np.asarray(res.cfe.get("kt", np.full(res.m, np.inf)), dtype=float)[k]
    flex = np.where(np.isfinite(kt), 1.0 / np.where(np.isfinite(kt), kt, 1.0), 0.0)
    slip = (ut - ut[:1]) - (Q - Q[:1]) * flex[None, :, None]
    area = np.asarray(res.cfe.get("area", np.ones(res.m)), dtype=float)[k]
    weight = area / area.sum() if area.sum() > 0 else np.full(k.size, 1.0 / k.size)
    mean = np.einsum("smt,m->st", slip, weight)
    size = np.linalg.norm(slip[-1], axis=1)
    j = int(np.argmax(size))
    if res.n_t == 1:
        slip, mean = slip[..., 0], mean[:, 0]
        pmax = float(slip[-1, j])
        pmean: float | np.ndarray = float(mean[-1])
    else:
        pmax, pmean = float(size[j]), mean[-1].copy()
    return JointSlip(interface=interface, time=np.asarray(res.time, dtype=float), slip=slip,
                     cfes=k, mean=mean, permanent_mean=pmean, permanent_max=pmax,
                     cfe_max=int(k[j]),
                     sliding_at_end=bool(np.any(slipping(np.asarray(res.state)[-1, k]))))


def rigid_block_yield(res, interface: str, mass: float, *, state: int = -1) -> float:
    """The yield acceleration of the part above a straight frictional joint taken as a rigid
    block (Newmark 1965), m/s²: the horizontal acceleration at which the joint's friction
    Σ f_k |N_k| is used up by the shear already on it and the inertia force m a_y,

        a_y = (Σ_k f_k |N_k| − |ΣQ_k|) / m

    from the CFE forces of ``res`` at ``state`` — the static result the dynamic run starts
    from (``initial`` of :func:`stepcontact.solve_dynamic`), its last state by default (N per
    metre of thickness in 2D; a dynamic run's first state already carries the ground
    acceleration at t = 0) — and ``mass`` (kg, per metre in 2D: the mass the joint carries).
    It assumes a joint along the direction of shaking (horizontal for a horizontal record),
    no cohesion, normal forces not changed by the shaking (no vertical record, no rocking),
    and sliding in the direction of the shear already on the joint (the other way a_y is
    (Σ f|N| + |ΣQ|)/m).  A rigid block of weight W = m g on a horizontal plane: a_y = f g.
    For a dam, where the water's uplift and the crack change N with the sliding, locate the
    yield acceleration with the pseudo-static coefficient as a load instead."""
    m = float(mass)
    if not np.isfinite(m) or m <= 0:
        raise ModelError("mass", f"must be a positive mass in kg (per metre of thickness in "
                         f"2D), got {mass!r}")
    k = _interface_cfes(res, interface)
    if not -res.n_states <= int(state) < res.n_states:
        raise ModelError("state", f"must be a state index in [0, {res.n_states}), got {state}")
    N = np.asarray(res.N, dtype=float)[int(state), k]
    Q = np.asarray(res.Q_t, dtype=float)[int(state), k]
    f = np.asarray(res.cfe["friction"], dtype=float)[k]
    resist = float(np.sum(f * np.abs(np.minimum(N, 0.0))))
    shear = float(np.linalg.norm(Q.sum(axis=0)))
    if resist <= shear:
        raise ModelError(f"interface '{interface}'", f"slides already at state {state} "
                         f"(Σ f|N| = {resist:.6g} N ≤ |ΣQ| = {shear:.6g} N): no yield "
                         "acceleration")
    return (resist - shear) / m


@dataclass(frozen=True)
class SlidingComparison:
    """Each joint's permanent slip in the dynamic run beside Newmark's rigid-block estimate
    for the same record and yield acceleration (:func:`sliding_comparison`).

    ``rows``: one dict per joint — ``interface``, ``dynamic_mean`` and ``dynamic_max`` (m,
    signed along the joint's tangent: :class:`JointSlip`; a 3D joint's: the lengths of the
    mean slip and of the largest), ``newmark`` (m, signed along the
    record's axis), ``ratio`` = |dynamic_mean| / |newmark| (NaN when Newmark's estimate is
    0), ``sliding_at_end``; ``newmark``: the :class:`NewmarkSliding` itself; ``a_yield``
    (m/s²); ``two_way``; ``joints``: the :class:`JointSlip` of each row."""

    rows: list[dict]
    newmark: NewmarkSliding
    a_yield: float
    two_way: bool
    joints: dict[str, JointSlip] = field(default_factory=dict, repr=False)

    def __str__(self) -> str:
        head = (f"permanent slip: the dynamic run beside Newmark's rigid block (a_y = "
                f"{self.a_yield:.4g} m/s², {'two' if self.two_way else 'one'}-directional)")
        lines = [head, f"{'joint':16s} {'mean (m)':>12s} {'max (m)':>12s} "
                       f"{'Newmark (m)':>12s} {'|mean|/|Newmark|':>17s}"]
        for r in self.rows:
            lines.append(f"{r['interface']:16s} {r['dynamic_mean']:12.5g} "
                         f"{r['dynamic_max']:12.5g} {r['newmark']:12.5g} {r['ratio']:17.4f}"
                         + ("  (still sliding at the end)" if r["sliding_at_end"] else ""))
        return "\n".join(lines)


def _record_arrays(record) -> tuple[np.ndarray, np.ndarray]:
    """(t, a) of ``record``: a pair of arrays (s, m/s²); a
    :class:`~stepcontact.model.timefunction.Tabulated` (any object with ``times`` and
    ``values``); a rectangular or triangular
    :class:`~stepcontact.model.timefunction.Pulse` (linear pieces: exact); or the run's
    ``ground_acceleration`` pair (time function, direction)."""
    if isinstance(record, tuple) and len(record) == 2 and callable(record[0]):
        record = record[0]  # (time function, direction) as given to solve_dynamic
    if isinstance(record, Pulse):
        t0, t1 = record.start, record.start + record.duration
        if record.shape == "rectangular":
            return np.array([t0, t1]), np.full(2, float(record.amplitude))
        if record.shape == "triangular":
            return (np.array([t0, 0.5 * (t0 + t1), t1]),
                    np.array([0.0, float(record.amplitude), 0.0]))
        raise ModelError("record", f"a {record.shape} pulse is not piecewise linear: give it "
                         "tabulated, Tabulated(times, values), fine enough for its curvature")
    if hasattr(record, "times") and hasattr(record, "values"):
        return np.asarray(record.times, float), np.asarray(record.values, float)
    try:
        t, a = record
        return np.asarray(t, float), np.asarray(a, float)
    except (TypeError, ValueError):
        raise ModelError("record", "give (t, a) arrays (s, m/s²), a Tabulated time function "
                         "or a rectangular or triangular Pulse") from None


def sliding_comparison(res, record, a_yield: float, *, interfaces=None,
                       two_way: bool = False, scale: float = 1.0) -> SlidingComparison:
    """The permanent slip of each joint of the dynamic run ``res`` (:func:`joint_slip`) beside
    Newmark's (1965) rigid-block estimate (:func:`~stepcontact.results.newmark.newmark_sliding`)
    for the same record and the yield acceleration ``a_yield`` (m/s²; e.g.
    :func:`rigid_block_yield`).

    ``record``: the run's ground acceleration — (t, a) arrays (s, m/s²), a ``Tabulated``
    time function, a rectangular or triangular ``Pulse``, or the ``ground_acceleration``
    pair given to the run — times ``scale`` (the record's amplitude factor, as given to the run);
    ``interfaces``: the joints (default all); ``two_way``: Newmark's two-directional sliding.
    """
    t, a = _record_arrays(record)
    nm = newmark_sliding(t, float(scale) * a, a_yield, two_way=two_way)
    names = list(res.interface_names) if interfaces is None else (
        [interfaces] if isinstance(interfaces, str) else list(interfaces))
    joints = {name: joint_slip(res, name) for name in names}
    rows = []
    for name, js in joints.items():
        mean = float(np.linalg.norm(np.atleast_1d(js.permanent_mean)))
        rows.append({"interface": name,
                     "dynamic_mean": float(np.atleast_1d(js.permanent_mean)[0])
                     if res.n_t == 1 else mean,
                     "dynamic_max": js.permanent_max, "newmark": nm.permanent,
                     "ratio": mean / nm.magnitude if nm.magnitude > 0 else float("nan"),
                     "sliding_at_end": js.sliding_at_end})
    return SlidingComparison(rows=rows, newmark=nm, a_yield=nm.a_yield, two_way=bool(two_way),
                             joints=joints)


__all__ = ["JointSlip", "SlidingComparison", "joint_slip", "rigid_block_yield",
           "sliding_comparison"]
