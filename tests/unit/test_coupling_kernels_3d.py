"""3D kernels of the ALE -> structure coupling (contact.coupling_kernels_3d, hex8 ALE against quad faces).

locate: natural coordinates round-trip through the buckets on a distorted hex8 mesh; face points:
the area shares of a face sum to its area (exact on a plane face) and reduce to the 2D kernel's
points on an extruded face; fluid-side depth: the volume cut off by the interface plane against the
exact volume of a cube cut by a plane, and the 2D kernel on an extruded quad.
"""
from __future__ import annotations

import itertools

import numpy as np
import pytest

from sphfem_cli.contact import coupling_common as cc
from sphfem_cli.contact import coupling_search as cs
from sphfem_cli.contact import coupling_kernels_3d as ck3

CORNERS = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                    [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)


def _shape(nat):
    return np.prod(1.0 + CORNERS * np.asarray(nat, dtype=float), axis=1) / 8.0


def _distorted_mesh(n=3, seed=0):
    """n^3 hex8 elements on [0, 1]^3, every node but the box's corners moved by up to 0.15 h."""
    rng = np.random.default_rng(seed)
    g = np.linspace(0.0, 1.0, n + 1)
    nodes = np.array([[x, y, z] for z in g for y in g for x in g])
    idx = lambda i, j, k: i + (n + 1) * (j + (n + 1) * k)  # noqa: E731
    conn = np.array([[idx(i + a, j + b, k + c) for a, b, c in
                      [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]]
                     for k in range(n) for j in range(n) for i in range(n)], dtype=np.int64)
    interior = np.all((nodes > 0.0) & (nodes < 1.0), axis=1)
    nodes[interior] += 0.15 / n * rng.uniform(-1.0, 1.0, (interior.sum(), 3))
    return nodes, conn


def test_locate_round_trips_natural_coordinates_on_a_distorted_hex_mesh():
    nodes, conn = _distorted_mesh()
    cell = float(np.cbrt(1.0 / len(conn)))
    lo = nodes.min(axis=0) - cell
    nb = np.ceil((nodes.max(axis=0) + cell - lo) / cell).astype(np.int64)
    start, items = ck3.build_bins_3d(nodes, conn, lo, cell, int(nb[0]), int(nb[1]), int(nb[2]))
    rng = np.random.default_rng(1)
    worst = 0.0
    for e in range(len(conn)):
        for nat in rng.uniform(-0.9, 0.9, (4, 3)):
            p = _shape(nat) @ nodes[conn[e]]
            found, *back = cs.locate_3d(nodes, conn, start, items, lo, cell, int(nb[0]), int(nb[1]), int(nb[2]), *p)
            assert found == e
            worst = max(worst, float(np.abs(np.array(back) - nat).max()))
    assert worst < 1e-10  # measured 2.3e-15
    outside = cs.locate_3d(nodes, conn, start, items, lo, cell, int(nb[0]), int(nb[1]), int(nb[2]), 0.5, 0.5, 1.2)
    assert outside[0] == -1


def _points(xs, nquad):
    f = np.arange(4, dtype=np.int64)
    return [ck3.face_point(xs, f, nquad, i, j) for i in range(nquad) for j in range(nquad)]


@pytest.mark.parametrize("nquad", [1, 2, 3, 4])
def test_area_shares_sum_to_a_plane_face_area(nquad):
    """A distorted quad in a tilted plane: shares sum to its shoelace area, normals are the plane's."""
    flat = np.array([[0.0, 0.0], [1.3, 0.1], [1.1, 0.9], [-0.2, 1.2]])
    area = 0.5 * abs(sum(flat[k, 0] * flat[(k + 1) % 4, 1] - flat[(k + 1) % 4, 0] * flat[k, 1] for k in range(4)))
    u = np.array([1.0, 2.0, 0.5]) / np.linalg.norm([1.0, 2.0, 0.5])
    v = np.cross(u, [0.0, 0.0, 1.0])
    v /= np.linalg.norm(v)
    xs = flat[:, :1] * u + flat[:, 1:] * v + np.array([0.3, -0.2, 0.7])
    pts = _points(xs, nquad)
    assert abs(sum(p[3] for p in pts) / area - 1.0) < 1e-13
    normal = np.cross(u, v)
    for w, x, n, _ in pts:
        assert abs(w.sum() - 1.0) < 1e-14
        np.testing.assert_allclose(x, w @ xs, atol=1e-14)
        np.testing.assert_allclose(n, normal, atol=1e-13)


