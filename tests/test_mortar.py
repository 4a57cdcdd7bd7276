"""Mortar (segment-to-segment) CFEs on meshes that do not match.

* The contact patch test: two elastic blocks of one material pressed together (and sheared)
  through a flat interface whose meshes do not match carry the uniform contact stress, and
  every node moves with the exact linear field, to round-off (1e-10), for several mesh ratios,
  both choices of S+, linear and quadratic elements.  The loads are consistent nodal forces
  of uniform tractions built here from the edge integrals ∫φ ds (not by ``EdgeLoad``), and the
  reference is the closed-form uniform stress state.
* The article's node-to-segment CFE fails it (a few per cent), which is why mortar is the
  default where meshes do not match.
* The choice of CFE kind (auto, explicit), its errors; the CFEs do not depend on which
  side is called S+.
* A block sliding on a base with non-matching meshes still slides at exactly f·W.
* Hertz (cylinder on a block, non-matching meshes): pressures converge like on matching ones,
  with no spurious jumps.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import stepcontact as sc
import verification_models as vm
from stepcontact import ContactMeshWarning, ModelError, Status
from stepcontact.contact.geometry import tributary_lengths
from stepcontact.contact.laws import STICK
from stepcontact.fem.assembly import assemble

E, NU = 2e10, 0.25
P, TAU = 1e6, 3e5  # Pa: uniform pressure and shear of the patch test
H = 0.5  # m, height of each block


def _traction(model: sc.Model, body: str, ns: sc.NodeSet, tx: float, ty: float) -> list:
    """Consistent nodal forces (N) of a uniform traction (tx, ty) in Pa on the edges of ``ns``:
    t·∫φ_i ds × thickness at every node (L/2 per linear edge end; L/6, L/6, 2L/3 quadratic)."""
    L = tributary_lengths(model.body(body), ns) * model.thickness
    return [sc.NodalLoad(sc.NodeSet(body, [i]), fx=tx * L[i], fy=ty * L[i]) for i in ns.index]


def patch_model(n_top: int, n_bot: int, element: str, top_plus: bool, shear: bool,
                cfe: str = "auto") -> sc.Model:
    """Block [0, 1] × [H, 2H] (``n_top`` cells along x) on a block [0, 1] × [0, H] (``n_bot``),
    one material.  Uniform stress σ_yy = −P, σ_xx = 0, τ_xy = TAU (if ``shear``) applied as
    the tractions σ·n on every face but the supported bottom (y fixed; x fixed at (0, 0)).
    Frictional (f = 0.5 > TAU/P) with shear; frictionless without, the top block then held in
    x at (0, 2H), where the exact field has u_x = 0."""
    mat = sc.Material(E, NU)
    bot = sc.rectangle("bot", (0, 0), (1, H), n_bot, 2, mat, element)
    top = sc.rectangle("top", (0, H), (1, 2 * H), n_top, 2, mat, element)
    m = sc.Model(bodies=[bot, top])
    tau = TAU if shear else 0.0
    loads = _traction(m, "top", m.select("top", y=2 * H), tau, -P)
    loads += _traction(m, "bot", m.select("bot", y=0.0), -tau, 0.0)
    for b in ("top", "bot"):
        loads += _traction(m, b, m.select(b, x=0.0), 0.0, -tau)
        loads += _traction(m, b, m.select(b, x=1.0), 0.0, tau)
    joint_top, joint_bot = m.select("top", y=H), m.select("bot", y=H)
    plus, minus = (joint_top, joint_bot) if top_plus else (joint_bot, joint_top)
    m = m.add(
        sc.Support("bed", m.select("bot", y=0.0), "y"),
        sc.Support("pin", m.select("bot", x=0.0, y=0.0), "x"),
        sc.Interface("joint", plus, minus, friction=0.5 if shear else 0.0, cfe=cfe),
        sc.LoadPattern("uniform", loads),
        sc.Segment("uniform", 1.0),
    )
    if not shear:
        m = m.add(sc.Support("hold", m.select("top", x=0.0, y=2 * H), "x"))
    return m


def exact_field(points: np.ndarray, shear: bool) -> np.ndarray:
    """Plane-strain displacements (m) of the uniform stress state with u_y(x, 0) = 0 and
    u_x(0, 0) = 0: ε_xx = ν(1+ν)P/E, ε_yy = −(1−ν²)P/E, γ_xy = 2(1+ν)τ/E (= ∂u_x/∂y)."""
    exx = NU * (1 + NU) * P / E
    eyy = -(1 - NU**2) * P / E
    gam = 2 * (1 + NU) * (TAU if shear else 0.0) / E
    x, y = points[:, 0], points[:, 1]
    return np.column_stack([exx * x + gam * y, eyy * y])


def _solve(model: sc.Model):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ContactMeshWarning)
        system = assemble(model)
        res = sc.solve_static(model)
    return system, res


@pytest.mark.parametrize("shear", [False, True], ids=["frictionless", "shear"])
@pytest.mark.parametrize("top_plus", [True, False], ids=["S+top", "S+bottom"])
@pytest.mark.parametrize("element", ["tri3", "quad4", "tri6", "quad8"])
@pytest.mark.parametrize("sizes", [(2, 3), (3, 5), (7, 4)], ids=lambda s: f"{s[0]}on{s[1]}")
def test_contact_patch_test_on_non_matching_meshes(sizes, element, top_plus, shear):
    """σ_n = −P and τ = TAU at every CFE, every CFE stuck, and every node on the exact linear
    field, to 1e-10 (relative to P and to the largest displacement)."""
    model = patch_model(*sizes, element, top_plus, shear)
    system, res = _solve(model)
    assert res.status == Status.COMPLETED, res.message
    area = system.cfe.area
    c = system.cfe  # mortar: the end on the finer side combines several nodes
    assert np.all((c.minus_nodes[:, 1] >= 0) | (c.plus_nodes[:, 1] >= 0)), "not mortar CFEs"
    assert np.abs(res.N[-1] / area + P).max() <= 1e-10 * P
    assert np.abs(np.abs(res.Q[-1] / area) - (TAU if shear else 0.0)).max() <= 1e-10 * P
    if shear:
        assert np.all(res.state[-1] == STICK)
    u = res.displacement(-1)
    exact = exact_field(model.points, shear)
    of = system.dofs.of
    got = np.column_stack([u[of[:, 0]], u[of[:, 1]]])
    assert np.abs(got - exact).max() <= 1e-10 * np.abs(exact).max()


@pytest.mark.parametrize("sizes", [(2, 3), (3, 5)], ids=lambda s: f"{s[0]}on{s[1]}")
def test_node_to_segment_fails_the_patch_test(sizes):
    """The article's CFE (cfe = 'node-to-segment') on the same meshes: the contact stress errs
    by more than 1 % somewhere (16 % on 2 against 3 cells), which mortar CFEs remove."""
    system, res = _solve(patch_model(*sizes, "quad4", True, False, cfe="node-to-segment"))
    assert res.status == Status.COMPLETED, res.message
    assert np.abs(res.N[-1] / system.cfe.area / -P - 1).max() > 0.01


def test_auto_chooses_node_to_node_on_matching_meshes_and_mortar_otherwise():
    """Matching meshes: each CFE joins two nodes (weight 1 on each side); meshes that do not
    match: mortar, whose S+ end is the S+ node and whose S− weights, ∫ψ_k φ_l / ∫φ_k, sum to 1."""
    s_match = assemble(patch_model(4, 4, "quad4", True, False))
    c = s_match.cfe
    assert np.all(c.plus_w[:, 0] == 1.0) and np.all(c.minus_w[:, 0] == 1.0)
    assert np.all(c.minus_nodes[:, 1:] < 0) and np.all(c.plus_nodes[:, 1:] < 0)
    assert np.allclose(s_match.model.points[c.minus_nodes[:, 0]], c.x, atol=1e-12)

    c = assemble(patch_model(2, 3, "quad8", True, False)).cfe
    assert np.all(c.plus_w[:, 0] == 1.0) and np.all(c.plus_nodes[:, 1:] < 0)
    w = np.where(c.minus_nodes >= 0, c.minus_w, 0.0)
    assert np.allclose(w.sum(axis=1), 1.0, atol=1e-13)
    # the contact areas are the S+ edge integrals ∫φ_k ds (quadratic: L/6 at the ends of an
    # edge, 2L/3 at its middle; 2 cells of 0.5 m)
    assert np.allclose(np.sort(c.area), np.sort([1 / 12, 1 / 12, 1 / 6, 1 / 3, 1 / 3]))


def test_cfe_kind_errors_name_the_interface():
    """node-to-node on meshes that do not match, an unknown kind, and mortar with node pairs are
    clean ModelErrors that name the interface (and the CFE where there is one)."""
    with pytest.raises(ModelError, match=r"interface 'joint' CFE \d+ at .*node-to-node"):
        assemble(patch_model(2, 3, "quad4", True, False, cfe="node-to-node"))
    with pytest.raises(ModelError, match=r"interface 'joint'\.cfe: unknown CFE kind 'nts'"):
        patch_model(2, 3, "quad4", True, False, cfe="nts")
    m = patch_model(2, 2, "quad4", True, False)
    with pytest.raises(ModelError, match=r"interface 'pins'\.cfe"):
        sc.Interface("pins", m.select("top", y=H), m.select("bot", y=H), pairs=True, cfe="mortar")


@pytest.mark.parametrize("sizes", [(13, 4), (4, 13), (5, 4), (3, 3)],
                         ids=lambda s: f"{s[0]}on{s[1]}")
def test_the_cfes_are_the_same_whichever_side_is_s_plus(sizes):
    """Swapping S+ and S− changes neither the CFEs nor their kinematics: the mortar CFEs sit on
    the coarser side (on a tie, on S+: the 3-on-3 meshes match and are node-to-node), and
    u_τ = t·(u⁺ − u⁻), u_n = −n·(u⁺ − u⁻) − g⁰ do not change sign when n, t and u⁺ − u⁻ all
    do.  B, g⁰ and the areas agree to 1e-14 (relative), the CFEs in the same order along S+,
    and the S+ points lie on the side called S+ (y = H on both: a flat joint)."""
    s1 = assemble(patch_model(*sizes, "quad4", True, False))
    s2 = assemble(patch_model(*sizes, "quad4", False, False))
    c1, c2 = s1.cfe, s2.cfe
    assert c1.m == c2.m == min(sizes) + 1
    o1, o2 = np.argsort(c1.x[:, 0]), np.argsort(c2.x[:, 0])
    m = c1.m
    rows1, rows2 = np.r_[o1, m + o1], np.r_[o2, m + o2]
    assert abs(s1.B[rows1] - s2.B[rows2]).max() <= 1e-14 * abs(s1.B).max()
    assert np.allclose(c1.area[o1], c2.area[o2], rtol=1e-14, atol=0)
    assert np.allclose(c1.gap, 0.0) and np.allclose(c2.gap, 0.0)
    assert np.allclose(c1.x[o1], c2.x[o2], atol=1e-14)
    assert np.all(np.diff(c1.s) > 0) and np.all(np.diff(c2.s) > 0)  # numbered along S+


@pytest.mark.parametrize("top_plus", [True, False], ids=["S+block", "S+base"])
def test_block_slides_at_f_times_w_on_non_matching_meshes(top_plus):
    """Block 2 m × 1 m (0.2 m cells) on a base 4 m wide (0.25 m cells), f = 0.5: self-weight,
    then a push; loss of equilibrium at H = f·W (1e-9), whichever side carries the CFEs (with
    S+ on the wider base, its nodes beyond the block get no CFE)."""
    concrete = sc.Material(30e9, 0.2, 2400.0)
    base = sc.rectangle("base", (0, 0), (4, 1), 16, 4, concrete)
    block = sc.rectangle("block", (1, 1), (3, 2), 10, 5, concrete)
    m = sc.Model(bodies=[base, block])
    left = m.select("block", x=1)
    bottom, top = m.select("block", y=1), m.select("base", y=1)
    plus, minus = (bottom, top) if top_plus else (top, bottom)
    m = m.add(
        sc.Support("bed", m.select("base", y=0), "xy"),
        sc.Interface("joint", plus, minus, friction=0.5),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
        sc.LoadPattern("push", [sc.NodalLoad(left, fx=1.0 / len(left))]),
        sc.Segment("weight", 1.0),
        sc.Segment("push", 1e6),
    )
    system, res = _solve(m)
    W = 2 * 1 * 2400 * 9.81
    assert res.status == Status.EQUILIBRIUM_LOST, res.message
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(0.5 * W, rel=1e-9)
    if not top_plus:  # base nodes at x = 0 … 0.75 and 3.25 … 4 face no part of the block
        assert system.cfe.m == 9
        assert system.cfe.x[:, 0].min() == pytest.approx(1.0)
        assert system.cfe.x[:, 0].max() == pytest.approx(3.0)


def _hertz_errors(k: int, **kw) -> tuple[float, float, float, float]:
    """(max |p − p_Hertz| / p0 for x ≤ 0.9 a, largest second difference of p / p0 over the
    closed CFEs, relative error of the vertical resultant, half-width error / a)."""
    a, p0 = vm.hertz_solution()
    system, res = _solve(vm.hertz_model(a / k, **kw))
    assert res.status == Status.COMPLETED, res.message
    c = system.cfe
    N = res.N[-1]
    x, p = c.x[:, 0], -N / c.area
    inner = x <= 0.9 * a
    err = np.abs(p[inner] - p0 * np.sqrt(1 - (x[inner] / a) ** 2)).max() / p0
    order = np.argsort(x)
    closed = order[N[order] < -1e-9 * np.abs(N).max()]
    jump = np.abs(np.diff(p[closed], 2)).max() / p0
    force = abs((N * c.normal[:, 1]).sum()) / (vm.HERTZ_P / 2) - 1
    return err, jump, force, abs(vm.hertz_half_width(x, N) / a - 1)


@pytest.mark.slow
def test_hertz_on_non_matching_meshes_converges_like_matching():
    """Cylinder on a block (see ``verification_models.hertz_model``), spacing a/10, a/16, a/24
    at the contact; the block's spacing 0.6 or 1.6 times the cylinder's, mortar CFEs on the
    coarser side, against the matching mesh with node-to-node-like CFEs (cfe = node-to-segment
    on the nearly matching mesh, the existing verification):

    * vertical resultant = P/2 to 1e-9 with the block's normal (S+ = block), and within the
      O(a/R)² tilt of the cylinder's normals otherwise;
    * pressure within 1 % of p0 √(1 − x²/a²) (x ≤ 0.9 a) on every mesh, as on the matching one;
    * no spurious jumps: second differences of the pressure ≤ 1.5 × those on the matching mesh
      + 0.01 p0, and falling under refinement;
    * half-width within 5 % on the finest mesh.
    """
    cases = {"matching": dict(cfe="node-to-segment"),
             "block finer": dict(block_ratio=0.6),
             "block coarser": dict(block_ratio=1.6, cylinder_plus=False)}
    out = {name: [_hertz_errors(k, **kw) for k in (10, 16, 24)] for name, kw in cases.items()}
    for name, rows in out.items():
        errs, jumps, forces, widths = np.array(rows).T
        assert np.all(errs <= 0.01), (name, errs)
        assert np.all(jumps <= 1.5 * np.array(out["matching"])[:, 1] + 0.01), (name, jumps)
        assert jumps[-1] < jumps[0], (name, jumps)
        assert widths[-1] <= 0.05, (name, widths)
        tol = 1e-9 if name in ("matching", "block coarser") else 5e-3
        assert np.all(np.abs(forces) <= tol), (name, forces)


def test_closest_segment_search_equals_brute_force():
    """The k-d tree search of the closest segment (used by every CFE kind) gives the same
    segment, ξ and distance as checking every segment, on a wiggly polyline with segments of
    very different lengths and points near and far (ties to the lowest index)."""
    from stepcontact.contact.geometry import _project

    rng = np.random.default_rng(3)
    s = np.cumsum(rng.uniform(0.01, 1.0, 60))
    pts = np.column_stack([s, 0.3 * np.sin(s)])
    a, b = pts[:-1], pts[1:]
    x = np.vstack([rng.uniform([-1, -2], [s[-1] + 1, 2], (300, 2)), pts[5:9]])
    seg, xi, dist = _project(x, a, b)
    ab = b - a
    t = np.clip(np.einsum("pjk,jk->pj", x[:, None] - a[None], ab) / (ab**2).sum(1), 0, 1)
    d = np.linalg.norm(x[:, None] - (a[None] + t[..., None] * ab[None]), axis=2)
    j = np.argmin(d, axis=1)
    assert np.allclose(dist, d[np.arange(len(x)), j], rtol=0, atol=1e-14)
    same = seg == j
    # a different segment only at an exact tie of distances
    assert np.all(same | (np.abs(d[np.arange(len(x)), seg] - d[np.arange(len(x)), j]) < 1e-14))
    assert np.allclose(xi[same], t[np.arange(len(x)), j][same], atol=1e-14)
