"""Validate loaded YAML against the pydantic schema; turn every failure into a one-line DeckError.

The ``@path:`` convention for schema validators
-----------------------------------------------
A validator (``model_validator`` or ``field_validator``) that wants its error to point at a key
other than the one pydantic reports raises ``ValueError`` (or ``PydanticCustomError``) with a
message that starts with a path marker::

    raise ValueError(f"@parts.{name}.material: unknown material '{m}' (known: steel, water)")

The converter strips ``@path:``, reports ``path`` as the error's path and points at that key's
line and column. The path is dotted; list indices may be written ``boundaries.0.part`` or
``boundaries[0].part``. It is read *relative to the location pydantic gives the error* (the
model whose validator raised it; for validators on ``Deck`` that is the deck root), and, if no
such key exists there, as an absolute path from the deck root. ``@:`` means the model itself.
The path ends at the first colon followed by white space, so names may hold spaces and colons
(not ``": "``); a key holding ``.`` or ``[`` is written as :func:`errors.format_path` does,
``parts["a.b"]``.
If the key is absent from the deck, the error points at its nearest existing ancestor.
A message without the marker is reported at pydantic's location.

Messages are rewritten for people: ``missing required key 'density'``, ``unknown key 'densty'
(did you mean 'density'?; allowed: ...)``, ``unknown type 'elastik' (did you mean 'elastic'?;
expected one of: ...)``, ``expected a number, got 'abc' (str)``, ``must be > 0, got -1.0``.
Discriminator tags and union member labels that pydantic inserts into ``loc`` are dropped from
paths: ``('materials', 'steel', 'elastic', 'density')`` becomes ``materials.steel.density``.
"""
from __future__ import annotations

import json
import math
import re
import types
import typing
from collections.abc import Hashable, Mapping, Sequence
from os import PathLike
from typing import Any, TypeVar

from pydantic import BaseModel, ValidationError

from . import loader
from .errors import DeckError, DeckErrors, did_you_mean, format_path, parse_path

__all__ = ["load_deck", "validate_model", "convert_validation_error"]

M = TypeVar("M", bound=BaseModel)
Path_ = tuple[Hashable, ...]

_MARKER = re.compile(r"@(.*?):(?:\s+|\Z)(.*)\Z", re.DOTALL)  # the path ends at the first ': ' (names hold spaces)
_MISSING = object()

_EXPECTED = {
    "float_type": "a number", "float_parsing": "a number",
    "int_type": "an integer", "int_parsing": "an integer", "int_from_float": "an integer",
    "bool_type": "true or false", "bool_parsing": "true or false",
    "string_type": "a string", "string_sub_type": "a string",
    "list_type": "a list", "tuple_type": "a list", "set_type": "a list", "iterable_type": "a list",
    "dict_type": "a mapping", "model_type": "a mapping", "model_attributes_type": "a mapping",
    "dataclass_type": "a mapping", "none_required": "null", "finite_number": "a finite number",
}
_BOUNDS = {"greater_than": ("gt", ">"), "greater_than_equal": ("ge", ">="),
           "less_than": ("lt", "<"), "less_than_equal": ("le", "<=")}


def _yaml_repr(value: Any) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isnan(value):
            return ".nan"
        if math.isinf(value):
            return ".inf" if value > 0 else "-.inf"
        return repr(value)
    if isinstance(value, str):
        text = value if len(value) <= 40 else value[:37] + "..."
        return "'" + text.replace("\n", " ") + "'"
    return str(value)


def _got(value: Any) -> str:
    if isinstance(value, Mapping):
        return "a mapping"
    if isinstance(value, (list, tuple)):
        return "a list"
    if value is None:
        return "null"
    return f"{_yaml_repr(value)} ({type(value).__name__})"


def _count(n: Any, noun: str) -> str:
    plural = noun[:-1] + "ies" if noun.endswith("y") else noun + "s"
    return f"{n} {noun if n == 1 else plural}"


def _number(value: Any) -> str:
    if isinstance(value, float) and value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return _yaml_repr(value)


def _unwrap(ann: Any) -> Any:
    """Strip ``Annotated`` and ``None`` from unions: what pydantic validates without a loc label."""
    while True:
        if typing.get_origin(ann) is typing.Annotated:
            ann = typing.get_args(ann)[0]
            continue
        if typing.get_origin(ann) in (typing.Union, types.UnionType):
            members = [a for a in typing.get_args(ann) if a is not type(None)]
            if len(members) == 1:
                ann = members[0]
                continue
        return ann


