"""The one declaration of the solid section table's columns, the hourglass types, the 2D formulations
and the element status ``INVERTED``: module-level ints without numba, so that the model build and
``sphfem check`` name them without loading the kernels (``fem.kernels`` re-exports them)."""
from __future__ import annotations

__numba_folded__ = True  # numba folds these ints into kernels: part of the compiled-cache key

HG_VISCOUS = 0
HG_STIFFNESS = 1

# 2D formulation of a solid section (deck: sections.<name>.formulation), column SEC_FORMULATION.
PLANE_STRAIN = 0  # eps_zz = 0, sigma_zz carried (the default; 3D and axisymmetric sections too)
PLANE_STRESS = 1  # sigma_zz = 0, the thickness strain solved for (docs/theory/fem.md "Plane stress")

# Section table columns.
SEC_HG_TYPE, SEC_HG_COEF, SEC_Q1, SEC_Q2, SEC_FORMULATION = 0, 1, 2, 3, 4
NSEC = 5

# Element status written into dt_elem when the element is invalid.
INVERTED = -1.0
