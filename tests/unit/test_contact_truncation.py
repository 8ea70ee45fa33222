"""docs/studies/structure_in_water_corner_truncation.py (issue 12, measured, not adopted): the truncated kernel's uniform-pressure force at a structure's corners made a flat face's.

A 10 x 40 mm rectangle (four convex corners) in a lattice of water (dx 2.5 mm, cubic spline h/dx 1.2) at a uniform
1 MPa:
- the boundary integral Gamma^s = oint W n' dS' equals -int_solid grad_i W dA' summed on a 0.01 mm grid over the
  rectangle, at points beside a corner and on a face;
- g(d), the integral next to an unbounded flat face, is the integral over the rectangle's long face at its middle;
- on the faces away from the corners the correction is zero to round-off; beside the corners its part along the
  face is 0.2152 p dx, the continuum counterpart of the lattice's 0.198 p dx;
- the correction plus its reactions on the rectangle's nodes sum to zero (momentum).
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from sphfem_cli.sph.kernel_functions import CUBIC_SPLINE, kernel_f

# the study module imported by name from docs/studies (a module numba can find again when it loads its cached
# kernels; one loaded from a file spec outside sys.modules is "<dynamic>" to numba and its cache cannot be reloaded)
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "docs" / "studies"))
import structure_in_water_corner_truncation as truncation  # noqa: E402
_GAUSS_W, _GAUSS_X = truncation._GAUSS_W, truncation._GAUSS_X
corner_correction, flat_integral, surface_integral = (truncation.corner_correction, truncation.flat_integral,
                                                      truncation.surface_integral)

DX, RHO, P = 0.0025, 1000.0, 1.0e6
H = 1.2 * DX
NODES = np.array([[0.02, 0.02], [0.03, 0.02], [0.03, 0.06], [0.02, 0.06]])
FACES = np.array([[0, 1], [1, 2], [2, 3], [3, 0]], dtype=np.int64)  # counter-clockwise: outward normal right of a -> b


def _lattice():
    g = (np.arange(32) + 0.5) * DX  # 80 mm: the rectangle 20 mm clear of the lattice's edges
    x = np.array([(a, b) for a in g for b in g], dtype=np.float64)
    return x[~np.all((x > NODES[0]) & (x < NODES[2]), axis=1)]


def test_surface_integral_is_the_solid_area_integral():
    cell = 1.0e-5
    gx = np.arange(0.02 + 0.5 * cell, 0.03, cell)
    for point in ([0.03125, 0.02125], [0.03125, 0.01875], [0.03375, 0.02375], [0.03125, 0.04]):
        sx = gx[np.abs(gx - point[0]) < 2 * H]
        sy = np.arange(0.02 + 0.5 * cell, 0.06, cell)
        sy = sy[np.abs(sy - point[1]) < 2 * H]
        X, Y = np.meshgrid(sx, sy, indexing="ij")
        d = np.stack([point[0] - X.ravel(), point[1] - Y.ravel()], axis=1)
        r = np.linalg.norm(d, axis=1)
        f = np.array([kernel_f(CUBIC_SPLINE, 2, rr, H) for rr in r])
        area = -(f[:, None] * d).sum(axis=0) * cell * cell
        quad = np.array(surface_integral(point[0], point[1], H, CUBIC_SPLINE, NODES, FACES, _GAUSS_X, _GAUSS_W))
        # measured: within 0.4e-6 to 5.8e-6 of |Gamma| at these four points
        np.testing.assert_allclose(quad, area, atol=1e-4 * np.linalg.norm(area))


def test_corner_correction_on_faces_corners_and_momentum():
    for d in (0.5 * DX, 1.5 * DX, 2.3 * DX):  # the long face x = 0.03, 40 mm: at its middle, beyond 2 h of its ends
        gx, gy = surface_integral(0.03 + d, 0.04, H, CUBIC_SPLINE, NODES, FACES, _GAUSS_X, _GAUSS_W)
        assert abs(gx - flat_integral(d, H, CUBIC_SPLINE, _GAUSS_X, _GAUSS_W)) < 1e-12 * gx and gy == 0.0
    x = _lattice()
    n = len(x)
    h, m, rho, p = np.full(n, H), np.full(n, RHO * DX * DX), np.full(n, RHO), np.full(n, P)
    f_point, f_master = np.zeros((n, 2)), np.zeros((len(NODES), 2))
    corner_correction(np.arange(n), x, h, m, rho, p, CUBIC_SPLINE, NODES, FACES, f_point, f_master)
    size = np.linalg.norm(f_point, axis=1) / (P * DX)
    # particles whose support reaches no corner (2 h or more from every vertex): no correction but the quadrature's
    far = np.min(np.linalg.norm(x[:, None, :] - NODES[None, :, :], axis=2), axis=1) >= 2 * H
    assert size[far].max() < 1e-9, size[far].max()  # measured 5.0e-15 (the same quadrature on the same chords)
    # beside a corner (0.5 dx from both face lines): along the face towards the corner, and as much into the face
    # (its support holds less solid than a flat face's: the flat face's normal push is made up)
    beside = np.all(np.isclose(np.abs(x - NODES[1]), [0.5 * DX, 0.5 * DX]), axis=1) & (x[:, 0] > 0.03)
    i = int(np.flatnonzero(beside & (x[:, 1] > 0.02))[0])
    np.testing.assert_allclose(f_point[i] / (P * DX), [-0.2152, -0.2152], atol=5e-4)  # measured -0.21517 both
    np.testing.assert_allclose(f_point.sum(axis=0) + f_master.sum(axis=0), 0.0, atol=1e-12 * P * DX)

FREE_PLATE = """
title: free plate in water under 1 MPa, penalty contact
units: {length: m, mass: kg, time: s}
dimension: 2
control: {end_time: 1.0, timestep_scale: 0.5, energy_band: null}
equations_of_state:
  water: {type: linear_polynomial, c0: 1000000.0, c1: 2200000000.0}
