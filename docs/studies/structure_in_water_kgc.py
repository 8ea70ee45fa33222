"""`sphfem` with a first-order consistent (kernel-gradient-corrected) pressure gradient and continuity for the water
next to the structure of every ``sph_boundary`` coupling (issue 12, docs/studies/structure_in_water.md, "mDBC's
velocity and a first-order pressure gradient"; used by structure_in_water_gap.py's kinds sbk / sbka and their a01c01
twins; the ratio-5 diagnosis of "The corrected gradient at ratio 5": kinds sbkats, sb0d). Study code, not in the
package.

    python docs/studies/structure_in_water_kgc.py [all] [nowall] [plain] [dense] run DECK -o OUT ...
    KGC_DUMP=FOLDER KGC_DUMP_EVERY=1e-4 python docs/studies/structure_in_water_kgc.py all run ...   # diagnostics
    python docs/studies/structure_in_water_kgc.py --analyse FOLDER|- RUN DX C0   # their tables (``analyse``)

"plain" applies no correction (the wrapper's "dense" on the plain gradient), "dense" gives every face of
the structure ceil(L_0 / dx) boundary particles per row instead of the coupling's round(L_0 / dx) (``dense_init``).

For every water point i that sees a boundary particle (within 2 h on the particle's face's side), the moment matrix
over its water neighbours j and the boundary particles w it sees (each coincident group behind a convex corner
weighed 1 / k, as ``structure_walls.wall_pairs`` weighs them),

    M_i = sum_j V_j (x_j - x_i) (x) grad_i W_ij        (the identity for a full support; Bonet & Lok 1999, Comput.
                                                          Methods Appl. Mech. Engrg. 180, 97; Randles & Libersky 1996)

gives the corrected kernel gradient L_i grad_i W_ij with L_i = M_i^-T (then sum_j V_j (f_j - f_i) L_i grad_i W_ij is
exact for a linear f; M_i is inverted where det M_i >= 1/4 (tr M_i / 2)^2, as ``sph.expansion``; else L_i = I, e.g.
at the free surface). Every pair then uses the symmetrised gradient (Oger et al. 2007's form, so the pair forces stay
antisymmetric) g~_ij = (L_i + L_j) / 2 grad_i W_ij, with L = I for the points that see no boundary particle and for
the boundary particles, in the pressure term and in the continuity term:

    F_i     = -m_i m_j (p_i / rho_i^2 + p_j / rho_j^2) g~_ij
    drho_i  = rho_i V_j v_ij . g~_ij                   (the decks' volume form; m_j v_ij . g~_ij in the mass form)
    de_i    = 1/2 m_j (p_i / rho_i^2 + p_j / rho_j^2) v_ij . g~_ij

so the pressure work and the internal energy stay one pair's (energy conserved by the pair, as with the plain
gradient). This script adds the difference g~_ij - grad_i W_ij = ((L_i - I) + (L_j - I)) / 2 grad_i W_ij to the
rates after ``fluid_rates`` and ``wall_pairs``: the water pairs' part to ``acc``, ``drho``, ``de`` (a pair of water
points: no external work), the boundary pairs' part to the coupling's ``f_fluid``, ``f_wall`` and its fluid power
(booked as ``wall_pairs``' own). The viscous and density-diffusion terms are unchanged (alpha = 0 in these decks).

On a lattice the bulk's own moment is not exactly I (cubic spline, h/dx 1.2: L - I about 0.009 per entry), so the
correction restricted to the water next to the plate scales its gradient by about 1 % against the bulk's; with "all"
every water point of the part whose M has a smaller eigenvalue of at least EIG_MIN (0.9: a nearly full support, the
corners' water included; not the free surface) is corrected too (kinds sbka / sbkaa01c01); "all nowall" leaves
the boundary pairs' gradient plain (kind sbkan, the diagnostic of the ratio-5 instability).
"""
import math
import os
import sys

