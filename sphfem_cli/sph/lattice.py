"""SPH particles from geometry: square/cubic lattices filling a box, circle, sphere, polygon, or the
inside of a closed surface (3D) or curve (2D) read from a mesh file.

Every generator puts one particle at the centre of each lattice cell of side ``dx`` whose centre
lies inside the shape, the lattice anchored at the shape's lower bounding-box corner, so a box
[lo, hi] is tiled exactly when (hi - lo)/dx is whole. Mass = density * dx^dim
(``lattice_particles``). ``hydrostatic_density`` gives the density of a liquid at rest under
gravity; ``box_wall_particles`` lays dummy wall particles (Adami et al. 2012) around a box.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

from ..materials.slots import P_RHO0
from .eos import densities_from_pressures


def _grid(lo, hi, dx) -> np.ndarray:
    lo = np.asarray(lo, dtype=np.float64)
    hi = np.asarray(hi, dtype=np.float64)
    counts = np.maximum(np.rint((hi - lo) / dx).astype(int), 0)
    axes = [lo[d] + (np.arange(counts[d]) + 0.5) * dx for d in range(len(lo))]
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.stack([m.ravel() for m in mesh], axis=1) if len(lo) else np.zeros((0, 0))


def box(lo: Sequence[float], hi: Sequence[float], dx: float) -> np.ndarray:
    """Cell centres of the lattice of spacing dx tiling [lo, hi] (2D or 3D); (N, dim)."""
    if len(lo) != len(hi):
        raise ValueError("box corners of different dimension")
    return _grid(lo, hi, dx)


def _ball(center, radius, dx, dim) -> np.ndarray:
    c = np.asarray(center, dtype=np.float64).reshape(dim)
    n = int(np.ceil(2.0 * radius / dx))
    lo = c - 0.5 * n * dx
    pts = _grid(lo, lo + n * dx, dx)
    return pts[np.sum((pts - c) ** 2, axis=1) < radius * radius]


def circle(center: Sequence[float], radius: float, dx: float) -> np.ndarray:
    """2D lattice points inside the circle (lattice centred on it)."""
    return _ball(center, radius, dx, 2)


def sphere(center: Sequence[float], radius: float, dx: float) -> np.ndarray:
    """3D lattice points inside the sphere (lattice centred on it)."""
    return _ball(center, radius, dx, 3)


def inside_polygon(points: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Even-odd (crossing number) test of 2D ``points`` against a closed polygon.

    Points are tested in chunks so that the (points x edges) temporaries stay near 64 MB.
    """
    vx, vy = vertices[:, 0], vertices[:, 1]
    wx, wy = np.roll(vx, -1), np.roll(vy, -1)
    out = np.zeros(len(points), dtype=bool)
    chunk = max(1, 4_000_000 // max(1, len(vx)))
    for s in range(0, len(points), chunk):
        px, py = points[s:s + chunk, 0:1], points[s:s + chunk, 1:2]
        straddle = (vy <= py) != (wy <= py)
        with np.errstate(divide="ignore", invalid="ignore"):
            xcross = vx + (py - vy) * (wx - vx) / (wy - vy)
        hits = straddle & (px < xcross)
        out[s:s + chunk] = (np.count_nonzero(hits, axis=1) % 2) == 1
    return out


def polygon(vertices: Sequence[Sequence[float]], dx: float) -> np.ndarray:
    """2D lattice points inside the polygon (vertices in order, either orientation)."""
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 2)
    lo, hi = v.min(axis=0), v.max(axis=0)
    n = np.ceil((hi - lo) / dx).astype(int)
    pts = _grid(lo, lo + n * dx, dx)
    return pts[inside_polygon(pts, v)]


def closed_boundary(path: str, dim: int, scale: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, faces) of the closed boundary in a mesh file read with meshio.

    3D: the file's triangles and quads (quads split into two triangles), faces (F, 3); 2D: its line
    segments, faces (F, 2). Raises ValueError unless the boundary is closed (3D: every edge shared
    by exactly two triangles; 2D: every vertex used by exactly two segments).
    """
    from ..model.mesh import read_meshio

    mesh = read_meshio(path)
    vertices = np.asarray(mesh.points, dtype=np.float64)[:, :dim] * scale
    faces = []
    for block in mesh.cells:
        if dim == 3 and block.type == "triangle":
            faces.append(block.data)
        elif dim == 3 and block.type == "quad":
            q = block.data
            faces += [q[:, [0, 1, 2]], q[:, [0, 2, 3]]]
        elif dim == 2 and block.type == "line":
            faces.append(block.data)
    want = "triangles or quads" if dim == 3 else "line segments"
    if not faces:
        raise ValueError(f"the file holds no {want} (a closed {'surface' if dim == 3 else 'curve'} is needed)")
    faces = np.vstack(faces).astype(np.int64)
    if dim == 3:
        edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
        _, counts = np.unique(edges, axis=0, return_counts=True)
        if np.any(counts != 2):
            raise ValueError(f"the surface is not closed: {int(np.sum(counts != 2))} edge(s) not shared by exactly two faces")
    else:
        degree = np.bincount(faces.ravel(), minlength=len(vertices))
        used = degree > 0
        if np.any(degree[used] != 2):
            raise ValueError(f"the curve is not closed: {int(np.sum(degree[used] != 2))} vertex(es) not on exactly two segments")
    return vertices, faces


def inside_closed_boundary(points: np.ndarray, vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Points inside a closed surface (3D triangles) or curve (2D segments), by the winding number.

    3D: w = sum over triangles of the solid angle they subtend at the point / 4 pi (Van Oosterom &
    Strackee 1983); 2D: w = sum of the signed angles the segments subtend / 2 pi. Inside where
    |w| > 1/2, whatever the faces' orientation and for several closed pieces (holes count as
    outside when oppositely oriented). One pass over the faces, vectorised over the points.
    """
    pts = np.asarray(points, dtype=np.float64)
    w = np.zeros(len(pts))
    if pts.shape[1] == 3:
        for a, b, c in vertices[faces]:
            ra, rb, rc = a - pts, b - pts, c - pts
            la, lb, lc = (np.linalg.norm(r, axis=1) for r in (ra, rb, rc))
            det = np.einsum("ij,ij->i", ra, np.cross(rb, rc))
            den = (la * lb * lc + np.einsum("ij,ij->i", ra, rb) * lc + np.einsum("ij,ij->i", rb, rc) * la
                   + np.einsum("ij,ij->i", rc, ra) * lb)
            w += 2.0 * np.arctan2(det, den)
        w /= 4.0 * np.pi
    else:
        for a, b in vertices[faces]:
            ra, rb = a - pts, b - pts
            w += np.arctan2(ra[:, 0] * rb[:, 1] - ra[:, 1] * rb[:, 0], np.einsum("ij,ij->i", ra, rb))
        w /= 2.0 * np.pi
    return np.abs(w) > 0.5


