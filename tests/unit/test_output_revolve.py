"""The revolved 3D view of axisymmetric parts (output/revolve.py, deck output.revolve), read back from the files.

Every check reads what the writer put on disk: the revolved XDMF with meshio's TimeSeriesReader, the
datasets with h5py.
"""
from __future__ import annotations

import h5py
import meshio
import numpy as np
import pytest

from sphfem_cli.output.results import revolved_step
from sphfem_cli.output.revolve import angles, revolve_connectivity, revolve_tensors
from sphfem_cli.output.xdmf import GridStep, XdmfWriter


def ring_mesh(r0: float, r1: float, h: float, nr: int, nz: int):
    """A meridian quad mesh of r0 <= r <= r1, 0 <= y <= h (counter-clockwise quads)."""
    r, y = np.meshgrid(np.linspace(r0, r1, nr + 1), np.linspace(0.0, h, nz + 1), indexing="ij")
    xy = np.column_stack([r.ravel(), y.ravel()])
    node = np.arange(xy.shape[0]).reshape(nr + 1, nz + 1)
    conn = np.column_stack([node[:-1, :-1].ravel(), node[1:, :-1].ravel(), node[1:, 1:].ravel(),
                            node[:-1, 1:].ravel()])
    return xy, conn


def hex_volumes(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Volumes of hex8 cells (VTK order) with planar faces: six tetrahedra about the diagonal 0-6, exact for
    planar faces; collapsed (axis) hexes give their wedge's volume."""
    tets = ((0, 1, 2, 6), (0, 2, 3, 6), (0, 3, 7, 6), (0, 7, 4, 6), (0, 4, 5, 6), (0, 5, 1, 6))
    p = points[cells]
    vol = np.zeros(len(cells))
    for a, b, c, d in tets:
        vol += np.einsum("ij,ij->i", p[:, b] - p[:, a], np.cross(p[:, c] - p[:, a], p[:, d] - p[:, a])) / 6.0
    return vol


def write_revolved(tmp_path, xy, conn, point, cell, segments=24, angle=360.0, topology="Quadrilateral"):
    """Write one meridian grid and its revolved view as RunOutput does; return the revolved file's path."""
    a, closed = angles(segments, angle)
    n = xy.shape[0]
    with XdmfWriter(tmp_path, "results") as w:
        w.add_grid("ring", topology, conn if topology != "Polyvertex" else None, n)
        w.add_grid("ring.revolved", *revolve_connectivity(topology, conn, n, segments, closed), n * len(a))
        for t in (0.0, 1.0):
            w.write_step(t, {"ring": GridStep(xy, point, cell),
                             "ring.revolved": revolved_step(xy, point, cell, segments, a, closed)})
    return tmp_path / "results.ring.revolved.xdmf"


def read_last(path):
    with meshio.xdmf.TimeSeriesReader(str(path)) as reader:
        points, cells = reader.read_points_cells()
        steps = [reader.read_data(k) for k in range(reader.num_steps)]
    return points, cells, steps


@pytest.mark.parametrize("r0", [0.0, 0.5])
def test_revolved_volume_is_the_ring_volume_less_the_chord_error(tmp_path, r0):
    """Sum of hex volumes = (sin d / d) * 2 pi * sum(r_c A) exactly (d = 2 pi / segments: each horizontal
    section of a sector is its chord polygon, area ratio sin d / d), i.e. within 1 - sin d / d = 1.14 % of the
    ring volume at 24 segments; with and without cells on the axis (collapsed hexes)."""
    xy, conn = ring_mesh(r0, 1.0, 0.7, 5, 3)
    path = write_revolved(tmp_path, xy, conn, {}, {})
    points, cells, _ = read_last(path)
    hexes = cells[0].data
    assert cells[0].type == "hexahedron" and hexes.shape == (24 * len(conn), 8)
    vol = hex_volumes(points, hexes)
    assert (vol > -1e-15).all()
    ring = np.pi * (1.0 ** 2 - r0 ** 2) * 0.7  # 2 pi int r dA
    d = 2 * np.pi / 24
    assert vol.sum() == pytest.approx(ring * np.sin(d) / d, rel=1e-12)
    assert abs(vol.sum() / ring - 1.0) < 1.0 - np.sin(d) / d + 1e-12
    if r0 == 0.0:  # the axis cells collapse to wedges of positive volume
        axis = np.flatnonzero(np.isclose(xy[conn[:, 0], 0], 0.0))
        assert (vol[axis] > 0).all()


def test_radial_velocity_revolves_to_a_x_a_y(tmp_path):
    """u_r = a r, u_y = 0 gives (a X, a Y, 0) at every revolved point, to round-off."""
    xy, conn = ring_mesh(0.0, 2.0, 1.0, 4, 2)
    rate = 3.5
    v = np.column_stack([rate * xy[:, 0], np.zeros(len(xy))])
    path = write_revolved(tmp_path, xy, conn, {"velocity": v}, {}, segments=16, angle=270.0)
    points, _, steps = read_last(path)
    got = steps[-1][1]["velocity"]
    assert points.shape == (17 * len(xy), 3)  # a partial sweep has segments + 1 rings of points
    np.testing.assert_allclose(got, np.column_stack([rate * points[:, 0], rate * points[:, 1], 0 * points[:, 2]]),
                               rtol=0, atol=1e-13)
    np.testing.assert_allclose(np.hypot(points[:, 0], points[:, 1]), np.tile(xy[:, 0], 17), atol=1e-14)
    np.testing.assert_array_equal(points[:, 2], np.tile(xy[:, 1], 17))


def test_hoop_stress_rotates_to_xx_and_yy():
    """A pressurised ring (sigma_rr = -p, sigma_tt = hoop, axial s_yy): at a = 0 sigma_YY = hoop and
    sigma_XX = -p; at a = 90 degrees sigma_XX = hoop, sigma_YY = -p; at 45 degrees XX = YY = (hoop - p) / 2
    and XY = (-p - hoop) / 2; ZZ stays the axial stress; the invariants are kept."""
    p, hoop, axial = 2.0, 7.0, 0.5
    t = np.array([[-p, axial, hoop, 0.0, 0.0, 0.0]])
    out = revolve_tensors(t, np.array([0.0, np.pi / 2, np.pi / 4]))
    np.testing.assert_allclose(out[0], [-p, hoop, axial, 0, 0, 0], atol=1e-14)
    np.testing.assert_allclose(out[1], [hoop, -p, axial, 0, 0, 0], atol=1e-14)
    np.testing.assert_allclose(out[2], [(hoop - p) / 2, (hoop - p) / 2, axial, (-p - hoop) / 2, 0, 0], atol=1e-14)
    rng = np.random.default_rng(15)
    t = rng.normal(size=(5, 6))
    a = rng.uniform(0, 2 * np.pi, 3)
    full = revolve_tensors(t, a)

    def matrix(v):  # code order xx, yy, zz, xy, yz, zx
        return np.array([[v[0], v[3], v[5]], [v[3], v[1], v[4]], [v[5], v[4], v[2]]])

    for k in range(3):
        c, s = np.cos(a[k]), np.sin(a[k])
        rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])  # (r, t, y) -> (X, Y, Z)
        perm = [0, 2, 1]  # meridian code order rr, yy, tt -> (r, t, y)
        for m in range(5):
            cyl = matrix(t[m])[np.ix_(perm, perm)]
            np.testing.assert_allclose(matrix(full[k * 5 + m]), rot @ cyl @ rot.T, atol=1e-13)


