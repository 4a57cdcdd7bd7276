"""The water level as the load parameter (``WaterLoad(nodes, level=None)``).

References:
* the load at every level equals the fixed-level water load (``WaterLoad(level=h)``, exact
  integration split at the level, an independent code path) to 1e-12, for linear and quadratic
  elements, vertical and battered faces, levels at nodes and inside edges;
* a dam block on rock slides at the level where the water thrust equals f·W, by hand statics:
  γ h²/2 = f W below the crest, γ H_d (h − H_d/2) = f W above it (1e-9);
* the first event on the rising level is exact: before it every CFE sticks, the response is
  linear in the load, so the same water load at that fixed level applied proportionally must
  reach its first event exactly at λ = 1 (1e-9), at the same CFE;
* equilibrium and the contact conditions hold at every state (1e-9);
* drawdown (a falling level) retraces the elastic part; clean errors for misuse.
"""

from __future__ import annotations

import numpy as np
import pytest
from skfem import MeshQuad, MeshTri

import stepcontact as sc
from stepcontact.fem.level import is_virtual

GAMMA = 9810.0
CONCRETE = sc.Material(E=25e9, nu=0.2, density=2400)
ROCK = sc.Material(E=20e9, nu=0.25, density=2600)


def block(element: str, shear: float) -> sc.Model:
    """A 4 m × 10 m block, upstream face x = shear · y, fixed at its base (1 m cells)."""
    grid = (MeshTri if element.startswith("tri") else MeshQuad).init_tensor(
        np.linspace(0.0, 4.0, 3), np.linspace(0.0, 10.0, 11))
    p = grid.p.copy()
    p[0] += shear * p[1] * (1.0 - p[0] / 4.0)
    b = sc.Body.from_mesh("block", type(grid)(p, grid.t), element, CONCRETE)
    m = sc.Model(bodies=[b])
    return m.add(sc.Support("base", m.select("block", y=0.0)))


@pytest.mark.parametrize("element", ["tri3", "quad4", "tri6", "quad8"])
@pytest.mark.parametrize("shear", [0.0, 0.3])
def test_level_basis_equals_the_fixed_level_load(element, shear):
    m = block(element, shear)
    face = m.select("block", lambda x, y: np.abs(x - shear * y) < 1e-9)
    sysm = sc.assemble(m.add(sc.LoadPattern("res", [sc.WaterLoad(face, level=None)])))
    basis = sysm.levels["res"]
    assert all(is_virtual(n) for n in basis.names) and not np.any(sysm.loads["res"].f)
    for h in (-1.0, 0.0, 2.0, 6.3, 9.75, 10.0, 12.5):
        f_level = basis.vectors.T @ basis.factors(h)
        ref = sc.assemble(m.add(sc.LoadPattern("w", [sc.WaterLoad(face, level=h)]))).loads["w"].f
        assert np.abs(f_level - ref).max() <= 1e-12 * max(np.abs(ref).max(), 1.0), h


@pytest.mark.parametrize("h0, h1", [(0.0, 7.0), (2.5, 9.3)])
def test_taylor_coefficients_are_exact_within_a_piece(h0, h1):
    """Between node levels the factors are polynomials of degree ≤ 4 in the level: the Taylor
    coefficients reproduce them at any level of the piece (1e-12)."""
    m = block("quad8", 0.3)
    face = m.select("block", lambda x, y: np.abs(x - 0.3 * y) < 1e-9)
    basis = sc.assemble(m.add(sc.LoadPattern("r", [sc.WaterLoad(face, level=None)]))).levels["r"]
    stops = np.r_[h0, basis.breaks(h0, h1), h1]
    for a, b in zip(stops[:-1], stops[1:], strict=True):
        c = basis.taylor(a, b)
        for z in (0.1, 0.5, 0.93):
            d = z * (b - a)
            g = basis.factors(a + d)
            assert np.abs(c.T @ d ** np.arange(len(c)) - g).max() <= 1e-12 * np.abs(g).max()


