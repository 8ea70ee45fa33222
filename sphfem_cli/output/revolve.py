"""The revolved 3D view of an axisymmetric part (deck ``output.revolve``): the meridian grid swept about its axis.

Axis convention: the meridian plane has x = r >= 0 and y = the axis. A meridian point (r, y) at sweep angle a
is the 3D point

    X = r cos a,   Y = r sin a,   Z = y            (the axis is 3D z; a = 0 is the 3D x-z plane)

with a_k = k * angle / segments, k = 0 .. K-1, K = segments for a closed 360-degree sweep (the last ring of
cells closes onto k = 0) and K = segments + 1 for a partial one. Revolved points are numbered ring-major:
point k * N + n is meridian point n at angle a_k.

Cells. A quad4 (n0, n1, n2, n3), counter-clockwise in (r, y), sweeps between a_k and a_k+1 to the hex8
(VTK order)

    (n0, n1, n2, n3) at a_k+1,  (n0, n1, n2, n3) at a_k

numbered k * E + e: the counter-clockwise quad's normal r x y = X x Z = -Y points from a_k+1 toward a_k, so
this order gives VTK's positive orientation (bottom face normal toward the top face). A quad with nodes on the axis (r = 0) gives a collapsed hex: its axis nodes have the
same coordinates at every angle, so the hex has zero-length edges there (a wedge drawn as a hex; VTK and
ParaView draw and integrate it, its volume is that of the wedge). The points are not merged, so the
connectivity and point data keep one layout for every cell. Particles (Polyvertex) become one point per
particle and angle, every point a cell.

Fields (meridian components r, y(axis), and for 3-vectors the hoop component t):

    vectors   (v_r, v_y, v_t)  ->  (v_r cos a - v_t sin a,  v_r sin a + v_t cos a,  v_y)
    tensors   code order xx, yy, zz, xy, yz, zx read as rr, yy(axial), tt(hoop), ry, y t, t r; with the
              rotation R(a) = [[c, -s, 0], [s, c, 0], [0, 0, 1]] from (r, t, y) to (X, Y, Z),
              sigma' = R sigma R^T:
                  XX = rr c^2 + tt s^2 - 2 tr s c     YY = rr s^2 + tt c^2 + 2 tr s c     ZZ = yy
                  XY = (rr - tt) s c + tr (c^2 - s^2)  YZ = ry s + yt c                    ZX = ry c - yt s
    scalars   copied to every angle.

The hoop rotation matrix and these component formulas are those of any cylindrical-to-Cartesian tensor
transformation (e.g. Malvern, Introduction to the Mechanics of a Continuous Medium, 1969, sec. 2.5).

Cost: every revolved dataset is K times its meridian dataset (K * E cells for a mesh), written at every field
step, so a 24-segment view multiplies the part's share of results.h5 by about 25.
"""
from __future__ import annotations

import numpy as np

__all__ = ["angles", "revolve_connectivity", "revolve_points", "revolve_point_field", "revolve_cell_field",
           "revolve_vectors", "revolve_tensors", "REVOLVED_SUFFIX"]

from .xdmf import REVOLVED as REVOLVED_SUFFIX
"""A part's revolved grid is named ``<part>.revolved`` (results.<part>.revolved.xdmf, group /<part>.revolved)."""


def angles(segments: int, angle_deg: float) -> tuple[np.ndarray, bool]:
    """The sweep angles a_k [rad] and whether the sweep is closed (360 degrees: the last cells join k = 0)."""
    closed = abs(angle_deg - 360.0) < 1e-9
    n = segments if closed else segments + 1
    return np.arange(n) * np.deg2rad(angle_deg) / segments, closed


