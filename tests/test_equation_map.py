"""docs/method.md is kept true to the code: its module table and its map of the article's
equations (1)–(12).

* The **module table** (the table headed ``| module | layer | holds |``) names every module of
  the package — a new module fails here until it is added — and nothing that does not exist,
  each with its layer (a module of ``stepcontact/X/`` is in layer X; the package's top-level
  modules in one of :data:`LAYERS`) and what it holds.
* The **equation map** (the table headed ``| article | meaning | code |``) has one row per
  equation (1)–(12); every backticked name in its code column is the full dotted path of an
  importable module, class, function or method (never a nested function, which cannot be
  imported), and the docstring of that object — a module's own docstring for a module — cites
  the row's equation: ``eq. (8)``, ``eqs. (7)–(10)``, ``eqs. (2), (3) and (12)`` or
  ``conditions (1)`` (a bare ``(8)`` is not a citation).

The checkers are tested on fake entries: they must reject a wrong path, a nested function, a
missing citation, a missing equation and a missing module.  No numbers: nothing to compare
within a tolerance; every check is exact.
"""

from __future__ import annotations

import inspect
import re
from pathlib import Path

import stepcontact
from test_docs import resolve

ROOT = Path(__file__).resolve().parents[1]
METHOD = ROOT / "docs" / "method.md"
PACKAGE = Path(stepcontact.__file__).resolve().parent

#: the layers of the module table, in the order of the data flow
LAYERS = ("base", "model", "fem", "contact", "solver", "results", "io", "post", "study", "cli",
          "api")
#: the article's equations
EQUATIONS = tuple(range(1, 13))

MODULE_HEADER = ("module", "layer", "holds")
MAP_HEADER = ("article", "meaning", "code")

#: a citation: "eq." / "eqs." / "equation(s)" / "condition(s)" and a list of equation numbers
#: in parentheses, joined by commas, "and" or dashes (a range)
_CITATION = re.compile(r"(?<!\w)(?:eqs?\.|equations?|conditions?)\s*"
                       r"(\(\d+\)(?:\s*(?:,|and|–|—|-)\s*\(\d+\))*)", re.IGNORECASE)
_NUMBER_OR_DASH = re.compile(r"\((\d+)\)|([–—-])")


