"""Construction in stages (:class:`~stepcontact.model.stages.Stage`) for the static solver.

One :class:`~stepcontact.fem.System` of the whole model (all bodies, supports, interfaces: the
same DOF numbering and CFE set at every stage); for each stage a modified copy:

* ``fixed``: the DOFs of active supports and prescribed DOFs, and every DOF of the bodies not
  yet built (frozen at zero: they carry nothing; their nodes start from zero displacement when
  they are built, so their elements start stress-free on the deformed structure);
* the CFEs not yet active are inert (held: they carry nothing and stay open);
* ``w0`` shifted for the CFEs of interfaces made at once (their mutual displacements at that
  moment become their zero) and for grouted CFEs that were open;
* automatic load patterns, held at factor 1 at the start of a stage and released to 0 by an
  automatic segment (events located): the reactions of removed supports, and minus the loads
  that patterns already standing at a nonzero factor put on the bodies just built (so that
  their loads ramp in); a support placed on a body already in place holds its DOFs where
  they are by a prescribed-displacement pattern at factor 1;
* reaction rows restricted to the DOFs of built bodies;
* after the segments of a stage with a dynamic interval (not the last stage), an automatic
  pattern and segment ``"<stage>: settle after dynamics"``: the force out of balance where the
  motion ends, held at factor 1 and released to 0 (the solver runs the interval and sets the
  pattern's vector, :meth:`~stepcontact.solver.static.StaticSolver._dynamic_interval`).

The solver refactorises at each stage boundary and keeps the contact state (s, w, states) and
the factors (:class:`~stepcontact.solver.static.StaticSolver`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.fem.assembly import LoadVectors, System
from stepcontact.model.stages import list_problems


def held_components(system: System) -> tuple[np.ndarray, np.ndarray]:
    """CFE components whose relative motion is held by supports on both ends (their row of
    the contact operator on the free DOFs is zero): (normal (m,), tangential (m,)) masks; with
    two tangential components a CFE is held tangentially when both are."""
    m = system.m
    if m == 0:
        return np.zeros(0, bool), np.zeros(0, bool)
    free = ~system.fixed
    B = system.B
    full = np.sqrt(np.asarray(B.multiply(B).sum(axis=1)).ravel())
    Bf = B[:, np.flatnonzero(free)]
    on_free = np.sqrt(np.asarray(Bf.multiply(Bf).sum(axis=1)).ravel())
    zero = on_free <= 1e-12 * np.maximum(full, 1e-300)
    lay = system.layout
    held_t = zero[lay.tangential_rows]
    return zero[lay.normal_rows], held_t if lay.n_t == 1 else held_t.all(axis=1)


def in_stages(system: System) -> bool:
    """True when ``system`` is of a model built in construction stages (a discrete model has
    none): its drivers run on the stage systems of a :class:`StagePlan`."""
    return bool(getattr(system.model, "stages", ())) and system.discrete is None


class StagePlan:
    """Which items act at each stage of ``system.model`` (checked), the automatic patterns
    and segments, and the stage systems."""

    def __init__(self, system: System):
        self.full = system
        model = system.model
        stages = model.stages
        self.names = tuple(st.name for st in stages)
        bodies = {b.name: b for b in model.bodies}
        itfs = {i.name: i for i in model.interfaces}
        sups = {s.name: s for s in model.supports}

        # the stages' lists (names exist, listed once, removed after placed, grout in place):
        # the model's rules (model.stages.list_problems), the first one raised
        problems = list_problems(stages, {"body": list(bodies), "interface": list(itfs),
                                          "support": list(sups)},
                                 lambda k: f"stage '{self.names[k]}'")
        if problems:
            k, key, text = problems[0]
            raise ModelError(f"stage '{self.names[k]}'.{key}", text)
        self.body_stage: dict[str, int] = {}
        itf_stage: dict[str, int] = {}
        self.contact_itf: set[str] = set()
        sup_stage: dict[str, int] = {}
        self.sup_removed: dict[str, int] = {}
        self.grout: dict[int, dict] = {}
        for k, st in enumerate(stages):
            self.body_stage.update(dict.fromkeys(st.bodies, k))
            itf_stage.update(dict.fromkeys((*st.interfaces, *st.contacts), k))
            self.contact_itf |= set(st.contacts)
            sup_stage.update(dict.fromkeys(st.supports, k))
            self.sup_removed.update(dict.fromkeys(st.remove_supports, k))
            self.grout[k] = dict(st.grout)
        self.body_stage = {b: self.body_stage.get(b, 0) for b in bodies}
        self.itf_stage = {i: itf_stage.get(i, 0) for i in itfs}
        self.sup_stage = {s: sup_stage.get(s, 0) for s in sups}
        for itf in model.interfaces:  # an interface acts only between bodies in place
            ends = [itf.plus.body] + ([itf.minus.body] if hasattr(itf.minus, "body") else [])
            for b in ends:
                if self.body_stage[b] > self.itf_stage[itf.name]:
                    raise ModelError(f"interface '{itf.name}'", f"acts from stage "
                                     f"'{self.names[self.itf_stage[itf.name]]}' but body "
                                     f"'{b}' is built later (stage "
                                     f"'{self.names[self.body_stage[b]]}'): list the interface "
                                     "in that stage (or a later one)")
        for tie in model.ties:
            if self.body_stage[tie.a.body] != self.body_stage[tie.b.body]:
                raise ModelError(f"tie '{tie.name}'", f"joins body '{tie.a.body}' and body "
                                 f"'{tie.b.body}', built at different stages: ties between "
                                 "stages are not supported (use an interface made at once)")
        for spr in model.springs:
            if spr.b is not None and self.body_stage[spr.a.body] != self.body_stage[spr.b.body]:
                raise ModelError(f"spring '{spr.name}'", f"joins body '{spr.a.body}' and body "
                                 f"'{spr.b.body}', built at different stages: springs between "
                                 "stages are not supported")
        dofs = system.dofs
        off = model.node_offsets
        self.body_dofs = {}
        for b in model.bodies:
            d = dofs.of[off[b.name] + np.arange(b.n_nodes)]
            self.body_dofs[b.name] = np.unique(d[d >= 0])
        self.sup_dofs = {}
        for s in model.supports:
            ids = model.global_nodes(s.nodes)
            self.sup_dofs[s.name] = np.unique(np.concatenate(
                [dofs.of[ids, dofs.column(c)] for c in s.dofs]))
        all_sup = np.zeros(system.ndof, bool)
        for d in self.sup_dofs.values():
            all_sup[d] = True
        base = system.fixed & ~all_sup  # moving obstacles
        for lv in system.loads.values():
            base[lv.dofs] = True
        self.base_fixed = base
        cfe = system.cfe
        itf_index = {name: j for j, name in enumerate(cfe.names)}
        self.cfe_stage = np.zeros(cfe.m, np.int64)
        for name, k in self.itf_stage.items():
            if name in itf_index:
                self.cfe_stage[cfe.interface == itf_index[name]] = k
        self.itf_index = itf_index
        # automatic patterns and the segments of every stage
        self.auto: dict[str, tuple[int, str, str]] = {}  # name -> (stage, kind, item)
        self.segments: list[tuple[str, float, float]] = []
        self.rates: list[dict[str, float]] = []
        self.stage_of_segment: list[int] = []
        user = model.segments_resolved()
        user_rates = model.segment_rates()
        j = 0
        for k, st in enumerate(stages):
            if k > 0:  # the new bodies' loads first: a weightless body could float off
                if st.bodies:
                    self._auto_segment(k, f"{st.name}: loads on {', '.join(st.bodies)}",
                                       "ramp", "")
                for s in st.remove_supports:
                    self._auto_segment(k, f"{st.name}: release {s}", "release", s)
                for s in st.supports:
                    if self.body_of_support(s) not in st.bodies:
                        self.auto[f"{st.name}: hold {s}"] = (k, "hold", s)
            for _ in st.program:
                self.segments.append(user[j])
                self.rates.append(user_rates[j])
                self.stage_of_segment.append(k)
                j += 1
            if st.dynamics is not None and k < len(stages) - 1:
                damped = np.flatnonzero(np.asarray(system.cfe.cn) > 0)
                if damped.size:
                    itf = system.cfe.names[system.cfe.interface[damped[0]]]
                    raise ModelError(f"stage '{st.name}'.dynamics", f"interface '{itf}' has "
                                     "a damped contact layer (c_n > 0): static stages cannot "
                                     "follow a dynamic interval with one (its force c_n u̇_n "
                                     "has no static counterpart); give the layer no damping, "
                                     "or put the interval on the last stage")
                cols = np.asarray(system.cfe.bond, float)
                residual = cols.ndim == 2 and cols.shape[1] > 4 and bool(
                    np.any(np.nan_to_num(cols[:, 4]) > 0))
                residual |= any(not (isinstance(b.residual_cohesion, int | float)
                                     and b.residual_cohesion == 0)
                                for later in stages[:k + 1] for b in later.grout.values())
                if residual:  # (checked here, before the static stages run, not at the shock)
                    raise ModelError(f"stage '{st.name}'.dynamics", "a bond with a residual "
                                     "cohesion acts: a dynamic interval with one is not "
                                     "supported yet (give residual_cohesion = 0)")
                self._auto_segment(k, f"{st.name}: settle after dynamics", "settle", "")
            if k > 0 and self.stage_of_segment.count(k) == 0:
                raise ModelError(f"stage '{st.name}'", "has no load segment: give it one "
                                 "(a stage begins with its first segment)")
        if not self.segments:
            raise ModelError("model.stages", "give at least one load segment")
        self.vectors: dict[str, LoadVectors] = {
            name: LoadVectors(np.zeros(system.ndof), np.zeros(system.ndof),
                              np.zeros(0, np.int64)) for name in self.auto}
        self.w0 = np.asarray(system.w0, float).copy()
        self.bond = np.array(cfe.bond, dtype=float, copy=True)
        self.friction = np.array(cfe.friction, dtype=float, copy=True)

    def body_of_support(self, name: str) -> str:
        return next(s.nodes.body for s in self.full.model.supports if s.name == name)

    def _auto_segment(self, k: int, name: str, kind: str, item: str) -> None:
        self.auto[name] = (k, kind, item)
        self.segments.append((name, 1.0, 0.0))
        self.rates.append({name: 1.0})
        self.stage_of_segment.append(k)

    # ---- what acts at stage k --------------------------------------------------------------
    def active_bodies(self, k: int) -> set[str]:
        return {b for b, j in self.body_stage.items() if j <= k}

    def active_cfes(self, k: int) -> np.ndarray:
        return self.cfe_stage <= k

    def support_active(self, name: str, k: int) -> bool:
        return self.sup_stage[name] <= k < self.sup_removed.get(name, 1 << 30)

    def fixed(self, k: int) -> np.ndarray:
        fixed = self.base_fixed.copy()
        for name, d in self.sup_dofs.items():
            if self.support_active(name, k):
                fixed[d] = True
        for b, j in self.body_stage.items():
            if j > k:
                fixed[self.body_dofs[b]] = True
        return fixed

    def built_dofs(self, k: int) -> np.ndarray:
        """(ndof,) bool: the DOFs of the bodies built by stage k (and of obstacles)."""
        out = np.ones(self.full.ndof, bool)
        for b, j in self.body_stage.items():
            if j > k:
                out[self.body_dofs[b]] = False
        return out

    def system(self, k: int) -> System:
        """The System of stage k with the automatic patterns' current vectors."""
        full = self.full
        loads = dict(full.loads)
        loads.update(self.vectors)
        rows = full.reaction_rows
        if rows is not None and rows.shape[0]:
            rows = (rows @ _diag(self.built_dofs(k))).tocsr()
        return dataclasses.replace(full, fixed=self.fixed(k), w0=self.w0.copy(), loads=loads,
                                   reaction_rows=rows)

    def bond_of(self, k: int) -> np.ndarray:
        """The bond columns of every CFE at stage k (grouted joints included)."""
        return self.bond

    def grout_stage(self, k: int) -> None:
        """Give the grouted interfaces of stage k their bond's strength (CFE columns)."""
        cfe = self.full.cfe
        for name, bond in self.grout.get(k, {}).items():
            rows = np.flatnonzero(cfe.interface == self.itf_index[name])
            self.bond[rows] = bond.arrays(cfe.x[rows], cfe.area[rows],
                                          f"stage '{self.names[k]}'.grout['{name}']")
            if bond.friction is not None:
                self.friction[rows] = float(bond.friction)

    def grouted_cfes(self, k: int) -> np.ndarray:
        cfe = self.full.cfe
        out = np.zeros(cfe.m, bool)
        for name in self.grout.get(k, {}):
            out |= cfe.interface == self.itf_index[name]
        return out


def _diag(mask: np.ndarray):
    import scipy.sparse as sp

    return sp.diags(mask.astype(float))


__all__ = ["StagePlan", "held_components", "in_stages"]
