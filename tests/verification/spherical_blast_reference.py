"""A 1D Lagrangian reference for the underwater explosion, computed without the solver (issue 15).

The scene of decks/underwater_explosion_free_field_axisymmetric_ale.yaml (and of the 3D octant
decks/underwater_explosion_3d_ale.yaml): a TNT sphere of radius a, detonated at its centre at t = 0,
in open water. Spherical symmetry makes it a 1D problem in r; `geometry` also gives the cylindrical
(an infinite TNT cylinder on an axis) and planar (a TNT slab) twins.

**Scheme** (Wilkins, "Calculation of elastic-plastic flow", Methods in Computational Physics 3 (1964),
and "Computer Simulation of Dynamic Phenomena", Springer 1999, ch. 2-3; Benson, CMAME 99 (1992)
235-394, sec. 2-3). Staggered grid: node radii r_i and velocities u_i, i = 0..N; zones j = 0..N-1
between r_j and r_j+1 hold mass m_j, specific internal energy e_j, pressure p_j and viscosity q_j.
Per unit solid angle (radian, unit area) with the exponent k = 2, 1, 0 (sphere, cylinder, slab):

    V_j = (r_j+1^(k+1) - r_j^(k+1)) / (k+1),   A_i = r_i^k,   rho_j = m_j / V_j,   M_i = (m_i-1 + m_i) / 2
    M_i du_i/dt = A_i (sigma_i-1 - sigma_i),      sigma = p + q                       (momentum)
    m_j de_j/dt = -(p_j + q_j) dV_j/dt                                              (energy)

Time integration: the predictor-corrector of Caramana, Burton, Shashkov & Whalen (J. Comput. Phys.
146 (1998) 227-262, sec. 5): predict r, e, p at t + dt/2 from the forces at t; then
    u^(n+1) = u^n + dt F^(n+1/2) / M,   ubar = (u^n + u^(n+1))/2,   r^(n+1) = r^n + dt ubar,
    m_j (e_j^(n+1) - e_j^n) = -dt sigma_j^(n+1/2) (A_j+1 ubar_j+1 - A_j ubar_j)      (A at t + dt/2).
The energy takes exactly the work of the nodal forces (F_i = A_i (sigma_i-1 - sigma_i)), so the total
energy sum(m e) + sum(M u^2)/2 is conserved to round-off ("compatible" discretisation). Wilkins' leapfrog
with q^(n-1/2) in the momentum and q^(n+1/2) in the energy was tried first: it gained 1.7 % of the total
energy during the burn and the water shock's entry, an error proportional to dt/dr that refinement at a
fixed Courant number does not remove.

Artificial viscosity: von Neumann & Richtmyer (J. Appl. Phys. 21 (1950) 232) quadratic plus
Landshoff's linear term, q = rho (C_Q^2 du^2 - C_L c du) where du = u_j+1 - u_j < 0, else 0
(C_Q = 1.5 as LS-DYNA's Q1; C_L = 0.3, not its Q2 = 0.06: with 0.06 a planar water shock of 75-370 MPa
overshoots its Hugoniot pressure by 6-9 % behind the front (`piston`), and a peak read from p keeps that
overshoot at every resolution; at C_L = 0.25 it is under 0.2 %, at 0.3 none). Step: dt = cfl min_j dr_j / (Q_j + sqrt(Q_j^2 +
c_j^2)), Q = C_L c + C_Q^2 |du| (the form of Benson 1992, sec. 3, and of the solver). Inner node: r = 0 held (sphere,
cylinder) or a driven piston (slab); outer node: a rigid wall placed beyond the reach of the reflected
wave. Probe pressure at a fixed radius R: the zone pressures p (not p + q) at the zone centres,
interpolated linearly in r, every step. The march is one numba kernel (cache=True): as NumPy calls a
step took 0.5 ms at 1460 zones, 30 x the kernel.

**Materials**, read from the deck (so no constant is typed here twice):

    JWL products (the deck's eos "tnt"; Lee, Hornig & Kury, UCRL-50422 (1968)), V = rho0/rho:
        p = A (1 - omega/(R1 V)) exp(-R1 V) + B (1 - omega/(R2 V)) exp(-R2 V) + omega E / V
    Mie-Gruneisen water (LS-DYNA *EOS_GRUNEISEN, the deck's eos "water"), mu = rho/rho0 - 1:
        mu > 0:  p = rho0 C^2 mu [1 + (1 - g0/2) mu - a mu^2/2] / [1 - (S1-1) mu - S2 mu^2/(mu+1)
                     - S3 mu^3/(mu+1)^2]^2 + (g0 + a mu) E
        mu <= 0: p = rho0 C^2 mu + (g0 + a mu) E,        then p = max(p, the section's cut-off)
    (schema defaults S2 = S3 = a = 0, e0 = 0 where the deck omits them). Sound speed, in the solver's
    variables eta = rho/rho0 and E: c^2 = (dp/deta|_E + p g / eta^2) / rho0, dp/deta by a central difference
    (for the step and the viscosity only).

**Burn**, as sphfem_cli/materials/burn.py (LS-DYNA *MAT_HIGH_EXPLOSIVE_BURN, BETA = 2): the products'
pressure is F p_JWL with
    t_L = |x| / D (x the zone's initial centre, detonation at the centre at t = 0),
    F = min(1, max(0, (t - t_L) D / (1.5 delta))),  delta = the zone's initial width
(burn.py's delta = area / longest edge of a square quad, or face area / volume of a cube, is its
side h: in 1D the zone width). The energy equation uses the same F p, as in the solver. The
alternative burn="instantaneous" lights the whole charge at t = 0 with F = 1 (constant-volume
explosion at rho0, E0: p = p_JWL(1, E0)), the limit D -> infinity.

**Similitude** (Cole, "Underwater Explosions", Princeton 1948, ch. 7; coefficients for TNT from
Swisdak, NSWC TR 76-116 (1978)): P_max = K (W^(1/3)/R)^alpha with K = 52.4 MPa, alpha = 1.13, and
the decay constant theta = K_t W^(1/3) (W^(1/3)/R)^(alpha_t) with K_t = 84 us, alpha_t = -0.23 (W in
kg TNT, R in m); theta is measured here as the time from the peak to peak/e. The constants are read from
tests/data/underwater_explosion_free_field.yaml (their sources and checks in the .md beside it), where this
reference's converged peaks are stored too (python -m tests.reference_data spherical-blast-1d).

**Interface.** `setup_from_deck(path)` reads the charge and water; `blast(setup, dr, radii)` returns the
pressure histories p(t) at fixed radii; `peaks` their peak, its time and theta; `cole_peak`,
`cole_theta` the similitude; `piston`, `water_hugoniot` and `cj_state` serve the checks
(tests/verification/test_spherical_blast_reference.py). The study: docs/studies/underwater_explosion_blast1d.py
and docs/studies/underwater_explosion.md, "The Cole excess: a 1D spherical reference".
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml
from numba import njit

from tests.reference_data import value

DECK = Path(__file__).resolve().parents[2] / "decks/underwater_explosion_free_field_axisymmetric_ale.yaml"
EXPONENT = {"planar": 0, "cylindrical": 1, "spherical": 2}
FREE_FIELD = "underwater_explosion_free_field"   # tests/data/underwater_explosion_free_field.{yaml,md}: sources
# Swisdak 1978, TNT: P_max [Pa] = K (W^(1/3)/R)^alpha; theta [s] = K W^(1/3) (W^(1/3)/R)^alpha
COLE_P = (value(FREE_FIELD, "cole_peak_k"), value(FREE_FIELD, "cole_peak_alpha"))
COLE_THETA = (value(FREE_FIELD, "cole_theta_k"), value(FREE_FIELD, "cole_theta_alpha"))


@dataclass(frozen=True)
class Jwl:
    """JWL products: p = f(eta) + g(eta) E, g = omega eta (eta = rho/rho0, E per reference volume)."""

    rho0: float
    A: float
    B: float
    R1: float
    R2: float
    omega: float
    e0: float
    detonation_velocity: float

    def fg(self, eta):
        v = 1.0 / eta
        f = (self.A * (1.0 - self.omega / (self.R1 * v)) * np.exp(-self.R1 * v)
             + self.B * (1.0 - self.omega / (self.R2 * v)) * np.exp(-self.R2 * v))
        return f, self.omega * eta


@dataclass(frozen=True)
class Gruneisen:
    """LS-DYNA Mie-Gruneisen: p = f(mu) + (gamma0 + a mu) E, the compressed branch for mu > 0."""

    rho0: float
    c: float
    s1: float
    s2: float
    s3: float
    gamma0: float
    a: float
    e0: float

    def fg(self, eta):
        mu = np.asarray(eta, dtype=float) - 1.0
        k0 = self.rho0 * self.c ** 2
        m1 = mu + 1.0
        num = 1.0 + (1.0 - 0.5 * self.gamma0) * mu - 0.5 * self.a * mu * mu
        den = 1.0 - (self.s1 - 1.0) * mu - self.s2 * mu * mu / m1 - self.s3 * mu ** 3 / (m1 * m1)
        f = np.where(mu > 0.0, k0 * mu * num / (den * den), k0 * mu)
        return f, self.gamma0 + self.a * mu


@dataclass(frozen=True)
class BlastSetup:
    """The charge (JWL, burn) of radius `charge_radius` in water; `pressure_cutoff` as the deck's section."""

    explosive: Jwl
    water: Gruneisen
    charge_radius: float
    pressure_cutoff: float

    @property
    def charge_mass(self) -> float:
        """Mass of the spherical charge, kg."""
        return self.explosive.rho0 * 4.0 / 3.0 * math.pi * self.charge_radius ** 3

    def replace(self, explosive: dict | None = None, water: dict | None = None, **kw) -> "BlastSetup":
        """A copy with some constants changed (the candidates of the study)."""
        exp = dataclasses.replace(self.explosive, **(explosive or {}))
        wat = dataclasses.replace(self.water, **(water or {}))
        return dataclasses.replace(self, explosive=exp, water=wat, **kw)


