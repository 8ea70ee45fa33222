"""The ring (r-z) geometry of a quad4: its exact ring volume (formulas: ``ale.axisymmetric``, whose ``ring_block``
also writes its gradient).

Inline helpers only (nothing here compiles on its own): the plane quad4 kernels call them under their
``ring`` flag (``energy.lagrange_energy``, ``remap.face_fluxes``) and ``axisymmetric`` in its ring
kernels; apart from ``axisymmetric`` so that ``lagrange`` and ``remap`` import them without a circle.
"""
from __future__ import annotations

import math

from numba import njit

PI_3 = math.pi / 3.0


@njit(cache=True, inline="always")
def ring_volume(r0, z0, r1, z1, r2, z2, r3, z3):
    """Signed ring volume 2 pi int r dA of the quad (0, 1, 2, 3) (counter-clockwise positive): (pi/3) S."""
    s = (r0 + r1) * (r0 * z1 - r1 * z0)
    s += (r1 + r2) * (r1 * z2 - r2 * z1)
    s += (r2 + r3) * (r2 * z3 - r3 * z2)
    s += (r3 + r0) * (r3 * z0 - r0 * z3)
    return PI_3 * s
