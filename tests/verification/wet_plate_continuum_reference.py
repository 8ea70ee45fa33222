"""The plate of decks/structure_in_water_*.yaml as a plane-strain continuum in linear acoustic water.

The independent reference of docs/studies/structure_in_water.md ("An independent continuum
reference"), computed without either solver: wet_plate_reference.py with its Timoshenko beam replaced
by a 2D linear-elastic solid, so that the plate's own modelling error (the beam's 0.4115 mm dry peak
against a continuum converging below it) no longer limits the comparison. The scene, the water's
acoustic elements, the drive and the gauges are those of wet_plate_reference.py (imported, not copied).

Plate (x = 0.20..0.21 m, y = 0.05..0.20 m; E = 70 GPa, nu = 0.33, rho_s = 2700 kg/m^3), plane strain,
small displacement u = (u_x, u_y): M_s u'' + K_s u = f, K_s = int B^T D B dA, M_s = int rho_s N^T N dA,
D the plane-strain elasticity (lambda + 2 mu, lambda; mu). Structured mesh of nx (through the
thickness) x ny (along) rectangles; ``element``:

- ``q9``: the 9-node Lagrange quadrilateral, biquadratic, full 3 x 3 Gauss integration, consistent
  mass (Zienkiewicz, Taylor & Zhu, *The Finite Element Method: its Basis and Fundamentals*, 7th ed.,
  2013, sec. 6.3-6.5; Hughes, *The Finite Element Method*, 1987, sec. 3.7). On rectangles it
  represents a linearly varying bending moment exactly (quadratic u_x along y), so it does not
  shear-lock and converges fast in bending; the reference's element.
- ``q4r``: the solvers' quad4 (sphfem_cli/fem/kernels.py) linearised: one-point (centroid) B,
  K = A B0^T D B0, plus Flanagan-Belytschko (1981) stiffness hourglass control per component
  K_hg = k gamma gamma^T, k = QM G A |b|^2 / 2, gamma = (1, -1, 1, -1) on a rectangle (counter-
  clockwise corners), QM = 0.1 (the decks' section ``plate``); row-sum lumped mass rho_s A / 4 per
  node. It lacks the solver's bulk viscosity (one-sided, in compression only; not linear).

Boundary conditions as in the decks: the top face's nodes (y = 0.2) fixed in x and y, the bottom
face's nodes (y = 0.05) moved in x as the decks' drive (``wet_plate_reference.drive_state``), free in
y; after the pulse they are held in x (pinned-like, but the whole end face held in x).

Water: the acoustic pressure p of wet_plate_reference.fluid (bilinear elements of size hf, closed
rigid tank, c = sqrt(2.2e9 / 1000)), M_f p'' + K_f p + rho Q u'' = 0, on the three wetted faces of the
plate (left x = 0.2, right x = 0.21 and the bottom end y = 0.05, which now moves in y through Poisson
and bending); the plate is loaded by Q^T p (Everstine 1981, J. Sound Vib. 79, 157; Morand & Ohayon
1995, ch. 5-8):

    Q_{k,(i,d)} = int_faces phi_k N_i n_d ds,

phi_k the fluid's hat at node k, N_i the plate's shape function at face node i (quadratic on q9 edges,
linear on q4r), n the fluid's outward normal (+x on the left face, -x on the right, +y on the bottom
face). The meshes need not match: the fluid and plate nodes along a face are merged into one set of
break points and each piece integrated with 3-point Gauss, exact for the products (degree <= 3), so
the coupling is conforming at any pair hf / plate mesh (Q appears transposed in both equations: the
coupled system conserves energy). The plate's faces lie on fluid grid lines (hf divides 5 mm).

Linear, small motion about rest: the ambient pressure (1 MPa in the decks) is a uniform p0 in
equilibrium with a uniform compression of the plate, which a linear model superposes on the
dynamic solution unchanged: it cancels and is left out (p here is the dynamic pressure; add p0 to
compare with the solvers' absolute pressures).

Time integration: Newmark's average acceleration (gamma 1/2, beta 1/4) of the coupled system
[M_s 0; rho Q M_f] z'' + [K_s -Q^T; 0 K_f] z = F(t), z = (u_free, p), the driven x dofs entering as
known u_b, u_b'' (F = -M_ub a_b - K_ub u_b); the effective matrix M + beta dt^2 K (non-symmetric,
sparse) factorised once by scipy.sparse.linalg.splu.

Energy (free vibration): with pi = int p dt (rho v_fluid = -grad pi), the coupled system conserves
E = u'^T M_s u' / 2 + u^T K_s u / 2 + (p^T M_f p + pi^T K_f pi) / (2 rho), the plate's kinetic and
strain energy plus the water's compression p^2 / (2 rho c^2) and kinetic rho v^2 / 2 energy.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import wet_plate_reference as wpr

E, NU, RHO_S, RHO_F = wpr.E, wpr.NU, wpr.RHO_S, wpr.RHO_F
X0, X1, Y0, Y1 = wpr.PLATE
E_PLANE = E / (1.0 - NU * NU)
HG_COEF = 0.1  # the decks' section plate: hourglass {type: stiffness, coefficient: 0.1}

_G3 = (np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)]), np.array([5.0, 8.0, 5.0]) / 9.0)


def _lagrange(nodes: np.ndarray, s: float) -> tuple[np.ndarray, np.ndarray]:
    """1D Lagrange shape functions on ``nodes`` and their derivatives at s."""
    n = len(nodes)
    v, d = np.ones(n), np.zeros(n)
    for a in range(n):
        for b in range(n):
            if b == a:
                continue
            v[a] *= (s - nodes[b]) / (nodes[a] - nodes[b])
            term = 1.0 / (nodes[a] - nodes[b])
            for c in range(n):
                if c not in (a, b):
                    term *= (s - nodes[c]) / (nodes[a] - nodes[c])
            d[a] += term
    return v, d


def elasticity(modulus: float = E, nu: float = NU) -> np.ndarray:
    """Plane-strain D for (eps_xx, eps_yy, gamma_xy)."""
    lam = modulus * nu / ((1 + nu) * (1 - 2 * nu))
    mu = modulus / (2 * (1 + nu))
    return np.array([[lam + 2 * mu, lam, 0.0], [lam, lam + 2 * mu, 0.0], [0.0, 0.0, mu]])


def _element_q9(hx: float, hy: float, D: np.ndarray, rho: float):
    """K, M (18 x 18, dofs (node, comp), nodes a + 3 b for a, b = 0..2 along x, y) of a q9 rectangle."""
    loc = np.array([-1.0, 0.0, 1.0])
    K, M = np.zeros((18, 18)), np.zeros((18, 18))
    g, w = _G3
    for xi, wx in zip(g, w):
        nx_, dx_ = _lagrange(loc, xi)
        for eta, wy in zip(g, w):
            ny_, dy_ = _lagrange(loc, eta)
            N = np.outer(ny_, nx_).ravel()                  # index 3 b + a
            Nx = np.outer(ny_, dx_).ravel() * 2.0 / hx
            Ny = np.outer(dy_, nx_).ravel() * 2.0 / hy
            B = np.zeros((3, 18))
            B[0, 0::2], B[1, 1::2] = Nx, Ny
            B[2, 0::2], B[2, 1::2] = Ny, Nx
            jw = wx * wy * hx * hy / 4.0
            K += jw * B.T @ D @ B
            Nm = np.zeros((2, 18))
            Nm[0, 0::2], Nm[1, 1::2] = N, N
            M += jw * rho * Nm.T @ Nm
    return K, M


def _element_q4r(hx: float, hy: float, D: np.ndarray, rho: float, modulus: float, nu: float,
                 qm: float = HG_COEF):
    """K, M (8 x 8, nodes a + 2 b) of the solvers' one-point quad4 with stiffness hourglass control."""
    area = hx * hy
    # counter-clockwise corners (0,0), (1,0), (1,1), (0,1) as (a, b); gamma = (1, -1, 1, -1) on them
    ccw = [(0, 0), (1, 0), (1, 1), (0, 1)]
    idx = [a + 2 * b for a, b in ccw]
    xi = np.array([-1.0, 1.0, 1.0, -1.0])
    eta = np.array([-1.0, -1.0, 1.0, 1.0])
    bx, by = xi / (2 * hx), eta / (2 * hy)
    B = np.zeros((3, 8))
    for k, n in enumerate(idx):
        B[0, 2 * n], B[1, 2 * n + 1] = bx[k], by[k]
        B[2, 2 * n], B[2, 2 * n + 1] = by[k], bx[k]
    K = area * B.T @ D @ B
    gam = np.zeros(4)
    gam[idx] = [1.0, -1.0, 1.0, -1.0]
    coef = 0.5 * qm * modulus / (2 * (1 + nu)) * area * float(np.sum(bx ** 2 + by ** 2))
    for c in range(2):
        K[c::2, c::2] += coef * np.outer(gam, gam)
    M = np.eye(8) * rho * area / 4.0
    return K, M


