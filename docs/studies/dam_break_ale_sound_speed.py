"""Issue 18 item 2 on decks/dam_break_ale.yaml: the front against the artificial sound speed c0 of its linear
polynomial water (c1 = rho0 c0^2), and the peak Mach number. Figures in docs/studies/dam_break_2d.md ("The ALE twin's
sound speed").

    python docs/studies/dam_break_ale_sound_speed.py 15 30 60     # c0 in m/s; from the repository root

Each c0 runs the shipped deck (one thread) into study_dam_ale/c0_<c0>/ with field outputs every 1.6 ms and prints
Z = x_front / a at T = t sqrt(2 g / a) = 0.832 / 1.219 / 1.997 / 2.547 (Martin & Moyce's a = 2.25 in series,
../shared/reference/dambreak_front_martin_moyce_1952.csv), the error against it, the peak Mach number (the largest
nodal speed over the elements more than half water in the field outputs, over c0) and the CPU seconds.
"""
from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import h5py
import numpy as np

from sphfem_cli import api

sys.path.insert(0, str(Path(__file__).resolve().parent))
from dam_break_2d import ROOT, front, reference  # noqa: E402  (the SPH twin's study: the compared times and Z)


def peak_speed(h5: Path) -> float:
    """The largest nodal speed over the nodes of elements more than half water, over the field outputs."""
    best = 0.0
    with h5py.File(h5, "r") as f:
        mesh = f["tank"]
        conn = np.asarray(mesh["connectivity"])
        for name, step in mesh.items():
            if not name.startswith("step_"):
                continue
            wet = np.unique(conn[np.asarray(step["cell"]["fraction_water"]) > 0.5])
            v = np.asarray(step["point"]["velocity"])[wet]
            best = max(best, float(np.linalg.norm(v, axis=1).max(initial=0.0)))
    return best


def run(c0: float) -> None:
    out = Path("study_dam_ale") / f"c0_{c0:g}"
    cpu = time.process_time()
    api.run(ROOT / "decks" / "dam_break_ale.yaml", out, {"equations_of_state.water.c1": 1000.0 * c0 * c0,
                                                         "output.interval": 0.0016}, threads=1, overwrite=True)
    cpu = time.process_time() - cpu
    Z = np.array(front(out))
    _, z_ref = reference()
    print(f"c0 {c0:g}: Z {np.round(Z, 3).tolist()} err % {np.round(100 * (Z / z_ref - 1), 1).tolist()} "
          f"peak Mach {peak_speed(out / 'results.h5') / c0:.3f} cpu {cpu:.1f} s load {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    for arg in sys.argv[1:]:
        run(float(arg))
