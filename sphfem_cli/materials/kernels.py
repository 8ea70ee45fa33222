"""Constitutive updates and equations of state as numba kernels.

Conventions (see docs/architecture.md): symmetric tensors are 6-vectors ``xx, yy, zz, xy, yz, zx``
with tensor shear components; pressure is positive in compression, sigma = s - p I. A material is
an integer type id plus a parameter row ``p`` of ``NPARAM`` floats packed by
``materials.tables.pack_material``; every slot is named in ``materials.slots`` (the only place a
slot number is written). The equation-of-state parameters live in
the same row from ``EOS_OFFSET`` on, so an EOS is called as
``eos_pressure(int(p[P_EOS_TYPE]), p[EOS_OFFSET:], rho_ratio, e_int)``.

Equations and sources: docs/theory/materials.md.
"""
from __future__ import annotations

import math

from numba import njit

from .ids import (  # noqa: F401  (re-exported: the type ids, declared in materials.ids)
    ELASTIC, ELASTIC_PLASTIC, EOS_GRUNEISEN, EOS_IDEAL_GAS, EOS_JWL, EOS_LINEAR_POLYNOMIAL, EOS_NONE,
    EOS_STIFFENED_GAS, EOS_TAIT, FLUID, JOHNSON_COOK, RIGID,
)
from .slots import NHIST, NPARAM  # noqa: F401  (re-exported: row lengths for callers of the kernels)
from .slots import (
    EOS_OFFSET, H_BACK_XX, H_BACK_XY, H_BACK_YY, H_BACK_YZ, H_BACK_ZX, H_BACK_ZZ, H_EPS, H_WP, P_EOS_TYPE,
    P_EP_BETA, P_EP_EP, P_EP_SIGMA_Y0, P_G, P_JC_A, P_JC_B, P_JC_C, P_JC_CP, P_JC_M, P_JC_N,
    P_JC_RATE0, P_JC_TM, P_JC_TR, P_K, P_PRESSURE_CUTOFF, P_RHO0, P_VISCOSITY, Q_GR_A, Q_GR_C, Q_GR_GAMMA0, Q_GR_S1, Q_GR_S2,
    Q_GR_S3, Q_IG_GAMMA, Q_JWL_A, Q_JWL_B, Q_JWL_OMEGA, Q_JWL_R1, Q_JWL_R2, Q_LP_C0, Q_LP_C1, Q_LP_C2,
    Q_LP_C3, Q_LP_C4, Q_LP_C5, Q_LP_C6, Q_RHO0, Q_SG_GAMMA, Q_SG_PINF, Q_TAIT_B, Q_TAIT_C0, Q_TAIT_GAMMA,
    Q_TAIT_PB, Q_TAIT_RHO_REF,
)

_JC_MAXIT = 100
_JC_RTOL = 1e-12


# ------------------------------------------------------------------------------ equations of state


