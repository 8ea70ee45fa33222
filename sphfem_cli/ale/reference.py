"""NumPy reference versions of the ALE kernels, for tests on small inputs (slow, obvious).

Each function mirrors the numba kernel of the same name in ``ale.kernels`` and returns its
outputs instead of writing them in place.
"""
from __future__ import annotations

import numpy as np

from ..materials.kernels import eos_state
from . import kernels as K

_GAMMA = np.array([1.0, -1.0, 1.0, -1.0])


def material_state(eos, q, rho0, rho, e_spec):
    if eos < 0 or rho0 <= 0.0 or rho <= 0.0:
        return 0.0, 0.0
    r = rho / rho0
    p, dpdmu, dpde = eos_state(int(eos), q, r, rho0 * e_spec)
    c2 = (dpdmu + p * dpde / (r * r)) / rho0
    return p, float(np.sqrt(max(c2, 0.0)))


def lagrange_forces(x, v, conn, vol_m, mass_m, ener_m, mat_eos, mat_q, mat_rho0, q1, q2, qhg, phi_eps,
                    pressure_cutoff=-np.inf, e_lag=None):
    """(f_elem, pres_m, bulk_m, q_elem, dt_elem), vectorised over elements except for the EOS; the EOS at the
    specific energy ener_m / mass_m + e_lag (default 0)."""
    if e_lag is None:
        e_lag = np.zeros_like(ener_m)
    xe = x[conn]  # (E, 4, 2)
    ve = v[conn]
    nxt = np.roll(np.arange(4), -1)
    prv = np.roll(np.arange(4), 1)
    area = 0.5 * ((xe[:, 2, 0] - xe[:, 0, 0]) * (xe[:, 3, 1] - xe[:, 1, 1])
                  + (xe[:, 1, 0] - xe[:, 3, 0]) * (xe[:, 2, 1] - xe[:, 0, 1]))
    b = np.empty((len(conn), 2, 4))
    b[:, 0, :] = (xe[:, nxt, 1] - xe[:, prv, 1]) / (2 * area[:, None])
    b[:, 1, :] = (xe[:, prv, 0] - xe[:, nxt, 0]) / (2 * area[:, None])
    vtot = vol_m.sum(axis=1)
    mtot = mass_m.sum(axis=1)
    pres = np.zeros_like(vol_m)
    bulk = np.zeros_like(vol_m)
    snd = np.zeros_like(vol_m)
    for e in range(len(conn)):
        for m in range(vol_m.shape[1]):
            if vol_m[e, m] > phi_eps * vtot[e] and mass_m[e, m] > K.RHO_VOID * mat_rho0[m] * vol_m[e, m]:
                rho = mass_m[e, m] / vol_m[e, m]
                p, c = material_state(mat_eos[m], mat_q[m], mat_rho0[m], rho, ener_m[e, m] / mass_m[e, m] + e_lag[e, m])
                pres[e, m], bulk[e, m], snd[e, m] = max(p, pressure_cutoff), rho * c * c, c
    p_mix = (vol_m / vtot[:, None] * pres).sum(axis=1)
    counted = snd > 0
    m_in = np.where(counted, mass_m, 0.0).sum(axis=1)
    c2 = np.where(counted, mass_m * snd ** 2, 0.0).sum(axis=1)
    c_max = np.sqrt(np.divide(c2, m_in, out=np.zeros_like(c2), where=m_in > 0))  # mixture (mass-weighted c^2)
    rho_e = mtot / area
    trace_d = np.einsum("eak,eka->e", ve, b)
    edges = np.linalg.norm(xe[:, nxt] - xe, axis=2).max(axis=1)
    length = area / edges
    q = np.where(trace_d < 0, rho_e * length * (q1 * q1 * length * trace_d ** 2 - q2 * c_max * trace_d), 0.0)
    c_eff = c_max + np.sqrt((ve ** 2).sum(axis=2).max(axis=1))
    qq = np.where(trace_d < 0, q2 * c_eff + q1 * q1 * length * np.abs(trace_d), 0.0)
    with np.errstate(divide="ignore"):
        dt = np.where(c_eff > 0, length / (qq + np.sqrt(qq * qq + c_eff * c_eff)), np.inf)
    f = (area * (p_mix + q))[:, None, None] * np.transpose(b, (0, 2, 1))
    gx = np.einsum("a,eak->ek", _GAMMA, xe)
    gam = _GAMMA[None, :] - np.einsum("ek,eka->ea", gx, b)
    hq = np.einsum("ea,eak->ek", gam, ve)
    coef = np.where(rho_e > 0, 0.25 * qhg * rho_e * c_max * np.sqrt(area), 0.0) if qhg > 0 else np.zeros(len(conn))
    f -= coef[:, None, None] * gam[:, :, None] * hq[:, None, :]
    return f, pres, bulk, q, dt


def swept_volume(xl0, xl1, xn0, xn1):
    """Signed area swept by face (0, 1) from x_lag to x_new, positive when its owner grows."""
    return K.quad_area.py_func(xl0[0], xl0[1], xn0[0], xn0[1], xn1[0], xn1[1], xl1[0], xl1[1])


def face_fluxes_donor(topo, face_open, x_lag, x_new, vol_m, mass_m, ener_m):
    """Donor-cell fluxes (order 1, donor fractions) through every face: (fvol, fmass, fener)."""
    nf = len(topo["face_nodes"])
    n_mat = vol_m.shape[1]
    fvol = np.zeros((nf, n_mat))
    fmass = np.zeros((nf, n_mat))
    fener = np.zeros((nf, n_mat))
    for f in range(nf):
        n0, n1 = topo["face_nodes"][f]
        el, er = topo["face_elem"][f]
        if er < 0 and not face_open[f]:
            continue
        dv = swept_volume(x_lag[n0], x_lag[n1], x_new[n0], x_new[n1])
        donor, sgn = (er, 1.0) if dv > 0 else (el, -1.0)
        if donor < 0:
            donor = el
        frac = vol_m[donor] / vol_m[donor].sum()
        dvol = abs(dv) * frac
        rho = np.divide(mass_m[donor], vol_m[donor], out=np.zeros(n_mat), where=vol_m[donor] > 0)
        e = np.divide(ener_m[donor], mass_m[donor], out=np.zeros(n_mat), where=mass_m[donor] > 0)
        fvol[f] = sgn * dvol
        fmass[f] = sgn * rho * dvol
        fener[f] = sgn * e * rho * dvol
    return fvol, fmass, fener


def nodal_mass(mass_m, conn, n_nodes):
    out = np.zeros(n_nodes)
    np.add.at(out, conn.ravel(), np.repeat(0.25 * mass_m.sum(axis=1), 4))
    return out
