"""Compiled kernels of the ALE -> structure penalty coupling in 3D (contact.coupling; docs/theory/coupling.md "3D").

hex8 ALE elements (corners in VTK order, model.mesh._HEX_XI) against the quad4 faces of a solid or
rigid part (a, b, c, d with the outward normal by the right-hand rule, contact.surface); the same
host rules, penetration and penalty as the 2D kernels (``coupling_kernels``), from the same bodies
(``coupling_search``, ``coupling_common``) with the hex8's corner count and dimension. numba compiles a
function at its first call, so a 2D deck compiles none of these. Arrays and scalars only.

- ``build_bins_3d``: buckets over the hex bounding boxes (``coupling_search``, which also holds
  ``locate_3d`` and ``natural_coords_3d``, the inverse trilinear map by Newton's method).
- ``face_point``, ``face_shares``: nquad x nquad coupling points per face and their area shares.
- in ``coupling_common``: the fluid of a partly filled hex as the part beyond a plane parallel to the
  face (``fluid_side_depth_3d``, ``hex_volume_beyond``: six clipped tetrahedra).
- ``coupling_forces_3d``, ``stiffness_sums_3d``: forces, scatters and the stable-step sums.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .coupling_common import penalty
from .coupling_search import _HETA, _HXI, _HZETA, bin_elements, clamp, host_point, natural_coords_3d

_GAUSS2 = 1.0 / math.sqrt(3.0)


@njit(cache=True)
def build_bins_3d(x, conn, origin, cell, nbx, nby, nbz):
    """(start, items): the hex8 elements overlapping each bucket (index ix + nbx (iy + nby iz); the body
    ``coupling_search.bin_elements``, shared with the quad4 form)."""
    return bin_elements(x, conn, origin, cell, nbx, nby, nbz, 8, 3)


@njit(cache=True)
def _face_tangents(xs, f, r, s):
    """(x_r, x_s) of the bilinear quad face f (nodes a, b, c, d at (r, s) = (-1,-1), (1,-1), (1,1), (-1,1))."""
    a = f[0]
    b = f[1]
    c = f[2]
    d = f[3]
    xr = np.empty(3)
    xsv = np.empty(3)
    for k in range(3):
        xr[k] = 0.25 * ((1.0 - s) * (xs[b, k] - xs[a, k]) + (1.0 + s) * (xs[c, k] - xs[d, k]))
        xsv[k] = 0.25 * ((1.0 - r) * (xs[d, k] - xs[a, k]) + (1.0 + r) * (xs[c, k] - xs[b, k]))
    return xr, xsv


@njit(cache=True)
def face_point(xs, f, nquad, qr, qs):
    """Coupling point (qr, qs) of quad face f: (weights (4,), position (3,), unit normal (3,), area share).

    The face's parameter square [-1, 1]^2 is cut into nquad x nquad equal cells; the point is a
    cell's centre (r_q = -1 + (2 qr + 1) / nquad, s_q alike: the tensor product of the 2D
    kernel's points, so a deck extruded from 2D carries the same points), its weights the
    bilinear shape functions N_a..N_d there, its normal x_r x x_s / |x_r x x_s| there (outward),
    and its area share the cell's area, the integral of |x_r x x_s| over the cell by 2 x 2 Gauss
    points (exact for a plane face, where |x_r x x_s| is linear in r and s): the shares of a face
    sum to its area.
    """
    h = 1.0 / nquad
    r = -1.0 + (2.0 * qr + 1.0) * h
    s = -1.0 + (2.0 * qs + 1.0) * h
    w = np.empty(4)
    w[0] = 0.25 * (1.0 - r) * (1.0 - s)
    w[1] = 0.25 * (1.0 + r) * (1.0 - s)
    w[2] = 0.25 * (1.0 + r) * (1.0 + s)
    w[3] = 0.25 * (1.0 - r) * (1.0 + s)
    p = np.zeros(3)
    for j in range(4):
        for k in range(3):
            p[k] += w[j] * xs[f[j], k]
    xr, xsv = _face_tangents(xs, f, r, s)
    n = np.empty(3)
    n[0] = xr[1] * xsv[2] - xr[2] * xsv[1]
    n[1] = xr[2] * xsv[0] - xr[0] * xsv[2]
    n[2] = xr[0] * xsv[1] - xr[1] * xsv[0]
    norm = math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
    if norm > 0.0:
        for k in range(3):
            n[k] /= norm
    share = 0.0
    for gi in range(2):
        for gj in range(2):
            rg = r + (2 * gi - 1) * _GAUSS2 * h
            sg = s + (2 * gj - 1) * _GAUSS2 * h
            ar, as_ = _face_tangents(xs, f, rg, sg)
            c0 = ar[1] * as_[2] - ar[2] * as_[1]
            c1 = ar[2] * as_[0] - ar[0] * as_[2]
            c2 = ar[0] * as_[1] - ar[1] * as_[0]
            share += math.sqrt(c0 * c0 + c1 * c1 + c2 * c2) * h * h  # cell of (2h)^2, Gauss weights 1/4
    return w, p, n, share


@njit(cache=True, inline="always")
def point_index(i, nquad):
    """(face s, qr, qs) of coupling point i = (s nquad + qr) nquad + qs (the points of a face in a row, qs fastest)."""
    s = i // (nquad * nquad)
    q = i - s * nquad * nquad
    qr = q // nquad
    return s, qr, q - qr * nquad



@njit(cache=True)
def face_shares(xs, faces, nquad, share):
    """share (S nquad^2,): the area share of every coupling point (point qr nquad + qs of face s)."""
    for i in range(faces.shape[0] * nquad * nquad):
        s, qr, qs = point_index(i, nquad)
        share[i] = face_point(xs, faces[s], nquad, qr, qs)[3]


@njit(cache=True)
def _hex_weights(xi, eta, zeta, w):
    for k in range(8):
        w[k] = 0.125 * (1.0 + _HXI[k] * xi) * (1.0 + _HETA[k] * eta) * (1.0 + _HZETA[k] * zeta)


@njit(cache=True)
def coupling_forces_3d(faces, xs, vs, ms, nquad, xa, va, ma, conn, start, items, origin, cell, nb,
                       frac, bulk, vol, min_fraction, pfac, damping, probe, leakage, dt_prev,
                       depth, host, stiff, fs, fa):
    """Penalty coupling forces of state n in 3D; returns the number of coupled points.

    The 2D ``coupling_forces`` on quad faces (S, 4) and hex8 ALE elements: point (qr, qs) of face
    s (``face_point``: position, bilinear weights N_a..N_d, outward normal n, area share A) is
    entry (s nquad + qr) nquad + qs of depth, host and stiff; nb (3,) the bucket counts, vol (E,)
    the elements' volumes. d^n = max(0, d^{n-1} + dt^{n-1/2} (v_s - v_f) . n), k = pfac K A^2 / V,
    f = k d + zeta 2 sqrt(k m_f m_s / (m_f + m_s)) (v_s - v_f) . n >= 0; +N_I f n to the host's
    eight nodes, -N_j f n to the face's four.
    """
    coupled = 0
    wa = np.empty(8)
    for i in range(faces.shape[0] * nquad * nquad):
        s, qr, qs = point_index(i, nquad)
        f = faces[s]
        w, p, n, share = face_point(xs, f, nquad, qr, qs)
        if share == 0.0:
            continue
        pushing = depth[i] > 0.0 or host[i] >= 0
        e, xi, eta, zeta = host_point(xa, conn, start, items, origin, cell, nb[0], nb[1], nb[2], frac, min_fraction,
                                      probe, leakage, pushing, p[0], p[1], p[2], n[0], n[1], n[2], 8, 3)
        if e < 0:
            depth[i] = 0.0
            host[i] = -1
            stiff[i] = 0.0
            continue
        _hex_weights(xi, eta, zeta, wa)
        rate = 0.0  # closing speed of the fluid onto the face, (v_s - v_f) . n
        mf = 0.0
        for k in range(8):
            node = conn[e, k]
            mf += wa[k] * ma[node]
            for d in range(3):
                rate += wa[k] * va[node, d] * n[d]
        rate = -rate
        msp = 0.0
        for j in range(4):
            msp += w[j] * ms[f[j]]
            for d in range(3):
                rate += w[j] * vs[f[j], d] * n[d]
        fn = penalty(depth, host, stiff, i, e, dt_prev, rate, pfac, bulk[e], share, vol[e], damping, mf, msp)
        if fn <= 0.0:
            continue
        coupled += 1
        for d in range(3):
            fd = fn * n[d]
            for k in range(8):
                fa[conn[e, k], d] += wa[k] * fd
            for j in range(4):
                fs[f[j], d] -= w[j] * fd
    return coupled


@njit(cache=True)
def stiffness_sums_3d(faces, nquad, conn, host, stiff, xs, xa, sum_s, sum_a):
    """The 3D ``stiffness_sums``: per node, sum over coupled points of shape weight x stiffness."""
    wa = np.empty(8)
    for i in range(faces.shape[0] * nquad * nquad):
        e = host[i]
        if e < 0:
            continue
        k_pen = stiff[i]
        s, qr, qs = point_index(i, nquad)
        f = faces[s]
        w, p, _, _ = face_point(xs, f, nquad, qr, qs)
        for j in range(4):
            sum_s[f[j]] += w[j] * k_pen
        xi, eta, zeta = natural_coords_3d(xa, conn, e, p[0], p[1], p[2])
        _hex_weights(clamp(xi), clamp(eta), clamp(zeta), wa)
        for k in range(8):
            sum_a[conn[e, k]] += wa[k] * k_pen
