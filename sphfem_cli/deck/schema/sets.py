"""Deck keyword family ``sets``: named node and segment sets chosen by part and geometric filters.
"""
from __future__ import annotations

from typing import Annotated, Literal, Union

from pydantic import Field

from .base import DeckModel, NonNegativeFloat
from .shapes import BallGeometry, Box, Plane

__all__ = [
    "Selection",
    "NodeSet",
    "SegmentSet",
    "SetDef",
]


class Selection(DeckModel):
    """Geometric filters; a node is selected when it passes every filter given."""

    part: str | None = Field(None, description="Only nodes of this part (default: all parts).")
    side: Literal["left", "right", "bottom", "top", "back", "front"] | None = Field(
        None, description="Nodes at the extreme x (left/right), y (bottom/top) or z (back/front) of the part."
    )
    box: Box | None = Field(None, description="Nodes inside a box {min, max}.")
    plane: Plane | None = Field(
        None, description="Nodes within tolerance of a plane {point, normal}."
    )
    sphere: BallGeometry | None = Field(
        None, description="Nodes within tolerance of a circle (2D) or sphere (3D) {center, radius}."
    )
    tolerance: NonNegativeFloat | None = Field(
        None, description="Distance tolerance [length]. Default 1e-6 of the model's size."
    )


class NodeSet(Selection):
    """Nodes chosen by part and geometric filters."""

    type: Literal["node"] = Field(description="Set selector: a node set.")


class SegmentSet(Selection):
    """Exterior element faces (edges in 2D) whose nodes all pass the filters."""

    type: Literal["segment"] = Field(description="Set selector: a segment set (faces, for pressure loads).")


SetDef = Annotated[Union[NodeSet, SegmentSet], Field(discriminator="type")]
