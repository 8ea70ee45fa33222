"""SPH fluid: smoothed particle hydrodynamics on particles (paper section 3).

numba kernels: ``kernel_functions`` (W, F, sigma), ``search`` (cell-linked list, point set,
neighbour lists), ``walls`` (ghosts, dummy-wall pressure, ghost friction), ``rates`` (viscous
stress, pair sums, interpolation), ``integration`` (leapfrog, bounds, stable step), ``eos``
(particle state from the EOS); ``slots`` names every slot of their settings, grid and point
arrays. ``system`` the ``SphSystem`` that drives them; ``lattice`` particles from geometry;
``scenes`` ready-made cases; ``reference`` short NumPy versions of the hot kernels for the tests.
Theory: docs/theory/sph.md.
"""
from .system import SphOptions, SphSystem, WallParticles, material_table
from .walls import Wall, box_walls

__all__ = ["SphOptions", "SphSystem", "Wall", "WallParticles", "box_walls", "material_table"]
