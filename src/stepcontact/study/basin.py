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
        """The case's outputs (SI): ``h_limit``, ``h_ratio``, ``h_failing``, ``runs``,
        ``mode``, ``when``, the stresses ``x``, ``sigma_n``, ``tau`` and ``before`` of
        :func:`edge_stresses`, ``x_open`` (m: where the joint first opens at the failing
        thickness, NaN if it slides), ``seconds`` (wall time) and ``software``/``computed``
        (:func:`~stepcontact.study.provenance.provenance`).  A parameter ``h0`` (m) starts the
        search there, moving by the study's ``tol`` (a search near a known limit: the mesh
        check)."""
        import time

        from stepcontact.study.provenance import provenance
        from stepcontact.study.sweep import current_case

        t0 = time.perf_counter()
        st = self.study
        near = params.get("h0")
        h0 = float(near) if near is not None else st.h0 if st.h0 is not None \
            else 0.5 * st.h_kr
        slab = st.slab(h0)
        imp = None
        opts: dict = {"criterion": st.criterion, "no_slip": st.no_slip, "alpha": st.alpha}
        if params["kind"] == "impulse":
            imp = st.impulse(params["position"], params["direction"], params["duration"])
            opts["dt"] = imp.duration / st.steps
            opts["duration"] = imp.start + 1.5 * imp.duration
        lim = limit_thickness(slab, imp, tol=st.tol, step=st.tol if near is not None else None,
                              **opts)
        failing = check(slab.with_thickness(lim.failing), imp, keep=True, **opts) \
            if lim.failing > 0 else None
        info = provenance()
        out = {"h_limit": lim.thickness, "h_ratio": lim.thickness / st.h_kr,
               "h_failing": lim.failing, "runs": len(lim.trials),
               "mode": "", "when": np.nan, "x": np.full(slab.cells[0] + 1, np.nan),
               "sigma_n": np.full(slab.cells[0] + 1, np.nan),
               "tau": np.full(slab.cells[0] + 1, np.nan), "before": np.nan,
               "x_open": np.nan, "software": str(info["software"]),
               "computed": str(info["date"])}
        if failing is not None and failing.result is not None:
            res = failing.result
            out["mode"] = "lift-off" if failing.lifted else "sliding"
            out["when"] = np.nan if failing.when is None else failing.when
            x, sn, tau, before = edge_stresses(res)
            n = min(len(x), len(out["x"]))
            out["x"][:n], out["sigma_n"][:n], out["tau"][:n] = x[:n], sn[:n], tau[:n]
            out["before"] = before
            out["x_open"] = first_opening(res)
            case = current_case()
            if self.results is not None and case is not None:
                Path(self.results).mkdir(parents=True, exist_ok=True)
                res.save(Path(self.results) / f"{case.id}.nc")
        out["seconds"] = time.perf_counter() - t0
        return out


def _first_opened(res):
    """The first OPENED event of the joint in a run (the earliest segment and parameter),
    or None."""
    opened = [e for e in res.events if e.interface == JOINT and e.transition.name == "OPENED"]
    return min(opened, key=lambda e: (e.segment, e.lam)) if opened else None


def first_opening(res) -> float:
    """x (m from the slab's upstream edge) of the CFE of the joint that opens first in a run
    (the smallest x of those opening at the same event point); NaN if none opens."""
    e0 = _first_opened(res)
    if e0 is None:
        return float("nan")
    same = [e for e in res.events if e.interface == JOINT and e.transition.name == "OPENED"
            and e.segment == e0.segment and e.lam == e0.lam]
    return float(min(e.x for e in same))


