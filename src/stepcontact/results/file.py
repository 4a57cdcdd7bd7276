"""Result files: a :class:`~stepcontact.results.StaticResult` as an :class:`xarray.Dataset`.

One result is one netCDF4/HDF5 file written with the ``h5netcdf`` engine.  The layout is
self-describing: every variable carries ``units`` (SI: N, m, Pa, m2, N m-1; ``"1"`` for
dimensionless numbers, indices and labels) and a ``long_name``.

Dimensions
----------
``state``
    Reported states (λ, forces, working scheme after each state).
``cfe``
    Contact finite elements; the CFE geometry arrays are ``cfe_<key>`` variables.
``tangent``
    The tangential components of a CFE along its tangents ("t1" in 2D; "t1", "t2" in 3D;
    the attribute ``tangential_components`` is their number n_t): the tangential variables
    ``Q``, ``ut`` (state × cfe × tangent) and ``event_Q_t`` (event × tangent).  Format
    version 2; a version-1 file has ``Q``, ``ut`` on (state × cfe) and no ``event_Q_t``.
    With n_t > 1 the file has ``Q_abs`` (state × cfe) = |Q| too, for other readers (derived,
    not read back), and the CFE data the faceted cone's number of facets (``facets`` in the
    attribute ``cfe_extra``).
``event``
    The event log, one entry per CFE transition (``event_<field>`` variables; a 3D result
    also ``event_z``, the z of each event's CFE; a file without it loads with ``z`` None).
``pattern``, ``interface``, ``segment_index``, ``multiplier``
    Load patterns, interface names, load-program segments, stability multipliers.
``field_state``, ``dof``
    Stored displacement vectors ``u``: only the states whose field the run stored (by default
    the start, segment starts and ends and the last state; the attribute ``field_states``
    lists them).  Every other state is exact from its contact unknowns:
    ``StaticResult.recover_fields(model)`` recomputes it.
``node``, ``xy``, ``node_dof``, ``element__<body>``, ``cell_node__<body>``
    Geometry for drawing and export (``points``, ``dof_of``, ``cells__<body>``).  A 3D model's
    coordinate axis is ``xyz`` (x, y, z; the CFE vectors ``cfe_x``, ``cfe_normal`` … of 3D
    CFEs too) and its ``node_dof`` ux, uy, uz (rx, ry, rz with space frames); 2D keeps ``xy``
    and ux, uy, rz.
``stress_state__<body>``, ``stress_element__<body>``, ``stress_component``
    Element stresses ``stress__<body>`` (Pa): σxx, σyy, σxy, σzz in 2D; σxx, σyy, σzz, σxy,
    σyz, σxz (the labels xx, yy, zz, xy, yz, xz) in 3D.
``resultant_component``
    ``load_resultant`` (pattern × Fx, Fy, Mz; 3D: Fx, Fy, Fz, Mx, My, Mz): each pattern's
    force resultant per unit λ.
``load_body``, ``load_moment_component``
    ``load_moments`` (pattern × body × Fx, Fy, Sxx, Sxy, Syx, Syy, Mz_nodal): each pattern's
    forces per unit λ on each body, their first-moment tensor S_ab = Σ x_a f_b about the
    origin and nodal moments (the overturning factor's moments; absent in older files).
``impulse``
    A dynamic result's impulses of its impacts, one entry per CFE and impact
    (``impulse_state``, ``impulse_time``, ``impulse_cfe``, ``impulse_normal``,
    ``impulse_tangential``, N s); the events carry theirs too (``event_impulse_n``,
    ``event_impulse_t``; a file without these columns loads with 0).

Enumerations are stored so they round-trip: contact states as integers (int16) with CF
``flag_values`` / ``flag_meanings`` attributes (the 2D codes 0–5 and every faceted-cone code
present, e.g. ``slip_facet_3``), the rule of the faceted codes in the attribute ``facet_codes``
of ``contact_state`` and ``state_codes`` of the file (slip on facet i of a faceted Coulomb cone
= 16 + i, at its vertex i = 144 + i, i < 128: :mod:`stepcontact.enums`), transitions and the
run status as their string values.  Dictionaries without a natural array layout (counters,
mechanism, units) are JSON strings in the dataset attributes; JSON keeps floats exactly
(shortest ``repr``), so a save → load round trip is bit-exact.

Format versions
---------------
1. The 2D layout: ``Q``, ``ut`` (state × cfe), contact states as written (int64).
2. (Written now.)  The ``tangent`` dimension on the tangential variables (``Q``, ``ut``,
   ``event_Q_t``), the attribute ``tangential_components`` (n_t), contact states as int16
   holding the faceted-cone codes.  A 2D result loads with ``Q``, ``ut`` of shape
   (n_states, m) as before.

Both versions load; a file of a newer version than this code knows is refused.

Files are written atomically (temporary file in the target directory, then
:func:`os.replace`): an interrupted write never leaves a half-written result.

Example
-------
>>> from stepcontact.results import load_result, save_result
>>> save_result(res, "out/run.nc")          # doctest: +SKIP
>>> res2 = load_result("out/run.nc")        # doctest: +SKIP
"""

from __future__ import annotations

import json
import os
import re
import time
from enum import Enum
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from stepcontact import enums as _enums
from stepcontact.atomic import write_netcdf
from stepcontact.enums import (
    FACET_SLIP,
    MAX_FACETS,
    VERTEX_SLIP,
    ContactState,
    Status,
    Transition,
)
from stepcontact.fem.assembly import LOAD_MOMENT_COMPONENTS
from stepcontact.fem.continuum import STRESS_COMPONENTS_3D
from stepcontact.interrupt import deferred
from stepcontact.results.events import Event, Multipliers

#: a :class:`~stepcontact.results.result.StaticResult` or a
#: :class:`~stepcontact.results.result.DynamicResult`, read here through its attributes (the
#: result types build on this module for their ``save``, ``load`` and ``to_dataset``)
Result = Any

FORMAT = "stepcontact-static-result"
#: 2: the ``tangent`` dimension (module docstring, "Format versions"); 1 files still load
FORMAT_VERSION = 2

_XY = np.array(["x", "y"])
_XYZ = np.array(["x", "y", "z"])
_NODE_DOF = np.array(["ux", "uy", "rz"])
#: the nodal DOFs of a 3D model: translations (solids), then rotations (space frames)
_NODE_DOF_3D = np.array(["ux", "uy", "uz", "rx", "ry", "rz"])
_STRESS_COMPONENTS = np.array(["xx", "yy", "xy", "zz"])
#: a 3D body's six stress components, in the order of
#: :data:`stepcontact.fem.continuum.STRESS_COMPONENTS_3D`
_STRESS_COMPONENTS_3D = np.array(STRESS_COMPONENTS_3D)
_RESULTANT = np.array(["Fx", "Fy", "Mz"])
#: a 3D load resultant: the force and its moment about the origin
_RESULTANT_3D = np.array(["Fx", "Fy", "Fz", "Mx", "My", "Mz"])

