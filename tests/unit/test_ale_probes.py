"""Probes in an ALE part (output.probes): pressure, the mixture pressure of the element at the
point, checked on a water column at rest under gravity (hydrostatic ALE fill) against
rho g (H - y) at the element centre; front, the furthest reach of a material, checked on the same
column (its top, exactly) and the dam break (tests/verification/test_dam_break_methods.py)."""
from __future__ import annotations

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from sphfem_cli.cli import main

DECK = {
    "dimension": 2,
    "control": {"end_time": 0.02},
    "equations_of_state": {"water": {"type": "linear_polynomial", "c1": 2.2e9}},
    "materials": {"water": {"type": "fluid", "density": 1000.0, "eos": "water"}, "void": {"type": "void"}},
    "sections": {"fluid": {"type": "ale_multi_material"}},
    "parts": {"tank": {"material": "void", "section": "fluid", "hydrostatic": True,
                       "geometry": {"box": {"min": [0.0, 0.0], "max": [0.2, 1.2], "element_size": 0.05}},
                       "fill": [{"material": "water", "box": {"min": [0.0, 0.0], "max": [0.2, 1.0]}}]}},
    "boundaries": [{"type": "ale_boundary", "part": "tank", "sides": ["left", "right", "bottom"], "condition": "slip"}],
    "loads": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
    "output": {"history_interval": 0.002, "probes": [
        {"name": "deep", "type": "pressure", "point": [0.1, 0.125]},
        {"name": "mid", "type": "pressure", "point": [0.1, 0.525], "part": "tank"},
        {"name": "top", "type": "front", "axis": "y", "material": "water"}]},
}


def test_ale_pressure_probes_read_the_hydrostatic_pressure(tmp_path):
    deck = tmp_path / "tank.yaml"
    deck.write_text(yaml.safe_dump(DECK))
    result = CliRunner().invoke(main, ["run", str(deck), "-o", str(tmp_path / "out"), "-q", "--threads", "1"])
    assert result.exit_code == 0, result.output
    for name, y in (("deep", 0.125), ("mid", 0.525)):
        h = np.genfromtxt(tmp_path / "out" / "histories" / f"{name}.csv", delimiter=",", names=True)
        assert len(h) > 5
        np.testing.assert_allclose(h["pressure"], 1000.0 * 9.81 * (1.0 - y), rtol=1e-3)
    top = np.genfromtxt(tmp_path / "out" / "histories" / "top.csv", delimiter=",", names=True)
    np.testing.assert_allclose(top["front"], 1.0, atol=1e-6)


@pytest.mark.parametrize("probe, message", [
    ({"name": "f", "type": "front"}, "a front probe in an ALE part needs 'material'"),
    ({"name": "f", "type": "front", "material": "air"}, "unknown material 'air'"),
    ({"name": "f", "type": "surface_height", "gauge": 0.1}, "surface_height probes measure SPH parts"),
    ({"name": "p", "type": "pressure", "point": [0.1, 0.1], "material": "water"}, "only a front probe"),
    ({"name": "p", "type": "pressure", "point": [0.1, 0.1], "part": "nope"}, "unknown part 'nope'"),
])
def test_probes_an_ale_part_cannot_take(tmp_path, probe, message):
    deck = dict(DECK, output={"probes": [probe]})
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(deck))
    result = CliRunner().invoke(main, ["check", str(path)])
    assert result.exit_code == 65 and message in result.output, result.output
