"""Multi-material ALE (operator split) on quad4 and hex8 meshes: numba kernels.

State (per element e, material m, extensive so that conservation is a matter of bookkeeping):
``vol_m[e, m]`` material volume, ``mass_m[e, m]`` material mass, ``ener_m[e, m]`` material
internal energy (energy, not per unit mass). Volume fraction phi_m = vol_m / sum_k vol_k,
density rho_m = mass_m / vol_m, specific internal energy e_m = ener_m / mass_m. Nodes carry the
velocity v (half-step, central difference) and the lumped mass m_I = sum_e M_e / 4.

One step (paper section 2, eqs. 2.5-2.8; Benson 1992):

1. ``lagrange_forces``: per element, each material's pressure from its EOS at its own density and
   energy; mixture stress sigma = -sum_m phi_m p_m (volume-weighted, the paper's mixture theory);
   bulk viscosity q (von Neumann-Richtmyer, linear + quadratic) and Flanagan-Belytschko viscous
   hourglass forces; element forces f_eI = V (p + q) b_I - hourglass; stable dt.
2. ``nodal_update``: gather of the element forces, v^{n+1/2} = v^{n-1/2} + dt f / m (eq. 2.7),
   velocity boundary conditions with the reaction impulse recorded.
3. ``lagrange_energy``: the work of the element forces over the step,
   W_e = -dt sum_I f_eI . (v_I^{n-1/2} + v_I^{n+1/2}) / 2 (compatible form: kinetic plus internal
   energy is conserved to round-off), the new Lagrangian volume at x + dt v^{n+1/2}, and the
   mixed-cell closure: the volume change split between materials (equal strain, or pressure
   relaxation), each material receiving its own -p_m dV_m plus its mass share of the remainder
   of W_e (viscous and hourglass work).
4. Remap (``face_fluxes``, ``apply_face_fluxes``, ``dual_fluxes``, ``apply_dual_fluxes``,
   ``finish_remap``): directional sweeps (order alternating each step) through the faces of one
   logical direction; the face flux of volume is the signed area swept by the face from its
   Lagrangian to its remapped position; material volumes split by a directional SLIC
   (Noh & Woodward 1976) or by donor fractions; mass and energy by donor-cell or van Leer (1977)
   MUSCL values; nodal momentum remapped on the dual mesh (half-index shift, Benson 1992 sec. 5.4)
   with the same mass fluxes, and the kinetic energy lost by the remap returned to the elements
   (DeBar's fix) so that total energy is conserved.

3D (hex8): the same steps, with ``*_3d`` kernels where the geometry differs (mean gradient and
hourglass modes of the hex8, exact swept volume of a quad face, three sweep directions); the
mixture state, closure, face flux of a given swept volume (``_mixture_pressure``,
``_closure_energy``, ``_face_flux``) and the element-face, dual-mesh and nodal-mass kernels are
shared (their loops take the corner count and dimension from the arrays).

Every parallel loop is a gather: faces write face arrays, elements their own rows, nodes their
own entries. Equations and references: docs/theory/ale.md.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ..fem.geometry import (HEX_GAMMA, QUAD_GAMMA, bulk_viscosity, hex8_char_length, hex8_gradient, hex8_volume,
                            quad4_char_length, quad4_gradient, stable_dt)
from ..materials.kernels import EOS_GRUNEISEN, _eos_state

# boundary condition codes per node
BC_FREE = 0
BC_SLIP = 1
BC_FIXED = 2
BC_VELOCITY = 3  # prescribed velocity (inflow): bc_normal holds the velocity itself
BC_LINE = 4  # 3D: a node on two slip planes moves along their intersection, bc_normal its unit direction

# interface (material volume flux) modes
IFACE_DONOR = 0
IFACE_SLIC = 1

# closures
CLOSURE_EQUAL_STRAIN = 0
CLOSURE_RELAX = 1

# SLIC orders the materials only where their fraction gradient across the donor is at least this
SLIC_JUMP = 0.1

# a material whose density is below RHO_VOID times its reference density (volume the remap left
# without mass) carries no pressure and no sound speed: it is void
RHO_VOID = 1e-9

# with a pressure cut-off (cavitation), a Gruneisen liquid below RHO_CAVITATED times its reference
# density is cavitated: pressure = the cut-off, sound speed its reference one. Below it the EOS's
# thermal term (Gamma rho = gamma0 rho0, fixed) with the cut-off's work p_c dV in the energy
# gave fog and traces MPa of pressure and sound speeds of 1e5-1.5e6 m/s (c^2 ~ gamma0 rho0 p / rho^2),
# collapsing the step (decks/underwater_explosion_ale.yaml); with normal energies
# (E < (K0/2 + p_c)/gamma0 per reference volume) the EOS gives the cut-off there anyway.
RHO_CAVITATED = 0.5

@njit(cache=True)
def material_state(eos, q, rho0, rho, e_spec):
    """(p, c) of one material at density rho and specific internal energy e_spec; (0, 0) for void."""
    if eos < 0 or rho0 <= 0.0 or rho <= 0.0:
        return 0.0, 0.0
    r = rho / rho0
    p, dpdmu, dpde = _eos_state(eos, q, r, rho0 * e_spec)
    c2 = (dpdmu + p * dpde / (r * r)) / rho0
    return p, math.sqrt(c2) if c2 > 0.0 else 0.0


@njit(cache=True)
def quad_area(x0, y0, x1, y1, x2, y2, x3, y3):
    """Signed area of the quadrilateral (0, 1, 2, 3): half the cross product of its diagonals."""
    return 0.5 * ((x2 - x0) * (y3 - y1) - (y2 - y0) * (x3 - x1))


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
def _mixture_pressure(e, vol_m, mass_m, ener_m, mat_eos, mat_q, mat_rho0, phi_eps, pscale, p_cut, pres_m, bulk_m):
    """Material pressures and bulk moduli of element e, and its mixture state (shared by 2D and 3D).

    Each present material's pressure p_m from its EOS at its own density and specific energy (times
    pscale, at least p_cut; a cavitated Gruneisen liquid at the cut-off); writes pres_m[e], bulk_m[e]
    (rho c^2). Returns (p_mix, c_e, M): the volume-weighted pressure sum_m phi_m p_m (the paper's
    mixture theory), the equal-strain mixture sound speed c_e^2 = sum_m M_m c_m^2 / M (see
    ``lagrange_forces``) and the element's mass.
    """
    n_mat = vol_m.shape[1]
    vtot = 0.0
    mtot = 0.0
    for m in range(n_mat):
        vtot += vol_m[e, m]
        mtot += mass_m[e, m]
    p_mix = 0.0
    mc2 = 0.0
    m_in = 0.0
    for m in range(n_mat):
        pres_m[e, m] = 0.0
        bulk_m[e, m] = 0.0
        if vol_m[e, m] > phi_eps * vtot and mass_m[e, m] > RHO_VOID * mat_rho0[m] * vol_m[e, m]:
            rho = mass_m[e, m] / vol_m[e, m]
            p, c = material_state(mat_eos[m], mat_q[m], mat_rho0[m], rho, ener_m[e, m] / mass_m[e, m])
            p = max(p * pscale[e, m], p_cut)
            if p_cut > -math.inf and mat_eos[m] == EOS_GRUNEISEN and rho < RHO_CAVITATED * mat_rho0[m]:
                p = p_cut
                c = material_state(mat_eos[m], mat_q[m], mat_rho0[m], mat_rho0[m], 0.0)[1]
            pres_m[e, m] = p
            bulk_m[e, m] = rho * c * c
            p_mix += vol_m[e, m] / vtot * p
            mc2 += mass_m[e, m] * c * c
            m_in += mass_m[e, m]
    c_max = math.sqrt(mc2 / m_in) if m_in > 0.0 else 0.0
    return p_mix, c_max, mtot


# ------------------------------------------------------------------------------ Lagrangian phase


@njit(parallel=True, cache=True)
def lagrange_forces(x, v, conn, vol_m, mass_m, ener_m, mat_eos, mat_q, mat_rho0, q1, q2, qhg,
                    phi_eps, pscale, p_cut, f_elem, pres_m, bulk_m, q_elem, dt_elem):
    """Element forces at x^n with v^{n-1/2} (see module docstring, step 1).

    pscale (E, N) multiplies each material's EOS pressure (1 except for a high explosive, where it
    is the programmed-burn fraction, ``materials.burn``); sound speed and bulk modulus are unscaled.
    p_cut: pressure cut-off, no material pressure below it (cavitation; -inf for none). A material
    below RHO_VOID of its reference density is void (no pressure, no sound speed).

    The element's sound speed (stable step, bulk and hourglass viscosity) is that of the
    equal-strain mixture, c_e^2 = sum_m phi_m K_m / rho_e = sum_m M_m c_m^2 / M: the element's
    stiffness over its mass. A trace of a material contributes in proportion to its mass, so a
    1 % trace of detonation products stretched to a tiny density with a huge sound speed does not
    set the step (for one material c_e = c).

    Written: f_elem (E, 4, 2) force on each element node, pres_m (E, N) material pressures,
    bulk_m (E, N) material bulk moduli rho c^2, q_elem (E,) bulk viscosity, dt_elem (E,) stable step.
    """
    n_elem = conn.shape[0]
    n_chunks = min(n_elem, 512)
    for chunk in prange(n_chunks):
        start = chunk * n_elem // n_chunks
        stop = (chunk + 1) * n_elem // n_chunks
        xe = np.empty((4, 2))
        ve = np.empty((4, 2))
        b = np.empty((2, 4))
        for e in range(start, stop):
            vmax2 = 0.0
            for a in range(4):
                n = conn[e, a]
                xe[a, 0] = x[n, 0]
                xe[a, 1] = x[n, 1]
                ve[a, 0] = v[n, 0]
                ve[a, 1] = v[n, 1]
                vmax2 = max(vmax2, v[n, 0] * v[n, 0] + v[n, 1] * v[n, 1])
            area = quad4_gradient(xe, b)
            p_mix, c_max, mtot = _mixture_pressure(e, vol_m, mass_m, ener_m, mat_eos, mat_q, mat_rho0, phi_eps,
                                                   pscale, p_cut, pres_m, bulk_m)
            rho_e = mtot / area
            trace_d = 0.0
            for a in range(4):
                trace_d += ve[a, 0] * b[0, a] + ve[a, 1] * b[1, a]
            length = quad4_char_length(xe, area)
            q = bulk_viscosity(rho_e, length, c_max, trace_d, q1, q2)
            q_elem[e] = q
            c_eff = c_max + math.sqrt(vmax2)
            dt_elem[e] = stable_dt(length, c_eff, trace_d, q1, q2) if c_eff > 0.0 else np.inf
            s = area * (p_mix + q)
            for a in range(4):
                f_elem[e, a, 0] = s * b[0, a]
                f_elem[e, a, 1] = s * b[1, a]
            if qhg > 0.0 and rho_e > 0.0:
                # gamma_a = Gamma_a - (Gamma . x) b_a (Flanagan & Belytschko 1981), viscous form
                gx0 = 0.0
                gx1 = 0.0
                for a in range(4):
                    gx0 += QUAD_GAMMA[a] * xe[a, 0]
                    gx1 += QUAD_GAMMA[a] * xe[a, 1]
                coef = 0.25 * qhg * rho_e * c_max * math.sqrt(area)
                hq0 = 0.0
                hq1 = 0.0
                for a in range(4):
                    g = QUAD_GAMMA[a] - gx0 * b[0, a] - gx1 * b[1, a]
                    hq0 += g * ve[a, 0]
                    hq1 += g * ve[a, 1]
                for a in range(4):
                    g = QUAD_GAMMA[a] - gx0 * b[0, a] - gx1 * b[1, a]
                    f_elem[e, a, 0] -= coef * hq0 * g
                    f_elem[e, a, 1] -= coef * hq1 * g


@njit(parallel=True, cache=True)
def nodal_update(f_elem, node_elem_ptr, node_elem_idx, f_ext, mass, m_floor, v, bc_type, bc_normal, dt, impulse):
    """v^{n+1/2} = v^{n-1/2} + dt (f_int + f_ext) / m (eq. 2.7), then the velocity conditions.

    bc_type per node: BC_FREE, BC_SLIP (normal component along bc_normal removed), BC_FIXED,
    BC_VELOCITY (v = bc_normal, a prescribed velocity).
    impulse (N, 2) receives the reaction impulse m (v_constrained - v_free) of this step.
    Nodes with a mass at or below m_floor (N,) (numerical fog, or none) are held at zero velocity,
    their momentum booked in impulse like a fixed node's; a prescribed velocity (BC_VELOCITY)
    holds whatever the mass.
    """
    n_nodes = v.shape[0]
    for n in prange(n_nodes):
        f0 = f_ext[n, 0]
        f1 = f_ext[n, 1]
        for r in range(node_elem_ptr[n], node_elem_ptr[n + 1]):
            ea = node_elem_idx[r]
            e = ea // 4
            a = ea - 4 * e
            f0 += f_elem[e, a, 0]
            f1 += f_elem[e, a, 1]
        m = mass[n]
        if m > 0.0:
            w0 = v[n, 0] + dt * f0 / m
            w1 = v[n, 1] + dt * f1 / m
        else:
            w0 = 0.0
            w1 = 0.0
        if m > m_floor[n] or bc_type[n] == BC_VELOCITY:
            u0, u1 = _apply_bc(bc_type[n], bc_normal[n, 0], bc_normal[n, 1], w0, w1)
        else:
            u0, u1 = 0.0, 0.0
        impulse[n, 0] = m * (u0 - w0)
        impulse[n, 1] = m * (u1 - w1)
        v[n, 0] = u0
        v[n, 1] = u1


@njit(cache=True)
def _apply_bc(kind, nx, ny, w0, w1):
    if kind == BC_FIXED:
        return 0.0, 0.0
    if kind == BC_SLIP:
        vn = w0 * nx + w1 * ny
        return w0 - vn * nx, w1 - vn * ny
    if kind == BC_VELOCITY:
        return nx, ny
    return w0, w1


@njit(cache=True, inline="always")
def _closure_energy(e, w, v_lag, vol_m, mass_m, ener_m, pres_m, bulk_m, closure, alpha, beta, phi_eps, dvm, dev):
    """Mixed-element closure of element e over the Lagrangian step (shared by 2D and 3D).

    The volume change dV = v_lag - sum_m V_m split between the materials (``lagrange_energy``:
    equal strain, or pressure relaxation limited by beta), each material's energy changed by its
    own -p_m dV_m plus its mass share of the rest of the element's work w (viscous and hourglass
    work). dvm, dev: scratch (N,).
    """
    n_mat = vol_m.shape[1]
    vtot = 0.0
    for m in range(n_mat):
        vtot += vol_m[e, m]
    dv = v_lag - vtot
    n_present = 0
    s_comp = 0.0
    s_p = 0.0
    kmax = 0.0
    for m in range(n_mat):
        dvm[m] = dv * vol_m[e, m] / vtot
        dev[m] = 0.0
        if vol_m[e, m] > phi_eps * vtot:
            n_present += 1
            kmax = max(kmax, bulk_m[e, m])
    if closure == CLOSURE_RELAX and n_present > 1 and kmax > 0.0:
        kmin = 1e-9 * kmax  # void (or a material without stiffness) takes the volume change
        for m in range(n_mat):
            if vol_m[e, m] > phi_eps * vtot:
                k = max(bulk_m[e, m], kmin)
                s_comp += vol_m[e, m] / k
                s_p += vol_m[e, m] * pres_m[e, m] / k
        pbar = s_p / s_comp
        scale = 1.0
        for m in range(n_mat):
            if vol_m[e, m] > phi_eps * vtot:
                k = max(bulk_m[e, m], kmin)
                target = dv * vol_m[e, m] / k / s_comp + alpha * vol_m[e, m] * (pres_m[e, m] - pbar) / k
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
        if mass_m[e, m] > 0.0:
            ener_m[e, m] += -pres_m[e, m] * dvm[m] + rest * mass_m[e, m] / mass_e
        vol_m[e, m] += dvm[m]


@njit(parallel=True, cache=True)
def lagrange_energy(x, v_old, v_new, dt, conn, f_elem, vol_m, mass_m, ener_m, pres_m, bulk_m, q_elem,
                    closure, alpha, beta, phi_eps, work_elem):
    """Internal energy and material volumes over the Lagrangian step (module docstring, step 3).

    work_elem (E,) receives W_e, the internal-energy increment of the element. Material volumes
    follow the Lagrangian volume at x + dt v_new. Closure CLOSURE_EQUAL_STRAIN: dV_m = phi_m dV;
    CLOSURE_RELAX: dV_m = dV (V_m/K_m) / S + alpha V_m (p_m - pbar) / K_m, S = sum V_k/K_k,
    pbar = sum (V_k p_k / K_k) / S (equal pressure increments plus a relaxation towards a common
    pressure), its departure from equal strain scaled down so that no material loses more than a
    fraction beta of its volume in one step.
    """
    n_elem = conn.shape[0]
    n_mat = vol_m.shape[1]
    n_chunks = min(n_elem, 512)
    for chunk in prange(n_chunks):
        start = chunk * n_elem // n_chunks
        stop = (chunk + 1) * n_elem // n_chunks
        dvm = np.empty(n_mat)
        dev = np.empty(n_mat)
        px = np.empty(4)
        py = np.empty(4)
        for e in range(start, stop):
            w = 0.0
            for a in range(4):
                n = conn[e, a]
                w -= f_elem[e, a, 0] * 0.5 * (v_old[n, 0] + v_new[n, 0]) + f_elem[e, a, 1] * 0.5 * (v_old[n, 1] + v_new[n, 1])
                px[a] = x[n, 0] + dt * v_new[n, 0]
                py[a] = x[n, 1] + dt * v_new[n, 1]
            w *= dt
            work_elem[e] = w
            v_lag = quad_area(px[0], py[0], px[1], py[1], px[2], py[2], px[3], py[3])
            _closure_energy(e, w, v_lag, vol_m, mass_m, ener_m, pres_m, bulk_m, closure, alpha, beta, phi_eps,
                            dvm, dev)


# ------------------------------------------------------------------------------ remap


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
    if iface == IFACE_SLIC:
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
                vol_m, mass_m, ener_m, order, iface, phi_eps, fvol, fmass, fener):
    """Fluxes through the listed faces, positive into the face's first element (its owner).

    The volume through face (n0, n1) (owner orientation) is the signed area swept by it from the
    Lagrangian position x_lag to the remapped position x_new: quad (l0, w0, w1, l1); positive when
    the owner gains volume, the other element (or the outside, on open faces) being the donor.
    Material volumes: IFACE_DONOR phi_m of the donor; IFACE_SLIC materials leave the donor in the
    order of their fraction gradient across it (acceptor minus upwind), the highest first, each
    at most its volume in the donor. Mass and energy: donor-cell (order 1) or van Leer (order 2)
    values of rho_m and e_m. Boundary faces carry flux only when open (transmitting): the outside
    state is a copy of the inside element. Writes fvol, fmass, fener rows of the listed faces.
    """
    nf = faces.shape[0]
    n_mat = vol_m.shape[1]
    n_chunks = min(nf, 512)
    for chunk in prange(n_chunks):
        start = chunk * nf // n_chunks
        stop = (chunk + 1) * nf // n_chunks
        dvm = np.empty(n_mat)
        g = np.empty(n_mat)
        used = np.empty(n_mat, dtype=np.bool_)
        for i in range(start, stop):
            f = faces[i]
            n0 = face_nodes[f, 0]
            n1 = face_nodes[f, 1]
            for m in range(n_mat):
                fvol[f, m] = 0.0
                fmass[f, m] = 0.0
                fener[f, m] = 0.0
            el = face_elem[f, 0]
            er = face_elem[f, 1]
            if er < 0 and not face_open[f]:
                continue
            dv = quad_area(x_lag[n0, 0], x_lag[n0, 1], x_new[n0, 0], x_new[n0, 1],
                           x_new[n1, 0], x_new[n1, 1], x_lag[n1, 0], x_lag[n1, 1])
            if dv == 0.0:
                continue
            if dv > 0.0:
                donor = er
                acc = el
                sgn = 1.0
                far = elem_nbr[er, (face_local[f, 1] + 2) % 4] if er >= 0 else -1
            else:
                donor = el
                acc = er
                sgn = -1.0
                far = elem_nbr[el, (face_local[f, 0] + 2) % 4]
            _face_flux(f, abs(dv), donor, acc, far, sgn, vol_m, mass_m, ener_m, order, iface, phi_eps,
                       fvol, fmass, fener, dvm, g, used)


@njit(parallel=True, cache=True)
def apply_face_fluxes(ka, kb, elem_face, elem_sign, fvol, fmass, fener, vol_m, mass_m, ener_m):
    """Each element adds the fluxes of its two faces ka, kb (local numbers) of this sweep direction (a gather)."""
    n_elem = elem_face.shape[0]
    n_mat = vol_m.shape[1]
    for e in prange(n_elem):
        for k in (ka, kb):
            f = elem_face[e, k]
            s = elem_sign[e, k]
            for m in range(n_mat):
                vol_m[e, m] += s * fvol[f, m]
                mass_m[e, m] += s * fmass[f, m]
                ener_m[e, m] += s * fener[f, m]


@njit(cache=True, inline="always")
def _dual_element(e, ka, kb, direction, elem_face, elem_sign, elem_nbr, face_open, any_open, fmass, node_line,
                  mnode, pnode, order, gm, gp, gk, bm, bp, bk, dim, n_edges):
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
    open_a = elem_nbr[e, ka] < 0 and face_open[fa]
    open_b = elem_nbr[e, kb] < 0 and face_open[fb]
    for h in range(n_edges):
        src = node_line[e, direction, h, 1]
        dst = node_line[e, direction, h, 2]
        gm[e, h] = gh
        if gh >= 0.0:
            donor = src
            acc = dst
            up = node_line[e, direction, h, 0]
        else:
            donor = dst
            acc = src
            up = node_line[e, direction, h, 3]
        md = mnode[donor]
        ke = 0.0
        for k in range(dim):
            vd = pnode[donor, k] / md if md > 0.0 else 0.0
            vf = vd
            if order == 2 and up >= 0 and md > 0.0 and mnode[acc] > 0.0 and mnode[up] > 0.0:
                courant = min(1.0, n_edges * abs(gh) / md)
                vf = van_leer(vd, pnode[acc, k] / mnode[acc], pnode[up, k] / mnode[up], courant)
            gp[e, h, k] = gh * vf
            ke += vf * vf
        gk[e, h] = 0.5 * gh * ke
        if any_open:
            for side in range(2):
                bm[e, h, side] = 0.0
                for k in range(dim):
                    bp[e, h, side, k] = 0.0
                bk[e, h, side] = 0.0
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
                mn = mnode[n]
                bm[e, h, side] = flux
                u2 = 0.0
                for k in range(dim):
                    u = pnode[n, k] / mn if mn > 0.0 else 0.0
                    bp[e, h, side, k] = flux * u
                    u2 += u * u
                bk[e, h, side] = 0.5 * flux * u2


@njit(parallel=True, cache=True)
def dual_fluxes(ka, kb, direction, conn, elem_face, elem_sign, elem_nbr, face_open, any_open, fmass, node_line,
                mnode, pnode, order, gm, gp, gk, bm, bp, bk):
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
    face's H nodes also receives 1/H of the face's mass flux with its own velocity (bm, bp, bk:
    [e, h, 0] into src through side a, [e, h, 1] into dst through side b); without open faces
    (any_open False) bm, bp, bk are left as they are (zero).
    """
    n_elem = conn.shape[0]
    three = pnode.shape[1] == 3
    for e in prange(n_elem):
        if three:
            _dual_element(e, ka, kb, direction, elem_face, elem_sign, elem_nbr, face_open, any_open, fmass,
                          node_line, mnode, pnode, order, gm, gp, gk, bm, bp, bk, 3, 4)
        else:
            _dual_element(e, ka, kb, direction, elem_face, elem_sign, elem_nbr, face_open, any_open, fmass,
                          node_line, mnode, pnode, order, gm, gp, gk, bm, bp, bk, 2, 2)