# field name -> (python kind, units, long name)
_SEGMENT_SPEC: dict[str, tuple[str, str, str]] = {
    "segment": ("int", "1", "load-program segment"),
    "pattern": ("str", "1", "load pattern of the segment"),
}
_EVENT_SPEC: dict[str, tuple[str, str, str]] = {
    "step": ("int", "1", "main step (event point) number, from 1"),
    "state": ("int", "1", "index of the reported state at the event"),
    **_SEGMENT_SPEC,
    "lam": ("float", "1", "load factor of the pattern at the event"),
    "cfe": ("int", "1", "global CFE index"),
    "interface": ("str", "1", "interface name"),
    "local": ("int", "1", "CFE index along its interface"),
    "position": ("float", "m", "arc length along the interface"),
    "x": ("float", "m", "x coordinate of the CFE's S+ end"),
    "y": ("float", "m", "y coordinate of the CFE's S+ end"),
    "transition": ("transition", "1", "transition of the CFE"),
    "N": ("float", "N", "normal CFE force at the event (negative in compression)"),
    "Q": ("float", "N", "tangential CFE force at the event (3D: its magnitude)"),
    "impulse_n": ("float", "N s", "normal impulse of an impact at the event (negative: "
                  "compressive; 0: no impact)"),
    "impulse_t": ("float", "N s", "tangential impulse of an impact at the event"),
    "Q_t": ("vector", "N", "tangential CFE force at the event, one component per tangent"),
    "z": ("float?", "m", "z coordinate of the CFE's S+ end (3D results only)"),
}
#: event columns added after format version 1 files were written: absent → this default
#: (``Q_t`` None: ``(Q,)``, :class:`~stepcontact.results.events.Event`)
_EVENT_DEFAULTS = {"impulse_n": 0.0, "impulse_t": 0.0, "Q_t": None, "z": np.nan}
#: event columns written only where an event has them (2D: no z; read back as None)
_EVENT_3D_ONLY = ("z",)

_MULT_SPEC: dict[str, tuple[str, str, str]] = {
    **_SEGMENT_SPEC,
    "first_slip": ("float?", "1", "load factor at the first slip (NaN: none)"),
    "first_opening": ("float?", "1", "load factor at the first opening (NaN: none)"),
    "first_closing": ("float?", "1", "load factor at the first closing (NaN: none)"),
    "equilibrium_lost": ("float?", "1", "load factor at loss of equilibrium (NaN: none)"),
}

# CFE geometry arrays: key -> (units, long name, name of the trailing dimension)
_CFE_SPEC: dict[str, tuple[str, str, str | None]] = {
    "interface": ("1", "interface index of the CFE", None),
    "local": ("1", "CFE index along its interface", None),
    "plus_nodes": ("1", "global nodes of the S+ end (-1 padding)", "end_node"),
    "plus_w": ("1", "interpolation weights of the S+ end", "end_node"),
    "minus_nodes": ("1", "global nodes of the S- end (-1 padding)", "end_node"),
    "minus_w": ("1", "interpolation weights of the S- end", "end_node"),
    "normal": ("1", "unit normal from S- to S+", "xy"),
    "tangent": ("1", "unit tangent t = (n_y, -n_x): the normal turned clockwise", "xy"),
    "x": ("m", "coordinates of the S+ end", "xy"),
    "s": ("m", "arc length along the interface", None),
    "area": ("m2", "contact area A_k", None),
    "friction": ("1", "Coulomb friction coefficient f_k", None),
    "gap": ("m", "initial gap g_k0", None),
    "kn": ("N m-1", "normal contact-layer stiffness C_nk (inf: rigid)", None),
    "kt": ("N m-1", "tangential contact-layer stiffness C_tk (inf: rigid)", None),
    "cn": ("N s m-1", "normal contact-layer damping c_nk (dynamics: Kelvin-Voigt layer)", None),
    "bond": ("1", "initial strength of bonded CFEs (eq. (12)): N_R (N), Q_R (N), alpha_R, "
             "1/alpha_t, residual cohesion C_r A_k after the break (N); NaN: no bond",
             "bond_column"),
    "cohesion_lost": ("1", "state from which the CFE's residual cohesion is lost (it opened "
                      "after its bond broke); -1: kept", None),
}

#: the variables with one row per state and one column per CFE; the tangential ones (Q, ut)
#: have the ``tangent`` dimension too (format version 2)
_STATE_VARS: dict[str, tuple[str, str]] = {
    "N": ("N", "normal CFE force (negative in compression)"),
    "Q": ("N", "tangential CFE force"),
    "un": ("m", "mutual normal displacement u_n (negative: open gap)"),
    "ut": ("m", "mutual tangential displacement u_t"),
}
_TANGENTIAL_VARS = ("Q", "ut")


# --------------------------------------------------------------------------------------------
# JSON with numpy arrays, tuples and enums (exact floats)
# --------------------------------------------------------------------------------------------
def _to_jsonable(obj: Any) -> Any:
    """Plain JSON structure for ``obj``; arrays, tuples, enums and int keys are tagged."""
    if isinstance(obj, Enum):
        return {"__enum__": type(obj).__name__, "value": obj.value}
    if isinstance(obj, np.ndarray):
        if obj.dtype.kind not in "biufU":
            raise TypeError(f"cannot store an array of dtype {obj.dtype} as JSON")
        return {"__ndarray__": obj.tolist(), "dtype": obj.dtype.str, "shape": list(obj.shape)}
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, tuple):
        return {"__tuple__": [_to_jsonable(v) for v in obj]}
    if isinstance(obj, list):
        return [_to_jsonable(v) for v in obj]
    if isinstance(obj, dict):
        if all(isinstance(k, str) for k in obj):
            if "__enum__" in obj or "__ndarray__" in obj or "__tuple__" in obj or "__dict__" in obj:
                return {"__dict__": [[k, _to_jsonable(v)] for k, v in obj.items()]}
            return {k: _to_jsonable(v) for k, v in obj.items()}
        return {"__dict__": [[_to_jsonable(k), _to_jsonable(v)] for k, v in obj.items()]}
    if obj is None or isinstance(obj, bool | int | float | str):
        return obj
    raise TypeError(f"cannot store an object of type {type(obj).__name__} in a result file")


def _from_jsonable(obj: Any) -> Any:
    """Inverse of :func:`_to_jsonable`."""
    if isinstance(obj, list):
        return [_from_jsonable(v) for v in obj]
    if not isinstance(obj, dict):
        return obj
    if "__enum__" in obj:
        return getattr(_enums, obj["__enum__"])(obj["value"])
    if "__ndarray__" in obj:
        return np.array(obj["__ndarray__"], dtype=np.dtype(obj["dtype"])).reshape(obj["shape"])
    if "__tuple__" in obj:
        return tuple(_from_jsonable(v) for v in obj["__tuple__"])
    if "__dict__" in obj:
        return {_hashable(_from_jsonable(k)): _from_jsonable(v) for k, v in obj["__dict__"]}
    return {k: _from_jsonable(v) for k, v in obj.items()}


def _hashable(k: Any) -> Any:
    return tuple(k) if isinstance(k, list) else k


def _dumps(obj: Any) -> str:
    return json.dumps(_to_jsonable(obj), ensure_ascii=False)


def _loads(text: str) -> Any:
    return _from_jsonable(json.loads(text))


# --------------------------------------------------------------------------------------------
# result -> dataset
# --------------------------------------------------------------------------------------------
def _var(dims: tuple[str, ...], data: Any, units: str, long_name: str, **attrs: Any):
    return (dims, data, {"units": units, "long_name": long_name, **attrs})


def _str_array(values: Any) -> np.ndarray:
    return np.array([str(v) for v in values], dtype=str) if len(values) else np.zeros(0, "<U1")


def _safe_names(names: list[str]) -> dict[str, str]:
    """Unique variable-name tokens (letters, digits, ``_``) for body names."""
    out: dict[str, str] = {}
    used: set[str] = set()
    for name in names:
        if name in out:
            continue
        base = re.sub(r"[^A-Za-z0-9_]", "_", name) or "body"
        tok, n = base, 1
        while tok in used:
            tok, n = f"{base}_{n}", n + 1
        used.add(tok)
        out[name] = tok
    return out


#: the rule of the state codes of a faceted Coulomb cone (:mod:`stepcontact.enums`)
FACET_CODES = (
    f"{FACET_SLIP} + i: slip on facet i of a faceted Coulomb cone (3D); {VERTEX_SLIP} + i: "
    f"slip at its vertex i, between facets i - 1 and i; i < {MAX_FACETS}"
)


