"""ALE mesh motion: where the remap puts the mesh after each Lagrangian phase.

Eulerian (back to the start), or the Lagrangian mesh smoothed: the mean of the edge neighbours
(Benson 1992 sec. 3), Winslow's equipotential point (Winslow 1967; Benson 1992 sec. 3.3) or
uniform motion along straight mesh lines (the paper's section 5; LS-DYNA *ALE_SMOOTHING), with
sliding straight sides and a pull back towards the start. Numpy only; options: ``options.MeshMotion``.
Equations: docs/theory/ale.md, "Mesh motion".
"""
from __future__ import annotations

import math

import numpy as np

from .options import AXES, MeshMotion
from .topology import hex_edges


class MeshMover:
    """The mesh target of ``MeshMotion`` on one mesh (start x0 (N, dim), conn, ``build_topology`` maps)."""

    def __init__(self, motion: MeshMotion, x0: np.ndarray, conn: np.ndarray, topo: dict):
        dim = x0.shape[1]
        n_nodes = x0.shape[0]
        if dim == 3 and motion.mesh_motion == "smoothed" and (motion.smoothing == "equipotential"
                                                               or motion.smoothing_boundary != "fixed"):
            raise ValueError("3D smoothed meshes take smoothing 'average' or 'straight_lines' with fixed boundary nodes only")
        self.motion = motion
        self.x0 = x0
        fn = topo["face_nodes"]
        edges = fn if dim == 2 else hex_edges(conn)
        self._nbr_a = np.concatenate([edges[:, 0], edges[:, 1]])
        self._nbr_b = np.concatenate([edges[:, 1], edges[:, 0]])
        self._degree = np.bincount(self._nbr_a, minlength=n_nodes).astype(float)
        self.line_axis = AXES.index(motion.line_axis)
        if motion.mesh_motion == "smoothed" and motion.smoothing == "straight_lines":
            if not 0 <= self.line_axis < dim:
                raise ValueError(f"line_axis {motion.line_axis} is not an axis of a {dim}D mesh")
            self.lines = _straight_lines(x0, edges, self.line_axis)
        on_boundary = np.zeros(n_nodes, dtype=bool)
        bf = fn[topo["face_elem"][:, 1] < 0]
        on_boundary[bf.ravel()] = True
        self._interior = ~on_boundary
        self._stencil = (np.zeros(0, dtype=np.int64), np.zeros((0, 8), dtype=np.int64))
        if dim == 2:
            if motion.mesh_motion == "smoothed" and motion.smoothing == "equipotential":  # its only user
                self._stencil = _winslow_stencil(conn, n_nodes, self._interior)
            self._slide = _sliding_nodes(x0, bf, n_nodes)
        else:
            self._slide = (np.zeros(0, dtype=np.int64),) * 3 + (np.zeros((0, 3)),)

    def target(self, x_lag: np.ndarray) -> np.ndarray:
        """Where the remap puts the mesh: its start (Eulerian), or a smoothed Lagrangian mesh.

        "smoothed": starting from x_lag, smoothing_iterations Jacobi passes move each interior node a
        fraction smoothing_weight towards its target: the mean of its edge neighbours (smoothing
        "average", Benson 1992 sec. 3) or the Winslow equipotential point (smoothing
        "equipotential", Winslow 1967; interior nodes with four elements, the others averaged).
        Boundary nodes: "fixed" back to their start; "sliding" (nodes inside a straight side) on
        that side's line, moved the same fraction towards the mean of their two boundary
        neighbours, corners fixed. Last, every moving node goes a fraction eulerian_pull back
        towards its start (which bounds the drift of a mesh in a steady stream).
        """
        mo = self.motion
        if mo.mesh_motion == "eulerian":
            return self.x0.copy()
        if mo.smoothing == "straight_lines":
            return self._straight_line_target(x_lag)
        inner = self._interior
        w = mo.smoothing_weight
        x = x_lag.copy()
        ids, nb0, nb1, tang = self._slide
        sliding = mo.smoothing_boundary == "sliding" and ids.size > 0
        for _ in range(mo.smoothing_iterations):
            mean = np.zeros_like(x)
            np.add.at(mean, self._nbr_a, x[self._nbr_b])
            mean /= self._degree[:, None]
            target = mean
            if mo.smoothing == "equipotential":
                target = _winslow_target(x, mean, self._stencil)
            x_prev = x.copy()
            x[inner] = x[inner] + w * (target[inner] - x[inner])
            x[~inner] = self.x0[~inner]
            if sliding:
                # on the side's line through x0, moved along it towards the boundary neighbours' mean
                s_pos = ((x_prev[ids] - self.x0[ids]) * tang).sum(axis=1)
                s_mean = ((0.5 * (x_prev[nb0] + x_prev[nb1]) - self.x0[ids]) * tang).sum(axis=1)
                x[ids] = self.x0[ids] + (s_pos + w * (s_mean - s_pos))[:, None] * tang
        moving = inner.copy()
        if sliding:
            moving[ids] = True
        x_new = self.x0.copy()
        x_new[moving] = x[moving] + mo.eulerian_pull * (self.x0[moving] - x[moving])
        return x_new

    def _straight_line_target(self, x_lag: np.ndarray) -> np.ndarray:
        """Smoothing "straight_lines": nodes move uniformly along the straight mesh lines along
        ``line_axis`` (the paper's section 5; LS-DYNA *ALE_SMOOTHING keeps a node at its initial
        parametric place between two master nodes).

        Every node moves along its line only (along the axis; the other coordinates keep their
        start): a line's two end nodes by the axis component of their Lagrangian displacement,
        the nodes inside it to their initial parameter s between the ends,
        x = x_a + s (x_b - x_a). So the mesh follows the material along the lines (a free surface
        at a line's end, a column compressed along them) and stays as straight and as evenly
        spread as it started; across the lines it is Eulerian. Last, every node goes a fraction
        eulerian_pull back towards its start.
        """
        ax = self.line_axis
        x = self.x0.copy()
        x[:, ax] = x_lag[:, ax]
        ids, a, b, s = self.lines
        x[ids] = x[a] + s[:, None] * (x[b] - x[a])
        return x + self.motion.eulerian_pull * (self.x0 - x)