def test_area_shares_of_a_warped_face_converge_to_its_area():
    """A warped face (one corner lifted): the shares' sum converges to the bilinear surface's area."""
    xs = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.4], [0.0, 1.0, 0.0]])
    r, w = np.polynomial.legendre.leggauss(40)  # the area by a 40 x 40 Gauss rule
    exact = 0.0
    for (ri, wi), (sj, wj) in itertools.product(zip(r, w), zip(r, w)):
        xr, xq = ck3._face_tangents(xs, np.arange(4, dtype=np.int64), ri, sj)
        exact += wi * wj * np.linalg.norm(np.cross(xr, xq))
    errors = [abs(sum(p[3] for p in _points(xs, nq)) / exact - 1.0) for nq in (1, 2, 4)]
    assert errors[0] < 1e-4 and errors[2] < errors[1] < errors[0]  # measured 2.3e-5, 1.4e-6, 8.6e-8


def test_face_points_on_an_extruded_face_are_the_2d_points():
    """A face extruded from the 2D segment (a, b) along z: the point rows are the 2D kernel's
    points r_q = -1 + (2q + 1) / nquad, each carrying (L / nquad) (depth / nquad), normal (t_y, -t_x)."""
    a, b, depth, nquad = np.array([0.2, 0.1]), np.array([0.5, 0.5]), 0.3, 3
    # right-hand rule: (x_b - x_a) x (x_d - x_a) = depth (t_y, -t_x, 0) for d = a + depth e_z
    xs = np.array([[*a, 0.0], [*b, 0.0], [*b, depth], [*a, depth]])
    length = np.linalg.norm(b - a)
    normal = np.array([(b - a)[1], -(b - a)[0], 0.0]) / length
    for (i, j), (w, x, n, share) in zip(itertools.product(range(nquad), range(nquad)), _points(xs, nquad)):
        r = -1.0 + (2.0 * i + 1.0) / nquad
        np.testing.assert_allclose(x[:2], 0.5 * (1 - r) * a + 0.5 * (1 + r) * b, atol=1e-15)
        np.testing.assert_allclose(n, normal, atol=1e-15)
        assert abs(share - length * depth / nquad ** 2) < 1e-15


def _cube_volume_beyond(n, level):
    """Volume of [0, 1]^3 where x . n > level (n > 0 componentwise): inclusion-exclusion over the corners."""
    total = 0.0
    for v in itertools.product((0.0, 1.0), repeat=3):
        total += (-1) ** int(sum(v)) * max(level - float(np.dot(n, v)), 0.0) ** 3  # volume below
    return 1.0 - total / (6.0 * n[0] * n[1] * n[2])


@pytest.mark.parametrize("fraction", [0.05, 0.3, 0.5, 0.8, 0.97])
def test_fluid_side_depth_cuts_off_the_fraction_of_a_rotated_cube(fraction):
    """A unit cube, rotated and moved, with an oblique normal: the plane p . n = p . n - depth cuts off
    the fraction's volume, checked against the exact cut of the cube."""
    rng = np.random.default_rng(2)
    rot, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    shift = np.array([0.4, -1.0, 2.0])
    cube = (CORNERS + 1.0) / 2.0
    nodes = cube @ rot.T + shift
    conn = np.arange(8, dtype=np.int64)[None, :]
    n_cube = np.array([0.3, 0.5, 0.81])
    n_cube /= np.linalg.norm(n_cube)
    n = rot @ n_cube
    p = np.array([0.6, 0.2, 0.4]) @ rot.T + shift
    depth = cc.fluid_side_depth_3d(nodes, conn, 0, *p, *n, fraction)
    level = float(p @ n) - depth - float(shift @ n)  # the interface in the cube's frame
    assert abs(_cube_volume_beyond(n_cube, level) - fraction) < 1e-10
    assert abs(cc.hex_volume_beyond(nodes, *n, level + float(shift @ n)) - fraction) < 1e-10


