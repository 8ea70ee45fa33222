"""SPH numba kernels: smoothing kernels, cell-linked-list search, ghosts, rates, time integration.

Arrays and scalars only (no objects, no I/O). ``sph/system.py`` orchestrates them; equations and
references are in ``docs/theory/sph.md``; ``sph/reference.py`` holds short NumPy versions that the
tests compare against.

Points. One evaluation works on a list of *points*: the active real particles (point id = particle
index ``i < n``), the ghost (mirror) particles of the planar walls (``n + g``) and the fixed dummy
wall particles (``n + ng + w``). Every point carries a kind (``KIND_FLUID``, ``KIND_GHOST``,
``KIND_WALL``) and a material id, packed as ``mat * 4 + kind`` in one float column.

Layout of an evaluation, all in cell order (slot ``k`` holds point ``perm[k]``):

* ``sx`` (npts, 4): x, y, z, h (coordinates padded with 0 above the dimension);
* ``sd`` (npts, ND): vx, vy, vz, rho, V = m/rho, p/rho^2, c, mat*4+kind;
* ``stau`` (npts, 6): viscous stress tau (xx, yy, zz, xy, yz, zx), only when a material has
  viscosity (otherwise a (1, 6) dummy);
* ``cell_start`` (ncell + 1): slots of cell ``key`` are ``cell_start[key]:cell_start[key+1]`` with
  ``key = (cz*ny + cy)*nx + cx``; cells are ``hmax`` wide, so a neighbour at distance < 2 h_ij
  lies within two cells, and a row of cells along x is one contiguous slot range.

Pair quantities use h_ij = (h_i + h_j)/2, which keeps the pair forces antisymmetric (momentum is
conserved to round-off). Every pair loop is a gather over the slots (``prange``): slot ``k``
writes only its own entries, so results do not depend on the number of threads.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ..materials.kernels import EOS_OFFSET, P_EOS_TYPE, P_RHO0, _eos_state, eos_pressure, eos_sound_speed
from ..materials.slots import P_VISCOSITY, Q_E0, Q_RHO0

CUBIC_SPLINE = 0
WENDLAND_C2 = 1

KIND_FLUID = 0
KIND_GHOST = 1
KIND_WALL = 2

# columns of the sorted data array sd
D_VX, D_VY, D_VZ, D_RHO, D_VOL, D_PR, D_C, D_MK = 0, 1, 2, 3, 4, 5, 6, 7
ND = 8

# slots of the float parameter vector fprm
F_ALPHA, F_BETA, F_EPS, F_DELTA, F_XSPH = 0, 1, 2, 3, 4
F_GX, F_GY, F_GZ = 5, 6, 7
F_HMAX, F_CELL, F_OX, F_OY, F_OZ = 8, 9, 10, 11, 12
F_MU_DIL, F_PMIN = 13, 14
NF = 15

# slots of the integer parameter vector iprm
I_DIM, I_KERNEL, I_NX, I_NY, I_NZ, I_VISCOUS, I_DELTA_HYDRO, I_NREAL, I_NWALL = 0, 1, 2, 3, 4, 5, 6, 7, 8
NI = 9

# Fast-math flags without nnan/ninf (NaN checks keep working), without "contract" and, but for the
# additions of the neighbour sums (_FMV, _pair_sums), without "reassoc". numba links a copy of each
# callee's optimised LLVM IR into its caller's module (linkonce_odr) and optimises that module
# again, and the caller's module is what it writes to its on-disk cache. The process that compiles
# runs the callee's own code, optimised once (the JIT linker resolves the weak copies to the
# definition it loaded first), a process that loads runs the copies in the cached caller: for
# _pair_sums the one in _fluid_rates, optimised three times (its library, the parfor gufunc's,
# _fluid_rates'). With "contract" or "reassoc" on every instruction each optimisation may fuse or
# regroup differently (reassoc on all of _pair_sums: the second pass regrouped the product of the
# delta-SPH term), so a run that compiled its kernels and one that loaded them differed at
# round-off (4 % in an elastic gate's tip velocity after 0.02 s, where the contact amplifies it).
# Without them re-optimising changes no result (the copies differ only in commuted operands), and
# the two are bit-identical (tests/robustness/test_determinism.py).
_FM = {"nsz", "arcp"}


# ------------------------------------------------------------------------------------ kernels


@njit(cache=True)
def kernel_sigma(kernel, dim):
    """Normalisation constant sigma_d of W = sigma_d / h^d theta(r/h) (support 2h)."""
    if kernel == WENDLAND_C2:
        if dim == 1:
            return 5.0 / 8.0
        if dim == 2:
            return 7.0 / (4.0 * math.pi)
        return 21.0 / (16.0 * math.pi)
    if dim == 1:
        return 2.0 / 3.0
    if dim == 2:
        return 10.0 / (7.0 * math.pi)
    return 1.0 / math.pi


@njit(cache=True)
def _theta(kernel, dim, q):
    """Kernel shape theta(q) and (1/q) dtheta/dq for 0 <= q < 2 (both 0 beyond)."""
    if q >= 2.0:
        return 0.0, 0.0
    if kernel == WENDLAND_C2:
        t = 1.0 - 0.5 * q
        t2 = t * t
        if dim == 1:
            return t2 * t * (1.5 * q + 1.0), -3.0 * t2
        return t2 * t2 * (2.0 * q + 1.0), -5.0 * t2 * t
    t = 2.0 - q
    inner = q < 1.0  # both branches computed, then selected: no misprediction in pair loops
    th = 1.0 - q * q * (1.5 - 0.75 * q) if inner else 0.25 * t * t * t
    dth = -3.0 + 2.25 * q if inner else -0.75 * t * t / q
    return th, dth


@njit(cache=True)
def _inv_pow(inv, dim):
    if dim == 1:
        return inv
    if dim == 2:
        return inv * inv
    return inv * inv * inv


@njit(cache=True)
def kernel_w(kernel, dim, r, h):
    """Kernel value W(r, h)."""
    inv = 1.0 / h
    return kernel_sigma(kernel, dim) * _inv_pow(inv, dim) * _theta(kernel, dim, r * inv)[0]


@njit(cache=True)
def kernel_f(kernel, dim, r, h):
    """F(r, h) = (1/r) dW/dr, so that grad_i W_ij = F r_ij with r_ij = x_i - x_j (finite at r = 0)."""
    inv = 1.0 / h
    return kernel_sigma(kernel, dim) * _inv_pow(inv, dim) * inv * inv * _theta(kernel, dim, r * inv)[1]


# ------------------------------------------------------------------------------- state update


@njit(cache=True)
def update_particle_state(rho, e, m, mat, active, params, eta, dim, pmin, p, c, h):
    """Pressure, sound speed and smoothing length of every active particle.

    p = max(p_eos(rho/rho0, rho0 e), pmin), c = c_eos (``eos_pressure`` and ``eos_sound_speed``
    of the materials module, evaluated through their common ``_eos_state`` so that the EOS is
    computed once), h = eta (m/rho)^(1/dim). ``e`` is the specific internal energy (per unit
    mass), so the EOS's energy per reference volume is rho0 e. Returns the largest h.
    """
    hmax = 0.0
    for i in range(rho.shape[0]):
        if not active[i]:
            continue
        k = mat[i]
        rho0 = params[k, P_RHO0]
        q = params[k, EOS_OFFSET:]
        r = rho[i] / rho0
        ee = rho0 * e[i]
        pr, dpdmu, dpde = _eos_state(int(params[k, P_EOS_TYPE]), q, r, ee)
        p[i] = pr if pr > pmin else pmin
        c2 = (dpdmu + pr * dpde / (r * r)) / q[Q_RHO0]  # as eos_sound_speed
        c[i] = math.sqrt(c2) if c2 > 0.0 else 0.0
        vol = m[i] / rho[i]
        if dim == 2:
            hi = eta * math.sqrt(vol)
        elif dim == 1:
            hi = eta * vol
        else:
            hi = eta * np.cbrt(vol)
        h[i] = hi
        hmax = max(hmax, hi)
    return hmax


@njit(cache=True)
def density_from_pressure(eos, q, rho0, p_target, ee, rho_guess):
    """Density at which p_eos(rho/rho0, ee) = p_target, by Newton's method with slope c^2."""
    rho = rho_guess
    for _ in range(40):
        r = rho / rho0
        f = eos_pressure(eos, q, r, ee) - p_target
        cs = eos_sound_speed(eos, q, r, ee)
        if cs <= 0.0:
            break
        nxt = rho - f / (cs * cs)
        if nxt < 0.2 * rho:
            nxt = 0.2 * rho
        elif nxt > 5.0 * rho:
            nxt = 5.0 * rho
        if abs(nxt - rho) <= 1e-14 * rho:
            return nxt
        rho = nxt
    return rho