@njit(cache=True, inline="always")
def _dual_node(n, corner_edge, corner_dst, node_elem_ptr, node_elem_idx, any_open, gm, gp, gk, bm, bp, bk,
               mnode, pnode, knode, dim, npe):
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
        s = 1.0 if side == 1 else -1.0
        dm += s * gm[e, h]
        dp0 += s * gp[e, h, 0]
        dp1 += s * gp[e, h, 1]
        if dim == 3:
            dp2 += s * gp[e, h, 2]
        dk += s * gk[e, h]
        if any_open:
            dm += bm[e, h, side]
            dp0 += bp[e, h, side, 0]
            dp1 += bp[e, h, side, 1]
            if dim == 3:
                dp2 += bp[e, h, side, 2]
            dk += bk[e, h, side]
    mnode[n] += dm
    pnode[n, 0] += dp0
    pnode[n, 1] += dp1
    if dim == 3:
        pnode[n, 2] += dp2
    knode[n] += dk


@njit(parallel=True, cache=True)
def apply_dual_fluxes(corner_edge, corner_dst, node_elem_ptr, node_elem_idx, any_open, gm, gp, gk, bm, bp, bk,
                      mnode, pnode, knode):
    """Each node adds the dual fluxes of its element corners (a gather); open-face terms if any_open.

    corner_edge[a], corner_dst[a]: the edge along this sweep that corner a of an element lies on,
    and 1 when it is the edge's dst end (on the side-b face).
    """
    n_nodes = mnode.shape[0]
    three = pnode.shape[1] == 3
    for n in prange(n_nodes):
        if three:
            _dual_node(n, corner_edge, corner_dst, node_elem_ptr, node_elem_idx, any_open, gm, gp, gk, bm, bp, bk,
                       mnode, pnode, knode, 3, 8)
        else:
            _dual_node(n, corner_edge, corner_dst, node_elem_ptr, node_elem_idx, any_open, gm, gp, gk, bm, bp, bk,
                       mnode, pnode, knode, 2, 4)


