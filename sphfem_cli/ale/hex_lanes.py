"""ALE hex8 force kernel (``lagrange.lagrange_forces_3d``): its passes over a block of elements, written so
that LLVM vectorises them (issue 17), as ``force_lanes`` does for the plane quad4 kernel.

Each block of _HX_BLOCK elements goes through: the material state (``force_lanes.gas_block`` for one ideal or
stiffened gas, else ``lagrange._mixture_pressure`` per element), the corner gather (``gather_hex_block``: the
eight corners' coordinates and velocities out of the node arrays into flat rows, one element per column), the
geometry (``hex_geometry_block``: volume, mean gradient, velocity divergence, largest corner speed, largest face
area), the viscosity and step (``hex_viscosity_block``), the hourglass coefficient (the kernel: its power
V^(2/3), which LLVM does not vectorise without a vector math library), the forces and hourglass
(``hex_force_block``), and their copy into the (E, 8, 3) force array (the kernel). The geometry, viscosity and force passes are straight-line loops over the block's columns (numpy's error
model: a division by zero gives inf or nan that the selects discard, instead of a Python exception): the
vector units take eight elements at once. Every value is the scalar code's operations in its order (the
same bits): ``fem.geometry.hex8_gradient`` through its scalar body ``hex8_dv``, ``fem.geometry.hex8_char_length``,
``lagrange.viscosity_and_step``.

The work arrays are flat, row r of the block at r * _HX_BLOCK (a constant row stride: LLVM then sees that
rows do not overlap; through a 2D array's runtime stride it did not vectorise, ``force_lanes``).
"""
from __future__ import annotations

import math

from numba import njit

from ..fem.geometry import hex8_dv, hex8_volume_origin

_HX_BLOCK = 64  # elements per block: corners 48 x 64 doubles (24 kB), work rows 35 x 64 (18 kB), forces 24 x 64
# rows of the corner array: x, y, z, u, v, w of corners 0..7
_HC_X, _HC_Y, _HC_Z, _HC_U, _HC_V, _HC_W = 0, 8, 16, 24, 32, 40
_HC_ROWS = 48
# rows of the work array: mixture pressure, sound speed, mass (the material state pass); volume, tr d, the
# largest corner |v|^2, the largest squared face-diagonal cross product (hex8_char_length); the mean gradient
# b_x (8), b_y (8), b_z (8); V (p + q) and rho_e (``hex_viscosity_block``); the hourglass coefficient
# qhg rho_e c V^(2/3) / 4 and 1.0 where the hourglass applies (qhg > 0 and rho_e > 0), else 0.0 (the kernel)
_HX_P, _HX_C, _HX_M, _HX_VOL, _HX_TRACE, _HX_VMAX2, _HX_LARGE2, _HX_B, _HX_S, _HX_RHO = 0, 1, 2, 3, 4, 5, 6, 7, 31, 32
_HX_COEF, _HX_HG = 33, 34
_HX_ROWS = 35
_HF_ROWS = 24  # rows of the forces (``hex_force_block``): corner a, component k at row 3 a + k


@njit(cache=True, inline="always")
def gather_hex_block(conn, start, nb, x, v, cx):
    """Corner coordinates and velocities of the nb hex8 from element start into the corner rows of cx."""
    B = _HX_BLOCK
    for i in range(nb):
        e = start + i
        for a in range(8):
            n = conn[e, a]
            cx[(_HC_X + a) * B + i] = x[n, 0]
            cx[(_HC_Y + a) * B + i] = x[n, 1]
            cx[(_HC_Z + a) * B + i] = x[n, 2]
            cx[(_HC_U + a) * B + i] = v[n, 0]
            cx[(_HC_V + a) * B + i] = v[n, 1]
            cx[(_HC_W + a) * B + i] = v[n, 2]


@njit(cache=True, inline="always")
def _cross2(px, py, pz, qx, qy, qz):
    """|p x q|^2, the components in ``hex8_char_length``'s order."""
    cx = py * qz - pz * qy
    cy = pz * qx - px * qz
    cz = px * qy - py * qx
    return cx * cx + cy * cy + cz * cz