import numpy as np
from numba import njit

from sphfem_cli.contact.sph_boundary import SphBoundaryCoupling
from sphfem_cli.sph import structure_walls as sw
from sphfem_cli.sph.kernel_functions import kernel_f
from sphfem_cli.sph.search import cell_range
from sphfem_cli.sph.slots import (CONTINUITY_MASS, D_MK, D_PR, D_RHO, D_VOL, D_VX, D_VY, GF_CELL, GF_HMAX, GF_OX,
                                  GF_OY, GF_OZ, GI_NX, GI_NY, GI_NZ, KIND_FLUID, SI_CONTINUITY, SI_DIM, SI_KERNEL)

OPTIONS = ("all", "nowall", "plain", "dense")
_WORDS = set()
if __name__ == "__main__":
    while len(sys.argv) > 1 and sys.argv[1] in OPTIONS:
        _WORDS.add(sys.argv.pop(1))
EVERYWHERE = "all" in _WORDS
WALLS = "nowall" not in _WORDS  # "all nowall": the boundary pairs uncorrected
EIG_MIN = 0.9  # "all": the water points corrected (a full support has M = I up to the lattice's own 1 %)
# "plain": no correction ("dense" on the plain gradient)
PLAIN = "plain" in _WORDS
# "dense": every face of the structure carries ceil(L_0 / dx) boundary particles per row instead of the coupling's
# round(L_0 / dx), so that they are never sparser along the face than the fluid (at ratio 5 the 2.5 mm faces of the
# 4 x 60 plate get 2 at 1.25 mm instead of 1 at 2.5 mm = 1.25 dx)
DENSE = "dense" in _WORDS
DUMP = os.environ.get("KGC_DUMP")  # folder: per-particle state, L and lambda every KGC_DUMP_EVERY s (diagnostics)
DUMP_EVERY = float(os.environ.get("KGC_DUMP_EVERY", "1e-4"))
_wall_pairs = sw.wall_pairs
_forces = SphBoundaryCoupling.forces
_init = SphBoundaryCoupling.__init__
STATE = {}


@njit(cache=True)
def _seen(ws, twins, w, x, y):
    """1 / k: the weight of boundary particle w for a fluid point at (x, y) that sees k of its coincident group."""
    seen = 1.0
    for t in range(twins.shape[1]):
        o = twins[w, t]
        if o >= 0 and sw._on_side(ws, o, x, y, 0.0):
            seen += 1.0
    return 1.0 / seen


