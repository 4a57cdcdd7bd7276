"""Joints with initial strength (article eq. (12), :class:`~stepcontact.model.bond.Bond`): a
bonded CFE carries tension and shear inside its strength surface, breaks exactly on it (an event
located like the others), releases what it can no longer carry at the same load factor, and is a
unilateral Coulomb contact from then on.

References:

* one bonded CFE (a discrete model, springs to the ground): the break load is N_R in tension,
  min(N_R, Q_R/α_R) in the article's form, Q_R + α_R p in shear at a constant compression p,
  exactly; after the break the CFE opens, or slips at Q = f p and follows Coulomb's law
  (sticks on unloading, slips the other way at −f p);
* a crack running along a bonded base: a rigid block on a Winkler layer (C = k A per CFE) with
  the Mohr–Coulomb bond, tensile strength varying along the joint, under its weight and a rising
  reservoir — solved here by hand (dense): for a set of broken CFEs the base forces are linear
  in λ (normal: vertical and moment equilibrium of the springs; shear: the horizontal thrust
  shared by the bonded springs and the slipping CFEs' f p); the next break is the first facet
  reached, and a break's release is the straight path between the two equilibria at that λ, on
  which a neighbour that reaches its facet breaks in turn (a cascade, in its order).  The block
  is 1e6 times stiffer than the layer: tolerance 1e-5 on λ.
"""

from __future__ import annotations

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.enums import Status, Transition
from stepcontact.errors import ModelError

BROKEN = Transition.BROKEN
OPEN, STICK, SLIP_POS, SLIP_NEG, BONDED = (int(s) for s in (
    sc.ContactState.OPEN, sc.ContactState.STICK, sc.ContactState.SLIP_POS,
    sc.ContactState.SLIP_NEG, sc.ContactState.BONDED))


def one_cfe(bond, program, k=1e3, friction=0.3):
    """A point (DOFs ux, uy) on springs k to the ground, bonded to a rigid base by one CFE."""
    return sc.DiscreteModel(
        K=[[k, 0.0], [0.0, k]], normal_rows=[[0, 1]], tangent_rows=[[1, 0]],
        loads={"pull": {"uy": 1.0}, "press": {"uy": -1.0}, "push": {"ux": 1.0}},
        friction=friction, bond=bond, dof_names=("ux", "uy"), program=program)


def _breaks(res):
    return [e for e in res.events if e.transition == BROKEN]


@pytest.mark.parametrize("alpha_t, shear, expect", [(np.inf, 60.0, 100.0), (None, 60.0, 100.0),
                                                    (np.inf, 40.0, 80.0), (None, 40.0, 80.0)])
def test_a_bond_breaks_in_tension_on_its_strength_surface_and_the_cfe_opens(alpha_t, shear,
                                                                            expect):
    """N_R = 100 N, α_R = 0.5, pulled at Q = 0: the bond breaks at N = min(N_R, Q_R/α_R) —
    the tension facet N ≤ N_R (a cut-off, or the article's N + |Q|/α_R ≤ N_R), unless the
    shear facet |Q| ≤ Q_R − α_R N reaches zero first (Q_R = 40 N: at N = 80 N)."""
    bond = sc.Bond(tensile=100.0, shear=shear, alpha=0.5, tension_alpha=alpha_t)
    res = sc.solve_static(one_cfe(bond, [sc.Segment("pull", 150.0)]))
    assert res.status == Status.COMPLETED
    (brk,) = _breaks(res)
    assert brk.lam == pytest.approx(expect, rel=1e-12)
    assert brk.N == pytest.approx(expect, rel=1e-12) and brk.Q == 0.0
    i = len(res.lam) - 1
    assert res.state[i][0] == OPEN and res.N[i][0] == 0.0
    # the spring takes what the bond released: u_y = λ/k
    assert res.displacement(i)[1] == pytest.approx(150.0 / 1e3, rel=1e-12)
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-9
    # before the break the CFE carried the whole pull in tension with no displacement
    j = int(np.flatnonzero(res.lam == expect)[0])
    assert res.state[j][0] == BONDED or res.state[j - 1][0] == BONDED


