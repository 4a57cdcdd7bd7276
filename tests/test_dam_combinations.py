"""Load combinations of a gravity dam and their checks against a guideline's required values.

The textbook example: a 36 m concrete dam (heel (0, 0), toe (27, 0) m, crest 5 m wide, vertical
upstream face, straight downstream face) on a rock block, a joint with f = 1 between them,
matching meshes (3 m cells).  The usual combination: reservoir at 33 m, tailwater 3 m, drains
6 m from the heel with the head H₂ + (H₁ − H₂)/3 there, silt 6 m deep (K = 0.5,
γ'_s = 9 kN/m³); the flood: reservoir at 36 m, tailwater 8 m, the same drains.

**Reference**: hand statics written below, independent of the library — the forces of the
weight (trapezoid = rectangle + triangle), the hydrostatic thrusts (γ_w h²/2 at h/3), the
tailwater's horizontal thrust and the weight of the water wedge on the downstream face, the
uplift (two trapezoids through the drain head), the silt (K γ'_s s²/2 at s/3), the pseudo-
static inertia k_h W at the centroid and the reservoir's hydrodynamic force (Westergaard 1933)
(7/12) k_h γ_w h² at 0.4 h above the base (vertical face); their moment about the toe gives
the resultant's distance a = M/N' from the toe, e = L/2 − a, and the sliding factor
F = (c A + N' tan φ)/H (EM 1110-2-2100 eq. 3-1), the linear base pressure N'/L (1 ± 6e/L)
and the flotation factor (N' + U)/U.

**Tolerance**: 1e-9 relative.  The joint's resultant force and moment equal the loads' by the
equilibrium of the dam whatever the foundation's stiffness; the loads are integrated exactly
(edges split at the water levels and at the drain).  The compressed area is the whole base
only while every CFE is closed: asserted first (with a rock as stiff as the concrete; a stiffer
rock opens the heel at this level — the re-entrant corner — which
``test_elastic_heel_opening_fails_only_the_compressed_base`` uses).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.errors import ModelError
from stepcontact.model.combinations import (
    BaseUplift,
    Combination,
    DamSite,
    Earthquake,
    Ice,
    PostTensioning,
    Reservoir,
    SelfWeight,
    Silt,
    Tailwater,
)
from stepcontact.results.dam_checks import (
    CHECKS,
    TO_BE_CHECKED,
    JointStrength,
    check_combination,
    guideline_table,
    load_guidelines,
)

GW, RHO, G = 9810.0, 2400.0, 9.81  # N/m³, kg/m³, m/s²
HEIGHT, B, CREST = 36.0, 27.0, 5.0
SLOPE = (B - CREST) / HEIGHT  # downstream face: x = B − SLOPE y
X_DRAIN, K_DRAIN = 6.0, 1.0 / 3.0
SILT = (6.0, 9000.0, 0.5)  # level (m), γ'_s (N/m³), K
C_PEAK, PHI_PEAK, PHI_RES = 300e3, 45.0, 35.0
RTOL = 1e-9
ROOT = Path(__file__).resolve().parents[1]


def dam_site(rock_E: float = 25e9, friction: float = 1.0) -> DamSite:
    concrete = sc.Material(E=25e9, nu=0.2, density=RHO)
    rock = sc.Material(E=rock_E, nu=0.2, density=0.0)
    dam = sc.quad_region("dam", [(0, 0), (B, 0), (CREST, HEIGHT), (0, HEIGHT)], 9, 12,
                         concrete)
    fnd = sc.rectangle("rock", (-27, -27), (54, 0), 27, 9, rock)  # 3 m cells, nodes match
    m = sc.Model(bodies=[fnd, dam], name="textbook dam")
    base = sc.Interface("base", plus=m.select("dam", y=0), minus=m.select("rock", y=0),
                        friction=friction)
    downstream = m.select("dam", lambda x, y: np.abs(x - (B - SLOPE * y)) < 1e-6)
    m = m.add(sc.Support("deep rock", m.select("rock", y=-27), "xy"), base)
    return DamSite(m, base="base", heel=(0, 0), toe=(B, 0), upstream=m.select("dam", x=0.0),
                   dam=("dam",), downstream=downstream)


def usual() -> Combination:
    return Combination("usual", "usual", (SelfWeight(), Reservoir(33.0), Tailwater(3.0),
                                          BaseUplift(drain=(X_DRAIN, 0.0), ratio=K_DRAIN),
                                          Silt(*SILT)))


def flood() -> Combination:
    return Combination("flood", "flood", (SelfWeight(), Reservoir(36.0), Tailwater(8.0),
                                          BaseUplift(drain=(X_DRAIN, 0.0), ratio=K_DRAIN)))


# ---- hand statics -----------------------------------------------------------------------------
def hand(h: float, t: float, silt=None, k_h: float = 0.0, k_v: float = 0.0,
         ice=None, hydro: bool = True) -> dict:
    """Forces (N/m; x downstream, y up) and moments about the toe (N·m/m, anticlockwise) of the
    loads on the dam, and the engineers' quantities of the base."""
    forces = []  # (fx, fy, x, y): a force and a point of its line of action

    a_rect, a_tri = CREST * HEIGHT, (B - CREST) * HEIGHT / 2
    for area, xc, yc in ((a_rect, CREST / 2, HEIGHT / 2),
                         (a_tri, (CREST + B + CREST) / 3, HEIGHT / 3)):
        w = RHO * G * area
        forces.append((0.0, -w, xc, yc))
        if k_h:
            forces.append((k_h * w, k_v * w, xc, yc))
    forces.append((GW * h * h / 2, 0.0, 0.0, h / 3))  # reservoir on the vertical face
    if k_h and hydro:  # Westergaard (1933): (7/12) k_h γ_w h² at 0.4 h, horizontal
        forces.append((7 / 12 * k_h * GW * h * h, 0.0, 0.0, 0.4 * h))
    forces.append((-GW * t * t / 2, 0.0, B, t / 3))  # tailwater, horizontal
    forces.append((0.0, -GW * SLOPE * t * t / 2, B - SLOPE * t / 3, 0.0))  # water wedge
    h_drain = t + K_DRAIN * (h - t)
    U = 0.0
    for (x0, h0), (x1, h1) in (((0.0, h), (X_DRAIN, h_drain)), ((X_DRAIN, h_drain), (B, t))):
        u = GW * (h0 + h1) / 2 * (x1 - x0)  # a trapezoid of head
        xc = x0 + (x1 - x0) * (h0 + 2 * h1) / (3 * (h0 + h1))
        forces.append((0.0, u, xc, 0.0))
        U += u
    if silt:
        s, gs, k = silt
        forces.append((k * gs * s * s / 2, 0.0, 0.0, s / 3))
    if ice:
        f_ice, y_ice = ice
        forces.append((f_ice, 0.0, 0.0, y_ice))
    F = np.array(forces)
    fx, fy = F[:, 0].sum(), F[:, 1].sum()
    M = ((F[:, 2] - B) * F[:, 1] - F[:, 3] * F[:, 0]).sum()  # about the toe (B, 0)
    n_eff, shear = -fy, fx
    a = M / n_eff  # the resultant's distance from the toe (M = a · N' for a force on y = 0)
    e = B / 2 - a
    return {"N": n_eff, "H": shear, "a": a, "e_rel": abs(e) / B, "U": U,
            "F_peak": (C_PEAK * B + n_eff * np.tan(np.radians(PHI_PEAK))) / shear,
            "F_res": n_eff * np.tan(np.radians(PHI_RES)) / shear,
            "uplift": (n_eff + U) / U,
            "sigma_heel": -n_eff / B * (1 - 6 * e / B), "sigma_toe": -n_eff / B * (1 + 6 * e / B)}