@njit(parallel=True, cache=True)
def finish_remap_nodes(mnode, pnode, knode, m_floor, bc_type, bc_normal, v, impulse, dissip):
    """Velocity from the remapped momentum, velocity conditions, kinetic energy lost (DeBar).

    v = p / m; the velocity conditions (reaction impulse into ``impulse``); dissip[n] = the
    kinetic energy carried into the node minus 1/2 m |v|^2 afterwards. A node whose remapped mass
    is at or below m_floor[n] gets v = 0 (its momentum p into ``impulse``, its kinetic energy into
    dissip): p and m come from different flux stencils, so p / m of a near-empty node is noise
    (a fog node of 2e-58 kg was measured at 8.6e6 m/s).
    """
    n_nodes = mnode.shape[0]
    for n in prange(n_nodes):
        m = mnode[n]
        if m > 0.0:
            w0 = pnode[n, 0] / m
            w1 = pnode[n, 1] / m
        else:
            w0 = 0.0
            w1 = 0.0
        if m > m_floor[n] or bc_type[n] == BC_VELOCITY:
            u0, u1 = _apply_bc(bc_type[n], bc_normal[n, 0], bc_normal[n, 1], w0, w1)
        else:
            u0, u1 = 0.0, 0.0
        impulse[n, 0] = -pnode[n, 0] if m <= 0.0 else m * (u0 - w0)
        impulse[n, 1] = -pnode[n, 1] if m <= 0.0 else m * (u1 - w1)
        v[n, 0] = u0
        v[n, 1] = u1
        dissip[n] = knode[n] - 0.5 * m * (u0 * u0 + u1 * u1) if m > 0.0 else knode[n]


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


