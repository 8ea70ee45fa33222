"""ALE plane force kernel (``lagrange.lagrange_forces``): three of its passes over a block of elements
written so that LLVM vectorises them (issue 17): the material state where the mesh holds one ideal or
stiffened gas (``gas_block``) or two (``two_gas_block``, the (E, 2) state read in place), the geometry (``geometry_block``), and the bulk viscosity and stable step
(``viscosity_block``).

The force kernel goes over each block of elements in passes through a work array (see the comment
above it). The state and viscosity passes are where its divisions and square roots are; written as straight-line
loops over flat arrays (no branch: every value computed, the cases selected afterwards; numpy's error
model: a division by zero gives inf or nan, which the selects discard, instead of a Python exception)
the vector units take 8 elements' divisions and roots at once. Each is the same operations in the same
order as the scalar code it replaces (the same bits).

The geometry pass (``geometry_block``) likewise, on the corner coordinates and velocities that
``gather_block`` copied out of the node arrays (LLVM does not vectorise the gather itself). The work
arrays are flat, row r of the block at r * _ST_BLOCK: with a constant row stride LLVM sees that the rows
do not overlap (through a 2D array's runtime row stride it did not vectorise).

One gas:

``lagrange._mixture_pressure`` for one material whose EOS is ``EOS_IDEAL_GAS`` (p = (gamma - 1) rho e)
or ``EOS_STIFFENED_GAS`` (p = (gamma - 1) rho e - gamma p_inf; Harlow & Amsden 1971, the ideal gas at
p_inf = 0), ``materials.kernels.eos_state`` with r = rho / rho0 and E = rho0 e per reference volume:
p = (gamma - 1) r E - gamma p_inf, dp/dmu = (gamma - 1) E, dp/dE = (gamma - 1) r, c^2 = (dp/dmu +
p dp/dE / r^2) / rho0. The same operations in the same order as the general path (the same bits),
without its branches: every element's state is computed and the void / absent cases are selected
afterwards, and the kernel uses numpy's error model (a division by zero gives inf or nan, which the
selects then discard, instead of a Python exception), so the loop body is straight-line code and the
divisions and square roots of several elements go through the vector units together.
"""
from __future__ import annotations

import math

from numba import njit

from ..fem.tables import QUAD_GAMMA
from ..materials.ids import EOS_IDEAL_GAS, EOS_STIFFENED_GAS
from ..materials.slots import Q_IG_GAMMA, Q_SG_GAMMA, Q_SG_PINF

# rows of the plane force kernel's per-run work array st (_ST_ROWS, _ST_BLOCK): one column per element of a block
_ST_P, _ST_C, _ST_M = 0, 1, 2  # mixture pressure, sound speed, mass (``_mixture_pressure``)
# area, tr d, largest corner |v|^2, the longest edge's squared length (the length A / sqrt of it: viscosity_block)
_ST_AREA, _ST_TRACE, _ST_VMAX2, _ST_LONG2 = 3, 4, 5, 6
_ST_GX, _ST_HQ, _ST_B = 7, 9, 11  # Gamma . x (2), hourglass rates gamma . v (2), mean gradient b_x (4) then b_y (4)
_ST_S, _ST_RHO, _ST_COEF = 19, 20, 21  # A (p + q), rho_e, hourglass coefficient (``viscosity_block``)
_ST_ROWS = 22
_ST_BLOCK = 128  # elements per block: st of 22 x 128 doubles (22 kB) and the corners' 16 x 128 (16 kB)
# rows of the corner array (16 rows of _ST_BLOCK, flat): x, y, u, w of corners 0..3
_CX_X, _CX_Y, _CX_U, _CX_W = 0, 4, 8, 12


