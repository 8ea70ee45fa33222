"""One stable, named ParaView/VTK source per part: results.<part>.xdmf read back with the VTK wheel's
XDMF reader gives that part alone, with its own arrays, at every time; results.paraview.py opens them
all; a later run into the folder (--overwrite) removes them as the run's own files."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from sphfem_cli import api

xdmf2 = pytest.importorskip("vtkmodules.vtkIOXdmf2")
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

DECK = Path(__file__).resolve().parents[2] / "decks" / "hydrostatic_plate_sph.yaml"


def _series(path):
    reader = xdmf2.vtkXdmfReader()
    reader.SetFileName(str(path))
    reader.UpdateInformation()
    times = reader.GetOutputInformation(0).Get(vtkStreamingDemandDrivenPipeline.TIME_STEPS())
    for t in times:
        reader.UpdateTimeStep(t)
        out = reader.GetOutputDataObject(0)
        point = {out.GetPointData().GetArrayName(i) for i in range(out.GetPointData().GetNumberOfArrays())}
        cell = {out.GetCellData().GetArrayName(i) for i in range(out.GetCellData().GetNumberOfArrays())}
        yield t, type(out).__name__, out.GetNumberOfPoints(), point, cell, vtk_to_numpy(out.GetPoints().GetData()).copy()


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


SHIPPED = sorted((DECK.parent).glob("*.yaml"))
# 7-12 s of CPU each (7 December 2026): -m validation, as test_snapshot.py's HEAVY; their part kinds stay covered
# by the smaller decks (a 3D ALE mesh: underwater_explosion_3d_ale; a 3D solid: cantilever_3d; a 2D ALE mesh
# with a rigid part: cylinder_entry_constant_speed_ale)
HEAVY = {"underwater_explosion_plate_3d_ale.yaml", "wedge_entry_zhao1996_ale.yaml"}


@pytest.mark.parametrize("deck", [pytest.param(d, marks=pytest.mark.validation) if d.name in HEAVY else d
                                  for d in SHIPPED], ids=lambda p: p.stem)
def test_every_shipped_deck_gives_one_named_source_per_part(deck, tmp_path):
    """Each part of every shipped deck, opened alone with the VTK wheel's reader, is that part at
    every saved time: the same point count and array names from the first step to the last."""
    import h5py
    import json

    # a tenth of the regression run's span: a few steps and three saved times are enough for the layout
    end = json.loads((DECK.parents[1] / "tests" / "regression" / "references" / f"{deck.stem}.json").read_text())["end_time"] / 10
    loaded = api.load(deck, {"control.end_time": end, "output.interval": end / 2})
    result = api.run(loaded, tmp_path / "run", threads=1)
    assert result.completed, result.message
    with h5py.File(tmp_path / "run" / "results.h5", "r") as f:
        n_times = len(f["times"])
    for p in loaded.model.parts:
        series = list(_series(tmp_path / "run" / f"results.{p.name}.xdmf"))
        assert len(series) == n_times >= 2, p.name
        first = series[0]
        for t, kind, n, point, cell, _ in series:
            assert (kind, n, point, cell) == first[1:5], (p.name, t)
        assert n > 0 and (point or cell), p.name
