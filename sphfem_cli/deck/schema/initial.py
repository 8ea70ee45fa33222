"""Deck keyword family ``initial``: initial conditions.
"""
from __future__ import annotations

from typing import Annotated, Literal, Union

from pydantic import Field

from .base import Vector
from .boundaries import Target

__all__ = [
    "InitialVelocity",
    "Initial",
]


class InitialVelocity(Target):
    """Initial nodal velocity (LS-DYNA *INITIAL_VELOCITY)."""

    type: Literal["velocity"] = Field(description="Initial-condition selector: nodal velocity.")
    velocity: Vector = Field(description="Velocity [length/time].")


Initial = Annotated[Union[InitialVelocity], Field(discriminator="type")]
