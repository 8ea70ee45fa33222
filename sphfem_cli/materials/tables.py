"""Pack deck materials and equations of state into ``(type id, parameter row)`` for the kernels.

The row layout (parameter row ``p``, EOS row ``q = p[EOS_OFFSET:]``) is declared in
``materials.slots``; this module only fills it. The model builder initialises the internal energy
per unit initial volume from ``q[Q_E0]``.
"""
from __future__ import annotations

import numpy as np

from ..deck.schema import materials as sm
from . import ids
from .slots import (
    EOS_OFFSET, NPARAM, NQ, P_DETONATION_VELOCITY, P_E, P_EOS_TYPE, P_EP_BETA, P_EP_EP, P_EP_ET,
    P_EP_SIGMA_Y0, P_G, P_JC_A, P_JC_B, P_JC_C, P_JC_CP, P_JC_M, P_JC_N, P_JC_RATE0, P_JC_TM, P_JC_TR,
    P_K, P_NU, P_PRESSURE_CUTOFF, P_RHO0, P_VISCOSITY, Q_E0, Q_GR_A, Q_GR_C, Q_GR_GAMMA0, Q_GR_S1, Q_GR_S2, Q_GR_S3,
    Q_IG_GAMMA, Q_JWL_A, Q_JWL_B, Q_JWL_OMEGA, Q_JWL_R1, Q_JWL_R2, Q_LP_C0, Q_LP_C1, Q_LP_C2, Q_LP_C3,
    Q_LP_C4, Q_LP_C5, Q_LP_C6, Q_RHO0, Q_SG_GAMMA, Q_SG_PINF, Q_TAIT_B, Q_TAIT_C0, Q_TAIT_GAMMA,
    Q_TAIT_PB, Q_TAIT_RHO_REF, Q_V0,
)

MATERIAL_IDS = {
    "elastic": ids.ELASTIC,
    "elastic_plastic": ids.ELASTIC_PLASTIC,
    "johnson_cook": ids.JOHNSON_COOK,
    "rigid": ids.RIGID,
    "fluid": ids.FLUID,
    "high_explosive": ids.FLUID,
}

EOS_IDS = {
    "linear_polynomial": ids.EOS_LINEAR_POLYNOMIAL,
    "gruneisen": ids.EOS_GRUNEISEN,
    "tait": ids.EOS_TAIT,
    "ideal_gas": ids.EOS_IDEAL_GAS,
    "stiffened_gas": ids.EOS_STIFFENED_GAS,
    "jwl": ids.EOS_JWL,
}


def pack_eos(eos, rho0: float) -> tuple[int, np.ndarray]:
    """EOS type id and its row ``q`` (length ``NQ``, slots ``Q_*``) for a material of density rho0."""
    q = np.zeros(NQ)
    q[Q_RHO0] = rho0
    q[Q_E0] = getattr(eos, "e0", 0.0)
    q[Q_V0] = getattr(eos, "v0", 1.0)
    if isinstance(eos, sm.LinearPolynomial):
        q[Q_LP_C0], q[Q_LP_C1], q[Q_LP_C2], q[Q_LP_C3] = eos.c0, eos.c1, eos.c2, eos.c3
        q[Q_LP_C4], q[Q_LP_C5], q[Q_LP_C6] = eos.c4, eos.c5, eos.c6
    elif isinstance(eos, sm.Gruneisen):
        q[Q_GR_C], q[Q_GR_S1], q[Q_GR_S2], q[Q_GR_S3] = eos.c, eos.s1, eos.s2, eos.s3
        q[Q_GR_GAMMA0], q[Q_GR_A] = eos.gamma0, eos.a
    elif isinstance(eos, sm.Tait):
        q[Q_TAIT_RHO_REF], q[Q_TAIT_C0], q[Q_TAIT_GAMMA] = eos.reference_density, eos.sound_speed, eos.gamma
        q[Q_TAIT_PB] = eos.background_pressure
        q[Q_TAIT_B] = eos.reference_density * eos.sound_speed**2 / eos.gamma
    elif isinstance(eos, sm.IdealGas):
        q[Q_IG_GAMMA] = eos.gamma
    elif isinstance(eos, sm.StiffenedGas):
        q[Q_SG_GAMMA], q[Q_SG_PINF] = eos.gamma, eos.p_inf
    elif isinstance(eos, sm.JWL):
        q[Q_JWL_A], q[Q_JWL_B], q[Q_JWL_R1], q[Q_JWL_R2], q[Q_JWL_OMEGA] = eos.A, eos.B, eos.R1, eos.R2, eos.omega
    else:
        raise TypeError(f"not an equation of state model: {type(eos).__name__}")
    return EOS_IDS[eos.type], q


