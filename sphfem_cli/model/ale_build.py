"""Deck -> the ALE part of a Model: its mesh's material layout (fills, hydrostatic start) as an ``AleMesh``.

Called by ``build.build_model`` after it has meshed and checked the part; ``fill_region`` (a fill's
region as a predicate on coordinates) also labels the fills in ``study.derive``. Nothing here runs per step.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..deck.schema import Deck
from ..materials.slots import EOS_OFFSET, P_EOS_TYPE, P_RHO0, Q_E0, Q_RHO0
from . import checks
from .mesh import MeshData


@dataclass
class AleMesh:
    """The ALE part's mesh and initial material layout.

    `materials` are indices into the model's material table; `fractions`, `density`, `pressure`
    are (E, len(materials)); `velocity` (N, dim) nodal, or None when no fill sets one (at rest).
    """

    part: int
    nodes: np.ndarray
    elements: np.ndarray
    materials: list[int]
    fractions: np.ndarray
    density: np.ndarray
    pressure: np.ndarray
    velocity: np.ndarray | None


def ale_mesh(model, deck: Deck, index: int, mesh: MeshData) -> AleMesh:
    """Lay out the materials of the ALE part ``model.parts[index]``, meshed (and checked) as ``mesh``:
    the part's material, then each fill in order."""
    from ..ale.fill import fill_fractions
    from ..materials.tables import eos_state_set_up
    from . import build  # ModelError, VOID (imported here: build imports this module)
    name = model.parts[index].name
    part = deck.parts[name]
    nodes, conn = mesh.nodes, mesh.elements
    names = [part.material] + [f.material for f in part.fill if f.material != part.material]
    names = list(dict.fromkeys(names))
    mats = [model.material_names.index(n) for n in names]
    n_elem, n_mat = len(conn), len(mats)
    rho0 = np.array([model.material_param[m, P_RHO0] for m in mats])

    def state(m: int, density: float) -> float:
        row = model.material_param[m]
        if model.material_type[m] == build.VOID:
            return 0.0
        return float(eos_state_set_up(int(row[P_EOS_TYPE]), row[EOS_OFFSET:], density / row[P_RHO0],
                                      row[EOS_OFFSET + Q_E0])[0])

    fractions = np.zeros((n_elem, n_mat))
    fractions[:, 0] = 1.0
    density = np.tile(rho0, (n_elem, 1))
    pressure = np.tile(np.array([state(m, rho0[j]) for j, m in enumerate(mats)], dtype=float), (n_elem, 1))
    velocity = None  # made by the first fill with a velocity (at rest, a 960^2 mesh saves 15 MB of fresh memory)
    for j, fill in enumerate(part.fill):
        inside = fill_region(fill)
        try:
            f = fill_fractions(nodes, conn, inside, ring=model.axisymmetric)
        except ValueError as exc:
            raise build.ModelError(f"parts.{name}.fill.{j}", str(exc)) from None
        k = names.index(fill.material)
        fractions *= (1.0 - f)[:, None]
        fractions[:, k] += f
        hit = f > 0
        rho = fill.density if fill.density is not None else rho0[k]
        density[hit, k] = rho
        pressure[hit, k] = fill.pressure if fill.pressure is not None else state(mats[k], rho)
        if fill.velocity is not None:
            if velocity is None:
                velocity = np.zeros((len(nodes), model.dim))
            velocity[inside(*nodes.T)] = fill.velocity
        if part.hydrostatic and model.material_type[mats[k]] != build.VOID:
            hydrostatic_fill(model, deck, name, j, nodes, conn, f, mats[k], density[:, k], pressure[:, k])
    for k, m in enumerate(mats):
        if model.material_type[m] != build.VOID:
            checks.density_range(f"parts.{name}.material" if k == 0 else f"parts.{name}.fill", density[:, k])
    return AleMesh(index, nodes, conn, mats, fractions, density, pressure, velocity)


