"""Pure cells of multi-material ALE meshes (issue 17): their lanes give the general path's bits.

A pure cell holds one material alone (``lagrange.pure_material``: the other materials' volume and mass 0,
its volume positive). There the force kernels' material state (``lagrange.state_block``: the pure cells of an
ideal or stiffened gas through ``force_lanes.gas_block``), the closure (``energy.closure_block``: the pure cells
through ``one_material_closure``) and the face fluxes between pure cells of one material (``remap.pure_face``:
``face_lanes.face_block``) replace the general loops over the materials. Each is compared with the general
helper called element by element (face by face) on the same state, to the bit (assert_array_equal), on a
random three-material state of 300 elements (two blocks of 128 and a rest): pure cells of a stiffened gas
(water), of an ideal gas (air) and of a Gruneisen liquid (not a gas: the general path), mixed cells, void
cells (no mass), an element of zero volume, with a pressure cut-off, and e_lag / pscale not trivial.
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.ale import AleOptions, AleSystem, fill_fractions
from sphfem_cli.ale import kernels as K
from sphfem_cli.ale.energy import PC_ROWS, _closure_energy, closure_block
from sphfem_cli.ale.fill import material_tables
from sphfem_cli.ale.lagrange import PW_ROWS, _mixture_pressure, pure_material, state_block
from sphfem_cli.ale.remap import _face_flux, pure_face
from sphfem_cli.deck.schema import materials as sm
from sphfem_cli.materials.tables import gas_row, pack_material
from sphfem_cli.model.mesh import box_mesh

N_ELEM = 300
WATER, AIR, LIQUID = 0, 1, 2
PHI_EPS = 1e-9


def _materials():
    """(mat_eos, mat_q, mat_rho0) of stiffened water, ideal air and a Gruneisen liquid (rows as ``AleSystem``'s)."""
    eos = sm.Gruneisen(type="gruneisen", c=1480.0, s1=1.92, gamma0=0.28)
    rows = [gas_row(4.4, 1000.0, 6e8), gas_row(1.4, 1.2), pack_material(sm.Fluid(type="fluid", density=1000.0,
                                                                                    eos="water"), eos)[1]]
    return material_tables(rows)[:3]


def _state(seed):
    """Random (vol_m, mass_m, ener_m, e_lag, pscale) of N_ELEM elements and 3 materials: each element pure in
    one material (70 %) or a mix of two or three; a few void (massless) materials and one zero-volume element."""
    rng = np.random.default_rng(seed)
    rho0 = np.array([1000.0, 1.2, 1000.0])
    frac = np.zeros((N_ELEM, 3))
    pure = rng.random(N_ELEM) < 0.7
    frac[pure, rng.integers(0, 3, pure.sum())] = 1.0
    mixed = ~pure
    w = rng.random((mixed.sum(), 3)) * (rng.random((mixed.sum(), 3)) < 0.7)
    w[:, 0] += 0.05
    frac[mixed] = w / w.sum(axis=1, keepdims=True)
    vol = (1.0 + 0.2 * rng.random(N_ELEM))[:, None] * frac
    vol_m = np.ascontiguousarray(vol)
    mass_m = vol_m * rho0 * (1.0 + 0.05 * rng.standard_normal((N_ELEM, 3)))
    e_spec = np.array([3e5, 2.1e5, 1e4]) * (1.0 + 0.3 * rng.random((N_ELEM, 3)))
    ener_m = mass_m * e_spec
    e_lag = 0.01 * e_spec * rng.standard_normal((N_ELEM, 3)) * (vol_m > 0.0)
    mass_m[:7, :] = 0.0  # void: volume without mass
    ener_m[:7, :] = 0.0
    vol_m[7, :] = 0.0  # an element of no volume
    mass_m[7, :] = 0.0
    ener_m[7, :] = 0.0
    pscale = np.where(rng.random((N_ELEM, 3)) < 0.2, rng.random((N_ELEM, 3)), 1.0)
    return vol_m, mass_m, ener_m, e_lag, pscale


def _kinds(vol_m, mass_m):
    """``pure_material`` of every element: its material where pure, else -1."""
    return np.array([pure_material(e, vol_m, mass_m) for e in range(vol_m.shape[0])])


@pytest.mark.parametrize("cutoff", [-np.inf, -1e4])
@pytest.mark.parametrize("seed", [0, 1])
def test_pure_cells_state_gives_the_mixture_pressures_bits(seed, cutoff):
    eos, q, rho0 = _materials()
    vol_m, mass_m, ener_m, e_lag, pscale = _state(seed)
    kinds = _kinds(vol_m, mass_m)
    assert set(kinds) == {-1, WATER, AIR, LIQUID}  # pure cells of all three, and mixed ones
    pres, bulk = np.full((N_ELEM, 3), np.nan), np.full((N_ELEM, 3), np.nan)
    st = np.full((3, N_ELEM), np.nan)
    flat = tuple(np.zeros(0) for _ in range(7))  # (one gas only)
    B = 128
    pw = np.empty(PW_ROWS * B)
    for block in range(0, N_ELEM, B):
        nb = min(B, N_ELEM - block)
        state_block(block, nb, False, 0.0, 0.0, flat, vol_m, mass_m, ener_m, e_lag, eos, q, rho0, PHI_EPS, pscale,
                    cutoff, pres, bulk, st[0, block:], st[1, block:], st[2, block:], pw, B)
    ref_pres, ref_bulk = np.full((N_ELEM, 3), np.nan), np.full((N_ELEM, 3), np.nan)
    ref = np.array([_mixture_pressure(e, vol_m, mass_m, ener_m, e_lag, eos, q, rho0, PHI_EPS, pscale, cutoff,
                                      ref_pres, ref_bulk) for e in range(N_ELEM)]).T
    np.testing.assert_array_equal(st, ref)
    np.testing.assert_array_equal(pres, ref_pres)
    np.testing.assert_array_equal(bulk, ref_bulk)
    gas = (kinds == WATER) | (kinds == AIR)
    assert np.all(ref[0, gas & (mass_m.sum(axis=1) > 0.0)] != 0.0)  # the pure gas cells carry pressure


@pytest.mark.parametrize("closure", [K.CLOSURE_EQUAL_STRAIN, K.CLOSURE_RELAX])
@pytest.mark.parametrize("seed", [0, 1])
def test_pure_cells_closure_gives_the_general_closures_bits(seed, closure):
    eos, q, rho0 = _materials()
    vol_m, mass_m, ener_m, e_lag, pscale = _state(seed)
    rng = np.random.default_rng(seed + 10)
    pres = np.full((N_ELEM, 3), np.nan)
    bulk = np.full((N_ELEM, 3), np.nan)
    for e in range(N_ELEM):
        _mixture_pressure(e, vol_m, mass_m, ener_m, e_lag, eos, q, rho0, PHI_EPS, pscale, -np.inf, pres, bulk)
    v_lag = vol_m.sum(axis=1) * (1.0 + 0.01 * rng.standard_normal(N_ELEM))  # compression and expansion
    work = 1e3 * rng.standard_normal(N_ELEM)
    pressed = rng.random(N_ELEM) < 0.1
    a = [arr.copy() for arr in (vol_m, ener_m, e_lag)]
    b = [arr.copy() for arr in (vol_m, ener_m, e_lag)]
    dvm, dev = np.empty(3), np.empty(3)
    B = 128
    pw = np.empty(PC_ROWS * B)
    for block in range(0, N_ELEM, B):
        nb = min(B, N_ELEM - block)
        closure_block(block, nb, work[block:block + nb], v_lag[block:block + nb], a[0], mass_m, a[1], a[2], pres, bulk,
                      closure, 0.5, 0.5, PHI_EPS, pressed, dvm, dev, pw)
    for e in range(N_ELEM):
        _closure_energy(e, work[e], v_lag[e], b[0], mass_m, b[1], b[2], pres, bulk, closure, 0.5, 0.5, PHI_EPS,
                        pressed, dvm, dev)
    for name, x, y in zip(("vol_m", "ener_m", "e_lag"), a, b):
        np.testing.assert_array_equal(x, y, err_msg=name)
    assert not np.array_equal(a[0], vol_m)  # the volumes changed


def _reference_fluxes(ale, x_lag, faces, out):
    """``_face_flux`` on every flowing face of a quad4 sweep: the swept area of the face from x_lag to the mesh,
    the donor the element losing volume, the upwind element its neighbour across the opposite side."""
    topo = ale.topo
    fn, fe, fl, nbr = topo["face_nodes"], topo["face_elem"], topo["face_local"], topo["elem_nbr"]
    x_new = ale.x0
    dvm, g, used = np.empty(3), np.empty(3), np.empty(3, dtype=np.bool_)
    for f in faces:
        el, er = fe[f]
        if er < 0:
            continue
        n0, n1 = fn[f, :2]
        dv = K.quad_area(x_lag[n0, 0], x_lag[n0, 1], x_new[n0, 0], x_new[n0, 1], x_new[n1, 0], x_new[n1, 1],
                         x_lag[n1, 0], x_lag[n1, 1])
        if dv == 0.0:
            continue
        if dv > 0.0:
            donor, acc, sgn, far = er, el, 1.0, nbr[er, (fl[f, 1] + 2) % 4]
        else:
            donor, acc, sgn, far = el, er, -1.0, nbr[el, (fl[f, 0] + 2) % 4]
        _face_flux(f, abs(dv), donor, acc, far, sgn, ale.vol_m, ale.mass_m, ale.ener_m, ale.order, ale.iface,
                   PHI_EPS, *out, dvm, g, used)


@pytest.mark.parametrize("order", [1, 2])
def test_pure_faces_give_the_scalar_fluxes_bits(order):
    """Water below a wavy line, air above (pure cells but along the line), the Lagrangian mesh displaced by up to
    about half a cell: every interior face's fluxes from ``face_fluxes`` (pure faces in lanes) and from
    ``_face_flux`` (all faces) agree to the bit."""
    mesh = box_mesh([0.0, 0.0], [1.0, 1.0], divisions=[20, 15])  # 300 elements
    nodes, conn = mesh.nodes, mesh.elements
    rng = np.random.default_rng(order)
    f = fill_fractions(nodes, conn, lambda x, y: y < 0.5 + 0.1 * np.sin(7 * x))
    rho = np.stack([1000.0 * (1.0 + 0.01 * rng.random(len(conn))), 1.2 * (1.0 + 0.1 * rng.random(len(conn)))], 1)
    p = 1e5 * (1.0 + rng.random(len(conn)))
    adv = "van_leer" if order == 2 else "donor_cell"
    ale = AleSystem(nodes, conn, [gas_row(4.4, 1000.0, 6e8), gas_row(1.4, 1.2)], np.stack([f, 1 - f], 1), rho,
                    pressure=np.stack([p, p], 1), options=AleOptions(advection=adv, interface="slic"))
    kinds = _kinds(ale.vol_m, ale.mass_m)
    assert np.sum(kinds == 0) > 50 and np.sum(kinds == 1) > 50 and np.sum(kinds < 0) > 10
    x_lag = nodes + (0.5 / 20) * rng.standard_normal(nodes.shape)
    topo = ale.topo
    n_pure = 0
    for d in range(2):
        faces = topo["faces_by_dir"][d]
        K.face_fluxes(faces, topo["face_nodes"], topo["face_elem"], topo["face_local"], topo["elem_nbr"],
                      ale.face_open, x_lag, ale.x0, ale.vol_m, ale.mass_m, ale.ener_m, ale.order, ale.iface, PHI_EPS,
                      ale._fvol, ale._fmass, ale._fener, ale._flow, False)
        out = tuple(np.zeros_like(a) for a in (ale._fvol, ale._fmass, ale._fener))
        _reference_fluxes(ale, x_lag, faces, out)
        for name, x, y in zip(("fvol", "fmass", "fener"), (ale._fvol, ale._fmass, ale._fener), out):
            np.testing.assert_array_equal(x[faces], y[faces], err_msg=f"{name}, direction {d}")
        fe = topo["face_elem"][faces]
        inner = fe[:, 1] >= 0
        n_pure += sum(pure_face(a, b, -1, ale.vol_m, ale.mass_m) >= 0 for a, b in fe[inner])
    assert n_pure > 100  # most faces lie between pure cells of one material
