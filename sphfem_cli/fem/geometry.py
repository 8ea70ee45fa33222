"""Element geometry and the element-level formulas the Lagrangian solids (``fem.kernels``) and the
ALE fluid (``ale``) share: mean gradients, exact volumes, characteristic lengths, hourglass base
vectors, bulk viscosity and the stable step.

- Mean (uniform) gradient b_I = (1/V) dV/dx_I (Flanagan & Belytschko 1981): quad4 from the
  diagonals' cross product, hex8 from the exact derivative of the trilinear volume (``HEX_DV``).
- Characteristic length l = V / longest edge (quad4), V / largest face area (hex8).
- Hourglass base vectors Gamma: quad4 xi*eta, hex8 xi*eta, eta*zeta, zeta*xi, xi*eta*zeta
  (``QUAD_GAMMA``, ``HEX_GAMMA``; Flanagan & Belytschko 1981).
- Bulk viscosity q = rho l (Q1^2 l tr(d)^2 - Q2 c tr(d)) in compression (von Neumann & Richtmyer
  1950; LS-DYNA's form) and the stable step l / (Q + sqrt(Q^2 + c^2)), Q = Q2 c + Q1^2 l |tr d|
  (paper eqs. 2.9-2.10).

Equations: docs/theory/fem.md; ALE use: docs/theory/ale.md.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .tables import HEX_DV, HEX_FACES


@njit(cache=True)
def quad4_gradient(x, b):
    """Mean gradient b (2, 4) of a quad4 with corners x (4, 2); returns the area (b is zero unless it is > 0).

    A = ((x2 - x0)(y3 - y1) + (x1 - x3)(y2 - y0)) / 2, b_xI = (y_{I+1} - y_{I-1}) / 2A,
    b_yI = (x_{I-1} - x_{I+1}) / 2A (the centre-point gradient, exact for the mean in 2D).
    """
    area = 0.5 * ((x[2, 0] - x[0, 0]) * (x[3, 1] - x[1, 1]) + (x[1, 0] - x[3, 0]) * (x[2, 1] - x[0, 1]))
    inv = 0.5 / area if area > 0.0 else 0.0  # inverted, collapsed or non-finite: the caller stops
    for i in range(4):
        nxt = (i + 1) % 4
        prv = (i + 3) % 4
        b[0, i] = (x[nxt, 1] - x[prv, 1]) * inv
        b[1, i] = (x[prv, 0] - x[nxt, 0]) * inv
    return area


# HEX_DV's rows are grouped by node I, HEX_DV_ROWS rows each (checked at import).
HEX_DV_ROWS = 9
assert (HEX_DV[:, 0] == np.repeat(np.arange(8), HEX_DV_ROWS)).all()


@njit(cache=True)
def hex8_gradient_rows(x, b):
    """``hex8_gradient`` from the rows of ``HEX_DV`` (the reference it equals bit for bit; tests check).

    The rows of node I are summed in table order: b_kI = 0 + s_1 c_1 + ... + s_9 c_9, then scaled by 1/V.
    """
    volume = 0.0
    for i in range(8):
        bx = 0.0
        by = 0.0
        bz = 0.0
        for r in range(i * HEX_DV_ROWS, (i + 1) * HEX_DV_ROWS):
            j = HEX_DV[r, 1]
            k = HEX_DV[r, 2]
            s = HEX_DV[r, 3] / 12.0
            xj0 = x[j, 0]
            xj1 = x[j, 1]
            xj2 = x[j, 2]
            xk0 = x[k, 0]
            xk1 = x[k, 1]
            xk2 = x[k, 2]
            bx += s * (xj1 * xk2 - xk1 * xj2)
            by += s * (xj2 * xk0 - xk2 * xj0)
            bz += s * (xj0 * xk1 - xk0 * xj1)
        b[0, i] = bx
        b[1, i] = by
        b[2, i] = bz
        volume += x[i, 0] * bx
    inv = 1.0 / volume if volume > 0.0 else 0.0  # inverted, collapsed or non-finite: the caller stops
    for k in range(3):
        for i in range(8):
            b[k, i] *= inv
    return volume


@njit(cache=True, inline="always")
def hex8_dv(x0, y0, z0, x1, y1, z1, x2, y2, z2, x3, y3, z3, x4, y4, z4, x5, y5, z5, x6, y6, z6, x7, y7, z7):
    """dV/dx_I of a hex8 from its corners as scalars: (dV/dx_0 .. dV/dx_7, dV/dy_0 .. dV/dy_7, dV/dz_0 .. dV/dz_7).

    The body of ``hex8_gradient`` (its docstring: the rows of ``HEX_DV`` written out in table order), on scalars
    so that a loop over elements can hold it (the ALE hex8 force kernel's geometry pass,
    ``ale.hex_lanes.hex_geometry_block``): the same operations, the same bits.
    """
    W = 1.0 / 12.0
    bx0 = (0.0 - W * (y1 * z2 - y2 * z1) - W * (y1 * z3 - y3 * z1) + W * (y1 * z4 - y4 * z1)
           + W * (y1 * z5 - y5 * z1) - W * (y2 * z3 - y3 * z2) - W * (y3 * z4 - y4 * z3)
           - W * (y3 * z7 - y7 * z3) - W * (y4 * z5 - y5 * z4) + W * (y4 * z7 - y7 * z4))
    by0 = (0.0 - W * (z1 * x2 - z2 * x1) - W * (z1 * x3 - z3 * x1) + W * (z1 * x4 - z4 * x1)
           + W * (z1 * x5 - z5 * x1) - W * (z2 * x3 - z3 * x2) - W * (z3 * x4 - z4 * x3)
           - W * (z3 * x7 - z7 * x3) - W * (z4 * x5 - z5 * x4) + W * (z4 * x7 - z7 * x4))
    bz0 = (0.0 - W * (x1 * y2 - x2 * y1) - W * (x1 * y3 - x3 * y1) + W * (x1 * y4 - x4 * y1)
           + W * (x1 * y5 - x5 * y1) - W * (x2 * y3 - x3 * y2) - W * (x3 * y4 - x4 * y3)
           - W * (x3 * y7 - x7 * y3) - W * (x4 * y5 - x5 * y4) + W * (x4 * y7 - x7 * y4))
    bx1 = (0.0 + W * (y0 * z2 - y2 * z0) + W * (y0 * z3 - y3 * z0) - W * (y0 * z4 - y4 * z0)
           - W * (y0 * z5 - y5 * z0) - W * (y2 * z3 - y3 * z2) + W * (y2 * z5 - y5 * z2)
           + W * (y2 * z6 - y6 * z2) - W * (y4 * z5 - y5 * z4) - W * (y5 * z6 - y6 * z5))
    by1 = (0.0 + W * (z0 * x2 - z2 * x0) + W * (z0 * x3 - z3 * x0) - W * (z0 * x4 - z4 * x0)
           - W * (z0 * x5 - z5 * x0) - W * (z2 * x3 - z3 * x2) + W * (z2 * x5 - z5 * x2)
           + W * (z2 * x6 - z6 * x2) - W * (z4 * x5 - z5 * x4) - W * (z5 * x6 - z6 * x5))
    bz1 = (0.0 + W * (x0 * y2 - x2 * y0) + W * (x0 * y3 - x3 * y0) - W * (x0 * y4 - x4 * y0)
           - W * (x0 * y5 - x5 * y0) - W * (x2 * y3 - x3 * y2) + W * (x2 * y5 - x5 * y2)
           + W * (x2 * y6 - x6 * y2) - W * (x4 * y5 - x5 * y4) - W * (x5 * y6 - x6 * y5))
    bx2 = (0.0 - W * (y0 * z1 - y1 * z0) + W * (y0 * z3 - y3 * z0) + W * (y1 * z3 - y3 * z1)
           - W * (y1 * z5 - y5 * z1) - W * (y1 * z6 - y6 * z1) + W * (y3 * z6 - y6 * z3)
           + W * (y3 * z7 - y7 * z3) - W * (y5 * z6 - y6 * z5) - W * (y6 * z7 - y7 * z6))
    by2 = (0.0 - W * (z0 * x1 - z1 * x0) + W * (z0 * x3 - z3 * x0) + W * (z1 * x3 - z3 * x1)
           - W * (z1 * x5 - z5 * x1) - W * (z1 * x6 - z6 * x1) + W * (z3 * x6 - z6 * x3)
           + W * (z3 * x7 - z7 * x3) - W * (z5 * x6 - z6 * x5) - W * (z6 * x7 - z7 * x6))
    bz2 = (0.0 - W * (x0 * y1 - x1 * y0) + W * (x0 * y3 - x3 * y0) + W * (x1 * y3 - x3 * y1)
           - W * (x1 * y5 - x5 * y1) - W * (x1 * y6 - x6 * y1) + W * (x3 * y6 - x6 * y3)
           + W * (x3 * y7 - x7 * y3) - W * (x5 * y6 - x6 * y5) - W * (x6 * y7 - x7 * y6))
    bx3 = (0.0 - W * (y0 * z1 - y1 * z0) - W * (y0 * z2 - y2 * z0) + W * (y0 * z4 - y4 * z0)
           + W * (y0 * z7 - y7 * z0) - W * (y1 * z2 - y2 * z1) - W * (y2 * z6 - y6 * z2)
           - W * (y2 * z7 - y7 * z2) + W * (y4 * z7 - y7 * z4) - W * (y6 * z7 - y7 * z6))
    by3 = (0.0 - W * (z0 * x1 - z1 * x0) - W * (z0 * x2 - z2 * x0) + W * (z0 * x4 - z4 * x0)
           + W * (z0 * x7 - z7 * x0) - W * (z1 * x2 - z2 * x1) - W * (z2 * x6 - z6 * x2)
           - W * (z2 * x7 - z7 * x2) + W * (z4 * x7 - z7 * x4) - W * (z6 * x7 - z7 * x6))
    bz3 = (0.0 - W * (x0 * y1 - x1 * y0) - W * (x0 * y2 - x2 * y0) + W * (x0 * y4 - x4 * y0)
           + W * (x0 * y7 - x7 * y0) - W * (x1 * y2 - x2 * y1) - W * (x2 * y6 - x6 * y2)
           - W * (x2 * y7 - x7 * y2) + W * (x4 * y7 - x7 * y4) - W * (x6 * y7 - x7 * y6))
    bx4 = (0.0 + W * (y0 * z1 - y1 * z0) - W * (y0 * z3 - y3 * z0) + W * (y0 * z5 - y5 * z0)
           - W * (y0 * z7 - y7 * z0) + W * (y1 * z5 - y5 * z1) - W * (y3 * z7 - y7 * z3)
           + W * (y5 * z6 - y6 * z5) + W * (y5 * z7 - y7 * z5) + W * (y6 * z7 - y7 * z6))
    by4 = (0.0 + W * (z0 * x1 - z1 * x0) - W * (z0 * x3 - z3 * x0) + W * (z0 * x5 - z5 * x0)
           - W * (z0 * x7 - z7 * x0) + W * (z1 * x5 - z5 * x1) - W * (z3 * x7 - z7 * x3)
           + W * (z5 * x6 - z6 * x5) + W * (z5 * x7 - z7 * x5) + W * (z6 * x7 - z7 * x6))
    bz4 = (0.0 + W * (x0 * y1 - x1 * y0) - W * (x0 * y3 - x3 * y0) + W * (x0 * y5 - x5 * y0)
           - W * (x0 * y7 - x7 * y0) + W * (x1 * y5 - x5 * y1) - W * (x3 * y7 - x7 * y3)
           + W * (x5 * y6 - x6 * y5) + W * (x5 * y7 - x7 * y5) + W * (x6 * y7 - x7 * y6))
    bx5 = (0.0 + W * (y0 * z1 - y1 * z0) - W * (y0 * z4 - y4 * z0) + W * (y1 * z2 - y2 * z1)
           - W * (y1 * z4 - y4 * z1) + W * (y1 * z6 - y6 * z1) + W * (y2 * z6 - y6 * z2)
           - W * (y4 * z6 - y6 * z4) - W * (y4 * z7 - y7 * z4) + W * (y6 * z7 - y7 * z6))
    by5 = (0.0 + W * (z0 * x1 - z1 * x0) - W * (z0 * x4 - z4 * x0) + W * (z1 * x2 - z2 * x1)
           - W * (z1 * x4 - z4 * x1) + W * (z1 * x6 - z6 * x1) + W * (z2 * x6 - z6 * x2)
           - W * (z4 * x6 - z6 * x4) - W * (z4 * x7 - z7 * x4) + W * (z6 * x7 - z7 * x6))
    bz5 = (0.0 + W * (x0 * y1 - x1 * y0) - W * (x0 * y4 - x4 * y0) + W * (x1 * y2 - x2 * y1)
           - W * (x1 * y4 - x4 * y1) + W * (x1 * y6 - x6 * y1) + W * (x2 * y6 - x6 * y2)
           - W * (x4 * y6 - x6 * y4) - W * (x4 * y7 - x7 * y4) + W * (x6 * y7 - x7 * y6))
    bx6 = (0.0 + W * (y1 * z2 - y2 * z1) - W * (y1 * z5 - y5 * z1) + W * (y2 * z3 - y3 * z2)
           - W * (y2 * z5 - y5 * z2) + W * (y2 * z7 - y7 * z2) + W * (y3 * z7 - y7 * z3)
           + W * (y4 * z5 - y5 * z4) - W * (y4 * z7 - y7 * z4) - W * (y5 * z7 - y7 * z5))
    by6 = (0.0 + W * (z1 * x2 - z2 * x1) - W * (z1 * x5 - z5 * x1) + W * (z2 * x3 - z3 * x2)
           - W * (z2 * x5 - z5 * x2) + W * (z2 * x7 - z7 * x2) + W * (z3 * x7 - z7 * x3)
           + W * (z4 * x5 - z5 * x4) - W * (z4 * x7 - z7 * x4) - W * (z5 * x7 - z7 * x5))
    bz6 = (0.0 + W * (x1 * y2 - x2 * y1) - W * (x1 * y5 - x5 * y1) + W * (x2 * y3 - x3 * y2)
           - W * (x2 * y5 - x5 * y2) + W * (x2 * y7 - x7 * y2) + W * (x3 * y7 - x7 * y3)
           + W * (x4 * y5 - x5 * y4) - W * (x4 * y7 - x7 * y4) - W * (x5 * y7 - x7 * y5))
    bx7 = (0.0 - W * (y0 * z3 - y3 * z0) + W * (y0 * z4 - y4 * z0) + W * (y2 * z3 - y3 * z2)
           - W * (y2 * z6 - y6 * z2) + W * (y3 * z4 - y4 * z3) - W * (y3 * z6 - y6 * z3)
           + W * (y4 * z5 - y5 * z4) + W * (y4 * z6 - y6 * z4) + W * (y5 * z6 - y6 * z5))
    by7 = (0.0 - W * (z0 * x3 - z3 * x0) + W * (z0 * x4 - z4 * x0) + W * (z2 * x3 - z3 * x2)
           - W * (z2 * x6 - z6 * x2) + W * (z3 * x4 - z4 * x3) - W * (z3 * x6 - z6 * x3)
           + W * (z4 * x5 - z5 * x4) + W * (z4 * x6 - z6 * x4) + W * (z5 * x6 - z6 * x5))
    bz7 = (0.0 - W * (x0 * y3 - x3 * y0) + W * (x0 * y4 - x4 * y0) + W * (x2 * y3 - x3 * y2)
           - W * (x2 * y6 - x6 * y2) + W * (x3 * y4 - x4 * y3) - W * (x3 * y6 - x6 * y3)
           + W * (x4 * y5 - x5 * y4) + W * (x4 * y6 - x6 * y4) + W * (x5 * y6 - x6 * y5))
    return (bx0, bx1, bx2, bx3, bx4, bx5, bx6, bx7, by0, by1, by2, by3, by4, by5, by6, by7,
            bz0, bz1, bz2, bz3, bz4, bz5, bz6, bz7)


@njit(cache=True)
def hex8_gradient(x, b):
    """Mean gradient b (3, 8) = (1/V) dV/dx_I of a hex8 with corners x (8, 3); returns V (b is zero unless V > 0).

    dV/dx_I = (1/12) sum over the rows (I, j, k, s) of ``HEX_DV`` of s (y_j z_k - y_k z_j), and cyclically
    (x -> y -> z) for dV/dy_I, dV/dz_I, written out row by row in table order (W = 1/12, s W c added
    as +- W c): the same operations in the same order as ``hex8_gradient_rows``, so the same bits, with
    no table look-up or indexed load in the loop (the table loop cost about 390 ns a call, this one
    see benchmarks/fem_passes.py). V = sum_I x_I dV/dx_I.
    """
    x0, y0, z0 = x[0, 0], x[0, 1], x[0, 2]
    x1, y1, z1 = x[1, 0], x[1, 1], x[1, 2]
    x2, y2, z2 = x[2, 0], x[2, 1], x[2, 2]
    x3, y3, z3 = x[3, 0], x[3, 1], x[3, 2]
    x4, y4, z4 = x[4, 0], x[4, 1], x[4, 2]
    x5, y5, z5 = x[5, 0], x[5, 1], x[5, 2]
    x6, y6, z6 = x[6, 0], x[6, 1], x[6, 2]
    x7, y7, z7 = x[7, 0], x[7, 1], x[7, 2]
    (bx0, bx1, bx2, bx3, bx4, bx5, bx6, bx7, by0, by1, by2, by3, by4, by5, by6, by7,
     bz0, bz1, bz2, bz3, bz4, bz5, bz6, bz7) = hex8_dv(x0, y0, z0, x1, y1, z1, x2, y2, z2, x3, y3, z3,
                                                        x4, y4, z4, x5, y5, z5, x6, y6, z6, x7, y7, z7)
    volume = (0.0 + x0 * bx0 + x1 * bx1 + x2 * bx2 + x3 * bx3
              + x4 * bx4 + x5 * bx5 + x6 * bx6 + x7 * bx7)
    inv = 1.0 / volume if volume > 0.0 else 0.0  # inverted, collapsed or non-finite: the caller stops
    b[0, 0], b[0, 1], b[0, 2], b[0, 3] = bx0 * inv, bx1 * inv, bx2 * inv, bx3 * inv
    b[0, 4], b[0, 5], b[0, 6], b[0, 7] = bx4 * inv, bx5 * inv, bx6 * inv, bx7 * inv
    b[1, 0], b[1, 1], b[1, 2], b[1, 3] = by0 * inv, by1 * inv, by2 * inv, by3 * inv
    b[1, 4], b[1, 5], b[1, 6], b[1, 7] = by4 * inv, by5 * inv, by6 * inv, by7 * inv
    b[2, 0], b[2, 1], b[2, 2], b[2, 3] = bz0 * inv, bz1 * inv, bz2 * inv, bz3 * inv
    b[2, 4], b[2, 5], b[2, 6], b[2, 7] = bz4 * inv, bz5 * inv, bz6 * inv, bz7 * inv
    return volume


@njit(cache=True)
def _node_faces(p, q, r, s, t, u):
    """(p x q) + (r x s) + (t x u) for 3-tuples: node I's three face terms of ``hex8_gradient_faces``."""
    return ((p[1] * q[2] - p[2] * q[1]) + (r[1] * s[2] - r[2] * s[1]) + (t[1] * u[2] - t[2] * u[1]),
            (p[2] * q[0] - p[0] * q[2]) + (r[2] * s[0] - r[0] * s[2]) + (t[2] * u[0] - t[0] * u[2]),
            (p[0] * q[1] - p[1] * q[0]) + (r[0] * s[1] - r[1] * s[0]) + (t[0] * u[1] - t[1] * u[0]))


