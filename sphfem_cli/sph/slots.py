"""Named slots of the SPH kernels' arrays: the one declaration of every index into them.

Four small vectors carry the scalars of an evaluation into the kernels (numba folds these
module-level integers into constants):

* ``settings_f`` (``N_SF``) and ``settings_i`` (``N_SI``): the deck's numerical settings, packed
  once by ``SphSystem`` (``sph/system.py``) and never rewritten;
* ``grid_f`` (``N_GF``) and ``grid_i`` (``N_GI``): the cell grid of the current evaluation,
  rewritten by ``search.sort_points`` at every neighbour search.

The rows of the sorted data array ``sd`` (``D_*``, ``ND`` of them; one column per point) and the point
kinds (``KIND_*``, packed with the material id as ``mat * 4 + kind``) are declared here too; the
layout of an evaluation is described in ``sph/search.py``.
"""
from __future__ import annotations

__numba_folded__ = True  # numba folds these ints into kernels: part of the compiled-cache key

# point kinds
KIND_FLUID = 0
KIND_GHOST = 1
KIND_WALL = 2

# the condition code of a ghost plane (column 3 of the planes array of walls.make_ghosts): a slip or
# no-slip wall, or a non-reflecting open side (sph/open_sides.py)
PLANE_SLIP, PLANE_NO_SLIP, PLANE_OPEN = 0.0, 1.0, 2.0

# columns of the sorted data array sd: vx, vy, vz, rho, V = m/rho, p/rho^2, c, mat*4+kind
D_VX, D_VY, D_VZ, D_RHO, D_VOL, D_PR, D_C, D_MK = 0, 1, 2, 3, 4, 5, 6, 7
ND = 8


def _vector_lanes() -> int:
    """Slots per chunk of the rates' candidate loops (``rates._row_sums``, ``axisymmetric``): 8 where the
    CPU has AVX-512 (LLVM then vectorises those loops 8 doubles wide, zmm), else 4 (AVX2: 4 wide, ymm).

    A row's candidates are rounded up to whole chunks so that the vectorised loop has no remainder; a
    padded slot adds exactly 0. Where LLVM's vector is 4 doubles and the loop is not interleaved, the
    accumulator lane of slot j is (j - s) mod 4 with chunks of 4 or 8 alike, so the chunk of 4 gives the
    same bits as that of 8, minus the all-padding half-chunks (rows of 1-4 slots past a multiple of
    8): on an AVX2 Zen 3, rates 330-337 -> 312-323 ns per particle-step (dam break, 89 888 particles,
    one thread, three alternated runs; issue 17). With 8-wide vectors a chunk of 4 leaves a scalar
    remainder (slower, and other sums). ``NUMBA_CPU_NAME`` set: the features named in
    ``NUMBA_CPU_FEATURES`` decide, 8 if none are named.
    """
    try:
        from numba.core import config

        if config.CPU_NAME is not None:
            feats = config.CPU_FEATURES
            return 8 if feats is None or "+avx512f" in feats else 4
        import llvmlite.binding as llvm

        return 8 if llvm.get_host_cpu_features().get("avx512f", False) else 4
    except Exception:  # noqa: BLE001 - no host features: the chunk every CPU vectorises without remainder
        return 8


# columns of sx and sd after the last point's: the sentinel and copies of it, so that the rates, which
# read their candidate slots in whole chunks of N_LANES (rates.py), never read past the arrays (eight
# whatever N_LANES is: the storage layout, which a checkpoint holds, does not depend on the CPU)
N_LANES = _vector_lanes()
N_SENTINEL = 8

# settings_f: Monaghan viscosity alpha, beta, eps; delta-SPH coefficient; XSPH coefficient;
# gravity; dilatational viscosity mu'; pressure cut-off (the deck's pressure_cutoff); with the shock
# switch (sph/switch.py), beta/alpha, the ratio that scales a pair's beta_ij = (beta/alpha) alpha_ij
SF_ALPHA, SF_BETA, SF_EPS, SF_DELTA, SF_XSPH = 0, 1, 2, 3, 4
SF_GX, SF_GY, SF_GZ = 5, 6, 7
SF_DILATATIONAL_VISCOSITY, SF_PRESSURE_CUTOFF = 8, 9
SF_BETA_PER_ALPHA = 10
N_SF = 11

# settings_i: dimension; smoothing kernel (kernel_functions.CUBIC_SPLINE / WENDLAND_C2); 1 when a
# material is viscous; 1 with the hydrostatic delta-SPH correction; number of dummy wall particles;
# the continuity form (CONTINUITY_VOLUME: rho_i sum V_j v_ij.grad W, CONTINUITY_MASS: sum m_j v_ij.grad W);
# the number of materials in the table
SI_DIM, SI_KERNEL, SI_VISCOUS, SI_DELTA_HYDROSTATIC, SI_NWALL, SI_CONTINUITY, SI_NMAT = 0, 1, 2, 3, 4, 5, 6
N_SI = 7
CONTINUITY_VOLUME, CONTINUITY_MASS = 0, 1
CONTINUITY_FORMS = {"volume": CONTINUITY_VOLUME, "mass": CONTINUITY_MASS}

# grid_f: largest smoothing length, cell width, grid origin
GF_HMAX, GF_CELL, GF_OX, GF_OY, GF_OZ = 0, 1, 2, 3, 4
N_GF = 5

# grid_i: number of cells along x, y, z
GI_NX, GI_NY, GI_NZ = 0, 1, 2
N_GI = 3
