"""What a run would refuse, found from the model alone (no assembly, no solving).

``stepcontact validate`` and ``stepcontact run`` call :func:`check_consistency` before
anything is solved, so that a model ``validate`` passes is not rejected by ``run`` after
minutes of work for a reason the model itself shows.  Each check names the stage, segment,
pattern or body concerned:

* a dynamic interval of a stage needs the mass of every body standing at that stage (a body
  of density 0 makes the mass matrix singular on its free DOFs);
* a pattern whose factor is a water level (a :class:`~stepcontact.model.WaterLoad` with
  ``level=None``) is moved by segments of its own, not by a segment with rates, and its first
  segment starts with the level at or below the lowest point of its wetted faces (else the
  water would load the structure at once, before the first state);
* a bond with a residual cohesion cannot be followed through a dynamic interval, nor a
  bonded joint with a damped contact layer;
* the strengths of a bond are ≥ 0 and a tension cut-off is not beyond the apex c·cot φ;
* crack water enters its joint at a point of it, and a given level is above the joint;
* a dynamic interval does not follow a prescribed displacement that stands at a nonzero
  factor when it starts (a staged model), and a body is not built at a stage while a
  prescribed displacement of its nodes stands at a nonzero factor.

:func:`program_warnings` lists segments that change nothing (λ from a value to itself).

Example
-------
>>> from importlib.resources import files
>>> from stepcontact.io.modelfile import load_model
>>> check_consistency(load_model(files("stepcontact") / "data" / "demo.toml"))
"""

from __future__ import annotations

import numpy as np

from stepcontact.errors import ModelError
from stepcontact.model.bodies import Body, Frame
from stepcontact.model.loads import PrescribedDisplacement
from stepcontact.model.structure import Model


def _density(b) -> float:
    return float(b.material.density) if isinstance(b, Body) else float(b.density)


def _stage_bodies(model: Model, k: int) -> list:
    """The bodies standing at stage ``k`` (not built by a later stage)."""
    later = {name for st in model.stages[k + 1:] for name in st.bodies}
    return [b for b in model.bodies if b.name not in later]


def check_stage_mass(model: Model) -> None:
    """Every body standing at a stage with a dynamic interval has mass (density > 0)."""
    for k, st in enumerate(model.stages):
        if getattr(st, "dynamics", None) is None:
            continue
        for b in _stage_bodies(model, k):
            if isinstance(b, Body | Frame) and not _density(b) > 0:
                kind = "frame" if isinstance(b, Frame) else "body"
                where = "" if isinstance(b, Frame) else " (its material's)"
                raise ModelError(f"stage '{st.name}'.dynamics", f"{kind} '{b.name}' has no "
                                 f"mass: its density{where} is 0 kg/m³, and a dynamic interval "
                                 "needs the mass of every body (the mass matrix would be "
                                 "singular on its DOFs); give it a density in kg/m³")


def _level_patterns(model: Model) -> dict[str, float]:
    """The patterns whose factor is a water level, with the lowest point of their wetted
    faces (m)."""
    from stepcontact.model.water import WaterLoad

    out: dict[str, float] = {}
    for p in model.patterns:
        ys = [model.body(ld.nodes.body).points[ld.nodes.index][:, 1]
              for ld in p.loads if isinstance(ld, WaterLoad) and ld.level is None]
        if ys:
            out[p.name] = float(np.concatenate(ys).min())
    return out


def check_level_segments(model: Model) -> None:
    """A water-level pattern moves by segments of its own, and its first one starts with the
    level at or below the lowest point of its wetted faces."""
    levels = _level_patterns(model)
    if not levels:
        return
    for st in model.stages[:-1]:  # a dynamic interval before the last stage moves a factor
        dyn = getattr(st, "dynamics", None)
        for name, _g in () if dyn is None else dyn.loads:
            if name in levels:
                raise ModelError(f"stage '{st.name}'.dynamics.loads['{name}']", f"pattern "
                                 f"'{name}' has the water level as its factor: a dynamic "
                                 "interval cannot move it (a time function's value is not a "
                                 "water level, and the static stages after it could not go on "
                                 "from it); give the interval a pattern of its own")
    resolved = model.segments_resolved()
    moved: set[str] = set()
    jumps = model.dynamic_jumps()
    for i, seg in enumerate(model.effective_program):
        for name in jumps.get(i, {}):
            moved.add(name)
        item = f"program segment {i} ('{seg.pattern}')"
        if seg.rates is not None:
            hit = [n for n, _ in seg.rates if n in levels]
            if hit:
                raise ModelError(item, f"pattern '{hit[0]}' has the water level as its factor: "
                                 "move it by a segment of its own, not with rates")
            continue
        if seg.pattern not in levels or seg.pattern in moved:
            continue
        moved.add(seg.pattern)
        start, low = resolved[i][1], levels[seg.pattern]
        if start > low + 1e-12 * max(1.0, abs(low)):
            raise ModelError(item, f"the water level starts at {start:g} m, where it already "
                             f"loads the structure (its wetted faces reach down to y = {low:g} "
                             "m): start the level at or below that, or let an earlier segment "
                             "raise it")


