"""Water in the opened parts of joints (:class:`~stepcontact.model.CrackWater`), as data for
the solver.

Where a CFE k of a joint with crack water is open (and, with an entry point, joined to it by
open CFEs), the water pushes the two faces apart with the force

    W_k = A_k (p_c,k − p_u,k)                                              (N)

p_c the crack pressure γ_w max(h_w − y_k, 0) (or a given pressure, uniform in the crack: the
pressure that reaches the gap through the joint) and p_u the uplift the model applies to that joint
(:class:`~stepcontact.model.Uplift`, which acts whether the joint is open or not: in the
crack, p_c replaces it).  W_k acts through the CFE's own force distribution, exactly like a
compressive normal force across the gap: in the condensed equations it is a force
s_w = [0; W] added to the contact forces, ŵ + G (s + s_w − D ŵ) = Σ c ĥ (its load on the
structure is −Bᵀ s_w).  W is linear in the load factors (piecewise linear in a water level:
it starts where the level passes the CFE), so between events it moves the path like any load;
at an event that changes which CFEs are wet it jumps, and the static driver applies the jump
at the same λ (:meth:`stepcontact.solver.static.StaticSolver._water_jump`); the dynamic
driver cuts the step where the wet set changes and applies the jump at that instant
(``settle_water`` in :meth:`stepcontact.solver.dynamic._DynamicRun.settle_water`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from stepcontact.contact.laws import OPEN
from stepcontact.errors import ModelError
from stepcontact.model.water import CrackWater


@dataclass(frozen=True, eq=False)
class CrackWaterData:
    """Crack water of a model, per CFE (m = number of CFEs).

    Attributes
    ----------
    wettable : (m,) bool
        CFEs of joints with crack water.
    crack : dict[str, (m,) float]
        Crack pressure per unit factor of each pattern whose factor scales it (crack water at
        a given level), Pa.
    uplift : dict[str, (m,) float]
        Uplift pressure per unit factor at the CFEs of those joints (what the crack pressure
        replaces), Pa.
    level : dict[str, (m,) float]
        Patterns whose factor is the level h: their crack pressure is γ_w max(h − y_k, 0) (this
        array holds γ_w, N/m³, zero on other CFEs).
    area : (m,) float
        A_k, m².
    y : (m,) float
        Height of each CFE, m (where a moving level starts to load it).
    runs : list of ((k,) int, (e,) int)
        For each joint with entry points: its CFEs in order along the joint and the positions
        in that order of the CFEs nearest the entries.
    """

    wettable: np.ndarray
    crack: dict[str, np.ndarray]
    uplift: dict[str, np.ndarray]
    level: dict[str, np.ndarray]
    area: np.ndarray
    y: np.ndarray
    runs: list[tuple[np.ndarray, np.ndarray]]

    def wet(self, states: np.ndarray) -> np.ndarray:
        """CFEs the water fills in the scheme ``states``: open, of a joint with crack water and
        (joints with entry points) joined to an entry by open CFEs."""
        wet = self.wettable & (states == OPEN)
        for order, at in self.runs:
            op = wet[order]
            label = np.cumsum(~op)  # runs of open CFEs share a label
            reached = label[at][op[at]]  # the runs that an open entry CFE belongs to
            wet[order] = op & np.isin(label, reached)
        return wet

    def uplift_pressure(self, factors: dict[str, float]) -> np.ndarray:
        """p_u (m,), Pa, at the pattern factors ``factors``."""
        p = np.zeros(len(self.y))
        for name, q in self.uplift.items():
            p += factors.get(name, 0.0) * q
        return p

    def net(self, factors: dict[str, float], rates: dict[str, float] | None = None
            ) -> np.ndarray:
        """p_c − p_u (m,), Pa, at the factors; with ``rates`` (per unit μ) its rate instead: a
        moving level loads the CFEs it is above, or at and rising."""
        p = np.zeros(len(self.y))
        moving = factors if rates is None else rates
        for name, q in self.crack.items():
            p += moving.get(name, 0.0) * q
        for name, q in self.uplift.items():
            p -= moving.get(name, 0.0) * q
        for name, g in self.level.items():
            if name not in moving:
                continue
            h = factors.get(name, 0.0)
            if rates is None:
                p += g * np.maximum(h - self.y, 0.0)
            else:
                r = rates[name]
                tol = 1e-12 * max(1.0, abs(h))
                above = (h - self.y > tol) | ((np.abs(h - self.y) <= tol) & (r > 0))
                p += r * np.where(above, g, 0.0)
        return p

    def force(self, states: np.ndarray, factors: dict[str, float]) -> np.ndarray:
        """W = A (p_c − p_u) (m,), N, on the wet CFEs of the scheme ``states`` at
        ``factors``."""
        return np.where(self.wet(states), self.area * self.net(factors), 0.0)

    def rate(self, states: np.ndarray, factors: dict[str, float],
             rates: dict[str, float]) -> np.ndarray:
        """dW/dμ (m,) of the scheme ``states`` when the factors move at ``rates`` (per unit
        μ) from ``factors``."""
        return np.where(self.wet(states), self.area * self.net(factors, rates), 0.0)

    def pressure(self, states: np.ndarray, factors: dict[str, float],
                 water: np.ndarray) -> np.ndarray:
        """Water pressure in the joint (m,), Pa, where the water acts: the CFEs wet in
        ``states`` or loaded by ``water`` (a jump in progress): W/A + p_u."""
        filled = self.wet(states) | (water != 0)
        return np.where(filled, water / self.area + self.uplift_pressure(factors), 0.0)

    def kinks(self, pattern: str) -> np.ndarray:
        """Levels (m) where the crack force of a level pattern has a kink (CFE heights)."""
        if pattern not in self.level:
            return np.zeros(0)
        return np.unique(self.y[self.level[pattern] != 0])


def crack_water(model, cfe, levels: dict) -> CrackWaterData | None:
    """The crack water of ``model`` (None if it has none) for its CFEs ``cfe``; ``levels``:
    the level patterns of the assembly (their factor is the water level)."""
    from stepcontact.model.water import Uplift

    items = [(p.name, ld) for p in model.patterns for ld in p.loads
             if isinstance(ld, CrackWater)]
    if not items:
        return None
    m = cfe.m
    names = list(cfe.names)
    wettable = np.zeros(m, bool)
    crack: dict[str, np.ndarray] = {}
    uplift: dict[str, np.ndarray] = {}
    level: dict[str, np.ndarray] = {}
    runs: list[tuple[np.ndarray, np.ndarray]] = []
    y = cfe.x[:, 1].copy() if m else np.zeros(0)
    entries: dict[str, tuple | None] = {}
    for pname, cw in items:
        item = f"load pattern '{pname}': crack water in interface '{cw.name}'"
        if cw.name not in names:
            known = ", ".join(repr(n) for n in names) or "none"
            raise ModelError(item, f"no such interface with CFEs (known: {known})")
        ks = np.flatnonzero(cfe.interface == names.index(cw.name))
        cw.check_level(y[ks], item)
        wettable[ks] = True
        if cw.name in entries and entries[cw.name] != cw.entry:
            raise ModelError(item, "the joint's crack water is given twice with different "
                             "entry points")
        entries[cw.name] = cw.entry
        if cw.pressure is not None:
            crack.setdefault(pname, np.zeros(m))[ks] += cw.pressure
        elif cw.level is None:
            if pname not in levels:
                raise ModelError(item, "level=None follows the water level of its pattern, but "
                                 "this pattern's factor is not a level (give the pattern a "
                                 "WaterLoad with level=None, or give the crack water a level)")
            level.setdefault(pname, np.zeros(m))[ks] += cw.unit_weight
        else:
            crack.setdefault(pname, np.zeros(m))[ks] += cw.crack_pressure(y[ks])
    for name, entry in entries.items():
        if entry is None:
            continue
        ks = np.flatnonzero(cfe.interface == names.index(name))
        order = ks[np.argsort(cfe.s[ks], kind="stable")]
        points = np.atleast_2d(np.asarray(entry, float))
        at = np.array([int(np.argmin(np.hypot(*(cfe.x[order] - pt).T))) for pt in points])
        CrackWater.check_entries(points, cfe.x[order],
                                 f"crack water in interface '{name}'.entry")
        runs.append((order, at))
    # in the crack, the crack pressure replaces the uplift given for the joint
    for p in model.patterns:
        for ld in p.loads:
            if isinstance(ld, Uplift) and ld.name in entries:
                ks = np.flatnonzero(cfe.interface == names.index(ld.name))
                pu = np.asarray(ld.function()(cfe.x[ks, 0], cfe.x[ks, 1]), float)
                uplift.setdefault(p.name, np.zeros(m))[ks] += np.broadcast_to(pu, ks.shape)
    return CrackWaterData(wettable, crack, uplift, level, cfe.area.copy(), y, runs)


__all__ = ["CrackWaterData", "crack_water"]
