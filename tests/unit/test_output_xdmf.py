"""XDMF/HDF5 writer: written series read back with VTK's own XDMF reader."""
from __future__ import annotations

import re
import subprocess
import sys
import textwrap
import xml.etree.ElementTree as ET

import h5py
import numpy as np
import pytest

from sphfem_cli.output.xdmf import GridStep, XdmfWriter

xdmf2 = pytest.importorskip("vtkmodules.vtkIOXdmf2")
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet  # noqa: E402
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

TIMES = [0.0, 1.0e-3, 2.5e-3]


def quad_mesh():
    xs, ys = np.meshgrid(np.linspace(0.0, 2.0, 3), np.linspace(0.0, 1.0, 3))
    nodes = np.column_stack([xs.ravel(), ys.ravel()])
    conn = np.array([[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]])
    return nodes, conn


def hex_mesh():
    nodes = np.array(
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1],
         [2, 0, 0], [2, 1, 0], [2, 0, 1], [2, 1, 1]],
        dtype=float,
    )
    conn = np.array([[0, 1, 2, 3, 4, 5, 6, 7], [1, 8, 9, 2, 5, 10, 11, 6]])
    return nodes, conn


def quad_coords(k):
    nodes, _ = quad_mesh()
    return nodes + 0.1 * k * np.column_stack([nodes[:, 1], -nodes[:, 0]])


def particle_coords(k):
    base = np.array([[0.5, 1.5], [1.0, 1.6], [1.5, 1.7], [2.0, 1.8], [2.5, 1.9]])
    return base + np.array([0.0, -0.2 * k])


def stress(k, n):
    return np.tile(np.arange(1.0, 7.0) + 10.0 * k, (n, 1)) + np.arange(n)[:, None]


def write_2d(directory, **kwargs):
    nodes, conn = quad_mesh()
    with XdmfWriter(directory, **kwargs) as w:
        w.add_grid("plate", "Quadrilateral", conn, len(nodes))
        w.add_grid("water", "Polyvertex", None, 5)
        for k, t in enumerate(TIMES):
            x = quad_coords(k)
            w.write_step(t, {
                "plate": GridStep(x, {"velocity": x - nodes, "temperature": x[:, 0] * k},
                                  {"stress": stress(k, 4), "plastic_strain": np.arange(4) * 0.5 * k}),
                "water": GridStep(particle_coords(k), {"density": np.full(5, 1000.0 + k)}),
            })
    return w


def read(path, t):
    reader = xdmf2.vtkXdmfReader()
    reader.SetFileName(str(path))
    reader.UpdateInformation()
    times = reader.GetOutputInformation(0).Get(vtkStreamingDemandDrivenPipeline.TIME_STEPS())
    reader.UpdateTimeStep(t)
    out = reader.GetOutputDataObject(0)
    blocks = {}
    for i in range(out.GetNumberOfBlocks()):
        name = out.GetMetaData(i).Get(vtkCompositeDataSet.NAME())
        blocks[re.sub(r"\[\d+\]$", "", name)] = out.GetBlock(i)
    return (tuple(times) if times else ()), blocks


def points(block):
    return vtk_to_numpy(block.GetPoints().GetData())


def array(data, name):
    a = data.GetArray(name)
    assert a is not None, name
    return vtk_to_numpy(a)


def tensor9(t6):
    xx, yy, zz, xy, yz, zx = t6.T
    return np.column_stack([xx, xy, zx, xy, yy, yz, zx, yz, zz])


def test_2d_series_reads_back_in_vtk(tmp_path):
    write_2d(tmp_path)
    times, blocks = read(tmp_path / "results.xdmf", TIMES[-1])
    assert np.allclose(times, TIMES)
    assert set(blocks) == {"plate", "water"}
    k = len(TIMES) - 1
    plate, water = blocks["plate"], blocks["water"]
    assert plate.GetNumberOfCells() == 4 and water.GetNumberOfCells() == 5
    expected = np.column_stack([quad_coords(k), np.zeros(9)])
    assert np.allclose(points(plate), expected)
    assert not np.allclose(points(plate), np.column_stack([quad_coords(0), np.zeros(9)]))
    assert np.allclose(points(water), np.column_stack([particle_coords(k), np.zeros(5)]))
    velocity = array(plate.GetPointData(), "velocity")
    assert velocity.shape == (9, 3) and np.allclose(velocity[:, :2], quad_coords(k) - quad_mesh()[0])
    assert np.allclose(velocity[:, 2], 0.0)
    assert np.allclose(array(plate.GetPointData(), "temperature"), quad_coords(k)[:, 0] * k)
    assert np.allclose(array(plate.GetCellData(), "plastic_strain"), np.arange(4) * 0.5 * k)
    assert np.allclose(array(plate.GetCellData(), "stress"), tensor9(stress(k, 4)))
    assert np.allclose(array(water.GetPointData(), "density"), 1000.0 + k)

    _, first = read(tmp_path / "results.xdmf", TIMES[0])
    assert np.allclose(points(first["plate"])[:, :2], quad_coords(0))


