"""sphfem against named peers, side by side (issue 17): one thread, interleaved pairs, CPU time.

    python benchmarks/peers.py [--cases ale2d,ale2dflow,ale2dtwo,hex8,sph2d,dambreak] [--pairs 3] [--size 1.0]

Cases (the ratio is sphfem's rate over the peer's, per cell-step / element-step / particle-step):

* ``ale2d``: sphfem's one-material ideal-gas ALE box (``ale_throughput.build``, n x n quad4,
  van Leer remap) against CloverLeaf_Serial (UK-MAC, its ``clover.in`` problem at n x n cells).
  Issue size n = 960; ``--size`` scales n (and the hex8 / SPH sizes) down for a shared machine.
* ``ale2dflow``: the same box flowing (``build(n, False, vortex=True)``, a Taylor-Green vortex: every
  face and node of the remap moves from the first step, as every cell of CloverLeaf computes) against
  the same CloverLeaf_Serial run. The ``ale2d`` box is at rest but for its bump's wave, which the
  remap's skips of zero fluxes make cheap; ``ale2dflow`` is the cost of a flow that fills the mesh.
* ``ale2dtwo``: the two-material box of the same size at rest (``build(n, True)``: water below a wavy line,
  air above, SLIC; most cells pure, mixed ones along the line) against the same one-material CloverLeaf_Serial
  run: issue 17's goal for two materials, 0.6 of CloverLeaf's one-material rate.
* ``hex8``: sphfem's elastic hex8 cube (``fem_throughput.CUBE_DECK``, n^3 elements) against
  LULESH 2.0 serial (``-s n -i steps``), n = 30 at size 1.
* ``sph2d``: sphfem's 2D dam break at about 90 000 particles (a/dx = 212) against the fused-step
  probe ``roofline_sph.py`` (``$SPHFEM_SHARED`` or ``../shared/bench``) on a lattice of the same count.
* ``dambreak``: sphfem's 2D dam break per fluid particle-step against PySPH's ``dam_break_2d``
  (``--no-openmp``), run from a PySPH venv at ``$SPHFEM_PEERS/pysph-venv``.

Timing. In-process cases (sphfem, the probe): ``time.process_time`` around the time loop, after
warm-up steps. External peers: the child's CPU time from ``os.wait4`` (user + system) of a run of
``steps`` steps minus that of a run of one step, i.e. the CPU time of ``steps - 1`` steps with the
peer's set-up (mesh generation, input parsing, start-up) subtracted. Each pair runs sphfem, then the
peer; the table gives min and median over the pairs of sphfem rate / peer rate, and the load
average before and after. Peers live in ``$SPHFEM_PEERS`` (default ``~/.cache/sphfem-peers``); a
missing peer prints "peer not built: ..." and the case still prints sphfem's figure.
How to build each peer: benchmarks/README.md.

Measured (3 December 2026, one thread, 3 pairs, CPU time, 2-core machine shared by 5 helpers, load
5.9-7.4): ale2d 240^2 (--size 0.25) 1.27 M vs CloverLeaf 5.75 M cell-steps/s, ratio 0.22 (min 0.22);
hex8 30^3 0.371 M vs LULESH 0.862 M, ratio 0.42 (min 0.42); sph2d 89 888 particles 1.00 M vs probe
2.30 M, ratio 0.44 (min 0.42); dambreak 0.900 M, PySPH not installed then (details: README.md).
hex8 after the hexspeed branch (10:14 UTC, load 0.5-0.6, 3 pairs, --steps-scale 0.25): 1.140 M vs
LULESH 1.030 M, ratio 1.28 (min 1.11).
"""
from __future__ import annotations

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

HERE = Path(__file__).resolve().parent
PEERS = Path(os.environ.get("SPHFEM_PEERS", Path.home() / ".cache" / "sphfem-peers"))
SHARED = Path(os.environ.get("SPHFEM_SHARED", HERE.parent.parent / "shared"))
if str(HERE) not in sys.path:  # the sibling benchmarks (ale_throughput, fem_throughput) build our cases
    sys.path.insert(0, str(HERE))


