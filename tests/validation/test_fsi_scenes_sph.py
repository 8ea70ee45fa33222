"""Issue 5's SPH scene decks run to their end: slamming, free-fall water entry, elastic gate.

Each test runs a shipped deck (decks/<name>.yaml) unchanged through the CLI path (load_model and
execute) and reads its history CSV back.

1. decks/cylinder_entry_constant_speed_sph.yaml: rigid cylinder D = 0.11 m at constant 2.955 m/s
   (water c0 = 60 m/s, tank 1.2 x 0.6 m: the echoes return at s/D ~ 0.5, after the compared window).
   Slamming coefficient Cs = F / (1/2 rho D V^2) against s/D, s = V (t - t_contact); the bounds are
   von Karman's pi and Wagner's 2 pi at first contact (2D, per unit length), from
   ../shared/reference/README.md ("Rigid cylinder entering still water at constant speed") and the
   issue's acceptance: the peak of Cs between pi and 1.2 x 2 pi, taken on the 1 ms running mean
   (the raw samples, 0.02 ms apart, swing by up to a factor 8 as particles arrive one by one
   and the soft contact rings), and Cs falling as the
   penetration grows, tested as: the mean Cs over s/D in [0.4, 0.6] (which holds the floor's
   acoustic echo at s/D ~ 0.51) below half the peak, and the mean over [0.8, 1.1] below the mean
   over the first 0.2 D.
2. decks/cylinder_free_fall_sph.yaml and decks/cylinder_free_fall_rho1000_sph.yaml: Greenhow & Lin
   (1983) setup (README above); no measured curve is in the reference folder, so the checks are the
   physics any entry must show: early on the penetration follows V t, bounded at T = 0.02 and
   0.05 from above by V t + g t^2/2 (the fluid only pushes up) and from below by
   V t - a_W t^2/2, a_W = 2 pi (1/2 rho D V^2) / m the deceleration Wagner's first-contact
   slamming force would give if it lasted (Cs only falls after contact); the body slows down; and
   the heavier cylinder is deeper at every T > 0.05.
3. decks/elastic_gate_sph.yaml: Antoci, Gallati & Sibilla (2007) setup (README above); no data file,
   so the test checks that the run completes and the gate opens the way the experiment's does
   (free end moving downstream, +x, and up, as the clamped gate bends), with the peak x displacement
   of the free end within a factor of two of the experiment's 0.04-0.045 m (read off the published
   figure; approximate, not validation).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from conftest import read_history as history, run_shipped_deck as run_deck

pytestmark = [pytest.mark.validation, pytest.mark.usefixtures("single_thread")]

G, D, V, RHO = 9.81, 0.11, 2.955, 1000.0
GAP = 0.005  # cylinder bottom above the free surface at t = 0 in the cylinder decks [m]


def test_cylinder_constant_speed_slamming(tmp_path):
    h = history(run_deck("cylinder_entry_constant_speed_sph", tmp_path), "cylinder")
    t_contact = GAP / V
    s_over_d = V * (h["time"] - t_contact) / D
    cs = h["contact_force_y"] / (0.5 * RHO * D * V * V)
    assert np.allclose(h["velocity_y"][1:], -V)  # the prescribed speed held
    assert np.all(cs[s_over_d < -0.01] == 0.0)  # no force before the body reaches the water
    n = int(round(1.0e-3 / float(h["time"][2] - h["time"][1])))  # samples in 1 ms
    smooth = np.convolve(cs, np.ones(n) / n, mode="same")  # centred 1 ms running mean
    peak = int(np.argmax(smooth))

    def mean(lo, hi):
        return float(cs[(s_over_d >= lo) & (s_over_d <= hi)].mean())

    early, middle, late = mean(0.0, 0.2), mean(0.4, 0.6), mean(0.8, 1.1)
    print(f"\nslamming: peak Cs (1 ms mean) {smooth[peak]:.2f} at s/D {s_over_d[peak]:.3f} (raw {cs.max():.2f}); "
          f"mean Cs {early:.2f} (s/D 0-0.2), {middle:.2f} (0.4-0.6), {late:.2f} (0.8-1.1)")
    assert np.pi <= smooth[peak] <= 1.2 * 2.0 * np.pi  # measured 5.88 at s/D 0.017 (raw 8.95)
    assert middle < 0.5 * smooth[peak]  # measured 1.30
    assert late < early  # measured 1.07 < 2.62


def free_fall(name: str, tmp_path: Path):
    h = history(run_deck(name, tmp_path), "cylinder")
    v0 = np.sqrt(V * V - 2.0 * G * GAP)  # the decks' initial speed (2.9384 m/s): it meets the water at V
    t_contact = (V - v0) / G
    y_contact = -(v0 * t_contact + 0.5 * G * t_contact ** 2)  # displacement at first contact
    T = (h["time"] - t_contact) * np.sqrt(G / D)
    penetration = (y_contact - h["displacement_y"]) / D
    assert np.all(h["displacement_x"] == 0.0)  # vertical motion only
    return T, penetration, h


def test_free_fall_entry(tmp_path):
    T5, p5, h5 = free_fall("cylinder_free_fall_sph", tmp_path)
    T10, p10, h10 = free_fall("cylinder_free_fall_rho1000_sph", tmp_path)
    for T, p, rho in ((T5, p5, 500), (T10, p10, 1000)):
        mass = rho * np.pi * (0.5 * D) ** 2  # per unit length (the 64-gon's is 0.2 % less)
        a_wagner = 2.0 * np.pi * 0.5 * RHO * D * V * V / mass
        print(f"\nrho {rho}: " + ", ".join(f"T {q:.2f}: {np.interp(q, T, p):.3f}"
                                          for q in (0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7)))
        for q in (0.02, 0.05):
            t = q * np.sqrt(D / G)
            pen = np.interp(q, T, p)
            assert (V * t - 0.5 * a_wagner * t * t) / D <= pen <= (V * t + 0.5 * G * t * t) / D, (rho, q, pen)
    assert -h5["velocity_y"][-1] < 0.6 * V and -h10["velocity_y"][-1] < V  # both slowed by the water
    later = T5 > 0.05
    deeper = np.interp(T5[later], T10, p10)
    assert np.all(deeper > p5[later])


def test_elastic_gate(tmp_path):
    h = history(run_deck("elastic_gate_sph", tmp_path), "gate_tip")
    ux, uy = h["displacement_x"], h["displacement_y"]
    i = int(np.argmax(ux))
    print(f"\nelastic gate: free end max x displacement {ux[i]:.4f} m at t = {h['time'][i]:.3f} s "
          f"(y {uy[i]:.4f} m); max y {uy.max():.4f} m at t = {h['time'][int(np.argmax(uy))]:.3f} s")
    assert h["time"][-1] >= 0.4 - 1e-9
    assert 0.5 * 0.04 <= ux[i] <= 2.0 * 0.045
    assert uy[i] > 0.0
