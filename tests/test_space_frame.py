"""Space frames (issue 28 §1): 12-DOF Euler–Bernoulli beams in a 3D model, alone and tied to a
solid, run through the static driver with no CFEs (m = 0).

References (closed forms; Euler–Bernoulli beams with cubic elements are exact at the nodes
for end loads and, with consistent loads, for a uniform line load):

* a cantilever of length L with a tip force P: δ = P L³ / (3 E I), θ = P L² / (2 E I); an
  axial force N: N L / (E A); a torque T: φ = T L / (G J) (Timoshenko & Gere, *Mechanics of
  Materials*); under its own weight q = ρ A g: δ = q L⁴ / (8 E I), θ = q L³ / (6 E I);
* a cantilever with a spring at its tip: u = (K_tip + k d dᵀ)⁻¹ F, K_tip the tip's translation
  stiffness (3 E I / L³ across, E A / L along the bar, the tip free to turn);
* statics: the reactions balance the loads, forces and moments about the origin.

Tolerances: 1e-9 relative to the closed form's value (round-off of a handful of elements is
~1e-13).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.fem.assembly import assemble, load_resultant

E, A, IY, IZ, J, G = 2.0e11, 1.0e-2, 2.0e-5, 5.0e-5, 3.0e-5, 8.0e10
SECTION = {"E": E, "A": A, "Iy": IY, "Iz": IZ, "J": J, "G": G}
CLAMPED = "xyzrxryrz"


def _solve(m: sc.Model):
    res = sc.solve_static(m)
    assert res.status == sc.Status.COMPLETED and len(res.events) == 0, res.message
    return res, assemble(m).dofs


def _node(res, dofs, node: int) -> np.ndarray:
    """The six displacements (ux, uy, uz, rx, ry, rz) of a global node at the last state."""
    return res.displacement(-1)[dofs.of[node]]


def _cantilever(start, end, n=4, loads=None, **section):
    fr = sc.Frame.line("beam", start, end, n, **{**SECTION, **section})
    m = sc.Model(bodies=(fr,))
    tip = sc.NodeSet("beam", [n], "tip")
    m = m.add(sc.Support("clamp", sc.NodeSet("beam", [0]), CLAMPED))
    if loads is not None:
        m = m.add(sc.LoadPattern("P", [sc.NodalLoad(tip, **loads)]), sc.Segment("P", 1.0))
    return m


def test_cantilever_along_x_tip_forces_and_torque_are_exact():
    """Local axes y' = global y, z' = global z (orientation (0, 1, 0)): a tip load
    (N, Py, Pz, T) gives ux = N L/(EA), uy = Py L³/(3 E Iz), uz = Pz L³/(3 E Iy),
    rx = T L/(G J), ry = −Pz L²/(2 E Iy), rz = Py L²/(2 E Iz), each to 1e-9 relative; the
    clamp's reactions are minus the loads (1e-9)."""
    L, N, Py, Pz, T = 3.0, 1.0e4, 1.0e3, 2.0e3, 5.0e2
    m = _cantilever((0, 0, 0), (L, 0, 0), loads={"fx": N, "fy": Py, "fz": Pz, "mx": T},
                    orientation=(0, 1, 0))
    res, dofs = _solve(m)
    assert dofs.names == ("x", "y", "z", "rx", "ry", "rz")
    exact = np.array([N * L / (E * A), Py * L**3 / (3 * E * IZ), Pz * L**3 / (3 * E * IY),
                      T * L / (G * J), -Pz * L**2 / (2 * E * IY), Py * L**2 / (2 * E * IZ)])
    np.testing.assert_allclose(_node(res, dofs, 4), exact, rtol=1e-9)
    loads = {"x": N, "y": Py, "z": Pz, "rx": T, "ry": -Pz * L, "rz": Py * L}
    for d, v in loads.items():  # reaction moments about the clamp's node at the origin
        assert abs(res.reaction("clamp", d)[-1] + v) <= 1e-9 * abs(v), d


