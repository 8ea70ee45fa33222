"""Determinism: the same deck gives bit-identical histories run after run and on 1 or 2 threads
(solid, SPH and ALE decks). Parallel loops gather (each element or particle writes only its own
entries) and every reduction runs in a fixed order, so no tolerance is needed."""
from __future__ import annotations

from pathlib import Path

import h5py
import numba
import numpy as np
import pytest
from click.testing import CliRunner

from sphfem_cli.cli import main

from . import decks


def _histories(deck, out, threads: int) -> dict[str, np.ndarray]:
    result = CliRunner().invoke(main, ["run", "-q", str(deck), "-o", str(out), "--threads", str(threads)])
    assert result.exit_code == 0, result.output
    assert f"threads: {threads}" in (out / "run.log").read_text()
    with h5py.File(out / "results.h5", "r") as f:
        group = f["histories"]
        tables = {name: group[name][()] for name in group}
        steps = sorted(k for k in f[next(n for n in f if n not in ("times", "histories"))] if k.startswith("step_"))
        last = f[next(n for n in f if n not in ("times", "histories"))][steps[-1]]
        tables["last coordinates"] = last["coordinates"][()]
    return tables


@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs 2 numba threads")
@pytest.mark.parametrize("kind", ["solid", "sph", "ale", "fsi_sph"])
def test_identical_run_after_run_and_on_1_or_2_threads(tmp_path, kind):
    """fsi_sph: SPH water against an elastic block through a nodes_to_surface contact."""
    text = (Path(__file__).parents[1] / "data" / "fuzz" / f"{kind}.yaml").read_text() if kind == "fsi_sph" else None
    deck = decks.write(tmp_path, kind, text)
    first = _histories(deck, tmp_path / "a", 1)
    again = _histories(deck, tmp_path / "b", 1)
    two = _histories(deck, tmp_path / "c", 2)
    for name, table in first.items():
        assert np.array_equal(table, again[name]), f"{kind} {name}: differs between two runs"
        assert np.array_equal(table, two[name]), f"{kind} {name}: differs between 1 and 2 threads"
    numba.set_num_threads(1)


def test_a_run_that_compiles_its_kernels_equals_one_that_loads_them(tmp_path):
    """The first run after a kernel change compiles the kernels and writes numba's cache, later runs
    load it: both must give the same bits (FMA contraction, then reassociation outside the neighbour
    sums differed between the two: see sphfem_cli/sph/rates.py, _FM). Two fresh interpreters on one empty cache folder; the SPH
    kernels are the ones with fast-math flags."""
    import os
    import subprocess
    import sys

    deck = decks.write(tmp_path, "sph")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "numba_cache"))
    runs = []
    for name in ("compiles", "loads"):
        out = tmp_path / name
        code = subprocess.run([sys.executable, "-c", "import sys; from sphfem_cli.cli import main; sys.argv[0] = 'sphfem'; main()",
                               "run", "-q", str(deck), "-o", str(out), "--threads", "1"], env=env, timeout=900).returncode
        assert code == 0, (out / "run.log").read_text()
        with h5py.File(out / "results.h5", "r") as f:
            group = f["histories"]
            runs.append({name: group[name][()] for name in group})
    assert any((tmp_path / "numba_cache").rglob("*.nbi")), "the first run wrote no cache"
    for name, table in runs[0].items():
        assert np.array_equal(table, runs[1][name]), f"{name}: a compiling run and a cache-loading run differ"
