"""Scheme relations as per-CFE blocks (:class:`stepcontact.contact.laws.Relations`).

* With two tangential components (3D: n = 3m contact unknowns) and random blocks — rows that
  couple all three components, facet rows d·Q' − μ p' = r, along-facet rows e·u_τ' = r,
  fixed, spring and free rows — the rates of :class:`SchemeSolver` equal a direct solve of the
  full (uncondensed) system

      K u' + Bᵀ s' = f',    S s' + W (B u' + e) = r      (per CFE: Σ_c S s_c' + W w_c' = r)

  assembled here from K and B alone (no G, no D), to 1e-10 relative: for a first scheme, for
  low-rank (Woodbury) updates of it, and with the scheme matrix in float32 refined against the
  exact operator.  The scheme matrix, A t and Aᵀ y equal the matrix written entry by entry from
  the block formula A_j = Σ_c S_jc e_c − Σ_c (S_jc d_c + W_jc) G_c.
* In 2D the blocks that :class:`CoulombLaw` writes for open, stuck (rigid and compliant),
  slipping (either way, exact and article), frictionless, bonded and held CFEs are the old
  relation kinds (FIXED, SPRING, FREE with its coupling), checked row by row by hand.
"""

from __future__ import annotations

import numpy as np
import pytest

from stepcontact.contact.bond import BondedJointLaw
from stepcontact.contact.laws import (
    BONDED,
    CLOSED,
    FIXED,
    FREE,
    OPEN,
    SLIP_NEG,
    SLIP_POS,
    SPRING,
    STICK,
    CoulombLaw,
    Relations,
)
from stepcontact.contact.layout import ContactLayout
from stepcontact.solver.schemes import (
    MechanismError,
    SchemeSolver,
    scheme_apply,
    scheme_apply_t,
    scheme_rhs,
    scheme_rows,
)

#: relative tolerance of the rates against the direct solve of the full system (the condensed
#: and the full system are equal in exact arithmetic; the problems are conditioned to 1e3..1e5)
RTOL = 1e-10


# ---- a small structure and random relation blocks ----------------------------------------------
def _structure(m: int, n_t: int, seed: int = 0):
    """A random SPD K (ndof × ndof), a random contact operator B (m (1 + n_t) × ndof, rows in
    the layout's component-major order) and the condensation G = B K₀⁻¹ Bᵀ with
    K₀ = K + Bᵀ D B, d_j = Σ_a B_ja² K_aa (as in :mod:`stepcontact.solver.condensation`)."""
    rng = np.random.default_rng(seed)
    lay = ContactLayout(m, n_t)
    ndof = lay.n + 6
    X = rng.standard_normal((ndof, ndof))
    K = X @ X.T + ndof * np.eye(ndof)
    B = rng.standard_normal((lay.n, ndof))
    d = (B**2) @ np.diag(K)
    K0 = K + B.T @ (d[:, None] * B)
    G = B @ np.linalg.solve(K0, B.T)
    G = 0.5 * (G + G.T)
    return lay, K, K0, B, G, d


def _random_blocks(lay: ContactLayout, rng: np.random.Generator, K_scale: float) -> Relations:
    """Relations of every form a law may write, picked at random per CFE component row:
    free (s_i' = r), fixed (w_i' = r), spring (s_i' − C w_i' = r), a full row coupling every
    component in S and W, a facet row d·Q' − μ p' = r (S only) and an along-facet row
    e·u_τ' = r (W only, tangential rows of 3D CFEs)."""
    m, nt, nc = lay.m, lay.n_t, lay.n_c
    rel = Relations.empty(lay)
    for k in range(m):
        for i in range(nc):
            S, W = np.zeros(nc), np.zeros(nc)
            form = rng.integers(6)
            if form == 0:
                S[i] = 1.0
            elif form == 1:
                W[i] = 1.0
            elif form == 2:
                S[i], W[i] = 1.0, -K_scale * rng.uniform(0.5, 2.0)
            elif form == 3:
                S[:] = rng.uniform(0.5, 1.5, nc) * rng.choice([-1, 1], nc)
                W[:] = K_scale * 0.3 * rng.standard_normal(nc)
                S[i] = 2.0  # a dominant own component keeps the block regular
            elif form == 4:
                ang = rng.uniform(0, 2 * np.pi)
                direction = np.array([np.cos(ang), np.sin(ang)])[:nt]
                S[:nt] = direction / np.linalg.norm(direction)
                S[nt] = -rng.uniform(0.2, 0.8) * np.cos(np.pi / 8)
                if i == nt:  # the normal row of a facet: the normal force is its own
                    S[:nt] *= 0.1
                    S[nt] = 1.0
            else:
                if i < nt and nt == 2:
                    ang = rng.uniform(0, 2 * np.pi)
                    W[0], W[1] = -np.sin(ang), np.cos(ang)
                    W[i] = W[i] if abs(W[i]) > 0.3 else np.copysign(0.3, W[i] or 1.0)
                else:
                    W[i] = 1.0
            rel.S[k, i], rel.W[k, i] = S, W
    return rel


