"""The one declaration of the solid section table's columns, the hourglass types and the element
status ``INVERTED``: module-level ints without numba, so that the model build and ``sphfem check``
name them without loading the kernels (``fem.kernels`` re-exports them)."""
from __future__ import annotations

__numba_folded__ = True  # numba folds these ints into kernels: part of the compiled-cache key

HG_VISCOUS = 0
HG_STIFFNESS = 1

# Section table columns.
SEC_HG_TYPE, SEC_HG_COEF, SEC_Q1, SEC_Q2 = 0, 1, 2, 3
NSEC = 4

# Element status written into dt_elem when the element is invalid.
INVERTED = -1.0
