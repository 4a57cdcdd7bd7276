"""The whole program of a model in one call: :func:`run` (``sc.run``).

A model's program is its construction stages (:class:`~stepcontact.model.Stage`) with their
load segments and the dynamic intervals of the stages before the last, all run by the static
driver (:func:`~stepcontact.solver.static.solve_static`; the intervals of the stages are kept
in ``StaticResult.dynamics``), then the model's own dynamic interval (``model.dynamics``,
:class:`~stepcontact.model.DynamicInterval`) from the completed last state by the Newmark
driver (:func:`~stepcontact.solver.dynamic.solve_dynamic`, eqs. (7)–(10)).  :func:`run` chains
them exactly as ``stepcontact run MODEL.toml`` and a model-file sweep do (both call it), so a
script, the command line and a study give the same states and events.

Example
-------
>>> import stepcontact as sc
>>> out = sc.run(sc.load_model("slab.toml"))               # doctest: +SKIP
>>> out.static.status, out.dynamic.time[-1]                 # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from stepcontact.enums import Status
from stepcontact.fem.assembly import System
from stepcontact.solver import dynamic as _dynamic
from stepcontact.solver import static as _static
from stepcontact.solver.dynamic import DynamicResult

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
    from stepcontact.fem.assembly import assemble
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
    :func:`~stepcontact.solver.dynamic.solve_dynamic` (Newmark with exact events, eqs.
    (7)–(10)) started from the static result (displacements m, contact forces N, states, the
    load factors held) — or from rest when the model has no load program.  A dynamic interval
    needs mass on every body that can move: that is checked first (ModelError naming the
    body, density in kg/m³) so that the static run is not lost to it.

    Parameters
    ----------
    model : Model, DiscreteModel or System
        The model (assembled by each driver) or an assembled system.
    slip, eps_p, max_events, store_fields, backend, rate_solver, precision, condensation
        The static driver's options (:func:`~stepcontact.solver.static.solve_static`):
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
                               ("rate_solver", rate_solver), ("condensation", condensation))
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
        dynamic = _dynamic.solve_dynamic(
            model, initial=static if m.effective_program else None, hooks=dynamic_hooks,
            **({} if backend is None else {"backend": backend}))
    return ProgramResult(static, dynamic, dynamics_not_run(model, static))


__all__ = ["NotRun", "ProgramResult", "check_dynamic_mass", "dynamics_not_run", "run"]
