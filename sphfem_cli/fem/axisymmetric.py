"""Axisymmetric quad4 solid (``dimension: axisymmetric``): one-point integration, volume-weighted form.

The meridian plane holds x = r >= 0 and y = z (the axis); the element is the ring swept by the quad
about the axis, and every force, mass and energy is for the full 2 pi (not per radian).

Formulation (volume-weighted, one point at the element centre xi = eta = 0; Hallquist, LS-DYNA
Theory Manual, "axisymmetric solid elements", type 15; Belytschko, Liu & Moran, Nonlinear Finite
Elements, sect. 4.4 and 8.4):

- r_c = (1/4) sum r_I (the radius of the centre point), A the quad's area, b_I the mean plane gradient
  (``fem.geometry.quad4_gradient``); the element volume is the one-point ring volume V = 2 pi r_c A.
- rate of deformation: d_rr = sum v_rI b_rI, d_zz = sum v_zI b_zI, d_rz = (sum v_rI b_zI + v_zI b_rI)/2,
  and the hoop rate d_tt = v_r(centre)/r_c = (1/4) sum v_rI / r_c, stored in slot zz of the 6-vector
  (stress zz is the hoop stress), so every material model takes it unchanged.
- internal force, the exact derivative of the one-point internal work V sigma : d:
  f_rI = -2 pi A [r_c (s_rr b_rI + s_rz b_zI) + s_tt / 4],  f_zI = -2 pi A r_c (s_rz b_rI + s_zz b_zI).
  Then sum_I f_I . v_I = -V sigma : d exactly, so the internal energy V sigma : d dt balances the
  work of the nodal forces to round-off (energy conservation); a uniform axial translation and any
  stress give no net axial force; a linear field v_r = a r gives d_tt = a exactly.
- Flanagan-Belytschko hourglass control in the r-z plane on the same gamma vectors as the plane
  quad4, weighted by 2 pi r_c: viscous a_h = QM rho c sqrt(A) 2 pi r_c / 4, stiffness k = QM G V |b|^2 / 2.
- stable step: the plane length A / longest edge, times sqrt(|b|^2 / (|b|^2 + 1/(4 r_c^2))), the
  part of the element's gradient norm the hoop term adds (sum_I (b_rI + 1/(4 r_c))^2 = |b_r|^2 + 1/(4 r_c^2)):
  1 far from the axis, sqrt(2/3) for a square element on it.

Why volume-weighted and not area-weighted (LS-DYNA type 14, forces per radian with the r-z terms
not weighted by r): the volume-weighted form is the consistent discretisation of the principle of
virtual power, so it conserves energy and axial momentum to round-off, and it converges to the Lame
solution; the area-weighted form behaves better for elements on the axis under hoop loading but
does not balance energy exactly (its forces are not the derivative of a work). Axis nodes (r = 0)
have u_r = 0 (``solver.boundary.Constraints``), which removes the one weakness of this form there.

Masses are lumped as for the plane and 3D elements, rho V0 / 4 per node with V0 = 2 pi r_c A at t = 0
(``model.build``): the same lumping the stable step assumes, and total mass rho0 sum V0 = the mass the
one-point densities rho0 V0 / V carry.
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from ..materials.kernels import sound_speed, update_stress
from ..materials.slots import P_G, P_RHO0
from .geometry import bulk_viscosity, quad4_char_length, quad4_gradient, stable_dt
from .kernels import HG_VISCOUS, INVERTED, SEC_HG_COEF, SEC_HG_TYPE, SEC_Q1, SEC_Q2, rotate_stress
from .tables import QUAD_GAMMA

TWO_PI = 2.0 * np.pi


@njit(cache=True)
def _stress_power(s, d):
    return s[0] * d[0] + s[1] * d[1] + s[2] * d[2] + 2.0 * (s[3] * d[3] + s[4] * d[4] + s[5] * d[5])


@njit(parallel=True, cache=True)
def axisymmetric_element_forces(
    x, v, conn, active, elem_mat, elem_sec, mat_type, mat_param, sec_param,
    vol0, dt, stress, hist, energy, hg_energy, hg_force, f_elem, dt_elem, vol, q_visc,
):
    """One step of every active axisymmetric quad4 (module docstring); the arguments and what is
    updated and written are those of ``fem.kernels.solid_element_forces`` (dim 2, vol the ring volumes)."""
    n_elem = conn.shape[0]
    n_chunks = min(n_elem, 64 * 8)
    for chunk in prange(n_chunks):
        start = chunk * n_elem // n_chunks
        stop = (chunk + 1) * n_elem // n_chunks
        xe = np.empty((4, 2))
        xm = np.empty((4, 2))
        ve = np.empty((4, 2))
        b = np.empty((2, 4))
        bm = np.empty((2, 4))
        deps = np.empty(6)
        d = np.empty(6)
        sig_old = np.empty(6)
        gam = np.empty(4)
        for e in range(start, stop):
            if not active[e]:
                dt_elem[e] = np.inf
                continue
            rc = 0.0
            rcm = 0.0
            vr = 0.0
            for a in range(4):
                n = conn[e, a]
                for k in range(2):
                    xe[a, k] = x[n, k]
                    ve[a, k] = v[n, k]
                    xm[a, k] = x[n, k] - 0.5 * dt * v[n, k]
                rc += 0.25 * xe[a, 0]
                rcm += 0.25 * xm[a, 0]
                vr += 0.25 * ve[a, 0]
            area_m = quad4_gradient(xm, bm)
            area = quad4_gradient(xe, b)
            vm = TWO_PI * rcm * area_m
            ve_new = TWO_PI * rc * area
            vol[e] = ve_new
            if not (area > 0.0 and area_m > 0.0 and rc > 0.0 and rcm > 0.0):
                dt_elem[e] = INVERTED
                for a in range(4):
                    f_elem[e, a, 0] = 0.0
                    f_elem[e, a, 1] = 0.0
                continue

            lxx = lyy = lxy = lyx = 0.0
            for a in range(4):
                lxx += ve[a, 0] * bm[0, a]
                lxy += ve[a, 0] * bm[1, a]
                lyx += ve[a, 1] * bm[0, a]
                lyy += ve[a, 1] * bm[1, a]
            hoop = vr / rcm
            d[0] = lxx
            d[1] = lyy
            d[2] = hoop
            d[3] = 0.5 * (lxy + lyx)
            d[4] = 0.0
            d[5] = 0.0
            trace_d = lxx + lyy + hoop

            m = elem_mat[e]
            p = mat_param[m]
            sec = sec_param[elem_sec[e]]
            sig = stress[e]
            for c in range(6):
                sig_old[c] = sig[c]
                deps[c] = d[c] * dt
            rotate_stress(sig, 0.5 * (lxy - lyx), 0.0, 0.0, dt)
            rel_volume = ve_new / vol0[e]
            update_stress(mat_type[m], p, sig, hist[e], deps, dt, rel_volume, energy[e] / vol0[e])

            rho = p[P_RHO0] / rel_volume
            c_snd = sound_speed(mat_type[m], p, rel_volume, energy[e] / vol0[e])
            bb = 0.0
            for k in range(2):
                for a in range(4):
                    bb += b[k, a] * b[k, a]
            hoop_g = 0.25 / (rc * rc)
            length = quad4_char_length(xe, area) * np.sqrt(bb / (bb + hoop_g))
            q = bulk_viscosity(rho, length, c_snd, trace_d, sec[SEC_Q1], sec[SEC_Q2])
            q_visc[e] = q
            dt_elem[e] = stable_dt(length, c_snd, trace_d, sec[SEC_Q1], sec[SEC_Q2])

            power = 0.5 * (_stress_power(sig_old, d) + _stress_power(sig, d)) - q * trace_d
            energy[e] += power * vm * dt

            srr = sig[0] - q
            szz = sig[1] - q
            stt = sig[2] - q
            srz = sig[3]
            ring = TWO_PI * area
            for a in range(4):
                f_elem[e, a, 0] = -ring * (rc * (srr * b[0, a] + srz * b[1, a]) + 0.25 * stt)
                f_elem[e, a, 1] = -ring * rc * (srz * b[0, a] + szz * b[1, a])

            qm = sec[SEC_HG_COEF]
            if qm > 0.0:
                if sec[SEC_HG_TYPE] == HG_VISCOUS:
                    coef = 0.25 * qm * rho * c_snd * np.sqrt(area) * TWO_PI * rc
                else:
                    coef = 0.5 * qm * p[P_G] * ve_new * bb
                g0 = 0.0
                g1 = 0.0
                for a in range(4):
                    g0 += QUAD_GAMMA[a] * xe[a, 0]
                    g1 += QUAD_GAMMA[a] * xe[a, 1]
                q0 = 0.0
                q1 = 0.0
                for a in range(4):
                    g = QUAD_GAMMA[a] - g0 * b[0, a] - g1 * b[1, a]
                    gam[a] = g
                    q0 += ve[a, 0] * g
                    q1 += ve[a, 1] * g
                work = 0.0
                for k in range(2):
                    qk = q0 if k == 0 else q1
                    if sec[SEC_HG_TYPE] == HG_VISCOUS:
                        resultant = coef * qk
                        work += resultant * qk * dt
                    else:
                        old = hg_force[e, 0, k]
                        hg_force[e, 0, k] += coef * qk * dt
                        resultant = hg_force[e, 0, k]
                        work += 0.5 * (old + resultant) * qk * dt
                    for a in range(4):
                        f_elem[e, a, k] -= resultant * gam[a]
                hg_energy[e] += work
