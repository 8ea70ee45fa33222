"""Pack deck materials and equations of state into ``(type id, parameter row)`` for the kernels.

Parameter row ``p`` (``NPARAM`` = 32 float64); unused slots are 0.

===========  ==================  ================================================================
slot         model               meaning
===========  ==================  ================================================================
0            all                 reference density rho0
1            all                 Young's modulus E (fluid: 0)
2            all                 Poisson ratio nu (fluid: 0.5)
3            all                 shear modulus G = E/(2(1+nu)) (fluid: 0)
4            all                 bulk modulus K = E/(3(1-2nu)) (fluid: rho0 c0^2 from the EOS)
5            elastic_plastic     initial yield stress sigma_y0
6            elastic_plastic     tangent modulus Et
7            elastic_plastic     hardening mix beta (1 isotropic, 0 kinematic)
8            elastic_plastic     plastic modulus Ep = E Et/(E - Et)
5..13        johnson_cook        A, B, n, C, m, reference strain rate, Tm, Tr, cp (0 = isothermal)
5            fluid               dynamic viscosity mu
5            high_explosive      0 (inviscid)
6            high_explosive      detonation velocity D (packed as a fluid; 0 for other fluids)
15           all                 EOS type id (``EOS_NONE`` = -1 when no EOS is attached)
16..31       all                 EOS row q = p[16:] (below)
===========  ==================  ================================================================

EOS row ``q`` (``q[i]`` = ``p[EOS_OFFSET + i]``):

=====  ==================  ===================================================================
q[i]   EOS                 meaning
=====  ==================  ===================================================================
0      all                 rho0 of the material (the reference density of mu = rho/rho0 - 1)
1      all                 e0, initial internal energy per unit reference volume
2      all                 v0, initial relative volume (linear_polynomial; 1 otherwise)
3..9   linear_polynomial   C0, C1, C2, C3, C4, C5, C6
3..8   gruneisen           C, S1, S2, S3, gamma0, a
3..7   tait                rho_ref, c0, gamma, p_b, B = rho_ref c0^2 / gamma
3      ideal_gas           gamma
3..4   stiffened_gas       gamma, p_inf
3..7   jwl                 A, B, R1, R2, omega
=====  ==================  ===================================================================

The model builder initialises the internal energy per unit initial volume from ``q[1]``.
"""
from __future__ import annotations

import numpy as np

from ..deck.schema import materials as sm
from . import kernels as k

MATERIAL_IDS = {
    "elastic": k.ELASTIC,
    "elastic_plastic": k.ELASTIC_PLASTIC,
    "johnson_cook": k.JOHNSON_COOK,
    "rigid": k.RIGID,
    "fluid": k.FLUID,
    "high_explosive": k.FLUID,
}

P_DETONATION_VELOCITY = 6
"""Slot of the detonation velocity D of a ``high_explosive`` (a fluid row); 0 for other fluids."""

EOS_IDS = {
    "linear_polynomial": k.EOS_LINEAR_POLYNOMIAL,
    "gruneisen": k.EOS_GRUNEISEN,
    "tait": k.EOS_TAIT,
    "ideal_gas": k.EOS_IDEAL_GAS,
    "stiffened_gas": k.EOS_STIFFENED_GAS,
    "jwl": k.EOS_JWL,
}


