"""Wet natural frequency of the plate of decks/structure_in_water_*.yaml, computed without either solver.

The scene (paper section 4.1, dimensions chosen in decks/structure_in_water_ale.yaml): a plate
x = 0.20..0.21 m, y = 0.05..0.20 m (length L = 0.15 m, thickness t = 0.01 m; aluminium E = 70 GPa,
nu = 0.33, rho_s = 2700 kg/m^3; plane strain) hanging from the top of a water tank x = 0..0.4 m,
y = 0..0.2 m (rho = 1000 kg/m^3, c = 1483 m/s), rigid top, left and bottom. After its drive pulse
the plate's top is clamped and its bottom held in x (y and rotation free): a clamped-pinned beam.

Model (linear, small motion about rest; a coupled structural-acoustic eigenproblem, e.g. Zienkiewicz
& Taylor, *The Finite Element Method*, vol. 1, ch. "Coupled systems"; Everstine 1981, J. Sound Vib.
79, 157-160; Morand & Ohayon, *Fluid-Structure Interaction*, Wiley 1995, ch. 5-8):

- Structure: Timoshenko beam along y (lateral deflection w(y), rotation theta(y)), plane strain
  E' = E/(1 - nu^2), EI = E' t^3/12, kappa G A = (5/6) G t, G = E/(2(1 + nu)); two-node elements,
  bending exact, shear with one-point (reduced) integration, consistent mass rho_s t (w) and
  rho_s t^3/12 (theta). Clamped at y = 0.2 (w = theta = 0), pinned at y = 0.05 (w = 0).
- Fluid: acoustic pressure p, del^2 p - p_tt / c^2 = 0 on the tank less the plate, bilinear
  quadrilaterals on a square grid of spacing hf: K_f = int grad N grad N, M_f = int N N / c^2.
  Rigid walls and the plate's bottom face (it moves tangentially): dp/dn = 0. On the plate's two
  long faces dp/dn = -rho w_tt (n_f . e_x), n_f the fluid's outward normal (+x on the left face,
  -x on the right one); the fluid pushes the plate with p n_f. Far side x = 0.4 m, one of:
  ``rigid`` (a wall, dp/dn = 0), ``release`` (p = 0, a free surface at ambient pressure),
  ``radiation`` (plane-wave impedance dp/dn = -p_t / c, exact for the channel's plane mode, whose
  higher modes are cut off below c/(2 H) = 3.7 kHz).
- Coupling: Q_ki = int phi_k N_i (n_f . e_x) ds over the two faces. Harmonic e^{i omega t}:
  (K_s - omega^2 [M_s + M_a(omega)]) u = 0, M_a = rho Q A^-1 Q^T, A = K_f + i omega C_f - omega^2 M_f
  (C_f = (1/c) int N N ds on a radiating side). Solved by fixed-point iteration on omega (M_a
  depends weakly on omega); with radiation omega is complex: its real part the frequency, its
  imaginary part the decay rate, zeta = Im(omega)/|omega|.

- Driven response (`driven_response`): the same matrices in the time domain, the bottom's w moved
  as the decks' drive, Newmark's average acceleration (the decks' histories to compare with).

The grid's columns of nodes (constant x) couple only to their neighbours, so A is block tridiagonal
and A^-1 Q^T is computed by block elimination (numpy only).
"""
from __future__ import annotations

import contextlib
import ctypes
import glob
import os
from dataclasses import dataclass

import numpy as np

TANK = (0.4, 0.2)                 # m, tank width and height
PLATE = (0.20, 0.21, 0.05, 0.20)  # m, x0, x1, y0 (free end), y1 (clamp)
E, NU, RHO_S = 7.0e10, 0.33, 2700.0
RHO_F, C_F = 1000.0, 1483.19      # c = sqrt(2.2e9 / 1000)


@contextlib.contextmanager
def one_blas_thread():
    """Run numpy's OpenBLAS on one thread (restored after): the blocks here are small, and OpenBLAS
    threads on a shared 2-core machine cost 15 times the wall time (measured: 20 s against 1.3 s)."""
    lib = None
    for path in glob.glob(os.path.join(os.path.dirname(np.__file__), "..", "numpy.libs", "*openblas*")):
        cand = ctypes.CDLL(path)
        if hasattr(cand, "scipy_openblas_set_num_threads64_"):
            lib = cand
    if lib is None:
        yield
        return
    before = lib.scipy_openblas_get_num_threads64_()
    lib.scipy_openblas_set_num_threads64_(1)
    try:
        yield
    finally:
        lib.scipy_openblas_set_num_threads64_(before)