@njit(cache=True, inline="always")
def gas_material(mat_eos, mat_q, mat_rho0, m):
    """(True, gamma - 1, gamma p_inf) when material m is an ideal or stiffened gas with rho0 > 0 (``gas_block``
    computes its state); else (False, 0, 0)."""
    if mat_rho0[m] <= 0.0:
        return False, 0.0, 0.0
    eos = mat_eos[m]
    if eos == EOS_IDEAL_GAS:
        return True, mat_q[m, Q_IG_GAMMA] - 1.0, 0.0
    if eos == EOS_STIFFENED_GAS:
        return True, mat_q[m, Q_SG_GAMMA] - 1.0, mat_q[m, Q_SG_GAMMA] * mat_q[m, Q_SG_PINF]
    return False, 0.0, 0.0


@njit(cache=True)
def one_gas(mat_eos, mat_q, mat_rho0):
    """(True, gamma - 1, gamma p_inf) when the mesh holds one material, an ideal or stiffened gas with
    rho0 > 0 (``gas_block`` applies, ``gas_material``); else (False, 0, 0). The ideal gas is the stiffened one at
    p_inf = 0: (gamma - 1) r E - 0.0 is (gamma - 1) r E to the bit."""
    if mat_eos.shape[0] != 1:
        return False, 0.0, 0.0
    return gas_material(mat_eos, mat_q, mat_rho0, 0)


@njit(cache=True, error_model="numpy")
def gas_block(nb, vol_m, mass_m, ener_m, e_lag, gm1, gpinf, rho0, phi_eps, rho_void, pscale,
              pressure_cutoff, pres_m, bulk_m, st_p, st_c, st_m):
    """``lagrange._mixture_pressure`` of the nb elements of a block, one gas (``one_gas``): writes pres_m,
    bulk_m and the block's mixture pressure, sound speed and mass into st_p, st_c, st_m [0, nb).
    The per-element arrays come as the block's slices of the flat (E,) views of the (E, 1) state, indexed
    by the loop counter: with the column index of the (E, N) form LLVM did not vectorise the loop, and
    with the element number start + i (of unknown sign to numba, so wrapped around where negative) it
    stored through scatters.

    As the general path: present when V > phi_eps V and M > rho_void rho0 V; then rho = M / V, the EOS at
    r = rho / rho0 and E = rho0 (E_stored / M + e_lag), c = sqrt(c^2) (0 where c^2 <= 0; p = c = 0 where
    rho <= 0), p = max(p pscale, cut-off); pres = p, bulk = (rho c) c, p_mix = 0 + (V / V) p, c_e =
    sqrt((0 + (M c) c) / (0 + M)), all zero where absent. (The general path's sums start from 0.0: kept, as
    0.0 + x differs from x when x is -0.0.) No Gruneisen cavitation branch: a gas has none.
    """
    for i in range(nb):
        vol = vol_m[i]
        mass = mass_m[i]
        vtot = 0.0 + vol
        mtot = 0.0 + mass
        present, p, c, rho = _gas_in_mixture(vol, mass, ener_m[i], e_lag[i], pscale[i], vtot, gm1, gpinf, rho0,
                                             phi_eps, rho_void, pressure_cutoff)
        p_in = 0.0 + vol / vtot * p
        mc2 = 0.0 + mass * c * c
        m_in = 0.0 + mass
        pres_m[i] = p if present else 0.0
        bulk_m[i] = rho * c * c if present else 0.0
        st_p[i] = p_in if present else 0.0
        m_in = m_in if present else 0.0
        st_c[i] = math.sqrt((mc2 if present else 0.0) / m_in) if m_in > 0.0 else 0.0
        st_m[i] = mtot


