"""The mass form of the SPH continuity equation in an axisymmetric deck (``continuity: mass``, issue 15, A4b).

In r-z the mass form is drho_i/dt = sum_j rho_j A_j v_ij . grad_i W_ij - rho_i v_r,i / r_i (sph/axisymmetric.py:
the plane code's m_j with the plane mass rho_j A_j = m_j / (2 pi r_j) of each ring). It was a deck error
until 7 December 2026 because four rings of Noh's sphere reached the axis; the hoop terms' time step
dt <= r / (c + |v|) (``axis_time_step``) stopped that, so a deck may ask for it (docs/theory/sph.md,
"Axisymmetric SPH"; docs/studies/axisymmetric_acceptance.md, A4b).

* A blast in a closed cylinder from a deck: ideal gas (gamma 1.4), density 1, a hot core (0 < r, z < 0.2,
  p = 1) in a cold gas (p = 0.1) inside slip walls at r = 0.5, z = 0 and z = 0.5 (the axis a ghost line),
  dx = 0.025 (400 rings), alpha 1, beta 2, no density diffusion, to t = 0.25 (the shock reflected from the
  walls). Mass is exact (no ring lost, every ring mass bit for bit its initial 2 pi r rho dx^2); the walls
  are at rest, so the kinetic + internal energy changes by the leapfrog's error only (measured 5.3e-6 of
  E(0) in 56 steps; the volume form 1.1e-6 in 58): asserted below 1e-4; no ring crosses the axis (closest
  0.475 dx; volume form 0.378 dx), every density positive (least 0.21). About 2 s.
* A restart (output.snapshot capture / restore, as a checkpoint) continues bit for bit: the form is the deck's,
  rebuilt with the system, and the state it acts on is the checkpointed one.
* The explosive products' renormalised continuity (``renormalise_ring_continuity``) replaces the plain
  first sum of whichever form the rates used: with the mass form it subtracted the volume form's
  rho_i sum_j A_j v_ij . grad W until 7 December 2026, leaving sum_j (rho_j - rho_i) A_j v_ij . grad W.
  Jittered lattice, densities 1000-1630 at random, the linear field v = (a r, d z): drho_i / rho_i =
  -(2 a + d) for every products particle in both forms, measured to 1.3e-15 (volume) and 1.5e-15 (mass;
  0.175 before the fix); asserted below 1e-10. The plane code's ``expansion.renormalise_continuity`` had the
  same fault (0.47 of the divergence, -(a + d) exact) and is checked by the same test.

Not here: at an interface of unequal density at equal spacing (8:1, the same cylinder with the cold gas at
0.125) the mass form takes the light gas's density negative in both plane and r-z (plane 2D: least
rho -0.033 and 16 wall crossings; r-z: negative at step 4, the step collapses at step 16): the heavy
neighbours' rho_j A_j weigh 8 times the light particle's own density in its rate. The volume form runs
both (docs/theory/sph.md, "Axisymmetric SPH").
"""
from __future__ import annotations

import json

import numpy as np
import pytest

from sphfem_cli.sph import lattice, scenes
from sphfem_cli.sph.options import SphOptions, material_table
from sphfem_cli.sph.slots import CONTINUITY_MASS, SI_CONTINUITY
from sphfem_cli.sph.system import SphSystem

DX = 0.025
BLAST = """
title: r-z SPH blast in a closed cylinder, mass form of the continuity equation
dimension: axisymmetric
control: {end_time: 0.25}
equations_of_state:
  hot: {type: ideal_gas, gamma: 1.4, e0: 2.5}
  cold: {type: ideal_gas, gamma: 1.4, e0: 0.25}
materials:
  core: {type: fluid, density: 1.0, eos: hot}
  ambient: {type: fluid, density: 1.0, eos: cold}
sections:
  gas: {type: sph, artificial_viscosity: {alpha: 1.0, beta: 2.0}, density_diffusion: 0.0, continuity: mass}
parts:
  core: {material: core, section: gas, geometry: {box: {min: [0.0, 0.0], max: [0.2, 0.2]}}, spacing: 0.025}
  ambient:
    material: ambient
    section: gas
    geometry: {polygon: {vertices: [[0.2, 0.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5], [0.0, 0.2], [0.2, 0.2]]}}
    spacing: 0.025
boundaries:
  - {type: wall, min: [0.0, 0.0], max: [0.5, 0.5], sides: [right, bottom, top], condition: slip}
output:
  interval: 0.05
"""


