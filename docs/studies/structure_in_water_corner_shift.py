"""`sphfem` with Fickian particle shifting restricted to the water next to the structure's submerged convex corners, on
every ``sph_boundary`` coupling (issue 12, docs/studies/structure_in_water.md, "mDBC at the corners"; used by
structure_in_water_gap.py's kinds sbs / sbsa01c01). Study code, not in the package.

    python docs/studies/structure_in_water_corner_shift.py A RADIUS run DECK -o OUT ...

After every step, each fluid particle i within RADIUS (in spacings dx) of a convex vertex of the structure below
its top 10 % (the plate's two lower corners; the clamp's corners at the free surface are left out) is moved by

    dr_i = -A h_i |v_i| dt Gamma_i,      Gamma_i = sum_fluid j V_j grad_i W_ij + sum_boundary w (1 / k_w) V_w grad_i W_iw

(Lind, Xu, Stansby & Rogers 2012, J. Comput. Phys. 231, 1499, the Fickian form dr = -D grad C with D = A h |v| dt and
C the kernel sum; |v_i| the particle's own speed, so the shift scales with the drive as the flow does), |dr_i| at
most 0.1 h_i. The boundary particles complete the kernel sum
(those on the fluid point's face's side, each coincident group behind a corner counted once, weight 1 / k as
``corner_particles: once``), so a lattice at rest next to a flat face or a corner has Gamma = 0 and is not shifted.
The particle's velocity and density are not corrected (a displacement of order 1e-3 dx per step). The shift is not a
force: the deck's energy band is off (structure_in_water_gap.py's ENERGY_GUARD_OFF).
"""
import math
import sys

import numpy as np
from numba import njit

from sphfem_cli.contact.sph_boundary import SphBoundaryCoupling
from sphfem_cli.sph import structure_walls as sw
from sphfem_cli.sph.kernel_functions import kernel_f
from sphfem_cli.sph.slots import SI_KERNEL

A, RADIUS = float(sys.argv[1]), float(sys.argv[2])
_record_work = SphBoundaryCoupling.record_work


@njit(cache=False)
def _shift(kernel, a, xf, vf, hf, volf, sel, ws, twins, dt, moves):
    """moves[k] = -A h_i |v_i| dt Gamma_i for i = sel[k] (rows of xf), Gamma_i over the fluid points xf and the
    boundary particles ws on i's side of their faces, a coincident group counted once; |move| <= 0.1 h_i."""
    for k in range(sel.shape[0]):
        i = sel[k]
        xi, yi, hi = xf[i, 0], xf[i, 1], hf[i]
        gx = gy = 0.0
        for j in range(xf.shape[0]):
            dx, dy = xi - xf[j, 0], yi - xf[j, 1]
            hij = 0.5 * (hi + hf[j])
            r = math.sqrt(dx * dx + dy * dy)
            if r == 0.0 or r >= 2.0 * hij:
                continue
            f = kernel_f(kernel, 2, r, hij) * volf[j]
            gx += f * dx
            gy += f * dy
        for w in range(ws.shape[0]):
            if (xi - ws[w, sw.W_FX]) * ws[w, sw.W_NX] + (yi - ws[w, sw.W_FY]) * ws[w, sw.W_NY] <= 0.0:
                continue
            dx, dy = xi - ws[w, sw.W_X], yi - ws[w, sw.W_Y]
            hij = 0.5 * (hi + ws[w, sw.W_H])
            r = math.sqrt(dx * dx + dy * dy)
            if r == 0.0 or r >= 2.0 * hij:
                continue
            seen = 1.0
            for t in range(twins.shape[1]):
                o = twins[w, t]
                if o >= 0 and (xi - ws[o, sw.W_FX]) * ws[o, sw.W_NX] + (yi - ws[o, sw.W_FY]) * ws[o, sw.W_NY] > 0.0:
                    seen += 1.0
            f = kernel_f(kernel, 2, r, hij) * ws[w, sw.W_M] / ws[w, sw.W_RHO] / seen
            gx += f * dx
            gy += f * dy
        speed = math.sqrt(vf[i, 0] ** 2 + vf[i, 1] ** 2)
        mx, my = -a * hi * speed * dt * gx, -a * hi * speed * dt * gy
        size = math.sqrt(mx * mx + my * my)
        if size > 0.1 * hi:
            mx *= 0.1 * hi / size
            my *= 0.1 * hi / size
        moves[k, 0] = mx
        moves[k, 1] = my


def _corners(self, x: np.ndarray) -> np.ndarray:
    """The convex vertices of the structure below the top 10 % of its height, at the nodes' positions x."""
    if not hasattr(self, "_shift_vertices"):
        faces = self.faces
        t = x[faces[:, 1]] - x[faces[:, 0]]
        starts = {int(a): g for g, a in enumerate(faces[:, 0])}
        nodes = [int(b) for f, b in enumerate(faces[:, 1]) if starts.get(int(b)) is not None
                 and t[f, 0] * t[starts[int(b)], 1] - t[f, 1] * t[starts[int(b)], 0] > 0.0]
        y = x[np.unique(faces), 1]
        top = y.max() - 0.1 * (y.max() - y.min())
        self._shift_vertices = np.array([n for n in nodes if x[n, 1] < top], dtype=np.int64)
        self._shift_twins = self._coincident(self.particles())
        self.shift_moved = 0
    return x[self._shift_vertices]


def record_work(self, dt: float, dt_avg: float, v_old: np.ndarray, st) -> None:
    _record_work(self, dt, dt_avg, v_old, st)
    ps = self.sim.particles.system
    corners = _corners(self, st.x)
    if not len(corners):
        return
    dx = self.spacing
    fluid = np.flatnonzero(ps.active & (self.sim.model.particles.part[ps.ids] == self.part_index))
    xf = ps.x[fluid, :2]
    dist = np.min(np.linalg.norm(xf[:, None, :] - corners[None, :, :], axis=2), axis=1)
    hmax = float(ps.h[fluid].max())
    sel = fluid[dist < RADIUS * dx]
    if not len(sel):
        return
    near_mask = dist < RADIUS * dx + 2.0 * hmax
    near = fluid[near_mask]
    rows = np.flatnonzero(dist[near_mask] < RADIUS * dx)  # sel's rows in near
    moves = np.zeros((len(rows), 2))
    _shift(int(ps.settings_i[SI_KERNEL]), A, np.ascontiguousarray(ps.x[near, :2]),
           np.ascontiguousarray(ps.v_half[near, :2]), ps.h[near], ps.m[near] / ps.rho[near], rows, self.ws,
           self._shift_twins, dt, moves)
    ps.x[sel, :2] += moves  # after every gamma: the shift is evaluated on the step's positions
    self.shift_moved += len(sel)


SphBoundaryCoupling.record_work = record_work

if __name__ == "__main__":
    from sphfem_cli.cli import main
    main(sys.argv[3:], prog_name="sphfem")