def hydrostatic_fill(model, deck: Deck, name: str, j: int, nodes, conn, f, m: int, density, pressure) -> None:
    """Hydrostatic pressure and density of one ALE fill (in place, on the elements it touches).

    Heights h are measured against gravity g. An element's part of the fill is taken as the lowest
    fraction f of its height span [h_lo, h_hi] (a horizontal free surface in a level-layered
    mesh); the fill's free surface s is the highest top h_lo + f (h_hi - h_lo) over its elements,
    the element's pressure p = rho0 |g| (s - h_c) at the middle h_c = h_lo + f (h_hi - h_lo) / 2 of
    its part, and its density solves p_eos(rho, e0) = p by Newton's method: rho <- rho - (p_eos(rho) - p) / c^2,
    c^2 = (dp/dmu + p dp/dE / r^2) / rho0 (r = rho / rho0; ``materials.kernels.eos_sound_speed``), from rho0 until
    |step| <= 1e-14 rho (at most 50 steps). All elements at once in numpy, each stopping at its own step:
    ``ale.at_rest.eos_state`` (the kernel ``eos_state``'s operations in its order, the C library's exp and pow)
    gives the bits the compiled ``eos_pressure`` and ``eos_sound_speed`` gave in the former per-element loop,
    with no kernel to compile or load before the first step.
    """
    from ..ale.at_rest import eos_state
    from ..deck.schema import Gravity
    from . import build

    dim = nodes.shape[1]
    g = sum((np.array(l.acceleration[:dim], dtype=float) for l in deck.loads
             if isinstance(l, Gravity) and (l.parts is None or name in l.parts)), np.zeros(dim))
    if not np.any(g):
        raise build.ModelError(f"parts.{name}.hydrostatic", "a hydrostatic start needs a gravity load on the part")
    up = -build.unit(g)
    hit = np.flatnonzero(f > 0)
    if not len(hit):  # a fill that covers no element has no hydrostatic state (found by fuzzing)
        return
    heights = nodes[conn[hit]] @ up  # (n, corners)
    lo, hi = heights.min(axis=1), heights.max(axis=1)
    top = lo + f[hit] * (hi - lo)
    surface = top.max()
    mid = lo + 0.5 * f[hit] * (hi - lo)
    row = model.material_param[m]
    rho0, eos, q = row[P_RHO0], int(row[P_EOS_TYPE]), np.ascontiguousarray(row[EOS_OFFSET:])
    p = rho0 * build.norm(g) * (surface - mid)
    rho = np.full(len(hit), rho0)
    active = np.arange(len(hit))  # the elements still iterating
    with np.errstate(all="ignore"):  # as the kernels: a non-finite state is the checks' to report
        for _ in range(50):
            r = rho[active] / rho0
            e0 = np.full(len(active), q[Q_E0])
            p_eos, dpdmu, dpde = eos_state(eos, q, r, e0)
            c2 = (dpdmu + p_eos * dpde / (r * r)) / q[Q_RHO0]
            c = np.sqrt(np.where(c2 > 0.0, c2, 0.0))  # 0 where c^2 <= 0 or NaN, as the kernel
            if np.any(c <= 0.0):
                raise build.ModelError(f"parts.{name}.fill.{j}", "hydrostatic start: the EOS has no sound speed at the "
                                       "reference density")
            step = (p_eos - p[active]) / (c * c)
            rho[active] -= step
            active = active[~(np.abs(step) <= 1e-14 * rho[active])]
            if not len(active):
                break
    density[hit] = rho
    pressure[hit] = p


def fill_region(fill):
    """inside(x, y) (2D) or inside(x, y, z) (3D) -> bool array for a fill's region."""
    if fill.box is not None:
        lo, hi = fill.box.min, fill.box.max
        return lambda *c: np.logical_and.reduce([(ck >= a) & (ck <= b) for ck, a, b in zip(c, lo, hi)])
    if fill.ball is not None:
        center, r = fill.ball.center, fill.ball.radius
        return lambda *c: sum((ck - a) ** 2 for ck, a in zip(c, center)) <= r * r
    if fill.cylinder is not None:
        cyl = fill.cylinder
        axis = "xyz".index(cyl.axis)
        center, r = cyl.center, cyl.radius
        half = np.inf if cyl.length is None else 0.5 * cyl.length

        def inside(*c):
            radial = sum((ck - a) ** 2 for k, (ck, a) in enumerate(zip(c, center)) if k != axis)
            return (radial <= r * r) & (np.abs(c[axis] - center[axis]) <= half)
        return inside
    if fill.polygon is not None:
        from ..sph.lattice import inside_polygon

        vertices = np.array(fill.polygon.vertices, dtype=float)
        return lambda x, y: inside_polygon(np.stack([np.ravel(x), np.ravel(y)], axis=1), vertices).reshape(np.shape(x))
    point, normal = fill.half_space.point, fill.half_space.normal
    return lambda *c: sum((ck - a) * n for ck, a, n in zip(c, point, normal)) <= 0.0
