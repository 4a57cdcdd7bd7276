"""The documentation is checked against the code.

* the generated references (docs/model-file-reference.md, docs/cli.md) are up to date;
* every complete TOML model in docs/*.md (one with a ``[[program]]`` or ``[[stages]]``) is
  valid, and every TOML block parses;
* the results the text states for a TOML model (``run:`` markers) are what the model gives;
* the Python snippets of docs/user-guide.md run, in order, as one session, and print what the
  guide shows after them (the text, and every number to its last shown digit);
* an example's output shown in the docs (``output:`` markers) is what the example prints;
* the example model files validate against the JSON schema and load;
* every ``stepcontact.X.Y`` named in docs/, examples/ and pyproject.toml resolves;
* relative links between the documents point to existing files.

Markers (HTML comments on the line before a code block, invisible when rendered):
``<!-- norun -->`` — a Python block that is not run (only compiled);
``<!-- fragment: reason -->`` — a TOML block that is an overview, not a complete model;
``<!-- run: KEY = VALUE (rtol R), … -->`` — a TOML model whose results the text just before
it states: KEY is a multiplier of the last segment (``equilibrium_lost``, ``first_slip``,
``first_opening``, ``first_closing``) or ``reaction NAME DOF`` at the last state; on a
fragment (``<!-- fragment: replaces [patterns.water] … of the model above; run: … -->``) the
fragment is applied to the complete model above it;
``<!-- output: examples/X.py -->`` — a ``text`` block that is what that example prints.
"""

from __future__ import annotations

import importlib.util
import re
import time
import tomllib
from dataclasses import dataclass
from pathlib import Path

import pytest

from stepcontact.io.modelfile import load_model, model_from_dict, schema

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
GUIDE = DOCS / "user-guide.md"
MODEL_FILES = sorted((ROOT / "examples" / "data").glob("*.toml")) + sorted(
    (ROOT / "src" / "stepcontact" / "data").glob("*.toml")
)
SNIPPET_BUDGET = 5.0  #: seconds the user-guide snippets may take (reported, not asserted)