def _winslow_stencil(conn: np.ndarray, n_nodes: int, interior: np.ndarray) -> tuple:
    """Logical neighbours of the interior nodes that have exactly four elements.

    Returns (ids, nbr) with nbr (len(ids), 8) = east, north, west, south, north-east, north-west,
    south-west, south-east: the elements around a node are chained counter-clockwise (the next
    element's first edge neighbour is this one's last), its edge neighbours in that order are
    E, N, W, S and the diagonal corners between them NE, NW, SW, SE. Which direction is "east"
    does not matter: the Winslow point is the same for each of the four choices.
    """
    a = np.arange(4 * conn.shape[0])
    e, k = a // 4, a % 4
    node = conn[e, k]
    valence = np.bincount(node, minlength=n_nodes)
    ok = interior & (valence == 4)
    ids = np.flatnonzero(ok)
    if ids.size == 0:
        return ids, np.zeros((0, 8), dtype=np.int64)
    sel = ok[node]
    order = np.argsort(node[sel], kind="stable")
    es, ks = e[sel][order].reshape(-1, 4), k[sel][order].reshape(-1, 4)
    c1 = conn[es, (ks + 1) % 4]
    c2 = conn[es, (ks + 2) % 4]
    c3 = conn[es, (ks + 3) % 4]
    nxt = np.argmax(c1[:, None, :] == c3[:, :, None], axis=2)  # nxt[n, i]: element after element i
    r = np.arange(ids.size)
    o = [np.zeros(ids.size, dtype=np.int64)]
    for _ in range(3):
        o.append(nxt[r, o[-1]])
    edges = [c1[r, j] for j in o]
    diags = [c2[r, j] for j in o]
    return ids, np.stack(edges + diags, axis=1).astype(np.int64)


