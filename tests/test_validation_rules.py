"""One source for each validation rule (issue 26, §5): the model's dataclasses own the rules, the
model file's schema takes its kinds and bounds from the model's constants, and
:func:`stepcontact.solve_dynamic` applies the same checks to its own arguments.

Every test here compares two ways of giving the same value — a Python object and a model file,
or the file's JSON schema and the model's constant — so it fails when one of them drifts from
the other.  The references are the bounds themselves, written out in the test (HHT-α ∈ [0, 1/3]:
Hilber, Hughes & Taylor 1977, unconditionally stable and second-order accurate there; e ∈ [0, 1];
Poisson's ratio in (−1, 1/2); φ ∈ [0°, 90°)); no tolerance is involved except at the bounds,
where values one part in 10¹² inside and outside are tried.
"""

from __future__ import annotations

import ast
import copy
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import stepcontact as sc
from stepcontact.errors import ModelError
from stepcontact.io.modelfile import model_from_dict, schema
from stepcontact.model.bond import FRICTION_ANGLE_RANGE
from stepcontact.model.items import CFE_KINDS, ELEMENT_KINDS, NU_RANGE, PLANE_KINDS
from stepcontact.model.obstacle import OBSTACLE_SIDES
from stepcontact.model.supports import _ALL_DOFS as ALL_DOFS
from stepcontact.model.timefunction import (
    HHT_ALPHA_RANGE,
    MASS_KINDS,
    PULSE_SHAPES,
    RESTITUTION_RANGE,
)

BASE = tomllib.loads("""
[materials.steel]
E = 210e9
nu = 0.3
density = 7850
[[bodies]]
name = "plate"
corner0 = [0, 0]
corner1 = [1, 1]
nx = 2
ny = 2
material = "steel"
[node_sets.bottom]
body = "plate"
y = 0
[node_sets.top]
body = "plate"
y = 1
[[supports]]
nodes = "bottom"
[patterns.push]
loads = [{type = "nodal", nodes = "top", fx = 1e3}]
[[program]]
pattern = "push"
end = 1
[dynamics]
dt = 1e-3
duration = 0.01
""")


def file_error(**dynamics) -> ModelError:
    """The error of the base model file with ``dynamics`` changed."""
    d = copy.deepcopy(BASE)
    d["dynamics"].update(dynamics)
    with pytest.raises(ModelError) as e:
        model_from_dict(d)
    return e.value


def file_with(**dynamics) -> sc.Model:
    d = copy.deepcopy(BASE)
    d["dynamics"].update(dynamics)
    return model_from_dict(d)


# ---- HHT-α: checked by DynamicInterval too (it was not), naming the field ----------------------
@pytest.mark.parametrize("alpha", [0.5, -0.1, 1 / 3 * (1 + 1e-12), math.nan, math.inf])
def test_a_dynamic_interval_refuses_an_hht_alpha_outside_0_to_one_third(alpha):
    with pytest.raises(ModelError) as e:
        sc.DynamicInterval(1e-3, 0.01, alpha=alpha)
    assert e.value.item == "dynamics.alpha"
    assert "HHT-α must lie in [0, 1/3]" in e.value.problem


@pytest.mark.parametrize("alpha", [0.0, 0.1, 1 / 3])
def test_a_dynamic_interval_takes_an_hht_alpha_inside_the_range(alpha):
    assert sc.DynamicInterval(1e-3, 0.01, alpha=alpha).alpha == alpha


def test_a_bad_alpha_in_a_stage_is_refused_when_the_stage_is_made():
    """A stage's interval is a DynamicInterval: the α of a stage is refused at once too."""
    with pytest.raises(ModelError) as e:
        sc.Stage("shake", dynamics=sc.DynamicInterval(1e-3, 0.01, alpha=0.4))
    assert e.value.item == "dynamics.alpha"


@pytest.mark.parametrize("alpha", [0.5, -0.1])
def test_a_model_file_with_the_same_bad_alpha_names_the_file_field(alpha):
    e = file_error(alpha=alpha)
    assert e.item == "dynamics.alpha"
    assert f"(got {alpha})" in e.problem


