"""Water in the opened parts of a joint (CrackWater): the crack pressure, the crack running along
a dam's base at one load factor (events in order), overturning, a moving level, the uplift it
replaces, files and errors.

Reference: a rigid block on a Winkler layer (the compliant contact layer, C_k = k_n A_k at the
CFE's point x_k), solved here by hand.  The base's normal problem does not depend on the
tangential one (every CFE lies on y = 0), so for a crack of the first j CFEs from the heel
(wet, each loaded by W_k = A_k (p_c − p_u)) the two unknowns v (vertical displacement at x = 0)
and θ (rotation) follow from vertical and moment equilibrium of the closed CFEs' springs
p_k = −C_k (v + θ x_k).  The crack grows where the next CFE's p_k reaches 0; when the water it
lets in makes the next one tensile at the same λ, that one opens too (a cascade).  The block
is made 1e6 times stiffer than the layer (E/k_n in m): tolerances 1e-5 (relative) on λ, 1e-5 of the
largest force on the contact forces, 1e-6 on the equilibrium residual (K spans 1e6 in stiffness).
"""

from __future__ import annotations

import string

import numpy as np
import pytest
from scipy.optimize import brentq

import stepcontact as sc
from model_toml import gravity_dam
from stepcontact.enums import Status, Transition
from stepcontact.errors import ModelError

GW = 9810.0
KN = 1e8  # Pa/m, the layer
HEIGHT = 12.0
RHO = 2400.0


def dam_model(B=8.0, H=11.0, lam_end=1.0, crack=True, level_param=False, uplift=False,
              nx=16, E=1e14):
    """A stiff rectangular block B × 12 m on a compliant layer on a rigid base (obstacle),
    weight then water on its upstream face (x = 0) to level H (or the level itself as the load
    parameter), with crack water entering at the heel."""
    conc = sc.Material(E=E, nu=0.2, density=RHO)
    dam = sc.rectangle("dam", (0, 0), (B, HEIGHT), nx, 24, conc)
    m = sc.Model(bodies=[dam])
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (B + 1.0, 0.0)])
    base = sc.Interface("base", plus=m.select("dam", y=0), minus=ground, friction=5.0,
                        layer=sc.ContactLayer(kn=KN, kt=KN))
    level = None if level_param else H
    water = [sc.WaterLoad(m.select("dam", x=0.0), level=level)]
    if crack:
        water.append(sc.CrackWater(base, level=level, entry=(0.0, 0.0)))
    if uplift:  # head (level at the heel) → 0 at the toe, per unit factor
        head = [(0.0, 0.0, 1.0 if level_param else H), (B, 0.0, 0.0)]
        water.append(sc.Uplift(base, head=head))
    m = m.add(base, sc.LoadPattern("weight", [sc.BodyForce(bodies=("dam",))]),
              sc.LoadPattern("water", water), sc.Segment("weight", 1.0),
              sc.Segment("water", lam_end))
    return m


