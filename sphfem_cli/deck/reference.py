"""The deck reference (docs/deck-reference.md), generated from the pydantic schema.

Everything a deck writer needs to know about one key (its type, whether it is required, its
default, its meaning and units) already lives in the schema: ``Field(description=...)`` on every
field and a docstring on every model. :func:`render_reference` walks the models reachable from
:class:`~sphfem_cli.deck.schema.Deck` and turns them into Markdown, so the reference cannot say
something the schema does not. The hand-written parts (header, example deck, conventions) are in
``reference_prose``; how a field's type and default read as text is ``reference_fields``::

    python -m sphfem_cli.deck.reference            # rewrite docs/deck-reference.md
    python -m sphfem_cli.deck.reference --check    # exit 1 if docs/deck-reference.md is stale

``tests/unit/test_deck_reference.py`` runs the check, requires a description on every field and
validates the example deck printed at the top of the reference.
"""
from __future__ import annotations

import argparse
import sys
import typing
from pathlib import Path
from typing import Any

from pydantic import BaseModel
from pydantic.fields import FieldInfo

from .reference_fields import (anchor_of, cell, default_text, docstring, field_type_text, iter_models, models_in,
                               nested_path, ordered_fields, prose, strip_annotated, type_tag)
from .reference_prose import CONVENTIONS, EXAMPLE_DECK, HEADER, limit_table, unit_table
from .schema import RESERVED_HISTORIES, Deck
from .schema.base import NAME_MAX_BYTES, NAME_MAX_CHARS

__all__ = ["EXAMPLE_DECK", "DEFAULT_OUTPUT", "render_reference", "iter_models", "main"]

DEFAULT_OUTPUT = Path(__file__).resolve().parents[2] / "docs" / "deck-reference.md"
"""Where the committed reference lives (repository root ``docs/``)."""


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
    for name, field in ordered_fields(model):
        child = f"{path}.{name}"
        type_text = field_type_text(field.annotation, list(field.metadata), child)
        w.add(
            f"| `{name}` | {cell(type_text)} | {cell(default_text(field))} "
            f"| {cell(prose(field.description or ''))} |"
        )
        if models_in(field.annotation):
            nested.append((child, field.annotation))
    w.add("")
    return nested


def _render_model(w: _Writer, model: type[BaseModel], path: str, level: int, title: str | None = None,
                  anchor: str | None = None) -> None:
    anchor = anchor or anchor_of(path)
    if anchor in w.anchors and w.models.get(anchor) is model:
        return  # the same model at the same path under another variant: documented once, linked from both
    w.models[anchor] = model
    w.heading(level, title or f"`{path}`", anchor)
    w.paragraph(prose(docstring(model)))
    for child, ann in _table(w, model, path):
        _render_nested(w, child, ann, level + 1)


def _render_nested(w: _Writer, child: str, ann: Any, level: int) -> None:
    where, model, variants = nested_path(child, ann)
    if model is not None:
        _render_model(w, model, where, level)
    elif variants is not None:
        for v in variants:
            _render_variant(w, v, where, level)


def _render_variant(w: _Writer, model: type[BaseModel], path: str, level: int) -> None:
    tag = type_tag(model)
    _render_model(w, model, path, level, title=f"`{path}` with `type: {tag}`",
                  anchor=anchor_of(f"{path}-{tag}"))


def _family(w: _Writer, name: str, field: FieldInfo) -> None:
    ann = field.annotation
    w.heading(2, f"`{name}`", anchor_of(name))
    w.paragraph(prose(field.description or ""))
    type_text = field_type_text(ann, list(field.metadata), name)
    where, model, variants = nested_path(name, ann)
    default = "**Required.**" if field.is_required() else f"**Default:** {default_text(field)}."
    w.paragraph(f"**Type:** {type_text}. {default}")
    if variants is not None:
        shape = (f"`{name}: {{<name>: {{type: <type>, ...}}, ...}}`" if typing.get_origin(strip_annotated(ann)[0]) is dict
                 else f"`{name}: [{{type: <type>, ...}}, ...]`")
        links = ", ".join(f"[`{type_tag(v)}`](#{anchor_of(f'{where}-{type_tag(v)}')})" for v in variants)
        w.paragraph(f"Written as {shape}. Types: {links}.")
        for v in variants:
            _render_variant(w, v, where, 3)
    elif model is not None and where == name:
        w.paragraph(prose(docstring(model)))
        for child, child_ann in _table(w, model, name):
            _render_nested(w, child, child_ann, 3)
    elif model is not None:
        _render_model(w, model, where, 3)


def render_reference() -> str:
    """The whole deck reference as Markdown, built from the schema."""
    w = _Writer()
    w.add(HEADER)
    w.heading(2, "A minimal deck", "a-minimal-deck")
    w.add("```yaml", EXAMPLE_DECK.rstrip("\n"), "```", "")
    w.add(CONVENTIONS.format(unit_table=unit_table(), name_chars=NAME_MAX_CHARS, name_bytes=NAME_MAX_BYTES,
                              reserved=", ".join(f"`{n}`" for n in RESERVED_HISTORIES), limits=limit_table()))
    w.heading(2, "Top-level keys", "top-level-keys")
    w.paragraph(prose(docstring(Deck)) + " Its keys, in the order of this reference:")
    w.add("| key | type | default | description |", "|---|---|---|---|")
    for name, field in Deck.model_fields.items():
        type_text = field_type_text(field.annotation, list(field.metadata), name, links=False)
        w.add(f"| [`{name}`](#{anchor_of(name)}) | {cell(type_text)} | {cell(default_text(field))} "
              f"| {cell(prose(field.description or ''))} |")
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
