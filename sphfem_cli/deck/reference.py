"""The deck reference (docs/deck-reference.md), generated from the pydantic schema.

Everything a deck writer needs to know about one key (its type, whether it is required, its
default, its meaning and units) already lives in the schema: ``Field(description=...)`` on every
field and a docstring on every model. :func:`render_reference` walks the models reachable from
:class:`~sphfem_cli.deck.schema.Deck` and turns them into Markdown, so the reference cannot say
something the schema does not::

    python -m sphfem_cli.deck.reference            # rewrite docs/deck-reference.md
    python -m sphfem_cli.deck.reference --check    # exit 1 if docs/deck-reference.md is stale

``tests/unit/test_deck_reference.py`` runs the check, requires a description on every field and
validates the example deck printed at the top of the reference.
"""
from __future__ import annotations

import argparse
import inspect
import json
import re
import sys
import types
import typing
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated, Any, Literal, Union

import annotated_types
from pydantic import BaseModel
from pydantic.fields import FieldInfo

from .loader import LIMITS
from .schema import RESERVED_HISTORIES, UNIT_SYSTEMS, Deck
from .schema.base import NAME_MAX_BYTES, NAME_MAX_CHARS, VECTOR

__all__ = ["EXAMPLE_DECK", "DEFAULT_OUTPUT", "render_reference", "iter_models", "main"]

DEFAULT_OUTPUT = Path(__file__).resolve().parents[2] / "docs" / "deck-reference.md"
"""Where the committed reference lives (repository root ``docs/``)."""

EXAMPLE_DECK = """\
# The smallest complete deck: a steel plate (plane strain) pushed at its left end.
title: Steel plate pushed at one end
units: {length: mm, mass: t, time: s}     # so force N, pressure MPa, density t/mm^3
dimension: 2                               # plane strain in the x-y plane

control:
  end_time: 1.0e-5                         # [time] = s

materials:
  steel: {type: elastic, density: 7.85e-9, youngs_modulus: 2.1e5, poisson_ratio: 0.3}

sections:
  solid: {type: solid}                     # default hourglass and bulk viscosity

parts:
  plate:
    material: steel                        # a name from materials
    section: solid                         # a name from sections
    geometry: {box: {min: [0.0, 0.0], max: [50.0, 10.0], element_size: 2.5}}

sets:
  left_end: {type: node, part: plate, side: left}

boundaries:
  - {type: prescribed_velocity, set: left_end, velocity: [1000.0, null]}   # 1 m/s, y left free

output:
  interval: 1.0e-6
  history_interval: 1.0e-7
  histories:
    - {name: tip, point: [50.0, 5.0], quantities: [displacement, velocity]}
"""
"""A complete, minimal deck; printed at the top of the reference and validated by the tests."""

_HEADER = """\
# Deck reference

<!-- Generated from sphfem_cli/deck/schema/ by `python -m sphfem_cli.deck.reference`.
     Do not edit by hand: change the schema's descriptions and docstrings, then regenerate.
     tests/unit/test_deck_reference.py fails when this file and the schema differ. -->

A deck is one YAML file. Its top-level keys are keyword families, in the manner of LS-DYNA's
keywords: `control` for the run, named `materials`, `equations_of_state`, `sections` and `parts`,
named node and segment `sets`, lists of `boundaries`, `initial` conditions and `loads`, and the
`output` requests. `sphfem check deck.yaml` validates a deck, builds the model and prints a
summary with the stable time step; `sphfem run deck.yaml` runs it.
"""

