"""History tables: CSV round trip and the HDF5 mirror."""
from __future__ import annotations

import h5py
import numpy as np
import pytest

from sphfem_cli.output.history import HistoryWriter

COLUMNS = ["time", "kinetic", "internal", "total"]


def rows(n):
    t = np.linspace(0.0, 1.0e-3, n)
    ke = 0.5 * (1.0 + np.sin(t * 1e4)) * 1.234567890123e6
    ie = 3.0e-7 * np.arange(n)
    return np.column_stack([t, ke, ie, ke + ie])


def test_csv_round_trip(tmp_path):
    data = rows(257)
    with HistoryWriter(tmp_path, "glstat", COLUMNS, flush_rows=50) as h:
        for r in data:
            h.append(r)
        assert h.n_rows == 257
    lines = (tmp_path / "glstat.csv").read_text().splitlines()
    assert lines[0] == "time,kinetic,internal,total"
    assert len(lines) == 258
    back = np.loadtxt(tmp_path / "glstat.csv", delimiter=",", skiprows=1)
    assert back.shape == data.shape
    np.testing.assert_allclose(back, data, rtol=1e-10, atol=0.0)


def test_partial_flush_is_readable(tmp_path):
    h = HistoryWriter(tmp_path, "nodout", ["time", "x"], flush_rows=10, flush_interval_s=1e9)
    for i in range(25):
        h.append([i * 0.1, i])
    back = np.loadtxt(tmp_path / "nodout.csv", delimiter=",", skiprows=1)
    assert back.shape == (20, 2)
    h.close()
    h.close()
    assert np.loadtxt(tmp_path / "nodout.csv", delimiter=",", skiprows=1).shape == (25, 2)


def test_hdf5_mirror(tmp_path):
    data = rows(300)
    with h5py.File(tmp_path / "results.h5", "w") as f:
        with HistoryWriter(tmp_path, "glstat", COLUMNS, h5=f, flush_rows=64) as h:
            for r in data:
                h.append(r)
        with HistoryWriter(tmp_path, "matsum", ["time", "ke_part1"], h5=f) as h:
            h.append([0.0, 1.0])
    with h5py.File(tmp_path / "results.h5", "r") as f:
        ds = f["histories/glstat"]
        assert list(ds.attrs["columns"]) == COLUMNS
        np.testing.assert_array_equal(ds[:], data)
        assert f["histories/matsum"].shape == (1, 2)


def test_wrong_row_length(tmp_path):
    with HistoryWriter(tmp_path, "glstat", COLUMNS) as h:
        with pytest.raises(ValueError):
            h.append([1.0, 2.0])
