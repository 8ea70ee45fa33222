"""ALE 2D step, pass by pass: ns per cell-step of every pass of the Eulerian quad4 step (issue 17).

    NUMBA_NUM_THREADS=1 python benchmarks/ale_passes.py [--n 240] [--steps 10] [--repeat 3] [--two]

Case: ``ale_throughput.build(n, two)``, the n x n box of ``peers.py``'s ``ale2d`` case (one
ideal gas with a pressure bump; ``--two`` adds the water/air case of ``ale_throughput``, two
materials with mixed cells along a wavy interface), slip walls, van Leer remap, SLIC, every step
remapped back to the Eulerian mesh. Each case is built, advanced two steps (compilation), then
timed over ``steps`` steps of ``ale.step(ale.stable_dt(0.5))``; the cases are interleaved
``repeat`` times and min and median over the repetitions are printed. Each pass is timed by
wrapping the kernel that the orchestration (``ale/system.py``) calls, with the process CPU time
(``time.process_time``) around each call:

* Lagrange phase: ``forces`` (``lagrange_forces``: EOS per material, mixture pressure, bulk and
  hourglass viscosity, element forces, element stable step), ``nodal update`` (``nodal_update``:
  force gather, v^{n+1/2}, velocity conditions), ``energy`` (``lagrange_energy``: compatible
  work, Lagrangian volume, mixed-cell closure), ``ext forces`` (``AleSystem._external_forces``);
* remap: ``mesh target`` (``MeshMover.target``), ``face fluxes`` (``face_fluxes``: swept volumes,
  SLIC material volumes, van Leer mass and energy; the interface reconstruction of the method
  is this pass's SLIC branch), ``apply faces`` (``apply_face_fluxes``), ``dual fluxes`` and
  ``apply dual`` (nodal momentum on the dual mesh; ``dual fluxes`` includes ``node_velocities`` where
  the code has it), ``finish nodes`` (``finish_remap_nodes``:
  v = p / m, bounds, conditions), ``nodal mass``, ``finish elems`` (DeBar's kinetic-energy fix);
* ``time step``: ``AleSystem.stable_dt`` minus the forces it triggers (the min over dt_elem);
* ``rest``: the step's CPU time minus the passes above (Python orchestration, temporaries).

The load average (``os.getloadavg``) is printed before and after.

Before / after: ``--trees A B`` (source trees, e.g. a ``git worktree`` of the base commit and this
one) runs every repetition once per tree, alternating A, B, A, B ..., each in a child process with
``PYTHONPATH`` set to the tree (this script's own file drives both), and prints each tree's table
and min / median over the repetitions of the per-repetition ratio of total CPU time A / B (the
speed-up of B).

Measured: see the end of this docstring (figures appended per measurement, with the code state).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))

PASSES = ("forces", "nodal update", "energy", "ext forces", "mesh target", "face fluxes", "apply faces",
          "dual fluxes", "apply dual", "finish nodes", "nodal mass", "finish elems", "time step")

# kernels looked up on the kernels module at each call by AleSystem (K.name)
_MODULE_KERNELS = {"apply_face_fluxes": "apply faces", "dual_fluxes": "dual fluxes", "node_velocities": "dual fluxes",
                   "apply_dual_fluxes": "apply dual", "nodal_mass": "nodal mass",
                   "finish_remap_elements": "finish elems"}
# kernels bound on the instance at construction (AleSystem._allocate)
_BOUND_KERNELS = {"_k_forces": "forces", "_k_nodal": "nodal update", "_k_energy": "energy",
                  "_k_faces": "face fluxes", "_k_finish": "finish nodes"}


class PassTimer:
    """CPU seconds per pass, accumulated by wrappers around the kernels of one AleSystem."""

    def __init__(self):
        self.t = dict.fromkeys(PASSES, 0.0)

    def wrap(self, name, fn):
        def timed(*args, **kwargs):
            c0 = time.process_time()
            out = fn(*args, **kwargs)
            self.t[name] += time.process_time() - c0
            return out
        return timed


def instrument(ale, timer: PassTimer):
    """Wrap ale's kernels (instance attributes and the kernels module) with timer; returns an undo."""
    from sphfem_cli.ale import system as S

    for attr, name in _BOUND_KERNELS.items():
        setattr(ale, attr, timer.wrap(name, getattr(ale, attr)))
    ale._external_forces = timer.wrap("ext forces", ale._external_forces)
    ale.mesh.target = timer.wrap("mesh target", ale.mesh.target)
    saved = {k: getattr(S.K, k) for k in _MODULE_KERNELS if hasattr(S.K, k)}  # an older code may lack one
    for k, fn in saved.items():
        setattr(S.K, k, timer.wrap(_MODULE_KERNELS[k], fn))
    stable = ale.stable_dt

    def timed_dt(scale=0.5):
        forces0 = timer.t["forces"]
        c0 = time.process_time()
        out = stable(scale)
        timer.t["time step"] += time.process_time() - c0 - (timer.t["forces"] - forces0)
        return out
    ale.stable_dt = timed_dt

    def undo():
        for k, fn in saved.items():
            setattr(S.K, k, fn)
    return undo


