"""Shared set-ups of the ALE verification tests: gas rows, shock tubes, exact Riemann solution."""
from __future__ import annotations

import numpy as np

from sphfem_cli.ale import AleOptions, AleSystem, fill_fractions
from sphfem_cli.materials.tables import gas_row
from sphfem_cli.model.mesh import box_mesh


def box_walls(ale: AleSystem, nodes: np.ndarray, lo, hi, tol: float = 1e-12) -> None:
    """Slip walls on the four sides of a box mesh (corners fixed)."""
    for axis in range(2):
        normal = np.eye(2)[axis]
        ale.set_slip(np.flatnonzero(np.abs(nodes[:, axis] - lo[axis]) < tol), normal)
        ale.set_slip(np.flatnonzero(np.abs(nodes[:, axis] - hi[axis]) < tol), normal)


def shock_tube(n: int, length: float, x_diaphragm: float, left: tuple, right: tuple, two_materials: bool,
               options: AleOptions | None = None) -> AleSystem:
    """Quasi-1D tube, n x 1 quad4, slip walls all round; left/right = (row, rho, p)."""
    h = length / n
    mesh = box_mesh([0.0, 0.0], [length, h], divisions=[n, 1])
    nodes, conn = mesh.nodes, mesh.elements
    f_left = fill_fractions(nodes, conn, lambda x, y: x < x_diaphragm)
    if two_materials:
        mats = [left[0], right[0]]
        fr = np.stack([f_left, 1.0 - f_left], axis=1)
        ale = AleSystem(nodes, conn, mats, fr, [left[1], right[1]], pressure=[left[2], right[2]], options=options)
    else:
        rho = np.where(f_left > 0.5, left[1], right[1])[:, None]
        pr = np.where(f_left > 0.5, left[2], right[2])[:, None]
        ale = AleSystem(nodes, conn, [left[0]], np.ones((n, 1)), rho, pressure=pr, options=options)
    box_walls(ale, nodes, (0.0, 0.0), (length, h), tol=1e-9 * length)
    return ale


def run_to(ale: AleSystem, t_end: float, cfl: float = 0.5) -> AleSystem:
    while ale.time < t_end * (1.0 - 1e-12):
        ale.step(min(ale.stable_dt(cfl), t_end - ale.time))
    return ale


def sod(n: int, options: AleOptions | None = None, two_materials: bool = False) -> AleSystem:
    g = gas_row(1.4, 1.0)
    two = two_materials
    right_row = gas_row(1.4, 0.125) if two else g
    return run_to(shock_tube(n, 1.0, 0.5, (g, 1.0, 1.0), (right_row, 0.125, 0.1), two, options), 0.2)


# ------------------------------------------------------------------ exact Riemann solution (Toro ch. 4)


def _f_k(p, rho, pk, ck, gam, pinf):
    """Toro's pressure function for a stiffened gas (p -> p + p_inf)."""
    a_k = 2.0 / ((gam + 1.0) * rho)
    b_k = (gam - 1.0) / (gam + 1.0) * (pk + pinf)
    if p > pk:
        return (p - pk) * np.sqrt(a_k / (p + pinf + b_k))
    return 2.0 * ck / (gam - 1.0) * (((p + pinf) / (pk + pinf)) ** ((gam - 1.0) / (2.0 * gam)) - 1.0)


def riemann_star(wl, wr):
    """(p*, u*) of the Riemann problem between states w = (rho, u, p, gamma, p_inf), by bisection."""
    rl, ul, pl, gl, pil = wl
    rr, ur, pr, gr, pir = wr
    cl = np.sqrt(gl * (pl + pil) / rl)
    cr = np.sqrt(gr * (pr + pir) / rr)

    def fun(p):
        return _f_k(p, rl, pl, cl, gl, pil) + _f_k(p, rr, pr, cr, gr, pir) + ur - ul

    lo = -min(pil, pir) + 1e-12 * max(pl, pr)
    hi = 10.0 * max(pl, pr) + 10.0 * max(pil, pir)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if fun(mid) > 0.0:
            hi = mid
        else:
            lo = mid
    p = 0.5 * (lo + hi)
    u = 0.5 * (ul + ur) + 0.5 * (_f_k(p, rr, pr, cr, gr, pir) - _f_k(p, rl, pl, cl, gl, pil))
    return p, u