def test_a_bond_breaks_in_shear_at_constant_compression_then_the_cfe_is_coulomb():
    """Pressed by p = 100 N, pushed sideways: the bond breaks at Q = Q_R + α_R p = 100 N; the
    CFE then slips with Q = f p = 30 N (the spring takes the rest), sticks when the push
    falls, and slips the other way at Q = −f p."""
    bond = sc.Bond(tensile=100.0, shear=50.0, alpha=0.5, tension_alpha=np.inf, friction=0.3)
    prog = [sc.Segment("press", 100.0), sc.Segment("push", 200.0), sc.Segment("push", -200.0)]
    res = sc.solve_static(one_cfe(bond, prog))
    assert res.status == Status.COMPLETED
    (brk,) = _breaks(res)
    assert (brk.segment, brk.lam) == (1, pytest.approx(100.0, rel=1e-12))
    assert brk.Q == pytest.approx(100.0, rel=1e-12) and brk.N == pytest.approx(-100.0)
    after = [e for e in res.events if e.step > brk.step]
    assert [e.transition for e in after] == [Transition.STUCK, Transition.SLIP_NEG]
    # sticks when the push starts to fall (at 200), slips back where Q reaches −f p:
    # ux = (200 − 30)/k held, push − k ux = −30 → push = 170 − 30 = 140
    assert after[0].lam == pytest.approx(200.0, rel=1e-12)
    assert after[1].lam == pytest.approx(140.0, rel=1e-12)
    i = len(res.lam) - 1
    assert res.Q[i][0] == pytest.approx(-30.0, rel=1e-12)
    assert res.displacement(i)[0] == pytest.approx((-200.0 + 30.0) / 1e3, rel=1e-12)
    # equilibrium and the contact conditions through the break
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-9


# ---- a crack running along a bonded base -----------------------------------------------------
GW, KN, RHO, HEIGHT, B, H = 9810.0, 1e8, 2400.0, 12.0, 8.0, 11.0
COHESION, PHI = 2e6, 35.0
TENSILE = (60e3, 20e3)  # Pa at the heel and at the toe (linear between)


def bonded_dam(bond=None, level=H, lam_end=4.0, nx=16, crack=False, tensile=TENSILE, width=B):
    """A stiff block B × 12 m on a compliant layer on a rigid base, its base bonded
    (Mohr–Coulomb), weight then water on its upstream face to level H (per unit λ)."""
    conc = sc.Material(E=1e14, nu=0.2, density=RHO)
    m = sc.Model(bodies=[sc.rectangle("dam", (0, 0), (width, HEIGHT), nx, 24, conc)])
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (width + 1.0, 0.0)])
    bond = bond or sc.Bond.mohr_coulomb(
        COHESION, [(0.0, 0.0, tensile[0]), (width, 0.0, tensile[1])], PHI)
    base = sc.Interface("base", plus=m.select("dam", y=0), minus=ground, friction=0.5,
                        layer=sc.ContactLayer(kn=KN, kt=KN), bond=bond)
    water = [sc.WaterLoad(m.select("dam", x=0.0), level=level)]
    if crack:
        water.append(sc.CrackWater(base, level=level, entry=(0.0, 0.0)))
    return m.add(base, sc.LoadPattern("weight", [sc.BodyForce(bodies=("dam",))]),
                 sc.LoadPattern("water", water), sc.Segment("weight", 1.0),
                 sc.Segment("water", lam_end))


