"""Stilling-basin hydraulics (stepcontact.study.hydraulics) against independent references.

References: closed forms recomputed here in another way (a cubic's roots, momentum and energy
balances, inverse functions), the rounded VOLGA-REF table of the study notes (slab-hydraulics,
§6: each value within one unit of its last printed digit), and numeric integration of the
load's resultant and moment for the rigid-slab (kern) lift-off.
"""

from __future__ import annotations

import contextlib
import io
import math
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from stepcontact.errors import ModelError
from stepcontact.study import hydraulics as hy

G = 9.81

# VOLGA-REF (h_kr = 3.48 m, phi = 0.95): E0 -> h1, V1, Fr1, h2, V1²/2g, L usbr/russian/
# pavlovsky/chertousov, UL - TW; rounded as printed.
TABLE = {
    20.0: (1.11, 18.3, 5.54, 8.17, 17.0, 49.8, 42.3, 36.0, 39.0, 11.5),
    25.0: (0.99, 20.6, 6.63, 8.77, 21.7, 53.5, 46.7, 39.2, 41.2, 16.0),
    30.0: (0.90, 22.7, 7.66, 9.26, 26.3, 56.5, 50.2, 41.8, 42.8, 20.5),
}


def _digit(printed: float) -> float:
    """One unit of the last printed digit of a table value (0.01 for 0.99, 0.1 for 18.3)."""
    return 0.01 if abs(printed) < 10 and round(printed, 1) != printed else 0.1


def _close(value: float, printed: float, unit: float | None = None) -> bool:
    return abs(value - printed) <= (unit if unit is not None else _digit(printed)) + 1e-12


@pytest.fixture(scope="module")
def jump25() -> hy.Jump:
    return hy.hydraulic_jump(h_kr=3.48, E0=25.0)


# ------------------------------------------------------------------------------- jump ---

def test_unit_discharge():
    q = hy.unit_discharge(3.48)
    assert round(q, 2) == 20.33
    assert math.isclose((q * q / G) ** (1 / 3), 3.48, rel_tol=1e-12)  # critical depth back


@pytest.mark.parametrize("E0", sorted(TABLE))
def test_volga_reference_table(E0):
    h1, V1, Fr1, h2, vh, Lu, Lr, Lp, Lc, drop = TABLE[E0]
    j = hy.hydraulic_jump(h_kr=3.48, E0=E0, phi=0.95)
    # two-decimal table entries: within 0.01; one-decimal entries: within 0.1
    assert _close(j.h1, h1, 0.01)
    assert _close(j.V1, V1, 0.1)
    assert _close(j.Fr1, Fr1, 0.01)
    assert _close(j.h2, h2, 0.01)
    assert _close(j.velocity_head, vh, 0.1)
    assert _close(j.L_j, Lu, 0.1) and j.formula == "usbr"
    assert _close(j.length("russian"), Lr, 0.1)
    assert _close(j.length("pavlovsky"), Lp, 0.1)
    assert _close(j.length("chertousov"), Lc, 0.1)
    # "UL - TW": E0 minus the tailwater energy head h2 + V2²/2g (our reading of the column)
    assert _close(E0 - j.h2 - (j.q / j.h2) ** 2 / (2 * G), drop, 0.1)


def test_contracted_depth_is_smallest_positive_root_of_the_cubic():
    q, E0, phi = 20.33, 25.0, 0.95
    c = q * q / (2 * G * phi * phi)
    roots = np.roots([1.0, -E0, 0.0, c])  # h³ − E0 h² + c = 0
    real = np.sort(roots[np.abs(roots.imag) < 1e-9].real)
    expected = real[real > 0][0]
    assert math.isclose(hy.contracted_depth(q, E0, phi), expected, rel_tol=1e-10)


@settings(max_examples=60, deadline=None)
@given(q=st.floats(0.5, 60.0), excess=st.floats(1.0001, 20.0), phi=st.floats(0.8, 1.0))
def test_contracted_depth_energy_equation(q, excess, phi):
    hc = (q * q / (G * phi * phi)) ** (1 / 3)
    E0 = 1.5 * hc * excess
    h1 = hy.contracted_depth(q, E0, phi)
    assert math.isclose(h1 + q * q / (2 * G * phi * phi * h1 * h1), E0, rel_tol=1e-9)
    assert h1 < hc  # the supercritical root


