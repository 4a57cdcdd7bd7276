"""The safety factors a dam engineer reads (shear friction, friction only, overturning about the
toe, resultant position, compressed length) and the load margins, against hand statics.

The dam: a concrete trapezoid (base B = 8 m from heel (0, 0) to toe (8, 0), crest 2 m, height
12 m, vertical upstream face; the section of examples/gravity_dam.py) on rock, matching meshes
(1 m cells: the CFEs at x = 0 … 8, tributary lengths 0.5 m at the ends, 1 m inside).  The
reservoir's factor is the water level h (m): hydrostatic pressure on the upstream face and
uplift from the head h at the heel to 0 at the toe.  Hand statics per metre of dam:

    W = γ_c (B + crest)/2 · height,  its lever about the toe x_W = 5.2 m,
    H = γ_w h²/2 at h/3,  U = γ_w h B/2 at 2B/3 from the toe,
    ΣN = W − U,  SFF = (c·B + f (W − U))/H,  friction only f (W − U)/H,
    overturning W x_W / (H h/3 + U 2B/3),  resultant from the toe (M_r − M_o)/(W − U).

The contact forces of a state are exact (equilibrium to round-off): the factors agree with the
hand values to 1e-9 relative (stated per test); the rectangular block of the partly open base
and the interpolated state likewise.
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose
from typer.testing import CliRunner

import stepcontact as sc
import verification_models as vm
from stepcontact.cli.commands import app

runner = CliRunner()
GAMMA_W = 9810.0
F, B, HEIGHT, CREST = 0.7, 8.0, 12.0, 2.0
CONCRETE = sc.Material(E=25e9, nu=0.2, density=2400)
ROCK = sc.Material(E=15e9, nu=0.25, density=2650)
W = 2400 * 9.81 * (B + CREST) / 2 * HEIGHT
X_W = 5.2  # lever of W about the toe, m: (2·12·7 + 6·12/2·4)/60
H_D = 10.0  # design level, m
RTOL = 1e-9  # the contact forces are exact: the factors to round-off


def hand(h: float, c: float, f: float = F) -> dict[str, float]:
    """The hand statics of the trapezoid at level h with cohesion c on the whole base."""
    H, U = GAMMA_W * h * h / 2, GAMMA_W * h * B / 2
    M_r, M_o = W * X_W, H * h / 3 + U * 2 * B / 3
    return {"N": W - U, "H": H, "sff": (c * B + f * (W - U)) / H, "friction": f * (W - U) / H,
            "overturning": M_r / M_o, "from_toe": (M_r - M_o) / (W - U), "M_r": M_r, "M_o": M_o}


def dam(bond: sc.Bond | None = None, levels=(H_D, 20.0), friction: float = F,
        crack_water: bool = False, swap: bool = False) -> sc.Model:
    dam_body = sc.quad_region("dam", [(0, 0), (B, 0), (CREST, HEIGHT), (0, HEIGHT)], 8, 12,
                              CONCRETE)
    rock = sc.rectangle("rock", (-10, -8), (18, 0), 28, 4, ROCK)
    m = sc.Model(bodies=[rock, dam_body], name="trapezoid-dam")
    faces = (m.select("dam", y=0), m.select("rock", y=0))
    plus, minus = faces[::-1] if swap else faces  # swap: S+ is the rock's face
    base = sc.Interface("base", plus=plus, minus=minus, friction=friction, bond=bond)
    crack = [sc.CrackWater(base, level=None, entry=(0.0, 0.0))] if crack_water else []
    return m.add(
        sc.Support("deep rock", m.select("rock", y=-8), "xy"), base,
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("dam",))]),
        sc.LoadPattern("reservoir", [sc.WaterLoad(m.select("dam", x=0.0), level=None),
                                     sc.Uplift(base, head=[(0.0, 0.0, 1.0), (B, 0.0, 0.0)]),
                                     *crack]),
        sc.Segment("weight", 1.0), *(sc.Segment("reservoir", h) for h in levels))


@pytest.fixture(scope="module")
def coulomb():
    """f = 0.7, no cohesion: slides at h = 11.672 m (examples/gravity_dam.py)."""
    return sc.solve_static(dam())


@pytest.fixture(scope="module")
def residual():
    """A bond of 1 Pa that breaks under the first increments of the weight, leaving the
    residual cohesion C_r = 100 kPa on every CFE (f = 0.7 after the break)."""
    bond = sc.Bond(tensile=1.0, shear=1.0, alpha=0.0, tension_alpha=np.inf, friction=F,
                   residual_cohesion=100e3)
    return sc.solve_static(dam(bond))


def test_design_cohesion_on_a_coulomb_joint(coulomb):
    """A design cohesion c = 150 kPa on the frictional joint at h = 10 m (a recorded state):
    every factor against the hand statics to 1e-9."""
    s = coulomb.interface_safety("base", design=H_D, cohesion=150e3)
    d, ref = s.design_values(), hand(H_D, 150e3)
    assert d["state"] is not None and not d["interpolated"] and d["notes"] == []
    assert d["parameter"] == "water level (m)" and d["pattern"] == "reservoir"
    assert_allclose(-d["normal_force"], ref["N"], rtol=RTOL)
    assert_allclose(d["shear_force"], ref["H"], rtol=RTOL)
    assert_allclose(d["compressed_length"], B, rtol=RTOL)  # in the kern: the whole base
    assert_allclose(d["cohesion"], 150e3, rtol=RTOL)
    assert "design cohesion" in d["cohesion_source"]
    assert_allclose(d["shear_friction_factor"], ref["sff"], rtol=RTOL)
    assert_allclose(d["friction_only_factor"], ref["friction"], rtol=RTOL)
    assert_allclose(d["overturning_factor"], ref["overturning"], rtol=RTOL)
    assert_allclose([d["resisting_moment"], d["overturning_moment"]], [ref["M_r"], ref["M_o"]],
                    rtol=RTOL)
    assert_allclose(d["resultant_from_toe"], ref["from_toe"], rtol=RTOL)
    assert_allclose(d["resultant_from_heel"], B - ref["from_toe"], rtol=RTOL)
    assert_allclose(d["e_over_B"], (B / 2 - ref["from_toe"]) / B, rtol=1e-8)
    assert d["in_middle_third"] is True
    # without the design cohesion: the joint has none, SFF = the friction-only factor
    own = coulomb.interface_safety("base", design=H_D).design_values()
    assert own["cohesion_source"].startswith("none")
    assert_allclose(own["shear_friction_factor"], ref["friction"], rtol=RTOL)


def test_margins_are_level_ratios_and_keep_their_old_names(coulomb):
    """The load margin against sliding: the level at sliding over the design level, m / m;
    sliding when γ_w h²/2 = f (W − γ_w h B/2) (hand root, 1e-9)."""
    a, b, c = GAMMA_W / 2, F * GAMMA_W * B / 2, -F * W
    h_slide = (-b + np.sqrt(b * b - 4 * a * c)) / (2 * a)
    s = coulomb.interface_safety("base", design=H_D)
    assert s.is_level and s.mechanism == "sliding"
    assert_allclose(s.margin_sliding, h_slide / H_D, rtol=RTOL)
    assert s.fs_sliding == s.margin_sliding and s.fs_overturning == s.margin_overturning
    assert s.margin_overturning is None
    assert_allclose(s.friction_only_factor[-1], 1.0, rtol=RTOL)  # every CFE slips
    # the weight's λ as the parameter: the dam slid in a segment of another pattern (no
    # margin); at λ = 1 of the weight alone there is no overturning moment
    w = coulomb.interface_safety("base", design=1.0, pattern="weight")
    assert w.margin_sliding is None and not w.is_level
    d = w.design_values()
    assert_allclose(-d["normal_force"], W, rtol=RTOL)
    assert d["overturning_factor"] is None  # the weight's nodal forces have no x component
    assert any("no overturning moment" in n for n in d["notes"])


def test_residual_cohesion_of_the_joint(residual):
    """The joint's own cohesion: its bonds broke under the weight, every CFE keeps the residual
    cohesion C_r = 100 kPa while closed.  At h = 10 m: SFF = (C_r B + f (W − U))/H (1e-9).
    At sliding every closed CFE slips at |Q| = f p + C_r A_k, the opened ones have lost C_r:
    the shear-friction factor with the joint's cohesion is 1 there (1e-9)."""
    s = residual.interface_safety("base", design=H_D)
    d, ref = s.design_values(), hand(H_D, 100e3)
    k = residual.cfe["interface"] == 0
    assert not np.any(residual.state[d["state"]][k] == int(sc.ContactState.BONDED))
    assert "bond" in d["cohesion_source"]
    assert_allclose(d["cohesion"], 100e3, rtol=RTOL)
    assert_allclose(d["shear_friction_factor"], ref["sff"], rtol=RTOL)
    assert_allclose(d["friction_only_factor"], ref["friction"], rtol=RTOL)
    assert_allclose(d["overturning_factor"], ref["overturning"], rtol=RTOL)
    assert residual.status == sc.Status.EQUILIBRIUM_LOST and s.mechanism == "sliding"
    lost = residual.cfe["cohesion_lost"][k] >= 0
    assert lost.any() and not lost.all()  # the heel opened before the dam slid
    assert_allclose(s.shear_friction_factor[-1], 1.0, rtol=RTOL)
    assert s.friction_only_factor[-1] < 1.0  # the cohesion carries part of the shear
    # the compressed length excludes the opened CFEs: the tributary lengths of the closed CFEs
    # with N < 0
    N, closed = residual.N[-1][k], residual.state[-1][k] != int(sc.ContactState.OPEN)
    x = residual.cfe["x"][k, 0]
    trib = np.where((x == 0.0) | (x == B), 0.5, 1.0)
    assert_allclose(s.compressed_length[-1], trib[(N < 0) & closed].sum(), rtol=RTOL)
    assert s.compressed_length[-1] < B