@njit(cache=True)
def densities_from_pressures(pressure, mat, params, out):
    """``out[i]`` = density of material ``mat[i]`` at pressure ``pressure[i]`` and its initial energy."""
    for i in range(pressure.shape[0]):
        k = mat[i]
        rho0 = params[k, P_RHO0]
        q = params[k, EOS_OFFSET:]
        out[i] = density_from_pressure(int(params[k, P_EOS_TYPE]), q, rho0, pressure[i], q[Q_E0], rho0)


# ------------------------------------------------------------------------------------- ghosts


@njit(cache=True)
def _near_mask(x, i, walls, reach):
    mask = 0
    for w in range(walls.shape[0]):
        d = walls[w, 2] * (x[i, int(walls[w, 0])] - walls[w, 1])
        if 0.0 <= d < reach:
            mask |= 1 << w
    return mask


@njit(cache=True)
def count_ghosts(x, active, walls, valid, reach, counts):
    """Number of mirror images of each particle: one per valid subset of the walls it is near.

    ``walls`` (nw, 4): axis, position, side (+1 fluid where x[axis] > position, -1 below),
    no-slip flag. ``valid[s]`` is true for wall subsets ``s`` (bit masks) with at most one wall
    per axis (a corner image is the mirror through both walls of the corner).
    """
    for i in range(x.shape[0]):
        cnt = 0
        if active[i]:
            mask = _near_mask(x, i, walls, reach)
            if mask != 0:
                for s in range(1, valid.shape[0]):
                    if valid[s] and (s & mask) == s:
                        cnt += 1
        counts[i] = cnt


@njit(cache=True)
def fill_ghosts(x, v, rho, c, active, walls, valid, reach, offsets, gravity, hydrostatic, gpos, gvel, gflip, gsrc,
                gdp, gdr):
    """Ghost positions, velocities, viscous flips, source particles and pressure offsets (see ``count_ghosts``).

    Position mirrored through each wall of the subset. Velocity: the free-slip mirror (normal
    component reversed) on every wall, slip or no-slip: that is the velocity the continuity,
    pressure and delta-SPH terms see, so a wall is impermeable without being a source of volume.
    ``gflip`` holds the factors (+-1 per component) that turn it into the no-slip velocity
    (whole vector reversed per no-slip wall, wall at rest) which the viscous terms see
    (``ghost_friction``, ``viscous_stress``): the tangential components are negated once per
    no-slip wall (Marrone et al. 2011, fixed ghost particles). The ghost carries its source's
    density and pressure; with ``hydrostatic`` they get the hydrostatic increments
    dp = rho_i g.(x_ghost - x_i) (``gdp``) and drho = dp / c_i^2 (``gdr``), otherwise 0.
    """
    dim = x.shape[1]
    for i in range(x.shape[0]):
        k = offsets[i]
        if offsets[i + 1] == k:
            continue
        mask = _near_mask(x, i, walls, reach)
        x0 = x[i, 0]
        x1 = x[i, 1] if dim > 1 else 0.0
        x2 = x[i, 2] if dim > 2 else 0.0
        v0 = v[i, 0]
        v1 = v[i, 1] if dim > 1 else 0.0
        v2 = v[i, 2] if dim > 2 else 0.0
        for s in range(1, valid.shape[0]):
            if not (valid[s] and (s & mask) == s):
                continue
            p0, p1, p2, u0, u1, u2 = x0, x1, x2, v0, v1, v2
            f0 = f1 = f2 = 1.0
            for w in range(walls.shape[0]):
                if s & (1 << w):
                    ax = int(walls[w, 0])
                    pos2 = 2.0 * walls[w, 1]
                    noslip = walls[w, 3] != 0.0
                    if ax == 0:
                        p0 = pos2 - p0
                        u0 = -u0
                    elif ax == 1:
                        p1 = pos2 - p1
                        u1 = -u1
                    else:
                        p2 = pos2 - p2
                        u2 = -u2
                    if noslip:
                        f0 = f0 if ax == 0 else -f0
                        f1 = f1 if ax == 1 else -f1
                        f2 = f2 if ax == 2 else -f2
            gpos[k, 0], gpos[k, 1], gpos[k, 2] = p0, p1, p2
            gvel[k, 0], gvel[k, 1], gvel[k, 2] = u0, u1, u2
            gflip[k, 0], gflip[k, 1], gflip[k, 2] = f0, f1, f2
            gsrc[k] = i
            if hydrostatic:
                dp = rho[i] * (gravity[0] * (p0 - x0) + gravity[1] * (p1 - x1) + gravity[2] * (p2 - x2))
                gdp[k] = dp
                gdr[k] = dp / (c[i] * c[i]) if c[i] > 0.0 else 0.0
            else:
                gdp[k] = 0.0
                gdr[k] = 0.0
            k += 1


@njit(cache=True)
def make_ghosts(x, v, rho, c, active, walls, valid, reach, gravity, hydrostatic):
    """Ghost particles of the planar walls: ``(gpos, gvel, gflip, gsrc, gdp, gdr)`` (see ``fill_ghosts``)."""
    n = x.shape[0]
    # the particles near a wall (few) are found first, wall by wall (loops over the particles
    # that LLVM vectorises; the test of _near_mask); their images are counted and filled for
    # those only, in the order count_ghosts/fill_ghosts give over all particles
    flag = np.zeros(n, dtype=np.uint8)
    for w in range(walls.shape[0]):
        ax = int(walls[w, 0])
        pos, side = walls[w, 1], walls[w, 2]
        for i in range(n):
            d = side * (x[i, ax] - pos)
            flag[i] |= (0.0 <= d) & (d < reach)
    nnear = 0
    for i in range(n):
        nnear += flag[i] & active[i]
    sub = np.empty(nnear, dtype=np.int64)
    a = 0
    for i in range(n):
        if flag[i] & active[i]:
            sub[a] = i
            a += 1
    counts = np.empty(nnear, dtype=np.int64)
    count_ghosts(x[sub], np.ones(nnear, dtype=np.bool_), walls, valid, reach, counts)
    offsets = np.zeros(nnear + 1, dtype=np.int64)
    for a in range(nnear):
        offsets[a + 1] = offsets[a] + counts[a]
    ng = offsets[nnear]
    gpos = np.empty((ng, 3))
    gvel = np.empty((ng, 3))
    gflip = np.empty((ng, 3))
    gsrc = np.empty(ng, dtype=np.int64)
    gdp = np.empty(ng)
    gdr = np.empty(ng)
    fill_ghosts(x[sub], v[sub], rho[sub], c[sub], np.ones(nnear, dtype=np.bool_), walls, valid, reach, offsets, gravity,
                hydrostatic, gpos, gvel, gflip, gsrc, gdp, gdr)
    for g in range(ng):
        gsrc[g] = sub[gsrc[g]]
    return gpos, gvel, gflip, gsrc, gdp, gdr


