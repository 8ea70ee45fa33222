"""ALE Lagrangian phase, step 3 (``kernels``): the compatible work of the element forces, the Lagrangian
volume and the mixed-element closure (``lagrange_energy``, ``_closure_energy``), and the exact hex8
volumes. Paper section 2, eq. 2.6; Caramana et al. 1998. Equations: docs/theory/ale.md.
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from ..fem.geometry import hex8_volume_origin
from .hex_lanes import _HV_BLOCK, _HV_ROWS, hex_volume_block
from .lagrange import N_CHUNKS, chunk_range, quad_area
from .ring_geometry import ring_volume

# closures
CLOSURE_EQUAL_STRAIN = 0
CLOSURE_RELAX = 1

_BLOCK = 128  # elements per block of the one-material closure and of the hex8 volumes (``energy_elements``)
assert _BLOCK == _HV_BLOCK


@njit(cache=True, inline="always")
def _closure_energy(e, w, v_lag, vol_m, mass_m, ener_m, e_lag, pres_m, bulk_m, closure, alpha, beta, phi_eps, pressed,
                    dvm, dev):
    """Mixed-element closure of element e over the Lagrangian step (shared by 2D and 3D).

    The volume change dV = v_lag - sum_m V_m split between the present materials (``lagrange_energy``:
    equal strain, or pressure relaxation limited by beta; a material at most phi_eps of the volume keeps
    its volume; where a structure presses on the element (pressed[e]) its void is the structure's volume
    and takes its equal-strain share, outside the relaxation), each material's energy changed by its
    own -p_m dV_m plus its mass share of the rest of the element's work w (viscous and hourglass
    work). e_lag[e, m]: the second half of the material's own work, -p_m dV_m / (2 M_m) (``lagrange_energy``).
    dvm, dev: scratch (N,).
    """
    n_mat = vol_m.shape[1]
    vtot = 0.0
    for m in range(n_mat):
        vtot += vol_m[e, m]
    dv = v_lag - vtot
    # equal strain among the present materials; an absent one (at most phi_eps of the volume) keeps its
    # volume, hence its density: strained with a collapsing void it reached 15-47 rho0 and, remapped into a
    # neighbour where it counted again, Tait pressures of 1e16 Pa (decks/bird_strike_axisymmetric_ale.yaml at
    # 1.25 mm stopped on the step guard at 0.37 ms)
    v_present = 0.0
    for m in range(n_mat):
        if vol_m[e, m] > phi_eps * vtot:
            v_present += vol_m[e, m]
    # the materials that relax: the present ones, less, in an element a structure presses on, those without
    # stiffness (void): there the void is the structure's own volume behind its face, which moves with the
    # structure and cannot close; relaxed against the water it took the compression the face imposes every
    # step, and the remap brought it back behind the face, so the water at the face never compressed
    # (decks/cylinder_entry_end_on_axisymmetric_ale.yaml: V(2 R/c) / V0 0.8369 against the acoustic 0.6211)
    n_relax = 0
    v_relax = 0.0
    s_comp = 0.0
    s_p = 0.0
    kmax = 0.0
    held = pressed[e]
    for m in range(n_mat):
        dvm[m] = 0.0
        dev[m] = 0.0
        if vol_m[e, m] > phi_eps * vtot:
            dvm[m] = dv * vol_m[e, m] / v_present
            if not (held and bulk_m[e, m] <= 0.0):
                n_relax += 1
                v_relax += vol_m[e, m]
                kmax = max(kmax, bulk_m[e, m])
    if closure == CLOSURE_RELAX and n_relax > 1 and kmax > 0.0:
        kmin = 1e-9 * kmax  # void (or a material without stiffness) takes the volume change
        dv_relax = dv if v_relax == v_present else dv * v_relax / v_present  # the relaxing materials' share
        for m in range(n_mat):
            if vol_m[e, m] > phi_eps * vtot and not (held and bulk_m[e, m] <= 0.0):
                k = max(bulk_m[e, m], kmin)
                s_comp += vol_m[e, m] / k
                s_p += vol_m[e, m] * pres_m[e, m] / k
        pbar = s_p / s_comp
        scale = 1.0
        for m in range(n_mat):
            if vol_m[e, m] > phi_eps * vtot and not (held and bulk_m[e, m] <= 0.0):
                k = max(bulk_m[e, m], kmin)
                target = dv_relax * vol_m[e, m] / k / s_comp + alpha * vol_m[e, m] * (pres_m[e, m] - pbar) / k
                dev[m] = target - dvm[m]
                if dev[m] < 0.0:
                    room = beta * vol_m[e, m] + dvm[m]
                    if room <= 0.0:
                        scale = 0.0
                    else:
                        scale = min(scale, room / -dev[m])
        for m in range(n_mat):
            dvm[m] += scale * dev[m]
    # energy: each material its own -p_m dV_m; the remainder of W_e (the shock viscosity's
    # and hourglass work) by mass fraction, so that a trace of material with volume but
    # almost no mass is not heated to an unbounded specific energy by q dV_m
    own = 0.0
    for m in range(n_mat):
        if mass_m[e, m] > 0.0:
            own -= pres_m[e, m] * dvm[m]
    rest = w - own
    mass_e = 0.0
    for m in range(n_mat):
        mass_e += mass_m[e, m]
    for m in range(n_mat):
        e_lag[e, m] = 0.0
        if mass_m[e, m] > 0.0:
            ener_m[e, m] += -pres_m[e, m] * dvm[m] + rest * mass_m[e, m] / mass_e
            e_lag[e, m] = -0.5 * pres_m[e, m] * dvm[m] / mass_m[e, m]
        vol_m[e, m] += dvm[m]


@njit(cache=True, error_model="numpy")
def one_material_closure(nb, w_blk, v_lag_blk, vol, mass, ener, e_lag, pres, phi_eps):
    """``_closure_energy`` of the nb elements of a block of a mesh holding one material, as a loop LLVM
    vectorises (straight-line; the block's slices of flat (E,) views indexed by the loop counter, see
    ``force_lanes.gas_block``; numpy's error model: the divisions of an absent or massless element give inf
    or nan that the selects discard). w_blk, v_lag_blk: the block's work and Lagrangian volume.

    With one material there is nothing to relax (n_relax <= 1), so both closures are: dV = V_lag - (0 + V);
    present when V > phi_eps (0 + V): dV_1 = (dV V) / (0 + V), else 0; own = 0 - p dV_1 where M > 0; rest =
    w - own; E += (-p) dV_1 + (rest M) / (0 + M) and e_lag = ((-0.5 p) dV_1) / M where M > 0, else e_lag = 0;
    V += dV_1. The general path's operations in its order (its sums start from 0.0): the same bits.
    """
    for i in range(nb):
        v = vol[i]
        m = mass[i]
        p = pres[i]
        vtot = 0.0 + v
        dv = v_lag_blk[i] - vtot
        present = v > phi_eps * vtot
        v_present = 0.0 + v
        dvm = dv * v / v_present if present else 0.0
        full = m > 0.0
        own = 0.0 - p * dvm if full else 0.0
        rest = w_blk[i] - own
        mass_e = 0.0 + m
        gained = ener[i] + (-p * dvm + rest * m / mass_e)
        lagged = -0.5 * p * dvm / m
        ener[i] = gained if full else ener[i]
        e_lag[i] = lagged if full else 0.0
        vol[i] = v + dvm


@njit(cache=True, inline="always")
def _volume_origin(p):
    """``fem.geometry.hex8_volume_origin`` of the corners p (8, 3) relative to p[0] (= 0): the bits of hex8_volume(p)."""
    return hex8_volume_origin(p[1, 0], p[1, 1], p[1, 2], p[2, 0], p[2, 1], p[2, 2], p[3, 0], p[3, 1], p[3, 2],
                              p[4, 0], p[4, 1], p[4, 2], p[5, 0], p[5, 1], p[5, 2], p[6, 0], p[6, 1], p[6, 2],
                              p[7, 0], p[7, 1], p[7, 2])


@njit(cache=True, inline="always")
def quad_work_volume(e, x, v_old, v_new, dt, conn, f_elem, p, ring):
    """(W_e, V_lag) of quad e: the compatible work -dt sum_a f_a . (v_a^{n-1/2} + v_a^{n+1/2}) / 2 (both
    components of a corner summed first) and the area (plane) or ring volume (``ring`` True) of the quad
    at x + dt v^{n+1/2}, its corners into p (4, 2)."""
    w = 0.0
    for a in range(4):
        n = conn[e, a]
        w -= f_elem[e, a, 0] * 0.5 * (v_old[n, 0] + v_new[n, 0]) + f_elem[e, a, 1] * 0.5 * (v_old[n, 1] + v_new[n, 1])
        p[a, 0] = x[n, 0] + dt * v_new[n, 0]
        p[a, 1] = x[n, 1] + dt * v_new[n, 1]
    if ring:
        v_lag = ring_volume(p[0, 0], p[0, 1], p[1, 0], p[1, 1], p[2, 0], p[2, 1], p[3, 0], p[3, 1])
    else:
        v_lag = quad_area(p[0, 0], p[0, 1], p[1, 0], p[1, 1], p[2, 0], p[2, 1], p[3, 0], p[3, 1])
    return w * dt, v_lag


@njit(cache=True, inline="always")
def hex_work_corners(e, x, v_old, v_new, dt, conn, f_elem, hv, i):
    """W_e of hex8 e, the compatible work (component by component), returned; its corners at x + dt v^{n+1/2}
    into column i of hv (``hex_lanes.hex_volume_block``'s rows, which give the trilinear volume
    ``fem.geometry.hex8_volume`` of the corners relative to corner 0)."""
    w = 0.0
    for a in range(8):
        n = conn[e, a]
        for k in range(3):
            w -= f_elem[e, a, k] * 0.5 * (v_old[n, k] + v_new[n, k])
            hv[(3 * a + k) * _BLOCK + i] = x[n, k] + dt * v_new[n, k]
    return w * dt


@njit(cache=True, inline="always")
def energy_elements(x, v_old, v_new, dt, conn, f_elem, vol_m, mass_m, ener_m, e_lag, pres_m, bulk_m, closure, alpha, beta,
                    phi_eps, pressed, work_elem, ring, npe, dim):
    """The body of ``lagrange_energy`` (quad4, plane or ring) and ``lagrange_energy_3d`` (hex8): per element its
    work and Lagrangian volume (``quad_work_volume``; hex8: ``hex_work_corners``, then the block's volumes together,
    ``hex_lanes.hex_volume_block``; npe and dim literal constants of the caller, the other element's branch
    pruned before typing), then the closure (``_closure_energy``)."""
    n_elem = conn.shape[0]
    n_mat = vol_m.shape[1]
    n_chunks = min(n_elem, N_CHUNKS)
    # one material: the closure in blocks through one_material_closure, on flat views of the (E, 1) state
    one = n_mat == 1
    vol1, mass1, ener1, lag1, pres1 = (vol_m.reshape(-1), mass_m.reshape(-1), ener_m.reshape(-1), e_lag.reshape(-1),
                                       pres_m.reshape(-1))
    for chunk in prange(n_chunks):
        start, stop = chunk_range(chunk, n_elem, n_chunks)
        dvm = np.empty(n_mat)
        dev = np.empty(n_mat)
        p = np.empty((npe, dim))
        v_blk = np.empty(_BLOCK)
        # hex8: the corners at x + dt v^{n+1/2} of a block (hex_lanes.hex_volume_block's rows; its volume row)
        if dim == 3:
            hv = np.empty(_HV_ROWS * _BLOCK)
        else:
            hv = v_blk  # (unread: no allocation on quad4)
        if one or dim == 3:
            for block in range(start, stop, _BLOCK):
                nb = min(_BLOCK, stop - block)
                for i in range(nb):
                    e = block + i
                    if dim == 3:
                        w = hex_work_corners(e, x, v_old, v_new, dt, conn, f_elem, hv, i)
                    else:
                        w, v_lag = quad_work_volume(e, x, v_old, v_new, dt, conn, f_elem, p, ring)
                        v_blk[i] = v_lag
                    work_elem[e] = w
                if dim == 3:
                    hex_volume_block(nb, hv)
                    v_blk[:nb] = hv[(_HV_ROWS - 1) * _BLOCK:(_HV_ROWS - 1) * _BLOCK + nb]
                end = block + nb
                if one:
                    one_material_closure(nb, work_elem[block:end], v_blk, vol1[block:end], mass1[block:end],
                                         ener1[block:end], lag1[block:end], pres1[block:end], phi_eps)
                else:
                    for i in range(nb):
                        _closure_energy(block + i, work_elem[block + i], v_blk[i], vol_m, mass_m, ener_m, e_lag, pres_m,
                                        bulk_m, closure, alpha, beta, phi_eps, pressed, dvm, dev)
            continue
        for e in range(start, stop):
            w, v_lag = quad_work_volume(e, x, v_old, v_new, dt, conn, f_elem, p, ring)
            work_elem[e] = w
            _closure_energy(e, w, v_lag, vol_m, mass_m, ener_m, e_lag, pres_m, bulk_m, closure, alpha, beta, phi_eps,
                            pressed, dvm, dev)


# quad4 and hex8: one body (``energy_elements``, inline, the element's work and volume chosen by literal
# constants), one compiled kernel per element kind. A fully dimension-generic kernel had measured 19-27 %
# (2D and 3D) slower per call (benchmarks/ale_throughput.py cases, 1 thread, min of 15 calls, 3 interleaved
# rounds); this one, against the former twins: bit-identical on eight ALE decks; min / median ms per call
# before -> after (benchmarks/ale_kernels.py --trees BASE THIS --rounds 5 --calls 50, 1 thread, 6 Dec 2026,
# load 3.9-4.0, BASE = e629c8f): plane 1.30 / 1.34 -> 1.19 / 1.23, two materials 1.38 / 1.44 -> 1.29 / 1.33,
# ring 1.38 / 1.41 -> 1.27 / 1.33, hex8 7.29 / 7.43 -> 7.32 / 7.42.
# The plane quad4 and the r-z ring share this one (the ``ring`` flag): against main's two kernels, min / median
# of 30 alternated calls, 1 thread, load 4-5 (report alefold): plane 1.042 / 1.054, two materials 1.041 / 1.045,
# ring 1.024 / 1.040, where the unchanged forces kernel read 0.985-1.034 in the same runs (the noise floor).
@njit(parallel=True, cache=True)
def lagrange_energy(x, v_old, v_new, dt, conn, f_elem, vol_m, mass_m, ener_m, e_lag, pres_m, bulk_m, q_elem,
                    closure, alpha, beta, phi_eps, pressed, work_elem, ring):
    """Internal energy and material volumes over the Lagrangian step (module docstring, step 3).

    work_elem (E,) receives W_e, the internal-energy increment of the element. Material volumes
    follow the Lagrangian volume at x + dt v_new. Closure CLOSURE_EQUAL_STRAIN: dV_m = (V_m / V_p) dV over
    the present materials (V_p their volume; one at most phi_eps of the element keeps its volume);
    CLOSURE_RELAX: dV_m = dV (V_m/K_m) / S + alpha V_m (p_m - pbar) / K_m, S = sum V_k/K_k,
    pbar = sum (V_k p_k / K_k) / S (equal pressure increments plus a relaxation towards a common
    pressure), its departure from equal strain scaled down so that no material loses more than a
    fraction beta of its volume in one step; in an element a structure presses on (pressed (E,) bool, set by
    the couplings) a material without stiffness (void: the structure's volume) keeps its equal-strain share
    and the others relax among themselves. The Lagrangian volume is the quad's area (plane) or,
    with ring True (r-z), its exact ring volume (``ring_geometry.ring_volume``). The body: ``energy_elements``.
    """
    energy_elements(x, v_old, v_new, dt, conn, f_elem, vol_m, mass_m, ener_m, e_lag, pres_m, bulk_m, closure, alpha, beta,
                    phi_eps, pressed, work_elem, ring, 4, 2)


@njit(parallel=True, cache=True)
def lagrange_energy_3d(x, v_old, v_new, dt, conn, f_elem, vol_m, mass_m, ener_m, e_lag, pres_m, bulk_m, q_elem,
                       closure, alpha, beta, phi_eps, pressed, work_elem):
    """``lagrange_energy`` on hex8: compatible work W_e = -dt sum_I f_eI . (v_I^{n-1/2} + v_I^{n+1/2}) / 2,
    the Lagrangian volume (``fem.geometry.hex8_volume_origin``) at x + dt v^{n+1/2}, then the same closure
    (``energy_elements``)."""
    energy_elements(x, v_old, v_new, dt, conn, f_elem, vol_m, mass_m, ener_m, e_lag, pres_m, bulk_m, closure, alpha, beta,
                    phi_eps, pressed, work_elem, False, 8, 3)


@njit(parallel=True, cache=True)
def element_volumes_3d(x, conn, out):
    """Exact trilinear volume of every hex8 (``fem.geometry.hex8_volume_origin``), (E,)."""
    n_elem = conn.shape[0]
    n_chunks = min(n_elem, N_CHUNKS)
    for chunk in prange(n_chunks):
        p = np.empty((8, 3))
        start, stop = chunk_range(chunk, n_elem, n_chunks)
        for e in range(start, stop):
            r = conn[e, 0]
            for a in range(8):
                n = conn[e, a]
                for k in range(3):
                    p[a, k] = x[n, k] - x[r, k]
            out[e] = _volume_origin(p)
