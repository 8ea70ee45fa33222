"""Deck keyword family ``output``: field output, time histories and fluid probes.
"""
from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from .base import DeckModel, PositiveFloat, Vector, exactly_one

__all__ = [
    "NODE_QUANTITIES",
    "ELEMENT_QUANTITIES",
    "FIELD_NAMES",
    "HISTORY_ONLY",
    "HistoryRequest",
    "Probe",
    "ProbeSensor",
    "ProbeFilter",
    "ReferenceCurve",
    "Output",
    "Revolve",
    "MAX_REVOLVE_SEGMENTS",
]


NODE_QUANTITIES = ("displacement", "velocity", "acceleration", "coordinates")
ELEMENT_QUANTITIES = ("stress", "von_mises", "pressure", "plastic_strain")
FIELD_NAMES = NODE_QUANTITIES + ELEMENT_QUANTITIES + ("density",)
HISTORY_ONLY = ("contact_force",)  # summed over the nodes: the force contacts and couplings exert on them


class HistoryRequest(DeckModel):
    """A time history of nodal (mean over the nodes) or element (at the nearest element) quantities."""

    name: str = Field(description="Name of the CSV table written (histories/<name>.csv).")
    part: str | None = Field(None, description="Mean over the nodes of a part.")
    set: str | None = Field(None, description="Mean over the nodes of a set.")
    point: Vector | None = Field(
        None, description="The node nearest this point (element quantities: the element nearest it)."
    )
    quantities: list[Literal[NODE_QUANTITIES + ELEMENT_QUANTITIES + HISTORY_ONLY]] = Field(
        default_factory=lambda: ["displacement", "velocity"],
        description="Quantities recorded (contact_force: the total force of contacts and couplings on the "
        "nodes, at the start of the last step). Default [displacement, velocity].",
    )

    @model_validator(mode="after")
    def _one_target(self) -> "HistoryRequest":
        exactly_one(self, ("part", "set", "point"), "target", at="name")
        return self


class ProbeSensor(DeckModel):
    """The size of a pressure transducer: the probe reports the mean pressure over its face (a
    segment of length `diameter` in 2D, a disc in 3D, perpendicular to `normal`), or without a
    normal over a disc (2D) / ball (3D) of that diameter, by a fixed quadrature rule
    (sphfem_cli/model/sensors.py; exact for quadratic fields). Points no fluid reaches read 0 (dry)."""

    diameter: PositiveFloat = Field(description="Diameter of the sensing face (or disc / ball) [length].")
    normal: Vector | None = Field(None, description="The wall's normal at the sensor: the face lies in the plane "
                                  "perpendicular to it (a transducer mounted flush in a wall). Default none: a disc / ball.")

    @model_validator(mode="after")
    def _normal(self) -> "ProbeSensor":
        if self.normal is not None and not any(c != 0.0 for c in self.normal):
            raise ValueError("@normal: the normal is the zero vector")
        return self


class ProbeFilter(DeckModel):
    """A low-pass filter applied after the run to a copy of the probe's raw series, written as
    histories/<name>_filtered.csv beside the raw histories/<name>.csv (sphfem_cli/output/filters.py).
    butterworth: zero phase (forward and backward), the stated cutoff is the -3 dB point of the whole
    filter; running_mean: causal, the mean over the trailing window."""

    kind: Literal["butterworth", "running_mean"] = Field(description="butterworth (zero-phase) or running_mean (causal).")
    cutoff: PositiveFloat | None = Field(None, description="butterworth: the -3 dB frequency [1/time], below the "
                                         "Nyquist frequency 1/(2 history_interval).")
    order: int | None = Field(None, ge=1, le=8, description="butterworth: order of the filter, 1 to 8. Default 2.")
    window: PositiveFloat | None = Field(None, description="running_mean: length of the trailing window [time], at "
                                         "least history_interval.")

    @model_validator(mode="after")
    def _settings(self) -> "ProbeFilter":
        if self.kind == "butterworth":
            if self.cutoff is None:
                raise ValueError("@cutoff: a butterworth filter needs 'cutoff' (its -3 dB frequency)")
            if self.window is not None:
                raise ValueError("@window: 'window' is for running_mean; a butterworth filter takes 'cutoff'")
        else:
            if self.window is None:
                raise ValueError("@window: a running_mean filter needs 'window' (its length in time)")
            for key in ("cutoff", "order"):
                if getattr(self, key) is not None:
                    raise ValueError(f"@{key}: '{key}' is for butterworth; a running_mean filter takes 'window'")
        return self


