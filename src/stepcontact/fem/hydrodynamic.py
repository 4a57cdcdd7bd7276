"""The reservoir's added mass on a face, lumped on its nodes, and the pseudo-static seismic load
(:mod:`stepcontact.model.seismic`; Westergaard 1933, Kuo 1982).

Lumping.  On a straight wet edge e (length L_e, outward unit normal n_e, thickness t) the node
i of the edge receives the 2 × 2 mass block

    M_i += t L_e ∫₀¹ m_a(z(s)) φ_i(s) ds · n_e n_eᵀ,      m_a(z) = (7/8) ρ_w √(H z)

(kg; φ_i the edge's shape function, linear or quadratic; z(s) the depth, linear along the
edge, clipped at 0 above the level): the row sums of the consistent added-mass matrix
∫ m_a φ_i φ_j n nᵀ dA.  Because Σ φ_i = 1 (and Σ φ_i y_i = y on straight edges), the lumped
masses carry exactly the integral of m_a and its first moment: under a rigid translation
with acceleration a the face receives Westergaard's force (7/12) ρ_w a H² at 0.4 H above the
base on any mesh of a vertical face — the masses are not the node's m_a times a tributary
length, which underestimates the node at the surface where √z is singular.  Nodes where
edges of different slope meet get the sum of the edges' blocks (a full 2 × 2 block).

The integrals are exact: with s = √z as the variable (z = s²), t ∫ t^j √z dt is a polynomial
of degree 2j + 2 ≤ 6 in the Gauss variable, integrated exactly by 4-point Gauss–Legendre,
with t(ξ) written without cancellation (:func:`sqrt_moments`).

The pseudo-static hydrodynamic load of a :class:`~stepcontact.model.seismic.SeismicCoefficient`
is the same block times the inertia acceleration: f_i = M_i g (k_h d, k_v) — the consistent
nodal forces of the traction m_a g (k_h d, k_v) · n n on every edge, exact.

Units: kg, N, m.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from stepcontact.contact.boundary import continuum_edges, outward_normals
from stepcontact.errors import ModelError

_GX, _GW = np.polynomial.legendre.leggauss(4)  # exact to degree 7
_GX, _GW = 0.5 * (_GX + 1.0), 0.5 * _GW  # on [0, 1]


def sqrt_moments(za: np.ndarray, zb: np.ndarray, k: int = 2) -> np.ndarray:
    """μ_j = ∫₀¹ t^j √(max(z(t), 0)) dt, j = 0…k, with z(t) = z_a + (z_b − z_a) t linear
    (the depth along an edge, m): (n, k + 1), m^½, exact to round-off.

    On the wet part [t₀, t₁] (z ≥ 0) substitute s = √z, s = s₀ + (s₁ − s₀) ξ: then
    t = t₀ + (t₁ − t₀) ξ (s + s₀)/(s₁ + s₀) and dt = (t₁ − t₀) 2 s/(s₁ + s₀) dξ (no
    difference of nearly equal numbers, even for a nearly level edge), and the integrand
    t^j s dt/dξ is a polynomial of degree 2j + 2 in ξ: Gauss–Legendre with 4 points is exact
    for k ≤ 2."""
    za, zb = np.asarray(za, float), np.asarray(zb, float)
    n = za.shape[0]
    out = np.zeros((n, k + 1))
    dz = zb - za
    with np.errstate(divide="ignore", invalid="ignore"):
        tc = np.where(dz != 0, -za / dz, 0.0)  # where z = 0
    wet_a, wet_b = za > 0, zb > 0
    t0 = np.where(wet_a, 0.0, np.where(wet_b, tc, 0.0))
    t1 = np.where(wet_b, 1.0, np.where(wet_a, tc, 0.0))
    s0 = np.where(wet_a, np.sqrt(np.maximum(za, 0.0)), 0.0)
    s1 = np.where(wet_b, np.sqrt(np.maximum(zb, 0.0)), 0.0)
    wet = (wet_a | wet_b) & (t1 > t0)
    if not wet.any():
        return out
    t0, t1, s0, s1 = t0[wet, None], t1[wet, None], s0[wet, None], s1[wet, None]
    s = s0 + (s1 - s0) * _GX[None, :]
    ssum = s1 + s0
    t = t0 + (t1 - t0) * _GX[None, :] * (s + s0) / ssum
    jac = (t1 - t0) * 2.0 * s / ssum
    w = _GW[None, :] * s * jac
    out[wet] = np.stack([(w * t**j).sum(axis=1) for j in range(k + 1)], axis=1)
    return out


def _edge_weights(mu: np.ndarray, quadratic: bool) -> np.ndarray:
    """∫₀¹ φ_i √z dt of each edge node (ends, then the mid-side node) from the moments μ_j."""
    if not quadratic:  # φ_a = 1 − t, φ_b = t
        return np.stack([mu[:, 0] - mu[:, 1], mu[:, 1]], axis=1)
    # φ_a = (1 − t)(1 − 2t), φ_b = t (2t − 1), φ_m = 4 t (1 − t)
    return np.stack([mu[:, 0] - 3 * mu[:, 1] + 2 * mu[:, 2], 2 * mu[:, 2] - mu[:, 1],
                     4 * (mu[:, 1] - mu[:, 2])], axis=1)


def face_masses(model, am, item: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The lumped added mass of the :class:`~stepcontact.model.seismic.AddedMass` ``am``:
    (global node ids (k,), 2 × 2 blocks (k, 2, 2) in kg), module docstring.  ModelError
    naming the item for a face that is not on a 2D continuum's boundary, a face below the
    reservoir bottom or a level not above it."""
    item = am.label if item is None else item
    b, edges = continuum_edges(model, am.face, item, "added masses")
    if b.dim != 2:
        raise ModelError(item, f"body '{b.name}' is 3D: the added mass is available on the "
                         "faces of 2D bodies")
    pts = b.points
    H = am.height(pts[np.unique(edges), 1], item)
    n = outward_normals(b, edges)
    za, zb = am.level - pts[edges[:, 0], 1], am.level - pts[edges[:, 1], 1]
    L = np.linalg.norm(pts[edges[:, 1]] - pts[edges[:, 0]], axis=1)
    w = _edge_weights(sqrt_moments(za, zb), edges.shape[1] > 2)
    w *= (7.0 / 8.0 * am.density * np.sqrt(H) * model.thickness * L)[:, None]
    nn = np.einsum("ei,ej->eij", n, n)
    blocks = w[:, :, None, None] * nn[:, None, :, :]  # (edges, nodes per edge, 2, 2)
    local, inv = np.unique(edges.ravel(), return_inverse=True)
    out = np.zeros((len(local), 2, 2))
    np.add.at(out, inv.ravel(), blocks.reshape(-1, 2, 2))
    return model.node_offsets[b.name] + local, out


