"""A concrete gravity dam checked as dam engineers check it: load combinations, guideline
verdicts, the yield acceleration located exactly, and hand statics beside every figure.

Plane strain, per metre of dam; SI units (m, N/m, N·m/m, Pa).  The dam is 40 m high with a
vertical upstream face, a 5 m crest and a downstream batter of 0.8 : 1, so the base runs
B = 5 + 0.8 × 40 = 37 m from the heel (0, 0) to the toe (37, 0).  Concrete E = 25 GPa,
ν = 0.2, 2400 kg/m³; rock E = 15 GPa, ν = 0.25 (massless: its weight is not applied, it only
carries the dam), 40 m deep and reaching 40 m beyond heel and toe, meshed with cells that do
not match the dam's (mortar CFEs).  The joint is frictional, f = tan 45° = 1, no cohesion.

Loads (:mod:`stepcontact.model.combinations`): self-weight; the reservoir (its pattern's
factor is the level); tailwater on the downstream face; uplift with a drain line 4 m from the
heel, the head there H₂ + K (H₁ − H₂) with EM 1110-2-2100's K = (1 − E)(L − X)/L for a drain
efficiency E = 0.5 [to be checked]; silt 10 m deep (K = 0.5, γ'_s = 9 kN/m³).  Combinations:

* usual — normal level 36 m, tailwater 2 m, silt;
* flood (unusual) — 39.5 m, tailwater 6 m, silt;
* extreme — the usual loads and a pseudo-static earthquake k_h = 0.1: the dam's inertia
  k_h W downstream and Westergaard's (1933) hydrodynamic pressure of the 36 m reservoir,
  (7/12) k_h γ_w h² at 0.4 h (:class:`~stepcontact.model.seismic.AddedMass`);
* post-earthquake — the extreme run with the earthquake removed again.

Each combination is one run (``Combination.model(site)``), checked against USACE
EM 1110-2-2100 and, side by side, the CDA 2007 guidelines (``check_combination``; every
required value is still [to be checked] against the documents).  The **yield acceleration**
k_y: after the usual loads, a segment of a ``SeismicCoefficient`` pattern per unit k_h (the
dam's inertia and Westergaard's pressure) runs until equilibrium is lost; its λ is k_y,
located as an event, and k_y / k_h is the margin on the extreme combination's coefficient.

The crack water is on (``Reservoir(level, crack_water=True)``): where the base opens from the
heel, the full reservoir head replaces the drained uplift.

Hand statics (rigid-body statics of the dam, independent of the model) are printed beside the
model's figures for every combination whose base stays compressed: ΣV' = N', ΣH, the moment
about the toe, the resultant's distance from the toe and the sliding factor N' tan φ / H.  At
the yield acceleration every CFE in contact slips, so limit equilibrium gives
k_y = (f (N' − ΣW) − H₀)/(W + (7/12) γ_w h²), ΣW the crack water's force beyond the uplift
(read from the run); without the crack (ΣW = 0) it is the uncracked base's k_y.

Figures (``dam_safety_*.png``): the section with its loads per combination, the base normal
stress per combination, and the k_h – crest displacement curve up to the yield acceleration.
Run:  python examples/dam_safety.py [--out DIR]   (figures in DIR, default ./dam_safety_out;
``--out docs/figures`` refreshes the user guide's figures; a few seconds)
"""

import sys
import time
from pathlib import Path

import numpy as np

import stepcontact as sc
from stepcontact.model.combinations import (
    BaseUplift,
    Combination,
    DamSite,
    Earthquake,
    Reservoir,
    SelfWeight,
    Silt,
    Tailwater,
)
from stepcontact.results.dam_checks import JointStrength, check_combination, load_guidelines

GAMMA_W, RHO_C, G = 9810.0, 2400.0, 9.81  # N/m³, kg/m³, m/s²
HEIGHT, CREST, SLOPE = 40.0, 5.0, 0.8  # m, m, horizontal per vertical (downstream batter)
B = CREST + SLOPE * HEIGHT  # 37 m
FRICTION = 1.0  # tan 45°
X_DRAIN, EFFICIENCY = 4.0, 0.5  # m from the heel; drain efficiency E [to be checked]
K_DRAIN = (1 - EFFICIENCY) * (B - X_DRAIN) / B  # EM 1110-2-2100: K = (1 − E)(L − X)/L
SILT = (10.0, 9000.0, 0.5)  # level (m), submerged unit weight (N/m³), lateral coefficient
NORMAL, FLOOD = (36.0, 2.0), (39.5, 6.0)  # (reservoir, tailwater) levels, m
K_H = 0.1  # the extreme combination's seismic coefficient


