"""The hand-written parts of the deck reference (docs/deck-reference.md): its header, the example
deck, the conventions every deck follows, and the tables of unit systems and file limits.

Everything about a single key is generated from the schema instead (``deck.reference``).
"""
from __future__ import annotations

from .loader import LIMITS
from .schema import UNIT_SYSTEMS

__all__ = ["EXAMPLE_DECK", "HEADER", "CONVENTIONS", "unit_table", "limit_table"]

EXAMPLE_DECK = """\
# The smallest complete deck: a steel plate (plane strain) pushed at its left end.
title: Steel plate pushed at one end
units: {length: mm, mass: t, time: s}     # so force N, pressure MPa, density t/mm^3
dimension: 2                               # plane strain in the x-y plane

control:
  end_time: 1.0e-5                         # [time] = s

materials:
  steel: {type: elastic, density: 7.85e-9, youngs_modulus: 2.1e5, poisson_ratio: 0.3}

sections:
  solid: {type: solid}                     # default hourglass and bulk viscosity

parts:
  plate:
    material: steel                        # a name from materials
    section: solid                         # a name from sections
    geometry: {box: {min: [0.0, 0.0], max: [50.0, 10.0], element_size: 2.5}}

sets:
  left_end: {type: node, part: plate, side: left}

boundaries:
  - {type: prescribed_velocity, set: left_end, velocity: [1000.0, null]}   # 1 m/s, y left free

output:
  interval: 1.0e-6
  history_interval: 1.0e-7
  histories:
    - {name: tip, point: [50.0, 5.0], quantities: [displacement, velocity]}
"""
"""A complete, minimal deck; printed at the top of the reference and validated by the tests."""

HEADER = """\
# Deck reference

<!-- Generated from sphfem_cli/deck/schema/ by `python -m sphfem_cli.deck.reference`.
     Do not edit by hand: change the schema's descriptions and docstrings, then regenerate.
     tests/unit/test_deck_reference.py fails when this file and the schema differ. -->

A deck is one YAML file. Its top-level keys are keyword families, in the manner of LS-DYNA's
keywords: `control` for the run, named `materials`, `equations_of_state`, `sections` and `parts`,
named node and segment `sets`, lists of `boundaries`, `initial` conditions and `loads`, and the
`output` requests. `sphfem check deck.yaml` validates a deck, builds the model and prints a
summary with the stable time step; `sphfem run deck.yaml` runs it.

**Completion and checks while typing.** `sphfem schema -o deck.schema.json` writes the deck's JSON
Schema (generated from the same models as this page; the repository keeps a copy in
`schema/deck.schema.json`). An editor with the YAML language server (VS Code's *YAML* extension,
neovim's yamlls, JetBrains IDEs) reads a first line
`# yaml-language-server: $schema=<path or URL of deck.schema.json>` and then completes keys, shows
these descriptions, and marks unknown keys, wrong types and out-of-range numbers as you type; every
shipped deck starts with such a line (`$schema=../schema/deck.schema.json`). Or map the schema to
your deck files once in the editor's settings (VS Code: `"yaml.schemas": {"schema/deck.schema.json":
"decks/*.yaml"}`). The schema checks each key alone; `sphfem check` also checks the cross-references
(a part's material exists, a set exists, ...).
"""