def _generator():
    spec = importlib.util.spec_from_file_location("generate_reference",
                                                  DOCS / "generate_reference.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@dataclass(frozen=True)
class Block:
    """A fenced code block of a markdown file."""

    path: Path
    line: int  # line of the opening fence, from 1
    lang: str
    text: str
    marker: str  # the HTML comment on the line before the fence ("" if none)

    @property
    def id(self) -> str:
        return f"{self.path.name}:{self.line}"


def code_blocks(path: Path) -> list[Block]:
    """Fenced code blocks (```lang ... ```) of a markdown file, with their markers."""
    lines = path.read_text(encoding="utf-8").splitlines()
    blocks, i = [], 0
    while i < len(lines):
        m = re.match(r"^(`{3,})\s*([\w+-]*)\s*$", lines[i])
        if not m:
            i += 1
            continue
        fence, lang = m.group(1), m.group(2).lower()
        j = i + 1
        while j < len(lines) and not lines[j].startswith(fence):
            j += 1
        assert j < len(lines), f"{path.name}:{i + 1}: unclosed code block"
        k = i - 1
        while k >= 0 and not lines[k].strip():
            k -= 1
        prev = lines[k].strip() if k >= 0 else ""
        marker = prev if prev.startswith("<!--") and prev.endswith("-->") else ""
        blocks.append(Block(path, i + 1, lang, "\n".join(lines[i + 1:j]) + "\n", marker))
        i = j + 1
    return blocks


DOC_FILES = sorted(DOCS.glob("*.md"))
TOML_BLOCKS = [b for p in DOC_FILES for b in code_blocks(p) if b.lang == "toml"]
MODEL_BLOCKS = [b for b in TOML_BLOCKS
                if re.search(r"^\s*\[\[(program|stages)\]\]", b.text, re.M)]
PYTHON_BLOCKS = [b for b in code_blocks(GUIDE) if b.lang == "python"]


# --------------------------------------------------------------------------------------------
# (a) generated references
# --------------------------------------------------------------------------------------------
def test_generated_references_are_up_to_date():
    gen = _generator()
    files = gen.outputs()
    assert set(files) == {DOCS / "model-file-reference.md", DOCS / "cli.md"}
    for path, text in files.items():
        assert path.is_file(), f"{path.name} is missing: run  python docs/generate_reference.py"
        assert path.read_text(encoding="utf-8") == text, (
            f"docs/{path.name} is out of date: run  python docs/generate_reference.py"
        )
    assert gen.stale(files) == []


def test_generator_check_mode_reports_stale_files(monkeypatch, capsys):
    gen = _generator()
    assert gen.main(["--check"]) == 0
    real = gen.outputs()
    changed = {p: text + "\nchanged\n" for p, text in real.items()}
    monkeypatch.setattr(gen, "outputs", lambda: changed)
    assert gen.main(["--check"]) == 1  # and writes nothing
    assert "is out of date" in capsys.readouterr().err
    assert all(p.read_text(encoding="utf-8") == t for p, t in real.items())


def test_model_file_reference_covers_the_schema():
    """Every table of the schema has a section and every field a row."""
    text = (DOCS / "model-file-reference.md").read_text(encoding="utf-8")
    s = schema()
    for name in s["properties"]:
        assert f"[{name}" in text or f"[[{name}]]" in text, name
    for def_name, d in s["$defs"].items():
        for field in d.get("properties", {}):
            assert f"| `{field}` |" in text, f"{def_name}.{field}"
    for kind in ("rectangle", "mesh"):
        assert f'`[[bodies]] kind = "{kind}"`' in text
    for load in ("gravity", "nodal", "pressure", "displacement"):
        assert f'loads with type = "{load}"' in text


def test_cli_reference_covers_every_command_and_option():
    import typer

    from stepcontact.cli import app

    text = (DOCS / "cli.md").read_text(encoding="utf-8")
    group = typer.main.get_command(app)
    ctx = group.context_class(group, info_name="stepcontact")
    for name in group.list_commands(ctx):
        cmd = group.get_command(ctx, name)
        assert f"## `stepcontact {name}`" in text, name
        for p in cmd.get_params(ctx):
            for opt in p.opts if p.param_type_name == "option" else []:
                assert opt in text, f"{name} {opt}"
    assert "\x1b" not in text  # no ANSI escapes


# --------------------------------------------------------------------------------------------
# (b) TOML models in the documentation
# --------------------------------------------------------------------------------------------
def test_docs_have_complete_models():
    assert [b for b in MODEL_BLOCKS if b.path == GUIDE], "the user guide has no complete model"


@pytest.mark.parametrize("block", TOML_BLOCKS, ids=[b.id for b in TOML_BLOCKS])
def test_toml_block_parses(block):
    tomllib.loads(block.text)


@pytest.mark.parametrize("block", MODEL_BLOCKS, ids=[b.id for b in MODEL_BLOCKS])
def test_toml_model_in_docs_is_valid(block):
    if block.marker.startswith("<!-- fragment"):
        reason = block.marker.removeprefix("<!-- fragment").strip(" :->")
        pytest.skip(f"{block.id} is marked as a fragment: {reason or 'not a complete model'}")
    data = tomllib.loads(block.text)
    mesh_file = (data.get("mesh") or {}).get("file")
    if mesh_file is not None:
        pytest.skip(f"{block.id} references the mesh file '{mesh_file}', which the docs do not "
                    "ship")
    model = model_from_dict(data)
    assert model.effective_program
    try:
        import jsonschema
    except ImportError:  # the pydantic validation above is the reference
        return
    jsonschema.Draft202012Validator(schema()).validate(data)


# --------------------------------------------------------------------------------------------
# (b2) models in the documentation whose results the text states: run and compared
# --------------------------------------------------------------------------------------------
#: what a ``run:`` marker may compare: the multipliers of the last segment reached, or a
#: support's or obstacle's reaction at the last state (``reaction NAME DOF``)
MULTIPLIERS = ("first_slip", "first_opening", "first_closing", "equilibrium_lost")


@dataclass(frozen=True)
class Stated:
    """One result a document states, from a ``run:`` marker: ``KEY = VALUE (rtol R)``."""

    key: str
    text: str  # the value as written (it must appear in the text before the block)
    value: float
    rtol: float


def _number(text: str) -> float:
    """A number or a quotient of two (``1/3``), as the docs write it."""
    a, _, b = text.partition("/")
    return float(a) / float(b) if b else float(a)


def stated_results(marker: str) -> list[Stated]:
    """The results a ``<!-- … run: KEY = VALUE (rtol R), … -->`` marker states."""
    m = re.search(r"run:(.*?)-->", marker)
    if not m:
        return []
    out = []
    for item in re.finditer(r"([\w ]+?)\s*=\s*([-+\d.e/]+)\s*\(rtol\s+([\d.e+-]+)\)",
                            m.group(1)):
        key, text, rtol = item.group(1).strip(), item.group(2), float(item.group(3))
        out.append(Stated(key, text, _number(text), rtol))
    assert out, f"unreadable run marker: {marker}"
    return out


def _merged(base: dict, fragment: dict, marker: str) -> dict:
    """A fragment applied to the model above it: the tables the marker says it replaces
    (``replaces [patterns.water]``) are removed, then its tables are merged one level deep
    and its arrays (``[[program]]``) replace the model's."""
    import copy

    data = copy.deepcopy(base)
    for dotted in re.findall(r"\[([\w.]+)\]", marker.split("run:")[0]):
        *parents, last = dotted.split(".")
        table = data
        for k in parents:
            table = table[k]
        del table[last]
    for key, value in fragment.items():
        if isinstance(value, dict) and isinstance(data.get(key), dict):
            data[key].update(value)
        else:
            data[key] = value
    return data


RUN_BLOCKS = [b for b in MODEL_BLOCKS if "run:" in b.marker]


def _model_of(block: Block) -> dict:
    data = tomllib.loads(block.text)
    if block.marker.startswith("<!-- fragment"):
        above = [b for b in MODEL_BLOCKS if b.path == block.path and b.line < block.line
                 and not b.marker.startswith("<!-- fragment")]
        assert above, f"{block.id}: a fragment with results needs a complete model above it"
        data = _merged(tomllib.loads(above[-1].text), data, block.marker)
    return data


def _prose_before(block: Block, lines: int = 14) -> str:
    text = block.path.read_text(encoding="utf-8").splitlines()
    return " ".join(text[max(0, block.line - 1 - lines):block.line - 1])


def test_docs_state_results_of_their_models():
    """The documents do state results of their models (a guard for the test below)."""
    assert {b.path.name for b in RUN_BLOCKS} >= {"model-file.md", "user-guide.md"}
    assert stated_results("<!-- run: a = 1/3 (rtol 1e-9), reaction g y = 4e5 (rtol 1e-6) -->") \
        == [Stated("a", "1/3", 1 / 3, 1e-9), Stated("reaction g y", "4e5", 4e5, 1e-6)]


@pytest.mark.parametrize("block", RUN_BLOCKS, ids=[b.id for b in RUN_BLOCKS])
def test_stated_results_of_a_docs_model(block):
    """Each result a document states for one of its TOML models (its ``run:`` marker: the
    value as the text writes it and a relative tolerance) is what the model gives; the
    value appears in the text just before the block, so the marker and the prose agree."""
    import stepcontact as sc

    stated = stated_results(block.marker)
    prose = _prose_before(block)
    for s in stated:
        assert s.text in prose, f"{block.id}: the text before the block does not state {s.text}"
    res = sc.solve_static(model_from_dict(_model_of(block)))
    for s in stated:
        if s.key in MULTIPLIERS:
            got = getattr(res.multipliers[-1], s.key)
        else:
            what, name, dof = s.key.split()
            assert what == "reaction", f"{block.id}: unknown result '{s.key}'"
            got = res.reaction(name, dof)[-1]
        assert got is not None, f"{block.id}: {s.key} did not happen (stated {s.text})"
        assert abs(got - s.value) <= s.rtol * abs(s.value), (
            f"{block.id}: {s.key} is {got!r}, the document states {s.text} (rtol {s.rtol})")


# --------------------------------------------------------------------------------------------
# (b3) printed output the documents show: the same text, the same numbers
# --------------------------------------------------------------------------------------------
_NUMBER = re.compile(r"[-+−]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?")


def _ulp(text: str) -> float:
    """One unit in the last printed digit of a number as written (1e-4 for 1.8738, 1 for
    23544, 1e-15 for 2.44e-15)."""
    mant, _, exp = text.lower().lstrip("+-−").partition("e")
    decimals = len(mant.partition(".")[2])
    return 10.0 ** (int(exp or 0) - decimals)


def output_differences(shown: str, printed: str, rtol: float = 1e-9,
                       roundoff: float = 1e-9) -> list[str]:
    """Where ``printed`` (what the code prints) differs from ``shown`` (what a document shows):
    the text between the numbers must be the same (whitespace aside), and each number equal
    within one unit of its last shown digit or ``rtol``; numbers below ``roundoff`` in both
    (equilibrium residuals, violations: round-off, machine-dependent) are not compared."""
    def split(text):
        return _NUMBER.split(" ".join(text.split())), _NUMBER.findall(" ".join(text.split()))

    (words_s, nums_s), (words_p, nums_p) = split(shown), split(printed)
    if words_s != words_p or len(nums_s) != len(nums_p):
        for a, b in zip(shown.splitlines(), printed.splitlines(), strict=False):
            if _NUMBER.sub("#", " ".join(a.split())) != _NUMBER.sub("#", " ".join(b.split())):
                return [f"line shown {a!r}, printed {b!r}"]
        return [f"shown {len(shown.splitlines())} lines, printed {len(printed.splitlines())}"]
    bad = []
    for a, b in zip(nums_s, nums_p, strict=True):
        x, y = float(a.replace("−", "-")), float(b.replace("−", "-"))
        if abs(x) < roundoff and abs(y) < roundoff:
            continue
        if abs(x - y) > max(_ulp(a) * 1.0000001, rtol * abs(x)):
            bad.append(f"{a} shown, {b} printed")
    return bad


def test_output_comparison_catches_a_changed_number():
    assert output_differences("slides at λ = 1.8738 (f·W)", "slides at λ = 1.8738 (f·W)") == []
    assert output_differences("residual 2.44e-15, λ = 23544", "residual 3.1e-16, λ = 23544") == []
    assert output_differences("λ = 1.8738", "λ = 1.8739") == []  # the last digit may flip
    assert output_differences("λ = 1.8738", "λ = 1.7009") == ["1.8738 shown, 1.7009 printed"]
    assert output_differences("slides at", "lifts at")


OUTPUT_BLOCKS = [b for p in DOC_FILES for b in code_blocks(p)
                 if b.marker.startswith("<!-- output:")]


def test_docs_show_example_outputs():
    assert any(b.path == GUIDE for b in OUTPUT_BLOCKS)


@pytest.mark.parametrize("block", OUTPUT_BLOCKS, ids=[b.id for b in OUTPUT_BLOCKS])
def test_example_output_shown_in_the_docs(block, tmp_path, monkeypatch, capsys):
    """A ``<!-- output: examples/X.py -->`` block is what the example prints (its own
    assertions run too): the text, and every number to its last shown digit."""
    import runpy

    script = ROOT / block.marker.removeprefix("<!-- output:").removesuffix("-->").strip()
    assert script.is_file(), f"{block.id}: no such example {script}"
    monkeypatch.chdir(tmp_path)
    capsys.readouterr()
    runpy.run_path(str(script), run_name="__main__")
    printed = capsys.readouterr().out
    bad = output_differences(block.text, printed)
    assert not bad, f"docs/{block.id} does not show what {script.name} prints: {bad[:5]}"


# --------------------------------------------------------------------------------------------
# (c) Python snippets of the user guide
# --------------------------------------------------------------------------------------------
def test_user_guide_has_snippets():
    assert len([b for b in PYTHON_BLOCKS if b.marker != "<!-- norun -->"]) >= 5


@pytest.mark.parametrize("block", PYTHON_BLOCKS, ids=[b.id for b in PYTHON_BLOCKS])
def test_user_guide_snippet_compiles(block):
    compile(block.text, block.id, "exec")


def shown_output(block: Block) -> Block | None:
    """The ``text`` block right after a Python block (blank lines between), if any: what the
    document says the snippet prints."""
    blocks = code_blocks(block.path)
    k = blocks.index(block)
    if k + 1 == len(blocks) or blocks[k + 1].lang != "text":
        return None
    after = block.line + block.text.count("\n") + 1  # the closing fence's line
    lines = block.path.read_text(encoding="utf-8").splitlines()
    gap = lines[after:blocks[k + 1].line - 1]
    return blocks[k + 1] if not any(s.strip() for s in gap) else None


def test_user_guide_snippets_run(tmp_path, monkeypatch, capsys):
    """The snippets build on each other (as in a notebook): run them in order in one
    namespace, in a temporary directory; ``<!-- norun -->`` blocks are skipped.  Where the
    guide shows a snippet's output (a ``text`` block right after it), the snippet prints that
    text, every number to its last shown digit (:func:`output_differences`)."""
    monkeypatch.chdir(tmp_path)
    namespace: dict[str, object] = {"__name__": "__user_guide__"}
    t0 = time.perf_counter()
    compared, wrong = 0, []
    for block in PYTHON_BLOCKS:
        if block.marker == "<!-- norun -->":
            continue
        capsys.readouterr()
        try:
            exec(compile(block.text, block.id, "exec"), namespace)
        except Exception as exc:
            raise AssertionError(f"the snippet at docs/{block.id} fails: {exc!r}") from exc
        shown = shown_output(block)
        if shown is not None:
            compared += 1
            bad = output_differences(shown.text, capsys.readouterr().out)
            if bad:
                wrong.append(f"docs/{shown.id}: {bad[:3]}")
    elapsed = time.perf_counter() - t0
    capsys.readouterr()
    assert compared >= 15, compared
    assert not wrong, "the guide shows another output than its snippets print: " + "; ".join(
        wrong)
    if elapsed > SNIPPET_BUDGET:  # keep them fast; not a failure (machines differ)
        print(f"user-guide snippets took {elapsed:.1f} s (budget {SNIPPET_BUDGET} s)")


# --------------------------------------------------------------------------------------------
# (d) example model files
# --------------------------------------------------------------------------------------------
def _ids(paths: list[Path]) -> list[str]:
    return [p.relative_to(ROOT).as_posix() for p in paths]


def test_there_are_example_model_files():
    assert len(MODEL_FILES) >= 3


@pytest.mark.parametrize("path", MODEL_FILES, ids=_ids(MODEL_FILES))
def test_example_model_file_matches_the_json_schema(path):
    jsonschema = pytest.importorskip("jsonschema")
    with open(path, "rb") as fh:
        data = tomllib.load(fh)
    jsonschema.Draft202012Validator(schema()).validate(data)


@pytest.mark.parametrize("path", MODEL_FILES, ids=_ids(MODEL_FILES))
def test_example_model_file_loads(path):
    model = load_model(path)
    with open(path, "rb") as fh:  # a file for the dam study needs no program of its own
        study = "dam" in tomllib.load(fh)
    assert model.bodies and (model.effective_program or study)


# --------------------------------------------------------------------------------------------
# links
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("path", DOC_FILES, ids=[p.name for p in DOC_FILES])
def test_relative_links_exist(path):
    text = path.read_text(encoding="utf-8")
    text = re.sub(r"```.*?```", "", text, flags=re.S)  # links in code blocks are not links
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"^[a-z]+:", target) or target.startswith("#"):
            continue
        file = target.split("#")[0]
        assert (path.parent / file).exists(), f"{path.name}: broken link to {target}"


