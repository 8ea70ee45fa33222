"""FEM throughput: element-steps per second of an elastic hex8 cube, the warm start of `sphfem run`,
and the cost of an axisymmetric quad4 element-step against a plane-strain one.

    python benchmarks/fem_throughput.py [--n 30] [--steps 200] [--quad 200] [--rounds 5] [--only-axisymmetric]

Prints element-steps/s on 1 and 2 threads (the whole step: element kernel, nodal gather,
central-difference update), peak resident memory, and the wall time of `sphfem run` on a tiny deck
with a warm numba cache. Target (issue 2): >= 0.5 M element-steps/s per thread, warm start <= 2 s.

Axisymmetric against plane strain (issue 15): the same quad x quad box of Johnson-Cook copper (the
Taylor rod's material, so the plastic return runs) struck along y, once as `dimension: 2` and once
as `dimension: axisymmetric`; the element kernel alone (the same arguments, dt of the run) and the
whole step, one thread, CPU time (time.process_time), the two interleaved round by round; the ratio is
of the medians. Target: axisymmetric <= 1.3 x plane strain.
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


QUAD_DECK = """
title: Johnson-Cook quad4 box, {dimension}
dimension: {dimension}
control: {{end_time: 1.0, energy_band: null}}
materials:
  copper: {{type: johnson_cook, density: 8960.0, youngs_modulus: 1.24e11, poisson_ratio: 0.34, A: 9.0e7, B: 2.92e8,
           n: 0.31, C: 0.025, m: 1.09, reference_strain_rate: 1.0, melt_temperature: 1356.0, room_temperature: 293.0,
           specific_heat: 383.0}}
sections:
  solid: {{type: solid, hourglass: {{type: viscous, coefficient: 0.1}}}}
parts:
  rod: {{material: copper, section: solid, geometry: {{box: {{min: [0, 0], max: [0.01, 0.01], divisions: [{n}, {n}]}}}}}}
sets:
  face: {{type: node, part: rod, side: bottom}}
boundaries:
  - {{type: symmetry, set: face, normal: y}}
initial:
  - {{type: velocity, part: rod, velocity: [0.0, -190.0]}}
"""


def axisymmetric_against_plane(n: int, steps: int, rounds: int) -> dict[str, tuple[float, float]]:
    """Median CPU seconds per element-step (kernel alone, whole step) of each dimension, interleaved."""
    import numba
    import numpy as np

    from sphfem_cli.driver import load_model
    from sphfem_cli.fem.axisymmetric import axisymmetric_element_forces
    from sphfem_cli.fem.kernels import quad4_element_forces
    from sphfem_cli.solver.explicit import Simulation

    numba.set_num_threads(1)
    sims = {}
    with tempfile.TemporaryDirectory() as tmp:
        for dim in ("2", "axisymmetric"):
            deck = Path(tmp) / f"box_{dim}.yaml"
            deck.write_text(QUAD_DECK.format(n=n, dimension=dim))
            sims[dim] = Simulation(load_model(str(deck)).model)
    kernels = {"2": quad4_element_forces, "axisymmetric": axisymmetric_element_forces}
    for sim in sims.values():
        for _ in range(20):  # warm-up: compiles on a cold cache, the plastic front forms
            sim.step()
    kernel_t = {k: [] for k in sims}
    step_t = {k: [] for k in sims}
    for _ in range(rounds):
        for dim, sim in sims.items():
            m, st = sim.model, sim.state
            f_elem = np.zeros((m.n_elements, 4, 2))
            dt_elem = np.zeros(m.n_elements)
            start = time.process_time()
            for _ in range(steps):  # the kernel on copies of the state (the run's own state untouched)
                kernels[dim](st.x, st.v, m.connectivity, m.element_active, m.element_material, m.element_section,
                             m.material_type, m.material_param, m.section_param, m.volume0, st.dt_prev,
                             st.stress.copy(), st.hist.copy(), st.energy.copy(), st.hg_energy.copy(),
                             st.hg_force.copy(), f_elem, dt_elem, st.volume.copy(), st.q_visc.copy())
            kernel_t[dim].append((time.process_time() - start) / (steps * m.n_elements))
            start = time.process_time()
            for _ in range(steps):
                sim.step()
            step_t[dim].append((time.process_time() - start) / (steps * m.n_elements))
    return {dim: (float(np.median(kernel_t[dim])), float(np.median(step_t[dim]))) for dim in sims}


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
    parser.add_argument("--quad", type=int, default=200, help="elements per edge of the quad4 box (default 200)")
    parser.add_argument("--rounds", type=int, default=5, help="interleaved rounds of the axisymmetric ratio (default 5)")
    parser.add_argument("--only-axisymmetric", action="store_true", help="only the axisymmetric / plane-strain ratio")
    args = parser.parse_args()

    print(f"quad4 Johnson-Cook box {args.quad}^2 = {args.quad ** 2} elements, {args.rounds} rounds of "
          f"{args.steps // 4} steps, 1 thread, CPU time per element-step (median)")
    res = axisymmetric_against_plane(args.quad, max(1, args.steps // 4), args.rounds)
    (k2, s2), (ka, sa) = res["2"], res["axisymmetric"]
    print(f"  element kernel: plane strain {k2 * 1e9:.0f} ns, axisymmetric {ka * 1e9:.0f} ns, ratio {ka / k2:.3f}")
    print(f"  whole step:     plane strain {s2 * 1e9:.0f} ns, axisymmetric {sa * 1e9:.0f} ns, ratio {sa / s2:.3f}")
    if args.only_axisymmetric:
        return

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
