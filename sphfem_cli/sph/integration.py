"""SPH time integration: the kick-drift-kick leapfrog, wall reflection and domain bounds, and the
stable time step. Equations: docs/theory/sph.md ("Time integration", "Time step").
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..materials.slots import P_VISCOSITY


@njit(cache=True, inline="always")
def _reflect(i, x, v, v_half, walls):
    """Mirror particle i back across every wall it has crossed (position, velocity and v^{n+1/2});
    1 if it crossed one, else 0."""
    crossed = 0
    for w in range(walls.shape[0]):
        ax = int(walls[w, 0])
        pos, side = walls[w, 1], walls[w, 2]
        if side * (x[i, ax] - pos) < 0.0:
            x[i, ax] = 2.0 * pos - x[i, ax]
            v[i, ax] = -v[i, ax]
            v_half[i, ax] = -v_half[i, ax]
            crossed = 1
    return crossed


@njit(cache=True, inline="always")
def _deactivate(i, v, e, m, acc, xsph, drho, de, active):
    """Take particle i out (it left the domain) and zero its rates; returns its mass and energy
    m (|v|^2 / 2 + e)."""
    active[i] = False
    ke = 0.0
    for d in range(v.shape[1]):
        ke += v[i, d] * v[i, d]
        acc[i, d] = 0.0
        xsph[i, d] = 0.0
    drho[i] = 0.0
    de[i] = 0.0
    return m[i], m[i] * (0.5 * ke + e[i])



@njit(cache=True, inline="always")
def _scalar_kdk(q, q_half, dq, hp, hn, closing):
    """(q^{n+1/2}, predicted q^{n+1}) of a particle scalar stepped as the density: q^n = q^{n-1/2} + hp dq
    closes the previous step (q itself on the first, ``closing`` false), q^{n+1/2} = q^n + hn dq, and
    q^{n+1} = q^{n+1/2} + hn dq is the prediction the next rates use (hp, hn = dt_prev/2, dt/2)."""
    qn = q_half + hp * dq if closing else q
    qh = qn + hn * dq
    return qh, qh + hn * dq


@njit(cache=True)
def advance_particles(x, v, v_half, rho, rho_half, e, e_half, acc, drho, de, xsph, f_ext, m, active,
                      gravity, dt, dt_prev, walls, lo, hi, use_domain, work):
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

    ``work``: scratch of at least N entries, used (by ``_advance_particles_2d``) in 2D; other
    systems may pass an empty array.
    """
    if x.shape[1] == 2 and work.shape[0] >= x.shape[0]:
        return _advance_particles_2d(x, v, v_half, rho, rho_half, e, e_half, acc, drho, de, xsph, f_ext, m,
                                     active, gravity, dt, dt_prev, walls, lo, hi, use_domain, work)
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
        rho_half[i], rho[i] = _scalar_kdk(rho[i], rho_half[i], drho[i], hp, hn, closing)
        e_half[i], e[i] = _scalar_kdk(e[i], e_half[i], de[i], hp, hn, closing)
        nref += _reflect(i, x, v, v_half, walls)
        if not use_domain:
            continue
        inside = True
        for d in range(dim):
            inside = inside and lo[d] <= x[i, d] <= hi[d]
        if inside:
            continue
        nlost += 1
        dm, de_lost = _deactivate(i, v, e, m, acc, xsph, drho, de, active)
        lost_mass += dm
        lost_energy += de_lost
    return ptot, nref, nlost, lost_mass, lost_energy