def setup_from_deck(path: Path | str = DECK) -> BlastSetup:
    """The charge and water of a free-field deck: its EOS, materials, fill ball radius and cut-off."""
    deck = yaml.safe_load(Path(path).read_text())
    eos, mats = deck["equations_of_state"], deck["materials"]
    he = next(m for m in mats.values() if m["type"] == "high_explosive")
    fl = next(m for m in mats.values() if m["type"] == "fluid")
    j, w = eos[he["eos"]], eos[fl["eos"]]
    assert j["type"] == "jwl" and w["type"] == "gruneisen", (j["type"], w["type"])
    num = lambda x: float(x)   # noqa: E731  (PyYAML reads 3.712e11, without a '+' in the exponent, as text)
    explosive = Jwl(*map(num, (he["density"], j["A"], j["B"], j["R1"], j["R2"], j["omega"], j.get("e0", 0.0),
                               he["detonation_velocity"])))
    water = Gruneisen(*map(num, (fl["density"], w["c"], w["s1"], w.get("s2", 0.0), w.get("s3", 0.0), w["gamma0"],
                                 w.get("a", 0.0), w.get("e0", 0.0))))
    ball = next(f["ball"] for p in deck["parts"].values() for f in p.get("fill", []) if "ball" in f)
    cutoff = next(float(s.get("pressure_cutoff", -math.inf)) for s in deck["sections"].values()
                  if s["type"].startswith("ale"))
    return BlastSetup(explosive, water, float(ball["radius"]), float(cutoff))


