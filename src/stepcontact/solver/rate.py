"""The rate problem at a degenerate point of the path: which working scheme comes next.

At an event point some CFEs sit at their limits (N = 0, |Q| = f(−N), u_n = 0) and every
slipping CFE may stick again; at the start of a load path from zero with closed contacts every
CFE is at every limit at once.  The next scheme is the one whose rates satisfy the contact
conditions (1) of these CFEs.  Written on the stuck base scheme (every CFE of the point closed
and stuck: the stiffest choice, regular whenever the structure is not a mechanism with them
stuck) with the opening and slip rates z ≥ 0 as unknowns, this is the standard linear
complementarity problem of 2D Coulomb friction:

    w = M z + q ≥ 0,   z ≥ 0,   zᵀ w = 0

    z: opening rate o (CFEs at the normal limit), slip rates a⁺, a⁻ (on the friction facets
       the CFE touches);
    w: the complements p' = −N' ≥ 0,  f p' − Q' ≥ 0,  f p' + Q' ≥ 0 (the rates of the
       facets f p + C ∓ Q, C the residual cohesion of a broken bond);

q is the base scheme's response to the load rate and column j of M its response to z_j = 1
(one block solve with the base scheme's factor).  It is solved by principal pivoting from the
current scheme (unique answer for P-matrices), then by Lemke's method, which terminates for any
M.  The rates of the answer are q's rates plus the columns times z: no further factorisation.

Outcomes: a scheme (with, for small problems, every other admissible scheme when there are
several — a result, reported with the one followed and why); or no solution, where the ray of
Lemke's method names a scheme: if that scheme is singular and the load drives its mechanism
(the load is not orthogonal to its left null space), equilibrium is lost; otherwise the rate
problem has no solution found, reported with the ray as certificate.
"""

from __future__ import annotations

import contextlib
import itertools
from dataclasses import dataclass, field

import numpy as np

from stepcontact.contact.laws import OPEN, OPENING, RateVariables
from stepcontact.enums import Status, slipping
from stepcontact.solver.lcp import BasisGroups, enumerate_solutions, lemke, principal_pivoting
from stepcontact.solver.schemes import MechanismError

#: rate problems with at most this many CFEs (and 3 variables each) are checked for other
#: solutions by enumeration when M is not positive definite (P-matrix: the answer is unique)
ENUMERATE_CFES = 5
#: … and with at most this many complementary bases in all (6⁵ = 7 776 in 2D: every 2D problem
#: of ENUMERATE_CFES CFEs; a faceted cone's k facets give 2 (1 + 2k) bases per CFE)
ENUMERATE_BASES = 8000
#: a point with at least this many CFEs in L (every slipping CFE is in L: it may stick) tries
#: the rate problem of its core first (:func:`_core_outcome`)
CORE_MIN = 64
#: … taking the CFEs its solution leaves inconsistent into the core, at most this many times
CORE_ROUNDS = 4
#: a rate problem of at least this many variables takes the base scheme's responses at its
#: own CFEs only (:func:`_responses`); a smaller one solves its columns as a block, whose
#: cost is a few passes over the dense matrices (and whose round-off its recorded event
#: sequences, e.g. the choices at a mechanism's point, were made with)
RESPONSE_ROWS_MIN = 64


class RateProblemFailure(Exception):
    """No consistent scheme was found at a point: ``status``, the CFEs involved, a message and,
    when Lemke's method ended on a ray, that ray's scheme (``certificate``)."""

    def __init__(self, status: Status, cfes: np.ndarray, message: str,
                 certificate: np.ndarray | None = None):
        self.status = status
        self.cfes = cfes
        self.certificate = certificate
        super().__init__(message)


@dataclass
class RateOutcome:
    """The scheme chosen at a point, its rates, how it was found, and the other admissible
    schemes (``alternatives``: state arrays over ``cfes``) when the answer is not unique."""

    states: np.ndarray
    ds: np.ndarray
    dw: np.ndarray
    method: str
    cfes: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    alternatives: list[np.ndarray] = field(default_factory=list)


