"""Wet first natural frequency and mode of a cantilever plate standing in a water tank, without either solver.

The scene (decks/wet_cantilever_{ale,sph}.yaml; plane strain, the x-y plane, gravity -y): a plate
x = X0..X1 (thickness t = X1 - X0), clamped on the tank's floor y = 0 and free at its top y = L,
stands in a tank x = 0..W with rigid floor and side walls, water (density rho, sound speed c) up to
the depth D on both sides (D <= L: the plate pierces the free surface), air above (p = 0).

Model (linear, small motion about the hydrostatic rest state; the coupled structural-acoustic
eigenproblem of Zienkiewicz & Taylor, *The Finite Element Method*, vol. 1, ch. "Coupled systems";
Morand & Ohayon, *Fluid-Structure Interaction*, Wiley 1995, ch. 5-8):

- Structure: Timoshenko beam along y (deflection w(y), rotation theta(y)), plane strain
  E' = E/(1 - nu^2), EI = E' t^3/12, kappa G A = (5/6) G t, G = E/(2(1 + nu)); two-node elements,
  bending exact, shear one-point (reduced) integration, consistent mass rho_s t (w) and
  rho_s t^3/12 (theta); ``shear=False``: kappa G A -> 1e6 EI / L^2 (Euler-Bernoulli limit). Clamped
  at y = 0 (w = theta = 0). The plate's own weight compresses it, N(y) = rho_s t g (L - y) (the
  water's pressure acts on its faces only, so no buoyancy acts along it): geometric stiffness
  -int N w'^2 (Bazant & Cedolin, *Stability of Structures*, ch. 1).
- Fluid: the pressure perturbation p, del^2 p - p_tt/c^2 = 0 (c = inf: Laplace, potential flow),
  bilinear quadrilaterals of size hf on the water less the plate: K_f = int grad N . grad N,
  M_f = int N N / c^2. Rigid floor and walls: dp/dn = 0. Free surface, linearised: total pressure
  zero on the moved surface, p = rho g eta, eta_tt = -(1/rho) dp/dy, so dp/dy = -p_tt / g
  (boundary mass M_g = (1/g) int N N ds; ``surface_waves``); by default p = 0 there, the limit
  omega^2 D / g -> inf (for the decks omega^2 D / g = 158: gravity waves at the wet frequency are
  3.9 mm long, shorter than any fluid mesh of the decks, and p = 0 is what those meshes resolve). Plate faces: dp/dn = -rho w_tt
  (n_f . e_x), n_f the fluid's outward normal (+x on the left face, -x on the right one); the water
  pushes the plate with p n_f. Q_ki = int N_k phi_i (n_f . e_x) ds over the wetted faces y < D.
- Harmonic e^{i omega t}: (K_s - omega^2 [M_s + M_a(omega)]) u = 0, M_a = rho Q^T A^-1 Q,
  A = K_f - omega^2 (M_f + M_g); c = inf and p = 0 on the surface: M_a does not depend on omega and the eigenproblem is
  one call of scipy.linalg.eigh; otherwise the eigenvalue nearest omega^2 is iterated to its fixed
  point.

Checks against closed forms (tests/verification/test_wet_cantilever_reference.py): the dry
cantilever (1.8751^2 sqrt(EI/(m L^4)) / 2 pi); the rigid plate's added mass against Westergaard's
series for a rigid wall before a reservoir of finite length (incompressible and acoustic, Chopra
1967); the empty tank's sloshing frequencies omega^2 = g k tanh(k D).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wet_plate_reference import Beam, dry_frequency, hats  # shared with the closed-tank reference

BETA_CANTILEVER = 1.8751040687  # first root of cos(bL) cosh(bL) = -1


@dataclass(frozen=True)
class Scene:
    """Dimensions [m], materials [kg/m^3, Pa] and gravity [m/s^2] of the tank and its plate."""

    width: float = 0.31        # tank x = 0..width
    depth: float = 0.10        # water y = 0..depth
    x0: float = 0.15           # plate x = x0..x1
    x1: float = 0.16
    length: float = 0.12       # plate y = 0..length (clamped at 0)
    E: float = 1.0e8
    nu: float = 0.3
    rho_s: float = 1200.0
    rho_f: float = 1000.0
    c: float = np.inf          # the water's sound speed (inf: incompressible)
    g: float = 9.81            # gravity: the plate's weight, and the free surface's where surface_waves
    surface_waves: bool = False  # False: p = 0 on the free surface (the limit omega^2 D / g -> inf)

    @property
    def thickness(self) -> float:
        return self.x1 - self.x0

    def with_(self, **kw) -> "Scene":
        d = dict(self.__dict__)
        d.update(kw)
        return Scene(**d)


# ------------------------------------------------------------------------------------------ beam

def beam(sc: Scene, n_el: int = 96, shear: bool = True, weight: bool = True) -> Beam:
    """Plane-strain Timoshenko beam y = 0 (clamped) .. L (free); dofs (w, theta) per node.

    ``weight``: the geometric stiffness of the plate's own weight under gravity sc.g (finite g only)."""
    t, L = sc.thickness, sc.length
    y = np.linspace(0.0, L, n_el + 1)
    ei = sc.E / (1.0 - sc.nu ** 2) * t ** 3 / 12.0
    kga = 5.0 / 6.0 * sc.E / (2.0 * (1.0 + sc.nu)) * t if shear else 1e6 * ei / L ** 2
    rho_a, rho_i = sc.rho_s * t, sc.rho_s * t ** 3 / 12.0
    q = sc.rho_s * t * sc.g if (weight and np.isfinite(sc.g)) else 0.0  # N/m, the weight per length
    ndof = 2 * (n_el + 1)
    K, M = np.zeros((ndof, ndof)), np.zeros((ndof, ndof))
    for e in range(n_el):
        le = y[e + 1] - y[e]
        dofs = [2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3]  # w_a, th_a, w_b, th_b
        kb = ei / le * np.array([[0, 0, 0, 0], [0, 1, 0, -1], [0, 0, 0, 0], [0, -1, 0, 1]], float)
        gam = np.array([-1.0 / le, -0.5, 1.0 / le, -0.5])  # w' - theta at the element's middle
        ks = kga * le * np.outer(gam, gam)
        n_mid = q * (L - 0.5 * (y[e] + y[e + 1]))  # compression at the element's middle
        dw = np.array([-1.0, 0.0, 1.0, 0.0]) / le  # w'
        kg = -n_mid * le * np.outer(dw, dw)
        mm = le / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
        me = np.zeros((4, 4))
        me[np.ix_([0, 2], [0, 2])] = rho_a * mm
        me[np.ix_([1, 3], [1, 3])] = rho_i * mm
        K[np.ix_(dofs, dofs)] += kb + ks + kg
        M[np.ix_(dofs, dofs)] += me
    return Beam(y, K, M, np.arange(2, ndof))


