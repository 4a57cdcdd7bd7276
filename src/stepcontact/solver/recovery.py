"""Field recovery of a result: its model gives every state's displacements and stresses again.

A run keeps its factorisation in the result it returns (``StaticResult._recover``); a result
loaded from a file or unpickled has none.  :func:`recover_fields` gives it one from the model
of the run: a static result is condensed once more (one factorisation) and recomputes any
state exactly from its contact unknowns (:class:`FieldRecovery`; the recovery a run in stages
keeps: :class:`StagedRecovery`, with its plan, :func:`stage_plan`); a dynamic result stores
the displacements of every state, and the model gives their stresses
(:class:`Stresses`).  ``res.recover_fields(model)`` is this function: the result types
(:mod:`stepcontact.results.result`) know no solver, this module provides it to them
(:func:`~stepcontact.results.result.provide_field_recovery`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from stepcontact.enums import Status
from stepcontact.fem.assembly import System, assemble
from stepcontact.results.result import (
    RECOVERY_RESIDUAL,
    RECOVERY_RTOL,
    DynamicResult,
    StaticResult,
    provide_field_recovery,
)
from stepcontact.solver.condensation import Condensed

if TYPE_CHECKING:
    from stepcontact.results.recorder import Recorder


#: the contact unknowns of recorded states: indices (k,) -> (factors {pattern: (k,)},
#: s (k, 2m), w (k, 2m))
Unknowns = Callable[[np.ndarray], tuple[dict[str, np.ndarray], np.ndarray, np.ndarray]]


def _stacked(t: np.ndarray) -> np.ndarray:
    """A result's tangential values (k, m) or, in 3D, (k, m, n_t) as the rows of the contact
    unknowns (k, m n_t): component by component (:meth:`ContactLayout.join`)."""
    t = np.asarray(t)
    return np.swapaxes(t, 1, 2).reshape(len(t), -1) if t.ndim == 3 else t


class FieldRecovery:
    """Displacement fields and stresses at any recorded state, exact from its contact
    unknowns (factors, s, w: between events the structure is linear): one solve with the
    run's factorisation, several states in one multi-right-hand-side solve; stresses from the
    displacements with the per-body :class:`~stepcontact.fem.continuum.StressRecovery`
    operators (one sparse product per body).  Held by a result in memory; it is not pickled
    or written (it holds the factorisation).
    """

    def __init__(self, cond: Condensed, unknowns: Unknowns, stress=None):
        self.cond = cond
        self.unknowns = unknowns
        #: the stresses from displacements (:class:`Stresses`, the dynamic result's too)
        self.of_fields = Stresses(cond.system, stress)
        self.stress = self.of_fields.stress
        #: global DOFs (ux, uy per node) of every continuum body with a stress operator
        self.body_dofs = self.of_fields.body_dofs

    @classmethod
    def of_recorder(cls, cond: Condensed, rec: Recorder, names: Sequence[str],
                    stress=None) -> FieldRecovery:
        """Recovery of the states recorded (so far and later) by ``rec`` of a run."""
        names = list(names)

        def unknowns(idx):
            F = rec.factors.view[idx]
            s = rec.s.view[idx].copy()
            water = rec.water.view[idx]  # crack water acts as the normal forces p do
            s[:, s.shape[1] - water.shape[1]:] += water  # (the last m: [Q₁; (Q₂;) p])
            return {n: F[:, j] for j, n in enumerate(names)}, s, rec.w.view[idx]

        return cls(cond, unknowns, stress)

    @classmethod
    def of_result(cls, cond: Condensed, res: StaticResult, stress=None) -> FieldRecovery:
        """Recovery of the states of a result (loaded from a file or unpickled)."""
        names = list(res.pattern_names)

        def unknowns(idx):
            F = np.asarray(res.factors)[idx]
            p = -res.N[idx] if res.water is None else np.asarray(res.water)[idx] - res.N[idx]
            s = np.concatenate([_stacked(res.Q[idx]), p], axis=1)
            w = np.concatenate([_stacked(res.ut[idx]), res.un[idx]], axis=1)
            return {n: F[:, j] for j, n in enumerate(names)}, s, w

        return cls(cond, unknowns, stress)

    def displacements(self, states) -> np.ndarray:
        """Displacements (k, ndof), m, of the states ``states`` (k,): one solve."""
        idx = np.asarray(states, dtype=np.int64).reshape(-1)
        factors, s, w = self.unknowns(idx)
        return self.cond.displacement(factors, np.reshape(s, (len(idx), -1)),
                                      np.reshape(w, (len(idx), -1)))

    def __call__(self, i: int) -> np.ndarray:
        """Displacement vector (ndof,) of state ``i``."""
        return self.displacements([i])[0]

    def stresses(self, u: np.ndarray) -> dict[str, np.ndarray]:
        """Element stresses of every continuum body from displacements ``u``
        (:meth:`Stresses.stresses`)."""
        return self.of_fields.stresses(u)


class StagedRecovery:
    """Field recovery of a run in stages: each state's field from its own stage's
    condensation (:class:`FieldRecovery` per stage)."""

    def __init__(self, rec: Recorder, names: Sequence[str]):
        self.rec = rec
        self.names = list(names)
        self.parts: dict[int, FieldRecovery] = {}
        #: the run's :class:`~stepcontact.solver.staging.StagePlan` (its final state: the
        #: last stage's system, shifted w⁰, automatic patterns, grouted bonds)
        self.plan = None

    def add(self, k: int, cond: Condensed) -> None:
        stress = next(iter(self.parts.values())).stress if self.parts else None
        self.parts[k] = FieldRecovery.of_recorder(cond, self.rec, self.names, stress)
        self.cond = cond

    @property
    def stress(self):
        return next(iter(self.parts.values())).stress

    def displacements(self, states) -> np.ndarray:
        idx = np.asarray(states, dtype=np.int64).reshape(-1)
        stage = self.rec.stage.view[idx]
        out = np.zeros((len(idx), self.cond.system.ndof))
        for k in np.unique(stage):
            sel = stage == k
            out[sel] = self.parts[int(k)].displacements(idx[sel]).reshape(int(sel.sum()), -1)
        return out

    def __call__(self, i: int) -> np.ndarray:
        return self.displacements([i])[0]

    def stresses(self, u: np.ndarray) -> dict[str, np.ndarray]:
        return next(iter(self.parts.values())).stresses(u)


def stage_plan(res):
    """The :class:`~stepcontact.solver.staging.StagePlan` of a result of a run in stages that
    still holds its recovery (:class:`StagedRecovery`); None for a result loaded from a file
    (which does not keep the stage systems) or of a run without stages."""
    rec = getattr(res, "_recover", None)
    return rec.plan if isinstance(rec, StagedRecovery) else None


class Stresses:
    """Stresses of the continuum bodies from displacements: the recovery of a dynamic result
    (which stores every state's displacements; only the stresses are recovered), and the
    stress part of :class:`FieldRecovery`.  ``stress``: a
    :class:`~stepcontact.fem.continuum.StressRecovery` of the model to share (default: made
    here)."""

    def __init__(self, system: System, stress=None):
        from stepcontact.fem.continuum import StressRecovery
        from stepcontact.model import Body

        model = system.model
        self.stress = stress if stress is not None else StressRecovery(model)
        off = model.node_offsets
        #: global DOFs (ux, uy per node) of every continuum body with a stress operator
        self.body_dofs = {
            b.name: system.dofs.of[off[b.name] + np.arange(b.n_nodes)][:, :b.dim].ravel()
            for b in model.bodies if isinstance(b, Body) and b.name in self.stress}

    def stresses(self, u: np.ndarray) -> dict[str, np.ndarray]:
        """Element stresses of every continuum body from displacements ``u``: (ndof,) gives
        {body: (n_el, 4)}, (k, ndof) gives {body: (k, n_el, 4)}; σxx, σyy, σxy, σzz in Pa."""
        u = np.asarray(u, dtype=float)
        if u.ndim == 1:
            return {n: self.stress(n, u[d]) for n, d in self.body_dofs.items()}
        return {n: self.stress(n, u[:, d].T) for n, d in self.body_dofs.items()}

    def __call__(self, i):  # (not used: the displacements are stored)
        raise KeyError(i)


def recover_fields(res: StaticResult, model) -> None:
    """Attach field recovery to a result loaded from a file or unpickled: ``model`` (the
    model of the run, or its assembled system) is condensed once more (one factorisation);
    ``res.displacement``, ``displacements``, ``stress`` and ``stresses_at`` then recompute any
    state exactly from its contact unknowns.

    The model is checked against the result: the same CFEs, load patterns and DOFs, and the
    field recomputed at a stored state equal to the stored one to
    :data:`~stepcontact.results.result.RECOVERY_RTOL`, or else the stored field in this
    model's equilibrium with the stored contact forces to
    :data:`~stepcontact.results.result.RECOVERY_RESIDUAL` (a tolerance scaled to the model:
    its conditioning does not enter); otherwise ValueError.  A staged run stores the field of
    every state and needs no recovery: nothing is done.  A dynamic result
    (:class:`~stepcontact.results.result.DynamicResult`) stores every state's displacements:
    its model gives the stresses (:class:`Stresses`).
    """
    if isinstance(res, DynamicResult):
        _recover_stresses(res, model)
        return
    if res.stage is not None and all(i in res.fields for i in range(res.n_states)):
        return  # a staged run stores every field (its stages' systems differ): nothing to do
    system = model if isinstance(model, System) else assemble(model)
    if system.m != res.m:
        raise ValueError(f"the model has {system.m} CFEs, the result {res.m}")
    if set(system.loads) != set(res.pattern_names):
        raise ValueError(f"the model's load patterns ({', '.join(system.loads) or 'none'}) "
                         f"are not the result's ({', '.join(res.pattern_names) or 'none'})")
    if res.fields:
        ndof = len(next(iter(res.fields.values())))
        if system.ndof != ndof:
            raise ValueError(f"the model has {system.ndof} DOFs, the result's fields {ndof}")
    cond = Condensed.from_system(system)
    recovery = FieldRecovery.of_result(cond, res)
    if res.fields:  # the same structure: a stored field is recomputed exactly
        i = _check_state(res)
        ref = np.asarray(res.fields[i], dtype=float)
        u = recovery(i)
        scale = max(float(np.abs(ref).max(initial=0)), float(np.abs(u).max(initial=0)))
        err = float(np.abs(u - ref).max(initial=0)) / scale if scale > 0 else 0.0
        if err > RECOVERY_RTOL:
            r = _stored_residual(cond, recovery, i, ref)
            tol = _residual_tolerance(res, i)
            if not r <= tol:
                raise ValueError(
                    f"the model is not the one of this result: the displacement field "
                    f"recomputed at state {i} differs from the stored one by {err:.1e} "
                    f"(relative), and the stored field is out of this model's "
                    f"equilibrium by {r:.1e} (relative; the run's own: "
                    f"{_run_residual(res, i):.1e}, allowed {tol:.1e})")
    res._recover = recovery


def _recover_stresses(res: DynamicResult, model) -> None:
    """The stress recovery of a dynamic result loaded from a file (its displacements are
    stored at every state): stresses, ``stresses_at`` and the ParaView export then work."""
    system = model if isinstance(model, System) else assemble(model)
    if system.ndof != res.u.shape[1]:
        raise ValueError(f"the model has {system.ndof} DOFs, the result {res.u.shape[1]}")
    res._recover = Stresses(system)


def _check_state(res: StaticResult) -> int:
    """The stored state whose field :func:`recover_fields` recomputes to check the model: the
    largest stored field, leaving out the last state of a run that stopped (lost equilibrium,
    cycling, …) unless no other stored field is nonzero.  A run can stop while broken bonds
    still transmit part of their forces (eq. (12): the release at fixed λ, followed from event
    to event): its last field carries those forces, which are not among the recorded contact
    forces, so it is not recomputed from them (the stored field is the one used for that
    state)."""
    def size(k: int) -> float:
        return float(np.abs(res.fields[k]).max(initial=0))

    last = res.n_states - 1
    stopped = res.status not in (Status.COMPLETED, Status.INCOMPLETE)
    states = [k for k in res.fields if not (stopped and k == last)]
    if not states or max(size(k) for k in states) == 0.0:
        states = list(res.fields)
    return max(states, key=size)


def _run_residual(res: StaticResult, i: int) -> float:
    r = getattr(res, "residual", None)
    return float(r[i]) if r is not None and len(r) > i and np.isfinite(r[i]) else 0.0


def _residual_tolerance(res: StaticResult, i: int) -> float:
    """The residual a stored field may show in the model of its run: 100 × the run's own
    residual at that state (the round-off of that model's factorisation), at least
    :data:`~stepcontact.results.result.RECOVERY_RESIDUAL`."""
    return max(RECOVERY_RESIDUAL, 100.0 * _run_residual(res, i))


def _stored_residual(cond: Condensed, recovery: FieldRecovery, i: int, u: np.ndarray) -> float:
    """Relative equilibrium residual ‖K u + Bᵀ s − f‖ / max(‖K u‖, ‖Bᵀ s‖, ‖f‖) of the stored
    field ``u`` of state ``i`` with its stored contact forces, in the model of ``cond``
    (:meth:`Condensed.check`): a backward error, free of the model's conditioning."""
    factors, s, w = recovery.unknowns(np.array([i]))
    c = {n: float(np.asarray(v).ravel()[0]) for n, v in factors.items()}
    r, _ = cond.check(c, np.asarray(s)[0], np.asarray(w)[0], u)
    return r


provide_field_recovery(recover_fields)

__all__ = ["FieldRecovery", "StagedRecovery", "Stresses", "recover_fields", "stage_plan"]