def _one_law(eng):
    """The law of ``eng`` when one law governs every CFE in order (the common case: its local
    indices are the global ones), else None."""
    views = eng._views_now()
    if len(views) == 1 and type(views[0][1]) is slice:
        return views[0][0]
    return None


def _base_scheme(eng, L: np.ndarray, states: np.ndarray) -> np.ndarray:
    """``states`` with the CFEs in L in each law's base state (closed and stuck)."""
    base = states.copy()
    one = _one_law(eng)
    if one is not None:
        base[L] = one.base_state(base)[L]
        return base
    for law in eng.laws:
        inl = np.isin(law.cfes, L)
        base[law.cfes[inl]] = law.base_state(base[law.cfes])[inl]
    return base


def _law_of(eng, k: int):
    """The law that governs CFE k."""
    return _one_law(eng) or next(lw for lw in eng.laws if k in lw.cfes)


def _variables(eng, L, normal_lim, two_sided) -> RateVariables:
    """The variables of every law for the CFEs in L."""
    tf, _ = eng.tolerances()
    Q, p = eng.layout.split(eng.s)
    one = _one_law(eng)
    if one is not None:
        return one.rate_variables(L, eng.states, Q, normal_lim, two_sided, p=p, tf=tf)
    parts = []
    for law in eng.laws:
        pos = np.searchsorted(law.cfes, L)
        pos = np.clip(pos, 0, max(len(law.cfes) - 1, 0))
        mine = np.flatnonzero(law.cfes[pos] == L) if len(law.cfes) else np.zeros(0, int)
        local = pos[mine]
        sl = law.cfes
        v = law.rate_variables(local, eng.states[sl], Q[sl], normal_lim[sl], two_sided[sl],
                               p=p[sl], tf=tf)
        parts.append(v)
    return RateVariables.concatenate(parts)


def _states_from(eng, base, var, active, z):
    one = _one_law(eng)
    if one is not None:
        return one.states_from_active(base, var.cfe, var.kind, active, z, facet=var.facet)
    new = base.copy()
    for law in eng.laws:
        sel = np.isin(var.cfe, law.cfes)
        loc = np.searchsorted(law.cfes, var.cfe[sel])
        new[law.cfes] = law.states_from_active(base[law.cfes], loc, var.kind[sel], active[sel],
                                               z[sel], facet=var.facet[sel])
    return new


def _start_basis(eng, var: RateVariables, guess: np.ndarray) -> np.ndarray:
    """The complementary basis that stands for the guessed scheme (pivoting starts there, so
    that a non-unique rate problem continues the current scheme where it can); each law says
    which of its variables its states stand for."""
    one = _one_law(eng)
    if one is not None:
        return np.asarray(one.active_for(guess[var.cfe], var.kind, var.facet), bool)
    out = np.zeros(len(var.cfe), bool)
    for law in eng.laws:
        sel = np.isin(var.cfe, law.cfes)
        if sel.any():
            out[sel] = law.active_for(guess[var.cfe[sel]], var.kind[sel], var.facet[sel])
    return out


