"""Start-up figures of issue 17: CPU seconds before the first step, each against its peer.

    python benchmarks/startup.py [--repeat 3] [--cases check,run,cold,ale2,ale1,sph] [--threads 1] [--against TREE]

Every figure is the CPU time (user + system, from the child's rusage) of a fresh process, so imports,
numba's cache loads and the model build all count (the package is byte-compiled first, as an
installed one is); the repetitions of all cases are interleaved (round r runs every case once, then
round r + 1), and min and median over the rounds are printed with the load average before and after.

* ``check``: ``sphfem check decks/cantilever_2d.yaml``, warm numba cache; peer ``python -c "import
  numpy"`` (goal: at most 3x the peer).
* ``run``: ``sphfem run`` of a tiny 2D deck (the cantilever, 8 x 2 quad4, 20 steps), warm cache
  (goal <= 1.5 s).
* ``cold``: the same run with an empty numba cache (a fresh ``NUMBA_CACHE_DIR``): the compile cost
  of what such a deck loads (goal <= 15 s; the run must say that it compiles).
* ``ale2`` / ``ale1``: model set-up of a 960 x 960 quad4 ALE mesh, water and air (SLIC, van Leer;
  ``decks/water_air_shock_tube.yaml`` on the unit square, water in [0, 0.7] x [0, 0.5]) or air
  alone: ``api.load`` (validate, mesh, fills, sets) and ``Simulation(model)`` (the ALE system: topology,
  material state, work arrays), in seconds of CPU inside the process, after its imports
  (goal <= 2 s).
* ``sph``: the same for the SPH dam break (``decks/dam_break_2d.yaml``) at spacing 1.144e-4 m,
  5.0e5 particles (goal <= 2 s).

* ``check3d`` / ``checkale`` / ``checkbird`` / ``checkdam``: ``sphfem check`` of ``decks/cantilever_3d.yaml``
  (hex8 solid at rest), ``decks/water_air_shock_tube.yaml`` (plane ALE at rest, two materials),
  ``decks/bird_strike_axisymmetric_ale.yaml`` (r-z ALE bird in motion, an axisymmetric solid disc) and
  ``decks/dam_break_2d.yaml`` (SPH), warm cache; ``checkdamale`` / ``checkuw3d``: ``decks/dam_break_ale.yaml`` (a
  hydrostatic ALE fill) and ``decks/underwater_explosion_plate_3d_ale.yaml`` (hex8 ALE, a 3D coupling);
  ``cold-check3d`` / ``cold-checkale`` / ... the same with an empty numba cache (a fresh
  ``NUMBA_CACHE_DIR`` per run): what the initial-state passes ``fem.at_rest`` and ``ale.at_rest`` save (not in
  the default cases: the empty-cache runs of a tree that compiles the force kernels cost 20-35 s each).

Every case also prints its user and system seconds apart (min / median): the set-up's system time is first
touches of fresh memory, and with transparent huge pages (numpy madvises its arrays of 4 MB and more) it swings
by seconds from run to run on this machine (a 2 MB fault may go through the kernel's direct compaction); since
branch setup19 the ALE part is built with numpy's advice off (``sphfem_cli/model/pages.py``).

``--against TREE``: every case also runs on the source tree TREE (e.g. a ``git archive`` copy of main: its
``sphfem_cli`` on ``PYTHONPATH``, its own numba cache), the two trees alternating within each round (which goes
first alternates between rounds); each case prints its min / median for both trees and the ratio of the medians.

No peer is run for the set-up figures (CloverLeaf reads its deck and generates its mesh in well
under a second; it is not built here).

Measured (2 December 2026, the 2-core machine shared with four other sessions, load average 11.1
before and 9.1 after, 3 interleaved rounds, min / median CPU seconds):

* check 0.764 / 0.785 against import numpy 0.109 / 0.113: 7.0x (goal 3x, not met: the numba
  import, 0.14 s, and loading the solid kernels, 0.19 s, are half of it; see the startup report);
* tiny run, warm 0.830 / 0.856 (goal 1.5 s); empty cache 8.82 / 8.88, and it says it compiles
  (goal 15 s);
* ALE 960^2, two materials 2.97 / 3.02 (main, one run in the same hour: 14.1 s), one material
  1.99 / 1.99 (main: 9.1-10.4 s); SPH 5e5 particles 0.515 / 0.537 (main: 1.07 s, one run).

After the startup17 branch (2 December 2026, same machine; CPU seconds min / median):

* ``--repeat 3``, all cases, load 2.5 before and 3.7 after: check 0.354 / 0.391 against import
  numpy 0.132 / 0.136 (ratio of the pairs: min 2.61, median 2.97); tiny run 1.11 / 1.22; empty
  cache 11.4 / 12.5, says it compiles; ALE 960^2 two materials 2.59 / 2.74, one material
  1.37 / 1.61; SPH 5e5 particles 0.84 / 0.92.
* ``--cases check,ale2,ale1 --repeat 5``, load 3.1 / 3.7: check 0.355 / 0.374 against numpy
  0.118 / 0.133 (pairs: min 2.62, median 2.82; min/min 3.00); ALE two materials 1.93 / 2.59,
  one material 1.36 / 1.72.
* main -> the branch, interleaved pairs in one run (3 rounds each; a first run at load 5.0 -> 5.7:
  check 1.15 / 1.18 -> 0.39 / 0.39, ALE two materials 1.98 / 2.08 -> 1.44 / 1.71, one material
  1.44 / 1.49 -> 1.30 / 1.36; a second at load 3.3 -> 2.9: ALE two materials 2.60 / 2.65 ->
  1.35 / 1.61, tiny run 1.01 / 1.15 -> 1.06 / 1.11, unchanged).

``check`` without the force kernels (branch ckale, 7 December 2026, 14:07-14:20 UTC): ``--cases
check3d,checkale,checkbird,cold-check3d,cold-checkale,cold-checkbird --repeat 3 --against`` a ``git archive``
copy of main b813973, load average 3.99 before and 5.25 after, CPU seconds min / median:

* warm cache, main -> branch: cantilever_3d 1.40 / 1.54 -> 1.40 / 1.53, water_air_shock_tube 1.51 / 1.70 ->
  1.57 / 1.73, bird_strike_axisymmetric_ale 1.82 / 2.02 -> 1.71 / 1.90 (unchanged: loading the cached force
  kernels was not what a warm check cost);
* empty cache, main -> branch: cantilever_3d 36.0 / 39.0 -> 4.48 / 4.76, water_air_shock_tube 21.1 / 22.7 ->
  4.98 / 5.19, bird_strike_axisymmetric_ale 33.1 / 34.7 -> 6.57 / 6.90. What the branch still compiles is the
  model's set-up: the hex8 initial volumes (then a kernel; numpy since 7 December), the ALE topology maps, fill
  sampling, nodal masses and ring volumes, and the EOS sound speed of ``materials.tables.pack_material``.

``check`` of a plane-strain solid deck at rest no longer loads numba (``fem.at_rest``). The ALE
set-up's CPU is now mostly system time: first touches of fresh memory (page faults, transparent
huge pages through numpy's madvise), which swing with what ran before it (the two-material case
after the empty-cache compiles of ``cold``: 2.6 s; without them: 1.4-1.9 s).
"""
from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

