"""The ALE force kernels' state pass of the initial state, in numpy: the material pressures, bulk moduli,
bulk viscosity and stable step that ``lagrange.lagrange_forces`` (plane quad4), ``axisymmetric.lagrange_forces_rz``
(r-z rings) and ``lagrange.lagrange_forces_3d`` (hex8) write, without compiling them.

``sphfem check`` needs the stable step of the initial state (and its pressures, for the output size and the
non-reflecting sides' far-field pressure) and nothing else of the force kernels, whose compilation on an empty
numba cache costs 17-30 s. This pass computes, per element (paper eqs. 2.9-2.10; docs/theory/ale.md):

- each material's state where it is present (V_m > phi_eps V and M_m > RHO_VOID rho0 V_m): rho = M_m / V_m,
  r = rho / rho0, E = rho0 (E_m / M_m + e_lag), (p, dp/dmu, dp/dE) of its equation of state
  (``materials.kernels.eos_state``: linear polynomial, Gruneisen, Tait, ideal and stiffened gas, JWL),
  c^2 = (dp/dmu + p dp/dE / r^2) / rho0, c = sqrt(c^2) (0 where c^2 <= 0), p = max(p pscale, cut-off), a
  Gruneisen liquid below RHO_CAVITATED rho0 under a cut-off at the cut-off with its reference sound speed
  (``lagrange.material_state``, ``_mixture_pressure``); pres_m = p, bulk_m = rho c c;
- the mixture: p_mix = sum phi_m p_m, c_e^2 = sum M_m c_m^2 / sum M_m over the present materials;
- the geometry of ``force_lanes.geometry_block`` (plane: area A, mean gradient b, tr d = sum_a v_a . b_a,
  the largest corner |v|^2, l = A / longest edge), with ``axisymmetric.ring_block`` on rings (ring volume V,
  tr d = sum_a v_a . dV/dx_a / V, l times min(1, |b| V / |dV/dx|)), or ``hex_lanes.hex_geometry_block`` on
  hex8 (V and b of ``fem.geometry.hex8_dv``, l = V / largest face area);
- q = rho_e l (Q1^2 l tr d^2 - Q2 c tr d) in compression, else 0, rho_e = M / V (A in the plane), and
  dt_e = l / (Q + sqrt(Q^2 + c_eff^2)), c_eff = c_e + |v|_max, Q = Q2 c_eff + Q1^2 l |tr d| in compression,
  else 0 (inf where c_eff <= 0): eq. 2.9 (``force_lanes.viscosity_block``, ``lagrange.viscosity_and_step``).

Every value is the kernel's operations in the kernel's order (the kernels' vectorised passes are the same
operations as their scalar forms: their docstrings), so the arrays are bit-identical to the kernel's;
tests/unit/test_at_rest_pass.py checks this on every shipped ALE deck and on synthetic ones (moving, mixed,
ring, hex8). exp and pow (JWL, Tait) go through Python's math module element by element: the C library's
functions, as the compiled kernels call them (numpy's own vectorised exp and power may differ in the last bit).

Which initial states it covers: any nodal velocity (at rest, or moving: the velocity enters through tr d and
|v|_max, elementary operations, so a bird moving at uniform speed in void, its boundary and mixed cells
included, is covered exactly); any mix of the six equations of state and void; programmed-burn pressure
scales (pscale). It declines (returns False, writes nothing; then the kernel runs as before) for an element
of non-positive volume or area, any non-finite result, or an unknown equation of state. It does not compute
the element forces: the first step runs the force kernel as always (``AleSystem._forces``).
"""
from __future__ import annotations

import math

import numpy as np

