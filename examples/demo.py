"""The built-in demo (``stepcontact demo``) through the Python API, with figures and files.

A concrete block (2 m × 1 m, 2400 kg/m³) on an elastic rock foundation, joined by a rigid joint
with friction f = 0.6 whose two faces are meshed differently (mortar CFEs):

1. ``demo_model()``: self-weight W, then a pressure on the block's left face.  The joint
   carries at most f·W, so the block slides as a whole at H = f·W.
2. ``demo_uplift_model()``: self-weight, then uplift pressure under the left half of the joint;
   the joint opens progressively and the block tips about its right edge at λ = W / 15 kN.

Writes results (.nc), a contact-stress figure, a deformed shape and a ParaView series into
``demo-example/``.  Run:  python examples/demo.py
"""

from pathlib import Path

import numpy as np

import stepcontact as sc
from stepcontact.demo import demo_uplift_model

out = Path("demo-example")
G = 9.81

# 1. sliding --------------------------------------------------------------------------------
res = sc.solve_static(sc.demo_model())
print(res.summary())
W = 2400 * G * 2.0 * 1.0  # N per metre run
H = res.multipliers[-1].equilibrium_lost * 1.0e4 * 1.0  # 10 kPa per unit λ on a 1 m face
print(f"sliding at H = {H:.3f} N; f·W = {0.6 * W:.3f} N")
assert res.status == sc.Status.EQUILIBRIUM_LOST
assert abs(H / (0.6 * W) - 1) < 1e-9
# the reactions of the foundation's base balance the loads at every state
assert np.allclose(res.reaction("fixed base", "x"), -res.factors[:, 1] * 1.0e4, rtol=1e-9,
                   atol=1e-6 * W)
res.save(out / "slide.nc")
sc.plot_interfaces(res, path=out / "slide-stresses.png")
sc.plot_deformed(res, path=out / "slide-deformed.png")
sc.export_vtu(res, out / "slide-vtu")

# 2. uplift ----------------------------------------------------------------------------------
up = sc.solve_static(demo_uplift_model())
print(up.summary())
assert up.status == sc.Status.EQUILIBRIUM_LOST
assert up.mechanism["bodies"][0]["mode"].startswith("rotation")
# it tips about its right edge when the uplift's moment about it (10 kPa · λ · 1 m at a lever
# of 1.5 m) equals the weight's (W · 1 m): λ = W / 15 000
assert abs(up.multipliers[-1].equilibrium_lost / (W / 1.5e4) - 1) < 1e-9
assert np.allclose(up.mechanism["bodies"][0]["centre"], [2.0, 0.0], atol=1e-9)
up.save(out / "uplift.nc")
sc.plot_event_timeline(up, path=out / "uplift-timeline.png")
print(f"written: {sorted(p.name for p in out.iterdir())}")
