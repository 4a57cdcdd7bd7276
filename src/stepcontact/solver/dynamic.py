"""The dynamic driver (method.md §4, article eqs. (7)–(10)): Newmark's average acceleration
between events, on the event engine.

Equation of motion (7) with the contact forces s = [Q; p] of the CFEs:

    M ü + C u̇ + K u + Bᵀ s = F(t)

Newmark (β = 1/4, γ = 1/2): over a step Δt, u_{n+1} = u_n + Δt u̇_n + Δt²/4 (ü_n + ü_{n+1}),
u̇_{n+1} = u̇_n + Δt/2 (ü_n + ü_{n+1}), so the end of the step solves the *static* problem

    K̂ u_{n+1} + Bᵀ s_{n+1} = F̂,   K̂ = K + 4M/Δt² + 2C/Δt,
    F̂ = F(t_{n+1}) + M (4u_n/Δt² + 4u̇_n/Δt + ü_n) + C (2u_n/Δt + u̇_n).

K̂ is factorised and condensed to the 2m contact unknowns once (the static condensation with
K̂ for K₀: Ĝ = B K̂⁻¹ Bᵀ); every step costs one solve for F̂ and the contact problem at the
step's end.  That contact problem is solved *exactly* by the event engine along the step: the
contact unknowns move from the start of the step (μ = 0) to its end (μ = 1) under the step's
increment of the free response, with the working scheme switched at every event met on the
way — the linear interpolation of eq. (10) between the step's ends, so each event's time is
t̂ = t_n + μ̂ Δt (the article's interpolation, second order in Δt).

Contact conditions in velocities (eq. (9)): a stuck CFE has no slip *velocity* at the end of
the step, u̇_τ,n+1 = 2 Δu_τ / Δt − u̇_τ,n = 0, i.e. Δu_τ = Δt u̇_τ,n / 2.  The engine works with
the slip beyond that drift, ũ_τ = u_τ − μ Δt u̇_τ,n / 2, so that stick is ũ_τ' = 0 as in
statics, and the sign of ũ_τ' is the sign of the slip velocity at the end of the step: the
engine's consistency check (slip in the direction of the friction force, slip → stick when it
would reverse) is then Coulomb's law in velocities.  Closed rigid contact holds u_n = 0 at the
end of the step; a CFE that closes during a step is an impact (Newton's law, restitution e:
the step is cut there, the velocities jump by the impulses, and a CFE that leaves the obstacle
with e > 0 opens at that instant).

Events inside a step (eq. (10)): the step is cut at the event time, the state there
interpolated linearly between the step's start and its end under the old scheme (the
expansion (8) in powers of the part step amplifies the stiff modes of a continuum at every
cut; the linear interpolation, a convex combination of two Newmark states, does not), the
scheme switched (an impact's velocities jump, forces that jump are resolved in
accelerations, the state is projected onto the new scheme's constraints), and the
integration restarts there with the same K̂ — no refactorisation.
Steps land on the breaks of the time functions (a pulse's start and end) and on the end of the
interval: a step that would pass one is a whole step of Δt (the load's rate over the part
before the break continued to its end) cut at the break like at an event — the state there
the convex combination of the step's ends, which has no more energy than they (a Newmark
step conserves it), so the landing gains no energy (the ledger books what it removes as
numerical); the load's jump at the break follows in accelerations.  (Newmark's β, γ scaled by
(Δt/h)², Δt/h for a short step h keep K̂ too, but change the energy by O(Δt² ü·Mü): a gain
where the accelerations jump.)  No step ever refactorises.

Water in opened joints (:class:`~stepcontact.model.CrackWater`, :mod:`stepcontact.fem.crack`):
on the wet CFEs the force W = A (p_c − p_u) is a load −Bᵀ [0; W] that follows its patterns'
time functions; where a CFE opens (closes) the step is cut there, as at any event, and the
load jumps at that instant — followed like a pulse's edge, the contact forces with it; a CFE
that opens under the jump is wet in turn.  The pressure in the gap thus follows the opened
length in time.  That is the choice ``crack_water="full"`` of the interval; ``"unchanged"``
holds the wet set and pressures the interval starts from, ``"none"`` holds them and puts no
pressure in the joints the motion opens (:class:`~stepcontact.model.DynamicInterval`,
:meth:`_DynamicRun._held_water`; issue 29 §1).

Joints with initial strength (eq. (12), :class:`~stepcontact.model.Bond`): a bonded CFE
carries tension and shear (no relative motion, or its layer's compliance) inside its strength
surface; the surface's facets are event functions like the others, so the step is cut at the
time a bond reaches it (eq. (10)) and the bond breaks there into its Coulomb state (open in
tension, else stuck or slipping).  What it can no longer carry is released at that instant:
with rigid contact the contact forces re-solve in accelerations at fixed t — the released
forces go to zero along a jump followed by the engine, and a bonded neighbour that reaches its
strength on the way breaks in turn (a cascade at one t, each break an event ``broken`` in its
order); with a compliant layer the layer's force drops (the forces follow the displacements,
nothing else jumps).  An impact on a body held by intact rigid bonds is carried by them (their
impulses are two-sided).

Friction in time (eqs. (9), (10)): a slip stops at the zero of its slip velocity inside the
step — for a compliant tangential layer (Jenkins: C_τ in series with the slider, eq. (11)),
whose row carries no drift, the velocity u̇_τ − Q̇/C_τ at the step's end from Newmark's
u̇_end = c₁ Δu_τ + c_v u̇_τ + c_a ü_τ (the engine alone sees the step's mean slip rate, a
stop half a step to a step late).  A rigid CFE that stops has its friction force re-solved in
accelerations at that instant (equilibrium at fixed t, |Q| ≤ f p; the forces of compliant
CFEs, which follow their displacements, held), also when the stop is decided at a step's
start; a stop that those forces undo (the slip goes on the same way) is no event.  A CFE
that opens or starts to slip inside a step is switched by the rate problem of the step that
starts at that instant (its forces are continuous there): the part step's rates, a chord of
the whole step, need not be those of the motion after the cut, and would switch it back at
once — a grazing corner's zero-duration chatter.

Two tangential components per CFE (3D, the faceted cone of
:class:`~stepcontact.contact.faceted.FacetedCoulombLaw`): the same driver with the contact
unknowns in blocks of 1 + 2 components.  A slip's rate is taken along its slip direction (a
facet's normal d_i, a vertex's bisector), and a vertex slip that turns onto one of its facets
does so where the other facet's slip rate (v = λ_a d_a + λ_b d_b) vanishes — both linear in
time over the step, as the 2D slip velocity, and its friction force is re-solved in
accelerations there; in a jump in accelerations a stuck rigid CFE whose force leaves the
polygon slips at the polygon's point nearest to it, a slip whose force runs past the end of
its facet at that vertex; an impact's tangential
impulses lie in the cone |T| ≤ f P, and a CFE sliding after it slips on the facet or at the
vertex whose normal cone holds its velocity.

Energy ledger (exact for this Newmark: the trapezoidal rule of every work term): kinetic
½ u̇ᵀMu̇, strain ½ uᵀKu (+ the contact layers' ½ s·C⁻¹s), work of the loads Σ Δuᵀ F̄, dissipated
by damping Σ Δuᵀ C ū̇, by friction Σ −Q̄ Δu_τ, in the normal contact Σ −p̄ Δu_n and the
impacts' velocity jumps, released by broken bonds ("fracture": the elastic energy ½ s²/C a
compliant bonded layer loses with the force it drops; a rigid bond stores none), and by the
integrator itself ("numerical": what the interpolation of cut steps removes; Newmark's whole
steps conserve energy); the balance error is what is left (round-off).  A cut at θ of a step
books θ times the works of the whole step under the old scheme: its state is the same convex
combination of the step's ends, whose energy (convex) lies below — the cut removes
½ θ (1 − θ) of the energy norm of the step's increment and never adds (the trapezoids over
the part step would miss the curvature of the contact forces' work along it: a friction
force that falls to zero at the cut, where a CFE opens, booked as a gain of energy).
"""

from __future__ import annotations

import dataclasses
import functools
import operator
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from stepcontact.contact.laws import BONDED, OPEN, SLIP_NEG, SLIP_POS, STICK, CoulombLaw
from stepcontact.contact.layout import ContactLayout
from stepcontact.enums import FACET_SLIP, VERTEX_SLIP, Status
from stepcontact.enums import slipping as _slipping
from stepcontact.errors import ModelError
from stepcontact.fem.assembly import System, assemble, dashpots
from stepcontact.model.structure import check_crack_water
from stepcontact.model.timefunction import MASS_KINDS, MAX_STEPS, check_interval, check_newmark
from stepcontact.results.build import build_result, cfe_arrays, stage_fields
from stepcontact.results.recorder import Recorder
from stepcontact.results.result import (
    ENERGY_TERMS,
    DynamicResult,
    Multipliers,
    StaticResult,
)
from stepcontact.solver.bonds import break_bonds as _break_bonds
from stepcontact.solver.bonds import breaking
from stepcontact.solver.clock import Stopwatch
from stepcontact.solver.condensation import Condensed
from stepcontact.solver.contactlaws import contact_law, law_inputs
from stepcontact.solver.engine import Decision, EventEngine
from stepcontact.solver.eventlog import EventLog
from stepcontact.solver.jump import AGAIN, JumpState, follow_jump
from stepcontact.solver.rate import RateProblemFailure
from stepcontact.solver.recovery import Stresses as _Stresses
from stepcontact.solver.recovery import stage_plan
from stepcontact.solver.reporting import VIOLATION_LIMIT, result_geometry
from stepcontact.solver.schemes import MechanismError, SchemeSolver
from stepcontact.solver.staging import in_stages


def _after_stages(system: System, initial, stage: int | None = None):
    """A dynamic interval after construction stages (:mod:`stepcontact.solver.staging`): the
    last stage's (or stage ``stage``'s) system (its held DOFs, shifted w⁰ of the interfaces
    made at once, removed supports gone, automatic patterns), the stage plan and the stage
    the contact law is built at (:func:`~stepcontact.solver.contactlaws.contact_law`: CFEs not
    active are inert; bonds of grouted joints) and ``initial``, the static result of
    the stages it starts from, which must hold its run's stages
    (:func:`~stepcontact.solver.recovery.stage_plan`): :func:`stepcontact.solve_dynamic`
    runs the staged program when none is given, and again (checked against it) for a result
    loaded from a file (which does not keep the stage systems).

    Returns (system, (plan, stage), initial, stage arrays of the result)."""
    plan = stage_plan(initial)
    if plan is None:
        raise ModelError("initial", "must be the result of the run of this model's stages "
                         "(solve_static(model)): stepcontact.solve_dynamic runs them when it "
                         "is not given")
    last = len(plan.names) - 1 if stage is None else int(stage)
    if initial.status != Status.COMPLETED or int(initial.stage[-1]) != last:
        raise ModelError("initial", f"the static run of the stages stopped in stage "
                         f"'{plan.names[int(initial.stage[-1])]}' ({initial.message}): the "
                         "dynamic interval follows the segments of stage "
                         f"'{plan.names[last]}'")
    stage_system = plan.system(last)
    i = len(initial.lam) - 1
    for j, name in enumerate(initial.pattern_names):
        lv = stage_system.loads[name]
        if initial.factors[i][j] != 0.0 and np.any(lv.u != 0.0):
            raise ModelError(f"pattern '{name}'", "prescribes nonzero displacements at the "
                             "end of the stages: a dynamic interval does not follow "
                             "prescribed displacements (place the support before its body "
                             "moves, or let the pattern return to 0)")
    arrays = {"stage_names": initial.stage_names, "stage_cfes": initial.stage_cfes,
              "stage_bodies": initial.stage_bodies, "last_stage": last}
    return stage_system, (plan, last), initial, arrays


def _initial(system: System, cond: Condensed, initial, u0, v0):
    """(u, v, s, w, states, static factors) at t = 0."""
    ndof, m, lay = system.ndof, system.m, system.layout
    u = np.zeros(ndof)
    s = lay.zeros()
    w = system.w0.copy()
    states = np.full(m, OPEN, np.int64)
    static: dict[str, float] = {}
    if initial is not None:
        i = len(initial.lam) - 1
        u = np.asarray(initial.displacement(i), float).copy()
        s = lay.join(initial.Q[i], -initial.N[i])
        w = lay.join(initial.ut[i], initial.un[i])
        states = np.asarray(initial.state[i], np.int64).copy()
        static = {n: float(c) for n, c in zip(initial.pattern_names, initial.factors[i],
                                               strict=True) if c != 0.0}
    if u0 is not None:
        u = np.asarray(u0, float).copy()
        w = system.B @ u + system.w0
    v = np.zeros(ndof) if v0 is None else np.asarray(v0, float).copy()
    if v.shape != (ndof,) or u.shape != (ndof,):
        raise ModelError("initial state", f"u0 and v0 must have {ndof} entries (the DOFs)")
    v[system.fixed] = 0.0
    return u, v, s, w, states, static


def _state_at_u0(system: System, law: CoulombLaw, u, v, s, w, states, initial):
    """The contact state at t = 0 given the displacements u0 (``u``, gaps w = B u0 + w⁰).

    Without ``initial``: a CFE whose gap is closed (−u_n ≤ 1e-9 of the displacement scale)
    and that does not separate (B_n v0 ≥ 0 to round-off) starts closed (stuck; frictionless:
    closed), the others open; a compliant layer closed carries its spring's force (p = C_n
    u_n, Q = C_τ u_τ, slipping at f p where it is beyond the cone).  The forces of rigid
    contacts are not known from u0: they are the solution of the contact problem in
    accelerations under the loads at t = 0 (M ü + Bᵀ s = F(0) − K u0 − C v0, the rate
    problem at that instant, solved by the driver), the definition of the initial state, not
    events.  A rigid CFE penetrating its obstacle beyond that tolerance is refused.

    With ``initial``: its contact states and forces are kept; every rigid CFE closed there
    must be closed at u0 too (else ModelError: u0 is not the static result's displacement).
    Returns (states, s, w)."""
    lay = system.layout
    cfe = system.cfe
    w = w.copy()
    scale = max(float(np.abs(u).max(initial=0.0)), float(np.abs(w).max(initial=0.0)), 1e-300)
    tol = 1e-9 * scale
    wn = lay.normal(w)  # a view of w
    rigid_n = ~np.isfinite(cfe.kn)
    live = ~law.inert
    if initial is not None:
        closed = (states != OPEN) & rigid_n & live
        bad = closed & (np.abs(wn) > 1e-6 * scale)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise ModelError("u0", f"is not the displacement of `initial`: CFE {k} of interface "
                             f"'{cfe.names[cfe.interface[k]]}', closed in the static result, "
                             f"has the gap {-wn[k]:.3g} m at u0 (give u0 equal to "
                             "initial.displacement(-1), or one of them)")
        wn[closed] = 0.0
        return states, s, w
    vn = lay.normal(system.B) @ v
    vtol = 1e-9 * max(float(np.abs(system.B @ v).max(initial=0.0)), 1e-300)
    deep = rigid_n & live & (wn > tol)
    if deep.any():
        k = int(np.flatnonzero(deep)[0])
        raise ModelError("u0", f"makes CFE {k} of interface '{cfe.names[cfe.interface[k]]}' "
                         f"penetrate its rigid obstacle by {wn[k]:.3g} m")
    touching = live & (wn >= -tol) & (vn >= -vtol)
    states = states.copy()
    states[touching] = law.closed_state()[touching]
    wn[touching & rigid_n] = 0.0
    s = s.copy()
    s_t, s_n = lay.split(s)  # views of s
    soft_n = touching & np.isfinite(cfe.kn)
    p = np.where(soft_n, np.where(soft_n, cfe.kn, 0.0) * np.maximum(wn, 0.0), 0.0)
    s_n[:] = np.where(soft_n, p, s_n)
    soft_t = soft_n & np.isfinite(cfe.kt)
    if lay.n_t > 1:  # a faceted cone (3D): beyond the polygon, slipping at its nearest point
        kt = np.where(soft_t, cfe.kt, 0.0)[:, None]
        q = np.where(soft_t[:, None], kt * lay.tangential(w), 0.0)
        at = law.state_at(q, p)
        over = soft_t & law.frictional & _slipping(at)
        q = q - np.where(over[:, None], law.released(at, q, p)[0], 0.0)
        states[over] = at[over]
        s_t[:] = np.where(soft_t[:, None], q, s_t)
        return states, s, w
    q = np.where(soft_t, np.where(soft_t, cfe.kt, 0.0) * lay.tangential(w), 0.0)
    lim = law.f * p
    over = soft_t & law.frictional & (np.abs(q) > lim)
    q = np.where(over, np.sign(q) * lim, q)
    states[over] = np.where(q[over] > 0, SLIP_POS, SLIP_NEG)
    s_t[:] = np.where(soft_t, q, s_t)
    return states, s, w


@dataclass(frozen=True)
class _Newmark:
    """Coefficients of one step of length h of the HHT-α family (α = 0: Newmark's average
    acceleration, β = 1/4, γ = 1/2; α ∈ (0, 1/3]: β = (1 + α)²/4, γ = 1/2 + α, numerical
    damping of the high frequencies, spectral radius (1 − α)/(1 + α) at ω h → ∞).

    a₁ = c0 Δu − c2 v₀ − c3 a₀,  v₁ = c1 Δu + cv v₀ + ca a₀,
    M a₁ + (1 − α)(C v₁ + K u₁) + α (C v₀ + K u₀) + Bᵀ s₁ = (1 − α) F₁ + α F₀."""

    h: float
    alpha: float = 0.0
    #: Δt / h ≥ 1 for a step shorter than Δt made with Δt's K̂: β and γ scaled by stretch² and
    #: stretch keep c0 = 1/(βh²) and c1 = γ/(βh), hence K̂ (not used by the driver, whose
    #: short steps are cuts of whole steps: this one can gain energy where ü jumps)
    stretch: float = 1.0

    @functools.cached_property
    def beta(self) -> float:
        return (1 + self.alpha) ** 2 / 4 * self.stretch**2

    @functools.cached_property
    def gamma(self) -> float:
        return (0.5 + self.alpha) * self.stretch

    @functools.cached_property
    def c0(self) -> float:
        return 1.0 / (self.beta * self.h**2)

    @functools.cached_property
    def c1(self) -> float:
        return self.gamma / (self.beta * self.h)

    @functools.cached_property
    def c2(self) -> float:
        return 1.0 / (self.beta * self.h)

    @functools.cached_property
    def c3(self) -> float:
        return 1.0 / (2 * self.beta) - 1.0

    @functools.cached_property
    def cv(self) -> float:
        return 1.0 - self.gamma / self.beta

    @functools.cached_property
    def ca(self) -> float:
        return self.h * (1.0 - self.gamma / (2 * self.beta))

    def stiffness(self, K, M, C):
        return (self.c0 * M + (1 - self.alpha) * (self.c1 * C + K)).tocsr()

    def rhs(self, K, M, C, F1, F0, u, v, a):
        """F̂ (the right-hand side of K̂ u₁ = F̂ − Bᵀ s₁); C without entries (``C.empty``, a
        :class:`_Memo`): no damping terms formed."""
        al = self.alpha
        damped = not getattr(C, "empty", False)
        # ((1 − α) F₁ is F₁ itself for α = 0; the mass product is no state's: not kept)
        Mh = getattr(M, "apply", M.__matmul__)
        out = (F1 if al == 0 else (1 - al) * F1) + Mh(self.c0 * u + self.c2 * v + self.c3 * a)
        if damped:
            out = out + (1 - al) * (C @ (self.c1 * u - self.cv * v - self.ca * a))
        if al:
            out = out + al * ((F0 - C @ v if damped else F0) - K @ u)
        return out

    def end(self, u1, u, v, a):
        du = u1 - u
        return (self.c0 * du - self.c2 * v - self.c3 * a,
                self.c1 * du + self.cv * v + self.ca * a)

    def velocity(self, u1, u, v, a):
        """v₁ alone (as :meth:`end`)."""
        return self.c1 * (u1 - u) + self.cv * v + self.ca * a

    def drift(self, wdot, wacc):
        """Δw that makes the end velocity zero: −(cv ẇ₀ + ca ẅ₀)/c1."""
        return -(self.cv * wdot + self.ca * wacc) / self.c1