class RigidBlock:
    """The hand reference: CFE points x (m), areas A (m²), and the loads as functions of the
    water parameter t (λ for a fixed level, the level h for a moving one)."""

    def __init__(self, res, B, H=None, level_param=False, uplift=False, crack=True):
        self.x = res.cfe["x"][:, 0]
        self.A = res.cfe["area"]
        self.C = KN * self.A
        self.W = RHO * 9.81 * B * HEIGHT
        self.B, self.H, self.level_param, self.uplift, self.crack = B, H, level_param, uplift, \
            crack

    def loads(self, t):
        """(water thrust, its moment about the base, crack pressure at y = 0, uplift at the
        CFE points (m,), the uplift's consistent nodal forces (m,)) at t.  Water above the
        crest (a moving level) loads only the face, 0 ≤ y ≤ 12 m."""
        h, c = (t, 1.0) if self.level_param else (self.H, t)
        d = min(h, HEIGHT)
        F = c * GW * (h * d - d * d / 2)
        M = c * GW * (h * d * d / 2 - d**3 / 3)
        if not self.uplift:
            zero = np.zeros_like(self.x)
            return F, M, c * GW * h, zero, zero
        pu = c * GW * h * (1 - self.x / self.B)
        # consistent nodal forces of the linear pressure on the base's edges (the assembly's)
        L = np.diff(self.x)
        fu = np.zeros_like(self.x)
        fu[:-1] += L * (2 * pu[:-1] + pu[1:]) / 6
        fu[1:] += L * (pu[:-1] + 2 * pu[1:]) / 6
        return F, M, c * GW * h, pu, fu

    def solve(self, j, t):
        """Contact forces p (m,) (compression > 0) with the first j CFEs open and wet."""
        F, MF, pc, pu, fu = self.loads(t)
        closed = np.arange(len(self.x)) >= j
        # external: weight at B/2, thrust, uplift (nodal forces up), crack water (pc − pu) A
        ext = -fu  # (as a force −p)
        if self.crack:
            ext = ext - np.where(~closed, (pc - pu) * self.A, 0.0)
        # vertical: Σ p_closed = W + Σ ext;  moment about x = 0
        fy = self.W + ext.sum()
        mz = self.W * self.B / 2 + MF + (ext * self.x).sum()
        Cc, xc = self.C[closed], self.x[closed]
        # p_k = −C_k (v + θ x_k): Σ p = fy, Σ p x = mz
        M = -np.array([[Cc.sum(), (Cc * xc).sum()], [(Cc * xc).sum(), (Cc * xc**2).sum()]])
        v, th = np.linalg.solve(M, [fy, mz])
        return np.where(closed, -self.C * (v + th * self.x), 0.0)

    def openings(self, t0, t1):
        """[(CFE, t)] of the crack from the heel between t0 and t1 (cascades at equal t), and
        t where one CFE is left (overturning) or None."""
        out, j, t = [], 0, t0
        while j < len(self.x) - 1:
            p = self.solve(j, t)
            if p[j] < -1e-9 * self.W:  # the water just let in opens the next one: cascade
                out.append((j, t))
                j += 1
                continue
            def g(s, j=j):
                return self.solve(j, s)[j]

            if g(t1) > 0:
                return out, None
            t = brentq(g, t, t1, xtol=1e-14, rtol=1e-15)
            out.append((j, t))
            j += 1
        return out, t


def openings_of(res):
    return [(e.local, e.lam) for e in res.events
            if e.transition == Transition.OPENED and e.segment == 1]


@pytest.fixture(scope="module")
def crack_run():
    m = dam_model(lam_end=2.0)
    return m, sc.solve_static(m)


def test_crack_runs_along_the_base_in_the_order_and_at_the_load_factors_of_the_reference(
        crack_run):
    _, res = crack_run
    ref, lost = RigidBlock(res, 8.0, 11.0).openings(0.0, 2.0)
    got = openings_of(res)
    # the run ends by overturning on the toe, where one CFE is left
    assert res.status == Status.EQUILIBRIUM_LOST
    assert "overturning" in res.message
    assert lost is not None and res.multipliers[-1].equilibrium_lost == pytest.approx(lost,
                                                                                      rel=1e-5)
    assert [k for k, _ in got] == [k for k, _ in ref]
    np.testing.assert_allclose([t for _, t in got], [t for _, t in ref], rtol=1e-5)
    lams = np.array([t for _, t in ref])
    assert np.sum(np.diff(lams) == 0) >= 3  # a cascade: several openings at one λ
    # every reported state: equilibrium with the crack water, contact conditions
    assert res.residual.max() < 1e-6
    assert res.violation.max() < 1e-9


def test_crack_pressure_is_the_water_pressure_and_the_closed_part_matches_the_reference(
        crack_run):
    m, _ = crack_run
    m = m.replace(program=(sc.Segment("weight", 1.0), sc.Segment("water", 1.55)))
    res = sc.solve_static(m)
    assert res.status == Status.COMPLETED
    i = len(res.lam) - 1
    wet = res.water[i] > 0
    assert wet.sum() >= 5
    # open CFEs: no contact force; the joint's normal stress is the crack pressure
    assert np.all(res.state[i][wet] == int(sc.ContactState.OPEN))
    W = RHO * 9.81 * 8.0 * HEIGHT
    np.testing.assert_allclose(res.N[i][wet], 0.0, atol=1e-9 * W)  # round-off of the path
    np.testing.assert_allclose(res.crack_pressure[i][wet], 1.55 * GW * 11.0, rtol=1e-8)
    # the crack runs from the heel without a gap
    assert np.all(wet[: wet.sum()])
    ref = RigidBlock(res, 8.0, 11.0).solve(int(wet.sum()), 1.55)
    np.testing.assert_allclose(-res.N[i], ref, rtol=0, atol=1e-5 * ref.max())