def tangent_labels(n_t: int) -> np.ndarray:
    """The labels of the tangential components: "t1"[, "t2"]."""
    return np.array([f"t{j + 1}" for j in range(n_t)])


def _flag_token(code: int) -> str:
    """A CF flag meaning (one word) for a state code: ``stick``, ``slip_facet_3`` …"""
    if code >= VERTEX_SLIP:
        return f"slip_vertex_{code - VERTEX_SLIP}"
    if code >= FACET_SLIP:
        return f"slip_facet_{code - FACET_SLIP}"
    return ContactState(code).name.lower()


def state_flag_attrs(codes: Any) -> dict[str, Any]:
    """CF ``flag_values`` / ``flag_meanings`` of an array of state codes: the 2D codes
    (:class:`ContactState`), then every faceted-cone code present (``slip_facet_i``,
    ``slip_vertex_i``), with the rule of those codes (``facet_codes``)."""
    codes = np.asarray(codes)
    values = [int(s) for s in ContactState]
    if codes.size:
        values += np.unique(codes[codes >= FACET_SLIP]).astype(int).tolist()
    return {
        "flag_values": np.array(values, dtype=codes.dtype),
        "flag_meanings": " ".join(_flag_token(v) for v in values),
        "facet_codes": FACET_CODES,
    }


def _state_codes(res: Result) -> np.ndarray:
    """The state codes to store: int16 (an int8 array, which holds no vertex code, as it
    is)."""
    st = np.asarray(res.state)
    return st if st.dtype.kind in "iu" and st.dtype.itemsize <= 2 else st.astype(np.int16)


def _index_coords(res: Result) -> dict[str, Any]:
    """The index coordinates of every result file: states, CFEs, events, patterns, interfaces,
    segments and multiplier records."""
    return {
        "state": _var(("state",), np.arange(res.n_states), "1", "reported state index"),
        "cfe": _var(("cfe",), np.arange(res.m), "1", "contact finite element index"),
        "tangent": _var(("tangent",), tangent_labels(res.n_t), "1",
                        "tangential component: along the CFE's tangent t1[, t2]"),
        "event": _var(("event",), np.arange(len(res.events)), "1", "event index"),
        "pattern": _var(("pattern",), _str_array(res.pattern_names), "1", "load pattern"),
        "interface": _var(("interface",), _str_array(res.interface_names), "1", "interface"),
        "segment_index": _var(
            ("segment_index",), np.arange(len(res.segments)), "1", "load-program segment"
        ),
        "multiplier": _var(
            ("multiplier",), np.arange(len(res.multipliers)), "1", "multiplier record"
        ),
    }


def _path_vars(res: Result, dv: dict[str, Any]) -> None:
    """Per state: the path (λ, segment, factors of all patterns, kind), the contact unknowns
    N, Q (N), u_n, u_t (m) and states of the CFEs, the residual and the violation."""
    n = res.n_states
    dv["lam"] = _var(("state",), np.asarray(res.lam), "1", "load factor of the active pattern")
    dv["segment"] = _var(("state",), np.asarray(res.segment), "1", "load-program segment")
    dv["factors"] = _var(
        ("state", "pattern"), np.asarray(res.factors).reshape(n, len(res.pattern_names)),
        "1", "load factors of all patterns",
    )
    dv["kind"] = _var(("state",), _str_array(res.kind), "1", "kind of reported state")
    for key, (units, long_name) in _STATE_VARS.items():
        if key in _TANGENTIAL_VARS:  # (state, cfe, tangent)
            dv[key] = _var(("state", "cfe", "tangent"), np.asarray(getattr(res, f"{key}_t")),
                           units, long_name)
        else:
            dv[key] = _var(("state", "cfe"), np.asarray(getattr(res, key)), units, long_name)
    if res.n_t > 1:  # 3D: the magnitude too, for readers of the file (not read back)
        dv["Q_abs"] = _var(("state", "cfe"), np.linalg.norm(np.asarray(res.Q_t), axis=2), "N",
                           "magnitude |Q| of the tangential CFE force (derived from Q)")
    st = _state_codes(res)
    dv["contact_state"] = _var(
        ("state", "cfe"), st, "1", "contact state of the CFE after the state",
        **state_flag_attrs(st),
    )
    dv["residual"] = _var(
        ("state",), np.asarray(res.residual), "1", "relative equilibrium residual"
    )
    dv["violation"] = _var(
        ("state",), np.asarray(res.violation), "1",
        "largest relative violation of the contact conditions",
    )


def _optional_state_vars(res: Result, dv: dict[str, Any], coords: dict[str, Any]) -> None:
    """Per state, when the result has them: the water in opened joints (N, Pa), the
    construction stages, the support reactions (N)."""
    if res.water is not None:
        dv["water"] = _var(
            ("state", "cfe"), np.asarray(res.water, float), "N",
            "force of the water in the opened joint on the CFE (crack pressure less uplift, "
            "times the CFE's area)",
        )
        dv["crack_pressure"] = _var(
            ("state", "cfe"), np.asarray(res.crack_pressure, float), "Pa",
            "water pressure in the opened joint",
        )
    if getattr(res, "stage", None) is not None:  # construction stages
        dv["stage"] = _var(("state",), np.asarray(res.stage, np.int64), "1",
                           "construction stage of the state (index into stage_names)")
        dv["stage_cfes"] = _var(("stage", "cfe"), np.asarray(res.stage_cfes, np.int8), "1",
                                "1 where the CFE acts at the stage")
    if len(res.reaction_labels):
        coords["reaction"] = _var(("reaction",), _str_array(list(res.reaction_labels)), "1",
                                  "support:component of each reaction resultant")
        dv["reactions"] = _var(
            ("state", "reaction"), np.asarray(res.reactions, float), "N",
            "resultant reaction of the support on the structure (N·m for rz components)",
        )


def _load_vars(res: Result, dv: dict[str, Any], coords: dict[str, Any]) -> None:
    """Per pattern and unit load factor: its load resultant (N, N m) and, per body, its
    forces' resultant, first-moment tensor and nodal moments."""
    R = np.asarray(res.load_resultants, float)
    labels = {3: _RESULTANT, 6: _RESULTANT_3D}.get(R.shape[1] if R.ndim == 2 else 0)
    if len(res.pattern_names) and labels is not None and R.shape[0] == len(res.pattern_names):
        coords["resultant_component"] = _var(("resultant_component",), labels, "1",
                                             "component of a load resultant")
        dv["load_resultant"] = _var(
            ("pattern", "resultant_component"), R, "N",
            "resultant of the pattern's forces per unit load factor: "
            + ("Fx, Fy in N, Mz about the origin in N m" if len(labels) == 3 else
               "Fx, Fy, Fz in N, Mx, My, Mz about the origin in N m"),
        )

    LM = None if res.load_moments is None else np.asarray(res.load_moments, float)
    bodies = [str(b["name"]) for b in (res.geometry or {}).get("bodies", [])]
    if LM is not None and LM.shape == (len(res.pattern_names), len(bodies),
                                       len(LOAD_MOMENT_COMPONENTS)) and bodies:
        coords["load_body"] = _var(("load_body",), _str_array(bodies), "1",
                                   "body the loads act on")
        coords["load_moment_component"] = _var(
            ("load_moment_component",), np.array(LOAD_MOMENT_COMPONENTS), "1",
            "Fx, Fy (N); first-moment tensor S_ab = sum x_a f_b (N m); nodal moments (N m)")
        dv["load_moments"] = _var(
            ("pattern", "load_body", "load_moment_component"), LM, "N",
            "the pattern's forces per unit load factor on each body: resultant, first-moment "
            "tensor about the origin and nodal moments (N m for the moments)",
        )


