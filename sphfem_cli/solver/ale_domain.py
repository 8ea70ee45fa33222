"""The ALE part of a model as a domain of the explicit loop (solver.domain), stepped with the loop's dt.

Imported only when a deck has an ALE part, so other runs compile no ALE kernel.
"""
from __future__ import annotations

import numpy as np

from ..ale import options as ale_options
from ..ale.system import AleSystem
from ..model import sets as selection
from ..model.build import VOID, Model
from ..model.options import AleDomainOptions
from ..model.sensors import probe_sensor_points, sensor_mean
from .domain import Domain, Energies, stable_or_nan
from .solid_domain import TOPOLOGY

_AXES = {"left": 0, "right": 0, "bottom": 1, "top": 1, "front": 2, "back": 2}  # each side's normal axis


class AleDomain(Domain):
    """One `AleSystem` holding the deck's ALE part, plus what the loop and the output ask of it."""

    kind = "ale"
    label = "ALE"
    non_finite_remedy = "lower the section's timestep_scale, check the equations of state and units"

    def __init__(self, model: Model, options: AleDomainOptions):
        mesh = model.ale
        self.model = model
        self.name = options.part
        self.parts = (mesh.part,)
        self.names = [model.material_names[m] for m in mesh.materials]
        rows = [None if model.material_type[m] == VOID else (int(model.material_type[m]), model.material_param[m])
                for m in mesh.materials]
        o = options
        motion = ale_options.MeshMotion(
            mesh_motion=o.mesh_motion, smoothing=o.smoothing, smoothing_weight=o.smoothing_weight,
            smoothing_iterations=o.smoothing_iterations, smoothing_boundary=o.smoothing_boundary,
            eulerian_pull=o.eulerian_pull, line_axis=o.line_axis)
        numerics = ale_options.AleOptions(
            advection=o.advection, interface=o.interface, closure=o.closure, advect_every=o.advect_every, q1=o.q1,
            q2=o.q2, hourglass=o.hourglass, timestep_scale=o.timestep_scale, pressure_cutoff=o.pressure_cutoff,
            motion=motion)
        self.system = AleSystem(mesh.nodes, mesh.elements, rows, mesh.fractions, mesh.density, pressure=mesh.pressure,
                                velocity=mesh.velocity, options=numerics, axisymmetric=model.axisymmetric)
        if o.burn:
            self.system.set_burn([j for j, _ in o.burn], [d for _, d in o.burn], list(o.detonations))
        for g in o.gravity:
            self.system.gravity += g
        for bc in o.sides:
            for side in bc.sides:
                nodes = selection.nodes_on_side(mesh.nodes, side)
                if bc.condition == "slip":
                    self.system.set_slip(nodes, np.eye(model.dim)[_AXES[side]])
                elif bc.condition == "fixed":
                    self.system.set_fixed(nodes)
                elif bc.condition == "inflow":
                    self.system.set_inflow(nodes, bc.material, bc.velocity[:model.dim], density=bc.density,
                                           energy=bc.energy, pressure=bc.pressure)
                elif bc.condition == "non_reflecting":
                    self.system.set_non_reflecting(nodes, bc.source)
                else:
                    self.system.set_transmit(nodes)

    # ------------------------------------------------------------------------------ loop

    def stable_dt(self, scale: float | None = None) -> float:
        """The mesh's stable step at the ALE section's timestep_scale (`scale`, control.timestep_scale, is not used)."""
        ale = self.system
        return stable_or_nan(lambda: ale.stable_dt(ale.options.timestep_scale), ale.x, ale.velocity)

    def clear_coupling(self) -> None:
        self.system.f_couple[:] = 0.0
        self.system.pressed[:] = False

    def advance(self, t: float, dt: float, dt_avg: float) -> None:
        """One step of the loop's dt; coupling forces (f_couple) get the impulse weight dt_avg."""
        self.system.step(dt, dt_avg)

    def limiter_description(self) -> str:
        e = int(np.argmin(self.system.dt_elem))
        return f"element {e} of ALE part '{self.name}'"

    def state_arrays(self) -> dict[str, np.ndarray]:
        """The evolving node and element arrays the output reads, by name."""
        ale = self.system
        return {"ALE node coordinates": ale.x, "ALE node velocity": ale.velocity, "ALE material volume": ale.vol_m,
                "ALE material mass": ale.mass_m, "ALE material energy": ale.ener_m, "ALE material pressure": ale.pres_m}

    def energies(self) -> Energies:
        """Kinetic and internal energy of the fluid; the work done on it by gravity and coupling forces
        so far (the loop's energy table takes the couplings' work back out and books it as contact energy)."""
        totals = self.system.totals()
        return Energies(totals["kinetic"], totals["internal"], 0.0,
                        self.system.gravity_work + self.system.coupling_work)

    def part_energies(self, part: int) -> tuple[float, float]:
        totals = self.system.totals()
        return totals["kinetic"], totals["internal"]

    # ---------------------------------------------------------------------------- output

    def grid(self, part: int) -> tuple[str, np.ndarray, int]:
        mesh = self.model.ale
        return TOPOLOGY[mesh.elements.shape[1]], mesh.elements, len(mesh.nodes)

    def history_tables(self) -> list[tuple[str, list[str]]]:
        """histories/ale_materials.csv: mass, internal and kinetic energy per material."""
        return [("ale_materials", self.material_columns())]

    def history_rows(self) -> list[list[float]]:
        return [self.material_row()]

    def owns_probe(self, probe) -> bool:
        """Probes on the ALE part, and those naming no part (when no SPH domain takes them first)."""
        return probe.part is None or probe.part == self.name

    def material_columns(self) -> list[str]:
        """Columns of histories/ale_materials.csv after time: mass, internal and kinetic energy per material."""
        return [f"{k}_{name}" for k in ("mass", "internal", "kinetic") for name in self.names]

    def material_row(self) -> list[float]:
        """Per-material mass, internal and kinetic energy (AleSystem.material_totals), in material_columns order."""
        mass, internal, kinetic = self.system.material_totals()
        return [*mass, *internal, *kinetic]

    def field_data(self, wanted) -> dict[int, tuple[np.ndarray, dict, dict]]:
        """Node coordinates, point fields and cell fields (mixture and per-material); written whatever
        the deck's output.fields selects."""
        ale = self.system
        fractions, density, pressure = ale.fractions(), ale.density(), ale.pressure()
        cell = {"density": ale.mixture_density(), "pressure": ale.pressure(mixture=True)}
        for j, name in enumerate(self.names):
            cell[f"fraction_{name}"] = fractions[:, j]
            if self.model.material_type[self.model.ale.materials[j]] != VOID:
                cell[f"density_{name}"] = density[:, j]
                cell[f"pressure_{name}"] = pressure[:, j]
        return {self.parts[0]: (ale.x, {"velocity": ale.velocity}, cell)}

    def probe(self, probe) -> float:
        """A deck probe in the ALE part.

        pressure: the mixture pressure of the element whose centroid is nearest `probe.point`; with a
        sensor, the weighted mean over the sensor's sample points of the nearest element's pressure.
        front: the furthest reach of `probe.material` along `probe.axis`, each element's material
        volume packed against its face on the -axis side: max over the elements holding a fraction
        phi > 1e-3 of x_min + phi (x_max - x_min) (a full element reaches its far face).
        """
        ale = self.system
        if probe.type == "front":
            axis = "xyz".index(probe.axis)
            phi = ale.fractions()[:, self.names.index(probe.material)]
            held = np.flatnonzero(phi > 1e-3)
            if held.size == 0:
                return float("nan")
            coord = ale.x[ale.conn[held], axis]
            lo, hi = coord.min(axis=1), coord.max(axis=1)
            return float(np.max(lo + phi[held] * (hi - lo)))
        centroids, pressure = ale.centroids(), ale.pressure(mixture=True)
        if probe.sensor is None:
            k = int(np.argmin(np.sum((centroids - np.array(probe.point)) ** 2, axis=1)))
            return float(pressure[k])
        points, weights = probe_sensor_points(probe)
        k = np.argmin(np.sum((centroids[None, :, :] - points[:, None, :]) ** 2, axis=2), axis=1)
        return sensor_mean(pressure[k], weights)

