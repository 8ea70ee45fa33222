"""Constitutive models and equations of state.

``kernels`` holds the numba functions (``update_stress``, ``sound_speed``, ``eos_pressure``,
``eos_sound_speed``; loaded on first use of one of these names, so that importing the package loads no
numba); ``ids`` declares the type-id constants; ``slots`` names every slot of the parameter, EOS
and history rows; ``tables.pack_material`` turns a deck material (and its equation of state) into
``(type id, parameter row)``. Theory: docs/theory/materials.md.
"""
from __future__ import annotations

from .ids import (
    EOS_GRUNEISEN,
    EOS_IDEAL_GAS,
    EOS_JWL,
    EOS_LINEAR_POLYNOMIAL,
    EOS_NONE,
    EOS_STIFFENED_GAS,
    EOS_TAIT,
    ELASTIC,
    ELASTIC_PLASTIC,
    FLUID,
    JOHNSON_COOK,
    RIGID,
)
from .slots import EOS_OFFSET, NHIST, NPARAM, P_EOS_TYPE

__all__ = [
    "ELASTIC", "ELASTIC_PLASTIC", "JOHNSON_COOK", "RIGID", "FLUID",
    "EOS_NONE", "EOS_LINEAR_POLYNOMIAL", "EOS_GRUNEISEN", "EOS_TAIT", "EOS_IDEAL_GAS",
    "EOS_STIFFENED_GAS", "EOS_JWL", "NPARAM", "NHIST", "P_EOS_TYPE", "EOS_OFFSET",
    "update_stress", "sound_speed", "eos_pressure", "eos_sound_speed",
]


_KERNEL_NAMES = ("update_stress", "sound_speed", "eos_pressure", "eos_sound_speed")


def __getattr__(name: str):
    """The kernel functions, from ``materials.kernels`` at first use (PEP 562)."""
    if name in _KERNEL_NAMES:
        from . import kernels

        return getattr(kernels, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
