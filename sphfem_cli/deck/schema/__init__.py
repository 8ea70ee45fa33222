"""The deck: one pydantic model per keyword family, and cross-reference checks over the whole.

Each keyword family has its module (``control`` for units, control and curves; ``materials`` for
materials and equations of state; ``sections``; ``parts``; ``sets``; ``boundaries``; ``initial``;
``loads``; ``interaction`` for contacts and couplings; ``output``), and ``shapes`` holds the
boxes, balls and planes several of them use. Every public name of those modules is importable
from this package. Field descriptions are the deck reference's text (docs/deck-reference.md is
generated from them), so each states meaning, units and default.

Cross-reference errors are raised as ``ValueError("@dotted.path: message")`` so that
``deck.validate`` can point at the offending key's line and column.
"""
from __future__ import annotations

from typing import Literal

from pydantic import Field, PrivateAttr, field_serializer, model_validator

from ..errors import format_path
from . import boundaries, control, initial, interaction, loads, materials, output, parts, sections, sets, shapes
from .base import DeckModel, check_vector_lengths, name_problem
from .boundaries import *  # noqa: F403
from .control import *  # noqa: F403
from .initial import *  # noqa: F403
from .interaction import *  # noqa: F403
from .loads import *  # noqa: F403
from .materials import *  # noqa: F403
from .output import *  # noqa: F403
from .parts import *  # noqa: F403
from .sections import *  # noqa: F403
from .sets import *  # noqa: F403
from .shapes import *  # noqa: F403

__all__ = ["Deck", "RESERVED_HISTORIES"] + [
    name for family in (control, materials, sections, parts, sets, boundaries, initial, loads, interaction, output,
                        shapes)
    for name in family.__all__
]


class Deck(DeckModel):
    """A whole input deck."""

    title: str = Field("", description="Free text shown in the output and logs.")
    units: Units = Field(default_factory=Units, description="Consistent unit system. Default m-kg-s.")
    dimension: Literal[2, 3, "axisymmetric"] = Field(
        description="2 = plane in x-y (plane strain, or plane stress by a solid section's formulation), 3 = solid, axisymmetric = the meridian plane of a body of revolution "
        "(x = radius r >= 0, y = the axis; solid and SPH parts and SPH-on-solid contacts so far; forces, masses "
        "and energies for the full 2 pi)."
    )
    control: Control = Field(description="End time and time-step control.")
    curves: dict[str, Curve] = Field(default_factory=dict, description="Named time curves.")
    equations_of_state: dict[str, EquationOfState] = Field(
        default_factory=dict, description="Named equations of state."
    )
    materials: dict[str, Material] = Field(min_length=1, description="Named materials.")
    sections: dict[str, Section] = Field(min_length=1, description="Named sections.")
    parts: dict[str, Part] = Field(min_length=1, description="Named parts.")
    sets: dict[str, SetDef] = Field(default_factory=dict, description="Named node and segment sets.")
    boundaries: list[Boundary] = Field(default_factory=list, description="Kinematic boundary conditions.")
    initial: list[Initial] = Field(default_factory=list, description="Initial conditions.")
    loads: list[Load] = Field(default_factory=list, description="Loads.")
    contacts: list[Contact] = Field(default_factory=list, description="Penalty contacts (SPH or nodes to surfaces).")
    couplings: list[Coupling] = Field(default_factory=list, description="Fluid to structure couplings: ALE (lagrange_in_solid) or SPH (sph_boundary).")
    detonations: list[Detonation] = Field(
        default_factory=list,
        description="Detonation points of the high explosives (programmed burn); none: every explosive lights at t = 0.",
    )
    output: Output = Field(default_factory=Output, description="Output requests.")

    _axisymmetric: bool = PrivateAttr(False)

    @property
    def axisymmetric(self) -> bool:
        """True for ``dimension: axisymmetric``; `dimension` then reads 2 (two coordinates, r and z)."""
        return self._axisymmetric

    @field_serializer("dimension")
    def _dimension_as_written(self, value: int | str) -> int | str:
        """A dump (deck.effective.yaml, the checkpoint's deck hash, the plots' unit labels) says
        "axisymmetric" where the deck did: `dimension` itself reads 2 once validated. Before, the
        effective deck of an r-z run said 2, which reloads as a plane-strain model."""
        return "axisymmetric" if self._axisymmetric else value

    @model_validator(mode="after")
    def _cross_references(self) -> "Deck":
        if self.dimension == "axisymmetric":
            self.dimension = 2
            self._axisymmetric = True
            _check_axisymmetric(self)
        elif self.output.revolve is not None:
            raise ValueError("@output.revolve: a revolved view needs dimension: axisymmetric (a meridian plane to "
                             f"revolve); this deck is dimension {self.dimension}")
        _check_names(self)
        _check_output_steps(self)
        check_vector_lengths(self, self.dimension)
        _check_references(self)
        _check_formulations(self)
        return self