def cj_state(jwl: Jwl) -> dict:
    """Chapman-Jouguet point of the JWL products: the minimum detonation speed along its Hugoniot.

    Products' Hugoniot from the unreacted state (V = 1, p = 0, E = E0): E = E0 + p (1 - V)/2, so
    p_H(V) = (f + g E0) / (1 - g (1 - V)/2); Rayleigh line D^2 = p / (rho0 (1 - V)); CJ = its minimum
    over V (Fickett & Davis, "Detonation", 1979, ch. 2). Returns D_CJ, p_CJ, V_CJ.
    """
    v = np.linspace(0.55, 0.95, 400001)
    f, g = jwl.fg(1.0 / v)
    p = (f + g * jwl.e0) / (1.0 - 0.5 * g * (1.0 - v))
    d2 = p / (jwl.rho0 * (1.0 - v))
    k = int(np.argmin(d2))
    return {"D": float(math.sqrt(d2[k])), "p": float(p[k]), "V": float(v[k])}


def _grid(setup: BlastSetup, dr: float, r_max: float):
    """Nodes from 0 to r_max: the charge [0, a] in whole zones of about dr, then the water."""
    n_he = max(1, round(setup.charge_radius / dr)) if setup.charge_radius > 0 else 0
    r_he = np.linspace(0.0, setup.charge_radius, n_he + 1)
    n_w = max(1, round((r_max - setup.charge_radius) / dr))
    return np.concatenate([r_he, np.linspace(setup.charge_radius, r_max, n_w + 1)[1:]]), n_he