_CONVENTIONS = """\
## Reading a deck

### Units

The deck declares one consistent unit system in `units:` and every number in the deck is in that
system. Nothing is ever converted: the kernels compute with the numbers as written, so a deck in
mm-t-s gives stresses in MPa. Descriptions state the dimension of each quantity in brackets:
[length], [time], [mass/length^3], [pressure], [force], [length/time], [-] for dimensionless.
The accepted systems (as LS-DYNA lists them) and the units they imply:

{unit_table}

### Numbers and other scalars

Scalars follow the YAML 1.2 core schema, not YAML 1.1: `1e-3`, `.5`, `2.1E11` and `1.` are
numbers; `yes`, `no`, `on`, `off`, `1_000` and `0b101` are strings. `true`/`false` are booleans
and `null` (or `~`, or nothing) is null. Where a number is expected an integer is accepted
(`7850` as well as `7850.0`); where an integer is expected a float is refused (`2.0` is not an
integer). A quoted number (`"1.0"`) is a string and is refused where a number is expected;
`.inf` and `.nan` are refused everywhere. Anchors, aliases and merge keys (`<<: *base`) work;
duplicate keys are an error.

### Errors

A bad deck stops before anything runs, with one line on stderr and exit status 65:

```
deck.yaml:4:26: materials.steel.densty: unknown key 'densty' (did you mean 'density'?; allowed: density, youngs_modulus, poisson_ratio, type)
```

that is `file:line:col: path.in.deck: what is wrong (what was expected)`. Unknown keys, unknown
`type` values and unknown names are reported with the closest match and the allowed choices.
Paths are dotted, list items by index: `boundaries[0].set`.

### Names and cross-references

`curves`, `equations_of_state`, `materials`, `sections`, `parts` and `sets` are mappings from a
name you choose to a definition. Other entries refer to those by name, and every reference is
checked when the deck is read (an unknown name is an error that lists the known ones):

| key | refers to |
|---|---|
| `materials.<name>.eos` | `equations_of_state` |
| `parts.<name>.material`, `parts.<name>.section` | `materials`, `sections` |
| `sets.<name>.part` | `parts` |
| `part`, `set`, `curve` in `boundaries`, `initial`, `loads` items | `parts`, `sets`, `curves` |
| `loads[i].parts` (gravity) | `parts` |
| `part`, `set` in `output.histories` items | `parts`, `sets` |

A `pressure` load needs a segment set and a `nodal_force` load a node set. A name is any string
of Unicode (`steel`, `left_end`, `名前`, `🔥`; plain words need no quotes) that the output files
can carry, since names become CSV columns, file names (`histories/<name>.csv`) and HDF5/XDMF
names, all written as UTF-8. Refused: an empty or blank name, control characters and line or
paragraph separators, the characters `,` `"` `/` `\\`, the names `.` and `..`, and names over
{name_chars} characters or {name_bytes} bytes of UTF-8. Histories and probes cannot take the
names of the tables the solver writes itself ({reserved}).

### Limits on the file

A deck is a regular file (not a FIFO, a device or a directory), read with these bounds, each an
error naming the bound when crossed; an environment variable raises each one:

{limits}

Mesh files named by `geometry.file` must be regular files too; a file that meshio cannot read
(a corrupt `.vtu`, an unknown format) is an error at the deck's `file:` key.

### Vectors and `dimension`

`dimension: 2` is plane strain in the x-y plane (forces, masses and energies per unit thickness);
`dimension: 3` is full 3D. A *vector of `dimension` numbers* (a point, a velocity, an
acceleration) has 2 components in 2D and 3 in 3D; its length is checked against `dimension`
once the whole deck has been read. Directions are named `x`, `y`, `z`; `z` does not exist in 2D.

### How to read the tables

Each table lists the keys of one mapping: its **type** (number, integer, string, boolean, a list,
a vector, one of a fixed set of words, or a nested mapping with its own table), its **default**
(**required** if it has none; `null` means unset, and the description says what unset implies)
and its **description**. Keys not listed are refused. Entries of `equations_of_state`,
`materials`, `sections`, `sets`, `boundaries`, `initial` and `loads` are selected by their
`type` key; each `type` has its own table.
"""


# ------------------------------------------------------------------------------ schema introspection


def _is_model(obj: Any) -> bool:
    return isinstance(obj, type) and issubclass(obj, BaseModel)


