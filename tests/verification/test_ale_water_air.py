"""ALE water-air shock tube (Saurel & Abgrall 1999), two materials with a mixed-cell closure.

Reference: ../shared/reference/README.md: stiffened-gas water (gamma 4.4, p_inf 6e8 Pa,
rho 1000, p 1e9 Pa) for x < 0.7 m, ideal-gas air (gamma 1.4, rho 50, p 1e5 Pa), t = 240 us:
p* = 1.4190e7 Pa, u* = 482.61 m/s, interface at 0.8158 m, air shock at 0.8401 m.
500 x 1 quad4, slip walls, van Leer, SLIC interface, pressure-relaxation closure, CFL 0.5.
Measured: plateau p within 0.2 %, u within 0.03 %; interface cells p and u within 0.2 %.
"""
from __future__ import annotations

import functools
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from ale_cases import gas_row, run_to, shock_tube  # noqa: E402

from sphfem_cli.ale import AleOptions  # noqa: E402

P_STAR = 1.4190e7
U_STAR = 482.61


@functools.lru_cache(maxsize=None)
def _run(n=500, closure="relax"):
    water = gas_row(4.4, 1000.0, 6e8)
    air = gas_row(1.4, 50.0)
    ale = shock_tube(n, 1.0, 0.7, (water, 1000.0, 1e9), (air, 50.0, 1e5), True, AleOptions(closure=closure))
    return run_to(ale, 240e-6)


def test_water_air_star_state():
    ale = _run()
    xc = ale.centroids()[:, 0]
    p = ale.pressure(mixture=True)
    u = ale.element_velocity()[:, 0]
    star = (xc > 0.75) & (xc < 0.83)
    assert np.max(np.abs(p[star] / P_STAR - 1.0)) < 0.02
    assert np.max(np.abs(u[star] / U_STAR - 1.0)) < 0.02


def test_water_air_interface_position_and_no_oscillation():
    ale = _run()
    xc = ale.centroids()[:, 0]
    phi_water = ale.fractions()[:, 0]
    h = xc[1] - xc[0]
    # interface: total water volume gives its position (water fills x < interface)
    x_int = phi_water.sum() * h
    assert abs(x_int - 0.8158) < 2 * h
    near = np.abs(xc - x_int) < 5 * h
    p = ale.pressure(mixture=True)
    u = ale.element_velocity()[:, 0]
    assert np.max(np.abs(p[near] / P_STAR - 1.0)) < 0.01
    assert np.max(np.abs(u[near] / U_STAR - 1.0)) < 0.01
    # the interface stays sharp: at most two mixed cells
    assert np.count_nonzero((phi_water > 1e-6) & (phi_water < 1 - 1e-6)) <= 2


def test_water_air_conservation():
    ale = _run()
    tot = ale.totals()
    np.testing.assert_allclose(tot["mass"], [0.7 * 1000.0 * 0.002, 0.3 * 50.0 * 0.002], rtol=1e-12)
    e0 = 0.002 * (0.7 * (1e9 + 4.4 * 6e8) / 3.4 + 0.3 * 1e5 / 0.4)
    assert abs(tot["total"] / e0 - 1.0) < 1e-10
    scale = np.abs(tot["momentum"]).max()
    np.testing.assert_allclose(tot["momentum"], tot["wall_impulse"], rtol=0, atol=1e-10 * scale)
