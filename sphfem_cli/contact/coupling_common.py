"""What the 2D and 3D kernels of the ALE -> structure coupling share, written once (docs/theory/coupling.md).

Inline helpers (``inline="always"``) that ``coupling_kernels`` (quad4 ALE, 2-node segments) and
``coupling_kernels_3d`` (hex8 ALE, quad4 faces) call with scalars and a literal element kind (npe
corners, dim components), so that each caller compiles as if written for its element and a 2D deck
compiles none of the 3D clipping:

- ``quad_area_beyond``, ``hex_volume_beyond``: the part of an element beyond a level of x . n (PLIC clip),
  ``measure_beyond`` the one of the element kind.
- ``side_depth``: the PLIC level that cuts off an element's fluid fraction, by bisection, and a point's
  distance beyond it: the body of ``fluid_side_depth`` (quad4) and ``fluid_side_depth_3d`` (hex8), which
  ``fluid_depth`` calls by dimension.
- ``penalty``: a coupling point's incremental penetration, penalty stiffness and damped normal force
  (``coupling_forces``, ``coupling_forces_3d``).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

# the six tetrahedra around the diagonal 0-6 that fill a hex8 (for its clipped volume)
_HEX_TETS = np.array([[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]])


@njit(cache=True)
def quad_area_beyond(pc, nx, ny, level):
    """Area of the quadrilateral pc (4, 2) where x . n >= level (Sutherland-Hodgman clip, shoelace)."""
    cx = np.empty(8)
    cy = np.empty(8)
    m = 0
    for k in range(4):
        j = (k + 1) % 4
        sk = pc[k, 0] * nx + pc[k, 1] * ny - level
        sj = pc[j, 0] * nx + pc[j, 1] * ny - level
        if sk >= 0.0:
            cx[m] = pc[k, 0]
            cy[m] = pc[k, 1]
            m += 1
        if (sk >= 0.0) != (sj >= 0.0):
            t = sk / (sk - sj)
            cx[m] = pc[k, 0] + t * (pc[j, 0] - pc[k, 0])
            cy[m] = pc[k, 1] + t * (pc[j, 1] - pc[k, 1])
            m += 1
    area = 0.0
    for k in range(m):
        j = (k + 1) % m
        area += cx[k] * cy[j] - cx[j] * cy[k]
    return 0.5 * area


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


@njit(cache=True, inline="always")
def measure_beyond(pc, nx, ny, nz, level, dim):
    """The area (dim 2: quad pc (4, 2), x . n >= level) or volume (dim 3: hex pc (8, 3), x . n > level) of an
    element beyond a level; dim a literal constant of the caller (the other branch pruned before typing)."""
    if dim == 3:
        return hex_volume_beyond(pc, nx, ny, nz, level)
    return quad_area_beyond(pc, nx, ny, level)


@njit(cache=True, inline="always")
def side_depth(x, conn, e, px, py, pz, nx, ny, nz, fraction, npe, dim):
    """Signed distance of point p beyond the fluid interface of element e (> 0: in the fluid); the body of
    ``fluid_side_depth`` (quad4: npe 4, dim 2, pz = nz = 0) and ``fluid_side_depth_3d`` (hex8: 8, 3), npe
    and dim literal constants of the caller.

    The element's fluid (volume fraction phi = ``fraction``) is reconstructed as the part of the
    element in front of a line (2D) or plane (3D) normal to n (the segment's or face's outward
    normal, pointing into the fluid): {x : x . n >= L} with area or volume phi A (PLIC with the normal
    given rather than taken from the fraction gradient; Youngs 1982 for the construction), the part
    beyond a level measured by ``measure_beyond`` (the clipped quad; the hex's six clipped tetrahedra),
    L found by bisection between the element's lowest and highest corner levels lo and hi (the part
    beyond L falls monotonically from A at lo to 0 at hi); the whole A is measured at lo - (hi - lo),
    below every corner (the quad's clip at lo, where it keeps every corner, gives the same area to
    the bit). Returns p . n - L. A full element (phi >= 1) gives the distance from its rearmost
    corner, >= 0 inside it; an empty one a negative number. Dot products summed in component order.
    """
    pc = np.empty((npe, dim))
    lo = np.inf
    hi = -np.inf
    for k in range(npe):
        for d in range(dim):
            pc[k, d] = x[conn[e, k], d]
        t = pc[k, 0] * nx + pc[k, 1] * ny
        if dim == 3:
            t += pc[k, 2] * nz
        lo = min(lo, t)
        hi = max(hi, t)
    tp = px * nx + py * ny
    if dim == 3:
        tp += pz * nz
    if fraction >= 1.0:
        return tp - lo
    if fraction <= 0.0:
        return tp - hi
    target = fraction * measure_beyond(pc, nx, ny, nz, lo - (hi - lo), dim)
    a = lo
    b = hi
    for _ in range(60):
        mid = 0.5 * (a + b)
        if measure_beyond(pc, nx, ny, nz, mid, dim) > target:
            a = mid
        else:
            b = mid
        if b - a <= 1e-12 * (hi - lo):
            break
    return tp - 0.5 * (a + b)


@njit(cache=True)
def fluid_side_depth(x, conn, e, px, py, nx, ny, fraction):
    """Signed distance of point (px, py) beyond the fluid interface of element e (> 0: in the fluid).

    The element's fluid (volume fraction phi = ``fraction``) is reconstructed as the part of the
    element in front of a line normal to n (the segment's outward normal, pointing into the
    fluid): {x : x . n >= L} with area phi A (PLIC with the normal given rather than taken from
    the fraction gradient; Youngs 1982 for the construction), L found by bisection on the clipped
    quad's area (``side_depth``, the body shared with the hex8 form). Returns
    p . n - L. A full element (phi >= 1) gives the distance from its rearmost corner, >= 0
    inside it; an empty one a negative number.
    """
    return side_depth(x, conn, e, px, py, 0.0, nx, ny, 0.0, fraction, 4, 2)


@njit(cache=True)
def fluid_side_depth_3d(x, conn, e, px, py, pz, nx, ny, nz, fraction):
    """Signed distance of point p beyond the fluid interface of hex8 element e (> 0: in the fluid).

    The 3D form of ``fluid_side_depth``, the same body (``side_depth``): the element's
    fluid (volume fraction phi) is the part of the element in front of a plane normal to n (the face's
    outward normal, into the fluid), {x : x . n >= L} with volume phi V (PLIC with the normal given;
    Youngs 1982), the volumes those of the element's six tetrahedra clipped by the plane
    (``hex_volume_beyond``), L by bisection. Returns p . n - L; a full element gives the distance from
    its rearmost corner, an empty one a negative number.
    """
    return side_depth(x, conn, e, px, py, pz, nx, ny, nz, fraction, 8, 3)


@njit(cache=True, inline="always")
def fluid_depth(x, conn, e, px, py, pz, nx, ny, nz, fraction, dim):
    """``fluid_side_depth_3d`` (dim 3) or ``fluid_side_depth`` (dim 2, pz and nz unused), dim a literal constant of
    the caller: a call to the compiled function, as the host rules made before they were written once (with
    ``side_depth`` inlined there instead the 2D force kernel measured no faster, within the noise of
    benchmarks/coupling_kernels.py at load 3)."""
    if dim == 3:
        return fluid_side_depth_3d(x, conn, e, px, py, pz, nx, ny, nz, fraction)
    return fluid_side_depth(x, conn, e, px, py, nx, ny, fraction)


@njit(cache=True, inline="always")
def penalty(depth, host, stiff, i, e, dt_prev, rate, pfac, bulk, share, vol, damping, mf, ms):
    """Normal force f of coupling point i with host e (2D and 3D; docs/theory/coupling.md, "Penalty");
    writes its penetration depth[i] = d^n, host[i] = e and stiffness stiff[i] = k.

    Incremental penetration d^n = max(0, d^{n-1} + dt^{n-1/2} rate), rate the closing speed
    (v_s - v_f) . n of the fluid onto the face (d^{n-1} = 0 for a point not coupled at the last pass);
    penalty stiffness k = pfac K A^2 / V (K = ``bulk``, the host's coupling-fluid bulk modulus, A =
    ``share``, the point's share of the face: its length, ring area or area; V = ``vol``, the host's
    area, ring volume or volume); normal force f = k d^n + zeta 2 sqrt(k m_f m_s / (m_f + m_s)) rate
    (zeta = ``damping`` of the critical damping of the two interpolated masses m_f, m_s, where both
    are > 0), and f = 0 where d^n = 0. The caller applies f only where it is > 0 (the coupling pushes,
    never pulls).
    """
    d = depth[i] + dt_prev * rate
    if d < 0.0:
        d = 0.0
    depth[i] = d
    host[i] = e
    k_pen = pfac * bulk * share * share / vol
    stiff[i] = k_pen
    if d <= 0.0:
        return 0.0
    fn = k_pen * d
    if damping > 0.0 and mf > 0.0 and ms > 0.0:
        fn += damping * 2.0 * math.sqrt(k_pen * mf * ms / (mf + ms)) * rate
    return fn