@settings(max_examples=60, deadline=None)
@given(h1=st.floats(0.05, 5.0), Fr1=st.floats(1.0, 15.0))
def test_belanger_momentum_balance(h1, Fr1):
    q = Fr1 * math.sqrt(G * h1) * h1
    h2 = hy.conjugate_depth(h1, Fr1)
    m1 = q * q / (G * h1) + h1 * h1 / 2
    m2 = q * q / (G * h2) + h2 * h2 / 2
    assert math.isclose(m1, m2, rel_tol=1e-9)
    assert h2 >= h1 * (1 - 1e-12)


def test_jump_length_formulas_recomputed():
    h1, h2, Fr1 = 0.8, 7.0, 7.5
    assert hy.jump_length(h1, h2, Fr1) == pytest.approx(42.7)  # 6.1 × 7
    assert hy.jump_length(h1, h2, Fr1, "russian") == pytest.approx(6 * 6.2)
    assert hy.jump_length(h1, h2, Fr1, "russian", coef=5.0) == pytest.approx(31.0)
    assert hy.jump_length(h1, h2, Fr1, "Pavlovsky") == pytest.approx(2.5 * (13.3 - 0.8))
    assert hy.jump_length(h1, h2, Fr1, "chertousov") == pytest.approx(
        10.3 * 0.8 * math.exp(0.81 * math.log(6.5)))
    t = (math.exp(0.75) - 1.0) / (math.exp(0.75) + 1.0)  # tanh(7.5/20)
    assert hy.jump_length(h1, h2, Fr1, "hager") == pytest.approx(0.8 * (160 * t - 12))


def test_jump_given_length_and_slab_length(jump25):
    j = hy.hydraulic_jump(E0=25.0, length=48.0)
    assert j.L_j == 48.0 and j.formula == "given"
    assert hy.slab_length(jump25, 1.25) == pytest.approx(1.25 * jump25.L_j)
    assert hy.slab_length(jump25) == jump25.L_j
    assert jump25.gamma_w == pytest.approx(9810.0)


def test_jump_errors():
    with pytest.raises(ModelError) as e:
        hy.hydraulic_jump(h_kr=3.48, E0=5.0)  # 1.5 h_c ≈ 5.4 m
    assert e.value.item == "E0"
    with pytest.raises(ModelError) as e:
        hy.jump_length(1.0, 8.0, 6.0, "smetana")
    assert e.value.item == "formula"
    assert all(name in str(e.value) for name in hy.JUMP_LENGTH_FORMULAS)
    with pytest.raises(ModelError) as e:
        hy.contracted_depth(20.0, 25.0, phi=1.2)
    assert e.value.item == "phi"
    with pytest.raises(ModelError) as e:
        hy.slab_length(hy.hydraulic_jump(), 0.0)
    assert e.value.item == "factor"
    with pytest.raises(ModelError) as e:
        hy.unit_discharge(-1.0)
    assert e.value.item == "h_kr"
    with pytest.raises(ModelError) as e:
        hy.jump_length(1.0, 1.2, 1.2, "hager")
    assert e.value.item == "Fr1"


def test_contracted_depth_at_minimum_energy():
    q, phi = 10.0, 0.9
    hc = (q * q / (G * phi * phi)) ** (1 / 3)
    assert hy.contracted_depth(q, 1.5 * hc, phi) == pytest.approx(hc, rel=1e-9)


# -------------------------------------------------------------------- top pressure ---

def test_mean_depth_profile(jump25):
    j = jump25
    Lr = j.roller_length
    x = np.linspace(0.0, 3 * Lr, 41).reshape(1, -1)
    y = hy.mean_depth(j, x)
    assert y.shape == x.shape
    assert y[0, 0] == pytest.approx(j.h1)
    assert np.all(np.diff(y[0]) > 0) and np.all(y < j.h2 + 1e-12)
    # inverse of Hager's tanh profile recovers x
    inner = slice(1, -1)
    x_back = np.arctanh((y[0, inner] - j.h1) / (j.h2 - j.h1)) * Lr / 1.5
    np.testing.assert_allclose(x_back, x[0, inner], rtol=1e-9)
    assert hy.mean_depth(j, -5.0) == pytest.approx(j.h1)
    assert hy.mean_depth(j, 1e4) == pytest.approx(j.h2)