@dataclass
class Plate:
    """The plate's FE model: nodes on a (mx x my) grid, node i + mx j at (xs[i], ys[j]); dof 2 n + d."""

    element: str
    xs: np.ndarray
    ys: np.ndarray
    K: sp.csr_matrix
    M: sp.csr_matrix
    fixed: np.ndarray     # the top face's x and y dofs
    driven: np.ndarray    # the bottom face's x dofs
    free: np.ndarray      # the rest (unknowns)
    order: int            # polynomial degree along an edge (2: q9, 1: q4r)

    def node(self, x: float, y: float) -> int:
        """The node at (x, y) (must be one)."""
        i = int(np.argmin(np.abs(self.xs - x)))
        j = int(np.argmin(np.abs(self.ys - y)))
        if abs(self.xs[i] - x) > 1e-9 or abs(self.ys[j] - y) > 1e-9:
            raise ValueError(f"({x}, {y}) is not a node of the {len(self.xs)} x {len(self.ys)} plate grid")
        return i + len(self.xs) * j


def plate(nx: int = 4, ny: int = 60, element: str = "q9", modulus: float = E, nu: float = NU,
          rho: float = RHO_S, qm: float = HG_COEF, x0: float = X0, x1: float = X1, y0: float = Y0,
          y1: float = Y1) -> Plate:
    """The plate of nx x ny ``element`` (q9 or q4r) rectangles; top clamped, bottom driven in x."""
    order = {"q9": 2, "q4r": 1}[element]
    hx, hy = (x1 - x0) / nx, (y1 - y0) / ny
    D = elasticity(modulus, nu)
    ke, me = (_element_q9(hx, hy, D, rho) if order == 2 else _element_q4r(hx, hy, D, rho, modulus, nu, qm))
    mx, my = order * nx + 1, order * ny + 1
    xs, ys = np.linspace(x0, x1, mx), np.linspace(y0, y1, my)
    a, b = np.meshgrid(np.arange(order + 1), np.arange(order + 1))
    loc = (a + mx * b).ravel()                    # local node a + (order + 1) b -> offset in the grid
    ei, ej = np.meshgrid(np.arange(nx), np.arange(ny))
    base = (order * ei + mx * order * ej).ravel()
    nodes = base[:, None] + loc[None, :]          # (elements, nodes per element)
    dofs = np.stack([2 * nodes, 2 * nodes + 1], axis=2).reshape(len(base), -1)
    rows = np.repeat(dofs, dofs.shape[1], axis=1).ravel()
    cols = np.tile(dofs, (1, dofs.shape[1])).ravel()
    n = 2 * mx * my
    K = sp.csr_matrix((np.tile(ke.ravel(), len(base)), (rows, cols)), shape=(n, n))
    M = sp.csr_matrix((np.tile(me.ravel(), len(base)), (rows, cols)), shape=(n, n))
    top = np.arange(mx) + mx * (my - 1)
    fixed = np.sort(np.concatenate([2 * top, 2 * top + 1]))
    driven = 2 * np.arange(mx)
    free = np.setdiff1d(np.arange(n), np.concatenate([fixed, driven]))
    return Plate(element, xs, ys, K, M, fixed, driven, free, order)


