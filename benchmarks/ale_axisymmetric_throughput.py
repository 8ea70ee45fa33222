"""Cost of an axisymmetric ALE element-step against a plane one (issue 15: at most 1.3 x).

The single-material gas of benchmarks/ale_throughput.py (pressure bump, slip walls, van Leer, Eulerian)
on an n x n mesh of [0, 1]^2, once plane (x-y) and once as rings (x = r, the axis at x = 0; the bump a
ring). Each round times `steps` steps of each, in turn (interleaved), in CPU seconds on one thread;
prints element-steps per CPU second of each round, the ratio of the minima and the load average.

    python benchmarks/ale_axisymmetric_throughput.py [n] [steps] [rounds]   (defaults 200, 10, 3)
"""
from __future__ import annotations

import os
import sys
import time

import numba
import numpy as np

from sphfem_cli.ale import AleSystem
from sphfem_cli.materials.tables import gas_row
from sphfem_cli.model.mesh import box_mesh


def build(n: int, axisymmetric: bool) -> AleSystem:
    mesh = box_mesh([0.0, 0.0], [1.0, 1.0], divisions=[n, n])
    nodes, conn = mesh.nodes, mesh.elements
    r2 = ((nodes[conn].mean(axis=1) - 0.5) ** 2).sum(axis=1)
    p = np.where(r2 < 0.01, 10.0, 1.0)
    ale = AleSystem(nodes, conn, [gas_row(1.4, 1.0)], np.ones((len(conn), 1)), [1.0], pressure=p[:, None],
                    axisymmetric=axisymmetric)
    for axis in range(2):
        ale.set_slip(np.flatnonzero((nodes[:, axis] == 0.0) | (nodes[:, axis] == 1.0)), np.eye(2)[axis])
    return ale


def main(argv: list[str]) -> None:
    n, steps, rounds = (int(a) for a in (argv + ["200", "10", "3"][len(argv):]))
    numba.set_num_threads(1)
    systems = {"plane": build(n, False), "axisymmetric": build(n, True)}
    for ale in systems.values():  # compile / warm up
        for _ in range(2):
            ale.step(ale.stable_dt(0.5))
    rates: dict[str, list[float]] = {k: [] for k in systems}
    for _ in range(rounds):
        for name, ale in systems.items():
            t0 = time.process_time()
            for _ in range(steps):
                ale.step(ale.stable_dt(0.5))
            rates[name].append(n * n * steps / (time.process_time() - t0))
    for name, r in rates.items():
        print(f"{name:13s} element-steps per CPU s: " + ", ".join(f"{x:.3e}" for x in r))
    ratio = max(rates["plane"]) / max(rates["axisymmetric"])
    print(f"cost ratio axisymmetric / plane (best rounds): {ratio:.3f}; n = {n}, {steps} steps x {rounds} rounds, "
          f"1 thread, load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main(sys.argv[1:])
