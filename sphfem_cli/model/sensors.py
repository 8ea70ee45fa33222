"""Sample points and weights of a sensor of finite size: the mean of a field over a transducer's face
(or over a disc / ball), as a quadrature rule  <q> = Σ_i w_i q(x_i),  Σ_i w_i = 1.

Shapes (D the diameter, R = D/2, c the centre):

- ``face`` (a ``normal`` n is given): the transducer's face in the wall, perpendicular to n. In 2D a
  segment of length D along the tangent t = (-n_y, n_x): Gauss–Legendre in s ∈ [-R, R], exact for
  polynomials of degree 2·G − 1 along it. In 3D a disc of radius R in the plane ⊥ n: polar rule below.
- ``disc`` (2D, no normal) and the 3D face: polar rule, x = c + r (cos θ e1 + sin θ e2), mean
  (1/πR²)∫∫ q r dr dθ with Gauss–Legendre in r ∈ [0, R] (weight ∝ r) and M equally spaced θ (the
  trapezoidal rule, exact for trigonometric polynomials of degree < M).
- ``ball`` (3D, no normal): x = c + r (sin φ cos θ, sin φ sin θ, cos φ), mean (3/4πR³)∫ q r² dr dΩ with
  Gauss–Legendre in r (weight ∝ r²) and in cos φ, equally spaced θ.

With G = 4 Gauss points (exact to degree 2G − 1 = 7) and M = 8 angles (exact for trigonometric
degree < 8), a polynomial of total degree k in the coordinates is averaged exactly up to k = 7 on
the segment, k = 6 on a disc (radial integrand r^(k+1)) and k = 5 in the ball (r^(k+2)):
tests/unit/test_probe_sensor.py checks linear and quadratic fields.

A diameter of zero (no sensor) gives the single point c with weight 1.
"""
from __future__ import annotations

import numpy as np

GAUSS = 4   # Gauss–Legendre points along the radius / the segment / cos φ
ANGLES = 8  # equally spaced angles θ


def _gauss01(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on [0, 1] (weights sum to 1)."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def _frame(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors spanning the plane ⊥ normal (3D)."""
    n = normal / np.linalg.norm(normal)
    helper = np.eye(3)[int(np.argmin(np.abs(n)))]
    e1 = np.cross(n, helper)
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(n, e1)


def _polar(centre: np.ndarray, radius: float, e1: np.ndarray, e2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Mean over the disc of `radius` centred at `centre` in the plane of the unit vectors e1, e2."""
    s, ws = _gauss01(GAUSS)
    r = radius * s
    wr = ws * 2.0 * s  # (1/πR²) ∫_0^R r dr ∫ dθ: weight 2 s ds on s ∈ [0, 1], θ mean
    theta = 2.0 * np.pi * (np.arange(ANGLES) + 0.5) / ANGLES
    pts = centre + r[:, None, None] * (np.cos(theta)[None, :, None] * e1 + np.sin(theta)[None, :, None] * e2)
    w = np.repeat(wr / ANGLES, ANGLES)
    return pts.reshape(-1, len(centre)), w


def sensor_points(centre, diameter: float, normal=None) -> tuple[np.ndarray, np.ndarray]:
    """(points (P, dim), weights (P,)) of the mean over the sensor (module docstring); dim = len(centre)."""
    c = np.asarray(centre, dtype=float)
    dim = len(c)
    if diameter <= 0.0:
        return c[None, :].copy(), np.ones(1)
    radius = 0.5 * float(diameter)
    if normal is not None:
        n = np.asarray(normal, dtype=float)
        n = n / np.linalg.norm(n)
        if dim == 2:
            t = np.array([-n[1], n[0]])
            s, ws = _gauss01(GAUSS)
            return c + (2.0 * s - 1.0)[:, None] * radius * t, ws
        e1, e2 = _frame(n)
        return _polar(c, radius, e1, e2)
    if dim == 2:
        return _polar(c, radius, np.array([1.0, 0.0]), np.array([0.0, 1.0]))
    s, ws = _gauss01(GAUSS)
    wr = ws * 3.0 * s ** 2  # (3/R³) ∫_0^R r² dr
    mu, wmu = _gauss01(GAUSS)
    mu = 2.0 * mu - 1.0  # cos φ on [-1, 1], mean weight wmu
    theta = 2.0 * np.pi * (np.arange(ANGLES) + 0.5) / ANGLES
    sin_phi = np.sqrt(1.0 - mu ** 2)
    dirs = np.stack([sin_phi[:, None] * np.cos(theta)[None, :], sin_phi[:, None] * np.sin(theta)[None, :],
                     np.repeat(mu[:, None], ANGLES, axis=1)], axis=-1).reshape(-1, 3)
    wdir = np.repeat(wmu / ANGLES, ANGLES)
    pts = c + (radius * s)[:, None, None] * dirs[None, :, :]
    w = wr[:, None] * wdir[None, :]
    return pts.reshape(-1, 3), w.ravel()


def sensor_mean(values: np.ndarray, weights: np.ndarray) -> float:
    """Σ w_i q_i over the sample points; a point no fluid reaches (NaN: dry, above the free surface)
    reads the ambient gauge pressure 0, as the dry part of a transducer's face does."""
    return float(np.dot(weights, np.where(np.isfinite(values), values, 0.0)))


_CACHE: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}


def probe_sensor_points(probe) -> tuple[np.ndarray, np.ndarray]:
    """The sample points (P, dim) of a deck probe's sensor and their weights, computed once per sensor."""
    key = (tuple(probe.point), probe.sensor.diameter, None if probe.sensor.normal is None else tuple(probe.sensor.normal))
    if key not in _CACHE:
        _CACHE[key] = sensor_points(probe.point, probe.sensor.diameter, probe.sensor.normal)
    return _CACHE[key]
