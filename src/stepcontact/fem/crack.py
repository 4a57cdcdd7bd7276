"""Water in the opened parts of joints (:class:`~stepcontact.model.CrackWater`), as data for
the solver, in 2D and 3D alike.

Where a CFE k of a joint with crack water is open (and, with an entry, joined to it by open
CFEs), the water pushes the two faces apart with the force

    W_k = A_k (p_c,k − p_u,k)                                              (N)

p_c the crack pressure γ_w max(h_w − y_k, 0) (y_k the CFE's height: y in 2D, z in 3D; or a
given pressure, uniform in the crack: the pressure that reaches the gap through the joint) and
p_u the uplift the model applies to that joint (:class:`~stepcontact.model.Uplift`, which acts
whether the joint is open or not: in the crack, p_c replaces it).  W_k acts through the CFE's
own force distribution along its normal n_k, exactly like a compressive normal force across the
gap: in the condensed equations it is a force s_w = [0; W] added to the contact forces,
ŵ + G (s + s_w − D ŵ) = Σ c ĥ (its load on the structure is −Bᵀ s_w).  W is linear in the load
factors (piecewise linear in a water level: it starts where the level passes the CFE), so
between events it moves the path like any load; at an event that changes which CFEs are wet it
jumps, and the static driver applies the jump at the same λ
(:meth:`stepcontact.solver.static.StaticSolver._water_jump`); the dynamic driver cuts the step
where the wet set changes and applies the jump at that instant (``settle_water`` in
:meth:`stepcontact.solver.dynamic._DynamicRun.settle_water`).

**Connected to the reservoir.**  A joint with an entry is a graph: its CFEs are the vertices,
and two CFEs are neighbours when they follow each other along the joint (2D: consecutive in the
order along S+) or when their nodes belong to one facet of the face that carries the CFEs (3D:
S+ for node-to-node, node-to-facet, rigid-plane and mortar CFEs on S+; S− for mortar CFEs on
S−'s nodes).  The entry CFEs are the CFE nearest each entry point (2D) or the row of CFEs along
each entry polyline (3D: those within half the shortest neighbour spacing of the nearest one's
distance).  The wet CFEs are the open CFEs of the components of the graph of open CFEs (the
edges between two open neighbours) that hold an open entry CFE: the water reaches a CFE through
open CFEs only.  In 2D this is the run of open CFEs from the heel; in 3D, the region of open
CFEs joined to the upstream edge.

**Bridged CFEs** (2D, :class:`~stepcontact.model.CrackWater` ``bridge``, m): closed CFEs
within that distance of the entry and not bonded (an intact bond keeps water out), which do
not cut the connection — at the singular re-entrant corner of a heel their closure is an
artefact of the elastic solution.  They count as
conducting in the graph; a component reached from an entry is wet if it holds at least one open
CFE, and then its bridged closed CFEs are wet too (the water's force acts on them as an
effective stress, their contact force dropping by W_k).

**The uplift beyond the tip** (``rule="em1110"``, 2D): on the CFEs beyond the wet run, along
the joint away from the entry, the given uplift p_u is replaced by the cracked-base profile of
USACE EM 1110-2-2200 (1995) / EM 1110-2-2100 (2005) [sections to be checked]: linear from the
crack pressure at the tip p_c,tip to the uplift at the far end (the toe) p_u,toe, through the
drained head at the drain line while the tip has not reached it
(:class:`~stepcontact.model.water.Drains`):

    p_k = a_k p_c,tip + b_k p_u,toe,    W_k = A_k (p_k − p_u,k)                   (N)

with a_k, b_k ≥ 0 the weights of the piecewise linear profile, functions of the tip's position
only: W is linear in the factors between events, and changes with the wet set (the tip), where
the drivers apply the jump as for water entering a CFE.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from stepcontact.contact.laws import BONDED, OPEN
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
        Height of each CFE, m (y in 2D, z in 3D: where a moving level starts to load it).
    links : (2, e) int
        Pairs of neighbouring CFEs of the joints with entries (see the module's docstring).
    entry : (m,) bool
        The entry CFEs of those joints.
    gated : (m,) bool
        CFEs of joints with entries (wet only when joined to an entry by open CFEs).
    bridged : (m,) bool
        Closed CFEs that do not cut the connection (conduct water while closed).
    beyond : tuple
        Joints with the EM 1110 rule: (order, s, drain) each — the joint's CFEs in order from
        the entry, their distances from the entry CFE along the joint (m), and (s_d, E,
        reference) of its drains or None.
    """

    wettable: np.ndarray
    crack: dict[str, np.ndarray]
    uplift: dict[str, np.ndarray]
    level: dict[str, np.ndarray]
    area: np.ndarray
    y: np.ndarray
    links: np.ndarray
    entry: np.ndarray
    gated: np.ndarray
    bridged: np.ndarray | None = None
    beyond: tuple = ()
    #: wet sets of the open sets seen so far (the driver asks for one scheme many times)
    _memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def wet(self, states: np.ndarray) -> np.ndarray:
        """CFEs the water fills in the scheme ``states``: open, of a joint with crack water and
        (joints with entries) joined to an entry CFE by open CFEs (the module's rule)."""
        op = self.wettable & (states == OPEN)
        if not self.gated.any():
            return op
        bridged = self.bridged
        if bridged is not None:  # closed, not bonded (an intact bond keeps water out)
            bridged = bridged & self.wettable & (states != BONDED) & ~op
        key = op.tobytes() if bridged is None else op.tobytes() + bridged.tobytes()
        wet = self._memo.get(key)
        if wet is None:
            conducts = op if bridged is None else op | bridged
            i, j = self.links
            both = conducts[i] & conducts[j]
            m = len(op)
            graph = sp.csr_matrix((np.ones(int(both.sum())), (i[both], j[both])),
                                  shape=(m, m))
            _, label = connected_components(graph, directed=False)
            reached = label[self.entry & conducts]
            if bridged is not None:  # a component of closed bridged CFEs holds no water
                reached = np.intersect1d(reached, label[op & self.gated])
            wet = conducts & (~self.gated | np.isin(label, reached))
            if len(self._memo) >= 256:
                self._memo.clear()
            self._memo[key] = wet
        return wet.copy()

    def _profile(self, wet: np.ndarray) -> tuple[np.ndarray, ...]:
        """The EM 1110 profile beyond the tip for the wet set ``wet``: (a, b, tip, end), each
        (m,) — p_k = a_k p_c[tip_k] + b_k p_u[end_k] on the CFEs with tip_k ≥ 0 (the module's
        docstring); tip = −1 elsewhere."""
        key = ("beyond", wet.tobytes())
        out = self._memo.get(key)
        if out is not None:
            return out
        m = len(wet)
        a, b = np.zeros(m), np.zeros(m)
        tip, end = np.full(m, -1, np.int64), np.full(m, -1, np.int64)
        for order, s, drain in self.beyond:
            w = np.flatnonzero(wet[order])
            if not len(w) or w[-1] == len(order) - 1:
                continue  # dry, or cracked through: nothing beyond the tip
            t = int(w[-1])
            rest = np.arange(t + 1, len(order))
            s_t, s_e, sk = s[t], s[-1], s[rest]
            if drain is None or drain[0] <= s_t:  # no drains, or the crack has reached them
                u = (sk - s_t) / (s_e - s_t)
                ak, bk = 1.0 - u, u
            else:  # tip → drained head at the drains → toe
                s_d, eff, ref = drain
                r = (1.0 - eff) * ((s_e - s_d) / (s_e - s_t) if ref == "line" else 1.0)
                up = sk <= s_d
                u1 = (sk - s_t) / (s_d - s_t)
                u2 = (sk - s_d) / max(s_e - s_d, 1e-300)
                ak = np.where(up, 1.0 - u1 + u1 * r, (1.0 - u2) * r)
                bk = np.where(up, u1 * (1.0 - r), (1.0 - u2) * (1.0 - r) + u2)
            ks = order[rest]
            a[ks], b[ks], tip[ks], end[ks] = ak, bk, order[t], order[-1]
        out = (a, b, tip, end)
        if len(self._memo) >= 256:
            self._memo.clear()
        self._memo[key] = out
        return out

    def _pressures(self, factors: dict[str, float], rates: dict[str, float] | None
                   ) -> tuple[np.ndarray, np.ndarray]:
        """(p_c, p_u) (m,), Pa, at the factors (or their rates per unit μ, as :meth:`net`)."""
        pc, pu = np.zeros(len(self.y)), np.zeros(len(self.y))
        moving = factors if rates is None else rates
        for name, q in self.crack.items():
            pc += moving.get(name, 0.0) * q
        for name, q in self.uplift.items():
            pu += moving.get(name, 0.0) * q
        for name, g in self.level.items():
            if name not in moving:
                continue
            h = factors.get(name, 0.0)
            if rates is None:
                pc += g * np.maximum(h - self.y, 0.0)
            else:
                r = rates[name]
                tol = 1e-12 * max(1.0, abs(h))
                above = (h - self.y > tol) | ((np.abs(h - self.y) <= tol) & (r > 0))
                pc += r * np.where(above, g, 0.0)
        return pc, pu

    def force_of(self, wet: np.ndarray, factors: dict[str, float],
                 rates: dict[str, float] | None = None) -> np.ndarray:
        """W (m,), N, of the wet set ``wet`` at ``factors`` (with ``rates``: dW/dμ): A (p_c −
        p_u) on the wet CFEs, and A (p_k − p_u) beyond the tips of EM 1110 joints."""
        W = np.where(wet, self.area * self.net(factors, rates), 0.0)
        if not self.beyond or not wet.any():
            return W
        a, b, tip, end = self._profile(wet)
        on = tip >= 0
        if not on.any():
            return W
        pc, pu = self._pressures(factors, rates)
        p = a[on] * pc[tip[on]] + b[on] * pu[end[on]]
        W[on] = self.area[on] * (p - pu[on])
        return W

    def loaded(self, wet: np.ndarray) -> np.ndarray:
        """The CFEs the crack water loads in the wet set ``wet``: the wet ones and, with the EM
        1110 rule, those beyond the tip."""
        if not self.beyond or not wet.any():
            return wet
        return wet | (self._profile(wet)[2] >= 0)

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
        return self.force_of(self.wet(states), factors)

    def rate(self, states: np.ndarray, factors: dict[str, float],
             rates: dict[str, float]) -> np.ndarray:
        """dW/dμ (m,) of the scheme ``states`` when the factors move at ``rates`` (per unit
        μ) from ``factors``."""
        return self.force_of(self.wet(states), factors, rates)

    def pressure(self, states: np.ndarray, factors: dict[str, float],
                 water: np.ndarray) -> np.ndarray:
        """Water pressure in the joint (m,), Pa, where the water acts: the CFEs wet in
        ``states`` (and beyond the tip under the EM 1110 rule) or loaded by ``water`` (a jump
        in progress): W/A + p_u."""
        filled = self.loaded(self.wet(states)) | (water != 0)
        return np.where(filled, water / self.area + self.uplift_pressure(factors), 0.0)

    def kinks(self, pattern: str) -> np.ndarray:
        """Levels (m) where the crack force of a level pattern has a kink (CFE heights)."""
        if pattern not in self.level:
            return np.zeros(0)
        return np.unique(self.y[self.level[pattern] != 0])


