"""The run's settings resolved from the deck once, as plain frozen dataclasses the domains take.

`resolve_options(deck, model)` runs at the end of `model.build.build_model` and sets
`Model.options`. Below `model/` nothing reads the deck: the solver, its domains, the output and
the checkpoint take these records (and the model's arrays). A caller that changes the deck after
building the model (`sphfem regress` shortens the run) resolves them again.

Every class derives from `Options`: a checkpoint skips them (`output.snapshot`), since settings
come from the deck, never from a checkpoint.

Contract of the records: deck names are kept field for field (`pressure_cutoff`, `smoothing_weight`,
...); a `None` means what the deck's `None` means; vectors are tuples of floats, tables numpy arrays.
Contacts and couplings keep their validated deck records (`contact/` reads them field by field).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..materials.slots import P_RHO0

AXES = {"x": 0, "y": 1, "z": 2}


class Options:
    """Marker base of every settings record (skipped by checkpoints)."""


@dataclass(frozen=True)
class ControlOptions(Options):
    """`control`: end time and the time-step and guard settings (deck keys of the same names)."""

    end_time: float
    timestep_scale: float
    dt_min: float
    dt_max: float | None
    energy_band: tuple[float, float] | None
    max_steps: float
    max_lost_fraction: float | None
    max_penetration: float | None


@dataclass(frozen=True)
class Curve(Options):
    """One `curves` entry: time points, values, and the scale applied to the values."""

    points: tuple[tuple[float, float], ...]
    scale: float


@dataclass(frozen=True)
class KinematicCondition(Options):
    """A fixed, symmetry or prescribed-velocity boundary on the nodes of `part` or `set`.

    `components` are (axis, velocity) pairs (0 for fixed and symmetry); `curve` scales the
    prescribed values; `holds_body`: on a rigid part, the body's rotation is held too (fixed in
    every direction, or hold_rotation).
    """

    part: str | None
    set: str | None
    components: tuple[tuple[int, float], ...]
    curve: str | None
    holds_body: bool


@dataclass(frozen=True)
class GravityLoad(Options):
    acceleration: tuple[float, ...]
    parts: tuple[str, ...] | None  # None: every part
    curve: str | None


@dataclass(frozen=True)
class PressureLoad(Options):
    set: str
    value: float
    curve: str | None


@dataclass(frozen=True)
class NodalForce(Options):
    set: str
    force: tuple[float, ...]
    curve: str | None


@dataclass(frozen=True)
class InitialVelocity(Options):
    part: str | None
    set: str | None
    velocity: tuple[float, ...]


@dataclass(frozen=True)
class Erosion(Options):
    """A solid part's `erosion`: on negative volume, the plastic-strain limit and the time-step fraction (None: none)."""

    on_negative_volume: bool
    max_plastic_strain: float | None
    min_time_step_ratio: float | None


@dataclass(frozen=True)
class SolidOptions(Options):
    """What the solids' loop reads: conditions, loads, initial velocities (in deck order) and erosion by part."""

    conditions: tuple[KinematicCondition, ...]
    gravity: tuple[GravityLoad, ...]
    pressures: tuple[PressureLoad, ...]
    nodal_forces: tuple[NodalForce, ...]
    initial: tuple[InitialVelocity, ...]
    erosion: dict[str, Erosion]


@dataclass(frozen=True)
class SphWall(Options):
    """A ghost-particle `wall` boundary: sides of the box min..max, `condition` (tangential, or a
    non_reflecting open side with the waves' `source` point)."""

    min: tuple[float, ...]
    max: tuple[float, ...]
    sides: tuple[str, ...]
    condition: str
    source: tuple[float, ...] | None = None


@dataclass(frozen=True)
class SphDomainOptions(Options):
    """The SPH section and what acts on the SPH parts (deck names; see sph.system.SphOptions).

    `gravity` is the sum of the gravity loads on any SPH part; `wall_points` the `dummy_wall`
    particles (None without), at `wall_spacing`; `initial_velocity` (part name, velocity) in deck order.
    """

    kernel: str
    smoothing_ratio: float
    alpha: float
    beta: float
    epsilon: float
    switch_alpha_max: float | None  # the viscosity switch (None: off) and its decay constant
    switch_decay: float | None
    density_diffusion: float
    density_diffusion_form: str
    xsph: float
    continuity: str
    diffusion_hydrostatic: bool
    ghost_hydrostatic: bool
    pressure_cutoff: float | None
    domain: tuple[tuple[float, ...], tuple[float, ...]] | None
    walls: tuple[SphWall, ...]
    gravity: np.ndarray
    initial_velocity: tuple[tuple[str, tuple[float, ...]], ...]
    wall_points: np.ndarray | None
    wall_spacing: float
    detonations: tuple[tuple[tuple[float, ...], float], ...]


