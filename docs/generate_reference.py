"""Generate the reference pages of the documentation from the code.

* ``docs/model-file-reference.md`` from the JSON schema of the TOML model file
  (:func:`stepcontact.io.modelfile.schema`, i.e. the pydantic models of ``io/modelfile/schema.py``);
* ``docs/cli.md`` from the typer application :data:`stepcontact.cli.app`, through
  typer's/click's own command objects (``typer.main.get_command``, contexts, help records).

Usage::

    python docs/generate_reference.py            # (re)write both files
    python docs/generate_reference.py --check    # exit 1 if a committed file is out of date

The output is deterministic: sections follow the order of the schema's properties and of the
commands' registration, and nothing depends on the terminal (width, colours) or the clock.
"""

from __future__ import annotations

import argparse
import inspect
import json
import re
import sys
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

DOCS = Path(__file__).resolve().parent
MODEL_FILE_REFERENCE = DOCS / "model-file-reference.md"
CLI_REFERENCE = DOCS / "cli.md"
GENERATOR = "docs/generate_reference.py"

try:  # the installed package; else the source tree next to docs/
    import stepcontact  # noqa: F401
except ImportError:  # pragma: no cover - only without `pip install -e .`
    sys.path.insert(0, str(DOCS.parent / "src"))

# --------------------------------------------------------------------------------------------
# model file reference
# --------------------------------------------------------------------------------------------
#: Descriptions of fields that the schema leaves without one, keyed by (schema $def, field).
#: The schema's own description always wins; a key naming a field the schema does not have
#: is an error (so a renamed field cannot leave a stale note behind).
FIELD_NOTES: dict[tuple[str, str], str] = {
    ("ModelSection", "name"): "name of the model (results, figures); default: the file's stem",
    ("ModelSection", "plane"): "plane strain or plane stress",
    ("RectangleSpec", "name"): "unique body name",
    ("RectangleSpec", "element"): "element kind (linear or quadratic triangles and quads)",
    ("RectangleSpec", "material"):
        "a material name from `[materials.NAME]`, or an inline table `{E, nu, density}`",
    ("MeshBodySpec", "name"): "body name (default: the physical surface `group`)",
    ("MeshBodySpec", "element"):
        "element kind (default: the cells' own kind; a linear mesh may be raised to the "
        "quadratic element of its shape)",
    ("MeshBodySpec", "material"):
        "a material name from `[materials.NAME]`, or an inline table `{E, nu, density}`; "
        "required (a missing one is reported with the other problems of the file)",
    ("FrameSpec", "name"): "unique body name of the frame",
    ("BoxSpec", "xmin"): "lower bound of x, m (none: unbounded)",
    ("BoxSpec", "xmax"): "upper bound of x, m (none: unbounded)",
    ("BoxSpec", "ymin"): "lower bound of y, m (none: unbounded)",
    ("BoxSpec", "ymax"): "upper bound of y, m (none: unbounded)",
    ("NodeSetSpec", "body"):
        "the body (or frame) whose nodes are selected; with `group` only for a curve shared "
        "by two conforming mesh bodies",
    ("NodeSetSpec", "where"): "nodes inside a box (bounds inclusive)",
    ("SupportSpec", "name"): "name of the support (default: the node set's name)",
    ("SupportSpec", "nodes"): "node set (or physical curve/point of `[mesh]`)",
    ("SupportSpec", "dofs"): "fixed degrees of freedom: any of `x`, `y`, `rz`, e.g. `\"xy\"`",
    ("TieSpec", "name"): "name of the tie (default: `a-b`)",
    ("TieSpec", "a"): "node set whose translations are tied",
    ("TieSpec", "b"): "node set of the same size; `a[i]` is tied to `b[i]`",
    ("SpringSpec", "name"): "name of the springs (default: the name of `a`)",
    ("SpringSpec", "a"): "node set at one end of the springs",
    ("SpringSpec", "b"): "node set at the other end (same size as `a`); absent: the ground",
    ("InterfaceSpec", "name"): "unique interface name",
    ("InterfaceSpec", "plus"): "node set on S+ (one CFE at each of its nodes)",
    ("InterfaceSpec", "minus"): "node set on S− (the meshes of S+ and S− need not match)",
    ("InterfaceSpec", "layer"): "compliant contact layer, eq. (11); absent: rigid contact",
    ("GravityLoad", "g"): "acceleration vector (g_x, g_y), m/s²",
    ("GravityLoad", "bodies"): "bodies that carry their self-weight (empty: all bodies)",
    ("NodalLoadSpec", "nodes"): "node set; the load acts on every node of it",
    ("NodalLoadSpec", "fx"): "force along x on each node, N (per unit load factor)",
    ("NodalLoadSpec", "fy"): "force along y on each node, N (per unit load factor)",
    ("NodalLoadSpec", "mz"): "moment on each node, N·m (frame nodes only)",
    ("PressureLoad", "nodes"): "node set; the body edges whose nodes all lie in it are loaded",
    ("DisplacementLoad", "nodes"): "node set whose degree of freedom is prescribed",
    ("DisplacementLoad", "dof"): "the prescribed degree of freedom",
    ("DisplacementLoad", "value"): "prescribed value, m (rad for `rz`) per unit load factor",
    ("PatternSpec", "loads"): "the loads of the pattern, all scaled by its load factor λ",
    ("SegmentSpec", "pattern"): "the load pattern whose factor changes",
    ("SegmentSpec", "end"): "load factor λ at the end of the segment",
}


