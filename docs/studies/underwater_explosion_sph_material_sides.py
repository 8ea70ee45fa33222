"""Prototype (not the solver): the SPH UNDEX twin with "material" open-side images (issue 18 A3).

The solver's open-side images are mirror images about the fixed plane (sph/walls.make_ghosts), carrying
the copied velocity of their source. Where the water streams out through the side, the particles close on
their own images (2 d, d the distance to the plane) while their copied velocity says the images move
with them; the lattice across the side is then not the continuation of the fluid's, and a strong wave
comes back (docs/studies/sph_open_side_amplitude.py). Here each image of an open side is placed at

    x_g = x_i + sum_w (-2 side_w d0_iw) e_w        (w over the open sides the image lies across)

d0_iw the particle's distance from side w at t = 0 (the images of the particles that started within
reach of the side, corner images of two open sides included): the image moves with its source, the side
moves with the water, and no particle leaves (the domain bound of the open sides is lifted). The walls'
images are the solver's. This is monkeypatched onto SphSystem for one run; it is a measurement of the
idea, not an implementation (no checkpoint of d0, no corner of an open side with a wall).

    PYTHONPATH=. NUMBA_NUM_THREADS=1 python docs/studies/underwater_explosion_sph_material_sides.py 0.0 1.3e-3 OUT

runs the deck derived as underwater_explosion_sph_echo_check.py derives it with `extra` metres more
water; compare with that script's runs (docs/studies/underwater_explosion.md, "3. The open sides").
"""
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import underwater_explosion_sph_echo_check as echo  # noqa: E402

from sphfem_cli import api  # noqa: E402
from sphfem_cli.sph import system as sph_system  # noqa: E402
from sphfem_cli.sph import walls as sph_walls  # noqa: E402
from sphfem_cli.sph.slots import PLANE_OPEN  # noqa: E402

MIRROR = sph_walls.make_ghosts
BUILD = sph_system.SphSystem._build_points
STATE = {"sys": None, "d0": None, "not_open": 0}


def build_points(self, hmax):
    STATE["sys"] = self
    if not STATE.get("lifted"):  # the side moves with the water: nothing leaves through it
        for ax, pos, side in self._open_planes[:, :3]:
            (self._dom_lo if side > 0 else self._dom_hi)[int(ax)] = -np.inf if side > 0 else np.inf
        STATE["lifted"] = True
    return BUILD(self, hmax)


def make_ghosts(x, v, rho, c, active, walls, valid, reach, gravity, hydrostatic):
    ps = STATE["sys"]
    op = [w for w in range(walls.shape[0]) if walls[w, 3] == PLANE_OPEN]
    keep = [w for w in range(walls.shape[0]) if walls[w, 3] != PLANE_OPEN]
    nk = len(keep)
    valid_keep = np.zeros(1 << nk, dtype=np.bool_)
    for s in range(1, 1 << nk):
        axes = [int(walls[keep[b], 0]) for b in range(nk) if s >> b & 1]
        valid_keep[s] = len(axes) == len(set(axes))
    out = MIRROR(x, v, rho, c, active, np.ascontiguousarray(walls[keep]), valid_keep, reach, gravity, hydrostatic)
    if STATE["d0"] is None:  # by particle id: the system reorders its arrays
        d0 = np.full((len(x), len(op)), np.inf)
        for b, w in enumerate(op):
            d0[ps.ids, b] = walls[w, 2] * (x[:, int(walls[w, 0])] - walls[w, 1])
        STATE["d0"] = d0
    d0 = STATE["d0"][ps.ids]
    near = (d0 >= 0.0) & (d0 < reach) & active[:, None]
    pos, vel, src = [], [], []
    for s in range(1, 1 << len(op)):
        members = [b for b in range(len(op)) if s >> b & 1]
        axes = [int(walls[op[b], 0]) for b in members]
        if len(axes) != len(set(axes)):
            continue
        idx = np.flatnonzero(np.all(near[:, members], axis=1))
        gp = np.zeros((len(idx), 3))
        gp[:, :x.shape[1]] = x[idx]
        for b in members:
            gp[:, int(walls[op[b], 0])] -= 2.0 * walls[op[b], 2] * d0[idx, b]
        gv = np.zeros((len(idx), 3))
        gv[:, :x.shape[1]] = v[idx]
        pos.append(gp)
        vel.append(gv)
        src.append(idx)
    gp, gv, gs = np.vstack(pos), np.vstack(vel), np.concatenate(src)
    beyond = np.zeros(len(gs), dtype=bool)
    for w in op:
        beyond |= walls[w, 2] * (gp[:, int(walls[w, 0])] - walls[w, 1]) < 0.0
    STATE["not_open"] = max(STATE["not_open"], int((~beyond).sum()))  # images open_ghost_state would miss
    return (np.vstack([out[0], gp]), np.vstack([out[1], gv]), np.vstack([out[2], np.ones((len(gs), 3))]),
            np.concatenate([out[3], gs]), np.concatenate([out[4], np.zeros(len(gs))]),
            np.concatenate([out[5], np.zeros(len(gs))]))


def main():
    extra, end, out = float(sys.argv[1]), float(sys.argv[2]), Path(sys.argv[3])
    sph_walls.make_ghosts = make_ghosts
    sph_system.SphSystem._build_points = build_points
    t0 = time.process_time()
    r = api.run(echo.sph_deck(extra, end), out, overwrite=True, threads=1)
    h = r.histories()["centre"]
    print(r.status, r.time, r.steps, f"cpu {time.process_time() - t0:.0f} s; images inside every side at most "
          f"{STATE['not_open']}", flush=True)
    for k, v in echo.peaks(h).items():
        print(f"{k}: {v:.4g}")


if __name__ == "__main__":
    main()