def test_top_and_deficit_pressure_add_to_tailwater(jump25):
    x = np.array([0.0, 3.0, 10.0, 40.0])
    total = hy.top_pressure(jump25, x) + hy.deficit_pressure(jump25, x)
    np.testing.assert_allclose(total, 1000.0 * 9.81 * jump25.h2, rtol=1e-12)
    assert hy.deficit_pressure(jump25, 0.0) == pytest.approx(9810 * (jump25.h2 - jump25.h1))


def test_triangular_deficit_force(jump25):
    L_p = hy.slab_length(jump25)
    x = np.linspace(0.0, L_p, 200001)
    p = hy.triangular_deficit(jump25, x, L_p)
    assert hy.triangular_deficit(jump25, -0.5, L_p) == 0.0
    W_d = 0.5 * 0.6 * (jump25.h2 - jump25.h1) * (2 / 3) * L_p * 9810.0
    assert np.trapezoid(p, x) == pytest.approx(W_d, rel=1e-6)
    assert p[0] == pytest.approx(0.6 * (jump25.h2 - jump25.h1) * 9810)
    assert hy.triangular_deficit(jump25, 0.7 * L_p, L_p) == 0.0
    assert 0.6 * (jump25.h2 - jump25.h1) == pytest.approx(4.67, abs=0.01)  # study notes §6


# ------------------------------------------------------------------------ seepage ---

def test_lane_creep_and_uplift():
    Lw = hy.lane_creep_length([8.0, 8.0, 3.0], [30.0, 45.0])
    assert Lw == pytest.approx(19.0 + 25.0)
    H, up = 16.0, 19.0 + 10.0  # 30 m of horizontal path before the slab
    x = np.array([0.0, 15.0, 45.0, 60.0])
    hs = hy.lane_uplift(x, H, up, Lw)
    # linear loss: head lost per weighted metre H/Lw, horizontal metre = 1/3 weighted metre
    expected = np.array([H - H * up / Lw, H - H * (up + 5) / Lw, 0.0, 0.0])
    np.testing.assert_allclose(hs, expected, atol=1e-12)
    assert hy.lane_check(Lw, H, "Fine sand") == pytest.approx(Lw / H / 7.0)
    assert hy.lane_check(Lw, H, "very_fine_sand_or_silt") == pytest.approx(Lw / H / 8.5)
    assert hy.LANE_RATIOS["medium clay"] == 2.0 and len(hy.LANE_RATIOS) == 12


def test_lane_errors():
    with pytest.raises(ModelError) as e:
        hy.lane_check(40.0, 10.0, "peat")
    assert e.value.item == "soil" and "medium sand" in str(e.value)
    with pytest.raises(ModelError) as e:
        hy.lane_creep_length([1.0, -2.0], [])
    assert e.value.item == "vertical"
    with pytest.raises(ModelError) as e:
        hy.lane_uplift(0.0, 10.0, 50.0, 40.0)
    assert e.value.item == "L_w_upstream"


def test_base_uplift(jump25):
    x = np.linspace(0.0, 50.0, 6)
    hs = hy.lane_uplift(x, 16.0, 20.0, 60.0)
    pb = hy.base_uplift(jump25, x, residual_head=hs)
    np.testing.assert_allclose(pb, 9810.0 * (jump25.h2 + hs))
    net = pb - hy.top_pressure(jump25, x)
    np.testing.assert_allclose(net, hy.deficit_pressure(jump25, x) + 9810.0 * hs, atol=1e-8)
    assert hy.base_uplift(jump25, 3.0, tailwater=9.0, thickness=2.0) == pytest.approx(
        9810.0 * 11.0)
    with pytest.raises(ModelError) as e:
        hy.base_uplift(jump25, x, residual_head=[1.0, 2.0])
    assert e.value.item == "residual_head"


# ------------------------------------------------------------------ fluctuations ---