STRENGTH = JointStrength(cohesion=C_PEAK, friction_angle=PHI_PEAK,
                         residual_friction_angle=PHI_RES)


@pytest.fixture(scope="module")
def runs():
    site = dam_site()
    return site, {c.name: (c, sc.solve_static(c.model(site))) for c in (usual(), flood())}


def _closed(res) -> None:
    s = res.interface_safety("base", heel=(0, 0))
    assert res.status == sc.Status.COMPLETED
    assert s.open_length[-1] == 0.0 and s.compressed_length[-1] == pytest.approx(B, rel=1e-12)


@pytest.mark.parametrize("name, h, t, silt", [("usual", 33.0, 3.0, SILT),
                                              ("flood", 36.0, 8.0, None)])
def test_combination_table_against_hand_statics(runs, name, h, t, silt):
    """Each value of the combination's table against the hand statics (1e-9 relative), and
    each verdict against the guideline's value read from the data file."""
    site, done = runs
    combo, res = done[name]
    _closed(res)  # the precondition of A_c = B
    ref = hand(h, t, silt)
    chk = check_combination(res, combo, site, guideline="usace", strength=STRENGTH)
    g = load_guidelines()["usace"]
    cls = g.condition_class(combo.condition)[0]
    assert cls == {"usual": "usual", "flood": "unusual"}[name]

    def row(check):
        return chk.row(name, "base", check)

    s = res.interface_safety("base", heel=(0, 0))
    assert -s.normal_force[-1] == pytest.approx(ref["N"], rel=RTOL)
    assert s.shear_force[-1] == pytest.approx(ref["H"], rel=RTOL)
    assert s.from_toe[-1] == pytest.approx(ref["a"], rel=RTOL)
    for check, key in ((CHECKS["sliding_peak"], "F_peak"),
                       (CHECKS["sliding_residual"], "F_res"),
                       ("resultant |e|/L", "e_rel"), (CHECKS["uplift"], "uplift"),
                       ("heel stress (linear)", "sigma_heel"),
                       ("toe stress (linear)", "sigma_toe")):
        assert row(check).value == pytest.approx(ref[key], rel=RTOL), check
    assert row(CHECKS["compressed_base"]).value == pytest.approx(1.0, rel=1e-12)
    assert row("crack length").value == 0.0
    # the verdicts: the guideline's value for the class, compared by hand
    f_req = g.required("sliding_peak", cls).value
    assert row(CHECKS["sliding_peak"]).required == f_req
    assert row(CHECKS["sliding_peak"]).passed == (ref["F_peak"] >= f_req)
    frac = g.required("compressed_base", cls).value
    assert row("resultant |e|/L").required == pytest.approx(0.5 - frac / 3, rel=1e-15)
    assert row("resultant |e|/L").passed == (ref["e_rel"] <= 0.5 - frac / 3)
    assert row(CHECKS["uplift"]).passed == (ref["uplift"] >= g.required("uplift", cls).value)
    assert row(CHECKS["sliding_residual"]).passed is None  # USACE sets no residual factor
    assert all(not r.checked for r in chk.rows if r.required is not None)  # all unconfirmed
    assert TO_BE_CHECKED in chk.to_markdown()
    assert chk.passed == all(r.passed for r in chk.rows if r.passed is not None)
    # FERC: the friction-only factor N' tan φ / H beside the peak one, its own required value
    ferc = check_combination(res, combo, site, guideline="ferc", strength=STRENGTH)
    fo = ferc.row(name, "base", CHECKS["sliding_friction_only"])
    assert fo.value == pytest.approx(ref["N"] / ref["H"], rel=RTOL)
    f_fo = load_guidelines()["ferc"].required("sliding_friction_only", "unusual" if
                                               name == "flood" else "usual").value
    assert fo.required == f_fo and fo.passed == (ref["N"] / ref["H"] >= f_fo)


