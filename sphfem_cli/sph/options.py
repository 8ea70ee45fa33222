"""The SPH fluid's settings as plain data: ``SphOptions`` (the numerical options, resolved once from a deck's SPH
section and walls by ``model.options``), ``WallParticles`` (fixed dummy wall particles) and the material table
(``material_table``). Nothing here compiles; ``system.SphSystem`` takes them.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .walls import Wall


@dataclass
class SphOptions:
    """Numerical options of an SPH fluid (defaults in brackets).

    kernel: "cubic_spline" or "wendland_c2" ["cubic_spline"]; smoothing_ratio: h/dx [1.2];
    alpha, beta, eps: Monaghan viscosity [0.1, 0.0, 0.01]; delta: delta-SPH density diffusion
    coefficient, 0 = off [0.0]; density_diffusion_form: "molteni_colagrossi" or "delta_plus" (Antuono
    et al. 2010's renormalised-gradient correction, ``sph.diffusion``) ["molteni_colagrossi"];
    delta_hydrostatic: subtract the hydrostatic density difference in the diffusion (Fourtakas-type,
    linearised; not with delta_plus, which removes any linear density field) [False]; xsph: XSPH coefficient, 0 = off [0.0];
    pressure_cutoff: lowest pressure a particle carries (cavitation) [-inf]; dilatational_viscosity mu' [0.0];
    walls: ghost-particle walls and non-reflecting open sides [()]; ghost_hydrostatic: add the hydrostatic increments
    dp = rho g.(x_ghost - x) and drho = dp/c^2 to the ghost's pressure and density [False, the
    paper's plain mirror]; domain: (lo, hi) box outside which particles are
    deactivated [None]; gravity: body acceleration [zero]; cfl, force_factor, viscous_factor:
    time-step constants [0.25, 0.25, 0.125]; reorder_every: evaluations between reorderings of
    the particle arrays, 0 = never [20]; max_cells_per_point: cell-grid size limit [4];
    axisymmetric: the 2D points are the meridian plane x = r > 0, y = the axis, masses are ring masses
    for the full 2 pi, the axis r = 0 is a slip ghost wall added here, and the rates are
    ``sph.axisymmetric``'s [False] (slip ghost walls only: no dummy wall particles, no viscous
    material, no no-slip or wall-function walls); continuity: the form of the continuity equation,
    "volume" drho_i/dt = rho_i sum_j V_j v_ij.grad W (the paper's eq. 3.8) or "mass" sum_j m_j
    v_ij.grad W (Monaghan 1992), see ``rates.fluid_rates`` and docs/theory/sph.md ["volume"];
    switch_alpha_max: the shock switch's ceiling alpha_max, None = no switch (``sph/switch.py``: a per-particle
    alpha_i from alpha (the floor) towards alpha_max where the fluid is compressed, beta_ij = (beta/alpha)
    alpha_ij) [None]; switch_decay: its decay constant l, tau_i = h_i / (l c_i) [0.1].
    """

    kernel: str = "cubic_spline"
    smoothing_ratio: float = 1.2
    alpha: float = 0.1
    beta: float = 0.0
    eps: float = 0.01
    delta: float = 0.0
    density_diffusion_form: str = "molteni_colagrossi"
    delta_hydrostatic: bool = False
    xsph: float = 0.0
    pressure_cutoff: float = -np.inf
    dilatational_viscosity: float = 0.0
    walls: Sequence[Wall] = ()
    ghost_hydrostatic: bool = False
    domain: tuple | None = None
    gravity: Sequence[float] | None = None
    cfl: float = 0.25
    force_factor: float = 0.25
    viscous_factor: float = 0.125
    reorder_every: int = 20
    max_cells_per_point: int = 4
    axisymmetric: bool = False
    continuity: str = "volume"
    switch_alpha_max: float | None = None
    switch_decay: float = 0.1


@dataclass
class WallParticles:
    """Fixed dummy wall particles (Adami et al. 2012) for walls of any shape.

    ``positions`` (Nw, dim) at spacing ``spacing``; volume spacing^dim, mass rho0 spacing^dim of
    material ``material``; ``velocities`` (Nw, dim), zero by default (used in continuity,
    viscosity and the viscous stress; the wall itself never moves).
    """

    positions: np.ndarray
    spacing: float
    material: int = 0
    velocities: np.ndarray | None = None


def material_table(entries) -> tuple[np.ndarray, np.ndarray]:
    """``(type ids (M,), rows (M, NPARAM))`` from ``[(material_model, eos_model), ...]``."""
    from ..materials.tables import pack_material

    ids, rows = [], []
    for mat, eos in entries:
        t, p = pack_material(mat, eos)
        ids.append(t)
        rows.append(p)
    return np.asarray(ids, dtype=np.int64), np.asarray(rows, dtype=np.float64)