def _md_cell(text: str) -> str:
    """Text for a markdown table cell: one line, pipes escaped."""
    return " ".join(text.split()).replace("|", "\\|")


def _rst_to_md(text: str) -> str:
    """A docstring (reST inline markup) as one markdown paragraph."""
    text = re.sub(r":\w+:`~?([^`]+)`", r"`\1`", text)  # :class:`~x.Y` -> `x.Y`
    return " ".join(text.replace("``", "`").split())


def _toml(value: Any) -> str:
    """A JSON value written as TOML."""
    if value is None:
        return "—"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    if isinstance(value, dict):
        if not value:
            return "{}"
        return "{ " + ", ".join(f"{k} = {_toml(v)}" for k, v in value.items()) + " }"
    return repr(value)


class _Reference:
    """Walks the schema and renders the model-file reference."""

    def __init__(self, schema: dict[str, Any]):
        self.schema = schema
        self.defs: dict[str, dict[str, Any]] = schema.get("$defs", {})
        self.anchor_of: dict[str, tuple[str, str]] = {}  # $def -> (anchor, title)
        self.used_notes: set[tuple[str, str]] = set()
        for def_name, field in FIELD_NOTES:
            props = self.defs.get(def_name, {}).get("properties", {})
            if field not in props:
                raise KeyError(
                    f"{GENERATOR}: FIELD_NOTES names {def_name}.{field}, which is not in the "
                    "schema any more: update FIELD_NOTES"
                )

    # ---- schema helpers --------------------------------------------------------------------
    def ref_name(self, node: dict[str, Any]) -> str | None:
        ref = node.get("$ref")
        if ref is None:
            return None
        prefix = "#/$defs/"
        if not ref.startswith(prefix):
            raise ValueError(f"unsupported $ref {ref!r}")
        return ref[len(prefix):]

    def resolve(self, node: dict[str, Any]) -> dict[str, Any]:
        name = self.ref_name(node)
        return node if name is None else self.resolve(self.defs[name])

    @staticmethod
    def alternatives(node: dict[str, Any]) -> list[dict[str, Any]]:
        """The alternatives of an anyOf/oneOf (flattened, ``null`` removed), else [node]."""
        alts = node.get("anyOf") or node.get("oneOf")
        if alts is None:
            return [node]
        out: list[dict[str, Any]] = []
        for a in alts:
            if a.get("type") == "null":
                continue
            out += _Reference.alternatives(a)
        return out

    def is_table(self, node: dict[str, Any]) -> bool:
        return self.resolve(node).get("type") == "object" and "properties" in self.resolve(node)

    def table_refs(self, node: dict[str, Any]) -> list[str]:
        """$defs of the tables a field holds (itself, or as items of an array)."""
        out = []
        for alt in self.alternatives(node):
            if alt.get("type") == "array" and "items" in alt:
                out += self.table_refs(alt["items"])
            name = self.ref_name(alt)
            if name is not None and self.is_table(alt):
                out.append(name)
        return out

    @staticmethod
    def discriminator(props: dict[str, Any]) -> tuple[str, Any] | None:
        for key, sub in props.items():
            if "const" in sub:
                return key, sub["const"]
        return None

    # ---- cells -------------------------------------------------------------------------------
    def type_of(self, node: dict[str, Any]) -> str:
        alts = self.alternatives(node)
        tables = [self.ref_name(a) for a in alts if self.is_table(a)]
        if len(alts) > 1 and len(tables) == len(alts):  # a discriminated union of tables
            links = []
            for name in tables:
                assert name is not None
                disc = self.discriminator(self.defs[name].get("properties", {}))
                anchor, title = self.anchor_of.get(name, ("", name))
                label = f"{disc[0]} = {_toml(disc[1])}" if disc is not None else title
                links.append(f"[`{label}`](#{anchor})" if anchor else f"`{label}`")
            return "table with " + " or ".join(links)
        if len(alts) > 1:
            parts = list(dict.fromkeys(self.type_of(a) for a in alts))
            return " or ".join(parts)
        node = alts[0]
        name = self.ref_name(node)
        if name is not None:
            if self.is_table(node):
                anchor, title = self.anchor_of.get(name, ("", name))
                return f"table ([`{title}`](#{anchor}))" if anchor else "table"
            return self.type_of(self.defs[name])
        if "const" in node:
            return f"`{_toml(node['const'])}`"
        if "enum" in node:
            return "one of " + ", ".join(f"`{_toml(v)}`" for v in node["enum"])
        t = node.get("type")
        if t == "array":
            if "prefixItems" in node:
                return "[" + ", ".join(self.type_of(i) for i in node["prefixItems"]) + "]"
            items = node.get("items")
            n_min, n_max = node.get("minItems"), node.get("maxItems")
            if items is not None and n_min is not None and n_min == n_max and n_min <= 3:
                return "[" + ", ".join([self.type_of(items)] * n_min) + "]"
            return f"array of {self.type_of(items)}" if items is not None else "array"
        if t == "object":
            extra = node.get("additionalProperties")
            if isinstance(extra, dict):
                return f"table of NAME = {self.type_of(extra)}"
            return "table"
        return {"number": "number", "integer": "integer", "string": "string",
                "boolean": "boolean"}.get(str(t), str(t))

    def constraints(self, node: dict[str, Any]) -> str:
        out: list[str] = []
        for alt in self.alternatives(node):
            alt = self.resolve(alt) if not self.is_table(alt) else alt
            bounds = (("minimum", "≥"), ("exclusiveMinimum", ">"), ("maximum", "≤"),
                      ("exclusiveMaximum", "<"))
            out += [f"{op} {alt[k]!r}" for k, op in bounds if k in alt]
            if alt.get("type") == "array" and "prefixItems" not in alt:
                n_min, n_max = alt.get("minItems"), alt.get("maxItems")
                fixed = n_min is not None and n_min == n_max and n_min <= 3
                if n_min is not None and not fixed:
                    out.append(f"at least {n_min} item{'s' * (n_min != 1)}")
                if n_max is not None and not fixed:
                    out.append(f"at most {n_max} item{'s' * (n_max != 1)}")
                items = alt.get("items")
                if isinstance(items, dict) and not self.is_table(items):
                    inner = self.constraints(items)
                    if inner:
                        out.append(f"items {inner}")
            if "minLength" in alt:
                out.append(f"length ≥ {alt['minLength']}")
        return ", ".join(dict.fromkeys(out))

    def description(self, def_name: str, field: str, node: dict[str, Any]) -> str:
        text = node.get("description")
        if text is None:
            for alt in node.get("anyOf") or node.get("oneOf") or []:
                if "description" in alt:
                    text = alt["description"]
                    break
        if text is None and (def_name, field) in FIELD_NOTES:
            text = FIELD_NOTES[(def_name, field)]
        if text is None and "const" in node:
            text = f"selects this kind of entry (`{field} = {_toml(node['const'])}`)"
        return _rst_to_md(text or "")

    def default(self, field: str, node: dict[str, Any], required: Iterable[str]) -> str:
        if field in required:
            return "**required**"
        if "default" not in node:
            return "—"
        d = node["default"]
        return "—" if d is None else f"`{_toml(d)}`"

    # ---- sections ---------------------------------------------------------------------------
    def fields_table(self, def_name: str) -> list[str]:
        d = self.defs[def_name]
        required = d.get("required", [])
        rows = ["| field | type | default | constraint | description |",
                "|---|---|---|---|---|"]
        for field, node in d.get("properties", {}).items():
            rows.append("| " + " | ".join(_md_cell(c) for c in (
                f"`{field}`", self.type_of(node), self.default(field, node, required),
                self.constraints(node), self.description(def_name, field, node),
            )) + " |")
        return rows

    def plan(self) -> list[dict[str, Any]]:
        """Sections in order: (def, title, anchor, level, header, parent) records."""
        sections: list[dict[str, Any]] = []
        root = self.schema.get("properties", {})
        for key, node in root.items():
            anchor = key.replace("_", "-")
            alts = self.alternatives(node)
            core = alts[0]
            if self.ref_name(core) is not None and len(alts) == 1:
                sections.append({"def": self.ref_name(core), "title": f"[{key}]",
                                 "anchor": anchor, "key": key})
            elif core.get("type") == "object" and isinstance(core.get("additionalProperties"),
                                                              dict):
                name = self.ref_name(core["additionalProperties"])
                sections.append({"def": name, "title": f"[{key}.NAME]", "anchor": anchor,
                                 "key": key})
            elif core.get("type") == "array":
                variants = self.alternatives(core["items"])
                for v in variants:
                    name = self.ref_name(v)
                    title, anc = f"[[{key}]]", anchor
                    disc = self.discriminator(self.defs[name].get("properties", {}))
                    if len(variants) > 1 and disc is not None:
                        title = f"[[{key}]] {disc[0]} = {_toml(disc[1])}"
                        anc = f"{anchor}-{disc[1]}"
                    sections.append({"def": name, "title": title, "anchor": anc, "key": key})
            else:
                raise ValueError(f"top-level property {key!r}: unsupported schema {node}")
        for s in sections:
            s["level"] = 2
            self.anchor_of.setdefault(s["def"], (s["anchor"], s["title"]))
        # nested tables (inline tables), each documented once, under its first use
        out: list[dict[str, Any]] = []
        documented = {s["def"] for s in sections}

        def nested(parent: dict[str, Any]) -> Iterator[dict[str, Any]]:
            for field, node in self.defs[parent["def"]].get("properties", {}).items():
                refs = self.table_refs(node)
                for name in refs:
                    if name in documented:
                        continue
                    documented.add(name)
                    disc = self.discriminator(self.defs[name].get("properties", {}))
                    title = f"{parent['title']} → {field}"
                    anchor = f"{parent['anchor']}-{field.replace('_', '-')}"
                    if len(refs) > 1 and disc is not None:
                        title += f" with {disc[0]} = {_toml(disc[1])}"
                        anchor += f"-{disc[1]}"
                    child = {"def": name, "title": title, "anchor": anchor,
                             "level": parent["level"] + 1, "key": parent["key"], "field": field}
                    self.anchor_of[name] = (anchor, title)
                    yield child
                    yield from nested(child)

        for s in sections:
            out.append(s)
            out.extend(nested(s))
        return out

    def render(self) -> str:
        plan = self.plan()
        root = self.schema
        required = root.get("required", [])
        lines = [
            "# Model file reference",
            "",
            f"<!-- Generated by {GENERATOR} from stepcontact.io.modelfile.schema(); "
            "do not edit. -->",
            "",
            "Every table and field of the TOML model file, generated from its JSON schema "
            "(`stepcontact schema` prints the schema itself; `stepcontact.io.modelfile.schema()` "
            "returns it).  [model-file.md](model-file.md) explains the format with examples, "
            "[user-guide.md](user-guide.md) the concepts.",
            "",
            "* Units are SI: m, N, Pa, kg/m³, m/s²; load factors λ are dimensionless.",
            "* Unknown keys are errors in every table, and so are NaN and inf.",
            "* *default* `—` means the field is not set (the description says what is used "
            "instead); **required** fields have no default.",
            "* `NAME` in a table header is a name you choose (`[materials.concrete]`).",
            "",
            "| section | form | required | constraint |",
            "|---|---|---|---|",
        ]
        props = root.get("properties", {})
        # {"anyOf": [{"required": [a]}, {"required": [b]}]}: one of the sections is required
        either = [k for alt in root.get("anyOf", []) for k in alt.get("required", [])]
        for s in plan:
            if s["level"] != 2:
                continue
            node = props[s["key"]]
            if s["key"] in either:
                need = "one of " + ", ".join(f"`{k}`" for k in either)
            else:
                need = "yes" if s["key"] in required else "no"
            form = ("table" if s["title"].startswith("[") and not s["title"].startswith("[[")
                    else "array of tables")
            if s["title"].endswith(".NAME]"):
                form = "named tables"
            lines.append("| " + " | ".join(_md_cell(c) for c in (
                f"[`{s['title']}`](#{s['anchor']})", form, need, self.constraints(node),
            )) + " |")
        for s in plan:
            d = self.defs[s["def"]]
            lines += ["", f'<a id="{s["anchor"]}"></a>', "",
                      f"{'#' * s['level']} `{s['title']}`", ""]
            if d.get("description"):
                lines += [_rst_to_md(d["description"]), ""]
            lines += self.fields_table(s["def"])
        return "\n".join(lines) + "\n"