def solve_rate_problem(eng, L: np.ndarray, guess: np.ndarray, forcing, normal_lim, two_sided,
                       method: str = "pivoting", guess_rates=None) -> RateOutcome:
    """Choose the states of the CFEs in L (ascending) so that the rates are consistent.

    ``eng`` is the :class:`~stepcontact.solver.engine.EventEngine` (its laws, state and scheme
    solver), ``guess`` the current scheme with the natural transitions of the CFEs that fired,
    ``forcing`` the load rates (ĥ, e) on the contact unknowns; ``guess_rates``: the guess's
    rates (ds, dw) if known (False: the guess is singular).  Raises
    :class:`MechanismError` (equilibrium lost, with evidence) or :class:`RateProblemFailure`.
    """
    # the guessed scheme is kept when its rates are consistent (the common case, one solve)
    kept = None
    if guess_rates is None:
        try:
            guess_rates = eng.rates(guess, forcing, article=False)
        except MechanismError:
            guess_rates = False
    if guess_rates is not False:
        ds, dw = guess_rates
        if _same(eng.consistent(guess, L, ds, dw, normal_lim, two_sided), guess[L]):
            kept = RateOutcome(guess, ds, dw, "the current scheme stays consistent", L)
    if kept is not None and _slipping_only(eng, L, normal_lim, two_sided):
        return kept  # CFEs in mid-slip, none at a limit: nothing else to choose from
    if kept is not None and not (len(L) <= ENUMERATE_CFES and _frictional(eng, L)):
        return kept
    if kept is None and len(L) >= CORE_MIN:
        out = _core_outcome(eng, L, guess, forcing, normal_lim, two_sided, method,
                            guess_rates)
        if out is not None:
            return out
    base = _base_scheme(eng, L, guess)
    h, e = forcing
    try:
        fact = eng.factor(base, article=False)
        ds0, dw0 = fact.load_rates(h, e)  # (a float32 update that does not refine is
        # refactorised here, which may find the scheme singular)
    except MechanismError as exc:
        # the stiffest scheme of the point is singular: so is every other one
        if kept is not None:
            return kept
        exc.states = base
        if eng.drives(base, forcing):
            raise
        return _singular_point(eng, L, guess, forcing, normal_lim, two_sided)
    var = _variables(eng, L, normal_lim, two_sided)
    lay = eng.layout
    nv = len(var.cfe)
    if nv == 0:
        return kept or RateOutcome(base, ds0, dw0, "stuck scheme", L)
    R = lay.zeros(nv)
    rows = lay.rows(var.cfe)  # (nv, 1 + n_t): the rows of each variable's CFE
    for c in range(lay.n_c):
        R[rows[:, c], np.arange(nv)] = var.effect[:, c]
    try:
        dS_at, combine = _responses(eng, fact, var, R, ds0, dw0)
    except MechanismError as exc:
        exc.states = base
        raise
    eng.counters["rate_solves"] += 1 + nv
    Wm = var.comp[:, :1] * dS_at(rows[:, 0])
    for c in range(1, lay.n_c):
        Wm = Wm + var.comp[:, c:c + 1] * dS_at(rows[:, c])
    q, M = Wm[:, 0], Wm[:, 1:]
    if kept is not None:  # small frictional point: are there other admissible schemes?
        kept.alternatives = _alternatives(eng, L, base, var, M, q, combine, kept)
        return kept
    start = _start_basis(eng, var, guess)
    sol = None
    how = ""
    if method == "pivoting":
        sol = principal_pivoting(M, q, start)
        eng.counters["pivots"] += sol.pivots
        how = "principal pivoting from the current scheme"
    if sol is None or not sol.solved:
        sol = lemke(M, q)
        eng.counters["lemke"] += 1
        how = "Lemke's method from the stuck scheme"
    if not sol.solved and method == "lemke":
        sol, how = _lemke_fallback(eng, M, q, start, sol)
    if sol.solved:
        z = sol.z
        active = z > 1e-9 * max(np.abs(z).max(initial=0), 1e-300)
        new = _states_from(eng, base, var, active, z)
        ds, dw = combine(z)  # (before a commit of the new scheme retires the base's factor)
        _check_mechanism(eng, new, forcing)
        out = RateOutcome(new, ds, dw, how, L)
        out.alternatives = _alternatives(eng, L, base, var, M, q, combine, out)
        return out
    # no solution found: the ray names a scheme; equilibrium is lost only with evidence
    ray = sol.ray if sol.ray is not None else np.zeros(nv, bool)
    trial = _states_from(eng, base, var, ray, np.ones(nv))
    try:
        eng.factor(trial, article=False)
        singular = False
    except MechanismError:
        singular = True
    if singular and eng.drives(trial, forcing):
        raise MechanismError(None, None, _admissible(eng, L, trial, forcing, normal_lim))
    found = _enumerate(eng, L, base, var, M, q)
    if not found:
        # the CFEs at their normal limit that the stuck scheme's rates pull apart separate
        # (a body whose last supports let go): a driven mechanism is a loss of equilibrium
        pulled = var.cfe[(var.kind == OPENING) & (q < 0)]
        if pulled.size:
            trial = base.copy()
            trial[pulled] = OPEN
            try:
                eng.factor(trial, article=False)
            except MechanismError:
                if eng.drives(trial, forcing):
                    raise MechanismError(None, None, _admissible(eng, L, trial, forcing,
                                                                 normal_lim)) from None
    if found:
        z = found[0]
        active = z > 1e-9 * max(np.abs(z).max(initial=0), 1e-300)
        new = _states_from(eng, base, var, active, z)
        ds, dw = combine(z)
        _check_mechanism(eng, new, forcing)
        out = RateOutcome(new, ds, dw, "enumeration of the LCP", L)
        out.alternatives = _alternatives(eng, L, base, var, M, q, combine, out)
        return out
    complete = _bases(eng, var) is not None
    names = {OPENING: "opens", 1: "slips +", -1: "slips −"}
    ray_text = ", ".join(
        f"CFE {int(k)} {names[int(v)] if fc < 0 else f'slips on facet {int(fc)}'}"
        for k, v, fc in zip(var.cfe[ray], var.kind[ray], var.facet[ray], strict=True)) or "none"
    raise RateProblemFailure(
        Status.RATE_PROBLEM, L,
        ("the rate problem has no solution: no scheme of these CFEs satisfies the contact "
         "conditions (every one checked); with this much friction the quasi-static path does "
         "not exist here" if complete else "the rate problem has no solution found") +
        f" (certificate: {sol.message}, along which {ray_text}; that scheme "
        f"{'is singular but the load does no work on it' if singular else 'is regular'})",
        certificate=trial[L])


