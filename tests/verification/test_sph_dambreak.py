"""2D dam break: the surge front against Martin & Moyce (1952), with the physical setup of decks/dam_break_2d.yaml.

Column a wide and 2a high (a = 57.2 mm, the experiment's larger column) at the left end of a dry tank 6a long,
built by ``sphfem_cli.sph.scenes.dam_break`` with the deck's settings: Tait water with c0 = 30 m/s (peak Mach
0.05), the water's viscosity 1.0e-3 Pa s, Monaghan's viscosity with the shock switch (alpha between 0.01 and 1,
decay 0.1, beta 0), delta-SPH 0.1, hydrostatic start, wall-function walls (slip ghosts plus the smooth-wall law's
shear on the first particle layer). Front Z = (largest particle x)/a, the deck's probe, against T = t sqrt(2g/a)
at the four times of the a = 2.25 in series of ../shared/reference/dambreak_front_martin_moyce_1952.csv (Martin &
Moyce 1952, Phil. Trans. R. Soc. A 244, Fig. 3, n^2 = 2).

Until 7 December 2026 this test (and the deck) used no-slip ghost walls with a fixed alpha 0.1, "as the
experiment's floor". That was wrong: the experiment's floor is no-slip, but its boundary layer at a Reynolds number
2 sqrt(2 g a) a / nu of about 1.2e5 is far thinner than a particle, while the no-slip ghosts apply the artificial
viscosity alpha h c0 / 8 over the whole kernel support (a Reynolds number near 380 at a/dx 40, c0 15), so the front
moved with the artificial c0 (Z(2.547) -6.4 % from c0 15 to 60). The wall function applies the wall law's shear
with the water's real viscosity instead (docs/theory/sph.md, "Wall function").

Measured Z (error against the experiment), docs/studies/dam_break_2d.md:

=============================  =============  =============  =============  =============
T                              0.832          1.219          1.997          2.547
experiment                     1.217          1.474          2.292          2.995
a/dx = 12 (this scene)         1.330 (+9.3%)  1.695 (+15.0%) 2.602 (+13.5%) 3.338 (+11.4%)
a/dx = 20 (the deck)           1.369 (+12.5%) 1.735 (+17.7%) 2.629 (+14.7%) 3.360 (+12.2%)
a/dx = 40 (the deck, spacing)  1.401 (+15.1%) 1.754 (+19.0%) 2.631 (+14.8%) 3.341 (+11.6%)
a/dx = 80 (the deck, spacing)  1.405 (+15.4%) 1.741 (+18.1%) 2.613 (+14.0%) 3.359 (+12.2%)
a/dx = 40, c0 60 (the deck)    1.396 (+14.7%) 1.749 (+18.7%) 2.620 (+14.3%) 3.338 (+11.4%)
a/dx = 40 (this scene)         1.402 (+15.2%) 1.755 (+19.1%) 2.617 (+14.2%) 3.333 (+11.3%)
a/dx = 40, c0 60 (this scene)  1.397 (+14.8%) 1.749 (+18.7%) 2.616 (+14.1%) 3.331 (+11.2%)
=============================  =============  =============  =============  =============

Z(0.832) converges monotonically (order 3.1, Richardson 1.405); at the later times the three grids oscillate
within 0.6-1.1 % (a one-particle front resolved to a fraction of dx): a/dx 40 lies within 0.74 % (the deck) and
0.82 % (this scene) of a/dx 80, the deck (a/dx 20) within 2.6 %; c0 x 2 moves a/dx 40 by at most 0.40 %
(the deck and this scene alike). The scene records the front every step, the deck every 2 ms.

The computed front leads the measured one, most at T = 1.2: the experiment's gate takes time to release the
column (an ALE/VOF solve of the same column with slip walls leads by 21-22 % at T = 1.2,
tests/verification/test_dam_break_methods.py; docs/theory/sph.md, "Dam break: why the early front leads the
experiment"). The issue's 10 % bound is therefore not met at T <= 2.5, and no setting is changed to meet it.
Tolerances: the front must lead (error > 0) and stay within 25 % of the experiment (the ALE/VOF lead, 22 %, plus
the deck's 3 % accuracy); at a/dx = 40 it must also lie within 1.5 % of the a/dx = 80 front (measured 0.82 %),
and moving c0 from 30 to 60 m/s must change it by less than 1 % (measured 0.40 %). The shipped deck must
reproduce its header's Z and lie within 3 % of the a/dx = 80 front (measured 2.6 %).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from sphfem_cli.sph import scenes

from conftest import read_history, run_shipped_deck

REFERENCE = Path(__file__).parents[3] / "shared" / "reference" / "dambreak_front_martin_moyce_1952.csv"
G = 9.81
A = 0.0572
SCALE = math.sqrt(2.0 * G / A)
T_COMPARED = (0.832, 1.219, 1.997, 2.547)
TOL = 0.25  # the front leads the experiment by less than this (relative)
FINEST = np.array([1.4048, 1.7408, 2.6132, 3.3592])  # Z at a/dx = 80, the deck's setup (docs/studies/dam_break_2d.md)
DECK_Z = np.array([1.3689, 1.7348, 2.6287, 3.3602])  # the deck's header


def reference_front():
    """T and Z of the a = 2.25 in series at the four compared times."""
    if not REFERENCE.exists():
        pytest.skip(f"reference data missing: {REFERENCE}")
    rows = [line.split(",") for line in REFERENCE.read_text().splitlines() if line.startswith("MM_a2.25in")]
    T = np.array([float(r[1]) for r in rows])
    Z = np.array([float(r[2]) for r in rows])
    keep = np.isin(T.round(3), T_COMPARED)
    assert keep.sum() == len(T_COMPARED)
    return T[keep], Z[keep]


def front(n: int, c0: float = 30.0) -> np.ndarray:
    """Z at the compared times for a/dx = n, the deck's setup (sound speed c0)."""
    T_ref, _ = reference_front()
    dx = A / n
    ps = scenes.dam_break(a=A, dx=dx, g=G, c0=c0, tank_length=6.0 * A, condition="wall_function",
                          viscosity=1.0e-3, alpha=0.01, beta=0.0, switch_alpha_max=1.0, switch_decay=0.1)
    T, Z = [0.0], [1.0]

    def record(s):
        T.append(s.time * SCALE)
        Z.append(s.front(0) / A)

    ps.run(T_ref.max() / SCALE * 1.01, every=record)
    assert ps.lost == 0
    assert ps.x[:, 1].min() >= 0.0 and ps.x[:, 0].min() >= 0.0
    return np.interp(T_ref, T, Z)


