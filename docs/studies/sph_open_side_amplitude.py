"""How much of a strong plane pulse an SPH non-reflecting side sends back (issue 18 A3, the SPH UNDEX twin).

The water column of tests/verification/test_sph_non_reflecting.py (Tait water, rho0 1000, c 1480 m/s,
gamma 7, cubic spline, h/dx 1.2; a right-moving Gaussian pulse p' = rho c u, half-width 0.05 m, centred at
0.5 m; slip wall at x = 0, the side at x = 1 m), at amplitudes beyond the linear one the test uses. What
comes back is the signed largest pressure difference, over [0, 1], to the same lattice in a 2 m column
at t c = 0.95 m, over the incident peak (the long column's at t c = 0.2 m).

``images`` picks how the side's ghost images are placed:

* ``mirror``: the solver's (sph/walls.make_ghosts): the images of the particles within reach of the side,
  mirrored about the fixed plane; particles crossing it leave;
* ``material`` (a prototype, monkeypatched here, not in the solver): each image at x_i + 2 d0_i n, d0_i the
  particle's distance from the side at t = 0, so it moves with its source as its copied velocity says; the
  side moves with the water and no particle leaves;
* ``material_strain``: the same with d0_i scaled by rho_i(0)/rho_i (1D: the layer's compression).

    PYTHONPATH=. NUMBA_NUM_THREADS=1 python docs/studies/sph_open_side_amplitude.py mirror 400 1e5,3e7,1e8 0.1

Figures (docs/studies/underwater_explosion.md, "3. The open sides").
"""
import sys

import numpy as np

from sphfem_cli.sph import walls as sph_walls
from sphfem_cli.sph.scenes import water
from sphfem_cli.sph.slots import PLANE_OPEN
from sphfem_cli.sph.options import SphOptions
from sphfem_cli.sph.system import SphSystem
from sphfem_cli.sph.walls import box_walls

C, RHO, GAMMA = 1480.0, 1000.0, 7.0
Z = RHO * C
MIRROR = sph_walls.make_ghosts


def density(dp):
    """Tait density of the pressure dp: p = (rho0 c^2 / gamma) ((rho/rho0)^gamma - 1)."""
    return RHO * (1.0 + GAMMA * dp / (RHO * C * C)) ** (1.0 / GAMMA)


def column(n, right, length=1.0, amp=1e5, width=0.05, alpha=0.1):
    dx = 1.0 / n
    m = int(round(length * n))
    x = ((np.arange(m) + 0.5) * dx)[:, None]
    dp = amp * np.exp(-(((x[:, 0] - 0.5) / width) ** 2))
    walls = box_walls([0.0], [length], ["left"])
    if right != "free":
        walls += box_walls([0.0], [length], ["right"], right)
    opt = SphOptions(walls=tuple(walls), domain=([-1.0], [length]), alpha=alpha)
    return SphSystem(x, (dp / Z)[:, None], np.full(m, RHO * dx), density(dp), np.zeros(m, dtype=np.int64),
                     water(C), opt)


def material_images(strain: bool):
    """A make_ghosts that places the open side's images at x_i + 2 d0_i n (1D, one open side, the walls'
    images as the solver makes them). The particle order must stay that of t = 0 (checked)."""
    state = {}

    def make(x, v, rho, c, active, walls, valid, reach, gravity, hydrostatic):
        op = [w for w in range(walls.shape[0]) if walls[w, 3] == PLANE_OPEN]
        keep = [w for w in range(walls.shape[0]) if w not in op]
        valid_keep = np.array([False] + [True] * ((1 << len(keep)) - 1))
        out = MIRROR(x, v, rho, c, active, walls[keep], valid_keep, reach, gravity, hydrostatic)
        ax, pos, side = int(walls[op[0], 0]), walls[op[0], 1], walls[op[0], 2]
        if "d0" not in state:
            state["d0"], state["rho0"] = side * (x[:, ax] - pos), rho.copy()
        assert np.all(np.diff(x[:, 0]) > 0.0)  # the order of t = 0
        d0 = state["d0"] * (state["rho0"] / rho if strain else 1.0)
        src = np.flatnonzero(active & (state["d0"] >= 0.0) & (state["d0"] < reach))
        gp = np.zeros((len(src), 3))
        gp[:, :x.shape[1]] = x[src]
        gp[:, ax] -= 2.0 * side * d0[src]
        gv = np.zeros((len(src), 3))
        gv[:, :x.shape[1]] = v[src]
        return (np.vstack([out[0], gp]), np.vstack([out[1], gv]), np.vstack([out[2], np.ones((len(src), 3))]),
                np.concatenate([out[3], src]), np.concatenate([out[4], np.zeros(len(src))]),
                np.concatenate([out[5], np.zeros(len(src))]))

    return make


def echo(n, amp, images="mirror", alpha=0.1):
    ref = column(n, "slip", 2.0, amp, alpha=alpha)
    ref.run(0.2 / C, 0.5)
    incident = np.abs(ref.p).max()
    ref.run(0.95 / C, 0.5)
    p_ref = ref.p[np.argsort(ref.ids)][:n]
    sph_walls.make_ghosts = MIRROR if images == "mirror" else material_images(images == "material_strain")
    try:
        ps = column(n, "non_reflecting", amp=amp, alpha=alpha)
        if images != "mirror":
            ps._dom_hi[:] = np.inf  # the side moves with the water: nothing leaves
        ps.run(0.95 / C, 0.5)
    finally:
        sph_walls.make_ghosts = MIRROR
    d = ps.p[np.argsort(ps.ids)] - p_ref
    return float(d[np.argmax(np.abs(d))] / incident), ps.lost


def main():
    images, n = sys.argv[1], int(sys.argv[2])
    amps = [float(a) for a in sys.argv[3].split(",")]
    alpha = float(sys.argv[4]) if len(sys.argv) > 4 else 0.1
    for amp in amps:
        r, lost = echo(n, amp, images, alpha)
        print(f"{images} n {n} alpha {alpha} amplitude {amp:.0e} Pa: sent back {100 * r:+.2f} %, lost {lost}",
              flush=True)


if __name__ == "__main__":
    main()
