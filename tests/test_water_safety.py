"""Water loads (hydrostatic pressure, uplift), pressures by coordinates and the safety of joints.

References are independent of the code: closed forms (γ d²/2 at d/3, trapezoid resultants),
per-node integrals by adaptive quadrature (scipy), and the hand statics of a gravity dam block
on rock: sliding at λ = f W / (H + f U), ΣN = −(W − λ U), the normal resultant from the moment
balance of the dam and overturning when it reaches the toe.
"""

from __future__ import annotations

import json
import tomllib
import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import quad
from skfem import MeshQuad, MeshTri
from typer.testing import CliRunner

import stepcontact as sc
from model_toml import gravity_dam
from stepcontact.cli.commands import app
from stepcontact.errors import ModelError
from stepcontact.io.modelfile import model_from_dict, validation_report
from stepcontact.model.water import HydrostaticPressure, LinearProfile

GAMMA = 9810.0
CONCRETE = sc.Material(E=30e9, nu=0.2, density=2400)
ROCK = sc.Material(E=10e9, nu=0.25, density=2600)
ELEMENTS = ("tri3", "quad4", "tri6", "quad8", "quad9")
runner = CliRunner()


def resultant(model: sc.Model, f: np.ndarray, body: str | None = None) -> np.ndarray:
    """[F_x, F_y, M_z about the origin] of a force vector (only the nodes of ``body``)."""
    sysm = sc.assemble(model) if not hasattr(model, "dofs") else model
    m = sysm.model
    pts = m.points
    keep = np.ones(len(pts), dtype=bool)
    if body is not None:
        keep[:] = False
        off = m.node_offsets[body]
        keep[off:off + m.body(body).n_nodes] = True
    fx, fy = f[sysm.dofs.of[keep, 0]], f[sysm.dofs.of[keep, 1]]
    x, y = pts[keep, 0], pts[keep, 1]
    return np.array([fx.sum(), fy.sum(), np.sum(x * fy - y * fx)])


def load_vector(model: sc.Model, load) -> tuple[object, np.ndarray]:
    m = model.add(sc.LoadPattern("w", [load]))
    sysm = sc.assemble(m)
    return sysm, sysm.loads["w"].f


def block(element: str, shear: float = 0.0, ny: int = 10) -> sc.Model:
    """A 4 m × 10 m block, its upstream face x = shear · y (a batter when shear > 0), on a
    support at its base; ny rows of cells (1 m high for ny = 10)."""
    grid = (MeshTri if element.startswith("tri") else MeshQuad).init_tensor(
        np.linspace(0.0, 4.0, 3), np.linspace(0.0, 10.0, ny + 1))
    p = grid.p.copy()
    p[0] += shear * p[1] * (1.0 - p[0] / 4.0)  # the face moves, the back x = 4 stays
    mesh = type(grid)(p, grid.t)
    b = sc.Body.from_mesh("block", mesh, element, CONCRETE)
    m = sc.Model(bodies=[b])
    return m.add(sc.Support("base", m.select("block", y=0.0)))


def face_of(m: sc.Model, shear: float) -> sc.NodeSet:
    return m.select("block", lambda x, y: np.abs(x - shear * y) < 1e-9)


# --------------------------------------------------------------------------------------------
# hydrostatic pressure
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("element", ELEMENTS)
@pytest.mark.parametrize("level", [6.0, 6.3, 9.75])  # at a node, inside an edge (twice)
@pytest.mark.parametrize("shear", [0.0, 0.3])  # vertical face, battered face
def test_hydrostatic_resultant_and_line_of_action(element, level, shear):
    m = block(element, shear)
    sysm, f = load_vector(m, sc.WaterLoad(face_of(m, shear), level=level))
    Fx, Fy, M = resultant(sysm, f)
    d = level
    H = GAMMA * d**2 / 2  # horizontal: the pressure on the vertical projection of the face
    V = -shear * H  # vertical: the weight of the water above the batter
    # resultant at d/3 above the base, on the face: (x, y) = (shear·d/3, d/3)
    M_ref = shear * d / 3 * V - d / 3 * H
    assert_allclose([Fx, Fy], [H, V], rtol=1e-12, atol=1e-9 * H)
    assert_allclose(M, M_ref, rtol=1e-12)
    assert_allclose(-M / Fx if shear == 0 else (shear * d / 3 * Fy - M) / Fx, d / 3, rtol=1e-10)


