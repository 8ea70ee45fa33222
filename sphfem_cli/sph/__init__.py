"""SPH fluid: smoothed particle hydrodynamics on particles (paper section 3).

numba kernels: ``kernel_functions`` (W, F, sigma), ``search`` (cell-linked list, point set,
neighbour lists), ``walls`` (the ``Wall`` spec, ghosts, dummy-wall pressure, ghost friction),
``open_sides`` (non-reflecting open sides), ``rates`` (viscous stress, pair sums, interpolation),
``expansion`` and ``diffusion`` (renormalised continuity of explosive products; the delta-plus
density diffusion), ``axisymmetric`` (r-z rates), ``integration`` (leapfrog, bounds, stable step),
``eos`` (particle state from the EOS); ``slots`` names every slot of their settings, grid and point
arrays. ``system`` the ``SphSystem`` that drives them; ``lattice`` particles from geometry;
``scenes`` ready-made cases; ``reference`` short NumPy versions of the hot kernels for the tests.
Theory: docs/theory/sph.md.
"""
from .system import SphOptions, SphSystem, WallParticles, material_table
from .walls import Wall, box_walls

__all__ = ["SphOptions", "SphSystem", "Wall", "WallParticles", "box_walls", "material_table"]