def test_a_stage_dynamics_with_a_bad_alpha_names_its_file_field():
    d = copy.deepcopy(BASE)
    dyn = d.pop("dynamics")
    d["stages"] = [{"name": "build", "program": d.pop("program"),
                    "dynamics": dict(dyn, alpha=0.4)}]
    with pytest.raises(ModelError) as e:
        model_from_dict(d)
    assert e.value.item == "stages[0].dynamics.alpha"


def test_the_file_and_the_dataclass_agree_on_the_bounds_of_alpha_and_restitution():
    """The last value inside each bound is taken by both, the first outside refused by both."""
    for key, (lo, hi) in (("alpha", (0.0, 1 / 3)), ("restitution", (0.0, 1.0))):
        for v in (lo, hi):
            assert getattr(file_with(**{key: v}).dynamics, key) == v
            assert getattr(sc.DynamicInterval(1e-3, 0.01, **{key: v}), key) == v
        for v in (lo - 1e-12, hi * (1 + 1e-12)):
            assert file_error(**{key: v}).item == f"dynamics.{key}"
            with pytest.raises(ModelError) as e:
                sc.DynamicInterval(1e-3, 0.01, **{key: v})
            assert e.value.item == f"dynamics.{key}"


def test_solve_dynamic_applies_the_interval_rules_to_its_own_arguments():
    """The same rules (one function, check_newmark), items without the ``dynamics.`` prefix."""
    dm = sc.DiscreteModel(np.eye(1), np.zeros((0, 1)), np.zeros((0, 1)))
    for kwargs, item, words in (
        ({"alpha": 0.4}, "alpha", "HHT-α must lie in [0, 1/3]"),
        ({"restitution": 1.5}, "restitution", "must lie in [0, 1]"),
        ({"dt": -1e-3}, "dt", "positive and finite"),
        ({"duration": math.nan}, "duration", "positive and finite"),
    ):
        args = {"dt": 1e-3, "duration": 0.01, "mass": np.eye(1)} | kwargs
        with pytest.raises(ModelError) as e:
            sc.solve_dynamic(dm, **args)
        assert e.value.item == item and words in e.value.problem


def test_solve_dynamic_lists_the_model_mass_kinds():
    dm = sc.DiscreteModel(np.eye(1), np.zeros((0, 1)), np.zeros((0, 1)))
    with pytest.raises(ModelError) as e:
        sc.solve_dynamic(dm, dt=1e-3, duration=0.01, mass="lumpy")
    assert e.value.item == "mass"
    assert "'consistent', 'lumped' or a matrix" in e.value.problem


# ---- the schema takes its kinds and bounds from the model --------------------------------------
def _prop(s: dict, table: str, key: str) -> dict:
    return s["$defs"][table]["properties"][key]


def _enum(p: dict) -> tuple:
    if "enum" in p:
        return tuple(p["enum"])
    return tuple(v for q in p["anyOf"] if "enum" in q for v in q["enum"])


