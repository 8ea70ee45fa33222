"""Compiled kernels of the ALE -> structure penalty coupling (contact.coupling; docs/theory/coupling.md).

2D: structure segments are 2-node lines, the ALE mesh is quad4 (counter-clockwise); the 3D forms
(quad4 faces against hex8 elements) are in ``coupling_kernels_3d``. What both dimensions share is
written once as inline bodies called with the element kind as literal constants: the host search in
``coupling_search``, the interface reconstruction and the penalty law in ``coupling_common``. Arrays
and scalars only.

- ``build_bins``: a uniform grid of buckets over the ALE mesh, each listing the elements whose
  bounding box overlaps it (CSR), rebuilt each step (the mesh may move).
- in ``coupling_search``: the element containing a point and its natural coordinates (inverse
  bilinear map by Newton's method, ``natural_coords``), through the buckets; in ``coupling_common``:
  how far a point lies inside the fluid of a partly filled element (``fluid_side_depth``), the fluid
  reconstructed as the part of the element beyond a line parallel to the segment.
- ``coupling_forces``: for every coupling point, the host element (``coupling_search.host_point``),
  the incremental penetration and the penalty force (``coupling_common.penalty``), scattered to the
  ALE nodes and the segment nodes (serial: a point writes to nodes that other points share).
- ``stiffness_sums``: the per-node stiffness sums of the stable step.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .coupling_common import penalty
from .coupling_search import bin_elements, clamp, host_point, natural_coords

_XI = np.array([-1.0, 1.0, 1.0, -1.0])
_ETA = np.array([-1.0, -1.0, 1.0, 1.0])
TWO_PI = 2.0 * math.pi


@njit(cache=True)
def build_bins(x, conn, origin, cell, nbx, nby):
    """(start, items): the elements overlapping each bucket (bucket index = ix + nbx * iy; the body
    ``coupling_search.bin_elements``, shared with the hex8 form)."""
    return bin_elements(x, conn, origin, cell, nbx, nby, 1, 4, 2)


# The host rules, the interface reconstruction and the penalty law are written once (coupling_search.host_point,
# coupling_common.side_depth and penalty), inlined here and in coupling_forces_3d with literal element kinds.
# Against the former 2D/3D twins: bit-identical histories, fields and checkpoints on five coupled decks (1026
# arrays); min ms per call before -> after (benchmarks/coupling_kernels.py --rounds 6 --calls 20 --repeat 100,
# 1 thread, 6 Dec 2026, load 2.0-2.2): plane 0.040 -> 0.038, entry 0.075 -> 0.076, ring 0.054 -> 0.055, hex8
# 0.971 -> 0.951 (per-round minima spread up to 10 %; the ring's by round +1 % on the median).
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
            pushing = depth[i] > 0.0 or host[i] >= 0  # in contact at the last pass
            e, xi, eta, _ = host_point(xa, conn, start, items, origin, cell, nbx, nby, 1, frac, min_fraction, probe,
                                       leakage, pushing, px, py, 0.0, nx, ny, 0.0, 4, 2)
            if e < 0:
                depth[i] = 0.0
                host[i] = -1
                stiff[i] = 0.0
                continue
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
            share = ell  # the point's share of the face: its length, or its ring's area
            if ring:
                share = TWO_PI * px * ell
            fn = penalty(depth, host, stiff, i, e, dt_prev, rate, pfac, bulk[e], share, area[e], damping, mf, msp)
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
            xi = clamp(xi)
            eta = clamp(eta)
            for k in range(4):
                w = 0.25 * (1.0 + _XI[k] * xi) * (1.0 + _ETA[k] * eta)
                sum_a[conn[e, k]] += w * k_pen
