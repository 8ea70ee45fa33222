"""Shared pieces of the deck schema: the strict base model and vector fields.

Every keyword-family model derives from :class:`DeckModel`: unknown keys are rejected, numbers
must be numbers (a quoted ``"1.0"`` is a string and an error), NaN and Inf are rejected.

Vectors (`Vector`) hold one value per space dimension; their length is checked against the deck's
``dimension`` once the whole deck is read (see ``check_vector_lengths``).
"""
from __future__ import annotations

import types
import typing
import unicodedata
from typing import Annotated, Any

from pydantic import BaseModel, ConfigDict, Field


class DeckModel(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False, frozen=False, defer_build=True)


class _VectorMarker:
    """Metadata tag on fields holding one component per space dimension."""


VECTOR = _VectorMarker()

Vector = Annotated[list[float], Field(min_length=2, max_length=3), VECTOR]
"""A point or direction: 2 components in 2D, 3 in 3D."""

OptionalComponents = Annotated[list[float | None], Field(min_length=2, max_length=3), VECTOR]
"""Per-direction values where ``null`` leaves that direction free."""

PositiveFloat = Annotated[float, Field(gt=0)]
NonNegativeFloat = Annotated[float, Field(ge=0)]


def exactly_one(model: BaseModel, names: tuple[str, ...], what: str, at: str = "") -> str:
    """The one of `names` given on `model`; ValueError('@at: ...') unless exactly one is."""
    given = [k for k in names if getattr(model, k) is not None]
    if len(given) != 1:
        options = ", ".join(f"'{k}'" for k in names)
        raise ValueError(f"@{at}: give exactly one {what} ({options}), got {len(given)}")
    return given[0]


def check_extent(lo: list[float] | None, hi: list[float] | None, what: str, strict: bool = True) -> None:
    """``ValueError('@max: ...')`` unless ``hi`` exceeds ``lo`` in every direction (``strict``), or
    is at least ``lo`` (not strict: a box of zero width that selects the nodes of a plane)."""
    if lo is None or hi is None:
        return
    if any(b < a for a, b in zip(lo, hi)):
        raise ValueError(f"@max: every component of max must be >= min ({what})")
    if strict and any(b == a for a, b in zip(lo, hi)):
        raise ValueError(f"@max: {what} has zero width: every component of max must exceed min")


def check_vector_lengths(model: BaseModel, dimension: int, path: tuple = ()) -> None:
    """Raise ``ValueError('@path: ...')`` for the first vector field whose length is not `dimension`."""
    for name, field in type(model).model_fields.items():
        value = getattr(model, name)
        here = path + (name,)
        if value is None:
            continue
        if _is_vector(field.metadata, field.annotation) and len(value) != dimension:
            raise ValueError(
                f"@{_dotted(here)}: expected {dimension} values (dimension {dimension}), got {len(value)}"
            )
        _walk(value, dimension, here)


def _is_vector(metadata: list, annotation: Any) -> bool:
    """Whether a field is a `Vector`: the marker on the field, or inside ``Vector | None``."""
    if any(m is VECTOR for m in metadata):
        return True
    if typing.get_origin(annotation) is Annotated:
        return any(m is VECTOR for m in annotation.__metadata__)
    if typing.get_origin(annotation) in (typing.Union, types.UnionType):
        return any(_is_vector([], a) for a in typing.get_args(annotation) if a is not type(None))
    return False


def _walk(value: Any, dimension: int, path: tuple) -> None:
    if isinstance(value, BaseModel):
        check_vector_lengths(value, dimension, path)
    elif isinstance(value, dict):
        for key, item in value.items():
            _walk(item, dimension, path + (key,))
    elif isinstance(value, list):
        for i, item in enumerate(value):
            if isinstance(item, BaseModel):
                _walk(item, dimension, path + (i,))


def _dotted(path: tuple) -> str:
    return ".".join(str(p) for p in path)


NAME_MAX_CHARS = 100
NAME_MAX_BYTES = 200
_NAME_FORBIDDEN = ',"/\\'


def name_problem(name: str) -> str | None:
    """Why ``name`` cannot name a deck entity, or None if it can.

    Any Unicode is allowed (``名前``, ``🔥``): names become CSV column names and file names
    (histories/<name>.csv), HDF5 and XDMF names, all written as UTF-8. Refused: the empty name,
    control characters and line or paragraph separators (Unicode categories Cc, Cs, Zl, Zp), the
    characters , " / \\ (CSV field and path separators), ``.`` and ``..``, and names over
    NAME_MAX_CHARS characters or NAME_MAX_BYTES bytes of UTF-8 (file names end at 255 bytes).
    """
    if not name.strip():
        return "a name must not be empty or blank"
    for ch in name:
        if unicodedata.category(ch) in ("Cc", "Cs", "Zl", "Zp"):
            return f"a name must not hold the control character U+{ord(ch):04X}"
        if ch in _NAME_FORBIDDEN:
            return f"a name must not hold {ch!r} (names become CSV columns and file names)"
    if name in (".", ".."):
        return f"'{name}' cannot be a name (names become file names)"
    if len(name) > NAME_MAX_CHARS or len(name.encode("utf-8")) > NAME_MAX_BYTES:
        return f"a name has at most {NAME_MAX_CHARS} characters and {NAME_MAX_BYTES} bytes of UTF-8"
    return None