def _responses(eng, fact, var, R: np.ndarray, ds0: np.ndarray, dw0: np.ndarray):
    """The base scheme's responses to the rate problem's variables (column j of ``R``: the
    relation right-hand sides of z_j = 1, nonzero in the rows of its CFE only).  Returns
    (``dS_at``: rows ↦ the force rates s' of every column in those rows (rows of the
    variables' CFEs), ``combine``: z ↦ the rates (s', w') of the base's load rates plus
    Σ z_j column j).

    Where the base scheme holds every variable's CFE by displacement rows only (S = 0 in its
    block, W regular: a stuck CFE on a rigid joint, w' = r), the columns are not solved in
    full: with y = t' = A⁻¹ b (b = R, scaled) and those rows' relations W w' = r,

        s'_R = y_R + D_R ŵ'_R = (A⁻¹)[R, R] b_R + D_R W⁻¹ r_R       (ĥ = e = 0)

    from the block (A⁻¹)[R, R] of the rows R of those CFEs (:meth:`SchemeFactor.solve_rows`,
    no pass over the inverse or over G), and the rates of a solution z by one solve of the
    combined right-hand side R z (one pass over each, its backward error checked as every
    solve's).  Otherwise (springs, a float32 scheme, fewer than ``RESPONSE_ROWS_MIN``
    columns) the columns are solved as a block (a pass over the inverse and G each)."""
    lay = eng.layout
    nv = R.shape[1]
    fact = fact._live() or fact
    rel = fact.rel
    cf = np.unique(var.cfe)
    Sb, Wb = rel.S[cf], rel.W[cf]
    if (nv >= RESPONSE_ROWS_MIN and not fact.owner.refine and not np.count_nonzero(Sb)
            and np.all(np.abs(np.linalg.det(Wb)) > 0)):
        rr = lay.rows(cf).T.ravel()  # the CFEs' rows, component-major
        pos = np.full(lay.n, -1)
        pos[rr] = np.arange(len(rr))
        Rr = R[rr]
        Y = fact.solve_rows(rr, fact.scale[rr, None] * Rr)
        # w' of each column's CFE from its relations W w' = r (column j: var.effect[j] on
        # the rows of its CFE alone)
        at = np.searchsorted(cf, var.cfe)
        wj = np.einsum("jab,jb->ja", np.linalg.inv(Wb)[at], var.effect)
        dS_rows = Y
        cols = np.arange(len(var.cfe))
        d = fact.owner.d
        for c in range(lay.n_c):
            rc = c * len(cf) + at  # (positions in rr of component c of each column's CFE)
            dS_rows[rc, cols] += d[rr[rc]] * wj[:, c]
        zeros = lay.zeros()

        def combine(z):
            ds, dw = fact.solve(zeros, zeros, R @ z)
            return ds0 + ds, dw0 + dw

        return (lambda r: np.concatenate([ds0[r, None], dS_rows[pos[r]]], axis=1)), combine
    dS, dW = fact.solve(lay.zeros(1), lay.zeros(1), R)
    S0 = np.concatenate([ds0[:, None], dS], axis=1)
    return (lambda r: S0[r]), (lambda z: (ds0 + dS @ z, dw0 + dW @ z))


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    """``np.array_equal`` of two state arrays, without its conversions (once per point)."""
    return a.shape == b.shape and not np.count_nonzero(a != b)


