"""A rigid body with one degree of freedom: `fixed` in x with `hold_rotation` (vertical motion only).

The body (a 2D box, or a 3D block) falls under gravity while a nodal force pushes one of its
corners sideways, which alone would both push it in x and spin it. Held in x with its rotation
held too, it must do what a one-degree-of-freedom body does: fall exactly as y = Y - 1/2 g t^2
(the side force has no y component), its nodes keeping their initial shape and x to round-off.
The same deck without hold_rotation spins (so the check is not empty), and hold_rotation on a
deformable part is refused when the deck is read.
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.driver import DeckProblem

pytestmark = pytest.mark.usefixtures("single_thread")


def deck(dim: int, hold: bool, rigid: bool = True) -> str:
    if dim == 2:
        box, g, push = "{min: [0, 0], max: [0.2, 0.1], divisions: [4, 2]}", "[0.0, -9.81]", "[50.0, 0.0]"
        cmin, cmax = "[0.19, 0.09]", "[0.21, 0.11]"
    else:
        box = "{min: [0, 0, 0], max: [0.2, 0.1, 0.1], divisions: [4, 2, 2]}"
        g, push = "[0.0, -9.81, 0.0]", "[50.0, 0.0, 0.0]"
        cmin, cmax = "[0.19, 0.09, 0.09]", "[0.21, 0.11, 0.11]"
    mat = "steel" if rigid else "rubber"
    return f"""
dimension: {dim}
control: {{end_time: 0.05}}
materials:
  steel: {{type: rigid, density: 7850.0, youngs_modulus: 2.0e11, poisson_ratio: 0.3}}
  rubber: {{type: elastic, density: 1000.0, youngs_modulus: 2.0e6, poisson_ratio: 0.45}}
sections:
  solid: {{type: solid}}
parts:
  body: {{material: {mat}, section: solid, geometry: {{box: {box}}}}}
sets:
  corner: {{type: node, part: body, box: {{min: {cmin}, max: {cmax}}}}}
boundaries:
  - {{type: fixed, part: body, directions: [x], hold_rotation: {str(hold).lower()}}}
loads:
  - {{type: gravity, acceleration: {g}}}
  - {{type: nodal_force, set: corner, force: {push}}}
"""


@pytest.mark.parametrize("dim", [2, 3])
def test_vertical_only(dim, sim_from_deck):
    sim = sim_from_deck(deck(dim, hold=True))
    X = sim.model.coordinates.copy()
    g = np.zeros(dim)
    g[1] = -9.81
    worst = [0.0]

    def check(st):
        exact = X + 0.5 * g * st.time ** 2
        worst[0] = max(worst[0], float(np.abs(st.x - exact).max()))

    sim.run(check)
    assert sim.state.step >= 50
    size = 0.2 + 0.5 * 9.81 * sim.state.time ** 2
    print(f"\n{dim}D vertical-only body: largest position error {worst[0] / size:.1e} of the size, "
          f"spin {np.abs(sim.rigid.spin[0]).max():.1e}")
    assert worst[0] <= 1e-12 * size
    assert np.abs(sim.rigid.spin[0]).max() == 0.0


@pytest.mark.parametrize("dim", [2, 3])
def test_without_hold_the_body_spins(dim, sim_from_deck):
    sim = sim_from_deck(deck(dim, hold=False))
    sim.run(lambda st: None)
    assert np.abs(sim.rigid.spin[0]).max() > 1e-3  # the corner force turns it
    assert np.abs(sim.rigid.velocity[0][0]) == 0.0  # x is held either way


def test_hold_rotation_needs_a_rigid_part(sim_from_deck):
    with pytest.raises(DeckProblem, match="hold_rotation"):
        sim_from_deck(deck(2, hold=True, rigid=False))