def render_model_file_reference(schema: dict[str, Any] | None = None) -> str:
    """The markdown of docs/model-file-reference.md."""
    if schema is None:
        from stepcontact.io.modelfile import schema as file_schema

        schema = file_schema()
    return _Reference(schema).render()


# --------------------------------------------------------------------------------------------
# command-line reference
# --------------------------------------------------------------------------------------------
_ANSI = re.compile(r"\x1b\[[0-9;?]*[ -/]*[@-~]")


def _plain(text: str, markup_mode: str | None) -> str:
    """Help text without rich markup and ANSI escapes (what a terminal shows, unstyled)."""
    if markup_mode == "rich" and "\x1b" not in text:
        from rich.text import Text

        text = Text.from_markup(text).plain
    return _ANSI.sub("", text)


def _help_markdown(text: str | None, markup_mode: str | None) -> list[str]:
    """A command's help text as markdown: prose paragraphs, indented blocks as code."""
    if not text:
        return []
    text = inspect.cleandoc(text).partition("\f")[0]
    text = _plain(text, markup_mode)
    out: list[str] = []
    code: list[str] = []

    def flush() -> None:
        if code:
            lang = "bash" if all(c.split()[0] == "stepcontact" for c in code if c) else "text"
            out.extend([f"```{lang}", *code, "```", ""])
            code.clear()

    for para in re.split(r"\n\s*\n", text.strip()):
        lines = para.split("\n")
        if para.startswith("\b") or all(ln[:1].isspace() for ln in lines):
            block = inspect.cleandoc(para.lstrip("\b"))
            code.extend(ln.rstrip() for ln in block.split("\n"))
            continue
        flush()
        out += [" ".join(" ".join(lines).split()).replace("<", "&lt;"), ""]
    flush()
    return out


