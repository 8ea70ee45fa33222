"""solver.domain: a new domain needs only its own class and one registration call. Point masses in
free fall run through the real loop (Simulation, RunOutput, the checkpoint's snapshot) beside a
model's solids: their path is the exact parabola, their energy balances in glstat, their table is
written with the histories and a restored run continues bit-identically."""
from __future__ import annotations

import csv

import numpy as np
import pytest

from sphfem_cli.driver import load_model
from sphfem_cli.output.results import RunOutput, history_tables
from sphfem_cli.output.snapshot import capture, restore
from sphfem_cli.solver.domain import Domain, Energies, register_domain, unregister_domain
from sphfem_cli.solver.explicit import Simulation

DECK = """\
title: a resting rigid block (the toy domain's host model)
units: {length: m, mass: kg, time: s}
dimension: 2
control: {end_time: 0.5}
materials:
  steel: {type: rigid, density: 7850.0, youngs_modulus: 2.1e11, poisson_ratio: 0.3}
sections:
  solid: {type: solid}
parts:
  block: {material: steel, section: solid, geometry: {box: {min: [0, 0], max: [1, 1], divisions: [1, 1]}}}
output: {interval: 0.1, history_interval: 0.01}
"""

G = np.array([0.0, -9.81])
X0 = np.array([[0.0, 10.0], [2.0, 5.0], [-1.0, 0.0]])
V0 = np.array([[1.0, 0.0], [0.0, 3.0], [-2.0, -1.0]])
MASS = np.array([1.0, 2.0, 0.5])


class FallingPoints(Domain):
    """Point masses under a constant acceleration g, touching nothing.

    Leapfrog with the loop's dt and dt_avg: v^{n+1/2} = v^{n-1/2} + dt_avg g, x^{n+1} = x^n + dt v^{n+1/2},
    v^{-1/2} = v0. The dt_avg of steps 0..n sum to t_n + dt_n/2, so x^n = x0 + v0 t_n + g t_n^2/2 for any
    sequence of steps; v(t_n) = v^{n-1/2} + g dt_{n-1}/2 = v0 + g t_n, and the work of gravity
    m g.(x - x0) equals the change of kinetic energy exactly.
    """

    kind = "points"
    label = "point-mass"

    def __init__(self, x0, v0, mass, g, dt_scale):
        self.x0, self.v0, self.mass, self.g = x0.copy(), v0.copy(), mass.copy(), g.copy()
        self.x, self.v_half = x0.copy(), v0.copy()
        self.dt_scale = dt_scale
        self.dt_last = 0.0

    def stable_dt(self, scale: float) -> float:
        return scale * self.dt_scale / (1.0 + float(np.abs(self.v_half).max()))  # varies from step to step

    def advance(self, t: float, dt: float, dt_avg: float) -> None:
        self.v_half += dt_avg * self.g
        self.x += dt * self.v_half
        self.dt_last = dt

    def velocity(self) -> np.ndarray:
        return self.v_half + 0.5 * self.dt_last * self.g

    def energies(self) -> Energies:
        v = self.velocity()
        return Energies(kinetic=0.5 * float(np.sum(self.mass[:, None] * v * v)),
                        work=float(np.sum(self.mass[:, None] * self.g * (self.x - self.x0))))

    def state_arrays(self) -> dict[str, np.ndarray]:
        return {"point positions": self.x, "point velocities": self.v_half}

    def history_tables(self) -> list[tuple[str, list[str]]]:
        return [("points", [f"p{i}_{a}" for i in range(len(self.x)) for a in "xy"])]

    def history_rows(self) -> list[list[float]]:
        return [list(self.x.ravel())]


@pytest.fixture
def points():
    # the one registration: how to build it, and the history table it adds
    register_domain("points", lambda sim: FallingPoints(X0, V0, MASS, G, 0.02), lambda model: ["points"])
    yield
    unregister_domain("points")