# ------------------------------------------------------------------------------ numba kernels
# jwl = [A, B, R1, R2, omega, D]; gr = [rho0 C^2, S1, S2, S3, gamma0, a]; mat 0 = JWL, 1 = water.


@njit(cache=True)
def _fg(mat, eta, jwl, gr):
    """f, g of p = f(eta) + g(eta) E (module docstring)."""
    if mat == 0:
        v = 1.0 / eta
        f = (jwl[0] * (1.0 - jwl[4] / (jwl[2] * v)) * math.exp(-jwl[2] * v)
             + jwl[1] * (1.0 - jwl[4] / (jwl[3] * v)) * math.exp(-jwl[3] * v))
        return f, jwl[4] * eta
    mu = eta - 1.0
    g = gr[4] + gr[5] * mu
    if mu <= 0.0:
        return gr[0] * mu, g
    m1 = mu + 1.0
    num = 1.0 + (1.0 - 0.5 * gr[4]) * mu - 0.5 * gr[5] * mu * mu
    den = 1.0 - (gr[1] - 1.0) * mu - gr[2] * mu * mu / m1 - gr[3] * mu * mu * mu / (m1 * m1)
    return gr[0] * mu * num / (den * den), g


@njit(cache=True)
def _zone_state(mat, eta, E, frac, rho0, cutoff, jwl, gr):
    """(p, c): p = max(F (f + g E), cut-off); c^2 = (dp/deta|_E + p_eos g / eta^2) / rho0 (unburnt: F = 1)."""
    f, g = _fg(mat, eta, jwl, gr)
    p_eos = f + g * E
    d = 1e-6 * eta
    fp, gp = _fg(mat, eta + d, jwl, gr)
    fm, gm = _fg(mat, eta - d, jwl, gr)
    c2 = ((fp + gp * E - fm - gm * E) / (2.0 * d) + p_eos * g / (eta * eta)) / rho0
    return max(frac * p_eos, cutoff), math.sqrt(max(c2, 1.0))


@njit(cache=True)
def _fraction(burn, t, t_light, delta, D):
    if burn == 1:
        return 1.0
    return min(1.0, max(0.0, (t - t_light) * D / (1.5 * delta)))


@njit(cache=True)
def _vol(k, r0, r1):
    return (r1 ** (k + 1) - r0 ** (k + 1)) / (k + 1)


