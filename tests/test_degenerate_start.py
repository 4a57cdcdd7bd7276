"""Loading from zero with every contact closed at N = Q = 0 (the fully degenerate rate problem),
and the other degenerate points found by trying real problems (issue: robust start).

References: the same model with a small preload (the path is then non-degenerate at its
start), closed-form statics (weights, resultants), and exhaustive enumeration of the schemes of
a one-CFE rate problem.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import stepcontact as sc
import verification_models as vm
from stepcontact.enums import ContactState

TOL = 1e-9


def pressed_plate(f: float, ratio: float, preload: float = 0.0, nx: int = 6) -> sc.Model:
    """A plate on a fixed base, zero gaps, pressed by a normal pressure (1 Pa per unit λ) and
    sheared by a lateral traction ``ratio`` Pa per unit λ along −x on its top, proportionally
    from zero (``preload``: a first segment of the normal pressure alone)."""
    m = vm.block_on_base(friction=f, nx=nx, ny=2, w=2.0, h=0.5)
    top = m.select("block", y=0.5)
    # the edge tangent of a top face is +x (t = (n_y, −n_x)): −ratio pushes along −x
    pats = [sc.LoadPattern("press", [sc.EdgeLoad(top, normal=1.0, tangential=-ratio)])]
    segs = [sc.Segment("press", 1e6)]
    if preload:
        pats.insert(0, sc.LoadPattern("pre", [sc.EdgeLoad(top, normal=1.0)]))
        segs.insert(0, sc.Segment("pre", preload))
    return m.add(*pats, *segs)


def assert_admissible(res: sc.StaticResult, tol: float = TOL) -> None:
    assert res.residual.max() < tol, res.residual.max()
    assert res.violation.max() < tol, res.violation.max()


@pytest.mark.parametrize("f", [0.5, 1.0, 2.0])
def test_plate_pressed_and_sheared_from_zero(f):
    """Proportional normal and lateral pressure from zero, with friction: the traction is below
    the friction limit everywhere (ratio 0.3 < f), so the program completes with every CFE
    closed; the same as with a preload (no false mechanism, no cycling at λ = 0)."""
    res = sc.solve_static(pressed_plate(f, 0.3))
    pre = sc.solve_static(pressed_plate(f, 0.3, preload=1e-3))
    assert res.status == sc.Status.COMPLETED, res.message
    assert pre.status == sc.Status.COMPLETED, pre.message
    assert np.all(res.state[-1] != ContactState.OPEN)
    assert_admissible(res)
    # statics: the CFE forces carry the resultant of the top loads (2 m × 1e6 Pa × λ)
    assert -res.N[-1].sum() == pytest.approx(2.0e6, rel=1e-9)
    assert res.Q[-1].sum() == pytest.approx(-0.3 * 2.0e6, rel=1e-9) or \
        res.Q[-1].sum() == pytest.approx(0.3 * 2.0e6, rel=1e-9)
    scale = np.abs(res.N[-1]).max()
    assert np.allclose(res.N[-1], pre.N[-1], atol=1e-6 * scale)


def test_plate_sheared_beyond_friction_slides_at_zero():
    """Traction above the friction limit (ratio 0.8 > f = 0.5): the plate slides at once —
    equilibrium is lost at λ = 0 with the mechanism 'sliding', and so it is with a preload
    (at the λ where the lateral load starts)."""
    res = sc.solve_static(pressed_plate(0.5, 0.8))
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert res.multipliers[-1].equilibrium_lost == 0.0
    assert res.mechanism["bodies"][0]["mode"] == "sliding"
    pre = sc.solve_static(pressed_plate(0.5, 0.8, preload=1e-3))
    assert pre.status == sc.Status.EQUILIBRIUM_LOST


def test_contact_node_on_a_roller_is_carried_by_the_supports():
    """A contact node fixed in y on a base node fixed in y: the CFE's normal row is zero.  A
    named warning says so, the supports carry its normal force (the CFE carries none), and the
    run goes on to the sliding load of the rest of the joint (no false mechanism at λ = 0).
    The meshes match (node-to-node CFEs): a mortar CFE would also tie the base nodes next to
    the corner, which are free."""
    m = vm.block_on_base(friction=0.5, nx=4, ny=2, base_nx=6)
    m = m.add(
        sc.Support("roller", m.select("block", x=0.0, y=0.0, boundary=False), "y"),
        sc.Support("base_corner", m.select("base", x=0.0, y=0.0, boundary=False), "xy"),
        sc.LoadPattern("w", [sc.BodyForce(bodies=("block",))]),
        sc.LoadPattern("push", [sc.NodalLoad(m.select("block", x=0.0), fx=1.0)]),
        sc.Segment("w", 1.0), sc.Segment("push", 1e5),
    )
    with pytest.warns(sc.ContactHeldWarning, match=r"contact\[0\].*normal"):
        res = sc.solve_static(m)
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    assert res.multipliers[1].equilibrium_lost > 0
    scale = np.abs(res.N).max()
    assert np.abs(res.N[:, 0]).max() <= 1e-12 * scale
    assert np.abs(res.Q[:, 0]).max() <= 1e-12 * scale
    # the rest of the joint slides at f × (its normal force): weight less the roller's share
    i = int(np.flatnonzero(res.kind == "event")[-1])
    assert res.Q[i, 1:].sum() == pytest.approx(-0.5 * res.N[i, 1:].sum(), rel=1e-9)
    assert_admissible(res)


def test_cfes_that_open_at_the_start_are_events():
    """A block with zero gaps loaded at one corner: the far CFEs open at λ = 0; each is an
    'opened' event at λ = 0 and first_opening is 0."""
    m = vm.block_on_base(friction=0.5, nx=6, ny=2)
    m = m.add(
        sc.Support("hold", m.select("block", x=1.0, y=0.5, boundary=False), "x"),
        sc.LoadPattern("corner", [sc.NodalLoad(m.select("block", x=0.0, y=0.5, boundary=False),
                                               fy=-1.0)]),
        sc.Segment("corner", 1e3),
    )
    res = sc.solve_static(m)
    assert res.status == sc.Status.COMPLETED
    opened = [e for e in res.events if e.transition == sc.Transition.OPENED]
    assert opened and all(e.lam == 0.0 for e in opened)
    assert {e.cfe for e in opened} == set(np.flatnonzero(res.state[-1] == ContactState.OPEN))
    assert res.multipliers[0].first_opening == 0.0
    assert -res.N[-1].sum() == pytest.approx(1e3, rel=1e-9)
    assert_admissible(res)


@pytest.mark.parametrize("n, end", [(6, 1.0), (24, 1.0), (24, 0.05)])
def test_closing_gaps_carry_no_tension(n, end):
    """A curved gap g = 1e-3 (x − 1)² closes progressively under a top pressure (over a long
    segment, and a short one that ends soon after the first closings): every state, in
    particular the states at which a gap closes, has N ≤ 0 to round-off."""
    m = vm.block_on_base(friction=0.5, nx=n, ny=2, gap=lambda x, y: 1e-3 * (x - 1.0) ** 2)
    m = m.add(sc.LoadPattern("down", [sc.EdgeLoad(m.select("block", y=0.5), normal=1e6)]),
              sc.Segment("down", end))
    res = sc.solve_static(m)
    assert res.status == sc.Status.COMPLETED
    assert sum(e.transition == sc.Transition.CLOSED for e in res.events) >= 2
    assert res.N.max() <= 1e-12 * np.abs(res.N).max()
    assert_admissible(res)


@pytest.mark.filterwarnings(  # f far beyond any real one on purpose: warned about, and legal
    "ignore::stepcontact.model.plausible.PlausibilityWarning")
@pytest.mark.parametrize("f", [1e8, 1e12])
def test_huge_friction_never_slides(f):
    """f = 1e12 is a (silly but legal) 'glued' joint: the push never slides it, and the run
    completes with the contact conditions met (not exit 0 with a violated state)."""
    res = sc.solve_static(vm.sliding_block(f, 10.0))
    assert res.status == sc.Status.COMPLETED, res.message
    assert_admissible(res)
    assert not any(e.transition in (sc.Transition.SLIP_POS, sc.Transition.SLIP_NEG)
                   for e in res.events)


@pytest.mark.parametrize("cfe", ["mortar", "node-to-segment"])
def test_body_lifted_straight_off_is_lift_off(cfe):
    """Gravity reversed on a block resting on a base: a translation, not an overturning (with
    mortar CFEs the rate problem at this degenerate point may keep a force-free CFE closed;
    the mechanism reported is then the scheme with it opened, whose motion opens it)."""
    m = vm.block_on_base(friction=0.5, nx=6, ny=2, cfe=cfe)
    m = m.add(sc.LoadPattern("up", [sc.BodyForce(bodies=("block",), g=(0.0, 9.81))]),
              sc.Segment("up", 1.0))
    res = sc.solve_static(m)
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    body = res.mechanism["bodies"][0]
    assert body["mode"] == "lift-off" and body["centre"] is None
    assert np.all(res.state[-1] == ContactState.OPEN)


# --------------------------------------------------------------------------------------------
# several solutions, and none
# --------------------------------------------------------------------------------------------
def strut(f: float, fx: float, fy: float) -> sc.Model:
    """A stiff strut at 45° from a clamped top (−cos 45°, sin 45°) m to a tip resting on a
    base: one CFE, whose tangential and normal stiffness are strongly coupled (the textbook
    two-DOF system of frictional contact).  Load (fx, fy) N at the tip per unit λ."""
    a = np.radians(45.0)
    top = (-np.cos(a), np.sin(a))
    bar = sc.Frame.line("bar", top, (0.0, 0.0), 1, E=2e11, A=1e-3, I=1e-6)
    base = sc.rectangle("base", (-0.5, -0.2), (0.5, 0.0), 2, 1, sc.Material(2e11, 0.3))
    m = sc.Model(bodies=[base, bar])
    tip = m.select("bar", x=0.0, y=0.0)
    return m.add(sc.Support("ground", m.select("base", y=-0.2), "xy"),
                 sc.Support("top", m.select("bar", x=top[0], y=top[1]), "xyrz"),
                 sc.Interface("c", plus=tip, minus=m.select("base", y=0.0), friction=f,
                              area=1.0),
                 sc.LoadPattern("p", [sc.NodalLoad(tip, fx=fx, fy=fy)]), sc.Segment("p", 1.0))


def _admissible_schemes(model: sc.Model) -> set[str]:
    """Every state of the one CFE at λ = 0 whose rates meet conditions (1), by brute force:
    each scheme solved directly with the condensed equations (independent of the LCP)."""
    from stepcontact.contact.laws import CoulombLaw
    from stepcontact.fem.assembly import assemble
    from stepcontact.solver.condensation import Condensed
    from stepcontact.solver.engine import EventEngine
    from stepcontact.solver.schemes import MechanismError, SchemeSolver

    system = assemble(model)
    cond = Condensed.from_system(system)
    cfe = system.cfe
    law = CoulombLaw(np.arange(cfe.m), cfe.friction, cfe.kn, cfe.kt)
    eng = EventEngine(SchemeSolver(cond.G, cond.d), [law], system.w0)
    forcing = (cond.hhat["p"], cond.e["p"])
    ok = set()
    for st_ in (ContactState.OPEN, ContactState.STICK, ContactState.SLIP_POS,
                ContactState.SLIP_NEG):
        try:
            ds, dw = eng.rates(np.array([int(st_)]), forcing)
        except MechanismError:
            continue
        Q, p, un, slip = ds[0], ds[1], dw[1], dw[0]
        f = cfe.friction[0]
        good = {
            ContactState.OPEN: un <= 0,
            ContactState.STICK: p >= 0 and abs(Q) <= f * p,
            ContactState.SLIP_POS: p >= 0 and slip > 0,
            ContactState.SLIP_NEG: p >= 0 and slip < 0,
        }[st_]
        if good:
            ok.add(st_.label)
    return ok


@pytest.mark.parametrize("f", [3.0, 10.0])
def test_several_admissible_schemes_are_reported(f):
    """Large f on the coupled strut, pushed sideways and down (30° below the horizontal): open,
    stick and slip+ all satisfy the contact conditions.  The run follows one, and reports the
    λ, the CFE, the alternatives, the one followed and why; the set equals the brute-force
    enumeration of the schemes."""
    model = strut(f, np.cos(np.radians(30)), -0.5)
    expected = _admissible_schemes(model)
    assert expected == {"open", "stick", "slip+"}
    res = sc.solve_static(model)
    assert res.status == sc.Status.COMPLETED
    assert len(res.nonunique) == 1
    nu = res.nonunique[0]
    assert nu["lam"] == 0.0 and nu["cfes"] == ["c[0]"]
    found = {nu["followed"][0], *(a[0] for a in nu["alternatives"])}
    assert found == expected
    assert nu["followed"][0] == ContactState(int(res.state[-1][0])).label
    assert nu["why"]
    # the report survives the result file
    assert res.to_dataset().attrs["nonunique"]


def test_unique_rate_problem_reports_nothing():
    """Small friction on the same strut: one admissible scheme, no report."""
    model = strut(0.3, 1.0, -0.5)
    assert len(_admissible_schemes(model)) == 1
    assert sc.solve_static(model).nonunique == []


def test_no_solution_is_a_reported_outcome(monkeypatch):
    """When no scheme is found (every LCP method and the enumeration fail: forced here, since
    the one-point strut always has a solution), the run stops with status rate_problem and a
    message that names the CFEs and gives the certificate — not a mechanism, not a crash."""
    from stepcontact.solver import rate
    from stepcontact.solver.lcp import LCPResult

    def fail(M, q, *a, **k):
        return LCPResult(np.zeros(len(q)), q.copy(), False, 1, "forced failure",
                         np.ones(len(q), bool))

    monkeypatch.setattr(rate, "principal_pivoting", fail)
    monkeypatch.setattr(rate, "lemke", fail)
    monkeypatch.setattr(rate, "_enumerate", lambda *a: [])
    res = sc.solve_static(strut(3.0, 1.0, -0.1))
    assert res.status == sc.Status.RATE_PROBLEM
    assert "certificate: forced failure" in res.message and "c[0]" in res.message


# --------------------------------------------------------------------------------------------
# property: loading from zero with closed contacts
# --------------------------------------------------------------------------------------------
def random_zero_start(kind: str, f: float, loads: list[tuple[float, float]], preload: float):
    """A random model of ``kind`` (block, stack or beam; zero gaps) loaded proportionally from
    zero by ``loads`` (its weight included in the same pattern), optionally after a preload
    segment of ``preload`` × the same pattern."""
    m = vm.random_frictional_model(kind, (f, f), loads, loads)
    pats = {p.name: p for p in m.patterns}
    both = sc.LoadPattern("all", [*pats["weight"].loads, *pats["L1"].loads])
    m = m.replace(patterns=(both,), program=())
    program = [sc.Segment("all", preload)] if preload else []
    return m.add(*program, sc.Segment("all", 1.0))


load = st.tuples(st.floats(-1.0, 1.0), st.floats(-1.5, 0.5))
cases = st.tuples(st.sampled_from(["block", "stack", "beam"]), st.floats(0.0, 2.0),
                  st.lists(load, min_size=3, max_size=3))


@settings(max_examples=25, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(params=cases)
def test_zero_start_property(params):
    """Random continua and frames on a fixed base, zero gaps, random proportional loads from
    zero, f in [0, 2]: the run never reports a mechanism that a preload of 1e-9 of the load
    does not also report, and every reported state satisfies equilibrium and conditions (1)
    to 1e-9."""
    kind, f, loads = params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.ContactHeldWarning)
        res = sc.solve_static(random_zero_start(kind, f, loads, 0.0))
        pre = sc.solve_static(random_zero_start(kind, f, loads, 1e-9))
    if res.status == sc.Status.EQUILIBRIUM_LOST:
        assert pre.status == sc.Status.EQUILIBRIUM_LOST, (res.message, pre.message)
    assert res.status in (sc.Status.COMPLETED, sc.Status.EQUILIBRIUM_LOST,
                          sc.Status.RATE_PROBLEM), res.message
    ok = slice(None) if res.status == sc.Status.COMPLETED else slice(None, -1)
    assert res.residual[ok].max(initial=0) < TOL
    assert res.violation.max() < TOL
    # restart: no CFE changes twice at one event point, and no event repeats at one λ
    seen = set()
    for e in res.events:
        key = (e.segment, e.lam, e.cfe, e.transition)
        assert key not in seen, key
        seen.add(key)
    steps = [(e.step, e.cfe) for e in res.events]
    assert len(steps) == len(set(steps))


def test_contact_node_on_a_roller_at_rest_in_dynamics():
    """The same roller in a dynamic interval from the static state under the weight: the
    supports carry the held CFE's normal force as in statics (its component is inert in both
    drivers), so the block stays at rest — the CFE forces stay the static ones (1e-9 of the
    largest) and the held CFE carries nothing.  (Before, the dynamic driver did not hold it
    and lost equilibrium at t = 0 under a weight applied suddenly from rest.)"""
    m = vm.block_on_base(friction=0.5, nx=4, ny=2, base_nx=6)
    m = m.add(
        sc.Support("roller", m.select("block", x=0.0, y=0.0, boundary=False), "y"),
        sc.Support("base_corner", m.select("base", x=0.0, y=0.0, boundary=False), "xy"),
        sc.LoadPattern("w", [sc.BodyForce(bodies=("block",))]),
        sc.Segment("w", 1.0),
    )
    with pytest.warns(sc.ContactHeldWarning):
        st = sc.solve_static(m)
    assert st.status == sc.Status.COMPLETED
    res = sc.solve_dynamic(m, initial=st, dt=1e-3, duration=1e-2)
    assert res.status == sc.Status.COMPLETED, res.message
    scale = np.abs(st.N[-1]).max()
    assert np.abs(res.N[:, 0]).max() <= 1e-12 * scale
    assert np.allclose(res.N[-1], st.N[-1], atol=1e-9 * scale)
    assert np.allclose(res.Q[-1], st.Q[-1], atol=1e-9 * scale)
    # the weight applied suddenly, from rest at zero (the case that failed)
    sudden = sc.solve_dynamic(m, dt=1e-3, duration=1e-2, loads={"w": sc.Constant(1.0)})
    assert sudden.status == sc.Status.COMPLETED, sudden.message
    assert np.abs(sudden.N[:, 0]).max() <= 1e-12 * scale
    assert np.abs(sudden.N).max() > 0.1 * scale