@njit(cache=True, error_model="numpy")
def hex_geometry_block(nb, cx, st):
    """The geometry of the nb hex8 of a block from their corners (cx, ``gather_hex_block``) into st (flat).

    V and b = (1/V) dV/dx_I (``fem.geometry.hex8_gradient``: b = 0 unless V > 0), tr d = sum_I v_I . b_I,
    the largest corner |v|^2, and the largest |(x_c - x_a) x (x_d - x_b)|^2 over the faces (a, b, c, d) of
    ``HEX_FACES`` (``fem.geometry.hex8_char_length``: l = V / (sqrt of it / 2)), each in the scalar code's order.
    """
    B = _HX_BLOCK
    for i in range(nb):
        x0, x1, x2, x3 = cx[(_HC_X + 0) * B + i], cx[(_HC_X + 1) * B + i], cx[(_HC_X + 2) * B + i], cx[(_HC_X + 3) * B + i]
        x4, x5, x6, x7 = cx[(_HC_X + 4) * B + i], cx[(_HC_X + 5) * B + i], cx[(_HC_X + 6) * B + i], cx[(_HC_X + 7) * B + i]
        y0, y1, y2, y3 = cx[(_HC_Y + 0) * B + i], cx[(_HC_Y + 1) * B + i], cx[(_HC_Y + 2) * B + i], cx[(_HC_Y + 3) * B + i]
        y4, y5, y6, y7 = cx[(_HC_Y + 4) * B + i], cx[(_HC_Y + 5) * B + i], cx[(_HC_Y + 6) * B + i], cx[(_HC_Y + 7) * B + i]
        z0, z1, z2, z3 = cx[(_HC_Z + 0) * B + i], cx[(_HC_Z + 1) * B + i], cx[(_HC_Z + 2) * B + i], cx[(_HC_Z + 3) * B + i]
        z4, z5, z6, z7 = cx[(_HC_Z + 4) * B + i], cx[(_HC_Z + 5) * B + i], cx[(_HC_Z + 6) * B + i], cx[(_HC_Z + 7) * B + i]
        (bx0, bx1, bx2, bx3, bx4, bx5, bx6, bx7, by0, by1, by2, by3, by4, by5, by6, by7,
         bz0, bz1, bz2, bz3, bz4, bz5, bz6, bz7) = hex8_dv(x0, y0, z0, x1, y1, z1, x2, y2, z2, x3, y3, z3,
                                                            x4, y4, z4, x5, y5, z5, x6, y6, z6, x7, y7, z7)
        volume = (0.0 + x0 * bx0 + x1 * bx1 + x2 * bx2 + x3 * bx3
                  + x4 * bx4 + x5 * bx5 + x6 * bx6 + x7 * bx7)
        inv = 1.0 / volume if volume > 0.0 else 0.0
        bx0, bx1, bx2, bx3, bx4, bx5, bx6, bx7 = bx0 * inv, bx1 * inv, bx2 * inv, bx3 * inv, bx4 * inv, bx5 * inv, \
            bx6 * inv, bx7 * inv
        by0, by1, by2, by3, by4, by5, by6, by7 = by0 * inv, by1 * inv, by2 * inv, by3 * inv, by4 * inv, by5 * inv, \
            by6 * inv, by7 * inv
        bz0, bz1, bz2, bz3, bz4, bz5, bz6, bz7 = bz0 * inv, bz1 * inv, bz2 * inv, bz3 * inv, bz4 * inv, bz5 * inv, \
            bz6 * inv, bz7 * inv
        vmax2 = 0.0
        trace_d = 0.0
        u, w, s = cx[(_HC_U + 0) * B + i], cx[(_HC_V + 0) * B + i], cx[(_HC_W + 0) * B + i]
        vmax2 = max(vmax2, u * u + w * w + s * s)
        trace_d += u * bx0 + w * by0 + s * bz0
        u, w, s = cx[(_HC_U + 1) * B + i], cx[(_HC_V + 1) * B + i], cx[(_HC_W + 1) * B + i]
        vmax2 = max(vmax2, u * u + w * w + s * s)
        trace_d += u * bx1 + w * by1 + s * bz1
        u, w, s = cx[(_HC_U + 2) * B + i], cx[(_HC_V + 2) * B + i], cx[(_HC_W + 2) * B + i]
        vmax2 = max(vmax2, u * u + w * w + s * s)
        trace_d += u * bx2 + w * by2 + s * bz2
        u, w, s = cx[(_HC_U + 3) * B + i], cx[(_HC_V + 3) * B + i], cx[(_HC_W + 3) * B + i]
        vmax2 = max(vmax2, u * u + w * w + s * s)
        trace_d += u * bx3 + w * by3 + s * bz3
        u, w, s = cx[(_HC_U + 4) * B + i], cx[(_HC_V + 4) * B + i], cx[(_HC_W + 4) * B + i]
        vmax2 = max(vmax2, u * u + w * w + s * s)
        trace_d += u * bx4 + w * by4 + s * bz4
        u, w, s = cx[(_HC_U + 5) * B + i], cx[(_HC_V + 5) * B + i], cx[(_HC_W + 5) * B + i]
        vmax2 = max(vmax2, u * u + w * w + s * s)
        trace_d += u * bx5 + w * by5 + s * bz5
        u, w, s = cx[(_HC_U + 6) * B + i], cx[(_HC_V + 6) * B + i], cx[(_HC_W + 6) * B + i]
        vmax2 = max(vmax2, u * u + w * w + s * s)
        trace_d += u * bx6 + w * by6 + s * bz6
        u, w, s = cx[(_HC_U + 7) * B + i], cx[(_HC_V + 7) * B + i], cx[(_HC_W + 7) * B + i]
        vmax2 = max(vmax2, u * u + w * w + s * s)
        trace_d += u * bx7 + w * by7 + s * bz7
        # HEX_FACES (a, b, c, d): p = x_c - x_a, q = x_d - x_b
        large2 = 0.0
        large2 = max(large2, _cross2(x2 - x0, y2 - y0, z2 - z0, x1 - x3, y1 - y3, z1 - z3))  # 0 3 2 1
        large2 = max(large2, _cross2(x6 - x4, y6 - y4, z6 - z4, x7 - x5, y7 - y5, z7 - z5))  # 4 5 6 7
        large2 = max(large2, _cross2(x5 - x0, y5 - y0, z5 - z0, x4 - x1, y4 - y1, z4 - z1))  # 0 1 5 4
        large2 = max(large2, _cross2(x6 - x1, y6 - y1, z6 - z1, x5 - x2, y5 - y2, z5 - z2))  # 1 2 6 5
        large2 = max(large2, _cross2(x7 - x2, y7 - y2, z7 - z2, x6 - x3, y6 - y3, z6 - z3))  # 2 3 7 6
        large2 = max(large2, _cross2(x4 - x3, y4 - y3, z4 - z3, x7 - x0, y7 - y0, z7 - z0))  # 3 0 4 7
        st[_HX_VOL * B + i] = volume
        st[_HX_TRACE * B + i] = trace_d
        st[_HX_VMAX2 * B + i] = vmax2
        st[_HX_LARGE2 * B + i] = large2
        st[(_HX_B + 0) * B + i] = bx0
        st[(_HX_B + 1) * B + i] = bx1
        st[(_HX_B + 2) * B + i] = bx2
        st[(_HX_B + 3) * B + i] = bx3
        st[(_HX_B + 4) * B + i] = bx4
        st[(_HX_B + 5) * B + i] = bx5
        st[(_HX_B + 6) * B + i] = bx6
        st[(_HX_B + 7) * B + i] = bx7
        st[(_HX_B + 8) * B + i] = by0
        st[(_HX_B + 9) * B + i] = by1
        st[(_HX_B + 10) * B + i] = by2
        st[(_HX_B + 11) * B + i] = by3
        st[(_HX_B + 12) * B + i] = by4
        st[(_HX_B + 13) * B + i] = by5
        st[(_HX_B + 14) * B + i] = by6
        st[(_HX_B + 15) * B + i] = by7
        st[(_HX_B + 16) * B + i] = bz0
        st[(_HX_B + 17) * B + i] = bz1
        st[(_HX_B + 18) * B + i] = bz2
        st[(_HX_B + 19) * B + i] = bz3
        st[(_HX_B + 20) * B + i] = bz4
        st[(_HX_B + 21) * B + i] = bz5
        st[(_HX_B + 22) * B + i] = bz6
        st[(_HX_B + 23) * B + i] = bz7