def test_earthquake_and_post_earthquake_against_hand_statics():
    """Pseudo-static k_h = 0.05, k_v = 0.025 (upwards) on the usual combination: the inertia
    k_h W, k_v W at the centroid and Westergaard's hydrodynamic force (7/12) k_h γ_w h² at
    0.4 h in the hand statics (1e-9 relative; k_h is below the heel's opening at 0.078 with
    the hydrodynamic force, so A_c = B).  Post-earthquake the earthquake is removed: the
    joint's forces are those of the usual loads again (equilibrium), whatever slip it left.
    Without the hydrodynamic force (``hydrodynamic=False``) the hand statics without it."""
    site = dam_site()
    cases = (SelfWeight(), Reservoir(33.0), Tailwater(3.0),
             BaseUplift(drain=(X_DRAIN, 0.0), ratio=K_DRAIN), Earthquake(0.05, k_v=0.025))
    eq = Combination("earthquake", "earthquake", cases)
    post = Combination("post-earthquake", "post-earthquake", cases)
    dry = Combination("dry", "earthquake", cases[:-1] + (Earthquake(0.05, k_v=0.025,
                                                                   hydrodynamic=False),))
    assert [(s.pattern, s.end) for s in post.segments()][-2:] == [("earthquake", 0.05),
                                                                   ("earthquake", 0.0)]
    for combo, ref in ((eq, hand(33.0, 3.0, k_h=0.05, k_v=0.025)), (post, hand(33.0, 3.0)),
                       (dry, hand(33.0, 3.0, k_h=0.05, k_v=0.025, hydro=False))):
        res = sc.solve_static(combo.model(site))
        _closed(res)
        chk = check_combination(res, combo, site, guideline="cda", strength=STRENGTH)
        assert chk.row(combo.name, "base", CHECKS["sliding_peak"]).value == pytest.approx(
            ref["F_peak"], rel=RTOL)
        assert chk.row(combo.name, "base", "resultant |e|/L").value == pytest.approx(
            ref["e_rel"], rel=RTOL)
    assert load_guidelines()["cda"].condition_class("earthquake")[0] == "earthquake"