TINY = """\
title: tiny cantilever (benchmarks/startup.py)
units: {length: m, mass: kg, time: s}
dimension: 2
control: {end_time: 3.0e-5, timestep_scale: 0.9}
materials:
  steel: {type: elastic, density: 7850.0, youngs_modulus: 2.1e11, poisson_ratio: 0.3}
sections:
  solid: {type: solid, hourglass: {type: stiffness, coefficient: 0.1}}
parts:
  beam: {material: steel, section: solid,
         geometry: {box: {min: [0.0, -0.025], max: [1.0, 0.025], divisions: [8, 2]}}}
sets:
  clamp: {type: node, part: beam, side: left}
  tip: {type: node, part: beam, side: right}
boundaries:
  - {type: fixed, set: clamp, directions: [x, y]}
loads:
  - {type: nodal_force, set: tip, force: [0.0, -7200.0]}
output:
  interval: 1.0e-5
  history_interval: 1.0e-6
  fields: [displacement, velocity]
  histories:
    - {name: tip, point: [1.0, 0.0], quantities: [displacement]}
"""

SETUP = textwrap.dedent("""\
    import resource, sys, time
    from sphfem_cli import api
    from sphfem_cli.solver.explicit import Simulation
    deck, overrides = sys.argv[1], eval(sys.argv[2])
    r0 = resource.getrusage(resource.RUSAGE_SELF)
    t0 = time.process_time()
    loaded = api.load(deck, overrides)
    t1 = time.process_time()
    sim = Simulation(loaded.model)
    t2 = time.process_time()
    r1 = resource.getrusage(resource.RUSAGE_SELF)
    print(f"{t2 - t0:.6f} {t1 - t0:.6f} {t2 - t1:.6f} {r1.ru_utime - r0.ru_utime:.6f} {r1.ru_stime - r0.ru_stime:.6f}")
""")