def dam_site(rock_E: float = 15e9, cell: float = 2.5, friction: float = FRICTION) -> DamSite:
    """The dam on its rock block: bodies, the deep-rock support and the base joint, no loads
    (``cell``: the dam's cell size, m; the rock's cells are 1.2 × larger: non-matching)."""
    concrete = sc.Material(E=25e9, nu=0.2, density=RHO_C)
    rock = sc.Material(E=rock_E, nu=0.25, density=0.0)
    nx, ny = round(B / cell), round(HEIGHT / cell)
    dam = sc.quad_region("dam", [(0, 0), (B, 0), (CREST, HEIGHT), (0, HEIGHT)], nx, ny,
                         concrete)
    width = B + 2 * HEIGHT
    nr = round(width / (1.2 * cell))
    fnd = sc.rectangle("rock", (-HEIGHT, -HEIGHT), (B + HEIGHT, 0.0), nr,
                       round(HEIGHT / (2 * cell)), rock)
    m = sc.Model(bodies=[fnd, dam], name="gravity dam 40 m")
    base = sc.Interface("base", plus=m.select("dam", y=0.0), minus=m.select("rock", y=0.0),
                        friction=friction)
    m = m.add(sc.Support("deep rock", m.select("rock", y=-HEIGHT), "xy"), base)
    downstream = m.select("dam", lambda x, y: np.abs(x - (B - SLOPE * y)) < 1e-6,
                          name="downstream face")
    return DamSite(m, base="base", heel=(0.0, 0.0), toe=(B, 0.0),
                   upstream=m.select("dam", x=0.0, name="upstream face"), dam=("dam",),
                   downstream=downstream)


def westergaard(site: DamSite, level: float) -> sc.AddedMass:
    """Westergaard's added mass of the reservoir at ``level`` on the upstream face."""
    return sc.AddedMass(site.upstream[0], level=level)


def combinations(site: DamSite) -> list[Combination]:
    """The four combinations: usual, flood (unusual), extreme (k_h = 0.1), post-earthquake."""
    def static(levels):
        h, t = levels
        return (SelfWeight(), Reservoir(h, crack_water=True), Tailwater(t),
                BaseUplift(drain=(X_DRAIN, 0.0), ratio=K_DRAIN), Silt(*SILT))

    # the dam's inertia and, on its upstream face, Westergaard's pressure of the reservoir
    quake = Earthquake(K_H)
    return [Combination("usual", "usual", static(NORMAL)),
            Combination("flood", "flood", static(FLOOD)),
            Combination("extreme", "extreme", static(NORMAL) + (quake,)),
            Combination("post-earthquake", "post-earthquake", static(NORMAL) + (quake,))]


def yield_model(site: DamSite, usual: Combination, k_max: float = 1.0) -> sc.Model:
    """The usual combination's model and a segment of k_h from 0 to ``k_max``: the dam's
    inertia and Westergaard's pressure per unit λ (λ is k_h)."""
    quake = sc.SeismicCoefficient(k_h=1.0, bodies=("dam",),
                                  reservoir=westergaard(site, usual.find(Reservoir).level))
    return usual.model(site).add(sc.LoadPattern("k_h", [quake]), sc.Segment("k_h", k_max))