def euler_bernoulli_frequency(sc: Scene) -> float:
    """First frequency [Hz] of the plane-strain Euler-Bernoulli cantilever in vacuum (no weight)."""
    t = sc.thickness
    ei = sc.E / (1.0 - sc.nu ** 2) * t ** 3 / 12.0
    return BETA_CANTILEVER ** 2 * np.sqrt(ei / (sc.rho_s * t * sc.length ** 4)) / (2 * np.pi)


# ----------------------------------------------------------------------------------------- fluid

@dataclass
class Fluid:
    """Acoustic FE of the water: sparse K_f, M_f (1/c^2), M_g (free surface, 1/g), node coordinates,
    and per wetted face (left, right): the fluid rows of its nodes, their y, and n_f . e_x."""

    K: sp.csc_matrix
    M: sp.csc_matrix
    Mg: sp.csc_matrix
    xy: np.ndarray
    faces: list = field(default_factory=list)


_KQ = np.array([[4, -1, -2, -1], [-1, 4, -1, -2], [-2, -1, 4, -1], [-1, -2, -1, 4]], float) / 6.0
_MQ = np.array([[4, 2, 1, 2], [2, 4, 2, 1], [1, 2, 4, 2], [2, 1, 2, 4]], float) / 36.0


def _index(v: float, hf: float, what: str) -> int:
    k = round(v / hf)
    if abs(k * hf - v) > 1e-9 * max(1.0, abs(v)):
        raise ValueError(f"hf = {hf}: the {what} ({v} m) is not on a grid line")
    return k