@njit(cache=True, inline="always")
def _gas_in_mixture(vol, mass, ener, lag, ps, vtot, gm1, gpinf, rho0, phi_eps, rho_void, pressure_cutoff):
    """One gas's part of ``lagrange._mixture_pressure`` in an element of total volume vtot, branch-free (as
    ``gas_block``): (present, p, c, rho), p and c to be used only where present."""
    present = vol > phi_eps * vtot and mass > rho_void * rho0 * vol
    rho = mass / vol
    r = rho / rho0
    big_e = rho0 * (ener / mass + lag)
    p = gm1 * r * big_e - gpinf
    dpdmu = gm1 * big_e
    dpde = gm1 * r
    c2 = (dpdmu + p * dpde / (r * r)) / rho0
    c = math.sqrt(c2) if c2 > 0.0 else 0.0
    if rho <= 0.0:
        p = 0.0
        c = 0.0
    p = max(p * ps, pressure_cutoff)
    return present, p, c, rho


@njit(cache=True, error_model="numpy")
def two_gas_block(nb, vol2, mass2, ener2, lag2, pscale2, gm1_0, gpinf_0, rho0_0, gm1_1, gpinf_1, rho0_1, phi_eps,
                  rho_void, pressure_cutoff, pres2, bulk2, st_p, st_c, st_m):
    """``lagrange._mixture_pressure`` of the nb elements of a block where the mesh holds two materials, both ideal
    or stiffened gases (``gas_material``), pure or mixed cells alike: the (E, 2) arrays come as the block's slices
    of their flat views (element i's materials at 2 i and 2 i + 1: a constant stride, interleaved loads), and both
    materials' states are computed for every element (``_gas_in_mixture``), the absent one's discarded by selects.

    The general path's operations in its order: vtot = (0.0 + V_0) + V_1, M likewise; p_mix = (0.0 + [V_0 / vtot
    p_0]) + [V_1 / vtot p_1], the bracket 0.0 where the material is absent (the general loop skips it: a sum started
    at +0.0 is never -0.0, so adding +0.0 changes no bit); sum M c^2 and the present mass likewise; c_e =
    sqrt(sum M c^2 / M_present), 0 without mass; pres, bulk = p, rho c c where present, else 0."""
    for i in range(nb):
        a = 2 * i
        b = a + 1
        v0 = vol2[a]
        v1 = vol2[b]
        m0 = mass2[a]
        m1 = mass2[b]
        vtot = 0.0 + v0 + v1
        mtot = 0.0 + m0 + m1
        in0, p0, c0, rho_0 = _gas_in_mixture(v0, m0, ener2[a], lag2[a], pscale2[a], vtot, gm1_0, gpinf_0, rho0_0,
                                             phi_eps, rho_void, pressure_cutoff)
        in1, p1, c1, rho_1 = _gas_in_mixture(v1, m1, ener2[b], lag2[b], pscale2[b], vtot, gm1_1, gpinf_1, rho0_1,
                                             phi_eps, rho_void, pressure_cutoff)
        pres2[a] = p0 if in0 else 0.0
        bulk2[a] = rho_0 * c0 * c0 if in0 else 0.0
        pres2[b] = p1 if in1 else 0.0
        bulk2[b] = rho_1 * c1 * c1 if in1 else 0.0
        p_mix = 0.0 + (v0 / vtot * p0 if in0 else 0.0)
        p_mix = p_mix + (v1 / vtot * p1 if in1 else 0.0)
        mc2 = 0.0 + (m0 * c0 * c0 if in0 else 0.0)
        mc2 = mc2 + (m1 * c1 * c1 if in1 else 0.0)
        m_in = 0.0 + (m0 if in0 else 0.0)
        m_in = m_in + (m1 if in1 else 0.0)
        st_p[i] = p_mix
        st_c[i] = math.sqrt(mc2 / m_in) if m_in > 0.0 else 0.0
        st_m[i] = mtot


