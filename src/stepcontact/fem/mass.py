"""Mass matrices and Rayleigh damping (method.md §4, the dynamics of article eqs. (7)–(10)).

* continua: the consistent mass M = ∫ ρ t N_iᵀ N_j dA (element kernel for tri3 and quad4,
  scikit-fem's form assembly for the others; in 3D M = ∫ ρ N_iᵀ N_j dV on tet4, hex8 and the
  quadratic tetrahedra and hexahedra, scikit-fem's form assembly), or lumped by the HRZ rule
  (Hinton, Rock & Zienkiewicz 1976): in every element the diagonal of the consistent matrix is
  scaled so that it sums to the element's mass — positive for quadratic elements too, where
  row-sum lumping gives zero or negative corner masses (tri6);
* frames (plane and space): lumped, ρ A L / 2 on the translations of each end;
* :func:`rayleigh_coefficients`: C = a₀ M + a₁ K from two modal damping ratios.

Units: kg (per metre of thickness in plane strain, times the thickness in plane stress), and
for C N·s/m.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from skfem import BilinearForm, asm

from stepcontact.errors import ModelError
from stepcontact.fem.continuum import basis_of, linear_kernel


def continuum_mass(body, thickness: float, lumped: bool = False) -> sp.csr_matrix:
    """Mass matrix (CSR, body-local vector DOFs d·i + c, d = 2 or 3 the body's dimension) of a
    continuum body, kg (a 3D body integrates its volume: no thickness).

    ``lumped``: the HRZ diagonal (element-wise scaled diagonal of the consistent matrix).
    tri3 and quad4 on straight-sided meshes by the element kernel (``M_e[i, j] = ρ t Σ_q dx_q
    φ_i(X_q) φ_j(X_q)`` with the data of :func:`~stepcontact.fem.continuum.linear_kernel`,
    all elements at once), other elements by scikit-fem's form assembly."""
    data = linear_kernel(body)
    if data is None:
        dim = getattr(body, "dim", 2)
        return _mass_generic(body, thickness if dim == 2 else 1.0, lumped, dim)
    rho_t = thickness * float(body.material.density)
    _, phi, dx = data  # phi (n_qp, Nbfun), dx (n_el, n_qp): weights × |J|
    cells = np.asarray(body.cells)
    n = body.n_nodes
    if not lumped:
        Me = rho_t * np.einsum("eq,qi,qj->eij", dx, phi, phi)
        r = np.broadcast_to(cells[:, :, None], Me.shape).ravel()
        c = np.broadcast_to(cells[:, None, :], Me.shape).ravel()
        Ms = sp.coo_matrix((Me.ravel(), (r, c)), shape=(n, n)).tocsr()
        return sp.kron(Ms, sp.identity(2, format="csr"), format="csr")
    diag = np.einsum("qi,eq->ie", phi**2, dx)
    return _hrz(diag, dx.sum(axis=1), cells.T, n, rho_t)


def _mass_generic(body, thickness: float, lumped: bool, dim: int = 2) -> sp.csr_matrix:
    """:func:`continuum_mass` by scikit-fem's form assembly (any element, 2D or 3D)."""
    rho = float(body.material.density)
    basis = basis_of(body, vector=False)
    if not lumped:

        @BilinearForm
        def form(u, v, w):
            return thickness * rho * u * v

        Ms = asm(form, basis).tocsr()  # scalar: the same for x, y (and z)
        return sp.kron(Ms, sp.identity(dim, format="csr"), format="csr")
    diag = np.array([((basis.basis[i][0].value ** 2) * basis.dx).sum(axis=1)
                     for i in range(basis.Nbfun)])  # (Nbfun, n_el)
    return _hrz(diag, basis.dx.sum(axis=1), basis.element_dofs, body.n_nodes, thickness * rho,
                dim)


def _hrz(diag: np.ndarray, m_el: np.ndarray, element_dofs: np.ndarray, n: int,
         rho_t: float, dim: int = 2) -> sp.csr_matrix:
    """HRZ lumping: the diagonal ``diag`` (Nbfun, n_el) of each element's consistent matrix
    (per unit ρ t) scaled to sum to the element's area (volume in 3D) ``m_el`` (m², m³),
    summed at the nodes, times ρ t; kg on every translation (``dim``) of each node."""
    scale = m_el / diag.sum(axis=0)
    nodal = np.bincount(element_dofs.ravel(), (diag * scale).ravel(), minlength=n)
    return sp.diags(np.repeat(rho_t * nodal, dim), format="csr")


def rayleigh_coefficients(zeta1: float, f1: float, zeta2: float, f2: float
                          ) -> tuple[float, float]:
    """(a₀, a₁) of Rayleigh damping C = a₀ M + a₁ K (the damping matrix of eq. (7)) with the
    damping ratios ζ₁ at the frequency f₁ and ζ₂ at f₂ (Hz): ζ(ω) = a₀ / (2ω) + a₁ ω / 2, so

        a₀ = 2 ω₁ ω₂ (ζ₁ ω₂ − ζ₂ ω₁) / (ω₂² − ω₁²),   a₁ = 2 (ζ₂ ω₂ − ζ₁ ω₁) / (ω₂² − ω₁²)

    (a₀ in 1/s, a₁ in s).  Equal ratios give ζ ≤ ζ₁ between the two frequencies."""
    vals = {"zeta1": zeta1, "f1": f1, "zeta2": zeta2, "f2": f2}
    for key, v in vals.items():
        if not np.isfinite(v) or v < 0 or (key.startswith("f") and v == 0):
            what = "positive" if key[0] == "f" else "non-negative"
            raise ModelError(f"rayleigh damping.{key}", f"must be {what} and finite, got {v}")
    if f1 == f2:
        raise ModelError("rayleigh damping", f"the two frequencies must differ (both {f1} Hz)")
    from stepcontact.model import plausible

    for key in ("zeta1", "zeta2"):
        plausible.warn("damping_ratio", vals[key], f"rayleigh damping.{key}")
    w1, w2 = 2 * np.pi * f1, 2 * np.pi * f2
    d = w2**2 - w1**2
    a0 = 2 * w1 * w2 * (zeta1 * w2 - zeta2 * w1) / d
    return float(a0), float(2 * (zeta2 * w2 - zeta1 * w1) / d)


def mass(model, dofs, lumped: bool = False) -> sp.csr_matrix:
    """Global mass matrix M of eq. (7) of the model's bodies (continua: consistent or
    HRZ-lumped; frames: lumped translations), kg, on the DOFs of ``dofs``; plus the
    reservoirs' added masses of ``model.added_masses`` (lumped,
    :mod:`stepcontact.fem.hydrodynamic`)."""
    from stepcontact.model import Body

    rows, cols, vals = [], [], []
    off = model.node_offsets
    for b in model.bodies:
        ids = off[b.name] + np.arange(b.n_nodes)
        if isinstance(b, Body):
            Mb = continuum_mass(b, model.thickness, lumped).tocoo()
            gd = dofs.of[ids][:, :b.dim].ravel()
            rows.append(gd[Mb.row])
            cols.append(gd[Mb.col])
            vals.append(Mb.data)
        else:  # frame: ρ A L / 2 at each end, on ux and uy (and uz: a space frame)
            c = b.cells
            L = np.linalg.norm(b.points[c[:, 1]] - b.points[c[:, 0]], axis=1)
            half = b.density * b.A * L / 2
            for end in (0, 1):
                for comp in range(b.dim):
                    d = dofs.of[ids[c[:, end]], comp]
                    rows.append(d)
                    cols.append(d)
                    vals.append(half)
    r, c, v = (np.concatenate(a) if a else np.zeros(0) for a in (rows, cols, vals))
    M = sp.coo_matrix((v, (r.astype(np.int64), c.astype(np.int64))),
                      shape=(dofs.ndof, dofs.ndof)).tocsr()
    if getattr(model, "added_masses", ()):  # the reservoirs (Westergaard 1933, Kuo 1982)
        from stepcontact.fem.hydrodynamic import added_mass_matrix

        M = (M + added_mass_matrix(model, dofs)).tocsr()
    return M


def check_mass(system, where: str = "dynamics") -> None:
    """A dynamic interval needs mass on every body that can move: ModelError naming the first
    body with a free translation but density 0 (kg/m³) — its mass matrix would be singular.
    Checked before any work (``run`` and ``validate`` of a model file with a dynamic interval,
    :func:`~stepcontact.solve_dynamic`); a discrete model gives its mass matrix itself."""
    if getattr(system, "discrete", None) is not None:
        return
    model = system.model
    off = model.node_offsets
    free = ~np.asarray(system.fixed, bool)
    for b in model.bodies:
        rho = float(b.material.density) if hasattr(b, "material") else float(b.density)
        if rho > 0:
            continue
        d = system.dofs.of[off[b.name] + np.arange(b.n_nodes)][:, :system.dofs.dim].ravel()
        d = d[d >= 0]
        if d.size and free[d].any():
            mat = "its material's" if hasattr(b, "material") else "its"
            raise ModelError(f"body '{b.name}'", f"has no mass ({mat} density is {rho:g} "
                             f"kg/m³): the dynamic interval ({where}) needs the density of "
                             "every body that can move")


__all__ = ["check_mass", "continuum_mass", "mass", "rayleigh_coefficients"]
