"""Topology of an ALE mesh (quad4 or hex8): faces, element-face and node-element maps, the dual
node lines of the momentum remap, and the local face/edge tables of the two element types.

Built once per mesh: numpy, and for large quad4 meshes two kernels (``TOPOLOGY_KERNEL_ABOVE``); the solver's
kernels take the arrays ``build_topology`` returns.
"""
from __future__ import annotations

import numpy as np
from numba import njit

# local faces of a quad4: face k joins corners k and k+1. Sweep direction 0 (xi) crosses faces
# 3 (side "a") and 1 (side "b"); direction 1 (eta) crosses faces 0 (a) and 2 (b).
# For a sweep direction d, half h joins corners QUAD_HALF_NODES[d, h] = (src, dst), src on side a, dst on side b.
QUAD_SIDE_A = (3, 0)
QUAD_SIDE_B = (1, 2)
# QUAD_CORNER_HALF[d, corner] = half index, QUAD_CORNER_DST[d, corner] = 1 when the corner is on side b.
QUAD_CORNER_HALF = np.array([[0, 0, 1, 1], [0, 1, 1, 0]], dtype=np.int64)
QUAD_CORNER_DST = np.array([[0, 1, 1, 0], [0, 0, 1, 1]], dtype=np.int64)
QUAD_HALF_NODES = np.array([[[0, 1], [3, 2]], [[0, 3], [1, 2]]], dtype=np.int64)

# hex8 corners in VTK order (model.mesh.box_mesh): 0 (-,-,-), 1 (+,-,-), 2 (+,+,-), 3 (-,+,-), then
# 4..7 above 0..3. Local faces, each listed with its normal (right-hand rule) pointing out of the
# element: 0 xi-, 1 xi+, 2 eta-, 3 eta+, 4 zeta-, 5 zeta+; face k crosses sweep direction k // 2,
# on side a (k even) or b (k odd); the opposite face is k ^ 1.
HEX_FACE_NODES = np.array([[0, 4, 7, 3], [1, 2, 6, 5], [0, 1, 5, 4], [3, 7, 6, 2], [0, 3, 2, 1], [4, 5, 6, 7]],
                          dtype=np.int64)
# HEX_EDGES[d, h] = (src, dst): the four edges along direction d, src on face 2d, dst on face 2d + 1
HEX_EDGES = np.array([
    [[0, 1], [3, 2], [4, 5], [7, 6]],
    [[0, 3], [1, 2], [4, 7], [5, 6]],
    [[0, 4], [1, 5], [2, 6], [3, 7]],
], dtype=np.int64)
# the three corners joined to each corner by an edge
HEX_CORNER_NBR = np.array([[1, 3, 4], [0, 2, 5], [1, 3, 6], [0, 2, 7], [0, 5, 7], [1, 4, 6], [2, 5, 7], [3, 4, 6]],
                          dtype=np.int64)