# ---- the checkers -----------------------------------------------------------------------------
def _cells(line: str) -> list[str]:
    """The cells of a markdown table row (``\\|`` inside a cell is not a separator)."""
    inner = line.strip().strip("|")
    return [c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", inner)]


def table(text: str, header: tuple[str, ...]) -> list[list[str]]:
    """The rows of the first markdown table of ``text`` whose header row is ``header``."""
    lines = text.splitlines()
    for i, line in enumerate(lines):
        if line.lstrip().startswith("|") and tuple(_cells(line)) == header:
            rows = []
            for row in lines[i + 2:]:  # (after the rule |---|)
                if not row.lstrip().startswith("|"):
                    break
                rows.append(_cells(row))
            return rows
    raise AssertionError(f"no table with the header {' | '.join(header)}")


def cited(doc: str | None) -> set[int]:
    """The equation numbers a docstring cites (ranges expanded: eqs. (7)–(10) is 7, 8, 9, 10)."""
    out: set[int] = set()
    for m in _CITATION.finditer(doc or ""):
        prev, dash = None, False
        for number, d in _NUMBER_OR_DASH.findall(m.group(1)):
            if d:
                dash = True
                continue
            n = int(number)
            out.update(range(prev, n + 1) if dash and prev is not None else (n,))
            prev, dash = n, False
    return out


def _docstring(obj) -> str | None:
    """The object's own docstring (never one inherited from a base class, as
    :func:`inspect.getdoc` would give), or None for an object that is not a module, class,
    function, method or property."""
    if isinstance(obj, property):
        obj = obj.fget
    if inspect.ismodule(obj) or inspect.isclass(obj) or inspect.isroutine(obj):
        return obj.__doc__ or ""
    return None


def entry_problems(eq: int, path: str) -> list[str]:
    """What is wrong with naming ``path`` as where eq. (``eq``) lives (empty: nothing)."""
    if not re.fullmatch(r"stepcontact(\.[A-Za-z_]\w*)*", path):
        return [f"({eq}) `{path}`: not a full dotted path stepcontact.…"]
    try:
        obj = resolve(path)
    except (ImportError, AttributeError) as e:
        return [f"({eq}) `{path}` does not import ({type(e).__name__}: {e}); a nested function "
                "cannot be named: name the function that holds it"]
    doc = _docstring(obj)
    if doc is None:
        return [f"({eq}) `{path}` is a {type(obj).__name__}, not a module, class, function or "
                "method"]
    if eq not in cited(doc):
        found = ", ".join(f"({n})" for n in sorted(cited(doc))) or "none"
        return [f"({eq}) `{path}`: its docstring does not cite eq. ({eq}) (cites {found})"]
    return []


def equation_map(text: str) -> dict[int, list[str]]:
    """{equation: the backticked names of its row's code column} of the map in ``text``."""
    out: dict[int, list[str]] = {}
    for row in table(text, MAP_HEADER):
        m = re.fullmatch(r"\((\d+)\)", row[0])
        assert m and len(row) == len(MAP_HEADER), f"a row of the map is not (N) | … | …: {row}"
        assert int(m.group(1)) not in out, f"eq. ({m.group(1)}) has two rows in the map"
        out[int(m.group(1))] = re.findall(r"`([^`]+)`", row[2])
    return out


def map_problems(text: str) -> list[str]:
    """Everything wrong with the equation map of ``text``."""
    emap = equation_map(text)
    problems = [f"({eq}) has no row in the map" for eq in EQUATIONS if eq not in emap]
    problems += [f"({eq}) is not one of the article's equations" for eq in emap
                 if eq not in EQUATIONS]
    for eq, paths in sorted(emap.items()):
        if not paths:
            problems.append(f"({eq}) names no object")
        for path in paths:
            problems += entry_problems(eq, path)
    return problems


def package_modules(package: Path = PACKAGE) -> set[str]:
    """Dotted names of every module of the package under ``package`` (packages by their
    ``__init__.py``)."""
    names = set()
    for f in package.rglob("*.py"):
        parts = ("stepcontact", *f.relative_to(package).with_suffix("").parts)
        names.add(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return names


def module_problems(text: str, modules: set[str]) -> list[str]:
    """Everything wrong with the module table of ``text`` against the modules ``modules``."""
    rows = table(text, MODULE_HEADER)
    problems, seen = [], set()
    for row in rows:
        if len(row) != len(MODULE_HEADER) or not re.fullmatch(r"`[\w.]+`", row[0]):
            problems.append(f"a row of the module table is not `module` | layer | holds: {row}")
            continue
        name, layer, holds = row[0].strip("`"), row[1], row[2]
        if name in seen:
            problems.append(f"{name} is listed twice")
        seen.add(name)
        if name not in modules:
            problems.append(f"{name} is listed but there is no such module")
        parts = name.split(".")
        if layer not in LAYERS:
            problems.append(f"{name}: layer {layer!r} is not one of {', '.join(LAYERS)}")
        elif len(parts) > 2 and layer != parts[1]:
            problems.append(f"{name}: layer {layer!r}, but it is in stepcontact/{parts[1]}/")
        if not holds:
            problems.append(f"{name}: no line on what it holds")
    problems += [f"{name} (missing from the table: add it with its layer and what it holds)"
                 for name in sorted(modules - seen)]
    return problems


# ---- docs/method.md as it is ----------------------------------------------------------------
def test_the_equation_map_names_importable_objects_that_cite_their_equation():
    problems = map_problems(METHOD.read_text(encoding="utf-8"))
    assert not problems, "docs/method.md's map of the equations:\n" + "\n".join(problems)


def test_the_module_table_names_every_module_with_its_layer():
    problems = module_problems(METHOD.read_text(encoding="utf-8"), package_modules())
    assert not problems, "docs/method.md's module table:\n" + "\n".join(problems)


# ---- the checkers on fake entries ---------------------------------------------------------------
def test_citation_forms():
    """What counts as citing an equation, and what does not."""
    assert cited("Newmark (eq. (8): ü linear)") == {8}
    assert cited("the dynamics of article eqs. (7)–(10)") == {7, 8, 9, 10}
    assert cited("Eqs. (4)-(6)") == {4, 5, 6}
    assert cited("compensating forces, eqs. (4), (6)") == {4, 6}
    assert cited("event functions of eqs. (2), (3) and (12) — columns") == {2, 3, 12}
    assert cited("violation of conditions (1) at a state") == {1}
    assert cited("eq. (18)") == {18}
    # not citations: a bare number in parentheses, a list item, another kind of reference
    assert cited("the interpolation (8) of the step") == set()
    assert cited("1. (2) the second item; Fig. (3); seq. (4); (5)–(6)") == set()
    assert cited(None) == set()


def test_checker_rejects_a_wrong_path():
    """A path that does not import — a missing attribute, a wrong module, a nested function, a
    short name — is a problem; the same entry with the right path is not."""
    assert entry_problems(2, "stepcontact.contact.laws.CoulombLaw.event_values") == []
    for wrong in ("stepcontact.contact.laws.CoulombLaw.event_value",
                  "stepcontact.contact.law.CoulombLaw.event_values",
                  "stepcontact.solver.program.solve_dynamic.cut"):  # a nested function
        (problem,) = entry_problems(2, wrong)
        assert "does not import" in problem and wrong in problem
    (problem,) = entry_problems(2, "CoulombLaw.event_values")
    assert "not a full dotted path" in problem
    (problem,) = entry_problems(12, "stepcontact.contact.laws.BOND_COLUMNS")  # a tuple
    assert "not a module, class, function or method" in problem


def test_checker_rejects_a_missing_citation():
    """An object whose docstring does not cite the equation is a problem (event_values cites
    (2), (3) and (12), not (5)); a module is judged by its own docstring (stepcontact.errors
    cites none); a method by its own, not its class's (CoulombLaw cites (1))."""
    (problem,) = entry_problems(5, "stepcontact.contact.bond.BondedJointLaw.event_values")
    assert "does not cite eq. (5)" in problem and "(2), (3), (12)" in problem
    (problem,) = entry_problems(1, "stepcontact.errors")
    assert "does not cite eq. (1)" in problem
    assert entry_problems(1, "stepcontact.contact.laws.CoulombLaw") == []
    (problem,) = entry_problems(1, "stepcontact.contact.laws.CoulombLaw.slipping")
    assert "does not cite eq. (1)" in problem


def test_map_checker_on_a_fake_map():
    """A fake map: a row with a wrong path, a row whose object does not cite it, a row with no
    object, and the equations without a row — each is reported."""
    rows = {eq: "`stepcontact.solver.dynamic`" for eq in (7, 8, 9, 10)}
    rows[2] = "`stepcontact.contact.laws.CoulombLaw.event_values` (columns 1, 2)"
    rows[3] = "`stepcontact.contact.laws.CoulombLaw.no_such_method`"
    rows[5] = "`stepcontact.solver.engine.EventEngine.snap`"  # cites (4), (6), not (5)
    rows[11] = "the layer, in words only"
    text = "\n".join(["intro", "", "| article | meaning | code |", "|---|---|---|",
                      *(f"| ({eq}) | \\|Q\\| ≤ −f N | {code} |" for eq, code in rows.items()),
                      "", "after the table | not a row"])
    assert equation_map(text)[2] == ["stepcontact.contact.laws.CoulombLaw.event_values"]
    problems = map_problems(text)
    assert sorted(p for p in problems if "no row" in p) == sorted(
        f"({eq}) has no row in the map" for eq in (1, 4, 6, 12))
    assert any(p.startswith("(3) `stepcontact.contact.laws.CoulombLaw.no_such_method` does "
                            "not import") for p in problems)
    assert any(p.startswith("(5) `stepcontact.solver.engine.EventEngine.snap`: its docstring "
                            "does not cite eq. (5)") for p in problems)
    assert "(11) names no object" in problems
    assert len(problems) == 4 + 3, problems  # nothing else: (2), (7)–(10) are right


def test_module_checker_on_a_fake_table():
    """A fake table against fake modules: a missing module, a stale one, a wrong layer, a layer
    that is not its folder, a duplicate and an empty description are each reported."""
    modules = {"stepcontact", "stepcontact.errors", "stepcontact.model", "stepcontact.model.items",
               "stepcontact.solver.engine", "stepcontact.solver.rate"}
    text = "\n".join([
        "| module | layer | holds |", "|---|---|---|",
        "| `stepcontact` | api | the public names |",
        "| `stepcontact.errors` | base | exceptions |",
        "| `stepcontact.model.items` | fem | dataclasses |",
        "| `stepcontact.solver.engine` | engine | the event engine |",
        "| `stepcontact.solver.engine` | solver | the event engine |",
        "| `stepcontact.solver.gone` | solver | a module that was removed |",
        "| `stepcontact.model` | model |  |",
    ])
    problems = module_problems(text, modules)
    assert problems == [
        "stepcontact.model.items: layer 'fem', but it is in stepcontact/model/",
        f"stepcontact.solver.engine: layer 'engine' is not one of {', '.join(LAYERS)}",
        "stepcontact.solver.engine is listed twice",
        "stepcontact.solver.gone is listed but there is no such module",
        "stepcontact.model: no line on what it holds",
        "stepcontact.solver.rate (missing from the table: add it with its layer and what it "
        "holds)",
    ]


def test_package_modules_are_found():
    """The scanner finds packages by their __init__.py and private modules too."""
    found = package_modules()
    assert {"stepcontact", "stepcontact.solver", "stepcontact.solver.dynamic",
            "stepcontact.fem._edge_kinks"} <= found
    assert not any(name.endswith("__init__") for name in found)
