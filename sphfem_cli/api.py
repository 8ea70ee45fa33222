"""sphfem from Python: load a deck (a file or a dict) with overrides, run it into a folder, read its
histories as numpy arrays. The ``sphfem`` command is built on the same driver (``driver``).

    from sphfem_cli import api

    result = api.run("decks/cantilever_2d.yaml", "runs/stiff", overrides={"control.end_time": 0.01})
    result.status                                  # "completed", "stopped by a guard", ...
    t, uy = result.series("tip", "displacement_y")  # one history column against time

Overrides map dotted key paths of the deck to values and are set before validation, so each is
checked as if it had been written in the file: ``control.end_time``, ``materials.steel.youngs_modulus``,
``parts.beam.geometry.box.divisions``, ``boundaries.0.directions`` (list items by index). A bad deck or
override raises DeckProblem (``message``: one line, file:line:col; ``exit_code`` 65); an output folder
holding another run raises OutputProblem unless ``overwrite=True``. A run that a guard stops is not an
exception: its ``status`` and ``message`` say why (and ``diagnostics.txt`` in its folder).
"""
from __future__ import annotations

import copy
import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from .driver import (DeckProblem, Loaded, OutputProblem, RunOutcome, announce_compiling, build_loaded, default_threads,
                     execute, prepare_folder)

__all__ = ["DeckProblem", "Loaded", "OutputProblem", "RunResult", "load", "read_histories", "run"]


def _set(data: Any, path: str, value: Any, where: str) -> None:
    """Set ``data[path]`` (dotted; integers index lists), making missing mappings on the way."""
    keys = path.split(".")
    node = data
    for i, key in enumerate(keys):
        last = i == len(keys) - 1
        if isinstance(node, list):
            if not key.isdigit() or int(key) >= len(node):
                raise DeckProblem(f"{where}: override '{path}': '{key}' is not an index of the list at "
                                  f"'{'.'.join(keys[:i]) or 'the deck'}' ({len(node)} items)")
            key = int(key)
        elif not isinstance(node, dict):
            raise DeckProblem(f"{where}: override '{path}': '{'.'.join(keys[:i])}' is a value, not a mapping")
        if last:
            node[key] = copy.deepcopy(value)
        else:
            if isinstance(node, dict) and key not in node:
                node[key] = {}
            node = node[key]


def load(deck: str | Path | Mapping, overrides: Mapping[str, Any] | None = None,
         base_dir: str | Path | None = None) -> Loaded:
    """Read (a path) or take (a dict, as YAML would load it) a deck, apply ``overrides``, validate and build.

    Files a deck names (meshes, reference curves) are read relative to the deck file's folder, or to
    ``base_dir`` (default: the current folder) for a dict."""
    from .deck import loader
    from .deck.errors import DeckError

    try:
        if isinstance(deck, Mapping):
            import yaml

            path = Path(base_dir or Path.cwd()) / "deck-from-python.yaml"
            data, positions = loader.loads(yaml.safe_dump(dict(deck), sort_keys=False), file=str(path))
        else:
            path = Path(deck)
            data, positions = loader.load(path)
    except DeckError as err:
        raise DeckProblem(str(err)) from None
    for key, value in (overrides or {}).items():
        _set(data, key, value, str(path))
    return build_loaded(data, positions, path)


def read_histories(folder: str | Path) -> dict[str, dict[str, np.ndarray]]:
    """Every history table of a run folder: ``{table: {column: values}}`` (``time`` among the columns)."""
    from .study.metrics import read_history

    out = {}
    for csv in sorted((Path(folder) / "histories").glob("*.csv")):
        columns, rows = read_history(csv)
        out[csv.stem] = {c: rows[:, i].copy() for i, c in enumerate(columns)}
    return out


@dataclass(frozen=True)
class RunResult(RunOutcome):
    """A finished run: how it ended (``RunOutcome``: ``code``, ``status``, ``message``, ``time``, ``steps``,
    ``wall``) and where its files are (``folder``: results.xdmf, results.h5, histories/, run.log)."""

    folder: Path

    @property
    def completed(self) -> bool:
        return self.status == "completed"

    def histories(self) -> dict[str, dict[str, np.ndarray]]:
        return read_histories(self.folder)

    def series(self, table: str, column: str) -> tuple[np.ndarray, np.ndarray]:
        """(time, values) of one history column; KeyError naming the known ones otherwise."""
        tables = self.histories()
        if table not in tables:
            raise KeyError(f"no history table '{table}' in {self.folder}; tables: {', '.join(tables)}")
        if column not in tables[table]:
            raise KeyError(f"table '{table}' has no column '{column}'; columns: {', '.join(tables[table])}")
        return tables[table]["time"], tables[table][column]


def run(deck: str | Path | Mapping | Loaded, output: str | Path, overrides: Mapping[str, Any] | None = None,
        overwrite: bool = False, threads: int | None = None, quiet: bool = True,
        base_dir: str | Path | None = None) -> RunResult:
    """Run a deck (path, dict or ``load``'s result) into the folder ``output`` and return its RunResult.

    ``threads`` defaults to the CLI's choice (one per 20 000 elements and particles); the caller's
    numba thread count is restored afterwards."""
    import numba

    announced = not isinstance(deck, Loaded) and announce_compiling(quiet)
    loaded = deck if isinstance(deck, Loaded) else load(deck, overrides, base_dir)
    if isinstance(deck, Loaded) and overrides:
        raise ValueError("overrides apply when the deck is loaded: pass them to load(), or pass the deck itself")
    out = prepare_folder(Path(output), None, overwrite)
    before = numba.get_num_threads()
    numba.set_num_threads(min(threads or default_threads(loaded.model), numba.config.NUMBA_NUM_THREADS))
    try:
        outcome: RunOutcome = execute(loaded, out, quiet=quiet, announced=announced)
    finally:
        numba.set_num_threads(before)
    return RunResult(**dataclasses.asdict(outcome), folder=out)
