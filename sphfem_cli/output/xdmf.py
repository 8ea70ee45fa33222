"""XDMF (v3) + HDF5 time-series writer for moving meshes and particles.

meshio's time-series writer fixes the geometry at the first step, so deforming meshes and moving
particles would not animate; this writer stores the coordinates of every grid at every step.

File layout, for ``XdmfWriter(directory, "results")``::

    results.h5
        /times                                   (S,) float64, one entry per written step
        /<grid>                                  attribute ``topology``
        /<grid>/connectivity                     (E, nodes per cell) int64, written once
        /<grid>/step_000012/coordinates          (N, 3) float64; 2D input is padded with z = 0
        /<grid>/step_000012/point/<field>        (N,) | (N, 3) | (N, 6)
        /<grid>/step_000012/cell/<field>         (E,) | (E, 3) | (E, 6)
    results.xdmf
        temporal collection of per-step spatial collections, one Uniform grid per part, every
        DataItem pointing into ``results.h5`` by relative path
    results.<grid>.xdmf
        one part alone: a temporal collection of that part's Uniform grids. ParaView and VTK open it
        as one source named after the part at every time (their readers number the blocks of a
        spatial collection per step, so a block chosen at one time is another block at the next)
    results.paraview.py
        a pvpython / ParaView-Python-shell script that opens every part file with a style per kind
        (Point Gaussian for particles, a surface with edges for meshes), coloured by a chosen field

Field shapes decide the XDMF attribute type: ``(n,)`` or ``(n, 1)`` is a Scalar, ``(n, 2)`` or
``(n, 3)`` a Vector (2D vectors are padded with a zero z component), ``(n, 6)`` a symmetric tensor
given in the code's order ``xx, yy, zz, xy, yz, zx``. XDMF's ``Tensor6`` lists the upper triangle
row by row, ``xx, xy, xz, yy, yz, zz``, so tensors are permuted to that order on write; the HDF5
dataset carries it in its ``component_order`` attribute.

Every step is flushed to the HDF5 file before it is listed in the XML, and the XML is replaced
atomically (temporary file + ``os.replace``), at the latest every ``xml_interval_s`` seconds of
wall time, at every step when ``xml_budget`` allows it (see ``__init__``), and always on ``close()``. A run killed at any moment therefore leaves a readable XDMF that
lists only steps whose data is on disk. The HDF5 library cannot recover from a write that fails half-way
(a full disk leaves the file unreadable), so disk space for each step is reserved first
(:func:`reserve_space`): a full disk, a quota or a file-size limit then fails before HDF5 writes
anything, with OSError, and the file keeps every step written before. The XDMF file appears with the first step (a stale one
from an earlier run in the same directory is removed when the writer opens). The HDF5 file is
opened without HDF5's file lock, so ParaView can open the series while the run is still going.
"""
from __future__ import annotations

import errno
import os
import tempfile
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import h5py
import numpy as np

REVOLVED = ".revolved"
"""Grids named ``<part>.revolved`` (output/revolve.py) have their own file only: results.xdmf keeps the
meridian parts, which a revolved view would otherwise overlap in one collection."""

__all__ = ["GridStep", "XdmfWriter", "TOPOLOGIES", "TENSOR6_XDMF_ORDER"]

TOPOLOGIES: dict[str, int] = {
    "Polyvertex": 1,
    "Triangle": 3,
    "Quadrilateral": 4,
    "Tetrahedron": 4,
    "Hexahedron": 8,
}
"""XDMF topology names accepted by :meth:`XdmfWriter.add_grid` and their nodes per cell."""

TENSOR6_XDMF_ORDER = (0, 3, 5, 1, 4, 2)
"""Indices into a code-order 6-vector (xx, yy, zz, xy, yz, zx) giving XDMF's xx, xy, xz, yy, yz, zz."""


@dataclass
class GridStep:
    """The state of one grid at one step.

    ``coordinates`` is ``(n_points, 2 | 3)``; ``point_data`` maps names to ``(n_points, ...)``
    arrays and ``cell_data`` to ``(n_cells, ...)`` arrays (see the module docstring for shapes).
    """

    coordinates: np.ndarray
    point_data: Mapping[str, np.ndarray] = field(default_factory=dict)
    cell_data: Mapping[str, np.ndarray] = field(default_factory=dict)


@dataclass
class _Grid:
    name: str
    topology: str
    n_points: int
    n_cells: int
    nodes_per_cell: int


@dataclass
class _Attribute:
    name: str
    kind: str
    center: str
    path: str
    shape: tuple[int, ...]
    dtype: np.dtype


