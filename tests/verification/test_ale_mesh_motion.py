"""ALE mesh motion: lagrangian (no remap), smoothed with equipotential (Winslow) smoothing and
sliding boundaries; conservation through a remap onto a moving mesh.

- Equipotential relaxation: a 20 x 20 unit square whose interior is distorted by a shear
  x += 0.06 sin(pi x) sin(2 pi y) (boundary nodes uniform), gas at rest: with smoothing_weight 1
  and eulerian_pull 0, the Winslow sweeps bring the nodes to the uniform grid (the discrete
  equipotential mesh of a square with uniform boundary spacing). Measured after 100 remaps:
  largest distance from the uniform grid 0.060 -> 0.0027 (simple average: 0.0027 too; on this
  mesh the two differ little), the uniform gas state unchanged (density 1 to 8e-15).
- Sliding boundaries: the bottom side's nodes bunched towards the left (x -> x^2 along it),
  smoothing_boundary sliding: they slide along the side to uniform spacing (spread of the
  spacings 0.18 -> 7e-6 after 200 remaps), staying on the line y = 0, corners fixed.
- Moving-mesh remap conservation: two gases, random velocities, closed box, equipotential mesh
  moving every step (up to 0.04 from its start): mass per material 4e-16, total energy 1e-16,
  momentum change - wall impulse 3e-16 of the momentum scale.
- lagrangian: a two-material Sod tube (interface on an element boundary): no element changes its
  materials (fractions stay exactly 0 or 1, element masses bit-identical), the contact node at
  0.68602 against the exact 0.5 + u* t = 0.68549 (u* = 0.92745, Toro table 4.2 test 1): 0.08 %.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
from ale_cases import box_walls, gas_row, run_to, shock_tube  # noqa: E402

from sphfem_cli.ale import AleOptions, AleSystem, MeshMotion, fill_fractions  # noqa: E402
from sphfem_cli.model.mesh import box_mesh  # noqa: E402


def _smoothed(**motion) -> AleOptions:
    return AleOptions(motion=MeshMotion(mesh_motion="smoothed", **motion))


def _sheared(n: int = 20, amp: float = 0.06):
    mesh = box_mesh([0.0, 0.0], [1.0, 1.0], divisions=[n, n])
    uniform = mesh.nodes.copy()
    x = uniform.copy()
    x[:, 0] += amp * np.sin(np.pi * x[:, 0]) * np.sin(2.0 * np.pi * x[:, 1])
    return uniform, x, mesh.elements


def test_equipotential_relaxes_a_sheared_grid():
    uniform, x, conn = _sheared()
    n_elem = len(conn)
    ale = AleSystem(x, conn, [gas_row(1.4, 1.0)], np.ones((n_elem, 1)), [1.0], pressure=[1.0],
                    options=_smoothed(smoothing="equipotential", smoothing_weight=1.0, eulerian_pull=0.0))
    box_walls(ale, x, (0.0, 0.0), (1.0, 1.0))
    m0 = ale.totals()["mass"]
    d0 = np.abs(ale.x - uniform).max()
    for _ in range(100):
        ale.step(ale.stable_dt(0.5))
    d1 = np.abs(ale.x - uniform).max()
    assert d0 > 0.05 and d1 < 0.1 * d0  # at least 10x closer to the uniform grid
    np.testing.assert_allclose(ale.totals()["mass"], m0, rtol=1e-12)
    np.testing.assert_allclose(ale.mixture_density(), 1.0, rtol=1e-12)


def test_sliding_boundary_nodes_even_out_along_a_straight_side():
    n = 10
    mesh = box_mesh([0.0, 0.0], [1.0, 1.0], divisions=[n, n])
    x = mesh.nodes.copy()
    bottom = np.flatnonzero(x[:, 1] < 1e-12)
    x[bottom, 0] = x[bottom, 0] ** 2  # bunched towards the left corner
    conn = mesh.elements
    ale = AleSystem(x, conn, [gas_row(1.4, 1.0)], np.ones((len(conn), 1)), [1.0], pressure=[1.0],
                    options=_smoothed(smoothing="equipotential", smoothing_weight=1.0, eulerian_pull=0.0,
                                     smoothing_boundary="sliding"))
    box_walls(ale, x, (0.0, 0.0), (1.0, 1.0))
    m0 = ale.totals()["mass"]
    spread0 = np.ptp(np.diff(np.sort(ale.x[bottom, 0])))
    for _ in range(200):
        ale.step(ale.stable_dt(0.5))
    xb = np.sort(ale.x[bottom, 0])
    spread1 = np.ptp(np.diff(xb))
    np.testing.assert_allclose(ale.x[bottom, 1], 0.0, atol=1e-14)  # on the side's line
    assert xb[0] == 0.0 and xb[-1] == 1.0  # corners fixed
    assert spread1 < 0.1 * spread0
    np.testing.assert_allclose(ale.totals()["mass"], m0, rtol=1e-12)
    np.testing.assert_allclose(ale.mixture_density(), 1.0, rtol=1e-12)


def test_moving_mesh_remap_conserves_mass_momentum_energy():
    rng = np.random.default_rng(11)
    uniform, x, conn = _sheared(16, 0.04)
    f = fill_fractions(x, conn, lambda px, py: py < 0.4 + 0.1 * np.sin(6 * px))
    ale = AleSystem(x, conn, [gas_row(1.4, 1.0), gas_row(1.67, 0.3)], np.stack([f, 1 - f], axis=1), [1.0, 0.3],
                    pressure=[1.0, 1.0], velocity=0.3 * rng.standard_normal(x.shape),
                    options=_smoothed(smoothing="equipotential", smoothing_weight=0.5, eulerian_pull=0.0))
    box_walls(ale, x, (0.0, 0.0), (1.0, 1.0))
    t0 = ale.totals()
    for _ in range(150):
        ale.step(ale.stable_dt(0.5))
    t1 = ale.totals()
    assert np.abs(ale.x - x).max() > 0.01  # the mesh moved
    np.testing.assert_allclose(t1["mass"], t0["mass"], rtol=1e-12)
    assert abs(t1["total"] / t0["total"] - 1.0) < 1e-10
    scale = float((ale.node_mass * np.linalg.norm(ale.velocity, axis=1)).sum())
    np.testing.assert_allclose(t1["momentum"] - t0["momentum"], t1["wall_impulse"], rtol=0, atol=1e-10 * scale)


def test_lagrangian_mode_does_not_advect():
    g = gas_row(1.4, 1.0)
    ale = shock_tube(100, 1.0, 0.5, (g, 1.0, 1.0), (gas_row(1.4, 0.125), 0.125, 0.1), True,
                     AleOptions(motion=MeshMotion(mesh_motion="lagrangian")))
    fr0, m0 = ale.fractions().copy(), ale.mass_m.copy()
    assert set(np.unique(fr0)) == {0.0, 1.0}
    run_to(ale, 0.2)
    assert np.array_equal(ale.fractions(), fr0)
    assert np.array_equal(ale.mass_m, m0)
    contact = ale.x[np.abs(ale.x0[:, 0] - 0.5) < 1e-12, 0]
    exact = 0.5 + 0.92745 * 0.2
    assert np.all(np.abs(contact - exact) < 0.01 * exact)


# heavy (7 s): the tests above move and remap the mesh in the default suite
@pytest.mark.heavy
def test_straight_lines_track_a_sloshing_free_surface():
    """Smoothing "straight_lines" (the paper's nodes moving uniformly along straight lines).

    First sloshing mode of a tank L = 1 m, water depth H = 0.5 m, no void: the mesh's top side is
    the free surface. Linear theory (Lamb 1932, art. 227): eta = A cos(kx) sin(wt), k = pi/L,
    w^2 = g k tanh(kH), T = 1.1818 s, started from its velocity field
    grad[(A w/k) cos(kx) cosh(ky)/sinh(kH)] with A = 5 mm; weakly compressible water (stiffened
    gas, c = 30 m/s), hydrostatic start, slip floor and sides, 40 x 20 elements, vertical lines
    (line_axis y), eulerian_pull 0. Measured: period of the surface at the wall 1.18302 s
    (+0.10 %), amplitude 1.0099 A, mass change 0, every node still on its vertical line (x exactly
    its start) and at its initial parameter between floor and surface.
    """
    L, H, g, A, c = 1.0, 0.5, 9.81, 0.005, 30.0
    k = np.pi / L
    w = np.sqrt(g * k * np.tanh(k * H))
    period = 2.0 * np.pi / w
    gamma = 7.0
    p_inf = c * c * 1000.0 / gamma
    mesh = box_mesh([0.0, 0.0], [L, H], divisions=[40, 20])
    x, conn = mesh.nodes, mesh.elements
    p = 1000.0 * g * (H - x[conn, 1].mean(axis=1))
    rho = 1000.0 * (1.0 + p / (gamma * p_inf)) ** (1.0 / gamma)
    v = A * w / np.sinh(k * H) * np.stack([-np.sin(k * x[:, 0]) * np.cosh(k * x[:, 1]),
                                           np.cos(k * x[:, 0]) * np.sinh(k * x[:, 1])], axis=1)
    ale = AleSystem(x, conn, [gas_row(gamma, 1000.0, p_inf)], np.ones((len(conn), 1)), rho[:, None],
                    pressure=p[:, None], velocity=v,
                    options=_smoothed(smoothing="straight_lines", line_axis="y", eulerian_pull=0.0))
    ale.gravity[:] = [0.0, -g]
    ale.set_slip(np.flatnonzero(np.abs(x[:, 1]) < 1e-9), [0.0, 1.0])
    for side in (0.0, L):
        ale.set_slip(np.flatnonzero(np.abs(x[:, 0] - side) < 1e-9), [1.0, 0.0])
    corner = int(np.flatnonzero((np.abs(x[:, 0]) < 1e-9) & (np.abs(x[:, 1] - H) < 1e-9))[0])
    m0 = ale.totals()["mass"]
    t, eta = [], []
    while ale.time < 2.2 * period:
        ale.step(ale.stable_dt(0.5))
        t.append(ale.time)
        eta.append(ale.x[corner, 1] - H)
    t, eta = np.array(t), np.array(eta)
    s = np.flatnonzero((eta[:-1] > 0.0) & (eta[1:] <= 0.0))  # downward zero crossings: T/2, 3T/2
    crossings = t[s] - eta[s] * (t[s + 1] - t[s]) / (eta[s + 1] - eta[s])
    assert len(crossings) == 2
    assert abs((crossings[1] - crossings[0]) / period - 1.0) < 0.01
    assert abs(eta.max() / A - 1.0) < 0.03
    np.testing.assert_allclose(ale.totals()["mass"], m0, rtol=1e-12)
    # the nodes moved along their vertical lines only, evenly spread between floor and surface
    assert np.array_equal(ale.x[:, 0], x[:, 0])
    column = np.isclose(x[:, 0], 0.5)
    y0, y = x[column, 1], ale.x[column, 1]
    np.testing.assert_allclose(y, y0 / H * y.max(), rtol=0, atol=1e-12)
    assert ale.x[column, 1].max() != H  # the surface there did move


def test_straight_lines_need_a_structured_mesh():
    mesh = box_mesh([0.0, 0.0], [1.0, 1.0], divisions=[4, 4])
    x, conn = mesh.nodes.copy(), mesh.elements.copy()
    ale = AleSystem(x, conn, [gas_row(1.4, 1.0)], np.ones((len(conn), 1)), [1.0], pressure=[1.0],
                    options=_smoothed(smoothing="straight_lines", line_axis="x"))
    assert len(ale.mesh.lines[0]) == 5 * 3  # 5 horizontal lines, 3 inner nodes each
    try:
        AleSystem(x, conn, [gas_row(1.4, 1.0)], np.ones((len(conn), 1)), [1.0], pressure=[1.0],
                  options=_smoothed(smoothing="straight_lines", line_axis="z"))
    except ValueError as err:
        assert "line_axis z" in str(err)
    else:
        raise AssertionError("a 2D mesh has no z lines")
