"""`sphfem check` warns when a lagrange_in_solid coupling has fewer than one coupling point per
fluid-element face (n = h / l < 1): the fluid then passes between the points.

On tests/verification/ale_plate_strip.yaml (one 5 mm plate segment, nquad 2, so l = 2.5 mm) the
water refined alone to 1.25 mm gave n = 0.5 and a face pressure of 22 MPa instead of 184 MPa
5 us after a 100 MPa step arrived (issue 12, aleshock3; summary.model_summary)."""
from pathlib import Path

from sphfem_cli import api
from sphfem_cli.summary import model_summary

DECK = Path(__file__).resolve().parents[1] / "verification" / "ale_plate_strip.yaml"
SIZE = "parts.tank.geometry.box.element_size"


def _warnings(overrides):
    loaded = api.load(DECK, overrides)
    return [w for w in model_summary(loaded.deck, loaded.model, DECK)[1] if "coupling points per" in w]


def test_points_per_fluid_element():
    # the deck as shipped: 2.5 mm water, 2.5 mm between points: n = 1, no warning
    assert _warnings({}) == []
    # the fluid refined alone: n = 0.5, warned, with the nquad that restores n = 1
    (w,) = _warnings({SIZE: 0.00125})
    assert "0.5 coupling points per fluid-element face" in w and "raise nquad to 4" in w
    # refined with it (nquad 4, or the plate's segments halved): no warning
    assert _warnings({SIZE: 0.00125, "couplings.0.nquad": 4}) == []
    assert _warnings({SIZE: 0.00125, "parts.plate.geometry.box.divisions": [2, 2]}) == []
    # n = 0.25 would need nquad 8, past the schema's bound of 5: refine the structure instead
    (w,) = _warnings({SIZE: 0.000625})
    assert "0.25 coupling points" in w and "refine the structure's segments" in w and "nquad 8" in w