@njit(cache=True, error_model="numpy")
def hex_viscosity_block(nb, st, q1, q2, q_elem, dt_elem):
    """``lagrange.viscosity_and_step`` of the nb hex8 of a block from their work rows (st, flat), and the force
    factors: l = V / (sqrt(largest^2) / 2) (``fem.geometry.hex8_char_length``), rho_e = M / V, q (bulk
    viscosity, 0 where tr d >= 0) into q_elem, the stable step with c_eff = c + |v|_max into dt_elem (inf where
    c_eff <= 0 or the denominator is not positive), V (p + q) and rho_e into their rows. q_elem, dt_elem: the
    block's slices. The operations of the scalar helpers in their order (``force_lanes.viscosity_block``).
    """
    B = _HX_BLOCK
    for i in range(nb):
        vol = st[_HX_VOL * B + i]
        c = st[_HX_C * B + i]
        length = vol / (0.5 * math.sqrt(st[_HX_LARGE2 * B + i]))
        trace_d = st[_HX_TRACE * B + i]
        rho_e = st[_HX_M * B + i] / vol
        q = rho_e * length * (q1 * q1 * length * trace_d * trace_d - q2 * c * trace_d)
        q = 0.0 if trace_d >= 0.0 else q
        q_elem[i] = q
        c_eff = c + math.sqrt(st[_HX_VMAX2 * B + i])
        qq = q2 * c_eff + q1 * q1 * length * (-trace_d) if trace_d < 0.0 else 0.0
        den = qq + math.sqrt(qq * qq + c_eff * c_eff)
        dt_elem[i] = length / den if c_eff > 0.0 and den > 0.0 else math.inf
        st[_HX_S * B + i] = vol * (st[_HX_P * B + i] + q)
        st[_HX_RHO * B + i] = rho_e


