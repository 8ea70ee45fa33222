"""Compiled kernels of the ALE -> structure penalty coupling in 3D (contact.coupling; docs/theory/coupling.md "3D").

hex8 ALE elements (corners in VTK order, model.mesh._HEX_XI) against the quad4 faces of a solid or
rigid part (a, b, c, d with the outward normal by the right-hand rule, contact.surface); the same
host rules, penetration and penalty as the 2D kernels (``coupling_kernels``). numba compiles a
function at its first call, so a 2D deck compiles none of these. Arrays and scalars only.

- ``build_bins_3d``, ``locate_3d``, ``natural_coords_3d``: buckets over the hex bounding boxes and the
  inverse trilinear map by Newton's method.
- ``face_point``, ``face_shares``: nquad x nquad coupling points per face and their area shares.
- ``fluid_side_depth_3d``, ``hex_volume_beyond``: the fluid of a partly filled hex as the part beyond
  a plane parallel to the face (six clipped tetrahedra).
- ``coupling_forces_3d``, ``stiffness_sums_3d``: forces, scatters and the stable-step sums.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .coupling_kernels import INSIDE_TOL, TOUCH_TOL, _clamp

_HXI = np.array([-1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0, -1.0])
_HETA = np.array([-1.0, -1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0])
_HZETA = np.array([-1.0, -1.0, -1.0, -1.0, 1.0, 1.0, 1.0, 1.0])
# the six tetrahedra around the diagonal 0-6 that fill a hex8 (for its clipped volume)
_HEX_TETS = np.array([[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]])
_GAUSS2 = 1.0 / math.sqrt(3.0)


@njit(cache=True)
def build_bins_3d(x, conn, origin, cell, nbx, nby, nbz):
    """(start, items): the hex8 elements overlapping each bucket (index ix + nbx (iy + nby iz))."""
    n_elem = conn.shape[0]
    count = np.zeros(nbx * nby * nbz + 1, dtype=np.int64)
    lo = np.empty((n_elem, 3), dtype=np.int64)
    hi = np.empty((n_elem, 3), dtype=np.int64)
    for e in range(n_elem):
        for d in range(3):
            a = x[conn[e, 0], d]
            b = a
            for k in range(1, 8):
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


@njit(cache=True)
def locate_3d(x, conn, start, items, origin, cell, nbx, nby, nbz, px, py, pz):
    """(element, xi, eta, zeta) of the hex8 containing point p, element -1 when outside the mesh."""
    ix = int(math.floor((px - origin[0]) / cell))
    iy = int(math.floor((py - origin[1]) / cell))
    iz = int(math.floor((pz - origin[2]) / cell))
    if ix < 0 or iy < 0 or iz < 0 or ix >= nbx or iy >= nby or iz >= nbz:
        return -1, 0.0, 0.0, 0.0
    b = ix + nbx * (iy + nby * iz)
    for r in range(start[b], start[b + 1]):
        e = items[r]
        xi, eta, zeta = natural_coords_3d(x, conn, e, px, py, pz)
        if abs(xi) <= 1.0 + INSIDE_TOL and abs(eta) <= 1.0 + INSIDE_TOL and abs(zeta) <= 1.0 + INSIDE_TOL:
            return e, xi, eta, zeta
    return -1, 0.0, 0.0, 0.0


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


@njit(cache=True)
def _tet_volume(p0, p1, p2, p3):
    """|det(p1 - p0, p2 - p0, p3 - p0)| / 6."""
    ax = p1[0] - p0[0]
    ay = p1[1] - p0[1]
    az = p1[2] - p0[2]
    bx = p2[0] - p0[0]
    by = p2[1] - p0[1]
    bz = p2[2] - p0[2]
    cx = p3[0] - p0[0]
    cy = p3[1] - p0[1]
    cz = p3[2] - p0[2]
    return abs(ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6.0


@njit(cache=True)
def _cut(pa, pb, sa, sb):
    """The point of edge a-b where the signed distance s (sa > 0 >= sb or the reverse) is 0."""
    t = sa / (sa - sb)
    q = np.empty(3)
    for k in range(3):
        q[k] = pa[k] + t * (pb[k] - pa[k])
    return q


@njit(cache=True)
def _tet_volume_beyond(pt, sd):
    """Volume of tetrahedron pt (4, 3) where the signed distance sd (4,) is > 0 (convex clip).

    One vertex beyond: the corner tetrahedron at it; three: the whole less the corner tetrahedron
    at the fourth; two (a, b beyond, c, d not): the wedge cut off, fanned from a over its faces
    that do not hold a, triangle (b, q_bc, q_bd) and quad (q_ac, q_ad, q_bd, q_bc).
    """
    n_pos = 0
    for k in range(4):
        if sd[k] > 0.0:
            n_pos += 1
    if n_pos == 0:
        return 0.0
    whole = _tet_volume(pt[0], pt[1], pt[2], pt[3])
    if n_pos == 4:
        return whole
    if n_pos == 1 or n_pos == 3:
        lone = 0
        for k in range(4):
            if (sd[k] > 0.0) == (n_pos == 1):
                lone = k
        o0 = (lone + 1) % 4
        o1 = (lone + 2) % 4
        o2 = (lone + 3) % 4
        corner = _tet_volume(pt[lone], _cut(pt[lone], pt[o0], sd[lone], sd[o0]),
                             _cut(pt[lone], pt[o1], sd[lone], sd[o1]), _cut(pt[lone], pt[o2], sd[lone], sd[o2]))
        return corner if n_pos == 1 else whole - corner
    ia = -1
    ib = -1
    ic = -1
    id_ = -1
    for k in range(4):
        if sd[k] > 0.0:
            if ia < 0:
                ia = k
            else:
                ib = k
        else:
            if ic < 0:
                ic = k
            else:
                id_ = k
    a = pt[ia]
    b = pt[ib]
    qac = _cut(a, pt[ic], sd[ia], sd[ic])
    qad = _cut(a, pt[id_], sd[ia], sd[id_])
    qbc = _cut(b, pt[ic], sd[ib], sd[ic])
    qbd = _cut(b, pt[id_], sd[ib], sd[id_])
    return _tet_volume(a, b, qbc, qbd) + _tet_volume(a, qac, qad, qbd) + _tet_volume(a, qac, qbd, qbc)


@njit(cache=True)
def hex_volume_beyond(ph, nx, ny, nz, level):
    """Volume of hex8 ph (8, 3) where x . n > level: its six tetrahedra about the diagonal 0-6, clipped."""
    pt = np.empty((4, 3))
    sd = np.empty(4)
    vol = 0.0
    for t in range(6):
        for k in range(4):
            c = _HEX_TETS[t, k]
            pt[k, 0] = ph[c, 0]
            pt[k, 1] = ph[c, 1]
            pt[k, 2] = ph[c, 2]
            sd[k] = ph[c, 0] * nx + ph[c, 1] * ny + ph[c, 2] * nz - level
        vol += _tet_volume_beyond(pt, sd)
    return vol


@njit(cache=True)
def fluid_side_depth_3d(x, conn, e, px, py, pz, nx, ny, nz, fraction):
    """Signed distance of point p beyond the fluid interface of hex8 element e (> 0: in the fluid).

    The 3D form of ``fluid_side_depth``: the element's fluid (volume fraction phi) is the part of
    the element in front of a plane normal to n (the face's outward normal, into the fluid),
    {x : x . n >= L} with volume phi V (PLIC with the normal given; Youngs 1982), the volumes
    those of the element's six tetrahedra clipped by the plane, L by bisection. Returns p . n - L;
    a full element gives the distance from its rearmost corner, an empty one a negative number.
    """
    ph = np.empty((8, 3))
    lo = np.inf
    hi = -np.inf
    for k in range(8):
        for d in range(3):
            ph[k, d] = x[conn[e, k], d]
        t = ph[k, 0] * nx + ph[k, 1] * ny + ph[k, 2] * nz
        lo = min(lo, t)
        hi = max(hi, t)
    tp = px * nx + py * ny + pz * nz
    if fraction >= 1.0:
        return tp - lo
    if fraction <= 0.0:
        return tp - hi
    target = fraction * hex_volume_beyond(ph, nx, ny, nz, lo - (hi - lo))
    a = lo
    b = hi
    for _ in range(60):  # the volume beyond L falls monotonically from V at lo to 0 at hi
        mid = 0.5 * (a + b)
        if hex_volume_beyond(ph, nx, ny, nz, mid) > target:
            a = mid
        else:
            b = mid
        if b - a <= 1e-12 * (hi - lo):
            break
    return tp - 0.5 * (a + b)


@njit(cache=True)
def face_shares(xs, faces, nquad, share):
    """share (S nquad^2,): the area share of every coupling point (point qr nquad + qs of face s)."""
    for s in range(faces.shape[0]):
        for qr in range(nquad):
            for qs in range(nquad):
                share[(s * nquad + qr) * nquad + qs] = face_point(xs, faces[s], nquad, qr, qs)[3]


@njit(cache=True)
def _hex_weights(xi, eta, zeta, w):
    for k in range(8):
        w[k] = 0.125 * (1.0 + _HXI[k] * xi) * (1.0 + _HETA[k] * eta) * (1.0 + _HZETA[k] * zeta)


@njit(cache=True)
def _host_3d(xa, conn, start, items, origin, cell, nb, frac, min_fraction, probe, leakage, pushing, p, n):
    """(element, xi, eta, zeta) hosting a coupling point at p with outward normal n, element -1 for none.

    The 2D kernel's rules (coupling_forces): a point in contact at the last pass (``pushing``)
    keeps the element at p if it holds >= min_fraction, else the one at p + probe n, else with
    ``leakage`` the one at p - probe n; a free point couples once it touches or has entered the
    fluid of the element at p, else of the element at p + probe n that p touches.
    """
    e, xi, eta, zeta = locate_3d(xa, conn, start, items, origin, cell, nb[0], nb[1], nb[2], p[0], p[1], p[2])
    if not pushing:
        touch = -TOUCH_TOL * probe
        entered = touch - 1.0
        if e >= 0 and frac[e] >= min_fraction:
            entered = fluid_side_depth_3d(xa, conn, e, p[0], p[1], p[2], n[0], n[1], n[2], frac[e])
        if entered < touch:
            e, xi, eta, zeta = locate_3d(xa, conn, start, items, origin, cell, nb[0], nb[1], nb[2],
                                         p[0] + probe * n[0], p[1] + probe * n[1], p[2] + probe * n[2])
            if e >= 0 and frac[e] >= min_fraction:
                xi, eta, zeta = natural_coords_3d(xa, conn, e, p[0], p[1], p[2])
                if max(abs(xi), abs(eta), abs(zeta)) <= 1.0 + TOUCH_TOL:
                    entered = fluid_side_depth_3d(xa, conn, e, p[0], p[1], p[2], n[0], n[1], n[2], frac[e])
            if entered < touch:
                e = -1
    elif e < 0 or frac[e] < min_fraction:
        e, xi, eta, zeta = locate_3d(xa, conn, start, items, origin, cell, nb[0], nb[1], nb[2],
                                     p[0] + probe * n[0], p[1] + probe * n[1], p[2] + probe * n[2])
        if e >= 0 and frac[e] >= min_fraction:
            xi, eta, zeta = natural_coords_3d(xa, conn, e, p[0], p[1], p[2])
        elif leakage:
            e, xi, eta, zeta = locate_3d(xa, conn, start, items, origin, cell, nb[0], nb[1], nb[2],
                                         p[0] - probe * n[0], p[1] - probe * n[1], p[2] - probe * n[2])
            if e >= 0 and frac[e] >= min_fraction:
                xi, eta, zeta = natural_coords_3d(xa, conn, e, p[0], p[1], p[2])
            else:
                e = -1
        else:
            e = -1
    return e, _clamp(xi), _clamp(eta), _clamp(zeta)


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
    for s in range(faces.shape[0]):
        f = faces[s]
        for qr in range(nquad):
            for qs in range(nquad):
                i = (s * nquad + qr) * nquad + qs
                w, p, n, share = face_point(xs, f, nquad, qr, qs)
                if share == 0.0:
                    continue
                pushing = depth[i] > 0.0 or host[i] >= 0
                e, xi, eta, zeta = _host_3d(xa, conn, start, items, origin, cell, nb, frac, min_fraction, probe,
                                            leakage, pushing, p, n)
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
                dn = depth[i] + dt_prev * rate
                if dn < 0.0:
                    dn = 0.0
                depth[i] = dn
                host[i] = e
                k_pen = pfac * bulk[e] * share * share / vol[e]
                stiff[i] = k_pen
                if dn <= 0.0:
                    continue
                fn = k_pen * dn
                if damping > 0.0 and mf > 0.0 and msp > 0.0:
                    fn += damping * 2.0 * math.sqrt(k_pen * mf * msp / (mf + msp)) * rate
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
    for s in range(faces.shape[0]):
        f = faces[s]
        for qr in range(nquad):
            for qs in range(nquad):
                i = (s * nquad + qr) * nquad + qs
                e = host[i]
                if e < 0:
                    continue
                k_pen = stiff[i]
                w, p, _, _ = face_point(xs, f, nquad, qr, qs)
                for j in range(4):
                    sum_s[f[j]] += w[j] * k_pen
                xi, eta, zeta = natural_coords_3d(xa, conn, e, p[0], p[1], p[2])
                _hex_weights(_clamp(xi), _clamp(eta), _clamp(zeta), wa)
                for k in range(8):
                    sum_a[conn[e, k]] += wa[k] * k_pen
