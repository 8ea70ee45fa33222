"""Host search of the ALE -> structure coupling, 2D and 3D written once (docs/theory/coupling.md, "Host").

Buckets over the ALE mesh, the element containing a point and its natural coordinates, and the rules
that choose a coupling point's host element. The bodies (``inline="always"``) take the element kind as
literal constants of the caller (npe corners: quad4 4, hex8 8; dim 2 or 3), as ``ale/lagrange.py``
does, so that each kernel of ``coupling_kernels`` (quad4 ALE, 2-node segments) and
``coupling_kernels_3d`` (hex8 ALE, quad4 faces) compiles as if written for its element; in 2D the
third coordinate is passed as 0 and a third bucket count as 1, and its lines drop out.

- ``bin_elements``: a uniform grid of buckets, each listing the elements whose bounding box overlaps
  it (CSR, bucket index ix + nbx (iy + nby iz)), rebuilt each step (the mesh may move).
- ``natural_coords`` (quad4, inverse bilinear map) and ``natural_coords_3d`` (hex8, inverse
  trilinear map) by Newton's method; ``natural`` the one of the element kind.
- ``locate_point``: the element containing a point and its natural coordinates, through the buckets.
- ``host_point``: the host element of a coupling point (the rules in ``host_point``'s docstring).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .coupling_common import fluid_depth

INSIDE_TOL = 1e-9  # natural-coordinate tolerance of "inside an element"
TOUCH_TOL = 1e-6  # a free point within this fraction of the probe distance of the fluid touches it

_HXI = np.array([-1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0, -1.0])
_HETA = np.array([-1.0, -1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0])
_HZETA = np.array([-1.0, -1.0, -1.0, -1.0, 1.0, 1.0, 1.0, 1.0])


@njit(cache=True)
def clamp(a):
    """a limited to [-1, 1] (natural coordinates of a point just outside its host)."""
    return min(1.0, max(-1.0, a))


@njit(cache=True, inline="always")
def bin_elements(x, conn, origin, cell, nbx, nby, nbz, npe, dim):
    """(start, items): the elements overlapping each bucket (index ix + nbx (iy + nby iz); 2D: nbz 1, iz 0)."""
    n_elem = conn.shape[0]
    count = np.zeros(nbx * nby * nbz + 1, dtype=np.int64)
    lo = np.zeros((n_elem, 3), dtype=np.int64)
    hi = np.zeros((n_elem, 3), dtype=np.int64)
    for e in range(n_elem):
        for d in range(dim):
            a = x[conn[e, 0], d]
            b = a
            for k in range(1, npe):
                v = x[conn[e, k], d]
                a = min(a, v)
                b = max(b, v)
            nb = nbx if d == 0 else (nby if d == 1 else nbz)
            i0 = int(math.floor((a - origin[d]) / cell))
            i1 = int(math.floor((b - origin[d]) / cell))
            lo[e, d] = min(max(i0, 0), nb - 1)
            hi[e, d] = min(max(i1, 0), nb - 1)
        for iz in range(lo[e, 2], hi[e, 2] + 1):
            for iy in range(lo[e, 1], hi[e, 1] + 1):
                for ix in range(lo[e, 0], hi[e, 0] + 1):
                    count[ix + nbx * (iy + nby * iz) + 1] += 1
    start = np.cumsum(count)
    items = np.empty(start[-1], dtype=np.int64)
    fill = start[:-1].copy()
    for e in range(n_elem):
        for iz in range(lo[e, 2], hi[e, 2] + 1):
            for iy in range(lo[e, 1], hi[e, 1] + 1):
                for ix in range(lo[e, 0], hi[e, 0] + 1):
                    b = ix + nbx * (iy + nby * iz)
                    items[fill[b]] = e
                    fill[b] += 1
    return start, items


@njit(cache=True)
def natural_coords(x, conn, e, px, py):
    """(xi, eta) of point (px, py) in quad4 element e by Newton's method on the bilinear map."""
    x0, y0 = x[conn[e, 0], 0], x[conn[e, 0], 1]
    x1, y1 = x[conn[e, 1], 0], x[conn[e, 1], 1]
    x2, y2 = x[conn[e, 2], 0], x[conn[e, 2], 1]
    x3, y3 = x[conn[e, 3], 0], x[conn[e, 3], 1]
    # x(xi, eta) = a + b xi + c eta + d xi eta
    ax, bx = 0.25 * (x0 + x1 + x2 + x3), 0.25 * (-x0 + x1 + x2 - x3)
    cx, dx = 0.25 * (-x0 - x1 + x2 + x3), 0.25 * (x0 - x1 + x2 - x3)
    ay, by = 0.25 * (y0 + y1 + y2 + y3), 0.25 * (-y0 + y1 + y2 - y3)
    cy, dy = 0.25 * (-y0 - y1 + y2 + y3), 0.25 * (y0 - y1 + y2 - y3)
    xi = 0.0
    eta = 0.0
    for _ in range(20):
        rx = ax + bx * xi + cx * eta + dx * xi * eta - px
        ry = ay + by * xi + cy * eta + dy * xi * eta - py
        j11 = bx + dx * eta
        j12 = cx + dx * xi
        j21 = by + dy * eta
        j22 = cy + dy * xi
        det = j11 * j22 - j12 * j21
        if det == 0.0:
            break
        dxi = (j22 * rx - j12 * ry) / det
        deta = (-j21 * rx + j11 * ry) / det
        xi -= dxi
        eta -= deta
        if abs(dxi) + abs(deta) < 1e-13:
            break
    return xi, eta