@pytest.mark.parametrize("element", ["quad4", "tri6", "quad8"])
def test_hydrostatic_nodal_forces_by_adaptive_quadrature(element):
    """Every nodal force ∫ p φ_i ds of a vertical face, the level inside an edge (y = 6.3):
    against scipy's adaptive quadrature of each edge (split at the kink)."""
    level = 6.3
    m = block(element)
    sysm, f = load_vector(m, sc.WaterLoad(face_of(m, 0.0), level=level))
    pts = m.points
    on_face = np.flatnonzero(np.abs(pts[:, 0]) < 1e-12)
    y = np.sort(pts[on_face, 1])
    quadratic = element in ("tri6", "quad8", "quad9")
    step = 2 if quadratic else 1
    ref = dict.fromkeys(np.round(y, 12), 0.0)
    for j in range(0, len(y) - 1, step):
        nodes = y[j:j + step + 1]
        a, b = nodes[0], nodes[-1]
        if quadratic:
            shapes = [lambda t: (1 - t) * (1 - 2 * t), lambda t: 4 * t * (1 - t),
                      lambda t: t * (2 * t - 1)]
        else:
            shapes = [lambda t: 1 - t, lambda t: t]
        for yn, phi in zip(nodes, shapes, strict=True):
            def integrand(s, phi=phi, a=a, b=b):
                return GAMMA * max(level - s, 0.0) * phi((s - a) / (b - a))

            val, _ = quad(integrand, a, b, points=[level] if a < level < b else None,
                          epsabs=1e-12, epsrel=1e-13)
            ref[round(yn, 12)] += val
    got = f[sysm.dofs.of[on_face, 0]]
    want = np.array([ref[round(v, 12)] for v in pts[on_face, 1]])
    assert_allclose(got, want, rtol=1e-10, atol=1e-9 * GAMMA)


def test_plain_gauss_rule_misses_the_kink():
    """Why the edge is split: the same pressure as an ordinary edge load (Gauss points) is
    integrated inexactly where the level cuts an edge."""
    m = block("quad4")
    _, f_exact = load_vector(m, sc.WaterLoad(face_of(m, 0.0), level=6.3))
    sysm, f_gauss = load_vector(m, sc.EdgeLoad(face_of(m, 0.0), normal=HydrostaticPressure(6.3)))
    H = GAMMA * 6.3**2 / 2
    assert abs(resultant(sysm, f_gauss)[0] / H - 1) > 1e-5
    assert_allclose(resultant(sysm, f_exact)[0], H, rtol=1e-13)


def test_water_follows_coordinates_not_node_order():
    m = block("quad8")
    face = face_of(m, 0.0)
    rev = sc.NodeSet(face.body, face.index[::-1])
    profile = LinearProfile(((0.0, 10.0, 0.0), (0.0, 0.0, GAMMA * 10.0)))
    vectors = [load_vector(m, ld)[1] for ld in (
        sc.WaterLoad(face, 10.0), sc.WaterLoad(rev, 10.0),
        sc.EdgeLoad(face, normal=profile), sc.EdgeLoad(rev, normal=profile))]
    for v in vectors[1:]:
        assert_allclose(v, vectors[0], rtol=1e-12, atol=1e-6)
    # the old pair follows the node order: reversing the set flips the triangle
    _, a = load_vector(m, sc.EdgeLoad(face, normal=(0.0, GAMMA * 10.0)))
    _, b = load_vector(m, sc.EdgeLoad(rev, normal=(0.0, GAMMA * 10.0)))
    assert np.abs(a - b).max() > 1e3


