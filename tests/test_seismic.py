"""Issue 29 §1: the reservoir's added mass (Westergaard 1933, Kuo 1982) and pseudo-static seismic
coefficients with the yield acceleration as an exact event.

References, derived here independently of the code:

* Westergaard (1933): m_a(z) = (7/8) ρ_w √(H z) per unit area of a rigid vertical face; the
  force under a uniform acceleration a is F = ∫₀ᴴ m_a a dz = (7/12) ρ_w a H², its line of
  action ∫ m_a (H − z) dz / ∫ m_a dz = 0.4 H above the base.  The lumped masses are
  integrated by hand below (antiderivatives (2/3) z^{3/2}, (2/5) z^{5/2}), not by the code's
  Gauss rule in √z.
* Limit equilibrium of a block on a frictional base (friction f, weight W, no cohesion):
  sliding when the horizontal force reaches f times the normal force.
"""

from __future__ import annotations

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.errors import ModelError
from stepcontact.fem.assembly import load_resultant
from stepcontact.fem.hydrodynamic import added_mass_matrix, face_masses

RHO_W, GAMMA_W, G = 1000.0, 9810.0, 9.81
RHO_C = 2400.0
CONCRETE = sc.Material(E=25e9, nu=0.2, density=RHO_C)


def _hand_edge_masses(y_lo: float, y_hi: float, level: float, H: float) -> tuple[float, float]:
    """∫ m_a φ ds of the two nodes of a vertical linear edge y_lo < y_hi (per metre of
    thickness), by the antiderivatives in the depth z = level − y: φ_lo = (y_hi − y)/L =
    (z − z_hi)/L, φ_hi = (z_lo − z)/L, ∫ √z dz = (2/3) z^{3/2}, ∫ z √z dz = (2/5) z^{5/2}."""
    L = y_hi - y_lo
    z_hi, z_lo = max(level - y_hi, 0.0), max(level - y_lo, 0.0)  # wet part only
    if z_lo <= 0.0:
        return 0.0, 0.0
    i0 = 2 / 3 * (z_lo**1.5 - z_hi**1.5)  # ∫ √z dz over [z_hi, z_lo]
    i1 = 2 / 5 * (z_lo**2.5 - z_hi**2.5)  # ∫ z √z dz
    c = 7 / 8 * RHO_W * np.sqrt(H)
    return c * (i1 - (level - y_hi) * i0) / L, c * ((level - y_lo) * i0 - i1) / L


@pytest.mark.parametrize("level", [10.0, 7.3])
def test_lumped_masses_of_a_vertical_face_by_hand(level):
    """Every nodal mass of a vertical face (quad4, 1 m edges; the level 7.3 m cuts an edge)
    against the hand integrals, relative 1e-12; their sum against Westergaard's integral
    (7/12) ρ_w H², and their first moment against the line of action 0.4 H: exact on any mesh
    (Σ φ_i = 1 and Σ φ_i y_i = y), relative 1e-12.  The added mass acts in x only."""
    dam = sc.rectangle("dam", (0, 0), (8, 10), 4, 10, CONCRETE)
    m = sc.Model(bodies=[dam])
    am = sc.AddedMass(m.select("dam", x=0.0), level=level)
    ids, blocks = face_masses(m, am)
    y = m.points[ids, 1]
    hand = np.zeros(len(ids))
    H = level  # bottom: the face's lowest point, y = 0
    for k in range(10):
        lo, hi = _hand_edge_masses(float(k), float(k + 1), level, H)
        hand[y == k] += lo
        hand[y == k + 1] += hi
    assert np.allclose(blocks[:, 0, 0], hand, rtol=1e-12, atol=1e-12 * hand.max())
    assert np.all(blocks[:, 0, 1] == 0) and np.all(blocks[:, 1, 1] == 0)
    total = blocks[:, 0, 0].sum()
    assert abs(total / (7 / 12 * RHO_W * H**2) - 1) < 1e-12
    assert abs((blocks[:, 0, 0] @ y) / total / H - 0.4) < 1e-12


