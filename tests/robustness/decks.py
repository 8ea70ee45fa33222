"""Small decks (a second or so each) for the guard, restart, determinism and output-integrity tests."""
from __future__ import annotations

from pathlib import Path

SOLID = """\
title: small solid impact (guard/restart tests)
units: {length: m, mass: kg, time: s}
dimension: 2
control: {end_time: 2.0e-4, timestep_scale: 0.9}
materials:
  steel: {type: elastic_plastic, density: 7850.0, youngs_modulus: 2.1e11, poisson_ratio: 0.3,
          yield_stress: 3.0e8, tangent_modulus: 1.0e9}
sections:
  solid: {type: solid}
parts:
  bar: {material: steel, section: solid,
        geometry: {box: {min: [0.0, 0.0], max: [0.05, 0.01], divisions: [20, 4]}}}
sets:
  struck: {type: node, part: bar, side: left}
initial:
  - {type: velocity, part: bar, velocity: [100.0, 0.0]}
boundaries:
  - {type: prescribed_velocity, set: struck, velocity: [0.0, 0.0]}
output:
  interval: 2.0e-5
  history_interval: 2.0e-6
  histories:
    - {name: tip, part: bar, quantities: [displacement, velocity, stress]}
"""

SPH = """\
title: small dam break (guard/restart tests)
units: {length: m, mass: kg, time: s}
dimension: 2
control: {end_time: 0.02, timestep_scale: 1.0}
equations_of_state:
  water: {type: tait, reference_density: 1000.0, sound_speed: 15.0, gamma: 7.0}
materials:
  water: {type: fluid, density: 1000.0, viscosity: 0.0, eos: water}
sections:
  fluid: {type: sph, kernel: cubic_spline, smoothing_ratio: 1.2, density_diffusion: 0.1,
          artificial_viscosity: {alpha: 0.1}}
parts:
  column: {material: water, section: fluid, spacing: 0.005, hydrostatic: true,
           geometry: {box: {min: [0.0, 0.0], max: [0.05, 0.1]}}}
boundaries:
  - {type: wall, min: [0.0, 0.0], max: [0.3, 0.3], sides: [left, right, bottom], condition: no_slip}
loads:
  - {type: gravity, acceleration: [0.0, -9.81]}
output:
  interval: 0.002
  history_interval: 0.0005
  probes:
    - {name: front, type: front, axis: x}
"""

ALE = """\
title: small water-air shock tube (guard/restart tests)
units: {length: m, mass: kg, time: s}
dimension: 2
control: {end_time: 3.0e-4}
equations_of_state:
  water: {type: stiffened_gas, gamma: 4.4, p_inf: 6.0e8}
  air: {type: ideal_gas, gamma: 1.4}
materials:
  water: {type: fluid, density: 1000.0, eos: water}
  air: {type: fluid, density: 50.0, eos: air}
sections:
  ale: {type: ale_multi_material, advection: van_leer, interface: slic, closure: relax}
parts:
  tube:
    material: air
    section: ale
    geometry: {box: {min: [0.0, 0.0], max: [1.0, 0.01], divisions: [100, 1]}}
    fill:
      - {material: air, box: {min: [0.0, 0.0], max: [1.0, 0.01]}, pressure: 1.0e5}
      - {material: water, box: {min: [0.0, 0.0], max: [0.7, 0.01]}, pressure: 1.0e9}
boundaries:
  - {type: ale_boundary, part: tube, sides: [left, right, bottom, top], condition: slip}
output:
  interval: 3.0e-5
  history_interval: 3.0e-6
"""

DECKS = {"solid": SOLID, "sph": SPH, "ale": ALE}


def write(directory: Path, kind: str, text: str | None = None, **control) -> Path:
    """Write deck `kind` (or `text`) into `directory`, with `control` keys replaced; returns its path."""
    import yaml

    from sphfem_cli.deck import loader

    tree, _ = loader.loads(text or DECKS[kind], f"{kind}.yaml")
    tree["control"].update(control)
    path = Path(directory) / f"{kind}.yaml"
    path.write_text(yaml.safe_dump(tree, sort_keys=False))
    return path
