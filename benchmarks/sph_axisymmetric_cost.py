"""Cost of an axisymmetric SPH particle-step against a plane one at the same particle count (issue 15).

    NUMBA_NUM_THREADS=1 python benchmarks/sph_axisymmetric_cost.py [--n 100] [--steps 20] [--rounds 5]

Both cases are a square of water at rest under gravity, [0, 1] x [0, 1] at dx = 1/n (n^2 particles),
hydrostatic start, delta-SPH 0.1, Monaghan alpha 0.02, cubic spline, h = 1.2 dx, slip ghost walls:
the plane tank (``scenes.still_water``: walls left, right, bottom) and the cylinder
(``scenes.still_water_cylinder``: the axis x = 0 as its ghost line, walls right and bottom), so both
have the same particles and the same ghosts; the whole step is timed (EOS and h, ghosts, cell sort,
rates, time step, leapfrog). The two are stepped in interleaved blocks of ``--steps`` steps, ``--rounds``
times (the machine is shared: interleaving puts both under the same load), after warm-up steps
(compilation, cell order); the figure is process-CPU seconds per particle-step, median over the rounds,
and their ratio (issue 15's goal: axisymmetric <= 1.3 x plane).

Measured: see docs/theory/sph.md ("Axisymmetric SPH", cost).
"""
from __future__ import annotations

import argparse
import statistics
import time


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100)
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    from sphfem_cli.sph import scenes

    dx = 1.0 / args.n
    systems = {"plane": scenes.still_water(depth=1.0, width=1.0, dx=dx),
               "axisymmetric": scenes.still_water_cylinder(depth=1.0, radius=1.0, dx=dx)}
    for ps in systems.values():
        for _ in range(25):  # compilation, reordering into cell order
            ps.advance()
    cpu = {k: [] for k in systems}
    for _ in range(args.rounds):
        for name, ps in systems.items():
            c0 = time.process_time()
            for _ in range(args.steps):
                ps.advance()
            cpu[name].append((time.process_time() - c0) / (args.steps * ps.n))
    import os

    print(f"n = {args.n} ({systems['plane'].n} particles), {args.rounds} rounds of {args.steps} steps, "
          f"load average {os.getloadavg()[0]:.2f}")
    for name, t in cpu.items():
        print(f"  {name:13s} {statistics.median(t) * 1e9:8.1f} ns CPU per particle-step "
              f"(rounds {', '.join(f'{x * 1e9:.0f}' for x in t)})")
    ratios = [a / p for a, p in zip(cpu["axisymmetric"], cpu["plane"])]
    print(f"  ratio axisymmetric / plane: median {statistics.median(ratios):.3f} "
          f"(rounds {', '.join(f'{r:.3f}' for r in ratios)})")


if __name__ == "__main__":
    main()
