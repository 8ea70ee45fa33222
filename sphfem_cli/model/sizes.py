"""Model sizes from the deck alone: node, element and particle counts, and the memory check.

``check_memory`` refuses, before anything is allocated, a deck whose model (meshes, particles,
dummy wall particles) would not fit in the available memory; ``Model.memory_bytes`` uses the same
bytes per entity.
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..deck.schema import Deck

# Bytes a run holds per node, element and particle (model arrays, solver state, output buffers).
BYTES_PER_NODE = 400
BYTES_PER_ELEMENT = 900
BYTES_PER_PARTICLE = 1000


def _as_count(value) -> int:
    """A count from a float estimate; an overflowing or non-finite one (extreme geometry) becomes 10**18."""
    value = float(value)
    return int(value) if value < 1e18 else 10**18


@np.errstate(over="ignore", invalid="ignore")
def estimate_counts(deck: Deck, name: str) -> tuple[int, int, int]:
    """(nodes, elements, particles) a part will have, from the deck alone (0s for a mesh file)."""
    part = deck.parts[name]
    g = part.geometry
    if part.spacing is not None:  # SPH: the lattice cells inside the shape's bounding box
        if g.file is not None:
            return 0, 0, 0  # known once the file is read
        if g.box is not None:
            lengths = np.subtract(g.box.max, g.box.min)
        elif g.ball is not None:
            lengths = np.full(deck.dimension, 2.0 * g.ball.radius)
        else:
            lengths = np.ptp(np.array(g.polygon.vertices, dtype=float), axis=0)
        return 0, 0, _as_count(np.prod(np.maximum(np.rint(lengths / part.spacing), 1.0)))
    if g.box is not None:
        lengths = np.subtract(g.box.max, g.box.min)
        div = (np.array(g.box.divisions, dtype=float) if g.box.divisions is not None
               else np.maximum(np.rint(lengths / g.box.element_size), 1.0))
        return _as_count(np.prod(div + 1)), _as_count(np.prod(div)), 0
    if g.ring is not None or g.cylinder is not None:
        r = g.ring or g.cylinder
        layers = (g.cylinder.elements_along + 1) if g.cylinder is not None else 1
        per_layer = r.elements_around * (r.elements_through + 1) + (r.elements_around // 4 + 1) ** 2
        along = g.cylinder.elements_along if g.cylinder is not None else 1
        return per_layer * layers, per_layer * along, 0
    return 0, 0, 0


@np.errstate(over="ignore", invalid="ignore", divide="ignore")
def estimate_wall_particles(deck: Deck) -> int:
    """Dummy wall particles the deck's `dummy_wall` boundaries will lay (model/options.py), from the deck alone."""
    from ..deck.schema import DummyWallBoundary

    walls = [bc for bc in deck.boundaries if isinstance(bc, DummyWallBoundary)]
    spacings = [p.spacing for p in deck.parts.values() if p.spacing is not None]
    if not walls or not (walls[0].spacing or spacings):
        return 0
    dx = walls[0].spacing or min(spacings)
    total = 0.0
    for bc in walls:
        if bc.region is None:  # layers outside the box: the grown box less the box
            inner = np.maximum(np.rint(np.subtract(bc.max, bc.min) / dx), 1.0)
            total += np.prod(inner + 2 * bc.layers) - np.prod(inner)
        elif bc.region.box is not None:
            total += np.prod(np.maximum(np.rint(np.subtract(bc.region.box.max, bc.region.box.min) / dx), 1.0))
        elif bc.region.ball is not None:
            total += np.ceil(2.0 * bc.region.ball.radius / dx) ** len(bc.region.ball.center)
        else:
            total += np.prod(np.ceil(np.ptp(np.array(bc.region.polygon.vertices, dtype=float), axis=0) / dx))
    return _as_count(total) if np.isfinite(total) else 10**18


def available_memory() -> int | None:
    """Bytes of memory available to a new allocation (Linux MemAvailable), or None if unknown."""
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def check_memory(deck: Deck) -> None:
    """Refuse, before allocating anything, a deck whose model would not fit in the available memory."""
    from . import build

    available = build.available_memory()  # looked up there: build is the module callers (and tests) patch
    if available is None:
        return
    total, largest, largest_name = 0, -1, ""
    for name in deck.parts:
        nodes, elements, particles = estimate_counts(deck, name)
        need = nodes * BYTES_PER_NODE + elements * BYTES_PER_ELEMENT + particles * BYTES_PER_PARTICLE
        total += need
        if need > largest:
            largest, largest_name = need, name
    walls = estimate_wall_particles(deck)
    if walls * BYTES_PER_PARTICLE > largest:
        largest_name = ""
    total += walls * BYTES_PER_PARTICLE
    if total > available:
        if not largest_name:
            index = next(i for i, bc in enumerate(deck.boundaries) if bc.type == "dummy_wall")
            raise build.ModelError(f"boundaries[{index}]", f"the dummy wall particles need about {total / 2**30:.1f} GiB, "
                             f"more than the {available / 2**30:.1f} GiB available (coarsen the wall spacing)")
        raise build.ModelError(
            f"parts.{largest_name}.geometry",
            f"the model needs about {total / 2**30:.1f} GiB, more than the {available / 2**30:.1f} GiB "
            "available (coarsen the mesh or the particle spacing)",
        )