@njit(cache=True, error_model="numpy")
def viscosity_block(nb, s_p, s_c, s_m, s_area, s_trace, s_vmax2, s_long2, q1, q2, qhg, q_elem, dt_elem,
                    s_s, s_rho, s_coef):
    """``lagrange.viscosity_and_step`` and the force factors of the nb elements of a block (q_elem, dt_elem:
    the block's slices, as in ``gas_block``) from their work rows (mixture pressure s_p, sound speed s_c, mass s_m, area, tr d, largest corner |v|^2, the longest
    edge's squared length).

    l = A / sqrt(longest^2) (``fem.geometry.quad4_char_length`` with one square root: the rounded root is monotone); rho_e = M / A; q = ``fem.geometry.bulk_viscosity`` (rho l (Q1^2 l tr d^2 - Q2 c tr d), 0 where tr d >= 0)
    into q_elem; dt_elem = ``fem.geometry.stable_dt`` with c_eff = c + |v|_max (l / (Q + sqrt(Q^2 + c_eff^2)),
    Q = Q2 c_eff + Q1^2 l |tr d| in compression, else 0; inf where c_eff <= 0 or the denominator is not
    positive); s_s = A (p + q), s_rho = rho_e, s_coef = qhg rho_e c sqrt(A) / 4 (the hourglass coefficient,
    used where qhg > 0 and rho_e > 0). Operation order as the scalar helpers'.
    """
    for i in range(nb):
        area = s_area[i]
        c = s_c[i]
        length = area / math.sqrt(s_long2[i])
        trace_d = s_trace[i]
        rho_e = s_m[i] / area
        q = rho_e * length * (q1 * q1 * length * trace_d * trace_d - q2 * c * trace_d)
        q = 0.0 if trace_d >= 0.0 else q
        q_elem[i] = q
        c_eff = c + math.sqrt(s_vmax2[i])
        qq = q2 * c_eff + q1 * q1 * length * (-trace_d) if trace_d < 0.0 else 0.0
        den = qq + math.sqrt(qq * qq + c_eff * c_eff)
        dt_elem[i] = length / den if c_eff > 0.0 and den > 0.0 else math.inf
        s_s[i] = area * (s_p[i] + q)
        s_rho[i] = rho_e
        s_coef[i] = 0.25 * qhg * rho_e * c * math.sqrt(area)


@njit(cache=True, inline="always")
def gather_block(conn, start, nb, x, v, cx):
    """Corner coordinates and velocities of the nb quads from element start into the corner rows of cx."""
    for i in range(nb):
        e = start + i
        for a in range(4):
            n = conn[e, a]
            cx[(_CX_X + a) * _ST_BLOCK + i] = x[n, 0]
            cx[(_CX_Y + a) * _ST_BLOCK + i] = x[n, 1]
            cx[(_CX_U + a) * _ST_BLOCK + i] = v[n, 0]
            cx[(_CX_W + a) * _ST_BLOCK + i] = v[n, 1]


