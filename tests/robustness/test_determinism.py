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


@pytest.mark.cold_cache
@pytest.mark.parametrize("viscosity", ["fixed", "switch"])
def test_a_run_that_compiles_its_kernels_equals_one_that_loads_them(tmp_path, viscosity):
    """The first run after a kernel change compiles the kernels and writes numba's cache, later runs
    load it: both must give the same bits (FMA contraction, then reassociation outside the neighbour
    sums differed between the two: see sphfem_cli/sph/rates.py, _FM). Two fresh interpreters on one empty cache folder; the SPH
    kernels are the ones with fast-math flags. ``switch``: the same deck with the viscosity's shock switch, the
    rates' other specialisation (sph/switch.py)."""
    import os
    import subprocess
    import sys

    text = decks.DECKS["sph"]
    if viscosity == "switch":
        text = text.replace("artificial_viscosity: {alpha: 0.1}",
                            "artificial_viscosity: {alpha: 0.1, beta: 0.2, switch: {alpha_max: 1.0}}")
        assert "switch" in text
    deck = decks.write(tmp_path, "sph", text)
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


_FIRST_CALLER = r"""
import numpy as np
from sphfem_cli.sph import SphOptions, SphSystem, WallParticles, lattice, scenes, walls
x = lattice.box([0.0, 0.0], [0.2, 0.2], 0.02)
rho = np.full(len(x), 1000.0)
ps = SphSystem(x, np.zeros_like(x), rho * 0.02**2, rho, np.zeros(len(x), dtype=int), scenes.water(20.0),
               SphOptions(gravity=[0.0, -9.81]), wall_particles=WallParticles(lattice.box([-0.06, -0.06], [0.26, 0.0], 0.02), 0.02))
pts = ps._build_points(ps._update_state())
walls.wall_pressure(pts["sx"], pts["sd"], pts["cell_start"], pts["sreach"], ps.settings_f, ps.settings_i, ps.grid_f, ps.grid_i, ps.params)
"""

_SHARED_CALLEES = r"""
import json
import numpy as np
from sphfem_cli.materials import kernels as mk, slots as ms
from sphfem_cli.sph import eos, kernel_functions as kf, scenes, search
row = scenes.water(20.0)[1][0]
q, kind = row[mk.EOS_OFFSET:], int(row[mk.P_EOS_TYPE])
out = [eos.density_from_pressure(kind, q, row[ms.P_RHO0], p, q[ms.Q_E0], row[ms.P_RHO0]) for p in np.linspace(0.0, 2e4, 200)]
out += [eos.sound_speed(kind, q, r, q[ms.Q_E0]) for r in np.linspace(0.99, 1.01, 50)]
for kernel in (kf.CUBIC_SPLINE, kf.WENDLAND_C2):
    out += [kf.kernel_sigma(kernel, 2)] + [v for t in np.linspace(0.01, 2.1, 50) for v in kf.kernel_shape(kernel, t)]
out += [float(c) for v in np.linspace(-1.0, 1.0, 20) for c in search.cell_range(v, 0.3, -1.0, 7.0, 12)]
print(json.dumps([float(v).hex() for v in out]))
"""


@pytest.mark.cold_cache
def test_a_shared_kernel_compiles_the_same_whoever_calls_it_first(tmp_path):
    """numba compiles a callee that states no fastmath with the flags of the caller that first needs
    it and caches that version; the functions the fast-math SPH kernels call state fastmath=False
    (sphfem_cli/sph/rates.py, _FM), so the ones the fast-math wall_pressure compiled and cached
    compute what they compute compiled on their own (density_from_pressure did not, by 1 ulp)."""
    import json
    import os
    import subprocess
    import sys

    def run(code, cache):
        env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / cache))
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=900)
        assert out.returncode == 0, out.stderr[-2000:]
        return out.stdout.strip().splitlines()[-1] if out.stdout.strip() else ""

    run(_FIRST_CALLER, "after_wall_pressure")
    loaded = json.loads(run(_SHARED_CALLEES, "after_wall_pressure"))
    alone = json.loads(run(_SHARED_CALLEES, "alone"))
    assert len(loaded) == len(alone) > 400
    assert loaded == alone, f"{sum(a != b for a, b in zip(loaded, alone))} values differ"
