"""Small models for the verification tests (helpers, no tests).

Every builder returns a complete :class:`stepcontact.Model` (bodies, supports, interfaces,
patterns, program).  Units SI.  The bodies held only by contact are restrained as each test
needs: frictionless models get an x-support (frictionless contact cannot hold a body
tangentially); frictional ones are held by friction alone unless stated.
"""

from __future__ import annotations

import numpy as np
from skfem import MeshQuad

from stepcontact import (
    Body,
    BodyForce,
    EdgeLoad,
    Frame,
    Interface,
    LoadPattern,
    Material,
    Model,
    NodalLoad,
    NodeSet,
    Segment,
    Spring,
    Support,
    rectangle,
)
from stepcontact.contact.laws import OPEN, SLIP_NEG, SLIP_POS, STICK

G = 9.81
CONCRETE = Material(30e9, 0.2, 2400.0)
SOFT = Material(1e9, 0.25, 2000.0)


def _node(model: Model, body: str, x: float, y: float) -> NodeSet:
    """The single node of ``body`` at (x, y)."""
    ns = model.select(body, x=x, y=y, boundary=False)
    assert len(ns) == 1, f"expected one node of {body} at ({x}, {y}), got {len(ns)}"
    return ns


def block_on_base(
    *,
    friction: float,
    w: float = 2.0,
    h: float = 0.5,
    nx: int = 4,
    ny: int = 1,
    base_nx: int | None = None,
    material: Material = SOFT,
    gap=None,
    x_support: bool = False,
    cfe: str = "auto",
) -> Model:
    """A block [0, w] × [0, h] on a base [-w/4, 5w/4] × [-h, 0] fixed at its bottom.

    Interface 'contact': S+ = block bottom, S− = base top (normal +y), CFEs of kind ``cfe``
    (mortar by default: the meshes do not match unless ``base_nx`` = 1.5 nx).  With
    ``x_support`` the top-centre node of the block is fixed in x (needs ``nx`` even).  No
    loads, no program.
    """
    base_nx = 2 * nx if base_nx is None else base_nx
    base = rectangle("base", (-w / 4, -h), (1.25 * w, 0.0), base_nx, max(ny, 1), material)
    block = rectangle("block", (0.0, 0.0), (w, h), nx, ny, material)
    m = Model().add(base, block)
    m = m.add(
        Support("base_bottom", m.select("base", y=-h)),
        Interface("contact", m.select("block", y=0.0), m.select("base", y=0.0),
                  friction=friction, gap=gap, cfe=cfe),
    )
    if x_support:
        m = m.add(Support("block_x", _node(m, "block", w / 2, h), "x"))
    return m


# --------------------------------------------------------------------------------------------
# frictionless models (path independent: final state = QP minimiser)
# --------------------------------------------------------------------------------------------
def frictionless_block(seed: int) -> Model:
    """Block on base, frictionless, random loads in four segments (incl. unloading).

    The gap is zero in a central band (so the block is never a mechanism) and grows
    quadratically outside it, so CFEs close and open along the path.  All vertical loads are
    downward except a corner lift of 0.3 W, which opens part of the contact but keeps the
    resultant inside the central band.
    """
    rng = np.random.default_rng(seed)
    w, h, nx = 2.0, 0.5, 6
    gap_scale = 1e-5 * (1 + rng.random())

    def gap(x, y):
        return gap_scale * np.maximum(np.abs(x - w / 2) - w / 4, 0.0) ** 2 / (w / 4) ** 2

    m = block_on_base(friction=0.0, w=w, h=h, nx=nx, ny=2, gap=gap, x_support=True)
    W = SOFT.density * G * w * h
    xs_top = np.linspace(0.0, w, nx + 1)
    loads1 = [
        NodalLoad(_node(m, "block", x, h), fx=rng.uniform(-0.3, 0.3) * W / nx,
                  fy=-rng.uniform(0.0, 1.0) * W / nx)
        for x in xs_top
    ]
    corner = 0.0 if rng.random() < 0.5 else w
    loads2 = [NodalLoad(_node(m, "block", corner, h), fy=0.3 * W)]
    loads2 += [
        NodalLoad(_node(m, "block", x, h), fy=-rng.uniform(0.0, 0.5) * W / nx)
        for x in xs_top[rng.permutation(nx + 1)[:2]]
    ]
    return m.add(
        LoadPattern("weight", [BodyForce(bodies=("block",))]),
        LoadPattern("random", loads1),
        LoadPattern("lift", loads2),
        Segment("weight", 1.0),
        Segment("random", 1.0),
        Segment("lift", 1.0),
        Segment("random", 0.2),
    )


