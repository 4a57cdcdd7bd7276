"""The stilling-basin slab study in small: how thick must an apron slab be so that neither the
jump's mean pressures nor a pressure impulse lift it off its soil foundation?

The hydraulics of the article's design discharge (h_kr = 3.48 m, energy head E0 = 25 m above
the apron: q = 20.3 m²/s, h1 = 0.99 m, V1 = 20.6 m/s, Fr1 = 6.6, h2 = 8.77 m, jump and slab
53.5 m long) give the loads: the jump's mean profile on the top, the tailwater pressure in the
joint under the slab (and its buoyancy), and an impulse of 0.4 ρV1²/2 (85 kPa) over 5 m for
0.5 s, up under the slab at x = 0.2 L_p.  For the static loads and for the impulse, the limit
thickness is found by bisection (each trial an exact static or dynamic contact run); a coarse
mesh keeps it to a minute.  `stepcontact study slab` runs the full study (positions along the
slab, both directions, two durations) and writes the report.

Printed: the hydraulics, each case's limit thickness (m and h/h_kr) and how the slab fails,
and the design formulas for the same inputs.  Written (./slab_study_out/): the study's store
(cases, result files, dataset), the figures and the report (Markdown and HTML).
Run:  python examples/slab_study.py
"""

from pathlib import Path

import numpy as np

import stepcontact as sc
from stepcontact.study import basin
from stepcontact.study.report import write_report
from stepcontact.study.slab import slab_model

study = basin.quick(positions=(0.2,), directions=("up",), durations=(0.5,), cells=(12, 2),
                    tol=0.1, steps=12)
jump = study.jump
print(f"hydraulics: q = {jump.q:.2f} m²/s, h1 = {jump.h1:.3f} m, V1 = {jump.V1:.2f} m/s, "
      f"Fr1 = {jump.Fr1:.2f}, h2 = {jump.h2:.2f} m, L_j = L_p = {study.length:.1f} m "
      f"({jump.formula}), V1²/2g = {jump.velocity_head:.1f} m")

out = Path("slab_study_out")
ds = basin.run_basin(study, out, executor="serial", progress=False)
for i, case in enumerate(ds["case"].values):
    print(f"{case:>14}: limit h = {ds['h_limit'].values[i]:.2f} m "
          f"(h/h_kr = {ds['h_ratio'].values[i]:.2f}); thinner: {ds['mode'].values[i]} at "
          f"{'λ' if case == 'static' else 't'} = {ds['when'].values[i]:.3f}")
print("design formulas for the same inputs:")
for name, h, note in basin.design_table(study, ds):
    print(f"  {name}: {h:.2f} m (h/h_kr = {h / study.h_kr:.2f}); {note}")

files = write_report(ds, study, out / "report")
print("written: " + ", ".join(str(f) for f in files.values()))

# ---- checks ---------------------------------------------------------------------------------
h = dict(zip(ds["kind"].values.astype(str), ds["h_limit"].values, strict=True))
assert list(ds["case_status"].values) == ["ok", "ok"]
# an impulse up under the slab on top of the mean loads needs at least the static thickness
assert h["impulse"] >= h["static"] - study.tol
# the static limit lies between whole-slab flotation (mean net uplift) and the kern rule of a
# rigid slab for the same net uplift (a flexible slab on soil lifts locally, before the
# whole slab floats, and no later than a rigid one's edge)
rows = {name: t for name, t, _ in basin.design_table(study)}
float_1 = rows["USACE flotation, SF = 1.1 (extreme)"] / 1.1
assert float_1 < h["static"] < rows["kern rule, rigid slab on a Winkler bed, deficit of the "
                                    "mean profile"] * 1.05
assert np.all(ds["h_limit"].values - ds["h_failing"].values <= study.tol + 1e-12)
# the slab at the static limit, solved again on its own: it carries the mean loads with every
# CFE of its base closed (and the static program completes)
at_limit = sc.solve_static(slab_model(study.slab(h["static"])))
assert at_limit.status == sc.Status.COMPLETED
assert not any(e.transition == sc.Transition.OPENED for e in at_limit.events)
