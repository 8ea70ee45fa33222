"""2D dam break: the surge front against Martin & Moyce (1952).

Column a wide and 2a high (a = 1 m) at the left end of a dry tank 5a long, Tait water with
c0 = 10 sqrt(2 g 2a), Monaghan alpha = 0.1, delta-SPH 0.1, hydrostatic start, ghost walls
(no-slip, as the experiment's floor). Front Z = (largest particle x + dx/2)/a against
T = t sqrt(2g/a); reference: ../shared/reference/dambreak_front_martin_moyce_1952.csv (Martin &
Moyce 1952, Phil. Trans. R. Soc. A 244, Fig. 3, n^2 = 2, both column sizes).

Measured relative errors (Z_sph - Z_exp)/Z_exp at the reference points with T <= 3:

=========  ======  ======  ======  ======  ======  ======  ======  ======  ======
T          0.832   0.849   1.212   1.219   1.602   1.997   2.283   2.547   2.950
a/dx = 12  +8.3 %  +6.8 %  +10.0%  +8.0 %  +1.7 %  +2.2 %  -0.4 %  -0.3 %  -6.2 %
a/dx = 40  +9.8 %  +8.3 %  +14.6%  +12.6%  +8.6 %  +7.8 %  +4.5 %  +5.4 %  -0.4 %
a/dx = 60  +12.2%  +10.7%  +15.4%  +13.5%  +8.9 %  +8.9 %  +6.3 %  +7.5 %  +0.8 %
=========  ======  ======  ======  ======  ======  ======  ======  ======  ======

From a/dx = 40 on the result is nearly converged; the computed front leads the measured one in
the first part of the collapse (T < 1.5, up to 15 % at T = 1.2) and matches it within 10 % from
T = 1.5 on. The early lead is the usual one of computations against this experiment, whose
release (removing the retaining gate) delays the start: an Eulerian ALE/VOF solve of the same
column, which shares nothing with SPH but the equations, gives the same front as SPH with slip
walls within 1 % (tests/verification/test_dam_break_methods.py), and both lead by 21-22 % at
T = 1.2 (the no-slip floor's friction takes off a third of that). The issue's bound (10 % for
all T <= 3) is therefore not met: the validation test holds T in [1.5, 3] to 10 % and all T <= 3
to 17 %; the coarse default-suite run is held to 20 %.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from sphfem_cli.sph import scenes

REFERENCE = Path(__file__).parents[3] / "shared" / "reference" / "dambreak_front_martin_moyce_1952.csv"
G = 9.81
A = 1.0


def reference_front():
    if not REFERENCE.exists():
        pytest.skip(f"reference data missing: {REFERENCE}")
    rows = [line.split(",") for line in REFERENCE.read_text().splitlines() if line and not line.startswith("#")]
    T = np.array([float(r[1]) for r in rows])
    Z = np.array([float(r[2]) for r in rows])
    keep = T <= 3.0
    return T[keep], Z[keep]


def front_errors(n):
    """Relative front errors at the reference times T <= 3 for a/dx = n."""
    T_ref, Z_ref = reference_front()
    dx = A / n
    ps = scenes.dam_break(a=A, dx=dx, g=G, condition="no_slip")
    scale = math.sqrt(2.0 * G / A)
    T, Z = [0.0], [A / A]

    def record(s):
        T.append(s.time * scale)
        Z.append((s.front(0) + 0.5 * dx) / A)

    ps.run(T_ref.max() / scale * 1.01, every=record)
    assert ps.lost == 0
    assert ps.x[:, 1].min() >= 0.0 and ps.x[:, 0].min() >= 0.0
    Z_sph = np.interp(T_ref, T, Z)
    return T_ref, (Z_sph - Z_ref) / Z_ref


def test_dam_break_front_coarse(single_thread):
    """a/dx = 12 (288 particles, about 1 900 steps); measured max |error| 10.1 %."""
    _, err = front_errors(12)
    assert np.abs(err).max() < 0.20


@pytest.mark.validation
def test_dam_break_front_a_over_dx_40(single_thread):
    """a/dx = 40 (3 200 particles, about 6 200 steps)."""
    T, err = front_errors(40)
    late = T >= 1.5
    assert np.abs(err[late]).max() < 0.10
    assert np.abs(err).max() < 0.17


@pytest.mark.parametrize("dim", [2, 3])
def test_no_slip_ghost_walls_conserve_energy(dim, single_thread):
    """A no-slip wall is at rest and does no work: what its friction takes from the fluid's kinetic
    energy goes into internal energy. Dam break to T = 3, plain ghosts (a/dx = 12 in 2D, 6 in 3D).
    Measured energy ratios 1.0000014 (2D, a/dx = 20) and 1.0000037 (3D, a/dx = 8); before the ghosts
    kept the no-slip velocity out of the continuity equation: 1.033 and 1.14."""
    n = 12 if dim == 2 else 6
    ps = scenes.dam_break(a=A, dx=A / n, g=G, condition="no_slip", dim=dim)
    e0 = ps.energies()["total"]
    ps.run(3.0 / math.sqrt(2.0 * G / A))
    e = ps.energies()
    assert e["kinetic"] < 0.6 * e0  # the friction did take energy from the motion
    assert abs(e["total"] / e0 - 1.0) < 2e-5


def test_no_slip_without_viscosity_is_slip(single_thread):
    """Without any viscosity a no-slip wall must act as a slip wall: the ghosts' no-slip velocity
    enters the viscous terms only. Bit-identical fronts (before: +17 % and 5 % energy gained)."""
    runs = []
    for condition in ("slip", "no_slip"):
        ps = scenes.dam_break(a=A, dx=A / 12, g=G, condition=condition, alpha=0.0)
        ps.run(2.0 / math.sqrt(2.0 * G / A))
        runs.append(ps.x.copy())
    assert np.array_equal(runs[0], runs[1])