def test_cell_stress_on_disk_at_the_cells_mid_angle(tmp_path):
    """The stress of each hex ring is rotated to its centroid's angle; on disk in XDMF Tensor6 order
    (xx, xy, xz, yy, yz, zz); scalars are copied to every ring."""
    xy, conn = ring_mesh(0.5, 1.0, 0.2, 1, 1)
    hoop = 4.0
    stress = np.array([[0.0, 0.0, hoop, 0.0, 0.0, 0.0]])
    path = write_revolved(tmp_path, xy, conn, {}, {"stress": stress, "pressure": np.array([1.25])}, segments=4)
    _, _, steps = read_last(path)
    with h5py.File(tmp_path / "results.h5", "r") as h5:
        ds = h5["ring.revolved/step_000001/cell/stress"]
        assert ds.attrs["component_order"] == "xx,xy,xz,yy,yz,zz"
        on_disk = ds[()]
    np.testing.assert_array_equal(on_disk, steps[-1][2]["stress"][0])
    mid = (np.arange(4) + 0.5) * np.pi / 2
    np.testing.assert_allclose(on_disk[:, 0], hoop * np.sin(mid) ** 2, atol=1e-14)
    np.testing.assert_allclose(on_disk[:, 3], hoop * np.cos(mid) ** 2, atol=1e-14)
    np.testing.assert_array_equal(steps[-1][2]["pressure"][0], np.full(4, 1.25))


def test_particles_revolve_to_rings_of_points(tmp_path):
    """Each particle becomes `segments` points on its ring (closed sweep); results.xdmf keeps the meridian."""
    xy = np.array([[0.0, 0.1], [0.3, 0.2], [1.0, -0.4]])
    rho = np.array([1000.0, 1001.0, 999.0])
    path = write_revolved(tmp_path, xy, None, {"density": rho}, {}, segments=8, topology="Polyvertex")
    points, cells, steps = read_last(path)
    assert points.shape == (24, 3) and sum(len(c.data) for c in cells) == 24
    np.testing.assert_allclose(np.hypot(points[:, 0], points[:, 1]).reshape(8, 3), np.tile(xy[:, 0], (8, 1)),
                               atol=1e-15)
    np.testing.assert_array_equal(steps[-1][1]["density"], np.tile(rho, 8))
    combined = (tmp_path / "results.xdmf").read_text()
    assert "ring.revolved" not in combined and 'Name="ring"' in combined
    assert "ring.revolved" in (tmp_path / "results.paraview.py").read_text()