def _cfe_vars(res: Result, dv: dict[str, Any], coords: dict[str, Any]) -> dict[str, Any]:
    """The CFEs' arrays with one row per CFE as ``cfe_*`` variables (:data:`_CFE_SPEC`);
    returns the other CFE data (stored as JSON in the attribute ``cfe_extra``)."""
    cfe_extra: dict[str, Any] = {}
    sizes: dict[str, int] = {"xy": 2, "xyz": 3}
    for key, val in res.cfe.items():
        if not (isinstance(val, np.ndarray) and val.ndim >= 1 and val.shape[0] == res.m):
            cfe_extra[key] = val
            continue
        units, long_name, trail = _CFE_SPEC.get(key, ("1", f"CFE array '{key}'", None))
        if trail == "xy" and val.ndim == 2 and val.shape[1] == 3:  # 3D vectors
            trail = "xyz"
        dims = ["cfe"]
        for j, size in enumerate(val.shape[1:], start=1):
            name = trail if (j == 1 and trail is not None) else f"cfe_{key}_dim{j}"
            if sizes.setdefault(name, size) != size:
                name = f"cfe_{key}_dim{j}"
            dims.append(name)
        dv[f"cfe_{key}"] = _var(tuple(dims), val, units, long_name)
    used = {d for v in dv.values() for d in v[0]}
    for axis, labels in (("xy", _XY), ("xyz", _XYZ)):
        if axis in used:
            coords[axis] = _var((axis,), labels, "1", "coordinate axis")
    return cfe_extra


def _event_vars(res: Result, dv: dict[str, Any]) -> None:
    """One ``event_*`` column per field of :class:`Event` (:data:`_EVENT_SPEC`)."""
    for name, (kind, units, long_name) in _EVENT_SPEC.items():
        vals = [getattr(e, name) for e in res.events]
        if name in _EVENT_3D_ONLY:
            if all(v is None for v in vals):
                continue  # 2D: no z (read back as None)
            vals = [np.nan if v is None else v for v in vals]
            kind = "float"
        if name == "Q" and res.n_t > 1:  # the vector is event_Q_t; Q its magnitude
            vals = [e.Q_abs for e in res.events]
        if kind == "vector":  # (event, tangent)
            dv[f"event_{name}"] = _var(("event", "tangent"), np.array(
                vals, dtype=np.float64).reshape(len(vals), res.n_t), units, long_name)
            continue
        if kind == "int":
            arr = np.array(vals, dtype=np.int64)
        elif kind == "float":
            arr = np.array(vals, dtype=np.float64)
        elif kind == "transition":
            arr = _str_array([Transition(v).value for v in vals])
        else:
            arr = _str_array(vals)
        attrs = {"values": " ".join(t.value for t in Transition)} if kind == "transition" else {}
        dv[f"event_{name}"] = _var(("event",), arr, units, long_name, **attrs)


def _program_vars(res: Result, dv: dict[str, Any]) -> None:
    """The load program's segments (pattern, λ at start and end) and the multiplier records
    (:data:`_MULT_SPEC`; None as NaN)."""
    segs = list(res.segments)
    dv["segment_pattern"] = _var(
        ("segment_index",), _str_array([s[0] for s in segs]), "1", "pattern of the segment"
    )
    dv["segment_lam_start"] = _var(
        ("segment_index",), np.array([s[1] for s in segs], dtype=np.float64), "1",
        "load factor at the start of the segment",
    )
    dv["segment_lam_end"] = _var(
        ("segment_index",), np.array([s[2] for s in segs], dtype=np.float64), "1",
        "load factor at the end of the segment",
    )
    for name, (kind, units, long_name) in _MULT_SPEC.items():
        vals = [getattr(mu, name) for mu in res.multipliers]
        if kind == "int":
            arr = np.array(vals, dtype=np.int64)
        elif kind == "str":
            arr = _str_array(vals)
        else:
            arr = np.array([np.nan if v is None else v for v in vals], dtype=np.float64)
        dv[f"multiplier_{name}"] = _var(("multiplier",), arr, units, long_name)


def _field_vars(res: Result, dv: dict[str, Any], coords: dict[str, Any]) -> None:
    """The stored displacement fields ``u`` (m, rotations in rad) at the states
    ``field_state``."""
    if res.fields:
        keys = sorted(res.fields)
        coords["field_state"] = _var(
            ("field_state",), np.array(keys, dtype=np.int64), "1",
            "reported state of the stored displacement field",
        )
        dv["u"] = _var(
            ("field_state", "dof"), np.stack([np.asarray(res.fields[k]) for k in keys]),
            "m", "nodal displacements (rotations in rad)",
        )


def _axis_dim(dim: int) -> str:
    """The name of the coordinate-axis dimension: ``xy`` (2D, as format version 1 wrote it) or
    ``xyz`` (3D)."""
    return "xy" if dim == 2 else "xyz"


def _node_dof_labels(dim: int, n: int) -> np.ndarray | None:
    """The labels of the ``n`` columns of the DOF map of a ``dim``-D model: ux, uy, rz (2D);
    ux, uy, uz[, rx, ry, rz] (3D: solids[, space frames]); None for another layout."""
    if dim == 2 and n == len(_NODE_DOF):
        return _NODE_DOF
    if dim == 3 and n in (3, 6):
        return _NODE_DOF_3D[:n]
    return None


def _stress_labels(n: int, body: str) -> np.ndarray:
    """The stress components of a body's (n_el, n) stress arrays: σxx, σyy, σxy, σzz (2D, n =
    4) or σxx, σyy, σzz, σxy, σyz, σxz (3D, n = 6)."""
    if n == len(_STRESS_COMPONENTS):
        return _STRESS_COMPONENTS
    if n == len(_STRESS_COMPONENTS_3D):
        return _STRESS_COMPONENTS_3D
    raise ValueError(
        f"stresses of body '{body}': expected (n_el, 4) arrays σxx, σyy, σxy, σzz (2D) or "
        f"(n_el, 6) arrays σxx, σyy, σzz, σxy, σyz, σxz (3D), got (…, {n})"
    )


def _body_tokens(res: Result) -> dict[str, str]:
    """Variable-name tokens of the bodies of the geometry and of the stresses."""
    bodies = list(dict(res.geometry).get("bodies", []) or [])
    stress_bodies = [b for s in sorted(res.stresses) for b in res.stresses[s]]
    return _safe_names([str(b["name"]) for b in bodies] + stress_bodies)


def _geometry_vars(res: Result, dv: dict[str, Any], coords: dict[str, Any],
                   tok: dict[str, str]) -> tuple[list[str], list[str], dict[str, Any]]:
    """The geometry: node coordinates (m), the DOF map, each body's connectivity and the other
    geometry arrays; returns the body variables, the geometry arrays' keys and the geometry
    left (stored as JSON)."""
    geo = dict(res.geometry)
    bodies = list(geo.pop("bodies", []) or [])
    dim = 2
    if "points" in geo:
        points = np.asarray(geo.pop("points"))
        dim = points.shape[1] if points.ndim == 2 else 2
        axis = _axis_dim(dim)
        dv["points"] = _var(("node", axis), points, "m", "node coordinates")
        coords[axis] = _var((axis,), _XY if dim == 2 else _XYZ, "1", "coordinate axis")
    if "dof_of" in geo:
        dof_of = np.asarray(geo.pop("dof_of"))
        labels = _node_dof_labels(dim, dof_of.shape[1])
        dv["dof_of"] = _var(
            ("node", "node_dof"), dof_of, "1",
            f"global dof of each node's {', '.join(labels) if labels is not None else 'DOFs'} "
            "(-1: none)"
        )
        if labels is not None:
            coords["node_dof"] = _var(("node_dof",), labels, "1", "nodal degree of freedom")
    body_vars: list[str] = []
    for b in bodies:
        t = tok[str(b["name"])]
        extra = {k: v for k, v in b.items() if k not in ("name", "kind", "element", "cells")}
        cells = np.asarray(b["cells"])
        var = f"cells__{t}"
        dv[var] = _var(
            (f"element__{t}", f"cell_node__{t}"), cells, "1",
            f"connectivity of body '{b['name']}' (global node ids)",
            body=str(b["name"]), kind=str(b.get("kind", "")), element=str(b.get("element", "")),
            extra=_dumps(extra),
        )
        body_vars.append(var)
    geo_vars: list[str] = []
    for key, val in list(geo.items()):
        if isinstance(val, np.ndarray) and val.ndim >= 1 and val.dtype.kind in "biufU":
            dims = tuple(f"geometry__{key}_dim{j}" for j in range(val.ndim))
            dv[f"geometry__{key}"] = _var(dims, val, "1", f"geometry array '{key}'")
            geo_vars.append(key)
            geo.pop(key)
    return body_vars, geo_vars, geo


