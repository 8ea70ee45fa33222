"""Short NumPy versions of the SPH hot kernels, for the tests (dense all-pairs, small inputs only).

``rates_reference`` recomputes, from the particle state alone, what ``SphSystem.compute_rates``
computes with the numba kernels: EOS state, ghost particles, dummy-wall pressures, viscous stress,
and the continuity / momentum / energy / delta-SPH / XSPH rates. It follows the equations of
docs/theory/sph.md directly, with O(N^2) memory.
"""
from __future__ import annotations

import itertools

import numpy as np

from ..materials import kernels as mk
from ..materials import slots as ms
from .eos import density_from_pressure
from .kernel_functions import CUBIC_SPLINE, WENDLAND_C2, kernel_sigma


def kernel_w(kernel: int, dim: int, r, h):
    """W(r, h), vectorised (dim 2 or 3)."""
    q = np.asarray(r, dtype=float) / h
    if kernel == WENDLAND_C2:
        t = np.maximum(1.0 - 0.5 * q, 0.0)
        th = t**4 * (2.0 * q + 1.0)
    else:
        th = np.where(q < 1.0, 1.0 - 1.5 * q**2 + 0.75 * q**3, 0.25 * np.maximum(2.0 - q, 0.0) ** 3)
    return kernel_sigma(kernel, dim) / h**dim * th


def kernel_f(kernel: int, dim: int, r, h):
    """(1/r) dW/dr, vectorised (finite at r = 0)."""
    q = np.asarray(r, dtype=float) / h
    if kernel == WENDLAND_C2:
        t = np.maximum(1.0 - 0.5 * q, 0.0)
        d = -5.0 * t**3
    else:
        with np.errstate(divide="ignore", invalid="ignore"):
            d = np.where(q < 1.0, -3.0 + 2.25 * q, -0.75 * np.maximum(2.0 - q, 0.0) ** 2 / q)
    return kernel_sigma(kernel, dim) / h ** (dim + 2) * d


def neighbour_pairs(x: np.ndarray, h: np.ndarray) -> set[tuple[int, int]]:
    """All ordered pairs (i, j), i != j, with |x_i - x_j| < 2 h_ij = h_i + h_j (brute force)."""
    d = np.sqrt(((x[:, None, :] - x[None, :, :]) ** 2).sum(-1))
    close = d < h[:, None] + h[None, :]
    np.fill_diagonal(close, False)
    return set(zip(*map(lambda a: a.tolist(), np.nonzero(close))))


def ghosts(x, v, rho, p, c, walls, reach, gravity=None, hydrostatic=False):
    """Mirror particles: one per subset (one wall per axis) of the walls within ``reach``.

    Returns (positions (G, 3), free-slip velocities (G, 3), source index (G,), pressure (G,),
    density (G,), viscous velocities (G, 3)): the free-slip velocity mirrors the normal component
    through every wall; the viscous one reverses the whole vector at a no-slip wall.
    """
    n, dim = x.shape
    x3 = np.zeros((n, 3))
    v3 = np.zeros((n, 3))
    x3[:, :dim], v3[:, :dim] = x, v
    g = np.zeros(3) if gravity is None else np.asarray(gravity, float)
    out_x, out_v, out_vv, src, pg, rg = [], [], [], [], [], []
    for i in range(n):
        near = [w for w in walls if 0.0 <= w.side * (x3[i, w.axis] - w.position) < reach]
        for size in range(1, len(near) + 1):
            for sub in itertools.combinations(near, size):
                if len({w.axis for w in sub}) < size:
                    continue
                xg, vg, vv = x3[i].copy(), v3[i].copy(), v3[i].copy()
                for w in sub:
                    xg[w.axis] = 2.0 * w.position - xg[w.axis]
                    vg[w.axis] = -vg[w.axis]
                    if w.condition == "no_slip":
                        vv = -vv
                    else:
                        vv[w.axis] = -vv[w.axis]
                out_x.append(xg)
                out_v.append(vg)
                out_vv.append(vv)
                src.append(i)
                dp = rho[i] * g @ (xg - x3[i]) if hydrostatic else 0.0
                pg.append(p[i] + dp)
                rg.append(rho[i] + (dp / c[i] ** 2 if c[i] > 0.0 else 0.0))  # as walls.fill_ghosts
    return (np.array(out_x).reshape(-1, 3), np.array(out_v).reshape(-1, 3), np.array(src, dtype=int),
            np.array(pg), np.array(rg), np.array(out_vv).reshape(-1, 3))


