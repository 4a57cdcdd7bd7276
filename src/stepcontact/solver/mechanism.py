"""The mechanism of a lost equilibrium: which bodies move, and how (sliding, lift-off,
overturning about a point)."""

from __future__ import annotations

import numpy as np

from stepcontact.solver.engine import EventEngine
from stepcontact.solver.schemes import lu, null_modes

#: a rigid-body fit whose rotation moves the body's extent by less than this fraction of its
#: translation is a translation (sliding, lift-off); null modes carry round-off of ~1e-8
TRANSLATION_RTOL = 1e-3


def rigid_fit(points: np.ndarray, u: np.ndarray) -> tuple[float, float, float, np.ndarray]:
    """Least-squares rigid motion u ≈ T + θ ẑ × (x − x̄) of a body: (tx, ty, θ, x̄)."""
    xc = points.mean(axis=0)
    x = points - xc
    A = np.zeros((2 * len(x), 3))
    A[0::2, 0] = 1
    A[1::2, 1] = 1
    A[0::2, 2] = -x[:, 1]
    A[1::2, 2] = x[:, 0]
    tx, ty, th = np.linalg.lstsq(A, u.ravel(), rcond=None)[0]
    return float(tx), float(ty), float(th), xc


def classify(points: np.ndarray, u: np.ndarray) -> dict:
    """Name the rigid motion ``u`` (n, 2) of a body.

    Scale-aware: the rotation counts when it moves the body's extent by at least
    ``TRANSLATION_RTOL`` of the translation; its centre P (u(P) = 0) near the body
    (within 5 sizes) is overturning about P, a far centre is a translation."""
    tx, ty, th, xc = rigid_fit(points, u)
    size = float(np.ptp(points, axis=0).max()) or 1.0
    t = max(abs(tx), abs(ty))
    centre = None
    if abs(th) * size > TRANSLATION_RTOL * t:
        centre = xc + np.array([-ty, tx]) / th
        centre[np.abs(centre) < 1e-9 * size] = 0.0  # round-off off a zero coordinate
    if centre is not None and np.linalg.norm(centre - xc) <= 5.0 * size:
        mode = f"rotation (overturning) about ({centre[0]:.4g}, {centre[1]:.4g})"
    elif abs(tx) >= abs(ty):
        mode = "sliding"
        centre = None
    else:
        mode = "lift-off" if ty > 0 else "sinking"
        centre = None
    return {"mode": mode, "translation": [tx, ty], "rotation": th,
            "centre": None if centre is None else [float(c) for c in centre]}


def classify3d(points: np.ndarray, u: np.ndarray) -> dict:
    """Name the rigid motion ``u`` (n, 3) of a 3D body: the least-squares fit
    u ≈ T + ω × (x − x̄); a rotation when it moves the body's extent by at least
    ``TRANSLATION_RTOL`` of the translation, else lift-off/sinking (T mostly along ±z) or
    sliding."""
    xc = points.mean(axis=0)
    x = points - xc
    n = len(x)
    A = np.zeros((3 * n, 6))
    for c in range(3):
        A[c::3, c] = 1.0
    # ω × x = (ω_y z − ω_z y, ω_z x − ω_x z, ω_x y − ω_y x)
    A[0::3, 4], A[0::3, 5] = x[:, 2], -x[:, 1]
    A[1::3, 5], A[1::3, 3] = x[:, 0], -x[:, 2]
    A[2::3, 3], A[2::3, 4] = x[:, 1], -x[:, 0]
    sol = np.linalg.lstsq(A, u.ravel(), rcond=None)[0]
    T, w = sol[:3], sol[3:]
    size = float(np.ptp(points, axis=0).max()) or 1.0
    t = float(np.abs(T).max())
    if np.linalg.norm(w) * size > TRANSLATION_RTOL * t:
        axis = w / np.linalg.norm(w)
        mode = f"rotation about the axis ({axis[0]:.3g}, {axis[1]:.3g}, {axis[2]:.3g})"
    elif abs(T[2]) > np.hypot(T[0], T[1]):
        mode = "lift-off" if T[2] > 0 else "sinking"
    else:
        mode = "sliding"
    return {"mode": mode, "translation": [float(v) for v in T],
            "rotation": [float(v) for v in w], "centre": None}


