"""SPH fluid: smoothed particle hydrodynamics on particles (paper section 3).

numba kernels: ``kernel_functions`` (W, F, sigma), ``search`` (cell-linked list, point set,
neighbour lists), ``walls`` (the ``Wall`` spec, ghosts, dummy-wall pressure, ghost friction),
``open_sides`` (non-reflecting open sides), ``rates`` (viscous stress, pair sums, interpolation),
``expansion`` and ``diffusion`` (renormalised continuity of explosive products; the delta-plus
density diffusion), ``axisymmetric`` (r-z rates), ``integration`` (leapfrog, bounds, stable step),
``eos`` (particle state from the EOS); ``slots`` names every slot of their settings, grid and point
arrays. ``options`` the settings as plain data; ``system`` the ``SphSystem`` that drives the kernels; ``lattice`` particles from geometry;
``scenes`` ready-made cases; ``reference`` short NumPy versions of the hot kernels for the tests.
Theory: docs/theory/sph.md.
"""
from .options import SphOptions, WallParticles, material_table
from .system import SphSystem
from .walls import Wall, box_walls

__all__ = ["SphOptions", "SphSystem", "Wall", "WallParticles", "box_walls", "material_table"]