def _record(param: Any, ctx: Any) -> tuple[str, str]:
    rec = param.get_help_record(ctx)
    if rec is None:
        return param.human_readable_name, ""
    return rec


def _params_table(title: str, params: list[Any], ctx: Any) -> list[str]:
    if not params:
        return []
    rows = [f"| {title} | description |", "|---|---|"]
    for p in params:
        name, text = _record(p, ctx)
        rows.append(f"| `{_md_cell(_plain(name, None))}` | "
                    f"{_md_cell(_plain(text, None)).replace('<', '&lt;')} |")
    return rows + [""]


def _command_section(cmd: Any, ctx: Any, title: str, level: int) -> list[str]:
    markup = getattr(cmd, "rich_markup_mode", None)
    lines = [f"{'#' * level} `{title}`", ""]
    if getattr(cmd, "hidden", False):
        lines += ["*Hidden command (not listed by `--help`).*", ""]
    lines += _help_markdown(cmd.help, markup)
    lines += ["```text", _plain(cmd.get_usage(ctx), None).strip(), "```", ""]
    params = [p for p in cmd.get_params(ctx) if not getattr(p, "hidden", False)]
    lines += _params_table("argument", [p for p in params if p.param_type_name == "argument"],
                           ctx)
    lines += _params_table("option", [p for p in params if p.param_type_name != "argument"], ctx)
    return lines