materials:
  water: {type: fluid, density: 1000.0, eos: water}
  aluminium: {type: elastic, density: 2700.0, youngs_modulus: 70000000000.0, poisson_ratio: 0.33}
sections:
  plate: {type: solid}
  sph: {type: sph, kernel: cubic_spline, smoothing_ratio: 1.2, artificial_viscosity: {alpha: 0.0, beta: 0.0}}
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
    spacing: 0.0025
initial:
  - {type: velocity, part: water, velocity: [2.0, 1.0]}
contacts:
- {type: nodes_to_surface, nodes: water, surface: plate, stiffness: soft_constraint, soft_scale: 0.1, damping: 0.1}
"""


def test_free_plate_momentum_with_the_correction(tmp_path, monkeypatch):
    """The correction added to the contact as docs/studies/structure_in_water_corner_run.py adds it: its forces on
    the particles and their reactions on the plate's nodes conserve fluid + plate momentum to round-off (the plate
    is free, no walls, no gravity) over 30 steps, and it acted."""
    from sphfem_cli.contact import system as contact_system
    add_corner_correction = truncation.add_corner_correction
    from sphfem_cli.driver import load_model
    from sphfem_cli.solver.explicit import Simulation
    from sphfem_cli.sph.slots import SI_KERNEL

    original, acted = contact_system.NodesToSurfaceContact.forces, []

    def forces(self, st):
        original(self, st)
        ps = self.sim.particles.system
        f_corr, reaction = np.zeros_like(self._f_point), np.zeros_like(self._f_master)
        add_corner_correction(ps, self._slaves()[3], st.x, self.faces, int(ps.settings_i[SI_KERNEL]), f_corr, reaction)
        acted.append(float(np.abs(f_corr).max()))
        ps.f_ext += f_corr
        st.f_contact += reaction
        self._f_point += f_corr
        self._f_master += reaction

    monkeypatch.setattr(contact_system.NodesToSurfaceContact, "forces", forces)
    deck = tmp_path / "deck.yaml"
    deck.write_text(FREE_PLATE)
    sim = Simulation(load_model(str(deck)).model)
    ps = sim.particles.system

    def momentum():
        fluid = ps.v_half if ps.nsteps else ps.v
        return (sim.model.mass[:, None] * sim.state.v).sum(axis=0) + (ps.m[:, None] * fluid).sum(axis=0)

    p0 = momentum()
    for _ in range(30):
        sim.step()
    assert max(acted) > 0.0
    assert np.abs(sim.state.v).max() > 0.01  # the water pushed the plate
    np.testing.assert_allclose(momentum(), p0, rtol=0.0, atol=1e-12 * np.linalg.norm(p0))
