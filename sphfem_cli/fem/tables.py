"""The elements' constant tables (VTK node order), numpy only: the numba kernels of ``fem.geometry`` (and its users)
fold them, the numpy initial-state passes (``fem.at_rest``, ``ale.at_rest``) read them without loading numba."""
from __future__ import annotations

import numpy as np

__numba_folded__ = True  # numba folds these tables into kernels: part of the compiled-cache key

# dV/dx_I = (1/12) sum over rows (I, j, k, s) of s (y_j z_k - y_k z_j), and cyclically for y, z:
# the exact derivative of the trilinear hex8 volume (VTK node order), derived symbolically.
HEX_DV = np.array([
    (0, 1, 2, -1), (0, 1, 3, -1), (0, 1, 4, 1), (0, 1, 5, 1), (0, 2, 3, -1), (0, 3, 4, -1),
    (0, 3, 7, -1), (0, 4, 5, -1), (0, 4, 7, 1),
    (1, 0, 2, 1), (1, 0, 3, 1), (1, 0, 4, -1), (1, 0, 5, -1), (1, 2, 3, -1), (1, 2, 5, 1),
    (1, 2, 6, 1), (1, 4, 5, -1), (1, 5, 6, -1),
    (2, 0, 1, -1), (2, 0, 3, 1), (2, 1, 3, 1), (2, 1, 5, -1), (2, 1, 6, -1), (2, 3, 6, 1),
    (2, 3, 7, 1), (2, 5, 6, -1), (2, 6, 7, -1),
    (3, 0, 1, -1), (3, 0, 2, -1), (3, 0, 4, 1), (3, 0, 7, 1), (3, 1, 2, -1), (3, 2, 6, -1),
    (3, 2, 7, -1), (3, 4, 7, 1), (3, 6, 7, -1),
    (4, 0, 1, 1), (4, 0, 3, -1), (4, 0, 5, 1), (4, 0, 7, -1), (4, 1, 5, 1), (4, 3, 7, -1),
    (4, 5, 6, 1), (4, 5, 7, 1), (4, 6, 7, 1),
    (5, 0, 1, 1), (5, 0, 4, -1), (5, 1, 2, 1), (5, 1, 4, -1), (5, 1, 6, 1), (5, 2, 6, 1),
    (5, 4, 6, -1), (5, 4, 7, -1), (5, 6, 7, 1),
    (6, 1, 2, 1), (6, 1, 5, -1), (6, 2, 3, 1), (6, 2, 5, -1), (6, 2, 7, 1), (6, 3, 7, 1),
    (6, 4, 5, 1), (6, 4, 7, -1), (6, 5, 7, -1),
    (7, 0, 3, -1), (7, 0, 4, 1), (7, 2, 3, 1), (7, 2, 6, -1), (7, 3, 4, 1), (7, 3, 6, -1),
    (7, 4, 5, 1), (7, 4, 6, 1), (7, 5, 6, 1),
], dtype=np.int64)

# Hourglass base vectors: quad4 xi*eta; hex8 xi*eta, eta*zeta, zeta*xi, xi*eta*zeta.
QUAD_GAMMA = np.array([1.0, -1.0, 1.0, -1.0])
HEX_GAMMA = np.array([
    [1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0],
    [1.0, 1.0, -1.0, -1.0, -1.0, -1.0, 1.0, 1.0],
    [1.0, -1.0, -1.0, 1.0, -1.0, 1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0, 1.0, 1.0, -1.0, 1.0, -1.0],
])
# Faces of a hex8 (for the characteristic length).
HEX_FACES = np.array([
    [0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]
], dtype=np.int64)
