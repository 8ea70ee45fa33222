"""The one declaration of every slot of a material's parameter row, its EOS row and its history row.

A material is an integer type id plus a parameter row ``p`` of ``NPARAM`` float64 (unused slots 0),
packed by ``materials.tables.pack_material``. Its equation of state lives in the same row from
``EOS_OFFSET`` on: ``q = p[EOS_OFFSET:]``, so ``q[Q_X]`` is ``p[EOS_OFFSET + Q_X]``. Every element of
a solid carries a history row ``hist`` of ``NHIST`` float64.

Slots 0..4 are common to all models; slots ``P_MODEL`` .. ``P_EOS_TYPE - 1`` belong to the model of
the row (the same slot means different things in different models, which is why every reader
names it through this module). The names are module-level ints so that numba folds them into the
kernels as constants (``sphfem_cli._kernel_source_hash`` keys the compiled cache on this file too,
through ``__numba_folded__``).

Parameter row ``p``:

=====================  ===============  ===========================================================
name                   model            meaning
=====================  ===============  ===========================================================
P_RHO0                 all              reference density rho0
P_E                    all              Young's modulus E (fluid: 0)
P_NU                   all              Poisson ratio nu (fluid: 0.5)
P_G                    all              shear modulus G = E/(2(1+nu)) (fluid: 0)
P_K                    all              bulk modulus K = E/(3(1-2nu)) (fluid: rho0 c0^2 of the EOS)
P_EP_SIGMA_Y0          elastic_plastic  initial yield stress sigma_y0
P_EP_ET                elastic_plastic  tangent modulus Et
P_EP_BETA              elastic_plastic  hardening mix beta (1 isotropic, 0 kinematic)
P_EP_EP                elastic_plastic  plastic modulus Ep = E Et/(E - Et)
P_JC_A .. P_JC_M       johnson_cook     A, B, n, C, m
P_JC_RATE0             johnson_cook     reference strain rate
P_JC_TM, P_JC_TR       johnson_cook     melt and room temperature
P_JC_CP                johnson_cook     specific heat cp (0 = isothermal)
P_PRESSURE_CUTOFF      elastic_plastic, lowest EOS pressure (cavitation, spall; -inf: none)
                       johnson_cook
P_VISCOSITY            fluid            dynamic viscosity mu (high_explosive: 0, inviscid)
P_DETONATION_VELOCITY  high_explosive   detonation velocity D (a fluid row; 0 for other fluids)
P_EOS_TYPE             all              EOS type id (``EOS_NONE`` = -1 when no EOS is attached)
EOS_OFFSET ..          all              the EOS row q (below)
=====================  ===============  ===========================================================

EOS row ``q``:

===================================  ==================  ====================================
name                                 EOS                 meaning
===================================  ==================  ====================================
Q_RHO0                               all                 rho0 of mu = rho/rho0 - 1
Q_E0                                 all                 e0, initial internal energy per unit
                                                         reference volume
Q_V0                                 all                 v0, initial relative volume
                                                         (linear_polynomial; 1 otherwise)
Q_LP_C0 .. Q_LP_C6                   linear_polynomial   C0 .. C6
Q_GR_C, Q_GR_S1..S3, Q_GR_GAMMA0,    gruneisen           C, S1, S2, S3, gamma0, a
Q_GR_A
Q_TAIT_RHO_REF, Q_TAIT_C0,           tait                rho_ref, c0, gamma, p_b,
Q_TAIT_GAMMA, Q_TAIT_PB, Q_TAIT_B                        B = rho_ref c0^2 / gamma
Q_IG_GAMMA                           ideal_gas           gamma
Q_SG_GAMMA, Q_SG_PINF                stiffened_gas       gamma, p_inf
Q_JWL_A, Q_JWL_B, Q_JWL_R1,          jwl                 A, B, R1, R2, omega
Q_JWL_R2, Q_JWL_OMEGA
===================================  ==================  ====================================

History row ``hist``: H_EPS effective plastic strain; H_BACK_XX .. H_BACK_ZX the back stress
(6-vector order xx, yy, zz, xy, yz, zx); H_WP plastic work per unit initial volume;
H_THICKNESS_STRAIN the logarithmic thickness strain ln(h/h0) of a plane-stress element (the sum of
its d_zz dt; 0 in every other element).

``MODEL_SLOTS``, ``EOS_SLOTS`` and ``HISTORY_SLOTS`` list each layout's names in slot order; the unit
tests check from them that no two names of one layout share a slot and that each stays in its range.
"""
from __future__ import annotations

__numba_folded__ = True  # numba folds these ints into kernels: part of the compiled-cache key

NPARAM = 32
NHIST = 9

