"""Deck keyword family ``parts``: each body's material, section and geometry (meshed or filled with
particles), ALE fills and solid erosion.
"""
from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from .base import DeckModel, PositiveFloat, NonNegativeFloat, Vector, exactly_one
from .shapes import BallGeometry, HalfSpace, PolygonGeometry, VolumeBox

__all__ = [
    "BoxGeometry",
    "RingGeometry",
    "CylinderGeometry",
    "FileGeometry",
    "GEOMETRY_KINDS",
    "MESH_KINDS",
    "PARTICLE_KINDS",
    "Geometry",
    "FillCylinder",
    "Fill",
    "Erosion",
    "Part",
]


class BoxGeometry(DeckModel):
    """A structured block of quad4 (2D) or hex8 (3D) elements between two corners."""

    min: Vector = Field(description="Lower corner [length].")
    max: Vector = Field(description="Upper corner [length].")
    divisions: list[Annotated[int, Field(ge=1)]] | None = Field(
        None, description="Elements per direction; or give element_size (solid parts; SPH parts use the part's spacing)."
    )
    element_size: PositiveFloat | None = Field(
        None, description="Target element edge length [length]; or give divisions."
    )

    @model_validator(mode="after")
    def _one_resolution(self) -> "BoxGeometry":
        if self.divisions is not None and self.element_size is not None:
            raise ValueError("@divisions: give only one of 'divisions' or 'element_size'")
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
    """A mesh read with meshio (Gmsh .msh, Abaqus .inp, VTU, STL, ...) or, for .k / .key / .dyn, as an
    LS-DYNA keyword file (*NODE, *ELEMENT_SOLID hexahedra, *ELEMENT_SHELL quadrilaterals for 2D, *PART,
    *SET_NODE_LIST; other keywords are ignored).

    Solid and ALE parts: its quad cells (2D) or hexahedra (3D) are the part's elements. SPH parts:
    its closed boundary, triangles and quads (3D, e.g. an STL surface) or line segments (2D), is
    filled with lattice particles (winding-number inside test).

    The file's named sets become node sets ``<part>.<set>`` that boundaries, initial conditions,
    nodal loads and histories can name: Abaqus NSET and ELSET, Gmsh physical groups (by their
    $PhysicalNames, else ``physical_<tag>``), and from LS-DYNA each *PART (its heading, else
    ``part_<pid>``) and each *SET_NODE_LIST (``set_<sid>``).
    """

    file: str = Field(description="Path, relative to the deck's folder.")
    scale: PositiveFloat = Field(1.0, description="Multiplies every coordinate. Default 1.")


GEOMETRY_KINDS = ("box", "ring", "cylinder", "file", "ball", "polygon")
MESH_KINDS = ("box", "ring", "cylinder", "file")
PARTICLE_KINDS = ("box", "ball", "polygon", "file")


class Geometry(DeckModel):
    """Exactly one shape: box, ring, cylinder or file for solid parts; box, ball or polygon for SPH parts."""

    box: BoxGeometry | None = Field(None, description="A block: structured elements, or particles (2D or 3D).")
    ring: RingGeometry | None = Field(None, description="A 2D annulus or disc of quad4.")
    cylinder: CylinderGeometry | None = Field(None, description="A 3D tube or solid cylinder of hex8.")
    file: FileGeometry | None = Field(None, description="A mesh read from a file.")
    ball: BallGeometry | None = Field(None, description="A disc (2D) or ball (3D) of particles.")
    polygon: PolygonGeometry | None = Field(None, description="A 2D polygon of particles.")

    @model_validator(mode="after")
    def _exactly_one(self) -> "Geometry":
        exactly_one(self, GEOMETRY_KINDS, "geometry")
        return self

    @property
    def kind(self) -> str:
        return next(k for k in GEOMETRY_KINDS if getattr(self, k) is not None)


class FillCylinder(DeckModel):
    """A circular cylinder (3D): points within `radius` of the axis line through `center`."""

    center: Vector = Field(description="A point on the axis, the middle of the cylinder [length].")
    radius: PositiveFloat = Field(description="Radius [length].")
    axis: Literal["x", "y", "z"] = Field("z", description="Axis direction. Default z.")
    length: PositiveFloat | None = Field(None, description="Length along the axis, centred on `center` [length]. Default unbounded.")


class Fill(DeckModel):
    """A region of an ALE part holding one material, at a given state."""

    material: str = Field(description="Name of a fluid or void material.")
    box: VolumeBox | None = Field(None, description="{min, max} box.")
    ball: BallGeometry | None = Field(None, description="A disc (2D) or sphere (3D).")
    cylinder: FillCylinder | None = Field(None, description="A cylinder (3D).")
    polygon: PolygonGeometry | None = Field(None, description="A 2D polygon.")
    half_space: HalfSpace | None = Field(None, description="A half-space.")
    density: PositiveFloat | None = Field(None, description="Initial density [mass/length^3]. Default the material's.")
    pressure: float | None = Field(None, description="Initial pressure [pressure]; the energy follows from the EOS. Default the EOS's e0.")
    velocity: Vector | None = Field(None, description="Initial velocity of the region's nodes [length/time]. Default 0.")

    @model_validator(mode="after")
    def _one_region(self) -> "Fill":
        exactly_one(self, ("box", "ball", "cylinder", "polygon", "half_space"), "region")
        return self


class Erosion(DeckModel):
    """Element erosion of a solid part: an eroded element is deactivated, its nodes keep their mass."""

    on_negative_volume: bool = Field(
        True, description="Erode an element whose volume (or Jacobian) becomes zero or negative. Default true."
    )
    max_plastic_strain: PositiveFloat | None = Field(
        None, description="Erode an element whose effective plastic strain exceeds this [-]. Default none."
    )
    min_time_step_ratio: Annotated[float, Field(gt=0, lt=1)] | None = Field(
        None, description="Erode an element whose stable time step falls below this fraction of the part's smallest "
        "initial element step (LS-DYNA *CONTROL_TERMINATION DTMIN with *CONTROL_TIMESTEP ERODE = 1): a crushed "
        "element of a soft body (a Lagrangian bird) no longer sets the whole model's step; its nodes keep their "
        "mass and stay contact slaves [-]. Default none."
    )


class Part(DeckModel):
    """A meshed body with one material and one section."""

    material: str = Field(description="Name of a material.")
    section: str = Field(description="Name of a section.")
    geometry: Geometry = Field(description="How the part is meshed.")
    rigid: bool = Field(
        False, description="Move as one rigid body (also implied by a material of type rigid). Default false."
    )
    spacing: PositiveFloat | None = Field(
        None, description="SPH parts: particle spacing dx on a square/cubic lattice [length]; mass = density dx^dimension."
    )
    hydrostatic: bool = Field(
        False, description="SPH parts: start at the hydrostatic density under the deck's gravity, free surface at the part's top. "
        "ALE parts: each fill of a fluid material starts at the hydrostatic pressure p = rho0 |g| (s - h) of its own free "
        "surface s (the top of the fill, measured against gravity; h the height of the element's part of the fill), "
        "its density from the EOS at that pressure; the part's own material is left at its state. Default false."
    )
    fill: list[Fill] = Field(
        default_factory=list,
        description="ALE parts: regions filled with other materials, in order (later ones win); the part's material fills the rest.",
    )
    erosion: Erosion | None = Field(
        None, description="Solid parts: delete (deactivate) elements that invert or exceed a plastic strain, and go on "
        "(LS-DYNA *MAT_ADD_EROSION). Default none: an inverted element stops the run."
    )
