"""A 3D (hex8) ALE part through the deck and the explicit loop (smoothed meshes too); what stays 2D is refused with a deck error."""
from __future__ import annotations

import h5py
import numpy as np
import pytest
from click.testing import CliRunner

from sphfem_cli.cli import main

DECK = """\
title: 3D ALE box
units: {length: m, mass: kg, time: s}
dimension: 3
control: {end_time: 1.5e-4}
equations_of_state:
  air: {type: ideal_gas, gamma: 1.4, e0: 2.5e5}
materials:
  air: {type: fluid, density: 1.2, eos: air}
  hot: {type: fluid, density: 1.2, eos: air}
sections:
  fluid: {type: ale_multi_material}
parts:
  box:
    material: air
    section: fluid
    geometry: {box: {min: [0, 0, 0], max: [0.1, 0.08, 0.06], divisions: [10, 8, 6]}}
    fill:
      - {material: hot, ball: {center: [0, 0, 0], radius: 0.03}, pressure: 1.0e6}
      - {material: hot, cylinder: {center: [0.1, 0.08, 0.03], radius: 0.01, axis: z, length: 0.04}, pressure: 5.0e5}
      - {material: air, half_space: {point: [0, 0, 0.05], normal: [0, 0, -1]}, velocity: [0, 0, 5.0]}
boundaries:
  - {type: ale_boundary, part: box, sides: [left, right, bottom, top, front, back], condition: slip}
loads:
  - {type: gravity, acceleration: [0, 0, -9.81]}
output:
  interval: 5.0e-5
  history_interval: 1.0e-5
  probes:
    - {name: near, type: pressure, point: [0.02, 0.0, 0.0]}
    - {name: far, type: pressure, point: [0.09, 0.0, 0.0]}
"""


def _run(tmp_path, text, name="deck.yaml"):
    deck = tmp_path / name
    deck.write_text(text)
    return CliRunner().invoke(main, ["run", str(deck), "-o", str(tmp_path / "out"), "-q"]), deck


def test_3d_ale_deck_runs(tmp_path):
    result, _ = _run(tmp_path, DECK)
    assert result.exit_code == 0, result.output
    out = tmp_path / "out"
    table = np.genfromtxt(out / "histories" / "ale_materials.csv", delimiter=",", names=True)
    # closed box: each material's mass stays to round-off
    for name in ("mass_air", "mass_hot"):
        assert abs(table[name][-1] / table[name][0] - 1.0) < 1e-12
    assert table["kinetic_air"][-1] > 0.0
    near = np.genfromtxt(out / "histories" / "near.csv", delimiter=",", names=True)
    assert near["pressure"][0] == pytest.approx(1.0e6, rel=1e-6)  # inside the sphere at the start
    with h5py.File(out / "results.h5", "r") as h5:
        grid = h5["box"]
        assert grid["connectivity"].shape == (480, 8)
        last = sorted(k for k in grid if k.startswith("step_"))[-1]
        assert {"fraction_hot", "density_air", "pressure_hot"} <= set(grid[f"{last}/cell"])
        assert grid[f"{last}/point/velocity"].shape == (693, 3)
    assert 'TopologyType="Hexahedron"' in (out / "results.xdmf").read_text()
    glstat = np.genfromtxt(out / "histories" / "glstat.csv", delimiter=",", names=True)
    # gravity's work is booked: kinetic plus internal energy balance it in a closed box
    assert abs(glstat["energy_ratio"][-1] - 1.0) < 1e-6