MAX_FIELD_STEPS = 100_000
"""The most field outputs a run may ask for: the solver lands a step on every output time, so an interval far
below the stable step would shrink the steps to it (a run that never ends)."""


def _check_output_steps(deck: Deck) -> None:
    """output.interval must give at most MAX_FIELD_STEPS field outputs over control.end_time."""
    interval = deck.output.interval
    if interval is not None and deck.control.end_time > MAX_FIELD_STEPS * interval:
        raise ValueError(f"@output.interval: {interval:g} gives more than {MAX_FIELD_STEPS} field outputs over "
                         f"end_time {deck.control.end_time:g} (each one is a step the solver lands on); "
                         f"use at least {deck.control.end_time / MAX_FIELD_STEPS:g}")


RESERVED_HISTORIES = ("glstat", "matsum", "ale_materials")
"""Tables the solver writes itself (histories/<name>.csv); a history or probe cannot take these names."""


AXISYMMETRIC_RIGID = "an axisymmetric rigid part moves along the axis (y) only"
AXISYMMETRIC_SPH = ("axisymmetric SPH supports inviscid fluids and high explosives with slip ghost walls only "
                    "for now (issue 15)")
AXISYMMETRIC_DETONATION = ("an axisymmetric SPH explosive is lit from points on the axis (x = r = 0): a point off "
                           "it is a ring in r-z")


def _check_axisymmetric(deck: Deck) -> None:
    """What an axisymmetric deck cannot hold: SPH parts only of inviscid fluids and high explosives, with
    slip ghost walls (sph/axisymmetric.py), and the detonation points of an SPH explosive on the axis;
    a radial velocity on a rigid part, which moves along the axis only (solver.boundary.RigidBodies)."""
    sph = explosive = False
    rigid: set[str] = set()
    for pname, part in deck.parts.items():
        section = deck.sections.get(part.section)
        kind = getattr(section, "type", "solid")
        material = deck.materials.get(part.material)
        if kind == "sph":
            sph = True
            _check_meridian_half_plane(pname, part)
            if getattr(section, "density_diffusion_form", "molteni_colagrossi") != "molteni_colagrossi":
                raise ValueError(f"@sections.{part.section}.density_diffusion_form: {AXISYMMETRIC_SPH}; the "
                                 f"'{section.density_diffusion_form}' form of the density diffusion is 2D/3D only "
                                 "(docs/theory/sph.md 'Rates')")
            if getattr(material, "viscosity", 0.0):
                raise ValueError(f"@parts.{pname}.material: {AXISYMMETRIC_SPH}; '{part.material}' is a viscous fluid")
            explosive |= getattr(material, "type", "") == "high_explosive"
        if part.rigid or getattr(material, "type", "") == "rigid":
            rigid.add(pname)
    for i, entry in enumerate(deck.initial):
        if getattr(entry, "part", None) in rigid and entry.velocity[0] != 0.0:
            raise ValueError(f"@initial.{i}.velocity: {AXISYMMETRIC_RIGID}; '{entry.part}' is rigid, its radial "
                             f"velocity must be 0 (got {entry.velocity[0]:g})")
    for i, bc in enumerate(deck.boundaries):
        if getattr(bc, "type", "") == "prescribed_velocity" and bc.part in rigid and (bc.velocity[0] or 0.0) != 0.0:
            raise ValueError(f"@boundaries.{i}.velocity: {AXISYMMETRIC_RIGID}; '{bc.part}' is rigid, its radial "
                             f"velocity must be 0 (got {bc.velocity[0]:g})")
    if explosive:
        for i, det in enumerate(deck.detonations):
            if det.point[0] != 0.0:
                raise ValueError(f"@detonations.{i}.point: {AXISYMMETRIC_DETONATION}; got x = {det.point[0]:g}")
    if sph:
        for i, bc in enumerate(deck.boundaries):
            kind = getattr(bc, "type", "")
            if kind == "dummy_wall":
                raise ValueError(f"@boundaries.{i}: {AXISYMMETRIC_SPH}; use a wall (ghost particles)")
            if kind == "wall" and bc.condition != "slip":
                raise ValueError(f"@boundaries.{i}.condition: {AXISYMMETRIC_SPH}; '{bc.condition}' walls are 2D/3D only")


