"""Node and segment selection (sphfem_cli.model.sets)."""

import numpy as np
import pytest

from sphfem_cli.model.mesh import box_mesh, cylinder_mesh, ring_mesh
from sphfem_cli.model.sets import (
    boundary_faces,
    nodes_in_box,
    nodes_near_circle,
    nodes_near_cylinder,
    nodes_near_plane,
    nodes_near_sphere,
    nodes_on_side,
    segments_in_box,
    segments_of_nodes,
    segments_on_side,
)


def face_normals(nodes, faces):
    """Outward normal (not normalised) per the module convention."""
    x = nodes[faces]
    if faces.shape[1] == 2:
        d = x[:, 1] - x[:, 0]
        return np.column_stack([d[:, 1], -d[:, 0]])
    return np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1])


def check_outward(nodes, elements, faces, owner):
    """Each face normal points from its owner's centroid out through the face."""
    n = face_normals(nodes, faces)
    mid = nodes[faces].mean(axis=1)
    centroid = nodes[elements[owner]].mean(axis=1)
    assert np.all(np.einsum("ij,ij->i", n, mid - centroid) > 0)
    # the face's nodes belong to its owner
    assert all(set(f) <= set(elements[o]) for f, o in zip(faces.tolist(), owner.tolist()))
    return n


# ------------------------------------------------------------------ boundary faces


def test_boundary_faces_box_2d():
    m = box_mesh((0, 0), (3, 2), divisions=(3, 2))
    faces, owner = boundary_faces(m.elements, 2)
    assert faces.shape == (2 * (3 + 2), 2) and faces.dtype == np.int64
    n = check_outward(m.nodes, m.elements, faces, owner)
    mid = m.nodes[faces].mean(axis=1)
    assert np.all(np.einsum("ij,ij->i", n, mid - [1.5, 1.0]) > 0)  # away from the centroid
    assert np.allclose(np.linalg.norm(n, axis=1), 1.0)
    assert np.all(np.diff(owner) >= 0)  # ordered by owner
    # total outward normal of a closed boundary vanishes
    assert np.allclose(n.sum(axis=0), 0.0)


def test_boundary_faces_box_3d():
    nx, ny, nz = 3, 2, 4
    m = box_mesh((0, 0, 0), (1, 1, 1), divisions=(nx, ny, nz))
    faces, owner = boundary_faces(m.elements, 3)
    assert faces.shape == (2 * (nx * ny + ny * nz + nz * nx), 4)
    n = check_outward(m.nodes, m.elements, faces, owner)
    mid = m.nodes[faces].mean(axis=1)
    assert np.all(np.einsum("ij,ij->i", n, mid - 0.5) > 0)
    assert np.allclose(n.sum(axis=0), 0.0)
    # each boundary normal is axis-aligned and its face lies on the matching side
    axis = np.argmax(np.abs(n), axis=1)
    on_side = mid[np.arange(len(mid)), axis]
    assert np.allclose(np.where(n[np.arange(len(n)), axis] > 0, on_side - 1.0, on_side), 0.0)


def test_boundary_faces_ring_and_cylinder():
    ring = ring_mesh((0, 0), 0.5, 1.0, 12, 2)
    faces, owner = boundary_faces(ring.elements, 2)
    n = check_outward(ring.nodes, ring.elements, faces, owner)
    mid = ring.nodes[faces].mean(axis=1)
    radial = np.einsum("ij,ij->i", n, mid)
    inner = np.linalg.norm(mid, axis=1) < 0.75
    assert inner.sum() == 12 and np.all(radial[inner] < 0) and np.all(radial[~inner] > 0)

    cyl = cylinder_mesh((0, 0, 0), "x", 0.0, 1.0, 2.0, 16, 2, 3)
    faces, owner = boundary_faces(cyl.elements, 3)
    sec = ring_mesh((0, 0), 0.0, 1.0, 16, 2)
    assert faces.shape[0] == 2 * sec.n_elements + 16 * 3
    n = check_outward(cyl.nodes, cyl.elements, faces, owner)
    assert np.allclose(n.sum(axis=0), 0.0)


def test_boundary_faces_empty_and_bad_dim():
    faces, owner = boundary_faces(np.zeros((0, 4), dtype=np.int64), 2)
    assert faces.shape == (0, 2) and owner.shape == (0,)
    with pytest.raises(ValueError):
        boundary_faces(np.zeros((1, 4), dtype=np.int64), 3)
    with pytest.raises(ValueError):
        boundary_faces(np.zeros((1, 4), dtype=np.int64), 1)


# ------------------------------------------------------------------ node selections


def test_nodes_on_side_2d_and_3d():
    m = box_mesh((-1, 0), (1, 2), divisions=(4, 2))  # 5 x 3 nodes
    expect = {
        "left": np.arange(0, 15, 5),
        "right": np.arange(4, 15, 5),
        "bottom": np.arange(5),
        "top": np.arange(10, 15),
    }
    for side, ids in expect.items():
        got = nodes_on_side(m.nodes, side)
        assert got.dtype == np.int64 and np.array_equal(got, ids), side
    with pytest.raises(ValueError):
        nodes_on_side(m.nodes, "front")
    with pytest.raises(ValueError):
        nodes_on_side(m.nodes, "north")

    b = box_mesh((0, 0, 0), (1, 1, 2), divisions=(2, 2, 2))
    assert np.array_equal(nodes_on_side(b.nodes, "front"), np.arange(9))
    assert np.array_equal(nodes_on_side(b.nodes, "back"), np.arange(18, 27))
    assert np.allclose(b.nodes[nodes_on_side(b.nodes, "top"), 1], 1.0)
    assert nodes_on_side(b.nodes, "right").size == 9