class BondedBlock:
    """The dense hand reference: a rigid block on CFE springs (C = KN A_k at x_k, normal and
    tangential), the Mohr–Coulomb bond per CFE, Coulomb friction tan φ after a break."""

    def __init__(self, res, tensile=TENSILE):
        self.x = res.cfe["x"][:, 0]
        A = res.cfe["area"]
        self.C = KN * A
        self.NR = A * np.interp(self.x, [0.0, B], tensile)
        self.QR = A * COHESION
        self.al = self.f = np.tan(np.radians(PHI))
        self.W = RHO * 9.81 * B * HEIGHT
        self.mode = np.zeros(len(self.x), int)  # 0 bonded, 1 open, 2 slipping (+)

    def loads(self, t):
        F = t * GW * H * H / 2
        return F, F * H / 3

    def forces(self, t, mode=None):
        """(p, Q) at λ = t for the modes (compression p > 0)."""
        mode = self.mode if mode is None else mode
        F, MF = self.loads(t)
        closed = mode != 1
        Cc, xc = self.C[closed], self.x[closed]
        M = -np.array([[Cc.sum(), (Cc * xc).sum()], [(Cc * xc).sum(), (Cc * xc**2).sum()]])
        v, th = np.linalg.solve(M, [self.W, self.W * B / 2 + MF])
        p = np.where(closed, -self.C * (v + th * self.x), 0.0)
        slip = mode == 2
        u = (F - self.f * p[slip].sum()) / self.C[mode == 0].sum()
        Q = np.where(mode == 0, self.C * u, np.where(slip, self.f * p, 0.0))
        return p, Q

    def facets(self, p, Q):
        """(tension, shear) facet values (m, 2) of the Mohr–Coulomb bond (a tension cut-off
        N ≤ N_R, |Q| ≤ Q_R + α p)."""
        return np.column_stack([self.NR + p, self.QR + self.al * p - np.abs(Q)])

    def first_crossing(self, before, after):
        """The earliest fraction s ∈ (0, 1] of the straight path from the forces ``before``
        to ``after`` where a bonded CFE's facet reaches zero (each facet is linear along it
        while Q keeps its sign): (s, CFE), or (inf, None)."""
        fb, fa = self.facets(*before), self.facets(*after)
        crossing = (self.mode == 0)[:, None] & (fa < 0) & (fb > fa)
        s = np.full(fb.shape, np.inf)
        s[crossing] = fb[crossing] / (fb[crossing] - fa[crossing])
        k = int(np.argmin(s.min(axis=1)))
        return (float(s[k].min()), k) if np.isfinite(s[k].min()) else (np.inf, None)

    def run(self, t_end):
        """[(CFE, λ)] of the breaks in order, and λ where equilibrium is lost (or None)."""
        out, t = [], 0.0
        while True:
            # the forces are linear in λ for fixed modes: the next facet reached
            s, k = self.first_crossing(self.forces(t), self.forces(t + t_end))
            if k is None or t + s * t_end > t_end:
                return out, None
            t += s * t_end
            before = self.forces(t)
            while k is not None:  # the break and its release (a cascade at this λ)
                out.append((k, t))
                p, Q = before
                self.mode[k] = 1 if p[k] <= 0 else 2  # open in tension, else slipping
                if np.sum(self.mode != 1) < 2 or not np.any(self.mode == 0):
                    return out, t  # overturning, or nothing bonded holds the thrust: lost
                after = self.forces(t)
                s, k = self.first_crossing(before, after)
                if k is not None:
                    before = tuple(b + s * (a - b) for b, a in zip(before, after, strict=True))


@pytest.mark.parametrize("tensile, cascades", [((60e3, 20e3), 1), ((300e3, 20e3), 7)])
def test_the_crack_runs_along_a_bonded_base_in_the_order_and_at_the_load_factors_of_the_reference(
        tensile, cascades):
    """σ_t falling from the heel to the toe: 60 → 20 kPa (the crack grows with the level),
    300 → 20 kPa (a strong heel: once it breaks, the crack runs through seven weaker CFEs at
    the same λ, in order)."""
    res = sc.solve_static(bonded_dam(tensile=tensile))
    ref, lost = BondedBlock(res, tensile).run(4.0)
    got = [(e.local, e.lam) for e in _breaks(res)]
    assert [k for k, _ in got] == [k for k, _ in ref]
    np.testing.assert_allclose([t for _, t in got], [t for _, t in ref], rtol=1e-5)
    # breaks at the same λ as the one before (a cascade), in the reference's order
    assert int(np.sum(np.diff([t for _, t in got]) == 0)) == cascades
    assert res.status == Status.EQUILIBRIUM_LOST and lost is not None
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(lost, rel=1e-5)
    # the heel breaks in tension at its strength: N = A σ_t(0)
    first = _breaks(res)[0]
    assert first.local == 0 and first.N == pytest.approx(res.cfe["area"][0] * tensile[0],
                                                         rel=1e-9)
    assert res.residual.max() < 1e-6 and res.violation.max() < 1e-9


