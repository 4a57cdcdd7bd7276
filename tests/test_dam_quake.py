"""The earthquake record in the dam study (issue 29 §1 and §3, stepcontact.study.dam_quake).

A stiff dam (E = 3e12 Pa) on a rigid frictional base (f = 0.3, no cohesion), the reservoir at
3 m on a vertical upstream face with full uplift, shaken by a pulse written here in PEER's
.AT2 form, samples every δ = 2 ms: 0 at t = 0, A = 0.5 g from δ to t₀ = 0.2 s, 0 from
t₀ + δ (a trapezoid whose impulse is A t₀), read with polarity −1 (the ground accelerates
upstream: the dam slides downstream relative to it).

References derived here:

* the yield acceleration by hand: f (W − U) − H = k (W + (7/12) γ_w h²) (rigid base, the
  Westergaard force of the pseudo-static run equal to the inertia of the added mass);
* Newmark's rigid block under the trapezoid, in closed form: it starts to slide at
  t₁ = δ a_y/A, stops at t_s = t₁ + (A t₀ − A t₁²/(2δ))/a_y and slides
  d = a_y (t_s² − t₁²)/2 − ∫_{t₁}^{t₀+δ} t a(t) dt; for δ → 0 Newmark's V²/(2 a_y)(1 − a_y/A)
  (checked to O(δ/t₀));
* the post-earthquake sliding factor by hand statics at the slid state: f (W − U)/H.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

import stepcontact as sc
from cli_checks import assert_one_line_error
from figure_checks import assert_readable
from stepcontact.cli import app
from stepcontact.errors import ModelError
from stepcontact.study.dam import DamSection
from stepcontact.study.dam_quake import QuakeRecord, plot_quake
from stepcontact.study.dam_report import write_report
from stepcontact.study.dam_study import run_dam

G, GAMMA_W, G_REC = 9.81, 9810.0, 9.80665  # model's g, N/m³, the records' g
F, A_G, T0, DELTA = 0.3, 0.5, 0.2, 0.002  # friction, pulse (g), its length (s), sampling (s)
H, BC, ND, LEVEL, RHO = 6.0, 6.0, 1.0, 3.0, 2400.0  # m, m, H:V, m, kg/m³
B = BC + ND * H
DT = DELTA / 4  # the run's time step, a whole fraction of the record's
runner = CliRunner()


def write_at2(path, values, dt: float) -> None:
    """A record in PEER's .AT2 form (g), five values a line."""
    with open(path, "w") as fh:
        fh.write("PEER NGA STRONG MOTION DATABASE RECORD\nSYNTHETIC PULSE\n"
                 "ACCELERATION TIME SERIES IN UNITS OF G\n"
                 f"NPTS= {len(values)}, DT= {dt:.4f} SEC\n")
        for i in range(0, len(values), 5):
            fh.write("".join(f"{x:15.7E}" for x in values[i:i + 5]) + "\n")


def pulse_values(length: float = 0.8) -> np.ndarray:
    n = round(T0 / DELTA)
    a = np.zeros(round(length / DELTA) + 1)
    a[1:n + 1] = A_G
    return a


def hand_yield() -> tuple[float, float, float, float]:
    """(k_y, W, U, H_w) of the stiff dam by hand (per metre)."""
    W = RHO * G * (B + BC) / 2 * H
    U = GAMMA_W * LEVEL * B / 2
    Hw = GAMMA_W * LEVEL**2 / 2
    P = 7 / 12 * GAMMA_W * LEVEL**2  # Westergaard per unit k_h (γ_w = ρ_w g)
    return (F * (W - U) - Hw) / (W + P), W, U, Hw


def trapezoid_slide(A: float, a_y: float, t0: float, delta: float) -> float:
    """Newmark's rigid block under the trapezoid (module docstring), m."""
    t1 = delta * a_y / A
    impulse = A * t0 - A * t1**2 / (2 * delta)  # ∫_{t1}^{t0+δ} a dt
    ts = t1 + impulse / a_y
    assert ts > t0 + delta  # still sliding when the pulse ends
    ta = (A * (delta**3 - t1**3) / (3 * delta) + A * (t0**2 - delta**2) / 2
          + A * (t0 * delta / 2 + delta**2 / 6))  # ∫_{t1}^{t0+δ} t a(t) dt
    return a_y * (ts**2 - t1**2) / 2 - ta


def stop_time(A: float, a_y: float, t0: float, delta: float) -> float:
    """t_s of the trapezoid's slide (module docstring), s."""
    t1 = delta * a_y / A
    return t1 + (A * t0 - A * t1**2 / (2 * delta)) / a_y


def stiff_section(path, **record) -> DamSection:
    rec = QuakeRecord(path, polarity=-1, damping_ratio=0.0, mass="lumped", **record)
    return DamSection(height=H, crest_width=BC, downstream_slope=ND,
                      concrete=sc.Material(3e12, 0.2, RHO), rock=None,
                      friction_angle=math.degrees(math.atan(F)), normal_level=LEVEL,
                      flood_level=LEVEL, max_level=2 * H, cell=1.0, record=rec)


