"""Boundary (dummy) particles carried by a structure: their Adami pressure and their pair terms with the fluid.

The particles lie inside the structure in layers behind its wetted faces (``contact/sph_boundary.py``
places them and moves them with the face's nodes). They are not points of the SPH evaluation
(``sph/search.py``): these kernels read the fluid slots of the last evaluation's cell-sorted point set
(``sx``, ``sd``, ``cell_start``, the grid) and add the wall pairs' terms to the fluid's rates afterwards.

One-sided: a boundary particle w of a face with outward normal n_w through the point x_fw (its
projection on the face) sees only fluid particles f with (x_f - x_fw) . n_w > 0, so a plate thinner
than the kernel support carries on each face the pressure of the water on that face, and the
layers of one face may lie beyond the other face.

Convex corners: where two faces meet at a convex vertex their layers overlap in a square behind the corner,
so a fluid point in both faces' half-planes (the quadrant diagonal to the corner) would see that square twice:
on a lattice at h/dx 1.2 its kernel sum sum_j V_j grad W_ij is then 0.099 / dx per axis towards the corner
(0 where the solid is counted once), and a uniform pressure pushes it out of the corner as hard as the truncated
kernel pushes it in without any wall (F_i = -(2 p / rho) m_i sum_j V_j grad W_ij). ``twins[w]`` lists the
particles of other faces that coincide with w (``contact/sph_boundary.py`` finds them); a fluid point that sees
k of a group weighs each by 1 / k, so the corner's solid counts once (``twins`` all -1: every particle counts).

Two ways to set the boundary particles' pressure and density (``sph_boundary``'s ``extrapolation``):
``wall_state`` (Adami et al. 2012, the default) and ``wall_state_mdbc`` (English et al. 2022's mDBC: the
fluid's density extrapolated to first order at a ghost node mirrored through the boundary).

Equations: docs/theory/coupling.md ("SPH boundary particles on a structure").
"""
from __future__ import annotations

import math

from numba import njit, prange

from ..materials.kernels import EOS_OFFSET, P_EOS_TYPE, P_RHO0, eos_pressure
from ..materials.slots import Q_E0
from .eos import density_from_pressure, sound_speed
from .kernel_functions import kernel_f, kernel_w
from .search import cell_range
from .slots import (CONTINUITY_MASS, D_C, D_MK, D_PR, D_RHO, D_VOL, D_VX, D_VY, D_VZ, GF_CELL, GF_HMAX, GF_OX,
                    GF_OY, GF_OZ, GI_NX, GI_NY, GI_NZ, KIND_FLUID, SF_ALPHA, SF_BETA, SF_EPS, SF_GX, SF_GY, SF_GZ,
                    SF_PRESSURE_CUTOFF, SI_CONTINUITY, SI_DIM, SI_KERNEL)

# columns of the boundary particles' state array ``ws`` (one row per particle)
W_X, W_Y, W_Z = 0, 1, 2          # position
W_VX, W_VY, W_VZ = 3, 4, 5       # velocity
W_AX, W_AY, W_AZ = 6, 7, 8       # acceleration of the wall
W_NX, W_NY, W_NZ = 9, 10, 11     # outward unit normal of its face
W_FX, W_FY, W_FZ = 12, 13, 14    # its projection on the face
W_M, W_H = 15, 16                # mass, smoothing length
W_RHO, W_P, W_C = 17, 18, 19     # density, pressure, sound speed (wall_state writes them)
W_GX, W_GY, W_GZ = 20, 21, 22    # its ghost node (wall_state_mdbc): mirrored through its face, or a convex vertex
NW = 23


@njit(cache=True, fastmath=False)
def _on_side(ws, w, x, y, z):
    """(x - x_fw) . n_w > 0: the fluid point lies on the side of particle w's face."""
    return ((x - ws[w, W_FX]) * ws[w, W_NX] + (y - ws[w, W_FY]) * ws[w, W_NY]
            + (z - ws[w, W_FZ]) * ws[w, W_NZ]) > 0.0


