"""Mesh generators and meshio import (sphfem_cli.model.mesh)."""

from pathlib import Path

import meshio
import numpy as np
import pytest

from sphfem_cli.model.mesh import (
    MeshData,
    box_mesh,
    cylinder_mesh,
    element_jacobian_sign_check,
    read_mesh,
    ring_mesh,
)
from sphfem_cli.model.sets import boundary_faces

DATA = Path(__file__).resolve().parents[1] / "data"


def polygon_area(n: int, r: float) -> float:
    """Area of the regular n-gon inscribed in a circle of radius r."""
    return 0.5 * n * r * r * np.sin(2.0 * np.pi / n)


def check_valid(mesh: MeshData, dim: int) -> np.ndarray:
    """Types, shapes, no unused / duplicate nodes, positive measure; returns the measures."""
    assert isinstance(mesh, MeshData)
    assert mesh.nodes.dtype == np.float64 and mesh.nodes.shape[1] == dim
    assert mesh.elements.dtype == np.int64
    assert mesh.elements.shape[1] == (4 if dim == 2 else 8)
    assert mesh.node_sets == {} or isinstance(mesh.node_sets, dict)
    # every node used, none duplicated
    assert np.array_equal(np.unique(mesh.elements), np.arange(mesh.n_nodes))
    rounded = np.round(mesh.nodes, 9)
    assert np.unique(rounded, axis=0).shape[0] == mesh.n_nodes
    vol = element_jacobian_sign_check(mesh.nodes, mesh.elements)
    assert np.all(vol > 0)
    return vol


# ------------------------------------------------------------------ signed measure


def test_sign_check_unit_square_and_cube():
    sq = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    assert element_jacobian_sign_check(sq, np.array([[0, 1, 2, 3]])) == pytest.approx([1.0])
    assert element_jacobian_sign_check(sq, np.array([[0, 3, 2, 1]])) == pytest.approx([-1.0])
    cube = np.array(
        [[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0], [0, 0, 3], [2, 0, 3], [2, 1, 3], [0, 1, 3]],
        dtype=float,
    )
    hexes = np.array([np.arange(8), [4, 5, 6, 7, 0, 1, 2, 3], [0, 3, 2, 1, 4, 7, 6, 5]])
    assert element_jacobian_sign_check(cube, hexes) == pytest.approx([6.0, -6.0, -6.0])


# ------------------------------------------------------------------ box


def test_box_2d_counts_order_area():
    m = box_mesh((0.0, -1.0), (2.0, 1.0), divisions=(4, 2))
    assert m.dim == 2 and m.n_nodes == 5 * 3 and m.n_elements == 4 * 2
    vol = check_valid(m, 2)
    assert vol == pytest.approx(np.full(8, 0.5))
    assert np.array_equal(m.nodes[1], [0.5, -1.0])  # x runs fastest
    assert np.array_equal(m.nodes[5], [0.0, 0.0])
    assert np.array_equal(m.elements[0], [0, 1, 6, 5])  # counter-clockwise
    assert m.node_sets == {} and m.element_sets == {}


def test_box_3d_counts_order_volume():
    m = box_mesh((0, 0, 0), (1, 2, 3), divisions=(2, 3, 4))
    assert m.n_nodes == 3 * 4 * 5 and m.n_elements == 2 * 3 * 4
    vol = check_valid(m, 3)
    assert vol.sum() == pytest.approx(6.0)
    nxy = 3 * 4
    assert np.array_equal(m.elements[0], [0, 1, 4, 3, nxy, nxy + 1, nxy + 4, nxy + 3])


def test_box_element_size():
    m = box_mesh((0, 0), (1, 0.1), element_size=0.3)
    assert m.n_elements == 3 * 1  # round(3.33) = 3, max(1, round(0.33)) = 1
    m = box_mesh((0, 0, 0), (1, 2, 4), element_size=(0.5, 0.5, 1.0))
    assert m.n_elements == 2 * 4 * 4


@pytest.mark.parametrize(
    "kwargs",
    [
        dict(lo=(0, 0), hi=(1, 1)),
        dict(lo=(0, 0), hi=(1, 1), divisions=2, element_size=0.5),
        dict(lo=(0, 0), hi=(0, 1), divisions=2),
        dict(lo=(0, 0), hi=(1, 1, 1), divisions=2),
        dict(lo=(0, 0), hi=(1, 1), divisions=0),
        dict(lo=(0, 0), hi=(1, 1), divisions=1.5),
        dict(lo=(0, 0), hi=(1, 1), element_size=-1.0),
    ],
)
def test_box_bad_input(kwargs):
    with pytest.raises(ValueError):
        box_mesh(**kwargs)


# ------------------------------------------------------------------ ring / disc


