"""Deck keyword family ``loads``: body accelerations, pressures on segments and forces on nodes.
"""
from __future__ import annotations

from typing import Annotated, Literal, Union

from pydantic import Field

from .base import DeckModel, Vector

__all__ = [
    "Gravity",
    "PressureLoad",
    "NodalForce",
    "Load",
]


class Gravity(DeckModel):
    """Body acceleration on every part (or the listed parts)."""

    type: Literal["gravity"] = Field(description="Load selector: body acceleration.")
    acceleration: Vector = Field(description="Acceleration vector [length/time^2], e.g. [0, -9.81].")
    parts: list[str] | None = Field(None, description="Parts it acts on. Default all.")
    curve: str | None = Field(None, description="Curve scaling it in time. Default constant.")


class PressureLoad(DeckModel):
    """Pressure on a segment set, positive pushing into the body (LS-DYNA *LOAD_SEGMENT_SET)."""

    type: Literal["pressure"] = Field(description="Load selector: pressure on segments.")
    set: str = Field(description="A segment set.")
    value: float = Field(description="Pressure [pressure].")
    curve: str | None = Field(None, description="Curve scaling it in time. Default constant.")


class NodalForce(DeckModel):
    """A force applied at each node of a node set (LS-DYNA *LOAD_NODE_SET)."""

    type: Literal["nodal_force"] = Field(description="Load selector: force on nodes.")
    set: str = Field(description="A node set.")
    force: Vector = Field(description="Force at each node [force].")
    curve: str | None = Field(None, description="Curve scaling it in time. Default constant.")


Load = Annotated[Union[Gravity, PressureLoad, NodalForce], Field(discriminator="type")]
