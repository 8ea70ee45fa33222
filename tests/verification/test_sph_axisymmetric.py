"""Axisymmetric SPH (sph/axisymmetric.py): water at rest in a cylinder, conservation in a closed cylinder,
and the semi-discrete energy balance of the rates.

* Hydrostatic column: meridian plane [0, R] x [0, H], R = 0.5 m, H = 1 m, dx = 0.05 (200 rings), slip
  ghost walls at r = R and the floor, the axis a ghost line, Tait water c0 = 10 sqrt(g H), alpha 0.02,
  delta-SPH 0.1 with the hydrostatic correction, hydrostatic ghosts. Each particle's pressure,
  averaged over 1.0-1.5 s (the start-up excites the column's acoustic mode, period 4H/c0 = 0.13 s,
  which alpha = 0.02 damps slowly), against rho g (H - z). Measured (sphfem 0.1.0): mean error
  +0.65 % of rho g H, largest 1.35 % (at the floor), the first column next to the axis the same; the
  plane tank of the same size and resolution (scenes.still_water, 0.5 m wide) gives +0.65 % and 1.35 %
  too (the cubic spline's pressure-gradient bias at h/dx = 1.2, see test_sph_still_water.py). No particle
  crosses or approaches the axis (the first column stays at r = dx/2: closest 0.4998 dx).
* Closed cylinder without gravity: a ring vortex (v_r, v_z of one cell) in [0, R] x [0.2, 0.8]
  inside a slip wall at r = R, no wall across the axis, free ends at z = 0.2 and 0.8: mass is exact (no
  particle leaves), the axial momentum sum m v_z drifts by the axial hoop term's truncation error only
  (measured 1.0e-9 of sum m |v_z| over 0.25 s; 3e-14 before issue 15 gave the hoop term its axial
  component kappa_z, which is a force on one particle and nonzero where the support is cut, here at the
  free ends; see the module docstring of sph/axisymmetric.py, also for why the axis images conserve it
  only to truncation error in general); asserted below 1e-8. The kinetic + internal energy changes by
  the leapfrog's error only (measured 5.8e-3 of the initial kinetic energy over 0.25 s, 2.7e-3 with the
  radial kappa alone; the rates balance exactly, test_rates_balance_energy_exactly); asserted below 1e-2.
* The rates alone: sum_i m_i (v_i . a_i + de_i/dt) = 0 to round-off at a jittered state with random
  velocities, the axis images and a wall at r = R included (the exactness the docstring claims; measured
  0 against 1.1e5 for sum |m v . a|).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from sphfem_cli.sph import lattice, scenes
from sphfem_cli.sph.options import SphOptions
from sphfem_cli.sph.system import SphSystem
from sphfem_cli.sph.walls import box_walls

G, H, R = 9.81, 1.0, 0.5


def test_hydrostatic_column_in_a_cylinder():
    dx = 0.05
    ps = scenes.still_water_cylinder(depth=H, radius=R, dx=dx, delta_hydrostatic=True, ghost_hydrostatic=True)
    ps.run(1.0)
    p_sum, k = np.zeros(ps.n), 0
    closest = ps.x[:, 0].min()
    for t in np.arange(1.05, 1.5001, 0.05):
        ps.run(t)
        closest = min(closest, ps.x[:, 0].min())
        order = np.argsort(ps.ids)
        p_sum += ps.p[order]
        k += 1
    order = np.argsort(ps.ids)
    p = p_sum / k
    z = ps.x[order, 1]
    err = (p - 1000.0 * G * (H - z)) / (1000.0 * G * H)
    axis = ps.x[order, 0] < dx
    print(f"mean {err.mean():+.4f} max {np.abs(err).max():.4f} first column {err[axis].mean():+.4f} "
          f"max {np.abs(err[axis]).max():.4f} closest r/dx {closest / dx:.4f}")
    assert abs(err.mean()) < 0.01, err.mean()
    assert np.abs(err).max() < 0.02, np.abs(err).max()
    assert np.abs(err[axis]).max() < 0.02
    assert ps.wall_crossings == 0 and ps.lost == 0
    assert closest > 0.45 * dx, closest  # the first column stays at r = dx/2


def _ring_vortex(dx=0.025):
    mats = scenes.water(20.0)
    x = lattice.box([0.0, 0.2], [R, 0.8], dx)
    rho = np.full(len(x), 1000.0)
    v = np.zeros_like(x)
    v[:, 1] = np.sin(math.pi * x[:, 0] / R) * np.cos(math.pi * (x[:, 1] - 0.2) / 0.6)
    v[:, 0] = 0.5 * np.sin(math.pi * x[:, 0] / R) * np.sin(math.pi * (x[:, 1] - 0.2) / 0.6)
    opt = SphOptions(alpha=0.05, delta=0.1, walls=box_walls([0, 0], [R, 1], ["right"]), axisymmetric=True)
    return SphSystem(x, v, scenes.ring_particles(x, dx, rho), rho, np.zeros(len(x), dtype=np.int64), mats, opt)


def test_closed_cylinder_conserves_mass_axial_momentum_and_energy():
    ps = _ring_vortex()
    m0, pz0, e0 = np.sort(ps.m), ps.momentum()[1], ps.energies()
    scale = float(np.sum(ps.m * np.abs(ps.v[:, 1])))
    ps.run(0.25)
    assert ps.lost == 0 and ps.active.all() and np.array_equal(np.sort(ps.m), m0)  # the same masses
    e = ps.energies()
    print(f"axial momentum {(ps.momentum()[1] - pz0) / scale:.2e}, energy {(e['total'] - e0['total']) / e0['kinetic']:.2e}")
    assert abs(ps.momentum()[1] - pz0) < 1e-8 * scale  # the axial hoop term's truncation error (docstring)
    assert abs(e["total"] - e0["total"]) < 1e-2 * e0["kinetic"]
    assert ps.wall_crossings == 0


def test_rates_balance_energy_exactly():
    rng = np.random.default_rng(3)
    dx = 0.05
    mats = scenes.water(20.0)
    x = lattice.box([0.0, 0.0], [R, 0.6], dx)
    x += rng.uniform(-0.2, 0.2, x.shape) * dx
    x[:, 0] = np.abs(x[:, 0])
    rho = 1000.0 * (1.0 + 0.01 * rng.uniform(-1, 1, len(x)))
    v = rng.normal(size=x.shape)
    opt = SphOptions(alpha=0.5, beta=1.0, delta=0.0, walls=box_walls([0, 0], [R, 1], ["right"]), axisymmetric=True)
    ps = SphSystem(x, v, scenes.ring_particles(x, dx, rho), rho, np.zeros(len(x), dtype=np.int64), mats, opt)
    ps.compute_rates()
    power = ps.m * np.sum(ps.v * ps.acc, axis=1)
    heating = ps.m * ps.de
    print(f"energy balance {(power.sum() + heating.sum()) / np.abs(power).sum():.2e}")
    assert abs(power.sum() + heating.sum()) < 1e-12 * np.abs(power).sum()


def _noh(dx):
    ps = scenes.noh_sphere_axisymmetric(dx=dx)
    e0, pz0, scale = ps.energies()["total"], ps.momentum()[1], float(np.sum(ps.m * np.abs(ps.v[:, 1])))
    ps.run(0.6)
    dist = np.linalg.norm(ps.x, axis=1)
    order = np.argsort(dist)
    shock = dist[order][np.flatnonzero((dist[order] > 0.1) & (ps.rho[order] < 40.0))[0]]
    post = (dist > 0.05) & (dist < 0.15)
    return ps, e0, pz0, scale, shock, float(ps.rho[post].mean())


def test_noh_implosion_is_robust_on_the_axis():
    """Noh's spherical implosion (scenes.noh_sphere_axisymmetric, dx = 0.04, t = 0.6): the flow converges
    on a point of the axis. Measured: no particle crosses the axis (closest r = 4.3e-3), energy 1.6e-4
    of the initial kinetic, axial momentum 1e-16 of sum m |v_z|, shock at R = 0.21 (exact 0.2); with the
    hoop terms' Courant condition (7 December 2026): closest r 4.36e-3, energy 2.1e-4, shock 0.2095."""
    ps, e0, pz0, scale, shock, _ = _noh(0.04)
    assert ps.wall_crossings == 0 and ps.x[:, 0].min() > 0.0
    assert abs(ps.energies()["total"] - e0) < 1e-3 * e0
    assert abs(ps.momentum()[1] - pz0) < 1e-10 * scale
    assert 0.18 < shock < 0.23, shock