# ---- hand statics ------------------------------------------------------------------------------
def hand_forces(h: float, t: float, k_h: float = 0.0) -> dict[str, tuple]:
    """The loads on the dam by rigid-body statics, per metre: {name: (F_x, F_y, x, y)}, a
    resultant (N; x downstream, y up) and a point of its line of action (m).  The weight as a
    rectangle and a triangle, the reservoir γ_w h²/2 at h/3, the tailwater's thrust γ_w t²/2 at
    t/3 and the water resting on the downstream face (n_d γ_w t²/2), the uplift as two
    trapezoids of head through the drain line, the silt K γ'_s s²/2 at s/3, the inertia k_h W
    at the centroid and Westergaard's (7/12) k_h γ_w h² at 0.4 h."""
    rect, tri = CREST * HEIGHT, (B - CREST) * HEIGHT / 2
    W = RHO_C * G * (rect + tri)
    x_w = (rect * CREST / 2 + tri * (2 * CREST + B) / 3) / (rect + tri)
    y_w = (rect * HEIGHT / 2 + tri * HEIGHT / 3) / (rect + tri)
    h_drain = t + K_DRAIN * (h - t)
    parts = [(GAMMA_W * (h0 + h1) / 2 * (x1 - x0), x0 + (x1 - x0) * (h0 + 2 * h1) / (3 * (h0 + h1)))
             for (x0, h0), (x1, h1) in (((0.0, h), (X_DRAIN, h_drain)),
                                        ((X_DRAIN, h_drain), (B, t)))]
    U = sum(u for u, _ in parts)
    s, gs, k = SILT
    out = {"W": (0.0, -W, x_w, y_w),
           "P": (GAMMA_W * h * h / 2, 0.0, 0.0, h / 3),
           "U": (0.0, U, sum(u * x for u, x in parts) / U, 0.0),
           "T": (-GAMMA_W * t * t / 2, 0.0, B - SLOPE * t / 3, t / 3),
           "V_t": (0.0, -GAMMA_W * SLOPE * t * t / 2, B - SLOPE * t / 3, t / 3),
           "S": (k * gs * s * s / 2, 0.0, 0.0, s / 3)}
    if k_h:
        out["E"] = (k_h * W, 0.0, x_w, y_w)
        out["P_d"] = (7 / 12 * k_h * GAMMA_W * h * h, 0.0, 0.0, 0.4 * h)
    return out


def hand(h: float, t: float, k_h: float = 0.0) -> dict[str, float]:
    """The base's figures by hand: N' = −ΣF_y, H = ΣF_x, the moment M of the loads about the
    toe (anticlockwise > 0: resisting), the resultant's distance a = M/N' from the toe, the
    sliding factor f N'/H (c = 0) and the yield acceleration of the uncracked base by limit
    equilibrium, k_y = (f N' − H)/(W + (7/12) γ_w h²) (k_h acts on W and Westergaard's
    pressure; N' does not change with it)."""
    F = np.array(list(hand_forces(h, t, k_h).values()))
    n_eff, shear = -F[:, 1].sum(), F[:, 0].sum()
    M = ((F[:, 2] - B) * F[:, 1] - F[:, 3] * F[:, 0]).sum()  # r × F about the toe (B, 0)
    W = -hand_forces(h, t)["W"][1]
    return {"N": n_eff, "H": shear, "M": M, "a": M / n_eff, "F": FRICTION * n_eff / shear,
            "W": W, "k_y": (FRICTION * n_eff - shear) / (W + 7 / 12 * GAMMA_W * h * h)}


# ---- output ------------------------------------------------------------------------------------
#: the table's rows: (check in DamCheck, label, scale of the value)
ROWS = [("sliding factor (peak)", "sliding factor N' tan φ / H", 1.0),
        ("resultant |e|/L", "resultant |e|/L", 1.0),
        ("compressed base (fraction)", "compressed base L_c/L", 1.0),
        ("uplift factor", "uplift factor (N' + U)/U", 1.0),
        ("heel stress (linear)", "heel σ (linear), MPa", 1e-6),
        ("toe stress (linear)", "toe σ (linear), MPa", 1e-6),
        ("crack length", "crack length, m", 1.0)]


def _cell(chk, combo: str, check: str, scale: float) -> str:
    r = chk.row(combo, "base", check)
    v = "—" if r.value is None else f"{r.value * scale:.3g}"
    if r.required is None:
        return v
    mark = "" if r.checked else "*"  # * a required value not confirmed against the document
    return f"{v} ({r.relation} {r.required:.3g}{mark}) {r.verdict}"


def verdict_table(checks: dict, combos: list[Combination], guideline: str) -> str:
    """The checks of every combination against ``guideline``, one column each: the
    guideline's class of the combination, then value (required value) verdict per check."""
    g = load_guidelines()[guideline]
    names = [c.name for c in combos]
    first = checks[names[0]]
    head = f"{first.guideline} ({first.variant})" if first.variant else first.guideline
    lines = [head, f"{'':28s}" + "".join(f"{n:>24s}" for n in names),
             f"{'class':28s}" + "".join(f"{g.condition_class(c.condition)[0]:>24s}"
                                        for c in combos)]
    for check, label, scale in ROWS:
        lines.append(f"{label:28s}" + "".join(f"{_cell(checks[n], n, check, scale):>24s}"
                                              for n in names))
    lines.append(f"{'verdict':28s}" + "".join(
        f"{('pass' if checks[n].verdicts().get(n, False) else 'FAIL'):>24s}" for n in names))
    return "\n".join(lines)


