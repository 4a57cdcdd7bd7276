"""The safety of a joint between 3D bodies along the path: the resultant of its CFE forces,
where the normal resultant acts on the joint (eccentricities in both directions, the kern and
the base), the compressed area and the sliding factor.

The CFE k acts on the S+ body at its S+ point x_k with the force (method.md §2; N ≤ 0 in
compression, Q = (Q₁, Q₂) on the local tangents t₁, t₂, n from S− to S+):

    F_k = −N_k n_k − Q_k1 t_k1 − Q_k2 t_k2

The joint's own axes are its mean normal n̄ (area-weighted, from S− to S+), e₁ the mean first
tangent made normal to n̄ (the interface's ``axis``) and e₂ = n̄ × e₁; its centroid is
x̄ = Σ A_k x_k / Σ A_k, its extent B₁ × B₂ that of the CFEs' points along e₁, e₂ (the joint's
bounding rectangle in its own plane).  Per state:

* the resultant force R = Σ F_k on S+ and its moment M = Σ (x_k − x̄) × F_k about x̄ (N, N·m),
  the normal force ΣN (N, ≤ 0 in compression) and the shear the S+ part puts on the joint,
  (S₁, S₂) = Σ_k Q_k·t_k along e₁, e₂ = −(R·e₁, R·e₂) (the load's shear on the joint);
* the normal resultant's point x_R = Σ N_k x_k / Σ N_k and its eccentricities
  (e₁, e₂) = ((x_R − x̄)·e₁, (x_R − x̄)·e₂), m; inside the kern of the bounding rectangle
  (|e₁|/B₁ + |e₂|/B₂ ≤ 1/6, the rhombus of the middle thirds) and inside the base
  (|e₁| ≤ B₁/2 and |e₂| ≤ B₂/2);
* the compressed area A_c = Σ_{N_k<0} A_k (m²) and the open area Σ_{open} A_k;
* the friction-only sliding factor Σ f_k (−N_k) / |S| (the true cone's; the faceted cone with k
  facets resists between cos(π/k) and 1 times that, stated in ``cone_bound``).

Hand statics checks it: the CFE forces balance the loads on the S+ part, so ΣN, S and x_R
are those of the loads whatever the elasticity (``tests/test_safety3d.py``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from stepcontact.enums import ContactState

#: a :class:`~stepcontact.results.result.StaticResult`, read through its attributes (the
#: result module imports this one)
StaticResult = Any


@dataclass(frozen=True)
class InterfaceSafety3D:
    """Safety of a 3D joint along the path (arrays: one entry per state; module docstring).

    Attributes
    ----------
    interface : str
    lam, segment : (n,) the path's factor and segment of each state
    normal_force : (n,) ΣN, N (≤ 0 in compression)
    shear : (n, 2) the shear on the joint (S₁, S₂) = Σ Q_k t_k along e₁, e₂, N
    shear_force : (n,) |S|, N
    resultant : (n, 3) R = Σ F_k on S+, global axes, N
    moment : (n, 3) Σ (x_k − x̄) × F_k about the centroid, global axes, N·m
    point : (n, 3) the normal resultant's point x_R, m (NaN where ΣN = 0)
    eccentricity : (n, 2) (e₁, e₂) of x_R from the centroid, m
    in_kern, in_base : (n,) bool
    compressed_area, open_area : (n,) m²
    sliding_factor : (n,) Σ f_k (−N_k) / |S| (inf where S = 0 to round-off)
    centroid : (3,) x̄, m
    axes : (3, 3) rows e₁, e₂, n̄
    extent : (2,) B₁, B₂, m
    area : Σ A_k, m²
    friction : the largest friction coefficient of the joint's CFEs
    facets : the friction polygon's facet count k (0: the 2D law)
    cone_bound : 1 − cos(π/k), the faceted cone's largest shortfall below f|N|
    lam_sliding, lam_overturning : λ where the run lost equilibrium with the joint's bodies
        sliding / rotating (overturning about an edge); None if not reached
    """

    interface: str
    lam: np.ndarray
    segment: np.ndarray
    normal_force: np.ndarray
    shear: np.ndarray
    shear_force: np.ndarray
    resultant: np.ndarray
    moment: np.ndarray
    point: np.ndarray
    eccentricity: np.ndarray
    in_kern: np.ndarray
    in_base: np.ndarray
    compressed_area: np.ndarray
    open_area: np.ndarray
    sliding_factor: np.ndarray
    centroid: np.ndarray
    axes: np.ndarray
    extent: np.ndarray
    area: float
    friction: float
    facets: int
    cone_bound: float
    lam_sliding: float | None = None
    lam_overturning: float | None = None

    def at(self, i: int = -1) -> dict[str, object]:
        """The values at state ``i`` as plain numbers (for tables and reports)."""
        return {
            "lam": float(self.lam[i]), "normal_force": float(self.normal_force[i]),
            "shear": self.shear[i].tolist(), "shear_force": float(self.shear_force[i]),
            "point": self.point[i].tolist(), "eccentricity": self.eccentricity[i].tolist(),
            "in_kern": bool(self.in_kern[i]), "in_base": bool(self.in_base[i]),
            "compressed_area": float(self.compressed_area[i]),
            "open_area": float(self.open_area[i]),
            "sliding_factor": float(self.sliding_factor[i]),
        }


def _joint_axes(normal: np.ndarray, tangent: np.ndarray, area: np.ndarray) -> np.ndarray:
    """Rows e₁, e₂, n̄: the area-weighted mean normal and first tangent, made orthonormal."""
    n = area @ normal
    n /= np.linalg.norm(n)
    t = area @ tangent[:, 0, :]
    t -= (t @ n) * n
    t /= np.linalg.norm(t)
    return np.stack([t, np.cross(n, t), n])


def cfe_geometry(res: StaticResult, k: np.ndarray, what: str):
    """(x (K, 3), n (K, 3), t (K, 2, 3), A (K,)) of the CFEs ``k`` of a 3D result, m and m²
    (t₂ = n × t₁ where only t₁ is kept); a ValueError naming ``what`` for a result without
    the CFEs' 3D geometry (a discrete model's)."""
    x = np.asarray(res.cfe.get("x", np.zeros((0, 0))), float)
    nrm = np.asarray(res.cfe.get("normal", np.zeros((0, 0))), float)
    tan = np.asarray(res.cfe.get("tangent", np.zeros((0, 0))), float)
    if x.ndim != 2 or x.shape[1:] != (3,) or nrm.shape != x.shape or tan.shape[-1:] != (3,):
        raise ValueError(f"{what}: the result has no 3D geometry of its CFEs (points, normals, "
                         "tangents): a discrete model's joints have no plane to draw or sum in")
    x, nrm, tan = x[k], nrm[k], tan[k]
    if tan.ndim == 2:
        tan = np.stack([tan, np.cross(nrm, tan)], axis=1)
    return x, nrm, tan, np.asarray(res.cfe["area"], float)[k]


def joint_frame(res: StaticResult, k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The centroid x̄ (3,) of the CFEs ``k`` (area-weighted, m) and the joint's axes (3, 3),
    rows e₁, e₂, n̄ (module docstring)."""
    x, nrm, tan, area = cfe_geometry(res, k, "the joint's frame")
    return area @ x / area.sum(), _joint_axes(nrm, tan, area)