SETUPS = {
    "ale2": ("decks/water_air_shock_tube.yaml",
             {"parts.tube.geometry.box.max": [1.0, 1.0], "parts.tube.geometry.box.divisions": [960, 960],
              "parts.tube.fill.1.box.max": [0.7, 0.5]}),
    "ale1": ("decks/water_air_shock_tube.yaml",
             {"parts.tube.geometry.box.max": [1.0, 1.0], "parts.tube.geometry.box.divisions": [960, 960],
              "parts.tube.fill": [{"material": "air", "box": {"min": [0.0, 0.0], "max": [1.0, 1.0]},
                                   "pressure": 1.0e5}]}),
    "sph": ("decks/dam_break_2d.yaml", {"parts.column.spacing": 1.144e-4}),
}
GOALS = {"check": "<= 3x numpy", "run": "<= 1.5 s", "cold": "<= 15 s", "ale2": "<= 2 s", "ale1": "<= 2 s",
         "sph": "<= 2 s"}
CHECKS = {"check3d": "decks/cantilever_3d.yaml", "checkale": "decks/water_air_shock_tube.yaml",
          "checkbird": "decks/bird_strike_axisymmetric_ale.yaml", "checkdam": "decks/dam_break_2d.yaml",
          "checkdamale": "decks/dam_break_ale.yaml", "checkuw3d": "decks/underwater_explosion_plate_3d_ale.yaml"}


