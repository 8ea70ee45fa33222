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


def test_deck_contact_runs_on_a_plate_finer_than_the_water(tmp_path):
    """The deck's soft_scale 0.1 on the 8 x 120 plate (face node 0.0021 kg/m under a 0.1 kg/m particle).

    With the spring from the particle's mass alone the pair was a two-mass spring at omega dt0 = 2.20 and the
    energy guard stopped the run at step 10 (with the guard off: 777 J of kinetic energy at 20 us);
    the reduced-mass spring keeps omega dt0 = sqrt(0.1) (docs/studies/structure_in_water.md, "The SPH deck's
    plate refined at the shipped spacing"). The full 3 ms run gives 0.5687 mm at this plate. Here the first
    20 us (117 steps): the run completes (the old spring: stopped at step 10) and its kinetic energy stays at
    the physical scale (measured 0.244 J; 0.248 J on the shipped 2 x 30 plate at 20 us; bound 1 J, nearly
    three orders below the unstable run's).
    """
    from sphfem_cli import api
    from sphfem_cli.study.metrics import history_columns

    res = api.run(DECKS / "structure_in_water_sph.yaml", tmp_path / "out",
                  {"parts.plate.geometry.box.divisions": [8, 120], "control.end_time": 2e-5}, threads=1)
    assert res.status == "completed", res.message
    glstat = history_columns(tmp_path / "out/histories/glstat.csv")
    assert glstat["kinetic"][-1] < 1.0