@njit(cache=True, parallel=True, fastmath=False, error_model="numpy")
def wall_state(ws, mat, sx, sd, mine, cell_start, settings_f, settings_i, grid_f, grid_i, params):
    """Adami, Hu & Adams (2012, J. Comput. Phys. 231, 7057, eq. 27) pressure of every boundary particle.

      p_w = (sum_f p_f W_wf + (g - a_w) . sum_f rho_f (x_w - x_f) W_wf) / sum_f W_wf

    over the fluid points f within 2 h_wf on its face's side (and of the coupled part: ``mine[slot]``); a_w the wall's acceleration. p_w is
    bounded below by the pressure cut-off; rho_w inverts the fluid material ``mat``'s EOS at p_w
    (initial energy), c_w its sound speed there. A particle with no fluid neighbour gets p = 0 and
    the reference density. Writes ``ws[:, W_RHO]``, ``ws[:, W_P]``, ``ws[:, W_C]``.
    """
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    hmax, cell = grid_f[GF_HMAX], grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    cutoff = settings_f[SF_PRESSURE_CUTOFF]
    inv_cell = 1.0 / cell
    rho0 = params[mat, P_RHO0]
    eos = int(params[mat, P_EOS_TYPE])
    q = params[mat, EOS_OFFSET:]
    for w in prange(ws.shape[0]):
        xw, yw, zw, hw = ws[w, W_X], ws[w, W_Y], ws[w, W_Z], ws[w, W_H]
        gx = settings_f[SF_GX] - ws[w, W_AX]
        gy = settings_f[SF_GY] - ws[w, W_AY]
        gz = settings_f[SF_GZ] - ws[w, W_AZ]
        reach = hw + hmax  # bounds every 2 h_wf
        x0, x1 = cell_range(xw, reach, ox, inv_cell, nx)
        y0, y1 = cell_range(yw, reach, oy, inv_cell, ny)
        z0, z1 = cell_range(zw, reach, oz, inv_cell, nz)
        sw = spw = srx = sry = srz = 0.0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if (int(sd[D_MK, j]) & 3) != KIND_FLUID or not mine[j]:
                        continue
                    if not _on_side(ws, w, sx[0, j], sx[1, j], sx[2, j]):
                        continue
                    dx, dy, dz = xw - sx[0, j], yw - sx[1, j], zw - sx[2, j]
                    hij = 0.5 * (hw + sx[3, j])
                    r2 = dx * dx + dy * dy + dz * dz
                    if r2 >= 4.0 * hij * hij:
                        continue
                    wv = kernel_w(kernel, dim, math.sqrt(r2), hij)
                    rj = sd[D_RHO, j]
                    sw += wv
                    spw += sd[D_PR, j] * rj * rj * wv  # sd holds p / rho^2
                    srx += rj * wv * dx
                    sry += rj * wv * dy
                    srz += rj * wv * dz
        pw = (spw + gx * srx + gy * sry + gz * srz) / sw if sw > 0.0 else 0.0
        if pw < cutoff:
            pw = cutoff
        rw = density_from_pressure(eos, q, rho0, pw, q[Q_E0], rho0) if sw > 0.0 else rho0
        ws[w, W_RHO] = rw
        ws[w, W_P] = pw
        ws[w, W_C] = sound_speed(eos, q, rw / rho0, q[Q_E0])


# wall_state_mdbc's first-order solve needs a ghost support this full (the Shepard sum sum V W, 1 in the bulk; DualSPHysics'
# mDBC takes 0.1 too) and a scaled system this well conditioned (1.0-5.0 for every ghost by the submerged faces and
# corners of the paper's section 4.1 plate at the start; 1e2 to infinity for ghosts above its free surface, where a
# first-order solve blew the run up within 45 steps); else the Shepard (zeroth-order) density
MDBC_SUM_MIN = 0.1
MDBC_COND_MAX = 50.0


