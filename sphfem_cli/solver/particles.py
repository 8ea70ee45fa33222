"""The SPH particles of a model inside the explicit loop: built from the deck, stepped with the loop's dt.

Imported only when a deck has SPH parts, so a solid-only run compiles no SPH kernel.
"""
from __future__ import annotations

import numpy as np

from ..deck.schema import DummyWallBoundary, Gravity, InitialVelocity, WallBoundary
from ..model.build import Model
from ..sph import lattice
from ..sph.system import ParticleSystem, SPHOptions, WallParticles, box_walls

AXES = {"x": 0, "y": 1, "z": 2}


def dummy_walls(deck, default_spacing: float) -> WallParticles | None:
    """The deck's `dummy_wall` boundaries as one set of wall particles (material: the first SPH fluid)."""
    walls = [bc for bc in deck.boundaries if isinstance(bc, DummyWallBoundary)]
    if not walls:
        return None
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
    return WallParticles(np.vstack(points), dx)


class Particles:
    """One `ParticleSystem` holding every SPH part, plus what the loop and the output ask of it."""

    def __init__(self, model: Model):
        self.model = model
        ps_model = model.particles
        deck = model.deck
        section = deck.sections[ps_model.section]
        walls = []
        for bc in deck.boundaries:
            if isinstance(bc, WallBoundary):
                walls += box_walls(bc.min, bc.max, bc.sides, bc.condition)
        gravity = np.zeros(model.dim)
        sph_names = {p.name for p in model.parts if p.kind == "sph"}
        for load in deck.loads:
            if isinstance(load, Gravity) and (load.parts is None or sph_names & set(load.parts)):
                gravity += np.array(load.acceleration)
        options = SPHOptions(
            kernel=section.kernel, smoothing_ratio=section.smoothing_ratio,
            alpha=section.artificial_viscosity.alpha, beta=section.artificial_viscosity.beta,
            eps=section.artificial_viscosity.epsilon, delta=section.density_diffusion, xsph=section.xsph,
            delta_hydrostatic=section.diffusion_hydrostatic, ghost_hydrostatic=section.ghost_hydrostatic,
            pressure_min=-np.inf if section.pressure_cutoff is None else section.pressure_cutoff,
            walls=tuple(walls), gravity=gravity,
            domain=None if section.domain is None else (section.domain.min, section.domain.max),
        )
        velocity = np.zeros_like(ps_model.x)
        for ic in deck.initial:
            if isinstance(ic, InitialVelocity) and ic.part in sph_names:
                velocity[model.parts[model.part_index(ic.part)].particles] = ic.velocity
        self.system = ParticleSystem(
            ps_model.x, velocity, ps_model.mass, ps_model.density, ps_model.material,
            (ps_model.material_type, ps_model.material_param), options,
            wall_particles=dummy_walls(deck, float(ps_model.spacing.min())),
        )
        from ..materials.slots import P_DETONATION_VELOCITY

        if np.any(ps_model.material_param[:, P_DETONATION_VELOCITY] > 0.0):  # a high_explosive
            self.system.set_burn([(det.point, det.time) for det in deck.detonations])
        self.potential0 = self.system.energies()["potential"]

    # ------------------------------------------------------------------------------ loop

    def stable_dt(self, scale: float) -> float:
        """Rates at the current state, then the particles' stable step."""
        self.system.compute_rates()
        return self.system.stable_dt(scale)

    def step(self, dt: float) -> None:
        self.system.step(dt)

    def state_arrays(self) -> dict[str, np.ndarray]:
        """The evolving per-particle arrays the output reads, by name (rows are particle slots)."""
        ps = self.system
        return {"SPH coordinates": ps.x, "SPH velocity": ps.v, "SPH density": ps.rho,
                "SPH internal energy": ps.e, "SPH pressure": ps.p}

    def energies(self) -> tuple[float, float, float, float]:
        """(kinetic, internal, work done on the particles by gravity, f_ext and dummy walls, energy carried off
        by lost particles)."""
        e = self.system.energies()
        work = self.potential0 - e["potential"] + e["external_work"] - e["wall"]
        return e["kinetic"], e["internal"], work, e["lost"]

    def part_sums(self, part_index: int) -> tuple[float, float]:
        """Kinetic and internal energy of one SPH part's active particles."""
        ps = self.system
        sel = ps.active & (self.model.particles.part[ps.ids] == part_index)
        ke = 0.5 * float(np.sum(ps.m[sel] * np.sum(ps.v[sel] ** 2, axis=1)))
        return ke, float(np.sum(ps.m[sel] * ps.e[sel]))

    # ---------------------------------------------------------------------------- output

    def original_order(self) -> np.ndarray:
        """Slots of the particles in their original (deck) order; the system reorders its arrays."""
        return np.argsort(self.system.ids)

    def part_fields(self, part_index: int, order: np.ndarray) -> tuple[np.ndarray, dict]:
        """Coordinates and point fields of one SPH part, in the part's original particle order."""
        ps = self.system
        slots = order[self.model.parts[part_index].particles]
        fields = {
            "velocity": ps.v[slots], "density": ps.rho[slots], "pressure": ps.p[slots],
            "mass": ps.m[slots], "smoothing_length": ps.h[slots], "active": ps.active[slots].astype(np.float64),
        }
        return ps.x[slots], fields

    def probe(self, probe) -> float:
        """The value of one deck probe (output.probes) at the current state."""
        ps = self.system
        axis = AXES[probe.axis]
        if probe.type == "pressure":
            return float(ps.interpolate(np.array([probe.point]), "pressure")[0])
        if probe.type == "surface_height":
            up = 1 if axis != 1 else (2 if self.model.dim == 3 else 0)
            return ps.surface_height(probe.gauge, axis=axis, up=up)
        sel = ps.active.copy()
        if probe.part is not None:
            sel &= self.model.particles.part[ps.ids] == self.model.part_index(probe.part)
        return float(ps.x[sel, axis].max()) if sel.any() else float("nan")