@njit(cache=True, error_model="numpy")
def geometry_block(nb, cx, st):
    """The geometry of the nb quads of a block from their corners (cx, ``gather_block``) into st (flat).

    ``fem.geometry.quad4_gradient`` (b_xa = (y_{a+1} - y_{a-1}) / 2A, b_ya = (x_{a-1} - x_{a+1}) / 2A, 0
    where A <= 0), the velocity divergence tr d = sum_a v_a . b_a, the largest corner |v|^2, the largest
    squared edge length (the characteristic length A / longest edge) and the hourglass rates of Flanagan & Belytschko
    (1981) (Gamma . x and (gamma . v) per component, gamma_a = Gamma_a - (Gamma . x) b_a), in the scalar code's order.
    """
    B = _ST_BLOCK
    for i in range(nb):
        x0, x1, x2, x3 = cx[(_CX_X + 0) * B + i], cx[(_CX_X + 1) * B + i], cx[(_CX_X + 2) * B + i], cx[(_CX_X + 3) * B + i]
        y0, y1, y2, y3 = cx[(_CX_Y + 0) * B + i], cx[(_CX_Y + 1) * B + i], cx[(_CX_Y + 2) * B + i], cx[(_CX_Y + 3) * B + i]
        u0, u1, u2, u3 = cx[(_CX_U + 0) * B + i], cx[(_CX_U + 1) * B + i], cx[(_CX_U + 2) * B + i], cx[(_CX_U + 3) * B + i]
        w0, w1, w2, w3 = cx[(_CX_W + 0) * B + i], cx[(_CX_W + 1) * B + i], cx[(_CX_W + 2) * B + i], cx[(_CX_W + 3) * B + i]
        vmax2 = max(0.0, u0 * u0 + w0 * w0)
        vmax2 = max(vmax2, u1 * u1 + w1 * w1)
        vmax2 = max(vmax2, u2 * u2 + w2 * w2)
        vmax2 = max(vmax2, u3 * u3 + w3 * w3)
        area = 0.5 * ((x2 - x0) * (y3 - y1) + (x1 - x3) * (y2 - y0))
        inv = 0.5 / area if area > 0.0 else 0.0
        bx0, by0 = (y1 - y3) * inv, (x3 - x1) * inv
        bx1, by1 = (y2 - y0) * inv, (x0 - x2) * inv
        bx2, by2 = (y3 - y1) * inv, (x1 - x3) * inv
        bx3, by3 = (y0 - y2) * inv, (x2 - x0) * inv
        trace_d = 0.0
        trace_d += u0 * bx0 + w0 * by0
        trace_d += u1 * bx1 + w1 * by1
        trace_d += u2 * bx2 + w2 * by2
        trace_d += u3 * bx3 + w3 * by3
        dx, dy = x1 - x0, y1 - y0
        longest2 = max(0.0, dx * dx + dy * dy)
        dx, dy = x2 - x1, y2 - y1
        longest2 = max(longest2, dx * dx + dy * dy)
        dx, dy = x3 - x2, y3 - y2
        longest2 = max(longest2, dx * dx + dy * dy)
        dx, dy = x0 - x3, y0 - y3
        longest2 = max(longest2, dx * dx + dy * dy)
        gx0 = 0.0
        gx1 = 0.0
        gx0 += QUAD_GAMMA[0] * x0
        gx1 += QUAD_GAMMA[0] * y0
        gx0 += QUAD_GAMMA[1] * x1
        gx1 += QUAD_GAMMA[1] * y1
        gx0 += QUAD_GAMMA[2] * x2
        gx1 += QUAD_GAMMA[2] * y2
        gx0 += QUAD_GAMMA[3] * x3
        gx1 += QUAD_GAMMA[3] * y3
        g0 = QUAD_GAMMA[0] - gx0 * bx0 - gx1 * by0
        g1 = QUAD_GAMMA[1] - gx0 * bx1 - gx1 * by1
        g2 = QUAD_GAMMA[2] - gx0 * bx2 - gx1 * by2
        g3 = QUAD_GAMMA[3] - gx0 * bx3 - gx1 * by3
        hq0 = 0.0
        hq1 = 0.0
        hq0 += g0 * u0
        hq1 += g0 * w0
        hq0 += g1 * u1
        hq1 += g1 * w1
        hq0 += g2 * u2
        hq1 += g2 * w2
        hq0 += g3 * u3
        hq1 += g3 * w3
        st[_ST_AREA * B + i] = area
        st[_ST_TRACE * B + i] = trace_d
        st[_ST_VMAX2 * B + i] = vmax2
        st[_ST_LONG2 * B + i] = longest2
        st[_ST_GX * B + i] = gx0
        st[(_ST_GX + 1) * B + i] = gx1
        st[_ST_HQ * B + i] = hq0
        st[(_ST_HQ + 1) * B + i] = hq1
        st[_ST_B * B + i] = bx0
        st[(_ST_B + 1) * B + i] = bx1
        st[(_ST_B + 2) * B + i] = bx2
        st[(_ST_B + 3) * B + i] = bx3
        st[(_ST_B + 4) * B + i] = by0
        st[(_ST_B + 5) * B + i] = by1
        st[(_ST_B + 6) * B + i] = by2
        st[(_ST_B + 7) * B + i] = by3