def test_heel_under_9_m_of_water_carries_minus_88290_pa():
    """A narrow block (B = 4 m) with 9 m of water: its heel cracks; the normal stress in the
    open part is −ρ_w g · 9 = −88 290 Pa."""
    res = sc.solve_static(dam_model(B=4.0, H=9.0, lam_end=1.0, nx=8))
    assert res.status == Status.COMPLETED
    i = len(res.lam) - 1
    wet = res.water[i] > 0
    assert wet.any()
    np.testing.assert_allclose(res.crack_pressure[i][wet], 88290.0, rtol=1e-8)
    # open: σ_n = 0 to round-off of the stresses (1e-8 of the water pressure)
    np.testing.assert_allclose(res.sigma_n[i][wet], 0.0, atol=1e-8 * 88290.0)
    assert res.residual[i] < 1e-6


def test_without_crack_water_the_crack_opens_later_and_the_dam_overturns_later():
    res_w = sc.solve_static(dam_model(lam_end=6.0, crack=True))
    res_d = sc.solve_static(dam_model(lam_end=6.0, crack=False))
    assert res_d.water is None
    ref_d, lost_d = RigidBlock(res_d, 8.0, 11.0, crack=False).openings(0.0, 6.0)
    np.testing.assert_allclose([t for _, t in openings_of(res_d)], [t for _, t in ref_d],
                               rtol=1e-5)
    assert res_d.multipliers[-1].equilibrium_lost == pytest.approx(lost_d, rel=1e-5)
    # the first opening is the same (the water enters only then); the rest come earlier
    assert openings_of(res_w)[0][1] == pytest.approx(openings_of(res_d)[0][1], rel=1e-9)
    assert res_w.multipliers[-1].equilibrium_lost < 0.5 * lost_d


def test_the_crack_pressure_replaces_the_uplift_in_the_open_part():
    m = dam_model(lam_end=2.0, uplift=True)
    res = sc.solve_static(m)
    rb = RigidBlock(res, 8.0, 11.0, uplift=True)
    ref, lost = rb.openings(0.0, 2.0)
    got = openings_of(res)
    assert [k for k, _ in got] == [k for k, _ in ref]
    np.testing.assert_allclose([t for _, t in got], [t for _, t in ref], rtol=1e-5)
    if lost is not None:
        assert res.multipliers[-1].equilibrium_lost == pytest.approx(lost, rel=1e-5)
    # on a wet CFE the water's force is the crack pressure less the uplift there
    i = int(np.flatnonzero(res.water.max(axis=1) > 0)[-1])
    wet = res.water[i] > 0
    lam = res.factors[i][list(res.pattern_names).index("water")]
    x = res.cfe["x"][wet, 0]
    expect = res.cfe["area"][wet] * lam * GW * 11.0 * (1 - (1 - x / 8.0))
    np.testing.assert_allclose(res.water[i][wet], expect, rtol=1e-12)


def test_the_level_as_load_parameter_moves_the_crack_water_with_it():
    m = dam_model(level_param=True, lam_end=20.0)
    res = sc.solve_static(m)
    rb = RigidBlock(res, 8.0, level_param=True)
    ref, lost = rb.openings(0.0, 20.0)
    got = openings_of(res)
    assert len(ref) >= 3
    assert [k for k, _ in got] == [k for k, _ in ref]
    np.testing.assert_allclose([t for _, t in got], [t for _, t in ref], rtol=1e-5)
    if lost is not None:
        assert res.multipliers[-1].equilibrium_lost == pytest.approx(lost, rel=1e-5)
    assert res.residual.max() < 1e-6


