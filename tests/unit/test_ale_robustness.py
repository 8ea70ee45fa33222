"""ALE robustness: nodal mass floor, pressure cut-off, mixture sound speed of mixed elements.

- A node whose remapped mass is at or below its floor gets v = 0, its momentum booked as impulse
  and its kinetic energy returned to the elements (the remap "fog" fix, docs/theory/ale.md).
- pressure_cutoff bounds every material pressure from below (cavitation, LS-DYNA *MAT_NULL PC).
- A trace of a light material with a huge sound speed does not set the element's step: the
  element's sound speed is that of the equal-strain mixture, sum M_m c_m^2 / M.
- A water slab under void, shaken with random velocities in a closed box (van Leer, SLIC): mass
  and total energy conserved, momentum equal to the wall impulse, no node faster than the start.
"""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.ale import AleOptions, AleSystem, fill_fractions
from sphfem_cli.ale import kernels as K
from sphfem_cli.deck.schema import materials as sm
from sphfem_cli.materials.tables import gas_row, pack_material
from sphfem_cli.model.mesh import box_mesh


def water_row() -> np.ndarray:
    eos = sm.Gruneisen(type="gruneisen", c=1480.0, s1=1.92, gamma0=0.28)
    return pack_material(sm.Fluid(type="fluid", density=1000.0, eos="water"), eos)[1]


def _one_quad(v_old):
    """finish_remap_nodes' topology arguments for one quad of nodes 0-3 and its velocities."""
    conn = np.array([[0, 1, 2, 3]])
    return np.asarray(v_old, dtype=float), conn, np.arange(5), np.arange(4)


def test_finish_remap_nodes_mass_floor():
    mnode = np.array([1e-58, 2.0, 0.0, 1.0])
    pnode = np.array([[1e-51, -3e-52], [4.0, 2.0], [1e-30, 0.0], [0.0, 0.0]])
    knode = np.array([1e-44, 5.0, 0.0, 0.0])
    floor = np.full(4, 1e-6)
    v = np.zeros((4, 2))
    impulse = np.zeros((4, 2))
    dissip = np.zeros(4)
    bc = np.zeros(4, dtype=np.int64)
    v_old, conn, ptr, idx = _one_quad([[0.0, 0.0], [2.0, 1.0], [0.0, 0.0], [0.0, 0.0]])
    K.finish_remap_nodes(mnode, pnode, knode, floor, v_old, conn, ptr, idx, bc, np.zeros((4, 2)), v, impulse, dissip,
                         np.zeros((1, 2, 2)), False)  # the corners scanned
    np.testing.assert_array_equal(v[0], 0.0)  # would be 1e7 m/s from p / m
    np.testing.assert_allclose(impulse[0], -pnode[0], rtol=1e-12)  # its momentum booked
    np.testing.assert_array_equal(impulse[2], -pnode[2])
    assert dissip[0] == knode[0]  # its kinetic energy goes back to the elements
    np.testing.assert_allclose(v[1], [2.0, 1.0])
    np.testing.assert_array_equal(impulse[1], 0.0)
    assert dissip[1] == pytest.approx(0.0, abs=1e-15)


def test_finish_remap_nodes_bounds_a_light_node_by_its_neighbours():
    # node 0 holds 1e-9 of its neighbours' mass, above the floor, and a momentum from another
    # stencil: p / m = 2.4e4 m/s where no neighbour moved faster than 10 m/s (the measured fog node)
    mnode = np.array([2.4e-11, 1.0, 1.0, 1.0])
    pnode = np.array([[-5.7e-7, 1.0e-7], [10.0, 1.0], [-3.0, 2.0], [1.0, -1.0]])
    knode = np.array([1.2e-9, 50.5, 6.5, 1.0])
    floor = np.full(4, 1e-12)
    v = np.zeros((4, 2))
    impulse = np.zeros((4, 2))
    dissip = np.zeros(4)
    bc = np.zeros(4, dtype=np.int64)
    v_old, conn, ptr, idx = _one_quad([[0.5, 0.5], [10.0, 1.0], [-3.0, 2.0], [1.0, -1.0]])
    K.finish_remap_nodes(mnode, pnode, knode, floor, v_old, conn, ptr, idx, bc, np.zeros((4, 2)), v, impulse, dissip,
                         np.zeros((1, 2, 2)), True)  # the element's range row
    np.testing.assert_allclose(v[0], [-3.0, 2.0])  # p / m = (-23750, 4167), held to [-3, 10] x [-1, 2]
    np.testing.assert_allclose(impulse[0], mnode[0] * (v[0] - pnode[0] / mnode[0]), rtol=1e-12)
    assert dissip[0] == pytest.approx(knode[0] - 0.5 * mnode[0] * 13.0)  # no kinetic energy made
    np.testing.assert_allclose(v[1:], pnode[1:])  # within the bounds: p / m unchanged
    np.testing.assert_array_equal(impulse[1:], 0.0)