def test_water_enters_the_crack_of_a_broken_bond_heel_under_9_m_of_water():
    """A narrow bonded block (4 m) under 9 m of water with crack water from the heel: the heel's
    bonds break, the crack opens and fills; the normal stress in the open part is
    −ρ_w g · 9 = −88 290 Pa, the bonded rest carries the block."""
    res = sc.solve_static(bonded_dam(level=9.0, lam_end=1.0, nx=8, crack=True,
                                     tensile=(20e3, 20e3), width=4.0))
    assert res.status == Status.COMPLETED
    i = len(res.lam) - 1
    wet = res.crack_pressure[i] > 0
    assert wet.any() and not wet.all()
    broken = {e.cfe for e in _breaks(res)}
    assert set(np.flatnonzero(wet)) <= broken  # water only where a bond broke
    assert np.all(res.state[i][wet] == OPEN)
    np.testing.assert_allclose(res.crack_pressure[i][wet], 88290.0, rtol=1e-8)
    # (the contact stress is round-off: 1e-8 of the crack pressure, 1e-10 of the base's forces)
    np.testing.assert_allclose(res.sigma_n[i][wet], 0.0, atol=1e-8 * 88290.0)
    assert np.any(res.state[i] == BONDED)
    assert res.residual.max() < 1e-6 and res.violation.max() < 1e-9


def test_model_file_bond_gives_the_same_breaks_as_the_python_model(tmp_path):
    from stepcontact.io.modelfile import load_model
    from test_crack_water import block_toml

    text = block_toml(8.0, 16, 0.5, '[{ type = "water", nodes = "upstream", level = 11.0 }]',
                      4.0, bond="""
[interfaces.bond]
cohesion = 2e6
tensile_strength = { from = [0.0, 0.0, 60e3], to = [8.0, 0.0, 20e3] }
friction_angle = 35.0
""")
    f = tmp_path / "m.toml"
    f.write_text(text)
    res = sc.solve_static(load_model(f))
    ref = sc.solve_static(bonded_dam())
    assert [e.cfe for e in _breaks(res)] == [e.cfe for e in _breaks(ref)]
    np.testing.assert_allclose([e.lam for e in _breaks(res)], [e.lam for e in _breaks(ref)],
                               rtol=1e-12)
    # the article's form, and a bond given both ways, in the file
    f.write_text(text.replace("cohesion = 2e6\ntensile_strength = { from = [0.0, 0.0, 60e3], "
                              "to = [8.0, 0.0, 20e3] }\nfriction_angle = 35.0",
                              "tensile = 60e3\nshear = 2e6\nalpha = 0.7"))
    assert load_model(f).interfaces[0].bond.alpha == 0.7
    f.write_text(text.replace("friction_angle = 35.0", "friction_angle = 35.0\nalpha = 0.7"))
    with pytest.raises(ModelError, match="not both"):
        load_model(f)


def test_bad_bonds_name_the_item():
    with pytest.raises(ModelError, match="bond.alpha"):
        sc.Bond(tensile=1e5, shear=1e5, alpha=0.0)  # the article's tension facets need α_R
    with pytest.raises(ModelError, match="bond.friction_angle"):
        sc.Bond.mohr_coulomb(1e5, 1e5, 95.0)
    with pytest.raises(ModelError, match="bond.tension_alpha"):
        sc.Bond(tensile=1e5, shear=1e5, alpha=0.5, tension_alpha=-1.0)
    with pytest.raises(ModelError, match="interface 'base'.bond.tensile"):
        sc.assemble(bonded_dam(bond=sc.Bond.mohr_coulomb(1e5, [(0, 0, 1e5), (8, 0, -1e5)],
                                                           30.0)))
    with pytest.raises(ModelError, match="interface 'base'.bond"):
        m = bonded_dam()
        sc.Interface("base", plus=m.interfaces[0].plus, minus=m.interfaces[0].minus,
                     bond="strong")
    with pytest.raises(ModelError, match="a bonded CFE must be closed"):
        sc.DiscreteModel(K=[[1e3]], normal_rows=[[1.0]], tangent_rows=[[0.0]], gaps=0.01,
                         bond=sc.Bond(1e2, 1e2, 0.5))
    # (a dynamic interval with intact bonds: tests/test_bonded_dynamic.py)