def errors(Z: np.ndarray) -> np.ndarray:
    return Z / reference_front()[1] - 1.0


def test_dam_break_front_coarse(single_thread):
    """a/dx = 12 (288 particles, about 3 600 steps, 3 s CPU); measured +9.3 / +15.0 / +13.5 / +11.4 %."""
    err = errors(front(12))
    assert (err > 0.0).all() and (err < TOL).all(), err


@pytest.mark.validation
def test_dam_break_front_a_over_dx_40(single_thread):
    """a/dx = 40 (3 200 particles, about 12 000 steps at c0 30, 23 000 at 60; the deck's
    runs at these settings took 87 and 144 s CPU)."""
    Z = front(40)
    err = errors(Z)
    assert (err > 0.0).all() and (err < TOL).all(), err
    assert np.abs(Z / FINEST - 1.0).max() < 0.015, Z
    Z60 = front(40, c0=60.0)
    print(f"a/dx 40: Z {Z.round(4)}, error {(100 * err).round(1)} %, vs a/dx 80 {(100 * (Z / FINEST - 1)).round(2)} %, "
          f"c0 60: Z {Z60.round(4)} ({(100 * (Z60 / Z - 1)).round(2)} %)")
    assert np.abs(Z60 / Z - 1.0).max() < 0.01, (Z, Z60)


@pytest.mark.validation
def test_deck_front_against_martin_moyce(tmp_path, single_thread):
    """decks/dam_break_2d.yaml as shipped: the front probe at the four times, the header's figures."""
    h = read_history(run_shipped_deck("dam_break_2d", tmp_path), "front")
    T_ref, _ = reference_front()
    Z = np.interp(T_ref, h["time"] * SCALE, h["front"] / A)
    assert np.abs(Z / DECK_Z - 1.0).max() < 1e-3, Z  # the header's values
    err = errors(Z)
    assert (err > 0.0).all() and (err < TOL).all(), err
    assert np.abs(Z / FINEST - 1.0).max() < 0.03, Z


@pytest.mark.parametrize("dim", [2, 3])
def test_no_slip_ghost_walls_conserve_energy(dim, single_thread):
    """A no-slip wall is at rest and does no work: what its friction takes from the fluid's kinetic
    energy goes into internal energy. Dam break (a = 1 m, the scene's default c0 and alpha 0.1) to T = 3,
    plain ghosts (a/dx = 12 in 2D, 6 in 3D).
    Measured energy ratios 1.0000014 (2D, a/dx = 20) and 1.0000037 (3D, a/dx = 8); before the ghosts
    kept the no-slip velocity out of the continuity equation: 1.033 and 1.14."""
    n = 12 if dim == 2 else 6
    ps = scenes.dam_break(a=1.0, dx=1.0 / n, g=G, condition="no_slip", dim=dim)
    e0 = ps.energies()["total"]
    ps.run(3.0 / math.sqrt(2.0 * G / 1.0))
    e = ps.energies()
    assert e["kinetic"] < 0.6 * e0  # the friction did take energy from the motion
    assert abs(e["total"] / e0 - 1.0) < 2e-5


def test_no_slip_without_viscosity_is_slip(single_thread):
    """Without any viscosity a no-slip wall must act as a slip wall: the ghosts' no-slip velocity
    enters the viscous terms only. Bit-identical fronts (before: +17 % and 5 % energy gained)."""
    runs = []
    for condition in ("slip", "no_slip"):
        ps = scenes.dam_break(a=1.0, dx=1.0 / 12, g=G, condition=condition, alpha=0.0)
        ps.run(2.0 / math.sqrt(2.0 * G / 1.0))
        runs.append(ps.x.copy())
    assert np.array_equal(runs[0], runs[1])
