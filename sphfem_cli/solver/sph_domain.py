"""The SPH particles of a model as a domain of the explicit loop (solver.domain), stepped with the loop's dt.

Imported only when a deck has SPH parts, so a solid-only run compiles no SPH kernel.
"""
from __future__ import annotations

import numpy as np

from ..model.build import Model
from ..model.sensors import probe_sensor_points, sensor_mean
from ..model.options import ControlOptions, SphDomainOptions
from ..sph.options import SphOptions, WallParticles
from ..sph.system import SphSystem
from ..sph.walls import box_walls
from .domain import Domain, Energies, stable_or_nan
from .guards import RunStopped

AXES = {"x": 0, "y": 1, "z": 2}


class SphDomain(Domain):
    """One `SphSystem` holding every SPH part, plus what the loop and the output ask of it."""

    kind = "sph"
    label = "SPH"
    non_finite_remedy = "lower timestep_scale, check the equation of state and units"

    def __init__(self, model: Model, options: SphDomainOptions, control: ControlOptions):
        self.model = model
        self.max_lost_fraction = control.max_lost_fraction
        self.parts = tuple(i for i, p in enumerate(model.parts) if p.kind == "sph")
        ps_model = model.particles
        walls = []
        for w in options.walls:
            walls += box_walls(w.min, w.max, w.sides, w.condition, w.source)
        sph_options = SphOptions(
            kernel=options.kernel, smoothing_ratio=options.smoothing_ratio,
            alpha=options.alpha, beta=options.beta, eps=options.epsilon, delta=options.density_diffusion,
            switch_alpha_max=options.switch_alpha_max,
            density_diffusion_form=options.density_diffusion_form, xsph=options.xsph, delta_hydrostatic=options.diffusion_hydrostatic, continuity=options.continuity,
            ghost_hydrostatic=options.ghost_hydrostatic,
            pressure_cutoff=-np.inf if options.pressure_cutoff is None else options.pressure_cutoff,
            walls=tuple(walls), gravity=options.gravity.copy(), domain=options.domain,
            axisymmetric=model.axisymmetric,  # ring masses (model.build), the axis a ghost line
        )
        if options.switch_decay is not None:
            sph_options.switch_decay = options.switch_decay
        velocity = np.zeros_like(ps_model.x)
        for part, v in options.initial_velocity:
            velocity[model.parts[model.part_index(part)].particles] = v
        walls = None if options.wall_points is None else WallParticles(options.wall_points, options.wall_spacing)
        self.system = SphSystem(
            ps_model.x, velocity, ps_model.mass, ps_model.density, ps_model.material,
            (ps_model.material_type, ps_model.material_param), sph_options, wall_particles=walls,
        )
        from ..materials.tables import P_DETONATION_VELOCITY

        if np.any(ps_model.material_param[:, P_DETONATION_VELOCITY] > 0.0):  # a high_explosive
            self.system.set_burn(list(options.detonations))
        self.potential0 = self.system.energies()["potential"]

    # ------------------------------------------------------------------------------ loop

    def stable_dt(self, scale: float) -> float:
        """Rates at the current state, then the particles' stable step (NaN on a non-finite state)."""
        ps = self.system
        return stable_or_nan(lambda: self._rates_and_dt(scale), ps.x, ps.v)

    def _rates_and_dt(self, scale: float) -> float:
        self.system.compute_rates()
        return self.system.stable_dt(scale)

    def check_step(self, st) -> None:
        """Stop when more than control.max_lost_fraction of the particles have left the domain."""
        limit = self.max_lost_fraction
        ps = self.system
        if limit is None or ps.lost <= limit * ps.n:
            return
        raise RunStopped(
            f"{ps.lost} of {ps.n} SPH particles ({ps.lost / ps.n:.1%}) have left the domain by t = {st.time:.6e}, "
            f"step {st.step}, more than max_lost_fraction {limit:g} (remedies: enlarge the section's domain or add "
            "walls, lower timestep_scale if particles were ejected by a blow-up, raise max_lost_fraction)",
            "lost_particles", {"lost": ps.lost, "particles": ps.n, "fraction": ps.lost / ps.n, "limit": limit},
        )

    def clear_coupling(self) -> None:
        self.system.f_ext[:] = 0.0

    def advance(self, t: float, dt: float, dt_avg: float) -> None:
        """Kick-drift-kick leapfrog with the rates of stable_dt; the kick weights f_ext by dt_avg itself."""
        self.system.step(dt)

    def limiter_description(self) -> str:
        ps, m = self.system, self.model
        with np.errstate(divide="ignore", invalid="ignore"):
            speed = ps.c + np.linalg.norm(ps.v, axis=1)
            cfl = np.where(ps.active, float(ps.options.cfl) * ps.h / speed, np.inf)
            # r-z: the hoop terms' condition r / (c + |v|) (sph.axisymmetric.axis_time_step) may be the smaller
            axis = np.where(ps.active, ps.x[:, 0] / speed, np.inf) if ps.axisymmetric else np.full_like(cfl, np.inf)
        k = int(np.argmin(np.minimum(cfl, axis)))
        i = int(ps.ids[k])
        which = " (its distance to the axis)" if axis[k] < cfl[k] else ""
        return f"SPH particle {i} of part '{m.parts[int(m.particles.part[i])].name}'{which}"

    def state_arrays(self) -> dict[str, np.ndarray]:
        """The evolving per-particle arrays the output reads, by name (rows are particle slots)."""
        ps = self.system
        return {"SPH coordinates": ps.x, "SPH velocity": ps.v, "SPH density": ps.rho,
                "SPH internal energy": ps.e, "SPH pressure": ps.p}

    def energies(self) -> Energies:
        """Kinetic, internal, the work done on the particles by gravity, f_ext, dummy walls and the
        non-reflecting sides (minus what they radiated), and the energy carried off by lost particles."""
        e = self.system.energies()
        work = self.potential0 - e["potential"] + e["external_work"] - e["wall"] - e["open"]
        return Energies(e["kinetic"], e["internal"], 0.0, work, e["lost"])

    def part_energies(self, part: int) -> tuple[float, float]:
        """Kinetic and internal energy of one SPH part's active particles."""
        ps = self.system
        sel = ps.active & (self.model.particles.part[ps.ids] == part)
        ke = 0.5 * float(np.sum(ps.m[sel] * np.sum(ps.v[sel] ** 2, axis=1)))
        return ke, float(np.sum(ps.m[sel] * ps.e[sel]))

    # ---------------------------------------------------------------------------- output

    def grid(self, part: int) -> tuple[str, None, int]:
        s = self.model.parts[part].particles
        return "Polyvertex", None, s.stop - s.start

    def original_order(self) -> np.ndarray:
        """Slots of the particles in their original (deck) order; the system reorders its arrays."""
        return np.argsort(self.system.ids)

    def field_data(self, wanted) -> dict[int, tuple[np.ndarray, dict, dict]]:
        """Coordinates and point fields of each SPH part, in the part's original particle order."""
        ps = self.system
        order = self.original_order()
        out = {}
        for i in self.parts:
            slots = order[self.model.parts[i].particles]
            point = {
                "velocity": ps.v[slots], "density": ps.rho[slots], "pressure": ps.p[slots],
                "mass": ps.m[slots], "smoothing_length": ps.h[slots], "active": ps.active[slots].astype(np.float64),
            }
            if ps.shock_switch:  # the switch's alpha_i (sph/switch.py), written whenever a deck uses it
                point["viscosity_alpha"] = ps.alpha[slots]
            out[i] = (ps.x[slots], {k: val for k, val in point.items() if wanted(k)}, {})
        return out

    def owns_probe(self, probe) -> bool:
        """Probes on an SPH part, and those naming no part (SPH measures them when the deck has SPH)."""
        return probe.part is None or self.model.parts[self.model.part_index(probe.part)].kind == "sph"

    def probe(self, probe) -> float:
        """The value of one deck probe (output.probes) at the current state; a pressure probe with a
        sensor the mean over its face (model/sensors.py) of the interpolated pressure."""
        ps = self.system
        axis = AXES[probe.axis]
        if probe.type == "pressure":
            if probe.sensor is None:
                return float(ps.interpolate(np.array([probe.point]), "pressure")[0])
            points, weights = probe_sensor_points(probe)
            return sensor_mean(ps.interpolate(points, "pressure"), weights)
        if probe.type == "surface_height":
            up = 1 if axis != 1 else (2 if self.model.dim == 3 else 0)
            return ps.surface_height(probe.gauge, axis=axis, up=up)
        sel = ps.active.copy()
        if probe.part is not None:
            sel &= self.model.particles.part[ps.ids] == self.model.part_index(probe.part)
        return float(ps.x[sel, axis].max()) if sel.any() else float("nan")
