"""SPH walls: ghost (mirror) particles of planar walls, the pressure of dummy wall particles, the
no-slip friction of the ghosts and the wall-function shear of slip walls.

Ghosts (``count_ghosts``, ``fill_ghosts``, ``make_ghosts``): one image of a particle per valid
subset of the planes it is near, mirrored about a wall's plane (Marrone et al. 2011, fixed ghost
particles), offset by twice its initial distance across a non-reflecting open side
(``sph/open_sides.py``). Dummy walls (``wall_pressure``): Adami et al. (2012). ``ghost_friction``: the no-slip correction of the
artificial viscosity. ``wall_shear``: the log-law wall shear on the first particle layer of a
``wall_function`` wall. Point layout and cell search: ``sph/search.py``; equations:
docs/theory/sph.md ("Boundaries").
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit, prange

from ..materials.kernels import EOS_OFFSET, P_EOS_TYPE, P_RHO0
from ..materials.slots import P_VISCOSITY, Q_E0
from .eos import density_from_pressure, sound_speed
from .kernel_functions import inv_pow, kernel_shape, kernel_f, kernel_sigma
from .rates import _FM
from .search import cell_range
from .slots import (D_C, D_MK, D_PR, D_RHO, D_VOL, D_VX, D_VY, D_VZ, GF_CELL, GF_OX, GF_OY, GF_OZ, GI_NX, GI_NY,
                    GI_NZ, KIND_FLUID, KIND_GHOST, KIND_WALL, PLANE_NO_SLIP, PLANE_OPEN, SF_ALPHA, SF_BETA,
                    SF_BETA_PER_ALPHA, SF_EPS, SF_GX, SF_GY, SF_GZ, SF_PRESSURE_CUTOFF, SI_DIM, SI_KERNEL)


@dataclass(frozen=True)
class Wall:
    """An axis-aligned planar wall x[axis] = position, modelled by ghost (mirror) particles.

    ``side`` = +1 when the fluid lies on x[axis] > position (e.g. a floor or a left wall),
    -1 when it lies below (a right wall, a ceiling). ``condition``: "slip" mirrors the normal
    velocity only; "no_slip" reverses the whole velocity (wall at rest); "wall_function" has slip
    ghosts and the smooth-wall law's shear on the first particle layer (``walls.wall_shear``);
    "non_reflecting" is no wall but an open side: its ghosts are images that move with their particles
    (the side moves with the water; no particle is deleted) and carry the impedance condition's pressure
    (``sph.open_sides``), for waves from ``source`` (a point, the centre of a spherical / cylindrical
    wave) or, without one, plane waves at normal incidence.
    """

    axis: int
    position: float
    side: int = 1
    condition: str = "slip"
    source: tuple | None = None

    def __post_init__(self):
        if self.side not in (1, -1):
            raise ValueError(f"wall side must be +1 or -1, got {self.side}")
        if self.condition not in ("slip", "no_slip", "wall_function", "non_reflecting"):
            raise ValueError("wall condition must be 'slip', 'no_slip', 'wall_function' or 'non_reflecting', "
                             f"got {self.condition!r}")
        if self.source is not None and self.condition != "non_reflecting":
            raise ValueError("only a non_reflecting side takes a source")


def box_walls(lo: Sequence[float], hi: Sequence[float], sides: Sequence[str], condition: str = "slip",
              source: Sequence[float] | None = None) -> list[Wall]:
    """Walls on the named faces of the box [lo, hi]: 'left'/'right' (x), 'bottom'/'top' (y),
    'back'/'front' (z); in 2D 'bottom'/'top' are y. ``source``:
    non_reflecting sides only (``Wall``)."""
    from ..deck.schema.boundaries import BOX_FACES

    out = []
    for s in sides:
        axis, which, side = BOX_FACES[s]
        out.append(Wall(axis, float((lo, hi)[which][axis]), side, condition,
                        None if source is None else tuple(float(v) for v in source)))
    return out



@njit(cache=True)
def _near_mask(x, d0, i, walls, reach):
    """Bit w set when particle i is near plane w: its distance 0 <= d < reach, d the distance now for a
    wall, the distance at t = 0 (``d0[i, w]``) for an open side (its image layer is the particles that
    started within reach of it: ``sph/open_sides.py``)."""
    mask = 0
    for w in range(walls.shape[0]):
        if walls[w, 3] == PLANE_OPEN:
            d = d0[i, w]
        else:
            d = walls[w, 2] * (x[i, int(walls[w, 0])] - walls[w, 1])
        if 0.0 <= d < reach:
            mask |= 1 << w
    return mask


@njit(cache=True)
def count_ghosts(x, d0, active, walls, valid, reach, counts):
    """Number of images of each particle: one per valid subset of the planes it is near (``_near_mask``).

    ``walls`` (nw, 4 or more): axis, position, side (+1 fluid where x[axis] > position, -1 below),
    condition code (``PLANE_SLIP``, ``PLANE_NO_SLIP``, ``PLANE_OPEN``: a non-reflecting open side,
    ``sph/open_sides.py``). ``d0`` (N, nw): each particle's distance from each plane at t = 0, read for
    the open sides only (with none, (N, 0)). ``valid[s]`` is true for plane subsets ``s`` (bit masks)
    with at most one plane per axis (a corner image is the image across both planes of the corner).
    """
    for i in range(x.shape[0]):
        cnt = 0
        if active[i]:
            mask = _near_mask(x, d0, i, walls, reach)
            if mask != 0:
                for s in range(1, valid.shape[0]):
                    if valid[s] and (s & mask) == s:
                        cnt += 1
        counts[i] = cnt


@njit(cache=True)
def fill_ghosts(x, v, rho, c, d0, active, walls, valid, reach, offsets, gravity, hydrostatic, gpos, gvel, gflip,
                gsrc, gsub, gdp, gdr):
    """Ghost positions, velocities, viscous flips, source particles, plane subsets (``gsub``, the bit mask
    of the planes the image lies across) and pressure offsets (see ``count_ghosts``).

    Position: across a wall the mirror image about its plane, x_ax -> 2 x_w - x_ax; across an open
    side (code ``PLANE_OPEN``) the particle's own position offset by twice its distance from the side
    at t = 0, x_ax -> x_ax - 2 side d0_iw (``sph/open_sides.py``: the image moves with its particle;
    a corner of an open side and a wall is mirrored across the wall and offset across the side; the
    two act on different axes, so the order does not matter). Velocity: the free-slip mirror (normal
    component reversed) on every wall, slip or no-slip: that is the velocity the continuity,
    pressure and delta-SPH terms see, so a wall is impermeable without being a source of volume.
    Through an open side (code ``PLANE_OPEN``) the velocity is copied, not mirrored (zero-gradient
    extrapolation; ``open_sides.open_ghost_state`` then sets the pressure of such ghosts).
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
        mask = _near_mask(x, d0, i, walls, reach)
        x0 = x[i, 0]
        x1 = x[i, 1]
        x2 = x[i, 2] if dim > 2 else 0.0
        v0 = v[i, 0]
        v1 = v[i, 1]
        v2 = v[i, 2] if dim > 2 else 0.0
        for s in range(1, valid.shape[0]):
            if not (valid[s] and (s & mask) == s):
                continue
            p0, p1, p2, u0, u1, u2 = x0, x1, x2, v0, v1, v2
            f0 = f1 = f2 = 1.0
            for w in range(walls.shape[0]):
                if s & (1 << w):
                    ax = int(walls[w, 0])
                    noslip = walls[w, 3] == PLANE_NO_SLIP
                    if walls[w, 3] == PLANE_OPEN:  # offset by 2 d0 outwards, velocity copied
                        shift = -2.0 * walls[w, 2] * d0[i, w]
                        if ax == 0:
                            p0 += shift
                        elif ax == 1:
                            p1 += shift
                        else:
                            p2 += shift
                    else:  # mirrored about the plane, normal velocity reversed
                        pos2 = 2.0 * walls[w, 1]
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
            gsub[k] = s
            if hydrostatic:
                dp = rho[i] * (gravity[0] * (p0 - x0) + gravity[1] * (p1 - x1) + gravity[2] * (p2 - x2))
                gdp[k] = dp
                gdr[k] = dp / (c[i] * c[i]) if c[i] > 0.0 else 0.0
            else:
                gdp[k] = 0.0
                gdr[k] = 0.0
            k += 1


