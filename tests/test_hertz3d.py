"""Hertz and Cattaneo–Mindlin point contact in 3D (issue 28 §5): a body with a spherical
tip (:func:`stepcontact.model.mesh.spherical_block`, hex8, refined towards the contact point)
pressed on a flat, then pushed sideways, through the static driver.

References (closed forms, independent of the code under test) and tolerances, per test:

* Hertz (frictionless, f = 0, a quarter model on a rigid plane, E* = E / (1 − ν²)): contact
  radius a = (3 P R / (4 E*))^(1/3), peak pressure p₀ = 3 P / (2 π a²), pressure
  p(r) = p₀ √(1 − r²/a²).  Measured on four meshes h = a/2.5 … a/5.5 at the contact: the
  centre CFE's pressure −N/A against p₀ (1 %, every mesh), and against Hertz's pressure
  averaged with that CFE's own weight φ (the bilinear hat over its cell, the average a nodal
  force measures), the contact radius from the second moment of the CFE forces
  (Σ N r² / Σ N = 2a²/5 for Hertz's pressure) and the contact edge (a between the last
  closed and the first open CFE along x: within one element h); the errors' order of
  convergence by ``np.polyfit`` of log error on log h (≥ 1) and the finest errors (stated
  below); equilibrium Σ N = −P/4 to 1e-9.
* Cattaneo–Mindlin (f = 0.5, the tip on an elastic block of the same material: Dundurs' β = 0,
  so pressing causes no shear and shear no pressure; E* = E / (2 (1 − ν²))): the top pressed
  down, then moved sideways along x (a rigid clamp); at every state the stick radius is
  c = a (1 − Q / (f_k P))^(1/3) within one element h (every stuck CFE at r ≤ c + h, every
  slipping one at r ≥ c − h), a from the measured P; gross sliding at Q = f_k Σ|N| (1e-9).
  The faceted cone with k facets (``facets``, vertices at ``facet_angle`` + 2πi/k) changes
  the friction coefficient along Q: f_k = f when Q points at a vertex (between two facets,
  the vertex is on the true cone) and f_k = f cos(π/k) when Q is along a facet's normal (the
  facet's distance from the axis); symmetric about Q either way, so the slip zone stays an
  annulus and Q₂ = 0 (1e-9 P).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.polynomial.legendre import leggauss
from skfem import MeshHex

import stepcontact as sc
from stepcontact.enums import ContactState, closed, slipping
from stepcontact.model.mesh import spherical_block

R = 0.1  # sphere radius, m
STEEL = sc.Material(210e9, 0.3, 7850.0)
A_NOM = 0.1 * R  # the nominal contact radius the meshes are refined for, m
TOL = 1e-9


def graded(length: float, h0: float, uniform: float, growth: float = 1.4) -> np.ndarray:
    """Grid lines on [0, length] (m): steps h0 up to ``uniform``, then growing by about
    ``growth`` each, the grown part scaled to end at ``length``."""
    k = int(math.ceil(uniform / h0 - 1e-9))
    x, h = list(h0 * np.arange(k + 1)), h0
    while x[-1] < length:
        h *= growth
        x.append(x[-1] + h)
    x = np.asarray(x)
    tail = x > k * h0
    x[tail] = k * h0 + (x[tail] - k * h0) * (length - k * h0) / (x[-1] - k * h0)
    return x


def hertz(P: float, e_star: float) -> tuple[float, float]:
    """Hertz's point contact of a sphere of radius R: a = (3 P R / (4 E*))^(1/3) (m) and
    p₀ = 3 P / (2 π a²) (Pa), P the whole load (N)."""
    a = (3 * P * R / (4 * e_star)) ** (1 / 3)
    return a, 3 * P / (2 * math.pi * a**2)


def test_spherical_block_puts_its_bottom_on_the_sphere():
    """spherical_block: every node of the named face 'bottom' on the sphere |x − (0, 0, R)| = R
    (1e-12 R), the top at z = top, the other faces at the grid's ends (1e-12 R), a column's
    nodes at z_s + ζ (top − z_s) for the layers' fractions ζ; the volume (Σ over elements = the
    integral of top − z_s over the block to 1e-2 relative: the bilinear faces cut below the
    sphere by about h²/(8R) = 0.1 mm here, measured 0.4 %);
    refusals name the body and the field."""
    xs, top = np.linspace(-0.03, 0.04, 8), 0.05
    tip = spherical_block("tip", R, xs, xs[:5], top, [0, 0.2, 0.5, 1.0], STEEL, "hex8")
    p, mesh = tip.points, tip.mesh
    face = {b: np.unique(mesh.facets[:, mesh.boundaries[b]]) for b in tip.boundary_names}
    centre = np.array([0.0, 0.0, R])
    np.testing.assert_allclose(np.linalg.norm(p[face["bottom"]] - centre, axis=1), R,
                               atol=1e-12 * R)
    assert len(face["bottom"]) == 8 * 5
    np.testing.assert_allclose(p[face["top"], 2], top, atol=1e-12 * R)
    for b, (axis, value) in {"left": (0, -0.03), "right": (0, 0.04), "front": (1, -0.03),
                             "back": (1, xs[4])}.items():
        np.testing.assert_allclose(p[face[b], axis], value, atol=1e-12 * R)
    corner = np.flatnonzero((p[:, 0] == xs[0]) & (p[:, 1] == xs[0]))
    zs = R - math.sqrt(R**2 - 2 * xs[0] ** 2)
    np.testing.assert_allclose(np.sort(p[corner, 2]), zs + np.array([0, 0.2, 0.5, 1.0])
                               * (top - zs), atol=1e-12 * R)
    from skfem import Basis, ElementHex1, Functional

    vol = Functional(lambda w: 1.0 + 0 * w.x[0]).assemble(Basis(mesh, ElementHex1()))
    g, w = leggauss(20)
    X, Y = np.meshgrid(0.035 * g + 0.005, 0.02 * g - 0.01, indexing="ij")
    exact = 0.035 * 0.02 * (np.outer(w, w) * (top - R + np.sqrt(R**2 - X**2 - Y**2))).sum()
    assert vol == pytest.approx(exact, rel=1e-2)
    with pytest.raises(sc.ModelError, match="body 'tip'.radius"):
        spherical_block("tip", -1.0, xs, xs, top, 2, STEEL)
    with pytest.raises(sc.ModelError, match="body 'tip'.*inside the sphere"):
        spherical_block("tip", 0.04, xs, xs, top, 2, STEEL)
    with pytest.raises(sc.ModelError, match="body 'tip'.*below the top"):
        spherical_block("tip", R, xs, xs, 0.001, 2, STEEL)
    with pytest.raises(sc.ModelError, match="body 'tip'.layers"):
        spherical_block("tip", R, xs, xs, top, [0, 0.5], STEEL)
    with pytest.raises(sc.ModelError, match="body 'tip'.element"):
        spherical_block("tip", R, xs, xs, top, 2, STEEL, "quad4")


# --------------------------------------------------------------------------------------------
# Hertz: a quarter of the tip on a rigid plane, frictionless
# --------------------------------------------------------------------------------------------
E_RIGID = STEEL.E / (1 - STEEL.nu**2)  # E* of an elastic sphere on a rigid flat, Pa
GROWTH = 1.8  # the growth of the steps beyond the refined zone
P_HERTZ = 4 * E_RIGID * A_NOM**3 / (3 * R)  # the load giving a = A_NOM, N (whole sphere)


def hertz_quarter(h0: float, growth: float = GROWTH) -> sc.Model:
    """The quarter x, y ≥ 0 of a tip of radius R, 0.5 R × 0.5 R × 0.5 R (= 5a each way),
    steps h0 up to 1.5 a from the contact point, on the rigid plane z = 0 (no friction):
    symmetry supports on x = 0 (u_x) and y = 0 (u_y), P/4 spread uniformly over the top;
    CFEs at the bottom nodes within 2a of the axis (the rest stays far from the plane)."""
    L = 0.5 * R
    xs = graded(L, h0, 1.5 * A_NOM, growth)
    zeta = graded(L, h0, 0.5 * A_NOM, growth) / L
    m = sc.Model(bodies=(spherical_block("tip", R, xs, xs, L, zeta, STEEL),))
    near = m.select("tip", lambda x, y, z: x**2 + y**2 <= (2 * A_NOM) ** 2 + 1e-12,
                    boundary="bottom")
    return m.add(
        sc.Support("sym_x", m.select("tip", boundary="left"), "x"),
        sc.Support("sym_y", m.select("tip", boundary="front"), "y"),
        sc.Interface("hertz", near, sc.RigidPlane("flat"), friction=0.0),
        sc.LoadPattern("P", [sc.EdgeForce(m.select("tip", boundary="top"), fz=-P_HERTZ / 4)]),
        sc.Segment("P", 1.0))


def centre_average(p0: float, a: float, h: float, n: int = 16) -> float:
    """Hertz's pressure p₀ √(1 − r²/a²) averaged over [0, h]² with the centre node's bilinear
    weight φ = (1 − x/h)(1 − y/h) (Gauss–Legendre, n × n points), Pa."""
    g, w = leggauss(n)
    X, Y = np.meshgrid(0.5 * h * (g + 1), 0.5 * h * (g + 1), indexing="ij")
    W = np.outer(w, w) * (1 - X / h) * (1 - Y / h)
    p = p0 * np.sqrt(np.maximum(1 - (X**2 + Y**2) / a**2, 0.0))
    return float((W * p).sum() / W.sum())


def test_hertz_sphere_on_a_rigid_flat_converges():
    """The frictionless quarter tip on a rigid plane, h = a/2.5, a/3.5, a/4.5, a/5.5 at the
    contact (a mid-element; 1 152 … 5 292 DOFs, 24 … 102 CFEs): Σ N = −P/4 (1e-9); the
    centre CFE's pressure within 1 % of p₀ on every mesh (measured −0.3 % … −0.5 %); against
    Hertz's pressure averaged with its weight the error falls as h^q, q ≥ 1 (measured 2.3 %,
    0.84 %, 0.37 %, 0.24 %), finest ≤ 0.5 %; the second-moment radius √(5/2 Σ N r² / Σ N)
    converges to a with q ≥ 1 (measured 2.3 %, 1.7 %, 1.05 %, 0.54 %), finest ≤ 1 %; along
    x the last closed CFE lies before a and the first open one beyond it (the contact edge
    within the element that contains a) on every mesh."""
    a, p0 = hertz(P_HERTZ, E_RIGID)
    assert a == pytest.approx(A_NOM, rel=1e-12)
    hs, p_err, a_err = [], [], []
    for div in (2.5, 3.5, 4.5, 5.5):
        h0 = a / div
        res = sc.solve_static(hertz_quarter(h0))
        assert res.status == sc.Status.COMPLETED, res.message
        N = np.asarray(res.N)[-1]
        A = np.asarray(res.cfe["area"])
        x = np.asarray(res.cfe["x"])
        r = np.hypot(x[:, 0], x[:, 1])
        assert N.sum() == pytest.approx(-P_HERTZ / 4, rel=TOL)
        centre = int(np.argmin(r))
        assert r[centre] == 0.0
        peak = -N[centre] / A[centre]
        assert peak == pytest.approx(p0, rel=0.01), f"a/{div}: {peak / p0 - 1:+.4f}"
        p_err.append(abs(peak / centre_average(p0, a, h0) - 1))
        a_err.append(abs(math.sqrt(2.5 * (N * r**2).sum() / N.sum()) / a - 1))
        touching = N < -1e-9 * np.abs(N).max()
        on_x = np.abs(x[:, 1]) <= 1e-12 * R
        last = r[on_x & touching].max()
        first = r[on_x & ~touching & (r > last)].min()
        assert last < a < first and first - last <= 1.01 * h0, (div, last / a, first / a)
        hs.append(h0)
    for name, err, finest in (("peak pressure", p_err, 0.005), ("contact radius", a_err, 0.01)):
        order = np.polyfit(np.log(hs), np.log(err), 1)[0]
        assert order >= 1.0, (name, order, err)
        assert err[-1] <= finest, (name, err)


# --------------------------------------------------------------------------------------------
# Cattaneo–Mindlin: the whole tip on an elastic block of the same material
# --------------------------------------------------------------------------------------------
F = 0.5
E_SAME = STEEL.E / (2 * (1 - STEEL.nu**2))  # E* of two equal bodies, Pa


def mindlin_model(k: int, facet_angle: float, div: float = 3.0) -> tuple[sc.Model, float]:
    """The whole tip, [−4a, 4a]² × 4a high, steps h0 = a/``div`` up to 1.2 a from the axis,
    on a block [−4a, 4a]² × 4a deep with the same (x, y) grid (node-to-facet CFEs: each tip
    node faces a block node), fixed at its bottom; f = 0.5 on the k-faceted cone.  The tip's
    top is a rigid clamp: pressed down by a²/R (segment 'press'), then moved along +x by
    a²/R (segment 'shift', far past gross sliding).  Returns (model, h0)."""
    L, h0 = 4 * A_NOM, A_NOM / div
    g = graded(L, h0, 1.2 * A_NOM, 2.0)
    xs = np.r_[-g[:0:-1], g]
    zeta = graded(L, h0, 0.5 * A_NOM, 2.0) / L
    tip = spherical_block("tip", R, xs, xs, L, zeta, STEEL)
    tol = 1e-9 * L
    mesh = MeshHex.init_tensor(xs, xs, -zeta[::-1] * L).with_boundaries(
        {"bottom": lambda q: np.abs(q[2] + L) <= tol, "top": lambda q: np.abs(q[2]) <= tol})
    flat = sc.Body.from_mesh("flat", mesh, "hex8", STEEL)
    m = sc.Model(bodies=(tip, flat))
    near = m.select("tip", lambda x, y, z: x**2 + y**2 <= (1.3 * A_NOM) ** 2 + 1e-12,
                    boundary="bottom")
    under = m.select("flat", lambda x, y, z: x**2 + y**2 <= (1.6 * A_NOM) ** 2 + 1e-12,
                     boundary="top")
    top = m.select("tip", boundary="top")
    d = A_NOM**2 / R
    return m.add(
        sc.Support("bed", m.select("flat", boundary="bottom"), "xyz"),
        sc.Interface("joint", near, under, friction=F, facets=k, facet_angle=facet_angle,
                     cfe="node-to-segment"),
        sc.LoadPattern("press", [sc.PrescribedDisplacement(top, "z", -1.0)]),
        sc.LoadPattern("shift", [sc.PrescribedDisplacement(top, "x", 1.0)]),
        sc.Segment("press", d), sc.Segment("shift", d)), h0


def stick_zone_misfit(res, f_k: float, h: float) -> tuple[float, int]:
    """How far (in elements h) the stick zone's edge lies from Mindlin's c = a (1 − Q /
    (f_k P))^(1/3) at worst over the states of the shift with 0 < Q < f_k P (a stuck CFE
    beyond c, or a slipping one inside c; a and P measured at each state), and the number
    of states checked."""
    N, Q, state = np.asarray(res.N), np.asarray(res.Q_t), np.asarray(res.state)
    x = np.asarray(res.cfe["x"])
    r = np.hypot(x[:, 0], x[:, 1])
    worst, checked = -np.inf, 0
    for i in np.flatnonzero(np.asarray(res.segment) == 1):
        P = -N[i].sum()
        ratio = abs(Q[i, :, 0].sum()) / (f_k * P)
        if not 0 < ratio < 1 - 1e-9:
            continue
        c = hertz(P, E_SAME)[0] * (1 - ratio) ** (1 / 3)
        stuck, slips = state[i] == ContactState.STICK, slipping(state[i])
        worst = max(worst, *(r[stuck] - c), *(c - r[slips]))
        checked += 1
    return worst / h, checked


@pytest.mark.parametrize("k, facet_angle, f_k", [
    (8, 0.0, F),  # Q at a vertex, between two facets: the true cone's f
    (4, math.pi / 4, F * math.cos(math.pi / 4)),  # Q along a facet's normal: f cos(π/k)
], ids=["between-facets", "facet-normal"])
def test_cattaneo_mindlin_stick_radius(k, facet_angle, f_k):
    """The tip pressed on the block (8 100 DOFs, 45 CFEs), then sheared: after pressing every
    closed CFE sticks and Σ Q = 0 (1e-9 P, β = 0), the closed zone's edge within h = a/3 of
    a (measured 0.07 h); during the shift P stays constant (1e-4, measured 5e-6: the unequal
    bodies' slight coupling) and Q₂ = 0 (1e-9 P); at every state with 0 < Q < f_k P the
    stick zone's edge lies within one element h of c = a (1 − Q/(f_k P))^(1/3) (a from the
    measured P; measured: 0.27 h between facets, 0.28 h along a facet's normal, where the
    untruncated f would miss by more than h: measured 2.1 h); at the end every closed CFE
    slips and the tip slides at Q = f_k Σ|N| (1e-9)."""
    model, h = mindlin_model(k, facet_angle)
    res = sc.solve_static(model)
    assert res.status == sc.Status.COMPLETED, res.message
    assert f"inscribed {k}-gon" in res.message
    N, Q = np.asarray(res.N), np.asarray(res.Q_t)
    state, seg = np.asarray(res.state), np.asarray(res.segment)
    x = np.asarray(res.cfe["x"])
    r = np.hypot(x[:, 0], x[:, 1])
    pressed = int(np.flatnonzero(seg == 0)[-1])
    P = -N[pressed].sum()
    touching = closed(state[pressed])
    assert np.all(state[pressed][touching] == ContactState.STICK)
    assert np.abs(Q[pressed].sum(axis=0)).max() <= TOL * P
    assert abs(r[touching].max() - hertz(P, E_SAME)[0]) <= h
    shift = seg == 1
    np.testing.assert_allclose(-N[shift].sum(axis=1), P, rtol=1e-4)
    assert np.abs(Q[shift, :, 1].sum(axis=1)).max() <= TOL * P
    misfit, checked = stick_zone_misfit(res, f_k, h)
    assert misfit <= 1.0 and checked >= 10, (misfit, checked)
    if f_k < F:  # the facet's middle: the untruncated cone's f is off by more than an element
        assert stick_zone_misfit(res, F, h)[0] > 1.0
    last = len(res.lam) - 1
    assert np.all(slipping(state[last]) == closed(state[last]))
    assert abs(Q[last, :, 0].sum()) == pytest.approx(f_k * -N[last].sum(), rel=TOL)