@dataclass
class Beam:
    """Timoshenko beam FE of the plate: stiffness, mass and the free dofs (w, theta per node)."""

    y: np.ndarray
    K: np.ndarray
    M: np.ndarray
    free: np.ndarray


def beam(n_el: int = 120, thickness: float = PLATE[1] - PLATE[0], modulus: float = E,
         nu: float = NU, rho: float = RHO_S, y0: float = PLATE[2], y1: float = PLATE[3],
         bottom: str = "pinned") -> Beam:
    """Plane-strain Timoshenko beam from y0 (``bottom``: pinned or free) to y1 (clamped)."""
    y = np.linspace(y0, y1, n_el + 1)
    e_ps = modulus / (1.0 - nu * nu)
    ei = e_ps * thickness ** 3 / 12.0
    kga = 5.0 / 6.0 * modulus / (2.0 * (1.0 + nu)) * thickness
    rho_a, rho_i = rho * thickness, rho * thickness ** 3 / 12.0
    ndof = 2 * (n_el + 1)
    K, M = np.zeros((ndof, ndof)), np.zeros((ndof, ndof))
    for e in range(n_el):
        le = y[e + 1] - y[e]
        dofs = [2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3]  # w_a, th_a, w_b, th_b
        kb = ei / le * np.array([[0, 0, 0, 0], [0, 1, 0, -1], [0, 0, 0, 0], [0, -1, 0, 1]], float)
        g = np.array([-1.0 / le, -0.5, 1.0 / le, -0.5])  # w' - theta at the element's middle
        ks = kga * le * np.outer(g, g)
        mm = le / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
        me = np.zeros((4, 4))
        me[np.ix_([0, 2], [0, 2])] = rho_a * mm
        me[np.ix_([1, 3], [1, 3])] = rho_i * mm
        K[np.ix_(dofs, dofs)] += kb + ks
        M[np.ix_(dofs, dofs)] += me
    fixed = [2 * n_el, 2 * n_el + 1] + ([0] if bottom == "pinned" else [])
    free = np.setdiff1d(np.arange(ndof), fixed)
    return Beam(y, K, M, free)


@dataclass
class Fluid:
    """Acoustic FE of the tank less the plate, stored as the blocks of a block-tridiagonal matrix."""

    hf: float
    cols: list          # per grid column i: the j indices of its fluid nodes
    Kd: list            # diagonal blocks of K_f, M_f, C_f (column i with itself)
    Md: list
    Cd: list
    Ko: list            # off-diagonal blocks (column i with column i - 1), i >= 1
    Mo: list
    face_left: tuple    # (column index, y of its nodes, row indices) of the plate's left face
    face_right: tuple


_KQ = np.array([[4, -1, -2, -1], [-1, 4, -1, -2], [-2, -1, 4, -1], [-1, -2, -1, 4]], float) / 6.0
_MQ = np.array([[4, 2, 1, 2], [2, 4, 2, 1], [1, 2, 4, 2], [2, 1, 2, 4]], float) / 36.0


