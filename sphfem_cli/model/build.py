"""Deck -> Model: every part meshed, materials and sections packed into tables, sets resolved.

The model is plain numpy arrays; nothing here runs per step.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from ..deck.schema import Deck, SegmentSet
from ..fem.slots import (HG_STIFFNESS, HG_VISCOUS, NSEC, PLANE_STRAIN, PLANE_STRESS, SEC_FORMULATION, SEC_HG_COEF,
                         SEC_HG_TYPE, SEC_Q1, SEC_Q2)
from ..materials.ids import RIGID
from ..materials.slots import NPARAM, P_G, P_K, P_RHO0

VOID = -1  # material type id of void (ALE only; no row in the kernels)
from ..materials.tables import pack_material
from . import checks
from . import mesh as meshgen
from . import sets as selection
from .ale_build import AleMesh, ale_mesh
from .pages import set_up_pages
from .options import RunOptions, resolve_options
from .sizes import (BYTES_PER_ELEMENT, BYTES_PER_NODE, BYTES_PER_PARTICLE,  # noqa: F401 - re-exported
                    available_memory, check_memory)


class ModelError(Exception):
    """A deck that validates but cannot be built (unreadable mesh, empty selection).

    Carries the dotted deck path so the caller can point at the key's line and column.
    """

    def __init__(self, path: str, message: str) -> None:
        self.path = path
        self.message = message
        super().__init__(f"{path}: {message}")


@dataclass
class PartInfo:
    """One part's slices into the global node and element arrays (solid) or particle arrays (sph)."""

    name: str
    nodes: slice
    elements: slice
    material: int
    section: int
    rigid: bool
    kind: str = "solid"
    particles: slice = field(default_factory=lambda: slice(0, 0))


@dataclass
class SphParticles:
    """The SPH particles of every SPH part, as one particle system.

    `material` indexes the fluid sub-table (`material_type`, `material_param`) and `fluid_names`.
    """

    x: np.ndarray  # (P, dim)
    mass: np.ndarray
    density: np.ndarray
    material: np.ndarray
    part: np.ndarray  # index into Model.parts
    spacing: np.ndarray  # per particle
    material_type: np.ndarray
    material_param: np.ndarray
    section: str

    @property
    def n(self) -> int:
        return len(self.x)


@dataclass
class RigidBody:
    """A rigid part: its nodes move as one body (3 DOF in 2D, 6 in 3D)."""

    part: int
    nodes: np.ndarray
    mass: float
    center: np.ndarray  # initial centre of mass
    inertia: np.ndarray  # 2D: polar moment (scalar array); 3D: (3, 3) about the centre


@dataclass
class Model:
    deck: Deck
    deck_path: Path
    dim: int
    coordinates: np.ndarray  # (N, dim) initial
    connectivity: np.ndarray  # (E, 4|8)
    parts: list[PartInfo]
    element_part: np.ndarray
    element_material: np.ndarray
    element_section: np.ndarray
    element_active: np.ndarray  # False for rigid-part elements
    material_names: list[str]
    material_type: np.ndarray  # (M,)
    material_param: np.ndarray  # (M, NPARAM)
    section_param: np.ndarray  # (S, NSEC)
    volume0: np.ndarray  # (E,)
    mass: np.ndarray  # (N,) lumped
    node_elem_ptr: np.ndarray
    node_elem_idx: np.ndarray
    node_sets: dict[str, np.ndarray] = field(default_factory=dict)
    segment_sets: dict[str, np.ndarray] = field(default_factory=dict)
    rigid_bodies: list[RigidBody] = field(default_factory=list)
    particles: SphParticles | None = None
    ale: "AleMesh | None" = None
    element_dt_factor: np.ndarray | None = None  # (E,) see free_dilatation_factor; None: all 1
    options: "RunOptions | None" = None  # the settings below model/ reads (model.options.resolve_options)
    axisymmetric: bool = False  # dimension: axisymmetric (x = r, y = the axis; volumes and masses for 2 pi)

    @property
    def n_nodes(self) -> int:
        return self.coordinates.shape[0]

    @property
    def n_elements(self) -> int:
        return self.connectivity.shape[0]

    @property
    def nodes_per_element(self) -> int:
        return self.connectivity.shape[1]

    def part_index(self, name: str) -> int:
        return next(i for i, p in enumerate(self.parts) if p.name == name)

    def part_nodes(self, name: str) -> np.ndarray:
        s = self.parts[self.part_index(name)].nodes
        return np.arange(s.start, s.stop)

    def target_nodes(self, part: str | None, set_name: str | None) -> np.ndarray:
        """Node ids of a part or of a node/segment set."""
        if part is not None:
            return self.part_nodes(part)
        if set_name in self.node_sets:
            return self.node_sets[set_name]
        return np.unique(self.segment_sets[set_name])

    def memory_bytes(self) -> int:
        """Estimated bytes of a run of this model (the same figures `check_memory` uses)."""
        particles = self.particles.n if self.particles is not None else 0
        ale_nodes = len(self.ale.nodes) if self.ale is not None else 0
        ale_elements = len(self.ale.elements) if self.ale is not None else 0
        return ((self.n_nodes + ale_nodes) * BYTES_PER_NODE + (self.n_elements + ale_elements) * BYTES_PER_ELEMENT
                + particles * BYTES_PER_PARTICLE)


