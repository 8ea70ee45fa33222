"""Compiled kernels of nodes-to-surface penalty contact (2D segments and 3D bilinear quads).

Conventions: slave points (SPH particles or nodes) `xp` (P, dim); master nodes `xm` (N, dim);
master segments `faces` (S, 2|4), outward-oriented (see contact.surface). The gap g of a point
is its signed distance from the segment along the outward normal n; with contact thickness t the
penetration is d = t - g, and a point with d > 0 (and g above the segment's depth limit -depth)
receives the penalty force

    f = k d n - c (v_rel . n) n + f_t,     c = 2 zeta sqrt(k m),  f . n >= 0 (no adhesion),

with v_rel = v_point - v_master(point) and f_t Coulomb friction |f_t| <= mu f.n opposing the
tangential slip (LS-DYNA's penalty contact with viscous damping VDC and static=dynamic friction).
The reaction -f goes to the segment's nodes through the segment's shape functions at the
contact point, so the pair exerts equal and opposite forces.

Search: segments are binned in a uniform cell grid by their bounding boxes grown by `reach`;
a point looks only at the segments of its own cell (counting sort, as the SPH neighbour search).
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange


@njit(cache=True)
def bin_segments(xm, faces, reach, lo, cell, ncell):
    """Counting sort of segments into the cells their grown bounding boxes touch.

    Returns (cell_start (C+1,), cell_segments) with C = prod(ncell), cells numbered x-fastest.
    """
    n_seg, nn = faces.shape
    dim = xm.shape[1]
    n_cells = 1
    for k in range(dim):
        n_cells *= ncell[k]
    count = np.zeros(n_cells + 1, dtype=np.int64)
    lo_c = np.empty(dim, dtype=np.int64)
    hi_c = np.empty(dim, dtype=np.int64)
    for sweep in range(2):
        if sweep == 1:
            for c in range(n_cells):
                count[c + 1] += count[c]
            fill = count[:-1].copy()
            segs = np.empty(count[n_cells], dtype=np.int64)
        for s in range(n_seg):
            for k in range(dim):
                a = xm[faces[s, 0], k]
                b = a
                for j in range(1, nn):
                    a = min(a, xm[faces[s, j], k])
                    b = max(b, xm[faces[s, j], k])
                lo_c[k] = max(0, min(ncell[k] - 1, int((a - reach - lo[k]) / cell)))
                hi_c[k] = max(0, min(ncell[k] - 1, int((b + reach - lo[k]) / cell)))
            kz_hi = hi_c[2] if dim == 3 else 0
            kz_lo = lo_c[2] if dim == 3 else 0
            for kz in range(kz_lo, kz_hi + 1):
                for ky in range(lo_c[1], hi_c[1] + 1):
                    for kx in range(lo_c[0], hi_c[0] + 1):
                        c = kx + ncell[0] * (ky + ncell[1] * kz)
                        if sweep == 0:
                            count[c + 1] += 1
                        else:
                            segs[fill[c]] = s
                            fill[c] += 1
    return count, segs


@njit(cache=True)
def _project_2d(p, xm, face, w, normal):
    """Closest point of segment a->b to p: weights w (2), contact normal; returns (gap, inside)."""
    a0, a1 = xm[face[0], 0], xm[face[0], 1]
    t0, t1 = xm[face[1], 0] - a0, xm[face[1], 1] - a1
    length2 = t0 * t0 + t1 * t1
    length = np.sqrt(length2)
    n0, n1 = t1 / length, -t0 / length  # outward: right of a->b
    s = ((p[0] - a0) * t0 + (p[1] - a1) * t1) / length2
    inside = 0.0 <= s <= 1.0
    s = min(1.0, max(0.0, s))
    w[0], w[1] = 1.0 - s, s
    d0, d1 = p[0] - (a0 + s * t0), p[1] - (a1 + s * t1)
    gap = d0 * n0 + d1 * n1
    if not inside and gap > 0.0:  # beyond an end, outside: push away from the end point
        dist = np.sqrt(d0 * d0 + d1 * d1)
        normal[0], normal[1] = d0 / dist, d1 / dist
        return dist, inside
    normal[0], normal[1] = n0, n1
    return gap, inside


@njit(cache=True)
def _project_3d(p, xm, face, w, normal):
    """Closest point of the bilinear quad to p by Newton on (xi, eta); weights w (4), normal."""
    xi, eta = 0.0, 0.0
    x = np.empty(3)
    dxi = np.empty(3)
    deta = np.empty(3)
    for _ in range(4):
        n1, n2, n3, n4 = 0.25 * (1 - xi) * (1 - eta), 0.25 * (1 + xi) * (1 - eta), 0.25 * (1 + xi) * (1 + eta), 0.25 * (1 - xi) * (1 + eta)
        for k in range(3):
            c1, c2, c3, c4 = xm[face[0], k], xm[face[1], k], xm[face[2], k], xm[face[3], k]
            x[k] = n1 * c1 + n2 * c2 + n3 * c3 + n4 * c4
            dxi[k] = 0.25 * ((1 - eta) * (c2 - c1) + (1 + eta) * (c3 - c4))
            deta[k] = 0.25 * ((1 - xi) * (c4 - c1) + (1 + xi) * (c3 - c2))
        r0 = 0.0
        r1 = 0.0
        a11 = 0.0
        a12 = 0.0
        a22 = 0.0
        for k in range(3):
            r0 += (p[k] - x[k]) * dxi[k]
            r1 += (p[k] - x[k]) * deta[k]
            a11 += dxi[k] * dxi[k]
            a12 += dxi[k] * deta[k]
            a22 += deta[k] * deta[k]
        det = a11 * a22 - a12 * a12
        xi += (a22 * r0 - a12 * r1) / det
        eta += (a11 * r1 - a12 * r0) / det
    inside = abs(xi) <= 1.0 and abs(eta) <= 1.0
    xi = min(1.0, max(-1.0, xi))
    eta = min(1.0, max(-1.0, eta))
    w[0], w[1], w[2], w[3] = 0.25 * (1 - xi) * (1 - eta), 0.25 * (1 + xi) * (1 - eta), 0.25 * (1 + xi) * (1 + eta), 0.25 * (1 - xi) * (1 + eta)
    for k in range(3):
        c1, c2, c3, c4 = xm[face[0], k], xm[face[1], k], xm[face[2], k], xm[face[3], k]
        x[k] = w[0] * c1 + w[1] * c2 + w[2] * c3 + w[3] * c4
        dxi[k] = 0.25 * ((1 - eta) * (c2 - c1) + (1 + eta) * (c3 - c4))
        deta[k] = 0.25 * ((1 - xi) * (c4 - c1) + (1 + xi) * (c3 - c2))
    nx = dxi[1] * deta[2] - dxi[2] * deta[1]
    ny = dxi[2] * deta[0] - dxi[0] * deta[2]
    nz = dxi[0] * deta[1] - dxi[1] * deta[0]
    nn = np.sqrt(nx * nx + ny * ny + nz * nz)
    normal[0], normal[1], normal[2] = nx / nn, ny / nn, nz / nn
    d0, d1, d2 = p[0] - x[0], p[1] - x[1], p[2] - x[2]
    gap = d0 * normal[0] + d1 * normal[1] + d2 * normal[2]
    if not inside and gap > 0.0:
        dist = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        normal[0], normal[1], normal[2] = d0 / dist, d1 / dist, d2 / dist
        return dist, inside
    return gap, inside


@njit(cache=True, parallel=True)
def point_forces(xp, vp, mp, slave, thickness, xm, vm, faces, seg_k, seg_depth, point_k, seg_inv, ring,
                 cell_start, cell_segs, lo, cell, ncell, damping, friction, dt,
                 f_point, seg_of, weights, gap_out):
    """Penalty force on every slave point (see module docstring); each point writes its own rows.

    slave (P,) bool selects the points in contact consideration; thickness (P,) per point;
    seg_k (S,) segment stiffness (used where point_k[i] <= 0) and point_k (P,) a per-point
    stiffness (soft constraint, k = s m_p / dt0^2) otherwise: that spring acts on the reduced mass of the point
    and its segment, m = m_p / (1 + m_p seg_inv[s]) with seg_inv (S,) the segment's largest 1 / m_node, so
    k = point_k m / m_p and the damping and friction below take m for m_p. ring (P,) multiplies the segment
    stiffness per point: 1 in 2D and 3D, the ring circumference 2 pi r_i of the point in an axisymmetric model, where seg_k is
    the meridian stiffness s K L^2 / A and the ring's k_i = 2 pi r_i s K L^2 / A (contact.system).
    Outputs: f_point (P, dim), seg_of (P,) the segment or
    -1, weights (P, nn) its shape functions at the contact point, gap_out (P,) the gap.
    """
    n_points, dim = xp.shape
    nn = faces.shape[1]
    for i in prange(n_points):
        seg_of[i] = -1
        for k in range(dim):
            f_point[i, k] = 0.0
        gap_out[i] = np.inf
        if not slave[i]:
            continue
        c = 0
        stride = 1
        outside = False
        for k in range(dim):
            kc = int(np.floor((xp[i, k] - lo[k]) / cell))
            if kc < 0 or kc >= ncell[k]:
                outside = True
                break
            c += kc * stride
            stride *= ncell[k]
        if outside:
            continue
        w = np.empty(nn)
        nrm = np.empty(dim)
        best = np.inf
        best_gap = 0.0
        best_w = np.empty(nn)
        best_n = np.empty(dim)
        best_s = -1
        for q in range(cell_start[c], cell_start[c + 1]):
            s = cell_segs[q]
            if dim == 2:
                gap, inside = _project_2d(xp[i], xm, faces[s], w, nrm)
            else:
                gap, inside = _project_3d(xp[i], xm, faces[s], w, nrm)
            if gap >= thickness[i] or gap <= -seg_depth[s] or (not inside and gap <= 0.0):
                continue  # beyond the segment's end on its inner side: a neighbouring segment's case
            rank = abs(gap) if inside else abs(gap) + thickness[i]  # prefer true projections
            if rank < best:
                best, best_gap, best_s = rank, gap, s
                best_w[:] = w
                best_n[:] = nrm
        if best_s < 0:
            continue
        m_pair = mp[i]
        if point_k[i] > 0.0:
            m_pair = mp[i] / (1.0 + mp[i] * seg_inv[best_s])
            k_pen = point_k[i] * m_pair / mp[i]
        else:
            k_pen = seg_k[best_s] * ring[i]
        vn = 0.0
        v_rel = np.empty(dim)
        for k in range(dim):
            vmk = 0.0
            for j in range(nn):
                vmk += best_w[j] * vm[faces[best_s, j], k]
            v_rel[k] = vp[i, k] - vmk
            vn += v_rel[k] * best_n[k]
        fn = k_pen * (thickness[i] - best_gap) - 2.0 * damping * np.sqrt(k_pen * m_pair) * vn
        if fn <= 0.0:
            continue
        ft = 0.0
        vt2 = 0.0
        for k in range(dim):
            vtk = v_rel[k] - vn * best_n[k]
            vt2 += vtk * vtk
        vt = np.sqrt(vt2)
        if friction > 0.0 and vt > 0.0:
            ft = min(friction * fn, m_pair * vt / dt)  # never more than stops the slip in one step
        for k in range(dim):
            f_point[i, k] = fn * best_n[k]
            if ft > 0.0:
                f_point[i, k] -= ft * (v_rel[k] - vn * best_n[k]) / vt
        seg_of[i] = best_s
        gap_out[i] = best_gap
        for j in range(nn):
            weights[i, j] = best_w[j]


@njit(cache=True)
def scatter_reactions(f_point, seg_of, weights, faces, f_master):
    """f_master[node] -= w_j f_point for each contacting point (serial: a fixed summation order)."""
    n_points, dim = f_point.shape
    nn = faces.shape[1]
    for i in range(n_points):
        s = seg_of[i]
        if s < 0:
            continue
        for j in range(nn):
            node = faces[s, j]
            for k in range(dim):
                f_master[node, k] -= weights[i, j] * f_point[i, k]
