"""Time-history tables (energy like glstat, part sums like matsum, points like nodout).

One :class:`HistoryWriter` per table: fixed column names, one row of floats per :meth:`append`.

- CSV: ``<directory>/<name>.csv``, a header line of comma-separated column names, then one row per
  line with numbers as ``%.10e``. Read back with ``numpy.loadtxt(path, delimiter=",", skiprows=1)``.
- HDF5 mirror (optional): ``/histories/<name>`` in the given h5py file or group, a ``(rows, columns)``
  float64 dataset resizable along rows, with the column names in its ``columns`` attribute.

Rows are buffered and written out every ``flush_rows`` rows or ``flush_interval_s`` seconds of wall
time, whichever comes first, and on :meth:`flush` / :meth:`close`. The CSV is UTF-8 and is written in
whole rows: a write that fails (a full disk) is cut back to the last complete row and raises
OSError, after which the writer writes nothing more, so the file stays a readable table.
"""
from __future__ import annotations

import time
from pathlib import Path
from typing import Sequence

import h5py
import numpy as np

from .xdmf import reserve_space, trim_space

__all__ = ["HistoryWriter"]


class HistoryWriter:
    """Append-only table written to ``<directory>/<name>.csv`` and optionally to ``h5[/histories/<name>]``."""

    def __init__(
        self,
        directory: Path | str,
        name: str,
        columns: Sequence[str],
        h5: h5py.Group | None = None,
        flush_rows: int = 100,
        flush_interval_s: float = 5.0,
        resume_rows: int | None = None,
    ):
        """``resume_rows``: continue an existing table after its first ``resume_rows`` rows (rows
        beyond them, written after a checkpoint, are dropped from the CSV and the HDF5 mirror)."""
        self.columns = [str(c) for c in columns]
        if not self.columns:
            raise ValueError("a history needs at least one column")
        for c in self.columns:
            if not c or "," in c or "\n" in c:
                raise ValueError(f"bad column name {c!r}")
        if not name or "/" in name:
            raise ValueError(f"bad history name {name!r}")
        self.name = name
        directory = Path(directory)
        directory.mkdir(parents=True, exist_ok=True)
        self.path = directory / f"{name}.csv"
        self.flush_rows = int(flush_rows)
        self.flush_interval_s = float(flush_interval_s)
        self._dataset = None
        if resume_rows is not None:
            self._reopen(h5, int(resume_rows))
        else:
            self._csv = open(self.path, "wb", buffering=0)
            self._failed = False
            self._write((",".join(self.columns) + "\n").encode("utf-8"))
        if h5 is not None and resume_rows is None:
            reserve_space(h5.file, 256 * len(self.columns) * 8)
            group = h5.require_group("histories")
            if name in group:
                del group[name]
            self._dataset = group.create_dataset(
                name,
                shape=(0, len(self.columns)),
                maxshape=(None, len(self.columns)),
                dtype="f8",
                chunks=(256, len(self.columns)),
            )
            self._dataset.attrs["columns"] = self.columns
        self._failed = False
        self._pending: list[np.ndarray] = []
        self._n_rows = 0 if resume_rows is None else int(resume_rows)
        self._last_flush = time.monotonic()
        self._closed = False

    def _reopen(self, h5, rows: int) -> None:
        """Keep the header and the first `rows` rows of the CSV and of the HDF5 mirror; append after them."""
        with open(self.path, "rb") as fh:
            raw = fh.read()
        header = (",".join(self.columns) + "\n").encode("utf-8")
        offset, found = len(header), 0
        while raw.startswith(header) and found < rows:
            end = raw.find(b"\n", offset)
            if end < 0:
                break
            offset, found = end + 1, found + 1
        if not raw.startswith(header) or found < rows:
            raise ValueError(f"{self.path}: does not hold the {rows} rows of {header.decode().strip()!r} the "
                             "checkpoint expects")
        self._csv = open(self.path, "r+b", buffering=0)  # cut after the kept rows: needs no disk space
        self._csv.truncate(offset)
        self._csv.seek(offset)
        if h5 is not None:
            self._dataset = h5.require_group("histories")[self.name]
            if self._dataset.shape[0] < rows:
                raise ValueError(f"{self.name}: {self._dataset.shape[0]} rows in the HDF5 mirror, expected {rows}")
            reserve_space(h5.file, 0)
            self._dataset.resize((rows, len(self.columns)))

    @property
    def n_rows(self) -> int:
        """Rows appended so far (flushed or not)."""
        return self._n_rows + len(self._pending)

    def note(self, key: str, text: str) -> None:
        """A text attribute `key` on the HDF5 mirror (what the CSV's one header line cannot carry); none without it."""
        dataset = getattr(self, "_dataset", None)
        if dataset is not None:
            dataset.attrs[key] = text

    def append(self, row: Sequence[float]) -> None:
        """Add one row; its length must equal the number of columns."""
        if self._closed:
            raise RuntimeError(f"history {self.name!r} is closed")
        values = np.asarray(row, dtype=np.float64).reshape(-1)
        if values.size != len(self.columns):
            raise ValueError(f"history {self.name!r}: {values.size} values for {len(self.columns)} columns")
        self._pending.append(values)
        if len(self._pending) >= self.flush_rows or time.monotonic() - self._last_flush >= self.flush_interval_s:
            self.flush()

    def flush(self) -> None:
        """Write buffered rows to the CSV and the HDF5 mirror and flush both files."""
        if self._closed or self._failed:
            return
        try:
            if self._pending:
                block = np.vstack(self._pending)
                if self._dataset is not None:  # before the CSV, so that both get the rows or neither
                    reserve_space(self._dataset.file, 2 * (block.nbytes + 256 * block.shape[1] * 8))
                self._write("".join(",".join(f"{v:.10e}" for v in r) + "\n" for r in block).encode("utf-8"))
                if self._dataset is not None:
                    start = self._dataset.shape[0]
                    self._dataset.resize((start + block.shape[0], block.shape[1]))
                    self._dataset[start:] = block
                self._n_rows += block.shape[0]
                self._pending.clear()
            if self._dataset is not None:
                self._dataset.file.flush()
                trim_space(self._dataset.file)
        except OSError:
            self._failed = True
            raise
        self._last_flush = time.monotonic()

    def _write(self, data: bytes) -> None:
        """Append `data` (whole rows) to the unbuffered CSV; on failure cut the file back to where it was."""
        start = self._csv.tell()
        view = memoryview(data)
        try:
            while view:
                view = view[self._csv.write(view):]
        except OSError:
            self._failed = True
            try:
                self._csv.truncate(start)
            except OSError:
                pass
            raise

    def close(self) -> None:
        """Flush and close the CSV; the HDF5 file belongs to the caller and stays open. Idempotent."""
        if self._closed:
            return
        try:
            self.flush()
        finally:
            self._closed = True
            self._csv.close()

    def __enter__(self) -> HistoryWriter:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