PLANE_STRESS_2D = "plane_stress is a formulation of 2D quad4 elements (dimension 2)"
PLANE_STRESS_MATERIALS = ("plane_stress takes elastic, elastic_plastic and johnson_cook materials without an "
                          "equation of state (the EOS pressure would need the thickness change: not yet)")


def _check_formulations(deck: Deck) -> None:
    """A plane_stress section only in a dimension 2 deck (not 3D, not axisymmetric: the hoop strain of a ring is
    kinematic), and on its parts only materials without an equation of state (fem.kernels: the thickness
    strain is solved so that sigma_zz = 0 from the deviatoric update; an EOS pressure is a function of the
    volume, which would need it inside the iteration)."""
    for sname, section in deck.sections.items():
        if getattr(section, "formulation", "plane_strain") != "plane_stress":
            continue
        if deck.dimension != 2 or deck.axisymmetric:
            this = "axisymmetric" if deck.axisymmetric else f"dimension {deck.dimension}"
            raise ValueError(f"@sections.{sname}.formulation: {PLANE_STRESS_2D}; this deck is {this}")
    for pname, part in deck.parts.items():
        section, material = deck.sections[part.section], deck.materials[part.material]
        if getattr(section, "formulation", "plane_strain") == "plane_stress" and getattr(material, "eos", None):
            raise ValueError(f"@parts.{pname}.material: {PLANE_STRESS_MATERIALS}; '{part.material}' has eos "
                             f"'{material.eos}' and section '{part.section}' is plane_stress")


def _check_meridian_half_plane(pname: str, part) -> None:
    """An axisymmetric SPH part's geometry lies in x = r >= 0; a ball may be centred on the axis (its
    meridian half-disc is filled), not straddle it off-centre."""
    g = part.geometry
    where, bad = None, ""
    if g.box is not None and g.box.min[0] < 0.0:
        where, bad = "box.min", f"the box reaches x = {g.box.min[0]:g}"
    elif g.polygon is not None and min(v[0] for v in g.polygon.vertices) < 0.0:
        where, bad = "polygon.vertices", f"a vertex lies at x = {min(v[0] for v in g.polygon.vertices):g}"
    elif g.ball is not None and g.ball.center[0] != 0.0 and g.ball.center[0] - g.ball.radius < 0.0:
        where, bad = "ball.center", "the ball crosses the axis off its centre (centre it on x = 0 or keep it in x >= 0)"
    if where is not None:
        raise ValueError(f"@parts.{pname}.geometry.{where}: an axisymmetric SPH part lies in x = r >= 0 "
                         f"(the axis is x = 0); {bad}")