def frictionless_two_blocks() -> Model:
    """Base, block A on the base, block B on A with non-matching meshes (node-to-segment CFEs,
    given explicitly: the article's CFE; B's end nodes overhang the part of A given as S−).

    Both interfaces frictionless; A and B are each fixed in x at one node.  B is loaded
    eccentrically so part of the B/A interface opens; then A gets a side push.
    """
    mat = SOFT
    base = rectangle("base", (-0.5, -0.5), (2.5, 0.0), 6, 1, mat)
    a = rectangle("A", (0.0, 0.0), (2.0, 0.5), 4, 2, mat)
    b = rectangle("B", (0.25, 0.5), (1.75, 1.0), 6, 2, mat)
    m = Model().add(base, a, b)
    m = m.add(
        Support("base_bottom", m.select("base", y=-0.5)),
        Support("A_x", _node(m, "A", 0.0, 0.25), "x"),
        Support("B_x", _node(m, "B", 1.0, 1.0), "x"),
        Interface("A_on_base", m.select("A", y=0.0), m.select("base", y=0.0)),
        Interface("B_on_A", m.select("B", y=0.5),
                  m.select("A", y=0.5, where=lambda x, y: (x > 0.2) & (x < 1.8)),
                  cfe="node-to-segment"),
    )
    W = mat.density * G * 0.75
    return m.add(
        LoadPattern("weight", [BodyForce(bodies=("A", "B"))]),
        LoadPattern("eccentric", [NodalLoad(_node(m, "B", 1.75, 1.0), fy=-0.8 * W),
                                  NodalLoad(_node(m, "B", 0.25, 1.0), fy=0.2 * W)]),
        LoadPattern("push", [NodalLoad(m.select("A", x=2.0), fx=-0.1 * W)]),
        Segment("weight", 1.0),
        Segment("eccentric", 1.0),
        Segment("push", 1.0),
        Segment("eccentric", 0.5),
    )


def frictionless_frame() -> Model:
    """A continuous beam (frame) on four unilateral supports against a rigid (fully fixed)
    base body.  The support at x = 4 has an initial gap; an end lift opens the support at
    x = 6 and the weight closes the gap at x = 4."""
    beam = Frame.line("beam", (0.0, 0.0), (6.0, 0.0), 12, E=30e9, A=0.15, I=3.1e-3,
                      density=2500.0)
    base = rectangle("base", (-0.5, -0.5), (6.5, 0.0), 7, 1, CONCRETE)
    m = Model().add(beam, base)
    supports = m.select("beam", where=lambda x, y: np.isin(np.round(x, 9), [0.0, 2.0, 4.0, 6.0]))

    def gap(x, y):
        return np.where(np.abs(x - 4.0) < 1e-9, 2e-6, 0.0)

    m = m.add(
        Support("rigid_base", m.select("base", boundary=False)),
        Support("beam_x", _node(m, "beam", 0.0, 0.0), "x"),
        Interface("bearings", supports, m.select("base", y=0.0), gap=gap),
    )
    W = 2500.0 * 0.15 * 6.0 * G
    return m.add(
        LoadPattern("weight", [BodyForce(bodies=("beam",))]),
        LoadPattern("loads", [NodalLoad(_node(m, "beam", 1.0, 0.0), fy=-0.5 * W),
                              NodalLoad(_node(m, "beam", 3.5, 0.0), fy=-0.8 * W)]),
        LoadPattern("lift", [NodalLoad(_node(m, "beam", 6.0, 0.0), fy=0.35 * W)]),
        Segment("weight", 1.0),
        Segment("lift", 1.0),
        Segment("loads", 1.0),
        Segment("lift", 0.4),
    )