def main(out: Path) -> None:
    t0 = time.process_time()
    site = dam_site()
    combos = combinations(site)
    strength = JointStrength(cohesion=0.0, friction_angle=45.0)
    runs, usace, cda = {}, {}, {}
    for c in combos:
        res = sc.solve_static(c.model(site))
        runs[c.name] = res
        usace[c.name] = check_combination(res, c, site, guideline="usace", strength=strength)
        cda[c.name] = check_combination(res, c, site, guideline="cda", strength=strength)
    names = [c.name for c in combos]
    print(f"gravity dam H = {HEIGHT:g} m, B = {B:g} m, f = {FRICTION:g}, c = 0; drains at "
          f"{X_DRAIN:g} m, K = {K_DRAIN:.4f}; silt {SILT[0]:g} m")
    print("\nguideline checks of the base: value (required value) verdict; * a required value "
          "[to be checked] against the document")
    print(verdict_table(usace, combos, "usace"))
    print(verdict_table(cda, combos, "cda"))

    print("\nhand statics beside the model (per metre; moments about the toe):")
    levels = {"usual": NORMAL + (0.0,), "flood": FLOOD + (0.0,), "extreme": NORMAL + (K_H,),
              "post-earthquake": NORMAL + (0.0,)}
    for name in names:
        s = runs[name].interface_safety("base", heel=site.heel)
        if s.open_length[-1] > 0:
            print(f"  {name}: the base opens over {s.open_length[-1]:.2f} m (no rigid-body "
                  "hand check of the stresses)")
            continue
        ref = hand(*levels[name])
        n_eff, shear, a = -s.normal_force[-1], abs(s.shear_force[-1]), s.from_toe[-1]
        print(f"  {name}: N' = {n_eff / 1e3:.2f} kN (hand {ref['N'] / 1e3:.2f}), H = "
              f"{shear / 1e3:.2f} kN (hand {ref['H'] / 1e3:.2f}), M = {n_eff * a / 1e3:.1f} "
              f"kN·m (hand {ref['M'] / 1e3:.1f})")
        print(f"  {'':{len(name)}s}  resultant {a:.4f} m from the toe (hand {ref['a']:.4f}), "
              f"N' tan φ / H = {n_eff * FRICTION / shear:.4f} (hand {ref['F']:.4f})")
        assert abs(n_eff / ref["N"] - 1) < 1e-9 and abs(shear / ref["H"] - 1) < 1e-9
        assert abs(a / ref["a"] - 1) < 1e-9

    usual = combos[0]
    res_y = sc.solve_static(yield_model(site, usual))
    mult = res_y.multipliers[-1]
    k_y = mult.equilibrium_lost
    ref = hand(*NORMAL)
    sy = res_y.interface_safety("base", heel=site.heel)
    wet = float(np.asarray(res_y.water)[-1].sum()) if res_y.water is not None else 0.0
    print(f"\nyield acceleration (the usual loads, then k_h raised to failure): k_y = {k_y:.6f}"
          f" ({res_y.message.split(': ')[-1]})")
    print(f"  on the k_h segment: first slip at k_h = {mult.first_slip:.4f}, the heel opens at "
          f"{mult.first_opening:.4f}, crack {sy.open_length[-1]:.2f} m long at k_y")
    # at failure every CFE in contact slips: f N' = H, with N' less the crack water's force
    # beyond the uplift (ΣW_crack, from the run) and H = H_0 + k_y (W + (7/12) γ_w h²)
    k_wet = (FRICTION * (ref["N"] - wet) - ref["H"]) / (ref["W"] + 7 / 12 * GAMMA_W
                                                       * NORMAL[0] ** 2)
    print(f"  hand limit equilibrium with the crack water's ΣW = {wet / 1e3:.2f} kN: "
          f"(f (N' − ΣW) − H)/(W + (7/12) γ_w h²) = {k_wet:.6f}")
    print(f"  uncracked base (no crack water), by hand: {ref['k_y']:.6f}; the crack water "
          f"lowers k_y by {100 * (1 - k_y / ref['k_y']):.1f} %")
    print(f"  margin on the extreme combination's coefficient: k_y / k_h = {k_y:.4f} / "
          f"{K_H:g} = {k_y / K_H:.3f}")
    assert res_y.status == sc.Status.EQUILIBRIUM_LOST and "sliding" in res_y.message
    assert abs(k_y / k_wet - 1) < 1e-9

    out.mkdir(parents=True, exist_ok=True)
    plot_sections(combos, runs, site, out / "dam_safety_sections.png")
    plot_base_stress(combos, runs, out / "dam_safety_base_stress.png")
    plot_yield(res_y, K_H, out / "dam_safety_yield.png")
    print(f"\nfigures in {out}/: dam_safety_sections.png, dam_safety_base_stress.png, "
          "dam_safety_yield.png")
    print(f"run time {time.process_time() - t0:.1f} s CPU", file=sys.stderr)