def fluid(sc: Scene, hf: float = 0.0025, plate: bool = True) -> Fluid:
    """Bilinear elements of size hf on the water (``plate`` False: the empty tank, for checks)."""
    nx, ny = _index(sc.width, hf, "tank width"), _index(sc.depth, hf, "depth")
    i0, i1 = _index(sc.x0, hf, "plate face x0"), _index(sc.x1, hf, "plate face x1")
    jt = min(_index(min(sc.length, sc.depth), hf, "plate top"), ny)
    wet = np.ones((nx, ny), bool)
    if plate:
        wet[i0:i1, :jt] = False
    # nodes: a grid node belongs to the left and right water separately where the plate splits them
    # (its faces' columns); elsewhere one node per grid point.
    key = {}
    xy = []
    conn = []
    for i in range(nx):
        for j in range(ny):
            if not wet[i, j]:
                continue
            side = 0 if (plate and i < i0) else 1
            corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
            row = []
            for (a, b) in corners:
                split = plate and b < jt and a in (i0, i1)  # a face node below the plate's top
                k = (a, b, side if split else -1)
                if k not in key:
                    key[k] = len(xy)
                    xy.append((a * hf, b * hf))
                row.append(key[k])
            conn.append(row)
    conn = np.array(conn)
    n = len(xy)
    xy = np.array(xy)
    inv_c2 = 0.0 if not np.isfinite(sc.c) else 1.0 / sc.c ** 2
    rows = np.repeat(conn, 4, axis=1).ravel()
    cols = np.tile(conn, (1, 4)).ravel()
    K = sp.csc_matrix((np.tile(_KQ.ravel(), len(conn)), (rows, cols)), shape=(n, n))
    M = sp.csc_matrix((np.tile((_MQ * hf * hf * inv_c2).ravel(), len(conn)), (rows, cols)), shape=(n, n))
    # free-surface edges: the top edge (corners 3, 2) of the elements of the top row
    top = conn[np.isclose(xy[conn[:, 3], 1], sc.depth)]
    m1 = hf / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
    inv_g = 1.0 / sc.g if (sc.surface_waves and np.isfinite(sc.g) and sc.g > 0) else 0.0
    e = top[:, [3, 2]]
    Mg = sp.csc_matrix((np.tile((m1 * inv_g).ravel(), len(e)),
                        (np.repeat(e, 2, axis=1).ravel(), np.tile(e, (1, 2)).ravel())), shape=(n, n))
    faces = []
    if plate:
        for (a, side, sign) in ((i0, 0, 1.0), (i1, 1, -1.0)):
            ks = [key[(a, b, side)] for b in range(jt + 1) if (a, b, side) in key]
            ks += [] if (a, jt, side) in key else [key[(a, jt, -1)]]  # the node at the plate's top
            ks = sorted(set(ks), key=lambda k: xy[k, 1])
            faces.append((np.array(ks), xy[ks, 1], sign))
    return Fluid(K, M, Mg, xy, faces)


def _surface_dirichlet(sc: Scene, fl: Fluid) -> np.ndarray:
    """The fluid's unknowns: every node, less the free surface's unless surface_waves (p = 0 there)."""
    if sc.surface_waves:
        return np.arange(len(fl.xy))
    return np.flatnonzero(~np.isclose(fl.xy[:, 1], sc.depth))


def coupling(sc: Scene, bm: Beam, fl: Fluid) -> np.ndarray:
    """Q (fluid nodes x beam dofs): int N_k phi_i (n_f . e_x) ds over the wetted faces, on the w dofs."""
    Q = np.zeros((len(fl.xy), bm.K.shape[0]))
    g = np.array([-1.0, 1.0]) / np.sqrt(3.0)
    top = min(sc.length, sc.depth)
    for rows, yf, sign in fl.faces:
        breaks = np.union1d(yf, bm.y[bm.y <= top])
        for a, b in zip(breaks[:-1], breaks[1:]):
            for s in g:
                yq = 0.5 * (a + b) + 0.5 * (b - a) * s
                Q[np.ix_(rows, np.arange(0, bm.K.shape[0], 2))] += sign * 0.5 * (b - a) * np.outer(
                    hats(yf, yq), hats(bm.y, yq))
    return Q


