"""What a model must satisfy at t = 0 beyond the deck's schema: valid elements, usable densities and moduli.

Each check raises ``build.ModelError`` with the deck path to point at (the CLI turns it into
``file:line:col: path: message``, exit 65), so a deck that passes ``sphfem check`` does not fail
at the first step on an inverted element or a degenerate particle state.
"""
from __future__ import annotations

import numpy as np

from ..materials.slots import P_E, P_G, P_K, P_RHO0
from . import mesh as meshgen

SPH_DENSITY_RATIO = 2.0
"""Largest factor between a particle's initial density and its material's density (``particle_density``)."""


def particle_density(model, deck, used: np.ndarray, local: np.ndarray, density: np.ndarray,
                     owners: np.ndarray) -> None:
    """Every particle's initial density in DENSITY_RANGE and within a factor SPH_DENSITY_RATIO of its
    material's density.

    h = smoothing_ratio (m / rho)^(1/dim) sizes the kernel and the neighbour grid, and m = density
    dx^dim; with rho far from that density h leaves dx (a reference density of 1e30 against 1000
    gave h = 1e-16 dx and a grid of 1e32 cells: found by fuzzing).
    """
    from . import build

    for part in np.unique(owners):
        density_range(f"parts.{model.parts[part].name}.material", density[owners == part])
    ratio = density / model.material_param[used[local], P_RHO0]
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


def geometry_path(name: str, part) -> str:
    """Deck path of a part's geometry; of its file name (``geometry.file.file``) for a mesh file."""
    kind = part.geometry.kind
    return f"parts.{name}.geometry.{kind}" + (".file" if kind == "file" else "")


COORDINATE_BOUND = 1.0e100  # |x| of any node: the cube of a size below it stays finite in double precision


_CHECK_CHUNK = 1 << 16
"""Elements per chunk of ``elements``' corner Jacobians (2 MB of quad4 corners)."""


def elements(name: str, part, mesh: meshgen.MeshData) -> None:
    """A mesh the elements can work with: finite coordinates within COORDINATE_BOUND, every corner Jacobian positive.

    A corner Jacobian <= 0 (``mesh.corner_jacobians``) is an inverted, collapsed or re-entrant
    element at t = 0; the error names the part, the element (0-based, in the part's order) and
    its corner.
    """
    from . import build

    where = geometry_path(name, part)
    if not np.all(np.isfinite(mesh.nodes)):
        raise build.ModelError(where, "the mesh has non-finite coordinates (check the sizes and units)")
    if np.abs(mesh.nodes).max(initial=0.0) > COORDINATE_BOUND:
        raise build.ModelError(where, f"the mesh has coordinates beyond {COORDINATE_BOUND:.0e} in magnitude, where an "
                                      "element's volume (a third power of its size) overflows (check the sizes and units)")
    first, count = None, 0  # the first bad element's (element, corner, shape), and how many are bad
    # by chunks of elements: the corner Jacobians of a whole 960^2 mesh were 29 MB of fresh memory
    for lo in range(0, len(mesh.elements), _CHECK_CHUNK):
        with np.errstate(over="ignore", invalid="ignore"):
            corners = meshgen.corner_jacobians(mesh.nodes, mesh.elements[lo:lo + _CHECK_CHUNK])
            bad = ~(np.isfinite(corners) & (corners > 0.0))
        if np.any(bad):
            count += int(bad.any(axis=1).sum())
            if first is None:
                e, c = np.unravel_index(int(np.argmax(bad)), bad.shape)
                first = (lo + e, c, "zero size" if np.all(corners[e] == 0.0) else "a corner Jacobian <= 0")
    if first is not None:
        e, c, shape = first
        raise build.ModelError(where, f"element {e} of part '{name}' is inverted, collapsed or re-entrant at "
                                      f"t = 0 ({shape} at its corner node {c}, {count} such "
                                      "element(s); check the sizes, the units and the mesh)")


def file_sets(deck, file_sets: dict) -> None:
    """Every ``<part>.<set>`` the deck names (not a deck set) is a set of that part's mesh file."""
    from . import build

    users = [(f"boundaries.{i}", b) for i, b in enumerate(deck.boundaries)] + \
            [(f"initial.{i}", c) for i, c in enumerate(deck.initial)] + \
            [(f"loads.{i}", ld) for i, ld in enumerate(deck.loads)] + \
            [(f"output.histories.{i}", h) for i, h in enumerate(deck.output.histories)]
    for path, item in users:
        name = getattr(item, "set", None)
        if name is None or name in deck.sets or name in file_sets:
            continue
        part = name.partition(".")[0]
        held = sorted(k.partition(".")[2] for k in file_sets if k.startswith(part + "."))
        raise build.ModelError(f"{path}.set", f"the mesh file of part '{part}' has no set '{name.partition('.')[2]}' "
                         f"(its sets: {', '.join(held) or 'none'})")


AXIS_TOLERANCE = 1e-12
"""Relative distance (to the part's largest |x|) within which a node is on the axis of an axisymmetric
model: r snapped to 0 there, an error below it."""


def radii(name: str, mesh) -> None:
    """Axisymmetric parts: every node at r = x >= 0; nodes within AXIS_TOLERANCE of the axis are put on it."""
    from . import build

    r = mesh.nodes[:, 0]
    scale = float(np.abs(r).max()) if len(r) else 0.0
    near = np.abs(r) <= AXIS_TOLERANCE * scale
    r[near] = 0.0
    if (r < 0.0).any():
        k = int(np.argmin(r))
        raise build.ModelError(f"parts.{name}.geometry",
                               f"node {k} is at r = x = {r[k]:g} < 0: an axisymmetric model lies in x = r >= 0 "
                               "(y is the axis)")