def test_cp_rms_default_shape():
    X = np.linspace(0.0, 100.0, 100001)
    c = hy.cp_rms(X)
    assert c[0] == 0.0
    assert X[np.argmax(c)] == pytest.approx(10.0, abs=1e-3)
    assert c.max() == pytest.approx(0.08, rel=1e-9)
    assert hy.cp_rms(54.0) == pytest.approx(0.02, abs=0.001)  # end of the jump, Fr1 ≈ 6.6
    assert np.all(np.diff(c[X > 10.001]) < 0)


def test_rms_profile_overrides():
    tab = hy.rms_profile(([0.0, 10.0, 50.0], [0.02, 0.1, 0.01]))
    np.testing.assert_allclose(tab([5.0, 30.0, 80.0]), [0.06, 0.055, 0.01])
    f = hy.rms_profile(lambda X: 0.05 + 0 * np.asarray(X))
    cp, cm = hy.extreme_coefficients([1.0, 20.0], profile=lambda X: 0.05 + 0 * np.asarray(X))
    np.testing.assert_allclose(f([1.0]), [0.05])
    np.testing.assert_allclose(cp, [0.2, 0.2])
    np.testing.assert_allclose(cm, [0.15, 0.15])
    assert hy.rms_profile(None) is hy.cp_rms
    with pytest.raises(ModelError) as e:
        hy.rms_profile(([0.0, 0.0], [0.1, 0.2]))
    assert e.value.item == "rms profile x_over_h1"


def test_extremes_and_impulse(jump25):
    cp, cm = hy.extreme_coefficients(10.0)
    assert (float(cp), float(cm)) == pytest.approx((0.32, 0.24))
    amp = hy.impulse_amplitude(jump25, 0.4)
    assert amp == pytest.approx(0.4 * 1000.0 * jump25.V1**2 / 2)
    assert amp / 9810.0 == pytest.approx(0.4 * 21.7, abs=0.04)  # 8.7 m of water (notes §7)


# --------------------------------------------------------------- design thicknesses ---

@pytest.mark.parametrize("omega_c, s_printed, rel_printed", [
    (0.10 * 0.8, 1.24, 0.36), (0.15 * 0.8, 1.86, 0.53), (0.15 * 1.0, 2.32, 0.67),
    (0.20 * 1.0, 3.10, 0.89)])
def test_fiorotto_rinaldo_notes_values(jump25, omega_c, s_printed, rel_printed):
    s = hy.fiorotto_rinaldo_thickness(jump25.V1, 1.0, omega_c / 2, omega_c / 2)
    assert _close(s, s_printed, 0.01)
    assert _close(s / 3.48, rel_printed, 0.01)
    # net uplift Δp = Ω(C⁺+C⁻) ρ V1²/2 balanced by the submerged weight (γc − γw) s
    assert s * (23544.0 - 9810.0) == pytest.approx(omega_c * 1000.0 * jump25.V1**2 / 2)


def test_fiorotto_rinaldo_uniform_uplift_of_notes_7(jump25):
    dp = 0.15 * 0.8 * jump25.velocity_head  # m of water
    assert _close(dp, 2.60, 0.01) and _close(dp * 9.81, 25.5, 0.1)  # kPa


def test_dombrovsky_and_usace(jump25):
    assert _close(hy.dombrovsky_thickness(jump25.V1, jump25.h1), 3.07, 0.01)
    assert hy.dombrovsky_thickness(20.0, 4.0) == pytest.approx(6.0)
    assert hy.usace_flotation_factor(100.0, 10.0, 20.0, 150.0, 50.0) == pytest.approx(1.3)
    assert hy.usace_flotation_factor(100.0, 0.0, 0.0, 50.0, 60.0) == math.inf
    assert hy.USACE_FLOTATION_REQUIRED == {"usual": 1.3, "unusual": 1.2, "extreme": 1.1}
    with pytest.raises(ModelError) as e:
        hy.fiorotto_rinaldo_thickness(20.0, 0.15, 0.4, 0.4, gamma_c=9000.0)
    assert e.value.item == "gamma_c"


def _net_load(x, s, q0, q1, a, dgamma):
    """Net downward load (N/m²): submerged weight minus the linear upward load on [0, a]."""
    q = np.where(x <= a, q0 + (q1 - q0) * x / a, 0.0)
    return dgamma * s - q


