"""Multi-material ALE / VOF fluid on quad4 and hex8 meshes: Lagrangian phase plus remap.

``system.AleSystem`` (the state and the step), ``options`` (its numerics), ``fill`` (initial
state), ``topology`` (mesh maps), ``motion`` (mesh motion), ``kernels`` (numba phases). The
kernels load with ``AleSystem``, not with this package, so a model can fill an ALE mesh or build
its options without loading them.
"""
from __future__ import annotations

from .fill import energy_from_pressure, fill_fractions
from .options import AleOptions, MeshMotion
from .topology import build_topology

__all__ = ["AleOptions", "AleSystem", "MeshMotion", "build_topology", "energy_from_pressure", "fill_fractions"]


def __getattr__(name: str):
    if name == "AleSystem":
        from .system import AleSystem
        return AleSystem
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
