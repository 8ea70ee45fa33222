"""ALE plane force kernel (``lagrange.lagrange_forces``): two of its passes over a block of elements
written so that LLVM vectorises them (issue 17): the material state where the mesh holds one ideal or
stiffened gas (``gas_block``), and the bulk viscosity and stable step (``viscosity_block``).

The force kernel goes over each block of elements in passes through a work array (see the comment
above it). These two passes are where its divisions and square roots are; written as straight-line
loops over flat arrays (no branch: every value computed, the cases selected afterwards; numpy's error
model: a division by zero gives inf or nan, which the selects discard, instead of a Python exception)
the vector units take 8 elements' divisions and roots at once. Each is the same operations in the same
order as the scalar code it replaces (the same bits).

One gas:

``lagrange._mixture_pressure`` for one material whose EOS is ``EOS_IDEAL_GAS`` (p = (gamma - 1) rho e)
or ``EOS_STIFFENED_GAS`` (p = (gamma - 1) rho e - gamma p_inf; Harlow & Amsden 1971, the ideal gas at
p_inf = 0), ``materials.kernels.eos_state`` with r = rho / rho0 and E = rho0 e per reference volume:
p = (gamma - 1) r E - gamma p_inf, dp/dmu = (gamma - 1) E, dp/dE = (gamma - 1) r, c^2 = (dp/dmu +
p dp/dE / r^2) / rho0. The same operations in the same order as the general path (the same bits),
without its branches: every element's state is computed and the void / absent cases are selected
afterwards, and the kernel uses numpy's error model (a division by zero gives inf or nan, which the
selects then discard, instead of a Python exception), so the loop body is straight-line code and the
divisions and square roots of several elements go through the vector units together.
"""
from __future__ import annotations

import math

from numba import njit

from ..materials.ids import EOS_IDEAL_GAS, EOS_STIFFENED_GAS
from ..materials.slots import Q_SG_GAMMA, Q_SG_PINF


@njit(cache=True)
def one_gas(mat_eos, mat_q, mat_rho0):
    """(True, gamma - 1, gamma p_inf) when the mesh holds one material, an ideal or stiffened gas with
    rho0 > 0 (``gas_block`` applies); else (False, 0, 0). The ideal gas is the stiffened one at
    p_inf = 0: (gamma - 1) r E - 0.0 is (gamma - 1) r E to the bit."""
    if mat_eos.shape[0] != 1 or mat_rho0[0] <= 0.0:
        return False, 0.0, 0.0
    eos = mat_eos[0]
    if eos == EOS_IDEAL_GAS:
        return True, mat_q[0, Q_SG_GAMMA] - 1.0, 0.0
    if eos == EOS_STIFFENED_GAS:
        return True, mat_q[0, Q_SG_GAMMA] - 1.0, mat_q[0, Q_SG_GAMMA] * mat_q[0, Q_SG_PINF]
    return False, 0.0, 0.0