def test_default_orientation_makes_y_prime_vertical():
    """Without an orientation a horizontal bar has y' = global z (up): a vertical tip force
    bends it about z' with Iz (the strong axis), P L³/(3 E Iz); a horizontal one with Iy;
    a vertical bar (a column) takes y' = global x.  1e-9 relative."""
    L, P = 2.0, 1.0e3
    res, dofs = _solve(_cantilever((0, 0, 0), (0, L, 0), loads={"fz": P, "fx": P}))
    u = _node(res, dofs, 4)
    np.testing.assert_allclose(u[[2, 0]], [P * L**3 / (3 * E * IZ), P * L**3 / (3 * E * IY)],
                               rtol=1e-9)
    res, dofs = _solve(_cantilever((0, 0, 0), (0, 0, L), loads={"fx": P, "fy": P}))
    u = _node(res, dofs, 4)
    np.testing.assert_allclose(u[[0, 1]], [P * L**3 / (3 * E * IZ), P * L**3 / (3 * E * IY)],
                               rtol=1e-9)


def test_oblique_cantilever_with_oblique_orientation_is_exact():
    """A bar along e = (1, 2, 2)/3 with the orientation v = (1, −1, 3): with y' the part of v
    normal to e and z' = e × y' (built here, independently of the code), a tip load
    N e + Py y' + Pz z' + T e gives u = N L/(EA) e + Py L³/(3EIz) y' + Pz L³/(3EIy) z' and
    θ = T L/(GJ) e + Py L²/(2EIz) z' − Pz L²/(2EIy) y', to 1e-9 of |u| and |θ|."""
    L, N, Py, Pz, T = 4.5, 3.0e4, 2.0e3, -1.5e3, 8.0e2
    e = np.array([1.0, 2.0, 2.0]) / 3.0
    v = np.array([1.0, -1.0, 3.0])
    y = v - (v @ e) * e
    y /= np.linalg.norm(y)
    z = np.cross(e, y)
    F = N * e + Py * y + Pz * z
    M = T * e
    m = _cantilever((1.0, -2.0, 0.5), np.array([1.0, -2.0, 0.5]) + L * e, n=5,
                    loads=dict(zip(("fx", "fy", "fz", "mx", "my", "mz"), (*F, *M), strict=True)),
                    orientation=tuple(v))
    res, dofs = _solve(m)
    got = _node(res, dofs, 5)
    u = N * L / (E * A) * e + Py * L**3 / (3 * E * IZ) * y + Pz * L**3 / (3 * E * IY) * z
    th = T * L / (G * J) * e + Py * L**2 / (2 * E * IZ) * z - Pz * L**2 / (2 * E * IY) * y
    assert np.abs(got[:3] - u).max() <= 1e-9 * np.linalg.norm(u)
    assert np.abs(got[3:] - th).max() <= 1e-9 * np.linalg.norm(th)


def test_cantilever_under_self_weight_and_nu_gives_g():
    """Self-weight along −z (the default BodyForce on a 3D model) of a horizontal cantilever:
    δ = q L⁴/(8 E Iz), θ = q L³/(6 E Iz) with q = ρ A g (consistent loads: exact at the nodes,
    1e-9); the clamp carries the weight q L (1e-12).  G from ν: E/(2(1 + ν)) exactly; the
    frame moved (translate) keeps its section (a copy re-checks it)."""
    L, rho = 5.0, 7850.0
    m = _cantilever((0, 0, 0), (L, 0, 0), n=6, density=rho, G=None, nu=0.25)
    assert m.body("beam").shear_modulus == E / 2.5
    m = m.add(sc.LoadPattern("weight", [sc.BodyForce()]), sc.Segment("weight", 1.0))
    res, dofs = _solve(m)
    moved = dataclasses.replace(m.body("beam"), points=m.body("beam").points + 1.0)
    assert moved.shear_modulus == E / 2.5 and moved.Iz == IZ
    q = rho * A * 9.81
    u = _node(res, dofs, 6)
    np.testing.assert_allclose(u[[2, 4]], [-q * L**4 / (8 * E * IZ), q * L**3 / (6 * E * IZ)],
                               rtol=1e-9)
    assert abs(res.reaction("clamp", "z")[-1] - q * L) <= 1e-12 * q * L


