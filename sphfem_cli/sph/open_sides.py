"""Non-reflecting open sides of an SPH fluid: the state of their ghost particles and the work they do.

An open side is a plane x[axis] = position (``walls.Wall`` with condition "non_reflecting"). Its
ghosts are the mirror images of the particles within the kernel support of it (``walls.make_ghosts``,
the machinery of the ghost walls, corner images included), with

* the velocity of their source particle, copied (not mirrored: ``walls.fill_ghosts``), a
  zero-gradient extrapolation of the velocity through the side;
* the pressure of the impedance condition at the ghost (``open_ghost_state``):

      p_g = p_far + rho_i c_i (v_g . n) [- k (c_i / r_g) I_i]

  n the side's outward normal (without a source; the normalised sum of the outward normals at a
  corner of two open sides), or with a ``source`` point x_s the radial unit vector (x_g - x_s) / r_g,
  r_g = |x_g - x_s|; k = 1/2 in plane 2D (a cylindrical wave), 1 in 3D; I_i = int (p_i - p_far,i) dt
  the impulse of the source particle's pressure excess since t = 0 (``SphSystem`` integrates it);
  p_far = the source particle's pressure at the first evaluation plus the hydrostatic increment
  rho_i g . (x_g - x_i) (the far field at rest). Without a source this is the plane-wave condition
  of Lysmer & Kuhlemeyer (1969), p' = rho c u_n; with it the first-order condition of Bayliss &
  Turkel (1980) for the outgoing spherical / cylindrical wave, as on the ALE solver's
  ``non_reflecting`` sides (docs/theory/ale.md). The density of the ghost is rho_i + (p_g - p_i)/c_i^2.

Why it does not reflect (docs/theory/sph.md, "Non-reflecting open sides"): in linear acoustics on
a uniform lattice the SPH momentum and continuity sums apply the same difference operator to p and
u, so the incoming characteristic p' - Z u_n obeys a closed equation; ghosts on which it is 0
(the condition above) feed none into the fluid, whatever the outgoing one does there. The buffer of
ghosts is the characteristic buffer of Lastiwka, Basa & Quinlan (2009, IJNMF 61:709), with the
incoming Riemann invariant taken from the far field and the velocity extrapolated from the fluid.

Particles crossing an open side leave the fluid (``SphSystem`` deactivates them: the side bounds
the domain). No particle enters: where the fluid flows inwards it recedes from the side, and its
images then lie 2 d from it (d the gap), so a gap of more than a fraction of the spacing
makes the side progressively a free surface (in decks/underwater_explosion_sph.yaml the mean gap
stays 1.0-1.6 mm, dx 2.5 mm, to 1.3 ms; docs/theory/sph.md).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from .kernel_functions import kernel_f
from .search import cell_range
from .slots import (D_C, D_MK, D_PR, D_RHO, D_VOL, D_VX, D_VY, D_VZ, GF_CELL, GF_OX, GF_OY, GF_OZ, GI_NX, GI_NY,
                    GI_NZ, KIND_FLUID, PLANE_NO_SLIP, PLANE_OPEN, PLANE_SLIP, SF_ALPHA, SF_BETA, SF_EPS, SI_DIM,
                    SI_KERNEL)


@njit(cache=True)
def open_ghost_state(x, p, rho, c, p_far, impulse, gpos, gvel, gsrc, gdp, gdr, planes, k_wave, gravity,
                     pressure_cutoff, is_open):
    """Pressure and density offsets (``gdp``, ``gdr``) of the ghosts beyond an open side (module docstring).

    ``planes`` (nw, 7): axis, position, side (+1 fluid above), condition code, source point (3, NaN for
    none: plane waves); the ghost g of particle i = gsrc[g] is an open ghost when it lies beyond a plane
    of code ``PLANE_OPEN`` (with a source when one of those planes has one). ``k_wave``: k of the
    Bayliss-Turkel term. The ghost pressure is held at ``pressure_cutoff`` or above, as the fluid's.
    Writes ``is_open[g]``.
    """
    dim = x.shape[1]
    for g in range(gsrc.shape[0]):
        n0 = n1 = n2 = 0.0
        beyond = False
        spherical = False
        s0 = s1 = s2 = 0.0
        for w in range(planes.shape[0]):
            if planes[w, 3] != PLANE_OPEN:
                continue
            ax = int(planes[w, 0])
            if planes[w, 2] * (gpos[g, ax] - planes[w, 1]) < 0.0:
                beyond = True  # outward normal: -side along the axis
                if not math.isnan(planes[w, 4]):
                    spherical = True
                    s0, s1, s2 = planes[w, 4], planes[w, 5], planes[w, 6]
                if ax == 0:
                    n0 -= planes[w, 2]
                elif ax == 1:
                    n1 -= planes[w, 2]
                else:
                    n2 -= planes[w, 2]
        is_open[g] = beyond
        if not beyond:
            continue
        i = gsrc[g]
        pf = p_far[i]
        for d in range(dim):
            pf += rho[i] * gravity[d] * (gpos[g, d] - x[i, d])
        z = rho[i] * c[i]
        extra = 0.0
        if spherical:
            n0, n1, n2 = gpos[g, 0] - s0, gpos[g, 1] - s1, gpos[g, 2] - s2
            r = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
            extra = -k_wave * c[i] / r * impulse[i]
        else:
            r = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
        un = (gvel[g, 0] * n0 + gvel[g, 1] * n1 + gvel[g, 2] * n2) / r
        pg = max(pf + z * un + extra, pressure_cutoff)
        gdp[g] = pg - p[i]
        gdr[g] = gdp[g] / (c[i] * c[i]) if c[i] > 0.0 else 0.0


@njit(cache=True, parallel=True, error_model="numpy")
def open_side_power(sx, sd, sopen, slots, perm, cell_start, sreach, settings_f, settings_i, grid_f, grid_i, power):
    """The power the open sides' ghosts put into the fluid: for the fluid slots ``slots`` (those with an
    open ghost within reach), over the open ghosts g (``sopen`` true) within 2 h_ig,

      power_i = -1/2 sum_g m_i m_g S_ig (v_i + v_g) . grad_i W_ig,  S = p_i/rho_i^2 + p_g/rho_g^2 + Pi_ig,

    the sum of m_i v_i . acc_i + m_i de_i over those pairs in ``rates.fluid_rates`` (pressure and
    Monaghan viscosity; a viscous material's stress pairs are not counted). Written at particle
    perm[k]; the energy balance books its time integral as work done on the fluid (negative: radiated).
    """
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    alpha, beta, eps = settings_f[SF_ALPHA], settings_f[SF_BETA], settings_f[SF_EPS]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    inv_cell = 1.0 / grid_f[GF_CELL]
    for t in prange(slots.shape[0]):
        k = slots[t]
        if (int(sd[D_MK, k]) & 3) != KIND_FLUID:
            continue
        xi, yi, zi, hi = sx[0, k], sx[1, k], sx[2, k], sx[3, k]
        ui, vi, wi = sd[D_VX, k], sd[D_VY, k], sd[D_VZ, k]
        rhoi, ci = sd[D_RHO, k], sd[D_C, k]
        mi = sd[D_VOL, k] * rhoi
        reach = sreach[k]
        x0, x1 = cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = cell_range(yi, reach, oy, inv_cell, ny)
        z0, z1 = cell_range(zi, reach, oz, inv_cell, nz)
        total = 0.0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if not sopen[j]:
                        continue
                    dx, dy, dz = xi - sx[0, j], yi - sx[1, j], zi - sx[2, j]
                    hij = 0.5 * (hi + sx[3, j])
                    r2 = dx * dx + dy * dy + dz * dz
                    if r2 >= 4.0 * hij * hij:
                        continue
                    uj, vj, wj = sd[D_VX, j], sd[D_VY, j], sd[D_VZ, j]
                    vdr = min((ui - uj) * dx + (vi - vj) * dy + (wi - wj) * dz, 0.0)
                    dd = r2 + eps * hij * hij
                    rhoj = sd[D_RHO, j]
                    mu = hij * vdr / dd
                    pi_ij = (beta * mu * mu - alpha * 0.5 * (ci + sd[D_C, j]) * mu) / (0.5 * (rhoi + rhoj))
                    s = sd[D_PR, k] + sd[D_PR, j] + pi_ij
                    f = kernel_f(kernel, dim, math.sqrt(r2), hij)
                    total -= 0.5 * mi * sd[D_VOL, j] * rhoj * s * f * ((ui + uj) * dx + (vi + vj) * dy
                                                                       + (wi + wj) * dz)
        power[perm[k]] = total


def open_slots(perm: np.ndarray, n: int, is_open: np.ndarray, gsrc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(per-slot flag of the open ghosts, sorted slots of the fluid particles that have one)."""
    ng = len(is_open)
    point_open = np.zeros(len(perm) + 1, dtype=np.bool_)
    pid = perm
    ghost = (pid >= n) & (pid < n + ng)
    point_open[:len(perm)][ghost] = is_open[pid[ghost] - n]
    slot_of = np.full(n, -1, dtype=np.int64)
    fluid = pid < n
    slot_of[pid[fluid]] = np.flatnonzero(fluid)
    src = np.unique(gsrc[is_open])
    slots = slot_of[src]
    return point_open, np.sort(slots[slots >= 0])


CONDITION_CODES = {"slip": PLANE_SLIP, "wall_function": PLANE_SLIP, "no_slip": PLANE_NO_SLIP,
                   "non_reflecting": PLANE_OPEN}


def ghost_planes(walls, dim: int) -> np.ndarray:
    """The ghost planes of ``walls`` (``walls.Wall``s), (nw, 7): axis, position, side, condition code
    (``CONDITION_CODES``), source point (padded to 3; NaN: none)."""
    rows = []
    for w in walls:
        if w.axis >= dim:
            raise ValueError("wall axis beyond the dimension")
        src = (np.nan,) * 3
        if w.source is not None:
            if len(w.source) != dim:
                raise ValueError("a non_reflecting side's source needs one coordinate per dimension")
            src = tuple(w.source) + (0.0,) * (3 - dim)
        rows.append([w.axis, w.position, w.side, CONDITION_CODES[w.condition], *src])
    return np.array(rows, dtype=np.float64).reshape(-1, 7)


def domain_bounds(domain, open_planes: np.ndarray, dim: int) -> tuple[np.ndarray, np.ndarray, bool]:
    """(lo, hi, used) of the box outside which particles are deactivated: ``domain`` ((lo, hi) or None)
    cut by the open sides (a particle crossing one leaves), unbounded where neither bounds it."""
    if domain is None and not len(open_planes):
        return np.zeros(dim), np.zeros(dim), False
    if domain is not None:
        lo, hi = (np.array(b, dtype=np.float64).reshape(dim) for b in domain)
    else:
        lo, hi = np.full(dim, -np.inf), np.full(dim, np.inf)
    for ax, pos, side in open_planes[:, :3]:
        if side > 0:
            lo[int(ax)] = max(lo[int(ax)], pos)
        else:
            hi[int(ax)] = min(hi[int(ax)], pos)
    return lo, hi, True