def _is_union(ann: Any) -> bool:
    return typing.get_origin(ann) in (typing.Union, types.UnionType)


def _is_model(ann: Any) -> bool:
    return isinstance(ann, type) and issubclass(ann, BaseModel)


def _literals(ann: Any) -> list[Any]:
    ann = _unwrap(ann)
    if typing.get_origin(ann) is typing.Literal:
        return list(typing.get_args(ann))
    if _is_union(ann):
        return [v for member in typing.get_args(ann) for v in _literals(member)]
    return []


def _tags(union: Any, discriminator: str) -> list[Any]:
    """Values of the discriminator field over the members of a tagged union."""
    tags = []
    for member in typing.get_args(_unwrap(union)):
        info = _field(member, discriminator) if _is_model(_unwrap(member)) else None
        tags += _literals(info.annotation) if info is not None else []
    return tags


def _field(model: type[BaseModel], key: Any) -> Any:
    for name, info in model.model_fields.items():
        if key in (name, info.alias):
            return info
    return None


def _member(union: Any, label: Any) -> Any:
    """The union member that pydantic's ``loc`` label (a tag or a type name) selects, or None."""
    for member in typing.get_args(union):
        plain = _unwrap(member)
        if label in (getattr(plain, "__name__", None), str(plain)):
            return plain
        if _is_model(plain) and any(label in _literals(f.annotation)
                                    for f in plain.model_fields.values()):
            return plain
    return None


def _child(ann: Any, key: Any) -> Any:
    ann = _unwrap(ann)
    if _is_model(ann):
        info = _field(ann, key)
        return info.annotation if info is not None else None
    origin, args = typing.get_origin(ann), typing.get_args(ann)
    if origin in (dict, Mapping, typing.Mapping) and len(args) == 2:
        return args[1]
    if origin is tuple and args:
        if len(args) == 2 and args[1] is Ellipsis:
            return args[0]
        return args[key] if isinstance(key, int) and 0 <= key < len(args) else None
    if origin in (list, set, frozenset, Sequence, typing.Sequence) and args:
        return args[0]
    return None


class _Where:
    """Where a pydantic ``loc`` lands in the data: path, value and schema annotations."""

    def __init__(self, model_cls: type[BaseModel], data: Any, loc: Sequence[Any],
                 keep_last: bool) -> None:
        self.path: Path_ = ()
        self.value: Any = data
        self.ann: Any = model_cls
        self.parent_ann: Any = None
        self.is_key = False
        for i, label in enumerate(loc):
            last = i == len(loc) - 1
            plain = _unwrap(self.ann)
            if _is_union(plain) and (member := _member(plain, label)) is not None:
                self.ann = member
            elif label == "[key]":
                mapping = _unwrap(self.parent_ann)
                if typing.get_origin(mapping) in (dict, Mapping, typing.Mapping):
                    self.ann = typing.get_args(mapping)[0]
                self.is_key = True
            elif (isinstance(self.value, Mapping) and label in self.value
                  or isinstance(self.value, list) and isinstance(label, int)
                  and 0 <= label < len(self.value)):
                self._descend(label, self.value[label])
            elif last and keep_last:
                self._descend(label, _MISSING)

    def _descend(self, key: Any, value: Any) -> None:
        self.parent_ann, self.ann = self.ann, _child(self.ann, key)
        self.path += (key,)
        self.value = value


def _value_at(data: Any, path: Path_) -> Any:
    for key in path:
        data = data[key]
    return data


def _normalise(path: Sequence[Any], data: Any) -> Path_ | None:
    """``path`` with list indices as ints, or None if it does not exist in ``data``."""
    out: list[Hashable] = []
    value = data
    for key in path:
        if isinstance(value, list) and isinstance(key, (str, int)) and str(key).isdigit():
            key = int(key)
            if key >= len(value):
                return None
        elif not (isinstance(value, Mapping) and key in value):
            return None
        out.append(key)
        value = value[key]
    return tuple(out)