def edge_stresses(res) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Contact stresses along the joint (position x from the upstream edge, σ_n, τ in Pa)
    at the last reported state before the first opening of a CFE of the joint (or at the
    last state if none opens), and that state's load parameter (λ or t)."""
    k = np.flatnonzero(res.cfe["interface"] == list(res.interface_names).index(JOINT))
    order = np.argsort(res.cfe["x"][k, 0])
    k = k[order]
    e0 = _first_opened(res)
    if e0 is not None:
        i = max(int(e0.state) - 1, 0)
        while i > 0 and (res.segment[i] == e0.segment and res.lam[i] >= e0.lam):
            i -= 1
    else:
        i = len(res.lam) - 1
    area = res.cfe["area"][k]
    return (res.cfe["x"][k, 0], res.N[i, k] / area, res.Q[i, k] / area, float(res.lam[i]))


def run_basin(study: BasinStudy, store: str | Path, *, executor="process",
              workers: int | None = None, progress: bool = True, rerun: bool = False,
              mesh_check: bool = True):
    """Run every case of ``study`` (limit thicknesses) into ``store`` and return the
    collected dataset (:func:`stepcontact.study.sweep.collect`; one row per case: ``kind``,
    ``position``, ``direction``, ``duration``, ``h_limit`` (m), ``h_ratio`` (h/h_kr),
    ``mode``, ``when``, the edge stresses ``x``, ``sigma_n``, ``tau`` (Pa), ``x_open`` (m)).

    With ``mesh_check`` (default), the governing case is then solved again on a mesh twice
    as fine (:func:`check_mesh`, stored under ``store/mesh-check``, resumable like the cases)
    and the :class:`MeshCheck` is kept as the dataset's attribute ``mesh_check`` (JSON; read
    it with :meth:`MeshCheck.of`), also in ``store/sweep.nc``."""
    from stepcontact.io.atomic import write_netcdf
    from stepcontact.study.sweep import run_sweep

    store = Path(store)
    func = BasinCase(study, str(store / "results"))
    ds = run_sweep(study.cases(), func, store, executor=executor, workers=workers,
                   progress=progress, rerun=rerun, name="slab study")
    if not mesh_check:
        return ds
    chk = check_mesh(study, ds, store / "mesh-check", executor=executor, progress=progress,
                     rerun=rerun)
    if chk is not None:
        ds.attrs["mesh_check"] = chk.to_json()
        write_netcdf(ds, store / "sweep.nc")
    return ds


def governing(ds) -> str | None:
    """The id of the study's governing case: the impulse case with the largest limit
    thickness (the top of the envelope), else the static case; None when no case has a
    limit."""
    if "kind" not in ds.variables or "h_ratio" not in ds.variables:
        return None  # no case has a limit (e.g. every case failed)
    kind = np.asarray(ds["kind"].values).astype(str)
    ratio = np.asarray(ds["h_ratio"].values, float)
    for sel in (kind == "impulse", kind == "static"):
        r = np.where(sel, ratio, np.nan)
        if np.any(np.isfinite(r)):
            return str(ds["case"].values[int(np.nanargmax(r))])
    return None


def refined(study: BasinStudy, factor: int = 2) -> BasinStudy:
    """The study on a mesh ``factor`` times as fine: the slab's cells along and through the
    slab multiplied by ``factor`` (the foundation's cells follow the slab's along the
    joint, :class:`~stepcontact.study.slab.Slab`), everything else the same."""
    nx, ny = study.cells
    return dataclasses.replace(study, cells=(factor * nx, factor * ny))


