"""The delta-plus density diffusion (sph/diffusion.py, Antuono et al. 2010): zero for a linear density
field also where the kernel is truncated, where the Molteni-Colagrossi term is not (issue 12: the
particles next to a structure in penalty contact have no points on its side)."""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.sph import SphOptions, SphSystem, lattice, scenes

C0 = 20.0
DELTA = 0.1


def linear_density_block(dim, form, seed=1):
    """A jittered block of water at rest, rho = rho_0 (1 + 0.01 (x + 2 y) / L): the continuity sum is 0 (v = 0),
    drho is the density diffusion alone. The block's faces truncate the kernel of their particles."""
    rng = np.random.default_rng(seed)
    dx, n_side = 0.1, {2: 12, 3: 6}[dim]
    x = lattice.box([0.0] * dim, [n_side * dx] * dim, dx) + rng.uniform(-0.15, 0.15, (n_side**dim, dim)) * dx
    mass, rho = lattice.lattice_particles(x, dx, 1000.0)
    grad = np.zeros(dim)
    grad[0], grad[1] = 1.0, 2.0
    rho = rho * (1.0 + 0.01 * (x @ grad) / (n_side * dx))
    ps = SphSystem(x, np.zeros_like(x), mass, rho, np.zeros(len(x), dtype=int), scenes.water(C0),
                   SphOptions(alpha=0.0, delta=DELTA, density_diffusion_form=form, reorder_every=0))
    return ps, 1000.0 * 0.01 * np.linalg.norm(grad) / (n_side * dx)


@pytest.mark.parametrize("dim", [2, 3])
def test_delta_plus_vanishes_for_a_linear_density_field(dim, single_thread):
    ps, grad_rho = linear_density_block(dim, "molteni_colagrossi")
    ps.compute_rates()
    mc = ps.drho.copy()
    ps, _ = linear_density_block(dim, "delta_plus")
    ps.compute_rates()
    # Molteni-Colagrossi at the truncated faces: of the order 2 delta c |grad rho| (module docstring),
    # independent of h; observed max |drho| / (2 delta c |grad rho|) 0.68 (2D), 0.61 (3D)
    scale = 2.0 * DELTA * C0 * grad_rho
    assert 0.3 < np.abs(mc).max() / scale < 1.5
    # delta-plus: zero to round-off (observed 1.8e-13 (2D), 9e-14 (3D) of the scale)
    assert np.abs(ps.drho).max() < 1e-9 * scale


def test_delta_plus_is_a_diffusion_of_the_nonlinear_part(single_thread):
    """A density bump in the interior diffuses with both forms: drho < 0 at its top, > 0 around it."""
    for form in ("molteni_colagrossi", "delta_plus"):
        ps, _ = linear_density_block(2, form)
        centre = np.argmin(np.linalg.norm(ps.x - ps.x.mean(axis=0), axis=1))
        ps.rho[centre] *= 1.001
        ps.compute_rates()
        near = np.linalg.norm(ps.x - ps.x[centre], axis=1) < 0.12
        near[centre] = False
        assert ps.drho[centre] < 0.0
        assert np.all(ps.drho[near] > 0.0)