def test_bond_strengths_are_kept_in_the_result_file_and_drawn_as_the_bonded_limit(tmp_path):
    """The result (and its file) keep the bond's columns; the interface figure draws, where
    the joint is still bonded, its shear strength ±(τ_R − α_R σ_n) instead of ±f|σ_n|."""
    import matplotlib

    matplotlib.use("Agg")
    res = sc.solve_static(bonded_dam(lam_end=2.0))
    path = tmp_path / "r.nc"
    res.save(path)
    back = sc.load_result(path)
    np.testing.assert_array_equal(back.cfe["bond"], res.cfe["bond"])
    i = len(res.lam) - 1
    toe = int(np.argmax(res.cfe["x"][:, 0]))
    assert res.state[i][toe] == BONDED and res.state[i][0] != BONDED
    fig = sc.plot_interfaces(back, lams=[float(res.lam[i])], segment=int(res.segment[i]))
    ax_t = fig.axes[1]
    upper = np.asarray([ln for ln in ax_t.get_lines() if ln.get_linestyle() == "--"][0]
                       .get_ydata(), float)  # in the order of s along the joint
    order = np.argsort(res.cfe["s"])
    A = res.cfe["area"]
    sigma = res.N[i] / A  # Pa, compression < 0
    bonded_lim = COHESION - np.tan(np.radians(PHI)) * sigma
    coulomb_lim = res.cfe["friction"] * np.abs(sigma)  # (tan φ after the break)
    expect = np.where(res.state[i] == BONDED, bonded_lim, coulomb_lim)[order]
    scale = expect[-1] / upper[-1]
    assert any(np.isclose(scale, u, rtol=1e-9) for u in (1.0, 1e3, 1e6))  # Pa, kPa or MPa
    np.testing.assert_allclose(upper * scale, expect, rtol=1e-9, atol=1e-9 * expect.max())


# ---- residual cohesion after the break -------------------------------------------------------
def test_after_the_break_the_cfe_slips_at_f_p_plus_its_residual_cohesion_both_ways():
    """Pressed by p = 100 N, the bond (Q_R + α_R p = 100 N) breaks into a Coulomb CFE with
    f = 0.3 and residual cohesion C_r A = 80 N (A = 1): it still sticks (|Q| = 100 < f p + C =
    110), slips where the push reaches Q = 110 N (the CFE is rigid: push = Q), sticks when the
    push falls at 150 (u_x = 40/k), and slips back at Q = −110 N: push − k u_x = −110 → −70."""
    bond = sc.Bond(tensile=100.0, shear=50.0, alpha=0.5, tension_alpha=np.inf, friction=0.3,
                   residual_cohesion=80.0)
    prog = [sc.Segment("press", 100.0), sc.Segment("push", 150.0), sc.Segment("push", -100.0)]
    res = sc.solve_static(one_cfe(bond, prog))
    assert res.status == Status.COMPLETED
    assert [e.transition for e in res.events] == [BROKEN, Transition.SLIP_POS,
                                                  Transition.STUCK, Transition.SLIP_NEG]
    brk, slip, stuck, back = res.events
    assert brk.lam == pytest.approx(100.0, rel=1e-12)
    assert slip.segment == 1 and abs(slip.lam - 110.0) <= 1e-12 * 110.0
    assert abs(slip.Q - 110.0) <= 1e-12 * 110.0
    assert stuck.lam == pytest.approx(150.0, rel=1e-12)
    assert back.segment == 2 and abs(back.lam + 70.0) <= 1e-12 * 110.0
    assert abs(back.Q + 110.0) <= 1e-12 * 110.0
    i = len(res.lam) - 1
    assert res.state[i][0] == SLIP_NEG and abs(res.Q[i][0] + 110.0) <= 1e-12 * 110.0
    assert res.displacement(i)[0] == pytest.approx((-100.0 + 110.0) / 1e3, rel=1e-12)
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-12
    assert res.cfe["bond"][0, 4] == 80.0 and res.cfe["cohesion_lost"][0] == -1
    # with C_r A = 20 N the break lands beyond the residual limit: the CFE slips at once,
    # with Q = f p + C = 50 N (the rest released to the spring), and back at −50 N
    res = sc.solve_static(one_cfe(sc.Bond(100.0, 50.0, 0.5, np.inf, 0.3, 20.0), [
        sc.Segment("press", 100.0), sc.Segment("push", 200.0), sc.Segment("push", -200.0)]))
    assert [e.transition for e in res.events] == [BROKEN, Transition.STUCK, Transition.SLIP_NEG]
    j = int(np.flatnonzero(res.kind == "event")[0])
    assert res.state[j][0] == SLIP_POS and abs(res.Q[j][0] - 50.0) <= 1e-12 * 50.0
    assert res.displacement(j)[0] == pytest.approx(50.0 / 1e3, rel=1e-12)
    # ux held at (200 − 50)/k, push − k ux = −50 → push = 100
    assert res.events[2].lam == pytest.approx(100.0, rel=1e-12)
    assert res.Q[-1][0] == pytest.approx(-50.0, rel=1e-12)