def _check_names(deck: Deck) -> None:
    """Every name is one the output files can carry (``base.name_problem``); no history overwrites a table."""
    for family in ("curves", "equations_of_state", "materials", "sections", "parts", "sets"):
        for name in getattr(deck, family):
            if (why := name_problem(name)) is not None:
                raise ValueError(f"@{format_path((family, name))}: {why}")
    for family in ("histories", "probes"):
        for i, request in enumerate(getattr(deck.output, family)):
            why = name_problem(request.name)
            if why is None and request.name in RESERVED_HISTORIES:
                why = f"'{request.name}' is a table the solver writes (reserved: {', '.join(RESERVED_HISTORIES)})"
            if why is not None:
                raise ValueError(f"@output.{family}.{i}.name: {why}")
    tables = {*RESERVED_HISTORIES, *(r.name for r in deck.output.histories), *(p.name for p in deck.output.probes)}
    for i, probe in enumerate(deck.output.probes):
        if probe.filter is not None:
            if f"{probe.name}_filtered" in tables:
                raise ValueError(f"@output.probes.{i}.filter: the filtered table '{probe.name}_filtered' is another "
                                 "history's name")
            tables.add(f"{probe.name}_filtered")
    for i, ref in enumerate(deck.output.references):
        table = ref.quantity.partition(".")[0]
        if table not in tables:
            raise ValueError(f"@output.references.{i}.quantity: no history table '{table}' (tables: "
                             f"{', '.join(sorted(tables))})")


def _check_filter(deck: Deck, filt, at: str) -> None:
    """A probe's filter must be resolvable by its history sampling (rows every history_interval)."""
    if filt is None:
        return
    interval = deck.output.history_interval or deck.control.end_time / 1000.0
    if filt.cutoff is not None and filt.cutoff * interval >= 0.5:
        raise ValueError(f"@{at}.cutoff: {filt.cutoff:g} is not below the Nyquist frequency "
                         f"{0.5 / interval:g} of the history rows (history_interval {interval:g})")
    if filt.window is not None and filt.window < interval:
        raise ValueError(f"@{at}.window: {filt.window:g} is shorter than the history_interval {interval:g}")


def _file_set(deck: Deck, name: str | None) -> bool:
    """True for ``<part>.<set>`` naming a set of a part meshed from a file (not a deck set)."""
    if name is None or name in deck.sets or "." not in name:
        return False
    part = deck.parts.get(name.partition(".")[0])
    return part is not None and part.geometry is not None and getattr(part.geometry, "file", None) is not None


def _ref(name: str | None, known: dict, path: str, what: str) -> None:
    if name is not None and name not in known:
        names = ", ".join(sorted(known)) or "none defined"
        raise ValueError(f"@{path}: unknown {what} '{name}' (known: {names})")


