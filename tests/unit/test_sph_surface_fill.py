"""SPH parts filled from the inside of a closed surface (3D) or curve (2D) in a mesh file.

The winding-number test (sph.lattice.inside_closed_boundary) against exact shapes: a sphere
triangulated from an icosahedron and a cube of quads (3D, STL/VTU written with meshio), a circle as
a closed polyline (2D). Checks: the particle volume N dx^dim against the shape's volume, agreement
with the analytic fills (box, ball) and error messages for open boundaries.
"""
from __future__ import annotations

import math

import meshio
import numpy as np
import pytest

from sphfem_cli.sph import lattice


def _icosphere(radius: float, levels: int) -> tuple[np.ndarray, np.ndarray]:
    t = (1.0 + math.sqrt(5.0)) / 2.0
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7),
         (9, 8, 1)]
    verts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    faces = f
    for _ in range(levels):
        mid, new = {}, []

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                m = verts[a] + verts[b]
                verts.append(m / np.linalg.norm(m))
                mid[key] = len(verts) - 1
            return mid[key]

        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return radius * np.array(verts), np.array(faces)


def test_sphere_surface_fills_like_the_analytic_ball(tmp_path):
    radius, dx = 0.5, 0.05
    verts, faces = _icosphere(radius, 3)  # 1 280 triangles, chord error 0.3 % of the radius
    path = tmp_path / "ball.stl"
    meshio.write_points_cells(str(path), verts, [("triangle", faces)])
    pts = lattice.surface_fill(str(path), 3, dx)
    volume = len(pts) * dx**3
    assert volume == pytest.approx(4.0 / 3.0 * math.pi * radius**3, rel=0.03)
    assert np.all(np.linalg.norm(pts, axis=1) < radius)
    # The same lattice as the analytic ball, up to the points between the facets and the sphere.
    ball = lattice.sphere([0.0, 0.0, 0.0], radius, dx)
    assert len(ball) - len(pts) <= 0.03 * len(ball)


def test_quad_surface_of_a_box_gives_the_box_lattice(tmp_path):
    lo, hi, dx = np.array([0.0, 0.0, 0.0]), np.array([0.4, 0.2, 0.3]), 0.05
    corners = np.array([[lo[0] if i & 1 == 0 else hi[0], lo[1] if i & 2 == 0 else hi[1], lo[2] if i & 4 == 0 else hi[2]]
                        for i in range(8)])
    quads = np.array([[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]])
    path = tmp_path / "box.vtu"
    meshio.write_points_cells(str(path), corners, [("quad", quads)])
    pts = lattice.surface_fill(str(path), 3, dx)
    expected = lattice.box(lo, hi, dx)
    assert len(pts) == len(expected)
    np.testing.assert_allclose(np.sort(pts, axis=0), np.sort(expected, axis=0))


def test_closed_polyline_in_2d_and_a_hole(tmp_path):
    n, radius, dx = 256, 0.3, 0.01
    angle = 2 * math.pi * np.arange(n) / n
    outer = np.column_stack([radius * np.cos(angle), radius * np.sin(angle), np.zeros(n)])
    inner = 0.5 * outer[::-1]  # opposite orientation: a hole
    points = np.vstack([outer, inner])
    segments = np.vstack([np.column_stack([np.arange(n), (np.arange(n) + 1) % n]),
                          n + np.column_stack([np.arange(n), (np.arange(n) + 1) % n])])
    path = tmp_path / "ring.vtu"
    meshio.write_points_cells(str(path), points, [("line", segments)])
    pts = lattice.surface_fill(str(path), 2, dx)
    area = len(pts) * dx**2
    assert area == pytest.approx(math.pi * (radius**2 - (0.5 * radius) ** 2), rel=0.02)
    r = np.linalg.norm(pts, axis=1)
    assert r.min() > 0.5 * radius * math.cos(math.pi / n) - 1e-12 and r.max() < radius


def test_open_boundaries_are_refused(tmp_path):
    verts, faces = _icosphere(1.0, 1)
    path = tmp_path / "open.stl"
    meshio.write_points_cells(str(path), verts, [("triangle", faces[:-1])])
    with pytest.raises(ValueError, match="not closed"):
        lattice.surface_fill(str(path), 3, 0.1)
    path2 = tmp_path / "open.vtu"
    meshio.write_points_cells(str(path2), np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.0]]), [("line", np.array([[0, 1], [1, 2]]))])
    with pytest.raises(ValueError, match="not closed"):
        lattice.surface_fill(str(path2), 2, 0.1)


def test_sph_part_from_a_surface_file_through_the_deck(tmp_path, model_from_deck):
    verts, faces = _icosphere(0.1, 2)
    meshio.write_points_cells(str(tmp_path / "drop.stl"), verts + 0.2, [("triangle", faces)])
    model = model_from_deck({
        "dimension": 3,
        "control": {"end_time": 0.01},
        "equations_of_state": {"water": {"type": "tait", "reference_density": 1000.0, "sound_speed": 20.0}},
        "materials": {"water": {"type": "fluid", "density": 1000.0, "eos": "water"}},
        "sections": {"fluid": {"type": "sph"}},
        "parts": {"drop": {"material": "water", "section": "fluid", "spacing": 0.02,
                           "geometry": {"file": {"file": "drop.stl"}}}},
    })
    ps = model.particles
    assert ps.n > 0 and np.all(np.linalg.norm(ps.x - 0.2, axis=1) < 0.1)
    assert ps.mass.sum() == pytest.approx(1000.0 * 4.0 / 3.0 * math.pi * 0.1**3, rel=0.1)