def _faces(pl: Plate, fl: wpr.Fluid):
    """Per wetted face: (plate face nodes, their coordinate s along the face, the normal's component d,
    its sign, the fluid's global node indices on the face, their s)."""
    mx, my = len(pl.xs), len(pl.ys)
    off = np.concatenate([[0], np.cumsum([len(c) for c in fl.cols])]).astype(int)
    hf = fl.hf
    jy0 = round(Y0 / hf)
    out = []
    for (ix, yf, rows), i_pl, sign in ((fl.face_left, 0, 1.0), (fl.face_right, mx - 1, -1.0)):
        out.append((i_pl + mx * np.arange(my), pl.ys, 0, sign, off[ix] + rows, yf))
    ix0, ix1 = round(X0 / hf), round(X1 / hf)
    gidx = np.array([off[i] + int(np.searchsorted(fl.cols[i], jy0)) for i in range(ix0, ix1 + 1)])
    out.append((np.arange(mx), pl.xs, 1, 1.0, gidx, np.arange(ix0, ix1 + 1) * hf))
    return out


def coupling(pl: Plate, fl: wpr.Fluid) -> sp.csr_matrix:
    """Q (fluid nodes x plate dofs): int phi_k N_i n_d ds over the three wetted faces."""
    nf = sum(len(c) for c in fl.cols)
    rows, cols, vals = [], [], []
    g, w = _G3
    for nodes, s_pl, d, sign, gidx, s_fl in _faces(pl, fl):
        blk = np.zeros((len(gidx), len(nodes)))
        for e in range(0, len(s_pl) - 1, pl.order):   # the plate's edges, order + 1 nodes each
            en = s_pl[e:e + pl.order + 1]
            cuts = np.union1d([en[0], en[-1]], s_fl[(s_fl > en[0]) & (s_fl < en[-1])])
            for a, b in zip(cuts[:-1], cuts[1:]):
                for gq, wq in zip(g, w):
                    s = 0.5 * (a + b) + 0.5 * (b - a) * gq
                    shape, _ = _lagrange(en, s)
                    blk[:, e:e + pl.order + 1] += 0.5 * (b - a) * wq * np.outer(wpr.hats(s_fl, s), shape)
        r, c = np.nonzero(blk)
        rows.append(gidx[r]), cols.append(2 * nodes[c] + d), vals.append(sign * blk[r, c])
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(nf, pl.K.shape[0]))