def test_water_is_kept_in_the_result_file_and_fields_are_recovered_with_it(tmp_path,
                                                                          crack_run):
    m, res = crack_run
    path = tmp_path / "r.nc"
    res.save(path)
    back = sc.load_result(path)
    np.testing.assert_array_equal(back.water, res.water)
    back.recover_fields(m)
    i = int(np.flatnonzero(res.water.max(axis=1) > 0)[len(res.events) // 4])
    np.testing.assert_allclose(back.displacement(i), res.displacement(i), rtol=1e-10,
                               atol=1e-14)


def test_bad_crack_water_inputs_name_the_item():
    m = dam_model()
    with pytest.raises(ModelError, match="interface 'nope'"):
        sc.assemble(m.replace(patterns=(*m.patterns, sc.LoadPattern(
            "more", [sc.CrackWater("nope", level=3.0)]))))
    with pytest.raises(ModelError, match="not a level"):
        sc.assemble(m.replace(patterns=(*m.patterns, sc.LoadPattern(
            "more", [sc.CrackWater("base", entry=(0.0, 0.0))]))))
    with pytest.raises(ModelError, match="entry"):
        sc.CrackWater("base", level=3.0, entry=(1.0,))
    with pytest.raises(ModelError, match="unit_weight"):
        sc.CrackWater("base", level=3.0, unit_weight=-1.0)
    with pytest.raises(ModelError, match="not both"):
        sc.CrackWater("base", level=3.0, pressure=1e4)
    with pytest.raises(ModelError, match="entry"):
        sc.CrackWater("base", pressure=1e4, entry=[(0.0, 0.0), (1.0,)])
    two = sc.CrackWater("base", pressure=1e4, entry=[(0.0, 0.0), (8.0, 0.0)])
    assert two.entry == ((0.0, 0.0), (8.0, 0.0)) and two.entries.shape == (2, 2)
    np.testing.assert_array_equal(two.crack_pressure(np.array([0.0, 5.0])), [1e4, 1e4])


def test_several_entries_wet_the_runs_joined_to_any_of_them():
    """A crack from each end of the base (entries at heel and toe): runs of open CFEs joined
    to either end are wet, an open CFE in between (not joined) stays dry."""
    m = dam_model(nx=8, crack=False)
    system = sc.assemble(m.replace(patterns=(*m.patterns, sc.LoadPattern("joint", [
        sc.CrackWater("base", pressure=1.0, entry=[(0.0, 0.0), (8.0, 0.0)])]))))
    crack = system.crack
    order = np.argsort(system.cfe.x[:, 0])
    states = np.full(system.m, int(sc.ContactState.STICK))
    states[order[[0, 1, 4, 7, 8]]] = int(sc.ContactState.OPEN)
    wet = crack.wet(states)
    assert set(np.flatnonzero(wet[order])) == {0, 1, 7, 8}


def block_toml(width: float, nx: int, friction: float, water: str, end: float,
               bond: str = "") -> str:
    """The stiff block of :func:`dam_model` in the model-file form (12 m high, ``width`` m
    wide, on a compliant layer on a rigid base; ``bond``: an ``[interfaces.bond]`` table),
    weight, then the pattern ``water`` (its loads, TOML) to ``end``."""
    return string.Template("""
[materials.c]
E = 1e14
nu = 0.2
density = 2400

[[bodies]]
name = "dam"
kind = "rectangle"
corner0 = [0.0, 0.0]
corner1 = [$width, 12.0]
nx = $nx
ny = 24
material = "c"

[node_sets.upstream]
body = "dam"
x = 0.0

[node_sets.bottom]
body = "dam"
y = 0.0

[[obstacles]]
name = "ground"
points = [[-1.0, 0.0], [$right, 0.0]]

[[interfaces]]
name = "base"
plus = "bottom"
obstacle = "ground"
friction = $friction
layer = { kn = 1e8, kt = 1e8 }
$bond

[patterns.weight]
loads = [{ type = "gravity" }]

[patterns.water]
loads = $water

[[program]]
pattern = "weight"
end = 1.0

[[program]]
pattern = "water"
end = $end
""").substitute(width=width, nx=nx, right=width + 1.0, friction=friction, water=water,
                end=end, bond=bond)


def test_model_file_crack_water(tmp_path):
    from stepcontact.io.modelfile import load_model

    text = block_toml(4.0, 8, 5.0, """[{ type = "water", nodes = "upstream", level = 9.0 },
         { type = "crack_water", interface = "base", level = 9.0, entry = [0.0, 0.0] }]""",
                      1.0)
    f = tmp_path / "m.toml"
    f.write_text(text)
    try:
        m = load_model(f)
    except ModelError as exc:  # the file format of this test must be the documented one
        pytest.fail(str(exc))
    res = sc.solve_static(m)
    i = len(res.lam) - 1
    wet = res.water[i] > 0
    assert wet.any()
    np.testing.assert_allclose(res.crack_pressure[i][wet], 88290.0, rtol=1e-8)
    # a given pressure in the crack (the same 88 290 Pa), with entries as a list of points
    f.write_text(text.replace('level = 9.0, entry = [0.0, 0.0]',
                              'pressure = 88290.0, entry = [[0.0, 0.0], [4.0, 0.0]]'))
    res2 = sc.solve_static(load_model(f))
    np.testing.assert_allclose(res2.crack_pressure[-1][wet], 88290.0, rtol=1e-8)
    f.write_text(text.replace('level = 9.0, entry', 'level = 9.0, pressure = 1.0, entry'))
    with pytest.raises(ModelError, match="not both"):
        load_model(f)


def test_stress_diagram_draws_the_crack_pressure(crack_run):
    import matplotlib

    matplotlib.use("Agg")
    _, res = crack_run
    i = int(np.flatnonzero(res.water.max(axis=1) > 0)[-1])
    fig = sc.plot_interfaces(res, states=[i])
    ax = fig.axes[0]
    dotted = [ln for ln in ax.get_lines() if ln.get_linestyle() == ":"]
    assert len(dotted) == 1
    y = np.asarray(dotted[0].get_ydata(), float)
    p = res.crack_pressure[i][np.argsort(res.cfe["s"], kind="stable")]
    scale = min((1.0, 1e3, 1e6), key=lambda v: abs(v * -np.nanmin(y) / p.max() - 1))
    np.testing.assert_allclose(-y[p > 0] * scale, p[p > 0], rtol=1e-12)
    assert np.all(np.isnan(y[p == 0]))
    assert "crack" in ax.get_ylabel()


# the docs' dam (docs/model-file.md) with drains and the EM 1110 cracked-base rule: water
# entering the heel's CFEs raises the pressure beyond the tip, which closes the heel, and
# dry the heel opens again: no wet set is consistent at that level
_EM1110_DAM = gravity_dam() + """
[patterns.reservoir]
loads = [
  { type = "water", nodes = "upstream" },
  { type = "uplift", interface = "base", drained = { heel = [0.0, 0.0], toe = [8.0, 0.0], \
drain = [2.0, 0.0], efficiency = 0.6667, reference = "tailwater" } },
  { type = "crack_water", interface = "base", entry = [0.0, 0.0], rule = "em1110", \
bridge = 1.0 },
]
[[program]]
pattern = "weight"
end = 1.0
[[program]]
pattern = "reservoir"
end = 30.0
"""


def test_a_wet_set_that_recurs_at_one_level_is_held_and_reported_not_chattered():
    """Where the heel's water and its opening have no consistent pair at one level, the run
    holds the water in the cycle's wet sets and records it in ``nonunique`` (before, the
    driver followed the flip-flop 50 times per point, 100 states at one λ, and its outcome
    depended on round-off).  Reference: the level at which the dam slides as the docs state
    it (12.98291 m, rtol 1e-6, the value of the run before the guard, which it does not
    change); equilibrium and contact conditions at every state to round-off."""
    import tomllib

    from stepcontact.io.modelfile.load import model_from_dict

    res = sc.solve_static(model_from_dict(tomllib.loads(_EM1110_DAM)))
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(12.98291, rel=1e-6)
    lam = np.asarray(res.lam)
    _, per_level = np.unique(np.round(lam, 9), return_counts=True)
    assert per_level.max() <= 12  # (the chatter recorded 101 and 173 states at one λ)
    held = [r for r in res.nonunique if r["why"].startswith("crack water")]
    for r in held:  # each names the CFEs whose water came and went, before the sliding
        assert r["cfes"] and all(c.startswith("base[") for c in r["cfes"])
        assert r["lam"] < res.multipliers[-1].equilibrium_lost
    assert res.residual.max() < 1e-6 and res.violation.max() < 1e-9
