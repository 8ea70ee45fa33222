"""How the deck schema reads as text: the models reachable from the deck, and each field's type,
default and description as the deck reference (docs/deck-reference.md) prints them.

Works on the pydantic annotations themselves (``Annotated`` constraints, ``Literal`` words,
``type``-discriminated unions, lists and mappings), so the reference cannot say something the schema
does not.
"""
from __future__ import annotations

import inspect
import json
import re
import types
import typing
from collections.abc import Iterator
from typing import Annotated, Any, Literal, Union

import annotated_types
from pydantic import BaseModel
from pydantic.fields import FieldInfo

from .schema import Deck
from .schema.base import VECTOR

__all__ = ["iter_models", "models_in", "strip_annotated", "type_variants", "type_tag", "ordered_fields", "docstring",
           "field_type_text", "default_text", "nested_path", "prose", "cell", "anchor_of"]


def _is_model(obj: Any) -> bool:
    return isinstance(obj, type) and issubclass(obj, BaseModel)


def strip_annotated(ann: Any) -> tuple[Any, list[Any], str | None]:
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


def type_variants(ann: Any) -> list[type[BaseModel]] | None:
    """The member models of a ``type``-discriminated union, or None if ``ann`` is not one."""
    base, _, discriminator = strip_annotated(ann)
    if discriminator is None:
        return None
    if _is_model(base):
        return [base]
    return [strip_annotated(a)[0] for a in _non_null(base)]


def type_tag(model: type[BaseModel]) -> str:
    """The ``type:`` value that selects a member of a discriminated union."""
    return str(typing.get_args(model.model_fields["type"].annotation)[0])


def ordered_fields(model: type[BaseModel]) -> list[tuple[str, FieldInfo]]:
    """Fields in declaration order, with a ``type`` selector first."""
    items = list(model.model_fields.items())
    return sorted(items, key=lambda kv: kv[0] != "type")


def docstring(model: type[BaseModel]) -> str:
    """The model's own docstring (not an inherited one), dedented; empty if none."""
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
            for sub in models_in(field.annotation):
                visit(sub)

    visit(root)
    yield from seen


def models_in(ann: Any) -> list[type[BaseModel]]:
    """The models an annotation holds, through unions, lists and mappings."""
    base, _, _ = strip_annotated(ann)
    if _is_model(base):
        return [base]
    out: list[type[BaseModel]] = []
    for arg in typing.get_args(base):
        if arg is not type(None) and not isinstance(arg, (str, int, float)):
            out.extend(models_in(arg))
    return out


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


def prose(text: str) -> str:
    """Schema text made safe for Markdown (no stray emphasis or HTML)."""
    text = " ".join(text.split())
    text = text.replace("\\", "\\\\").replace("*", "\\*")
    return re.sub(r"<(?=[A-Za-z/!?])", "&lt;", text)


def cell(text: str) -> str:
    """Text made safe inside a Markdown table cell."""
    return text.replace("|", "\\|")


def anchor_of(path: str) -> str:
    """The HTML anchor of a dotted deck path."""
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


def field_type_text(ann: Any, meta: list[Any], child: str, links: bool = True) -> str:
    """Human-readable type of a field.

    `child` is the dotted path of the table of a nested model, linked to when `links` is true.
    """
    if type_variants(ann) is not None:
        return "mapping, selected by `type`" + (" (types below)" if links else "")
    base, more, _ = strip_annotated(ann)
    meta = list(meta) + more
    if any(m is VECTOR for m in meta):
        item = typing.get_args(base)[0]
        nulls = _is_union(item) and type(None) in typing.get_args(item)
        return "vector of `dimension` numbers" + (" or nulls" if nulls else "")
    if base is type(None):
        return "null"
    if _is_union(base):
        args = _non_null(base)
        return " or ".join(field_type_text(a, meta if len(args) == 1 else [], child, links) for a in args)
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
        return f"mapping, see [`{child}`](#{anchor_of(child)})" if links else "mapping"
    origin = typing.get_origin(base)
    if origin is list:
        item_text = field_type_text(typing.get_args(base)[0], [], child + "[i]", links)
        lo, hi = _lengths(meta)
        if lo is not None and lo == hi:
            return f"list of {lo} {_plural(item_text)}"
        if typing.get_origin(strip_annotated(typing.get_args(base)[0])[0]) is Literal:
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
        key_base = strip_annotated(key)[0]
        value_text = field_type_text(value, [], child + ".<name>", links)
        if typing.get_origin(key_base) is Literal:
            keys = ", ".join(f"`{k}`" for k in typing.get_args(key_base))
            return f"mapping with keys {keys} → {value_text}"
        lo, _ = _lengths(meta)
        return f"mapping name → {value_text}" + (f", at least {lo} {'entry' if lo == 1 else 'entries'}" if lo else "")
    return getattr(base, "__name__", str(base))


def default_text(field: FieldInfo) -> str:
    """The default column: **required**, the default as YAML, or "its keys' defaults" for a long mapping."""
    if field.is_required():
        return "**required**"
    value = field.default_factory() if field.default_factory is not None else field.default
    text = _yaml(value)
    if isinstance(value, BaseModel) and len(text) > 40:
        return "its keys' defaults"
    return f"`{text}`"


def nested_path(child: str, ann: Any) -> tuple[str, type[BaseModel] | None, list[type[BaseModel]] | None]:
    """Where a nested model's table goes: list items get ``[i]``, mapping values ``.<name>``."""
    base, _, _ = strip_annotated(ann)
    if _is_union(base) and type_variants(ann) is None:
        args = _non_null(base)
        if len(args) == 1:
            return nested_path(child, args[0])
    variants = type_variants(ann)
    if variants is not None:
        return child, None, variants
    if _is_model(base):
        return child, base, None
    origin = typing.get_origin(base)
    if origin is list:
        return nested_path(child + "[i]", typing.get_args(base)[0])
    if origin is dict:
        return nested_path(child + ".<name>", typing.get_args(base)[1])
    return child, None, None
