"""The solids' element pass of the initial state, in numpy: what ``fem.kernels.solid_element_forces``
computes for a zero step (dt = 0) of plane-strain and plane-stress quad4 and of hex8 elements at rest,
and ``fem.axisymmetric.axisymmetric_element_forces`` for axisymmetric quad4 at rest, without loading numba.

``sphfem check`` needs the stable step of the initial state and nothing else of the kernels; at rest
(every nodal velocity zero) the rate of deformation d is zero, so the zero step leaves the stress,
history, energies and hourglass resultants as they are (zero stress at t = 0), the bulk viscosity
is q = 0 (tr d = 0 is not compression) and the element step is (paper eqs. 2.9-2.10,
``fem.geometry.stable_dt`` with Q = 0)

    dt_e = l / sqrt(c^2),   c = sqrt((K + 4 G / 3) / rho),   rho = rho0 / (V / V0)
                                                             (``materials.kernels.sound_speed``),
    quad4: l = A / longest edge (``fem.geometry.quad4_char_length``), A of ``fem.geometry.quad4_gradient``;
           plane stress c = sqrt(M / rho), M = 4 G (K + G/3) / (K + 4 G/3) (``plane_stress_sound_speed``;
           the thickness is h0 at rest);
    hex8:  l = V / largest face area (``fem.geometry.hex8_char_length``: the face area half the norm of
           its diagonals' cross product, the largest squared norm found first), V of
           ``fem.geometry.hex8_gradient_faces`` (the kernel's hex8 path, ``fem.kernels._hex8_elements``):
           12 V = sum_I x_I g_I, g_I the x component of the sum of (x_a + x_b) x (x_b + x_c) over
           node I's three faces;
    axisymmetric quad4: V = 2 pi r_c A (r_c the mean corner radius), l = A / longest edge times
           sqrt(|b|^2 / (|b|^2 + 1/(4 r_c^2))), b the plane mean gradient (the hoop term's part of the
           gradient norm; ``fem.axisymmetric``), c = sqrt((K + 4 G / 3) / rho), valid where A > 0 and r_c > 0.

Every operation is the kernel's, in the kernel's order, so the arrays are bit-identical to the kernel's
(tests/unit/test_at_rest_pass.py checks this on every shipped deck at rest that the pass covers, and on
a plane-stress one). The pass applies only where the kernel's answer is this simple: quad4 (plane or
axisymmetric) or hex8, a zero step, zero velocities and zero stress, every active element of an elastic,
elastic-plastic or Johnson-Cook material without an equation of state, and every element valid (V > 0)
with a finite step. Anything else is the kernel's (``covers`` is False) and so are all the messages of an
invalid initial state.
"""
from __future__ import annotations

import numpy as np

from ..materials.ids import EOS_NONE, ELASTIC, ELASTIC_PLASTIC, JOHNSON_COOK
from .tables import HEX_FACES
from .slots import PLANE_STRESS, SEC_FORMULATION
from ..materials.slots import P_EOS_TYPE, P_G, P_K, P_RHO0

AT_REST_TYPES = (ELASTIC, ELASTIC_PLASTIC, JOHNSON_COOK)
TWO_PI = 2.0 * np.pi  # fem.axisymmetric.TWO_PI

# ``fem.geometry.hex8_gradient_faces``: per node I, its three faces' edge pairs (a + b, b + c) as
# ((j, k), (k, l)) node pairs, in that function's order (the x component of dV/dx_I is all the volume needs)
_HEX_NODE_FACES = (
    (((2, 3), (1, 2)), ((1, 5), (4, 5)), ((4, 7), (3, 7))),
    (((0, 3), (2, 3)), ((4, 5), (0, 4)), ((2, 6), (5, 6))),
    (((0, 1), (0, 3)), ((5, 6), (1, 5)), ((3, 7), (6, 7))),
    (((1, 2), (0, 1)), ((6, 7), (2, 6)), ((0, 4), (4, 7))),
    (((5, 6), (6, 7)), ((0, 1), (1, 5)), ((3, 7), (0, 3))),
    (((6, 7), (4, 7)), ((0, 4), (0, 1)), ((1, 2), (2, 6))),
    (((4, 7), (4, 5)), ((1, 5), (1, 2)), ((2, 3), (3, 7))),
    (((4, 5), (5, 6)), ((2, 6), (2, 3)), ((0, 3), (0, 4))),
)


def quad4_area(xe):
    """``fem.geometry.quad4_gradient``'s area of the quads xe (E, 4, 2)."""
    return 0.5 * ((xe[:, 2, 0] - xe[:, 0, 0]) * (xe[:, 3, 1] - xe[:, 1, 1])
                  + (xe[:, 1, 0] - xe[:, 3, 0]) * (xe[:, 2, 1] - xe[:, 0, 1]))


def quad4_char_length(xe, area):
    """``fem.geometry.quad4_char_length``: the area over the longest edge, (E,)."""
    longest = np.zeros(len(xe))
    for i in range(4):
        j = (i + 1) % 4
        longest = np.maximum(longest, np.sqrt((xe[:, j, 0] - xe[:, i, 0]) ** 2 + (xe[:, j, 1] - xe[:, i, 1]) ** 2))
    return area / longest


