"""Keyword families of the deck other than materials and equations of state.

One pydantic model per family; field descriptions are the deck reference's text
(docs/deck-reference.md is generated from them), so each states meaning, units and default.
"""
from __future__ import annotations

from typing import Annotated, Literal, Union

from pydantic import Field, model_validator

from .base import DeckModel, NonNegativeFloat, OptionalComponents, PositiveFloat, Vector

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


# ---------------------------------------------------------------------------------------- sections


class Hourglass(DeckModel):
    """Flanagan–Belytschko hourglass control of one-point elements."""

    type: Literal["viscous", "stiffness"] = Field(
        "viscous", description="viscous (Flanagan-Belytschko viscous form with the LS-DYNA IHQ=1 coefficient; like IHQ=2) or stiffness (Flanagan-Belytschko stiffness form, like IHQ=4). Default viscous."
    )
    coefficient: Annotated[float, Field(ge=0, le=0.12)] = Field(
        0.1, description="Hourglass coefficient QM [-], at most 0.12. Default 0.1 (0.05–0.1 typical for stiffness). The hourglass terms are not part of the stable time step: in 3D, viscous QM above about 0.14 (LS-DYNA warns above 0.15) and stiffness QM above about 0.2 make a run unstable, hence the bound."
    )


class BulkViscosity(DeckModel):
    """Von Neumann–Richtmyer shock viscosity, active in compression."""

    q1: NonNegativeFloat = Field(1.5, description="Quadratic coefficient Q1. Default 1.5.")
    q2: NonNegativeFloat = Field(0.06, description="Linear coefficient Q2. Default 0.06.")


class SolidSection(DeckModel):
    """Lagrangian solid elements: quad4 plane strain (2D) or hex8 (3D), one-point integration."""

    type: Literal["solid"] = Field(description="Section selector: Lagrangian solid elements.")
    hourglass: Hourglass = Field(default_factory=Hourglass, description="Hourglass control.")
    bulk_viscosity: BulkViscosity = Field(default_factory=BulkViscosity, description="Shock viscosity.")


Section = Annotated[Union[SolidSection], Field(discriminator="type")]


# ------------------------------------------------------------------------------------------- parts


class BoxGeometry(DeckModel):
    """A structured block of quad4 (2D) or hex8 (3D) elements between two corners."""

    min: Vector = Field(description="Lower corner [length].")
    max: Vector = Field(description="Upper corner [length].")
    divisions: list[Annotated[int, Field(ge=1)]] | None = Field(
        None, description="Elements per direction; or give element_size."
    )
    element_size: PositiveFloat | None = Field(
        None, description="Target element edge length [length]; or give divisions."
    )

    @model_validator(mode="after")
    def _one_resolution(self) -> "BoxGeometry":
        if (self.divisions is None) == (self.element_size is None):
            raise ValueError("@divisions: give exactly one of 'divisions' or 'element_size'")
        if any(hi <= lo for lo, hi in zip(self.min, self.max)):
            raise ValueError("@max: every component of max must exceed min")
        return self


class RingGeometry(DeckModel):
    """A 2D O-grid annulus of quad4 (a filled disc with a square core when inner_radius is 0)."""

    center: Vector = Field(description="Centre [length].")
    inner_radius: NonNegativeFloat = Field(description="Inner radius [length]; 0 for a filled disc.")
    outer_radius: PositiveFloat = Field(description="Outer radius [length].")
    elements_around: Annotated[int, Field(ge=4)] = Field(description="Elements around the circumference.")
    elements_through: Annotated[int, Field(ge=1)] = Field(description="Elements through the radius.")


class CylinderGeometry(RingGeometry):
    """A 3D O-grid tube (or solid cylinder) of hex8: the ring extruded along an axis."""

    axis: Literal["x", "y", "z"] = Field("z", description="Axis direction. Default z.")
    length: PositiveFloat = Field(description="Length along the axis from the centre plane [length].")
    elements_along: Annotated[int, Field(ge=1)] = Field(description="Elements along the axis.")


class FileGeometry(DeckModel):
    """A mesh read with meshio (Gmsh .msh, Abaqus .inp, VTU, ...): quad cells in 2D, hexahedra in 3D."""

    file: str = Field(description="Path, relative to the deck's folder.")
    scale: PositiveFloat = Field(1.0, description="Multiplies every coordinate. Default 1.")


