"""Mortar CFEs give the same answer whichever side of an interface is called S+.

The CFEs sit on the coarser side and their normals are the curvature-weighted mean of both
faces' normals (``stepcontact.contact.geometry._mortar_elements``), so the finer side may be
S+ (as in the demo and ``examples/block_on_base.py``) or S−.  Each test runs both
orientations against an independent reference:

* the contact patch test (uniform pressure and shear) at mesh ratios 1.25, 1.6 and 3 with the
  finer side as S+ and as S−: uniform stresses and the exact linear field to round-off;
* Hertz with partial slip (Cattaneo–Mindlin): two equal cylinders pressed together and then
  sheared by Q < fP: contact half-width a = √(4PR*/(πE*)) and stick-zone half-width
  c = a √(1 − Q/(fP)), centred, within half the CFE spacing, on two meshes;
* a gap that closes: a block pushed onto a coarser base through a geometric gap g: every CFE
  closes at λ = g/δ (hand calculation) and the joint then carries the uniform-compression load
  of the two blocks in series, to round-off; a block hung on springs that bends as its CFEs
  close one by one: contact conditions within 1e-9 at every state (with the CFEs on the finer
  block they were violated by up to 5e-7) and equilibrium to round-off;
* a joint near opening: a block on a block under a uniform pressure and a growing linear
  (moment) traction: the heel opens where σ_yy = −P + λq reaches zero, λ = P/q, within the
  O(h) discretisation error of bilinear elements, the same in both orientations.
"""

from __future__ import annotations

import numpy as np
import pytest
from skfem import MeshQuad

import stepcontact as sc
import verification_models as vm
from stepcontact import Status
from stepcontact.contact.laws import OPEN, STICK
from stepcontact.fem.assembly import assemble
from test_mortar import exact_field, patch_model

P_PATCH, TAU = 1e6, 3e5  # Pa, as in test_mortar


# --------------------------------------------------------------------------------------------
# patch test
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("finer_plus", [True, False], ids=["finer=S+", "finer=S-"])
@pytest.mark.parametrize("element", ["quad4", "tri6"])
@pytest.mark.parametrize("sizes", [(5, 4), (8, 5), (12, 4)], ids=["1.25", "1.6", "3"])
def test_patch_test_with_the_finer_side_as_s_plus_or_s_minus(sizes, element, finer_plus):
    """Blocks of one material, the top one finer by 1.25, 1.6 or 3, under the uniform stress
    σ_yy = −P, τ_xy = TAU (test_mortar.patch_model, f = 0.5): every CFE stuck with
    σ_n = −P and τ = TAU to 1e-10 P, every node on the exact linear field to 1e-10 of the
    largest displacement, whichever side is S+."""
    model = patch_model(*sizes, element, top_plus=finer_plus, shear=True)
    system = assemble(model)
    res = sc.solve_static(model)
    assert res.status == Status.COMPLETED, res.message
    area = system.cfe.area
    assert np.abs(res.N[-1] / area + P_PATCH).max() <= 1e-10 * P_PATCH
    assert np.abs(np.abs(res.Q[-1] / area) - TAU).max() <= 1e-10 * P_PATCH
    assert np.all(res.state[-1] == STICK)
    u = res.displacement(-1)
    exact = exact_field(model.points, True)
    of = system.dofs.of
    got = np.column_stack([u[of[:, 0]], u[of[:, 1]]])
    assert np.abs(got - exact).max() <= 1e-10 * np.abs(exact).max()


# --------------------------------------------------------------------------------------------
# Hertz with partial slip (Cattaneo–Mindlin)
# --------------------------------------------------------------------------------------------
R = 0.05  # m, radius of both cylinders
STEEL = sc.Material(210e9, 0.3)
FRICTION = 0.3
A_NOMINAL = 5e-3  # m: the meshes are uniform up to 1.6 × this from the contact point
PRESS, SHEAR = 2e-3, 7e-4  # m: prescribed approach and shift of the upper cylinder's top


def _half_disc(h0: float, below: bool) -> MeshQuad:
    """The lower half of the disc of radius R about (0, R) (``below``: its mirror image, the
    upper half of the disc about (0, −R)), quad4, spacing ``h0`` up to 1.6 A_NOMINAL from the
    contact point (0, 0): the quarter disc of ``verification_models.quarter_disc_mesh``
    mirrored in x = 0."""
    q = vm.quarter_disc_mesh(R, h0, 1.6 * A_NOMINAL)
    p, n = q.p, q.p.shape[1]
    axis = np.abs(p[0]) <= 1e-12 * R
    ids = np.where(axis, np.arange(n), n + np.cumsum(~axis) - 1)
    pts = np.hstack([p, p[:, ~axis] * np.array([[-1.0], [1.0]])])
    t = np.hstack([q.t, ids[q.t][::-1]])  # mirrored cells: reversed to stay counter-clockwise
    if below:
        pts, t = pts * np.array([[1.0], [-1.0]]), t[::-1]
    return MeshQuad(pts, t)


