"""The solids' element pass of the initial state, in numpy: what ``fem.kernels.solid_element_forces``
computes for a zero step (dt = 0) of plane-strain and plane-stress quad4 elements at rest, without
loading numba.

``sphfem check`` needs the stable step of the initial state and nothing else of the kernels; at rest
(every nodal velocity zero) the rate of deformation d is zero, so the zero step leaves the stress,
history, energies and hourglass resultants as they are (zero stress at t = 0), the bulk viscosity
is q = 0 (tr d = 0 is not compression) and the element step is (paper eqs. 2.9-2.10,
``fem.geometry.stable_dt`` with Q = 0)

    dt_e = l / sqrt(c^2),   l = A / longest edge (``fem.geometry.quad4_char_length``),
    c = sqrt((K + 4 G / 3) / rho),   rho = rho0 / (A / A0)   (``materials.kernels.sound_speed``),
    c = sqrt(M / rho),  M = 4 G (K + G/3) / (K + 4 G/3)      (plane stress, ``plane_stress_sound_speed``;
                                                              the thickness is h0 at rest)

with the area A of ``fem.geometry.quad4_gradient``. Every operation is the kernel's, in the kernel's
order, so the arrays are bit-identical to the kernel's (tests/unit/test_at_rest_pass.py checks this
on every shipped plane-strain deck at rest, and on a plane-stress one). The pass applies only where
the kernel's answer is this simple: quad4, not axisymmetric, a zero step, zero velocities and zero stress, every
active element of an elastic, elastic-plastic or Johnson-Cook material without an equation of state,
and every element valid (A > 0) with a finite step. Anything else is the kernel's (``covers`` is
False) and so are all the messages of an invalid initial state.
"""
from __future__ import annotations

import numpy as np

from ..materials.ids import EOS_NONE, ELASTIC, ELASTIC_PLASTIC, JOHNSON_COOK
from .slots import PLANE_STRESS, SEC_FORMULATION
from ..materials.slots import P_EOS_TYPE, P_G, P_K, P_RHO0

AT_REST_TYPES = (ELASTIC, ELASTIC_PLASTIC, JOHNSON_COOK)


def at_rest_element_pass(x, v, conn, active, elem_mat, elem_sec, mat_type, mat_param, sec_param, vol0, dt, stress,
                         hg_force, f_elem, dt_elem, vol, q_visc) -> bool:
    """The zero step of the module docstring; returns False (and writes nothing) where it does not apply.

    Arguments as ``fem.kernels.solid_element_forces``; written when it applies: dt_elem (E,), vol (E,)
    and q_visc (E,) of the active elements, dt_elem = inf on inactive ones, and zero element forces
    (the kernel's are zeros of either sign; their sum at every node is +0 either way).
    """
    if dt != 0.0 or conn.shape[1] != 4 or x.shape[1] != 2 or np.any(v) or np.any(stress) or np.any(hg_force):
        return False
    act = np.flatnonzero(active)
    mats = elem_mat[act]
    p = mat_param[mats]
    if not (np.isin(mat_type[mats], AT_REST_TYPES).all() and (p[:, P_EOS_TYPE] == EOS_NONE).all()):
        return False
    xe = x[conn[act]]  # (A, 4, 2); the kernel's mid-step corners x - 0.5 dt v are x itself here
    area = 0.5 * ((xe[:, 2, 0] - xe[:, 0, 0]) * (xe[:, 3, 1] - xe[:, 1, 1])
                  + (xe[:, 1, 0] - xe[:, 3, 0]) * (xe[:, 2, 1] - xe[:, 0, 1]))
    if not (area > 0.0).all():
        return False
    rho = p[:, P_RHO0] / (area / vol0[act])  # the kernel's rel_volume (h/h0 = 1 at rest in plane stress)
    k, g = p[:, P_K], p[:, P_G]
    plane_stress = sec_param[elem_sec[act], SEC_FORMULATION] == PLANE_STRESS
    modulus = np.where(plane_stress, 4.0 * g * (k + g / 3.0) / (k + 4.0 * g / 3.0), k + 4.0 * g / 3.0)
    c = np.sqrt(modulus / rho)
    longest = np.zeros(len(act))
    for i in range(4):
        j = (i + 1) % 4
        longest = np.maximum(longest, np.sqrt((xe[:, j, 0] - xe[:, i, 0]) ** 2 + (xe[:, j, 1] - xe[:, i, 1]) ** 2))
    length = area / longest
    denominator = 0.0 + np.sqrt(0.0 * 0.0 + c * c)
    with np.errstate(divide="ignore", invalid="ignore"):
        dt_act = np.where(denominator <= 0.0, np.inf, length / denominator)
    if not (np.isfinite(dt_act).all() and (dt_act > 0.0).all()):
        return False
    dt_elem[:] = np.inf
    dt_elem[act] = dt_act
    vol[act] = area
    q_visc[act] = 0.0
    f_elem[act] = 0.0
    return True