def _packed(name: str, m, deck: Deck) -> tuple[int, np.ndarray]:
    """The (type id, parameter row) of material `name`; a derived constant that overflows is a deck error."""
    if m.type == "void":
        return VOID, np.zeros(NPARAM)
    eos_name = getattr(m, "eos", None) or ""
    try:
        return pack_material(m, deck.equations_of_state.get(eos_name, None))
    except OverflowError:  # e.g. sound_speed 1e308: rho0 c^2 (found by fuzzing)
        where = f"equations_of_state.{eos_name}" if eos_name in deck.equations_of_state else f"materials.{name}"
        raise ModelError(where, "a constant derived from these values overflows (check their magnitude and the units)") from None


def build_model(deck: Deck, deck_path: Path) -> Model:
    """Mesh every part and pack every table of the deck into a :class:`Model`."""
    check_memory(deck)
    dim = deck.dimension
    material_names = list(deck.materials)
    rows = [_packed(name, m, deck) for name, m in deck.materials.items()]
    material_type = np.array([r[0] for r in rows], dtype=np.int64)
    material_param = np.vstack([r[1] for r in rows])
    checks.moduli(SimpleNamespace(material_names=material_names, material_param=material_param))

    section_names = list(deck.sections)
    section_param = np.zeros((len(section_names), NSEC))
    for i, s in enumerate(deck.sections.values()):
        if s.type != "solid":
            continue
        section_param[i, SEC_HG_TYPE] = HG_STIFFNESS if s.hourglass.type == "stiffness" else HG_VISCOUS
        section_param[i, SEC_HG_COEF] = s.hourglass.coefficient
        section_param[i, SEC_Q1] = s.bulk_viscosity.q1
        section_param[i, SEC_Q2] = s.bulk_viscosity.q2
        section_param[i, SEC_FORMULATION] = PLANE_STRESS if s.formulation == "plane_stress" else PLANE_STRAIN

    coords, conns, parts, file_sets = [], [], [], {}
    n_nodes = n_elems = 0
    for name, part in deck.parts.items():
        fluid_kind = {"sph": "sph", "ale_multi_material": "ale"}.get(deck.sections[part.section].type)
        if fluid_kind is not None:
            parts.append(PartInfo(name, slice(n_nodes, n_nodes), slice(n_elems, n_elems),
                                  material_names.index(part.material), section_names.index(part.section),
                                  False, kind=fluid_kind))
            continue
        mesh = _mesh_part(name, part, dim, deck_path)
        checks.elements(name, part, mesh)
        if deck.axisymmetric:
            checks.radii(name, mesh)
        conns.append(mesh.elements + n_nodes)
        coords.append(mesh.nodes)
        mat = material_names.index(part.material)
        rigid = part.rigid or material_type[mat] == RIGID
        parts.append(PartInfo(name, slice(n_nodes, n_nodes + mesh.n_nodes),
                              slice(n_elems, n_elems + mesh.n_elements),
                              mat, section_names.index(part.section), bool(rigid)))
        for set_name, ids in mesh.node_sets.items():
            file_sets[f"{name}.{set_name}"] = ids + n_nodes
        n_nodes += mesh.n_nodes
        n_elems += mesh.n_elements

    npe = 4 if dim == 2 else 8
    coordinates = np.vstack(coords) if coords else np.zeros((0, dim))
    connectivity = np.vstack(conns).astype(np.int64) if conns else np.zeros((0, npe), dtype=np.int64)
    element_part = np.concatenate([np.full(p.elements.stop - p.elements.start, i, dtype=np.int64)
                                   for i, p in enumerate(parts)])
    element_material = np.array([parts[i].material for i in element_part], dtype=np.int64)
    element_section = np.array([parts[i].section for i in element_part], dtype=np.int64)
    element_active = np.array([not parts[i].rigid for i in element_part])

    if dim == 3 and len(connectivity):
        volume0 = meshgen.hex8_volumes(coordinates, connectivity)  # fem.geometry.hex8_gradient's bits, numpy
    else:
        volume0 = meshgen.element_jacobian_sign_check(coordinates, connectivity)  # exact quad4 areas
    if deck.axisymmetric and len(connectivity):
        volume0 = meshgen.ring_volumes(coordinates, connectivity)  # 2 pi r_c A, fem.axisymmetric's bits, numpy
    mass = np.zeros(len(coordinates))
    np.add.at(mass, connectivity, (material_param[element_material, P_RHO0] * volume0 / npe)[:, None])

    ptr, idx = _node_element_map(connectivity, len(coordinates))
    dt_factor = free_dilatation_factor(connectivity, dim, material_param[element_material],
                                       section_param[element_section, SEC_FORMULATION] == PLANE_STRESS)
    model = Model(
        deck=deck, deck_path=deck_path, dim=dim, coordinates=coordinates, connectivity=connectivity,
        parts=parts, element_part=element_part, element_material=element_material,
        element_section=element_section, element_active=element_active,
        material_names=material_names, material_type=material_type, material_param=material_param,
        section_param=section_param, volume0=volume0, mass=mass, node_elem_ptr=ptr, node_elem_idx=idx,
        element_dt_factor=dt_factor, axisymmetric=deck.axisymmetric,
    )
    model.node_sets.update(file_sets)
    checks.file_sets(deck, file_sets)
    _resolve_sets(model, deck)
    model.rigid_bodies = [_rigid_body(model, i) for i, p in enumerate(parts) if p.rigid]
    if any(p.kind == "sph" for p in parts):
        model.particles = _particles(model, deck)
    if any(p.kind == "ale" for p in parts):
        index = next(i for i, p in enumerate(parts) if p.kind == "ale")
        name = parts[index].name
        with set_up_pages():  # numpy's huge-page advice off (model/pages.py)
            mesh = _mesh_part(name, deck.parts[name], dim, deck_path)
            checks.elements(name, deck.parts[name], mesh)  # an ALE mesh too (a box 5e-324 wide failed later; fuzzing)
            if deck.axisymmetric:  # rings about the axis (ale/axisymmetric.py): x = r >= 0, near-axis nodes on it
                checks.radii(name, mesh)
            model.ale = ale_mesh(model, deck, index, mesh)
    model.options = resolve_options(deck, model)
    return model