def _resolve_marked(base: Path_, rel: str, data: Any) -> Path_:
    parts = parse_path(rel)
    for candidate in (base + parts, parts):
        found = _normalise(candidate, data)
        if found is not None:
            return found
    longest: Path_ = ()
    for candidate in (base + parts, parts):
        for n in range(len(candidate), 0, -1):
            found = _normalise(candidate[:n], data)
            if found is not None and len(found) > len(longest):
                longest = found + tuple(candidate[n:])
                break
    return longest or base + parts


class _Report:
    """One converted error before it is located: path, message, and which position to use."""

    def __init__(self, path: Path_, message: str, *, at_key: bool = False,
                 expected: str | None = None, got: str | None = None) -> None:
        self.path, self.message, self.at_key, self.kind = path, message, at_key, ""
        self.expected, self.got = expected, got


def _allowed(model_ann: Any) -> list[str]:
    model = _unwrap(model_ann)
    if not _is_model(model):
        return []
    return [info.alias or name for name, info in model.model_fields.items()]


def _choices(word: Any, options: Sequence[Any], label: str) -> str:
    listed = ", ".join(str(o) for o in options)
    hint = did_you_mean(word, [str(o) for o in options])
    inside = "; ".join(p for p in (f"did you mean '{hint}'?" if hint else "",
                                   f"{label}: {listed}" if listed else "") if p)
    return f" ({inside})" if inside else ""


def _quoted_list(text: str) -> list[str]:
    quoted = re.findall(r"'([^']*)'", text)
    return quoted or [t for t in re.split(r",\s*|\s+or\s+", text) if t]


def _report(err: Mapping[str, Any], model_cls: type[BaseModel], data: Any) -> _Report:
    kind, loc, ctx = err["type"], tuple(err["loc"]), err.get("ctx") or {}
    value = err.get("input")
    where = _Where(model_cls, data, loc, keep_last=kind in ("missing", "extra_forbidden"))
    path = where.path

    if kind == "missing":
        key = path[-1] if path else loc[-1]
        fixed = typing.get_args(_unwrap(where.parent_ann))
        if isinstance(key, int) and fixed and Ellipsis not in fixed:
            got = len(_value_at(data, path[:-1]))
            return _Report(path[:-1], f"expected {len(fixed)} values, got {got}")
        return _Report(path[:-1], f"missing required key '{key}'", at_key=True)
    if kind == "extra_forbidden":
        key = path[-1] if path else loc[-1]
        return _Report(path, f"unknown key '{key}'" + _choices(key, _allowed(where.parent_ann),
                                                                  "allowed"), at_key=True)
    if kind in ("union_tag_invalid", "union_tag_not_found"):
        disc = ctx.get("discriminator", "'type'").strip("'\"")
        tags = _tags(where.ann, disc) or _quoted_list(str(ctx.get("expected_tags", "")))
        if kind == "union_tag_not_found" or not isinstance(where.value, Mapping):
            return _Report(path, f"missing required key '{disc}'" + _choices(None, tags, "one of"),
                           at_key=True)
        tag = ctx.get("tag", where.value.get(disc))
        return _Report(path + (disc,), f"unknown {disc} {_yaml_repr(tag)}"
                       + _choices(tag, tags, "expected one of"))
    if kind in ("literal_error", "enum"):
        options = _literals(where.ann) or _quoted_list(str(ctx.get("expected", "")))
        what = "key" if where.is_key else "value"
        return _Report(path, f"unknown {what} {_yaml_repr(value)}"
                       + _choices(value, options, "expected one of"), at_key=where.is_key)
    if kind in _EXPECTED:
        if where.is_key:
            return _Report(path, f"mapping key {_got(value)} must be {_EXPECTED[kind]}",
                           at_key=True)
        return _Report(path, "", expected=_EXPECTED[kind], got=_got(value))
    if kind in _BOUNDS:
        name, op = _BOUNDS[kind]
        return _Report(path, f"must be {op} {_number(ctx.get(name))}, got {_yaml_repr(value)}")
    if kind in ("too_short", "too_long", "string_too_short", "string_too_long"):
        shape = _unwrap(where.ann)
        fixed = typing.get_args(shape)
        if typing.get_origin(shape) is tuple and fixed and Ellipsis not in fixed:
            return _Report(path, f"expected {len(fixed)} values, got {ctx.get('actual_length')}")
        word, bound = (("at least", ctx.get("min_length")) if kind.endswith("short")
                       else ("at most", ctx.get("max_length")))
        if kind.startswith("string"):
            return _Report(path, f"must have {word} {_count(bound, 'character')}, "
                                 f"got {_yaml_repr(value)}")
        noun = "entry" if ctx.get("field_type") == "Dictionary" else "value"
        return _Report(path, f"expected {word} {_count(bound, noun)}, "
                             f"got {ctx.get('actual_length')}")
    if kind == "string_pattern_mismatch":
        return _Report(path, f"must match {ctx.get('pattern')}, got {_yaml_repr(value)}")
    if kind == "multiple_of":
        return _Report(path, f"must be a multiple of {_number(ctx.get('multiple_of'))}, "
                             f"got {_yaml_repr(value)}")

    text = str(ctx["error"]) if kind == "value_error" and "error" in ctx else str(err["msg"])
    for prefix in ("Value error, ", "Assertion failed, "):
        text = text.removeprefix(prefix)
    marked = _MARKER.match(text.strip())
    if marked:
        return _Report(_resolve_marked(path, marked[1], data), marked[2], at_key=True)
    if kind in ("value_error", "assertion_error") or not kind.endswith("_type"):
        return _Report(path, text[:1].lower() + text[1:] if text[1:2].islower() else text)
    return _Report(path, f"{text}, got {_got(value)}")