class PeerMissing(Exception):
    """The peer is not built or installed; the message says how to build it."""


@dataclass
class Case:
    name: str
    unit: str
    size: str
    ours: Callable[[], float]   # returns sphfem's rate (work units per CPU second)
    peer: Callable[[], float]   # returns the peer's rate, or raises PeerMissing
    peer_name: str


def child_cpu(cmd: list[str], cwd: Path, env: dict | None = None) -> tuple[float, str]:
    """(user + system CPU seconds of the child, its stdout+stderr) via os.wait4."""
    with tempfile.TemporaryFile() as out:
        proc = subprocess.Popen(cmd, cwd=cwd, stdout=out, stderr=subprocess.STDOUT, env=env)
        _, status, ru = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        text = out.read().decode(errors="replace")
    if proc.returncode != 0:
        raise RuntimeError(f"{cmd[0]} exited {proc.returncode}: {text[-400:]}")
    return ru.ru_utime + ru.ru_stime, text


def loop_cpu(run_steps: Callable[[int], float], steps: int) -> float:
    """CPU seconds of steps - 1 steps: a run of ``steps`` minus a run of one step (set-up removed)."""
    return run_steps(steps) - run_steps(1)


def one_thread_env() -> dict:
    env = dict(os.environ)
    env.update(OMP_NUM_THREADS="1", NUMBA_NUM_THREADS="1")
    return env


# --- ALE 2D ---------------------------------------------------------------------------------

CLOVER_IN = """*clover
 state 1 density=0.2 energy=1.0
 state 2 density=1.0 energy=2.5 geometry=rectangle xmin=0.0 xmax=5.0 ymin=0.0 ymax=2.0
 x_cells={n}
 y_cells={n}
 xmin=0.0
 ymin=0.0
 xmax=10.0
 ymax=10.0
 initial_timestep=0.04
 timestep_rise=1.5
 max_timestep=0.04
 end_step={steps}
*endclover
"""


def ale2d_case(n: int, steps: int, vortex: bool = False, two: bool = False) -> Case:
    def ours() -> float:
        from ale_throughput import build

        ale = build(n, two, vortex)
        for _ in range(2):
            ale.step(ale.stable_dt(0.5))
        c0 = time.process_time()
        for _ in range(steps):
            ale.step(ale.stable_dt(0.5))
        return n * n * steps / (time.process_time() - c0)

    def peer() -> float:
        exe = PEERS / "CloverLeaf_Serial" / "clover_leaf"
        if not exe.exists():
            raise PeerMissing(f"{exe} missing; build CloverLeaf_Serial with gfortran (README)")

        def run(k: int) -> float:
            with tempfile.TemporaryDirectory() as tmp:
                Path(tmp, "clover.in").write_text(CLOVER_IN.format(n=n, steps=k))
                return child_cpu([str(exe)], Path(tmp), one_thread_env())[0]
        return n * n * (steps - 1) / loop_cpu(run, steps)

    return Case("ale2dtwo" if two else "ale2dflow" if vortex else "ale2d", "cell-steps/s", f"{n}^2 cells, {steps} steps", ours, peer,
                "CloverLeaf_Serial")


# --- hex8 FEM ---------------------------------------------------------------------------------

def hex8_case(n: int, steps: int) -> Case:
    def ours() -> float:
        from fem_throughput import CUBE_DECK

        from sphfem_cli.driver import load_model
        from sphfem_cli.solver.explicit import Simulation

        with tempfile.TemporaryDirectory() as tmp:
            deck = Path(tmp) / "cube.yaml"
            deck.write_text(CUBE_DECK.format(n=n))
            model = load_model(str(deck)).model
        sim = Simulation(model)
        for _ in range(5):
            sim.step()
        c0 = time.process_time()
        for _ in range(steps):
            sim.step()
        return model.n_elements * steps / (time.process_time() - c0)

    def peer() -> float:
        exe = PEERS / "lulesh2.0"
        if not exe.exists():
            raise PeerMissing(f"{exe} missing; build LULESH 2.0 serial with g++ -O3 (README)")

        def run(k: int) -> float:
            return child_cpu([str(exe), "-s", str(n), "-i", str(k)], PEERS, one_thread_env())[0]
        return n ** 3 * (steps - 1) / loop_cpu(run, steps)

    return Case("hex8", "element-steps/s", f"{n}^3 hex8, {steps} steps", ours, peer,
                "LULESH 2.0 serial")