def render_cli_reference(app: Any = None, prog: str = "stepcontact") -> str:
    """The markdown of docs/cli.md, from the typer app (default :data:`stepcontact.cli.app`)."""
    import typer

    if app is None:
        from stepcontact.cli import app
    group = typer.main.get_command(app)
    ctx = group.context_class(group, info_name=prog)
    lines = [
        "# Command-line reference",
        "",
        f"<!-- Generated by {GENERATOR} from the typer app stepcontact.cli:app; do not edit. -->",
        "",
        f"Every command of `{prog}`, with its help text, usage and options, as "
        f"`{prog} COMMAND --help` prints them.  Bad input (a missing file, a model error) "
        "prints one line `error: ...` on stderr and exits with code 2; a run that ends with lost "
        "equilibrium is a result, not an error (exit code 0), but a dynamic interval it "
        "could then not run is said (`dynamics not run: <reason>` on stderr) and exits with "
        "code 3.  Tables show names and messages as written (brackets such as `stages[1]` "
        "included) and never cut a number: in a narrow terminal their text columns wrap "
        "instead.  See "
        "[user-guide.md](user-guide.md#workflow) for a complete workflow.",
        "",
    ]
    lines += _help_markdown(group.help, getattr(group, "rich_markup_mode", None))
    lines += ["```text", _plain(group.get_usage(ctx), None).strip(), "```", ""]
    lines += _params_table("option", list(group.get_params(ctx)), ctx)
    names = list(group.list_commands(ctx)) if hasattr(group, "list_commands") else []
    commands = [(n, group.get_command(ctx, n)) for n in names]
    lines += ["| command | what it does |", "|---|---|"]
    for name, cmd in commands:
        short = cmd.get_short_help_str(limit=200)
        hidden = " (hidden)" if getattr(cmd, "hidden", False) else ""
        lines.append(f"| [`{name}`](#{prog}-{name}){hidden} | "
                     f"{_md_cell(_plain(short, getattr(cmd, 'rich_markup_mode', None)))} |")
    lines.append("")
    for name, cmd in commands:
        sub_ctx = cmd.context_class(cmd, info_name=name, parent=ctx)
        lines += [f'<a id="{prog}-{name}"></a>', ""]
        lines += _command_section(cmd, sub_ctx, f"{prog} {name}", 2)
    lines += ["", *FAULTS_SECTION]
    return "\n".join(lines).rstrip("\n") + "\n"