@njit(cache=True)
def natural_coords_3d(x, conn, e, px, py, pz):
    """(xi, eta, zeta) of point p in hex8 element e by Newton's method on the trilinear map.

    x(xi) = sum_k N_k(xi) x_k, N_k = (1 + xi_k xi)(1 + eta_k eta)(1 + zeta_k zeta) / 8; each
    iteration solves J dxi = x(xi) - p (J = dx/dxi, Cramer's rule) from xi = 0, with the 2D
    iteration's limits (20 iterations, |dxi|_1 < 1e-13).
    """
    xi = 0.0
    eta = 0.0
    zeta = 0.0
    for _ in range(20):
        r0 = -px
        r1 = -py
        r2 = -pz
        j00 = j01 = j02 = j10 = j11 = j12 = j20 = j21 = j22 = 0.0
        for k in range(8):
            a = 1.0 + _HXI[k] * xi
            b = 1.0 + _HETA[k] * eta
            c = 1.0 + _HZETA[k] * zeta
            w = 0.125 * a * b * c
            dxi = 0.125 * _HXI[k] * b * c
            deta = 0.125 * _HETA[k] * a * c
            dzeta = 0.125 * _HZETA[k] * a * b
            node = conn[e, k]
            X = x[node, 0]
            Y = x[node, 1]
            Z = x[node, 2]
            r0 += w * X
            r1 += w * Y
            r2 += w * Z
            j00 += dxi * X
            j01 += deta * X
            j02 += dzeta * X
            j10 += dxi * Y
            j11 += deta * Y
            j12 += dzeta * Y
            j20 += dxi * Z
            j21 += deta * Z
            j22 += dzeta * Z
        c00 = j11 * j22 - j12 * j21
        c01 = j12 * j20 - j10 * j22
        c02 = j10 * j21 - j11 * j20
        det = j00 * c00 + j01 * c01 + j02 * c02
        if det == 0.0:
            break
        # J^-1 = adj(J) / det, adj(J)[i, j] = cofactor[j, i]
        d0 = (c00 * r0 + (j02 * j21 - j01 * j22) * r1 + (j01 * j12 - j02 * j11) * r2) / det
        d1 = (c01 * r0 + (j00 * j22 - j02 * j20) * r1 + (j02 * j10 - j00 * j12) * r2) / det
        d2 = (c02 * r0 + (j01 * j20 - j00 * j21) * r1 + (j00 * j11 - j01 * j10) * r2) / det
        xi -= d0
        eta -= d1
        zeta -= d2
        if abs(d0) + abs(d1) + abs(d2) < 1e-13:
            break
    return xi, eta, zeta


@njit(cache=True, inline="always")
def natural(x, conn, e, px, py, pz, dim):
    """(xi, eta, zeta) of point p in element e: ``natural_coords_3d`` (dim 3) or ``natural_coords`` (dim 2,
    zeta 0); dim a literal constant of the caller."""
    if dim == 3:
        return natural_coords_3d(x, conn, e, px, py, pz)
    xi, eta = natural_coords(x, conn, e, px, py)
    return xi, eta, 0.0