def _lemke_fallback(eng, M, q, start, failed):
    """With ``rate_solver="lemke"``: Lemke's method ended without a solution (a secondary
    ray — its M is not copositive-plus at a point where CFEs sit at every limit, e.g. the
    slip rates a⁺, a⁻ of one CFE have opposite columns) — so the default solver, principal
    pivoting from the current scheme, takes over.  Counted in ``counters["lemke_fallbacks"]``
    and named in the outcome's method.  Returns (solution, how); Lemke's own outcome (with
    its ray, the certificate) when the pivoting fails too."""
    sol = principal_pivoting(M, q, start)
    eng.counters["pivots"] += sol.pivots
    eng.counters["lemke_fallbacks"] = eng.counters.get("lemke_fallbacks", 0) + 1
    if not sol.solved:
        return failed, "Lemke's method from the stuck scheme"
    return sol, f"principal pivoting from the current scheme, after {failed.message}"


def _core_outcome(eng, L: np.ndarray, guess: np.ndarray, forcing, normal_lim, two_sided,
                  method: str, guess_rates) -> RateOutcome | None:
    """The rate problem of the point's core only, if its solution is consistent for all of L;
    else None (the whole problem decides).

    L holds every slipping CFE, since any of them may stick when others change; in a large
    joint that is hundreds of CFEs in mid-slip, whose stuck scheme (the base of the whole
    problem) is that many rows from the current one.  The core is the rest of L: the CFEs
    that fired (the guess changes them), the closed ones that are not slipping and those at a
    normal or two-sided limit.  Its problem keeps the others in their (slipping) states; its
    solution is taken when the rates of that scheme leave every CFE of L in its state (the
    test of a kept scheme); the CFEs they leave out of their states join the core and its
    problem is solved again (at most :data:`CORE_ROUNDS` times, while the core is at most
    half of L).  A mechanism or a failure of the core problem is left to the whole problem,
    which may stick a slipping CFE.  A P-matrix problem
    has one solution, which this is; where the whole problem has several, this is the one
    that keeps the mid-slip CFEs slipping (as the whole problem's start from the guessed
    scheme aims to)."""
    one = _one_law(eng)
    states = eng.states
    sl = (one.slip_mask(states) if one is not None and hasattr(one, "slip_mask")
          else slipping(states))
    core = L[(guess[L] != states[L]) | ~sl[L] | normal_lim[L] | two_sided[L]]
    for _ in range(CORE_ROUNDS):
        if not 0 < core.size <= len(L) // 2:
            return None
        try:
            out = solve_rate_problem(eng, core, guess, forcing, normal_lim, two_sided, method,
                                     guess_rates)
        except (MechanismError, RateProblemFailure):
            return None
        cons = eng.consistent(out.states, L, out.ds, out.dw, normal_lim, two_sided)
        off = cons != out.states[L]
        if not np.count_nonzero(off):
            return out
        core = np.union1d(core, L[off])  # (the CFEs its rates leave out of their states)
    return None


