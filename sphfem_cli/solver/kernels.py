"""Kernels of the time loop itself (the physics have their own, in their folders)."""
from __future__ import annotations

from numba import njit


@njit(cache=True, fastmath={"reassoc"}, error_model="numpy")
def first_non_finite_array(arrays):
    """Index in `arrays` (a tuple of 1D float64 arrays) of the first holding a NaN or an infinity, else -1.

    sum a_i * 0 is 0 for finite entries and NaN for a NaN or an infinity; reassoc lets LLVM vectorise
    the sum, and without nnan/ninf it may not fold a_i * 0 to 0.
    """
    for k in range(len(arrays)):
        a = arrays[k]
        acc = 0.0
        for i in range(a.size):
            acc += a[i] * 0.0
        if acc != acc:
            return k
    return -1