@dataclass
class Response:
    t: np.ndarray
    w_mid: np.ndarray       # m, u_x of the right face's node at y_mid (the decks' history ``mid``)
    v_mid: np.ndarray       # m/s
    gauges: dict            # Pa, {(y_a, y_b): E' (eps_right - eps_left) / 2}, wpr.GAUGES
    p_range: np.ndarray     # Pa, (min, max) of the dynamic pressure over the run
    energy: np.ndarray      # J/m, E of the module docstring at each step
    corner: np.ndarray = None  # Pa, (steps + 1, 3): dynamic p at the fluid node on the plate's lower left
    #                            corner (0.2, 0.05), and the min and max within ``corner_r`` of it
    n_dofs: tuple = ()      # (plate unknowns, fluid nodes)


def driven_response(nx: int = 4, ny: int = 60, hf: float = 0.005, dt: float = 2e-6, end: float = 3e-3,
                    element: str = "q9", wet: bool = True, y_mid: float = 0.125, drive: bool = True,
                    u0: np.ndarray | None = None, corner_r: float = 0.012, c: float = wpr.C_F) -> Response:
    """The plate's response to the decks' drive (``drive`` False and ``u0`` given: free vibration from
    the plate displacement u0, over all plate dofs, with the driven dofs held at 0)."""
    pl = plate(nx, ny, element)
    f, bdofs = pl.free, pl.driven
    Ks, Ms = pl.K.tocsc(), pl.M.tocsc()
    if wet:
        fl = wpr.fluid(hf, "rigid", c)
        Kf, Mf, _Cf, _off = wpr.fluid_global(fl)
        Q = coupling(pl, fl).tocsc()
        nfl = Kf.shape[0]
    else:
        nfl = 0
    ns = len(f)
    blocks_M = [[Ms[f][:, f], None], [RHO_F * Q[:, f], Mf]] if wet else [[Ms[f][:, f]]]
    blocks_K = [[Ks[f][:, f], -Q[:, f].T], [None, Kf]] if wet else [[Ks[f][:, f]]]
    M = sp.bmat(blocks_M, format="csc")
    K = sp.bmat(blocks_K, format="csc")
    ones = np.ones(len(bdofs))
    Mb = np.concatenate([Ms[f][:, bdofs] @ ones] + ([RHO_F * (Q[:, bdofs] @ ones)] if wet else []))
    Kb = np.concatenate([Ks[f][:, bdofs] @ ones] + ([np.zeros(nfl)] if wet else []))
    beta, gamma = 0.25, 0.5
    lu = spla.splu((M + beta * dt * dt * K).tocsc())
    n = ns + nfl
    x, v, a = np.zeros(n), np.zeros(n), np.zeros(n)
    if u0 is not None:
        x[:ns] = u0[f]
        a = spla.spsolve(M, -(K @ x))  # at rest: M a0 = -K x0
    k_mid = int(np.flatnonzero(f == 2 * pl.node(X1, y_mid))[0])
    # gauges: u_y of the face nodes (the clamp's, y = 0.2, are fixed: 0)
    gy = {}
    for xf in (X0, X1):
        for yy in {y for pair in wpr.GAUGES for y in pair}:
            dof = 2 * pl.node(xf, yy) + 1
            hit = np.flatnonzero(f == dof)
            gy[(xf, yy)] = int(hit[0]) if len(hit) else None
    n_pl = Ks.shape[0]
    drv = [0.0, 0.0]  # the driven dofs' displacement and velocity now
    if wet:
        xy = np.array([(i * hf, j * hf) for i, js in enumerate(fl.cols) for j in js])
        dist = np.hypot(xy[:, 0] - X0, xy[:, 1] - Y0)
        near, at = np.flatnonzero(dist <= corner_r + 1e-12), int(np.argmin(dist))
    pi = np.zeros(nfl)
    steps = int(round(end / dt))
    t_out = np.arange(steps + 1) * dt
    w_out, v_out, e_out = np.zeros(steps + 1), np.zeros(steps + 1), np.zeros(steps + 1)
    g_out = {g: np.zeros(steps + 1) for g in wpr.GAUGES}
    p_lo = p_hi = 0.0
    corner = np.zeros((steps + 1, 3))

    def uy(key):
        return 0.0 if gy[key] is None else x[gy[key]]

    def record(k):
        w_out[k], v_out[k] = x[k_mid], v[k_mid]
        for ya, yb in wpr.GAUGES:
            eps = [(uy((xf, yb)) - uy((xf, ya))) / (yb - ya) for xf in (X1, X0)]
            g_out[(ya, yb)][k] = 0.5 * E_PLANE * (eps[0] - eps[1])
        us, vs = np.zeros(n_pl), np.zeros(n_pl)  # every plate dof: the driven ones' motion counts
        us[f], vs[f] = x[:ns], v[:ns]
        us[bdofs], vs[bdofs] = drv[0], drv[1]
        en = 0.5 * vs @ (Ms @ vs) + 0.5 * us @ (Ks @ us)
        if wet:
            p = x[ns:]
            en += (0.5 * p @ (Mf @ p) + 0.5 * pi @ (Kf @ pi)) / RHO_F
        e_out[k] = en

    record(0)
    for k in range(1, steps + 1):
        t = k * dt
        ub, vb, ab = wpr.drive_state(t) if drive else (0.0, 0.0, 0.0)
        drv[:] = ub, vb
        xp = x + dt * v + (0.5 - beta) * dt * dt * a
        vp = v + (1 - gamma) * dt * a
        p_old = x[ns:].copy()
        a = lu.solve(-Mb * ab - Kb * ub - K @ xp)
        x = xp + beta * dt * dt * a
        v = vp + gamma * dt * a
        if wet:
            pi += 0.5 * dt * (p_old + x[ns:])
            p_lo, p_hi = min(p_lo, float(x[ns:].min())), max(p_hi, float(x[ns:].max()))
            pc = x[ns + near]
            corner[k] = x[ns + at], pc.min(), pc.max()
        record(k)
    return Response(t_out, w_out, v_out, g_out, np.array([p_lo, p_hi]), e_out, corner, (ns, nfl))


