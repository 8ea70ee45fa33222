"""ALE throughput: element-steps per second of the Eulerian multi-material solver.

Cases: a single-material ideal gas with a pressure bump, and water (stiffened gas) with an air
column (two materials, mixed cells along the interface), both on an n x n quad4 mesh with slip
walls; and the single-material gas in 3D on an n3 x n3 x n3 hex8 mesh (slip walls, a spherical
bump). Prints element-steps/s on 1 and 2 threads (Lagrangian phase + remap, van Leer, SLIC).

    python benchmarks/ale_throughput.py [n] [steps] [--n3 N] [--threads 1 2]   (defaults 480, 20, 60, 1 2)
"""
from __future__ import annotations

import argparse
import time

import numba
import numpy as np

from sphfem_cli.ale import AleSystem, fill_fractions
from sphfem_cli.materials.tables import gas_row
from sphfem_cli.model.mesh import box_mesh


def build_3d(n, vortex=False):
    """The n^3 hex8 box: one ideal gas, p = 10 in a sphere of radius 0.1 at the centre, 1 around, rho = 1;
    slip walls. vortex: the 2D Taylor-Green vortex of ``vortex_velocity`` in every z layer (U = 0.5, w = 0:
    divergence-free, no normal velocity on the six walls), so that the whole box flows."""
    mesh = box_mesh([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], divisions=[n, n, n])
    nodes, conn = mesh.nodes, mesh.elements
    r2 = ((nodes[conn].mean(axis=1) - 0.5) ** 2).sum(axis=1)
    p = np.where(r2 < 0.01, 10.0, 1.0)
    velocity = np.concatenate([vortex_velocity(nodes, 0.5), np.zeros((len(nodes), 1))], 1) if vortex else None
    ale = AleSystem(nodes, conn, [gas_row(1.4, 1.0)], np.ones((len(conn), 1)), [1.0], pressure=p[:, None],
                    velocity=velocity)
    for axis in range(3):
        ale.set_slip(np.flatnonzero((nodes[:, axis] == 0.0) | (nodes[:, axis] == 1.0)), np.eye(3)[axis])
    return ale


def vortex_velocity(nodes, speed):
    """Taylor-Green vortex in the unit box: u = U sin(pi x) cos(pi y), v = -U cos(pi x) sin(pi y).

    Divergence-free, with zero normal velocity on the four walls (slip walls keep it), and non-zero
    at every node but the corners, the centre and the walls' midpoints: every face of the mesh sweeps
    volume from the first step, so the remap computes every flux (the moving-flow case of issue 17).
    """
    x, y = nodes[:, 0], nodes[:, 1]
    return speed * np.stack([np.sin(np.pi * x) * np.cos(np.pi * y), -np.cos(np.pi * x) * np.sin(np.pi * y)], 1)


def build(n, two, vortex=False):
    """The n x n box: one ideal gas (p = 10 in a bump of radius 0.1, 1 around, rho = 1) or, with two,
    water with air above a wavy line (p = 1e7 in the bump, 1e5 around); slip walls. vortex: the gas at
    U = 0.5 (Mach 0.42 against c = 1.18) or the water at U = 10 m/s in a Taylor-Green vortex
    (``vortex_velocity``), so that the whole box flows; else at rest (only the bump's wave moves)."""
    mesh = box_mesh([0.0, 0.0], [1.0, 1.0], divisions=[n, n])
    nodes, conn = mesh.nodes, mesh.elements
    velocity = vortex_velocity(nodes, 10.0 if two else 0.5) if vortex else None
    xc = nodes[conn].mean(axis=1)
    r2 = ((xc - 0.5) ** 2).sum(axis=1)
    if two:
        f = fill_fractions(nodes, conn, lambda x, y: y < 0.5 + 0.1 * np.sin(7 * x))
        p = np.where(r2 < 0.01, 1e7, 1e5)
        ale = AleSystem(nodes, conn, [gas_row(4.4, 1000.0, 6e8), gas_row(1.4, 1.2)], np.stack([f, 1 - f], 1),
                        [1000.0, 1.2], pressure=np.stack([p, p], 1), velocity=velocity)
    else:
        p = np.where(r2 < 0.01, 10.0, 1.0)
        ale = AleSystem(nodes, conn, [gas_row(1.4, 1.0)], np.ones((len(conn), 1)), [1.0], pressure=p[:, None],
                        velocity=velocity)
    for axis in range(2):
        ale.set_slip(np.flatnonzero((nodes[:, axis] == 0.0) | (nodes[:, axis] == 1.0)), np.eye(2)[axis])
    return ale


def measure(n, steps, two, threads, dim=2):
    numba.set_num_threads(threads)
    ale = build(n, two) if dim == 2 else build_3d(n)
    for _ in range(2):  # compile / warm up
        ale.step(ale.stable_dt(0.5))
    t0 = time.perf_counter()
    for _ in range(steps):
        ale.step(ale.stable_dt(0.5))
    dt = time.perf_counter() - t0
    return steps * len(ale.conn) / dt


def main():
    parser = argparse.ArgumentParser(description="ALE throughput: element-steps/s of a 2D Eulerian mesh, "
                                                 "one and two materials, on 1 and 2 threads.")
    parser.add_argument("n", nargs="?", type=int, default=480, help="elements per side (default 480)")
    parser.add_argument("steps", nargs="?", type=int, default=20, help="timed steps (default 20)")
    parser.add_argument("--n3", type=int, default=60, help="3D case: elements per side (default 60; 0 skips it)")
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2], help="thread counts (default 1 2)")
    args = parser.parse_args()
    n, steps = args.n, args.steps
    max_threads = numba.config.NUMBA_NUM_THREADS
    threads_list = [t for t in args.threads if t <= max_threads]
    print(f"ALE throughput, {n} x {n} quad4 = {n * n} elements, {steps} steps, van Leer + SLIC")
    for two, name in ((False, "single-material gas"), (True, "two-material water/air")):
        for threads in threads_list:
            rate = measure(n, steps, two, threads)
            print(f"  {name:24s} threads={threads}: {rate / 1e6:6.2f} M element-steps/s "
                  f"({rate / threads / 1e6:5.2f} M per thread)")
    if args.n3 > 0:
        n3 = args.n3
        print(f"3D: {n3} x {n3} x {n3} hex8 = {n3 ** 3} elements, {steps} steps")
        for threads in threads_list:
            rate = measure(n3, steps, False, threads, dim=3)
            print(f"  {'single-material gas 3D':24s} threads={threads}: {rate / 1e6:6.2f} M element-steps/s "
                  f"({rate / threads / 1e6:5.2f} M per thread)")


if __name__ == "__main__":
    main()