def mesh_info(study: BasinStudy, thickness: float) -> dict:
    """The mesh of the study's model for a slab ``thickness`` (m): ``element`` (type),
    ``bodies`` ({name: (cells along x, cells along y, cell width m, cell height m,
    elements, nodes)}), ``cfes`` (CFEs of the joint), ``cfe_length`` (m, the length of an
    inner CFE), ``dofs`` (degrees of freedom of the assembled model)."""
    import warnings

    from stepcontact.fem.assembly import assemble
    from stepcontact.study.slab import slab_model

    with warnings.catch_warnings():  # the study's runs warn about its inputs, not this count
        warnings.simplefilter("ignore")
        model = slab_model(study.slab(thickness))
        system = assemble(model)
    bodies = {}
    for b in model.bodies:
        xs, ys = (np.unique(np.round(b.points[:, k], 9)) for k in (0, 1))
        nx, ny = len(xs) - 1, len(ys) - 1
        bodies[b.name] = (nx, ny, float(np.ptp(xs)) / nx, float(np.ptp(ys)) / ny,
                          int(len(b.cells)), int(b.n_nodes))
    k = np.flatnonzero(system.cfe.interface == list(system.cfe.names).index(JOINT))
    area = np.asarray(system.cfe.area)[k] / model.thickness
    return {"element": model.bodies[0].element, "bodies": bodies,
            "cfes": int(k.size), "cfe_length": float(np.median(area)),
            "dofs": int(system.ndof)}


#: a mesh check is acceptable when the two limits differ by at most this fraction ...
MESH_RELATIVE = 0.05


@dataclass(frozen=True)
class MeshCheck:
    """The governing case solved on two meshes (:func:`check_mesh`).

    ``case``: its id; ``cells``: the slab's cells (along, through) of the study's mesh and of
    the finer one; ``h``: the limit thickness on each (m, NaN if the fine run failed),
    ``h_failing``: the thickest failing trial on each (m); ``x_open``: where the joint first
    opens on each (m from the upstream edge, NaN when the slab slides); ``mode`` on each;
    ``tol``: the bisection tolerance (m); ``runs``, ``seconds``: trials and wall time of the
    fine search; ``status``/``message`` of the fine run ("ok" or "failed")."""

    case: str
    cells: tuple[tuple[int, int], tuple[int, int]]
    h: tuple[float, float]
    h_failing: tuple[float, float]
    x_open: tuple[float, float]
    mode: tuple[str, str]
    tol: float
    runs: int = 0
    seconds: float = float("nan")
    status: str = "ok"
    message: str = ""

    @property
    def difference(self) -> float:
        """h on the fine mesh minus h on the study's mesh, m."""
        return self.h[1] - self.h[0]

    @property
    def relative(self) -> float:
        """:attr:`difference` over the fine mesh's h."""
        return self.difference / self.h[1] if self.h[1] else float("nan")

    @property
    def acceptable(self) -> bool:
        """|Δh| within the bisection's tolerance, or within :data:`MESH_RELATIVE` of h."""
        d = abs(self.difference)
        return bool(np.isfinite(d) and (d <= self.tol * (1 + 1e-9)
                                        or d <= MESH_RELATIVE * abs(self.h[1])))

    def summary(self) -> str:
        """One line: the governing case's limit on both meshes, the difference and the
        verdict (:attr:`acceptable`)."""
        (a, b), (c, d) = self.cells
        head = f"mesh check ({self.case}): h_p {self.h[0]:.3f} m on {a} × {b}"
        if self.status != "ok":
            return f"{head}; the run on {c} × {d} failed: {self.message or self.status}"
        verdict = "acceptable" if self.acceptable else "NOT acceptable: refine the mesh"
        return (f"{head}, {self.h[1]:.3f} m on {c} × {d}: {self.difference:+.3f} m "
                f"({100 * self.relative:+.1f} %), {verdict}")

    def to_json(self) -> str:
        import json

        return json.dumps(dataclasses.asdict(self), allow_nan=True)

    @classmethod
    def from_json(cls, text: str) -> MeshCheck:
        import json

        d = json.loads(text)
        d["cells"] = tuple(tuple(int(v) for v in c) for c in d["cells"])
        for key in ("h", "h_failing", "x_open", "mode"):
            d[key] = tuple(d[key])
        return cls(**d)

    @classmethod
    def of(cls, ds) -> MeshCheck | None:
        """The check kept in a study's dataset (:func:`run_basin`), or None."""
        text = ds.attrs.get("mesh_check")
        return None if not text else cls.from_json(str(text))