_MAXIMUM = np.maximum.reduce
#: the ledger's terms in the order of ENERGY_TERMS (a recorded state's row)
_LEDGER_ROW = operator.itemgetter(*ENERGY_TERMS)


def _absmax(x) -> float:
    """max |x| over every entry (0 for an empty x): ``float(np.abs(x).max(initial=0.0))``
    without its Python-level wrapper (several per step)."""
    return float(_MAXIMUM(np.abs(x), axis=None, initial=0.0))


#: a model whose contact matrix B has at most this many entries (2m × n, zeros included)
#: makes the step's products with B densely
DENSE_PRODUCTS = 4096


class _Diagonal:
    """M⁻¹ of a lumped (diagonal) mass matrix: a division, not a sparse LU's solve."""

    def __init__(self, M):
        d = M.diagonal()
        if np.any(d <= 0):
            raise RuntimeError("a zero or negative diagonal entry")
        self.inv = 1.0 / d

    @staticmethod
    def fits(M) -> bool:
        return M.nnz == np.count_nonzero(M.diagonal())

    def solve(self, b: np.ndarray) -> np.ndarray:
        b = np.asarray(b)
        return b * (self.inv if b.ndim == 1 else self.inv[:, None])


def _direct_solve(factor):
    """``factor.solve`` — for a small model's dense Cholesky factor (the ``dense`` backend of
    :mod:`stepcontact.solver.linalg`) LAPACK's ``potrs`` on its factor called directly: the
    same computation as SciPy's ``cho_solve`` without its checks and dispatch, which cost
    more than the solve itself on a model of a few DOFs (every step makes two)."""
    import scipy.linalg as sla

    cf = getattr(factor, "cf", None)
    if getattr(factor, "name", "") != "dense" or not isinstance(cf, tuple) or len(cf) != 2:
        return factor.solve
    c, lower = cf
    potrs = sla.get_lapack_funcs("potrs", (c,))

    def solve(b: np.ndarray) -> np.ndarray:
        x, info = potrs(c, np.asarray(b, dtype=float), lower=lower, overwrite_b=False)
        if info != 0:
            return factor.solve(b)
        return x

    return solve


def _spd_factor(W: np.ndarray):
    """b ↦ x with W x = b for a small symmetric positive semi-definite W (B_r M⁻¹ B_rᵀ):
    Cholesky, or the least-squares (minimum-norm) solution where W is singular (rows that
    depend on each other, e.g. at a corner; a pivot below 1e-12 of the largest diagonal).
    The factor is formed once: the returned function solves for any b."""
    import scipy.linalg as sla

    if W.size == 0:
        return lambda b: np.zeros(0)
    try:
        c = sla.cho_factor(W, check_finite=False)
        if np.diag(c[0]).min() ** 2 > 1e-12 * np.diag(W).max():  # not nearly singular
            return lambda b: sla.cho_solve(c, b, check_finite=False)
    except np.linalg.LinAlgError:
        pass
    return lambda b: np.linalg.lstsq(W, b, rcond=None)[0]


def _spd_solve(W: np.ndarray, b: np.ndarray) -> np.ndarray:
    """x with W x = b for a small symmetric positive semi-definite W (:func:`_spd_factor`)."""
    return _spd_factor(W)(b)


@functools.cache
def _lapack(name: str):
    """LAPACK's float64 routine ``name`` (SciPy's wrapper, looked up once)."""
    import scipy.linalg as sla

    return sla.get_lapack_funcs(name, (np.zeros((1, 1)),))


class _TrackedFactor:
    """The Cholesky factor L Lᵀ = W_r of W_r = B_r M⁻¹ B_rᵀ (a principal block of GM) for a
    row set r that changes by a few rows between uses (the closed and stuck rows of the
    projection after a cut, :func:`_project`), updated instead of formed again:

    * rows that leave: with p the first of them in the factor's order, the leading block
      L₁₁ (p × p) and the rows of L below it on its columns stay; the trailing block is the
      Cholesky factor of W₂₂ − L₂₁ L₂₁ᵀ on the rows that remain after p;
    * rows that join are appended: L₂₁ = (L₁₁⁻¹ W₁₂)ᵀ, L₂₂ = chol(W₂₂ − L₂₁ L₂₁ᵀ)

    — O(r² k) for k rows joining at the end (and O((r − p)² r) where rows leave at p), against
    O(r³) for a new factor; an unchanged set reuses the factor as it is.  A set whose factor
    has a pivot below the criterion of :func:`_spd_factor` (rows that depend on each other)
    is solved as there (least squares on W_r) and the tracking starts again from the next
    set."""

    def __init__(self, GM: np.ndarray):
        self.GM = GM
        self.diag = np.ascontiguousarray(np.diag(GM))
        self.order: np.ndarray | None = None  # the rows of r in the factor's order
        self.L = np.zeros((0, 0))
        self.pos = np.full(len(GM), -1, np.int64)  # row → its place in ``order`` (or −1)
        self.singular: tuple[bytes, object] | None = None  # (set, solver) of a singular W_r

    def _regular(self, L: np.ndarray, rows: np.ndarray) -> bool:
        """:func:`_spd_factor`'s criterion: no pivot below 1e-12 of the largest diagonal."""
        return bool(np.diag(L).min() ** 2 > 1e-12 * self.diag[rows].max())

    def _set(self, order: np.ndarray, L: np.ndarray) -> None:
        if self.order is not None:
            self.pos[self.order] = -1
        self.order, self.L = order, L
        self.pos[order] = np.arange(len(order))

    @staticmethod
    def _cholesky(S: np.ndarray) -> np.ndarray | None:
        """The lower Cholesky factor of S (a temporary, overwritten), or None where S is not
        positive definite: LAPACK's potrf as ``scipy.linalg.cholesky`` calls it, without its
        checks (a cut makes two)."""
        if S.size == 0:
            return np.zeros((0, 0))
        c, info = _lapack("potrf")(S, lower=1, overwrite_a=1, clean=1)
        return c if info == 0 else None

    def _factor(self, rows: np.ndarray) -> bool:
        """A new factor of W_r (rows in the order given); False where it is singular."""
        L = self._cholesky(self.GM[rows[:, None], rows])
        if L is None:
            return False
        if not self._regular(L, rows):
            return False
        self._set(rows.copy(), L)
        return True

    def _update(self, rows: np.ndarray) -> bool:
        """The factor of the set ``rows`` from the current one (class docstring); False where
        the result is singular."""
        import scipy.linalg as sla

        order, L, GM = self.order, self.L, self.GM
        stays = np.zeros(len(GM), bool)
        stays[rows] = True
        kept = stays[order]
        added = rows[self.pos[rows] < 0]
        all_kept = bool(kept.all())
        if all_kept and not added.size:
            return True  # the same set
        p = int(np.argmin(kept)) if not all_kept else len(order)
        head, tail_kept = order[:p], order[p:][kept[p:]]
        L21 = L[p:, :p][kept[p:]]
        if added.size:
            L21_add = (sla.solve_triangular(L[:p, :p], GM[head[:, None], added], lower=True,
                                            check_finite=False).T if p
                       else np.zeros((len(added), 0)))
            L21 = np.vstack([L21, L21_add])
        tail = np.concatenate((tail_kept, added)).astype(np.int64, copy=False)
        L22 = self._cholesky(GM[tail[:, None], tail] - L21 @ L21.T)
        if L22 is None:
            return False
        r = p + len(tail)
        Ln = np.zeros((r, r), order="F")  # (LAPACK's order: its solves do not copy it)
        Ln[:p, :p] = L[:p, :p]
        Ln[p:, :p] = L21
        Ln[p:, p:] = L22
        new_order = np.concatenate((head, tail)).astype(np.int64, copy=False)
        if not self._regular(Ln, new_order):
            return False
        self._set(new_order, Ln)
        return True

    def solve(self, rows: np.ndarray, b: np.ndarray) -> np.ndarray:
        """λ with W_r λ = b (``b`` in the order of ``rows``)."""
        import scipy.linalg as sla

        rows = np.asarray(rows, dtype=np.int64)
        if rows.size == 0:
            return np.zeros(0)
        done = self.order is not None and self._update(rows)
        if not done:
            done = self._factor(rows)
        if not done:  # singular (dependent rows): least squares, as _spd_factor
            if self.order is not None:  # the tracking starts again from the next set
                self.pos[self.order] = -1
                self.order, self.L = None, np.zeros((0, 0))
            key = rows.tobytes()
            if self.singular is None or self.singular[0] != key:
                self.singular = (key, _spd_factor(self.GM[np.ix_(rows, rows)]))
            return self.singular[1](b)
        at = self.pos[rows]
        bo = np.zeros(len(self.order))
        bo[at] = b
        # (LAPACK's potrs on the factor, as cho_solve calls it, without its checks)
        x, info = _lapack("potrs")(self.L, bo, lower=True)
        if info != 0:
            return sla.cho_solve((self.L, True), bo, check_finite=False)[at]
        return x[at]


class _ContactMetric:
    """The contact rows in the metric of the mass matrix: X = M⁻¹ B_fᵀ (n_free × 2m, formed
    once: 2m solves with M, or a scaling of Bᵀ for a lumped M) and GM = B_f M⁻¹ B_fᵀ (2m × 2m)
    — for the impacts, the projection after a cut and the contact problem in accelerations.

    The projection after a cut (:func:`_project`) solves with W_r = B_r M⁻¹ B_rᵀ on the closed
    and stuck rows and on the closed ones; between cuts these sets change by a few CFEs or not
    at all, so their factors are kept and updated (:class:`_TrackedFactor`, one per set:
    ``tracked(name)``)."""

    def __init__(self, X, GM: np.ndarray, layout: ContactLayout, free: np.ndarray | None = None,
                 ndof: int | None = None):
        self.X, self.GM, self.layout = X, GM, layout
        #: X on all DOFs (zero rows on the held ones) where X is sparse (a lumped mass), by
        #: columns as X: the projection's corrections of the full fields in one product
        self.X_all = None
        if sp.issparse(X) and free is not None:
            Xc = X.tocsc()
            self.X_all = sp.csc_matrix((Xc.data, free[Xc.indices], Xc.indptr),
                                       shape=(int(ndof), X.shape[1]))
        self._tracked: dict[str, _TrackedFactor] = {}
        self.XtKX: np.ndarray | None = None  # (formed by the driver on first use)

    def apply(self, rows: np.ndarray, z: np.ndarray) -> np.ndarray:
        """M⁻¹ B_rᵀ z on the free DOFs (without copying columns of X)."""
        full = self.layout.zeros()
        full[rows] = z
        return self.X @ full

    def gram(self, rows: np.ndarray) -> np.ndarray:
        """W_r = B_r M⁻¹ B_rᵀ (a copy)."""
        return self.GM[np.ix_(rows, rows)]

    def tracked(self, name: str) -> _TrackedFactor:
        """The kept factor of the row set ``name`` (:class:`_TrackedFactor`)."""
        if name not in self._tracked:
            self._tracked[name] = _TrackedFactor(self.GM)
        return self._tracked[name]


