"""The UNDEX plate scene at 5 mm, 3D quarter and r-z twin, both plates with the viscous hourglass form (issue 15 B3b).

    python docs/studies/underwater_explosion_plate_hourglass.py [--work DIR]

The scene and the twin are ``underwater_explosion_plate_3d.py``'s (``solid_scene``, ``rz_scene``) with one more override
for both: ``sections.plate.hourglass`` = viscous, 0.1 (the decks: stiffness, 0.1). Why: dry, the 3D plate at 5 mm with
the stiffness form peaks at 0.693 of the r-z plate and 31 % under its own converged peak, the hourglass control taking
35 % of its energy; with the viscous form 0.967 (``underwater_explosion_plate_dry.py``; docs/studies/underwater_explosion.md,
"The two plates dry"). Prints per run the plate centre's maximum and its time, u(0.3 ms), u(0.8 ms), the largest
energy ratio and the CPU seconds (one thread).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import underwater_explosion_plate_3d as scene  # noqa: E402

from sphfem_cli import api  # noqa: E402

VISCOUS = {"sections.plate.hourglass": {"type": "viscous", "coefficient": 0.1}}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--work", type=Path, default=Path("study_undex_plate_hourglass"))
    args = parser.parse_args()
    for dim in (2, 3):
        deck, overrides = (scene.DECK_3D, scene.solid_scene(0.005)) if dim == 3 else (scene.DECK_RZ, scene.rz_scene(0.005))
        folder = args.work / f"{dim}d_h5mm_viscous"
        cpu = time.process_time()
        result = api.run(deck, folder, {**overrides, **VISCOUS}, threads=1, overwrite=True)
        cpu = time.process_time() - cpu
        centre = np.genfromtxt(folder / "histories" / "centre.csv", delimiter=",", names=True)
        glstat = np.genfromtxt(folder / "histories" / "glstat.csv", delimiter=",", names=True)
        t, u = centre["time"], centre["displacement_z" if dim == 3 else "displacement_y"]
        i = int(np.argmax(u))
        print(f"{'3D quarter' if dim == 3 else 'r-z twin'}: completed {result.completed}, maximum {u[i] * 1e3:.2f} mm at "
              f"{t[i] * 1e3:.3f} ms, u(0.3 ms) {np.interp(3e-4, t, u) * 1e3:.2f} mm, u(0.8 ms) {u[-1] * 1e3:.2f} mm, "
              f"energy ratio at most {glstat['energy_ratio'].max():.6f}, {cpu:.1f} s CPU", flush=True)


if __name__ == "__main__":
    main()