def test_tip_spring_in_any_direction():
    """A spring k along d = (0, 1, 1)/√2 from the tip of a cantilever along x to the ground:
    u = (K_tip + k d dᵀ)⁻¹ F with K_tip = diag(EA/L, 3EIy/L³, 3EIz/L³) (default axes:
    global y bends with Iy, z with Iz), to 1e-9 relative."""
    L, k = 2.0, 4.0e6
    F = np.array([5.0e3, 1.0e3, -3.0e3])
    m = _cantilever((0, 0, 0), (L, 0, 0), loads={"fx": F[0], "fy": F[1], "fz": F[2]})
    m = m.add(sc.Spring("prop", sc.NodeSet("beam", [4]), k=k, direction=(0.0, 1.0, 1.0)))
    res, dofs = _solve(m)
    d = np.array([0.0, 1.0, 1.0]) / np.sqrt(2.0)
    K = np.diag([E * A / L, 3 * E * IY / L**3, 3 * E * IZ / L**3]) + k * np.outer(d, d)
    exact = np.linalg.solve(K, F)
    assert np.abs(_node(res, dofs, 4)[:3] - exact).max() <= 1e-9 * np.abs(exact).max()


def _portal(h=3.0, a=4.0, b=2.5, n=2):
    """A 3D portal: four columns of height h at the corners of an a × b rectangle, joined at
    the top by four beams; each member in n elements; one Frame (shared corner nodes)."""
    corners = np.array([[0, 0], [a, 0], [a, b], [0, b]], float)
    pts = [np.r_[c, 0.0] for c in corners] + [np.r_[c, h] for c in corners]
    cells = []

    def member(i, j):
        prev = i
        for s in np.linspace(0, 1, n + 1)[1:-1]:
            pts.append((1 - s) * pts[i] + s * pts[j])
            cells.append((prev, len(pts) - 1))
            prev = len(pts) - 1
        cells.append((prev, j))

    for k in range(4):
        member(k, k + 4)
        member(4 + k, 4 + (k + 1) % 4)
    return sc.Frame("portal", np.array(pts), np.array(cells), nu=0.3,
                    **{k: v for k, v in SECTION.items() if k != "G"})


def test_space_portal_reactions_balance_the_loads():
    """Four clamped column bases (one support each) and forces and moments at the top
    corners: Σ R + Σ F = 0 and Σ (x × R + M_R) + Σ (x × F + M) = 0 about the origin, to
    1e-9 of the loads' scale (force, and force × size for moments)."""
    fr = _portal()
    m = sc.Model(bodies=(fr,))
    for k in range(4):
        m = m.add(sc.Support(f"base{k}", sc.NodeSet("portal", [k]), CLAMPED))
    loads = [sc.NodalLoad(sc.NodeSet("portal", [4]), fx=2e4, fy=-1e4, fz=-5e4, mz=3e3),
             sc.NodalLoad(sc.NodeSet("portal", [6]), fy=1.5e4, mx=-2e3, my=4e3),
             sc.NodalLoad(sc.NodeSet("portal", [7]), fz=-3e4)]
    m = m.add(sc.LoadPattern("P", loads), sc.Segment("P", 1.0))
    res, dofs = _solve(m)
    applied = load_resultant(m, dofs, assemble(m).loads["P"].f)
    np.testing.assert_allclose(applied[:3], [2e4, 5e3, -8e4], rtol=1e-15)
    names = ("x", "y", "z", "rx", "ry", "rz")
    total = applied.copy()
    for k in range(4):
        r = np.array([res.reaction(f"base{k}", d)[-1] for d in names])
        total += np.r_[r[:3], np.cross(fr.points[k], r[:3]) + r[3:]]
    scale = 8e4
    assert np.abs(total[:3]).max() <= 1e-9 * scale
    assert np.abs(total[3:]).max() <= 1e-9 * scale * 4.0


