"""Deck keyword family ``boundaries``: kinematic conditions on nodes and rigid parts, SPH walls
(ghost and dummy particles) and the sides of ALE meshes.
"""
from __future__ import annotations

from typing import Annotated, Literal, Union

from pydantic import Field, model_validator

from .base import DeckModel, OptionalComponents, PositiveFloat, Vector, check_extent, exactly_one
from .shapes import BallGeometry, PolygonGeometry, VolumeBox

__all__ = [
    "Target",
    "Direction",
    "FixedBoundary",
    "SymmetryBoundary",
    "PrescribedVelocity",
    "WallBoundary",
    "DummyWallBoundary",
    "WallRegion",
    "AleBoundary",
    "Boundary",
]


class Target(DeckModel):
    """Exactly one of a part name or a set name."""

    part: str | None = Field(None, description="All nodes of this part.")
    set: str | None = Field(None, description="A node set (or the nodes of a segment set). A set holding every "
                            "node of one rigid part and nothing else is that part; one holding only some of a rigid "
                            "part's nodes is an error (a rigid body moves as one: name it by `part`).")

    @model_validator(mode="after")
    def _one_target(self) -> "Target":
        exactly_one(self, ("part", "set"), "target", at="part")
        return self


Direction = Literal["x", "y", "z"]
# a wall boundary's sides: name -> (axis, 0 at its min / 1 at its max, +1 when the fluid lies above the plane)
BOX_FACES = {"left": (0, 0, 1), "right": (0, 1, -1), "bottom": (1, 0, 1), "top": (1, 1, -1),
             "back": (2, 0, 1), "front": (2, 1, -1)}