def _strip(ann: Any) -> tuple[Any, list[Any], str | None]:
    """Unwrap ``Annotated``: the bare type, its metadata (constraints, markers) and a discriminator."""
    meta: list[Any] = []
    discriminator = None
    while typing.get_origin(ann) is Annotated:
        base, *extra = typing.get_args(ann)
        for item in extra:
            if isinstance(item, FieldInfo):
                meta.extend(item.metadata)
                if isinstance(item.discriminator, str):
                    discriminator = item.discriminator
            else:
                meta.append(item)
        ann = base
    return ann, meta, discriminator


def _is_union(ann: Any) -> bool:
    return typing.get_origin(ann) in (Union, types.UnionType)


def _non_null(ann: Any) -> list[Any]:
    return [a for a in typing.get_args(ann) if a is not type(None)]


def _variants(ann: Any) -> list[type[BaseModel]] | None:
    """The member models of a ``type``-discriminated union, or None if ``ann`` is not one."""
    base, _, discriminator = _strip(ann)
    if discriminator is None:
        return None
    if _is_model(base):
        return [base]
    return [_strip(a)[0] for a in _non_null(base)]


def _type_tag(model: type[BaseModel]) -> str:
    """The ``type:`` value that selects a member of a discriminated union."""
    return str(typing.get_args(model.model_fields["type"].annotation)[0])


def _ordered_fields(model: type[BaseModel]) -> list[tuple[str, FieldInfo]]:
    """Fields in declaration order, with a ``type`` selector first."""
    items = list(model.model_fields.items())
    return sorted(items, key=lambda kv: kv[0] != "type")


def _docstring(model: type[BaseModel]) -> str:
    doc = model.__dict__.get("__doc__")
    return inspect.cleandoc(doc) if doc else ""


def iter_models(root: type[BaseModel] = Deck) -> Iterator[type[BaseModel]]:
    """Every model reachable from `root` through its fields (root first, each model once)."""
    seen: list[type[BaseModel]] = []

    def visit(model: type[BaseModel]) -> None:
        if model in seen:
            return
        seen.append(model)
        for field in model.model_fields.values():
            for sub in _models_in(field.annotation):
                visit(sub)

    visit(root)
    yield from seen


def _models_in(ann: Any) -> list[type[BaseModel]]:
    base, _, _ = _strip(ann)
    if _is_model(base):
        return [base]
    out: list[type[BaseModel]] = []
    for arg in typing.get_args(base):
        if arg is not type(None) and not isinstance(arg, (str, int, float)):
            out.extend(_models_in(arg))
    return out


# --------------------------------------------------------------------------------- text helpers


def _num(value: Any) -> str:
    if isinstance(value, float) and value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return repr(value) if isinstance(value, float) else str(value)


_PLAIN_WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_.\-]*\Z")
_YAML_WORDS = {"null", "true", "false", "yes", "no", "on", "off", "~"}