@pytest.mark.parametrize("section", [
    "mesh_motion: smoothed",
    "mesh_motion: smoothed, smoothing: equipotential, smoothing_boundary: sliding, eulerian_pull: 0.0",
], ids=["average", "equipotential_sliding"])
def test_3d_ale_smoothed_runs(tmp_path, section):
    """A smoothed 3D ALE part runs through the loop: each material's mass in the closed box unchanged in
    the 11 digits ale_materials.csv prints (round-off: tests/verification/test_ale_mesh_motion_3d.py);
    with sliding walls the boundary nodes stay in their walls' planes."""
    result, _ = _run(tmp_path, DECK.replace("  fluid: {type: ale_multi_material}",
                                            f"  fluid: {{type: ale_multi_material, {section}}}"))
    assert result.exit_code == 0, result.output
    out = tmp_path / "out"
    table = np.genfromtxt(out / "histories" / "ale_materials.csv", delimiter=",", names=True)
    for name in ("mass_air", "mass_hot"):
        assert abs(table[name][-1] / table[name][0] - 1.0) < 1e-12
    with h5py.File(out / "results.h5", "r") as h5:
        grid = h5["box"]
        steps = sorted(k for k in grid if k.startswith("step_"))
        x0, x = grid[f"{steps[0]}/coordinates"][()], grid[f"{steps[-1]}/coordinates"][()]
    assert np.abs(x - x0).max() > 1e-5  # the mesh moved
    for axis, (lo, hi) in enumerate(((0.0, 0.1), (0.0, 0.08), (0.0, 0.06))):
        for value in (lo, hi):
            on = np.abs(x0[:, axis] - value) < 1e-12
            assert np.abs(x[on, axis] - x0[on, axis]).max() < 1e-15


def test_3d_ale_polygon_fill_is_a_deck_error(tmp_path):
    text = DECK.replace("      - {material: air, half_space: {point: [0, 0, 0.05], normal: [0, 0, -1]}, velocity: [0, 0, 5.0]}",
                        "      - {material: air, polygon: {vertices: [[0, 0], [0.05, 0], [0, 0.05]]}}")
    result, deck = _run(tmp_path, text)
    assert result.exit_code != 0
    assert f"{deck}:20:25: parts.box.fill[2].polygon: polygons are 2D" in result.output and str(deck) in result.output


def test_3d_ale_coupling_check_prints_its_penalty_layer(tmp_path):
    """A 3D lagrange_in_solid loads; `sphfem check` states its layer L_c = n^2 h / pfac (issue 15 item 2).

    Plate faces of 10 x 10 mm, nquad 2 (A = 25 mm^2), air elements of 10 mm (V = 1e-6 m^3,
    h = 10 mm): n = h / sqrt(A) = 2, L_c = V / (pfac A) = 0.4 m = 40 h at pfac 0.1 (LS-DYNA's default; the
    5 mm edge faces, A = 12.5 mm^2: 80 h), and the check warns with the 3D rule pfac >= 2 n^2. At the
    default pfac (auto: 2 n^2 = 8 from the median face) L_c = h / 2 and the check does not warn."""
    text = DECK.replace("sections:\n", "sections:\n  plate: {type: solid}\n").replace(
        "  hot: {type: fluid, density: 1.2, eos: air}\n",
        "  hot: {type: fluid, density: 1.2, eos: air}\n"
        "  steel: {type: elastic, density: 7850.0, youngs_modulus: 2.1e11, poisson_ratio: 0.3}\n").replace(
        "boundaries:\n",
        "  plate:\n    material: steel\n    section: plate\n"
        "    geometry: {box: {min: [0.02, 0.02, 0.03], max: [0.06, 0.06, 0.035], divisions: [4, 4, 1]}}\n"
        "couplings:\n  - {type: lagrange_in_solid, structure: plate, fluid: box}\nboundaries:\n")
    deck = tmp_path / "deck.yaml"
    deck.write_text(text)
    result = CliRunner().invoke(main, ["check", str(deck)])
    assert result.exit_code == 0, result.output
    assert ("coupling box->plate: penalty layer L_c = n^2 h / pfac = 0.5 h (median over the wetted faces' area; "
            "max 1 h; pfac 8 (auto), nquad 2)") in result.output
    assert "above h/2" not in result.output
    deck.write_text(text.replace("fluid: box}", "fluid: box, pfac: 0.1}"))
    result = CliRunner().invoke(main, ["check", str(deck)])
    assert result.exit_code == 0, result.output
    assert ("coupling box->plate: penalty layer L_c = n^2 h / pfac = 40 h (median over the wetted faces' area; "
            "max 80 h; pfac 0.1, nquad 2)") in result.output
    assert "(L_c = n^2 h / pfac above h/2); pfac >= 2 n^2 keeps it below h/2" in result.output