def cattaneo_model(h0: float, ratio: float, upper_plus: bool) -> sc.Model:
    """Two equal steel cylinders (R = 50 mm) touching at the origin, the upper one meshed with
    spacing ``h0`` at the contact, the lower one with ``ratio`` × h0; interface 'contact'
    (f = 0.3) on the arcs |x| ≤ 0.3 R, S+ the upper arc if ``upper_plus``.

    The lower cylinder's flat face is held in y (and its centre in x); the upper one's flat
    face is pushed down by PRESS (segment 1, 'press'), then its centre is moved by SHEAR
    along x (segment 2, 'shear').  The flat faces cannot turn, and the pair is symmetric
    under a half turn about the contact point, so that the exact contact pressure and shear
    are even in x: no moment reaches the contact and pressing locks in no shear (a half
    cylinder on a block would lock in a shear of ≈ 0.04 p at the edge of the contact, the
    mismatch of their surface displacements under the pressure, which Cattaneo–Mindlin's
    half-spaces do not have)."""
    up = sc.Body.from_mesh("upper", _half_disc(h0, False), "quad4", STEEL)
    lo = sc.Body.from_mesh("lower", _half_disc(h0 * ratio, True), "quad4", STEEL)
    m = sc.Model(bodies=[up, lo])

    def arc(y0):
        return lambda x, y: (np.abs(np.hypot(x, y - y0) - R) <= 1e-9 * R) & (np.abs(x) <= 0.3 * R)

    a_up, a_lo = m.select("upper", where=arc(R)), m.select("lower", where=arc(-R))
    plus, minus = (a_up, a_lo) if upper_plus else (a_lo, a_up)
    return m.add(
        sc.Support("flat", m.select("lower", y=-R), "y"),
        sc.Support("centre", m.select("lower", x=0.0, y=-R), "x"),
        sc.Interface("contact", plus, minus, friction=FRICTION),
        sc.LoadPattern("press", [sc.PrescribedDisplacement(m.select("upper", y=R), "y",
                                                           -PRESS)]),
        sc.LoadPattern("shear", [sc.PrescribedDisplacement(m.select("upper", x=0.0, y=R),
                                                           "x", SHEAR)]),
        sc.Segment("press", 1.0),
        sc.Segment("shear", 1.0),
    )


def _zone(x: np.ndarray, inside: np.ndarray) -> tuple[float, float]:
    """(half-width, centre) of the CFEs ``inside`` (contiguous along x), each end midway
    between the last CFE inside and the first outside."""
    k = np.flatnonzero(inside)
    lo = 0.5 * (x[k[0]] + x[k[0] - 1])
    hi = 0.5 * (x[k[-1]] + x[k[-1] + 1])
    return 0.5 * (hi - lo), 0.5 * (hi + lo)


def cattaneo_errors(h0: float, ratio: float, upper_plus: bool) -> dict:
    """The final state of :func:`cattaneo_model`: P and Q (reactions of the upper cylinder's
    prescribed face and centre, N), and the contact and stick zones against Hertz (two equal
    cylinders: R* = R/2, E* = E / (2(1 − ν²)), a = √(4PR*/(πE*))) and Cattaneo–Mindlin
    (c = a √(1 − Q/(fP))), in units of the CFE spacing h = h0 × max(1, ratio)."""
    res = sc.solve_static(cattaneo_model(h0, ratio, upper_plus))
    assert res.status == Status.COMPLETED, res.message
    x = res.cfe["x"][:, 0]
    o = np.argsort(x)
    state = res.state[-1][o]
    P = abs(res.reaction("press (prescribed)", "y")[-1])
    Q = abs(res.reaction("shear (prescribed)", "x")[-1])
    e_star = STEEL.E / (2 * (1 - STEEL.nu**2))
    a = np.sqrt(4 * P * (R / 2) / (np.pi * e_star))
    c = a * np.sqrt(1 - Q / (FRICTION * P))
    a_fe, a_mid = _zone(x[o], state != OPEN)
    c_fe, c_mid = _zone(x[o], state == STICK)
    h = h0 * max(1.0, ratio)
    return dict(P=P, Q=Q, a=a, c=c, q_ratio=Q / (FRICTION * P), da=(a_fe - a) / h,
                a_mid=a_mid / h, dc=(c_fe - c) / h, c_mid=c_mid / h, events=len(res.events))


