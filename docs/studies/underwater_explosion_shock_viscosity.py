"""Issue 15: a steady water shock in SPH against its Rankine-Hugoniot state, per Monaghan (alpha, beta)
(docs/studies/underwater_explosion.md, "Axisymmetric SPH free field"; docs/theory/sph.md, "Shock viscosity").

A water column (the UNDEX decks' Gruneisen water: c 1480 m/s, S1 1.92, gamma0 0.28) moving at -up onto a slip
wall at its foot, 0.15 m long and 20 dx wide (plane 2D: slip walls on both long sides) or of radius 10 dx (r-z:
the axis a ghost line, a slip wall at r = R), dx as given, t = 25 us, timestep_scale 0.9. A plane shock runs up
the column and leaves the water at rest at p_H = rho0 Us up (``spherical_blast_reference.water_hugoniot``). Per
run: the peak of the Shepard probe (as a deck probe) read every step at 10 / 20 / 30 mm from the wall, on the
column's centre line, over p_H; its reading at the end (the plateau, at 10 / 20 mm); and the peak of the
particle nearest each probe (what the probe smooths).

    PYTHONPATH=. NUMBA_NUM_THREADS=1 python docs/studies/underwater_explosion_shock_viscosity.py \
        --geometry rz plane --up 80 150 330 --viscosity 0.1 0 1 2 1.5 3 [--dx 0.001]

About 0.3 s CPU per run at dx 1 mm (tests/verification/test_sph_axisymmetric_shock.py asserts the r-z runs).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
from sphfem_cli.sph import lattice, scenes  # noqa: E402
from sphfem_cli.sph.options import SphOptions, material_table  # noqa: E402
from sphfem_cli.sph.system import SphSystem  # noqa: E402
from sphfem_cli.sph.walls import box_walls  # noqa: E402
from tests.verification.spherical_blast_reference import setup_from_deck, water_hugoniot  # noqa: E402
from tests.verification.test_sph_axisymmetric_explosive import WATER  # noqa: E402

LENGTH, T_END = 0.15, 25.0e-6


def steady_shock(geometry: str, dx: float, up: float, alpha: float, beta: float) -> dict:
    """One run (module docstring): probe peaks, plateau and nearest-particle peaks over p_H, CPU s."""
    rz = geometry == "rz"
    width = (10 if rz else 20) * dx
    # the column along y (= z in r-z), the wall at y = 0
    x = lattice.box([0.0, 0.0], [width, LENGTH], dx)
    v = np.zeros_like(x)
    v[:, 1] = -up
    rho = np.full(len(x), 1000.0)
    sides = ["right", "bottom"] if rz else ["left", "right", "bottom"]
    opt = SphOptions(alpha=alpha, beta=beta, axisymmetric=rz, pressure_cutoff=-1e5,
                     walls=box_walls([0.0, 0.0], [width, LENGTH], sides))
    mass = scenes.ring_particles(x, dx, rho) if rz else rho * dx * dx
    ps = SphSystem(x, v, mass, rho, np.zeros(len(x), np.int64), material_table([WATER]), opt)
    probes = np.array([[0.5 * width, y] for y in (0.01, 0.02, 0.03)])
    readings, nearest = [], []

    def every(s):
        readings.append(s.interpolate(probes))
        d = np.linalg.norm(s.x[None, :, :] - probes[:, None, :], axis=2)
        nearest.append(s.p[np.argmin(d, axis=1)])

    cpu = time.process_time()
    ps.run(T_END, scale=0.9, every=every)
    cpu = time.process_time() - cpu
    p_h = water_hugoniot(setup_from_deck().water, up)["p"]
    readings, nearest = np.array(readings), np.array(nearest)
    return {"p_h": p_h, "peak": readings.max(axis=0) / p_h - 1.0, "plateau": readings[-1, :2] / p_h - 1.0,
            "nearest": nearest.max(axis=0) / p_h - 1.0, "cpu": cpu, "steps": len(readings)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--geometry", nargs="+", default=["rz", "plane"], choices=["rz", "plane"])
    ap.add_argument("--up", type=float, nargs="+", default=[80.0, 150.0, 330.0])
    ap.add_argument("--viscosity", type=float, nargs="+", default=[0.1, 0.0, 1.0, 2.0, 1.5, 3.0],
                    help="alpha beta pairs")
    ap.add_argument("--dx", type=float, default=0.001)
    args = ap.parse_args()
    pairs = list(zip(args.viscosity[::2], args.viscosity[1::2]))
    pct = lambda a: "/".join(f"{100 * x:+.1f}" for x in a)  # noqa: E731
    for geometry in args.geometry:
        for up in args.up:
            for alpha, beta in pairs:
                r = steady_shock(geometry, args.dx, up, alpha, beta)
                print(f"{geometry} dx {args.dx * 1e3:g} mm up {up:g} m/s (p_H {r['p_h'] / 1e6:.1f} MPa) alpha {alpha:g} "
                      f"beta {beta:g}: probe peak {pct(r['peak'])} %, plateau {pct(r['plateau'])} %, nearest "
                      f"particle {pct(r['nearest'])} %; {r['steps']} steps, {r['cpu']:.1f} s CPU", flush=True)


if __name__ == "__main__":
    main()