@njit(cache=True)
def correction_matrices(ws, twins, sx, sd, mine, cell_start, settings_i, grid_f, grid_i, lmat, everywhere=False,
                        eig=None):
    """lmat[k] = L_k - I (2 x 2) for every fluid slot k that sees a boundary particle (0 elsewhere); returns the
    number of such slots and how many of them fell back on L = I. With ``everywhere`` every fluid slot of the
    coupling's part is corrected (the boundary particles in M where it sees them), where M_k's smaller eigenvalue is
    at least EIG_MIN (a nearly full support: not at the free surface). ``eig`` (if given) gets M_k's smaller
    eigenvalue (of its symmetric part) at every slot examined (-1 elsewhere)."""
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    hmax, cell = grid_f[GF_HMAX], grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    inv_cell = 1.0 / cell
    near = np.zeros(sx.shape[1], dtype=np.bool_)
    for w in range(ws.shape[0]):  # the fluid slots within 2 h_wf of a boundary particle, on its face's side
        xw, yw, hw = ws[w, sw.W_X], ws[w, sw.W_Y], ws[w, sw.W_H]
        x0, x1 = cell_range(xw, hw + hmax, ox, inv_cell, nx)
        y0, y1 = cell_range(yw, hw + hmax, oy, inv_cell, ny)
        z0, z1 = cell_range(ws[w, sw.W_Z], hw + hmax, oz, inv_cell, nz)
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for k in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if (int(sd[D_MK, k]) & 3) != KIND_FLUID or not mine[k]:
                        continue
                    if not sw._on_side(ws, w, sx[0, k], sx[1, k], sx[2, k]):
                        continue
                    hij = 0.5 * (hw + sx[3, k])
                    if (sx[0, k] - xw) ** 2 + (sx[1, k] - yw) ** 2 < 4.0 * hij * hij:
                        near[k] = True
    count = fallback = 0
    lmat[:] = 0.0
    if eig is not None:
        eig[:] = -1.0
    for k in range(sx.shape[1]):
        if not near[k] and not (everywhere and (int(sd[D_MK, k]) & 3) == KIND_FLUID and mine[k]):
            continue
        count += 1
        xi, yi, hi = sx[0, k], sx[1, k], sx[3, k]
        m00 = m01 = m10 = m11 = 0.0  # M[a, b] = sum V (x_j - x_i)_a (grad_i W_ij)_b
        x0, x1 = cell_range(xi, hi + hmax, ox, inv_cell, nx)
        y0, y1 = cell_range(yi, hi + hmax, oy, inv_cell, ny)
        z0, z1 = cell_range(sx[2, k], hi + hmax, oz, inv_cell, nz)
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for j in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if j == k or (int(sd[D_MK, j]) & 3) != KIND_FLUID or not mine[j]:
                        continue
                    dx, dy = xi - sx[0, j], yi - sx[1, j]
                    hij = 0.5 * (hi + sx[3, j])
                    r2 = dx * dx + dy * dy
                    if r2 >= 4.0 * hij * hij or r2 == 0.0:
                        continue
                    f = kernel_f(kernel, dim, math.sqrt(r2), hij) * sd[D_VOL, j]
                    m00 -= dx * f * dx
                    m01 -= dx * f * dy
                    m10 -= dy * f * dx
                    m11 -= dy * f * dy
        for w in range(ws.shape[0] if near[k] else 0):
            if not sw._on_side(ws, w, xi, yi, sx[2, k]):
                continue
            dx, dy = xi - ws[w, sw.W_X], yi - ws[w, sw.W_Y]
            hij = 0.5 * (hi + ws[w, sw.W_H])
            r2 = dx * dx + dy * dy
            if r2 >= 4.0 * hij * hij or r2 == 0.0:
                continue
            f = (kernel_f(kernel, dim, math.sqrt(r2), hij) * ws[w, sw.W_M] / ws[w, sw.W_RHO]
                 * _seen(ws, twins, w, xi, yi))
            m00 -= dx * f * dx
            m01 -= dx * f * dy
            m10 -= dy * f * dx
            m11 -= dy * f * dy
        det = m00 * m11 - m01 * m10
        tr = m00 + m11
        b, c = 0.5 * (m01 + m10), 0.5 * (m00 - m11)
        lam = 0.5 * tr - math.sqrt(c * c + b * b)  # the smaller eigenvalue of M's symmetric part
        if eig is not None:
            eig[k] = lam
        if det < 0.25 * (0.5 * tr) ** 2 or det <= 0.0:
            fallback += 1
            continue
        if everywhere and lam < EIG_MIN:
            fallback += 1
            continue
        # L = M^-T
        lmat[k, 0, 0] = m11 / det - 1.0
        lmat[k, 0, 1] = -m10 / det
        lmat[k, 1, 0] = -m01 / det
        lmat[k, 1, 1] = m00 / det - 1.0
    return count, fallback


