"""Water in the opened parts of a 3D joint (CrackWater on a 3D interface), with the reservoir
level as the load parameter (issue 28 §3): the same data and driver as in 2D
(:mod:`stepcontact.fem.crack`), the wet region the open CFEs joined to the entry edge through
open neighbours (CFEs whose nodes share a facet of the face that carries them).

References (independent of the code under test) and tolerances, per test:

* a prismatic block (one hex8 layer through the width, u_y = 0 at every node: plane strain)
  against the 2D block of the same section (its own 2D path): every 2D event is two 3D events
  (the CFEs at x on the two faces) of the same kind at the same level, in the same order, to
  1e-9 relative; the crack water's force of the two 3D CFEs at x adds up to the 2D CFE's
  (1e-9 of the largest);
* the statics of a 3D block whose heel has opened under full crack water: the vertical joint
  forces −N_k + W_k balance the weight, and their moments about the heel line and the side
  y = 0 balance the weight's and the hydrostatic thrust's (γ_w W_d h²/2 at h/3), to 1e-9 of
  the weight (× its lever); the crack water is γ_w h A_k on each wet CFE and the crack
  pressure γ_w h (1e-12 relative), and where the wet region is whole rows from the heel its
  resultant is γ_w h times the wet strip's area [0, x_j + a/2] × [0, W_d] (1e-12 relative);
* an eccentric load (a pull up at one downstream corner) that opens the joint unevenly: at
  every settled state (the last at its level, the water let in) the wet CFEs are those a
  breadth-first search over the grid's facet neighbours (written here) reaches from the heel
  row through open CFEs, and the water force is γ_w h A_k there and 0 elsewhere (1e-12 relative);
* mortar CFEs on the coarser side's nodes: their neighbours are the node pairs of its facets
  (listed by hand), and the displacements recovered at a state with water equal the stored
  ones (1e-12 of the largest).
"""

from __future__ import annotations

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.enums import ContactState, Transition
from stepcontact.errors import ModelError
from stepcontact.fem.assembly import assemble
from stepcontact.model.mesh import box

GW, G = 9810.0, 9.81
CONC = sc.Material(E=25e9, nu=0.2, density=2400.0)
KN = 1e9  # Pa/m, the contact layer
TOL = 1e-9


# --------------------------------------------------------------------------------------------
# (a) the prismatic block against the 2D block
# --------------------------------------------------------------------------------------------
B2, H2, NX, NY = 8.0, 12.0, 8, 12


def _head(x, y):
    """The uplift head per metre of water: 1 at the heel, 0 at the toe."""
    return 1.0 - np.asarray(x, float) / B2


def dam_2d() -> sc.Model:
    """A block B × H on a compliant layer on a rigid base, its weight, then the reservoir level
    h rising from 0 to 30 m on its upstream face x = 0, uplift h (1 − x/B) through the CFEs
    and crack water entering at the heel."""
    dam = sc.rectangle("dam", (0, 0), (B2, H2), NX, NY, CONC)
    m = sc.Model(bodies=[dam])
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (B2 + 1.0, 0.0)])
    base = sc.Interface("base", plus=m.select("dam", y=0), minus=ground, friction=0.9,
                        layer=sc.ContactLayer(kn=KN, kt=KN))
    return m.add(base, sc.LoadPattern("weight", [sc.BodyForce(bodies=("dam",))]),
                 sc.LoadPattern("water", [
                     sc.WaterLoad(m.select("dam", x=0.0), level=None),
                     sc.Uplift(base, head=_head, through="cfes"),
                     sc.CrackWater(base, entry=(0.0, 0.0))]),
                 sc.Segment("weight", 1.0), sc.Segment("water", 30.0))


def dam_prism() -> sc.Model:
    """The same block as a 3D body, x along the base, the width y (1 m, one hex8 layer), z up,
    u_y = 0 at every node (plane strain) on a rigid plane z = 0 with the same layer; the
    crack water enters along the heel edge x = z = 0."""
    dam = box("dam", (0, 0, 0), (B2, 1.0, H2), (NX, 1, NY), CONC)
    m = sc.Model(bodies=[dam])
    base = sc.Interface("base", plus=m.select("dam", boundary="bottom"),
                        minus=sc.RigidPlane("ground"), friction=0.9,
                        layer=sc.ContactLayer(kn=KN, kt=KN))
    every = m.select("dam", lambda x, y, z: np.ones(np.shape(x), bool))
    return m.add(base, sc.Support("plane strain", every, "y"),
                 sc.LoadPattern("weight", [sc.BodyForce(g=(0.0, 0.0, -G), bodies=("dam",))]),
                 sc.LoadPattern("water", [
                     sc.WaterLoad(m.select("dam", lambda x, y, z: np.abs(x) < 1e-9),
                                  level=None),
                     sc.Uplift(base, head=_head, through="cfes"),
                     sc.CrackWater(base, entry=[(0.0, 0.0, 0.0), (0.0, 1.0, 0.0)])]),
                 sc.Segment("weight", 1.0), sc.Segment("water", 30.0))


