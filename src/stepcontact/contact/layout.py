"""The layout of the contact unknowns: m CFEs, each with n_t tangential components and one
normal component.

The forces s = [Q; p] (p = −N ≥ 0 in compression, N) and the mutual displacements
w = [u_τ; u_n] (m) of all CFEs are vectors of n = m (1 + n_t) entries, ordered component-major
as the article writes them in 2D (eq. (1)): every CFE's first tangential component, then every
CFE's second one (3D), then every CFE's normal component::

    x = [x_t1 (m); x_t2 (m, 3D only); x_n (m)]

so that row ``j·m + k`` is component j of CFE k (j < n_t tangential, j = n_t normal).  In 2D
(n_t = 1) this is today's [Q; p] and [u_τ; u_n] exactly.

The views are NumPy views of the vector (no copy): writing into them writes into the vector.
Every leading-axis array works alike ((n,) vectors and (n, k) blocks of columns).

Each CFE has a local basis, rows t₁[, t₂], n (unit vectors, n from S− to S+), from which the
contact operator B (n × ndof) is built: row (j, k) of B is t_j,k · (u⁺ − u⁻) for a tangential
component and −n_k · (u⁺ − u⁻) for the normal one (u_n ≤ 0: no interpenetration, eq. (1)).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np


@dataclass(frozen=True)
class ContactLayout:
    """The block layout of the contact unknowns of m CFEs with n_t tangential components
    (1 in 2D, 2 in 3D); see the module docstring for the ordering."""

    m: int
    n_t: int = 1

    def __post_init__(self):
        if self.m < 0:
            raise ValueError(f"ContactLayout: m = {self.m} CFEs, must be ≥ 0")
        if self.n_t not in (1, 2):
            raise ValueError(f"ContactLayout: n_t = {self.n_t} tangential components, "
                             "must be 1 (2D) or 2 (3D)")

    @classmethod
    def of_size(cls, n: int, n_t: int = 1) -> ContactLayout:
        """The layout of a vector of n = m (1 + n_t) contact unknowns (one object per size:
        the scheme functions that see only vectors share its index arrays)."""
        return _of_size(cls, int(n), int(n_t))

    @classmethod
    def _make(cls, n: int, n_t: int) -> ContactLayout:
        if n % (1 + n_t):
            raise ValueError(f"ContactLayout: {n} contact unknowns are not m (1 + n_t) "
                             f"with n_t = {n_t}")
        return cls(n // (1 + n_t), n_t)

    # ---- sizes ------------------------------------------------------------------------------
    @property
    def n_c(self) -> int:
        """Components per CFE, 1 + n_t."""
        return 1 + self.n_t

    @property
    def n(self) -> int:
        """Number of contact unknowns of one kind (forces or displacements), m (1 + n_t)."""
        return self.m * (1 + self.n_t)

    @property
    def n_tangential(self) -> int:
        """Number of tangential unknowns, m n_t."""
        return self.m * self.n_t

    # ---- views (no copies) ------------------------------------------------------------------
    def tangential(self, x: np.ndarray) -> np.ndarray:
        """The tangential components of x (leading axis n): (m, …) in 2D as today, (m, n_t, …)
        in 3D; a view of x."""
        t = x[: self.n_tangential]
        if self.n_t == 1:
            return t
        return np.swapaxes(t.reshape((self.n_t, self.m) + x.shape[1:]), 0, 1)

    def normal(self, x: np.ndarray) -> np.ndarray:
        """The normal components of x (leading axis n), (m, …); a view of x."""
        return x[self.n_tangential:]

    def component(self, x: np.ndarray, j: int) -> np.ndarray:
        """Component j (j < n_t tangential, j = n_t normal) of every CFE, (m, …); a view."""
        if not 0 <= j <= self.n_t:
            raise IndexError(f"component {j} of a layout with {self.n_c} components per CFE")
        return x[j * self.m:(j + 1) * self.m]

    def split(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(tangential(x), normal(x)), both views of x."""
        return self.tangential(x), self.normal(x)

    def join(self, t, n) -> np.ndarray:
        """The vector x with tangential(x) = t and normal(x) = n (a new array); the inverse of
        :meth:`split`.  t: (m, …) in 2D, (m, n_t, …) in 3D; n: (m, …)."""
        t, n = np.asarray(t), np.asarray(n)
        if self.n_t > 1:
            t = np.swapaxes(t, 0, 1).reshape((self.n_tangential,) + t.shape[2:])
        return np.concatenate([t, n])

    def join_each(self, t, n) -> np.ndarray:
        """The vector x with every tangential component of CFE k equal to t[k] and the normal
        one n[k] (a new array; t, n: (m, …), one value per CFE — a stiffness, a flag); in 2D
        the same as :meth:`join`."""
        t, n = np.asarray(t), np.asarray(n)
        return np.concatenate([t] * self.n_t + [n])

    def zeros(self, *trailing: int, dtype=float) -> np.ndarray:
        """A zero array (n, *trailing) of contact unknowns."""
        return np.zeros((self.n,) + tuple(trailing), dtype)

    # ---- index arrays -----------------------------------------------------------------------
    @cached_property
    def tangential_rows(self) -> np.ndarray:
        """Rows of the tangential components: (m,) in 2D, (m, n_t) in 3D."""
        r = np.arange(self.n_tangential).reshape(self.n_t, self.m).T
        r = r[:, 0].copy() if self.n_t == 1 else r.copy()
        r.setflags(write=False)
        return r

    @cached_property
    def normal_rows(self) -> np.ndarray:
        """Rows of the normal components, (m,)."""
        r = np.arange(self.n_tangential, self.n)
        r.setflags(write=False)
        return r

    def rows(self, cfes) -> np.ndarray:
        """Rows of the components of the CFEs ``cfes`` (an index or index array):
        (…, 1 + n_t), columns t₁[, t₂], n."""
        k = np.asarray(cfes)
        return k[..., None] + self.m * np.arange(self.n_c)

    def index(self, cfes, j) -> np.ndarray:
        """The row of component j (j < n_t tangential, j = n_t normal) of CFE(s) ``cfes``."""
        return np.asarray(j) * self.m + np.asarray(cfes)

    def block(self, x: np.ndarray, k: int) -> np.ndarray:
        """The components (t₁[, t₂], n) of CFE k in x, (1 + n_t, …)."""
        return x[self.rows(k)]

    def cfe_of(self, j) -> np.ndarray:
        """The CFE of row j."""
        return np.asarray(j) % self.m

    def component_of(self, j) -> np.ndarray:
        """The component (0 … n_t) of row j."""
        return np.asarray(j) // self.m

    def partner(self, j) -> np.ndarray:
        """The other component of row j's CFE in 2D (tangential k ↔ normal m + k), the one
        component a FREE relation row couples (slip: Q' = σ f p')."""
        if self.n_t != 1:
            raise NotImplementedError("a single partner component exists only in 2D (n_t = 1)")
        j = np.asarray(j)
        return np.where(j < self.m, j + self.m, j - self.m)

    # ---- local basis and the contact operator -----------------------------------------------
    def basis(self, tangent: np.ndarray, normal: np.ndarray) -> np.ndarray:
        """The local basis of every CFE, (m, 1 + n_t, dim): rows t₁[, t₂], n.

        ``tangent``: (m, dim) in 2D (t = (n_y, −n_x), contact/geometry.py), (m, n_t, dim) in
        3D; ``normal``: (m, dim), unit, from S− to S+."""
        tangent, normal = np.asarray(tangent, float), np.asarray(normal, float)
        if tangent.ndim == 2:
            tangent = tangent[:, None, :]
        if tangent.shape[:2] != (self.m, self.n_t) or normal.shape != (self.m, tangent.shape[2]):
            raise ValueError(f"ContactLayout.basis: tangents {tangent.shape} and normals "
                             f"{normal.shape} do not fit {self.m} CFEs with n_t = {self.n_t}")
        return np.concatenate([tangent, normal[:, None, :]], axis=1)

    def operator_rows(self, basis: np.ndarray) -> np.ndarray:
        """The rows of B per CFE, (m, 1 + n_t, dim): +t_j for the tangential components, −n for
        the normal one (u_n = −n · (u⁺ − u⁻) ≤ 0: no interpenetration)."""
        sign = np.ones(self.n_c)
        sign[-1] = -1.0
        return basis * sign[None, :, None]


@lru_cache(maxsize=16)
def _of_size(cls, n: int, n_t: int) -> ContactLayout:
    return cls._make(n, n_t)


__all__ = ["ContactLayout"]
