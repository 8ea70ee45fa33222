"""The ALE coupling begins at contact, not before (issue 18 item 2; docs/theory/coupling.md).

A coupling point that is not pushing couples only once it lies inside the fluid of its own ALE
element: the element holds at least ``min_fraction`` of coupling fluid and the point lies beyond
the element's interface, reconstructed as a line parallel to the segment that cuts off the fluid's
fraction of the element (``fluid_side_depth``). Before, a point in void took the water element h/2
in front of it as host and the force on a cylinder entering at constant speed began at s/D = -0.018
(5 mm elements, D = 0.11 m), with 17 % of the early impulse before contact.
"""
from __future__ import annotations

import numpy as np

from sphfem_cli.contact.coupling_common import fluid_side_depth
from sphfem_cli.driver import load_model
from sphfem_cli.solver.explicit import Simulation

H = 0.01  # ALE element size [m]
DECK = f"""
title: cylinder entering ALE water at constant speed, contact onset (test)
units: {{length: m, mass: kg, time: s}}
dimension: 2
control: {{end_time: 3.0e-3}}
equations_of_state:
  water: {{type: linear_polynomial, c1: 3.6e6}}
materials:
  water: {{type: fluid, density: 1000.0, eos: water}}
  void: {{type: void}}
  body: {{type: rigid, density: 1000.0, youngs_modulus: 2.0e11, poisson_ratio: 0.3}}
sections:
  fluid: {{type: ale_multi_material}}
  solid: {{type: solid}}
parts:
  tank:
    material: void
    section: fluid
    geometry: {{box: {{min: [0.0, 0.0], max: [0.4, 0.32], element_size: {H}}}}}
    fill: [{{material: water, box: {{min: [0.0, 0.0], max: [0.4, 0.2]}}}}]
  cylinder:
    material: body
    section: solid
    geometry: {{ring: {{center: [0.2, 0.2605], inner_radius: 0.0, outer_radius: 0.055,
                      elements_around: 32, elements_through: 2}}}}
boundaries:
  - {{type: ale_boundary, part: tank, sides: [left, right, bottom], condition: slip}}
  - {{type: prescribed_velocity, part: cylinder, velocity: [0.0, -2.955]}}
couplings: [{{type: lagrange_in_solid, structure: cylinder, fluid: tank, pfac: 1.0}}]
output: {{interval: 1.0e-3}}
"""
SURFACE = 0.2
V = 2.955


def test_interface_depth_of_a_partly_filled_element():
    """fluid_side_depth on a unit-free square and a sheared quad: the line it finds cuts off
    exactly the fluid's fraction (Monte Carlo area, 2e5 samples, to 0.5 %) on the normal's side."""
    x = np.array([[0.0, 0.0], [H, 0.0], [H, H], [0.0, H]])
    conn = np.array([[0, 1, 2, 3]])
    # the body above, fluid below (n = -y): 30 % of fluid fills y < 0.3 H
    for y, expected in [(0.5 * H, -0.2 * H), (0.25 * H, 0.05 * H), (0.0, 0.3 * H)]:
        assert abs(fluid_side_depth(x, conn, 0, 0.5 * H, y, 0.0, -1.0, 0.3) - expected) < 1e-12 * H
    assert fluid_side_depth(x, conn, 0, 0.5 * H, 0.999 * H, 0.0, -1.0, 1.0) > 0.0  # full: anywhere inside
    assert fluid_side_depth(x, conn, 0, 0.5 * H, 0.001 * H, 0.0, -1.0, 0.0) < 0.0  # empty: nowhere
    sheared = np.array([[0.0, 0.0], [1.0, 0.1], [1.3, 1.0], [0.2, 0.8]])
    n = np.array([0.6, -0.8])
    rng = np.random.default_rng(1)
    pts = rng.random((200_000, 2)) * 1.3
    a, b, c, d = sheared

    def inside(p):  # convex quad, counter-clockwise
        return np.all([(q[0] - p0[0]) * (p[:, 1] - p0[1]) - (q[1] - p0[1]) * (p[:, 0] - p0[0]) >= 0
                       for p0, q in [(a, b), (b, c), (c, d), (d, a)]], axis=0)

    pts = pts[inside(pts)]
    for f in (0.2, 0.5, 0.85):
        g = fluid_side_depth(sheared, conn, 0, 0.6, 0.5, n[0], n[1], f)
        level = 0.6 * n[0] + 0.5 * n[1] - g
        assert abs(np.mean(pts @ n >= level) - f) < 5e-3


def _lowest_point(coupling, x):
    """The lowest coupling point's height (points at the midpoints of nquad equal sub-segments)."""
    a, b = x[coupling.segments[:, 0]], x[coupling.segments[:, 1]]
    r = (2.0 * np.arange(coupling.nquad) + 1.0) / coupling.nquad - 1.0
    y = 0.5 * (1.0 - r)[None, :] * a[:, 1:2] + 0.5 * (1.0 + r)[None, :] * b[:, 1:2]
    return float(y.min())


def test_cylinder_force_begins_at_contact(tmp_path):
    """Constant-speed cylinder entry, 10 mm elements: zero force and no host while every coupling
    point is above the surface (measured exactly 0 at every such step), a force from the first
    force pass with a point in the water; the gap is that of the state the forces are of."""
    path = tmp_path / "cyl.yaml"
    path.write_text(DECK)
    sim = Simulation(load_model(str(path)).model)
    coupling = sim.interactions[0]
    before, after = [], []
    while sim.state.time < sim.control.end_time * (1 - 1e-12):
        gap = _lowest_point(coupling, sim.state.x) - SURFACE
        depth = -(float(sim.state.x[:, 1].min()) - SURFACE)
        sim.step()
        force = float(coupling.f_solid[:, 1].sum())
        (before if gap > 0.0 else after).append((depth, force, np.count_nonzero(coupling.host >= 0)))
    before, after = np.array(before), np.array(after)
    assert len(before) > 10 and len(after) > 10
    assert np.all(before[:, 1] == 0.0) and np.all(before[:, 2] == 0)
    assert after[0, 1] > 0.0 and after[0, 2] > 0  # the first pass with a point in the water pushes (up)
    # by s/D = 0.02 the force is a slamming force: Cs = F / (1/2 rho D V^2) in [1, 10]
    s_over_d = after[:, 0] / 0.11
    cs = after[np.searchsorted(s_over_d, 0.02), 1] / (0.5 * 1000.0 * 0.11 * V * V)
    assert 1.0 < cs < 10.0
