"""What `sphfem check` prints about a built model: counts per part, each material's constants in the
deck's units (with the warnings of `materials.plausibility`), the stable step and what sets it, memory."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .materials.plausibility import material_figures
from .model.build import VOID


def model_summary(deck, model, deck_path: Path) -> tuple[list[str], list[str]]:
    """(lines for stdout, warnings for stderr). Raises solver.guards.RunStopped when the model cannot take
    its first step (a stable step of zero, a run that would need more than control.max_steps)."""
    from .solver.explicit import Simulation

    with np.errstate(all="ignore"):
        sim = Simulation(model)
        dt = sim.stable_dt()
    units = deck.units
    force, pressure, density = units.derived
    n_particles = model.particles.n if model.particles is not None else 0
    n_nodes = model.n_nodes + (len(model.ale.nodes) if model.ale is not None else 0)
    n_elements = model.n_elements + (len(model.ale.elements) if model.ale is not None else 0)
    lines = [f"{deck.title or deck_path.name}",
             f"  units: {units.length}-{units.mass}-{units.time} (force {force}, pressure {pressure}, "
             f"density {density}); dimension {deck.dimension}",
             f"  {n_nodes} nodes, {n_elements} elements, {n_particles} particles, {len(model.parts)} part(s)"]
    for p in model.parts:
        kind = "rigid" if p.rigid else deck.parts[p.name].section
        material = model.material_names[p.material]
        if p.kind == "sph":
            lines.append(f"    {p.name}: {p.particles.stop - p.particles.start} particles, material {material}, {kind}")
        elif p.kind == "ale":
            names = ", ".join(model.material_names[m] for m in model.ale.materials)
            lines.append(f"    {p.name}: {len(model.ale.nodes)} nodes, {len(model.ale.elements)} ALE elements, "
                         f"materials {names}, {kind}")
        else:
            lines.append(f"    {p.name}: {p.nodes.stop - p.nodes.start} nodes, {p.elements.stop - p.elements.start} "
                         f"elements, material {material}, {kind}")
    warnings = []
    for i, (name, m) in enumerate(deck.materials.items()):
        if model.material_type[i] == VOID:
            lines.append(f"  material {name}: {m.type}")
            continue
        fig = material_figures(name, model.material_param[i], not hasattr(m, "youngs_modulus"), units)
        figures = [f"density {fig.density:g} {density}"]
        if fig.modulus is not None:
            figures.append(f"Young's modulus {fig.modulus:g} {pressure}")
        if fig.sound_speed is not None:
            figures.append(f"sound speed {fig.sound_speed:.4g} {units.length}/{units.time}")
        lines.append(f"  material {name}: {m.type}, {', '.join(figures)}")
        warnings += [f"warning: material {name}: {w}" for w in fig.warnings]
    end = deck.control.end_time
    lines.append(f"  stable time step {dt:.4e} {units.time} (timestep_scale {deck.control.timestep_scale}), set by "
                 f"{sim.limiter_description()}; about {end / dt:.3g} steps to end_time {end:g} {units.time}")
    lines.append(f"  memory estimate {model.memory_bytes() / 2**20:.1f} MiB")
    return lines, warnings