# ------------------------------------------------------------------------- cell-linked list


@njit(cache=True)
def bin_points(x, h, active, gpos, gsrc, wpos, wh, max_cells_per_point):
    """Counting sort of all points by cell.

    Returns ``perm`` (slot -> point id), ``cell_start``, the grid ``(ox, oy, oz, cell)``,
    ``(nx, ny, nz)`` and hmax. The cell width is hmax (half the largest support 2 hmax), widened
    if the bounding box would need more than ``max_cells_per_point`` cells per point. The sort is
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
    npts = ng + nw
    for i in range(n):
        if active[i]:
            npts += 1
            for d in range(dim):
                lo[d] = min(lo[d], x[i, d])
                hi[d] = max(hi[d], x[i, d])
            hmax = max(hmax, h[i])
    for g in range(ng):
        for d in range(dim):
            lo[d] = min(lo[d], gpos[g, d])
            hi[d] = max(hi[d], gpos[g, d])
    for w in range(nw):
        for d in range(dim):
            lo[d] = min(lo[d], wpos[w, d])
            hi[d] = max(hi[d], wpos[w, d])
        hmax = max(hmax, wh[w])
    if npts == 0:
        lo[:] = 0.0
        hi[:] = 0.0
        hmax = 1.0
    cell = hmax
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
            c1 = int((x[pid, 1] - lo[1]) * inv) if dim > 1 else 0
            c2 = int((x[pid, 2] - lo[2]) * inv) if dim > 2 else 0
        else:
            if pid < n + ng:
                g = pid - n
                a0, a1, a2 = gpos[g, 0], gpos[g, 1], gpos[g, 2]
            else:
                w = pid - n - ng
                a0 = wpos[w, 0]
                a1 = wpos[w, 1] if dim > 1 else 0.0
                a2 = wpos[w, 2] if dim > 2 else 0.0
            c0 = int((a0 - lo[0]) * inv)
            c1 = int((a1 - lo[1]) * inv) if dim > 1 else 0
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
    return perm, cell_start, lo[0], lo[1], lo[2], cell, nx, ny, nz, hmax


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
            sx[k, 0] = x[i, 0]
            sx[k, 1] = x[i, 1] if dim > 1 else 0.0
            sx[k, 2] = x[i, 2] if dim > 2 else 0.0
            sx[k, 3] = h[i]
            sd[k, D_VX] = v[i, 0]
            sd[k, D_VY] = v[i, 1] if dim > 1 else 0.0
            sd[k, D_VZ] = v[i, 2] if dim > 2 else 0.0
            r = rho[i]
            sd[k, D_RHO] = r
            sd[k, D_VOL] = m[i] / r
            sd[k, D_PR] = p[i] / (r * r)
            sd[k, D_C] = c[i]
            sd[k, D_MK] = mat[i] * 4 + KIND_FLUID
        elif pid < n + ng:
            g = pid - n
            i = gsrc[g]
            sx[k, 0], sx[k, 1], sx[k, 2] = gpos[g, 0], gpos[g, 1], gpos[g, 2]
            sx[k, 3] = h[i]
            sd[k, D_VX], sd[k, D_VY], sd[k, D_VZ] = gvel[g, 0], gvel[g, 1], gvel[g, 2]
            r = rho[i] + gdr[g]
            sd[k, D_RHO] = r
            sd[k, D_VOL] = m[i] / r
            sd[k, D_PR] = (p[i] + gdp[g]) / (r * r)
            sd[k, D_C] = c[i]
            sd[k, D_MK] = mat[i] * 4 + KIND_GHOST
        else:
            w = pid - n - ng
            sx[k, 0] = wpos[w, 0]
            sx[k, 1] = wpos[w, 1] if dim > 1 else 0.0
            sx[k, 2] = wpos[w, 2] if dim > 2 else 0.0
            sx[k, 3] = wh[w]
            sd[k, D_VX] = wvel[w, 0]
            sd[k, D_VY] = wvel[w, 1] if dim > 1 else 0.0
            sd[k, D_VZ] = wvel[w, 2] if dim > 2 else 0.0
            sd[k, D_RHO] = wrho[w]
            sd[k, D_VOL] = wm[w] / wrho[w]
            sd[k, D_PR] = 0.0
            sd[k, D_C] = 0.0
            sd[k, D_MK] = wmat[w] * 4 + KIND_WALL


@njit(cache=True)
def sort_points(x, v, rho, m, p, c, h, mat, active, gpos, gvel, gsrc, gdp, gdr,
                wpos, wvel, wrho, wm, wh, wmat, max_cells_per_point, fprm, iprm):
    """Cell-sort all points (``bin_points``) and copy their data into cell order (``gather_points``).

    Returns ``(perm, cell_start, sx, sd)``; ``sx`` and ``sd`` have one extra last row, the
    sentinel: a point far from everything (1e30 in every coordinate) with zero volume and kind
    wall, whose every pair term is exactly 0; neighbour lists are padded with it. Writes the grid (hmax, cell, origin, nx, ny, nz) into
    ``fprm`` and ``iprm``.
    """
    perm, cell_start, ox, oy, oz, cell, nx, ny, nz, hmax = bin_points(x, h, active, gpos, gsrc, wpos, wh,
                                                                      max_cells_per_point)
    npts = perm.shape[0]
    sx = np.empty((npts + 1, 4))
    sd = np.empty((npts + 1, ND))
    gather_points(perm, x, v, rho, m, p, c, h, mat, gpos, gvel, gsrc, gdp, gdr, wpos, wvel, wrho, wm, wh, wmat, sx, sd)
    sx[npts, 0] = 1e30
    sx[npts, 1] = 1e30
    sx[npts, 2] = 1e30
    sx[npts, 3] = 1.0
    sd[npts, :] = 0.0
    sd[npts, D_RHO] = 1.0
    sd[npts, D_C] = 1.0
    sd[npts, D_MK] = KIND_WALL
    fprm[F_HMAX] = hmax
    fprm[F_CELL] = cell
    fprm[F_OX] = ox
    fprm[F_OY] = oy
    fprm[F_OZ] = oz
    iprm[I_NX] = nx
    iprm[I_NY] = ny
    iprm[I_NZ] = nz
    iprm[I_NREAL] = x.shape[0]
    iprm[I_NWALL] = wpos.shape[0]
    return perm, cell_start, sx, sd


@njit(cache=True)
def _cell_range(v, reach, o, inv_cell, n):
    lo = int(math.floor((v - reach - o) * inv_cell))
    hi = int(math.floor((v + reach - o) * inv_cell))
    if lo < 0:
        lo = 0
    if hi > n - 1:
        hi = n - 1
    return lo, hi


# ------------------------------------------------------------------------------ pair passes


@njit(cache=True, parallel=True, fastmath=_FM, error_model="numpy")
def wall_pressure(sx, sd, cell_start, fprm, iprm, params):
    """Adami et al. (2012) pressure of the dummy wall points, extrapolated from the fluid.

    p_w = (sum_f p_f W_wf + g . sum_f rho_f r_wf W_wf) / sum_f W_wf (fixed wall, a_w = 0), over
    fluid points f within 2 h_wf; rho_w inverts the wall material's EOS at p_w (energy e0).
    A wall point with no fluid neighbour keeps p = 0. Writes rho, p/rho^2 and c of wall slots.
    """
    kernel, dim = iprm[I_KERNEL], iprm[I_DIM]
    nx, ny, nz = iprm[I_NX], iprm[I_NY], iprm[I_NZ]
    hmax, cell = fprm[F_HMAX], fprm[F_CELL]
    ox, oy, oz = fprm[F_OX], fprm[F_OY], fprm[F_OZ]
    gx, gy, gz = fprm[F_GX], fprm[F_GY], fprm[F_GZ]
    pmin = fprm[F_PMIN]
    inv_cell = 1.0 / cell
    sig = kernel_sigma(kernel, dim)
    for k in prange(cell_start[-1]):
        mk = int(sd[k, D_MK])
        if (mk & 3) != KIND_WALL:
            continue
        xi, yi, zi, hi = sx[k, 0], sx[k, 1], sx[k, 2], sx[k, 3]
        reach = hi + hmax
        x0, x1 = _cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = _cell_range(yi, reach, oy, inv_cell, ny)
        z0, z1 = _cell_range(zi, reach, oz, inv_cell, nz)
        sw = 0.0
        spw = 0.0
        srx = 0.0
        sry = 0.0
        srz = 0.0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if (int(sd[j, D_MK]) & 3) != KIND_FLUID:
                        continue
                    dx = xi - sx[j, 0]
                    dy = yi - sx[j, 1]
                    dz = zi - sx[j, 2]
                    hij = 0.5 * (hi + sx[j, 3])
                    r2 = dx * dx + dy * dy + dz * dz
                    if r2 >= 4.0 * hij * hij:
                        continue
                    inv = 1.0 / hij
                    wv = sig * _inv_pow(inv, dim) * _theta(kernel, dim, math.sqrt(r2) * inv)[0]
                    rj = sd[j, D_RHO]
                    sw += wv
                    spw += sd[j, D_PR] * rj * rj * wv
                    rw = rj * wv
                    srx += rw * dx
                    sry += rw * dy
                    srz += rw * dz
        mat = mk >> 2
        rho0 = params[mat, P_RHO0]
        eos = int(params[mat, P_EOS_TYPE])
        q = params[mat, EOS_OFFSET:]
        pw = 0.0
        if sw > 0.0:
            pw = (spw + gx * srx + gy * sry + gz * srz) / sw
        if pw < pmin:
            pw = pmin
        rw = density_from_pressure(eos, q, rho0, pw, q[Q_E0], sd[k, D_RHO])
        sd[k, D_VOL] *= sd[k, D_RHO] / rw  # same mass at the new density
        sd[k, D_RHO] = rw
        sd[k, D_PR] = pw / (rw * rw)
        sd[k, D_C] = eos_sound_speed(eos, q, rw / rho0, q[Q_E0])


@njit(cache=True, parallel=True, fastmath=_FM, error_model="numpy")
def viscous_stress(sx, sd, svf, cell_start, fprm, iprm, params, stau):
    """Newtonian viscous stress at every point from the SPH velocity gradient.

    L_ab = sum_j V_j (v_j,a - v_i,a) dW_ij/dx_i,b (paper eq. 3.6 form), D = (L + L^T)/2,
    tau = mu (2D - (2/3) tr(D) I) + mu' tr(D) I (paper eq. 3.16), mu from the material row and
    the dilatational viscosity mu' from ``fprm[F_MU_DIL]``. Writes stau[k] for every slot.
    Velocities are ``sd``'s times the per-slot factors ``svf`` (the no-slip velocity of the
    ghosts of no-slip walls, ``fill_ghosts``); a (1, 3) ``svf`` means no factors.
    """
    kernel, dim = iprm[I_KERNEL], iprm[I_DIM]
    nx, ny, nz = iprm[I_NX], iprm[I_NY], iprm[I_NZ]
    hmax, cell = fprm[F_HMAX], fprm[F_CELL]
    ox, oy, oz = fprm[F_OX], fprm[F_OY], fprm[F_OZ]
    mu_dil = fprm[F_MU_DIL]
    inv_cell = 1.0 / cell
    sig = kernel_sigma(kernel, dim)
    flips = svf.shape[0] > 1
    for k in prange(cell_start[-1]):
        mat = int(sd[k, D_MK]) >> 2
        mu = params[mat, P_VISCOSITY]
        if mu == 0.0 and mu_dil == 0.0:
            for a in range(6):
                stau[k, a] = 0.0
            continue
        xi, yi, zi, hi = sx[k, 0], sx[k, 1], sx[k, 2], sx[k, 3]
        fk = np.int64(k) if flips else np.int64(0)
        ui, vi, wi = sd[k, D_VX] * svf[fk, 0], sd[k, D_VY] * svf[fk, 1], sd[k, D_VZ] * svf[fk, 2]
        reach = hi + hmax
        x0, x1 = _cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = _cell_range(yi, reach, oy, inv_cell, ny)
        z0, z1 = _cell_range(zi, reach, oz, inv_cell, nz)
        l00 = l01 = l02 = l10 = l11 = l12 = l20 = l21 = l22 = 0.0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    dx = xi - sx[j, 0]
                    dy = yi - sx[j, 1]
                    dz = zi - sx[j, 2]
                    hij = 0.5 * (hi + sx[j, 3])
                    r2 = dx * dx + dy * dy + dz * dz
                    if r2 >= 4.0 * hij * hij or r2 == 0.0:
                        continue
                    inv = 1.0 / hij
                    f = sig * _inv_pow(inv, dim) * inv * inv * _theta(kernel, dim, math.sqrt(r2) * inv)[1]
                    vol = sd[j, D_VOL] * f
                    gx, gy, gz = vol * dx, vol * dy, vol * dz
                    fj = np.int64(j) if flips else np.int64(0)
                    du = sd[j, D_VX] * svf[fj, 0] - ui
                    dv = sd[j, D_VY] * svf[fj, 1] - vi
                    dw = sd[j, D_VZ] * svf[fj, 2] - wi
                    l00 += du * gx
                    l01 += du * gy
                    l02 += du * gz
                    l10 += dv * gx
                    l11 += dv * gy
                    l12 += dv * gz
                    l20 += dw * gx
                    l21 += dw * gy
                    l22 += dw * gz
        div = l00 + l11 + l22
        iso = (mu_dil - 2.0 / 3.0 * mu) * div
        stau[k, 0] = 2.0 * mu * l00 + iso
        stau[k, 1] = 2.0 * mu * l11 + iso
        stau[k, 2] = 2.0 * mu * l22 + iso
        stau[k, 3] = mu * (l01 + l10)
        stau[k, 4] = mu * (l12 + l21)
        stau[k, 5] = mu * (l20 + l02)


_BLOCK = 32
_PAD = 4  # pair lists are padded to a multiple of the vector width with the sentinel slot

# reassoc lets LLVM vectorise the neighbour sums (their order of additions is then LLVM's); it is
# given to the sums only, not to the terms (see _FM)
_FMV = {"nsz", "arcp", "reassoc"}


@njit(cache=True, fastmath=_FM, forceinline=True, error_model="numpy")
def _pair_terms(j, sxf, sdf, kshape, dshape, tshape, sig, xi, yi, zi, hi, ui, vi, wi, rhoi, pri, ci, fmati,
                alpha, beta, eps, gx, gy, gz, dhydro):
    """The terms of neighbour slot ``j`` in the sums of ``_pair_sums`` (same arguments, same order).

    Without "reassoc" and always inlined into ``_pair_sums`` (LLVM keeps each instruction's flags
    when it inlines), so re-optimising the inlined code cannot reorder these products and sums.
    """
    kernel = WENDLAND_C2 if kshape.ndim == 2 else CUBIC_SPLINE
    dim = dshape.ndim
    full = tshape.ndim == 1
    wend = kernel == WENDLAND_C2
    one_d = dim == 1
    jx = j * np.uint64(4)
    jd = j * np.uint64(ND)
    dx = xi - sxf[jx]
    dy = yi - sxf[jx + 1] if dim > 1 else 0.0
    dz = zi - sxf[jx + 2] if dim > 2 else 0.0
    hij = 0.5 * (hi + sxf[jx + 3])
    r2 = dx * dx
    if dim > 1:
        r2 += dy * dy
    if dim > 2:
        r2 += dz * dz
    r = math.sqrt(r2)
    a = 1.0 / (hij * r)
    inv = r * a  # 1/h_ij
    q = r2 * a  # r/h_ij
    # kernel shape theta(q) and (1/q) dtheta/dq; both branches of the spline computed, then selected
    if wend:
        tw = max(1.0 - 0.5 * q, 0.0)
        tw2 = tw * tw
        th = tw2 * tw * (1.5 * q + 1.0) if one_d else tw2 * tw2 * (2.0 * q + 1.0)
        dth = -3.0 * tw2 if one_d else -5.0 * tw2 * tw
    else:
        tc = max(2.0 - q, 0.0)
        inner = q < 1.0
        th = 1.0 - q * q * (1.5 - 0.75 * q) if inner else 0.25 * tc * tc * tc
        dth = -3.0 + 2.25 * q if inner else -0.75 * tc * tc * hij * hij * a  # -0.75 (2-q)^2 / q
    invd = inv * (inv if dim >= 2 else 1.0) * (inv if dim >= 3 else 1.0)
    norm = sig * invd
    f = norm * inv * inv * dth
    wgx = f * dx
    wgy = f * dy
    wgz = f * dz
    du = ui - sdf[jd + D_VX]
    dv = vi - sdf[jd + D_VY] if dim > 1 else 0.0
    dw = wi - sdf[jd + D_VZ] if dim > 2 else 0.0
    rhoj = sdf[jd + D_RHO]
    vol = sdf[jd + D_VOL]
    mj = vol * rhoj
    vdotg = du * wgx
    vdr = du * dx
    if dim > 1:
        vdotg += dv * wgy
        vdr += dv * dy
    if dim > 2:
        vdotg += dw * wgz
        vdr += dw * dz
    vdotr = min(vdr, 0.0)
    cj = sdf[jd + D_C]
    cij = 0.5 * (ci + cj)
    rij = 0.5 * (rhoi + rhoj)
    dd = r2 + eps * hij * hij
    rcp = 1.0 / (dd * dd * rij)
    hv = hij * vdotr
    # Monaghan: Pi = (-alpha c mu + beta mu^2)/rho_ij, mu = h v.r/(r^2 + eps h^2) for v.r < 0
    pi_ij = hv * (beta * hv - alpha * cij * dd) * rcp
    coef = mj * (pri + sdf[jd + D_PR] + pi_ij)
    work = coef * vdotg
    mk = sdf[jd + D_MK]  # mat * 4 + kind, decoded in floating point (exact for these integers)
    matj = np.floor(0.25 * mk)
    notwall = 1.0 if mk - 4.0 * matj != KIND_WALL else 0.0
    wall_work = (1.0 - notwall) * work if full else 0.0
    same = notwall if matj == fmati else 0.0
    psi = rhoj - rhoi
    if dhydro:
        gr = gx * dx
        if dim > 1:
            gr += gy * dy
        if dim > 2:
            gr += gz * dz
        psi += rij * gr / (cij * cij)
    diff = same * hij * cij * psi * f * vol
    wr = notwall * norm * th * mj * (dd * dd * rcp) if full else 0.0
    return (coef * wgx, coef * wgy, coef * wgz, vol * vdotg, work, wall_work, diff, wr * du, wr * dv, wr * dw)


@njit(cache=True, fastmath=_FMV, error_model="numpy")
def _pair_sums(nbj, cnt, sxf, sdf, kshape, dshape, tshape, sig, xi, yi, zi, hi, ui, vi, wi, rhoi, pri, ci, mati,
               alpha, beta, eps, gx, gy, gz, dhydro):
    """Branch-free sums over the neighbour slots ``nbj[:cnt]`` of one particle (LLVM vectorises it).

    ``sxf``, ``sdf``: ``sx``, ``sd`` flattened (rows of 4 and ``ND`` = 8), indexed with the unsigned
    slots of ``nbj`` (no negative-index handling in the gathers). The kernel, the dimension and
    the term set are compile-time constants, the numbers of dimensions of the empty arrays
    ``kshape``, ``dshape`` and ``tshape`` (see ``fluid_rates``): one compiled version per
    combination, in which the other kernel's shape, the coordinates and velocities above ``dim``
    (in 2D exactly 0) and, with ``tshape.ndim == 2``, the wall work and XSPH sums (then exactly 0)
    are not computed. The terms of one pair are ``_pair_terms``'.

    Returns (ax, ay, az, cont, work, wall_work, diff, sxu, sxv, sxw): the pressure + artificial-viscosity
    acceleration -sum m_j S grad W (S = p_i/rho_i^2 + p_j/rho_j^2 + Pi_ij), sum V_j v_ij.grad W,
    sum m_j S v_ij.grad W, its part over dummy wall points j, the delta-SPH sum sum h c psi F V (same material, no wall) and the
    XSPH sums sum (m_j/rho_ij) W (v_j - v_i) (no wall). Sentinel entries add exactly zero.
    """
    dim = dshape.ndim
    full = tshape.ndim == 1
    fmati = float(mati)
    ax = ay = az = 0.0
    cont = work = wall_work = diff = 0.0
    sxu = sxv = sxw = 0.0
    for t in range(cnt):
        tx, ty, tz, tc, tw, tww, td, tu, tv, tws = _pair_terms(
            nbj[t], sxf, sdf, kshape, dshape, tshape, sig, xi, yi, zi, hi, ui, vi, wi, rhoi, pri, ci, fmati,
            alpha, beta, eps, gx, gy, gz, dhydro)
        ax -= tx
        if dim > 1:
            ay -= ty
        if dim > 2:
            az -= tz
        cont += tc
        work += tw
        diff += td
        if full:
            wall_work += tww
            sxu -= tu
            if dim > 1:
                sxv -= tv
            if dim > 2:
                sxw -= tws
    return ax, ay, az, cont, work, wall_work, diff, sxu, sxv, sxw


def fluid_rates(sx, sd, stau, perm, cell_start, fprm, iprm, acc, drho, de, xsph, wall_power):
    """Continuity, momentum, energy, delta-SPH and XSPH rates of every real (fluid) point.

    For fluid slot k (particle i = perm[k]) and every point j within 2 h_ij, with
    grad_i W_ij = F_ij r_ij, v_ij = v_i - v_j, V_j = m_j/rho_j, Pi_ij the Monaghan viscosity:

      drho_i = rho_i sum_j V_j v_ij . grad_i W_ij                                  (paper 3.8)
               - 2 delta sum_j h_ij c_ij psi_ij F_ij V_j    (fluid/ghost j of the same material)
      acc_i  = sum_j m_j (sigma_i/rho_i^2 + sigma_j/rho_j^2 - Pi_ij I) . grad_i W_ij   (paper 3.9)
      de_i   = -1/2 sum_j m_j (sigma_i/rho_i^2 + sigma_j/rho_j^2 - Pi_ij I) : (v_ij (x) grad_i W_ij)
      xsph_i = eps_x sum_j (m_j / rho_ij) (v_j - v_i) W_ij             (fluid and ghost j only)

    with sigma = -p I + tau, psi_ij = (rho_j - rho_i) [- rho_ij g.(x_j - x_i)/c_ij^2 with the
    hydrostatic correction]. ``acc`` excludes gravity and external forces.

    A dummy wall point has no energy of its own: of a fluid-wall pair's work m_i m_j S v_ij.grad W
    the fluid particle keeps half (in de_i), the other half is the power the wall absorbs,
    ``wall_power[i]`` = m_i/2 sum_(wall j) m_j S v_ij.grad W (the energy balance counts it).

    Per particle: the candidates of the cell rows within reach (each row of cells along x is one
    contiguous slot range) are filtered into a neighbour list without branches (the index is
    always written, the count advances only for a neighbour); the list is padded to a
    multiple of ``_PAD`` with the sentinel slot (the last row of ``sx``/``sd``, ``sort_points``) and summed by
    ``_pair_sums``; the viscous-stress terms, when present, are a second loop. Slots are taken
    in blocks of ``_BLOCK`` per parallel task. Each particle's sums depend only on its own
    neighbour list, so the result does not depend on the thread count. Equations and
    references: docs/theory/sph.md.

    The work is done by ``_fluid_rates``, compiled once per kernel, dimension and term set: these
    are compile-time constants there, the numbers of dimensions of three empty arrays
    (``kshape``: 1 cubic spline, 2 Wendland C2; ``dshape``: dim; ``tshape``: 1 every term, 2 no
    dummy wall points and no XSPH, whose sums are then not computed: they would be exactly 0).
    This function, plain Python (the one exception to the module's rule), only picks the
    specialisation, so that numba compiles just the ones a run uses.
    """
    kernel, dim = int(iprm[I_KERNEL]), int(iprm[I_DIM])
    lean = iprm[I_NWALL] == 0 and fprm[F_XSPH] == 0.0
    _fluid_rates(sx, sd, stau, perm, cell_start, fprm, iprm, acc, drho, de, xsph, wall_power,
                 _SHAPES[2 if kernel == WENDLAND_C2 else 1], _SHAPES[dim], _SHAPES[2 if lean else 1])


_SHAPES = {1: np.empty(0), 2: np.empty((0, 0)), 3: np.empty((0, 0, 0))}


@njit(cache=True, parallel=True, error_model="numpy")
def _fluid_rates(sx, sd, stau, perm, cell_start, fprm, iprm, acc, drho, de, xsph, wall_power, kshape, dshape,
                 tshape):
    """``fluid_rates`` for one kernel, dimension and term set (``kshape``, ``dshape``, ``tshape``)."""
    kernel = WENDLAND_C2 if kshape.ndim == 2 else CUBIC_SPLINE
    dim = dshape.ndim
    nx, ny, nz = iprm[I_NX], iprm[I_NY], iprm[I_NZ]
    viscous = iprm[I_VISCOUS] != 0
    dhydro = iprm[I_DELTA_HYDRO] != 0
    alpha, beta, eps = fprm[F_ALPHA], fprm[F_BETA], fprm[F_EPS]
    delta, exsph = fprm[F_DELTA], fprm[F_XSPH]
    gx, gy, gz = fprm[F_GX], fprm[F_GY], fprm[F_GZ]
    hmax, cell = fprm[F_HMAX], fprm[F_CELL]
    ox, oy, oz = fprm[F_OX], fprm[F_OY], fprm[F_OZ]
    inv_cell = 1.0 / cell
    sig = kernel_sigma(kernel, dim)
    npts = cell_start[-1]
    sentinel = sx.shape[0] - 1
    sxf = sx.reshape(-1)
    sdf = sd.reshape(-1)
    for b in prange((npts + _BLOCK - 1) // _BLOCK):
        nbj = np.empty(512, dtype=np.uint64)
        for k in range(b * _BLOCK, min(npts, (b + 1) * _BLOCK)):
            mki = int(sd[k, D_MK])
            if (mki & 3) != KIND_FLUID:
                continue
            xi, yi, zi, hi = sx[k, 0], sx[k, 1], sx[k, 2], sx[k, 3]
            reach = hi + hmax  # largest 2 h_ij
            x0, x1 = _cell_range(xi, reach, ox, inv_cell, nx)
            y0, y1 = _cell_range(yi, reach, oy, inv_cell, ny)
            z0, z1 = _cell_range(zi, reach, oz, inv_cell, nz)
            cnt = 0
            for cz in range(z0, z1 + 1):
                for cy in range(y0, y1 + 1):
                    base = (cz * ny + cy) * nx
                    j0 = cell_start[base + x0]
                    j1 = cell_start[base + x1 + 1]
                    if cnt + (j1 - j0) + _PAD > nbj.shape[0]:
                        grown = np.empty(2 * (cnt + (j1 - j0) + _PAD), dtype=np.uint64)
                        for t in range(cnt):  # an explicit loop: slices inside prange trip numba's array analysis
                            grown[t] = nbj[t]
                        nbj = grown
                    for j in range(j0, j1):
                        dx = xi - sx[j, 0]
                        r2 = dx * dx
                        if dim > 1:
                            dy = yi - sx[j, 1]
                            r2 += dy * dy
                        if dim > 2:
                            dz = zi - sx[j, 2]
                            r2 += dz * dz
                        hs = hi + sx[j, 3]  # 2 h_ij
                        nbj[cnt] = j
                        cnt += (r2 < hs * hs) & (j != k)
            npad = (cnt + _PAD - 1) // _PAD * _PAD
            for t in range(cnt, npad):
                nbj[t] = sentinel
            ui, vi, wi = sd[k, D_VX], sd[k, D_VY], sd[k, D_VZ]
            rhoi, pri, ci = sd[k, D_RHO], sd[k, D_PR], sd[k, D_C]
            ax, ay, az, cont, work, wall_work, diff, sxu, sxv, sxw = _pair_sums(
                nbj, npad, sxf, sdf, kshape, dshape, tshape, sig, xi, yi, zi, hi, ui, vi, wi, rhoi, pri, ci, mki >> 2,
                alpha, beta, eps, gx, gy, gz, dhydro)
            if viscous:
                irho2 = 1.0 / (rhoi * rhoi)
                t0i, t1i, t2i = stau[k, 0] * irho2, stau[k, 1] * irho2, stau[k, 2] * irho2
                t3i, t4i, t5i = stau[k, 3] * irho2, stau[k, 4] * irho2, stau[k, 5] * irho2
                for t in range(cnt):
                    j = nbj[t]
                    dx, dy, dz = xi - sx[j, 0], yi - sx[j, 1], zi - sx[j, 2]
                    f = kernel_f(kernel, dim, math.sqrt(dx * dx + dy * dy + dz * dz), 0.5 * (hi + sx[j, 3]))
                    wgx, wgy, wgz = f * dx, f * dy, f * dz
                    rhoj = sd[j, D_RHO]
                    mj = sd[j, D_VOL] * rhoj
                    irj = 1.0 / (rhoj * rhoj)
                    s0 = mj * (t0i + stau[j, 0] * irj)
                    s1 = mj * (t1i + stau[j, 1] * irj)
                    s2 = mj * (t2i + stau[j, 2] * irj)
                    s3 = mj * (t3i + stau[j, 3] * irj)
                    s4 = mj * (t4i + stau[j, 4] * irj)
                    s5 = mj * (t5i + stau[j, 5] * irj)
                    tx = s0 * wgx + s3 * wgy + s5 * wgz
                    ty = s3 * wgx + s1 * wgy + s4 * wgz
                    tz = s5 * wgx + s4 * wgy + s2 * wgz
                    ax += tx
                    ay += ty
                    az += tz
                    if (int(sd[j, D_MK]) & 3) == KIND_GHOST:  # a wall at rest does no work: all of it to i
                        work -= 2.0 * (ui * tx + vi * ty + wi * tz)
                    else:
                        work -= (ui - sd[j, D_VX]) * tx + (vi - sd[j, D_VY]) * ty + (wi - sd[j, D_VZ]) * tz
            i = perm[k]
            acc[i, 0] = ax
            if dim > 1:
                acc[i, 1] = ay
            if dim > 2:
                acc[i, 2] = az
            drho[i] = rhoi * cont - 2.0 * delta * diff
            de[i] = 0.5 * work
            wall_power[i] = 0.5 * sd[k, D_VOL] * rhoi * wall_work
            xsph[i, 0] = exsph * sxu
            if dim > 1:
                xsph[i, 1] = exsph * sxv
            if dim > 2:
                xsph[i, 2] = exsph * sxw


@njit(cache=True, parallel=True, error_model="numpy")
def ghost_friction(sx, sd, svf, slots, perm, cell_start, fprm, iprm, acc, de):
    """No-slip correction of the artificial viscosity between fluid particles and ghosts.

    ``fluid_rates`` evaluates every ghost with its free-slip velocity v_g (``fill_ghosts``). Near
    a no-slip wall the viscous term must see the no-slip velocity v_g' = svf_g * v_g instead; for
    the fluid slots ``slots`` (the particles with a no-slip ghost) this adds, over the ghosts g
    within 2 h_ig whose factors are not all 1,

      acc_i -= sum_g m_g (Pi_ig' - Pi_ig) grad_i W_ig,     de_i += sum_g m_g (Pi_ig' - Pi_ig) v_i . grad_i W_ig

    with Pi_ig' and Pi_ig the Monaghan viscosity of ``fluid_rates`` with v_i - v_g' and v_i - v_g.
    The wall is at rest and does no work: the kinetic energy the friction takes from particle i
    goes, all of it, into its internal energy (so ghost walls conserve energy, no-slip or not).
    """
    kernel, dim = iprm[I_KERNEL], iprm[I_DIM]
    nx, ny, nz = iprm[I_NX], iprm[I_NY], iprm[I_NZ]
    alpha, beta, eps = fprm[F_ALPHA], fprm[F_BETA], fprm[F_EPS]
    hmax, cell = fprm[F_HMAX], fprm[F_CELL]
    ox, oy, oz = fprm[F_OX], fprm[F_OY], fprm[F_OZ]
    inv_cell = 1.0 / cell
    for t in prange(slots.shape[0]):
        k = slots[t]
        xi, yi, zi, hi = sx[k, 0], sx[k, 1], sx[k, 2], sx[k, 3]
        ui, vi, wi = sd[k, D_VX], sd[k, D_VY], sd[k, D_VZ]
        rhoi, ci = sd[k, D_RHO], sd[k, D_C]
        reach = hi + hmax
        x0, x1 = _cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = _cell_range(yi, reach, oy, inv_cell, ny)
        z0, z1 = _cell_range(zi, reach, oz, inv_cell, nz)
        ax = ay = az = power = 0.0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if (int(sd[j, D_MK]) & 3) != KIND_GHOST:
                        continue
                    f0, f1, f2 = svf[j, 0], svf[j, 1], svf[j, 2]
                    if f0 == 1.0 and f1 == 1.0 and f2 == 1.0:
                        continue
                    dx, dy, dz = xi - sx[j, 0], yi - sx[j, 1], zi - sx[j, 2]
                    hij = 0.5 * (hi + sx[j, 3])
                    r2 = dx * dx + dy * dy + dz * dz
                    if r2 >= 4.0 * hij * hij:
                        continue
                    uj, vj, wj = sd[j, D_VX], sd[j, D_VY], sd[j, D_VZ]
                    slip = min((ui - uj) * dx + (vi - vj) * dy + (wi - wj) * dz, 0.0)
                    stuck = min((ui - f0 * uj) * dx + (vi - f1 * vj) * dy + (wi - f2 * wj) * dz, 0.0)
                    dd = r2 + eps * hij * hij
                    rhoij = 0.5 * (rhoi + sd[j, D_RHO])
                    cij = 0.5 * (ci + sd[j, D_C])
                    scale = hij / (dd * rhoij)
                    mu_s, mu_n = scale * slip, scale * stuck  # mu_ij / rho_ij
                    dpi = (beta * rhoij * (mu_n * mu_n - mu_s * mu_s) - alpha * cij * (mu_n - mu_s))
                    coef = sd[j, D_VOL] * sd[j, D_RHO] * dpi * kernel_f(kernel, dim, math.sqrt(r2), hij)
                    ax -= coef * dx
                    ay -= coef * dy
                    az -= coef * dz
                    power += coef * (ui * dx + vi * dy + wi * dz)
        i = perm[k]
        acc[i, 0] += ax
        if dim > 1:
            acc[i, 1] += ay
        if dim > 2:
            acc[i, 2] += az
        de[i] += power


# ------------------------------------------------------------------------------- search utils


@njit(cache=True)
def count_neighbours(sx, cell_start, fprm, iprm, counts):
    """Number of points j != k with |x_k - x_j| < 2 h_kj, for every slot k (cell search)."""
    nx, ny, nz = iprm[I_NX], iprm[I_NY], iprm[I_NZ]
    hmax, inv_cell = fprm[F_HMAX], 1.0 / fprm[F_CELL]
    ox, oy, oz = fprm[F_OX], fprm[F_OY], fprm[F_OZ]
    for k in range(cell_start[-1]):
        xi, yi, zi, hi = sx[k, 0], sx[k, 1], sx[k, 2], sx[k, 3]
        reach = hi + hmax
        x0, x1 = _cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = _cell_range(yi, reach, oy, inv_cell, ny)
        z0, z1 = _cell_range(zi, reach, oz, inv_cell, nz)
        cnt = 0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if j == k:
                        continue
                    dx, dy, dz = xi - sx[j, 0], yi - sx[j, 1], zi - sx[j, 2]
                    hij = 0.5 * (hi + sx[j, 3])
                    if dx * dx + dy * dy + dz * dz < 4.0 * hij * hij:
                        cnt += 1
        counts[k] = cnt


@njit(cache=True)
def fill_neighbours(sx, cell_start, fprm, iprm, offsets, out):
    """CSR neighbour lists in slot numbering (``offsets`` from ``count_neighbours``)."""
    nx, ny, nz = iprm[I_NX], iprm[I_NY], iprm[I_NZ]
    hmax, inv_cell = fprm[F_HMAX], 1.0 / fprm[F_CELL]
    ox, oy, oz = fprm[F_OX], fprm[F_OY], fprm[F_OZ]
    for k in range(cell_start[-1]):
        xi, yi, zi, hi = sx[k, 0], sx[k, 1], sx[k, 2], sx[k, 3]
        reach = hi + hmax
        x0, x1 = _cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = _cell_range(yi, reach, oy, inv_cell, ny)
        z0, z1 = _cell_range(zi, reach, oz, inv_cell, nz)
        pos = offsets[k]
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if j == k:
                        continue
                    dx, dy, dz = xi - sx[j, 0], yi - sx[j, 1], zi - sx[j, 2]
                    hij = 0.5 * (hi + sx[j, 3])
                    if dx * dx + dy * dy + dz * dz < 4.0 * hij * hij:
                        out[pos] = j
                        pos += 1


@njit(cache=True)
def interpolate_points(points, sx, sd, cell_start, fprm, iprm, column, include_walls):
    """Shepard-normalised SPH interpolation at arbitrary ``points`` (P, 3).

    f(x) = sum_j V_j f_j W(|x - x_j|, h_j) / sum_j V_j W(|x - x_j|, h_j) over fluid and ghost
    points (and wall points with ``include_walls``). ``column`` selects the field: a column of
    ``sd`` (D_VX .. D_C), or -1 for the pressure p = (p/rho^2) rho^2. NaN where no point is near.
    """
    kernel, dim = iprm[I_KERNEL], iprm[I_DIM]
    nx, ny, nz = iprm[I_NX], iprm[I_NY], iprm[I_NZ]
    hmax, inv_cell = fprm[F_HMAX], 1.0 / fprm[F_CELL]
    ox, oy, oz = fprm[F_OX], fprm[F_OY], fprm[F_OZ]
    out = np.empty(points.shape[0])
    for a in range(points.shape[0]):
        xi, yi, zi = points[a, 0], points[a, 1], points[a, 2]
        reach = 2.0 * hmax
        x0, x1 = _cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = _cell_range(yi, reach, oy, inv_cell, ny)
        z0, z1 = _cell_range(zi, reach, oz, inv_cell, nz)
        num = 0.0
        den = 0.0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if (int(sd[j, D_MK]) & 3) == KIND_WALL and not include_walls:
                        continue
                    dx, dy, dz = xi - sx[j, 0], yi - sx[j, 1], zi - sx[j, 2]
                    r = math.sqrt(dx * dx + dy * dy + dz * dz)
                    wv = kernel_w(kernel, dim, r, sx[j, 3])
                    if wv == 0.0:
                        continue
                    vw = sd[j, D_VOL] * wv
                    if column < 0:
                        val = sd[j, D_PR] * sd[j, D_RHO] * sd[j, D_RHO]
                    else:
                        val = sd[j, column]
                    num += vw * val
                    den += vw
        out[a] = num / den if den > 0.0 else np.nan
    return out


# ------------------------------------------------------------------------- time integration


@njit(cache=True)
def kick_drift(x, v, v_half, rho, rho_half, e, e_half, acc, drho, de, xsph, f_ext, m, active,
               gravity, dt, dt_prev, work):
    """One leapfrog step (kick-drift-kick, one rate evaluation per step).

    With total acceleration a^n = acc + g + f_ext/m and rates evaluated at step n:
      v^n      = v^{n-1/2} + dt_prev/2 a^n           (closes the previous step; skipped if dt_prev = 0)
      v^{n+1/2} = v^n + dt/2 a^n
      x^{n+1}  = x^n + dt (v^{n+1/2} + xsph^n)
      v       <- v^{n+1/2} + dt/2 a^n                 (prediction of v^{n+1} for the next rates)
    and the same for rho and e (their rates are drho, de). Net effect
    v^{n+1/2} = v^{n-1/2} + (dt_prev + dt)/2 a^n, the central difference of the FEM loop.
    ``work[i]`` = f_ext . (v^{n-1/2} + v^{n+1/2})/2 (dt_prev + dt)/2, the work of f_ext over the
    step exactly as the kicks apply it (the FEM loop counts nodal work the same way), so that an
    impulsive force (contact) is not over-counted.
    """
    dim = x.shape[1]
    hp = 0.5 * dt_prev
    hn = 0.5 * dt
    for i in range(x.shape[0]):
        if not active[i]:
            work[i] = 0.0
            continue
        im = 1.0 / m[i]
        pw = 0.0
        for d in range(dim):
            a = acc[i, d] + gravity[d] + f_ext[i, d] * im
            v_old = v_half[i, d] if dt_prev > 0.0 else v[i, d]
            vn = v_old + hp * a
            vh = vn + hn * a
            v_half[i, d] = vh
            x[i, d] += dt * (vh + xsph[i, d])
            v[i, d] = vh + hn * a
            pw += f_ext[i, d] * 0.5 * (v_old + vh)
        work[i] = pw * (hp + hn)
        rn = rho_half[i] + hp * drho[i] if dt_prev > 0.0 else rho[i]
        rh = rn + hn * drho[i]
        rho_half[i] = rh
        rho[i] = rh + hn * drho[i]
        en = e_half[i] + hp * de[i] if dt_prev > 0.0 else e[i]
        eh = en + hn * de[i]
        e_half[i] = eh
        e[i] = eh + hn * de[i]


@njit(cache=True)
def advance_particles(x, v, v_half, rho, rho_half, e, e_half, acc, drho, de, xsph, f_ext, m, active,
                      gravity, dt, dt_prev, walls, lo, hi, use_domain):
    """``kick_drift`` then ``enforce_bounds``; zeroes the rates of particles just deactivated.

    Returns (work of f_ext over the step (see ``kick_drift``), number reflected at walls, number
    deactivated, their mass, their kinetic + internal energy).
    """
    n = x.shape[0]
    work = np.empty(n)
    kick_drift(x, v, v_half, rho, rho_half, e, e_half, acc, drho, de, xsph, f_ext, m, active, gravity, dt,
               dt_prev, work)
    ptot = 0.0
    for i in range(n):
        ptot += work[i]
    crossed = np.zeros(n, dtype=np.int64)
    lost = np.zeros(n, dtype=np.int64)
    nref, nlost = 0, 0
    lost_mass = 0.0
    lost_energy = 0.0
    if walls.shape[0] > 0 or use_domain:
        nref, nlost = enforce_bounds(x, v, v_half, active, walls, lo, hi, use_domain, crossed, lost)
        if nlost:
            dim = x.shape[1]
            for i in range(n):
                if lost[i]:
                    ke = 0.0
                    for d in range(dim):
                        ke += v[i, d] * v[i, d]
                        acc[i, d] = 0.0
                        xsph[i, d] = 0.0
                    lost_mass += m[i]
                    lost_energy += m[i] * (0.5 * ke + e[i])
                    drho[i] = 0.0
                    de[i] = 0.0
    return ptot, nref, nlost, lost_mass, lost_energy


@njit(cache=True)
def enforce_bounds(x, v, v_half, active, walls, lo, hi, use_domain, crossed, lost):
    """After the drift: reflect particles that crossed a ghost wall; deactivate those outside the domain.

    A particle found behind a wall plane is mirrored back and its normal velocity reversed
    (``crossed[i]`` = 1); one outside the domain box is deactivated (``lost[i]`` = 1).
    Returns (number reflected, number deactivated).
    """
    dim = x.shape[1]
    nref = 0
    nlost = 0
    for i in range(x.shape[0]):
        crossed[i] = 0
        lost[i] = 0
        if not active[i]:
            continue
        for w in range(walls.shape[0]):
            ax = int(walls[w, 0])
            pos, side = walls[w, 1], walls[w, 2]
            if side * (x[i, ax] - pos) < 0.0:
                x[i, ax] = 2.0 * pos - x[i, ax]
                v[i, ax] = -v[i, ax]
                v_half[i, ax] = -v_half[i, ax]
                crossed[i] = 1
        nref += crossed[i]
        if use_domain:
            for d in range(dim):
                if not (lo[d] <= x[i, d] <= hi[d]):
                    active[i] = False
                    lost[i] = 1
                    nlost += 1
                    break
    return nref, nlost


@njit(cache=True)
def stable_time_step(h, c, v, acc, f_ext, m, rho, mat, active, params, gravity, cfl, cforce, cvisc):
    """min over active particles of cfl h/(c + |v|), cforce sqrt(h/|a|), cvisc rho h^2/mu."""
    dim = v.shape[1]
    dt = np.inf
    ha = np.inf
    for i in range(h.shape[0]):
        if not active[i]:
            continue
        vv = 0.0
        aa = 0.0
        im = 1.0 / m[i]
        for d in range(dim):
            vv += v[i, d] * v[i, d]
            a = acc[i, d] + gravity[d] + f_ext[i, d] * im
            aa += a * a
        speed = c[i] + math.sqrt(vv)
        if speed > 0.0:
            dt = min(dt, cfl * h[i] / speed)
        if aa > 0.0:
            # min of cforce sqrt(h/|a|) = cforce sqrt(min of h/|a|): sqrt is monotonic and
            # correctly rounded, so taking it once at the end gives the same number
            ha = min(ha, h[i] / math.sqrt(aa))
        mu = params[mat[i], P_VISCOSITY]
        if mu > 0.0:
            dt = min(dt, cvisc * rho[i] * h[i] * h[i] / mu)
    if ha < np.inf:
        dt = min(dt, cforce * math.sqrt(ha))
    return dt