def _check_cattaneo(k: int) -> list[dict]:
    """Both orientations at ratios 1.25 and 1.6 (the lower cylinder coarser), spacing a/k."""
    out = []
    for ratio in (1.25, 1.6):
        both = [cattaneo_errors(A_NOMINAL / k, ratio, up) for up in (True, False)]
        for r in both:
            assert 0.3 < r["q_ratio"] < 0.7, r  # partial slip, well inside 0 < Q < fP
            assert abs(r["a"] / A_NOMINAL - 1.15) < 0.05, r  # a/R ≈ 0.11: Hertz applies
            # the zones within half the CFE spacing (+ 1 % of a for the finite cylinders)
            assert abs(r["da"]) <= 0.5 + 0.01 * r["a"] / (A_NOMINAL / k), r
            assert abs(r["dc"]) <= 0.5 + 0.01 * r["a"] / (A_NOMINAL / k), r
            # centred: the ends of each zone are symmetric to round-off of the positions
            assert abs(r["a_mid"]) <= 1e-6 and abs(r["c_mid"]) <= 1e-6, r
        # the same state in both orientations: loads to 1e-9, the same events
        assert both[0]["P"] == pytest.approx(both[1]["P"], rel=1e-9)
        assert both[0]["Q"] == pytest.approx(both[1]["Q"], rel=1e-9)
        assert both[0]["events"] == both[1]["events"]
        out += both
    return out


def test_cattaneo_mindlin_partial_slip_in_both_orientations():
    """Two equal cylinders (a ≈ 5.7 mm, R = 50 mm, f = 0.3) pressed, then sheared to
    Q ≈ 0.45 fP, spacing a/10 on the upper one and 1.25 or 1.6 times that on the lower, each
    as S+ and as S−: contact half-width within h/2 + 1 % of a of Hertz's, stick-zone half-width
    within h/2 + 1 % of a of Cattaneo–Mindlin's, both zones centred (1e-6 h), and the same
    loads (1e-9) and events in both orientations; h the CFE spacing (the coarser side's)."""
    _check_cattaneo(10)


@pytest.mark.slow
def test_cattaneo_mindlin_converges_under_refinement():
    """As above at spacing a/20: the same tolerances in units of the halved spacing, so the
    errors in metres shrink with h."""
    _check_cattaneo(20)


# --------------------------------------------------------------------------------------------
# a gap that closes
# --------------------------------------------------------------------------------------------
E_BLOCK, NU_BLOCK = 30e9, 0.2
GAP, PUSH = 1e-5, 1e-5  # m: initial gap; prescribed lowering of the block's top per unit λ
B, H_BLOCK, H_BASE = 2.0, 1.0, 1.0


def gap_model(n_block: int, n_base: int, block_plus: bool, element: str = "quad4") -> sc.Model:
    """A block [0, B] × [g, g + H_BLOCK] (``n_block`` cells along x) above a base
    [0, B] × [−H_BASE, 0] (``n_base``), one material, the gap g = GAP geometric (drawn, not
    given).  The base's bottom is held in y (its left corner in x); the block's top is lowered
    by λ PUSH (prescribed, its left corner held in x).  Interface 'joint' (f = 0.5)."""
    mat = sc.Material(E_BLOCK, NU_BLOCK)
    base = sc.rectangle("base", (0, -H_BASE), (B, 0), n_base, 4, mat, element)
    block = sc.rectangle("block", (0, GAP), (B, GAP + H_BLOCK), n_block, 4, mat, element)
    m = sc.Model(bodies=[base, block])
    bottom, top = m.select("block", y=GAP), m.select("base", y=0.0)
    plus, minus = (bottom, top) if block_plus else (top, bottom)
    face = m.select("block", y=GAP + H_BLOCK)
    return m.add(
        sc.Support("bed", m.select("base", y=-H_BASE), "y"),
        sc.Support("pin", m.select("base", x=0.0, y=-H_BASE), "x"),
        sc.Support("guide", m.select("block", x=0.0, y=GAP + H_BLOCK), "x"),
        sc.Interface("joint", plus, minus, friction=0.5),
        sc.LoadPattern("push", [sc.PrescribedDisplacement(face, "y", -PUSH)]),
        sc.Segment("push", 3.0),
    )


@pytest.mark.parametrize("block_plus", [True, False], ids=["block=S+", "base=S+"])
@pytest.mark.parametrize("element", ["quad4", "quad8"])
@pytest.mark.parametrize("sizes", [(10, 8), (10, 6), (12, 4), (16, 6)],
                         ids=["1.25", "1.67", "3", "2.67"])