def _check_references(deck: Deck) -> None:
    for mname, mat in deck.materials.items():
        _ref(getattr(mat, "eos", None), deck.equations_of_state, f"materials.{mname}.eos", "equation of state")

    sph_parts, ale_parts = set(), set()
    for pname, part in deck.parts.items():
        _ref(part.material, deck.materials, f"parts.{pname}.material", "material")
        _ref(part.section, deck.sections, f"parts.{pname}.section", "section")
        kind = part.geometry.kind
        where = f"parts.{pname}"
        if deck.sections[part.section].type == "sph":
            sph_parts.add(pname)
            if deck.materials[part.material].type not in ("fluid", "high_explosive"):
                raise ValueError(f"@{where}.material: an SPH part needs a material of type fluid (or high_explosive), "
                                 f"'{part.material}' is {deck.materials[part.material].type}")
            if part.spacing is None:
                raise ValueError(f"@{where}: an SPH part needs 'spacing' (the particle spacing)")
            if kind not in PARTICLE_KINDS:
                raise ValueError(f"@{where}.geometry.{kind}: SPH parts are filled from box, ball, polygon or file")
            if kind == "box" and (part.geometry.box.divisions or part.geometry.box.element_size):
                raise ValueError(f"@{where}.geometry.box: an SPH box takes its resolution from the part's spacing")
            if part.rigid:
                raise ValueError(f"@{where}.rigid: an SPH part cannot be rigid")
        elif deck.sections[part.section].type == "ale_multi_material":
            ale_parts.add(pname)
            _check_ale_part(deck, pname, part)
        else:
            if kind not in MESH_KINDS:
                raise ValueError(f"@{where}.geometry.{kind}: solid parts are meshed from box, ring, cylinder or file")
            if kind == "box" and not (part.geometry.box.divisions or part.geometry.box.element_size):
                raise ValueError(f"@{where}.geometry.box: give 'divisions' or 'element_size'")
            if part.spacing is not None or part.hydrostatic:
                key = "spacing" if part.spacing is not None else "hydrostatic"
                raise ValueError(f"@{where}.{key}: only SPH parts take '{key}'")
            if deck.materials[part.material].type == "void":
                raise ValueError(f"@{where}.material: void fills ALE parts only")
            if deck.materials[part.material].type in ("fluid", "high_explosive"):
                raise ValueError(f"@{where}.material: {deck.materials[part.material].type} materials fill SPH or ALE parts only")
        if part.fill and pname not in ale_parts:
            raise ValueError(f"@{where}.fill: only ALE parts take 'fill'")
        if pname in sph_parts and part.section != deck.parts[min(sph_parts)].section:
            raise ValueError(f"@{where}.section: every SPH part must use the same sph section "
                             "(they form one particle system)")
        if kind == "polygon" and deck.dimension != 2:
            raise ValueError(f"@{where}.geometry.polygon: polygons are 2D (use box or ball in 3D)")
        if kind == "ring" and deck.dimension != 2:
            raise ValueError(f"@parts.{pname}.geometry.ring: ring meshes are 2D (use cylinder in 3D)")
        if kind == "cylinder" and deck.dimension != 3:
            raise ValueError(f"@parts.{pname}.geometry.cylinder: cylinder meshes are 3D (use ring in 2D)")

    for sname, s in deck.sets.items():
        _ref(s.part, deck.parts, f"sets.{sname}.part", "part")
        if s.part in sph_parts | ale_parts:
            raise ValueError(f"@sets.{sname}.part: sets select nodes of solid parts, '{s.part}' is a fluid part")
        if s.side in ("back", "front") and deck.dimension == 2:
            raise ValueError(f"@sets.{sname}.side: side '{s.side}' exists only in 3D")

    def check_target(item, path: str) -> None:
        _ref(getattr(item, "part", None), deck.parts, f"{path}.part", "part")
        name = getattr(item, "set", None)
        if not _file_set(deck, name):  # `<part>.<set>` of a part meshed from a file: model.build checks it
            _ref(name, deck.sets, f"{path}.set", "set")
        _ref(getattr(item, "curve", None), deck.curves, f"{path}.curve", "curve")

    for i, bc in enumerate(deck.boundaries):
        check_target(bc, f"boundaries.{i}")
        if isinstance(bc, DummyWallBoundary):
            if not sph_parts:
                raise ValueError(f"@boundaries.{i}: dummy walls act on SPH parts and this deck has none")
            if deck.dimension == 2 and ({"back", "front"} & set(bc.sides or [])):
                raise ValueError(f"@boundaries.{i}.sides: back and front walls exist only in 3D")
            if bc.region is not None and bc.region.polygon is not None and deck.dimension != 2:
                raise ValueError(f"@boundaries.{i}.region.polygon: polygons are 2D (use box or ball in 3D)")
            default = min(deck.parts[n].spacing for n in sph_parts)
            spacings = {b.spacing or default for b in deck.boundaries if isinstance(b, DummyWallBoundary)}
            if len(spacings) > 1:
                raise ValueError(f"@boundaries.{i}.spacing: every dummy_wall must have the same spacing "
                                 f"(got {', '.join(f'{v:g}' for v in sorted(spacings))}; default {default:g})")
            continue
        if isinstance(bc, WallBoundary):
            if not sph_parts:
                raise ValueError(f"@boundaries.{i}: walls act on SPH parts and this deck has none")
            if deck.dimension == 2 and ({"back", "front"} & set(bc.sides)):
                raise ValueError(f"@boundaries.{i}.sides: back and front walls exist only in 3D")
            continue
        if isinstance(bc, AleBoundary):
            if bc.part not in ale_parts:
                raise ValueError(f"@boundaries.{i}.part: '{bc.part}' is not an ALE part")
            if deck.dimension == 2 and ({"back", "front"} & set(bc.sides)):
                raise ValueError(f"@boundaries.{i}.sides: back and front sides exist only in 3D")
            if bc.condition == "inflow":
                _ref(bc.material, deck.materials, f"boundaries.{i}.material", "material")
                if deck.materials[bc.material].type not in ("fluid", "high_explosive"):
                    raise ValueError(f"@boundaries.{i}.material: an inflow material is a fluid or high explosive, "
                                     f"'{bc.material}' is {deck.materials[bc.material].type}")
            section = deck.sections.get(deck.parts[bc.part].section)
            if bc.source is not None and deck.axisymmetric and bc.source[0] != 0.0:
                raise ValueError(f"@boundaries.{i}.source: in an axisymmetric deck the source is a point on the "
                                 f"axis (r = 0), not r = {bc.source[0]:g} (a ring)")
            if bc.condition in ("inflow", "transmit", "non_reflecting") and getattr(section, "mesh_motion", "") == "lagrangian":
                raise ValueError(f"@boundaries.{i}.condition: a lagrangian ALE mesh has no advection, "
                                 f"so no {bc.condition} sides")
            continue
        if getattr(bc, "part", None) in sph_parts | ale_parts:
            kind = "wall" if bc.part in sph_parts else "ale_boundary"
            raise ValueError(f"@boundaries.{i}.part: '{bc.part}' is a fluid part: use a {kind} boundary")
        directions = getattr(bc, "directions", None) or [getattr(bc, "normal", "x")]
        if deck.dimension == 2 and "z" in directions:
            key = "directions" if hasattr(bc, "directions") else "normal"
            raise ValueError(f"@boundaries.{i}.{key}: direction 'z' does not exist in 2D")
        if getattr(bc, "hold_rotation", False):
            part = deck.parts.get(bc.part) if bc.part is not None else None
            if part is None or not (part.rigid or getattr(deck.materials.get(part.material), "type", "") == "rigid"):
                raise ValueError(f"@boundaries.{i}.hold_rotation: holds the rotation of a rigid part, given by 'part'")

    for i, ic in enumerate(deck.initial):
        check_target(ic, f"initial.{i}")

    for i, load in enumerate(deck.loads):
        check_target(load, f"loads.{i}")
        if isinstance(load, Gravity):
            for name in load.parts or []:
                _ref(name, deck.parts, f"loads.{i}.parts", "part")
            acts_on_sph = sph_parts & set(load.parts or deck.parts)
            if load.curve is not None and acts_on_sph:
                raise ValueError(f"@loads.{i}.curve: gravity on SPH parts is constant (no curve)")
            if load.curve is not None and ale_parts & set(load.parts or deck.parts):
                raise ValueError(f"@loads.{i}.curve: gravity on ALE parts is constant (no curve)")
        if isinstance(load, PressureLoad) and _file_set(deck, getattr(load, "set", None)):
            raise ValueError(f"@loads.{i}.set: pressure needs a segment set; the sets of a mesh file are node sets")
        if _file_set(deck, getattr(load, "set", None)):
            continue
        if isinstance(load, PressureLoad) and not isinstance(deck.sets[load.set], SegmentSet):
            raise ValueError(f"@loads.{i}.set: pressure needs a segment set, '{load.set}' is a node set")
        if isinstance(load, NodalForce) and isinstance(deck.sets[load.set], SegmentSet):
            raise ValueError(f"@loads.{i}.set: nodal_force needs a node set, '{load.set}' is a segment set")

    names = set()
    for i, probe in enumerate(deck.output.probes):
        _ref(probe.part, deck.parts, f"output.probes.{i}.part", "part")
        front_in_ale = probe.type == "front" and (probe.part in ale_parts or (probe.part is None and not sph_parts))
        if front_in_ale and probe.material is None:
            raise ValueError(f"@output.probes.{i}: a front probe in an ALE part needs 'material' (whose front)")
        if probe.material is not None:
            _ref(probe.material, deck.materials, f"output.probes.{i}.material", "material")
            if not front_in_ale:
                raise ValueError(f"@output.probes.{i}.material: only a front probe in an ALE part takes a material")
            held = {m for name in ({probe.part} if probe.part else ale_parts)
                    for m in [deck.parts[name].material, *(f.material for f in deck.parts[name].fill or [])]}
            held |= {b.material for b in deck.boundaries if getattr(b, "condition", None) == "inflow"}
            if probe.material not in held:
                raise ValueError(f"@output.probes.{i}.material: '{probe.material}' is not a material of the ALE part "
                                 f"(it holds: {', '.join(sorted(m for m in held if m))})")
        if probe.type == "pressure" and probe.part in ale_parts:
            pass  # the ALE element at the point
        elif probe.type in ("pressure", "front") and probe.part is None and ale_parts and not sph_parts:
            pass
        elif front_in_ale:
            pass
        elif not sph_parts:
            raise ValueError(f"@output.probes.{i}: {probe.type} probes measure SPH parts and this deck has none"
                             + (" (an ALE part takes pressure and front probes)" if ale_parts else ""))
        elif probe.part is not None and probe.part not in sph_parts:
            raise ValueError(f"@output.probes.{i}.part: '{probe.part}' is not an SPH part "
                             f"(SPH parts: {', '.join(sorted(sph_parts))}"
                             + ("; pressure and front probes may name the ALE part" if ale_parts else "") + ")")
        _check_filter(deck, probe.filter, f"output.probes.{i}.filter")
        if probe.name in names:
            raise ValueError(f"@output.probes.{i}.name: duplicate history name '{probe.name}'")
        names.add(probe.name)
    for i, h in enumerate(deck.output.histories):
        check_target(h, f"output.histories.{i}")
        if h.part in sph_parts | ale_parts:
            raise ValueError(f"@output.histories.{i}.part: '{h.part}' is a fluid part: use output.probes or fields")
        if h.name in names:
            raise ValueError(f"@output.histories.{i}.name: duplicate history name '{h.name}'")
        names.add(h.name)
    if len(ale_parts) > 1:
        raise ValueError(f"@parts.{sorted(ale_parts)[1]}: one ALE part per deck (several material groups fill it)")
    _check_interactions(deck, sph_parts, ale_parts)


