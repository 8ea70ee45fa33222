"""Ready-made SPH scenes: the verification and benchmark cases as ``SphSystem`` builders.

Each builder takes the geometry and resolution and any ``SphOptions`` field as a keyword to
override its defaults. Materials are packed from the deck schema models (``materials.tables``).
"""
from __future__ import annotations

import math

import numpy as np
from pydantic import TypeAdapter

from ..deck.schema.materials import EquationOfState, Material
from . import lattice
from .options import SphOptions, material_table
from .system import SphSystem
from .walls import box_walls

_MAT = TypeAdapter(Material)
_EOS = TypeAdapter(EquationOfState)


def water(c0: float, rho0: float = 1000.0, viscosity: float = 0.0, gamma: float = 7.0):
    """Material table of one Tait liquid (weakly compressible water)."""
    mat = _MAT.validate_python({"type": "fluid", "density": rho0, "viscosity": viscosity, "eos": "water"})
    eos = _EOS.validate_python({"type": "tait", "reference_density": rho0, "sound_speed": c0, "gamma": gamma})
    return material_table([(mat, eos)])


def ideal_gas(gamma: float = 1.4, rho0: float = 1.0):
    """Material table of one ideal gas."""
    mat = _MAT.validate_python({"type": "fluid", "density": rho0, "eos": "gas"})
    eos = _EOS.validate_python({"type": "ideal_gas", "gamma": gamma})
    return material_table([(mat, eos)])


def _options(defaults: dict, overrides: dict) -> SphOptions:
    return SphOptions(**{**defaults, **overrides})


def still_water(depth: float = 1.0, width: float = 1.0, dx: float = 0.025, g: float = 9.81,
                c0: float | None = None, **options) -> SphSystem:
    """2D tank [0, width] x [0, depth] full of water at rest, hydrostatic density, ghost walls on
    the left, right and bottom (slip); c0 = 10 sqrt(g depth) unless given."""
    c0 = 10.0 * math.sqrt(g * depth) if c0 is None else c0
    mats = water(c0)
    x = lattice.box([0.0, 0.0], [width, depth], dx)
    mat = np.zeros(len(x), dtype=np.int64)
    rho = lattice.hydrostatic_density(x, mats[1], mat, [0.0, -g], [0.0, depth])
    mass, rho = lattice.lattice_particles(x, dx, rho)
    walls = box_walls([0.0, 0.0], [width, depth], ["left", "right", "bottom"])
    opt = _options({"alpha": 0.02, "delta": 0.1, "gravity": [0.0, -g], "walls": walls}, options)
    return SphSystem(x, np.zeros_like(x), mass, rho, mat, mats, opt)


def dam_break(a: float = 1.0, dx: float = 0.025, tank_length: float | None = None, dim: int = 2,
              depth: float | None = None, g: float = 9.81, c0: float | None = None, condition: str = "slip",
              viscosity: float = 0.0, **options) -> SphSystem:
    """Water column a wide and 2a high at the left end of a dry tank (Martin & Moyce 1952).

    Tank [0, tank_length] (default 5a) with ghost walls (``condition`` slip or no_slip) left,
    right and bottom; water of dynamic ``viscosity`` (default inviscid); in 3D the
    tank is ``depth`` (default a) wide in z with walls at both sides. Hydrostatic start;
    c0 = 10 sqrt(2 g 2a) (ten times the largest free-fall speed) unless given.
    """
    tank_length = 5.0 * a if tank_length is None else tank_length
    c0 = 10.0 * math.sqrt(2.0 * g * 2.0 * a) if c0 is None else c0
    mats = water(c0, viscosity=viscosity)
    if dim == 2:
        lo, hi = [0.0, 0.0], [a, 2.0 * a]
        tank_hi = [tank_length, 4.0 * a]
        sides = ["left", "right", "bottom"]
    else:
        depth = a if depth is None else depth
        lo, hi = [0.0, 0.0, 0.0], [a, 2.0 * a, depth]
        tank_hi = [tank_length, 4.0 * a, depth]
        sides = ["left", "right", "bottom", "back", "front"]
    x = lattice.box(lo, hi, dx)
    mat = np.zeros(len(x), dtype=np.int64)
    gvec = [0.0, -g] + [0.0] * (dim - 2)
    rho = lattice.hydrostatic_density(x, mats[1], mat, gvec, [0.0, 2.0 * a] + [0.0] * (dim - 2))
    mass, rho = lattice.lattice_particles(x, dx, rho)
    walls = box_walls([0.0] * dim, tank_hi, sides, condition)
    domain = ([-a] * dim, [tank_length + a, 8.0 * a] + [tank_hi[-1] + a] * (dim - 2))
    opt = _options({"alpha": 0.1, "delta": 0.1, "gravity": gvec, "walls": walls, "domain": domain}, options)
    return SphSystem(x, np.zeros_like(x), mass, rho, mat, mats, opt)


