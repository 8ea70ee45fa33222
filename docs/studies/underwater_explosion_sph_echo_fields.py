"""Where the SPH UNDEX twin's echo check differs (issue 18 A3): the two runs' particle velocities compared.

Reads two runs of docs/studies/underwater_explosion_sph_echo_check.py (OUT/sph_ship and OUT/sph_big, or
any two runs of the twin), matches the water particles of the smaller tank to the larger one's by their
initial positions (the lattices coincide: both are the ALE element centres), and prints

* the plate centre's history: the first time its difference exceeds 1e-6 / 1e-4 / 1e-3 / 1e-2 of the
  larger tank's peak (displacement, velocity, von Mises);
* at each field output (every 0.1 ms), the vertical velocity of the column of particles x = 0.149 nearest to the
  bottom side (every 2.5 mm upwards), both runs (nan: a particle that has left).

    PYTHONPATH=. python docs/studies/underwater_explosion_sph_echo_fields.py OUT/sph_ship OUT/sph_big
"""
import sys

import h5py
import numpy as np
from scipy.spatial import cKDTree

from sphfem_cli import api

PART = "tank_fill0"


def first_differences(a, b):
    ha, hb = api.read_histories(a)["centre"], api.read_histories(b)["centre"]
    t = np.arange(0.0, min(ha["time"][-1], hb["time"][-1]), 1e-6)
    for k in ("displacement_y", "velocity_y", "von_mises"):
        x, y = (np.interp(t, h["time"], h[k]) for h in (ha, hb))
        d, peak = np.abs(x - y), np.abs(y).max()
        first = []
        for frac in (1e-6, 1e-4, 1e-3, 1e-2):
            j = np.flatnonzero(d > frac * peak)
            first.append(f"{1e3 * t[j[0]]:.3f}" if len(j) else "-")
        print(f"centre {k}: first |difference| > 1e-6 / 1e-4 / 1e-3 / 1e-2 of the peak at {' / '.join(first)} ms")


def bottom_column(a, b, x_col=0.14875, rows=14):
    fa, fb = h5py.File(f"{a}/results.h5", "r"), h5py.File(f"{b}/results.h5", "r")
    xa0 = fa[f"{PART}/step_000000/coordinates"][:, :2]
    xb0 = fb[f"{PART}/step_000000/coordinates"][:, :2]
    dist, match = cKDTree(xb0).query(xa0)
    assert dist.max() < 1e-9, dist.max()
    col = np.flatnonzero(np.abs(xa0[:, 0] - x_col) < 1e-6)
    col = col[np.argsort(xa0[col, 1])][:rows]
    steps = sorted(k for k in fa[PART] if k.startswith("step_"))
    for s in steps[1:]:
        if s not in fb[PART]:
            break
        va = np.where(fa[f"{PART}/{s}/point/active"][:] > 0, fa[f"{PART}/{s}/point/velocity"][:, 1], np.nan)
        vb = fb[f"{PART}/{s}/point/velocity"][:, 1][match]
        print(f"{s} v_y at x = {x_col}, y0 = {xa0[col[0], 1]:.4f} upwards every 2.5 mm: "
              f"small tank {np.round(va[col], 1).tolist()}; large tank {np.round(vb[col], 1).tolist()}")


def main():
    a, b = sys.argv[1], sys.argv[2]
    first_differences(a, b)
    bottom_column(a, b)


if __name__ == "__main__":
    main()
