#!/usr/bin/env python3
"""Generates two reference pages of the book from the code, so that they cannot drift from it.

- docs/src/reference/scenario-fields.md, from the scenario format's JSON Schema
  (scenarios/carfollow-scenario.schema.json, itself generated from the Rust types): every
  table and field of a scenario file with its TOML path, type, range, default, whether it is
  required, and its doc comment.
- docs/src/reference/python-api.md, from the Python package's sources and type stubs
  (sim/python/python/carfollow/__init__.py, env.py, vector.py and _carfollow.pyi), read
  with `ast` (the package is never imported: it is a compiled extension that may not be built): every
  public module-level constant, function and class, and every public method, property and
  attribute, with its signature as written and its docstring.

Usage (from anywhere; paths are relative to the repository):

    python3 docs/gen_reference.py          # writes both pages
    python3 docs/gen_reference.py --check  # exit 1, one line per stale page, if a committed
                                           # page differs from what would be generated

Standard library only, Python 3.9 or later. The output is deterministic: fields in the
schema's order (the top level in the file's order of sections), Python names in source
order. A schema construct the script does not understand stops it (exit 2, one line naming
the construct's place in the schema) rather than being left out.
"""

from __future__ import annotations

import argparse
import ast
import inspect
import json
import re
import struct
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCHEMA = ROOT / "scenarios" / "carfollow-scenario.schema.json"
PACKAGE = ROOT / "sim" / "python" / "python" / "carfollow"
FIELDS_PAGE = ROOT / "docs" / "src" / "reference" / "scenario-fields.md"
PYTHON_PAGE = ROOT / "docs" / "src" / "reference" / "python-api.md"
COMMAND = "python3 docs/gen_reference.py"

# The top level's fields in the order of `ScenarioFile` (sim/core/src/scenario/file.rs), which
# the schema, sorting them by name, does not keep. Fields missing here follow, in schema order.
TOP_LEVEL_ORDER = [
    "name", "description", "duration_s", "seed", "route", "lead", "chase", "camera",
    "tracker", "loop", "environment", "expect",
]

# ---------------------------------------------------------------------------------------
# Markdown helpers

CODE_SPAN = re.compile(r"(`+)(.+?)\1", re.S)


def slug(heading: str) -> str:
    """The id mdBook (and a forge) gives a heading: code spans' text kept, lower case,
    letters, digits, `-` and `_` kept, whitespace to `-`, everything else dropped."""
    text = CODE_SPAN.sub(lambda m: m.group(2), heading)
    out = []
    for ch in text.strip().lower():
        if ch.isspace():
            out.append("-")
        elif ch in "-_" or ch.isalnum():
            out.append(ch)
    return "".join(out)


FENCE = re.compile(r"^```[^\n]*\n.*?^```[ \t]*$", re.S | re.M)


def md_text(text: str, in_table: bool) -> str:
    """Doc-comment prose as Markdown: rustdoc's intra-doc links ([`X`]) as code, `*` and `<`
    escaped outside code, paragraphs kept (as <br><br> inside a table cell) and `|` escaped
    inside one. A fenced example is kept as it is written, but left out of a table cell."""
    blocks, last = [], 0
    for m in FENCE.finditer(text):
        blocks += [md_prose(text[last:m.start()], in_table), "" if in_table else m.group(0)]
        last = m.end()
    blocks.append(md_prose(text[last:], in_table))
    return ("<br><br>" if in_table else "\n\n").join(b for b in blocks if b)


def md_prose(text: str, in_table: bool) -> str:
    """[`md_text`] of prose without fenced blocks."""
    text = re.sub(r"\[(`[^`\n]+`)\](?![(\[])", r"\1", text.strip())
    paragraphs = []
    for para in re.split(r"\n\s*\n", text):
        para = " ".join(para.split())
        pieces, last = [], 0
        for m in CODE_SPAN.finditer(para):
            pieces += [escape_prose(para[last:m.start()]), m.group(0)]  # code kept as is
            last = m.end()
        para = "".join(pieces) + escape_prose(para[last:])
        paragraphs.append(para.replace("|", r"\|") if in_table else para)
    return ("<br><br>" if in_table else "\n\n").join(p for p in paragraphs if p)


def escape_prose(text: str) -> str:
    """Text outside code with no emphasis or HTML tags made of its `*` and `<`."""
    return re.sub(r"<(?=[A-Za-z/!?])", "&lt;", text.replace("*", r"\*"))


def code(text: str) -> str:
    """`text` as a code span."""
    fence = "``" if "`" in text else "`"
    pad = " " if fence == "``" else ""
    return f"{fence}{pad}{text}{pad}{fence}"


# ---------------------------------------------------------------------------------------
# The scenario schema

ANNOTATIONS = {"description", "title", "default"}
KEYWORDS = ANNOTATIONS | {
    "$schema", "$defs", "$ref", "type", "properties", "additionalProperties", "required",
    "format", "minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum", "items",
    "minItems", "maxItems", "anyOf", "oneOf", "allOf", "const", "enum",
}
TYPES = {"object", "array", "string", "number", "integer", "boolean", "null"}
NUMBER_FORMATS = {"double", "float"}
INTEGER_FORMATS = {
    f"{sign}{bits}" for sign in ("int", "uint") for bits in ("", "8", "16", "32", "64", "128")
}
RANGE_KEYWORDS = ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum")
# Keywords a node of each kind may carry besides the annotations.
ALLOWED = {
    "object": {"type", "properties", "additionalProperties", "required", "$defs", "$schema"},
    "array": {"type", "items", "minItems", "maxItems"},
    "number": {"type", "format", *RANGE_KEYWORDS},
    "integer": {"type", "format", *RANGE_KEYWORDS},
    "string": {"type", "format"},
    "boolean": {"type"},
}


