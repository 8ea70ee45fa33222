"""Contacts and couplings: how fluids and structures push on each other.

`contacts` are penalty contacts with points as slaves (SPH particles or the nodes of a solid part)
and the outer faces of a solid part as master segments (LS-DYNA *CONTACT_AUTOMATIC_NODES_TO_SURFACE).
`couplings` join an ALE fluid to a Lagrangian structure (LS-DYNA *CONSTRAINED_LAGRANGE_IN_SOLID,
penalty form), or an SPH fluid to a structure by boundary particles the structure carries (``sph_boundary``).
"""
from __future__ import annotations

from typing import Annotated, Literal, Union

from pydantic import Field

from .base import DeckModel, NonNegativeFloat, PositiveFloat

__all__ = ["NodesToSurface", "LagrangeInSolid", "SphBoundary", "Contact", "Coupling"]


class NodesToSurface(DeckModel):
    """Penalty contact: slave points (particles or nodes) against master segments."""

    type: Literal["nodes_to_surface"] = Field(description="Contact selector: nodes (or SPH particles) to surface.")
    nodes: str = Field(description="Slave side: an SPH part (its particles), a solid part (its nodes) or a node set.")
    surface: str = Field(
        description="Master side: a solid or rigid part (its outer faces) or a segment set."
    )
    thickness: PositiveFloat | None = Field(
        None, description="Contact distance from the master surface at which the slave is pushed back [length]. "
        "Default half the particle spacing for SPH slaves, 0.1 of the master's smallest element edge for node slaves."
    )
    stiffness: Literal["penalty", "soft_constraint"] = Field(
        "penalty", description="penalty: k = penalty_scale K A^2/V (3D) or K L^2/A (2D) from the master element's "
        "bulk modulus K (the run's time step is bounded by the contact spring's stable step); soft_constraint: "
        "k = soft_scale m / dt0^2 from the first step and the reduced mass m of the slave and the master segment's "
        "lightest node, for a soft slave against a stiff "
        "master (water on steel, a rigid body): it never shortens the step. Default penalty."
    )
    penalty_scale: PositiveFloat = Field(0.1, description="Scale of the penalty stiffness [-]. Default 0.1.")
    soft_scale: PositiveFloat = Field(0.1, description="Scale of the soft-constraint stiffness [-]. Default 0.1.")
    damping: NonNegativeFloat = Field(
        0.1, le=1.0, description="Viscous contact damping, fraction of critical for the slave's mass [-] (LS-DYNA's VDC "
        "as a fraction). It damps the contact spring's own oscillation, which an undamped penalty turns into "
        "spurious energy. Default 0.1."
    )
    friction: NonNegativeFloat = Field(0.0, description="Coulomb friction coefficient [-]. Default 0 (frictionless).")


class LagrangeInSolid(DeckModel):
    """Penalty coupling of an ALE fluid to the faces of a Lagrangian structure."""

    type: Literal["lagrange_in_solid"] = Field(description="Coupling selector: ALE fluid to structure.")
    structure: str = Field(description="The structure: a solid or rigid part (its outer faces) or a segment set.")
    fluid: str = Field(description="The ALE part.")
    materials: list[str] | None = Field(
        None, description="Fluid materials that couple. Default all non-void materials of the ALE part."
    )
    nquad: int = Field(2, ge=1, le=16, description=(
        "Coupling points per segment direction [-] (nquad per 2D segment, nquad x nquad per 3D face). Keep at "
        "least one per fluid element along the face (n = h / l >= 1, l = segment length / nquad): below, the fluid "
        "passes between the points (`sphfem check` warns); refine nquad or the structure with the fluid (nquad doubled with each halving of h keeps n). Default 2, at most 16."))
    min_fraction: float = Field(
        0.5, gt=0.0, le=1.0, description="Fluid volume fraction from which an ALE element couples [-]. Default 0.5."
    )
    pfac: PositiveFloat | Literal["auto"] = Field("auto", description=(
        "Scale of the penalty stiffness from the fluid's bulk modulus [-]: k = pfac K l^2 / V per coupling point "
        "(LS-DYNA's PFAC; l the point's share of the segment, V the host element's area; 3D: k = pfac K A^2 / V, "
        "A the point's share of the face's area, V the host's volume; axisymmetric: A = 2 pi r l the point's ring, "
        "V the host's ring volume, forces for the full 2 pi). The penalty acts as an extra fluid layer "
        "L_c = n h / pfac (h the fluid element size, n = h / l the coupling points per fluid-element face; 3D: "
        "L_c = n^2 h / pfac, n = h / sqrt(A)); pfac >= 2 n (3D: 2 n^2) keeps L_c below h/2 (`sphfem check` "
        "prints L_c and warns above h/2). auto: pfac = 2 n (3D: 2 n^2) with n the median over the wetted faces of "
        "the initial geometry, so that L_c = h/2 there (docs/theory/coupling.md, 'Stiffness'; LS-DYNA's default "
        "0.1 is a layer of 10 n h here, which lets a structure sink into the fluid and the fluid's load lag). "
        "Default auto."))
    damping: NonNegativeFloat = Field(
        0.0, le=1.0, description="Viscous coupling damping, fraction of critical [-]. Default 0."
    )
    leakage_control: bool = Field(
        True, description="Push back fluid found behind the structure's surface (LS-DYNA ILEAK). Default true."
    )


