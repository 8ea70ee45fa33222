"""Deck keyword families ``units``, ``control`` and ``curves``: the unit system, the run's end and
time step, and the named time curves that scale boundaries and loads.
"""
from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from .base import DeckModel, NonNegativeFloat, PositiveFloat

__all__ = [
    "UNIT_SYSTEMS",
    "Units",
    "Control",
    "Curve",
]


# Consistent unit systems, as LS-DYNA lists them: (length, mass, time) -> (force, pressure, density).
UNIT_SYSTEMS: dict[tuple[str, str, str], tuple[str, str, str]] = {
    ("m", "kg", "s"): ("N", "Pa", "kg/m^3"),
    ("mm", "t", "s"): ("N", "MPa", "t/mm^3"),
    ("mm", "kg", "ms"): ("kN", "GPa", "kg/mm^3"),
    ("mm", "g", "ms"): ("N", "MPa", "g/mm^3"),
    ("cm", "g", "us"): ("1e7 N", "Mbar", "g/cm^3"),
}


class Units(DeckModel):
    """The deck's consistent unit system; kernels never convert."""

    length: Literal["m", "mm", "cm"] = Field("m", description="Length unit. Default m.")
    mass: Literal["kg", "t", "g"] = Field("kg", description="Mass unit (t is the tonne, 1000 kg). Default kg.")
    time: Literal["s", "ms", "us"] = Field("s", description="Time unit (us is the microsecond). Default s.")

    @model_validator(mode="after")
    def _consistent(self) -> "Units":
        if (self.length, self.mass, self.time) not in UNIT_SYSTEMS:
            known = "; ".join("-".join(k) for k in UNIT_SYSTEMS)
            raise ValueError(
                f"@units: {self.length}-{self.mass}-{self.time} is not a consistent unit system "
                f"(known: {known})"
            )
        return self

    @property
    def derived(self) -> tuple[str, str, str]:
        """(force, pressure, density) units implied by the system."""
        return UNIT_SYSTEMS[(self.length, self.mass, self.time)]


class Control(DeckModel):
    """Run control."""

    end_time: PositiveFloat = Field(description="Simulated time at which the run ends [time].")
    timestep_scale: Annotated[float, Field(gt=0, le=10)] = Field(
        0.9, description="Fraction of the element time step l/c used (LS-DYNA TSSFAC), l = volume over largest face. Default 0.9, stable for meshes several elements thick; parts one element thick or isolated elements need about 0.7 (an isolated hex8 goes unstable above 0.73)."
    )
    dt_min: NonNegativeFloat = Field(
        0.0, description="The run stops with a diagnosis if the step falls below this [time]. Default 0 (off)."
    )
    dt_max: PositiveFloat | None = Field(None, description="Upper bound on the time step [time]. Default none.")
    energy_band: Annotated[list[PositiveFloat], Field(min_length=2, max_length=2)] | None = Field(
        [0.9, 1.1], description="The run stops with a diagnosis when the energy error leaves [low - 1, high - 1]: "
        "total energy less (initial energy plus external work), over the energy in play (the largest so far of "
        "|kinetic| + |internal| + |hourglass| + |contact| and of initial energy plus external work). Where every "
        "energy is positive this is the glstat energy_ratio leaving [low, high]; where energies of opposite sign "
        "exchange (water released from rest) the ratio of two small numbers is not judged. Checked every 10 "
        "steps from step 5 on and at end_time; before step 100 the band is widened by (100/step)^2 for the start-up error of the central "
        "difference. null switches the check off. Default [0.9, 1.1]."
    )
    max_steps: PositiveFloat = Field(
        1.0e9, description="The run stops at once when end_time over the first stable step exceeds this number of "
        "steps (a run that would not end: a timestep_scale or dt_max far too small, units mixed up) [-]. "
        "Default 1e9."
    )
    max_lost_fraction: Annotated[float, Field(ge=0, le=1)] | None = Field(
        0.5, description="The run stops when more than this fraction of the SPH particles has left the domain "
        "(deactivated) [-]. null switches the check off. Default 0.5."
    )
    max_penetration: PositiveFloat | None = Field(
        None, description="The run stops when a contact or coupling reports a penetration deeper than this, checked "
        "after every step [length]. Default none: each contact's own limit, if it has one."
    )
    checkpoint_interval: PositiveFloat | None = Field(
        None, description="Simulated time between restart checkpoints (checkpoint.npz in the output folder, "
        "replaced each time) [time]. Default: one at every field output. A checkpoint is also written on "
        "Ctrl-C or SIGTERM."
    )
    checkpoint_wall_interval: PositiveFloat | None = Field(
        None, description="Wall-clock seconds between restart checkpoints, besides checkpoint_interval [s]. Default none."
    )

    @model_validator(mode="after")
    def _band(self) -> "Control":
        if self.energy_band is not None and not self.energy_band[0] < 1.0 < self.energy_band[1]:
            raise ValueError("@energy_band: must be [low, high] with low < 1 < high")
        return self


class Curve(DeckModel):
    """A tabulated function of time, linearly interpolated, constant beyond its ends."""

    points: list[Annotated[list[float], Field(min_length=2, max_length=2)]] = Field(
        min_length=1, description="[[t0, f0], [t1, f1], ...] with increasing t."
    )
    scale: float = Field(1.0, description="Multiplies every ordinate. Default 1.")

    @model_validator(mode="after")
    def _increasing(self) -> "Curve":
        ts = [p[0] for p in self.points]
        if any(b <= a for a, b in zip(ts, ts[1:])):
            raise ValueError("@points: abscissae must be strictly increasing")
        return self