@njit(cache=True)
def hex8_gradient_faces(x, b):
    """``hex8_gradient`` in a factored form: b (3, 8) = (1/V) dV/dx_I and V of a hex8 with corners x (8, 3).

    Grouping the nine rows of ``HEX_DV`` of node I by the three faces that hold I: on a face whose
    corners follow I in ``HEX_FACES``'s order as a, b, c, its three rows are
    [a, b] + [a, c] + [b, c], [j, k] = x_j x x_k (the same sign +1 on every face; the test
    tests/unit/test_fem_kernels.py::test_hex8_gradient_faces_is_the_table_form checks it), and
    [a, b] + [a, c] + [b, c] = (x_a + x_b) x (x_b + x_c). So

        12 dV/dx_I = sum over the three faces of I of (x_a + x_b) x (x_b + x_c),

    with the sums over two edges of the face away from I (12 edge sums, each used four times):
    3 cross products per node instead of 9. 12 V = sum_I x_I (12 dV/dx_I) and
    b_I = (12 dV/dx_I) / (12 V). The same numbers as ``hex8_gradient`` up to round-off (not the
    same bits; about a third of its operations); the FEM hex8 kernel uses it, ALE and the model's
    initial volumes keep ``hex8_gradient``.
    """
    x0, y0, z0 = x[0, 0], x[0, 1], x[0, 2]
    x1, y1, z1 = x[1, 0], x[1, 1], x[1, 2]
    x2, y2, z2 = x[2, 0], x[2, 1], x[2, 2]
    x3, y3, z3 = x[3, 0], x[3, 1], x[3, 2]
    x4, y4, z4 = x[4, 0], x[4, 1], x[4, 2]
    x5, y5, z5 = x[5, 0], x[5, 1], x[5, 2]
    x6, y6, z6 = x[6, 0], x[6, 1], x[6, 2]
    x7, y7, z7 = x[7, 0], x[7, 1], x[7, 2]
    # The 12 edge sums e_jk = x_j + x_k.
    e01 = (x0 + x1, y0 + y1, z0 + z1)
    e12 = (x1 + x2, y1 + y2, z1 + z2)
    e23 = (x2 + x3, y2 + y3, z2 + z3)
    e03 = (x0 + x3, y0 + y3, z0 + z3)
    e45 = (x4 + x5, y4 + y5, z4 + z5)
    e56 = (x5 + x6, y5 + y6, z5 + z6)
    e67 = (x6 + x7, y6 + y7, z6 + z7)
    e47 = (x4 + x7, y4 + y7, z4 + z7)
    e04 = (x0 + x4, y0 + y4, z0 + z4)
    e15 = (x1 + x5, y1 + y5, z1 + z5)
    e26 = (x2 + x6, y2 + y6, z2 + z6)
    e37 = (x3 + x7, y3 + y7, z3 + z7)
    # Node I: the edge pair (a + b, b + c) of each of its faces (bottom or top first).
    g0 = _node_faces(e23, e12, e15, e45, e47, e37)  # faces 0-3-2-1, 0-1-5-4, 3-0-4-7
    g1 = _node_faces(e03, e23, e45, e04, e26, e56)  # 1-0-3-2, 1-5-4-0, 1-2-6-5
    g2 = _node_faces(e01, e03, e56, e15, e37, e67)  # 2-1-0-3, 2-6-5-1, 2-3-7-6
    g3 = _node_faces(e12, e01, e67, e26, e04, e47)  # 3-2-1-0, 3-7-6-2, 3-0-4-7
    g4 = _node_faces(e56, e67, e01, e15, e37, e03)  # 4-5-6-7, 4-0-1-5, 4-7-3-0
    g5 = _node_faces(e67, e47, e04, e01, e12, e26)  # 5-6-7-4, 5-4-0-1, 5-1-2-6
    g6 = _node_faces(e47, e45, e15, e12, e23, e37)  # 6-7-4-5, 6-5-1-2, 6-2-3-7
    g7 = _node_faces(e45, e56, e26, e23, e03, e04)  # 7-4-5-6, 7-6-2-3, 7-3-0-4
    total = (x0 * g0[0] + x1 * g1[0] + x2 * g2[0] + x3 * g3[0]
             + x4 * g4[0] + x5 * g5[0] + x6 * g6[0] + x7 * g7[0])  # 12 V
    inv = 1.0 / total if total > 0.0 else 0.0  # inverted, collapsed or non-finite: the caller stops
    b[0, 0], b[1, 0], b[2, 0] = g0[0] * inv, g0[1] * inv, g0[2] * inv
    b[0, 1], b[1, 1], b[2, 1] = g1[0] * inv, g1[1] * inv, g1[2] * inv
    b[0, 2], b[1, 2], b[2, 2] = g2[0] * inv, g2[1] * inv, g2[2] * inv
    b[0, 3], b[1, 3], b[2, 3] = g3[0] * inv, g3[1] * inv, g3[2] * inv
    b[0, 4], b[1, 4], b[2, 4] = g4[0] * inv, g4[1] * inv, g4[2] * inv
    b[0, 5], b[1, 5], b[2, 5] = g5[0] * inv, g5[1] * inv, g5[2] * inv
    b[0, 6], b[1, 6], b[2, 6] = g6[0] * inv, g6[1] * inv, g6[2] * inv
    b[0, 7], b[1, 7], b[2, 7] = g7[0] * inv, g7[1] * inv, g7[2] * inv
    return total * (1.0 / 12.0)