def added_mass(sc: Scene, fl: Fluid, Q: np.ndarray, omega: float = 0.0) -> np.ndarray:
    """M_a(omega) = rho Q^T A^-1 Q, A = K_f - omega^2 (M_f + M_g), on the unknowns of the fluid."""
    keep = _surface_dirichlet(sc, fl)
    A = (fl.K - omega * omega * (fl.M + fl.Mg))[keep][:, keep].tocsc()
    Qk = Q[keep]
    used = np.flatnonzero(np.any(Qk != 0.0, axis=0))
    X = spla.splu(A).solve(Qk[:, used])
    Ma = np.zeros((Q.shape[1], Q.shape[1]))
    Ma[np.ix_(used, used)] = sc.rho_f * Qk[:, used].T @ X
    return 0.5 * (Ma + Ma.T)


# ------------------------------------------------------------------------------------ wet mode

@dataclass
class WetMode:
    frequency: float   # Hz
    dry: float         # Hz, the same beam in vacuum
    shape: np.ndarray  # w at the beam nodes, w(L) = 1
    y: np.ndarray
    added_mass: float  # kg/m, the modal added mass (shape normalised to w(L) = 1)
    modal_mass: float  # kg/m, the plate's modal mass (same normalisation)
    iterations: int


def wet_mode(sc: Scene, n_el: int = 96, hf: float = 0.0025, tol: float = 1e-8, shear: bool = True,
             weight: bool = True) -> WetMode:
    """First wet mode: the eigenvalue of (K_s, M_s + M_a(omega)) nearest omega^2 at its fixed point."""
    bm = beam(sc, n_el, shear, weight)
    fl = fluid(sc, hf)
    Q = coupling(sc, bm, fl)
    f = bm.free
    Ks, Ms = bm.K[np.ix_(f, f)], bm.M[np.ix_(f, f)]
    dry = dry_frequency(bm)
    fixed = not (np.isfinite(sc.c) or sc.surface_waves)

    def lowest(om):
        Ma = added_mass(sc, fl, Q, om)[np.ix_(f, f)]
        lam, vec = sla.eigh(Ks, Ms + Ma, subset_by_index=[0, min(5, len(f) - 1)])
        k = 0 if fixed else int(np.argmin(np.abs(lam - om * om)))
        return float(np.sqrt(lam[k])), vec[:, k], Ma

    om, vec, Ma = lowest(0.0 if fixed else np.pi * dry)  # from half the dry frequency: A(0) is
    it = 1                                                # singular with surface waves
    while not fixed:  # M_a varies slowly with omega (away from the water's own modes): plain iteration
        new, vec, Ma = lowest(om)
        it += 1
        done = abs(new - om) < tol * new
        om = new
        if done:
            break
        if it > 100:
            raise RuntimeError("wet_mode: the fixed point did not converge")
    o1 = om
    u = np.zeros(bm.K.shape[0])
    u[f] = vec
    scale = u[-2]
    u, vec = u / scale, vec / scale
    return WetMode(o1 / (2 * np.pi), dry, u[0::2], bm.y, float(vec @ Ma @ vec), float(vec @ Ms @ vec), it)


# ---------------------------------------------------------------------------- closed-form checks

def westergaard_added_mass(sc: Scene, omega: float = 0.0, reservoir: float | None = None,
                           terms: int = 4000) -> float:
    """Added mass [kg/m] of a rigid vertical wall translating before a reservoir of depth D, length
    ``reservoir`` (a rigid far wall; None: the left one, x0), free surface p = 0, rigid floor.

    p = sum_n B_n cos(l_n y) cosh(m_n (R - x)), l_n = (2n - 1) pi / (2 D), m_n = sqrt(l_n^2 - omega^2/c^2)
    (Westergaard 1933, Trans. ASCE 98, 418-433; acoustic: Chopra 1967, J. Eng. Mech. Div. 93, 205-223):
    M_a = sum_n 2 rho / (D l_n^2 m_n tanh(m_n R)); R -> inf, c -> inf: 0.5430 rho D^2."""
    R = sc.x0 if reservoir is None else reservoir
    n = np.arange(1, terms + 1)
    lam = (2 * n - 1) * np.pi / (2 * sc.depth)
    k2 = 0.0 if not np.isfinite(sc.c) else (omega / sc.c) ** 2
    mu = np.sqrt(lam ** 2 - k2)
    return float(np.sum(2 * sc.rho_f / (sc.depth * lam ** 2 * mu * np.tanh(mu * R))))