def test_linear_profile_values_and_checks():
    p = LinearProfile(((0.0, 0.0, 10.0), (2.0, 0.0, 4.0), (8.0, 0.0, 0.0)))
    assert_allclose(p(np.array([0.0, 1.0, 2.0, 5.0, 8.0, 10.0]), np.zeros(6)),
                    [10.0, 7.0, 4.0, 2.0, 0.0, -4.0 / 3.0])  # continued beyond the ends
    assert_allclose(p(np.array([5.0]), np.array([3.0])), [2.0])  # by projection on the chord
    for bad in ([(0, 0, 1)], [(0, 0, 1), (0, 0, 2)], [(0, 0, 1), (2, 0, 1), (1, 0, 1)],
                [(0, 0, np.nan), (1, 0, 1)]):
        with pytest.raises(ModelError):
            LinearProfile(tuple(bad))
    with pytest.raises(ModelError, match="either head"):
        sc.Uplift("base")
    with pytest.raises(ModelError, match="unit_weight"):
        sc.WaterLoad(sc.NodeSet("b", [0]), 1.0, unit_weight=0.0)


# --------------------------------------------------------------------------------------------
# uplift
# --------------------------------------------------------------------------------------------
def dam_model(f: float = 0.7, element: str = "quad4", rock_nx: int = 18, d: float = 9.5,
              head=None, B: float = 8.0) -> sc.Model:
    """A B × 10 m concrete dam block on a rock base 18 m wide (x −5 … 13), joint friction f;
    patterns "weight" (the dam only) and "water" (level d on the upstream face x = 0 and
    uplift from head d at the heel to 0 at the toe)."""
    rock = sc.rectangle("rock", (-5.0, -5.0), (13.0, 0.0), rock_nx, 5, ROCK, element)
    dam = sc.rectangle("dam", (0.0, 0.0), (B, 10.0), int(B), 10, CONCRETE, element)
    m = sc.Model(bodies=[rock, dam], name="dam")
    base = sc.Interface("base", m.select("dam", y=0.0), m.select("rock", y=0.0), friction=f)
    head = [(0.0, 0.0, d), (B, 0.0, 0.0)] if head is None else head
    return m.add(
        sc.Support("bed", m.select("rock", y=-5.0)), base,
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("dam",))]),
        sc.LoadPattern("water", [sc.WaterLoad(m.select("dam", x=0.0), level=d),
                                 sc.Uplift(base, head=head)]),
        sc.Segment("weight", 1.0), sc.Segment("water", 3.0),
    )


@pytest.mark.parametrize("element", ["quad4", "quad8"])
@pytest.mark.parametrize("rock_nx", [18, 12])  # matching meshes; rock edges across the ends
def test_uplift_equal_and_opposite(element, rock_nx):
    m = dam_model(element=element, rock_nx=rock_nx)
    sysm, f = load_vector(m, sc.Uplift("base", head=[(0.0, 0.0, 9.5), (8.0, 0.0, 3.0)]))
    # trapezoid 9.5 → 3 m of head over B = 8 m: resultant and its distance from the heel
    U = GAMMA * (9.5 + 3.0) / 2 * 8.0
    xU = 8.0 * (9.5 + 2 * 3.0) / (3 * (9.5 + 3.0))
    on_dam = resultant(sysm, f, "dam")
    on_rock = resultant(sysm, f, "rock")
    assert_allclose(on_dam, [0.0, U, xU * U], rtol=1e-12, atol=1e-9 * U)
    assert_allclose(on_rock, [0.0, -U, -xU * U], rtol=1e-12, atol=1e-9 * U)
    assert_allclose(on_dam + on_rock, 0.0, atol=1e-9 * U)