@njit(cache=True)
def _march(r, u, m, M, e, p, q, c, rho0, mat, t_light, delta, jwl, gr, cutoff, burn, k, cq, cl, cfl,
           piston, clock, t_stop, radii, times, hist):
    """Steps until clock[0] >= t_stop or the history buffers are full; returns the samples written.

    One predictor-corrector step (Caramana et al. 1998, sec. 5): forces at t + dt/2, the energy takes
    exactly the nodal forces' work, so sum(m e) + sum(M u^2)/2 changes only by a piston's work.
    """
    n = len(m)
    nn = n + 1
    uh = np.empty(nn)
    rh = np.empty(nn)
    u1 = np.empty(nn)
    sig = np.empty(n)
    qh = np.empty(n)
    rc = np.empty(n)
    pos = np.empty(nn)
    ns = 0
    D = jwl[5]
    while clock[0] < t_stop and ns < len(times):
        t = clock[0]
        dt = 1e30
        for j in range(n):
            du = u[j + 1] - u[j]
            Q = cl * c[j] + (cq * cq * (-du) if du < 0.0 else 0.0)
            dt = min(dt, (r[j + 1] - r[j]) / (Q + math.sqrt(Q * Q + c[j] * c[j])))
        dt *= cfl
        # predictor: velocities and the state at t + dt/2 from the forces at t
        for j in range(n):
            sig[j] = p[j] + q[j]
        for i in range(nn):
            rh[i] = r[i] + 0.5 * dt * u[i]
            if 0 < i < n:
                uh[i] = u[i] + 0.5 * dt * r[i] ** k * (sig[i - 1] - sig[i]) / M[i]
        uh[0] = piston if k == 0 else 0.0
        uh[n] = 0.0
        for j in range(n):
            v0 = _vol(k, r[j], r[j + 1])
            vh = _vol(k, rh[j], rh[j + 1])
            eh = e[j] - sig[j] * (vh - v0) / m[j]
            frac = 1.0 if mat[j] == 1 else _fraction(burn, t + 0.5 * dt, t_light[j], delta[j], D)
            f, g = _fg(mat[j], m[j] / vh / rho0[j], jwl, gr)
            ph = max(frac * (f + g * rho0[j] * eh), cutoff)
            du = uh[j + 1] - uh[j]
            if du < 0.0:
                v1 = _vol(k, r[j] + dt * uh[j], r[j + 1] + dt * uh[j + 1])
                qh[j] = 2.0 * m[j] / (v0 + v1) * (cq * cq * du * du - cl * c[j] * du)
            else:
                qh[j] = 0.0
            sig[j] = ph + qh[j]
        # corrector: velocity to t + dt; energy from the same forces' work (flux = A ubar)
        for i in range(nn):
            u1[i] = u[i]
            if 0 < i < n:
                u1[i] = u[i] + dt * rh[i] ** k * (sig[i - 1] - sig[i]) / M[i]
        u1[0] = piston if k == 0 else 0.0
        u1[n] = 0.0
        for i in range(nn):
            pos[i] = 0.5 * (u[i] + u1[i]) * (rh[i] ** k if 0 < i < n else (1.0 if k == 0 else 0.0))
        for j in range(n):
            e[j] -= dt * sig[j] * (pos[j + 1] - pos[j]) / m[j]
        for i in range(nn):
            r[i] += dt * 0.5 * (u[i] + u1[i])
            u[i] = u1[i]
        t += dt
        clock[0] = t
        for j in range(n):
            q[j] = qh[j]
            eta = m[j] / _vol(k, r[j], r[j + 1]) / rho0[j]
            frac = 1.0 if mat[j] == 1 else _fraction(burn, t, t_light[j], delta[j], D)
            p[j], c[j] = _zone_state(mat[j], eta, rho0[j] * e[j], frac, rho0[j], cutoff, jwl, gr)
            rc[j] = 0.5 * (r[j] + r[j + 1])
        times[ns] = t
        hist[ns, :] = np.interp(radii, rc, p)
        ns += 1
    return ns


