"""Verification of the static solver against independent references and closed-form results.

* frictionless path independence: final state (and every segment end) = QP minimiser;
* block on a base with friction: equilibrium lost at H = f W, slip zone only grows;
* uniform uplift under a slab on a rigid base: lift-off at uplift = weight;
* Hertz line contact (NAFEMS-style cylinder on a block): peak pressure and half-width;
* property tests on random small frictional systems: admissible states, event functions zero
  at the events, a load segment split in two gives the same path;
* the article's ε_p scheme converges (at least linearly) to the exact slip treatment.

The models are in ``verification_models.py``, the frictionless reference and the independent
state checks in ``reference.py``.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

import verification_models as vm
from reference import (
    contact_violation,
    equilibrium_residual,
    final_factors,
    frictionless_reference,
)
from stepcontact import ContactState, Status, Transition
from stepcontact.fem.assembly import assemble
from stepcontact.solver.static import solve_static

OPEN, STICK, SLIP_POS, SLIP_NEG = (int(s) for s in (ContactState.OPEN, ContactState.STICK,
                                                    ContactState.SLIP_POS,
                                                    ContactState.SLIP_NEG))
SLIPPING = (SLIP_POS, SLIP_NEG)


# --------------------------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------------------------
def factors_at(res, i: int) -> dict[str, float]:
    """Load factors of all patterns at reported state i."""
    return {name: float(v) for name, v in zip(res.pattern_names, res.factors[i], strict=True)}


def last(res) -> int:
    return res.n_states - 1


def scales(res, system) -> tuple[float, float]:
    """Force scale (N) and length scale (m) of a whole path, for relative tolerances."""
    F = max(float(np.abs(res.N).max(initial=0.0)), float(np.abs(res.Q).max(initial=0.0)))
    for i in range(res.n_states):
        f = sum(lam * system.loads[p].f for p, lam in factors_at(res, i).items())
        F = max(F, float(np.abs(f).max(initial=0.0)))
    L = max(float(np.abs(res.displacement(i)).max(initial=0.0)) for i in range(res.n_states))
    return max(F, 1e-300), max(L, 1e-300)


def assert_matches_reference(res, system, i: int, rtol: float) -> None:
    """State i of a frictionless run equals the QP minimiser at its load factors (dense
    quadprog identification up to 2000 DOFs, the sparse active-set route above)."""
    method = "quadprog" if system.ndof <= 2000 else "active_set"
    ref = frictionless_reference(system, factors_at(res, i), method=method)
    u = res.displacement(i)
    u_scale = np.abs(ref.u).max()
    n_scale = np.abs(ref.N).max()
    assert_allclose(u, ref.u, rtol=0, atol=rtol * u_scale, err_msg=f"u at state {i}")
    assert_allclose(res.N[i], ref.N, rtol=0, atol=rtol * n_scale, err_msg=f"N at state {i}")
    assert_allclose(res.Q[i], 0.0, rtol=0, atol=rtol * n_scale, err_msg=f"Q at state {i}")
    assert_allclose(res.un[i], ref.un, rtol=0, atol=rtol * u_scale, err_msg=f"un at state {i}")


# --------------------------------------------------------------------------------------------
# 1. frictionless: path independence
# --------------------------------------------------------------------------------------------
FRICTIONLESS = {
    "block_seed0": lambda: vm.frictionless_block(0),
    "block_seed1": lambda: vm.frictionless_block(1),
    "block_seed2": lambda: vm.frictionless_block(2),
    "two_blocks": vm.frictionless_two_blocks,
    "frame_on_bearings": vm.frictionless_frame,
}


@pytest.mark.parametrize("name", sorted(FRICTIONLESS))
def test_frictionless_final_state_is_qp_minimiser(name):
    """Frictionless contact is path independent: after a program of several segments (with
    unloading) the final state, and every segment end, equals the minimiser of the potential
    energy under u_n ≤ 0 (tests/reference.py).  Tolerance 1e-8 relative to max|u| and max|N|
    (the reference is exact to round-off; the path accumulates a few dozen linear solves)."""
    model = FRICTIONLESS[name]()
    system = assemble(model)
    res = solve_static(model)
    assert res.status == Status.COMPLETED, res.message
    assert res.events, "the model is built so that CFEs open or close along the path"
    fin = factors_at(res, last(res))
    for p, lam in final_factors(model).items():
        assert fin[p] == pytest.approx(lam, abs=1e-12)
    assert_matches_reference(res, system, last(res), rtol=1e-8)
    # the last reported state of every segment (its end)
    ends = [int(np.flatnonzero(res.segment == s).max()) for s in range(len(model.program))]
    for i in ends:
        assert_matches_reference(res, system, i, rtol=1e-8)


@settings(max_examples=10, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(3, 2**32 - 1))
def test_frictionless_random_blocks_match_qp_minimiser(seed):
    """The block-on-base program of ``frictionless_block`` with random loads and gaps from
    more seeds: final state = QP minimiser to 1e-8 relative (as above)."""
    model = vm.frictionless_block(seed)
    res = solve_static(model)
    assert res.status == Status.COMPLETED, res.message
    assert_matches_reference(res, assemble(model), last(res), rtol=1e-8)


# --------------------------------------------------------------------------------------------
# 2. block on a base with friction: loss of equilibrium at H = f W
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("friction", [0.3, 0.6])
def test_sliding_block_loses_equilibrium_at_f_times_W(friction):
    """A block held only by contact (no support; base fixed at its bottom) under its weight W
    and a growing horizontal body force H slides off as a whole when every CFE slips, i.e.
    when H = Σ|Q| = f Σ(−N) = f W.  Tolerance 1e-9 relative on that load factor.  Along the
    H segment the number of slipping CFEs never decreases (monotone loading)."""
    lam_star = vm.G * friction  # H = λ W / g
    model = vm.sliding_block(friction, 2 * lam_star)
    system = assemble(model)
    W = -system.loads["weight"].f.sum()
    H1 = system.loads["H"].f.sum()
    assert H1 * lam_star == pytest.approx(friction * W, rel=1e-12)  # the model is as meant

    res = solve_static(model)
    assert res.status == Status.EQUILIBRIUM_LOST, res.message
    mu = res.multipliers[1]
    assert mu.pattern == "H"
    # 1e-9 relative: the exact (event-driven) load factor of the mechanism
    assert mu.equilibrium_lost == pytest.approx(friction * W / H1, rel=1e-9)
    assert res.lam[last(res)] == pytest.approx(mu.equilibrium_lost, rel=1e-9)
    assert mu.first_slip is not None and mu.first_slip < mu.equilibrium_lost

    on_h = np.flatnonzero(res.segment == 1)
    slipping = np.isin(res.state[on_h], SLIPPING).sum(axis=1)
    assert np.all(np.diff(slipping) >= 0), f"slip zone shrank: {slipping}"
    # at the loss every CFE is on its friction limit |Q| = f(−N) (the scheme reported there
    # may still hold the last CFE as sticking: no scheme after a mechanism), so the friction
    # forces carry H: Σ|Q| = f Σ(−N) = f W (1e-9 relative)
    i = last(res)
    assert_allclose(np.abs(res.Q[i]), -friction * res.N[i], rtol=0, atol=1e-9 * W)
    assert np.abs(res.Q[i]).sum() == pytest.approx(friction * W, rel=1e-9)
    assert -res.N[i].sum() == pytest.approx(W, rel=1e-9)


# --------------------------------------------------------------------------------------------
# 3. uniform uplift: lift-off at uplift = weight
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("weight", ["body_force", "top_pressure"])
def test_uplift_lifts_slab_off_at_its_weight(weight):
    """A slab on a rigid (fully fixed) base under uniform uplift: equilibrium is lost (the slab
    lifts off) exactly when the uplift force equals the weight (1e-9 relative).  With the
    weight as a top pressure the stress state is uniform and all CFEs open at that same load
    factor (simultaneous events); with self-weight the slab bends slightly and the contact
    shrinks from the edges first."""
    model = vm.uplift_slab(weight, 20.0)
    system = assemble(model)
    W = -system.loads["weight"].f.sum()
    U1 = system.loads["uplift"].f.sum()
    lam_star = W / U1
    assert 1.0 < lam_star < 20.0

    res = solve_static(model)
    assert res.status == Status.EQUILIBRIUM_LOST, res.message
    mu = res.multipliers[1]
    assert mu.equilibrium_lost == pytest.approx(lam_star, rel=1e-9)
    # at lift-off every contact force has vanished (1e-9 relative to the weight) and the
    # reported scheme is the mechanism: every CFE open, the slab translating upwards
    assert_allclose(res.N[last(res)], 0.0, rtol=0, atol=1e-9 * W)
    assert np.all(res.state[last(res)] == 0)
    (body,) = res.mechanism["bodies"]
    assert body["body"] == "slab" and body["mode"] == "lift-off"
    tx, ty = body["translation"]
    assert abs(tx) < 1e-6 and ty == pytest.approx(1.0, rel=1e-6)
    if weight == "top_pressure":  # every N reaches 0 at λ*: no opening before the loss
        assert mu.first_opening is None or mu.first_opening == pytest.approx(lam_star, rel=1e-9)
        assert all(e.lam == pytest.approx(lam_star, rel=1e-9)
                   for e in res.events if e.transition == Transition.OPENED)
    else:
        assert mu.first_opening is not None and mu.first_opening < lam_star * (1 - 1e-6)
        # before the lift-off the reported states are the frictionless minimisers (1e-8)
        before = [i for i in range(res.n_states)
                  if res.segment[i] == 1 and res.lam[i] < lam_star * (1 - 1e-6)]
        for i in before[-2:]:
            assert_matches_reference(res, system, i, rtol=1e-8)


# --------------------------------------------------------------------------------------------
# 4. Hertz line contact
# --------------------------------------------------------------------------------------------
def test_hertz_formulas_give_the_nafems_values():
    """a = sqrt(4PR/(πE*)), p0 = 2P/(πa) for the NAFEMS data give a = 6.21 mm and
    p0 = 3585 MPa (to the digits quoted)."""
    a, p0 = vm.hertz_solution()
    assert a == pytest.approx(6.21e-3, abs=0.005e-3)
    assert p0 == pytest.approx(3585e6, abs=0.5e6)


@pytest.mark.slow
def test_hertz_cylinder_on_block():
    """Cylinder (R = 50 mm, 210 GPa) pressed on a block (70 GPa) by P = 35 kN/mm, plane strain,
    half model, frictionless, geometric gaps; three meshes with spacing a/10, a/16, a/24 at the
    contact (finest ≈ 15k DOFs).

    * total contact force = P/2 (1e-9 relative, equilibrium);
    * peak pressure −N/A at x = 0 within 1 % of p0 on every mesh (the discretisation error is
      already below the ≈ 0.1 % difference between the finite bodies and Hertz's half-spaces)
      and within 5 % on the finest;
    * pressure profile within 3 % of p0 √(1 − x²/a²) for x ≤ 0.9 a;
    * contact half-width (midway between the last closed and first open CFE) within 5 % on the
      finest mesh, its error decreasing under refinement;
    * the coarse mesh's final state equals the frictionless QP minimiser (1e-8 relative).
    """
    a, p0 = vm.hertz_solution()
    width_errors = []
    for k in (10, 16, 24):
        model = vm.hertz_model(a / k)
        system = assemble(model)
        res = solve_static(model)
        assert res.status == Status.COMPLETED, res.message
        i = last(res)
        N = res.N[i]
        x = system.cfe.x[:, 0]
        p = -N / system.cfe.area
        # vertical resultant: the mortar CFEs' normals are the cylinder's (tilted by ≤ 0.3 rad)
        assert -(N * system.cfe.normal[:, 1]).sum() == pytest.approx(vm.HERTZ_P / 2, rel=1e-9)
        peak = p[np.argmin(x)]
        assert peak == pytest.approx(p0, rel=0.01), f"a/{k}: peak {peak / 1e6:.1f} MPa"
        inner = x <= 0.9 * a
        hertz = p0 * np.sqrt(1 - (x[inner] / a) ** 2)
        assert np.abs(p[inner] - hertz).max() <= 0.03 * p0
        width_errors.append(abs(vm.hertz_half_width(x, N) / a - 1))
        if k == 10:
            assert_matches_reference(res, system, i, rtol=1e-8)
    assert peak == pytest.approx(p0, rel=0.05)
    assert width_errors[-1] <= 0.05, width_errors
    assert np.all(np.diff(width_errors) < 0), width_errors


# --------------------------------------------------------------------------------------------
# 5. property tests on random small frictional systems
# --------------------------------------------------------------------------------------------
def _random_params(seed: int) -> dict:
    """Frictions in [0.1, 0.9] and nodal loads (fx in [−0.4, 0.4], fy in [−1.5, 1.2], in units
    of W / number of loaded nodes) from a seed: uniformly random, never trivially zero."""
    rng = np.random.default_rng(seed)

    def loads():
        return [(float(fx), float(fy)) for fx, fy in
                zip(rng.uniform(-0.4, 0.4, 5), rng.uniform(-1.5, 1.2, 5), strict=True)]

    return {"frictions": tuple(float(v) for v in rng.uniform(0.1, 0.9, 2)),
            "loads1": loads(), "loads2": loads()}


random_systems = st.integers(0, 2**32 - 1).map(_random_params)
PROPERTY_SETTINGS = settings(max_examples=20, deadline=None, derandomize=True, database=None,
                             suppress_health_check=[HealthCheck.too_slow])

#: the state each transition leads to (the last event of a CFE at an event point decides)
AFTER = {
    Transition.OPENED: {OPEN},
    Transition.CLOSED: {STICK, SLIP_POS, SLIP_NEG},
    Transition.SLIP_POS: {SLIP_POS},
    Transition.SLIP_NEG: {SLIP_NEG},
    Transition.STUCK: {STICK},
}


def check_path(res, system) -> None:
    """Every reported state is admissible, every stretch between two states follows the
    working scheme reported for it, and every event is a root of its event function.

    Tolerances, all 1e-9 relative: forces to the largest force of the path (loads, N, Q),
    displacements to the largest displacement of the path.
    """
    F, L = scales(res, system)
    f = system.cfe.friction
    m = system.m
    # the solver's own measures
    assert np.all(res.residual <= 1e-9), res.residual.max()
    assert np.all(res.violation <= 1e-9), res.violation.max()
    # independent recomputation from the assembled system at every state
    for i in range(res.n_states):
        u = res.displacement(i)
        eq = equilibrium_residual(system, factors_at(res, i), u, res.N[i], res.Q[i])
        assert eq <= 1e-9, f"state {i}: equilibrium residual {eq:.2e}"
        viol = contact_violation(system, u, res.N[i], res.Q[i], res.state[i],
                                 force_scale=F, length_scale=L)
        for key, v in viol.items():
            assert v <= 1e-9, f"state {i}: {key} violated by {v:.2e}"
        w = system.B @ u + system.w0
        assert_allclose(res.ut[i], w[:m], rtol=0, atol=1e-9 * L)
        assert_allclose(res.un[i], w[m:], rtol=0, atol=1e-9 * L)
    # between consecutive states the path is linear with the scheme of the first one: a
    # sticking CFE does not slip, a slipping one slips in its direction (Q Δu_τ ≥ 0) on the
    # friction limit, an open one carries nothing, a closed one keeps u_n = 0
    for i in range(res.n_states - 1):
        st_i = res.state[i]
        dut = res.ut[i + 1] - res.ut[i]
        sigma = np.where(st_i == SLIP_POS, 1.0, np.where(st_i == SLIP_NEG, -1.0, 0.0))
        slip = sigma != 0
        stick, opn = st_i == STICK, st_i == OPEN
        assert np.all(np.abs(dut[stick]) <= 1e-9 * L), (i, dut, st_i)
        assert np.all(sigma[slip] * dut[slip] >= -1e-9 * L), (i, dut, st_i)
        j = i + 1
        assert np.all(np.abs(res.Q[j, slip] + sigma[slip] * f[slip] * res.N[j, slip])
                      <= 1e-9 * F), (i, st_i)
        assert np.all(np.abs(res.N[j, opn]) <= 1e-9 * F), (i, st_i)
        assert np.all(np.abs(res.Q[j, opn]) <= 1e-9 * F), (i, st_i)
        assert np.all(np.abs(res.un[j, ~opn]) <= 1e-9 * L), (i, st_i)
    # events: event functions vanish, forces are those of the reported state
    for e in res.events:
        k, i = e.cfe, e.state
        assert res.lam[i] == pytest.approx(e.lam, abs=1e-12 * max(1.0, abs(e.lam)))
        assert e.N == pytest.approx(res.N[i, k], abs=1e-9 * F)
        assert e.Q == pytest.approx(res.Q[i, k], abs=1e-9 * F)
        if e.transition == Transition.OPENED:  # N = 0 (and so Q = 0)
            assert abs(e.N) <= 1e-9 * F and abs(e.Q) <= 1e-9 * F, e
        elif e.transition == Transition.CLOSED:  # u_n = 0, no force yet
            assert abs(res.un[i, k]) <= 1e-9 * L, e
            assert abs(e.N) <= 1e-9 * F, e
        else:  # slip± or stuck: on the friction limit |Q| = f|N|
            assert abs(abs(e.Q) - f[k] * abs(e.N)) <= 1e-9 * F, e
            if e.transition == Transition.SLIP_POS:
                assert e.Q >= -1e-9 * F, e
            elif e.transition == Transition.SLIP_NEG:
                assert e.Q <= 1e-9 * F, e
    last_event = {(e.state, e.cfe): e.transition for e in res.events}
    for (i, k), tr in last_event.items():
        assert int(res.state[i, k]) in AFTER[tr], (i, k, tr, res.state[i, k])
    # events lie in their segment and in order along it
    for s, (_pat, lo, hi) in enumerate(res.segments):
        lams = [e.lam for e in res.events if e.segment == s]
        a, b = min(lo, hi), max(lo, hi)
        assert all(a - 1e-12 <= v <= b + 1e-12 for v in lams), (s, lams)
        d = np.diff(lams) * np.sign(hi - lo)
        assert np.all(d >= -1e-12), (s, lams)


@pytest.mark.parametrize("kind", vm.RANDOM_KINDS)
@PROPERTY_SETTINGS
@given(params=random_systems)
def test_random_paths_are_admissible(kind, params):
    """Random small frictional systems (a block on a base, two stacked blocks, a frame on
    bearings; random f and loads, with unloading): at every reported state equilibrium and the
    contact conditions (1) hold to 1e-9 relative, and every event is a root of its event
    function (see :func:`check_path`)."""
    model = vm.random_frictional_model(kind, **params)
    res = solve_static(model, store_fields="all")
    check_path(res, assemble(model))


def same_events(a, b, tol: float = 1e-9) -> None:
    """Two event logs list the same events: pattern, CFE, transition, λ (abs. tol ``tol``),
    order within one load factor ignored."""
    assert len(a.events) == len(b.events), (len(a.events), len(b.events))
    unused = list(b.events)
    for e in a.events:
        match = next((f for f in unused if f.pattern == e.pattern and f.cfe == e.cfe
                      and f.transition == e.transition and abs(f.lam - e.lam) <= tol), None)
        assert match is not None, f"no match for {e}"
        unused.remove(match)


@pytest.mark.parametrize("kind", vm.RANDOM_KINDS)
@PROPERTY_SETTINGS
@given(params=random_systems, split=st.floats(0.2, 0.8))
def test_splitting_a_segment_does_not_change_the_path(kind, params, split):
    """The same program with the segment of 'L2' split in two at a random factor gives the
    same events (λ to 1e-9, transitions, CFEs) and the same final state (N, Q, u_n, u_τ, u to
    1e-9 relative, same working scheme)."""
    model = vm.random_frictional_model(kind, **params)
    model_split = vm.random_frictional_model(kind, **params, split=split)
    res = solve_static(model)
    res2 = solve_static(model_split)
    assert res2.status == res.status
    same_events(res, res2)
    i, j = last(res), last(res2)
    assert factors_at(res, i) == pytest.approx(factors_at(res2, j), abs=1e-12)
    F = max(np.abs(res.N).max(), np.abs(res.Q).max(), 1e-300)
    u, u2 = res.displacement(i), res2.displacement(j)
    L = max(np.abs(u).max(), 1e-300)
    assert_allclose(res2.N[j], res.N[i], rtol=0, atol=1e-9 * F)
    assert_allclose(res2.Q[j], res.Q[i], rtol=0, atol=1e-9 * F)
    assert_allclose(res2.un[j], res.un[i], rtol=0, atol=1e-9 * L)
    assert_allclose(res2.ut[j], res.ut[i], rtol=0, atol=1e-9 * L)
    assert_allclose(u2, u, rtol=0, atol=1e-9 * L)
    np.testing.assert_array_equal(res2.state[j], res.state[i])


# --------------------------------------------------------------------------------------------
# 6. the article's scheme converges to the exact one
# --------------------------------------------------------------------------------------------
def test_article_scheme_converges_to_exact_as_eps_p_vanishes():
    """Block on a base (f = 0.4) held by springs, pushed sideways while being lifted, so the
    normal forces (and the friction limit) fall while it slips.  Exact mode: at the end every
    CFE slips and Σ|Q| = f Σ(−N) = f (W − V) (1e-9 relative).  Article mode with
    ε_p = 0.1, 0.05, 0.025, 0.0125: the error of the final state (max of the relative errors of
    u, N and Q against exact mode) decreases at least linearly — fitted log-log slope ≥ 0.9 —
    and is below 5 % at the smallest ε_p."""
    f = 0.4
    model = vm.spring_held_block(f)
    system = assemble(model)
    exact = solve_static(model, slip="exact")
    assert exact.status == Status.COMPLETED, exact.message
    i = last(exact)
    closed = exact.state[i] != OPEN
    assert np.all(np.isin(exact.state[i][closed], SLIPPING)), exact.state[i]
    W = -system.loads["weight"].f.sum()
    V = system.loads["push"].f[system.dofs.of[:, 1]].sum()
    assert -exact.N[i].sum() == pytest.approx(W - V, rel=1e-9)
    assert np.abs(exact.Q[i]).sum() == pytest.approx(f * (W - V), rel=1e-9)

    u_ex = exact.displacement(i)
    eps = np.array([0.1, 0.05, 0.025, 0.0125])
    errors = []
    for e in eps:
        art = solve_static(model, slip="article", eps_p=e)
        assert art.status == Status.COMPLETED, art.message
        j = last(art)
        err_u = np.abs(art.displacement(j) - u_ex).max() / np.abs(u_ex).max()
        err_n = np.abs(art.N[j] - exact.N[i]).max() / np.abs(exact.N[i]).max()
        err_q = np.abs(art.Q[j] - exact.Q[i]).max() / np.abs(exact.Q[i]).max()
        errors.append(max(err_u, err_n, err_q))
    errors = np.asarray(errors)
    assert errors[-1] <= 0.05, errors
    if errors.max() > 1e-10:  # (an article path that is exact to round-off passes trivially)
        slope = np.polyfit(np.log(eps), np.log(np.maximum(errors, 1e-300)), 1)[0]
        assert slope >= 0.9, (slope, errors)
