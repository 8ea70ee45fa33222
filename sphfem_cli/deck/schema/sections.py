"""Deck keyword family ``sections``: how a part is discretised (Lagrangian solid elements, SPH
particles or multi-material ALE) and the numerical controls of each.
"""
from __future__ import annotations

from typing import Annotated, Literal, Union

from pydantic import Field, model_validator

from .base import DeckModel, NonNegativeFloat, PositiveFloat
from .shapes import VolumeBox

__all__ = [
    "Hourglass",
    "BulkViscosity",
    "SolidSection",
    "ViscositySwitch",
    "ArtificialViscosity",
    "SphSection",
    "AleSection",
    "Section",
]


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
    """Lagrangian solid elements: quad4 plane strain or plane stress (2D), ring quad4 (axisymmetric) or hex8
    (3D), one-point integration."""

    type: Literal["solid"] = Field(description="Section selector: Lagrangian solid elements.")
    formulation: Literal["plane_strain", "plane_stress"] = Field(
        "plane_strain", description="2D quad4 elements: plane_strain (eps_zz = 0, sigma_zz carried; a slice of a long "
        "body) or plane_stress (sigma_zz = 0, the thickness strain solved for; a thin plate loaded in its plane, "
        "like LS-DYNA's 2D plane-stress shell, *SECTION_SHELL ELFORM 12). Either way masses, forces and energies "
        "are per unit (initial) thickness; in plane stress the element's volume per unit initial thickness is "
        "its area times h/h0. plane_stress takes elastic, elastic_plastic and johnson_cook materials without an "
        "equation of state (the thickness strain solved so that sigma_zz = 0 after the return map; "
        "docs/theory/fem.md 'Plane stress') and only dimension 2 (not 3 or axisymmetric). Default plane_strain."
    )
    hourglass: Hourglass = Field(default_factory=Hourglass, description="Hourglass control.")
    bulk_viscosity: BulkViscosity = Field(default_factory=BulkViscosity, description="Shock viscosity.")


class ViscositySwitch(DeckModel):
    """Shock switch of the artificial viscosity (Morris & Monaghan 1997, with the source limited as Rosswog et al.
    2000): each particle carries its own alpha_i, d alpha_i/dt = -(alpha_i - alpha)/tau_i + max(-div v_i, 0)
    (alpha_max - alpha_i), tau_i = h_i/(decay c_i), from the section's alpha (the floor) towards alpha_max where
    the fluid is compressed; a pair uses alpha_ij = (alpha_i + alpha_j)/2 and beta_ij = (beta/alpha) alpha_ij.
    2D, 3D and axisymmetric; alpha_i is written as the particle field viscosity_alpha. docs/theory/sph.md,
    "Shock switch"."""

    alpha_max: PositiveFloat = Field(
        1.0, description="Ceiling alpha_max the source drives alpha_i towards (above the section's alpha). Default 1 "
        "(Monaghan's shock setting alpha 1; with beta = 2 alpha, beta_ij reaches 2 there)."
    )
    decay: Annotated[float, Field(gt=0, le=1)] = Field(
        0.1, description="Decay constant l of tau_i = h_i/(l c_i), the time alpha_i takes back to the floor (Morris "
        "& Monaghan 1997: 0.1-0.2; at l = 0.1, tau = 10 h/c, the time sound takes to cross 10 smoothing lengths). "
        "Default 0.1."
    )


