"""SphSystem: conservation, time integration, walls, domain, external forces, lattices, 3D run."""
from __future__ import annotations

import math

import numpy as np
import pytest

from sphfem_cli.materials import kernels as mk
from sphfem_cli.sph import SphOptions, SphSystem, Wall, WallParticles, box_walls, lattice, scenes


def jittered_block(dim, n_side, dx=0.1, seed=0, speed=1.0, c0=20.0, **options):
    rng = np.random.default_rng(seed)
    x = lattice.box([0.0] * dim, [n_side * dx] * dim, dx) + rng.uniform(-0.15, 0.15, (n_side**dim, dim)) * dx
    mass, rho = lattice.lattice_particles(x, dx, 1000.0)
    rho = rho * (1.0 + rng.uniform(-0.01, 0.01, len(x)))
    v = rng.normal(0.0, speed, x.shape)
    return SphSystem(x, v, mass, rho, np.zeros(len(x), dtype=int), scenes.water(c0), SphOptions(**options))


@pytest.mark.parametrize("dim,n_side,steps", [(2, 14, 400), (3, 6, 60)])
def test_linear_momentum_conserved_to_round_off(dim, n_side, steps, single_thread):
    """No walls, no gravity, random velocities; viscosity, delta-SPH and XSPH on."""
    ps = jittered_block(dim, n_side, alpha=0.5, beta=1.0, delta=0.1, xsph=0.5)
    p0 = ps.momentum()
    scale = float(np.sum(ps.m[:, None] * np.abs(ps.v)))
    for _ in range(steps):
        ps.advance(0.5)
    assert ps.nsteps == steps
    assert np.abs(ps.momentum() - p0).max() <= 1e-13 * scale


def test_total_energy_conserved_by_the_rates_and_the_integrator(single_thread):
    """With Monaghan viscosity (heating e) but no diffusion terms, kinetic + internal energy is
    conserved up to the O(dt^2) integration error."""
    ps = jittered_block(2, 12, alpha=1.0, beta=2.0, speed=2.0)
    e0 = ps.energies()
    for _ in range(300):
        ps.advance(0.5)
    e1 = ps.energies()
    assert e1["internal"] > 0.01 * e0["kinetic"]  # the viscosity did heat the fluid
    assert abs(e1["total"] - e0["total"]) <= 1e-3 * e0["kinetic"]


def lone_particle(x, v, **options):
    x = np.atleast_2d(np.asarray(x, dtype=float))
    v = np.atleast_2d(np.asarray(v, dtype=float))
    return SphSystem(x, v, np.array([1.0]), np.array([1000.0]), np.array([0]), scenes.water(20.0),
                          SphOptions(**options))


def test_leapfrog_is_exact_under_constant_acceleration():
    g = np.array([0.3, -9.81])
    ps = lone_particle([0.0, 0.0], [1.0, 2.0], gravity=g)
    dts = [1e-3, 2e-3, 0.5e-3, 1.5e-3] * 25
    for dt in dts:
        ps.compute_rates()
        ps.step(dt)
    t = sum(dts)
    assert ps.time == pytest.approx(t)
    np.testing.assert_allclose(ps.x[0], np.array([1.0, 2.0]) * t + 0.5 * g * t * t, rtol=1e-12)
    ps.compute_rates()
    ps.step(1e-3)  # closes the previous kick: v at the old step is exact
    np.testing.assert_allclose(ps.v_half[0] - 0.5e-3 * g, np.array([1.0, 2.0]) + g * t, rtol=1e-12)


def test_external_force_is_applied_and_its_work_counted():
    ps = lone_particle([0.0, 0.0], [0.0, 0.0])
    f = np.array([2.0, -1.0])
    for _ in range(200):
        ps.compute_rates()
        ps.f_ext[0] = f
        ps.step(1e-3)
    t = 0.2
    np.testing.assert_allclose(ps.x[0], 0.5 * f * t * t, rtol=1e-12)
    assert ps.energies()["external_work"] == pytest.approx(ps.energies()["kinetic"], rel=1e-2)