def rates_reference(x, v, rho, e, m, mat, params, opt, wall=None):
    """Rates of the particle state (all particles active) with the options ``opt`` (SphOptions)
    and optional dummy walls ``wall`` = (positions, spacing, material).

    Returns dict with acc (N, dim), drho, de, xsph (N, dim), p, c, h.
    """
    n, dim = x.shape
    if any(w.condition == "non_reflecting" for w in opt.walls):
        raise ValueError("the reference rates have no non-reflecting open sides (sph.open_sides)")
    kern = {"cubic_spline": CUBIC_SPLINE, "wendland_c2": WENDLAND_C2}[opt.kernel]
    g = np.zeros(3)
    if opt.gravity is not None:
        g[:dim] = opt.gravity
    p = np.empty(n)
    c = np.empty(n)
    for i in range(n):
        row = params[mat[i]]
        rho0 = row[ms.P_RHO0]
        eos, q, r, ee = int(row[mk.P_EOS_TYPE]), row[mk.EOS_OFFSET:], rho[i] / rho0, rho0 * e[i]
        p[i] = max(mk.eos_pressure(eos, q, r, ee), opt.pressure_cutoff)
        c[i] = mk.eos_sound_speed(eos, q, r, ee)
    h = opt.smoothing_ratio * (m / rho) ** (1.0 / dim)
    hmax = h.max()

    # point set: fluid, ghosts, walls
    X = [np.pad(x, ((0, 0), (0, 3 - dim)))]
    V = [np.pad(v, ((0, 0), (0, 3 - dim)))]
    VV = [V[0]]  # velocities the viscous terms see
    R, M, P, C, H, MAT, KIND = [rho], [m], [p], [c], [h], [mat], [np.zeros(n, int)]
    if opt.walls:
        wr = max(hmax, opt.smoothing_ratio * wall[1]) if wall is not None else hmax
        gx, gv, gs, gp, gr, gvv = ghosts(x, v, rho, p, c, list(opt.walls), 2.0 * wr, g, opt.ghost_hydrostatic)
        X.append(gx)
        V.append(gv)
        VV.append(gvv)
        R.append(gr)
        M.append(m[gs])
        P.append(gp)
        C.append(c[gs])
        H.append(h[gs])
        MAT.append(mat[gs])
        KIND.append(np.ones(len(gs), int))
    if wall is not None:
        wx, spacing, wmat = wall
        nw = len(wx)
        wx3 = np.pad(np.asarray(wx, float), ((0, 0), (0, 3 - dim)))
        hw = np.full(nw, opt.smoothing_ratio * spacing)
        row = params[wmat]
        # Adami et al. 2012: p_w = (sum p_f W + g . sum rho_f r_wf W) / sum W over fluid f
        rwf = wx3[:, None, :] - X[0][None, :, :]
        W = kernel_w(kern, dim, np.sqrt((rwf**2).sum(-1)), 0.5 * (hw[:, None] + h[None, :]))
        sw = W.sum(1)
        pw = np.where(sw > 0, (W @ p + (rho[None, :, None] * rwf * W[:, :, None]).sum(1) @ g) / np.where(sw > 0, sw, 1), 0.0)
        pw = np.maximum(pw, opt.pressure_cutoff)
        eos, q, rho0 = int(row[mk.P_EOS_TYPE]), row[mk.EOS_OFFSET:], row[ms.P_RHO0]
        rw = np.array([density_from_pressure(eos, q, rho0, pp, q[ms.Q_E0], rho0) for pp in pw])
        cw = np.array([mk.eos_sound_speed(eos, q, r / rho0, q[ms.Q_E0]) for r in rw])
        X.append(wx3)
        V.append(np.zeros((nw, 3)))
        VV.append(np.zeros((nw, 3)))
        R.append(rw)
        M.append(np.full(nw, rho0 * spacing**dim))
        P.append(pw)
        C.append(cw)
        H.append(hw)
        MAT.append(np.full(nw, wmat))
        KIND.append(np.full(nw, 2))
    X, V, VV, R, M, P, C, H, MAT, KIND = map(np.concatenate, (X, V, VV, R, M, P, C, H, MAT, KIND))

    rij = X[:n, None, :] - X[None, :, :]  # fluid i, point j
    r = np.sqrt((rij**2).sum(-1))
    hij = 0.5 * (h[:, None] + H[None, :])
    inside = (r < 2.0 * hij) & (r > 0.0)
    F = np.where(inside, kernel_f(kern, dim, r, hij), 0.0)
    Wv = np.where(inside, kernel_w(kern, dim, r, hij), 0.0)
    gradW = F[:, :, None] * rij
    vij = V[:n, None, :] - V[None, :, :]
    vol = M / R

    # viscous stress at every point (needs the gradient at all points, fluid i -> all i)
    mu = params[MAT, ms.P_VISCOSITY]
    viscous = bool(np.any(params[:, ms.P_VISCOSITY] > 0) or opt.dilatational_viscosity > 0)
    if viscous:
        ra = X[:, None, :] - X[None, :, :]
        rr = np.sqrt((ra**2).sum(-1))
        ha = 0.5 * (H[:, None] + H[None, :])
        Fa = np.where((rr < 2 * ha) & (rr > 0), kernel_f(kern, dim, rr, ha), 0.0)
        L = np.einsum("j,ija,ijb->iab", vol, VV[None, :, :] - VV[:, None, :], Fa[:, :, None] * ra)
        D = 0.5 * (L + L.transpose(0, 2, 1))
        div = np.trace(L, axis1=1, axis2=2)
        tau = 2.0 * mu[:, None, None] * D + ((opt.dilatational_viscosity - 2.0 / 3.0 * mu) * div)[:, None, None] * np.eye(3)
    else:
        tau = np.zeros((len(X), 3, 3))

    cbar = 0.5 * (c[:, None] + C[None, :])
    rbar = 0.5 * (rho[:, None] + R[None, :])

    def monaghan(vel):
        mu_ij = hij * np.minimum(((vel * rij).sum(-1)), 0.0) / (r**2 + opt.eps * hij**2)
        return (-opt.alpha * cbar * mu_ij + opt.beta * mu_ij**2) / rbar

    Pi_slip = monaghan(vij)  # every pair as fluid_rates evaluates it
    Pi = monaghan(V[:n, None, :] - VV[None, :, :])  # no-slip ghosts: the viscous velocity
    S = (p / rho**2)[:, None] + (P / R**2)[None, :] + Pi  # pressure part, times -I
    T = tau[:n, None] / (rho**2)[:, None, None, None] + tau[None, :] / (R**2)[None, :, None, None]
    sig = -S[:, :, None, None] * np.eye(3) + T  # sigma_i/rho_i^2 + sigma_j/rho_j^2 - Pi I
    acc = np.einsum("j,ijab,ijb->ia", M, sig * inside[:, :, None, None], gradW)
    # energy: half of each pair's work, except what a ghost wall (at rest, no work) takes from i:
    # the viscous stress and the no-slip part of Pi put all of it into i's internal energy
    ghost = (KIND == 1)[None, :, None]
    vi = np.broadcast_to(V[:n, None, :], vij.shape)
    S_shared = (p / rho**2)[:, None] + (P / R**2)[None, :] + Pi_slip
    de = 0.5 * np.einsum("j,ij,ija,ija->i", M, S_shared * inside, vij, gradW)
    de += np.einsum("j,ij,ija,ija->i", M, (Pi - Pi_slip) * inside, vi, gradW)
    de -= 0.5 * np.einsum("j,ijab,ija,ijb->i", M, T * inside[:, :, None, None], np.where(ghost, 2.0 * vi, vij), gradW)
    drho = rho * np.einsum("j,ija,ija->i", vol, vij, gradW)
    if opt.delta:
        psi = R[None, :] - rho[:, None]
        if opt.delta_hydrostatic:
            c2 = cbar**2
            psi = psi + np.divide(rbar * (rij @ g), c2, out=np.zeros_like(c2), where=c2 > 0.0)
        same = (MAT[None, :] == mat[:, None]) & (KIND[None, :] != 2)
        drho = drho - 2.0 * opt.delta * np.sum(same * hij * cbar * psi * F * vol[None, :], axis=1)
    notwall = KIND[None, :] != 2
    xs = opt.xsph * np.einsum("ij,ija->ia", notwall * Wv * M[None, :] / rbar, -vij)
    return {"acc": acc[:, :dim], "drho": drho, "de": de, "xsph": xs[:, :dim], "p": p, "c": c, "h": h}