@njit(cache=True)
def hex8_volume(p):
    """Exact volume of the trilinear hexahedron with corners p (8, 3) (VTK order), without its gradient.

    V = sum_I x_I dV/dx_I (V is linear in the x components), with the rows of ``HEX_DV``:
    V = (1/12) sum_rows s x_I (y_j z_k - y_k z_j), the same exact formula as ``hex8_gradient``.
    Callers pass corners relative to one of them (translation-invariant; less cancellation).
    """
    v = 0.0
    for r in range(HEX_DV.shape[0]):
        i = HEX_DV[r, 0]
        j = HEX_DV[r, 1]
        k = HEX_DV[r, 2]
        v += HEX_DV[r, 3] * p[i, 0] * (p[j, 1] * p[k, 2] - p[k, 1] * p[j, 2])
    return v / 12.0


@njit(cache=True, inline="always")
def hex8_volume_origin(x1, y1, z1, x2, y2, z2, x3, y3, z3, x4, y4, z4, x5, y5, z5, x6, y6, z6, x7, y7, z7):
    """``hex8_volume`` of corners relative to corner 0 (x_0 = 0; the others' coordinates as scalars), written out.

    The 45 rows of ``HEX_DV`` that name neither I = 0 nor a corner 0 in their product, in table order: each of
    the other 27 rows gives exactly +-0 when x_0 = 0 (finite coordinates), and a running sum from +0.0 is
    unchanged by a signed zero (x + -0 = x; an exact cancellation gives +0), so the same bits as ``hex8_volume``
    with p[0] = 0, without the table look-ups and the indexed loads (the ALE face sweep, the hex8
    Lagrangian volume and the initial volumes call it once per face or element). s x_I c is written
    +- x_I c: the product with s = +-1 is exact. V = (1/12) sum_rows s x_I (y_j z_k - y_k z_j).
    """
    v = (0.0 - x1 * (y2 * z3 - y3 * z2) + x1 * (y2 * z5 - y5 * z2) + x1 * (y2 * z6 - y6 * z2)
         - x1 * (y4 * z5 - y5 * z4) - x1 * (y5 * z6 - y6 * z5) + x2 * (y1 * z3 - y3 * z1)
         - x2 * (y1 * z5 - y5 * z1) - x2 * (y1 * z6 - y6 * z1) + x2 * (y3 * z6 - y6 * z3)
         + x2 * (y3 * z7 - y7 * z3) - x2 * (y5 * z6 - y6 * z5) - x2 * (y6 * z7 - y7 * z6)
         - x3 * (y1 * z2 - y2 * z1) - x3 * (y2 * z6 - y6 * z2) - x3 * (y2 * z7 - y7 * z2)
         + x3 * (y4 * z7 - y7 * z4) - x3 * (y6 * z7 - y7 * z6) + x4 * (y1 * z5 - y5 * z1)
         - x4 * (y3 * z7 - y7 * z3) + x4 * (y5 * z6 - y6 * z5) + x4 * (y5 * z7 - y7 * z5)
         + x4 * (y6 * z7 - y7 * z6) + x5 * (y1 * z2 - y2 * z1) - x5 * (y1 * z4 - y4 * z1)
         + x5 * (y1 * z6 - y6 * z1) + x5 * (y2 * z6 - y6 * z2) - x5 * (y4 * z6 - y6 * z4)
         - x5 * (y4 * z7 - y7 * z4) + x5 * (y6 * z7 - y7 * z6) + x6 * (y1 * z2 - y2 * z1)
         - x6 * (y1 * z5 - y5 * z1) + x6 * (y2 * z3 - y3 * z2) - x6 * (y2 * z5 - y5 * z2)
         + x6 * (y2 * z7 - y7 * z2) + x6 * (y3 * z7 - y7 * z3) + x6 * (y4 * z5 - y5 * z4)
         - x6 * (y4 * z7 - y7 * z4) - x6 * (y5 * z7 - y7 * z5) + x7 * (y2 * z3 - y3 * z2)
         - x7 * (y2 * z6 - y6 * z2) + x7 * (y3 * z4 - y4 * z3) - x7 * (y3 * z6 - y6 * z3)
         + x7 * (y4 * z5 - y5 * z4) + x7 * (y4 * z6 - y6 * z4) + x7 * (y5 * z6 - y6 * z5))
    return v / 12.0


