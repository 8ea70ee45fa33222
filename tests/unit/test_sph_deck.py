"""SPH parts through the deck and the explicit loop: run output, probes, deck errors (what a scene compiles: test_only_what_is_needed.py)."""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from sphfem_cli.cli import main

DECKS = Path(__file__).parents[2] / "decks"

TANK = """
title: Small still tank
dimension: 2
control: {end_time: 0.02}
equations_of_state:
  water: {type: tait, reference_density: 1000.0, sound_speed: 20.0}
materials:
  water: {type: fluid, density: 1000.0, eos: water}
sections:
  fluid: {type: sph}
parts:
  pool: {material: water, section: fluid, geometry: {box: {min: [0, 0], max: [0.1, 0.05]}}, spacing: 0.005,
         hydrostatic: true}
boundaries:
  - {type: wall, min: [0, 0], max: [0.1, 0.2], sides: [left, right, bottom]}
loads:
  - {type: gravity, acceleration: [0, -9.81]}
output:
  interval: 0.01
  probes:
    - {name: p_floor, type: pressure, point: [0.05, 0.0025]}
    - {name: level, type: surface_height, gauge: 0.05}
    - {name: front, type: front}
"""


def invoke(args):
    result = CliRunner().invoke(main, args)
    assert "Traceback" not in (result.output or "")
    return result


def test_tank_runs_and_writes_particles(tmp_path):
    deck = tmp_path / "tank.yaml"
    deck.write_text(TANK)
    out = tmp_path / "out"
    result = invoke(["run", str(deck), "-o", str(out), "-q"])
    assert result.exit_code == 0, result.output
    import h5py

    with h5py.File(out / "results.h5", "r") as h5:
        assert h5["pool"].attrs["topology"] == "Polyvertex"
        last = sorted(k for k in h5["pool"] if k.startswith("step_"))[-1]
        assert h5[f"pool/{last}/coordinates"].shape == (200, 3)
        for name in ("velocity", "density", "pressure", "mass", "smoothing_length", "active"):
            assert name in h5[f"pool/{last}/point"], name
    # Hydrostatic start: the floor pressure is close to rho g H = 490.5 Pa and the level stays at H.
    p = np.loadtxt(out / "histories" / "p_floor.csv", delimiter=",", skiprows=1)
    level = np.loadtxt(out / "histories" / "level.csv", delimiter=",", skiprows=1)
    front = np.loadtxt(out / "histories" / "front.csv", delimiter=",", skiprows=1)
    assert p[-1, 1] == pytest.approx(1000 * 9.81 * (0.05 - 0.0025), rel=0.1)
    assert level[-1, 1] == pytest.approx(0.05, abs=0.005)
    assert front[-1, 1] == pytest.approx(0.0975, abs=0.003)
    # A tank at rest has almost no energy to compare with: measure the balance error against the
    # column's potential-energy scale M g H / 2 instead of the energy ratio.
    glstat = np.genfromtxt(out / "histories" / "glstat.csv", delimiter=",", names=True)
    reference = glstat["total"][-1] / glstat["energy_ratio"][-1]
    scale = 1000 * 0.1 * 0.05 * 9.81 * 0.05 / 2
    assert abs(glstat["total"][-1] - reference) < 0.01 * scale


@pytest.mark.parametrize("change, where", [
    (("spacing: 0.005,\n", "\n"), r"parts\.pool: an SPH part needs 'spacing'"),
    (("{type: fluid, density: 1000.0, eos: water}",
      "{type: elastic, density: 1000.0, youngs_modulus: 1.0e9, poisson_ratio: 0.3}"),
     r"parts\.pool\.material: an SPH part needs a material of type fluid"),
    (("sides: [left, right, bottom]", "sides: [left, front]"), r"boundaries\[0\]\.sides: back and front walls exist only in 3D"),
    (("{name: front, type: front}", "{name: front, type: pressure}"), r"output\.probes\[2\]\.point: a pressure probe needs 'point'"),
    (("fluid: {type: sph}", "fluid: {type: sph, artificial_viscosity: {alpha: 0.1, switch: {alpha_max: 0.05}}}"),
     r"sections\.fluid\.artificial_viscosity\.switch: alpha_max 0\.05 must exceed alpha 0\.1"),
    (("fluid: {type: sph}", "fluid: {type: sph, artificial_viscosity: {alpha: 0, switch: {}}}"),
     r"sections\.fluid\.artificial_viscosity\.alpha: a viscosity switch needs alpha > 0"),
])
def test_bad_sph_decks(tmp_path, change, where):
    deck = tmp_path / "bad.yaml"
    deck.write_text(TANK.replace(*change))
    result = invoke(["check", str(deck)])
    assert result.exit_code == 65, result.output
    assert len(result.output.strip().splitlines()) == 1
    assert re.match(rf"^{re.escape(str(deck))}:\d+:\d+: {where}", result.output), result.output