@njit(cache=True, parallel=True, fastmath=False, error_model="numpy")
def wall_state_mdbc(ws, side2, mat, sx, sd, mine, cell_start, settings_f, settings_i, grid_f, grid_i, params, out,
                    cond_out):
    """mDBC (English, Crespo, Rogers, Dominguez, Moxley & Gomez-Gesteira 2022, Comp. Part. Mech. 9, 1; the
    first-order consistent kernel interpolation of Liu & Liu 2006, Appl. Numer. Math. 56, 19) density and pressure
    of every boundary particle (2D plane).

    Each particle w has a ghost node x_g in the fluid (``ws[w, W_GX:W_GY+1]``; ``contact/sph_boundary.py`` places
    it: x_f + d n_w, its mirror through its face, or 2 x_v - x_w through a convex vertex v of the structure).
    The fluid's density there and its gradient G solve, with r_j = x_j - x_g, h_gj = (h_w + h_j) / 2 and the
    test functions W_gj and grad_g W_gj over the fluid points j within 2 h_gj of x_g on w's face's side (or, with
    ``side2[w] >= 0``, on the side of that particle's face too: a vertex ghost sees both faces' water),

      sum_j m_j W_gj      = rho_g sum_j V_j W_gj      + G . sum_j V_j r_j W_gj
      sum_j m_j grad W_gj = rho_g sum_j V_j grad W_gj + (sum_j V_j grad W_gj r_j^T) G

    (the Taylor expansion rho_j = rho_g + G . r_j tested with W and grad W: exact for a linear density on any
    particle arrangement whose 3 x 3 matrix is regular), and the particle takes

      rho_w = rho_g + G . (x_w - x_g),      p_w = p_eos(rho_w / rho_0, E_0),      c_w = c_eos there.

    The system A (rho_g, h_w G) = b is solved in units of h_w (gradient rows times h_w, position columns over
    h_w: A is about diag(1, -1, -1) in a full support); where the ghost's support is not full enough to carry a
    gradient (the Shepard sum sum_j V_j W_gj below ``MDBC_SUM_MIN``, or A's infinity-norm condition number above
    ``MDBC_COND_MAX``: ghosts near a free surface or a corner's empty side, as DualSPHysics' mDBC falls back on a
    small kernel sum or an ill-conditioned matrix) the Shepard value rho_w = sum m W / sum V W is used. p_w is bounded below by the pressure cut-off (rho_w then the EOS's
    density there); a particle whose ghost sees no fluid gets p = 0 and the reference density (as ``wall_state``).
    Writes ``ws[:, W_RHO]``, ``ws[:, W_P]``, ``ws[:, W_C]``; ``out[w]`` = 1 where the first-order solve was used, 0
    where the Shepard fallback was, -1 where no fluid was seen; ``cond_out[w]`` the condition number.
    """
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    hmax, cell = grid_f[GF_HMAX], grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    cutoff = settings_f[SF_PRESSURE_CUTOFF]
    inv_cell = 1.0 / cell
    rho0 = params[mat, P_RHO0]
    eos = int(params[mat, P_EOS_TYPE])
    q = params[mat, EOS_OFFSET:]
    for w in prange(ws.shape[0]):
        xg, yg, zg, hw = ws[w, W_GX], ws[w, W_GY], ws[w, W_GZ], ws[w, W_H]
        o = side2[w]
        reach = hw + hmax  # bounds every 2 h_gj
        x0, x1 = cell_range(xg, reach, ox, inv_cell, nx)
        y0, y1 = cell_range(yg, reach, oy, inv_cell, ny)
        z0, z1 = cell_range(zg, reach, oz, inv_cell, nz)
        # a[r][c]: rows W, h d/dx W, h d/dy W; columns rho_g, h G_x, h G_y; b the right-hand side
        a00 = a01 = a02 = a10 = a11 = a12 = a20 = a21 = a22 = 0.0
        b0 = b1 = b2 = 0.0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if (int(sd[D_MK, j]) & 3) != KIND_FLUID or not mine[j]:
                        continue
                    if not _on_side(ws, w, sx[0, j], sx[1, j], sx[2, j]):
                        if o < 0 or not _on_side(ws, o, sx[0, j], sx[1, j], sx[2, j]):
                            continue
                    rx, ry, rz = sx[0, j] - xg, sx[1, j] - yg, sx[2, j] - zg  # r_j = x_j - x_g
                    hij = 0.5 * (hw + sx[3, j])
                    r2 = rx * rx + ry * ry + rz * rz
                    if r2 >= 4.0 * hij * hij:
                        continue
                    r = math.sqrt(r2)
                    wv = kernel_w(kernel, dim, r, hij)
                    f = kernel_f(kernel, dim, r, hij) * hw  # grad_g W = F (x_g - x_j) = -F r_j; times h_w
                    gx, gy = -f * rx, -f * ry
                    vj = sd[D_VOL, j]
                    mj = vj * sd[D_RHO, j]
                    sx_, sy_ = rx / hw, ry / hw
                    a00 += vj * wv
                    a01 += vj * wv * sx_
                    a02 += vj * wv * sy_
                    a10 += vj * gx
                    a11 += vj * gx * sx_
                    a12 += vj * gx * sy_
                    a20 += vj * gy
                    a21 += vj * gy * sx_
                    a22 += vj * gy * sy_
                    b0 += mj * wv
                    b1 += mj * gx
                    b2 += mj * gy
        if a00 <= 0.0:
            ws[w, W_RHO] = rho0
            ws[w, W_P] = 0.0
            ws[w, W_C] = sound_speed(eos, q, 1.0, q[Q_E0])
            out[w] = -1
            cond_out[w] = math.inf
            continue
        c00 = a11 * a22 - a12 * a21
        c01 = a12 * a20 - a10 * a22
        c02 = a10 * a21 - a11 * a20
        det = a00 * c00 + a01 * c01 + a02 * c02
        cond = math.inf
        if det != 0.0:  # the infinity-norm condition number ||A|| ||A^-1|| of the scaled system
            i00, i01, i02 = c00 / det, (a02 * a21 - a01 * a22) / det, (a01 * a12 - a02 * a11) / det
            i10, i11, i12 = c01 / det, (a00 * a22 - a02 * a20) / det, (a02 * a10 - a00 * a12) / det
            i20, i21, i22 = c02 / det, (a01 * a20 - a00 * a21) / det, (a00 * a11 - a01 * a10) / det
            na = max(abs(a00) + abs(a01) + abs(a02), abs(a10) + abs(a11) + abs(a12), abs(a20) + abs(a21) + abs(a22))
            ni = max(abs(i00) + abs(i01) + abs(i02), abs(i10) + abs(i11) + abs(i12), abs(i20) + abs(i21) + abs(i22))
            cond = na * ni
        cond_out[w] = cond
        if a00 >= MDBC_SUM_MIN and cond <= MDBC_COND_MAX:
            rg = i00 * b0 + i01 * b1 + i02 * b2  # rho_g, h G_x, h G_y = A^-1 b
            hgx = i10 * b0 + i11 * b1 + i12 * b2
            hgy = i20 * b0 + i21 * b1 + i22 * b2
            rw = rg + (hgx * (ws[w, W_X] - xg) + hgy * (ws[w, W_Y] - yg)) / hw
            out[w] = 1
        else:
            rw = b0 / a00
            out[w] = 0
        pw = eos_pressure(eos, q, rw / rho0, q[Q_E0])
        if pw < cutoff:
            pw = cutoff
            rw = density_from_pressure(eos, q, rho0, pw, q[Q_E0], rw)
        ws[w, W_RHO] = rw
        ws[w, W_P] = pw
        ws[w, W_C] = sound_speed(eos, q, rw / rho0, q[Q_E0])


