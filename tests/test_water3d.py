"""Water loads on the faces of 3D bodies (z up), at a fixed level and with the level as the load
parameter (issue 28 §3; ``stepcontact.fem.level.FacetWetting``).

References (closed forms and an independent integration):
* on a vertical face of width W and depth d the resultant is γ_w W d²/2 at d/3 above the bottom
  (full face under a head above the top: the trapezoid's resultant and centroid), on a battered
  face normal to it with γ_w W d² / (2 cos β), β the batter angle — to 1e-12 relative;
* nodal forces equal scikit-fem's face integration of p = γ_w (h − z) (an independent code
  path, exact when the whole face is wet) — to 1e-12;
* within a piece (between corner levels) the factors are polynomials of the stated degree in h:
  the Taylor coefficients reproduce them at any level of the piece — to 1e-12;
* the level-following load at every level equals the fixed-level load — to 1e-12;
* a static run with the level as the load parameter: the reactions balance the water's
  resultant at every recorded level — to 1e-9.
"""

from __future__ import annotations

import numpy as np
import pytest
from skfem import MeshHex

import faceted_reference as fr
import stepcontact as sc
from stepcontact.errors import ModelError
from stepcontact.model.mesh import box

GAMMA = 9810.0
CONCRETE = sc.Material(E=25e9, nu=0.2, density=2400)
ELEMENTS = ["hex8", "hex20", "hex27", "tet4", "tet10"]
W, H = 3.0, 10.0  # width (y) and height (z) of the block, m


def block(element: str, batter: float = 0.0) -> tuple[sc.Model, sc.NodeSet]:
    """A 4 × 3 × 10 m block fixed at its base; upstream face x = batter · z (2 × 2 × 5 cells)."""
    b = box("dam", (0, 0, 0), (4.0, W, H), (2, 2, 5), CONCRETE, element=element)
    if batter:
        mesh = b.mesh
        p = mesh.p.copy()
        p[0] += batter * p[2] * (1.0 - p[0] / 4.0)  # faces stay flat parallelograms
        b = sc.Body.from_mesh("dam", type(mesh)(p, mesh.t), element, CONCRETE)
    m = sc.Model(bodies=[b])
    m = m.add(sc.Support("base", m.select("dam", lambda x, y, z: np.abs(z) < 1e-9), "xyz"))
    return m, m.select("dam", lambda x, y, z: np.abs(x - batter * z) < 1e-9)


def fixed_loads(m: sc.Model, face, levels) -> list[np.ndarray]:
    """The nodal forces (n, 3) of a water load at each fixed level (one assembly)."""
    pats = [sc.LoadPattern(f"w{i}", [sc.WaterLoad(face, level=h)]) for i, h in enumerate(levels)]
    sysm = sc.assemble(m.add(*pats))
    return [sysm.loads[p.name].f.reshape(-1, 3) for p in pats]


@pytest.mark.parametrize("element", ELEMENTS)
def test_resultant_and_its_height_on_a_vertical_face(element):
    m, face = block(element)
    z = m.body("dam").points[:, 2]
    levels = (4.0, 6.3, 10.0, 12.0)
    for h, f in zip(levels, fixed_loads(m, face, levels), strict=True):
        d = min(h, H)
        force = GAMMA * W * (h * d - d * d / 2)  # ∫₀^d γ (h − z) W dz
        arm = (h * d * d / 2 - d ** 3 / 3) / (h * d - d * d / 2)  # ∫ z p dz / ∫ p dz
        assert f[:, 0].sum() == pytest.approx(force, rel=1e-12)  # pushes into the body: +x
        assert np.abs(f[:, 1:]).max() <= 1e-12 * force
        assert (f[:, 0] * z).sum() / force == pytest.approx(arm, rel=1e-12)