def test_a_cfe_pulled_open_loses_its_residual_cohesion_and_releases_its_shear():
    """After the break and a slip (Q = f p + C = 110 N) the push falls to 100 (Q = 60 N, stuck),
    then the CFE is pulled: at p = 0 it opens with Q = 60 N, which is released at the same
    load factor to the spring (u_x = 100/k); it stays open (u_y = 50/k at the pull of 50).
    Pressed again it closes without cohesion: it slips at Q = f p = 30 N, at push 130."""
    bond = sc.Bond(tensile=100.0, shear=50.0, alpha=0.5, tension_alpha=np.inf, friction=0.3,
                   residual_cohesion=80.0)
    prog = [sc.Segment("press", 100.0), sc.Segment("push", 150.0), sc.Segment("push", 100.0),
            sc.Segment("press", -50.0)]
    res = sc.solve_static(one_cfe(bond, prog))
    assert res.status == Status.COMPLETED
    opened = res.events[-1]
    assert opened.transition == Transition.OPENED and opened.segment == 3
    assert abs(opened.lam) <= 1e-12 * 100.0 and opened.Q == pytest.approx(60.0, rel=1e-12)
    i = opened.state
    assert res.cfe["cohesion_lost"][0] == i
    assert res.state[i][0] == OPEN and res.Q[i][0] == 0.0 and res.N[i][0] == 0.0
    np.testing.assert_allclose(res.displacement(i), [100.0 / 1e3, 0.0], rtol=0, atol=1e-15)
    end = len(res.lam) - 1
    assert res.state[end][0] == OPEN
    np.testing.assert_allclose(res.displacement(end), [0.1, 0.05], rtol=1e-12)
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-12
    # closed again: purely frictional
    res = sc.solve_static(one_cfe(bond, [*prog, sc.Segment("press", 100.0),
                                         sc.Segment("push", 200.0)]))
    slip = res.events[-1]
    assert slip.transition == Transition.SLIP_POS and slip.segment == 5
    assert slip.lam == pytest.approx(130.0, rel=1e-12) and slip.Q == pytest.approx(30.0)
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-12


def sliding_block(bond, width=20.0):
    """A block ``width`` × 12 m (E = 30 GPa) on a compliant bonded layer, weight then water
    to 11 m per unit λ (no opening: the resultant stays in the middle third)."""
    conc = sc.Material(E=3e10, nu=0.2, density=RHO)
    m = sc.Model(bodies=[sc.rectangle("dam", (0, 0), (width, HEIGHT), 10, 12, conc)])
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (width + 1.0, 0.0)])
    base = sc.Interface("base", plus=m.select("dam", y=0), minus=ground, friction=0.5,
                        layer=sc.ContactLayer(kn=KN, kt=KN), bond=bond)
    return m.add(base, sc.LoadPattern("weight", [sc.BodyForce(bodies=("dam",))]),
                 sc.LoadPattern("water", [sc.WaterLoad(m.select("dam", x=0.0), level=H)]),
                 sc.Segment("weight", 1.0), sc.Segment("water", 10.0))
@pytest.mark.filterwarnings(  # σ_t beyond c·cot φ on purpose: the cut-off plays no part
    "ignore::stepcontact.model.plausible.PlausibilityWarning")