@njit(cache=True)
def add_correction(ws, twins, sx, sd, mine, perm, cell_start, settings_i, grid_f, grid_i, lmat, acc, f_fluid, drho,
                   de, f_wall, walls=True, cpow=None):
    """Add the pair terms with g~_ij - grad_i W_ij (module docstring) for every fluid slot k with lmat[k] != 0:
    its half (L_k - I) / 2 grad_k W_kj of every pair, to both points. Returns the boundary pairs' fluid power
    sum m_i de_i (``wall_pairs``' share). ``walls`` False: the boundary pairs keep the plain gradient (L_k = I in them).
    ``cpow`` (if given, per particle): the correction's power on each water particle, m_i acc_i . v_i, of its water
    pairs (the diagnostics)."""
    kernel, dim = settings_i[SI_KERNEL], settings_i[SI_DIM]
    mform = settings_i[SI_CONTINUITY] == CONTINUITY_MASS
    nx, ny, nz = grid_i[GI_NX], grid_i[GI_NY], grid_i[GI_NZ]
    hmax, cell = grid_f[GF_HMAX], grid_f[GF_CELL]
    ox, oy, oz = grid_f[GF_OX], grid_f[GF_OY], grid_f[GF_OZ]
    inv_cell = 1.0 / cell
    power = 0.0
    bx0 = by0 = np.inf  # the boundary particles' box widened by the largest support: no pair outside it
    bx1 = by1 = -np.inf
    for w in range(ws.shape[0]):
        bx0, bx1 = min(bx0, ws[w, sw.W_X]), max(bx1, ws[w, sw.W_X])
        by0, by1 = min(by0, ws[w, sw.W_Y]), max(by1, ws[w, sw.W_Y])
    bx0, bx1, by0, by1 = bx0 - 2.0 * hmax, bx1 + 2.0 * hmax, by0 - 2.0 * hmax, by1 + 2.0 * hmax
    for k in range(sx.shape[1]):
        l00, l01, l10, l11 = lmat[k, 0, 0], lmat[k, 0, 1], lmat[k, 1, 0], lmat[k, 1, 1]
        if l00 == 0.0 and l01 == 0.0 and l10 == 0.0 and l11 == 0.0:
            continue
        i = perm[k]
        xi, yi, hi = sx[0, k], sx[1, k], sx[3, k]
        rhoi, voli, si = sd[D_RHO, k], sd[D_VOL, k], sd[D_PR, k]
        mi = voli * rhoi
        x0, x1 = cell_range(xi, hi + hmax, ox, inv_cell, nx)
        y0, y1 = cell_range(yi, hi + hmax, oy, inv_cell, ny)
        z0, z1 = cell_range(sx[2, k], hi + hmax, oz, inv_cell, nz)
        for cz in range(z0, z1 + 1):
            for cy in range(y0, y1 + 1):
                base = (cz * ny + cy) * nx
                for jj in range(cell_start[base + x0], cell_start[base + x1 + 1]):
                    if jj == k or (int(sd[D_MK, jj]) & 3) != KIND_FLUID or not mine[jj]:
                        continue
                    dx, dy = xi - sx[0, jj], yi - sx[1, jj]
                    hij = 0.5 * (hi + sx[3, jj])
                    r2 = dx * dx + dy * dy
                    if r2 >= 4.0 * hij * hij or r2 == 0.0:
                        continue
                    f = kernel_f(kernel, dim, math.sqrt(r2), hij)
                    wx, wy = f * dx, f * dy  # grad_i W_ij
                    gx, gy = 0.5 * (l00 * wx + l01 * wy), 0.5 * (l10 * wx + l11 * wy)
                    j = perm[jj]
                    rhoj, volj = sd[D_RHO, jj], sd[D_VOL, jj]
                    mj = volj * rhoj
                    s = si + sd[D_PR, jj]
                    acc[i, 0] -= mj * s * gx
                    acc[i, 1] -= mj * s * gy
                    acc[j, 0] += mi * s * gx
                    acc[j, 1] += mi * s * gy
                    vg = (sd[D_VX, k] - sd[D_VX, jj]) * gx + (sd[D_VY, k] - sd[D_VY, jj]) * gy
                    if cpow is not None:
                        cpow[i] -= mi * mj * s * (gx * sd[D_VX, k] + gy * sd[D_VY, k])
                        cpow[j] += mi * mj * s * (gx * sd[D_VX, jj] + gy * sd[D_VY, jj])
                    drho[i] += (mj if mform else rhoi * volj) * vg
                    drho[j] += (mi if mform else rhoj * voli) * vg
                    de[i] += 0.5 * mj * s * vg
                    de[j] += 0.5 * mi * s * vg
        inside = walls and bx0 <= xi <= bx1 and by0 <= yi <= by1
        for w in range(ws.shape[0] if inside else 0):
            if not sw._on_side(ws, w, xi, yi, sx[2, k]):
                continue
            dx, dy = xi - ws[w, sw.W_X], yi - ws[w, sw.W_Y]
            hij = 0.5 * (hi + ws[w, sw.W_H])
            r2 = dx * dx + dy * dy
            if r2 >= 4.0 * hij * hij or r2 == 0.0:
                continue
            f = kernel_f(kernel, dim, math.sqrt(r2), hij)
            wx, wy = f * dx, f * dy
            gx, gy = 0.5 * (l00 * wx + l01 * wy), 0.5 * (l10 * wx + l11 * wy)
            rw = ws[w, sw.W_RHO]
            mw = ws[w, sw.W_M] * _seen(ws, twins, w, xi, yi)
            s = si + ws[w, sw.W_P] / (rw * rw)
            c = mi * mw * s
            f_fluid[i, 0] -= c * gx
            f_fluid[i, 1] -= c * gy
            f_wall[w, 0] += c * gx
            f_wall[w, 1] += c * gy
            vg = (sd[D_VX, k] - ws[w, sw.W_VX]) * gx + (sd[D_VY, k] - ws[w, sw.W_VY]) * gy
            drho[i] += (mw if mform else rhoi * mw / rw) * vg
            dei = 0.5 * mw * s * vg
            de[i] += dei
            power += mi * dei
    return power