def _kind(t: Transition) -> str:
    return "slip" if t in (Transition.SLIP_POS, Transition.SLIP_NEG, Transition.SLIP) else \
        t.value


def test_prismatic_block_reproduces_the_2d_crack_water_run():
    r2 = sc.solve_static(dam_2d())
    r3 = sc.solve_static(dam_prism())
    assert r2.status == r3.status == sc.Status.EQUILIBRIUM_LOST, (r2.message, r3.message)
    e2 = [e for e in r2.events if e.segment == 1]
    e3 = [e for e in r3.events if e.segment == 1]
    assert sum(e.transition == Transition.OPENED for e in e2) >= 6  # the crack runs along
    assert len(e3) == 2 * len(e2)
    x3 = np.asarray(r3.cfe["x"])
    # the 3D events in pairs (same kind, same x, the two faces y = 0 and 1), in 2D's order
    groups: list[list] = []
    for e in e3:
        key = (_kind(e.transition), round(float(x3[e.cfe, 0]), 9))
        g = next((g for g in groups if g[0] == key and len(g[1]) < 2), None)
        if g is None:
            groups.append([key, [e]])
        else:
            g[1].append(e)
    assert len(groups) == len(e2)
    x2 = np.asarray(r2.cfe["x"])[:, 0]
    for a, (key, pair) in zip(e2, groups, strict=True):
        assert key == (_kind(a.transition), pytest.approx(x2[a.cfe], abs=1e-12))
        assert len(pair) == 2
        assert sorted(float(x3[e.cfe, 1]) for e in pair) == pytest.approx([0.0, 1.0])
        for e in pair:
            assert e.lam == pytest.approx(a.lam, rel=TOL)
    assert r3.lam[-1] == pytest.approx(r2.lam[-1], rel=TOL)
    # the crack water's forces: the two 3D CFEs at x carry the 2D CFE's
    w2, w3 = np.asarray(r2.water)[-1], np.asarray(r3.water)[-1]
    per_x = np.array([w3[np.isclose(x3[:, 0], xi)].sum() for xi in x2])
    assert np.count_nonzero(w2) >= 6
    assert np.abs(per_x - w2).max() <= TOL * np.abs(w2).max()
    assert r3.residual.max() < TOL and r3.violation.max() < TOL


# --------------------------------------------------------------------------------------------
# (b), (c) a 3D block, its heel opening under full crack water
# --------------------------------------------------------------------------------------------
B, WD, HT, A_CELL = 4.0, 2.0, 8.0, 1.0  # m: base, width, height, cell size


def block_3d(pull: float = 0.0) -> sc.Model:
    """A block B × W_d × H (1 m hex8 cells) on a compliant layer on the rigid plane z = 0, its
    weight (with ``pull`` N up at the downstream corner x = B, y = 0 on top), then the level
    h rising from 0 to H on its upstream face x = 0, crack water (no uplift) entering along
    the heel edge."""
    dam = box("dam", (0, 0, 0), (B, WD, HT), (4, 2, 8), CONC)
    m = sc.Model(bodies=[dam])
    base = sc.Interface("base", plus=m.select("dam", boundary="bottom"),
                        minus=sc.RigidPlane("ground"), friction=2.0,
                        layer=sc.ContactLayer(kn=KN, kt=KN))
    loads = [sc.BodyForce(g=(0.0, 0.0, -G), bodies=("dam",))]
    if pull:
        corner = m.select("dam", lambda x, y, z: (np.abs(x - B) < 1e-9) & (np.abs(y) < 1e-9)
                          & (np.abs(z - HT) < 1e-9))
        loads.append(sc.NodalLoad(corner, fz=pull))
    return m.add(base, sc.LoadPattern("weight", loads),
                 sc.LoadPattern("water", [
                     sc.WaterLoad(m.select("dam", lambda x, y, z: np.abs(x) < 1e-9),
                                  level=None),
                     sc.CrackWater(base, entry=[(0.0, 0.0, 0.0), (0.0, WD, 0.0)])]),
                 sc.Segment("weight", 1.0), sc.Segment("water", HT))


def _levels(res) -> np.ndarray:
    """The water level h (m) of every state (0 during the weight segment)."""
    return np.asarray(res.factors)[:, list(res.pattern_names).index("water")]


