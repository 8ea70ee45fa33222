"""Underwater explosion on a clamped steel plate: decks/underwater_explosion_ale.yaml and its SPH
twin decks/underwater_explosion_sph.yaml (particles at the ALE element centres), both to 1.3 ms,
past the plate's maximum.

Checks: the histories are written, the plate centre moves away from the charge (+y), reaches its
maximum before the end and is coming back at it (ALE 68.4 mm at 1.05 ms in the larger tank with
non-reflecting sides, 66.9 mm at 1.01 ms in the smaller transmitting one; SPH 70.86 mm in the same larger
tank, 7 December 2026, 59.3 mm at 1.13 ms in the old smaller free-surface tank; with the 120 x 4 plate), it yields (von Mises above the 300 MPa yield stress); the ALE
energy ratio falls as the waves leave through the open sides (0.72 at 1.3 ms, 0.56 in the smaller
tank, so only a lower bound), the SPH one stays near 1; the
peak water pressure falls with distance from the charge: at half the stand-off it exceeds the
peak at the plate, and both are below the CJ pressure (21 GPa). No absolute pressure reference:
Cole's P = 52.4 (W^(1/3)/R)^1.13 MPa is for a spherical charge; the 2D charge is an infinite
cylinder, whose pressure decays more slowly (about R^-1/2 acoustically). The two variants agree
on the plate's displacement at 100 us (ALE 3.79 mm, SPH 3.49 mm measured) within 25 %.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from sphfem_cli.driver import load_model
from sphfem_cli.cli import main
from sphfem_cli.solver.explicit import Simulation

DECK = Path(__file__).parents[2] / "decks" / "underwater_explosion_ale.yaml"
DECK_SPH = DECK.with_name("underwater_explosion_sph.yaml")
U100_ALE = 3.79e-3  # plate-centre displacement at 100 us, ALE deck (its header; 3.82e-3 with the 60 x 2 plate)
MAX_ALE = 68.42e-3  # the plate centre's maximum, ALE deck in the larger tank with non-reflecting sides (its header)


def run(deck: Path, out: Path):
    result = CliRunner().invoke(main, ["run", str(deck), "-o", str(out), "-q", "--threads", "1"])
    assert result.exit_code == 0, result.output
    h = np.genfromtxt(out / "histories" / "centre.csv", delimiter=",", names=True)
    g = np.genfromtxt(out / "histories" / "glstat.csv", delimiter=",", names=True)
    assert h["time"][-1] == pytest.approx(1.3e-3)
    assert np.interp(5.0e-4, h["time"], h["displacement_y"]) > 0.02  # away from the charge: 33.3 / 31.7 mm
    # past the maximum: the plate has stopped and turned back (ALE 1.01 ms, SPH 1.13 ms measured)
    first_back = h["time"][np.argmax((h["time"] > 3.0e-4) & (h["velocity_y"] <= 0.0))]
    assert 6.0e-4 < first_back < 1.25e-3
    assert h["von_mises"].max() > 3.0e8  # yielded (442 / 381 MPa measured)
    print(f"\n{deck.stem}: max displacement {h['displacement_y'].max() * 1e3:.2f} mm "
          f"(first at {first_back * 1e3:.3f} ms), peak velocity {h['velocity_y'].max():.1f} m/s, "
          f"peak von Mises {h['von_mises'].max() / 1e6:.0f} MPa")
    return h, g["energy_ratio"]


@pytest.mark.validation
def test_underwater_explosion_ale_run(tmp_path):
    h, ratio = run(DECK, tmp_path / "out")
    assert np.interp(1.0e-4, h["time"], h["displacement_y"]) == pytest.approx(U100_ALE, rel=0.05)
    assert 0.055 < h["displacement_y"].max() < 0.07  # 68.4 mm measured (66.9 in the smaller tank)
    assert 0.45 < ratio[-1] < 1.01  # waves leave through the open sides (0.721 measured; 0.562 smaller tank)


@pytest.mark.validation
def test_underwater_explosion_sph_run(tmp_path):
    out = tmp_path / "out"
    h, ratio = run(DECK_SPH, out)
    assert np.interp(1.0e-4, h["time"], h["displacement_y"]) == pytest.approx(U100_ALE, rel=0.25)
    assert 0.95 < ratio[-1] < 1.05  # 1.006 measured (0.996 with the 60 x 2 plate)
    # code to code in the same tank (open sides, the ALE deck's larger tank since 6 December 2026): 70.86 mm
    # measured (+3.6 %); 10 % covers the ALE maximum's own uncertainty (-7 % from 2.5 to 1.25 mm water, not
    # monotone; 65.6-68.2 mm over its plate series: the ALE deck's header). The old bound, 50-65 mm, was the
    # smaller free-surface tank's (59.3 mm) and failed once the scene changed.
    assert h["displacement_y"].max() == pytest.approx(MAX_ALE, rel=0.10)
    plate = np.genfromtxt(out / "histories" / "plate_pressure.csv", delimiter=",", names=True)["pressure"]
    half = np.genfromtxt(out / "histories" / "half_pressure.csv", delimiter=",", names=True)["pressure"]
    plate = plate[np.isfinite(plate)]
    half = half[np.isfinite(half)]  # NaN where no particle reaches the probe (cavitated water, late)
    print(f"SPH peak pressure: {half.max() / 1e6:.1f} MPa at 50 mm from the charge, {plate.max() / 1e6:.1f} MPa "
          "at the plate")
    assert 21e9 > half.max() > plate.max() > 1e6  # 372 > 342 MPa measured (7 December 2026; 372 > 348 before)


@pytest.mark.validation
def test_underwater_explosion_ale_pressure_falls_with_distance():
    sim = Simulation(load_model(str(DECK)).model)
    ale = sim.ale.system
    c = ale.x0[ale.conn].mean(axis=1)
    near_x = np.abs(c[:, 0] - 0.15) < 0.02
    plate_row = near_x & (c[:, 1] < 0.0) & (c[:, 1] > -0.0025)
    half_row = near_x & (np.abs(c[:, 1] + 0.05) < 0.00125)
    water = ale.n_mat and sim.ale.names.index("water")
    peak_plate = peak_half = 0.0
    while sim.state.time < 1.0e-4 * (1 - 1e-9):  # the first loading
        sim.step()
        p = ale.pressure()[:, water]
        peak_plate = max(peak_plate, p[plate_row].max())
        peak_half = max(peak_half, p[half_row].max())
    print(f"peak water pressure: {peak_half / 1e6:.1f} MPa at 50 mm from the charge, "
          f"{peak_plate / 1e6:.1f} MPa under the plate (100 mm)")
    assert 21e9 > peak_half > peak_plate > 1e6  # 380.5 > 322.0 MPa measured (60 x 2 plate: 374 > 324; pfac 0.1: 374 > 125)
