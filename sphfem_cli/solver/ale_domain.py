"""The ALE part of a model inside the explicit loop: built from the deck, stepped with the loop's dt.

Imported only when a deck has an ALE part, so other runs compile no ALE kernel.
"""
from __future__ import annotations

import numpy as np

from ..ale.system import AleSystem
from ..deck.schema import AleBoundary, Gravity
from ..materials.slots import P_RHO0
from ..model import sets as selection
from ..model.build import VOID, Model

_AXES = {"left": 0, "right": 0, "bottom": 1, "top": 1, "front": 2, "back": 2}  # each side's normal axis


class AleDomain:
    """One `AleSystem` holding the deck's ALE part, plus what the loop and the output ask of it."""

    def __init__(self, model: Model):
        mesh = model.ale
        deck = model.deck
        part = model.parts[mesh.part]
        section = deck.sections[deck.parts[part.name].section]
        _add_inflow_materials(model, deck, part.name)
        self.model = model
        self.name = part.name
        self.names = [model.material_names[m] for m in mesh.materials]
        rows = [None if model.material_type[m] == VOID else (int(model.material_type[m]), model.material_param[m])
                for m in mesh.materials]
        self.section = section
        self.system = AleSystem(
            mesh.nodes, mesh.elements, rows, mesh.fractions, mesh.density, pressure=mesh.pressure,
            velocity=mesh.velocity, q1=section.bulk_viscosity.q1, q2=section.bulk_viscosity.q2,
            hourglass=section.hourglass, order=1 if section.advection == "donor_cell" else 2,
            interface=section.interface, closure=section.closure, advect_every=section.advect_every,
            mesh_motion={"smoothed": "smooth"}.get(section.mesh_motion, section.mesh_motion),
            smoothing=section.smoothing, smooth_weight=section.smoothing_weight,
            smooth_iterations=section.smoothing_iterations, eulerian_pull=section.eulerian_pull,
            smooth_boundary=section.smoothing_boundary, pressure_cutoff=section.pressure_cutoff,
            line_axis="xyz".index(section.line_axis),
        )
        burn = [(j, deck.materials[n].detonation_velocity) for j, n in enumerate(self.names)
                if deck.materials[n].type == "high_explosive"]
        if burn:
            self.system.set_burn([j for j, _ in burn], [d for _, d in burn],
                                 [(det.point, det.time) for det in deck.detonations])
        for load in deck.loads:
            if isinstance(load, Gravity) and (load.parts is None or part.name in load.parts):
                self.system.gravity += np.array(load.acceleration[:model.dim], dtype=float)
        for bc in deck.boundaries:
            if not isinstance(bc, AleBoundary):
                continue
            for side in bc.sides:
                nodes = selection.nodes_on_side(mesh.nodes, side)
                if bc.condition == "slip":
                    self.system.set_slip(nodes, np.eye(model.dim)[_AXES[side]])
                elif bc.condition == "fixed":
                    self.system.set_fixed(nodes)
                elif bc.condition == "inflow":
                    self.system.set_inflow(nodes, self.names.index(bc.material), bc.velocity[:model.dim], density=bc.density,
                                           energy=bc.energy, pressure=bc.pressure)
                else:
                    self.system.set_transmit(nodes)

    def stable_dt(self) -> float:
        return self.system.stable_dt(self.section.courant)

    def step(self, dt: float, dt_avg: float | None = None) -> None:
        """One step of the loop's dt; coupling forces (f_couple) get the impulse weight dt_avg."""
        self.system.step(dt, dt_avg)

    def external_work(self) -> float:
        """Work done on the fluid by gravity and coupling forces so far (the loop's energy table takes
        the couplings' work back out and books it as contact energy)."""
        return self.system.gravity_work + self.system.coupling_work

    def state_arrays(self) -> dict[str, np.ndarray]:
        """The evolving node and element arrays the output reads, by name."""
        ale = self.system
        return {"ALE node coordinates": ale.x, "ALE node velocity": ale.velocity, "ALE material volume": ale.vol_m,
                "ALE material mass": ale.mass_m, "ALE material energy": ale.ener_m, "ALE material pressure": ale.pres_m}

    def energies(self) -> tuple[float, float]:
        """(kinetic, internal) of the ALE fluid."""
        totals = self.system.totals()
        return totals["kinetic"], totals["internal"]

    def material_columns(self) -> list[str]:
        """Columns of histories/ale_materials.csv after time: mass, internal and kinetic energy per material."""
        return [f"{k}_{name}" for k in ("mass", "internal", "kinetic") for name in self.names]

    def material_row(self) -> list[float]:
        """Per-material mass, internal and kinetic energy (AleSystem.material_totals), in material_columns order."""
        mass, internal, kinetic = self.system.material_totals()
        return [*mass, *internal, *kinetic]

    def fields(self) -> tuple[np.ndarray, dict, dict]:
        """Node coordinates, point fields and cell fields (mixture and per-material) for the output."""
        ale = self.system
        fractions, density, pressure = ale.fractions(), ale.density(), ale.pressure()
        cell = {"density": ale.mixture_density(), "pressure": ale.pressure(mixture=True)}
        for j, name in enumerate(self.names):
            cell[f"fraction_{name}"] = fractions[:, j]
            if self.model.material_type[self.model.ale.materials[j]] != VOID:
                cell[f"density_{name}"] = density[:, j]
                cell[f"pressure_{name}"] = pressure[:, j]
        return ale.x, {"velocity": ale.velocity}, cell

    def probe(self, probe) -> float:
        """A deck probe in the ALE part.

        pressure: the mixture pressure of the element whose centroid is nearest `probe.point`.
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
        k = int(np.argmin(np.sum((ale.centroids() - np.array(probe.point)) ** 2, axis=1)))
        return float(ale.pressure(mixture=True)[k])


def _add_inflow_materials(model: Model, deck, part: str) -> None:
    """Materials entering through inflow sides that no fill holds join the ALE part with zero fraction."""
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