def dof_mode(discrete, u: np.ndarray, limit: int = 8) -> dict:
    """The mechanism of a discrete model: ``{"body": its name, "mode": "moves along …",
    "dofs": {DOF name: component}}``, the mode scaled to a largest component of 1 (its sign
    chosen positive) and the components below 1e-3 left out."""
    u = np.asarray(u, dtype=float)
    big = int(np.argmax(np.abs(u))) if u.size else 0
    scale = u[big] if u.size and u[big] != 0 else 1.0
    v = u / scale
    keep = np.flatnonzero(np.abs(v) >= 1e-3)
    keep = keep[np.argsort(-np.abs(v[keep]), kind="stable")]
    names = discrete.dof_names
    parts = [f"{names[d]} {v[d]:.4g}" for d in keep[:limit]]
    more = f" and {keep.size - limit} more" if keep.size > limit else ""
    return {"body": discrete.name, "mode": f"moves along ({', '.join(parts)}{more})",
            "dofs": {names[d]: float(v[d]) for d in keep}}


def _mode(engine: EventEngine, cond, system, states: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Displacement (ndof,) of the mechanism of scheme ``states`` along the load rate ``f``."""
    rel = engine.relations(states, article=False)
    A, scale = engine.schemes.dense(rel)
    per = 6 if system.discrete is None and system.dofs.dim == 3 else 3  # rigid modes a body
    k = min(per * max(len(system.model.bodies), 1), A.shape[0])
    T = null_modes(A, lu(A), k=k, apply=engine.schemes.exact_apply(rel, scale))
    U = np.column_stack([cond.mode_displacement(T[:, j]) for j in range(T.shape[1])])
    work = f @ U
    return U @ np.linalg.lstsq(U.T @ U, work, rcond=None)[0] if np.any(work != 0) else U[:, 0]


def constraint_conflict(engine: EventEngine, cond, states: np.ndarray) -> np.ndarray | None:
    """CFEs whose rigid relations in scheme ``states`` constrain one motion twice (their rows
    of the contact operator are dependent: e.g. a node held in x by a stuck CFE on a fixed
    base and pushed in x by a closed CFE against a moving wall), or None.

    Such a scheme is singular, but not a mechanism: its null space holds a self-equilibrated
    set of contact forces (Bᵀ t = 0), not a motion; when the load drives it, the two
    constraints contradict each other (the forces would have to jump), which rigid contact
    cannot resolve."""
    rel = engine.relations(states, article=False)
    A, scale = engine.schemes.dense(rel)
    T = null_modes(A, lu(A), k=min(3, A.shape[0]), apply=engine.schemes.exact_apply(rel, scale))
    for j in range(T.shape[1]):
        t = T[:, j]
        size = np.linalg.norm(t)
        if size > 0 and np.linalg.norm(cond.Bf.T @ t) <= 1e-9 * size:
            big = np.flatnonzero(np.abs(t) > 1e-6 * np.abs(t).max())
            return np.unique(engine.layout.cfe_of(big))
    return None


def free_to_open(engine: EventEngine, cond, system, states: np.ndarray, f: np.ndarray,
                 N: np.ndarray, tol: float) -> np.ndarray:
    """The scheme whose mechanism to report: ``states``, or the same with its closed CFEs that
    carry no force (|N| ≤ ``tol``) opened, when that scheme is a mechanism too and its motion
    along the load opens every one of them.  At a degenerate point (a body resting on zero
    forces, pulled off) several schemes are mechanisms; the one that keeps a force-free CFE
    closed names a rotation about it, where the body in fact lifts off."""
    from stepcontact.contact.laws import BONDED, OPEN

    idle = (states != OPEN) & (states != BONDED) & (np.abs(N) <= tol)
    if not idle.any():
        return states
    alt = states.copy()
    alt[idle] = OPEN
    try:
        u = _mode(engine, cond, system, alt, f)
    except Exception:  # noqa: BLE001 - the alternative is not a mechanism: keep the scheme
        return states
    # normal relative displacement rates of the mode (w⁰ does not move)
    un = system.layout.normal(system.B @ u)
    size = np.abs(un).max(initial=0.0)
    if size > 0 and np.all(un[idle] <= 1e-9 * size):
        return alt
    return states


def describe_mechanism(engine: EventEngine, cond, system, states: np.ndarray,
                       f: np.ndarray) -> list[dict]:
    """Bodies that move in the mechanism of scheme ``states`` and their modes: among the null
    modes of the scheme, the combination along the load rate ``f`` (ndof,) (the projection of
    the load on the modes: a slab freed of all contact can translate and rotate; the load lifts
    it)."""
    model = system.model
    u = _mode(engine, cond, system, states, f)
    if system.discrete is not None:  # DOFs without nodes: the mode shape by DOF
        return [dof_mode(system.discrete, u)]
    off = model.node_offsets
    umax = np.abs(u).max() or 1.0
    bodies = []
    for b in model.bodies:
        ids = off[b.name] + np.arange(b.n_nodes)
        dim = b.points.shape[1]
        ub = u[system.dofs.of[ids][:, :dim]] / umax
        if np.abs(ub).max() < 1e-3:
            continue
        bodies.append({"body": b.name, **(classify3d if dim == 3 else classify)(b.points, ub)})
    return bodies