# ---- figures -----------------------------------------------------------------------------------
COLORS = {"W": "#555555", "P": "#1f77b4", "U": "#6a3d9a", "T": "#17becf", "V_t": "#17becf",
          "S": "#8c564b", "E": "#d62728", "P_d": "#ff7f0e", "R": "#2ca02c"}
LABELS = {"W": "weight W", "P": "reservoir P", "U": "uplift U", "T": "tailwater T",
          "S": "silt S", "E": "inertia k_h W", "P_d": "Westergaard P_d",
          "R": "base resultant N' (model)"}
_WATER = "#c6dbef"


def _quake(combo: Combination) -> float:
    q = combo.find(Earthquake)
    return 0.0 if q is None or combo.condition == "post-earthquake" else float(q.k_h)


def plot_sections(combos, runs, site, path=None):
    """The section per combination with its loads: water, silt, and the resultant of each
    load as an arrow (lengths ∝ force, one scale), the model's base resultant N' at its
    distance from the toe, and the middle third (dotted)."""
    from stepcontact.post.common import new_figure, save_figure

    fig = new_figure(figsize=(9.0, 8.6))
    axes = fig.subplots(2, 2, sharex=True, sharey=True)
    scale = -0.45 * HEIGHT / hand_forces(*NORMAL)["W"][1]  # m per N: W is 0.45 H long
    for ax, combo in zip(axes.flat, combos, strict=True):
        h, t = combo.find(Reservoir).level, combo.find(Tailwater).level
        k = _quake(combo)
        ax.fill([-20, B + 20, B + 20, -20], [0, 0, -25, -25], color="#e5d8bd", lw=0)
        ax.fill([-20, 0, 0, -20], [0, 0, h, h], color=_WATER, lw=0)
        ax.fill([-20, 0, 0, -20], [0, 0, SILT[0], SILT[0]], color="#d9c7a7", lw=0)
        ax.fill([B - SLOPE * t, B + 20, B + 20, B], [t, t, 0, 0], color=_WATER, lw=0)
        ax.fill([0, B, CREST, 0], [0, 0, HEIGHT, HEIGHT], color="0.85", ec="0.2", lw=1.0)
        for x in (B / 3, 2 * B / 3):
            ax.plot([x, x], [0, -25], color="0.3", ls=":", lw=0.8)
        loads = hand_forces(h, t, k)
        for name, (fx, fy, x, y) in loads.items():
            if name == "V_t":
                continue
            dx, dy = fx * scale, fy * scale
            x0, y0 = x - dx, y - dy  # the head at the point of application
            ax.annotate("", xy=(x0 + dx, y0 + dy), xytext=(x0, y0),
                        arrowprops={"arrowstyle": "-|>", "color": COLORS[name], "lw": 2.0,
                                    "mutation_scale": 14})
            ax.plot([], [], color=COLORS[name], lw=2.0,
                    label=f"{LABELS[name]} {np.hypot(fx, fy) / 1e6:.3g} MN")
        s = runs[combo.name].interface_safety("base", heel=site.heel)
        n_eff, xr = -s.normal_force[-1], B - s.from_toe[-1]
        ax.annotate("", xy=(xr, 0.0), xytext=(xr, -n_eff * scale),
                    arrowprops={"arrowstyle": "-|>", "color": COLORS["R"], "lw": 2.5,
                                "mutation_scale": 14})
        ax.plot([], [], color=COLORS["R"], lw=2.5, label=f"{LABELS['R']} {n_eff / 1e6:.3g} MN,"
                f" {s.from_toe[-1]:.2f} m from the toe")
        ax.set_aspect("equal")
        ax.set_xlim(-12, B + 12)
        ax.set_ylim(-n_eff * scale - 2, HEIGHT + 12)
        title = f"{combo.name}: h = {h:g} m, t = {t:g} m" + (f", k_h = {k:g}" if k else "")
        if combo.condition == "post-earthquake":
            title += f", after k_h = {combo.find(Earthquake).k_h:g}"
        ax.set_title(title, fontsize="medium")
        ax.legend(loc="upper right", fontsize="xx-small", frameon=False)
    for ax in axes[-1]:
        ax.set_xlabel("x (m)")
    for ax in axes[:, 0]:
        ax.set_ylabel("y (m)")
    fig.suptitle("Load combinations: resultants by hand statics (one force scale), the model's "
                 "base resultant; dotted: the middle third", fontsize="medium")
    save_figure(fig, None if path is None else Path(path))
    return fig