def check_dynamic_bonds(model: Model) -> None:
    """No bond with a residual cohesion in a model with a dynamic interval after its program
    (one of a stage before the last is refused by the stage plan,
    :class:`~stepcontact.solver.staging.StagePlan`, which validate builds too)."""
    if model.dynamics is None:
        return
    bonds = [(f"interface '{i.name}'.bond", i.bond) for i in model.interfaces
             if i.bond is not None]
    bonds += [(f"stage '{st.name}'.grout['{name}']", b) for st in model.stages
              for name, b in st.grout.items()]
    for item, bond in bonds:
        rc = bond.residual_cohesion
        if callable(rc) or np.ndim(rc) > 0 or float(rc) != 0.0:
            raise ModelError(f"{item}.residual_cohesion", "a residual cohesion after the "
                             "break is followed in static load programs; a dynamic interval "
                             "with one is not supported yet (give residual_cohesion = 0)")


def _factors_after(model: Model, n: int | None = None, jump: bool = True
                   ) -> dict[str, float]:
    """The factor of every pattern after the first ``n`` segments of the load program (all
    when None) and the dynamic intervals of the stages they belong to (``jump`` False: not
    that of the stage the ``n``-th segment ends)."""
    current: dict[str, float] = {}
    jumps = model.dynamic_jumps()
    resolved = model.segments_resolved()
    n = len(resolved) if n is None else n
    for i, (seg, (label, a, b)) in enumerate(zip(model.effective_program[:n], resolved[:n],
                                                  strict=True)):
        for name, dg in jumps.get(i, {}).items():
            current[name] = current.get(name, 0.0) + dg
        if seg.rates is None:
            current[label] = b
        else:
            for name, rate in seg.rates:
                current[name] = current.get(name, 0.0) + rate * (b - a)
    for name, dg in jumps.get(n, {}).items() if jump else ():
        current[name] = current.get(name, 0.0) + dg
    return current


def check_dynamic_displacements(model: Model) -> None:
    """No dynamic interval of a stage starts with a prescribed displacement at a nonzero
    factor."""
    n = 0
    for st in model.stages:
        n += len(st.program)
        if getattr(st, "dynamics", None) is None:
            continue
        factors = _factors_after(model, n, jump=False)
        for p in model.patterns:
            if not factors.get(p.name, 0.0):
                continue
            if any(isinstance(ld, PrescribedDisplacement) and ld.value != 0 for ld in p.loads):
                raise ModelError(f"pattern '{p.name}'", "prescribes nonzero displacements when "
                                 f"the dynamic interval of stage '{st.name}' starts (factor "
                                 f"{factors[p.name]:g}): a dynamic interval does not follow "
                                 "prescribed displacements (place the support before its body "
                                 "moves, or let the pattern return to 0)")


def check_damped_bonds(model: Model) -> None:
    """A bonded joint with a damped contact layer (Kelvin–Voigt, c_n > 0) cannot go through
    the model's last dynamic interval (one before the last stage refuses any damped layer:
    the static stages cannot follow it): refused unless the layer has no damping."""
    if model.dynamics is None:
        return
    grouted = {name for st in model.stages for name in st.grout}
    for itf in model.interfaces:
        if itf.layer is None or not itf.layer.damping > 0:
            continue
        if itf.bond is not None or itf.name in grouted:
            raise ModelError(f"interface '{itf.name}'.bond", "a bonded joint with a damped "
                             "contact layer (Kelvin–Voigt, c_n > 0) is not supported in a "
                             "dynamic interval (it is refused when the interval starts with "
                             "its bond intact): give the layer no damping")