@pytest.fixture(scope="module")
def stiff(tmp_path_factory):
    path = tmp_path_factory.mktemp("quake") / "pulse.AT2"
    write_at2(path, pulse_values(), DELTA)
    return run_dam(stiff_section(path, dt=DT))


def test_the_closed_form_of_the_trapezoid_tends_to_newmarks_rectangle():
    """The trapezoid's closed form against Newmark's V²/(2 a_y)(1 − a_y/A) for the same
    impulse: they differ by O(δ/t₀) (tolerance 2 δ/t₀), and by less at a smaller δ."""
    A, a_y = A_G * G_REC, 0.2 * G
    rect = (A * T0) ** 2 / (2 * a_y) * (1 - a_y / A)
    errs = [abs(trapezoid_slide(A, a_y, T0, d) / rect - 1) for d in (DELTA, DELTA / 10)]
    assert errs[0] < 2 * DELTA / T0 and errs[1] < errs[0] / 5


def test_the_study_slides_newmarks_distance_on_a_stiff_dam(stiff):
    """The yield acceleration of the study against the hand value (1e-9); the reported
    Newmark estimate against the trapezoid's closed form (1e-9: exact integration of the
    same piecewise-linear record); the dynamic run's mean permanent slip of the base against
    the closed form within Δt/(2 t₀) = 1.25e-3 at Δt = δ/4 = 0.5 ms (the stiff elastic block
    of tests/test_newmark.py: its CFEs start to slip one by one in the first step, first
    order in Δt; measured here 5.1e-4 at 0.5 ms and 4.5e-3 at 2 ms).  The base stays closed
    but for one CFE (0.5 m) that opens for an instant when the slide stops (the friction
    force's jump rocks the elastic dam), within 1 ms of the closed form's stop time."""
    q = stiff.earthquake
    k_hand, *_ = hand_yield()
    assert stiff.yield_acceleration.k_y == pytest.approx(k_hand, rel=1e-9)
    a_y = k_hand * G
    d = trapezoid_slide(A_G * G_REC, a_y, T0, DELTA)
    assert abs(q.newmark_one.newmark.permanent) == pytest.approx(d, rel=1e-9)
    assert q.result.status == sc.Status.COMPLETED and not q.slip.sliding_at_end
    assert q.dt == pytest.approx(DT, rel=1e-9) and q.duration == pytest.approx(0.8)
    err = abs(q.slip.permanent_mean / d - 1)
    assert q.slip.permanent_mean > 0  # downstream
    assert err < DELTA / (2 * T0), err
    assert q.max_open <= 0.5 + 1e-9
    assert abs(q.max_open_time - stop_time(A_G * G_REC, a_y, T0, DELTA)) < 1e-3


def test_the_post_earthquake_state_is_the_hand_statics_at_the_slid_state(stiff):
    """After the shaking the dam rests, slid, under the usual loads: ΣN = −(W − U),
    ΣQ = H_w (to 1e-9 W: the run's equilibrium residual is 1e-9 of the largest force;
    measured 5e-10 W) and the friction-only sliding factor f (W − U)/H_w (its relative error
    then at most 1e-9 W (1/(W − U) + 1/H_w) ≈ 3e-8: tolerance 5e-8); the guideline's
    post-earthquake verdict is evaluated on that state."""
    q = stiff.earthquake
    _, W, U, Hw = hand_yield()
    assert q.post["normal_force"] == pytest.approx(-(W - U), rel=0, abs=1e-9 * W)
    assert q.post["shear_force"] == pytest.approx(Hw, rel=0, abs=1e-9 * W)
    assert q.post["sliding_factor"] == pytest.approx(F * (W - U) / Hw, rel=5e-8)
    assert q.verdict in ("pass", "FAIL")
    assert any(r.check.startswith("sliding factor") for r in q.checks.rows)
    # the slid state: the dam displaced downstream by the slip
    ux = q.result.node_history(point=(0.0, H), quantity="ux", body="dam")
    assert ux[-1] == pytest.approx(q.slip.permanent_mean, rel=1e-3)


def test_the_report_has_the_earthquake_section_and_its_figure(stiff, tmp_path):
    """The report's earthquake section and figure, the summary's figures, and the figure's
    layout (no overlapping texts, the yield acceleration marked on the record)."""
    files = write_report(stiff, tmp_path / "report")
    md = files["markdown"].read_text()
    assert "## Earthquake record" in md and "figures/earthquake.png" in md
    assert "Newmark, one-directional downstream" in md
    assert files["quake"].stat().st_size > 10_000
    summ = json.loads(files["summary"].read_text())
    assert summ["earthquake"]["slip_mean"] == pytest.approx(stiff.earthquake.slip.permanent_mean)
    fig = plot_quake(stiff.earthquake, base_length=B)
    assert_readable(fig)
    ax_a, ax_s, ax_o = fig.axes[:3]
    k = stiff.yield_acceleration.k_y * G / G_REC
    ys = sorted(line.get_ydata()[0] for line in ax_a.get_lines() if line.get_linestyle() == ":")
    assert ys == pytest.approx([-k, k], rel=1e-12)
    assert "slip" in ax_s.get_ylabel() and "open" in ax_o.get_ylabel()