def plot_base_stress(combos, runs, path=None):
    """σ_n = N/A of the base's CFEs (MPa, compression < 0) against x from the heel, one curve
    per combination, beside the gravity method's linear distribution N'/L (1 ± 6e/L)."""
    from stepcontact.post.common import new_figure, save_figure

    fig = new_figure(figsize=(8.0, 5.0))
    ax = fig.add_subplot()
    for i, combo in enumerate(combos):
        res = runs[combo.name]
        x = np.asarray(res.cfe["x"])[:, 0]
        o = np.argsort(x, kind="stable")
        sig = np.asarray(res.N)[-1] / np.asarray(res.cfe["area"])
        line, = ax.plot(x[o], sig[o] / 1e6, marker=".", lw=1.4, ls=("-", "--", "-.", ":")[i],
                        label=combo.name)
        heel, toe = res.interface_safety("base", heel=(0.0, 0.0)).linear_stresses(-1)
        ax.plot([0.0, B], [heel / 1e6, toe / 1e6], color=line.get_color(), lw=0.8, alpha=0.6)
    ax.plot([], [], color="0.4", lw=0.8, label="gravity method: linear (same colour)")
    ax.axhline(0.0, color="0.3", lw=0.6)
    ax.set_xlim(0.0, B)
    ax.set_xlabel("x from the heel (m)")
    ax.set_ylabel("σ_n = N/A (MPa), compression < 0")
    ax.grid(True, alpha=0.3)
    ax.set_title("Normal stress along the base, per combination (CFEs of the elastic model)",
                 fontsize="medium")
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncols=3,
               fontsize="small", frameon=False)
    save_figure(fig, None if path is None else Path(path))
    return fig


def plot_yield(res, k_h: float, path=None):
    """k_h against the crest's horizontal displacement (mm) on the k_h segment, to the yield
    acceleration; the first slip, the first opening and the design coefficient marked."""
    from stepcontact.post.common import new_figure, save_figure

    seg = len(res.multipliers) - 1
    i = np.flatnonzero(np.asarray(res.segment) == seg)
    ux = res.node_history(point=(0.0, HEIGHT), body="dam", quantity="ux")[i]
    lam = np.asarray(res.lam)[i]
    mult = res.multipliers[-1]
    fig = new_figure(figsize=(8.0, 5.0))
    ax = fig.add_subplot()
    ax.plot((ux - ux[0]) * 1e3, lam, color="k", marker=".", lw=1.4, label="states (events)")
    for v, c, text in ((k_h, "#1f77b4", f"extreme combination k_h = {k_h:g}"),
                       (mult.first_slip, "#ff7f0e", f"first slip {mult.first_slip:.3f}"),
                       (mult.first_opening, "#2ca02c", f"heel opens {mult.first_opening:.3f}"),
                       (mult.equilibrium_lost, "#d62728",
                        f"yield acceleration k_y = {mult.equilibrium_lost:.4f}")):
        ax.axhline(v, color=c, ls=":", lw=1.2, label=text)
    ax.set_xlabel("crest displacement u_x (mm, downstream > 0; from the usual state)")
    ax.set_ylabel("seismic coefficient k_h")
    ax.set_ylim(0.0, 1.1 * mult.equilibrium_lost)
    ax.grid(True, alpha=0.3)
    ax.set_title("Pseudo-static k_h raised to the yield acceleration (usual loads held)",
                 fontsize="medium")
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncols=3,
               fontsize="small", frameon=False)
    save_figure(fig, None if path is None else Path(path))
    return fig


if __name__ == "__main__":
    args = sys.argv[1:]
    target = Path(args[args.index("--out") + 1]) if "--out" in args else Path("dam_safety_out")
    main(target)