def fluid(hf: float = 0.005, far: str = "rigid", c: float = C_F, plate: bool = True) -> Fluid:
    """Bilinear acoustic elements of size hf (the plate's faces must lie on grid lines; ``plate``
    False: the empty tank, for checks)."""
    nx, ny = round(TANK[0] / hf), round(TANK[1] / hf)
    ix0, ix1 = round(PLATE[0] / hf), round(PLATE[1] / hf)
    jy0 = round(PLATE[2] / hf)
    if abs(ix0 * hf - PLATE[0]) > 1e-9 or abs(ix1 * hf - PLATE[1]) > 1e-9 or abs(jy0 * hf - PLATE[2]) > 1e-9:
        raise ValueError(f"hf = {hf}: the plate's faces are not on grid lines")
    solid = np.zeros((nx, ny), bool)  # elements inside the plate
    solid[ix0:ix1, jy0:] = plate
    used = np.zeros((nx + 1, ny + 1), bool)
    for i in range(nx):
        for j in range(ny):
            if not solid[i, j]:
                used[i:i + 2, j:j + 2] = True
    if far == "release":
        used[nx, :] = False  # p = 0 there: those nodes are not unknowns
    cols = [np.flatnonzero(used[i]) for i in range(nx + 1)]
    row = [dict(zip(js.tolist(), range(len(js)))) for js in cols]
    inv_c2 = 0.0 if not np.isfinite(c) else 1.0 / c ** 2
    Kd = [np.zeros((len(js), len(js))) for js in cols]
    Md = [np.zeros((len(js), len(js))) for js in cols]
    Cd = [np.zeros((len(js), len(js))) for js in cols]
    Ko = [None] + [np.zeros((len(cols[i]), len(cols[i - 1]))) for i in range(1, nx + 1)]
    Mo = [None] + [np.zeros((len(cols[i]), len(cols[i - 1]))) for i in range(1, nx + 1)]
    corners = [(0, 0), (1, 0), (1, 1), (0, 1)]  # counter-clockwise (di, dj)
    mq = _MQ * hf * hf * inv_c2
    for i in range(nx):
        for j in range(ny):
            if solid[i, j]:
                continue
            for a, (da, ea) in enumerate(corners):
                ia, ja = i + da, j + ea
                if not used[ia, ja]:
                    continue
                for b, (db, eb) in enumerate(corners):
                    ib, jb = i + db, j + eb
                    if not used[ib, jb]:
                        continue
                    ra, rb = row[ia][ja], row[ib][jb]
                    if ia == ib:
                        Kd[ia][ra, rb] += _KQ[a, b]
                        Md[ia][ra, rb] += mq[a, b]
                    elif ia == ib + 1:
                        Ko[ia][ra, rb] += _KQ[a, b]
                        Mo[ia][ra, rb] += mq[a, b]
    if far == "radiation" and np.isfinite(c):
        for j in range(ny):  # boundary mass (1/c) int N N ds on x = 0.4
            ra, rb = row[nx][j], row[nx][j + 1]
            m1 = hf / 6.0 / c * np.array([[2.0, 1.0], [1.0, 2.0]])
            Cd[nx][np.ix_([ra, rb], [ra, rb])] += m1
    def face(ix):
        js = np.array([j for j in cols[ix] if j >= jy0])
        return ix, js * hf, np.array([row[ix][j] for j in js])
    return Fluid(hf, cols, Kd, Md, Cd, Ko, Mo, face(ix0), face(ix1))


def _block_solve(fl: Fluid, omega: complex, rhs: dict) -> dict:
    """X = A^-1 B for A = K + i omega C - omega^2 M (block tridiagonal, complex symmetric).

    ``rhs`` maps a column index to its block of B (rows of that column, m right-hand sides); the
    result maps every column to its block of X (block elimination, the blocks solved by LU)."""
    n = len(fl.cols)
    m = next(iter(rhs.values())).shape[1]
    w2 = omega * omega
    S, Y = [None] * n, [None] * n
    for i in range(n):
        D = fl.Kd[i] + 1j * omega * fl.Cd[i] - w2 * fl.Md[i]
        B = rhs.get(i, np.zeros((len(fl.cols[i]), m)))
        if i > 0:
            Lo = fl.Ko[i] - w2 * fl.Mo[i]
            G = np.linalg.solve(S[i - 1].T, Lo.T).T  # Lo S_{i-1}^-1
            D = D - G @ Lo.T
            B = B - G @ Y[i - 1]
        S[i], Y[i] = D, B
    X = [None] * n
    X[n - 1] = np.linalg.solve(S[n - 1], Y[n - 1])
    for i in range(n - 2, -1, -1):
        Up = (fl.Ko[i + 1] - w2 * fl.Mo[i + 1]).T
        X[i] = np.linalg.solve(S[i], Y[i] - Up @ X[i + 1])
    return dict(enumerate(X))


def fluid_global(fl: Fluid):
    """K_f, M_f, C_f of ``fl`` as scipy.sparse CSR matrices on the fluid nodes numbered column by
    column (node j of column i is ``off[i] + searchsorted(cols[i], j)``), and ``off``."""
    import scipy.sparse as sp
    sizes = [len(cc) for cc in fl.cols]
    off = np.concatenate([[0], np.cumsum(sizes)]).astype(int)
    n = int(off[-1])
    out = []
    for diag, low in ((fl.Kd, fl.Ko), (fl.Md, fl.Mo), (fl.Cd, None)):
        rows, cols, vals = [], [], []
        for i in range(len(sizes)):
            r, c = np.nonzero(diag[i])
            rows.append(off[i] + r), cols.append(off[i] + c), vals.append(diag[i][r, c])
            if low is not None and i > 0:
                r, c = np.nonzero(low[i])
                v = low[i][r, c]
                rows += [off[i] + r, off[i - 1] + c]
                cols += [off[i - 1] + c, off[i] + r]
                vals += [v, v]
        out.append(sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                 shape=(n, n)))
    return out[0], out[1], out[2], off