def rigid_plate_added_mass(sc: Scene, hf: float, omega: float = 0.0) -> float:
    """The same from the FE fluid: the plate translating as a whole, both faces (kg/m)."""
    bm = beam(sc, max(1, round(sc.length / hf)))
    fl = fluid(sc, hf)
    Q = coupling(sc, bm, fl)
    one = np.zeros(bm.K.shape[0])
    one[0::2] = 1.0
    return float(one @ added_mass(sc, fl, Q, omega) @ one)


def sloshing_frequencies(sc: Scene, hf: float, n: int = 3) -> np.ndarray:
    """The empty tank's lowest n sloshing frequencies [Hz] from the FE fluid (incompressible):
    the Laplace operator condensed onto the surface nodes, against M_g."""
    fl = fluid(sc.with_(c=np.inf, surface_waves=True), hf, plate=False)
    s = np.flatnonzero(np.isclose(fl.xy[:, 1], sc.depth))
    i = np.setdiff1d(np.arange(len(fl.xy)), s)
    K = fl.K.tocsr()
    Kss = K[s][:, s].toarray()
    Ksi = K[s][:, i].tocsc()
    cond = Kss - Ksi @ spla.splu(K[i][:, i].tocsc()).solve(Ksi.T.toarray())
    lam = sla.eigh(0.5 * (cond + cond.T), fl.Mg[s][:, s].toarray(), eigvals_only=True)
    return np.sqrt(np.clip(lam[1:n + 1], 0.0, None)) / (2 * np.pi)  # lam[0] = 0: the constant p


def acoustic_frequency(sc: Scene, hf: float) -> float:
    """Lowest acoustic frequency [Hz] of the water with the plate held rigid, p = 0 on the surface."""
    fl = fluid(sc, hf)
    keep = np.flatnonzero(~np.isclose(fl.xy[:, 1], sc.depth))
    K, M = fl.K[keep][:, keep].tocsc(), fl.M[keep][:, keep].tocsc()
    lam = spla.eigsh(K, k=1, M=M, sigma=0.0, which="LM", return_eigenvectors=False)
    return float(np.sqrt(lam[0]) / (2 * np.pi))


# ------------------------------------------------------------------------------ measuring a run

@dataclass
class Ringing:
    frequency: float   # Hz, the damped sinusoid's fit
    zeta: float        # its decay rate over omega
    crossings: float   # Hz, from the mean-crossings (first to last, whole periods)
    periods: float     # periods in the window
    residual: float    # rms of the fit's residual over the signal's rms


def ringing(t: np.ndarray, u: np.ndarray, t0: float) -> Ringing:
    """Free ringing of u(t) on t >= t0: u = c + e^{-zeta w t}(a cos w_d t + b sin w_d t) fitted by least
    squares (scipy.optimize.least_squares, started from the crossings of the mean); the frequency
    reported is the undamped w / 2 pi = w_d / (2 pi sqrt(1 - zeta^2))."""
    from scipy.optimize import least_squares

    m = t >= t0
    t, u = t[m] - t0, u[m]
    z = u - u.mean()
    s = np.flatnonzero(np.sign(z[1:]) != np.sign(z[:-1]))
    tc = t[s] - z[s] * (t[s + 1] - t[s]) / (z[s + 1] - z[s])
    if len(tc) < 3:
        raise ValueError("ringing: fewer than three crossings of the mean")
    n_half = len(tc) - 1
    f_cross = 0.5 * n_half / (tc[-1] - tc[0])

    def model(x):
        c, a, b, w, sig = x
        e = np.exp(-sig * t)
        return c + e * (a * np.cos(w * t) + b * np.sin(w * t))

    w0 = 2 * np.pi * f_cross
    A = np.stack([np.ones_like(t), np.cos(w0 * t), np.sin(w0 * t)], axis=1)
    c0, a0, b0 = np.linalg.lstsq(A, u, rcond=None)[0]
    fit = least_squares(lambda x: model(x) - u, [c0, a0, b0, w0, 0.0], x_scale="jac")
    c, a, b, wd, sig = fit.x
    wn = np.hypot(wd, sig)
    return Ringing(float(wn / (2 * np.pi)), float(sig / wn), float(f_cross), float(t[-1] * wd / (2 * np.pi)),
                   float(np.sqrt(np.mean(fit.fun ** 2)) / np.std(u)))
