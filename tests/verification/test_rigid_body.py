"""Rigid parts: free fall, uniform motion and prescribed motion (2D, 3D and axisymmetric).

Central differences with the half-step velocity, v^{n+1/2} = v^{n-1/2} + (dt_{n-1/2}) a and
x^{n+1} = x^n + dt_n v^{n+1/2}, integrate a constant acceleration exactly, for constant and
for varying steps alike, and a constant velocity trivially. So a rigid part under gravity must
follow x = X + 1/2 g t^2, one with an initial velocity x = X + v0 t, and one with a prescribed
velocity the integral of it, all to round-off: the position error is held to 1e-12 of the size
of the coordinates (plus displacement) over about 1000 steps. A deformable part falling beside
the rigid one must do the same, stress free. In an axisymmetric deck (x = r) a rigid part is a
body of revolution that moves along the axis only.
"""
from __future__ import annotations

import numpy as np
import pytest

pytestmark = pytest.mark.usefixtures("single_thread")

G = {2: [0.0, -9.81], 3: [0.0, 0.0, -9.81], "axisymmetric": [0.0, -9.81]}
SIZE = 0.7  # largest coordinate of the models below


def deck(dim: int | str, extra: str, end_time: float = 0.5, with_solid: bool = False) -> str:
    if dim in (2, "axisymmetric"):
        box = "{min: [0, 0], max: [0.2, 0.1], divisions: [4, 2]}"
        box2 = "{min: [0.5, 0], max: [0.7, 0.1], divisions: [2, 2]}"
    else:
        box = "{min: [0, 0, 0], max: [0.2, 0.1, 0.1], divisions: [4, 2, 2]}"
        box2 = "{min: [0.5, 0, 0], max: [0.7, 0.1, 0.1], divisions: [2, 2, 2]}"
    solid = f"\n  block: {{material: rubber, section: solid, geometry: {{box: {box2}}}}}" if with_solid else ""
    return f"""
dimension: {dim}
control: {{end_time: {end_time}}}
materials:
  steel: {{type: rigid, density: 7850.0, youngs_modulus: 2.0e11, poisson_ratio: 0.3}}
  rubber: {{type: elastic, density: 1000.0, youngs_modulus: 2.0e6, poisson_ratio: 0.45}}
sections:
  solid: {{type: solid}}
parts:
  body: {{material: steel, section: solid, geometry: {{box: {box}}}}}{solid}
{extra}"""


def run(sim, check):
    """Step to the end, calling check(t, x) after every step."""
    sim.run(lambda st: check(st.time, st.x))
    assert sim.state.step >= 100


@pytest.mark.parametrize("dim", [2, 3, "axisymmetric"])
def test_free_fall(dim, sim_from_deck):
    g = np.array(G[dim])
    sim = sim_from_deck(deck(dim, f"loads:\n  - {{type: gravity, acceleration: {G[dim]}}}\n", with_solid=True))
    X = sim.model.coordinates
    worst = [0.0]

    def check(t, x):
        exact = X + 0.5 * g * t * t
        worst[0] = max(worst[0], np.abs(x - exact).max() / (SIZE + 0.5 * 9.81 * t * t))

    run(sim, check)
    st = sim.state
    print(f"\n{dim} free fall: largest position error {worst[0]:.1e} (relative to coordinates + drop) over {st.step} steps")
    assert worst[0] <= 1e-12
    # the velocity held is the half-step one, v^{n+1/2} = g (t - dt/2) (the last step is shortened)
    assert np.allclose(st.v, g * (st.time - 0.5 * st.dt_prev), rtol=0, atol=1e-12 * 9.81 * st.time)
    # the deformable block fell with it, stress free
    assert np.abs(st.stress).max() <= 1e-12 * 2.0e6


