"""What a model must satisfy at t = 0 beyond the deck's schema: valid elements, a usable fluid state.

Each check raises ``build.ModelError`` with the deck path to point at (the CLI turns it into
``file:line:col: path: message``, exit 65), so a deck that passes ``sphfem check`` does not fail
at the first step on an inverted element or a degenerate particle state.
"""
from __future__ import annotations

import numpy as np

from . import mesh as meshgen

SPH_DENSITY_RATIO = 2.0
"""Largest factor between a particle's initial density and its material's density (``particle_density``)."""


def particle_density(model, deck, used: np.ndarray, local: np.ndarray, density: np.ndarray,
                     owners: np.ndarray) -> None:
    """Every particle's initial density within a factor SPH_DENSITY_RATIO of its material's density.

    h = smoothing_ratio (m / rho)^(1/dim) sizes the kernel and the neighbour grid, and m = density
    dx^dim; with rho far from that density h leaves dx (a reference density of 1e30 against 1000
    gave h = 1e-16 dx and a grid of 1e32 cells: found by fuzzing).
    """
    from . import build

    ratio = density / model.material_param[used[local], 0]
    off = ~((ratio >= 1.0 / SPH_DENSITY_RATIO) & (ratio <= SPH_DENSITY_RATIO))
    if off.any():
        k = int(np.argmax(off))
        name = model.parts[owners[k]].name
        eos = getattr(deck.materials[deck.parts[name].material], "eos", None)
        where = f"parts.{name}.hydrostatic" if deck.parts[name].hydrostatic else f"parts.{name}.material"
        raise build.ModelError(where,
                               f"the initial particle density {density[k]:g} is {ratio[k]:.3g} times the material's density "
                               f"(allowed: 1/{SPH_DENSITY_RATIO:g} to {SPH_DENSITY_RATIO:g}): the material density "
                               f"and the reference density of equation of state '{eos}' disagree (check them and the units)")


DENSITY_RANGE = (float(np.sqrt(np.finfo(np.float64).tiny)), float(np.sqrt(np.finfo(np.float64).max)))
"""Densities whose square is a normal finite float64: the kernels divide by rho^2 (p / rho^2 in the
SPH momentum sum); 1e-300 made rho^2 underflow to 0 and the first step divide by zero (found by fuzzing)."""


def moduli(model) -> None:
    """Every solid material's E, G and K at most DENSITY_RANGE[1], so that its square is finite: the kernels
    multiply moduli together (E = 1e300 overflowed in the plastic return map of the first force pass; found
    by fuzzing). Tiny moduli are left to the solver's step guards (E = 1e-300 runs into them)."""
    from . import build
    from ..materials.kernels import P_E, P_G, P_K

    hi = DENSITY_RANGE[1]
    for m, name in enumerate(model.material_names):
        if model.material_param[m, P_E] == 0.0:
            continue  # a fluid (its K follows from the EOS) or void
        for slot, what in ((P_E, "Young's modulus"), (P_G, "shear modulus"), (P_K, "bulk modulus")):
            value = float(model.material_param[m, slot])
            if not abs(value) <= hi:
                raise build.ModelError(f"materials.{name}", f"the {what} {value:g} is over {hi:.3g}, where its "
                                                           "square overflows (check the constants and the units)")


def density_range(where: str, density: np.ndarray) -> None:
    """Every initial density in DENSITY_RANGE (about 1.5e-154 to 1.3e154)."""
    from . import build

    lo, hi = DENSITY_RANGE
    density = np.asarray(density, dtype=np.float64)
    off = ~((density >= lo) & (density <= hi))
    if off.any():
        raise build.ModelError(where, f"an initial density of {density.flat[int(np.argmax(off))]:g} is outside "
                                      f"[{lo:.3g}, {hi:.3g}], where its square is a normal number (the kernels "
                                      "divide by density^2; check the densities and the units)")


def fluid_state(model, deck, used: np.ndarray, local: np.ndarray, density: np.ndarray,
                owners: np.ndarray) -> None:
    """The EOS gives every particle a finite pressure and a positive finite sound speed at t = 0.

    Evaluated as the particle system does (``sph.kernels``: rho/rho0 and the EOS's initial energy)
    at each material's lowest and highest initial density (the EOSs are monotonic in density). A
    zero sound speed (density 1e-300 against a reference of 1000: c = c0 (1e-303)^3 underflows)
    divided the ghosts' hydrostatic correction by zero (found by fuzzing).
    """
    from ..materials.kernels import EOS_OFFSET, P_EOS_TYPE, P_RHO0, eos_pressure, eos_sound_speed

    from . import build

    for j in np.unique(local):
        first = int(np.flatnonzero(local == j)[0])
        density_range(f"parts.{model.parts[owners[first]].name}.material", density[local == j])
    for j, m in enumerate(used):
        row = model.material_param[m]
        q = np.ascontiguousarray(row[EOS_OFFSET:])
        mine = np.flatnonzero(local == j)
        for k in (mine[np.argmin(density[mine])], mine[np.argmax(density[mine])]):
            r = density[k] / row[P_RHO0]
            with np.errstate(all="ignore"):
                p, c = eos_pressure(int(row[P_EOS_TYPE]), q, r, q[1]), eos_sound_speed(int(row[P_EOS_TYPE]), q, r, q[1])
            if not (np.isfinite(p) and np.isfinite(c) and c > 0.0):
                name = model.parts[owners[k]].name
                raise build.ModelError(f"parts.{name}.material",
                                       f"at the initial density {density[k]:g} the equation of state of material "
                                       f"'{model.material_names[m]}' gives pressure {p:g} and sound speed {c:g} (a "
                                       "finite pressure and a positive sound speed are needed: check the densities, "
                                       "the EOS constants and the units)")


def geometry_path(name: str, part) -> str:
    """Deck path of a part's geometry; of its file name (``geometry.file.file``) for a mesh file."""
    kind = part.geometry.kind
    return f"parts.{name}.geometry.{kind}" + (".file" if kind == "file" else "")


def elements(name: str, part, mesh: meshgen.MeshData) -> None:
    """A mesh the elements can work with: finite coordinates, every corner Jacobian positive.

    A corner Jacobian <= 0 (``mesh.corner_jacobians``) is an inverted, collapsed or re-entrant
    element at t = 0; the error names the part, the element (0-based, in the part's order) and
    its corner.
    """
    from . import build

    where = geometry_path(name, part)
    if not np.all(np.isfinite(mesh.nodes)):
        raise build.ModelError(where, "the mesh has non-finite coordinates (check the sizes and units)")
    with np.errstate(over="ignore", invalid="ignore"):
        corners = meshgen.corner_jacobians(mesh.nodes, mesh.elements)
        bad = ~(np.isfinite(corners) & (corners > 0.0))
    if np.any(bad):
        e, c = np.unravel_index(int(np.argmax(bad)), bad.shape)
        shape = "zero size" if np.all(corners[e] == 0.0) else "a corner Jacobian <= 0"
        raise build.ModelError(where, f"element {e} of part '{name}' is inverted, collapsed or re-entrant at "
                                      f"t = 0 ({shape} at its corner node {c}, {int(bad.any(axis=1).sum())} such "
                                      "element(s); check the sizes, the units and the mesh)")