def test_uplift_through_a_drainage_line():
    """A piecewise-linear head (heel 10 m, 3 m at the drain x = 2.5, inside an edge; 0 at the
    toe), given as pressure in Pa: trapezoid + triangle."""
    pts = [(0.0, 0.0, GAMMA * 10.0), (2.5, 0.0, GAMMA * 3.0), (8.0, 0.0, 0.0)]
    m = dam_model()
    sysm, f = load_vector(m, sc.Uplift("base", pressure=pts))
    parts = [(GAMMA * 13.0 / 2 * 2.5, 2.5 * (10 + 2 * 3) / (3 * 13)),
             (GAMMA * 3.0 / 2 * 5.5, 2.5 + 5.5 / 3)]
    U = sum(p for p, _ in parts)
    M = sum(p * x for p, x in parts)
    assert_allclose(resultant(sysm, f, "dam"), [0.0, U, M], rtol=1e-12, atol=1e-9 * U)
    assert_allclose(resultant(sysm, f, "rock"), [0.0, -U, -M], rtol=1e-12, atol=1e-9 * U)


# --------------------------------------------------------------------------------------------
# the gravity dam: sliding, ΣN, sliding factor, eccentricity, overturning
# --------------------------------------------------------------------------------------------
B, HEIGHT, D, F = 8.0, 10.0, 9.5, 0.7
W = 2400 * 9.81 * B * HEIGHT  # weight of the dam only (the rock's goes to the support)
H = GAMMA * D**2 / 2  # water on the upstream face, at D/3
U = GAMMA * D * B / 2  # uplift triangle, at B/3 from the heel


@pytest.fixture(scope="module")
def sliding_run():
    m = dam_model(F)
    return m, sc.solve_static(m)


def factors(res, name: str) -> np.ndarray:
    return np.asarray(res.factors)[:, list(res.pattern_names).index(name)]


def test_dam_slides_at_the_hand_load_factor(sliding_run):
    _, res = sliding_run
    lam_hand = F * W / (H + F * U)  # λ H = f (W − λ U)
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    assert "sliding" in res.message
    assert_allclose(res.multipliers[-1].equilibrium_lost, lam_hand, rtol=1e-7)
    s = res.interface_safety("base", design=1.25)
    assert s.mechanism == "sliding" and s.lam_overturning is None
    assert_allclose(s.lam_sliding, lam_hand, rtol=1e-7)
    assert_allclose(s.fs_sliding, lam_hand / 1.25, rtol=1e-7)
    assert_allclose(s.sliding_factor[-1], 1.0, rtol=1e-9)


def test_dam_resultants_and_sliding_factor_by_hand(sliding_run):
    _, res = sliding_run
    s = res.interface_safety("base")
    lw, lg = factors(res, "water"), factors(res, "weight")
    k = np.flatnonzero(np.asarray(res.cfe["interface"]) == 0)
    sN, sQ = res.N[:, k].sum(axis=1), res.Q[:, k].sum(axis=1)
    # vertical and horizontal equilibrium of the dam: ΣN = −(W − λ U), ΣQ = λ H
    assert_allclose(s.normal_force, -(lg * W - lw * U), rtol=1e-9, atol=1e-6 * W)
    assert_allclose(s.shear_force, lw * H, rtol=1e-9, atol=1e-6 * W)
    closed = ~np.any(res.state[:, k] == int(sc.ContactState.OPEN), axis=1)
    assert closed[:3].all() and not closed[-1]
    assert_allclose(s.normal_force[closed], -(lg * W - lw * U)[closed], rtol=1e-10)
    assert_allclose(s.open_length[closed], 0.0)
    loaded = np.abs(sQ) > 1e-6 * W
    assert_allclose(s.sliding_factor[loaded], F * -sN[loaded] / np.abs(sQ[loaded]), rtol=1e-12)
    assert np.all(s.sliding_factor[loaded] >= 1.0 - 1e-9)
    # open length: the tributary lengths (1 m inside, 0.5 m at the ends) of the open CFEs
    trib = np.where((res.cfe["x"][k, 0] == 0.0) | (res.cfe["x"][k, 0] == B), 0.5, 1.0)
    is_open = res.state[:, k] == int(sc.ContactState.OPEN)
    assert_allclose(s.open_length, is_open @ trib, atol=1e-12)
    assert s.open_length[-1] > 0


