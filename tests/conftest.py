"""Shared test helpers: build a model or a simulation straight from a deck given as text or a dict.

The deck goes through the whole input path (YAML loader, schema validation, model builder), as it
would from the command line: it is written to a temporary file and read with ``cli.load_model``.
"""
from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest
import yaml

_counter = itertools.count()


def load_deck(directory: Path, deck: str | dict, name: str | None = None):
    """Write `deck` (YAML text or a dict) into `directory` and build it; returns the Model."""
    from sphfem_cli.driver import load_model

    text = deck if isinstance(deck, str) else yaml.safe_dump(deck, sort_keys=False)
    path = Path(directory) / (name or f"deck_{next(_counter)}.yaml")
    path.write_text(text)
    return load_model(str(path)).model


def make_simulation(directory: Path, deck: str | dict):
    """A `Simulation` of the deck (see `load_deck`)."""
    from sphfem_cli.solver.explicit import Simulation

    return Simulation(load_deck(directory, deck))


@pytest.fixture
def single_thread():
    """Run numba kernels on one thread for the test, then restore the previous count.

    The verification models are tiny (tens to hundreds of elements), where a parallel launch costs
    far more than the work, the more so on a loaded machine; results do not depend on the count.
    """
    import sphfem_cli  # noqa: F401  (sets NUMBA_CACHE_DIR before numba is imported)
    import numba

    before = numba.get_num_threads()
    numba.set_num_threads(1)
    yield
    numba.set_num_threads(before)


@pytest.fixture
def model_from_deck(tmp_path):
    """`model_from_deck(deck)` -> Model, the deck (text or dict) written under tmp_path."""
    return lambda deck: load_deck(tmp_path, deck)


@pytest.fixture
def sim_from_deck(tmp_path):
    """`sim_from_deck(deck)` -> Simulation, the deck (text or dict) written under tmp_path."""
    return lambda deck: make_simulation(tmp_path, deck)


def distorted_box(rng: np.random.Generator, geometry: str) -> tuple[np.ndarray, np.ndarray]:
    """Nodes and elements of the ALE pass tests' meshes: the unit box in 13 x 11 quad4 ("plane"; "ring": the same
    with every radius made positive, rings off the axis) or 7 x 6 x 5 hex8 ("hex8"), each node moved by
    0.02 N(0, 1) (the first draw of ``rng``): 143 quads (a block of 128 and a rest) or 210 hex8 (blocks of 64 and
    a rest)."""
    from sphfem_cli.model.mesh import box_mesh

    dim = 3 if geometry == "hex8" else 2
    mesh = box_mesh([0.0] * dim, [1.0] * dim, divisions=[7, 6, 5] if dim == 3 else [13, 11])
    nodes = mesh.nodes + 0.02 * rng.standard_normal(mesh.nodes.shape)
    if geometry == "ring":
        nodes[:, 0] = np.abs(nodes[:, 0]) + 0.05
    return nodes, mesh.elements


def crossing_times(t: np.ndarray, y: np.ndarray, level: float = 0.0, rising: bool | None = None) -> np.ndarray:
    """Times at which the sampled signal y(t) crosses `level`, by linear interpolation.

    rising=True keeps upward crossings only, False downward only, None both.
    """
    s = np.asarray(y, dtype=float) - level
    i = np.flatnonzero((s[:-1] < 0.0) != (s[1:] < 0.0))
    if rising is not None:
        i = i[(s[i + 1] > s[i]) == rising]
    frac = s[i] / (s[i] - s[i + 1])
    return t[i] + frac * (t[i + 1] - t[i])


DECKS = Path(__file__).resolve().parents[1] / "decks"


def run_shipped_deck(name: str, tmp_path: Path) -> Path:
    """Run decks/<name>.yaml to its end through the CLI path into tmp_path/<name>; its histories folder."""
    from sphfem_cli.driver import execute, load_model

    out = tmp_path / name
    out.mkdir()
    code = execute(load_model(str(DECKS / f"{name}.yaml")), out, quiet=True).code
    assert code == 0, (out / "run.log").read_text()
    return out / "histories"


def read_history(folder: Path, name: str) -> dict[str, np.ndarray]:
    """histories/<name>.csv as {column: array}."""
    data = np.genfromtxt(folder / f"{name}.csv", delimiter=",", names=True)
    return {k: data[k] for k in data.dtype.names}


def xdmf_series(path):
    """Each saved time of an XDMF file read back with the VTK wheel's reader, as ParaView reads it:
    (time, dataset class name, point count, point array names, cell array names, point coordinates)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline
    from vtkmodules.vtkIOXdmf2 import vtkXdmfReader

    reader = vtkXdmfReader()
    reader.SetFileName(str(path))
    reader.UpdateInformation()
    times = reader.GetOutputInformation(0).Get(vtkStreamingDemandDrivenPipeline.TIME_STEPS())
    for t in times:
        reader.UpdateTimeStep(t)
        out = reader.GetOutputDataObject(0)
        point = {out.GetPointData().GetArrayName(i) for i in range(out.GetPointData().GetNumberOfArrays())}
        cell = {out.GetCellData().GetArrayName(i) for i in range(out.GetCellData().GetNumberOfArrays())}
        yield t, type(out).__name__, out.GetNumberOfPoints(), point, cell, vtk_to_numpy(out.GetPoints().GetData()).copy()
