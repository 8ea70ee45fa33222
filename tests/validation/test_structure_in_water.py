"""The paper's section-4.1 scene, a plate in water driven at its bottom: decks/structure_in_water_{ale,sph}.yaml.

Full runs (about 20 s each on one thread). The paper gives no data for this scene; the reference is
computed without either solver (tests/verification/wet_plate_reference.py: Timoshenko beam and
acoustic FE, the water attached and linear): mid-height peak displacement 0.570 mm at 1.25 ms, wet
first frequency 458 Hz. Checks: the driven bottom follows the prescribed motion, the stress is
finite and positive, energy is balanced, the wet plate (period 2.2 ms, long against the 0.5 ms
pulse) overshoots where the plate in vacuum (period 0.64 ms; 0.434 mm, 1.84 m/s measured with the
coupling removed) follows the drive, and peak and free-ringing frequency against the reference
within the shipped decks' measured discretisation errors (10 mm fluid, 2 x 30 plate):

| deck | peak (ref 0.570 mm) | ringing after the pulse (ref 458 Hz) |
|---|---|---|
| ALE 10 mm (pfac 8) | 0.625 mm (+10 %) | 385 Hz (-16 %) |
| SPH ratio 1 (alpha 0) | 0.591 mm (+4 %) | 421 Hz (-8 %) |

(SPH with the contact spring on the particle's mass alone, before 7 Dec 2026: 0.593 mm, 422 Hz; at
alpha 0.1, before 4 Dec 2026: 0.544 mm, 393 Hz.)

The frequency converges towards the reference with the fluid and the plate meshes (ALE 5 mm and a
4 x 60 plate: 429 Hz, -6 %; docs/studies/structure_in_water.md).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml
from click.testing import CliRunner

from sphfem_cli.cli import main

DECKS = Path(__file__).parents[2] / "decks"
V = 2.0                                             # m/s, the deck's drive velocity
CURVE = np.array([[0.0, 0.0], [1e-4, 1.0], [4e-4, 1.0], [5e-4, 0.0], [1.0, 0.0]])
DRY_PEAK_DISPLACEMENT = 4.34e-4                     # m, the plate in vacuum
DRY_PEAK_VELOCITY = 1.84                            # m/s
REF_PEAK = 5.70e-4                                  # m, wet_plate_reference.driven_response
REF_FREQUENCY = 458.0                               # Hz, wet_plate_reference.wet_mode (closed tank)


def ringing_frequency(t: np.ndarray, u: np.ndarray, t0: float = 7e-4) -> float:
    """Frequency [Hz] of u = c + exp(-s t)(a cos wt + b sin wt) fitted to u on t > t0 (grid over w, s)."""
    m = t > t0
    t, u = t[m] - t0, u[m]
    best = (np.inf, 0.0)
    for w in 2 * np.pi * np.arange(150.0, 1500.0, 1.0):
        for s in np.linspace(0.0, 1500.0, 31):
            e = np.exp(-s * t)
            A = np.stack([np.ones_like(t), e * np.cos(w * t), e * np.sin(w * t)], axis=1)
            r = np.sum((A @ np.linalg.lstsq(A, u, rcond=None)[0] - u) ** 2)
            if r < best[0]:
                best = (r, w)
    return best[1] / (2 * np.pi)


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
    # from 0.1 ms on (the SPH run starts at 1.57 at 0.02 ms, 0.95 at 0.04 ms, while the 1 MPa
    # ambient pressure settles the first particle layer onto the plate; the energies are small then)
    late = glstat["time"] >= 1e-4
    assert np.all(np.abs(glstat["energy_ratio"][late] - 1.0) < 0.02)

    mid = table(out, "mid")
    peak_u = np.abs(mid["displacement_x"]).max()
    peak_v = np.abs(mid["velocity_x"]).max()
    assert peak_u > DRY_PEAK_DISPLACEMENT               # the heavier wet plate overshoots
    assert peak_v < DRY_PEAK_VELOCITY                   # and moves slower
    assert peak_u == pytest.approx(REF_PEAK, rel=0.12)
    f = ringing_frequency(mid["time"], mid["displacement_x"])
    assert 0.8 * REF_FREQUENCY < f < REF_FREQUENCY


REF_PEAK_Q4R = 5.734e-4  # m, wet_plate_continuum_reference.driven_response with the solvers' quad4, plate 4 x 60


@pytest.mark.validation
def test_sph_in_the_linear_limit_meets_the_continuum_reference(tmp_path):
    """SPH (ratio 3, plate 4 x 60, alpha 0) with the drive and the ambient pressure both scaled by 0.1.

    The continuum reference is linear (tests/verification/wet_plate_continuum_reference.py, the
    solvers' quad4 plate 4 x 60: 0.5734 mm, GCI 0.06 %). With every pressure ratio of the deck kept and
    the particles moving 0.03 of a spacing instead of 0.3, SPH's peak / 0.1 is +0.60 / +0.54 / +0.43 /
    +0.65 % from it at ratios 3 / 4 / 5 / 6 (docs/studies/structure_in_water.md, "SPH's gap grows
    with the drive's amplitude"; 18 s CPU at ratio 3; with the reduced-mass contact spring, 7 December
    2026: +0.58 % at ratio 3); at the deck's drive the same particles give -2.8 to -2.9 % (unchanged by
    that spring), an amplitude effect not covered here. Tolerance 1.5 %: the ALE extrapolation's
    band (0.38 %) plus the SPH levels' spread (0.22 %) and the ratio-3 level's offset, rounded up.
    """
    d = yaml.safe_load(open(DECKS / "structure_in_water_sph.yaml"))
    d["control"]["end_time"] = 0.002
    d["parts"]["plate"]["geometry"]["box"]["divisions"] = [4, 60]
    d["parts"]["tank"]["spacing"] = 0.01 / 3.0
    d["equations_of_state"]["water"]["c0"] *= 0.1
    drive = next(b for b in d["boundaries"] if b["type"] == "prescribed_velocity")
    drive["velocity"] = [0.1 * V, None]
    assert d["sections"]["sph"]["artificial_viscosity"]["alpha"] == 0.0
    deck = tmp_path / "linear_limit.yaml"
    yaml.safe_dump(d, open(deck, "w"), sort_keys=False)
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["run", str(deck), "-o", str(out), "-q", "--threads", "1"])
    assert result.exit_code == 0, result.output
    peak = np.abs(table(out, "mid")["displacement_x"]).max() / 0.1
    assert peak == pytest.approx(REF_PEAK_Q4R, rel=0.015)