def wall_pairs(ws, twins, slip, sx, sd, mine, perm, cell_start, settings_f, settings_i, grid_f, grid_i, f_fluid, drho,
               de, f_wall):
    power = _wall_pairs(ws, twins, slip, sx, sd, mine, perm, cell_start, settings_f, settings_i, grid_f, grid_i,
                        f_fluid, drho, de, f_wall)
    if PLAIN:
        return power
    ps = STATE["ps"]
    lmat = np.zeros((sx.shape[1], 2, 2))
    eig = np.empty(sx.shape[1])
    count, fallback = correction_matrices(ws, twins, sx, sd, mine, cell_start, settings_i, grid_f, grid_i, lmat,
                                          EVERYWHERE, eig)
    STATE["corrected"] = STATE.get("corrected", 0) + count - fallback
    STATE["fallback"] = STATE.get("fallback", 0) + fallback
    cpow = np.zeros(ps.n) if DUMP else None
    power += add_correction(ws, twins, sx, sd, mine, perm, cell_start, settings_i, grid_f, grid_i, lmat,
                            ps.acc, f_fluid, drho, de, f_wall, WALLS, cpow)
    if DUMP:
        dump(ps, sx, perm, lmat, eig, cpow)
    return power


def dump(ps, sx, perm, lmat, eig, cpow) -> None:
    """Diagnostics (KGC_DUMP): every call, the number of water particles whose correction switched on or off (L
    from I to M^-T or back) and the correction's total power; every KGC_DUMP_EVERY s, per particle: position,
    velocity, density, pressure, specific internal energy, L - I, lambda, the correction's power, the switches so
    far (npz in the folder KGC_DUMP); switches.txt: time, switched on, switched off, corrected, correction power."""
    n = ps.n
    real = np.zeros(lmat.shape[0], dtype=np.bool_)  # the slots of particles (not ghosts, not the sentinels)
    real[: perm.shape[0]] = perm < n
    perm = np.concatenate((perm, np.full(lmat.shape[0] - perm.shape[0], n)))
    on = np.zeros(n, dtype=np.bool_)
    on[perm[real]] = np.any(lmat[real] != 0.0, axis=(1, 2))
    lam = np.full(n, -1.0)
    lam[perm[real]] = eig[real]
    li = np.zeros((n, 2, 2))
    li[perm[real]] = lmat[real]
    prev = STATE.get("on")
    STATE.setdefault("switches", np.zeros(n, dtype=np.int64))
    if prev is not None:
        STATE["switches"] += on != prev
        with open(os.path.join(DUMP, "switches.txt"), "a") as f:
            f.write(f"{ps.time:.9e} {int(np.sum(on & ~prev))} {int(np.sum(~on & prev))} {int(on.sum())} "
                    f"{cpow.sum():.6e}\n")
    STATE["on"] = on
    if ps.time >= STATE.get("next_dump", 0.0):
        STATE["next_dump"] = STATE.get("next_dump", 0.0) + DUMP_EVERY
        np.savez_compressed(os.path.join(DUMP, f"t{1e6 * ps.time:07.1f}us.npz"), t=ps.time, x=ps.x[:, :2], v=ps.v[:, :2],
                            rho=ps.rho, p=ps.p, e=ps.e, m=ps.m, li=li, lam=lam, cpow=cpow,
                            switches=STATE["switches"], active=ps.active)