CONVENTIONS = """\
## Reading a deck

### Units

The deck declares one consistent unit system in `units:` and every number in the deck is in that
system. Nothing is ever converted: the kernels compute with the numbers as written, so a deck in
mm-t-s gives stresses in MPa. Descriptions state the dimension of each quantity in brackets:
[length], [time], [mass/length^3], [pressure], [force], [length/time], [-] for dimensionless.
The accepted systems (as LS-DYNA lists them) and the units they imply:

{unit_table}

### Numbers and other scalars

Scalars follow the YAML 1.2 core schema, not YAML 1.1: `1e-3`, `.5`, `2.1E11` and `1.` are
numbers; `yes`, `no`, `on`, `off`, `1_000` and `0b101` are strings. `true`/`false` are booleans
and `null` (or `~`, or nothing) is null. Where a number is expected an integer is accepted
(`7850` as well as `7850.0`); where an integer is expected a float is refused (`2.0` is not an
integer). A quoted number (`"1.0"`) is a string and is refused where a number is expected;
`.inf` and `.nan` are refused everywhere. Anchors, aliases and merge keys (`<<: *base`) work;
duplicate keys are an error.

### Errors

A bad deck stops before anything runs, with one line on stderr and exit status 65:

```
deck.yaml:4:26: materials.steel.densty: unknown key 'densty' (did you mean 'density'?; allowed: density, youngs_modulus, poisson_ratio, type)
```

that is `file:line:col: path.in.deck: what is wrong (what was expected)`. Unknown keys, unknown
`type` values and unknown names are reported with the closest match and the allowed choices.
Paths are dotted, list items by index: `boundaries[0].set`.

### Names and cross-references

`curves`, `equations_of_state`, `materials`, `sections`, `parts` and `sets` are mappings from a
name you choose to a definition. Other entries refer to those by name, and every reference is
checked when the deck is read (an unknown name is an error that lists the known ones):

| key | refers to |
|---|---|
| `materials.<name>.eos` | `equations_of_state` |
| `parts.<name>.material`, `parts.<name>.section` | `materials`, `sections` |
| `sets.<name>.part` | `parts` |
| `part`, `set`, `curve` in `boundaries`, `initial`, `loads` items | `parts`, `sets`, `curves` |
| `loads[i].parts` (gravity) | `parts` |
| `part`, `set` in `output.histories` items | `parts`, `sets` |

A `pressure` load needs a segment set and a `nodal_force` load a node set. A name is any string
of Unicode (`steel`, `left_end`, `名前`, `🔥`; plain words need no quotes) that the output files
can carry, since names become CSV columns, file names (`histories/<name>.csv`) and HDF5/XDMF
names, all written as UTF-8. Refused: an empty or blank name, control characters and line or
paragraph separators, the characters `,` `"` `/` `\\`, the names `.` and `..`, and names over
{name_chars} characters or {name_bytes} bytes of UTF-8. Histories and probes cannot take the
names of the tables the solver writes itself ({reserved}).

### Limits on the file

A deck is a regular file (not a FIFO, a device or a directory), read with these bounds, each an
error naming the bound when crossed; an environment variable raises each one:

{limits}

Mesh files named by `geometry.file` must be regular files too; a file that meshio cannot read
(a corrupt `.vtu`, an unknown format) is an error at the deck's `file:` key.

### Vectors and `dimension`

`dimension: 2` is plane strain in the x-y plane (forces, masses and energies per unit thickness);
`dimension: 3` is full 3D. A *vector of `dimension` numbers* (a point, a velocity, an
acceleration) has 2 components in 2D and 3 in 3D; its length is checked against `dimension`
once the whole deck has been read. Directions are named `x`, `y`, `z`; `z` does not exist in 2D.

`dimension: axisymmetric` is the meridian plane of a body of revolution: `x` is the radius r (every
node at x >= 0) and `y` the axis, so vectors have 2 components (r, z) as in 2D. Masses, forces
(loads, reactions, histories), energies and the glstat table are for the **full 2 pi** (the whole
body), not per radian; a pressure acts on the ring an edge sweeps (area 2 pi r L). The **axis
condition is automatic**: nodes at x = 0 (within 1e-12 of the part's size) keep u_r = 0, with no
boundary keyword. Solid and SPH parts so far, and `contacts` of an SPH part or a solid part's nodes on
a solid part's faces (a meridian segment sweeps a ring, the force on a particle or node is its whole
ring's, docs/theory/contact.md "Axisymmetric"; faces on the axis are no contact surface); a **rigid part**
is a body of revolution that moves along the axis only (its mass the sum of its ring masses, its force the
axial sum of its rings' forces; a radial initial or prescribed velocity on it is a deck error);
`sph_boundary` couplings are deck errors (issue 15);
ALE `lagrange_in_solid` couplings work in r–z (a coupling point stands for its ring, docs/theory/coupling.md). The element is the one-point volume-weighted ring quad4 with
Flanagan-Belytschko hourglass control; the hoop strain rate v_r/r at the element centre is the
stress's `zz` component (docs/theory/fem.md, `sphfem_cli/fem/axisymmetric.py`).

An **ALE part** in an axisymmetric deck is a mesh of rings (`sphfem_cli/ale/axisymmetric.py`, docs/theory/ale.md
"Axisymmetric"): every element is the ring its quad sweeps (exact volume 2 pi r_bar A), its forces the
derivative of that volume times the pressure and viscosity (the volume-weighted form, which holds the hoop
stress and conserves mass, axial momentum and total energy to round-off), its remap fluxes the ring volumes
the faces sweep. The axis is automatic (nodes at x = 0 slide along it); `ale_boundary` sides, fills,
programmed burn, gravity along y and probes are those of 2D (a fill's volume fraction is its share of the
element's ring volume, 2 pi r dA over 3 x 3 Jacobian-weighted points). `mesh_motion` is `eulerian`,
`lagrangian` or `smoothed` (the 2D smoothing of the meridian plane, every `smoothing`; axis nodes stay
fixed, or with `smoothing_boundary: sliding` slide along the axis, at x = 0 exactly; the swept ring
volumes keep the remap conservative); `lagrange_in_solid` couplings to structures work in r–z.

An **SPH part** in an axisymmetric deck is a set of rings: its geometry (a box, ball or polygon in
x = r >= 0, y = z; a deck error if it reaches x < 0) is filled at `spacing` as in 2D, and each particle
carries the mass of the ring its cell sweeps, 2 pi r rho dx^2 (the part's mass in `sphfem check` is the
whole body's). A `ball` centred on the axis (center x = 0) is a sphere: its meridian half-disc is filled
on the lattice x = (i + 1/2) dx. The rates are the
areal form of Garcia-Senz et al. (2009) with the hoop terms (`sphfem_cli/sph/axisymmetric.py`,
docs/theory/sph.md "Axisymmetric SPH"). The **axis is automatic** here too: r = 0 is a line of
reflected ghost particles (r -> -r, v_r -> -v_r), so no `wall` is needed on the `left` side (one
there is the same line). Ghost `wall`s on the other sides carry over from 2D (a `right` wall is the
cylinder wall r = R, `bottom`/`top` are planes z = const), slip only; the equations of state, the
density diffusion, the artificial viscosity, XSPH, `hydrostatic` starts, `domain` and pressure probes
are those of 2D, and so are both forms of `continuity` (the mass form weighs each ring by its plane
mass rho_j A_j). A `high_explosive` part burns as in 2D (programmed burn, its products' renormalised
continuity carried to r-z: docs/theory/sph.md "Explosive products in r-z"); its `detonations` lie on
the axis (x = 0; a point off it would be a ring: a deck error). Deck errors name what stays 2D/3D only:
viscous fluids (`viscosity` > 0), `dummy_wall` boundaries and `no_slip`/`wall_function` walls.

Results of an axisymmetric deck are the meridian plane (`results.<part>.xdmf`). `output.revolve`
(`{{segments: 24, angle: 360}}`, off by default, a deck error elsewhere) adds `results.<part>.revolved.xdmf`,
the body of revolution for ParaView: r goes to 3D (x, y) = (r cos a, r sin a), the axis is 3D z; quads
sweep to hex8 (collapsed hexes, i.e. wedges, at the axis), particles to rings of points; vectors and
stress are rotated to Cartesian components, scalars copied. Its faces are chords, so its volume is
sin(d)/d of the ring's (d = 2 pi / segments: 1.1 % short at 24). It costs `segments` times the part's
datasets in `results.h5` at every field step (docs/output.md "Revolved 3D view").

### How to read the tables

Each table lists the keys of one mapping: its **type** (number, integer, string, boolean, a list,
a vector, one of a fixed set of words, or a nested mapping with its own table), its **default**
(**required** if it has none; `null` means unset, and the description says what unset implies)
and its **description**. Keys not listed are refused. Entries of `equations_of_state`,
`materials`, `sections`, `sets`, `boundaries`, `initial` and `loads` are selected by their
`type` key; each `type` has its own table.
"""


def unit_table() -> str:
    """The accepted unit systems and the units they imply, as a Markdown table."""
    rows = ["| length | mass | time | force | pressure | density |", "|---|---|---|---|---|---|"]
    for (length, mass, time), (force, pressure, density) in UNIT_SYSTEMS.items():
        rows.append(f"| {length} | {mass} | {time} | {force} | {pressure} | {density} |")
    return "\n".join(rows)


_LIMIT_TEXT = {
    "SPHFEM_MAX_DECK_BYTES": "bytes in the deck file",
    "SPHFEM_MAX_DECK_NODES": "values (scalars, lists and mappings) with every alias and merge key expanded: "
                             "an alias bomb stops here",
    "SPHFEM_MAX_DECK_DEPTH": "nesting depth of lists and mappings",
}


def limit_table() -> str:
    """The bounds on a deck file, their environment variables and defaults, as a Markdown table."""
    rows = ["| environment variable | default | bounds |", "|---|---|---|"]
    rows += [f"| `{name}` | {value} | {_LIMIT_TEXT[name]} |" for name, value in LIMITS.items()]
    return "\n".join(rows)
