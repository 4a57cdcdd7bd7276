"""The stilling-basin study (method.md §7; the article's Figs. 4–5): the limit thickness of an
apron slab against the position of the pressure impulse, from the hydraulics of the design
discharge.

Inputs (:class:`BasinStudy`, SI): the critical depth h_kr of the design unit discharge
(3.48 m in the article), the energy head E0 above the apron, the jump-length formula, the
slab (length (1–1.25) L_j, concrete), its foundation (soil, friction, optional compliant
layer) and the impulse cases (positions x/L_p, directions, durations, amplitude as a fraction
of the velocity head V1²/2g, footprint).  The loads follow
:mod:`stepcontact.study.hydraulics`:

* on the slab's top, the mean pressure of the jump: hydrostatic under its mean surface profile
  (Hager's tanh profile), ρ_w g y(x);
* in the joint under the slab (referred to the top's level), the tailwater pressure ρ_w g h2
  plus a residual seepage head (m, default 0), and the slab's buoyancy γ_w h;
* the impulse: ``fraction`` ρ_w V1²/2 over the footprint, down on the top or up in the joint,
  half-sine in time.

Each case's limit thickness (:func:`stepcontact.study.slab.limit_thickness`) is one case of
a sweep (:func:`stepcontact.study.sweep.run_sweep`): resumable, on a process pool or a
dask.distributed cluster.  The static case (no impulse) gives the dashed line of Fig. 5.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model import ContactLayer, Material
from stepcontact.study import hydraulics as hy
from stepcontact.study.slab import (
    CRITERIA,
    DIRECTIONS,
    GAP_PRESSURES,
    JOINT,
    Impulse,
    Slab,
    check,
    limit_thickness,
)


@dataclass(frozen=True)
class BasinStudy:
    """The inputs of the stilling-basin study (SI units; defaults: the article's h_kr and the
    reference case of docs/slab-hydraulics.md).

    Hydraulics: ``h_kr`` (m), ``E0`` (m), ``phi`` (velocity coefficient), ``jump_length``
    (formula of :func:`~stepcontact.study.hydraulics.jump_length`), ``slab_factor``
    (L_p = factor · L_j), ``residual_head`` (m of seepage head in the joint beyond the
    tailwater).  Slab and foundation: ``concrete``, ``soil``, ``soil_depth`` (m, default
    L_p/2), ``friction``, ``layer``, ``cells`` (along, through the slab), ``added_mass``
    (the tailwater depth h2 of water above the slab moves with it in the response),
    ``layer_thickness`` (m: a compliant layer of the soil's E and ν that thick in the joint,
    eq. (11), when ``layer`` is not given), ``end_joints`` (friction of the joints against the
    neighbouring slabs, taken as rigid; None: free ends), ``gap_pressure`` (the pressure in
    the opened joint: "uplift", or "joint" — the upstream joint's pressure, mean and impulse,
    following the opened length; :class:`~stepcontact.study.slab.Slab`).  Impulses:
    ``positions`` (x/L_p of the footprint's centre), ``directions``, ``durations`` (s),
    ``amplitude`` (fraction of ρ_w V1²/2), ``footprint`` (m), ``shape``.  Search: ``tol`` (m),
    ``h0`` (m, first trial), ``criterion``, ``no_slip``, ``steps`` (time steps per impulse
    duration), ``alpha`` (HHT)."""

    h_kr: float = 3.48
    E0: float = 25.0
    phi: float = 0.95
    jump_length: str = "usbr"
    slab_factor: float = 1.0
    residual_head: float = 0.0
    concrete: Material = field(default_factory=lambda: Material(30e9, 0.2, 2400.0))
    soil: Material = field(default_factory=lambda: Material(100e6, 0.3, 2000.0))
    soil_depth: float | None = None
    friction: float = 0.6
    layer: ContactLayer | None = None
    cells: tuple[int, int] = (40, 4)
    added_mass: bool = False
    layer_thickness: float | None = None
    end_joints: float | None = None
    gap_pressure: str = "uplift"
    positions: tuple[float, ...] = (0.05, 0.2, 0.35, 0.5, 0.65, 0.8, 0.95)
    directions: tuple[str, ...] = DIRECTIONS
    durations: tuple[float, ...] = (0.1, 1.0)
    amplitude: float = 0.4
    footprint: float = 5.0
    shape: str = "half_sine"
    tol: float = 0.02
    h0: float | None = None
    criterion: str = "opening"
    no_slip: bool = False
    steps: int = 60
    alpha: float = 0.05

    def __post_init__(self):
        if self.criterion not in CRITERIA:
            raise ModelError("criterion", f"'{self.criterion}' is not one of "
                             f"{', '.join(CRITERIA)}")
        if self.gap_pressure not in GAP_PRESSURES:
            raise ModelError("gap_pressure", f"'{self.gap_pressure}' is not one of "
                             f"{', '.join(GAP_PRESSURES)}")
        for d in self.directions:
            if d not in DIRECTIONS:
                raise ModelError("directions", f"'{d}' is not one of {', '.join(DIRECTIONS)}")
        for key in ("amplitude", "footprint", "tol", "slab_factor"):
            v = getattr(self, key)
            if not (np.isfinite(v) and v > 0):
                raise ModelError(key, f"must be positive, got {v}")
        if not all(0.0 <= p <= 1.0 for p in self.positions):
            raise ModelError("positions", f"are x/L_p, in [0, 1]; got {self.positions}")
        if not all(np.isfinite(t) and t > 0 for t in self.durations):
            raise ModelError("durations", f"must be positive (s), got {self.durations}")
        if self.steps < 4:
            raise ModelError("steps", f"give at least 4 time steps per impulse, got {self.steps}")
        _ = self.jump  # the hydraulics check their inputs

    @property
    def jump(self) -> hy.Jump:
        return hy.hydraulic_jump(self.h_kr, self.E0, self.phi, self.jump_length)

    @property
    def length(self) -> float:
        """L_p, m."""
        return hy.slab_length(self.jump, self.slab_factor)

    def slab(self, thickness: float | None = None) -> Slab:
        """The :class:`Slab` of the study (its static loads from the hydraulics)."""
        jump, L = self.jump, self.length
        h = self.h_kr * 0.5 if thickness is None else float(thickness)
        top = _TopPressure(jump)
        uplift = _JointPressure(jump, self.residual_head)
        layer = self.layer
        if layer is None and self.layer_thickness is not None:
            layer = ContactLayer(thickness=self.layer_thickness, E=self.soil.E, nu=self.soil.nu)
        return Slab(length=L, thickness=h, concrete=self.concrete, soil=self.soil,
                    soil_depth=self.soil_depth, friction=self.friction, layer=layer,
                    end_joints=self.end_joints, gap_pressure=self.gap_pressure,
                    top=top, uplift=uplift, cells=self.cells,
                    water_depth=jump.h2 if self.added_mass else 0.0)

    def impulse(self, position: float, direction: str, duration: float) -> Impulse:
        return Impulse(position, hy.impulse_amplitude(self.jump, self.amplitude), duration,
                       footprint=self.footprint, direction=direction, shape=self.shape,
                       start=0.0)

    def cases(self):
        """The sweep's cases: ``static`` (position −1, direction "none", duration 0) and one
        per position × direction × duration."""
        from stepcontact.study.sweep import cases_from_list

        rows = [{"id": "static", "kind": "static", "position": -1.0, "direction": "none",
                 "duration": 0.0}]  # (no impulse: its fields are placeholders)
        rows += [{"id": f"{d}-t{t:g}-x{p:g}", "kind": "impulse", "position": float(p),
                  "direction": d, "duration": float(t)}
                 for d in self.directions for t in self.durations for p in self.positions]
        return cases_from_list(rows)


@dataclass(frozen=True)
class _TopPressure:
    """ρ_w g y(x) of the jump's mean profile (picklable for the worker processes)."""

    jump: hy.Jump

    def __call__(self, x):
        return hy.top_pressure(self.jump, x)


@dataclass(frozen=True)
class _JointPressure:
    """Tailwater plus residual seepage head in the joint, referred to the top's level, Pa."""

    jump: hy.Jump
    residual_head: float = 0.0

    def __call__(self, x):
        return hy.base_uplift(self.jump, x, residual_head=self.residual_head)


@dataclass(frozen=True)
class BasinCase:
    """The case function of the sweep: the limit thickness of one impulse case (or of the
    static loads), with the contact stresses of the failing slab just before it lifts off;
    the run at the failing thickness is kept as ``results/<case>.nc`` under ``results``."""

    study: BasinStudy
    results: str | None = None

    @property
    def sweep_key(self) -> str:
        import hashlib

        return hashlib.blake2b(repr(self.study).encode(), digest_size=8).hexdigest()

    def __call__(self, params: dict) -> dict:
        from stepcontact.study.sweep import current_case

        st = self.study
        slab = st.slab(st.h0 if st.h0 is not None else 0.5 * st.h_kr)
        imp = None
        opts: dict = {"criterion": st.criterion, "no_slip": st.no_slip, "alpha": st.alpha}
        if params["kind"] == "impulse":
            imp = st.impulse(params["position"], params["direction"], params["duration"])
            opts["dt"] = imp.duration / st.steps
            opts["duration"] = imp.start + 1.5 * imp.duration
        lim = limit_thickness(slab, imp, tol=st.tol, **opts)
        failing = check(slab.with_thickness(lim.failing), imp, keep=True, **opts) \
            if lim.failing > 0 else None
        out = {"h_limit": lim.thickness, "h_ratio": lim.thickness / st.h_kr,
               "h_failing": lim.failing, "runs": len(lim.trials),
               "mode": "", "when": np.nan, "x": np.full(slab.cells[0] + 1, np.nan),
               "sigma_n": np.full(slab.cells[0] + 1, np.nan),
               "tau": np.full(slab.cells[0] + 1, np.nan), "before": np.nan}
        if failing is not None and failing.result is not None:
            res = failing.result
            out["mode"] = "lift-off" if failing.lifted else "sliding"
            out["when"] = np.nan if failing.when is None else failing.when
            x, sn, tau, before = edge_stresses(res)
            n = min(len(x), len(out["x"]))
            out["x"][:n], out["sigma_n"][:n], out["tau"][:n] = x[:n], sn[:n], tau[:n]
            out["before"] = before
            case = current_case()
            if self.results is not None and case is not None:
                Path(self.results).mkdir(parents=True, exist_ok=True)
                res.save(Path(self.results) / f"{case.id}.nc")
        return out


def edge_stresses(res) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Contact stresses along the joint (position x from the upstream edge, σ_n, τ in Pa)
    at the last reported state before the first opening of a CFE of the joint (or at the
    last state if none opens), and that state's load parameter (λ or t)."""
    k = np.flatnonzero(res.cfe["interface"] == list(res.interface_names).index(JOINT))
    order = np.argsort(res.cfe["x"][k, 0])
    k = k[order]
    opened = [e for e in res.events if e.interface == JOINT and e.transition.name == "OPENED"]
    if opened:
        e0 = min(opened, key=lambda e: (e.segment, e.lam))
        i = max(int(e0.state) - 1, 0)
        while i > 0 and (res.segment[i] == e0.segment and res.lam[i] >= e0.lam):
            i -= 1
    else:
        i = len(res.lam) - 1
    area = res.cfe["area"][k]
    return (res.cfe["x"][k, 0], res.N[i, k] / area, res.Q[i, k] / area, float(res.lam[i]))


def run_basin(study: BasinStudy, store: str | Path, *, executor="process",
              workers: int | None = None, progress: bool = True, rerun: bool = False):
    """Run every case of ``study`` (limit thicknesses) into ``store`` and return the
    collected dataset (:func:`stepcontact.study.sweep.collect`; one row per case: ``kind``,
    ``position``, ``direction``, ``duration``, ``h_limit`` (m), ``h_ratio`` (h/h_kr),
    ``mode``, ``when``, the edge stresses ``x``, ``sigma_n``, ``tau`` (Pa))."""
    from stepcontact.study.sweep import run_sweep

    store = Path(store)
    func = BasinCase(study, str(store / "results"))
    return run_sweep(study.cases(), func, store, executor=executor, workers=workers,
                     progress=progress, rerun=rerun, name="slab study")


def envelope(ds) -> dict[str, np.ndarray]:
    """The limit thickness ratio h/h_kr against x/L_p: per direction (max over durations)
    and the envelope over all impulse cases; and the static limit."""
    kind = np.asarray(ds["kind"].values).astype(str)
    pos = np.asarray(ds["position"].values, float)
    ratio = np.asarray(ds["h_ratio"].values, float)
    dirs = np.asarray(ds["direction"].values).astype(str)
    imp = kind == "impulse"
    xs = np.unique(pos[imp])
    out: dict[str, np.ndarray] = {"x": xs}
    for d in np.unique(dirs[imp]):
        out[d] = np.array([np.nanmax(np.where(imp & (dirs == d) & (pos == x), ratio, np.nan))
                           for x in xs])
    out["envelope"] = np.array([np.nanmax(np.where(imp & (pos == x), ratio, np.nan))
                                for x in xs]) if xs.size else xs
    st = ratio[kind == "static"]
    out["static"] = np.array([st[0] if st.size else np.nan])
    return out


def design_table(study: BasinStudy, ds=None) -> list[tuple[str, float, str]]:
    """The study's limits beside the design formulas for the same inputs: (name, thickness
    in m, source/note)."""
    jump, L = study.jump, study.length
    gc = study.concrete.density * hy.G
    rows: list[tuple[str, float, str]] = []
    if ds is not None:
        env = envelope(ds)
        rows.append(("this study, static loads only", float(env["static"][0]) * study.h_kr,
                     f"criterion: {study.criterion}"))
        if env["envelope"].size:
            rows.append(("this study, envelope of the impulses",
                         float(np.nanmax(env["envelope"])) * study.h_kr,
                         f"amplitude {study.amplitude:g} ρV1²/2, footprint "
                         f"{study.footprint:g} m"))
    x = np.linspace(0.0, L, 2001)
    net = hy.base_uplift(jump, x, residual_head=study.residual_head) - hy.top_pressure(jump, x)
    # flotation (USACE ETL 1110-2-307): SF = W / (U − W_G) with the net uplift on the slab
    U_net = float(np.sum(0.5 * (net[1:] + net[:-1]) * np.diff(x)))  # N/m, trapezoids
    for case, sf in hy.USACE_FLOTATION_REQUIRED.items():
        rows.append((f"USACE flotation, SF = {sf:g} ({case})", sf * U_net / ((gc - hy.GAMMA_W)
                                                                           * L),
                     "ETL 1110-2-307; net uplift of the mean profile"))
    cp, cm = hy.extreme_coefficients(10.0)
    rows.append(("Fiorotto & Rinaldo (1992), Ω = 0.15",
                 hy.fiorotto_rinaldo_thickness(jump.V1, 0.15, float(cp), float(cm), gamma_c=gc),
                 f"C⁺p + C⁻p = {float(cp + cm):.2f} at 10 h1 [RECALLED defaults]"))
    rows.append(("Fiorotto & Rinaldo (1992), Ω = 0.15, C⁺p + C⁻p = 0.8",
                 hy.fiorotto_rinaldo_thickness(jump.V1, 0.15, 0.4, 0.4, gamma_c=gc),
                 "the reference case of docs/slab-hydraulics.md"))
    rows.append(("Dombrovsky, t = 0.15 V1 √h1", hy.dombrovsky_thickness(jump.V1, jump.h1),
                 "[RECALLED]"))
    q0 = float(net[0])
    rows.append(("kern rule, rigid slab on a Winkler bed, deficit of the mean profile",
                 hy.kern_liftoff_thickness(q0, L, L, q1=float(net[-1]), gamma_c=gc),
                 "linear fit through the ends of the net uplift"))
    return rows


def quick(**changes) -> BasinStudy:
    """A coarse version of the study (a few minutes on one core): three positions, one
    duration, a coarse mesh and tolerance."""
    base = dict(cells=(20, 2), positions=(0.1, 0.5, 0.9), durations=(0.5,), tol=0.05,
                steps=30)
    base.update(changes)
    return dataclasses.replace(BasinStudy(), **base)


__all__ = ["BasinCase", "BasinStudy", "design_table", "edge_stresses", "envelope", "quick",
           "run_basin"]