def _stress_vars(res: Result, dv: dict[str, Any], coords: dict[str, Any],
                 tok: dict[str, str]) -> list[str]:
    """The element stresses (Pa) of each body at its states: σxx, σyy, σxy, σzz (2D) or σxx,
    σyy, σzz, σxy, σyz, σxz (3D) along ``stress_component``; returns the stress variables."""
    stress_bodies = [b for s in sorted(res.stresses) for b in res.stresses[s]]
    stress_vars: list[str] = []
    labels: np.ndarray | None = None
    for body in dict.fromkeys(stress_bodies):
        t = tok[body]
        states = [s for s in sorted(res.stresses) if body in res.stresses[s]]
        arr = np.stack([np.asarray(res.stresses[s][body]) for s in states])
        if arr.ndim != 3:
            raise ValueError(f"stresses of body '{body}': expected (n_el, 4) or (n_el, 6) "
                             f"arrays, got {arr.shape[1:]}")
        own = _stress_labels(arr.shape[2], body)
        if labels is not None and len(own) != len(labels):
            raise ValueError(f"stresses of body '{body}': {len(own)} components, the other "
                             f"bodies' {len(labels)} (2D and 3D bodies in one result)")
        if labels is None:
            labels = own
            coords["stress_component"] = _var(
                ("stress_component",), labels, "1", "stress component"
            )
        coords[f"stress_state__{t}"] = _var(
            (f"stress_state__{t}",), np.array(states, dtype=np.int64), "1",
            f"reported states with stresses of body '{body}'",
        )
        var = f"stress__{t}"
        dv[var] = _var(
            (f"stress_state__{t}", f"stress_element__{t}", "stress_component"), arr, "Pa",
            f"element stresses of body '{body}'", body=body,
        )
        stress_vars.append(var)
    return stress_vars


def _file_attrs(res: Result, cfe_extra: dict[str, Any], body_vars: list[str],
                stress_vars: list[str], geo_vars: list[str],
                geo: dict[str, Any]) -> dict[str, Any]:
    """The file's attributes: format, status, counters, stages, the JSON of what has no array
    and the names of the variables that hold bodies, stresses and geometry arrays."""
    return {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "title": "stepcontact static result",
        "tangential_components": int(res.n_t),
        "state_codes": (
            "contact_state: " + ", ".join(f"{int(c)} {c.name.lower()}" for c in ContactState)
            + f"; {FACET_CODES}"),
        "status": Status(res.status).value,
        "message": str(res.message),
        "counters": _dumps(dict(res.counters)),
        "mechanism": _dumps(res.mechanism),
        "nonunique": _dumps(list(res.nonunique)),
        "stages": _dumps({"names": list(getattr(res, "stage_names", ())),
                          "bodies": [list(b) for b in getattr(res, "stage_bodies", ())]}),
        "complete": int(Status(res.status) != Status.INCOMPLETE),
        "path_axis": res.path_axis,
        "units": _dumps(dict(res.units)),
        "cfe_extra": _dumps(cfe_extra),
        "body_variables": _dumps(body_vars),
        "stress_variables": _dumps(stress_vars),
        "geometry_arrays": _dumps(geo_vars),
        "geometry_extra": _dumps(geo),
        "geometry_keys": _dumps([str(k) for k in res.geometry]),
        "field_states": _dumps(sorted(int(k) for k in res.fields)),
        "stress_states": _dumps(sorted(int(k) for k in res.stresses)),
        "fields_note": (
            f"displacement fields (u) are stored at {len(res.fields)} of {res.n_states} "
            "states (field_states), stresses at the states listed in stress_states; any other "
            "state is exact from its contact unknowns: load the result, call "
            "res.recover_fields(model) with the model of the run, then res.displacement(i), "
            "res.displacements(states) or res.stress(i) (command line: stepcontact export / "
            "plot --model MODEL.toml)"
        ),
    }


def _dynamic_vars(res: Result, dv: dict[str, Any], attrs: dict[str, Any]) -> None:
    """A dynamic result's fields in time (u in m, v in m/s, a in m/s²), its energy ledger (J),
    its time step (s) and the impulses of its impacts (N s); nothing for a static result."""
    if not getattr(res, "energy", None):
        return
    for key, long in (("u", "displacement, m"), ("v", "velocity, m/s"),
                      ("a", "acceleration, m/s2")):
        dv[f"dyn_{key}"] = _var(("state", "dyn_dof"), np.asarray(getattr(res, key), float),
                                long.split(", ")[1], long.split(",")[0] + " of every DOF")
    for key, vals in res.energy.items():
        dv[f"energy_{key}"] = _var(("state",), np.asarray(vals, float), "J",
                                   f"energy ledger: {key}")
    attrs["dynamic_dt"] = float(res.dt)
    imp = getattr(res, "impulses", None) or {}
    for key, (units, long) in _IMPULSE_SPEC.items():
        dv[f"impulse_{key}"] = _var(("impulse",), np.asarray(
            imp.get(key, np.zeros(0)), np.int64 if key in ("state", "cfe") else float),
            units, long)


def result_to_dataset(res: Result) -> xr.Dataset:
    """The result as an :class:`xarray.Dataset` (the content of a result file).

    Parameters
    ----------
    res : StaticResult

    Returns
    -------
    xarray.Dataset
        Dimensions ``state``, ``cfe``, ``event``, ``pattern``, ``interface``,
        ``segment_index``, ``multiplier``; ``field_state`` and ``dof`` when displacement
        fields were stored; ``node`` etc. when the result has a geometry.  Forces in N,
        displacements and coordinates in m, stresses in Pa.
    """
    dv: dict[str, Any] = {}
    coords = _index_coords(res)
    _path_vars(res, dv)
    _optional_state_vars(res, dv, coords)
    _load_vars(res, dv, coords)
    cfe_extra = _cfe_vars(res, dv, coords)
    _event_vars(res, dv)
    _program_vars(res, dv)
    _field_vars(res, dv, coords)
    tok = _body_tokens(res)
    body_vars, geo_vars, geo = _geometry_vars(res, dv, coords, tok)
    stress_vars = _stress_vars(res, dv, coords, tok)
    attrs = _file_attrs(res, cfe_extra, body_vars, stress_vars, geo_vars, geo)
    _dynamic_vars(res, dv, attrs)
    return xr.Dataset(dv, coords=coords, attrs=attrs)


#: the impulses of the impacts of a dynamic result (one entry per CFE and impact)
_IMPULSE_SPEC = {
    "state": ("1", "index of the reported state at the impact"),
    "time": ("s", "time of the impact"),
    "cfe": ("1", "global CFE index"),
    "normal": ("N s", "normal impulse on the CFE (negative: compressive)"),
    "tangential": ("N s", "tangential impulse on the CFE"),
}


# --------------------------------------------------------------------------------------------
# dataset -> result
# --------------------------------------------------------------------------------------------
def _py(kind: str, v: Any) -> Any:
    if kind == "int":
        return int(v)
    if kind == "float":
        return float(v)
    if kind == "float?":
        return None if np.isnan(v) else float(v)
    if kind == "transition":
        return Transition(str(v))
    if kind == "vector":
        return None if v is None else tuple(float(x) for x in np.ravel(v))
    return str(v)