@pytest.mark.parametrize("dim", [2, 3, "axisymmetric"])
def test_initial_velocity_is_kept(dim, sim_from_deck):
    v0 = np.array([0.0, -1.0]) if dim == "axisymmetric" else np.array([3.0, -1.0, 0.5][:dim])
    sim = sim_from_deck(deck(dim, f"initial:\n  - {{type: velocity, part: body, velocity: {v0.tolist()}}}\n"))
    X = sim.model.coordinates
    worst = [0.0]

    def check(t, x):
        worst[0] = max(worst[0], np.abs(x - (X + v0 * t)).max() / (SIZE + np.abs(v0).max() * t))

    run(sim, check)
    assert worst[0] <= 1e-12
    assert np.allclose(sim.state.v, v0, rtol=0, atol=1e-12)


@pytest.mark.parametrize("dim", [2, 3])
def test_prescribed_velocity_moves_the_body(dim, sim_from_deck):
    """x velocity prescribed on a ramp (piecewise linear, kinks on step boundaries), the vertical
    direction left free under gravity: x follows the integral of the ramp, y or z free fall."""
    free = [None] * (dim - 1)
    extra = f"""curves:
  ramp: {{points: [[0.0, 0.0], [0.1, 1.0], [1.0, 1.0]]}}
boundaries:
  - {{type: prescribed_velocity, part: body, velocity: {[2.0] + free}, curve: ramp}}
loads:
  - {{type: gravity, acceleration: {G[dim]}}}
""".replace("None", "null")
    sim = sim_from_deck(deck(dim, extra))
    X = sim.model.coordinates
    g = np.array(G[dim])

    def ux(t):  # integral of 2 * ramp(t)
        return t * t * 10.0 if t <= 0.1 else 0.1 + 2.0 * (t - 0.1)

    worst = [0.0]

    def check(t, x):
        exact = X + 0.5 * g * t * t
        exact[:, 0] = X[:, 0] + ux(t)
        worst[0] = max(worst[0], np.abs(x - exact).max() / (SIZE + ux(t) + 0.5 * 9.81 * t * t))

    run(sim, check)
    # the step is end_time / 1000 for an all-rigid model, so the kink at t = 0.1 is a step boundary
    assert worst[0] <= 1e-12
    assert np.allclose(sim.state.v[:, 0], 2.0, rtol=0, atol=1e-12)


@pytest.mark.parametrize("dim", [2, 3])
def test_fixed_set_of_all_its_nodes_holds_the_body(dim, sim_from_deck):
    """A `fixed` condition given by a node set that holds exactly a rigid part's nodes is the part's:
    under gravity and an initial velocity the body stays where it is (before, the nodes' flags were
    set and the body ignored them, so a 'fixed' anvil flew off under a Taylor rod)."""
    extra = f"""sets:
  all_body: {{type: node, part: body}}
boundaries:
  - {{type: fixed, set: all_body}}
loads:
  - {{type: gravity, acceleration: {G[dim]}}}
"""
    sim = sim_from_deck(deck(dim, extra, with_solid=True))
    body = sim.model.part_nodes("body")
    X = sim.model.coordinates[body]
    sim.run()
    assert sim.state.step >= 100
    assert np.array_equal(sim.state.x[body], X)


@pytest.mark.parametrize("extra_nodes", [False, True])
def test_set_with_part_of_a_rigid_body_is_a_deck_error(extra_nodes, sim_from_deck):
    """Some of a rigid part's nodes (or its nodes with a deformable part's) cannot be held apart
    from the body: a one-line model error at the boundary's set, naming the fix."""
    from sphfem_cli.driver import DeckProblem

    box = "{min: [0.0, 0.0], max: [0.6, 0.1]}" if extra_nodes else "{min: [0.0, 0.0], max: [0.05, 0.1]}"
    extra = f"""sets:
  some: {{type: node, box: {box}}}
boundaries:
  - {{type: fixed, set: some}}
"""
    with pytest.raises(DeckProblem) as err:
        sim_from_deck(deck(2, extra, with_solid=True))
    text = str(err.value)
    assert "\n" not in text and ":15:" in text  # file:line:col of the boundary's set
    assert "boundaries.0.set" in text and "rigid part 'body'" in text and "part: body" in text
    assert ("other nodes" in text) == extra_nodes