@njit(cache=True)
def make_ghosts(x, v, rho, c, d0, active, walls, valid, reach, gravity, hydrostatic):
    """Ghost particles of the planar walls and open sides: ``(gpos, gvel, gflip, gsrc, gsub, gdp, gdr)``
    (see ``fill_ghosts``; ``d0`` as in ``count_ghosts``)."""
    n = x.shape[0]
    # the particles near a wall (few) are found first, wall by wall (loops over the particles
    # that LLVM vectorises; the test of _near_mask); their images are counted and filled for
    # those only, in the order count_ghosts/fill_ghosts give over all particles
    flag = np.zeros(n, dtype=np.uint8)
    for w in range(walls.shape[0]):
        ax = int(walls[w, 0])
        pos, side = walls[w, 1], walls[w, 2]
        if walls[w, 3] == PLANE_OPEN:
            for i in range(n):
                flag[i] |= (0.0 <= d0[i, w]) & (d0[i, w] < reach)
        else:
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
    d0s = d0[sub]
    count_ghosts(x[sub], d0s, np.ones(nnear, dtype=np.bool_), walls, valid, reach, counts)
    offsets = np.zeros(nnear + 1, dtype=np.int64)
    for a in range(nnear):
        offsets[a + 1] = offsets[a] + counts[a]
    ng = offsets[nnear]
    gpos = np.empty((ng, 3))
    gvel = np.empty((ng, 3))
    gflip = np.empty((ng, 3))
    gsrc = np.empty(ng, dtype=np.int64)
    gsub = np.empty(ng, dtype=np.int64)
    gdp = np.empty(ng)
    gdr = np.empty(ng)
    fill_ghosts(x[sub], v[sub], rho[sub], c[sub], d0s, np.ones(nnear, dtype=np.bool_), walls, valid, reach, offsets,
                gravity, hydrostatic, gpos, gvel, gflip, gsrc, gsub, gdp, gdr)
    for g in range(ng):
        gsrc[g] = sub[gsrc[g]]
    return gpos, gvel, gflip, gsrc, gsub, gdp, gdr