def test_no_spurious_heating_on_the_axis():
    """Issue 15: no spurious heating on the axis. Noh's sphere (scenes.noh_sphere_axisymmetric, the decks'
    volume form, dx = 0.02, t = 0.6; about 1.5 s CPU): behind the shock the exact specific internal energy is
    u0^2/2 = 0.5, ahead of it 0. The particles within two spacings of the axis against those more than 45 deg off
    it, at the same spherical radius. Measured: plateau (0.08 < R < 0.17) e = 0.502 on the axis, 0.532 off it
    (ratio 0.945; 1.090 / 0.945 / 0.938 at dx 0.04 / 0.02 / 0.01, 0.481 / 0.513 at 0.01); inflow (0.25 < R < 0.45)
    e = 0.0043 on the axis, 0.0105 off it (0.0147 / 0.0043 / 0.0011 on the axis at 0.04 / 0.02 / 0.01).
    Asserted: the axis no hotter than off it by more than 5 % in the plateau, within 10 % of 0.5, and its inflow
    heating under 2 % of 0.5. With the hoop terms' Courant condition (sph/axisymmetric.py axis_time_step, 7
    December 2026, dx 0.02): plateau 0.5038 on the axis, 0.5314 off it; inflow 0.0043 on the axis, 0.0019 off
    it (was 0.0105: the smaller steps heat the off-axis inflow less); inflow density axis / off 1.298.

    Found on the way, not a heating: the inflow within two spacings of the axis is denser than off it (9.95 against
    7.65 at dx 0.02, exact about 7.7; 9.68 / 9.95 / 9.80 at dx 0.04 / 0.02 / 0.01): +27 % to +30 % in a layer two
    spacings wide that does not shrink relative to them with refinement (the same layer in the r-z ALE is +9 %,
    test_ale_axisymmetric_noh.py). Asserted below 1.4 times the off-axis density (a guard, not a goal)."""
    dx = 0.02
    ps = scenes.noh_sphere_axisymmetric(dx=dx)
    ps.run(0.6)
    r, z = ps.x[:, 0], ps.x[:, 1]
    rad = np.hypot(r, z)
    axis, off = r < 2.0 * dx, r > np.abs(z)
    plateau = (rad > 0.08) & (rad < 0.17)
    inflow = (rad > 0.25) & (rad < 0.45)
    e_axis, e_off = ps.e[plateau & axis].mean(), ps.e[plateau & off].mean()
    dense = ps.rho[inflow & axis].mean() / ps.rho[inflow & off].mean()
    print(f"plateau e axis {e_axis:.4f} off {e_off:.4f}; inflow e axis {ps.e[inflow & axis].mean():.4f} "
          f"off {ps.e[inflow & off].mean():.4f}; inflow density axis / off {dense:.3f}")
    assert e_axis < 1.05 * e_off
    assert abs(e_axis / 0.5 - 1.0) < 0.1
    assert ps.e[inflow & axis].mean() < 0.02 * 0.5
    assert dense < 1.4