_REQUIRED = ("lam", "segment", "factors", "kind", "N", "Q", "un", "ut", "contact_state",
             "residual", "violation", "segment_pattern", "segment_lam_start",
             "segment_lam_end", "pattern", "interface", "cfe", "event")


def _inconsistent(text: str) -> ValueError:
    return ValueError(f"inconsistent result file: {text}")


def _shape(ds: xr.Dataset, name: str) -> tuple[int, ...]:
    return tuple(int(k) for k in ds[name].shape)


def _expect(ds: xr.Dataset, name: str, want: tuple[int | None, ...], what: str) -> None:
    """``ds[name]`` has the shape ``want`` (None: any length), else a ValueError naming it."""
    got = _shape(ds, name)
    if len(got) != len(want) or any(w is not None and g != w
                                    for g, w in zip(got, want, strict=False)):
        text = ", ".join("…" if w is None else str(w) for w in want)
        raise _inconsistent(f"variable '{name}' has shape {got}, expected ({text}) "
                            f"({what})")


def _within(ds: xr.Dataset, name: str, size: int, what: str) -> None:
    """The indices in ``ds[name]`` (integers; −1 allowed) point inside ``size`` items."""
    v = np.asarray(ds[name].values)
    if v.size and v.dtype.kind in "iu" and (v.min() < -1 or v.max() >= size):
        raise _inconsistent(f"variable '{name}' refers to {what} {int(v.max())}, but "
                            f"there are {size}")


def _check_states(ds: xr.Dataset) -> tuple[int, int, int]:
    """The required variables are there, every per-state array has one row per state of
    ``lam`` and the contact unknowns one column per CFE; returns the numbers of states, CFEs
    and events."""
    for name in _REQUIRED:
        if name not in ds.variables:
            raise _inconsistent(f"variable '{name}' is missing")
    n = _shape(ds, "lam")[0] if len(_shape(ds, "lam")) == 1 else -1
    if n < 0:
        raise _inconsistent(f"variable 'lam' has shape {_shape(ds, 'lam')}, expected (states,)")
    n_pat, m, n_ev = _shape(ds, "pattern")[0], _shape(ds, "cfe")[0], _shape(ds, "event")[0]
    states = f"{n} states of 'lam'"
    for name in ("segment", "kind", "residual", "violation"):
        _expect(ds, name, (n,), states)
    _expect(ds, "factors", (n, n_pat), f"{states} × {n_pat} load patterns")
    n_t = _n_t(ds)
    for name in ("N", "Q", "un", "ut", "contact_state"):
        if name in _TANGENTIAL_VARS and "tangent" in ds.dims:  # format version 2
            _expect(ds, name, (n, m, n_t), f"{states} × {m} CFEs × {n_t} tangential "
                    "components")
        else:
            _expect(ds, name, (n, m), f"{states} × {m} CFEs")
    if "reactions" in ds:
        _expect(ds, "reactions", (n, None), states)
    for name in ("water", "crack_pressure"):
        if name in ds:
            _expect(ds, name, (n, m), f"{states} × {m} CFEs")
    return n, m, n_ev


def _check_columns(ds: xr.Dataset, n: int, m: int, n_ev: int) -> None:
    """The CFE, event, segment, multiplier and impulse columns have one length each, and the
    segments, states and CFEs they refer to exist."""
    for name in ds.data_vars:
        if str(name).startswith("cfe_"):
            got = _shape(ds, str(name))
            if not got or got[0] != m:
                raise _inconsistent(f"variable '{name}' has shape {got}, expected ({m}, …) "
                                    f"({m} CFEs)")
        if str(name).startswith("event_"):
            vector = _EVENT_SPEC.get(str(name)[len("event_"):], ("",))[0] == "vector"
            _expect(ds, str(name), (n_ev, _n_t(ds)) if vector else (n_ev,),
                    f"{n_ev} events" + (" × tangential components" if vector else ""))
    n_seg = _shape(ds, "segment_pattern")[0] if _shape(ds, "segment_pattern") else 0
    for name in ("segment_lam_start", "segment_lam_end"):
        _expect(ds, name, (n_seg,), f"{n_seg} segments of 'segment_pattern'")
    mult = [str(v) for v in ds.data_vars if str(v).startswith("multiplier_")]
    for name in mult:
        _expect(ds, name, (_shape(ds, mult[0])[0],), f"as '{mult[0]}'")
    _within(ds, "segment", n_seg, "segment")
    if "event_state" in ds:
        _within(ds, "event_state", n, "state")
    if "event_cfe" in ds:
        _within(ds, "event_cfe", m, "CFE")
    if "impulse_state" in ds:  # the impulses of a dynamic result's impacts
        n_imp = _shape(ds, "impulse_state")[0]
        for name in _IMPULSE_SPEC:
            if f"impulse_{name}" in ds:
                _expect(ds, f"impulse_{name}", (n_imp,), f"{n_imp} impulses")
        _within(ds, "impulse_state", n, "state")
        if "impulse_cfe" in ds:
            _within(ds, "impulse_cfe", m, "CFE")


def _check_geometry(ds: xr.Dataset, n: int) -> None:
    """The DOF map, connectivities and CFE ends refer to nodes of ``points``, the displacement
    fields match the DOF map, and the stresses their elements and states."""
    n_nodes = _shape(ds, "points")[0] if "points" in ds else None
    if "dof_of" in ds and n_nodes is not None:
        _expect(ds, "dof_of", (n_nodes, None), f"{n_nodes} nodes of 'points'")
    if n_nodes is not None:
        for name in ds.data_vars:
            if str(name).startswith("cells__"):
                _within(ds, str(name), n_nodes, "node")
        for key in ("cfe_plus_nodes", "cfe_minus_nodes"):
            if key in ds:
                _within(ds, key, n_nodes, "node")
    if "u" in ds:
        n_f = _shape(ds, "field_state")[0] if "field_state" in ds.variables else -1
        ndof = int(np.max(ds["dof_of"].values, initial=-1)) + 1 if "dof_of" in ds else None
        _expect(ds, "u", (n_f, ndof), f"{n_f} stored fields × {ndof} DOFs of 'dof_of'"
                if ndof is not None else f"{n_f} stored fields")
        _within(ds, "field_state", n, "state")
    for name in ds.data_vars:
        if str(name).startswith("stress__"):
            t = str(name)[len("stress__"):]
            k = f"stress_state__{t}"
            n_s = _shape(ds, k)[0] if k in ds.variables else -1
            cells = f"cells__{t}"
            n_el = _shape(ds, cells)[0] if cells in ds.variables else None
            n_c = ds.sizes.get("stress_component", 4)
            if n_c not in (len(_STRESS_COMPONENTS), len(_STRESS_COMPONENTS_3D)):
                raise _inconsistent(f"dimension 'stress_component' has {n_c} components, "
                                    "expected 4 (2D) or 6 (3D)")
            _expect(ds, str(name), (n_s, n_el, n_c),
                    f"{n_s} states of '{k}' × elements × {n_c} components")
            _within(ds, k, n, "state")


def _n_t(ds: xr.Dataset) -> int:
    """The number of tangential components of a result file (1 in a version-1 file)."""
    return int(ds.sizes["tangent"]) if "tangent" in ds.dims else 1


def _tangential(ds: xr.Dataset, name: str) -> np.ndarray:
    """A tangential variable (Q, ut) as the result holds it: (n_states, m) in 2D (a
    version-1 file's as it is, a version-2 file's without its tangent axis of length 1),
    (n_states, m, n_t) in 3D."""
    v = ds[name].values
    return v[..., 0] if v.ndim == 3 and v.shape[2] == 1 else v