def revolve_connectivity(topology: str, connectivity: np.ndarray, n_points: int, segments: int,
                         closed: bool) -> tuple[str, np.ndarray | None]:
    """The revolved grid's topology and connectivity: Quadrilateral -> Hexahedron (k * E + e), Polyvertex ->
    Polyvertex (None: every point a cell)."""
    if topology == "Polyvertex":
        return "Polyvertex", None
    if topology != "Quadrilateral":
        raise ValueError(f"only quad4 meshes and particles revolve, not {topology}")
    conn = np.asarray(connectivity, dtype=np.int64)
    k = np.arange(segments, dtype=np.int64)
    k1 = (k + 1) % segments if closed else k + 1
    lower = conn[None, :, :] + (k * n_points)[:, None, None]
    upper = conn[None, :, :] + (k1 * n_points)[:, None, None]
    return "Hexahedron", np.concatenate([upper, lower], axis=2).reshape(-1, 8)


def revolve_points(xy: np.ndarray, a: np.ndarray) -> np.ndarray:
    """(N, 2|3) meridian coordinates (r, y) -> (K N, 3) points (r cos a, r sin a, y), ring-major."""
    r, y = xy[:, 0], xy[:, 1]
    c, s = np.cos(a)[:, None], np.sin(a)[:, None]
    return np.stack([c * r, s * r, np.broadcast_to(y, (len(a), len(y)))], axis=2).reshape(-1, 3)


def revolve_vectors(v: np.ndarray, a: np.ndarray) -> np.ndarray:
    """(M, 2|3) meridian vectors (v_r, v_y[, v_t]) -> (K M, 3) Cartesian vectors (module docstring)."""
    vr, vy = v[:, 0], v[:, 1]
    vt = v[:, 2] if v.shape[1] > 2 else np.zeros_like(vr)
    c, s = np.cos(a)[:, None], np.sin(a)[:, None]
    return np.stack([vr * c - vt * s, vr * s + vt * c, np.broadcast_to(vy, (len(a), len(vy)))],
                    axis=2).reshape(-1, 3)


def revolve_tensors(t: np.ndarray, a: np.ndarray) -> np.ndarray:
    """(M, 6) meridian tensors in code order (rr, yy, tt, ry, yt, tr) -> (K M, 6) Cartesian tensors in code
    order (XX, YY, ZZ, XY, YZ, ZX), sigma' = R sigma R^T (module docstring)."""
    rr, yy, tt, ry, yt, tr = (t[:, i] for i in range(6))
    c, s = np.cos(a)[:, None], np.sin(a)[:, None]
    out = np.empty((len(a), t.shape[0], 6))
    out[..., 0] = rr * c * c + tt * s * s - 2.0 * tr * s * c
    out[..., 1] = rr * s * s + tt * c * c + 2.0 * tr * s * c
    out[..., 2] = yy
    out[..., 3] = (rr - tt) * s * c + tr * (c * c - s * s)
    out[..., 4] = ry * s + yt * c
    out[..., 5] = ry * c - yt * s
    return out.reshape(-1, 6)


def _revolve_field(values: np.ndarray, a: np.ndarray, copies: int) -> np.ndarray:
    v = np.asarray(values)
    if v.ndim == 2 and v.shape[1] == 1:
        v = v[:, 0]
    if v.ndim == 1:
        return np.tile(v, copies)
    if v.shape[1] in (2, 3):
        return revolve_vectors(v, a[:copies])
    if v.shape[1] == 6:
        return revolve_tensors(v, a[:copies])
    raise ValueError(f"a field of shape {v.shape} does not revolve")


def revolve_point_field(values: np.ndarray, a: np.ndarray) -> np.ndarray:
    """A point field at every angle a_k (scalars copied, vectors and tensors rotated), ring-major."""
    return _revolve_field(values, a, len(a))


def revolve_cell_field(values: np.ndarray, a: np.ndarray, segments: int) -> np.ndarray:
    """A cell field on the `segments` cell rings: ring k takes the rotation of its mid-angle
    (a_k + a_k+1) / 2, which is where the hex's centroid lies."""
    step = a[1] - a[0]
    return _revolve_field(values, a[:segments] + 0.5 * step, segments)
