"""SPH neighbour search: the cell-linked list (counting sort of the points by cell), the
cell-ordered point set every pair loop reads, and CSR neighbour lists.

Arrays and scalars only (no objects, no I/O), like every kernel module of ``sph/``
(``kernel_functions``, ``search``, ``walls``, ``rates``, ``integration``, ``eos``; slot names in
``slots``). ``sph/system.py`` orchestrates them; equations and references are in
``docs/theory/sph.md``; ``sph/reference.py`` holds short NumPy versions that the tests compare
against.

Points. One evaluation works on a list of *points*: the active real particles (point id = particle
index ``i < n``), the ghost (mirror) particles of the planar walls (``n + g``) and the fixed dummy
wall particles (``n + ng + w``). Every point carries a kind (``KIND_FLUID``, ``KIND_GHOST``,
``KIND_WALL``) and a material id, packed as ``mat * 4 + kind`` in one float column.

Layout of an evaluation, all in cell order (slot ``k`` holds point ``perm[k]``), structure of arrays:
one row per quantity, one column per slot, so that a run of slots is a run of memory in every row:

* ``sx`` (4, width): x, y, z, h (coordinates padded with 0 above the dimension);
* ``sd`` (ND, width): vx, vy, vz, rho, V = m/rho, p/rho^2, c, mat*4+kind (rows ``D_*``);
  for both, columns ``0 .. npts - 1`` are the points, column ``npts`` the sentinel (a point far from
  everything whose every pair term is exactly 0) and ``npts + 1 .. npts + N_SENTINEL - 1`` copies of
  it; the width may be larger (the storage is reused from one evaluation to the next, ``sort_points``)
  and the columns beyond are not read;
* ``stau`` (npts, 6): viscous stress tau (xx, yy, zz, xy, yz, zx), only when a material has
  viscosity (otherwise a (1, 6) dummy);
* ``cell_start`` (ncell + 1): slots of cell ``key`` are ``cell_start[key]:cell_start[key+1]`` with
  ``key = (cz*ny + cy)*nx + cx``; a row of cells along x is one contiguous slot range;
* ``sreach`` (npts + 1): the search radius of every slot, ``sreach[k] = h_k + H_k`` with H_k an
  upper bound of the h_j of every neighbour j (|x_k - x_j| < 2 h_kj = h_k + h_j); the pair loops
  scan the cells within ``sreach[k]`` of slot k (``search_reach`` and the grid choice below);
* ``grid_f``, ``grid_i``: hmax, cell width and origin; nx, ny, nz (slots ``GF_*``, ``GI_*``),
  written by ``sort_points``.

Grid and reach (``bin_points``, ``search_reach``). With nearly uniform smoothing lengths
(hmax <= ``SPREAD`` hmin) the cells are hmax wide and H_k = hmax for every slot (the plain
cell-linked list). With a wider spread (the explosive products of an underwater explosion grow to
several times the water's h) a search sized by hmax makes every small-h particle scan the large
particles' area; then the cells are hmin wide (at least hmax / ``MAX_ROWS``) and H_k is local:
H_k = max(h_k, T, G[cell of k]) with T = ``SPREAD_FLOOR`` hmin and G[c] the largest h of the cells
with some point of h > T whose 2 h-box covers cell c. Proof that no neighbour is lost: if
h_j <= max(h_k, T), then h_k + h_j <= sreach[k]; else h_j > h_k, so |x_k - x_j| < 2 h_j and the
cell of k lies in the 2 h_j-box of j's cell, whence G >= h_j. The pair test itself is unchanged,
so the neighbour set is the same as the plain search's; only the slot order (and so the order of
the neighbour sums) differs when the grid does.

Pair quantities use h_ij = (h_i + h_j)/2, which keeps the pair forces antisymmetric (momentum is
conserved to round-off). Every pair loop is a gather over the slots (``prange``): slot ``k``
writes only its own entries, so results do not depend on the number of threads.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .slots import (D_C, D_MK, D_PR, D_RHO, D_VOL, D_VX, D_VY, D_VZ, GF_CELL, GF_HMAX, GF_OX, GF_OY, GF_OZ,
                    GI_NX, GI_NY, GI_NZ, KIND_FLUID, KIND_GHOST, KIND_WALL, N_SENTINEL, ND)

SPREAD = 2.0  # hmax / hmin above which the cells are sized by hmin and the reach is local
SPREAD_FLOOR = 1.5  # T / hmin: points of h <= T are not spread into G (their h is bounded by T)
MAX_ROWS = 8.0  # the cell is at least hmax / MAX_ROWS wide (bounds the cell rows a large point scans)


@njit(cache=True)
def bin_points(x, h, active, gpos, gsrc, wpos, wh, max_cells_per_point):
    """Counting sort of all points by cell.

    Returns ``perm`` (slot -> point id), ``cell_start``, the grid ``(ox, oy, oz, cell)``,
    ``(nx, ny, nz)``, hmax and hmin. The cell width is hmax (half the largest support 2 hmax) if
    hmax <= ``SPREAD`` hmin, else max(hmin, hmax / ``MAX_ROWS``) (module docstring), widened if the
    bounding box would need more than ``max_cells_per_point`` cells per point. The sort is
    stable: within a cell points keep increasing point id, so the order is deterministic.
    """
    n = x.shape[0]
    dim = x.shape[1]
    ng = gpos.shape[0]
    nw = wpos.shape[0]
    lo = np.full(3, np.inf)
    hi = np.full(3, -np.inf)
    lo[dim:] = 0.0
    hi[dim:] = 0.0
    hmax = 0.0
    hmin = np.inf
    npts = ng + nw
    for i in range(n):
        if active[i]:
            npts += 1
            for d in range(dim):
                lo[d] = min(lo[d], x[i, d])
                hi[d] = max(hi[d], x[i, d])
            hmax = max(hmax, h[i])
            hmin = min(hmin, h[i])
    for g in range(ng):
        for d in range(dim):
            lo[d] = min(lo[d], gpos[g, d])
            hi[d] = max(hi[d], gpos[g, d])
    for w in range(nw):
        for d in range(dim):
            lo[d] = min(lo[d], wpos[w, d])
            hi[d] = max(hi[d], wpos[w, d])
        hmax = max(hmax, wh[w])
        hmin = min(hmin, wh[w])
    if npts == 0:
        lo[:] = 0.0
        hi[:] = 0.0
        hmax = 1.0
    if not hmin <= hmax:  # no point (or a NaN h): the plain grid
        hmin = hmax
    cell = hmax if hmax <= SPREAD * hmin else max(hmin, hmax / MAX_ROWS)
    nc = np.ones(3, dtype=np.int64)
    while True:
        total = 1
        for d in range(dim):
            nc[d] = int((hi[d] - lo[d]) / cell) + 1
            total *= nc[d]
        if total <= max_cells_per_point * npts + 64:
            break
        cell *= 1.5
    nx, ny, nz = nc[0], nc[1], nc[2]
    ntot = n + ng + nw
    keys = np.full(ntot, -1, dtype=np.int64)
    counts = np.zeros(total + 1, dtype=np.int64)
    inv = 1.0 / cell
    for pid in range(ntot):
        if pid < n:
            if not active[pid]:
                continue
            c0 = int((x[pid, 0] - lo[0]) * inv)
            c1 = int((x[pid, 1] - lo[1]) * inv)
            c2 = int((x[pid, 2] - lo[2]) * inv) if dim > 2 else 0
        else:
            if pid < n + ng:
                g = pid - n
                a0, a1, a2 = gpos[g, 0], gpos[g, 1], gpos[g, 2]
            else:
                w = pid - n - ng
                a0 = wpos[w, 0]
                a1 = wpos[w, 1]
                a2 = wpos[w, 2] if dim > 2 else 0.0
            c0 = int((a0 - lo[0]) * inv)
            c1 = int((a1 - lo[1]) * inv)
            c2 = int((a2 - lo[2]) * inv) if dim > 2 else 0
        c0 = min(max(c0, 0), nx - 1)
        c1 = min(max(c1, 0), ny - 1)
        c2 = min(max(c2, 0), nz - 1)
        key = (c2 * ny + c1) * nx + c0
        keys[pid] = key
        counts[key + 1] += 1
    for kk in range(total):
        counts[kk + 1] += counts[kk]
    cell_start = counts.copy()
    perm = np.empty(npts, dtype=np.int64)
    for pid in range(ntot):
        key = keys[pid]
        if key >= 0:
            perm[counts[key]] = pid
            counts[key] += 1
    return perm, cell_start, lo[0], lo[1], lo[2], cell, nx, ny, nz, hmax, hmin


@njit(cache=True)
def gather_points(perm, x, v, rho, m, p, c, h, mat, gpos, gvel, gsrc, gdp, gdr,
                  wpos, wvel, wrho, wm, wh, wmat, sx, sd):
    """Copy every point's data into cell order (``sx``, ``sd``; layout in the module docstring).

    Wall points get their material's reference density, zero pressure and the EOS sound speed
    here; ``wall_pressure`` overwrites them.
    """
    n = x.shape[0]
    dim = x.shape[1]
    ng = gpos.shape[0]
    for k in range(perm.shape[0]):
        pid = perm[k]
        if pid < n:
            i = pid
            sx[0, k] = x[i, 0]
            sx[1, k] = x[i, 1]
            sx[2, k] = x[i, 2] if dim > 2 else 0.0
            sx[3, k] = h[i]
            sd[D_VX, k] = v[i, 0]
            sd[D_VY, k] = v[i, 1]
            sd[D_VZ, k] = v[i, 2] if dim > 2 else 0.0
            r = rho[i]
            sd[D_RHO, k] = r
            sd[D_VOL, k] = m[i] / r
            sd[D_PR, k] = p[i] / (r * r)
            sd[D_C, k] = c[i]
            sd[D_MK, k] = mat[i] * 4 + KIND_FLUID
        elif pid < n + ng:
            g = pid - n
            i = gsrc[g]
            sx[0, k], sx[1, k], sx[2, k] = gpos[g, 0], gpos[g, 1], gpos[g, 2]
            sx[3, k] = h[i]
            sd[D_VX, k], sd[D_VY, k], sd[D_VZ, k] = gvel[g, 0], gvel[g, 1], gvel[g, 2]
            r = rho[i] + gdr[g]
            sd[D_RHO, k] = r
            sd[D_VOL, k] = m[i] / r
            sd[D_PR, k] = (p[i] + gdp[g]) / (r * r)
            sd[D_C, k] = c[i]
            sd[D_MK, k] = mat[i] * 4 + KIND_GHOST
        else:
            w = pid - n - ng
            sx[0, k] = wpos[w, 0]
            sx[1, k] = wpos[w, 1]
            sx[2, k] = wpos[w, 2] if dim > 2 else 0.0
            sx[3, k] = wh[w]
            sd[D_VX, k] = wvel[w, 0]
            sd[D_VY, k] = wvel[w, 1]
            sd[D_VZ, k] = wvel[w, 2] if dim > 2 else 0.0
            sd[D_RHO, k] = wrho[w]
            sd[D_VOL, k] = wm[w] / wrho[w]
            sd[D_PR, k] = 0.0
            sd[D_C, k] = 0.0
            sd[D_MK, k] = wmat[w] * 4 + KIND_WALL


@njit(cache=True)
def search_reach(sx, cell_start, cell, ox, oy, oz, nx, ny, nz, dim, hmax, hmin, sreach):
    """Search radius ``sreach[k] = h_k + H_k`` of every slot (H_k: module docstring).

    H_k = hmax for every slot when hmax <= ``SPREAD`` hmin (the plain search); otherwise
    H_k = max(h_k, T, G[cell of k]), T = ``SPREAD_FLOOR`` hmin, G[c] = max h over the cells c' whose
    largest h exceeds T and whose box widened by 2 h (plus a hundredth of a cell against round-off
    in the cell indices) covers cell c. The sentinel (last) slot gets 0.
    """
    npts = cell_start[-1]
    sreach[npts] = 0.0
    if hmax <= SPREAD * hmin:
        for k in range(npts):
            sreach[k] = sx[3, k] + hmax
        return
    floor = SPREAD_FLOOR * hmin
    total = cell_start.shape[0] - 1
    grow = np.zeros(total)
    inv = 1.0 / cell
    for key in range(total):
        hc = 0.0
        for k in range(cell_start[key], cell_start[key + 1]):
            hc = max(hc, sx[3, k])
        if hc <= floor:
            continue
        cx = key % nx
        cy = (key // nx) % ny
        cz = key // (nx * ny)
        w = 2.0 * hc + 0.01 * cell
        x0, x1 = cell_range(ox + (cx + 0.5) * cell, 0.5 * cell + w, ox, inv, nx)
        y0, y1 = cell_range(oy + (cy + 0.5) * cell, 0.5 * cell + w, oy, inv, ny)
        z0, z1 = cell_range(oz + (cz + 0.5) * cell, 0.5 * cell + w, oz, inv, nz) if dim > 2 else (0, 0)
        for bz in range(z0, z1 + 1):
            for by in range(y0, y1 + 1):
                base = (bz * ny + by) * nx
                for bx in range(x0, x1 + 1):
                    if grow[base + bx] < hc:
                        grow[base + bx] = hc
    for key in range(total):
        g = max(grow[key], floor)
        for k in range(cell_start[key], cell_start[key + 1]):
            hk = sx[3, k]
            sreach[k] = hk + max(hk, g)


@njit(cache=True)
def sort_points(x, v, rho, m, p, c, h, mat, active, gpos, gvel, gsrc, gdp, gdr,
                wpos, wvel, wrho, wm, wh, wmat, max_cells_per_point, grid_f, grid_i, sx, sd):
    """Cell-sort all points (``bin_points``), copy their data into cell order (``gather_points``)
    and set every slot's search radius (``search_reach``).

    Returns ``(perm, cell_start, sreach, sx, sd)``: ``sx`` (4, width) and ``sd`` (ND, width), one column per
    slot (layout in the module docstring), two arrays of their own: columns
    ``npts .. npts + N_SENTINEL - 1`` (npts = len(perm)) hold the sentinel, a point far from everything
    (1e30 in every coordinate) with zero volume and kind wall, whose every pair term is exactly 0;
    ``sreach`` has npts + 1 entries, the last one the sentinel's. The ``sx`` and ``sd`` passed in are
    reused from one evaluation to the next: fresh zeroed ones 5/4 as wide as needed are made (and
    returned) only when those passed in are too narrow. (Two arrays, not two views of one: a checkpoint
    restores them as they are and the restored run reuses them, bit-identical to the one it continues.) (A fresh 50 MB array at every step of 5e5 particles costs
    its page faults and zeroing; startup17 report, section 3.)
    Writes the grid (hmax, cell, origin; nx, ny, nz) into ``grid_f`` and ``grid_i``.
    """
    perm, cell_start, ox, oy, oz, cell, nx, ny, nz, hmax, hmin = bin_points(x, h, active, gpos, gsrc, wpos, wh,
                                                                            max_cells_per_point)
    npts = perm.shape[0]
    width = npts + N_SENTINEL
    if sx.shape[0] != 4 or sd.shape[0] != ND or sx.shape[1] < width or sd.shape[1] != sx.shape[1]:
        sx = np.zeros((4, width + width // 4))
        sd = np.zeros((ND, width + width // 4))
    gather_points(perm, x, v, rho, m, p, c, h, mat, gpos, gvel, gsrc, gdp, gdr, wpos, wvel, wrho, wm, wh, wmat, sx, sd)
    for k in range(npts, width):
        sx[0, k] = 1e30
        sx[1, k] = 1e30
        sx[2, k] = 1e30
        sx[3, k] = 1.0
        for d in range(ND):
            sd[d, k] = 0.0
        sd[D_RHO, k] = 1.0
        sd[D_C, k] = 1.0
        sd[D_MK, k] = KIND_WALL
    sreach = np.empty(npts + 1)
    search_reach(sx, cell_start, cell, ox, oy, oz, nx, ny, nz, x.shape[1], hmax, hmin, sreach)
    grid_f[GF_HMAX] = hmax
    grid_f[GF_CELL] = cell
    grid_f[GF_OX] = ox
    grid_f[GF_OY] = oy
    grid_f[GF_OZ] = oz
    grid_i[GI_NX] = nx
    grid_i[GI_NY] = ny
    grid_i[GI_NZ] = nz
    return perm, cell_start, sreach, sx, sd


@njit(cache=True, fastmath=False)  # called from fast-math kernels too (see rates._FM)
def cell_range(v, reach, o, inv_cell, n):
    """Cells ``lo..hi`` (clipped to ``0..n-1``) along one axis that hold points within ``reach`` of ``v``."""
    lo = int(math.floor((v - reach - o) * inv_cell))
    hi = int(math.floor((v + reach - o) * inv_cell))
    if lo < 0:
        lo = 0
    if hi > n - 1:
        hi = n - 1
    return lo, hi


@njit(cache=True, inline="always", error_model="numpy")
def neighbour_list(nbj, k, xi, yi, zi, hi, reach, sx, cell_start, grid_o, inv_cell, grid_n, dshape, pad):
    """Neighbour slots of slot ``k`` into ``nbj``, found without branches: returns ``(cnt, npad)``.

    Scans the cell rows within ``reach`` of (xi, yi, zi) (a row of cells along x is one contiguous
    slot range) and keeps, in slot order, every slot j != k with
    |x_k - x_j|^2 < (h_k + h_j)^2 = (2 h_kj)^2: the index is always written, the count advances only
    for a neighbour. Entries ``cnt .. npad - 1`` (npad: cnt rounded up to a multiple of ``pad``) are
    the sentinel slot (column npts of ``sx``, ``sort_points``), whose pair terms are exactly 0.
    When the candidates could overflow ``nbj`` nothing is scanned and ``(-need, 0)`` is returned:
    the caller allocates a list of at least ``need`` entries and calls again. (Growing the list
    inside the scan, as the loops of rates.py did before, kept LLVM from holding the list's pointer
    in a register and cost about a third of the rates pass; so did returning the array, whose
    reference count then changes at every call; issue 17.)

    ``sx``: rows x, y, z, h (``sort_points``), read with unsigned slots (no negative-index
    wrap-around in the loads); ``grid_o`` = (ox, oy, oz), ``grid_n`` = (nx, ny, nz);
    ``dshape.ndim``: the dimension, a compile-time constant. The neighbours and their order are
    those of the scan this replaces, so every sum over them is bit-identical. Inlined into the
    caller's numba IR (``inline="always"``): it computes in the caller's floating-point flags, and
    both callers (``rates._fluid_rates``, ``axisymmetric._axisymmetric_rates``) have none.
    """
    dim = dshape.ndim
    ox, oy, oz = grid_o
    nx, ny, nz = grid_n
    x0, x1 = cell_range(xi, reach, ox, inv_cell, nx)
    y0, y1 = cell_range(yi, reach, oy, inv_cell, ny)
    z0, z1 = cell_range(zi, reach, oz, inv_cell, nz)
    need = pad
    for cz in range(z0, z1 + 1):
        for cy in range(y0, y1 + 1):
            base = (cz * ny + cy) * nx
            need += cell_start[base + x1 + 1] - cell_start[base + x0]
    if need > nbj.shape[0]:
        return -need, 0
    ku = np.uint64(k)
    cnt = np.uint64(0)
    for cz in range(z0, z1 + 1):
        for cy in range(y0, y1 + 1):
            base = (cz * ny + cy) * nx
            for j in range(np.uint64(cell_start[base + x0]), np.uint64(cell_start[base + x1 + 1])):
                dx = xi - sx[0, j]
                r2 = dx * dx
                dy = yi - sx[1, j]
                r2 += dy * dy
                if dim > 2:
                    dz = zi - sx[2, j]
                    r2 += dz * dz
                hs = hi + sx[3, j]  # 2 h_kj
                nbj[cnt] = j
                cnt += np.uint64((r2 < hs * hs) & (j != ku))
    n = np.int64(cnt)
    npad = (n + pad - 1) // pad * pad
    sentinel = np.uint64(cell_start[-1])
    for t in range(n, npad):
        nbj[t] = sentinel
    return n, npad


@njit(cache=True)
def count_neighbours(sx, cell_start, sreach, grid_f, grid_i, counts):
    """Number of points j != k with |x_k - x_j| < 2 h_kj, for every slot k (cells within ``sreach[k]``)."""
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    inv_cell = 1.0 / grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    for k in range(cell_start[-1]):
        xi, yi, zi, hi = sx[0, k], sx[1, k], sx[2, k], sx[3, k]
        reach = sreach[k]
        x0, x1 = cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = cell_range(yi, reach, oy, inv_cell, ny)
        z0, z1 = cell_range(zi, reach, oz, inv_cell, nz)
        cnt = 0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if j == k:
                        continue
                    dx, dy, dz = xi - sx[0, j], yi - sx[1, j], zi - sx[2, j]
                    hij = 0.5 * (hi + sx[3, j])
                    if dx * dx + dy * dy + dz * dz < 4.0 * hij * hij:
                        cnt += 1
        counts[k] = cnt


@njit(cache=True)
def fill_neighbours(sx, cell_start, sreach, grid_f, grid_i, offsets, out):
    """CSR neighbour lists in slot numbering (``offsets`` from ``count_neighbours``)."""
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    inv_cell = 1.0 / grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    for k in range(cell_start[-1]):
        xi, yi, zi, hi = sx[0, k], sx[1, k], sx[2, k], sx[3, k]
        reach = sreach[k]
        x0, x1 = cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = cell_range(yi, reach, oy, inv_cell, ny)
        z0, z1 = cell_range(zi, reach, oz, inv_cell, nz)
        pos = offsets[k]
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if j == k:
                        continue
                    dx, dy, dz = xi - sx[0, j], yi - sx[1, j], zi - sx[2, j]
                    hij = 0.5 * (hi + sx[3, j])
                    if dx * dx + dy * dy + dz * dz < 4.0 * hij * hij:
                        out[pos] = j
                        pos += 1