class Lagrangian1D:
    """The state of the staggered Lagrangian scheme (module docstring) and its march in time."""

    def __init__(self, setup: BlastSetup, r: np.ndarray, n_he: int, geometry: str = "spherical",
                 burn: str = "programmed", cq: float = 1.5, cl: float = 0.3, cfl: float = 0.5):
        self.k = EXPONENT[geometry]
        self.setup, self.cq, self.cl, self.cfl = setup, cq, cl, cfl
        self.burn = {"programmed": 0, "instantaneous": 1}[burn]
        self.r = np.array(r, dtype=float)
        self.u = np.zeros_like(self.r)
        nz = len(self.r) - 1
        self.mat = np.where(np.arange(nz) < n_he, 0, 1).astype(np.int64)
        ex, wa = setup.explosive, setup.water
        self.rho0 = np.where(self.mat == 0, ex.rho0, wa.rho0)
        self.m = self.rho0 * self.volume()
        self.M = np.zeros_like(self.r)
        self.M[:-1] += 0.5 * self.m
        self.M[1:] += 0.5 * self.m
        self.e = np.where(self.mat == 0, ex.e0, wa.e0) / self.rho0            # specific, J/kg
        self.t_light = 0.5 * (self.r[1:] + self.r[:-1]) / ex.detonation_velocity
        self.delta = np.diff(self.r)
        self.jwl = np.array([ex.A, ex.B, ex.R1, ex.R2, ex.omega, ex.detonation_velocity])
        self.gr = np.array([wa.rho0 * wa.c ** 2, wa.s1, wa.s2, wa.s3, wa.gamma0, wa.a])
        self.clock = np.zeros(1)
        self.q = np.zeros(nz)
        self.p, self.c = np.zeros(nz), np.zeros(nz)
        for j in range(nz):
            frac = 1.0 if self.mat[j] == 1 else _fraction(self.burn, 0.0, self.t_light[j], self.delta[j],
                                                          ex.detonation_velocity)
            self.p[j], self.c[j] = _zone_state(self.mat[j], 1.0, self.rho0[j] * self.e[j], frac, self.rho0[j],
                                               setup.pressure_cutoff, self.jwl, self.gr)
        self.piston = 0.0          # velocity of node 0 in the planar geometry

    @property
    def t(self) -> float:
        return float(self.clock[0])

    def volume(self):
        return np.diff(self.r ** (self.k + 1)) / (self.k + 1)

    def march(self, t_stop: float, radii, chunk: int = 200000):
        """Advance to t_stop; returns (times, pressures (n_t, n_r)) at `radii` after every step."""
        radii = np.atleast_1d(np.asarray(radii, dtype=float))
        ts, ps = [], []
        while self.t < t_stop:
            times, hist = np.empty(chunk), np.empty((chunk, len(radii)))
            ns = _march(self.r, self.u, self.m, self.M, self.e, self.p, self.q, self.c, self.rho0, self.mat,
                        self.t_light, self.delta, self.jwl, self.gr, self.setup.pressure_cutoff, self.burn,
                        self.k, self.cq, self.cl, self.cfl, self.piston, self.clock, t_stop, radii, times, hist)
            ts.append(times[:ns])
            ps.append(hist[:ns])
        if not ts:
            return np.empty(0), np.empty((0, len(radii)))
        return np.concatenate(ts), np.concatenate(ps)

    def energy(self):
        """(internal, kinetic) J per unit solid angle (per unit area in the slab)."""
        return float(np.sum(self.m * self.e)), float(0.5 * np.sum(self.M * self.u ** 2))


def blast(setup: BlastSetup, dr: float, radii, t_end: float | None = None, geometry: str = "spherical",
          burn: str = "programmed", r_max: float | None = None, **scheme) -> dict:
    """Pressure histories p(t) at the fixed radii `radii` (m) of the charge of `setup`, zone size `dr`.

    t_end defaults to the sound's travel to the farthest radius plus 80 us (the peak and its decay
    to 1/e at 25 charge radii); r_max (the rigid outer wall) defaults to a distance the reflection
    from which cannot reach the farthest radius before t_end. Returns times, pressures (n_t, n_r),
    the energy (internal, kinetic) at the start and the end, and the step count.
    """
    radii = np.atleast_1d(np.asarray(radii, dtype=float))
    c_w = setup.water.c
    if t_end is None:
        t_end = radii.max() / c_w + 8.0e-5
    if r_max is None:
        r_max = radii.max() + 0.6 * c_w * max(t_end - radii.max() / (2.0 * c_w), 0.0) + 20 * dr
    r, n_he = _grid(setup, dr, r_max)
    h = Lagrangian1D(setup, r, n_he, geometry, burn, **scheme)
    e_start = h.energy()
    p0 = np.interp(radii, 0.5 * (h.r[1:] + h.r[:-1]), h.p)
    t, p = h.march(t_end, radii)
    return {"t": np.concatenate([[0.0], t]), "p": np.vstack([p0, p]), "radii": radii, "energy_start": e_start,
            "energy_end": h.energy(), "steps": len(t), "zones": len(h.m)}


