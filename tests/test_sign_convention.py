"""One sign convention for tangents: edge loads and CFEs turn the normal clockwise.

An edge with outward unit normal n has the tangent t = (n_y, −n_x), the rule of the CFE
tangent (n from S− to S+).  References are closed form: the resultants of constant tractions on
the faces of a rectangle, the total of an :class:`EdgeForce`, and a block pushed along its top
face that slides at λ = f·W/T.
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from numpy.testing import assert_allclose

import stepcontact as sc
import verification_models as vm
from stepcontact.contact.laws import SLIP_POS
from stepcontact.fem.assembly import assemble, load_resultant, load_resultants
from stepcontact.io.modelfile import model_from_dict

X0, Y0, X1, Y1 = 1.0, 0.5, 4.0, 2.5  # a rectangle away from the origin: moments are not trivial
TH = 0.4  # thickness, m
MAT = sc.Material(1e9, 0.25, 2000.0)


def rect_model(element: str = "quad4", grading=(1.0, 1.0), **patterns) -> sc.Model:
    """The rectangle [X0, X1] × [Y0, Y1], fixed at its bottom, with one pattern per keyword
    (name -> list of loads built from the face node sets by a function of the model)."""
    body = sc.rectangle("r", (X0, Y0), (X1, Y1), 6, 4, MAT, element=element, grading=grading)
    m = sc.Model(bodies=[body], plane="stress", thickness=TH)
    m = m.add(sc.Support("bed", m.select("r", y=Y0, name="bottom")))
    pats = [sc.LoadPattern(name, make(m)) for name, make in patterns.items()]
    return m.add(*pats, sc.Segment(pats[0].name, 1.0))


def faces(m: sc.Model) -> dict[str, sc.NodeSet]:
    return {"top": m.select("r", y=Y1, name="top"), "bottom": m.select("r", y=Y0),
            "left": m.select("r", x=X0, name="left"), "right": m.select("r", x=X1, name="right")}


def resultants(m: sc.Model) -> dict[str, np.ndarray]:
    return load_resultants(assemble(m))


# --------------------------------------------------------------------------------------------
# edge tangent of each face
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("element", ["quad4", "tri6", "quad8"])
def test_tangential_on_a_top_edge_is_the_x_traction(element):
    """+1 Pa tangential on a top face (n = +y, t = +x) is the traction (1, 0): the same load
    vector, and a positive F_x = 1 Pa × width × thickness."""
    p = 1.0
    m = rect_model(element,
                   t=lambda m: [sc.EdgeLoad(faces(m)["top"], tangential=p)],
                   q=lambda m: [sc.EdgeLoad(faces(m)["top"], traction=(p, 0.0))])
    sysm = assemble(m)
    f_t, f_q = sysm.loads["t"].f, sysm.loads["q"].f
    assert_allclose(f_t, f_q, rtol=0, atol=1e-14 * np.abs(f_q).max())
    R = load_resultant(m, sysm.dofs, f_t)
    assert R[0] > 0
    assert_allclose(R, [p * (X1 - X0) * TH, 0.0, -Y1 * p * (X1 - X0) * TH], rtol=1e-12,
                    atol=1e-12)


@pytest.mark.parametrize("element", ["quad4", "tri6"])
def test_tangential_on_each_face_of_a_rectangle(element):
    """Constant tangential traction p on each face, t = (n_y, −n_x): top +x, bottom −x,
    right −y, left +y.  Resultants (F_x, F_y, M_z about the origin) in closed form; on the
    whole boundary the forces cancel and M_z = −2 p A · thickness (t runs clockwise)."""
    p = 3.0e3
    w, h = X1 - X0, Y1 - Y0
    m = rect_model(element, **{
        name: (lambda m, name=name: [sc.EdgeLoad(faces(m)[name], tangential=p)])
        for name in ("top", "bottom", "left", "right")
    }, ring=lambda m: [sc.EdgeLoad(m.select("r"), tangential=p)])
    R = resultants(m)
    expected = {
        "top": [p * w * TH, 0.0, -Y1 * p * w * TH],
        "bottom": [-p * w * TH, 0.0, Y0 * p * w * TH],
        "right": [0.0, -p * h * TH, -X1 * p * h * TH],
        "left": [0.0, p * h * TH, X0 * p * h * TH],
        "ring": [0.0, 0.0, -2.0 * p * w * h * TH],
    }
    scale = p * max(w, h) * TH * max(X1, Y1)
    for name, ref in expected.items():
        assert_allclose(R[name], ref, rtol=0, atol=1e-12 * scale, err_msg=name)


def test_normal_pressure_and_traction_components():
    """normal > 0 pushes into the body; the traction's components are global x, y on any face;
    functions of (x, y) are integrated exactly (a linear traction on linear edges)."""
    p = 2.0
    h = Y1 - Y0
    m = rect_model(
        "quad8",
        n=lambda m: [sc.EdgeLoad(faces(m)["right"], normal=p)],
        q=lambda m: [sc.EdgeLoad(faces(m)["left"], traction=(0.0, p))],
        lin=lambda m: [sc.EdgeLoad(faces(m)["left"], traction=(0.0, lambda x, y: p * y))],
    )
    R = resultants(m)
    assert_allclose(R["n"], [-p * h * TH, 0.0, (Y0 + Y1) / 2 * p * h * TH], atol=1e-12)
    assert_allclose(R["q"], [0.0, p * h * TH, X0 * p * h * TH], atol=1e-12)
    fy = p * (Y1**2 - Y0**2) / 2 * TH
    assert_allclose(R["lin"], [0.0, fy, X0 * fy], rtol=1e-12, atol=1e-12)


def test_the_cfe_tangent_is_the_edge_tangent_of_s_minus():
    """For a joint, the CFE (n, t) is the outward normal and the edge tangent of the S− face:
    base top n = +y, t = +x; a tangential load on the base's top acts along the CFE's t."""
    m = vm.block_on_base(friction=0.5)
    m = m.add(sc.LoadPattern("shear", [sc.EdgeLoad(m.select("base", y=0.0), tangential=1.0)]),
              sc.Segment("shear", 1.0))
    sysm = assemble(m)
    assert_allclose(sysm.cfe.normal, np.tile([0.0, 1.0], (sysm.m, 1)), atol=1e-15)
    assert_allclose(sysm.cfe.tangent, np.tile([1.0, 0.0], (sysm.m, 1)), atol=1e-15)
    Fx = load_resultants(sysm)["shear"][0]
    assert Fx == pytest.approx(1.5 * 2.0, rel=1e-12)  # base top is 1.5 w = 3 m long


# --------------------------------------------------------------------------------------------
# total forces along an edge
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("element", ["quad4", "tri6", "quad8"])
def test_edge_force_total_is_exact_and_uniform(element):
    """EdgeForce(F) on a graded face: the nodal forces sum to F exactly, and they are the
    consistent forces of the uniform traction F / (L · thickness)."""
    F = (1.234e4, -5.678e3)
    L = Y1 - Y0
    m = rect_model(element, grading=(1.0, 1.7),
                   F=lambda m: [sc.EdgeForce(faces(m)["right"], *F)],
                   q=lambda m: [sc.EdgeLoad(faces(m)["right"],
                                            traction=(F[0] / (L * TH), F[1] / (L * TH)))],
                   nodal=lambda m: [sc.NodalLoad(faces(m)["right"], *F)])
    sysm = assemble(m)
    f = sysm.loads["F"].f
    R = load_resultants(sysm)
    assert_allclose(R["F"][:2], F, rtol=1e-14)
    assert_allclose(f, sysm.loads["q"].f, rtol=0, atol=1e-12 * np.abs(f).max())
    # non-uniform node spacing: the nodal forces are not equal (tributary lengths differ)
    on = f[sysm.dofs.of[m.global_nodes(faces(m)["right"]), 0]]
    assert np.ptp(on) > 1e-3 * np.abs(on).max()
    # NodalLoad puts its value on every node: n times the force in all
    n = len(faces(m)["right"])
    assert_allclose(R["nodal"][:2], np.multiply(F, n), rtol=1e-14)


def test_edge_force_on_a_frame_is_an_error():
    fr = sc.Frame.line("beam", (0, 0), (2, 0), 4, E=2e11, A=1e-2, I=1e-4)
    m = sc.Model(bodies=[fr]).add(
        sc.Support("ends", sc.NodeSet("beam", [0, 4]), "xyrz"),
        sc.LoadPattern("p", [sc.EdgeForce(sc.NodeSet("beam", [1, 2, 3]), fy=1.0)]),
        sc.Segment("p", 1.0))
    with pytest.raises(sc.ModelError, match="continuum body"):
        assemble(m)


def test_traction_must_have_two_components():
    with pytest.raises(sc.ModelError, match="traction"):
        sc.EdgeLoad(sc.NodeSet("r", [0, 1]), traction=1.0)
    with pytest.raises(sc.ModelError, match="traction"):
        sc.EdgeLoad(sc.NodeSet("r", [0, 1]), traction=(1.0, 2.0, 3.0))


RAMP = f"{{ from = [{X0}, {Y1}, 0.0], to = [{X1}, {Y1}, 2.0] }}"  # ty: 0 to 2 Pa
MODEL_FILE = f"""
[model]
plane = "stress"
thickness = {TH}
[materials.m]
E = 1e9
nu = 0.25
[[bodies]]
name = "r"
kind = "rectangle"
corner0 = [{X0}, {Y0}]
corner1 = [{X1}, {Y1}]
nx = 6
ny = 4
material = "m"
[node_sets.top]
body = "r"
y = {Y1}
[node_sets.bottom]
body = "r"
y = {Y0}
[[supports]]
name = "bed"
nodes = "bottom"
[patterns.t]
loads = [{{ type = "pressure", nodes = "top", tangential = 1.0 }}]
[patterns.q]
loads = [{{ type = "pressure", nodes = "top", traction = [1.0, {RAMP}] }}]
[patterns.F]
loads = [{{ type = "edge_force", nodes = "top", fx = 10.0, fy = -4.0 }}]
[[program]]
pattern = "t"
end = 1.0
"""


def test_model_file_traction_and_edge_force():
    """``pressure`` with ``traction = [tx, ty]`` and ``edge_force`` in a model file give the
    Python loads."""
    m = model_from_dict(tomllib.loads(MODEL_FILE))
    (q,) = m.pattern("q").loads
    assert isinstance(q, sc.EdgeLoad) and q.traction[0] == 1.0 and callable(q.traction[1])
    (F,) = m.pattern("F").loads
    assert isinstance(F, sc.EdgeForce) and (F.fx, F.fy) == (10.0, -4.0)
    R = resultants(m)
    w = X1 - X0
    assert_allclose(R["t"], [w * TH, 0.0, -Y1 * w * TH], rtol=1e-12, atol=1e-12)
    assert_allclose(R["q"][:2], [w * TH, 1.0 * w * TH], rtol=1e-12)
    assert_allclose(R["F"][:2], [10.0, -4.0], rtol=1e-14)


# --------------------------------------------------------------------------------------------
# a block pushed along its top face
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("how", ["tangential", "traction", "edge_force"])
def test_block_pushed_along_its_top_slides_at_f_w_over_t(how):
    """Self-weight W, then a +x shear on the block's top face (T = 1 Pa × width per unit λ,
    given as tangential = +1, traction = (1, 0) or a total edge force): the block slides along
    +x (every CFE slip+, Q ≥ 0) at λ = f·W/T."""
    f, w, h = 0.4, 2.0, 0.5
    m = vm.block_on_base(friction=f, w=w, h=h, nx=4, ny=2)
    top = m.select("block", y=h)
    load = {"tangential": sc.EdgeLoad(top, tangential=1.0),
            "traction": sc.EdgeLoad(top, traction=(1.0, 0.0)),
            "edge_force": sc.EdgeForce(top, fx=w * 1.0)}[how]
    m = m.add(sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
              sc.LoadPattern("push", [load]),
              sc.Segment("weight", 1.0), sc.Segment("push", 1e6))
    res = sc.solve_static(m)
    W = vm.SOFT.density * vm.G * w * h
    T = 1.0 * w
    assert res.status == sc.Status.EQUILIBRIUM_LOST, res.message
    assert res.multipliers[-1].equilibrium_lost == pytest.approx(f * W / T, rel=1e-9)
    assert_allclose(res.load_resultant("push"), [T, 0.0, -h * T], rtol=1e-12, atol=1e-12)
    last = res.state[-1]
    closed = last != 0
    assert np.all(last[closed] == SLIP_POS)
    assert res.Q[-1].sum() == pytest.approx(f * W, rel=1e-9)
    ux = res.node_history(point=(w / 2, h), quantity="ux")
    assert ux[-1] > 0


def test_summary_prints_the_resultants():
    m = vm.block_on_base(friction=0.5)
    m = m.add(sc.LoadPattern("weight", [sc.BodyForce(bodies=("block",))]),
              sc.LoadPattern("push", [sc.EdgeLoad(m.select("block", y=0.5), tangential=1e3)]),
              sc.Segment("weight", 1.0), sc.Segment("push", 1.0))
    res = sc.solve_static(m)
    text = res.summary()
    assert "load resultants per unit λ" in text
    assert "'push': Fx = 2000, Fy = 0, Mz = -1000" in text
    from stepcontact.cli import result_summary

    js = result_summary(res)["load_resultants"]
    assert js["push"] == pytest.approx({"Fx": 2000.0, "Fy": 0.0, "Mz": -1000.0}, abs=1e-9)
    assert js["weight"]["Fy"] == pytest.approx(-vm.SOFT.density * vm.G * 2.0 * 0.5, rel=1e-12)


def test_cli_run_prints_the_resultants(tmp_path):
    """``stepcontact run`` prints each pattern's resultant; ``--json`` has them as numbers."""
    import json

    from typer.testing import CliRunner

    from stepcontact.cli import app

    (tmp_path / "rect.toml").write_text(MODEL_FILE, encoding="utf-8")
    runner = CliRunner()
    args = ["run", str(tmp_path / "rect.toml"), "-o", str(tmp_path / "r.nc"), "--no-plot"]
    out = runner.invoke(app, [*args, "--quiet"])
    assert out.exit_code == 0, out.output
    w = X1 - X0
    assert f"'t': Fx = {w * TH:.6g}, Fy = 0, Mz = {-Y1 * w * TH:.6g}" in out.output
    assert "'F': Fx = 10, Fy = -4" in out.output
    js = runner.invoke(app, [*args, "--quiet", "--json"])
    assert js.exit_code == 0, js.output
    R = json.loads(js.stdout)["load_resultants"]
    assert R["t"]["Fx"] == pytest.approx(w * TH, rel=1e-12)
    assert R["t"]["Mz"] == pytest.approx(-Y1 * w * TH, rel=1e-12)