def coupling(bm: Beam, fl: Fluid) -> dict:
    """Q^T per face column: rows the face's fluid nodes, columns the beam's w dofs (n_f . e_x folded in)."""
    out = {}
    nb = len(bm.y)
    for (ix, yf, _rows), sign in ((fl.face_left, 1.0), (fl.face_right, -1.0)):
        breaks = np.union1d(yf, bm.y)
        g = np.array([-1.0, 1.0]) / np.sqrt(3.0)
        Qt = np.zeros((len(yf), nb))
        for a, b in zip(breaks[:-1], breaks[1:]):
            for s in g:
                yq = 0.5 * (a + b) + 0.5 * (b - a) * s
                wq = 0.5 * (b - a)
                Qt += sign * wq * np.outer(hats(yf, yq), hats(bm.y, yq))
        block = np.zeros((len(fl.cols[ix]), 2 * nb))
        block[_rows, 0::2] = Qt
        out[ix] = block
    return out


def hats(nodes: np.ndarray, y: float) -> np.ndarray:
    """Values at y of the piecewise-linear hat functions on ``nodes``."""
    v = np.zeros(len(nodes))
    k = int(np.clip(np.searchsorted(nodes, y) - 1, 0, len(nodes) - 2))
    s = (y - nodes[k]) / (nodes[k + 1] - nodes[k])
    v[k], v[k + 1] = 1.0 - s, s
    return v


def added_mass(bm: Beam, fl: Fluid, omega: complex, rho: float = RHO_F, qt: dict | None = None) -> np.ndarray:
    """M_a = rho Q A(omega)^-1 Q^T on the beam's dofs."""
    qt = coupling(bm, fl) if qt is None else qt
    X = _block_solve(fl, omega, qt)
    return rho * sum(qt[i].T @ X[i] for i in qt)


def dry_frequency(bm: Beam) -> float:
    """First natural frequency [Hz] of the beam in vacuum."""
    f = bm.free
    lam = np.linalg.eigvals(np.linalg.solve(bm.M[np.ix_(f, f)], bm.K[np.ix_(f, f)]))
    return float(np.sqrt(np.min(lam.real)) / (2 * np.pi))


@dataclass
class WetMode:
    frequency: float   # Hz, Re(omega) / 2 pi
    zeta: float        # Im(omega) / |omega| (radiation damping; 0 for a closed tank)
    dry: float         # Hz, the same beam in vacuum
    shape: np.ndarray  # w at the beam nodes, max |w| = 1
    y: np.ndarray
    iterations: int


def wet_mode(n_el: int = 60, hf: float = 0.005, far: str = "rigid", c: float = C_F,
             tol: float = 1e-9, **beam_args) -> WetMode:
    """First wet mode: omega -> M_a(omega) -> the eigenvalue nearest omega^2, to its fixed point."""
    with one_blas_thread():
        return _wet_mode(n_el, hf, far, c, tol, **beam_args)


def _wet_mode(n_el, hf, far, c, tol, **beam_args) -> WetMode:
    bm = beam(n_el, **beam_args)
    fl = fluid(hf, far, c)
    qt = coupling(bm, fl)
    f = bm.free
    Kf = bm.K[np.ix_(f, f)]
    dry = dry_frequency(bm)
    Ms = bm.M[np.ix_(f, f)]

    def lowest(om):  # the eigenvalue of (K_s, M_s + M_a(om)) nearest om^2, as a frequency
        Ma = added_mass(bm, fl, om, qt=qt)[np.ix_(f, f)]
        lam, vec = np.linalg.eig(np.linalg.solve(Ms + Ma, Kf))
        k = int(np.argmin(np.abs(lam - om * om)))
        new = np.sqrt(lam[k])
        return (new if new.real > 0 else -new), vec[:, k]

    # secant steps on g(omega) = lowest(omega) - omega (the fixed point), from two plain iterations
    o0 = 2 * np.pi * dry / 3.0 + 0j
    o1, vec = lowest(o0)
    g0 = o1 - o0
    it = 1
    for it in range(2, 40):
        o2, vec = lowest(o1)
        g1 = o2 - o1
        if abs(g1) < tol * abs(o2):
            o1 = o2
            break
        o0, o1, g0 = o1, (o1 - g1 * (o1 - o0) / (g1 - g0)) if g1 != g0 else o2, g1
    omega = o1
    u = np.zeros(bm.K.shape[0], complex)
    u[f] = vec
    w = u[0::2]
    w = (w / w[np.argmax(np.abs(w))]).real
    return WetMode(float(omega.real / (2 * np.pi)), float(omega.imag / abs(omega)), dry, w, bm.y, it)


