"""Keyword families of the deck other than materials and equations of state.

One pydantic model per family; field descriptions are the deck reference's text
(docs/deck-reference.md is generated from them), so each states meaning, units and default.
"""
from __future__ import annotations

from typing import Annotated, Literal, Union

from pydantic import Field, model_validator

from .base import DeckModel, check_extent, exactly_one, NonNegativeFloat, OptionalComponents, PositiveFloat, Vector

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


class ArtificialViscosity(DeckModel):
    """Monaghan artificial viscosity Pi_ij = (-alpha c mu_ij + beta mu_ij^2)/rho for approaching pairs."""

    alpha: NonNegativeFloat = Field(0.1, description="Linear coefficient alpha. Default 0.1.")
    beta: NonNegativeFloat = Field(0.0, description="Quadratic coefficient beta. Default 0.")
    epsilon: PositiveFloat = Field(0.01, description="Singularity guard eps in mu_ij = h v.r/(r^2 + eps h^2). Default 0.01.")


class SphSection(DeckModel):
    """Smoothed particle hydrodynamics: the part is filled with particles at `spacing` (see parts)."""

    type: Literal["sph"] = Field(description="Section selector: SPH particles.")
    kernel: Literal["cubic_spline", "wendland_c2"] = Field("cubic_spline", description="Smoothing kernel. Default cubic_spline.")
    smoothing_ratio: Annotated[float, Field(gt=0.5, le=3.0)] = Field(
        1.2, description="Smoothing length over particle spacing, h/dx. Default 1.2."
    )
    artificial_viscosity: ArtificialViscosity = Field(
        default_factory=ArtificialViscosity, description="Monaghan artificial viscosity."
    )
    density_diffusion: float = Field(
        0.1, ge=0, le=1, description="delta-SPH density diffusion coefficient (Molteni & Colagrossi 2009), 0 to 1 (they use 0.1); 0 turns it off. Default 0.1."
    )
    diffusion_hydrostatic: bool = Field(
        True, description="Subtract the hydrostatic density difference in the density diffusion (Fourtakas-type), so that it does not smear a liquid at rest under gravity. Default true."
    )
    ghost_hydrostatic: bool = Field(
        True, description="Ghost particles carry the mirrored particle's pressure plus the hydrostatic increment rho g.(x_ghost - x); false is the paper's plain mirror, which leaves the rows next to a floor about 5 % low under gravity. Default true."
    )
    xsph: float = Field(0.0, ge=0, le=1, description="XSPH velocity smoothing coefficient epsilon, 0 to 1 (Monaghan 1989 uses 0.5); 0 turns it off. Default 0.")
    pressure_cutoff: float | None = Field(
        None, description="Lowest pressure a particle may carry (cavitation) [pressure]. Default none."
    )
    domain: VolumeBox | None = Field(
        None, description="{min, max}: particles leaving this box are deactivated and counted. Default none."
    )


