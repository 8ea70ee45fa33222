"""`sphfem` with a first-order consistent (kernel-gradient-corrected) pressure gradient and continuity for the water
next to the structure of every ``sph_boundary`` coupling (issue 12, docs/studies/structure_in_water.md, "mDBC's
velocity and a first-order pressure gradient"; used by structure_in_water_gap.py's kinds sbk / sbka and their a01c01
twins). Study code, not in the package.

    python docs/studies/structure_in_water_kgc.py [all [nowall]] run DECK -o OUT ...

For every water point i that sees a boundary particle (within 2 h on the particle's face's side), the moment matrix
over its water neighbours j and the boundary particles w it sees (each coincident group behind a convex corner
weighed 1 / k, as ``structure_walls.wall_pairs`` weighs them),

    M_i = sum_j V_j (x_j - x_i) (x) grad_i W_ij        (the identity for a full support; Bonet & Lok 1999, Comput.
                                                          Methods Appl. Mech. Engrg. 180, 97; Randles & Libersky 1996)

gives the corrected kernel gradient L_i grad_i W_ij with L_i = M_i^-T (then sum_j V_j (f_j - f_i) L_i grad_i W_ij is
exact for a linear f; M_i is inverted where det M_i >= 1/4 (tr M_i / 2)^2, as ``sph.expansion``; else L_i = I, e.g.
at the free surface). Every pair then uses the symmetrised gradient (Oger et al. 2007's form, so the pair forces stay
antisymmetric) g~_ij = (L_i + L_j) / 2 grad_i W_ij, with L = I for the points that see no boundary particle and for
the boundary particles, in the pressure term and in the continuity term:

    F_i     = -m_i m_j (p_i / rho_i^2 + p_j / rho_j^2) g~_ij
    drho_i  = rho_i V_j v_ij . g~_ij                   (the decks' volume form; m_j v_ij . g~_ij in the mass form)
    de_i    = 1/2 m_j (p_i / rho_i^2 + p_j / rho_j^2) v_ij . g~_ij

so the pressure work and the internal energy stay one pair's (energy conserved by the pair, as with the plain
gradient). This script adds the difference g~_ij - grad_i W_ij = ((L_i - I) + (L_j - I)) / 2 grad_i W_ij to the
rates after ``fluid_rates`` and ``wall_pairs``: the water pairs' part to ``acc``, ``drho``, ``de`` (a pair of water
points: no external work), the boundary pairs' part to the coupling's ``f_fluid``, ``f_wall`` and its fluid power
(booked as ``wall_pairs``' own). The viscous and density-diffusion terms are unchanged (alpha = 0 in these decks).

On a lattice the bulk's own moment is not exactly I (cubic spline, h/dx 1.2: L - I about 0.009 per entry), so the
correction restricted to the water next to the plate scales its gradient by about 1 % against the bulk's; with "all"
every water point of the part whose M has a smaller eigenvalue of at least EIG_MIN (0.9: a nearly full support, the
corners' water included; not the free surface) is corrected too (kinds sbka / sbkaa01c01); "all nowall" leaves
the boundary pairs' gradient plain (kind sbkan, the diagnostic of the ratio-5 instability).
"""
import math
import sys

import numpy as np
from numba import njit

from sphfem_cli.contact.sph_boundary import SphBoundaryCoupling
from sphfem_cli.sph import structure_walls as sw
from sphfem_cli.sph.kernel_functions import kernel_f
from sphfem_cli.sph.search import cell_range
from sphfem_cli.sph.slots import (CONTINUITY_MASS, D_MK, D_PR, D_RHO, D_VOL, D_VX, D_VY, GF_CELL, GF_HMAX, GF_OX,
                                  GF_OY, GF_OZ, GI_NX, GI_NY, GI_NZ, KIND_FLUID, SI_CONTINUITY, SI_DIM, SI_KERNEL)