def _chain_links(order: np.ndarray) -> np.ndarray:
    """(2, k − 1) neighbours of a 2D joint: consecutive CFEs of ``order`` (along S+)."""
    return np.vstack([order[:-1], order[1:]])


def _carrier(model, cfe, itf, ks: np.ndarray) -> tuple[np.ndarray, object]:
    """The global nodes (k,) that carry the CFEs ``ks`` of 3D interface ``itf`` and the node
    set of their face: S+ when every CFE's S+ end is one node of its own (weight 1), else S−
    (mortar CFEs on S−'s nodes)."""
    pn, pw = cfe.plus_nodes[ks], cfe.plus_w[ks]
    single = (np.all(pn[:, 1:] < 0) and np.allclose(pw[:, 0], 1.0, rtol=0, atol=1e-12)
              and len(np.unique(pn[:, 0])) == len(ks))
    if single:
        return pn[:, 0], itf.plus
    return cfe.minus_nodes[ks, 0], itf.minus


def _facet_links(model, cfe, itf, ks: np.ndarray) -> np.ndarray:
    """(2, e) neighbours of a 3D joint: CFEs whose nodes belong to one facet of the face that
    carries them (:func:`_carrier`)."""
    from stepcontact.contact.interface3d import face_surface

    nodes, side = _carrier(model, cfe, itf, ks)
    body = model.body(side.body)
    surf = face_surface(body, side, f"interface '{itf.name}'")
    off = model.node_offsets[body.name]
    lookup = np.full(off + body.n_nodes, -1, dtype=np.int64)
    lookup[nodes] = ks
    f = lookup[surf.facets + off]  # (F, n): the CFE at each facet node, or −1
    a, b = np.triu_indices(f.shape[1], 1)
    i, j = f[:, a].ravel(), f[:, b].ravel()
    keep = (i >= 0) & (j >= 0) & (i != j)
    pairs = np.sort(np.vstack([i[keep], j[keep]]), axis=0)
    return np.unique(pairs, axis=1) if pairs.size else np.zeros((2, 0), np.int64)


