"""What `sphfem check` prints about a built model: counts per part, each material's constants in the
deck's units (with the warnings of `materials.plausibility`), the stable step and what sets it, memory."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .materials.plausibility import material_figures
from .model.build import VOID
from .study.derive import NQUAD_MAX


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
             f"density {density}); dimension {'axisymmetric (full 2 pi)' if deck.axisymmetric else deck.dimension}",
             f"  {n_nodes} nodes, {n_elements} elements, {n_particles} particles, {len(model.parts)} part(s)"]
    masses = part_masses(model)
    mass_unit = f"{units.mass}{'/' + units.length if deck.dimension == 2 and not deck.axisymmetric else ''}"
    for p, mass in zip(model.parts, masses):
        kind = "rigid" if p.rigid else deck.parts[p.name].section
        if not p.rigid and getattr(deck.sections[kind], "formulation", "plane_strain") == "plane_stress":
            kind += " (plane stress)"
        material = model.material_names[p.material]
        if p.kind == "sph":
            lines.append(f"    {p.name}: {p.particles.stop - p.particles.start} particles, material {material}, {kind}, "
                         f"mass {mass:.4g} {mass_unit}")
        elif p.kind == "ale":
            names = ", ".join(model.material_names[m] for m in model.ale.materials)
            lines.append(f"    {p.name}: {len(model.ale.nodes)} nodes, {len(model.ale.elements)} ALE elements, "
                         f"materials {names}, {kind}, mass {mass:.4g} {mass_unit}")
        else:
            lines.append(f"    {p.name}: {p.nodes.stop - p.nodes.start} nodes, {p.elements.stop - p.elements.start} "
                         f"elements, material {material}, {kind}, mass {mass:.4g} {mass_unit}")
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
    for name, section in deck.sections.items():
        if getattr(section, "courant", None) is not None:
            warnings.append(f"warning: sections.{name}.courant is the deprecated name of timestep_scale "
                            f"(read as timestep_scale {section.courant:g})")
    end = deck.control.end_time
    lines.append(f"  stable time step {dt:.4e} {units.time} (timestep_scale {deck.control.timestep_scale}), set by "
                 f"{sim.limiter_description()}; about {end / dt:.3g} steps to end_time {end:g} {units.time}")
    for c in sim.interactions:
        if not hasattr(c, "layer_in_h"):
            continue
        layer, length, wetted = c.layer_in_h()
        if layer.size == 0:
            continue
        from .contact.coupling import typical_layer  # loaded with the coupling already

        typical = typical_layer(layer, length)  # the median over the wetted length
        # 3D: L_c = n^2 h / pfac (n = h / sqrt(A) per direction of a face, A a point's share of its area)
        solid = getattr(c, "dim", 2) == 3
        form, measure = ("n^2 h / pfac", "area") if solid else ("n h / pfac", "length")
        lines.append(f"  coupling {c.name}: penalty layer L_c = {form} = {typical:.3g} h (median over "
                     f"the {'wetted ' if wetted else ''}faces' {measure}; max {layer.max():.3g} h; pfac {c.pfac:.3g}{' (auto)' if c.spec.pfac == 'auto' else ''}, nquad {c.nquad})")
        # n = h / l coupling points per fluid-element face (L_c / h = n / pfac), over the same median:
        # below one point per element, fluid elements along the face hold no coupling point and the
        # water passes between the points (LS-DYNA's guidance for *CONSTRAINED_LAGRANGE_IN_SOLID: two
        # or more per fluid element). Measured on tests/verification/ale_plate_strip.yaml (5 mm plate
        # segment, nquad 2): at 2.5 mm water (n = 1) the face takes 184 MPa 5 us after the 100 MPa
        # step arrives; the fluid alone refined to 1.25 mm (n = 0.5) 22 MPa, to 0.625 mm (n = 0.25)
        # 13 MPa, and the plate 50 us after arrival 19.8 and 7.5 m/s against 100.6 at n = 1.
        points = typical * c.pfac
        if solid:
            points = np.sqrt(points)
        if float(f"{points:.3g}") < 1.0:
            need = int(np.ceil(c.nquad / points - 1e-9))
            remedy = (f"raise nquad to {need} or refine the structure's segments with the fluid" if need <= NQUAD_MAX
                      else f"refine the structure's segments with the fluid (nquad {need} would pass its bound {NQUAD_MAX})")
            warnings.append(f"warning: coupling {c.name}: {points:.3g} coupling points per fluid-element face "
                            f"(n = h / l below 1): fluid elements along the structure hold no point and the "
                            f"fluid passes between them; {remedy}")
        if float(f"{typical:.3g}") > 0.5:  # as printed: a layer shown as 0.5 h does not warn
            rule = "pfac >= 2 n^2" if solid else "pfac >= 2 n"
            warnings.append(f"warning: coupling {c.name}: the penalty acts as {typical:.3g} h of extra fluid "
                            f"(L_c = {form} above h/2); {rule} keeps it below h/2 "
                            f"(n = h / l coupling points per fluid-element face)")
    lines.append(f"  memory estimate {model.memory_bytes() / 2**20:.1f} MiB")
    lines += _counts(deck)
    lines.append(_output_size(sim, model, dt))
    return lines, warnings


def part_masses(model) -> list[float]:
    """The mass of each part at t = 0 in the deck's mass unit (per unit thickness in 2D, for the full 2 pi
    when axisymmetric): solids the sum of their nodal masses, SPH parts of their particles' masses, the
    ALE part Σ φ ρ V of its fills (V its elements' ring volumes when axisymmetric)."""
    out = []
    for i, p in enumerate(model.parts):
        if p.kind == "sph":
            out.append(float(model.particles.mass[model.particles.part == i].sum()))
        elif p.kind == "ale":
            from .model.mesh import element_jacobian_sign_check

            if model.axisymmetric:  # rings, for the full 2 pi (ale/axisymmetric.py)
                from .ale.axisymmetric import quad_ring_volumes

                x = model.ale.nodes[model.ale.elements]
                volume = np.abs(quad_ring_volumes(x[:, 0], x[:, 1], x[:, 2], x[:, 3]))
            else:
                volume = np.abs(element_jacobian_sign_check(model.ale.nodes, model.ale.elements))
            out.append(float((model.ale.fractions * model.ale.density * volume[:, None]).sum()))
        else:
            out.append(float(model.mass[p.nodes].sum()))
    return out


def _counts(deck) -> list[str]:
    """Contacts, couplings, boundaries, loads and output requests, counted by kind."""
    def by_kind(items) -> str:
        kinds: dict[str, int] = {}
        for item in items:
            kinds[item.type] = kinds.get(item.type, 0) + 1
        return ", ".join(f"{n} {k}" for k, n in kinds.items()) or "none"

    return [f"  contacts: {by_kind(deck.contacts)}; couplings: {by_kind(deck.couplings)}",
            f"  boundaries: {by_kind(deck.boundaries)}; loads: {by_kind(deck.loads)}; initial: {by_kind(deck.initial)}",
            f"  output: {len(deck.output.histories)} histories, {len(deck.output.probes)} probes"]


def _output_size(sim, model, dt: float) -> str:
    """The expected size of results.h5: the fields of one output step (asked of the domains at t = 0)
    times the output steps, plus the history tables."""
    out = model.options.output
    end = model.options.control.end_time
    fields = {}
    for d in sim.domains:
        fields.update(d.field_data(lambda name: name in out.fields or name not in out.selectable))
    per_step = sum(coords.nbytes + sum(np.asarray(a).nbytes for a in (*point.values(), *cell.values()))
                   for coords, point, cell in fields.values())
    steps = int(np.floor(end / out.interval + 1e-9)) + 1
    steps += not math.isclose(end, (steps - 1) * out.interval, rel_tol=1e-9)  # the state at end_time
    run_steps = end / dt + 1.0 if dt > 0 else np.inf  # a history row is written at most once per step
    rows = int(min(np.floor(end / out.history_interval + 1e-9) + 1, run_steps, 1e15))
    tables = 8 * rows * (10 + 3 * len(model.parts) + 12 * (len(out.histories) + len(out.probes)))
    total = steps * per_step + tables
    return (f"  output size: {steps} field steps of {per_step / 2**20:.2f} MiB and about {rows} history rows: "
            f"results.h5 about {total / 2**20:.1f} MiB")