from ..fem.tables import HEX_DV, HEX_FACES
from ..materials.ids import EOS_GRUNEISEN, EOS_IDEAL_GAS, EOS_JWL, EOS_LINEAR_POLYNOMIAL, EOS_STIFFENED_GAS, EOS_TAIT
from ..materials.slots import (Q_GR_A, Q_GR_C, Q_GR_GAMMA0, Q_GR_S1, Q_GR_S2, Q_GR_S3, Q_IG_GAMMA, Q_JWL_A, Q_JWL_B,
                               Q_JWL_OMEGA, Q_JWL_R1, Q_JWL_R2, Q_LP_C0, Q_LP_C1, Q_LP_C2, Q_LP_C3, Q_LP_C4, Q_LP_C5,
                               Q_LP_C6, Q_RHO0, Q_SG_GAMMA, Q_SG_PINF, Q_TAIT_B, Q_TAIT_C0, Q_TAIT_GAMMA, Q_TAIT_PB,
                               Q_TAIT_RHO_REF)

# lagrange.RHO_VOID, lagrange.RHO_CAVITATED and ring_geometry.PI_3 (those modules load numba;
# tests/unit/test_at_rest_pass.py checks the copies are equal)
RHO_VOID = 1e-9
RHO_CAVITATED = 0.5
PI_3 = math.pi / 3.0
KNOWN_EOS = (EOS_LINEAR_POLYNOMIAL, EOS_GRUNEISEN, EOS_TAIT, EOS_IDEAL_GAS, EOS_STIFFENED_GAS, EOS_JWL)


def _larger(acc, value):
    """numba's max(acc, value) of two floats: value where value > acc, else acc."""
    return np.where(value > acc, value, acc)


def _each(fn, values):
    """fn (a math-module function of one float) of every element: the C library's result, as compiled code gets."""
    return np.fromiter((fn(a) for a in values.tolist()), dtype=np.float64, count=values.size)


def eos_state(eos: int, q: np.ndarray, r: np.ndarray, e: np.ndarray):
    """``materials.kernels.eos_state`` on arrays r = rho/rho0, e = E per reference volume: (p, dp/dmu, dp/dE)."""
    mu = r - 1.0
    if eos == EOS_LINEAR_POLYNOMIAL:
        c0, c1, c2, c3 = q[Q_LP_C0], q[Q_LP_C1], q[Q_LP_C2], q[Q_LP_C3]
        c4, c5, c6 = q[Q_LP_C4], q[Q_LP_C5], q[Q_LP_C6]
        c2 = np.where(mu < 0.0, 0.0, c2)  # LS-DYNA drops the quadratic terms in tension
        c6 = np.where(mu < 0.0, 0.0, c6)
        p = c0 + mu * (c1 + mu * (c2 + mu * c3)) + (c4 + mu * (c5 + mu * c6)) * e
        dpdmu = c1 + mu * (2.0 * c2 + 3.0 * c3 * mu) + (c5 + 2.0 * c6 * mu) * e
        dpde = c4 + mu * (c5 + mu * c6)
        return p, dpdmu, dpde
    if eos == EOS_GRUNEISEN:
        rho0, c, s1, s2, s3 = q[Q_RHO0], q[Q_GR_C], q[Q_GR_S1], q[Q_GR_S2], q[Q_GR_S3]
        g0, a = q[Q_GR_GAMMA0], q[Q_GR_A]
        k0 = rho0 * c * c
        dpde = g0 + a * mu
        m1 = mu + 1.0
        num = 1.0 + (1.0 - 0.5 * g0) * mu - 0.5 * a * mu * mu
        dnum = (1.0 - 0.5 * g0) - a * mu
        den = 1.0 - (s1 - 1.0) * mu - s2 * mu * mu / m1 - s3 * mu * mu * mu / (m1 * m1)
        dden = -(s1 - 1.0) - s2 * mu * (mu + 2.0) / (m1 * m1) - s3 * mu * mu * (mu + 3.0) / (m1 * m1 * m1)
        compressed = mu > 0.0
        p = np.where(compressed, k0 * mu * num / (den * den) + dpde * e, k0 * mu + dpde * e)
        dpdmu = np.where(compressed,
                         k0 * ((num + mu * dnum) / (den * den) - 2.0 * mu * num * dden / (den * den * den)) + a * e,
                         k0 + a * e)
        return p, dpdmu, dpde
    if eos == EOS_TAIT:
        rho0, rho_ref, c, gam = q[Q_RHO0], q[Q_TAIT_RHO_REF], q[Q_TAIT_C0], q[Q_TAIT_GAMMA]
        pb, b = q[Q_TAIT_PB], q[Q_TAIT_B]
        x = rho0 * r / rho_ref
        y = float(gam - 1.0)
        xg1 = _each(lambda a: a ** y, x)  # Python floats: the C library's pow
        p = b * (xg1 * x - 1.0) + pb
        dpdmu = b * gam * xg1 * rho0 / rho_ref
        return p, dpdmu, 0.0
    if eos == EOS_IDEAL_GAS:
        gm1 = q[Q_IG_GAMMA] - 1.0
        return gm1 * r * e, gm1 * e, gm1 * r
    if eos == EOS_STIFFENED_GAS:
        gam, pinf = q[Q_SG_GAMMA], q[Q_SG_PINF]
        gm1 = gam - 1.0
        return gm1 * r * e - gam * pinf, gm1 * e, gm1 * r
    if eos == EOS_JWL:
        a, b, r1, r2, w = q[Q_JWL_A], q[Q_JWL_B], q[Q_JWL_R1], q[Q_JWL_R2], q[Q_JWL_OMEGA]
        v = 1.0 / r
        x1 = _each(math.exp, -r1 * v)
        x2 = _each(math.exp, -r2 * v)
        p = a * (1.0 - w / (r1 * v)) * x1 + b * (1.0 - w / (r2 * v)) * x2 + w * e * r
        dpdv = (
            a * x1 * (w / (r1 * v * v) - r1 + w / v)
            + b * x2 * (w / (r2 * v * v) - r2 + w / v)
            - w * e / (v * v)
        )
        return p, -v * v * dpdv, w * r
    raise ValueError(f"unknown equation of state {eos}")


