"""`sphfem check` says what a user needs before a run: the mass of each part (SPH, ALE and solid, per
unit thickness in 2D), the contacts, couplings, boundaries and loads by kind, and the output volume."""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from sphfem_cli.cli import main

DECKS = Path(__file__).resolve().parents[2] / "decks"


@pytest.mark.parametrize("deck, fluid", [("hydrostatic_plate_sph", "water"), ("hydrostatic_plate_ale", "tank")])
def test_masses_counts_and_output_size(deck, fluid):
    result = CliRunner().invoke(main, ["check", str(DECKS / f"{deck}.yaml")])
    assert result.exit_code == 0, result.output
    out = result.output
    # a 1.0 m x 2.0 m water column (hydrostatic density within 0.1 %) on a 1.0 x 0.05 m aluminium plate
    water = float(re.search(rf"{fluid}: .* mass ([0-9.e+]+) kg/m", out).group(1))
    plate = float(re.search(r"plate: .* mass ([0-9.e+]+) kg/m", out).group(1))
    assert water == pytest.approx(2000.0, rel=2e-3) and plate == pytest.approx(1.0 * 0.05 * 2700.0, rel=1e-9)
    assert re.search(r"stable time step [0-9.e+-]+ s .* set by element \d+ of part 'plate'", out)
    assert "boundaries: " in out and "loads: 1 gravity" in out
    assert ("contacts: 1 nodes_to_surface" in out) == (deck.endswith("sph"))
    assert ("couplings: 1 lagrange_in_solid" in out) == (deck.endswith("ale"))
    assert re.search(r"output size: \d+ field steps of [0-9.]+ MiB .* results.h5 about [0-9.]+ MiB", out)


def test_a_plane_stress_part_says_so(tmp_path):
    """`check` names the formulation of a plane-stress part, and its step is the plane-stress one: longer than
    the shipped plane-strain gate's by sqrt((1 - nu)^2 / (1 - 2 nu)) = 1.342 at nu = 0.4 (same element sets it)."""
    import yaml

    deck = yaml.safe_load((DECKS / "elastic_gate_sph.yaml").read_text())
    deck["sections"]["solid"]["formulation"] = "plane_stress"
    path = tmp_path / "gate_plane_stress.yaml"
    path.write_text(yaml.safe_dump(deck, sort_keys=False))
    outputs = [CliRunner().invoke(main, ["check", str(p)]) for p in (path, DECKS / "elastic_gate_sph.yaml")]
    assert all(r.exit_code == 0 for r in outputs), [r.output for r in outputs]
    assert "gate: 165 nodes, 128 elements, material rubber, solid (plane stress)" in outputs[0].output
    assert "(plane stress)" not in outputs[1].output
    dt = [float(re.search(r"stable time step ([0-9.e+-]+) s", r.output).group(1)) for r in outputs]
    assert dt[0] / dt[1] == pytest.approx(np.sqrt(0.6**2 / 0.2), rel=1e-3)