# --------------------------------------------------------------------------------------------
# closed-form limits
# --------------------------------------------------------------------------------------------
def sliding_block(friction: float, h_max: float) -> Model:
    """Block on base held only by contact (friction f); weight W, then a horizontal
    acceleration pattern 'H' (BodyForce g = (1, 0) m/s² on the block: H = W λ / 9.81) from 0
    to ``h_max``.  Sliding starts at λ = 9.81 f (H = f W)."""
    m = block_on_base(friction=friction, w=2.0, h=0.4, nx=6, ny=1)
    return m.add(
        LoadPattern("weight", [BodyForce((0.0, -G), bodies=("block",))]),
        LoadPattern("H", [BodyForce((1.0, 0.0), bodies=("block",))]),
        Segment("weight", 1.0),
        Segment("H", h_max),
    )


def pushed_block(E: float = 30e9, base_cells: tuple[int, int] = (16, 4),
                 block_cells: tuple[int, int] = (10, 5), element: str = "quad4",
                 name: str = "block-on-base") -> Model:
    """examples/block_on_base.py: a 2 m × 1 m block (f = 0.5) on a 4 m × 1 m base fixed at
    its bottom; self-weight, then a push of 1 N per unit λ on the block's left side until it
    slides at λ = f·W."""
    concrete = Material(E=E, nu=0.2, density=2400)
    base = rectangle("base", (0, 0), (4, 1), *base_cells, concrete, element=element)
    block = rectangle("block", (1, 1), (3, 2), *block_cells, concrete, element=element)
    m = Model(bodies=[base, block], plane="strain", thickness=1.0, name=name)
    left = m.select("block", x=1)
    return m.add(
        Support("bed", m.select("base", y=0), "xy"),
        Interface("joint", plus=m.select("block", y=1), minus=m.select("base", y=1),
                  friction=0.5),
        LoadPattern("weight", [BodyForce(bodies=("block",))]),
        LoadPattern("push", [NodalLoad(left, fx=1.0 / len(left))]),
        Segment("weight", 1.0),
        Segment("push", 1e6),
    )


def uplift_slab(weight: str, lam_max: float) -> Model:
    """A slab [0, 4] × [0, 0.5] on a rigid (fully fixed) base, frictionless, fixed in x at its
    top centre.  Weight ``"body_force"`` (self-weight) or ``"top_pressure"`` (the same weight
    as a uniform pressure on the top); then a uniform uplift pressure of 1 kPa per unit λ on
    its bottom, up to ``lam_max``."""
    w, h = 4.0, 0.5
    base = rectangle("base", (-1.0, -1.0), (w + 1.0, 0.0), 6, 1, CONCRETE)
    slab = rectangle("slab", (0.0, 0.0), (w, h), 8, 2, CONCRETE)
    m = Model().add(base, slab)
    W = CONCRETE.density * G * w * h
    if weight == "body_force":
        wl = BodyForce(bodies=("slab",))
    elif weight == "top_pressure":
        wl = EdgeLoad(m.select("slab", y=h), normal=W / w)
    else:
        raise ValueError(weight)
    return m.add(
        Support("rigid_base", m.select("base", boundary=False)),
        Support("slab_x", _node(m, "slab", w / 2, h), "x"),
        Interface("contact", m.select("slab", y=0.0), m.select("base", y=0.0)),
        LoadPattern("weight", [wl]),
        LoadPattern("uplift", [EdgeLoad(m.select("slab", y=0.0), normal=1000.0)]),
        Segment("weight", 1.0),
        Segment("uplift", lam_max),
    )


def spring_held_block(friction: float) -> Model:
    """Block on base with friction, held horizontally by springs on its right edge.

    Weight W, then pattern 'push' = BodyForce g = (0.5 g, +0.3 g) on the block: a horizontal
    push of 0.5 W and an uplift of 0.3 W at λ = 1, so the normal forces fall while the block
    slips (whole-block sliding starts near λ = f / (0.5 + 0.3 f)); the springs carry the
    excess and keep equilibrium.
    """
    m = block_on_base(friction=friction, w=2.0, h=0.5, nx=4, ny=1)
    right = m.select("block", x=2.0)
    return m.add(
        Spring("holder", right, None, kx=2.5e7 / len(right)),
        LoadPattern("weight", [BodyForce((0.0, -G), bodies=("block",))]),
        LoadPattern("push", [BodyForce((0.5 * G, 0.3 * G), bodies=("block",))]),
        Segment("weight", 1.0),
        Segment("push", 1.0),
    )