@dataclass
class _GridRecord:
    grid: str
    coordinates: str
    attributes: list[_Attribute]


@dataclass
class _StepRecord:
    time: float
    grids: list[_GridRecord]


_UNSUPPORTED = {errno.EINVAL, errno.EOPNOTSUPP, errno.ENOSYS, errno.ENODEV}
_OVERHEAD = 64 * 1024  # bytes of HDF5 metadata reserved besides the data: object headers, B-tree nodes, heaps
_PER_DATASET = 4 * 1024


def reserve_space(h5: h5py.File, nbytes: int) -> None:
    """Allocate the disk blocks for the next `nbytes` (plus metadata) the HDF5 library will append to
    `h5`, so that a full disk, a quota or a file-size limit raises OSError here, before HDF5 writes.

    The blocks are allocated after the file's end of allocated space (``H5Fget_filesize``) with
    posix_fallocate; :func:`trim_space` gives back what a flush left unused. A file system without
    fallocate support is written without the reservation."""
    try:
        fd = h5.id.get_vfd_handle()
        end = h5.id.get_filesize()
    except (ValueError, TypeError, RuntimeError, OSError):  # not the default (sec2) driver
        return
    try:
        os.posix_fallocate(fd, end, int(nbytes) + _OVERHEAD)
    except OSError as err:
        if err.errno not in _UNSUPPORTED:
            raise OSError(err.errno, err.strerror, h5.filename) from None


def trim_space(h5: h5py.File) -> None:
    """Cut the file back to HDF5's end of allocated space after a flush (the unused reservation)."""
    try:
        fd = h5.id.get_vfd_handle()
        end = h5.id.get_filesize()
        if os.fstat(fd).st_size > end:
            os.ftruncate(fd, end)
    except (ValueError, TypeError, RuntimeError, OSError):
        pass


def _number_type(dtype: np.dtype) -> tuple[str, int]:
    if dtype.kind == "f":
        return "Float", dtype.itemsize
    if dtype.kind == "i":
        return "Int", dtype.itemsize
    if dtype.kind == "u":
        return "UInt", dtype.itemsize
    raise TypeError(f"unsupported dtype {dtype}")


def _pad3(values: np.ndarray) -> np.ndarray:
    if values.shape[1] == 3:
        return values
    out = np.zeros((values.shape[0], 3), dtype=values.dtype)
    out[:, : values.shape[1]] = values
    return out


def _as_attribute(values: np.ndarray, n: int, what: str) -> tuple[str, np.ndarray]:
    """Classify and reshape a field; return its XDMF attribute type and the array to store."""
    a = np.asarray(values)
    if a.dtype.kind == "b":
        a = a.astype(np.int8)
    elif a.dtype.kind not in "fiu":
        a = a.astype(np.float64)
    if a.ndim == 2 and a.shape[1] == 1:
        a = a[:, 0]
    if a.shape[0] != n:
        raise ValueError(f"{what}: {a.shape[0]} rows, expected {n}")
    if a.ndim == 1:
        return "Scalar", np.ascontiguousarray(a)
    if a.ndim == 2 and a.shape[1] in (2, 3):
        return "Vector", np.ascontiguousarray(_pad3(a))
    if a.ndim == 2 and a.shape[1] == 6:
        return "Tensor6", np.ascontiguousarray(a[:, TENSOR6_XDMF_ORDER])
    raise ValueError(f"{what}: shape {a.shape} is not (n,), (n, 2), (n, 3) or (n, 6)")


