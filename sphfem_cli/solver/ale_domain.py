"""The ALE part of a model inside the explicit loop: built from the deck, stepped with the loop's dt.

Imported only when a deck has an ALE part, so other runs compile no ALE kernel.
"""
from __future__ import annotations

import numpy as np

from ..ale.system import AleSystem
from ..deck.schema.model import AleBoundary, Gravity
from ..model import sets as selection
from ..model.build import VOID, Model

_NORMALS = {"left": (1.0, 0.0), "right": (1.0, 0.0), "bottom": (0.0, 1.0), "top": (0.0, 1.0)}


class AleDomain:
    """One `AleSystem` holding the deck's ALE part, plus what the loop and the output ask of it."""

    def __init__(self, model: Model):
        mesh = model.ale
        deck = model.deck
        part = model.parts[mesh.part]
        section = deck.sections[deck.parts[part.name].section]
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
            mesh_motion="eulerian" if section.mesh_motion == "eulerian" else "smooth",
            pressure_cutoff=section.pressure_cutoff,
        )
        burn = [(j, deck.materials[n].detonation_velocity) for j, n in enumerate(self.names)
                if deck.materials[n].type == "high_explosive"]
        if burn:
            self.system.set_burn([j for j, _ in burn], [d for _, d in burn],
                                 [(det.point, det.time) for det in deck.detonations])
        for load in deck.loads:
            if isinstance(load, Gravity) and (load.parts is None or part.name in load.parts):
                self.system.gravity += np.array(load.acceleration[:2], dtype=float)
        for bc in deck.boundaries:
            if not isinstance(bc, AleBoundary):
                continue
            for side in bc.sides:
                nodes = selection.nodes_on_side(mesh.nodes, side)
                if bc.condition == "slip":
                    self.system.set_slip(nodes, _NORMALS[side])
                elif bc.condition == "fixed":
                    self.system.set_fixed(nodes)
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

    def energies(self) -> tuple[float, float]:
        """(kinetic, internal) of the ALE fluid."""
        totals = self.system.totals()
        return totals["kinetic"], totals["internal"]

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
        """A pressure probe: the mixture pressure of the element whose centroid is nearest `probe.point`."""
        ale = self.system
        k = int(np.argmin(np.sum((ale.centroids() - np.array(probe.point)) ** 2, axis=1)))
        return float(ale.pressure(mixture=True)[k])