def _numeric_liftoff(q0, q1, a, L, x_edge_resultant, dgamma=23544.0 - 9810.0):
    """s at which the resultant of the net load sits at ``x_edge_resultant`` (2L/3: upstream
    edge at zero pressure; L/3: downstream edge), by numeric integration and brentq (the
    weight over [0, L] and the upward load over [0, a], each on its own grid: the load may
    jump at x = a)."""
    xw = np.linspace(0.0, L, 20001)
    xq = np.linspace(0.0, a, 20001)
    q = q0 + (q1 - q0) * xq / a
    mq = np.trapezoid(q * (xq - x_edge_resultant), xq)
    mw = np.trapezoid(dgamma * (xw - x_edge_resultant), xw)

    def moment(s):  # moment of the net load about the kern point
        return s * mw - mq

    return brentq(moment, -1e3, 1e3, xtol=1e-13)


def test_kern_triangular_deficit_of_notes_6(jump25):
    L = hy.slab_length(jump25)
    q0 = 0.6 * (jump25.h2 - jump25.h1) * 9810.0
    s = hy.kern_liftoff_thickness(q0, 2 * L / 3, L)
    assert _close(s, 2.96, 0.01) and _close(s / 3.48, 0.85, 0.01)
    assert s == pytest.approx(_numeric_liftoff(q0, 0.0, 2 * L / 3, L, 2 * L / 3), rel=1e-6)
    assert s == pytest.approx(8 / 9 * q0 / 9810.0 / 1.4, rel=1e-12)
    # the two other static figures of §6 for the same load: flotation and overturning
    x = np.linspace(0.0, L, 60001)
    q = hy.triangular_deficit(jump25, x, L)
    Q, Mq = np.trapezoid(q, x), np.trapezoid(q * (L - x), x)  # about the downstream edge
    dg = 23544.0 - 9810.0
    assert _close(Q / (dg * L), 1.11, 0.01)
    assert _close(Mq / (dg * L * L / 2), 1.73, 0.01)
    # a Winkler bed under the rigid slab at that thickness: zero pressure at the upstream edge
    f = _net_load(x, s, q0, 0.0, 2 * L / 3, dg)
    R, M = np.trapezoid(f, x), np.trapezoid(f * (x - L / 2), x)
    assert abs(R / L - 6 * M / L**2) < 1e-5 * q0


@settings(max_examples=25, deadline=None)
@given(q0=st.floats(0.0, 1e5), q1=st.floats(0.0, 1e5), xi=st.floats(0.05, 1.0))
def test_kern_trapezoid_against_numeric(q0, q1, xi):
    L = 40.0
    a = xi * L
    s_up = hy.kern_liftoff_thickness(q0, a, L, q1=q1)
    s_dn = hy.kern_liftoff_thickness(q0, a, L, q1=q1, edge="downstream")
    scale = (q0 + q1 + 1.0) / (23544.0 - 9810.0)
    assert s_up == pytest.approx(_numeric_liftoff(q0, q1, a, L, 2 * L / 3), abs=1e-6 * scale)
    assert s_dn == pytest.approx(max(_numeric_liftoff(q0, q1, a, L, L / 3), 0.0),
                                 abs=1e-6 * scale)


def test_kern_errors():
    with pytest.raises(ModelError) as e:
        hy.kern_liftoff_thickness(1e4, 50.0, 40.0)
    assert e.value.item == "a"
    with pytest.raises(ModelError) as e:
        hy.kern_liftoff_thickness(1e4, 20.0, 40.0, edge="left")
    assert e.value.item == "edge"


def test_docs_worked_example_prints_what_the_page_shows():
    """docs/slab-hydraulics.md: the worked example's snippet prints the block that follows it."""
    text = (Path(__file__).resolve().parents[1] / "docs" / "slab-hydraulics.md").read_text(
        encoding="utf-8")
    m = re.search(r"```python\n(.*?)```\s*\nprints\s*\n```text\n(.*?)```", text, flags=re.S)
    assert m, "worked example not found"
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        exec(compile(m.group(1), "slab-hydraulics.md", "exec"), {})
    assert buf.getvalue() == m.group(2)


# ------------------------------------------------------- the coefficients and their sources ---