# --- SPH 2D against the fused-step probe -----------------------------------------------------

def dam_break(ratio: int):
    from sphfem_cli.sph import scenes

    return scenes.dam_break(a=1.0, dx=1.0 / ratio, dim=2)


def sph_ours(ratio: int, steps: int) -> tuple[Callable[[], float], list]:
    """sphfem's dam-break rate (``ps.n`` counts fluid particles, ghosts apart); ``count`` receives it."""
    count: list = []

    def ours() -> float:
        ps = dam_break(ratio)
        count[:] = [ps.n]
        for _ in range(3):
            ps.advance(0.9)
        c0 = time.process_time()
        for _ in range(steps):
            ps.advance(0.9)
        return ps.n * steps / (time.process_time() - c0)
    return ours, count


def sph2d_case(ratio: int, steps: int) -> Case:
    ours, count = sph_ours(ratio, steps)

    def peer() -> float:
        probe = SHARED / "bench" / "roofline_sph.py"
        if not probe.exists():
            raise PeerMissing(f"{probe} missing; set SPHFEM_SHARED to the folder holding bench/")
        import importlib.util

        import numpy as np

        spec = importlib.util.spec_from_file_location("roofline_sph", probe)
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        from numba.core.caching import NullCache

        for kernel in vars(mod).values():  # compiled in this process (before the clock): a probe kernel loaded
            if hasattr(kernel, "_cache"):  # from numba's cache failed to rebuild (No module named '<dynamic>')
                kernel._cache = NullCache()
        # the probe's own lattice (its main()), with nside chosen so that 2 nside^2 = sphfem's count
        n_target = count[0] if count else 2 * ratio * ratio
        nside = max(int(round((n_target / 2) ** 0.5)), 2)
        dx = 1.0 / nside
        g = (np.arange(nside) + 0.5) * dx
        X, Y = np.meshgrid(g, 2 * g)
        x = X.ravel().copy()
        y = Y.ravel().copy()
        n = x.size
        rng = np.random.default_rng(0)
        x += 0.01 * dx * rng.standard_normal(n)
        y += 0.01 * dx * rng.standard_normal(n)
        u = np.zeros(n); v = np.zeros(n); rho = np.full(n, 1000.0); p = np.zeros(n)
        h = 1.2 * dx; cell = 2 * h; m = 1000.0 * dx * dx; c0 = 50.0
        xmin, ymin = -0.1, -0.1
        nx = int(1.2 / cell) + 1; ny = int(2.4 / cell) + 1
        drho = np.empty(n); ax = np.empty(n); ay = np.empty(n)

        def step():
            start, order = mod.build_cells(x, y, cell, nx, ny, xmin, ymin)
            mod.rates(x, y, u, v, rho, p, c0, m, h, start, order, nx, ny, xmin, ymin, cell, drho, ax, ay)
        step()
        t0 = time.process_time()
        for _ in range(steps):
            step()
        return n * steps / (time.process_time() - t0)

    return Case("sph2d", "particle-steps/s", f"dam break a/dx={ratio}, {steps} steps", ours, peer,
                "roofline_sph.py probe")


# --- SPH dam break against PySPH ---------------------------------------------------------------

PYSPH_RUN = """
import sys
from pysph.examples.dam_break_2d import DamBreak2D
app = DamBreak2D()
app.run(['--no-openmp', '--disable-output', '--max-steps', sys.argv[1], '-d', sys.argv[2], '-q'])
fluid = [pa for pa in app.particles if pa.name == 'fluid'][0]
print('FLUID', fluid.get_number_of_particles())
"""


