"""Load programs: segments that move several patterns at once (non-proportional loading)."""

from __future__ import annotations

import numpy as np
import pytest

import stepcontact as sc
import verification_models as vm
from stepcontact.io.modelfile import model_from_dict


def push_and_lift(rates: dict[str, float]) -> sc.Model:
    """Block (2 m × 0.5 m, density 2000) on a base, f = 0.5: its weight, then a horizontal push
    (1 N per unit factor on its left face) and an uplift (its weight reversed per unit factor)
    together, at the given rates."""
    m = vm.block_on_base(friction=0.5, nx=4, ny=1)
    left = m.select("block", x=0.0)
    return m.add(
        sc.LoadPattern("w", [sc.BodyForce(bodies=("block",))]),
        sc.LoadPattern("push", [sc.NodalLoad(left, fx=1.0 / len(left))]),
        sc.LoadPattern("lift", [sc.BodyForce(bodies=("block",), g=(0.0, vm.G))]),
        sc.Segment("w", 1.0),
        sc.Segment("both", 1.0, rates=rates),
    )


@pytest.mark.parametrize("rate_push, rate_lift", [(2e4, 0.5), (1e4, 0.0), (3e4, 0.8)])
def test_two_patterns_at_once_slide_at_the_closed_form(rate_push, rate_lift):
    """Push and uplift grow together: the block slides when the push equals f × (weight −
    uplift), i.e. at t* = f W / (r_push + f r_lift W) of the segment's parameter (1e-9)."""
    W = vm.SOFT.density * vm.G * 1.0
    res = sc.solve_static(push_and_lift({"push": rate_push, "lift": rate_lift}))
    t_star = 0.5 * W / (rate_push + 0.5 * rate_lift * W)
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    assert res.multipliers[-1].pattern == "both"
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(t_star, rel=1e-9)
    # the factors of both patterns follow their rates along the segment
    i = res.n_states - 1
    names = list(res.pattern_names)
    assert res.factors[i, names.index("push")] == pytest.approx(rate_push * t_star, rel=1e-9)
    assert res.factors[i, names.index("lift")] == pytest.approx(rate_lift * t_star, rel=1e-9,
                                                                 abs=1e-12)
    assert res.residual[:-1].max() < 1e-9 and res.violation.max() < 1e-9


def test_rates_equal_two_single_pattern_runs_when_one_rate_is_zero():
    """A combined segment with one rate 0 is the single-pattern segment (same events)."""
    a = sc.solve_static(push_and_lift({"push": 1e4, "lift": 0.0}))
    m = push_and_lift({"push": 1.0})
    m = m.replace(program=(sc.Segment("w", 1.0), sc.Segment("push", 1e4)))
    b = sc.solve_static(m)
    assert [(e.cfe, e.transition) for e in a.events] == [(e.cfe, e.transition) for e in b.events]
    assert np.allclose([e.lam * 1e4 for e in a.events], [e.lam for e in b.events], rtol=1e-9)


def test_single_pattern_segment_chains_after_a_segment_with_rates():
    """A segment with rates moves its patterns; a single-pattern segment after it starts where
    the pattern stands (it used to start from 0 and, ending at 0, silently did nothing): push
    to 0.9 f W with a rates segment, then back to 0 and on to 2 f W alone: the block slides at
    f W on the last segment (1e-9) and the program's starts chain."""
    W = vm.SOFT.density * vm.G * 1.0
    m = push_and_lift({"push": 0.9 * 0.5 * W})
    m = m.add(sc.Segment("push", 0.0), sc.Segment("push", W))
    segs = m.segments_resolved()
    assert segs[2] == ("push", pytest.approx(0.45 * W, rel=1e-12), 0.0)
    with pytest.raises(sc.ModelError, match="does not chain"):
        m.add(sc.Segment("push", 1.0, start=0.0)).segments_resolved()
    res = sc.solve_static(m)
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    assert res.multipliers[-1].segment == 3
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(0.5 * W, rel=1e-9)


def test_bad_rates_name_the_item():
    with pytest.raises(sc.ModelError, match=r"rates.*nope|nope"):
        sc.solve_static(push_and_lift({"nope": 1.0}))
    with pytest.raises(sc.ModelError, match="label that is not a load pattern"):
        m = push_and_lift({"push": 1.0})
        sc.solve_static(m.replace(program=(sc.Segment("push", 1.0, rates={"lift": 1.0}),)))


def block_file(push: dict, *program: dict) -> dict:
    """A block on a base in the model-file form: patterns 'w' (its weight) and 'push' (the load
    ``push`` on the block's left face), the weight applied first, then ``program``."""
    return {
        "materials": {"soft": {"E": 1e9, "nu": 0.25, "density": 2000.0}},
        "bodies": [
            {"name": "base", "kind": "rectangle", "corner0": [-0.5, -0.5],
             "corner1": [2.5, 0.0], "nx": 6, "ny": 1, "material": "soft"},
            {"name": "block", "kind": "rectangle", "corner0": [0.0, 0.0], "corner1": [2.0, 0.5],
             "nx": 4, "ny": 1, "material": "soft"},
        ],
        "node_sets": {
            "bed": {"body": "base", "y": -0.5}, "top": {"body": "base", "y": 0.0},
            "bottom": {"body": "block", "y": 0.0}, "left": {"body": "block", "x": 0.0},
        },
        "supports": [{"name": "bed", "nodes": "bed", "dofs": "xy"}],
        "interfaces": [{"name": "joint", "plus": "bottom", "minus": "top", "friction": 0.5}],
        "patterns": {
            "w": {"loads": [{"type": "gravity", "g": [0.0, -9.81], "bodies": ["block"]}]},
            "push": {"loads": [{"nodes": "left", **push}]},
        },
        "program": [{"pattern": "w", "end": 1.0}, *program],
    }


def test_rates_in_the_model_file():
    """``[[program]]`` with ``rates`` in a model file: unknown patterns are named."""
    text = block_file({"type": "pressure", "normal": 1.0},
                      {"pattern": "both", "end": 1.0, "rates": {"push": 1e5, "w": 0.0}})
    model = model_from_dict(text)
    assert model.program[1].rates == (("push", 1e5), ("w", 0.0))
    res = sc.solve_static(model)
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    bad = dict(text, program=[{"pattern": "both", "end": 1.0, "rates": {"pull": 1.0}}])
    with pytest.raises(sc.ModelError, match=r"program\[0\]\.rates\.pull"):
        model_from_dict(bad)