# --------------------------------------------------------------------------------------------
# Hertz: cylinder on a block (plane strain, half model)
# --------------------------------------------------------------------------------------------
HERTZ_R = 0.05  # m
HERTZ_P = 35e6  # N per m of thickness (35 kN/mm)
HERTZ_CYL = Material(210e9, 0.3)
HERTZ_BLOCK = Material(70e9, 0.3)


def hertz_solution(P: float = HERTZ_P, R: float = HERTZ_R,
                   m1: Material = HERTZ_CYL, m2: Material = HERTZ_BLOCK) -> tuple[float, float]:
    """Hertz line contact: half-width a = sqrt(4 P R / (π E*)) (m) and peak pressure
    p0 = 2 P / (π a) (Pa), 1/E* = (1-ν1²)/E1 + (1-ν2²)/E2; P per unit length (N/m)."""
    e_star = 1.0 / ((1 - m1.nu**2) / m1.E + (1 - m2.nu**2) / m2.E)
    a = np.sqrt(4 * P * R / (np.pi * e_star))
    return float(a), float(2 * P / (np.pi * a))


def graded_axis(length: float, h0: float, uniform: float, growth: float = 1.2) -> np.ndarray:
    """Grid points on [0, length]: spacing h0 up to ``uniform``, then growing geometrically
    (ratio about ``growth``, the last part scaled to end exactly at ``length``)."""
    k = int(np.ceil(uniform / h0))
    steps = [h0] * k
    grown: list[float] = []
    while k * h0 + sum(grown) < length:
        grown.append(h0 * growth ** (len(grown) + 1))
    g = np.asarray(grown) * (length - k * h0) / sum(grown)
    return np.r_[0.0, np.cumsum(np.r_[steps, g])]


def quarter_disc_mesh(R: float, h0: float, uniform: float) -> MeshQuad:
    """Quad mesh of the quarter disc {x ≥ 0, y ≤ R, x² + (y−R)² ≤ R²} (centre (0, R),
    touching y = 0 at the origin), graded towards the origin.

    A transfinite (Coons) map of the unit square: η = 0 → the arc from the origin to the 45°
    point, ξ = 1 → the arc from there to (R, R), ξ = 0 → the symmetry line x = 0, η = 1 → the
    cut y = R.  The grid lines are :func:`graded_axis` in arc length / depth.
    """
    quarter = R * np.pi / 4
    xi = graded_axis(quarter, h0, uniform) / quarter
    eta = graded_axis(R, h0, uniform) / R
    X, Y = np.meshgrid(xi, eta, indexing="ij")

    def arc(t):
        return np.stack([R * np.sin(t * np.pi / 4), R - R * np.cos(t * np.pi / 4)])

    c00, c10, c11, c01 = (np.array(c)[:, None, None] for c in
                          ((0.0, 0.0), arc(np.array(1.0)), (R, R), (0.0, R)))
    pts = ((1 - Y) * arc(X) + Y * np.stack([X * R, R + 0 * X])
           + (1 - X) * np.stack([0 * Y, Y * R]) + X * arc(1 + Y)
           - (1 - X) * (1 - Y) * c00 - X * (1 - Y) * c10 - X * Y * c11 - (1 - X) * Y * c01)
    idx = np.arange(X.size).reshape(X.shape)
    t = np.stack([idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(),
                  idx[:-1, 1:].ravel()])
    return MeshQuad(pts.reshape(2, -1), t)


