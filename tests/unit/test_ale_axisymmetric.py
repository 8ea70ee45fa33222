"""ALE in r-z (ale/axisymmetric.py): ring volumes and their gradient, swept ring volumes, conservation in a
closed axisymmetric box, a uniform state at rest, the axis, and an axisymmetric ALE deck end to end."""
from __future__ import annotations

import numpy as np
import pytest

from sphfem_cli.ale import AleOptions, AleSystem, build_topology, fill_fractions
from sphfem_cli.ale import axisymmetric as A
from sphfem_cli.ale import kernels as K
from sphfem_cli.ale.options import MeshMotion
from sphfem_cli.materials.tables import gas_row
from sphfem_cli.model.mesh import box_mesh
from sphfem_cli.summary import part_masses


def _ring_volumes(x, conn):
    out = np.empty(len(conn))
    A.ring_volumes(x, conn, out)
    return out


def test_ring_volume_of_an_annulus_is_exact():
    """A box r in [r1, r2], z in [z1, z2] sweeps pi (r2^2 - r1^2)(z2 - z1); its elements add up to it."""
    mesh = box_mesh([0.3, -0.2], [1.1, 0.5], divisions=[5, 3])
    vol = _ring_volumes(mesh.nodes, mesh.elements)
    assert vol.sum() == pytest.approx(np.pi * (1.1 ** 2 - 0.3 ** 2) * 0.7, rel=1e-14)
    assert (vol > 0).all()


def test_fill_fractions_of_a_ring_are_shares_of_its_volume():
    """r < 0.5 in the element r, z in [0, 1]: a quarter of the ring's volume (0.5^2), half its meridian
    area; with 2 x 2 sample points the region is two whole sub-cells, so both are exact."""
    mesh = box_mesh([0.0, 0.0], [1.0, 1.0], divisions=[1, 1])
    inside = lambda x, y: x < 0.5  # noqa: E731
    assert fill_fractions(mesh.nodes, mesh.elements, inside, samples=2, ring=True)[0] == pytest.approx(0.25, rel=1e-14)
    assert fill_fractions(mesh.nodes, mesh.elements, inside, samples=2)[0] == pytest.approx(0.5, rel=1e-14)
    # a sphere of radius R on the axis, filled on a 2 x 4 mesh of R/2: within 5 % of 4/3 pi R^3 by volume
    mesh = box_mesh([0.0, -1.0], [1.0, 1.0], divisions=[2, 4])
    ball = lambda x, y: x * x + y * y < 1.0  # noqa: E731
    vol = _ring_volumes(mesh.nodes, mesh.elements)
    by_volume = (fill_fractions(mesh.nodes, mesh.elements, ball, ring=True) * vol).sum()
    by_area = (fill_fractions(mesh.nodes, mesh.elements, ball) * vol).sum()
    exact = 4.0 / 3.0 * np.pi
    assert abs(by_volume / exact - 1.0) < abs(by_area / exact - 1.0)
    assert by_volume == pytest.approx(exact, rel=0.05)


def _ring_block(x, v=None):
    """``ring_block`` on one quad with corners x (4, 2) (velocities v, 0 if None): its gradient (2, 4), ring volume
    and divergence; the plane gradient rows of st left 0 (only |b|^2 reads them)."""
    from sphfem_cli.ale.force_lanes import _CX_U, _CX_W, _CX_X, _CX_Y, _ST_BLOCK, _ST_ROWS

    v = np.zeros((4, 2)) if v is None else v
    cx = np.zeros(16 * _ST_BLOCK)
    for row, column in ((_CX_X, x[:, 0]), (_CX_Y, x[:, 1]), (_CX_U, v[:, 0]), (_CX_W, v[:, 1])):
        cx[(row + np.arange(4)) * _ST_BLOCK] = column
    rg = np.zeros(A._RG_ROWS * _ST_BLOCK)
    A.ring_block(1, cx, np.zeros(_ST_ROWS * _ST_BLOCK), rg)
    g = rg[(A._RG_G + np.arange(8)) * _ST_BLOCK].reshape(2, 4)
    return g, rg[A._RG_VOL * _ST_BLOCK], rg[A._RG_TRACE * _ST_BLOCK]