def dambreak_case(ratio: int, steps: int) -> Case:
    ours, _ = sph_ours(ratio, steps)

    def peer() -> float:
        py = PEERS / "pysph-venv" / "bin" / "python"
        if not py.exists():
            raise PeerMissing(f"{py} missing; make a venv there and pip install pysph (README)")
        fluid: list = []

        def run(k: int) -> float:
            with tempfile.TemporaryDirectory() as tmp:
                cpu, text = child_cpu([str(py), "-c", PYSPH_RUN, str(k), tmp], Path(tmp), one_thread_env())
            fluid[:] = [int(re.search(r"FLUID (\d+)", text).group(1))]
            return cpu
        cpu = loop_cpu(run, steps)
        return fluid[0] * (steps - 1) / cpu

    return Case("dambreak", "fluid particle-steps/s", f"sphfem a/dx={ratio}, {steps} steps; PySPH default dx",
                ours, peer, "PySPH dam_break_2d --no-openmp")


# --- table -----------------------------------------------------------------------------------

@dataclass
class Result:
    case: Case
    ours: list
    peer: list
    missing: str | None


def run_pairs(case: Case, pairs: int) -> Result:
    ours, peer, missing = [], [], None
    for _ in range(pairs):
        ours.append(case.ours())
        if missing is None:
            try:
                peer.append(case.peer())
            except PeerMissing as exc:
                missing = str(exc)
    return Result(case, ours, peer, missing)


def format_table(results: list[Result], load_before, load_after) -> str:
    lines = [f"load average before {load_before[0]:.1f} {load_before[1]:.1f} {load_before[2]:.1f}, "
             f"after {load_after[0]:.1f} {load_after[1]:.1f} {load_after[2]:.1f}",
             "| case | size | sphfem (median) | peer | peer rate (median) | ratio min | ratio median |",
             "|---|---|---|---|---|---|---|"]
    for r in results:
        ours = f"{statistics.median(r.ours) / 1e6:.3f} M {r.case.unit}"
        if r.missing is not None or not r.peer:
            lines.append(f"| {r.case.name} | {r.case.size} | {ours} | {r.case.peer_name} | - | - | - |")
            continue
        ratios = [a / b for a, b in zip(r.ours, r.peer)]
        lines.append(f"| {r.case.name} | {r.case.size} | {ours} | {r.case.peer_name} | "
                     f"{statistics.median(r.peer) / 1e6:.3f} M | {min(ratios):.2f} | {statistics.median(ratios):.2f} |")
    for r in results:
        if r.missing is not None:
            lines.append(f"{r.case.name}: peer not built: {r.missing}")
    return "\n".join(lines)


def make_cases(size: float, steps_scale: float) -> dict[str, Callable[[], Case]]:
    n_ale = max(int(round(960 * size)), 8)
    n_hex = max(int(round(30 * size)), 4)
    ratio = max(int(round(212 * size)), 8)
    s = lambda k: max(int(round(k * steps_scale)), 2)  # noqa: E731
    return {"ale2d": lambda: ale2d_case(n_ale, s(20)),
            "ale2dflow": lambda: ale2d_case(n_ale, s(20), vortex=True),
            "ale2dtwo": lambda: ale2d_case(n_ale, s(20), two=True),
            "hex8": lambda: hex8_case(n_hex, s(200)),
            "sph2d": lambda: sph2d_case(ratio, s(20)),
            "dambreak": lambda: dambreak_case(ratio, s(20))}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default="ale2d,hex8,sph2d,dambreak")
    ap.add_argument("--pairs", type=int, default=3, help="interleaved sphfem/peer pairs per case (>= 3)")
    ap.add_argument("--size", type=float, default=1.0,
                    help="linear scale of the issue's sizes (ALE 960^2, hex8 30^3, SPH a/dx 212)")
    ap.add_argument("--steps-scale", type=float, default=1.0, help="scale of the timed step counts")
    args = ap.parse_args(argv)
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    import numba

    numba.set_num_threads(1)
    cases = make_cases(args.size, args.steps_scale)
    load_before = os.getloadavg()
    results = []
    for name in args.cases.split(","):
        case = cases[name]()
        print(f"{name}: {case.size}, {args.pairs} pairs ...", flush=True)
        results.append(run_pairs(case, args.pairs))
    print(format_table(results, load_before, os.getloadavg()))


if __name__ == "__main__":
    main()
