"""SPH fluid: smoothed particle hydrodynamics on particles (paper section 3).

``kernels`` numba kernels (smoothing kernels, cell search, ghosts, rates, integration);
``system`` the ``ParticleSystem`` that drives them; ``lattice`` particles from geometry;
``reference`` short NumPy versions of the hot kernels for the tests. Theory: docs/theory/sph.md.
"""
from .system import ParticleSystem, SPHOptions, Wall, WallParticles, box_walls, material_table

__all__ = ["ParticleSystem", "SPHOptions", "Wall", "WallParticles", "box_walls", "material_table"]
