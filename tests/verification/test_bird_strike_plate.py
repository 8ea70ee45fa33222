"""decks/bird_strike_axisymmetric_plate_{sph,ale,lagrangian}.yaml: a water bird (D 0.1 m, L 0.2 m, 1.571 kg, 100 m/s)
onto a clamped 4 mm aluminium 2024-T3 plate of radius 0.25 m, r-z; figures from
docs/studies/bird_strike_plate.py (docs/studies/bird_strike_plate.md). The reference values below are read from
tests/data/bird_strike_axisymmetric_plate.yaml and tests/data/bird_strike_axisymmetric.yaml (sources, how each
was obtained and the resolution study: the .md files beside them).

What is checked, with the tolerance and where it comes from:

* energy balance of the SPH deck (no outflow there): |energy ratio - 1| <= 1 % at every glstat row
  (measured at most 0.02 %, 7 December 2026);
* the peak centre deflection against the SPH deck at dx 1.25 mm (the finest fluid level, 30.04 mm with the
  viscous plate): within 3 % (the fluid series 30.48 / 29.89 / 30.04 mm is not monotone; the shipped 5 mm is
  +1.5 %; soft_scale 0.03-1.0 moves it by 1.0 %, the deck's header);
* the permanent centre deflection (mean over 3.5-5 ms) against the same run's 22.48 mm: within 8 % (the
  shipped 5 mm reads +4.8 %; the series 23.56 / 22.56 / 22.48 mm converges, order 3.7, GCI 0.04 % on the
  finest; tests/data/bird_strike_axisymmetric_plate.md);
* the peak against the rigid-plastic membrane estimate (study, "Independent estimate"): 26.6-35.7 mm over
  the flow stresses 496-369 MPa;
* the impulse of the bird on the plate within 15 % of m v = 157.1 N s (measured 1.05-1.10 m v over the fluid series: the plate's
  spring-back throws water back, so it exceeds m v);
* plastic but not torn: plastic strain at the centre > 1 % and the largest in the plate below 18 % (a
  typical elongation at break of 2024-T3 sheet; the decks have no failure model).

All three are behind -m validation: the SPH deck runs whole (5 ms, 32-50 s CPU warm, by the load; the default
suite runs its first steps in tests/regression), the ALE deck (about 300 s CPU) and the Lagrangian bird (about
170 s) are checked against the SPH figures (code to
code: peak within 5 %, permanent within 10 %).
"""
from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from sphfem_cli import api
from tests.reference_data import value

DECKS = Path(__file__).parents[2] / "decks"
PLATE = "bird_strike_axisymmetric_plate"  # tests/data/bird_strike_axisymmetric_plate.{yaml,md}: values, sources
MOMENTUM = value("bird_strike_axisymmetric", "momentum")  # m v of the bird, N s (Wilbeck 1978)
PERMANENT = (3.5e-3, 5.0e-3)  # s, after the bird has gone
SPH_FINEST = {"peak": value(PLATE, "sph_finest_peak_deflection"),  # m: SPH dx 1.25 mm, plate 100 x 4
              "permanent": value(PLATE, "sph_finest_permanent_deflection")}  # (computed, 7 December 2026)
MEMBRANE_BAND = (value(PLATE, "membrane_peak_low"), value(PLATE, "membrane_peak_high"))  # m: flow stress 496, 369 MPa
ELONGATION = value(PLATE, "elongation_at_break")  # 2024-T3 sheet, typical (a plausibility bound)


def strike(deck: str, folder: Path) -> dict:
    result = api.run(DECKS / deck, folder, threads=1)
    assert result.completed, result.message
    hist = result.histories()
    t, w = hist["centre"]["time"], -hist["centre"]["displacement_y"]
    late = (t >= PERMANENT[0]) & (t <= PERMANENT[1])
    with h5py.File(result.folder / "results.h5") as f:
        plate = f["plate"]
        strain = max(float(plate[s]["cell"]["plastic_strain"][:].max()) for s in plate if s.startswith("step"))
    return {"peak": float(w.max()), "permanent": float(w[late].mean()),
            "impulse": float(np.trapezoid(-hist["plate"]["contact_force_y"], hist["plate"]["time"])) / MOMENTUM,
            "energy_err": float(np.abs(hist["glstat"]["energy_ratio"] - 1.0).max()),
            "centre_strain": float(hist["centre"]["plastic_strain"][-1]), "max_strain": strain}


@pytest.mark.validation
def test_sph_bird_on_plate(tmp_path):
    got = strike("bird_strike_axisymmetric_plate_sph.yaml", tmp_path / "sph")
    print("SPH 5 mm, plate 100 x 4:", {k: round(v, 5) for k, v in got.items()})
    assert got["energy_err"] < 0.01, got
    assert got["peak"] == pytest.approx(SPH_FINEST["peak"], rel=0.03), got
    assert got["permanent"] == pytest.approx(SPH_FINEST["permanent"], rel=0.08), got
    assert MEMBRANE_BAND[0] <= got["peak"] <= MEMBRANE_BAND[1], got
    assert got["permanent"] < got["peak"], got
    assert abs(got["impulse"] - 1.0) < 0.15, got
    assert 0.01 < got["centre_strain"] and got["max_strain"] < ELONGATION, got


@pytest.mark.validation
@pytest.mark.parametrize("deck, strain_limit, energy_limit",
                         [("bird_strike_axisymmetric_plate_ale.yaml", ELONGATION, None),
                          ("bird_strike_axisymmetric_plate_lagrangian.yaml", None, 0.01)], ids=["ale", "lagrangian"])
def test_bird_on_plate_against_sph(tmp_path, deck, strain_limit, energy_limit):
    """The shipped 2.5 mm ALE deck (about 300 s CPU) and Lagrangian bird (about 170 s) against the SPH deck's finest
    figures, code to code. The Lagrangian bird's largest plastic strain is not bounded: its crushed and eroded
    elements next to the axis dent the plate's first element (0.55 / 0.30 at 5 / 2.5 mm, falling with the bird's
    element; docs/studies/bird_strike_plate.md, "The Lagrangian bird"). The ALE deck's energy balance is not checked:
    its water leaves through the transmitting sides."""
    got = strike(deck, tmp_path / "run")
    print(deck, "2.5 mm, plate 100 x 4:", {k: round(v, 5) for k, v in got.items()})
    assert got["peak"] == pytest.approx(SPH_FINEST["peak"], rel=0.05), got
    assert got["permanent"] == pytest.approx(SPH_FINEST["permanent"], rel=0.10), got
    assert MEMBRANE_BAND[0] <= got["peak"] <= MEMBRANE_BAND[1], got
    assert abs(got["impulse"] - 1.0) < 0.15, got
    assert got["centre_strain"] > 0.01, got
    assert strain_limit is None or got["max_strain"] < strain_limit, got
    assert energy_limit is None or got["energy_err"] < energy_limit, got