def material_state(eos: int, q: np.ndarray, rho0: float, rho: np.ndarray, e_spec: np.ndarray):
    """``lagrange.material_state``: (p, c) of one material at densities rho and specific energies e_spec (arrays);
    (0, 0) where rho <= 0 (and everywhere for void, eos < 0, or rho0 <= 0)."""
    if eos < 0 or rho0 <= 0.0:
        return np.zeros_like(rho), np.zeros_like(rho)
    r = rho / rho0
    p, dpdmu, dpde = eos_state(eos, q, r, rho0 * e_spec)
    c2 = (dpdmu + p * dpde / (r * r)) / rho0
    c = np.where(c2 > 0.0, np.sqrt(np.where(c2 > 0.0, c2, 0.0)), 0.0)
    live = rho > 0.0
    return np.where(live, p, 0.0), np.where(live, c, 0.0)


def mixture_state(vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q, mat_rho0, phi_eps, pscale, pressure_cutoff):
    """``lagrange._mixture_pressure`` of every element: (p_mix, c_e, M, pres_m, bulk_m), materials in order."""
    n_elem, n_mat = vol_m.shape
    vtot = 0.0
    mtot = 0.0
    for m in range(n_mat):
        vtot = vtot + vol_m[:, m]
        mtot = mtot + mass_m[:, m]
    p_mix = np.zeros(n_elem)
    mc2 = np.zeros(n_elem)
    m_in = np.zeros(n_elem)
    pres = np.zeros((n_elem, n_mat))
    bulk = np.zeros((n_elem, n_mat))
    for m in range(n_mat):
        vol, mass = vol_m[:, m], mass_m[:, m]
        present = (vol > phi_eps * vtot) & (mass > RHO_VOID * mat_rho0[m] * vol)
        if not present.any():
            continue
        idx = np.flatnonzero(present)
        vol, mass = vol[idx], mass[idx]
        rho = mass / vol
        eos, rho0 = int(mat_eos[m]), mat_rho0[m]
        p, c = material_state(eos, mat_q[m], rho0, rho, ener_m[idx, m] / mass + e_lag[idx, m])
        p = p * pscale[idx, m]
        p = _larger(p, pressure_cutoff)
        if pressure_cutoff > -math.inf and eos == EOS_GRUNEISEN:
            cavitated = rho < RHO_CAVITATED * rho0
            c_ref = material_state(eos, mat_q[m], rho0, np.array([rho0]), np.zeros(1))[1][0]
            p = np.where(cavitated, pressure_cutoff, p)
            c = np.where(cavitated, c_ref, c)
        pres[idx, m] = p
        bulk[idx, m] = rho * c * c
        p_mix[idx] = p_mix[idx] + vol / vtot[idx] * p
        mc2[idx] = mc2[idx] + mass * c * c
        m_in[idx] = m_in[idx] + mass
    with np.errstate(divide="ignore", invalid="ignore"):
        c_e = np.where(m_in > 0.0, np.sqrt(mc2 / np.where(m_in > 0.0, m_in, 1.0)), 0.0)
    return p_mix, c_e, mtot, pres, bulk