def _segment_distance(x: np.ndarray, line: np.ndarray) -> np.ndarray:
    """Distance (k,) of the points ``x`` (k, 3) from the polyline ``line`` (n, 3), m."""
    if len(line) == 1:
        return np.linalg.norm(x - line[0], axis=1)
    a, b = line[:-1], line[1:]
    ab = b - a
    den = np.einsum("ij,ij->i", ab, ab)
    t = np.einsum("kij,ij->ki", x[:, None, :] - a[None], ab) / np.where(den > 0, den, 1.0)
    t = np.clip(t, 0.0, 1.0)
    closest = a[None] + t[..., None] * ab[None]
    return np.linalg.norm(x[:, None, :] - closest, axis=2).min(axis=1)


def _entry_rows(cw: CrackWater, x: np.ndarray, links: np.ndarray, local: np.ndarray,
                item: str) -> np.ndarray:
    """Positions (in ``x``, the joint's CFE points (k, 3)) of the CFEs along each entry
    polyline of 3D crack water: within half the shortest neighbour spacing of the nearest
    CFE's distance; a polyline farther than the longest spacing from every CFE is refused."""
    if cw.entry_dim != 3:
        raise ModelError(item, f"is a 2D point {cw.entry!r}, but the joint is 3D: give the "
                         "edge where water reaches it, a polyline of points (x, y, z) (the "
                         "heel edge), or a point (x, y, z)")
    spacing = np.linalg.norm(x[local[links[0]]] - x[local[links[1]]], axis=1)
    extent = float(np.ptp(x, axis=0).max()) if len(x) > 1 else 0.0
    near = max(float(spacing.min()) / 2 if spacing.size else 0.0, 1e-9 * max(extent, 1.0))
    far = max(float(spacing.max()) if spacing.size else 0.0, 1e-9 * max(extent, 1.0))
    out = []
    for line in cw.entry_lines:
        d = _segment_distance(x, line)
        if d.min() > far:
            lo, hi = x.min(axis=0), x.max(axis=0)
            raise ModelError(item, f"{tuple(line[0].round(6))} … is {d.min():.3g} m from the "
                             f"joint, which spans x = {lo[0]:g} … {hi[0]:g} m, y = {lo[1]:g} … "
                             f"{hi[1]:g} m, z = {lo[2]:g} … {hi[2]:g} m: water enters a crack "
                             "along an edge of its joint (e.g. the heel); give that edge")
        out.append(np.flatnonzero(d <= d.min() + near))
    return np.unique(np.concatenate(out))


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
    y = cfe.x[:, -1].copy() if m else np.zeros(0)  # the height: y in 2D, z in 3D
    entries: dict[str, CrackWater] = {}
    for pname, cw in items:
        item = f"load pattern '{pname}': crack water in interface '{cw.name}'"
        if cw.name not in names:
            known = ", ".join(repr(n) for n in names) or "none"
            raise ModelError(item, f"no such interface with CFEs (known: {known})")
        ks = np.flatnonzero(cfe.interface == names.index(cw.name))
        cw.check_level(y[ks], item)
        wettable[ks] = True
        if cw.name in entries and entries[cw.name].entry != cw.entry:
            raise ModelError(item, "the joint's crack water is given twice with different "
                             "entry points")
        entries[cw.name] = cw
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
    links = [np.zeros((2, 0), np.int64)]
    entry = np.zeros(m, bool)
    gated = np.zeros(m, bool)
    bridged = np.zeros(m, bool)
    beyond = []
    for name, cw in entries.items():
        if cw.entry is None:
            continue
        item = f"crack water in interface '{name}'.entry"
        ks = np.flatnonzero(cfe.interface == names.index(name))
        gated[ks] = True
        if cfe.x.shape[1] == 2:  # 2D: the chain along S+, the CFE nearest each point
            order = ks[np.argsort(cfe.s[ks], kind="stable")]
            points = cw.entries
            if not len(points):
                raise ModelError(item, f"is a 3D entry {cw.entry!r}, but the joint is 2D: "
                                 "give the point (x, y) where water reaches it")
            CrackWater.check_entries(points, cfe.x[order], item)
            at = [int(np.argmin(np.hypot(*(cfe.x[order] - pt).T))) for pt in points]
            links.append(_chain_links(order))
            entry[order[at]] = True
            bridged[_bridged(cw, cfe.x[order], order)] = True
            if cw.rule == "em1110":
                beyond.append(_em1110_joint(model, cw, cfe.x[order], order, at, item))
        else:  # 3D: the facets of the carrying face, the CFEs along each polyline
            itf = next(i for i in model.interfaces if i.name == name)
            lk = _facet_links(model, cfe, itf, ks)
            local = np.full(m, -1, dtype=np.int64)
            local[ks] = np.arange(len(ks))
            links.append(lk)
            entry[ks[_entry_rows(cw, cfe.x[ks], lk, local, item)]] = True
    # in the crack, the crack pressure replaces the uplift given for the joint
    for p in model.patterns:
        for ld in p.loads:
            if isinstance(ld, Uplift) and ld.name in entries:
                ks = np.flatnonzero(cfe.interface == names.index(ld.name))
                pu = np.asarray(ld.function()(cfe.x[ks, 0], cfe.x[ks, 1]), float)
                uplift.setdefault(p.name, np.zeros(m))[ks] += np.broadcast_to(pu, ks.shape)
    return CrackWaterData(wettable, crack, uplift, level, cfe.area.copy(), y,
                          np.concatenate(links, axis=1), entry, gated,
                          bridged if bridged.any() else None, tuple(beyond))