@pytest.mark.parametrize("element", ["tri3", "quad8", "tri6"])
def test_westergaard_force_on_other_elements(element):
    """The hydrodynamic force of a rigid vertical face under a uniform acceleration a, as the
    added-mass matrix times the rigid translation (M_a r a), against (7/12) ρ_w a H² at
    0.4 H above the base (relative 1e-12: exact for straight linear and quadratic edges on
    any mesh, so no refinement is needed; 3 elements over the height here).  The bottom is
    given (y = 0, the face's foot) and the level 9 m is below the crest."""
    dam = sc.rectangle("dam", (0, 0), (6, 10), 2, 3, CONCRETE, element=element)
    m = sc.Model(bodies=[dam])
    m = m.add(sc.AddedMass(m.select("dam", x=0.0), level=9.0, bottom=0.0),
              sc.Support("base", m.select("dam", y=0.0), "xy"))
    system = sc.assemble(m)
    a = 3.0
    r = np.zeros(system.ndof)
    r[system.dofs.of[:, 0]] = 1.0
    F = added_mass_matrix(m, system.dofs) @ (a * r)
    fx, fy = F[system.dofs.of[:, 0]], F[system.dofs.of[:, 1]]
    assert abs(fx.sum() / (7 / 12 * RHO_W * a * 81.0) - 1) < 1e-12
    assert np.abs(fy).max() == 0.0
    assert abs((fx @ m.points[:, 1]) / fx.sum() / 9.0 - 0.4) < 1e-12


def test_inclined_face_in_the_normal_direction():
    """An upstream face inclined at θ from the vertical (x = s y, s = tan θ = 0.3): the added
    mass acts along the normal n = (−cos θ, sin θ) (Kuo 1982), so under a horizontal
    acceleration a the force per unit face area is m_a a n_x n and, with ds = dz / cos θ,
    F = (7/12) ρ_w a H² (cos θ, −sin θ) by hand; relative 1e-12 (exact on the mesh)."""
    s, H = 0.3, 12.0
    dam = sc.quad_region("dam", [(0, 0), (9, 0), (s * H + 2, H), (s * H, H)], 4, 6, CONCRETE)
    m = sc.Model(bodies=[dam])
    face = m.select("dam", lambda x, y: np.abs(x - s * y) < 1e-9)
    ids, blocks = face_masses(m, sc.AddedMass(face, level=H))
    F = (blocks @ np.array([2.0, 0.0])).sum(axis=0)
    th = np.arctan(s)
    ref = 7 / 12 * RHO_W * 2.0 * H**2 * np.array([np.cos(th), -np.sin(th)])
    assert np.allclose(F, ref, rtol=1e-12, atol=0)


def test_dynamic_driver_carries_the_added_mass():
    """The dynamic driver: a stiff block 8 m × 6 m (E = 25 GPa) stuck on a rigid base
    (f = 5), water 5 m deep on its upstream face, the ground acceleration ramped to
    a = 2 m/s² in 0.02 s and held; with Rayleigh damping (ζ = 0.5) and HHT α = 0.1 the
    vibrations die out and the base shear tends to (m_block + (7/12) ρ_w h²) a by Newton's
    law (the whole mass, block and water, moves with the ground).  The independent check of
    the driver: without the added mass the shear is m_block a, 11 % less.  Measured error
    ~1e-12; tolerance 1e-9 relative on the shear, 1e-8 on its hydrodynamic part and on its
    line of action 0.4 h (from the moment of the normal contact forces)."""
    B, Hb, h, a = 8.0, 6.0, 5.0, 2.0
    m = sc.Model(bodies=[sc.rectangle("blk", (0, 0), (B, Hb), 8, 6, CONCRETE)])
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (B + 1.0, 0.0)])
    base = sc.Interface("base", plus=m.select("blk", y=0.0), minus=ground, friction=5.0)
    m = m.add(base, sc.LoadPattern("weight", [sc.BodyForce()]), sc.Segment("weight", 1.0),
              sc.AddedMass(m.select("blk", x=0.0), level=h))
    static = sc.solve_static(m)
    a0, a1 = sc.rayleigh_coefficients(0.5, 20.0, 0.5, 400.0)
    ramp = sc.Tabulated((0.0, 0.02, 1.0), (0.0, a, a))
    res = sc.solve_dynamic(m, dt=1e-3, duration=0.3, initial=static, mass="lumped",
                           ground_acceleration=(ramp, (1.0, 0.0)), damping=(a0, a1), alpha=0.1)
    assert res.status == sc.Status.COMPLETED
    shear = abs(res.Q[-1].sum())
    block = RHO_C * B * Hb * a
    water = 7 / 12 * RHO_W * a * h**2
    assert abs(shear / (block + water) - 1) < 1e-9
    assert abs((shear - block) / water - 1) < 1e-8
    # the line of action: moments about the heel (0, 0) of the normal contact forces balance
    # the weight W B/2 less the inertia turning the block upstream, m a H_b/2 (HRZ masses of
    # rectangles: their first moment is exact) and the water's F_d · 0.4 h; the hydrodynamic
    # force's lever from that balance is 0.4 h, relative 1e-8 (measured ~3e-11)
    W = RHO_C * G * B * Hb
    moment = (-res.N[-1]) @ res.cfe["x"][:, 0]
    lever = (W * B / 2 - block * Hb / 2 - moment) / water
    assert abs(lever / (0.4 * h) - 1) < 1e-8


