"""ALE in r-z (``dimension: axisymmetric``): the ring geometry of the quad4 kernels.

The meridian plane holds x = r >= 0 and y = z (the axis). An element is the ring its quad sweeps
about the axis; every volume, mass, force and energy is for the full 2 pi. The plane quad4 kernels
``energy.lagrange_energy`` and ``remap.face_fluxes`` take the ring geometry (``ring_geometry``)
when called with ``ring`` True (one compiled form serves plane and r-z; the branch is per element or
face); the forces have their own kernel here, ``lagrange_forces_rz`` (the flagged plane kernel
measured slower; both take their shared parts from ``lagrange`` and ``force_lanes``), compiled, with
``ring_volumes`` and ``ring_block``, only for an axisymmetric mesh.

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

from ..fem.tables import QUAD_GAMMA
from .force_lanes import (_CX_U, _CX_W, _CX_X, _CX_Y, _ST_AREA, _ST_B, _ST_BLOCK, _ST_C, _ST_GX, _ST_HQ, _ST_LONG2, _ST_M,
                          _ST_P, _ST_ROWS, _ST_VMAX2, gather_block, geometry_block, one_gas)
from .lagrange import N_CHUNKS, chunk_range, state_block, viscosity_and_step
from .ring_geometry import PI_3, ring_volume

TWO_PI = 2.0 * math.pi


@njit(parallel=True, cache=True)
def ring_volumes(x, conn, out):
    """Exact ring volume of every quad4 (E,) for the full 2 pi."""
    for e in prange(conn.shape[0]):
        n0, n1, n2, n3 = conn[e, 0], conn[e, 1], conn[e, 2], conn[e, 3]
        out[e] = ring_volume(x[n0, 0], x[n0, 1], x[n1, 0], x[n1, 1], x[n2, 0], x[n2, 1], x[n3, 0], x[n3, 1])


# rows of the ring pass's work array (flat, row r at r * _ST_BLOCK): dV/dr_a (4), dV/dz_a (4), V, tr d, |b|^2, |dV/dx|^2
_RG_G, _RG_VOL, _RG_TRACE, _RG_BB, _RG_GG = 0, 8, 9, 10, 11
_RG_ROWS = 12


@njit(cache=True, error_model="numpy")
def ring_block(nb, cx, st, rg):
    """The ring geometry of the nb quads of a block from their corners (cx, ``force_lanes.gather_block``) and
    their plane mean gradients (st, ``force_lanes.geometry_block``) into rg (flat): dV/dx_a = (pi / 3) dS/dx_a (module
    docstring), the ring volume V, the divergence tr d = sum_a v_a . dV/dx_a / V (0 where V <= 0) and the
    squared norms |b|^2 and |dV/dx|^2 of the stable step's hoop factor; the scalar code's operations in its
    order (straight-line, so that LLVM vectorises the loop over the block)."""
    B = _ST_BLOCK
    for i in range(nb):
        r0, r1, r2, r3 = cx[(_CX_X + 0) * B + i], cx[(_CX_X + 1) * B + i], cx[(_CX_X + 2) * B + i], cx[(_CX_X + 3) * B + i]
        z0, z1, z2, z3 = cx[(_CX_Y + 0) * B + i], cx[(_CX_Y + 1) * B + i], cx[(_CX_Y + 2) * B + i], cx[(_CX_Y + 3) * B + i]
        u0, u1, u2, u3 = cx[(_CX_U + 0) * B + i], cx[(_CX_U + 1) * B + i], cx[(_CX_U + 2) * B + i], cx[(_CX_U + 3) * B + i]
        w0, w1, w2, w3 = cx[(_CX_W + 0) * B + i], cx[(_CX_W + 1) * B + i], cx[(_CX_W + 2) * B + i], cx[(_CX_W + 3) * B + i]
        gr0 = PI_3 * (2.0 * r0 * (z1 - z3) + r1 * (z1 - z0) + r3 * (z0 - z3))
        gz0 = PI_3 * (r3 - r1) * (r3 + r0 + r1)
        gr1 = PI_3 * (2.0 * r1 * (z2 - z0) + r2 * (z2 - z1) + r0 * (z1 - z0))
        gz1 = PI_3 * (r0 - r2) * (r0 + r1 + r2)
        gr2 = PI_3 * (2.0 * r2 * (z3 - z1) + r3 * (z3 - z2) + r1 * (z2 - z1))
        gz2 = PI_3 * (r1 - r3) * (r1 + r2 + r3)
        gr3 = PI_3 * (2.0 * r3 * (z0 - z2) + r0 * (z0 - z3) + r2 * (z3 - z2))
        gz3 = PI_3 * (r2 - r0) * (r2 + r3 + r0)
        vol = ring_volume(r0, z0, r1, z1, r2, z2, r3, z3)
        bx0, bx1, bx2, bx3 = st[_ST_B * B + i], st[(_ST_B + 1) * B + i], st[(_ST_B + 2) * B + i], st[(_ST_B + 3) * B + i]
        by0, by1, by2, by3 = st[(_ST_B + 4) * B + i], st[(_ST_B + 5) * B + i], st[(_ST_B + 6) * B + i], st[(_ST_B + 7) * B + i]
        trace_d = 0.0
        trace_d += u0 * gr0 + w0 * gz0
        trace_d += u1 * gr1 + w1 * gz1
        trace_d += u2 * gr2 + w2 * gz2
        trace_d += u3 * gr3 + w3 * gz3
        bb = 0.0
        bb += bx0 * bx0 + by0 * by0
        bb += bx1 * bx1 + by1 * by1
        bb += bx2 * bx2 + by2 * by2
        bb += bx3 * bx3 + by3 * by3
        gg = 0.0
        gg += gr0 * gr0 + gz0 * gz0
        gg += gr1 * gr1 + gz1 * gz1
        gg += gr2 * gr2 + gz2 * gz2
        gg += gr3 * gr3 + gz3 * gz3
        rg[(_RG_G + 0) * B + i] = gr0
        rg[(_RG_G + 1) * B + i] = gr1
        rg[(_RG_G + 2) * B + i] = gr2
        rg[(_RG_G + 3) * B + i] = gr3
        rg[(_RG_G + 4) * B + i] = gz0
        rg[(_RG_G + 5) * B + i] = gz1
        rg[(_RG_G + 6) * B + i] = gz2
        rg[(_RG_G + 7) * B + i] = gz3
        rg[_RG_VOL * B + i] = vol
        rg[_RG_TRACE * B + i] = trace_d / vol if vol > 0.0 else 0.0
        rg[_RG_BB * B + i] = bb
        rg[_RG_GG * B + i] = gg


@njit(parallel=True, cache=True)
def lagrange_forces_rz(x, v, conn, vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q, mat_rho0, q1, q2, qhg,
                       phi_eps, pscale, pressure_cutoff, f_elem, pres_m, bulk_m, q_elem, dt_elem):
    """``lagrange.lagrange_forces`` on rings (its own kernel: the plane kernel with a ring flag measured
    slower, the comment there): f_a = (p_mix + q) dV/dx_a - hourglass (module docstring).

    Arguments and outputs as the plane kernel's; vol_m and mass_m are ring volumes and masses. Passes over
    each block of _ST_BLOCK elements, as the plane kernel's (the comment above it): the material state
    (``force_lanes.gas_block`` for one ideal or stiffened gas, else ``_mixture_pressure``), the corner gather
    and plane geometry (``force_lanes.gather_block``, ``geometry_block``), the ring geometry (``ring_block``),
    then the viscosity, step and forces. The same operations in the same order as the one-pass kernel they
    replaced (bit-identical histories of benchmarks/ale_axisymmetric_throughput.py's case and of the decks
    underwater_explosion_free_field_axisymmetric_ale and bird_strike_axisymmetric_ale): 93 -> 48 ns per element
    on that case's 200^2 rings of one gas (1 thread, 40 calls, load 3-4; the plane kernel 33 ns), the benchmark's
    cost ratio ring / plane 1.40 -> 1.15.
    """
    n_elem = conn.shape[0]
    n_chunks = min(n_elem, N_CHUNKS)
    gas, gm1, gpinf = one_gas(mat_eos, mat_q, mat_rho0)
    # one gas: the (E, 1) state as flat (E,) views for gas_block (as lagrange.lagrange_forces)
    flat = (vol_m.reshape(-1), mass_m.reshape(-1), ener_m.reshape(-1), e_lag.reshape(-1), pres_m.reshape(-1),
            bulk_m.reshape(-1), pscale.reshape(-1))
    B = _ST_BLOCK
    for chunk in prange(n_chunks):
        start, stop = chunk_range(chunk, n_elem, n_chunks)
        st = np.empty((_ST_ROWS, B))
        st_flat = st.reshape(-1)
        cx = np.empty(16 * B)
        rg = np.empty(_RG_ROWS * B)
        for block in range(start, stop, B):
            nb = min(B, stop - block)
            state_block(block, nb, gas, gm1, gpinf, flat, vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q, mat_rho0,
                        phi_eps, pscale, pressure_cutoff, pres_m, bulk_m, st[_ST_P], st[_ST_C], st[_ST_M])
            gather_block(conn, block, nb, x, v, cx)
            geometry_block(nb, cx, st_flat)
            ring_block(nb, cx, st_flat, rg)
            for i in range(nb):
                e = block + i
                c_max = st[_ST_C, i]
                area = st[_ST_AREA, i]
                vol = rg[_RG_VOL * B + i]
                gg = rg[_RG_GG * B + i]
                rho_e = st[_ST_M, i] / vol if vol > 0.0 else 0.0
                length = area / math.sqrt(st[_ST_LONG2, i])  # fem.geometry.quad4_char_length with one square root
                if gg > 0.0 and vol > 0.0:
                    length *= min(1.0, math.sqrt(rg[_RG_BB * B + i] / gg) * vol)  # |b| / |b_V|, b_V = gv / V
                q = viscosity_and_step(e, rho_e, length, c_max, rg[_RG_TRACE * B + i], st[_ST_VMAX2, i], q1, q2,
                                       q_elem, dt_elem)
                s = st[_ST_P, i] + q
                if qhg > 0.0 and rho_e > 0.0 and area > 0.0:
                    # the plane kernel's hourglass (lagrange_forces) with its coefficient qhg rho c sqrt(A) / 4 times the ring
                    # length 2 pi r_bar = V / A
                    coef = 0.25 * qhg * rho_e * c_max * math.sqrt(area) * (vol / area)
                    gx0 = st[_ST_GX, i]
                    gx1 = st[_ST_GX + 1, i]
                    hq0 = st[_ST_HQ, i]
                    hq1 = st[_ST_HQ + 1, i]
                    for a in range(4):
                        g = QUAD_GAMMA[a] - gx0 * st[_ST_B + a, i] - gx1 * st[_ST_B + 4 + a, i]
                        f_elem[e, a, 0] = s * rg[(_RG_G + a) * B + i] - coef * hq0 * g
                        f_elem[e, a, 1] = s * rg[(_RG_G + 4 + a) * B + i] - coef * hq1 * g
                else:
                    for a in range(4):
                        f_elem[e, a, 0] = s * rg[(_RG_G + a) * B + i]
                        f_elem[e, a, 1] = s * rg[(_RG_G + 4 + a) * B + i]


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
