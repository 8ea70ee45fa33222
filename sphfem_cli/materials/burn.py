"""Programmed burn of high explosives (LS-DYNA *MAT_HIGH_EXPLOSIVE_BURN with *INITIAL_DETONATION).

A high explosive is a fluid whose pressure is the JWL (or any EOS) pressure times a burn fraction
F in [0, 1] that depends only on time and position:

    t_L = min over detonation points k of (t_k + |x - x_k| / D)          (lighting time)
    F   = min(1, max(0, (t - t_L) D / (1.5 delta)))                         (burn fraction)
    p   = F p_eos(rho/rho0, E)

x is an ALE element's centroid (on the Eulerian mesh) or an SPH particle's initial position; D the
detonation velocity; delta the element's size A / L_max (area over longest edge; LS-DYNA's
"A_e,max / v_e" in 3D: face area over volume) or the particle spacing. This is LS-DYNA's
time-based fraction F1 = 2 (t - t_L) D A_emax / (3 v_e) (Keyword Manual Vol. II, material 8; Theory
Manual, "Material Model 8: High Explosive Burn"); the volumetric beta-burn F2 = (1 - V)/(1 - V_CJ)
is not used: this is LS-DYNA's BETA = 2 option (programmed burn only; its default BETA = 0 takes
max(F1, F2)). Without detonation points every point lights
at t = 0, as LS-DYNA does when no *INITIAL_DETONATION is given.

Plain NumPy: evaluated once per step on arrays of elements or particles.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np


def lighting_time(points: np.ndarray, detonations: Sequence[tuple[Sequence[float], float]], velocity: float) -> np.ndarray:
    """t_L (N,) of each point (N, dim): min over detonations (point, time) of time + distance / D."""
    pts = np.asarray(points, dtype=float)
    if not len(detonations):
        return np.zeros(len(pts))
    t = np.full(len(pts), np.inf)
    for point, time in detonations:
        x0 = np.asarray(point, dtype=float)[: pts.shape[1]]
        t = np.minimum(t, float(time) + np.linalg.norm(pts - x0, axis=1) / velocity)
    return t


def burn_fraction(time: float, t_light: np.ndarray, velocity: np.ndarray | float, delta: np.ndarray | float) -> np.ndarray:
    """F = min(1, max(0, (t - t_L) D / (1.5 delta))), elementwise."""
    return np.clip((time - t_light) * velocity / (1.5 * np.asarray(delta, dtype=float)), 0.0, 1.0)


def quad_size(nodes: np.ndarray, conn: np.ndarray) -> np.ndarray:
    """delta = area / longest edge of each quad4 (2D) element."""
    x = np.asarray(nodes, dtype=float)[conn]
    area = 0.5 * ((x[:, 2, 0] - x[:, 0, 0]) * (x[:, 3, 1] - x[:, 1, 1])
                  - (x[:, 2, 1] - x[:, 0, 1]) * (x[:, 3, 0] - x[:, 1, 0]))
    edges = np.linalg.norm(x - np.roll(x, -1, axis=1), axis=2).max(axis=1)
    return area / edges
