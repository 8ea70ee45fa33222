"""The independent reference for decks/structure_in_water_*.yaml: the plate's wet first mode.

wet_plate_reference.py (beam FE + acoustic FE, numpy only; equations and sources in its docstring)
is checked here against closed forms, then its converged value is pinned. Figures (this machine):

| model | first frequency |
|---|---|
| plate in vacuum, Timoshenko clamped-pinned, 60 elements | 1665.9 Hz (Euler-Bernoulli 1770 Hz) |
| wet, closed rigid tank, hf 10 / 5 / 2.5 mm (60 beam elements) | 461.0 / 459.0 / 458.2 Hz; beam 30 / 120 elements (hf 5 mm) 459.6 / 458.9 Hz |
| wet, far side radiating (rho c), hf 5 mm | 440.6 Hz, zeta 0.034 |
| wet, far side a free surface (p = 0), hf 5 mm | 430.1 Hz |

The solvers' comparison (their free ringing after the drive pulse) is
tests/validation/test_structure_in_water.py.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
import wet_plate_reference as ref  # noqa: E402

BETA_CP = 3.926602312  # clamped-pinned beam, first root of tan(bL) = tanh(bL)


def test_slender_beam_matches_euler_bernoulli():
    """t = 1 mm (L/t = 150): Timoshenko -> Euler-Bernoulli, f = (bL)^2 sqrt(EI/(m L^4)) / 2 pi."""
    t, L = 0.001, 0.15
    ei = ref.E / (1 - ref.NU ** 2) * t ** 3 / 12
    exact = BETA_CP ** 2 * np.sqrt(ei / (ref.RHO_S * t * L ** 4)) / (2 * np.pi)
    assert ref.dry_frequency(ref.beam(200, thickness=t)) == pytest.approx(exact, rel=5e-4)


def _dense(fl, omega):
    """The block-tridiagonal A = K + i omega C - omega^2 M of ``fl`` as one dense matrix."""
    sizes = [len(c) for c in fl.cols]
    off = np.concatenate([[0], np.cumsum(sizes)])
    A = np.zeros((off[-1], off[-1]), complex)
    for i in range(len(sizes)):
        A[off[i]:off[i + 1], off[i]:off[i + 1]] = fl.Kd[i] + 1j * omega * fl.Cd[i] - omega ** 2 * fl.Md[i]
        if i > 0:
            L = fl.Ko[i] - omega ** 2 * fl.Mo[i]
            A[off[i]:off[i + 1], off[i - 1]:off[i]] = L
            A[off[i - 1]:off[i], off[i]:off[i + 1]] = L.T
    return A, off


def test_block_elimination_equals_a_dense_solve():
    """M_a = rho Q A^-1 Q^T by block elimination equals a dense solve of the same matrices (radiating
    far side: complex A); a translation of the plate has a positive added mass."""
    bm = ref.beam(30)
    fl = ref.fluid(0.01, "radiation")
    qt = ref.coupling(bm, fl)
    omega = 2 * np.pi * 400.0
    ma = ref.added_mass(bm, fl, omega, qt=qt)
    A, off = _dense(fl, omega)
    B = np.zeros((off[-1], qt[next(iter(qt))].shape[1]))
    for i, blk in qt.items():
        B[off[i]:off[i + 1]] = blk
    dense = ref.RHO_F * B.T @ np.linalg.solve(A, B)
    np.testing.assert_allclose(ma, dense, rtol=1e-8, atol=1e-10 * np.abs(dense).max())
    w = np.zeros(ma.shape[0])
    w[0::2] = 1.0
    assert (w @ ma @ w).real > 0


def test_acoustic_fe_first_mode_of_the_empty_tank():
    """K_f, M_f of the empty tank (hf 10 mm): the first non-zero Neumann mode is f = c/(2 W),
    W = 0.4 m (bilinear elements: relative error (k h)^2 / 24 = 1.5e-4)."""
    fl = ref.fluid(0.01, "rigid", plate=False)
    K, off = _dense(fl, 0.0)
    M = -(_dense(fl, 1.0)[0] - K)
    lam = np.sort(np.linalg.eigvals(np.linalg.solve(M.real, K.real)).real)
    assert lam[0] == pytest.approx(0.0, abs=1e-8 * lam[1])
    assert np.sqrt(lam[1]) / (2 * np.pi) == pytest.approx(ref.C_F / (2 * 0.4), rel=5e-4)


def test_wet_frequency_converges_with_the_fluid_grid():
    """Closed rigid tank (the shipped decks' walls): hf 10 and 5 mm within 0.5 %; value pinned."""
    coarse = ref.wet_mode(30, 0.01, "rigid")
    fine = ref.wet_mode(30, 0.005, "rigid")
    assert coarse.frequency == pytest.approx(fine.frequency, rel=5e-3)
    assert fine.frequency == pytest.approx(459.0, rel=5e-3)
    assert abs(fine.zeta) < 1e-9                       # no loss in a closed tank
    assert fine.frequency < 0.3 * fine.dry             # added mass about 12 times the plate's
    # the mode: zero at both ends, one hump, its maximum in the lower half (pinned end below)
    w = fine.shape
    assert w[0] == 0.0 and w[-1] == 0.0 and np.all(w >= -1e-9)
    assert fine.y[np.argmax(w)] < 0.5 * (ref.PLATE[2] + ref.PLATE[3])


def test_far_side_conditions_bracket_the_wet_frequency():
    """The far side's condition moves the wet frequency by a few per cent; radiation damps it."""
    rigid = ref.wet_mode(30, 0.01, "rigid")
    release = ref.wet_mode(30, 0.01, "release")
    radiation = ref.wet_mode(30, 0.01, "radiation")
    assert release.frequency < radiation.frequency < rigid.frequency
    assert (rigid.frequency - release.frequency) / rigid.frequency < 0.08
    assert 0.01 < radiation.zeta < 0.1


def test_drive_state_integrates_the_curve():
    """The drive: 0.8 mm at the end of the pulse (2 m/s over 0.1 / 0.3 / 0.1 ms ramp-hold-ramp)."""
    u, v, a = ref.drive_state(1e-3)
    assert u == pytest.approx(8.0e-4, rel=1e-12) and v == 0.0 and a == 0.0
    u, v, a = ref.drive_state(5e-5)
    assert u == pytest.approx(0.5 * 1e4 * 2 * 5e-5 ** 2, rel=1e-12) and v == pytest.approx(1.0)
    assert a == pytest.approx(2e4)


def test_driven_response_in_vacuum_and_in_water():
    """The plate driven as in the decks, 3 ms, hf 10 mm (the wet figures move by < 0.3 % at 5 mm).

    In vacuum the reference gives a mid-height peak of 0.4115 mm and 1.737 m/s, the solver's plate
    (decks/structure_in_water_*.yaml without water) 0.434 / 1.844 at its 2 x 30 quads, 0.416 / 1.717
    at 4 x 60 and 0.409 / 1.731 at 8 x 120: converging to the beam. In water (attached, linear):
    0.570 mm at 1.25 ms, 1.23 m/s; the water's dynamic pressure spans -0.72 to +0.68 MPa, so water
    at a lower ambient pressure would cavitate or leave the plate on its suction side."""
    dry = ref.driven_response(30, 0.01, end=3e-3, wet=False)
    wet = ref.driven_response(30, 0.01, end=3e-3)
    assert np.abs(dry.w_mid).max() == pytest.approx(4.115e-4, rel=5e-3)
    assert np.abs(dry.v_mid).max() == pytest.approx(1.737, rel=1e-2)
    i = int(np.argmax(np.abs(wet.w_mid)))
    assert wet.w_mid[i] == pytest.approx(5.70e-4, rel=5e-3)
    assert wet.t[i] == pytest.approx(1.25e-3, rel=2e-2)
    assert np.abs(wet.v_mid).max() == pytest.approx(1.23, rel=2e-2)
    assert wet.p_range[0] < -5e5 and wet.p_range[1] > 5e5


def test_gauges_converge_with_the_beam_mesh():
    """The face-strain gauges (mean bending stress over 0-25 and 25-50 mm under the clamp) are bounded
    where the clamp's point stress is not, and converge with the beam mesh: measured (hf 10 mm,
    2 ms) 30 / 60 beam elements: 122.6 / 122.3 MPa (0-25 mm), 44.5 / 43.9 MPa (25-50 mm; at hf 5 mm
    and 120 elements 122.2 and 43.9 MPa, the figures docs/studies/structure_in_water.md compares
    with); the 0-25 mm gauge below twice the clamp
    point's (z = 2.5 mm) sigma_yy, the face stress at the clamp, which bounds the mean of a moment
    falling from the clamp."""
    peaks = {}
    for n_el in (30, 60):
        r = ref.driven_response(n_el, 0.01, end=2e-3)
        assert set(r.gauges) == set(ref.GAUGES)
        peaks[n_el] = {g: np.abs(a).max() for g, a in r.gauges.items()}
        face_at_clamp = 2.0 * np.abs(r.vm_clamp).max() / np.sqrt(1.0 - ref.NU + ref.NU**2)
        assert peaks[n_el][ref.GAUGES[0]] < face_at_clamp
        assert peaks[n_el][ref.GAUGES[0]] > 2.0 * peaks[n_el][ref.GAUGES[1]]
    for g in ref.GAUGES:
        assert peaks[60][g] == pytest.approx(peaks[30][g], rel=2e-2)