def hex8_volume_faces(xe):
    """``fem.geometry.hex8_gradient_faces``'s volume of the hexahedra xe (E, 8, 3): total * (1/12), total =
    x_0 g_0 + ... + x_7 g_7 summed in node order, g_I = sum over I's faces of the x component of
    (x_a + x_b) x (x_b + x_c), each cross product (p_y q_z - p_z q_y) and the three added left to right."""
    y = [xe[:, a, 1] for a in range(8)]
    z = [xe[:, a, 2] for a in range(8)]
    total = None
    for i, faces in enumerate(_HEX_NODE_FACES):
        g = None
        for (j, k), (m, n) in faces:
            term = (y[j] + y[k]) * (z[m] + z[n]) - (z[j] + z[k]) * (y[m] + y[n])
            g = term if g is None else g + term
        total = xe[:, i, 0] * g if total is None else total + xe[:, i, 0] * g
    return total, total * (1.0 / 12.0)


def hex8_char_length(xe, volume):
    """``fem.geometry.hex8_char_length``: V / (sqrt(largest |(x_c - x_a) x (x_d - x_b)|^2) / 2) over HEX_FACES."""
    largest = np.zeros(len(xe))
    for a, b, c, d in HEX_FACES:
        p = xe[:, c] - xe[:, a]
        q = xe[:, d] - xe[:, b]
        cx = p[:, 1] * q[:, 2] - p[:, 2] * q[:, 1]
        cy = p[:, 2] * q[:, 0] - p[:, 0] * q[:, 2]
        cz = p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]
        largest = np.maximum(largest, cx * cx + cy * cy + cz * cz)
    return volume / (0.5 * np.sqrt(largest))


def quad4_ring(xe, area):
    """``fem.axisymmetric.axisymmetric_element_forces``' ring of the quads xe (E, 4, 2) (x = r) at rest: (r_c, one-point
    ring volume 2 pi r_c A, the hoop factor sqrt(|b|^2 / (|b|^2 + 1/(4 r_c^2))) of its stable step), b the mean
    gradient of ``fem.geometry.quad4_gradient`` (b_x = (y_{I+1} - y_{I-1}) / 2A, b_y = (x_{I-1} - x_{I+1}) / 2A) and
    |b|^2 summed over b_x then b_y, corner order."""
    rc = 0.0
    for a in range(4):
        rc = rc + 0.25 * xe[:, a, 0]
    inv = 0.5 / area
    bb = 0.0
    for k, sign in ((1, 1), (0, -1)):  # b_x from y, b_y from x (reversed)
        for i in range(4):
            nxt, prv = (i + 1) % 4, (i + 3) % 4
            b = (xe[:, nxt, k] - xe[:, prv, k]) * inv if sign > 0 else (xe[:, prv, k] - xe[:, nxt, k]) * inv
            bb = bb + b * b
    hoop_g = 0.25 / (rc * rc)
    return rc, TWO_PI * rc * area, np.sqrt(bb / (bb + hoop_g))


def at_rest_element_pass(x, v, conn, active, elem_mat, elem_sec, mat_type, mat_param, sec_param, vol0, dt, stress,
                         hg_force, f_elem, dt_elem, vol, q_visc, axisymmetric: bool = False) -> bool:
    """The zero step of the module docstring; returns False (and writes nothing) where it does not apply.

    Arguments as ``fem.kernels.solid_element_forces`` (axisymmetric: ``fem.axisymmetric``'s kernel); written when it
    applies: dt_elem (E,), vol (E,) and q_visc (E,) of the active elements, dt_elem = inf on inactive ones, and zero
    element forces (the kernel's are zeros of either sign; their sum at every node is +0 either way).
    """
    npe, dim = conn.shape[1], x.shape[1]
    if dt != 0.0 or (npe, dim) not in ((4, 2), (8, 3)) or np.any(v) or np.any(stress) or np.any(hg_force):
        return False
    act = np.flatnonzero(active)
    mats = elem_mat[act]
    p = mat_param[mats]
    if not (np.isin(mat_type[mats], AT_REST_TYPES).all() and (p[:, P_EOS_TYPE] == EOS_NONE).all()):
        return False
    xe = x[conn[act]]  # (A, npe, dim); the kernel's mid-step corners x - 0.5 dt v are x itself here
    if dim == 2:
        area = volume = quad4_area(xe)
        valid = area > 0.0
        if axisymmetric:
            with np.errstate(divide="ignore", invalid="ignore"):
                rc, volume, hoop = quad4_ring(xe, area)
            valid &= rc > 0.0
    else:
        total, volume = hex8_volume_faces(xe)
        valid = total > 0.0
    if not (valid.all() and (volume > 0.0).all()):
        return False
    rho = p[:, P_RHO0] / (volume / vol0[act])  # the kernel's rel_volume (h/h0 = 1 at rest in plane stress)
    k, g = p[:, P_K], p[:, P_G]
    modulus = k + 4.0 * g / 3.0
    if dim == 2 and not axisymmetric:
        plane_stress = sec_param[elem_sec[act], SEC_FORMULATION] == PLANE_STRESS
        modulus = np.where(plane_stress, 4.0 * g * (k + g / 3.0) / (k + 4.0 * g / 3.0), modulus)
    c = np.sqrt(modulus / rho)
    length = quad4_char_length(xe, area) if dim == 2 else hex8_char_length(xe, volume)
    if axisymmetric:
        length = length * hoop
    denominator = 0.0 + np.sqrt(0.0 * 0.0 + c * c)
    with np.errstate(divide="ignore", invalid="ignore"):
        dt_act = np.where(denominator <= 0.0, np.inf, length / denominator)
    if not (np.isfinite(dt_act).all() and (dt_act > 0.0).all()):
        return False
    dt_elem[:] = np.inf
    dt_elem[act] = dt_act
    vol[act] = volume
    q_visc[act] = 0.0
    f_elem[act] = 0.0
    return True