class AleSection(DeckModel):
    """Multi-material ALE (quad4 in 2D, hex8 in 3D): a Lagrangian phase on the mesh, then a remap back
    (Eulerian) or to a smoothed mesh, moving each material's volume, mass and energy across element
    faces. In 3D a smoothed mesh takes smoothing average with fixed boundary nodes."""

    type: Literal["ale_multi_material"] = Field(description="Section selector: multi-material ALE.")
    advection: Literal["donor_cell", "van_leer"] = Field(
        "van_leer", description="donor_cell (first order) or van_leer (second-order MUSCL). Default van_leer."
    )
    mesh_motion: Literal["eulerian", "lagrangian", "smoothed"] = Field(
        "eulerian", description="eulerian: the mesh returns to its start after each Lagrangian phase; lagrangian: no remap, the mesh moves with the material (no advection; no transmit or inflow sides); smoothed: the Lagrangian mesh relaxed by `smoothing` (LS-DYNA *CONTROL_ALE METH with AFAC/DFAC). Default eulerian."
    )
    smoothing: Literal["average", "equipotential", "straight_lines"] = Field(
        "average", description="smoothed meshes: average (each interior node towards the mean of its edge neighbours, LS-DYNA AFAC), equipotential (Winslow's equipotential point on the four-element stencil, LS-DYNA DFAC; other nodes averaged; 2D only) or straight_lines (the paper's variant: every node moves only along the straight mesh line through it along `line_axis`, the lines' end nodes with the material, the nodes inside a line kept at their initial parameter between its ends, like LS-DYNA *ALE_SMOOTHING; a structured mesh; smoothing_weight, smoothing_iterations and smoothing_boundary do not apply). Default average."
    )
    line_axis: Literal["x", "y", "z"] = Field(
        "y", description="straight_lines smoothing: the axis the mesh lines run along (the lines' ends follow the material along it, e.g. a free surface). Default y."
    )
    smoothing_weight: Annotated[float, Field(ge=0, le=1)] = Field(
        0.5, description="Fraction of the way to the smoothing target each pass moves a node. Default 0.5."
    )
    smoothing_iterations: Annotated[int, Field(ge=1)] = Field(1, description="Smoothing passes per remap. Default 1.")
    eulerian_pull: Annotated[float, Field(ge=0, le=1)] = Field(
        0.2, description="After smoothing, fraction of the way back to its start each moving node goes (bounds the drift of a mesh in a steady stream; 0 for pure smoothing). Default 0.2."
    )
    smoothing_boundary: Literal["fixed", "sliding"] = Field(
        "fixed", description="Boundary nodes of a smoothed mesh: fixed (Eulerian) or sliding along straight sides (corners fixed). Default fixed."
    )
    advect_every: Annotated[int, Field(ge=1)] = Field(1, description="Remap every N steps. Default 1.")
    interface: Literal["slic", "donor"] = Field(
        "slic", description="Material-volume fluxes: slic (sharp interfaces, directional SLIC) or donor. Default slic."
    )
    closure: Literal["relax", "equal_strain"] = Field(
        "relax", description="Mixed elements: relax (pressure relaxation between materials) or equal_strain. Default relax."
    )
    hourglass: Annotated[float, Field(ge=0, le=0.12)] = Field(0.1, description="Viscous hourglass coefficient. Default 0.1.")
    courant: Annotated[float, Field(gt=0, le=1.0)] = Field(
        0.5, description="Fraction of the ALE element step l/(c + |v|) used (the remap needs it below 1). Default 0.5, as verified on the shock tubes."
    )
    bulk_viscosity: BulkViscosity = Field(default_factory=BulkViscosity, description="Shock viscosity.")
    pressure_cutoff: float | None = Field(
        None, description="Lowest pressure any ALE material may carry (cavitation; LS-DYNA *MAT_NULL PC) [pressure]. Default none (a fluid EOS may go into tension)."
    )


Section = Annotated[Union[SolidSection, SphSection, AleSection], Field(discriminator="type")]


# ------------------------------------------------------------------------------------------- parts


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
    """A mesh read with meshio (Gmsh .msh, Abaqus .inp, VTU, STL, ...).

    Solid and ALE parts: its quad cells (2D) or hexahedra (3D) are the part's elements. SPH parts:
    its closed boundary, triangles and quads (3D, e.g. an STL surface) or line segments (2D), is
    filled with lattice particles (winding-number inside test).
    """

    file: str = Field(description="Path, relative to the deck's folder.")
    scale: PositiveFloat = Field(1.0, description="Multiplies every coordinate. Default 1.")


class BallGeometry(DeckModel):
    """A disc (2D) or ball (3D) filled with particles."""

    center: Vector = Field(description="Centre [length].")
    radius: PositiveFloat = Field(description="Radius [length].")