def _yaml(value: Any) -> str:
    """A value as YAML flow text."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return _num(value) if isinstance(value, int) else repr(value)
    if isinstance(value, str):
        if _PLAIN_WORD.match(value) and value.lower() not in _YAML_WORDS:
            return value
        return json.dumps(value)
    if isinstance(value, BaseModel):
        value = value.model_dump()
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_yaml(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_yaml(v) for v in value) + "]"
    return str(value)


def _prose(text: str) -> str:
    """Schema text made safe for Markdown (no stray emphasis or HTML)."""
    text = " ".join(text.split())
    text = text.replace("\\", "\\\\").replace("*", "\\*")
    return re.sub(r"<(?=[A-Za-z/!?])", "&lt;", text)


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def _anchor(path: str) -> str:
    return re.sub(r"[^a-z0-9]+", "-", path.lower()).strip("-")


def _bounds(meta: list[Any]) -> str:
    lo = hi = None
    for m in meta:
        if isinstance(m, annotated_types.Gt):
            lo = (">", m.gt)
        elif isinstance(m, annotated_types.Ge):
            lo = ("≥", m.ge)
        elif isinstance(m, annotated_types.Lt):
            hi = ("<", m.lt)
        elif isinstance(m, annotated_types.Le):
            hi = ("≤", m.le)
    if lo and hi:
        left = "(" if lo[0] == ">" else "["
        right = ")" if hi[0] == "<" else "]"
        return f" in {left}{_num(lo[1])}, {_num(hi[1])}{right}"
    if lo:
        return f" {lo[0]} {_num(lo[1])}"
    if hi:
        return f" {hi[0]} {_num(hi[1])}"
    return ""


def _lengths(meta: list[Any]) -> tuple[int | None, int | None]:
    lo = hi = None
    for m in meta:
        if isinstance(m, annotated_types.MinLen):
            lo = m.min_length
        elif isinstance(m, annotated_types.MaxLen):
            hi = m.max_length
    return lo, hi


_PLURALS = {"number": "numbers", "integer": "integers", "string": "strings", "boolean": "booleans",
            "mapping": "mappings", "non-empty string": "non-empty strings"}


def _plural(text: str) -> str:
    for word, plural in _PLURALS.items():
        if text == word or text.startswith(word + " ") or text.startswith(word + ","):
            return plural + text[len(word):]
    return f"({text})"


def _words(values: tuple[Any, ...]) -> str:
    shown = [f"`{_yaml(v)}`" for v in values]
    return shown[0] if len(shown) == 1 else "one of " + " | ".join(shown)


def _type_text(ann: Any, meta: list[Any], child: str, links: bool = True) -> str:
    """Human-readable type of a field.

    `child` is the dotted path of the table of a nested model, linked to when `links` is true.
    """
    if _variants(ann) is not None:
        return "mapping, selected by `type`" + (" (types below)" if links else "")
    base, more, _ = _strip(ann)
    meta = list(meta) + more
    if any(m is VECTOR for m in meta):
        item = typing.get_args(base)[0]
        nulls = _is_union(item) and type(None) in typing.get_args(item)
        return "vector of `dimension` numbers" + (" or nulls" if nulls else "")
    if base is type(None):
        return "null"
    if _is_union(base):
        args = _non_null(base)
        return " or ".join(_type_text(a, meta if len(args) == 1 else [], child, links) for a in args)
    if typing.get_origin(base) is Literal:
        return _words(typing.get_args(base))
    if base is bool:
        return "boolean"
    if base is int:
        return "integer" + _bounds(meta)
    if base is float:
        return "number" + _bounds(meta)
    if base is str:
        lo, _ = _lengths(meta)
        return "non-empty string" if lo else "string"
    if _is_model(base):
        return f"mapping, see [`{child}`](#{_anchor(child)})" if links else "mapping"
    origin = typing.get_origin(base)
    if origin is list:
        item_text = _type_text(typing.get_args(base)[0], [], child + "[i]", links)
        lo, hi = _lengths(meta)
        if lo is not None and lo == hi:
            return f"list of {lo} {_plural(item_text)}"
        if typing.get_origin(_strip(typing.get_args(base)[0])[0]) is Literal:
            text = f"list, each {item_text}"
        else:
            text = f"list of {_plural(item_text)}"
        if lo:
            text += f", at least {lo}"
        if hi is not None:
            text += f", at most {hi}"
        return text
    if origin is dict:
        key, value = typing.get_args(base)
        key_base = _strip(key)[0]
        value_text = _type_text(value, [], child + ".<name>", links)
        if typing.get_origin(key_base) is Literal:
            keys = ", ".join(f"`{k}`" for k in typing.get_args(key_base))
            return f"mapping with keys {keys} → {value_text}"
        lo, _ = _lengths(meta)
        return f"mapping name → {value_text}" + (f", at least {lo} {'entry' if lo == 1 else 'entries'}" if lo else "")
    return getattr(base, "__name__", str(base))


def _default_text(field: FieldInfo) -> str:
    if field.is_required():
        return "**required**"
    value = field.default_factory() if field.default_factory is not None else field.default
    text = _yaml(value)
    if isinstance(value, BaseModel) and len(text) > 40:
        return "its keys' defaults"
    return f"`{text}`"


# ------------------------------------------------------------------------------------ rendering


class _Writer:
    def __init__(self) -> None:
        self.lines: list[str] = []
        self.anchors: set[str] = set()
        self.models: dict[str, type[BaseModel]] = {}

    def add(self, *lines: str) -> None:
        self.lines.extend(lines)

    def heading(self, level: int, text: str, anchor: str) -> None:
        if anchor in self.anchors:
            raise ValueError(f"duplicate anchor {anchor!r} in the deck reference")
        self.anchors.add(anchor)
        self.add(f'<a id="{anchor}"></a>', "", f"{'#' * min(level, 6)} {text}", "")

    def paragraph(self, text: str) -> None:
        if text:
            self.add(text, "")

    def text(self) -> str:
        while self.lines and not self.lines[-1]:
            self.lines.pop()
        return "\n".join(self.lines) + "\n"


def _table(w: _Writer, model: type[BaseModel], path: str) -> list[tuple[str, Any]]:
    """The field table of `model`; returns (child path, annotation) of nested models to render."""
    w.add("| key | type | default | description |", "|---|---|---|---|")
    nested: list[tuple[str, Any]] = []
    for name, field in _ordered_fields(model):
        child = f"{path}.{name}"
        type_text = _type_text(field.annotation, list(field.metadata), child)
        w.add(
            f"| `{name}` | {_cell(type_text)} | {_cell(_default_text(field))} "
            f"| {_cell(_prose(field.description or ''))} |"
        )
        if _models_in(field.annotation):
            nested.append((child, field.annotation))
    w.add("")
    return nested


def _nested_path(child: str, ann: Any) -> tuple[str, type[BaseModel] | None, list[type[BaseModel]] | None]:
    """Where a nested model's table goes: list items get ``[i]``, mapping values ``.<name>``."""
    base, _, _ = _strip(ann)
    if _is_union(base) and _variants(ann) is None:
        args = _non_null(base)
        if len(args) == 1:
            return _nested_path(child, args[0])
    variants = _variants(ann)
    if variants is not None:
        return child, None, variants
    if _is_model(base):
        return child, base, None
    origin = typing.get_origin(base)
    if origin is list:
        return _nested_path(child + "[i]", typing.get_args(base)[0])
    if origin is dict:
        return _nested_path(child + ".<name>", typing.get_args(base)[1])
    return child, None, None