K_MARGIN = 0.3  # see free_dilatation_factor


def free_dilatation_factor(connectivity: np.ndarray, dim: int, params: np.ndarray,
                           plane_stress: np.ndarray | None = None) -> np.ndarray | None:
    """Per element, the factor on its stable step V/A_max c for the directions it can dilate freely.

    An element whose two opposite faces are both exterior along k of its directions can stretch
    along them without its neighbours resisting: the one-point element's highest mode is then the
    dilatation in those directions, omega^2 = 4 (k lambda + 2 mu) / (rho h^2) with lumped mass,
    against 4 (lambda + 2 mu) / (rho h^2) for a confined element, so its step is
    sqrt((lambda + 2 mu) / (k lambda + 2 mu)) of the usual one (an isolated hex8 at nu = 0.3: 0.734,
    an isolated quad4: 0.836, the exact limits in tests/verification/test_stable_step.py).
    k carries a margin of K_MARGIN where it is not 0, for what the element-wise mode leaves out:
    neighbours moving in opposition couple into the free mode (a plate one element thick, without
    hourglass control, needs 0.994 of its k = 1 step at nu = 0.3: tests/verification/test_stable_step.py),
    and hourglass stiffness adds to it (the same plate struck at 10 m/s with stiffness hourglass
    control 0.1 still grew at a margin of 0.1, and runs at 0.3: benchmarks/stability_extremes.py,
    group "thin 3D parts"). With the margin a k = 1 element takes 0.941 of the step at nu = 0.3.
    In plane-stress elements (``plane_stress`` (E,) True) lambda is the plane-stress
    lambda_bar = 2 mu lambda / (lambda + 2 mu) = E nu / (1 - nu^2), with which lambda_bar + 2 mu is the
    modulus of the element's wave speed (``materials.kernels.plane_stress_sound_speed``).
    None when every factor is 1 (a mesh without thin parts).
    """
    if not len(connectivity):
        return None
    exterior = selection.exterior_faces(connectivity, dim)
    k = np.zeros(len(connectivity))
    for a, b in selection.OPPOSITE_FACES[dim]:
        k += exterior[:, a] & exterior[:, b]
    g = params[:, P_G]
    lam = params[:, P_K] - 2.0 * g / 3.0
    if plane_stress is not None:
        with np.errstate(invalid="ignore", divide="ignore"):
            lam = np.where(plane_stress, 2.0 * g * lam / (lam + 2.0 * g), lam)
    with np.errstate(invalid="ignore", divide="ignore"):
        factor = np.sqrt((lam + 2.0 * g) / ((k + np.where(k > 0, K_MARGIN, 0.0)) * lam + 2.0 * g))
    factor = np.where(np.isfinite(factor) & (factor > 0.0), np.minimum(factor, 1.0), 1.0)
    return factor if np.any(factor < 1.0) else None