def _bridged(cw: CrackWater, x: np.ndarray, order: np.ndarray) -> np.ndarray:
    """The CFEs (global indices) of a 2D joint whose closure does not cut the crack from the
    reservoir (:class:`CrackWater` ``bridge``): those within ``bridge`` metres of an entry
    point (``x``: the joint's CFE points in ``order``; none for ``bridge=0``)."""
    if cw.bridge <= 0:
        return order[:0]
    d = np.min([np.hypot(*(x - pt).T) for pt in cw.entries], axis=0)
    return order[d <= cw.bridge * (1 + 1e-12)]


def _em1110_joint(model, cw: CrackWater, x: np.ndarray, order: np.ndarray, at: list[int],
                  item: str) -> tuple:
    """(order, s, drain) of a 2D joint with the EM 1110 rule (:attr:`CrackWaterData.beyond`):
    its CFEs from the entry end, their distances along the joint from the entry CFE (m), and
    (s_d, E, reference) of the drains of its :class:`~stepcontact.model.Uplift` (None: no
    drains).  The entry must be at an end of the joint (the heel)."""
    from stepcontact.model.water import Uplift

    if len(at) != 1 or at[0] not in (0, len(order) - 1) or len(order) < 2:
        raise ModelError(f"{item[:-len('.entry')]}.rule", "'em1110' needs one entry at an end of "
                         "the joint (the heel): the uplift beyond the crack runs from the tip "
                         "to the other end (the toe)")
    if at[0] != 0:
        order, x = order[::-1], x[::-1]
    s = np.r_[0.0, np.cumsum(np.hypot(*np.diff(x, axis=0).T))]
    drains = [ld.drains for p in model.patterns for ld in p.loads
              if isinstance(ld, Uplift) and ld.name == cw.name and ld.drains is not None]
    drain = None
    if drains:
        dr = drains[0]
        d = x[-1] - x[0]
        s_d = float((np.asarray(dr.at) - x[0]) @ d / np.hypot(*d)) * s[-1] / np.hypot(*d)
        drain = (s_d, dr.efficiency, dr.reference)
    return order, s, drain


__all__ = ["CrackWaterData", "crack_water"]