@njit(cache=True, parallel=True, fastmath=_FM, error_model="numpy")
def wall_pressure(sx, sd, cell_start, sreach, settings_f, settings_i, grid_f, grid_i, params):
    """Adami et al. (2012) pressure of the dummy wall points, extrapolated from the fluid.

    p_w = (sum_f p_f W_wf + g . sum_f rho_f r_wf W_wf) / sum_f W_wf (fixed wall, a_w = 0), over
    fluid points f within 2 h_wf; rho_w inverts the wall material's EOS at p_w (energy e0).
    A wall point with no fluid neighbour keeps p = 0. Writes rho, p/rho^2 and c of wall slots.
    """
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    cell = grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    gx, gy, gz = settings_f[SF_GX], settings_f[SF_GY], settings_f[SF_GZ]
    pressure_cutoff = settings_f[SF_PRESSURE_CUTOFF]
    inv_cell = 1.0 / cell
    sig = kernel_sigma(kernel, dim)
    for k in prange(cell_start[-1]):
        mk = int(sd[D_MK, k])
        if (mk & 3) != KIND_WALL:
            continue
        xi, yi, zi, hi = sx[0, k], sx[1, k], sx[2, k], sx[3, k]
        reach = sreach[k]  # bounds every 2 h_kj (search.search_reach)
        x0, x1 = cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = cell_range(yi, reach, oy, inv_cell, ny)
        z0, z1 = cell_range(zi, reach, oz, inv_cell, nz)
        sw = 0.0
        spw = 0.0
        srx = 0.0
        sry = 0.0
        srz = 0.0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if (int(sd[D_MK, j]) & 3) != KIND_FLUID:
                        continue
                    dx = xi - sx[0, j]
                    dy = yi - sx[1, j]
                    dz = zi - sx[2, j]
                    hij = 0.5 * (hi + sx[3, j])
                    r2 = dx * dx + dy * dy + dz * dz
                    if r2 >= 4.0 * hij * hij:
                        continue
                    inv = 1.0 / hij
                    wv = sig * inv_pow(inv, dim) * kernel_shape(kernel, math.sqrt(r2) * inv)[0]
                    rj = sd[D_RHO, j]
                    sw += wv
                    spw += sd[D_PR, j] * rj * rj * wv
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
        if pw < pressure_cutoff:
            pw = pressure_cutoff
        rw = density_from_pressure(eos, q, rho0, pw, q[Q_E0], sd[D_RHO, k])
        sd[D_VOL, k] *= sd[D_RHO, k] / rw  # same mass at the new density
        sd[D_RHO, k] = rw
        sd[D_PR, k] = pw / (rw * rw)
        sd[D_C, k] = sound_speed(eos, q, rw / rho0, q[Q_E0])