def _coefficient(name: str) -> hy.Coefficient:
    (c,) = [c for c in hy.COEFFICIENTS if c.name == name]
    return c


def test_the_quoted_coefficients_are_those_the_code_uses():
    """Each coefficient the slab report lists (hydraulics.COEFFICIENTS) is the number the
    functions compute with: recovered from their results on made-up inputs (to 1e-12)."""
    from stepcontact.study.basin import BasinStudy

    h1, h2, Fr1 = 0.8, 7.5, 6.0
    (usbr,) = _coefficient("USBR jump length").values
    assert hy.jump_length(h1, h2, Fr1, "usbr") == pytest.approx(usbr * h2, rel=1e-12)
    (ru,) = _coefficient("Russian jump length").values
    assert hy.jump_length(h1, h2, Fr1, "russian") == pytest.approx(ru * (h2 - h1), rel=1e-12)
    a, b = _coefficient("Pavlovsky jump length").values
    assert hy.jump_length(h1, h2, Fr1, "pavlovsky") == pytest.approx(a * (b * h2 - h1),
                                                                     rel=1e-12)
    a, n = _coefficient("Chertousov jump length").values
    assert hy.jump_length(h1, h2, Fr1, "chertousov") == pytest.approx(
        a * h1 * (Fr1 - 1) ** n, rel=1e-12)
    a, b, c = _coefficient("Hager roller length").values
    L_r = h1 * (a + b * math.tanh(Fr1 / c))
    assert hy.jump_length(h1, h2, Fr1, "hager") == pytest.approx(L_r, rel=1e-12)
    (k,) = _coefficient("Hager mean surface profile").values
    jump = hy.hydraulic_jump()
    x = 0.3 * jump.roller_length
    y = jump.h1 + (jump.h2 - jump.h1) * math.tanh(k * x / jump.roller_length)
    assert float(hy.mean_depth(jump, x)) == pytest.approx(y, rel=1e-12)
    peak, x_peak, shape = _coefficient("rms pressure coefficient C′p").values
    assert float(hy.cp_rms(x_peak)) == pytest.approx(peak, rel=1e-12)
    assert float(hy.cp_rms(2 * x_peak)) == pytest.approx(
        peak * 2**shape * math.exp(-shape), rel=1e-12)
    n_plus, n_minus = _coefficient("extreme-value factors N⁺, N⁻").values
    cp, cm = hy.extreme_coefficients(x_peak)
    assert (float(cp), float(cm)) == pytest.approx((n_plus * peak, n_minus * peak), rel=1e-12)
    (d,) = _coefficient("Dombrovsky thickness").values
    assert hy.dombrovsky_thickness(20.0, 1.0) == pytest.approx(d * 20.0, rel=1e-12)
    assert tuple(hy.USACE_FLOTATION_REQUIRED.values()) == \
        _coefficient("USACE required flotation factors").values
    assert tuple(hy.LANE_RATIOS.values()) == \
        _coefficient("Lane's weighted-creep ratios C_w").values
    study = BasinStudy()
    assert (study.h_kr, study.phi, study.amplitude, study.friction) == (
        _coefficient("critical depth of the design discharge h_kr (m)").values[0],
        _coefficient("velocity coefficient of the inflow φ").values[0],
        _coefficient("impulse amplitude").values[0],
        _coefficient("friction of concrete on sand f").values[0])
    assert {c.status for c in hy.COEFFICIENTS} <= {hy.CHECKED, hy.SEEN, hy.RECALLED}
    assert all(bool(c.against) == (c.status == hy.CHECKED) for c in hy.COEFFICIENTS)


def test_the_checked_coefficient_is_in_its_source():
    """The only coefficient marked checked, h_kr = 3.48 m, is in the article's text (its
    §7) when that text is at hand (the project's seed copy)."""
    seed = Path("/work/shared/seed/lukashevich-rozin-2013.txt")
    if not seed.is_file():
        pytest.skip("the article's text is not on this machine")
    text = seed.read_text(encoding="utf-8")
    checked = [c for c in hy.COEFFICIENTS if c.status == hy.CHECKED]
    assert [c.name for c in checked] == ["critical depth of the design discharge h_kr (m)"]
    assert re.search(r"h_\{кр\} = 3,48\s*\$?\s*м", text)