def test_ring_gradient_is_the_derivative_of_the_ring_volume():
    """dV/dx_a of the force kernel's ring pass (``ring_block``) against central differences of the ring volume
    (h = 1e-6; observed 3e-10 absolute), and its divergence sum_a v_a . dV/dx_a / V for a rigid axial translation
    (0) and a uniform radial expansion v_r = a r (dV/dt / V = 2a: exact, the ring's hoop rate included)."""
    rng = np.random.default_rng(0)
    x = np.array([[0.1, 0.0], [1.0, 0.1], [1.2, 0.9], [0.0, 1.0]]) + 0.05 * rng.random((4, 2))
    g, vol, _ = _ring_block(x)
    fd = np.zeros((2, 4))
    for a in range(4):
        for k in range(2):
            xp, xm = x.copy(), x.copy()
            xp[a, k] += 1e-6
            xm[a, k] -= 1e-6
            fd[k, a] = (_ring_volumes(xp, np.array([[0, 1, 2, 3]]))[0] - _ring_volumes(xm, np.array([[0, 1, 2, 3]]))[0]) / 2e-6
    np.testing.assert_allclose(g, fd, atol=1e-8)
    assert vol == pytest.approx(_ring_volumes(x, np.array([[0, 1, 2, 3]]))[0], rel=1e-15)
    assert abs(_ring_block(x, np.tile([0.0, 3.0], (4, 1)))[2]) < 1e-14
    assert _ring_block(x, np.column_stack([0.7 * x[:, 0], np.zeros(4)]))[2] == pytest.approx(1.4, rel=1e-12)
    assert abs(g[1].sum()) < 1e-14 * abs(g[1]).max()  # a translation along the axis keeps V


def test_swept_ring_volumes_close_the_element_volume_change():
    """V_new - V_lag = the sum of the ring volumes the element's faces sweep (Green's theorem)."""
    mesh = box_mesh([0.0, 0.0], [1.0, 1.0], divisions=[3, 3])
    nodes, conn = mesh.nodes, mesh.elements
    topo = build_topology(conn, len(nodes))
    rng = np.random.default_rng(1)
    x_lag = nodes + 0.05 * rng.standard_normal(nodes.shape)
    x_new = nodes + 0.05 * rng.standard_normal(nodes.shape)
    x_lag[:, 0] = np.abs(x_lag[:, 0])
    x_new[:, 0] = np.abs(x_new[:, 0])
    n0, n1 = topo["face_nodes"].T
    dv = A.quad_ring_volumes(x_lag[n0], x_new[n0], x_new[n1], x_lag[n1])
    gain = (dv[topo["elem_face"]] * topo["elem_sign"]).sum(axis=1)
    np.testing.assert_allclose(_ring_volumes(x_lag, conn) + gain, _ring_volumes(x_new, conn), rtol=1e-13, atol=1e-15)


