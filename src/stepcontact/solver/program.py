"""The whole program of a model in one call: :func:`run` (``sc.run``), and the public Newmark
driver :func:`solve_dynamic` (``sc.solve_dynamic``), the one place that uses both drivers for
one interval: it runs the static stages a dynamic interval starts from (or checks a result
loaded from a file against them), then integrates the interval
(:func:`stepcontact.solver.dynamic.integrate`).

A model's program is its construction stages (:class:`~stepcontact.model.Stage`) with their
load segments and the dynamic intervals of the stages before the last, all run by the static
driver (:func:`~stepcontact.solver.static.solve_static`; the intervals of the stages are kept
in ``StaticResult.dynamics``), then the model's own dynamic interval (``model.dynamics``,
:class:`~stepcontact.model.DynamicInterval`) from the completed last state by the Newmark
driver (:func:`solve_dynamic`, eqs. (7)–(10)).  :func:`run` chains them exactly as
``stepcontact run MODEL.toml`` and a model-file sweep do (both call it), so a script, the
command line and a study give the same states and events.

Example
-------
>>> import stepcontact as sc
>>> out = sc.run(sc.load_model("slab.toml"))               # doctest: +SKIP
>>> out.static.status, out.dynamic.time[-1]                 # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from stepcontact.enums import Status
from stepcontact.errors import ModelError
from stepcontact.fem.assembly import System, assemble
from stepcontact.solver import dynamic as _dynamic
from stepcontact.solver import static as _static
from stepcontact.solver.dynamic import DynamicResult
from stepcontact.solver.recovery import stage_plan
from stepcontact.solver.staging import in_stages

if TYPE_CHECKING:
    from stepcontact.model import DiscreteModel, Model
    from stepcontact.results.result import StaticResult
    from stepcontact.solver.condensation import Condensation


@dataclass(frozen=True)
class NotRun:
    """A dynamic interval the model asks for that the run did not reach, and why."""

    #: ``"dynamics"`` (the model's interval) or ``"dynamics of stage 'NAME'"``
    interval: str
    #: why it was not run (the static program stopped before it: its status and message)
    reason: str


@dataclass(frozen=True)
class ProgramResult:
    """What :func:`run` returns: the static program's result (with the dynamic intervals of
    its stages in ``static.dynamics``), the model's final dynamic interval, and the intervals
    asked for but not run."""

    #: the stages, their segments and the dynamic intervals between them
    static: StaticResult
    #: the model's dynamic interval (``model.dynamics``) from the completed last static state;
    #: None when the model has none or it was not run (see ``not_run``)
    dynamic: DynamicResult | None
    #: the dynamic intervals asked for that the program did not reach, in program order
    not_run: tuple[NotRun, ...] = ()

    @property
    def stage_dynamics(self) -> dict[str, DynamicResult]:
        """The dynamic intervals of the stages before the last, by stage name (run inside the
        static program: ``static.dynamics``)."""
        return dict(self.static.dynamics or {})

    @property
    def completed(self) -> bool:
        """True when every part of the program ran to its end: the static program completed,
        no dynamic interval was left out, and the final interval (if any) completed."""
        return (self.static.status == Status.COMPLETED and not self.not_run
                and (self.dynamic is None or self.dynamic.status == Status.COMPLETED))


def _model_of(model) -> Model | DiscreteModel:
    return model.model if isinstance(model, System) else model


def check_dynamic_mass(model: Model | DiscreteModel | System) -> None:
    """A model with a dynamic interval needs mass on every body that can move: checked before
    the static program (:func:`stepcontact.fem.mass.check_mass`; ModelError naming the body),
    so that a missing density (kg/m³) is not found only after the static run."""
    m = _model_of(model)
    stages = [st for st in getattr(m, "stages", ()) if st.dynamics is not None]
    if getattr(m, "dynamics", None) is None and not stages:
        return
    if all(float(b.material.density if hasattr(b, "material") else b.density) > 0
           for b in m.bodies):
        return  # (no body without density: nothing to assemble for the check)
    from stepcontact.fem.mass import check_mass

    check_mass(model if isinstance(model, System) else assemble(m),
               "dynamics" if not stages else f"stage '{stages[0].name}'.dynamics")


def dynamics_not_run(model: Model | DiscreteModel | System,
                     static: StaticResult) -> tuple[NotRun, ...]:
    """The dynamic intervals the model asks for that the static program ``static`` did not
    reach (it stopped before them: lost equilibrium, or no answer), each with the reason."""
    m = _model_of(model)
    why = (f"the load program before it stopped ({static.status.value}: {static.message}); "
           "the dynamic interval starts from the program's completed last state")
    done = set(static.dynamics or {})
    out = [NotRun(f"dynamics of stage '{st.name}'", why)
           for st in getattr(m, "stages", ())[:-1]
           if st.dynamics is not None and st.name not in done]
    if getattr(m, "dynamics", None) is not None and static.status != Status.COMPLETED:
        out.append(NotRun("dynamics", why))
    return tuple(out)


@_dynamic.one_thread
def solve_dynamic(
    model,
    *,
    dt: float | None = None,
    duration: float | None = None,
    loads: Mapping[str, object] | None = None,
    mass: str | sp.spmatrix = "consistent",
    damping: tuple[float, float] = (0.0, 0.0),
    initial: StaticResult | None = None,
    u0: np.ndarray | None = None,
    v0: np.ndarray | None = None,
    ground_acceleration: object = None,
    restitution: float = 0.0,
    alpha: float = 0.0,
    record_every: int = 1,
    max_events: int = 1_000_000,
    rtol: float = 1e-10,
    hooks: Sequence = (),
    stage: int | str | None = None,
    backend: str = "auto",
    max_steps: int | None = None,
    crack_water: str | None = None,
) -> DynamicResult:
    """Newmark time integration with the contact state followed exactly at every step, eqs.
    (7)–(10) (:mod:`stepcontact.solver.dynamic`'s docstring; the steps are
    :func:`stepcontact.solver.dynamic.integrate`'s).

    Parameters
    ----------
    model : Model, DiscreteModel or System
    dt, duration : float
        Time step and length of the analysis, s.  Omitted (both): the model's dynamic
        interval (:class:`~stepcontact.model.DynamicInterval`, ``model.dynamics``) gives them
        and the loads, mass, damping, restitution and recording.
    loads : {pattern: time function}
        The load patterns applied in time, each times its function g(t)
        (:mod:`stepcontact.model.timefunction`); patterns held by ``initial`` stay at their
        factors.
    mass : "consistent", "lumped" or a matrix
        Continua: consistent or HRZ-lumped mass (frames lumped); a (ndof, ndof) matrix for a
        discrete model.
    damping : (a₀, a₁)
        Rayleigh damping C = a₀ M + a₁ K (:func:`stepcontact.fem.mass.rayleigh_coefficients`);
        the dashpots of the model's springs (``Spring.damping``, N·s/m) are added to it.
    initial : StaticResult, optional
        Start from the last state of a static run of the same model (displacements, contact
        forces and states; its pattern factors are held).
    u0, v0 : (ndof,) arrays, optional
        Initial displacements and velocities (m, m/s).  The contact state at t = 0
        (:func:`_state_at_u0`): with ``initial``, its states and forces (every rigid CFE
        closed there must be closed at u0); from u0 alone, the CFEs whose gap B u0 + w⁰ is
        closed (and not separating under v0) closed, the others open, the closed rigid ones'
        forces those of the contact problem in accelerations under the loads at t = 0 (the
        rate problem there; not events: a CFE that opens or slips under the loads at t = 0
        starts so), a compliant layer's its spring's.  A static state
        given as u0 (its loads as time functions, e.g. ``Constant(1.0)``) thus gives the
        answer of ``initial=``.
    ground_acceleration : (time function, (dx, dy)), record or GroundMotion, optional
        Ground acceleration a_g(t) (m/s²) along the unit direction (dx, dy) — (dx, dy, dz) in
        3D, or an axis "x", "y", "z" —: the effective load −M r a_g(t), r the rigid
        translation along it; a list of such pairs, an earthquake record
        (:class:`~stepcontact.model.records.AccelerationRecord`) or the records that act
        together (:class:`~stepcontact.model.records.GroundMotion`, e.g. horizontal and
        vertical) are applied together.  A positive a_g accelerates the ground along +d;
        the displacements, velocities and accelerations reported are relative to the ground
        (the result's ``units["ground_acceleration"]`` says so).  Default: the model's
        dynamic interval's ``ground``.
    restitution : float
        Newton's coefficient e ∈ [0, 1] of the impacts of rigid contacts: the step is cut
        where a CFE closes, the normal velocities of the closing (and closed) CFEs jump to
        −e times their approach velocities by impulses (with friction's impulses by
        Coulomb's law), and the integration restarts there; a CFE that leaves the obstacle
        opens at that instant (events ``closed`` and ``opened`` at one time), except where
        its flight would be shorter than Δt (:func:`_restitution_of`: it stays closed).  The
        impulses are recorded (``Event.impulse_n``/``impulse_t``,
        :attr:`DynamicResult.impulses`, :meth:`DynamicResult.impacts`); the ledger books
        the kinetic energy the impact takes as ``impact``.  Compliant contact closes
        smoothly without it.
    alpha : float
        HHT-α numerical damping, α ∈ [0, 1/3] (0: Newmark's average acceleration, no
        numerical dissipation; 0.05–0.1 damps the high, spurious modes of a mesh — its share is
        the ledger's ``numerical``).
    record_every : int
        Record every k-th step (events and the last step always).
    hooks : sequence
        Objects with an optional ``after_step(step, t, end)`` (progress in simulated time)
        and an optional ``stop_requested`` flag, polled before every step: once true the run
        ends there with status ``incomplete`` and the states so far
        (:class:`~stepcontact.io.interrupt.StopRequest`: SIGTERM or Ctrl-C in the CLI).
    stage : int or str, optional
        A run in stages: the stage (index or name) whose dynamic interval this is (default:
        the last).  The interval of an earlier stage is run by
        :func:`~stepcontact.solve_static` inside the run of the stages, from ``initial``, the
        result of the run so far (it ends in that stage); its result is
        ``StaticResult.dynamics[stage name]``.
    backend : str
        Sparse factorisation backend of K̂ (``auto``, ``scipy``, ``cholmod``, ``pypardiso``;
        :mod:`stepcontact.solver.linalg`), as for :func:`~stepcontact.solve_static`.
    max_steps : int, optional
        Limit of the number of time steps (default: the dynamic interval's ``max_steps``, or
        :data:`~stepcontact.model.timefunction.MAX_STEPS` = 10⁷): an interval that would take
        more (duration / Δt plus the loads' breaks) is refused before any work, with the
        estimate.
    crack_water : "full", "unchanged" or "none", optional
        The water in the opened joints (:class:`~stepcontact.model.CrackWater`) during the
        interval (default: the dynamic interval's ``crack_water`` where the model's interval
        is run, else ``"full"``):
        :class:`~stepcontact.model.DynamicInterval` and the user guide's *Crack water during
        an earthquake* (issue 29 §1).

    Refused before any work (ModelError naming the item,
    :func:`~stepcontact.model.timefunction.check_interval`): Δt longer than the interval; more
    steps than ``max_steps``; a load (or the ground acceleration) that acts only outside
    [0, duration] or is zero everywhere; a varying load (a harmonic; a half-sine or
    triangular pulse, a table that returns to zero: 5 steps in its duration) with fewer than
    10 steps per period — sampled at the steps' ends only, it would be missed.  A rectangular
    pulse is followed exactly however short: the steps land on its edges, where its jumps
    are resolved in accelerations.

    Construction stages (``model.stages``, :class:`~stepcontact.model.Stage`)
        The interval follows the last stage and runs on its system: its supports (those
        removed gone), the CFEs of every stage acting (interfaces made at once with their
        zero where they were made), grouted joints bonded, the automatic patterns (released
        reactions, ramps, holds) at their final factors.  It starts from the last state of
        ``initial``, the static result of the stages; without ``initial`` the staged
        program is run first (:func:`~stepcontact.solve_static`), and a result loaded from a
        file (which does not keep the stage systems) is checked against a run of the
        program.  The result carries ``stage`` (every state in the last stage),
        ``stage_names``, ``stage_cfes`` and ``stage_bodies`` as the static result does.  The
        interval can be given on the last stage (``Stage(..., dynamics=...)``, the model's
        ``dynamics``); not on an earlier one: static segments after a dynamic interval are
        not supported (the state at its end is not at rest).  A pattern that still
        prescribes nonzero displacements at the end of the stages is refused (prescribed
        displacements are not followed in time).

    Joints with initial strength (eq. (12))
        Intact bonds carry tension and shear up to their strength surface; reaching it is
        an event located in time, the bond breaks and what it carried is released at that
        instant, its neighbours breaking in turn where they reach theirs (module
        docstring); each break is an event ``broken`` (N, Q at the break).  The ledger
        books the elastic energy released by compliant bonded layers as ``fracture``.  A
        bonded CFE with a damped layer (c_n > 0) is refused.

    Example
    -------
    >>> import numpy as np, stepcontact as sc                           # doctest: +SKIP
    >>> dm = sc.DiscreteModel(np.zeros((2, 2)), [[0, 1]], [[1, 0]], loads={"P": [0, 1]},
    ...                       kn=1e4, kt=1e4, bond=sc.Bond(1.5, 10.0, 0.5))
    >>> res = sc.solve_dynamic(dm, dt=1e-4, duration=0.03, mass=np.eye(2),
    ...                        loads={"P": sc.Constant(1.0)})
    >>> str(res.events[0].transition), round(res.events[0].lam, 4)  # N = P(1 − cos ωt) = N_R
    ('broken', 0.0209)
    """
    iv = _dynamic.dynamic_interval(
        model, stage=stage, dt=dt, duration=duration, loads=loads, mass=mass, damping=damping,
        restitution=restitution, record_every=record_every, alpha=alpha, max_steps=max_steps,
        ground_acceleration=ground_acceleration, crack_water=crack_water)
    system = model if isinstance(model, System) else assemble(model)
    if in_stages(system):
        initial = _stages_before(system, initial, iv.stage)
    return _dynamic.integrate(system, iv, initial=initial, u0=u0, v0=v0,
                              ground_acceleration=ground_acceleration, hooks=hooks,
                              max_events=max_events, rtol=rtol, backend=backend)


def _stages_before(system: System, initial: StaticResult | None,
                   stage: int | None) -> StaticResult:
    """The static result of the construction stages a dynamic interval of the staged
    ``system`` starts from (:func:`solve_dynamic`): ``initial`` when it holds its run's stages
    (:func:`~stepcontact.solver.recovery.stage_plan`); without ``initial``, the staged program
    run here (:func:`~stepcontact.solver.static.solve_static`); a result loaded from a file
    (which does not keep the stage systems) is replaced by a run of the program, its last
    state checked against that run's (the same CFE states; N and Q equal to 1e-6 of the
    largest, N): else ModelError.  The interval of a stage before the last is run only inside
    the static program, from the result so far (ModelError otherwise)."""
    n_stages = len(system.model.stages)
    if stage is not None and stage < n_stages - 1 and stage_plan(initial) is None:
        raise ModelError("initial", f"the dynamic interval of stage "
                         f"'{system.model.stages[stage].name}' starts from the run of the "
                         "stages before it: run solve_static(model), which runs it and keeps "
                         "its result in StaticResult.dynamics")
    if initial is None:
        return _static.solve_static(system)
    if stage_plan(initial) is not None:
        return initial
    again = _static.solve_static(system)
    i, j = len(initial.lam) - 1, len(again.lam) - 1
    scale = max(float(np.abs(again.N[j]).max(initial=0.0)),
                float(np.abs(again.Q[j]).max(initial=0.0)), 1e-300)
    same = (initial.m == again.m and initial.stage is not None
            and np.array_equal(initial.state[i], again.state[j])
            and max(float(np.abs(initial.N[i] - again.N[j]).max(initial=0.0)),
                    float(np.abs(initial.Q[i] - again.Q[j]).max(initial=0.0)))
            <= 1e-6 * scale)
    if not same:
        raise ModelError("initial", "is not the result of this model's stages (its last "
                         "state differs from the staged program's)")
    return again


def run(
    model: Model | DiscreteModel | System,
    *,
    slip: str = "exact",
    eps_p: float = 0.01,
    max_events: int = 100_000,
    store_fields: str | None = None,
    backend: str | None = None,
    rate_solver: str | None = None,
    precision: str = "auto",
    condensation: Condensation | None = None,
    scheduler=None,
    output=None,
    hooks: Sequence = (),
    dynamic_hooks: Sequence = (),
    after_static: Callable[[StaticResult], object] | None = None,
    before_dynamics: Callable[[], object] | None = None,
) -> ProgramResult:
    """Run the whole program of ``model``: its stages and load segments with the dynamic
    intervals between stages, then its dynamic interval (``model.dynamics``) from the last
    state when the static program completed.

    The static part is :func:`~stepcontact.solver.static.solve_static` (exact event-driven
    quasi-static path, eqs. (1)–(6); the dynamic interval of a stage before the last is run
    inside it and kept in ``StaticResult.dynamics``), the final interval
    :func:`solve_dynamic` (Newmark with exact events, eqs.
    (7)–(10)) started from the static result (displacements m, contact forces N, states, the
    load factors held) — or from rest when the model has no load program.  A dynamic interval
    needs mass on every body that can move: that is checked first (ModelError naming the
    body, density in kg/m³) so that the static run is not lost to it.

    Parameters
    ----------
    model : Model, DiscreteModel or System
        The model (assembled by each driver) or an assembled system.
    slip, eps_p, max_events, store_fields, backend, rate_solver, precision, condensation, scheduler
        The static driver's options (:func:`~stepcontact.solver.static.solve_static`;
        ``scheduler``: form G on a dask.distributed cluster):
        ``eps_p`` is eq. (5)'s ε_p (dimensionless), ``max_events`` the event budget of the
        static program; ``store_fields``, ``backend``, ``rate_solver`` and ``condensation``
        left at None take the driver's defaults (``ends``, ``auto``, ``pivoting``, none).
        The final interval takes its time step Δt (s), duration (s), loads, mass, damping and
        recording from ``model.dynamics`` and factorises with ``backend``.
    output : path or ResultWriter, optional
        The static program's result file, written as it runs (as ``solve_static``); the
        dynamic results are returned, not written.
    hooks : sequence
        Hooks of the static program (``before_run``, ``after_event``, ``after_segment``,
        ``interrupted``; ``after_step`` also for the intervals of stages).
    dynamic_hooks : sequence
        Hooks of the final dynamic interval: ``after_step(step, t, end)`` (t, end in s) and a
        ``stop_requested`` flag polled before every step (the interval then ends with status
        ``incomplete`` and its states so far).
    after_static : callable, optional
        Called with the static result as soon as the static program ends, before the final
        interval starts (to report or write it while the dynamics run is still to come).
    before_dynamics : callable, optional
        Called without arguments right before the final interval starts (only when it runs).

    Returns
    -------
    ProgramResult
        ``static`` (with ``dynamics`` of the stages), ``dynamic`` (the final interval or
        None) and ``not_run`` (intervals asked for that the program did not reach, with the
        reason; ``completed`` is then False).

    Example
    -------
    >>> out = sc.run(model)                                   # doctest: +SKIP
    >>> out.completed, len(out.static.events), out.dynamic.energy["error"][-1]  # doctest: +SKIP
    """
    check_dynamic_mass(model)
    given = {k: v for k, v in (("store_fields", store_fields), ("backend", backend),
                               ("rate_solver", rate_solver), ("condensation", condensation),
                               ("scheduler", scheduler))
             if v is not None}  # (the others: the driver's defaults)
    static = _static.solve_static(model, slip=slip, eps_p=eps_p, max_events=max_events,
                                  hooks=hooks, output=output, precision=precision, **given)
    if after_static is not None:
        after_static(static)
    m = _model_of(model)
    dynamic = None
    if getattr(m, "dynamics", None) is not None and static.status == Status.COMPLETED:
        if before_dynamics is not None:
            before_dynamics()
        dynamic = solve_dynamic(
            model, initial=static if m.effective_program else None, hooks=dynamic_hooks,
            **({} if backend is None else {"backend": backend}))
    return ProgramResult(static, dynamic, dynamics_not_run(model, static))


__all__ = ["NotRun", "ProgramResult", "check_dynamic_mass", "dynamics_not_run", "run",
           "solve_dynamic"]
