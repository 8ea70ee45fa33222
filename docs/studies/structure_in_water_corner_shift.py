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
from scipy.spatial import cKDTree

from sphfem_cli.contact.sph_boundary import SphBoundaryCoupling
from sphfem_cli.sph import structure_walls as sw
from sphfem_cli.sph.kernel_functions import kernel_f
from sphfem_cli.sph.slots import SI_DIM, SI_KERNEL

A, RADIUS = float(sys.argv[1]), float(sys.argv[2])
_record_work = SphBoundaryCoupling.record_work


@njit(cache=False)
def _gamma(kernel, dim, xi, hi, xj, vj, hj, wj):
    """sum_j w_j V_j grad_i W_ij (h_ij = (h_i + h_j) / 2) for one point i over the candidates j."""
    gx = gy = 0.0
    for j in range(xj.shape[0]):
        dx, dy = xi[0] - xj[j, 0], xi[1] - xj[j, 1]
        hij = 0.5 * (hi + hj[j])
        r = math.sqrt(dx * dx + dy * dy)
        if r == 0.0 or r >= 2.0 * hij:
            continue
        f = kernel_f(kernel, dim, r, hij) * vj[j] * wj[j]
        gx += f * dx
        gy += f * dy
    return gx, gy


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
    near = fluid[dist < RADIUS * dx + 2.0 * hmax]
    tree = cKDTree(ps.x[near, :2])
    ws = self.ws
    wx = ws[:, sw.W_X:sw.W_Y + 1]
    wtree = cKDTree(wx)
    kernel, dim = int(ps.settings_i[SI_KERNEL]), int(ps.settings_i[SI_DIM])
    moves = np.zeros((len(sel), 2))
    for k, i in enumerate(sel):
        xi, hi = ps.x[i, :2], float(ps.h[i])
        js = near[tree.query_ball_point(xi, 2.0 * hmax)]
        gx, gy = _gamma(kernel, dim, xi, hi, ps.x[js, :2], ps.m[js] / ps.rho[js], ps.h[js], np.ones(len(js)))
        cand = np.asarray(wtree.query_ball_point(xi, 2.0 * hmax), dtype=np.int64)
        if len(cand):
            on = ((xi[0] - ws[cand, sw.W_FX]) * ws[cand, sw.W_NX] + (xi[1] - ws[cand, sw.W_FY]) * ws[cand, sw.W_NY]) > 0.0
            cand = cand[on]
        if len(cand):
            seen = np.ones(len(cand))
            for c, w in enumerate(cand):
                for o in self._shift_twins[w]:
                    if o >= 0 and ((xi[0] - ws[o, sw.W_FX]) * ws[o, sw.W_NX]
                                   + (xi[1] - ws[o, sw.W_FY]) * ws[o, sw.W_NY]) > 0.0:
                        seen[c] += 1.0
            bx, by = _gamma(kernel, dim, xi, hi, wx[cand], ws[cand, sw.W_M] / ws[cand, sw.W_RHO], ws[cand, sw.W_H],
                            1.0 / seen)
            gx, gy = gx + bx, gy + by
        d = -A * hi * float(np.linalg.norm(ps.v_half[i, :2])) * dt * np.array([gx, gy])
        size = float(np.linalg.norm(d))
        if size > 0.1 * hi:
            d *= 0.1 * hi / size
        moves[k] = d
    ps.x[sel, :2] += moves  # after every gamma: the shift is evaluated on the step's positions
    self.shift_moved += len(sel)


SphBoundaryCoupling.record_work = record_work

if __name__ == "__main__":
    from sphfem_cli.cli import main
    main(sys.argv[3:], prog_name="sphfem")