class FixedBoundary(Target):
    """Zero velocity in the listed directions (LS-DYNA *BOUNDARY_SPC).

    On a rigid part it holds the body's translation in those directions; fixed in every direction,
    the body is held entirely (no rotation either). With hold_rotation the body's rotation is held
    as well, e.g. directions [x] leaves a 2D body one degree of freedom, translation in y.
    """

    type: Literal["fixed"] = Field(description="Boundary selector: fixed directions.")
    directions: list[Direction] | None = Field(
        None, description="Fixed directions. Default all directions of the deck's dimension."
    )
    hold_rotation: bool = Field(
        False, description="Rigid parts only (given by part): hold the body's rotation too (no spin), whatever the "
        "directions. Default false: a rigid body turns freely unless every direction is fixed."
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


class WallBoundary(DeckModel):
    """Planar walls on sides of a box for SPH particles, modelled by ghost (mirror) particles, or
    non-reflecting open sides.

    Ghosts carry the mirrored particle's density and pressure (the paper's method); "slip" mirrors
    the normal velocity, "no_slip" the whole velocity. A "non_reflecting" side is open: its ghosts are
    images that move with their particles (the side moves with the water; nothing leaves through it)
    and carry the copied velocity and the impedance condition's pressure (the ALE solver's
    `non_reflecting`, docs/theory/sph.md "Non-reflecting open sides").
    """

    type: Literal["wall"] = Field(description="Boundary selector: SPH ghost-particle walls.")
    min: Vector = Field(description="Lower corner of the box whose sides are walls [length].")
    max: Vector = Field(description="Upper corner [length].")
    sides: list[Literal["left", "right", "bottom", "top", "back", "front"]] = Field(
        min_length=1, description="Which sides are walls: left/right (x), bottom/top (y), back/front (z)."
    )
    condition: Literal["slip", "no_slip", "wall_function", "non_reflecting"] = Field(
        "slip", description="Tangential condition: slip (mirror of the normal velocity), no_slip (the whole "
        "velocity mirrored: the artificial viscosity acts on the wall over the kernel support), wall_function "
        "(slip ghosts plus the smooth-wall law's shear rho u_tau^2 on the first particle layer, from the "
        "material's viscosity; none for an inviscid one), non_reflecting (no wall: an open side; its ghosts are "
        "images of the particles that start within a kernel support of it, each at its particle's position plus "
        "twice the particle's initial distance from the side, outwards, so that they move with their particles, "
        "and carry their velocity and the pressure p_far + rho c u_n, p_far the pressure the source particle "
        "started with plus the hydrostatic increment: a plane acoustic wave leaves at normal incidence without "
        "reflection, Lysmer & Kuhlemeyer 1969, as the ALE solver's non_reflecting sides. The side moves with "
        "the water: no particle leaves or enters through it, and the fluid may drift past the side's initial "
        "plane by the water's displacement there; only the section's domain, if set, deletes particles. For "
        "waves and transients, not a steady current through the side). Default slip.")
    source: Vector | None = Field(
        None, description="non_reflecting: the centre of the waves the side lets out (a charge's centre) [length]. "
        "With it the ghosts' pressure is p_far + rho c u_r - k (c / r) int (p - p_far) dt, r and u_r the distance "
        "from the source and the radial velocity at the ghost, the integral the source particle's pressure excess "
        "since t = 0, k = 1/2 in plane 2D (a cylindrical wave), 1 in 3D (Bayliss & Turkel 1980): the side absorbs "
        "such a wave at any incidence. Default none: a plane wave at normal incidence.")

    @model_validator(mode="after")
    def _volume(self) -> "WallBoundary":
        check_extent(self.min, self.max, "the walls' box")
        if self.source is not None and self.condition != "non_reflecting":
            raise ValueError("@source: only non_reflecting sides take 'source'")
        return self


class DummyWallBoundary(DeckModel):
    """Fixed dummy wall particles for SPH (Adami, Hu & Adams 2012): walls of any shape.

    Either layers of particles outside sides of a box (`min`, `max`, `sides`, as a ghost `wall`),
    or a region filled with wall particles (`region`: a box, ball or polygon). The wall particles
    take part in the fluid's sums; their pressure is extrapolated from the fluid around them
    (with gravity), their velocity is zero (no-slip for viscous terms).
    """

    type: Literal["dummy_wall"] = Field(description="Boundary selector: SPH dummy wall particles.")
    min: Vector | None = Field(None, description="Box sides mode: lower corner of the box [length].")
    max: Vector | None = Field(None, description="Box sides mode: upper corner [length].")
    sides: list[Literal["left", "right", "bottom", "top", "back", "front"]] | None = Field(
        None, description="Box sides mode: which sides get wall layers outside the box."
    )
    region: "WallRegion | None" = Field(None, description="Region mode: {box | ball | polygon} filled with wall particles.")
    layers: int = Field(3, ge=1, le=10, description="Box sides mode: particle layers (cover the kernel support 2h). Default 3.")
    spacing: PositiveFloat | None = Field(None, description="Wall particle spacing [length]. Default the smallest SPH part spacing.")

    @model_validator(mode="after")
    def _one_mode(self) -> "DummyWallBoundary":
        box_mode = [k for k in ("min", "max", "sides") if getattr(self, k) is not None]
        if self.region is None and len(box_mode) != 3:
            raise ValueError("@type: give 'min', 'max' and 'sides' (layers outside a box) or 'region'")
        if self.region is not None and box_mode:
            raise ValueError(f"@{box_mode[0]}: give either 'region' or 'min'/'max'/'sides', not both")
        check_extent(self.min, self.max, "the walls' box")
        return self


class WallRegion(DeckModel):
    """A region filled with dummy wall particles."""

    box: VolumeBox | None = Field(None, description="{min, max} box.")
    ball: BallGeometry | None = Field(None, description="A disc (2D) or ball (3D).")
    polygon: PolygonGeometry | None = Field(None, description="A 2D polygon.")

    @model_validator(mode="after")
    def _one_region(self) -> "WallRegion":
        exactly_one(self, ("box", "ball", "polygon"), "region")
        return self


DummyWallBoundary.model_rebuild()


class AleBoundary(DeckModel):
    """A condition on sides of an ALE part's mesh: slip wall, fixed (no-slip) wall, transmitting outflow,
    non-reflecting (impedance) side, or inflow of a material at a given state."""

    type: Literal["ale_boundary"] = Field(description="Boundary selector: sides of an ALE mesh.")
    part: str = Field(description="An ALE part.")
    sides: list[Literal["left", "right", "bottom", "top", "front", "back"]] = Field(
        min_length=1, description="Sides of the part's mesh (front and back: z-min and z-max, 3D)."
    )
    condition: Literal["slip", "fixed", "transmit", "non_reflecting", "inflow"] = Field(
        "slip", description="slip, fixed, transmit (open, zero gradient: the inside pressure acts from outside), non_reflecting (open as transmit, and the outside pressure is the side's initial pressure plus rho c times the outward normal velocity, Lysmer & Kuhlemeyer 1969, LS-DYNA *BOUNDARY_NON_REFLECTING: a plane acoustic wave leaves at normal incidence without reflection) or inflow (a ghost element outside, reset to the inflow state every step, is the donor of the advection through the side; the side's nodes move at `velocity`). Default slip."
    )
    source: Vector | None = Field(None, description="non_reflecting: the centre of the waves the side lets out (a charge's centre) [length]. With it the side absorbs a spherical wave from that point (3D, axisymmetric; a cylindrical one in plane 2D) at any incidence, its near field and after-flow included: p = p_far + rho c u_r - k (c / r) int (p - p_far) dt, k = 1 (1/2 in plane 2D). Default none: a plane wave at normal incidence.")
    material: str | None = Field(None, description="inflow: the entering material (fluid or high explosive; added to the part's materials if no fill holds it).")
    velocity: Vector | None = Field(None, description="inflow: velocity of the side's nodes [length/time] (on a slip wall only its tangential part).")
    density: PositiveFloat | None = Field(None, description="inflow: density of the entering material [mass/length^3]. Default the material's.")
    pressure: float | None = Field(None, description="inflow: pressure of the entering material [pressure]; the energy follows from the EOS. Default the EOS's e0.")
    energy: float | None = Field(None, description="inflow: specific internal energy of the entering material [energy/mass]; or give pressure.")

    @model_validator(mode="after")
    def _inflow_state(self) -> "AleBoundary":
        if self.source is not None and self.condition != "non_reflecting":
            raise ValueError("@source: only non_reflecting boundaries take 'source'")
        keys = ("material", "velocity", "density", "pressure", "energy")
        if self.condition != "inflow":
            for key in keys:
                if getattr(self, key) is not None:
                    raise ValueError(f"@{key}: only inflow boundaries take '{key}'")
            return self
        for key in ("material", "velocity"):
            if getattr(self, key) is None:
                raise ValueError(f"@{key}: an inflow boundary needs '{key}'")
        if self.pressure is not None and self.energy is not None:
            raise ValueError("@energy: give only one of 'pressure' or 'energy'")
        return self


Boundary = Annotated[
    Union[FixedBoundary, SymmetryBoundary, PrescribedVelocity, WallBoundary, DummyWallBoundary, AleBoundary],
    Field(discriminator="type"),
]