def ring_particles(x: np.ndarray, dx: float, rho: np.ndarray) -> np.ndarray:
    """Ring masses of lattice particles in the meridian plane (axisymmetric): m = 2 pi r rho dx^2, full 2 pi."""
    return 2.0 * math.pi * x[:, 0] * np.asarray(rho, dtype=np.float64) * dx * dx


def still_water_cylinder(depth: float = 1.0, radius: float = 0.5, dx: float = 0.025, g: float = 9.81,
                         c0: float | None = None, **options) -> SphSystem:
    """Axisymmetric water column at rest in a cylinder: meridian plane [0, radius] x [0, depth]
    (x = r, y = z, gravity along -z), hydrostatic density, slip ghost walls at r = radius and on the
    floor, the axis r = 0 a reflecting ghost line (``SphOptions.axisymmetric``); c0 = 10 sqrt(g depth)."""
    c0 = 10.0 * math.sqrt(g * depth) if c0 is None else c0
    mats = water(c0)
    x = lattice.box([0.0, 0.0], [radius, depth], dx)
    mat = np.zeros(len(x), dtype=np.int64)
    rho = lattice.hydrostatic_density(x, mats[1], mat, [0.0, -g], [0.0, depth])
    walls = box_walls([0.0, 0.0], [radius, depth], ["right", "bottom"])
    opt = _options({"alpha": 0.02, "delta": 0.1, "gravity": [0.0, -g], "walls": walls, "axisymmetric": True},
                   options)
    return SphSystem(x, np.zeros_like(x), ring_particles(x, dx, rho), rho, mat, mats, opt)


def noh_sphere_axisymmetric(dx: float = 0.02, radius: float = 1.2, gamma: float = 5.0 / 3.0, **options) -> SphSystem:
    """Noh's (1987) spherical implosion as an axisymmetric SPH system: the ball of ``radius`` about the
    origin in the meridian plane (x = r > 0, y = z), an ideal gas of density 1, specific energy 1e-6
    (p ~ 0) and velocity -x/|x| (unit speed towards the centre), lattice spacing dx, no walls (the axis
    is the ghost line). Exact (gamma 5/3): a shock at R = t/3, density 64 behind it, (1 + t/R)^2 ahead.
    Monaghan alpha = 1, beta = 2 (a strong shock), no density diffusion."""
    mats = ideal_gas(gamma=gamma, rho0=1.0)
    x = lattice.box([0.0, -radius], [radius, radius], dx)
    dist = np.linalg.norm(x, axis=1)
    x = x[dist < radius]
    dist = dist[dist < radius]
    rho = np.ones(len(x))
    opt = _options({"alpha": 1.0, "beta": 2.0, "eps": 0.01, "delta": 0.0, "axisymmetric": True}, options)
    return SphSystem(x, -x / dist[:, None], ring_particles(x, dx, rho), rho, np.zeros(len(x), dtype=np.int64), mats,
                     opt, energy=np.full(len(x), 1e-6))


def noh_disk(dx: float = 0.02, radius: float = 1.0, gamma: float = 5.0 / 3.0, **options) -> SphSystem:
    """Noh's (1987) cylindrical implosion in plane 2D: the disk of ``radius`` about the origin, an ideal gas
    of density 1, specific energy 1e-6 (p ~ 0) and velocity -x/|x| (unit speed towards the centre),
    lattice spacing dx, no walls. Exact: a shock at R = (gamma - 1)/2 t (t/3 for gamma 5/3), density
    ((gamma + 1)/(gamma - 1))^2 = 16 behind it, 1 + t/R ahead (``noh_density``). Monaghan alpha = 1,
    beta = 2, no density diffusion, the mass form of the continuity equation (docs/theory/sph.md "Noh")."""
    mats = ideal_gas(gamma=gamma, rho0=1.0)
    x = lattice.box([-radius, -radius], [radius, radius], dx)
    dist = np.linalg.norm(x, axis=1)
    x = x[dist < radius]
    dist = dist[dist < radius]
    rho = np.ones(len(x))
    opt = _options({"alpha": 1.0, "beta": 2.0, "eps": 0.01, "delta": 0.0, "continuity": "mass"}, options)
    return SphSystem(x, -x / dist[:, None], rho * dx * dx, rho, np.zeros(len(x), dtype=np.int64), mats, opt,
                     energy=np.full(len(x), 1e-6))


def noh_density(r, t: float, dim: int, gamma: float = 5.0 / 3.0):
    """Exact density of Noh's implosion (unit inflow speed, density 1, cold gas) in ``dim`` = 2 (cylinder)
    or 3 (sphere) at radius r and time t: ((g+1)/(g-1))^dim behind the shock R = (g-1)/2 t,
    (1 + t/r)^(dim-1) ahead of it (Noh 1987, J. Comput. Phys. 72, 78)."""
    r = np.asarray(r, dtype=np.float64)
    shock = 0.5 * (gamma - 1.0) * t
    post = ((gamma + 1.0) / (gamma - 1.0)) ** dim
    return np.where(r < shock, post, (1.0 + t / np.maximum(r, 1e-300)) ** (dim - 1))