def build_topology(conn: np.ndarray, n_nodes: int, kernel: bool | None = None) -> dict:
    """Faces, element-face and node-element maps and dual node lines of a quad4 (or hex8) mesh.

    Besides the maps, per sweep direction d: ``side_a[d]``, ``side_b[d]`` the local faces it
    crosses, ``corner_edge[d]``, ``corner_dst[d]`` (npe,) the edge along d each corner lies on and
    whether it is that edge's far (side-b) end, ``faces_by_dir[d]`` the faces it sweeps.
    ``node_line`` is int32 (node numbers below 2^31): the dual fluxes read a quarter of it per sweep, and
    half the bytes measured 10.9 -> 7.9 ns per element-sweep of ``dual.dual_fluxes`` (480^2 gas, mostly at rest).
    The quad4 face maps and node lines: numpy up to TOPOLOGY_KERNEL_ABOVE elements, else (or with ``kernel``)
    the kernels ``_quad_face_maps``, ``_quad_node_lines_kernel``; the same arrays (tests/unit/test_setup_numpy.py).
    """
    if n_nodes >= 2 ** 31:
        raise ValueError("ALE meshes are limited to 2^31 - 1 nodes (int32 node lines)")
    conn = np.ascontiguousarray(conn, dtype=np.int64)
    if conn.shape[1] == 8:
        return _build_topology_3d(conn, n_nodes)
    n_elem = conn.shape[0]
    a = conn.ravel()
    b = conn[:, [1, 2, 3, 0]].ravel()  # face k joins corners k and k + 1
    key = np.minimum(a, b)
    key *= n_nodes
    key += np.maximum(a, b)
    first, inv = _unique_keys(key)
    del key
    face_nodes = np.stack([a[first], b[first]], axis=1)
    if (n_elem > TOPOLOGY_KERNEL_ABOVE) if kernel is None else kernel:
        n_faces = first.size
        face_elem = np.empty((n_faces, 2), dtype=np.int64)
        face_local = np.empty((n_faces, 2), dtype=np.int64)
        elem_face = np.empty((n_elem, 4), dtype=np.int64)
        elem_sign = np.empty((n_elem, 4), dtype=np.int8)  # +1 / -1: 4 bytes an element for the sweeps, not 32
        elem_nbr = np.empty((n_elem, 4), dtype=np.int64)
        if _quad_face_maps(first, inv, face_elem, face_local, elem_face, elem_sign, elem_nbr):
            raise ValueError("a face is shared by more than two elements")
        node_line = np.empty((n_elem, 2, 2, 4), dtype=np.int32)
        _quad_node_lines_kernel(conn, elem_nbr, np.array(QUAD_SIDE_A, dtype=np.int64),
                                np.array(QUAD_SIDE_B, dtype=np.int64), QUAD_HALF_NODES, node_line)
    else:
        face_elem, face_local, elem_face, elem_sign, elem_nbr = _face_maps(first, inv, 4)
        node_line = _quad_node_lines(conn, elem_nbr, elem_face, elem_sign, face_local)
    face_dir = (face_local[:, 0] % 2 == 0).view(np.int8)  # local faces 1, 3 cross direction 0, faces 0, 2 direction 1

    node_elem_idx = np.argsort(a, kind="stable").astype(np.int64, copy=False)
    node_elem_ptr = np.zeros(n_nodes + 1, dtype=np.int64)
    node_elem_ptr[1:] = np.cumsum(np.bincount(a, minlength=n_nodes))

    return dict(
        face_nodes=face_nodes.astype(np.int64, copy=False), face_elem=face_elem, face_local=face_local,
        elem_face=elem_face, elem_sign=elem_sign, elem_nbr=elem_nbr,
        node_elem_ptr=node_elem_ptr, node_elem_idx=node_elem_idx, node_line=node_line,
        faces_by_dir=[np.flatnonzero(face_dir == d).astype(np.int64, copy=False) for d in range(2)],
        side_a=QUAD_SIDE_A, side_b=QUAD_SIDE_B, corner_edge=QUAD_CORNER_HALF, corner_dst=QUAD_CORNER_DST,
    )