def test_space_portal_in_a_plane_matches_the_plane_frame():
    """A one-bay portal in the x–z plane of a 3D model (Iy = Iz = I), loaded in its plane,
    moves as the plane frame (x–y plane, 3 DOFs per node) under the same loads: (ux, uz, −ry)
    of the 3D portal = (ux, uy, rz) of the plane one, to 1e-9 of the largest; its
    out-of-plane response (uy, rx, rz) is zero to 1e-12 of it."""
    h, a = 3.0, 4.0
    pts2 = np.array([[0, 0], [0, h], [a, h], [a, 0], [0, h / 2], [a / 2, h], [a, h / 2]])
    cells = np.array([[0, 4], [4, 1], [1, 5], [5, 2], [2, 6], [6, 3]])
    pts3 = np.column_stack([pts2[:, 0], np.zeros(len(pts2)), pts2[:, 1]])
    plane = sc.Frame("f", pts2, cells, E, A, IZ)
    space = sc.Frame("f", pts3, cells, E, A, IZ, J=J, G=G)  # I: Iy = Iz = IZ
    out = []
    for fr, clamp, load in ((plane, "xyrz", {"fx": 1e4, "fy": -3e4, "mz": 2e3}),
                            (space, CLAMPED, {"fx": 1e4, "fz": -3e4, "my": -2e3})):
        m = sc.Model(bodies=(fr,))
        m = m.add(sc.Support("bases", sc.NodeSet("f", [0, 3]), clamp),
                  sc.LoadPattern("P", [sc.NodalLoad(sc.NodeSet("f", [1, 5]), **load)]),
                  sc.Segment("P", 1.0))
        res, dofs = _solve(m)
        out.append(res.displacement(-1)[dofs.of].reshape(len(pts2), -1))
    u2, u3 = out
    mapped = np.column_stack([u3[:, 0], u3[:, 2], -u3[:, 4]])
    assert np.abs(mapped - u2).max() <= 1e-9 * np.abs(u2).max()
    assert np.abs(u3[:, [1, 3, 5]]).max() <= 1e-12 * np.abs(u2).max()


def test_space_frame_tied_to_a_solid():
    """A beam along the top edge of a clamped hex8 box, its first three nodes tied to the
    box's nodes, overhanging by 2 m with a tip force P (z): the box's bottom reactions
    balance P and its moment (1e-9); the tied nodes move together (exactly: shared DOFs); the
    overhang is a cantilever from its root at x = 1: w_tip = w₁ + 2 θ₁ + P 2³/(3 E Iz) with
    θ₁ = −ry₁ (1e-9 of w_tip − w₁)."""
    block = sc.box("block", (0, 0, 0), (1, 1, 1), (2, 2, 2), sc.Material(3e10, 0.2), "hex8")
    beam = sc.Frame.line("beam", (0, 0, 1), (3, 0, 1), 6, **SECTION)
    m = sc.Model(bodies=(block, beam))
    edge = m.select("block", where=lambda x, y, z: (y == 0) & (z == 1), name="edge")
    order = np.argsort(block.points[edge.index, 0])
    P = -2.0e4
    m = m.add(sc.Support("bed", m.select("block", boundary="bottom"), "xyz"),
              sc.Support("twist", sc.NodeSet("beam", [0]), "rx"),
              sc.Tie("joint", sc.NodeSet("beam", [0, 1, 2]),
                     sc.NodeSet("block", edge.index[order])),
              sc.LoadPattern("P", [sc.NodalLoad(sc.NodeSet("beam", [6]), fz=P)]),
              sc.Segment("P", 1.0))
    res, dofs = _solve(m)
    assert dofs.of.shape[1] == 6 and np.all(dofs.of[: block.n_nodes, 3:] == -1)
    off = m.node_offsets["beam"]
    u = res.displacement(-1)
    np.testing.assert_array_equal(dofs.of[off + np.arange(3), :3],
                                  dofs.of[edge.index[order], :3])
    assert abs(res.reaction("bed", "z")[-1] + P) <= 1e-9 * abs(P)
    assert abs(res.reaction("bed", "x")[-1]) <= 1e-9 * abs(P)
    assert abs(res.reaction("twist", "rx")[-1]) <= 1e-9 * abs(P)
    root, tip = dofs.of[off + 2], dofs.of[off + 6]
    rise = u[tip[2]] - u[root[2]]
    expected = -2.0 * u[root[4]] + P * 2.0**3 / (3 * E * IZ)
    assert abs(rise - expected) <= 1e-9 * abs(rise)