@njit(cache=True, inline="always")
def locate_point(x, conn, start, items, origin, cell, nbx, nby, nbz, px, py, pz, dim):
    """(element, xi, eta, zeta) of the element containing point p (natural coordinates within
    1 + INSIDE_TOL), element -1 when outside the mesh; the first such element of p's bucket."""
    ix = int(math.floor((px - origin[0]) / cell))
    iy = int(math.floor((py - origin[1]) / cell))
    iz = 0
    if dim == 3:
        iz = int(math.floor((pz - origin[2]) / cell))
    if ix < 0 or iy < 0 or iz < 0 or ix >= nbx or iy >= nby or iz >= nbz:
        return -1, 0.0, 0.0, 0.0
    b = ix + nbx * (iy + nby * iz)
    for r in range(start[b], start[b + 1]):
        e = items[r]
        xi, eta, zeta = natural(x, conn, e, px, py, pz, dim)
        if abs(xi) <= 1.0 + INSIDE_TOL and abs(eta) <= 1.0 + INSIDE_TOL and (dim == 2 or abs(zeta) <= 1.0 + INSIDE_TOL):
            return e, xi, eta, zeta
    return -1, 0.0, 0.0, 0.0


@njit(cache=True)
def locate_3d(x, conn, start, items, origin, cell, nbx, nby, nbz, px, py, pz):
    """(element, xi, eta, zeta) of the hex8 containing point p, element -1 when outside the mesh (``locate_point``)."""
    return locate_point(x, conn, start, items, origin, cell, nbx, nby, nbz, px, py, pz, 3)


@njit(cache=True, inline="always")
def host_point(xa, conn, start, items, origin, cell, nbx, nby, nbz, frac, min_fraction, probe, leakage, pushing,
               px, py, pz, nx, ny, nz, npe, dim):
    """(element, xi, eta, zeta) hosting a coupling point at p with outward normal n, element -1 for none;
    the natural coordinates clamped to [-1, 1] (``clamp``; 2D: zeta 0).

    A point in contact at the last pass (``pushing``: d^{n-1} > 0 or a host then) keeps a host: the
    element at p if it holds >= min_fraction of coupling fluid, else the one at p + probe n (just in
    front of the face), else with ``leakage`` the one at p - probe n (just behind). A free point
    couples only once it touches or has entered fluid (no force before contact): the element at p,
    else the one at p + probe n that p touches (natural coordinates within 1 + TOUCH_TOL: its fluid
    ends at the element's faces), holds >= min_fraction and p lies at or beyond that element's
    reconstructed interface (``fluid_depth`` >= -TOUCH_TOL probe).
    """
    e, xi, eta, zeta = locate_point(xa, conn, start, items, origin, cell, nbx, nby, nbz, px, py, pz, dim)
    if not pushing:
        touch = -TOUCH_TOL * probe
        entered = touch - 1.0  # the point's distance inside the fluid of its host
        if e >= 0 and frac[e] >= min_fraction:
            entered = fluid_depth(xa, conn, e, px, py, pz, nx, ny, nz, frac[e], dim)
        if entered < touch:
            e, xi, eta, zeta = locate_point(xa, conn, start, items, origin, cell, nbx, nby, nbz,
                                            px + probe * nx, py + probe * ny, pz + probe * nz, dim)
            if e >= 0 and frac[e] >= min_fraction:
                xi, eta, zeta = natural(xa, conn, e, px, py, pz, dim)
                reach = max(abs(xi), abs(eta), abs(zeta)) if dim == 3 else max(abs(xi), abs(eta))
                if reach <= 1.0 + TOUCH_TOL:
                    entered = fluid_depth(xa, conn, e, px, py, pz, nx, ny, nz, frac[e], dim)
            if entered < touch:
                e = -1
    elif e < 0 or frac[e] < min_fraction:
        e, xi, eta, zeta = locate_point(xa, conn, start, items, origin, cell, nbx, nby, nbz,
                                        px + probe * nx, py + probe * ny, pz + probe * nz, dim)
        if e >= 0 and frac[e] >= min_fraction:
            xi, eta, zeta = natural(xa, conn, e, px, py, pz, dim)
        elif leakage:
            e, xi, eta, zeta = locate_point(xa, conn, start, items, origin, cell, nbx, nby, nbz,
                                            px - probe * nx, py - probe * ny, pz - probe * nz, dim)
            if e >= 0 and frac[e] >= min_fraction:
                xi, eta, zeta = natural(xa, conn, e, px, py, pz, dim)
            else:
                e = -1
        else:
            e = -1
    return e, clamp(xi), clamp(eta), clamp(zeta)