def child_cpu(cmd: list[str], env: dict | None = None, cwd: Path = ROOT) -> tuple[float, str, tuple[float, float]]:
    """(user + system CPU seconds of the child, its stdout + stderr, (user, system) seconds)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited {done.returncode}:\n{done.stdout}{done.stderr}")
    split = (after.ru_utime - before.ru_utime, after.ru_stime - before.ru_stime)
    return sum(split), done.stdout + done.stderr, split


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--cases", default="check,run,cold,ale2,ale1,sph")
    ap.add_argument("--threads", type=int, default=1, help="NUMBA_NUM_THREADS of the children")
    ap.add_argument("--against", type=Path, default=None, help="a second source tree, run alternately (module docstring)")
    args = ap.parse_args()
    cases = args.cases.split(",")
    trees = [ROOT] + ([args.against.resolve()] if args.against else [])
    tmp = Path(tempfile.mkdtemp(prefix="sphfem-startup-"))
    tiny = tmp / "tiny.yaml"
    tiny.write_text(TINY)
    sphfem = [sys.executable, "-m", "sphfem_cli.cli"]
    run_cmd = sphfem + ["run", str(tiny), "-o", str(tmp / "out"), "--overwrite", "--threads", "1"]
    envs = {}
    for tree in trees:
        envs[tree] = dict(os.environ, NUMBA_NUM_THREADS=str(args.threads), PYTHONPATH=str(tree))
        # the package's bytecode, as an installed package has it (pip byte-compiles; an editable
        # checkout under PYTHONDONTWRITEBYTECODE=1 would compile every module in every child)
        subprocess.run([sys.executable, "-m", "compileall", "-q", str(tree / "sphfem_cli")], check=True,
                       capture_output=True)
        child_cpu(run_cmd, envs[tree], tree)  # a warm cache for every kernel of the tiny deck
        for case in cases:
            if case in CHECKS:
                child_cpu(sphfem + ["check", CHECKS[case]], envs[tree], tree)  # and of the checked decks
            elif case in SETUPS:  # and of the set-up cases (a fresh tree compiles what Simulation(model) calls)
                child_cpu([sys.executable, "-c", SETUP, SETUPS[case][0], repr(SETUPS[case][1])], envs[tree], tree)
    results: dict[tuple[str, Path], list[float]] = {(c, t): [] for c in cases + ["numpy"] for t in trees}
    notes: dict[str, str] = {}
    splits: dict[tuple[str, Path], list[tuple[float, float]]] = {}  # (user, system) s of each measured child
    load0 = os.getloadavg()
    cold = 0
    for r in range(args.repeat):
        for case in cases:
            for tree in (trees if r % 2 == 0 else trees[::-1]):
                env, key = envs[tree], (case, tree)
                if case == "check":
                    results["numpy", tree].append(child_cpu([sys.executable, "-c", "import numpy"], env, tree)[0])
                    results[key].append(child_cpu(sphfem + ["check", "decks/cantilever_2d.yaml"], env, tree)[0])
                elif case in CHECKS or case.startswith("cold-"):
                    if case.startswith("cold-"):
                        cold += 1
                        env = dict(env, NUMBA_CACHE_DIR=str(tmp / f"cold-cache-{cold}"))
                    cpu, out, split = child_cpu(sphfem + ["check", CHECKS[case.removeprefix("cold-")]], env, tree)
                    results[key].append(cpu)
                    splits.setdefault(key, []).append(split)
                    notes[case] = next((line.strip() for line in out.splitlines() if "stable time step" in line), "")
                elif case == "run":
                    results[key].append(child_cpu(run_cmd, env, tree)[0])
                elif case == "cold":
                    cold += 1
                    cold_env = dict(env, NUMBA_CACHE_DIR=str(tmp / f"cold-cache-{cold}"))
                    cpu, out, _ = child_cpu(run_cmd, cold_env, tree)
                    results[key].append(cpu)
                    notes["cold"] = "says it compiles" if "compiling kernels" in out else "SILENT (no compile notice)"
                else:
                    deck, overrides = SETUPS[case]
                    cpu, out, _ = child_cpu([sys.executable, "-c", SETUP, deck, repr(overrides)], env, tree)
                    total, load, build, user, system = (float(v) for v in out.split()[-5:])
                    results[key].append(total)
                    splits.setdefault(key, []).append((user, system))
                    notes[case] = f"last: load {load:.2f} s + Simulation {build:.2f} s"
    load1 = os.getloadavg()
    print(f"load average {load0[0]:.2f} before, {load1[0]:.2f} after; {args.repeat} interleaved rounds; "
          f"CPU seconds of each process, NUMBA_NUM_THREADS={args.threads}")
    if len(trees) > 1:
        print(f"trees: this {trees[0]}, against {trees[1]}")
    print(f"{'case':24s} {'min':>8s} {'median':>8s}  goal")
    for case in ["numpy"] + cases if "check" in cases else cases:
        for tree in trees:
            v = results[case, tree]
            name = case if len(trees) == 1 else f"{case}{'' if tree == ROOT else ' (against)'}"
            line = f"{name:24s} {min(v):8.3f} {statistics.median(v):8.3f}  {GOALS.get(case, '-' if case != 'numpy' else 'peer')}"
            if (case, tree) in splits:
                user, system = zip(*splits[case, tree])
                line += (f"; user {min(user):.2f} / {statistics.median(user):.2f}, "
                         f"system {min(system):.2f} / {statistics.median(system):.2f}")
            if case == "check":
                numpy = results["numpy", tree]
                ratios = [c / n for c, n in zip(v, numpy)]
                line += (f"; ratio to numpy: min {min(ratios):.2f}, median {statistics.median(ratios):.2f}, "
                         f"min/min {min(v) / min(numpy):.2f}")
            if len(trees) > 1 and tree != ROOT:
                line += f"; median this / against {statistics.median(results[case, ROOT]) / statistics.median(v):.3f}"
            elif case in notes:
                line += f"; {notes[case]}"
            print(line)


if __name__ == "__main__":
    main()