@pytest.mark.validation
@pytest.mark.xfail(strict=True, reason="the SPH continuity density over-compresses strong convergent shocks: "
                   "post-shock 76 and 89 at dx = 0.02, 0.01 (exact 64); the plane 2D cylindrical Noh does the "
                   "same (21.6 for 16) and is cured there by the mass form (continuity: mass, test_sph_noh.py), "
                   "whose axisymmetric version converges (test_noh_sphere_converges_with_the_mass_form: 61.0 at "
                   "dx = 0.01); unchanged by the axis time step (75.98, 88.5 on 7 December 2026); "
                   "docs/theory/sph.md 'Axisymmetric SPH'")
@pytest.mark.parametrize("dx", [0.02, 0.01])
def test_noh_post_shock_density(dx):
    *_, post = _noh(dx)
    assert abs(post - 64.0) < 0.1 * 64.0, post


def test_deck_particles_carry_ring_masses():
    """decks/water_column_axisymmetric_sph.yaml: the SPH rings of a cylinder R = 0.1 m, H = 0.2 m weigh
    pi R^2 H rho (the midpoint lattice sums 2 pi r dx^2 exactly to pi R^2 per layer), and the model's
    SPH system is axisymmetric with the axis as its first ghost wall. The exact mass is read from
    tests/data/water_column_axisymmetric_sph.yaml; tolerance 1e-9 (the lattice's sum is exact)."""
    from pathlib import Path

    from sphfem_cli.driver import load_model
    from sphfem_cli.solver.sph_domain import SphDomain
    from tests.reference_data import value

    deck = Path(__file__).resolve().parents[2] / "decks" / "water_column_axisymmetric_sph.yaml"
    model = load_model(deck).model
    assert model.axisymmetric
    mass = model.particles.mass.sum()
    exact = value("water_column_axisymmetric_sph", "mass")  # rho pi R^2 H
    assert exact == pytest.approx(math.pi * 0.1**2 * 0.2 * 1000.0, rel=1e-9)  # the stored digits
    assert abs(mass - exact) < 1e-9 * mass
    dom = SphDomain(model, model.options.sph, model.options.control)
    w = dom.system.options.walls[0]
    assert dom.system.axisymmetric and (w.axis, w.position, w.side, w.condition) == (0, 0.0, 1, "slip")