def test_annulus_counts_area_and_seam():
    n, nt, r, R = 24, 3, 0.5, 1.25
    m = ring_mesh((1.0, -2.0), r, R, n, nt)
    assert m.n_nodes == n * (nt + 1) and m.n_elements == n * nt
    vol = check_valid(m, 2)
    assert vol.sum() == pytest.approx(polygon_area(n, R) - polygon_area(n, r), rel=1e-12)
    radius = np.linalg.norm(m.nodes - [1.0, -2.0], axis=1)
    assert radius.min() == pytest.approx(r) and radius.max() == pytest.approx(R)
    # the seam is closed: only the inner and outer circles are boundary
    faces, _ = boundary_faces(m.elements, 2)
    assert faces.shape[0] == 2 * n


def test_annulus_area_converges():
    r, R = 0.3, 1.0
    exact = np.pi * (R**2 - r**2)
    errs = []
    for n in (8, 16, 32, 64):
        m = ring_mesh((0, 0), r, R, n, 2)
        errs.append(exact - element_jacobian_sign_check(m.nodes, m.elements).sum())
    errs = np.array(errs)
    assert np.all(errs > 0) and np.all(np.diff(errs) < 0)
    # second order: halving the angle quarters the error
    assert errs[:-1] / errs[1:] == pytest.approx(np.full(3, 4.0), rel=0.05)


@pytest.mark.parametrize("n", [4, 8, 12, 16, 32, 64, 96])
@pytest.mark.parametrize("nt", [1, 2, 3, 5, 8])
def test_disc_valid_and_exact_polygon_area(n, nt):
    R = 2.0
    m = ring_mesh((0.5, 0.25), 0.0, R, n, nt)
    k = n // 4
    assert m.n_nodes == (k + 1) ** 2 + n * nt
    assert m.n_elements == k * k + n * nt
    vol = check_valid(m, 2)
    assert vol.sum() == pytest.approx(polygon_area(n, R), rel=1e-12)
    radius = np.linalg.norm(m.nodes - [0.5, 0.25], axis=1)
    assert radius.max() == pytest.approx(R)
    assert np.sum(np.isclose(radius, R)) == n
    faces, _ = boundary_faces(m.elements, 2)
    assert faces.shape[0] == n