@njit(cache=True, error_model="numpy")
def hex_force_block(nb, cx, st, fo):
    """The forces of the nb hex8 of a block into the 24 rows of fo (corner a, component k at row 3 a + k):
    f_a = V (p + q) b_a, then where the hourglass applies (row _HX_HG), for each of the four modes gamma_j =
    Gamma_j - (Gamma_j . x) b (Flanagan & Belytschko 1981), f_a -= (c_hg (gamma_j . v)) gamma_ja, c_hg the
    row _HX_COEF. ``lagrange_forces_3d``'s scalar loop written out mode by mode (Gamma_j = +-1: Gamma . x as
    sums and differences of the corners from 0.0, in corner order), the same operations in the same order.
    """
    B = _HX_BLOCK
    for i in range(nb):
        x0, x1, x2, x3 = cx[(_HC_X + 0) * B + i], cx[(_HC_X + 1) * B + i], cx[(_HC_X + 2) * B + i], cx[(_HC_X + 3) * B + i]
        x4, x5, x6, x7 = cx[(_HC_X + 4) * B + i], cx[(_HC_X + 5) * B + i], cx[(_HC_X + 6) * B + i], cx[(_HC_X + 7) * B + i]
        y0, y1, y2, y3 = cx[(_HC_Y + 0) * B + i], cx[(_HC_Y + 1) * B + i], cx[(_HC_Y + 2) * B + i], cx[(_HC_Y + 3) * B + i]
        y4, y5, y6, y7 = cx[(_HC_Y + 4) * B + i], cx[(_HC_Y + 5) * B + i], cx[(_HC_Y + 6) * B + i], cx[(_HC_Y + 7) * B + i]
        z0, z1, z2, z3 = cx[(_HC_Z + 0) * B + i], cx[(_HC_Z + 1) * B + i], cx[(_HC_Z + 2) * B + i], cx[(_HC_Z + 3) * B + i]
        z4, z5, z6, z7 = cx[(_HC_Z + 4) * B + i], cx[(_HC_Z + 5) * B + i], cx[(_HC_Z + 6) * B + i], cx[(_HC_Z + 7) * B + i]
        u0, u1, u2, u3 = cx[(_HC_U + 0) * B + i], cx[(_HC_U + 1) * B + i], cx[(_HC_U + 2) * B + i], cx[(_HC_U + 3) * B + i]
        u4, u5, u6, u7 = cx[(_HC_U + 4) * B + i], cx[(_HC_U + 5) * B + i], cx[(_HC_U + 6) * B + i], cx[(_HC_U + 7) * B + i]
        v0, v1, v2, v3 = cx[(_HC_V + 0) * B + i], cx[(_HC_V + 1) * B + i], cx[(_HC_V + 2) * B + i], cx[(_HC_V + 3) * B + i]
        v4, v5, v6, v7 = cx[(_HC_V + 4) * B + i], cx[(_HC_V + 5) * B + i], cx[(_HC_V + 6) * B + i], cx[(_HC_V + 7) * B + i]
        w0, w1, w2, w3 = cx[(_HC_W + 0) * B + i], cx[(_HC_W + 1) * B + i], cx[(_HC_W + 2) * B + i], cx[(_HC_W + 3) * B + i]
        w4, w5, w6, w7 = cx[(_HC_W + 4) * B + i], cx[(_HC_W + 5) * B + i], cx[(_HC_W + 6) * B + i], cx[(_HC_W + 7) * B + i]
        bx0, bx1, bx2, bx3 = st[(_HX_B + 0) * B + i], st[(_HX_B + 1) * B + i], st[(_HX_B + 2) * B + i], st[(_HX_B + 3) * B + i]
        bx4, bx5, bx6, bx7 = st[(_HX_B + 4) * B + i], st[(_HX_B + 5) * B + i], st[(_HX_B + 6) * B + i], st[(_HX_B + 7) * B + i]
        by0, by1, by2, by3 = st[(_HX_B + 8) * B + i], st[(_HX_B + 9) * B + i], st[(_HX_B + 10) * B + i], st[(_HX_B + 11) * B + i]
        by4, by5, by6, by7 = st[(_HX_B + 12) * B + i], st[(_HX_B + 13) * B + i], st[(_HX_B + 14) * B + i], st[(_HX_B + 15) * B + i]
        bz0, bz1, bz2, bz3 = st[(_HX_B + 16) * B + i], st[(_HX_B + 17) * B + i], st[(_HX_B + 18) * B + i], st[(_HX_B + 19) * B + i]
        bz4, bz5, bz6, bz7 = st[(_HX_B + 20) * B + i], st[(_HX_B + 21) * B + i], st[(_HX_B + 22) * B + i], st[(_HX_B + 23) * B + i]
        s = st[_HX_S * B + i]
        coef = st[_HX_COEF * B + i]
        f0x, f0y, f0z = s * bx0, s * by0, s * bz0
        f1x, f1y, f1z = s * bx1, s * by1, s * bz1
        f2x, f2y, f2z = s * bx2, s * by2, s * bz2
        f3x, f3y, f3z = s * bx3, s * by3, s * bz3
        f4x, f4y, f4z = s * bx4, s * by4, s * bz4
        f5x, f5y, f5z = s * bx5, s * by5, s * bz5
        f6x, f6y, f6z = s * bx6, s * by6, s * bz6
        f7x, f7y, f7z = s * bx7, s * by7, s * bz7
        # mode 0: Gamma = (1, -1, 1, -1, 1, -1, 1, -1)
        g0 = 0.0 + x0 - x1 + x2 - x3 + x4 - x5 + x6 - x7
        g1 = 0.0 + y0 - y1 + y2 - y3 + y4 - y5 + y6 - y7
        g2 = 0.0 + z0 - z1 + z2 - z3 + z4 - z5 + z6 - z7
        q0 = 1.0 - g0 * bx0 - g1 * by0 - g2 * bz0
        q1 = -1.0 - g0 * bx1 - g1 * by1 - g2 * bz1
        q2 = 1.0 - g0 * bx2 - g1 * by2 - g2 * bz2
        q3 = -1.0 - g0 * bx3 - g1 * by3 - g2 * bz3
        q4 = 1.0 - g0 * bx4 - g1 * by4 - g2 * bz4
        q5 = -1.0 - g0 * bx5 - g1 * by5 - g2 * bz5
        q6 = 1.0 - g0 * bx6 - g1 * by6 - g2 * bz6
        q7 = -1.0 - g0 * bx7 - g1 * by7 - g2 * bz7
        h0 = coef * (0.0 + q0 * u0 + q1 * u1 + q2 * u2 + q3 * u3 + q4 * u4 + q5 * u5 + q6 * u6 + q7 * u7)
        h1 = coef * (0.0 + q0 * v0 + q1 * v1 + q2 * v2 + q3 * v3 + q4 * v4 + q5 * v5 + q6 * v6 + q7 * v7)
        h2 = coef * (0.0 + q0 * w0 + q1 * w1 + q2 * w2 + q3 * w3 + q4 * w4 + q5 * w5 + q6 * w6 + q7 * w7)
        h0x, h0y, h0z = f0x - h0 * q0, f0y - h1 * q0, f0z - h2 * q0
        h1x, h1y, h1z = f1x - h0 * q1, f1y - h1 * q1, f1z - h2 * q1
        h2x, h2y, h2z = f2x - h0 * q2, f2y - h1 * q2, f2z - h2 * q2
        h3x, h3y, h3z = f3x - h0 * q3, f3y - h1 * q3, f3z - h2 * q3
        h4x, h4y, h4z = f4x - h0 * q4, f4y - h1 * q4, f4z - h2 * q4
        h5x, h5y, h5z = f5x - h0 * q5, f5y - h1 * q5, f5z - h2 * q5
        h6x, h6y, h6z = f6x - h0 * q6, f6y - h1 * q6, f6z - h2 * q6
        h7x, h7y, h7z = f7x - h0 * q7, f7y - h1 * q7, f7z - h2 * q7
        # mode 1: Gamma = (1, 1, -1, -1, -1, -1, 1, 1)
        g0 = 0.0 + x0 + x1 - x2 - x3 - x4 - x5 + x6 + x7
        g1 = 0.0 + y0 + y1 - y2 - y3 - y4 - y5 + y6 + y7
        g2 = 0.0 + z0 + z1 - z2 - z3 - z4 - z5 + z6 + z7
        q0 = 1.0 - g0 * bx0 - g1 * by0 - g2 * bz0
        q1 = 1.0 - g0 * bx1 - g1 * by1 - g2 * bz1
        q2 = -1.0 - g0 * bx2 - g1 * by2 - g2 * bz2
        q3 = -1.0 - g0 * bx3 - g1 * by3 - g2 * bz3
        q4 = -1.0 - g0 * bx4 - g1 * by4 - g2 * bz4
        q5 = -1.0 - g0 * bx5 - g1 * by5 - g2 * bz5
        q6 = 1.0 - g0 * bx6 - g1 * by6 - g2 * bz6
        q7 = 1.0 - g0 * bx7 - g1 * by7 - g2 * bz7
        h0 = coef * (0.0 + q0 * u0 + q1 * u1 + q2 * u2 + q3 * u3 + q4 * u4 + q5 * u5 + q6 * u6 + q7 * u7)
        h1 = coef * (0.0 + q0 * v0 + q1 * v1 + q2 * v2 + q3 * v3 + q4 * v4 + q5 * v5 + q6 * v6 + q7 * v7)
        h2 = coef * (0.0 + q0 * w0 + q1 * w1 + q2 * w2 + q3 * w3 + q4 * w4 + q5 * w5 + q6 * w6 + q7 * w7)
        h0x, h0y, h0z = h0x - h0 * q0, h0y - h1 * q0, h0z - h2 * q0
        h1x, h1y, h1z = h1x - h0 * q1, h1y - h1 * q1, h1z - h2 * q1
        h2x, h2y, h2z = h2x - h0 * q2, h2y - h1 * q2, h2z - h2 * q2
        h3x, h3y, h3z = h3x - h0 * q3, h3y - h1 * q3, h3z - h2 * q3
        h4x, h4y, h4z = h4x - h0 * q4, h4y - h1 * q4, h4z - h2 * q4
        h5x, h5y, h5z = h5x - h0 * q5, h5y - h1 * q5, h5z - h2 * q5
        h6x, h6y, h6z = h6x - h0 * q6, h6y - h1 * q6, h6z - h2 * q6
        h7x, h7y, h7z = h7x - h0 * q7, h7y - h1 * q7, h7z - h2 * q7
        # mode 2: Gamma = (1, -1, -1, 1, -1, 1, 1, -1)
        g0 = 0.0 + x0 - x1 - x2 + x3 - x4 + x5 + x6 - x7
        g1 = 0.0 + y0 - y1 - y2 + y3 - y4 + y5 + y6 - y7
        g2 = 0.0 + z0 - z1 - z2 + z3 - z4 + z5 + z6 - z7
        q0 = 1.0 - g0 * bx0 - g1 * by0 - g2 * bz0
        q1 = -1.0 - g0 * bx1 - g1 * by1 - g2 * bz1
        q2 = -1.0 - g0 * bx2 - g1 * by2 - g2 * bz2
        q3 = 1.0 - g0 * bx3 - g1 * by3 - g2 * bz3
        q4 = -1.0 - g0 * bx4 - g1 * by4 - g2 * bz4
        q5 = 1.0 - g0 * bx5 - g1 * by5 - g2 * bz5
        q6 = 1.0 - g0 * bx6 - g1 * by6 - g2 * bz6
        q7 = -1.0 - g0 * bx7 - g1 * by7 - g2 * bz7
        h0 = coef * (0.0 + q0 * u0 + q1 * u1 + q2 * u2 + q3 * u3 + q4 * u4 + q5 * u5 + q6 * u6 + q7 * u7)
        h1 = coef * (0.0 + q0 * v0 + q1 * v1 + q2 * v2 + q3 * v3 + q4 * v4 + q5 * v5 + q6 * v6 + q7 * v7)
        h2 = coef * (0.0 + q0 * w0 + q1 * w1 + q2 * w2 + q3 * w3 + q4 * w4 + q5 * w5 + q6 * w6 + q7 * w7)
        h0x, h0y, h0z = h0x - h0 * q0, h0y - h1 * q0, h0z - h2 * q0
        h1x, h1y, h1z = h1x - h0 * q1, h1y - h1 * q1, h1z - h2 * q1
        h2x, h2y, h2z = h2x - h0 * q2, h2y - h1 * q2, h2z - h2 * q2
        h3x, h3y, h3z = h3x - h0 * q3, h3y - h1 * q3, h3z - h2 * q3
        h4x, h4y, h4z = h4x - h0 * q4, h4y - h1 * q4, h4z - h2 * q4
        h5x, h5y, h5z = h5x - h0 * q5, h5y - h1 * q5, h5z - h2 * q5
        h6x, h6y, h6z = h6x - h0 * q6, h6y - h1 * q6, h6z - h2 * q6
        h7x, h7y, h7z = h7x - h0 * q7, h7y - h1 * q7, h7z - h2 * q7
        # mode 3: Gamma = (-1, 1, -1, 1, 1, -1, 1, -1)
        g0 = 0.0 - x0 + x1 - x2 + x3 + x4 - x5 + x6 - x7
        g1 = 0.0 - y0 + y1 - y2 + y3 + y4 - y5 + y6 - y7
        g2 = 0.0 - z0 + z1 - z2 + z3 + z4 - z5 + z6 - z7
        q0 = -1.0 - g0 * bx0 - g1 * by0 - g2 * bz0
        q1 = 1.0 - g0 * bx1 - g1 * by1 - g2 * bz1
        q2 = -1.0 - g0 * bx2 - g1 * by2 - g2 * bz2
        q3 = 1.0 - g0 * bx3 - g1 * by3 - g2 * bz3
        q4 = 1.0 - g0 * bx4 - g1 * by4 - g2 * bz4
        q5 = -1.0 - g0 * bx5 - g1 * by5 - g2 * bz5
        q6 = 1.0 - g0 * bx6 - g1 * by6 - g2 * bz6
        q7 = -1.0 - g0 * bx7 - g1 * by7 - g2 * bz7
        h0 = coef * (0.0 + q0 * u0 + q1 * u1 + q2 * u2 + q3 * u3 + q4 * u4 + q5 * u5 + q6 * u6 + q7 * u7)
        h1 = coef * (0.0 + q0 * v0 + q1 * v1 + q2 * v2 + q3 * v3 + q4 * v4 + q5 * v5 + q6 * v6 + q7 * v7)
        h2 = coef * (0.0 + q0 * w0 + q1 * w1 + q2 * w2 + q3 * w3 + q4 * w4 + q5 * w5 + q6 * w6 + q7 * w7)
        h0x, h0y, h0z = h0x - h0 * q0, h0y - h1 * q0, h0z - h2 * q0
        h1x, h1y, h1z = h1x - h0 * q1, h1y - h1 * q1, h1z - h2 * q1
        h2x, h2y, h2z = h2x - h0 * q2, h2y - h1 * q2, h2z - h2 * q2
        h3x, h3y, h3z = h3x - h0 * q3, h3y - h1 * q3, h3z - h2 * q3
        h4x, h4y, h4z = h4x - h0 * q4, h4y - h1 * q4, h4z - h2 * q4
        h5x, h5y, h5z = h5x - h0 * q5, h5y - h1 * q5, h5z - h2 * q5
        h6x, h6y, h6z = h6x - h0 * q6, h6y - h1 * q6, h6z - h2 * q6
        h7x, h7y, h7z = h7x - h0 * q7, h7y - h1 * q7, h7z - h2 * q7
        hg = st[_HX_HG * B + i] > 0.0  # the hourglass applies (qhg > 0 and rho_e > 0)
        fo[0 * B + i] = h0x if hg else f0x
        fo[1 * B + i] = h0y if hg else f0y
        fo[2 * B + i] = h0z if hg else f0z
        fo[3 * B + i] = h1x if hg else f1x
        fo[4 * B + i] = h1y if hg else f1y
        fo[5 * B + i] = h1z if hg else f1z
        fo[6 * B + i] = h2x if hg else f2x
        fo[7 * B + i] = h2y if hg else f2y
        fo[8 * B + i] = h2z if hg else f2z
        fo[9 * B + i] = h3x if hg else f3x
        fo[10 * B + i] = h3y if hg else f3y
        fo[11 * B + i] = h3z if hg else f3z
        fo[12 * B + i] = h4x if hg else f4x
        fo[13 * B + i] = h4y if hg else f4y
        fo[14 * B + i] = h4z if hg else f4z
        fo[15 * B + i] = h5x if hg else f5x
        fo[16 * B + i] = h5y if hg else f5y
        fo[17 * B + i] = h5z if hg else f5z
        fo[18 * B + i] = h6x if hg else f6x
        fo[19 * B + i] = h6y if hg else f6y
        fo[20 * B + i] = h6z if hg else f6z
        fo[21 * B + i] = h7x if hg else f7x
        fo[22 * B + i] = h7y if hg else f7y
        fo[23 * B + i] = h7z if hg else f7z


