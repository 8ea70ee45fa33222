"""Lagrangian solid elements: quad4 (plane strain or plane stress) and hex8, one-point integration.

Per element and step (central difference, paper eqs. 2.5-2.8):

1. rate of deformation d and spin w from the mid-step configuration x^{n+1/2} = x^{n+1} - dt/2 v^{n+1/2}
   with the uniform (mean) gradient b_I = (1/V) dV/dx_I (Flanagan & Belytschko 1981), which makes
   a linear velocity field give its exact gradient and a constant stress self-equilibrated
   (patch test) on any element shape;
2. stress rotated by the Hughes-Winget (Cayley) increment R = (I - dt/2 W)^-1 (I + dt/2 W), the
   objective integration of the Jaumann rate, then the material update with deps = d dt;
3. bulk (shock) viscosity q = rho l (Q1^2 l tr(d)^2 - Q2 c tr(d)) in compression (von Neumann &
   Richtmyer 1950; LS-DYNA's form);
4. internal force f_I = -V (sigma - q I) b_I at x^{n+1} (paper eq. 2.8 with one-point quadrature);
5. Flanagan-Belytschko hourglass forces on the hourglass shape vectors
   gamma_aI = Gamma_aI - (Gamma_a . x_k) b_kI, viscous (f = -a_h q gamma, a_h = QM rho c V^{(d-1)/d} / 4)
   or stiffness (Q += k q dt, f = -Q gamma, k = QM G V |b|^2 / 2, work (Q^n + Q^{n+1})/2 . q dt);
6. stable step l / (Q + sqrt(Q^2 + c^2)), Q = Q2 c + Q1^2 l |tr d| in compression (the signal speed
   the viscosity q adds), l = V / largest face (area in 3D, edge in 2D).

Plane stress (quad4 of a section with ``formulation: plane_stress``, ``SEC_FORMULATION`` = ``PLANE_STRESS``):
the thickness strain increment d_zz dt is solved so that sigma_zz = 0 (``materials.kernels``
``elastic_plane_stress_update``, ``plane_stress_update``), summed into the logarithmic thickness strain
hist[H_THICKNESS_STRAIN] = ln(h/h0), and the element's volume per unit initial thickness A h/h0 takes the
place of A in the forces, the energy, the density and the hourglass coefficients; the stable step
takes the plane-stress wave speed sqrt(E / ((1 - nu^2) rho)) (``plane_stress_sound_speed``).

Element results are written per element (forces per element node); `gather_nodal_forces` sums them
at nodes through the node->element map, so results do not depend on the thread count.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ..materials.ids import ELASTIC, EOS_NONE
from ..materials.kernels import (elastic_plane_stress_update, elastic_sound_speed, elastic_stress_update,
                                 plane_stress_sound_speed, plane_stress_update, sound_speed, update_stress)
from ..materials.slots import H_THICKNESS_STRAIN, P_EOS_TYPE, P_G, P_RHO0
from .geometry import (bulk_viscosity, hex8_char_length, hex8_gradient_faces, quad4_char_length,
                       quad4_gradient, stable_dt)
from .slots import (  # noqa: F401  (re-exported: declared in fem.slots)
    HG_STIFFNESS, HG_VISCOUS, INVERTED, NSEC, PLANE_STRAIN, PLANE_STRESS, SEC_FORMULATION, SEC_HG_COEF, SEC_HG_TYPE,
    SEC_Q1, SEC_Q2,
)
from .tables import HEX_GAMMA, QUAD_GAMMA


@njit(cache=True)
def rotate_stress(s, w_xy, w_yz, w_zx, dt):
    """s <- R s R^T with R the Cayley transform of S = dt/2 W (Hughes & Winget 1980).

    W is the spin, W_ij = (L_ij - L_ji)/2, given by its components w_xy, w_yz, w_zx;
    R = I + 2/(1 + |a|^2) (S + S^2), a the axial vector of S (an exact rotation).
    """
    h = 0.5 * dt
    a = h * w_xy  # S_xy = -S_yx
    b = h * w_yz  # S_yz = -S_zy
    c = h * w_zx  # S_zx = -S_xz
    if a == 0.0 and b == 0.0 and c == 0.0:
        return
    f = 2.0 / (1.0 + a * a + b * b + c * c)
    # S = [[0, a, -c], [-a, 0, b], [c, -b, 0]]; S^2 is symmetric.
    r00 = 1.0 + f * (-a * a - c * c)
    r11 = 1.0 + f * (-a * a - b * b)
    r22 = 1.0 + f * (-b * b - c * c)
    r01 = f * (a + b * c)
    r10 = f * (-a + b * c)
    r02 = f * (-c + a * b)
    r20 = f * (c + a * b)
    r12 = f * (b + a * c)
    r21 = f * (-b + a * c)
    sxx, syy, szz, sxy, syz, szx = s[0], s[1], s[2], s[3], s[4], s[5]
    # T = R s
    t00 = r00 * sxx + r01 * sxy + r02 * szx
    t01 = r00 * sxy + r01 * syy + r02 * syz
    t02 = r00 * szx + r01 * syz + r02 * szz
    t10 = r10 * sxx + r11 * sxy + r12 * szx
    t11 = r10 * sxy + r11 * syy + r12 * syz
    t12 = r10 * szx + r11 * syz + r12 * szz
    t20 = r20 * sxx + r21 * sxy + r22 * szx
    t21 = r20 * sxy + r21 * syy + r22 * syz
    t22 = r20 * szx + r21 * syz + r22 * szz
    # s' = T R^T
    s[0] = t00 * r00 + t01 * r01 + t02 * r02
    s[1] = t10 * r10 + t11 * r11 + t12 * r12
    s[2] = t20 * r20 + t21 * r21 + t22 * r22
    s[3] = t00 * r10 + t01 * r11 + t02 * r12
    s[4] = t10 * r20 + t11 * r21 + t12 * r22
    s[5] = t20 * r00 + t21 * r01 + t22 * r02


@njit(cache=True)
def _stress_power(s, d):
    """s : d with tensor components in order xx, yy, zz, xy, yz, zx."""
    return s[0] * d[0] + s[1] * d[1] + s[2] * d[2] + 2.0 * (s[3] * d[3] + s[4] * d[4] + s[5] * d[5])


def solid_element_forces(
    x, v, conn, active, elem_mat, elem_sec, mat_type, mat_param, sec_param,
    vol0, dt, stress, hist, energy, hg_energy, hg_force, f_elem, dt_elem, vol, q_visc,
):
    """One step of every active solid element (see module docstring).

    Inputs: node coordinates x^{n+1} (N, dim), velocities v^{n+1/2} (N, dim), connectivity
    (E, 4|8), active (E,) bool (rigid-part elements are inactive), material/section ids and tables,
    initial volumes vol0 (E,), the step dt just taken.
    Updated in place: stress (E, 6), hist (E, NHIST), energy (E,) internal energy, hg_energy (E,),
    hg_force (E, modes, dim) stiffness hourglass resultants.
    Written: f_elem (E, nodes, dim) force on each element node, dt_elem (E,) stable step
    (INVERTED where the volume is not positive), vol (E,), q_visc (E,) bulk viscosity.

    hex8 meshes go to ``hex8_element_forces`` (``_hex8_elements``: the same operations in the same
    order with the dimension and node count as constants, except the factored mean gradient
    ``hex8_gradient_faces``, equal up to round-off), quad4 meshes to ``quad4_element_forces``. In both,
    an elastic material without an equation of state takes ``elastic_stress_update`` /
    ``elastic_sound_speed`` (the same bits as ``update_stress`` / ``sound_speed``). A quad4 of a
    plane-stress section (``sec[SEC_FORMULATION] == PLANE_STRESS``) solves its thickness strain (module
    docstring); vol is then A h/h0, the volume per unit initial thickness.

    This function, plain Python, only picks the kernel, so that a plane deck compiles no hex8 code and a
    3D deck no quad4 code (issue 17: a cold cache's first run).
    """
    kernel = hex8_element_forces if conn.shape[1] == 8 and x.shape[1] == 3 else quad4_element_forces
    kernel(x, v, conn, active, elem_mat, elem_sec, mat_type, mat_param, sec_param,
           vol0, dt, stress, hist, energy, hg_energy, hg_force, f_elem, dt_elem, vol, q_visc)


@njit(parallel=True, cache=True)
def hex8_element_forces(
    x, v, conn, active, elem_mat, elem_sec, mat_type, mat_param, sec_param,
    vol0, dt, stress, hist, energy, hg_energy, hg_force, f_elem, dt_elem, vol, q_visc,
):
    """``solid_element_forces`` of a hex8 mesh: ``_hex8_elements`` over chunks of elements."""
    n_elem = conn.shape[0]
    n_chunks = min(n_elem, 64 * 8)
    for chunk in prange(n_chunks):
        _hex8_elements(
            chunk * n_elem // n_chunks, (chunk + 1) * n_elem // n_chunks,
            x, v, conn, active, elem_mat, elem_sec, mat_type, mat_param, sec_param,
            vol0, dt, stress, hist, energy, hg_energy, hg_force, f_elem, dt_elem, vol, q_visc,
        )


@njit(parallel=True, cache=True)
def quad4_element_forces(
    x, v, conn, active, elem_mat, elem_sec, mat_type, mat_param, sec_param,
    vol0, dt, stress, hist, energy, hg_energy, hg_force, f_elem, dt_elem, vol, q_visc,
):
    """``solid_element_forces`` of a quad4 mesh (plane strain or plane stress)."""
    n_elem, npe = conn.shape
    dim = x.shape[1]
    n_chunks = min(n_elem, 64 * 8)
    for chunk in prange(n_chunks):
        start = chunk * n_elem // n_chunks
        stop = (chunk + 1) * n_elem // n_chunks
        nd = npe * dim
        nh = hist.shape[1]
        scratch = np.empty(5 * nd + 3 * 6 + npe + 2 * 3 + 6 + nh)  # one allocation per chunk, carved below
        xe = scratch[0:nd].reshape((npe, dim))
        xm = scratch[nd:2 * nd].reshape((npe, dim))
        ve = scratch[2 * nd:3 * nd].reshape((npe, dim))
        b = scratch[3 * nd:4 * nd].reshape((dim, npe))
        bm = scratch[4 * nd:5 * nd].reshape((dim, npe))
        deps = scratch[5 * nd:5 * nd + 6]
        d = scratch[5 * nd + 6:5 * nd + 12]
        sig_old = scratch[5 * nd + 12:5 * nd + 18]
        gam = scratch[5 * nd + 18:5 * nd + 18 + npe]
        gx = scratch[5 * nd + 18 + npe:5 * nd + 21 + npe]
        qv = scratch[5 * nd + 21 + npe:5 * nd + 24 + npe]
        sig_start = scratch[5 * nd + 24 + npe:5 * nd + 30 + npe]  # plane stress: the trials' start
        hist_start = scratch[5 * nd + 30 + npe:5 * nd + 30 + npe + nh]
        for e in range(start, stop):
            if not active[e]:
                dt_elem[e] = np.inf
                continue
            for a in range(npe):
                n = conn[e, a]
                for k in range(dim):
                    xe[a, k] = x[n, k]
                    ve[a, k] = v[n, k]
                    xm[a, k] = x[n, k] - 0.5 * dt * v[n, k]
            vm = quad4_gradient(xm, bm)
            ve_new = quad4_gradient(xe, b)
            vol[e] = ve_new
            if not (ve_new > 0.0 and vm > 0.0):
                dt_elem[e] = INVERTED
                for a in range(npe):
                    for k in range(dim):
                        f_elem[e, a, k] = 0.0
                continue

            # Velocity gradient L_ij = sum_a v_ia b_ja at mid-step.
            lxx = lyy = lzz = lxy = lyx = lyz = lzy = lzx = lxz = 0.0
            for a in range(npe):
                lxx += ve[a, 0] * bm[0, a]
                lxy += ve[a, 0] * bm[1, a]
                lyx += ve[a, 1] * bm[0, a]
                lyy += ve[a, 1] * bm[1, a]
            d[0] = lxx
            d[1] = lyy
            d[2] = lzz
            d[3] = 0.5 * (lxy + lyx)
            d[4] = 0.5 * (lyz + lzy)
            d[5] = 0.5 * (lzx + lxz)
            trace_d = lxx + lyy + lzz

            m = elem_mat[e]
            p = mat_param[m]
            sec = sec_param[elem_sec[e]]
            sig = stress[e]
            for c in range(6):
                sig_old[c] = sig[c]
                deps[c] = d[c] * dt
            rotate_stress(sig, 0.5 * (lxy - lyx), 0.5 * (lyz - lzy), 0.5 * (lzx - lxz), dt)
            rel_volume = ve_new / vol0[e]
            # Thickness over initial thickness h/h0 at mid-step and end of step (1: plane strain, 3D).
            thick_mid = 1.0
            thick_new = 1.0
            if sec[SEC_FORMULATION] == PLANE_STRESS:
                eps_zz = hist[e, H_THICKNESS_STRAIN]
                if mat_type[m] == ELASTIC:
                    elastic_plane_stress_update(p, sig, deps)
                else:
                    plane_stress_update(mat_type[m], p, sig, hist[e], deps, dt, rel_volume, energy[e] / vol0[e],
                                        sig_start, hist_start)
                hist[e, H_THICKNESS_STRAIN] = eps_zz + deps[2]  # ln(h/h0) += d_zz dt
                thick_mid = math.exp(eps_zz + 0.5 * deps[2])
                thick_new = math.exp(eps_zz + deps[2])
                rel_volume = rel_volume * thick_new
                c_snd = plane_stress_sound_speed(p, rel_volume)
            elif mat_type[m] == ELASTIC and p[P_EOS_TYPE] == EOS_NONE:  # the same numbers, inlined
                elastic_stress_update(p, sig, deps)
                c_snd = elastic_sound_speed(p, rel_volume)
            else:
                update_stress(mat_type[m], p, sig, hist[e], deps, dt, rel_volume, energy[e] / vol0[e])
                c_snd = sound_speed(mat_type[m], p, rel_volume, energy[e] / vol0[e])
            vol_t = ve_new * thick_new  # the volume per unit initial thickness (A h/h0); V in 3D
            vol[e] = vol_t
            rho = p[P_RHO0] / rel_volume
            length = quad4_char_length(xe, ve_new)
            q = bulk_viscosity(rho, length, c_snd, trace_d, sec[SEC_Q1], sec[SEC_Q2])
            q_visc[e] = q
            dt_elem[e] = stable_dt(length, c_snd, trace_d, sec[SEC_Q1], sec[SEC_Q2])

            # Internal energy: mid-step stress power plus bulk-viscosity work (in plane stress
            # sigma_zz = 0, so d_zz does no work, and q, driven by the in-plane trace, works on it).
            power = 0.5 * (_stress_power(sig_old, d) + _stress_power(sig, d)) - q * trace_d
            energy[e] += power * (vm * thick_mid) * dt

            # f_I = -V (sigma - q I) . b_I
            sxx = sig[0] - q
            syy = sig[1] - q
            for a in range(npe):
                f_elem[e, a, 0] = -vol_t * (sxx * b[0, a] + sig[3] * b[1, a])
                f_elem[e, a, 1] = -vol_t * (sig[3] * b[0, a] + syy * b[1, a])

            # Flanagan-Belytschko hourglass control.
            qm = sec[SEC_HG_COEF]
            if qm > 0.0:
                n_modes = 1
                if sec[SEC_HG_TYPE] == HG_VISCOUS:
                    scale = ve_new ** ((dim - 1.0) / dim)
                    coef = 0.25 * qm * rho * c_snd * scale * thick_new
                else:
                    bb = 0.0
                    for k in range(dim):
                        for a in range(npe):
                            bb += b[k, a] * b[k, a]
                    coef = 0.5 * qm * p[P_G] * vol_t * bb
                for mode in range(n_modes):
                    # gamma_a = Gamma_a - (Gamma . x_k) b_k
                    gx[0] = gx[1] = gx[2] = 0.0
                    qv[0] = qv[1] = qv[2] = 0.0
                    for a in range(npe):
                        g = QUAD_GAMMA[a]
                        for k in range(dim):
                            gx[k] += g * xe[a, k]
                    for a in range(npe):
                        g = QUAD_GAMMA[a]
                        for k in range(dim):
                            g -= gx[k] * b[k, a]
                        gam[a] = g
                        for k in range(dim):
                            qv[k] += ve[a, k] * g
                    work = 0.0
                    for k in range(dim):
                        if sec[SEC_HG_TYPE] == HG_VISCOUS:
                            resultant = coef * qv[k]
                            work += resultant * qv[k] * dt
                        else:
                            # Stored (elastic) energy: trapezoidal work of the resultant over the
                            # step, as for the stress power, so that it sums to Q^2/(2k).
                            old = hg_force[e, mode, k]
                            hg_force[e, mode, k] += coef * qv[k] * dt
                            resultant = hg_force[e, mode, k]
                            work += 0.5 * (old + resultant) * qv[k] * dt
                        for a in range(npe):
                            f_elem[e, a, k] -= resultant * gam[a]
                    hg_energy[e] += work


@njit(cache=True)
def _hex8_elements(
    start, stop, x, v, conn, active, elem_mat, elem_sec, mat_type, mat_param, sec_param,
    vol0, dt, stress, hist, energy, hg_energy, hg_force, f_elem, dt_elem, vol, q_visc,
):
    """Elements start..stop-1 of a hex8 mesh: ``quad4_element_forces``' loop for dim = 3, npe = 8.

    Every value is computed by the operations of that loop, written for three dimensions (the z terms
    of the velocity gradient and of the forces, four hourglass modes), except the mean gradients,
    which take the factored ``hex8_gradient_faces`` (``hex8_gradient``'s numbers up to round-off, a
    third of the operations); the loops over nodes (8) and
    components (3) have constant trip counts that LLVM unrolls; a loop over the 4 hourglass modes
    stays a loop (its body is too large to unroll), so the sums Gamma_m . x_k are written out with
    HEX_GAMMA's signs (the same bits: a product by +-1 is exact; 4-6 % of the element kernel,
    benchmarks/fem_passes.py) and the shape vectors, mode velocities and forces are computed node by
    node for the 4 modes together, each sum in the order of the mode-by-mode loop (the same bits;
    2-4 %); the nodal data sit in three (8, 3) scratch arrays, the
    viscous / stiffness hourglass choice is made once per element, and an elastic material without
    an equation of state takes ``elastic_stress_update`` / ``elastic_sound_speed`` (the same
    numbers as ``update_stress`` / ``sound_speed``, small enough to inline).

    Not compiled with ``fastmath={"contract"}`` (fused multiply-adds): 7-8 % faster, but the bits then
    depended on the compile path (a callee compiled and cached before, e.g. by a unit test, gave
    results other than a fresh compile of the whole kernel), against the rule that cached and
    compiled runs are bit-identical (branch hex8speed, 6 Dec 2026).
    """
    scratch = np.empty(5 * 24 + 3 * 6 + 32 + 12 + 12)  # one allocation per chunk, carved into the work arrays
    xe = scratch[0:24].reshape((8, 3))
    xm = scratch[24:48].reshape((8, 3))
    ve = scratch[48:72].reshape((8, 3))
    b = scratch[72:96].reshape((3, 8))
    bm = scratch[96:120].reshape((3, 8))
    d = scratch[120:126]  # rate of deformation
    deps = scratch[126:132]  # strain increment d dt
    sig_old = scratch[132:138]  # stress at the start of the step
    gam = scratch[138:170].reshape((4, 8))  # hourglass shape vectors gamma_ma
    gxm = scratch[170:182].reshape((4, 3))  # Gamma_m . x_k of the hourglass modes
    qvm = scratch[182:194].reshape((4, 3))  # their velocities q_mk, then resultants r_mk
    half_dt = 0.5 * dt
    for e in range(start, stop):
        if not active[e]:
            dt_elem[e] = np.inf
            continue
        for a in range(8):
            n = conn[e, a]
            for k in range(3):
                xe[a, k] = x[n, k]
                ve[a, k] = v[n, k]
                xm[a, k] = x[n, k] - half_dt * v[n, k]
        vm = hex8_gradient_faces(xm, bm)
        ve_new = hex8_gradient_faces(xe, b)
        vol[e] = ve_new
        if not (ve_new > 0.0 and vm > 0.0):
            dt_elem[e] = INVERTED
            for a in range(8):
                for k in range(3):
                    f_elem[e, a, k] = 0.0
            continue

        # Velocity gradient L_ij = sum_a v_ia b_ja at mid-step.
        lxx = lyy = lzz = lxy = lyx = lyz = lzy = lzx = lxz = 0.0
        for a in range(8):
            lxx += ve[a, 0] * bm[0, a]
            lxy += ve[a, 0] * bm[1, a]
            lyx += ve[a, 1] * bm[0, a]
            lyy += ve[a, 1] * bm[1, a]
            lxz += ve[a, 0] * bm[2, a]
            lzx += ve[a, 2] * bm[0, a]
            lyz += ve[a, 1] * bm[2, a]
            lzy += ve[a, 2] * bm[1, a]
            lzz += ve[a, 2] * bm[2, a]
        d[0] = lxx
        d[1] = lyy
        d[2] = lzz
        d[3] = 0.5 * (lxy + lyx)
        d[4] = 0.5 * (lyz + lzy)
        d[5] = 0.5 * (lzx + lxz)
        trace_d = lxx + lyy + lzz

        m = elem_mat[e]
        p = mat_param[m]
        sec = sec_param[elem_sec[e]]
        sig = stress[e]
        for c in range(6):
            sig_old[c] = sig[c]
            deps[c] = d[c] * dt
        rotate_stress(sig, 0.5 * (lxy - lyx), 0.5 * (lyz - lzy), 0.5 * (lzx - lxz), dt)
        rel_volume = ve_new / vol0[e]
        rho = p[P_RHO0] / rel_volume
        if mat_type[m] == ELASTIC and p[P_EOS_TYPE] == EOS_NONE:  # the same numbers, inlined
            elastic_stress_update(p, sig, deps)
            c_snd = elastic_sound_speed(p, rel_volume)
        else:
            update_stress(mat_type[m], p, sig, hist[e], deps, dt, rel_volume, energy[e] / vol0[e])
            c_snd = sound_speed(mat_type[m], p, rel_volume, energy[e] / vol0[e])
        length = hex8_char_length(xe, ve_new)
        q = bulk_viscosity(rho, length, c_snd, trace_d, sec[SEC_Q1], sec[SEC_Q2])
        q_visc[e] = q
        dt_elem[e] = stable_dt(length, c_snd, trace_d, sec[SEC_Q1], sec[SEC_Q2])

        # Internal energy: mid-step stress power plus bulk-viscosity work.
        power = 0.5 * (_stress_power(sig_old, d) + _stress_power(sig, d)) - q * trace_d
        energy[e] += power * vm * dt

        # f_I = -V (sigma - q I) . b_I
        sxx = sig[0] - q
        syy = sig[1] - q
        szz = sig[2] - q
        sxy = sig[3]
        syz = sig[4]
        szx = sig[5]
        for a in range(8):
            f_elem[e, a, 0] = -ve_new * (sxx * b[0, a] + sxy * b[1, a] + szx * b[2, a])
            f_elem[e, a, 1] = -ve_new * (sxy * b[0, a] + syy * b[1, a] + syz * b[2, a])
            f_elem[e, a, 2] = -ve_new * (szx * b[0, a] + syz * b[1, a] + szz * b[2, a])

        # Flanagan-Belytschko hourglass control.
        qm = sec[SEC_HG_COEF]
        if qm > 0.0:
            viscous = sec[SEC_HG_TYPE] == HG_VISCOUS
            if viscous:
                # V^(2/3) stays a pow: cbrt(V)^2 measured no faster (22.0 against 23.3 ns a call).
                coef = 0.25 * qm * rho * c_snd * ve_new ** ((3 - 1.0) / 3)
            else:
                bb = 0.0
                for k in range(3):
                    for a in range(8):
                        bb += b[k, a] * b[k, a]
                coef = 0.5 * qm * p[P_G] * ve_new * bb
            # Gamma_m . x_k of the 4 modes, HEX_GAMMA's signs written out (the bits of summing g x_ak
            # from 0.0 in node order: a product by +-1 is exact).
            for k in range(3):
                x0, x1, x2, x3 = xe[0, k], xe[1, k], xe[2, k], xe[3, k]
                x4, x5, x6, x7 = xe[4, k], xe[5, k], xe[6, k], xe[7, k]
                gxm[0, k] = 0.0 + x0 - x1 + x2 - x3 + x4 - x5 + x6 - x7
                gxm[1, k] = 0.0 + x0 + x1 - x2 - x3 - x4 - x5 + x6 + x7
                gxm[2, k] = 0.0 + x0 - x1 - x2 + x3 - x4 + x5 + x6 - x7
                gxm[3, k] = 0.0 - x0 + x1 - x2 + x3 + x4 - x5 + x6 - x7
            # gamma_ma = Gamma_ma - (Gamma_m . x_k) b_ka and q_mk = sum_a v_ak gamma_ma, node by node with
            # the 4 modes together (b_a, v_a read once; each sum still in node order).
            g00, g01, g02 = gxm[0, 0], gxm[0, 1], gxm[0, 2]
            g10, g11, g12 = gxm[1, 0], gxm[1, 1], gxm[1, 2]
            g20, g21, g22 = gxm[2, 0], gxm[2, 1], gxm[2, 2]
            g30, g31, g32 = gxm[3, 0], gxm[3, 1], gxm[3, 2]
            q00 = q01 = q02 = q10 = q11 = q12 = q20 = q21 = q22 = q30 = q31 = q32 = 0.0
            for a in range(8):
                b0, b1, b2 = b[0, a], b[1, a], b[2, a]
                v0, v1, v2 = ve[a, 0], ve[a, 1], ve[a, 2]
                g = HEX_GAMMA[0, a] - g00 * b0 - g01 * b1 - g02 * b2
                gam[0, a] = g
                q00 += v0 * g
                q01 += v1 * g
                q02 += v2 * g
                g = HEX_GAMMA[1, a] - g10 * b0 - g11 * b1 - g12 * b2
                gam[1, a] = g
                q10 += v0 * g
                q11 += v1 * g
                q12 += v2 * g
                g = HEX_GAMMA[2, a] - g20 * b0 - g21 * b1 - g22 * b2
                gam[2, a] = g
                q20 += v0 * g
                q21 += v1 * g
                q22 += v2 * g
                g = HEX_GAMMA[3, a] - g30 * b0 - g31 * b1 - g32 * b2
                gam[3, a] = g
                q30 += v0 * g
                q31 += v1 * g
                q32 += v2 * g
            qvm[0, 0], qvm[0, 1], qvm[0, 2] = q00, q01, q02
            qvm[1, 0], qvm[1, 1], qvm[1, 2] = q10, q11, q12
            qvm[2, 0], qvm[2, 1], qvm[2, 2] = q20, q21, q22
            qvm[3, 0], qvm[3, 1], qvm[3, 2] = q30, q31, q32
            work = hg_energy[e]
            for mode in range(4):
                qv0, qv1, qv2 = qvm[mode, 0], qvm[mode, 1], qvm[mode, 2]
                if viscous:
                    r0 = coef * qv0
                    r1 = coef * qv1
                    r2 = coef * qv2
                    mode_work = 0.0 + r0 * qv0 * dt + r1 * qv1 * dt + r2 * qv2 * dt
                else:
                    # Stored (elastic) energy: trapezoidal work of the resultant over the step.
                    o0 = hg_force[e, mode, 0]
                    o1 = hg_force[e, mode, 1]
                    o2 = hg_force[e, mode, 2]
                    r0 = o0 + coef * qv0 * dt
                    r1 = o1 + coef * qv1 * dt
                    r2 = o2 + coef * qv2 * dt
                    hg_force[e, mode, 0] = r0
                    hg_force[e, mode, 1] = r1
                    hg_force[e, mode, 2] = r2
                    mode_work = (0.0 + 0.5 * (o0 + r0) * qv0 * dt + 0.5 * (o1 + r1) * qv1 * dt
                                 + 0.5 * (o2 + r2) * qv2 * dt)
                qvm[mode, 0], qvm[mode, 1], qvm[mode, 2] = r0, r1, r2  # the resultant r_m replaces q_m
                work += mode_work
            hg_energy[e] = work
            # f_aI -= r_m gamma_ma, modes in order 0..3 (the bits of adding them one mode at a time).
            r00, r01, r02 = qvm[0, 0], qvm[0, 1], qvm[0, 2]
            r10, r11, r12 = qvm[1, 0], qvm[1, 1], qvm[1, 2]
            r20, r21, r22 = qvm[2, 0], qvm[2, 1], qvm[2, 2]
            r30, r31, r32 = qvm[3, 0], qvm[3, 1], qvm[3, 2]
            for a in range(8):
                y0, y1, y2, y3 = gam[0, a], gam[1, a], gam[2, a], gam[3, a]
                f_elem[e, a, 0] = f_elem[e, a, 0] - r00 * y0 - r10 * y1 - r20 * y2 - r30 * y3
                f_elem[e, a, 1] = f_elem[e, a, 1] - r01 * y0 - r11 * y1 - r21 * y2 - r31 * y3
                f_elem[e, a, 2] = f_elem[e, a, 2] - r02 * y0 - r12 * y1 - r22 * y2 - r32 * y3


@njit(parallel=True, cache=True)
def gather_nodal_forces(f_elem, node_elem_ptr, node_elem_idx, out):
    """out[n] = sum of f_elem[e, a] over the (e, a) pairs listed for node n (CSR map).

    node_elem_idx holds e * nodes_per_element + a; a gather, so deterministic for any thread count.
    """
    n_nodes, dim = out.shape
    f = f_elem.reshape((f_elem.shape[0] * f_elem.shape[1], dim))  # row e * npe + a: the listed index
    if dim == 3:  # sums in scalars, in list order (the same bits as summing into out)
        for n in prange(n_nodes):
            f0 = f1 = f2 = 0.0
            for r in range(node_elem_ptr[n], node_elem_ptr[n + 1]):
                ea = node_elem_idx[r]
                f0 += f[ea, 0]
                f1 += f[ea, 1]
                f2 += f[ea, 2]
            out[n, 0] = f0
            out[n, 1] = f1
            out[n, 2] = f2
        return
    for n in prange(n_nodes):
        for k in range(dim):
            out[n, k] = 0.0
        for r in range(node_elem_ptr[n], node_elem_ptr[n + 1]):
            ea = node_elem_idx[r]
            for k in range(dim):
                out[n, k] += f[ea, k]


@njit(parallel=True, cache=True)
def central_difference_update(x, v, f_int, f_ext, inv_mass, free, v_prescribed, dt_avg, dt, power):
    """One central-difference step for the nodes (paper eq. 2.7).

    v^{n+1/2} = v^{n-1/2} + dt_avg (f_int + f_ext)/m where free is 1, v_prescribed where free is 0;
    x^{n+1} = x^n + dt v^{n+1/2}. power[n] receives the work of the applied forces over the step,
    F . (v^{n-1/2} + v^{n+1/2})/2 dt_avg, with F = f_ext on free components and the reaction
    m a - f_int on prescribed ones; summing it afterwards keeps the total order-independent.
    """
    n_nodes, dim = x.shape
    for n in prange(n_nodes):
        w = 0.0
        for k in range(dim):
            v_old = v[n, k]
            if free[n, k]:
                v_new = v_old + dt_avg * (f_int[n, k] + f_ext[n, k]) * inv_mass[n]
                applied = f_ext[n, k]
            else:
                v_new = v_prescribed[n, k]
                applied = (v_new - v_old) / dt_avg / inv_mass[n] - f_int[n, k] if dt_avg > 0.0 else 0.0
            w += applied * 0.5 * (v_old + v_new) * dt_avg
            v[n, k] = v_new
            x[n, k] += dt * v_new
        power[n] = w