def forces(self, st) -> None:
    STATE["ps"] = self.sim.particles.system
    _forces(self, st)


def dense_init(self, sim, spec) -> None:
    """The coupling's own construction, then its boundary particles rebuilt with ceil(L_0 / dx) per face and row
    (``SphBoundaryCoupling.__init__``'s layout otherwise: s_k = (k + 1/2) / n_s, d_l = (l + 1/2) dx, mass rho_0
    (L_0 / n_s) dx, so the boundary's mass per face is unchanged)."""
    _init(self, sim, spec)
    model = sim.model
    x0 = np.asarray(model.coordinates, dtype=np.float64)
    dx = self.spacing
    length0 = np.linalg.norm(x0[self.faces[:, 1]] - x0[self.faces[:, 0]], axis=1)
    per_face = np.maximum(1, np.ceil(length0 / dx - 1e-9)).astype(np.int64)
    rho0 = float(self.ws[0, sw.W_RHO])
    seg, s, depth, mass = [], [], [], []
    for f in range(len(self.faces)):
        n_s = int(per_face[f])
        for layer in range(self.layers):
            for k in range(n_s):
                seg.append(f)
                s.append((k + 0.5) / n_s)
                depth.append((layer + 0.5) * dx)
                mass.append(rho0 * length0[f] / n_s * dx)
    h = float(self.ws[0, sw.W_H])
    self.seg = np.asarray(seg, dtype=np.int64)
    self.s = np.asarray(s, dtype=np.float64)
    self.depth = np.asarray(depth, dtype=np.float64)
    self.ws = np.zeros((len(self.seg), sw.NW))
    self.ws[:, sw.W_M] = mass
    self.ws[:, sw.W_H] = h
    self.ws[:, sw.W_RHO] = rho0
    self.f_wall = np.zeros((len(self.seg), 3))
    self.vertex = np.full(len(self.seg), -1, dtype=np.int64)
    self.place(x0, np.zeros_like(x0), np.zeros_like(x0))
    coincident = self._coincident(self.particles()) if spec.corner_particles == "once" or self.mdbc else None
    self.twins = coincident if spec.corner_particles == "once" else np.full((len(self.seg), 1), -1, dtype=np.int64)
    self.side2 = np.full(len(self.seg), -1, dtype=np.int64)
    self.mdbc_order = np.zeros(len(self.seg), dtype=np.int64)
    self.mdbc_cond = np.zeros(len(self.seg))
    if self.mdbc:
        self._corner_ghosts(coincident, x0)
        self.place(x0, np.zeros_like(x0), np.zeros_like(x0))
    print(f"dense: {len(self.seg)} boundary particles ({int(per_face.sum())} per row against "
          f"{int(np.maximum(1, np.round(length0 / dx)).sum())} by the coupling's rule)", file=sys.stderr)