def _block(B=8.0, Hb=4.0, f=0.6, nx=8, ny=4):
    """A stiff block B × Hb (E = 1e13 Pa: rigid for the statics) on a rigid base with friction
    f, and its weight pattern."""
    conc = sc.Material(E=1e13, nu=0.2, density=RHO_C)
    m = sc.Model(bodies=[sc.rectangle("blk", (0, 0), (B, Hb), nx, ny, conc)])
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (B + 1.0, 0.0)])
    base = sc.Interface("base", plus=m.select("blk", y=0.0), minus=ground, friction=f)
    return m.add(base, sc.LoadPattern("weight", [sc.BodyForce()]), sc.Segment("weight", 1.0))


@pytest.mark.parametrize(("k_v", "ratio"), [(0.0, 0.0), (0.1, 0.0), (0.0, 0.5)])
def test_yield_acceleration_of_a_block(k_v, ratio):
    """The pseudo-static yield acceleration of a rigid block on a frictional base, the λ at
    which equilibrium is lost on the k_h segment, against limit equilibrium (relative 1e-9:
    the event is exact).  Inertia W k_h along +x, W k_v upwards (the ground accelerating
    down): N = W (1 − k_v), T = k_h W, sliding at T = f N:

    * k_v = 0: k_y = f;
    * a constant k_v (its own pattern at λ = 1 before the k_h segment): k_y = f (1 − k_v);
    * k_v = r k_h moving with λ (``SeismicCoefficient(k_h=1, k_v=r)``): k_h W = f W (1 − r
      k_h), k_y = f / (1 + f r).

    The block (8 m × 4 m) tips only at k_h = B/Hb = 2 and its base opens at e = B/6, i.e.
    k_h = B/(3 Hb) = 0.67 > k_y: the dam slides, as the hand analysis assumes."""
    f = 0.6
    m = _block(f=f)
    if k_v:
        m = m.add(sc.LoadPattern("vertical", [sc.SeismicCoefficient(k_h=0.0, k_v=k_v)]),
                  sc.Segment("vertical", 1.0))
    m = m.add(sc.LoadPattern("quake", [sc.SeismicCoefficient(k_h=1.0, k_v=ratio)]),
              sc.Segment("quake", 2.0))
    res = sc.solve_static(m)
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    k_y = res.multipliers[-1].equilibrium_lost
    hand = f * (1 - k_v) / (1 + f * ratio)
    assert abs(k_y / hand - 1) < 1e-9


def test_yield_acceleration_with_the_reservoir():
    """A block 8 m × 6 m holding water h = 5 m deep on its upstream face (x = 0), uplift from
    the full head at the heel to 0 at the toe, then k_h with Westergaard's hydrodynamic force
    on the face.  Hand limit equilibrium per metre (no cohesion, γ_w = ρ_w g):

        W = ρ_c g B H_b,  U = γ_w h B / 2,  P = γ_w h² / 2,  P_d = (7/12) k γ_w h²,
        k W + P + P_d = f (W − U)   ⇒   k_y = (f (W − U) − P) / (W + (7/12) γ_w h²)

    (k_y = 0.4538 here; overturning about the toe needs more).  Relative 1e-9 (exact event).
    Without the hydrodynamic force k_y would be 13 % higher: the test fails if it is lost."""
    f, B, Hb, h = 0.75, 8.0, 6.0, 5.0
    m = _block(B=B, Hb=Hb, f=f, nx=8, ny=6)
    face = m.select("blk", x=0.0)
    base = m.interfaces[0]
    m = m.add(
        sc.LoadPattern("water", [sc.WaterLoad(face, level=h),
                                 sc.Uplift(base, head=[(0.0, 0.0, h), (B, 0.0, 0.0)])]),
        sc.Segment("water", 1.0),
        sc.LoadPattern("quake", [sc.SeismicCoefficient(
            k_h=1.0, reservoir=sc.AddedMass(face, level=h))]),
        sc.Segment("quake", 2.0))
    res = sc.solve_static(m)
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    W, U, P = RHO_C * G * B * Hb, GAMMA_W * h * B / 2, GAMMA_W * h**2 / 2
    hand = (f * (W - U) - P) / (W + 7 / 12 * GAMMA_W * h**2)
    assert abs(res.multipliers[-1].equilibrium_lost / hand - 1) < 1e-9


