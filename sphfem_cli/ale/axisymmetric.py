"""ALE in r-z (``dimension: axisymmetric``): the quad4 kernels whose geometry is the ring, not the plane.

The meridian plane holds x = r >= 0 and y = z (the axis). An element is the ring its quad sweeps
about the axis; every volume, mass, force and energy is for the full 2 pi. Imported only by an
axisymmetric ``AleSystem``: a plane or 3D mesh compiles none of these kernels.

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

from ..fem.geometry import QUAD_GAMMA, bulk_viscosity, quad4_gradient, stable_dt
from .lagrange import _closure_energy, _mixture_pressure, _quad_char_length
from .remap import _face_flux

PI_3 = math.pi / 3.0
TWO_PI = 2.0 * math.pi


@njit(cache=True, inline="always")
def ring_volume(r0, z0, r1, z1, r2, z2, r3, z3):
    """Signed ring volume 2 pi int r dA of the quad (0, 1, 2, 3) (counter-clockwise positive): (pi/3) S."""
    s = (r0 + r1) * (r0 * z1 - r1 * z0)
    s += (r1 + r2) * (r1 * z2 - r2 * z1)
    s += (r2 + r3) * (r2 * z3 - r3 * z2)
    s += (r3 + r0) * (r3 * z0 - r0 * z3)
    return PI_3 * s


@njit(cache=True, inline="always")
def ring_gradient(x, g):
    """dV/dx_a (2, 4) of the ring volume of the quad with corners x (4, 2) (module docstring); returns V."""
    for a in range(4):
        nxt = (a + 1) % 4
        prv = (a + 3) % 4
        ra, za = x[a, 0], x[a, 1]
        rn, zn = x[nxt, 0], x[nxt, 1]
        rp, zp = x[prv, 0], x[prv, 1]
        g[0, a] = PI_3 * (2.0 * ra * (zn - zp) + rn * (zn - za) + rp * (za - zp))
        g[1, a] = PI_3 * (rp - rn) * (rp + ra + rn)
    return ring_volume(x[0, 0], x[0, 1], x[1, 0], x[1, 1], x[2, 0], x[2, 1], x[3, 0], x[3, 1])


@njit(parallel=True, cache=True)
def ring_volumes(x, conn, out):
    """Exact ring volume of every quad4 (E,) for the full 2 pi."""
    for e in prange(conn.shape[0]):
        n0, n1, n2, n3 = conn[e, 0], conn[e, 1], conn[e, 2], conn[e, 3]
        out[e] = ring_volume(x[n0, 0], x[n0, 1], x[n1, 0], x[n1, 1], x[n2, 0], x[n2, 1], x[n3, 0], x[n3, 1])


@njit(parallel=True, cache=True)
def lagrange_forces_rz(x, v, conn, vol_m, mass_m, ener_m, mat_eos, mat_q, mat_rho0, q1, q2, qhg,
                       phi_eps, pscale, p_cut, f_elem, pres_m, bulk_m, q_elem, dt_elem):
    """``lagrange.lagrange_forces`` on rings: f_a = (p_mix + q) dV/dx_a - hourglass (module docstring).

    Arguments and outputs as the plane kernel's; vol_m and mass_m are ring volumes and masses.
    """
    n_elem = conn.shape[0]
    n_chunks = min(n_elem, 512)
    for chunk in prange(n_chunks):
        start = chunk * n_elem // n_chunks
        stop = (chunk + 1) * n_elem // n_chunks
        xe = np.empty((4, 2))
        ve = np.empty((4, 2))
        b = np.empty((2, 4))
        gv = np.empty((2, 4))
        for e in range(start, stop):
            vmax2 = 0.0
            for a in range(4):
                n = conn[e, a]
                xe[a, 0] = x[n, 0]
                xe[a, 1] = x[n, 1]
                ve[a, 0] = v[n, 0]
                ve[a, 1] = v[n, 1]
                vmax2 = max(vmax2, v[n, 0] * v[n, 0] + v[n, 1] * v[n, 1])
            area = quad4_gradient(xe, b)
            vol = ring_gradient(xe, gv)
            p_mix, c_max, mtot = _mixture_pressure(e, vol_m, mass_m, ener_m, mat_eos, mat_q, mat_rho0, phi_eps,
                                                   pscale, p_cut, pres_m, bulk_m)
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
            q = bulk_viscosity(rho_e, length, c_max, trace_d, q1, q2)
            q_elem[e] = q
            c_eff = c_max + math.sqrt(vmax2)
            dt_elem[e] = stable_dt(length, c_eff, trace_d, q1, q2) if c_eff > 0.0 else np.inf
            s = p_mix + q
            for a in range(4):
                f_elem[e, a, 0] = s * gv[0, a]
                f_elem[e, a, 1] = s * gv[1, a]
            if qhg > 0.0 and rho_e > 0.0 and area > 0.0:
                gx0 = 0.0
                gx1 = 0.0
                for a in range(4):
                    gx0 += QUAD_GAMMA[a] * xe[a, 0]
                    gx1 += QUAD_GAMMA[a] * xe[a, 1]
                # the plane coefficient qhg rho c sqrt(A) / 4 times the ring length 2 pi r_bar = V / A
                coef = 0.25 * qhg * rho_e * c_max * math.sqrt(area) * (vol / area)
                hq0 = 0.0
                hq1 = 0.0
                for a in range(4):
                    g = QUAD_GAMMA[a] - gx0 * b[0, a] - gx1 * b[1, a]
                    hq0 += g * ve[a, 0]
                    hq1 += g * ve[a, 1]
                for a in range(4):
                    g = QUAD_GAMMA[a] - gx0 * b[0, a] - gx1 * b[1, a]
                    f_elem[e, a, 0] -= coef * hq0 * g
                    f_elem[e, a, 1] -= coef * hq1 * g


@njit(parallel=True, cache=True)
def lagrange_energy_rz(x, v_old, v_new, dt, conn, f_elem, vol_m, mass_m, ener_m, pres_m, bulk_m, q_elem,
                       closure, alpha, beta, phi_eps, work_elem):
    """``lagrange.lagrange_energy`` on rings: the compatible work W_e, the Lagrangian ring volume at
    x + dt v^{n+1/2}, then the mixed-element closure (``lagrange._closure_energy``)."""
    n_elem = conn.shape[0]
    n_mat = vol_m.shape[1]
    n_chunks = min(n_elem, 512)
    for chunk in prange(n_chunks):
        start = chunk * n_elem // n_chunks
        stop = (chunk + 1) * n_elem // n_chunks
        dvm = np.empty(n_mat)
        dev = np.empty(n_mat)
        px = np.empty(4)
        py = np.empty(4)
        for e in range(start, stop):
            w = 0.0
            for a in range(4):
                n = conn[e, a]
                w -= f_elem[e, a, 0] * 0.5 * (v_old[n, 0] + v_new[n, 0]) + f_elem[e, a, 1] * 0.5 * (v_old[n, 1] + v_new[n, 1])
                px[a] = x[n, 0] + dt * v_new[n, 0]
                py[a] = x[n, 1] + dt * v_new[n, 1]
            w *= dt
            work_elem[e] = w
            v_lag = ring_volume(px[0], py[0], px[1], py[1], px[2], py[2], px[3], py[3])
            _closure_energy(e, w, v_lag, vol_m, mass_m, ener_m, pres_m, bulk_m, closure, alpha, beta, phi_eps,
                            dvm, dev)


@njit(parallel=True, cache=True)
def face_fluxes_rz(faces, face_nodes, face_elem, face_local, elem_nbr, face_open, x_lag, x_new,
                   vol_m, mass_m, ener_m, order, iface, phi_eps, fvol, fmass, fener):
    """``remap.face_fluxes`` with the swept ring volume of the quad (l0, w0, w1, l1) (module docstring)."""
    nf = faces.shape[0]
    n_mat = vol_m.shape[1]
    n_chunks = min(nf, 512)
    for chunk in prange(n_chunks):
        start = chunk * nf // n_chunks
        stop = (chunk + 1) * nf // n_chunks
        dvm = np.empty(n_mat)
        g = np.empty(n_mat)
        used = np.empty(n_mat, dtype=np.bool_)
        for i in range(start, stop):
            f = faces[i]
            n0 = face_nodes[f, 0]
            n1 = face_nodes[f, 1]
            for m in range(n_mat):
                fvol[f, m] = 0.0
                fmass[f, m] = 0.0
                fener[f, m] = 0.0
            el = face_elem[f, 0]
            er = face_elem[f, 1]
            if er < 0 and not face_open[f]:
                continue
            dv = ring_volume(x_lag[n0, 0], x_lag[n0, 1], x_new[n0, 0], x_new[n0, 1],
                             x_new[n1, 0], x_new[n1, 1], x_lag[n1, 0], x_lag[n1, 1])
            if dv == 0.0:
                continue
            if dv > 0.0:
                donor = er
                acc = el
                sgn = 1.0
                far = elem_nbr[er, (face_local[f, 1] + 2) % 4] if er >= 0 else -1
            else:
                donor = el
                acc = er
                sgn = -1.0
                far = elem_nbr[el, (face_local[f, 0] + 2) % 4]
            _face_flux(f, abs(dv), donor, acc, far, sgn, vol_m, mass_m, ener_m, order, iface, phi_eps,
                       fvol, fmass, fener, dvm, g, used)


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