def viscosity_and_step(rho_e, length, c, trace_d, vmax2, q1, q2):
    """``force_lanes.viscosity_block`` / ``lagrange.viscosity_and_step``: (q, dt_e)."""
    q = rho_e * length * (q1 * q1 * length * trace_d * trace_d - q2 * c * trace_d)
    q = np.where(trace_d >= 0.0, 0.0, q)
    c_eff = c + np.sqrt(vmax2)
    qq = np.where(trace_d < 0.0, q2 * c_eff + q1 * q1 * length * (-trace_d), 0.0)
    den = qq + np.sqrt(qq * qq + c_eff * c_eff)
    dt = np.where((c_eff > 0.0) & (den > 0.0), length / np.where(den > 0.0, den, 1.0), np.inf)
    return q, dt


def quad_geometry(x, v, conn, moving: bool, gradient: bool):
    """``force_lanes.geometry_block``: (corners x, y, u, w as lists of (E,) arrays, area, b_x, b_y, tr d, largest
    corner |v|^2, longest squared edge). Where no node moves (moving False) tr d is +0.0 whatever the finite b is
    (each v . b is +-0, and 0.0 + -0.0 = +0.0) and |v|^2 is 0: then u, w are zeros and b is formed only if
    gradient (the ring's hoop factor needs it)."""
    xs = [x[conn[:, a], 0] for a in range(4)]
    ys = [x[conn[:, a], 1] for a in range(4)]
    x0, x1, x2, x3 = xs
    y0, y1, y2, y3 = ys
    area = 0.5 * ((x2 - x0) * (y3 - y1) + (x1 - x3) * (y2 - y0))
    longest2 = 0.0
    for a in range(4):
        j = (a + 1) % 4
        dx, dy = xs[j] - xs[a], ys[j] - ys[a]
        longest2 = _larger(longest2, dx * dx + dy * dy)
    zero = np.zeros(len(conn))
    us = ws = [zero] * 4
    bx = by = None
    trace_d, vmax2 = zero, zero
    if moving or gradient:
        with np.errstate(divide="ignore"):
            inv = np.where(area > 0.0, 0.5 / area, 0.0)
        bx = [(y1 - y3) * inv, (y2 - y0) * inv, (y3 - y1) * inv, (y0 - y2) * inv]
        by = [(x3 - x1) * inv, (x0 - x2) * inv, (x1 - x3) * inv, (x2 - x0) * inv]
    if moving:
        us = [v[conn[:, a], 0] for a in range(4)]
        ws = [v[conn[:, a], 1] for a in range(4)]
        vmax2 = 0.0
        for a in range(4):
            vmax2 = _larger(vmax2, us[a] * us[a] + ws[a] * ws[a])
        trace_d = 0.0
        for a in range(4):
            trace_d = trace_d + (us[a] * bx[a] + ws[a] * by[a])
    return xs, ys, us, ws, area, bx, by, trace_d, vmax2, longest2