@dataclass(frozen=True)
class AleSide(Options):
    """An `ale_boundary` on some sides; `material` indexes the ALE part's materials (inflow only); `source`
    the centre of the waves a non_reflecting side lets out."""

    sides: tuple[str, ...]
    condition: str
    material: int | None
    velocity: tuple[float, ...] | None
    density: float | None
    energy: float | None
    pressure: float | None
    source: tuple[float, ...] | None = None


@dataclass(frozen=True)
class AleDomainOptions(Options):
    """The ALE part's section, burn, gravity and sides (deck names; see ale.system.AleSystem).

    `burn` holds (material index in the part, detonation velocity) of its high explosives;
    `gravity` the acceleration of each gravity load on the part, in deck order.
    """

    part: str
    q1: float
    q2: float
    hourglass: float
    advection: str
    interface: str
    closure: str
    advect_every: int
    mesh_motion: str
    smoothing: str
    smoothing_weight: float
    smoothing_iterations: int
    eulerian_pull: float
    smoothing_boundary: str
    pressure_cutoff: float | None
    line_axis: str
    timestep_scale: float
    burn: tuple[tuple[int, float], ...]
    detonations: tuple[tuple[tuple[float, ...], float], ...]
    gravity: tuple[np.ndarray, ...]
    sides: tuple[AleSide, ...]


@dataclass(frozen=True)
class OutputOptions(Options):
    """`output` with its defaults filled in: field and history intervals, the selected fields
    (`selectable`: the names a deck can select; a domain writes its other fields always),
    the history requests and probes (deck records, read field by field)."""

    interval: float
    history_interval: float
    fields: frozenset[str]
    selectable: frozenset[str]
    histories: tuple = ()
    probes: tuple = ()
    revolve: tuple[int, float] | None = None  # output.revolve (segments, angle in degrees); axisymmetric decks only


@dataclass(frozen=True)
class RunOptions(Options):
    control: ControlOptions
    curves: dict[str, Curve]
    solids: SolidOptions
    output: OutputOptions
    sph: SphDomainOptions | None = None
    ale: AleDomainOptions | None = None
    contacts: tuple = ()
    couplings: tuple = ()
    detonations: tuple[tuple[tuple[float, ...], float], ...] = field(default=())


def _vec(v) -> tuple[float, ...] | None:
    return None if v is None else tuple(float(c) for c in v)


def resolve_options(deck, model) -> RunOptions:
    """Every setting the run reads, from the validated deck (see the module docstring)."""
    from ..deck.schema import FIELD_NAMES

    c = deck.control
    control = ControlOptions(
        end_time=c.end_time, timestep_scale=c.timestep_scale, dt_min=c.dt_min, dt_max=c.dt_max,
        energy_band=None if c.energy_band is None else tuple(c.energy_band), max_steps=c.max_steps,
        max_lost_fraction=c.max_lost_fraction, max_penetration=c.max_penetration,
    )
    out = deck.output
    output = OutputOptions(
        interval=out.interval or c.end_time / 50.0, history_interval=out.history_interval or c.end_time / 1000.0,
        fields=frozenset(out.fields), selectable=frozenset(FIELD_NAMES),
        histories=tuple(out.histories), probes=tuple(out.probes),
        revolve=None if out.revolve is None else (out.revolve.segments, out.revolve.angle),
    )
    detonations = tuple((_vec(d.point), d.time) for d in deck.detonations)
    return RunOptions(
        control=control,
        curves={name: Curve(tuple((p[0], p[1]) for p in cv.points), cv.scale) for name, cv in deck.curves.items()},
        solids=_solid_options(deck, model), output=output,
        sph=_sph_options(deck, model, detonations) if model.particles is not None else None,
        ale=_ale_options(deck, model, detonations) if model.ale is not None else None,
        contacts=tuple(deck.contacts), couplings=tuple(deck.couplings), detonations=detonations,
    )


def _rigid_target(model, bc, where: str) -> tuple[str | None, str | None]:
    """(part, set) of a kinematic condition, with a set on a rigid body's nodes read as its part.

    A rigid body moves as one (solver.boundary.RigidBodies), so its condition is the body's: a set
    that holds every node of one rigid part and nothing else is that part; a set holding some of a
    rigid part's nodes, or rigid nodes with others, is an error (before, the nodes' flags were set
    and the body ignored them: a 'fixed' anvil under a Taylor rod flew off with it).
    """
    from . import build

    if bc.set is None or not model.rigid_bodies:
        return bc.part, bc.set
    nodes = np.unique(model.target_nodes(None, bc.set))
    for body in model.rigid_bodies:
        shared = np.intersect1d(nodes, body.nodes)
        if not len(shared):
            continue
        name = model.parts[body.part].name
        if len(shared) == len(body.nodes) == len(nodes):
            return name, None
        raise build.ModelError(f"{where}.set", f"set '{bc.set}' holds {len(shared)} of the {len(body.nodes)} nodes of "
                               f"rigid part '{name}'" + (f" and {len(nodes) - len(shared)} other nodes" if len(nodes) > len(shared) else "")
                               + f": a rigid body moves as one; constrain it with `part: {name}`")
    return bc.part, bc.set


