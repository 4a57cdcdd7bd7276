"""The static event loop at the floor of its dense work (issue 27 §1), against full solves.

* The equilibrium residual recorded at a state without a stored field comes from the G t that
  the engine keeps current along the path (no pass over G): at every such state it equals the
  residual with G t formed in full (the reference: one dense product of the state's t) to
  1e-13 of the residual's scale, and is never below it by more than 1e-14 (a bound of the
  tracking error is added), while G t was formed in full at fewer than half of the checks.
* An error injected into the state along the path (the tangential force of a stuck CFE moved
  by 1e-6 of the path's force scale after event point 40: off equilibrium, on its relations,
  so no snap repairs it) is seen at every later recorded state: the recorded residual is at
  least the residual with G t formed in full by hand (‖ŵ + G (s − D ŵ) − Σ c ĥ‖ over the same
  scale, the path's displacement scale at that state included: the reference, less 1e-14)
  and at least 1e3 times the largest residual recorded before it.
* A snap that only corrects round-off is made CFE by CFE, without a scheme solve: afterwards
  the relations of the scheme hold to 4 ε of the forces, the state equals the state the
  scheme's solve gives (the dense reference: LU of the full scheme matrix) to 1e-13 of its
  scale (the round-off of that solve: the two differ by a few hundred ε), and the residual of
  the condensed equilibrium moves by at most 1e-14 of its scale; a snap beyond round-off (a
  CFE 1e-8 of the forces off its relation) is a solve of the scheme, checked the same way
  (its relations to 1e-14 of the forces).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

import stepcontact as sc
import verification_models as vm
from stepcontact.contact.laws import OPEN, SLIP_NEG, SLIP_POS, STICK, CoulombLaw
from stepcontact.fem.assembly import assemble
from stepcontact.solver.condensation import Condensed
from stepcontact.solver.engine import EventEngine
from stepcontact.solver.schemes import SchemeSolver, scheme_rhs, scheme_rows
from stepcontact.solver.static import StaticSolver

EPS = np.finfo(float).eps


def _slab() -> sc.Model:
    """benchmarks/slab_on_foundation.py at k = 1: a slab on an elastic foundation (76 CFEs),
    weight, a push (slip spreads along the joint) and uplift until it lifts off: about 110
    events."""
    concrete = sc.Material(E=30e9, nu=0.2, density=2400)
    rock = sc.Material(E=5e9, nu=0.25, density=2200)
    slab = sc.rectangle("slab", (10, 0), (40, 2), 75, 2, concrete)
    found = sc.rectangle("foundation", (0, -20), (50, 0), 125, 19, rock)
    m = sc.Model(bodies=[found, slab], plane="strain", thickness=1.0)
    joint_f = m.select("foundation", where=lambda x, y: (np.abs(y) < 1e-9) & (x > 9.99)
                       & (x < 40.01))
    return m.add(
        sc.Support("bed", m.select("foundation", y=-20), "xy"),
        sc.Support("sides", m.select("foundation", where=lambda x, y: (x < 1e-9)
                                     | (x > 50 - 1e-9)), "x"),
        sc.Interface("joint", plus=m.select("slab", y=0), minus=joint_f, friction=0.7),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("slab",))]),
        sc.LoadPattern("push", [sc.EdgeLoad(m.select("slab", x=10), normal=1.0)]),
        sc.LoadPattern("uplift", [sc.EdgeLoad(m.select("slab", y=0), normal=(1.0, 0.0))]),
        sc.Segment("weight", 1.0),
        sc.Segment("push", 2.0e5),
        sc.Segment("uplift", 1.0e6),
    )


def test_recorded_residuals_from_the_tracked_product_equal_full_products():
    solver = StaticSolver(assemble(_slab()))
    cond = solver.cond
    pairs = []
    n_full = [0]
    product = cond.product

    def counting(t):
        n_full[0] += 1
        return product(t)

    cond.product = counting
    residual = cond.condensed_residual

    def both(factors, s, w, w_scale=0.0, product=None):
        got = residual(factors, s, w, w_scale, product=product)
        n = n_full[0]
        ref = residual(factors, s, w, w_scale)  # G t formed in full: the reference
        n_full[0] = n
        pairs.append((got, ref))
        return got

    cond.condensed_residual = both
    res = solver.run()
    assert len(res.events) > 80, res.message
    got, ref = np.array(pairs).T
    assert len(got) > 64
    assert np.all(np.abs(got - ref) <= 1e-13), np.abs(got - ref).max()
    assert np.all(got >= ref - 1e-14)
    assert got.max() < 1e-10
    assert n_full[0] < len(got) / 2, (n_full[0], len(got))


class _Inject:
    """Hook: after event point ``at``, the tangential force of the first stuck CFE moves by
    ``size`` × the path's force scale (N) — an error the event loop does not make itself; keeps
    the path's displacement scale at every recorded event state (the residual's scale)."""

    def __init__(self, solver, at: int, size: float):
        self.solver, self.at, self.size = solver, at, size
        self.state = None
        self.w_scale: dict[int, float] = {}

    def after_event(self, info):
        eng = self.solver.engine
        self.w_scale[len(self.solver.rec) - 1] = eng.W_scale
        if info.step != self.at:
            return
        k = int(np.flatnonzero(eng.states == STICK)[0])
        eng.layout.tangential(eng.s)[k] += self.size * eng.F_scale
        self.state = len(self.solver.rec)  # the first state recorded after it


def _full_residual(cond, res, i, w_scale):
    """The relative residual of the condensed equilibrium at recorded state i with G t formed
    in full: ‖ŵ + G (s − D ŵ) − Σ_P c_P ĥ_P‖∞ / max(‖ŵ‖∞, ‖Σ c ĥ‖∞, w_scale)."""
    s = cond.layout.join(res.Q[i], -res.N[i])
    w = cond.layout.join(res.ut[i], res.un[i])
    e = sum(c * cond.e[n] for n, c in zip(res.pattern_names, res.factors[i], strict=True))
    h = sum(c * cond.hhat[n] for n, c in zip(res.pattern_names, res.factors[i], strict=True))
    w_hat = w - cond.system.w0 - e
    r = w_hat + cond.G @ (s - cond.d * w_hat) - h
    return np.abs(r).max() / max(np.abs(w_hat).max(), np.abs(h).max(), w_scale)


def test_an_error_injected_into_the_state_is_seen_at_every_later_recorded_state():
    solver = StaticSolver(assemble(_slab()))
    hook = _Inject(solver, at=40, size=1e-6)
    solver.hooks = (hook,)
    res = solver.run()
    assert hook.state is not None and len(res.events) > 60, res.message
    j = hook.state
    events = np.flatnonzero(np.asarray(res.kind) == "event")
    after = [i for i in events[events >= j] if i in hook.w_scale]
    assert len(after) > 20
    before = float(np.max(res.residual[events[events < j]]))
    for i in after:
        ref = _full_residual(solver.cond, res, i, hook.w_scale[i])
        assert res.residual[i] >= ref - 1e-14, (i, res.residual[i], ref)
        assert res.residual[i] >= 1e3 * before, (i, res.residual[i], before)


def _engine():
    mdl = vm.random_frictional_model("stack", (0.4, 0.6), [(0, -1)] * 3, [(0, -1)] * 3)
    system = assemble(mdl)
    cond = Condensed.from_system(system)
    law = CoulombLaw(np.arange(system.cfe.m), system.cfe.friction, system.cfe.kn,
                     system.cfe.kt)
    return EventEngine(SchemeSolver(cond.G, cond.d), [law], system.w0), cond, law


def _dense_snap(eng, cond, r):
    """The snap by a dense solve of the scheme's full matrix (the reference)."""
    rel = eng.relations(eng.states)
    n = eng.layout.n
    A, scale = scheme_rows(cond.G, cond.d, rel, np.arange(n))
    t = sla.solve(A, scale * scheme_rhs(cond.d, rel, np.zeros(n), np.zeros(n), r))
    w_hat = -cond.G @ t
    return eng.s + t + cond.d * w_hat, eng.w + w_hat


