"""FEM throughput: element-steps per second of an elastic hex8 cube, and the warm start of `sphfem run`.

    python benchmarks/fem_throughput.py [--n 30] [--steps 200]

Prints element-steps/s on 1 and 2 threads (the whole step: element kernel, nodal gather,
central-difference update), peak resident memory, and the wall time of `sphfem run` on a tiny deck
with a warm numba cache. Target (issue 2): >= 0.5 M element-steps/s per thread, warm start <= 2 s.
"""
from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CUBE_DECK = """
title: Elastic hex8 cube, throughput benchmark
dimension: 3
control: {{end_time: 1.0}}
materials:
  steel: {{type: elastic, density: 7850.0, youngs_modulus: 2.1e11, poisson_ratio: 0.3}}
sections:
  solid: {{type: solid, hourglass: {{type: viscous, coefficient: 0.1}}}}
parts:
  cube:
    material: steel
    section: solid
    geometry: {{box: {{min: [0, 0, 0], max: [1, 1, 1], divisions: [{n}, {n}, {n}]}}}}
sets:
  bottom: {{type: node, part: cube, side: bottom}}
boundaries:
  - {{type: fixed, set: bottom}}
initial:
  - {{type: velocity, part: cube, velocity: [1.0, 0.5, -0.3]}}
"""

TINY_DECK = """
title: Tiny warm-start deck
dimension: 2
control: {end_time: 1.0e-5}
materials:
  steel: {type: elastic, density: 7850.0, youngs_modulus: 2.1e11, poisson_ratio: 0.3}
sections:
  solid: {type: solid}
parts:
  block: {material: steel, section: solid, geometry: {box: {min: [0, 0], max: [0.1, 0.1], divisions: [4, 4]}}}
initial:
  - {type: velocity, part: block, velocity: [1.0, 0.0]}
"""


def element_steps_per_second(n: int, steps: int, threads: int) -> float:
    import numba

    from sphfem_cli.driver import load_model
    from sphfem_cli.solver.explicit import Simulation

    numba.set_num_threads(threads)
    with tempfile.TemporaryDirectory() as tmp:
        deck = Path(tmp) / "cube.yaml"
        deck.write_text(CUBE_DECK.format(n=n))
        model = load_model(str(deck)).model
    sim = Simulation(model)
    for _ in range(5):  # warm-up (compiles on a cold cache)
        sim.step()
    start = time.perf_counter()
    for _ in range(steps):
        sim.step()
    elapsed = time.perf_counter() - start
    return model.n_elements * steps / elapsed


def warm_start_seconds() -> float:
    exe = Path(sys.executable).with_name("sphfem")
    with tempfile.TemporaryDirectory() as tmp:
        deck = Path(tmp) / "tiny.yaml"
        deck.write_text(TINY_DECK)
        cmd = [str(exe), "run", str(deck), "-o", str(Path(tmp) / "out"), "-q"]
        subprocess.run(cmd, check=True)  # fills the cache
        start = time.perf_counter()
        subprocess.run(cmd, check=True)
        return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--n", type=int, default=30, help="elements per edge of the cube (default 30)")
    parser.add_argument("--steps", type=int, default=200, help="timed steps (default 200)")
    args = parser.parse_args()

    import numba

    print(f"hex8 elastic cube {args.n}^3 = {args.n ** 3} elements, {args.steps} steps")
    rates = {}
    for threads in sorted({1, min(2, numba.config.NUMBA_NUM_THREADS)}):
        rates[threads] = element_steps_per_second(args.n, args.steps, threads)
        print(f"  {threads} thread(s): {rates[threads] / 1e6:.3f} M element-steps/s "
              f"({rates[threads] / threads / 1e6:.3f} M per thread)")
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"  peak resident memory: {peak:.0f} MiB")
    print(f"warm start of `sphfem run` on a tiny deck: {warm_start_seconds():.2f} s")


if __name__ == "__main__":
    main()