def test_step_needs_fresh_rates():
    ps = lone_particle([0.0, 0.0], [0.0, 0.0])
    with pytest.raises(RuntimeError):
        ps.step(1e-3)
    ps.compute_rates()
    ps.step(1e-3)
    with pytest.raises(RuntimeError):
        ps.step(1e-3)


def test_particles_leaving_the_domain_are_deactivated_and_counted():
    x = np.array([[0.5, 0.5], [0.95, 0.5]])
    v = np.array([[0.0, 0.0], [100.0, 0.0]])
    ps = SphSystem(x, v, np.ones(2), np.full(2, 1000.0), np.zeros(2, dtype=int), scenes.water(20.0),
                        SphOptions(domain=([0.0, 0.0], [1.0, 1.0]), reorder_every=0))
    for _ in range(20):
        ps.advance(0.5, dt_max=1e-3)
    assert ps.lost == 1
    assert ps.lost_mass == 1.0
    assert list(ps.active) == [True, False]
    assert ps.energies()["kinetic"] == 0.0
    assert ps.energies()["lost"] == pytest.approx(0.5 * 100.0**2)
    assert ps.acc[1].tolist() == [0.0, 0.0]


def test_particle_behind_a_ghost_wall_is_mirrored_back_and_counted():
    ps = lone_particle([0.5, 0.001], [0.0, -50.0], walls=[Wall(1, 0.0, +1)])
    ps.compute_rates()
    ps.step(1e-4)
    assert ps.wall_crossings == 1
    assert ps.x[0, 1] == pytest.approx(0.004, rel=1e-2)  # 0.001 - 1e-4 * 50, mirrored
    assert ps.v[0, 1] > 0.0


def test_ghost_images_of_a_corner_particle():
    """A particle near two walls has three images: one per wall and the corner one. Ghosts carry
    the free-slip mirror velocity; their viscous factors give the no-slip one (reversed per wall)."""
    walls = box_walls([0.0, 0.0], [1.0, 1.0], ["left", "bottom"], "no_slip")
    ps = lone_particle([0.02, 0.03], [1.0, 2.0], walls=walls)
    ps.compute_rates()
    s = ps._sorted
    npts = len(s["perm"])
    is_ghost = s["perm"] >= 1
    ghosts = s["sx"][:2, :npts].T[is_ghost]
    vel = s["sd"][:2, :npts].T[is_ghost]
    order = np.lexsort(ghosts.T)
    np.testing.assert_allclose(ghosts[order], [[-0.02, -0.03], [0.02, -0.03], [-0.02, 0.03]])
    np.testing.assert_allclose(vel[order], [[-1.0, -2.0], [1.0, -2.0], [-1.0, 2.0]])
    viscous = (s["sd"][:2, :npts].T * s["svf"][:npts, :2])[is_ghost]
    np.testing.assert_allclose(viscous[order], [[1.0, 2.0], [-1.0, -2.0], [-1.0, -2.0]])
    assert s["friction_slots"].tolist() == np.flatnonzero(s["perm"] == 0).tolist()


def test_lattice_generators():
    dx = 0.05
    b = lattice.box([0.0, 0.0], [1.0, 0.5], dx)
    assert b.shape == (200, 2)
    assert b.min() == pytest.approx(dx / 2) and b[:, 0].max() == pytest.approx(1.0 - dx / 2)
    assert lattice.box([0, 0, 0], [0.2, 0.2, 0.1], dx).shape == (32, 3)
    c = lattice.circle([0.3, 0.2], 0.25, dx)
    assert len(c) == pytest.approx(math.pi * 0.25**2 / dx**2, rel=0.05)
    assert np.all(np.linalg.norm(c - [0.3, 0.2], axis=1) < 0.25)
    s = lattice.sphere([0.0, 0.0, 0.0], 0.3, dx)
    assert len(s) == pytest.approx(4 / 3 * math.pi * 0.3**3 / dx**3, rel=0.05)
    tri = lattice.polygon([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], dx)
    assert len(tri) == pytest.approx(0.5 / dx**2, rel=0.05)
    assert np.all(tri.sum(axis=1) < 1.0)
    m, rho = lattice.lattice_particles(b, dx, 1000.0)
    assert m[0] == pytest.approx(1000.0 * dx**2) and rho[0] == 1000.0
    w = lattice.box_wall_particles([0.0, 0.0], [1.0, 1.0], 0.1, 3, ["left", "right", "bottom"])
    assert len(w) == 3 * 10 * 2 + 3 * 16
    assert np.all((w[:, 0] < 0) | (w[:, 0] > 1) | (w[:, 1] < 0))