def install() -> None:
    sw.wall_pairs = wall_pairs
    SphBoundaryCoupling.forces = forces
    if DENSE:
        SphBoundaryCoupling.__init__ = dense_init


def elastic_energy(rho, rho0, c0, c1):
    """eps(rho) = int_rho0^rho p / r^2 dr of the linear-polynomial EOS p = c0 + c1 (r / rho0 - 1) (J/kg): the
    specific internal energy the density alone implies (``e`` booked by the pair work equals it when the continuity
    is the time derivative of a function of the positions, as for the plain summation-consistent form)."""
    return c0 * (1.0 / rho0 - 1.0 / rho) + c1 * (np.log(rho / rho0) / rho0 + 1.0 / rho - 1.0 / rho0)


def face_noise(run: str) -> None:
    """The plate's kinetic energy and its faces' node-to-node noise at each field output: for the face nodes
    (x = the plate's min / max x) in order of y, the RMS of v_k - (v_k-1 + v_k+1) / 2 (both components), and the
    fastest node (m/s)."""
    import h5py
    with h5py.File(os.path.join(run, "results.h5"), "r") as f:
        rho = 2700.0
        for step in sorted(k for k in f["plate"] if k.startswith("step_"))[1:]:
            x0 = f["plate/step_000000/coordinates"][:, :2]
            v = f[f"plate/{step}/point/velocity"][:, :2]
            conn = f["plate/connectivity"][:]
            area = np.zeros(len(x0))  # lumped node areas of the quad4 mesh (reference configuration)
            for q in conn:
                xq = x0[q]
                a = 0.5 * abs(np.dot(xq[:, 0], np.roll(xq[:, 1], -1)) - np.dot(xq[:, 1], np.roll(xq[:, 0], -1)))
                area[q] += a / 4.0
            ke = 0.5 * rho * float(np.sum(area * np.sum(v ** 2, axis=1)))
            out = []
            for xf in (x0[:, 0].min(), x0[:, 0].max()):
                idx = np.flatnonzero(np.abs(x0[:, 0] - xf) < 1e-6)
                idx = idx[np.argsort(x0[idx, 1])]
                vf = v[idx]
                out.append(float(np.sqrt(np.mean(np.sum((vf[1:-1] - 0.5 * (vf[:-2] + vf[2:])) ** 2, axis=1)))))
            t = 0.5 * int(step[-1])
            print(f"  plate at {t:.1f} ms: kinetic {ke:.3f} J/m, face noise left / right {out[0]:.3f} / {out[1]:.3f} m/s,"
                  f" fastest node {np.linalg.norm(v, axis=1).max():.2f} m/s")