def check_built_bodies(model: Model) -> None:
    """A body built at a stage has no prescribed displacement standing at a nonzero factor
    when it is built (it is placed stress-free where the structure stands)."""
    n = 0
    for st in model.stages:
        if st.bodies:
            factors = _factors_after(model, n)
            for p in model.patterns:
                c = factors.get(p.name, 0.0)
                hit = [ld for ld in p.loads if isinstance(ld, PrescribedDisplacement)
                       and ld.value != 0 and ld.nodes.body in st.bodies]
                if c and hit:
                    raise ModelError(f"stage '{st.name}'", f"body '{hit[0].nodes.body}' is "
                                     f"built while pattern '{p.name}' prescribes displacements "
                                     f"of its nodes at factor {c:g}: start that pattern after "
                                     "the body is built")
        n += len(st.program)


def check_crack_water(model: Model) -> None:
    """Crack water enters its 2D joint at a point of it (within one node spacing of an S+
    node, where the CFEs are; a 3D joint's entry edge: the assembly, fem.crack) and its
    level, if given, is above the joint's lowest point
    (:meth:`~stepcontact.model.water.CrackWater.check_entries`, ``check_level``; the
    assembly checks the same at the CFEs)."""
    from stepcontact.model.water import CrackWater

    interfaces = {i.name: i for i in model.interfaces}
    for p in model.patterns:
        for ld in p.loads:
            if not isinstance(ld, CrackWater) or ld.name not in interfaces:
                continue  # (an unknown interface is the assembly's error)
            itf = interfaces[ld.name]
            pts = model.body(itf.plus.body).points[itf.plus.index]
            ld.check_level(pts[:, -1], f"load pattern '{p.name}': crack water in interface "
                           f"'{ld.name}'")  # the height: y (2D), z (3D)
            if ld.entry is not None and len(pts) and pts.shape[1] == 2 == ld.entry_dim:
                c = pts.mean(axis=0)
                d = np.linalg.svd(pts - c, full_matrices=False)[2][0] if len(pts) > 1 else c
                order = np.argsort((pts - c) @ d, kind="stable")
                CrackWater.check_entries(ld.entries, pts[order],
                                         f"crack water in interface '{ld.name}'.entry")


def check_bonds(model: Model) -> None:
    """The strengths of every bond (of an interface, or grouted at a stage) at the S+ nodes
    of its joint: finite, ≥ 0, and a tension cut-off not beyond the apex of the shear facets
    (Mohr–Coulomb: σ_t ≤ c·cot φ; :meth:`~stepcontact.model.bond.Bond.arrays`, which the
    assembly calls at the CFEs)."""
    interfaces = {i.name: i for i in model.interfaces}
    bonds = [(f"interface '{i.name}'", i, i.bond) for i in model.interfaces
             if i.bond is not None]
    bonds += [(f"stage '{st.name}'.grout['{name}']", interfaces[name], b)
              for st in model.stages for name, b in st.grout.items() if name in interfaces]
    for item, itf, bond in bonds:
        pts = model.body(itf.plus.body).points[itf.plus.index]
        bond.arrays(pts, np.ones(len(pts)), item)


def check_consistency(model: Model) -> None:
    """Raise a :class:`ModelError` for the first thing a run would refuse that the model
    shows without solving (see the module's docstring)."""
    check_stage_mass(model)
    check_built_bodies(model)
    check_crack_water(model)
    check_bonds(model)
    check_level_segments(model)
    check_dynamic_bonds(model)
    check_dynamic_displacements(model)
    check_damped_bonds(model)


def program_warnings(model: Model) -> list[tuple[str, str]]:
    """(item, text) for every segment of the program that changes nothing."""
    out = []
    for i, (name, a, b) in enumerate(model.segments_resolved()):
        if a == b:
            out.append((f"program segment {i} ('{name}')", f"goes from λ = {a:g} to {b:g}: "
                        "it changes nothing (give it a different end)"))
    return out


__all__ = ["check_bonds", "check_built_bodies", "check_consistency", "check_crack_water",
           "check_damped_bonds", "check_dynamic_bonds", "check_dynamic_displacements",
           "check_level_segments", "check_stage_mass", "program_warnings"]
