"""Rigid obstacles: contact against a fixed or moving line or polyline, not meshed.

Closed forms:

* a block on a fixed rigid line slides at H = f·W, and its contact forces sum to W;
* a block on a rigid line inclined at 30°, pushed horizontally up the slope: it slides when
  P cos α − W sin α = f (W cos α + P sin α), P* = W (sin α + f cos α) / (cos α − f sin α);
* a block in a frictionless V-groove (a polyline with a kink) rests on its two lower corners,
  each carrying N = W / (2 cos α); the gaps of the other nodes are their distances to the
  faces; on a ridge the CFE at the kink takes the mean of the two normals;
* a block pulled up off a rigid line lifts off at T = W;
* a rigid line pushed up by δ·λ against a block held by springs k at its contact nodes: the
  gap closes at λ = g⁰/δ and the contact force is k(δλ − g⁰) (so is the obstacle's reaction);
  a line turned by θ·λ about a point closes the farthest node first, at λ = g⁰/(θ x);
* the same block on a meshed, very stiff foundation comes close to the rigid-obstacle answer.

Every solve: equilibrium residual and contact-condition violation ≤ 1e-9.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import stepcontact as sc
from stepcontact import ModelError, Status
from stepcontact.contact.geometry import build_contact
from stepcontact.fem.assembly import assemble

RHO, G = 2400.0, 9.81
CONCRETE = sc.Material(30e9, 0.2, RHO)
TOL = 1e-9


def solve(model: sc.Model) -> sc.StaticResult:
    res = sc.solve_static(model)
    assert np.max(res.residual) <= TOL
    assert np.max(res.violation) <= TOL
    return res


def flat_block(friction: float = 0.5, obstacle: sc.RigidObstacle | None = None) -> sc.Model:
    """Block [1, 3] × [0, 1] on the rigid line y = 0: self-weight, then a push along +x."""
    block = sc.rectangle("block", (1, 0), (3, 1), 8, 4, CONCRETE)
    m = sc.Model(bodies=[block])
    ground = obstacle or sc.RigidObstacle("ground", [(-5, 0), (5, 0)])
    left = m.select("block", x=1)
    return m.add(
        sc.Interface("base", plus=m.select("block", y=0), minus=ground, friction=friction),
        sc.LoadPattern("weight", [sc.BodyForce()]),
        sc.LoadPattern("push", [sc.EdgeForce(left, fx=1.0)]),
        sc.Segment("weight", 1.0),
        sc.Segment("push", 1e6),
    )


# --------------------------------------------------------------------------------------------
# fixed obstacles
# --------------------------------------------------------------------------------------------
def test_block_slides_on_a_fixed_rigid_line_at_f_W():
    m = flat_block()
    res = solve(m)
    W = 2 * 1 * RHO * G
    assert res.status == Status.EQUILIBRIUM_LOST
    assert_allclose(res.multipliers[-1].equilibrium_lost, 0.5 * W, rtol=TOL)
    after_weight = int(np.flatnonzero(res.segment == 0)[-1])
    assert_allclose(-res.N[after_weight].sum(), W, rtol=TOL)
    assert_allclose(res.Q[after_weight].sum(), 0.0, atol=TOL * W)
    # the S− ends have no nodes: the obstacle is the ground
    assert np.all(np.asarray(res.cfe["minus_nodes"]) == -1)
    assert_allclose(res.cfe["normal"], np.tile([0.0, 1.0], (res.m, 1)), atol=1e-15)
    assert_allclose(res.cfe["gap"], 0.0, atol=0)
    assert len(res.geometry["points"]) == m.bodies[0].n_nodes  # a fixed obstacle: no nodes


@pytest.mark.parametrize("f", [0.7, 1.0])
def test_block_on_a_30_degree_rigid_line_slides_up_at_the_hand_statics_load(f):
    a = np.radians(30.0)
    block = sc.rotate(sc.rectangle("block", (0, 0), (2, 0.5), 8, 2, CONCRETE), a)
    m = sc.Model(bodies=[block])
    slope = sc.RigidObstacle("slope", [(-5 * np.cos(a), -5 * np.sin(a)),
                                       (5 * np.cos(a), 5 * np.sin(a))])
    on = lambda x, y: np.abs(-np.sin(a) * x + np.cos(a) * y) < 1e-9  # noqa: E731
    back = lambda x, y: np.abs(np.cos(a) * x + np.sin(a) * y) < 1e-9  # noqa: E731
    m = m.add(
        sc.Interface("base", plus=m.select("block", on), minus=slope, friction=f),
        sc.LoadPattern("weight", [sc.BodyForce()]),
        sc.LoadPattern("push", [sc.EdgeForce(m.select("block", back), fx=1.0)]),
        sc.Segment("weight", 1.0),
        sc.Segment("push", 1e6),
    )
    res = solve(m)
    W = 2 * 0.5 * RHO * G
    P = W * (np.sin(a) + f * np.cos(a)) / (np.cos(a) - f * np.sin(a))
    assert res.status == Status.EQUILIBRIUM_LOST
    assert_allclose(res.multipliers[-1].equilibrium_lost, P, rtol=TOL)
    assert_allclose(res.cfe["normal"], np.tile([-np.sin(a), np.cos(a)], (res.m, 1)), atol=1e-15)
    after_weight = int(np.flatnonzero(res.segment == 0)[-1])
    assert_allclose(-res.N[after_weight].sum(), W * np.cos(a), rtol=TOL)
    assert_allclose(res.Q[after_weight].sum(), -W * np.sin(a), rtol=TOL)  # t points downhill


def test_block_in_a_v_groove_rests_on_its_corners():
    """Polyline with a kink (a valley): frictionless, x held at the top centre (the
    instantaneous rotation about the crossing of the two corner normals)."""
    a = np.radians(30.0)
    b, h, y0 = 1.0, 0.5, 0.5 * np.tan(a)
    groove = sc.RigidObstacle("groove", [(-2, 2 * np.tan(a)), (0, 0), (2, 2 * np.tan(a))])
    block = sc.rectangle("block", (-b / 2, y0), (b / 2, y0 + h), 4, 2, CONCRETE)
    m = sc.Model(bodies=[block])
    bottom = m.select("block", y=y0)
    m = m.add(
        sc.Interface("groove", plus=bottom, minus=groove),
        sc.Support("hold", m.select("block", x=0.0, y=y0 + h), "x"),
        sc.LoadPattern("weight", [sc.BodyForce()]),
        sc.Segment("weight", 1.0),
    )
    res = solve(m)
    W = b * h * RHO * G
    x = np.asarray(res.cfe["x"])
    corner = np.isclose(np.abs(x[:, 0]), b / 2)
    assert_allclose(res.N[-1, corner], -W / (2 * np.cos(a)), rtol=TOL)
    assert_allclose(res.N[-1, ~corner], 0.0, atol=TOL * W)
    assert_allclose(res.reaction("hold", "x")[-1], 0.0, atol=TOL * W)
    # geometry: the gaps are the distances to the faces, the normals those of the faces
    assert_allclose(res.cfe["gap"], (b / 2 - np.abs(x[:, 0])) * np.sin(a), atol=1e-15)
    nx = np.where(x[:, 0] < 0, np.sin(a), -np.sin(a))
    side = x[:, 0] != 0  # the centre node is as far from both faces: either normal
    assert_allclose(np.asarray(res.cfe["normal"])[side],
                    np.column_stack([nx, np.full(len(x), np.cos(a))])[side], atol=1e-15)


def test_ridge_kink_normals_and_gaps():
    """A ridge: flat for x < 0, falling at β for x > 0.  Ends that coincide take the normal of
    their segment, at the kink the mean of the two; beyond it the gap is x sin β."""
    beta = np.radians(20.0)
    ridge = sc.RigidObstacle("ridge", [(-2, 0), (0, 0), (2, -2 * np.tan(beta))])
    block = sc.rectangle("block", (-1, 0), (1, 0.5), 8, 2, CONCRETE)
    m = sc.Model(bodies=[block])
    m = m.add(sc.Interface("base", plus=m.select("block", y=0), minus=ridge, friction=0.5))
    cfe = build_contact(m)
    x = cfe.x[:, 0]
    left, kink, right = x < -1e-12, np.abs(x) <= 1e-12, x > 1e-12
    assert_allclose(cfe.normal[left], np.tile([0.0, 1.0], (left.sum(), 1)), atol=1e-15)
    assert_allclose(cfe.normal[kink], [[np.sin(beta / 2), np.cos(beta / 2)]], atol=1e-15)
    assert_allclose(cfe.normal[right], np.tile([np.sin(beta), np.cos(beta)], (right.sum(), 1)),
                    atol=1e-15)
    assert_allclose(cfe.gap, np.where(right, x * np.sin(beta), 0.0), atol=1e-15)
    assert_allclose(cfe.tangent, np.column_stack([cfe.normal[:, 1], -cfe.normal[:, 0]]))
    assert np.all(cfe.minus_nodes == -1)


def test_ends_that_coincide_on_a_segment_take_its_normal_both_sides():
    """A block under a ceiling (side="right" of a line drawn left to right): normal −y."""
    ceiling = sc.RigidObstacle("ceiling", [(-5, 1), (5, 1)], side="right")
    block = sc.rectangle("block", (0, 0), (1, 1), 2, 2, CONCRETE)
    m = sc.Model(bodies=[block])
    m = m.add(sc.Interface("top", plus=m.select("block", y=1), minus=ceiling))
    cfe = build_contact(m)
    assert_allclose(cfe.normal, np.tile([0.0, -1.0], (cfe.m, 1)), atol=1e-15)
    assert_allclose(cfe.gap, 0.0, atol=0)


def test_block_lifts_off_a_rigid_line_at_W():
    block = sc.rectangle("block", (0, 0), (2, 1), 8, 4, CONCRETE)
    m = sc.Model(bodies=[block])
    ground = sc.RigidObstacle("ground", [(-1, 0), (3, 0)])
    m = m.add(
        sc.Interface("base", plus=m.select("block", y=0), minus=ground, friction=0.5),
        sc.LoadPattern("weight", [sc.BodyForce()]),
        sc.LoadPattern("pull", [sc.EdgeForce(m.select("block", y=1), fy=1.0)]),
        sc.Segment("weight", 1.0),
        sc.Segment("pull", 1e6),
    )
    res = solve(m)
    W = 2 * RHO * G
    assert res.status == Status.EQUILIBRIUM_LOST
    assert_allclose(res.multipliers[-1].equilibrium_lost, W, rtol=TOL)
    assert res.multipliers[-1].first_opening <= W  # the corners open first (elasticity)


def test_nodes_beyond_the_ends_of_the_obstacle_get_no_cfe():
    short = sc.RigidObstacle("short", [(0.0, 0.0), (1.0, 0.0)])
    block = sc.rectangle("block", (0, 0), (2, 1), 4, 2, CONCRETE)
    m = sc.Model(bodies=[block])
    m = m.add(sc.Interface("base", plus=m.select("block", y=0), minus=short))
    cfe = build_contact(m)
    assert_allclose(np.sort(cfe.x[:, 0]), [0.0, 0.5, 1.0])


# --------------------------------------------------------------------------------------------
# moving obstacles
# --------------------------------------------------------------------------------------------
G0, K, DELTA = 1e-3, 2e8, 3e-3


def lifted_block(motion) -> sc.Model:
    """Block [0, 2] × [g⁰, 1 + g⁰] over the line y = 0, held by springs (k in all, x and y) at
    its bottom nodes; the line moved by ``motion(obstacle)``."""
    block = sc.rectangle("block", (0, G0), (2, 1 + G0), 4, 2, CONCRETE)
    m = sc.Model(bodies=[block])
    ground = sc.RigidObstacle("ground", [(-1, 0), (3, 0)])
    bot = m.select("block", y=G0)
    n = len(bot)
    return m.add(
        sc.Interface("base", plus=bot, minus=ground),
        sc.Spring("hold", bot, None, kx=K / n, ky=K / n),
        sc.LoadPattern("lift", [motion(ground)]),
        sc.Segment("lift", 1.0),
    )


def test_moving_obstacle_closes_the_gap_and_pushes_with_k_times_the_overlap():
    m = lifted_block(lambda o: sc.ObstacleMotion(o, dy=DELTA))
    res = solve(m)
    lam = np.asarray(res.lam)
    assert_allclose(res.multipliers[0].first_closing, G0 / DELTA, rtol=TOL)
    assert_allclose(-res.N.sum(axis=1), K * np.maximum(lam * DELTA - G0, 0.0),
                    rtol=TOL, atol=TOL * K * DELTA)
    # the obstacle's reaction on the structure, and its vertex nodes after the bodies' nodes
    assert_allclose(res.reaction("ground", "y"), K * np.maximum(lam * DELTA - G0, 0.0),
                    rtol=TOL, atol=TOL * K * DELTA)
    assert_allclose(res.reaction("ground", "x"), 0.0, atol=TOL * K * DELTA)
    n_body = m.bodies[0].n_nodes
    assert_allclose(res.geometry["points"][n_body:], [[-1, 0], [3, 0]])
    assert np.all(np.asarray(res.cfe["minus_nodes"])[:, :2] == [n_body, n_body + 1])
    assert_allclose(np.asarray(res.cfe["minus_w"]).sum(axis=1), 1.0)
    u = res.displacements([len(res.lam) - 1])[0]
    dof = np.asarray(res.geometry["dof_of"])[n_body:, :2]
    assert_allclose(u[dof], [[0, DELTA], [0, DELTA]], atol=1e-18)


def test_turning_obstacle_closes_the_farthest_node_first():
    theta = 1e-3  # rad per unit λ about (0, 0)
    m = lifted_block(lambda o: sc.ObstacleMotion(o, rotation=theta, about=(0.0, 0.0)))
    res = solve(m)
    first = res.events[0]
    assert_allclose(first.lam, G0 / (theta * 2.0), rtol=TOL)
    assert_allclose(np.asarray(res.cfe["x"])[first.cfe, 0], 2.0)


def test_obstacle_motion_in_a_model_file_matches_the_api():
    text = {
        "materials": {"concrete": {"E": 30e9, "nu": 0.2, "density": 2400}},
        "bodies": [{"name": "block", "kind": "rectangle", "corner0": [0, G0],
                    "corner1": [2, 1 + G0], "nx": 4, "ny": 2, "material": "concrete"}],
        "node_sets": {"bottom": {"body": "block", "y": G0}},
        "springs": [{"name": "hold", "a": "bottom", "kx": K / 5, "ky": K / 5}],
        "obstacles": [{"name": "ground", "points": [[-1, 0], [3, 0]]}],
        "interfaces": [{"name": "base", "plus": "bottom", "obstacle": "ground"}],
        "patterns": {"lift": {"loads": [{"type": "obstacle_motion", "obstacle": "ground",
                                         "dy": DELTA}]}},
        "program": [{"pattern": "lift", "end": 1.0}],
    }
    res = solve(sc.model_from_dict(text))
    ref = solve(lifted_block(lambda o: sc.ObstacleMotion(o, dy=DELTA)))
    assert_allclose(res.N, ref.N, rtol=1e-12, atol=1e-6)
    bad = dict(text, interfaces=[{"name": "base", "plus": "bottom", "obstacle": "grund"}])
    with pytest.raises(ModelError, match=r"interfaces\[0\].obstacle.*unknown obstacle 'grund'"):
        sc.model_from_dict(bad)
    both = dict(text, interfaces=[{"name": "base", "plus": "bottom", "minus": "bottom",
                                   "obstacle": "ground"}])
    with pytest.raises(ModelError, match="either minus"):
        sc.model_from_dict(both)
    side = dict(text, obstacles=[{"name": "ground", "points": [[-1, 0], [3, 0]],
                                  "side": "up"}])
    with pytest.raises(ModelError, match=r"obstacles\[0\]\.side"):
        sc.model_from_dict(side)


# --------------------------------------------------------------------------------------------
# results, files, transforms
# --------------------------------------------------------------------------------------------
def test_result_file_and_export_with_obstacles(tmp_path):
    meshio = pytest.importorskip("meshio")
    for model in (flat_block(), lifted_block(lambda o: sc.ObstacleMotion(o, dy=DELTA))):
        res = solve(model)
        path = tmp_path / f"{model.interfaces[0].name}{res.m}.nc"
        res.save(path)
        back = sc.load_result(path)
        assert_allclose(back.cfe["minus_nodes"], res.cfe["minus_nodes"])
        assert_allclose(back.N, res.N)
        out = sc.export_vtu(res, tmp_path / f"vtu{len(res.geometry['points'])}")
        cfe = meshio.read(sorted((out.parent / out.stem).glob("*_cfe_*.vtu"))[-1])
        m = res.m
        x, n, g = (np.asarray(res.cfe[k]) for k in ("x", "normal", "gap"))
        # the S− end of every CFE lies on the obstacle (where it stood at the start)
        assert_allclose(cfe.points[m:, :2], x - g[:, None] * n, atol=1e-12)


def test_translate_and_rotate_move_the_obstacle():
    m = flat_block()
    moved = sc.translate(m, (10.0, -2.0))
    assert_allclose(moved.obstacles[0].points, [[5, -2], [15, -2]])
    res = solve(moved)
    assert_allclose(res.multipliers[-1].equilibrium_lost, 0.5 * 2 * RHO * G, rtol=TOL)
    turned = sc.rotate(m, np.pi / 2)
    assert_allclose(turned.obstacles[0].points, [[0, -5], [0, 5]], atol=1e-12)
    assert_allclose(build_contact(turned).normal, np.tile([-1.0, 0.0], (9, 1)), atol=1e-12)


# --------------------------------------------------------------------------------------------
# errors
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("points, side, match", [
    ([(0, 0)], "left", r"obstacle 'wall'.points: needs at least two points"),
    ([(0, 0), (0, 0), (1, 0)], "left", r"obstacle 'wall'.points: segment 0"),
    ([(0, 0), (np.nan, 0)], "left", r"obstacle 'wall'.points: contains NaN"),
    ([(0, 0, 0), (1, 0, 0)], "left", r"obstacle 'wall'.points: must be a list of \(x, y\)"),
    ([(0, 0), (1, 0)], "above", r"obstacle 'wall'.side: must be 'left' or 'right'"),
])
def test_bad_obstacles_are_named(points, side, match):
    with pytest.raises(ModelError, match=match):
        sc.RigidObstacle("wall", points, side)


def test_errors_name_the_obstacle():
    block = sc.rectangle("block", (0, 0), (1, 1), 2, 2, CONCRETE)
    m = sc.Model(bodies=[block])
    bottom = m.select("block", y=0)
    below = sc.RigidObstacle("floor", [(-1, 0.25), (2, 0.25)])  # cuts into the block
    with pytest.raises(ModelError, match=r"interface 'base' CFE 0 .*penetrates obstacle "
                                         r"'floor' by 0.25 m"):
        build_contact(m.add(sc.Interface("base", plus=bottom, minus=below)))
    wrong_side = sc.RigidObstacle("floor", [(2, 0), (-1, 0)])  # bodies below it
    with pytest.raises(ModelError, match="obstacle's side"):
        build_contact(m.add(sc.Interface("base", plus=m.select("block", y=1),
                                         minus=wrong_side)))
    ground = sc.RigidObstacle("ground", [(-1, 0), (2, 0)])
    with pytest.raises(ModelError, match=r"interface 'base'.pairs: .*obstacle 'ground'"):
        sc.Interface("base", plus=bottom, minus=ground, pairs=True)
    with pytest.raises(ModelError, match=r"interface 'base'.cfe: 'mortar' .*obstacle 'ground'"):
        sc.Interface("base", plus=bottom, minus=ground, cfe="mortar")
    with pytest.raises(ModelError, match=r"interface 'base'.plus: is obstacle 'ground'"):
        sc.Interface("base", plus=ground, minus=bottom)
    with pytest.raises(ModelError, match=r"obstacle 'ground'.*enters a model"):
        m.add(ground)
    other = sc.RigidObstacle("ground", [(-1, 0), (3, 0)])
    with pytest.raises(ModelError, match=r"obstacle 'ground': two different obstacles"):
        m.add(sc.Interface("a", plus=bottom, minus=ground),
              sc.Interface("b", plus=m.select("block", y=1), minus=other))
    far = sc.RigidObstacle("far", [(5, 0), (6, 0)])
    with pytest.raises(ModelError, match=r"obstacle 'far'.*beyond its ends"):
        build_contact(m.add(sc.Interface("base", plus=bottom, minus=far)))
    moved = m.add(sc.Interface("base", plus=bottom, minus=ground),
                  sc.LoadPattern("lift", [sc.ObstacleMotion("nowhere", dy=1e-3)]),
                  sc.Segment("lift", 1.0))
    with pytest.raises(ModelError, match=r"obstacle 'nowhere': no interface"):
        assemble(moved)
    with pytest.raises(ModelError, match=r"motion of obstacle 'ground'.dx"):
        sc.ObstacleMotion(ground, dx=np.inf)


# --------------------------------------------------------------------------------------------
# cross-check: a meshed, very stiff foundation
# --------------------------------------------------------------------------------------------
def test_a_very_stiff_meshed_foundation_approaches_the_rigid_line():
    rigid = solve(flat_block())
    stiff = sc.Material(30e9 * 1e4, 0.2, 0.0)
    block = sc.rectangle("block", (1, 0), (3, 1), 8, 4, CONCRETE)
    base = sc.rectangle("base", (-1, -1), (5, 0), 24, 4, stiff)
    m = sc.Model(bodies=[base, block])
    left = m.select("block", x=1)
    m = m.add(
        sc.Support("bed", m.select("base", y=-1), "xy"),
        sc.Interface("base", plus=m.select("block", y=0), minus=m.select("base", y=0),
                     friction=0.5),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
        sc.LoadPattern("push", [sc.EdgeForce(left, fx=1.0)]),
        sc.Segment("weight", 1.0),
        sc.Segment("push", 1e6),
    )
    meshed = solve(m)
    W = 2 * RHO * G
    # sliding at f·W is exact in both; the contact forces and the first slip come close
    assert_allclose(meshed.multipliers[-1].equilibrium_lost, 0.5 * W, rtol=TOL)
    i, j = (int(np.flatnonzero(r.segment == 0)[-1]) for r in (rigid, meshed))
    assert_allclose(meshed.N[j], rigid.N[i], rtol=0, atol=1e-3 * W)
    assert_allclose(meshed.multipliers[-1].first_slip, rigid.multipliers[-1].first_slip,
                    rtol=1e-2)


def _walled_block(layer: sc.ContactLayer | None) -> sc.Model:
    """A block on a fixed line, squeezed by a wall moving 1 mm left per unit λ from 1 mm away;
    the wall interface includes the block's bottom corner, which the base also holds."""
    m = sc.Model(bodies=[sc.rectangle("block", (1, 0), (3, 1), 8, 4, CONCRETE)])
    ground = sc.RigidObstacle("ground", [(-5, 0), (5, 0)])
    wall = sc.RigidObstacle("wall", [(3.001, 0), (3.001, 2)])
    return m.add(
        sc.Interface("base", plus=m.select("block", y=0), minus=ground, friction=0.5),
        sc.Interface("side", plus=m.select("block", x=3), minus=wall, layer=layer),
        sc.LoadPattern("weight", [sc.BodyForce()]),
        sc.LoadPattern("squeeze", [sc.ObstacleMotion(wall, dx=-1e-3)]),
        sc.Segment("weight", 1.0),
        sc.Segment("squeeze", 2.0),
    )


def test_rigid_constraints_in_conflict_are_named_not_a_mechanism():
    """The corner is held in x by its stuck base CFE and pushed in x by the wall: two rigid
    constraints on one motion that the load drives apart.  Not a loss of equilibrium: a
    rate-problem stop that names both CFEs and says what to change; with a compliant layer
    on the wall the run completes, the base sliding under the wall's push f·W."""
    res = sc.solve_static(_walled_block(None))
    assert res.status == Status.RATE_PROBLEM
    assert "rigid contacts conflict" in res.message
    assert "base[8]" in res.message and "side[0]" in res.message
    soft = sc.solve_static(_walled_block(sc.ContactLayer(kn=1e12, kt=1e12)))
    assert soft.status == Status.COMPLETED, soft.message
    W = RHO * 9.81 * 2.0
    assert -soft.reaction("wall", "x")[-1] == pytest.approx(0.5 * W, rel=1e-6)