def test_a_gap_that_closes_onto_a_coarser_base(sizes, element, block_plus):
    """Hand calculation: the block translates freely until every CFE closes at λ = g/PUSH = 1
    (1e-9); then both blocks are in uniform uniaxial compression, the force through the joint
    F = E/(1 − ν²) · B · (λ PUSH − g)/(H_BLOCK + H_BASE) (plane strain, σ_xx = 0), which the
    reaction of the prescribed face and the sum of the CFE normal forces give to 1e-9 at
    λ = 3; no CFE opens or slips, status completed, residual and violation < 1e-9."""
    res = sc.solve_static(gap_model(*sizes, block_plus, element))
    assert res.status == Status.COMPLETED, res.message
    closed = [e for e in res.events if e.transition.value == "closed"]
    assert len(closed) == len(res.events) == res.m
    assert all(e.lam == pytest.approx(GAP / PUSH, rel=1e-9) for e in closed)
    lam = 3.0
    F = E_BLOCK / (1 - NU_BLOCK**2) * B * (lam * PUSH - GAP) / (H_BLOCK + H_BASE)
    assert -res.reaction("push (prescribed)", "y")[-1] == pytest.approx(F, rel=1e-9)
    assert -res.N[-1].sum() == pytest.approx(F, rel=1e-9)
    assert np.abs(res.Q[-1]).max() <= 1e-9 * F
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-9


def hanging_block(n_block: int, n_base: int, base_span: tuple[float, float],
                  block_plus: bool) -> sc.Model:
    """Quad8 block [0, B] × [g, g + H_BLOCK] hung from the ground by equal vertical springs at
    its top nodes (k = 1e8 N/m in all) and pressed by a uniform pressure on its top (1 Pa per
    unit λ, up to 30 times the load that closes the gap g = 1e-5 m): it bends, so its CFEs
    close one after another onto the base [x0, x1] × [−H_BASE, 0] (held at its bottom)."""
    mat = sc.Material(E_BLOCK, NU_BLOCK)
    base = sc.rectangle("base", (base_span[0], -H_BASE), (base_span[1], 0), n_base, 3, mat,
                        "quad8")
    block = sc.rectangle("block", (0, GAP), (B, GAP + H_BLOCK), n_block, 4, mat, "quad8")
    m = sc.Model(bodies=[base, block])
    bottom, top = m.select("block", y=GAP), m.select("base", y=0.0)
    plus, minus = (bottom, top) if block_plus else (top, bottom)
    face = m.select("block", y=GAP + H_BLOCK)
    k = 1e8
    return m.add(
        sc.Support("bed", m.select("base", y=-H_BASE), "xy"),
        sc.Spring("hang", face, kx=k / len(face), ky=k / len(face)),
        sc.Interface("joint", plus, minus, friction=0.5),
        sc.LoadPattern("press", [sc.EdgeLoad(face, normal=1.0)]),
        sc.Segment("press", 30 * GAP * k / B),
    )


@pytest.mark.parametrize("block_plus", [True, False], ids=["block=S+", "base=S+"])
@pytest.mark.parametrize("case", [(16, 6, (0.0, 2.0)), (24, 6, (-0.5, 2.5))],
                         ids=["16on6", "24on6-wider"])
def test_a_bending_block_closes_a_gap_and_carries_the_load(case, block_plus):
    """The CFEs close one by one as the block bends (with the CFEs on the finer block the
    contact conditions were violated by 1e-7..5e-7 here, 2e-6 in the reported case); now: status
    completed, every CFE closed at the end, contact conditions within 1e-9 (relative) at every
    state; the same closing loads (1e-9) in both orientations; equilibrium to round-off: the
    base's support reaction equals the sum of the CFE normal forces, and with the springs'
    forces it balances the applied pressure (1e-9 of the load)."""
    n_block, n_base, span = case
    runs = []
    for plus in (block_plus, not block_plus):
        model = hanging_block(n_block, n_base, span, plus)
        res = sc.solve_static(model)
        assert res.status == Status.COMPLETED, res.message
        assert res.violation.max() < 1e-9
        assert np.all(res.state[-1] != OPEN)
        runs.append((model, res))
    lams = [sorted(e.lam for e in r.events if e.transition.value == "closed") for _, r in runs]
    np.testing.assert_allclose(lams[0], lams[1], rtol=1e-9)
    model, res = runs[0]
    system = assemble(model)
    u = res.displacement(-1)
    face = model.select("block", y=GAP + H_BLOCK)
    uy = u[system.dofs.of[model.global_nodes(face), 1]]
    springs = -(1e8 / len(face)) * uy.sum()  # N, upwards on the block
    load = B * 1.0 * res.lam[-1]  # N, downwards
    contact = abs((res.N[-1] * res.cfe["normal"][:, 1]).sum())  # N, upwards on the block
    bed = res.reaction("bed", "y")[-1]
    assert abs(bed - contact) <= 1e-9 * load
    assert abs(springs + contact - load) <= 1e-9 * load
    assert contact > 0.5 * load  # the joint carries most of the load afterwards