def eos_state_set_up(eos_type: int, q: np.ndarray, r, e) -> tuple:
    """``materials.kernels.eos_state`` (p, dp/dmu, dp/dE) at one state, run by the interpreter for the few calls
    of a model's set-up: its Python body (``py_func``) on float64 scalars does the same IEEE operations in the
    same order as the compiled kernel (libm's pow and exp in both; no fused multiply-add), so the same bits
    (tests/unit/test_setup_numpy.py checks every EOS), with nothing to compile or load from numba's cache. As
    the kernel, silent on invalid operations (a non-finite state is the guards' to report)."""
    from .kernels import eos_state
    with np.errstate(all="ignore"):
        return eos_state.py_func(int(eos_type), q, np.float64(r), np.float64(e))


def eos_sound_speed_set_up(eos_type: int, q: np.ndarray, r, e) -> float:
    """``materials.kernels.eos_sound_speed`` at one state, by ``eos_state_set_up``: c^2 = (dp/dmu + p (dp/dE) /
    (rho/rho0)^2) / rho0, 0 where c^2 <= 0 (the kernel's operations in its order: the same bits)."""
    r = np.float64(r)
    p, dpdmu, dpde = eos_state_set_up(eos_type, q, r, e)
    with np.errstate(all="ignore"):
        c2 = (dpdmu + p * dpde / (r * r)) / q[Q_RHO0]
    return float(np.sqrt(c2)) if c2 > 0.0 else 0.0


def pack_material(material, eos=None) -> tuple[int, np.ndarray]:
    """Material type id and parameter row (``NPARAM`` float64) from the deck models.

    ``eos`` is the resolved equation-of-state model when ``material.eos`` names one, else None.
    """
    wants_eos = getattr(material, "eos", None) is not None
    if wants_eos and eos is None:
        raise ValueError(f"material of type {material.type} names eos '{material.eos}' but none was given")
    if eos is not None and not wants_eos:
        raise ValueError(f"material of type {material.type} takes no equation of state here")

    p = np.zeros(NPARAM)
    p[P_EOS_TYPE] = ids.EOS_NONE
    rho0 = material.density
    p[P_RHO0] = rho0
    if eos is not None:
        eos_id, q = pack_eos(eos, rho0)
        p[P_EOS_TYPE] = eos_id
        p[EOS_OFFSET :] = q

    if isinstance(material, (sm.Fluid, sm.HighExplosive)):
        c0 = float(eos_sound_speed_set_up(int(p[P_EOS_TYPE]), p[EOS_OFFSET :], 1.0, p[EOS_OFFSET + Q_E0]))
        p[P_E], p[P_NU], p[P_G], p[P_K] = 0.0, 0.5, 0.0, rho0 * c0 * c0
        if isinstance(material, sm.HighExplosive):
            p[P_DETONATION_VELOCITY] = material.detonation_velocity
        else:
            p[P_VISCOSITY] = material.viscosity
        return ids.FLUID, p

    e, nu = material.youngs_modulus, material.poisson_ratio
    p[P_E], p[P_NU] = e, nu
    p[P_G] = e / (2.0 * (1.0 + nu))
    p[P_K] = e / (3.0 * (1.0 - 2.0 * nu))
    if isinstance(material, (sm.ElasticPlastic, sm.JohnsonCook)):
        cut = material.pressure_cutoff
        p[P_PRESSURE_CUTOFF] = -np.inf if cut is None else cut
    if isinstance(material, sm.ElasticPlastic):
        et = material.tangent_modulus
        p[P_EP_SIGMA_Y0], p[P_EP_ET], p[P_EP_BETA] = material.yield_stress, et, material.hardening_beta
        p[P_EP_EP] = e * et / (e - et)
    elif isinstance(material, sm.JohnsonCook):
        m = material
        p[P_JC_A], p[P_JC_B], p[P_JC_N], p[P_JC_C], p[P_JC_M] = m.A, m.B, m.n, m.C, m.m
        p[P_JC_RATE0], p[P_JC_TM], p[P_JC_TR] = m.reference_strain_rate, m.melt_temperature, m.room_temperature
        p[P_JC_CP] = m.specific_heat if m.specific_heat is not None else 0.0
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