@njit(cache=True, parallel=True, error_model="numpy")
def ghost_friction(sx, sd, svf, slots, perm, cell_start, sreach, settings_f, settings_i, grid_f, grid_i, acc, de,
                   salpha):
    """No-slip correction of the artificial viscosity between fluid particles and ghosts.

    ``fluid_rates`` evaluates every ghost with its free-slip velocity v_g (``fill_ghosts``). Near
    a no-slip wall the viscous term must see the no-slip velocity v_g' = svf_g * v_g instead; for
    the fluid slots ``slots`` (the particles with a no-slip ghost) this adds, over the ghosts g
    within 2 h_ig whose factors are not all 1,

      acc_i -= sum_g m_g (Pi_ig' - Pi_ig) grad_i W_ig,     de_i += sum_g m_g (Pi_ig' - Pi_ig) v_i . grad_i W_ig

    with Pi_ig' and Pi_ig the Monaghan viscosity of ``fluid_rates`` with v_i - v_g' and v_i - v_g.
    The wall is at rest and does no work: the kinetic energy the friction takes from particle i
    goes, all of it, into its internal energy (so ghost walls conserve energy, no-slip or not).
    With the shock switch (``salpha``, the alpha of every slot, longer than 1: ``sph/switch.py``) Pi takes the
    pair's alpha_ig = (alpha_i + alpha_g)/2 and beta_ig = (beta/alpha) alpha_ig, as in ``fluid_rates``; a
    one-entry ``salpha`` means the section's alpha and beta.
    """
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    alpha, beta, eps = settings_f[SF_ALPHA], settings_f[SF_BETA], settings_f[SF_EPS]
    bpa = settings_f[SF_BETA_PER_ALPHA]
    switched = salpha.shape[0] > 1
    cell = grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    inv_cell = 1.0 / cell
    for t in prange(slots.shape[0]):
        k = slots[t]
        xi, yi, zi, hi = sx[0, k], sx[1, k], sx[2, k], sx[3, k]
        ui, vi, wi = sd[D_VX, k], sd[D_VY, k], sd[D_VZ, k]
        rhoi, ci = sd[D_RHO, k], sd[D_C, k]
        reach = sreach[k]  # bounds every 2 h_kj (search.search_reach)
        x0, x1 = cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = cell_range(yi, reach, oy, inv_cell, ny)
        z0, z1 = cell_range(zi, reach, oz, inv_cell, nz)
        ax = ay = az = power = 0.0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if (int(sd[D_MK, j]) & 3) != KIND_GHOST:
                        continue
                    f0, f1, f2 = svf[j, 0], svf[j, 1], svf[j, 2]
                    if f0 == 1.0 and f1 == 1.0 and f2 == 1.0:
                        continue
                    dx, dy, dz = xi - sx[0, j], yi - sx[1, j], zi - sx[2, j]
                    hij = 0.5 * (hi + sx[3, j])
                    r2 = dx * dx + dy * dy + dz * dz
                    if r2 >= 4.0 * hij * hij:
                        continue
                    uj, vj, wj = sd[D_VX, j], sd[D_VY, j], sd[D_VZ, j]
                    slip = min((ui - uj) * dx + (vi - vj) * dy + (wi - wj) * dz, 0.0)
                    stuck = min((ui - f0 * uj) * dx + (vi - f1 * vj) * dy + (wi - f2 * wj) * dz, 0.0)
                    dd = r2 + eps * hij * hij
                    rhoij = 0.5 * (rhoi + sd[D_RHO, j])
                    cij = 0.5 * (ci + sd[D_C, j])
                    scale = hij / (dd * rhoij)
                    mu_s, mu_n = scale * slip, scale * stuck  # mu_ij / rho_ij
                    aij = 0.5 * (salpha[k] + salpha[j]) if switched else alpha
                    bij = bpa * aij if switched else beta
                    dpi = (bij * rhoij * (mu_n * mu_n - mu_s * mu_s) - aij * cij * (mu_n - mu_s))
                    coef = sd[D_VOL, j] * sd[D_RHO, j] * dpi * kernel_f(kernel, dim, math.sqrt(r2), hij)
                    ax -= coef * dx
                    ay -= coef * dy
                    az -= coef * dz
                    power += coef * (ui * dx + vi * dy + wi * dz)
        i = perm[k]
        acc[i, 0] += ax
        acc[i, 1] += ay
        if dim > 2:
            acc[i, 2] += az
        de[i] += power