def test_intact_bond_gives_tau_r_and_alpha_r():
    """An intact bond: c = τ_R = 300 kPa and tan φ = α_R = 0.7 on the bonded CFEs (1e-9)."""
    res = sc.solve_static(dam(sc.Bond(tensile=5e6, shear=300e3, alpha=F, friction=F), (H_D,)))
    d = res.interface_safety("base", design=H_D).design_values()
    k = res.cfe["interface"] == 0
    assert np.all(res.state[d["state"]][k] == int(sc.ContactState.BONDED))
    assert_allclose(d["shear_friction_factor"], hand(H_D, 300e3)["sff"], rtol=RTOL)
    assert_allclose(d["compressed_length"], B, rtol=RTOL)


def test_crack_water_counts_in_the_overturning_moment():
    """f = 1.2 and crack water entering at the heel (sc.CrackWater): the heel opens above the
    crest level and the water in the crack lifts the dam.  At the last state (the level h
    above the 12 m face, the crack open over part of the base), about the toe: M_r = W x_W,
    M_o = H y_H + U 2B/3 + Σ W_k (B − x_k), with the face load a trapezoid of pressures
    γ_w (h − 12) … γ_w h over 12 m (resultant H at y_H above the base), U = γ_w h B/2 and W_k
    the crack water's force on each CFE beyond the uplift (res.water); ΣN = W − U − ΣW_k.
    The crack water is a state-dependent load: it must be in M_o (1e-9)."""
    res = sc.solve_static(dam(levels=(11.0, 12.0, 20.0), friction=1.2, crack_water=True))
    k = res.cfe["interface"] == 0
    Wk, x = res.water[-1][k], res.cfe["x"][k, 0]
    assert Wk.sum() > 0.05 * W  # the crack holds water
    h = res.lam[-1]
    top, bot = GAMMA_W * (h - HEIGHT), GAMMA_W * h
    H = (top + bot) / 2 * HEIGHT
    y_H = HEIGHT * (2 * top + bot) / (3 * (top + bot))
    U = GAMMA_W * h * B / 2
    M_r, M_o = W * X_W, H * y_H + U * 2 * B / 3 + (Wk * (B - x)).sum()
    s = res.interface_safety("base")
    assert s.overturning_note is None
    assert_allclose(-s.normal_force[-1], W - U - Wk.sum(), rtol=RTOL)
    assert_allclose([s.resisting_moment[-1], s.overturning_moment[-1]], [M_r, M_o], rtol=RTOL)
    assert_allclose(s.overturning_factor[-1], M_r / M_o, rtol=RTOL)
    assert_allclose(s.from_toe[-1], (M_r - M_o) / (W - U - Wk.sum()), rtol=1e-8)