def norm(v) -> float:
    """|v| without underflow or overflow of the squares (a gravity of 1e-300 has |g| = 1e-300, not 0)."""
    v = np.asarray(v, dtype=np.float64)
    scale = float(np.max(np.abs(v))) if v.size else 0.0
    return scale * float(np.linalg.norm(v / scale)) if scale > 0.0 else 0.0


def unit(v) -> np.ndarray:
    """v / |v| for a nonzero finite v (see :func:`norm`)."""
    v = np.asarray(v, dtype=np.float64)
    scaled = v / np.max(np.abs(v))
    return scaled / np.linalg.norm(scaled)


def _particles(model: Model, deck: Deck) -> SphParticles:
    """Fill every SPH part with lattice particles; one fluid sub-table for the particle system."""
    from ..deck.schema import Gravity
    from ..sph import lattice

    sph = [(i, p) for i, p in enumerate(model.parts) if p.kind == "sph"]
    used = sorted({p.material for _, p in sph})
    xs, rho, mat, owner, dx_of = [], [], [], [], []
    start = 0
    for i, p in sph:
        part = deck.parts[p.name]
        dx, g = part.spacing, part.geometry
        if g.box is not None:
            pts = lattice.box(g.box.min, g.box.max, dx)
        elif g.ball is not None and deck.axisymmetric and g.ball.center[0] == 0.0:
            # a sphere on the axis: its meridian half-disc, on the lattice x = (i + 1/2) dx from the axis
            cz, rad = g.ball.center[1], g.ball.radius
            pts = lattice.box([0.0, cz - rad], [rad, cz + rad], dx)
            pts = pts[np.hypot(pts[:, 0], pts[:, 1] - cz) < rad]
        elif g.ball is not None:
            pts = (lattice.circle if model.dim == 2 else lattice.sphere)(g.ball.center, g.ball.radius, dx)
        elif g.polygon is not None:
            pts = lattice.polygon(g.polygon.vertices, dx)
        else:
            try:
                memory = available_memory()
                pts = lattice.surface_fill((model.deck_path.parent / g.file.file).resolve(), model.dim, dx,
                                           g.file.scale, None if memory is None else memory // BYTES_PER_PARTICLE)
            except (ValueError, OSError) as exc:
                raise ModelError(f"parts.{p.name}.geometry.file", f"{g.file.file}: {str(exc).splitlines()[0]}") from None
        if len(pts) == 0:
            raise ModelError(f"parts.{p.name}.spacing", f"spacing {dx:g} leaves no particle in the part's geometry")
        local = used.index(p.material)
        density = np.full(len(pts), model.material_param[p.material, P_RHO0])
        if part.hydrostatic:
            gravity = sum((np.array(l.acceleration) for l in deck.loads
                           if isinstance(l, Gravity) and (l.parts is None or p.name in l.parts)),
                          np.zeros(model.dim))
            if not np.any(gravity):
                raise ModelError(f"parts.{p.name}.hydrostatic", "a hydrostatic start needs a gravity load")
            up = -unit(gravity)
            surface = pts[np.argmax(pts @ up)] + 0.5 * dx * up
            density = lattice.hydrostatic_density(pts, model.material_param[used], np.full(len(pts), local),
                                                  gravity, surface)
        model.parts[i].particles = slice(start, start + len(pts))
        start += len(pts)
        xs.append(pts)
        rho.append(density)
        mat.append(np.full(len(pts), local, dtype=np.int64))
        owner.append(np.full(len(pts), i, dtype=np.int64))
        dx_of.append(np.full(len(pts), dx))
    x = np.vstack(xs)
    spacing = np.concatenate(dx_of)
    density = np.concatenate(rho)
    volume = spacing ** model.dim
    if deck.axisymmetric:  # ring volumes 2 pi r dx^2 for the full 2 pi (sph/axisymmetric.py)
        off = np.flatnonzero(~(x[:, 0] > 0.0))
        if off.size:
            k = int(off[0])
            raise ModelError(f"parts.{model.parts[np.concatenate(owner)[k]].name}.geometry",
                             f"particle at r = x = {x[k, 0]:g}: an axisymmetric SPH part lies in x = r > 0 "
                             "(the axis is x = 0)")
        volume = 2.0 * np.pi * x[:, 0] * volume
    mass = model.material_param[np.array(used)[np.concatenate(mat)], P_RHO0] * volume
    owners = np.concatenate(owner)
    tiny = np.finfo(np.float64).tiny
    degenerate = ~((mass >= tiny) & np.isfinite(mass) & (density >= tiny) & np.isfinite(density))
    if degenerate.any():  # e.g. a density of 5e-324 makes the mass underflow to zero (found by fuzzing)
        k = int(np.argmax(degenerate))
        raise ModelError(f"parts.{model.parts[owners[k]].name}.material",
                         f"particle mass {mass[k]:g} and density {density[k]:g} must be finite positive normal "
                         "numbers (check the material density, the spacing and the units)")
    checks.particle_density(model, deck, np.array(used), np.concatenate(mat), density, owners)
    return SphParticles(
        x=x, mass=mass, density=density,
        material=np.concatenate(mat), part=owners, spacing=spacing,
        material_type=model.material_type[used], material_param=model.material_param[used],
        section=deck.parts[sph[0][1].name].section,
    )


def _mesh_part(name, part, dim, deck_path: Path) -> meshgen.MeshData:
    g = part.geometry
    where = checks.geometry_path(name, part)
    try:
        if g.box is not None:
            return meshgen.box_mesh(g.box.min, g.box.max, divisions=g.box.divisions, element_size=g.box.element_size)
        if g.ring is not None:
            r = g.ring
            return meshgen.ring_mesh(r.center, r.inner_radius, r.outer_radius, r.elements_around, r.elements_through)
        if g.cylinder is not None:
            c = g.cylinder
            return meshgen.cylinder_mesh(c.center, c.axis, c.inner_radius, c.outer_radius, c.length,
                                         c.elements_around, c.elements_through, c.elements_along)
        path = (deck_path.parent / g.file.file).resolve()
        data = meshgen.read_mesh(path, dim)
        data.nodes *= g.file.scale
        return data
    except (ValueError, OSError) as exc:
        raise ModelError(where, str(exc).splitlines()[0]) from None


def _node_element_map(conn: np.ndarray, n_nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """CSR map node -> (element * nodes_per_element + local index), sorted for determinism."""
    flat = conn.ravel()
    order = np.argsort(flat, kind="stable")
    counts = np.bincount(flat, minlength=n_nodes)
    ptr = np.zeros(n_nodes + 1, dtype=np.int64)
    np.cumsum(counts, out=ptr[1:])
    return ptr, order.astype(np.int64)


def _resolve_sets(model: Model, deck: Deck) -> None:
    extent = np.ptp(model.coordinates, axis=0).max() if model.n_nodes else 1.0
    for name, s in deck.sets.items():
        if s.part is not None:
            candidates = model.part_nodes(s.part)
        else:
            candidates = np.arange(model.n_nodes)
        x = model.coordinates[candidates]
        tol = s.tolerance if s.tolerance is not None else 1e-6 * extent
        keep = np.ones(len(candidates), dtype=bool)
        if s.side is not None:
            axis, sign = selection.SIDES[s.side]
            target = x[:, axis].max() if sign > 0 else x[:, axis].min()
            keep &= np.abs(x[:, axis] - target) <= tol
        if s.box is not None:
            lo, hi = np.array(s.box.min), np.array(s.box.max)
            keep &= np.all((x >= lo - tol) & (x <= hi + tol), axis=1)
        if s.plane is not None:
            normal = np.array(s.plane.normal, dtype=float)
            normal = unit(normal)
            keep &= np.abs((x - np.array(s.plane.point)) @ normal) <= tol
        if s.sphere is not None:
            dist = np.linalg.norm(x - np.array(s.sphere.center), axis=1)
            keep &= np.abs(dist - s.sphere.radius) <= tol
        nodes = candidates[keep]
        if len(nodes) == 0:
            raise ModelError(f"sets.{name}", "the selection matches no node")
        if isinstance(s, SegmentSet):
            segs = _segments_with_nodes(model, nodes, s.part)
            if len(segs) == 0:
                raise ModelError(f"sets.{name}", "the selection matches no exterior face")
            model.segment_sets[name] = segs
        else:
            model.node_sets[name] = nodes


def _segments_with_nodes(model: Model, nodes: np.ndarray, part: str | None) -> np.ndarray:
    """Exterior faces (outward-oriented) of each part, or of `part`, whose nodes all lie in `nodes`."""
    chosen = np.zeros(model.n_nodes, dtype=bool)
    chosen[nodes] = True
    out = []
    for p in model.parts:
        if part is not None and p.name != part:
            continue
        faces, _ = selection.boundary_faces(model.connectivity[p.elements], model.dim)
        out.append(faces[np.all(chosen[faces], axis=1)])
    return np.vstack(out) if out else np.zeros((0, 2 if model.dim == 2 else 4), dtype=np.int64)


def _rigid_body(model: Model, part_index: int) -> RigidBody:
    s = model.parts[part_index].nodes
    nodes = np.arange(s.start, s.stop)
    m = model.mass[nodes]
    total = m.sum()
    center = (m[:, None] * model.coordinates[nodes]).sum(axis=0) / total
    r = model.coordinates[nodes] - center
    if model.dim == 2:
        inertia = np.array((m * (r ** 2).sum(axis=1)).sum())
    else:
        inertia = (m[:, None, None] * ((r ** 2).sum(axis=1)[:, None, None] * np.eye(3)
                                        - r[:, :, None] * r[:, None, :])).sum(axis=0)
    return RigidBody(part_index, nodes, float(total), center, inertia)
