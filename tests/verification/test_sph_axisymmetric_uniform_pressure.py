"""Axisymmetric SPH rates (sph/axisymmetric.py) under a uniform pressure: the pair sum with the images'
signed radii plus the hoop term must reduce exactly to the plane code's pressure sum.

For uniform p and rho the areal form's pair term with s_j (module docstring) is
-(p/rho) sum_j A_j (1 + x_j/r_i) grad_i W_ij; the hoop term (p/(rho r_i)) grad~r_i, with
grad~r_i = sum_j A_j (x_j - r_i) grad_i W_ij the kernel's estimate of grad r, turns it into
-(2 p/rho) sum_j A_j grad_i W_ij (the plane code's -sum_j m_j (p_i/rho_i^2 + p_j/rho_j^2) grad W with the
plane masses rho A_j), in both components, for any particle arrangement. Before issue 15's fix the hoop
term had only its radial component kappa_i = grad~r_i . e_r: the axial force then missed
-(p/(rho r_i)) grad~r_i . e_z, which is zero on a regular lattice but, near a support cut by a floor
without ghosts (a contact floor), grows with a particle's radial offset and as 1/r towards the axis
(the corner instability of the water column on a contact floor, test_sph_fem_axisymmetric).

Scene: a jittered lattice (0.2 dx) in [0, 0.3] x [0, 0.3], free on three sides and the axis a ghost
line, uniform rho and p, at rest, no gravity. The NumPy reference sums over the particles and their
mirror images (-r, z). Tolerance 1e-9 of the largest |a| (round-off of the kernel sums).
"""
from __future__ import annotations

import numpy as np

from sphfem_cli.sph import lattice, scenes
from sphfem_cli.sph.kernel_functions import CUBIC_SPLINE, kernel_f
from sphfem_cli.sph.options import SphOptions
from sphfem_cli.sph.system import SphSystem


def test_uniform_pressure_reduces_to_the_plane_sum():
    rng = np.random.default_rng(7)
    dx = 0.01
    x = lattice.box([0.0, 0.0], [0.3, 0.3], dx)
    x += rng.uniform(-0.2, 0.2, x.shape) * dx
    x[:, 0] = np.abs(x[:, 0])
    rho = np.full(len(x), 1001.0)  # uniform, compressed: p > 0
    opt = SphOptions(alpha=0.0, delta=0.0, axisymmetric=True)
    ps = SphSystem(x, np.zeros_like(x), scenes.ring_particles(x, dx, rho), rho, np.zeros(len(x), dtype=np.int64),
                   scenes.water(20.0), opt)
    ps.compute_rates()
    p = float(ps.p[0])
    assert p > 0.0 and np.allclose(ps.p, p, rtol=0.0, atol=0.0)
    area = ps.m / (2.0 * np.pi * ps.x[:, 0] * ps.rho)  # A_j, the meridian area
    pts = np.concatenate([ps.x, ps.x * np.array([-1.0, 1.0])])  # particles, then their axis images
    a_pts = np.concatenate([area, area])
    h_pts = np.concatenate([ps.h, ps.h])
    ref = np.zeros_like(ps.x)
    for i in range(len(ps.x)):
        d = ps.x[i] - pts
        r = np.linalg.norm(d, axis=1)
        hij = 0.5 * (ps.h[i] + h_pts)
        near = (r < 2.0 * hij) & (r > 0.0)
        f = np.array([kernel_f(CUBIC_SPLINE, 2, rr, hh) for rr, hh in zip(r[near], hij[near])])
        ref[i] = -2.0 * p / rho[0] * np.sum((a_pts[near] * f)[:, None] * d[near], axis=0)
    scale = float(np.abs(ref).max())
    err = np.abs(ps.acc - ref).max(axis=0)
    near_axis = ps.x[:, 0] < 2.0 * dx
    print(f"max |a| {scale:.4g}, error r {err[0] / scale:.2e}, z {err[1] / scale:.2e}; "
          f"axial |a| next to the axis {np.abs(ps.acc[near_axis, 1]).max():.4g}")
    assert err[0] < 1e-9 * scale, err[0]
    assert err[1] < 1e-9 * scale, err[1]