# ------------------------------------------------------------------------------ 3D (hex8)
# (local faces and edges of a hex8: ale.topology)


@njit(cache=True)
def swept_volume_3d(face_nodes, f, x_lag, x_new, p):
    """Signed volume swept by the quad face f from x_lag to x_new: the trilinear hexahedron whose
    bottom is the face at x_lag and top the face at x_new (face_nodes[f] ordered with the normal
    out of the owner element), positive when the face moves out of the owner, which then gains
    that volume from its neighbour. The six swept volumes of an element sum exactly to its new
    minus its Lagrangian volume (each lateral bilinear side is shared by two swept hexahedra with
    opposite orientations). p: scratch (8, 3)."""
    r = face_nodes[f, 0]
    for a in range(4):
        n = face_nodes[f, a]
        for k in range(3):
            p[a, k] = x_lag[n, k] - x_lag[r, k]
            p[a + 4, k] = x_new[n, k] - x_lag[r, k]
    return hex8_volume(p)


@njit(parallel=True, cache=True)
def swept_volumes_3d(faces, face_nodes, x_lag, x_new, out):
    """out[i] = swept_volume_3d of faces[i] (used for the inflow faces)."""
    for i in prange(faces.shape[0]):
        p = np.empty((8, 3))
        out[i] = swept_volume_3d(face_nodes, faces[i], x_lag, x_new, p)