def _solid_options(deck, model) -> SolidOptions:
    from ..deck.schema import AleBoundary, DummyWallBoundary, FixedBoundary, Gravity
    from ..deck.schema import NodalForce as DeckNodal
    from ..deck.schema import PressureLoad as DeckPressure
    from ..deck.schema import SymmetryBoundary, WallBoundary

    conditions = []
    for i, bc in enumerate(deck.boundaries):
        if isinstance(bc, (WallBoundary, DummyWallBoundary, AleBoundary)):
            continue  # fluid walls: SPH ghosts, ALE mesh conditions
        part, node_set = _rigid_target(model, bc, f"boundaries.{i}")
        if isinstance(bc, FixedBoundary):
            comps = tuple((AXES[d], 0.0) for d in (bc.directions or "xyz"[:model.dim]))
            conditions.append(KinematicCondition(part, node_set, comps, None,
                                                 len(comps) == model.dim or bc.hold_rotation))
        elif isinstance(bc, SymmetryBoundary):
            conditions.append(KinematicCondition(part, node_set, ((AXES[bc.normal], 0.0),), None, False))
        else:
            comps = tuple((k, val) for k, val in enumerate(bc.velocity) if val is not None)
            conditions.append(KinematicCondition(part, node_set, comps, bc.curve, False))
    erosion = {}
    for name, part in deck.parts.items():
        spec = getattr(part, "erosion", None)
        if spec is not None:
            erosion[name] = Erosion(spec.on_negative_volume, spec.max_plastic_strain, spec.min_time_step_ratio)
    return SolidOptions(
        conditions=tuple(conditions),
        gravity=tuple(GravityLoad(_vec(g.acceleration), None if g.parts is None else tuple(g.parts), g.curve)
                      for g in deck.loads if isinstance(g, Gravity)),
        pressures=tuple(PressureLoad(p.set, p.value, p.curve) for p in deck.loads if isinstance(p, DeckPressure)),
        nodal_forces=tuple(NodalForce(f.set, _vec(f.force), f.curve) for f in deck.loads if isinstance(f, DeckNodal)),
        initial=tuple(InitialVelocity(ic.part, ic.set, _vec(ic.velocity)) for ic in deck.initial),
        erosion=erosion,
    )


def _dummy_wall_points(deck, default_spacing: float) -> tuple[np.ndarray | None, float]:
    """The deck's `dummy_wall` boundaries as one array of wall particles, and their spacing."""
    from ..deck.schema import DummyWallBoundary
    from ..sph import lattice

    walls = [bc for bc in deck.boundaries if isinstance(bc, DummyWallBoundary)]
    if not walls:
        return None, default_spacing
    dx = walls[0].spacing or default_spacing  # one spacing for all (checked with the deck)
    points = []
    for bc in walls:
        if bc.region is None:
            points.append(lattice.box_wall_particles(bc.min, bc.max, dx, bc.layers, bc.sides))
        elif bc.region.box is not None:
            points.append(lattice.box(bc.region.box.min, bc.region.box.max, dx))
        elif bc.region.ball is not None:
            fill = lattice.circle if len(bc.region.ball.center) == 2 else lattice.sphere
            points.append(fill(bc.region.ball.center, bc.region.ball.radius, dx))
        else:
            points.append(lattice.polygon(bc.region.polygon.vertices, dx))
    return np.vstack(points), dx


def _check_open_sides(deck, model) -> None:
    """A non_reflecting side needs every particle on its inner side at the start (its images are offset
    outwards from their particles, sph/open_sides.py): a deck error (ModelError) otherwise."""
    from ..deck.schema import WallBoundary
    from ..deck.schema.boundaries import BOX_FACES
    from .build import ModelError

    x = model.particles.x
    for i, bc in enumerate(deck.boundaries):
        if not (isinstance(bc, WallBoundary) and bc.condition == "non_reflecting"):
            continue
        for s in bc.sides:
            axis, which, side = BOX_FACES[s]
            if axis >= x.shape[1]:
                continue
            beyond = side * (x[:, axis] - (bc.min, bc.max)[which][axis]) < 0.0
            if beyond.any():
                raise ModelError(f"boundaries.{i}.sides", f"{int(beyond.sum())} particles start beyond the "
                                 f"non_reflecting side '{s}' (the first at {x[np.argmax(beyond)].tolist()}); "
                                 "an open side needs the fluid on its inner side")


