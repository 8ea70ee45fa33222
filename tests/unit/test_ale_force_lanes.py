"""The plane ALE force kernel's vectorised passes (ale/force_lanes.py) give the general path's bits.

One ideal or stiffened gas takes ``gas_block``; the same gas as the first of two materials, the second (an
ideal gas) absent everywhere (volume fraction 0), takes ``two_gas_block`` (two gases, issue 17), and with a
third material absent too the general ``_mixture_pressure`` loop, whose sums over the absent materials add
nothing: the forces, pressures, bulk moduli, viscosity and stable step must agree to the bit
(assert_array_equal), on a randomly perturbed mesh with random velocities (compression and expansion both
present), voids and a pressure cut-off included; ``two_gas_block`` also on pure and mixed cells of water and
air against the general loop (the three-material system).
"""
from __future__ import annotations

import numpy as np
import pytest

from conftest import distorted_box
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


def _two_gases(seed, cutoff=None, geometry="plane"):
    """(two-gas system, the same with a third material absent everywhere): water (stiffened) and air (ideal) with
    pure and mixed cells at random fractions, void cells (no mass) and random e_lag; the three-material system
    takes the general ``_mixture_pressure`` loop, whose sums over the absent third material add nothing."""
    rng = np.random.default_rng(seed)
    axi = geometry == "ring"
    nodes, conn = distorted_box(rng, geometry)  # 143 quads (a block of 128 and a rest) or 210 hex8 (blocks of 64)
    n_elem = len(conn)
    f = np.where(rng.random(n_elem) < 0.5, rng.integers(0, 2, n_elem).astype(float), rng.random(n_elem))
    rho = np.stack([1000.0 * (1.0 + 0.01 * rng.random(n_elem)), 1.2 * (1.0 + 0.3 * rng.random(n_elem))], 1)
    p = np.stack([1e5 * (1.0 + rng.random(n_elem))] * 2, 1)
    v = 20.0 * rng.standard_normal(nodes.shape)
    opt = AleOptions(pressure_cutoff=cutoff)
    rows = [gas_row(4.4, 1000.0, 6e8), gas_row(1.4, 1.2)]
    two = AleSystem(nodes, conn, rows, np.stack([f, 1 - f], 1), rho, pressure=p, velocity=v, options=opt,
                    axisymmetric=axi)
    three = AleSystem(nodes, conn, rows + [gas_row(1.67, 0.2)], np.stack([f, 1 - f, np.zeros(n_elem)], 1),
                      np.concatenate([rho, np.full((n_elem, 1), 0.2)], 1), pressure=np.concatenate([p, p[:, :1]], 1),
                      velocity=v, options=opt, axisymmetric=axi)
    lag = 0.01 * rng.standard_normal((n_elem, 2)) * two.ener_m / np.maximum(two.mass_m, 1e-300)
    for ale in (two, three):
        ale.e_lag[:, :2] = lag
        ale.mass_m[:5, :2] = 0.0  # void elements
        ale.ener_m[:5, :2] = 0.0
    return two, three


@pytest.mark.parametrize("geometry", ["plane", "ring", "hex8"])
@pytest.mark.parametrize("cutoff", [None, -1e4])
@pytest.mark.parametrize("seed", [0, 1])
def test_two_gas_pass_gives_the_general_paths_bits(seed, cutoff, geometry):
    """``force_lanes.two_gas_block`` (two ideal or stiffened gases, pure and mixed cells together) against the
    general ``_mixture_pressure`` loop, in the plane, r-z and hex8 force kernels (``lagrange.state_block``):
    forces, pressures, bulk moduli, viscosity and stable step to the bit."""
    two, three = _two_gases(seed, cutoff, geometry)
    mixed = (two.vol_m > 0.0).all(axis=1)
    assert mixed.sum() > 30 and (~mixed).sum() > 30  # mixed and pure cells both present
    two._forces()
    three._forces()
    for name in ("f_elem", "q_elem", "dt_elem"):
        np.testing.assert_array_equal(getattr(two, name), getattr(three, name), err_msg=name)
    for name in ("pres_m", "bulk_m"):
        np.testing.assert_array_equal(getattr(two, name), getattr(three, name)[:, :2], err_msg=name)
    assert np.all(two.pres_m[:5] == 0.0) and np.any(two.q_elem > 0.0)
