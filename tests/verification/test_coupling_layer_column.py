"""The lagrange_in_solid penalty is an extra fluid layer L_c = n h / pfac (docs/theory/coupling.md,
"Stiffness"), measured by static compression.

A column of water (height H = 0.1 m, bulk modulus K = 2.2 GPa, ambient pressure p0 = 1 MPa, slip walls)
stands on a fixed plate. At rest the penetration d gives the face pressure k d / l = p, and the column,
expanded by d, has p = p0 - K d / H; with k / l = K / L_c this gives p = p0 / (1 + L_c / H). Measured
(4-5 ms mean, damping 0.1): n 4 pfac 1: 0.7145 MPa (0.7143 predicted, L_c 39.96 against 40 mm); n 8
pfac 1: 0.5557 (0.5556, 79.97 mm); n 4 pfac 8: 0.9524 (0.9524, 5.00 mm); n 4 pfac 0.1: 0.1986 (0.2000,
still ringing). n = h / l: two 5 mm plate segments under a 10 mm element, nquad points each.
"""
from pathlib import Path

import pytest

from sphfem_cli import api

DECK = Path(__file__).with_name("coupling_layer_column.yaml")
P0, H, h = 1.0e6, 0.1, 0.01


@pytest.mark.parametrize("nquad, pfac", [(2, 1.0), (4, 1.0)])
def test_penalty_is_a_layer_of_n_h_over_pfac(tmp_path, nquad, pfac):
    api.run(DECK, tmp_path / "out", {"couplings.0.nquad": nquad, "couplings.0.pfac": pfac}, threads=1)
    probe = api.read_histories(tmp_path / "out")["mid"]
    late = probe["time"] > 0.004
    p = probe["pressure"][late].mean()
    n = 2 * nquad
    measured = H * (P0 / p - 1.0)
    assert measured == pytest.approx(n * h / pfac, rel=0.01)