class ArtificialViscosity(DeckModel):
    """Monaghan artificial viscosity Pi_ij = (-alpha c mu_ij + beta mu_ij^2)/rho for approaching pairs."""

    alpha: NonNegativeFloat = Field(
        0.1, description="Linear coefficient alpha; with a switch, the floor every particle starts at and decays to. "
        "Default 0.1."
    )
    beta: NonNegativeFloat = Field(
        0.0, description="Quadratic coefficient beta; with a switch, beta at the floor alpha: a pair's beta_ij = "
        "(beta/alpha) alpha_ij. Default 0."
    )
    epsilon: PositiveFloat = Field(0.01, description="Singularity guard eps in mu_ij = h v.r/(r^2 + eps h^2). Default 0.01.")
    switch: ViscositySwitch | None = Field(
        None, description="{alpha_max, decay}: a per-particle alpha_i raised at shocks and decaying behind them "
        "(Morris & Monaghan 1997). Default none (alpha and beta fixed)."
    )

    @model_validator(mode="after")
    def _switch_range(self) -> "ArtificialViscosity":
        if self.switch is not None:
            if self.alpha <= 0.0:
                raise ValueError("@alpha: a viscosity switch needs alpha > 0 (the floor alpha_i decays to; beta/alpha "
                                 "scales beta_ij)")
            if self.switch.alpha_max <= self.alpha:
                raise ValueError(f"@switch: alpha_max {self.switch.alpha_max:g} must exceed alpha {self.alpha:g}, the "
                                 "floor the switch raises alpha_i from")
        return self


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
    density_diffusion_form: Literal["molteni_colagrossi", "delta_plus"] = Field(
        "molteni_colagrossi", description="Form of the density diffusion: molteni_colagrossi, psi_ij = 2 (rho_j - rho_i) (Molteni & Colagrossi 2009), or delta_plus, psi_ij = 2 (rho_j - rho_i) + (G_i + G_j).r_ij with G the renormalised density gradient (Antuono, Colagrossi, Marrone & Molteni 2010), which vanishes for a linear density field also where the kernel is truncated (a free surface, a structure in contact) and replaces diffusion_hydrostatic; 2D and 3D only (an axisymmetric deck's error). Costs two more neighbour passes. docs/theory/sph.md. Default molteni_colagrossi."
    )
    diffusion_hydrostatic: bool = Field(
        True, description="Subtract the hydrostatic density difference in the density diffusion (Fourtakas-type), so that it does not smear a liquid at rest under gravity. Default true."
    )
    ghost_hydrostatic: bool = Field(
        True, description="Ghost particles carry the mirrored particle's pressure plus the hydrostatic increment rho g.(x_ghost - x); false is the paper's plain mirror, which leaves the rows next to a floor about 5 % low under gravity. Default true."
    )
    continuity: Literal["volume", "mass"] = Field(
        "volume", description="Form of the continuity equation: volume, drho_i/dt = rho_i sum_j V_j v_ij.grad W (the paper's form, suited to liquids and interfaces of unequal density), or mass, sum_j m_j v_ij.grad W (Monaghan 1992, the rate of the summation density), for gas with strong shocks: the volume form over-weights the light side of a strong density jump and drifts from the particles' volumes (the cylindrical Noh implosion's post-shock density overshoots and diverges with resolution; docs/theory/sph.md, Noh's implosion and the continuity form). In an axisymmetric deck mass is sum_j rho_j A_j v_ij.grad W with A_j = m_j/(2 pi r_j rho_j) the ring's area in the meridian plane (the hoop term -rho v_r/r in both forms): Noh's sphere converges with it (order 1.3) where the volume form over-compresses; an explosive's products take the renormalised continuity in both forms. Not for an interface of unequal density at equal spacing (particles of unequal mass), in r-z as in 2D: an 8:1 gas interface took the light side's density negative, while water and explosive products gave the same peaks as the volume form (docs/theory/sph.md 'Axisymmetric SPH'). Default volume."
    )
    xsph: float = Field(0.0, ge=0, le=1, description="XSPH velocity smoothing coefficient epsilon, 0 to 1 (Monaghan 1989 uses 0.5); 0 turns it off. Default 0.")
    pressure_cutoff: float | None = Field(
        None, description="Lowest pressure a particle may carry (cavitation) [pressure]. Default none."
    )
    domain: VolumeBox | None = Field(
        None, description="{min, max}: particles leaving this box are deactivated and counted (the only place "
        "SPH particles are deleted: walls mirror them back, non_reflecting sides move with the water). Default none."
    )