def test_index_links_every_document():
    text = (DOCS / "index.md").read_text(encoding="utf-8")
    for doc in DOC_FILES:
        if doc.name != "index.md":
            assert f"]({doc.name})" in text, f"index.md does not link {doc.name}"


# --------------------------------------------------------------------------------------------
# dotted names of stepcontact in the docs, the examples and pyproject.toml
# --------------------------------------------------------------------------------------------
NAME_FILES = sorted(
    [*DOCS.glob("*.md"), ROOT / "README.md", ROOT / "pyproject.toml",
     *(p for p in (ROOT / "examples").rglob("*") if p.is_file()
       and p.suffix in {".py", ".toml", ".geo", ".md", ".txt"})]
)
#: file endings after a dotted name that make it a file name, not a Python name
_FILE_ENDINGS = {"json", "toml", "nc", "png", "pdf", "svg", "py", "msh", "geo", "vtu", "pvd",
                 "xdmf", "csv", "md", "txt", "h5"}


def dotted_names(text: str) -> set[str]:
    """``stepcontact.X.Y`` names and the names of ``from stepcontact.X import a, b`` lines."""
    names = set()
    for m in re.finditer(r"(?<![\w./-])stepcontact(?:\.[A-Za-z_]\w*)+", text):
        name = m.group(0)
        if name.rsplit(".", 1)[-1] in _FILE_ENDINGS:
            continue
        names.add(name)
    for m in re.finditer(r"from[ \t]+(stepcontact(?:\.\w+)*)[ \t]+import[ \t]+"
                         r"(\(([^)]*)\)|[\w \t,]+)", text):
        listed = m.group(3) if m.group(3) is not None else m.group(2)
        for n in listed.split(","):
            n = n.split("#")[0].split(" as ")[0].strip()
            if n.isidentifier():
                names.add(f"{m.group(1)}.{n}")
    return names