class SphBoundary(DeckModel):
    """SPH fluid on a structure through dummy boundary particles carried by the structure's wetted faces."""

    type: Literal["sph_boundary"] = Field(description=(
        "Coupling selector: SPH fluid to structure by boundary (dummy) particles the structure carries (Adami, Hu & "
        "Adams 2012 pressure with the wall's acceleration; DualSPHysics' boundary particles of a floating or driven "
        "body). Layers of particles at the fluid's spacing lie inside the structure along each outer face, tied to "
        "the face's nodes; each interacts only with fluid on its face's side, and the fluid's forces on them are "
        "scattered to the nodes. 2D plane models only for now (3D and axisymmetric decks are refused)."))
    structure: str = Field(description="The structure: a solid or rigid part (its outer faces) or a segment set.")
    fluid: str = Field(description="The SPH part.")
    layers: int | None = Field(None, ge=1, le=8, description=(
        "Layers of boundary particles behind each face [-]. Default enough to cover the kernel support: "
        "ceil(2 h / dx), 3 for the cubic spline at h/dx = 1.2."))
    condition: Literal["no_slip", "slip"] = Field("no_slip", description=(
        "The artificial viscosity between fluid and boundary particles: no_slip takes the face's velocity, slip only "
        "its normal component (the tangential relative velocity is dropped). Default no_slip."))
    wall_acceleration: bool = Field(False, description=(
        "Use the nodes' accelerations (from their last two velocities) in the boundary pressure p_w = (sum p_f W + "
        "(g - a_w) . sum rho_f r_wf W) / sum W. Off by default: on the paper's section 4.1 plate (4 x 60 "
        "elements, dx 5 mm) the nodes' step-to-step accelerations made the run blow up within 23 steps; "
        "off, a_w = 0 and only gravity enters."))
    corner_particles: Literal["per_face", "once"] = Field("per_face", description=(
        "Behind a convex corner the layers of the two faces overlap (a square of layers x layers particles that "
        "coincide). per_face: every particle counts for the fluid on its face's side, so the fluid diagonal to the "
        "corner, on both sides, sees the square twice and a uniform pressure pushes it out of the corner. once: "
        "a fluid point that sees k coincident particles (within dx / 4 at the start) weighs each by 1 / k, so "
        "the kernel sum with the boundary is complete there too (a uniform pressure exerts no net force on a "
        "lattice). Default per_face (measured on the paper's section 4.1 plate: "
        "docs/studies/structure_in_water.md, \"Convex corners\")."))
    sampling: Literal["face", "arc_length"] = Field("face", description=(
        "How each row of boundary particles is spaced along the structure's outline. face: round(L / dx) particles "
        "per face (at least one), evenly on the face, so the wall's spacing L / round(L / dx) is not dx where a face "
        "is not a whole number of spacings (0.75 / 1.0 / 1.25 / 0.75 dx on 2.5 mm faces at dx 3.33 / 2.5 / 2 / 1.67 "
        "mm) and does not refine with the fluid. arc_length: each run of faces between corners (a turn of more than 30 "
        "degrees) gets round(L_run / dx) particles every L_run / n ~ dx, measured from the run's first corner, each "
        "on the face that holds it, of mass rho_0 (L_run / n) dx. Default face (arc_length measured on the paper's "
        "section 4.1 plate: docs/studies/structure_in_water.md, \"The wall's sampling refined with the water\")."))
    extrapolation: Literal["adami", "mdbc"] = Field("adami", description=(
        "How the boundary particles' pressure and density are set from the fluid. adami: p_w = (sum_f p_f W_wf + "
        "(g - a_w) . sum_f rho_f (x_w - x_f) W_wf) / sum_f W_wf over the fluid on the particle's face's side (Adami, "
        "Hu & Adams 2012, J. Comput. Phys. 231, 7057, eq. 27), rho_w from the EOS. mdbc: the modified dynamic boundary "
        "condition (English et al. 2022, Comp. Part. Mech. 9, 1): each particle's ghost node x_g is its mirror through "
        "its face (x_f + d n), or through the convex vertex (2 x_v - x_w) for the particles behind a corner where two "
        "faces' layers coincide; the fluid's density there and its gradient G solve the first-order (Liu & Liu 2006) "
        "system sum m_j W_gj = rho_g sum V_j W_gj + G . sum V_j r_j W_gj, sum m_j grad W_gj = rho_g sum V_j grad W_gj + "
        "(sum V_j grad W_gj r_j^T) G (r_j = x_j - x_g; a 3 x 3 system in 2D, exact for a linear density), and "
        "rho_w = rho_g + G . (x_w - x_g), p_w = p_eos(rho_w) (the Shepard density sum m W / sum V W where the "
        "ghost's support cannot carry a gradient: the system, scaled by h, has an infinity-norm condition number "
        "above 50 or sum V W < 0.1, e.g. ghosts above a free surface). Default adami (mdbc measured on the paper's "
        "section 4.1 plate, where it does not change the peak's amplitude dependence: "
        "docs/studies/structure_in_water.md, \"mDBC at the corners\")."))


Contact = Annotated[Union[NodesToSurface], Field(discriminator="type")]
Coupling = Annotated[Union[LagrangeInSolid, SphBoundary], Field(discriminator="type")]