# ------------------------------------------------------------------------------ driven response

DRIVE = np.array([[0.0, 0.0], [1e-4, 1.0], [4e-4, 1.0], [5e-4, 0.0], [1.0, 0.0]])  # the decks' curve
V_DRIVE = 2.0  # m/s


def drive_state(t: float) -> tuple[float, float, float]:
    """Bottom displacement, velocity, acceleration of the decks' drive (V times the curve, exactly)."""
    tt, cc = DRIVE[:, 0], DRIVE[:, 1]
    v = V_DRIVE * float(np.interp(t, tt, cc))
    k = int(np.clip(np.searchsorted(tt, t, side="right") - 1, 0, len(tt) - 2))
    a = V_DRIVE * (cc[k + 1] - cc[k]) / (tt[k + 1] - tt[k])
    u = 0.0
    for j in range(len(tt) - 1):  # trapezoids of the piecewise-linear velocity up to t
        t0, t1 = tt[j], min(tt[j + 1], t)
        if t1 <= t0:
            break
        v0 = V_DRIVE * cc[j]
        v1 = V_DRIVE * float(np.interp(t1, tt, cc))
        u += 0.5 * (v0 + v1) * (t1 - t0)
    return u, v, a


# Strain gauges on the plate's faces (y_a, y_b), m: the mean face strain over the gauge is
# (u_y(y_b) - u_y(y_a)) / (y_b - y_a), a difference of two nodal displacements, defined alike on every
# mesh and bounded at the clamp (where the point stress of the 2D solid is singular). Beam: u_y = -z theta
# at the face z = +-c, c = t/2, so the mean bending stress is E' c |theta(y_a) - theta(y_b)| / (y_b - y_a)
# (plane strain, sigma_xx = 0 at the free face). The solvers' decks record u_y at these face nodes.
GAUGES = ((0.175, 0.2), (0.15, 0.175))


@dataclass
class Response:
    t: np.ndarray
    w_mid: np.ndarray      # m, lateral displacement at y = y_mid
    v_mid: np.ndarray      # m/s
    vm_clamp: np.ndarray   # Pa, von Mises at the solvers' clamp point (x = 0.2025, y = 0.1975)
    p_range: np.ndarray    # Pa, (min, max) of the water's dynamic pressure over the run
    gauges: dict = None    # Pa, {(y_a, y_b): bending stress E' c (theta_a - theta_b) / (y_b - y_a)}: GAUGES