def _snap_rhs(eng, law):
    Q, p = eng.layout.split(eng.s)
    ut, un = eng.layout.split(eng.w)
    return np.concatenate(law.snap(eng.states, Q, p, un))


def _setup_state(eng, cond, law, states, mu):
    """The state μ (s', w') of the scheme ``states`` under the first pattern's load rates
    (on its relations and in equilibrium, to round-off); returns the load (ĥ, e) at μ."""
    h, e = vm.first_forcing(cond)
    eng.states = states.copy()
    ds, dw = eng.rates(states, (h, e))
    eng.s = mu * ds
    eng.w = eng.w * 0.0 + mu * dw
    eng.update_scales()
    return mu * h, mu * e


def _equilibrium(eng, cond, h, e):
    """The residual vector of the condensed equilibrium, relative to its scale."""
    w_hat = eng.w - e
    r = w_hat + cond.G @ (eng.s - cond.d * w_hat) - h
    return r / max(np.abs(w_hat).max(), np.abs(h).max())


def test_a_round_off_snap_is_made_per_cfe_and_equals_the_schemes_solve():
    eng, cond, law = _engine()
    m = eng.m
    states = np.full(m, STICK)
    states[[0, m - 1]] = OPEN
    states[1], states[m - 2] = SLIP_POS, SLIP_NEG
    rng = np.random.default_rng(5)
    h, e = _setup_state(eng, cond, law, states, 2.0)
    F = eng.F_scale
    # round-off off the relations: the open CFEs carry 1e-17 F of force
    eng.layout.normal(eng.s)[[0, m - 1]] += 1e-17 * F * rng.standard_normal(2)
    r = _snap_rhs(eng, law)
    assert np.abs(r).max() > 0
    s_ref, w_ref = _dense_snap(eng, cond, r)
    solves = eng.schemes.counters["scheme_solves"]
    before = _equilibrium(eng, cond, h, e)
    eng.snap()
    assert eng.schemes.counters["scheme_solves"] == solves  # no solve of the scheme
    assert np.abs(_snap_rhs(eng, law)).max() <= 4 * EPS * F
    assert np.abs(eng.s - s_ref).max() <= 1e-13 * F
    assert np.abs(eng.w - w_ref).max() <= 1e-13 * max(eng.W_scale, np.abs(w_ref).max())
    assert np.abs(_equilibrium(eng, cond, h, e) - before).max() <= 1e-14


def test_a_snap_beyond_round_off_is_a_solve_of_the_scheme():
    eng, cond, law = _engine()
    m = eng.m
    states = np.full(m, STICK)
    states[0] = OPEN
    h, e = _setup_state(eng, cond, law, states, 2.0)
    F = eng.F_scale
    eng.layout.normal(eng.s)[0] += 1e-8 * F  # an open CFE 1e-8 F off its relation (N = 0)
    r = _snap_rhs(eng, law)
    s_ref, w_ref = _dense_snap(eng, cond, r)
    solves = eng.schemes.counters["scheme_solves"]
    before = _equilibrium(eng, cond, h, e)
    eng.snap()
    assert eng.schemes.counters["scheme_solves"] > solves
    assert np.abs(_snap_rhs(eng, law)).max() <= 1e-14 * F
    assert np.abs(eng.s - s_ref).max() <= 1e-13 * F
    assert np.abs(_equilibrium(eng, cond, h, e) - before).max() <= 1e-14
