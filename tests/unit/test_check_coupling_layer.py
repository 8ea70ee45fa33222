"""`sphfem check` prints the lagrange_in_solid penalty's extra fluid layer L_c = n h / pfac in units of h
and warns above h/2 (docs/theory/coupling.md, "Stiffness")."""
from pathlib import Path

from sphfem_cli import api
from sphfem_cli.summary import model_summary

DECK = Path(__file__).resolve().parents[2] / "decks" / "structure_in_water_ale.yaml"


def _summary(pfac, nquad):
    loaded = api.load(DECK, {"couplings.0.pfac": pfac, "couplings.0.nquad": nquad})
    return model_summary(loaded.deck, loaded.model, DECK)


def test_layer_is_n_h_over_pfac():
    # 5 mm plate segments on 10 mm water: nquad 2 -> n = 4, pfac 8 -> L_c = h / 2, no warning
    lines, warnings = _summary(8.0, 2)
    assert any("penalty layer L_c = n h / pfac = 0.5 h" in line for line in lines)
    assert not any("extra fluid" in w for w in warnings)
    # the deck before issue 12 (pfac 1): 4 h, warned; nquad 4 doubles n and the layer
    lines, warnings = _summary(1.0, 2)
    assert any("= 4 h" in line for line in lines) and any("4 h of extra fluid" in w for w in warnings)
    lines, _ = _summary(1.0, 4)
    assert any("= 8 h" in line for line in lines)