def test_3d_hex_series_reads_back_in_vtk(tmp_path):
    nodes, conn = hex_mesh()
    with XdmfWriter(tmp_path, "hex") as w:
        w.add_grid("block", "Hexahedron", conn, len(nodes))
        for k, t in enumerate(TIMES):
            x = nodes * (1.0 + 0.1 * k)
            w.write_step(t, {"block": GridStep(x, {"displacement": x - nodes},
                                               {"stress": stress(k, 2), "id": np.array([7, 8])})})
    times, blocks = read(tmp_path / "hex.xdmf", TIMES[-1])
    assert np.allclose(times, TIMES)
    block = blocks["block"]
    assert block.GetNumberOfCells() == 2 and block.GetCellType(0) == 12
    assert np.allclose(points(block), nodes * 1.2)
    assert np.allclose(array(block.GetPointData(), "displacement"), nodes * 0.2)
    assert np.allclose(array(block.GetCellData(), "stress"), tensor9(stress(2, 2)))
    assert list(array(block.GetCellData(), "id")) == [7, 8]
    with h5py.File(tmp_path / "hex.h5", "r") as h5:
        assert np.allclose(h5["times"][:], TIMES)
        assert h5["block/connectivity"].shape == (2, 8)
        assert h5["block/step_000002/coordinates"].shape == (12, 3)


def test_xml_valid_after_every_step(tmp_path):
    nodes, conn = quad_mesh()
    w = XdmfWriter(tmp_path, xml_interval_s=0.0)
    assert not w.xdmf_path.exists()
    w.add_grid("plate", "Quadrilateral", conn, len(nodes))
    for k, t in enumerate(TIMES):
        w.write_step(t, {"plate": GridStep(quad_coords(k), {"v": quad_coords(k)})})
        root = ET.parse(w.xdmf_path).getroot()
        steps = root.findall("./Domain/Grid[@CollectionType='Temporal']/Grid")
        assert len(steps) == k + 1
        assert [float(s.find("Time").get("Value")) for s in steps] == TIMES[: k + 1]
        for item in root.iter("DataItem"):
            filename, path = item.text.split(":")
            assert filename == "results.h5"
            dims = tuple(int(d) for d in item.get("Dimensions").split())
            assert w.h5[path].shape == dims
    w.close()
    w.close()
    assert not list(tmp_path.glob("*.tmp"))


def test_killed_run_leaves_readable_xdmf(tmp_path):
    script = textwrap.dedent(f"""
        import os, sys
        import numpy as np
        from sphfem_cli.output.xdmf import GridStep, XdmfWriter
        w = XdmfWriter({str(tmp_path)!r}, xml_interval_s=1e9)
        w.add_grid("water", "Polyvertex", None, 3)
        x = np.zeros((3, 2))
        w.write_step(0.0, {{"water": GridStep(x)}})
        w.write_step(0.5, {{"water": GridStep(x + 1.0)}})
        w.write_xml()
        w.write_step(1.0, {{"water": GridStep(x + 2.0)}})
        os._exit(0)
    """)
    subprocess.run([sys.executable, "-c", script], check=True)
    times, blocks = read(tmp_path / "results.xdmf", 0.5)
    assert np.allclose(times, [0.0, 0.5])
    assert np.allclose(points(blocks["water"])[:, :2], 1.0)


def test_live_run_readable(tmp_path):
    nodes, conn = quad_mesh()
    with XdmfWriter(tmp_path, xml_interval_s=0.0) as w:
        w.add_grid("plate", "Quadrilateral", conn, len(nodes))
        for k, t in enumerate(TIMES[:2]):
            w.write_step(t, {"plate": GridStep(quad_coords(k))})
        times, blocks = read(w.xdmf_path, TIMES[1])
        assert np.allclose(times, TIMES[:2])
        assert np.allclose(points(blocks["plate"])[:, :2], quad_coords(1))
        w.write_step(TIMES[2], {"plate": GridStep(quad_coords(2))})


def test_bad_input_rejected(tmp_path):
    nodes, conn = quad_mesh()
    with XdmfWriter(tmp_path) as w:
        w.add_grid("plate", "Quadrilateral", conn, len(nodes))
        with pytest.raises(ValueError):
            w.add_grid("plate", "Quadrilateral", conn, len(nodes))
        with pytest.raises(ValueError):
            w.add_grid("bad", "Hexahedron", conn, len(nodes))
        with pytest.raises(ValueError):
            w.add_grid("p", "Polyvertex", conn, len(nodes))
        with pytest.raises(KeyError):
            w.write_step(0.0, {"other": GridStep(nodes)})
        with pytest.raises(ValueError):
            w.write_step(0.0, {"plate": GridStep(nodes[:5])})
        with pytest.raises(ValueError):
            w.write_step(0.0, {"plate": GridStep(nodes, {"f": np.zeros((9, 4))})})
