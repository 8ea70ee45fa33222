"""Deriving the SPH variant of an underwater-explosion scene: a high_explosive ball fill in water
becomes a part of explosive particles at the element centres (programmed burn on them), and the
ALE section's pressure cut-off becomes the SPH section's."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from sphfem_cli.deck.schema import Deck
from sphfem_cli.model.build import build_model
from sphfem_cli.study import derive


def _undex_scene():
    return {
        "dimension": 2, "control": {"end_time": 1e-5},
        "equations_of_state": {
            "tnt": {"type": "jwl", "A": 3.712e11, "B": 3.231e9, "R1": 4.15, "R2": 0.95, "omega": 0.3, "e0": 7.0e9},
            "water": {"type": "gruneisen", "c": 1480.0, "s1": 1.92, "gamma0": 0.28}},
        "materials": {"tnt": {"type": "high_explosive", "density": 1630.0, "detonation_velocity": 6930.0, "eos": "tnt"},
                      "water": {"type": "fluid", "density": 1000.0, "eos": "water"}, "void": {"type": "void"}},
        "detonations": [{"point": [0.05, 0.05], "time": 0.0}],
        "sections": {"fluid": {"type": "ale_multi_material", "pressure_cutoff": -1.0e5}},
        "parts": {"tank": {"material": "void", "section": "fluid",
                           "geometry": {"box": {"min": [0.0, 0.0], "max": [0.1, 0.1], "element_size": 0.01}},
                           "fill": [{"material": "water", "box": {"min": [0.0, 0.0], "max": [0.1, 0.08]}},
                                    {"material": "tnt", "ball": {"center": [0.05, 0.05], "radius": 0.011}}]}},
    }


def test_explosive_fill_and_pressure_cutoff_are_derived():
    d = derive.sph_variant(_undex_scene(), 1)
    out = d.data
    assert out["sections"]["sph"]["pressure_cutoff"] == -1.0e5
    assert out["parts"]["tank_fill1"]["material"] == "tnt"
    assert d.parts == {"tank_fill0": 80 - 4, "tank_fill1": 4}  # centres at 0.045 / 0.055 are in the ball
    model = build_model(Deck.model_validate(out), Path("."))
    ps = model.particles
    x = ps.x[ps.density == 1630.0]  # the explosive's particles
    np.testing.assert_allclose(np.sort(x[:, 0]), [0.045, 0.045, 0.055, 0.055])
    np.testing.assert_allclose(np.sort(x[:, 1]), [0.045, 0.045, 0.055, 0.055])


def test_an_sph_section_in_the_ale_deck_is_the_scenes_choice():
    """An sph section no ALE part uses is taken as it is (decks/structure_in_water_ale.yaml: alpha 0);
    without one the derivation writes its own (alpha 0.1)."""
    scene = _undex_scene()
    assert derive.sph_variant(scene, 1).data["sections"]["sph"]["artificial_viscosity"]["alpha"] == 0.1
    own = {"type": "sph", "kernel": "wendland_c2", "smoothing_ratio": 1.5, "artificial_viscosity": {"alpha": 0.0, "beta": 0.0}}
    scene["sections"]["water_sph"] = own
    out = derive.sph_variant(scene, 1).data
    assert out["sections"]["water_sph"] == own and "sph" not in out["sections"]
    assert {p["section"] for p in out["parts"].values()} == {"water_sph"}
