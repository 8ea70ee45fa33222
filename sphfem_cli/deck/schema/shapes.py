"""Geometric shapes shared by several keyword families: boxes, planes, balls, polygons and half-spaces
(selections of ``sets``, regions of ALE ``fill`` and dummy walls, the SPH ``domain``).
"""
from __future__ import annotations

from typing import Annotated

from pydantic import Field, model_validator

from .base import DeckModel, PositiveFloat, Vector, check_extent

__all__ = [
    "Box",
    "VolumeBox",
    "Plane",
    "BallGeometry",
    "PolygonGeometry",
    "HalfSpace",
]


class Box(DeckModel):
    """An axis-aligned box (max >= min in every direction)."""

    min: Vector = Field(description="Lower corner [length].")
    max: Vector = Field(description="Upper corner [length].")

    @model_validator(mode="after")
    def _ordered(self) -> "Box":
        check_extent(self.min, self.max, "the box", strict=False)
        return self


class VolumeBox(Box):
    """An axis-aligned box of positive width in every direction."""

    @model_validator(mode="after")
    def _volume(self) -> "VolumeBox":
        check_extent(self.min, self.max, "the box")
        return self


class Plane(DeckModel):
    """A plane through a point."""

    point: Vector = Field(description="A point on the plane [length].")
    normal: Vector = Field(description="Normal direction [-].")

    @model_validator(mode="after")
    def _direction(self) -> "Plane":
        if not any(self.normal):
            raise ValueError("@normal: a normal must not be the zero vector")
        return self


class BallGeometry(DeckModel):
    """A disc (2D) or ball (3D) filled with particles."""

    center: Vector = Field(description="Centre [length].")
    radius: PositiveFloat = Field(description="Radius [length].")


class PolygonGeometry(DeckModel):
    """A closed 2D polygon filled with particles (even-odd rule)."""

    vertices: list[Annotated[list[float], Field(min_length=2, max_length=2)]] = Field(
        min_length=3, description="[[x0, y0], [x1, y1], ...] in order [length]."
    )


class HalfSpace(DeckModel):
    """The side of a plane the normal points away from: (x - point) . normal <= 0."""

    point: Vector = Field(description="A point on the plane [length].")
    normal: Vector = Field(description="Outward normal of the filled side [-].")

    @model_validator(mode="after")
    def _direction(self) -> "HalfSpace":
        if not any(self.normal):
            raise ValueError("@normal: a normal must not be the zero vector")
        return self