# ---------------------------------------------------------------- parameter row p, common slots
P_RHO0, P_E, P_NU, P_G, P_K = range(5)
P_MODEL = 5  # first model-specific slot
P_EOS_TYPE = 15
EOS_OFFSET = 16
NQ = NPARAM - EOS_OFFSET  # length of the EOS row q

# elastic_plastic (LS-DYNA *MAT_PLASTIC_KINEMATIC, MAT_003)
P_EP_SIGMA_Y0, P_EP_ET, P_EP_BETA, P_EP_EP = range(P_MODEL, P_MODEL + 4)

# johnson_cook (LS-DYNA *MAT_JOHNSON_COOK, MAT_015)
(P_JC_A, P_JC_B, P_JC_N, P_JC_C, P_JC_M, P_JC_RATE0, P_JC_TM, P_JC_TR,
 P_JC_CP) = range(P_MODEL, P_MODEL + 9)

# elastic_plastic and johnson_cook with an EOS: the lowest pressure (LS-DYNA *MAT_ELASTIC_PLASTIC_HYDRO PC),
# after both models' own slots (the last model slot)
P_PRESSURE_CUTOFF = P_EOS_TYPE - 1

# fluid and high_explosive (a high explosive packs as an inviscid fluid)
P_VISCOSITY, P_DETONATION_VELOCITY = range(P_MODEL, P_MODEL + 2)

# ---------------------------------------------------------------- EOS row q = p[EOS_OFFSET:]
Q_RHO0, Q_E0, Q_V0 = range(3)
Q_MODEL = 3  # first EOS-specific slot

(Q_LP_C0, Q_LP_C1, Q_LP_C2, Q_LP_C3, Q_LP_C4, Q_LP_C5, Q_LP_C6) = range(Q_MODEL, Q_MODEL + 7)
Q_GR_C, Q_GR_S1, Q_GR_S2, Q_GR_S3, Q_GR_GAMMA0, Q_GR_A = range(Q_MODEL, Q_MODEL + 6)
Q_TAIT_RHO_REF, Q_TAIT_C0, Q_TAIT_GAMMA, Q_TAIT_PB, Q_TAIT_B = range(Q_MODEL, Q_MODEL + 5)
Q_IG_GAMMA = Q_MODEL
Q_SG_GAMMA, Q_SG_PINF = range(Q_MODEL, Q_MODEL + 2)
Q_JWL_A, Q_JWL_B, Q_JWL_R1, Q_JWL_R2, Q_JWL_OMEGA = range(Q_MODEL, Q_MODEL + 5)

# ---------------------------------------------------------------- history row hist
H_EPS = 0
H_BACK_XX, H_BACK_YY, H_BACK_ZZ, H_BACK_XY, H_BACK_YZ, H_BACK_ZX = range(1, 7)
H_WP = 7
H_THICKNESS_STRAIN = 8

COMMON_SLOTS = ("P_RHO0", "P_E", "P_NU", "P_G", "P_K")
MODEL_SLOTS = {
    "elastic": (),
    "rigid": (),
    "elastic_plastic": ("P_EP_SIGMA_Y0", "P_EP_ET", "P_EP_BETA", "P_EP_EP", "P_PRESSURE_CUTOFF"),
    "johnson_cook": ("P_JC_A", "P_JC_B", "P_JC_N", "P_JC_C", "P_JC_M", "P_JC_RATE0", "P_JC_TM",
                     "P_JC_TR", "P_JC_CP", "P_PRESSURE_CUTOFF"),
    "fluid": ("P_VISCOSITY", "P_DETONATION_VELOCITY"),
}
COMMON_EOS_SLOTS = ("Q_RHO0", "Q_E0", "Q_V0")
EOS_SLOTS = {
    "linear_polynomial": ("Q_LP_C0", "Q_LP_C1", "Q_LP_C2", "Q_LP_C3", "Q_LP_C4", "Q_LP_C5", "Q_LP_C6"),
    "gruneisen": ("Q_GR_C", "Q_GR_S1", "Q_GR_S2", "Q_GR_S3", "Q_GR_GAMMA0", "Q_GR_A"),
    "tait": ("Q_TAIT_RHO_REF", "Q_TAIT_C0", "Q_TAIT_GAMMA", "Q_TAIT_PB", "Q_TAIT_B"),
    "ideal_gas": ("Q_IG_GAMMA",),
    "stiffened_gas": ("Q_SG_GAMMA", "Q_SG_PINF"),
    "jwl": ("Q_JWL_A", "Q_JWL_B", "Q_JWL_R1", "Q_JWL_R2", "Q_JWL_OMEGA"),
}
HISTORY_SLOTS = ("H_EPS", "H_BACK_XX", "H_BACK_YY", "H_BACK_ZZ", "H_BACK_XY", "H_BACK_YZ", "H_BACK_ZX",
                 "H_WP", "H_THICKNESS_STRAIN")