EVERYWHERE = __name__ == "__main__" and sys.argv[1] == "all"
WALLS = not (__name__ == "__main__" and sys.argv[2] == "nowall")  # "all nowall": the boundary pairs uncorrected
EIG_MIN = 0.9  # "all": the water points corrected (a full support has M = I up to the lattice's own 1 %)
_wall_pairs = sw.wall_pairs
_forces = SphBoundaryCoupling.forces
STATE = {}


@njit(cache=True)
def _seen(ws, twins, w, x, y):
    """1 / k: the weight of boundary particle w for a fluid point at (x, y) that sees k of its coincident group."""
    seen = 1.0
    for t in range(twins.shape[1]):
        o = twins[w, t]
        if o >= 0 and sw._on_side(ws, o, x, y, 0.0):
            seen += 1.0
    return 1.0 / seen


@njit(cache=True)
def correction_matrices(ws, twins, sx, sd, mine, cell_start, settings_i, grid_f, grid_i, lmat, everywhere=False):
    """lmat[k] = L_k - I (2 x 2) for every fluid slot k that sees a boundary particle (0 elsewhere); returns the
    number of such slots and how many of them fell back on L = I. With ``everywhere`` every fluid slot of the
    coupling's part is corrected (the boundary particles in M where it sees them), where M_k's smaller eigenvalue is
    at least EIG_MIN (a nearly full support: not at the free surface)."""
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    hmax, cell = grid_f[GF_HMAX], grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    inv_cell = 1.0 / cell
    near = np.zeros(sx.shape[1], dtype=np.bool_)
    for w in range(ws.shape[0]):  # the fluid slots within 2 h_wf of a boundary particle, on its face's side
        xw, yw, hw = ws[w, sw.W_X], ws[w, sw.W_Y], ws[w, sw.W_H]
        x0, x1 = cell_range(xw, hw + hmax, ox, inv_cell, nx)
        y0, y1 = cell_range(yw, hw + hmax, oy, inv_cell, ny)
        z0, z1 = cell_range(ws[w, sw.W_Z], hw + hmax, oz, inv_cell, nz)
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for k in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if (int(sd[D_MK, k]) & 3) != KIND_FLUID or not mine[k]:
                        continue
                    if not sw._on_side(ws, w, sx[0, k], sx[1, k], sx[2, k]):
                        continue
                    hij = 0.5 * (hw + sx[3, k])
                    if (sx[0, k] - xw) ** 2 + (sx[1, k] - yw) ** 2 < 4.0 * hij * hij:
                        near[k] = True
    count = fallback = 0
    lmat[:] = 0.0
    for k in range(sx.shape[1]):
        if not near[k] and not (everywhere and (int(sd[D_MK, k]) & 3) == KIND_FLUID and mine[k]):
            continue
        count += 1
        xi, yi, hi = sx[0, k], sx[1, k], sx[3, k]
        m00 = m01 = m10 = m11 = 0.0  # M[a, b] = sum V (x_j - x_i)_a (grad_i W_ij)_b
        x0, x1 = cell_range(xi, hi + hmax, ox, inv_cell, nx)
        y0, y1 = cell_range(yi, hi + hmax, oy, inv_cell, ny)
        z0, z1 = cell_range(sx[2, k], hi + hmax, oz, inv_cell, nz)
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if j == k or (int(sd[D_MK, j]) & 3) != KIND_FLUID or not mine[j]:
                        continue
                    dx, dy = xi - sx[0, j], yi - sx[1, j]
                    hij = 0.5 * (hi + sx[3, j])
                    r2 = dx * dx + dy * dy
                    if r2 >= 4.0 * hij * hij or r2 == 0.0:
                        continue
                    f = kernel_f(kernel, dim, math.sqrt(r2), hij) * sd[D_VOL, j]
                    m00 -= dx * f * dx
                    m01 -= dx * f * dy
                    m10 -= dy * f * dx
                    m11 -= dy * f * dy
        for w in range(ws.shape[0] if near[k] else 0):
            if not sw._on_side(ws, w, xi, yi, sx[2, k]):
                continue
            dx, dy = xi - ws[w, sw.W_X], yi - ws[w, sw.W_Y]
            hij = 0.5 * (hi + ws[w, sw.W_H])
            r2 = dx * dx + dy * dy
            if r2 >= 4.0 * hij * hij or r2 == 0.0:
                continue
            f = (kernel_f(kernel, dim, math.sqrt(r2), hij) * ws[w, sw.W_M] / ws[w, sw.W_RHO]
                 * _seen(ws, twins, w, xi, yi))
            m00 -= dx * f * dx
            m01 -= dx * f * dy
            m10 -= dy * f * dx
            m11 -= dy * f * dy
        det = m00 * m11 - m01 * m10
        tr = m00 + m11
        if det < 0.25 * (0.5 * tr) ** 2 or det <= 0.0:
            fallback += 1
            continue
        if everywhere:  # the smaller eigenvalue of M's symmetric part
            b, c = 0.5 * (m01 + m10), 0.5 * (m00 - m11)
            if 0.5 * tr - math.sqrt(c * c + b * b) < EIG_MIN:
                fallback += 1
                continue
        # L = M^-T
        lmat[k, 0, 0] = m11 / det - 1.0
        lmat[k, 0, 1] = -m10 / det
        lmat[k, 1, 0] = -m01 / det
        lmat[k, 1, 1] = m00 / det - 1.0
    return count, fallback