#: the hand-written end of docs/cli.md: what the commands do when things go wrong
FAULTS_SECTION = [
    "## Faults: interruptions, locks, a full disk",
    "",
    "- **Periodic writes.** `run` writes its result file as it goes (status `incomplete` "
    "until the run ends): at segment ends, and within a long segment after the event at which "
    "`--write-interval` seconds (default 15) have passed since the last write. The interval "
    "is a bound: while a write takes less than a fifth of it, at most a fifth of the run's "
    "time goes into writing; a run killed outright (`kill -9`, a crash, a power cut) loses at "
    "most about one interval of work (plus the step in progress).",
    "- **Signals.** On SIGTERM (`kill`, a batch system's time limit) or SIGINT (Ctrl-C), `run` "
    "writes every state finished (status `incomplete`, message `interrupted`), prints "
    "`error: interrupted by SIGTERM: 'RUN.nc' holds the N states finished …` and exits with "
    "128 + the signal's number (143, 130). A signal that arrives during a write waits until "
    "the file is whole. In the model's dynamic interval the signal ends the integration "
    "after its current step: `MODEL-dynamic.nc` gets the interval's states up to there "
    "(status `incomplete`; the static result is already written) and the message names "
    "both files and the time reached; `kill -9` during the interval keeps the static "
    "result only. `sweep` stops its workers at once, keeps every finished case "
    "(`STORE/cases/`) and exits the same way; run it again to resume. The workers of a "
    "local pool also die with their parent when it is killed outright (`kill -9`).",
    "- **One output, one run.** `run` holds an exclusive lock on its result file for the "
    "whole run (`flock` on `RUN.nc.lock` beside it, holding the run's process id; removed at "
    "the end, released by the kernel if the run is killed). A second `run` writing the same "
    "file stops at once with `error: the result file 'RUN.nc' is being written by another "
    "run (process PID …)`; `sweep` locks its store the same way.",
    "- **A full disk.** Every result, case and export file is written to a temporary file "
    "beside its target and then renamed into place, so a failed write never leaves a partial "
    "file and the previous file is intact. A netCDF file is made in memory and its size "
    "checked against the free space before anything is written (an export: after its first "
    "frame, that frame's size times the frames); a write that fails anyway is one line, "
    "e.g. `error: could not write the result file 'RUN.nc': the device is full (No space "
    "left on device); the previous file 'RUN.nc' is intact; free some space or write elsewhere` "
    "(exit code 2) — in `run`, `sweep` and `export` alike.",
    "- **The model of a result.** `run` records the model file's path and a SHA-256 hash of "
    "its content in the result files. `export` and `plot` of a dynamic result "
    "(`RUN-dynamic.nc`) use that file, or `RUN.toml` beside it, when its content still has "
    "that hash; a static result uses that file when its content still has that hash, else "
    "`RESULT.toml` beside the result file (either checked against the stored fields). "
    "`--model` names another.",
    "",
]