def _sph_options(deck, model, detonations) -> SphDomainOptions:
    from ..deck.schema import Gravity, InitialVelocity as DeckVelocity, WallBoundary

    section = deck.sections[model.particles.section]
    sph_names = {p.name for p in model.parts if p.kind == "sph"}
    gravity = np.zeros(model.dim)
    for load in deck.loads:
        if isinstance(load, Gravity) and (load.parts is None or sph_names & set(load.parts)):
            gravity += np.array(load.acceleration)
    points, dx = _dummy_wall_points(deck, float(model.particles.spacing.min()))
    _check_open_sides(deck, model)
    visc = section.artificial_viscosity
    return SphDomainOptions(
        kernel=section.kernel, smoothing_ratio=section.smoothing_ratio, alpha=visc.alpha, beta=visc.beta,
        epsilon=visc.epsilon, density_diffusion=section.density_diffusion,
        switch_alpha_max=None if visc.switch is None else visc.switch.alpha_max,
        switch_decay=None if visc.switch is None else visc.switch.decay,
        density_diffusion_form=section.density_diffusion_form, xsph=section.xsph,
        continuity=section.continuity, diffusion_hydrostatic=section.diffusion_hydrostatic, ghost_hydrostatic=section.ghost_hydrostatic,
        pressure_cutoff=section.pressure_cutoff,
        domain=None if section.domain is None else (_vec(section.domain.min), _vec(section.domain.max)),
        walls=tuple(SphWall(_vec(bc.min), _vec(bc.max), tuple(bc.sides), bc.condition,
                            None if bc.source is None else _vec(bc.source))
                    for bc in deck.boundaries if isinstance(bc, WallBoundary)),
        gravity=gravity,
        initial_velocity=tuple((ic.part, _vec(ic.velocity)) for ic in deck.initial
                               if isinstance(ic, DeckVelocity) and ic.part in sph_names),
        wall_points=points, wall_spacing=dx, detonations=detonations,
    )


def _ale_options(deck, model, detonations) -> AleDomainOptions:
    from ..deck.schema import AleBoundary, Gravity

    name = model.parts[model.ale.part].name
    section = deck.sections[deck.parts[name].section]
    add_inflow_materials(deck, model, name)
    names = [model.material_names[m] for m in model.ale.materials]
    sides = tuple(
        AleSide(tuple(bc.sides), bc.condition, None if bc.material is None else names.index(bc.material),
                _vec(bc.velocity), bc.density, bc.energy, bc.pressure, _vec(bc.source))
        for bc in deck.boundaries if isinstance(bc, AleBoundary))
    return AleDomainOptions(
        part=name, q1=section.bulk_viscosity.q1, q2=section.bulk_viscosity.q2, hourglass=section.hourglass,
        advection=section.advection, interface=section.interface, closure=section.closure,
        advect_every=section.advect_every, mesh_motion=section.mesh_motion, smoothing=section.smoothing,
        smoothing_weight=section.smoothing_weight, smoothing_iterations=section.smoothing_iterations,
        eulerian_pull=section.eulerian_pull, smoothing_boundary=section.smoothing_boundary,
        pressure_cutoff=section.pressure_cutoff, line_axis=section.line_axis, timestep_scale=section.timestep_scale,
        burn=tuple((j, deck.materials[n].detonation_velocity) for j, n in enumerate(names)
                   if deck.materials[n].type == "high_explosive"),
        detonations=detonations,
        gravity=tuple(np.array(load.acceleration[:model.dim], dtype=float) for load in deck.loads
                      if isinstance(load, Gravity) and (load.parts is None or name in load.parts)),
        sides=sides,
    )


def add_inflow_materials(deck, model, part: str) -> None:
    """Materials entering through inflow sides that no fill holds join the ALE part with zero
    fraction (density the material's rho0, pressure 0); a material already there is left alone."""
    from ..deck.schema import AleBoundary

    mesh = model.ale
    for bc in deck.boundaries:
        if not (isinstance(bc, AleBoundary) and bc.part == part and bc.condition == "inflow"):
            continue
        m = model.material_names.index(bc.material)
        if m in mesh.materials:
            continue
        n_elem = len(mesh.elements)
        rho0 = float(model.material_param[m, P_RHO0])
        mesh.materials.append(m)
        mesh.fractions = np.hstack([mesh.fractions, np.zeros((n_elem, 1))])
        mesh.density = np.hstack([mesh.density, np.full((n_elem, 1), rho0)])
        mesh.pressure = np.hstack([mesh.pressure, np.zeros((n_elem, 1))])