def test_a_block_with_residual_cohesion_slides_at_f_w_plus_c_r_times_its_length():
    """The bond (c = 20 kPa, φ = 30°) is weaker than the residual strength (f = 0.6, C_r from
    40 kPa at the heel to 20 kPa at the toe): every CFE breaks into a stuck one, then slips,
    and the block slides when the thrust γ_w H²/2 · λ reaches f W + ∫C_r dx = 0.6 W + 30 kPa ·
    20 m (hand statics: Σp = W with the base closed throughout)."""
    width = 20.0
    bond = sc.Bond.mohr_coulomb(20e3, 50e3, 30.0, residual_friction=0.6,
                                residual_cohesion=[(0.0, 0.0, 40e3), (width, 0.0, 20e3)])
    res = sc.solve_static(sliding_block(bond, width))
    W = RHO * 9.81 * width * HEIGHT
    lam = (0.6 * W + 30e3 * width) / (GW * H * H / 2)
    assert res.status == Status.EQUILIBRIUM_LOST and "sliding" in res.message
    assert abs(res.multipliers[-1].equilibrium_lost - lam) <= 1e-9 * lam
    assert len(_breaks(res)) == res.m and np.all(res.cfe["cohesion_lost"] == -1)
    np.testing.assert_allclose(res.cfe["bond"][:, 4].sum(), 30e3 * width, rtol=1e-12)
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-9
    # without residual cohesion (and f = 0.7 so that the residual strength is still the
    # larger): at f W
    res0 = sc.solve_static(sliding_block(sc.Bond.mohr_coulomb(20e3, 50e3, 30.0, 0.7), width))
    lam0 = 0.7 * W / (GW * H * H / 2)
    assert abs(res0.multipliers[-1].equilibrium_lost - lam0) <= 1e-9 * lam0
    assert "cohesion_lost" not in res0.cfe and res0.cfe["bond"][:, 4].max() == 0.0
    # the interface figure draws the broken CFEs' limit ±(f|σ_n| + C_r) (the last state
    # before sliding: every CFE broken, closed, its cohesion kept)
    import matplotlib

    matplotlib.use("Agg")
    i = len(res.lam) - 2
    assert not np.any(res.state[i] == BONDED) and not np.any(res.state[i] == OPEN)
    fig = sc.plot_interfaces(res, states=[i])
    upper = np.asarray([ln for ln in fig.axes[1].get_lines() if ln.get_linestyle() == "--"][0]
                       .get_ydata(), float)
    order = np.argsort(res.cfe["s"])
    A = res.cfe["area"]
    expect = (0.6 * np.abs(res.N[i]) / A + res.cfe["bond"][:, 4] / A)[order]
    scale = expect[-1] / upper[-1]
    assert any(np.isclose(scale, u, rtol=1e-9) for u in (1.0, 1e3, 1e6))  # Pa, kPa or MPa
    np.testing.assert_allclose(upper * scale, expect, rtol=1e-9)
@pytest.mark.filterwarnings(  # σ_t beyond c·cot φ on purpose: the cut-off plays no part
    "ignore::stepcontact.model.plausible.PlausibilityWarning")
def test_model_file_residual_cohesion_gives_the_same_run_as_the_python_model(tmp_path):
    """Heel CFEs break in shear, keep a residual cohesion, and lose it when the crack opens
    them: the same events (and the same states where the cohesion was lost) from the file."""
    from stepcontact.io.modelfile import load_model
    from test_crack_water import block_toml

    text = block_toml(8.0, 16, 0.5, '[{ type = "water", nodes = "upstream", level = 11.0 }]',
                      4.0, bond="""
[interfaces.bond]
cohesion = 150e3
tensile_strength = 300e3
friction_angle = 35.0
friction = 0.5
residual_cohesion = { from = [0.0, 0.0, 80e3], to = [8.0, 0.0, 40e3] }
""")
    f = tmp_path / "m.toml"
    f.write_text(text)
    res = sc.solve_static(load_model(f))
    ref = sc.solve_static(bonded_dam(bond=sc.Bond.mohr_coulomb(
        150e3, 300e3, 35.0, 0.5, [(0.0, 0.0, 80e3), (8.0, 0.0, 40e3)])))
    assert [(e.cfe, e.transition) for e in res.events] == [(e.cfe, e.transition)
                                                           for e in ref.events]
    np.testing.assert_allclose([e.lam for e in res.events], [e.lam for e in ref.events],
                               rtol=1e-12)
    np.testing.assert_array_equal(res.cfe["cohesion_lost"], ref.cfe["cohesion_lost"])
    lost = ref.cfe["cohesion_lost"] >= 0
    assert lost.any() and not lost.all()
    # a CFE lost its cohesion where its bond broke open (in tension) or where it opened later
    # with shear (its event at the state after the release); from then on |Q| ≤ f p (the
    # release may close it again at the same λ, and the rising water open it once more)
    scale = np.abs(ref.Q).max()
    opened = 0
    for k in np.flatnonzero(lost):
        i = ref.cfe["cohesion_lost"][k]
        ev = next(e for e in ref.events if e.cfe == k and e.state == i)
        assert ev.transition in (BROKEN, Transition.OPENED)
        if ev.transition == Transition.OPENED:
            assert abs(ev.N) <= 1e-9 * scale and ev.Q > 0.2 * ref.cfe["bond"][k, 4]
            opened += 1
        after = np.arange(len(ref.lam)) >= i
        assert np.all(np.abs(ref.Q[after, k]) <= 0.5 * -ref.N[after, k] + 1e-9 * scale)
    assert opened >= 3
    assert ref.residual.max() < 1e-6 and ref.violation.max() < 1e-9
    # the result file keeps the residual cohesion and where it was lost
    path = tmp_path / "r.nc"
    ref.save(path)
    back = sc.load_result(path)
    np.testing.assert_array_equal(back.cfe["cohesion_lost"], ref.cfe["cohesion_lost"])
    np.testing.assert_array_equal(back.cfe["bond"], ref.cfe["bond"])