def _slipping_only(eng, L: np.ndarray, normal_lim, two_sided) -> bool:
    """Are all CFEs of L slipping and none at a normal or two-sided limit?  (Then a consistent
    current scheme is the only one: a slip that goes on is not a degenerate point.)"""
    one = _one_law(eng)
    sl = (one.slip_mask(eng.states) if hasattr(one, "slip_mask") else slipping(eng.states))[L]
    return bool(np.count_nonzero(sl) == len(L)
                and not np.count_nonzero(normal_lim[L] | two_sided[L]))


def _singular_point(eng, L, guess, forcing, normal_lim, two_sided) -> RateOutcome:
    """The rate problem at a point whose stuck scheme is singular but not driven by the load
    (a body held at one point, loaded through it): every scheme of the CFEs in L is tried
    (small L), each with its unique rates, or its minimum-norm rates when it is singular and
    not driven.  A consistent scheme is followed; if there is none and one of the schemes is a
    mechanism the load drives, equilibrium is lost."""
    cfes = L[:ENUMERATE_CFES + 1]
    if len(L) > ENUMERATE_CFES:
        raise RateProblemFailure(Status.RATE_PROBLEM, L, "the stuck scheme of the point is "
                                 "singular but the load does no work on its free modes")
    # the tangential force rates of the stuck scheme (its indeterminate part split by the
    # CFEs' capacities): a faceted cone offers the slip states around their direction only
    hint = None
    if eng.layout.n_t > 1:
        stuck = _base_scheme(eng, L, guess)
        with contextlib.suppress(MechanismError):
            hint = eng.layout.tangential(eng.rates_redundant(stuck, forcing)[0])
    options = []
    for k in cfes:
        law = _law_of(eng, k)
        j = int(np.searchsorted(law.cfes, k))
        # (a closed CFE opens only from its normal limit, N = 0; a bond holds: its break is
        # the driver's)
        options.append(law.state_options(j, bool(normal_lim[k]), int(guess[k]),
                                         hint=None if hint is None else hint[k]))
    driven = None
    # the schemes closest to the guess first (a non-unique point continues the current scheme
    # with the natural transitions where it can: a rigid body stuck on two corners whose
    # friction is exhausted slips; it does not open a corner)
    # and the CFEs that share a self-stress (redundant rows: their relative motion is held by
    # the others) in one state before any split of them (one corner slipping at a zero rate
    # while the other sticks is admissible, but only an artefact of the indeterminate split)
    groups = _redundant_groups(eng, L, guess, cfes)

    for combo in _ordered_schemes(options, groups, guess[cfes]):
        trial = guess.copy()
        trial[cfes] = combo
        try:
            ds, dw = eng.rates(trial, forcing, article=False)
        except MechanismError:
            if eng.drives(trial, forcing):
                driven = trial if driven is None else driven
                continue
            ds, dw = eng.rates_redundant(trial, forcing)
        if np.array_equal(eng.consistent(trial, L, ds, dw, normal_lim, two_sided), trial[L]):
            return RateOutcome(trial, ds, dw, "enumeration of the schemes of a singular point", L)
    if driven is not None:
        raise MechanismError(None, None, _admissible(eng, L, driven, forcing, normal_lim))
    raise RateProblemFailure(Status.RATE_PROBLEM, L, "no consistent scheme at a point whose "
                             "stuck scheme is singular")


#: combinations of states keyed per block in :func:`_ordered_schemes`
_KEY_BLOCK = 1 << 20


