"""A friction sweep on one factorisation, a load segment that moves two patterns at once, and
the same kind of sweep as a resumable parameter study on a local process pool.

The block of ``block_on_base.py`` (2 m × 1 m of concrete on a concrete base): the structure is
condensed to its contact unknowns once (``sc.condense``); every friction coefficient then reuses
it.  Closed form: the block slides when the push reaches H = f·W.  Then, for f = 0.5, a second
program pushes and lifts the block together (``Segment(..., rates=...)``: push 20 kN and uplift
0.5 W per unit of the segment's parameter t), so that it slides at f (W − 0.5 W t) = 20 000 t.

Last, ``stepcontact.study.sweep`` runs the built-in demo model file (a block on a foundation
pushed by a pressure p per unit λ) over a grid of friction × pressure on a local process pool
(one BLAS thread per worker): each case is stored as it finishes in
``friction-sweep-output/store/`` (a rerun skips the finished ones), the collected dataset is
printed, and the load at first slip and at sliding, λ·p (N per metre run), is plotted against
the friction coefficient to ``friction-sweep-output/first_slip.png``.
Run:  python examples/friction_sweep.py
"""

import runpy
import tomllib
from importlib.resources import files
from pathlib import Path

import numpy as np

import stepcontact as sc
from stepcontact.study.studyfile import ModelCase
from stepcontact.study.sweep import grid, run_sweep, to_grid

OUTPUT = Path("friction-sweep-output")
# the model of block_on_base.py (its function, without running that script)
block_model = runpy.run_path(str(Path(__file__).with_name("block_on_base.py")),
                             run_name="block_on_base")["block_model"]


def one_condensation() -> None:
    """The friction sweep and the two-pattern segment in this process, on one condensation."""
    m = block_model().add(
        sc.LoadPattern("uplift", [sc.BodyForce(bodies=("block",), g=(0.0, 9.81))]))  # W/unit
    W = 2 * 1 * 2400 * 9.81  # N per metre run

    c = sc.condense(m)  # one factorisation for the whole sweep
    print("f      sliding load H, N     f·W, N          factorisations")
    for f in np.linspace(0.2, 1.0, 5):
        res = sc.solve_static(m.with_friction(f), condensation=c, store_fields="ends")
        H = res.multipliers[-1].equilibrium_lost
        print(f"{f:.2f}   {H:14.6f}   {f * W:14.6f}   {res.counters['factorizations']}")
        assert abs(H / (f * W) - 1) < 1e-9
        assert res.counters["factorizations"] == 0

    both = m.replace(program=(sc.Segment("weight", 1.0),
                              sc.Segment("push and uplift", 1.0,
                                         rates={"push": 2e4, "uplift": 0.5})))
    res = sc.solve_static(both, condensation=c)
    t = res.multipliers[-1].equilibrium_lost
    t_exact = 0.5 * W / (2e4 + 0.25 * W)
    print(f"push and uplift together: slides at t = {t:.10f} (closed form {t_exact:.10f})")
    assert abs(t / t_exact - 1) < 1e-9


def study_on_a_process_pool() -> None:
    """A grid of friction × pressure over the demo model file, on a local process pool."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    demo = files("stepcontact") / "data" / "demo.toml"
    doc = tomllib.loads(demo.read_text(encoding="utf-8"))
    func = ModelCase(doc=doc, base_dir=str(OUTPUT), results_dir=str(OUTPUT / "results"),
                     outputs=("first_slip", "equilibrium_lost", "status", "events"),
                     model_name="block-slide", save_results=False)
    cases = grid({"interfaces.joint.friction": [0.3, 0.45, 0.6],
                  "patterns.push.loads.0.normal": [1e4, 2e4]})  # -, Pa per unit λ
    ds = run_sweep(cases, func, OUTPUT / "store", executor="process", workers=2)
    print(ds)
    assert (ds.case_status == "ok").all()
    g = to_grid(ds)
    f = g["interfaces.joint.friction"]
    p = g["patterns.push.loads.0.normal"]
    W = 2400 * 9.81 * 2 * 1  # the block's weight, N per metre run
    slide = g.equilibrium_lost * p  # horizontal load at sliding, N per metre run
    assert float(abs(slide / (f * W) - 1).max()) < 1e-6  # the closed form f·W
    fig, ax = plt.subplots(figsize=(5, 3.5))
    for j, pj in enumerate(p.values):
        ax.plot(f, g.first_slip.isel({p.name: j}) * pj / 1e3, "o-",
                label=f"first slip, p = {pj / 1e3:g} kPa per unit λ")
    ax.plot(f, slide.isel({p.name: 0}) / 1e3, "k--", label="sliding (f·W)")
    ax.set_xlabel("friction coefficient f")
    ax.set_ylabel("horizontal load, kN per m")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(OUTPUT / "first_slip.png", dpi=120)
    plt.close(fig)
    print(f"written: {OUTPUT / 'store' / 'sweep.nc'}, {OUTPUT / 'first_slip.png'}")


if __name__ == "__main__":  # the process pool imports this file in its workers: keep the guard
    one_condensation()
    OUTPUT.mkdir(exist_ok=True)
    study_on_a_process_pool()
