"""ALE inflow boundary: water entering a channel at a prescribed state (AleSystem.set_inflow).

Quasi-1D channel 1 m x 1 cell, 50 elements, slip walls top and bottom. The left side is an inflow
of stiffened-gas water (gamma 4.4, p_inf 6e8 Pa, rho 1000 kg/m^3, p 1e5 Pa) at u = 10 m/s, t = 0.05 s:
the front should stand at u t = 0.5 m and the water mass be rho u A t = 10 kg/m (A = one cell, 0.02 m).

- into void (pressure cut-off 0, so that the water does not pull on the void), right end a wall;
- into air at 1e5 Pa (ideal gas, 1.2 kg/m^3), right end transmitting.

Measured: void: front 0.50095 m (speed between t/2 and t 10.016 m/s), mass rho u A t to 4e-16;
air: front 0.499995 m (9.9999 m/s), mass to 4e-12; the booked inflow (totals()["outflow"],
negative) equals the mass inside to 1e-15 relative.
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.ale import AleOptions, AleSystem
from sphfem_cli.materials.tables import gas_row
from sphfem_cli.model.mesh import box_mesh

N, L, U, T_END, RHO = 50, 1.0, 10.0, 0.05, 1000.0


def _channel(case: str):
    h = L / N
    mesh = box_mesh([0.0, 0.0], [L, h], divisions=[N, 1])
    nodes, conn = mesh.nodes, mesh.elements
    water = gas_row(4.4, RHO, 6e8)
    fr = np.tile([1.0, 0.0], (N, 1))
    if case == "void":
        ale = AleSystem(nodes, conn, [None, water], fr, [0.0, RHO], pressure=[0.0, 1e5],
                        options=AleOptions(pressure_cutoff=0.0))
    else:
        ale = AleSystem(nodes, conn, [gas_row(1.4, 1.2), water], fr, [1.2, RHO], pressure=[1e5, 1e5])
    ale.set_inflow(np.flatnonzero(nodes[:, 0] < 1e-12), 1, (U, 0.0), pressure=1e5)
    for y in (0.0, h):
        ale.set_slip(np.flatnonzero(np.abs(nodes[:, 1] - y) < 1e-12), (0.0, 1.0))
    right = np.flatnonzero(nodes[:, 0] > L - 1e-12)
    if case == "void":
        ale.set_slip(right, (1.0, 0.0))
    else:
        ale.set_transmit(right)
    return ale, h


def _run(ale: AleSystem, h: float, t_end: float) -> None:
    # void has no sound speed: the step is also held below half a cell crossing at the inflow speed
    while ale.time < t_end * (1.0 - 1e-12):
        ale.step(min(ale.stable_dt(0.5), 0.5 * h / U, t_end - ale.time))


@pytest.mark.parametrize("case", ["void", "air"])
def test_inflow_front_speed_and_mass(case):
    ale, h = _channel(case)
    _run(ale, h, 0.5 * T_END)
    front_half = ale.fractions()[:, 1].sum() * h
    _run(ale, h, T_END)
    front = ale.fractions()[:, 1].sum() * h
    mass = ale.totals()["mass"][1]
    assert np.all(np.isfinite(ale.velocity))
    assert abs(front / (U * T_END) - 1.0) < 0.02
    assert abs((front - front_half) / (0.5 * T_END) / U - 1.0) < 0.03
    assert abs(mass / (RHO * U * h * T_END) - 1.0) < 0.01
    # every kilogram inside came through the inflow face and was booked there
    assert abs(-ale.totals()["outflow"][1] - mass) <= 1e-12 * mass
    # the inflow nodes hold the inflow velocity
    left = ale.x0[:, 0] < 1e-12
    np.testing.assert_allclose(ale.velocity[left], [[U, 0.0]] * int(left.sum()))