def pack_eos(eos, rho0: float) -> tuple[int, np.ndarray]:
    """EOS type id and its row ``q`` (length ``NPARAM - EOS_OFFSET``) for a material of density rho0."""
    q = np.zeros(k.NPARAM - k.EOS_OFFSET)
    q[0] = rho0
    q[1] = getattr(eos, "e0", 0.0)
    q[2] = getattr(eos, "v0", 1.0)
    if isinstance(eos, sm.LinearPolynomial):
        q[3:10] = [eos.c0, eos.c1, eos.c2, eos.c3, eos.c4, eos.c5, eos.c6]
    elif isinstance(eos, sm.Gruneisen):
        q[3:9] = [eos.c, eos.s1, eos.s2, eos.s3, eos.gamma0, eos.a]
    elif isinstance(eos, sm.Tait):
        b = eos.reference_density * eos.sound_speed**2 / eos.gamma
        q[3:8] = [eos.reference_density, eos.sound_speed, eos.gamma, eos.background_pressure, b]
    elif isinstance(eos, sm.IdealGas):
        q[3] = eos.gamma
    elif isinstance(eos, sm.StiffenedGas):
        q[3:5] = [eos.gamma, eos.p_inf]
    elif isinstance(eos, sm.JWL):
        q[3:8] = [eos.A, eos.B, eos.R1, eos.R2, eos.omega]
    else:
        raise TypeError(f"not an equation of state model: {type(eos).__name__}")
    return EOS_IDS[eos.type], q


def pack_material(material, eos=None) -> tuple[int, np.ndarray]:
    """Material type id and parameter row (``NPARAM`` float64) from the deck models.

    ``eos`` is the resolved equation-of-state model when ``material.eos`` names one, else None.
    """
    wants_eos = getattr(material, "eos", None) is not None
    if wants_eos and eos is None:
        raise ValueError(f"material of type {material.type} names eos '{material.eos}' but none was given")
    if eos is not None and not wants_eos:
        raise ValueError(f"material of type {material.type} takes no equation of state here")

    p = np.zeros(k.NPARAM)
    p[k.P_EOS_TYPE] = k.EOS_NONE
    rho0 = material.density
    p[k.P_RHO0] = rho0
    if eos is not None:
        eos_id, q = pack_eos(eos, rho0)
        p[k.P_EOS_TYPE] = eos_id
        p[k.EOS_OFFSET :] = q

    if isinstance(material, (sm.Fluid, sm.HighExplosive)):
        c0 = float(k.eos_sound_speed(int(p[k.P_EOS_TYPE]), p[k.EOS_OFFSET :], 1.0, p[k.EOS_OFFSET + 1]))
        p[k.P_E], p[k.P_NU], p[k.P_G], p[k.P_K] = 0.0, 0.5, 0.0, rho0 * c0 * c0
        if isinstance(material, sm.HighExplosive):
            p[P_DETONATION_VELOCITY] = material.detonation_velocity
        else:
            p[5] = material.viscosity
        return k.FLUID, p

    e, nu = material.youngs_modulus, material.poisson_ratio
    p[k.P_E], p[k.P_NU] = e, nu
    p[k.P_G] = e / (2.0 * (1.0 + nu))
    p[k.P_K] = e / (3.0 * (1.0 - 2.0 * nu))
    if isinstance(material, sm.ElasticPlastic):
        et = material.tangent_modulus
        p[5:9] = [material.yield_stress, et, material.hardening_beta, e * et / (e - et)]
    elif isinstance(material, sm.JohnsonCook):
        m = material
        cp = m.specific_heat if m.specific_heat is not None else 0.0
        p[5:14] = [m.A, m.B, m.n, m.C, m.m, m.reference_strain_rate, m.melt_temperature, m.room_temperature, cp]
    elif not isinstance(material, (sm.Elastic, sm.Rigid)):
        raise TypeError(f"not a material model: {type(material).__name__}")
    return MATERIAL_IDS[material.type], p


def gas_row(gamma: float, density: float, p_inf: float = 0.0) -> np.ndarray:
    """Parameter row of a fluid with an ideal-gas (p_inf = 0) or stiffened-gas EOS.

    For scripts and tests that build an ALE or SPH system directly, without a deck.
    """
    eos = (sm.IdealGas(type="ideal_gas", gamma=gamma) if p_inf == 0.0
           else sm.StiffenedGas(type="stiffened_gas", gamma=gamma, p_inf=p_inf))
    return pack_material(sm.Fluid(type="fluid", density=density, eos="gas"), eos)[1]