def test_dam_eccentricity_from_the_moment_balance(sliding_run):
    _, res = sliding_run
    s = res.interface_safety("base", heel=(0.0, 0.0))
    lw, lg = factors(res, "water"), factors(res, "weight")
    # moments about the heel of the forces on the dam: weight at B/2, water at D/3 above the
    # base, uplift at B/3, the joint's normal resultant −ΣN at x_R (its shear acts at y = 0)
    on = lg > 0
    lw, lg = lw[on], lg[on]
    xR = np.full(res.n_states, np.nan)
    xR[on] = (lg * W * B / 2 + lw * H * D / 3 - lw * U * B / 3) / (lg * W - lw * U)
    assert_allclose(s.position[on], xR[on], rtol=1e-9)
    assert_allclose(s.eccentricity[on], xR[on] - B / 2, rtol=1e-9, atol=1e-9)
    assert_allclose(s.point[on, 0], xR[on], rtol=1e-9)
    assert_array_equal_bool(s.in_kern[on], np.abs(xR[on] - B / 2) <= B / 6)
    assert s.in_kern[1] and not s.in_kern[-1]
    assert_allclose(s.heel, [0.0, 0.0]) and assert_allclose(s.toe, [B, 0.0])
    k = np.flatnonzero(np.asarray(res.cfe["interface"]) == 0)
    k = k[np.argsort(res.cfe["s"][k])]
    assert_allclose(s.sigma_heel, res.N[:, k[0]] / res.cfe["area"][k[0]])
    assert_allclose(s.sigma_toe, res.N[:, k[-1]] / res.cfe["area"][k[-1]])
    # the heel named at the other end: positions measured from x = B
    r = res.interface_safety("base", heel=(B + 1.0, 0.0))
    assert_allclose(r.position[on], B - xR[on], rtol=1e-9)
    assert_allclose(r.sigma_heel, s.sigma_toe)


def assert_array_equal_bool(a, b) -> None:
    assert np.array_equal(np.asarray(a, dtype=bool), np.asarray(b, dtype=bool)), (a, b)


def test_dam_overturns_when_the_resultant_reaches_the_toe():
    """f = 1: sliding would need λ = W / (H + U) = 2.31; the dam tips first, when the normal
    resultant reaches the toe: W B/2 = λ (H D/3 + U (B − B/3))."""
    res = sc.solve_static(dam_model(1.0))
    lam_o = W * B / 2 / (H * D / 3 + U * (B - B / 3))
    s = res.interface_safety("base", design=1.0)
    assert s.lam_sliding is None
    assert_allclose(s.lam_overturning, lam_o, rtol=1e-7)
    assert_allclose(s.fs_overturning, lam_o, rtol=1e-7)
    assert_allclose(s.eccentricity[-1], B / 2, rtol=1e-9)
    # the mechanism: the dam rotates about the toe, where only the toe CFE (0.5 m) is closed
    assert res.status == sc.Status.EQUILIBRIUM_LOST and "overturning" in res.message
    assert_allclose(res.multipliers[-1].equilibrium_lost, lam_o, rtol=1e-7)
    assert_allclose(s.open_length[-1], B - 0.5, atol=1e-12)


def test_safety_round_trips_through_the_result_file(sliding_run, tmp_path):
    _, res = sliding_run
    res.save(tmp_path / "dam.nc")
    back = sc.load_result(tmp_path / "dam.nc").interface_safety("base", 1.0).at()
    assert back == res.interface_safety("base", 1.0).at()
    with pytest.raises(KeyError, match="no interface 'joint'"):
        res.interface_safety("joint")
    with pytest.raises(ValueError, match="design"):
        res.interface_safety("base", design=0.0)


