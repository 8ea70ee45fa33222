"""Multi-material ALE / VOF fluid on quad4 meshes: Lagrangian phase plus remap (see ``system``)."""
from __future__ import annotations

from .system import AleSystem, build_topology, energy_from_pressure, fill_fractions

__all__ = ["AleSystem", "build_topology", "energy_from_pressure", "fill_fractions"]