class AleSection(DeckModel):
    """Multi-material ALE (quad4 in 2D, hex8 in 3D): a Lagrangian phase on the mesh, then a remap back
    (Eulerian) or to a smoothed mesh, moving each material's volume, mass and energy across element
    faces. Every smoothing and smoothing boundary works in 2D, 3D and r-z (where axis nodes slide along
    the axis or stay fixed)."""

    type: Literal["ale_multi_material"] = Field(description="Section selector: multi-material ALE.")
    advection: Literal["donor_cell", "van_leer"] = Field(
        "van_leer", description="donor_cell (first order) or van_leer (second-order MUSCL). Default van_leer."
    )
    mesh_motion: Literal["eulerian", "lagrangian", "smoothed"] = Field(
        "eulerian", description="eulerian: the mesh returns to its start after each Lagrangian phase; lagrangian: no remap, the mesh moves with the material (no advection; no transmit or inflow sides); smoothed: the Lagrangian mesh relaxed by `smoothing` (LS-DYNA *CONTROL_ALE METH with AFAC/DFAC). Default eulerian."
    )
    smoothing: Literal["average", "equipotential", "straight_lines"] = Field(
        "average", description="smoothed meshes: average (each interior node towards the mean of its edge neighbours, LS-DYNA AFAC), equipotential (Winslow's equipotential point on the structured stencil of an interior node with four elements, eight in 3D, LS-DYNA DFAC; other nodes averaged) or straight_lines (the paper's variant: every node moves only along the straight mesh line through it along `line_axis`, the lines' end nodes with the material, the nodes inside a line kept at their initial parameter between its ends, like LS-DYNA *ALE_SMOOTHING; a structured mesh; smoothing_weight, smoothing_iterations and smoothing_boundary do not apply). Default average."
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
        "fixed", description="Boundary nodes of a smoothed mesh: fixed (Eulerian) or sliding: along straight sides in 2D and r-z (axis nodes along the axis), in 3D in the plane of a flat face of the boundary and along straight edges where two such faces meet; corners and nodes of curved boundary faces fixed. Default fixed."
    )
    advect_every: Annotated[int, Field(ge=1)] = Field(1, description="Remap every N steps. Default 1.")
    interface: Literal["slic", "donor"] = Field(
        "slic", description="Material-volume fluxes: slic (sharp interfaces, directional SLIC) or donor. Default slic."
    )
    closure: Literal["relax", "equal_strain"] = Field(
        "relax", description="Mixed elements: relax (pressure relaxation between materials; where a structure's coupling presses on an element, its void, the structure's own volume, keeps its equal-strain share and only the other materials relax) or equal_strain. Default relax."
    )
    hourglass: Annotated[float, Field(ge=0, le=0.12)] = Field(0.1, description="Viscous hourglass coefficient. Default 0.1.")
    timestep_scale: Annotated[float, Field(gt=0, le=1.0)] = Field(
        0.5, description="Fraction of the ALE element step l/(c + |v|) used (the remap needs it at most 1); the name solids, SPH and contacts use. Default 0.5, as verified on the shock tubes."
    )
    courant: Annotated[float, Field(gt=0, le=1.0)] | None = Field(
        None, description="Deprecated name of timestep_scale: still read (`sphfem check` warns); give one of the two."
    )
    bulk_viscosity: BulkViscosity = Field(default_factory=BulkViscosity, description="Shock viscosity.")
    pressure_cutoff: float | None = Field(
        None, description="Lowest pressure any ALE material may carry (cavitation; LS-DYNA *MAT_NULL PC) [pressure]. Default none (a fluid EOS may go into tension)."
    )

    @model_validator(mode="after")
    def _deprecated_courant(self) -> "AleSection":
        if self.courant is not None:
            if "timestep_scale" in self.model_fields_set:
                raise ValueError("@courant: courant is the deprecated name of timestep_scale; give only timestep_scale")
            self.timestep_scale = self.courant
        return self


Section = Annotated[Union[SolidSection, SphSection, AleSection], Field(discriminator="type")]
