"""2D dam break: the surge front against Martin & Moyce (1952).

Column a wide and 2a high (a = 1 m) at the left end of a dry tank 5a long, Tait water with
c0 = 10 sqrt(2 g 2a), Monaghan alpha = 0.1, delta-SPH 0.1, hydrostatic start, ghost walls
(no-slip, as the experiment's floor). Front Z = (largest particle x + dx/2)/a against
T = t sqrt(2g/a); reference: ../shared/reference/dambreak_front_martin_moyce_1952.csv (Martin &
Moyce 1952, Phil. Trans. R. Soc. A 244, Fig. 3, n^2 = 2, both column sizes).

Measured relative errors (Z_sph - Z_exp)/Z_exp at the reference points with T <= 3:

=========  ======  ======  ======  ======  ======  ======  ======  ======  ======
T          0.832   0.849   1.212   1.219   1.602   1.997   2.283   2.547   2.950
a/dx = 12  +7.5 %  +6.0 %  +10.1%  +8.2 %  +4.9 %  +2.6 %  -2.0 %  -1.6 %  -9.3 %
a/dx = 40  +10.6%  +8.9 %  +15.7%  +13.6%  +9.4 %  +8.6 %  +5.1 %  +5.8 %  -3.2 %
a/dx = 60  +11.5%  +10.1%  +15.9%  +14.0%  +9.2 %  +8.1 %  +4.9 %  +5.3 %  -0.3 %
=========  ======  ======  ======  ======  ======  ======  ======  ======  ======

From a/dx = 40 on the result is converged; the computed front leads the measured one in the
first part of the collapse (T < 1.5, up to 16 % at T = 1.2) and matches it within 10 % from
T = 1.5 on. The early lead is the usual one of inviscid computations against this experiment,
whose release (removing the retaining gate) delays the start; with a slip floor the lead is larger
(21 % at T = 1.2). The validation test therefore holds T in [1.5, 3] to 10 % and all T <= 3 to
17 %; the coarse default-suite run is held to 20 %.
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