def test_yield_acceleration_with_the_heel_opening():
    """An elastic dam (E = 25 GPa, 8 m × 12 m) on a compliant joint (k_n = k_t = 1e8 Pa/m)
    holding water 11 m deep with full uplift: on the k_h segment the heel opens step by step
    (opening events) before the base slides throughout.  Global limit equilibrium holds
    whatever the opened length while the resultant stays inside the base (overturning about
    the toe needs k ≈ 0.3 here), so k_y = (f (W − U) − P) / (W + (7/12) γ_w h²) = 0.1706 as in
    the rigid case; relative 1e-9 (measured ~2e-11; with E = 1e13 on this soft layer the
    round-off of the stiffness ratio reaches ~4e-9)."""
    f, B, Hb, h = 0.6, 8.0, 12.0, 11.0
    m = sc.Model(bodies=[sc.rectangle("blk", (0, 0), (B, Hb), 8, 12, CONCRETE)])
    ground = sc.RigidObstacle("ground", [(-1.0, 0.0), (B + 1.0, 0.0)])
    base = sc.Interface("base", plus=m.select("blk", y=0.0), minus=ground, friction=f,
                        layer=sc.ContactLayer(kn=1e8, kt=1e8))
    face = m.select("blk", x=0.0)
    m = m.add(
        base, sc.LoadPattern("weight", [sc.BodyForce()]), sc.Segment("weight", 1.0),
        sc.LoadPattern("water", [sc.WaterLoad(face, level=h),
                                 sc.Uplift(base, head=[(0.0, 0.0, h), (B, 0.0, 0.0)])]),
        sc.Segment("water", 1.0),
        sc.LoadPattern("quake", [sc.SeismicCoefficient(reservoir=sc.AddedMass(face, level=h))]),
        sc.Segment("quake", 1.0))
    res = sc.solve_static(m)
    assert res.status == sc.Status.EQUILIBRIUM_LOST
    opened = [e for e in res.events if e.segment == 2 and e.transition == sc.Transition.OPENED]
    assert len(opened) >= 2  # the crack grows with k_h
    W, U, P = RHO_C * G * B * Hb, GAMMA_W * h * B / 2, GAMMA_W * h**2 / 2
    hand = (f * (W - U) - P) / (W + 7 / 12 * GAMMA_W * h**2)
    assert abs(res.multipliers[-1].equilibrium_lost / hand - 1) < 1e-9


def test_pseudo_static_pattern_resultant_and_line_of_action():
    """The load of ``SeismicCoefficient(k_h=1)`` with a reservoir h = 5 m on the block's face:
    F_x = W + (7/12) γ_w h² (N per unit λ), F_y = 0, and its moment about the origin
    M_z = −(W H_b/2 + (7/12) γ_w h² · 0.4 h) (inertia at the centroid, Westergaard's force at
    0.4 h above the base), by hand; relative 1e-12.  With direction −1 the load reverses
    (the hydrodynamic pressure becomes a suction, Westergaard's antisymmetric response)."""
    B, Hb, h = 8.0, 6.0, 5.0
    m = _block(B=B, Hb=Hb, nx=4, ny=6)
    face = m.select("blk", x=0.0)
    W, Pd = RHO_C * G * B * Hb, 7 / 12 * GAMMA_W * h**2
    for d in (1.0, -1.0):
        q = sc.SeismicCoefficient(reservoir=sc.AddedMass(face, level=h), direction=d)
        system = sc.assemble(m.add(sc.LoadPattern("quake", [q])))
        Fx, Fy, Mz = load_resultant(system.model, system.dofs, system.loads["quake"].f)
        assert abs(Fx / (d * (W + Pd)) - 1) < 1e-12
        assert abs(Fy) < 1e-12 * W
        assert abs(Mz / (-d * (W * Hb / 2 + Pd * 0.4 * h)) - 1) < 1e-12