@pytest.mark.validation
def test_noh_sphere_converges_with_the_mass_form():
    """Noh's sphere with the mass form of the continuity equation (drho_i/dt = sum_j rho_j A_j v_ij.grad W
    - rho_i v_r/r, sph/axisymmetric.py), dx = 0.04, 0.02, 0.01, t = 0.6, exact solution Noh (1987)
    (scenes.noh_density). Measured 7 December 2026 (one thread, load ~5, with the hoop terms' Courant
    condition dt <= r/(c + |v|), sph/axisymmetric.py axis_time_step): L1(rho) over R < 0.4 5.310 / 2.161 /
    0.872 (observed order 1.30, 1.31; the volume form: 2.31 / 2.21 / 3.43), post-shock rho (0.05 < R <
    0.15) 38.1 / 54.4 / 61.0 (exact 64: -4.7 % at dx = 0.01), energy 2.4e-4 / 1.6e-4 / 1.0e-4 of the
    initial kinetic energy, no particle reaches the axis (closest r 0.10 dx), 227 / 536 / 1195 steps
    (the axis condition sets the step in 90-98 % of them; this file's three validation tests: 44.7 CPU
    s). Without the axis condition (until then) the innermost rings' radial mode went unstable and the run
    at dx = 0.04 collapsed its step at t = 0.365 (tests/unit/test_sph_axis_time_step.py). Asserted: L1
    falling, order > 1 between the two finer levels, post-shock within 6 % of 64, energy within 3e-3."""
    l1 = []
    for dx in (0.04, 0.02, 0.01):
        ps = scenes.noh_sphere_axisymmetric(dx=dx, continuity="mass")
        e0 = ps.energies()["total"]
        ps.run(0.6)
        r = np.linalg.norm(ps.x, axis=1)
        near = r < 0.4
        vol = ps.m[near] / ps.rho[near]
        l1.append(float(np.sum(vol * np.abs(ps.rho[near] - scenes.noh_density(r[near], 0.6, 3))) / vol.sum()))
        assert abs(ps.energies()["total"] - e0) < 3e-3 * e0
    post = float(ps.rho[(r > 0.05) & (r < 0.15)].mean())
    print("L1", l1, "post", post)
    assert l1[0] > l1[1] > l1[2] and math.log2(l1[1] / l1[2]) > 1.0
    assert abs(post - 64.0) < 0.06 * 64.0, post