@pytest.fixture
def deck(tmp_path):
    path = tmp_path / "block.yaml"
    path.write_text(DECK)
    return path


def test_point_masses_fall_on_the_exact_parabola_and_balance_their_energy(points, deck, tmp_path):
    sim = Simulation(load_model(str(deck)).model)
    assert [d.kind for d in sim.domains] == ["solid", "points"]
    assert history_tables(sim.model) == ["glstat", "matsum", "points"]  # the folder's manifest lists it
    out = RunOutput(sim, tmp_path / "out")
    out()
    steps = []
    sim.run(on_step=lambda st: (steps.append(st.dt_prev), out()), next_stop=out.next_field_time)
    out(force=True)
    out.close()
    t = sim.state.time
    pts = sim.domain("points")
    assert t == pytest.approx(0.5, rel=1e-12) and len(set(steps)) > 10  # many different steps
    np.testing.assert_allclose(pts.x, X0 + V0 * t + 0.5 * G * t * t, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(pts.velocity(), V0 + G * t, rtol=1e-12, atol=1e-12)
    assert sim.limiter == "points"

    with open(tmp_path / "out" / "histories" / "glstat.csv") as fh:
        glstat = list(csv.DictReader(fh))
    ke0 = 0.5 * float(np.sum(MASS[:, None] * V0 * V0))
    ke_end = 0.5 * float(np.sum(MASS[:, None] * (V0 + G * t) ** 2))
    assert float(glstat[0]["kinetic"]) == pytest.approx(ke0, rel=1e-10)  # the CSV keeps 11 digits
    assert float(glstat[-1]["kinetic"]) == pytest.approx(ke_end, rel=1e-10)
    assert all(abs(float(row["energy_ratio"]) - 1.0) < 1e-10 for row in glstat)
    row = sim.energy_row()
    assert row.kinetic == pytest.approx(ke_end, rel=1e-12) and abs(row.ratio - 1.0) < 1e-13

    with open(tmp_path / "out" / "histories" / "points.csv") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["time", "p0_x", "p0_y", "p1_x", "p1_y", "p2_x", "p2_y"]
    assert len(rows) == len(glstat) + 1
    np.testing.assert_allclose([float(v) for v in rows[-1][1:]], pts.x.ravel(), rtol=1e-10)


def test_a_restored_run_of_the_new_domain_continues_bit_identically(points, deck):
    sim = Simulation(load_model(str(deck)).model)
    for _ in range(5):
        sim.step()
    tree, arrays = capture(sim)
    fresh = Simulation(load_model(str(deck)).model)
    restore(tree, [a.copy() for a in arrays], fresh)
    for _ in range(5):
        sim.step()
        fresh.step()
    assert np.array_equal(sim.domain("points").x, fresh.domain("points").x)
    assert sim.state.time == fresh.state.time and sim.domain("points").dt_last == fresh.domain("points").dt_last


def test_a_non_finite_state_of_the_new_domain_stops_the_run(points, deck):
    from sphfem_cli.solver.guards import RunStopped

    sim = Simulation(load_model(str(deck)).model)
    sim.step()
    sim.domain("points").x[1, 0] = np.nan
    with pytest.raises(RunStopped, match=r"non-finite point positions \(row 1\)"):
        sim.step()


def test_nothing_below_model_reads_the_deck():
    """Settings reach the solver, its domains, the output and the physics folders as model.options
    (model/options.py), never as `<something>.deck` (importing schema types is not reading a deck)."""
    import re
    from pathlib import Path

    root = Path(__file__).parents[2] / "sphfem_cli"
    reads = re.compile(r"(?<!\.)\.deck\b")
    found = [f"{path.relative_to(root)}:{n}: {line.strip()}"
             for folder in ("solver", "output", "sph", "ale", "contact")
             for path in sorted((root / folder).glob("**/*.py"))
             for n, line in enumerate(path.read_text().splitlines(), 1)
             if reads.search(line.split("#")[0])]
    assert not found, "\n".join(found)