def test_the_schema_kinds_are_the_model_constants():
    s = schema()
    expected = {
        ("ModelSection", "plane"): ("strain", "stress"),
        ("RectangleSpec", "element"): ("tri3", "tri6", "quad4", "quad8", "quad9"),
        ("PolygonSpec", "element"): ("tri3", "tri6", "quad4", "quad8", "quad9"),
        ("MeshBodySpec", "element"): ("tri3", "tri6", "quad4", "quad8", "quad9",  # then 3D
                                      "tet4", "tet10", "hex8", "hex20", "hex27"),
        ("InterfaceSpec", "cfe"): ("auto", "mortar", "node-to-segment", "node-to-node"),
        ("ObstacleSpec", "side"): ("left", "right"),
        ("DisplacementLoad", "dof"): ("x", "y", "rz", "z", "rx", "ry"),  # 2D, then 3D (frames)
        ("TimeFunctionSpec", "shape"): ("rectangular", "triangular", "half_sine"),
        ("DynamicsSpec", "mass"): ("consistent", "lumped"),
    }
    for (table, key), kinds in expected.items():
        assert _enum(_prop(s, table, key)) == kinds, (table, key)
    dof_names = ALL_DOFS  # the supports' DOF names: 2D's, then 3D's (space frames' rx, ry)
    assert (PLANE_KINDS, ELEMENT_KINDS, CFE_KINDS, OBSTACLE_SIDES, dof_names, PULSE_SHAPES,
            MASS_KINDS) == (expected[("ModelSection", "plane")],
                            expected[("RectangleSpec", "element")],
                            expected[("InterfaceSpec", "cfe")],
                            expected[("ObstacleSpec", "side")],
                            expected[("DisplacementLoad", "dof")],
                            expected[("TimeFunctionSpec", "shape")],
                            expected[("DynamicsSpec", "mass")])


def test_the_schema_bounds_are_the_model_ranges():
    s = schema()
    assert HHT_ALPHA_RANGE == (0, 1 / 3) and RESTITUTION_RANGE == (0, 1)
    assert NU_RANGE == (-1.0, 0.5) and FRICTION_ANGLE_RANGE == (0, 90)
    for table, key, lo, hi, (lo_key, hi_key) in (
        ("DynamicsSpec", "alpha", *HHT_ALPHA_RANGE, ("minimum", "maximum")),
        ("DynamicsSpec", "restitution", *RESTITUTION_RANGE, ("minimum", "maximum")),
        ("MaterialSpec", "nu", *NU_RANGE, ("exclusiveMinimum", "exclusiveMaximum")),
    ):
        p = _prop(s, table, key)
        assert (p[lo_key], p[hi_key]) == (lo, hi), (table, key)
    for table in ("LayerSpec", "BondSpec"):
        key = "nu" if table == "LayerSpec" else "friction_angle"
        bounds = [q for q in _prop(s, table, key)["anyOf"] if q.get("type") == "number"][0]
        got = ((bounds["exclusiveMinimum"], bounds["exclusiveMaximum"]) if key == "nu" else
               (bounds["minimum"], bounds["exclusiveMaximum"]))
        assert got == (NU_RANGE if key == "nu" else FRICTION_ANGLE_RANGE), table


# ---- rules written once, asked of the dataclass by the file ------------------------------------
def _file_problem(d: dict, path: str) -> str:
    with pytest.raises(ModelError) as e:
        model_from_dict(d)
    found = dict(getattr(e.value, "errors", [(e.value.item, e.value.problem)]))
    assert path in found, found
    return found[path]


def _python_problem(make) -> str:
    with pytest.raises(ModelError) as e:
        make()
    return e.value.problem


def test_young_modulus_out_of_range_is_one_message_for_materials_frames_and_files():
    e = 1e30
    text = _python_problem(lambda: sc.Material(e, 0.2).check("m"))
    assert text.startswith("Young's modulus E = 1e+30 is outside 1e-10 … 1e+20 (Pa)")
    frame = _python_problem(lambda: sc.Frame.line("f", (0, 0), (1, 0), 2, E=e, A=1.0, I=1.0))
    d = copy.deepcopy(BASE)
    d["materials"]["steel"]["E"] = e
    assert frame == text == _file_problem(d, "materials.steel.E")


@pytest.mark.parametrize("layer", [{"kn": 1e9}, {"kn": 1e9, "kt": 1e9, "thickness": 0.1},
                                   {"nu": 0.2}])