class PolygonGeometry(DeckModel):
    """A closed 2D polygon filled with particles (even-odd rule)."""

    vertices: list[Annotated[list[float], Field(min_length=2, max_length=2)]] = Field(
        min_length=3, description="[[x0, y0], [x1, y1], ...] in order [length]."
    )


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


class HalfSpace(DeckModel):
    """The side of a plane the normal points away from: (x - point) . normal <= 0."""

    point: Vector = Field(description="A point on the plane [length].")
    normal: Vector = Field(description="Outward normal of the filled side [-].")

    @model_validator(mode="after")
    def _direction(self) -> "HalfSpace":
        if not any(self.normal):
            raise ValueError("@normal: a normal must not be the zero vector")
        return self


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


# -------------------------------------------------------------------------------------------- sets


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


# ---------------------------------------------------------------------------- boundaries and loads


class Target(DeckModel):
    """Exactly one of a part name or a set name."""

    part: str | None = Field(None, description="All nodes of this part.")
    set: str | None = Field(None, description="A node set (or the nodes of a segment set).")

    @model_validator(mode="after")
    def _one_target(self) -> "Target":
        exactly_one(self, ("part", "set"), "target", at="part")
        return self


Direction = Literal["x", "y", "z"]


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
    """Planar walls on sides of a box for SPH particles, modelled by ghost (mirror) particles.

    Ghosts carry the mirrored particle's density and pressure (the paper's method); "slip" mirrors
    the normal velocity, "no_slip" the whole velocity.
    """

    type: Literal["wall"] = Field(description="Boundary selector: SPH ghost-particle walls.")
    min: Vector = Field(description="Lower corner of the box whose sides are walls [length].")
    max: Vector = Field(description="Upper corner [length].")
    sides: list[Literal["left", "right", "bottom", "top", "back", "front"]] = Field(
        min_length=1, description="Which sides are walls: left/right (x), bottom/top (y), back/front (z)."
    )
    condition: Literal["slip", "no_slip"] = Field("slip", description="Tangential condition. Default slip.")

    @model_validator(mode="after")
    def _volume(self) -> "WallBoundary":
        check_extent(self.min, self.max, "the walls' box")
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
    or inflow of a material at a given state."""

    type: Literal["ale_boundary"] = Field(description="Boundary selector: sides of an ALE mesh.")
    part: str = Field(description="An ALE part.")
    sides: list[Literal["left", "right", "bottom", "top", "front", "back"]] = Field(
        min_length=1, description="Sides of the part's mesh (front and back: z-min and z-max, 3D)."
    )
    condition: Literal["slip", "fixed", "transmit", "inflow"] = Field(
        "slip", description="slip, fixed, transmit (open, zero gradient) or inflow (a ghost element outside, reset to the inflow state every step, is the donor of the advection through the side; the side's nodes move at `velocity`). Default slip."
    )
    material: str | None = Field(None, description="inflow: the entering material (fluid or high explosive; added to the part's materials if no fill holds it).")
    velocity: Vector | None = Field(None, description="inflow: velocity of the side's nodes [length/time] (on a slip wall only its tangential part).")
    density: PositiveFloat | None = Field(None, description="inflow: density of the entering material [mass/length^3]. Default the material's.")
    pressure: float | None = Field(None, description="inflow: pressure of the entering material [pressure]; the energy follows from the EOS. Default the EOS's e0.")
    energy: float | None = Field(None, description="inflow: specific internal energy of the entering material [energy/mass]; or give pressure.")

    @model_validator(mode="after")
    def _inflow_state(self) -> "AleBoundary":
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

    @model_validator(mode="after")
    def _needs(self) -> "Probe":
        if self.type == "pressure" and self.point is None:
            raise ValueError("@point: a pressure probe needs 'point'")
        if self.type == "surface_height" and self.gauge is None:
            raise ValueError("@gauge: a surface_height probe needs 'gauge'")
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
    probes: list[Probe] = Field(default_factory=list, description="SPH probes, written as histories.")
