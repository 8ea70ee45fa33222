"""ALE in r-z (``dimension: axisymmetric``): the ring geometry of the quad4 kernels.

The meridian plane holds x = r >= 0 and y = z (the axis). An element is the ring its quad sweeps
about the axis; every volume, mass, force and energy is for the full 2 pi. The plane quad4 kernels
``energy.lagrange_energy`` and ``remap.face_fluxes`` take the ring geometry (``ring_geometry``)
when called with ``ring`` True (one compiled form serves plane and r-z; the branch is per element or
face); the forces have their own kernel here, ``lagrange_forces_rz`` (the flagged plane kernel
measured slower; both take their shared parts from ``lagrange``), compiled, with ``ring_volumes``, only
for an axisymmetric mesh.

Formulation: volume-weighted, with the exact ring volume of the straight-sided quad
(Green's theorem over its four edges, i -> j = i + 1)

    V = 2 pi int r dA = (pi / 3) S,   S = sum_i (r_i + r_j)(r_i z_j - r_j z_i),

and element forces f_a = (p + q) dV/dx_a (the control-volume force of a pressure; Benson 1992
sec. 2 with the ring volume, LS-DYNA's volume-weighted axisymmetric form):

    dS/dr_a = 2 r_a (z_{a+1} - z_{a-1}) + r_{a+1} (z_{a+1} - z_a) + r_{a-1} (z_a - z_{a-1}),
    dS/dz_a = (r_{a-1} - r_{a+1}) (r_{a-1} + r_a + r_{a+1}).

The hoop stress of a pressure (sigma_tt = -p) is in dV/dr_a: it is the d(2 pi r)/dr part of the
ring volume's derivative. Why this form and not the area-weighted one (Caramana & Whalen 1998,
forces of the plane quad times the node radius): the forces are the exact derivative of the ring
volume, so with lumped ring masses m_I = sum_e M_e / 4 (fixed over the Lagrangian phase) the
compatible work W_e = -dt sum_a f_a . (v^{n-1/2} + v^{n+1/2}) / 2 equals the change of kinetic
energy and total energy is conserved to round-off; sum_a dS/dz_a = 0 (translation along the axis
leaves V unchanged), so axial momentum is conserved too. The area-weighted form keeps spherical
symmetry better on equal-angle meshes but its nodal masses change with the motion and its work
does not balance a ring kinetic energy exactly. Axis nodes (r = 0) slip along the axis (u_r = 0,
``AleSystem``), as the FEM axisymmetric solid's do (``fem.axisymmetric``, the same
volume-weighted choice, there with the one-point volume 2 pi r_c A; here the exact ring volume,
because the remap needs swept ring volumes that add up to the element's change of volume).

Viscosity: von Neumann-Richtmyer bulk viscosity with the divergence div v = (dV/dt) / V =
sum_a v_a . dV/dx_a / V (hoop rate included) and the plane length A / longest edge; Flanagan-Belytschko
viscous hourglass on the plane quad's gamma vectors, weighted by the ring length 2 pi r_bar = V / A.
Stable step: the plane length times min(1, |b| / |b_V|) (b the plane mean gradient, b_V = dV/dx / V,
norms over the four corners): the hoop term's stiffening, as the FEM form's factor
sqrt(|b|^2 / (|b|^2 + 1/(4 r_c^2))) (``fem.axisymmetric``); 1 far from the axis.

Remap: the volume a face sweeps from x_lag to x_new is the signed ring volume of the quad
(l0, w0, w1, l1); every edge term of S is shared, with opposite orientations, by the two regions
it bounds, so an element's swept ring volumes sum to its new minus its Lagrangian ring volume.
The mass and energy fluxes, and the dual (nodal momentum) remap built on those mass fluxes, are the
plane kernels' (``remap._face_flux``, ``dual``): they carry ring masses.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from .lagrange import (N_CHUNKS, _mixture_pressure, _quad_char_length, chunk_range, quad_corners, quad_hourglass, quad_scratch,
                       viscosity_and_step)
from .ring_geometry import PI_3, ring_gradient, ring_volume

TWO_PI = 2.0 * math.pi


@njit(parallel=True, cache=True)
def ring_volumes(x, conn, out):
    """Exact ring volume of every quad4 (E,) for the full 2 pi."""
    for e in prange(conn.shape[0]):
        n0, n1, n2, n3 = conn[e, 0], conn[e, 1], conn[e, 2], conn[e, 3]
        out[e] = ring_volume(x[n0, 0], x[n0, 1], x[n1, 0], x[n1, 1], x[n2, 0], x[n2, 1], x[n3, 0], x[n3, 1])


@njit(parallel=True, cache=True)
def lagrange_forces_rz(x, v, conn, vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q, mat_rho0, q1, q2, qhg,
                       phi_eps, pscale, pressure_cutoff, f_elem, pres_m, bulk_m, q_elem, dt_elem):
    """``lagrange.lagrange_forces`` on rings (its own kernel: the plane kernel with a ring flag measured
    slower, the comment there): f_a = (p_mix + q) dV/dx_a - hourglass (module docstring).

    Arguments and outputs as the plane kernel's; vol_m and mass_m are ring volumes and masses.
    """
    n_elem = conn.shape[0]
    n_chunks = min(n_elem, N_CHUNKS)
    for chunk in prange(n_chunks):
        start, stop = chunk_range(chunk, n_elem, n_chunks)
        xe, ve, b = quad_scratch()
        gv = np.empty((2, 4))
        for e in range(start, stop):
            vmax2, area = quad_corners(conn, e, x, v, xe, ve, b)
            vol = ring_gradient(xe, gv)
            p_mix, c_max, mtot = _mixture_pressure(e, vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q, mat_rho0, phi_eps,
                                                   pscale, pressure_cutoff, pres_m, bulk_m)
            rho_e = mtot / vol if vol > 0.0 else 0.0
            trace_d = 0.0
            bb = 0.0
            gg = 0.0
            for a in range(4):
                trace_d += ve[a, 0] * gv[0, a] + ve[a, 1] * gv[1, a]
                bb += b[0, a] * b[0, a] + b[1, a] * b[1, a]
                gg += gv[0, a] * gv[0, a] + gv[1, a] * gv[1, a]
            trace_d = trace_d / vol if vol > 0.0 else 0.0
            length = _quad_char_length(xe, area)
            if gg > 0.0 and vol > 0.0:
                length *= min(1.0, math.sqrt(bb / gg) * vol)  # |b| / |b_V|, b_V = gv / V
            q = viscosity_and_step(e, rho_e, length, c_max, trace_d, vmax2, q1, q2, q_elem, dt_elem)
            s = p_mix + q
            for a in range(4):
                f_elem[e, a, 0] = s * gv[0, a]
                f_elem[e, a, 1] = s * gv[1, a]
            if qhg > 0.0 and rho_e > 0.0 and area > 0.0:
                # the plane coefficient qhg rho c sqrt(A) / 4 times the ring length 2 pi r_bar = V / A
                quad_hourglass(e, xe, ve, b, 0.25 * qhg * rho_e * c_max * math.sqrt(area) * (vol / area), f_elem)


def quad_ring_volumes(p0, p1, p2, p3):
    """Signed ring volumes (numpy, (F,)) of the quads (p0, p1, p2, p3), corners each (F, 2): ``ring_volume`` on
    arrays (an element's, or the quad (l0, w0, w1, l1) a face sweeps)."""
    q = (p0, p1, p2, p3)
    s = np.zeros(len(p0))
    for i in range(4):
        a, b = q[i], q[(i + 1) % 4]
        s += (a[:, 0] + b[:, 0]) * (a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1])
    return PI_3 * s


def face_pressure_forces(x, n0, n1, p, f):
    """Nodal forces (added to f (N, 2)) of an outside pressure p (F,) on the ring faces (n0, n1) (owner
    orientation, outward normal (t_z, -t_r) / L with t = x1 - x0): on node a of a face,
    -p int 2 pi r N_a n dl = -p 2 pi n L (2 r_a + r_b) / 6 (linear shape functions along the face)."""
    t = x[n1] - x[n0]
    r0, r1 = x[n0, 0], x[n1, 0]
    for node, w in ((n0, (2.0 * r0 + r1)), (n1, (2.0 * r1 + r0))):
        c = p * (TWO_PI / 6.0) * w
        np.add.at(f[:, 0], node, -c * t[:, 1])
        np.add.at(f[:, 1], node, c * t[:, 0])
    return f