def analyse(folder: str, run: str, dx: float, c0: float, c1: float = 2.2e9, rho0: float = 1000.0) -> None:
    """The KGC_DUMP diagnostics of one run of the section 4.1 scene (tank 0.4 x 0.2 with slip ghost walls, plate
    0.2-0.21 x 0.05-0.2): per dump the water's kinetic energy and m (e - e0 - eps(rho)) summed over four bands
    (``wall``: within 3 dx of the tank's walls, where M lacks the ghost particles; ``plate``: within 2.4 dx of the
    plate, its corners' water included; ``corner``: within 10 mm of its lower corners (a subset of ``plate`` and
    the bulk); ``bulk``: the rest), the corrected particles whose lambda lies within 0.05 of EIG_MIN, the
    switches so far, and the five fastest particles; the energy table's ratio, kinetic and contact energies."""
    import glob
    e = np.genfromtxt(os.path.join(run, "histories", "glstat.csv"), delimiter=",", names=True)
    print("t ms | energy ratio | kinetic | internal | contact | external (J/m)")
    for t in np.arange(0.2e-3, 2.01e-3, 0.2e-3):
        k = int(np.searchsorted(e["time"], t))
        k = min(k, len(e) - 1)
        print(f"{1e3 * e['time'][k]:.2f} | {e['energy_ratio'][k]:.4f} | {e['kinetic'][k]:.3f} | {e['internal'][k]:.3f}"
              f" | {e['contact'][k]:.3f} | {e['external_work'][k]:.3f}")
    face_noise(run)
    if folder == "-":
        return
    sw_ = np.loadtxt(os.path.join(folder, "switches.txt"))
    print("switches per 0.2 ms (on / off), corrected particles at its end, the correction's power (W/m) mean:")
    for t0 in np.arange(0.0, 2.0e-3, 0.2e-3):
        m = (sw_[:, 0] >= t0) & (sw_[:, 0] < t0 + 0.2e-3)
        if m.any():
            print(f"  {1e3 * t0:.1f}-{1e3 * (t0 + 0.2e-3):.1f} ms: {int(sw_[m, 1].sum())} / {int(sw_[m, 2].sum())}, "
                  f"{int(sw_[m, 3][-1])}, {sw_[m, 4].mean():.3e}")
    files = sorted(glob.glob(os.path.join(folder, "t*us.npz")))
    first = np.load(files[0])
    e_init = first["e"]
    print("t ms | KE wall / plate / corner / bulk (J/m) | m(e - e0 - eps(rho)) wall / plate / corner / bulk (J/m) | "
          "corrected with |lambda - EIG_MIN| < 0.05 | fastest 5: x, y mm, |v| m/s, lambda, switches")
    for f in files[1:]:
        d = np.load(f)
        a = d["active"]
        x, v, m, lam = d["x"], d["v"], d["m"], d["lam"]
        speed = np.linalg.norm(v, axis=1)
        ke = 0.5 * m * speed ** 2
        drift = m * (d["e"] - e_init - elastic_energy(d["rho"], rho0, c0, c1))
        wall = (x[:, 0] < 3 * dx) | (x[:, 0] > 0.4 - 3 * dx) | (x[:, 1] < 3 * dx) | (x[:, 1] > 0.2 - 3 * dx)
        px = np.clip(x[:, 0], 0.2, 0.21)
        py = np.clip(x[:, 1], 0.05, 0.2)
        plate = (np.hypot(x[:, 0] - px, x[:, 1] - py) < 2.4 * dx) & ~wall
        corner = (np.hypot(x[:, 0] - 0.2, x[:, 1] - 0.05) < 0.01) | (np.hypot(x[:, 0] - 0.21, x[:, 1] - 0.05) < 0.01)
        bulk = ~wall & ~plate
        on = np.any(d["li"] != 0.0, axis=(1, 2))
        edge = on & (np.abs(lam - EIG_MIN) < 0.05)
        order = np.argsort(-speed * a)[:5]
        fast = "; ".join(f"{1e3 * x[i, 0]:.0f},{1e3 * x[i, 1]:.0f} {speed[i]:.1f} {lam[i]:.2f} {d['switches'][i]}"
                         for i in order)
        print(f"{1e3 * float(d['t']):.2f} | " + " / ".join(f"{ke[r & a].sum():.3f}" for r in (wall, plate, corner, bulk))
              + " | " + " / ".join(f"{drift[r & a].sum():+.3f}" for r in (wall, plate, corner, bulk))
              + f" | {int(edge.sum())} | {fast}")


if __name__ == "__main__" and sys.argv[1:2] == ["--analyse"]:
    analyse(sys.argv[2], sys.argv[3], float(sys.argv[4]), float(sys.argv[5]))
    sys.exit()


if __name__ == "__main__":
    install()
    from sphfem_cli.cli import main
    if DUMP:
        os.makedirs(DUMP, exist_ok=True)
    main(sys.argv[1:], prog_name="sphfem")
