"""ALE remap, node side (``kernels`` step 4, after the sweeps): velocities from the remapped nodal momentum,
bounded by the old velocities around each node (``finish_remap_nodes``, ``finish_nodes``), DeBar's kinetic-energy
fix of the elements (``finish_remap_elements``), the nodal state the dual sweeps start from
(``remap_nodal_state``) and the nodal masses (``nodal_mass``). The element side (the face fluxes) is
``remap.py``, the nodal momentum's own fluxes ``dual.py``. Equations: docs/theory/ale.md.
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from .lagrange import BC_VELOCITY, N_CHUNKS, chunk_range, node_conditions


@njit(cache=True, inline="always")
def element_velocity_range(e, v_old, conn, vrange, dim, npe):
    """vrange[e, 0, k], vrange[e, 1, k] = min and max of v_old[:, k] over the corners of element e (corner order).

    Written once per element and remap where the flow fills the mesh (``finish_nodes``' use_ranges), so that
    a node's bound reads one row per element instead of npe corner velocities: in a moving flow every node
    scanned the npe x dim corner values of one to all of its elements, a range that each of the element's
    npe nodes recomputed (the bound 25 -> 13 ns per node in a vortex at 240^2, 1 thread).
    """
    for k in range(dim):
        c = v_old[conn[e, 0], k]
        lo = c
        hi = c
        for a in range(1, npe):
            q = v_old[conn[e, a], k]
            lo = min(lo, q)
            hi = max(hi, q)
        vrange[e, 0, k] = lo
        vrange[e, 1, k] = hi


@njit(cache=True, inline="always")
def bounded_velocity(n, w, v_old, conn, vrange, use_ranges, npe, node_elem_ptr, node_elem_idx, lo, hi, u):
    """u = w with each component held within the range of v_old over node n and the nodes of its
    elements (w, u, lo, hi: (dim,) scratch; u may be w; use_ranges: read the elements' corner ranges
    from vrange, ``element_velocity_range``, else scan their corners here; a constant at the call, as the
    corner count npe: a literal 4 or 8 makes node_elem_idx // npe a shift, conn.shape[1] a division that
    cost the bound 3-4 ns a node).

    One remap sweep moves nodal momentum between neighbours along a node line, so after the sweeps
    (one per direction) a node's velocity is a mean of those of its element-sharing neighbours: a
    monotone remap keeps it in their range (the local bound of Shashkov & Wendroff 2004, J. Comput.
    Phys. 198, 265-277, "the repair paradigm"; here the excess is booked as impulse, not spread).
    The elements are visited in turn until w lies within the range found so far, which in smooth
    flow is after one or two elements; w outside the whole range is clamped to it. The range
    lo = min(v_n, min over the elements of their corners' min) is the number the former corner-by-corner
    scan found (min and max do not depend on the grouping, but for the sign of a zero and NaN, which
    only the clamp of an out-of-range w could pass on; the ALE decks and tests compared bit for bit).
    """
    dim = w.shape[0]
    inside = True
    for k in range(dim):
        u[k] = w[k]
        if w[k] != v_old[n, k]:
            inside = False
    if inside:
        return
    for k in range(dim):
        lo[k] = v_old[n, k]
        hi[k] = v_old[n, k]
    for r in range(node_elem_ptr[n], node_elem_ptr[n + 1]):
        e = node_elem_idx[r] // npe
        inside = True
        if use_ranges:
            for k in range(dim):
                lo[k] = min(lo[k], vrange[e, 0, k])
                hi[k] = max(hi[k], vrange[e, 1, k])
                if w[k] < lo[k] or w[k] > hi[k]:
                    inside = False
        else:
            for k in range(dim):
                for a in range(npe):
                    q = v_old[conn[e, a], k]
                    lo[k] = min(lo[k], q)
                    hi[k] = max(hi[k], q)
                if w[k] < lo[k] or w[k] > hi[k]:
                    inside = False
        if inside:
            return
    for k in range(dim):
        u[k] = min(max(w[k], lo[k]), hi[k])



@njit(cache=True, inline="always")
def _finish_node(n, mnode, pnode, knode, m_floor, v_old, conn, node_elem_ptr, node_elem_idx, bc_type, bc_normal, v,
                 impulse, dissip, vrange, use_ranges, w, lo, hi, dim, npe):
    """``finish_nodes`` of node n (use_ranges, dim and npe constants at the call)."""
    m = mnode[n]
    if m > 0.0:
        for k in range(dim):
            w[k] = pnode[n, k] / m
    else:
        for k in range(dim):
            w[k] = 0.0
    w0 = w[0]
    w1 = w[1]
    w2 = w[2] if dim == 3 else 0.0
    live = m > m_floor[n] or bc_type[n] == BC_VELOCITY
    if live:
        bounded_velocity(n, w, v_old, conn, vrange, use_ranges, npe, node_elem_ptr, node_elem_idx, lo, hi, w)
    u0, u1, u2 = node_conditions(live, bc_type[n], bc_normal[n], w[0], w[1], (w[2] if dim == 3 else 0.0), dim)
    impulse[n, 0] = -pnode[n, 0] if m <= 0.0 else m * (u0 - w0)
    impulse[n, 1] = -pnode[n, 1] if m <= 0.0 else m * (u1 - w1)
    v[n, 0] = u0
    v[n, 1] = u1
    u2sum = u0 * u0 + u1 * u1
    if dim == 3:
        impulse[n, 2] = -pnode[n, 2] if m <= 0.0 else m * (u2 - w2)
        v[n, 2] = u2
        u2sum += u2 * u2
    dissip[n] = knode[n] - 0.5 * m * u2sum if m > 0.0 else knode[n]


@njit(cache=True, inline="always")
def finish_nodes(mnode, pnode, knode, m_floor, v_old, conn, node_elem_ptr, node_elem_idx, bc_type, bc_normal, v,
                 impulse, dissip, vrange, use_ranges, dim, npe):
    """The body of ``finish_remap_nodes`` (quad4) and ``finish_remap_nodes_3d`` (hex8): dim components, a
    literal constant of the caller, so that each compiles as if written for its dimension (the third
    component's lines dropped in 2D).

    With use_ranges, first the corner ranges of v_old of every element (``element_velocity_range``, into
    vrange (E, 2, dim)), which the nodes' bounds then read, one row per element; without, each bound scans
    its elements' corners (the same numbers: ``bounded_velocity``). The remap asks for the ranges where mass
    crossed at least a quarter of the elements (``AleSystem._remap``). Then per node: w = p / m, bounded
    (``bounded_velocity``) and under the velocity conditions, or 0 at or below the mass floor
    (``node_conditions``): u; impulse m (u - w) (p itself without mass), v = u, dissip = knode - m |u|^2 / 2
    (|u|^2 summed in component order).
    """
    if use_ranges:
        for e in prange(conn.shape[0]):
            element_velocity_range(e, v_old, conn, vrange, dim, npe)
    n_nodes = mnode.shape[0]
    n_chunks = min(n_nodes, N_CHUNKS)
    for chunk in prange(n_chunks):
        w = np.empty(dim)
        lo = np.empty(dim)
        hi = np.empty(dim)
        start, stop = chunk_range(chunk, n_nodes, n_chunks)
        if use_ranges:  # two loops, each compiled with its bound (the choice inside the loop cost 4 ns a node)
            for n in range(start, stop):
                _finish_node(n, mnode, pnode, knode, m_floor, v_old, conn, node_elem_ptr, node_elem_idx, bc_type,
                             bc_normal, v, impulse, dissip, vrange, True, w, lo, hi, dim, npe)
        else:
            for n in range(start, stop):
                _finish_node(n, mnode, pnode, knode, m_floor, v_old, conn, node_elem_ptr, node_elem_idx, bc_type,
                             bc_normal, v, impulse, dissip, vrange, False, w, lo, hi, dim, npe)


# quad4 and hex8: one body (``finish_nodes``, inline, the dimension a literal constant), one compiled kernel
# per element kind. A fully dimension-generic kernel had measured 15-30 % (2D) slower per call, and the 3D
# kernel serving 2D 14.5 -> 20.3 ns per cell-step (one material), 29.9 -> 35.7 (two) (benchmarks/ale_passes.py
# --n 240 --steps 10 --repeat 3 --two --trees, 4 Dec 2026); this body with the velocity conditions on scalars,
# against the former twins: bit-identical on eight ALE decks; min / median ms per call before -> after
# (benchmarks/ale_kernels.py --trees BASE THIS --rounds 5 --calls 50, 1 thread, 6 Dec 2026, load 3.9-4.0,
# BASE = e629c8f): plane 0.39 / 0.44 -> 0.37 / 0.39, two materials 0.42 / 0.55 -> 0.39 / 0.45, ring 0.60 / 0.87
# -> 0.56 / 0.87, hex8 2.79 / 3.18 -> 2.48 / 3.10.
@njit(parallel=True, cache=True)
def finish_remap_nodes(mnode, pnode, knode, m_floor, v_old, conn, node_elem_ptr, node_elem_idx, bc_type, bc_normal,
                       v, impulse, dissip, vrange, use_ranges):
    """Velocity from the remapped momentum, bounded by its neighbours', velocity conditions, kinetic
    energy lost (DeBar); the body: ``finish_nodes``.

    w = p / m, each component then held within the range of the velocities before the remap,
    v_old, of the node and of every node of its elements (``bounded_velocity``); the velocity
    conditions (reaction and bound impulse m (u - w) into ``impulse``); dissip[n] = the kinetic
    energy carried into the node minus 1/2 m |u|^2 afterwards. A node whose remapped mass is at or
    below m_floor[n] gets u = 0 (its momentum p into ``impulse``, its kinetic energy into dissip).
    Why the bound: p and m come from different flux stencils, so p / m of a near-empty node is
    noise (fog nodes of 2e-58 kg were measured at 8.6e6 m/s, of 2.4e-11 kg, ten times the floor,
    at 2.4e4 m/s beside a water-entry jet where no node moved faster than 11 m/s).
    vrange (E, 2, 2): scratch, the elements' velocity ranges, computed and read when use_ranges (bool).
    """
    finish_nodes(mnode, pnode, knode, m_floor, v_old, conn, node_elem_ptr, node_elem_idx, bc_type, bc_normal, v,
                 impulse, dissip, vrange, use_ranges, 2, 4)


@njit(parallel=True, cache=True)
def finish_remap_nodes_3d(mnode, pnode, knode, m_floor, v_old, conn, node_elem_ptr, node_elem_idx, bc_type,
                          bc_normal, v, impulse, dissip, vrange, use_ranges):
    """``finish_remap_nodes`` on hex8 nodes (N, 3): the same body (``finish_nodes``), 3 components; vrange (E, 2, 3)."""
    finish_nodes(mnode, pnode, knode, m_floor, v_old, conn, node_elem_ptr, node_elem_idx, bc_type, bc_normal, v,
                 impulse, dissip, vrange, use_ranges, 3, 8)


@njit(parallel=True, cache=True)
def finish_remap_elements(conn, mass_m, ener_m, node_mass, dissip, ke_fix):
    """Element share of the nodal kinetic-energy loss, by corner mass M_e / n_corners, into material energies."""
    n_elem, npe = conn.shape
    n_mat = mass_m.shape[1]
    corner = 1.0 / npe
    if not ke_fix:
        return
    for e in prange(n_elem):
        me = 0.0
        for m in range(n_mat):
            me += mass_m[e, m]
        if me <= 0.0:
            continue
        add = 0.0
        for a in range(npe):
            n = conn[e, a]
            if node_mass[n] > 0.0:
                add += dissip[n] * corner * me / node_mass[n]
        for m in range(n_mat):
            ener_m[e, m] += add * mass_m[e, m] / me


@njit(cache=True)
def remap_nodal_state(node_mass, v, mnode, pnode, knode):
    """The nodal state the dual remap carries: mnode = m, pnode = m v, knode = m |v|^2 / 2.

    In the order of the numpy expressions it replaces (``pnode = m[:, None] * v``,
    ``knode = 0.5 * m * (v ** 2).sum(axis=1)``), so the results are the same to the bit.
    """
    dim = v.shape[1]
    for n in range(v.shape[0]):
        m = node_mass[n]
        mnode[n] = m
        s = v[n, 0] * v[n, 0]
        pnode[n, 0] = m * v[n, 0]
        for k in range(1, dim):
            s += v[n, k] * v[n, k]
            pnode[n, k] = m * v[n, k]
        knode[n] = 0.5 * m * s


@njit(cache=True)
def add_column_sums(a, out):
    """out[k] += sum_n a[n, k], summed in row order from a[0, k] (numpy's ``a.sum(axis=0)`` of a
    C-ordered (N, dim) array adds the rows one after the other: the same bits, without the
    per-row overhead of its strided reduction). Serial, so the sum does not depend on the threads."""
    n_rows, dim = a.shape
    if n_rows == 0:
        return
    if dim == 2:  # both columns in one loop: two independent chains of additions, each in row order
        s0 = a[0, 0]
        s1 = a[0, 1]
        for n in range(1, n_rows):
            s0 += a[n, 0]
            s1 += a[n, 1]
        out[0] += s0
        out[1] += s1
        return
    if dim == 3:
        s0 = a[0, 0]
        s1 = a[0, 1]
        s2 = a[0, 2]
        for n in range(1, n_rows):
            s0 += a[n, 0]
            s1 += a[n, 1]
            s2 += a[n, 2]
        out[0] += s0
        out[1] += s1
        out[2] += s2
        return
    for k in range(dim):
        s = a[0, k]
        for n in range(1, n_rows):
            s += a[n, k]
        out[k] += s


@njit(cache=True, inline="always")
def _node_mass(n, mass_m, node_elem_ptr, node_elem_idx, npe):
    s = 0.0
    for r in range(node_elem_ptr[n], node_elem_ptr[n + 1]):
        e = node_elem_idx[r] // npe
        for m in range(mass_m.shape[1]):
            s += (1.0 / npe) * mass_m[e, m]
    return s


@njit(parallel=True, cache=True)
def nodal_mass(mass_m, node_elem_ptr, node_elem_idx, npe, out):
    """m_I = sum over the node's elements of M_e / npe (gather; node_elem_idx lists e * npe + corner)."""
    for n in prange(out.shape[0]):
        if npe == 8:
            out[n] = _node_mass(n, mass_m, node_elem_ptr, node_elem_idx, 8)
        else:
            out[n] = _node_mass(n, mass_m, node_elem_ptr, node_elem_idx, 4)
