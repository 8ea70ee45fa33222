"""The sph_boundary coupling (contact/sph_boundary.py, sph/structure_walls.py): boundary particles carried by a
structure's faces, their reactions scattered to its nodes.

- a free (unsupported) plate in a water blob moving at (2, 1) m/s, no walls, no gravity: the total momentum of
  fluid (m v^{n+1/2}) and structure (m v^{n+1/2}) is conserved to round-off, and the energy table closes;
- a water column on a clamped plate (validation, 0.1 s): the plate carries the water's weight within 1 %, and the
  particles of the face the water does not touch carry no pressure though the other face's layers reach past it.
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.driver import load_model
from sphfem_cli.solver.explicit import Simulation
from sphfem_cli.contact.sph_boundary import face_sampling
from sphfem_cli.sph.structure_walls import W_FY, W_M, W_NY, W_P

FREE_PLATE = """
title: free plate in water, sph_boundary
units: {length: m, mass: kg, time: s}
dimension: 2
control: {end_time: 1.0, timestep_scale: 0.5}
equations_of_state:
  water: {type: linear_polynomial, c0: 0.0, c1: 2200000000.0}
materials:
  water: {type: fluid, density: 1000.0, eos: water}
  aluminium: {type: elastic, density: 2700.0, youngs_modulus: 70000000000.0, poisson_ratio: 0.33}
sections:
  plate: {type: solid}
  sph: {type: sph, kernel: cubic_spline, smoothing_ratio: 1.2, artificial_viscosity: {alpha: 0.1, beta: 0.0}}
parts:
  plate:
    material: aluminium
    section: plate
    geometry: {box: {min: [0.04, 0.045], max: [0.06, 0.055], divisions: [4, 2]}}
  water:
    material: water
    section: sph
    geometry:
      polygon:
        vertices: [[0.0, 0.0], [0.1, 0.0], [0.1, 0.1], [0.0, 0.1], [0.0, 0.0], [0.04, 0.045], [0.04, 0.055],
                   [0.06, 0.055], [0.06, 0.045], [0.04, 0.045]]
    spacing: 0.005
initial:
  - {type: velocity, part: water, velocity: [2.0, 1.0]}
couplings:
- {type: sph_boundary, structure: plate, fluid: water}
"""

COLUMN = """
title: water column on a clamped plate, sph_boundary
units: {length: m, mass: kg, time: s}
dimension: 2
control: {end_time: 0.1, timestep_scale: 0.9}
equations_of_state:
  water: {type: linear_polynomial, c1: 400000.0}