class _Rows:
    """The recorded fields (u, u̇, ü) of a run, one (ndof,) row per state, in one buffer that
    is given to the result as it is: sized for the run's steps, grown (doubled) and trimmed
    at the end in place (``ndarray.resize``: the allocator remaps a large block rather than
    copying it), never copied whole — at 82k DOFs a copy of the three arrays of 758 states
    took about as long as 200 sparse solves."""

    #: the first buffer holds at most this many bytes (it grows by doubling beyond)
    FIRST_BYTES = 256 * 2**20

    def __init__(self, ndof: int, states: int = 64):
        rows = max(1, min(int(states), max(64, self.FIRST_BYTES // (8 * max(ndof, 1)))))
        self.buf: np.ndarray | None = np.empty((rows, ndof))
        self.n = 0

    def append(self, row: np.ndarray) -> None:
        buf = self.buf
        if self.n == len(buf):
            buf.resize((2 * len(buf), buf.shape[1]), refcheck=False)  # (no view of it lives)
        buf[self.n] = row
        self.n += 1

    def array(self) -> np.ndarray:
        """The (states, ndof) array; the buffer is handed over (no more rows after this)."""
        buf, self.buf = self.buf, None
        buf.resize((self.n, buf.shape[1]), refcheck=False)
        return buf


class _Memo:
    """A sparse matrix whose products with the last few vectors are kept (looked up by the
    arrays' identity: the driver never changes a state vector in place once formed), so that
    K u and M v are formed once per state for the step, the ledger and the records."""

    def __init__(self, A, keep: int = 6):
        self.A, self.keep = A, keep
        self._last: list[tuple[np.ndarray, np.ndarray]] = []
        #: a matrix without entries (no damping): its products are zero, not formed
        self.empty = A.nnz == 0
        self._zero = np.zeros(A.shape[0])
        self._zero.flags.writeable = False
        #: a diagonal matrix (a lumped mass): its product is a scaling (the same floats as
        #: the sparse product, 0 + d_i x_i, without its dispatch)
        self.diag = (A.diagonal() if not self.empty and A.shape[0] == A.shape[1]
                     and A.nnz == np.count_nonzero(A.diagonal()) else None)

    def __call__(self, x: np.ndarray) -> np.ndarray:
        if self.empty:
            return self._zero
        for xx, y in self._last:
            if xx is x:
                return y
        y = self.A @ x if self.diag is None else self.diag * x
        self._last.append((x, y))
        if len(self._last) > self.keep:
            self._last.pop(0)
        return y

    __matmul__ = __call__

    def apply(self, x: np.ndarray) -> np.ndarray:
        """A x, not kept (a vector that is no state's)."""
        if self.empty:
            return self._zero
        return self.A @ x if self.diag is None else self.diag * x


def _stick_times(eng, old, new, changed, forcing, w_start, wdot, mu, t, dt, c1=None,
                 nm=None, wacc=None, law=None, rates_of=None) -> dict:
    """Times of the slip → stick transitions decided at μ of a step (eq. (10), second row):
    where the slip velocity, linear in time over the step, would cross zero under the old
    (slipping) scheme — u̇_τ at the step's end is 2 Δũ_τ / Δt (module docstring) for a rigid
    tangential row; for a compliant one (Jenkins: C_τ in series with the slider, eq. (11)) the
    slip velocity is u̇_τ − Q̇/C_τ with Newmark's u̇_τ,end = c₁ Δu_τ + c_v u̇_τ + c_a ü_τ (the
    row carries no drift) and Q̇ = ΔQ/Δt (Q linear over the step)."""
    slipping = _slipping(old)
    ks = changed[slipping[changed] & (new[changed] != OPEN)]
    if eng.layout.n_t > 1:  # a faceted cone (3D): a stop, or a vertex slip onto one of its
        # facets (the other facet's slip rate vanishes) — not a slip whose force reaches a
        # vertex (an event of the forces, located by the engine)
        ks = ks[(new[ks] == STICK) | ((old[ks] >= VERTEX_SLIP) & _slipping(new[ks]))]
    if ks.size == 0:
        return {}
    try:
        ds_o, dw_o = (eng.rates_any if rates_of is None else rates_of)(old, forcing)
    except MechanismError:
        return {}
    v0, v_end = _slip_velocities(eng, ks, ds_o, dw_o, w_start, wdot, mu, dt, c1, nm, wacc, law,
                                 old, new)
    den = v0 - v_end
    with np.errstate(divide="ignore", invalid="ignore"):
        frac = np.where(np.abs(den) > 0, v0 / den, mu)
    frac = np.clip(np.nan_to_num(frac, nan=mu), mu, 1.0)
    return {int(k): t + float(f) * dt for k, f in zip(ks, frac, strict=True)}


def _slip_velocities(eng, ks, ds_o, dw_o, w_start, wdot, mu, dt, c1=None, nm=None, wacc=None,
                     law=None, states=None, new=None):
    """Slip velocities (m/s) of the CFEs ``ks`` at the start and at the end of the step under
    the rates (ds_o, dw_o) from μ on (see :func:`_stick_times`); with two tangential
    components (3D) the slip rates that vanish where ``states`` turn into ``new`` (default:
    a stop; :meth:`FacetedCoulombLaw.vanishing_rate` — along the slip direction, or a
    vertex's facet rate), linear in time as the velocities are."""
    r = eng.layout.tangential_rows[ks]  # the CFEs' tangential rows of s, w ((k, 2) in 3D)
    dw = eng.w[r] - w_start[r] + (1.0 - mu) * dw_o[r]
    v_end = (2.0 / dt if c1 is None else c1) * dw
    v0 = wdot[r].copy()
    if law is not None and nm is not None:
        soft = ~law.rigid_t[ks]
        if soft.any():
            kt = np.where(soft, law.kt[ks], 1.0)
            if r.ndim > 1:  # (two tangential components per CFE)
                soft, kt = soft[:, None], kt[:, None]
            # (Q̇ = Q'/Δt: Q' its rate along μ, constant under the scheme)
            q_rate = ds_o[r] / (kt * dt)
            v_end = np.where(soft, nm.c1 * dw + nm.cv * wdot[r] + nm.ca * wacc[r] - q_rate,
                             v_end)
            v0 = np.where(soft, v0 - q_rate, v0)
    if r.ndim > 1:  # a faceted cone (3D): the slip rates that vanish
        old = states[ks]
        to = np.full(len(ks), STICK) if new is None else new[ks]
        return (law.vanishing_rate(ks, old, to, v0), law.vanishing_rate(ks, old, to, v_end))
    return v0, v_end


def _compliant_stops(eng, law, dec, w_start, wdot, wacc, nm, dt) -> np.ndarray:
    """Compliant slipping CFEs (Jenkins element, eq. (11)) that the decision at a step's start
    keeps slipping but whose slip velocity reverses inside the step (eq. (10), second row):
    the engine sees the step's mean slip rate Δu_τ/Δt (a compliant row has no drift), which
    keeps its sign until the zero of the velocity lies in the first half of the step — the
    stop would be found a step late.  They stop at the zero (:func:`_stick_times`)."""
    sl = ~law.rigid_t & law.frictional
    if not sl.any():  # (rigid friction only)
        return np.zeros(0, np.int64)
    sl &= _slipping(dec.new)
    ks = np.flatnonzero(sl & (dec.old == dec.new))
    if ks.size == 0:
        return ks
    v0, v1 = _slip_velocities(eng, ks, dec.ds, dec.dw, w_start, wdot, 0.0, dt, None, nm, wacc,
                              law, dec.new)
    sg = np.where(dec.new[ks] == SLIP_NEG, -1.0, 1.0)  # (3D: the rates along the slip)
    tol = 1e-9 * max(float(np.abs(v0).max(initial=0.0)), float(np.abs(v1).max(initial=0.0)),
                     1e-300)
    return ks[(sg * v0 > tol) & (sg * v1 < -tol)]


def _quiet_start(eng: EventEngine, law, forcing, span: float, group: float):
    """The engine's decision at a step's start (:meth:`EventEngine.decide` without fired CFEs,
    not the start of the path) where it cannot change the scheme, or None: the same scheme
    with the same rates, from the same calls, without the rate problem's set-up.  Exact: no
    CFE has an event function within its tolerance of its limit, and the slipping ones (in
    mid-slip: at no normal or two-sided limit) have rates that keep them slipping — then the
    engine keeps the scheme too (``solve_rate_problem``: the current scheme stays consistent,
    a slip that goes on is not a degenerate point; the check is
    :meth:`EventEngine.consistent`'s).  ``law``: the one law of every CFE, in order.  Any
    other case (or a singular scheme) is the engine's (None).

    Returns (the decision, whether no event function reaches its limit along its rates
    within ``span`` and ``group`` beyond — :meth:`EventEngine.next_event` from this state,
    the same floats: it would return Δμ = span with nothing fired)."""
    eng.update_scales()  # (as EventEngine.at_limit)
    tf, tw = eng.tolerances()
    states = eng.states
    lay = eng.layout
    Q, p = lay.split(eng.s)
    un = lay.normal(eng.w)
    phi = law.event_values(states, Q, p, un)
    gap = law.column_kinds == 1
    if np.count_nonzero(phi <= np.where(gap, tw, tf)):
        return None  # a CFE at a limit: the rate problem decides
    L = np.flatnonzero(_slipping(states))
    if L.size:
        normal, two = law.limits(states, Q, p, un, tf, tw)
        if np.count_nonzero(normal[L]) or np.count_nonzero(two[L]):
            return None
    try:
        ds, dw = eng.rates(states, forcing, article=False)
    except MechanismError:
        return None
    dQ, dp = lay.split(ds)
    dut, dun = lay.split(dw)
    rf = 1e3 * eng.rtol * max(_absmax(ds), 1e-300)  # (the rates' tolerances, as the
    rw = 1e3 * eng.rtol * max(_absmax(dw), 1e-300)  # engine's consistent and next_event)
    if L.size and np.count_nonzero(law.consistent(states, Q, dQ, dp, dun, dut, normal, two,
                                                  rf, rw, p=p, tf=tf)[L] != states[L]):
        return None  # a slip that would stop here: the rate problem decides
    old = states.copy()
    eng.states = new = states.copy()
    dphi = law.event_values(new, dQ, dp, dun, False)
    active = np.isfinite(phi)
    active &= dphi < np.where(gap, -rw, -rf)
    if not np.count_nonzero(active):
        return Decision(old, new, ds, dw), True
    steps = np.full(phi.shape, np.inf)
    np.divide(np.maximum(phi, 0.0), np.negative(dphi), out=steps, where=active)
    return Decision(old, new, ds, dw), not float(steps.min()) <= span + group


def _vertex_stops(eng, law, dec, w_start, wdot, wacc, nm, dt) -> np.ndarray:
    """CFEs slipping at a vertex of a faceted cone (3D) that the decision at a step's start
    turns onto one of its facets while their slip velocity at the step's end vanishes (below
    1e-9 of the start's, eq. (10): the two facets' slip rates are both round-off there, and
    round-off picked the facet): they stop at the step's end (:func:`_stick_times`)."""
    ks = np.flatnonzero((dec.old >= VERTEX_SLIP) & _slipping(dec.new) & (dec.old != dec.new))
    if ks.size == 0:
        return ks
    v0, v1 = _slip_velocities(eng, ks, dec.ds, dec.dw, w_start, wdot, 0.0, dt, nm.c1, nm,
                              wacc, law, dec.old)
    return ks[(v0 > 0) & (np.abs(v1) <= 1e-9 * v0)]  # (along the vertex's bisector)


def _onto_facet(old, new) -> np.ndarray:
    """CFEs whose slip at a vertex of a faceted cone (3D) turns onto one of its facets: its
    friction force jumps from the vertex to the facet's point that equilibrium at that instant
    requires (re-solved in accelerations, as a stop's: else the facet's kinematic row,
    e_i · u̇_τ = 0, would start from the vertex's acceleration across it and alternate with
    Newmark's constrained DOFs).  Never in 2D."""
    new = np.asarray(new)
    return (np.asarray(old) >= VERTEX_SLIP) & (new >= FACET_SLIP) & (new < VERTEX_SLIP)


def _deferred(old, new, changed, law, damped) -> np.ndarray:
    """Of the CFEs ``changed`` at an event inside a step, those whose switch is left to the
    rate problem at the start of the next step (the same instant): a closed CFE that opens
    and a stuck one that starts to slip — their forces are continuous there, so nothing jumps
    in between.  Not a bond (its break releases forces), a damped layer (its shift depends on
    the state), a closing (an impact) or a stop (a friction force that jumps)."""
    k = changed[(old[changed] != BONDED) & ~np.isin(changed, damped) & ~law.inert[changed]]
    opens = (old[k] != OPEN) & (new[k] == OPEN)
    slips = (old[k] == STICK) & _slipping(new[k])
    return k[opens | slips]


def _project(system, cond, metric: _ContactMetric, u, v, states, law, rigid_n):
    """The state after a cut onto the constraints of its scheme (in the metric of M): the
    closed rigid CFEs' normal gap and normal velocity to zero, the stuck rigid CFEs' slip
    velocity to zero — so that no round-off of the interpolation (8) seeds the alternating
    velocities of Newmark's constrained DOFs — and no open rigid CFE penetrating.

    The corrections are M-orthogonal: Δu̇ = −M⁻¹ B_rᵀ λ with W_r λ = B_r u̇ (W_r = B_r M⁻¹ B_rᵀ,
    r the closed normal and stuck tangential rows), and likewise for u on the closed normal
    rows; the relative motions are one product with B_f each, the factors of W_r are kept
    and updated between cuts (:class:`_TrackedFactor`).  Returns (u, u̇, corrections):
    corrections = (z_u, z_v, X z_u, X z_v) with X = M⁻¹ B_fᵀ (z on the 2m contact rows; the
    displacement and velocity taken off the free DOFs), None where nothing was projected."""
    lay = system.layout
    nr = lay.normal_rows  # the normal rows of B
    closed = np.flatnonzero((states != OPEN) & ~law.inert & rigid_n)
    stuck = np.flatnonzero((((states == STICK) & law.frictional) | (states == BONDED))
                           & law.rigid_t & ~law.inert)
    rows_v = np.r_[nr[closed], lay.tangential_rows[stuck].ravel()].astype(np.int64)
    if rows_v.size == 0:
        return u, v, None
    free, Bf = cond.free, cond.Bf
    Xa = metric.X_all  # (M⁻¹ Bᵀ on all DOFs where it is sparse: no gather and scatter)
    vf = np.take(v, free)
    zv = metric.layout.zeros()
    zv[rows_v] = metric.tracked("v").solve(rows_v, (Bf @ vf)[rows_v])
    if Xa is not None:
        dv_all = Xa @ zv
        dv = np.take(dv_all, free)  # (the same floats as X z_v: Xa is X by the same columns)
        v = v - dv_all
    else:
        dv = metric.X @ zv
        v = v.copy()
        v[free] = vf - dv
    # positions: closed rigid CFEs onto their obstacles, and an open one that the cut's
    # interpolation (or a neighbour's correction on shared nodes of mortar CFEs) left
    # penetrating onto its obstacle too (an active set: no open CFE ends inside)
    rig = np.flatnonzero(~law.inert & rigid_n)
    act = states[rig] != OPEN
    uf = np.take(u, free)
    r_rig, w0_rig = nr[rig], system.w0[nr[rig]]
    w_all = (Bf @ uf)[r_rig] + w0_rig
    tol = 1e-9 * max(float(np.abs(uf).max(initial=0.0)), 1e-300)
    u_try = uf
    zu, du = metric.layout.zeros(), np.zeros(len(uf))
    du_all = None
    for _ in range(len(rig) + 1):
        rows = r_rig[act].astype(np.int64)
        if rows.size:
            zu = metric.layout.zeros()
            zu[rows] = metric.tracked("u").solve(rows, w_all[act])
            if Xa is not None:
                du_all = Xa @ zu
                du = np.take(du_all, free)  # (= X z_u, as for the velocities)
            else:
                du = metric.X @ zu
            u_try = uf - du
        pen = ~act & ((Bf @ u_try)[r_rig] + w0_rig > tol)
        if not pen.any():
            break
        act |= pen
    if Xa is not None:
        u = u.copy() if du_all is None else u - du_all  # (nothing moved: u − X 0 = u)
    else:
        u = u.copy()
        u[free] = u_try
    return u, v, (zu, zv, du, dv)


def _impact(system, cond, minv, v: np.ndarray, cand: np.ndarray, closing: np.ndarray,
            e: float, law, states: np.ndarray, impulses: dict | None = None):
    """Velocities after an impact (Newton's law): impulses P ≥ 0 on the normal rows of the
    CFEs ``cand`` (closing and already closed) such that each active one leaves with the
    normal velocity −e u̇_n⁻ (closing) or 0 (closed): M Δv = −B_nᵀ P, by an active set (an
    impulse that would pull is dropped); then the tangential impulses of Coulomb's law
    (:func:`_friction_impulse`).  Returns (velocities, slip direction per CFE of ``cand``
    after the impact, 0 where it sticks).

    The contact law ``law`` (over all CFEs, in ``states`` before the impact) says which
    normal impulses may pull (:meth:`~stepcontact.contact.bond.BondedJointLaw.impulse_pulls`:
    an intact bond, eq. (12), holds both ways) and bounds the tangential ones
    (:meth:`~stepcontact.contact.laws.CoulombLaw.impulse_limit`: f P, unbounded for a bond
    rigid in shear — its strength is checked on the forces after the impact).

    ``impulses``: a dict that receives the impulses per CFE of ``cand``, N·s (per metre of
    thickness in plane strain), in the sign convention of the forces s = [Q; p]: ``"p"`` the
    normal impulse (≥ 0 compressive, except a bond's pull), ``"Q"`` the tangential one."""
    rows_n = system.layout.normal_rows[cand]  # the normal rows of the CFEs cand
    free = cond.free
    Bn = cond.Bf[rows_n]  # normal rows on the free DOFs
    if impulses is not None:
        impulses["p"], impulses["Q"] = np.zeros(len(cand)), np.zeros(len(cand))
    if Bn.shape[0] == 0:
        return v, np.zeros(len(cand))
    vf = v[free]
    wd = Bn @ vf  # normal relative velocities (positive: approaching)
    target = np.where(np.isin(cand, closing), -np.asarray(e) * wd, 0.0)  # (e: one, or per
    # CFE of cand)
    X, W = minv(rows_n)  # M⁻¹ Bᵀ, B M⁻¹ Bᵀ
    bil = law.impulse_pulls(states)[cand]
    active = (wd > 0) | bil  # approaching (or closed and pushed on; bonded: held)
    P = np.zeros(len(cand))
    for _ in range(2 * len(cand) + 1):
        P[:] = 0.0
        idx = np.flatnonzero(active)
        if idx.size:
            P[idx] = _spd_solve(W[np.ix_(idx, idx)], wd[idx] - target[idx])
        after = wd - W @ P
        neg = active & (P < 0) & ~bil
        pen = ~active & (after > 1e-12 * max(np.abs(wd).max(initial=0.0), 1e-300))
        if not (neg.any() or pen.any()):
            break
        active = (active & ~neg) | pen
    out = v.copy()
    out[free] = vf - X(P)
    P_all = np.zeros(len(states))
    P_all[cand] = P
    limit = law.impulse_limit(states, P_all)[cand]
    T = np.zeros(len(cand))
    sig = _friction_impulse(system, cond, minv, out, cand, limit, T)
    if impulses is not None:
        impulses["p"], impulses["Q"] = P.copy(), T
    return out, sig


def _restitution_of(cond, lay: ContactLayout, e: float, v: np.ndarray, a: np.ndarray,
                    cand: np.ndarray, dt: float) -> np.ndarray | float:
    """Newton's coefficient e per CFE of ``cand`` at an impact: e, except where the rebound
    could not be followed — its flight 2 e u̇⁻ / ü_n (u̇⁻ the approach velocity, ü_n > 0 the
    relative acceleration towards the obstacle before the impact) would be shorter than the
    time step Δt: the bounces that remain (a geometric series, Zeno's) last less than
    Δt / (1 − e) in all and end at rest, so that CFE stays closed (e = 0 for it; the kinetic
    energy left, ½ m (e u̇⁻)², goes to the ledger's ``impact``)."""
    if e <= 0.0:
        return e
    free = cond.free
    Bn = cond.Bf[lay.normal_rows[cand]]
    wd = Bn @ v[free]  # approach velocities (positive: closing)
    acc = Bn @ a[free]
    with np.errstate(divide="ignore", invalid="ignore"):
        short = (acc > 0) & (2.0 * e * np.maximum(wd, 0.0) < acc * dt)
    return np.where(short, 0.0, e)


def _rebounding(cond, lay: ContactLayout, v0: np.ndarray, v: np.ndarray, cand: np.ndarray,
                old: np.ndarray) -> np.ndarray:
    """The CFEs of ``cand`` that leave the obstacle after an impact with restitution e > 0
    (Newton's law: a closing CFE's normal relative velocity after it is −e times the approach
    one, separating): not bonded, with a separating normal velocity after the impact (``v``)
    beyond round-off (1e-9 of the largest relative velocity of ``cand`` before it, ``v0``).
    They open at the impact's instant."""
    free = cond.free
    Bn = cond.Bf[lay.normal_rows[cand]]
    wn = Bn @ v[free]  # positive: approaching
    tol = 1e-9 * max(float(np.abs(Bn @ v0[free]).max(initial=0.0)), 1e-300)
    return cand[(wn < -tol) & (old[cand] != BONDED)]


def _friction_impulse(system, cond, minv, v: np.ndarray, cand: np.ndarray,
                      limit: np.ndarray, T_out: np.ndarray | None = None) -> np.ndarray:
    """Tangential impulses of an impact within the law's bounds ``limit`` (per CFE of
    ``cand``, N·s: f P by Coulomb's law, ``inf`` for a bond rigid in shear, 0 where none
    acts): each CFE with a bound stops sliding if the impulse that stops it is within the
    bound, else slides on with |T| at the bound against its slip.  Changes ``v`` in place;
    returns per CFE of ``cand`` the slip direction after the impact (0: stuck), and writes
    the tangential impulses (N·s, the sign of Q) into ``T_out`` (len(cand),) if given."""
    sig = np.zeros(len(cand))
    k = np.flatnonzero(limit > 0)
    if k.size == 0:
        return sig
    limit = limit[k]
    free = cond.free
    cfes = cand[k]
    rows = system.layout.tangential_rows[cfes]
    if rows.ndim > 1:  # two tangential components (3D): the cone's impulses
        T3, sl3 = _cone_impulse(cond, minv, v, rows, limit)
        if T_out is not None:
            T_out[k] = np.linalg.norm(T3, axis=1)
        sig = np.zeros((len(cand), 2))
        sig[k] = np.where(sl3[:, None], (cond.Bf[rows.ravel()] @ v[free]).reshape(-1, 2), 0.0)
        return sig
    Bt = cond.Bf[rows]  # tangential rows
    X, W = minv(rows)
    wt = Bt @ v[free]
    T = np.zeros(len(k))
    sliding = np.zeros(len(k), bool)
    for _ in range(2 * len(k) + 1):
        stick = np.flatnonzero(~sliding)
        T[sliding] = np.sign(T[sliding]) * limit[sliding]
        if stick.size:
            rhs = wt[stick] - W[np.ix_(stick, np.flatnonzero(sliding))] @ T[sliding]
            T[stick] = _spd_solve(W[np.ix_(stick, stick)], rhs)
        over = ~sliding & (np.abs(T) > limit * (1 + 1e-12))
        if not over.any():
            break
        sliding |= over
    v[free] -= X(T)
    if T_out is not None:
        T_out[k] = T
    after = Bt @ v[free]
    sig[k] = np.where(sliding, np.sign(after), 0.0)
    return sig


def _cone_impulse(cond, minv, v: np.ndarray, rows: np.ndarray, limit: np.ndarray):
    """The tangential impulses T (k, 2) of an impact on CFEs with two tangential components
    (``rows`` (k, 2), 3D) within Coulomb's cone |T_k| ≤ ``limit`` (f P, N·s): each CFE stops
    sliding if the impulse that stops it is within the bound, else slides on with |T_k| at the
    bound along that impulse's direction (against its slip: exact for one CFE, whose W is
    isotropic in the tangent plane), by an active set as in 2D (:func:`_friction_impulse`).
    Changes ``v`` in place; returns (T, sliding (k,))."""
    free, k = cond.free, len(limit)
    flat = rows.ravel()  # (CFE-major: t₁, t₂ of each CFE)
    X, W = minv(flat)
    wt = cond.Bf[flat] @ v[free]
    T = np.zeros(2 * k)
    sliding = np.zeros(k, bool)
    dirs = np.zeros((k, 2))
    for _ in range(2 * k + 1):
        sl = np.repeat(sliding, 2)
        T[sl] = (limit[sliding, None] * dirs[sliding]).ravel()
        st = np.flatnonzero(~sl)
        if st.size:
            T[st] = _spd_solve(W[np.ix_(st, st)], wt[st] - W[np.ix_(st, np.flatnonzero(sl))]
                               @ T[sl])
        Tk = T.reshape(k, 2)
        mag = np.linalg.norm(Tk, axis=1)
        over = ~sliding & (mag > limit * (1 + 1e-12))
        if not over.any():
            break
        dirs[over] = Tk[over] / mag[over, None]
        sliding |= over
    v[free] -= X(T)
    return T.reshape(k, 2), sliding


class _DampedLayers:
    """Kelvin–Voigt contact layers: CFEs whose compliant layer (C_n, eq. (11)) has a normal
    damping c_n > 0 (N·s/m).

    Closed, the layer's force is p = C_n u_n + c_n u̇_n (compression positive).  With Newmark's
    u̇_{n+1} = c₁ Δu_n + c_v u̇_n + c_a ü_n, the end of a step relates p and u_n through the
    stiffness Ĉ_n = C_n + c_n c₁ (constant: every step uses Δt's c₁), so the engine's law
    carries Ĉ_n, and along the step p' = Ĉ_n (u_n' + e) with the constant
    e = c_n ((c_v − 1) u̇_n + c_a ü_n)/Ĉ_n of the step's start: the same shift of the mutual
    displacement as the stuck CFEs' drift (the engine's forcing e).

    The layer opens when its force reaches zero (it cannot pull), still compressed by
    x = u_n > 0; open, it relaxes, C_n x + c_n ẋ = 0, x(t) = x₀ e^{−C_n t / c_n}, and the CFE
    closes again where u_n reaches the layer's surface x (the law's ``surface``: the
    exponential at the steps' ends, linear in time between them, as eq. (10) interpolates the
    structure).  At a closing the force jumps to C_n u_n + c_n u̇_n ≥ 0:
    the dashpot's share of an impact.  Energy: ½ C_n x² is stored; what the dashpot takes
    (closed: c_n ū̇_n Δu_n; open: the relaxation) is the ledger's ``damping``."""

    def __init__(self, cfe, law: CoulombLaw, layout: ContactLayout):
        self.k = np.flatnonzero((cfe.cn > 0) & np.isfinite(cfe.kn))
        # the layers' rows in s, w: normal (u_n, p) and tangential (u_τ, Q)
        self.rows = layout.normal_rows[self.k]
        self.rows_t = layout.tangential_rows[self.k]
        self.kn, self.cn = cfe.kn[self.k], cfe.cn[self.k]
        self.khat = law.kn[self.k]
        self.law = law
        self.x = np.zeros(len(self.k))  # compression of each layer, m
        self.x1 = self.x  # … of an open one at the end of the current step

    def __bool__(self) -> bool:
        return bool(self.k.size)

    @staticmethod
    def law_stiffness(cfe, c1: float) -> np.ndarray:
        """C_n of the engine's law: Ĉ_n = C_n + c_n c₁ for the damped layers."""
        damped = (cfe.cn > 0) & np.isfinite(cfe.kn)
        return np.where(damped, cfe.kn + cfe.cn * c1, cfe.kn)

    def set_initial(self, states, w) -> None:
        closed = states[self.k] != OPEN
        self.x = np.where(closed, w[self.rows], 0.0)
        self.sync(states, None, w)

    def relaxed(self, frac: float) -> np.ndarray:
        """Compression of a layer open throughout the step, at ``frac`` of the step."""
        return self.x + frac * (self.x1 - self.x)

    def sync(self, states, s, w) -> None:
        """The law's offsets (closed: p = Ĉ_n u_n + offset holds at this state) and surfaces
        (open: the layer's compression) for the schemes ``states``."""
        closed = states[self.k] != OPEN
        if s is not None:
            p = s[self.rows]
            self.law.offset[self.k] = np.where(closed, p - self.khat * w[self.rows], 0.0)
        self.law.surface[self.k] = np.where(closed, 0.0, self.x)

    def start(self, states, s, w, wdot, wacc, nm: _Newmark, drift: np.ndarray) -> None:
        """The step's shift (``drift`` of the normal rows, −e) and the law's offsets and
        surfaces for the schemes ``states`` at the step's start."""
        if not self:
            return
        j = self.rows
        closed = states[self.k] != OPEN
        e = self.cn * ((nm.cv - 1.0) * wdot[j] + nm.ca * wacc[j]) / self.khat
        self.x1 = self.x * np.exp(-nm.h * self.kn / self.cn)
        drift[j] = np.where(closed, -e, self.x1 - self.x)
        self.sync(states, s, w)

    def at(self, states, w, frac: float) -> np.ndarray:
        """Compressions at ``frac`` of the step under ``states``."""
        closed = states[self.k] != OPEN
        return np.where(closed, w[self.rows], self.relaxed(frac))

    def closing_states(self, old, new) -> np.ndarray:
        """A damped layer that closes with a compliant tangential layer closes stuck: its
        shear force grows from zero with the tangential displacement (C_τ), whatever the jump
        of its normal force; it slips later, where the shear reaches f p."""
        k = self.k[(old[self.k] == OPEN) & (new[self.k] != OPEN) & ~self.law.rigid_t[self.k]]
        if k.size == 0:
            return new
        new = new.copy()
        new[k] = self.law.closed_state()[k]
        return new

    def restart(self, old, new, s, w, wdot, frac: float) -> None:
        """After a cut at ``frac`` of the step (``s`` changed in place): the closed layers'
        force p = C_n u_n + c_n u̇_n (a closing's jump), the open ones' compression."""
        if not self:
            return
        j = self.rows
        was_closed = old[self.k] != OPEN
        closed = new[self.k] != OPEN
        self.x = np.where(closed | was_closed, w[j], self.relaxed(frac))
        s[j] = np.where(closed, np.maximum(self.kn * w[j] + self.cn * wdot[j], 0.0), 0.0)
        s[self.rows_t] = np.where(closed.reshape((-1,) + (1,) * (self.rows_t.ndim - 1)),
                                  s[self.rows_t], 0.0)  # ((k, 2) rows in 3D)
        self.sync(new, s, w)

    def energy(self, x=None) -> np.ndarray:
        """½ C_n x² of every damped layer, J."""
        x = self.x if x is None else x
        return 0.5 * self.kn * x**2


#: the axes a ground acceleration may name (y vertical in 2D, z in 3D)
_AXES = ("x", "y", "z")
#: the sign convention of a ground acceleration, carried in the result's ``units``
#: (``units["ground_acceleration"]``) of a run with one
GROUND_CONVENTION = ("m s-2; a positive value accelerates the ground along +axis (its "
                     "direction); u, v, a are relative to the ground (the effective load is "
                     "-M r a_g(t))")


#: what each crack-water choice of an interval does (issue 29 §1), carried in the result's
#: ``units["crack_water"]`` of a run with crack water as "choice: note"
#: (:attr:`~stepcontact.results.result.DynamicResult.crack_water`)
CRACK_WATER_NOTES = {
    "full": "the static rule in time (water enters every opening joined to an entry)",
    "unchanged": "the wet set and pressures of the start held (no water enters new openings)",
    "none": "the wet set and pressures of the start held, no pressure in new openings"}


def crack_water_note(choice: str) -> str:
    """``units["crack_water"]`` of a dynamic result run with crack-water choice ``choice``."""
    return f"{choice}: {CRACK_WATER_NOTES[choice]}"


def _ground_components(ground_acceleration) -> tuple[tuple[object, object], ...]:
    """The components (a_g(t), direction) of ``ground_acceleration``, checked: None (none);
    (a_g, (dx, dy)) — (dx, dy, dz) in 3D, or an axis "x", "y", "z" —; a sequence of such
    pairs, applied together; or a record or ground motion
    (:class:`~stepcontact.model.records.AccelerationRecord`,
    :class:`~stepcontact.model.records.GroundMotion`: its ``components()``)."""
    if ground_acceleration is None:
        return ()
    if hasattr(ground_acceleration, "components"):
        pairs = tuple(ground_acceleration.components())
    elif (isinstance(ground_acceleration, Sequence) and ground_acceleration
          and not callable(ground_acceleration[0])
          and all(isinstance(p, Sequence) and len(p) == 2 for p in ground_acceleration)):
        pairs = tuple(ground_acceleration)
    else:
        pairs = (ground_acceleration,)
    out = []
    for pair in pairs:
        try:
            g_fun, direction = pair
        except (TypeError, ValueError):
            raise ModelError("ground_acceleration", "give (time function, (dx, dy)), or "
                             "(dx, dy, dz) in 3D, a list of such pairs, or a record "
                             "(AccelerationRecord, GroundMotion)") from None
        if not callable(g_fun):
            raise ModelError("ground_acceleration", "its first entry must be a time function "
                             "a_g(t), m/s²")
        if isinstance(direction, str):
            if direction not in _AXES:
                raise ModelError("ground_acceleration", f"the axis must be one of "
                                 f"{', '.join(_AXES)}, got {direction!r}")
        else:
            d = np.asarray(direction, float)
            if d.shape not in ((2,), (3,)) or not np.all(np.isfinite(d)) or not np.any(d):
                raise ModelError("ground_acceleration", f"the direction must be a nonzero "
                                 f"vector (dx, dy), or (dx, dy, dz) in 3D, got {direction!r}")
        out.append((g_fun, direction))
    return tuple(out)


def _ground_translation(system: System, direction) -> np.ndarray:
    """r (ndof,): the displacements of a rigid translation by 1 m along the unit vector
    ``direction`` (the effective load of a ground acceleration is −M r a_g(t)).  Continua and
    frames: their nodes' u_x, u_y; a discrete model: its DOFs' axes
    (:attr:`~stepcontact.DiscreteModel.dof_axes`, r_i = e_i · d) — refused when none of its
    DOFs translates along the direction (the load would be zero)."""
    dim = (system.discrete.dof_axes.shape[1] if system.discrete is not None
           else system.dofs.dim)
    if isinstance(direction, str):  # an axis: its unit vector in the model's dimension
        if _AXES.index(direction) >= dim:
            raise ModelError("ground_acceleration", f"axis '{direction}' in a {dim}D model: "
                             f"give {' or '.join(_AXES[:dim])} (the vertical is "
                             f"{_AXES[dim - 1]})")
        direction = np.eye(dim)[_AXES.index(direction)]
    d = np.asarray(direction, float)
    d = d / np.linalg.norm(d)
    if len(d) != dim:
        raise ModelError("ground_acceleration", f"the direction has {len(d)} components, the "
                         f"model is {dim}D: give ({', '.join('dx dy dz'.split()[:dim])})")
    if system.discrete is not None:
        r = system.discrete.dof_axes @ d
        if not np.any(np.abs(r) > 1e-12):
            named = np.any(system.discrete.dof_axes != 0.0)
            raise ModelError("ground_acceleration", (
                f"no DOF of the discrete model translates along ({', '.join(f'{x:g}' for x in d)})"
                if named else "the discrete model's DOFs have no direction") + ": the ground "
                "acceleration would apply no load; say which DOFs are translations along "
                "which axis (DiscreteModel(dof_axes={'ux': 'x', 'uy': 'y'}))")
        return r
    r = np.zeros(system.ndof)
    has = system.dofs.of >= 0
    for c in range(dim):
        r[system.dofs.of[has[:, c], c]] = d[c]
    return r


@dataclass
class Interval:
    """The dynamic interval a run integrates, resolved from the arguments of
    :func:`stepcontact.solve_dynamic` and the model's (or a stage's) ``dynamics``
    (:func:`dynamic_interval`)."""

    mdl: object  # the Model (or DiscreteModel) of the run
    stage: int | None
    dt: float
    duration: float
    loads: Mapping[str, object] | None
    mass: object
    damping: tuple[float, float]
    restitution: float
    record_every: int
    alpha: float
    #: the ground acceleration's components (a_g(t), direction or axis)
    #: (:func:`_ground_components`): the argument's, or the dynamic interval's ``ground``
    ground: tuple = ()
    #: the crack water during the interval (:data:`~stepcontact.model.structure.
    #: CRACK_WATER_CHOICES`)
    crack_water: str = "full"


def dynamic_interval(model, *, stage: int | str | None = None, dt: float | None = None,
                     duration: float | None = None, loads: Mapping[str, object] | None = None,
                     mass: str | sp.spmatrix = "consistent",
                     damping: tuple[float, float] = (0.0, 0.0), restitution: float = 0.0,
                     record_every: int = 1, alpha: float = 0.0, max_steps: int | None = None,
                     ground_acceleration=None, crack_water: str | None = None) -> Interval:
    """The interval to run: the arguments, or (without dt and duration) the dynamic interval
    of the model or of the stage ``stage``; Δt, the duration, HHT-α and the loads' sampling
    checked before any work (:func:`~stepcontact.model.timefunction.check_interval`).
    ``crack_water`` None: the model's (or stage's) interval's own when it is the one run
    (``DynamicInterval.crack_water``), else ``"full"``."""
    mdl = model.model if isinstance(model, System) else model
    spec = getattr(mdl, "dynamics", None)
    if stage is not None:
        stages = tuple(getattr(mdl, "stages", ()))
        names = [st.name for st in stages]
        if isinstance(stage, str):
            if stage not in names:
                raise ModelError("stage", f"no such stage '{stage}' (known: "
                                 f"{', '.join(map(repr, names)) or 'none'})")
            stage = names.index(stage)
        if not 0 <= int(stage) < len(stages):
            raise ModelError("stage", f"must be a stage index in [0, {len(stages)}), got {stage}")
        stage = int(stage)
        spec = stages[stage].dynamics
        if spec is None:
            raise ModelError(f"stage '{names[stage]}'.dynamics", "is not given: the stage has "
                             "no dynamic interval")
    if spec is not None and dt is None and duration is None:  # the model's dynamic interval
        dt, duration = spec.dt, spec.duration
        loads = dict(spec.loads) if loads is None else loads
        mass, damping = spec.mass, spec.damping
        restitution, record_every = spec.restitution, spec.record_every
        alpha = spec.alpha
        max_steps = getattr(spec, "max_steps", None) if max_steps is None else max_steps
        if ground_acceleration is None:  # the record of the model's interval
            ground_acceleration = getattr(spec, "ground", None)
        if crack_water is None:
            crack_water = getattr(spec, "crack_water", "full")
    crack_water = check_crack_water("full" if crack_water is None else crack_water,
                                    "crack_water")
    if dt is None or duration is None:
        raise ModelError("dynamics", "give dt and duration (s), or a model with a dynamic "
                         "interval (model.dynamics)")
    check_newmark(dt, duration, alpha=alpha, restitution=restitution)  # the model's rules
    ground = _ground_components(ground_acceleration)
    _warn_off_grid(ground_acceleration, dt)
    # Δt, the step count and every load's sampling, before any work (check_interval)
    check_interval(dt, duration, loads or {}, max_steps=MAX_STEPS if max_steps is None
                   else max_steps, ground=_ground_items(ground))
    return Interval(mdl, stage, dt, duration, loads, mass, damping, restitution,
                    record_every, alpha, ground, crack_water)


def _warn_off_grid(ground_acceleration, dt: float) -> None:
    """A :class:`~stepcontact.model.records.RecordGridWarning` for every earthquake record of
    ``ground_acceleration`` whose samples are off the step grid of ``dt``
    (:func:`~stepcontact.model.records.grid_problem`: every step would be cut at them)."""
    from stepcontact.model.records import (
        AccelerationRecord,
        GroundMotion,
        RecordGridWarning,
        grid_problem,
    )

    recs = (ground_acceleration.records if isinstance(ground_acceleration, GroundMotion)
            else (ground_acceleration,) if isinstance(ground_acceleration, AccelerationRecord)
            else ())
    for r in recs:
        text = grid_problem(r, dt)
        if text:
            warnings.warn(RecordGridWarning(f"ground_acceleration: {text}"), stacklevel=4)


def _ground_items(ground: tuple) -> dict[str, object]:
    """{item: a_g(t)} of the ground acceleration's components, for the messages of
    :func:`~stepcontact.model.timefunction.check_interval`."""
    if len(ground) == 1:
        return {"ground_acceleration": ground[0][0]}
    return {f"ground_acceleration[{i}]" + (f" ({d})" if isinstance(d, str) else ""): g
            for i, (g, d) in enumerate(ground)}


def one_thread(fn):
    """Run ``fn`` with every thread pool (BLAS, MKL PARDISO, OpenMP) held to one thread: a
    time step's work is a forward and back substitution and small dense algebra, which a
    second thread does not speed up, while the pools' idle threads spinning between calls take
    the core the run needs (the 21k-DOF benchmark slab ran 3.4× slower with two threads on two
    busy cores)."""

    @functools.wraps(fn)
    def run(*args, **kwargs):
        from threadpoolctl import threadpool_limits

        with threadpool_limits(limits=1):
            return fn(*args, **kwargs)

    return run


@one_thread
def integrate(model, iv: Interval, *, initial: StaticResult | None = None,
              u0: np.ndarray | None = None, v0: np.ndarray | None = None,
              ground_acceleration: tuple[object, tuple[float, float]] | None = None,
              hooks: Sequence = (), max_events: int = 1_000_000, rtol: float = 1e-10,
              backend: str = "auto") -> DynamicResult:
    """Integrate the dynamic interval ``iv`` (:func:`dynamic_interval`) of ``model`` in time:
    Newmark (HHT-α) steps with the contact state followed exactly, eqs. (7)–(10) (module
    docstring).  The arguments are those of :func:`stepcontact.solve_dynamic`, the public
    driver, which resolves the interval and, for a model in construction stages, the static
    result of the stages it starts from; here a staged model needs ``initial``, the result of
    the run of its stages in memory (the static driver gives its own for the interval of a
    stage, :meth:`~stepcontact.solver.static.StaticSolver._dynamic_interval`)."""
    run = _DynamicRun(model, iv, initial=initial, u0=u0, v0=v0,
                      ground_acceleration=ground_acceleration, hooks=hooks,
                      max_events=max_events, rtol=rtol, backend=backend)
    run.start()
    run.integrate()
    return run.result()


class _DynamicRun:
    """One dynamic interval in progress (:func:`integrate`, module docstring): the system
    with its factorised K̂, the event engine (the contact forces s, mutual displacements w and
    states of the CFEs), the fields u, u̇, ü at time t, the loads, the recorder and the energy
    ledger.  Set up and checked by the constructor; :meth:`start` settles the state at t = 0,
    :meth:`integrate` runs the steps of eqs. (7)–(10), :meth:`result` builds the result."""

    def __init__(self, model, iv: Interval, *, initial, u0, v0, ground_acceleration, hooks,
                 max_events: int, rtol: float, backend: str):
        self.iv = iv
        self.alpha, self.restitution = iv.alpha, iv.restitution
        self.record_every = iv.record_every
        #: (a_g(t), direction) of every component of the ground acceleration
        self.ground = (iv.ground if ground_acceleration is None
                       else _ground_components(ground_acceleration))
        self.hooks, self.max_events, self.rtol = hooks, max_events, rtol
        self.u0 = u0
        self._assemble(model, initial)
        self._matrices(backend)
        self._contact_law()
        self._initial_state(u0, v0)
        self._initial_loads()
        self._initial_acceleration()
        self._books()

    # -- set-up ------------------------------------------------------------------------------

    def _assemble(self, model, initial) -> None:
        """The system of the interval (after the construction stages, :func:`_after_stages`:
        the stage plan and stage the law is built at), and the loads (each a pattern of the
        system with a time function)."""
        system = model if isinstance(model, System) else assemble(model)
        self.stage_arrays: dict | None = None
        self.staged: tuple = (None, None)  # (plan, stage) of a run after stages
        if in_stages(system):
            system, self.staged, initial, self.stage_arrays = _after_stages(system, initial,
                                                                            self.iv.stage)
        loads = dict(self.iv.loads or {})
        for name, g in loads.items():
            if name not in system.loads:
                raise ModelError(f"loads['{name}']", f"no such load pattern (known: "
                                 f"{', '.join(map(repr, system.loads)) or 'none'})")
            if not callable(g):
                raise ModelError(f"loads['{name}']", "must be a time function g(t)")
        self.system, self.initial, self.loads = system, initial, loads
        self.ndof, self.m = system.ndof, system.m
        self.layout = system.layout  # the contact unknowns s = [Q; p], w = [u_τ; u_n]
        self.cfe = system.cfe

    def _matrices(self, backend: str) -> None:
        """M, C = a₀ M + a₁ K (+ the springs' dashpots) and K̂ = K + 4M/Δt² + 2C/Δt of eq. (7)
        (HHT-α: :class:`_Newmark`), factorised and condensed once: the steps shorter than Δt
        (to land on a load's break or the end, or to go on after an event) use it too."""
        from stepcontact.fem.mass import check_mass
        from stepcontact.fem.mass import mass as mass_matrix

        iv, system, ndof = self.iv, self.system, self.ndof
        mass = iv.mass
        if isinstance(mass, str):
            if mass not in MASS_KINDS:
                raise ModelError("mass", f"must be {', '.join(map(repr, MASS_KINDS))} or a "
                                 f"matrix, got '{mass}'")
            if system.discrete is not None:
                raise ModelError("mass", "a discrete model has no geometry: give its mass "
                                 "matrix")
            check_mass(system, "dynamics" if iv.stage is None else
                       f"stage '{iv.mdl.stages[iv.stage].name}'.dynamics")
            M = mass_matrix(system.model, system.dofs, lumped=mass == "lumped")
        else:
            M = sp.csr_matrix(mass, dtype=float)
            if M.shape != (ndof, ndof):
                raise ModelError("mass", f"has shape {M.shape}, expected ({ndof}, {ndof})")
        a0, a1 = (float(x) for x in iv.damping)
        K = system.K.tocsr()
        C = (a0 * M + a1 * K).tocsr() if a0 or a1 else sp.csr_matrix((ndof, ndof))
        if system.discrete is None and any(sp_.damping for sp_ in system.model.springs):
            C = (C + dashpots(system.model, system.dofs)).tocsr()  # the springs' dashpots
        self.M, self.K, self.C = M, K, C
        self.dt0 = float(iv.dt)
        self.nm0 = _Newmark(self.dt0, self.alpha)
        self.Kx, self.Mx, self.Cx = _Memo(K), _Memo(M), _Memo(C)  # products kept
        t0 = Stopwatch.start()
        self.cond = Condensed.from_system(dataclasses.replace(
            system, K=_Newmark(self.dt0, self.alpha).stiffness(K, M, C)), backend)
        self.schemes = SchemeSolver(self.cond.G, self.cond.d, product=self.cond.product)
        # every step solves with K̂: PARDISO keeps a full factorisation for the solves beside
        # the partial one G was read off (one call per solve instead of three)
        getattr(self.cond.factor, "for_many_solves", lambda: None)()
        self.solve_hat = _direct_solve(self.cond.factor)  # K̂⁻¹ b on the free DOFs
        self.t_setup = t0.counters("setup")

    def _contact_law(self) -> None:
        """The Coulomb law of the CFEs (eq. (1); compliant layers eq. (11), damped ones with
        Newmark's c₁, :class:`_DampedLayers`; bonds eq. (12)) and the event engine on the
        condensed K̂; refuses the combinations a dynamic interval does not follow.  Built by
        :func:`~stepcontact.solver.contactlaws.contact_law` as in the static driver: the
        components held by supports on both ends are inert (their supports carry them), and
        after stages the CFEs not active at the stage."""
        cfe = self.cfe
        plan, stage = self.staged
        _, bond_cols, _, _ = law_inputs(self.system, plan=plan, stage=stage)
        self.bond_cols = bond_cols
        if bond_cols is not None:
            bonded = ~np.isnan(np.asarray(bond_cols, float)[:, 0])
            damped_bond = bonded & (cfe.cn > 0)
            if self.initial is not None:  # (bonds already broken by the static run: not)
                damped_bond &= np.asarray(self.initial.state)[-1] == BONDED
            if damped_bond.any():
                k = int(np.flatnonzero(damped_bond)[0])
                raise ModelError(f"interface '{cfe.names[cfe.interface[k]]}'.bond", "a bonded "
                                 "joint with a damped contact layer (Kelvin–Voigt, c_n > 0) is "
                                 "not supported in a dynamic interval: give the layer no "
                                 "damping while its bond is intact")
            cols = np.asarray(bond_cols, float)
            if cols.ndim == 2 and cols.shape[1] > 4 and np.any(np.nan_to_num(cols[:, 4]) > 0):
                k = int(np.flatnonzero(np.nan_to_num(cols[:, 4]) > 0)[0])
                raise ModelError(f"interface '{cfe.names[cfe.interface[k]]}'.bond.residual_"
                                 "cohesion", "a residual cohesion after the break is followed "
                                 "in static load programs; a dynamic interval with one is not "
                                 "supported yet (give residual_cohesion = 0 for the dynamic "
                                 "run)")
        if np.any((cfe.cn > 0) & ~np.isfinite(cfe.kn)):
            k = int(np.flatnonzero((cfe.cn > 0) & ~np.isfinite(cfe.kn))[0])
            raise ModelError(f"interface '{cfe.names[cfe.interface[k]]}'", "a damped contact "
                             "layer needs a finite normal stiffness kn")
        self.law = law = contact_law(
            self.system, plan=plan, stage=stage,
            kn=_DampedLayers.law_stiffness(cfe, _Newmark(self.dt0, self.alpha).c1),
            held_by_supports=True)
        self.layers = _DampedLayers(cfe, law, self.layout)
        self.bonds_on = bool(law.has_bond.any())
        self.eng = EventEngine(self.schemes, [law], self.system.w0, rtol=self.rtol,
                               layout=self.layout)
        self.all_rigid = bool(np.all(~np.isfinite(cfe.kn)) and np.all(~np.isfinite(cfe.kt)))
        # a model whose CFEs are each rigid or compliant in both components: the rigid ones'
        # forces jump in accelerations (accel_forces), the compliant ones' are held
        self.soft_cfe = soft_cfe = np.isfinite(cfe.kn) & np.isfinite(cfe.kt)
        self.split = bool(np.all(soft_cfe | (~np.isfinite(cfe.kn) & ~np.isfinite(cfe.kt)))
                          and not soft_cfe.all())
        self.held = self.layout.join_each(soft_cfe, soft_cfe)
        self.rigid_n = ~np.isfinite(cfe.kn)
        self.soft_t = np.isfinite(cfe.kt)  # (compliant tangential rows: no drift, eq. (9))
        self.any_soft_t = bool(self.soft_t.any())
        # the law of every CFE in order (the engine's common case): a step's start where no
        # CFE is at a limit is decided without the rate problem (_quiet_start)
        self.one_law = (law if len(law.cfes) == self.m
                        and np.array_equal(law.cfes, np.arange(self.m)) else None)
        # … where its start is decided by the engine alone: no bonds (their breaks at the
        # start), rigid tangential rows (no compliant slip that stops inside a step)
        # (one tangential component: the faceted cone's vertex slips and turns are the engine's)
        self.quiet_steps = bool(self.one_law is not None and not self.bonds_on
                                and self.layout.n_t == 1
                                and law.rigid_t.all() and self.m)

    def _initial_state(self, u0, v0) -> None:
        """The fields and the contact state at t = 0 (:func:`_initial`, :func:`_state_at_u0`;
        joints with initial strength start bonded, eq. (12)), set in the engine."""
        system, cfe, law, eng, initial = self.system, self.cfe, self.law, self.eng, self.initial
        u, v, s, w, states, static = _initial(system, self.cond, initial, u0, v0)
        if u0 is not None and self.m:  # the contact state at u0 (gaps w = B u0 + w⁰)
            states, s, w = _state_at_u0(system, law, u, v, s, w, states, initial)
        if initial is None:  # joints with initial strength start bonded (eq. (12)), their
            states = law.initial_states(states)  # compliant layers carrying C w at u0
            stiff0 = self.layout.join_each(cfe.kt, cfe.kn)
            on = self.layout.join_each(states == BONDED, states == BONDED) & np.isfinite(stiff0)
            s = np.where(on, np.where(on, stiff0, 0.0) * w, s)
        eng.s, eng.w, eng.states = s.copy(), w.copy(), states.copy()
        if self.bonds_on:  # the bonds' strengths are forces of the problem's scale
            eng.F_scale = max(eng.F_scale, float(np.abs(np.r_[law.NR, law.QR]).max()))
        self.layers.set_initial(states, w)
        self.u, self.v, self.s_init, self.w_init, self.static = u, v, s, w, static
        self.free = self.cond.free
        #: every DOF free (a small discrete model): no gather and scatter of the free DOFs
        self.all_free = bool(len(self.free) == self.ndof
                             and np.array_equal(self.free, np.arange(self.ndof)))
        self.names = list(system.loads)
        self.f_of = {n: system.loads[n].f for n in self.names}
        self.r_ground: list[tuple[object, np.ndarray]] = []
        self._factors_last: tuple[float, dict] | None = None
        self._F_held_part: tuple[bool, np.ndarray] | None = None
        for g_fun, direction in self.ground:  # −M r a_g(t) per component
            self.r_ground.append((g_fun, -(self.M @ _ground_translation(system, direction))))
        # water in the opened joints (fem.crack): W = A (p_c − p_u) on the CFEs of
        # ``water_on`` (the wet set of the scheme the run is in), a load −Bᵀ [0; W] that
        # follows the factors in time and jumps where the wet set changes (settle_water)
        self.crack = crack = system.crack
        self.water_on = (crack.wet(states) if crack is not None and initial is not None
                         else np.zeros(self.m, bool))
        self._held_water(states)

    def _held_water(self, states) -> None:
        """The crack water of the interval's choice (``Interval.crack_water``, issue 29 §1),
        fixed at the start for ``"unchanged"`` and ``"none"``: ``p_open`` (m,), Pa, the water
        pressure a CFE carries (NaN: dry, the joint's uplift p_u acts as before) — the wet set
        of the start (``water_on``, ``held``) holds its crack pressure p_c = (p_c − p_u) + p_u
        at the factors the interval starts from while it is open; with ``"none"`` a CFE of a
        crack-water joint closed at the start and carrying uplift (``drains``) holds 0 from
        the instant it first opens, open or closed again (W = −A p_u cancels the uplift of a
        crack the shaking opened: the rule is monotone, so a CFE that only the uplift's help
        opens cannot chatter between its two pressures at one instant).  None for ``"full"``
        (the static rule, :meth:`~stepcontact.fem.crack.CrackWaterData.wet`, in time)."""
        crack, choice = self.crack, self.iv.crack_water
        self.p_open = None
        if crack is None or choice == "full":
            return
        c0 = self.static
        p_open = np.full(self.m, np.nan)
        # (its own name: ``held`` is the compliant layers' components, 2m, in accel_forces)
        self.water_held = held = self.water_on.copy()
        p_open[held] = (crack.net(c0) + crack.uplift_pressure(c0))[held]
        self.drains = np.zeros(self.m, bool)
        self.drained = np.zeros(self.m, bool)  # the drains opened so far
        if choice == "none":
            lifted = np.zeros(self.m, bool)
            for q in crack.uplift.values():
                lifted |= q != 0
            self.drains = crack.wettable & lifted & (states != OPEN) & ~held
            p_open[self.drains] = 0.0
        self.p_open = p_open

    def wet_of(self, states) -> np.ndarray:
        """The CFEs the crack water loads in the scheme ``states`` (m,) bool: the static rule
        for ``"full"``; else the open held CFEs and the drains open now or opened before."""
        if self.p_open is None:
            return self.crack.wet(states)
        op = states == OPEN
        return (op & self.water_held) | (self.drains & (op | self.drained))

    def _initial_loads(self) -> None:
        """The load at t = 0 and the load held from the static run (a static state is at
        rest); the time functions' values at t = 0 are a jump, followed in accelerations."""
        self.F = self.force_at(0.0)
        F_held = np.zeros(self.ndof)
        for name, c in self.static.items():
            F_held += c * self.f_of[name]
        if self.crack is not None and self.water_on.any():  # the static run's crack water
            F_held += self.water_load(self.water_at(0.0, self.static))
        self.F_held = F_held

    def _initial_acceleration(self) -> None:
        """ü at t = 0 from the equation of motion (7) with the initial contact forces and the
        loads held; the mass matrix factorised on the free DOFs (kept: M_lu)."""
        from scipy.sparse.linalg import splu

        cond, free, M = self.cond, self.free, self.M
        self.Bf = cond.Bf
        # Bᵀ on the free DOFs by columns: its products (n_free × 2m, a few entries per
        # column) loop over the 2m columns, not the n_free rows (the same sums in the same
        # order as by rows)
        self.BfT = self.Bf.T.tocsc()
        # the step's products with B (B u̇, B ü, B Δu, Bᵀ t): a tiny model's as dense arrays
        # (a sparse product's dispatch costs more than the product itself)
        small = self.system.B.shape[0] * self.ndof <= DENSE_PRODUCTS
        self.Bx, self.Bfx, self.BfTx = ((self.system.B.toarray(), self.Bf.toarray(),
                                         self.BfT.toarray()) if small
                                        else (self.system.B, self.Bf, self.BfT))
        rhs = (self.rest_force(self.F_held, self.u, self.v)
               - self.BfT @ self.s_init)
        Mff = M[free][:, free].tocsc()
        try:
            self.M_lu = _Diagonal(Mff) if _Diagonal.fits(Mff) else splu(Mff)
            a = np.zeros(self.ndof)
            a[free] = self.M_lu.solve(rhs)
        except RuntimeError as exc:
            raise ModelError("mass", f"the mass matrix is singular on the free DOFs ({exc}): "
                             "every free DOF needs mass") from None
        self.a = a
        self.accel: dict[str, object] = {}

    def _books(self) -> None:
        """The recorder, the energy ledger (module docstring) and the run's counters."""
        m, cfe, u = self.m, self.cfe, self.u
        ndof = self.ndof
        self.rec = Recorder(self.layout, len(self.names), 0)
        self.events = EventLog(self.rec, cfe, self.layout)
        # the states the run records: every record_every-th step, the events, the cuts —
        # room for four times the steps (the buffers' pages are only taken as rows are
        # written: a buffer larger than the run needs costs no memory, one that grows
        # costs a reallocation)
        states = 4 * (int(self.iv.duration / self.dt0 / max(self.record_every, 1)) + 2) + 8
        self.extra = {"u": _Rows(ndof, states), "v": _Rows(ndof, states),
                      "a": _Rows(ndof, states)}
        self.energy: list[tuple[float, ...]] = []  # the ledger's terms per state
        self.ledger = dict.fromkeys(ENERGY_TERMS, 0.0)
        # the scale of mutual displacements: at rest on closed rigid contact they are
        # round-off, so the fields' displacements set it (the contact conditions are judged
        # against it)
        self.w_scale = max(float(np.abs(self.w_init).max(initial=0.0)),
                           float(np.abs(u).max(initial=0.0)))
        self.eng.W_scale = max(self.eng.W_scale, self.w_scale)
        self.parts = dict.fromkeys(("cut", "projection", "hht", "short_steps"), 0.0)
        lay = self.layout
        self.stiff = lay.join_each(cfe.kt, cfe.kn)
        self.soft = np.isfinite(self.stiff) & (self.stiff > 0)
        self.any_soft = bool(self.soft.any())
        self.no_layer_energy = lay.zeros()
        self.no_water = np.zeros(m)
        self.no_water.flags.writeable = False
        self._gt_end: tuple | None = None  # (t, G t) of the state a step ended in
        self.no_contact = lay.zeros()  # the rates (s', w') of a model without CFEs
        self.no_contact.flags.writeable = False
        self.no_layer_energy.flags.writeable = False
        self.damped = lay.zeros(dtype=bool)
        # Kelvin–Voigt layers: ½ C_n x², the dashpot's
        lay.normal(self.damped)[self.layers.k] = True
        self.e0 = 0.5 * self.v @ (self.Mx(self.v)) + self.strain_energy(u, self.s_init)
        self.mult = {"first_slip": None, "first_opening": None, "first_closing": None,
                     "equilibrium_lost": None}
        self.impulse_log: list[tuple[int, float, int, float, float]] = []  # (state, t, k, n, τ)
        self.status, self.message = Status.COMPLETED, "time interval completed"
        # a state recorded with its conditions broken sets it
        self.status_box = [self.status, self.message]
        self.first = True
        self.deferred = np.zeros(m, bool)
        self.n = 0

    # -- loads -------------------------------------------------------------------------------

    def factors_at(self, t: float) -> dict[str, float]:
        """The patterns' factors at time t: held ones plus the time functions g(t) (the last
        instant's kept: the load and the record at a step's end ask for the same; not to be
        changed by the caller)."""
        last = self._factors_last
        if last is not None and last[0] == t:
            return last[1]
        c = dict(self.static)
        for name, g in self.loads.items():
            c[name] = c.get(name, 0.0) + float(g(t))
        self._factors_last = (t, c)
        return c

    def water_at(self, t: float, c: dict | None = None) -> np.ndarray:
        """W (m,), N, on the CFEs of ``water_on`` at time t (factors ``c``)."""
        crack, water_on = self.crack, self.water_on
        if crack is None or not water_on.any():
            return np.zeros(self.m)
        c = self.factors_at(t) if c is None else c
        if self.p_open is not None:  # held pressures: W = A (p_held − p_u(t))
            return np.where(water_on, crack.area * (np.nan_to_num(self.p_open)
                                                    - crack.uplift_pressure(c)), 0.0)
        return crack.force_of(water_on, c)

    def water_load(self, W: np.ndarray) -> np.ndarray:
        """The nodal load (ndof,) of crack-water forces W (m,): −Bᵀ [0; W]."""
        z = self.layout.zeros()
        self.layout.normal(z)[:] = W
        return -(self.system.B.T @ z)

    def force_at(self, t: float) -> np.ndarray:
        """F(t) of eq. (7) (ndof,), N: the patterns times their factors, the ground
        acceleration's −M r a_g(t) and the crack water's load."""
        c_t = self.factors_at(t)
        f_of = self.f_of
        if self._F_held_part is None:  # the held patterns' sum, in the order of the loop
            # below, formed once — where no time function scales a held pattern too
            shared = any(n in self.loads for n in self.static)
            F0 = np.zeros(self.ndof)
            for name, c in self.static.items():
                if c and not shared:
                    F0 += c * f_of[name]
            F0.flags.writeable = False
            self._F_held_part = (shared, F0)
        shared, F0 = self._F_held_part
        F = None  # (F⁰ plus the first term: no copy of F⁰ first)
        for name, c in c_t.items():
            if c and (shared or name not in self.static):
                if F is None:
                    F = F0 + c * f_of[name]
                else:
                    F += c * f_of[name]
        if F is None:
            F = F0.copy()
        for g_fun, r in self.r_ground:
            F += float(g_fun(t)) * r
        if self.crack is not None and self.water_on.any():
            F += self.water_load(self.water_at(t, c_t))
        return F

    def rest_force(self, F: np.ndarray, u, v) -> np.ndarray:
        """F − K u − C u̇ on the free DOFs (C without entries: not formed)."""
        free = self.free
        out = np.take(F, free) - np.take(self.Kx(u), free)
        if not self.Cx.empty:
            out = out - np.take(self.Cx(v), free)
        return out

    def _rest_accel(self, F: np.ndarray, u, v) -> np.ndarray:
        """ü = M⁻¹ (F − K u − C u̇ − Bᵀ s) on the free DOFs (eq. (7)) with the engine's s."""
        out = np.zeros(self.ndof)
        free = self.free
        out[free] = self.M_lu.solve(self.rest_force(F, u, v)
                                    - self.BfT @ self.eng.s)
        return out

    # -- the contact problem in accelerations (jumps of the forces at fixed time) -----------

    def metric(self) -> _ContactMetric:
        """The contact rows in the metric of M (:class:`_ContactMetric`): the columns of
        M⁻¹ Bᵀ formed once (2m solves with the mass matrix; a lumped one: a scaling of Bᵀ)
        and kept for every impact, projection and force jump."""
        accel, M_lu = self.accel, self.M_lu
        if "metric" not in accel:
            Bf, BfT = self.Bf, self.BfT
            if isinstance(M_lu, _Diagonal):  # lumped: M⁻¹ Bᵀ is as sparse as Bᵀ
                X = (sp.diags(M_lu.inv) @ BfT).tocsc()  # (by columns, as Bᵀ)
                GM = (Bf @ X).toarray()
            else:
                X = M_lu.solve(np.ascontiguousarray(BfT.toarray())) if self.m else np.zeros(
                    (len(self.free), 0))
                X = X.reshape(len(self.free), self.layout.n)
                GM = np.asarray(Bf @ X)
            accel["X"], accel["GM"] = X, 0.5 * (GM + GM.T)
            accel["metric"] = _ContactMetric(X, accel["GM"], self.layout, self.free, self.ndof)
        return accel["metric"]

    def minv(self, rows: np.ndarray):
        """(z ↦ M⁻¹ B_rᵀ z, B_r M⁻¹ B_rᵀ) for contact rows r (:meth:`metric`)."""
        metric = self.metric()
        rows = np.asarray(rows, dtype=np.int64)
        return functools.partial(metric.apply, rows), metric.gram(rows)

    def accel_engine(self) -> EventEngine:
        """The event engine of the contact problem in accelerations: M ü + Bᵀ s = f with
        the contact conditions on (s, B ü), condensed to B M⁻¹ Bᵀ (built on first use)."""
        accel = self.accel
        if "eng" not in accel:
            self.metric()
            lay = self.layout
            accel["eng"] = EventEngine(SchemeSolver(accel["GM"], lay.zeros()), [self.law],
                                       lay.zeros(), rtol=self.rtol, layout=lay)
        return accel["eng"]

    def accel_forces(self, t_now: float) -> np.ndarray:
        """Contact forces and accelerations of the current scheme at (u, v): the scheme's
        relations in accelerations (stuck: B_τ ü = 0, closed: B_n ü = 0, slipping:
        Q = σ f p, open: s = 0) with M ü + Bᵀ s = F − K u − C v (eq. (7)) — where a switch
        makes the forces jump (a slip that stops, an impact).  Sets them; returns ü."""
        eng, law, m, free, lay = self.eng, self.law, self.m, self.free, self.layout
        M_lu, Bf, BfT = self.M_lu, self.Bf, self.BfT
        Fn = self.force_at(t_now)
        f_rest = self.rest_force(Fn, self.u, self.v)
        out = np.zeros(self.ndof)
        if m and (self.all_rigid or self.split):  # (a compliant layer's force is its
            # spring's: it does not jump, it is held at its value as a load)
            held, soft_cfe = self.held, self.soft_cfe
            ea = self.accel_engine()
            s_held = np.where(held, eng.s, 0.0)
            hM = Bf @ M_lu.solve(np.ascontiguousarray(f_rest - BfT @ s_held))
            states = eng.states.copy()
            free_now = np.zeros(m, bool)  # closed CFEs without force at this instant
            for _ in range(2 * m + 2):  # active set: a stuck CFE beyond its cone slips
                trial = np.where(free_now | soft_cfe, OPEN, states)
                try:  # (redundant constraints: the indeterminate split by capacity)
                    s_new, _ = ea.rates_any(trial, (hM, lay.zeros()), absolute=True)
                except MechanismError:
                    break  # a free mode in accelerations: keep the interpolated forces
                Q, p = lay.split(s_new)
                fp = law.f * p
                tol = 1e-9 * max(float(np.abs(s_new).max(initial=0.0)), eng.F_scale, 1e-300)
                stuck = (states == STICK) & law.frictional & ~free_now & ~soft_cfe
                if lay.n_t == 1:
                    up = stuck & (Q > fp + tol)
                    down = stuck & (Q < -fp - tol)
                    slips = np.where(up, SLIP_POS, SLIP_NEG)
                else:  # a faceted cone (3D): a stuck CFE beyond a facet slips at the
                    # polygon's point nearest to Q; a slip whose force runs along its facet
                    # past an end slips at that vertex (the engine's transition, ``fire``)
                    sliding = law.slipping(states) & ~free_now & ~soft_cfe
                    g = law.margins(Q, p)
                    up = (stuck | sliding) & (g.min(axis=1) < -tol)
                    down = np.zeros(m, bool)
                    past = law.fire(states, np.where(sliding, np.argmin(g, axis=1) + 1, -1))
                    slips = np.where(sliding, past, law.state_at(Q, np.maximum(p, 0.0)))
                # a closed CFE that the accelerations would pull on carries no force at this
                # instant (N = Q = 0, admissible closed); whether it separates, the step's
                # contact problem decides with its gap and velocity (with a consistent mass
                # the acceleration level alone may pull where the step does not)
                pulled = ((trial != OPEN) & (trial != BONDED) & ~law.inert & self.rigid_n
                          & (p < -tol))
                if not (up.any() or down.any() or pulled.any()):
                    eng.s = np.where(held, s_held, s_new)
                    break
                new = states.copy()
                new[up | down] = slips[up | down]
                free_now |= pulled
                for k in np.flatnonzero(new != states):
                    self.log_event(self.n, k, states[k], new[k], t_now)
                states = new
            eng.states = states
            if self.bonds_on:  # bonds the forces' jump takes beyond their strength break here
                tf, _ = eng.tolerances()
                over = (states == BONDED) & law.has_bond & (
                    law.bond_values(*lay.split(eng.s)).min(axis=1) < -tf)
                if over.any():
                    return self.load_jump(np.zeros(self.ndof), t_now, self.n, brk=over)
        out[free] = M_lu.solve(np.ascontiguousarray(f_rest - BfT @ eng.s))
        return out

    def break_bonds(self, E: EventEngine, brk: np.ndarray, t_now: float, step: int) -> np.ndarray:
        """Break the bonds of the CFEs ``brk`` (eq. (12)) at t_now in the engine ``E`` (the
        step's, or the one in accelerations): each takes its Coulomb state (open in tension,
        else stuck or slipping, :meth:`CoulombLaw.broken_state`) and drops the part of its
        forces it can no longer carry (:meth:`CoulombLaw.released`).  Logs a ``broken``
        event per CFE (in the order of the CFEs), books the elastic energy ½ s²/C a
        compliant layer loses with that force as ``fracture``; returns the forces g (2m,)
        released (N).  (The break itself is both drivers':
        :func:`~stepcontact.solver.bonds.break_bonds`.)"""
        g, s_before = _break_bonds(E, self.law, brk, self.events, self.mult, step=step,
                                   state=len(self.rec), segment=0, pattern="dynamic",
                                   lam=t_now)
        self.ledger["fracture"] += float(self.layer_energy(s_before).sum()
                                         - self.layer_energy(E.s).sum())
        return g

    def follow_jump(self, ea: EventEngine, forcing, t_now: float, step: int,
                    depth: int = 0) -> None:
        """Follow the contact problem in accelerations along a jump at fixed time (μ from 0
        to 1 under ``forcing``, events located on the way and logged at t_now).  A bond that
        reaches its strength surface (eq. (12)) on the way (a facet, or the rates of the
        scheme decided drive it beyond) breaks there: what it carried is released first (the
        forces g go to zero along their own jump, forcing B M⁻¹ Bᵀ g, its neighbours breaking
        in turn — the cascade at t_now in its order), then the jump goes on
        (:func:`~stepcontact.solver.jump.follow_jump`: at most 10 m + 10 points)."""
        law, m = self.law, self.m

        def point(state: JumpState):
            old = ea.states.copy()
            dec = ea.decide(state.fired, forcing)
            if dec.switched or state.fired.any():
                ea.snap()
            for k in np.flatnonzero(old != dec.new):
                self.log_event(step, k, old[k], dec.new[k], t_now)
            if self.bonds_on and depth <= m:
                brk = breaking(ea, law, dec.ds, state.fired)
                if brk.any():  # released in a jump of its own first, then on from here
                    self.release(ea, self.break_bonds(ea, brk, t_now, step), t_now, step,
                                 depth)
                    return AGAIN
            return dec.ds, dec.dw

        follow_jump(ea, point, JumpState(np.zeros(m, bool)), stop_at_end=True,
                    max_points=10 * m + 10)

    def release(self, ea: EventEngine, g: np.ndarray, t_now: float, step: int,
                depth: int) -> None:
        """Release the forces g (2m,) of broken bonds (eq. (12)) at t_now in accelerations:
        the load −Bᵀ g they still put on the structure goes to zero (:meth:`follow_jump`)."""
        ea.F_scale = max(ea.F_scale, float(np.abs(g).max(initial=0.0)))
        dh = self.accel["GM"] @ g
        ea.W_scale = max(ea.W_scale, float(np.abs(dh).max(initial=0.0)))
        self.follow_jump(ea, self.pinned(dh), t_now, step, depth + 1)

    def pinned(self, dh: np.ndarray):
        """The forcing (dh, e) of a jump in accelerations: a CFE that slips with a velocity
        keeps slipping whatever its acceleration (its slip rate pinned to its direction)."""
        lay = self.layout
        wd = self.system.B @ self.v
        st = self.eng.states
        if lay.n_t > 1:  # a faceted cone (3D): pinned along its slip direction
            d = self.law.slip_directions(st)
            rate = np.einsum("kj,kj->k", lay.tangential(wd), d)
            moving = rate > 1e-9 * max(np.abs(wd).max(initial=0.0), 1e-300)
            e = lay.zeros()
            lay.tangential(e)[:] = np.where(
                moving[:, None], d * 1e3 * max(float(np.abs(dh).max(initial=0.0)), 1e-300), 0.0)
            return dh, e
        sig = np.where(st == SLIP_POS, 1.0, np.where(st == SLIP_NEG, -1.0, 0.0))
        moving = (sig != 0) & (np.abs(lay.tangential(wd)) > 1e-9 * max(
            np.abs(wd).max(initial=0.0), 1e-300))
        e = lay.zeros()
        lay.tangential(e)[:] = np.where(
            moving, sig * 1e3 * max(float(np.abs(dh).max(initial=0.0)), 1e-300), 0.0)
        return dh, e

    def load_jump(self, dF: np.ndarray, t_now: float, step: int,
                  brk: np.ndarray | None = None) -> np.ndarray:
        """A load that jumps by dF at t_now (the start, a pulse's edge): the contact forces
        jump with it.  Followed in accelerations at fixed time (the engine along the jump,
        events located in it and logged at t_now); returns the accelerations after it and
        sets the contact forces and states.  ``brk``: bonds that break at t_now (eq. (12)),
        broken and released first (:meth:`follow_jump`).  With compliant layers the forces
        follow the displacements and do not jump: a broken bond's layer force drops."""
        eng, law = self.eng, self.law
        if not self.all_rigid:  # compliant layers: the forces follow the displacements
            if brk is not None and brk.any():
                self.break_bonds(eng, brk, t_now, step)
            return self._rest_accel(self.force_at(t_now), self.u, self.v)
        ea = self.accel_engine()
        ea.states = eng.states.copy()
        ea.s = eng.s.copy()
        wa = self.system.B @ self.a
        _, tw = eng.tolerances()
        wd = self.system.B @ self.v
        lay = self.layout
        wa_t, wa_n = lay.split(wa)  # views of wa
        apart = (eng.states == OPEN) & ((-lay.normal(eng.w) > tw) | (lay.normal(wd) < 0))
        wa_n[:] = np.where(apart, -1e30, wa_n)  # open with a gap: cannot close now
        if self.bonds_on:
            # the rows the scheme holds have no relative acceleration: not Newmark's residue
            # there (a correction of it would move the forces off a bond's strength surface)
            st_ = eng.states
            wa_n[(st_ != OPEN) & law.rigid_n & ~law.inert] = 0.0
            wa_t[(((st_ == STICK) & law.frictional) | (st_ == BONDED)) & law.rigid_t
                 & ~law.inert] = 0.0
        ea.w = wa
        ea.F_scale = max(eng.F_scale, float(np.abs(dF).max(initial=0.0)))
        ea.W_scale = float(np.abs(wa[np.abs(wa) < 1e29]).max(initial=0.0)) or 1e-300
        if brk is not None and brk.any():
            self.release(ea, self.break_bonds(ea, brk, t_now, step), t_now, step, 0)
        if np.any(dF != 0.0) or not (self.bonds_on or brk is not None):
            dh = self.Bf @ self.M_lu.solve(np.ascontiguousarray(dF[self.free]))
            if self.bonds_on:  # (bonded at rest: no accelerations give the scale)
                ea.W_scale = max(ea.W_scale, float(np.abs(dh).max(initial=0.0)))
            self.follow_jump(ea, self.pinned(dh), t_now, step)
        eng.states = ea.states.copy()
        eng.s = ea.s.copy()
        return self._rest_accel(self.force_at(t_now), self.u, self.v)

    def settle_water(self, t_now: float, step: int) -> bool:
        """Let the water into the CFEs that opened (out of those that closed) at t_now: the
        crack-water load jumps there by −Bᵀ [0; ΔW], followed like any load jump
        (:meth:`load_jump`, the contact forces with it at fixed time); a CFE that opens under
        it is wet in turn, until the wet set is the scheme's.  Sets the accelerations;
        returns whether the water moved."""
        moved = False
        for _ in range(2 * self.m + 2):
            new = self.wet_of(self.eng.states)
            if np.array_equal(new, self.water_on):
                break
            F_left = self.force_at(t_now)
            self.water_on[:] = new
            if self.p_open is not None:  # ("none": a drain once opened stays drained)
                self.drained |= new & self.drains
            self.a = self.load_jump(self.force_at(t_now) - F_left, t_now, step)
            moved = True
        return moved

    def jump_at_break(self, F_left, u_, v_, t_now: float, step: int):
        """The load's jump at a break of its time functions, t_now: (F, a) after it — the
        contact forces and accelerations follow the jump (without CFEs, M a = F − K u − C v)."""
        F_new = self.force_at(t_now)
        if self.m:
            return F_new, self.load_jump(F_new - F_left, t_now, step)
        free = self.free
        a_new = np.zeros(self.ndof)
        a_new[free] = self.M_lu.solve(self.rest_force(F_new, u_, v_))
        return F_new, a_new

    # -- energy, records, events -------------------------------------------------------------

    def layer_energy(self, s_, x_=None):
        """½ s²/C of every component of a compliant layer (2m,), J (eq. (11); ½ C_n x² of a
        damped layer of compression x, :class:`_DampedLayers`)."""
        soft, layers = self.soft, self.layers
        if not layers and not self.any_soft:  # rigid contact stores nothing
            return self.no_layer_energy
        out = np.where(soft, 0.5 * s_**2 / np.where(soft, self.stiff, 1.0), 0.0)
        if layers:
            self.layout.normal(out)[layers.k] = layers.energy(x_)
        return out

    def strain_energy(self, u_, s_, x_=None):
        """½ uᵀK u plus the layers' energy, J."""
        if not self.layers and not self.any_soft:  # rigid contact stores nothing
            return float(0.5 * u_ @ (self.Kx(u_)) + 0.0)
        return float(0.5 * u_ @ (self.Kx(u_)) + self.layer_energy(s_, x_).sum())

    def book_contact(self, diss: np.ndarray) -> dict[str, float]:
        """The contact's dissipation per component → friction, impact (normal) and damping
        (the damped layers' dashpots)."""
        lay, damped = self.layout, self.damped
        if not self.layers:  # (no dashpots: the normal dissipation is the impacts')
            return {"friction": float(lay.tangential(diss).sum()),
                    "impact": float(lay.normal(diss).sum()), "damping": 0.0}
        return {"friction": float(lay.tangential(diss).sum()),
                "impact": float(lay.normal(diss)[~lay.normal(damped)].sum()),
                "damping": float(diss[damped].sum())}

    def record(self, t: float, kind: str, residual: float) -> int:
        """Record the state at t (fields, contact unknowns, energy ledger); a state whose
        conditions are broken (:func:`_broken_conditions`) ends the run."""
        ledger, eng, crack, u, v = self.ledger, self.eng, self.crack, self.u, self.v
        ledger["kinetic"] = float(0.5 * v @ (self.Mx(v)))
        ledger["strain"] = self.strain_energy(u, eng.s)
        total = ledger["kinetic"] + ledger["strain"]
        ledger["error"] = (total - self.e0 - ledger["external"] + ledger["damping"]
                           + ledger["friction"] + ledger["impact"] + ledger["fracture"]
                           + ledger["numerical"])
        c = self.factors_at(t)
        if crack is None:
            W_t = p_t = self.no_water  # (the recorder copies the row)
        else:
            W_t = self.water_at(t, c)
            p_t = np.where(crack.loaded(self.water_on), W_t / crack.area
                           + crack.uplift_pressure(c), 0.0)
        viol = eng.violation()
        i = self.rec.append(lam=t, segment=0, kind=kind,
                            factors=[c.get(n, 0.0) for n in self.names],
                            s=eng.s, w=eng.w, state=eng.states, residual=residual,
                            violation=viol, reactions=np.zeros(0),
                            water=W_t, pressure=p_t)
        broken = _broken_conditions(viol, residual, t)
        if broken and self.status_box[0] == Status.COMPLETED:
            self.status_box[:] = [Status.VIOLATION, broken]
        for k, arr in (("u", u), ("v", v), ("a", self.a)):
            self.extra[k].append(arr)
        self.energy.append(_LEDGER_ROW(ledger))
        return i

    def log_event(self, step: int, k, was, now, t_ev: float, s_=None, impulse=None) -> None:
        """Log CFE k's transition was → now at t_ev (forces ``s_``, default the engine's;
        an impact's (normal, tangential) impulse) and the first slip, opening, closing
        (:class:`~stepcontact.solver.eventlog.EventLog`)."""
        self.events.event(k, was, now, self.eng.s if s_ is None else s_, step=step,
                          state=len(self.rec), segment=0, pattern="dynamic", lam=t_ev,
                          impulse=impulse, first=self.mult)

    # -- the run -----------------------------------------------------------------------------

    def start(self) -> None:
        """The state at t = 0: the forces of the contact problem in accelerations where the
        loads jump at the start (:meth:`load_jump`), the crack water settled, the round-off of
        the closed rigid CFEs' gaps projected away; recorded as the state ``start``."""
        eng, m, law, rigid_n = self.eng, self.m, self.law, self.rigid_n
        u, v, F, F_held = self.u, self.v, self.F, self.F_held
        if m and self.initial is not None:
            self.a = self.load_jump(F - F_held, 0.0, 0)
            self.first = False
        elif m and self.all_rigid and self.u0 is None and np.any(eng.states == BONDED):
            # rigid bonds from rest: their forces jump with the loads at t = 0
            self.a = self.load_jump(F - F_held, 0.0, 0)
        elif m and self.all_rigid and self.u0 is not None and np.any(eng.states != OPEN):
            # from u0: the forces of the closed rigid contacts are those of the contact
            # problem in accelerations under the loads at t = 0 (_state_at_u0) — the initial
            # state, not events (bonds that break under those loads are)
            rec = self.rec
            n_ev0, mult0 = len(rec.events), dict(self.mult)
            self.a = np.zeros(self.ndof)
            self.a = self.load_jump(F - self.Kx(u) - self.Cx(v), 0.0, 0)
            rec.events[n_ev0:] = [e for e in rec.events[n_ev0:] if self.bonds_on]
            if not self.bonds_on:
                self.mult.update(mult0)
            self.first = False
        else:
            free = self.free
            a = np.zeros(self.ndof)
            a[free] = self.M_lu.solve(self.rest_force(F, u, v)
                                      - self.BfT @ self.s_init)
            self.a = a
        if self.crack is not None and self.initial is not None and self.settle_water(0.0, 0):
            self.F = self.force_at(0.0)
        # a closed rigid CFE is on the obstacle: the round-off of the start's gap (a static
        # solution's, judged closed there to its own scale; or closed at u0 within 1e-9,
        # _state_at_u0) is projected away with the fields (in the metric of M, as after a
        # cut: the first step's constraint would otherwise remove it, seeding the
        # alternating accelerations of Newmark's constrained DOFs), not left as a violation
        # of u_n = 0 (a rigid body at rest has no displacement scale to judge it against)
        on0 = (eng.states != OPEN) & rigid_n & ~law.inert
        if on0.any():
            self.u, self.v, _ = _project(self.system, self.cond, self.metric(), self.u,
                                         self.v, eng.states, law, rigid_n)
            eng.w = self.system.B @ self.u + self.system.w0  # (the projected fields')
            self.layout.normal(eng.w)[on0] = 0.0
        # the scales the start's conditions are judged against (as every step's)
        eng.update_scales()
        eng.F_scale = max(eng.F_scale, float(np.abs(self.F).max(initial=0.0)),
                          float(np.abs(F_held).max(initial=0.0)))
        self.record(0.0, "start", 0.0)
        self.t_run = Stopwatch.start()
        self.t = 0.0
        self.n = 0
        self.n_impacts = 0
        self.zero_restarts = 0
        self.end_time = end_time = float(self.iv.duration)
        breaks = np.unique(np.concatenate(
            [np.asarray(g.breaks(), float) for g in self.loads.values() if hasattr(g, "breaks")]
            + [np.asarray(g.breaks(), float) for g, _ in self.ground if hasattr(g, "breaks")]
            + [np.zeros(0)]))
        self.breaks = breaks[(breaks > 0) & (breaks < end_time)]

    def integrate(self) -> None:
        """The steps from t = 0 to the end of the interval (eqs. (7)–(10)): each followed by
        the engine (:meth:`_follow_step`), cut at its first event (:meth:`_restart`) or
        ended (:meth:`_end_step`); stops where a recorded state breaks the conditions, at a
        stop request of a hook, or where the contact problem fails."""
        dt0, end_time, hooks = self.dt0, self.end_time, self.hooks
        while self.t < end_time - 1e-6 * dt0:
            if self.status_box[0] != Status.COMPLETED:  # conditions broken at a state
                break
            if hooks and any(getattr(hk, "stop_requested", False)  # SIGTERM, Ctrl-C
                             for hk in hooks):
                self.status = Status.INCOMPLETE
                self.message = (f"interrupted at t = {self.t:.6g} s of {end_time:g} s: the "
                                "states up to there are complete")
                break
            self.n += 1
            self._begin_step()
            if self.m:
                restart, mu, ds, dw = self._follow_step()
            else:  # no CFEs: nothing for the engine to follow (a Newmark step, eq. (7))
                restart, mu, ds, dw = None, self.land, self.no_contact, self.no_contact
                self.first = False
            if self.stop:
                break
            landing = restart is None and self.land < 1.0  # a short step: its state at the
            if landing:                                     # break
                states = self.eng.states
                restart = (self.land, mu, ds, dw, states.copy(), states.copy(), {})
            if restart is not None:
                self._restart(restart, landing)
                continue
            self._end_step()

    def _begin_step(self) -> None:
        """Set up step n from t: its length (Δt, or landing on a load's break or the end: a
        whole step under the load's rate continued, its state at the break the convex
        combination of its ends — ``land`` < 1, as a cut at an event: no energy gained), the
        load F̂ of eq. (7) with Newmark's (HHT-α) history, the free response's increment h
        at the contact rows (the engine's forcing), the drift of the slip velocities
        (eq. (9)) and the scales the engine judges against."""
        eng, lay, system, cond = self.eng, self.layout, self.system, self.cond
        dt0, t, F = self.dt0, self.t, self.F
        dt = dt0
        ahead = self.breaks[self.breaks > t + 1e-9 * dt0] if self.breaks.size else self.breaks
        stop_at = min(float(ahead[0]) if ahead.size else np.inf, self.end_time)
        land = 1.0
        if stop_at < t + dt0 * (1 - 1e-6):  # (within 1e-6 Δt: a whole step lands there)
            land = (stop_at - t) / dt0
        nm = self.nm0  # (every step has Δt's coefficients: a short one is a cut of it)
        t1 = t + land * dt
        at_break = bool(ahead.size) and t1 >= float(ahead[0]) - 1e-6 * dt0
        if at_break:
            t1 = float(ahead[0])
        elif land < 1.0:
            t1 = stop_at
        # a step that ends on a break takes the load's left limit there
        F1 = self.force_at(t1 - 1e-9 * dt0) if at_break else self.force_at(t1)
        F_land = F1
        if land < 1.0:  # the load's rate over the part step continued to t + Δt
            F1 = F + (F1 - F) / land
        Fhat = nm.rhs(self.Kx, self.Mx, self.Cx, F1, F, self.u, self.v, self.a)
        y = self.solve_hat(Fhat if self.all_free else np.take(Fhat, self.free))
        h_end = self.Bfx @ y
        # the condensed identity at the step's start: ŵ + Ĝ (s − d ŵ) = h(0) (G t of this
        # state: the last step's residual check formed it, if nothing moved since)
        w_hat = eng.w - system.w0
        t_hat = eng.s - cond.d * w_hat
        gt = self._gt_end
        self._gt_end = None
        h0 = w_hat + (gt[1] if gt is not None and not np.any(gt[0] != t_hat)
                      else cond.product(t_hat))
        wdot = self.Bx @ self.v
        wacc = self.Bx @ self.a
        drift = lay.zeros()
        dr = nm.drift(lay.tangential(wdot), lay.tangential(wacc))
        soft = self.soft_t if lay.n_t == 1 else self.soft_t[:, None]
        lay.tangential(drift)[:] = np.where(soft, 0.0, dr) if self.any_soft_t else dr
        if self.layers:
            self.layers.start(eng.states, eng.s, eng.w, wdot, wacc, nm, drift)
            self.x_start = self.layers.x.copy()
        else:
            self.x_start = self.layers.x
        dh = h_end - h0
        self.forcing = (dh, -drift)
        # a body at rest (after a stop, no load): a step's load at round-off of the
        # displacements (1e-19 m) drives no mechanism of a singular scheme (EventEngine.drives)
        eng.rest_scale = self.rtol * self.w_scale
        # the scale of forces: the contact forces, the loads, and the force that would stop
        # the motion within a step (|M u̇| / Δt: before any contact force, an impact's scale)
        eng.F_scale = max(eng.F_scale, _absmax(eng.s), _absmax(F),
                          _absmax(self.Mx(self.v)) / dt0)
        eng.W_scale = max(eng.W_scale, self.w_scale, _absmax(dh))
        self.s_start, self.w_start = eng.s.copy(), eng.w.copy()
        self.dt, self.nm, self.land, self.t1, self.at_break = dt, nm, land, t1, at_break
        self.F1, self.F_land, self.Fhat, self.h_end = F1, F_land, Fhat, h_end
        self.wdot, self.wacc, self.drift = wdot, wacc, drift
        self.bond_brk = None  # bonds that break where the step is cut (eq. (12))
        self.step_events = 0
        self.stop = False

    def _follow_step(self):
        """Follow the contact problem of the step's end along the step with the engine (μ
        from 0 to ``land``, the linear interpolation of eq. (10)): the scheme decided at the
        step's start (:meth:`_decided_at_start`), events located on the way, contact
        conditions in velocities (eq. (9)).  Returns (restart, μ, ds, dw): ``restart`` the
        cut of the step at an event (frac, μ, rates, old states, new states, stop times) or
        None; sets ``stop`` where the contact problem fails or the events repeat."""
        eng, m, law, rec = self.eng, self.m, self.law, self.rec
        t, dt, land, forcing = self.t, self.dt, self.land, self.forcing
        mu = 0.0
        # CFEs that reached a limit where the last step was cut: the rate problem of this
        # step, at that same instant, decides their state (_deferred)
        fired, self.deferred = self.deferred, np.zeros(m, bool)
        small = 0
        restart = None
        ds = dw = None
        quiet = None
        if (self.quiet_steps and not self.first and not fired.any()
                and len(rec.events) <= self.max_events):
            # a step's start where no CFE is at a limit (_quiet_start); without an event in
            # the step the engine moves straight to its end: the same
            # decision, event search and move as the loop below makes
            quiet = _quiet_start(eng, self.one_law, forcing, land, 1e-10)
            if quiet is not None and quiet[1]:
                ds, dw = quiet[0].ds, quiet[0].dw
                eng.advance(land, ds, dw)
                return None, 0.0 + land, ds, dw
        while True:
            old = eng.states.copy()
            try:
                if quiet is not None:
                    dec, quiet = quiet[0], None
                else:
                    dec = eng.decide(fired, forcing, natural=self.first)
            except (MechanismError, RateProblemFailure) as exc:
                self.status = (Status.EQUILIBRIUM_LOST if isinstance(exc, MechanismError)
                               else exc.status)
                self.message = (f"the contact problem of the step at t = {t + mu * dt:.6g} s "
                                f"has no solution ({type(exc).__name__}: {exc})")
                self.stop = True
                break
            if self.first:
                # contact at rest is the initial scheme, not an event
                touching = ((-self.layout.normal(eng.w) <= 1e-12 * max(self.w_scale, 1e-300))
                            & (old == OPEN))
                old = np.where(touching, dec.new, old)
                self.first = False
            if ds is None:
                restart, changed = self._decided_at_start(old, dec)
                if restart is not None:
                    break
            else:
                changed = np.flatnonzero(old != dec.new)
                if changed.size and mu > 1e-9:
                    # an event inside the step: cut the step here (eq. (10)) and restart; a
                    # CFE that opens or starts to slip is switched by the next step's rate
                    # problem at this instant (its forces are continuous; the part step's
                    # rates, a chord of the whole step, may point the other way than the
                    # motion after the cut: it would switch back at once — the chatter of a
                    # grazing corner)
                    wait = _deferred(old, dec.new, changed, law, self.layers.k)
                    self.deferred[wait] = True
                    keep = dec.new.copy()
                    keep[wait] = old[wait]
                    restart = (mu, mu, ds, dw, old, keep, {})
                    break
            if dec.switched or fired.any():
                eng.snap()
            for k in changed:
                self.log_event(self.n, k, old[k], dec.new[k], t + mu * dt)
                self.step_events += 1
            ds, dw = dec.ds, dec.dw
            if mu >= land:
                break
            dmu, _, fired = eng.next_event(ds, dw, land - mu, 1e-10)
            small = small + 1 if dmu <= 1e-12 else 0
            if small > 100 or len(rec.events) > self.max_events:
                self.status = Status.CYCLING if small > 100 else Status.MAX_EVENTS
                self.message = f"no progress in the step at t = {t:.6g} s: events repeat"
                self.stop = True
                break
            eng.advance(dmu, ds, dw)
            mu += dmu
            if self.bonds_on and np.any(fired & (eng.states == BONDED)):
                # a bond reaches its strength surface (eq. (12)): the step is cut at that
                # time (eq. (10)), the bond breaks there and its forces are released
                self.bond_brk = fired & (eng.states == BONDED)
                restart = (mu, mu, ds, dw, eng.states.copy(), eng.states.copy(), {})
                break
            if mu >= land - 1e-15 and not fired.any():
                break
        return restart, mu, ds, dw

    def _decided_at_start(self, old, dec):
        """The scheme decided at the step's start (μ = 0): bonds on their strength surface
        (eq. (12)) that the rates drive beyond break here; a compliant slip whose velocity
        reverses inside the step stops (eq. (11)); a slip that stops inside the step
        (eq. (10), second row) is cut where its velocity vanishes.  Returns (restart or
        None, the CFEs whose state changed)."""
        eng, law, layers, crack = self.eng, self.law, self.layers, self.crack
        t, dt, nm = self.t, self.dt, self.nm
        if self.bonds_on:
            # at the step's start: bonds on their strength surface that the rates of the
            # scheme decided drive beyond it break here, before anything else
            brk = breaking(eng, law, dec.ds)
            if brk.any():
                self.bond_brk = brk
                return (0.0, 0.0, dec.ds, dec.dw, old, old.copy(), {}), None
        # a compliant slip whose velocity reverses inside the step
        dec.new[_compliant_stops(eng, law, dec, self.w_start, self.wdot, self.wacc, nm,
                                 dt)] = STICK
        if self.layout.n_t > 1:  # (3D) a vertex slip that ends at rest: no turn onto a facet
            dec.new[_vertex_stops(eng, law, dec, self.w_start, self.wdot, self.wacc, nm,
                                  dt)] = STICK
        eng.states = dec.new
        changed = np.flatnonzero(old != dec.new)
        if not changed.size:
            return None, changed
        got: dict = {}  # (the old scheme's rates, asked for again below: the same call)

        def rates_of(states, forcing):
            if "rates" not in got:
                try:
                    got["rates"] = eng.rates_any(states, forcing)
                except MechanismError as exc:
                    got["rates"] = exc
            if isinstance(got["rates"], MechanismError):
                raise got["rates"]
            return got["rates"]

        times = _stick_times(eng, old, dec.new, changed, self.forcing, self.w_start,
                             self.wdot, 0.0, t, dt, nm.c1, nm, self.wacc, law, rates_of)
        later = bool(times) and min(times.values()) > t + 1e-9 * dt
        now = changed[~np.isin(changed, list(times))] if later else changed
        # changes at the step's start that the step cannot carry (the schemes of its part
        # steps are fixed): beside a slip that stops later in the step (the part step runs
        # under the old scheme), and a damped layer that opens or closes (its shift e
        # depends on the state).  They are made here at t and the step restarts from the
        # same point (twice at most: then the step goes on)
        sw = changed[np.isin(changed, layers.k)
                     & ((old[changed] == OPEN) != (dec.new[changed] == OPEN))]
        # and a CFE that opens (closes) where crack water enters (leaves): the load of the
        # step changes with it
        wet_moves = crack is not None and not np.array_equal(self.wet_of(dec.new),
                                                             self.water_on)
        # and a rigid slip that stops here: its friction force jumps to what equilibrium
        # at t requires (re-solved in accelerations, not the slip's f p)
        stops = (self.all_rigid or self.split) and bool(np.any(
            (_slipping(old[now]) & (dec.new[now] == STICK) | _onto_facet(old[now], dec.new[now]))
            & law.rigid_t[now]))
        if self.zero_restarts < 2 and ((later and now.size) or sw.size or wet_moves
                                       or stops):
            keep = old.copy()
            keep[now] = dec.new[now]
            return (0.0, 0.0, dec.ds, dec.dw, old, keep, {}), changed
        # decided at the step's start: a slip that stops inside the step is cut where its
        # velocity vanishes; the other changes happen at t
        if times and min(times.values()) > t + 1e-9 * dt:
            try:
                ds_o, dw_o = rates_of(old, self.forcing)
            except MechanismError:
                ds_o = None
            if ds_o is not None:
                t_cut = min(times.values())
                frac = min((t_cut - t) / dt, self.land)
                t_cut = min(t_cut, t + frac * dt)
                # another CFE's event under the slipping scheme before the slip stops: the
                # step is cut there first, the schemes unchanged (the next step decides at
                # that point)
                eng.states, new_now = old, eng.states
                try:
                    _d, mu_ev, _f = eng.next_event(ds_o, dw_o, frac, 1e-10)
                finally:
                    eng.states = new_now
                if 1e-9 < mu_ev < frac * (1 - 1e-9):
                    return (mu_ev, 0.0, ds_o, dw_o, old, old.copy(), {}), changed
                keep = old.copy()
                for k, tk in times.items():
                    if tk <= t_cut * (1 + 1e-12):
                        keep[k] = dec.new[k]
                return (frac, 0.0, ds_o, dw_o, old, keep, times), changed
        return None, changed

    def cut(self, frac, mu, ds_o, dw_o, run_states, F_i=None, part="cut"):
        """The state at t + frac·Δt of the step under the scheme before an event (eq. (8):
        ü linear in time over the step, with the step's end under that scheme; the event's
        time from the interpolation (10)), the works of the part step in the ledger — frac
        times the whole step's (load F1 at its end), as the state is — (the integrator's
        share in ``parts[part]``).  ``F_i``: the load there (default F(t + frac·Δt); a
        break's left limit for a landing).  Returns (u, v, s, w, F) there."""
        eng, system, cond, layers = self.eng, self.system, self.cond, self.layers
        u, v, t = self.u, self.v, self.t
        self._cut_books = None
        if frac == 0.0 and mu == 0.0:  # a restart at the step's start: nothing moved
            return (u, v, eng.s.copy(), system.B @ u + system.w0,
                    self.force_at(t) if F_i is None else F_i)
        s_start, x_start, F, F_end = self.s_start, self.x_start, self.F, self.F1
        s_end = eng.s + (1.0 - mu) * ds_o
        w_end = eng.w + (1.0 - mu) * dw_o + self.drift
        tv = s_end - cond.d * (w_end - system.w0)
        u_end = np.zeros(self.ndof)
        u_end[self.free] = self.solve_hat(np.take(self.Fhat, self.free) - self.BfTx @ tv)
        v_end = self.nm.velocity(u_end, u, v, self.a)
        tau = frac * self.dt
        # linear between the step's ends (a convex combination of two Newmark states: stable
        # for the stiff modes, where the expansion (8) in powers of τ is not)
        u_i = u + frac * (u_end - u)
        v_i = v + frac * (v_end - v)
        s_i = eng.s + (frac - mu) * ds_o
        F_i = self.force_at(t + tau) if F_i is None else F_i
        w_i = self.Bx @ u_i + system.w0
        x_i = layers.at(run_states, w_i, frac) if layers else None
        # the works of the part step: the share frac of the whole step's (the state is the
        # same convex combination of the step's ends; a Newmark step's works are its energy
        # change, so the state's energy, convex, lies below them: the interpolation removes
        # ½ frac (1 − frac) of the energy norm of the step's increment, never adds).  (The
        # trapezoid over the part step instead misses the curvature of the contact forces'
        # work along the step — a CFE that unloads to its limit: its friction force falls —
        # which the linear state does not follow: a gain where that work is front-loaded.)
        du_w = u_end - u
        x_end = (layers.at(run_states, system.B @ u_end + system.w0, 1.0) if layers
                 else None)
        diss = frac * (0.5 * (s_start + s_end) * (self.Bx @ du_w)
                       - (self.layer_energy(s_end, x_end)
                          - self.layer_energy(s_start, x_start)))
        contact = self.book_contact(diss)
        works = {"external": frac * float(du_w @ (0.5 * (F + F_end))),
                 "damping": (frac * float(du_w @ (self.C @ (0.5 * (v + v_end))))
                             if not self.Cx.empty else 0.0)
                 + contact["damping"],
                 "friction": contact["friction"], "impact": contact["impact"]}
        ledger = self.ledger
        for key, val in works.items():
            ledger[key] += val
        # the interpolation (8) is not a Newmark step: what it adds or removes is the
        # integrator's (numerical) share of the part step, booked by _restart with the
        # state's energy (from the projected state's, :meth:`_book_cut`: no products of K
        # and M with the state at the cut)
        e_start = 0.5 * v @ (self.Mx(v)) + self.strain_energy(u, s_start, x_start)
        self._cut_books = (part, works["external"] - works["damping"] - works["friction"]
                           - works["impact"], e_start,
                           float(self.layer_energy(s_i, x_i).sum()))
        return u_i, v_i, s_i, w_i, F_i

    def _restart(self, restart, landing: bool) -> None:
        """Cut the step at its first event (eq. (10)) or where it lands on a break: the state
        there (:meth:`cut`), an impact's velocity jumps (:meth:`_impact_at`), the new scheme
        logged and projected onto, the forces that jump re-solved in accelerations (bonds
        that break released, eq. (12)); recorded, and the integration restarts there."""
        eng, lay, system, law, rec = self.eng, self.layout, self.system, self.law, self.rec
        t, dt, dt0, n, land = self.t, self.dt, self.dt0, self.n, self.land
        frac, mu_r, ds_o, dw_o, old, new_states, times = restart
        self.zero_restarts = self.zero_restarts + 1 if frac == 0.0 else 0
        # a cut where the step lands on a break: the load's left limit there, its jump
        # after the cut
        lands = (land < 1.0 or self.at_break) and t + frac * dt >= self.t1 - 1e-9 * dt0
        n_events = len(rec.events)
        u_i, v_i, s_i, w_i, F_i = self.cut(frac, mu_r, ds_o, dw_o, old,
                                           self.F_land if lands else None,
                                           "short_steps" if landing else "cut")
        t_i = self.t1 if lands else t + frac * dt
        closing = np.flatnonzero((old == OPEN) & (new_states != OPEN) & self.rigid_n)
        lay.normal(s_i)[closing] = 0.0
        lay.normal(w_i)[closing] = 0.0  # on the obstacle (the root of eq. (10))
        imp: dict[int, tuple[float, float]] = {}  # CFE → (normal, tangential) impulse
        bounced = closed_as = np.zeros(0, np.int64)
        ke_impact = 0.0  # the kinetic energy the impact takes
        if closing.size:  # an impact: normal velocities jump (Newton's law)
            ke0 = self.ledger["impact"]
            v_i, imp, bounced, closed_as = self._impact_at(old, new_states, closing, s_i,
                                                           v_i, t_i)
            ke_impact = self.ledger["impact"] - ke0
        new_states = self.layers.closing_states(old, new_states)
        for k in bounced:  # the contact of a rebound lasts an instant: closed, opened
            if old[k] == OPEN:
                self.log_event(n, k, OPEN, closed_as[k], t_i, impulse=imp.get(int(k)))
                self.log_event(n, k, closed_as[k], OPEN, t_i)
        n_logged = len(rec.events)
        for k in np.flatnonzero(old != new_states):
            self.log_event(n, k, old[k], new_states[k], times.get(int(k), t_i),
                           impulse=imp.get(int(k)))
        eng.states = new_states.copy()
        u_i, v_i, corrections = _project(system, self.cond, self.metric(), u_i, v_i,
                                         new_states, law, self.rigid_n)
        self._book_cut(u_i, v_i, corrections, ke_impact)
        w_i = system.B @ u_i + system.w0
        on = (new_states != OPEN) & self.rigid_n
        lay.normal(w_i)[on] = 0.0  # on the obstacle (round-off of the projection)
        if self.layers:
            self.layers.restart(old, new_states, s_i, w_i, system.B @ v_i, frac)
        eng.s, eng.w = s_i, w_i
        eng.snap()
        self.u, self.v = u_i, v_i
        self.F = F_i
        if self.bond_brk is not None:  # the bonds break: their forces are released here
            self.a = self.load_jump(np.zeros(self.ndof), t_i, n, brk=self.bond_brk)
        elif closing.size or np.any(_slipping(old) & ~_slipping(new_states)
                                    & (new_states != OPEN) | _onto_facet(old, new_states)):
            self.a = self.accel_forces(t_i)  # the forces jump: an impact, a slip that stops
            # (3D: or turns from a vertex onto a facet, its force from the vertex onto it)
            # a stop that the forces at this instant undo (the CFE slips on the same way: its
            # velocity only touched zero) is no event: the rate problem in accelerations
            # decided the state
            undone = ((old != new_states) & (new_states == STICK) & (eng.states == old)
                      & _slipping(old))
            if undone.any():
                rec.events[n_logged:] = [e for e in rec.events[n_logged:]
                                         if not undone[e.cfe]]
        else:
            self.a = self._rest_accel(F_i, self.u, self.v)
        self.t = t = t_i
        if lands and self.at_break:  # the load jumps here: the contact forces with it
            self.F, self.a = self.jump_at_break(self.F, self.u, self.v, t, n)
        if self.crack is not None and self.settle_water(t, n):
            self.F = self.force_at(t)
        self.record(t, "event" if len(rec.events) > n_events or not landing else "step", 0.0)
        if landing:
            for hk in self.hooks:
                if hasattr(hk, "after_step"):
                    hk.after_step(n, t, self.end_time)

    def _book_cut(self, u_p, v_p, corrections, ke_impact: float) -> None:
        """The integrator's (numerical) shares of a cut (:meth:`cut`) and of the projection
        after it (:func:`_project`) in the ledger, from the energy of the projected state
        (u_p, v_p), whose products with K and M the next steps use anyway: the state at the
        cut differs from it by the projection's corrections Δu = M⁻¹ B_rᵀ z_u, Δu̇ = M⁻¹ B_rᵀ
        z_v (on the free DOFs), so its energy is that of (u_p, v_p) plus

            z_vᵀ Xᵀ (M u̇_p) + ½ z_vᵀ (B M⁻¹ Bᵀ) z_v + z_uᵀ Xᵀ (K u_p) + ½ z_uᵀ (Xᵀ K X) z_u

        (X = M⁻¹ B_fᵀ) — the projection's share, without the round-off of two large energies'
        difference — and the kinetic energy an impact at the cut took (booked as ``impact``)."""
        Mx, Kx = self.Mx, self.Kx
        e_p = 0.5 * v_p @ (Mx(v_p)) + 0.5 * u_p @ (Kx(u_p))
        d_proj = self.projection_energy(u_p, v_p, *corrections) if corrections else 0.0
        self.ledger["numerical"] += d_proj
        self.parts["projection"] += d_proj
        if self._cut_books is None:  # (a restart at the step's start: nothing moved)
            return
        part, works, e_start, layer_i = self._cut_books
        self._cut_books = None
        d_num = float(works - (e_p + d_proj + ke_impact + layer_i - e_start))
        self.ledger["numerical"] += d_num
        self.parts[part] += d_num

    def projection_energy(self, u_p, v_p, zu: np.ndarray, zv: np.ndarray, du: np.ndarray,
                          dv: np.ndarray) -> float:
        """The energy ½ u̇ᵀMu̇ + ½ uᵀKu that the projection (:func:`_project`) removed from the
        state it made (u_p, v_p) by the corrections −du = −X z_u, −dv = −X z_v on the free
        DOFs (``zu``, ``zv`` (2m,), X = M⁻¹ B_fᵀ): see :meth:`_book_cut`.  XᵀKX (2m × 2m) is
        formed once where X is sparse (a lumped mass); else the correction's product with K
        is made."""
        metric, free = self.metric(), self.free
        X = metric.X
        out = 0.0
        if zv.any():
            out += float(dv @ np.take(self.Mx(v_p), free) + 0.5 * zv @ (metric.GM @ zv))
        if zu.any():
            if sp.issparse(X):
                if metric.XtKX is None:
                    Kff = self.K[free][:, free]
                    XtKX = (X.T @ (Kff @ X)).toarray()
                    metric.XtKX = 0.5 * (XtKX + XtKX.T)
                quad = float(zu @ (metric.XtKX @ zu))
            else:
                du_all = np.zeros(self.ndof)
                du_all[free] = du
                quad = float(du_all @ (self.K @ du_all))
            out += float(du @ np.take(self.Kx(u_p), free)) + 0.5 * quad
        return out

    def _impact_at(self, old, new_states, closing, s_i, v_i, t_i):
        """An impact where rigid CFEs ``closing`` close at t_i: the normal velocities of the
        closing (and closed) CFEs jump to −e times their approach velocities by impulses,
        with friction's impulses by Coulomb's law (:func:`_impact`); a CFE still sliding
        after it slips on; with e > 0 a CFE that leaves the obstacle opens (Newton's rebound,
        its ``new_states`` and ``s_i`` changed in place).  Books the kinetic energy taken as
        ``impact`` and logs the impulses.  Returns (v, impulses, rebounding CFEs, their
        states while closed)."""
        law, cond, Mx = self.law, self.cond, self.Mx
        closed_now = np.flatnonzero((old != OPEN) & self.rigid_n)
        cand = np.union1d(closing, closed_now)
        got: dict = {}
        v_before = v_i
        e_k = _restitution_of(cond, self.layout, self.restitution, v_i, self.a, cand, self.dt0)
        v_new, sig = _impact(self.system, cond, self.minv, v_i, cand, closing, e_k, law, old,
                             got)
        self.ledger["impact"] += float(0.5 * v_i @ (Mx(v_i)) - 0.5 * v_new @ (Mx(v_new)))
        v_i = v_new
        # a CFE still sliding after its impact slips on (with its velocity)
        if sig.ndim > 1:  # (3D: the facet or vertex whose normal cone holds its velocity)
            on = np.any(sig != 0, axis=1) & np.isin(cand, closing)
            new_states[cand[on]] = law.slip_state_towards(cand[on], sig[on])
            sig = np.zeros(0)
        for k_, sg in zip(cand[:len(sig)], sig, strict=True):
            if sg != 0 and k_ in closing:
                new_states[k_] = SLIP_POS if sg > 0 else SLIP_NEG
        bounced = closed_as = np.zeros(0, np.int64)
        if self.restitution > 0.0:  # Newton's rebound: a CFE leaving the obstacle opens
            bounced = _rebounding(cond, self.layout, v_before, v_i, cand, old)
            closed_as = new_states.copy()
            new_states[bounced] = OPEN
            self.layout.tangential(s_i)[bounced] = 0.0
            self.layout.normal(s_i)[bounced] = 0.0
        imp = {int(k_): (-float(pk), float(qk))
               for k_, pk, qk in zip(cand, got["p"], got["Q"], strict=True)
               if pk != 0.0 or qk != 0.0}
        for k_, (pn_, qt_) in sorted(imp.items()):
            self.impulse_log.append((len(self.rec), t_i, k_, pn_, qt_))
        self.n_impacts += 1
        return v_i, imp, bounced, closed_as

    def _end_step(self) -> None:
        """The end of a step without a cut: the real mutual displacements (the drift of
        eq. (9) added), the fields from F̂ (eq. (7)) and Newmark's update, the works of the
        step in the ledger (HHT-α's and a short step's share as numerical), the load's jump
        at a break, the crack water, and the record every ``record_every`` steps."""
        eng, system, cond, layers = self.eng, self.system, self.cond, self.layers
        ledger, Mx, Cx = self.ledger, self.Mx, self.Cx
        u, v, a, F, F1 = self.u, self.v, self.a, self.F, self.F1
        s_start, x_start, dt, dt0, n = self.s_start, self.x_start, self.dt, self.dt0, self.n
        self.zero_restarts = 0
        eng.w += self.drift
        gone = eng.states == OPEN
        if gone.any():
            s_t, s_n = self.layout.split(eng.s)  # views
            s_t[gone] = 0.0  # an open CFE carries nothing (not the scheme solve's round-off)
            s_n[gone] = 0.0
        if layers:
            layers.x = layers.at(eng.states, eng.w, 1.0)
            layers.sync(eng.states, eng.s, eng.w)
        w_hat = eng.w - system.w0
        tvec = eng.s - cond.d * w_hat
        if self.all_free:
            u_new = self.solve_hat(self.Fhat - self.BfTx @ tvec)
        else:
            u_new = np.zeros(self.ndof)
            u_new[self.free] = self.solve_hat(np.take(self.Fhat, self.free) - self.BfTx @ tvec)
        a_new, v_new = self.nm.end(u_new, u, v, a)
        du = u_new - u
        w_ext = float(du @ (0.5 * (F + F1)))
        ledger["external"] += w_ext
        F = F1
        damped = not Cx.empty
        vbar = 0.5 * (v + v_new) if damped else None
        w_damp = float(du @ (Cx(vbar))) if damped else 0.0
        ledger["damping"] += w_damp
        # contact work −s̄·Δw on the structure; what the layers store is not dissipated
        sbar = 0.5 * (s_start + eng.s)
        # (Δw = B Δu: the kinematics of the fields, not the engine's snapped values)
        diss = sbar * (self.Bx @ du)
        if layers or self.any_soft:
            diss = diss - (self.layer_energy(eng.s) - self.layer_energy(s_start, x_start))
        for key, val in self.book_contact(diss).items():
            ledger[key] += val
        if self.alpha or dt < dt0:  # HHT-α and short steps dissipate: their share is what
            # the works leave
            e_step0 = 0.5 * v @ (Mx(v)) + self.strain_energy(u, s_start, x_start)
            e_step1 = 0.5 * v_new @ (Mx(v_new)) + self.strain_energy(u_new, eng.s)
            d_num = w_ext - w_damp - float(diss.sum()) - (e_step1 - e_step0)
            ledger["numerical"] += d_num
            self.parts["hht" if dt == dt0 else "short_steps"] += d_num
        self.u, self.v, self.a, self.F = u_new, v_new, a_new, F
        self.t = t = self.t1
        if self.at_break:  # the load jumps here: the contact forces and accelerations with it
            self.F, self.a = self.jump_at_break(F, u_new, v_new, t, n)
        if self.crack is not None and self.settle_water(t, n):  # (a catch-all: a wet set
            self.F = self.force_at(t)       # that moved at the step's start is settled there)
            self.step_events += 1
        self.w_scale = max(self.w_scale, _absmax(eng.w), _absmax(self.u))
        last = t >= self.end_time - 1e-6 * dt0
        re = self.record_every
        if re <= 1 or n % re == 0 or self.step_events or last:
            h_end = self.h_end
            gt = cond.product(tvec)
            self._gt_end = (tvec, gt)  # (the next step's start is this state: its G t)
            r = h_end - (w_hat + gt)
            res_rel = float(_absmax(r) / max(_absmax(h_end), self.w_scale, 1e-300))
            self.record(t, "event" if self.step_events else "step", res_rel)
        for hk in self.hooks:
            if hasattr(hk, "after_step"):
                hk.after_step(n, t, self.end_time)

    def result(self) -> DynamicResult:
        """The run's :class:`DynamicResult`: the recorded states, events, impulses, energy
        ledger, counters and the status (a state recorded with its conditions broken ends
        the run with status ``violation``, never "completed")."""
        status, message = self.status, self.message
        if status == Status.COMPLETED and self.status_box[0] != Status.COMPLETED:
            status, message = self.status_box
        mult, rec, cfe, m, system = self.mult, self.rec, self.cfe, self.m, self.system
        if status != Status.COMPLETED:
            mult["equilibrium_lost"] = self.t if status == Status.EQUILIBRIUM_LOST else None
        rec.multipliers.append(Multipliers(0, "dynamic", **mult))
        counters = dict(self.cond.counters) | self.schemes.counters | self.eng.counters | {
            "events": len(rec.events), "steps": self.n, "impacts": self.n_impacts,
            **self.t_setup,
            **{f"numerical_{k}": v for k, v in self.parts.items()},
            **self.t_run.counters("run"), "ndof": self.ndof, "cfes": m}
        stage_arrays, extra = self.stage_arrays, self.extra
        return build_result(
            rec, cls=DynamicResult, cfe=cfe,
            cfe_data=cfe_arrays(cfe, bond=self.bond_cols if self.bonds_on else None,
                                damping=True),
            pattern_names=self.names, segments=[("dynamic", 0.0, float(self.t))],
            status=status, message=message, counters=counters,
            geometry=result_geometry(system), crack=self.crack is not None,
            units={"lam": "s", "N": "N", "Q": "N", "un": "m", "ut": "m", "sigma_n": "Pa",
                   "tau": "Pa", "u": "m", "stress": "Pa", "position": "m", "area": "m2",
                   **({"ground_acceleration": GROUND_CONVENTION} if self.ground else {}),
                   **({"crack_water": crack_water_note(self.iv.crack_water)}
                      if self.crack is not None else {})},
            u=extra["u"].array(), v=extra["v"].array(), a=extra["a"].array(),
            energy=dict(zip(ENERGY_TERMS, np.array(self.energy, float).reshape(
                -1, len(ENERGY_TERMS)).T.copy(), strict=True)), dt=self.dt0,
            impulses=_impulse_arrays(self.impulse_log),
            _recover=None if system.discrete is not None else _Stresses(system),
            **({} if stage_arrays is None else stage_fields(
                np.full(len(rec), stage_arrays["last_stage"], np.int64),
                stage_arrays["stage_names"], stage_arrays["stage_cfes"],
                stage_arrays["stage_bodies"])),
        )


def _broken_conditions(violation: float, residual: float, t: float) -> str:
    """Why a recorded dynamic state is not a solution, or "": its relative violation of the
    contact conditions (1) (or its residual of equilibrium) beyond
    :data:`~stepcontact.solver.reporting.VIOLATION_LIMIT`, the static solver's limit — a run
    that reaches such a state ends with status ``violation`` there, never "completed"."""
    for what, val in (("the contact conditions are violated", violation),
                      ("equilibrium is violated (residual)", residual)):
        if not val <= VIOLATION_LIMIT:
            return (f"{what} by {val:.2e} (relative, limit {VIOLATION_LIMIT:.0e}) at "
                    f"t = {t:.6g} s; the run stops here")
    return ""


def _impulse_arrays(log: list[tuple[int, float, int, float, float]]) -> dict[str, np.ndarray]:
    """The impulse log (state, t, CFE, normal, tangential) as the arrays of
    :attr:`DynamicResult.impulses`."""
    cols = list(zip(*log, strict=True)) if log else [()] * 5
    return {"state": np.asarray(cols[0], np.int64), "time": np.asarray(cols[1], float),
            "cfe": np.asarray(cols[2], np.int64), "normal": np.asarray(cols[3], float),
            "tangential": np.asarray(cols[4], float)}


__all__ = ["ENERGY_TERMS", "DynamicResult", "Interval", "dynamic_interval", "integrate"]