def _water_elements(rho, **kw):
    mesh = box_mesh([0.0, 0.0], [0.02, 0.01], divisions=[2, 1])
    return AleSystem(mesh.nodes, mesh.elements, [water_row()], np.ones((2, 1)), [rho], energy=[0.0], options=AleOptions(**kw))


def test_pressure_cutoff():
    free = _water_elements(990.0)
    p_eos = free.pressure()[0, 0]
    assert p_eos < -1e7  # Gruneisen water stretched by 1 %: about -22 MPa
    cut = _water_elements(990.0, pressure_cutoff=-1e5)
    np.testing.assert_array_equal(cut.pressure()[:, 0], -1e5)
    np.testing.assert_allclose(cut.bulk_m, free.bulk_m)  # the stiffness (and the step) unchanged
    squeezed = _water_elements(1010.0, pressure_cutoff=-1e5)
    assert squeezed.pressure()[0, 0] == pytest.approx(_water_elements(1010.0).pressure()[0, 0])


def test_trace_of_fast_material_does_not_set_the_step():
    mesh = box_mesh([0.0, 0.0], [0.01, 0.01], divisions=[1, 1])
    gas = gas_row(1.4, 1.0)
    rho = [1000.0, 1e-7]
    e = [0.0, 1e10]  # a stretched, hot trace: c = sqrt(gamma (gamma - 1) e) = 7.5e4 m/s
    mixed = AleSystem(mesh.nodes, mesh.elements, [water_row(), gas], np.array([[0.99, 0.01]]), rho, energy=e)
    pure = AleSystem(mesh.nodes, mesh.elements, [water_row()], np.ones((1, 1)), [1000.0], energy=[0.0])
    c_gas = np.sqrt(1.4 * 0.4 * 1e10)
    assert mixed.stable_dt(1.0) == pytest.approx(pure.stable_dt(1.0), rel=1e-6)
    assert mixed.stable_dt(1.0) > 20.0 * 0.01 / c_gas  # the gas's own step would be 50 x smaller
    # the mixture speed is the mass-weighted mean of c^2
    c_mix = np.sqrt((mixed.mass_m[0] * np.array([1480.0, c_gas]) ** 2).sum() / mixed.mass_m[0].sum())
    assert c_mix == pytest.approx(1480.0, rel=1e-6)


def test_water_under_void_shaken_in_a_closed_box():
    mesh = box_mesh([0.0, 0.0], [0.2, 0.2], divisions=[20, 20])
    nodes, conn = mesh.nodes, mesh.elements
    f = fill_fractions(nodes, conn, lambda x, y: y < 0.1 + 0.03 * np.sin(20 * x))
    rng = np.random.default_rng(3)
    ale = AleSystem(nodes, conn, [water_row(), None], np.stack([f, 1 - f], axis=1), [1000.0, 0.0],
                    energy=[0.0, 0.0], velocity=5.0 * rng.standard_normal(nodes.shape),
                    options=AleOptions(pressure_cutoff=-1e5))
    x = nodes
    ale.set_slip(np.flatnonzero((x[:, 0] == 0.0) | (x[:, 0] == 0.2)), (1.0, 0.0))
    ale.set_slip(np.flatnonzero((x[:, 1] == 0.0) | (x[:, 1] == 0.2)), (0.0, 1.0))
    t0 = ale.totals()
    v_start = np.abs(ale.velocity).max()
    for _ in range(300):
        ale.step(ale.stable_dt(0.5))
        assert np.abs(ale.velocity).max() <= v_start
    t1 = ale.totals()
    np.testing.assert_allclose(t1["mass"][0], t0["mass"][0], rtol=1e-12)
    assert t1["total"] == pytest.approx(t0["total"], rel=1e-10)
    np.testing.assert_allclose(t1["momentum"] - t0["momentum"], t1["wall_impulse"], atol=1e-10 * t0["mass"][0] * v_start)
