"""Discrete models: a structure given by its matrices (stiffness, contact rows, loads).

References:

* the two-DOF frictional contact of a point on a rough floor (Klarbring's textbook system: a
  mass point held by springs whose stiffness couples the tangential and normal motions), solved
  by hand: slip at λ = f P, lift-off at λ = −P k11 / k12, the slip-back on unloading, the
  first closing of a gap, the slip of a compliant layer (a 2 × 2 solve by Cramer's rule);
* the assembled K, B and load vectors of continuum models (``sc.assemble``) entered as a
  discrete model reproduce the continuum runs: the same events and load factors to 1e-12;
* every state satisfies equilibrium K u = f + Aᵀ(−N) − Tᵀ Q on the free DOFs and the
  kinematics u_n = −A u − g, u_τ = T u (checked independently here, not by the solver's own
  residual).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from typer.testing import CliRunner

import stepcontact as sc
import verification_models as vm
from stepcontact.cli import app
from stepcontact.enums import ContactState, Status, Transition
from stepcontact.model import PrescribedDisplacement

K11, K12, K22 = 2.0e3, -1.0e3, 2.0e3  # N/m: pushing along x lifts the point (k12 < 0)
F, P = 0.5, 100.0  # friction coefficient, press force (N)


def two_dof(*program, friction=F, k=(K11, K12, K22), **kw) -> sc.DiscreteModel:
    """A point (u_x, u_y; u_y > 0 lifts it) on a rough floor: patterns 'press' (F_y = −1 N)
    and 'push' (F_x = +1 N) per unit λ."""
    k11, k12, k22 = k
    return sc.DiscreteModel(
        K=[[k11, k12], [k12, k22]], normal_rows=[[0.0, 1.0]], tangent_rows=[[1.0, 0.0]],
        loads={"press": {"uy": -1.0}, "push": {"ux": 1.0}}, friction=friction,
        dof_names=("ux", "uy"), name="point", program=program, **kw)


def check_states(dm: sc.DiscreteModel, res: sc.StaticResult, tol: float = 1e-9) -> None:
    """Equilibrium and kinematics at every state, from the matrices of ``dm``."""
    U = res.displacements()
    A, T = dm.normal_rows.toarray(), dm.tangent_rows.toarray()
    K = dm.K.toarray()
    free = ~dm.fixed
    for p in dm.prescribed:
        free[[dm.dof(k) for k in dm.prescribed[p]]] = False
    wscale = max(np.abs(U).max(), np.abs(dm.gaps).max(initial=0), 1e-300)
    for i in range(res.n_states):
        u = U[i]
        f = sum(c * dm.loads.get(n, 0.0) for n, c in
                zip(res.pattern_names, res.factors[i], strict=True))
        r = K @ u - f - A.T @ (-res.N[i]) + T.T @ res.Q[i]
        scale = max(np.abs(K @ u).max(), np.abs(f).max(initial=0), 1e-300)
        assert np.abs(r[free]).max(initial=0) <= tol * scale, i
        assert np.allclose(res.un[i], -A @ u - dm.gaps, rtol=0, atol=tol * wscale)
        assert np.allclose(res.ut[i], T @ u, rtol=0, atol=tol * wscale)
        for p_name, spec in dm.prescribed.items():
            c = res.factors[i, res.pattern_names.index(p_name)]
            for k, v in spec.items():
                assert u[dm.dof(k)] == pytest.approx(c * v, abs=1e-15)
    assert np.max(res.residual) <= tol


def lam_of(res, transition) -> list[float]:
    return [e.lam for e in res.events if e.transition == transition]


# --------------------------------------------------------------------------------------------
# the two-DOF textbook system, by hand
# --------------------------------------------------------------------------------------------
def test_two_dof_slip_then_lift_off_closed_form():
    dm = two_dof(sc.Segment("press", P), sc.Segment("push", 300.0))
    res = sc.solve_static(dm)
    assert res.status == Status.COMPLETED
    lam_slip = F * P
    lam_lift = -P * K11 / K12  # N = −P − k12 (λ − fP)/(k11 + f k12) = 0
    assert lam_slip == 50.0 and lam_lift == 200.0
    assert [(e.transition, e.segment) for e in res.events] == [
        (Transition.SLIP_POS, 1), (Transition.OPENED, 1)]
    assert res.multipliers[1].first_slip == pytest.approx(lam_slip, rel=1e-12)
    assert res.multipliers[1].first_opening == pytest.approx(lam_lift, rel=1e-12)
    # stick: the point does not move, the floor carries everything
    at = res.interpolate(30.0, segment=1)
    assert at["N"][0] == pytest.approx(-P, rel=1e-12)
    assert at["Q"][0] == pytest.approx(30.0, rel=1e-12)
    # slip: u_y = 0, Q = −f N, k11 u_x = λ − Q, k12 u_x = −P − N
    lam = 120.0
    ux = (lam - F * P) / (K11 + F * K12)
    at = res.interpolate(lam, segment=1)
    assert at["N"][0] == pytest.approx(-P - K12 * ux, rel=1e-12)
    assert at["Q"][0] == pytest.approx(F * (P + K12 * ux), rel=1e-12)
    assert at["ut"][0] == pytest.approx(ux, rel=1e-12)
    assert at["state"][0] == int(ContactState.SLIP_POS)
    # open: the free solution u = K⁻¹ (λ, −P), lifted off the floor
    u_end = np.linalg.solve([[K11, K12], [K12, K22]], [300.0, -P])
    assert np.allclose(res.displacement(res.n_states - 1), u_end, rtol=1e-12)
    assert res.un[-1, 0] == pytest.approx(-u_end[1], rel=1e-12) and u_end[1] > 0
    check_states(dm, res)


def test_two_dof_unloading_sticks_then_slips_back():
    lam_end = 150.0
    dm = two_dof(sc.Segment("press", P), sc.Segment("push", lam_end), sc.Segment("push", 0.0))
    res = sc.solve_static(dm, store_fields="all")
    ux_s = (lam_end - F * P) / (K11 + F * K12)  # the slip reached on loading
    # sticking on the way back: u frozen, N = −P − k12 u_s, Q = λ − k11 u_s; slip− at Q = f N
    lam_back = K11 * ux_s - F * P - F * K12 * ux_s
    events = [(e.transition, e.segment) for e in res.events]
    assert events == [(Transition.SLIP_POS, 1), (Transition.STUCK, 2),
                      (Transition.SLIP_NEG, 2)]
    assert lam_of(res, Transition.STUCK) == pytest.approx([lam_end], rel=1e-12)
    assert lam_of(res, Transition.SLIP_NEG) == pytest.approx([lam_back], rel=1e-12)
    # slipping back: Q = f N, k11 u_x = λ − Q, N = −P − k12 u_x
    ux_0 = (0.0 + F * P) / (K11 - F * K12)
    assert res.ut[-1, 0] == pytest.approx(ux_0, rel=1e-12)
    assert res.N[-1, 0] == pytest.approx(-P - K12 * ux_0, rel=1e-12)
    check_states(dm, res)


def test_two_dof_gap_closes_at_the_free_solution():
    g = 0.01
    dm = two_dof(sc.Segment("press", 100.0), sc.Segment("push", 60.0), gaps=g)
    res = sc.solve_static(dm)
    det = K11 * K22 - K12**2
    lam_close = g * det / K11  # u_y = −λ k11 / det = −g
    assert res.multipliers[0].first_closing == pytest.approx(lam_close, rel=1e-12)
    # closed, stick from then on: N carries the rest of the press, P_rest = P − λ_close
    # (u stays at the closing position u_c, so N = −(P − λ_close) + (k12 u_x,c + k22 u_y,c + λc)
    # = λ_close − P in the press segment)
    assert res.N[res.segment == 0][-1][0] == pytest.approx(lam_close - 100.0, rel=1e-12)
    check_states(dm, res)


def test_compliant_layer_slip_by_cramer():
    kn, kt = 5.0e3, 1.5e3
    dm = two_dof(sc.Segment("press", P), sc.Segment("push", 300.0), kn=kn, kt=kt)
    res = sc.solve_static(dm)
    # stick with a layer: (K + diag(kt, kn)) u = (λ, −P); Q = kt u_x, N = kn u_y
    a, b, d = K11 + kt, K12, K22 + kn
    det = a * d - b * b

    def u(lam):
        return np.array([(d * lam + b * P) / det, (-b * lam - a * P) / det])

    # slip+ when Q + f N = 0: kt u_x(λ) + f kn u_y(λ) = 0, linear in λ
    c1 = kt * d / det - F * kn * b / det
    c0 = kt * b * P / det - F * kn * a * P / det
    lam_slip = -c0 / c1
    assert res.multipliers[1].first_slip == pytest.approx(lam_slip, rel=1e-12)
    at = res.interpolate(0.5 * lam_slip, segment=1)
    ux, uy = u(0.5 * lam_slip)
    assert at["Q"][0] == pytest.approx(kt * ux, rel=1e-12)
    assert at["N"][0] == pytest.approx(kn * uy, rel=1e-12)
    assert at["un"][0] == pytest.approx(-uy, rel=1e-12)  # N = −C_n u_n
    check_states(dm, res)


def test_loss_of_equilibrium_names_the_moving_dof():
    """Without a spring along x the point slides away at λ = f P."""
    dm = two_dof(sc.Segment("press", P), sc.Segment("push", 300.0), k=(0.0, 0.0, K22))
    res = sc.solve_static(dm)
    assert res.status == Status.EQUILIBRIUM_LOST
    assert res.multipliers[1].equilibrium_lost == pytest.approx(F * P, rel=1e-12)
    assert "'point' moves along (ux 1)" in res.message
    assert res.mechanism["bodies"][0]["dofs"] == {"ux": 1.0}


def test_mechanism_even_with_every_cfe_stuck_names_dofs():
    dm = sc.DiscreteModel(K=np.diag([1e3, 0.0, 1e3]), normal_rows=[[1.0, 0, 0]],
                          tangent_rows=[[0, 0, 0]], loads={"P": [-1.0, 0, 0]},
                          program=[sc.Segment("P", 1.0)])
    with pytest.raises(sc.ModelError, match=r"DOFs u1 can move freely"):
        sc.solve_static(dm)


# --------------------------------------------------------------------------------------------
# fixed and prescribed DOFs, reactions
# --------------------------------------------------------------------------------------------
def test_fixed_and_prescribed_dofs_and_their_reactions():
    """The point is held along x by a spring k_s to a support DOF 'w' moved by 'drag'."""
    ks = 800.0
    K = np.array([[ks, 0.0, -ks], [0.0, K22, 0.0], [-ks, 0.0, ks]])
    K[1, 1] += 0.0
    dm = sc.DiscreteModel(
        K=sp.csr_matrix(K), normal_rows=[[0, 1, 0]], tangent_rows=[[1, 0, 0]],
        loads={"press": {"uy": -1.0}}, prescribed={"drag": {"w": 1e-3}},
        fixed=[], friction=F, dof_names=("ux", "uy", "w"),
        program=[sc.Segment("press", P), sc.Segment("drag", 200.0)])
    res = sc.solve_static(dm)
    # stick: ux = 0, the spring pulls Q = ks w; slip when ks w = f P
    lam_slip = F * P / (ks * 1e-3)
    assert res.multipliers[1].first_slip == pytest.approx(lam_slip, rel=1e-12)
    assert res.reaction_labels == ("drag (prescribed):w",)
    # the reaction on the dragged DOF: −(spring force) = −ks (w − ux); sliding: f P
    assert res.reaction("drag", "w")[-1] == pytest.approx(F * P, rel=1e-12)
    check_states(dm, res)
    # the same with the support DOF fixed and the spring pulled by a force instead
    dm2 = dm.replace(prescribed={}, fixed=["w"], loads={"press": {"uy": -1.0}},
                     program=[sc.Segment("press", P)])
    res2 = sc.solve_static(dm2)
    assert res2.reaction_labels == ("fixed:w",)
    assert res2.reaction("fixed", "w")[-1] == pytest.approx(0.0, abs=1e-12)


# --------------------------------------------------------------------------------------------
# the matrices of a continuum model reproduce its run exactly
# --------------------------------------------------------------------------------------------
def discrete_of(model: sc.Model) -> tuple[sc.DiscreteModel, sc.System]:
    """The assembled K, B, loads, supports and CFE data of ``model`` as a discrete model."""
    system = sc.assemble(model)
    m = system.m
    cfe = system.cfe
    presc = np.zeros(system.ndof, bool)
    prescribed = {}
    for name, lv in system.loads.items():
        presc[lv.dofs] = True
        if len(lv.dofs):
            prescribed[name] = {int(d): float(lv.u[d]) for d in lv.dofs}
    dm = sc.DiscreteModel(
        K=system.K, normal_rows=-system.B[m:], tangent_rows=system.B[:m],
        loads={name: lv.f for name, lv in system.loads.items()},
        prescribed=prescribed, fixed=np.flatnonzero(system.fixed & ~presc).tolist(),
        gaps=-system.w0[m:], friction=cfe.friction, kn=cfe.kn, kt=cfe.kt,
        names=[cfe.names[i] for i in cfe.interface], program=model.program, name=model.name)
    return dm, system


def dragged_block() -> sc.Model:
    m = vm.block_on_base(friction=0.4, w=2.0, h=0.5, nx=4, ny=1, x_support=False)
    top = m.select("block", y=0.5)
    return m.add(
        sc.LoadPattern("weight", [sc.BodyForce((0.0, -9.81), bodies=("block",))]),
        sc.LoadPattern("drag", [PrescribedDisplacement(top, "x", 1e-5)]),
        sc.Segment("weight", 1.0), sc.Segment("drag", 3.0), sc.Segment("drag", -1.0))


@pytest.mark.parametrize("make", [
    lambda: vm.spring_held_block(0.5),
    lambda: vm.uplift_slab("body_force", 60.0),
    dragged_block,
], ids=["spring-held-block", "uplift-slab", "dragged-block"])
def test_matrices_of_a_continuum_model_reproduce_its_run(make):
    model = make()
    dm, system = discrete_of(model)
    ref = sc.solve_static(model)
    res = sc.solve_static(dm)
    assert res.status == ref.status
    assert len(res.events) == len(ref.events) > 0
    for a, b in zip(res.events, ref.events, strict=True):
        assert (a.cfe, a.transition, a.segment, a.local) == (b.cfe, b.transition, b.segment,
                                                             b.local)
        assert a.lam == pytest.approx(b.lam, rel=1e-12, abs=1e-12)
    for a, b in zip(res.multipliers, ref.multipliers, strict=True):
        for key in ("first_slip", "first_opening", "first_closing", "equilibrium_lost"):
            va, vb = getattr(a, key), getattr(b, key)
            assert (va is None) == (vb is None)
            if va is not None:
                assert va == pytest.approx(vb, rel=1e-12, abs=1e-12)
    assert np.allclose(res.lam, ref.lam, rtol=1e-12, atol=1e-12)
    scale = np.abs(ref.N).max()
    assert np.allclose(res.N, ref.N, rtol=0, atol=1e-10 * scale)
    assert np.allclose(res.Q, ref.Q, rtol=0, atol=1e-10 * scale)
    assert np.array_equal(res.state, ref.state)
    assert res.interface_names == ref.interface_names
    # reactions: the per-DOF reactions of the discrete run sum to the supports' resultants
    rows = system.reaction_rows.toarray()
    for j, label in enumerate(ref.reaction_labels):
        dofs = np.flatnonzero(rows[j])
        cols = [res.reaction_labels.index(lb) for lb in res.reaction_labels
                if int(dm.dof(lb.rsplit(":", 1)[1])) in dofs]
        R = res.reactions[:, cols].sum(axis=1)
        assert np.allclose(R, ref.reactions[:, j], rtol=1e-9, atol=1e-9 * scale), label
    check_states(dm, res)


# --------------------------------------------------------------------------------------------
# results: file round trip, info, plots that need a mesh
# --------------------------------------------------------------------------------------------
def test_result_file_round_trip_and_info(tmp_path):
    dm = two_dof(sc.Segment("press", P), sc.Segment("push", 300.0))
    res = sc.solve_static(dm)
    res.save(tmp_path / "point.nc")
    back = sc.load_result(tmp_path / "point.nc")
    assert back.status == Status.COMPLETED
    assert [(e.transition, e.lam) for e in back.events] == [
        (e.transition, e.lam) for e in res.events]
    assert np.array_equal(back.N, res.N) and np.array_equal(back.state, res.state)
    assert list(back.geometry["dof_names"]) == ["ux", "uy"]
    assert back.summary() == res.summary()
    assert "first slip λ=50" in back.summary()
    # the fields of any state, recomputed from the model
    back.recover_fields(dm)
    assert np.allclose(back.displacements(), res.displacements(), rtol=0, atol=1e-15)
    out = CliRunner().invoke(app, ["info", str(tmp_path / "point.nc")])
    assert out.exit_code == 0, out.output
    assert "slip+" in out.output and "DOFs" in out.output
    out = CliRunner().invoke(app, ["info", "--json", str(tmp_path / "point.nc")])
    assert out.exit_code == 0, out.output
    assert '"dofs": 2' in out.output


def test_mesh_results_give_clean_errors():
    import matplotlib

    matplotlib.use("Agg")
    res = sc.solve_static(two_dof(sc.Segment("press", P), sc.Segment("push", 100.0)))
    with pytest.raises(ValueError, match="no mesh geometry"):
        sc.plot_deformed(res)
    with pytest.raises(ValueError, match="discrete model has no nodes"):
        res.node_history(0)
    with pytest.raises(ValueError, match="no geometry"):
        sc.export_vtu(res, "unused.vtu")
    sc.plot_interfaces(res)  # the diagrams of N and Q by CFE number work
    sc.plot_load_path(res)


# --------------------------------------------------------------------------------------------
# input errors name the field
# --------------------------------------------------------------------------------------------
BASE = dict(K=[[K11, K12], [K12, K22]], normal_rows=[[0.0, 1.0]], tangent_rows=[[1.0, 0.0]],
            loads={"press": [0.0, -1.0]}, friction=F)


@pytest.mark.parametrize(("change", "item", "text"), [
    (dict(K=[[1.0, 2.0], [3.0, 4.0]]), "K", "not symmetric"),
    (dict(K=[[1.0, np.nan], [np.nan, 1.0]]), "K", "NaN or inf"),
    (dict(K=[[1.0, 0.0, 0.0]]), "K", "square"),
    (dict(K=[[1.0, 2.0], [2.0, 1.0]]), "K", "positive semi-definite"),
    (dict(normal_rows=[[0.0, 0.0]]), "normal_rows[0]", "all zero"),
    (dict(normal_rows=[[1.0, 0.0, 0.0]]), "normal_rows", "shape"),
    (dict(tangent_rows=[[1.0, 0.0], [0.0, 1.0]]), "tangent_rows", "shape"),
    (dict(tangent_rows=[[0.0, 0.0]]), "tangent_rows[0]", "friction"),
    (dict(friction=-0.1), "friction[0]", "≥ 0"),
    (dict(gaps=[0.0, 1.0]), "gaps", "one per CFE"),
    (dict(gaps=np.inf), "gaps[0]", "finite"),
    (dict(kn=0.0), "kn[0]", "> 0"),
    (dict(loads={"press": [1.0, 2.0, 3.0]}), "loads['press']", "2 entries"),
    (dict(loads={"press": [np.nan, 2.0]}), "loads['press']", "NaN"),
    (dict(loads={"press": {"q": 1.0}}), "loads['press']['q']", "no DOF named 'q'"),
    (dict(fixed=[7]), "fixed[0]", "does not exist"),
    (dict(prescribed={"move": {0: 1.0}}, fixed=[0]), "prescribed['move']", "also in 'fixed'"),
    (dict(names=["a", "b"]), "names", "one per CFE"),
    (dict(dof_names=["a", "a"]), "dof_names", "duplicate"),
    (dict(program=[sc.Segment("nope", 1.0)]), "load pattern 'nope'", "no such pattern"),
])
def test_errors_name_the_field(change, item, text):
    with pytest.raises(sc.ModelError, match=text) as info:
        sc.DiscreteModel(**(BASE | change))
    assert info.value.item == item


def test_condensation_is_shared_by_runs_that_differ_in_friction():
    dm = two_dof(sc.Segment("press", P), sc.Segment("push", 300.0))
    cond = sc.condense(dm)
    for f in (0.2, 0.5):
        res = sc.solve_static(dm.replace(friction=f), condensation=cond)
        assert res.counters["condensation_reused"] == 1
        assert res.multipliers[1].first_slip == pytest.approx(f * P, rel=1e-12)
        assert res.multipliers[1].first_opening == pytest.approx(-P * K11 / K12, rel=1e-12)
