"""EOS glue of the SPH particles: pressure, sound speed and smoothing length from the state,
and the density at a given pressure (wall points, hydrostatic initial states).

The equations of state are the materials module's (``materials.kernels``); docs/theory/sph.md
("Equation of state") states how the SPH fluid uses them. ``density_from_pressure`` and
``sound_speed`` state ``fastmath=False``: the fast-math kernel ``walls.wall_pressure`` calls them,
and without it numba would compile them, and the EOS functions below them, with that caller's
flags whenever it is the first to need them, and cache that version (see ``rates._FM``).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..materials.kernels import EOS_OFFSET, EOS_TAIT, P_EOS_TYPE, P_RHO0, eos_state, eos_pressure, eos_sound_speed
from ..materials.slots import Q_E0, Q_RHO0, Q_TAIT_B, Q_TAIT_GAMMA, Q_TAIT_PB, Q_TAIT_RHO_REF


@njit(cache=True)
def update_particle_state(rho, e, m, mat, active, params, eta, dim, pressure_cutoff, p, c, h):
    """Pressure, sound speed and smoothing length of every active particle.

    p = max(p_eos(rho/rho0, rho0 e), pressure_cutoff), c = c_eos (``eos_pressure`` and ``eos_sound_speed``
    of the materials module, evaluated through their common ``eos_state`` so that the EOS is
    computed once), h = eta (m/rho)^(1/dim). ``e`` is the specific internal energy (per unit
    mass), so the EOS's energy per reference volume is rho0 e. Returns the largest h.

    A table of one Tait material (the water of most decks) in 2D takes ``_tait_state``: the
    same operations in three loops, so that the divisions and square roots are vectorised (issue 17).
    """
    if params.shape[0] == 1 and int(params[0, P_EOS_TYPE]) == EOS_TAIT and dim == 2:
        return _tait_state(rho, m, active, params, eta, pressure_cutoff, p, c, h)
    hmax = 0.0
    for i in range(rho.shape[0]):
        if not active[i]:
            continue
        k = mat[i]
        rho0 = params[k, P_RHO0]
        r = rho[i] / rho0
        if int(params[k, P_EOS_TYPE]) == EOS_TAIT:
            # eos_state's Tait branch, operation for operation (bit-identical), read from the row
            # directly: the slice q of the general path costs more than the EOS (35 -> 2x ns, issue 17)
            qr0 = params[k, EOS_OFFSET + Q_RHO0]
            rho_ref, gam = params[k, EOS_OFFSET + Q_TAIT_RHO_REF], params[k, EOS_OFFSET + Q_TAIT_GAMMA]
            xt = qr0 * r / rho_ref
            xg1 = xt ** (gam - 1.0)
            pr = params[k, EOS_OFFSET + Q_TAIT_B] * (xg1 * xt - 1.0) + params[k, EOS_OFFSET + Q_TAIT_PB]
            dpdmu = params[k, EOS_OFFSET + Q_TAIT_B] * gam * xg1 * qr0 / rho_ref
            dpde = 0.0
        else:
            qr0 = params[k, EOS_OFFSET + Q_RHO0]
            pr, dpdmu, dpde = eos_state(int(params[k, P_EOS_TYPE]), params[k, EOS_OFFSET:], r, rho0 * e[i])
        p[i] = pr if pr > pressure_cutoff else pressure_cutoff
        c2 = (dpdmu + pr * dpde / (r * r)) / qr0  # as eos_sound_speed
        c[i] = math.sqrt(c2) if c2 > 0.0 else 0.0
        vol = m[i] / rho[i]
        hi = eta * math.sqrt(vol) if dim == 2 else eta * np.cbrt(vol)
        h[i] = hi
        hmax = max(hmax, hi)
    return hmax


@njit(cache=True, error_model="numpy")
def _tait_state(rho, m, active, params, eta, pressure_cutoff, p, c, h):
    """``update_particle_state`` for a table of one Tait material in 2D, bit-identical to it.

    The operations of its Tait branch, in three loops over the particles instead of one: (1) the
    compression x = rho0_q (rho/rho0) / rho_ref and x^(gamma - 1) (libm ``pow``, a call LLVM does not
    vectorise), kept in ``c`` and ``p`` of the active particles; (2) p, c and h from them, a loop of
    divisions and square roots without calls, which LLVM vectorises (the inactive particles' p, c,
    h are selected back unchanged); (3) the largest h, ``max`` as in the general loop. Every value
    is computed by the same operations in the same order (IEEE division and square root are
    correctly rounded in the vector units too), so p, c, h and hmax are those of the general loop.
    (3D keeps the general loop: its h is a libm ``cbrt``.)
    """
    n = rho.shape[0]
    rho0 = params[0, P_RHO0]
    qr0 = params[0, EOS_OFFSET + Q_RHO0]
    rho_ref, gam = params[0, EOS_OFFSET + Q_TAIT_RHO_REF], params[0, EOS_OFFSET + Q_TAIT_GAMMA]
    bt, pb = params[0, EOS_OFFSET + Q_TAIT_B], params[0, EOS_OFFSET + Q_TAIT_PB]
    for i in range(n):
        if active[i]:
            xt = qr0 * (rho[i] / rho0) / rho_ref
            c[i] = xt
            p[i] = xt ** (gam - 1.0)
    for i in range(n):
        r = rho[i] / rho0
        xt = c[i]
        xg1 = p[i]
        pr = bt * (xg1 * xt - 1.0) + pb
        dpdmu = bt * gam * xg1 * qr0 / rho_ref
        dpde = 0.0
        pn = pr if pr > pressure_cutoff else pressure_cutoff
        c2 = (dpdmu + pr * dpde / (r * r)) / qr0  # as eos_sound_speed
        cn = math.sqrt(c2) if c2 > 0.0 else 0.0
        vol = m[i] / rho[i]
        hn = eta * math.sqrt(vol)
        act = active[i]
        p[i] = pn if act else xg1
        c[i] = cn if act else xt
        h[i] = hn if act else h[i]
    hmax = 0.0
    for i in range(n):
        if active[i]:
            hmax = max(hmax, h[i])
    return hmax


@njit(cache=True, fastmath=False)
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


@njit(cache=True, fastmath=False)
def sound_speed(eos, q, r, ee):
    """``materials.kernels.eos_sound_speed`` at compression r = rho/rho0 and energy ee, compiled without
    fast-math whoever calls it first."""
    return eos_sound_speed(eos, q, r, ee)


@njit(cache=True)
def densities_from_pressures(pressure, mat, params, out):
    """``out[i]`` = density of material ``mat[i]`` at pressure ``pressure[i]`` and its initial energy."""
    for i in range(pressure.shape[0]):
        k = mat[i]
        rho0 = params[k, P_RHO0]
        q = params[k, EOS_OFFSET:]
        out[i] = density_from_pressure(int(params[k, P_EOS_TYPE]), q, rho0, pressure[i], q[Q_E0], rho0)