# --------------------------------------------------------------------------------------------
# a joint near opening
# --------------------------------------------------------------------------------------------
P_J, Q_J = 1e6, 1e6  # Pa: uniform pressure; linear traction ±Q_J at the ends (per unit λ)
B_J, H_J = 2.0, 0.5


def joint_model(n_top: int, n_bot: int, top_plus: bool) -> sc.Model:
    """Block [0, B_J] × [H_J, 2H_J] (``n_top`` square-ish quad4 cells along x) on a block
    [0, B_J] × [0, H_J] (``n_bot``), one material, joint f = 0.5.  The bottom is held in y
    (its left corner in x); on the top face a uniform pressure P_J ('weight', λ = 1) and then a
    linear traction σ_yy = Q_J (x − B_J/2)/(B_J/2) ('moment', λ from 0 to 2).  The exact
    stress is σ_yy = −P_J + λ Q_J (x − B_J/2)/(B_J/2) everywhere (linear, so compatible): the
    heel x = B_J opens at λ = P_J/Q_J = 1."""
    mat = sc.Material(2e10, 0.25)
    bot = sc.rectangle("bot", (0, 0), (B_J, H_J), n_bot, max(2, n_bot // 4), mat)
    top = sc.rectangle("top", (0, H_J), (B_J, 2 * H_J), n_top, max(2, n_top // 4), mat)
    m = sc.Model(bodies=[bot, top])
    jt, jb = m.select("top", y=H_J), m.select("bot", y=H_J)
    plus, minus = (jt, jb) if top_plus else (jb, jt)
    face = m.select("top", y=2 * H_J)
    return m.add(
        sc.Support("bed", m.select("bot", y=0.0), "y"),
        sc.Support("pin", m.select("bot", x=0.0, y=0.0), "x"),
        sc.Interface("joint", plus, minus, friction=0.5),
        sc.LoadPattern("weight", [sc.EdgeLoad(face, normal=P_J)]),
        sc.LoadPattern("moment", [sc.EdgeLoad(
            face, normal=lambda x, y: -Q_J * (x - B_J / 2) / (B_J / 2))]),
        sc.Segment("weight", 1.0),
        sc.Segment("moment", 2.0),
    )


def opening_load(model: sc.Model) -> tuple[float, float]:
    """λ and position x of the first CFE that opens."""
    res = sc.solve_static(model)
    assert res.status == Status.COMPLETED, res.message
    ev = next(e for e in res.events if e.transition.value == "opened")
    return ev.lam, float(res.cfe["x"][res.cfe["local"] == ev.local, 0][0])


@pytest.mark.parametrize("n_top", [20, 26, 48], ids=["1.25", "1.6", "3"])
def test_a_joint_near_opening_opens_at_the_hand_value(n_top):
    """The top block finer by 1.25, 1.6 or 3 than the bottom one (16 cells): the heel opens
    first, at λ within 0.7 h/B_J of the hand value 1 (h = B_J/16 the coarser spacing: the
    O(h) error of the bilinear elements' end pressure, 0.6 h/B_J on these meshes as on
    matching ones), and at the same λ (1e-9) whichever side is S+."""
    got = [opening_load(joint_model(n_top, 16, tp)) for tp in (True, False)]
    assert got[0][0] == pytest.approx(got[1][0], rel=1e-9)
    for lam, x in got:
        assert x == pytest.approx(B_J)
        assert abs(lam - 1.0) <= 0.7 / 16


def test_a_joint_near_opening_converges_under_refinement():
    """Ratio 1.6 with the finer side as S+: the opening load's error against the hand value
    falls by at least 1.7 when the spacing halves (16 → 32 cells below; measured 2.1), and
    stays within 0.7 h/B_J."""
    errors = []
    for n in (16, 32):
        lam, _ = opening_load(joint_model(int(round(1.6 * n)), n, True))
        errors.append(abs(lam - 1.0))
        assert errors[-1] <= 0.7 / n
    assert errors[0] >= 1.7 * errors[1], errors