def test_model_add_and_mass_matrix():
    """``Model.add`` puts an AddedMass into ``model.added_masses`` and the model's mass matrix
    (fem.mass.mass, the one the dynamic driver builds) holds it: the added u_x mass of the
    face sums to (7/12) ρ_w H² (relative 1e-12), nothing else changes."""
    from stepcontact.fem.mass import mass

    m = _block(B=8.0, Hb=6.0, nx=4, ny=6)
    am = sc.AddedMass(m.select("blk", x=0.0), level=6.0)
    wet = m.add(am)
    assert wet.added_masses == (am,) and m.added_masses == ()
    system = sc.assemble(wet)
    dM = mass(wet, system.dofs, lumped=True) - mass(m, system.dofs, lumped=True)
    r = np.zeros(system.ndof)
    r[system.dofs.of[:, 0]] = 1.0
    assert abs((r @ dM @ r) / (7 / 12 * RHO_W * 36.0) - 1) < 1e-12
    ry = np.zeros(system.ndof)
    ry[system.dofs.of[:, 1]] = 1.0
    assert abs(ry @ dM @ ry) == 0.0


def test_errors_name_the_item():
    """Bad input is a ModelError naming the item: an empty reservoir (level not above the
    bottom), a face reaching below the given bottom, a node set that is not on the boundary,
    a frame or a 3D body, a zero or misdirected seismic coefficient, a reservoir that is not
    an AddedMass, a negative density."""
    m = _block(B=8.0, Hb=6.0, nx=4, ny=6)
    face = m.select("blk", x=0.0, name="upstream")
    with pytest.raises(ModelError, match=r"added mass on node set 'upstream'\.level.*empty"):
        sc.AddedMass(face, level=2.0, bottom=3.0)
    with pytest.raises(ModelError, match=r"added mass on node set 'upstream'\.level.*empty"):
        face_masses(m, sc.AddedMass(face, level=-1.0))  # below the face's foot (y = 0)
    with pytest.raises(ModelError, match=r"added mass on node set 'upstream'\.bottom"):
        face_masses(m, sc.AddedMass(face, level=5.0, bottom=1.0))
    with pytest.raises(ModelError, match=r"added mass on node set 'upstream'\.density"):
        sc.AddedMass(face, level=5.0, density=-1000.0)
    with pytest.raises(ModelError, match=r"added mass.*level.*finite"):
        sc.AddedMass(face, level=float("nan"))
    inner = sc.NodeSet("blk", np.array([6, 7]), name="inside")  # not on one edge
    with pytest.raises(ModelError, match=r"added mass on node set 'inside'.*no boundary edge"):
        face_masses(m, sc.AddedMass(inner, level=5.0))
    with pytest.raises(ModelError, match=r"seismic coefficient\.k_h.*zero"):
        sc.SeismicCoefficient(k_h=0.0, k_v=0.0)
    with pytest.raises(ModelError, match=r"seismic coefficient\.direction"):
        sc.SeismicCoefficient(direction=2.0)
    with pytest.raises(ModelError, match=r"seismic coefficient\.reservoir\[0\]"):
        sc.SeismicCoefficient(reservoir=(face,))
    frame = sc.Frame("beam", [(0.0, 0.0), (0.0, 5.0)], [(0, 1)], E=2e11, A=0.01, I=1e-4,
                     density=7850)
    mf = sc.Model(bodies=[frame])
    with pytest.raises(ModelError, match=r"added mass on node set 'col'.*frame"):
        face_masses(mf, sc.AddedMass(mf.select("beam", x=0.0, name="col"), level=4.0))
    with pytest.raises(ModelError, match=r"model\.added_masses\[0\].*AddedMass"):
        m.replace(added_masses=(face,))
    # the error of an assembled pattern names the pattern, the load and the reservoir
    bad = m.add(sc.LoadPattern("quake", [sc.SeismicCoefficient(
        reservoir=sc.AddedMass(face, level=-1.0))]))
    with pytest.raises(ModelError, match=r"load pattern 'quake' load 0\.reservoir\[0\]"):
        sc.assemble(bad)


def test_three_d_face_is_refused():
    """An added mass on a 3D body's face is refused, naming the item (2D only for now)."""
    solid = sc.box("cube", (0, 0, 0), (2, 2, 2), (1, 1, 1), CONCRETE)
    m = sc.Model(bodies=[solid])
    am = sc.AddedMass(m.select("cube", boundary="left", name="wet"), level=1.5)
    with pytest.raises(ModelError, match=r"added mass on node set 'wet'.*3D"):
        face_masses(m, am)