def interface_safety_3d(res: StaticResult, interface: str) -> InterfaceSafety3D:
    """The :class:`InterfaceSafety3D` of ``interface`` along the path of a 3D result."""
    names = list(res.interface_names)
    if interface not in names:
        raise KeyError(f"no interface '{interface}' (interfaces: "
                       f"{', '.join(map(repr, names)) or 'none'})")
    k = np.flatnonzero(np.asarray(res.cfe["interface"]) == names.index(interface))
    if k.size == 0:
        raise ValueError(f"interface '{interface}' has no CFE")
    x, nrm, tan, area = cfe_geometry(res, k, f"interface_safety('{interface}')")
    fric = np.asarray(res.cfe["friction"], float)[k]
    N = np.asarray(res.N, float)[:, k]
    Q = np.asarray(res.Q_t, float)[:, k]
    centroid, axes = joint_frame(res, k)
    local = (x - centroid) @ axes[:2].T  # (K, 2) in-plane coordinates
    extent = np.ptp(local, axis=0)
    force = -N[..., None] * nrm[None] - np.einsum("skj,kjd->skd", Q, tan)  # (n, K, 3)
    R = force.sum(axis=1)
    M = np.cross((x - centroid)[None], force).sum(axis=1)
    sN = N.sum(axis=1)
    shear = -(R @ axes[:2].T)  # Σ Q_k t_k: the shear S+ puts on the joint
    S = np.linalg.norm(shear, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        loaded = sN != 0
        point = np.where(loaded[:, None], (N @ x) / np.where(loaded, sN, 1.0)[:, None], np.nan)
        ecc = (point - centroid) @ axes[:2].T
        no_shear = S <= 1e-12 * np.abs(sN)
        sliding = np.where(no_shear, np.inf, -(N @ fric) / np.where(no_shear, 1.0, S))
        B = np.where(extent > 0, extent, np.inf)
        tol = 1e-12
        in_kern = loaded & ((np.abs(ecc) / B).sum(axis=1) <= 1 / 6 + tol)
        in_base = loaded & np.all(np.abs(ecc) <= B / 2 + tol * B, axis=1)
    states = np.asarray(res.state, dtype=np.int64)[:, k]
    open_ = states == int(ContactState.OPEN)
    facets = int(np.asarray(res.cfe.get("facets", 0)).max(initial=0))
    return InterfaceSafety3D(
        interface, np.asarray(res.lam, float), np.asarray(res.segment), sN, shear, S, R, M,
        point, ecc, in_kern, in_base, np.where(N < 0, area, 0.0).sum(axis=1),
        np.where(open_, area, 0.0).sum(axis=1), sliding, centroid, axes, extent,
        float(area.sum()), float(fric.max()), facets,
        float(1 - np.cos(np.pi / facets)) if facets else 0.0, *_limits(res))


def _limits(res: StaticResult) -> tuple[float | None, float | None]:
    """λ where the run lost equilibrium with a body sliding, and with a body rotating
    (:func:`stepcontact.solver.mechanism.classify3d`); None where not."""
    mech = res.mechanism or {}
    modes = [str(b.get("mode", "")) for b in mech.get("bodies", [])]
    lam = float(mech.get("lam", res.lam[-1])) if modes else None
    return (lam if "sliding" in modes else None,
            lam if any(m.startswith("rotation") for m in modes) else None)


__all__ = ["InterfaceSafety3D", "cfe_geometry", "interface_safety_3d", "joint_frame"]