materials:
  water: {type: fluid, density: 1000.0, eos: water}
  soft: {type: elastic, density: 7850.0, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
sections:
  plate: {type: solid}
  sph: {type: sph, kernel: cubic_spline, smoothing_ratio: 1.2, artificial_viscosity: {alpha: 0.3, beta: 0.0}}
parts:
  plate:
    material: soft
    section: plate
    geometry: {box: {min: [0.0, -0.01], max: [0.1, 0.0], divisions: [10, 1]}}
  water:
    material: water
    section: sph
    geometry: {box: {min: [0.0, 0.0], max: [0.1, 0.1]}}
    spacing: 0.005
    hydrostatic: true
sets:
  all: {type: node, part: plate}
boundaries:
- {type: fixed, set: all, directions: [x, y]}
- {type: wall, min: [0.0, -0.01], max: [0.1, 0.2], sides: [left, right], condition: slip}
loads:
- {type: gravity, acceleration: [0.0, -9.81], parts: [water]}
couplings:
- {type: sph_boundary, structure: plate, fluid: water}
"""


def _sim(tmp_path, text: str) -> Simulation:
    deck = tmp_path / "deck.yaml"
    deck.write_text(text)
    return Simulation(load_model(str(deck)).model)


def _momentum(sim: Simulation) -> np.ndarray:
    ps = sim.particles.system
    fluid = ps.v_half if ps.nsteps else ps.v
    return (sim.model.mass[:, None] * sim.state.v).sum(axis=0) + (ps.m[:, None] * fluid).sum(axis=0)


def test_free_plate_conserves_momentum_and_energy(tmp_path):
    sim = _sim(tmp_path, FREE_PLATE)
    coupling = sim.interactions[0]
    p0 = _momentum(sim)
    for _ in range(40):
        sim.step()
    # the plate was pushed (the coupling acted) and the fluid lost what it gained
    assert np.abs(sim.state.v).max() > 0.05
    assert np.abs(coupling.f_nodes).max() > 0.0
    np.testing.assert_allclose(_momentum(sim), p0, rtol=0.0, atol=1e-12 * np.linalg.norm(p0))
    row = sim.energy_row()
    assert abs(row.ratio - 1.0) < 1e-3, row  # 0.99991 measured after these 40 steps


@pytest.mark.validation
def test_water_column_weight_on_plate(tmp_path):
    sim = _sim(tmp_path, COLUMN)
    ps, coupling = sim.particles.system, sim.interactions[0]
    weight = 9.81 * float(ps.m.sum())
    times, loads = [], []
    while sim.state.time < sim.control.end_time * (1.0 - 1e-12):
        sim.step()
        times.append(sim.state.time)
        loads.append(-float(coupling.f_nodes[:, 1].sum()))
    times, loads = np.array(times), np.array(loads)
    late = times >= 0.05
    assert abs(loads[late].mean() / weight - 1.0) < 0.01
    # the bottom face (y = -0.01) touches no water: its particles carry no pressure, though the top face's
    # three layers (to 15 mm deep) reach 5 mm below it
    bottom = coupling.ws[:, W_FY] < -0.0099  # the face point's y
    assert bottom.any() and np.all(coupling.ws[bottom, W_P] == 0.0)


# a lattice of water at rest under a uniform 1 MPa round a plate 20 x 10 mm (4 x 2 elements): the only forces are
# the truncated kernel's and the boundary particles'
AT_REST = FREE_PLATE.replace("c0: 0.0", "c0: 1000000.0").replace(
    "initial:\n  - {type: velocity, part: water, velocity: [2.0, 1.0]}\n", "")


def _near_plate(sim: Simulation, reach: float) -> np.ndarray:
    """Fluid particles within ``reach`` of the plate's box [0.04, 0.06] x [0.045, 0.055]."""
    x = sim.particles.system.x[:, :2]
    gap = np.maximum(np.maximum(0.04 - x, x - [0.06, 0.055]), [0.0, 0.0])
    gap[:, 1] = np.maximum(np.maximum(0.045 - x[:, 1], x[:, 1] - 0.055), 0.0)
    return np.linalg.norm(gap, axis=1) < reach


@pytest.mark.parametrize("corners", ["per_face", "once"])
def test_uniform_pressure_at_convex_corners(tmp_path, corners):
    """sum_j V_j grad W_ij with the boundary particles: per_face counts the squares behind the plate's four convex
    corners twice for the diagonal fluid, which a uniform pressure then pushes out of the corner; once counts them
    once and no particle next to the plate is pushed (round-off)."""
    sim = _sim(tmp_path, AT_REST.replace(
        "{type: sph_boundary, structure: plate, fluid: water}",
        f"{{type: sph_boundary, structure: plate, fluid: water, corner_particles: {corners}}}"))
    coupling, ps = sim.interactions[0], sim.particles.system
    assert coupling.twins.shape[0] == len(coupling.ws)
    sim.step()
    near = _near_plate(sim, 0.011)  # two spacings and a bit: every particle whose support the plate cuts
    v = np.linalg.norm(ps.v_half[near], axis=1)
    # the scale: the truncated kernel's push on the first layer, (2 p / rho) |sum V grad W| dt ~ 0.93 * 2 p / (rho dx) dt
    scale = 2.0 * 1.0e6 / (1000.0 * 0.005) * sim.state.dt_prev
    if corners == "once":
        assert v.max() < 1e-9 * scale, v.max() / scale  # measured 7.4e-16 of the scale (40 particles)
    else:
        # the diagonal particles: |sum V grad W| = 0.099 sqrt(2) / dx, a first half-step kick of 0.070 of the scale
        assert v.max() > 0.05 * scale, v.max() / scale  # measured 0.0701
    assert np.abs(coupling.f_nodes).max() > 0.0


def test_free_plate_conserves_momentum_with_corners_once(tmp_path):
    sim = _sim(tmp_path, FREE_PLATE.replace("fluid: water}", "fluid: water, corner_particles: once}"))
    assert (sim.interactions[0].twins >= 0).sum() > 0
    p0 = _momentum(sim)
    for _ in range(40):
        sim.step()
    np.testing.assert_allclose(_momentum(sim), p0, rtol=0.0, atol=1e-12 * np.linalg.norm(p0))
    row = sim.energy_row()
    assert abs(row.ratio - 1.0) < 1e-3, row


def test_stable_dt_gershgorin_bound_by_hand(tmp_path):
    """SphBoundaryCoupling.stable_dt = min_i sqrt(2 m_i / S_i), S_i = k (L_1 + L_2) / 2 over node i's two faces,
    k = K W1(0): on the free plate (5 mm square quad4, aluminium 2700 kg/m^3, every outer face 5 mm) the corner node
    is the lightest, m = 2700 x 0.005^2 / 4 = 0.016875 kg/m, with S = k x 0.005; K = c1 = 2.2e9 Pa (linear
    polynomial, rho_0 c^2 = c1), W1(0) = 15 / (7 pi h) for the 2D cubic spline (2 int_0^2h W dr: sigma 10 / (7 pi h^2),
    int_0^2 theta = 3/4), h = 1.2 x 0.005. Tolerance 1e-6 relative: the midpoint rule's error on W1(0)."""
    sim = _sim(tmp_path, FREE_PLATE)
    coupling = sim.interactions[0]
    h = 1.2 * 0.005
    k = 2.2e9 * 15.0 / (7.0 * np.pi * h)
    m_corner = 2700.0 * 0.005 ** 2 / 4.0
    assert sim.model.mass.min() == pytest.approx(m_corner, rel=1e-12)
    assert coupling.face_stiffness() == pytest.approx(k, rel=1e-6)
    assert coupling.stable_dt() == pytest.approx(np.sqrt(2.0 * m_corner / (k * 0.005)), rel=1e-6)
    # the loop takes it times timestep_scale (0.5 here) when it is the smallest
    assert sim.stable_dt() <= 0.5 * coupling.stable_dt() * (1.0 + 1e-12)


def test_stable_dt_scales_as_sqrt_dx(tmp_path):
    """Halving the fluid's spacing (the plate unchanged) doubles k = K W1(0) ~ 1 / dx: the bound falls by sqrt(2)
    (to round-off: the midpoint rule's relative error is the same at every h)."""
    coarse = _sim(tmp_path, FREE_PLATE).interactions[0].stable_dt()
    fine = _sim(tmp_path, FREE_PLATE.replace("spacing: 0.005", "spacing: 0.0025")).interactions[0].stable_dt()
    assert fine / coarse == pytest.approx(1.0 / np.sqrt(2.0), rel=1e-9)


def test_arc_length_sampling_refines_with_the_fluid(tmp_path):
    """sampling: arc_length on the free plate meshed 8 x 4 (2.5 mm faces) in water at dx 5 mm: per face the row
    would be max(1, round(0.5)) = 1 particle every 2.5 mm (0.5 dx); by arc length each side (20 / 10 mm between the
    convex corners) carries 4 / 2 particles every dx, (k + 1/2) dx from its first corner, so the corner squares hold
    coincident pairs (counted once with corner_particles: once). The row's mass is rho_0 x perimeter x dx per layer
    (the layers' area), and the momentum of fluid and plate is conserved to round-off."""
    deck = FREE_PLATE.replace("divisions: [4, 2]", "divisions: [8, 4]")
    sim = _sim(tmp_path, deck.replace("fluid: water}", "fluid: water, sampling: arc_length}"))
    coupling, dx = sim.interactions[0], 0.005
    seg, _, ds = face_sampling(sim.model.coordinates, coupling.faces, dx)  # the default's row: 1 per face
    assert len(seg) == 24 and np.allclose(ds, 0.0025)
    assert coupling.layers == 3 and len(coupling.seg) == 3 * (4 + 2 + 4 + 2)
    np.testing.assert_allclose(coupling.ws[:, W_M].sum(), 1000.0 * 0.06 * 3 * dx, rtol=1e-12)
    x = coupling.particles()
    first = coupling.depth == 0.5 * dx
    bottom = first & (coupling.ws[:, W_NY] < -0.99)  # the bottom face's first row (outward normal -y)
    np.testing.assert_allclose(np.sort(x[bottom, 0]), 0.04 + (np.arange(4) + 0.5) * dx, atol=1e-12)
    assert (coupling._coincident(x) >= 0).sum() == 4 * 2 * 9  # 3 x 3 pairs behind each of the 4 corners
    p0 = _momentum(sim)
    for _ in range(10):
        sim.step()
    assert np.abs(coupling.f_nodes).max() > 0.0
    np.testing.assert_allclose(_momentum(sim), p0, rtol=0.0, atol=1e-12 * np.linalg.norm(p0))


def test_outline_runs_cut_at_corners_only():
    """A faceted circle (36 faces, 10 degree turns) is one run; a square meshed 3 faces a side is four runs of 3."""
    from sphfem_cli.contact.sph_boundary import arc_length_sampling, outline_runs
    angle = np.linspace(0.0, 2.0 * np.pi, 37)[:-1]
    circle = np.stack([np.cos(angle), np.sin(angle)], axis=1)
    ring = np.stack([np.arange(36), (np.arange(36) + 1) % 36], axis=1)
    assert [len(r) for r in outline_runs(circle, ring)] == [36]
    seg, s, ds = arc_length_sampling(circle, ring, 0.05)
    perimeter = 36 * 2.0 * np.sin(np.pi / 36)
    assert len(seg) == round(perimeter / 0.05) and np.allclose(ds, perimeter / len(seg)) and np.all((s >= 0) & (s <= 1))
    t = np.linspace(0.0, 1.0, 4)[:-1]
    square = np.concatenate([np.stack([t, 0 * t], 1), np.stack([1 + 0 * t, t], 1), np.stack([1 - t, 1 + 0 * t], 1),
                             np.stack([0 * t, 1 - t], 1)])
    faces = np.stack([np.arange(12), (np.arange(12) + 1) % 12], axis=1)
    assert sorted(len(r) for r in outline_runs(square, faces)) == [3, 3, 3, 3]
