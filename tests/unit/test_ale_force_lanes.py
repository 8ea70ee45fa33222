"""The plane ALE force kernel's vectorised passes (ale/force_lanes.py) give the general path's bits.

One ideal or stiffened gas takes ``gas_block``; the same gas as the first of two materials, the second
absent everywhere (volume fraction 0), takes the general ``_mixture_pressure`` loop, whose sums over the
second material add nothing: the forces, pressures, bulk moduli, viscosity and stable step must agree to
the bit (assert_array_equal), on a randomly perturbed mesh with random velocities (compression and
expansion both present), voids and a pressure cut-off included.
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.ale import AleOptions, AleSystem
from sphfem_cli.ale.force_lanes import one_gas
from sphfem_cli.materials.tables import gas_row
from sphfem_cli.model.mesh import box_mesh


def _pair(row, seed, cutoff=None):
    """(one-material system, two-material system whose second material is absent), same state."""
    rng = np.random.default_rng(seed)
    mesh = box_mesh([0.0, 0.0], [1.0, 1.0], divisions=[13, 11])  # 143 elements: a block of 128 and a rest
    nodes = mesh.nodes + 0.02 * rng.standard_normal(mesh.nodes.shape)
    conn = mesh.elements
    n_elem = len(conn)
    rho = 1.0 + 0.3 * rng.random(n_elem)
    p = 1e5 * (1.0 + rng.random(n_elem))
    v = 20.0 * rng.standard_normal(nodes.shape)
    opt = AleOptions(pressure_cutoff=cutoff)
    one = AleSystem(nodes, conn, [row], np.ones((n_elem, 1)), rho[:, None], pressure=p[:, None], velocity=v,
                    options=opt)
    two = AleSystem(nodes, conn, [row, gas_row(1.4, 1.2)], np.stack([np.ones(n_elem), np.zeros(n_elem)], 1),
                    np.stack([rho, np.full(n_elem, 1.2)], 1), pressure=np.stack([p, p], 1), velocity=v, options=opt)
    lag = 0.01 * rng.standard_normal(n_elem) * one.ener_m[:, 0] / one.mass_m[:, 0]
    for ale in (one, two):
        ale.e_lag[:, 0] = lag
        ale.mass_m[:5, 0] = 0.0  # void elements: no pressure, no sound speed
        ale.ener_m[:5, 0] = 0.0
    return one, two


@pytest.mark.parametrize("row", [gas_row(1.4, 1.0), gas_row(4.4, 1000.0, 6e8)], ids=["ideal", "stiffened"])
@pytest.mark.parametrize("cutoff", [None, -1e4])
def test_one_gas_pass_gives_the_general_paths_bits(row, cutoff):
    one, two = _pair(row, seed=4, cutoff=cutoff)
    assert one_gas(one.mat_eos, one.mat_q, one.mat_rho0)[0]
    assert not one_gas(two.mat_eos, two.mat_q, two.mat_rho0)[0]
    one._forces()
    two._forces()
    np.testing.assert_array_equal(one.e_lag[:, 0], two.e_lag[:, 0])
    for name in ("f_elem", "q_elem", "dt_elem"):
        np.testing.assert_array_equal(getattr(one, name), getattr(two, name), err_msg=name)
    for name in ("pres_m", "bulk_m"):
        np.testing.assert_array_equal(getattr(one, name)[:, 0], getattr(two, name)[:, 0], err_msg=name)
    assert np.all(one.pres_m[:5] == 0.0) and np.all(one.bulk_m[:5] == 0.0)
    assert np.any(one.q_elem > 0.0) and np.any(one.q_elem == 0.0)  # compression and expansion both present