@njit(cache=True)
def eos_state(eos_type, q, r, e):
    """Pressure and its partial derivatives ``(p, dp/dmu at fixed E, dp/dE at fixed mu)``.

    ``r`` = rho/rho0, mu = r - 1, ``e`` = internal energy per unit reference volume E.
    """
    mu = r - 1.0
    if eos_type == EOS_LINEAR_POLYNOMIAL:
        c0, c1, c2, c3 = q[Q_LP_C0], q[Q_LP_C1], q[Q_LP_C2], q[Q_LP_C3]
        c4, c5, c6 = q[Q_LP_C4], q[Q_LP_C5], q[Q_LP_C6]
        if mu < 0.0:  # LS-DYNA drops the quadratic terms in tension
            c2 = 0.0
            c6 = 0.0
        p = c0 + mu * (c1 + mu * (c2 + mu * c3)) + (c4 + mu * (c5 + mu * c6)) * e
        dpdmu = c1 + mu * (2.0 * c2 + 3.0 * c3 * mu) + (c5 + 2.0 * c6 * mu) * e
        dpde = c4 + mu * (c5 + mu * c6)
        return p, dpdmu, dpde
    if eos_type == EOS_GRUNEISEN:
        rho0, c, s1, s2, s3 = q[Q_RHO0], q[Q_GR_C], q[Q_GR_S1], q[Q_GR_S2], q[Q_GR_S3]
        g0, a = q[Q_GR_GAMMA0], q[Q_GR_A]
        k0 = rho0 * c * c
        dpde = g0 + a * mu
        if mu > 0.0:
            m1 = mu + 1.0
            num = 1.0 + (1.0 - 0.5 * g0) * mu - 0.5 * a * mu * mu
            dnum = (1.0 - 0.5 * g0) - a * mu
            den = 1.0 - (s1 - 1.0) * mu - s2 * mu * mu / m1 - s3 * mu * mu * mu / (m1 * m1)
            dden = -(s1 - 1.0) - s2 * mu * (mu + 2.0) / (m1 * m1) - s3 * mu * mu * (mu + 3.0) / (m1 * m1 * m1)
            p = k0 * mu * num / (den * den) + dpde * e
            dpdmu = k0 * ((num + mu * dnum) / (den * den) - 2.0 * mu * num * dden / (den * den * den)) + a * e
        else:
            p = k0 * mu + dpde * e
            dpdmu = k0 + a * e
        return p, dpdmu, dpde
    if eos_type == EOS_TAIT:
        rho0, rho_ref, c, gam = q[Q_RHO0], q[Q_TAIT_RHO_REF], q[Q_TAIT_C0], q[Q_TAIT_GAMMA]
        pb, b = q[Q_TAIT_PB], q[Q_TAIT_B]
        x = rho0 * r / rho_ref
        xg1 = x ** (gam - 1.0)
        p = b * (xg1 * x - 1.0) + pb
        dpdmu = b * gam * xg1 * rho0 / rho_ref
        return p, dpdmu, 0.0
    if eos_type == EOS_IDEAL_GAS:
        gm1 = q[Q_IG_GAMMA] - 1.0
        return gm1 * r * e, gm1 * e, gm1 * r
    if eos_type == EOS_STIFFENED_GAS:
        gam, pinf = q[Q_SG_GAMMA], q[Q_SG_PINF]
        gm1 = gam - 1.0
        return gm1 * r * e - gam * pinf, gm1 * e, gm1 * r
    if eos_type == EOS_JWL:
        a, b, r1, r2, w = q[Q_JWL_A], q[Q_JWL_B], q[Q_JWL_R1], q[Q_JWL_R2], q[Q_JWL_OMEGA]
        v = 1.0 / r
        x1 = math.exp(-r1 * v)
        x2 = math.exp(-r2 * v)
        p = a * (1.0 - w / (r1 * v)) * x1 + b * (1.0 - w / (r2 * v)) * x2 + w * e * r
        dpdv = (
            a * x1 * (w / (r1 * v * v) - r1 + w / v)
            + b * x2 * (w / (r2 * v * v) - r2 + w / v)
            - w * e / (v * v)
        )
        return p, -v * v * dpdv, w * r
    return 0.0, 0.0, 0.0


@njit(cache=True)
def eos_pressure(eos_type, q, rho_ratio, e_int):
    """Pressure p(rho/rho0, E) of equation of state ``eos_type`` with parameter row ``q``.

    ``e_int`` is the internal energy per unit reference volume (LS-DYNA's E). Formulas per type in
    docs/theory/materials.md; the row layout is in ``materials.slots``.
    """
    return eos_state(eos_type, q, rho_ratio, e_int)[0]


@njit(cache=True)
def eos_sound_speed(eos_type, q, rho_ratio, e_int):
    """Isentropic sound speed c = sqrt((dp/drho)_e + p/rho^2 (dp/de)_rho).

    In the variables mu = rho/rho0 - 1 and E = rho0 e this is
    c^2 = (dp/dmu + p (dp/dE) / (rho/rho0)^2) / rho0. Negative c^2 is clamped to 0.
    """
    p, dpdmu, dpde = eos_state(eos_type, q, rho_ratio, e_int)
    c2 = (dpdmu + p * dpde / (rho_ratio * rho_ratio)) / q[Q_RHO0]
    return math.sqrt(c2) if c2 > 0.0 else 0.0


# ------------------------------------------------------------------------------ plasticity helpers