def test_nodes_on_side_tolerance_is_relative_to_the_given_nodes():
    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [0.999, 1.0], [0.5, 0.5]])
    assert np.array_equal(nodes_on_side(nodes, "right"), [1])
    assert np.array_equal(nodes_on_side(nodes, "right", tol=0.01), [1, 2])


def test_nodes_in_box_and_near_plane():
    m = box_mesh((0, 0), (2, 2), divisions=(2, 2))
    assert np.array_equal(nodes_in_box(m.nodes, (0, 0), (1, 1)), [0, 1, 3, 4])
    assert np.array_equal(nodes_in_box(m.nodes, (0.01, 0), (1, 1)), [1, 4])
    assert np.array_equal(nodes_in_box(m.nodes, (0.01, 0), (1, 1), tol=0.02), [0, 1, 3, 4])
    diag = nodes_near_plane(m.nodes, (0, 0), (1, -1), 1e-9)
    assert np.array_equal(diag, [0, 4, 8])
    b = box_mesh((0, 0, 0), (1, 1, 1), divisions=2)
    mid = nodes_near_plane(b.nodes, (0, 0, 0.5), (0, 0, 3), 1e-9)
    assert mid.size == 9 and np.allclose(b.nodes[mid, 2], 0.5)


def test_nodes_near_circle_sphere_cylinder():
    ring = ring_mesh((1.0, 1.0), 0.5, 1.0, 20, 4)
    outer = nodes_near_circle(ring.nodes, (1.0, 1.0), 1.0, 1e-9)
    assert outer.size == 20 and np.array_equal(outer, np.arange(80, 100))
    with pytest.raises(ValueError):
        nodes_near_circle(np.zeros((2, 3)), (0, 0), 1.0, 0.1)
    b = box_mesh((-1, -1, -1), (1, 1, 1), divisions=2)
    corners = nodes_near_sphere(b.nodes, (0, 0, 0), np.sqrt(3.0), 1e-9)
    assert corners.size == 8
    cyl = cylinder_mesh((0, 0, 0), "y", 0.3, 1.0, 2.0, 12, 2, 2)
    inner = nodes_near_cylinder(cyl.nodes, (0, 5, 0), "y", 0.3, 1e-9)
    assert inner.size == 12 * 3
    same = nodes_near_cylinder(cyl.nodes, (0, 0, 0), (0, -2, 0), 0.3, 1e-9)
    assert np.array_equal(inner, same)


# ------------------------------------------------------------------ segment selections


def test_segments_on_side_2d():
    m = box_mesh((0, 0), (2, 1), divisions=(4, 3))
    for side, normal, count in [
        ("left", (-1, 0), 3),
        ("right", (1, 0), 3),
        ("bottom", (0, -1), 4),
        ("top", (0, 1), 4),
    ]:
        faces, owner = segments_on_side(m.nodes, m.elements, side)
        assert faces.shape == (count, 2), side
        n = face_normals(m.nodes, faces)
        assert np.allclose(n / np.linalg.norm(n, axis=1)[:, None], normal), side


def test_segments_on_side_3d_and_in_box():
    m = box_mesh((0, 0, 0), (1, 1, 1), divisions=(2, 3, 4))
    faces, owner = segments_on_side(m.nodes, m.elements, "front")
    assert faces.shape == (6, 4)
    n = face_normals(m.nodes, faces)
    assert np.all(n[:, 2] < 0) and np.allclose(n[:, :2], 0.0)
    assert np.all(owner < 6)  # the first z layer
    faces, _ = segments_on_side(m.nodes, m.elements, "back")
    assert np.all(face_normals(m.nodes, faces)[:, 2] > 0)

    # a box around the strip of the x-max face with y <= 1/3: 1 y-division x 4 z-divisions
    faces, owner = segments_in_box(m.nodes, m.elements, (0.9, 0, 0), (1.1, 1 / 3, 1), tol=1e-9)
    assert faces.shape == (4, 4)
    assert np.allclose(m.nodes[faces, 0], 1.0)
    ids = nodes_in_box(m.nodes, (0.9, 0, 0), (1.1, 0.34, 1))
    faces2, owner2 = segments_of_nodes(m.elements, 3, ids)
    assert np.array_equal(faces, faces2) and np.array_equal(owner, owner2)


def test_segments_on_ring_outer_circle():
    ring = ring_mesh((0, 0), 0.0, 1.0, 16, 2)
    ids = nodes_near_circle(ring.nodes, (0, 0), 1.0, 1e-9)
    faces, owner = segments_of_nodes(ring.elements, 2, ids)
    assert faces.shape == (16, 2)
    n = face_normals(ring.nodes, faces)
    assert np.all(np.einsum("ij,ij->i", n, ring.nodes[faces].mean(axis=1)) > 0)