def driven_response(n_el: int = 60, hf: float = 0.005, far: str = "rigid", c: float = C_F,
                    dt: float = 2e-6, end: float = 3e-3, y_mid: float = 0.125,
                    wet: bool = True) -> Response:
    """The plate's response to the decks' drive (bottom moved in x by V_DRIVE times the curve).

    The coupled system  M_s u'' + K_s u - Q p = 0,  M_f p'' + C_f p' + K_f p + rho Q^T u'' = 0
    (beam dofs less the clamp and the driven w at the bottom, whose motion enters as known
    u_b, u_b''), integrated with Newmark's average acceleration (gamma 1/2, beta 1/4:
    unconditionally stable, period error (omega dt)^2/12: 0.1 % at the dry frequency for 2 us).
    ``wet`` False: the plate in vacuum."""
    with one_blas_thread():
        bm = beam(n_el)
        fl = fluid(hf, far, c)
        qt = coupling(bm, fl)
        nb = bm.K.shape[0]
        f = bm.free
        b = 0  # the bottom's w dof, driven
        Kf, Mf, Cf, off = (m.toarray() if k < 3 else m for k, m in enumerate(fluid_global(fl)))
        nfl = int(off[-1]) if wet else 0
        Kf, Mf, Cf = Kf[:nfl, :nfl], Mf[:nfl, :nfl], Cf[:nfl, :nfl]
        Qt = np.zeros((nfl, nb))
        if wet:
            for i, blk in qt.items():
                Qt[off[i]:off[i + 1]] = blk
        ns = len(f)
        n = ns + nfl
        M = np.zeros((n, n))
        K = np.zeros((n, n))
        C = np.zeros((n, n))
        M[:ns, :ns] = bm.M[np.ix_(f, f)]
        K[:ns, :ns] = bm.K[np.ix_(f, f)]
        if wet:
            K[:ns, ns:] = -Qt[:, f].T
            M[ns:, :ns] = RHO_F * Qt[:, f]
            M[ns:, ns:] = Mf
            K[ns:, ns:] = Kf
            C[ns:, ns:] = Cf
        # the driven dof's columns: forces -M_xb a_b - K_xb u_b on the unknowns
        Mb = np.zeros(n)
        Kb = np.zeros(n)
        Mb[:ns] = bm.M[f, b]
        Kb[:ns] = bm.K[f, b]
        if wet:
            Mb[ns:] = RHO_F * Qt[:, b]
        beta, gamma = 0.25, 0.5
        Ainv = np.linalg.inv(M + gamma * dt * C + beta * dt * dt * K)
        x = np.zeros(n)
        v = np.zeros(n)
        a = np.zeros(n)
        steps = int(round(end / dt))
        j_mid = int(np.argmin(np.abs(bm.y - y_mid)))
        k_mid = int(np.flatnonzero(f == 2 * j_mid)[0])
        # von Mises at (0.2025, 0.1975): plane strain, sigma_yy = E' kappa z (z = -2.5 mm from the
        # mid-plane), sigma_zz = nu sigma_yy, sigma_xx = 0: sqrt(1 - nu + nu^2) |sigma_yy|
        j_cl = int(np.argmin(np.abs(0.5 * (bm.y[1:] + bm.y[:-1]) - 0.1975)))
        th = [np.flatnonzero(f == 2 * jj + 1) for jj in (j_cl, j_cl + 1)]
        le = bm.y[j_cl + 1] - bm.y[j_cl]
        vm_fac = E / (1.0 - NU * NU) * 0.0025 * np.sqrt(1.0 - NU + NU * NU)
        p_lo, p_hi = 0.0, 0.0
        out_t, out_w, out_v, out_s = [0.0], [0.0], [0.0], [0.0]
        # theta dofs at the gauges' ends (None: the clamp, theta = 0)
        g_dofs = []
        for ya, yb in GAUGES:
            ends = []
            for yy in (ya, yb):
                j = int(np.argmin(np.abs(bm.y - yy)))
                if abs(bm.y[j] - yy) > 1e-9:
                    raise ValueError(f"gauge end y = {yy} is not a beam node (n_el {n_el})")
                hit = np.flatnonzero(f == 2 * j + 1)
                ends.append(int(hit[0]) if len(hit) else None)
            g_dofs.append(ends)
        g_fac = E / (1.0 - NU * NU) * 0.5 * (PLATE[1] - PLATE[0])
        out_g = [[0.0] for _ in GAUGES]
        for k in range(1, steps + 1):
            t = k * dt
            ub, vb, ab = drive_state(t)
            xp = x + dt * v + (0.5 - beta) * dt * dt * a
            vp = v + (1 - gamma) * dt * a
            rhs = -Mb * ab - Kb * ub - C @ vp - K @ xp
            a = Ainv @ rhs
            x = xp + beta * dt * dt * a
            v = vp + gamma * dt * a
            out_t.append(t)
            out_w.append(x[k_mid])
            out_v.append(v[k_mid])
            th_a = x[th[0][0]] if len(th[0]) else 0.0
            th_b = x[th[1][0]] if len(th[1]) else 0.0
            out_s.append(vm_fac * abs(th_b - th_a) / le)
            for (ya, yb), (da, db), og in zip(GAUGES, g_dofs, out_g):
                ta = x[da] if da is not None else 0.0
                tb = x[db] if db is not None else 0.0
                og.append(g_fac * abs(ta - tb) / (yb - ya))
            if wet:
                p_lo, p_hi = min(p_lo, float(x[ns:].min())), max(p_hi, float(x[ns:].max()))
        return Response(np.array(out_t), np.array(out_w), np.array(out_v), np.array(out_s),
                        np.array([p_lo, p_hi]), {g: np.array(og) for g, og in zip(GAUGES, out_g)})