def riemann_sample(wl, wr, x, x0, t):
    """Exact (rho, u, p) at points x for the Riemann problem with the jump at x0 (Toro 4.5)."""
    ps, us = riemann_star(wl, wr)
    out = np.zeros((3, len(x)))
    for i, xi in enumerate(np.asarray(x)):
        s = (xi - x0) / t
        if s <= us:
            rho, u, p, g, pinf = wl
            sign = 1.0
        else:
            rho, u, p, g, pinf = wr
            sign = -1.0
        c = np.sqrt(g * (p + pinf) / rho)
        gm = (g - 1.0) / (g + 1.0)
        if ps > p:  # shock
            rs = rho * ((ps + pinf) / (p + pinf) + gm) / (gm * (ps + pinf) / (p + pinf) + 1.0)
            sh = u - sign * c * np.sqrt((g + 1.0) / (2.0 * g) * (ps + pinf) / (p + pinf) + (g - 1.0) / (2.0 * g))
            behind = (s > sh) if sign > 0 else (s < sh)
            out[:, i] = (rs, us, ps) if behind else (rho, u, p)
        else:  # rarefaction
            rs = rho * ((ps + pinf) / (p + pinf)) ** (1.0 / g)
            cs = np.sqrt(g * (ps + pinf) / rs)
            head = u - sign * c
            tail = us - sign * cs
            if (sign > 0 and s <= head) or (sign < 0 and s >= head):
                out[:, i] = (rho, u, p)
            elif (sign > 0 and s >= tail) or (sign < 0 and s <= tail):
                out[:, i] = (rs, us, ps)
            else:
                uu = 2.0 / (g + 1.0) * (sign * c + (g - 1.0) / 2.0 * u + s)
                cc = sign * (uu - s)
                rr = rho * (cc / c) ** (2.0 / (g - 1.0))
                pp = (p + pinf) * (cc / c) ** (2.0 * g / (g - 1.0)) - pinf
                out[:, i] = (rr, uu, pp)
    return out


NOH_GAMMA = 5.0 / 3.0


def noh_rz(n: int, t_end: float = 0.6, side: float = 1.0, axisymmetric: bool = True) -> dict:
    """Noh's implosion (Noh 1987, J. Comput. Phys. 72, 78-120) on an n x n Eulerian mesh of [0, side]^2.

    axisymmetric True: the spherical problem in r-z (x = r, y = z), the axis slipping (AleSystem) and
    z = 0 a slip symmetry plane; False: the cylindrical one in x-y, x = 0 and y = 0 slip planes. Cold
    ideal gas (gamma 5/3, rho 1, e 0) moving at unit speed towards the origin; r = side and z = side
    are transmitting faces (zero gradient: the inflowing gas a copy of the boundary element). Exact
    at time t, with k = 2 (spherical) or 1 (cylindrical): a shock at R = t/3, density
    ((gamma + 1)/(gamma - 1))^(k + 1) = 64 (16) behind it, (1 + t / R)^k ahead of it. The gas that
    reaches the shock by t_end = 0.6 started inside R = 0.8, untouched by the boundary (which the
    cold gas, at rest sound speed 0, hears only by the flow: R > side - t).

    Returns centroid radii R, mixture density, the exact density, meridian areas, ring (or plane)
    volumes, the step count, the centroids (E, 2) and the specific internal energy (exact: u0^2 / 2 = 0.5
    behind the shock, 0 ahead of it).
    """
    mesh = box_mesh([0.0, 0.0], [side, side], divisions=[n, n])
    x, conn = mesh.nodes.copy(), mesh.elements
    radius = np.hypot(x[:, 0], x[:, 1])
    v = np.zeros_like(x)
    inside = radius > 0.0
    v[inside] = -x[inside] / radius[inside, None]
    ale = AleSystem(x, conn, [gas_row(NOH_GAMMA, 1.0)], np.ones((len(conn), 1)), [1.0], energy=[0.0], velocity=v,
                    options=AleOptions(), axisymmetric=axisymmetric)
    ale.set_slip(np.flatnonzero(x[:, 1] == 0.0), (0.0, 1.0))
    if not axisymmetric:
        ale.set_slip(np.flatnonzero(x[:, 0] == 0.0), (1.0, 0.0))
    ale.set_transmit(np.flatnonzero((x[:, 0] == side) | (x[:, 1] == side)))
    run_to(ale, t_end)
    c = ale.centroids()
    rc = np.hypot(c[:, 0], c[:, 1])
    k = 2 if axisymmetric else 1
    g = NOH_GAMMA
    exact = np.where(rc < t_end / 3.0, ((g + 1.0) / (g - 1.0)) ** (k + 1), (1.0 + t_end / rc) ** k)
    p = ale.x[conn]
    area = 0.5 * ((p[:, 2, 0] - p[:, 0, 0]) * (p[:, 3, 1] - p[:, 1, 1]) - (p[:, 2, 1] - p[:, 0, 1]) * (p[:, 3, 0] - p[:, 1, 0]))
    return dict(radius=rc, density=ale.mixture_density(), exact=exact, area=area, volume=ale.vol_m.sum(axis=1),
                steps=ale.n_steps, centroid=c, energy=ale.ener_m.sum(axis=1) / ale.mass_m.sum(axis=1))


def noh_l1(case: dict, r_min: float = 0.1, r_max: float = 0.4, weight: str = "area") -> float:
    """L1 density error over r_min < R < r_max (outside the wall-heating zone R < r_min and the gas the
    boundary reached), mean |rho - rho_exact| weighted by meridian area or by volume."""
    sel = (case["radius"] > r_min) & (case["radius"] < r_max)
    w = case[weight][sel]
    return float((np.abs(case["density"] - case["exact"])[sel] * w).sum() / w.sum())