def check_dataset(ds: xr.Dataset) -> None:
    """Raise a ValueError naming the variable when the arrays of a result dataset do not fit
    together (a damaged or hand-edited file): every per-state array has one row per state of
    ``lam``, every per-CFE array one column per CFE, the event, multiplier and segment columns
    have one length each, the displacement fields match the DOF map, and the indices stored
    (segments, states, CFEs, nodes) point inside their arrays."""
    n, m, n_ev = _check_states(ds)
    _check_columns(ds, n, m, n_ev)
    _check_geometry(ds, n)


def _dynamic_parts(ds: xr.Dataset) -> dict[str, Any]:
    """The extra arguments of a dynamic result (none for a static one)."""
    if "dyn_u" not in ds:
        return {}
    n = ds.sizes["state"]
    for key in ("dyn_u", "dyn_v", "dyn_a"):
        if key not in ds or ds[key].shape[0] != n:
            raise _inconsistent(f"variable '{key}' is missing or has not {n} states")
    energy = {str(k)[len("energy_"):]: ds[k].values for k in ds.data_vars
              if str(k).startswith("energy_")}
    impulses = {k: ds[f"impulse_{k}"].values.copy() for k in _IMPULSE_SPEC
                if f"impulse_{k}" in ds}
    return {"u": ds["dyn_u"].values, "v": ds["dyn_v"].values, "a": ds["dyn_a"].values,
            "energy": energy, "dt": float(ds.attrs.get("dynamic_dt", 0.0)),
            **({"impulses": impulses} if impulses else {})}


def _check_format(ds: xr.Dataset) -> None:
    """``ds`` is a stepcontact result of a format version this code reads."""
    if ds.attrs.get("format") != FORMAT:
        raise ValueError("not a stepcontact static result (attribute 'format' missing)")
    if int(ds.attrs["format_version"]) > FORMAT_VERSION:
        raise ValueError(
            f"result file format version {ds.attrs['format_version']} is newer than this "
            f"stepcontact supports ({FORMAT_VERSION})"
        )


def _strs(ds: xr.Dataset, name: str) -> list[str]:
    return [str(v) for v in ds[name].values]


def _cfe_data(ds: xr.Dataset) -> dict[str, Any]:
    """The CFE data: the ``cfe_*`` arrays and the JSON of the others."""
    cfe: dict[str, Any] = {
        str(name)[len("cfe_"):]: ds[str(name)].values
        for name in ds.data_vars
        if str(name).startswith("cfe_")
    }
    cfe.update(_loads(ds.attrs["cfe_extra"]))
    return cfe


def _events(ds: xr.Dataset) -> list[Event]:
    """The events; columns a version-1 file lacks take :data:`_EVENT_DEFAULTS`."""
    n_ev = ds.sizes["event"]
    ev_cols = {k: (ds[f"event_{k}"].values if f"event_{k}" in ds or k not in _EVENT_DEFAULTS
                   else np.full(n_ev, _EVENT_DEFAULTS[k])) for k in _EVENT_SPEC}
    return [
        Event(**{k: _py(spec[0], ev_cols[k][i]) for k, spec in _EVENT_SPEC.items()})
        for i in range(n_ev)
    ]


def _multipliers(ds: xr.Dataset) -> list[Multipliers]:
    mu_cols = {k: ds[f"multiplier_{k}"].values for k in _MULT_SPEC}
    return [
        Multipliers(**{k: _py(spec[0], mu_cols[k][i]) for k, spec in _MULT_SPEC.items()})
        for i in range(ds.sizes["multiplier"])
    ]


def _segments(ds: xr.Dataset) -> list[tuple[str, float, float]]:
    """The load program's segments: (pattern, λ at the start, λ at the end)."""
    return [
        (p, float(a), float(b))
        for p, a, b in zip(
            _strs(ds, "segment_pattern"), ds["segment_lam_start"].values,
            ds["segment_lam_end"].values, strict=True,
        )
    ]


def _fields(ds: xr.Dataset) -> dict[int, np.ndarray]:
    """The stored displacement fields by state."""
    if "u" not in ds:
        return {}
    u = ds["u"].values
    return {int(k): u[i].copy() for i, k in enumerate(ds["field_state"].values)}


def _stresses(ds: xr.Dataset) -> dict[int, dict[str, np.ndarray]]:
    """The stored element stresses by state and body (a state listed in ``stress_states``
    without a body's stresses, e.g. of a discrete model: an empty dict)."""
    stresses: dict[int, dict[str, np.ndarray]] = {
        int(s): {} for s in _loads(ds.attrs.get("stress_states", "[]"))}
    for var in _loads(ds.attrs["stress_variables"]):
        body = str(ds[var].attrs["body"])
        t = var[len("stress__"):]
        for i, s in enumerate(ds[f"stress_state__{t}"].values):
            stresses.setdefault(int(s), {})[body] = ds[var].values[i].copy()
    return dict(sorted(stresses.items()))


def _geometry(ds: xr.Dataset) -> dict[str, Any]:
    """The geometry, its keys in their order: points, DOF map, bodies, arrays, the rest."""
    geo_arrays = set(_loads(ds.attrs["geometry_arrays"]))
    geo_extra = _loads(ds.attrs["geometry_extra"])
    geometry: dict[str, Any] = {}
    for key in _loads(ds.attrs["geometry_keys"]):
        if key in ("points", "dof_of") and key in ds:
            geometry[key] = ds[key].values
        elif key == "bodies":
            geometry[key] = [
                {"name": str(ds[var].attrs["body"]), "kind": str(ds[var].attrs["kind"]),
                 "element": str(ds[var].attrs["element"]), "cells": ds[var].values,
                 **_loads(ds[var].attrs["extra"])}
                for var in _loads(ds.attrs["body_variables"])
            ]
        elif key in geo_arrays:
            geometry[key] = ds[f"geometry__{key}"].values
        else:
            geometry[key] = geo_extra[key]
    return geometry


def dataset_arguments(ds: xr.Dataset) -> tuple[bool, dict[str, Any]]:
    """Whether ``ds`` holds a dynamic result, and the keyword arguments of its result type
    (:func:`stepcontact.results.result.dataset_to_result`, the inverse of
    :func:`result_to_dataset`; ``ds`` must be loaded in memory).  A dataset whose arrays do
    not fit together raises a ValueError naming the variable (:func:`check_dataset`)."""
    _check_format(ds)
    check_dataset(ds)

    def arr(name: str) -> np.ndarray:
        return ds[name].values

    def optional(name: str, default: Any = None) -> Any:
        return arr(name) if name in ds else default

    cfe, events, multipliers = _cfe_data(ds), _events(ds), _multipliers(ds)
    segments, fields, stresses, geometry = _segments(ds), _fields(ds), _stresses(ds), _geometry(ds)
    dyn = _dynamic_parts(ds)
    return bool(dyn), dict(
        pattern_names=tuple(_strs(ds, "pattern")),
        segments=segments,
        cfe=cfe,
        interface_names=tuple(_strs(ds, "interface")),
        lam=arr("lam"),
        segment=arr("segment"),
        factors=arr("factors"),
        kind=arr("kind").astype(str),
        N=arr("N"),
        Q=_tangential(ds, "Q"),
        un=arr("un"),
        ut=_tangential(ds, "ut"),
        state=arr("contact_state"),
        residual=arr("residual"),
        violation=arr("violation"),
        events=events,
        multipliers=multipliers,
        status=Status(ds.attrs["status"]),
        message=str(ds.attrs["message"]),
        fields=fields,
        stresses=stresses,
        counters=_loads(ds.attrs["counters"]),
        mechanism=_loads(ds.attrs["mechanism"]),
        nonunique=_loads(ds.attrs["nonunique"]) if "nonunique" in ds.attrs else [],
        geometry=geometry,
        units=_loads(ds.attrs["units"]),
        reactions=(arr("reactions") if "reactions" in ds
                   else np.zeros((ds.sizes["state"], 0))),
        reaction_labels=tuple(_strs(ds, "reaction")) if "reaction" in ds.coords else (),
        load_resultants=optional("load_resultant", np.zeros((0, 3))),
        load_moments=optional("load_moments"),
        water=optional("water"),
        **dyn,
        crack_pressure=optional("crack_pressure"),
        **_stage_fields(ds, arr),
    )