def hertz_model(h0: float, *, block_ratio: float = 1.0, cfe: str = "auto",
                cylinder_plus: bool = True) -> Model:
    """NAFEMS-style cylinder on a block, half model (x ≥ 0), frictionless, quad4.

    Quarter of the cylinder (R = 50 mm, E = 210 GPa, ν = 0.3) on a block [0, 2R] × [−2R, 0]
    (E = 70 GPa, ν = 0.3), both with spacing ``h0`` up to 1.6 a from the contact point.  The
    half load P/2 is a uniform pressure on the cut y = R; x = 0 is a symmetry line (fixed in
    x); the block's bottom is fixed.  CFEs: S+ = the cylinder's arc nodes with x ≤ 0.3 R,
    S− = the block's top with x ≤ 0.4 R; gaps geometric (≈ x²/2R).

    ``block_ratio`` scales the block's spacing (≠ 1: meshes that clearly do not match),
    ``cfe`` is the interface's CFE kind, ``cylinder_plus`` False swaps S+ and S−.
    """
    R = HERTZ_R
    a, _ = hertz_solution()
    cyl = Body.from_mesh("cylinder", quarter_disc_mesh(R, h0, 1.6 * a), "quad4", HERTZ_CYL)
    ax = graded_axis(2 * R, h0 * block_ratio, 1.6 * a)
    block = rectangle("block", (0.0, -2 * R), (2 * R, 0.0), 1, 1, HERTZ_BLOCK,
                      xs=ax, ys=-ax[::-1])
    m = Model().add(cyl, block)

    def on_arc(x, y):
        return (np.abs(np.hypot(x, y - R) - R) <= 1e-9 * R) & (x <= 0.3 * R)

    m = m.add(
        Support("cyl_sym", m.select("cylinder", x=0.0), "x"),
        Support("block_sym", m.select("block", x=0.0), "x"),
        Support("block_bottom", m.select("block", y=-2 * R)),
    )
    arc = m.select("cylinder", where=on_arc)
    top = m.select("block", y=0.0, where=lambda x, y: x <= 0.4 * R)
    plus, minus = (arc, top) if cylinder_plus else (top, arc)
    return m.add(
        Interface("hertz", plus, minus, friction=0.0, cfe=cfe),
        LoadPattern("P", [EdgeLoad(m.select("cylinder", y=R), normal=HERTZ_P / 2 / R)]),
        Segment("P", 1.0),
    )


def hertz_half_width(x: np.ndarray, N: np.ndarray) -> float:
    """Contact half-width of the FE solution: midway between the last closed CFE and the first
    open one along x (error ≤ half the local spacing).  Closed: N < −1e-9 max|N| (open CFEs may
    carry round-off forces)."""
    order = np.argsort(x)
    x, N = x[order], N[order]
    closed = np.flatnonzero(N < -1e-9 * np.abs(N).max())
    k = closed.max()
    return float(0.5 * (x[k] + x[k + 1])) if k + 1 < len(x) else float(x[k])


# --------------------------------------------------------------------------------------------
# random frictional systems (property tests)
# --------------------------------------------------------------------------------------------
RANDOM_KINDS = ("block", "stack", "beam")


