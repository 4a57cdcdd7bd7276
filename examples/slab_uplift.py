"""A slab on an elastic foundation lifted by uplift pressure that grows upstream.

Self-weight, then a triangular uplift pressure under the slab (largest at the upstream edge):
the joint opens from the upstream edge, slip spreads ahead of the opening, and the slab finally
lifts off or tips.  Writes the result file and a figure of the contact stresses.
Run:  python examples/slab_uplift.py
"""

from pathlib import Path

import stepcontact as sc
from stepcontact.post.plotting import plot_interfaces


def slab_model() -> sc.Model:
    """The slab, its foundation, the joint, the loads and the program (N, m, Pa)."""
    concrete = sc.Material(E=30e9, nu=0.2, density=2400)
    rock = sc.Material(E=5e9, nu=0.25, density=2200)
    slab = sc.rectangle("slab", (2, 0), (12, 1), 40, 4, concrete)
    found = sc.rectangle("foundation", (0, -6), (14, 0), 28, 12, rock)  # non-matching meshes
    m = sc.Model(bodies=[found, slab], name="slab-uplift")
    joint = m.select("slab", y=0)
    return m.add(
        sc.Support("bed", m.select("foundation", y=-6), "xy"),
        sc.Interface("joint", plus=joint,
                     minus=m.select("foundation", where=lambda x, y: abs(y) < 1e-9),
                     friction=0.7),
        sc.LoadPattern("weight", [sc.BodyForce(bodies=("slab",))]),
        sc.LoadPattern("uplift", [sc.EdgeLoad(joint, normal=(1.0, 0.0))]),  # Pa per unit λ
        sc.Segment("weight", 1.0),
        sc.Segment("uplift", 1e6),
    )


if __name__ == "__main__":
    m = slab_model()
    res = sc.solve_static(m)
    print(res.summary())
    out = Path("slab_uplift_out")
    out.mkdir(exist_ok=True)
    res.save(out / "slab_uplift.nc")
    lost = res.multipliers[-1].equilibrium_lost
    lams = [0.5 * res.multipliers[-1].first_opening, res.multipliers[-1].first_opening, lost]
    plot_interfaces(res, lams=lams, segment=1, path=out / "slab_uplift.png")
    print(f"result and figure written to {out}/")
    assert res.residual.max() < 1e-9 and res.violation.max() < 1e-9
