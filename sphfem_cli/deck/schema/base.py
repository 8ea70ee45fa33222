"""Shared pieces of the deck schema: the strict base model and vector fields.

Every keyword-family model derives from :class:`DeckModel`: unknown keys are rejected, numbers
must be numbers (a quoted ``"1.0"`` is a string and an error), NaN and Inf are rejected.

Vectors (`Vector`) hold one value per space dimension; their length is checked against the deck's
``dimension`` once the whole deck is read (see ``check_vector_lengths``).
"""
from __future__ import annotations

from typing import Annotated, Any

from pydantic import BaseModel, ConfigDict, Field


class DeckModel(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False, frozen=False)


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


def check_vector_lengths(model: BaseModel, dimension: int, path: tuple = ()) -> None:
    """Raise ``ValueError('@path: ...')`` for the first vector field whose length is not `dimension`."""
    for name, field in type(model).model_fields.items():
        value = getattr(model, name)
        here = path + (name,)
        if value is None:
            continue
        if any(m is VECTOR for m in field.metadata) and len(value) != dimension:
            raise ValueError(
                f"@{_dotted(here)}: expected {dimension} values (dimension {dimension}), got {len(value)}"
            )
        _walk(value, dimension, here)


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