def random_frictional_model(
    kind: str,
    frictions: tuple[float, float],
    loads1: list[tuple[float, float]],
    loads2: list[tuple[float, float]],
    split: float | None = None,
) -> Model:
    """A small frictional system with random loads.

    ``kind``: ``"block"`` (block on base), ``"stack"`` (block B on block A on a base, meshes
    not matching) or ``"beam"`` (a frame on three frictional bearings against a rigid base).
    ``frictions``: coefficients of the (up to two) interfaces.  ``loads1``/``loads2``: (fx, fy)
    per loaded node, in units of the weight W divided by the number of loaded nodes (the extra
    entries are ignored; for the beam W is three times its weight).  Program: weight 0→1,
    'L1' 0→1, 'L2' 0→1, 'L1' 1→0; with ``split``
    the segment of 'L2' is split in two at ``split``.
    """
    if kind == "block":
        m = block_on_base(friction=frictions[0], w=1.5, h=0.5, nx=3, ny=1)
        loaded = m.select("block", y=0.5)
        W = SOFT.density * G * 0.75
        weight = BodyForce(bodies=("block",))
    elif kind == "stack":
        base = rectangle("base", (-0.5, -0.4), (2.0, 0.0), 5, 1, SOFT)
        a = rectangle("A", (0.0, 0.0), (1.5, 0.4), 2, 1, SOFT)
        b = rectangle("B", (0.2, 0.4), (1.2, 0.8), 3, 1, SOFT)
        m = Model().add(base, a, b)
        m = m.add(
            Support("base_bottom", m.select("base", y=-0.4)),
            Interface("A_on_base", m.select("A", y=0.0), m.select("base", y=0.0),
                      friction=frictions[0]),
            Interface("B_on_A", m.select("B", y=0.4), m.select("A", y=0.4),
                      friction=frictions[1]),
        )
        loaded = m.select("B", y=0.8)
        W = SOFT.density * G * (0.6 + 0.4)
        weight = BodyForce(bodies=("A", "B"))
    elif kind == "beam":
        beam = Frame.line("beam", (0.0, 0.0), (4.0, 0.0), 4, E=30e9, A=0.15, I=3.1e-3,
                          density=2500.0)
        base = rectangle("base", (-0.5, -0.5), (4.5, 0.0), 5, 1, CONCRETE)
        m = Model().add(beam, base)
        bearings = m.select("beam", where=lambda x, y: np.isin(np.round(x, 9), [0.0, 2.0, 4.0]))
        m = m.add(
            Support("rigid_base", m.select("base", boundary=False)),
            Interface("bearings", bearings, m.select("base", y=0.0), friction=frictions[0]),
        )
        loaded = m.select("beam", where=lambda x, y: np.isin(np.round(x, 9), [1.0, 2.0, 3.0]))
        W = 3 * 2500.0 * 0.15 * 4.0 * G  # loads up to 3 × the beam's weight: bearings open
        weight = BodyForce(bodies=("beam",))
    else:
        raise ValueError(kind)
    n = len(loaded)

    def pattern(name, loads):
        return LoadPattern(name, [
            NodalLoad(NodeSet(loaded.body, [node]), fx=fx * W / n, fy=fy * W / n)
            for node, (fx, fy) in zip(loaded.index, loads, strict=False)
        ])

    program = [Segment("weight", 1.0), Segment("L1", 1.0)]
    program += [Segment("L2", 1.0)] if split is None else [Segment("L2", split),
                                                          Segment("L2", 1.0)]
    program += [Segment("L1", 0.0)]
    return m.add(LoadPattern("weight", [weight]), pattern("L1", loads1), pattern("L2", loads2),
                 *program)


def beam_on_supports(xs: tuple[float, ...] = (0.0, 2.0, 4.0, 6.0, 8.0)) -> Model:
    """A steel beam (0, 0.5)–(8, 0.5) on frictionless supports at ``xs`` of a base; weight,
    then its right end is lifted by 1 N per unit λ (the supports open one after another)."""
    beam = Frame.line("beam", (0.0, 0.5), (8.0, 0.5), 8, E=210e9, A=0.01, I=2e-4,
                      density=7850.0)
    base = rectangle("base", (-1.0, 0.0), (9.0, 0.5), 10, 1, Material(200e9, 0.2))
    m = Model(bodies=[base, beam], name="frame")
    on = m.select("beam", where=lambda x, y: np.isin(np.round(x, 9), np.asarray(xs)))
    return m.add(
        Support("ground", m.select("base", y=0.0), "xy"),
        Support("pin", m.select("beam", x=0.0), "x"),
        Interface("supports", plus=on, minus=m.select("base", y=0.5), friction=0.0),
        LoadPattern("weight", [BodyForce(bodies=("beam",))]),
        LoadPattern("lift", [NodalLoad(m.select("beam", x=8.0), fy=1.0)]),
        Segment("weight", 1.0),
        Segment("lift", 1e6),
    )


def random_states(rng: np.random.Generator, m: int) -> np.ndarray:
    """Random working-scheme states of m CFEs (open 20 %, stuck 50 %, slipping ±15 % each):
    the schemes the scheme-solver tests draw."""
    return rng.choice([OPEN, STICK, SLIP_POS, SLIP_NEG], size=m, p=[0.2, 0.5, 0.15, 0.15])


def random_scheme_cases(rng: np.random.Generator, m: int, n: int = 40):
    """n random schemes of m CFEs (:func:`random_states`), each with a random relation
    right-hand side r (2m,) of size 1e-6: (states, r) pairs."""
    for _ in range(n):
        yield random_states(rng, m), rng.standard_normal(2 * m) * 1e-6


def first_forcing(cond) -> tuple[np.ndarray, np.ndarray]:
    """The load rates (ĥ, e) on the contact unknowns of a condensed system's first pattern."""
    name = next(iter(cond.hhat))
    return cond.hhat[name], cond.e[name]