def test_the_part_may_be_on_the_minus_side(coulomb):
    """The same dam with the rock's face as S+ and the dam's as S−: the part the joint holds
    is found on the S− side (the rock is supported); every factor as before (1e-9) — the
    heel chosen as the end the loads push away from."""
    res = sc.solve_static(dam(levels=(H_D,), swap=True))
    d = res.interface_safety("base", design=H_D, cohesion=150e3, heel="auto").design_values()
    ref = hand(H_D, 150e3)
    assert d["notes"] == []
    for key, value in (("shear_friction_factor", ref["sff"]), ("overturning_factor",
                       ref["overturning"]), ("resultant_from_toe", ref["from_toe"]),
                       ("compressed_length", B)):
        assert_allclose(d[key], value, rtol=RTOL, err_msg=key)


def test_level_without_a_state_at_the_design_level(coulomb):
    """h_d = 10.5 m inside a segment that moves the level: no number, a note to end a segment
    there (a level segment is not linear in the level between events)."""
    s = coulomb.interface_safety("base", design=10.5)
    d = s.design_values()
    assert d["state"] is None and "shear_friction_factor" not in d
    assert any("end a segment at 10.5 m" in n for n in d["notes"])
    assert_allclose(s.margin_sliding * 10.5, s.lam_sliding, rtol=1e-12)
    beyond = coulomb.interface_safety("base", design=30.0).design_values()
    assert beyond["state"] is None and "does not reach" in beyond["notes"][0]