def test_the_forms_of_a_contact_layer_are_one_rule(layer):
    """A layer is {kn, kt} or {thickness, E[, nu]}: the file says what the dataclass says."""
    d = copy.deepcopy(BASE)
    d["bodies"].append({"name": "base", "corner0": [0, -1], "corner1": [1, 0], "nx": 2, "ny": 1,
                        "material": "steel"})
    d["node_sets"]["base_top"] = {"body": "base", "y": 0}
    d["interfaces"] = [{"name": "j", "plus": "bottom", "minus": "base_top", "layer": layer}]
    python = sc.ContactLayer.form_problem(layer.get("kn"), layer.get("kt"),
                                          layer.get("thickness"), layer.get("E"),
                                          layer.get("nu"))
    assert python is not None
    assert _file_problem(d, "interfaces[0].layer") == python
    if "nu" not in layer and "thickness" not in layer:  # the dataclass itself, same words
        assert _python_problem(lambda: sc.ContactLayer(**layer).stiffness_per_area("l")) == python


def test_uplift_and_crack_water_forms_are_one_rule():
    d = copy.deepcopy(BASE)
    d["bodies"].append({"name": "base", "corner0": [0, -1], "corner1": [1, 0], "nx": 2, "ny": 1,
                        "material": "steel"})
    d["node_sets"]["base_top"] = {"body": "base", "y": 0}
    d["interfaces"] = [{"name": "j", "plus": "bottom", "minus": "base_top"}]
    d["patterns"]["water"] = {"loads": [
        {"type": "uplift", "interface": "j", "head": 1.0, "pressure": 1e4},
        {"type": "crack_water", "interface": "j", "level": 1.0, "pressure": 1e4}]}
    uplift = _python_problem(lambda: sc.Uplift("j", head=1.0, pressure=1e4))
    crack = _python_problem(lambda: sc.CrackWater("j", level=1.0, pressure=1e4))
    assert _file_problem(d, "patterns.water.loads[0]") == uplift
    assert _file_problem(d, "patterns.water.loads[1]") == crack


def test_a_zero_interface_normal_and_a_negative_residual_cohesion_are_one_rule_each():
    d = copy.deepcopy(BASE)
    d["bodies"].append({"name": "base", "corner0": [0, -1], "corner1": [1, 0], "nx": 2, "ny": 1,
                        "material": "steel"})
    d["node_sets"]["base_top"] = {"body": "base", "y": 0}
    d["interfaces"] = [{"name": "j", "plus": "bottom", "minus": "base_top", "normal": [0, 0],
                        "bond": {"tensile": 1e5, "shear": 1e5, "alpha": 0.7,
                                 "residual_cohesion": -5.0}}]
    normal = _python_problem(lambda: sc.Interface("j", sc.NodeSet("plate", [0]),
                                                  sc.NodeSet("plate", [1]), normal=(0.0, 0.0)))
    residual = _python_problem(lambda: sc.Bond(1e5, 1e5, 0.7, residual_cohesion=-5.0))
    assert _file_problem(d, "interfaces[0].normal") == f"normal {normal}"
    assert _file_problem(d, "interfaces[0].bond.residual_cohesion") == residual


def test_the_friction_angle_bound_is_the_bonds():
    with pytest.raises(ModelError) as e:
        sc.Bond.mohr_coulomb(1e5, 1e4, FRICTION_ANGLE_RANGE[1])
    assert e.value.item == "bond.friction_angle" and "[0, 90)" in e.value.problem
    d = copy.deepcopy(BASE)
    d["bodies"].append({"name": "base", "corner0": [0, -1], "corner1": [1, 0], "nx": 2, "ny": 1,
                        "material": "steel"})
    d["node_sets"]["base_top"] = {"body": "base", "y": 0}
    d["interfaces"] = [{"name": "j", "plus": "bottom", "minus": "base_top",
                        "bond": {"cohesion": 1e5, "tensile_strength": 1e4,
                                 "friction_angle": 90.0}}]
    assert "less than 90" in _file_problem(d, "interfaces[0].bond.friction_angle")