def resolve(name: str) -> object:
    """Import the longest importable module prefix of ``name``, then get the attributes."""
    import importlib

    parts = name.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ModuleNotFoundError:
            continue
        for attr in parts[k:]:
            obj = getattr(obj, attr)  # AttributeError: the name does not exist
        return obj
    raise ModuleNotFoundError(name)


def test_dotted_names_are_found():
    """The scanner finds the names it must (a regression guard for the test below)."""
    text = ("see stepcontact.io.meshfile.mesh_geo and stepcontact schema > "
            "stepcontact.schema.json; from stepcontact.io.modelfile import load_model, schema")
    assert dotted_names(text) == {"stepcontact.io.meshfile.mesh_geo", "stepcontact.io.modelfile",
                                  "stepcontact.io.modelfile.load_model",
                                  "stepcontact.io.modelfile.schema"}
    with pytest.raises((ModuleNotFoundError, AttributeError)):
        resolve("stepcontact.meshfile.mesh_geo")


@pytest.mark.parametrize("path", NAME_FILES, ids=_ids(NAME_FILES))
def test_dotted_names_resolve(path):
    """Every ``stepcontact.X.Y`` a document, example or pyproject.toml names imports."""
    bad = []
    for name in sorted(dotted_names(path.read_text(encoding="utf-8"))):
        try:
            resolve(name)
        except (ImportError, AttributeError) as e:
            bad.append(f"{name} ({type(e).__name__}: {e})")
    assert not bad, f"{path.relative_to(ROOT)} names what does not exist: {'; '.join(bad)}"