@njit(cache=True)
def add_correction(ws, twins, sx, sd, mine, perm, cell_start, settings_i, grid_f, grid_i, lmat, acc, f_fluid, drho,
                   de, f_wall, walls=True):
    """Add the pair terms with g~_ij - grad_i W_ij (module docstring) for every fluid slot k with lmat[k] != 0:
    its half (L_k - I) / 2 grad_k W_kj of every pair, to both points. Returns the boundary pairs' fluid power
    sum m_i de_i (``wall_pairs``' share). ``walls`` False: the boundary pairs keep the plain gradient (L_k = I in them)."""
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    mform = settings_i[SI_CONTINUITY] == CONTINUITY_MASS
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    hmax, cell = grid_f[GF_HMAX], grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    inv_cell = 1.0 / cell
    power = 0.0
    bx0 = by0 = np.inf  # the boundary particles' box widened by the largest support: no pair outside it
    bx1 = by1 = -np.inf
    for w in range(ws.shape[0]):
        bx0, bx1 = min(bx0, ws[w, sw.W_X]), max(bx1, ws[w, sw.W_X])
        by0, by1 = min(by0, ws[w, sw.W_Y]), max(by1, ws[w, sw.W_Y])
    bx0, bx1, by0, by1 = bx0 - 2.0 * hmax, bx1 + 2.0 * hmax, by0 - 2.0 * hmax, by1 + 2.0 * hmax
    for k in range(sx.shape[1]):
        l00, l01, l10, l11 = lmat[k, 0, 0], lmat[k, 0, 1], lmat[k, 1, 0], lmat[k, 1, 1]
        if l00 == 0.0 and l01 == 0.0 and l10 == 0.0 and l11 == 0.0:
            continue
        i = perm[k]
        xi, yi, hi = sx[0, k], sx[1, k], sx[3, k]
        rhoi, voli, si = sd[D_RHO, k], sd[D_VOL, k], sd[D_PR, k]
        mi = voli * rhoi
        x0, x1 = cell_range(xi, hi + hmax, ox, inv_cell, nx)
        y0, y1 = cell_range(yi, hi + hmax, oy, inv_cell, ny)
        z0, z1 = cell_range(sx[2, k], hi + hmax, oz, inv_cell, nz)
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for jj in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if jj == k or (int(sd[D_MK, jj]) & 3) != KIND_FLUID or not mine[jj]:
                        continue
                    dx, dy = xi - sx[0, jj], yi - sx[1, jj]
                    hij = 0.5 * (hi + sx[3, jj])
                    r2 = dx * dx + dy * dy
                    if r2 >= 4.0 * hij * hij or r2 == 0.0:
                        continue
                    f = kernel_f(kernel, dim, math.sqrt(r2), hij)
                    wx, wy = f * dx, f * dy  # grad_i W_ij
                    gx, gy = 0.5 * (l00 * wx + l01 * wy), 0.5 * (l10 * wx + l11 * wy)
                    j = perm[jj]
                    rhoj, volj = sd[D_RHO, jj], sd[D_VOL, jj]
                    mj = volj * rhoj
                    s = si + sd[D_PR, jj]
                    acc[i, 0] -= mj * s * gx
                    acc[i, 1] -= mj * s * gy
                    acc[j, 0] += mi * s * gx
                    acc[j, 1] += mi * s * gy
                    vg = (sd[D_VX, k] - sd[D_VX, jj]) * gx + (sd[D_VY, k] - sd[D_VY, jj]) * gy
                    drho[i] += (mj if mform else rhoi * volj) * vg
                    drho[j] += (mi if mform else rhoj * voli) * vg
                    de[i] += 0.5 * mj * s * vg
                    de[j] += 0.5 * mi * s * vg
        inside = walls and bx0 <= xi <= bx1 and by0 <= yi <= by1
        for w in range(ws.shape[0] if inside else 0):
            if not sw._on_side(ws, w, xi, yi, sx[2, k]):
                continue
            dx, dy = xi - ws[w, sw.W_X], yi - ws[w, sw.W_Y]
            hij = 0.5 * (hi + ws[w, sw.W_H])
            r2 = dx * dx + dy * dy
            if r2 >= 4.0 * hij * hij or r2 == 0.0:
                continue
            f = kernel_f(kernel, dim, math.sqrt(r2), hij)
            wx, wy = f * dx, f * dy
            gx, gy = 0.5 * (l00 * wx + l01 * wy), 0.5 * (l10 * wx + l11 * wy)
            rw = ws[w, sw.W_RHO]
            mw = ws[w, sw.W_M] * _seen(ws, twins, w, xi, yi)
            s = si + ws[w, sw.W_P] / (rw * rw)
            c = mi * mw * s
            f_fluid[i, 0] -= c * gx
            f_fluid[i, 1] -= c * gy
            f_wall[w, 0] += c * gx
            f_wall[w, 1] += c * gy
            vg = (sd[D_VX, k] - ws[w, sw.W_VX]) * gx + (sd[D_VY, k] - ws[w, sw.W_VY]) * gy
            drho[i] += (mw if mform else rhoi * mw / rw) * vg
            dei = 0.5 * mw * s * vg
            de[i] += dei
            power += mi * dei
    return power


