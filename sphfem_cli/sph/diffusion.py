"""The delta-plus correction of the delta-SPH density diffusion (Antuono, Colagrossi, Marrone & Molteni 2010).

``rates.fluid_rates`` adds the density diffusion of Molteni & Colagrossi (2009),

    D_i^MC = -2 delta sum_j h_ij c_ij (rho_j - rho_i) F_ij V_j,     grad_i W_ij = F_ij r_ij, r_ij = x_i - x_j,

(sum over fluid and ghost points j of the particle's material). With a full kernel support it is a
Laplacian of the density, O(h^2); where the support is truncated (a free surface, a structure in
penalty contact, which puts no points on its side of the kernel) the sum of a linear density field
rho_j - rho_i = -g . r_ij does not vanish: it is about 2 delta c g . n, independent of h, so the
term does not go away with refinement. Antuono, Colagrossi, Marrone & Molteni (2010, Comput. Phys.
Commun. 181, 532; the delta-SPH of Marrone et al. 2011, CMAME 200, 1526) subtract the
linear part with the renormalised density gradient:

    D_i = -delta sum_j h_ij c_ij psi_ij F_ij V_j,
    psi_ij = 2 (rho_j - rho_i) + (G_i + G_j) . r_ij,
    G_i = L_i sum_j (rho_j - rho_i) grad_i W_ij V_j,   L_i = [sum_j (x_j - x_i) (x) grad_i W_ij V_j]^-1,

exact (zero) for any linear density field whatever the support. The first part of psi is the
Molteni-Colagrossi term that ``fluid_rates`` already adds, so this module adds only

    drho_i += -delta sum_j h_ij c_ij (G_i + G_j) . r_ij F_ij V_j.

It replaces the hydrostatic correction of ``fluid_rates`` (the hydrostatic density gradient is a
linear field, which G removes), so the caller turns that one off. L_i is inverted where it is well
conditioned (det M >= 1/4 (tr M / d)^d, as ``expansion.renormalised_divergence``), else the scalar
renormalisation M -> (tr M / d) I is used, and with no neighbour G_i = 0. G is computed for fluid and
ghost slots (ghosts are neighbours too); dummy wall points carry none and are no neighbour in either
sum, as in the Molteni-Colagrossi term. Each slot writes its own entries (no dependence on threads).
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from .kernel_functions import kernel_f
from .search import cell_range
from .slots import (D_C, D_MK, D_RHO, D_VOL, GF_CELL, GF_OX, GF_OY, GF_OZ, GI_NX, GI_NY, GI_NZ, KIND_FLUID,
                    KIND_WALL, SF_DELTA, SI_DIM, SI_KERNEL)


@njit(cache=True, parallel=True)
def density_gradient(sx, sd, cell_start, sreach, settings_i, grid_f, grid_i, grad):
    """G_k = L_k sum_j (rho_j - rho_k) grad_k W_kj V_j (module docstring) into ``grad[:, k]`` (3, slots)
    for every fluid and ghost slot; dummy wall slots get 0."""
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    inv_cell = 1.0 / grid_f[GF_CELL]
    for k in prange(cell_start[-1]):
        grad[0, k] = grad[1, k] = grad[2, k] = 0.0
        mk = int(sd[D_MK, k])
        if (mk & 3) == KIND_WALL:
            continue
        mat = mk >> 2
        xi, yi, zi, hi, rhoi = sx[0, k], sx[1, k], sx[2, k], sx[3, k], sd[D_RHO, k]
        x0, x1 = cell_range(xi, sreach[k], ox, inv_cell, nx)
        y0, y1 = cell_range(yi, sreach[k], oy, inv_cell, ny)
        z0, z1 = cell_range(zi, sreach[k], oz, inv_cell, nz)
        m = np.zeros((3, 3))  # M_pq = sum_j V_j (x_j - x_i)_p (grad W)_q = -sum_j V_j F r_p r_q (symmetric)
        b = np.zeros(3)  # sum_j V_j (rho_j - rho_i) grad W
        r = np.zeros(3)
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    mj = int(sd[D_MK, j])
                    if j == k or (mj & 3) == KIND_WALL or (mj >> 2) != mat:
                        continue
                    r[0], r[1], r[2] = xi - sx[0, j], yi - sx[1, j], zi - sx[2, j]
                    dist2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
                    hs = hi + sx[3, j]
                    if dist2 >= hs * hs:
                        continue
                    fv = kernel_f(kernel, dim, np.sqrt(dist2), 0.5 * hs) * sd[D_VOL, j]
                    drj = sd[D_RHO, j] - rhoi
                    for p in range(dim):
                        b[p] += drj * fv * r[p]
                        for q in range(dim):
                            m[p, q] -= fv * r[p] * r[q]
        _solve_renormalised(m, b, dim)
        for p in range(dim):
            grad[p, k] = b[p]


@njit(cache=True)
def _solve_renormalised(m, b, dim):
    """b <- M^-1 b for the symmetric (dim x dim) moment M; the scalar renormalisation b / (tr M / dim)
    where det M < 1/4 (tr M / dim)^dim; b <- 0 where tr M <= 0 (no neighbour)."""
    tr = 0.0
    for d in range(dim):
        tr += m[d, d]
    if tr <= 0.0:
        b[:] = 0.0
        return
    s = tr / dim
    if dim == 2:
        det = m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]
        if det < 0.25 * s * s:
            b[0] /= s
            b[1] /= s
            return
        g0 = (m[1, 1] * b[0] - m[0, 1] * b[1]) / det
        g1 = (m[0, 0] * b[1] - m[1, 0] * b[0]) / det
        b[0], b[1] = g0, g1
        return
    c00 = m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1]
    c01 = m[1, 2] * m[2, 0] - m[1, 0] * m[2, 2]
    c02 = m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0]
    det = m[0, 0] * c00 + m[0, 1] * c01 + m[0, 2] * c02
    if det < 0.25 * s * s * s:
        for d in range(3):
            b[d] /= s
        return
    g0 = (c00 * b[0] + (m[0, 2] * m[2, 1] - m[0, 1] * m[2, 2]) * b[1] + (m[0, 1] * m[1, 2] - m[0, 2] * m[1, 1]) * b[2])
    g1 = (c01 * b[0] + (m[0, 0] * m[2, 2] - m[0, 2] * m[2, 0]) * b[1] + (m[0, 2] * m[1, 0] - m[0, 0] * m[1, 2]) * b[2])
    g2 = (c02 * b[0] + (m[0, 1] * m[2, 0] - m[0, 0] * m[2, 1]) * b[1] + (m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]) * b[2])
    b[0], b[1], b[2] = g0 / det, g1 / det, g2 / det


@njit(cache=True, parallel=True)
def delta_plus_correction(sx, sd, perm, cell_start, sreach, settings_f, settings_i, grid_f, grid_i, grad, drho):
    """drho_i += -delta sum_j h_ij c_ij (G_i + G_j) . r_ij F_ij V_j for every fluid slot (module docstring),
    over the fluid and ghost points j of its material (the neighbours of the Molteni-Colagrossi sum)."""
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    delta = settings_f[SF_DELTA]
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    inv_cell = 1.0 / grid_f[GF_CELL]
    for k in prange(cell_start[-1]):
        mk = int(sd[D_MK, k])
        if (mk & 3) != KIND_FLUID:
            continue
        mat = mk >> 2
        xi, yi, zi, hi, ci = sx[0, k], sx[1, k], sx[2, k], sx[3, k], sd[D_C, k]
        x0, x1 = cell_range(xi, sreach[k], ox, inv_cell, nx)
        y0, y1 = cell_range(yi, sreach[k], oy, inv_cell, ny)
        z0, z1 = cell_range(zi, sreach[k], oz, inv_cell, nz)
        acc = 0.0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    mj = int(sd[D_MK, j])
                    if j == k or (mj & 3) == KIND_WALL or (mj >> 2) != mat:
                        continue
                    dx, dy, dz = xi - sx[0, j], yi - sx[1, j], zi - sx[2, j]
                    dist2 = dx * dx + dy * dy + dz * dz
                    hs = hi + sx[3, j]
                    if dist2 >= hs * hs:
                        continue
                    hij = 0.5 * hs
                    f = kernel_f(kernel, dim, np.sqrt(dist2), hij)
                    gr = (grad[0, k] + grad[0, j]) * dx + (grad[1, k] + grad[1, j]) * dy + (grad[2, k] + grad[2, j]) * dz
                    acc += hij * 0.5 * (ci + sd[D_C, j]) * gr * f * sd[D_VOL, j]
        drho[perm[k]] -= delta * acc
