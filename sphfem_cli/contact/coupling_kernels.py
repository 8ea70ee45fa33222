"""Compiled kernels of the ALE -> structure penalty coupling (contact.coupling; docs/theory/coupling.md).

2D: structure segments are 2-node lines, the ALE mesh is quad4 (counter-clockwise); the 3D twins
(quad4 faces against hex8 elements) are in ``coupling_kernels_3d``. Arrays and scalars only.

- ``build_bins``: a uniform grid of buckets over the ALE mesh, each listing the elements whose
  bounding box overlaps it (CSR), rebuilt each step (the mesh may move).
- ``locate``: the element containing a point and its natural coordinates (inverse bilinear map
  by Newton's method), through the buckets.
- ``fluid_side_depth``: how far a point lies inside the fluid of a partly filled element, the
  fluid reconstructed as the part of the element beyond a line parallel to the segment.
- ``coupling_forces``: for every coupling point, the host element, the incremental penetration
  and the penalty force, scattered to the ALE nodes and the segment nodes (serial: a point
  writes to nodes that other points share).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

_XI = np.array([-1.0, 1.0, 1.0, -1.0])
_ETA = np.array([-1.0, -1.0, 1.0, 1.0])
INSIDE_TOL = 1e-9  # natural-coordinate tolerance of "inside an element"
TOUCH_TOL = 1e-6  # a free point within this fraction of the probe distance of the fluid touches it
TWO_PI = 2.0 * math.pi


@njit(cache=True)
def build_bins(x, conn, origin, cell, nbx, nby):
    """(start, items): the elements overlapping each bucket (bucket index = ix + nbx * iy)."""
    n_elem = conn.shape[0]
    count = np.zeros(nbx * nby + 1, dtype=np.int64)
    lo = np.empty((n_elem, 2), dtype=np.int64)
    hi = np.empty((n_elem, 2), dtype=np.int64)
    for e in range(n_elem):
        for d in range(2):
            a = x[conn[e, 0], d]
            b = a
            for k in range(1, 4):
                v = x[conn[e, k], d]
                a = min(a, v)
                b = max(b, v)
            nb = nbx if d == 0 else nby
            i0 = int(math.floor((a - origin[d]) / cell))
            i1 = int(math.floor((b - origin[d]) / cell))
            lo[e, d] = min(max(i0, 0), nb - 1)
            hi[e, d] = min(max(i1, 0), nb - 1)
        for iy in range(lo[e, 1], hi[e, 1] + 1):
            for ix in range(lo[e, 0], hi[e, 0] + 1):
                count[ix + nbx * iy + 1] += 1
    start = np.cumsum(count)
    items = np.empty(start[-1], dtype=np.int64)
    fill = start[:-1].copy()
    for e in range(n_elem):
        for iy in range(lo[e, 1], hi[e, 1] + 1):
            for ix in range(lo[e, 0], hi[e, 0] + 1):
                b = ix + nbx * iy
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
def locate(x, conn, start, items, origin, cell, nbx, nby, px, py):
    """(element, xi, eta) containing point (px, py), element -1 when outside the mesh."""
    ix = int(math.floor((px - origin[0]) / cell))
    iy = int(math.floor((py - origin[1]) / cell))
    if ix < 0 or iy < 0 or ix >= nbx or iy >= nby:
        return -1, 0.0, 0.0
    b = ix + nbx * iy
    for r in range(start[b], start[b + 1]):
        e = items[r]
        xi, eta = natural_coords(x, conn, e, px, py)
        if abs(xi) <= 1.0 + INSIDE_TOL and abs(eta) <= 1.0 + INSIDE_TOL:
            return e, xi, eta
    return -1, 0.0, 0.0


@njit(cache=True)
def _clamp(a):
    return min(1.0, max(-1.0, a))


@njit(cache=True)
def _area_beyond(px4, py4, nx, ny, level):
    """Area of the quadrilateral (px4, py4) where x . n >= level (Sutherland-Hodgman clip, shoelace)."""
    cx = np.empty(8)
    cy = np.empty(8)
    m = 0
    for k in range(4):
        j = (k + 1) % 4
        sk = px4[k] * nx + py4[k] * ny - level
        sj = px4[j] * nx + py4[j] * ny - level
        if sk >= 0.0:
            cx[m] = px4[k]
            cy[m] = py4[k]
            m += 1
        if (sk >= 0.0) != (sj >= 0.0):
            t = sk / (sk - sj)
            cx[m] = px4[k] + t * (px4[j] - px4[k])
            cy[m] = py4[k] + t * (py4[j] - py4[k])
            m += 1
    area = 0.0
    for k in range(m):
        j = (k + 1) % m
        area += cx[k] * cy[j] - cx[j] * cy[k]
    return 0.5 * area


@njit(cache=True)
def fluid_side_depth(x, conn, e, px, py, nx, ny, fraction):
    """Signed distance of point (px, py) beyond the fluid interface of element e (> 0: in the fluid).

    The element's fluid (volume fraction phi = ``fraction``) is reconstructed as the part of the
    element in front of a line normal to n (the segment's outward normal, pointing into the
    fluid): {x : x . n >= L} with area phi A (PLIC with the normal given rather than taken from
    the fraction gradient; Youngs 1982 for the construction), L found by bisection. Returns
    p . n - L. A full element (phi >= 1) gives the distance from its rearmost corner, >= 0
    inside it; an empty one a negative number.
    """
    px4 = np.empty(4)
    py4 = np.empty(4)
    lo = np.inf
    hi = -np.inf
    for k in range(4):
        px4[k] = x[conn[e, k], 0]
        py4[k] = x[conn[e, k], 1]
        t = px4[k] * nx + py4[k] * ny
        lo = min(lo, t)
        hi = max(hi, t)
    tp = px * nx + py * ny
    if fraction >= 1.0:
        return tp - lo
    if fraction <= 0.0:
        return tp - hi
    target = fraction * _area_beyond(px4, py4, nx, ny, lo)
    a = lo
    b = hi
    for _ in range(60):  # the area beyond L falls monotonically from A at lo to 0 at hi
        mid = 0.5 * (a + b)
        if _area_beyond(px4, py4, nx, ny, mid) > target:
            a = mid
        else:
            b = mid
        if b - a <= 1e-12 * (hi - lo):
            break
    return tp - 0.5 * (a + b)


@njit(cache=True)
def coupling_forces(seg, xs, vs, ms, nquad, xa, va, ma, conn, start, items, origin, cell, nbx, nby,
                    frac, bulk, area, min_fraction, pfac, damping, probe, leakage, dt_prev, ring,
                    depth, host, stiff, fs, fa):
    """Penalty coupling forces of state n; returns the number of coupled points.

    seg (S, 2) segment nodes (outward normal to the right of a -> b); xs, vs, ms structure nodes;
    xa, va, ma ALE nodes; frac (E,) coupling-fluid volume fraction, bulk (E,) its bulk modulus,
    area (E,) element areas; probe the distance of the front / behind probes. Point q of segment
    s is entry s * nquad + q of depth (penetration, updated in place), host (element, -1 when not
    coupled) and stiff (penalty stiffness). Forces are added to fs (structure) and fa (ALE).

    ring (``dimension: axisymmetric``, x = r): a point at radius r_p stands for the ring it sweeps,
    of area A = 2 pi r_p l, area (E,) holds the hosts' ring volumes V and masses are ring masses,
    so k = pfac K A^2 / V and every force is for the full 2 pi (as the FEM and ALE r-z forces).
    A point on the axis (r_p = 0) has A = 0 and carries no force. Plane (ring False): A = l.
    """
    n_seg = seg.shape[0]
    coupled = 0
    for s in range(n_seg):
        a = seg[s, 0]
        b = seg[s, 1]
        tx = xs[b, 0] - xs[a, 0]
        ty = xs[b, 1] - xs[a, 1]
        length = math.sqrt(tx * tx + ty * ty)
        if length == 0.0:
            continue
        nx = ty / length
        ny = -tx / length
        ell = length / nquad
        for q in range(nquad):
            i = s * nquad + q
            r = -1.0 + (2.0 * q + 1.0) / nquad
            n1 = 0.5 * (1.0 - r)
            n2 = 0.5 * (1.0 + r)
            px = n1 * xs[a, 0] + n2 * xs[b, 0]
            py = n1 * xs[a, 1] + n2 * xs[b, 1]
            # A point in contact at the last pass keeps a host: the fluid at the point, else just in
            # front of the segment, else (leakage) just behind. A free point couples only once it
            # touches or has entered fluid (no force before contact): the element at the point,
            # else the one just in front, holds at least min_fraction and the point lies at or
            # beyond that element's reconstructed interface.
            pushing = depth[i] > 0.0 or host[i] >= 0  # in contact at the last pass
            e, xi, eta = locate(xa, conn, start, items, origin, cell, nbx, nby, px, py)
            if not pushing:
                touch = -TOUCH_TOL * probe
                entered = touch - 1.0  # the point's distance inside the fluid of its host
                if e >= 0 and frac[e] >= min_fraction:
                    entered = fluid_side_depth(xa, conn, e, px, py, nx, ny, frac[e])
                if entered < touch:
                    e, xi, eta = locate(xa, conn, start, items, origin, cell, nbx, nby,
                                        px + probe * nx, py + probe * ny)
                    if e >= 0 and frac[e] >= min_fraction:
                        xi, eta = natural_coords(xa, conn, e, px, py)
                        # the point must touch that element (its fluid ends at the element's faces)
                        if max(abs(xi), abs(eta)) <= 1.0 + TOUCH_TOL:
                            entered = fluid_side_depth(xa, conn, e, px, py, nx, ny, frac[e])
                    if entered < touch:
                        e = -1
            elif e < 0 or frac[e] < min_fraction:
                e, xi, eta = locate(xa, conn, start, items, origin, cell, nbx, nby, px + probe * nx, py + probe * ny)
                if e >= 0 and frac[e] >= min_fraction:
                    xi, eta = natural_coords(xa, conn, e, px, py)
                elif leakage:
                    e, xi, eta = locate(xa, conn, start, items, origin, cell, nbx, nby,
                                        px - probe * nx, py - probe * ny)
                    if e >= 0 and frac[e] >= min_fraction:
                        xi, eta = natural_coords(xa, conn, e, px, py)
                    else:
                        e = -1
                else:
                    e = -1
            if e < 0:
                depth[i] = 0.0
                host[i] = -1
                stiff[i] = 0.0
                continue
            xi = _clamp(xi)
            eta = _clamp(eta)
            vfx = 0.0
            vfy = 0.0
            mf = 0.0
            for k in range(4):
                w = 0.25 * (1.0 + _XI[k] * xi) * (1.0 + _ETA[k] * eta)
                node = conn[e, k]
                vfx += w * va[node, 0]
                vfy += w * va[node, 1]
                mf += w * ma[node]
            vsx = n1 * vs[a, 0] + n2 * vs[b, 0]
            vsy = n1 * vs[a, 1] + n2 * vs[b, 1]
            msp = n1 * ms[a] + n2 * ms[b]
            rate = -((vfx - vsx) * nx + (vfy - vsy) * ny)  # closing speed of the fluid onto the segment
            d = depth[i] + dt_prev * rate  # depth is 0 where the point was not coupled
            if d < 0.0:
                d = 0.0
            depth[i] = d
            host[i] = e
            share = ell  # the point's share of the face: its length, or its ring's area
            if ring:
                share = TWO_PI * px * ell
            k_pen = pfac * bulk[e] * share * share / area[e]
            stiff[i] = k_pen
            if d <= 0.0:
                continue
            fn = k_pen * d
            if damping > 0.0 and mf > 0.0 and msp > 0.0:
                fn += damping * 2.0 * math.sqrt(k_pen * mf * msp / (mf + msp)) * rate
            if fn <= 0.0:
                continue
            coupled += 1
            fx = fn * nx
            fy = fn * ny
            for k in range(4):
                w = 0.25 * (1.0 + _XI[k] * xi) * (1.0 + _ETA[k] * eta)
                node = conn[e, k]
                fa[node, 0] += w * fx
                fa[node, 1] += w * fy
            fs[a, 0] -= n1 * fx
            fs[a, 1] -= n1 * fy
            fs[b, 0] -= n2 * fx
            fs[b, 1] -= n2 * fy
    return coupled


@njit(cache=True)
def stiffness_sums(seg, nquad, conn, host, stiff, xs, xa, sum_s, sum_a):
    """Per node, sum over coupled points of (shape-function weight x penalty stiffness).

    The Gershgorin bound of the coupling's stiffness matrix: its largest eigenvalue relative to
    the lumped masses is at most max_i 2 sum_i / m_i (each point's weights sum to 1 on either side).
    """
    n_seg = seg.shape[0]
    for s in range(n_seg):
        a = seg[s, 0]
        b = seg[s, 1]
        for q in range(nquad):
            i = s * nquad + q
            e = host[i]
            if e < 0:
                continue
            k_pen = stiff[i]
            r = -1.0 + (2.0 * q + 1.0) / nquad
            n1 = 0.5 * (1.0 - r)
            n2 = 0.5 * (1.0 + r)
            sum_s[a] += n1 * k_pen
            sum_s[b] += n2 * k_pen
            px = n1 * xs[a, 0] + n2 * xs[b, 0]
            py = n1 * xs[a, 1] + n2 * xs[b, 1]
            xi, eta = natural_coords(xa, conn, e, px, py)
            xi = _clamp(xi)
            eta = _clamp(eta)
            for k in range(4):
                w = 0.25 * (1.0 + _XI[k] * xi) * (1.0 + _ETA[k] * eta)
                sum_a[conn[e, k]] += w * k_pen
