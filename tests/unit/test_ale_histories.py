"""histories/ale_materials.csv: mass, internal and kinetic energy per material of the ALE part.

- Closed box (slip walls), air with a moving water blob: each material's mass constant to 1e-12
  relative (measured in the full-precision HDF5 mirror: air 1.3e-15, water 3e-16), the sum of the
  per-material energies (kinetic + internal) constant to 1e-10 relative (measured 9e-16), and
  equal to the ALE part's kinetic + internal energy in matsum.
- Inflow deck (ale_boundary condition inflow): water entering a void channel through the CLI;
  the water, held by no fill, joins the part, and its mass grows as rho u A t.
"""
from __future__ import annotations

import h5py
import numpy as np
import yaml
from click.testing import CliRunner

from sphfem_cli.cli import main

BOX = {
    "dimension": 2,
    "control": {"end_time": 0.002},
    "equations_of_state": {"water": {"type": "linear_polynomial", "c1": 2.2e9},
                           "air": {"type": "ideal_gas", "gamma": 1.4, "e0": 2.5e5}},
    "materials": {"water": {"type": "fluid", "density": 1000.0, "eos": "water"},
                  "air": {"type": "fluid", "density": 1.0, "eos": "air"}},
    "sections": {"fluid": {"type": "ale_multi_material"}},
    "parts": {"box": {"material": "air", "section": "fluid",
                      "geometry": {"box": {"min": [0.0, 0.0], "max": [1.0, 0.5], "divisions": [20, 10]}},
                      "fill": [{"material": "water", "ball": {"center": [0.4, 0.25], "radius": 0.12},
                                "velocity": [20.0, 5.0]}]}},
    "boundaries": [{"type": "ale_boundary", "part": "box", "sides": ["left", "right", "bottom", "top"],
                    "condition": "slip"}],
    "output": {"history_interval": 0.0001},
}


def _run(tmp_path, deck: dict):
    path = tmp_path / "deck.yaml"
    path.write_text(yaml.safe_dump(deck))
    result = CliRunner().invoke(main, ["run", str(path), "-o", str(tmp_path / "out"), "-q", "--threads", "1"])
    assert result.exit_code == 0, result.output
    hist = tmp_path / "out" / "histories"
    csv = np.genfromtxt(hist / "ale_materials.csv", delimiter=",", names=True)
    # the CSV holds 11 significant digits; the HDF5 mirror the full float64 values
    with h5py.File(tmp_path / "out" / "results.h5", "r") as f:
        # (the writer nests the tables one group deeper than the docstring's /histories/<name>)
        path = "histories/ale_materials"
        data = f[path]
        names = list(data.attrs["columns"])
        full = np.rec.fromarrays(np.asarray(data[:]).T, names=names)
    assert tuple(names) == csv.dtype.names and len(full) == len(csv)
    np.testing.assert_allclose(np.asarray(csv.tolist()), np.asarray(full.tolist()), rtol=1e-10)
    return full, np.genfromtxt(hist / "matsum.csv", delimiter=",", names=True)


def test_material_masses_constant_in_a_closed_box(tmp_path):
    h, matsum = _run(tmp_path, BOX)
    assert h.dtype.names == ("time", "mass_air", "mass_water", "internal_air", "internal_water",
                             "kinetic_air", "kinetic_water")
    assert len(h) >= 20
    for m in ("air", "water"):
        mass = h[f"mass_{m}"]
        assert mass[0] > 0
        np.testing.assert_allclose(mass, mass[0], rtol=1e-12, atol=0)
    energy = sum(h[f"{k}_{m}"] for k in ("internal", "kinetic") for m in ("air", "water"))
    np.testing.assert_allclose(energy, energy[0], rtol=1e-10, atol=0)
    assert h["kinetic_water"][-1] != h["kinetic_water"][0]  # the blob moved and slowed
    np.testing.assert_allclose(h["kinetic_air"] + h["kinetic_water"], matsum["box_kinetic"], rtol=1e-9)
    np.testing.assert_allclose(h["internal_air"] + h["internal_water"], matsum["box_internal"], rtol=1e-9)


def test_inflow_material_mass_grows_as_rho_u_a_t(tmp_path):
    u, h = 10.0, 0.02
    deck = {
        "dimension": 2,
        "control": {"end_time": 0.02},
        "equations_of_state": {"water": {"type": "linear_polynomial", "c1": 2.2e9}},
        "materials": {"water": {"type": "fluid", "density": 1000.0, "eos": "water"}, "void": {"type": "void"}},
        "sections": {"fluid": {"type": "ale_multi_material", "pressure_cutoff": 0.0}},
        "parts": {"channel": {"material": "void", "section": "fluid",
                              "geometry": {"box": {"min": [0.0, 0.0], "max": [1.0, h], "divisions": [50, 1]}}}},
        "boundaries": [
            {"type": "ale_boundary", "part": "channel", "sides": ["bottom", "top", "right"], "condition": "slip"},
            {"type": "ale_boundary", "part": "channel", "sides": ["left"], "condition": "inflow",
             "material": "water", "velocity": [u, 0.0]}],
        "output": {"history_interval": 0.002},
    }
    hist, _ = _run(tmp_path, deck)
    np.testing.assert_allclose(hist["mass_water"], 1000.0 * u * h * hist["time"], rtol=1e-9, atol=1e-12)
    assert hist["mass_water"][-1] > 0


def _check(tmp_path, boundary: dict, section: dict | None = None):
    deck = dict(BOX, boundaries=[BOX["boundaries"][0], boundary])
    if section is not None:
        deck["sections"] = {"fluid": dict(BOX["sections"]["fluid"], **section)}
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(deck))
    return CliRunner().invoke(main, ["check", str(path)])


def test_inflow_deck_errors(tmp_path):
    base = {"type": "ale_boundary", "part": "box", "sides": ["left"], "condition": "inflow"}
    cases = [
        (dict(base, velocity=[1.0, 0.0]), None, "an inflow boundary needs 'material'"),
        (dict(base, material="water"), None, "an inflow boundary needs 'velocity'"),
        (dict(base, material="water", velocity=[1.0, 0.0], pressure=1.0, energy=1.0), None, "only one of"),
        (dict(base, condition="slip", material="water"), None, "only inflow boundaries take 'material'"),
        (dict(base, material="nope", velocity=[1.0, 0.0]), None, "unknown material 'nope'"),
        (dict(base, material="water", velocity=[1.0, 0.0]), {"mesh_motion": "lagrangian"}, "no inflow sides"),
    ]
    for boundary, section, message in cases:
        result = _check(tmp_path, boundary, section)
        assert result.exit_code == 65 and message in result.output, (message, result.output)