def _ordered_schemes(options: list, groups: list[np.ndarray], guess: np.ndarray):
    """The schemes of :func:`_singular_point`: every combination of the CFEs' state
    ``options`` (the product, the last CFE's option varying fastest), ordered by (the number
    of redundant ``groups`` whose CFEs are not all in one state, the number of CFEs whose
    state differs from ``guess``), ties in product order — the order of a stable sort of
    ``itertools.product(*options)`` by that key, without forming it: the key of every
    combination is computed in vectorised blocks from its mixed-radix index (one byte each:
    34⁴ = 1.3 M combinations of a plate on 4 corners with 32 facets cost 0.1 s instead of a
    Python sort of 85 s), and the combinations are decoded one at a time, lowest key first,
    as they are tried."""
    opts = [np.asarray(o) for o in options]
    sizes = np.array([len(o) for o in opts], dtype=np.int64)
    total = int(np.prod(sizes))
    if total == 0:
        return
    strides = np.ones(len(opts), dtype=np.int64)
    strides[:-1] = np.cumprod(sizes[::-1])[::-1][1:]

    def decode(idx: np.ndarray) -> np.ndarray:
        return np.stack([o[(idx // st) % n] for o, st, n in zip(opts, strides, sizes, strict=True)],
                        axis=1)

    width = len(opts) + 1
    keys = np.empty(total, dtype=np.int16)
    for a in range(0, total, _KEY_BLOCK):
        cb = decode(np.arange(a, min(total, a + _KEY_BLOCK)))
        mixed = np.zeros(len(cb), dtype=np.int16)
        for g in groups:
            mixed += np.any(cb[:, g] != cb[:, g[:1]], axis=1)
        keys[a:a + len(cb)] = mixed * width + np.count_nonzero(cb != guess, axis=1)
    for k in np.unique(keys):
        for a in range(0, total, _KEY_BLOCK):
            for i in a + np.flatnonzero(keys[a:a + _KEY_BLOCK] == k):
                yield tuple(decode(np.array([i]))[0].tolist())


def _redundant_groups(eng, L, guess, cfes) -> list[np.ndarray]:
    """Positions in ``cfes`` of the CFEs that share a self-stress of the point's stuck scheme
    (:meth:`EventEngine.self_stress`), one array per group of two or more."""
    base = _base_scheme(eng, L, guess)
    Z = eng.self_stress(base)
    if Z.shape[1] == 0:
        return []
    ZQ, Zp = eng.layout.split(Z)
    aq = np.abs(ZQ) if eng.layout.n_t == 1 else np.abs(ZQ).sum(axis=1)
    on = (aq + np.abs(Zp))[cfes] > 1e-9  # (len(cfes), k)
    label = np.arange(len(cfes))
    for col in on.T:  # union of the supports of the modes (connected components)
        idx = np.flatnonzero(col)
        if idx.size > 1:
            label[np.isin(label, label[idx])] = label[idx].min()
    return [g for g in (np.flatnonzero(label == v) for v in np.unique(label)) if g.size > 1]


def _check_mechanism(eng, states, forcing) -> None:
    """A solution whose scheme is singular stands for a mechanism (its z grow without bound
    as the round-off of M → 0): equilibrium is lost when the load drives it."""
    try:
        eng.factor(states, article=False)
    except MechanismError:
        if eng.drives(states, forcing):
            raise MechanismError(None, None, states) from None


def _admissible(eng, L, states, forcing, normal_lim) -> np.ndarray:
    """The mechanism scheme as reported: a closed CFE at its normal limit that the driven
    mechanism would pull in tension (p' < 0 in the minimum-norm force rates of the singular
    scheme) separates instead, until none does (a block lifted off a base opens everywhere,
    rather than rotating about one corner that would have to hold it down)."""
    states = states.copy()
    for _ in range(len(L)):
        ds, _ = eng.rates_singular(states, forcing)
        tf = 1e3 * eng.rtol * max(np.abs(ds).max(initial=0), 1e-300)
        pull = L[(states[L] != OPEN) & normal_lim[L] & (eng.layout.normal(ds)[L] < -tf)]
        if pull.size == 0:
            break
        states[pull] = OPEN
    return states


def _frictional(eng, L) -> bool:
    one = _one_law(eng)
    if one is not None:
        return bool(np.count_nonzero(one.frictional[L]))
    return any(bool(law.frictional[np.isin(law.cfes, L)].any()) for law in eng.laws)


def _bases(eng, var: RateVariables) -> BasisGroups | None:
    """Complementary bases that stand for distinct CFE states (each law's
    :meth:`~stepcontact.contact.laws.ContactLaw.basis_options`: in 2D per CFE none (stick),
    slip+, slip−, opening alone, or opening with a slip rate), grouped for
    :func:`~stepcontact.solver.lcp.enumerate_solutions`; None when there are too many."""
    one = _one_law(eng)
    c = var.cfe
    if one is not None and len(c) and not np.count_nonzero(c[1:] < c[:-1]):
        # (variables by ascending CFE, as a Coulomb law gives them: groups without a sort)
        first = np.empty(len(c), bool)
        first[0] = True
        np.not_equal(c[1:], c[:-1], out=first[1:])
        cfes, group = c[first], np.cumsum(first) - 1
    else:
        cfes, group = np.unique(c, return_inverse=True)
    if len(cfes) > ENUMERATE_CFES:
        return None
    laws = [one] * len(cfes) if one is not None else [_law_of(eng, k) for k in cfes]
    # the bases depend only on which variables share a CFE, their kinds and facets and the
    # CFEs' laws: kept (read-only) for the next point with the same pattern
    key = (group.tobytes(), var.kind.tobytes(), var.facet.tobytes(), tuple(laws))
    cache = eng.__dict__.setdefault("_bases_cache", {})
    if key in cache:
        return cache[key]
    choices = []
    for j, law in enumerate(laws):
        idx = np.flatnonzero(group == j)
        opts = law.basis_options(var.kind[idx], var.facet[idx])
        choices.append([[int(idx[i]) for i in o] for o in opts])
    if np.prod([float(len(c)) for c in choices]) > ENUMERATE_BASES:
        out = None  # (a faceted cone's many facets: too many bases to try)
    else:
        rows = []
        for combo in itertools.product(*choices):
            b = np.zeros(len(var.cfe), bool)
            b[[i for part in combo for i in part]] = True
            rows.append(b)
        out = BasisGroups(np.array(rows))
    cache[key] = out
    if len(cache) > 64:
        del cache[next(iter(cache))]
    return out


def _enumerate(eng, L, base, var, M, q, bases=None) -> list[np.ndarray]:
    bases = _bases(eng, var) if bases is None else bases
    if bases is None:
        return []
    return enumerate_solutions(M, q, bases)


def _alternatives(eng, L, base, var, M, q, combine, chosen: RateOutcome) -> list[np.ndarray]:
    """Other admissible schemes of a small rate problem with several solutions (none when M is
    positive definite: a P-matrix has exactly one); ``combine``: z ↦ the rates of a solution
    (:func:`_responses`)."""
    bases = _bases(eng, var)
    if bases is None:  # too many CFEs to enumerate: nothing to report
        return []
    sym = 0.5 * (M + M.T)
    try:
        if np.linalg.eigvalsh(sym).min() > 1e-10 * max(np.abs(M).max(initial=0), 1e-300):
            return []
    except np.linalg.LinAlgError:
        pass
    sols = _enumerate(eng, L, base, var, M, q, bases)
    if len(sols) < 2:
        return []
    scale = max(np.abs(chosen.ds).max(initial=0), 1e-300)
    seen = [chosen.ds]
    out = []
    for z in sols:
        ds = combine(z)[0]
        if any(np.abs(ds - s).max() <= 1e-7 * scale for s in seen):
            continue
        seen.append(ds)
        active = z > 1e-9 * max(np.abs(z).max(initial=0), 1e-300)
        out.append(_states_from(eng, base, var, active, z)[L])
    return out


__all__ = ["RateOutcome", "RateProblemFailure", "solve_rate_problem"]
