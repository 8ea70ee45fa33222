"""The one declaration of the material and equation-of-state type ids.

A material is a type id plus a parameter row (``materials.slots``); the EOS id sits in the row's
``P_EOS_TYPE`` slot. The ids live in this module without numba, so that the model build and
``sphfem check`` can name them without loading the kernels (``materials.kernels`` re-exports them).
"""
from __future__ import annotations

__numba_folded__ = True  # numba folds these ints into kernels: part of the compiled-cache key

# material type ids
ELASTIC = 0
ELASTIC_PLASTIC = 1
JOHNSON_COOK = 2
RIGID = 3
FLUID = 4

# equation-of-state type ids
EOS_NONE = -1
EOS_LINEAR_POLYNOMIAL = 0
EOS_GRUNEISEN = 1
EOS_TAIT = 2
EOS_IDEAL_GAS = 3
EOS_STIFFENED_GAS = 4
EOS_JWL = 5