def _render_model(w: _Writer, model: type[BaseModel], path: str, level: int, title: str | None = None,
                  anchor: str | None = None) -> None:
    anchor = anchor or _anchor(path)
    if anchor in w.anchors and w.models.get(anchor) is model:
        return  # the same model at the same path under another variant: documented once, linked from both
    w.models[anchor] = model
    w.heading(level, title or f"`{path}`", anchor)
    w.paragraph(_prose(_docstring(model)))
    for child, ann in _table(w, model, path):
        _render_nested(w, child, ann, level + 1)


def _render_nested(w: _Writer, child: str, ann: Any, level: int) -> None:
    where, model, variants = _nested_path(child, ann)
    if model is not None:
        _render_model(w, model, where, level)
    elif variants is not None:
        for v in variants:
            _render_variant(w, v, where, level)


def _render_variant(w: _Writer, model: type[BaseModel], path: str, level: int) -> None:
    tag = _type_tag(model)
    _render_model(w, model, path, level, title=f"`{path}` with `type: {tag}`",
                  anchor=_anchor(f"{path}-{tag}"))


def _family(w: _Writer, name: str, field: FieldInfo) -> None:
    ann = field.annotation
    w.heading(2, f"`{name}`", _anchor(name))
    w.paragraph(_prose(field.description or ""))
    type_text = _type_text(ann, list(field.metadata), name)
    where, model, variants = _nested_path(name, ann)
    default = "**Required.**" if field.is_required() else f"**Default:** {_default_text(field)}."
    w.paragraph(f"**Type:** {type_text}. {default}")
    if variants is not None:
        shape = (f"`{name}: {{<name>: {{type: <type>, ...}}, ...}}`" if typing.get_origin(_strip(ann)[0]) is dict
                 else f"`{name}: [{{type: <type>, ...}}, ...]`")
        links = ", ".join(f"[`{_type_tag(v)}`](#{_anchor(f'{where}-{_type_tag(v)}')})" for v in variants)
        w.paragraph(f"Written as {shape}. Types: {links}.")
        for v in variants:
            _render_variant(w, v, where, 3)
    elif model is not None and where == name:
        w.paragraph(_prose(_docstring(model)))
        for child, child_ann in _table(w, model, name):
            _render_nested(w, child, child_ann, 3)
    elif model is not None:
        _render_model(w, model, where, 3)


