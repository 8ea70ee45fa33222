"""ALE mesh motion: where the remap puts the mesh after each Lagrangian phase.

Eulerian (back to the start), or the Lagrangian mesh smoothed: the mean of the edge neighbours
(Benson 1992 sec. 3), Winslow's equipotential point (Winslow 1967; Benson 1992 sec. 3.3; in 3D
Thompson, Warsi & Mastin 1985 ch. 6) or uniform motion along straight mesh lines (the paper's
section 5; LS-DYNA *ALE_SMOOTHING), with boundary nodes sliding along straight sides (2D, and the
meridian plane of an r-z mesh, whose axis nodes slide along the axis), in flat faces and along
straight edges (3D), and a pull back towards the start. Numpy only; options:
``options.MeshMotion``. Equations: docs/theory/ale.md, "Mesh motion".
"""
from __future__ import annotations

import math

import numpy as np

from .options import AXES, MeshMotion
from .topology import HEX_CORNER_NBR, hex_edges


class MeshMover:
    """The mesh target of ``MeshMotion`` on one mesh (start x0 (N, dim), conn, ``build_topology`` maps)."""

    def __init__(self, motion: MeshMotion, x0: np.ndarray, conn: np.ndarray, topo: dict):
        dim = x0.shape[1]
        n_nodes = x0.shape[0]
        self.motion = motion
        self.x0 = x0
        self.line_axis = AXES.index(motion.line_axis)
        if motion.mesh_motion != "smoothed":
            # Eulerian (the target is x0) or Lagrangian (no target): no neighbours, stencils or sliding nodes (at
            # 960^2 the edge lists and degrees alone were 66 MB of fresh memory before the first step)
            return
        fn = topo["face_nodes"]
        edges = fn if dim == 2 else hex_edges(conn)
        self._nbr_a = np.concatenate([edges[:, 0], edges[:, 1]])
        self._nbr_b = np.concatenate([edges[:, 1], edges[:, 0]])
        self._degree = np.bincount(self._nbr_a, minlength=n_nodes).astype(float)
        if motion.smoothing == "straight_lines":
            if not 0 <= self.line_axis < dim:
                raise ValueError(f"line_axis {motion.line_axis} is not an axis of a {dim}D mesh")
            self.lines = _straight_lines(x0, edges, self.line_axis)
        on_boundary = np.zeros(n_nodes, dtype=bool)
        bf = fn[topo["face_elem"][:, 1] < 0]
        on_boundary[bf.ravel()] = True
        self._interior = ~on_boundary
        self._stencil = (np.zeros(0, dtype=np.int64), np.zeros((0, 8 if dim == 2 else 18), dtype=np.int64))
        if motion.smoothing == "equipotential":  # its only user
            self._stencil = (_winslow_stencil if dim == 2 else _winslow_stencil_3d)(conn, n_nodes, self._interior)
        no = np.zeros(0, dtype=np.int64)
        self._slide_plane = (no, no, no, np.zeros(0), np.zeros((0, dim)))
        if dim == 2:
            self._slide = _sliding_nodes(x0, bf, n_nodes)
        elif motion.smoothing_boundary == "sliding":
            self._slide, self._slide_plane = _sliding_nodes_3d(x0, bf, n_nodes)
        else:
            self._slide = (no, no, no, np.zeros((0, dim)))

    def target(self, x_lag: np.ndarray) -> np.ndarray:
        """Where the remap puts the mesh: its start (Eulerian), or a smoothed Lagrangian mesh.

        "smoothed": starting from x_lag, smoothing_iterations Jacobi passes move each interior node a
        fraction smoothing_weight towards its target: the mean of its edge neighbours (smoothing
        "average", Benson 1992 sec. 3) or the Winslow equipotential point (smoothing
        "equipotential", Winslow 1967; interior nodes with four elements (eight in 3D) in the
        structured arrangement, the others averaged). Boundary nodes: "fixed" back to their start;
        "sliding": a node inside a straight side (2D) or a straight edge of the boundary (3D) on
        that line, moved the same fraction towards the mean of its two neighbours along it; a node
        inside a flat face of the boundary (3D) in that plane, moved the same fraction towards the
        mean of its boundary neighbours, x <- x0 + P (d + w (d_mean - d)), d = x - x0, P = I - n n^T
        the projection onto the plane; other boundary nodes (corners) fixed. Last, every moving
        node goes a fraction eulerian_pull back towards its start (which bounds the drift of a
        mesh in a steady stream).
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
        p_ids, p_row, p_nbr, p_count, p_normal = self._slide_plane
        sliding = mo.smoothing_boundary == "sliding"
        for _ in range(mo.smoothing_iterations):
            mean = np.zeros_like(x)
            np.add.at(mean, self._nbr_a, x[self._nbr_b])
            mean /= self._degree[:, None]
            target = mean
            if mo.smoothing == "equipotential":
                target = (_winslow_target if x.shape[1] == 2 else _winslow_target_3d)(x, mean, self._stencil)
            x_prev = x.copy()
            x[inner] = x[inner] + w * (target[inner] - x[inner])
            x[~inner] = self.x0[~inner]
            if sliding and ids.size > 0:
                # on the side's line through x0, moved along it towards the boundary neighbours' mean
                s_pos = ((x_prev[ids] - self.x0[ids]) * tang).sum(axis=1)
                s_mean = ((0.5 * (x_prev[nb0] + x_prev[nb1]) - self.x0[ids]) * tang).sum(axis=1)
                x[ids] = self.x0[ids] + (s_pos + w * (s_mean - s_pos))[:, None] * tang
            if sliding and p_ids.size > 0:
                # in the face's plane through x0, moved in it towards the boundary neighbours' mean
                p_mean = np.zeros((p_ids.size, x.shape[1]))
                np.add.at(p_mean, p_row, x_prev[p_nbr])
                p_mean /= p_count[:, None]
                d = x_prev[p_ids] - self.x0[p_ids]
                d += w * (p_mean - self.x0[p_ids] - d)
                d -= (d * p_normal).sum(axis=1)[:, None] * p_normal
                x[p_ids] = self.x0[p_ids] + d
        moving = inner.copy()
        if sliding:
            moving[ids] = True
            moving[p_ids] = True
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


def _face_opposite_corners() -> np.ndarray:
    """opposite[k, a, b]: the hex8 corner across the face through corner k and two of its edge
    neighbours a, b (the common edge neighbour of a and b other than k); -1 where a, b are not two
    edge neighbours of k."""
    opposite = -np.ones((8, 8, 8), dtype=np.int64)
    for k in range(8):
        for a in HEX_CORNER_NBR[k]:
            for b in HEX_CORNER_NBR[k]:
                if a != b:
                    (opposite[k, a, b],) = set(HEX_CORNER_NBR[a]) & set(HEX_CORNER_NBR[b]) - {k}
    return opposite


_HEX_FACE_OPPOSITE = _face_opposite_corners()
_PLANES = ((0, 1), (0, 2), (1, 2))  # the logical coordinate planes (xi eta, xi zeta, eta zeta) of the 3D stencil


def _winslow_stencil_3d(conn: np.ndarray, n_nodes: int, interior: np.ndarray) -> tuple:
    """Logical neighbours of the interior hex8 nodes whose eight elements sit as in a structured mesh.

    Returns (ids, nbr) with nbr (len(ids), 18): columns 2d, 2d + 1 the edge neighbours at +1 and
    -1 along logical direction d (xi, eta, zeta); then, for each plane (i, j) of ``_PLANES`` in turn,
    the four face-diagonal neighbours at (+i +j), (+i -j), (-i +j), (-i -j). The directions are
    read off the first element around the node (its three edge neighbours there are +xi, +eta,
    +zeta); -d is the neighbour, other than those three, of the element that holds the other two
    plus neighbours but not +d; the face diagonal at (s_i, s_j) is the corner across the face
    that an element holding those two neighbours shares with the node. A node qualifies when it
    has eight elements, each holding one neighbour of each pair, in the eight different sign
    patterns (the regular 26-neighbour arrangement); the others fall back to the average. Neither
    the choice of +d nor the handedness changes the Winslow point (``_winslow_target_3d``).
    """
    a = np.arange(8 * conn.shape[0])
    e, k = a // 8, a % 8
    node = conn[e, k]
    ok = interior & (np.bincount(node, minlength=n_nodes) == 8)
    ids = np.flatnonzero(ok)
    sel = ok[node]
    order = np.argsort(node[sel], kind="stable")
    es, ks = e[sel][order].reshape(-1, 8), k[sel][order].reshape(-1, 8)  # the eight (element, corner) of each node
    loc = HEX_CORNER_NBR[ks]  # (M, 8, 3) the corners joined to it by an edge, local
    nb = conn[es[:, :, None], loc]  # the same, global
    r = np.arange(ids.size)
    plus = nb[:, 0, :]
    has = (nb[:, :, :, None] == plus[:, None, None, :]).any(axis=2)  # (M, 8, 3): element j holds plus[d]
    minus = np.empty_like(plus)
    for d in range(3):
        j = np.argmax(~has[:, :, d] & has[:, :, (d + 1) % 3] & has[:, :, (d + 2) % 3], axis=1)
        cand = nb[r, j]
        off_plus = ~(cand[:, :, None] == plus[:, None, :]).any(axis=2)
        minus[:, d] = cand[r, np.argmax(off_plus, axis=1)]
    expected = np.where(has, plus[:, None, :], minus[:, None, :])  # (M, 8, 3) the neighbour along d in element j
    pattern = (has * np.array([4, 2, 1])).sum(axis=2)
    regular = ((np.sort(nb, axis=2) == np.sort(expected, axis=2)).all(axis=(1, 2))
               & (np.sort(pattern, axis=1) == np.arange(8)).all(axis=1))
    at = np.argmax(nb[:, :, :, None] == expected[:, :, None, :], axis=2)  # (M, 8, 3): where expected[d] sits in nb
    corner = np.take_along_axis(loc, at, axis=2)  # (M, 8, 3) local corner of the neighbour along d
    nbr = np.empty((ids.size, 18), dtype=np.int64)
    nbr[:, 0:6:2] = plus
    nbr[:, 1:6:2] = minus
    for q, (i, j) in enumerate(_PLANES):
        diag = conn[es, _HEX_FACE_OPPOSITE[ks, corner[:, :, i], corner[:, :, j]]]  # (M, 8)
        col = 6 + 4 * q + 2 * (~has[:, :, i]) + (~has[:, :, j])
        nbr[r[:, None], col] = diag  # each diagonal twice (the two elements beside it), the same node
    return ids[regular], nbr[regular]


def _winslow_target_3d(x: np.ndarray, fallback: np.ndarray, stencil: tuple) -> np.ndarray:
    """Jacobi point of the 3D Winslow (equipotential) equations sum_ij C_ij x_(xi_i xi_j) = 0.

    The logical coordinates xi_i are harmonic in physical space (Laplace, Winslow 1967); exchanging
    dependent and independent variables gives sum_ij g^ij x_(xi_i xi_j) = 0 with g^ij = grad xi_i .
    grad xi_j (Thompson, Warsi & Mastin 1985, "Numerical Grid Generation", ch. 6, the elliptic system
    without control functions). With a_i = x_(xi_i) and b_i = a_j x a_k ((i, j, k) cyclic),
    grad xi_i = b_i / J, so times J^2 the coefficients are C_ij = b_i . b_j (in 2D they reduce to
    alpha = |x_eta|^2, -beta = -x_xi . x_eta, gamma = |x_xi|^2). Central differences on the logical
    stencil (unit spacing; a_i = (x_(+i) - x_(-i)) / 2, x_(xi_i xi_i) = x_(+i) - 2 x + x_(-i),
    x_(xi_i xi_j) = (x_(+i+j) - x_(+i-j) - x_(-i+j) + x_(-i-j)) / 4), solved for x with the
    coefficients frozen:
    x = [sum_i C_ii (x_(+i) + x_(-i)) + 1/2 sum_(i<j) C_ij (x_(+i+j) - x_(+i-j) - x_(-i+j) + x_(-i-j))]
    / (2 sum_i C_ii). On a uniform (or any affine) grid this is the node itself. Nodes outside the
    stencil (``_winslow_stencil_3d``) keep ``fallback``.
    """
    ids, nb = stencil
    out = fallback.copy()
    if ids.size == 0:
        return out
    xp = [x[nb[:, 2 * d]] for d in range(3)]
    xm = [x[nb[:, 2 * d + 1]] for d in range(3)]
    a = [0.5 * (xp[d] - xm[d]) for d in range(3)]
    b = [np.cross(a[1], a[2]), np.cross(a[2], a[0]), np.cross(a[0], a[1])]
    num = np.zeros_like(a[0])
    den = np.zeros((ids.size, 1))
    for d in range(3):
        c = (b[d] * b[d]).sum(axis=1)[:, None]
        num += c * (xp[d] + xm[d])
        den += c
    for q, (i, j) in enumerate(_PLANES):
        c = (b[i] * b[j]).sum(axis=1)[:, None]
        pp, pm, mp, mm = (x[nb[:, 6 + 4 * q + m]] for m in range(4))
        num += 0.5 * c * (pp - pm - mp + mm)
    out[ids] = num / (2.0 * den)
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


def _sliding_nodes_3d(x0: np.ndarray, boundary_faces: np.ndarray, n_nodes: int) -> tuple:
    """Boundary nodes of a hex8 mesh that slide: (line, plane).

    plane = (ids, row, nbr, count, normal): nodes inside a flat face of the boundary, i.e. every
    boundary quad at the node is flat (its corners within 1e-9 of its size of its plane) and has
    the same unit normal (cross product below 1e-9); (row, nbr) the pairs (place in ids, boundary
    neighbour) along the boundary quads' edges, count the neighbours of each, normal (len(ids), 3).
    line = (ids, first and second neighbour, unit tangent), as ``_sliding_nodes`` gives in 2D:
    nodes inside a straight edge of the boundary, i.e. every boundary quad at the node is flat and
    lies in one of exactly two planes that meet at an angle, and exactly two boundary neighbours
    lie on the planes' intersection line (within 1e-9 of their distance), one on each side.
    Every other boundary node (a corner, a node of a curved or warped surface) is fixed.
    """
    q = x0[boundary_faces]
    normal = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])
    size = np.linalg.norm(normal, axis=1)
    normal /= size[:, None]
    warp = np.abs(((q - q.mean(axis=1, keepdims=True)) * normal[:, None, :]).sum(axis=2)).max(axis=1)
    flat = warp <= 1e-9 * np.sqrt(size)
    node = boundary_faces.ravel()
    order = np.argsort(node, kind="stable")
    node, face = node[order], np.repeat(np.arange(len(boundary_faces)), 4)[order]
    nodes, start = np.unique(node, return_index=True)
    seg = np.repeat(np.arange(nodes.size), np.diff(np.append(start, node.size)))
    n_f = normal[face]
    ref1 = n_f[start]
    in1 = _same_direction(n_f, ref1[seg])
    first_off = np.minimum.reduceat(np.where(in1, node.size, np.arange(node.size)), start)
    ref2 = n_f[np.minimum(first_off, node.size - 1)]
    in2 = _same_direction(n_f, ref2[seg])
    tang = np.cross(ref1, ref2)
    t_len = np.linalg.norm(tang, axis=1)
    all_flat = np.logical_and.reduceat(flat[face], start)
    one = all_flat & np.logical_and.reduceat(in1, start)
    two = all_flat & (first_off < node.size) & (t_len > 1e-9) & np.logical_and.reduceat(in1 | in2, start)
    # the boundary edges, each way
    ends = boundary_faces[:, [0, 1, 1, 2, 2, 3, 3, 0]].reshape(-1, 2)
    ends = np.unique(np.sort(ends, axis=1), axis=0)
    a = np.concatenate([ends[:, 0], ends[:, 1]])
    b = np.concatenate([ends[:, 1], ends[:, 0]])
    order = np.argsort(a, kind="stable")
    a, b = a[order], b[order]
    # in a face
    place = -np.ones(n_nodes, dtype=np.int64)
    p_ids = nodes[one]
    place[p_ids] = np.arange(p_ids.size)
    in_face = place[a] >= 0
    p_row, p_nbr = place[a[in_face]], b[in_face]
    p_count = np.bincount(p_row, minlength=p_ids.size).astype(float)
    plane = (p_ids.astype(np.int64), p_row, p_nbr.astype(np.int64), p_count, ref1[one])
    # along an edge
    t_node = np.zeros((n_nodes, 3))
    t_node[nodes[two]] = tang[two] / t_len[two][:, None]
    cand = np.zeros(n_nodes, dtype=bool)
    cand[nodes[two]] = True
    d = x0[b] - x0[a]
    on_line = cand[a] & (np.linalg.norm(np.cross(d, t_node[a]), axis=1) <= 1e-9 * np.linalg.norm(d, axis=1))
    la, lb = a[on_line], b[on_line]
    count = np.bincount(la, minlength=n_nodes)
    pairs = np.flatnonzero(count == 2)
    first = np.searchsorted(la, pairs)
    nb0, nb1 = lb[first], lb[first + 1]
    across = ((x0[nb0] - x0[pairs]) * (x0[nb1] - x0[pairs])).sum(axis=1) < 0.0
    ids, nb0, nb1 = pairs[across], nb0[across], nb1[across]
    t = x0[nb1] - x0[nb0]
    t /= np.linalg.norm(t, axis=1)[:, None]
    return (ids.astype(np.int64), nb0.astype(np.int64), nb1.astype(np.int64), t), plane


def _same_direction(n: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """Unit normals n (k, 3) that point as ref (k, 3) does (cross product below 1e-9, positive dot product)."""
    return (np.linalg.norm(np.cross(n, ref), axis=1) <= 1e-9) & ((n * ref).sum(axis=1) > 0.0)


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