@njit(cache=True)
def _bilinear_return(p, hist, s0, s1, s2, s3, s4, s5, G):
    """Radial return for bilinear von Mises plasticity with combined hardening (LS-DYNA MAT_003).

    sigma_y = sigma_y0 + beta Ep eps_p, Ep = E Et/(E - Et); back stress rate (1 - beta) Ep deps_p
    times the unit flow direction xi/xi_eq; deps_p = f/(3G + Ep). Updates ``hist`` and returns the
    corrected deviator and the plastic work s_{n+1} : deps^p.
    """
    sy0, beta, ep_mod = p[P_EP_SIGMA_Y0], p[P_EP_BETA], p[P_EP_EP]
    a0, a1, a2 = hist[H_BACK_XX], hist[H_BACK_YY], hist[H_BACK_ZZ]
    a3, a4, a5 = hist[H_BACK_XY], hist[H_BACK_YZ], hist[H_BACK_ZX]
    x0, x1, x2, x3, x4, x5 = s0 - a0, s1 - a1, s2 - a2, s3 - a3, s4 - a4, s5 - a5
    xeq = math.sqrt(1.5 * (x0 * x0 + x1 * x1 + x2 * x2 + 2.0 * (x3 * x3 + x4 * x4 + x5 * x5)))
    eps = hist[H_EPS]
    f = xeq - (sy0 + beta * ep_mod * eps)
    if f <= 0.0:
        return s0, s1, s2, s3, s4, s5, 0.0
    dl = f / (3.0 * G + ep_mod)
    k = 3.0 * G * dl / xeq
    s0, s1, s2, s3, s4, s5 = s0 - k * x0, s1 - k * x1, s2 - k * x2, s3 - k * x3, s4 - k * x4, s5 - k * x5
    h = (1.0 - beta) * ep_mod * dl / xeq
    hist[H_BACK_XX], hist[H_BACK_YY], hist[H_BACK_ZZ] = a0 + h * x0, a1 + h * x1, a2 + h * x2
    hist[H_BACK_XY], hist[H_BACK_YZ], hist[H_BACK_ZX] = a3 + h * x3, a4 + h * x4, a5 + h * x5
    hist[H_EPS] = eps + dl
    sx = s0 * x0 + s1 * x1 + s2 * x2 + 2.0 * (s3 * x3 + s4 * x4 + s5 * x5)
    dwp = 1.5 * dl * sx / xeq
    hist[H_WP] += dwp
    return s0, s1, s2, s3, s4, s5, dwp


@njit(cache=True)
def jc_thermal_factor(p, wp):
    """Johnson-Cook thermal factor 1 - T*^m, T* = (T - Tr)/(Tm - Tr), T = Tr + Wp/(rho0 cp).

    ``wp`` is the plastic work per unit initial volume; cp = 0 means isothermal (factor 1).
    """
    cp = p[P_JC_CP]
    if cp <= 0.0:
        return 1.0
    troom, tmelt = p[P_JC_TR], p[P_JC_TM]
    tstar = (wp / (p[P_RHO0] * cp)) / (tmelt - troom)
    if tstar <= 0.0:
        return 1.0
    if tstar >= 1.0:
        return 0.0
    return 1.0 - tstar ** p[P_JC_M]


@njit(cache=True)
def jc_flow_stress(p, eps, rate_star, theta):
    """Johnson-Cook flow stress (A + B eps^n)(1 + C ln max(rate*, 1)) theta."""
    a, b, n, c = p[P_JC_A], p[P_JC_B], p[P_JC_N], p[P_JC_C]
    hard = a + b * eps ** n if eps > 0.0 else a
    rate = 1.0 + c * math.log(rate_star) if rate_star > 1.0 else 1.0
    return hard * rate * theta