@njit(cache=True)
def quad4_char_length(x, area):
    """Area over the longest edge."""
    longest = 0.0
    for i in range(4):
        j = (i + 1) % 4
        e = np.sqrt((x[j, 0] - x[i, 0]) ** 2 + (x[j, 1] - x[i, 1]) ** 2)
        longest = max(longest, e)
    return area / longest


@njit(cache=True)
def hex8_char_length(x, volume):
    """Volume over the largest face area (face area from its diagonals' cross product).

    The largest squared norm is found first and one square root taken: sqrt is monotone and correctly
    rounded, so max_f (|c_f| / 2) = sqrt(max_f |c_f|^2) / 2 bit for bit, with one sqrt instead of six.
    """
    largest = 0.0
    for f in range(6):
        a, b_, c, d = HEX_FACES[f, 0], HEX_FACES[f, 1], HEX_FACES[f, 2], HEX_FACES[f, 3]
        p0 = x[c, 0] - x[a, 0]
        p1 = x[c, 1] - x[a, 1]
        p2 = x[c, 2] - x[a, 2]
        q0 = x[d, 0] - x[b_, 0]
        q1 = x[d, 1] - x[b_, 1]
        q2 = x[d, 2] - x[b_, 2]
        cx = p1 * q2 - p2 * q1
        cy = p2 * q0 - p0 * q2
        cz = p0 * q1 - p1 * q0
        largest = max(largest, cx * cx + cy * cy + cz * cz)
    return volume / (0.5 * np.sqrt(largest))


@njit(cache=True)
def bulk_viscosity(rho, length, c, trace_d, q1, q2):
    """q = rho l (Q1^2 l tr(d)^2 - Q2 c tr(d)) for tr(d) < 0, else 0."""
    if trace_d >= 0.0:
        return 0.0
    return rho * length * (q1 * q1 * length * trace_d * trace_d - q2 * c * trace_d)


@njit(cache=True)
def stable_dt(length, c, trace_d, q1, q2):
    """l / (Q + sqrt(Q^2 + c^2)), Q = Q2 c + Q1^2 l |tr d| in compression (consistent with q).

    A state with no signal speed at all (c = 0, no compression) sets no limit: +inf.
    """
    qq = 0.0
    if trace_d < 0.0:
        qq = q2 * c + q1 * q1 * length * (-trace_d)
    denominator = qq + np.sqrt(qq * qq + c * c)
    if denominator <= 0.0:
        return np.inf
    return length / denominator