def test_a_negative_residual_cohesion_names_the_field(tmp_path):
    with pytest.raises(ModelError, match="bond.residual_cohesion"):
        sc.Bond(1e5, 1e5, 0.5, residual_cohesion=-1.0)
    with pytest.raises(ModelError, match="bond.residual_cohesion"):
        sc.Bond.mohr_coulomb(1e5, 1e5, 30.0, residual_cohesion=-1e3)
    with pytest.raises(ModelError, match="interface 'base'.bond.residual_cohesion"):
        sc.assemble(bonded_dam(bond=sc.Bond.mohr_coulomb(
            1e5, 1e5, 30.0, residual_cohesion=[(0, 0, 1e5), (8, 0, -1e5)])))
    from stepcontact.io.modelfile import load_model
    from test_crack_water import block_toml

    f = tmp_path / "m.toml"
    f.write_text(block_toml(8.0, 4, 0.5, "[]", 1.0, bond="""
[interfaces.bond]
cohesion = 150e3
tensile_strength = 300e3
friction_angle = 35.0
residual_cohesion = -5e3
"""))
    with pytest.raises(ModelError, match="residual_cohesion"):
        load_model(f)
@pytest.mark.filterwarnings(  # σ_t beyond c·cot φ on purpose: the cut-off plays no part
    "ignore::stepcontact.model.plausible.PlausibilityWarning")
def test_a_lost_residual_cohesion_stays_lost_across_construction_stages():
    """The run of the model-file test split into two stages at λ = 2.3 of the water (the law
    is rebuilt at the stage boundary): the same events, and each CFE's cohesion lost at the
    same load factor as in one stage (not again at the start of the second)."""
    import dataclasses

    bond = sc.Bond.mohr_coulomb(150e3, 300e3, 35.0, 0.5, [(0.0, 0.0, 80e3), (8.0, 0.0, 40e3)])
    m = bonded_dam(bond=bond)
    ref = sc.solve_static(m)
    res = sc.solve_static(dataclasses.replace(m, program=()).add(
        sc.Stage("one", [sc.Segment("weight", 1.0), sc.Segment("water", 2.3)]),
        sc.Stage("two", [sc.Segment("water", 4.0)])))
    assert [(e.cfe, e.transition) for e in res.events] == [(e.cfe, e.transition)
                                                           for e in ref.events]
    np.testing.assert_allclose([e.lam for e in res.events], [e.lam for e in ref.events],
                               rtol=1e-9)
    lost, lost_ref = res.cfe["cohesion_lost"], ref.cfe["cohesion_lost"]
    np.testing.assert_array_equal(lost >= 0, lost_ref >= 0)
    assert np.sum(ref.lam[lost_ref[lost_ref >= 0]] < 2.3) >= 3  # lost in the first stage
    np.testing.assert_allclose(res.lam[lost[lost >= 0]], ref.lam[lost_ref[lost_ref >= 0]],
                               rtol=1e-9)
