"""ALE Lagrangian phase (``kernels`` steps 1-2): element forces and nodal update; the work and closure
(step 3) are in ``energy``.

Per element e and material m: the material's pressure from its EOS at its own density and energy
(``material_state``), the volume-weighted mixture pressure (``_mixture_pressure``), bulk and
viscous hourglass viscosity, element forces and the stable step (``lagrange_forces``); the
central-difference velocity update with the velocity conditions (``nodal_update``,
``apply_bc``). Paper section 2, eqs.
2.5-2.8; Benson 1992. Equations: docs/theory/ale.md.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ..fem.geometry import bulk_viscosity, stable_dt
from ..fem.tables import QUAD_GAMMA
from ..materials.kernels import EOS_GRUNEISEN, eos_state
from .force_lanes import (_ST_AREA, _ST_B, _ST_BLOCK, _ST_C, _ST_COEF, _ST_GX, _ST_HQ, _ST_LONG2, _ST_M, _ST_P, _ST_RHO,
                          _ST_ROWS, _ST_S, _ST_TRACE, _ST_VMAX2, gas_block, gas_material, gather_block, geometry_block,
                          one_gas, two_gas_block, viscosity_block)
from .hex_lanes import (_HC_ROWS, _HF_ROWS, _HX_BLOCK, _HX_C, _HX_COEF, _HX_HG, _HX_M, _HX_P, _HX_RHO, _HX_ROWS, _HX_VOL,
                        gather_hex_block, hex_force_block, hex_geometry_block, hex_viscosity_block)


# boundary condition codes per node
BC_FREE = 0
BC_SLIP = 1
BC_FIXED = 2
BC_VELOCITY = 3  # prescribed velocity (inflow): bc_normal holds the velocity itself
BC_LINE = 4  # 3D: a node on two slip planes moves along their intersection, bc_normal its unit direction

# a material whose density is below RHO_VOID times its reference density (volume the remap left
# without mass) carries no pressure and no sound speed: it is void
RHO_VOID = 1e-9

# with a pressure cut-off (cavitation), a Gruneisen liquid below RHO_CAVITATED times its reference
# density is cavitated: pressure = the cut-off, sound speed its reference one. Below it the EOS's
# thermal term (Gamma rho = gamma0 rho0, fixed) with the cut-off's work p_c dV in the energy
# gave fog and traces MPa of pressure and sound speeds of 1e5-1.5e6 m/s (c^2 ~ gamma0 rho0 p / rho^2),
# collapsing the step (decks/underwater_explosion_ale.yaml); with normal energies
# (E < (K0/2 + p_c)/gamma0 per reference volume) the EOS gives the cut-off there anyway.
RHO_CAVITATED = 0.5


# ``materials.kernels.eos_state``, its source inlined into these kernels (numba's inliner, as the other
# helpers here) rather than called: a call to the shared compiled eos_state, which may raise (its
# Python-error-model divisions), kept numba's reference counts of the element loop's arrays alive around
# it, an NRT_incref and NRT_decref (atomic calls) of each of nine arrays per element that the pruning pass
# could not remove across the raise path: 81 -> 71 ns per cell-step of lagrange_forces, one material,
# 240^2 cells, 1 thread (the same arithmetic: same bits).
_eos_state = njit(inline="always")(eos_state.py_func)


@njit(cache=True, inline="always")
def material_state(eos, q, rho0, rho, e_spec):
    """(p, c) of one material at density rho and specific internal energy e_spec; (0, 0) for void."""
    if eos < 0 or rho0 <= 0.0 or rho <= 0.0:
        return 0.0, 0.0
    r = rho / rho0
    p, dpdmu, dpde = _eos_state(eos, q, r, rho0 * e_spec)
    c2 = (dpdmu + p * dpde / (r * r)) / rho0
    return p, math.sqrt(c2) if c2 > 0.0 else 0.0


@njit(cache=True)
def quad_area(x0, y0, x1, y1, x2, y2, x3, y3):
    """Signed area of the quadrilateral (0, 1, 2, 3): half the cross product of its diagonals."""
    return 0.5 * ((x2 - x0) * (y3 - y1) - (y2 - y0) * (x3 - x1))


@njit(cache=True, inline="always")
def _mixture_pressure(e, vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q, mat_rho0, phi_eps, pscale, pressure_cutoff,
                      pres_m, bulk_m):
    """Material pressures and bulk moduli of element e, and its mixture state (shared by 2D and 3D).

    Each present material's pressure p_m from its EOS at its own density and specific energy, the stored
    one plus e_lag[e, m] (``lagrange_energy``: the stored energy lags half a step), times pscale, at least
    pressure_cutoff (a cavitated Gruneisen liquid at the cut-off); writes pres_m[e], bulk_m[e] (rho c^2). Returns (p_mix, c_e, M): the volume-weighted pressure sum_m phi_m p_m (the paper's
    mixture theory), the equal-strain mixture sound speed c_e^2 = sum_m M_m c_m^2 / M (see
    ``lagrange_forces``) and the element's mass.
    """
    n_mat = vol_m.shape[1]
    vtot = 0.0
    mtot = 0.0
    for m in range(n_mat):
        vtot += vol_m[e, m]
        mtot += mass_m[e, m]
    p_mix = 0.0
    mc2 = 0.0
    m_in = 0.0
    for m in range(n_mat):
        pres_m[e, m] = 0.0
        bulk_m[e, m] = 0.0
        if vol_m[e, m] > phi_eps * vtot and mass_m[e, m] > RHO_VOID * mat_rho0[m] * vol_m[e, m]:
            rho = mass_m[e, m] / vol_m[e, m]
            p, c = material_state(mat_eos[m], mat_q[m], mat_rho0[m], rho, ener_m[e, m] / mass_m[e, m] + e_lag[e, m])
            p = max(p * pscale[e, m], pressure_cutoff)
            if pressure_cutoff > -math.inf and mat_eos[m] == EOS_GRUNEISEN and rho < RHO_CAVITATED * mat_rho0[m]:
                p = pressure_cutoff
                c = material_state(mat_eos[m], mat_q[m], mat_rho0[m], mat_rho0[m], 0.0)[1]
            pres_m[e, m] = p
            bulk_m[e, m] = rho * c * c
            p_mix += vol_m[e, m] / vtot * p
            mc2 += mass_m[e, m] * c * c
            m_in += mass_m[e, m]
    c_max = math.sqrt(mc2 / m_in) if m_in > 0.0 else 0.0
    return p_mix, c_max, mtot


@njit(cache=True)
def state_block(block, nb, gas, gm1, gpinf, flat, vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q, mat_rho0, phi_eps,
                pscale, pressure_cutoff, pres_m, bulk_m, st_p, st_c, st_m):
    """The material-state pass of the force kernels over elements block .. block + nb - 1: each element's mixture
    pressure, sound speed and mass into st_p, st_c, st_m [0, nb), and pres_m, bulk_m. Where the mesh holds one ideal
    or stiffened gas (``gas``, ``force_lanes.one_gas``) ``force_lanes.gas_block`` on the block's slices of ``flat``
    (the (E, 1) state as flat (E,) views: vol, mass, ener, e_lag, pres, bulk, pscale); where it holds two, both
    ideal or stiffened gases (``force_lanes.gas_material``), ``force_lanes.two_gas_block`` on the block's slices of
    the same flat (2 E,) views, pure and mixed cells alike (issue 17); else ``_mixture_pressure`` element by
    element. Called once per block, not inlined: inlined, its every equation of state was typed and lowered again
    in each of the three force kernels (plane, ring, hex8; issue 17's compile time: ``lagrange_forces_rz`` 17.2 s
    -> 4.5 s plus this 6.4 s once, on an empty cache at load 6)."""
    if gas:
        vol1, mass1, ener1, lag1, pres1, bulk1, pscale1 = flat
        end = block + nb
        gas_block(nb, vol1[block:end], mass1[block:end], ener1[block:end], lag1[block:end], gm1, gpinf,
                  mat_rho0[0], phi_eps, RHO_VOID, pscale1[block:end], pressure_cutoff, pres1[block:end],
                  bulk1[block:end], st_p, st_c, st_m)
        return
    if vol_m.shape[1] == 2:  # two gases: force_lanes.two_gas_block on the flat (2 E,) views
        ok0, gm1_0, gpinf_0 = gas_material(mat_eos, mat_q, mat_rho0, 0)
        ok1, gm1_1, gpinf_1 = gas_material(mat_eos, mat_q, mat_rho0, 1)
        if ok0 and ok1:
            vol1, mass1, ener1, lag1, pres1, bulk1, pscale1 = flat
            a = 2 * block
            z = 2 * (block + nb)
            two_gas_block(nb, vol1[a:z], mass1[a:z], ener1[a:z], lag1[a:z], pscale1[a:z], gm1_0, gpinf_0, mat_rho0[0],
                          gm1_1, gpinf_1, mat_rho0[1], phi_eps, RHO_VOID, pressure_cutoff, pres1[a:z], bulk1[a:z],
                          st_p, st_c, st_m)
            return
    for i in range(nb):
        p_mix, c_max, mtot = _mixture_pressure(block + i, vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q,
                                               mat_rho0, phi_eps, pscale, pressure_cutoff, pres_m, bulk_m)
        st_p[i] = p_mix
        st_c[i] = c_max
        st_m[i] = mtot


# Every parallel kernel splits its items into min(n, N_CHUNKS) fixed runs (``chunk_range``), so the
# partition, and with it every sum, is the same on any thread count.
N_CHUNKS = 512


@njit(cache=True, inline="always")
def chunk_range(chunk, n, n_chunks):
    """Items [start, stop) of run ``chunk`` when n items are split into n_chunks runs."""
    return chunk * n // n_chunks, (chunk + 1) * n // n_chunks


@njit(cache=True, inline="always")
def viscosity_and_step(e, rho_e, length, c_e, trace_d, vmax2, q1, q2, q_elem, dt_elem):
    """Bulk viscosity q of element e (``fem.geometry.bulk_viscosity``; written to q_elem[e] and
    returned) and its stable step (``fem.geometry.stable_dt`` with the signal speed c_e + |v|_max, the
    Eulerian bound of the remap's transport; dt_elem[e], inf where nothing moves or sounds)."""
    q = bulk_viscosity(rho_e, length, c_e, trace_d, q1, q2)
    q_elem[e] = q
    c_eff = c_e + math.sqrt(vmax2)
    dt_elem[e] = stable_dt(length, c_eff, trace_d, q1, q2) if c_eff > 0.0 else np.inf
    return q


# quad4 and hex8 force kernels: a dimension-generic kernel (inline body with the dimension as a constant,
# as in FEM solid_element_forces) measured 6-17 % (2D) and 13-20 % (3D) slower per call (benchmarks/
# ale_throughput.py cases, 1 thread, min of 15 calls, 3 interleaved rounds; docs/theory/ale.md "3D"), so both
# stay. The r-z ring has its own kernel too (axisymmetric.lagrange_forces_rz): this kernel with a ring flag measured
# 14-17 % slower on the ring and 2-5 % on the plane (min / median of 30 alternated calls, report alefold).
# What the plane, ring and hex8 kernels share is inlined from one place (``viscosity_and_step``,
# ``material_state``) or is one of the ``force_lanes`` block passes below.
# The plane kernel goes over each run of elements three times (issue 17): the material state
# (``_mixture_pressure``), the geometry (``quad_geometry``, on scalars), then the viscosity, step and
# forces, through the run's work array st. One element's chain of divisions and square roots (density,
# EOS, sound speed, length, step) is long; a short loop lets the processor overlap those of several
# elements, where the one-pass body (hundreds of instructions per element) kept it waiting. Same
# arithmetic in the same order (bit-identical states of the one- and two-material benchmark cases and
# the ALE decks); 71 -> 51 ns per cell-step, one material, 240^2 cells, 1 thread (min of 20 calls).
# Since (issue 17, second round) the passes of each block of _ST_BLOCK elements are: the material state
# (``force_lanes.gas_block`` for one ideal or stiffened gas, else ``_mixture_pressure``), the corner gather
# (``force_lanes.gather_block``), the geometry (``force_lanes.geometry_block``), the viscosity and step
# (``force_lanes.viscosity_block``), the forces (here); the ``force_lanes`` passes are loops LLVM vectorises
# (its module docstring). Bit-identical; per element, 480^2 one gas, 1 thread, min of 15 calls: state 15.5 ->
# 4.7 ns, viscosity and step 14.8 -> 4.4 (the kernel 52.7 -> 32.8) before the geometry pass, which took the
# kernel from 2.87 to 1.60 ms per call at 240^2 (benchmarks/ale_kernels.py, load 5.6-6.8).
# Two materials, both ideal or stiffened gases (issue 17, the water/air box of benchmarks/ale_throughput.py): the
# state pass force_lanes.two_gas_block reads the (E, 2) arrays in place and computes both gases and the mixture for
# every cell with selects (bit-identical: hashes of the boxes and water_air_shock_tube); min / median ms per call,
# 240^2, 1 thread, 3 rounds of 30 calls alternated with 75c5111 (benchmarks/ale_kernels.py, load 4.1-4.2): 2.481 /
# 2.803 -> 1.883 / 2.039. Gathering the pure cells into gas_block's lanes instead (branch ale2mat a03f2cc) had been
# slower than the scalar loop (2.576 -> 2.691): benchmarks/README.md.
@njit(parallel=True, cache=True)
def lagrange_forces(x, v, conn, vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q, mat_rho0, q1, q2, qhg,
                    phi_eps, pscale, pressure_cutoff, f_elem, pres_m, bulk_m, q_elem, dt_elem):
    """Element forces at x^n with v^{n-1/2} (see module docstring, step 1).

    pscale (E, N) multiplies each material's EOS pressure (1 except for a high explosive, where it
    is the programmed-burn fraction, ``materials.burn``); sound speed and bulk modulus are unscaled.
    pressure_cutoff: pressure cut-off, no material pressure below it (cavitation; -inf for none). A material
    below RHO_VOID of its reference density is void (no pressure, no sound speed).

    The element's sound speed (stable step, bulk and hourglass viscosity) is that of the
    equal-strain mixture, c_e^2 = sum_m phi_m K_m / rho_e = sum_m M_m c_m^2 / M: the element's
    stiffness over its mass. A trace of a material contributes in proportion to its mass, so a
    1 % trace of detonation products stretched to a tiny density with a huge sound speed does not
    set the step (for one material c_e = c).

    Written: f_elem (E, 4, 2) force on each element node, pres_m (E, N) material pressures,
    bulk_m (E, N) material bulk moduli rho c^2, q_elem (E,) bulk viscosity, dt_elem (E,) stable step.
    """
    n_elem = conn.shape[0]
    n_chunks = min(n_elem, N_CHUNKS)
    gas, gm1, gpinf = one_gas(mat_eos, mat_q, mat_rho0)
    # one gas: the (E, 1) state as flat (E,) views for gas_block
    flat = (vol_m.reshape(-1), mass_m.reshape(-1), ener_m.reshape(-1), e_lag.reshape(-1), pres_m.reshape(-1),
            bulk_m.reshape(-1), pscale.reshape(-1))
    for chunk in prange(n_chunks):
        start, stop = chunk_range(chunk, n_elem, n_chunks)
        # three passes over each block of the run, through its rows of st (the block's elements along each
        # row): the material state; the geometry; the forces (see the comment above the kernel). Blocks of
        # _ST_BLOCK elements keep st in the first-level cache whatever the run's length.
        st = np.empty((_ST_ROWS, _ST_BLOCK))
        st_flat = st.reshape(-1)
        cx = np.empty(16 * _ST_BLOCK)
        for block in range(start, stop, _ST_BLOCK):
            nb = min(_ST_BLOCK, stop - block)
            state_block(block, nb, gas, gm1, gpinf, flat, vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q, mat_rho0,
                        phi_eps, pscale, pressure_cutoff, pres_m, bulk_m, st[_ST_P], st[_ST_C], st[_ST_M])
            gather_block(conn, block, nb, x, v, cx)
            geometry_block(nb, cx, st_flat)
            viscosity_block(nb, st[_ST_P], st[_ST_C], st[_ST_M], st[_ST_AREA], st[_ST_TRACE], st[_ST_VMAX2],
                            st[_ST_LONG2], q1, q2, qhg, q_elem[block:block + nb], dt_elem[block:block + nb], st[_ST_S],
                            st[_ST_RHO], st[_ST_COEF])
            for i in range(nb):
                e = block + i
                s = st[_ST_S, i]
                if qhg > 0.0 and st[_ST_RHO, i] > 0.0:  # hourglass (Flanagan & Belytschko 1981): f_a -= coef (gamma . v) gamma_a
                    coef = st[_ST_COEF, i]
                    gx0 = st[_ST_GX, i]
                    gx1 = st[_ST_GX + 1, i]
                    hq0 = st[_ST_HQ, i]
                    hq1 = st[_ST_HQ + 1, i]
                    for a in range(4):
                        b0 = st[_ST_B + a, i]
                        b1 = st[_ST_B + 4 + a, i]
                        g = QUAD_GAMMA[a] - gx0 * b0 - gx1 * b1
                        f_elem[e, a, 0] = s * b0 - coef * hq0 * g
                        f_elem[e, a, 1] = s * b1 - coef * hq1 * g
                else:
                    for a in range(4):
                        f_elem[e, a, 0] = s * st[_ST_B + a, i]
                        f_elem[e, a, 1] = s * st[_ST_B + 4 + a, i]


@njit(parallel=True, cache=True)
def lagrange_forces_3d(x, v, conn, vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q, mat_rho0, q1, q2, qhg,
                       phi_eps, pscale, pressure_cutoff, f_elem, pres_m, bulk_m, q_elem, dt_elem):
    """``lagrange_forces`` on hex8: element forces at x^n with v^{n-1/2}.

    Mean-gradient (Flanagan & Belytschko 1981) b = (1/V) dV/dx_I (fem.geometry.hex8_gradient),
    f_eI = V (p_mix + q) b_I with the same mixture pressure (``_mixture_pressure``), bulk viscosity
    and stable step (length V / largest face area, fem.geometry.hex8_char_length); viscous
    hourglass on the four hex8 modes gamma_j = Gamma_j - (Gamma_j . x) b, force
    -c_hg (gamma_j . v) gamma_j with c_hg = qhg rho c V^(2/3) / 4 (the FEM solid's viscous form).
    Written: f_elem (E, 8, 3), pres_m, bulk_m, q_elem, dt_elem as in 2D.

    In passes over blocks of elements (``hex_lanes``: state, gather, geometry, viscosity and step, hourglass
    coefficient, forces), the vectorised ones the scalar code's operations in its order: the same bits as the
    one-element-at-a-time loop it replaced (hashes of the 3D ALE decks and benchmark boxes). 40^3 box in a
    vortex, 1 thread, min of 7 calls: 250 -> 121 ns per element (the scalar hourglass had been 167 of the 250;
    now the corner gather 38, geometry 29, forces and hourglass 24, the copy into f_elem 20, the rest 9). A
    collapsed element (V = 0) gives rho_e = inf here (numpy's error model) where the scalar loop raised
    ZeroDivisionError.
    """
    n_elem = conn.shape[0]
    n_chunks = min(n_elem, N_CHUNKS)
    gas, gm1, gpinf = one_gas(mat_eos, mat_q, mat_rho0)
    flat = (vol_m.reshape(-1), mass_m.reshape(-1), ener_m.reshape(-1), e_lag.reshape(-1), pres_m.reshape(-1),
            bulk_m.reshape(-1), pscale.reshape(-1))
    B = _HX_BLOCK
    for chunk in prange(n_chunks):
        start, stop = chunk_range(chunk, n_elem, n_chunks)
        # passes over each block of the run through its work rows (ale/hex_lanes.py): the material state, the
        # corner gather, the geometry, the viscosity and step, then the forces and hourglass here
        st = np.empty(_HX_ROWS * B)
        cx = np.empty(_HC_ROWS * B)
        fo = np.empty(_HF_ROWS * B)
        for block in range(start, stop, B):
            nb = min(B, stop - block)
            end = block + nb
            state_block(block, nb, gas, gm1, gpinf, flat, vol_m, mass_m, ener_m, e_lag, mat_eos, mat_q, mat_rho0,
                        phi_eps, pscale, pressure_cutoff, pres_m, bulk_m, st[_HX_P * B:(_HX_P + 1) * B],
                        st[_HX_C * B:(_HX_C + 1) * B], st[_HX_M * B:(_HX_M + 1) * B])
            gather_hex_block(conn, block, nb, x, v, cx)
            hex_geometry_block(nb, cx, st)
            hex_viscosity_block(nb, st, q1, q2, q_elem[block:end], dt_elem[block:end])
            for i in range(nb):  # the hourglass coefficient (the power: scalar)
                rho_e = st[_HX_RHO * B + i]
                hg = qhg > 0.0 and rho_e > 0.0
                st[_HX_HG * B + i] = 1.0 if hg else 0.0
                st[_HX_COEF * B + i] = 0.25 * qhg * rho_e * st[_HX_C * B + i] * st[_HX_VOL * B + i] ** (2.0 / 3.0) \
                    if hg else 0.0
            hex_force_block(nb, cx, st, fo)
            for i in range(nb):
                e = block + i
                for a in range(8):
                    for k in range(3):
                        f_elem[e, a, k] = fo[(3 * a + k) * B + i]


@njit(cache=True, inline="always")
def apply_bc(kind, bc, w0, w1, w2, dim):
    """Velocity conditions on the velocity (w0, w1[, w2]) of a node, returned as a triple (the third 0 in
    2D); bc = the node's bc_normal row; dim (2 or 3) a literal constant of the caller.

    BC_FIXED: w = 0; BC_SLIP: w - (w . n) n; BC_VELOCITY: w = bc (the prescribed velocity);
    BC_LINE (3D): (w . t) t along the unit direction t of two walls' intersection; BC_FREE: w.
    Dot products summed in component order.
    """
    if kind == BC_FIXED:
        return 0.0, 0.0, 0.0
    if kind == BC_SLIP:
        vn = w0 * bc[0] + w1 * bc[1]
        if dim == 3:
            vn += w2 * bc[2]
            return w0 - vn * bc[0], w1 - vn * bc[1], w2 - vn * bc[2]
        return w0 - vn * bc[0], w1 - vn * bc[1], 0.0
    if kind == BC_VELOCITY:
        return bc[0], bc[1], (bc[2] if dim == 3 else 0.0)
    if dim == 3 and kind == BC_LINE:
        vt = w0 * bc[0] + w1 * bc[1] + w2 * bc[2]
        return vt * bc[0], vt * bc[1], vt * bc[2]
    return w0, w1, w2


@njit(cache=True, inline="always")
def node_conditions(live, kind, bc, w0, w1, w2, dim):
    """The velocity of a node after its update (``nodal_update``) or remap (``finish_remap_nodes``): its
    velocity conditions (``apply_bc``) where it is live (its mass above its floor, or a prescribed
    velocity), else (0, 0, 0) (a fog node is held)."""
    if live:
        return apply_bc(kind, bc, w0, w1, w2, dim)
    return 0.0, 0.0, 0.0


@njit(cache=True, inline="always")
def update_nodes(f_elem, node_elem_ptr, node_elem_idx, f_ext, mass, m_floor, v, bc_type, bc_normal, dt, impulse,
                 x, v_old, v_mid, v_lag, x_lag, npe, dim):
    """The body of ``nodal_update`` (quad4) and ``nodal_update_3d`` (hex8): npe corners per element and dim
    components, literal constants of the caller, so that each compiles as if written for its element
    (scalars, the third component's lines dropped in 2D).

    Per node: f = f_ext + its corner forces, gathered over node_elem_ptr / node_elem_idx (e * npe + corner)
    in that order; w = v + dt f / m (0 without mass); u = w under the velocity conditions
    (``node_conditions``); impulse = m (u - w); v_old = v (before), v = v_lag = u,
    v_mid = (v_old + u) * 0.5, x_lag = x + u * dt (the step's node arrays, numpy expressions before).
    """
    for n in prange(v.shape[0]):
        f0 = f_ext[n, 0]
        f1 = f_ext[n, 1]
        f2 = f_ext[n, 2] if dim == 3 else 0.0
        for r in range(node_elem_ptr[n], node_elem_ptr[n + 1]):
            ea = node_elem_idx[r]
            e = ea // npe
            a = ea - npe * e
            f0 += f_elem[e, a, 0]
            f1 += f_elem[e, a, 1]
            if dim == 3:
                f2 += f_elem[e, a, 2]
        m = mass[n]
        v0 = v[n, 0]
        v1 = v[n, 1]
        v2 = v[n, 2] if dim == 3 else 0.0
        w0 = v0 + dt * f0 / m if m > 0.0 else 0.0
        w1 = v1 + dt * f1 / m if m > 0.0 else 0.0
        w2 = v2 + dt * f2 / m if dim == 3 and m > 0.0 else 0.0
        u0, u1, u2 = node_conditions(m > m_floor[n] or bc_type[n] == BC_VELOCITY, bc_type[n], bc_normal[n], w0, w1, w2,
                                     dim)
        impulse[n, 0] = m * (u0 - w0)
        impulse[n, 1] = m * (u1 - w1)
        v[n, 0] = u0
        v[n, 1] = u1
        v_old[n, 0] = v0
        v_old[n, 1] = v1
        v_lag[n, 0] = u0
        v_lag[n, 1] = u1
        v_mid[n, 0] = (v0 + u0) * 0.5
        v_mid[n, 1] = (v1 + u1) * 0.5
        x_lag[n, 0] = x[n, 0] + u0 * dt
        x_lag[n, 1] = x[n, 1] + u1 * dt
        if dim == 3:
            impulse[n, 2] = m * (u2 - w2)
            v[n, 2] = u2
            v_old[n, 2] = v2
            v_lag[n, 2] = u2
            v_mid[n, 2] = (v2 + u2) * 0.5
            x_lag[n, 2] = x[n, 2] + u2 * dt


# quad4 and hex8: one body (``update_nodes``, inline, the corner count and dimension literal constants), one
# compiled kernel per element kind. A dimension-generic kernel with the node's velocity in arrays had
# measured 10-25 % (2D) slower per call (benchmarks/ale_throughput.py cases, 1 thread, min of 15 calls, 3
# interleaved rounds), and so did this body with arrays (1.20-1.41 x, one round); with scalars, against the
# former twins: bit-identical on eight ALE decks; min / median ms per call before -> after (benchmarks/
# ale_kernels.py --trees BASE THIS --rounds 5 --calls 50, 1 thread, 6 Dec 2026, load 3.9-4.0, BASE = e629c8f):
# plane 0.62 / 0.68 -> 0.55 / 0.64, two materials 0.59 / 0.66 -> 0.56 / 0.61, ring 0.56 / 0.66 -> 0.55 / 0.63,
# hex8 1.37 / 1.75 -> 1.25 / 1.66.
@njit(parallel=True, cache=True)
def nodal_update(f_elem, node_elem_ptr, node_elem_idx, f_ext, mass, m_floor, v, bc_type, bc_normal, dt, impulse,
                 x, v_old, v_mid, v_lag, x_lag):
    """v^{n+1/2} = v^{n-1/2} + dt (f_int + f_ext) / m (eq. 2.7), then the velocity conditions (``update_nodes``).

    bc_type per node: BC_FREE, BC_SLIP (normal component along bc_normal removed), BC_FIXED,
    BC_VELOCITY (v = bc_normal, a prescribed velocity).
    impulse (N, 2) receives the reaction impulse m (v_constrained - v_free) of this step.
    Nodes with a mass at or below m_floor (N,) (numerical fog, or none) are held at zero velocity,
    their momentum booked in impulse like a fixed node's; a prescribed velocity (BC_VELOCITY)
    holds whatever the mass.
    Also written, for the rest of the step (one pass over the nodes instead of five numpy ones): v_old (N, 2)
    the velocity before, v_lag = v^{n+1/2}, v_mid = (v_old + v^{n+1/2}) * 0.5, x_lag = x + v^{n+1/2} * dt.
    """
    update_nodes(f_elem, node_elem_ptr, node_elem_idx, f_ext, mass, m_floor, v, bc_type, bc_normal, dt, impulse,
                 x, v_old, v_mid, v_lag, x_lag, 4, 2)


@njit(parallel=True, cache=True)
def nodal_update_3d(f_elem, node_elem_ptr, node_elem_idx, f_ext, mass, m_floor, v, bc_type, bc_normal, dt, impulse,
                    x, v_old, v_mid, v_lag, x_lag):
    """``nodal_update`` on hex8 nodes (N, 3): the same body (``update_nodes``), 8 corners, 3 components."""
    update_nodes(f_elem, node_elem_ptr, node_elem_idx, f_ext, mass, m_floor, v, bc_type, bc_normal, dt, impulse,
                 x, v_old, v_mid, v_lag, x_lag, 8, 3)