def _closed_box(n=10, motion="eulerian", seed=0, two_materials=False):
    """A gas in the closed box r, z in [0, 1]: the axis, slip walls, a hot ring (of a second, lighter gas
    with two_materials: SLIC interfaces, pressure relaxation), random velocities. motion: a mesh_motion,
    or "smoothed <smoothing> <smoothing_boundary>" (no pull back, so the mesh moves freely)."""
    rng = np.random.default_rng(seed)
    mesh_motion, *smoothing = motion.split()
    motion = MeshMotion(mesh_motion=mesh_motion, **(dict(zip(("smoothing", "smoothing_boundary"), smoothing),
                                                        eulerian_pull=0.0) if smoothing else {}))
    mesh = box_mesh([0.0, 0.0], [1.0, 1.0], divisions=[n, n])
    nodes, conn = mesh.nodes.copy(), mesh.elements
    hot = fill_fractions(nodes, conn, lambda r, z: (r - 0.4) ** 2 + (z - 0.5) ** 2 < 0.09)
    velocity = 0.2 * rng.standard_normal(nodes.shape)
    if two_materials:
        ale = AleSystem(nodes, conn, [gas_row(1.4, 1.0), gas_row(5.0 / 3.0, 0.2)], np.stack([1.0 - hot, hot], axis=1),
                        [1.0, 0.2], pressure=[1.0, 5.0], velocity=velocity,
                        options=AleOptions(interface="slic", closure="relax", motion=motion),
                        axisymmetric=True)
    else:
        ale = AleSystem(nodes, conn, [gas_row(1.4, 1.0)], np.ones((len(conn), 1)), [1.0],
                        pressure=1.0 + 4.0 * hot[:, None], velocity=velocity,
                        options=AleOptions(motion=motion), axisymmetric=True)
    ale.set_slip(np.flatnonzero(nodes[:, 1] == 0.0), (0.0, 1.0))
    ale.set_slip(np.flatnonzero(nodes[:, 1] == 1.0), (0.0, 1.0))
    ale.set_slip(np.flatnonzero(nodes[:, 0] == 1.0), (1.0, 0.0))
    return ale


@pytest.mark.parametrize("motion, two_materials", [
    ("eulerian", False), ("lagrangian", False), ("eulerian", True), ("smoothed average fixed", True),
    ("smoothed equipotential sliding", True), ("smoothed average sliding", False)])
def test_closed_box_conserves_mass_axial_momentum_and_energy(motion, two_materials):
    """100 steps (van Leer, DeBar fix): mass (per material) to 1e-14 relative, axial momentum minus the
    wall impulse to 1e-14 of the momentum scale (sum m |v|), total energy to 1e-13 relative; observed
    1e-16 to 3e-15. A smoothed mesh is the plane smoothing of the meridian plane, remapped by swept ring
    volumes: the same figures (mass 1e-16 to 3e-16, axial momentum 3e-17 to 4e-16, energy 0 to 2e-16; the
    element volumes those of the moved mesh to 1.2e-15); its axis nodes stay at r = 0 exactly (sliding:
    they move along the axis, up to 0.045)."""
    ale = _closed_box(motion=motion, two_materials=two_materials)
    axis = np.flatnonzero(ale.x0[:, 0] == 0.0)
    assert (ale.bc_type[axis] != K.BC_FREE).all() and (ale.velocity[axis, 0] == 0.0).all()
    start = ale.totals()
    scale = float((ale.node_mass * np.abs(ale.velocity).sum(axis=1)).sum())
    for _ in range(100):
        ale.step(ale.stable_dt(0.5))
    end = ale.totals()
    np.testing.assert_allclose(end["mass"], start["mass"], rtol=1e-14)
    assert abs(end["momentum"][1] - start["momentum"][1] - end["wall_impulse"][1]) < 1e-14 * scale
    assert end["total"] == pytest.approx(start["total"], rel=1e-13)
    assert end["kinetic"] != pytest.approx(start["kinetic"], rel=1e-3)  # the flow did move energy around
    assert (ale.x[axis, 0] == 0.0).all() and (ale.x[:, 0] >= 0.0).all()  # nothing crosses the axis
    if "sliding" in motion:
        assert np.abs(ale.x[axis, 1] - ale.x0[axis, 1]).max() > 0.01  # the axis nodes slid along it
    if "smoothed" in motion:
        assert np.abs(ale.x - ale.x0).max() > 0.005
        np.testing.assert_allclose(ale.vol_m.sum(axis=1), _ring_volumes(ale.x, ale.conn), rtol=1e-12)