def _unique_keys(*keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(first, inverse) of ``np.unique(key, return_index=True, return_inverse=True)``: the index of each
    distinct key's first occurrence, in increasing key order, and each entry's distinct-key number. Several
    keys (most significant first) are one key read lexicographically: a hex8 face's sorted nodes packed as
    (k0 N + k1, k2 N + k3) (N the node count, N^2 < 2^63) give ``np.unique(axis=0)``'s rows, order and first
    occurrences without its row-as-record sort (96 000 hex8: 0.55-0.66 -> 0.02 s)."""
    order = np.argsort(keys[0], kind="stable") if len(keys) == 1 else np.lexsort(keys[::-1])  # both stable
    n = len(keys[0])
    new = np.zeros(n, dtype=bool)
    new[:1] = True
    for key in keys:
        sorted_key = key[order]
        new[1:] |= sorted_key[1:] != sorted_key[:-1]
    rank = np.cumsum(new, out=sorted_key)  # each sorted entry's distinct-key number + 1, in
    rank -= 1  # the sorted keys' buffer (int64, n; not needed any more): 29 MB less fresh memory at 960^2
    inverse = np.empty(n, dtype=np.int64)
    inverse[order] = rank
    return order[new], inverse


TOPOLOGY_KERNEL_ABOVE = 1 << 18
"""Quad4 meshes of more elements than this build their face maps and node lines with kernels (compiled once into
numba's cache), smaller ones in numpy (nothing to compile or load before the first step): the same arrays. At 960^2
the whole ``build_topology`` took 0.36-0.40 s of user time on the numpy path against 0.21-0.23 s on the kernels'
(``benchmarks/startup.py`` docstring: 3 interleaved rounds in one process, load 7-8, 7 December 2026), about 0.17 us
more per element; loading the two cached kernels costs some 40 ms (20 ms each, as ``ale.fill._quad_samples``),
compiling them about 0.9 s: numpy is the cheaper up to about 2.5e5 elements on a warm cache."""


@njit(cache=True)
def _quad_face_maps(first, inv, face_elem, face_local, elem_face, elem_sign, elem_nbr):
    """The face maps of a quad4 mesh from its local faces' face numbers inv (4E,) (local face k of
    element e at 4 e + k) and each face's first local face first (F,): face_elem, face_local (F, 2)
    owner then neighbour (-1: none), elem_face, elem_sign (+1 on the owner's side, -1 on the
    neighbour's), elem_nbr (-1: none) (E, 4). True when a face is met more than twice."""
    for f in range(first.size):
        face_elem[f, 0] = first[f] // 4
        face_local[f, 0] = first[f] % 4
        face_elem[f, 1] = -1
        face_local[f, 1] = -1
    too_many = False
    for i in range(inv.size):
        f = inv[i]
        e, k = i // 4, i % 4
        elem_face[e, k] = f
        if first[f] == i:
            elem_sign[e, k] = 1
        else:
            elem_sign[e, k] = -1
            if face_elem[f, 1] >= 0:
                too_many = True
            face_elem[f, 1] = e
            face_local[f, 1] = k
    for e in range(elem_face.shape[0]):
        for k in range(4):
            f = elem_face[e, k]
            elem_nbr[e, k] = face_elem[f, 1] if elem_sign[e, k] > 0 else face_elem[f, 0]
    return too_many


@njit(cache=True)
def _quad_node_lines_kernel(conn, elem_nbr, side_a, side_b, half_nodes, node_line):
    """node_line[e, d, h] = (before src, src, dst, after dst) of quad4 element e's half h along sweep
    direction d (src, dst = half_nodes[d, h]): "before src" is the corner of the side-a neighbour
    across face side_a[d] joined to src by the neighbour's edge that leaves the shared face, "after
    dst" the same across side_b[d]; -1 without a neighbour."""
    for e in range(conn.shape[0]):
        for d in range(2):
            for h in range(2):
                src = conn[e, half_nodes[d, h, 0]]
                dst = conn[e, half_nodes[d, h, 1]]
                node_line[e, d, h, 1] = src
                node_line[e, d, h, 2] = dst
                for side in range(2):
                    col = 0 if side == 0 else 3
                    node = src if side == 0 else dst
                    k = side_a[d] if side == 0 else side_b[d]
                    nb = elem_nbr[e, k]
                    if nb < 0:
                        node_line[e, d, h, col] = -1
                        continue
                    fa = conn[e, k]
                    other = conn[e, (k + 1) % 4] if fa == node else fa
                    c = 0
                    for j in range(4):
                        if conn[nb, j] == node:
                            c = j
                            break
                    c1 = conn[nb, (c + 1) % 4]
                    node_line[e, d, h, col] = conn[nb, (c + 3) % 4] if c1 == other else c1


def _face_maps(first: np.ndarray, inv: np.ndarray, nf: int) -> tuple:
    """The face maps of a mesh of elements with nf local faces, from each local face's face number inv
    (nf E,) (local face k of element e at nf e + k) and each face's first local face first (F,):
    face_elem, face_local (F, 2) owner (the first occurrence) then neighbour (-1: none), elem_face,
    elem_sign (+1 on the owner's side, -1 on the neighbour's), elem_nbr (-1: none) (E, nf). Raises
    ValueError when a face is met more than twice."""
    n_local = inv.size
    if n_local and np.bincount(inv).max() > 2:
        raise ValueError("a face is shared by more than two elements")
    owner = first[inv] == np.arange(n_local)
    face_elem = np.full((first.size, 2), -1, dtype=np.int64)
    face_local = np.full((first.size, 2), -1, dtype=np.int64)
    face_elem[:, 0] = first // nf
    face_local[:, 0] = first % nf
    second = np.flatnonzero(~owner)
    face_elem[inv[second], 1] = second // nf
    face_local[inv[second], 1] = second % nf
    elem_face = inv.reshape(-1, nf)
    elem_sign = np.where(owner, 1, -1).astype(np.int8).reshape(-1, nf)
    elem_nbr = face_elem.ravel()[2 * elem_face + owner.reshape(-1, nf)]  # the other side's element
    return face_elem, face_local, elem_face, elem_sign, elem_nbr


def _quad_node_lines(conn: np.ndarray, elem_nbr: np.ndarray, elem_face: np.ndarray, elem_sign: np.ndarray,
                     face_local: np.ndarray) -> np.ndarray:
    """node_line (E, 2, 2, 4) int32: node_line[e, d, h] = (before src, src, dst, after dst) of quad4 element e's
    half h along sweep direction d (src, dst = QUAD_HALF_NODES[d, h]). "before src" is the corner of the side-a
    neighbour nb across face k = QUAD_SIDE_A[d] joined to src by nb's edge that leaves the shared face: with src
    at nb's corner c (its first), nb's corner c + 1 unless that is the shared face's other node, else its corner
    c - 1; "after dst" the same across QUAD_SIDE_B[d]; -1 without a neighbour.

    The shared face is nb's local face j (``face_local``), its corners j and j + 1: src at corner j gives corner
    j - 1, at j + 1 corner j + 2, the same node as the rule above wherever nb's and e's corners are four distinct
    nodes; elements with a repeated corner (a collapsed quad) and their neighbours take the rule itself.
    """
    n_elem = conn.shape[0]
    node_line = np.empty((n_elem, 2, 2, 4), dtype=np.int32)
    flat = conn.ravel()
    repeated = np.zeros(n_elem, dtype=bool)
    for i in range(4):
        for j in range(i + 1, 4):
            repeated |= conn[:, i] == conn[:, j]
    local = face_local.ravel()
    # by chunks of elements: a chunk's temporaries and its rows of node_line stay in cache (at 960^2 the whole-mesh
    # passes wrote node_line's 59 MB once per column, and fresh temporaries cost system time)
    for lo in range(0, n_elem, _NODE_LINE_CHUNK):
        hi = min(lo + _NODE_LINE_CHUNK, n_elem)
        out = node_line[lo:hi].reshape(hi - lo, 16)  # column 8 d + 4 h + c
        corner = [np.ascontiguousarray(conn[lo:hi, a]) for a in range(4)]
        for d in range(2):
            for h in range(2):
                out[:, 8 * d + 4 * h + 1] = corner[QUAD_HALF_NODES[d, h, 0]]
                out[:, 8 * d + 4 * h + 2] = corner[QUAD_HALF_NODES[d, h, 1]]
        for side, (col, faces) in enumerate(((0, QUAD_SIDE_A), (3, QUAD_SIDE_B))):
            for d in range(2):
                k = faces[d]
                nb = elem_nbr[lo:hi, k]
                has = nb >= 0
                nb0 = np.where(has, nb, 0)
                # the face in nb (-1: none): its local face on the side that is not e's
                j = local[2 * elem_face[lo:hi, k] + (elem_sign[lo:hi, k] > 0)]
                base = 4 * nb0
                at_j = flat[base + np.where(has, j, 0)]
                before = flat[base + ((j + 3) & 3)]  # nb's corner j - 1 (j + 3 >= 0: & 3 is % 4)
                after = flat[base + ((j + 2) & 3)]  # nb's corner j + 2
                slow = np.flatnonzero(has & (repeated[lo:hi] | repeated[nb0]))
                for h in range(2):
                    node = corner[QUAD_HALF_NODES[d, h, side]]
                    line = np.where(node == at_j, before, after)
                    line[~has] = -1
                    if len(slow):
                        line[slow] = _node_line_rule(conn, slow + lo, nb[slow], k, node[slow])
                    out[:, 8 * d + 4 * h + col] = line
    return node_line


_NODE_LINE_CHUNK = 1 << 14
"""Elements per chunk of ``_quad_node_lines``: 16384 rows of node_line are 1 MB."""


def _node_line_rule(conn: np.ndarray, e: np.ndarray, nb: np.ndarray, k: int, node: np.ndarray) -> np.ndarray:
    """``_quad_node_lines``' rule itself for elements e with neighbours nb across their face k: node at nb's
    first corner c holding it, nb's corner c + 1 unless that is the face's other node, else corner c - 1."""
    fa, fb = conn[e, k], conn[e, (k + 1) % 4]
    other = np.where(fa == node, fb, fa)
    cn = conn[nb]
    c = np.argmax(cn == node[:, None], axis=1)
    rows = np.arange(len(e))
    c1 = cn[rows, (c + 1) % 4]
    return np.where(c1 == other, cn[rows, (c + 3) % 4], c1)


def _build_topology_3d(conn: np.ndarray, n_nodes: int) -> dict:
    """build_topology for hex8 (VTK order; local faces, edges: HEX_FACE_NODES, HEX_EDGES).

    A face is keyed by its sorted four nodes; its first element (owner) gives face_nodes in the
    owner's outward order, face_local and the sweep direction face_local // 2. node_line[e, d, h]
    = (before src, src, dst, after dst) along edge h of direction d: "before src" is the node
    joined to src by the edge of the side-a neighbour that leaves the shared face (-1 without one).
    """
    n_elem = conn.shape[0]
    loc = HEX_FACE_NODES
    quads = conn[:, loc].reshape(6 * n_elem, 4)  # (6E, 4) in outward order
    key = np.sort(quads, axis=1)
    first, inv = _unique_keys(key[:, 0] * n_nodes + key[:, 1], key[:, 2] * n_nodes + key[:, 3])
    if np.bincount(inv).max(initial=0) > 2:
        raise ValueError("a face is shared by more than two elements")
    n_faces = first.size
    flat = np.arange(6 * n_elem)
    face_nodes = quads[first]
    face_elem = -np.ones((n_faces, 2), dtype=np.int64)
    face_local = -np.ones((n_faces, 2), dtype=np.int64)
    face_elem[:, 0] = first // 6
    face_local[:, 0] = first % 6
    second = flat[flat != first[inv]]
    face_elem[inv[second], 1] = second // 6
    face_local[inv[second], 1] = second % 6
    elem_face = inv.reshape(n_elem, 6).astype(np.int64)
    elem_sign = np.where(flat == first[inv], 1, -1).astype(np.int8).reshape(n_elem, 6)
    elem_nbr = np.where(elem_sign > 0, face_elem[elem_face, 1], face_elem[elem_face, 0]).astype(np.int64)
    face_dir = face_local[:, 0] // 2

    a = conn.ravel()
    order = np.argsort(a, kind="stable")
    node_elem_idx = np.arange(8 * n_elem, dtype=np.int64)[order]
    node_elem_ptr = np.zeros(n_nodes + 1, dtype=np.int64)
    node_elem_ptr[1:] = np.cumsum(np.bincount(a, minlength=n_nodes))

    node_line = -np.ones((n_elem, 3, 4, 4), dtype=np.int64)
    e_all = np.arange(n_elem)
    for d in range(3):
        for h in range(4):
            src = conn[:, HEX_EDGES[d, h, 0]]
            dst = conn[:, HEX_EDGES[d, h, 1]]
            node_line[:, d, h, 1] = src
            node_line[:, d, h, 2] = dst
            for col, node, k in ((0, src, 2 * d), (3, dst, 2 * d + 1)):
                nb = elem_nbr[:, k]
                ok = nb >= 0
                shared = conn[e_all[ok][:, None], loc[k][None, :]]  # (M, 4) nodes of the shared face
                cn = conn[nb[ok]]
                c = np.argmax(cn == node[ok, None], axis=1)
                cand = cn[np.arange(cn.shape[0])[:, None], HEX_CORNER_NBR[c]]  # (M, 3)
                off = ~(cand[:, :, None] == shared[:, None, :]).any(axis=2)
                node_line[ok, d, h, col] = cand[np.arange(cand.shape[0]), np.argmax(off, axis=1)]
    corner_edge = np.zeros((3, 8), dtype=np.int64)
    corner_dst = np.zeros((3, 8), dtype=np.int64)
    for d in range(3):
        for h in range(4):
            corner_edge[d, HEX_EDGES[d, h]] = h
            corner_dst[d, HEX_EDGES[d, h, 1]] = 1
    return dict(
        face_nodes=face_nodes.astype(np.int64, copy=False), face_elem=face_elem, face_local=face_local,
        elem_face=elem_face, elem_sign=elem_sign, elem_nbr=elem_nbr,
        node_elem_ptr=node_elem_ptr, node_elem_idx=node_elem_idx, node_line=node_line.astype(np.int32),
        faces_by_dir=[np.flatnonzero(face_dir == d).astype(np.int64, copy=False) for d in range(3)],
        side_a=(0, 2, 4), side_b=(1, 3, 5), corner_edge=corner_edge, corner_dst=corner_dst,
    )


def hex_edges(conn: np.ndarray) -> np.ndarray:
    """Unique edges (n, 2) of a hex8 mesh."""
    e = np.sort(np.concatenate([conn[:, HEX_EDGES[d]].reshape(-1, 2) for d in range(3)]), axis=1)
    n = int(e.max(initial=-1)) + 1
    first, _ = _unique_keys(e[:, 0] * n + e[:, 1])  # np.unique(e, axis=0)'s rows, as one integer key
    return e[first]


def largest_face_area(nodes: np.ndarray, conn: np.ndarray) -> np.ndarray:
    """Largest face area of each hex8 (half the cross product of the face's diagonals)."""
    q = nodes[conn[:, HEX_FACE_NODES]]  # (E, 6, 4, 3)
    return 0.5 * np.linalg.norm(np.cross(q[:, :, 2] - q[:, :, 0], q[:, :, 3] - q[:, :, 1]), axis=2).max(axis=1)
