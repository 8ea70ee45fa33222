"""The one-material face fluxes (ale/face_lanes.py, blocks of faces together) give the scalar flux's bits.

One gas takes ``face_lanes.face_block`` in ``remap.face_fluxes``; the same gas as the first of two
materials, the second absent everywhere (volume fraction 0), takes the scalar ``remap._face_flux``, whose
SLIC finds no interface (one material present: g_max - g_min = 0) and whose sums over the second material
add nothing. The volume, mass and energy fluxes of every face must agree to the bit (assert_array_equal)
at order 1 and 2, on a mesh whose Lagrangian position is displaced by up to about a cell (so that some
faces sweep more than their donor holds), with a transmitting side (outflow and inflow faces), an empty
element (no mass) and elements of negative internal energy (the cap dE <= E_d applies only where E_d > 0).
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.ale import AleOptions, AleSystem
from sphfem_cli.ale import kernels as K
from sphfem_cli.materials.tables import gas_row
from sphfem_cli.model.mesh import box_mesh


def _pair(seed, order):
    """(one-material system, two-material system whose second material is absent), the same state."""
    rng = np.random.default_rng(seed)
    mesh = box_mesh([0.0, 0.0], [1.0, 1.0], divisions=[17, 11])  # 17 x 12 + 18 x 11 faces: blocks of 128 and rests
    nodes, conn = mesh.nodes, mesh.elements
    n_elem = len(conn)
    rho = 1.0 + 0.5 * rng.random(n_elem)
    p = 1.0 + rng.random(n_elem)
    adv = "van_leer" if order == 2 else "donor_cell"
    one = AleSystem(nodes, conn, [gas_row(1.4, 1.0)], np.ones((n_elem, 1)), rho[:, None], pressure=p[:, None],
                    options=AleOptions(advection=adv))
    two = AleSystem(nodes, conn, [gas_row(1.4, 1.0), gas_row(4.4, 2.0, 0.5)],
                    np.stack([np.ones(n_elem), np.zeros(n_elem)], 1), np.stack([rho, np.ones(n_elem)], 1),
                    pressure=np.stack([p, p], 1), options=AleOptions(advection=adv, interface="slic"))
    left = np.flatnonzero(nodes[:, 0] == 0.0)
    for ale in (one, two):
        ale.set_transmit(left)
        ale.mass_m[5, 0] = 0.0  # an empty element
        ale.ener_m[5, 0] = 0.0
        ale.ener_m[40:60, 0] *= -1.0  # negative internal energy
    x_lag = nodes + (0.7 / 17) * rng.standard_normal(nodes.shape)
    return one, two, x_lag


def _fluxes(ale, x_lag):
    topo = ale.topo
    out = []
    for d in range(2):
        K.face_fluxes(topo["faces_by_dir"][d], topo["face_nodes"], topo["face_elem"], topo["face_local"],
                      topo["elem_nbr"], ale.face_open, x_lag, ale.x0, ale.vol_m, ale.mass_m, ale.ener_m, ale.order,
                      ale.iface, ale.options.phi_eps, ale._fvol, ale._fmass, ale._fener, ale._flow, False)
        out.append((ale._fvol.copy(), ale._fmass.copy(), ale._fener.copy(), ale._flow.copy()))
    return out


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("seed", [0, 1])
def test_one_material_face_block_gives_the_scalar_flux(order, seed):
    one, two, x_lag = _pair(seed, order)
    assert one.order == two.order == order
    for (v1, m1, e1, f1), (v2, m2, e2, f2) in zip(_fluxes(one, x_lag), _fluxes(two, x_lag)):
        np.testing.assert_array_equal(f1, f2)
        assert f1.sum() > 100  # most faces sweep volume
        for a, b in ((v1, v2), (m1, m2), (e1, e2)):
            np.testing.assert_array_equal(a[:, 0], b[:, 0])
            np.testing.assert_array_equal(b[:, 1], 0.0)
        # the cases the block selects between are all present
        assert np.any(one.face_open)
        fe = one.topo["face_elem"]
        vd = one.vol_m[:, 0]
        owner, other = vd[fe[:, 0]], np.where(fe[:, 1] >= 0, vd[np.maximum(fe[:, 1], 0)], np.nan)
        assert np.any(f1 & ((np.abs(v1[:, 0]) == owner) | (np.abs(v1[:, 0]) == other)))  # a donor emptied (dV = V_d)


def test_hex8_faces_that_have_not_moved_sweep_nothing():
    """hex8 face sweep (``remap.face_fluxes``): a face whose four nodes have x_lag = x_new sweeps no volume (flow
    False, zero fluxes) without computing its swept volume; every face that moved has flow exactly where
    ``swept_volume_3d`` (the per-face formula) is non-zero. On this skewed mesh the formula itself leaves a
    round-off volume on some faces that have not moved (the reason the sweep does not evaluate it there), below
    1e-12 of a cell's volume."""
    rng = np.random.default_rng(3)
    mesh = box_mesh([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], divisions=[7, 6, 5])  # faces per direction: blocks and rests
    nodes = mesh.nodes.copy()
    inner = np.all((nodes > 0.0) & (nodes < 1.0), axis=1)
    nodes[inner] += 0.03 * rng.standard_normal((inner.sum(), 3))  # skewed faces, positive volumes
    n_elem = len(mesh.elements)
    ale = AleSystem(nodes, mesh.elements, [gas_row(1.4, 1.0)], np.ones((n_elem, 1)), 1.0 + rng.random((n_elem, 1)),
                    pressure=np.ones((n_elem, 1)), options=AleOptions(advection="van_leer"))
    moved = rng.random(len(nodes)) < 0.3
    x_lag = ale.x0.copy()
    x_lag[moved] += 0.01 * rng.standard_normal((moved.sum(), 3))
    topo = ale.topo
    static_round_off = 0
    for d in range(3):
        faces = topo["faces_by_dir"][d]
        K.face_fluxes(faces, topo["face_nodes"], topo["face_elem"], topo["face_local"], topo["elem_nbr"],
                      ale.face_open, x_lag, ale.x0, ale.vol_m, ale.mass_m, ale.ener_m, ale.order, ale.iface,
                      ale.options.phi_eps, ale._fvol, ale._fmass, ale._fener, ale._flow, False)
        dv = np.empty(len(faces))
        K.swept_volumes_3d(faces, topo["face_nodes"], x_lag, ale.x0, dv)
        still = ~moved[topo["face_nodes"][faces]].any(axis=1)
        interior = topo["face_elem"][faces, 1] >= 0
        flow = ale._flow[faces]
        assert not flow[still].any()
        for a in (ale._fvol, ale._fmass, ale._fener):
            np.testing.assert_array_equal(a[faces[still]], 0.0)
        np.testing.assert_array_equal(flow[~still & interior], dv[~still & interior] != 0.0)
        assert (~still & interior).sum() > 50 and (still & interior).sum() > 10
        assert np.all(np.abs(dv[still]) < 1e-12 * ale.vol0.min())
        static_round_off += np.count_nonzero(dv[still & interior])
    assert static_round_off > 0  # the formula's round-off on faces that have not moved, which the sweep does not make
