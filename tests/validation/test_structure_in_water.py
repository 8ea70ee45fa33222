"""The paper's section-4.1 scene, a plate in water driven at its bottom: decks/structure_in_water_{ale,sph}.yaml.

Full runs (about 20 s each on one thread). No reference data exists for this scene (the paper gives
no dimensions); the checks are the sanity of the run: the driven bottom follows the prescribed
motion, the stress is finite and positive, energy is balanced, and the water holds the plate back
against the same plate in vacuum (measured with the coupling removed: mid-height peak
displacement 0.434 mm, peak velocity 1.84 m/s).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from sphfem_cli.cli import main

DECKS = Path(__file__).parents[2] / "decks"
V = 2.0                                             # m/s, the deck's drive velocity
CURVE = np.array([[0.0, 0.0], [1e-4, 1.0], [4e-4, 1.0], [5e-4, 0.0], [1.0, 0.0]])
DRY_PEAK_DISPLACEMENT = 4.34e-4                     # m, the plate in vacuum
DRY_PEAK_VELOCITY = 1.84                            # m/s


def prescribed_displacement(t: np.ndarray) -> np.ndarray:
    """The integral of V * drive(t), exact for the piecewise-linear curve (fine sampling)."""
    s = np.linspace(0.0, float(t.max()), 200_001)
    v = V * np.interp(s, CURVE[:, 0], CURVE[:, 1])
    u = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(s))])
    return np.interp(t, s, u)


def table(out: Path, name: str) -> np.ndarray:
    return np.genfromtxt(out / "histories" / f"{name}.csv", delimiter=",", names=True)


@pytest.mark.validation
@pytest.mark.parametrize("variant", ["ale", "sph"])
def test_structure_in_water(variant, tmp_path):
    out = tmp_path / "out"
    deck = DECKS / f"structure_in_water_{variant}.yaml"
    result = CliRunner().invoke(main, ["run", str(deck), "-o", str(out), "-q", "--threads", "1"])
    assert result.exit_code == 0, result.output

    bottom = table(out, "bottom")
    expected = prescribed_displacement(bottom["time"])
    assert expected[-1] == pytest.approx(8.0e-4, rel=1e-6)
    assert np.abs(bottom["displacement_x"] - expected).max() < 0.01 * expected[-1]

    vm = table(out, "clamp")["von_mises"]
    assert np.all(np.isfinite(vm))
    assert vm[1:].min() > 0.0 and 1e6 < vm.max() < 2e8  # the elastic plate stays far from 200 MPa

    glstat = table(out, "glstat")
    assert np.all(np.abs(glstat["energy_ratio"][1:] - 1.0) < 0.05)

    mid = table(out, "mid")
    peak_u = np.abs(mid["displacement_x"]).max()
    peak_v = np.abs(mid["velocity_x"]).max()
    assert 0.4 * DRY_PEAK_DISPLACEMENT < peak_u < DRY_PEAK_DISPLACEMENT  # the water holds it back
    assert peak_v < DRY_PEAK_VELOCITY
