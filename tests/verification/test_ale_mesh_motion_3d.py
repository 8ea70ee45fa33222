"""3D (hex8) ALE mesh motion: Winslow (equipotential) smoothing and sliding boundaries
(ale/motion.py, docs/theory/ale.md "Mesh motion").

- Stencil: the Winslow point computed on the stencil read from the connectivity equals the one
  written with the structured indices (i +- 1, j +- 1, k +- 1) of a 6 x 5 x 4 box under a smooth
  non-affine map, for the box's own element order, shuffled elements and elements whose corners
  are renumbered by a quarter turn: to 2e-16 (tolerance 1e-14).
- A uniform and an affinely mapped box are left where they are: 1e-16 and 4e-16 (tolerance 1e-14).
- Relaxation: the interior of an 8^3 unit cube displaced by 0.05 sin(pi x) sin(2 pi y) sin(pi z)
  (each component; boundary nodes uniform), Jacobi passes with weight 1 and no pull: largest
  distance from the uniform grid 0.050 -> 2.0e-3 after 20 passes, 5e-9 after 100, 1e-16 after 300
  (the uniform grid is the discrete Winslow mesh of a cube with uniform boundary spacing).
  Through AleSystem, gas at rest, 60 remaps: 0.050 -> 3.3e-6, mass change 0, density 1 to 6e-15.
- Sliding: a rotated 6 x 5 x 4 box whose nodes are bunched towards one corner along all three
  logical directions (u -> u^2): its 94 face nodes slide in their planes, its 48 edge nodes along
  their edges, its 8 corners stay; after 400 passes every face node is within 2.2e-16 of its
  plane and every edge node within 1.4e-16 of its line (tolerance 1e-14), the corners are
  bit-identical, and the mesh is the uniform box to 4e-16 (from 0.27). A bulged top face is not
  flat: its nodes stay fixed while the flat bottom's slide.
- Conservation with a moving mesh: closed box 8 x 7 x 6, two gases, a pressure bump, random
  velocities, sliding walls, 60 steps (average and equipotential alike): mass per material 3e-15,
  total energy 4e-16, momentum - wall impulse 1.6e-15 of the momentum scale, every boundary node
  on its wall exactly, the element volumes those of the moved mesh to 9e-16 (a node sliding in its
  wall sweeps no volume through it).
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
from ale_cases import gas_row  # noqa: E402
from test_ale_3d import walls_3d  # noqa: E402

from sphfem_cli.ale import AleOptions, AleSystem, MeshMotion, build_topology, fill_fractions  # noqa: E402
from sphfem_cli.ale import kernels as K  # noqa: E402
from sphfem_cli.ale.motion import MeshMover, _winslow_target_3d  # noqa: E402
from sphfem_cli.model.mesh import box_mesh  # noqa: E402

QUARTER_TURN = np.array([1, 2, 3, 0, 5, 6, 7, 4])  # hex8 corners renumbered by a turn about the element's zeta axis


def _mover(x0, conn, **motion):
    motion = MeshMotion(mesh_motion="smoothed", **{"smoothing_weight": 1.0, "eulerian_pull": 0.0, **motion})
    return MeshMover(motion, x0, conn, build_topology(conn, len(x0)))


def _structured_winslow(x, n):
    """The Winslow point of every interior node of a box mesh of n = (nx, ny, nz) elements, written
    with the structured indices: the 3D equipotential equation sum_ij C_ij x_(ij) = 0,
    C_ij = b_i . b_j, b_i = a_j x a_k (docs/theory/ale.md), solved for the centre node."""
    grid = x.reshape(n[2] + 1, n[1] + 1, n[0] + 1, 3)  # [k, j, i]: x fastest

    def at(di, dj, dk):
        return grid[1 + dk:n[2] + dk, 1 + dj:n[1] + dj, 1 + di:n[0] + di].reshape(-1, 3)

    unit = np.eye(3, dtype=int)
    xp = [at(*unit[d]) for d in range(3)]
    xm = [at(*-unit[d]) for d in range(3)]
    a = [0.5 * (xp[d] - xm[d]) for d in range(3)]
    b = [np.cross(a[1], a[2]), np.cross(a[2], a[0]), np.cross(a[0], a[1])]
    c = [[(b[i] * b[j]).sum(axis=1)[:, None] for j in range(3)] for i in range(3)]
    num = sum(c[d][d] * (xp[d] + xm[d]) for d in range(3))
    for i, j in ((0, 1), (0, 2), (1, 2)):
        ei, ej = unit[i], unit[j]
        cross = at(*(ei + ej)) - at(*(ei - ej)) - at(*(ej - ei)) + at(*-(ei + ej))
        num = num + 0.5 * c[i][j] * cross
    ids = np.arange(len(x)).reshape(grid.shape[:3])[1:-1, 1:-1, 1:-1].ravel()
    return ids, num / (2.0 * (c[0][0] + c[1][1] + c[2][2]))


def test_winslow_3d_stencil_is_the_structured_one():
    n = (6, 5, 4)
    mesh = box_mesh([0.0, 0.0, 0.0], [1.0, 0.8, 0.6], divisions=list(n))
    x0, conn = mesh.nodes, mesh.elements
    x = x0 + 0.05 * np.sin(3.0 * x0[:, [1, 2, 0]]) + 0.04 * np.cos(2.0 * x0[:, [2, 0, 1]])
    ids, expected = _structured_winslow(x, n)
    rng = np.random.default_rng(5)
    turned = conn.copy()
    some = rng.random(len(conn)) < 0.5
    turned[some] = conn[some][:, QUARTER_TURN]
    for c in (conn, conn[rng.permutation(len(conn))], turned):
        mover = _mover(x0, c, smoothing="equipotential")
        assert np.array_equal(np.sort(mover._stencil[0]), np.sort(ids))  # every interior node, none else
        got = _winslow_target_3d(x, np.full_like(x, np.nan), mover._stencil)
        np.testing.assert_allclose(got[ids], expected, rtol=0, atol=1e-14)


def test_winslow_3d_leaves_uniform_and_affine_meshes():
    mesh = box_mesh([0.0, 0.0, 0.0], [1.0, 0.8, 0.6], divisions=[6, 5, 4])
    affine = np.array([[1.0, 0.3, 0.1], [0.2, 0.9, -0.2], [0.05, 0.1, 1.1]])
    for x0 in (mesh.nodes, mesh.nodes @ affine.T):
        mover = _mover(x0, mesh.elements, smoothing="equipotential", smoothing_boundary="sliding")
        np.testing.assert_allclose(mover.target(x0), x0, rtol=0, atol=1e-14)


def _displaced_cube(n=8, amp=0.05):
    mesh = box_mesh([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], divisions=[n, n, n])
    uniform = mesh.nodes
    s = np.sin(np.pi * uniform[:, 0]) * np.sin(2.0 * np.pi * uniform[:, 1]) * np.sin(np.pi * uniform[:, 2])
    return uniform, uniform + amp * s[:, None], mesh.elements


def test_winslow_3d_relaxes_a_distorted_mesh_to_the_uniform_one():
    uniform, x, conn = _displaced_cube()
    mover = _mover(uniform, conn, smoothing="equipotential")
    d0 = np.abs(x - uniform).max()
    for _ in range(20):
        x = mover.target(x)
    d20 = np.abs(x - uniform).max()
    for _ in range(280):
        x = mover.target(x)
    d300 = np.abs(x - uniform).max()
    assert d0 > 0.03 and d20 < 0.1 * d0 and d300 < 1e-12


def test_winslow_3d_relaxes_an_ale_mesh_with_the_gas_at_rest():
    uniform, x, conn = _displaced_cube()
    ale = AleSystem(x, conn, [gas_row(1.4, 1.0)], np.ones((len(conn), 1)), [1.0], pressure=[1.0],
                    options=AleOptions(motion=MeshMotion(mesh_motion="smoothed", smoothing="equipotential",
                                                         smoothing_weight=1.0, eulerian_pull=0.0)))
    walls_3d(ale, x, (0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    m0 = ale.totals()["mass"]
    d0 = np.abs(ale.x - uniform).max()
    for _ in range(60):
        ale.step(ale.stable_dt(0.5))
    assert np.abs(ale.x - uniform).max() < 1e-3 * d0
    np.testing.assert_allclose(ale.totals()["mass"], m0, rtol=1e-14)
    np.testing.assert_allclose(ale.mixture_density(), 1.0, rtol=1e-12)


def _rotation():
    q, _ = np.linalg.qr(np.random.default_rng(2).standard_normal((3, 3)))
    return q * np.sign(np.linalg.det(q))


def test_sliding_3d_keeps_boundary_nodes_on_their_faces_and_edges():
    n, size = (6, 5, 4), np.array([1.0, 0.8, 0.6])
    mesh = box_mesh([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], divisions=list(n))
    u, conn = mesh.nodes, mesh.elements  # logical coordinates in [0, 1]^3
    rot = _rotation()
    x0 = (u ** 2 * size) @ rot.T  # bunched towards one corner: boundary nodes stay on their faces and edges
    uniform = (u * size) @ rot.T
    mover = _mover(x0, conn, smoothing="equipotential", smoothing_boundary="sliding")
    on_side = (u == 0.0) | (u == 1.0)  # (N, 3): on the side across axis d
    sides = on_side.sum(axis=1)
    face, edge, corner = sides == 1, sides == 2, sides == 3
    assert np.array_equal(np.sort(mover._slide_plane[0]), np.flatnonzero(face))  # 94
    assert np.array_equal(np.sort(mover._slide[0]), np.flatnonzero(edge))  # 48
    x = x0.copy()
    spread0 = np.abs(x - uniform).max()
    for _ in range(400):
        x = mover.target(x)
    d = (x - x0) @ rot  # displacements in the box's axes
    off_plane = np.abs(np.where(on_side, d, 0.0)).max(axis=1)  # across the sides the node lies on
    assert off_plane[face | edge].max() < 1e-14
    assert np.array_equal(x[corner], x0[corner])
    assert np.abs(d[face | edge]).max() > 0.1  # they did slide
    assert spread0 > 0.2 and np.abs(x - uniform).max() < 1e-10


def test_sliding_3d_fixes_the_nodes_of_a_curved_face():
    mesh = box_mesh([0.0, 0.0, 0.0], [1.0, 1.0, 0.5], divisions=[5, 5, 3])
    x0, conn = mesh.nodes.copy(), mesh.elements
    top = np.flatnonzero(x0[:, 2] == 0.5)
    x0[top, 2] += 0.05 * np.sin(np.pi * x0[top, 0]) * np.sin(np.pi * x0[top, 1])
    mover = _mover(x0, conn, smoothing="average", smoothing_boundary="sliding")
    sliding = np.concatenate([mover._slide_plane[0], mover._slide[0]])
    assert not np.isin(top, sliding).any()
    rng = np.random.default_rng(3)
    x = x0 + 0.02 * rng.standard_normal(x0.shape)
    out = mover.target(x)
    assert np.array_equal(out[top], x0[top])
    bottom = np.flatnonzero(x0[:, 2] == 0.0)
    assert (out[bottom, 2] == 0.0).all() and np.abs(out[bottom, :2] - x0[bottom, :2]).max() > 1e-3


@pytest.mark.parametrize("smoothing", ["average", "equipotential"])
def test_moving_3d_mesh_remap_conserves_mass_momentum_energy(smoothing):
    rng = np.random.default_rng(11)
    lo, hi = (0.0, 0.0, 0.0), (1.0, 0.8, 0.6)
    mesh = box_mesh(lo, hi, divisions=[8, 7, 6])
    nodes, conn = mesh.nodes, mesh.elements
    f = fill_fractions(nodes, conn, lambda x, y, z: z < 0.3 + 0.1 * np.sin(6 * x) * np.cos(5 * y))
    xc = nodes[conn].mean(axis=1)
    bump = 1.0 + 4.0 * np.exp(-((xc - [0.6, 0.5, 0.3]) ** 2).sum(axis=1) / 0.02)
    motion = MeshMotion(mesh_motion="smoothed", smoothing=smoothing, smoothing_boundary="sliding", eulerian_pull=0.0)
    ale = AleSystem(nodes, conn, [gas_row(1.4, 1.0), gas_row(1.67, 0.3)], np.stack([f, 1 - f], axis=1),
                    [1.0, 0.3], pressure=np.stack([bump, bump], axis=1),
                    velocity=0.3 * rng.standard_normal(nodes.shape), options=AleOptions(motion=motion))
    walls_3d(ale, nodes, lo, hi)
    t0 = ale.totals()
    for _ in range(60):
        ale.step(ale.stable_dt(0.5))
    t1 = ale.totals()
    np.testing.assert_allclose(t1["mass"], t0["mass"], rtol=1e-13)
    assert abs(t1["total"] / t0["total"] - 1.0) < 1e-13
    scale = float((ale.node_mass * np.linalg.norm(ale.velocity, axis=1)).sum())
    np.testing.assert_allclose(t1["momentum"] - t0["momentum"], t1["wall_impulse"], rtol=0, atol=1e-13 * scale)
    boundary = ~ale.mesh._interior
    assert np.abs(ale.x - nodes)[boundary].max() > 0.01  # boundary nodes slid
    for axis in range(3):
        for value in (lo[axis], hi[axis]):
            assert (ale.x[nodes[:, axis] == value, axis] == value).all()  # on their walls, exactly
    vol = np.empty(len(conn))
    K.element_volumes_3d(ale.x, conn, vol)
    np.testing.assert_allclose(ale.vol_m.sum(axis=1), vol, rtol=1e-12)
