"""Renormalised continuity of explosive products (sph/expansion.py): exact divergence of a linear
velocity field whatever the particle volumes, where the plain sum under-estimates it in proportion
to the volume error (the cause of the underwater explosion's frozen SPH products)."""
from __future__ import annotations

import numpy as np
import pytest
from pydantic import TypeAdapter

from sphfem_cli.deck.schema.materials import EquationOfState, Material
from sphfem_cli.sph import SphOptions, SphSystem, lattice, material_table
from sphfem_cli.sph.expansion import renormalised_divergence

MAT = TypeAdapter(Material)
EOS = TypeAdapter(EquationOfState)


def tnt():
    return material_table([
        (MAT.validate_python({"type": "high_explosive", "density": 1630.0, "detonation_velocity": 6930.0,
                              "eos": "tnt"}),
         EOS.validate_python({"type": "jwl", "A": 3.712e11, "B": 3.231e9, "R1": 4.15, "R2": 0.95,
                              "omega": 0.30, "e0": 7.0e9})),
    ])


def expanding_block(dim, volume_factor, seed=3):
    """A jittered block of products moving with v = a (x - x0): div v = dim a. The densities are
    1/volume_factor of the lattice's, so that V_j = m/rho is volume_factor times the area per particle."""
    rng = np.random.default_rng(seed)
    dx, n_side = 0.001, {2: 10, 3: 5}[dim]
    x = lattice.box([0.0] * dim, [n_side * dx] * dim, dx) + rng.uniform(-0.15, 0.15, (n_side**dim, dim)) * dx
    a = 2.0e4
    v = a * (x - x.mean(axis=0))
    rho = np.full(len(x), 1630.0 / volume_factor)
    m = np.full(len(x), 1630.0 * dx**dim)
    ps = SphSystem(x, v, m, rho, np.zeros(len(x), dtype=int), tnt(), SphOptions(alpha=0.0, reorder_every=0))
    return ps, dim * a


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("volume_factor", [1.0, 0.5])
def test_products_divergence_is_exact_for_a_linear_field(dim, volume_factor, single_thread):
    ps, div = expanding_block(dim, volume_factor)
    ps.compute_rates()
    plain = -ps.drho / ps.rho  # no explosive: the plain continuity sum of fluid_rates
    ps.set_burn([([0.0] * dim, 0.0)])
    ps.compute_rates()
    renorm = -ps.drho / ps.rho
    np.testing.assert_allclose(renorm, div, rtol=1e-9)
    # the plain sum sees only the share of the kernel its (under-estimated) volumes fill
    interior = np.all(np.abs(ps.x - ps.x.mean(axis=0)) < 0.2 * np.ptp(ps.x, axis=0), axis=1)
    assert interior.any()
    assert np.all(np.abs(plain[interior] / div - volume_factor) < 0.15)


def test_renormalised_divergence_falls_back_where_the_moment_is_singular():
    a = np.zeros((3, 3))
    a[0, 0], a[1, 1] = 2.0, 4.0
    m = np.zeros((3, 3))
    assert renormalised_divergence(a, m, 2) == 6.0  # no neighbour: the plain sum
    m[0, 0] = 1.0  # rank one: scalar form tr A / (tr M / 2)
    assert renormalised_divergence(a, m, 2) == pytest.approx(12.0)
    m[1, 1] = 0.5
    assert renormalised_divergence(a, m, 2) == pytest.approx(2.0 + 8.0)
