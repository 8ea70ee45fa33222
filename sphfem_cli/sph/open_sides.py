"""Non-reflecting open sides of an SPH fluid: where their ghost images lie, their state and the work they do.

An open side is a plane x[axis] = position (``walls.Wall`` with condition "non_reflecting", side s = +1
when the fluid lies above). Its ghosts are images of the particles that start within the kernel support
of it (``walls.make_ghosts``, the machinery of the ghost walls, corner images included), placed so that
they move with their particle:

      x_g = x_i - 2 s d0_i e_axis,      d0_i = s (x_i(0) - position)

d0_i the particle's distance from the side at t = 0 (``initial_distances``; kept per particle, reordered
and checkpointed with it). At t = 0 that is the mirror image about the plane; afterwards the image keeps
its offset from its particle, so the layer of images is a rigid copy of the boundary layer of fluid,
moving with it: the side moves with the water, and no particle crosses it or is deleted. (An image
mirrored about the fixed plane would not: a particle streaming out closes on its own image, 2 d apart,
although the image carries the particle's velocity; the lattice across the side is then no continuation
of the fluid's, the symmetric pressure sum no longer cancels a uniform pressure there, and a strong
wave comes back: +17.5 % of a 30 MPa plane pulse at 400 particles per metre, growing with the
resolution, against -5.6 % with these images; docs/studies/underwater_explosion.md "3a.".) At a corner
of an open side and a wall the image is mirrored across the wall and offset across the side; at a
corner of two open sides it is offset across both. The images carry

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
  Which ghosts are open is told by the subset of planes each is the image across (``gsub``), not by
  where it lies.

Why it does not reflect (docs/theory/sph.md, "Non-reflecting open sides"): in linear acoustics on
a uniform lattice the SPH momentum and continuity sums apply the same difference operator to p and
u, so the incoming characteristic p' - Z u_n obeys a closed equation; ghosts on which it is 0
(the condition above) feed none into the fluid, whatever the outgoing one does there. The buffer of
ghosts is the characteristic buffer of Lastiwka, Basa & Quinlan (2009, IJNMF 61:709), with the
incoming Riemann invariant taken from the far field and the velocity extrapolated from the fluid;
here the buffer's particles are the images of a fixed set of fluid particles instead of particles
created and deleted.

What bounds the fluid: nothing at an open side; it drifts with the water's displacement there (in
decks/underwater_explosion_sph.yaml about 12-15 mm by 1.3 ms, dx 2.5 mm). A section's ``domain``
still deactivates particles outside it. For that reason an open side suits waves and transients, not
a steady current through it: its layer of images would be carried away with the current (an outlet or
inlet needs buffer layers whose particles are created and deleted, Lastiwka et al. 2009, Tafuni et al.
2018; not modelled). Where the water recedes from a side the image layer follows it (the side never
turns into a free surface).
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
def open_ghost_state(x, p, rho, c, p_far, impulse, gpos, gvel, gsrc, gsub, gdp, gdr, planes, k_wave, gravity,
                     pressure_cutoff, is_open):
    """Pressure and density offsets (``gdp``, ``gdr``) of the ghosts across an open side (module docstring).

    ``planes`` (nw, 7): axis, position, side (+1 fluid above), condition code, source point (3, NaN for
    none: plane waves); the ghost g of particle i = gsrc[g] is an open ghost when the subset of planes it
    is the image across (``gsub[g]``, bit w for plane w: ``walls.fill_ghosts``) holds a plane of code
    ``PLANE_OPEN`` (with a source when one of those planes has one). Where the image lies does not decide
    it: the side moves with the water, and an image may lie on the fluid's side of the side's plane at
    t = 0. ``k_wave``: k of the Bayliss-Turkel term. The ghost pressure is held at ``pressure_cutoff`` or
    above, as the fluid's. Writes ``is_open[g]``.
    """
    dim = x.shape[1]
    for g in range(gsrc.shape[0]):
        n0 = n1 = n2 = 0.0
        across = False
        spherical = False
        s0 = s1 = s2 = 0.0
        for w in range(planes.shape[0]):
            if planes[w, 3] != PLANE_OPEN or not (gsub[g] >> w) & 1:
                continue
            ax = int(planes[w, 0])
            across = True  # outward normal: -side along the axis
            if not math.isnan(planes[w, 4]):
                spherical = True
                s0, s1, s2 = planes[w, 4], planes[w, 5], planes[w, 6]
            if ax == 0:
                n0 -= planes[w, 2]
            elif ax == 1:
                n1 -= planes[w, 2]
            else:
                n2 -= planes[w, 2]
        is_open[g] = across
        if not across:
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


def initial_distances(x: np.ndarray, planes: np.ndarray) -> np.ndarray:
    """d0 (N, nw): each particle's distance side_w (x[axis_w] - position_w) from each ghost plane at t = 0,
    the offset of its images across the open sides (module docstring); (N, 0) when no plane is open (the
    walls' images do not need it). A particle that starts beyond an open side is refused (ValueError):
    its image would lie on the fluid's side."""
    open_rows = planes[:, 3] == PLANE_OPEN
    if not open_rows.any():
        return np.zeros((len(x), 0))
    d0 = np.empty((len(x), len(planes)))
    for w, (ax, pos, side) in enumerate(planes[:, :3]):
        d0[:, w] = side * (x[:, int(ax)] - pos)
    outside = (d0[:, open_rows] < 0.0).any(axis=1)
    if outside.any():
        i = int(np.flatnonzero(outside)[0])
        raise ValueError(f"{int(outside.sum())} particles start beyond a non_reflecting side (the first at "
                         f"{x[i].tolist()}): an open side's images need the fluid on its inner side")
    return d0