def _settled(res) -> np.ndarray:
    """(n_states,) bool: the last state recorded at its level in its segment, where the
    water that the openings let in has entered (the states before it at the same level are
    events under that jump, with part of it applied)."""
    lam, seg = np.asarray(res.lam), np.asarray(res.segment)
    last = np.ones(len(lam), bool)
    last[:-1] = (lam[1:] != lam[:-1]) | (seg[1:] != seg[:-1])
    # a run that stops while the water enters (the crack runs through) ends under the jump
    last[-1] = res.status == sc.Status.COMPLETED
    return last


def test_an_opened_heel_carries_the_hydrostatic_resultant_of_its_crack_water():
    res = sc.solve_static(block_3d())
    assert res.status == sc.Status.COMPLETED, res.message
    x, A = np.asarray(res.cfe["x"]), np.asarray(res.cfe["area"])
    N, Wc, h = np.asarray(res.N), np.asarray(res.water), _levels(res)
    settled = _settled(res)
    cw = np.asarray(res.factors)[:, list(res.pattern_names).index("weight")]
    checked = strips = 0
    for i in range(len(res.lam)):
        # the block's statics at every state (under a jump too): joint forces up
        # V_k = −N_k + W_k at (x_k, y_k, 0)
        V = -N[i] + Wc[i]
        weight = cw[i] * CONC.density * G * B * WD * HT
        thrust = GW * WD * h[i] ** 2 / 2  # at z = h/3 on the face x = 0
        scale = CONC.density * G * B * WD * HT
        assert V.sum() == pytest.approx(weight, abs=TOL * scale)
        assert V @ x[:, 0] == pytest.approx(weight * B / 2 + thrust * h[i] / 3,
                                            abs=TOL * scale * B)
        assert V @ x[:, 1] == pytest.approx(weight * WD / 2, abs=TOL * scale * WD)
        wet = Wc[i] != 0
        if not (wet.any() and settled[i]):
            continue
        checked += 1
        # the crack water: the full hydrostatic pressure γ_w h at z = 0 on each wet CFE
        assert Wc[i][wet] == pytest.approx(GW * h[i] * A[wet], rel=1e-12)
        pc = np.asarray(res.crack_pressure)[i]
        assert pc[wet] == pytest.approx(GW * h[i], rel=1e-12) and not pc[~wet].any()
        # whole rows from the heel wet: the resultant is γ_w h × the strip's area
        xs = np.unique(x[wet, 0])
        if np.array_equal(wet, x[:, 0] <= xs.max() + 1e-9):
            strips += 1
            strip = (xs.max() + A_CELL / 2) * WD
            assert Wc[i].sum() == pytest.approx(GW * h[i] * strip, rel=1e-12)
    assert checked >= 3 and strips >= 3
    assert res.residual.max() < TOL and res.violation.max() < TOL


def _reached(x: np.ndarray, open_: np.ndarray) -> np.ndarray:
    """The open CFEs a breadth-first search reaches from the open ones of the heel row x = 0
    through open grid neighbours (nodes of one quad facet: |Δx|, |Δy| ≤ one cell)."""
    near = (np.abs(x[:, None, 0] - x[None, :, 0]) <= A_CELL + 1e-9) & \
           (np.abs(x[:, None, 1] - x[None, :, 1]) <= A_CELL + 1e-9)
    seen = open_ & (np.abs(x[:, 0]) < 1e-9)
    todo = list(np.flatnonzero(seen))
    while todo:
        k = todo.pop()
        for j in np.flatnonzero(near[k] & open_ & ~seen):
            seen[j] = True
            todo.append(j)
    return seen


def test_an_uneven_crack_is_wet_where_it_joins_the_heel_through_open_cfes():
    res = sc.solve_static(block_3d(pull=5e5))
    x, A = np.asarray(res.cfe["x"]), np.asarray(res.cfe["area"])
    st, Wc, h = np.asarray(res.state), np.asarray(res.water), _levels(res)
    heel = np.abs(x[:, 0]) < 1e-9
    corner = np.flatnonzero(np.isclose(x[:, 0], B) & np.isclose(x[:, 1], 0.0))
    dry_open = uneven = 0
    corner_dry = corner_wet = False
    for i in np.flatnonzero(_settled(res)):
        open_ = st[i] == ContactState.OPEN
        wet = _reached(x, open_)
        assert Wc[i] == pytest.approx(np.where(wet, GW * h[i] * A, 0.0), rel=1e-12,
                                      abs=0.0), i
        dry_open += int(np.any(open_ & ~wet))
        uneven += int(0 < np.count_nonzero(open_ & heel) < np.count_nonzero(heel)
                      and wet.any())
        corner_dry |= bool(open_[corner].all() and not wet[corner].any())
        corner_wet |= bool(wet[corner].all() and corner_dry)
    assert dry_open >= 3  # open CFEs away from the heel that the water does not reach
    assert uneven >= 1  # the heel open and wet on one side of the width only
    # the downstream corner, opened and dry under the pull, is wet once the crack along
    # y = 0 has reached it
    assert corner_dry and corner_wet
    # the crack then runs through at one level and the block tips over about the x axis
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert res.residual.max() < TOL and res.violation.max() < TOL


