"""An ALE part through the deck and the explicit loop, checked against the exact water-air star state."""
from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest
from click.testing import CliRunner

from sphfem_cli.cli import main

DECK = Path(__file__).parents[2] / "decks" / "water_air_shock_tube.yaml"


def test_water_air_shock_tube_deck(tmp_path):
    """Saurel & Abgrall (1999) star state (../shared/reference/README.md): p* = 1.4190e7 Pa,
    u* = 482.61 m/s at 240 us; tolerance 2 % as issue 4 states, observed about 0.1 %."""
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["run", str(DECK), "-o", str(out), "-q"])
    assert result.exit_code == 0, result.output
    with h5py.File(out / "results.h5", "r") as h5:
        grid = h5["tube"]
        last = sorted(k for k in grid if k.startswith("step_"))[-1]
        assert h5["times"][-1] == pytest.approx(2.4e-4, rel=1e-9)
        x = grid[f"{last}/coordinates"][:, 0]
        centres = x[grid["connectivity"][:]].mean(axis=1)
        pressure = grid[f"{last}/cell/pressure"][:]
        velocity = grid[f"{last}/point/velocity"][:, 0]
        assert {"fraction_water", "fraction_air", "density_water", "pressure_air"} <= set(grid[f"{last}/cell"])
    star = (centres > 0.78) & (centres < 0.81)
    assert pressure[star].mean() == pytest.approx(1.4190e7, rel=0.02)
    assert velocity[(x > 0.78) & (x < 0.81)].mean() == pytest.approx(482.61, rel=0.02)
    glstat = np.genfromtxt(out / "histories" / "glstat.csv", delimiter=",", names=True)
    assert abs(glstat["energy_ratio"][-1] - 1.0) < 1e-6


@pytest.mark.parametrize("change, message", [
    (("  water: {type: fluid, density: 1000.0, eos: water}",
      "  water: {type: elastic, density: 1000.0, youngs_modulus: 1.0e9, poisson_ratio: 0.3}"),
     "parts.tube.fill[1].material: ALE materials are fluid or void, 'water' is elastic"),
    (("output:", "curves:\n  ramp: {points: [[0, 0], [1, 1]]}\nloads:\n  - {type: gravity, acceleration: [0, -9.81], curve: ramp}\noutput:"),
     "loads[0].curve: gravity on ALE parts is constant (no curve)"),
])
def test_bad_ale_decks(tmp_path, change, message):
    deck = tmp_path / "bad.yaml"
    deck.write_text(DECK.read_text().replace(*change))
    result = CliRunner().invoke(main, ["check", str(deck)])
    assert result.exit_code == 65, result.output
    assert message in result.output and len(result.output.strip().splitlines()) == 1


SECTION = "  ale: {type: ale_multi_material, advection: van_leer, interface: slic, closure: relax}"


def test_courant_is_a_deprecated_name_of_timestep_scale(tmp_path):
    """The ALE section's step fraction is timestep_scale, as for solids, SPH and contacts; the old
    key courant is still read as it, with a warning, and giving both is a deck error."""
    steps = {}
    for key in ("timestep_scale", "courant"):
        deck = tmp_path / f"{key}.yaml"
        deck.write_text(DECK.read_text().replace(SECTION, SECTION[:-1] + f", {key}: 0.25}}"))
        result = CliRunner().invoke(main, ["check", str(deck)])
        assert result.exit_code == 0, result.output
        assert ("deprecated name of timestep_scale" in result.stderr) == (key == "courant")
        steps[key] = [line for line in result.stdout.splitlines() if "stable time step" in line]
    assert steps["courant"] == steps["timestep_scale"] and steps["courant"]
    both = tmp_path / "both.yaml"
    both.write_text(DECK.read_text().replace(SECTION, SECTION[:-1] + ", courant: 0.25, timestep_scale: 0.25}"))
    result = CliRunner().invoke(main, ["check", str(both)])
    assert result.exit_code == 65, result.output
    assert "sections.ale.courant: courant is the deprecated name of timestep_scale" in result.output
    assert len(result.output.strip().splitlines()) == 1