@njit(cache=True)
def _jc_return(p, hist, s0, s1, s2, s3, s4, s5, G, dt):
    """Radial return for Johnson-Cook plasticity (isotropic hardening).

    Solves xi_eq - 3G dl - sigma_y(eps_p + dl, dl/(dt rate0)) = 0 for dl by Newton's method
    safeguarded by bisection on [0, xi_eq/(3G)]; the rate is the plastic strain rate dl/dt and
    the temperature is taken from the plastic work at the start of the step.
    """
    a, b, n, c, rate0 = p[P_JC_A], p[P_JC_B], p[P_JC_N], p[P_JC_C], p[P_JC_RATE0]
    xeq = math.sqrt(1.5 * (s0 * s0 + s1 * s1 + s2 * s2 + 2.0 * (s3 * s3 + s4 * s4 + s5 * s5)))
    eps = hist[H_EPS]
    theta = jc_thermal_factor(p, hist[H_WP])
    if xeq <= jc_flow_stress(p, eps, 0.0, theta):
        return s0, s1, s2, s3, s4, s5, 0.0
    if theta <= 0.0:  # melted: no deviatoric strength
        dl = xeq / (3.0 * G)
        hist[H_EPS] = eps + dl
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    inv_rate = 1.0 / (dt * rate0) if dt > 0.0 else 0.0
    lo = 0.0
    hi = xeq / (3.0 * G)
    dl = 0.5 * hi * (1.0 - jc_flow_stress(p, eps, 0.0, theta) / xeq)
    for _ in range(_JC_MAXIT):
        e1 = eps + dl
        rs = dl * inv_rate
        hard = a + b * e1 ** n if e1 > 0.0 else a
        rate = 1.0 + c * math.log(rs) if rs > 1.0 else 1.0
        f = xeq - 3.0 * G * dl - hard * rate * theta
        if f > 0.0:
            lo = dl
        else:
            hi = dl
        if abs(f) <= _JC_RTOL * xeq:
            break
        dhard = b * n * e1 ** (n - 1.0) if e1 > 0.0 else 0.0
        drate = c / dl if rs > 1.0 else 0.0
        df = -3.0 * G - theta * (dhard * rate + hard * drate)
        nxt = dl - f / df
        if not (lo < nxt < hi):
            nxt = 0.5 * (lo + hi)
        if abs(nxt - dl) <= _JC_RTOL * hi:
            dl = nxt
            break
        dl = nxt
    scale = 1.0 - 3.0 * G * dl / xeq
    hist[H_EPS] = eps + dl
    dwp = dl * scale * xeq
    hist[H_WP] += dwp
    return s0 * scale, s1 * scale, s2 * scale, s3 * scale, s4 * scale, s5 * scale, dwp


# ------------------------------------------------------------------------------ stress update


@njit(cache=True)
def elastic_stress_update(p, sig, deps):
    """``update_stress`` of an elastic material without an equation of state, the same operations in the
    same order: sm = tr(sigma)/3, sm' = sm + K tr(deps), sigma_i' = (sigma_i - sm + 2G (deps_i - tr/3)) + sm'
    (normal components), tau' = tau + 2G deps (shear).

    Small enough for LLVM to inline into an element loop; ``update_stress`` (every other material)
    cost about 130-160 ns a call on an elastic element, this about 6 (benchmarks/fem_passes.py).
    """
    tr = deps[0] + deps[1] + deps[2]
    third = tr / 3.0
    sm = (sig[0] + sig[1] + sig[2]) / 3.0
    sm_new = sm + p[P_K] * tr
    g2 = 2.0 * p[P_G]
    s0 = sig[0] - sm + g2 * (deps[0] - third)
    s1 = sig[1] - sm + g2 * (deps[1] - third)
    s2 = sig[2] - sm + g2 * (deps[2] - third)
    sig[3] = sig[3] + g2 * deps[3]
    sig[4] = sig[4] + g2 * deps[4]
    sig[5] = sig[5] + g2 * deps[5]
    sig[0] = s0 + sm_new
    sig[1] = s1 + sm_new
    sig[2] = s2 + sm_new


@njit(cache=True)
def elastic_sound_speed(p, rel_volume):
    """``sound_speed`` of an elastic material without an equation of state (same operations):
    sqrt((K + 4G/3) / rho), rho = rho0 / rel_volume."""
    rho = p[P_RHO0] / rel_volume
    return math.sqrt((p[P_K] + 4.0 * p[P_G] / 3.0) / rho)


@njit(cache=True)
def elastic_plane_stress_update(p, sig, deps):
    """``elastic_stress_update`` under plane stress: the thickness strain increment deps[2] is chosen so
    that sigma_zz = 0 after the step, and returned in deps[2].

    The hypoelastic increment gives sigma_zz' = sigma_zz + lambda (deps_xx + deps_yy + deps_zz) + 2G deps_zz,
    so sigma_zz' = 0 for deps_zz = -(sigma_zz + lambda (deps_xx + deps_yy)) / (lambda + 2G), lambda = K - 2G/3.
    The in-plane increments are then the plane-stress law (e.g. Timoshenko & Goodier, Theory of
    Elasticity, 1970, ch. 2):
    dsigma_xx = E/(1 - nu^2) (deps_xx + nu deps_yy), dsigma_yy = E/(1 - nu^2) (deps_yy + nu deps_xx),
    dsigma_xy = 2G deps_xy (lambda_bar = 2G lambda / (lambda + 2G) = E nu / (1 - nu^2) in place of lambda).
    sigma_zz is then set to 0 exactly (the formula leaves round-off).
    """
    g2 = 2.0 * p[P_G]
    lam = p[P_K] - g2 / 3.0
    deps[2] = -(sig[2] + lam * (deps[0] + deps[1])) / (lam + g2)
    elastic_stress_update(p, sig, deps)
    sig[2] = 0.0