# ---- the split model-file package: no cycle among its modules ----------------------------------
def test_the_model_file_modules_import_one_another_without_a_cycle():
    """Static import graph of stepcontact/io/modelfile/*.py (imports under TYPE_CHECKING left
    out): a DAG, and no module imports the package itself."""
    root = Path(sc.__file__).parent / "io" / "modelfile"
    graph: dict[str, set[str]] = {}
    for f in root.glob("*.py"):
        name = f.stem
        deps = set()
        for node in ast.parse(f.read_text(encoding="utf-8")).body:
            if isinstance(node, ast.ImportFrom) and node.module:
                if node.module == "stepcontact.io.modelfile" and name != "__init__":
                    pytest.fail(f"{name}.py imports the package stepcontact.io.modelfile")
                if node.module.startswith("stepcontact.io.modelfile."):
                    deps.add(node.module.rsplit(".", 1)[1])
        graph[name] = deps
    assert set(graph) >= {"__init__", "schema", "errors", "references", "build", "checks",
                          "load"}
    done: set[str] = set()

    def visit(n: str, path: tuple[str, ...]) -> None:
        assert n not in path, f"import cycle: {' -> '.join(path + (n,))}"
        if n in done:
            return
        for m in graph.get(n, ()):
            visit(m, path + (n,))
        done.add(n)

    for n in graph:
        visit(n, ())


# ---- the mesh generators' rules -----------------------------------------------------------------
def test_rectangle_corners_and_grading_are_one_rule_each():
    """rectangle() refuses what the file refuses, in the same words (a negative grading was
    refused only by the file before: from Python it gave NaN grid lines)."""
    mat = sc.Material(210e9, 0.3)
    for kwargs, field, item in (({"corner1": (1.0, -1.0)}, "", "body 'r'"),
                                ({"grading": (1.0, -2.0)}, ".grading", "body 'r'.grading")):
        args = {"corner0": (0.0, 0.0), "corner1": (1.0, 1.0), "grading": (1.0, 1.0)} | kwargs
        with pytest.raises(ModelError) as e:
            sc.rectangle("r", args["corner0"], args["corner1"], 2, 2, mat,
                         grading=args["grading"])
        assert e.value.item == item
        d = copy.deepcopy(BASE)
        d["bodies"][0].update({k: list(v) for k, v in kwargs.items()})
        assert _file_problem(d, f"bodies[0]{field}") == e.value.problem


@pytest.mark.parametrize("cells", [{"n": 2, "size": 0.5}, {}])
def test_a_polygon_needs_one_of_n_and_size_in_python_and_in_a_file(cells):
    mat = sc.Material(210e9, 0.3)
    tri = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]
    with pytest.raises(ModelError) as e:
        sc.polygon_region("p", tri, mat, **cells)
    assert e.value.item == "body 'p'.n" and "either n" in e.value.problem
    d = copy.deepcopy(BASE)
    d["bodies"][0] = {"name": "plate", "kind": "polygon", "vertices": [list(p) for p in tri],
                      "material": "steel", **cells}
    assert _file_problem(d, "bodies[0]") == e.value.problem


def test_the_half_disc_bounds_of_the_schema_are_the_generators():
    from stepcontact.model.mesh import HALF_DISC_MIN_AROUND, SIZE_RATIO_MIN

    p = schema()["$defs"]["HalfDiscSpec"]["properties"]
    assert (p["n_around"]["minimum"], p["ratio"]["minimum"]) == (4, 1)
    assert (HALF_DISC_MIN_AROUND, SIZE_RATIO_MIN) == (4, 1)
    mat = sc.Material(210e9, 0.3)
    with pytest.raises(ModelError, match=">= 4"):
        sc.half_disc("d", (0.0, 0.0), 1.0, 2, 2, mat)
    with pytest.raises(ModelError, match=">= 1"):
        sc.half_disc("d", (0.0, 0.0), 1.0, 2, 8, mat, ratio=0.5)


# ---- the lists of construction stages: one rule for the solver and the file ----------------------
def _staged(**lists) -> tuple[sc.Model, dict]:
    """The base model in one stage (no dynamics) with ``lists`` on that stage, as a Python model
    and as a model file."""
    d = copy.deepcopy(BASE)
    d.pop("dynamics")
    m = model_from_dict(d)
    staged = m.replace(program=(), stages=(sc.Stage("first", m.program, **lists),))
    d["stages"] = [{"name": "first", "program": d.pop("program"),
                    **{k: list(v) for k, v in lists.items()}}]
    return staged, d