def test_nodal_moments_count_in_the_load_resultant():
    """[F, M] of nodal forces and moments on a space frame: M = Σ x × f + Σ m (exact sums of
    a few products, 1e-15 relative)."""
    m = _cantilever((0, 0, 0), (2, 0, 0), loads={"fz": 10.0, "mx": 3.0, "my": -4.0, "mz": 5.0})
    sysm = assemble(m)
    got = load_resultant(m, sysm.dofs, sysm.loads["P"].f)
    np.testing.assert_allclose(got, [0, 0, 10, 3, -4 - 20, 5], rtol=1e-15, atol=1e-15)


def _raises(fn, item: str, text: str):
    with pytest.raises(sc.ModelError) as info:
        fn()
    assert info.value.item == item, info.value
    assert text in info.value.problem, info.value


def test_space_frame_errors_name_the_item():
    pts = np.array([[0, 0, 0], [0, 0, 2.0]])
    cells = np.array([[0, 1]])
    no_g = {k: v for k, v in SECTION.items() if k != "G"}
    _raises(lambda: sc.Frame("f", pts, cells, orientation=(0, 0, 5), **SECTION),
            "frame 'f' element 0", "orientation")
    _raises(lambda: sc.Frame("f", pts, cells, **no_g), "frame 'f'.G", "nu")
    _raises(lambda: sc.Frame("f", pts, cells, nu=0.3, **SECTION), "frame 'f'.G", "not both")
    _raises(lambda: sc.Frame("f", pts, cells, **{**SECTION, "J": None}), "frame 'f'.J",
            "needed")
    _raises(lambda: sc.Frame("f", pts, cells, **{**SECTION, "Iy": -1.0}), "frame 'f'.Iy",
            "positive")
    _raises(lambda: sc.Frame("f", pts, cells, orientation=(1, 0), **SECTION),
            "frame 'f'.orientation", "finite vector")
    _raises(lambda: sc.Frame("f", pts[:, :2] + [[0, 0], [1, 0]], cells, E, A, IZ, J=J),
            "frame 'f'.J", "space frames")


def test_moments_and_rotations_on_nodes_without_rotation_are_refused():
    """A moment on a solid's node in a model with a space frame; a rotation support on a 2D
    model; a 3D spring in a 2D model: each a ModelError naming the item."""
    block = sc.box("block", (0, 0, 0), (1, 1, 1), (1, 1, 1), sc.Material(3e10, 0.2))
    beam = sc.Frame.line("beam", (0, 0, 1), (2, 0, 1), 2, **SECTION)
    m = sc.Model(bodies=(block, beam))
    m = m.add(sc.Support("bed", m.select("block", boundary="bottom"), "xyz"),
              sc.LoadPattern("P", [sc.NodalLoad(m.select("block", boundary="top"), mx=1.0)]),
              sc.Segment("P", 1.0))
    _raises(lambda: assemble(m), "load pattern 'P' load 0.mx", "without rotation")
    flat = sc.Frame.line("flat", (0, 0), (2, 0), 2, E=E, A=A, I=IZ)
    m2 = sc.Model(bodies=(flat,)).add(sc.Support("s", sc.NodeSet("flat", [0]), "xyrx"))
    _raises(lambda: assemble(m2), "support 's'.dofs", "'rx'")
    m3 = sc.Model(bodies=(flat,)).add(sc.Support("s", sc.NodeSet("flat", [0]), "xyrz"),
                                      sc.Spring("k", sc.NodeSet("flat", [2]), kz=1.0))
    _raises(lambda: assemble(m3), "spring 'k'", "2D")


def test_prescribed_twist_gives_the_torque_of_saint_venant():
    """A prescribed rotation rx = φ at the tip of a clamped bar (PrescribedDisplacement on a
    rotation): a linear twist, φ/2 at mid-length, and the clamp's torque −G J φ / L (1e-9)."""
    L, phi = 2.0, 1.0e-3
    m = _cantilever((0, 0, 0), (L, 0, 0), n=2)
    m = m.add(sc.LoadPattern("twist", [sc.PrescribedDisplacement(sc.NodeSet("beam", [2]), "rx",
                                                                 phi)]),
              sc.Segment("twist", 1.0))
    res, dofs = _solve(m)
    assert abs(_node(res, dofs, 1)[3] - phi / 2) <= 1e-9 * phi
    assert abs(res.reaction("clamp", "rx")[-1] + G * J * phi / L) <= 1e-9 * G * J * phi / L
