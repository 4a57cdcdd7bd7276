"""The layout of the contact unknowns (stepcontact.contact.layout.ContactLayout).

References: the 2D ordering [all tangential; all normal] written out by hand (the ordering of
s = [Q; p] and w = [u_τ; u_n] used before the layout existed), index arithmetic by hand for a 3D
layout, and the contact operator B assembled by the explicit formula the code used before it was
built from the local basis.  Every comparison is exact (tolerance 0): the layout only moves
numbers, it never computes with them.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.sparse as sp

import stepcontact as sc
from stepcontact.contact.layout import ContactLayout
from stepcontact.fem.assembly import assemble, contact_operator


def test_2d_views_are_todays_slices_and_share_memory():
    """2D: tangential(x) is x[:m], normal(x) is x[m:] (today's slices), both views of x
    (writing into them writes into x); the index arrays are 0..m−1 and m..2m−1."""
    m = 5
    lay = ContactLayout(m)
    assert (lay.n, lay.n_c, lay.n_tangential) == (2 * m, 2, m)
    x = np.arange(2.0 * m)
    t, n = lay.split(x)
    assert np.array_equal(t, x[:m]) and np.array_equal(n, x[m:])
    assert np.shares_memory(t, x) and np.shares_memory(n, x)
    t[2] = -1.0
    n[3] = -2.0
    assert x[2] == -1.0 and x[m + 3] == -2.0
    assert np.array_equal(lay.tangential_rows, np.arange(m))
    assert np.array_equal(lay.normal_rows, np.arange(m, 2 * m))
    assert np.array_equal(lay.rows(3), [3, m + 3])
    assert np.array_equal(lay.block(x, 3), [x[3], x[m + 3]])
    assert np.array_equal(lay.partner(np.arange(2 * m)), np.r_[np.arange(m, 2 * m), np.arange(m)])
    # (2m, k) blocks of columns: the same rows
    X = np.arange(2.0 * m * 3).reshape(2 * m, 3)
    assert np.shares_memory(lay.tangential(X), X)
    assert np.array_equal(lay.normal(X), X[m:])


def test_join_inverts_split_2d_and_3d():
    """join(split(x)) == x exactly, for vectors and blocks, with n_t = 1 and 2."""
    rng = np.random.default_rng(0)
    for n_t in (1, 2):
        lay = ContactLayout(7, n_t)
        for shape in ((lay.n,), (lay.n, 4)):
            x = rng.standard_normal(shape)
            assert np.array_equal(lay.join(*lay.split(x)), x)
    assert ContactLayout.of_size(12, 2) == ContactLayout(4, 2)
    with pytest.raises(ValueError, match="not m"):
        ContactLayout.of_size(7)


def test_3d_layout_blocks():
    """n_t = 2: x = [t₁ (m); t₂ (m); n (m)]; tangential(x) is (m, 2) with row k = (x[k], x[m+k]),
    a view; the block of CFE k is (x[k], x[m+k], x[2m+k])."""
    m = 4
    lay = ContactLayout(m, 2)
    assert (lay.n, lay.n_c, lay.n_tangential) == (3 * m, 3, 2 * m)
    x = np.arange(3.0 * m)
    t = lay.tangential(x)
    assert t.shape == (m, 2)
    assert np.array_equal(t, np.c_[x[:m], x[m:2 * m]])
    assert np.shares_memory(t, x)
    t[1, 1] = -5.0
    assert x[m + 1] == -5.0
    assert np.array_equal(lay.normal(x), x[2 * m:])
    assert np.array_equal(lay.tangential_rows, np.c_[np.arange(m), m + np.arange(m)])
    assert np.array_equal(lay.normal_rows, 2 * m + np.arange(m))
    for k in range(m):
        assert np.array_equal(lay.rows(k), [k, m + k, 2 * m + k])
        assert np.array_equal(lay.block(x, k), x[[k, m + k, 2 * m + k]])
    assert np.array_equal(lay.cfe_of(lay.rows(2)), [2, 2, 2])
    assert np.array_equal(lay.component_of(lay.rows(2)), [0, 1, 2])
    with pytest.raises(NotImplementedError):
        lay.partner(0)
    basis = lay.basis(np.tile(np.eye(3)[:2], (m, 1, 1)), np.tile([0.0, 0.0, 1.0], (m, 1)))
    assert basis.shape == (m, 3, 3)
    assert np.array_equal(lay.operator_rows(basis)[0], np.diag([1.0, 1.0, -1.0]))


def _old_contact_operator(cfe, dofs):
    """B and w0 by the formula used before the local basis (rows k: t·(u⁺−u⁻), m+k:
    −n·(u⁺−u⁻)), written out without the layout."""
    m = cfe.m
    nodes = np.concatenate([cfe.plus_nodes, cfe.minus_nodes], axis=1)
    w = np.concatenate([cfe.plus_w, -cfe.minus_w], axis=1)
    valid = nodes >= 0
    safe = np.where(valid, nodes, 0)
    B = sp.lil_matrix((2 * m, dofs.ndof))
    for k in range(m):
        for a in range(nodes.shape[1]):
            if not valid[k, a]:
                continue
            for c in (0, 1):
                d = dofs.of[safe[k, a], c]
                if d < 0:
                    continue
                B[k, d] += w[k, a] * cfe.tangent[k, c]
                B[m + k, d] += -w[k, a] * cfe.normal[k, c]
    return B.tocsr(), np.r_[np.zeros(m), -cfe.gap]


def test_operator_from_basis_equals_the_explicit_formula():
    """B built from the local bases equals, entry by entry (difference exactly 0), the explicit
    2D formula, on non-matching meshes (CFE ends inside segments: three end nodes) with the
    CFEs' normals turned to arbitrary directions (every entry of the basis non-zero)."""
    mat = sc.Material(30e9, 0.2)
    bot = sc.rectangle("bot", (0, 0), (1, 0.5), 3, 2, mat, "quad8")
    top = sc.rectangle("top", (0, 0.5), (1, 1.0), 4, 2, mat, "quad4")
    model = sc.Model(bodies=[bot, top])
    model = model.add(
        sc.Support("bed", model.select("bot", y=0.0), "xy"),
        sc.Interface("joint", model.select("top", y=0.5), model.select("bot", y=0.5),
                     friction=0.5),
    )
    system = assemble(model)
    cfe = system.cfe
    assert cfe.m > 0
    rng = np.random.default_rng(1)
    ang = rng.uniform(0, 2 * np.pi, cfe.m)
    nrm = np.c_[np.cos(ang), np.sin(ang)]
    turned = dataclasses.replace(cfe, normal=nrm, tangent=np.c_[nrm[:, 1], -nrm[:, 0]])
    for c in (cfe, turned):
        B, w0 = contact_operator(c, system.dofs)
        B_ref, w0_ref = _old_contact_operator(c, system.dofs)
        assert B.shape == B_ref.shape == (2 * c.m, system.dofs.ndof)
        assert abs(B - B_ref).max() == 0.0
        assert np.array_equal(w0, w0_ref)
    assert abs(system.B - contact_operator(cfe, system.dofs)[0]).max() == 0.0
    assert np.array_equal(cfe.basis[:, 0], cfe.tangent)
    assert np.array_equal(cfe.basis[:, 1], cfe.normal)