def _scatter(dofs, ids: np.ndarray, blocks: np.ndarray) -> sp.csr_matrix:
    d = dofs.of[ids][:, :2]  # (k, 2) the u_x, u_y DOFs of each node
    r = np.broadcast_to(d[:, :, None], blocks.shape).ravel()
    c = np.broadcast_to(d[:, None, :], blocks.shape).ravel()
    keep = blocks.ravel() != 0.0
    return sp.coo_matrix((blocks.ravel()[keep], (r[keep], c[keep])),
                         shape=(dofs.ndof, dofs.ndof)).tocsr()


def added_mass_matrix(model, dofs, items=None) -> sp.csr_matrix:
    """The added mass M_a (ndof × ndof, kg) of ``items`` (default: the model's
    ``added_masses``), to be added to the mass matrix of eq. (7)."""
    items = getattr(model, "added_masses", ()) if items is None else items
    M = sp.csr_matrix((dofs.ndof, dofs.ndof))
    for am in items:
        ids, blocks = face_masses(model, am)
        M = M + _scatter(dofs, ids, blocks)
    return M.tocsr()


def reservoir_forces(model, dofs, ld, item: str) -> np.ndarray:
    """The hydrodynamic part of a :class:`~stepcontact.model.seismic.SeismicCoefficient`
    ``ld`` per unit λ: f = M_a g (k_h d, k_v) summed over its reservoirs, N (ndof,)."""
    f = np.zeros(dofs.ndof)
    acc = np.asarray(ld.acceleration(), float)
    for i, am in enumerate(ld.reservoir):
        ids, blocks = face_masses(model, am, f"{item}.reservoir[{i}] ({am.label})")
        np.add.at(f, dofs.of[ids][:, :2].ravel(), (blocks @ acc).ravel())
    return f


__all__ = ["added_mass_matrix", "face_masses", "reservoir_forces", "sqrt_moments"]
