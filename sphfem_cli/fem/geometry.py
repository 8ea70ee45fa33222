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

# dV/dx_I = (1/12) sum over rows (I, j, k, s) of s (y_j z_k - y_k z_j), and cyclically for y, z:
# the exact derivative of the trilinear hex8 volume (VTK node order), derived symbolically.
HEX_DV = np.array([
    (0, 1, 2, -1), (0, 1, 3, -1), (0, 1, 4, 1), (0, 1, 5, 1), (0, 2, 3, -1), (0, 3, 4, -1),
    (0, 3, 7, -1), (0, 4, 5, -1), (0, 4, 7, 1),
    (1, 0, 2, 1), (1, 0, 3, 1), (1, 0, 4, -1), (1, 0, 5, -1), (1, 2, 3, -1), (1, 2, 5, 1),
    (1, 2, 6, 1), (1, 4, 5, -1), (1, 5, 6, -1),
    (2, 0, 1, -1), (2, 0, 3, 1), (2, 1, 3, 1), (2, 1, 5, -1), (2, 1, 6, -1), (2, 3, 6, 1),
    (2, 3, 7, 1), (2, 5, 6, -1), (2, 6, 7, -1),
    (3, 0, 1, -1), (3, 0, 2, -1), (3, 0, 4, 1), (3, 0, 7, 1), (3, 1, 2, -1), (3, 2, 6, -1),
    (3, 2, 7, -1), (3, 4, 7, 1), (3, 6, 7, -1),
    (4, 0, 1, 1), (4, 0, 3, -1), (4, 0, 5, 1), (4, 0, 7, -1), (4, 1, 5, 1), (4, 3, 7, -1),
    (4, 5, 6, 1), (4, 5, 7, 1), (4, 6, 7, 1),
    (5, 0, 1, 1), (5, 0, 4, -1), (5, 1, 2, 1), (5, 1, 4, -1), (5, 1, 6, 1), (5, 2, 6, 1),
    (5, 4, 6, -1), (5, 4, 7, -1), (5, 6, 7, 1),
    (6, 1, 2, 1), (6, 1, 5, -1), (6, 2, 3, 1), (6, 2, 5, -1), (6, 2, 7, 1), (6, 3, 7, 1),
    (6, 4, 5, 1), (6, 4, 7, -1), (6, 5, 7, -1),
    (7, 0, 3, -1), (7, 0, 4, 1), (7, 2, 3, 1), (7, 2, 6, -1), (7, 3, 4, 1), (7, 3, 6, -1),
    (7, 4, 5, 1), (7, 4, 6, 1), (7, 5, 6, 1),
], dtype=np.int64)

# Hourglass base vectors: quad4 xi*eta; hex8 xi*eta, eta*zeta, zeta*xi, xi*eta*zeta.
QUAD_GAMMA = np.array([1.0, -1.0, 1.0, -1.0])
HEX_GAMMA = np.array([
    [1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0],
    [1.0, 1.0, -1.0, -1.0, -1.0, -1.0, 1.0, 1.0],
    [1.0, -1.0, -1.0, 1.0, -1.0, 1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0, 1.0, 1.0, -1.0, 1.0, -1.0],
])
# Faces of a hex8 (for the characteristic length).
HEX_FACES = np.array([
    [0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]
], dtype=np.int64)


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


@njit(cache=True)
def hex8_gradient(x, b):
    """Mean gradient b (3, 8) = (1/V) dV/dx_I of a hex8 with corners x (8, 3); returns V (b is zero unless V > 0)."""
    for k in range(3):
        for i in range(8):
            b[k, i] = 0.0
    for r in range(HEX_DV.shape[0]):
        i = HEX_DV[r, 0]
        j = HEX_DV[r, 1]
        k = HEX_DV[r, 2]
        s = HEX_DV[r, 3] / 12.0
        b[0, i] += s * (x[j, 1] * x[k, 2] - x[k, 1] * x[j, 2])
        b[1, i] += s * (x[j, 2] * x[k, 0] - x[k, 2] * x[j, 0])
        b[2, i] += s * (x[j, 0] * x[k, 1] - x[k, 0] * x[j, 1])
    volume = 0.0
    for i in range(8):
        volume += x[i, 0] * b[0, i]
    inv = 1.0 / volume if volume > 0.0 else 0.0  # inverted, collapsed or non-finite: the caller stops
    for k in range(3):
        for i in range(8):
            b[k, i] *= inv
    return volume


@njit(cache=True)
def hex8_volumes(x, conn):
    """Exact trilinear volume of every hex8 (the one `hex8_gradient` computes), (E,)."""
    out = np.empty(conn.shape[0])
    xe = np.empty((8, 3))
    b = np.empty((3, 8))
    for e in range(conn.shape[0]):
        for a in range(8):
            for k in range(3):
                xe[a, k] = x[conn[e, a], k]
        out[e] = hex8_gradient(xe, b)
    return out


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
    """Volume over the largest face area (face area from its diagonals' cross product)."""
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
        largest = max(largest, 0.5 * np.sqrt(cx * cx + cy * cy + cz * cz))
    return volume / largest


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