@pytest.fixture
def blast(tmp_path):
    from sphfem_cli.driver import load_model
    from sphfem_cli.solver.explicit import Simulation

    deck = tmp_path / "blast.yaml"
    deck.write_text(BLAST)
    return lambda: Simulation(load_model(str(deck)).model)


def test_a_deck_runs_the_mass_form_and_keeps_mass_exactly(blast):
    sim = blast()
    ps = sim.particles.system
    assert ps.axisymmetric and ps.settings_i[SI_CONTINUITY] == CONTINUITY_MASS
    ring = 2.0 * np.pi * ps.x[:, 0] * ps.rho * DX * DX  # the lattice's ring masses, rho = 1
    assert ps.n == 400 and np.allclose(ps.m, ring, rtol=1e-14, atol=0.0)
    m0 = dict(zip(ps.ids.tolist(), ps.m.tolist()))
    e0 = ps.energies()["total"]
    sim.run()
    energy = abs(ps.energies()["total"] - e0) / e0
    print(f"steps {ps.nsteps} energy {energy:.2e} closest r/dx {ps.x[:, 0].min() / DX:.3f} rho min {ps.rho.min():.3g}")
    assert sim.state.time == pytest.approx(0.25, rel=1e-12)
    assert ps.n == 400 and ps.active.all()
    assert all(m0[i] == m for i, m in zip(ps.ids.tolist(), ps.m.tolist()))
    assert ps.wall_crossings == 0 and ps.x[:, 0].min() > 0.0
    assert ps.rho.min() > 0.0 and np.isfinite(ps.h).all()
    assert energy < 1e-4, energy
    assert np.abs(ps.v).max() > 0.3  # the blast moved the gas (the core's sound speed is 1.18)


def test_a_restart_continues_the_mass_form_bit_for_bit(blast):
    from sphfem_cli.output.snapshot import capture, restore

    sim = blast()
    for _ in range(10):
        sim.step()
    tree, arrays = capture(sim)
    fresh = blast()
    restore(json.loads(json.dumps(tree)), [a.copy() for a in arrays], fresh)
    a, b = sim.particles.system, fresh.particles.system
    assert b.settings_i[SI_CONTINUITY] == CONTINUITY_MASS
    for _ in range(5):
        sim.step()
        fresh.step()
    for name in ("x", "v", "rho", "e", "m"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


@pytest.mark.parametrize("ring", [True, False], ids=["rz", "plane"])
def test_products_renormalised_continuity_is_the_same_in_both_forms(ring):
    """The products' renormalised continuity (r-z ``axisymmetric.renormalise_ring_continuity``, plane
    ``expansion.renormalise_continuity``) takes out the rates' own first sum in either form: before 7 December 2026
    the mass form's was taken out as the volume form's, off by 0.175 (r-z) and 0.47 (plane) of the divergence on
    this lattice. Jittered lattice, densities 1000-1630 at random, v = (a x, d y): drho/rho = -div to round-off."""
    from pydantic import TypeAdapter

    from sphfem_cli.deck.schema.materials import EquationOfState, Material

    tnt = (TypeAdapter(Material).validate_python({"type": "high_explosive", "density": 1630.0,
                                                   "detonation_velocity": 6930.0, "eos": "tnt"}),
           TypeAdapter(EquationOfState).validate_python({"type": "jwl", "A": 3.712e11, "B": 3.231e9, "R1": 4.15,
                                                         "R2": 0.95, "omega": 0.3, "e0": 7.0e9}))
    dx, a, d = 0.002, 300.0, -120.0
    x = lattice.box([0.0, 0.0], [0.03, 0.03], dx)
    rng = np.random.default_rng(3)
    x += rng.uniform(-0.2, 0.2, x.shape) * dx  # jittered, still at r > 0
    rho = rng.uniform(1000.0, 1630.0, len(x))
    v = np.column_stack([a * x[:, 0], d * x[:, 1]])
    div = (2.0 * a if ring else a) + d  # r-z: the hoop term v_r / r = a
    for form in ("volume", "mass"):
        opt = SphOptions(alpha=0.1, axisymmetric=ring, pressure_cutoff=-1e5, continuity=form)
        mass = scenes.ring_particles(x, dx, rho) if ring else rho * dx * dx
        ps = SphSystem(x, v, mass, rho, np.zeros(len(x), dtype=np.int64), material_table([tnt]), opt)
        ps.set_burn([((0.0, 0.0), 0.0)])
        ps.compute_rates()
        err = np.abs(ps.drho / ps.rho + div) / abs(div)
        assert err.max() < 1e-10, (form, err.max())  # round-off of the renormalised sums