def test_disc_area_converges_to_circle():
    errs = []
    for n in (8, 16, 32, 64):
        m = ring_mesh((0, 0), 0.0, 1.0, n, n // 8)
        errs.append(np.pi - element_jacobian_sign_check(m.nodes, m.elements).sum())
    assert np.all(np.diff(errs) < 0) and errs[-1] < 0.01


@pytest.mark.parametrize(
    "args",
    [
        ((0, 0), 0.0, 1.0, 10, 2),  # disc needs elements_around % 4 == 0
        ((0, 0), 1.0, 0.5, 8, 2),
        ((0, 0), -0.1, 1.0, 8, 2),
        ((0, 0), 0.5, 1.0, 2, 2),
        ((0, 0), 0.5, 1.0, 8, 0),
        ((0, 0, 0), 0.5, 1.0, 8, 1),
    ],
)
def test_ring_bad_input(args):
    with pytest.raises(ValueError):
        ring_mesh(*args)


# ------------------------------------------------------------------ cylinder


@pytest.mark.parametrize("axis", ["x", "y", "z"])
@pytest.mark.parametrize("r", [0.0, 0.4])
def test_cylinder_counts_volume_extent(axis, r):
    n, nt, nl, R, L = 16, 3, 5, 1.0, 3.0
    c = np.array([1.0, 2.0, 3.0])
    m = cylinder_mesh(c, axis, r, R, L, n, nt, nl)
    sec = ring_mesh((0, 0), r, R, n, nt)
    assert m.n_nodes == sec.n_nodes * (nl + 1)
    assert m.n_elements == sec.n_elements * nl
    vol = check_valid(m, 3)
    exact = (polygon_area(n, R) - polygon_area(n, r)) * L
    assert vol.sum() == pytest.approx(exact, rel=1e-12)
    ia = "xyz".index(axis)
    along = m.nodes[:, ia]
    assert along.min() == pytest.approx(c[ia] - L / 2)
    assert along.max() == pytest.approx(c[ia] + L / 2)
    d = m.nodes - c
    d[:, ia] = 0.0
    assert np.linalg.norm(d, axis=1).max() == pytest.approx(R)
    # bottom face (nodes 0-3) lies at the lower axial level of each hex
    assert np.all(m.nodes[m.elements[:, :4], ia] < m.nodes[m.elements[:, 4:], ia])


def test_cylinder_volume_converges():
    exact = np.pi * (1.0 - 0.25) * 2.0
    errs = []
    for n in (8, 16, 32):
        m = cylinder_mesh((0, 0, 0), "z", 0.5, 1.0, 2.0, n, 2, 2)
        errs.append(exact - element_jacobian_sign_check(m.nodes, m.elements).sum())
    assert np.all(np.array(errs) > 0) and np.all(np.diff(errs) < 0)


def test_cylinder_bad_axis():
    with pytest.raises(ValueError):
        cylinder_mesh((0, 0, 0), "w", 0.0, 1.0, 1.0, 8, 1, 1)
    with pytest.raises(ValueError):
        cylinder_mesh((0, 0), "z", 0.0, 1.0, 1.0, 8, 1, 1)


# ------------------------------------------------------------------ read_mesh


def test_read_gmsh41_quads_with_reversed_element_and_groups():
    m = read_mesh(DATA / "quad_2x1_gmsh41.msh", 2)
    assert m.nodes.shape == (6, 2) and m.elements.shape == (2, 4)
    vol = check_valid(m, 2)
    assert vol == pytest.approx([1.0, 1.0])
    assert np.array_equal(m.elements[1], [1, 2, 5, 4])  # the CW element, flipped
    assert np.array_equal(m.node_sets["left"], [0, 3])  # from a physical curve
    assert np.array_equal(m.node_sets["plate"], np.arange(6))
    assert np.array_equal(m.element_sets["plate"], [0, 1])
    assert "left" not in m.element_sets


def test_read_abaqus_hexes_drops_unused_node_and_reads_sets():
    m = read_mesh(DATA / "hex_2x1x1.inp", 3)
    assert m.nodes.shape == (12, 3) and m.elements.shape == (2, 8)
    vol = check_valid(m, 3)
    assert vol == pytest.approx([1.0, 1.0])
    assert np.allclose(m.nodes[0], 0.0)  # unused node 100 dropped, the rest renumbered
    assert np.array_equal(m.node_sets["fixed"], [0, 3, 6, 9])
    assert np.array_equal(m.node_sets["withref"], [2])  # the unused node is left out
    assert np.array_equal(m.element_sets["block"], [0, 1])
    assert np.array_equal(m.element_sets["first"], [0])
    assert np.allclose(m.nodes[m.node_sets["fixed"], 0], 0.0)


def test_read_vtu_inside_out_hex():
    m = read_mesh(DATA / "hex_2x1x1_flipped.vtu", 3)
    vol = check_valid(m, 3)
    assert vol == pytest.approx([1.0, 1.0])
    assert m.node_sets == {} and m.element_sets == {}


def test_read_round_trip_and_2d_from_3_columns(tmp_path):
    ref = ring_mesh((0.0, 0.0), 0.0, 1.0, 16, 2)
    pts = np.column_stack([ref.nodes, np.full(ref.n_nodes, 0.5)])
    bad = ref.elements.copy()
    bad[::2] = bad[::2][:, [0, 3, 2, 1]]
    path = tmp_path / "disc.vtu"
    meshio.write(path, meshio.Mesh(pts, [("quad", bad), ("line", ref.elements[:3, :2])]))
    m = read_mesh(path, 2)
    assert np.allclose(m.nodes, ref.nodes)
    check_valid(m, 2)
    assert np.allclose(
        element_jacobian_sign_check(m.nodes, m.elements),
        element_jacobian_sign_check(ref.nodes, ref.elements),
    )

    cyl = cylinder_mesh((0, 0, 0), "y", 0.2, 1.0, 1.0, 12, 2, 3)
    path = tmp_path / "cyl.msh"
    meshio.write(path, meshio.Mesh(cyl.nodes, [("hexahedron", cyl.elements)]),
                 file_format="gmsh22", binary=False)
    m = read_mesh(path, 3)
    assert np.allclose(m.nodes, cyl.nodes) and np.array_equal(m.elements, cyl.elements)


def test_read_errors(tmp_path):
    tri = tmp_path / "tri.vtu"
    meshio.write(tri, meshio.Mesh(np.eye(3), [("triangle", np.array([[0, 1, 2]]))]))
    with pytest.raises(ValueError, match="1 triangle"):
        read_mesh(tri, 2)
    with pytest.raises(ValueError, match="no hexahedron"):
        read_mesh(DATA / "quad_2x1_gmsh41.msh", 3)
    warped = tmp_path / "warped.vtu"
    pts = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.3], [0, 1, 0]], dtype=float)
    meshio.write(warped, meshio.Mesh(pts, [("quad", np.array([[0, 1, 2, 3]]))]))
    with pytest.raises(ValueError, match="z = const"):
        read_mesh(warped, 2)
    with pytest.raises(ValueError):
        read_mesh(DATA / "hex_2x1x1.inp", 1)
