"""ALE remap, nodal side (``kernels`` step 4): momentum and kinetic energy on the dual mesh.

The nodal masses, momenta and kinetic energies are remapped with the element mass fluxes of the
sweep (half-index shift, Benson 1992 sec. 5.4; generalised to hex8), upwind or van Leer
velocities along the node lines (``dual_fluxes``), gathered by the nodes (``apply_dual_fluxes``).
Equations: docs/theory/ale.md.

Layout: the fluxes of an element's edge sit together, ``g[e, h]`` = (mass, kinetic energy,
momentum components) in the slots ``G_MASS``, ``G_KIN``, ``G_MOM + k`` (and ``b[e, h, side]`` for
the open-face terms), so that a node's gather reads one row per corner instead of one per
quantity; the node velocities p / m of the sweep are divided once per node (``node_velocities``),
not once per use. Both are the same arithmetic as before (the same bits).
"""
from __future__ import annotations

from numba import njit, prange

from .remap import van_leer

# slots of a dual-edge flux row g[e, h] (and b[e, h, side]): mass, kinetic energy, then momentum
G_MASS = 0
G_KIN = 1
G_MOM = 2


@njit(parallel=True, cache=True)
def node_velocities(mnode, pnode, m_floor, u):
    """u = p / m per node, 0 where m is at or below the node's mass floor m_floor (N,): the velocities the dual
    fluxes of one sweep upwind.

    A node at or below its floor (a fog node) is held at zero velocity after the remap (``remap_nodes.finish_nodes``)
    and in the Lagrangian update; between the sweeps its p / m is noise as well: a node of 1.7e-41 kg (floor
    1.6e-13) at 9.4e26 m/s after one sweep gave the next sweep's dual flux 4.7e10 J of kinetic energy, which DeBar's
    fix (``remap_nodes.finish_remap_elements``) handed as +4.7e10 and -4.4e10 J of internal energy to two nearly
    empty elements, the step guard stopping the run two steps later (decks/underwater_explosion_plate_3d_ale.yaml at
    10 mm, t = 0.234 ms, traced with a trace floor then tried). Without this the 10 mm quarter stopped at 0.506 ms and
    the 5 mm deck at 0.345 ms; with it the 10 mm quarter runs to 0.8 ms (docs/studies/underwater_explosion.md, "The
    plate scene in 3D").
    """
    dim = pnode.shape[1]
    for n in prange(mnode.shape[0]):
        m = mnode[n]
        for k in range(dim):
            u[n, k] = pnode[n, k] / m if m > m_floor[n] else 0.0


@njit(cache=True, inline="always")
def _dual_element(e, ka, kb, direction, elem_face, elem_sign, elem_nbr, face_open, any_open, fmass, node_line,
                  mnode, u, order, g, b, moving, dim, n_edges):
    """``dual_fluxes`` of element e; dim and n_edges are constants at the call (unrolled loops)."""
    n_mat = fmass.shape[1]
    share = 1.0 / n_edges
    fa = elem_face[e, ka]
    fb = elem_face[e, kb]
    fa_in = 0.0
    fb_in = 0.0
    for m in range(n_mat):
        fa_in += fmass[fa, m]
        fb_in += fmass[fb, m]
    fa_in *= elem_sign[e, ka]
    fb_in *= elem_sign[e, kb]
    gh = 0.5 * share * (fa_in - fb_in)
    # no mass crosses (gh = 0): the element's g rows are zeros (gh v_f would be a zero of either sign), which the
    # node sums of apply_dual_fluxes, started from +0.0, would add without a change; they are neither written
    # nor read (most of a mesh at rest), moving[e] False tells apply_dual_fluxes: the same bits
    moving[e] = gh != 0.0
    # open boundary faces (read only when there are some: two rows fewer per element otherwise)
    open_a = any_open and elem_nbr[e, ka] < 0 and face_open[fa]
    open_b = any_open and elem_nbr[e, kb] < 0 and face_open[fb]
    if gh == 0.0 and not any_open:
        return  # nothing to write: the node lines are not read (their rows, 128 bytes a hex8 and sweep, are traffic)
    for h in range(n_edges):
        src = node_line[e, direction, h, 1]
        dst = node_line[e, direction, h, 2]
        if gh != 0.0:
            g[e, h, G_MASS] = gh
            if gh > 0.0:
                donor = src
                acc = dst
                up = node_line[e, direction, h, 0]
            else:
                donor = dst
                acc = src
                up = node_line[e, direction, h, 3]
            md = mnode[donor]
            ke = 0.0
            limited = order == 2 and up >= 0 and md > 0.0 and mnode[acc] > 0.0 and mnode[up] > 0.0
            courant = min(1.0, n_edges * abs(gh) / md) if limited else 0.0
            for k in range(dim):
                vd = u[donor, k]
                vf = vd
                if limited:
                    vf = van_leer(vd, u[acc, k], u[up, k], courant)
                g[e, h, G_MOM + k] = gh * vf
                ke += vf * vf
            g[e, h, G_KIN] = 0.5 * gh * ke
        if any_open:
            for side in range(2):
                for k in range(G_MOM + dim):
                    b[e, h, side, k] = 0.0
            for side in range(2):
                if side == 0:
                    if not open_a:
                        continue
                    flux = share * fa_in
                    n = src
                else:
                    if not open_b:
                        continue
                    flux = share * fb_in
                    n = dst
                b[e, h, side, G_MASS] = flux
                u2 = 0.0
                for k in range(dim):
                    un = u[n, k]
                    b[e, h, side, G_MOM + k] = flux * un
                    u2 += un * un
                b[e, h, side, G_KIN] = 0.5 * flux * u2


