"""The numerical options of an ALE fluid, resolved once (from a deck section or by a caller).

Field names and values are those of the deck's ``ale_multi_material`` section
(docs/deck-reference.md), so that one concept has one name from the deck to the kernel; the few
that no deck sets (``relax_alpha``, ``relax_beta``, ``ke_fix``, ``phi_eps``, ``mass_floor``) say
so in their comments. Validation here raises ValueError (the deck schema already bounds what a
deck can give). Imports nothing that compiles: a model can build these without loading a kernel.
"""
from __future__ import annotations

from dataclasses import dataclass, field

ADVECTION_ORDER = {"donor_cell": 1, "van_leer": 2}
INTERFACES = ("slic", "donor")
CLOSURES = ("relax", "equal_strain")
MESH_MOTIONS = ("eulerian", "lagrangian", "smoothed")
SMOOTHINGS = ("average", "equipotential", "straight_lines")
SMOOTHING_BOUNDARIES = ("fixed", "sliding")
AXES = "xyz"


def _one_of(name: str, value, allowed) -> None:
    if value not in allowed:
        raise ValueError(f"{name} must be one of {', '.join(repr(a) for a in allowed)}, got {value!r}")


@dataclass(frozen=True)
class MeshMotion:
    """Where the remap puts the mesh (``ale.motion.MeshMover``).

    mesh_motion: "eulerian" (back to its start), "lagrangian" (no remap: the mesh moves with the
    material) or "smoothed" (the Lagrangian mesh relaxed: ``smoothing_iterations`` passes moving
    interior nodes ``smoothing_weight`` of the way to their target, ``smoothing`` "average" (mean
    of their edge neighbours), "equipotential" (Winslow) or "straight_lines" (along the mesh lines
    along ``line_axis``), then ``eulerian_pull`` of the way back to their start;
    ``smoothing_boundary`` "fixed" (boundary nodes Eulerian) or "sliding" (along straight sides; in
    3D in flat faces and along straight edges; corners fixed)).
    """

    mesh_motion: str = "eulerian"
    smoothing: str = "average"
    smoothing_weight: float = 0.5
    smoothing_iterations: int = 1
    smoothing_boundary: str = "fixed"
    eulerian_pull: float = 0.2
    line_axis: str = "y"

    def __post_init__(self):
        _one_of("mesh_motion", self.mesh_motion, MESH_MOTIONS)
        _one_of("smoothing", self.smoothing, SMOOTHINGS)
        _one_of("smoothing_boundary", self.smoothing_boundary, SMOOTHING_BOUNDARIES)
        _one_of("line_axis", self.line_axis, tuple(AXES))


@dataclass(frozen=True)
class AleOptions:
    """Numerics of ``AleSystem``.

    advection "donor_cell" (first order) or "van_leer" (MUSCL) mass, energy and momentum fluxes;
    interface "slic" (directional SLIC, sharp) or "donor" material-volume fluxes; closure "relax"
    (pressure relaxation, with relax_alpha the fraction of the pressure difference removed per
    step and relax_beta the largest relative volume loss of one material per step) or
    "equal_strain" for mixed elements; advect_every: remap every N steps; q1, q2 the quadratic
    and linear bulk-viscosity coefficients, hourglass the viscous hourglass coefficient;
    timestep_scale the fraction of the element step l / (c + |v|) a step may take (the deck's
    ``timestep_scale``, formerly ``courant``); pressure_cutoff the lowest material pressure
    (cavitation, LS-DYNA *MAT_NULL PC; None for none); ke_fix: the kinetic energy lost by the
    momentum remap returned to the internal energy (DeBar; total energy conserved); phi_eps: a
    material below this volume fraction counts as absent; mass_floor: nodes whose mass is at or
    below this fraction of their full mass (their elements' reference volumes filled at the
    largest reference density) are held at zero velocity, their momentum booked with the wall
    impulse (1e-10: the gas front expanding into void, tests/verification/test_ale_void.py, moves
    within 0.1 cell of 1e-12's; 1e-8 holds it back 3 cells).
    """

    advection: str = "van_leer"
    interface: str = "slic"
    closure: str = "relax"
    relax_alpha: float = 0.5  # no deck key
    relax_beta: float = 0.5  # no deck key
    advect_every: int = 1
    q1: float = 1.5
    q2: float = 0.06
    hourglass: float = 0.1
    timestep_scale: float = 0.5
    pressure_cutoff: float | None = None
    ke_fix: bool = True  # no deck key
    phi_eps: float = 1e-9  # no deck key
    mass_floor: float = 1e-10  # no deck key
    motion: MeshMotion = field(default_factory=MeshMotion)

    def __post_init__(self):
        _one_of("advection", self.advection, tuple(ADVECTION_ORDER))
        _one_of("interface", self.interface, INTERFACES)
        _one_of("closure", self.closure, CLOSURES)
        if int(self.advect_every) < 1:
            raise ValueError(f"advect_every must be at least 1, got {self.advect_every}")

    @property
    def order(self) -> int:
        """Advection order: 1 donor cell, 2 van Leer."""
        return ADVECTION_ORDER[self.advection]
