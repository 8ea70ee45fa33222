"""SPH rates: viscous stress, the pair sums of continuity, momentum, energy, delta-SPH and XSPH,
and SPH interpolation at arbitrary points.

Every pair loop is a gather over the slots of the cell-sorted point set (``sph/search.py``):
slot ``k`` writes only its own entries, so results do not depend on the number of threads.
Equations and references: docs/theory/sph.md ("Rates").
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ..materials.slots import P_VISCOSITY
from .kernel_functions import CUBIC_SPLINE, WENDLAND_C2, inv_pow, kernel_shape, kernel_f, kernel_sigma, kernel_w
from .search import cell_range
from .switch import pair_coefficients
from .slots import (D_C, D_MK, D_PR, D_RHO, D_VOL, D_VX, D_VY, D_VZ, GF_CELL, GF_HMAX, GF_OX, GF_OY, GF_OZ,
                    GI_NX, GI_NY, GI_NZ, KIND_FLUID, KIND_GHOST, KIND_WALL, N_LANES, SF_ALPHA, SF_BETA,
                    SF_BETA_PER_ALPHA, SF_DELTA, SF_DILATATIONAL_VISCOSITY, SF_EPS, SF_GX, SF_GY, SF_GZ, SF_XSPH, SI_DELTA_HYDROSTATIC,
                    SI_CONTINUITY, SI_DIM, SI_KERNEL, SI_NMAT, SI_NWALL, SI_VISCOUS, CONTINUITY_MASS)

# Fast-math flags without nnan/ninf (NaN checks keep working), without "contract" and, but for the
# additions of the neighbour sums (_FMV, _row_sums; before it _pair_sums), without "reassoc". numba
# links a copy of each callee's optimised LLVM IR into its caller's module (linkonce_odr) and
# optimises that module again, and the caller's module is what it writes to its on-disk cache. The
# process that compiles runs the callee's own code, optimised once (the JIT linker resolves the weak
# copies to the definition it loaded first), a process that loads runs the copies in the cached
# caller: for _pair_sums the one in _fluid_rates, optimised three times (its library, the parfor
# gufunc's, _fluid_rates'). With "contract" or "reassoc" on every instruction each optimisation may
# fuse or regroup differently (reassoc on all of _pair_sums: the second pass regrouped the product of
# the delta-SPH term), so a run that compiled its kernels and one that loaded them differed at
# round-off (4 % in an elastic gate's tip velocity after 0.02 s, where the contact amplifies it).
# Without them re-optimising changes no result (the copies differ only in commuted operands), and
# the two are bit-identical (tests/robustness/test_determinism.py).
# numba compiles a callee that states no fastmath with the flags of the caller that first needs it
# (numba.core.cpu.CPUTargetOptions: fastmath is inherited) and caches it under its signature alone,
# so every function the fast-math kernels here and in walls.py call states fastmath=False
# (kernel_functions, search.cell_range, eos.density_from_pressure, eos.sound_speed); otherwise its
# code depended on which kernel compiled it first: density_from_pressure compiled first from
# wall_pressure gave hydrostatic densities 1 ulp apart from one compiled on its own.
_FM = {"nsz", "arcp"}


@njit(cache=True, parallel=True, fastmath=_FM, error_model="numpy")
def viscous_stress(sx, sd, svf, cell_start, sreach, settings_f, settings_i, grid_f, grid_i, params, stau):
    """Newtonian viscous stress at every point from the SPH velocity gradient.

    L_ab = sum_j V_j (v_j,a - v_i,a) dW_ij/dx_i,b (paper eq. 3.6 form), D = (L + L^T)/2,
    tau = mu (2D - (2/3) tr(D) I) + mu' tr(D) I (paper eq. 3.16), mu from the material row and
    the dilatational viscosity mu' from ``settings_f[SF_DILATATIONAL_VISCOSITY]``. Writes stau[k] for every slot.
    Velocities are ``sd``'s times the per-slot factors ``svf`` (the no-slip velocity of the
    ghosts of no-slip walls, ``fill_ghosts``); a (1, 3) ``svf`` means no factors.
    """
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    hmax, cell = grid_f[GF_HMAX], grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    mu_dil = settings_f[SF_DILATATIONAL_VISCOSITY]
    inv_cell = 1.0 / cell
    sig = kernel_sigma(kernel, dim)
    flips = svf.shape[0] > 1
    for k in prange(cell_start[-1]):
        mat = int(sd[D_MK, k]) >> 2
        mu = params[mat, P_VISCOSITY]
        if mu == 0.0 and mu_dil == 0.0:
            for a in range(6):
                stau[k, a] = 0.0
            continue
        xi, yi, zi, hi = sx[0, k], sx[1, k], sx[2, k], sx[3, k]
        fk = np.int64(k) if flips else np.int64(0)
        ui, vi, wi = sd[D_VX, k] * svf[fk, 0], sd[D_VY, k] * svf[fk, 1], sd[D_VZ, k] * svf[fk, 2]
        reach = sreach[k]  # search.search_reach: bounds every 2 h_kj
        x0, x1 = cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = cell_range(yi, reach, oy, inv_cell, ny)
        z0, z1 = cell_range(zi, reach, oz, inv_cell, nz)
        l00 = l01 = l02 = l10 = l11 = l12 = l20 = l21 = l22 = 0.0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    dx = xi - sx[0, j]
                    dy = yi - sx[1, j]
                    dz = zi - sx[2, j]
                    hij = 0.5 * (hi + sx[3, j])
                    r2 = dx * dx + dy * dy + dz * dz
                    if r2 >= 4.0 * hij * hij or r2 == 0.0:
                        continue
                    inv = 1.0 / hij
                    f = sig * inv_pow(inv, dim) * inv * inv * kernel_shape(kernel, math.sqrt(r2) * inv)[1]
                    vol = sd[D_VOL, j] * f
                    gx, gy, gz = vol * dx, vol * dy, vol * dz
                    fj = np.int64(j) if flips else np.int64(0)
                    du = sd[D_VX, j] * svf[fj, 0] - ui
                    dv = sd[D_VY, j] * svf[fj, 1] - vi
                    dw = sd[D_VZ, j] * svf[fj, 2] - wi
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

# reassoc lets LLVM vectorise the neighbour sums (their order of additions is then LLVM's); it is
# given to the sums only, not to the terms (see _FM)
_FMV = {"nsz", "arcp", "reassoc"}


@njit(cache=True, fastmath=_FM, forceinline=True, error_model="numpy")
def _pair_terms(j, k, e, sx, sd, kshape, dshape, tshape, sig, xi, yi, zi, hi, ui, vi, wi, rhoi, pri, ci, fmati,
                alpha, beta, eps, gx, gy, gz, dhydro, mform, ashape, salpha, ai, bpa):
    """The terms of candidate slot ``j`` (unsigned) in the sums of ``_row_sums`` (same arguments, same order).

    Slot ``j`` is a neighbour of slot ``k`` when j != k, j < e (the end of the row's candidates) and
    |x_k - x_j|^2 < (h_k + h_j)^2 = (2 h_kj)^2 (the test of ``search.neighbour_list``); for any other
    candidate every term is selected to exactly 0 (its arithmetic, which may be inf or NaN at
    j == k, is discarded, not multiplied). With the shock switch (``ashape.ndim == 2``, a compile-time
    constant) the viscosity's alpha, beta are the pair's alpha_ij = (alpha_i + alpha_j)/2 (``ai`` and the
    per-slot ``salpha``) and beta_ij = ``bpa`` alpha_ij (``sph/switch.py``); without it (``ashape.ndim == 1``)
    the section's ``alpha``, ``beta`` and ``salpha`` is not read. Without "reassoc" and always inlined into ``_row_sums``
    (LLVM keeps each instruction's flags when it inlines), so re-optimising the inlined code cannot
    reorder these products and sums.
    """
    kernel = WENDLAND_C2 if kshape.ndim == 2 else CUBIC_SPLINE
    dim = dshape.ndim
    full = tshape.ndim == 1
    wend = kernel == WENDLAND_C2
    dx = xi - sx[0, j]
    dy = yi - sx[1, j]
    dz = zi - sx[2, j] if dim > 2 else 0.0
    hs = hi + sx[3, j]
    hij = 0.5 * hs
    r2 = dx * dx + dy * dy
    if dim > 2:
        r2 += dz * dz
    ok = (r2 < hs * hs) & (j != k) & (j < e)
    r = math.sqrt(r2)
    a = 1.0 / (hij * r)
    inv = r * a  # 1/h_ij
    q = r2 * a  # r/h_ij
    # kernel shape theta(q) and (1/q) dtheta/dq; both branches of the spline computed, then selected
    if wend:
        tw = max(1.0 - 0.5 * q, 0.0)
        tw2 = tw * tw
        th = tw2 * tw2 * (2.0 * q + 1.0)
        dth = -5.0 * tw2 * tw
    else:
        tc = max(2.0 - q, 0.0)
        inner = q < 1.0
        th = 1.0 - q * q * (1.5 - 0.75 * q) if inner else 0.25 * tc * tc * tc
        dth = -3.0 + 2.25 * q if inner else -0.75 * tc * tc * hij * hij * a  # -0.75 (2-q)^2 / q
    invd = inv * inv * (inv if dim >= 3 else 1.0)
    norm = sig * invd
    f = norm * inv * inv * dth
    wgx = f * dx
    wgy = f * dy
    wgz = f * dz
    du = ui - sd[D_VX, j]
    dv = vi - sd[D_VY, j]
    dw = wi - sd[D_VZ, j] if dim > 2 else 0.0
    rhoj = sd[D_RHO, j]
    vol = sd[D_VOL, j]
    mj = vol * rhoj
    vdotg = du * wgx + dv * wgy
    vdr = du * dx + dv * dy
    if dim > 2:
        vdotg += dw * wgz
        vdr += dw * dz
    vdotr = min(vdr, 0.0)
    cj = sd[D_C, j]
    cij = 0.5 * (ci + cj)
    rij = 0.5 * (rhoi + rhoj)
    dd = r2 + eps * hij * hij
    rcp = 1.0 / (dd * dd * rij)
    hv = hij * vdotr
    aij, bij = pair_coefficients(ashape, ai, salpha, j, bpa, alpha, beta)
    # Monaghan: Pi = (-alpha c mu + beta mu^2)/rho_ij, mu = h v.r/(r^2 + eps h^2) for v.r < 0
    pi_ij = hv * (bij * hv - aij * cij * dd) * rcp
    coef = mj * (pri + sd[D_PR, j] + pi_ij)
    work = coef * vdotg
    mk = sd[D_MK, j]  # mat * 4 + kind, decoded in floating point (exact for these integers)
    matj = np.floor(0.25 * mk)
    notwall = 1.0 if mk - 4.0 * matj != KIND_WALL else 0.0
    wall_work = (1.0 - notwall) * work if full else 0.0
    # tshape.ndim == 3: no dummy wall points and one material, so every candidate that is a neighbour is a
    # fluid or ghost point of the material of k (the sentinel past the row's end is selected away by ok):
    # same = 1 exactly, and 1 * hij below is hij (bit-identical), without decoding mk for every pair
    same = 1.0 if tshape.ndim == 3 else (notwall if matj == fmati else 0.0)
    psi = rhoj - rhoi
    if dhydro:
        gr = gx * dx + gy * dy
        if dim > 2:
            gr += gz * dz
        psi += rij * gr / (cij * cij) if cij > 0.0 else 0.0  # c_ij = 0: no diffusion, no correction (0/0)
    diff = same * hij * cij * psi * f * vol
    wr = notwall * norm * th * mj * (dd * dd * rcp) if full else 0.0
    cw = mj if mform else vol  # the continuity weight: m_j (mass form) or V_j (volume form)
    z = 0.0
    return (coef * wgx if ok else z, coef * wgy if ok else z, coef * wgz if ok else z, cw * vdotg if ok else z,
            work if ok else z, wall_work if ok else z, diff if ok else z, wr * du if ok else z,
            wr * dv if ok else z, wr * dw if ok else z)


@njit(cache=True, fastmath=_FMV, forceinline=True, error_model="numpy")
def _row_sums(s, e, k, sx, sd, kshape, dshape, tshape, sig, xi, yi, zi, hi, ui, vi, wi, rhoi, pri, ci, mati,
              alpha, beta, eps, gx, gy, gz, dhydro, mform, ashape, salpha, ai, bpa):
    """Branch-free sums over the candidate slots ``s .. e - 1`` (one row of cells) of slot ``k``.

    The slots are read in whole chunks of ``N_LANES`` (``s`` to the multiple of ``N_LANES`` above
    ``e``, at most ``e + N_LANES - 1``: the sentinel columns of ``sx``, ``sd``), contiguously from the
    rows of ``sx`` and ``sd`` (structure of arrays, unsigned slots: no negative-index handling), so
    LLVM vectorises the loop with plain vector loads and no remainder; a candidate that is no
    neighbour adds exactly 0 (``_pair_terms``). The kernel, the dimension and the term set are
    compile-time constants, the numbers of dimensions of the empty arrays ``kshape``, ``dshape``
    and ``tshape`` (see ``fluid_rates``): one compiled version per combination, in which the other
    kernel's shape, the coordinates and velocities above ``dim`` (in 2D exactly 0) and, with
    ``tshape.ndim`` 2 or 3, the wall work and XSPH sums (then exactly 0) are not computed; with 3 (one
    material) neither is the material test of the delta-SPH term.

    Returns (ax, ay, az, cont, work, wall_work, diff, sxu, sxv, sxw): the pressure + artificial-viscosity
    acceleration -sum m_j S grad W (S = p_i/rho_i^2 + p_j/rho_j^2 + Pi_ij), sum V_j v_ij.grad W
    (with ``mform``, the mass form: sum m_j v_ij.grad W),
    sum m_j S v_ij.grad W, its part over dummy wall points j, the delta-SPH sum sum h c psi F V (same material, no wall) and the
    XSPH sums sum (m_j/rho_ij) W (v_j - v_i) (no wall).

    Always inlined (``forceinline``, at the LLVM level: its instructions keep their flags) into the
    parfor loop of ``_fluid_rates``: called, the copy of it optimised in the caller's module ran as a
    scalar loop (rates 355 against 210 ns per particle-step, 2D dam break of 89 888 particles).
    """
    dim = dshape.ndim
    full = tshape.ndim == 1
    fmati = float(mati)
    ax = ay = az = 0.0
    cont = work = wall_work = diff = 0.0
    sxu = sxv = sxw = 0.0
    lanes = np.uint64(N_LANES)
    end = s + (e - s + lanes - np.uint64(1)) // lanes * lanes
    for j in range(s, end):
        tx, ty, tz, tc, tw, tww, td, tu, tv, tws = _pair_terms(
            j, k, e, sx, sd, kshape, dshape, tshape, sig, xi, yi, zi, hi, ui, vi, wi, rhoi, pri, ci, fmati,
            alpha, beta, eps, gx, gy, gz, dhydro, mform, ashape, salpha, ai, bpa)
        ax -= tx
        ay -= ty
        if dim > 2:
            az -= tz
        cont += tc
        work += tw
        diff += td
        if full:
            wall_work += tww
            sxu -= tu
            sxv -= tv
            if dim > 2:
                sxw -= tws
    return ax, ay, az, cont, work, wall_work, diff, sxu, sxv, sxw


def fluid_rates(sx, sd, stau, perm, cell_start, sreach, settings_f, settings_i, grid_f, grid_i, acc, drho, de, xsph,
                wall_power, conv, salpha, switch):
    """Continuity, momentum, energy, delta-SPH and XSPH rates of every real (fluid) point.

    For fluid slot k (particle i = perm[k]) and every point j within 2 h_ij, with
    grad_i W_ij = F_ij r_ij, v_ij = v_i - v_j, V_j = m_j/rho_j, Pi_ij the Monaghan viscosity:

      drho_i = rho_i sum_j V_j v_ij . grad_i W_ij                                  (paper 3.8)
               [mass form, SphOptions.continuity = "mass": sum_j m_j v_ij . grad_i W_ij,
                Monaghan 1992 ARA&A 30, 543: the rate of the summation density at fixed h]
               - 2 delta sum_j h_ij c_ij psi_ij F_ij V_j    (fluid/ghost j of the same material)
      acc_i  = sum_j m_j (sigma_i/rho_i^2 + sigma_j/rho_j^2 - Pi_ij I) . grad_i W_ij   (paper 3.9)
      de_i   = -1/2 sum_j m_j (sigma_i/rho_i^2 + sigma_j/rho_j^2 - Pi_ij I) : (v_ij (x) grad_i W_ij)
      xsph_i = eps_x sum_j (m_j / rho_ij) (v_j - v_i) W_ij             (fluid and ghost j only)

    with sigma = -p I + tau, psi_ij = (rho_j - rho_i) [- rho_ij g.(x_j - x_i)/c_ij^2 with the
    hydrostatic correction]. ``acc`` excludes gravity and external forces. ``conv[i]`` = -(div v)_i =
    sum_j V_j v_ij . grad_i W_ij (mass form: that sum with m_j, over rho_i), the continuity sum without
    delta-SPH: the source of the shock switch (``sph/switch.py``). With ``switch`` true, Pi_ij takes the
    pair's alpha_ij = (alpha_i + alpha_j)/2, ``salpha`` the alpha of every slot, and beta_ij = (beta/alpha)
    alpha_ij (``settings_f[SF_BETA_PER_ALPHA]``); without it the section's alpha and beta.

    A dummy wall point has no energy of its own: of a fluid-wall pair's work m_i m_j S v_ij.grad W
    the fluid particle keeps half (in de_i), the other half is the power the wall absorbs,
    ``wall_power[i]`` = m_i/2 sum_(wall j) m_j S v_ij.grad W (the energy balance counts it).

    Per particle: each row of cells along x within reach is one contiguous slot range, whose
    candidates ``_row_sums`` sums without branches and without a neighbour list (whole chunks of
    ``N_LANES`` slots read with vector loads from the rows of ``sx``/``sd``; a candidate out of
    range adds exactly 0); the row sums are added in row order. The viscous-stress terms, when
    present, are a second scan of the same rows, over the neighbours in slot order. Slots are
    taken in blocks of ``_BLOCK`` per parallel task. Each particle's sums depend only on its own
    rows, so the result does not depend on the thread count. Equations and references:
    docs/theory/sph.md.

    The work is done by ``_fluid_rates``, compiled once per kernel, dimension and term set: these
    are compile-time constants there, the numbers of dimensions of three empty arrays
    (``kshape``: 1 cubic spline, 2 Wendland C2; ``dshape``: dim; ``tshape``: 1 every term, 2 no
    dummy wall points and no XSPH, whose sums are then not computed: they would be exactly 0; 3 the
    same with one material in the table, ``settings_i[SI_NMAT]``, when the delta-SPH term of every
    neighbour counts: no per-pair material test) and switch (``ashape``: 1 the section's alpha and beta, 2
    the shock switch's per-pair values).
    This function, plain Python (the one exception to the kernel modules' rule), only picks the
    specialisation, so that numba compiles just the ones a run uses.
    """
    kernel, dim = int(settings_i[SI_KERNEL]), int(settings_i[SI_DIM])
    lean = settings_i[SI_NWALL] == 0 and settings_f[SF_XSPH] == 0.0
    terms = (3 if settings_i[SI_NMAT] == 1 else 2) if lean else 1
    _fluid_rates(sx, sd, stau, perm, cell_start, sreach, settings_f, settings_i, grid_f, grid_i, acc, drho, de, xsph,
                 wall_power, conv, salpha, _SHAPES[2 if kernel == WENDLAND_C2 else 1], _SHAPES[dim], _SHAPES[terms],
                 _SHAPES[2 if switch else 1])


_SHAPES = {1: np.empty(0), 2: np.empty((0, 0)), 3: np.empty((0, 0, 0))}


@njit(cache=True, parallel=True, error_model="numpy")
def _fluid_rates(sx, sd, stau, perm, cell_start, sreach, settings_f, settings_i, grid_f, grid_i, acc, drho, de, xsph,
                 wall_power, conv, salpha, kshape, dshape, tshape, ashape):
    """``fluid_rates`` for one kernel, dimension, term set and switch (``kshape``, ``dshape``, ``tshape``,
    ``ashape``)."""
    kernel = WENDLAND_C2 if kshape.ndim == 2 else CUBIC_SPLINE
    dim = dshape.ndim
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    viscous = settings_i[SI_VISCOUS] != 0
    dhydro = settings_i[SI_DELTA_HYDROSTATIC] != 0
    mform = settings_i[SI_CONTINUITY] == CONTINUITY_MASS
    alpha, beta, eps = settings_f[SF_ALPHA], settings_f[SF_BETA], settings_f[SF_EPS]
    bpa = settings_f[SF_BETA_PER_ALPHA]
    delta, exsph = settings_f[SF_DELTA], settings_f[SF_XSPH]
    gx, gy, gz = settings_f[SF_GX], settings_f[SF_GY], settings_f[SF_GZ]
    hmax, cell = grid_f[GF_HMAX], grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    inv_cell = 1.0 / cell
    sig = kernel_sigma(kernel, dim)
    npts = cell_start[-1]
    for b in prange((npts + _BLOCK - 1) // _BLOCK):
        for k in range(b * _BLOCK, min(npts, (b + 1) * _BLOCK)):
            mki = int(sd[D_MK, k])
            if (mki & 3) != KIND_FLUID:
                continue
            xi, yi, zi, hi = sx[0, k], sx[1, k], sx[2, k], sx[3, k]
            ui, vi, wi = sd[D_VX, k], sd[D_VY, k], sd[D_VZ, k]
            rhoi, pri, ci = sd[D_RHO, k], sd[D_PR, k], sd[D_C, k]
            reach = sreach[k]  # every 2 h_kj is below sreach[k] (search.search_reach)
            x0, x1 = cell_range(xi, reach, ox, inv_cell, nx)
            y0, y1 = cell_range(yi, reach, oy, inv_cell, ny)
            z0, z1 = cell_range(zi, reach, oz, inv_cell, nz)
            ku = np.uint64(k)
            ai = salpha[k] if ashape.ndim == 2 else alpha
            ax = ay = az = 0.0
            cont = work = wall_work = diff = 0.0
            sxu = sxv = sxw = 0.0
            for cz in range(z0, z1 + 1):
                for cy in range(y0, y1 + 1):
                    base = (cz * ny + cy) * nx
                    r0, r1, r2, r3, r4, r5, r6, r7, r8, r9 = _row_sums(
                        np.uint64(cell_start[base + x0]), np.uint64(cell_start[base + x1 + 1]), ku, sx, sd,
                        kshape, dshape, tshape, sig, xi, yi, zi, hi, ui, vi, wi, rhoi, pri, ci, mki >> 2,
                        alpha, beta, eps, gx, gy, gz, dhydro, mform, ashape, salpha, ai, bpa)
                    ax += r0
                    ay += r1
                    az += r2
                    cont += r3
                    work += r4
                    wall_work += r5
                    diff += r6
                    sxu += r7
                    sxv += r8
                    sxw += r9
            if viscous:
                irho2 = 1.0 / (rhoi * rhoi)
                t0i, t1i, t2i = stau[k, 0] * irho2, stau[k, 1] * irho2, stau[k, 2] * irho2
                t3i, t4i, t5i = stau[k, 3] * irho2, stau[k, 4] * irho2, stau[k, 5] * irho2
                for cz in range(z0, z1 + 1):
                    for cy in range(y0, y1 + 1):
                        base = (cz * ny + cy) * nx
                        for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                            dx, dy, dz = xi - sx[0, j], yi - sx[1, j], zi - sx[2, j]
                            r2 = dx * dx + dy * dy
                            if dim > 2:
                                r2 += dz * dz
                            hs = hi + sx[3, j]
                            if not r2 < hs * hs or j == k:  # the neighbour test of _pair_terms
                                continue
                            f = kernel_f(kernel, dim, math.sqrt(dx * dx + dy * dy + dz * dz), 0.5 * (hi + sx[3, j]))
                            wgx, wgy, wgz = f * dx, f * dy, f * dz
                            rhoj = sd[D_RHO, j]
                            mj = sd[D_VOL, j] * rhoj
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
                            if (int(sd[D_MK, j]) & 3) == KIND_GHOST:  # a wall at rest does no work: all of it to i
                                work -= 2.0 * (ui * tx + vi * ty + wi * tz)
                            else:
                                work -= (ui - sd[D_VX, j]) * tx + (vi - sd[D_VY, j]) * ty + (wi - sd[D_VZ, j]) * tz
            i = perm[k]
            acc[i, 0] = ax
            acc[i, 1] = ay
            if dim > 2:
                acc[i, 2] = az
            drho[i] = (cont if mform else rhoi * cont) - 2.0 * delta * diff
            conv[i] = cont / rhoi if mform else cont
            de[i] = 0.5 * work
            wall_power[i] = 0.5 * sd[D_VOL, k] * rhoi * wall_work
            xsph[i, 0] = exsph * sxu
            xsph[i, 1] = exsph * sxv
            if dim > 2:
                xsph[i, 2] = exsph * sxw


@njit(cache=True)
def interpolate_points(points, sx, sd, cell_start, settings_i, grid_f, grid_i, column, include_walls):
    """Shepard-normalised SPH interpolation at arbitrary ``points`` (P, 3).

    f(x) = sum_j V_j f_j W(|x - x_j|, h_j) / sum_j V_j W(|x - x_j|, h_j) over fluid and ghost
    points (and wall points with ``include_walls``). ``column`` selects the field: a column of
    ``sd`` (D_VX .. D_C), or -1 for the pressure p = (p/rho^2) rho^2. NaN where no point is near.
    """
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    hmax, inv_cell = grid_f[GF_HMAX], 1.0 / grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    out = np.empty(points.shape[0])
    for a in range(points.shape[0]):
        xi, yi, zi = points[a, 0], points[a, 1], points[a, 2]
        reach = 2.0 * hmax
        x0, x1 = cell_range(xi, reach, ox, inv_cell, nx)
        y0, y1 = cell_range(yi, reach, oy, inv_cell, ny)
        z0, z1 = cell_range(zi, reach, oz, inv_cell, nz)
        num = 0.0
        den = 0.0
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if (int(sd[D_MK, j]) & 3) == KIND_WALL and not include_walls:
                        continue
                    dx, dy, dz = xi - sx[0, j], yi - sx[1, j], zi - sx[2, j]
                    r = math.sqrt(dx * dx + dy * dy + dz * dz)
                    wv = kernel_w(kernel, dim, r, sx[3, j])
                    if wv == 0.0:
                        continue
                    vw = sd[D_VOL, j] * wv
                    if column < 0:
                        val = sd[D_PR, j] * sd[D_RHO, j] * sd[D_RHO, j]
                    else:
                        val = sd[column, j]
                    num += vw * val
                    den += vw
        out[a] = num / den if den > 0.0 else np.nan
    return out
