"""ALE remap, element side (``kernels`` step 4): face fluxes of material volume, mass and energy.

Directional sweeps through the faces of one logical direction: the volume through a face is
the signed volume it sweeps from its Lagrangian to its remapped position; material volumes are
split by a directional SLIC (Noh & Woodward 1976) or by donor fractions, mass and energy by
donor-cell or van Leer (1977) MUSCL values (``face_fluxes``, ``_face_flux``), added by each
element (``apply_face_fluxes``). What follows the sweeps (velocities from the remapped momentum,
DeBar's kinetic-energy fix, the nodal masses) is ``remap_nodes.py``. Equations: docs/theory/ale.md.
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from ..fem.geometry import hex8_volume_origin
from .face_lanes import (FL_AMOUNT, FL_BLOCK, FL_EA, FL_ED, FL_EU, FL_HASFAR, FL_MA, FL_MD, FL_MU, FL_OE, FL_OM, FL_OV,
                         FL_ROWS, FL_SGN, FL_VA, FL_VD, FL_VU, face_block)
from .hex_lanes import _HV_BLOCK, _HV_ROWS, hex_volume_block
from .ring_geometry import ring_volume
from .lagrange import N_CHUNKS, chunk_range, quad_area


assert FL_BLOCK == _HV_BLOCK  # the swept volumes of a block of faces go through hex_volume_block's rows

# interface (material volume flux) modes
IFACE_DONOR = 0
IFACE_SLIC = 1

# SLIC orders the materials only where their fraction gradient across the donor is at least this
SLIC_JUMP = 0.1


@njit(cache=True)
def van_leer(qd, qa, qu, courant):
    """Face value of q leaving donor d towards acceptor a (u: upwind of d), van Leer limited.

    slope s = 2 (qa - qd)(qd - qu) / (qa - qu) where both differences share a sign, else 0;
    value at the centre of the swept region: qd + s (1 - courant) / 2.
    """
    d1 = qa - qd
    d2 = qd - qu
    if d1 * d2 <= 0.0:
        return qd
    return qd + (1.0 - courant) * d1 * d2 / (d1 + d2)


@njit(cache=True, inline="always")
def _face_flux(f, amount, donor, acc, far, sgn, vol_m, mass_m, ener_m, order, iface, phi_eps, fvol, fmass, fener,
               dvm, g, used):
    """Material volume, mass and energy fluxes of face f for a swept volume ``amount`` (shared by 2D and 3D).

    donor gives, acc receives, far is the element upwind of the donor (-1: none); sgn +1 when the
    acceptor is the face's owner. See ``face_fluxes``: a donor of -1 (inflow through an open face)
    is a copy of the acceptor, an acceptor of -1 (outflow) a copy of the donor; material volumes by
    SLIC or donor fractions, mass and energy by donor cell or van Leer. Writes fvol, fmass, fener
    rows of f (already zero); dvm, g, used: scratch (N,).
    """
    n_mat = vol_m.shape[1]
    if donor < 0:
        # inflow through an open boundary: the outside is a copy of the acceptor
        vt = 0.0
        for m in range(n_mat):
            vt += vol_m[acc, m]
        for m in range(n_mat):
            if vol_m[acc, m] > 0.0:
                dvol = amount * vol_m[acc, m] / vt
                dmass = dvol * mass_m[acc, m] / vol_m[acc, m]
                fvol[f, m] = sgn * dvol
                fmass[f, m] = sgn * dmass
                if mass_m[acc, m] > 0.0:
                    fener[f, m] = sgn * dmass * ener_m[acc, m] / mass_m[acc, m]
        return
    if acc < 0:
        acc = donor  # outflow: zero gradient outside
    vd = 0.0
    va = 0.0
    vu = 0.0
    for m in range(n_mat):
        vd += vol_m[donor, m]
        va += vol_m[acc, m]
        if far >= 0:
            vu += vol_m[far, m]
    amount = min(amount, vd)
    # material volumes
    sharp = False
    if iface == IFACE_SLIC and n_mat > 1:  # one material: no interface to order (g_max - g_min = 0)
        gmin = 1.0
        gmax = -1.0
        for m in range(n_mat):
            used[m] = vol_m[donor, m] <= 0.0
            dvm[m] = 0.0
            fu = vol_m[far, m] / vu if far >= 0 else vol_m[donor, m] / vd
            g[m] = vol_m[acc, m] / va - fu
            if not used[m]:
                gmin = min(gmin, g[m])
                gmax = max(gmax, g[m])
        # an interface across the sweep shows as a fraction jump; without one (interface
        # along the sweep, or an isolated fragment) the donor's fractions are used
        sharp = gmax - gmin >= SLIC_JUMP
    if sharp:
        left = amount
        for it in range(n_mat):
            best = -1
            for m in range(n_mat):
                if not used[m] and (best < 0 or g[m] > g[best]):
                    best = m
            if best < 0:
                break
            used[best] = True
            take = min(left, vol_m[donor, best])
            dvm[best] = take
            left -= take
            if left <= 0.0:
                break
    else:
        for m in range(n_mat):
            dvm[m] = amount * vol_m[donor, m] / vd
    for m in range(n_mat):
        if dvm[m] <= 0.0:
            continue
        vdm = vol_m[donor, m]
        if dvm[m] >= vdm * (1.0 - 1e-12):
            dmass = mass_m[donor, m]
            dener = ener_m[donor, m]
            dvol = vdm
        else:
            dvol = dvm[m]
            mdm = mass_m[donor, m]
            if mdm > 0.0:
                rho_d = mdm / vdm
                e_d = ener_m[donor, m] / mdm
                rho_f = rho_d
                e_f = e_d
                ha = False
                hu = False
                if order == 2 and far >= 0:
                    ha = vol_m[acc, m] > phi_eps * va and mass_m[acc, m] > 0.0
                    hu = vol_m[far, m] > phi_eps * vu and mass_m[far, m] > 0.0
                    if ha and hu:
                        # Courant number of the material itself, so that what stays in the
                        # donor keeps a density between its neighbours' (no mass without volume)
                        rho_f = van_leer(rho_d, mass_m[acc, m] / vol_m[acc, m],
                                         mass_m[far, m] / vol_m[far, m], dvol / vdm)
                dmass = min(rho_f * dvol, mdm)
                if order == 2 and far >= 0 and ha and hu:
                    e_f = van_leer(e_d, ener_m[acc, m] / mass_m[acc, m],
                                   ener_m[far, m] / mass_m[far, m], dmass / mdm)
                dener = e_f * dmass
                if ener_m[donor, m] > 0.0:
                    dener = min(dener, ener_m[donor, m])
            else:
                dmass = 0.0
                dener = 0.0
        fvol[f, m] = sgn * dvol
        fmass[f, m] = sgn * dmass
        fener[f, m] = sgn * dener


@njit(parallel=True, cache=True)
def face_fluxes(faces, face_nodes, face_elem, face_local, elem_nbr, face_open, x_lag, x_new,
                vol_m, mass_m, ener_m, order, iface, phi_eps, fvol, fmass, fener, flow, ring):
    """Fluxes through the listed faces, positive into the face's first element (its owner).

    The volume through a face (owner orientation) is the signed volume it sweeps from the
    Lagrangian position x_lag to the remapped position x_new, positive when the owner gains volume,
    the other element (or the outside, on open faces) being the donor: on quad4 meshes (face_nodes
    (F, 2)) the signed area of the quad (l0, w0, w1, l1), or with ring True (r-z) its ring volume
    (``ring_geometry.ring_volume``); on hex8 meshes (face_nodes (F, 4)) the exact swept volume of
    the quad face (``swept_volume_3d``). The upwind element of a donor is its neighbour across the
    opposite side: local face (k + 2) % 4 of a quad4, k ^ 1 of a hex8.
    Material volumes: IFACE_DONOR phi_m of the donor; IFACE_SLIC materials leave the donor in the
    order of their fraction gradient across it (acceptor minus upwind), the highest first, each
    at most its volume in the donor. Mass and energy: donor-cell (order 1) or van Leer (order 2)
    values of rho_m and e_m (``_face_flux``). Boundary faces carry flux only when open
    (transmitting): the outside state is a copy of the inside element. Writes fvol, fmass, fener
    rows of the listed faces, and flow[f]: False where the face sweeps nothing (a closed boundary face, or
    a swept volume of 0: its rows are zeros), for ``apply_face_fluxes``. With one material the faces go in
    blocks of ``face_lanes.FL_BLOCK``: the flowing faces' donor, acceptor and upwind states are copied
    into a work array and their fluxes computed together by ``face_lanes.face_block`` (vectorised; the
    bits of ``_face_flux``); inflow faces (donor outside) and multi-material meshes take ``_face_flux``.
    On a hex8 mesh the swept volumes of each block of faces are computed together first
    (``hex_lanes.hex_volume_block``, vectorised; the bits of ``swept_volume_3d``), of the faces that moved only:
    a face whose four nodes have x_lag = x_new sweeps nothing (0: the formula's +-0 where the face lies in a
    coordinate plane, as on an Eulerian box mesh; a round-off volume it could leave on a skewed face is not made). In the 3D benchmark
    box at rest but for a bump 90 % of the interior faces have not moved after 4 steps (40^3): face fluxes
    130.8 / 133.7 -> 96.0 / 97.8 ns per cell-step at 60^3 (benchmarks/README.md, "ALE 3D per cell against 2D,
    second round").

    One kernel for the three geometries (plane, ring, hex8): the branch is per face, outside
    ``_face_flux``, where the time goes. Against main's three kernels (min / median of 30 alternated
    calls, 1 thread, load 4-5, two runs; report alefold): plane 0.999-1.023 / 0.954-1.039, hex8
    0.999-1.034 / 0.982-1.004, ring 1.048-1.098 / 0.998-1.074 (the ring the one case possibly over
    3 %, with unchanged kernels reading 0.94-1.17 in the same runs).
    """
    nf = faces.shape[0]
    n_mat = vol_m.shape[1]
    hexa = face_nodes.shape[1] == 4
    n_chunks = min(nf, N_CHUNKS)
    one = n_mat == 1  # one material: the fluxes of each block of faces together (face_lanes.face_block)
    second = order == 2
    B = FL_BLOCK
    SV = FL_ROWS * B  # hex8: the swept-volume rows in wk
    for chunk in prange(n_chunks):
        start, stop = chunk_range(chunk, nf, n_chunks)
        dvm = np.empty(n_mat)
        g = np.empty(n_mat)
        used = np.empty(n_mat, dtype=np.bool_)
        # the block's work rows (face_lanes.FL_*) and face numbers, allocated at the chunk's first flowing face
        wk = np.empty(0)
        lane_f = np.empty(0, dtype=np.int64)
        # hex8: the column of each face's swept volume in wk's volume rows, -1 where the face has not moved
        lane_v = np.empty(0, dtype=np.int64)
        for block in range(start, stop, B):
            bend = min(block + B, stop)
            if hexa:  # the block's swept volumes together (hex_lanes.hex_volume_block), after the flux rows of wk
                if wk.shape[0] == 0:
                    wk = np.empty((FL_ROWS + _HV_ROWS) * B)
                    lane_f = np.empty(B, dtype=np.int64)
                    lane_v = np.empty(B, dtype=np.int64)
                nv = 0
                for i in range(block, bend):
                    f = faces[i]
                    # a face whose four nodes are where they were (x_lag = x_new) sweeps no volume: not computed (the
                    # formula gives +-0 there for a face in a coordinate plane, as on an Eulerian box mesh; on a
                    # skewed face it could leave a round-off volume)
                    moved = False
                    for a in range(4):
                        n = face_nodes[f, a]
                        for k in range(3):
                            if x_lag[n, k] != x_new[n, k]:
                                moved = True
                    if not moved or (face_elem[f, 1] < 0 and not face_open[f]):
                        lane_v[i - block] = -1
                        continue
                    lane_v[i - block] = nv
                    for a in range(4):
                        n = face_nodes[f, a]
                        for k in range(3):
                            wk[SV + (3 * a + k) * B + nv] = x_lag[n, k]
                            wk[SV + (3 * a + 12 + k) * B + nv] = x_new[n, k]
                    nv += 1
                if nv > 0:
                    hex_volume_block(nv, wk[SV:])
            nb = 0
            for i in range(block, bend):
                f = faces[i]
                for m in range(n_mat):
                    fvol[f, m] = 0.0
                    fmass[f, m] = 0.0
                    fener[f, m] = 0.0
                el = face_elem[f, 0]
                er = face_elem[f, 1]
                flow[f] = False
                if er < 0 and not face_open[f]:
                    continue
                if hexa:
                    j = lane_v[i - block]
                    dv = wk[SV + (_HV_ROWS - 1) * B + j] if j >= 0 else 0.0  # swept_volume_3d
                else:
                    n0 = face_nodes[f, 0]
                    n1 = face_nodes[f, 1]
                    if ring:
                        dv = ring_volume(x_lag[n0, 0], x_lag[n0, 1], x_new[n0, 0], x_new[n0, 1],
                                         x_new[n1, 0], x_new[n1, 1], x_lag[n1, 0], x_lag[n1, 1])
                    else:
                        dv = quad_area(x_lag[n0, 0], x_lag[n0, 1], x_new[n0, 0], x_new[n0, 1],
                                       x_new[n1, 0], x_new[n1, 1], x_lag[n1, 0], x_lag[n1, 1])
                if dv == 0.0:
                    continue
                flow[f] = True
                if dv > 0.0:
                    donor = er
                    acc = el
                    sgn = 1.0
                    far = elem_nbr[er, _opposite_face(face_local[f, 1], hexa)] if er >= 0 else -1
                else:
                    donor = el
                    acc = er
                    sgn = -1.0
                    far = elem_nbr[el, _opposite_face(face_local[f, 0], hexa)]
                if one and donor >= 0:
                    if wk.shape[0] == 0:
                        wk = np.empty(FL_ROWS * B)
                        lane_f = np.empty(B, dtype=np.int64)
                    a = acc if acc >= 0 else donor  # outflow: zero gradient outside
                    lane_f[nb] = f
                    wk[FL_AMOUNT * B + nb] = abs(dv)
                    wk[FL_SGN * B + nb] = sgn
                    wk[FL_VD * B + nb] = vol_m[donor, 0]
                    wk[FL_MD * B + nb] = mass_m[donor, 0]
                    wk[FL_ED * B + nb] = ener_m[donor, 0]
                    wk[FL_VA * B + nb] = vol_m[a, 0]
                    wk[FL_MA * B + nb] = mass_m[a, 0]
                    wk[FL_EA * B + nb] = ener_m[a, 0]
                    u = far if far >= 0 else donor  # (read only where far >= 0: FL_HASFAR)
                    wk[FL_HASFAR * B + nb] = 1.0 if far >= 0 else 0.0
                    wk[FL_VU * B + nb] = vol_m[u, 0] if far >= 0 else 0.0
                    wk[FL_MU * B + nb] = mass_m[u, 0]
                    wk[FL_EU * B + nb] = ener_m[u, 0]
                    nb += 1
                else:
                    _face_flux(f, abs(dv), donor, acc, far, sgn, vol_m, mass_m, ener_m, order, iface, phi_eps,
                               fvol, fmass, fener, dvm, g, used)
            if nb > 0:
                face_block(nb, wk[FL_AMOUNT * B:(FL_AMOUNT + 1) * B], wk[FL_SGN * B:(FL_SGN + 1) * B],
                           wk[FL_HASFAR * B:(FL_HASFAR + 1) * B], wk[FL_VD * B:(FL_VD + 1) * B],
                           wk[FL_MD * B:(FL_MD + 1) * B], wk[FL_ED * B:(FL_ED + 1) * B], wk[FL_VA * B:(FL_VA + 1) * B],
                           wk[FL_MA * B:(FL_MA + 1) * B], wk[FL_EA * B:(FL_EA + 1) * B], wk[FL_VU * B:(FL_VU + 1) * B],
                           wk[FL_MU * B:(FL_MU + 1) * B], wk[FL_EU * B:(FL_EU + 1) * B], second, phi_eps,
                           wk[FL_OV * B:(FL_OV + 1) * B], wk[FL_OM * B:(FL_OM + 1) * B], wk[FL_OE * B:(FL_OE + 1) * B])
                for j in range(nb):
                    f = lane_f[j]
                    fvol[f, 0] = wk[FL_OV * B + j]
                    fmass[f, 0] = wk[FL_OM * B + j]
                    fener[f, 0] = wk[FL_OE * B + j]


@njit(cache=True, inline="always")
def _opposite_face(k, hexa):
    """The local face opposite local face k: k ^ 1 on a hex8 (faces numbered in opposite pairs),
    (k + 2) % 4 on a quad4 (sides counter-clockwise)."""
    return k ^ 1 if hexa else (k + 2) % 4


@njit(parallel=True, cache=True)
def apply_face_fluxes(ka, kb, elem_face, elem_sign, fvol, fmass, fener, flow, vol_m, mass_m, ener_m):
    """Each element adds the fluxes of its two faces ka, kb (local numbers) of this sweep direction (a gather).

    An element neither of whose faces has flow (``face_fluxes``: their rows are zeros) is skipped, without
    reading the rows or its state (most of a mesh at rest). Adding the zeros would change nothing: x + 0 is x,
    except for a state entry of -0.0, which the sums that write the state never make from +0.0 (x + y is -0.0
    only when both are), so only a -0.0 given in the initial state would keep its sign here.
    """
    n_elem = elem_face.shape[0]
    n_mat = vol_m.shape[1]
    for e in prange(n_elem):
        if not (flow[elem_face[e, ka]] or flow[elem_face[e, kb]]):
            continue
        for k in (ka, kb):
            f = elem_face[e, k]
            s = elem_sign[e, k]
            for m in range(n_mat):
                vol_m[e, m] += s * fvol[f, m]
                mass_m[e, m] += s * fmass[f, m]
                ener_m[e, m] += s * fener[f, m]


@njit(cache=True, inline="always")
def swept_volume_3d(face_nodes, f, x_lag, x_new):
    """Signed volume swept by the quad face f from x_lag to x_new: the trilinear hexahedron whose
    bottom is the face at x_lag and top the face at x_new (face_nodes[f] ordered with the normal
    out of the owner element), positive when the face moves out of the owner, which then gains
    that volume from its neighbour. The six swept volumes of an element sum exactly to its new
    minus its Lagrangian volume (each lateral bilinear side is shared by two swept hexahedra with
    opposite orientations). Corners relative to the face's first node at x_lag
    (``fem.geometry.hex8_volume_origin``: the bits of ``hex8_volume``)."""
    r = face_nodes[f, 0]
    n1 = face_nodes[f, 1]
    n2 = face_nodes[f, 2]
    n3 = face_nodes[f, 3]
    xr = x_lag[r, 0]
    yr = x_lag[r, 1]
    zr = x_lag[r, 2]
    return hex8_volume_origin(x_lag[n1, 0] - xr, x_lag[n1, 1] - yr, x_lag[n1, 2] - zr,
                              x_lag[n2, 0] - xr, x_lag[n2, 1] - yr, x_lag[n2, 2] - zr,
                              x_lag[n3, 0] - xr, x_lag[n3, 1] - yr, x_lag[n3, 2] - zr,
                              x_new[r, 0] - xr, x_new[r, 1] - yr, x_new[r, 2] - zr,
                              x_new[n1, 0] - xr, x_new[n1, 1] - yr, x_new[n1, 2] - zr,
                              x_new[n2, 0] - xr, x_new[n2, 1] - yr, x_new[n2, 2] - zr,
                              x_new[n3, 0] - xr, x_new[n3, 1] - yr, x_new[n3, 2] - zr)


@njit(parallel=True, cache=True)
def swept_volumes_3d(faces, face_nodes, x_lag, x_new, out):
    """out[i] = swept_volume_3d of faces[i] (used for the inflow faces)."""
    for i in prange(faces.shape[0]):
        out[i] = swept_volume_3d(face_nodes, faces[i], x_lag, x_new)