def test_fluid_side_depth_of_an_extruded_quad_is_the_2d_depth():
    """A distorted quad extruded along z, normal in its plane: the 3D depth is the 2D kernel's."""
    quad = np.array([[0.0, 0.0], [1.1, 0.2], [0.9, 1.0], [-0.1, 0.8]])
    nodes = np.vstack([np.column_stack([quad, np.zeros(4)]), np.column_stack([quad, 0.5 * np.ones(4)])])
    conn3 = np.arange(8, dtype=np.int64)[None, :]
    conn2 = np.arange(4, dtype=np.int64)[None, :]
    n2 = np.array([0.6, -0.8])
    for fraction in (0.0, 0.2, 0.6, 1.0):
        d2 = cc.fluid_side_depth(quad, conn2, 0, 0.4, 0.5, *n2, fraction)
        d3 = cc.fluid_side_depth_3d(nodes, conn3, 0, 0.4, 0.5, 0.25, *n2, 0.0, fraction)
        assert abs(d3 - d2) < 1e-10


@pytest.mark.parametrize("nquad", [1, 2])
def test_coupling_forces_3d_penalty_and_scatter(nquad):
    """A face of 0.4 x 0.4 at mid-height of a full unit water hex, closing at 2 m/s for 1e-3 s: each
    point's force is k d, k = pfac K A^2 / V, A = 0.16 / nquad^2, along the face's normal; the hex's
    eight nodes take the opposite of what the face's four lose."""
    hexes = np.array([[x, y, z] for z in (0.0, 1.0) for y in (0.0, 1.0) for x in (0.0, 1.0)])
    xa = hexes[[0, 1, 3, 2, 4, 5, 7, 6]]  # VTK order
    conn = np.arange(8, dtype=np.int64)[None, :]
    xs = np.array([[0.3, 0.3, 0.5], [0.7, 0.3, 0.5], [0.7, 0.7, 0.5], [0.3, 0.7, 0.5]])  # normal +z
    faces = np.arange(4, dtype=np.int64)[None, :]
    vs = np.tile([0.0, 0.0, 2.0], (4, 1))
    ms, ma, va = np.ones(4), np.ones(8), np.zeros((8, 3))
    origin, cell = np.array([-1.0, -1.0, -1.0]), 1.0
    nb = np.array([3, 3, 3], dtype=np.int64)
    start, items = ck3.build_bins_3d(xa, conn, origin, cell, 3, 3, 3)
    pfac, bulk, dt = 0.1, 2.2e9, 1e-3
    n_pts = nquad * nquad
    depth, host, stiff = np.zeros(n_pts), -np.ones(n_pts, dtype=np.int64), np.zeros(n_pts)
    fs, fa = np.zeros((4, 3)), np.zeros((8, 3))
    coupled = ck3.coupling_forces_3d(faces, xs, vs, ms, nquad, xa, va, ma, conn, start, items, origin, cell, nb,
                                    np.ones(1), np.array([bulk]), np.ones(1), 0.5, pfac, 0.0, 0.25, True, dt,
                                    depth, host, stiff, fs, fa)
    share = 0.16 / n_pts
    k = pfac * bulk * share ** 2 / 1.0
    assert coupled == n_pts and np.all(host == 0)
    np.testing.assert_allclose(depth, 2.0 * dt, rtol=1e-14)
    np.testing.assert_allclose(stiff, k, rtol=1e-13)
    total = n_pts * k * 2.0 * dt
    np.testing.assert_allclose(fa.sum(axis=0), [0.0, 0.0, total], rtol=1e-13, atol=1e-9 * total)
    np.testing.assert_allclose(fs.sum(axis=0), -fa.sum(axis=0), rtol=1e-14, atol=1e-12 * total)
    np.testing.assert_allclose(fs[:, 2], -total / 4, rtol=1e-13)  # a centred face: a quarter per node
    np.testing.assert_allclose(fa[:, 2], total / 8, rtol=1e-13)  # at the hex's centre plane: an eighth