def _full_rates(lay, K, B, rel, f, e, r):
    """(s', w') from the full system [K, Bᵀ; W B, S] [u'; s'] = [f'; r − W e], assembled from
    the blocks (w = B u + e: e the rate of the displacements that the supports impose)."""
    n, ndof = lay.n, K.shape[0]
    Sg, Wg = np.zeros((n, n)), np.zeros((n, n))
    rows = lay.rows(np.arange(lay.m))  # (m, n_c) global rows of each CFE
    for k in range(lay.m):
        Sg[np.ix_(rows[k], rows[k])] = rel.S[k]
        Wg[np.ix_(rows[k], rows[k])] = rel.W[k]
    A = np.block([[K, B.T], [Wg @ B, Sg]])
    x = np.linalg.solve(A, np.concatenate([f, r - Wg @ e]))
    u, s = x[:ndof], x[ndof:]
    return s, B @ u + e


def _block_matrix(lay, G, d, rel):
    """A (unscaled) entry by entry: A_jc = S_jc − Σ_c' (S_jc' d_c' + W_jc') G_c'c."""
    n = lay.n
    A = np.zeros((n, n))
    for k in range(lay.m):
        rows = lay.rows(k)
        for i, j in enumerate(rows):
            for c, col in enumerate(rows):
                A[j, col] += rel.S[k, i, c]
                A[j] -= (rel.S[k, i, c] * d[col] + rel.W[k, i, c]) * G[col]
    return A


def _close(x, ref, rtol=RTOL):
    return np.abs(x - ref).max() <= rtol * np.abs(ref).max()


@pytest.mark.parametrize("n_t", [1, 2])
def test_scheme_matrix_and_products_follow_the_block_formula(n_t):
    """scheme_rows (float64, and the float32 shifted form M = D G − I), scheme_apply (A t) and
    scheme_apply_t (Aᵀ y) equal the matrix written entry by entry from the blocks: float64
    to 1e-13 of the largest entry, float32 to 1e-6 (its round-off, 6e-8 per entry)."""
    lay, K, _, B, G, d = _structure(7, n_t)
    rng = np.random.default_rng(11)
    rel = _random_blocks(lay, rng, float(np.mean(d)))
    A_ref = _block_matrix(lay, G, d, rel)
    idx = np.arange(lay.n)
    A, scale = scheme_rows(G, d, rel, idx)
    assert _close(A, scale[:, None] * A_ref, 1e-13)
    M32 = (d[:, None] * G - np.eye(lay.n)).astype(np.float32)
    A32, scale32 = scheme_rows(M32, d, rel, idx, shifted=True)
    assert _close(A32.astype(float) / scale32[:, None], A_ref, 1e-6)
    t, y = rng.standard_normal((2, lay.n))
    assert _close(scheme_apply(d, rel, scale, t, G @ t), scale * (A_ref @ t), 1e-13)
    assert _close(scheme_apply_t(d, rel, scale, y, lambda v: G @ v), A_ref.T @ (scale * y),
                  1e-13)
    T = rng.standard_normal((lay.n, 3))  # blocks of columns
    assert _close(scheme_apply(d, rel, scale, T, G @ T), scale[:, None] * (A_ref @ T), 1e-13)
    assert _close(scheme_apply_t(d, rel, scale, T, lambda v: G @ v),
                  A_ref.T @ (scale[:, None] * T), 1e-13)
    # rows picked out of the middle (the update path forms only the changed rows)
    pick = np.array([1, lay.m + 3, lay.n - 1])
    rows, sc = scheme_rows(G, d, rel, pick)
    assert _close(rows, sc[:, None] * A_ref[pick], 1e-13)