def check_mesh(study: BasinStudy, ds, store: str | Path, *, executor="serial",
               progress: bool = False, rerun: bool = False,
               factor: int = 2) -> MeshCheck | None:
    """Solve the governing case of ``ds`` (:func:`governing`) again on the mesh ``factor``
    times as fine (:func:`refined`), starting the search at its limit on the study's mesh
    and moving by ``tol`` (two trials when the limit does not change by more than ``tol``).
    A one-case sweep in ``store`` (resumable: a rerun with the same limit runs nothing).
    Returns the :class:`MeshCheck`, or None when no case has a limit."""
    from stepcontact.study.sweep import cases_from_list, run_sweep

    gov = governing(ds)
    if gov is None:
        return None
    ids = [str(c) for c in ds["case"].values]
    i = ids.index(gov)

    def val(name, default=np.nan):
        return ds[name].values[i] if name in ds.variables else default

    h0 = float(val("h_limit"))
    params = {"id": gov, "kind": str(val("kind")), "position": float(val("position")),
              "direction": str(val("direction")), "duration": float(val("duration")),
              "h0": h0}
    fine = refined(study, factor)
    out = run_sweep(cases_from_list([params]), BasinCase(fine), store, executor=executor,
                    workers=1, progress=progress, rerun=rerun, name="mesh check")
    ok = str(out["case_status"].values[0]) == "ok"

    def fine_val(name):
        return out[name].values[0] if ok and name in out.variables else np.nan

    x0 = float(val("x_open"))
    mode0 = str(val("mode", ""))
    return MeshCheck(
        case=gov, cells=(tuple(study.cells), tuple(fine.cells)),
        h=(h0, float(fine_val("h_limit"))),
        h_failing=(float(val("h_failing")), float(fine_val("h_failing"))),
        x_open=(x0, float(fine_val("x_open"))),
        mode=(mode0, str(out["mode"].values[0]) if ok else ""),
        tol=study.tol, runs=int(fine_val("runs")) if ok else 0,
        seconds=float(fine_val("seconds")), status=str(out["case_status"].values[0]),
        message=str(out["case_message"].values[0]))


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
                 f"C⁺p + C⁻p = {float(cp + cm):.2f} at 10 h1 (defaults {hy.RECALLED})"))
    rows.append(("Fiorotto & Rinaldo (1992), Ω = 0.15, C⁺p + C⁻p = 0.8",
                 hy.fiorotto_rinaldo_thickness(jump.V1, 0.15, 0.4, 0.4, gamma_c=gc),
                 "the reference case of docs/slab-hydraulics.md"))
    rows.append(("Dombrovsky, t = 0.15 V1 √h1", hy.dombrovsky_thickness(jump.V1, jump.h1),
                 hy.RECALLED))
    q0 = float(net[0])
    rows.append(("kern rule, rigid slab on a Winkler bed, deficit of the mean profile",
                 hy.kern_liftoff_thickness(q0, L, L, q1=float(net[-1]), gamma_c=gc),
                 "linear fit through the ends of the net uplift"))
    return rows


def quick(**changes) -> BasinStudy:
    """A coarse version of the study (about 30 s on two cores, with the mesh check of
    :func:`run_basin` on a 40 × 4 mesh): three positions, one duration, a 20 × 2 slab mesh
    and a tolerance of 5 cm."""
    base = dict(cells=(20, 2), positions=(0.1, 0.5, 0.9), durations=(0.5,), tol=0.05,
                steps=30)
    base.update(changes)
    return dataclasses.replace(BasinStudy(), **base)


__all__ = ["MESH_RELATIVE", "BasinCase", "BasinStudy", "MeshCheck", "check_mesh", "design_table",
           "edge_stresses", "envelope", "first_opening", "governing", "mesh_info", "quick",
           "refined", "run_basin"]