class SchemaError(Exception):
    """A construct the generator does not understand, at a JSON pointer into the schema."""

    def __init__(self, pointer: str, what: str) -> None:
        super().__init__(f"{SCHEMA.relative_to(ROOT)}: {pointer}: {what}")


class Node:
    """A schema with its `$ref`s followed and its `allOf` merged."""

    def __init__(self, ptr: str, s: dict, desc: str | None, def_desc: str | None) -> None:
        self.ptr, self.s, self.desc, self.def_desc = ptr, s, desc, def_desc
        self.has_default = "default" in s
        self.default = s.get("default")


class TypeInfo:
    """What a field holds: kind is scalar, enum, const, table, tagged (an internally tagged
    enum of tables) or array."""

    def __init__(self, kind: str, node: Node, **extra) -> None:
        self.kind, self.node = kind, node
        self.name = extra.get("name", "")
        self.values = extra.get("values", [])  # enum: [(value, description)]
        self.tag = extra.get("tag", "")  # tagged: the tag's key
        self.variants = extra.get("variants", [])  # tagged: [(tag value, Node)]
        self.items = extra.get("items")  # array: TypeInfo of its items
        self.nullable = extra.get("nullable", False)


class Schema:
    def __init__(self, root: dict) -> None:
        self.root = root
        self.defs = root.get("$defs", {})
        self.reached: set[str] = set()

    def resolve(self, s: object, ptr: str, stack: tuple = ()) -> Node:
        if not isinstance(s, dict):
            raise SchemaError(ptr, f"a boolean or non-object schema ({json.dumps(s)})")
        for key in s:
            if key not in KEYWORDS:
                raise SchemaError(f"{ptr}/{key}", f"unsupported keyword {key!r}")
        if "$ref" in s:
            return self._follow_ref(s, ptr, stack)
        if "allOf" in s:
            return self._merge_all_of(s, ptr, stack)
        return Node(ptr, s, s.get("description"), None)

    def _follow_ref(self, s: dict, ptr: str, stack: tuple) -> Node:
        ref = s["$ref"]
        m = re.fullmatch(r"#/\$defs/([^/]+)", ref) if isinstance(ref, str) else None
        if not m or m.group(1) not in self.defs:
            raise SchemaError(f"{ptr}/$ref", f"unresolvable $ref {ref!r}")
        if ref in stack:
            raise SchemaError(f"{ptr}/$ref", f"recursive $ref {ref!r}")
        for key in s:
            if key not in ANNOTATIONS and key != "$ref":
                raise SchemaError(f"{ptr}/{key}", f"keyword {key!r} beside $ref")
        self.reached.add(m.group(1))
        target = self.resolve(self.defs[m.group(1)], ref, stack + (ref,))
        merged = dict(target.s)
        merged.update({k: v for k, v in s.items() if k != "$ref"})
        return Node(target.ptr, merged, s.get("description", target.desc), target.desc)

    def _merge_all_of(self, s: dict, ptr: str, stack: tuple) -> Node:
        parts = s["allOf"]
        if not isinstance(parts, list) or not parts:
            raise SchemaError(f"{ptr}/allOf", "allOf must be a non-empty list")
        merged = {k: v for k, v in s.items() if k != "allOf" and k not in ANNOTATIONS}
        props: dict = {}
        required: list = []
        def_desc = None
        for i, part in enumerate(parts):
            node = self.resolve(part, f"{ptr}/allOf/{i}", stack)
            def_desc = def_desc or node.def_desc or node.desc
            for key, value in node.s.items():
                if key == "properties":
                    for name, prop in value.items():
                        if name in props and props[name] != prop:
                            raise SchemaError(f"{ptr}/allOf/{i}/properties/{name}",
                                              "conflicting definitions in allOf")
                        props[name] = prop
                elif key == "required":
                    required += [r for r in value if r not in required]
                elif key in ANNOTATIONS:
                    continue
                elif key in merged and merged[key] != value:
                    raise SchemaError(f"{ptr}/allOf/{i}/{key}", f"conflicting {key!r} in allOf")
                else:
                    merged[key] = value
        if props:
            merged["properties"] = props
        if required:
            merged["required"] = required
        merged.update({k: v for k, v in s.items() if k in ANNOTATIONS})
        return Node(ptr, merged, s.get("description", def_desc), def_desc)

    def type_info(self, node: Node) -> TypeInfo:
        s = node.s
        if "anyOf" in s and "oneOf" in s:
            raise SchemaError(node.ptr, "both anyOf and oneOf")
        for keyword in ("anyOf", "oneOf"):
            if keyword in s:
                return self._alternatives(node, keyword)
        if "enum" in s:
            # A null among the values is an optional field's "not set": not a value to write.
            values = [v for v in s["enum"] if v is not None]
            scalar = (str, int, float)
            if not values or not all(isinstance(v, scalar) and not isinstance(v, bool)
                                     for v in values):
                raise SchemaError(f"{node.ptr}/enum",
                                  "an enum of anything but strings and numbers")
            return TypeInfo("enum", node, values=[(v, None) for v in values])
        if "const" in s:
            if not isinstance(s["const"], str) or s.get("type", "string") != "string":
                raise SchemaError(f"{node.ptr}/const", "a const that is not a string")
            return TypeInfo("const", node, name=s["const"])
        types = s.get("type")
        if types is None:
            raise SchemaError(node.ptr, "a schema without a type")
        types = types if isinstance(types, list) else [types]
        for t in types:
            if t not in TYPES:
                raise SchemaError(f"{node.ptr}/type", f"unknown type {t!r}")
        kinds = [t for t in types if t != "null"]
        if len(kinds) != 1:
            raise SchemaError(f"{node.ptr}/type", f"type {types!r}: not one type (or null)")
        info = self._typed(node, kinds[0])
        info.nullable = "null" in types
        return info

    def _typed(self, node: Node, kind: str) -> TypeInfo:
        s = node.s
        for key in s:
            if key not in ALLOWED[kind] and key not in ANNOTATIONS:
                raise SchemaError(f"{node.ptr}/{key}", f"keyword {key!r} on a {kind}")
        fmt = s.get("format")
        if fmt is not None:
            known = {"number": NUMBER_FORMATS, "integer": INTEGER_FORMATS}.get(kind, set())
            if fmt not in known:
                raise SchemaError(f"{node.ptr}/format", f"unknown format {fmt!r} of a {kind}")
        if kind == "object":
            if not isinstance(s.get("properties"), dict):
                raise SchemaError(node.ptr, "an object without properties (a map)")
            if s.get("additionalProperties", False) is not False:
                raise SchemaError(f"{node.ptr}/additionalProperties",
                                  "additionalProperties other than false (a map)")
            for name in s.get("required", []):
                if name not in s["properties"]:
                    raise SchemaError(f"{node.ptr}/required", f"required {name!r} undefined")
            return TypeInfo("table", node)
        if kind == "array":
            if not isinstance(s.get("items"), dict):
                raise SchemaError(f"{node.ptr}/items", "an array without one items schema")
            items = self.type_info(self.resolve(s["items"], f"{node.ptr}/items"))
            return TypeInfo("array", node, items=items)
        return TypeInfo("scalar", node, name=kind)

    def _alternatives(self, node: Node, keyword: str) -> TypeInfo:
        ptr = f"{node.ptr}/{keyword}"
        branches = [self.resolve(b, f"{ptr}/{i}") for i, b in enumerate(node.s[keyword])]
        rest = {k for k in node.s if k != keyword and k not in ANNOTATIONS}
        if rest:
            raise SchemaError(f"{node.ptr}/{sorted(rest)[0]}", f"keyword beside {keyword}")
        nulls = [b for b in branches if b.s.get("type") == "null"]
        others = [b for b in branches if b.s.get("type") != "null"]
        if len(others) == 1 and nulls:
            inner = others[0]
            merged = dict(inner.s)
            merged.update({k: v for k, v in node.s.items() if k in ANNOTATIONS})
            desc = node.s.get("description", inner.desc)
            info = self.type_info(Node(inner.ptr, merged, desc, inner.def_desc or inner.desc))
            info.nullable = True
            return info
        if nulls:
            raise SchemaError(ptr, "null beside several alternatives")
        infos = [self.type_info(b) for b in others]
        if all(i.kind == "const" for i in infos):
            return TypeInfo("enum", node, values=[(i.name, i.node.desc) for i in infos])
        if all(i.kind == "table" for i in infos):
            return TypeInfo("tagged", node, **self._tag(ptr, others))
        raise SchemaError(ptr, "alternatives neither nullable, string constants nor tagged tables")

    def _tag(self, ptr: str, variants: list) -> dict:
        """The tag key of an internally tagged enum: a property that is a string constant in
        every variant."""
        def consts(v: Node) -> dict:
            out = {}
            for name, prop in v.s["properties"].items():
                if isinstance(prop, dict) and "const" in prop:
                    out[name] = prop["const"]
            return out

        tags = set.intersection(*(set(consts(v)) for v in variants))
        if len(tags) != 1:
            raise SchemaError(ptr, f"tables without exactly one common tag (found {sorted(tags)})")
        tag = tags.pop()
        values = [consts(v)[tag] for v in variants]
        if len(set(values)) != len(values):
            raise SchemaError(ptr, f"tag {tag!r} repeats a value")
        return {"tag": tag, "variants": list(zip(values, variants))}


