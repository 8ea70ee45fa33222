"""SPH smoothing kernels: W(r, h), F(r, h) = (1/r) dW/dr and the normalisation sigma_d (d = 2, 3).

W = sigma_d / h^d theta(r/h) with support 2h: the cubic spline (Monaghan & Lattanzio 1985) and
the Wendland C2 kernel (Wendland 1995; Dehnen & Aly 2012). Equations in docs/theory/sph.md
("Kernels"). The pair loop (``rates._pair_terms``) computes theta inline.

Every function here states ``fastmath=False``: they are called from kernels with and without
fast-math flags, and numba compiles a callee that states none with the flags of the caller that
first needs it, then caches that version under its signature alone (see ``rates._FM``).
"""
from __future__ import annotations

import math

from numba import njit

CUBIC_SPLINE = 0
WENDLAND_C2 = 1


@njit(cache=True, fastmath=False)
def kernel_sigma(kernel, dim):
    """Normalisation constant sigma_d of W = sigma_d / h^d theta(r/h) (support 2h)."""
    if kernel == WENDLAND_C2:
        if dim == 2:
            return 7.0 / (4.0 * math.pi)
        return 21.0 / (16.0 * math.pi)
    if dim == 2:
        return 10.0 / (7.0 * math.pi)
    return 1.0 / math.pi


@njit(cache=True, fastmath=False)
def kernel_shape(kernel, q):
    """Kernel shape theta(q) and (1/q) dtheta/dq for 0 <= q < 2 (both 0 beyond); the same in 2D and 3D."""
    if q >= 2.0:
        return 0.0, 0.0
    if kernel == WENDLAND_C2:
        t = 1.0 - 0.5 * q
        t2 = t * t
        return t2 * t2 * (2.0 * q + 1.0), -5.0 * t2 * t
    t = 2.0 - q
    inner = q < 1.0  # both branches computed, then selected: no misprediction in pair loops
    th = 1.0 - q * q * (1.5 - 0.75 * q) if inner else 0.25 * t * t * t
    dth = -3.0 + 2.25 * q if inner else -0.75 * t * t / q
    return th, dth


@njit(cache=True, fastmath=False)
def inv_pow(inv, dim):
    """inv^dim for dim 2, 3 (1/h^d of the normalisation)."""
    if dim == 2:
        return inv * inv
    return inv * inv * inv


@njit(cache=True, fastmath=False)
def kernel_w(kernel, dim, r, h):
    """Kernel value W(r, h)."""
    inv = 1.0 / h
    return kernel_sigma(kernel, dim) * inv_pow(inv, dim) * kernel_shape(kernel, r * inv)[0]


@njit(cache=True, fastmath=False)
def kernel_f(kernel, dim, r, h):
    """F(r, h) = (1/r) dW/dr, so that grad_i W_ij = F r_ij with r_ij = x_i - x_j (finite at r = 0)."""
    inv = 1.0 / h
    return kernel_sigma(kernel, dim) * inv_pow(inv, dim) * inv * inv * kernel_shape(kernel, r * inv)[1]