@pytest.mark.parametrize("element", ["hex8", "hex27", "tet10"])
def test_battered_face(element):
    """Face x = 0.3 z: |F| = γ W d² / (2 cos β) normal to the face, d = 7.4 m."""
    batter, h = 0.3, 7.4
    m, face = block(element, batter)
    f = fixed_loads(m, face, [h])[0].sum(axis=0)
    beta = np.arctan(batter)
    n = np.array([np.cos(beta), 0.0, -np.sin(beta)])  # into the body
    assert np.linalg.norm(f) == pytest.approx(GAMMA * W * h * h / (2 * np.cos(beta)), rel=1e-12)
    assert np.linalg.norm(np.cross(f, n)) <= 1e-12 * np.linalg.norm(f)
    assert f @ n > 0


@pytest.mark.parametrize("element", ELEMENTS)
def test_nodal_forces_equal_skfem_face_integration_when_all_wet(element):
    """Head above the top: p = γ (h − z) is smooth on every face, so the ordinary face
    integration of a pressure function (an independent code path) is exact."""
    m, face = block(element)
    h = 13.5
    f = fixed_loads(m, face, [h])[0]
    ref = sc.assemble(m.add(sc.LoadPattern("p", [sc.EdgeLoad(
        face, normal=lambda x, y, z: GAMMA * (h - z))]))).loads["p"].f.reshape(-1, 3)
    assert np.abs(f - ref).max() <= 1e-12 * np.abs(ref).max()


@pytest.mark.parametrize("element", ELEMENTS)
def test_level_pattern_equals_the_fixed_level_load(element):
    m, face = block(element, 0.2)
    levels = (-1.0, 0.0, 2.0, 5.5, 6.3, 9.75, 10.0, 12.5)
    fixed = [sc.LoadPattern(f"w{i}", [sc.WaterLoad(face, level=h)]) for i, h in enumerate(levels)]
    sysm = sc.assemble(m.add(sc.LoadPattern("res", [sc.WaterLoad(face, level=None)]), *fixed))
    basis = sysm.levels["res"]
    nodes = len(np.unique(face.index))
    assert len(basis.names) == nodes  # a flat face: one virtual pattern per wetted node
    for i, h in enumerate(levels):
        f_level = basis.vectors.T @ basis.factors(h)
        ref = sysm.loads[f"w{i}"].f
        assert np.abs(f_level - ref).max() <= 1e-12 * max(np.abs(ref).max(), 1.0), h


@pytest.mark.parametrize("element", ELEMENTS)
def test_taylor_coefficients_are_exact_within_a_piece(element):
    m, face = block(element, 0.2)
    basis = sc.assemble(m.add(sc.LoadPattern("r", [sc.WaterLoad(face, level=None)]))).levels["r"]
    h0, h1 = 0.3, 9.1
    stops = np.r_[h0, basis.breaks(h0, h1), h1]
    assert len(stops) == 6  # corner levels 2, 4, 6, 8 m and the two ends
    for a, b in zip(stops[:-1], stops[1:], strict=True):
        c = basis.taylor(a, b)
        assert len(c) == basis.degree + 1
        for s in (0.1, 0.5, 0.93):
            d = s * (b - a)
            g = basis.factors(a + d)
            assert np.abs(c.T @ d ** np.arange(len(c)) - g).max() <= 1e-12 * np.abs(g).max()


def test_static_run_with_the_level_as_parameter():
    """Level 0 → 14 m on the block fixed at its base: at every recorded level the base's
    reaction balances the water's resultant γ W (h d − d²/2) (1e-9), and the piece ends
    (corner levels 2, 4, 6, 8, 10 m) are recorded states."""
    m, face = block("hex8")
    m = m.add(sc.LoadPattern("res", [sc.WaterLoad(face, level=None)]))
    res = sc.solve_static(m.replace(program=(sc.Segment("res", 14.0),)))
    assert res.status.value == "completed", res.message
    h = res.factors[:, res.pattern_names.index("res")]
    d = np.clip(h, 0.0, H)
    force = GAMMA * W * (h * d - d * d / 2)
    rx = res.reaction("base", "x")
    assert np.abs(rx + force).max() <= 1e-9 * force.max()
    assert h[-1] == pytest.approx(14.0, rel=1e-12)
    assert np.abs(res.residual).max() <= 1e-9


