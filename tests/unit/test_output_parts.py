"""One stable, named ParaView/VTK source per part: results.<part>.xdmf read back with the VTK wheel's
XDMF reader gives that part alone, with its own arrays, at every time; results.paraview.py opens them
all; a later run into the folder (--overwrite) removes them as the run's own files."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from sphfem_cli import api

from conftest import xdmf_series as _series

pytest.importorskip("vtkmodules.vtkIOXdmf2")

DECK = Path(__file__).resolve().parents[2] / "decks" / "hydrostatic_plate_sph.yaml"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("parts") / "run"
    result = api.run(DECK, out, overrides={"control.end_time": 2e-4, "output.interval": 5e-5})
    assert result.completed, result.message
    return out


def test_each_part_is_one_named_source_at_every_time(run):
    water = list(_series(run / "results.water.xdmf"))
    plate = list(_series(run / "results.plate.xdmf"))
    assert [w[0] for w in water] == pytest.approx([0.0, 5e-5, 1e-4, 1.5e-4, 2e-4])
    assert [p[0] for p in plate] == [w[0] for w in water]
    for t, kind, n, point, cell, _ in water:
        assert kind == "UnstructuredGrid" and n == 3200 and {"velocity", "density"} <= point and not cell
    for t, kind, n, point, cell, _ in plate:
        assert kind == "UnstructuredGrid" and n == 205 and {"displacement", "velocity"} <= point
        assert "von_mises" in cell
    assert not np.array_equal(water[0][5], water[-1][5])  # the particles move: coordinates per step


def test_the_paraview_script_names_every_part(run):
    text = (run / "results.paraview.py").read_text()
    compile(text, "results.paraview.py", "exec")
    assert "('water', True)" in text and "('plate', False)" in text and "Point Gaussian" in text


def test_a_new_run_removes_the_part_files_of_the_last(tmp_path):
    import yaml

    deck = yaml.safe_load(DECK.read_text())
    folder = tmp_path / "again"
    api.run(deck, folder, overrides={"control.end_time": 5e-5}, base_dir=DECK.parent)
    assert (folder / "results.water.xdmf").exists()
    (folder / "results.mine.xdmf").write_text("a user's file: kept")
    deck["parts"]["fluid"] = deck["parts"].pop("water")
    deck["contacts"][0]["nodes"] = "fluid"
    api.run(deck, folder, overrides={"control.end_time": 5e-5}, base_dir=DECK.parent, overwrite=True)
    assert (folder / "results.fluid.xdmf").exists() and not (folder / "results.water.xdmf").exists()
    assert (folder / "results.mine.xdmf").read_text() == "a user's file: kept"