def wet_frequency(nx: int = 2, ny: int = 30, hf: float = 0.01, element: str = "q9", wet: bool = True,
                  guess: float = 450.0) -> float:
    """The plate's first natural frequency [Hz] in the closed tank (``wet`` False: in vacuum), the bottom
    face held in x as after the pulse: the eigenvalue of K z = omega^2 M z (the coupled matrices of
    ``driven_response``) nearest (2 pi guess)^2, by shift-invert (operator (K - s M)^-1 M)."""
    pl = plate(nx, ny, element)
    f = pl.free
    Ks, Ms = pl.K.tocsc()[f][:, f], pl.M.tocsc()[f][:, f]
    if wet:
        fl = wpr.fluid(hf, "rigid")
        Kf, Mf, _Cf, _off = wpr.fluid_global(fl)
        Q = coupling(pl, fl).tocsc()[:, f]
        M = sp.bmat([[Ms, None], [RHO_F * Q, Mf]], format="csc")
        K = sp.bmat([[Ks, -Q.T], [None, Kf]], format="csc")
    else:
        M, K = Ms, Ks
    s = (2 * np.pi * guess) ** 2
    lu = spla.splu((K - s * M).tocsc())
    op = spla.LinearOperator(K.shape, matvec=lambda z: lu.solve(M @ z), dtype=float)
    mu = spla.eigs(op, k=3, which="LM", return_eigenvectors=False)
    lam = s + 1.0 / mu
    lam = lam[np.argmin(np.abs(lam - s))]
    return float(np.sqrt(lam.real) / (2 * np.pi))