def dam(f: float, height: float = 10.0, top: float = 30.0) -> sc.Model:
    """Dam block 8 m × ``height`` on rock (non-matching meshes), f; self-weight, then the
    reservoir level rising on the upstream face x = 0 from 0 to ``top`` (m)."""
    body = sc.rectangle("dam", (0, 0), (8.0, height), 8, int(height), CONCRETE)
    rock = sc.rectangle("rock", (-6, -6), (14, 0), 14, 6, ROCK)
    m = sc.Model(bodies=[rock, body], name="dam")
    return m.add(
        sc.Support("deep", m.select("rock", y=-6), "xy"),
        sc.Interface("base", m.select("dam", y=0), m.select("rock", y=0), friction=f),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("dam",))]),
        sc.LoadPattern("reservoir", [sc.WaterLoad(m.select("dam", x=0), level=None)]),
        sc.Segment("weight", 1.0),
        sc.Segment("reservoir", top),
    )


@pytest.mark.parametrize("f, height", [(0.7, 10.0), (0.3, 20.0)])
def test_dam_slides_at_the_hand_level(f, height):
    """Sliding where the thrust equals f W: above the crest (f = 0.7, 10 m) and below it
    (f = 0.3, 20 m, the level inside the face) — 1e-9; every state in equilibrium."""
    res = sc.solve_static(dam(f, height))
    W = CONCRETE.density * 9.81 * 8.0 * height
    h_star = np.sqrt(2 * f * W / GAMMA)
    if h_star > height:
        h_star = f * W / (GAMMA * height) + height / 2
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert "sliding" in res.message
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(h_star, rel=1e-9)
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-9
    # the pattern's factor is the level, the virtual patterns are its exact loads
    names = list(res.pattern_names)
    seg = res.segment == 1
    assert np.allclose(res.factors[seg, names.index("reservoir")], res.lam[seg], rtol=1e-14)


def test_first_event_on_the_rising_level_is_exact():
    """The first event of the level path after its start, at h_e: the fixed-level load at h_e,
    applied proportionally after the weight, has its first event after its start at λ = 1
    (1e-9), at the same CFE.  (Both start from the weight's state, whose corners slip, and
    stick again at the start of the water; from there both paths keep one scheme, on which
    the response is linear in the load, up to the event.)"""
    res = sc.solve_static(dam(0.3, 20.0))
    first = next(e for e in res.events if e.segment == 1 and e.lam > 0)
    h_e = first.lam
    m = dam(0.3, 20.0)
    m = m.replace(patterns=(m.patterns[0], sc.LoadPattern(
        "fixed", [sc.WaterLoad(m.select("dam", x=0), level=h_e)])),
        program=(sc.Segment("weight", 1.0), sc.Segment("fixed", 2.0)))
    ref = sc.solve_static(m)
    start = [(e.cfe, e.transition) for e in ref.events if e.segment == 1 and e.lam == 0]
    assert start == [(e.cfe, e.transition) for e in res.events if e.segment == 1 and e.lam == 0]
    ev = next(e for e in ref.events if e.segment == 1 and e.lam > 0)
    assert ev.lam == pytest.approx(1.0, rel=1e-9)
    assert (ev.cfe, ev.transition) == (first.cfe, first.transition)


def test_drawdown_retraces_the_elastic_path():
    """Level up to 6 m (no event for f = 0.7: all stuck) and back down to 0: the contact forces
    return to those of the weight alone (1e-9), the level path being elastic."""
    m = dam(0.7)
    m = m.replace(program=(sc.Segment("weight", 1.0), sc.Segment("reservoir", 6.0),
                           sc.Segment("reservoir", 0.0)))
    res = sc.solve_static(m)
    assert res.status == sc.Status.COMPLETED, res.message
    after_weight = int(np.flatnonzero(res.segment == 0)[-1])
    scale = np.abs(res.N).max()
    assert np.abs(res.N[-1] - res.N[after_weight]).max() <= 1e-9 * scale
    assert np.abs(res.Q[-1] - res.Q[after_weight]).max() <= 1e-9 * scale
    assert not res.events