@pytest.mark.parametrize("lists, key, words", [
    ({"remove_supports": ("bottom",)}, "remove_supports",
     "support 'bottom' is removed before or when it is placed (in place from the start)"),
    ({"bodies": ("nothing",)}, "bodies", "no such body 'nothing' (known: 'plate')"),
    ({"supports": ("bottom", "bottom")}, "supports", "lists support 'bottom' twice"),
])
def test_a_stage_list_is_refused_in_the_same_words_by_the_solver_and_the_file(lists, key, words):
    """The solver (StagePlan, at the run) and the model file (at loading) apply
    model.stages.list_problems: the same message, the item named each one's way."""
    staged, d = _staged(**lists)
    with pytest.raises(ModelError) as e:
        sc.solve_static(staged)
    assert e.value.item == f"stage 'first'.{key}"
    assert words in e.value.problem
    assert _file_problem(d, f"stages[0].{key}") == e.value.problem


def test_stage_list_problems_name_other_stages_by_the_callers_label():
    from stepcontact.io.modelfile import StageSpec
    from stepcontact.model.stages import list_problems

    known = {"body": ["a", "b"], "interface": ["j"], "support": ["s"]}
    objects = [sc.Stage("one", bodies=("a",)), sc.Stage("two", bodies=("a",), contacts=("j",)),
               sc.Stage("three", interfaces=("j",), remove_supports=("s",))]
    tables = [StageSpec(name="one", bodies=["a"]),
              StageSpec(name="two", bodies=["a"], contacts=["j"]),
              StageSpec(name="three", interfaces=["j"], remove_supports=["s"])]
    expected = [(1, "bodies", "body 'a' is already listed by <one>"),
                (2, "interfaces", "interface 'j' is already listed by <two>")]
    for stages in (objects, tables):
        names = [st.name for st in stages]
        assert list_problems(stages, known, lambda k, n=names: f"<{n[k]}>") == expected


# ---- that segments chain is the model's rule; the file reports it at the entry's path ------------
def test_a_segment_after_rates_starts_where_the_rates_left_its_pattern_in_a_file_too():
    """A segment with rates {push = 1} over [0, 1] leaves push at 1 × (1 − 0) = 1 (by hand): the
    file takes a next segment of push from 1, as the Python model does (the file's own copy of
    the rule ignored the rates and refused it), and refuses one from 0, naming its field."""
    d = copy.deepcopy(BASE)
    d.pop("dynamics")
    d["program"] = [{"pattern": "mix", "start": 0.0, "end": 1.0, "rates": {"push": 1.0}},
                    {"pattern": "push", "start": 1.0, "end": 2.0}]
    assert model_from_dict(d).segments_resolved() == [("mix", 0.0, 1.0), ("push", 1.0, 2.0)]
    d["program"][1]["start"] = 0.0
    text = _file_problem(d, "program[1].start")
    assert "do not chain" in text and "stands at λ = 1" in text


def test_a_stage_after_a_dynamic_interval_starts_where_the_interval_left_the_pattern():
    """A constant load g = 2 in the interval of stage one adds g(T) = 2 to push, which stood at
    1: push stands at 3 (by hand) when stage two begins, in the file as in the model."""
    d = copy.deepcopy(BASE)
    dyn = d.pop("dynamics")
    dyn["loads"] = [{"pattern": "push", "type": "constant", "amplitude": 2.0}]
    d["stages"] = [{"name": "one", "program": d.pop("program"), "dynamics": dyn},
                   {"name": "two", "program": [{"pattern": "push", "start": 3.0, "end": 4.0}]}]
    assert model_from_dict(d).segments_resolved()[-1] == ("push", 3.0, 4.0)
    d["stages"][1]["program"][0]["start"] = 1.0
    assert "stands at λ = 3" in _file_problem(d, "stages[1].program[0].start")
