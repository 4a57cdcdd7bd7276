"""A block on an inclined base, held up the slope by a rope (an inclined spring) to a winch.

The model is built horizontally with ``rectangle`` and turned by the slope angle α with
``rotate``: node sets chosen before the rotation stay valid, the spring directions and the
geometry turn, gravity stays vertical.  The rope is a spring along the slope between the block
and a small sled; the sled is guided by two springs normal to the slope (an inclined roller)
and pulled up the slope by the winch force T (pattern ``winch``, 1 N per unit λ).

Program: the self-weight W and the winch force T = W sin α are applied together (segment
``hold``; the block is held without friction), then the winch is slackened by s newtons
(segment ``slacken``: T = W sin α − s).  The rope force is the winch force (the sled is in
equilibrium along the slope and its guides act normal to it), so by hand statics of the block —
rope force + friction = W sin α, friction at most f W cos α — the block starts to slide down
the slope at the slack s = f W cos α, when

    T = W (sin α − f cos α).

Run:  python examples/inclined_block_springs.py
"""

import numpy as np

import stepcontact as sc

ALPHA = np.radians(30.0)  # slope angle
FRICTION = 0.3  # block on base (< tan α: without the rope the block slides)
CONCRETE = sc.Material(E=30e9, nu=0.2, density=2400)  # Pa, -, kg/m³
STEEL = sc.Material(E=210e9, nu=0.3)  # the sled (weightless)


def block_weight() -> float:
    """Weight of the 2 m × 1 m block, N per metre run."""
    return 2.0 * 1.0 * CONCRETE.density * 9.81


def hand_slide_force(alpha: float = ALPHA, friction: float = FRICTION) -> float:
    """Winch (= rope) force at which the block starts to slide down, N: W (sin α − f cos α)."""
    W = block_weight()
    return W * (np.sin(alpha) - friction * np.cos(alpha))


def inclined_model(alpha: float = ALPHA, friction: float = FRICTION,
                   k_rope: float = 5e8, k_guide: float = 1e9) -> sc.Model:
    """The block on the slope α (radians), rope stiffness ``k_rope`` and guide stiffness
    ``k_guide`` in N/m (neither changes the load at which the block slides)."""
    base = sc.rectangle("base", (0, 0), (6, 1), 24, 4, CONCRETE)  # m
    block = sc.rectangle("block", (1, 1), (3, 2), 8, 4, CONCRETE)
    sled = sc.rectangle("sled", (3.5, 1.25), (4.0, 1.75), 1, 2, STEEL)
    flat = sc.Model(bodies=[base, block, sled], name="inclined block")
    # node sets picked on the horizontal layout: local node indices, valid after the rotation
    rope_block = flat.select("block", x=3, y=1.5, name="rope_block")
    rope_sled = flat.select("sled", x=3.5, y=1.5, name="rope_sled")
    guided = flat.select("sled", y=1.5, boundary=False, name="guided")
    flat = flat.add(
        sc.Support("bed", flat.select("base", y=0), "xy"),
        sc.Interface("joint", plus=flat.select("block", y=1), minus=flat.select("base", y=1),
                     friction=friction),
        # the rope along the slope and the guides normal to it (directions turn with the model)
        sc.Spring("rope", rope_block, rope_sled, k=k_rope, direction=(1.0, 0.0)),
        sc.Spring("guide", guided, None, k=k_guide, direction=(0.0, 1.0)),
    )
    m = sc.rotate(flat, alpha, about=(0.0, 0.0))
    W = block_weight()
    up_slope = (np.cos(alpha), np.sin(alpha))
    pull = flat.select("sled", x=4.0, y=1.5, name="winch")
    return m.add(
        sc.LoadPattern("weight", [sc.BodyForce(g=(0.0, -9.81), bodies=("block",))]),
        sc.LoadPattern("winch", [sc.NodalLoad(pull, fx=up_slope[0], fy=up_slope[1])]),
        # weight and winch force W sin α together, then the winch is slackened by s (N)
        sc.Segment("hold", 1.0, rates={"weight": 1.0, "winch": W * np.sin(alpha)}),
        sc.Segment("slacken", W * np.sin(alpha), rates={"winch": -1.0}),
    )


def slide_force(res: sc.StaticResult) -> float:
    """The winch force (load factor of pattern ``winch``) when equilibrium is lost, N."""
    return float(res.factors[-1, list(res.pattern_names).index("winch")])


if __name__ == "__main__":
    m = inclined_model()
    res = sc.solve_static(m)
    print(res.summary())
    T = slide_force(res)
    slack = res.multipliers[-1].equilibrium_lost
    hand = hand_slide_force()
    W = block_weight()
    rel = T / hand - 1
    print(f"slope {np.degrees(ALPHA):g}°, f = {FRICTION}, W = {W:.3f} N/m")
    print(f"block starts to slide at winch (rope) force T = {T:.6f} N, slack {slack:.6f} N")
    print(f"hand statics W (sin α − f cos α) = {hand:.6f} N: rope {hand:.3f} N + friction "
          f"{FRICTION * W * np.cos(ALPHA):.3f} N = W sin α {W * np.sin(ALPHA):.3f} N")
    print(f"relative difference {rel:.1e}")
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    assert abs(rel) < 1e-8
    assert abs(slack / (FRICTION * W * np.cos(ALPHA)) - 1) < 1e-8