def _stage_fields(ds, arr) -> dict:
    """The construction stages of a result file (none in a file without them)."""
    if "stage" not in ds:
        return {}
    info = _loads(ds.attrs["stages"]) if "stages" in ds.attrs else {}
    return {"stage": np.asarray(arr("stage"), np.int64),
            "stage_cfes": np.asarray(arr("stage_cfes"), bool),
            "stage_names": tuple(info.get("names", ())),
            "stage_bodies": tuple(tuple(b) for b in info.get("bodies", ()))}


# --------------------------------------------------------------------------------------------
# files
# --------------------------------------------------------------------------------------------
def save_result(res: Result, path: str | os.PathLike[str],
                attrs: dict[str, str] | None = None) -> Path:
    """Write ``res`` to ``path`` (netCDF4/HDF5, engine ``h5netcdf``) atomically.

    The file is made in memory, the free space checked for it, then written to a temporary
    file next to ``path`` which replaces ``path`` with :func:`os.replace`; if writing fails
    (a full disk: :class:`~stepcontact.atomic.WriteError` naming the file) the temporary
    file is removed and an existing file at ``path`` is left untouched.  Parent directories
    are created.  ``attrs``: extra attributes of the file (strings, e.g. ``model_file``).

    Returns
    -------
    pathlib.Path
        The path written.
    """
    path = Path(path)
    if path.exists() and path.is_dir():
        raise IsADirectoryError(f"path '{path}' is a directory, expected a result file name")
    ds = result_to_dataset(res)
    ds.attrs.update({str(k): str(v) for k, v in (attrs or {}).items()})
    write_netcdf(ds, path)
    return path


def read_dataset(path: str | os.PathLike[str]) -> xr.Dataset:
    """The dataset of a result file written by :func:`save_result`, loaded in memory (the
    result: :func:`stepcontact.results.result.load_result`)."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"path '{path}': no such result file")
    with xr.open_dataset(
        path, engine="h5netcdf", decode_times=False, decode_timedelta=False
    ) as ds:
        return ds.load()


def result_attrs(path: str | os.PathLike[str]) -> dict[str, Any]:
    """The attributes of a result file without loading its arrays (e.g. ``model_file``, the
    model file of the run that wrote it, and ``model_sha256``, a hash of its content)."""
    with xr.open_dataset(Path(path), engine="h5netcdf", decode_times=False,
                         decode_timedelta=False) as ds:
        return dict(ds.attrs)


#: the longest wall time between two writes of a run's result file, s (``stepcontact run
#: --write-interval``): a run killed (SIGKILL, a crash) loses at most about this much work
WRITE_INTERVAL = 15.0


class ResultWriter:
    """Solver hook that writes the result as the run goes (atomically each time).

    The file holds every state finished so far, with status ``incomplete`` until the run ends;
    an interrupted run (Ctrl-C, SIGTERM under :func:`stepcontact.interrupt.signals_interrupt`)
    writes what it has.  Writes come at segment ends and, within a long segment, after the
    event at which ``interval`` seconds of wall time have passed since the last write
    (:meth:`checkpoint_due`): a run killed outright loses at most about ``interval`` seconds
    of work (plus the step in progress).  The time between writes is

        wait = max(min_interval, min(c (1 − s)/s, interval)),

    c the duration of the last write and s = :attr:`max_share`: while a write takes less than
    ``interval`` · s/(1 − s) seconds (3.75 s at 15 s), at most a share s of the run's time goes
    into writing (a write of the whole result grows with the run: long programs of many short
    segments stay linear in the number of segments); beyond, the file is still written every
    ``interval`` seconds — the bound on the work lost wins.  With ``min_interval`` 0 every
    segment end and every event writes.  The last segment's result and :meth:`finish` always
    write.

    Parameters
    ----------
    path : str or PathLike
        Result file.
    min_interval : float
        Shortest time between two writes, s (0: at every segment end).
    interval : float
        Longest time between two writes, s (default :data:`WRITE_INTERVAL`).
    attrs : dict, optional
        Extra attributes of the file (strings), e.g. the model file of the run.

    Example
    -------
    >>> res = sc.solve_static(model, output="out/run.nc")          # doctest: +SKIP
    """

    #: the largest share of the run's time spent writing (while writes are short enough)
    max_share: float = 0.2

    def __init__(self, path: str | os.PathLike[str], min_interval: float = 0.0, *,
                 interval: float | None = None, attrs: dict[str, str] | None = None) -> None:
        self.path = Path(path)
        self.interval = float(WRITE_INTERVAL if interval is None else interval)
        if not (self.interval > 0 and np.isfinite(self.interval)):
            raise ValueError(f"interval: {interval} s must be a positive number of seconds")
        self.min_interval = min(float(min_interval), self.interval)
        self.attrs = dict(attrs or {})
        self.writes = 0
        #: (states, status) of the last write, None before the first
        self.written: tuple[int, str] | None = None
        self._start = time.monotonic()
        self._last = -float("inf")
        self._cost = 0.0  # seconds the last write took
        self._final: tuple | None = None  # (states, events, status, message) of a final write

    @staticmethod
    def _key(result: Result) -> tuple:
        return len(result.lam), len(result.events), str(result.status), result.message

    def _wait(self) -> float:
        """Seconds from the last write to the next one (0 with ``min_interval`` 0)."""
        if self.min_interval <= 0:
            return 0.0
        share = self._cost * (1.0 - self.max_share) / self.max_share
        return max(self.min_interval, min(share, self.interval))

    def _write(self, result: Result) -> None:
        t0 = time.monotonic()
        with deferred():  # a SIGTERM waits until the file is whole
            save_result(result, self.path, **({"attrs": self.attrs} if self.attrs else {}))
            self.writes += 1
            self._last = time.monotonic()
            self._cost = self._last - t0
            self.written = (len(getattr(result, "lam", ())), str(Status(result.status).value))
            final = Status(result.status) != Status.INCOMPLETE
            self._final = self._key(result) if final else None

    def after_segment(self, result: Result) -> None:
        """Save ``result`` (the run up to the end of the segment just finished)."""
        final = Status(result.status) != Status.INCOMPLETE
        if final or time.monotonic() - self._last >= self._wait():
            self._write(result)

    def checkpoint_due(self) -> bool:
        """True when the file should be written now, within a segment (the solver then calls
        :meth:`checkpoint` with the run so far)."""
        return time.monotonic() - max(self._last, self._start) >= self._wait()

    def checkpoint(self, result: Result) -> None:
        """Save ``result`` (the run up to the last event, status ``incomplete``)."""
        self._write(result)

    def interrupted(self, result: Result) -> None:
        """The run was interrupted: keep what it has."""
        self._write(result)

    def finish(self, result: Result) -> None:
        """The run has ended: write the complete result (unless the last segment's hook has
        written it already: the same states, events, status and message)."""
        if self._final != self._key(result):
            self._write(result)

    def __fspath__(self) -> str:
        """The writer stands for its file (``Path(writer)``, ``open(writer)``)."""
        return os.fspath(self.path)

    def __repr__(self) -> str:
        return f"ResultWriter('{self.path}', writes={self.writes})"


__all__ = [
    "WRITE_INTERVAL",
    "ResultWriter",
    "check_dataset",
    "dataset_arguments",
    "read_dataset",
    "result_attrs",
    "result_to_dataset",
    "save_result",
]
