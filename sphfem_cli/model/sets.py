"""Node and boundary-segment selection (numpy only).

Node selections return sorted, unique int64 node indices. Segment selections return
``(faces, owner)`` like :func:`boundary_faces`.

Segment orientation (the convention contact and pressure loads rely on):

- 2D: a segment is a node pair ``(a, b)`` taken in the owning quad's counter-clockwise order,
  so the outward normal is ``(dy, -dx)`` with ``(dx, dy) = x_b - x_a``.
- 3D: a segment is a quad ``(a, b, c, d)`` ordered so that the right-hand normal
  ``(x_c - x_a) x (x_d - x_b)`` points out of the owning hex.

Sides: ``left``/``right`` are x-min/x-max, ``bottom``/``top`` y-min/y-max, and in 3D
``front``/``back`` z-min/z-max, each meaning the extreme coordinate *of the nodes given*
within ``tol``.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

__all__ = [
    "boundary_faces",
    "nodes_in_box",
    "nodes_on_side",
    "nodes_near_plane",
    "nodes_near_circle",
    "nodes_near_sphere",
    "nodes_near_cylinder",
    "segments_of_nodes",
    "segments_on_side",
    "segments_in_box",
    "SIDES",
]

# Local faces with outward orientation (quad4 CCW; hex8 VTK order).
_QUAD_EDGES = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
_HEX_FACES = np.array(
    [
        [0, 3, 2, 1],  # bottom (-zeta)
        [4, 5, 6, 7],  # top (+zeta)
        [0, 1, 5, 4],  # -eta
        [1, 2, 6, 5],  # +xi
        [2, 3, 7, 6],  # +eta
        [3, 0, 4, 7],  # -xi
    ]
)

#: side name -> (coordinate axis, +1 for the maximum / -1 for the minimum)
SIDES = {
    "left": (0, -1),
    "right": (0, 1),
    "bottom": (1, -1),
    "top": (1, 1),
    "front": (2, -1),
    "back": (2, 1),
}


def boundary_faces(elements: np.ndarray, dim: int) -> tuple[np.ndarray, np.ndarray]:
    """Exterior faces of a quad4 (``dim=2``) or hex8 (``dim=3``) mesh.

    A face is exterior when no other element has a face with the same node set. Returns
    ``faces`` int64 ``(F, 2)`` in 2D / ``(F, 4)`` in 3D, oriented with the outward normal as in
    the module docstring, and ``owner`` int64 ``(F,)``, the element each face belongs to.
    Faces come ordered by owner, then by local face number.
    """
    elements = np.asarray(elements, dtype=np.int64)
    if dim == 2:
        local = _QUAD_EDGES
    elif dim == 3:
        local = _HEX_FACES
    else:
        raise ValueError(f"dim must be 2 or 3, got {dim!r}")
    if elements.ndim != 2 or elements.shape[1] != (4 if dim == 2 else 8):
        raise ValueError(f"elements of shape {elements.shape} do not match dim={dim}")
    nf = local.shape[0]
    faces = elements[:, local].reshape(-1, local.shape[1])  # element-major
    if faces.shape[0] == 0:
        return faces, np.zeros(0, dtype=np.int64)
    picked = np.flatnonzero(_exterior(faces, dim))
    return faces[picked], (picked // nf).astype(np.int64)


def exterior_faces(elements: np.ndarray, dim: int) -> np.ndarray:
    """(E, 4) in 2D / (E, 6) in 3D bool: which local faces of each element are exterior.

    Local faces in the order of the module's tables; opposite faces are (0, 2), (1, 3) in 2D and
    (0, 1), (2, 4), (3, 5) in 3D (OPPOSITE_FACES).
    """
    elements = np.asarray(elements, dtype=np.int64)
    local = _QUAD_EDGES if dim == 2 else _HEX_FACES
    faces = elements[:, local].reshape(-1, local.shape[1])
    if faces.shape[0] == 0:
        return np.zeros((0, local.shape[0]), dtype=bool)
    return _exterior(faces, dim).reshape(len(elements), local.shape[0])


OPPOSITE_FACES = {2: ((0, 2), (1, 3)), 3: ((0, 1), (2, 4), (3, 5))}


def _exterior(faces: np.ndarray, dim: int) -> np.ndarray:
    """Mask of the faces (rows of node ids) no other face shares the node set of."""
    key = np.sort(faces, axis=1)
    base = np.int64(key.max()) + 1
    if dim == 2:
        keys = (key[:, 1] * base + key[:, 0],)  # lexsort: last key is primary
    else:
        keys = (key[:, 3] * base + key[:, 2], key[:, 1] * base + key[:, 0])
    order = np.lexsort(keys)
    sorted_keys = [k[order] for k in keys]
    same_as_next = np.ones(order.size - 1, dtype=bool)
    for k in sorted_keys:
        same_as_next &= k[1:] == k[:-1]
    unique = np.ones(order.size, dtype=bool)
    unique[1:] &= ~same_as_next
    unique[:-1] &= ~same_as_next
    mask = np.zeros(order.size, dtype=bool)
    mask[order[unique]] = True
    return mask


def _default_tol(nodes: np.ndarray, tol: float | None) -> float:
    if tol is not None:
        return float(tol)
    if nodes.shape[0] == 0:
        return 0.0
    span = np.array([np.ptp(nodes[:, k]) for k in range(nodes.shape[1])])  # per column: 20x np.ptp(axis=0)
    return 1.0e-6 * float(np.linalg.norm(span))


def nodes_in_box(
    nodes: np.ndarray, lo: Sequence[float], hi: Sequence[float], tol: float = 0.0
) -> np.ndarray:
    """Nodes with ``lo - tol <= x <= hi + tol`` in every coordinate."""
    nodes = np.asarray(nodes, dtype=np.float64)
    lo = np.asarray(lo, dtype=np.float64)
    hi = np.asarray(hi, dtype=np.float64)
    if lo.shape != (nodes.shape[1],) or hi.shape != lo.shape:
        raise ValueError(f"lo and hi need {nodes.shape[1]} entries for {nodes.shape[1]}D nodes")
    inside = np.all((nodes >= lo - tol) & (nodes <= hi + tol), axis=1)
    return np.flatnonzero(inside).astype(np.int64)


def nodes_on_side(nodes: np.ndarray, side: str, tol: float | None = None) -> np.ndarray:
    """Nodes whose coordinate is within ``tol`` of the extreme of ``nodes`` on ``side``.

    ``side`` is one of ``left right bottom top`` (x-min, x-max, y-min, y-max), and in 3D also
    ``front back`` (z-min, z-max). ``tol`` defaults to 1e-6 times the bounding-box diagonal.
    """
    nodes = np.asarray(nodes, dtype=np.float64)
    if side not in SIDES:
        raise ValueError(f"unknown side {side!r}; expected one of {', '.join(SIDES)}")
    axis, sign = SIDES[side]
    if axis >= nodes.shape[1]:
        raise ValueError(f"side {side!r} needs 3D nodes")
    if nodes.shape[0] == 0:
        return np.zeros(0, dtype=np.int64)
    tol = _default_tol(nodes, tol)
    x = nodes[:, axis]
    if sign > 0:
        mask = x >= x.max() - tol
    else:
        mask = x <= x.min() + tol
    return np.flatnonzero(mask).astype(np.int64)


def nodes_near_plane(
    nodes: np.ndarray, point: Sequence[float], normal: Sequence[float], tol: float
) -> np.ndarray:
    """Nodes within ``tol`` of the plane (a line in 2D) through ``point`` normal to ``normal``."""
    nodes = np.asarray(nodes, dtype=np.float64)
    n = np.asarray(normal, dtype=np.float64)
    norm = np.linalg.norm(n)
    if n.shape != (nodes.shape[1],) or norm == 0:
        raise ValueError(f"normal must be a non-zero {nodes.shape[1]}-vector, got {normal!r}")
    dist = (nodes - np.asarray(point, dtype=np.float64)) @ (n / norm)
    return np.flatnonzero(np.abs(dist) <= tol).astype(np.int64)


def nodes_near_sphere(
    nodes: np.ndarray, center: Sequence[float], radius: float, tol: float
) -> np.ndarray:
    """Nodes within ``tol`` of the sphere (circle for 2D nodes) of ``radius`` about ``center``."""
    nodes = np.asarray(nodes, dtype=np.float64)
    c = np.asarray(center, dtype=np.float64)
    if c.shape != (nodes.shape[1],):
        raise ValueError(f"center needs {nodes.shape[1]} entries, got {center!r}")
    r = np.linalg.norm(nodes - c, axis=1)
    return np.flatnonzero(np.abs(r - radius) <= tol).astype(np.int64)


def nodes_near_circle(
    nodes: np.ndarray, center: Sequence[float], radius: float, tol: float
) -> np.ndarray:
    """2D nodes within ``tol`` of the circle of ``radius`` about ``center``."""
    nodes = np.asarray(nodes, dtype=np.float64)
    if nodes.shape[1] != 2:
        raise ValueError("nodes_near_circle takes 2D nodes; use nodes_near_cylinder in 3D")
    return nodes_near_sphere(nodes, center, radius, tol)


def nodes_near_cylinder(
    nodes: np.ndarray, center: Sequence[float], axis: Sequence[float] | str, radius: float,
    tol: float,
) -> np.ndarray:
    """3D nodes within ``tol`` of the infinite cylinder of ``radius`` about the line through
    ``center`` along ``axis`` (a 3-vector or ``'x'``, ``'y'``, ``'z'``)."""
    nodes = np.asarray(nodes, dtype=np.float64)
    if nodes.shape[1] != 3:
        raise ValueError("nodes_near_cylinder takes 3D nodes")
    if isinstance(axis, str):
        a = np.zeros(3)
        a["xyz".index(axis)] = 1.0
    else:
        a = np.asarray(axis, dtype=np.float64)
    if a.shape != (3,) or np.linalg.norm(a) == 0:
        raise ValueError(f"axis must be 'x', 'y', 'z' or a non-zero 3-vector, got {axis!r}")
    a = a / np.linalg.norm(a)
    d = nodes - np.asarray(center, dtype=np.float64)
    radial = d - np.outer(d @ a, a)
    r = np.linalg.norm(radial, axis=1)
    return np.flatnonzero(np.abs(r - radius) <= tol).astype(np.int64)


def segments_of_nodes(
    elements: np.ndarray, dim: int, node_ids: np.ndarray, n_nodes: int | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Boundary faces (see :func:`boundary_faces`) whose nodes all lie in ``node_ids``."""
    faces, owner = boundary_faces(elements, dim)
    size = n_nodes if n_nodes is not None else int(np.max(elements, initial=-1)) + 1
    member = np.zeros(max(size, 1), dtype=bool)
    member[np.asarray(node_ids, dtype=np.int64)] = True
    keep = np.all(member[faces], axis=1)
    return faces[keep], owner[keep]


def segments_on_side(
    nodes: np.ndarray, elements: np.ndarray, side: str, tol: float | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Boundary faces whose nodes all lie on ``side`` (see :func:`nodes_on_side`).

    The side's extreme is taken over all ``nodes``; ``dim`` is ``nodes.shape[1]``.
    """
    nodes = np.asarray(nodes, dtype=np.float64)
    ids = nodes_on_side(nodes, side, tol)
    return segments_of_nodes(elements, nodes.shape[1], ids, nodes.shape[0])


def segments_in_box(
    nodes: np.ndarray,
    elements: np.ndarray,
    lo: Sequence[float],
    hi: Sequence[float],
    tol: float = 0.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Boundary faces whose nodes all lie in the box (see :func:`nodes_in_box`)."""
    nodes = np.asarray(nodes, dtype=np.float64)
    ids = nodes_in_box(nodes, lo, hi, tol)
    return segments_of_nodes(elements, nodes.shape[1], ids, nodes.shape[0])
