"""Solver pieces on tiny models: load resultants, determinism across thread counts, imported meshes."""
from __future__ import annotations

from pathlib import Path

import numba
import numpy as np
import pytest

from sphfem_cli.driver import load_model
from sphfem_cli.solver.explicit import Simulation

DATA = Path(__file__).parents[1] / "data"

BLOCK_2D = """
dimension: 2
control: {end_time: 1.0e-4}
materials:
  steel: {type: elastic, density: 7850.0, youngs_modulus: 2.1e11, poisson_ratio: 0.3}
sections:
  solid: {type: solid}
parts:
  block: {material: steel, section: solid, geometry: {box: {min: [0, 0], max: [0.2, 0.1], divisions: [8, 4]}}}
sets:
  top: {type: segment, part: block, side: top}
  right: {type: node, part: block, side: right}
  base: {type: node, part: block, side: bottom}
boundaries:
  - {type: fixed, set: base}
loads:
  - {type: pressure, set: top, value: 2.0e6}
  - {type: nodal_force, set: right, force: [100.0, 0.0]}
  - {type: gravity, acceleration: [0.0, -9.81]}
"""

BLOCK_3D = """
dimension: 3
control: {end_time: 1.0e-4}
materials:
  steel: {type: elastic, density: 7850.0, youngs_modulus: 2.1e11, poisson_ratio: 0.3}
sections:
  solid: {type: solid}
parts:
  block: {material: steel, section: solid, geometry: {box: {min: [0, 0, 0], max: [0.2, 0.1, 0.3], divisions: [4, 2, 3]}}}
sets:
  top: {type: segment, part: block, side: top}
loads:
  - {type: pressure, set: top, value: 1.0e6}
"""


def build(tmp_path, text, name="deck.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return load_model(str(path)).model


def test_load_resultants_2d(tmp_path):
    """Pressure p on the top edge (width w, unit thickness) pushes down with p w; nodal force on each node."""
    model = build(tmp_path, BLOCK_2D)
    sim = Simulation(model)
    f = sim.state.f_ext.sum(axis=0)
    n_right = len(model.node_sets["right"])
    weight = model.mass.sum() * 9.81
    assert model.mass.sum() == pytest.approx(7850.0 * 0.2 * 0.1, rel=1e-12)
    assert f[0] == pytest.approx(100.0 * n_right, rel=1e-12)
    assert f[1] == pytest.approx(-2.0e6 * 0.2 - weight, rel=1e-12)


def test_pressure_resultant_3d(tmp_path):
    model = build(tmp_path, BLOCK_3D)
    f = Simulation(model).state.f_ext.sum(axis=0)
    assert f == pytest.approx([0.0, -1.0e6 * 0.2 * 0.3, 0.0], abs=1e-6)


def test_results_identical_for_one_and_two_threads(tmp_path):
    """Element results are gathered at nodes in a fixed order, so the thread count changes nothing."""
    text = BLOCK_2D.replace("end_time: 1.0e-4", "end_time: 2.0e-5")
    states = []
    default = numba.get_num_threads()
    try:
        for threads in (1, min(2, numba.config.NUMBA_NUM_THREADS)):
            numba.set_num_threads(threads)
            sim = Simulation(build(tmp_path, text))
            sim.run()
            states.append((sim.state.x.copy(), sim.state.stress.copy(), sim.energy_row().values()))
    finally:
        numba.set_num_threads(default)
    (x1, s1, e1), (x2, s2, e2) = states
    assert np.array_equal(x1, x2) and np.array_equal(s1, s2) and e1 == e2


def test_static_pressure_equilibrium_with_damping_free_average(tmp_path):
    """Under a suddenly applied pressure the block oscillates about the static strain: the time mean of
    the vertical stress in the elements tends to -p (here within 5 % over a few periods)."""
    text = BLOCK_2D.replace("end_time: 1.0e-4", "end_time: 4.0e-4").replace(
        "  - {type: nodal_force, set: right, force: [100.0, 0.0]}\n  - {type: gravity, acceleration: [0.0, -9.81]}\n", "")
    sim = Simulation(build(tmp_path, text))
    samples = []
    sim.run(on_step=lambda st: samples.append(st.stress[:, 1].mean()))
    assert np.mean(samples[len(samples) // 4:]) == pytest.approx(-2.0e6, rel=0.05)


def test_imported_mesh_part(tmp_path):
    """A part meshed from an Abaqus .inp file through meshio; the mesh's sets are exposed as part.set."""
    deck = f"""
dimension: 3
control: {{end_time: 1.0e-6}}
materials:
  steel: {{type: elastic, density: 7850.0, youngs_modulus: 2.1e11, poisson_ratio: 0.3}}
sections:
  solid: {{type: solid}}
parts:
  brick: {{material: steel, section: solid, geometry: {{file: {{file: {DATA / 'hex_2x1x1.inp'}, scale: 2.0}}}}}}
"""
    model = build(tmp_path, deck)
    assert model.n_elements == 2 and model.connectivity.shape[1] == 8
    assert np.all(model.volume0 > 0)
    Simulation(model).run()