def test_mortar_cfes_on_the_coarser_side_are_neighbours_through_its_facets():
    """The block on a rock of its footprint meshed coarser (2 m cells): the mortar CFEs sit on
    the rock's 6 top nodes, and their neighbours are the node pairs of its two top facets
    (listed here by hand: 6 pairs per quad, the shared side once); the entry CFEs are the two
    on the heel edge.  The water enters the opened heel (γ_w h A_k, 1e-12), and the
    displacements recovered at a state with water equal the stored ones (1e-12 of the
    largest)."""
    dam = box("dam", (0, 0, 0), (B, WD, HT), (4, 2, 8), CONC)
    rock = box("rock", (0, 0, -2.0), (B, WD, 0.0), (2, 1, 1), CONC)
    m = sc.Model(bodies=[rock, dam])
    base = sc.Interface("base", plus=m.select("dam", boundary="bottom"),
                        minus=m.select("rock", boundary="top"), friction=2.0, cfe="mortar",
                        layer=sc.ContactLayer(kn=KN, kt=KN))
    m = m.add(base, sc.Support("bed", m.select("rock", boundary="bottom"), "xyz"),
              sc.LoadPattern("weight", [sc.BodyForce(g=(0.0, 0.0, -G), bodies=("dam",))]),
              sc.LoadPattern("water", [
                  sc.WaterLoad(m.select("dam", lambda x, y, z: np.abs(x) < 1e-9), level=None),
                  sc.CrackWater(base, entry=[(0.0, 0.0, 0.0), (0.0, WD, 0.0)])]),
              sc.Segment("weight", 1.0), sc.Segment("water", HT))
    system = assemble(m)
    x = system.cfe.x
    assert len(x) == 6  # the rock's nodes (x, y) ∈ {0, 2, 4} × {0, 2}
    at = {(round(p[0]), round(p[1])): k for k, p in enumerate(x)}
    quads = [[(0, 0), (2, 0), (2, 2), (0, 2)], [(2, 0), (4, 0), (4, 2), (2, 2)]]
    pairs = {tuple(sorted((at[a], at[b]))) for q in quads for a in q for b in q if a != b}
    links = system.crack.links
    assert len(pairs) == 11 and {tuple(sorted(p)) for p in links.T} == pairs
    assert links.shape[1] == 11
    assert set(np.flatnonzero(system.crack.entry)) == {at[(0, 0)], at[(0, 2)]}
    res = sc.solve_static(m, store_fields="all")
    Wc, A, h = np.asarray(res.water), np.asarray(res.cfe["area"]), _levels(res)
    i = int(np.flatnonzero(_settled(res) & (Wc != 0).any(axis=1))[0])
    wet = Wc[i] != 0
    assert set(np.flatnonzero(wet)) == {at[(0, 0)], at[(0, 2)]}
    assert Wc[i][wet] == pytest.approx(GW * h[i] * A[wet], rel=1e-12)
    stored = res.fields[i]
    res.fields.pop(i)
    assert np.abs(res.displacement(i) - stored).max() <= 1e-12 * np.abs(stored).max()


def test_3d_entry_errors_name_the_item():
    m = block_3d()
    far = m.replace(patterns=(m.patterns[0], sc.LoadPattern("water", [
        sc.WaterLoad(m.select("dam", lambda x, y, z: np.abs(x) < 1e-9), level=None),
        sc.CrackWater("base", entry=[(-5.0, 0.0, 0.0), (-5.0, WD, 0.0)])])))
    with pytest.raises(ModelError, match=r"'base'.entry.*from the joint"):
        sc.solve_static(far)
    flat = m.replace(patterns=(m.patterns[0], sc.LoadPattern("water", [
        sc.WaterLoad(m.select("dam", lambda x, y, z: np.abs(x) < 1e-9), level=None),
        sc.CrackWater("base", entry=(0.0, 0.0))])))
    with pytest.raises(ModelError, match=r"'base'.entry.*2D point"):
        sc.solve_static(flat)
    with pytest.raises(ModelError, match="entry"):
        sc.CrackWater("base", level=3.0, entry=[[(0.0, 0.0, 0.0)], [(1.0, 0.0)]])
    two = sc.CrackWater("base", level=3.0, entry=[[(0, 0, 0), (0, 2, 0)], [(4, 0, 0)]])
    assert two.entry_dim == 3 and [len(p) for p in two.entry_lines] == [2, 1]