def test_ice_and_post_tensioning_statics():
    """The ice line load (lever rule on the face nodes around its level, here between nodes)
    and an anchor force (on the crest nodes, its reaction on the rock) against the hand
    statics: an anchor adds its force to N' and its moment about the toe (1e-9 relative)."""
    site = dam_site()
    crest = site.model.select("dam", y=HEIGHT)
    rock_top = site.model.select("rock", lambda x, y: (np.abs(y + 27) < 1e-9) & (x <= 0))
    P = 2e6  # N/m, down on the crest nodes
    combo = Combination("usual + ice", "usual", (
        SelfWeight(), Reservoir(33.0), Tailwater(3.0),
        BaseUplift(drain=(X_DRAIN, 0.0), ratio=K_DRAIN), Ice(150e3, 32.0),
        PostTensioning(P, head=crest, anchor=rock_top)))
    res = sc.solve_static(combo.model(site))
    assert res.status == sc.Status.COMPLETED
    ref = hand(33.0, 3.0, ice=(150e3, 32.0))
    pts = site.model.body("dam").points[crest.index]
    x_p = pts[:, 0].mean()  # equal shares on the crest nodes
    n_eff = ref["N"] + P
    a = (ref["a"] * ref["N"] + P * (B - x_p)) / n_eff
    s = res.interface_safety("base", heel=(0, 0))
    assert -s.normal_force[-1] == pytest.approx(n_eff, rel=RTOL)
    assert s.shear_force[-1] == pytest.approx(ref["H"], rel=RTOL)
    assert s.from_toe[-1] == pytest.approx(a, rel=RTOL)