def test_cli_info_and_plot_show_the_safety(sliding_run, tmp_path):
    _, res = sliding_run
    nc = tmp_path / "dam.nc"
    res.save(nc)
    out = runner.invoke(app, ["info", str(nc), "--design", "1.0"])
    assert out.exit_code == 0, out.output
    s = res.interface_safety("base", 1.0)
    for text in ("interface 'base' at the last state", "friction-only factor", "in the kern",
                 f"{s.lam_sliding:.6g}", "margin: λ at sliding / design λ",
                 "shear-friction factor", "overturning factor"):
        assert text in out.stdout, text
    out = runner.invoke(app, ["info", str(nc), "--json"])
    (got,) = json.loads(out.stdout)["interface_safety"]
    assert got["interface"] == "base" and got["mechanism"] == "sliding"
    assert_allclose(got["sliding_factor"], s.sliding_factor[-1])
    assert_allclose(got["open_length"], s.open_length[-1])
    out = runner.invoke(app, ["plot", str(nc), "--kind", "safety", "-o", str(tmp_path / "s.png")])
    assert out.exit_code == 0, out.output
    assert (tmp_path / "s.png").read_bytes()[:4] == b"\x89PNG"
    fig = sc.plot_safety(res, design=1.0)
    # the whole path: 3 rows × a column per segment (weight, then water), each on its own λ
    assert len(fig.axes) == 3 * 2
    assert [ax.get_xlabel() for ax in fig.axes[4:]] == ["λ\nof 'weight'", "λ of 'water'"]


# --------------------------------------------------------------------------------------------
# model files
# --------------------------------------------------------------------------------------------
DAM_FILE = gravity_dam() + """
[patterns.water]
loads = [
    { type = "water", nodes = "upstream", level = 9.5 },
    { type = "uplift", interface = "base", head = { from = [0, 0, 9.5], to = [8, 0, 0] } },
]
[[program]]
pattern = "weight"
end = 1.0
[[program]]
pattern = "water"
end = 3.0
"""


def test_model_file_water_and_uplift_match_the_api():
    mf = model_from_dict(tomllib.loads(DAM_FILE))
    api = dam_model()
    a, b = sc.assemble(mf), sc.assemble(api)
    for name in ("weight", "water"):
        assert_allclose(a.loads[name].f, b.loads[name].f, rtol=1e-12, atol=1e-6)
    res = sc.solve_static(mf)
    assert_allclose(res.multipliers[-1].equilibrium_lost, F * W / (H + F * U), rtol=1e-7)


def test_model_file_pressure_by_coordinates_and_deprecated_pair(tmp_path):
    by_coords = DAM_FILE.replace(
        '{ type = "water", nodes = "upstream", level = 9.5 }',
        '{ type = "pressure", nodes = "upstream", normal = { from = [0.0, 5.0, 49050.0], '
        'to = [0.0, 0.0, 98100.0] } }')
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mf = model_from_dict(tomllib.loads(by_coords))
    # linear in y through the two points, continued up to the crest: the 10 m level
    ref = dam_model(d=10.0, head=[(0.0, 0.0, 9.5), (8.0, 0.0, 0.0)])
    assert_allclose(sc.assemble(mf).loads["water"].f, sc.assemble(ref).loads["water"].f,
                    rtol=1e-12, atol=1e-6)
    pair = DAM_FILE.replace('{ type = "water", nodes = "upstream", level = 9.5 }',
                            '{ type = "pressure", nodes = "upstream", normal = [93195.0, 0.0] }')
    with pytest.warns(FutureWarning, match="varies along the node set's order"):
        model_from_dict(tomllib.loads(pair))
    path = tmp_path / "pair.toml"
    path.write_text(pair)
    report = validation_report(path)
    assert report.ok and any("normal" in w.item for w in report.warnings)


@pytest.mark.parametrize(("change", "where", "message"), [
    ('interface = "base", head', "interface", "unknown interface 'bottom'"),
    ("level = 9.5", "loads[0]", "level"),
    ("head = {", "loads[1]", "either head"),
])
def test_model_file_water_errors(change, where, message):
    bad = {
        'interface = "base", head': DAM_FILE.replace('interface = "base", head',
                                                     'interface = "bottom", head'),
        "level = 9.5": DAM_FILE.replace("level = 9.5", 'level = "high"'),
        "head = {": DAM_FILE.replace("head = {", "pressure = 1.0, head = {"),
    }[change]
    with pytest.raises(ModelError) as e:
        model_from_dict(tomllib.loads(bad))
    assert where in e.value.item and message in str(e.value)
