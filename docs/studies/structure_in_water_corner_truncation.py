"""Study code (issue 12, docs/studies/structure_in_water.md "Convex corners"; not in the package): the truncated kernel's
uniform-pressure force at a structure's corners, made that of a flat face (2D).

Measuring code for issue 12 (no deck option: measured to put energy into the model, see below), applied to an
SPH-slave penalty contact by docs/studies/structure_in_water_corner_run.py. SPH's symmetric pressure
force on particle i (``sph.rates``), for a pressure that is uniform, p_j = p_i, is

    F_i^u = -m_i sum_j m_j (2 p_i / rho_i^2) grad_i W_ij = -(2 p_i / rho_i) m_i Gamma_i,
    Gamma_i = sum_j V_j grad_i W_ij = grad_i sum_j V_j W_ij      (V_j = m_j / rho_j),

zero where the kernel's support is complete and, where the structure cuts it, a push towards the structure
(Gamma_i points away from it). On a flat face it is normal and the penalty contact balances it (that balance is
the ambient pressure's preload on the wall). At a convex corner it is not: on a lattice the particles beside
the corner are pushed 0.198 p dx along the faces, away from it, which a frictionless contact cannot balance
(docs/studies/structure_in_water.md, "SPH's gap: ...").

Gamma_i is taken from the geometry alone, in the continuum (the particle sum also holds the lattice's own
restoring force, which must stay): with the fluid filling everything outside the structure,

    Gamma_i^s = -int_solid grad_i W(x_i - x') dV' = oint_surface W(x_i - x') n' dS'

(n' the structure's outward normal; the kernel vanishes on its support's edge; the boundary integral of
Kulasegaram et al. 2004, Comput. Mech. 33, 316), over the segments within 2 h_i by Gauss-Legendre quadrature
(``_w_line``). Next to an unbounded flat face at distance d it is g(d) n with g(d) = int W(sqrt(d^2 + u^2)) du.
This module adds to every fluid particle within 2 h_i of the surface

    F_i^c = (2 p_i / rho_i) m_i (Gamma_i^s - g(d_i) n_i),

d_i the distance to the surface and n_i the unit vector from its nearest point to x_i (the face's normal on a
face, the direction from the vertex beyond a corner; n_i = grad d_i outside a convex body). It is zero next to
a flat face (to the quadrature's error) and leaves there the flat face's normal push to the contact; near a
corner it takes out the difference. Gamma^s - g(d) n is the gradient of S^s(x) - G(d(x)) (S^s the
continuum kernel sum, G' = g), so at a uniform p the correction is a conservative force; a first form that took
out only the tangential part of Gamma^s (not a gradient) did the same on the paper's section 4.1 plate: both
put about twice the drive's work into the model as contact energy (study, "Convex corners"). -F_i^c goes to the nodes of the nearest segment with its linear weights, so fluid +
structure momentum is conserved to round-off; the forces are the contact's (their work is booked as contact
energy).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from sphfem_cli.sph.kernel_functions import kernel_w


@njit(cache=True)
def _nearest(px, py, xm, faces):
    """Nearest point of the segments to (px, py): (segment, parameter s in [0, 1], distance)."""
    best, best_s, best_d2 = -1, 0.0, np.inf
    for f in range(faces.shape[0]):
        a0, a1 = xm[faces[f, 0], 0], xm[faces[f, 0], 1]
        t0, t1 = xm[faces[f, 1], 0] - a0, xm[faces[f, 1], 1] - a1
        s = ((px - a0) * t0 + (py - a1) * t1) / (t0 * t0 + t1 * t1)
        s = min(1.0, max(0.0, s))
        d0, d1 = px - (a0 + s * t0), py - (a1 + s * t1)
        d2 = d0 * d0 + d1 * d1
        if d2 < best_d2:
            best, best_s, best_d2 = f, s, d2
    return best, best_s, math.sqrt(best_d2)


_GAUSS_X = np.array([-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526])
_GAUSS_W = np.array([0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538])
_SUB = 2  # sub-intervals of each piece (below)


@njit(cache=True)
def _w_line(d2, u_lo, u_hi, hi, kernel, gx_, gw_):
    """int W(sqrt(d2 + u^2), h_i) du over [u_lo, u_hi] (u along a line at distance sqrt(d2) from x_i, 0 at the
    perpendicular's foot), split where r = h_i (the cubic spline's pieces) and at u = 0 (the minimum of r), each
    piece by _SUB sub-intervals of Gauss-Legendre points."""
    if u_lo >= u_hi:
        return 0.0
    c1 = math.sqrt(max(hi * hi - d2, 0.0))
    br = np.empty(5)
    br[0], br[1], br[2], br[3], br[4] = u_lo, -c1, 0.0, c1, u_hi
    for k in range(5):
        br[k] = min(u_hi, max(u_lo, br[k]))
    br.sort()
    acc = 0.0
    for k in range(4):
        width = (br[k + 1] - br[k]) / _SUB
        for q in range(_SUB):
            for g in range(gx_.shape[0]):
                u = br[k] + width * (q + 0.5 * (gx_[g] + 1.0))
                acc += 0.5 * width * gw_[g] * kernel_w(kernel, 2, math.sqrt(d2 + u * u), hi)
    return acc


@njit(cache=True)
def surface_integral(px, py, hi, kernel, xm, faces, gx_, gw_):
    """Gamma^s = oint W(x_i - x', h_i) n' dS' over the segments (outward normal n' to the right of a -> b) within
    2 h_i: on each, the chord within the support by ``_w_line``."""
    ix = iy = 0.0
    for f in range(faces.shape[0]):
        a0, a1 = xm[faces[f, 0], 0], xm[faces[f, 0], 1]
        t0, t1 = xm[faces[f, 1], 0] - a0, xm[faces[f, 1], 1] - a1
        length = math.sqrt(t0 * t0 + t1 * t1)
        s0 = ((px - a0) * t0 + (py - a1) * t1) / (length * length)  # the perpendicular's foot, unclamped
        d0, d1 = px - (a0 + s0 * t0), py - (a1 + s0 * t1)
        d2 = d0 * d0 + d1 * d1
        if d2 >= 4.0 * hi * hi:
            continue
        c2 = math.sqrt(4.0 * hi * hi - d2)
        acc = _w_line(d2, max(-s0 * length, -c2), min((1.0 - s0) * length, c2), hi, kernel, gx_, gw_)
        ix += acc * t1 / length
        iy -= acc * t0 / length
    return ix, iy


@njit(cache=True)
def flat_integral(d, hi, kernel, gx_, gw_):
    """g(d) = int W(sqrt(d^2 + u^2), h_i) du over the whole line: |Gamma^s| next to an unbounded flat face at
    distance d (Gamma^s = g(d) n there)."""
    c2 = math.sqrt(max(4.0 * hi * hi - d * d, 0.0))
    return _w_line(d * d, -c2, c2, hi, kernel, gx_, gw_)


@njit(cache=True)
def corner_correction(near, x, h, m, rho, p, kernel, xm, faces, f_point, f_master):
    """F_i^c of the module's docstring on the particles ``near`` (indices into x); adds F_i^c to f_point[i] and
    -F_i^c to f_master at the nearest segment's nodes (weights 1 - s, s). Particles 2 h_i or more from the
    surface, or on it (distance 0: no n_i), are left alone."""
    for a in range(near.shape[0]):
        i = near[a]
        xi, yi, hi = x[i, 0], x[i, 1], h[i]
        seg, s, dist = _nearest(xi, yi, xm, faces)
        if seg < 0 or dist >= 2.0 * hi or dist == 0.0:
            continue
        gx, gy = surface_integral(xi, yi, hi, kernel, xm, faces, _GAUSS_X, _GAUSS_W)
        a0, a1 = xm[faces[seg, 0], 0], xm[faces[seg, 0], 1]
        b0, b1 = xm[faces[seg, 1], 0], xm[faces[seg, 1], 1]
        nx = (xi - (a0 + s * (b0 - a0))) / dist
        ny = (yi - (a1 + s * (b1 - a1))) / dist
        gf = flat_integral(dist, hi, kernel, _GAUSS_X, _GAUSS_W)
        c = 2.0 * p[i] / rho[i] * m[i]
        fx, fy = c * (gx - gf * nx), c * (gy - gf * ny)
        f_point[i, 0] += fx
        f_point[i, 1] += fy
        f_master[faces[seg, 0], 0] -= (1.0 - s) * fx
        f_master[faces[seg, 0], 1] -= (1.0 - s) * fy
        f_master[faces[seg, 1], 0] -= s * fx
        f_master[faces[seg, 1], 1] -= s * fy


def add_corner_correction(ps, mask: np.ndarray, x_nodes: np.ndarray, faces: np.ndarray, kernel: int,
                          f_point: np.ndarray, f_master: np.ndarray, pressure: float | None = None) -> None:
    """Select the slave particles (``mask``) within 2 h_max of the faces' bounding box, then call
    ``corner_correction`` with the particles' pressures p_i, or with one ``pressure`` for all (a uniform p:
    then, for a structure at rest, the correction is the gradient of a fixed potential)."""
    if not len(faces) or not mask.any():
        return
    used = x_nodes[np.unique(faces)]
    hmax = float(ps.h[mask].max())
    lo, hi = used.min(axis=0)[:2], used.max(axis=0)[:2]
    x = np.ascontiguousarray(ps.x[:, :2])
    inside = mask & np.all((x > lo - 2.0 * hmax) & (x < hi + 2.0 * hmax), axis=1)
    p = ps.p if pressure is None else np.full(len(ps.p), float(pressure))
    corner_correction(np.flatnonzero(inside), x, ps.h, ps.m, ps.rho, p, kernel,
                      np.ascontiguousarray(x_nodes[:, :2]), faces, f_point, f_master)
