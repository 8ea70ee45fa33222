"""decks/structure_in_water_sph.yaml is the mesh study's ratio-1 derivation of the ALE deck.

If this fails after a change to the ALE deck or to sphfem_cli/study/derive.py, regenerate the SPH
deck as its header says (derive.sph_variant(data, 1), title changed) and its regression reference.
"""
from __future__ import annotations

from pathlib import Path

import yaml

from sphfem_cli.study import derive
from sphfem_cli.study.study import load_deck_data

DECKS = Path(__file__).parents[2] / "decks"


def test_sph_deck_is_the_ratio_1_derivation():
    derived = derive.sph_variant(load_deck_data(DECKS / "structure_in_water_ale.yaml"), 1)
    shipped = yaml.safe_load((DECKS / "structure_in_water_sph.yaml").read_text())
    assert derived.parts == {"tank": 785}  # one particle per water element (800 less the 15 under the plate)
    shipped.pop("title"), derived.data.pop("title")
    assert shipped == derived.data
    contact, = shipped["contacts"]
    assert contact["stiffness"] == "soft_constraint" and contact["soft_scale"] == 0.1