# the corner rows of ``hex_volume_block``: corner a, component k at row 3 a + k (rows of _HV_BLOCK), the volume
# at row _HV_ROWS - 1
_HV_BLOCK = 128
_HV_ROWS = 25


@njit(cache=True, error_model="numpy")
def hex_volume_block(nb, c):
    """Trilinear volumes of nb hexahedra from their corners (rows of c, flat, 8 corners in VTK order), into
    the last row of c: ``fem.geometry.hex8_volume_origin`` of the corners relative to corner 0 (p_a = c_a - c_0),
    the bits of ``hex8_volume``. For the ALE face sweep (``remap.face_fluxes``: the face at x_lag then at
    x_new) and the hex8 Lagrangian volume (``energy.lagrange_energy_3d``). Its sum of 45 terms is one
    chain of dependent additions per hexahedron, which the vector units run for 8 hexahedra at once.
    ``face_fluxes`` at rest per face and sweep (40^3 box, 1 thread): about 150 ns through the table loop of
    ``hex8_volume`` (the pass benchmark), 42-44 written out, 38 with this block (min of 7 calls; the gather of
    the 24 coordinates and the per-face bookkeeping are most of what is left).
    """
    B = _HV_BLOCK
    for i in range(nb):
        x0, y0, z0 = c[0 * B + i], c[1 * B + i], c[2 * B + i]
        c[(_HV_ROWS - 1) * B + i] = hex8_volume_origin(
            c[3 * B + i] - x0, c[4 * B + i] - y0, c[5 * B + i] - z0, c[6 * B + i] - x0, c[7 * B + i] - y0,
            c[8 * B + i] - z0, c[9 * B + i] - x0, c[10 * B + i] - y0, c[11 * B + i] - z0, c[12 * B + i] - x0,
            c[13 * B + i] - y0, c[14 * B + i] - z0, c[15 * B + i] - x0, c[16 * B + i] - y0, c[17 * B + i] - z0,
            c[18 * B + i] - x0, c[19 * B + i] - y0, c[20 * B + i] - z0, c[21 * B + i] - x0, c[22 * B + i] - y0,
            c[23 * B + i] - z0)