# --------------------------------------------------------------------------------------------
# main
# --------------------------------------------------------------------------------------------
def outputs() -> dict[Path, str]:
    """Every generated file and its content."""
    return {
        MODEL_FILE_REFERENCE: render_model_file_reference(),
        CLI_REFERENCE: render_cli_reference(),
    }


def stale(files: dict[Path, str] | None = None) -> list[Path]:
    """The generated files whose committed content differs from what would be generated."""
    files = outputs() if files is None else files
    return [p for p, text in files.items()
            if not p.is_file() or p.read_text(encoding="utf-8") != text]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--check", action="store_true",
                        help="write nothing; exit 1 if a generated file is out of date")
    args = parser.parse_args(argv)
    files = outputs()
    out_of_date = stale(files)
    rel = {p: p.relative_to(DOCS.parent).as_posix() for p in files}
    if args.check:
        for p in out_of_date:
            print(f"{rel[p]} is out of date: run  python {GENERATOR}", file=sys.stderr)
        if not out_of_date:
            print("generated references are up to date: " + ", ".join(rel.values()))
        return 1 if out_of_date else 0
    for p, text in files.items():
        if p in out_of_date:
            p.write_text(text, encoding="utf-8", newline="\n")
            print(f"wrote {rel[p]}")
        else:
            print(f"{rel[p]} is up to date")
    return 0


if __name__ == "__main__":
    sys.exit(main())