class XdmfWriter:
    """Write a time series of one or more grids (parts) as ``<basename>.xdmf`` + ``<basename>.h5``.

    Declare each grid once with :meth:`add_grid`, then call :meth:`write_step` for every output
    time. Use as a context manager, or call :meth:`close` (idempotent) at the end.
    """

    def __init__(self, directory: Path | str, basename: str = "results", xml_interval_s: float = 5.0,
                 resume: dict | None = None, xml_budget: float | None = None):
        """``resume``: a :meth:`state` of an earlier writer on the same files; the series continues
        after its steps (steps written after that state are dropped), grids are not declared again.
        ``xml_budget``: also rewrite the XML at a step whenever that keeps the rewrites below this
        fraction of the wall time (the last rewrite's duration / budget has passed), so a short
        series lists every step as soon as it is flushed; None: only every ``xml_interval_s``."""
        self.xml_budget = xml_budget
        self._xml_cost = 0.0
        self.directory = Path(directory)
        self.directory.mkdir(parents=True, exist_ok=True)
        self.basename = basename
        self.h5_path = self.directory / f"{basename}.h5"
        self.xdmf_path = self.directory / f"{basename}.xdmf"
        self.xml_interval_s = float(xml_interval_s)
        self._last_xml = -np.inf
        self._closed = False
        if resume is not None:
            self._resume(resume)
            return
        self.h5 = h5py.File(self.h5_path, "w", locking=False)
        self._times = self.h5.create_dataset("times", shape=(0,), maxshape=(None,), dtype="f8", chunks=(1024,))
        self._grids: dict[str, _Grid] = {}
        self._steps: list[_StepRecord] = []
        self.xdmf_path.unlink(missing_ok=True)
        self.script_path.unlink(missing_ok=True)

    def state(self) -> dict:
        """What :meth:`__init__` needs to continue this series later, as plain JSON-able data:
        ``grids`` maps each grid to [topology, points, cells, nodes per cell]; ``steps`` lists
        [time, [[grid, coordinates path, [[name, kind, center, path, shape, dtype], ...]], ...]]."""
        grids = {g.name: [g.topology, g.n_points, g.n_cells, g.nodes_per_cell] for g in self._grids.values()}
        steps = [[s.time, [[r.grid, r.coordinates, [[a.name, a.kind, a.center, a.path, list(a.shape), a.dtype.str]
                                                    for a in r.attributes]] for r in s.grids]]
                 for s in self._steps]
        return {"grids": grids, "steps": steps}

    def _resume(self, state: dict) -> None:
        if not self.h5_path.exists():
            raise FileNotFoundError(f"{self.h5_path}: the HDF5 file of the run to continue is missing")
        self.h5 = h5py.File(self.h5_path, "a", locking=False)
        self._grids = {name: _Grid(name, str(topo), int(n), int(c), int(npc))
                       for name, (topo, n, c, npc) in state["grids"].items()}
        self._steps = [_StepRecord(float(t), [_GridRecord(str(g), str(xyz), [
                           _Attribute(str(a), str(k), str(c), str(p), tuple(int(i) for i in shape), np.dtype(dt))
                           for a, k, c, p, shape, dt in attrs]) for g, xyz, attrs in grids])
                       for t, grids in state["steps"]]
        n = len(self._steps)
        self._times = self.h5["times"]
        reserve_space(self.h5, 0)  # the truncation below rewrites metadata
        if self._times.shape[0] < n:
            raise ValueError(f"{self.h5_path}: {self._times.shape[0]} steps on disk, the checkpoint lists {n}")
        self._times.resize((n,))
        for name in self._grids:
            for key in list(self.h5[name].keys()):
                if key.startswith("step_") and int(key[5:]) >= n:
                    del self.h5[name][key]
        self.h5.flush()
        self.write_xml()

    @property
    def n_steps(self) -> int:
        """Number of steps written so far."""
        return len(self._steps)

    @property
    def last_time(self) -> float | None:
        """Time of the last step written, None before the first."""
        return self._steps[-1].time if self._steps else None

    def add_grid(self, name: str, topology: str, connectivity: np.ndarray | None, n_points: int) -> None:
        """Declare a grid; its connectivity is written once.

        ``topology`` is a key of :data:`TOPOLOGIES`. Connectivity is ``(n_cells, nodes per cell)``
        zero-based node indices (hex8 in VTK order); for ``"Polyvertex"`` it is ``None`` and every
        point is a cell.
        """
        if self._closed:
            raise RuntimeError("writer is closed")
        if name in self._grids or name in ("times", "histories") or "/" in name or not name:
            raise ValueError(f"grid name {name!r} is empty, reserved or already declared")
        if topology not in TOPOLOGIES:
            raise ValueError(f"topology {topology!r} is not one of {sorted(TOPOLOGIES)}")
        npc = TOPOLOGIES[topology]
        if topology == "Polyvertex":
            if connectivity is not None:
                raise ValueError("Polyvertex grids take connectivity=None")
            conn = np.arange(n_points, dtype=np.int64).reshape(-1, 1)
        else:
            conn = np.asarray(connectivity, dtype=np.int64)
            if conn.ndim != 2 or conn.shape[1] != npc:
                raise ValueError(f"{topology} connectivity must be (E, {npc}), got {conn.shape}")
            if conn.size and (conn.min() < 0 or conn.max() >= n_points):
                raise ValueError(f"connectivity of {name!r} references nodes outside 0..{n_points - 1}")
        reserve_space(self.h5, conn.nbytes + _PER_DATASET)
        group = self.h5.create_group(name)
        group.attrs["topology"] = topology
        group.create_dataset("connectivity", data=conn)
        self._grids[name] = _Grid(name, topology, int(n_points), conn.shape[0], npc)

    def write_step(self, time_value: float, data: Mapping[str, GridStep]) -> None:
        """Write one output step: ``data`` maps declared grid names to their :class:`GridStep`.

        Grids left out of ``data`` are absent from this step. The HDF5 file is flushed, then the
        XML is rewritten if ``xml_interval_s`` has passed since the last rewrite.
        """
        if self._closed:
            raise RuntimeError("writer is closed")
        prepared = []
        for name, state in data.items():
            grid = self._grids.get(name)
            if grid is None:
                raise KeyError(f"grid {name!r} was not declared with add_grid")
            xyz = np.asarray(state.coordinates, dtype=np.float64)
            if xyz.ndim != 2 or xyz.shape[0] != grid.n_points or xyz.shape[1] not in (2, 3):
                raise ValueError(f"{name}: coordinates must be ({grid.n_points}, 2|3), got {xyz.shape}")
            fields = []
            for sub, center, arrays, n in (
                ("point", "Node", state.point_data, grid.n_points),
                ("cell", "Cell", state.cell_data, grid.n_cells),
            ):
                for field_name, values in arrays.items():
                    if "/" in field_name or not field_name:
                        raise ValueError(f"{name}: bad field name {field_name!r}")
                    kind, stored = _as_attribute(values, n, f"{name}.{sub}.{field_name}")
                    fields.append((sub, center, field_name, kind, stored))
            prepared.append((name, _pad3(xyz), fields))

        index = len(self._steps)
        step_name = f"step_{index:06d}"
        records = []
        n_data = sum(1 + len(fields) for _, _, fields in prepared)
        reserve_space(self.h5, sum(xyz.nbytes + sum(f[4].nbytes for f in fields) for _, xyz, fields in prepared)
                      + _PER_DATASET * (n_data + 2))
        for name, xyz, fields in prepared:
            parent = self.h5[name]
            if step_name in parent:
                del parent[step_name]
            group = parent.create_group(step_name)
            group.create_dataset("coordinates", data=xyz)
            attributes = []
            for sub, center, field_name, kind, stored in fields:
                ds = group.create_dataset(f"{sub}/{field_name}", data=stored)
                if kind == "Tensor6":
                    ds.attrs["component_order"] = "xx,xy,xz,yy,yz,zz"
                attributes.append(_Attribute(field_name, kind, center, ds.name, stored.shape, stored.dtype))
            records.append(_GridRecord(name, group.name + "/coordinates", attributes))
        self._times.resize((index + 1,))
        self._times[index] = float(time_value)
        self.h5.flush()
        trim_space(self.h5)
        self._steps.append(_StepRecord(float(time_value), records))
        age = time.monotonic() - self._last_xml
        if age >= self.xml_interval_s or (self.xml_budget and age >= self._xml_cost / self.xml_budget):
            self.write_xml()

    def _data_item(self, parent: ET.Element, path: str, shape: tuple[int, ...], dtype: np.dtype) -> None:
        number_type, precision = _number_type(np.dtype(dtype))
        item = ET.SubElement(
            parent,
            "DataItem",
            Dimensions=" ".join(str(s) for s in shape),
            NumberType=number_type,
            Precision=str(precision),
            Format="HDF",
        )
        item.text = f"{self.h5_path.name}:{path}"

    def _uniform(self, parent: ET.Element, record: _GridRecord) -> ET.Element:
        grid = self._grids[record.grid]
        uniform = ET.SubElement(parent, "Grid", Name=grid.name, GridType="Uniform")
        topo = ET.SubElement(uniform, "Topology", TopologyType=grid.topology, NumberOfElements=str(grid.n_cells),
                             NodesPerElement=str(grid.nodes_per_cell))
        self._data_item(topo, f"/{grid.name}/connectivity", (grid.n_cells, grid.nodes_per_cell), np.dtype(np.int64))
        geometry = ET.SubElement(uniform, "Geometry", GeometryType="XYZ")
        self._data_item(geometry, record.coordinates, (grid.n_points, 3), np.dtype(np.float64))
        for attr in record.attributes:
            element = ET.SubElement(uniform, "Attribute", Name=attr.name, AttributeType=attr.kind, Center=attr.center)
            self._data_item(element, attr.path, attr.shape, attr.dtype)
        return uniform

    def _xml_tree(self, part: str | None = None) -> ET.Element:
        """Every part per step (``part`` None), or the temporal series of one part."""
        root = ET.Element("Xdmf", Version="3.0")
        domain = ET.SubElement(root, "Domain")
        series = ET.SubElement(domain, "Grid", Name=part or "TimeSeries", GridType="Collection",
                               CollectionType="Temporal")
        for step in self._steps:
            if part is None:
                records = [r for r in step.grids if not r.grid.endswith(REVOLVED)]
                if not records:
                    continue
                spatial = ET.SubElement(series, "Grid", Name="Parts", GridType="Collection", CollectionType="Spatial")
                ET.SubElement(spatial, "Time", Value=repr(step.time))
                for record in records:
                    self._uniform(spatial, record)
                continue
            for record in step.grids:
                if record.grid == part:
                    uniform = self._uniform(series, record)
                    uniform.insert(0, ET.Element("Time", Value=repr(step.time)))
        return root

    def part_path(self, part: str) -> Path:
        """The XDMF file of one part: ``<basename>.<part>.xdmf``."""
        return self.directory / f"{self.basename}.{part}.xdmf"

    @property
    def script_path(self) -> Path:
        return self.directory / f"{self.basename}.paraview.py"

    def write_xml(self) -> None:
        """Rewrite the XDMF file atomically, listing every step written so far.

        Nothing is written before the first step: VTK's XDMF reader crashes on a file without grids.
        """
        if not self._steps:
            return
        started = time.monotonic()
        for part, path in ((None, self.xdmf_path), *((g, self.part_path(g)) for g in self._grids)):
            root = self._xml_tree(part)
            ET.indent(root, space="  ")
            self._replace(path, '<?xml version="1.0" ?>\n<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>\n'
                          + ET.tostring(root, encoding="unicode") + "\n")
        if not self.script_path.exists():
            self._replace(self.script_path, paraview_script(self.basename, {
                g.name: g.topology for g in self._grids.values()}))
        self._last_xml = time.monotonic()
        self._xml_cost = self._last_xml - started

    def _replace(self, path: Path, text: str) -> None:
        """Write `path` atomically: a temporary file in the folder, fsync, rename."""
        fd, tmp = tempfile.mkstemp(prefix=f".{self.basename}.", suffix=".xdmf.tmp", dir=self.directory)
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as fh:
                fh.write(text)
                fh.flush()
                os.fsync(fh.fileno())
            os.chmod(tmp, 0o644)
            os.replace(tmp, path)
        except BaseException:
            if os.path.exists(tmp):
                os.unlink(tmp)
            raise

    def close(self) -> None:
        """Write the final XML and close the HDF5 file; calling it again does nothing."""
        if self._closed:
            return
        try:
            self.write_xml()
        finally:
            self._closed = True
            self.h5.close()

    def __enter__(self) -> XdmfWriter:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


