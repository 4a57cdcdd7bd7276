"""Discrete models: a structure given by its matrices (stiffness, contact rows, loads).

For researchers and textbook systems: the same event-driven solver, results and reports as a
finite-element :class:`~stepcontact.model.Model`, without a mesh.  The degrees of freedom are
numbered 0 … n−1 (optionally named); CFE k is given by two rows over them (three with a
second tangential direction, 3D):

.. math::

    u_{nk} = -\\,a_k \\cdot u - g_k^0, \\qquad u_{\\tau k} = t_k \\cdot u
    \\quad [\\,u_{\\tau 2 k} = t_{2k} \\cdot u\\,]

``a_k`` (``normal_rows[k]``) gives the *opening* of the contact, the growth of the distance
between its two sides (n·(u⁺ − u⁻) in the notation of :mod:`stepcontact.contact.geometry`), and
``t_k`` (``tangent_rows[k]``) the slip of the S+ side relative to S− along the CFE tangent.  So
the gap is g_k⁰ + a_k · u ≥ 0 (u_n ≤ 0: no interpenetration), N_k ≤ 0 is compression and
|Q_k| ≤ −f_k N_k.  The contact forces act on the structure as K u = f + a_k (−N_k) − t_k Q_k:
a compressed contact pushes its S+ side open, friction opposes the slip.

With ``tangent2_rows`` (rows t₂ₖ) every CFE has two tangential directions (n_t = 2, a point
on a surface in space): the slip is the vector (t₁ₖ · u, t₂ₖ · u), the friction force
(Q₁ₖ, Q₂ₖ) lies in a regular polygon of ``facets`` sides inscribed in the disc of radius
−f_k N_k (the faceted Coulomb cone, :mod:`stepcontact.contact.faceted`), and the forces act
as K u = f + a_k (−N_k) − t₁ₖ Q₁ₖ − t₂ₖ Q₂ₖ.

Example: a point on a rough floor (DOFs u_x, u_y; u_y > 0 lifts it), pressed down, then pushed
along x:

>>> import stepcontact as sc                                           # doctest: +SKIP
>>> dm = sc.DiscreteModel(
...     K=[[2e3, -1e3], [-1e3, 2e3]], normal_rows=[[0, 1]], tangent_rows=[[1, 0]],
...     loads={"press": {"uy": -1.0}, "push": {"ux": 1.0}}, friction=0.5,
...     dof_names=("ux", "uy"),
...     program=[sc.Segment("press", 100.0), sc.Segment("push", 300.0)])
>>> round(sc.solve_static(dm).multipliers[1].first_slip, 9)           # doctest: +SKIP
50.0
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from stepcontact.enums import MAX_FACETS
from stepcontact.errors import ModelError
from stepcontact.model.loads import LoadPattern
from stepcontact.model.structure import Model, Segment

#: relative asymmetry of K accepted as round-off
SYMMETRY_RTOL = 1e-10
#: DOF count up to which K is checked to be positive semi-definite by its eigenvalues
PSD_CHECK_MAX = 400


def _matrix(value, item: str, shape: tuple[int | None, int | None]) -> sp.csr_matrix:
    """A finite real sparse matrix of ``shape`` (None: any size) from dense or sparse input."""
    if sp.issparse(value):
        A = sp.csr_matrix(value, dtype=float)
    else:
        try:
            a = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise ModelError(item, "must be a matrix of numbers") from None
        if a.ndim == 1 and shape[0] is not None and shape[0] <= 1:
            a = a[None, :]
        if a.ndim != 2:
            raise ModelError(item, f"must be a 2D matrix, got an array of shape {a.shape}")
        A = sp.csr_matrix(a)
    for j, want in enumerate(shape):
        if want is not None and A.shape[j] != want:
            raise ModelError(item, f"has shape {A.shape}, expected "
                             f"{tuple('any' if w is None else w for w in shape)}")
    if not np.all(np.isfinite(A.data)):
        raise ModelError(item, "contains NaN or inf")
    A.eliminate_zeros()
    return A


def _per_cfe(value, m: int, item: str, *, low: float = 0.0, inf_ok: bool = False,
             strict: bool = False) -> np.ndarray:
    """A value per CFE (a scalar for all of them, or m values) checked to be ≥ ``low``
    (> with ``strict``), finite unless ``inf_ok``."""
    a = np.asarray(value, dtype=float)
    if a.ndim == 0:
        a = np.full(m, float(a))
    if a.shape != (m,):
        raise ModelError(item, f"give one value or {m} (one per CFE), got shape {a.shape}")
    bad = np.isnan(a) | (~np.isfinite(a) & ~inf_ok) | (a <= low if strict else a < low)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        cmp = ">" if strict else "≥"
        raise ModelError(f"{item}[{k}]", f"must be {cmp} {low:g}"
                         f"{'' if inf_ok else ' and finite'}, got {a[k]}")
    return a


@dataclass(frozen=True, eq=False)
class DiscreteModel:
    """A structure given by matrices: stiffness, contact rows, loads, supports.

    Parameters
    ----------
    K : (n, n) array or sparse matrix
        Symmetric stiffness of the structure without its contacts, N/m (N·m/rad for
        rotations).  Springs to the ground are part of K.
    normal_rows : (m, n)
        Row k gives the opening a_k · u of CFE k: u_n = −a_k · u − g_k⁰ (module docstring).
    tangent_rows : (m, n)
        Row k gives the slip u_τ = t_k · u of CFE k (its first tangential direction t₁ in 3D).
    loads : {pattern: force vector}
        Forces per unit load factor, N: an (n,) vector, or {dof: value} (a DOF by index or
        by name).
    program : sequence of Segment
        The load program, as for a :class:`~stepcontact.model.Model`.
    fixed : sequence of DOFs, or (n,) bool
        DOFs held at zero (their reactions are ``res.reaction("fixed", dof_name)``).
    prescribed : {pattern: {dof: value}}
        Displacements per unit load factor of ``pattern`` (m or rad); those DOFs are held
        from the start of the program (reactions ``res.reaction(pattern, dof_name)``).
    gaps : float or (m,)
        Initial gaps g⁰ ≥ 0, m.
    friction : float or (m,)
        Friction coefficients f ≥ 0.
    kn, kt : float or (m,)
        Contact-layer stiffnesses C_n, C_τ > 0 of eq. (11), N/m (``inf``: rigid contact).
    cn : float or (m,)
        Normal damping of the contact layer, N·s/m (≥ 0; dynamics only: a Kelvin–Voigt layer,
        which needs a finite ``kn``).
    bond : Bond, or a sequence of m Bond or None, optional
        Initial strength of the CFEs (eq. (12), :class:`~stepcontact.model.bond.Bond`; with
        area 1, its strengths are the CFE's limit forces N_R, Q_R in N); its ``friction``,
        if given, replaces ``friction`` after the break.  Bonded CFEs need zero gaps.
    names : str or sequence of m str
        CFE names: CFEs of one name form an interface of the result (``res.interface_names``;
        ``local`` numbers them in order).  One string names them all.
    dof_names : sequence of n str, optional
        Names of the DOFs (default ``u0``, ``u1``, …), for loads, supports and reactions.
    dof_axes : {dof: axis} or (n, 2) array, optional
        Which DOFs are translations along which axis, for a ground acceleration
        (``solve_dynamic(ground_acceleration=...)``): ``"x"``, ``"y"`` or a unit vector
        (dx, dy) per translational DOF (by index or name); the others (rotations, internal
        DOFs) are not moved by the ground.  An (n, 2) array gives the axis of every DOF (zero
        rows: none).  Stored as that (n, 2) array; without it a ground acceleration is
        refused (it would load nothing).  In 3D (``tangent2_rows``) also ``"z"``, vectors
        (dx, dy, dz) and an (n, 3) array.
    name : str
    tangent2_rows : (m, n), optional
        Row k gives the slip u_τ2 = t₂ₖ · u of CFE k along its second tangential direction
        (3D: a point on a surface; n_t = 2).  Without it n_t = 1 (2D).  The rows of a CFE
        are t₁ (``tangent_rows``), t₂, a (``normal_rows``); the forces act on the structure
        as K u = f + a (−N) − t₁ Q₁ − t₂ Q₂, and (Q₁, Q₂) obeys the faceted Coulomb cone.
        A CFE with friction needs t₁ and t₂ independent.
    facets : int
        Number k of facets of the faceted Coulomb cone (3D: 2 < k ≤ ``MAX_FACETS`` = 128;
        default 8): the regular k-gon with its vertices on the circle of radius f|N|, so the
        limit force is f|N| cos(π/k) ≤ |Q| ≤ f|N| (relative error ≤ 1 − cos(π/k)).  In 2D
        only the default is accepted (the two "facets" there are slip+ and slip−).
    facet_angle : float or (m,)
        Direction of vertex 0 of each CFE's polygon, rad, measured from t₁ towards t₂
        (3D only; default 0).
    facet_stagger : bool
        Turn every other CFE's polygon (the odd-numbered CFEs) by π/k more, so that
        neighbouring CFEs do not share their facet directions (3D only).
    facet_adaptive : bool
        Turn each CFE's polygon at its first slip so that a vertex lies on its tangential
        force, the direction a cone would slip in (once, at that event; 3D only).

    In 3D (``tangent2_rows`` given) a bonded joint (``bond``, eq. (12)) has its strength
    surface written on the cone's polygon (|Q| ≤ … becomes d_i · Q ≤ cos(π/k) …, the same
    inner approximation as the friction limit) and breaks into the faceted Coulomb law; the
    faceted law does not yet take a residual cohesion after the break (refused with a
    :class:`~stepcontact.errors.ModelError`).  Dynamics runs in 3D as in 2D (contact-layer
    damping ``cn``, a ground acceleration along (dx, dy, dz) with ``dof_axes`` 'x', 'y', 'z').

    The CFEs carry no geometry: in the result their coordinates and normals are NaN, their
    position along the interface is their number within their name and their area is 1 (so
    σ_n and τ equal N and Q in value).  Plots and exports of the deformed mesh and results
    per node are not available (a ValueError says so); everything else (events,
    multipliers, N, Q, states, reactions, summaries, result files, the interface diagrams)
    is the same as for a finite-element model.

    Example
    -------
    >>> dm = DiscreteModel([[1e3]], [[1.0]], [[0.0]], loads={"P": [-1.0]},
    ...                    program=[Segment("P", 10.0)])                   # doctest: +SKIP
    """

    K: object
    normal_rows: object
    tangent_rows: object
    loads: Mapping = field(default_factory=dict)
    program: Sequence[Segment] = ()
    fixed: object = ()
    prescribed: Mapping = field(default_factory=dict)
    gaps: object = 0.0
    friction: object = 0.0
    kn: object = np.inf
    kt: object = np.inf
    cn: object = 0.0
    bond: object = None
    names: object = "contact"
    dof_names: Sequence[str] | None = None
    dof_axes: object = None
    name: str = "discrete"
    tangent2_rows: object = None
    facets: int = 8
    facet_angle: object = 0.0
    facet_stagger: bool = False
    facet_adaptive: bool = False

    def __post_init__(self):
        put = object.__setattr__
        K = _matrix(self.K, "K", (None, None))
        n = K.shape[0]
        if K.shape != (n, n) or n == 0:
            raise ModelError("K", f"must be a square, non-empty matrix, got shape {K.shape}")
        asym = abs(K - K.T)
        scale = float(abs(K).max()) if K.nnz else 0.0
        if asym.nnz and float(asym.max()) > SYMMETRY_RTOL * scale:
            r, c = (int(v[0]) for v in asym.nonzero())
            raise ModelError("K", f"is not symmetric: K[{r}, {c}] = {K[r, c]:g} but "
                             f"K[{c}, {r}] = {K[c, r]:g}")
        diag = K.diagonal()
        if np.any(diag < 0):
            d = int(np.flatnonzero(diag < 0)[0])
            raise ModelError("K", f"has a negative diagonal entry K[{d}, {d}] = {diag[d]:g}: "
                             "a stiffness must be positive semi-definite")
        if n <= PSD_CHECK_MAX and scale > 0:
            low = float(np.linalg.eigvalsh(K.toarray())[0])
            if low < -1e-10 * scale * n:
                raise ModelError("K", f"is not positive semi-definite (an eigenvalue is "
                                 f"{low:.3g}): a stiffness must be")
        put(self, "K", K)

        names = self.dof_names
        if names is None:
            names = tuple(f"u{i}" for i in range(n))
        else:
            names = tuple(str(v) for v in names)
            if len(names) != n:
                raise ModelError("dof_names", f"give {n} names (one per DOF), got {len(names)}")
            dup = sorted({v for v in names if names.count(v) > 1})
            if dup:
                raise ModelError("dof_names", f"duplicate name '{dup[0]}'")
        put(self, "dof_names", names)
        put(self, "dof_axes", self._axes(self.dof_axes))

        An = _matrix(self.normal_rows, "normal_rows", (None, n))
        m = An.shape[0]
        At = _matrix(self.tangent_rows, "tangent_rows", (m, n))
        At2 = None if self.tangent2_rows is None else _matrix(self.tangent2_rows,
                                                              "tangent2_rows", (m, n))
        put(self, "tangent2_rows", At2)
        self._facet_options(m)
        for item, A in (("normal_rows", An), ("tangent_rows", At)):
            empty = np.flatnonzero(A.getnnz(axis=1) == 0)
            if empty.size and item == "normal_rows":
                raise ModelError(f"normal_rows[{int(empty[0])}]", "is all zero: the CFE "
                                 "would not connect anything")
        put(self, "normal_rows", An)
        put(self, "tangent_rows", At)
        put(self, "gaps", _per_cfe(self.gaps, m, "gaps"))
        put(self, "friction", _per_cfe(self.friction, m, "friction"))
        put(self, "kn", _per_cfe(self.kn, m, "kn", inf_ok=True, strict=True))
        put(self, "kt", _per_cfe(self.kt, m, "kt", inf_ok=True, strict=True))
        put(self, "cn", _per_cfe(self.cn, m, "cn"))
        rigid_damped = (self.cn > 0) & ~np.isfinite(self.kn)
        if rigid_damped.any():
            k = int(np.flatnonzero(rigid_damped)[0])
            raise ModelError(f"cn[{k}]", "a damped contact layer needs a finite stiffness kn "
                             "(the damping acts in the layer)")
        put(self, "bond", self._bonds(m))
        frictional = self.friction > 0
        for item, T in (("tangent_rows", At), ("tangent2_rows", At2)):
            no_t = np.zeros(m, bool) if T is None else T.getnnz(axis=1) == 0
            if np.any(frictional & no_t):
                k = int(np.flatnonzero(frictional & no_t)[0])
                raise ModelError(f"{item}[{k}]", f"is all zero but the CFE has friction "
                                 f"{self.friction[k]:g}: give its slip row or friction 0")
        if At2 is not None:
            self._refuse_3d(At, At2, frictional)
        cfe_names = self.names
        if isinstance(cfe_names, str):
            cfe_names = (cfe_names,) * m
        else:
            cfe_names = tuple(str(v) for v in cfe_names)
            if len(cfe_names) != m:
                raise ModelError("names", f"give one name or {m} (one per CFE), got "
                                 f"{len(cfe_names)}")
        put(self, "names", cfe_names)

        fixed = self._dof_mask(self.fixed, "fixed")
        put(self, "fixed", fixed)
        if not isinstance(self.loads, Mapping):
            raise ModelError("loads", "must be a mapping {pattern: force vector}")
        if not isinstance(self.prescribed, Mapping):
            raise ModelError("prescribed", "must be a mapping {pattern: {dof: value}}")
        loads = {str(p): self._vector(v, f"loads['{p}']") for p, v in self.loads.items()}
        prescribed = {}
        for p, spec in self.prescribed.items():
            item = f"prescribed['{p}']"
            if not isinstance(spec, Mapping):
                raise ModelError(item, "must be a mapping {dof: value}")
            u = self._vector(spec, item)
            mask = self._dof_mask(list(spec), item)
            both = mask & fixed
            if both.any():
                raise ModelError(item, f"DOF '{names[int(np.flatnonzero(both)[0])]}' is also "
                                 "in 'fixed'")
            prescribed[str(p)] = {names[d]: float(u[d]) for d in np.flatnonzero(mask)}
        put(self, "loads", loads)
        put(self, "prescribed", prescribed)
        put(self, "program", tuple(self.program))
        for i, seg in enumerate(self.program):
            if not isinstance(seg, Segment):
                raise ModelError(f"program[{i}]", f"must be a Segment, got {type(seg).__name__}")
        self.as_model().segments_resolved()  # names the segment that does not chain

    # ---- input helpers --------------------------------------------------------------------
    @property
    def ndof(self) -> int:
        return self.K.shape[0]

    @property
    def m(self) -> int:
        return self.normal_rows.shape[0]

    @property
    def n_t(self) -> int:
        """Tangential directions per CFE: 1 (2D), 2 with ``tangent2_rows`` (3D)."""
        return 1 if self.tangent2_rows is None else 2

    def _facet_options(self, m: int) -> None:
        """Check and store ``facets``, ``facet_angle`` (m,), ``facet_stagger`` and
        ``facet_adaptive``."""
        put = object.__setattr__
        k = self.facets
        if isinstance(k, bool) or not isinstance(k, int | np.integer):
            raise ModelError("facets", f"must be an integer number of facets, got {k!r}")
        stagger, adaptive = self.facet_stagger, self.facet_adaptive
        for item, flag in (("facet_stagger", stagger), ("facet_adaptive", adaptive)):
            if not isinstance(flag, bool | np.bool_):
                raise ModelError(item, f"must be True or False, got {flag!r}")
        try:
            angle = np.asarray(self.facet_angle, dtype=float)
        except (TypeError, ValueError):
            raise ModelError("facet_angle", "must be a number (rad) or one per CFE") from None
        if angle.ndim == 0:
            angle = np.full(m, float(angle))
        if angle.shape != (m,):
            raise ModelError("facet_angle", f"give one value or {m} (one per CFE), got shape "
                             f"{angle.shape}")
        if not np.all(np.isfinite(angle)):
            c = int(np.flatnonzero(~np.isfinite(angle))[0])
            raise ModelError(f"facet_angle[{c}]", f"must be finite (rad), got {angle[c]}")
        if self.tangent2_rows is None:
            for item, bad in (("facets", int(k) != 8), ("facet_angle", np.any(angle != 0.0)),
                              ("facet_stagger", bool(stagger)),
                              ("facet_adaptive", bool(adaptive))):
                if bad:
                    raise ModelError(item, "a faceted cone needs two tangential directions "
                                     "(tangent2_rows); in 2D the friction limit has exactly "
                                     "two facets, slip+ and slip−")
        elif not 2 < int(k) <= MAX_FACETS:
            raise ModelError("facets", f"a faceted Coulomb cone has 3 … {MAX_FACETS} facets, "
                             f"got {k}")
        put(self, "facets", int(k))
        put(self, "facet_angle", angle)
        put(self, "facet_stagger", bool(stagger))
        put(self, "facet_adaptive", bool(adaptive))

    def _refuse_3d(self, At: sp.csr_matrix, At2: sp.csr_matrix, frictional: np.ndarray) -> None:
        """What the faceted (3D) law does not take yet, and parallel tangent rows."""
        why = "is not available with two tangential directions (tangent2_rows) yet"
        residual = np.nan_to_num(self.bond[:, 4]) > 0 if self.bond.shape[1] > 4 else []
        if np.any(residual):
            raise ModelError(f"bond[{int(np.flatnonzero(residual)[0])}]",
                             f"a residual cohesion after a bond's break {why}")
        t11 = np.asarray(At.multiply(At).sum(axis=1)).ravel()
        t22 = np.asarray(At2.multiply(At2).sum(axis=1)).ravel()
        t12 = np.asarray(At.multiply(At2).sum(axis=1)).ravel()
        parallel = frictional & (t11 * t22 - t12 ** 2 <= 1e-12 * t11 * t22)
        if parallel.any():
            k = int(np.flatnonzero(parallel)[0])
            raise ModelError(f"tangent2_rows[{k}]", f"is parallel to tangent_rows[{k}]: the "
                             "two tangential directions of a CFE with friction must be "
                             "independent")

    def dof(self, key, item: str = "dof") -> int:
        """Index of a DOF given by index or by name."""
        n = self.K.shape[0]
        if isinstance(key, str):
            if key not in self.dof_names:
                raise ModelError(item, f"no DOF named '{key}' (DOFs: "
                                 f"{', '.join(self.dof_names[:12])}{' …' if n > 12 else ''})")
            return self.dof_names.index(key)
        if isinstance(key, bool) or not isinstance(key, int | np.integer):
            raise ModelError(item, f"a DOF is an index or a name, got {key!r}")
        if not 0 <= int(key) < n:
            raise ModelError(item, f"DOF {key} does not exist (DOFs 0…{n - 1})")
        return int(key)

    def _bonds(self, m: int) -> np.ndarray:
        """The bond columns (m, 5) of the law (NaN rows: no bond); sets the friction after
        the break where a bond gives one."""
        from stepcontact.model.bond import Bond

        out = np.full((m, 5), np.nan)
        spec = self.bond
        if isinstance(spec, np.ndarray) and spec.shape == (m, 4):  # without C_r: 0
            spec = np.column_stack([spec, np.where(np.isnan(spec[:, 0]), np.nan, 0.0)])
        if spec is None or isinstance(spec, np.ndarray) and spec.shape == (m, 5):
            return out if spec is None else np.asarray(spec, float)
        bonds = [spec] * m if isinstance(spec, Bond) else list(spec)
        if len(bonds) != m:
            raise ModelError("bond", f"give one Bond or {m} (one per CFE, None for none), got "
                             f"{len(bonds)}")
        for k, b in enumerate(bonds):
            if b is None:
                continue
            if not isinstance(b, Bond):
                raise ModelError(f"bond[{k}]", f"must be a Bond or None, got "
                                 f"{type(b).__name__}")
            if self.gaps[k] > 0:
                raise ModelError(f"bond[{k}]", f"a bonded CFE must be closed: its gap is "
                                 f"{self.gaps[k]:g} m")
            out[k] = b.arrays(np.zeros((1, 2)), np.ones(1), f"bond[{k}]")[0]
            if b.friction is not None:
                self.friction[k] = float(b.friction)
        return out

    def _axes(self, spec) -> np.ndarray:
        """The (n, dim) unit axes of the translational DOFs (zero rows: not a translation;
        dim = 3 with ``tangent2_rows``, axes 'x', 'y', 'z', else 2)."""
        n = self.K.shape[0]
        dim = 2 if self.tangent2_rows is None else 3
        names = ("x", "y", "z")[:dim]
        vec = "(dx, dy)" if dim == 2 else "(dx, dy, dz)"
        if spec is None:
            return np.zeros((n, dim))
        if not isinstance(spec, Mapping):
            try:
                a = np.array(spec, dtype=float)
            except (TypeError, ValueError):
                raise ModelError("dof_axes", f"give {{dof: {' | '.join(map(repr, names))} | "
                                 f"{vec}}} or an (n, {dim}) array") from None
            if a.shape != (n, dim) or not np.all(np.isfinite(a)):
                raise ModelError("dof_axes", f"an array of axes must have shape ({n}, {dim}) "
                                 f"and finite entries, got shape {a.shape}")
            spec = {i: a[i] for i in range(n) if np.any(a[i])}
        out = np.zeros((n, dim))
        for key, axis in spec.items():
            item = f"dof_axes[{key!r}]"
            d = self.dof(key, item)
            if isinstance(axis, str):
                if axis not in names:
                    raise ModelError(item, f"an axis is {', '.join(map(repr, names))} or a "
                                     f"vector {vec}, got '{axis}'")
                out[d] = np.eye(dim)[names.index(axis)]
                continue
            try:
                v = np.asarray(axis, dtype=float)
            except (TypeError, ValueError):
                v = np.zeros(0)
            norm = float(np.linalg.norm(v)) if v.shape == (dim,) else np.nan
            if not np.isfinite(norm) or norm == 0.0:
                raise ModelError(item, f"an axis is {', '.join(map(repr, names))} or a nonzero "
                                 f"vector {vec}, got {axis!r}")
            out[d] = v / norm
        return out

    def _dof_mask(self, spec, item: str) -> np.ndarray:
        n = self.K.shape[0]
        a = np.asarray(spec) if not isinstance(spec, str) else np.asarray([spec])
        if a.dtype == bool:
            if a.shape != (n,):
                raise ModelError(item, f"a mask must have {n} entries, got shape {a.shape}")
            return a.copy()
        mask = np.zeros(n, dtype=bool)
        for j, key in enumerate(a.reshape(-1).tolist()):
            mask[self.dof(key, f"{item}[{j}]")] = True
        return mask

    def _vector(self, spec, item: str) -> np.ndarray:
        n = self.K.shape[0]
        if isinstance(spec, Mapping):
            v = np.zeros(n)
            for key, val in spec.items():
                try:
                    val = float(val)
                except (TypeError, ValueError):
                    raise ModelError(f"{item}[{key!r}]", f"must be a number, got {val!r}") from None
                v[self.dof(key, f"{item}[{key!r}]")] += val
        else:
            try:
                v = np.asarray(spec.toarray() if sp.issparse(spec) else spec, dtype=float)
            except (TypeError, ValueError):
                raise ModelError(item, "must be a vector of numbers or {dof: value}") from None
            v = v.reshape(-1) if v.size == n else v
            if v.shape != (n,):
                raise ModelError(item, f"must have {n} entries (one per DOF), got shape "
                                 f"{v.shape}")
        if not np.all(np.isfinite(v)):
            raise ModelError(item, "contains NaN or inf")
        return v

    # ---- what the solver and the results need ---------------------------------------------
    @property
    def pattern_names(self) -> tuple[str, ...]:
        return tuple(dict.fromkeys([*self.loads, *self.prescribed]))

    def as_model(self) -> Model:
        """The load program as a :class:`~stepcontact.model.Model` without bodies (patterns by
        name only): what the solver reads of a model besides the matrices."""
        return Model(patterns=tuple(LoadPattern(p) for p in self.pattern_names),
                     program=self.program, name=self.name)

    def prescribed_vectors(self, pattern: str) -> tuple[np.ndarray, np.ndarray]:
        """(u (n,) per unit factor, prescribed DOFs) of ``pattern``."""
        u = np.zeros(self.ndof)
        spec = self.prescribed.get(pattern, {})
        dofs = np.array(sorted(self.dof(k) for k in spec), dtype=np.int64)
        for k, v in spec.items():
            u[self.dof(k)] = v
        return u, dofs

    def segments_resolved(self) -> list[tuple[str, float, float]]:
        return self.as_model().segments_resolved()

    def replace(self, **changes) -> DiscreteModel:
        """A copy with fields replaced (checked again)."""
        return dataclasses.replace(self, **changes)

    def add(self, *segments: Segment) -> DiscreteModel:
        """A copy with ``segments`` appended to the load program."""
        return self.replace(program=(*self.program, *segments))


__all__ = ["DiscreteModel"]