def _merge_union_branches(reports: list[_Report]) -> list[_Report]:
    """Join type errors of the same value from several union branches: 'a number or a list'."""
    merged: list[_Report] = []
    for rep in reports:
        prev = merged[-1] if merged else None
        if prev is not None and rep.expected and prev.expected and rep.path == prev.path:
            if rep.expected not in prev.expected.split(" or "):
                prev.expected += " or " + rep.expected
            continue
        merged.append(rep)
    for rep in merged:
        if rep.expected:
            rep.message = f"expected {rep.expected}, got {rep.got}"
    return merged


def _locate(rep: _Report, data: Any, positions: loader.Positions) -> tuple[int, int]:
    found = _normalise(rep.path, data)
    if found is None:
        return positions.position_of(rep.path)
    container = isinstance(_value_at(data, found), (Mapping, list))
    return positions.position_of(found, value=not (rep.at_key or container))


def convert_validation_error(exc: ValidationError, model_cls: type[BaseModel], data: Any,
                             positions: loader.Positions, file: str) -> DeckErrors:
    """All entries of a pydantic ``ValidationError`` as located DeckErrors, sorted by position.

    A missing key sorts just after an unknown key of the same mapping (likely its misspelling).
    """
    reports = []
    for err in exc.errors():
        rep = _report(err, model_cls, data)
        rep.kind = err["type"]
        reports.append(rep)
    located = [(rep, _locate(rep, data, positions)) for rep in _merge_union_branches(reports)]
    unknown_at = {rep.path[:-1]: pos for rep, pos in located if rep.kind == "extra_forbidden"}

    def order(item: tuple[_Report, tuple[int, int]]) -> tuple[int, int, int]:
        rep, pos = item
        if rep.kind == "missing" and rep.path in unknown_at:
            return (*unknown_at[rep.path], 1)
        return (*pos, 0)

    located.sort(key=order)
    return DeckErrors([DeckError(rep.message, file=file, line=line, col=col,
                                 path=format_path(rep.path)) for rep, (line, col) in located])


def validate_model(model_cls: type[M], data: Any, positions: loader.Positions,
                   file: str = "<deck>") -> M:
    """Validate ``data`` as ``model_cls``; raise :class:`DeckErrors` (a DeckError) on failure.

    Validation runs in pydantic's JSON mode, since YAML data are JSON data: lists fill tuples,
    strings fill enums, and a strict schema still refuses ``"1.0"`` for a number.
    """
    try:
        return model_cls.model_validate_json(json.dumps(data, allow_nan=True))
    except ValidationError as exc:
        raise convert_validation_error(exc, model_cls, data, positions, file) from None


def load_deck(path: str | PathLike[str]) -> Any:
    """Read, parse and validate the deck at ``path``; return a ``schema.Deck``.

    Raises :class:`DeckError` (for validation failures its subclass :class:`DeckErrors`, which
    prints as the first error and lists them all in ``.errors``).
    """
    from .schema import Deck

    data, positions = loader.load(path)
    return validate_model(Deck, data, positions, str(path))