class Geometry(DeckModel):
    """Exactly one of box, ring, cylinder or file."""

    box: BoxGeometry | None = Field(None, description="A structured block of elements (2D or 3D).")
    ring: RingGeometry | None = Field(None, description="A 2D annulus or disc of quad4.")
    cylinder: CylinderGeometry | None = Field(None, description="A 3D tube or solid cylinder of hex8.")
    file: FileGeometry | None = Field(None, description="A mesh read from a file.")

    @model_validator(mode="after")
    def _exactly_one(self) -> "Geometry":
        given = [k for k in ("box", "ring", "cylinder", "file") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(
                f"@: give exactly one geometry (box, ring, cylinder or file), got {len(given)}"
            )
        return self

    @property
    def kind(self) -> str:
        return next(k for k in ("box", "ring", "cylinder", "file") if getattr(self, k) is not None)


class Part(DeckModel):
    """A meshed body with one material and one section."""

    material: str = Field(description="Name of a material.")
    section: str = Field(description="Name of a section.")
    geometry: Geometry = Field(description="How the part is meshed.")
    rigid: bool = Field(
        False, description="Move as one rigid body (also implied by a material of type rigid). Default false."
    )


# -------------------------------------------------------------------------------------------- sets


class Selection(DeckModel):
    """Geometric filters; a node is selected when it passes every filter given."""

    part: str | None = Field(None, description="Only nodes of this part (default: all parts).")
    side: Literal["left", "right", "bottom", "top", "back", "front"] | None = Field(
        None, description="Nodes at the extreme x (left/right), y (bottom/top) or z (back/front) of the part."
    )
    box: dict[Literal["min", "max"], Vector] | None = Field(None, description="{min: [...], max: [...]}.")
    plane: dict[Literal["point", "normal"], Vector] | None = Field(
        None, description="Nodes within tolerance of a plane {point, normal}."
    )
    sphere: dict[Literal["center"], Vector] | None = Field(
        None, description="{center: [...]} with radius: nodes within tolerance of a circle/sphere."
    )
    radius: PositiveFloat | None = Field(None, description="Radius for sphere [length].")
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


# ---------------------------------------------------------------------------- boundaries and loads


class Target(DeckModel):
    """Exactly one of a part name or a set name."""

    part: str | None = Field(None, description="All nodes of this part.")
    set: str | None = Field(None, description="A node set (or the nodes of a segment set).")

    @model_validator(mode="after")
    def _one_target(self) -> "Target":
        if (self.part is None) == (self.set is None):
            raise ValueError("@part: give exactly one of 'part' or 'set'")
        return self


Direction = Literal["x", "y", "z"]


class FixedBoundary(Target):
    """Zero velocity in the listed directions (LS-DYNA *BOUNDARY_SPC).

    On a rigid part it holds the body's translation in those directions; fixed in every direction,
    the body is held entirely (no rotation either).
    """

    type: Literal["fixed"] = Field(description="Boundary selector: fixed directions.")
    directions: list[Direction] | None = Field(
        None, description="Fixed directions. Default all directions of the deck's dimension."
    )


class SymmetryBoundary(Target):
    """A symmetry plane: zero velocity normal to it."""

    type: Literal["symmetry"] = Field(description="Boundary selector: symmetry plane.")
    normal: Direction = Field(description="Axis normal to the symmetry plane.")


class PrescribedVelocity(Target):
    """Velocity imposed on nodes, or on a rigid part as a whole (LS-DYNA *BOUNDARY_PRESCRIBED_MOTION)."""

    type: Literal["prescribed_velocity"] = Field(description="Boundary selector: prescribed velocity.")
    velocity: OptionalComponents = Field(
        description="Velocity [length/time] per direction; null leaves a direction free."
    )
    curve: str | None = Field(None, description="Curve scaling the velocity in time. Default constant.")


Boundary = Annotated[
    Union[FixedBoundary, SymmetryBoundary, PrescribedVelocity], Field(discriminator="type")
]


class InitialVelocity(Target):
    """Initial nodal velocity (LS-DYNA *INITIAL_VELOCITY)."""

    type: Literal["velocity"] = Field(description="Initial-condition selector: nodal velocity.")
    velocity: Vector = Field(description="Velocity [length/time].")


Initial = Annotated[Union[InitialVelocity], Field(discriminator="type")]


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


# ------------------------------------------------------------------------------------------ output

NODE_QUANTITIES = ("displacement", "velocity", "acceleration", "coordinates")
ELEMENT_QUANTITIES = ("stress", "von_mises", "pressure", "plastic_strain")
FIELD_NAMES = NODE_QUANTITIES + ELEMENT_QUANTITIES + ("density",)


class HistoryRequest(DeckModel):
    """A time history of nodal (mean over the nodes) or element (at the nearest element) quantities."""

    name: str = Field(description="Name of the CSV table written (histories/<name>.csv).")
    part: str | None = Field(None, description="Mean over the nodes of a part.")
    set: str | None = Field(None, description="Mean over the nodes of a set.")
    point: Vector | None = Field(
        None, description="The node nearest this point (element quantities: the element nearest it)."
    )
    quantities: list[Literal[NODE_QUANTITIES + ELEMENT_QUANTITIES]] = Field(
        default_factory=lambda: ["displacement", "velocity"],
        description="Quantities recorded. Default [displacement, velocity].",
    )

    @model_validator(mode="after")
    def _one_target(self) -> "HistoryRequest":
        given = [k for k in ("part", "set", "point") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError("@name: give exactly one of 'part', 'set' or 'point'")
        return self


class Output(DeckModel):
    """What is written, and how often."""

    interval: PositiveFloat | None = Field(
        None, description="Simulated time between field outputs to XDMF/HDF5 [time]. Default end_time/50."
    )
    history_interval: PositiveFloat | None = Field(
        None, description="Simulated time between history rows [time]. Default end_time/1000."
    )
    fields: list[Literal[FIELD_NAMES]] = Field(
        default_factory=lambda: list(FIELD_NAMES), description="Fields written to XDMF. Default all."
    )
    histories: list[HistoryRequest] = Field(default_factory=list, description="Requested time histories.")
