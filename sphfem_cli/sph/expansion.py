"""Renormalised continuity of the particles of a strongly expanding gas (explosive products).

The plain continuity equation (``rates.fluid_rates``, paper eq. 3.8) estimates the velocity
divergence as

    div_i = - sum_j V_j v_ij . grad_i W_ij,          V_j = m_j / rho_j, v_ij = v_i - v_j,

which is exact for a linear velocity field only while the kernel's first moment is the identity,
M_i = sum_j V_j (x_j - x_i) (x) grad_i W_ij = I. When a gas expands by a large factor with few
particles (a detonation's products: 12 to 112 particles of a 5 mm charge whose bubble grows
10-20 times in area within 0.1 ms), the particles move apart faster than their volumes V_j = m/rho
follow, M_i falls below I in proportion, the divergence and hence the density drop are
under-estimated, h = eta (m/rho)^(1/d) stays small, the particles lose their neighbours and their
density and energy freeze: the products stop working on the water with half their energy left
(docs/studies/underwater_explosion.md, "Cause"). Here their divergence is taken with the
first-order consistent (renormalised) gradient of Randles & Libersky (1996) and Bonet & Lok (1999),

    grad v_i = A_i M_i^-1,   A_i = sum_j V_j (v_j - v_i) (x) grad_i W_ij,   div_i = tr(A_i M_i^-1),

exact for a linear velocity field whatever the particle volumes, and

    drho_i/dt = - rho_i div_i   (+ the delta-SPH term of ``fluid_rates``, unchanged),

so that the products' density follows the volume they actually fill. M_i is inverted when it is
well conditioned (det M >= 1/4 (tr M / d)^d); otherwise the scalar renormalisation
div_i = tr(A_i) / (tr(M_i) / d) is used, and with no neighbour (tr M = 0) the plain sum (0).
The momentum and energy equations are not changed: the pair forces stay antisymmetric (momentum
and total energy are conserved as before); the products' energy still falls by the work their
pressure does on the neighbours.

Sums over every point within 2 h_ij (fluid, ghost and wall points, as the continuity sum of
``fluid_rates``), on the sorted point set of ``search.sort_points``.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .kernel_functions import kernel_f
from .search import cell_range
from .slots import (D_MK, D_RHO, D_VOL, D_VX, D_VY, D_VZ, GF_CELL, GF_OX, GF_OY, GF_OZ, GI_NX, GI_NY,
                    GI_NZ, KIND_FLUID, SI_CONTINUITY, SI_DIM, SI_KERNEL, CONTINUITY_MASS)


@njit(cache=True)
def renormalised_divergence(a, m, dim):
    """tr(A M^-1) of the (dim x dim) sums ``a``, ``m`` (3 x 3 arrays, the first dim rows/columns used);
    the scalar form tr(A) / (tr(M)/dim) where M is ill conditioned; tr(A) where tr(M) <= 0."""
    tr_a = 0.0
    tr_m = 0.0
    for d in range(dim):
        tr_a += a[d, d]
        tr_m += m[d, d]
    if tr_m <= 0.0:
        return tr_a
    s = tr_m / dim
    if dim == 2:
        det = m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]
        if det < 0.25 * s * s:
            return tr_a / s
        # tr(A M^-1) with M^-1 = [[m11, -m01], [-m10, m00]] / det
        return (a[0, 0] * m[1, 1] - a[0, 1] * m[1, 0] - a[1, 0] * m[0, 1] + a[1, 1] * m[0, 0]) / det
    c00 = m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1]
    c01 = m[1, 2] * m[2, 0] - m[1, 0] * m[2, 2]
    c02 = m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0]
    det = m[0, 0] * c00 + m[0, 1] * c01 + m[0, 2] * c02
    if det < 0.25 * s * s * s:
        return tr_a / s
    inv = np.empty((3, 3))
    inv[0, 0] = c00
    inv[1, 0] = c01
    inv[2, 0] = c02
    inv[0, 1] = m[0, 2] * m[2, 1] - m[0, 1] * m[2, 2]
    inv[1, 1] = m[0, 0] * m[2, 2] - m[0, 2] * m[2, 0]
    inv[2, 1] = m[0, 1] * m[2, 0] - m[0, 0] * m[2, 1]
    inv[0, 2] = m[0, 1] * m[1, 2] - m[0, 2] * m[1, 1]
    inv[1, 2] = m[0, 2] * m[1, 0] - m[0, 0] * m[1, 2]
    inv[2, 2] = m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]
    out = 0.0
    for p in range(3):
        for q in range(3):
            out += a[p, q] * inv[q, p]
    return out / det


@njit(cache=True)
def renormalise_continuity(sx, sd, perm, cell_start, sreach, settings_i, grid_f, grid_i, flag, drho):
    """Replace the plain divergence in ``drho`` by the renormalised one for every fluid slot whose
    particle ``perm[k]`` has ``flag`` set: the plain sum that ``fluid_rates`` put in drho_i is taken out and
    -rho_i div_i put in. The plain sum is the continuity form's (``SI_CONTINUITY``): the volume form's
    drho_i = rho_i sum_j V_j v_ij . grad_i W_ij, the mass form's sum_j m_j v_ij . grad_i W_ij (m_j = rho_j V_j);
    the mass form's was taken out as the volume form's before 7 December 2026, which left
    sum_j (rho_j - rho_i) V_j v_ij . grad_i W_ij in the products' rate (as ``axisymmetric``'s ring version did).
    Returns the number of particles corrected."""
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    mform = settings_i[SI_CONTINUITY] == CONTINUITY_MASS
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    cell = grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    inv_cell = 1.0 / cell
    n = flag.shape[0]
    a = np.zeros((3, 3))
    m = np.zeros((3, 3))
    r = np.zeros(3)
    u = np.zeros(3)
    done = 0
    for k in range(cell_start[-1]):
        if (int(sd[D_MK, k]) & 3) != KIND_FLUID:
            continue
        i = perm[k]
        if i >= n or not flag[i]:
            continue
        xi, yi, zi, hi = sx[0, k], sx[1, k], sx[2, k], sx[3, k]
        reach = sreach[k]  # bounds every 2 h_kj (search.search_reach)
        x0, x1 = cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = cell_range(yi, reach, oy, inv_cell, ny)
        z0, z1 = cell_range(zi, reach, oz, inv_cell, nz)
        a[:, :] = 0.0
        m[:, :] = 0.0
        plain = 0.0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if j == k:
                        continue
                    r[0] = xi - sx[0, j]
                    r[1] = yi - sx[1, j]
                    r[2] = zi - sx[2, j]
                    dist2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
                    hs = hi + sx[3, j]
                    if dist2 >= hs * hs:
                        continue
                    f = kernel_f(kernel, dim, np.sqrt(dist2), 0.5 * hs)  # grad_i W_ij = f r_ij
                    vol = sd[D_VOL, j]
                    weight = vol * sd[D_RHO, j] if mform else vol  # the rates' first sum: m_j or V_j
                    u[0] = sd[D_VX, k] - sd[D_VX, j]
                    u[1] = sd[D_VY, k] - sd[D_VY, j]
                    u[2] = sd[D_VZ, k] - sd[D_VZ, j]
                    for p in range(dim):
                        plain += weight * u[p] * f * r[p]
                        for q in range(dim):
                            # (v_j - v_i)_p (grad W)_q and (x_j - x_i)_p (grad W)_q
                            a[p, q] -= vol * u[p] * f * r[q]
                            m[p, q] -= vol * r[p] * f * r[q]
        div = renormalised_divergence(a, m, dim)
        rhoi = sd[D_RHO, k]
        drho[i] -= (plain + rhoi * div) if mform else rhoi * (plain + div)  # the volume form's arithmetic as before
        done += 1
    return done