def _check_interactions(deck: Deck, sph_parts: set, ale_parts: set) -> None:
    """Contacts and couplings name existing parts and sets of the right kinds."""
    fluid_parts = sph_parts | ale_parts

    def surface(name: str, path: str) -> None:
        if name in deck.sets:
            if not isinstance(deck.sets[name], SegmentSet):
                raise ValueError(f"@{path}: '{name}' is a node set; a surface is a solid part or a segment set")
            return
        _ref(name, deck.parts, path, "part or segment set")
        if name in fluid_parts:
            raise ValueError(f"@{path}: '{name}' is a fluid part; a surface is a solid part or a segment set")

    for i, c in enumerate(deck.contacts):
        path = f"contacts.{i}"
        surface(c.surface, f"{path}.surface")
        if c.nodes in deck.sets:
            if isinstance(deck.sets[c.nodes], SegmentSet):
                raise ValueError(f"@{path}.nodes: '{c.nodes}' is a segment set; slaves are a part or a node set")
        else:
            _ref(c.nodes, deck.parts, f"{path}.nodes", "part or node set")
            if c.nodes in ale_parts:
                raise ValueError(f"@{path}.nodes: '{c.nodes}' is an ALE part: couple it with couplings.lagrange_in_solid")
        if c.nodes == c.surface:
            raise ValueError(f"@{path}.nodes: a part cannot be in contact with itself")
    for i, c in enumerate(deck.couplings):
        path = f"couplings.{i}"
        surface(c.structure, f"{path}.structure")
        _ref(c.fluid, deck.parts, f"{path}.fluid", "part")
        if c.type == "sph_boundary":
            if c.fluid not in sph_parts:
                raise ValueError(f"@{path}.fluid: '{c.fluid}' is not an SPH part (sph_boundary couples SPH particles; "
                                 "an ALE part takes lagrange_in_solid)")
            if deck.dimension != 2 or deck.axisymmetric:
                raise ValueError(f"@{path}.type: sph_boundary couplings are 2D plane only for now (3D or "
                                 "axisymmetric: use a nodes_to_surface contact)")
            material = deck.materials.get(deck.parts[c.fluid].material)
            if getattr(material, "viscosity", 0.0):
                raise ValueError(f"@{path}.fluid: sph_boundary couples inviscid fluids only for now (the viscous "
                                 f"stress does not see the boundary particles); '{deck.parts[c.fluid].material}' "
                                 "is viscous")
            continue
        if c.fluid not in ale_parts:
            raise ValueError(f"@{path}.fluid: '{c.fluid}' is not an ALE part")
        for j, mname in enumerate(c.materials or []):
            groups = [deck.parts[c.fluid].material] + [f.material for f in deck.parts[c.fluid].fill]
            if mname not in groups:
                raise ValueError(f"@{path}.materials.{j}: '{mname}' is not a material of ALE part '{c.fluid}' "
                                 f"(its materials: {', '.join(groups)})")


