"""The wall-function shear of `condition: wall_function` ghost walls (sph/walls.py, issue 18 item 3).

- friction_velocity solves the smooth-wall law: u_tau^2 = nu u / y in the viscous sublayer
  (y+ < 11.06), u/u_tau = ln(9.8 y+)/0.41 above it, to 1e-10 (Pope 2000, section 7.1);
- wall_shear acts on the first particle layer only (at the layer's middle y >= d/2), against the tangential velocity, with
  |a| = u_tau^2 / d, and puts the kinetic energy it takes into internal energy (a . v + de = 0);
  an inviscid fluid feels none.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from sphfem_cli.materials.slots import NPARAM, P_VISCOSITY
from sphfem_cli.sph.walls import friction_velocity, wall_shear


@pytest.mark.parametrize("u, y, nu", [(1e-4, 1e-3, 1e-6), (3.0, 2.5e-3, 1e-6), (0.5, 0.01, 1e-5)])
def test_friction_velocity_solves_the_law_of_the_wall(u, y, nu):
    ut = friction_velocity(u, y, nu)
    y_plus = y * ut / nu
    if y_plus <= 11.06:
        assert ut * ut == pytest.approx(nu * u / y, rel=1e-12)
    else:
        assert u / ut == pytest.approx(math.log(9.8 * y_plus) / 0.41, rel=1e-10)
    assert friction_velocity(0.0, y, nu) == 0.0 and friction_velocity(u, y, 0.0) == 0.0


def _shear(x, v, mu, spacing=0.005):
    n = len(x)
    params = np.zeros((1, NPARAM))
    params[0, P_VISCOSITY] = mu
    rho = np.full(n, 1000.0)
    m = rho * spacing ** 2
    acc, de = np.zeros((n, 2)), np.zeros(n)
    floor = np.array([[1.0, 0.0, 1.0]])  # y = 0, fluid above
    wall_shear(np.array(x, float), np.array(v, float), rho, m, np.zeros(n, np.int64), np.ones(n, np.bool_),
               params, floor, acc, de)
    return acc, de


def test_first_layer_only_against_the_slip_velocity_energy_to_heat():
    x = [[0.1, 0.0025], [0.2, 0.0075], [0.3, 0.0025], [0.4, 1e-9]]
    v = [[3.0, -0.2], [3.0, 0.0], [-1.0, 0.0], [1e-3, 0.0]]
    acc, de = _shear(x, v, mu=1e-3)
    assert np.all(acc[1] == 0.0) and de[1] == 0.0  # second layer: no wall shear
    assert acc[0, 1] == 0.0 and acc[0, 0] < 0.0 < acc[2, 0]  # tangential, against the slip
    ut = friction_velocity(3.0, 0.0025, 1e-6)
    assert -acc[0, 0] == pytest.approx(ut * ut / 0.005, rel=1e-12)
    # a particle pressed against the wall takes the shear at the layer's middle d/2, not at y -> 0
    assert -acc[3, 0] == pytest.approx(friction_velocity(1e-3, 0.0025, 1e-6) ** 2 / 0.005, rel=1e-12)
    power = np.sum(acc * np.array(v), axis=1) + de
    assert np.allclose(power, 0.0, atol=1e-12)
    acc0, de0 = _shear(x, v, mu=0.0)
    assert not acc0.any() and not de0.any()  # inviscid: no wall shear