@pytest.mark.parametrize("n_t", [2, 1])
@pytest.mark.parametrize("precision", ["float64", "float32"])
def test_block_scheme_rates_equal_a_direct_solve_of_the_full_system(n_t, precision):
    """Random block relations of 8 CFEs: the rates (s', w') of the scheme solver equal the
    direct solve of the full system (:func:`_full_rates`) to 1e-10 relative — the first
    scheme (one LU), three later schemes that change 2–5 CFEs' blocks (low-rank Woodbury
    updates of it, rows changed again and changed back), the load rates alone (r = 0, the
    O(k n) update of the base's cached solution), and, in float32, after the refinement
    against the exact float64 operator."""
    lay, K, K0, B, G, d = _structure(8, n_t, seed=3)
    rng = np.random.default_rng(5)
    ndof = K.shape[0]
    f = rng.standard_normal(ndof)
    e = 1e-3 * rng.standard_normal(lay.n)
    hhat = B @ np.linalg.solve(K0, f)
    if precision == "float64":
        solver = SchemeSolver(G, d)
    else:
        M32 = (d[:, None] * G - np.eye(lay.n)).astype(np.float32)
        solver = SchemeSolver(M32, d, product=lambda t: G @ t)
    rel = _random_blocks(lay, rng, float(np.mean(d)))
    schemes = [rel]
    for n_changed in (2, 5, 3):
        new = Relations(lay, schemes[-1].S.copy(), schemes[-1].W.copy())
        other = _random_blocks(lay, rng, float(np.mean(d)))
        ks = rng.choice(lay.m, n_changed, replace=False)
        new.S[ks], new.W[ks] = other.S[ks], other.W[ks]
        schemes.append(new)
    schemes.append(rel)  # back to the base
    updated = 0
    for i, sch in enumerate(schemes):
        fac = solver.factor(sch)
        updated += fac.V is not None  # a low-rank update of the base LU
        r = 1e-3 * rng.standard_normal(lay.n)
        ds, dw = fac.solve(hhat, e, r)
        s_ref, w_ref = _full_rates(lay, K, B, sch, f, e, r)
        assert _close(ds, s_ref) and _close(dw, w_ref), i
        ds, dw = fac.load_rates(hhat, e)
        s_ref, w_ref = _full_rates(lay, K, B, sch, f, e, np.zeros(lay.n))
        assert _close(ds, s_ref) and _close(dw, w_ref), i
        # the unscaled right-hand side b of A t' = b agrees with the full system: A t_ref = b
        t_ref = s_ref - d * (w_ref - e)
        A_ref = _block_matrix(lay, G, d, sch)
        b = scheme_rhs(d, sch, hhat, e, 0.0)
        assert _close(A_ref @ t_ref, b, 1e-9)
    assert updated >= 2  # the Woodbury path is exercised (not only full factorisations)


def test_dependent_rows_of_a_block_are_a_mechanism():
    """Two rows of one CFE's block that are the same relation make the scheme singular: a
    MechanismError (float64 LU and float32 confirmed by the exact operator), not a solve."""
    lay, K, _, B, G, d = _structure(5, 2, seed=8)
    rel = _random_blocks(lay, np.random.default_rng(2), float(np.mean(d)))
    rel.S[2, 0], rel.W[2, 0] = rel.S[2, 1], rel.W[2, 1]
    with pytest.raises(MechanismError):
        SchemeSolver(G, d).factor(rel)
    M32 = (d[:, None] * G - np.eye(lay.n)).astype(np.float32)
    with pytest.raises(MechanismError):
        SchemeSolver(M32, d, product=lambda t: G @ t).factor(rel)
    with pytest.raises(ValueError, match="read-only"):  # used relations do not change
        rel.S[0, 0, 0] = 2.0