def test_verdicts_fail_exactly_the_check_designed_to_fail(runs):
    """Required values chosen around the hand values: each case fails exactly one check."""
    site, done = runs
    combo, res = done["usual"]
    ref = hand(33.0, 3.0, SILT)
    base = {"sliding_peak": 0.99 * ref["F_peak"], "compressed_base": 1.0,
            "uplift": 0.99 * ref["uplift"]}
    ok = check_combination(res, combo, site, strength=STRENGTH, required=base)
    assert ok.passed and not ok.failed()
    for key, check in (("sliding_peak", CHECKS["sliding_peak"]), ("uplift", CHECKS["uplift"])):
        chk = check_combination(res, combo, site, strength=STRENGTH,
                                required=base | {key: 1.01 * ref[
                                    "F_peak" if key == "sliding_peak" else "uplift"]})
        assert [r.check for r in chk.failed()] == [check]
        assert not chk.passed and chk.verdicts() == {"usual": False}
    # friction only (c = 0, tan φ = 1): N'/H ≈ 1.97 against the guideline's usual 2.0
    chk = check_combination(res, combo, site, strength=JointStrength(friction_angle=PHI_PEAK))
    f = ref["N"] / ref["H"]
    assert chk.row("usual", "base", CHECKS["sliding_peak"]).value == pytest.approx(f, rel=RTOL)
    assert [r.check for r in chk.failed()] == ([CHECKS["sliding_peak"]] if f < 2.0 else [])


def test_elastic_heel_opening_fails_only_the_compressed_base():
    """On a rock ten times stiffer than the concrete the heel CFE opens at 33 m (the
    re-entrant corner) while the resultant stays in the middle third: the elastic compressed
    length fails the 100 % rule, the resultant's position (exact statics) passes."""
    site = dam_site(rock_E=250e9)
    combo = usual()
    res = sc.solve_static(combo.model(site))
    s = res.interface_safety("base", heel=(0, 0))
    assert res.status == sc.Status.COMPLETED and s.open_length[-1] > 0  # the precondition
    ref = hand(33.0, 3.0, SILT)
    chk = check_combination(res, combo, site, strength=STRENGTH,
                            required={"sliding_peak": 1.0, "compressed_base": 1.0,
                                      "uplift": 1.0})
    assert chk.row("usual", "base", "resultant |e|/L").value == pytest.approx(ref["e_rel"],
                                                                              rel=RTOL)
    assert [r.check for r in chk.failed()] == [CHECKS["compressed_base"]]
    assert chk.row("usual", "base", "crack length").value == pytest.approx(s.open_length[-1])


def test_a_run_that_slides_fails():
    """f = 0.3: the dam slides before the flood level; the combination fails, saying why."""
    site = dam_site(friction=0.3)
    res = sc.solve_static(flood().model(site))
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    chk = check_combination(res, flood(), site)
    bad = chk.row("flood", "—", "run reached the combination's state")
    assert bad.passed is False and "sliding" in bad.note and not chk.passed


def test_every_guideline_value_has_a_source_and_the_docs_table_is_generated():
    """Every required value names its source; the docs table is the data file's."""
    gs = load_guidelines()
    assert set(gs) == {"usace", "ferc", "cda"}
    for g in gs.values():
        assert g.document and g.default_variant in g.variants
        for cond, c in g.condition_of.items():
            assert c["source"].strip() and c["value"] in g.conditions, (g.key, cond)
        for c in g.criteria:
            assert c.source.strip(), c
            assert c.value is None or c.value >= 0, c
            assert c.condition in g.conditions and c.check in CHECKS, c
    text = (ROOT / "docs" / "user-guide.md").read_text(encoding="utf-8")
    part = text.split("### Guideline criteria", 1)[1]
    rows = [ln for ln in part.splitlines() if ln.startswith("|")]
    first = part.index(rows[0])
    assert part[first:].startswith(guideline_table()), "regenerate the docs table"


