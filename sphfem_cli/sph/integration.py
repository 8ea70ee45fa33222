"""SPH time integration: the kick-drift-kick leapfrog, wall reflection and domain bounds, and the
stable time step. Equations: docs/theory/sph.md ("Time integration", "Time step").
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..materials.slots import P_VISCOSITY


@njit(cache=True)
def advance_particles(x, v, v_half, rho, rho_half, e, e_half, acc, drho, de, xsph, f_ext, m, active,
                      gravity, dt, dt_prev, walls, lo, hi, use_domain):
    """One leapfrog step of every active particle (kick-drift-kick, one rate evaluation per step),
    then its wall reflection and domain check; zeroes the rates of particles just deactivated.

    With total acceleration a^n = acc + g + f_ext/m and rates evaluated at step n:
      v^n      = v^{n-1/2} + dt_prev/2 a^n           (closes the previous step; skipped if dt_prev = 0)
      v^{n+1/2} = v^n + dt/2 a^n
      x^{n+1}  = x^n + dt (v^{n+1/2} + xsph^n)
      v       <- v^{n+1/2} + dt/2 a^n                 (prediction of v^{n+1} for the next rates)
    and the same for rho and e (their rates are drho, de). Net effect
    v^{n+1/2} = v^{n-1/2} + (dt_prev + dt)/2 a^n, the central difference of the FEM loop.
    The work of f_ext is f_ext . (v^{n-1/2} + v^{n+1/2})/2 (dt_prev + dt)/2 per particle, exactly as
    the kicks apply it (the FEM loop counts nodal work the same way), so that an impulsive force
    (contact) is not over-counted; it is summed in particle order.

    After its drift, a particle found behind a ghost-wall plane (``walls`` rows: axis, position,
    side) is mirrored back and its normal velocity reversed; one outside the domain box [lo, hi]
    (``use_domain``) is deactivated, its rates zeroed and its mass and kinetic + internal energy
    counted.

    Returns (work of f_ext over the step, number reflected at walls, number deactivated, their
    mass, their kinetic + internal energy). One pass, each particle's step done in full before
    the next: the operations and their order are those of the three passes (kick-drift, bounds,
    lost particles) it replaced, so the results are bit-identical, without their three temporary
    arrays per step (issue 17). (With the kick-drift as a separate numba function called per
    particle the pass took 10 times longer: the call of a function of 12 array arguments costs more
    than the particle's arithmetic.)
    """
    n = x.shape[0]
    dim = x.shape[1]
    hp = 0.5 * dt_prev
    hn = 0.5 * dt
    closing = dt_prev > 0.0
    ptot = 0.0
    nref, nlost = 0, 0
    lost_mass = 0.0
    lost_energy = 0.0
    for i in range(n):
        if not active[i]:
            continue
        im = 1.0 / m[i]
        pw = 0.0
        for d in range(dim):
            a = acc[i, d] + gravity[d] + f_ext[i, d] * im
            v_old = v_half[i, d] if closing else v[i, d]
            vn = v_old + hp * a
            vh = vn + hn * a
            v_half[i, d] = vh
            x[i, d] += dt * (vh + xsph[i, d])
            v[i, d] = vh + hn * a
            pw += f_ext[i, d] * 0.5 * (v_old + vh)
        ptot += pw * (hp + hn)
        rn = rho_half[i] + hp * drho[i] if closing else rho[i]
        rh = rn + hn * drho[i]
        rho_half[i] = rh
        rho[i] = rh + hn * drho[i]
        en = e_half[i] + hp * de[i] if closing else e[i]
        eh = en + hn * de[i]
        e_half[i] = eh
        e[i] = eh + hn * de[i]
        crossed = 0
        for w in range(walls.shape[0]):
            ax = int(walls[w, 0])
            pos, side = walls[w, 1], walls[w, 2]
            if side * (x[i, ax] - pos) < 0.0:
                x[i, ax] = 2.0 * pos - x[i, ax]
                v[i, ax] = -v[i, ax]
                v_half[i, ax] = -v_half[i, ax]
                crossed = 1
        nref += crossed
        if not use_domain:
            continue
        inside = True
        for d in range(dim):
            inside = inside and lo[d] <= x[i, d] <= hi[d]
        if inside:
            continue
        active[i] = False
        nlost += 1
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