def test_level_pattern_errors():
    """Rates on a level pattern, a start above the wetted faces' bottom, the article's slip
    treatment: clean ModelErrors naming the segment."""
    m = dam(0.7)
    with pytest.raises(sc.ModelError, match=r"segment 1 \('reservoir'\).*slip='exact'"):
        sc.solve_static(m, slip="article")
    rated = m.replace(program=(sc.Segment("weight", 1.0),
                               sc.Segment("both", 5.0, rates={"reservoir": 1.0, "weight": 0.0})))
    with pytest.raises(sc.ModelError, match=r"segment 1 \('both'\).*water level"):
        sc.solve_static(rated)
    late = m.replace(program=(sc.Segment("weight", 1.0), sc.Segment("reservoir", 8.0, start=3.0)))
    with pytest.raises(sc.ModelError, match="does not chain|already loads"):
        sc.solve_static(late)


def test_model_file_water_without_level_is_a_level_pattern():
    """`type = "water"` without `level` in a model file: the same level pattern as the API
    (the docs' dam, docs/model-file.md), sliding where γ_w·10·(h − 5) = f·(W − γ_w·h·B/2)."""
    import re
    import tomllib
    from pathlib import Path

    from stepcontact.io.modelfile import model_from_dict

    text = (Path(__file__).parents[1] / "docs" / "model-file.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```toml\n(.*?)```", text, flags=re.S)
    full = tomllib.loads(next(b for b in blocks if 'name = "gravity dam"' in b))
    level = tomllib.loads(next(b for b in blocks if "[patterns.reservoir]" in b))
    full["patterns"] = {"weight": full["patterns"]["weight"], **level["patterns"]}
    full["program"] = level["program"]
    res = sc.solve_static(model_from_dict(full))
    W, f, B = 2400 * 9.81 * 8.0 * 10.0, 0.7, 8.0
    h = (f * W + GAMMA * 10 * 5) / (GAMMA * 10 + f * GAMMA * B / 2)
    assert h == pytest.approx(14.40625, rel=1e-12)
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(h, rel=1e-9)


def test_interpolation_in_a_level_segment_is_refused():
    """States of a level segment are not linear in the level between events: interpolating
    one is a clear error that says to end a segment there."""
    res = sc.solve_static(dam(0.7))
    with pytest.raises(ValueError, match="end a segment at"):
        res.interpolate(5.0, segment=1)
    res.interpolate(0.5, segment=0)  # the weight segment is proportional: fine


def test_a_level_segment_of_zero_length_is_a_no_op():
    """A segment to the level already reached (here 0 m after the weight, and 5 m twice) does
    nothing, as a proportional segment of zero length: the same events at the same levels as
    the program without it, the same sliding level (1e-12 relative), and its start and end
    states equal the state before it (1e-12 of the largest force)."""
    ref = sc.solve_static(dam(0.3, 20.0).replace(program=(
        sc.Segment("weight", 1.0), sc.Segment("reservoir", 5.0), sc.Segment("reservoir", 30.0))))
    res = sc.solve_static(dam(0.3, 20.0).replace(program=(
        sc.Segment("weight", 1.0), sc.Segment("reservoir", 0.0), sc.Segment("reservoir", 5.0),
        sc.Segment("reservoir", 5.0), sc.Segment("reservoir", 30.0))))
    assert res.status == ref.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(
        ref.multipliers[-1].equilibrium_lost, rel=1e-12)
    moved = {0: 0, 2: 1, 4: 2}  # segments of res that are segments of ref
    assert [(e.cfe, e.transition) for e in res.events if e.segment in (1, 3)] == []
    assert [(moved[e.segment], e.cfe, e.transition) for e in res.events] == [
        (e.segment, e.cfe, e.transition) for e in ref.events]
    assert np.allclose([e.lam for e in res.events], [e.lam for e in ref.events],
                       rtol=1e-12, atol=0)
    scale = np.abs(res.N).max()
    for seg in (1, 3):
        idx = np.flatnonzero(res.segment == seg)
        before = idx[0] - 1
        for i in idx:
            assert np.abs(res.N[i] - res.N[before]).max() <= 1e-12 * scale
            assert np.abs(res.Q[i] - res.Q[before]).max() <= 1e-12 * scale