class Probe(DeckModel):
    """A fluid measurement written as a history (histories/<name>.csv): SPH particles, or pressure in an ALE part."""

    name: str = Field(description="Name of the CSV table written.")
    type: Literal["pressure", "surface_height", "front"] = Field(
        description="pressure: kernel-interpolated at `point`; surface_height: free-surface height at the "
        "gauge position `gauge` along `axis`; front: the furthest particle of `part` (all SPH parts by default) along `axis`, "
        "or in an ALE part the furthest reach of `material` (each element's material volume packed against its "
        "face on the -axis side: x_min + phi (x_max - x_min) over the elements holding more than 1e-3 of it)."
    )
    point: Vector | None = Field(None, description="pressure: where [length].")
    gauge: float | None = Field(None, description="surface_height: gauge position along `axis` [length].")
    axis: Literal["x", "y", "z"] = Field("x", description="surface_height and front: the horizontal axis. Default x.")
    part: str | None = Field(None, description="front: an SPH part (default all SPH parts) or the ALE part; pressure: "
                             "the ALE part to measure instead of the SPH particles (the mixture pressure of the element "
                             "at `point`; the default in a deck whose only fluid is ALE).")
    material: str | None = Field(None, description="front in an ALE part: the material whose front is measured "
                                 "(required there).")
    sensor: ProbeSensor | None = Field(None, description="pressure: the transducer's size; the probe reports the mean "
                                       "over it. Default none: the value at `point`.")
    filter: ProbeFilter | None = Field(None, description="A low-pass filter of the series, written after the run as "
                                       "histories/<name>_filtered.csv; the raw table is kept. Default none.")

    @model_validator(mode="after")
    def _needs(self) -> "Probe":
        if self.type == "pressure" and self.point is None:
            raise ValueError("@point: a pressure probe needs 'point'")
        if self.type == "surface_height" and self.gauge is None:
            raise ValueError("@gauge: a surface_height probe needs 'gauge'")
        if self.sensor is not None and self.type != "pressure":
            raise ValueError(f"@sensor: only a pressure probe takes a sensor size (this is a {self.type} probe)")
        return self


class ReferenceCurve(DeckModel):
    """A reference history (measurement, exact or published result) that `sphfem plot` draws beside a
    computed quantity. The CSV's ``#`` lines are comments, a first column that is not a number names the
    series; time = time_scale x column ``columns[0]``, value = value_scale x column ``columns[1]``
    (numeric columns counted from 0), which turns a dimensionless curve into the deck's units."""

    file: str = Field(description="CSV file, relative to the deck's folder.")
    quantity: str = Field(description="The history it compares with, TABLE.COLUMN (e.g. front.front, tip.displacement_y).")
    series: str | None = Field(None, description="Only the rows of this series (the first column's text). Default all.")
    columns: list[int] = Field([0, 1], min_length=2, max_length=2,
                               description="The numeric columns of time and value. Default [0, 1].")
    time_scale: PositiveFloat = Field(1.0, description="Multiplies the time column [time]. Default 1.")
    value_scale: float = Field(1.0, description="Multiplies the value column [the quantity's unit]. Default 1.")
    label: str | None = Field(None, description="Legend text. Default the file name and series.")

    @model_validator(mode="after")
    def _quantity(self):
        table, _, column = self.quantity.partition(".")
        if not table or not column:
            raise ValueError("@quantity: name it TABLE.COLUMN, e.g. front.front")
        if min(self.columns) < 0:
            raise ValueError("@columns: column numbers count from 0")
        return self


MAX_REVOLVE_SEGMENTS = 360
"""The most segments a revolved view may have: its datasets are `segments` (+1 for a partial sweep) times
the meridian's, at every field step."""


class Revolve(DeckModel):
    """A revolved 3D view of each part of an axisymmetric deck, for ParaView (as ParaView's Rotational
    Extrusion filter, or LS-DYNA's 2D-to-3D display): results.<part>.revolved.xdmf beside the meridian
    plane's results.<part>.xdmf. Meridian x = r turns into 3D (x, y) = (r cos a, r sin a); the axis
    (meridian y) is 3D z. Quad rings become hex8 cells (those touching the axis collapse, see docs/output.md),
    particles points on `segments` angles of their ring; vectors and stress are rotated to Cartesian components."""

    segments: int = Field(24, ge=3, le=MAX_REVOLVE_SEGMENTS,
                          description="Angular divisions of the sweep (3 to 360). The revolved datasets are "
                          "`segments` times the meridian's (one more ring of points for a partial sweep), at every "
                          "field step. Default 24.")
    angle: float = Field(360.0, gt=0.0, le=360.0,
                         description="Sweep angle from the meridian plane (a = 0, 3D x-z plane) toward +y [degrees], "
                         "up to 360 (closed). Default 360.")


class Output(DeckModel):
    """What is written, and how often."""

    interval: PositiveFloat | None = Field(
        None, description="Simulated time between field outputs to XDMF/HDF5 [time]; at most 100 000 outputs per run "
        "(the solver lands a step on each), and the state at end_time when the interval does not land on it (as "
        "LS-DYNA writes a d3plot state at termination). Default end_time/50."
    )
    history_interval: PositiveFloat | None = Field(
        None, description="Simulated time between history rows [time]. Default end_time/1000."
    )
    revolve: Revolve | None = Field(
        None, description="Axisymmetric decks only: also write a revolved 3D view of every part "
        "(results.<part>.revolved.xdmf). Default none (the meridian plane only)."
    )
    fields: list[Literal[FIELD_NAMES]] = Field(
        default_factory=lambda: list(FIELD_NAMES), description="Fields written to XDMF. Default all."
    )
    histories: list[HistoryRequest] = Field(default_factory=list, description="Requested time histories.")
    probes: list[Probe] = Field(default_factory=list, description="SPH probes, written as histories.")
    references: list[ReferenceCurve] = Field(
        default_factory=list, description="Reference curves `sphfem plot` draws beside the histories they name."
    )