@njit(cache=True, error_model="numpy")
def _advance_particles_2d(x, v, v_half, rho, rho_half, e, e_half, acc, drho, de, xsph, f_ext, m, active,
                          gravity, dt, dt_prev, walls, lo, hi, use_domain, work):
    """``advance_particles`` in 2D, bit-identical to it, in two loops: (1) the kicks and the drift of
    every particle and its f_ext power (into ``work``), the general loop's operations in its order,
    the two components written out through flat views of the (N, 2) arrays (component d of
    particle i at 2 i + d), without branches (an inactive particle's new values are computed and
    not stored); (2) in particle order, the sum of the power, the wall reflections and the domain
    check (branches). Each particle's step only reads and writes its own entries, so splitting it
    in two changes no value, and the sums are taken in the same order. (LLVM leaves loop (1)
    scalar (its asm has no vector multiply; probably the runtime overlap checks of the seven arrays
    it writes against the eight it reads); split further into one loop per written array,
    recomputing v^{n+1/2}, the pass without walls and domain took 12.7 ns against the general
    loop's 8.1 in the same run, where this one takes 6.8 against 8.1. The split saves the per-component loop and keeps the wall tests out of the arithmetic:
    14.0-14.4 -> 11.8-12.0 ns per particle-step; issue 17.)
    """
    n = x.shape[0]
    hp = 0.5 * dt_prev
    hn = 0.5 * dt
    closing = dt_prev > 0.0
    xf, vf, vhf = x.reshape(-1), v.reshape(-1), v_half.reshape(-1)
    af, sf, ff = acc.reshape(-1), xsph.reshape(-1), f_ext.reshape(-1)
    g0, g1 = gravity[0], gravity[1]
    for i in range(n):  # branch-free: an inactive particle's values are computed and discarded (selected)
        act = active[i]
        im = 1.0 / m[i]
        pw = 0.0
        for d in range(2):
            f = 2 * i + d
            a = af[f] + (g0 if d == 0 else g1) + ff[f] * im
            v_old = vhf[f] if closing else vf[f]
            vn = v_old + hp * a
            vh = vn + hn * a
            x_new = xf[f] + dt * (vh + sf[f])
            v_new = vh + hn * a
            vhf[f] = vh if act else vhf[f]
            xf[f] = x_new if act else xf[f]
            vf[f] = v_new if act else vf[f]
            pw += ff[f] * 0.5 * (v_old + vh)
        work[i] = pw
        rh, r_new = _scalar_kdk(rho[i], rho_half[i], drho[i], hp, hn, closing)
        rho_half[i] = rh if act else rho_half[i]
        rho[i] = r_new if act else rho[i]
        eh, e_new = _scalar_kdk(e[i], e_half[i], de[i], hp, hn, closing)
        e_half[i] = eh if act else e_half[i]
        e[i] = e_new if act else e[i]
    ptot = 0.0
    nref, nlost = 0, 0
    lost_mass = 0.0
    lost_energy = 0.0
    for i in range(n):
        if not active[i]:
            continue
        ptot += work[i] * (hp + hn)
        nref += _reflect(i, x, v, v_half, walls)
        if not use_domain:
            continue
        inside = lo[0] <= x[i, 0] <= hi[0]
        inside = inside and lo[1] <= x[i, 1] <= hi[1]
        if inside:
            continue
        nlost += 1
        dm, de_lost = _deactivate(i, v, e, m, acc, xsph, drho, de, active)
        lost_mass += dm
        lost_energy += de_lost
    return ptot, nref, nlost, lost_mass, lost_energy


@njit(cache=True)
def stable_time_step(h, c, v, acc, f_ext, m, rho, mat, active, params, gravity, cfl, cforce, cvisc, work):
    """min over active particles of cfl h/(c + |v|), cforce sqrt(h/|a|), cvisc rho h^2/mu.

    ``work``: scratch of at least (3, N), used (by ``_stable_time_step_2d``) for a 2D system of one
    material; any other system may pass a (0, 0) array.
    """
    if v.shape[1] == 2 and params.shape[0] == 1 and work.shape[0] >= 3 and work.shape[1] >= h.shape[0]:
        return _stable_time_step_2d(h, c, v, acc, f_ext, m, rho, active, params[0, P_VISCOSITY], gravity, cfl,
                                    cforce, cvisc, work)
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


@njit(cache=True, error_model="numpy")
def _stable_time_step_2d(h, c, v, acc, f_ext, m, rho, active, mu, gravity, cfl, cforce, cvisc, work):
    """``stable_time_step`` of a 2D system of one material (viscosity ``mu``), bit-identical to it.

    Two loops instead of one: (1) every particle's three candidates, cfl h/(c + |v|), h/|a| and
    cvisc rho h^2/mu, by the same operations as the general loop (its sums over the two components
    begin at 0.0, and 0.0 + x = x for the squares), +inf where the general loop skips the particle
    or the criterion (inactive, c + |v| not > 0, |a|^2 not > 0, mu not > 0), into ``work``: no
    call, no reduction, so LLVM vectorises its divisions and square roots; (2) the minima, in
    particle order, with ``min`` as in the general loop: ``min(d, t)`` is ``t if t < d else d``
    (numba's builtin), so ``min(d, inf)`` is ``d`` for every d, NaN included, and a +inf candidate
    is a skipped one. (The general loop spends most of its time in the scalar divisions and
    square roots; issue 17.)
    """
    n = h.shape[0]
    # flat views (the system's arrays are C-contiguous): component d of particle i at 2 i + d, a stride
    # LLVM knows at compile time (through the (N, 2) arrays the row stride is a runtime value, and the
    # loop stays scalar: 9.1 against 2.7 ns per particle)
    vf, af, ff = v.reshape(-1), acc.reshape(-1), f_ext.reshape(-1)
    g0, g1 = gravity[0], gravity[1]
    viscous = mu > 0.0
    for i in range(n):
        im = 1.0 / m[i]
        v0, v1 = vf[2 * i], vf[2 * i + 1]
        vv = v0 * v0 + v1 * v1
        a0 = af[2 * i] + g0 + ff[2 * i] * im
        a1 = af[2 * i + 1] + g1 + ff[2 * i + 1] * im
        aa = a0 * a0 + a1 * a1
        speed = c[i] + math.sqrt(vv)
        act = active[i]
        work[0, i] = cfl * h[i] / speed if act and speed > 0.0 else np.inf
        work[1, i] = h[i] / math.sqrt(aa) if act and aa > 0.0 else np.inf
        work[2, i] = cvisc * rho[i] * h[i] * h[i] / mu if act and viscous else np.inf
    dt = np.inf
    ha = np.inf
    for i in range(n):
        dt = min(dt, work[0, i])
        ha = min(ha, work[1, i])
        dt = min(dt, work[2, i])
    if ha < np.inf:
        dt = min(dt, cforce * math.sqrt(ha))
    return dt