# ---- 2D: the blocks of the Coulomb law are the old relation kinds --------------------------------
def test_coulomb_blocks_are_the_2d_relation_kinds():
    """CoulombLaw's blocks for the 2D states, by hand (rows: 0 tangential, 1 normal; columns:
    Q, p in S and u_τ, u_n in W):

    * open: Q' = r, p' = r (FREE, no coupling): S = I, W = 0;
    * stuck rigid and bonded rigid: u_τ' = r, u_n' = r (FIXED): S = 0, W = I;
    * stuck compliant: Q' − C_τ u_τ' = r, p' − C_n u_n' = r (SPRING): S = I, W = −diag(C);
    * slip±: Q' − (±f) p' = r (FREE with couple ∓f), normal fixed;
    * slip in article mode: Q' = r (FREE, no coupling);
    * closed frictionless: Q' = r, normal fixed;
    * held normally (inert): open whatever its state.
    The same rows come from :meth:`Relations.from_kinds` of the old (kind, stiff, couple)."""
    f, kt, kn = 0.6, 2e8, 5e8
    states = np.array([OPEN, STICK, STICK, SLIP_POS, SLIP_NEG, CLOSED, BONDED, STICK])
    m = len(states)
    inf = np.inf
    law = CoulombLaw(np.arange(m), [f, f, f, f, f, 0.0, f, f],
                     [inf, inf, kn, inf, kn, inf, inf, inf],
                     [inf, inf, kt, inf, kt, inf, inf, inf],
                     held_normal=[False] * 7 + [True])
    law = BondedJointLaw(law, np.array([[np.nan] * 5] * 6 + [[1e3, 1e3, 0.5, 1.0, 0.0]] * 2))
    lay = ContactLayout(m)
    rel = Relations.empty(lay)
    law.relations(states, rel, lay)
    S, W = rel.S, rel.W
    I2, Z2 = np.eye(2), np.zeros((2, 2))
    assert np.array_equal(S[0], I2) and np.array_equal(W[0], Z2)  # open
    assert np.array_equal(S[1], Z2) and np.array_equal(W[1], I2)  # stuck rigid
    assert np.array_equal(S[2], I2) and np.array_equal(W[2], -np.diag([kt, kn]))  # compliant
    assert np.array_equal(S[3], [[1.0, -f], [0.0, 0.0]])  # slip+: Q' − f p' = r, u_n' = r
    assert np.array_equal(W[3], [[0.0, 0.0], [0.0, 1.0]])
    assert np.array_equal(S[4], [[1.0, f], [0.0, 1.0]])  # slip−, compliant normal
    assert np.array_equal(W[4], [[0.0, 0.0], [0.0, -kn]])
    assert np.array_equal(S[5], [[1.0, 0.0], [0.0, 0.0]])  # frictionless: Q' = r, u_n' = r
    assert np.array_equal(W[5], [[0.0, 0.0], [0.0, 1.0]])
    assert np.array_equal(S[6], Z2) and np.array_equal(W[6], I2)  # bonded rigid
    assert np.array_equal(S[7], I2) and np.array_equal(W[7], Z2)  # held normally: open
    article = Relations.empty(lay)
    law.relations(states, article, lay, article=True)
    assert np.array_equal(article.S[3], [[1.0, 0.0], [0.0, 0.0]])  # Q held in the step
    # the old per-component form of the same scheme
    kind_t = [FREE, FIXED, SPRING, FREE, FREE, FREE, FIXED, FREE]
    kind_n = [FREE, FIXED, SPRING, FIXED, SPRING, FIXED, FIXED, FREE]
    couple_t = [0, 0, 0, -f, f, 0, 0, 0]
    old = Relations.from_kinds(np.r_[kind_t, kind_n], np.r_[law.kt, law.kn],
                               np.r_[couple_t, np.zeros(m)])
    assert np.array_equal(old.S, rel.S) and np.array_equal(old.W, rel.W)


def test_2d_scheme_rows_keep_the_kind_formula():
    """In 2D the scheme rows from the blocks are the rows of the relation kinds,
    A_j = rs_j e_j − (rw_j + d_j rs_j) G_j + c_j (e_P − d_P G_P) (rw = 1, rs = 0 FIXED;
    rw = −C, rs = 1 SPRING; rw = 0, rs = 1 FREE; P the CFE's other component), formed here
    from that formula: equal to 1e-14 of each row's largest entry (round-off)."""
    lay, _, _, _, G, d = _structure(6, 1, seed=4)
    m, n = lay.m, lay.n
    rng = np.random.default_rng(9)
    kind = rng.integers(0, 3, n)
    stiff = float(np.mean(d)) * rng.uniform(0.5, 2, n)
    couple = np.where((kind == FREE) & (rng.random(n) < 0.6), rng.uniform(-1, 1, n), 0.0)
    rel = Relations.from_kinds(kind, stiff, couple)
    rw = np.where(kind == FIXED, 1.0, np.where(kind == SPRING, -stiff, 0.0))
    rs = np.where(kind == FIXED, 0.0, 1.0)
    P = np.r_[np.arange(m, n), np.arange(m)]
    A = rs[:, None] * np.eye(n) - (rw + d * rs)[:, None] * G
    A += couple[:, None] * (np.eye(n)[P] - d[P][:, None] * G[P])
    rows, scale = scheme_rows(G, d, rel, np.arange(n))
    big = np.abs(A).max(axis=1, keepdims=True)
    assert np.all(np.abs(rows / scale[:, None] - A) <= 1e-14 * big)