def _winslow_target(x: np.ndarray, fallback: np.ndarray, stencil: tuple) -> np.ndarray:
    """Jacobi point of the Winslow (equipotential) equations alpha x_xixi - 2 beta x_xieta + gamma x_etaeta = 0.

    alpha = |x_eta|^2, beta = x_xi . x_eta, gamma = |x_xi|^2 with central differences on the
    logical stencil (Winslow 1967; Benson 1992 sec. 3.3): x = [alpha (x_E + x_W) + gamma (x_N + x_S)
    - beta/2 (x_NE - x_NW + x_SW - x_SE)] / (2 (alpha + gamma)). Nodes outside the stencil keep
    ``fallback``.
    """
    ids, nb = stencil
    out = fallback.copy()
    if ids.size == 0:
        return out
    xe, xn, xw, xs, xne, xnw, xsw, xse = (x[nb[:, j]] for j in range(8))
    x_xi = 0.5 * (xe - xw)
    x_eta = 0.5 * (xn - xs)
    alpha = (x_eta ** 2).sum(axis=1)[:, None]
    gamma = (x_xi ** 2).sum(axis=1)[:, None]
    beta = (x_xi * x_eta).sum(axis=1)[:, None]
    out[ids] = (alpha * (xe + xw) + gamma * (xn + xs) - 0.5 * beta * (xne - xnw + xsw - xse)) / (2.0 * (alpha + gamma))
    return out


def _sliding_nodes(x0: np.ndarray, boundary_faces: np.ndarray, n_nodes: int) -> tuple:
    """Boundary nodes inside a straight side: (ids, first and second boundary neighbour, unit tangent).

    A node qualifies when it has exactly two boundary neighbours and the three points are
    collinear (cross product below 1e-9 of the squared edge lengths); corners do not.
    """
    a = np.concatenate([boundary_faces[:, 0], boundary_faces[:, 1]])
    b = np.concatenate([boundary_faces[:, 1], boundary_faces[:, 0]])
    order = np.argsort(a, kind="stable")
    a, b = a[order], b[order]
    count = np.bincount(a, minlength=n_nodes)
    two = np.flatnonzero(count == 2)
    start = np.searchsorted(a, two)
    nb0, nb1 = b[start], b[start + 1]
    d0 = x0[nb0] - x0[two]
    d1 = x0[nb1] - x0[two]
    cross = d0[:, 0] * d1[:, 1] - d0[:, 1] * d1[:, 0]
    straight = np.abs(cross) <= 1e-9 * (d0 ** 2).sum(axis=1) ** 0.5 * (d1 ** 2).sum(axis=1) ** 0.5
    ids = two[straight]
    t = x0[nb1[straight]] - x0[nb0[straight]]
    t /= np.linalg.norm(t, axis=1)[:, None]
    return ids.astype(np.int64), nb0[straight].astype(np.int64), nb1[straight].astype(np.int64), t


def _straight_lines(x0: np.ndarray, edges: np.ndarray, axis: int) -> tuple:
    """The mesh lines along ``axis``: (ids, end_a, end_b, s) for the nodes inside a line.

    A line is a chain of edges more aligned with ``axis`` than across it (|d . e_axis| > |d|/sqrt 2
    at the start); its two end nodes are the chain's ends; s in (0, 1) is each inner node's
    parameter between them at the start (arc length from end_a over the chain's length). Raises
    ValueError where a node has more than two such edges (not a structured mesh along ``axis``).
    """
    d = x0[edges[:, 1]] - x0[edges[:, 0]]
    along = np.abs(d[:, axis]) > np.linalg.norm(d, axis=1) / math.sqrt(2.0)
    a, b = edges[along, 0], edges[along, 1]
    n = x0.shape[0]
    deg = np.bincount(np.concatenate([a, b]), minlength=n)
    if deg.max(initial=0) > 2:
        raise ValueError("straight_lines smoothing needs a structured mesh: a node has more than two edges along the line axis")
    nbr = -np.ones((n, 2), dtype=np.int64)
    for u, w in ((a, b), (b, a)):
        for i, j in zip(u.tolist(), w.tolist()):
            nbr[i, 0 if nbr[i, 0] < 0 else 1] = j
    ids, end_a, end_b, par = [], [], [], []
    for start in np.flatnonzero(deg == 1):
        chain, prev, cur = [start], -1, start
        while True:
            nxt = [j for j in nbr[cur] if j >= 0 and j != prev]
            if not nxt:
                break
            prev, cur = cur, nxt[0]
            chain.append(cur)
        if chain[0] > chain[-1]:  # each chain once, from its lower-numbered end
            continue
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(x0[chain], axis=0), axis=1))])
        for node, t in zip(chain[1:-1], arc[1:-1] / arc[-1]):
            ids.append(node)
            end_a.append(chain[0])
            end_b.append(chain[-1])
            par.append(t)
    return (np.array(ids, dtype=np.int64), np.array(end_a, dtype=np.int64), np.array(end_b, dtype=np.int64),
            np.array(par, dtype=np.float64))