# -- rendering of values and types


def fmt_float(x: float, f32: bool) -> str:
    """The shortest text that reads back as the same f64 (or, for an f32, the same f32)."""
    if f32:
        for digits in range(1, 18):
            text = f"{x:.{digits}g}"
            if struct.unpack("<f", struct.pack("<f", float(text)))[0] == x:
                return repr(float(text))
    return repr(x)


def toml_value(value: object, info: TypeInfo | None, schema: Schema) -> str:
    """A default as a TOML user writes it."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        f32 = info is not None and info.node.s.get("format") == "float"
        return fmt_float(value, f32)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        items = info.items if info is not None and info.kind == "array" else None
        return "[" + ", ".join(toml_value(v, items, schema) for v in value) + "]"
    if isinstance(value, dict):
        node = info.node if info is not None else None
        keys = list(value)
        if info is not None and info.kind == "tagged":
            tag_value = value.get(info.tag)
            node = next((n for v, n in info.variants if v == tag_value), None)
            keys.sort(key=lambda k: k != info.tag)
        props = node.s.get("properties", {}) if node is not None else {}
        parts = []
        for key in keys:
            sub = None
            if key in props:
                sub = schema.type_info(schema.resolve(props[key], f"{node.ptr}/properties/{key}"))
            name = key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else json.dumps(key)
            parts.append(f"{name} = {toml_value(value[key], sub, schema)}")
        return "{ " + ", ".join(parts) + " }" if parts else "{}"
    raise SchemaError("default", f"a default that is not TOML: {json.dumps(value)}")


def range_text(info: TypeInfo) -> str:
    s = info.node.s
    f32 = s.get("format") == "float"

    def num(x: object) -> str:
        text = fmt_float(x, f32) if isinstance(x, float) else str(x)
        return text[:-2] if text.endswith(".0") else text

    low = ("[", s["minimum"]) if "minimum" in s else None
    low = ("(", s["exclusiveMinimum"]) if "exclusiveMinimum" in s else low
    high = ("]", s["maximum"]) if "maximum" in s else None
    high = (")", s["exclusiveMaximum"]) if "exclusiveMaximum" in s else high
    if low and high:
        return f"in {low[0]}{num(low[1])}, {num(high[1])}{high[0]}"
    if low:
        return ("≥ " if low[0] == "[" else "> ") + num(low[1])
    if high:
        return ("≤ " if high[0] == "]" else "< ") + num(high[1])
    return ""


def type_text(info: TypeInfo, plural: bool = False) -> str:
    """The type as a TOML user would say it."""
    if info.kind == "scalar":
        word = info.name + ("s" if plural else "")
        rng = range_text(info)
        return f"{word} {rng}" if rng else word
    if info.kind == "enum":
        values = " | ".join(code(json.dumps(v, ensure_ascii=False)) for v, _ in info.values)
        if plural:
            words = "strings" if all(isinstance(v, str) for v, _ in info.values) else "values"
            return f"{words}, each one of {values}"
        return f"one of {values}"
    if info.kind == "const":
        value = code(json.dumps(info.name, ensure_ascii=False))
        return f"strings, each {value}" if plural else value
    if info.kind in ("table", "tagged"):
        return "tables" if plural else "table"
    s = info.node.s
    lo, hi = s.get("minItems"), s.get("maxItems")
    inner = type_text(info.items, plural=True)
    if lo is not None and lo == hi:
        count = f"{lo} " if lo != 1 else "1 "
        inner = inner if lo != 1 else type_text(info.items)
    elif lo is not None and hi is not None:
        count = f"{lo}–{hi} "
    elif lo is not None:
        count = f"at least {lo} "
    elif hi is not None:
        count = f"at most {hi} "
    else:
        count = ""
    return ("arrays" if plural else "array") + f" of {count}{inner}"


# -- the page's sections


class Section:
    def __init__(self, heading: str, level: int) -> None:
        self.heading, self.level = heading, level
        self.intro: list[str] = []
        self.rows: list[tuple[str, str, str, str]] = []
        self.variants: list[tuple[str, str, list]] = []  # (heading, description, rows)
        self.children: list[Section] = []


class FieldsPage:
    def __init__(self, schema: Schema) -> None:
        self.schema = schema
        self.anchors: dict[str, str] = {}
        self.missing: list[str] = []  # schema pointers of fields without a description
        self.fields = 0
        self.active: list[str] = []  # the tables being filled, outermost first
        self.active_headings: dict[str, str] = {}  # their sections' headings

    def anchor(self, heading: str) -> str:
        anchor = slug(heading)
        if anchor in self.anchors:
            raise SchemaError(heading, f"two headings with the anchor #{anchor}")
        self.anchors[anchor] = heading
        return anchor

    def section(self, heading: str, level: int, node: Node, lead: str = "") -> Section:
        sec = Section(heading, level)
        intro = [lead] if lead else []
        if node.desc:
            intro.append(md_text(node.desc, False))
        if node.def_desc and node.def_desc != node.desc:
            own = re.sub(r"^`\[\[?[^`\]]+\]\]?`\s*[:.]?\s*", "", node.def_desc.strip())
            if own:
                intro.append(md_text(own[0].upper() + own[1:], False))
        sec.intro = intro
        self.anchor(heading)
        return sec

    def fill_table(self, sec: Section, node: Node, prefix: str, ctx: tuple | None,
                   order: list | None = None, rows: list | None = None) -> None:
        """Adds a row per field of the table `node` to `rows` (the section's by default), and
        a child section per sub-table. `ctx` is (default object, its table's path) when an
        enclosing table's default supplies this table's values."""
        rows = sec.rows if rows is None else rows
        if node.ptr in self.active:
            raise SchemaError(node.ptr, "a table that holds itself (a recursive $ref)")
        self.active.append(node.ptr)
        self.active_headings[node.ptr] = sec.heading
        props = node.s["properties"]
        names = list(props)
        if order:
            names = [n for n in order if n in props] + [n for n in names if n not in order]
        required = node.s.get("required", [])
        for name in names:
            ptr = f"{node.ptr}/properties/{name}"
            field = self.schema.resolve(props[name], ptr)
            info = self.schema.type_info(field)
            path = prefix + name
            child_ctx = None
            if isinstance(field.default, dict):
                child_ctx = (field.default, path)
            elif ctx and isinstance(ctx[0].get(name), dict):
                child_ctx = (ctx[0][name], ctx[1])
            # A field holding the table it is in (a trigger's members): a link back to the
            # table's section, not a section of its own.
            target = info.items if info.kind == "array" else info
            back = self.active_headings.get(target.node.ptr) if target.node.ptr in self.active else None
            kind = (f"{type_text(info)}, each as [{back}](#{slug(back)})" if back
                    else self.type_cell(info, path))
            default = self.default_cell(name, field, info, name in required, ctx)
            desc = field.desc or info.node.desc or ""
            if not desc and info.kind != "const":
                self.missing.append(ptr)
            desc = md_text(desc, True)
            if info.kind == "const":
                desc = desc or "Chooses this kind."
            enum = info.items if info.kind == "array" and info.items.kind == "enum" else info
            if enum.kind == "enum" and any(d for _, d in enum.values):
                notes = "<br>".join(f"{code(json.dumps(v))}: {md_text(d or '', True)}"
                                    for v, d in enum.values)
                desc = f"{desc}<br><br>{notes}" if desc else notes
            rows.append((code(path), kind, default, desc or "—"))
            self.fields += 1
            if not back:
                self.sub_sections(sec, field, info, path, child_ctx)
        self.active.pop()

    def type_cell(self, info: TypeInfo, path: str) -> str:
        text = type_text(info)
        target = info.items if info.kind == "array" else info
        if target.kind not in ("table", "tagged"):
            return md_text(text, True)
        if info.kind == "array" and info.items.kind != target.kind:
            raise SchemaError(info.node.ptr, "an array of arrays of tables")
        heading = code(f"[[{path}]]" if info.kind == "array" else f"[{path}]")
        link = f"[{text}](#{slug(heading)})"
        if target.kind == "tagged":
            values = " \\| ".join(code(json.dumps(v)) for v, _ in target.variants)
            link += f" by {code(target.tag)}: {values}"
        return link

    def default_cell(self, name: str, field: Node, info: TypeInfo, required: bool,
                     ctx: tuple | None) -> str:
        inherited = None
        if ctx and ctx[0].get(name) is not None and info.kind != "table":
            inherited = (toml_value(ctx[0][name], info, self.schema), ctx[1])
        own = None
        if field.has_default and field.default is not None and info.kind != "table":
            own = toml_value(field.default, info, self.schema)
        if required:
            text = "**required**"
        elif own is not None:
            text = code(own)
        elif inherited is not None:
            return f"{code(inherited[0])} without {code(f'[{inherited[1]}]')}"
        else:
            return "optional"
        if inherited is not None and inherited[0] != own:
            text += f" ({code(inherited[0])} without {code(f'[{inherited[1]}]')})"
        return text.replace("|", r"\|")

    def sub_sections(self, parent: Section, field: Node, info: TypeInfo, path: str,
                     ctx: tuple | None) -> None:
        """The section of a field that is a table or an array of tables."""
        if info.kind == "array" and info.items.kind in ("table", "tagged"):
            items = info.items
            heading = code(f"[[{path}]]")
            lead = f"Each item of {code(path)}, an array of tables."
            level = 2 if "." not in path else 3
            sec = self.section(heading, level, self.merge_desc(field, items.node), lead)
            parent.children.append(sec)
            self.fill_kind(sec, items, path + "[].", None)
        elif info.kind in ("table", "tagged"):
            level = 2 if "." not in path else 3
            sec = self.section(code(f"[{path}]"), level, info.node)
            parent.children.append(sec)
            self.fill_kind(sec, info, path + ".", ctx)

    def merge_desc(self, field: Node, item: Node) -> Node:
        return Node(item.ptr, item.s, field.desc, item.def_desc or item.desc)

    def fill_kind(self, sec: Section, info: TypeInfo, prefix: str, ctx: tuple | None) -> None:
        if info.kind == "table":
            self.fill_table(sec, info.node, prefix, ctx)
            return
        default = ctx[0] if ctx else None
        if default is not None:
            sec.intro.append(f"Default: {code(toml_value(default, info, self.schema))}.")
        table = prefix.rstrip(".")
        links = []
        for value, variant in info.variants:
            heading = code(f"{prefix}{info.tag} = {json.dumps(value)}")
            links.append(f"[{code(json.dumps(value))}](#{self.anchor(heading)})")
            rows: list = []
            holder = Section(heading, 4)
            own_ctx = ctx if ctx and ctx[0].get(info.tag) == value else None
            self.fill_table(holder, variant, prefix, own_ctx, order=[info.tag], rows=rows)
            sec.variants.append((heading, md_text(variant.desc or "", False), rows))
            lead = f"With {code(f'{info.tag} = {json.dumps(value)}')} in {code(f'[{table}]')}."
            for child in holder.children:
                child.intro.insert(0, lead)
                sec.children.append(child)
        sec.intro.append(f"One of {len(links)} kinds, chosen by {code(info.tag)}: "
                         + ", ".join(links) + ".")

    def build(self) -> list[Section]:
        root = self.schema.resolve(self.schema.root, "#")
        info = self.schema.type_info(root)
        if info.kind != "table":
            raise SchemaError("#", "the root is not a table")
        top = Section("Top level", 2)
        self.anchor("Top level")
        top.intro = ["The fields outside any table, at the start of the file."]
        self.fill_table(top, root, "", None, order=TOP_LEVEL_ORDER)
        unused = sorted(set(self.schema.defs) - self.schema.reached)
        if unused:
            raise SchemaError(f"#/$defs/{unused[0]}", "a definition no field reaches")
        return [top]


def render_rows(rows: list) -> list[str]:
    out = ["| Field | Type | Default | Description |", "|---|---|---|---|"]
    out += [f"| {f} | {t} | {d} | {desc} |" for f, t, d, desc in rows]
    return out


def render_section(sec: Section, out: list[str]) -> int:
    """Appends the section and its children; returns how many sections it wrote."""
    out += ["", f"{'#' * sec.level} {sec.heading}", ""]
    for para in sec.intro:
        out += [para, ""]
    if sec.rows:
        out += render_rows(sec.rows)
    for heading, desc, rows in sec.variants:
        out += ([] if out[-1] == "" else [""]) + [f"#### {heading}", ""]
        if desc:
            out += [desc, ""]
        out += render_rows(rows)
    count = 1 + len(sec.variants)
    for child in sec.children:
        count += render_section(child, out)
    return count


def fields_page() -> tuple[str, dict]:
    schema = Schema(json.loads(SCHEMA.read_text(encoding="utf-8")))
    page = FieldsPage(schema)
    page.anchor("Scenario fields (generated)")
    sections = page.build()
    out = [
        f"*Generated by `{COMMAND}` from `scenarios/carfollow-scenario.schema.json`: "
        "do not edit by hand.*",
        "",
        "# Scenario fields (generated)",
        "",
        "Every table and field of a scenario file, from the format's JSON Schema, which is "
        "derived from the Rust types and their doc comments (a test keeps it equal to them). "
        "[Scenario files](scenario.md) describes the format; this page lists it whole.",
        "",
        "Fields are named by their TOML path; `[]` stands for an item of an array of tables "
        "(`--set` names it by its index, `environment.distractors.0.offset_px`). The type "
        "says what to write and, where the schema states one, the range. The default column "
        "holds the value used when the field is left out, **required** for a field that must "
        "be given, or \"optional\" where the description says what leaving it out means. Top-"
        "level tables come in the file's order, the fields of each table in the schema's.",
    ]
    count = sum(render_section(sec, out) for sec in sections)
    stats = {"sections": count, "fields": page.fields, "missing": page.missing}
    return "\n".join(out) + "\n", stats


# ---------------------------------------------------------------------------------------
# The Python API

MAX_LINE = 88


class Entry:
    """One documented name: kind is constant, alias, function, class, method, property or
    attribute; code holds its signature lines as written."""

    def __init__(self, kind: str, name: str, code_lines: list, doc: str | None) -> None:
        self.kind, self.name, self.code, self.doc = kind, name, code_lines, doc
        self.members: list[Entry] = []
        self.read_write = False


def segment(src: str, node: ast.AST) -> str:
    """The source text of a node, on one line."""
    text = ast.get_source_segment(src, node)
    if text is None:
        text = ast.unparse(node)
    return " ".join(text.split())


def params(src: str, args: ast.arguments) -> list[str]:
    out = []
    positional = args.posonlyargs + args.args
    defaults = [None] * (len(positional) - len(args.defaults)) + list(args.defaults)

    def one(arg: ast.arg, default: ast.AST | None, star: str = "") -> str:
        text = star + arg.arg
        if arg.annotation is not None:
            text += f": {segment(src, arg.annotation)}"
        if default is not None:
            sep = " = " if arg.annotation is not None else "="
            text += sep + segment(src, default)
        return text

    for i, (arg, default) in enumerate(zip(positional, defaults)):
        out.append(one(arg, default))
        if args.posonlyargs and i == len(args.posonlyargs) - 1:
            out.append("/")
    if args.vararg is not None:
        out.append(one(args.vararg, None, "*"))
    elif args.kwonlyargs:
        out.append("*")
    for arg, default in zip(args.kwonlyargs, args.kw_defaults):
        out.append(one(arg, default))
    if args.kwarg is not None:
        out.append(one(args.kwarg, None, "**"))
    return out


def def_lines(src: str, fn: ast.FunctionDef | ast.AsyncFunctionDef) -> list[str]:
    """The decorators and the `def` line, wrapped as black would past MAX_LINE."""
    lines = [f"@{segment(src, d)}" for d in fn.decorator_list]
    head = ("async def " if isinstance(fn, ast.AsyncFunctionDef) else "def ") + fn.name
    tail = f" -> {segment(src, fn.returns)}" if fn.returns is not None else ""
    ps = params(src, fn.args)
    one = f"{head}({', '.join(ps)}){tail}"
    if len(one) <= MAX_LINE:
        return lines + [one]
    return lines + [f"{head}("] + [f"    {p}," for p in ps] + [f"){tail}"]


def is_public(name: str, doc: str | None, in_class: bool) -> bool:
    if name == "__init__":
        return in_class
    if name.startswith("__") and name.endswith("__"):
        return doc is not None
    return not name.startswith("_")


def assigned_names(stmt: ast.stmt) -> list[str]:
    targets = stmt.targets if isinstance(stmt, ast.Assign) else [stmt.target]
    names = []
    for target in targets:
        elts = target.elts if isinstance(target, (ast.Tuple, ast.List)) else [target]
        names += [e.id for e in elts if isinstance(e, ast.Name)]
    return names


def collect(src: str, body: list, in_class: bool, public=None, stub: bool = False
            ) -> list[Entry]:
    """The documented names of a module's or a class's body, in source order. `public`, when
    given, says which module-level names are public: public(name, docstring)."""
    entries: list[Entry] = []
    by_name: dict[str, Entry] = {}
    for i, stmt in enumerate(body):
        following = body[i + 1] if i + 1 < len(body) else None
        if isinstance(stmt, (ast.FunctionDef, ast.AsyncFunctionDef)):
            decorators = [segment(src, d) for d in stmt.decorator_list]
            if any(d.endswith((".setter", ".deleter")) for d in decorators):
                owner = by_name.get(stmt.name)
                if owner is not None:
                    owner.read_write = True
                continue
            doc = ast.get_docstring(stmt)
            if not (public(stmt.name, doc) if public else is_public(stmt.name, doc, in_class)):
                continue
            if stmt.name in by_name and "overload" in " ".join(decorators):
                by_name[stmt.name].code += def_lines(src, stmt)
                by_name[stmt.name].doc = by_name[stmt.name].doc or doc
                continue
            is_property = any(d.split(".")[-1] in ("property", "cached_property")
                              for d in decorators)
            kind = "property" if is_property else ("method" if in_class else "function")
            entry = Entry(kind, stmt.name, def_lines(src, stmt), doc)
        elif isinstance(stmt, ast.ClassDef):
            doc = ast.get_docstring(stmt)
            if not (public(stmt.name, doc) if public else is_public(stmt.name, doc, in_class)):
                continue
            bases = [segment(src, b) for b in stmt.bases + stmt.keywords]
            line = f"class {stmt.name}" + (f"({', '.join(bases)})" if bases else "")
            decorators = [f"@{segment(src, d)}" for d in stmt.decorator_list]
            entry = Entry("class", stmt.name, decorators + [line], doc)
            entry.members = collect(src, stmt.body, True, stub=stub)
        elif isinstance(stmt, (ast.Assign, ast.AnnAssign)):
            doc = None
            if (isinstance(following, ast.Expr) and isinstance(following.value, ast.Constant)
                    and isinstance(following.value.value, str)):
                doc = inspect.cleandoc(following.value.value)  # an attribute docstring
            names = [n for n in assigned_names(stmt)
                     if (public(n, doc) if public else is_public(n, doc, in_class))]
            if not names:
                continue
            alias = stub and isinstance(stmt, ast.Assign)  # `X = ...` in a stub: a type alias
            kind = "attribute" if in_class else ("alias" if alias else "constant")
            entry = Entry(kind, ", ".join(names), [segment(src, stmt)], doc)
        else:
            continue
        entries.append(entry)
        by_name[entry.name] = entry
    return entries


def doc_markdown(doc: str) -> str:
    """A reST-flavoured docstring as Markdown: ``x`` to `x`, section titles (a line
    underlined with =, -, ~ ...) to bold, simple tables (==== borders) kept as text."""
    lines = doc.splitlines()
    out: list[str] = []
    prose: list[str] = []
    border = re.compile(r"^\s*=+(\s+=+)+\s*$")
    underline = re.compile(r"^([=\-~^\"'`#*+])\1{2,}$")

    def flush() -> None:
        text = "\n".join(prose)
        text = re.sub(r"``(.+?)``", lambda m: code(" ".join(m.group(1).split())), text,
                      flags=re.S)
        out.extend(text.split("\n") if prose else [])
        prose.clear()

    i = 0
    while i < len(lines):
        line = lines[i]
        nxt = lines[i + 1] if i + 1 < len(lines) else ""
        if border.match(line):
            flush()
            j = i + 1
            while j < len(lines) and not (border.match(lines[j]) and
                                          (j + 1 == len(lines) or not lines[j + 1].strip())):
                j += 1
            out += ["```text"] + lines[i:j + 1] + ["```"]
            i = j + 1
        elif line.strip() and underline.match(nxt.strip()) and len(nxt.strip()) >= len(
                line.strip()) and not prose_open(prose):
            flush()
            out += [f"**{line.strip()}**", ""]
            i += 2
        else:
            prose.append(line)
            i += 1
    flush()
    return "\n".join(out).strip()


def prose_open(prose: list) -> bool:
    """Whether a paragraph is open (a section title must follow a blank line)."""
    return bool(prose) and bool(prose[-1].strip())


def parse(path: Path) -> tuple[str, ast.Module]:
    src = path.read_text(encoding="utf-8")
    return src, ast.parse(src, filename=str(path))


def module_all(tree: ast.Module) -> list[str] | None:
    for stmt in tree.body:
        if isinstance(stmt, ast.Assign) and "__all__" in assigned_names(stmt):
            return [ast.literal_eval(e) for e in stmt.value.elts]
    return None


def render_entry(entry: Entry, level: int, owner: str, out: list[str]) -> int:
    """Appends an entry and its members; returns how many entries it wrote."""
    name = f"{owner}.{entry.name}" if owner else entry.name
    label = {"class": "class ", "property": "property "}.get(entry.kind, "")
    call = "()" if entry.kind in ("function", "method") else ""
    note = " (read-write)" if entry.read_write else ""
    out += ["", f"{'#' * level} {label}{code(name + call)}{note}", "", "```python"]
    out += entry.code + ["```"]
    if entry.doc:
        out += ["", doc_markdown(entry.doc)]
    count = 1
    for member in entry.members:
        count += render_entry(member, min(level + 1, 6), name, out)
    return count


def ordered(entries: list[Entry]) -> list[Entry]:
    rank = {"constant": 0, "alias": 1, "function": 2, "class": 3}
    return sorted(entries, key=lambda e: rank[e.kind])  # stable: source order within a kind


def python_page() -> tuple[str, dict]:
    init_src, init_tree = parse(PACKAGE / "__init__.py")
    stub_src, stub_tree = parse(PACKAGE / "_carfollow.pyi")
    env_src, env_tree = parse(PACKAGE / "env.py")
    vec_src, vec_tree = parse(PACKAGE / "vector.py")
    exported = module_all(init_tree) or []
    stub = collect(stub_src, stub_tree.body, False,
                   public=lambda n, d: n in exported or is_public(n, d, False), stub=True)
    own = collect(init_src, init_tree.body, False, public=lambda n, d: n in exported)
    top = own + [e for e in stub if e.name in exported and e.name not in {o.name for o in own}]
    unknown = sorted(set(exported) - {e.name for e in top})
    if unknown:
        raise SystemExit(f"gen_reference.py: carfollow.__all__ names {unknown[0]!r}, which "
                         "neither __init__.py nor _carfollow.pyi defines")
    native_only = [e for e in stub if e.name not in exported]
    modules = [
        ("carfollow", ast.get_docstring(init_tree), ordered(top),
         "The names of its `__all__`; those of the native module are documented by its type "
         "stubs."),
        ("carfollow._carfollow", ast.get_docstring(stub_tree), ordered(native_only),
         "Names the type stubs declare that `carfollow` does not re-export: type aliases "
         "and protocols of the signatures above, and the native core of `carfollow.env`."),
        ("carfollow.env", ast.get_docstring(env_tree), ordered(collect(env_src, env_tree.body,
                                                                       False)), ""),
        ("carfollow.vector", ast.get_docstring(vec_tree), ordered(collect(vec_src, vec_tree.body,
                                                                          False)), ""),
    ]
    out = [
        f"*Generated by `{COMMAND}` from `sim/python/python/carfollow/` (`__init__.py`, "
        "`env.py`, `vector.py` and the type stubs `_carfollow.pyi`): do not edit by hand.*",
        "",
        "# Python API (generated)",
        "",
        "Every public module-level constant, function and class of the `carfollow` package, "
        "and every public method, property and attribute of its classes, with its signature "
        "as written in the sources and the type stubs and its docstring. "
        "[The Python API](python.md) is the guided description.",
    ]
    count = 0
    for name, doc, entries, note in modules:
        out += ["", f"## {code(name)}", ""]
        for para in (doc_markdown(doc) if doc else "", note):
            out += [para, ""] if para else []
        out.pop()
        for entry in entries:
            count += render_entry(entry, 3, "", out)
    missing = []
    for module, _, entries, _ in modules:
        stack = [(module, e) for e in entries]
        while stack:
            owner, entry = stack.pop(0)
            if not entry.doc:
                missing.append(f"{owner}.{entry.name}")
            stack += [(f"{owner}.{entry.name}", m) for m in entry.members]
    return "\n".join(out) + "\n", {"entries": count, "missing": missing}


# ---------------------------------------------------------------------------------------


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true",
                        help="exit 1 if a committed page differs from what would be generated")
    parser.add_argument("--stats", action="store_true",
                        help="print counts and undocumented fields and names to stderr")
    args = parser.parse_args()
    try:
        fields, fields_stats = fields_page()
    except SchemaError as err:
        print(f"gen_reference.py: unsupported schema construct: {err}", file=sys.stderr)
        return 2
    python, python_stats = python_page()
    stale = 0
    for path, text in ((FIELDS_PAGE, fields), (PYTHON_PAGE, python)):
        current = path.read_text(encoding="utf-8") if path.exists() else None
        if current == text:
            continue
        rel = path.relative_to(ROOT)
        if args.check:
            print(f"{rel} is stale: run {COMMAND}")
            stale += 1
        else:
            path.write_text(text, encoding="utf-8", newline="\n")
            print(f"wrote {rel}", file=sys.stderr)
    if args.stats:
        print(f"scenario fields: {fields_stats['fields']} fields in "
              f"{fields_stats['sections']} sections", file=sys.stderr)
        for ptr in fields_stats["missing"]:
            print(f"  no description: {ptr}", file=sys.stderr)
        print(f"python API: {python_stats['entries']} entries", file=sys.stderr)
        for name in python_stats["missing"]:
            print(f"  no docstring: {name}", file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