def peaks(result: dict) -> dict:
    """Per radius: the peak pressure, its time and theta (time from the peak to peak/e; nan if not reached)."""
    t, p = result["t"], result["p"]
    k = np.argmax(p, axis=0)
    out = {"peak": p[k, np.arange(p.shape[1])], "t_peak": t[k], "theta": np.full(p.shape[1], np.nan)}
    for i, ki in enumerate(k):
        level = p[ki, i] / math.e
        below = np.nonzero(p[ki:, i] <= level)[0]
        if len(below):
            j = ki + below[0]
            s = (p[j - 1, i] - level) / (p[j - 1, i] - p[j, i])
            out["theta"][i] = t[j - 1] + s * (t[j] - t[j - 1]) - t[ki]
    return out


def cole_peak(w: float, radius, k: float = COLE_P[0], alpha: float = COLE_P[1]):
    """Cole's similitude P_max = K (W^(1/3)/R)^alpha, Pa (W kg TNT, R m)."""
    return k * (w ** (1.0 / 3.0) / np.asarray(radius, dtype=float)) ** alpha


def cole_theta(w: float, radius, k: float = COLE_THETA[0], alpha: float = COLE_THETA[1]):
    """Cole's decay constant theta = K W^(1/3) (W^(1/3)/R)^alpha, s."""
    return k * w ** (1.0 / 3.0) * (w ** (1.0 / 3.0) / np.asarray(radius, dtype=float)) ** alpha


def piston(setup: BlastSetup, u_piston: float, dx: float, length: float, t_end: float, **scheme) -> dict:
    """A planar piston driven at u_piston into the deck's water at rest (no explosive): the zones'
    pressure, velocity and density at t_end, for the Hugoniot check against `water_hugoniot`."""
    water_only = setup.replace(charge_radius=0.0)
    r = np.linspace(0.0, length, round(length / dx) + 1)
    h = Lagrangian1D(water_only, r, 0, "planar", **scheme)
    h.piston = u_piston
    h.march(t_end, [0.5 * length])
    return {"x": 0.5 * (h.r[1:] + h.r[:-1]), "p": h.p.copy(), "u": 0.5 * (h.u[1:] + h.u[:-1]),
            "rho": h.m / np.diff(h.r), "t": h.t, "energy": h.energy()}


def water_hugoniot(water: Gruneisen, up: float) -> dict:
    """The Rankine-Hugoniot state of the EOS behind a shock of particle speed up into water at rest:
    mass rho0 Us = rho (Us - up), momentum p = rho0 Us up, energy E = rho0 up^2/2 (per reference
    volume), p = f(eta) + g(eta) E, solved for Us by bisection. For S2 = S3 = a = 0 it returns
    Us = C + S1 up (the form of the LS-DYNA Gruneisen compressed branch)."""
    lo, hi = water.c, water.c + 10.0 * up * max(water.s1, 1.0) + 10.0
    for _ in range(200):
        us = 0.5 * (lo + hi)
        eta = us / (us - up)
        f, g = water.fg(np.array([eta]))
        resid = float(f[0] + g[0] * 0.5 * water.rho0 * up * up) - water.rho0 * us * up
        lo, hi = (us, hi) if resid > 0.0 else (lo, us)
    return {"Us": 0.5 * (lo + hi), "p": water.rho0 * 0.5 * (lo + hi) * up, "eta": eta}