PLANE_STRESS_MAXIT = 30
PLANE_STRESS_RTOL = 1e-12


@njit(cache=True)
def plane_stress_update(mtype, p, sig, hist, deps, dt, rel_volume, e_int, sig_start, hist_start):
    """``update_stress`` under plane stress: deps[2] (the thickness strain increment, returned there) is
    solved so that sigma_zz(deps_zz) = 0 after the whole update, return mapping included; returns the
    plastic work like ``update_stress``.

    The standard approach for plane-stress plasticity with a 3D return map (the thickness strain as
    the unknown of sigma_zz = 0: de Souza Neto, Peric & Owen, Computational Methods for
    Plasticity, 2008, ch. 9, the plane-stress constraint at the Gauss point; LS-DYNA's shell plasticity,
    *CONTROL_SHELL MITER = 1, secant iterations): secant iterations on
    r(x) = sigma_zz after ``update_stress`` with deps_zz = x, started from the elastic value
    x0 = -(sigma_zz + lambda (deps_xx + deps_yy)) / (lambda + 2G) and a first step with the elastic
    slope lambda + 2G (an upper bound of dr/dx, so r is monotone and the secant converges), each trial
    from the stress ``sig`` and history ``hist`` at the start of the step (copied into the scratch
    rows ``sig_start`` (6,) and ``hist_start`` (NHIST,)). Stops at |r| <= PLANE_STRESS_RTOL times the
    in-plane stress scale, or after PLANE_STRESS_MAXIT trials; sigma_zz is then set to 0. An elastic
    material takes the closed form (``elastic_plane_stress_update``): this iteration gives it in one
    trial. Without an equation of state (the deck refuses one with plane stress), ``rel_volume`` and
    ``e_int`` are passed through unused.
    """
    nh = hist.shape[0]
    for c in range(6):
        sig_start[c] = sig[c]
    for c in range(nh):
        hist_start[c] = hist[c]
    g2 = 2.0 * p[P_G]
    lam = p[P_K] - g2 / 3.0
    slope = lam + g2
    x0 = -(sig[2] + lam * (deps[0] + deps[1])) / slope
    deps[2] = x0
    dwp = update_stress(mtype, p, sig, hist, deps, dt, rel_volume, e_int)
    r0 = sig[2]
    scale = (abs(sig_start[0]) + abs(sig_start[1]) + abs(sig_start[3])
             + slope * (abs(deps[0]) + abs(deps[1]) + abs(deps[3])))
    tol = PLANE_STRESS_RTOL * scale
    x1 = x0 - r0 / slope
    for _ in range(PLANE_STRESS_MAXIT):
        if abs(r0) <= tol:
            break
        for c in range(6):
            sig[c] = sig_start[c]
        for c in range(nh):
            hist[c] = hist_start[c]
        deps[2] = x1
        dwp = update_stress(mtype, p, sig, hist, deps, dt, rel_volume, e_int)
        r1 = sig[2]
        if abs(r1) <= tol or r1 == r0:
            break
        x2 = x1 - r1 * (x1 - x0) / (r1 - r0)
        x0, r0, x1 = x1, r1, x2
    sig[2] = 0.0
    return dwp


@njit(cache=True)
def plane_stress_sound_speed(p, rel_volume):
    """Wave speed for the stable step of a plane-stress element (no EOS): the in-plane dilatational speed
    sqrt(M / rho) with the plane-stress P-wave modulus M = lambda_bar + 2G = E / (1 - nu^2)
    = 4G (K + G/3) / (K + 4G/3), rho = rho0 / rel_volume (rel_volume with the thickness change).
    The plane-strain modulus K + 4G/3 = E (1 - nu) / ((1 + nu)(1 - 2 nu)) (``elastic_sound_speed``) is
    (1 - nu)^2 / (1 - 2 nu) times M: its speed is 1.34 times this one at nu = 0.4, 1.11 at nu = 0.3.
    """
    rho = p[P_RHO0] / rel_volume
    k, g = p[P_K], p[P_G]
    modulus = 4.0 * g * (k + g / 3.0) / (k + 4.0 * g / 3.0)
    return math.sqrt(modulus / rho)