def test_bad_inputs_name_the_item():
    site = dam_site()
    with pytest.raises(ModelError, match="dam site.heel"):
        DamSite(site.model, base="base", heel=(0, 1), toe=(B, 0), upstream=site.upstream,
                dam=("dam",))
    with pytest.raises(ModelError, match="base uplift.drain"):
        BaseUplift(drain=(40.0, 0.0)).shapes(site)
    with pytest.raises(ModelError, match="post-earthquake"):
        Combination("p", "post-earthquake", (SelfWeight(),))
    with pytest.raises(ModelError, match="condition"):
        Combination("p", "normal", (SelfWeight(),))
    with pytest.raises(ModelError, match="downstream face"):
        nodown = DamSite(site.model, base="base", heel=(0, 0), toe=(B, 0),
                         upstream=site.upstream, dam=("dam",))
        Combination("t", "usual", (Reservoir(30.0), Tailwater(2.0))).model(nodown)
    with pytest.raises(ModelError, match="ice.level"):
        Combination("i", "usual", (Ice(1e5, 50.0),)).model(site)
    with pytest.raises(KeyError, match="variant"):
        check_combination(None, usual(), site, variant="critical, excellent")
    with pytest.raises(ModelError, match="friction_angle"):
        JointStrength(friction_angle=95.0)
    assert re.search(r"\[to be checked\]", guideline_table())


def test_per_joint_checks_of_a_dam_in_two_lifts():
    """The dam in two lifts joined at y = 18 m (matching meshes, f = 1): the base's checks are
    the single dam's, and the lift joint's are the hand statics of the upper lift — its weight
    (a rectangle and a triangle) and the reservoir on its face, (h − 18)²γ_w/2 at (h − 18)/3
    above the joint, about the joint's toe (16, 18) (1e-9 relative); no uplift is given in the
    lift joint, so its uplift factor is not evaluated."""
    y1 = 18.0
    x1 = B - SLOPE * y1  # 16 m
    concrete = sc.Material(E=25e9, nu=0.2, density=RHO)
    rock = sc.Material(E=25e9, nu=0.2, density=0.0)
    lower = sc.quad_region("lift 1", [(0, 0), (B, 0), (x1, y1), (0, y1)], 9, 6, concrete)
    upper = sc.quad_region("lift 2", [(0, y1), (x1, y1), (CREST, HEIGHT), (0, HEIGHT)], 9, 6,
                           concrete)
    fnd = sc.rectangle("rock", (-27, -27), (54, 0), 27, 9, rock)
    m = sc.Model(bodies=[fnd, lower, upper], name="dam in lifts")
    base = sc.Interface("base", plus=m.select("lift 1", y=0), minus=m.select("rock", y=0),
                        friction=1.0)
    lift = sc.Interface("lift", plus=m.select("lift 2", y=y1), minus=m.select("lift 1", y=y1),
                        friction=1.0)
    m = m.add(sc.Support("deep rock", m.select("rock", y=-27), "xy"), base, lift)
    on_face = lambda x, y: np.abs(x - (B - SLOPE * y)) < 1e-6  # noqa: E731
    site = DamSite(m, base="base", heel=(0, 0), toe=(B, 0), dam=("lift 1", "lift 2"),
                   upstream=(m.select("lift 1", x=0.0), m.select("lift 2", x=0.0)),
                   downstream=(m.select("lift 1", on_face), m.select("lift 2", on_face)))
    combo = usual()
    res = sc.solve_static(combo.model(site))
    chk = check_combination(res, combo, site, strength=STRENGTH)
    assert res.status == sc.Status.COMPLETED
    assert all(chk.row("usual", j, "crack length").value == 0.0 for j in ("base", "lift"))
    ref = hand(33.0, 3.0, SILT)
    assert chk.row("usual", "base", CHECKS["sliding_peak"]).value == pytest.approx(
        ref["F_peak"], rel=RTOL)
    assert chk.row("usual", "base", "resultant |e|/L").value == pytest.approx(ref["e_rel"],
                                                                              rel=RTOL)
    # the upper lift about the lift joint's toe (x1, y1)
    d = 33.0 - y1
    w_r, w_t = RHO * G * CREST * (HEIGHT - y1), RHO * G * (x1 - CREST) * (HEIGHT - y1) / 2
    x_t = (CREST + x1 + CREST) / 3
    n_eff, shear = w_r + w_t, GW * d * d / 2
    M = -(CREST / 2 - x1) * w_r - (x_t - x1) * w_t - d / 3 * shear  # r × F about the toe
    a = M / n_eff
    f_peak = (C_PEAK * x1 + n_eff * np.tan(np.radians(PHI_PEAK))) / shear
    assert chk.row("usual", "lift", CHECKS["sliding_peak"]).value == pytest.approx(f_peak,
                                                                                   rel=RTOL)
    assert chk.row("usual", "lift", "resultant |e|/L").value == pytest.approx(
        abs(x1 / 2 - a) / x1, rel=RTOL)
    assert chk.row("usual", "lift", CHECKS["uplift"]).passed is None


