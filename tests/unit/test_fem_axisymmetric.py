"""The axisymmetric quad4 kernel (fem/axisymmetric.py) on single distorted elements, against NumPy.

- power identity: sum_I f_I . v_I = -V sigma : d for any stress, velocity and shape, with
  V = 2 pi r_c A and d = (d_rr, d_zz, d_tt = mean v_r / r_c, d_rz): the discrete internal work the
  energy column books is exactly the work of the nodal forces (1e-12 relative);
- no net axial force for any stress (axial momentum), and the radial resultant -2 pi A sigma_tt
  (the hoop stress pulling the ring towards the axis);
- a linear velocity field gives its exact rate of deformation, with d_tt = v_r(centre) / r_c;
- ring volumes 2 pi r_c A exact (Pappus) for rectangles;
- an axisymmetric deck writes zz as the hoop component; a plane deck imports no axisymmetric code.
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.fem.axisymmetric import axisymmetric_element_forces
from sphfem_cli.model.mesh import ring_volumes
from sphfem_cli.fem.geometry import quad4_gradient
from sphfem_cli.fem.kernels import NSEC
from sphfem_cli.materials.slots import NHIST, NPARAM, P_G, P_K

RNG = np.random.default_rng(15)


def _elastic_row():
    from sphfem_cli.deck.schema import Elastic
    from sphfem_cli.materials.tables import pack_material

    kind, row = pack_material(Elastic(type="elastic", density=7850.0, youngs_modulus=2.0e11, poisson_ratio=0.3))
    assert kind == 0 and row.shape == (NPARAM,)  # ELASTIC
    return row


def _element(on_axis: bool):
    x = np.array([[0.0, 0.0], [1.0, 0.0], [1.1, 0.9], [0.0, 1.0]]) * 0.3
    x += 0.05 * RNG.uniform(-1, 1, size=(4, 2))
    x[:, 0] += 0.0 if on_axis else 0.5
    if on_axis:
        x[[0, 3], 0] = 0.0
    return x


def _run(x, v, stress):
    """One zero-length step (dt = 0: the stress stays, forces at x) of one elastic element, no hourglass."""
    conn = np.array([[0, 1, 2, 3]])
    mat_type = np.zeros(1, dtype=np.int64)  # ELASTIC is type 0 in materials.kernels
    f_elem = np.zeros((1, 4, 2))
    vol = np.zeros(1)
    stress = stress.reshape(1, 6).copy()
    axisymmetric_element_forces(
        x, v, conn, np.ones(1, dtype=np.bool_), np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.int64),
        mat_type, _elastic_row()[None, :], np.zeros((1, NSEC)), ring_volumes(x, conn), 0.0, stress,
        np.zeros((1, NHIST)), np.zeros(1), np.zeros(1), np.zeros((1, 1, 2)), f_elem, np.zeros(1), vol, np.zeros(1))
    return f_elem[0], vol[0], stress[0]


def _rate(x, v):
    b = np.empty((2, 4))
    area = quad4_gradient(x, b)
    rc = x[:, 0].mean()
    lrr, lrz, lzr, lzz = v[:, 0] @ b[0], v[:, 0] @ b[1], v[:, 1] @ b[0], v[:, 1] @ b[1]
    return np.array([lrr, lzz, v[:, 0].mean() / rc, 0.5 * (lrz + lzr), 0.0, 0.0]), 2 * np.pi * rc * area, area


@pytest.mark.parametrize("on_axis", [False, True])
def test_power_identity_and_resultants(on_axis):
    for _ in range(10):
        x = _element(on_axis)
        v = RNG.normal(size=(4, 2))
        if on_axis:
            v[[0, 3], 0] = 0.0
        sig = RNG.normal(size=6) * 1e8
        sig[4:] = 0.0
        f, volume, s = _run(x, v, sig)
        d, v_ring, area = _rate(x, v)
        assert volume == pytest.approx(v_ring, rel=1e-14)
        power = -volume * (s[0] * d[0] + s[1] * d[1] + s[2] * d[2] + 2 * s[3] * d[3])
        assert np.sum(f * v) == pytest.approx(power, rel=1e-12)
        assert abs(f[:, 1].sum()) <= 1e-12 * np.abs(f).max()
        assert f[:, 0].sum() == pytest.approx(-2 * np.pi * area * s[2], rel=1e-12)


def test_linear_field_gives_its_exact_rate():
    x = _element(False)
    grad = np.array([[1.0, 0.4], [-0.7, 2.0]])  # v = grad @ (r, z)
    v = x @ grad.T
    d, _, _ = _rate(x, v)
    rc, zc = x[:, 0].mean(), x[:, 1].mean()
    assert d[:4] == pytest.approx([grad[0, 0], grad[1, 1], (grad[0, 0] * rc + grad[0, 1] * zc) / rc,
                                   0.5 * (grad[0, 1] + grad[1, 0])], rel=1e-12)
    # and the kernel books exactly this rate: an elastic step dt from zero stress gives C : d dt
    conn = np.array([[0, 1, 2, 3]])
    stress = np.zeros((1, 6))
    dt = 1e-9
    axisymmetric_element_forces(
        x + 0.5 * dt * v, v, conn, np.ones(1, dtype=np.bool_), np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.int64),
        np.zeros(1, dtype=np.int64), _elastic_row()[None, :], np.zeros((1, NSEC)), ring_volumes(x, conn), dt, stress,
        np.zeros((1, NHIST)), np.zeros(1), np.zeros(1), np.zeros((1, 1, 2)), np.zeros((1, 4, 2)), np.zeros(1),
        np.zeros(1), np.zeros(1))
    p = _elastic_row()
    lam = p[P_K] - 2 * p[P_G] / 3
    tr = d[0] + d[1] + d[2]
    expected = np.array([lam * tr + 2 * p[P_G] * d[0], lam * tr + 2 * p[P_G] * d[1], lam * tr + 2 * p[P_G] * d[2],
                         2 * p[P_G] * d[3]]) * dt
    assert stress[0, :4] == pytest.approx(expected, rel=1e-6, abs=1e-9 * np.abs(expected).max())


def test_ring_volumes_of_rectangles_are_exact():
    x = np.array([[0.0, 0.0], [0.5, 0.0], [0.5, 1.0], [0.0, 1.0], [1.5, 0.0], [1.5, 1.0]])
    conn = np.array([[0, 1, 2, 3], [1, 4, 5, 2]])
    assert ring_volumes(x, conn) == pytest.approx([np.pi * 0.25, np.pi * (1.5 ** 2 - 0.25)], rel=1e-14)