def _check_ale_part(deck: Deck, pname: str, part) -> None:
    where = f"parts.{pname}"
    section = deck.sections[part.section]
    if section.mesh_motion == "smoothed" and section.smoothing == "straight_lines" and deck.dimension == 2 \
            and section.line_axis == "z":
        raise ValueError(f"@sections.{part.section}.line_axis: a 2D mesh has lines along x or y only")
    for j, fill in enumerate(part.fill):
        if fill.polygon is not None and deck.dimension != 2:
            raise ValueError(f"@{where}.fill.{j}.polygon: polygons are 2D (use box, ball, cylinder or half_space in 3D)")
        if fill.cylinder is not None and deck.dimension != 3:
            raise ValueError(f"@{where}.fill.{j}.cylinder: cylinders are 3D (use ball in 2D)")
    kind = part.geometry.kind
    if kind not in ("box", "file"):
        raise ValueError(f"@{where}.geometry.{kind}: ALE parts are meshed from box or file")
    if kind == "box" and not (part.geometry.box.divisions or part.geometry.box.element_size):
        raise ValueError(f"@{where}.geometry.box: give 'divisions' or 'element_size'")
    if part.spacing is not None or part.rigid:
        raise ValueError(f"@{where}: ALE parts take no spacing or rigid")
    for j, name in enumerate([part.material] + [f.material for f in part.fill]):
        key = "material" if j == 0 else f"fill.{j - 1}.material"
        _ref(name, deck.materials, f"{where}.{key}", "material")
        if deck.materials[name].type not in ("fluid", "high_explosive", "void"):
            raise ValueError(f"@{where}.{key}: ALE materials are fluid or void, '{name}' is "
                             f"{deck.materials[name].type}")
