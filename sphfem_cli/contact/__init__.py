"""Contact and coupling: penalty forces between slave points and master segments.

- `surface`: master segments (outer faces of solid parts, or segment sets) with their owners.
- `kernels`: the compiled search and penalty kernels of nodes-to-surface contact.
- `system`: `NodesToSurfaceContact`, the deck's `contacts` inside the explicit loop.
- `coupling`, `coupling_kernels`, `coupling_kernels_3d`: `LagrangeInSolidCoupling`, the deck's ALE-to-structure `couplings`.
- `coupling_search`, `coupling_common`: what the 2D and 3D coupling kernels share (host search; interface
  reconstruction and penalty law), inline bodies called with a literal element kind.
- `sph_boundary`: `SphBoundaryCoupling`, SPH-to-structure `couplings` by boundary particles the structure carries
  (kernels in sph/structure_walls.py).

Imported only when a deck has contacts or couplings (see solver.explicit for the interface).
"""