_COLOUR_BY = ("von_mises", "pressure", "velocity", "displacement", "density")


def paraview_script(basename: str, grids: Mapping[str, str]) -> str:
    """The text of ``<basename>.paraview.py``: open each part's XDMF as a source named after the part,
    particles as Point Gaussian, meshes as surfaces with edges, coloured by the first field of
    ``_COLOUR_BY`` the part has. Coordinates are the deformed ones at every step: no warp is needed."""
    parts = ",\n".join(f"    ({name!r}, {'True' if topo == 'Polyvertex' else 'False'})" for name, topo in grids.items())
    return f'''"""Open this run's parts in ParaView: `pvpython {basename}.paraview.py` (then File > Save State), or
ParaView's View > Python Shell > Run Script. Written by sphfem; one source per part, named after it."""
import os

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetAnimationScene, Render, ResetCamera, Show,
                             Xdmf3ReaderT)

HERE = os.path.dirname(os.path.abspath(__file__))
PARTS = [
{parts},
]
COLOUR_BY = {_COLOUR_BY!r}

view = GetActiveViewOrCreate("RenderView")
for name, particles in PARTS:
    source = Xdmf3ReaderT(registrationName=name, FileName=[os.path.join(HERE, f"{basename}.{{name}}.xdmf")])
    source.UpdatePipelineInformation()
    shown = Show(source, view)
    if particles:
        shown.SetRepresentationType("Point Gaussian")
        shown.GaussianRadius = 0.5 * shown.GaussianRadius
    else:
        shown.SetRepresentationType("Surface With Edges")
    arrays = list(source.PointData.keys()) + list(source.CellData.keys())
    for field in COLOUR_BY:
        if field in arrays:
            where = "POINTS" if field in source.PointData.keys() else "CELLS"
            ColorBy(shown, (where, field))
            shown.RescaleTransferFunctionToDataRange(True, False)
            break
GetAnimationScene().UpdateAnimationUsingDataTimeSteps()
view.InteractionMode = "2D" if all(abs(b) < 1e-300 for b in source.GetDataInformation().GetBounds()[4:]) else "3D"
ResetCamera(view)
Render(view)
'''