def surface_fill(path: str, dim: int, dx: float, scale: float = 1.0, max_points: int | None = None) -> np.ndarray:
    """Lattice points inside the closed boundary in a mesh file (see ``closed_boundary``); (N, dim).

    The lattice is anchored at the boundary's lower bounding-box corner, as for the other shapes.
    ValueError, before anything is allocated, if the bounding box's lattice exceeds ``max_points``.
    """
    vertices, faces = closed_boundary(path, dim, scale)
    used = vertices[np.unique(faces)]
    lo, hi = used.min(axis=0), used.max(axis=0)
    with np.errstate(over="ignore", invalid="ignore"):
        cells = np.ceil((hi - lo) / dx)
        count = float(np.prod(cells))
    if not np.all(np.isfinite(cells)) or (max_points is not None and count > max_points):
        raise ValueError(f"spacing {dx:g} makes a lattice of {count:.3g} points in the surface's bounding box, "
                         f"more than the {max_points} the available memory holds (coarsen the spacing)")
    n = cells.astype(int)
    pts = _grid(lo, lo + n * dx, dx)
    keep = np.zeros(len(pts), dtype=bool)
    chunk = 200_000
    for s in range(0, len(pts), chunk):
        keep[s:s + chunk] = inside_closed_boundary(pts[s:s + chunk], vertices, faces)
    return pts[keep]


def lattice_particles(points: np.ndarray, dx: float, density) -> tuple[np.ndarray, np.ndarray]:
    """``(mass, density)`` arrays for lattice points of spacing dx: m_i = rho_i dx^dim.

    ``density`` is a scalar or one value per point (e.g. ``hydrostatic_density``): giving each
    particle the mass of its own lattice cell at its own density makes the SPH sums of the
    initial state consistent (summation density = particle density), so a hydrostatic start is
    close to a discrete equilibrium.
    """
    n, dim = points.shape
    rho = np.broadcast_to(np.asarray(density, dtype=np.float64), (n,)).copy()
    return rho * dx**dim, rho


def hydrostatic_density(points: np.ndarray, params: np.ndarray, material: np.ndarray, gravity: Sequence[float],
                        surface_point: Sequence[float]) -> np.ndarray:
    """Density of a liquid at rest under ``gravity`` with its free surface through ``surface_point``.

    p = rho0 g.(x - x_surface) (clamped at 0 above the surface) and rho from the inverse of each
    particle's EOS (``params`` rows, ``material`` indices) at its initial energy.
    """
    pts = np.asarray(points, dtype=np.float64)
    dim = pts.shape[1]
    g = np.asarray(gravity, dtype=np.float64).reshape(-1)[:dim]
    s = np.asarray(surface_point, dtype=np.float64).reshape(-1)[:dim]
    mat = np.asarray(material, dtype=np.int64).reshape(len(pts))
    rho0 = params[mat, P_RHO0]
    with np.errstate(over="ignore", invalid="ignore"):  # an overflowing column is model.checks' deck error
        pressure = np.maximum(rho0 * ((pts - s) @ g), 0.0)
    out = np.empty(len(pts))
    densities_from_pressures(pressure, mat, np.ascontiguousarray(params, dtype=np.float64), out)
    return out


def box_wall_particles(lo: Sequence[float], hi: Sequence[float], dx: float, layers: int = 3,
                       sides: Sequence[str] = ("left", "right", "bottom")) -> np.ndarray:
    """Dummy wall particles filling ``layers`` lattice layers outside the named faces of [lo, hi]
    ('left'/'right' x, 'bottom'/'top' y, 'back'/'front' z), corners included; (Nw, dim)."""
    lo = np.asarray(lo, dtype=np.float64)
    hi = np.asarray(hi, dtype=np.float64)
    dim = len(lo)
    faces = {"left": (0, 0), "right": (0, 1), "bottom": (1, 0), "top": (1, 1), "back": (2, 0), "front": (2, 1)}
    ext_lo, ext_hi = lo.copy(), hi.copy()
    for s in sides:
        axis, which = faces[s]
        if which == 0:
            ext_lo[axis] -= layers * dx
        else:
            ext_hi[axis] += layers * dx
    pts = _grid(ext_lo, ext_hi, dx)
    inside = np.all((pts > lo) & (pts < hi), axis=1)
    keep = ~inside
    for d in range(dim):  # drop the layers beyond faces that carry no wall
        keep &= (pts[:, d] > ext_lo[d]) & (pts[:, d] < ext_hi[d])
    return pts[keep]