@njit(cache=True, error_model="numpy")
def gas_block(nb, vol_m, mass_m, ener_m, e_lag, gm1, gpinf, rho0, phi_eps, rho_void, pscale,
              pressure_cutoff, pres_m, bulk_m, st_p, st_c, st_m):
    """``lagrange._mixture_pressure`` of the nb elements of a block, one gas (``one_gas``): writes pres_m,
    bulk_m and the block's mixture pressure, sound speed and mass into st_p, st_c, st_m [0, nb).
    The per-element arrays come as the block's slices of the flat (E,) views of the (E, 1) state, indexed
    by the loop counter: with the column index of the (E, N) form LLVM did not vectorise the loop, and
    with the element number start + i (of unknown sign to numba, so wrapped around where negative) it
    stored through scatters.

    As the general path: present when V > phi_eps V and M > rho_void rho0 V; then rho = M / V, the EOS at
    r = rho / rho0 and E = rho0 (E_stored / M + e_lag), c = sqrt(c^2) (0 where c^2 <= 0; p = c = 0 where
    rho <= 0), p = max(p pscale, cut-off); pres = p, bulk = (rho c) c, p_mix = 0 + (V / V) p, c_e =
    sqrt((0 + (M c) c) / (0 + M)), all zero where absent. (The general path's sums start from 0.0: kept, as
    0.0 + x differs from x when x is -0.0.) No Gruneisen cavitation branch: a gas has none.
    """
    for i in range(nb):
        vol = vol_m[i]
        mass = mass_m[i]
        vtot = 0.0 + vol
        mtot = 0.0 + mass
        present = vol > phi_eps * vtot and mass > rho_void * rho0 * vol
        rho = mass / vol
        r = rho / rho0
        big_e = rho0 * (ener_m[i] / mass + e_lag[i])
        p = gm1 * r * big_e - gpinf
        dpdmu = gm1 * big_e
        dpde = gm1 * r
        c2 = (dpdmu + p * dpde / (r * r)) / rho0
        c = math.sqrt(c2) if c2 > 0.0 else 0.0
        if rho <= 0.0:
            p = 0.0
            c = 0.0
        p = max(p * pscale[i], pressure_cutoff)
        p_in = 0.0 + vol / vtot * p
        mc2 = 0.0 + mass * c * c
        m_in = 0.0 + mass
        pres_m[i] = p if present else 0.0
        bulk_m[i] = rho * c * c if present else 0.0
        st_p[i] = p_in if present else 0.0
        m_in = m_in if present else 0.0
        st_c[i] = math.sqrt((mc2 if present else 0.0) / m_in) if m_in > 0.0 else 0.0
        st_m[i] = mtot


@njit(cache=True, error_model="numpy")
def viscosity_block(nb, s_p, s_c, s_m, s_area, s_trace, s_vmax2, s_long2, q1, q2, qhg, q_elem, dt_elem,
                    s_s, s_rho, s_coef):
    """``lagrange.viscosity_and_step`` and the force factors of the nb elements of a block (q_elem, dt_elem:
    the block's slices, as in ``gas_block``) from their work rows (mixture pressure s_p, sound speed s_c, mass s_m, area, tr d, largest corner |v|^2, the longest
    edge's squared length).

    l = A / sqrt(longest^2) (``lagrange._quad_char_length``); rho_e = M / A; q = ``fem.geometry.bulk_viscosity`` (rho l (Q1^2 l tr d^2 - Q2 c tr d), 0 where tr d >= 0)
    into q_elem; dt_elem = ``fem.geometry.stable_dt`` with c_eff = c + |v|_max (l / (Q + sqrt(Q^2 + c_eff^2)),
    Q = Q2 c_eff + Q1^2 l |tr d| in compression, else 0; inf where c_eff <= 0 or the denominator is not
    positive); s_s = A (p + q), s_rho = rho_e, s_coef = qhg rho_e c sqrt(A) / 4 (the hourglass coefficient,
    used where qhg > 0 and rho_e > 0). Operation order as the scalar helpers'.
    """
    for i in range(nb):
        area = s_area[i]
        c = s_c[i]
        length = area / math.sqrt(s_long2[i])
        trace_d = s_trace[i]
        rho_e = s_m[i] / area
        q = rho_e * length * (q1 * q1 * length * trace_d * trace_d - q2 * c * trace_d)
        q = 0.0 if trace_d >= 0.0 else q
        q_elem[i] = q
        c_eff = c + math.sqrt(s_vmax2[i])
        qq = q2 * c_eff + q1 * q1 * length * (-trace_d) if trace_d < 0.0 else 0.0
        den = qq + math.sqrt(qq * qq + c_eff * c_eff)
        dt_elem[i] = length / den if c_eff > 0.0 and den > 0.0 else math.inf
        s_s[i] = area * (s_p[i] + q)
        s_rho[i] = rho_e
        s_coef[i] = 0.25 * qhg * rho_e * c * math.sqrt(area)