def test_uniform_state_at_rest_stays_at_rest():
    """Uniform pressure in the closed box: the ring forces of the elements around an interior node
    cancel (d(sum V)/dx = 0), walls and axis take the rest; 50 steps leave v below 1e-13."""
    mesh = box_mesh([0.0, 0.0], [1.0, 1.0], divisions=[6, 5])
    nodes = mesh.nodes.copy()
    nodes[:, 0] = nodes[:, 0] ** 1.5  # graded towards the axis
    ale = AleSystem(nodes, mesh.elements, [gas_row(1.4, 1.0)], np.ones((len(mesh.elements), 1)), [1.0],
                    pressure=[1.0], axisymmetric=True)
    ale.set_slip(np.flatnonzero(nodes[:, 1] == 0.0), (0.0, 1.0))
    ale.set_slip(np.flatnonzero(nodes[:, 1] == 1.0), (0.0, 1.0))
    ale.set_slip(np.flatnonzero(nodes[:, 0] == 1.0), (1.0, 0.0))
    for _ in range(50):
        ale.step(ale.stable_dt(0.5))
    assert np.abs(ale.velocity).max() < 1e-13
    np.testing.assert_allclose(ale.pressure(mixture=True), 1.0, rtol=1e-12)


def test_axisymmetric_system_refuses_what_it_cannot_hold():
    mesh = box_mesh([-0.1, 0.0], [1.0, 1.0], divisions=[2, 2])
    with pytest.raises(ValueError, match="x = r >= 0"):
        AleSystem(mesh.nodes, mesh.elements, [gas_row(1.4, 1.0)], np.ones((4, 1)), [1.0], pressure=[1.0],
                  axisymmetric=True)


DECK = """
title: axisymmetric ALE, a gas ring expanding in a closed can
dimension: axisymmetric
control: {end_time: 2.0e-3}
equations_of_state:
  air: {type: ideal_gas, gamma: 1.4}
materials:
  air: {type: fluid, density: 1.0, eos: air}
sections:
  ale: {type: ale_multi_material}
parts:
  can:
    material: air
    section: ale
    geometry: {box: {min: [0.0, 0.0], max: [1.0, 1.0], divisions: [10, 10]}}
    fill:
      - {material: air, box: {min: [0.0, 0.0], max: [1.0, 1.0]}, pressure: 1.0e5}
      - {material: air, box: {min: [0.0, 0.3], max: [0.4, 0.7]}, pressure: 5.0e5}
boundaries:
  - {type: ale_boundary, part: can, sides: [right, bottom, top], condition: slip}
"""


@pytest.mark.parametrize("section", ["{type: ale_multi_material}",
                                     "{type: ale_multi_material, mesh_motion: smoothed, smoothing: equipotential, "
                                     "smoothing_boundary: sliding, eulerian_pull: 0.0}"], ids=["eulerian", "smoothed"])
def test_axisymmetric_ale_deck_runs_and_balances_energy(sim_from_deck, section):
    """The deck path: the ALE part on rings (axis nodes slip along it), energy for the full 2 pi; a
    smoothed mesh too (its axis nodes slide along the axis, at r = 0 exactly)."""
    sim = sim_from_deck(DECK.replace("{type: ale_multi_material}", section))
    sim.run()
    ale = next(d for d in sim.domains if d.kind == "ale").system
    axis = np.flatnonzero(ale.x0[:, 0] == 0.0)
    assert (ale.x[axis, 0] == 0.0).all()
    assert (np.abs(ale.x - ale.x0).max() > 1e-3) == ("smoothed" in section)
    assert ale.axisymmetric
    assert ale.mass_m.sum() == pytest.approx(np.pi * 1.0, rel=1e-12)  # rho V = 1 * pi r^2 h
    assert part_masses(sim.model)[0] == pytest.approx(np.pi, rel=1e-12)  # what `sphfem check` prints
    axis = np.flatnonzero(ale.x0[:, 0] == 0.0)
    assert (ale.velocity[axis, 0] == 0.0).all() and np.abs(ale.velocity).max() > 1.0
    # the hot ring fills whole elements: internal energy at the start sum p V / (gamma - 1) exactly
    start = (1.0e5 * np.pi + 4.0e5 * np.pi * 0.4 ** 2 * 0.4) / 0.4
    energies = ale.totals()
    assert energies["kinetic"] > 1e-3 * start
    assert energies["total"] == pytest.approx(start, rel=1e-12)