# --------------------------------------------------------------------------------------------
# a rectangular block under a linear load: an interpolated design state, a partly open base
# --------------------------------------------------------------------------------------------
BR, HR, D = 8.0, 10.0, 9.5  # block width and height, water depth (m)
WR = 2400 * 9.81 * BR * HR
HW, UW = GAMMA_W * D**2 / 2, GAMMA_W * D * BR / 2  # per unit λ: at D/3, and 2B/3 from the toe


@pytest.fixture(scope="module")
def block():
    rock = sc.rectangle("rock", (-5.0, -5.0), (13.0, 0.0), 18, 5, ROCK)
    body = sc.rectangle("dam", (0.0, 0.0), (BR, HR), 8, 10, CONCRETE)
    m = sc.Model(bodies=[rock, body], name="block")
    base = sc.Interface("base", m.select("dam", y=0.0), m.select("rock", y=0.0), friction=1.0)
    m = m.add(
        sc.Support("bed", m.select("rock", y=-5.0)), base,
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("dam",))]),
        sc.LoadPattern("water", [sc.WaterLoad(m.select("dam", x=0.0), level=D),
                                 sc.Uplift(base, head=[(0.0, 0.0, D), (BR, 0.0, 0.0)])]),
        sc.Segment("weight", 1.0), sc.Segment("water", 3.0))
    return sc.solve_static(m)


def test_interpolated_state_with_a_partly_open_base(block):
    """λ_d = 2 of the water pattern lies between two events: the state is interpolated
    (linear path).  The resultant lies outside the kern, the heel is open: the cohesion counts
    on the compressed CFEs only.  Hand: ΣN = W − 2U, SFF = (c L_c + f ΣN)/(2H) with L_c the
    tributary lengths of the closed CFEs with N < 0 (StaticResult.interpolate), overturning
    W (B/2) / (2 (H D/3 + U 2B/3)), resultant from the toe (M_r − M_o)/ΣN; 1e-9."""
    lam, c = 2.0, 100e3
    s = block.interface_safety("base", design=lam, cohesion=c)
    d = s.design_values()
    assert d["interpolated"] and d["state"] is None and d["pattern"] == "water"
    assert not np.any(np.abs(block.lam[block.segment == 1] - lam) < 1e-9)
    seg = int(np.flatnonzero([p == "water" for p, _, _ in block.segments])[0])
    k = block.cfe["interface"] == 0
    at = block.interpolate(lam, seg)
    N, closed = at["N"][k], at["state"][k] != int(sc.ContactState.OPEN)
    x = block.cfe["x"][k, 0]
    trib = np.where((x == 0.0) | (x == BR), 0.5, 1.0)
    L_c = trib[(N < 0) & closed].sum()
    assert 0 < L_c < BR  # partly open
    sN = WR - lam * UW
    M_r, M_o = WR * BR / 2, lam * (HW * D / 3 + UW * 2 * BR / 3)
    assert_allclose(d["compressed_length"], L_c, rtol=RTOL)
    assert_allclose(-d["normal_force"], sN, rtol=RTOL)
    assert_allclose(d["shear_friction_factor"], (c * L_c + 1.0 * sN) / (lam * HW), rtol=RTOL)
    assert_allclose(d["friction_only_factor"], sN / (lam * HW), rtol=RTOL)
    assert_allclose(d["overturning_factor"], M_r / M_o, rtol=RTOL)
    assert_allclose(d["resultant_from_toe"], (M_r - M_o) / sN, rtol=RTOL)
    assert d["in_middle_third"] is False


