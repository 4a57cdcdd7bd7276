"""A rigid gravity dam on a compliant base, the reservoir rising: the heel-opening level, the
crack length against the level and the level at which the dam slides or overturns, against
hand limit equilibrium with the uplift in the crack (issue 29 §4, third check).

The model: a triangular dam (heel (0, 0), toe (B, 0), crest (0, H), vertical upstream face),
stiff (E = 1e14 Pa) on a stiff slab, joined by a compliant contact layer (k_n = k_t = 1e8
Pa/m, article eq. (11)): the dam is a rigid body on Winkler springs, and the effective base
pressure is linear where the joint is closed — the guidelines' assumption made exact.  The
reservoir's level h is the load factor: the face pressure γ_w (h − y), the uplift (linear from
γ_w h at the heel to 0 at the toe, or drained: γ_w h/3 at the drain line), applied through the
CFEs, and crack water entering at the heel (``rule="connected"``: full reservoir pressure in
the crack, the given uplift beyond; ``rule="em1110"``: beyond the tip, linear from the tip's
γ_w h to the toe's 0, through the drains' head while the crack has not reached them).

**The hand solution** (derived here, independent of the solver).  Per metre; the base CFEs at
x_k = 0, Δ, …, B (linear elements: tributary lengths A_k = Δ, Δ/2 at the ends).  For a level
h and the first n CFEs open (the crack, wet), the water pressure on CFE k is p_k = γ_w h in the
crack and the rule's uplift beyond; the closed CFEs carry N_k = k_n A_k (a + b x_k) (the rigid
dam's settlement, linear).  Vertical and moment (about the heel) equilibrium of the dam:

    Σ_closed k_n A_k (a + b x_k)     = W − Σ A_k p_k                       (N')
    Σ_closed k_n A_k (a + b x_k) x_k = W B/3 + γ_w h³/6 − Σ A_k p_k x_k    (M')

with W = ρ g B H/2 at B/3 and the thrust γ_w h²/2 at h/3 (h ≤ H; above the crest the
trapezoid γ_w (h − y), 0 ≤ y ≤ H) — moments of the resultants: the dam is rigid.  CFE n
opens at the first level h_n where a + b x_n = 0 (a root in h, brentq); a CFE whose level is
already passed opens at once (the crack runs at one level: a cascade).  The dam slides when
the thrust reaches f N' (every closed CFE slipping) with the crack of that level, and
overturns when no closed set is left.  The continuous form (Δ → 0, the guidelines' cracked-base
iteration): the effective pressure is a triangle from the tip c to the toe, so its resultant
x_R = M'/N' lies at c + 2(B − c)/3: c = 3 x_R − 2B, solved with the uplift of that crack.

Tolerances: the discrete hand solution is the model's exact answer but for the dam's own
flexibility (E = 1e14 Pa against k_n = 1e8 Pa/m over B = 32 m: relative ~1e-6), so the
opening and sliding levels agree to 1e-5 relative (measured: ≤ 3e-6).  Against the
continuous form the discrete model's crack, when CFE n opens, ends between x_n − Δ/2 (its
wet tributary lengths) and x_n; the trapezoidal springs (Δ = B/16) make the levels differ by
O(Δ/B): 1.5 % relative (measured: 0.03 % at the heel, up to 1.4 % as the crack grows); with
drains, 4 % (the pressure steps at the tip from γ_w h to the drained profile, and the discrete
model places that step within Δ/2; measured up to 1.9 %).  Where the crack runs on at one
level (a cascade), the continuous path is unstable there too: only h(c) ≤ that level is
checked.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

import stepcontact as sc
from stepcontact.enums import Transition

H, B, DX = 40.0, 32.0, 2.0  # m: height, base, CFE spacing
RHO, G, GAMMA_W = 2400.0, 9.81, 9810.0  # kg/m³, m/s², N/m³
KN = 1e8  # Pa/m, the layer's stiffness (normal and tangential)
W = RHO * G * B * H / 2  # N/m, at B/3 from the heel
X = np.arange(0.0, B + DX / 2, DX)  # the base CFEs, m from the heel
A = np.full(X.shape, DX)
A[[0, -1]] = DX / 2  # tributary lengths, m (per metre: m²)
DRAIN = 4.0  # m from the heel, head h/3 (E = 2/3 against the tailwater, none here)
REL = 1e-5  # relative tolerance on levels (the dam's flexibility, see the module docstring)
CONT = 0.015  # against the continuous form (Δ = B/16; see the module docstring)
CONT_DRAINS = 0.04  # the same with drains (the step at the tip; see the module docstring)


def dam(f: float, rule: str = "connected", drain: float | None = None, bridge: float = 0.0,
        top: float = 60.0, entry: tuple = (0.0, 0.0)) -> sc.Model:
    """The rigid dam on its compliant layer, friction ``f``, then the reservoir to ``top``."""
    stiff = sc.Material(E=1e14, nu=0.2, density=RHO)
    body = sc.polygon_region("dam", [(0.0, 0.0), (B, 0.0), (0.0, H)], stiff, "quad4",
                             n=int(B / DX))
    slab = sc.rectangle("rock", (-2 * DX, -DX), (B + 2 * DX, 0.0), int(B / DX) + 4, 1,
                        sc.Material(E=1e14, nu=0.2, density=2650.0))
    m = sc.Model(bodies=[slab, body])
    base = sc.Interface("base", plus=m.select("dam", y=0.0), minus=m.select("rock", y=0.0),
                        friction=f, layer=sc.ContactLayer(kn=KN, kt=KN))
    if drain is None:
        up = sc.Uplift(base, head=[(0.0, 0.0, 1.0), (B, 0.0, 0.0)], through="cfes")
    else:
        up = sc.Uplift.drained(base, heel=(0.0, 0.0), toe=(B, 0.0), drain=(drain, 0.0),
                               efficiency=2 / 3, reference="tailwater", through="cfes")
    loads = [sc.WaterLoad(m.select("dam", x=0.0), level=None), up,
             sc.CrackWater(base, level=None, entry=entry, rule=rule, bridge=bridge)]
    return m.add(sc.Support("slab", m.select("rock", y=-DX)), base,
                 sc.LoadPattern("weight", [sc.BodyForce(bodies=("dam",))]),
                 sc.LoadPattern("reservoir", loads),
                 sc.Segment("weight", 1.0), sc.Segment("reservoir", top))


# ---- the hand solution ---------------------------------------------------------------------
def uplift(h: float, x: np.ndarray, drain: float | None) -> np.ndarray:
    """The given uplift, Pa: linear γ_w h → 0, or through γ_w h/3 at the drain line."""
    if drain is None:
        return GAMMA_W * h * (1 - x / B)
    return GAMMA_W * h * np.interp(x, [0.0, drain, B], [1.0, 1 / 3, 0.0])


def water(h: float, n: int, rule: str, drain: float | None, x=X) -> np.ndarray:
    """p_k, Pa, with the first n CFEs (x ≤ x_{n−1}) cracked and wet."""
    p = uplift(h, x, drain)
    if n == 0:
        return p
    tip = X[n - 1]
    crack = x <= tip + 1e-9
    p = np.where(crack, GAMMA_W * h, p)
    if rule == "em1110":
        beyond = ~crack
        if drain is not None and tip < drain:  # tip → h_toe + (1 − E)(h_tip − h_toe) → toe
            prof = np.interp(x, [tip, drain, B], [GAMMA_W * h, GAMMA_W * h / 3, 0.0])
        else:  # the drains are ineffective once the crack reaches them
            prof = np.interp(x, [tip, B], [GAMMA_W * h, 0.0])
        p = np.where(beyond, prof, p)
    return p


def thrust(h: float) -> tuple[float, float]:
    """The face's thrust (N/m) and its moment about the heel (N·m/m): γ_w (h − y) on the
    wetted height d = min(h, H) of the vertical face (above the crest, h > H, a trapezoid)."""
    d = min(h, H)
    return GAMMA_W * d * (h - d / 2), GAMMA_W * d * d * (h / 2 - d / 3)


def settlement(h: float, n: int, rule: str, drain: float | None) -> tuple[float, float, float]:
    """(a, b, N') of the closed CFEs k ≥ n at level h: N_k = k_n A_k (a + b x_k)."""
    p = water(h, n, rule, drain)
    Np = W - (A * p).sum()
    Mp = W * B / 3 + thrust(h)[1] - (A * p * X).sum()
    k, x = KN * A[n:], X[n:]
    a, b = np.linalg.solve([[k.sum(), (k * x).sum()], [(k * x).sum(), (k * x * x).sum()]],
                           [Np, Mp])
    return a, b, Np


def _first_root(fun, lo: float, hi: float = 60.0) -> float:
    """The first level h ≥ lo where fun(h) ≥ 0 (fun rising through 0; inf if none by hi)."""
    if fun(lo) >= 0:
        return lo
    hs = np.linspace(lo, hi, 241)
    up = np.flatnonzero(np.array([fun(h) for h in hs]) >= 0)
    if not len(up):
        return np.inf
    return brentq(fun, hs[up[0] - 1], hs[up[0]], xtol=1e-12)


def path(f: float, rule: str, drain: float | None) -> tuple[list[float], float, str]:
    """The hand's path as the level rises: the levels at which CFEs 0, 1, … open (a CFE whose
    level is already passed opens at once: a cascade), the level where equilibrium is lost and
    how — ``"sliding"`` (the thrust reaches f N', every closed CFE slipping) or
    ``"overturning"`` (no closed set is left that carries the moment)."""
    levels, h = [], 1.0
    for n in range(len(X) - 1):
        def tension(h, n=n):  # > 0: CFE n would pull (it opens)
            a, b, _ = settlement(h, n, rule, drain)
            return -(a + b * X[n])

        def excess(h, n=n):  # ≥ 0: the joint cannot hold the thrust
            return thrust(h)[0] - f * settlement(h, n, rule, drain)[2]

        h_open, h_slide = _first_root(tension, h), _first_root(excess, h)
        if h_slide <= h_open:
            return levels, h_slide, "sliding"
        h = h_open
        levels.append(h)
    return levels, h, "overturning"


def continuous_level(c: float, rule: str, drain: float | None) -> float:
    """The guidelines' form (Δ → 0): the level h (m) at which the crack is c long — the
    effective pressure a triangle from the tip c to the toe, its resultant x_R = M'/N' at
    c + 2(B − c)/3, i.e. 3 x_R − 2B = c, with the water of that crack (c = 0: the heel opens,
    the resultant at the downstream third point)."""
    x = np.linspace(0.0, B, 6401)

    def resid(h):
        p = np.where(x <= c, GAMMA_W * h, uplift(h, x, drain))
        if rule == "em1110" and c > 0:
            if drain is None or c >= drain:  # the drains ineffective once reached
                beyond = np.interp(x, [c, B], [GAMMA_W * h, 0.0])
            else:
                beyond = np.interp(x, [c, drain, B], [GAMMA_W * h, GAMMA_W * h / 3, 0.0])
            p = np.where(x <= c, p, beyond)
        Np = W - np.trapezoid(p, x)
        Mp = W * B / 3 + thrust(h)[1] - np.trapezoid(p * x, x)
        return 3 * Mp / Np - 2 * B - c

    return _first_root(resid, 20.0)


# ---- the model's answers ---------------------------------------------------------------------
def openings(res) -> list[tuple[float, float]]:
    """(level, x) of the CFEs that opened while the reservoir rose, first opening of each."""
    seen, out = set(), []
    for e in res.events:
        if e.segment == 1 and e.transition == Transition.OPENED and e.cfe not in seen:
            seen.add(e.cfe)
            out.append((e.lam, e.x))
    return out


@pytest.mark.parametrize(("rule", "f", "drain"), [
    ("connected", 1.0, None), ("connected", 1.5, None), ("em1110", 1.0, None),
    ("em1110", 1.5, None), ("connected", 1.5, DRAIN), ("em1110", 1.5, DRAIN)])
def test_rigid_dam_opening_crack_and_failure(rule, f, drain):
    """Heel opening, the crack front against the level and the level at which the dam is lost
    (sliding, with water in the crack) against the hand's path, to 1e-5 relative; the level
    at which the crack reaches each CFE against the continuous guideline form to 1.5 % (4 %
    with drains)."""
    res = sc.solve_static(dam(f, rule, drain))
    x_b = res.cfe["x"][:, 0]
    np.testing.assert_allclose(np.sort(x_b), X, atol=1e-9)  # the hand's CFEs are the model's
    levels, h_fail, mode = path(f, rule, drain)
    got = openings(res)
    n = len(levels)
    assert n >= 2 and len(got) >= n  # (the FE also lists the CFEs of the failure's cascade)
    np.testing.assert_allclose([x for _, x in got], X[:len(got)], atol=1e-9)  # from the heel
    np.testing.assert_allclose([lam for lam, _ in got[:n]], levels, rtol=REL)
    # the solver names the mechanism by its centre of rotation (a cascade that ends in sliding
    # may read "rotation"): the level is what is compared, not the name
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    np.testing.assert_allclose(res.multipliers[-1].equilibrium_lost, h_fail, rtol=REL)
    # the crack length against the level: the continuous form's levels for the crack reaching
    # each CFE's tributary (x_n − Δ/2) and the CFE (x_n) bracket the discrete level where the
    # crack stops at each CFE; where it runs on at one level (a cascade), the continuous crack
    # is at least as long at that level
    lv = np.array(levels)
    own = np.r_[True, lv[1:] > lv[:-1]]  # the crack stopped at CFE n−1 before CFE n opened
    tol = CONT if drain is None else CONT_DRAINS
    for k in range(n):
        x = X[k]
        # (just short of x_n: the crack reaches CFE n — and, at the drain line, loses the
        # drains — only once CFE n is open)
        lo, hi = (continuous_level(c, rule, drain) for c in (max(x - DX / 2, 0.0),
                                                            max(x - 1e-9 * B, 0.0)))
        if own[k]:
            assert abs(lv[k] / lo - 1) <= tol and abs(lv[k] / hi - 1) <= tol, (k, lv[k], lo, hi)
        else:
            assert min(lo, hi) <= lv[k] * (1 + tol), (k, lv[k], lo, hi)


# ---- the elastic dam: the crack's connection to the reservoir, and why drains do not delay the
# heel's opening (issue 29 §2) ------------------------------------------------------------------
H40, B40 = 40.0, 32.0  # m: the 40 m dam (triangular, vertical upstream face)


def elastic_dam(*, bridge: float = 0.0, bond: bool = True, uplift: bool = True,
                crack: bool = True, top: float = 60.0) -> sc.Model:
    """The issue's 40 m dam (B = 32 m), concrete (25 GPa) on rock (15 GPa), 2 m cells
    (quad8: a CFE every metre), rigid contact; the base bonded (c = 300 kPa, σ_t = 0,
    φ = 45°); uplift linear from the full head at the heel to 0 at the toe, crack water from
    the heel (``bridge``: :class:`CrackWater`); the reservoir raised to ``top``."""
    concrete = sc.Material(E=25e9, nu=0.2, density=RHO)
    rock = sc.Material(E=15e9, nu=0.25, density=2650.0)
    body = sc.polygon_region("dam", [(0.0, 0.0), (B40, 0.0), (0.0, H40)], concrete, "quad8",
                             n=16)
    ground = sc.rectangle("rock", (-B40, -B40), (2 * B40, 0.0), 48, 8, rock)
    m = sc.Model(bodies=[ground, body])
    base = sc.Interface("base", plus=m.select("dam", y=0.0), minus=m.select("rock", y=0.0),
                        friction=1.0,
                        bond=sc.Bond.mohr_coulomb(300e3, 0.0, 45.0) if bond else None)
    loads = [sc.WaterLoad(m.select("dam", x=0.0), level=None)]
    if uplift:
        loads.append(sc.Uplift(base, head=[(0.0, 0.0, 1.0), (B40, 0.0, 0.0)], through="cfes"))
    if crack:
        loads.append(sc.CrackWater(base, level=None, entry=(0.0, 0.0), bridge=bridge))
    return m.add(sc.Support("deep rock", m.select("rock", y=-B40)), base,
                 sc.LoadPattern("weight", [sc.BodyForce(bodies=("dam",))]),
                 sc.LoadPattern("reservoir", loads),
                 sc.Segment("weight", 1.0), sc.Segment("reservoir", top))


def rule_wet(states: np.ndarray, x: np.ndarray, bridge: float) -> np.ndarray:
    """The connection rule written out (independent of fem.crack): walking from the heel
    along the joint, the water passes open CFEs and, within ``bridge`` of the heel, closed
    CFEs whose bond has broken; the run it reaches is wet if it holds an open CFE."""
    order = np.argsort(x)
    wet = np.zeros(len(x), bool)
    run = []
    for k in order:
        is_open = states[k] == int(sc.ContactState.OPEN)
        passes = (bridge > 0 and states[k] != int(sc.ContactState.BONDED)
                  and x[k] <= bridge + 1e-9)
        if not (is_open or passes):
            break
        run.append(k)
    if any(states[k] == int(sc.ContactState.OPEN) for k in run):
        wet[run] = True
    return wet


def most_openings_at_one_level(res) -> int:
    """The largest number of CFEs that open at one level while the reservoir rises."""
    lv = [round(e.lam, 9) for e in res.events
          if e.segment == 1 and e.transition == Transition.OPENED]
    return max(np.unique(lv, return_counts=True)[1], default=0)


def test_crack_water_passes_the_closed_heel():
    """The issue's 40 m dam: the heel CFE closes again (the singular corner) while the CFEs
    behind it open.  With the strict rule (bridge = 0) water stays out until the heel opens,
    then the crack fills in a cascade of openings at one level (the issue saw ~30 events);
    with a bridge of 2 m (two CFEs) it enters as soon as the crack behind the heel opens, at
    a lower level, and the crack grows level by level.  At the last state of every level (the
    water's jumps at that level done; within a cascade a CFE that just closed still holds its
    water until the next jump) the wet CFEs are those of the rule written out in the test
    (:func:`rule_wet`), exactly."""
    first_wet = {}
    for bridge in (0.0, 2.0):
        res = sc.solve_static(elastic_dam(bridge=bridge))
        x = res.cfe["x"][:, 0]
        seg = np.flatnonzero(res.segment == 1)
        settled = seg[np.r_[res.lam[seg][1:] != res.lam[seg][:-1], True]]
        for i in settled:  # the last state at each level (the water's jumps there done)
            wet = res.crack_pressure[i] > 0
            np.testing.assert_array_equal(wet, rule_wet(res.state[i], x, bridge),
                                          err_msg=f"bridge {bridge} m, state {i}")
        # the first level where water is in the crack beyond the heel CFE
        deep = [i for i in np.flatnonzero(res.segment == 1)
                if (res.crack_pressure[i][x > 0.5] > 0).any()]
        first_wet[bridge] = res.lam[deep[0]]
        if bridge == 0.0:
            assert most_openings_at_one_level(res) >= 6  # the cascade at water entry
        else:
            assert most_openings_at_one_level(res) <= 3
    assert first_wet[2.0] < first_wet[0.0] - 1.0  # water in the crack a metre of level earlier


def test_uplift_on_a_closed_rigid_joint_only_relieves_the_contact():
    """Why drains do not delay the heel's opening in an elastic dam on elastic rock: on a
    closed joint with rigid contact the uplift pushes both faces apart by equal forces that
    the contact carries across, so nothing deforms — each CFE's compression drops by exactly
    A_k p_k (the effective stress), σ' = σ₀ − p.  A CFE opens where σ₀ reaches p; at the heel
    p = γ_w h with or without drains.  Checked at h = 30 m (closed) against the same dam
    without uplift: displacements equal to 1e-9 of their size, N_k + A_k p_k equal to 1e-9 of
    the largest N."""
    runs = [sc.solve_static(elastic_dam(bond=False, uplift=u, crack=False, top=30.0))
            for u in (True, False)]
    with_u, without = runs
    i, j = len(with_u.lam) - 1, len(without.lam) - 1
    assert with_u.lam[i] == without.lam[j] == 30.0
    assert not (with_u.state[i] == int(sc.ContactState.OPEN)).any()
    u1, u0 = with_u.displacement(i), without.displacement(j)
    np.testing.assert_allclose(u1, u0, atol=1e-9 * np.abs(u0).max())
    x, area = with_u.cfe["x"][:, 0], with_u.cfe["area"]
    p = GAMMA_W * 30.0 * (1 - x / B40)
    N0 = np.abs(without.N[j]).max()
    np.testing.assert_allclose(-with_u.N[i] + area * p, -without.N[j], atol=1e-9 * N0)


# ---- the drained uplift and the rule's inputs ----------------------------------------------
@pytest.mark.parametrize(("reference", "h_d"), [
    # h_down + (1 − E)(h_up − h_down)·r: r = (L − X)/L on the line, 1 from the tailwater
    ("line", 2.0 + (1 - 0.5) * (30.0 - 2.0) * (20.0 - 4.0) / 20.0),
    ("tailwater", 2.0 + (1 - 0.5) * (30.0 - 2.0))])
def test_drained_uplift_profile(reference, h_d):
    """Uplift.drained: the full head at the heel, h_d at the drains, the tailwater's head at
    the toe, linear between (hand values, 1e-12)."""
    up = sc.Uplift.drained("base", heel=(0.0, 0.0), toe=(20.0, 0.0), drain=(4.0, 0.0),
                           efficiency=0.5, head_up=30.0, head_down=2.0, reference=reference)
    x = np.array([0.0, 2.0, 4.0, 12.0, 20.0])
    want = np.interp(x, [0.0, 4.0, 20.0], [30.0, h_d, 2.0]) * GAMMA_W
    np.testing.assert_allclose(up.function()(x, 0 * x), want, rtol=1e-12)
    assert up.drains.efficiency == 0.5 and up.drains.at == (4.0, 0.0)


@pytest.mark.parametrize(("kw", "field"), [
    ({"efficiency": 1.5}, "efficiency"), ({"drain": (25.0, 0.0)}, "drain"),
    ({"reference": "heel"}, "reference"), ({"drain": (4.0,)}, "drain")])
def test_drained_uplift_refuses_bad_input(kw, field):
    """A drain efficiency outside [0, 1], drains off the base, an unknown reference or a
    malformed point: a ModelError naming the field."""
    args = {"heel": (0.0, 0.0), "toe": (20.0, 0.0), "drain": (4.0, 0.0), "efficiency": 0.5}
    with pytest.raises(sc.ModelError, match=field):
        sc.Uplift.drained("base", **{**args, **kw})


def test_crack_water_rule_and_bridge_inputs():
    """rule="em1110" needs a 2D entry (the heel); a negative bridge and an unknown rule are
    refused, naming the field."""
    with pytest.raises(sc.ModelError, match="rule"):
        sc.CrackWater("base", rule="em1110")
    with pytest.raises(sc.ModelError, match="rule"):
        sc.CrackWater("base", entry=(0.0, 0.0), rule="usbr")
    with pytest.raises(sc.ModelError, match="bridge"):
        sc.CrackWater("base", entry=(0.0, 0.0), bridge=-1.0)


def test_em1110_needs_the_entry_at_an_end_of_the_joint():
    """The EM 1110 profile runs from the tip to the far end: an entry in the middle of the
    base is refused when the model is assembled, naming the crack water's rule."""
    with pytest.raises(sc.ModelError, match="rule"):
        sc.solve_static(dam(1.5, "em1110", entry=(B / 2, 0.0)))


def test_model_file_drained_uplift_and_crack_rule():
    """The model file's ``drained`` table builds the same uplift as ``Uplift.drained`` (hand
    values at the heel, the drains and the toe, 1e-12), and refuses ``drained`` beside a
    head; ``crack_water`` passes ``rule`` and ``bridge``."""
    from pydantic import ValidationError

    from stepcontact.io.modelfile import schema
    from stepcontact.io.modelfile.schema import CrackWaterSpec, UpliftLoadSpec

    drained = {"heel": [0.0, 0.0], "toe": [B, 0.0], "drain": [DRAIN, 0.0],
               "efficiency": 2 / 3, "reference": "tailwater"}
    spec = UpliftLoadSpec(interface="base", drained=drained)
    assert spec.drained.efficiency == 2 / 3 and spec.head is None
    with pytest.raises(ValidationError, match="not both"):
        UpliftLoadSpec(interface="base", head=1.0, drained=drained)
    cw = CrackWaterSpec(interface="base", entry=(0.0, 0.0), rule="em1110", bridge=1.5)
    assert (cw.rule, cw.bridge) == ("em1110", 1.5)
    with pytest.raises(ValidationError):
        CrackWaterSpec(interface="base", entry=(0.0, 0.0), bridge=-1.0)
    assert "drained" in str(schema())
    up = sc.Uplift.drained("base", heel=(0.0, 0.0), toe=(B, 0.0), drain=(DRAIN, 0.0),
                           efficiency=2 / 3, reference="tailwater")
    x = np.array([0.0, DRAIN, B])
    np.testing.assert_allclose(up.function()(x, 0 * x), GAMMA_W * np.array([1.0, 1 / 3, 0.0]),
                               rtol=1e-12, atol=1e-9)


def fixed_level_dam(rule: str, h: float = 44.0) -> sc.Model:
    """The rigid dam with drains at a fixed level h (m), the reservoir's pattern scaling it
    (λ = 1: the face pressure, the drained uplift and the crack water of level h)."""
    m = dam(1.5, rule, DRAIN)
    base = m.interfaces[0]
    loads = [sc.WaterLoad(m.select("dam", x=0.0), level=h),
             sc.Uplift.drained(base, heel=(0.0, 0.0), toe=(B, 0.0), drain=(DRAIN, 0.0),
                               efficiency=2 / 3, reference="tailwater", head_up=h,
                               through="cfes"),
             sc.CrackWater(base, level=h, entry=(0.0, 0.0), rule=rule)]
    return m.replace(patterns=(m.patterns[0], sc.LoadPattern("reservoir", loads)),
                     program=(sc.Segment("weight", 1.0), sc.Segment("reservoir", 1.0)))


def em1110_profile(x: np.ndarray, tip: float, p_tip: float) -> np.ndarray:
    """The EM 1110 pressure beyond a tip upstream of the drains ("tailwater", E = 2/3, no
    tailwater): p_tip at the tip, p_tip/3 at the drains, 0 at the toe, linear between."""
    return np.interp(x, [tip, DRAIN, B], [p_tip, p_tip / 3, 0.0])


def test_em1110_profile_beyond_the_tip_static_and_dynamic():
    """Fixed level h = 44 m, the reservoir's factor ramped to 1: once the heel and the CFE
    at 2 m have opened (the tip upstream of the drains at 4 m), the water pressure beyond the
    tip is the EM 1110 profile — γ_w h λ at the tip, a third of it at the drains, 0 at the
    toe — at the static state and at every dynamic state with that crack (1e-9 relative).  A
    slow ramp (20 s against the block's rocking period ≈ 0.1 s) opens the first two CFEs at the
    static factors within 0.1 % (the dynamic part of the response)."""
    m = fixed_level_dam("em1110")
    st = sc.solve_static(m)
    x = st.cfe["x"][:, 0]
    beyond = x > 2.0 + 1e-9

    def check(res, i, lam):
        if set(x[res.state[i] == int(sc.ContactState.OPEN)]) != {0.0, 2.0}:
            return False  # (the crack of the heel and the CFE at 2 m only)
        p_tip = GAMMA_W * 44.0 * lam
        np.testing.assert_allclose(res.crack_pressure[i][beyond],
                                   em1110_profile(x[beyond], 2.0, p_tip), rtol=1e-9,
                                   atol=1e-9 * p_tip)
        return True

    opened = [e for e in st.events if e.transition == Transition.OPENED]
    assert [e.x for e in opened[:2]] == [0.0, 2.0]
    i2 = int(np.flatnonzero(st.lam == opened[1].lam)[-1])
    assert check(st, i2, st.lam[i2])
    weight = sc.solve_static(m.replace(program=(sc.Segment("weight", 1.0),)))
    T = 20.0

    def ramp(t):
        return 0.5 * (1 - np.cos(np.pi * min(float(t), T) / T))

    dyn = sc.solve_dynamic(m, dt=0.02, duration=T, loads={"reservoir": ramp}, initial=weight)
    d_open = [e for e in dyn.events if e.transition == Transition.OPENED]
    assert [e.x for e in d_open[:2]] == [0.0, 2.0]
    for e, s in zip(d_open[:2], opened[:2], strict=True):
        assert ramp(e.lam) == pytest.approx(s.lam, rel=1e-3)
    checked = sum(check(dyn, i, ramp(dyn.time[i])) for i in range(len(dyn.time)))
    assert checked >= 2
