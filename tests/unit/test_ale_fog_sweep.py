"""Fog nodes between the ALE remap's sweeps (``dual.node_velocities``): a node at or below its mass floor has no
velocity there, as after the sweeps (``remap_nodes.finish_nodes``) and in the Lagrangian update.

The mechanism it mends (docs/studies/underwater_explosion.md, "The plate scene in 3D"): after one sweep
a node of 1.7e-41 kg (floor 1.6e-13) had p / m = 9.4e26 m/s; the next sweep's dual flux carried 4.7e10 J of kinetic
energy out of it, which DeBar's fix handed as a +/- pair of internal energy to two nearly empty elements.
"""
from __future__ import annotations

import numpy as np

from sphfem_cli.ale import kernels as K


def test_a_fog_node_has_no_velocity_between_the_sweeps():
    """p / m above the floor; 0 at or below it (1.7e-41 kg, and 1.6e-13 kg under a floor of 1.63e-13), and without
    mass."""
    mnode = np.array([1.0e-3, 1.7e-41, 1.6e-13, 0.0])
    pnode = np.array([[2e-3, 0.0, -1e-3], [1.6e-14, 0.0, 0.0], [1.6e-12, 0.0, 0.0], [0.0, 0.0, 0.0]])
    m_floor = np.full(4, 1.63e-13)
    u = np.full((4, 3), np.nan)
    K.node_velocities(mnode, pnode, m_floor, u)
    np.testing.assert_array_equal(u[0], [2.0, 0.0, -1.0])
    assert not u[1:].any()

