"""Axisymmetric SPH rates (``dimension: axisymmetric``): the fluid in the meridian plane x = r >= 0, y = z.

Imported only by an axisymmetric ``SphSystem`` (``SphOptions.axisymmetric``), so a plane or 3D deck
compiles no kernel of this module. Equations and their derivation: docs/theory/sph.md ("Axisymmetric
SPH").

Formulation: the areal ("eta") form of axisymmetric SPH of Garcia-Senz, Relano, Cabezon & Bravo (2009),
MNRAS 392, 346, "Axisymmetric smoothed particle hydrodynamics with self-gravity" (also Brookshaw 2003,
ANZIAM J. 44 (E); the axis singularity: Omang, Borve & Trulsen 2006, J. Comput. Phys. 213, 391). A
particle is the ring swept by its point about the axis; its mass m is the ring's, for the full 2 pi,
m = 2 pi r rho A (A the particle's area in the meridian plane). With the areal density eta = 2 pi r rho,
the plane 2D kernel W (normalised in r-z) and Q = p / (rho eta) = p / (2 pi r rho^2):

  continuity   drho_i/dt = rho_i sum_j A_j v_ij . grad_i W_ij  -  rho_i v_r,i / r_i
                           - 2 delta sum_j h_ij c_ij psi_ij F_ij A_j             (delta-SPH, as in 2D)
               [mass form (SphOptions.continuity = "mass", the plane code's sum_j m_j v_ij . grad W with
                the plane mass rho_j A_j = m_j / (2 pi r_j) of each ring): the first sum is
                sum_j rho_j A_j v_ij . grad_i W_ij; rho is even across the axis, so the images' +rho_j A_j
                continue it consistently. It converges on Noh's sphere where the volume form over-compresses
                (docs/theory/sph.md); a deck's continuity: mass since 7 December 2026, with the axis time
                step below]
  momentum     dv_i/dt   = - sum_j m_j (s_j Q_i + Q_j + Pi_ij / (2 pi rbar_ij)) grad_i W_ij
                           + p_i / (rho_i r_i) kappa_i
  energy       de_i/dt   = 1/2 sum_j m_j (Q_i + Q_j + Pi_ij / (2 pi rbar_ij)) v_ij . grad_i W_ij
                           + sum_j m_j (s_j - 1) Q_i v_i . grad_i W_ij  -  p_i / (rho_i r_i) kappa_i . v_i

The pair term m_j (Q_i + Q_j) grad W is the areal form's 2 pi (r_i p_i / eta_i^2 + r_j p_j / eta_j^2)
m_j grad W; p/(rho r) is the hoop term of the momentum equation, -p v_r/(rho r) that of the energy
equation, -rho v_r/r that of the continuity equation (the 2D divergence misses v_r/r). Pi_ij is the
Monaghan viscosity of the plane code (``rates._pair_terms``, with rho_ij), divided by 2 pi rbar_ij with
rbar_ij = (r_i + r_j)/2, so that m_j Pi_ij / (2 pi rbar_ij) is about the plane mass times Pi_ij: the
plane code's dissipation.

The axis r = 0 is a slip ghost wall (reflected ghosts r -> -r, v_r -> -v_r; ``SphSystem`` adds it).
Every ghost j carries its source particle's ring mass m_j, density, pressure and radius r_j (so Q_j and
A_j are the source's) at its mirrored position x_j. s_j = x_j / r_j is the ghost's coordinate over its
source's radius: 1 for a particle and for the ghosts of walls across z (floors, lids), -1 for an image
across the axis, (2R - r_j)/r_j for an image across a wall at r = R. With s_j the i-part of the pair sum
sees the images' signed radii: eta = 2 pi r rho is extended linearly (oddly across the axis), the
consistent continuation of a field that vanishes on the axis, so that sum_j m_j s_j grad W estimates
grad eta at every distance from the axis; with the plain mirror (s_j = 1) it misses 2 pi rho near the
axis and the first rows are pushed off it and the column near the free surface goes unstable (seen
in the hydrostatic test). The vector kappa_i = sum_j A_j (x_j - r_i) grad_i W_ij is the kernel's estimate
of grad r = e_r: radially -sum_j A_j F_ij (r_i - x_j)^2 (1 in the bulk for an exact quadrature, 1/2 at a
free surface), axially -sum_j A_j F_ij (r_i - x_j)(z_i - z_j) (0 on a regular lattice). For a uniform
pressure the pair sum plus the hoop term is then exactly the plane code's -(2 p/rho) sum_j A_j grad_i W_ij
in both components, for any arrangement (with the exact p/(rho r) e_r the kernel's truncation at the
free surface pushes the top rows next to the axis outwards) -- this renormalisation is this
implementation's, in the spirit of the axis corrections of Garcia-Senz et al. The axial component is
needed where the support is cut in z, at a floor without ghosts (a contact floor): there the axial force
of the images' odd term is first order in a particle's radial offset and grows as 1/r towards the axis,
and with the radial kappa alone a water column on a contact floor blew up at the corner of the axis and
the floor (issue 15; docs/theory/sph.md gives the figures).

Time step: besides the plane cfl h/(c + |v|), dt <= r/(c + |v|) (``axis_time_step``): the hoop terms vary
over the distance r to the axis, which is below h for a ring squeezed onto the axis (Noh's implosion).

Conservation: masses never change (mass exact). The part of the pair term with s_j - 1 (images only)
does its work on particle i alone (the axis and the walls are at rest), and the hoop work goes into
e_i, so the semi-discrete kinetic + internal energy is conserved exactly. Particle-particle pairs and
the ghosts of walls across z are symmetric in i and j, so they conserve the axial momentum sum m v_z
to round-off; the images across the axis do not quite (their axial force on i, m_j (Q_j - Q_i), and
that of the image of i on j are equal, not opposite): the axial force they leave is of the order of
the kernel's truncation error (5e-4 of sum m |a_z| on a jittered lattice with an axial pressure
gradient; 2.4e-10 in Noh's implosion at dx = 0.01) -- the price of the consistent (odd) extension;
the symmetric (even) mirror conserves it exactly but is unstable. The axial component of the hoop term,
p_i kappa_i . e_z / (rho_i r_i), is a force on i alone as well: 0 on a regular lattice, of the kernel's
truncation error where the support is cut in z. With it the closed-cylinder test (free ends at z = 0.2
and 0.8) drifts 1.0e-9 of sum m |v_z| over 0.25 s (3e-14 with the radial kappa alone), the price of
the consistency at a cut support that a contact floor needs (issue 15).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from .expansion import renormalised_divergence
from .kernel_functions import CUBIC_SPLINE, WENDLAND_C2, kernel_f, kernel_sigma
from .search import cell_range
from .switch import pair_coefficients
from .slots import (D_C, D_MK, D_PR, D_RHO, D_VOL, D_VX, D_VY, D_VZ, GF_CELL, GF_OX, GF_OY, GI_NX,
                    GI_NY, KIND_FLUID, KIND_GHOST, KIND_WALL, SF_ALPHA, SF_BETA, SF_BETA_PER_ALPHA, SF_DELTA, SF_EPS, SF_GX, SF_GY, SF_XSPH,
                    SI_DELTA_HYDROSTATIC, SI_KERNEL, SI_CONTINUITY, CONTINUITY_MASS, N_LANES)

TWO_PI = 2.0 * math.pi
INV_TWO_PI = 1.0 / TWO_PI

# the fast-math flags of rates._FM (no contract, no reassoc: see there why)
_FM = {"nsz", "arcp"}


@njit(cache=True)
def ring_smoothing_lengths(x, rho, m, active, eta, h):
    """h_i = eta sqrt(A_i), A_i = m_i / (2 pi r_i rho_i) the particle's area in the meridian plane
    (the plane h = eta (m/rho)^(1/2) with the ring mass m = 2 pi r rho A). Returns the largest h."""
    hmax = 0.0
    for i in range(x.shape[0]):
        if not active[i]:
            continue
        hi = eta * math.sqrt(m[i] / (TWO_PI * x[i, 0] * rho[i]))
        h[i] = hi
        hmax = max(hmax, hi)
    return hmax


@njit(cache=True)
def axis_time_step(x, c, v, active):
    """min over active particles of r_i / (c_i + |v_i|): the Courant condition of the hoop terms.

    The hoop terms (-rho v_r / r of the continuity equation, p / (rho r) of the momentum equation) vary
    over the particle's distance r to the axis, not over h: a ring squeezed to r << h (Noh's implosion
    gathers hot rings on the axis at r = 0.1-0.15 dx with h/r = 5.5) has a radial mode of length r that
    the plane condition cfl h / (c + |v|) does not resolve. With dt <= r / (c + |v|) one step moves a
    particle less than its distance to the axis (|v_r| dt < r: it cannot cross the axis in one step) and
    the hoop term's density change rho |v_r| dt / r stays below rho (rho stays positive). Measured
    (Noh's sphere, mass form, dx 0.04, cfl 0.25 alone): the innermost rings' radial velocity alternates
    in sign from step to step and grows (c dt / r = 1.25 there) until a density goes negative and the
    step collapses; cfl 0.22 (c dt / r about 1.1): two crossings of the axis, energy error 3.5e-3;
    cfl 0.2 (about 1.0): none. A particle farther than cfl h from the axis (every row of a lattice,
    r >= dx/2 > cfl h for h < 2 dx) is never limited by it. docs/studies/axisymmetric_acceptance.md (A4b).
    """
    dt = np.inf
    for i in range(x.shape[0]):
        if not active[i]:
            continue
        speed = c[i] + math.sqrt(v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1])
        if speed > 0.0:
            dt = min(dt, x[i, 0] / speed)
    return dt


def axisymmetric_rates(sx, sd, perm, cell_start, sreach, settings_f, settings_i, grid_f, grid_i, acc, drho, de, xsph,
                       conv, salpha, switch):
    """Continuity, momentum, energy, delta-SPH and XSPH rates of every fluid point (module docstring).

    ``sd[D_VZ, k]`` of a ghost slot holds its source particle's radius r_j (``SphSystem`` writes it
    into the ghost velocities' third column, unused in 2D); of a particle it is 0 and r_j = x_j.
    The loop is the plane code's row scan (``rates._fluid_rates``): per particle each row of cells within
    reach is one contiguous slot range whose candidates ``_row_sums`` sums without branches and without a
    neighbour list (a candidate that is no neighbour adds exactly 0); the row sums are added in row order.
    (Until December 2026 a branch-free neighbour list, ``search.neighbour_list``: the same neighbours and
    terms, summed in another grouping, so results moved at round-off: `sphfem regress` of the six r-z SPH decks
    within 2.2e-6 of the stored references; the rates fell from 310 to 270 ns per particle-step and
    benchmarks/sph_axisymmetric_cost.py's ratio to the plane step from 1.45 to 1.26, docs/studies/
    axisymmetric_acceptance.md.) Plain Python
    that picks the kernel's, the term set's and the switch's specialisation (as ``rates.fluid_rates``).
    ``conv[i]`` = -(div v)_i = sum_j A_j v_ij . grad_i W_ij - v_r,i / r_i (mass form: the first sum with
    rho_j A_j, over rho_i), the continuity equation's estimate without delta-SPH, the shock switch's source;
    with ``switch`` Pi_ij takes alpha_ij = (alpha_i + alpha_j)/2 from the per-slot ``salpha`` and beta_ij =
    (beta/alpha) alpha_ij (``sph/switch.py``), without it the section's alpha and beta.
    """
    kernel = int(settings_i[SI_KERNEL])
    lean = settings_f[SF_XSPH] == 0.0
    kshape = _SHAPES[2 if kernel == WENDLAND_C2 else 1]
    tshape = _SHAPES[2 if lean else 1]
    _axisymmetric_rates(sx, sd, perm, cell_start, sreach, settings_f, settings_i, grid_f, grid_i, acc, drho, de, xsph,
                        conv, salpha, kshape, tshape, _SHAPES[2 if switch else 1])


_SHAPES = {1: np.empty(0), 2: np.empty((0, 0))}
_BLOCK = 32
_FMV = {"nsz", "arcp", "reassoc"}  # for the neighbour sums only (as rates._FMV)


@njit(cache=True, fastmath=_FM, forceinline=True, error_model="numpy")
def _pair_terms(j, k, e, sx, sd, kshape, tshape, sig, xi, yi, hi, ui, vi, rhoi, ci, qi, mati, alpha, beta, eps,
                gx, gy, dhydro, mform, ashape, salpha, ai, bpa):
    """The terms of candidate slot ``j`` (unsigned) in the sums of ``_row_sums`` (module docstring); exactly 0 for
    a wall point and for a candidate that is no neighbour of slot ``k``: j == k, j >= e (past the row's
    candidates) or |x_k - x_j|^2 >= (h_k + h_j)^2 (the test of ``search.neighbour_list``); its arithmetic, inf or
    NaN at j == k, is selected away, not multiplied (as ``rates._pair_terms``). Always inlined, without "reassoc" (see ``rates._pair_terms``). ``ashape.ndim``
    2: the shock switch's alpha_ij = (``ai`` + ``salpha[j]``)/2, beta_ij = ``bpa`` alpha_ij; 1: ``alpha``,
    ``beta`` (``salpha`` not read)."""
    wend = kshape.ndim == 2
    full = tshape.ndim == 1
    xj = sx[0, j]
    dx = xi - xj
    dy = yi - sx[1, j]
    hs = hi + sx[3, j]
    hij = 0.5 * hs
    r2 = dx * dx + dy * dy
    ok = (r2 < hs * hs) & (j != k) & (j < e)
    r = math.sqrt(r2)
    a = 1.0 / (hij * r)
    inv = r * a  # 1/h_ij
    q = r2 * a  # r/h_ij
    if wend:
        tw = max(1.0 - 0.5 * q, 0.0)
        tw2 = tw * tw
        th = tw2 * tw2 * (2.0 * q + 1.0)
        dth = -5.0 * tw2 * tw
    else:  # both branches computed, then selected
        tc = max(2.0 - q, 0.0)
        inner = q < 1.0
        th = 1.0 - q * q * (1.5 - 0.75 * q) if inner else 0.25 * tc * tc * tc
        dth = -3.0 + 2.25 * q if inner else -0.75 * tc * tc * hij * hij * a  # -0.75 (2-q)^2 / q
    norm = sig * inv * inv
    f = norm * inv * inv * dth  # F_ij = (1/r) dW/dr
    wgx = f * dx
    wgy = f * dy
    mk = sd[D_MK, j]  # mat * 4 + kind, decoded in floating point (exact for these integers)
    matj = np.floor(0.25 * mk)
    kind = mk - 4.0 * matj
    notwall = 1.0 if kind != KIND_WALL else 0.0
    rj = xj if kind == KIND_FLUID else (sd[D_VZ, j] if kind == KIND_GHOST else 1.0)  # the source's radius
    irj = INV_TWO_PI / rj
    rhoj = sd[D_RHO, j]
    vol = sd[D_VOL, j] * notwall  # ring volume m_j / rho_j (0 for walls and the sentinel)
    mj = vol * rhoj
    area = vol * irj  # A_j
    qj = sd[D_PR, j] * irj
    du = ui - sd[D_VX, j]
    dv = vi - sd[D_VY, j]
    vdotg = du * wgx + dv * wgy
    vdotr = min(du * dx + dv * dy, 0.0)
    cij = 0.5 * (ci + sd[D_C, j])
    rij = 0.5 * (rhoi + rhoj)
    dd = r2 + eps * hij * hij
    hv = hij * vdotr
    aij, bij = pair_coefficients(ashape, ai, salpha, j, bpa, alpha, beta)
    # Monaghan: Pi = (-alpha c mu + beta mu^2)/rho_ij, mu = h v.r/(r^2 + eps h^2) for v.r < 0
    pi_ij = hv * (bij * hv - aij * cij * dd) / (dd * dd * rij)
    coef = mj * (qi + qj + pi_ij * (2.0 * INV_TWO_PI) / (xi + rj))
    odd = mj * (xj * (1.0 / rj) - 1.0) * qi  # the images' signed radii (0 for particles and floor ghosts)
    ct = coef + odd
    work = 0.5 * coef * vdotg + odd * (ui * wgx + vi * wgy)
    psi = rhoj - rhoi
    if dhydro:
        psi += rij * (gx * dx + gy * dy) / (cij * cij) if cij > 0.0 else 0.0  # c_ij = 0: no correction (0/0)
    same = 1.0 if matj == mati else 0.0
    diff = same * hij * cij * psi * f * area
    wr = norm * th * area * rhoj / rij if full else 0.0
    cw = area * rhoj if mform else area  # continuity weight: rho_j A_j (mass form) or A_j (volume form)
    z = 0.0
    return (ct * wgx if ok else z, ct * wgy if ok else z, work if ok else z, cw * vdotg if ok else z,
            -area * f * dx * dx if ok else z, -area * f * dx * dy if ok else z, diff if ok else z,
            wr * du if ok else z, wr * dv if ok else z)


@njit(cache=True, fastmath=_FMV, forceinline=True, error_model="numpy")
def _row_sums(s, e, k, sx, sd, kshape, tshape, sig, xi, yi, hi, ui, vi, rhoi, ci, qi, mati, alpha, beta, eps,
              gx, gy, dhydro, mform, ashape, salpha, ai, bpa):
    """Branch-free sums of ``_pair_terms`` over the candidate slots ``s .. e - 1`` (one row of cells) of slot
    ``k``: (ax, ay, work, cont, kappa_r, kappa_z, diff, sxu, sxv). As ``rates._row_sums``: the slots are read
    in whole chunks of ``N_LANES`` (into the sentinel columns past the points), contiguously from the rows of
    ``sx`` and ``sd``, so that LLVM vectorises the loop with plain loads and no remainder; a candidate that is
    no neighbour adds exactly 0. Always inlined (at the LLVM level) into the parfor loop of
    ``_axisymmetric_rates``."""
    full = tshape.ndim == 1
    fmati = float(mati)
    ax = ay = work = cont = kap = kapz = diff = sxu = sxv = 0.0
    lanes = np.uint64(N_LANES)
    end = s + (e - s + lanes - np.uint64(1)) // lanes * lanes
    for j in range(s, end):
        tx, ty, tw, tc, tk, tkz, td, tu, tv = _pair_terms(j, k, e, sx, sd, kshape, tshape, sig, xi, yi, hi, ui, vi,
                                                          rhoi, ci, qi, fmati, alpha, beta, eps, gx, gy, dhydro, mform,
                                                          ashape, salpha, ai, bpa)
        ax -= tx
        ay -= ty
        work += tw
        cont += tc
        kap += tk
        kapz += tkz
        diff += td
        if full:
            sxu -= tu
            sxv -= tv
    return ax, ay, work, cont, kap, kapz, diff, sxu, sxv


@njit(cache=True, parallel=True, error_model="numpy")
def _axisymmetric_rates(sx, sd, perm, cell_start, sreach, settings_f, settings_i, grid_f, grid_i, acc, drho, de, xsph,
                        conv, salpha, kshape, tshape, ashape):
    """``axisymmetric_rates`` for one kernel (``kshape.ndim``: 1 cubic spline, 2 Wendland C2), term set
    (``tshape.ndim``: 1 with XSPH, 2 without) and switch (``ashape.ndim``: 1 off, 2 on)."""
    kernel = WENDLAND_C2 if kshape.ndim == 2 else CUBIC_SPLINE
    nx, ny = grid_i[GI_NX], grid_i[GI_NY]
    dhydro = settings_i[SI_DELTA_HYDROSTATIC] != 0
    mform = settings_i[SI_CONTINUITY] == CONTINUITY_MASS
    alpha, beta, eps = settings_f[SF_ALPHA], settings_f[SF_BETA], settings_f[SF_EPS]
    bpa = settings_f[SF_BETA_PER_ALPHA]
    delta, exsph = settings_f[SF_DELTA], settings_f[SF_XSPH]
    gx, gy = settings_f[SF_GX], settings_f[SF_GY]
    cell = grid_f[GF_CELL]
    ox, oy = grid_f[GF_OX], grid_f[GF_OY]
    inv_cell = 1.0 / cell
    sig = kernel_sigma(kernel, 2)
    npts = cell_start[-1]
    for b in prange((npts + _BLOCK - 1) // _BLOCK):
        for k in range(b * _BLOCK, min(npts, (b + 1) * _BLOCK)):
            mki = int(sd[D_MK, k])
            if (mki & 3) != KIND_FLUID:
                continue
            xi, yi, hi = sx[0, k], sx[1, k], sx[3, k]
            reach = sreach[k]  # every 2 h_kj is below sreach[k] (search.search_reach)
            x0, x1 = cell_range(xi, reach, ox, inv_cell, nx)
            y0, y1 = cell_range(yi, reach, oy, inv_cell, ny)
            ku = np.uint64(k)
            ui, vi = sd[D_VX, k], sd[D_VY, k]
            rhoi, pri, ci = sd[D_RHO, k], sd[D_PR, k], sd[D_C, k]  # pri = p_i / rho_i^2
            qi = pri * INV_TWO_PI / xi  # Q_i = p_i / (2 pi r_i rho_i^2)
            ai = salpha[k] if ashape.ndim == 2 else alpha
            ax = ay = work = cont = kap = kapz = diff = sxu = sxv = 0.0
            for cy in range(y0, y1 + 1):  # the rows of cells within reach, each one contiguous slot range
                base = cy * nx
                r0, r1, r2, r3, r4, r5, r6, r7, r8 = _row_sums(
                    np.uint64(cell_start[base + x0]), np.uint64(cell_start[base + x1 + 1]), ku, sx, sd, kshape,
                    tshape, sig, xi, yi, hi, ui, vi, rhoi, ci, qi, mki >> 2, alpha, beta, eps, gx, gy, dhydro, mform,
                    ashape, salpha, ai, bpa)
                ax += r0
                ay += r1
                work += r2
                cont += r3
                kap += r4
                kapz += r5
                diff += r6
                sxu += r7
                sxv += r8
            i = perm[k]
            hoop = pri * rhoi / xi  # p_i / (rho_i r_i), times kappa_i = sum_j A_j (x_j - r_i) grad_i W_ij
            acc[i, 0] = ax + hoop * kap
            acc[i, 1] = ay + hoop * kapz
            drho[i] = (cont if mform else rhoi * cont) - rhoi * ui / xi - 2.0 * delta * diff
            conv[i] = (cont / rhoi if mform else cont) - ui / xi
            de[i] = work - hoop * (kap * ui + kapz * vi)
            xsph[i, 0] = exsph * sxu
            xsph[i, 1] = exsph * sxv


@njit(cache=True)
def renormalise_ring_continuity(sx, sd, perm, cell_start, sreach, settings_i, grid_f, grid_i, flag, drho):
    """The renormalised continuity of explosive products (``expansion.py``) in the areal r-z form.

    The r-z divergence is the meridian-plane one plus the hoop term, div v = dv_r/dr + dv_z/dz + v_r/r.
    ``axisymmetric_rates`` put in drho_i the plain estimate rho_i sum_j A_j v_ij . grad_i W_ij of
    -rho_i (dv_r/dr + dv_z/dz) (mass form, ``SI_CONTINUITY`` = ``CONTINUITY_MASS``: sum_j rho_j A_j v_ij .
    grad_i W_ij) and the exact hoop term -rho_i v_r,i / r_i. For every fluid slot whose particle ``perm[k]``
    has ``flag`` set, the first (of either form: the one the rates used is subtracted) is replaced by
    -rho_i tr(G_i M_i^-1) with

        G_i = sum_j A_j (v_j - v_i) (x) grad_i W_ij,   M_i = sum_j A_j (x_j - x_i) (x) grad_i W_ij

    over the particles and ghosts within 2 h_ij (A_j = V_j / (2 pi r_j), r_j the source's radius, as in
    ``axisymmetric_rates``; the plane 2D kernel), so that

        drho_i/dt = -rho_i (tr(G_i M_i^-1) + v_r,i / r_i)  (+ delta-SPH, unchanged),

    the same for both forms (the renormalised divergence has no weight to choose).

    The hoop term is the particle's own v_r/r, not renormalised (it is exact). The images across the
    axis carry (-v_r, v_z) at (-r, z): the odd continuation of v_r, even of v_z, which is the Cartesian
    field's own, so a linear field (v_r = a r + b z, v_z = c r + d z continued this way is linear
    only for b = c = 0, the axisymmetric linear fields) is differentiated exactly up to the axis: div
    = 2 a + d. M_i^-1: ``expansion.renormalised_divergence`` (its fallbacks where M is ill conditioned).
    Randles & Libersky 1996; Bonet & Lok 1999; the areal form: Garcia-Senz et al. 2009. Returns the
    number of particles corrected. Derivation: docs/theory/sph.md ("Explosive products in r-z").
    """
    kernel = settings_i[SI_KERNEL]
    mform = settings_i[SI_CONTINUITY] == CONTINUITY_MASS
    nx, ny = grid_i[GI_NX], grid_i[GI_NY]
    cell = grid_f[GF_CELL]
    ox, oy = grid_f[GF_OX], grid_f[GF_OY]
    inv_cell = 1.0 / cell
    n = flag.shape[0]
    g = np.zeros((3, 3))
    mm = np.zeros((3, 3))
    done = 0
    for k in range(cell_start[-1]):
        if (int(sd[D_MK, k]) & 3) != KIND_FLUID:
            continue
        i = perm[k]
        if i >= n or not flag[i]:
            continue
        xi, yi, hi = sx[0, k], sx[1, k], sx[3, k]
        ui, vi = sd[D_VX, k], sd[D_VY, k]
        reach = sreach[k]  # bounds every 2 h_kj (search.search_reach)
        x0, x1 = cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = cell_range(yi, reach, oy, inv_cell, ny)
        g[:, :] = 0.0
        mm[:, :] = 0.0
        plain = 0.0
        for cy in range(y0, y1 + 1):
            base = cy * nx
            for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                if j == k:
                    continue
                kind = int(sd[D_MK, j]) & 3
                if kind == KIND_WALL:
                    continue
                dx = xi - sx[0, j]
                dy = yi - sx[1, j]
                dist2 = dx * dx + dy * dy
                hs = hi + sx[3, j]
                if dist2 >= hs * hs:
                    continue
                f = kernel_f(kernel, 2, math.sqrt(dist2), 0.5 * hs)  # grad_i W_ij = f (x_i - x_j)
                rj = sx[0, j] if kind == KIND_FLUID else sd[D_VZ, j]  # the source's radius
                area = sd[D_VOL, j] * INV_TWO_PI / rj
                du = ui - sd[D_VX, j]
                dv = vi - sd[D_VY, j]
                plain += (area * sd[D_RHO, j] if mform else area) * f * (du * dx + dv * dy)  # the rates' first sum
                # (v_j - v_i)_p (grad W)_q and (x_j - x_i)_p (grad W)_q
                g[0, 0] -= area * du * f * dx
                g[0, 1] -= area * du * f * dy
                g[1, 0] -= area * dv * f * dx
                g[1, 1] -= area * dv * f * dy
                mm[0, 0] -= area * dx * f * dx
                mm[0, 1] -= area * dx * f * dy
                mm[1, 0] -= area * dy * f * dx
                mm[1, 1] -= area * dy * f * dy
        div = renormalised_divergence(g, mm, 2)
        rhoi = sd[D_RHO, k]
        drho[i] -= (plain + rhoi * div) if mform else rhoi * (plain + div)  # the volume form's arithmetic as before
        done += 1
    return done