def measure(n: int, steps: int, two: bool) -> dict:
    """ns per cell-step of each pass, 'rest' and 'total', over ``steps`` steps after two warm-up steps."""
    from ale_throughput import build

    ale = build(n, two)
    for _ in range(2):
        ale.step(ale.stable_dt(0.5))
    timer = PassTimer()
    undo = instrument(ale, timer)
    try:
        c0 = time.process_time()
        for _ in range(steps):
            ale.step(ale.stable_dt(0.5))
        total = time.process_time() - c0
    finally:
        undo()
    cells = len(ale.conn) * steps
    out = {k: 1e9 * v / cells for k, v in timer.t.items()}
    out["rest"] = 1e9 * (total - sum(timer.t.values())) / cells
    out["total"] = 1e9 * total / cells
    return out


def print_table(title: str, cases, runs: dict) -> None:
    print(title)
    print(f"{'pass':14s}" + "".join(f"{name + ' min / median':>24s}" for name in cases))
    for k in PASSES + ("rest", "total"):
        row = f"{k:14s}"
        for name in cases:
            vals = [r[k] for r in runs[name]]
            row += f"{min(vals):12.1f} / {statistics.median(vals):8.1f}"
        print(row)
    for name in cases:
        tot = [r["total"] for r in runs[name]]
        print(f"{name}: {1e3 / statistics.median(tot):.3f} M cell-steps/s (median), {1e3 / min(tot):.3f} (best)")


def compare(trees, args, cases) -> None:
    """Interleaved repetitions of every tree in child processes; per-repetition total ratios."""
    runs = {t: {name: [] for name in cases} for t in trees}
    for _ in range(args.repeat):
        for t in trees:
            env = dict(os.environ, PYTHONPATH=t, NUMBA_NUM_THREADS="1")
            cmd = [sys.executable, str(Path(__file__).resolve()), "--n", str(args.n), "--steps", str(args.steps),
                   "--repeat", "1", "--json"] + (["--two"] if args.two else [])
            out = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
            for name, r in json.loads(out.strip().splitlines()[-1]).items():
                runs[t][name].append(r)
    for t in trees:
        print_table(f"tree {t}", cases, runs[t])
    a, b = trees[0], trees[-1]
    for name in cases:
        ratio = [x["total"] / y["total"] for x, y in zip(runs[a][name], runs[b][name])]
        print(f"{name}: speed-up of {b} over {a}: min {min(ratio):.3f}, median {statistics.median(ratio):.3f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=240, help="cells per side (default 240)")
    ap.add_argument("--steps", type=int, default=10, help="timed steps per repetition (default 10)")
    ap.add_argument("--repeat", type=int, default=3, help="interleaved repetitions (default 3)")
    ap.add_argument("--two", action="store_true", help="also the two-material water/air case")
    ap.add_argument("--trees", nargs="+", help="source trees to compare, interleaved (child processes)")
    ap.add_argument("--json", action="store_true", help=argparse.SUPPRESS)  # a child's one line of results
    args = ap.parse_args()
    cases = [("one", False)] + ([("two", True)] if args.two else [])
    names = [name for name, _ in cases]
    if args.trees:
        print(f"ALE 2D passes, {args.n} x {args.n} cells, {args.steps} steps, 1 thread, load {os.getloadavg()[0]:.2f}")
        compare(args.trees, args, names)
        print(f"load after {os.getloadavg()[0]:.2f}")
        return
    import numba

    runs = {name: [] for name in names}
    for _ in range(args.repeat):
        for name, two in cases:
            runs[name].append(measure(args.n, args.steps, two))
    if args.json:
        print(json.dumps({name: r[0] for name, r in runs.items()}))
        return
    print_table(f"ALE 2D passes, {args.n} x {args.n} cells, {args.steps} steps, numba threads "
                f"{numba.get_num_threads()}, load {os.getloadavg()[0]:.2f}", names, runs)
    print(f"load after {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
