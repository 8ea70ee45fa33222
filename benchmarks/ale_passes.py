"""ALE step, pass by pass: ns per cell-step of every pass of the Eulerian quad4 (or hex8) step (issue 17).

    NUMBA_NUM_THREADS=1 python benchmarks/ale_passes.py [--n 240] [--steps 10] [--repeat 3] [--two] [--advance 2]
                                                        [--vortex] [--dim 3]

``--dim 3``: the n^3 hex8 box of ``ale_throughput.build_3d`` instead (one ideal gas, a spherical pressure bump,
slip walls; with ``--vortex`` the 2D vortex in every z layer, w = 0), the same passes (the hex8 kernels the
orchestration calls under the same names); ``--two`` is ignored. The 3D figures (60^3, main against the
branch ale3dspeed, and the 3D / 2D per-cell ratio of issue 17): benchmarks/README.md, "ALE 3D".

Case: ``ale_throughput.build(n, two)``, the n x n box of ``peers.py``'s ``ale2d`` case (one
ideal gas with a pressure bump; ``--two`` adds the water/air case of ``ale_throughput``, two
materials with mixed cells along a wavy interface), slip walls, van Leer remap, SLIC, every step
remapped back to the Eulerian mesh. Each case is built, advanced two steps (compilation;
``--advance K``: K steps, so that the wave from the bump fills the box: at 2 to 12 steps 3-4 % of the
nodes of the 960^2 box move, and the remap skips what does not; 500 steps at 240^2 set 99.9 % moving),
then timed over ``steps`` steps of ``ale.step(ale.stable_dt(0.5))``; the cases are interleaved
``repeat`` times and min and median over the repetitions are printed. Each pass is timed by
wrapping the kernel that the orchestration (``ale/system.py``) calls, with the process CPU time
(``time.process_time``) around each call:

* Lagrange phase: ``forces`` (``lagrange_forces``: EOS per material, mixture pressure, bulk and
  hourglass viscosity, element forces, element stable step), ``nodal update`` (``nodal_update``:
  force gather, v^{n+1/2}, velocity conditions), ``energy`` (``lagrange_energy``: compatible
  work, Lagrangian volume, mixed-cell closure), ``ext forces`` (``AleSystem._external_forces``);
* remap: ``mesh target`` (``MeshMover.target``), ``face fluxes`` (``face_fluxes``: swept volumes,
  SLIC material volumes, van Leer mass and energy; the interface reconstruction of the method
  is this pass's SLIC branch), ``apply faces`` (``apply_face_fluxes``), ``node velocities`` (p / m of
  each sweep), ``dual fluxes`` and ``apply dual`` (nodal momentum on the dual mesh; the tables below
  before 6 December 2026 evening count ``node velocities`` in ``dual fluxes``), ``finish nodes`` (``finish_remap_nodes``:
  v = p / m, bounds, conditions), ``nodal mass``, ``finish elems`` (DeBar's kinetic-energy fix);
* ``time step``: ``AleSystem.stable_dt`` minus the forces it triggers (the min over dt_elem);
* ``rest``: the step's CPU time minus the passes above (Python orchestration, temporaries).

The load average (``os.getloadavg``) is printed before and after.

Before / after: ``--trees A B`` (source trees, e.g. a ``git worktree`` of the base commit and this
one) runs every repetition once per tree, alternating A, B, A, B ..., each in a child process with
``PYTHONPATH`` set to the tree (this script's own file drives both), and prints each tree's table
and min / median over the repetitions of the per-repetition ratio of total CPU time A / B (the
speed-up of B).

Transparent huge pages: ``--madvise`` runs every repetition twice in child processes of this tree, with numpy's
madvise of its arrays of 4 MB and more to huge pages off (``NUMPY_MADVISE_HUGEPAGE=0``), on (``=1``), and off only
while the case is built (``numpy._core.multiarray._set_madvise_hugepage``; on for the steps), the order reversed
on alternate repetitions, and prints the ratios off / on and set-up-off / on of the total CPU time of the timed
steps (above 1: the loop is slower without huge pages). It says nothing of the set-up (``startup.py``). Since
branch setup19 ``AleSystem`` builds its arrays with the advice off whatever the setting (``sphfem_cli/model/pages.py``):
"on" and "off for the set-up" then differ only in the mesh and fill the case makes before it (run the script on a
tree before that switch to compare the loop with and without huge pages on the system's arrays).

Measured (3 December 2026, 10:06 UTC, 1 thread, the 2-core machine shared with other sessions, load
average 1.9; ``--n 240 --steps 10 --repeat 3 --two --trees BASE THIS``, BASE = 76efb01 (main before
this work), THIS = the commit adding this figure; min / median of 3 interleaved repetitions, ns per
cell-step):

============  ===============  ===============  ===============  ===============
pass          one, before      one, after       two, before      two, after
============  ===============  ===============  ===============  ===============
forces        110.4 / 134.0    104.3 / 134.1    137.4 / 145.5    125.4 / 148.3
nodal update  20.6 / 25.5      20.5 / 26.0      24.8 / 27.6      25.8 / 28.9
energy        35.9 / 46.5      36.0 / 49.7      51.3 / 60.1      44.3 / 60.4
ext forces    3.1 / 3.3        3.2 / 3.4        3.2 / 3.5        3.5 / 3.5
mesh target   3.2 / 3.2        3.2 / 3.7        3.1 / 3.4        3.4 / 3.6
face fluxes   35.1 / 41.2      32.2 / 44.5      48.3 / 53.4      50.5 / 56.0
apply faces   26.6 / 31.1      24.1 / 33.1      39.0 / 45.7      40.4 / 46.9
dual fluxes   74.7 / 88.4      69.7 / 90.2      100.1 / 113.9    97.5 / 105.9
apply dual    59.6 / 72.1      43.2 / 58.0      72.8 / 93.0      56.5 / 67.5
finish nodes  15.8 / 20.1      14.2 / 20.8      29.4 / 32.9      26.2 / 32.8
nodal mass    10.8 / 13.2      9.6 / 13.7       16.6 / 18.3      15.7 / 18.8
finish elems  14.0 / 17.6      11.9 / 18.1      19.3 / 22.1      18.2 / 23.2
time step     2.1 / 2.2        2.1 / 2.4        1.9 / 2.3        2.5 / 2.8
rest          99.8 / 114.8     33.1 / 37.6      110.2 / 115.2    36.6 / 42.7
total         512.1 / 612.8    407.5 / 539.5    657.6 / 740.2    546.5 / 641.4
============  ===============  ===============  ===============  ===============

Speed-up of the total, per repetition: one material min 1.14, median 1.21; two materials min 0.96,
median 1.15. The gain is the ``rest`` (per-step temporaries: x + dt v, the nodal momentum and
kinetic energy of the remap, and numpy's strided ``impulse.sum(axis=0)``, 100-115 -> 33-37 ns) and
``apply dual`` (one flux row per corner, 60-73 -> 43-57). The remaining step is the element
kernels: forces (EOS, viscosity, hourglass, stable step) about 105-135, the dual-mesh momentum
remap about 115-150 for its two sweeps, the element face fluxes and their gather about 60-75.
In the same minutes ``peers.py --cases ale2d --size 0.25 --steps-scale 0.5 --pairs 3`` gave, run
alternately on the two trees twice: before 0.22 / 0.22 (ratio sphfem / CloverLeaf_Serial, median,
1.73 and 1.60 M cell-steps/s), after 0.26 / 0.29 (1.81 and 1.91 M against CloverLeaf's 6.6-6.9 M).
At the issue's 960^2 (``--n 960 --steps 5 --repeat 3 --trees``, one material, 10:08-10:13 UTC, load
2.3 -> 3.1): total 584.6 / 605.9 -> 507.6 / 561.9 ns per cell-step, speed-up min 1.04, median 1.08
(rest 105 / 111 -> 40 / 40, apply dual 74 / 75 -> 57 / 65; the other passes within the noise).

Second round (6 December 2026, main 448264a against branch alespeed, 240^2 one and two materials and
960^2 one material, load 4): the table in benchmarks/README.md ("Measured", ale2d); forces 81-84 -> 50-53,
rest 15-17 -> 5-8 ns per cell-step, step speed-up median 1.15-1.21.

``--vortex`` (fourth round, the remap where the whole box flows: ``ale_throughput.vortex_velocity``): main
45e359a against the branch, 6 December 2026 17:39 UTC, load 6: the velocity bound 27.8 -> 16.7, the face
fluxes 70.5 -> 62.7 (noisy: medians 72.5 -> 73.4), total 299.8 -> 284.2 ns per cell-step (min; one
material); the table in benchmarks/README.md ("ALE remap in moving flow").
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
          "node velocities", "dual fluxes", "apply dual", "finish nodes", "nodal mass", "finish elems", "time step")

# kernels looked up on the kernels module at each call by AleSystem (K.name)
_MODULE_KERNELS = {"apply_face_fluxes": "apply faces", "dual_fluxes": "dual fluxes", "node_velocities": "node velocities",
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


def measure(n: int, steps: int, two: bool, advance: int = 2, vortex: bool = False, dim: int = 2,
            setup_hugepages: bool = True) -> dict:
    """ns per cell-step of each pass, 'rest' and 'total', over ``steps`` steps after ``advance`` warm-up steps
    (vortex: the box flowing, ``ale_throughput.vortex_velocity``; dim 3: the n^3 hex8 box of
    ``ale_throughput.build_3d``, one gas, the vortex with w = 0). setup_hugepages False: numpy's huge-page madvise
    off while the case is built (``AleSystem(...)``: every array it holds), on again for the steps."""
    from ale_throughput import build, build_3d

    if not setup_hugepages:
        from numpy._core.multiarray import _set_madvise_hugepage
        _set_madvise_hugepage(False)
    ale = build(n, two, vortex) if dim == 2 else build_3d(n, vortex)
    if not setup_hugepages:
        _set_madvise_hugepage(True)
    for _ in range(advance):
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


def compare(trees, args, cases, madvise: bool = False) -> None:
    """Interleaved repetitions of every tree in child processes; per-repetition total ratios. madvise: one tree,
    run with numpy's huge-page madvise off ("hugepages off") and on ("hugepages on"), alternating."""
    variants = {"hugepages off": "0", "hugepages on": "1", "off for the set-up": "setup"} if madvise else \
        {t: None for t in trees}
    root = trees[0] if madvise else None
    trees = list(variants)
    runs = {t: {name: [] for name in cases} for t in trees}
    for r in range(args.repeat):
        for t in (trees if r % 2 == 0 or not madvise else trees[::-1]):
            env = dict(os.environ, PYTHONPATH=root or t, NUMBA_NUM_THREADS="1")
            if madvise:
                env["NUMPY_MADVISE_HUGEPAGE"] = "0" if variants[t] == "0" else "1"
            cmd = [sys.executable, str(Path(__file__).resolve()), "--n", str(args.n), "--steps", str(args.steps),
                   "--advance", str(args.advance), "--dim", str(args.dim), "--repeat", "1", "--json"] + (["--two"] if args.two else []) \
                + (["--vortex"] if args.vortex else []) + (["--setup-hugepages-off"] if variants[t] == "setup" else [])
            out = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
            for name, res in json.loads(out.strip().splitlines()[-1]).items():
                runs[t][name].append(res)
    for t in trees:
        print_table(f"tree {t}", cases, runs[t])
    pairs = [(trees[0], trees[1]), (trees[2], trees[1])] if madvise else [(trees[0], trees[-1])]
    for a, b in pairs:
        for name in cases:
            ratio = [x["total"] / y["total"] for x, y in zip(runs[a][name], runs[b][name])]
            print(f"{name}: speed-up of {b} over {a}: min {min(ratio):.3f}, median {statistics.median(ratio):.3f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=240, help="cells per side (default 240)")
    ap.add_argument("--steps", type=int, default=10, help="timed steps per repetition (default 10)")
    ap.add_argument("--repeat", type=int, default=3, help="interleaved repetitions (default 3)")
    ap.add_argument("--two", action="store_true", help="also the two-material water/air case")
    ap.add_argument("--advance", type=int, default=2,
                    help="steps before the timed ones (default 2, the compilation; the wave from the bump then "
                         "covers a few %% of the box: 500 at 240^2 set 99.9 %% of the nodes moving)")
    ap.add_argument("--vortex", action="store_true",
                    help="the box flowing from the start (a Taylor-Green vortex, ale_throughput.vortex_velocity): "
                         "every face and node of the remap moves")
    ap.add_argument("--dim", type=int, choices=(2, 3), default=2,
                    help="3: the hex8 box of ale_throughput.build_3d, n^3 cells, one gas (--two ignored)")
    ap.add_argument("--trees", nargs="+", help="source trees to compare, interleaved (child processes)")
    ap.add_argument("--madvise", action="store_true",
                    help="compare numpy's huge-page madvise off and on, this tree, interleaved (child processes)")
    ap.add_argument("--json", action="store_true", help=argparse.SUPPRESS)  # a child's one line of results
    ap.add_argument("--setup-hugepages-off", action="store_true", help=argparse.SUPPRESS)  # a --madvise child
    args = ap.parse_args()
    cases = [("one", False)] + ([("two", True)] if args.two and args.dim == 2 else [])
    names = [name for name, _ in cases]
    if args.trees or args.madvise:
        print(f"ALE {args.dim}D passes, {args.n}^{args.dim} cells{', vortex' if args.vortex else ''}, {args.steps} steps after "
              f"{args.advance}, 1 thread, "
              f"load {os.getloadavg()[0]:.2f}")
        compare(args.trees or [str(Path(__file__).resolve().parents[1])], args, names, args.madvise)
        print(f"load after {os.getloadavg()[0]:.2f}")
        return
    import numba

    runs = {name: [] for name in names}
    for _ in range(args.repeat):
        for name, two in cases:
            runs[name].append(measure(args.n, args.steps, two, args.advance, args.vortex, args.dim,
                                      not args.setup_hugepages_off))
    if args.json:
        print(json.dumps({name: r[0] for name, r in runs.items()}))
        return
    print_table(f"ALE {args.dim}D passes, {args.n}^{args.dim} cells, {args.steps} steps, numba threads "
                f"{numba.get_num_threads()}, load {os.getloadavg()[0]:.2f}", names, runs)
    print(f"load after {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
