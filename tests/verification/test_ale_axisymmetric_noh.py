"""Spherical Noh implosion in r-z on Eulerian ALE meshes (ale/axisymmetric.py; set-up tests/verification/ale_cases.noh_rz).

Exact: shock at R = t/3, density 64 behind it, (1 + t/R)^2 ahead. Observed (docs/studies/ale_axisymmetric_noh.py,
docs/theory/ale.md "Axisymmetric"): the L1 error over 0.1 < R < 0.4 is pre-asymptotic on 20^2 and 40^2 (the shock
spread over as many elements as the post-shock gas holds), then converges, order 0.38 (40 -> 80), 0.75
(80 -> 160) and 0.95 (160 -> 320, L1 3.67, plateau 53.5).
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
from ale_cases import noh_l1, noh_rz  # noqa: E402


def test_noh_rz_post_shock_density_rises_with_resolution():
    """20^2 and 40^2 (about 10 s): the post-shock L1 error falls (observed 57.8 -> 50.0), so does the mean
    relative error of the inflow at 0.45 < R < 0.6 (0.18 -> 0.078), the densest element moves in towards the
    shock at R = 0.2 (R = 0.38 -> 0.29), and nothing is denser than the exact plateau (64) by more than 5 %."""
    post, pre, peak = [], [], []
    for n in (20, 40):
        case = noh_rz(n)
        post.append(noh_l1(case, 0.1, 0.18))
        inflow = (case["radius"] > 0.45) & (case["radius"] < 0.6)
        pre.append(float(np.mean(np.abs(case["density"][inflow] / case["exact"][inflow] - 1.0))))
        peak.append(float(case["radius"][np.argmax(case["density"])]))
        assert case["density"].max() < 1.05 * 64.0
    assert post[1] < post[0] and pre[1] < pre[0]
    assert 0.2 < peak[1] < peak[0]


@pytest.mark.validation
def test_noh_rz_converges_on_three_meshes():
    """40^2, 80^2, 160^2 (about 4 minutes at load 10): the L1 density error over 0.1 < R < 0.4 falls on each
    refinement with observed order at least 0.5 on the finest pair (observed 11.87 -> 7.08, order 0.75)
    and the finest plateau density (0.1 < R < 0.15) within 40 % of 64 (observed 43.0)."""
    errors, plateau = [], 0.0
    for n in (40, 80, 160):
        case = noh_rz(n)
        errors.append(noh_l1(case))
        sel = (case["radius"] > 0.1) & (case["radius"] < 0.15)
        plateau = float(np.mean(case["density"][sel]))
    assert errors[0] > errors[1] > errors[2]
    assert math.log2(errors[1] / errors[2]) >= 0.5
    assert plateau > 0.6 * 64.0


def _bands(case, h):
    """(axis, off) masks: the two element columns next to the axis, and the elements more than 45 deg off it."""
    r, z = case["centroid"][:, 0], case["centroid"][:, 1]
    return r < 2.0 * h, np.arctan2(r, z) > 0.25 * math.pi


# heavy (7 s): test_noh_rz_post_shock_density_rises_with_resolution runs the r-z Noh problem in the default suite
@pytest.mark.heavy
def test_no_spurious_heating_on_the_axis():
    """Issue 15: no spurious heating on the axis. Noh's sphere on 160^2 (about 5 s CPU): behind the shock the
    exact specific internal energy is u0^2/2 = 0.5 everywhere; ahead of it 0 (cold gas, p = 0: compression does
    no work). The elements next to the axis (two columns) against those more than 45 deg off it, at the same
    spherical radius. Measured: plateau (0.08 < R < 0.17) e = 0.526 on the axis, 0.561 off it (ratio 0.938;
    0.877 / 0.910 / 0.938 / 0.948 on 40^2 / 80^2 / 160^2 / 320^2, both tending to 0.5: 0.494 / 0.521 at 320^2);
    inflow (0.25 < R < 0.45) e = 0.0051 on the axis, 0.0046 off it (the bulk viscosity's heating of the
    converging flow, falling about 4 x per refinement: 0.0715 / 0.0051 / 0.0013 on the axis at 80^2 / 160^2 /
    320^2). Asserted: the axis no hotter than off it by more than 5 % in the plateau, within 10 % of 0.5, and
    its inflow heating under 2 % of 0.5.

    Found on the way, not a heating: the inflow next to the axis is denser than the exact (1 + t/R)^2, by
    +8.8 % at 160^2 and +8.9 % at 320^2 (8.40, 8.42 against 7.72, 7.73; off the axis 7.46, 7.44 against 7.45), a
    layer of the two columns next to the axis that does not shrink relative to them with refinement: the
    volume-weighted ring forces' known weakness in spherical flow on the axis (ale/axisymmetric.py docstring,
    why the area-weighted form keeps spherical symmetry better). Asserted below 15 % (a guard, not a goal)."""
    n = 160
    case = noh_rz(n)
    axis, off = _bands(case, 1.0 / n)
    e, rad = case["energy"], case["radius"]
    plateau = (rad > 0.08) & (rad < 0.17)
    inflow = (rad > 0.25) & (rad < 0.45)
    e_axis, e_off = e[plateau & axis].mean(), e[plateau & off].mean()
    rho_axis = case["density"][inflow & axis].mean() / case["exact"][inflow & axis].mean()
    print(f"plateau e axis {e_axis:.4f} off {e_off:.4f}; inflow e axis {e[inflow & axis].mean():.4f} "
          f"off {e[inflow & off].mean():.4f}; inflow density on the axis / exact {rho_axis:.4f}")
    assert e_axis < 1.05 * e_off
    assert abs(e_axis / 0.5 - 1.0) < 0.1
    assert e[inflow & axis].mean() < 0.02 * 0.5
    assert rho_axis < 1.15