def wall_pairs(ws, twins, slip, sx, sd, mine, perm, cell_start, settings_f, settings_i, grid_f, grid_i, f_fluid, drho,
               de, f_wall):
    power = _wall_pairs(ws, twins, slip, sx, sd, mine, perm, cell_start, settings_f, settings_i, grid_f, grid_i,
                        f_fluid, drho, de, f_wall)
    ps = STATE["ps"]
    lmat = np.zeros((sx.shape[1], 2, 2))
    count, fallback = correction_matrices(ws, twins, sx, sd, mine, cell_start, settings_i, grid_f, grid_i, lmat,
                                          EVERYWHERE)
    STATE["corrected"] = STATE.get("corrected", 0) + count - fallback
    STATE["fallback"] = STATE.get("fallback", 0) + fallback
    return power + add_correction(ws, twins, sx, sd, mine, perm, cell_start, settings_i, grid_f, grid_i, lmat,
                                  ps.acc, f_fluid, drho, de, f_wall, WALLS)


def forces(self, st) -> None:
    STATE["ps"] = self.sim.particles.system
    _forces(self, st)


def install() -> None:
    sw.wall_pairs = wall_pairs
    SphBoundaryCoupling.forces = forces


if __name__ == "__main__":
    install()
    from sphfem_cli.cli import main
    main(sys.argv[1 + (sys.argv[1] == "all") + (sys.argv[2] == "nowall"):], prog_name="sphfem")