def test_program_order_and_crack_water_in_the_uplift_factor():
    """The program: self-weight, tailwater, reservoir to its level, silt (exact list).  With
    crack water and k_h = 0.15 (with the hydrodynamic force) the heel opens over 4.5 m and
    water enters beyond the heel CFE
    (where the uplift is below the reservoir's head): the uplift factor is the downward loads
    over the uplift plus the crack water, (W + V_tw)/(U + ΣW_crack), with W, V_tw (the
    tailwater wedge) and U by hand and ΣW_crack from the run (1e-9 relative)."""
    assert [(s.pattern, s.end) for s in usual().segments()] == [
        ("self-weight", 1.0), ("tailwater", 1.0), ("reservoir", 33.0), ("silt", 1.0)]
    site = dam_site()
    combo = Combination("wet", "earthquake", (SelfWeight(), Reservoir(33.0, crack_water=True),
                                              Tailwater(3.0),
                                              BaseUplift(drain=(X_DRAIN, 0.0), ratio=K_DRAIN),
                                              Earthquake(0.15)))
    res = sc.solve_static(combo.model(site))
    assert res.status == sc.Status.COMPLETED
    wet = float(np.asarray(res.water)[-1].sum())
    assert wet > 0  # the precondition: water entered the opened heel
    ref = hand(33.0, 3.0)
    down = RHO * G * (B + CREST) / 2 * HEIGHT + GW * SLOPE * 3.0**2 / 2
    chk = check_combination(res, combo, site)
    assert chk.row("wet", "base", CHECKS["uplift"]).value == pytest.approx(
        down / (ref["U"] + wet), rel=RTOL)
    assert chk.row("wet", "base", "crack length").value > 0


def test_silt_level_between_nodes_is_exact():
    """Silt to 7.5 m on 3 m cells (the level inside an edge): the silt's thrust K γ'_s s²/2
    at s/3 by hand, through ΣQ and the resultant's position (1e-9 relative).  Integrated by
    the edge's Gauss rule across the kink ΣQ was off by 1.3e-4; the silt is now a WaterLoad of
    its equivalent fluid, split at its level."""
    site = dam_site()
    silt = (7.5, 9000.0, 0.5)
    combo = Combination("usual", "usual", (SelfWeight(), Reservoir(33.0), Tailwater(3.0),
                                           BaseUplift(drain=(X_DRAIN, 0.0), ratio=K_DRAIN),
                                           Silt(*silt)))
    res = sc.solve_static(combo.model(site))
    _closed(res)
    ref = hand(33.0, 3.0, silt)
    s = res.interface_safety("base", heel=(0, 0))
    assert s.shear_force[-1] == pytest.approx(ref["H"], rel=RTOL)
    assert s.from_toe[-1] == pytest.approx(ref["a"], rel=RTOL)