KAPPA = 0.41  # von Karman constant
LOG_E = 9.8   # smooth-wall log-law constant E (u+ = ln(E y+) / kappa, i.e. B = 5.56)
Y_PLUS_LAMINAR = 11.06  # where u+ = y+ meets the log law


@njit(cache=True)
def friction_velocity(u, y, nu):
    """u_tau of the smooth-wall law of the wall at distance ``y`` where the tangential speed is ``u``:
    u/u_tau = y u_tau/nu in the viscous sublayer (y+ < 11.06), else u/u_tau = ln(E y u_tau/nu)/kappa
    (Spalding's two-layer form; Pope, Turbulent Flows, 2000, section 7.1), solved by Newton's method."""
    if u <= 0.0 or nu <= 0.0:
        return 0.0
    ut = math.sqrt(nu * u / y)
    if ut * y / nu <= Y_PLUS_LAMINAR:
        return ut
    for _ in range(50):  # f(ut) = ut ln(E y ut/nu) - kappa u, f' = ln(E y ut/nu) + 1; from the sublayer guess
        g = math.log(LOG_E * y * ut / nu)
        step = (ut * g - KAPPA * u) / (g + 1.0)
        ut -= step
        if abs(step) < 1e-12 * ut:
            break
    return ut


@njit(cache=True, error_model="numpy")
def wall_shear(x, v, rho, m, mat, active, params, wf_walls, acc, de):
    """Wall-function friction of slip-ghost walls (``condition: wall_function``) on the first layer.

    A particle i of spacing d_i = (m_i/rho_i)^(1/dim) within d_i of such a wall (distance y_i from
    it, tangential velocity u_t) carries the wall shear tau_w = rho_i u_tau^2 of the smooth-wall law
    (``friction_velocity`` with nu = mu/rho of its material at y = max(y_i, d_i/2): the particle
    stands for the layer [0, d_i], whose mean velocity sits at its middle; a particle pressed closer
    to the wall would otherwise get an unbounded sublayer shear nu u_t/y_i, explicitly unstable)
    over its wall area d_i^(dim-1), against u_t:

      acc_i -= (u_tau^2 / d_i) u_t/|u_t|,      de_i += (u_tau^2 / d_i) |u_t|

    (the wall is at rest: the kinetic energy the friction takes goes into internal energy). The drag
    depends on the wall distance and the fluid's viscosity, not on the kernel support; an inviscid
    material (mu = 0) feels none. ``wf_walls`` (K, 3): axis, position, side (+1 fluid above).
    """
    dim = x.shape[1]
    for i in range(x.shape[0]):
        if not active[i]:
            continue
        mu = params[mat[i], P_VISCOSITY]
        if mu <= 0.0:
            continue
        d = (m[i] / rho[i]) ** (1.0 / dim)
        for w in range(wf_walls.shape[0]):
            ax = int(wf_walls[w, 0])
            y = wf_walls[w, 2] * (x[i, ax] - wf_walls[w, 1])
            if y <= 0.0 or y >= d:
                continue
            speed2 = 0.0
            for k in range(dim):
                if k != ax:
                    speed2 += v[i, k] * v[i, k]
            u = math.sqrt(speed2)
            if u == 0.0:
                continue
            ut = friction_velocity(u, max(y, 0.5 * d), mu / rho[i])
            a = ut * ut / d
            for k in range(dim):
                if k != ax:
                    acc[i, k] -= a * v[i, k] / u
            de[i] += a * u
