"""`sphfem` with the boundary particles' velocity extrapolated from mDBC's ghost nodes (issue 12,
docs/studies/structure_in_water.md, "mDBC's velocity and a first-order pressure gradient"; used by
structure_in_water_gap.py's kinds sbmn / sbmf and their a01c01 twins). Study code, not in the package.

    python docs/studies/structure_in_water_mdbc_velocity.py MODE run DECK -o OUT ...

MODE "no_slip" or "slip"; DECK uses ``sph_boundary`` with ``extrapolation: mdbc`` (the ghost nodes x_g of
``structure_walls.wall_state_mdbc``). After the density of every boundary particle w is extrapolated, the fluid's
velocity at its ghost node is, with the same 3 x 3 matrix A of the first-order (Liu & Liu 2006) system tested with W
and grad W (r_j = x_j - x_g, over the fluid points on w's face's side, both faces' sides for a vertex ghost),

    A (v_g, h_w grad v_g) = (sum_j V_j v_j W_gj, sum_j V_j v_j h_w grad W_gj)      for each velocity component

(the Shepard mean sum V v W / sum V W where A fails the mDBC's conditions: sum V W < 0.1 or condition number > 50;
the wall's velocity where no fluid is seen), and the particle takes, with v_wall its face's velocity (``place``) and
n_w its face's outward normal,

    no_slip:  v_w = 2 v_wall - v_g                                   (the velocity mirrored through the wall)
    slip:     v_w = v_g - 2 ((v_g - v_wall) . n_w) n_w               (the normal relative velocity mirrored, the
                                                                       tangential kept: no shear at the wall)

(English, Crespo, Rogers, Dominguez, Moxley & Gomez-Gesteira 2022, Comp. Part. Mech. 9, 1, and Adami, Hu & Adams
2012, J. Comput. Phys. 231, 7057, eq. 22-23, where the Shepard mean of the fluid round the boundary particle takes
the ghost's place). v_w replaces the wall's velocity in every pair term of ``structure_walls.wall_pairs``: the
viscous term (zero here: alpha = beta = 0, Pi_iw = h v.r (beta h v.r - alpha c dd) / ... vanishes identically), the
continuity term drho_i += rho_i V_w (v_i - v_w) . grad_i W_iw and the fluid's half of the pair work de_i. The
reaction on the structure is unchanged (the pressure force), so the pair work booked on the fluid's side is no longer
the nodes' work: the energy table shows the difference.
"""
import math
import sys

import numpy as np
from numba import njit

from sphfem_cli.sph import structure_walls as sw
from sphfem_cli.sph.kernel_functions import kernel_f, kernel_w
from sphfem_cli.sph.search import cell_range
from sphfem_cli.sph.slots import (D_MK, D_VOL, D_VX, D_VY, GF_CELL, GF_HMAX, GF_OX, GF_OY, GF_OZ, GI_NX, GI_NY,
                                  GI_NZ, KIND_FLUID, SI_DIM, SI_KERNEL)

MODES = {"no_slip": 0, "slip": 1}
MODE = MODES[sys.argv[1]] if __name__ == "__main__" else 0
_wall_state_mdbc = sw.wall_state_mdbc


@njit(cache=True)
def ghost_velocity(ws, side2, sx, sd, mine, cell_start, settings_i, grid_f, grid_i, mode, order):
    """Overwrite ws[:, W_VX:W_VY + 1] (the wall's velocity at the particle, from ``place``) by v_w of the module's
    docstring; ``order[w]`` 1 first order, 0 Shepard, -1 no fluid seen (2D)."""
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    hmax, cell = grid_f[GF_HMAX], grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    inv_cell = 1.0 / cell
    for w in range(ws.shape[0]):
        xg, yg, zg, hw = ws[w, sw.W_GX], ws[w, sw.W_GY], ws[w, sw.W_GZ], ws[w, sw.W_H]
        o = side2[w]
        reach = hw + hmax
        x0, x1 = cell_range(xg, reach, ox, inv_cell, nx)
        y0, y1 = cell_range(yg, reach, oy, inv_cell, ny)
        z0, z1 = cell_range(zg, reach, oz, inv_cell, nz)
        a = np.zeros((3, 3))
        b = np.zeros((3, 2))
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if (int(sd[D_MK, j]) & 3) != KIND_FLUID or not mine[j]:
                        continue
                    if not sw._on_side(ws, w, sx[0, j], sx[1, j], sx[2, j]):
                        if o < 0 or not sw._on_side(ws, o, sx[0, j], sx[1, j], sx[2, j]):
                            continue
                    rx, ry = sx[0, j] - xg, sx[1, j] - yg
                    hij = 0.5 * (hw + sx[3, j])
                    r2 = rx * rx + ry * ry + (sx[2, j] - zg) ** 2
                    if r2 >= 4.0 * hij * hij:
                        continue
                    r = math.sqrt(r2)
                    wv = kernel_w(kernel, dim, r, hij)
                    f = kernel_f(kernel, dim, r, hij) * hw
                    t = (wv, -f * rx, -f * ry)  # W, h grad_g W
                    s = (1.0, rx / hw, ry / hw)
                    vj = sd[D_VOL, j]
                    for p in range(3):
                        for q in range(3):
                            a[p, q] += vj * t[p] * s[q]
                        b[p, 0] += vj * t[p] * sd[D_VX, j]
                        b[p, 1] += vj * t[p] * sd[D_VY, j]
        uwx, uwy = ws[w, sw.W_VX], ws[w, sw.W_VY]
        if a[0, 0] <= 0.0:
            order[w] = -1
            continue
        first = False
        gx = gy = 0.0
        if a[0, 0] >= sw.MDBC_SUM_MIN:
            det = np.linalg.det(a)
            if det != 0.0:
                inv = np.linalg.inv(a)
                cond = np.abs(a).sum(axis=1).max() * np.abs(inv).sum(axis=1).max()
                if cond <= sw.MDBC_COND_MAX:
                    first = True
                    sol = inv @ b
                    gx, gy = sol[0, 0], sol[0, 1]
        if not first:
            gx, gy = b[0, 0] / a[0, 0], b[0, 1] / a[0, 0]
        order[w] = 1 if first else 0
        if mode == 0:
            ws[w, sw.W_VX], ws[w, sw.W_VY] = 2.0 * uwx - gx, 2.0 * uwy - gy
        else:
            nxw, nyw = ws[w, sw.W_NX], ws[w, sw.W_NY]
            vn = (gx - uwx) * nxw + (gy - uwy) * nyw
            ws[w, sw.W_VX], ws[w, sw.W_VY] = gx - 2.0 * vn * nxw, gy - 2.0 * vn * nyw


def wall_state_mdbc(ws, side2, mat, sx, sd, mine, cell_start, settings_f, settings_i, grid_f, grid_i, params, out,
                    cond_out):
    _wall_state_mdbc(ws, side2, mat, sx, sd, mine, cell_start, settings_f, settings_i, grid_f, grid_i, params, out,
                     cond_out)
    ghost_velocity(ws, side2, sx, sd, mine, cell_start, settings_i, grid_f, grid_i, MODE,
                   np.zeros(ws.shape[0], dtype=np.int64))


if __name__ == "__main__":
    sw.wall_state_mdbc = wall_state_mdbc
    from sphfem_cli.cli import main
    main(sys.argv[2:], prog_name="sphfem")