def test_errors_name_the_field(tmp_path):
    path = tmp_path / "p.AT2"
    write_at2(path, pulse_values(0.3), DELTA)
    cases = [({"crack_water": "wet"}, "dam.record.crack_water"),
             ({"polarity": 2}, "dam.record.polarity"),
             ({"damping_ratio": 1.5}, "dam.record.damping_ratio"),
             ({"damping_frequencies": (2.0, 2.0)}, "dam.record.damping_frequencies"),
             ({"target_pga": -0.1}, "dam.record.target_pga"),
             ({"dt": 0.0}, "dam.record.dt")]
    for kw, item in cases:
        with pytest.raises(ModelError) as e:
            QuakeRecord(path, **kw)
        assert e.value.item == item, (kw, str(e.value))
    with pytest.raises(ModelError, match="dam.record.horizontal"):
        QuakeRecord(tmp_path / "missing.AT2")
    with pytest.raises(ModelError, match="dam.record"):
        DamSection(record="quake.AT2")
    with pytest.raises(ModelError, match=r"dam.record.horizontal \(units\)"):
        QuakeRecord(path, units="m/s2").records()


def test_the_staged_model_carries_the_choices(tmp_path):
    """The record run's model: the stages usual → earthquake → post-earthquake, the
    interval with the chosen crack water, the record's time step and length, the Rayleigh
    coefficients of ζ at the two frequencies (a₀ = 2ζω₁ω₂/(ω₁ + ω₂), a₁ = 2ζ/(ω₁ + ω₂) for
    equal ratios, 1e-12), and Westergaard's added mass at the normal level."""
    from stepcontact.study.dam_quake import quake_model

    path = tmp_path / "p.AT2"
    write_at2(path, pulse_values(0.3), DELTA)
    s = stiff_section(path).replace(record=QuakeRecord(
        path, crack_water="none", damping_ratio=0.05, damping_frequencies=(2.0, 10.0)))
    model, *_, interval, (a0, a1, fs) = quake_model(s)
    assert [st.name for st in model.stages] == ["usual", "earthquake", "post-earthquake"]
    assert model.stages[1].dynamics is interval and interval.crack_water == "none"
    assert interval.dt == pytest.approx(DELTA) and interval.duration == pytest.approx(0.3)
    w1, w2 = 2 * np.pi * 2.0, 2 * np.pi * 10.0
    assert a0 == pytest.approx(2 * 0.05 * w1 * w2 / (w1 + w2), rel=1e-12)
    assert a1 == pytest.approx(2 * 0.05 / (w1 + w2), rel=1e-12)
    assert interval.damping == (a0, a1) and fs == (2.0, 10.0)
    masses = model.added_masses
    assert len(masses) == 1 and masses[0].level == LEVEL


def test_the_vertical_component_takes_the_horizontal_factor(tmp_path):
    """A vertical record is read along y and scaled by the horizontal's factor (the target
    PGA is the horizontal's); the polarity flips the horizontal only: hand values of the
    peaks, 1e-12."""
    h, v = tmp_path / "h.AT2", tmp_path / "v.AT2"
    write_at2(h, pulse_values(0.3), DELTA)
    write_at2(v, 0.5 * pulse_values(0.3), DELTA)
    rh, rv = QuakeRecord(h, vertical=v, target_pga=0.25, polarity=-1).records()
    assert rh.axis == "x" and rv.axis == "y"
    assert rh.values.min() == pytest.approx(-0.25 * G_REC, rel=1e-12)
    assert rv.values.max() == pytest.approx(0.5 * 0.25 * G_REC, rel=1e-12)


def test_the_command_line_options(tmp_path):
    """--record without a file, --crack-water without --record, a bad choice: one-line
    errors naming the option or the field."""
    path = tmp_path / "p.AT2"
    write_at2(path, pulse_values(0.3), DELTA)
    out = str(tmp_path / "o")
    r = runner.invoke(app, ["study", "dam", "--quick", "--record", str(tmp_path / "x.AT2"),
                            "-o", out])
    assert_one_line_error(r, "dam.record.horizontal")
    r = runner.invoke(app, ["study", "dam", "--quick", "--crack-water", "full", "-o", out])
    assert_one_line_error(r, "--crack-water")
    r = runner.invoke(app, ["study", "dam", "--quick", "--record", str(path), "--crack-water",
                            "wet", "-o", out])
    assert_one_line_error(r, "dam.record.crack_water")
    r = runner.invoke(app, ["study", "slab", "--record", str(path), "-o", out])
    assert_one_line_error(r, "--record")
    txt = tmp_path / "r.txt"
    txt.write_text("0.0 0.1\n0.01 0.2\n0.02 0.0\n")
    r = runner.invoke(app, ["study", "dam", "--quick", "--record", str(txt), "-o", out])
    assert_one_line_error(r, "format")
    r = runner.invoke(app, ["study", "dam", "--quick", "--record", str(txt), "--record-format",
                            "two_column", "-o", out])
    assert_one_line_error(r, "units")