QUAKE_TOML = """
[model]
name = "block holding water"

[materials.stiff]
E = 1e13
nu = 0.2
density = 2400

[[bodies]]
name = "dam"
kind = "rectangle"
corner0 = [0.0, 0.0]
corner1 = [8.0, 6.0]
nx = 8
ny = 6
material = "stiff"

[node_sets.upstream]
body = "dam"
x = 0.0

[node_sets.base]
body = "dam"
y = 0.0

[[obstacles]]
name = "ground"
points = [[-1.0, 0.0], [9.0, 0.0]]

[[interfaces]]
name = "base"
plus = "base"
obstacle = "ground"
friction = 0.75

[[added_masses]]
nodes = "upstream"
level = 5.0

[patterns.weight]
loads = [{ type = "gravity" }]

[patterns.water]
loads = [
  { type = "water", nodes = "upstream", level = 5.0 },
  { type = "uplift", interface = "base", head = { from = [0.0, 0.0, 5.0], to = [8.0, 0.0, 0.0] } },
]

[patterns.quake]
loads = [{ type = "seismic", k_h = 1.0, reservoir = [{ nodes = "upstream", level = 5.0 }] }]

[[program]]
pattern = "weight"
end = 1.0

[[program]]
pattern = "water"
end = 1.0

[[program]]
pattern = "quake"
end = 1.0
"""


def test_model_file_items():
    """The model file's ``[[added_masses]]`` and ``type = "seismic"`` load build the same
    items: the yield acceleration of the reservoir test's block against the same hand limit
    equilibrium (relative 1e-9), and the added mass in ``model.added_masses``."""
    import tomllib

    from stepcontact.io.modelfile import model_from_dict

    m = model_from_dict(tomllib.loads(QUAKE_TOML))
    assert len(m.added_masses) == 1 and m.added_masses[0].level == 5.0
    res = sc.solve_static(m)
    W, U, P = RHO_C * G * 48.0, GAMMA_W * 5.0 * 8.0 / 2, GAMMA_W * 25.0 / 2
    hand = (0.75 * (W - U) - P) / (W + 7 / 12 * GAMMA_W * 25.0)
    assert abs(res.multipliers[-1].equilibrium_lost / hand - 1) < 1e-9


@pytest.mark.parametrize(("change", "path", "text"), [
    (("added_masses", 0, "nodes", "nope"), "added_masses[0].nodes", "unknown node set 'nope'"),
    (("added_masses", 0, "bottom", 6.0), "added_masses[0].level", "reservoir is empty"),
    (("quake", "direction", 2), "patterns.quake.loads[0].direction", "1 or -1"),
    (("quake", "k_h", 0.0), "patterns.quake.loads[0].k_h", "load is zero"),
    (("quake", "bodies", ["x"]), "patterns.quake.loads[0].bodies", "unknown body 'x'"),
    (("reservoir", "nodes", "zz"), "patterns.quake.loads[0].reservoir[0].nodes",
     "unknown node set 'zz'"),
])
def test_model_file_errors_name_the_field(change, path, text):
    """A bad entry is reported at its field path with a message naming what is wrong."""
    import tomllib

    from stepcontact.io.modelfile import model_from_dict

    d = tomllib.loads(QUAKE_TOML)
    *where, key, value = change
    target = {"quake": lambda: d["patterns"]["quake"]["loads"][0],
              "reservoir": lambda: d["patterns"]["quake"]["loads"][0]["reservoir"][0],
              "added_masses": lambda: d["added_masses"][where[1]]}[where[0]]()
    target[key] = value
    with pytest.raises(ModelError) as err:
        model_from_dict(d)
    found = dict(err.value.errors)
    assert path in found and text in found[path], found


def test_validate_reports_an_empty_reservoir(tmp_path):
    """``validate`` checks the added masses against the mesh: a level below the face's foot
    is reported at ``added_masses[0].level``."""
    from stepcontact.io.modelfile import validate_model_file

    bad = tmp_path / "bad.toml"
    bad.write_text(QUAKE_TOML.replace("nodes = \"upstream\"\nlevel = 5.0",
                                      "nodes = \"upstream\"\nlevel = -1.0"), encoding="utf-8")
    problems = validate_model_file(bad)
    assert [(p.item, "reservoir is empty" in p.message) for p in problems] == [
        ("added_masses[0].level", True)]