def test_old_result_file_gives_no_overturning_factor(block, tmp_path):
    """The round trip keeps the load moments (bitwise) and every factor; a file written before
    they were stored gives no overturning factor and says why — never a wrong number."""
    block.save(tmp_path / "block.nc")
    back = sc.load_result(tmp_path / "block.nc")
    assert_allclose(back.load_moments, block.load_moments, rtol=0, atol=0)
    a = back.interface_safety("base", design=2.0, cohesion=1e5)
    b = block.interface_safety("base", design=2.0, cohesion=1e5)
    assert a.design_values() == b.design_values()
    assert a.at() == b.at()
    import xarray as xr

    with xr.open_dataset(tmp_path / "block.nc") as ds:
        old = ds.drop_vars(["load_moments", "load_body", "load_moment_component"]).load()
    old.to_netcdf(tmp_path / "old.nc")
    s = sc.load_result(tmp_path / "old.nc").interface_safety("base", design=2.0, cohesion=1e5)
    d = s.design_values()
    assert d["overturning_factor"] is None and np.isnan(s.overturning_factor).all()
    assert any("written before" in n for n in d["notes"])
    assert_allclose(d["shear_friction_factor"], b.design_values()["shear_friction_factor"])


def test_a_part_held_by_a_support_has_no_overturning_factor():
    """A block held in x at its top as well as by the joint: the moment of its loads about the
    toe is not the joint's, so no overturning factor (a note says why)."""
    m = vm.block_on_base(friction=0.5, nx=4, x_support=True)
    top = m.select("block", y=0.5)
    m = m.add(sc.LoadPattern("push", [sc.EdgeLoad(top, normal=1e3, tangential=-200.0)]),
              sc.Segment("push", 1.0))
    s = sc.solve_static(m).interface_safety("contact", design=1.0)
    d = s.design_values()
    assert d["overturning_factor"] is None and "not held by the joint alone" in d["notes"][-1]


def test_degenerate_start_gives_no_nan_warning():
    """Loaded from zero with every contact closed at N = Q = 0: state 0 has no force on the
    joint; the factors there are None (JSON) / NaN-free of warnings, and at λ_d the hand
    values: ΣN = p w, ΣQ = r w, SFF = friction only = f p / r, overturning about the toe from
    the pressure alone (its moment resists, the shear's overturns: p w (w/2) / (r w h))."""
    p, r, f, w, h = 1.0, 0.3, 0.6, 2.0, 0.5
    m = vm.block_on_base(friction=f, nx=4, ny=2, w=w, h=h)
    top = m.select("block", y=h)
    m = m.add(sc.LoadPattern("press", [sc.EdgeLoad(top, normal=p, tangential=-r)]),
              sc.Segment("press", 1e6))
    res = sc.solve_static(m)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = res.interface_safety("contact", design=5e5, heel="auto")
        first = s.at(0)
        d = s.design_values()
    assert first["shear_friction_factor"] is None and first["overturning_factor"] is None
    assert first["friction_only_factor"] is None
    lam = 5e5
    assert_allclose(-d["normal_force"], lam * p * w, rtol=RTOL)
    assert_allclose(d["shear_friction_factor"], f * p / r, rtol=RTOL)
    # the traction pushes along −x: the heel is at x = w ("auto"), the toe at x = 0, about
    # which the traction at height h lifts the heel and the pressure holds it down
    assert_allclose(s.joint_heel, [w, 0.0], atol=1e-12)
    M_r, M_o = lam * p * w * w / 2, lam * r * w * h
    assert_allclose(d["overturning_factor"], M_r / M_o, rtol=RTOL)