def ring_geometry(xs, ys, us, ws, bx, by, moving: bool):
    """``axisymmetric.ring_block``: (ring volume V, tr d = sum_a v_a . dV/dx_a / V (0 where V <= 0), |b|^2,
    |dV/dx|^2); tr d = +0.0 where no node moves (``quad_geometry``)."""
    r0, r1, r2, r3 = xs
    z0, z1, z2, z3 = ys
    gr = [PI_3 * (2.0 * r0 * (z1 - z3) + r1 * (z1 - z0) + r3 * (z0 - z3)),
          PI_3 * (2.0 * r1 * (z2 - z0) + r2 * (z2 - z1) + r0 * (z1 - z0)),
          PI_3 * (2.0 * r2 * (z3 - z1) + r3 * (z3 - z2) + r1 * (z2 - z1)),
          PI_3 * (2.0 * r3 * (z0 - z2) + r0 * (z0 - z3) + r2 * (z3 - z2))]
    gz = [PI_3 * (r3 - r1) * (r3 + r0 + r1),
          PI_3 * (r0 - r2) * (r0 + r1 + r2),
          PI_3 * (r1 - r3) * (r1 + r2 + r3),
          PI_3 * (r2 - r0) * (r2 + r3 + r0)]
    s = (r0 + r1) * (r0 * z1 - r1 * z0)
    s = s + (r1 + r2) * (r1 * z2 - r2 * z1)
    s = s + (r2 + r3) * (r2 * z3 - r3 * z2)
    s = s + (r3 + r0) * (r3 * z0 - r0 * z3)
    vol = PI_3 * s
    trace_d = 0.0
    bb = 0.0
    gg = 0.0
    if moving:
        for a in range(4):
            trace_d = trace_d + (us[a] * gr[a] + ws[a] * gz[a])
    for a in range(4):
        bb = bb + (bx[a] * bx[a] + by[a] * by[a])
    for a in range(4):
        gg = gg + (gr[a] * gr[a] + gz[a] * gz[a])
    if moving:
        with np.errstate(divide="ignore", invalid="ignore"):
            trace_d = np.where(vol > 0.0, trace_d / vol, 0.0)
    else:
        trace_d = np.zeros(len(vol))
    return vol, trace_d, bb, gg


def hex_geometry(x, v, conn, moving: bool):
    """``hex_lanes.hex_geometry_block``: (V, tr d, largest corner |v|^2, largest squared face cross product).

    dV/dx_I of ``fem.geometry.hex8_dv``: from 0.0, the rows (I, j, k, s) of HEX_DV in table order, each adding
    (s = 1) or subtracting W (y_j z_k - y_k z_j), W = 1/12 (and cyclically for y, z); V = 0.0 + sum_I x_I dV/dx_I
    in node order; b = dV/dx / V (0 unless V > 0). Where every corner of an element is at rest tr d is +0.0
    whatever b is (a finite b times 0 is +-0, and 0.0 + -0.0 = +0.0), so b_y, b_z are formed only for a mesh
    with a moving node.
    """
    c = [[x[conn[:, a], k] for k in range(3)] for a in range(8)]
    W = 1.0 / 12.0

    def dv(comp):
        k1, k2 = (comp + 1) % 3, (comp + 2) % 3  # x: (y, z), y: (z, x), z: (x, y)
        out = []
        for i in range(8):
            acc = 0.0
            for (node, j, k, s) in HEX_DV[9 * i:9 * i + 9]:
                term = W * (c[j][k1] * c[k][k2] - c[k][k1] * c[j][k2])
                acc = acc + term if s > 0 else acc - term
            out.append(acc)
        return out

    bx = dv(0)
    volume = 0.0
    for i in range(8):
        volume = volume + c[i][0] * bx[i]
    vmax2 = trace_d = np.zeros(len(conn))
    if moving:
        u = [[v[conn[:, a], k] for k in range(3)] for a in range(8)]
        vmax2 = 0.0
        for a in range(8):
            vmax2 = _larger(vmax2, u[a][0] * u[a][0] + u[a][1] * u[a][1] + u[a][2] * u[a][2])
        by, bz = dv(1), dv(2)
        with np.errstate(divide="ignore"):
            inv = np.where(volume > 0.0, 1.0 / volume, 0.0)
        trace_d = 0.0
        for a in range(8):
            trace_d = trace_d + (u[a][0] * (bx[a] * inv) + u[a][1] * (by[a] * inv) + u[a][2] * (bz[a] * inv))
    large2 = 0.0
    for a, b, cc, d in HEX_FACES:
        px, py, pz = c[cc][0] - c[a][0], c[cc][1] - c[a][1], c[cc][2] - c[a][2]
        qx, qy, qz = c[d][0] - c[b][0], c[d][1] - c[b][1], c[d][2] - c[b][2]
        cx = py * qz - pz * qy
        cy = pz * qx - px * qz
        cz = px * qy - py * qx
        large2 = _larger(large2, cx * cx + cy * cy + cz * cz)
    return volume, trace_d, vmax2, large2


