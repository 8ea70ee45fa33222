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
