"""Euler–Bernoulli frame elements, plane and space, vectorised over the bars.

One kernel for both dimensions (:class:`~stepcontact.model.Frame` carries its dimension as
data).  In the bar's local axes x', y', z' (:meth:`~stepcontact.model.Frame.local_axes`) a
space-frame element has the 12 DOFs (u', v', w', θx', θy', θz') of each end and the stiffness
(SI units: N/m, N, N·m)

* axial: E A / L on u'; torsion: G J / L on θx';
* bending in the x'–y' plane (v', θz', with E I_z): 12 E I_z / L³, ±6 E I_z / L², 4 E I_z / L,
  2 E I_z / L, θz' = dv'/dx';
* bending in the x'–z' plane (w', θy', with E I_y): the same with θy' = −dw'/dx' (the signs of
  the coupling terms turn);

a plane-frame element is the (u', v', θz') part of it (6 DOFs).  The global stiffness of a bar
is Tᵀ k T, T = diag(R, R, R, R) (space) or diag(R, R) (plane, R the 3 × 3 rotation of
(u, v, θz)), R the rows x', y', z' (McGuire, Gallagher & Ziemian, *Matrix Structural
Analysis*, 2nd ed., eqs. 4.34 and 5.9).
"""

from __future__ import annotations

import numpy as np

from stepcontact.model import Frame

#: the plane-frame DOFs (u', v', θz' of each end) among the 12 of a space-frame element
_PLANE = np.array([0, 1, 5, 6, 7, 11])


def local_stiffness(L: np.ndarray, EA: float, EIz: float, EIy: float = 0.0,
                    GJ: float = 0.0) -> np.ndarray:
    """(ne, 12, 12) the local stiffness of space-frame bars of lengths ``L`` (m): axial
    ``EA`` (N), bending ``EIz`` about z', ``EIy`` about y' (N·m²), torsion ``GJ`` (N·m²);
    the module docstring gives the terms."""
    ne = len(L)
    k = np.zeros((ne, 12, 12))
    a, t = EA / L, GJ / L
    k[:, 0, 0] = k[:, 6, 6] = a
    k[:, 0, 6] = k[:, 6, 0] = -a
    k[:, 3, 3] = k[:, 9, 9] = t
    k[:, 3, 9] = k[:, 9, 3] = -t
    for EI, v, r, sign in ((EIz, 1, 5, 1.0), (EIy, 2, 4, -1.0)):
        b12, b6, b4, b2 = 12 * EI / L**3, sign * 6 * EI / L**2, 4 * EI / L, 2 * EI / L
        v2, r2 = v + 6, r + 6
        k[:, v, v] = k[:, v2, v2] = b12
        k[:, v, v2] = k[:, v2, v] = -b12
        k[:, v, r] = k[:, r, v] = k[:, v, r2] = k[:, r2, v] = b6
        k[:, v2, r] = k[:, r, v2] = k[:, v2, r2] = k[:, r2, v2] = -b6
        k[:, r, r] = k[:, r2, r2] = b4
        k[:, r, r2] = k[:, r2, r] = b2
    return k


def _transformation(fr: Frame) -> np.ndarray:
    """(ne, n, n) T: global element DOFs -> local ones (n = 6 plane, 12 space)."""
    R = fr.local_axes()  # (ne, 3, 3)
    blocks = 2 if fr.dim == 2 else 4
    ne = len(R)
    T = np.zeros((ne, 3 * blocks, 3 * blocks))
    for j in range(blocks):
        T[:, 3 * j : 3 * j + 3, 3 * j : 3 * j + 3] = R
    return T


def frame_stiffness(fr: Frame, gdofs: np.ndarray):
    """COO triplets (rows, cols, values) of the frame's bars in global axes; ``gdofs`` (n, 3)
    the global DOFs x, y, rz of its nodes (plane) or (n, 6) x, y, z, rx, ry, rz (space)."""
    p, c = fr.points, fr.cells
    L = np.linalg.norm(p[c[:, 1]] - p[c[:, 0]], axis=1)
    if fr.dim == 2:
        k = local_stiffness(L, fr.E * fr.A, fr.E * fr.I)[:, _PLANE][:, :, _PLANE]
    else:
        k = local_stiffness(L, fr.E * fr.A, fr.E * fr.Iz, fr.E * fr.Iy, fr.shear_modulus * fr.J)
    T = _transformation(fr)
    kg = np.einsum("eji,ejk,ekl->eil", T, k, T)
    nd = kg.shape[1]
    ed = np.column_stack([gdofs[c[:, 0], : nd // 2], gdofs[c[:, 1], : nd // 2]])  # (ne, nd)
    return np.repeat(ed[:, :, None], nd, 2), np.repeat(ed[:, None, :], nd, 1), kg


def add_self_weight(f: np.ndarray, fr: Frame, gdofs: np.ndarray, g) -> None:
    """Add to ``f`` the consistent nodal loads of the frame's weight, a uniform line load
    q = ρ A g (N/m) on every bar: q L / 2 at each end and the fixed-end moments
    ±(L² / 12) e × q of its part normal to the bar (e the bar's unit axis; about z on a plane
    frame, a vector on a space frame), N and N·m.  ``gdofs`` as for :func:`frame_stiffness`."""
    c = fr.cells
    d = fr.points[c[:, 1]] - fr.points[c[:, 0]]
    L = np.linalg.norm(d, axis=1)
    q = fr.density * fr.A * np.asarray(g, float)
    dim = fr.dim
    if dim == 2:  # e × q: (ne,) about z, plane; (ne, 3) space, N/m
        moment = (-d[:, 1] * q[0] + d[:, 0] * q[1]) / L
    else:
        moment = np.cross(d, q) / L[:, None]
    rot = [2] if dim == 2 else [3, 4, 5]
    for end, sign in ((0, 1.0), (1, -1.0)):
        nodes = gdofs[c[:, end]]
        for comp in range(dim):
            np.add.at(f, nodes[:, comp], q[comp] * L / 2)
        for j, col in enumerate(rot):
            m = moment if dim == 2 else moment[:, j]
            np.add.at(f, nodes[:, col], sign * m * L**2 / 12)


__all__ = ["add_self_weight", "frame_stiffness", "local_stiffness"]
