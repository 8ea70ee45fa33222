"""decks/elastic_gate_{sph,ale}.yaml run to 0.4 s against the measured free-end displacement of Antoci, Gallati &
Sibilla (2007) (tests/data/elastic_gate_antoci2007.csv, .md: a secondary digitisation, 10 frames 0.04 s apart).

Uncertainties the tolerances are set against:

- reading of the digitisation (its .md): about +-0.5 mm in x and y, and +-3 ms in time, which is +-1.6 mm in x
  while the gate opens fastest (0.04-0.09 s);
- discretisation (docs/studies/elastic_gate.md): the SPH deck's converged estimate lies 3.1 % (x peak) and 6.9 %
  (y peak) under the shipped values; the ALE deck's shipped 5 mm water is >= 7.5 % (x peak) and >= 18 % (y peak)
  above its 1.25 mm run, and refinement closes the gate further after the peak in both methods.

What the models get, asserted with the observed error rounded up (figures in docs/studies/elastic_gate.md,
"Against the experiment"):

- the opening, frames 1-3 (t <= 0.084 s): model - measurement within OPENING_TOL per frame.

What they miss, asserted as a disagreement of the size measured (the tolerances are the observed errors rounded
up, far outside the uncertainties above, so they state a miss, not an agreement):

- the peak: the models stop opening at 0.116-0.118 s and peak 18 % (SPH) / 12 % (ALE) under the measured 46.0 mm
  largest sample (0.162 s); y peaks 34 % / 22 % under the measured 17.1 mm;
- after the peak the models close the gate to 24-27 mm near 0.27 s while the measured gate eases back from 46 to
  37 mm by 0.36 s: frames 5-10 lie 11-18 mm (SPH) and 8-15 mm (ALE) under the measurement. The ALE deck is
  nearer only through its unconverged 5 mm water: at 1.25 mm its peak is 37.8 mm, the SPH deck's.
  ``test_later_phase`` states the target (the opening's tolerance) as a strict xfail: it passes only when the
  model of the scene is fixed (issue 18), and then must be turned into a plain test.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from sphfem_cli.cli import main

ROOT = Path(__file__).parents[2]
sys.path.insert(0, str(ROOT / "docs" / "studies"))
import elastic_gate_experiment as study  # noqa: E402

OPENING_TOL = 4.0e-3  # m, frames 1-3; observed at most SPH +3.1 mm, ALE +3.6 mm (frame 2, 0.044 s)
PEAK_X_TOL = {"sph": 0.20, "ale": 0.13}  # relative; observed SPH -17.8 %, ALE -11.8 %: a miss
PEAK_Y_TOL = {"sph": 0.35, "ale": 0.25}  # relative; observed SPH -33.5 %, ALE -21.8 %: a miss
PEAK_T_TOL = 0.05  # s; observed SPH -0.046 s, ALE -0.044 s against the largest sample (+-0.02 s): a miss


@pytest.fixture(scope="module", params=["sph", "ale"])
def history(request, tmp_path_factory):
    out = tmp_path_factory.mktemp(request.param) / "out"
    deck = ROOT / "decks" / f"elastic_gate_{request.param}.yaml"
    result = CliRunner().invoke(main, ["run", str(deck), "-o", str(out), "-q", "--threads", "1"])
    assert result.exit_code == 0, result.output
    h = np.genfromtxt(out / "histories" / "gate_tip.csv", delimiter=",", names=True)
    assert h["time"][-1] == pytest.approx(0.4)
    g = np.genfromtxt(out / "histories" / "glstat.csv", delimiter=",", names=True)
    return request.param, h["time"], h["displacement_x"], h["displacement_y"], g


@pytest.mark.validation
def test_opening(history):
    method, t, ux, uy, _ = history
    d = study.load_data()
    err = np.interp(d["t_x"][:3], t, ux) - d["x"][:3]
    print(method, "x - measured, frames 1-3 [mm]:", np.round(1e3 * err, 2))
    assert np.all(np.abs(err) <= OPENING_TOL)
    err = np.interp(d["t_y"][:3], t, uy) - d["y"][:3]
    print(method, "y - measured, frames 1-3 [mm]:", np.round(1e3 * err, 2))
    assert np.all(np.abs(err) <= OPENING_TOL)


@pytest.mark.validation
def test_peak_miss(history):
    method, t, ux, uy, _ = history
    c = study.compare(t, ux, uy)
    print(method, {k: round(v, 4) for k, v in c.items() if "peak" in k})
    assert c["x peak model"] == pytest.approx(c["x peak measured"], rel=PEAK_X_TOL[method])
    assert c["y peak model"] == pytest.approx(c["y peak measured"], rel=PEAK_Y_TOL[method])
    assert abs(c["t x peak error"]) <= PEAK_T_TOL


@pytest.mark.validation
@pytest.mark.xfail(strict=True, reason="issue 18: after 0.12 s the modelled gate stops opening and closes to "
                   "24-27 mm; the measured one opens to 46 mm and eases back to 37 mm by 0.36 s")
def test_later_phase(history):
    method, t, ux, uy, _ = history
    d = study.load_data()
    err = np.interp(d["t_x"][4:], t, ux) - d["x"][4:]
    print(method, "x - measured, frames 5-10 [mm]:", np.round(1e3 * err, 2))
    assert np.all(np.abs(err) <= OPENING_TOL)


@pytest.mark.validation
def test_energy_balance_and_coupling_energy(history):
    """ALE: energy ratio within 1 % of 1 at every output after the first, the coupling's energy never negative
    and under 5 % of the total; the free end rises as the clamped gate bends (its y at the x peak > 0)."""
    method, t, ux, uy, g = history
    assert uy[int(np.argmax(ux))] > 0.0
    if method != "ale":
        pytest.skip("measured for the ALE deck (the SPH deck's contact energy is not bounded here)")
    assert np.all(np.abs(g["energy_ratio"][1:] - 1.0) < 0.01)
    assert g["contact"].min() >= 0.0 and g["contact"].max() < 0.05 * g["total"].max()