@njit(parallel=True, cache=True)
def dual_fluxes(ka, kb, direction, conn, elem_face, elem_sign, elem_nbr, face_open, any_open, fmass, node_line,
                mnode, u, order, g, b, moving):
    """Mass, momentum and kinetic-energy fluxes of the dual (nodal) cells in this sweep (2D and 3D).

    The element's H edges along the sweep direction (H = 2 for a quad4, 4 for a hex8) join a
    corner src on its side-a face ka to a corner dst on its side-b face kb. The dual face that
    cuts edge h inside element e carries the mass G/H, G = (F_a,in + F_b,out) / 2 the mean of the
    element's mass fluxes through its side-a and side-b faces (half-index shift, Benson 1992
    sec. 5.4, generalised to 3D: the dual cell of a node gains what its 2^dim corner shares
    M_e / 2^dim gain, so that the remapped nodal masses are those of the remapped elements); the
    momentum G/H v_face and kinetic energy G/(2H) |v_face|^2 with v_face the upwind node's velocity
    (order 1) or van Leer along the node line node_line[e, direction, h] = (before src, src, dst,
    after dst), with the dual Courant number H |G/H| / m_donor. On open boundary faces each of the
    face's H nodes also receives 1/H of the face's mass flux with its own velocity (b[e, h, 0] into
    src through side a, b[e, h, 1] into dst through side b); without open faces (any_open False) b
    is left as it is (zero). u: the node velocities p / m (``node_velocities``); g (E, H, 2 + dim)
    and b (E, H, 2, 2 + dim) rows in the slots G_MASS, G_KIN, G_MOM + k. moving (E,) bool: G != 0; an
    element without (no mass crosses its dual faces) leaves its g rows as they were (its fluxes are zero).
    """
    n_elem = conn.shape[0]
    three = u.shape[1] == 3
    for e in prange(n_elem):
        if three:
            _dual_element(e, ka, kb, direction, elem_face, elem_sign, elem_nbr, face_open, any_open, fmass,
                          node_line, mnode, u, order, g, b, moving, 3, 4)
        else:
            _dual_element(e, ka, kb, direction, elem_face, elem_sign, elem_nbr, face_open, any_open, fmass,
                          node_line, mnode, u, order, g, b, moving, 2, 2)


@njit(cache=True, inline="always")
def _dual_node(n, corner_edge, corner_dst, node_elem_ptr, node_elem_idx, any_open, g, b, moving, mnode, pnode, knode,
               dim, npe):
    """``apply_dual_fluxes`` of node n; dim and npe are constants at the call."""
    dm = 0.0
    dp0 = 0.0
    dp1 = 0.0
    dp2 = 0.0
    dk = 0.0
    for r in range(node_elem_ptr[n], node_elem_ptr[n + 1]):
        ea = node_elem_idx[r]
        e = ea // npe
        a = ea - npe * e
        h = corner_edge[a]
        side = corner_dst[a]
        if moving[e]:  # (else its fluxes are zeros: dual_fluxes)
            s = 1.0 if side == 1 else -1.0
            dm += s * g[e, h, G_MASS]
            dp0 += s * g[e, h, G_MOM]
            dp1 += s * g[e, h, G_MOM + 1]
            if dim == 3:
                dp2 += s * g[e, h, G_MOM + 2]
            dk += s * g[e, h, G_KIN]
        if any_open:
            dm += b[e, h, side, G_MASS]
            dp0 += b[e, h, side, G_MOM]
            dp1 += b[e, h, side, G_MOM + 1]
            if dim == 3:
                dp2 += b[e, h, side, G_MOM + 2]
            dk += b[e, h, side, G_KIN]
    mnode[n] += dm
    pnode[n, 0] += dp0
    pnode[n, 1] += dp1
    if dim == 3:
        pnode[n, 2] += dp2
    knode[n] += dk


@njit(parallel=True, cache=True)
def apply_dual_fluxes(corner_edge, corner_dst, node_elem_ptr, node_elem_idx, any_open, g, b, moving, mnode, pnode,
                      knode):
    """Each node adds the dual fluxes of its element corners (a gather); open-face terms if any_open.

    corner_edge[a], corner_dst[a]: the edge along this sweep that corner a of an element lies on,
    and 1 when it is the edge's dst end (on the side-b face). Elements not ``moving`` (``dual_fluxes``) add
    nothing from g (their fluxes are zeros).
    """
    n_nodes = mnode.shape[0]
    three = pnode.shape[1] == 3
    for n in prange(n_nodes):
        if three:
            _dual_node(n, corner_edge, corner_dst, node_elem_ptr, node_elem_idx, any_open, g, b, moving, mnode, pnode,
                       knode, 3, 8)
        else:
            _dual_node(n, corner_edge, corner_dst, node_elem_ptr, node_elem_idx, any_open, g, b, moving, mnode, pnode,
                       knode, 2, 4)