# --------------------------------------------------------------------------------------------
# the CLI
# --------------------------------------------------------------------------------------------
def test_cli_info_prints_the_engineers_factors(residual, tmp_path):
    nc = tmp_path / "dam.nc"
    residual.save(nc)
    ref = hand(H_D, 100e3)
    out = runner.invoke(app, ["info", str(nc), "--design", "10"])
    assert out.exit_code == 0, out.output
    text = out.stdout
    for label in ("at the design level h = 10 m of 'reservoir'",
                  "shear-friction factor (c·A_c + N'·tanφ)/H",
                  "friction-only factor N'·tanφ/H",
                  "overturning factor ΣM_r/ΣM_o about the toe",
                  "resultant from the toe (m)", "e/B, in the middle third",
                  "compressed length (m)", "cohesion from",
                  "margin: level at sliding / design level"):
        assert label in text, label
    assert f"{ref['sff']:.6g}" in text and f"{ref['overturning']:.6g}" in text
    assert f"{residual.interface_safety('base').lam_sliding:.6g} m / 10 m" in text
    out = runner.invoke(app, ["info", str(nc), "--design", "10", "--cohesion", "2e5", "--json"])
    assert out.exit_code == 0, out.output
    info = json.loads(out.stdout)
    (got,) = info["interface_safety"]
    # the user's patterns, not the level's internal pieces
    assert info["model"]["patterns"] == ["weight", "reservoir"]
    d = got["design_state"]
    assert_allclose(d["shear_friction_factor"], hand(H_D, 2e5)["sff"], rtol=RTOL)
    assert_allclose(d["overturning_factor"], ref["overturning"], rtol=RTOL)
    assert_allclose(d["compressed_length"], B, rtol=RTOL)
    assert "design cohesion" in d["cohesion_source"]
    assert_allclose(got["margin_sliding"] * 10, got["lam_sliding"], rtol=1e-12)
    out = runner.invoke(app, ["info", str(nc), "--design", "10.5"])
    assert out.exit_code == 0, out.output
    assert "end a segment at 10.5 m" in " ".join(out.stdout.split())
    out = runner.invoke(app, ["info", str(nc), "--design", "10", "--cohesion", "-1"])
    assert out.exit_code != 0


def test_a_lift_joint_inside_a_sliding_body_is_not_where_it_slides():
    """Two blocks stacked on a foundation (lift joint f = 0.9 between them, base f = 0.5),
    weight, then a push on the lower block: both slide together on the base at
    P = 0.5 (W₁ + W₂) (hand statics, 1e-9).  The mechanism moves both blocks alike, so it is
    the base's sliding, not the lift joint's (whose faces do not move relative to each other)."""
    mat = sc.Material(E=30e9, nu=0.2, density=2400)
    m = sc.Model(bodies=[sc.rectangle("ground", (-2, -1), (4, 0), 6, 2, mat),
                         sc.rectangle("lower", (0, 0), (2, 1), 4, 2, mat),
                         sc.rectangle("upper", (0, 1), (2, 2), 4, 2, mat)])
    W = 2 * 2400 * 9.81 * 2.0  # both blocks, N per metre
    m = m.add(
        sc.Support("fixed", m.select("ground", y=-1), "xy"),
        sc.Interface("base", plus=m.select("lower", y=0), minus=m.select("ground", y=0),
                     friction=0.5),
        sc.Interface("lift", plus=m.select("upper", y=1), minus=m.select("lower", y=1),
                     friction=0.9),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("lower", "upper"))]),
        sc.LoadPattern("push", [sc.EdgeLoad(m.select("lower", x=0), traction=(1.0, 0.0))]),
        sc.Segment("weight", 1.0), sc.Segment("push", 2 * W),
    )
    res = sc.solve_static(m)
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    base, lift = (res.interface_safety(n, heel="auto") for n in ("base", "lift"))
    assert base.mechanism == "sliding"
    assert_allclose(base.lam_sliding, 0.5 * W, rtol=RTOL)  # traction 1 Pa on a 1 m face
    assert lift.mechanism is None and lift.lam_sliding is None


def test_info_shows_the_round_off_of_an_open_end_as_zero():
    """An open heel's σn is 0 up to the round-off of the sum of the CFE forces (here 3e-13 Pa
    beside 1.3 MPa at the toe): info prints 0, and keeps a real small stress."""
    from stepcontact.cli.commands import _clean_pair

    assert _clean_pair(3.3e-13, -1.32e6) == (0.0, -1.32e6)
    assert _clean_pair(-5.0, -1.32e6) == (-5.0, -1.32e6)
    assert _clean_pair(0.0, 0.0) == (0.0, 0.0)