def _unit_table() -> str:
    rows = ["| length | mass | time | force | pressure | density |", "|---|---|---|---|---|---|"]
    for (length, mass, time), (force, pressure, density) in UNIT_SYSTEMS.items():
        rows.append(f"| {length} | {mass} | {time} | {force} | {pressure} | {density} |")
    return "\n".join(rows)


_LIMIT_TEXT = {
    "SPHFEM_MAX_DECK_BYTES": "bytes in the deck file",
    "SPHFEM_MAX_DECK_NODES": "values (scalars, lists and mappings) with every alias and merge key expanded: "
                             "an alias bomb stops here",
    "SPHFEM_MAX_DECK_DEPTH": "nesting depth of lists and mappings",
}


def _limit_table() -> str:
    rows = ["| environment variable | default | bounds |", "|---|---|---|"]
    rows += [f"| `{name}` | {value} | {_LIMIT_TEXT[name]} |" for name, value in LIMITS.items()]
    return "\n".join(rows)


def render_reference() -> str:
    """The whole deck reference as Markdown, built from the schema."""
    w = _Writer()
    w.add(_HEADER)
    w.heading(2, "A minimal deck", "a-minimal-deck")
    w.add("```yaml", EXAMPLE_DECK.rstrip("\n"), "```", "")
    w.add(_CONVENTIONS.format(unit_table=_unit_table(), name_chars=NAME_MAX_CHARS, name_bytes=NAME_MAX_BYTES,
                              reserved=", ".join(f"`{n}`" for n in RESERVED_HISTORIES), limits=_limit_table()))
    w.heading(2, "Top-level keys", "top-level-keys")
    w.paragraph(_prose(_docstring(Deck)) + " Its keys, in the order of this reference:")
    w.add("| key | type | default | description |", "|---|---|---|---|")
    for name, field in Deck.model_fields.items():
        type_text = _type_text(field.annotation, list(field.metadata), name, links=False)
        w.add(f"| [`{name}`](#{_anchor(name)}) | {_cell(type_text)} | {_cell(_default_text(field))} "
              f"| {_cell(_prose(field.description or ''))} |")
    w.add("")
    for name, field in Deck.model_fields.items():
        _family(w, name, field)
    return w.text()


# ------------------------------------------------------------------------------------------ CLI


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m sphfem_cli.deck.reference",
        description="Write the deck reference generated from the schema (docs/deck-reference.md).",
    )
    parser.add_argument("--check", action="store_true",
                        help="do not write; exit 1 if the file differs from what the schema gives")
    parser.add_argument("-o", "--output", type=Path, default=DEFAULT_OUTPUT,
                        help=f"file to write or check (default: {DEFAULT_OUTPUT})")
    args = parser.parse_args(argv)
    text = render_reference()
    if args.check:
        current = args.output.read_text(encoding="utf-8") if args.output.exists() else None
        if current != text:
            print(f"{args.output} is out of date; run `python -m sphfem_cli.deck.reference`", file=sys.stderr)
            return 1
        print(f"{args.output} is up to date")
        return 0
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(text, encoding="utf-8")
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