@njit(cache=True, fastmath=False, error_model="numpy")
def wall_pairs(ws, twins, slip, sx, sd, mine, perm, cell_start, settings_f, settings_i, grid_f, grid_i, f_fluid, drho,
               de, f_wall):
    """The pair terms between every boundary particle w and the fluid on its face's side.

    For fluid point i within 2 h_iw on w's face's side, of the coupled part (``mine[slot]``) (grad_i W_iw = F_iw (x_i - x_w), v_iw = v_i - v_w, Pi_iw the
    Monaghan viscosity of ``rates.fluid_rates`` with the same alpha, beta, eps; with ``slip`` it sees
    only the normal part (v_iw . n_w) n_w of the relative velocity):

      F_i      = -m_i m_w (p_i/rho_i^2 + p_w/rho_w^2 + Pi_iw) grad_i W_iw     (added to f_fluid[i])
      drho_i  += rho_i V_w v_iw . grad_i W_iw      [mass form: m_w v_iw . grad_i W_iw]
      de_i    += 1/2 m_w (p_i/rho_i^2 + p_w/rho_w^2 + Pi_iw) v_iw . grad_i W_iw

    (the fluid's half of the pair work, as for fixed dummy walls in ``fluid_rates``), and the
    reaction -F_i on the boundary particle (added to f_wall[w]), so the pair forces cancel. m_w is
    weighed by 1 / k where i sees k of w's coincident group (w and its ``twins[w]``; 1 without twins). Serial
    over the boundary particles: each fluid row is written by every particle near it.

    Returns the fluid's internal power sum_i m_i (its de increments), the energy table's share.
    """
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    mform = settings_i[SI_CONTINUITY] == CONTINUITY_MASS
    alpha, beta, eps = settings_f[SF_ALPHA], settings_f[SF_BETA], settings_f[SF_EPS]
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    hmax, cell = grid_f[GF_HMAX], grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    inv_cell = 1.0 / cell
    power = 0.0
    for w in range(ws.shape[0]):
        xw, yw, zw, hw = ws[w, W_X], ws[w, W_Y], ws[w, W_Z], ws[w, W_H]
        uw, vw, ww = ws[w, W_VX], ws[w, W_VY], ws[w, W_VZ]
        nxw, nyw, nzw = ws[w, W_NX], ws[w, W_NY], ws[w, W_NZ]
        mw, rw, cw = ws[w, W_M], ws[w, W_RHO], ws[w, W_C]
        sw = ws[w, W_P] / (rw * rw)
        volw = mw / rw
        reach = hw + hmax
        x0, x1 = cell_range(xw, reach, ox, inv_cell, nx)
        y0, y1 = cell_range(yw, reach, oy, inv_cell, ny)
        z0, z1 = cell_range(zw, reach, oz, inv_cell, nz)
        fx = fy = fz = 0.0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for k in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if (int(sd[D_MK, k]) & 3) != KIND_FLUID or not mine[k]:
                        continue
                    if not _on_side(ws, w, sx[0, k], sx[1, k], sx[2, k]):
                        continue
                    dx, dy, dz = sx[0, k] - xw, sx[1, k] - yw, sx[2, k] - zw  # x_i - x_w
                    hij = 0.5 * (hw + sx[3, k])
                    r2 = dx * dx + dy * dy + dz * dz
                    if r2 >= 4.0 * hij * hij or r2 == 0.0:
                        continue
                    seen = 1
                    for t in range(twins.shape[1]):  # coincident particles of other faces that i also sees
                        o = twins[w, t]
                        if o >= 0 and _on_side(ws, o, sx[0, k], sx[1, k], sx[2, k]):
                            seen += 1
                    mwk = mw / seen
                    f = kernel_f(kernel, dim, math.sqrt(r2), hij)
                    gx, gy, gz = f * dx, f * dy, f * dz
                    du, dv, dw = sd[D_VX, k] - uw, sd[D_VY, k] - vw, sd[D_VZ, k] - ww
                    vdotg = du * gx + dv * gy + dw * gz
                    vr = du * dx + dv * dy + dw * dz
                    if slip:  # the normal part of v_iw only, in the viscosity
                        vn = du * nxw + dv * nyw + dw * nzw
                        rn = dx * nxw + dy * nyw + dz * nzw
                        vr = vn * rn
                    vr = min(vr, 0.0)
                    rhoi = sd[D_RHO, k]
                    dd = r2 + eps * hij * hij
                    rij = 0.5 * (rhoi + rw)
                    cij = 0.5 * (sd[D_C, k] + cw)
                    hv = hij * vr
                    pi_iw = hv * (beta * hv - alpha * cij * dd) / (dd * dd * rij)
                    s = sd[D_PR, k] + sw + pi_iw
                    i = perm[k]
                    mi = sd[D_VOL, k] * rhoi
                    c = mi * mwk * s
                    f_fluid[i, 0] -= c * gx
                    fx += c * gx
                    f_fluid[i, 1] -= c * gy
                    fy += c * gy
                    if dim > 2:
                        f_fluid[i, 2] -= c * gz
                        fz += c * gz
                    drho[i] += (mwk if mform else rhoi * volw / seen) * vdotg
                    dei = 0.5 * mwk * s * vdotg
                    de[i] += dei
                    power += mi * dei
        f_wall[w, 0] += fx
        f_wall[w, 1] += fy
        f_wall[w, 2] += fz
    return power