def test_a_warped_wetted_face_is_refused_by_name():
    b = box("dam", (0, 0, 0), (4.0, W, H), (2, 2, 5), CONCRETE)
    p = b.mesh.p.copy()
    p[0] += 0.05 * p[1] * p[2] * (p[0] == 0)  # the face x = 0 becomes warped
    b = sc.Body.from_mesh("dam", MeshHex(p, b.mesh.t), "hex8", CONCRETE)
    m = sc.Model(bodies=[b])
    m = m.add(sc.Support("base", m.select("dam", lambda x, y, z: np.abs(z) < 1e-9)))
    face = m.select("dam", lambda x, y, z: x - 0.05 * y * z < 1e-9)
    with pytest.raises(ModelError, match=r"load 0 facet \d+.*not a flat"):
        sc.assemble(m.add(sc.LoadPattern("w", [sc.WaterLoad(face, level=5.0)])))


# --------------------------------------------------------------------------------------------
# uplift in a 3D joint (through the CFEs)
# --------------------------------------------------------------------------------------------
def uplift_block(k: int = 8, push: float = 0.0) -> tuple[sc.Model, float, float]:
    """A 2 × 1 × 1 m block (hex8, 4 × 2 × 1 cells) on a rough rigid plane z = 0 (f = 0.6):
    its weight, then a uniform uplift of 1 m head per unit λ through the CFEs (and a push
    ``push`` · W along x with it).  Returns (model, W, uplift force per unit λ)."""
    rho, g, f = 2400.0, 9.81, 0.6
    blk = box("block", (0, 0, 0), (2.0, 1.0, 1.0), (4, 2, 1), sc.Material(25e9, 0.2, rho))
    m = sc.Model(bodies=[blk])
    W = rho * g * 2.0
    m = m.add(
        sc.Interface("joint", m.select("block", boundary="bottom"), sc.RigidPlane("ground"),
                     friction=f, facets=k),
        sc.LoadPattern("weight", [sc.BodyForce(g=(0, 0, -g))]),
        sc.LoadPattern("uplift", [sc.Uplift("joint", head=1.0, through="cfes")]
                       + ([sc.EdgeForce(m.select("block", boundary="top"), fx=push * W)]
                          if push else [])),
        sc.Segment("weight", 1.0), sc.Segment("uplift", 10.0))
    return m, W, GAMMA * 2.0


def test_uniform_uplift_lifts_the_block_off_at_its_weight():
    """Every CFE's normal force drops by A_k γ_w λ (the effective stress), and the block lifts
    off at λ = W / (γ_w A) — an event located exactly (1e-9)."""
    m, W, U = uplift_block()
    res = sc.solve_static(m)
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert res.lam[-1] == pytest.approx(W / U, rel=1e-9)
    N = np.asarray(res.N)
    fac = np.asarray(res.factors)
    lam_w, lam = (fac[:, res.pattern_names.index(p)] for p in ("weight", "uplift"))
    assert np.abs(N.sum(axis=1) - (-W * lam_w + U * lam)).max() <= 1e-9 * W


def test_uplift_reduces_the_sliding_resistance():
    """Pushed along x by 0.2 W per unit λ with the uplift: slides when 0.2 W λ = s (W − γ_w A
    λ), s the inscribed 8-gon's limit per unit normal force along x
    (faceted_reference.slip_limit), to 1e-9."""
    m, W, U = uplift_block(8, 0.2)
    res = sc.solve_static(m)
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    # slip when 0.2 W λ = s (W − U λ), s = slip_limit(f, 8, 0) per unit normal force
    s = fr.slip_limit(0.6, 8, 0.0)
    assert res.lam[-1] == pytest.approx(s * W / (0.2 * W + s * U), rel=1e-9)


def test_uplift_on_the_faces_of_a_3d_joint_is_refused():
    m, _, _ = uplift_block()
    with pytest.raises(ModelError, match=r"load 0\.through.*through='cfes'"):
        m.add(sc.LoadPattern("u2", [sc.Uplift("joint", head=1.0)]))