@njit(cache=True)
def update_stress(mtype, p, sig, hist, deps, dt, rel_volume, e_int):
    """Advance the Cauchy stress ``sig`` (6,) in place over one step; return the plastic work.

    ``sig`` is the stress at the start of the step, already rotated (Jaumann); ``deps`` = d dt is
    the strain increment (tensor shear); ``hist`` (NHIST,) is updated in place; ``rel_volume`` =
    V/V0 and ``e_int`` (internal energy per unit initial volume) feed the EOS when one is
    attached (``p[P_EOS_TYPE] >= 0``). Hypoelastic (Wilkins):
    sigma += lambda tr(deps) I + 2G deps, then the deviator is returned to the yield surface
    (elastic_plastic, johnson_cook). With an EOS the pressure is max(p_eos(1/rel_volume, e_int), p_cut)
    (p_cut = ``P_PRESSURE_CUTOFF``, -inf unless the deck's ``pressure_cutoff``: LS-DYNA
    *MAT_ELASTIC_PLASTIC_HYDRO's PC) and only the deviator comes from the rate form.
    Fluid: sigma = -p_eos I + 2 mu_visc dev(deps)/dt.
    Returns the plastic work increment per unit volume (0 for elastic, rigid and fluid).
    """
    if mtype == RIGID:
        return 0.0
    eos = int(p[P_EOS_TYPE])
    tr = deps[0] + deps[1] + deps[2]
    third = tr / 3.0
    sm = (sig[0] + sig[1] + sig[2]) / 3.0
    if eos >= 0:
        sm_new = -eos_pressure(eos, p[EOS_OFFSET:], 1.0 / rel_volume, e_int)
    else:
        sm_new = sm + p[P_K] * tr
    if mtype == FLUID:
        k = 2.0 * p[P_VISCOSITY] / dt if dt > 0.0 else 0.0
        sig[0] = sm_new + k * (deps[0] - third)
        sig[1] = sm_new + k * (deps[1] - third)
        sig[2] = sm_new + k * (deps[2] - third)
        sig[3] = k * deps[3]
        sig[4] = k * deps[4]
        sig[5] = k * deps[5]
        return 0.0
    if eos >= 0 and sm_new > -p[P_PRESSURE_CUTOFF]:  # cavitation / spall: p >= p_cut
        sm_new = -p[P_PRESSURE_CUTOFF]
    g2 = 2.0 * p[P_G]
    s0 = sig[0] - sm + g2 * (deps[0] - third)
    s1 = sig[1] - sm + g2 * (deps[1] - third)
    s2 = sig[2] - sm + g2 * (deps[2] - third)
    s3 = sig[3] + g2 * deps[3]
    s4 = sig[4] + g2 * deps[4]
    s5 = sig[5] + g2 * deps[5]
    dwp = 0.0
    if mtype == ELASTIC_PLASTIC:
        s0, s1, s2, s3, s4, s5, dwp = _bilinear_return(p, hist, s0, s1, s2, s3, s4, s5, p[P_G])
    elif mtype == JOHNSON_COOK:
        s0, s1, s2, s3, s4, s5, dwp = _jc_return(p, hist, s0, s1, s2, s3, s4, s5, p[P_G], dt)
    sig[0] = s0 + sm_new
    sig[1] = s1 + sm_new
    sig[2] = s2 + sm_new
    sig[3] = s3
    sig[4] = s4
    sig[5] = s5
    return dwp


@njit(cache=True)
def sound_speed(mtype, p, rel_volume, e_int=0.0):
    """Wave speed for the stable time step.

    Solids: dilatational speed sqrt((K + 4G/3)/rho), rho = rho0/rel_volume; with an EOS attached
    K is replaced by max(K, rho c_eos^2). Fluids: the EOS sound speed at (rho0/rel_volume, e_int)
    (without an EOS, sqrt(K/rho)). ``e_int`` matters only for energy-dependent EOSs.
    """
    rho = p[P_RHO0] / rel_volume
    eos = int(p[P_EOS_TYPE])
    k = p[P_K]
    if eos >= 0:
        c = eos_sound_speed(eos, p[EOS_OFFSET:], 1.0 / rel_volume, e_int)
        if mtype == FLUID:
            return c
        k = max(k, rho * c * c)
    return math.sqrt((k + 4.0 * p[P_G] / 3.0) / rho)