def test_hydrostatic_density_inverts_the_eos():
    table = scenes.water(30.0)
    x = np.array([[0.0, 0.0], [0.0, 0.5], [0.0, 1.0], [0.0, 1.5]])
    mat = np.zeros(4, dtype=int)
    rho = lattice.hydrostatic_density(x, table[1], mat, [0.0, -9.81], [0.0, 1.0])
    row = table[1][0]
    p = [mk.eos_pressure(int(row[mk.P_EOS_TYPE]), row[mk.EOS_OFFSET:], r / 1000.0, 0.0) for r in rho]
    np.testing.assert_allclose(p, [9810.0, 4905.0, 0.0, 0.0], atol=1e-6)


def test_dummy_wall_tank_holds_water(single_thread):
    """Adami et al. (2012) dummy particles around a small tank: after a short settling the water
    stays inside and the pressure near the floor is close to hydrostatic."""
    g, depth, dx = 9.81, 0.4, 0.02
    table = scenes.water(10.0 * math.sqrt(g * depth))
    x = lattice.box([0.0, 0.0], [0.4, depth], dx)
    mat = np.zeros(len(x), dtype=int)
    rho = lattice.hydrostatic_density(x, table[1], mat, [0.0, -g], [0.0, depth])
    mass, rho = lattice.lattice_particles(x, dx, rho)
    walls = WallParticles(lattice.box_wall_particles([0.0, 0.0], [0.4, 1.0], dx, 3, ["left", "right", "bottom"]), dx)
    ps = SphSystem(x, np.zeros_like(x), mass, rho, mat, table,
                        SphOptions(alpha=0.05, delta=0.1, gravity=[0.0, -g]), wall_particles=walls)
    ps.run(0.3)
    assert ps.x[:, 1].min() > 0.0 and ps.x[:, 0].min() > 0.0 and ps.x[:, 0].max() < 0.4
    assert np.abs(ps.v).max() < 0.05 * math.sqrt(g * depth)
    p = ps.interpolate([[0.2, 2 * dx]])[0]
    assert p == pytest.approx(1000.0 * g * (depth - 2 * dx), rel=0.05)


def test_small_3d_dam_break_runs(single_thread):
    ps = scenes.dam_break(a=0.3, dx=0.05, dim=3, depth=0.15, tank_length=1.0)
    assert ps.n == 6 * 12 * 3
    ps.run(0.05)
    assert np.all(np.isfinite(ps.x)) and ps.lost == 0
    assert ps.front(0) > 0.3 - 0.025 + 0.01
    assert ps.x[:, 1].min() >= 0.0 and ps.x[:, 2].min() >= 0.0 and ps.x[:, 2].max() <= 0.15


def test_interpolation_of_a_linear_field(single_thread):
    """Shepard-normalised interpolation reproduces a linear velocity field inside the fluid."""
    dx = 0.05
    x = lattice.box([0.0, 0.0], [1.0, 1.0], dx)
    mass, rho = lattice.lattice_particles(x, dx, 1000.0)
    v = np.stack([0.2 + 0.5 * x[:, 0] - 0.3 * x[:, 1], np.zeros(len(x))], axis=1)
    ps = SphSystem(x, v, mass, rho, np.zeros(len(x), dtype=int), scenes.water(20.0), SphOptions())
    pts = np.array([[0.5, 0.5], [0.31, 0.62], [0.77, 0.2]])
    got = ps.interpolate(pts, "vx")
    np.testing.assert_allclose(got, 0.2 + 0.5 * pts[:, 0] - 0.3 * pts[:, 1], atol=1e-3)
    assert np.isnan(ps.interpolate([[5.0, 5.0]])[0])
