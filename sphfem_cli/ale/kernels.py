"""Multi-material ALE (operator split) on quad4 and hex8 meshes: the numba kernels, by phase.

State (per element e, material m, extensive so that conservation is a matter of bookkeeping):
``vol_m[e, m]`` material volume, ``mass_m[e, m]`` material mass, ``ener_m[e, m]`` material
internal energy (energy, not per unit mass). Volume fraction phi_m = vol_m / sum_k vol_k,
density rho_m = mass_m / vol_m, specific internal energy e_m = ener_m / mass_m. Nodes carry the
velocity v (half-step, central difference) and the lumped mass m_I = sum_e M_e / 4.

One step (paper section 2, eqs. 2.5-2.8; Benson 1992):

1. ``lagrange_forces``: per element, each material's pressure from its EOS at its own density and
   energy; mixture stress sigma = -sum_m phi_m p_m (volume-weighted, the paper's mixture theory);
   bulk viscosity q (von Neumann-Richtmyer, linear + quadratic) and Flanagan-Belytschko viscous
   hourglass forces; element forces f_eI = V (p + q) b_I - hourglass; stable dt.
2. ``nodal_update``: gather of the element forces, v^{n+1/2} = v^{n-1/2} + dt f / m (eq. 2.7),
   velocity boundary conditions with the reaction impulse recorded.
3. ``lagrange_energy``: the work of the element forces over the step,
   W_e = -dt sum_I f_eI . (v_I^{n-1/2} + v_I^{n+1/2}) / 2 (compatible form: kinetic plus internal
   energy is conserved to round-off), the new Lagrangian volume at x + dt v^{n+1/2}, and the
   mixed-cell closure: the volume change split between materials (equal strain, or pressure
   relaxation), each material receiving its own -p_m dV_m plus its mass share of the remainder
   of W_e (viscous and hourglass work).
4. Remap (``face_fluxes``, ``apply_face_fluxes``, ``dual_fluxes``, ``apply_dual_fluxes``,
   ``finish_remap``): directional sweeps (order alternating each step) through the faces of one
   logical direction; the face flux of volume is the signed area swept by the face from its
   Lagrangian to its remapped position; material volumes split by a directional SLIC
   (Noh & Woodward 1976) or by donor fractions; mass and energy by donor-cell or van Leer (1977)
   MUSCL values; nodal momentum remapped on the dual mesh (half-index shift, Benson 1992 sec. 5.4)
   with the same mass fluxes, and the kinetic energy lost by the remap returned to the elements
   (DeBar's fix) so that total energy is conserved.

3D (hex8): the same steps. The node kernels (``nodal_update``, ``finish_remap_nodes``) and the energy
kernel (``lagrange_energy``) are each one inline body compiled twice, for quad4 and for hex8
(``*_3d``), with the corner count and dimension as literal constants; the force kernels stay one per
geometry (plane ``lagrange_forces``, ring ``axisymmetric.lagrange_forces_rz``, ``lagrange_forces_3d``)
and share their parts. ``face_fluxes`` serves quad4, ring and hex8 meshes (a branch per face on the
swept volume; the flux itself is the shared ``_face_flux``), and the r-z ring is the ``ring`` flag
of the quad4 energy and face kernels. The mixture state, closure, face flux of a given swept volume
(``_mixture_pressure``, ``_closure_energy``, ``_face_flux``), the velocity conditions (``apply_bc``)
and the element-face, dual-mesh and nodal-mass kernels are shared (their loops take the corner count
and dimension from the arrays). Measured forms and figures: the comments above the kernels. The
kernels live in ``lagrange`` (steps 1-2; its plane force kernel's vectorised passes in ``force_lanes``, the
hex8 one's in ``hex_lanes``, which also computes blocks of hex8 and swept volumes),
``energy`` (step 3), ``remap`` (step 4, element side; its one-material face fluxes' vectorised block in
``face_lanes``) and ``dual`` (step 4, nodal momentum on the dual mesh);
this module names them together. Where nothing moves the remap skips work with the same bits: faces that
sweep no volume are flagged (``face_fluxes``' flow) and their elements skipped by ``apply_face_fluxes``;
elements through which no mass crosses write and read no dual fluxes (``dual_fluxes``' moving).

Every parallel loop is a gather: faces write face arrays, elements their own rows, nodes their
own entries. Equations and references: docs/theory/ale.md.
"""
from __future__ import annotations

from .dual import G_KIN, G_MASS, G_MOM, apply_dual_fluxes, dual_fluxes, node_velocities
from .energy import CLOSURE_EQUAL_STRAIN, CLOSURE_RELAX, element_volumes_3d, lagrange_energy, lagrange_energy_3d
from .lagrange import (BC_FIXED, BC_FREE, BC_LINE, BC_SLIP, BC_VELOCITY, RHO_CAVITATED, RHO_VOID, apply_bc,
                       lagrange_forces, lagrange_forces_3d, material_state, nodal_update, nodal_update_3d, quad_area)
from .remap import (IFACE_DONOR, IFACE_SLIC, SLIC_JUMP, apply_face_fluxes, face_fluxes, swept_volume_3d,
                    swept_volumes_3d, van_leer)
from .remap_nodes import (add_column_sums, finish_remap_elements, finish_remap_nodes, finish_remap_nodes_3d,
                          nodal_mass, remap_nodal_state)

__all__ = [
    "BC_FIXED", "BC_FREE", "BC_LINE", "BC_SLIP", "BC_VELOCITY", "CLOSURE_EQUAL_STRAIN", "CLOSURE_RELAX",
    "G_KIN", "G_MASS", "G_MOM", "IFACE_DONOR", "IFACE_SLIC", "RHO_CAVITATED", "RHO_VOID", "SLIC_JUMP",
    "add_column_sums", "apply_bc", "apply_dual_fluxes", "apply_face_fluxes", "dual_fluxes",
    "element_volumes_3d",
    "face_fluxes", "finish_remap_elements", "finish_remap_nodes", "finish_remap_nodes_3d",
    "lagrange_energy", "lagrange_energy_3d", "lagrange_forces", "lagrange_forces_3d", "material_state",
    "nodal_mass", "nodal_update", "nodal_update_3d", "node_velocities", "quad_area", "remap_nodal_state",
    "swept_volume_3d", "swept_volumes_3d", "van_leer",
]