@njit(parallel=True, cache=True)
def element_volumes_3d(x, conn, out):
    """Exact trilinear volume of every hex8 (``fem.geometry.hex8_volume``), (E,)."""
    n_elem = conn.shape[0]
    n_chunks = min(n_elem, 512)
    for chunk in prange(n_chunks):
        p = np.empty((8, 3))
        for e in range(chunk * n_elem // n_chunks, (chunk + 1) * n_elem // n_chunks):
            r = conn[e, 0]
            for a in range(8):
                n = conn[e, a]
                for k in range(3):
                    p[a, k] = x[n, k] - x[r, k]
            out[e] = hex8_volume(p)


@njit(parallel=True, cache=True)
def lagrange_forces_3d(x, v, conn, vol_m, mass_m, ener_m, mat_eos, mat_q, mat_rho0, q1, q2, qhg,
                       phi_eps, pscale, p_cut, f_elem, pres_m, bulk_m, q_elem, dt_elem):
    """``lagrange_forces`` on hex8: element forces at x^n with v^{n-1/2}.

    Mean-gradient (Flanagan & Belytschko 1981) b = (1/V) dV/dx_I (fem.geometry.hex8_gradient),
    f_eI = V (p_mix + q) b_I with the same mixture pressure (``_mixture_pressure``), bulk viscosity
    and stable step (length V / largest face area, fem.geometry.hex8_char_length); viscous
    hourglass on the four hex8 modes gamma_j = Gamma_j - (Gamma_j . x) b, force
    -c_hg (gamma_j . v) gamma_j with c_hg = qhg rho c V^(2/3) / 4 (the FEM solid's viscous form).
    Written: f_elem (E, 8, 3), pres_m, bulk_m, q_elem, dt_elem as in 2D.
    """
    n_elem = conn.shape[0]
    n_chunks = min(n_elem, 512)
    for chunk in prange(n_chunks):
        start = chunk * n_elem // n_chunks
        stop = (chunk + 1) * n_elem // n_chunks
        xe = np.empty((8, 3))
        ve = np.empty((8, 3))
        b = np.empty((3, 8))
        gam = np.empty(8)
        for e in range(start, stop):
            vmax2 = 0.0
            for a in range(8):
                n = conn[e, a]
                for k in range(3):
                    xe[a, k] = x[n, k]
                    ve[a, k] = v[n, k]
                vmax2 = max(vmax2, v[n, 0] * v[n, 0] + v[n, 1] * v[n, 1] + v[n, 2] * v[n, 2])
            vol = hex8_gradient(xe, b)
            p_mix, c_max, mtot = _mixture_pressure(e, vol_m, mass_m, ener_m, mat_eos, mat_q, mat_rho0, phi_eps,
                                                   pscale, p_cut, pres_m, bulk_m)
            rho_e = mtot / vol
            trace_d = 0.0
            for a in range(8):
                trace_d += ve[a, 0] * b[0, a] + ve[a, 1] * b[1, a] + ve[a, 2] * b[2, a]
            length = hex8_char_length(xe, vol)
            q = bulk_viscosity(rho_e, length, c_max, trace_d, q1, q2)
            q_elem[e] = q
            c_eff = c_max + math.sqrt(vmax2)
            dt_elem[e] = stable_dt(length, c_eff, trace_d, q1, q2) if c_eff > 0.0 else np.inf
            s = vol * (p_mix + q)
            for a in range(8):
                for k in range(3):
                    f_elem[e, a, k] = s * b[k, a]
            if qhg > 0.0 and rho_e > 0.0:
                coef = 0.25 * qhg * rho_e * c_max * vol ** (2.0 / 3.0)
                for mode in range(4):
                    gx0 = 0.0
                    gx1 = 0.0
                    gx2 = 0.0
                    for a in range(8):
                        gx0 += HEX_GAMMA[mode, a] * xe[a, 0]
                        gx1 += HEX_GAMMA[mode, a] * xe[a, 1]
                        gx2 += HEX_GAMMA[mode, a] * xe[a, 2]
                    h0 = 0.0
                    h1 = 0.0
                    h2 = 0.0
                    for a in range(8):
                        g = HEX_GAMMA[mode, a] - gx0 * b[0, a] - gx1 * b[1, a] - gx2 * b[2, a]
                        gam[a] = g
                        h0 += g * ve[a, 0]
                        h1 += g * ve[a, 1]
                        h2 += g * ve[a, 2]
                    for a in range(8):
                        f_elem[e, a, 0] -= coef * h0 * gam[a]
                        f_elem[e, a, 1] -= coef * h1 * gam[a]
                        f_elem[e, a, 2] -= coef * h2 * gam[a]


@njit(cache=True)
def _apply_bc_3d(kind, bc, w):
    """Velocity conditions on w (3,) in place (``_apply_bc`` in 3D; bc = the node's bc_normal row)."""
    if kind == BC_FIXED:
        w[0] = 0.0
        w[1] = 0.0
        w[2] = 0.0
    elif kind == BC_SLIP:
        vn = w[0] * bc[0] + w[1] * bc[1] + w[2] * bc[2]
        for k in range(3):
            w[k] -= vn * bc[k]
    elif kind == BC_VELOCITY:
        for k in range(3):
            w[k] = bc[k]
    elif kind == BC_LINE:
        vt = w[0] * bc[0] + w[1] * bc[1] + w[2] * bc[2]
        for k in range(3):
            w[k] = vt * bc[k]


@njit(parallel=True, cache=True)
def nodal_update_3d(f_elem, node_elem_ptr, node_elem_idx, f_ext, mass, m_floor, v, bc_type, bc_normal, dt, impulse):
    """``nodal_update`` in 3D: v^{n+1/2} = v^{n-1/2} + dt (f_int + f_ext) / m, then the velocity conditions."""
    n_nodes = v.shape[0]
    n_chunks = min(n_nodes, 512)
    for chunk in prange(n_chunks):
        w = np.empty(3)
        u = np.empty(3)
        for n in range(chunk * n_nodes // n_chunks, (chunk + 1) * n_nodes // n_chunks):
            f0 = f_ext[n, 0]
            f1 = f_ext[n, 1]
            f2 = f_ext[n, 2]
            for r in range(node_elem_ptr[n], node_elem_ptr[n + 1]):
                ea = node_elem_idx[r]
                e = ea // 8
                a = ea - 8 * e
                f0 += f_elem[e, a, 0]
                f1 += f_elem[e, a, 1]
                f2 += f_elem[e, a, 2]
            m = mass[n]
            if m > 0.0:
                w[0] = v[n, 0] + dt * f0 / m
                w[1] = v[n, 1] + dt * f1 / m
                w[2] = v[n, 2] + dt * f2 / m
            else:
                w[0] = 0.0
                w[1] = 0.0
                w[2] = 0.0
            for k in range(3):
                u[k] = w[k]
            if m > m_floor[n] or bc_type[n] == BC_VELOCITY:
                _apply_bc_3d(bc_type[n], bc_normal[n], u)
            else:
                u[0] = 0.0
                u[1] = 0.0
                u[2] = 0.0
            for k in range(3):
                impulse[n, k] = m * (u[k] - w[k])
                v[n, k] = u[k]


@njit(parallel=True, cache=True)
def lagrange_energy_3d(x, v_old, v_new, dt, conn, f_elem, vol_m, mass_m, ener_m, pres_m, bulk_m, q_elem,
                       closure, alpha, beta, phi_eps, work_elem):
    """``lagrange_energy`` on hex8: compatible work W_e = -dt sum_I f_eI . (v_I^{n-1/2} + v_I^{n+1/2}) / 2,
    the Lagrangian volume (``fem.geometry.hex8_volume``) at x + dt v^{n+1/2}, then the same closure (``_closure_energy``)."""
    n_elem = conn.shape[0]
    n_mat = vol_m.shape[1]
    n_chunks = min(n_elem, 512)
    for chunk in prange(n_chunks):
        start = chunk * n_elem // n_chunks
        stop = (chunk + 1) * n_elem // n_chunks
        dvm = np.empty(n_mat)
        dev = np.empty(n_mat)
        p = np.empty((8, 3))
        for e in range(start, stop):
            w = 0.0
            r = conn[e, 0]
            for a in range(8):
                n = conn[e, a]
                for k in range(3):
                    w -= f_elem[e, a, k] * 0.5 * (v_old[n, k] + v_new[n, k])
                    p[a, k] = (x[n, k] + dt * v_new[n, k]) - (x[r, k] + dt * v_new[r, k])
            w *= dt
            work_elem[e] = w
            v_lag = hex8_volume(p)
            _closure_energy(e, w, v_lag, vol_m, mass_m, ener_m, pres_m, bulk_m, closure, alpha, beta, phi_eps,
                            dvm, dev)


@njit(parallel=True, cache=True)
def face_fluxes_3d(faces, face_nodes, face_elem, face_local, elem_nbr, face_open, x_lag, x_new,
                   vol_m, mass_m, ener_m, order, iface, phi_eps, fvol, fmass, fener):
    """``face_fluxes`` on hex8 meshes: the volume through a quad face is its exact swept volume
    (``swept_volume_3d``), the upwind element of a donor is its neighbour across the opposite face
    (local face k ^ 1); the rest is ``_face_flux``."""
    nf = faces.shape[0]
    n_mat = vol_m.shape[1]
    n_chunks = min(nf, 512)
    for chunk in prange(n_chunks):
        start = chunk * nf // n_chunks
        stop = (chunk + 1) * nf // n_chunks
        dvm = np.empty(n_mat)
        g = np.empty(n_mat)
        used = np.empty(n_mat, dtype=np.bool_)
        p = np.empty((8, 3))
        for i in range(start, stop):
            f = faces[i]
            for m in range(n_mat):
                fvol[f, m] = 0.0
                fmass[f, m] = 0.0
                fener[f, m] = 0.0
            el = face_elem[f, 0]
            er = face_elem[f, 1]
            if er < 0 and not face_open[f]:
                continue
            dv = swept_volume_3d(face_nodes, f, x_lag, x_new, p)
            if dv == 0.0:
                continue
            if dv > 0.0:
                donor = er
                acc = el
                sgn = 1.0
                far = elem_nbr[er, face_local[f, 1] ^ 1] if er >= 0 else -1
            else:
                donor = el
                acc = er
                sgn = -1.0
                far = elem_nbr[el, face_local[f, 0] ^ 1]
            _face_flux(f, abs(dv), donor, acc, far, sgn, vol_m, mass_m, ener_m, order, iface, phi_eps,
                       fvol, fmass, fener, dvm, g, used)


@njit(parallel=True, cache=True)
def finish_remap_nodes_3d(mnode, pnode, knode, m_floor, bc_type, bc_normal, v, impulse, dissip):
    """``finish_remap_nodes`` in 3D: v = p / m, velocity conditions, kinetic energy lost (DeBar)."""
    n_nodes = mnode.shape[0]
    n_chunks = min(n_nodes, 512)
    for chunk in prange(n_chunks):
        w = np.empty(3)
        u = np.empty(3)
        for n in range(chunk * n_nodes // n_chunks, (chunk + 1) * n_nodes // n_chunks):
            m = mnode[n]
            for k in range(3):
                w[k] = pnode[n, k] / m if m > 0.0 else 0.0
                u[k] = w[k]
            if m > m_floor[n] or bc_type[n] == BC_VELOCITY:
                _apply_bc_3d(bc_type[n], bc_normal[n], u)
            else:
                u[0] = 0.0
                u[1] = 0.0
                u[2] = 0.0
            u2 = 0.0
            for k in range(3):
                impulse[n, k] = -pnode[n, k] if m <= 0.0 else m * (u[k] - w[k])
                v[n, k] = u[k]
                u2 += u[k] * u[k]
            dissip[n] = knode[n] - 0.5 * m * u2 if m > 0.0 else knode[n]