# elements per block of the pass: its temporaries (some 50 arrays of the block) stay in the cache and are reused,
# where whole-mesh temporaries cost a page fault per page first touched (960^2 cells, two materials, at rest:
# 2.0 s CPU in one block, 0.22 s in blocks of 4096)
BLOCK = 4096


def _block(x, v, conn, vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q, mat_rho0, q1, q2, phi_eps, pscale,
           pressure_cutoff, ring, moving):
    """The pass over one block of elements: (pres, bulk, q, dt), or None where it does not cover the block."""
    dim = x.shape[1]
    p_mix, c_e, mtot, pres, bulk = mixture_state(vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q, mat_rho0, phi_eps,
                                                 pscale, pressure_cutoff)
    if dim == 2:
        xs, ys, us, ws, area, bx, by, trace_d, vmax2, longest2 = quad_geometry(x, v, conn, moving, ring)
        if not (area > 0.0).all():
            return None
        length = area / np.sqrt(longest2)
        if ring:
            vol, trace_d, bb, gg = ring_geometry(xs, ys, us, ws, bx, by, moving)
            if not (vol > 0.0).all():
                return None
            factor = np.sqrt(bb / gg) * vol
            length = np.where(gg > 0.0, length * np.where(factor < 1.0, factor, 1.0), length)
        else:
            vol = area
    else:
        vol, trace_d, vmax2, large2 = hex_geometry(x, v, conn, moving)
        if not (vol > 0.0).all():
            return None
        length = vol / (0.5 * np.sqrt(large2))
    q, dt = viscosity_and_step(mtot / vol, length, c_e, trace_d, vmax2, q1, q2)
    return pres, bulk, q, dt


def initial_element_pass(x, v, conn, vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q, mat_rho0, q1, q2, phi_eps, pscale,
                         pressure_cutoff, ring, pres_m, bulk_m, q_elem, dt_elem) -> bool:
    """pres_m, bulk_m, q_elem, dt_elem of the force kernel for the state (module docstring); False (nothing
    written) where the pass does not cover it. Arguments as ``lagrange.lagrange_forces``; ring: the r-z kernel's
    (``axisymmetric.lagrange_forces_rz``); hex8 for (E, 8) connectivity in 3D. In blocks of BLOCK elements."""
    dim, npe = x.shape[1], conn.shape[1]
    if (dim, npe) not in ((2, 4), (3, 8)) or (ring and dim != 2) or len(conn) == 0:
        return False
    if not all(int(e) < 0 or int(e) in KNOWN_EOS for e in mat_eos):
        return False
    moving = bool(np.any(v))
    out = (np.empty_like(pres_m), np.empty_like(bulk_m), np.empty_like(q_elem), np.empty_like(dt_elem))
    with np.errstate(all="ignore"):
        for start in range(0, len(conn), BLOCK):
            b = slice(start, start + BLOCK)
            done = _block(x, v, conn[b], vol_m[b], mass_m[b], ener_m[b], e_lag[b], mat_eos, mat_q, mat_rho0, q1, q2,
                          phi_eps, pscale[b], pressure_cutoff, ring, moving)
            if done is None:
                return False
            for target, value in zip(out, done):
                target[b] = value
    pres, bulk, q, dt = out
    if not (np.isfinite(pres).all() and np.isfinite(bulk).all() and np.isfinite(q).all()
            and not np.isnan(dt).any() and (dt > 0.0).all()):
        return False
    pres_m[:] = pres
    bulk_m[:] = bulk
    q_elem[:] = q
    dt_elem[:] = dt
    return True
