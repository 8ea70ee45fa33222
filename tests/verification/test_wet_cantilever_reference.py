"""The independent reference for decks/wet_cantilever_*.yaml: the plate's wet first frequency.

wet_cantilever_reference.py (Timoshenko beam FE + potential-flow / acoustic FE of the water, scipy;
equations and sources in its docstring) checked against closed forms, then its value pinned.
Figures (this machine; the decks' scene: plate 10 x 120 mm, E = 100 MPa, nu = 0.3, rho_s = 1200,
water 100 mm deep on both sides in a 310 mm tank, p = 0 on the free surface):

| model | first frequency |
|---|---|
| plate in vacuum: Euler-Bernoulli closed form / Timoshenko, 96 elements / + its own weight | 33.947 / 33.748 / 33.700 Hz |
| wet, incompressible, fluid grid hf 10 / 5 / 2.5 / 1.25 mm (96 beam elements) | 19.848 / 19.710 / 19.669 / 19.657 Hz |
| wet, hf 2.5 mm, beam 24 / 48 / 192 elements | 19.671 / 19.670 / 19.669 Hz |
| wet, acoustic c = 1483 / 150 / 100 / 60 / 40 m/s (hf 2.5 mm) | 19.669 / 19.664 / 19.657 / 19.635 / 19.591 Hz |

The solvers' comparison is tests/validation/test_wet_cantilever.py.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
import wet_cantilever_reference as ref  # noqa: E402

SCENE = ref.Scene()


def test_dry_limit_is_the_cantilever_closed_form():
    """A slender plate (t = 1 mm, L/t = 120, weightless, 200 elements): the Timoshenko beam is the
    closed form 1.8751^2 sqrt(EI/(m L^4)) / 2 pi within 0.05 % (shear and rotary inertia ~ (t/L)^2);
    the decks' plate (t/L = 1/12) sits below it by 0.2..1 %; its own weight lowers it by < 0.5 %."""
    thin = SCENE.with_(x1=SCENE.x0 + 0.001)
    exact = ref.euler_bernoulli_frequency(thin)
    assert ref.dry_frequency(ref.beam(thin, 200, weight=False)) == pytest.approx(exact, rel=5e-4)
    assert ref.dry_frequency(ref.beam(thin, 200, shear=False, weight=False)) == pytest.approx(exact, rel=5e-4)
    exact = ref.euler_bernoulli_frequency(SCENE)
    timo = ref.dry_frequency(ref.beam(SCENE, 96, weight=False))
    assert 0.99 * exact < timo < 0.998 * exact
    heavy = ref.dry_frequency(ref.beam(SCENE, 96))
    assert 0.995 * timo < heavy < timo


@pytest.mark.parametrize("c, f_hz", [(np.inf, 0.0), (100.0, 100.0)])
def test_rigid_plate_added_mass_is_westergaards(c, f_hz):
    """The plate translating rigidly: the FE fluid's added mass (both faces, hf 2.5 mm) against the
    series for a rigid wall before a reservoir of the same length, p = 0 on top (Westergaard 1933;
    acoustic, Chopra 1967, at 100 Hz below the 250 Hz cut-off) within 0.2 %; hf 5 -> 2.5 mm
    converges (error 0.15 % -> 0.04 % incompressible)."""
    sc = SCENE.with_(c=c)
    omega = 2 * np.pi * f_hz
    exact = 2 * ref.westergaard_added_mass(sc, omega)
    fine = ref.rigid_plate_added_mass(sc, 0.0025, omega)
    coarse = ref.rigid_plate_added_mass(sc, 0.005, omega)
    assert fine == pytest.approx(exact, rel=2e-3)
    assert abs(fine - exact) < abs(coarse - exact)


def test_westergaard_series_limits():
    """A long reservoir tends to 0.5430 rho D^2 (16/pi^3 (7/8) zeta(3)); compressibility raises it."""
    long = ref.westergaard_added_mass(SCENE, reservoir=10.0)
    assert long == pytest.approx(16 / np.pi ** 3 * 7 / 8 * 1.2020569 * SCENE.rho_f * SCENE.depth ** 2, rel=1e-6)
    sc = SCENE.with_(c=100.0)
    assert ref.westergaard_added_mass(sc, 2 * np.pi * 100) > ref.westergaard_added_mass(sc, 0.0)


def test_free_surface_term_gives_the_sloshing_frequencies():
    """Empty tank, surface waves on: omega^2 = g k tanh(k D), k = n pi / W, within 0.5 % (hf 5 mm)."""
    f = ref.sloshing_frequencies(SCENE, 0.005, 3)
    k = np.arange(1, 4) * np.pi / SCENE.width
    exact = np.sqrt(SCENE.g * k * np.tanh(k * SCENE.depth)) / (2 * np.pi)
    np.testing.assert_allclose(f, exact, rtol=5e-3)


def test_acoustic_mode_of_the_layer():
    """Plate rigid, p = 0 on top: the lowest mode is the layer's quarter wave c / (4 D) within 0.1 %."""
    sc = SCENE.with_(c=100.0)
    assert ref.acoustic_frequency(sc, 0.005) == pytest.approx(100.0 / (4 * sc.depth), rel=1e-3)


def test_wet_frequency_converges_and_is_pinned():
    """Incompressible, p = 0 on top: hf 5 -> 2.5 mm moves it by 0.2 %, monotone down to the pinned
    19.669 Hz (hf 2.5 mm, within 0.01 %); the added mass is about twice the plate's modal mass; the
    deck's c = 100 m/s lowers it by 0.06 %, and the mode is a cantilever's (tip largest, base 0)."""
    coarse = ref.wet_mode(SCENE, 48, 0.005)
    fine = ref.wet_mode(SCENE, 48, 0.0025)
    assert fine.frequency < coarse.frequency < 1.003 * fine.frequency
    assert fine.frequency == pytest.approx(19.669, rel=1e-4)
    assert 1.9 < fine.added_mass / fine.modal_mass < 2.1
    assert fine.shape[0] == 0.0 and fine.shape[-1] == 1.0 and np.all(np.diff(fine.shape) > 0)
    acoustic = ref.wet_mode(SCENE.with_(c=100.0), 48, 0.0025)
    assert 0.999 * fine.frequency < acoustic.frequency < fine.frequency


def test_ringing_recovers_a_damped_sinusoid():
    """The measurement the solvers' runs go through: f and zeta of a sampled damped sinusoid plus an
    offset and 1 % noise, over 4 periods, within 0.2 % and 0.005."""
    rng = np.random.default_rng(3)
    f, zeta = 18.0, 0.02
    t = np.arange(0.0, 0.3, 2e-4)
    wn = 2 * np.pi * f
    u = 1e-5 + 3e-4 * np.exp(-zeta * wn * t) * np.cos(wn * np.sqrt(1 - zeta ** 2) * t + 0.4)
    u += 3e-6 * rng.standard_normal(len(t))
    r = ref.ringing(t, u, 0.05)
    assert r.frequency == pytest.approx(f, rel=2e-3)
    assert abs(r.zeta - zeta) < 5e-3
    assert r.periods > 4
