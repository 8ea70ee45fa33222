"""How much of a strong plane pulse an SPH non-reflecting side sends back (issue 18 A3, the SPH UNDEX twin).

The water column of tests/verification/test_sph_non_reflecting.py (Tait water, rho0 1000, c 1480 m/s,
gamma 7, cubic spline, h/dx 1.2; a right-moving Gaussian pulse p' = rho c u, half-width 0.05 m, centred at
0.5 m; slip wall at x = 0, the side at x = 1 m), at amplitudes beyond the linear one the test uses. What
comes back is the signed largest pressure difference, over [0, 1], to the same lattice in a 2 m column
at t c = 0.95 m, over the incident peak (the long column's at t c = 0.2 m).

The side's images are the solver's (sph/open_sides.py): x_g = x_i + 2 d0_i n, d0_i the particle's distance
from the side at t = 0, so they move with their particles; the side moves with the water and nothing
leaves. (Until December 2026 they were mirror images about the fixed plane, and particles crossing the
side left; this script then also held the offset images as a monkeypatched prototype. That version, with
its ``mirror`` / ``material`` / ``material_strain`` modes, is in git at commit 75c5111.)

    PYTHONPATH=. NUMBA_NUM_THREADS=1 python docs/studies/sph_open_side_amplitude.py 400 1e5,3e7,1e8 0.1

Figures: docs/studies/underwater_explosion.md, "3a.", measured on a 1D column (the 1D SPH mode, removed on
7 December 2026 as no deck reaches it; the script at commit 3092e31 runs it). The column is now the test's
plane 2D channel three spacings high between slip walls, which gives the 1e5 Pa echo within 0.3 points of
the 1D one (tests/verification/test_sph_non_reflecting.py).
"""
import sys

import numpy as np

from sphfem_cli.sph import lattice
from sphfem_cli.sph.scenes import water
from sphfem_cli.sph.options import SphOptions
from sphfem_cli.sph.system import SphSystem
from sphfem_cli.sph.walls import box_walls

C, RHO, GAMMA = 1480.0, 1000.0, 7.0
Z = RHO * C


def density(dp):
    """Tait density of the pressure dp: p = (rho0 c^2 / gamma) ((rho/rho0)^gamma - 1)."""
    return RHO * (1.0 + GAMMA * dp / (RHO * C * C)) ** (1.0 / GAMMA)


ROWS = 3  # the channel's height in spacings (wider than 2 h = 2.4 dx: single wall images suffice)


def column(n, right, length=1.0, amp=1e5, width=0.05, alpha=0.1):
    """The test's column: a plane 2D channel ROWS spacings high between slip walls (1D SPH is gone)."""
    dx = 1.0 / n
    height = ROWS * dx
    x = lattice.box([0.0, 0.0], [length, height], dx)
    dp = amp * np.exp(-(((x[:, 0] - 0.5) / width) ** 2))
    walls = (box_walls([0.0, 0.0], [length, height], ["left", "bottom", "top"])
             + box_walls([0.0, 0.0], [length, height], ["right"], right))
    opt = SphOptions(walls=tuple(walls), alpha=alpha)
    v = np.zeros_like(x)
    v[:, 0] = dp / Z
    return SphSystem(x, v, np.full(len(x), RHO * dx * dx), density(dp), np.zeros(len(x), dtype=np.int64),
                     water(C), opt)


def echo(n, amp, alpha=0.1):
    """(signed echo over the incident peak, particles lost, the outermost particle's distance past the side)."""
    ref = column(n, "slip", 2.0, amp, alpha=alpha)
    ref.run(0.2 / C, 0.5)
    incident = np.abs(ref.p).max()
    ref.run(0.95 / C, 0.5)
    p_ref = ref.p[np.argsort(ref.ids)][: ROWS * n]  # lattice.box orders x first: the particles of [0, 1]
    ps = column(n, "non_reflecting", amp=amp, alpha=alpha)
    ps.run(0.95 / C, 0.5)
    d = ps.p[np.argsort(ps.ids)] - p_ref
    return float(d[np.argmax(np.abs(d))] / incident), ps.lost, float(ps.x[:, 0].max() - 1.0)


def main():
    n = int(sys.argv[1])
    amps = [float(a) for a in sys.argv[2].split(",")]
    alpha = float(sys.argv[3]) if len(sys.argv) > 3 else 0.1
    for amp in amps:
        r, lost, past = echo(n, amp, alpha)
        print(f"n {n} alpha {alpha} amplitude {amp:.0e} Pa: sent back {100 * r:+.2f} %, lost {lost}, "
              f"outermost particle {1e3 * past:+.3f} mm past the side's initial plane", flush=True)


if __name__ == "__main__":
    main()
